//! Solver-level tests: uniform states, conservation, determinism,
//! checkpoints and reduced shock tubes.

use brisance_core::Solver;
use brisance_eos::IdealGas;
use brisance_grid::Level;

use crate::solver::GHOST;
use crate::{
    Advection, CellState, ExchangeCoefficients, IceBoundary, IceOptions, IceSolver, MaterialState,
};

fn mat(theta: f64, density: f64, u: f64) -> MaterialState {
    MaterialState {
        volume_fraction: theta,
        density,
        velocity: [u, 0.0, 0.0],
    }
}

/// Sod tube of one material on `cells` cells to t = `t_end`; returns the solver.
pub(crate) fn sod_one(cells: usize, scheme: Advection, t_end: f64) -> IceSolver<IdealGas> {
    let level = Level::new([0.0; 3], [1.0, 0.1, 0.1], [cells, 1, 1], [1, 1, 1], GHOST).unwrap();
    let mut s = IceSolver::new(
        vec![IdealGas::new(1.4, 1.0, 1.0)],
        level,
        std::array::from_fn(|_| IceBoundary::Outflow),
        ExchangeCoefficients::uniform(1, 0.0, 0.0),
        IceOptions {
            advection: scheme,
            ..Default::default()
        },
        |x| {
            if x[0] < 0.5 {
                CellState {
                    pressure: 1.0,
                    materials: vec![mat(1.0, 1.0, 0.0)],
                }
            } else {
                CellState {
                    pressure: 0.1,
                    materials: vec![mat(1.0, 0.125, 0.0)],
                }
            }
        },
    )
    .unwrap();
    run_to(&mut s, t_end);
    s
}

pub(crate) fn run_to<S: Solver>(s: &mut S, t_end: f64) {
    while s.time() < t_end * (1.0 - 1e-12) {
        let dt = s.stable_dt().unwrap().min(t_end - s.time());
        s.advance(dt).unwrap();
    }
}

#[test]
fn sod_plateaus_are_close_to_the_exact_star_states() {
    let s = sod_one(200, Advection::VanLeer, 0.2);
    let d = s
        .cell_data(&["density".into(), "pressure".into(), "velocity_x".into()])
        .unwrap();
    let (rho, p, u) = (
        d.field("density").unwrap(),
        d.field("pressure").unwrap(),
        d.field("velocity_x").unwrap(),
    );
    for i in (0..200).step_by(10) {
        eprintln!(
            "{:.3} {:.4} {:.4} {:.4}",
            (i as f64 + 0.5) / 200.0,
            rho[i],
            u[i],
            p[i]
        );
    }
    // Toro's exact star state: p* = 0.30313, u* = 0.92745, ρ*L = 0.42632,
    // ρ*R = 0.26557; x = 0.7 lies between contact (0.685) and shock (0.850).
    let i = 150; // x = 0.7525
    assert!((p[i] - 0.30313).abs() < 0.01, "p = {}", p[i]);
    assert!((u[i] - 0.92745).abs() < 0.02, "u = {}", u[i]);
    assert!((rho[i] - 0.26557).abs() < 0.01, "rho = {}", rho[i]);
    let i = 120; // x = 0.6025, left plateau
    assert!((rho[i] - 0.42632).abs() < 0.01, "rho = {}", rho[i]);
}
