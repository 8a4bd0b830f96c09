//! Tests of the rate-stick helpers of E-RATESTICK: the grid's cell
//! count and the sticks that fit (the parabola fit's tests are in
//! `brisance_validation::rate_stick`).

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
