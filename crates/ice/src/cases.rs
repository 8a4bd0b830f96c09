//! Shock-tube cases of V-SOD-ICE as functions, shared by the unit tests
//! (reduced resolutions) and `cargo xtask validate` (full resolutions).

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

/// Advances `s` to `t_end` at its stable step (the last step shortened to land on it).
pub fn run_to<S: Solver>(s: &mut S, t_end: f64) -> Result<(), brisance_core::SolverError> {
    while s.time() < t_end * (1.0 - 1e-12) {
        let dt = s.stable_dt()?.min(t_end - s.time());
        s.advance(dt)?;
    }
    Ok(())
}

/// Sod tube of one material on `cells` cells to t = `t_end`; returns the solver.
pub fn sod_one(cells: usize, scheme: Advection, t_end: f64) -> IceSolver<IdealGas> {
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
    run_to(&mut s, t_end).unwrap();
    s
}

/// Two-material Sod tube (γ 1.4 left, 1.67 right), each material present
/// everywhere, a trace 1e-6 where it is absent.
pub fn sod_two(cells: usize, scheme: Advection, t_end: f64) -> IceSolver<IdealGas> {
    let level = Level::new([0.0; 3], [1.0, 0.1, 0.1], [cells, 1, 1], [1, 1, 1], GHOST).unwrap();
    let eps = 1e-6;
    let mut s = IceSolver::new(
        vec![IdealGas::new(1.4, 1.0, 1.0), IdealGas::new(1.67, 1.0, 1.0)],
        level,
        std::array::from_fn(|_| IceBoundary::Outflow),
        ExchangeCoefficients::uniform(2, 1e15, 0.0),
        IceOptions {
            advection: scheme,
            ..Default::default()
        },
        |x| {
            if x[0] < 0.5 {
                CellState {
                    pressure: 1.0,
                    materials: vec![mat(1.0 - eps, 1.0, 0.0), mat(eps, 0.125, 0.0)],
                }
            } else {
                CellState {
                    pressure: 0.1,
                    materials: vec![mat(eps, 1.0, 0.0), mat(1.0 - eps, 0.125, 0.0)],
                }
            }
        },
    )
    .unwrap();
    run_to(&mut s, t_end).unwrap();
    s
}

/// Sharpness of the two-material contact and the pressure around it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ContactMeasure {
    /// Distance, in cells, between where θ_1 crosses 0.9 and 0.1 (linear
    /// interpolation between cell centres).
    pub width_cells: f64,
    /// Cells with 0.01 < θ_1 < 0.99.
    pub mixed_cells: usize,
    /// Index of the first cell with θ_1 < 0.5.
    pub contact_cell: usize,
    /// Largest |p − p_ref|/p_ref within 5 cells of the contact, p_ref the
    /// mean of the pressures 8 cells to either side.
    pub pressure_excursion: f64,
}

/// Measures the contact of a two-material tube along x (material 1 on the left).
pub fn contact_width<S: Solver>(s: &S) -> Result<ContactMeasure, String> {
    let d = s
        .cell_data(&["volume_fraction_1".into(), "pressure".into()])
        .map_err(|e| e.to_string())?;
    let th = d.field("volume_fraction_1").ok_or("no volume fraction")?;
    let p = d.field("pressure").ok_or("no pressure")?;
    let crossing = |level: f64| -> Option<f64> {
        (1..th.len())
            .find(|&i| th[i - 1] >= level && th[i] < level)
            .map(|i| (i - 1) as f64 + (th[i - 1] - level) / (th[i - 1] - th[i]))
    };
    let (a, b) = (
        crossing(0.9).ok_or("θ never falls below 0.9")?,
        crossing(0.1).ok_or("θ never falls below 0.1")?,
    );
    let c = th.iter().position(|&t| t < 0.5).ok_or("no contact")?;
    if c < 8 || c + 8 >= th.len() {
        return Err(format!("contact at cell {c} too close to the end"));
    }
    let reference = 0.5 * (p[c - 8] + p[c + 8]);
    let excursion = p[c - 5..c + 5]
        .iter()
        .map(|x| (x - reference).abs())
        .fold(0.0, f64::max)
        / reference;
    Ok(ContactMeasure {
        width_cells: b - a,
        mixed_cells: th.iter().filter(|&&t| t > 0.01 && t < 0.99).count(),
        contact_cell: c,
        pressure_excursion: excursion,
    })
}
