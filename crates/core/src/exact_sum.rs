//! Exactly rounded sums of `f64` values, in any order and over any split.
//!
//! [`ExactSum`] is a long fixed-point accumulator (a Kulisch accumulator):
//! every finite `f64` is an integer multiple of 2⁻¹⁰⁷⁴, the smallest
//! subnormal, so a sum of them is an integer count of that unit, which the
//! accumulator holds exactly in 32-bit digits (each kept in an `i64`, so
//! that 2³⁰ additions go by before a carry must move). Only
//! [`ExactSum::value`] rounds, once, to the nearest `f64` (ties to even).
//! The result is therefore the same bits whatever the order of the
//! additions and however they were split between accumulators merged with
//! [`ExactSum::merge`] — the property the conservation totals need to be
//! summed rank by rank (each rank its own cells) and still come out as the
//! bits of one rank. The digits travel between processes as `u64`s
//! ([`ExactSum::to_words`], [`ExactSum::add_words`]) whose wrapping sum
//! (`MPI_SUM` on unsigned 64-bit integers) is the merged accumulator.
//!
//! The crate `xsum` (Neal's small and large superaccumulators) sums as
//! exactly and faster, but it offers no way to merge accumulators from
//! several processes, which is what this one is for; the totals it serves
//! are summed only at output times.

/// Bits per digit.
const DIGIT_BITS: u32 = 32;
/// Digits: the unit 2⁻¹⁰⁷⁴ times the largest finite magnitude needs 2098
/// bits; 67 digits (2144 bits) leave room for the carries of more than
/// 2⁴⁰ additions of `f64::MAX`, which overflow to infinity in the end.
const DIGITS: usize = 67;
/// Additions between two carry propagations: each adds less than 2³² to a
/// digit, so 2³⁰ of them keep a digit well inside an `i64`.
const CARRY_EVERY: u32 = 1 << 30;

/// An exact sum of `f64` values; see the [module documentation](self).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ExactSum {
    /// The sum in units of 2⁻¹⁰⁷⁴: Σ digit[k] · 2^(32k).
    digits: [i64; DIGITS],
    /// Additions since the last carry propagation.
    pending: u32,
    /// How many +∞, −∞ and NaN values were added.
    specials: [u64; 3],
}

impl Default for ExactSum {
    fn default() -> Self {
        Self::new()
    }
}

impl ExactSum {
    /// Words of [`Self::to_words`]: the digits, then the three counts of
    /// non-finite values.
    pub const WORDS: usize = DIGITS + 3;

    /// Zero.
    pub fn new() -> Self {
        Self {
            digits: [0; DIGITS],
            pending: 0,
            specials: [0; 3],
        }
    }

    /// Adds `x` exactly.
    #[inline]
    pub fn add(&mut self, x: f64) {
        let bits = x.to_bits();
        let biased = ((bits >> 52) & 0x7ff) as i64;
        let fraction = bits & ((1 << 52) - 1);
        if biased == 0x7ff {
            let k = if fraction != 0 {
                2
            } else if x > 0.0 {
                0
            } else {
                1
            };
            self.specials[k] += 1;
            return;
        }
        // x = m · 2^(shift − 1074), m < 2⁵³.
        let (m, shift) = if biased == 0 {
            (fraction, 0)
        } else {
            (fraction | (1 << 52), biased - 1)
        };
        if m == 0 {
            return;
        }
        let shift = shift as u32;
        let k = (shift / DIGIT_BITS) as usize;
        let v = u128::from(m) << (shift % DIGIT_BITS);
        let parts = [
            (v & 0xffff_ffff) as i64,
            ((v >> 32) & 0xffff_ffff) as i64,
            (v >> 64) as i64,
        ];
        if bits >> 63 == 0 {
            for (d, p) in self.digits[k..k + 3].iter_mut().zip(parts) {
                *d += p;
            }
        } else {
            for (d, p) in self.digits[k..k + 3].iter_mut().zip(parts) {
                *d -= p;
            }
        }
        self.pending += 1;
        if self.pending == CARRY_EVERY {
            self.carry();
        }
    }

