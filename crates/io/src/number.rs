//! Text formatting of `f64` values that reads back to the identical bits.

/// Formats `x` with the fewest digits that parse back (with
/// `str::parse::<f64>`) to exactly the same value.
///
/// Values of ordinary magnitude (`1e-5 <= |x| < 1e16`, and zero) use Rust's
/// plain `{}` notation (`0.30000000000000004`, `1500`); very small or very
/// large ones use `{:e}` notation (`1e-300`, `2.5e20`) so that they stay
/// short. Non-finite values print as `NaN`, `inf` and `-inf`.
pub fn format_f64(x: f64) -> String {
    let magnitude = x.abs();
    if !x.is_finite() || x == 0.0 || (1e-5..1e16).contains(&magnitude) {
        format!("{x}")
    } else {
        format!("{x:e}")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ordinary_values_use_plain_notation() {
        assert_eq!(format_f64(0.1 + 0.2), "0.30000000000000004");
        assert_eq!(format_f64(1500.0), "1500");
        assert_eq!(format_f64(-2.5), "-2.5");
        assert_eq!(format_f64(0.0), "0");
        assert_eq!(format_f64(1e-5), "0.00001");
    }

    #[test]
    fn extreme_values_use_exponent_notation() {
        assert_eq!(format_f64(1e-300), "1e-300");
        assert_eq!(format_f64(-2.5e20), "-2.5e20");
        assert_eq!(format_f64(f64::MIN_POSITIVE), "2.2250738585072014e-308");
    }

    #[test]
    fn every_value_reads_back_bit_for_bit() {
        let values = [
            0.1 + 0.2,
            1e-300,
            5e-324,
            f64::MAX,
            f64::MIN,
            -0.0,
            1.0 / 3.0,
            1e16 - 2.0,
            1e16,
            f64::INFINITY,
            f64::NEG_INFINITY,
        ];
        for x in values {
            let back: f64 = format_f64(x).parse().unwrap();
            assert_eq!(back.to_bits(), x.to_bits(), "{x:e}");
        }
        let nan: f64 = format_f64(f64::NAN).parse().unwrap();
        assert!(nan.is_nan());
    }
}
