//! Open faces through which a flow enters: a uniform stream through a 1D
//! tube and Toro's test 5 (two shocks from moving states, the flow
//! entering through both ends), on the FDM, ICE and MPM pipelines, built
//! from scenario text as a user writes it. The integration tests
//! (`tests/open_faces.rs`, `tests/v_toro5.rs`) run these cases;
//! [`run_tube_outcome`] also keeps what a run that stops reached, for the
//! shock-tube suite ([`super::shock_tubes`]).

use brisance_compose::{build::build_solver, load_str, run::next_step};
use brisance_core::{SafeguardUse, Solver, SolverError};

use super::riemann::toro_test;

/// The methods the cases run on.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Method {
    /// `Fdm(material: "gas", viscosity: Adaptive)`, cfl 0.8.
    Fdm,
    /// `Ice(materials: ["gas"])`, its own cfl 0.4.
    Ice,
    /// `Mpm` with gas particles: an inviscid `Null` material with the same
    /// ideal gas, MUSL, 4 particles per cell, Courant number 0.4, the
    /// given shape function and bulk viscosity (`Off` or `On(...)`).
    Mpm {
        /// `Linear`, `Gimp`, `CpGimp` or `QuadraticBSpline`.
        shape: &'static str,
        /// `Off`, or the config's `On(quadratic: .., linear: ..)`.
        bulk_viscosity: &'static str,
    },
}

impl Method {
    /// The material, pipeline and cfl of the scenario text.
    fn scenario_parts(self) -> (String, String, f64) {
        const GAS: &str = "IdealGas(gamma: 1.4, cv: 1.0, rho0: 1.0)";
        match self {
            Method::Fdm => (
                format!("(eos: {GAS})"),
                "Fdm(material: \"gas\", viscosity: Adaptive)".into(),
                0.8,
            ),
            Method::Ice => (
                format!("(eos: {GAS})"),
                "Ice(materials: [\"gas\"])".into(),
                0.4,
            ),
            Method::Mpm {
                shape,
                bulk_viscosity,
            } => (
                format!("(model: Null(eos: {GAS}, viscosity: 0.0))"),
                format!(
                    "Mpm(shape_function: {shape}, scheme: Musl, ppc: 4, bulk_viscosity: {bulk_viscosity})"
                ),
                0.4,
            ),
        }
    }
}

/// A primitive state (ρ, u, p) of the tube.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TubeState {
    /// Density.
    pub density: f64,
    /// Velocity along the tube.
    pub velocity: f64,
    /// Pressure.
    pub pressure: f64,
}

impl TubeState {
    fn ron(&self) -> String {
        format!(
            "density: {:?}, velocity: ({:?}, 0.0, 0.0), pressure: {:?}",
            self.density, self.velocity, self.pressure
        )
    }
}

/// The scenario text of a 1D tube x ∈ [0, 1] of `cells` cells (0.01 thick)
/// run to `end` by `method`: `left` everywhere, `right` from `diaphragm`
/// on, faces `x_low` and `x_high` (config text, e.g. `ZeroGradient`).
pub fn tube_scenario(
    method: Method,
    cells: usize,
    left: TubeState,
    right: TubeState,
    diaphragm: f64,
    faces: [&str; 2],
    end: f64,
) -> String {
    let (material, pipeline, cfl) = method.scenario_parts();
    format!(
        r#"Scenario(
    name: "tube",
    domain: (lower: (0.0, 0.0, 0.0), upper: (1.0, 0.01, 0.01), cells: ({cells}, 1, 1)),
    boundaries: (x_low: {x_low}, x_high: {x_high}),
    time: (end: {end:?}, cfl: {cfl:?}),
    materials: {{ "gas": {material} }},
    pipeline: {pipeline},
    initial: [
        (region: Everywhere, material: "gas", state: ({left})),
        (region: HalfSpace(point: ({diaphragm:?}, 0, 0), normal: (1, 0, 0)), material: "gas", state: ({right})),
    ],
    outputs: (fields: ["density", "velocity_x", "pressure"]),
)"#,
        x_low = faces[0],
        x_high = faces[1],
        left = left.ron(),
        right = right.ron(),
    )
}

/// The density, velocity and pressure profiles of a run and what it
/// booked.
#[derive(Debug, Clone)]
pub struct TubeRun {
    /// Cell centres.
    pub x: Vec<f64>,
    /// Density per cell.
    pub density: Vec<f64>,
    /// Velocity per cell.
    pub velocity: Vec<f64>,
    /// Pressure per cell.
    pub pressure: Vec<f64>,
    /// Steps taken.
    pub steps: u64,
    /// The faces the solver reports as having held back an inflow.
    pub blocked_inflow: [bool; 6],
    /// (final − initial)/initial of the conservation totals' mass (what
    /// is inside plus what left minus what entered, where the solver books
    /// its faces).
    pub relative_mass_change: f64,
    /// What the solver booked as having left (negative: entered), if it
    /// books it.
    pub outflow_mass: Option<f64>,
    /// Particle methods: the particles at the end and the largest particle
    /// identity (above the initial count when particles entered).
    pub particles: Option<(usize, u64)>,
}

/// Runs `text` to its end time; a run that stops is an error.
pub fn run_tube(text: &str) -> Result<TubeRun, String> {
    let outcome = run_tube_outcome(text, &[])?;
    match outcome.stopped {
        Some(error) => Err(error),
        None => Ok(outcome.run),
    }
}

