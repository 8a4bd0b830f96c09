//! Assembling a solver from a validated scenario.

use brisance_core::Solver;
use brisance_scene::{IntoSolver, PipelineSpec};

use crate::config::{Pipeline, Scenario};
use crate::error::ConfigError;

pub use brisance_scene::PipelineLimits;

/// The limits of a scenario's pipeline on its grid.
pub fn pipeline_limits(s: &Scenario) -> PipelineLimits {
    let geometry = s.domain.geometry;
    match &s.pipeline {
        Pipeline::FdmMpmBridge(b) => b.limits(geometry),
        Pipeline::Ice(ice) => ice.limits(geometry),
        // The fluids' grid with the particles' node fields; the coupled
        // state is checkpointed whole.
        Pipeline::IceMpm(c) => c.limits(geometry),
        Pipeline::Plugin(p) => p.section().limits(geometry),
        Pipeline::Peridynamics(pd) => pd.limits(geometry),
        Pipeline::Mpm(mpm) => mpm.limits(geometry),
        Pipeline::Fdm(f) => f.limits(geometry),
    }
}

pub use brisance_fdm::pipeline::primitive_state;

pub(crate) fn located(path: &str, message: String) -> ConfigError {
    ConfigError {
        file: String::new(),
        position: None,
        field: Some(path.into()),
        message,
    }
}

/// Builds the solver a scenario describes; a particle pipeline's holds
/// the particle sets of `outputs.particle_gauges`
/// ([`Solver::sample_particle_gauge`]). Errors carry the field path; the
/// caller fills in the file and position.
pub fn build_solver(s: &Scenario) -> Result<Box<dyn Solver>, ConfigError> {
    match &s.pipeline {
        Pipeline::Fdm(fdm) => build_owned(fdm, s),
        Pipeline::Mpm(mpm) => build_owned(mpm, s),
        Pipeline::Peridynamics(pd) => build_owned(pd, s),
        Pipeline::Plugin(p) => p
            .section()
            .build(&crate::scene::scene_of(s))
            .map_err(|e| located(&e.field, e.message)),
        Pipeline::FdmMpmBridge(b) => build_owned(b, s),
        Pipeline::IceMpm(c) => build_owned(c, s),
        Pipeline::Ice(ice) => build_owned(ice, s),
    }
}

/// The solver a pipeline's own section builds, by its type (the coupled
/// `IceMpm`, say, for a tool that reads its particles), from the
/// scenario's [`crate::scene`]. Errors carry the field path.
pub fn build_section<P: PipelineSpec>(p: &P, s: &Scenario) -> Result<P::Solver, ConfigError> {
    p.build(&crate::scene::scene_of(s))
        .map_err(|e| located(&e.field, e.message))
}

/// The solver of a pipeline whose crate owns its section
/// ([`PipelineSpec`]), built from the scenario's [`crate::scene`].
fn build_owned<P: PipelineSpec>(p: &P, s: &Scenario) -> Result<Box<dyn Solver>, ConfigError>
where
    P::Solver: IntoSolver,
{
    build_section(p, s).map(IntoSolver::into_solver)
}

/// A one-paragraph description of the assembled pipeline (for `check`).
pub fn describe(s: &Scenario) -> String {
    match &s.pipeline {
        Pipeline::Fdm(fdm) => fdm.describe(&crate::scene::scene_of(s)),
        Pipeline::Mpm(mpm) => mpm.describe(&crate::scene::scene_of(s)),
        Pipeline::Peridynamics(pd) => pd.describe(&crate::scene::scene_of(s)),
        Pipeline::Plugin(p) => p.section().describe(&crate::scene::scene_of(s)),
        Pipeline::Ice(ice) => ice.describe(&crate::scene::scene_of(s)),
        Pipeline::IceMpm(c) => c.describe(&crate::scene::scene_of(s)),
        Pipeline::FdmMpmBridge(b) => b.describe(&crate::scene::scene_of(s)),
    }
}

#[cfg(test)]
mod tests;
