//! The verification cases of docs/validation.md as functions, shared by the
//! integration tests (reduced resolutions) and `cargo xtask validate` (full
//! resolutions), so both measure the same thing.

use brisance_compose::{build::build_solver, load_str, run::advance_to};
use brisance_core::Solver;
use brisance_eos::IdealGas;
use brisance_fdm::{ArtificialViscosity, FdmBoundary, FdmOptions, FdmSolver, PrimitiveState};
use brisance_grid::Level;

use super::riemann::{l1_distance, sod, RiemannSolution};
use super::smooth::AdvectedSine;

/// The V-SOD scenario file.
pub const SOD_CONFIG: &str = include_str!("../../../configs/sod.ron");

/// Observed orders of accuracy between successive refinements:
/// log(e_k / e_{k+1}) / log(n_{k+1} / n_k).
pub fn observed_orders(cells: &[usize], errors: &[f64]) -> Vec<f64> {
    cells
        .windows(2)
        .zip(errors.windows(2))
        .map(|(n, e)| (e[0] / e[1]).ln() / (n[1] as f64 / n[0] as f64).ln())
        .collect()
}

/// Result of one V-SOD run.
#[derive(Debug, Clone)]
pub struct SodResult {
    /// Number of cells.
    pub cells: usize,
    /// Steps taken.
    pub steps: u64,
    /// Cell centres.
    pub x: Vec<f64>,
    /// Computed density, velocity and pressure.
    pub density: Vec<f64>,
    /// Computed velocity.
    pub velocity: Vec<f64>,
    /// Computed pressure.
    pub pressure: Vec<f64>,
    /// Exact cell averages of density, velocity and pressure.
    pub exact_density: Vec<f64>,
    /// Exact velocity cell averages.
    pub exact_velocity: Vec<f64>,
    /// Exact pressure cell averages.
    pub exact_pressure: Vec<f64>,
    /// L1 norm of the density error, Σ|ρ − ρ_exact| Δx.
    pub l1_density: f64,
    /// Largest density overshoot near the contact, as a fraction of the
    /// contact's density jump.
    pub contact_overshoot: f64,
    /// Largest density overshoot near the shock, as a fraction of the
    /// shock's density jump.
    pub shock_overshoot: f64,
    /// Largest pressure overshoot near the shock, as a fraction of the
    /// shock's pressure jump.
    pub shock_pressure_overshoot: f64,
    /// Relative change of total mass over the run.
    pub relative_mass_change: f64,
    /// Largest |ρ − ρ*_L|/ρ*_L on the plateau between the rarefaction tail
    /// and the contact (2 % of the tube in from each end): the size of the
    /// oscillations a scheme leaves in a region that should be constant.
    pub plateau_oscillation: f64,
    /// Particle solvers: (Σ V_p − V_tube)/V_tube at the end, the drift of
    /// the particle volumes away from the volume they fill; `None` for a
    /// grid solver.
    pub particle_volume_excess: Option<f64>,
}

/// Largest excursion of `values[i]` (cells with centre in `[a, b)`) outside
/// the band between `lo` and `hi`, as a fraction of `hi − lo`.
pub(crate) fn overshoot(x: &[f64], values: &[f64], a: f64, b: f64, lo: f64, hi: f64) -> f64 {
    x.iter()
        .zip(values)
        .filter(|(xi, _)| **xi >= a && **xi < b)
        .map(|(_, v)| (v - hi).max(lo - v).max(0.0))
        .fold(0.0, f64::max)
        / (hi - lo)
}

/// Runs V-SOD (configs/sod.ron) at `cells` cells and compares with the
/// exact solution averaged over each cell.
pub fn sod_case(cells: usize) -> Result<SodResult, String> {
    sod_run(cells, &[])
}

/// The artificial bulk viscosity of V-SOD-MPM: LS-DYNA's default
/// coefficients Q₁ = 1.5, Q₂ = 0.06 (docs/physics/mpm/bulk_viscosity.md).
pub const SOD_MPM_BULK_VISCOSITY: &str = "On(quadratic: 1.5, linear: 0.06)";

/// V-SOD-MPM: the same tube with gas particles (an inviscid null material
/// with the same ideal gas, MUSL, 4 particles per cell, Courant number 0.4,
/// the artificial bulk viscosity [`SOD_MPM_BULK_VISCOSITY`]) and rigid tube
/// ends (particles cannot leave an MPM domain the way an Eulerian outflow
/// face lets gas out), with `shape` = `Linear`, `Gimp` or `CpGimp`.
pub fn sod_mpm_case(cells: usize, shape: &str) -> Result<SodResult, String> {
    sod_mpm_case_with(cells, shape, SOD_MPM_BULK_VISCOSITY)
}

