//! The [`Solver`](brisance_core::Solver) contract
//! (`brisance_core::solver_contract`) on every pipeline, each built by the
//! composer from a shipped scenario on a small grid: one line per solver.
//! Conservation is checked where the scheme conserves on the problem in
//! the steps taken (no wave has reached an open face yet). Each line is a
//! proptest over where the checkpoint falls, how many steps follow it and
//! the fraction of the stable Δt each step takes.

use brisance_core::solver_contract::{check_solver, SolverContract};
use proptest::prelude::*;

/// Loads `configs/<config>` with `sets`, and checks the contract `c` on
/// the solvers it builds.
fn check(config: &str, sets: &[&str], c: SolverContract) {
    let path = format!("{}/../../configs/{config}", env!("CARGO_MANIFEST_DIR"));
    let text = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{path}: {e}"));
    let sets: Vec<String> = sets.iter().map(|s| s.to_string()).collect();
    let loaded = crate::load::load_str(config, &text, &sets).unwrap_or_else(|e| panic!("{e}"));
    let make = || crate::build::build_solver(&loaded.scenario).unwrap_or_else(|e| panic!("{e}"));
    check_solver(&make, &c).unwrap_or_else(|e| panic!("{config}: {e}"));
}

/// One proptest per solver: `$contract` maps (steps before the
/// checkpoint, steps after it, Δt fraction) to the contract checked.
macro_rules! solver_contract {
    ($name:ident, $config:expr, $sets:expr, $contract:expr) => {
        proptest! {
            #![proptest_config(ProptestConfig::with_cases(3))]
            #[test]
            fn $name(before in 1usize..4, after in 1usize..4, fraction in 0.3f64..1.0) {
                let contract: fn(usize, usize, f64) -> SolverContract = $contract;
                check($config, &$sets, contract(before, after, fraction));
            }
        }
    };
}

solver_contract!(fdm, "sod.ron", ["domain.cells=(64,1,1)"], |b, a, f| {
    SolverContract::new(b, a)
        .with_dt_fraction(f)
        .conserving_mass(1e-14)
        .conserving_energy(1e-14)
});
solver_contract!(
    fdm_on_rings,
    "rz_blast.ron",
    ["domain.cells=(12,24,1)"],
    |b, a, f| { SolverContract::new(b, a).with_dt_fraction(f) }
);
solver_contract!(ice, "sod_ice.ron", ["domain.cells=(64,1,1)"], |b, a, f| {
    SolverContract::new(b, a)
        .with_dt_fraction(f)
        .conserving_mass(1e-14)
        .conserving_energy(1e-14)
});
solver_contract!(
    ice_implicit_pressure,
    "sod_ice.ron",
    // Gas at rest gives the implicit step no bound (its Δt follows the
    // material velocity): the tube moves at 0.5.
    [
        "domain.cells=(64,1,1)",
        "pipeline.pressure=Implicit(tolerance: 1e-12)",
        "initial=[(region: Everywhere, material: \"gas\", state: (density: 1.0, pressure: 1.0, velocity: (0.5, 0, 0))), (region: HalfSpace(point: (0.5, 0, 0), normal: (1, 0, 0)), material: \"gas\", state: (density: 0.125, pressure: 0.1, velocity: (0.5, 0, 0)))]"
    ],
    |b, a, f| SolverContract::new(b, a)
        .with_dt_fraction(f)
        .conserving_mass(1e-14)
);
solver_contract!(
    mpm,
    "taylor2d.ron",
    ["domain.cells=(10,20,1)"],
    |b, a, f| {
        SolverContract::new(b, a)
            .with_dt_fraction(f)
            .conserving_mass(1e-14)
    }
);
solver_contract!(
    ice_mpm,
    "piston_icempm.ron",
    ["domain.cells=(50,1,1)"],
    |b, a, f| { SolverContract::new(b, a).with_dt_fraction(f) }
);
solver_contract!(
    ice_mpm_on_rings,
    "default.ron",
    [
        "domain.cells=(10,28,1)",
        "outputs.particle_gauges=[]",
        "outputs.plots=[]"
    ],
    |b, a, f| SolverContract::new(b, a).with_dt_fraction(f)
);
solver_contract!(
    fdm_mpm_bridge,
    "plate_case1_rz.ron",
    ["domain.cells=(54,46,1)", "pipeline.w=Some(4)"],
    |b, a, f| { SolverContract::new(5 * b, 5 * a).with_dt_fraction(f) }
);
solver_contract!(peridynamics, "pd_cylinder.ron", [], |b, a, f| {
    SolverContract::new(b, a).with_dt_fraction(f)
});
solver_contract!(lattice, "lattice_impact.ron", [], |b, a, f| {
    SolverContract::new(b, a).with_dt_fraction(f)
});
solver_contract!(
    one_dimensional_detonation,
    "ratestick_1d.ron",
    ["domain.cells=(50,1,1)"],
    |b, a, f| { SolverContract::new(b, a).with_dt_fraction(f) }
);
