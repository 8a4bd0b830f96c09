//! Tests of the rate-stick helpers of E-RATESTICK: the grid's cell
//! count, the sticks that fit, and the parabola fits of the diameter effect.

use super::*;

#[test]
fn quarter_cells_counts_the_rate_stick_grid() {
    // 10 cm / 1 mm = 100 along the axis, (4 + 6) mm / 1 mm = 10 across.
    assert_eq!(quarter_cells(1e-3, 4e-3), 100 * 10 * 10);
    // At 0.5 mm: 200 × 20 × 20, and 200 × 24 × 24 for R = 6 mm.
    assert_eq!(quarter_cells(0.5e-3, 4e-3), 80_000);
    assert_eq!(quarter_cells(0.5e-3, 6e-3), 115_200);
    assert_eq!(quarter_cells(0.5e-3, 20e-3), 200 * 52 * 52);
}

#[test]
fn only_the_four_millimetre_stick_fits_at_half_a_millimetre() {
    assert_eq!(fine_radii(), vec![4e-3]);
}

#[test]
fn the_parabola_fit_recovers_an_exact_parabola_and_refuses_two_points() {
    let pts: Vec<(f64, f64)> = [0.0, 0.05, 0.1, 0.15]
        .iter()
        .map(|&x| (x, 5900.0 - 3000.0 * x - 40000.0 * x * x))
        .collect();
    let c = quadratic_fit(&pts).unwrap();
    assert!((c[0] - 5900.0).abs() < 1e-6, "{c:?}");
    assert!((c[1] + 3000.0).abs() < 1e-4, "{c:?}");
    assert!((c[2] + 40000.0).abs() < 1e-3, "{c:?}");
    assert!(quadratic_fit(&[(0.0, 1.0), (1.0, 2.0), (1.0, 3.0)]).is_none());
}

#[test]
fn the_llnl_parabola_passes_near_its_ideal_limit_and_falls_with_one_over_r() {
    // The fit's value at 1/R → 0 lies within the data's scatter of the
    // ideal-limit point (5890 m/s), and D falls across the data range.
    let c = quadratic_fit(&LLNL_ANFO_K1).unwrap();
    let d = |x: f64| c[0] + c[1] * x + c[2] * x * x;
    assert!((d(0.0) - 5890.0).abs() < 200.0, "{c:?}");
    assert!(
        d(0.0) > d(0.05) && d(0.05) > d(0.1) && d(0.1) > d(0.15),
        "{c:?}"
    );
}