/// V-SOD-MPM with the config value `bulk_viscosity` (`Off`, or `On(...)`),
/// to show what the viscosity changes.
pub fn sod_mpm_case_with(
    cells: usize,
    shape: &str,
    bulk_viscosity: &str,
) -> Result<SodResult, String> {
    let sets = [
        format!(
            "pipeline=Mpm(shape_function: {shape}, scheme: Musl, ppc: 4, bulk_viscosity: {bulk_viscosity})"
        ),
        "materials.gas=(model: Null(eos: IdealGas(gamma: 1.4, cv: 1.0, rho0: 1.0), viscosity: 0.0))".to_string(),
        "time.cfl=0.4".to_string(),
        "boundaries.x_low=Reflective".to_string(),
        "boundaries.x_high=Reflective".to_string(),
    ];
    sod_run(cells, &sets)
}

/// Runs configs/sod.ron at `cells` cells with extra `--set` overrides and
/// compares with the exact solution averaged over each cell.
fn sod_run(cells: usize, extra: &[String]) -> Result<SodResult, String> {
    let mut sets = vec![
        format!("domain.cells=({cells},1,1)"),
        format!("outputs.lineouts.0.points={cells}"),
    ];
    sets.extend_from_slice(extra);
    let loaded = load_str("configs/sod.ron", SOD_CONFIG, &sets).map_err(|e| e.to_string())?;
    let end = loaded.scenario.time.end;
    let mut solver = build_solver(&loaded.scenario).map_err(|e| loaded.locate(e).to_string())?;
    let initial_mass = solver.conservation_totals().mass;
    let steps = advance_to(solver.as_mut(), end).map_err(|e| e.to_string())?;
    let names = ["density", "velocity_x", "pressure"].map(String::from);
    let data = solver.cell_data(&names).map_err(|e| e.to_string())?;
    let g = data.geometry;
    let dx = g.spacing[0];
    let x: Vec<f64> = (0..cells).map(|i| g.cell_centre([i, 0, 0])[0]).collect();
    let exact: RiemannSolution = sod().solve()?;
    let averages: Vec<_> = x
        .iter()
        .map(|xc| exact.cell_average(xc - 0.5 * dx, xc + 0.5 * dx, 0.5, end))
        .collect();
    let col = |k: usize| data.fields[k].1.clone();
    let (density, velocity, pressure) = (col(0), col(1), col(2));
    let exact_density: Vec<f64> = averages.iter().map(|s| s.density).collect();
    let l1_density = l1_distance(&density, &exact_density, dx);
    // Windows: the contact between the rarefaction tail and the shock, the
    // shock from half-way to it up to the end of the tube.
    let w = exact.waves();
    let (xc, xs) = (0.5 + w.contact * end, 0.5 + w.right_head * end);
    let xt = 0.5 + w.left_tail * end;
    let mid_cs = 0.5 * (xc + xs);
    let (rho_l, rho_r) = (exact.rho_star_left(), exact.rho_star_right());
    let right = exact.problem().right;
    let contact_overshoot = overshoot(&x, &density, 0.5 * (xt + xc), mid_cs, rho_r, rho_l);
    let shock_overshoot = overshoot(&x, &density, mid_cs, 1.0, right.density, rho_r);
    let shock_pressure_overshoot =
        overshoot(&x, &pressure, mid_cs, 1.0, right.pressure, exact.p_star());
    let plateau_oscillation = x
        .iter()
        .zip(&density)
        .filter(|(xi, _)| **xi > xt + 0.02 && **xi < xc - 0.02)
        .map(|(_, r)| (r - rho_l).abs() / rho_l)
        .fold(0.0, f64::max);
    let final_mass = solver.conservation_totals().mass;
    let tube: f64 = (0..3).map(|d| g.spacing[d] * g.cells[d] as f64).product();
    let particle_volume_excess = solver
        .particle_data()
        .and_then(|p| Some(p.field("volume")?.iter().sum::<f64>() / tube - 1.0));
    Ok(SodResult {
        cells,
        steps,
        x,
        density,
        velocity,
        pressure,
        exact_density,
        exact_velocity: averages.iter().map(|s| s.velocity).collect(),
        exact_pressure: averages.iter().map(|s| s.pressure).collect(),
        l1_density,
        contact_overshoot,
        shock_overshoot,
        shock_pressure_overshoot,
        relative_mass_change: (final_mass - initial_mass) / initial_mass,
        plateau_oscillation,
        particle_volume_excess,
    })
}

