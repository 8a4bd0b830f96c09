//! V-FLYER reduced: configs/flyer_icempm.ron (a copper plate driven by a
//! 10 GPa gas, ICE–MPM in 1D) at h = 0.125 mm with its GIMP shape
//! functions; the plate's mean velocity at 2 µs against the exact
//! p* t/(ρ₀ L) of `brisance::verification::flyer`. The full sequence in h,
//! with linear shape functions beside it, is `cargo xtask validate --only
//! flyer`.

use brisance::compose::build::{build, Built};
use brisance::compose::load_str;
use brisance::core::Solver;
use brisance::verification::flyer::{interface, mean_velocity, Gas, Hugoniot};

#[test]
fn a_gimp_plate_driven_at_10_gpa_takes_the_exact_impulse() {
    let text = include_str!("../configs/flyer_icempm.ron");
    let sets = [
        "domain.cells=(480,1,1)".to_string(),
        "domain.upper=(0.06,0.000125,0.000125)".to_string(),
        "outputs.lineouts=[]".to_string(),
    ];
    let loaded = load_str("flyer_icempm.ron", text, &sets).unwrap();
    let Built::IceMpm { mut solver, .. } = build(&loaded.scenario).unwrap() else {
        panic!("configs/flyer_icempm.ron is an IceMpm pipeline");
    };
    let t_end = loaded.scenario.time.end;
    while solver.time() < t_end * (1.0 - 1e-12) {
        let dt = solver.stable_dt().unwrap();
        solver.advance(dt.min(t_end - solver.time())).unwrap();
    }
    let ps = solver.mpm().particles();
    let (mut mv, mut m) = (0.0, 0.0);
    for (v, mass) in ps.velocity.iter().zip(&ps.mass) {
        mv += mass * v[0];
        m += mass;
    }
    let copper = Hugoniot {
        density: 8930.0,
        c0: 3619.7,
        s: 1.489,
    };
    let gas = Gas {
        pressure: 1.0e10,
        density: 1260.0,
        gamma: 3.0,
    };
    let exact = mean_velocity(interface(gas, copper), copper, 0.01, t_end);
    let err = mv / m / exact - 1.0;
    // Measured −1.25 % (the particles' softer pressure law accounts for
    // −0.8 %); linear shape functions give −4.3 % here.
    assert!(err.abs() < 0.02, "plate {} m/s against {exact} m/s", mv / m);
}