/// What a tube run reached, whether or not it got to its end time.
#[derive(Debug, Clone)]
pub struct TubeOutcome {
    /// The profiles at the end time, or as the solver left them when it
    /// stopped.
    pub run: TubeRun,
    /// `None` when the run reached its end time; the solver's error when
    /// it stopped.
    pub stopped: Option<String>,
    /// The time reached (that of the last completed step).
    pub time: f64,
    /// The smallest density of any cell, at the start and after every
    /// completed step.
    pub min_density: f64,
    /// The smallest pressure of any cell, at the start and after every
    /// completed step.
    pub min_pressure: f64,
    /// How often the method's safeguards acted (the FDM's face limiter);
    /// empty for a method without any.
    pub safeguards: Vec<SafeguardUse>,
}

/// Runs `text`, with the `--set` overrides `sets`, to its end time with
/// the run loop's step rule, watching the smallest density and pressure.
/// A run that stops is an outcome (`stopped`), not an error; the error is
/// kept for a scenario that does not load or build.
pub fn run_tube_outcome(text: &str, sets: &[String]) -> Result<TubeOutcome, String> {
    let loaded = load_str("tube.ron", text, sets).map_err(|e| e.to_string())?;
    let end = loaded.scenario.time.end;
    let mut solver = build_solver(&loaded.scenario).map_err(|e| loaded.locate(e).to_string())?;
    let m0 = solver.conservation_totals().mass;
    let names = ["density", "velocity_x", "pressure"].map(String::from);
    let smallest = |solver: &dyn Solver| -> Result<(f64, f64), String> {
        let data = solver.cell_data(&names[..]).map_err(|e| e.to_string())?;
        let min = |k: usize| {
            data.fields[k]
                .1
                .iter()
                .cloned()
                .fold(f64::INFINITY, f64::min)
        };
        Ok((min(0), min(2)))
    };
    let (mut min_density, mut min_pressure) = smallest(solver.as_ref())?;
    let mut steps = 0;
    let mut time = solver.time();
    let mut stopped = None;
    // One step of the run loop's rule; whether it reached the end.
    let step = |solver: &mut dyn Solver| -> Result<bool, SolverError> {
        let (dt, hits) = next_step(solver.stable_dt()?, end - solver.time());
        solver.advance(dt)?;
        Ok(hits)
    };
    while end - solver.time() > 0.0 {
        let hits = match step(solver.as_mut()) {
            Ok(hits) => hits,
            Err(e) => {
                stopped = Some(e.to_string());
                break;
            }
        };
        steps += 1;
        time = solver.time();
        let (rho, p) = smallest(solver.as_ref())?;
        min_density = min_density.min(rho);
        min_pressure = min_pressure.min(p);
        if hits {
            break;
        }
    }
    let data = solver.cell_data(&names).map_err(|e| e.to_string())?;
    let g = data.geometry;
    let col = |k: usize| data.fields[k].1.clone();
    let run = TubeRun {
        x: (0..g.cells[0])
            .map(|i| g.cell_centre([i, 0, 0])[0])
            .collect(),
        density: col(0),
        velocity: col(1),
        pressure: col(2),
        steps,
        blocked_inflow: solver.blocked_inflow(),
        relative_mass_change: (solver.conservation_totals().mass - m0) / m0,
        outflow_mass: solver.outflow_totals().map(|o| o.mass),
        particles: solver.particle_data().map(|p| {
            let max = p
                .field("id")
                .map_or(0.0, |v| v.iter().copied().fold(0.0, f64::max));
            (p.positions.len(), max as u64)
        }),
    };
    Ok(TubeOutcome {
        run,
        stopped,
        time,
        min_density,
        min_pressure,
        safeguards: solver.safeguards(),
    })
}

/// The stream of the uniform-stream cases: ρ = 1, u = 0.5, p = 1 (γ =
/// 1.4, Mach 0.42), entering through x_low.
pub const STREAM: TubeState = TubeState {
    density: 1.0,
    velocity: 0.5,
    pressure: 1.0,
};

/// A uniform stream ([`STREAM`]) through a tube of `cells` cells with
/// `x_low` as given and `ZeroGradient` at x_high, run to t = 0.5 (the
/// stream moves a quarter of the tube).
pub fn uniform_stream(method: Method, cells: usize, x_low: &str) -> Result<TubeRun, String> {
    run_tube(&tube_scenario(
        method,
        cells,
        STREAM,
        STREAM,
        1.0,
        [x_low, "ZeroGradient"],
        0.5,
    ))
}

/// The largest |q − q₀|/|q₀| of `values` about `reference`.
pub fn largest_relative_deviation(values: &[f64], reference: f64) -> f64 {
    values
        .iter()
        .map(|v| (v - reference).abs() / reference.abs())
        .fold(0.0, f64::max)
}

/// Toro's test 5 at t = 0.035 on x ∈ [0, 1] with the diaphragm at 0.4 and
/// `faces` at both ends, on `cells` cells; returns the run and its L1
/// density error Σ|ρ − ρ̄_exact| Δx against the exact solution's cell
/// averages.
pub fn toro5_case(
    method: Method,
    cells: usize,
    faces: [&str; 2],
) -> Result<(TubeRun, f64), String> {
    let problem = toro_test(5).ok_or("no Toro test 5")?;
    let state = |s: &super::riemann::PrimitiveState| TubeState {
        density: s.density,
        velocity: s.velocity,
        pressure: s.pressure,
    };
    let (x0, end) = (0.4, 0.035);
    let run = run_tube(&tube_scenario(
        method,
        cells,
        state(&problem.left),
        state(&problem.right),
        x0,
        faces,
        end,
    ))?;
    let exact = problem.solve()?;
    let dx = 1.0 / cells as f64;
    let l1 = exact.l1_density_error(&run.x, &run.density, dx, x0, end);
    Ok((run, l1))
}
