//! Assembling a solver from a validated scenario.

use brisance_core::Solver;
use brisance_scene::PipelineSpec;

use crate::config::Scenario;
use crate::error::ConfigError;

pub use brisance_scene::PipelineLimits;

/// The limits of a scenario's pipeline on its grid.
pub fn pipeline_limits(s: &Scenario) -> PipelineLimits {
    s.pipeline.spec().limits(s.domain.geometry)
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
    s.pipeline
        .spec()
        .build(&crate::scene::scene_of(s))
        .map_err(|e| located(&e.field, e.message))
}

/// The solver a pipeline's own section builds, by its type (the coupled
/// `IceMpm`, say, for a tool that reads its particles), from the
/// scenario's [`crate::scene`]. Errors carry the field path.
pub fn build_section<P: PipelineSpec>(p: &P, s: &Scenario) -> Result<P::Solver, ConfigError> {
    p.build(&crate::scene::scene_of(s))
        .map_err(|e| located(&e.field, e.message))
}

/// A one-paragraph description of the assembled pipeline (for `check`).
pub fn describe(s: &Scenario) -> String {
    s.pipeline.spec().describe(&crate::scene::scene_of(s))
}

#[cfg(test)]
mod tests;