    /// Adds every accumulated value of `other`.
    pub fn merge(&mut self, other: &ExactSum) {
        self.carry();
        let mut o = other.clone();
        o.carry();
        for (d, e) in self.digits.iter_mut().zip(o.digits) {
            *d += e;
        }
        for (s, t) in self.specials.iter_mut().zip(o.specials) {
            *s += t;
        }
        self.carry();
    }

    /// Moves each digit's excess over 2³² into the next, so that every
    /// digit but the last lies in [0, 2³²) and the last carries the sign.
    fn carry(&mut self) {
        for k in 0..DIGITS - 1 {
            let c = self.digits[k] >> DIGIT_BITS;
            self.digits[k] -= c << DIGIT_BITS;
            self.digits[k + 1] += c;
        }
        self.pending = 0;
    }

    /// The accumulator as [`Self::WORDS`] words whose element-wise
    /// wrapping sum over several accumulators is their merged state
    /// ([`Self::add_words`]): the sum of fewer than 2³⁰ of them.
    pub fn to_words(&self) -> Vec<u64> {
        let mut s = self.clone();
        s.carry();
        s.digits
            .iter()
            .map(|&d| d as u64)
            .chain(s.specials)
            .collect()
    }

    /// Adds the accumulated values of `words` (from [`Self::to_words`],
    /// or the wrapping sum of several such).
    ///
    /// # Panics
    /// If `words` does not hold [`Self::WORDS`] words.
    pub fn add_words(&mut self, words: &[u64]) {
        assert_eq!(words.len(), Self::WORDS, "ExactSum words");
        self.carry();
        for (d, &w) in self.digits.iter_mut().zip(&words[..DIGITS]) {
            *d = d.wrapping_add(w as i64);
        }
        for (s, &w) in self.specials.iter_mut().zip(&words[DIGITS..]) {
            *s += w;
        }
        self.carry();
    }

    /// The sum, rounded once to the nearest `f64` (ties to even): ±∞
    /// beyond the largest finite value, NaN if a NaN or both infinities
    /// were added, the infinity if one was; +0 for an exact zero.
    pub fn value(&self) -> f64 {
        let [pos, neg, nan] = self.specials;
        if nan > 0 || (pos > 0 && neg > 0) {
            return f64::NAN;
        }
        if pos > 0 {
            return f64::INFINITY;
        }
        if neg > 0 {
            return f64::NEG_INFINITY;
        }
        let mut s = self.clone();
        s.carry();
        let negative = s.digits[DIGITS - 1] < 0;
        if negative {
            for d in &mut s.digits {
                *d = -*d;
            }
            s.carry();
        }
        let magnitude = s.round_magnitude();
        if negative {
            -magnitude
        } else {
            magnitude
        }
    }

    /// The non-negative carried sum N (units of 2⁻¹⁰⁷⁴) rounded to the
    /// nearest `f64`.
    fn round_magnitude(&self) -> f64 {
        let Some(top) = self.digits.iter().rposition(|&d| d != 0) else {
            return 0.0;
        };
        let length = DIGIT_BITS * top as u32 + (64 - (self.digits[top] as u64).leading_zeros());
        if length <= 53 {
            // N < 2⁵³: exact as an f64, and so is N · 2⁻¹⁰⁷⁴.
            let n = self.bits(0, length);
            return n as f64 * f64::from_bits(1);
        }
        // Keep the top 53 bits; round on the next bit and the rest.
        let shift = length - 53;
        let mut mantissa = self.bits(shift, 53);
        let round = self.bits(shift - 1, 1) == 1;
        let sticky = self.any_below(shift - 1);
        let mut shift = shift;
        if round && (sticky || mantissa & 1 == 1) {
            mantissa += 1;
            if mantissa == 1 << 53 {
                mantissa >>= 1;
                shift += 1;
            }
        }
        // N ≥ 2⁵³ units is a normal number: m · 2^(shift − 1074), whose
        // biased exponent is shift + 1.
        let biased = u64::from(shift) + 1;
        if biased >= 0x7ff {
            return f64::INFINITY;
        }
        f64::from_bits((biased << 52) | (mantissa & ((1 << 52) - 1)))
    }

