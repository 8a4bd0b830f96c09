//! The `Ice` pipeline through the composer: its example scenarios load,
//! validate, build and step, and its errors name their fields. The
//! pipeline's section, validation and builder are `brisance_ice`'s
//! (`brisance_ice::pipeline`); the composer hands it the scenario's shared
//! parts (`crate::scene::scene_of`).

use brisance_eos::EosModel;
use brisance_ice::pipeline::IceConfig;
use brisance_ice::{IceReaction, IceSolver};
use brisance_scene::{FieldError, PipelineSpec};

use crate::config::Scenario;

pub(crate) use brisance_ice::pipeline::IceReactionModel;
pub(crate) use brisance_ice::IceRate;

/// The solver the pipeline builds for scenario `s`.
fn build(s: &Scenario, ice: &IceConfig) -> Result<IceSolver<EosModel>, FieldError> {
    ice.build(&crate::scene::scene_of(s))
}

/// The reactions of the pipeline of scenario `s`.
fn reactions(s: &Scenario, ice: &IceConfig) -> Result<Vec<IceReaction>, FieldError> {
    ice.reactions(&crate::scene::scene_of(s))
}

mod tests;
