//! Assembling a solver from a validated scenario.

use brisance_core::Solver;
use brisance_scene::PipelineSpec;

use brisance_mpm::{MpmSolver, ParticleSet, SetQuantity};

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

/// A built run: the solver, and for the particle pipeline the particle
/// sets of `outputs.particle_gauges` (in that order). Dereferences to the
/// solver.
pub enum Built {
    /// A solver without particle gauges.
    Solver(Box<dyn Solver>),
    /// The MPM solver and the particle sets of its particle gauges.
    Mpm {
        /// The solver.
        solver: Box<MpmSolver>,
        /// One set per particle gauge.
        particle_gauges: Vec<ParticleSet>,
    },
    /// The coupled ICE–MPM solver and the particle sets of its gauges.
    IceMpm {
        /// The solver.
        solver: Box<brisance_couple::IceMpm>,
        /// One set per particle gauge (of the solid's particles).
        particle_gauges: Vec<ParticleSet>,
    },
    /// The FDM–MPM bridge and the particle sets of its gauges.
    Bridge {
        /// The solver.
        solver: Box<dyn brisance_couple::BridgeSolver>,
        /// One set per particle gauge (of the MPM region's particles).
        particle_gauges: Vec<ParticleSet>,
    },
}

impl std::ops::Deref for Built {
    type Target = dyn Solver;
    fn deref(&self) -> &Self::Target {
        match self {
            Built::Solver(s) => s.as_ref(),
            Built::Mpm { solver, .. } => solver.as_ref(),
            Built::IceMpm { solver, .. } => solver.as_ref(),
            Built::Bridge { solver, .. } => solver.as_ref(),
        }
    }
}

impl std::ops::DerefMut for Built {
    fn deref_mut(&mut self) -> &mut Self::Target {
        match self {
            Built::Solver(s) => s.as_mut(),
            Built::Mpm { solver, .. } => solver.as_mut(),
            Built::IceMpm { solver, .. } => solver.as_mut(),
            Built::Bridge { solver, .. } => solver.as_mut(),
        }
    }
}

impl Built {
    /// The solver alone.
    pub fn into_solver(self) -> Box<dyn Solver> {
        match self {
            Built::Solver(s) => s,
            Built::Mpm { solver, .. } => solver,
            Built::IceMpm { solver, .. } => solver,
            Built::Bridge { solver, .. } => solver,
        }
    }

    /// Samples particle gauge `k` (its set averages of `quantities`, see
    /// [`ParticleSet::sample`]) into `out`; false when there is no such
    /// gauge.
    pub fn sample_particle_gauge(
        &self,
        k: usize,
        quantities: &[SetQuantity],
        out: &mut Vec<f64>,
    ) -> bool {
        match self {
            Built::Mpm {
                solver,
                particle_gauges,
            } if k < particle_gauges.len() => {
                particle_gauges[k].sample(solver, quantities, out);
                true
            }
            Built::IceMpm {
                solver,
                particle_gauges,
            } if k < particle_gauges.len() => {
                particle_gauges[k].sample(solver.mpm(), quantities, out);
                true
            }
            Built::Bridge {
                solver,
                particle_gauges,
            } if k < particle_gauges.len() => {
                particle_gauges[k].sample(solver.mpm(), quantities, out);
                true
            }
            _ => false,
        }
    }
}

/// Builds the solver a scenario describes. Errors carry the field path;
/// the caller fills in the file and position.
pub fn build_solver(s: &Scenario) -> Result<Box<dyn Solver>, ConfigError> {
    build(s).map(Built::into_solver)
}

/// Builds the solver a scenario describes with its particle gauges. Errors
/// carry the field path; the caller fills in the file and position.
pub fn build(s: &Scenario) -> Result<Built, ConfigError> {
    match &s.pipeline {
        Pipeline::Fdm(fdm) => fdm
            .build(&crate::scene::scene_of(s))
            .map(Built::Solver)
            .map_err(|e| located(&e.field, e.message)),
        Pipeline::Mpm(mpm) => mpm
            .build(&crate::scene::scene_of(s))
            .map(|run| Built::Mpm {
                solver: Box::new(run.solver),
                particle_gauges: run.particle_gauges,
            })
            .map_err(|e| located(&e.field, e.message)),
        Pipeline::Peridynamics(pd) => build_owned(pd, s),
        Pipeline::Plugin(p) => p
            .section()
            .build(&crate::scene::scene_of(s))
            .map(Built::Solver)
            .map_err(|e| located(&e.field, e.message)),
        Pipeline::FdmMpmBridge(b) => b
            .build(&crate::scene::scene_of(s))
            .map(|run| Built::Bridge {
                solver: run.solver,
                particle_gauges: run.particle_gauges,
            })
            .map_err(|e| located(&e.field, e.message)),
        Pipeline::IceMpm(c) => c
            .build(&crate::scene::scene_of(s))
            .map(|run| Built::IceMpm {
                solver: Box::new(run.solver),
                particle_gauges: run.particle_gauges,
            })
            .map_err(|e| located(&e.field, e.message)),
        Pipeline::Ice(ice) => build_owned(ice, s),
    }
}

/// The solver of a pipeline whose crate owns its section
/// ([`PipelineSpec`]), built from the scenario's [`crate::scene`].
fn build_owned<P: PipelineSpec>(p: &P, s: &Scenario) -> Result<Built, ConfigError>
where
    P::Solver: Solver + 'static,
{
    p.build(&crate::scene::scene_of(s))
        .map(|solver| Built::Solver(Box::new(solver)))
        .map_err(|e| located(&e.field, e.message))
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
