//! V-WATER-AIR-ICE: the water–air shock tube (Saurel & Abgrall 1999;
//! Murrone & Guillard 2005) run by the two-material ICE solver and compared
//! with the exact solution of [`crate::riemann`]. Water (stiffened gas,
//! γ = 4.4, p∞ = 6 × 10⁸ Pa) at 10⁹ Pa and 1000 kg/m³ on [0, x0), air
//! (γ = 1.4) at 10⁵ Pa and 50 kg/m³ on (x0, 1], x0 = 0.7, t = 240 µs: a
//! density ratio of 20 and a pressure ratio of 10⁴ across the interface,
//! the stress test of the equilibration pressure (seed 000 eq 7) in cells
//! that hold both a stiff liquid and a gas.

use brisance_core::{Solver, SolverError};
use brisance_grid::Level;

use crate::riemann::{ExactRiemann, RiemannSide};
use crate::solver::GHOST;
use crate::MaterialState;
use crate::{Advection, CellState, ExchangeCoefficients, IceBoundary, IceOptions, IceSolver};
use brisance_eos::StiffenedGas;

/// Settings of the water–air tube.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WaterAir {
    /// Cells along x on [0, 1] m.
    pub cells: usize,
    /// End time, s (the standard case: 240 µs).
    pub t_end: f64,
    /// Advection scheme.
    pub advection: Advection,
    /// Volume fraction of the absent material on each side.
    pub trace: f64,
}

impl WaterAir {
    /// The standard case on `cells` cells.
    pub fn standard(cells: usize) -> Self {
        Self {
            cells,
            t_end: 240e-6,
            advection: Advection::VanLeer,
            trace: 1e-6,
        }
    }
}

/// Interface position, m.
pub const X0: f64 = 0.7;
/// Left (water) and right (air) states.
pub const WATER: (f64, f64) = (1000.0, 1.0e9);
/// Right (air) state (ρ, p).
pub const AIR: (f64, f64) = (50.0, 1.0e5);

/// What the tube measured against the exact solution.
#[derive(Debug, Clone, PartialEq)]
pub struct WaterAirResult {
    /// Exact star pressure and velocity.
    pub p_star: f64,
    /// Exact contact velocity, m/s.
    pub u_star: f64,
    /// L1 error of the mixture density, Σ|ρ − ρ_exact|Δx, kg/m².
    pub l1_density: f64,
    /// `l1_density` over ∫ρ_exact dx.
    pub l1_density_relative: f64,
    /// Air shock position measured (pressure half-way between p_R and p*), m.
    pub shock_position: f64,
    /// Exact air shock position, m.
    pub shock_position_exact: f64,
    /// Contact position measured (θ_water = 0.5), m.
    pub contact_position: f64,
    /// Exact contact position, m.
    pub contact_position_exact: f64,
    /// Largest equilibration iteration count of any cell in any step.
    pub max_iterations: usize,
    /// Mean equilibration iterations per cell and step.
    pub mean_iterations: f64,
    /// Largest |1 − Σθ| left by the equilibration in any step.
    pub max_residual: f64,
    /// Steps taken.
    pub steps: u64,
    /// Cell centres, mixture density, pressure, velocity, θ_water, and the
    /// exact density, pressure and velocity (for plots).
    pub profile: Vec<[f64; 8]>,
}

/// Builds the tube (materials: water, air).
pub fn water_air_solver(cfg: &WaterAir) -> Result<IceSolver<StiffenedGas>, String> {
    let level = Level::new(
        [0.0; 3],
        [1.0, 0.01, 0.01],
        [cfg.cells, 1, 1],
        [1, 1, 1],
        GHOST,
    )
    .map_err(|e| e.to_string())?;
    let eps = cfg.trace;
    let mat = |theta: f64, density: f64| MaterialState {
        volume_fraction: theta,
        density,
        velocity: [0.0; 3],
    };
    IceSolver::new(
        vec![StiffenedGas::water(), StiffenedGas::air()],
        level,
        std::array::from_fn(|_| IceBoundary::Outflow),
        ExchangeCoefficients::uniform(2, 1e15, 0.0),
        IceOptions {
            advection: cfg.advection,
            // The stiffened-gas water must stay on its own EOS through
            // step 2 (docs/physics/ice/water_air.md).
            fixed_energy_equilibration: true,
            ..Default::default()
        },
        |x| {
            let (p, th) = if x[0] < X0 {
                (WATER.1, 1.0 - eps)
            } else {
                (AIR.1, eps)
            };
            CellState {
                pressure: p,
                materials: vec![mat(th, WATER.0), mat(1.0 - th, AIR.0)],
            }
        },
    )
    .map_err(|e| e.to_string())
}