    /// Bits `from .. from + count` (count ≤ 64) of the carried sum.
    fn bits(&self, from: u32, count: u32) -> u64 {
        let mut out = 0u128;
        let first = (from / DIGIT_BITS) as usize;
        for (j, k) in (first..DIGITS).take(4).enumerate() {
            out |= u128::from(self.digits[k] as u32) << (DIGIT_BITS * j as u32);
        }
        let out = out >> (from % DIGIT_BITS);
        (out & ((1u128 << count) - 1)) as u64
    }

    /// Whether any of bits `0 .. below` of the carried sum is set.
    fn any_below(&self, below: u32) -> bool {
        let full = (below / DIGIT_BITS) as usize;
        self.digits[..full].iter().any(|&d| d != 0)
            || self.digits[full] as u64 & ((1u64 << (below % DIGIT_BITS)) - 1) != 0
    }
}

/// Exact sums of the conserved quantities ([`crate::ConservationTotals`]):
/// mass, the three momentum components and energy, in that order.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct ExactTotals {
    /// Mass, momentum x, y, z, energy.
    pub sums: [ExactSum; 5],
}

impl ExactTotals {
    /// Adds one contribution exactly.
    #[inline]
    pub fn add(&mut self, mass: f64, momentum: [f64; 3], energy: f64) {
        self.sums[0].add(mass);
        for (s, m) in self.sums[1..4].iter_mut().zip(momentum) {
            s.add(m);
        }
        self.sums[4].add(energy);
    }

