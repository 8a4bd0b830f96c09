//! Assembling a solver from a validated scenario.

use brisance_core::{Eos, Solver};
use brisance_eos::IdealGas;
use brisance_fdm::{ArtificialViscosity, FdmBoundary, FdmOptions, FdmSolver, PrimitiveState};
use brisance_grid::Level;

use brisance_eos::EosModel;

use crate::config::{BoundaryConfig, Pipeline, Region, Scenario, StateConfig, ViscosityConfig};
use crate::error::ConfigError;

/// What validation needs to know about a pipeline.
#[derive(Debug, Clone, Copy)]
pub struct PipelineLimits {
    /// Output field names.
    pub fields: &'static [&'static str],
    /// Largest Courant number the scheme is stable at.
    pub max_cfl: f64,
    /// Ghost layers each patch must hold.
    pub ghost: usize,
}

/// The limits of a pipeline.
pub fn pipeline_limits(p: &Pipeline) -> PipelineLimits {
    match p {
        Pipeline::Fdm(_) => PipelineLimits {
            fields: &FdmSolver::<IdealGas>::FIELDS,
            max_cfl: brisance_fdm::solver::MAX_CFL,
            ghost: brisance_fdm::sweep::GHOST,
        },
    }
}

/// Whether `x` lies in the region.
pub fn region_contains(r: &Region, x: [f64; 3]) -> bool {
    let dot = |a: [f64; 3], b: [f64; 3]| a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
    let sub = |a: [f64; 3], b: [f64; 3]| [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
    match r {
        Region::Everywhere => true,
        Region::Box { min, max } => (0..3).all(|d| x[d] >= min[d] && x[d] <= max[d]),
        Region::Sphere { centre, radius } => {
            let v = sub(x, *centre);
            dot(v, v) <= radius * radius
        }
        Region::Cylinder {
            base,
            axis,
            radius,
            length,
        } => {
            let n = dot(*axis, *axis).sqrt();
            let a = axis.map(|c| c / n);
            let v = sub(x, *base);
            let s = dot(v, a);
            let r = sub(v, a.map(|c| c * s));
            (0.0..=*length).contains(&s) && dot(r, r) <= radius * radius
        }
        Region::HalfSpace { point, normal } => dot(sub(x, *point), *normal) >= 0.0,
    }
}

/// The primitive state a [`StateConfig`] describes, for material `eos`.
pub fn primitive_state<E: Eos>(eos: &E, s: &StateConfig) -> Result<PrimitiveState, String> {
    let pressure = match (s.pressure, s.specific_internal_energy, s.temperature) {
        (Some(p), _, _) => p,
        (None, Some(e), _) => eos.pressure(s.density, e),
        (None, None, Some(t)) => eos.pressure(
            s.density,
            eos.specific_internal_energy_from_temperature(s.density, t),
        ),
        _ => return Err("no pressure, energy or temperature".into()),
    };
    Ok(PrimitiveState {
        density: s.density,
        velocity: s.velocity,
        pressure,
    })
}

fn located(path: &str, message: String) -> ConfigError {
    ConfigError {
        file: String::new(),
        position: None,
        field: Some(path.into()),
        message,
    }
}

/// Builds the solver a scenario describes. Errors carry the field path;
/// the caller fills in the file and position.
pub fn build_solver(s: &Scenario) -> Result<Box<dyn Solver>, ConfigError> {
    let d = &s.domain;
    let Pipeline::Fdm(fdm) = &s.pipeline;
    let level = Level::new(
        d.lower,
        d.upper,
        d.cells,
        d.patches,
        brisance_fdm::sweep::GHOST,
    )
    .map_err(|e| located("domain.patches", e.to_string()))?;
    let eos = s
        .materials
        .get(&fdm.material)
        .and_then(|m| m.eos())
        .ok_or_else(|| located("pipeline.material", "unknown material".into()))?;
    // The ideal gas gets its own monomorphic solver; other gases go through
    // the model enum.
    match eos {
        EosModel::IdealGas(gas) => build_fdm(s, level, *gas),
        other => build_fdm(s, level, other.clone()),
    }
}

/// The FDM solver of scenario `s` for gas `eos` on `level`.
fn build_fdm<E: Eos + 'static>(
    s: &Scenario,
    level: Level,
    eos: E,
) -> Result<Box<dyn Solver>, ConfigError> {
    let Pipeline::Fdm(fdm) = &s.pipeline;
    let d = &s.domain;
    let mut boundaries = [FdmBoundary::Outflow; 6];
    for (k, (face, bc)) in s.boundaries.faces().into_iter().enumerate() {
        boundaries[k] = match bc {
            BoundaryConfig::Outflow => FdmBoundary::Outflow,
            BoundaryConfig::Reflective => FdmBoundary::Reflective,
            BoundaryConfig::Periodic => FdmBoundary::Periodic,
            BoundaryConfig::Fixed(state) => FdmBoundary::Fixed(
                primitive_state(&eos, state)
                    .map_err(|m| located(&format!("boundaries.{face}"), m))?,
            ),
        };
    }
    let states = s
        .initial
        .iter()
        .enumerate()
        .map(|(i, r)| {
            primitive_state(&eos, &r.state).map_err(|m| located(&format!("initial.{i}.state"), m))
        })
        .collect::<Result<Vec<_>, _>>()?;
    // Every cell must be covered; find an uncovered one before building.
    let geometry = level.geometry;
    let covered = |x: [f64; 3]| s.initial.iter().any(|r| region_contains(&r.region, x));
    for k in 0..d.cells[2] {
        for j in 0..d.cells[1] {
            for i in 0..d.cells[0] {
                let x = geometry.cell_centre([i, j, k]);
                if !covered(x) {
                    return Err(located("initial", format!("cell ({i}, {j}, {k}) at {x:?} is in no initial region; add an `Everywhere` region first")));
                }
            }
        }
    }
    let init = |x: [f64; 3]| {
        // Later regions override earlier ones.
        let idx = s
            .initial
            .iter()
            .rposition(|r| region_contains(&r.region, x))
            .unwrap_or(0);
        states[idx]
    };
    let options = FdmOptions {
        cfl: s.time.cfl,
        viscosity: match fdm.viscosity {
            ViscosityConfig::Adaptive => ArtificialViscosity::Adaptive,
            ViscosityConfig::Constant(eta) => ArtificialViscosity::Constant(eta),
            ViscosityConfig::Off => ArtificialViscosity::Off,
        },
        ..Default::default()
    };
    let solver = FdmSolver::new(eos, level, boundaries, options, init)
        .map_err(|e| located("pipeline", e.to_string()))?;
    Ok(Box::new(solver))
}

