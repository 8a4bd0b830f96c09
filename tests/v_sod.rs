//! V-SOD, reduced: Sod's shock tube at 200 and 400 cells against the exact
//! Riemann solution (docs/validation.md has the full 100–1600 study).
//! Targets from the validation plan: L1(ρ) ≤ 5e-3 at 400 cells, observed
//! order ≥ 0.8, overshoot at shock and contact ≤ 5 % of the jump.

use brisance::verification::cases::{observed_orders, sod_case};

#[test]
fn v_sod_meets_the_accuracy_and_order_targets() {
    let coarse = sod_case(200).unwrap();
    let fine = sod_case(400).unwrap();
    assert!(
        fine.l1_density <= 5e-3,
        "L1(ρ) at 400 cells = {:e}",
        fine.l1_density
    );
    let order = observed_orders(&[200, 400], &[coarse.l1_density, fine.l1_density])[0];
    assert!(order >= 0.8, "observed order 200→400 = {order}");
    for r in [&coarse, &fine] {
        assert!(
            r.contact_overshoot <= 0.05,
            "contact overshoot {} at {} cells",
            r.contact_overshoot,
            r.cells
        );
        // No wave reaches the ends by t = 0.2: mass is conserved to round-off.
        assert!(
            r.relative_mass_change.abs() < 1e-13,
            "mass change {}",
            r.relative_mass_change
        );
    }
}

/// The face limiter's density bounds at shocks remove Lax–Wendroff's
/// ripple behind the shock (5.3 % of the density jump without them, 0.13 %
/// with them, docs/validation.md).
#[test]
fn v_sod_shock_overshoot_is_within_five_percent_of_the_jump() {
    for cells in [200, 400] {
        let r = sod_case(cells).unwrap();
        assert!(
            r.shock_overshoot <= 0.05,
            "density overshoot {} at {cells} cells",
            r.shock_overshoot
        );
        assert!(
            r.shock_pressure_overshoot <= 0.05,
            "pressure overshoot {} at {cells} cells",
            r.shock_pressure_overshoot
        );
    }
}

#[test]
fn v_sod_plateaus_match_the_exact_star_states() {
    // Away from the waves the computed star states are those of the exact
    // solution (p* = 0.30313, u* = 0.92745, Toro table 4.3).
    let r = sod_case(400).unwrap();
    let i = r.x.iter().position(|&x| x > 0.60).unwrap();
    assert!(
        (r.pressure[i] - 0.303_13).abs() < 1e-3,
        "p = {}",
        r.pressure[i]
    );
    assert!(
        (r.velocity[i] - 0.927_45).abs() < 1e-3,
        "u = {}",
        r.velocity[i]
    );
}