    /// The totals, each rounded once.
    pub fn totals(&self) -> crate::ConservationTotals {
        crate::ConservationTotals {
            mass: self.sums[0].value(),
            momentum: std::array::from_fn(|a| self.sums[1 + a].value()),
            energy: self.sums[4].value(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    fn sum(values: &[f64]) -> f64 {
        let mut s = ExactSum::new();
        for &x in values {
            s.add(x);
        }
        s.value()
    }

    #[test]
    fn sums_that_floating_point_addition_gets_wrong_come_out_exact() {
        assert_eq!(sum(&[]), 0.0);
        assert_eq!(sum(&[0.1, 0.2]), 0.1 + 0.2);
        // Left to right, 1e308 + 1 − 1e308 is 0.
        assert_eq!(sum(&[1e308, 1.0, -1e308]), 1.0);
        assert_eq!(sum(&[1.0, 1e-300, -1.0]), 1e-300);
        // 0.1 · 10 in f64 is 0.999…9; exactly, the ten 0.1s sum to
        // 1.0000000000000000555…, which rounds to 1.
        assert_eq!(sum(&[0.1; 10]), 1.0);
        // Subnormals count in units of the smallest.
        let tiny = f64::from_bits(1);
        assert_eq!(sum(&[tiny, tiny, tiny]), f64::from_bits(3));
        assert_eq!(
            sum(&[f64::MIN_POSITIVE, -tiny]).to_bits(),
            0x000f_ffff_ffff_ffff
        );
        assert_eq!(sum(&[-2.5, 2.5]).to_bits(), 0.0f64.to_bits());
        assert_eq!(sum(&[-0.0, -0.0]).to_bits(), 0.0f64.to_bits());
        assert_eq!(sum(&[-3.0, 1.0]), -2.0);
    }

    #[test]
    fn ties_round_to_even_and_the_rest_rounds_to_nearest() {
        let ulp = f64::EPSILON; // the spacing just above 1
                                // 1 + ulp/2: a tie, to the even 1.
        assert_eq!(sum(&[1.0, ulp / 2.0]), 1.0);
        // 1 + ulp + ulp/2: a tie, to the even 1 + 2 ulp.
        assert_eq!(sum(&[1.0, ulp, ulp / 2.0]), 1.0 + 2.0 * ulp);
        // Just above the tie rounds up, just below rounds down.
        assert_eq!(sum(&[1.0, ulp / 2.0, 1e-300]), 1.0 + ulp);
        assert_eq!(sum(&[1.0, ulp / 2.0, -1e-300]), 1.0);
        // A carry out of the mantissa: (2 − ulp) + ulp/2 ties to 2.
        assert_eq!(sum(&[2.0 - ulp, ulp / 2.0]), 2.0);
    }

    #[test]
    fn overflow_and_non_finite_values() {
        assert_eq!(sum(&[f64::MAX, f64::MAX]), f64::INFINITY);
        assert_eq!(sum(&[f64::MAX, f64::MAX, -f64::MAX]), f64::MAX);
        assert_eq!(sum(&[-f64::MAX, -f64::MAX]), f64::NEG_INFINITY);
        assert_eq!(sum(&[1.0, f64::INFINITY]), f64::INFINITY);
        assert_eq!(sum(&[f64::NEG_INFINITY, 1.0]), f64::NEG_INFINITY);
        assert!(sum(&[f64::INFINITY, f64::NEG_INFINITY]).is_nan());
        assert!(sum(&[1.0, f64::NAN]).is_nan());
    }

    #[test]
    fn many_additions_carry_without_overflow() {
        // Digit 33 counts units of 2^(1056 − 1074) = 2⁻¹⁸: a digit of
        // 2⁶¹ (far beyond 2³²) is 2⁴³, and 1.0 adds 2¹⁸ to it.
        let mut s = ExactSum::new();
        s.digits[33] = 1 << 61;
        s.pending = CARRY_EVERY - 3;
        for _ in 0..10 {
            s.add(1.0);
        }
        assert!(s.pending < 10, "carried on the way");
        assert_eq!(s.value(), 2f64.powi(43) + 10.0);
    }

    /// An exactly computed reference: values m · 2^e with e in [−40, 20],
    /// summed as integers in units of 2⁻⁴⁰ (at most 118 bits), rounded by
    /// Rust's i128 → f64 conversion (to nearest, ties to even).
    fn reference(values: &[(i64, i32)]) -> f64 {
        let n: i128 = values.iter().map(|&(m, e)| i128::from(m) << (e + 40)).sum();
        n as f64 * 2f64.powi(-40)
    }

    fn value_of((m, e): (i64, i32)) -> f64 {
        m as f64 * 2f64.powi(e)
    }

    proptest! {
        #[test]
        fn the_sum_is_the_exact_sum_rounded_once(
            values in proptest::collection::vec((-(1i64 << 53) + 1..(1i64 << 53), -40i32..20), 0..24)
        ) {
            let xs: Vec<f64> = values.iter().map(|&v| value_of(v)).collect();
            prop_assert_eq!(sum(&xs).to_bits(), reference(&values).to_bits());
        }

        #[test]
        fn order_and_split_do_not_change_a_bit(
            xs in proptest::collection::vec(proptest::num::f64::NORMAL | proptest::num::f64::SUBNORMAL, 1..40),
            rotate in 0usize..40,
            split in 0usize..40,
        ) {
            let whole = sum(&xs);
            let mut turned = xs.clone();
            turned.reverse();
            let r = rotate % turned.len();
            turned.rotate_left(r);
            prop_assert_eq!(sum(&turned).to_bits(), whole.to_bits());
            // Two accumulators, merged directly and through their words.
            let cut = split % (xs.len() + 1);
            let (mut a, mut b) = (ExactSum::new(), ExactSum::new());
            xs[..cut].iter().for_each(|&x| a.add(x));
            xs[cut..].iter().for_each(|&x| b.add(x));
            let mut merged = a.clone();
            merged.merge(&b);
            prop_assert_eq!(merged.value().to_bits(), whole.to_bits());
            let words: Vec<u64> = a
                .to_words()
                .iter()
                .zip(b.to_words())
                .map(|(x, y)| x.wrapping_add(y))
                .collect();
            let mut from_words = ExactSum::new();
            from_words.add_words(&words);
            prop_assert_eq!(from_words.value().to_bits(), whole.to_bits());
        }
    }
}