/// A one-paragraph description of the assembled pipeline (for `check`).
pub fn describe(s: &Scenario) -> String {
    let d = &s.domain;
    let Pipeline::Fdm(fdm) = &s.pipeline;
    let dims = d.cells.iter().filter(|&&c| c > 1).count();
    format!(
        "scenario `{}`: Fdm pipeline (Lax-Wendroff Euler, seed 001 §2.1), {dims}D\n  \
         grid: {} x {} x {} cells = {} cells in {} x {} x {} patches, from {:?} to {:?} m\n  \
         gas: `{}` ({}), viscosity {:?}\n  \
         time: to {} s at cfl {}\n  \
         boundaries: {}\n  \
         initial regions: {}\n  \
         outputs: interval {:?}, fields [{}], {} gauges, {} line-outs, checkpoints every {:?} steps",
        s.name,
        d.cells[0],
        d.cells[1],
        d.cells[2],
        d.cells.iter().product::<usize>(),
        d.patches[0],
        d.patches[1],
        d.patches[2],
        d.lower,
        d.upper,
        fdm.material,
        s.materials
            .get(&fdm.material)
            .and_then(|m| m.eos())
            .map_or("?", |e| e.variant()),
        fdm.viscosity,
        s.time.end,
        s.time.cfl,
        s.boundaries.faces().iter().map(|(f, b)| format!("{f}={}", bc_name(b))).collect::<Vec<_>>().join(" "),
        s.initial.len(),
        s.outputs.interval,
        s.outputs.fields.join(", "),
        s.outputs.gauges.len(),
        s.outputs.lineouts.len(),
        s.outputs.checkpoint_every,
    )
}

fn bc_name(b: &BoundaryConfig) -> &'static str {
    match b {
        BoundaryConfig::Outflow => "outflow",
        BoundaryConfig::Reflective => "reflective",
        BoundaryConfig::Periodic => "periodic",
        BoundaryConfig::Fixed(_) => "fixed",
    }
}
