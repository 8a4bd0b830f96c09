//! Tests of the ICE cases: a reduced run of E-RATESTICK (V-SOD-ICE's
//! reduced run is in `brisance_validation::sod_ice`).

use super::*;

/// Reduced E-RATESTICK: a 1D ANFO-K1 stick at h = 2 mm, 6 cm long,
/// detonates and runs within 15 % of D_CJ (measured in the grid's
/// frame 5077 m/s, −14 %, at this coarse cell and short run; the
/// validate case runs finer and longer), and D is the front's speed
/// into the explosive, which moves at −90 m/s ahead of it.
#[test]
fn e_ratestick_reduced() {
    let mut c = brisance::ice::cases::RateStick::seed(2e-3);
    c.length = 0.06;
    c.gauges = [0.03, 0.05];
    let r = run_stick("reduced", &c).unwrap();
    let d = r.result.detonation_velocity.expect("no detonation");
    assert!((d / 5899.0 - 1.0).abs() < 0.15, "{d}");
    let ahead = r.result.velocity_ahead.unwrap();
    assert!((ahead + 90.0).abs() < 0.5, "{ahead}");
    let lab = r.result.lab_velocity.unwrap();
    assert!((d - (lab - ahead)).abs() < 1e-9 * d, "{d} {lab} {ahead}");
    assert!(r.result.burnt_fraction > 0.5);
}
