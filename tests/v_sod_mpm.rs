//! V-SOD-MPM, reduced: Sod's shock tube with gas particles (GIMP, MUSL,
//! 4 particles per cell, artificial bulk viscosity). docs/validation.md has
//! the 100–800 cell study beside FDM (`cargo xtask validate`).

use brisance::verification::cases::{sod_case, sod_mpm_case, sod_mpm_case_with};

#[test]
fn bulk_viscosity_cuts_the_gimp_sod_error_and_its_ringing() {
    // Measured at 200 cells: L1(ρ) 6.4e-3 with q, 2.4e-2 without; plateau
    // oscillation 7.5 % with q, 8.6 % without (13.4 and 23.4 % without at
    // 400 and 800 cells, 8.7 and 13.7 % with: docs/validation.md). Before
    // the gas particles started at their pressure, the first step's jolt
    // rang at 12.7 % without q at 200 cells.
    let with_q = sod_mpm_case(200, "Gimp").unwrap();
    let without = sod_mpm_case_with(200, "Gimp", "Off").unwrap();
    assert!(
        with_q.l1_density < 0.5 * without.l1_density,
        "L1(ρ) {:e} with q, {:e} without",
        with_q.l1_density,
        without.l1_density
    );
    assert!(
        with_q.plateau_oscillation < without.plateau_oscillation,
        "plateau oscillation {} with q, {} without",
        with_q.plateau_oscillation,
        without.plateau_oscillation
    );
    // Particles carry the mass: it cannot change.
    assert_eq!(with_q.relative_mass_change, 0.0);
}

/// The report's target: the GIMP error falls with refinement. With the bulk
/// viscosity it falls 100 → 200 cells (9.6e-3 → 6.4e-3) and then grows
/// again (7.5e-3 at 400, 1.24e-2 at 800): the particle volumes V = J V⁰
/// drift from the space the particles fill (Σ V_p exceeds the tube by
/// 0.1 % at 100 cells, 3 % at 800), concentrated behind the rarefaction,
/// which the viscosity does not address. See docs/validation.md; cpGIMP
/// (`shape_function: CpGimp`) removes the growth
/// (`v_sod_mpm_cpgimp_error_falls_with_refinement`).
#[test]
#[ignore = "known failing: GIMP L1(ρ) grows again beyond 200 cells, see docs/validation.md"]
fn v_sod_mpm_gimp_error_falls_with_refinement() {
    let errors: Vec<f64> = [100, 200, 400, 800]
        .iter()
        .map(|&n| sod_mpm_case(n, "Gimp").unwrap().l1_density)
        .collect();
    assert!(
        errors.windows(2).all(|w| w[1] < w[0]),
        "GIMP L1(ρ) at 100, 200, 400, 800 cells: {errors:?}"
    );
}

#[test]
fn cpgimp_halves_the_particle_volume_drift_of_ugimp_at_200_cells() {
    // Measured at 200 cells: Σ V_p exceeds the tube by 0.60 % with uGIMP
    // and falls 0.25 % short of it with cpGIMP, whose domains follow the
    // stretch of the gas (docs/physics/mpm/gimp.md); L1(ρ) 6.4e-3 and
    // 5.4e-3.
    let u = sod_mpm_case(200, "Gimp").unwrap();
    let cp = sod_mpm_case(200, "CpGimp").unwrap();
    let (eu, ecp) = (
        u.particle_volume_excess.unwrap(),
        cp.particle_volume_excess.unwrap(),
    );
    assert!(
        ecp.abs() < 0.5 * eu.abs(),
        "volume excess: uGIMP {eu:e}, cpGIMP {ecp:e}"
    );
    assert!(
        cp.l1_density < u.l1_density,
        "L1(ρ): uGIMP {:e}, cpGIMP {:e}",
        u.l1_density,
        cp.l1_density
    );
    assert_eq!(cp.relative_mass_change, 0.0);
    // A grid solver has no particle volumes.
    assert_eq!(sod_case(50).unwrap().particle_volume_excess, None);
}

/// With cpGIMP the error falls at every refinement (9.7e-3, 5.4e-3,
/// 3.2e-3, 2.1e-3 at 100, 200, 400, 800 cells; docs/validation.md).
#[test]
#[ignore = "the full 100–800 cell study; run on demand"]
fn v_sod_mpm_cpgimp_error_falls_with_refinement() {
    let errors: Vec<f64> = [100, 200, 400, 800]
        .iter()
        .map(|&n| sod_mpm_case(n, "CpGimp").unwrap().l1_density)
        .collect();
    assert!(
        errors.windows(2).all(|w| w[1] < w[0]),
        "cpGIMP L1(ρ) at 100, 200, 400, 800 cells: {errors:?}"
    );
}

/// Prints the whole study (`cargo test --test integration v_sod_mpm_table
/// -- --ignored --nocapture`), as `cargo xtask validate` writes it.
#[test]
#[ignore = "prints the V-SOD-MPM study; run on demand"]
fn v_sod_mpm_table() {
    println!(
        "cells | FDM L1 | GIMP L1 | linear L1 | GIMP L1 without q | plateau osc. GIMP / linear | GIMP shock overshoot"
    );
    for n in [100, 200, 400, 800] {
        let f = sod_case(n).unwrap();
        let g = sod_mpm_case(n, "Gimp").unwrap();
        let l = sod_mpm_case(n, "Linear").unwrap();
        let g0 = sod_mpm_case_with(n, "Gimp", "Off").unwrap();
        println!(
            "{n} | {:.3e} | {:.3e} | {:.3e} | {:.3e} | {:.1} % / {:.1} % | {:.1} %",
            f.l1_density,
            g.l1_density,
            l.l1_density,
            g0.l1_density,
            100.0 * g.plateau_oscillation,
            100.0 * l.plateau_oscillation,
            100.0 * g.shock_overshoot,
        );
    }
}