/// The exact solution of the tube.
pub fn water_air_exact() -> Result<ExactRiemann, String> {
    let (w, a) = (StiffenedGas::water(), StiffenedGas::air());
    ExactRiemann::solve(
        RiemannSide {
            gamma: w.gamma,
            p_inf: w.p_inf,
            rho: WATER.0,
            u: 0.0,
            p: WATER.1,
        },
        RiemannSide {
            gamma: a.gamma,
            p_inf: a.p_inf,
            rho: AIR.0,
            u: 0.0,
            p: AIR.1,
        },
    )
}

/// Runs the tube and measures it against the exact solution.
pub fn water_air(cfg: &WaterAir) -> Result<WaterAirResult, String> {
    let exact = water_air_exact()?;
    let mut s = water_air_solver(cfg)?;
    let (mut max_it, mut max_res, mut total) = (0usize, 0.0f64, 0u64);
    let run = |s: &mut IceSolver<StiffenedGas>| -> Result<(), SolverError> {
        let dt = s.stable_dt()?.min(cfg.t_end - s.time());
        s.advance(dt)
    };
    while s.time() < cfg.t_end * (1.0 - 1e-12) {
        run(&mut s).map_err(|e| e.to_string())?;
        let st = s.equilibration_stats();
        max_it = max_it.max(st.max_iterations);
        max_res = max_res.max(st.max_residual);
        total += st.total_iterations;
    }
    let names: Vec<String> = ["density", "pressure", "velocity_x", "volume_fraction_1"]
        .iter()
        .map(|s| s.to_string())
        .collect();
    let d = s.cell_data(&names).map_err(|e| e.to_string())?;
    let field = |n: &str| d.field(n).ok_or(format!("no field {n}"));
    let (rho, p, u, th) = (
        field("density")?,
        field("pressure")?,
        field("velocity_x")?,
        field("volume_fraction_1")?,
    );
    let n = cfg.cells;
    let h = 1.0 / n as f64;
    let t = s.time();
    let mut profile = Vec::with_capacity(n);
    let (mut l1, mut mass) = (0.0, 0.0);
    for i in 0..n {
        let x = (i as f64 + 0.5) * h;
        let e = exact.sample((x - X0) / t);
        l1 += (rho[i] - e.rho).abs() * h;
        mass += e.rho * h;
        profile.push([x, rho[i], p[i], u[i], th[i], e.rho, e.p, e.u]);
    }
    // Air shock: the last crossing, from the right, of p half-way between
    // the air and star pressures.
    let level = 0.5 * (AIR.1 + exact.p_star);
    let shock = (1..n)
        .rev()
        .find(|&i| p[i - 1] >= level && p[i] < level)
        .map(|i| (i as f64 - 0.5 + (p[i - 1] - level) / (p[i - 1] - p[i])) * h)
        .ok_or("no air shock found")?;
    let contact = (1..n)
        .find(|&i| th[i - 1] >= 0.5 && th[i] < 0.5)
        .map(|i| (i as f64 - 0.5 + (th[i - 1] - 0.5) / (th[i - 1] - th[i])) * h)
        .ok_or("no contact found")?;
    let speed = exact.shock_speeds()[1].ok_or("exact solution has no air shock")?;
    Ok(WaterAirResult {
        p_star: exact.p_star,
        u_star: exact.u_star,
        l1_density: l1,
        l1_density_relative: l1 / mass,
        shock_position: shock,
        shock_position_exact: X0 + speed * t,
        contact_position: contact,
        contact_position_exact: X0 + exact.u_star * t,
        max_iterations: max_it,
        mean_iterations: total as f64 / (s.steps().max(1) as f64 * n as f64),
        max_residual: max_res,
        steps: s.steps(),
        profile,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Reduced tube (100 cells, the standard 240 µs). Tolerances of
    /// V-WATER-AIR-ICE at this resolution: the run completes, relative
    /// L1(ρ) ≤ 5 %, air shock and contact within 2 cells of the exact ones.
    /// With the fixed-energy equilibration (`IceOptions::
    /// fixed_energy_equilibration`, which this case turns on) the tube runs;
    /// it fails the shock bound: the air shock lags the exact one by about
    /// 2.5 cells at this resolution (V-WATER-AIR-ICE in docs/validation.md):
    /// the air in the smeared contact is four to seven times too dense,
    /// because step 12's separately limited total energy and velocity drain
    /// its internal energy where its kinetic energy is 10–30 times larger
    /// (docs/physics/ice/water_air.md, "Why the air shock lags two cells").
    #[test]
    #[ignore = "fails: the air shock lags the exact one by about 2.5 cells against the 2-cell bound (docs/validation.md, V-WATER-AIR-ICE)"]
    fn reduced_water_air_tube_tracks_the_exact_solution() {
        let r = water_air(&WaterAir::standard(100)).unwrap();
        let h = 0.01;
        assert!(r.l1_density_relative <= 0.05, "{}", r.l1_density_relative);
        assert!((r.shock_position - r.shock_position_exact).abs() <= 2.0 * h);
        assert!((r.contact_position - r.contact_position_exact).abs() <= 2.0 * h);
    }

    /// The parts of the reduced tube that hold: it runs to 240 µs (it
    /// stopped in its first step with the isothermal equilibration),
    /// relative L1(ρ) ≤ 5 % and the contact within 2 cells of the exact
    /// one.
    #[test]
    fn reduced_water_air_tube_runs_and_places_the_contact() {
        let r = water_air(&WaterAir::standard(100)).unwrap();
        let h = 0.01;
        assert!(r.l1_density_relative <= 0.05, "{}", r.l1_density_relative);
        assert!(
            (r.contact_position - r.contact_position_exact).abs() <= 2.0 * h,
            "contact {} vs {}",
            r.contact_position,
            r.contact_position_exact
        );
    }

    /// The initial state is in pressure equilibrium per side: the first
    /// equilibration of a water and an air cell returns 10⁹ and 10⁵ Pa with
    /// the given densities.
    #[test]
    fn initial_state_is_equilibrated() {
        let s = water_air_solver(&WaterAir::standard(10)).unwrap();
        let names = [
            "pressure".to_string(),
            "density_1".to_string(),
            "density_2".to_string(),
        ];
        let d = s.cell_data(&names).unwrap();
        let (p, rw, ra) = (&d.fields[0].1, &d.fields[1].1, &d.fields[2].1);
        assert!((p[0] - 1e9).abs() < 1e-6 * 1e9, "{}", p[0]);
        assert!((p[9] - 1e5).abs() < 1e-6 * 1e5, "{}", p[9]);
        // The fields are the averaged densities θ_r ρ_r.
        let main = 1.0 - 1e-6;
        assert!((rw[0] - 1000.0 * main).abs() < 1e-9, "{}", rw[0]);
        assert!((ra[9] - 50.0 * main).abs() < 1e-9, "{}", ra[9]);
    }

    /// The exact solution of the standard case: a rarefaction into the
    /// water and a shock into the air; p* between the two pressures.
    #[test]
    fn exact_solution_has_a_rarefaction_and_a_shock() {
        let e = water_air_exact().unwrap();
        let [left, right] = e.shock_speeds();
        assert!(left.is_none());
        let s = right.unwrap();
        assert!(s > e.u_star && e.u_star > 0.0);
        assert!(e.p_star > AIR.1 && e.p_star < WATER.1);
    }
}