/// The smooth problem: a density sine wave ρ = 1 + 0.2 sin(2πx) advected at
/// u = 1 with p = 1 (γ = 1.4) once around the periodic unit interval.
pub fn advected_sine() -> AdvectedSine {
    AdvectedSine {
        mean_density: 1.0,
        amplitude: 0.2,
        velocity: 1.0,
        pressure: 1.0,
        length: 1.0,
        x_min: 0.0,
    }
}

/// L1 density error of the advected sine wave after one period (t = 1) on
/// `cells` cells, with the given viscosity and per-sweep Courant number.
pub fn advected_sine_l1(
    cells: usize,
    viscosity: ArtificialViscosity,
    cfl: f64,
) -> Result<f64, String> {
    let wave = advected_sine();
    let level = Level::new(
        [0.0; 3],
        [1.0, 0.01, 0.01],
        [cells, 1, 1],
        [1, 1, 1],
        brisance_fdm::GHOST,
    )
    .map_err(|e| e.to_string())?;
    let gas = IdealGas::new(1.4, 1.0, 1.0);
    // Initialise with exact cell averages so the comparison is between
    // averages (a second-order scheme otherwise carries an O(h²) offset
    // either way).
    let dx = 1.0 / cells as f64;
    let init = |x: [f64; 3]| PrimitiveState {
        density: wave.cell_average_density(x[0] - 0.5 * dx, x[0] + 0.5 * dx, 0.0),
        velocity: [wave.velocity, 0.0, 0.0],
        pressure: wave.pressure,
    };
    let options = FdmOptions {
        cfl,
        viscosity,
        ..Default::default()
    };
    let mut solver = FdmSolver::new(gas, level, [FdmBoundary::Periodic; 6], options, init)
        .map_err(|e| e.to_string())?;
    let end = 1.0;
    advance_to(&mut solver, end).map_err(|e| e.to_string())?;
    let data = solver
        .cell_data(&["density".to_string()])
        .map_err(|e| e.to_string())?;
    Ok(data.fields[0]
        .1
        .iter()
        .enumerate()
        .map(|(i, rho)| {
            let xc = (i as f64 + 0.5) * dx;
            (rho - wave.cell_average_density(xc - 0.5 * dx, xc + 0.5 * dx, end)).abs()
        })
        .sum::<f64>()
        * dx)
}

/// A 3D box of `n³` cells holding a spherical blast (ideal gas, reflective
/// walls), the throughput benchmark's problem.
pub fn blast_box(n: usize, layout: [usize; 3]) -> Result<FdmSolver<IdealGas>, String> {
    let level = Level::new([0.0; 3], [1.0; 3], [n, n, n], layout, brisance_fdm::GHOST)
        .map_err(|e| e.to_string())?;
    let gas = IdealGas::air();
    FdmSolver::new(
        gas,
        level,
        [FdmBoundary::Reflective; 6],
        FdmOptions::default(),
        |x| {
            let r2 = (x[0] - 0.5).powi(2) + (x[1] - 0.5).powi(2) + (x[2] - 0.5).powi(2);
            let pressure = if r2 < 0.04 { 1.0e6 } else { 1.0e5 };
            PrimitiveState {
                density: if r2 < 0.04 { 5.0 } else { 1.2 },
                velocity: [0.0; 3],
                pressure,
            }
        },
    )
    .map_err(|e| e.to_string())
}

/// An `n × n` plane holding a sphere of compressed air on the axis x = 0
/// (walls all round), read as a planar (x, y) slab or, with
/// `axisymmetric`, as an (r, z) plane: the benchmark of an r–z
/// cell-update against a planar one (docs/physics/axisymmetric.md).
pub fn blast_plane(n: usize, axisymmetric: bool) -> Result<FdmSolver<IdealGas>, String> {
    let geometry = if axisymmetric {
        brisance_core::Geometry::Axisymmetric
    } else {
        brisance_core::Geometry::Cartesian
    };
    let ghost = brisance_fdm::ghost_layers(geometry);
    let level = Level::new([0.0; 3], [1.0, 1.0, 0.01], [n, n, 1], [1, 1, 1], ghost)
        .map_err(|e| e.to_string())?;
    let options = FdmOptions {
        geometry,
        ..Default::default()
    };
    FdmSolver::new(
        IdealGas::air(),
        level,
        [FdmBoundary::Reflective; 6],
        options,
        |x| {
            let inside = x[0] * x[0] + (x[1] - 0.5).powi(2) < 0.04;
            PrimitiveState {
                density: if inside { 5.0 } else { 1.2 },
                velocity: [0.0; 3],
                pressure: if inside { 1.0e6 } else { 1.0e5 },
            }
        },
    )
    .map_err(|e| e.to_string())
}

