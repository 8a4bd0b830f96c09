//! Tests of the ICE cases: reduced runs of E-RATESTICK and V-SOD-ICE.

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

/// Reduced V-SOD-ICE: L1(ρ) falls between 100 and 200 cells (measured
/// order 0.76) and van Leer beats donor cell.
#[test]
fn v_sod_ice_reduced() {
    let a = ice_tube(100, &sod(), |c, t| sod_one(c, Advection::VanLeer, t)).unwrap();
    let b = ice_tube(200, &sod(), |c, t| sod_one(c, Advection::VanLeer, t)).unwrap();
    let d = ice_tube(100, &sod(), |c, t| sod_one(c, Advection::DonorCell, t)).unwrap();
    let order = (a.l1_density / b.l1_density).ln() / 2f64.ln();
    eprintln!(
        "L1 {:.4e} {:.4e} order {order:.3} donor {:.4e}",
        a.l1_density, b.l1_density, d.l1_density
    );
    assert!(b.l1_density < a.l1_density);
    assert!(order > 0.6, "{order}");
    assert!(a.l1_density < d.l1_density);
    // The tube's ends are outflow faces, so mass conservation to
    // round-off is checked in crates/ice's closed-tube tests instead.
}