/// Result of one V-BAR run.
#[derive(Debug, Clone, Copy)]
pub struct BarResult {
    /// Measured period of the first mode, s.
    pub period: f64,
    /// Exact period 4L/c, s.
    pub exact_period: f64,
    /// Largest |E(t) − E(0)|/E(0) over the run.
    pub energy_drift: f64,
    /// Steps taken.
    pub steps: u64,
}

/// V-BAR: an elastic bar 0 ≤ x ≤ L = 1 m on a 1D MPM grid, fixed at x = 0
/// and free at x = L, started in its first mode v(x) = v₀ sin(πx/2L)
/// (hypoelastic, K 60 GPa, G 30 GPa, ρ 8000 kg/m³, 2 particles per cell).
///
/// On a 1D grid the motion is uniaxial *strain*, so the wave speed is the
/// longitudinal c = √((K + 4G/3)/ρ) and the exact period T = 4L/c. The
/// period is measured from the zero crossings of the bar's total momentum
/// (∝ cos ωt); the energy drift is the largest relative change of the total
/// energy over the run.
pub fn v_bar(
    cells_in_bar: usize,
    periods: f64,
    scheme: brisance_mpm::UpdateScheme,
) -> Result<BarResult, String> {
    use brisance_constitutive::{Hypoelastic, MaterialModel, ObjectiveRate, PressureModel};
    use brisance_mpm::{
        fill_shape, FillSpec, GridBoundary, MaterialId, MpmOptions, MpmSolver, Particles, Shape,
    };
    let length = 1.0;
    let (bulk, shear, rho, v0) = (60.0e9, 30.0e9, 8000.0, 1.0);
    let dx = length / cells_in_bar as f64;
    let n = cells_in_bar + 2;
    let level = Level::new([0.0; 3], [n as f64 * dx, 1.0, 1.0], [n, 1, 1], [1, 1, 1], 0)
        .map_err(|e| e.to_string())?;
    let mut particles = Particles::new(0);
    let spec = FillSpec {
        shape: Shape::Box {
            min: [0.0; 3],
            max: [length, 1.0, 1.0],
        },
        ppc: 2,
        density: rho,
        material: MaterialId(0),
        velocity: [0.0; 3],
        temperature: 300.0,
        specific_internal_energy: 0.0,
    };
    fill_shape(&mut particles, &level.geometry, &spec).map_err(|e| e.to_string())?;
    for p in 0..particles.len() {
        particles.velocity[p][0] =
            v0 * (std::f64::consts::PI * particles.position[p][0] / (2.0 * length)).sin();
    }
    let mut boundaries = [GridBoundary::Free; 6];
    boundaries[0] = GridBoundary::Fixed;
    let model = MaterialModel::Hypoelastic(Hypoelastic {
        shear_modulus: shear,
        pressure: PressureModel::Linear { bulk_modulus: bulk },
        rate: ObjectiveRate::Jaumann,
    });
    let options = MpmOptions {
        scheme,
        cfl: 0.4,
        boundaries,
        ..Default::default()
    };
    let mut solver =
        MpmSolver::new(level, vec![model], particles, options).map_err(|e| e.to_string())?;
    let exact_period = 4.0 * length / ((bulk + 4.0 * shear / 3.0) / rho).sqrt();
    let e0 = solver.conservation_totals().energy;
    let mut drift: f64 = 0.0;
    let mut crossings = Vec::new();
    let mut last = (0.0, solver.conservation_totals().momentum[0]);
    let mut steps = 0;
    while solver.time() < periods * exact_period {
        let dt = solver.stable_dt().map_err(|e| e.to_string())?;
        solver.advance(dt).map_err(|e| e.to_string())?;
        steps += 1;
        let t = solver.conservation_totals();
        drift = drift.max((t.energy - e0).abs() / e0);
        let now = (solver.time(), t.momentum[0]);
        if last.1 > 0.0 && now.1 <= 0.0 || last.1 < 0.0 && now.1 >= 0.0 {
            crossings.push(last.0 + (now.0 - last.0) * last.1 / (last.1 - now.1));
        }
        last = now;
    }
    // Successive zero crossings are half a period apart.
    let k = crossings.len();
    if k < 3 {
        return Err(format!("only {k} zero crossings of the momentum"));
    }
    let period = 2.0 * (crossings[k - 1] - crossings[0]) / (k - 1) as f64;
    Ok(BarResult {
        period,
        exact_period,
        energy_drift: drift,
        steps,
    })
}
