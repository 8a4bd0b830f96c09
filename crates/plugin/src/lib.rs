//! Brisance plugin registries: what the equation-of-state, reaction and
//! constitutive families share to take models from their own crates.
//!
//! A family (`brisance_eos::plugin`, `brisance_reaction::plugin`,
//! `brisance_constitutive::plugin`) defines its registration struct (the
//! RON name, a summary, the docs page, a RON example and the function that
//! builds the model) and implements [`PluginInfo`] for it; everything else
//! is here, generic over that struct:
//!
//! - [`registry`]: [`Registry`], the plugins of one program in
//!   registration order, refusing a built-in name or a name registered
//!   twice; [`Installed`], the process-wide slot a family keeps in a
//!   `static` and installs its registry into once, through which its
//!   model enum's deserializer resolves names.
//! - [`params`]: a plugin's parameters as RON text. The text is taken from
//!   the config through the ron deserializer's raw-value protocol
//!   ([`ParamsText`]), parsed into the plugin's own serde type with the
//!   config reader's extensions ([`parse_params`]), and kept as that type
//!   serialized again ([`Params`]), one canonical text per parameter set,
//!   which writes itself back verbatim.
//! - [`variant`]: [`PluginInstance`], a plugin model as a model enum holds it
//!   (the registration, the canonical parameters, the model), and
//!   [`PluginEnum`] with [`deserialize`] and [`serialize_plugin`], the
//!   serde of a model enum whose built-in variants keep their types and
//!   whose other names go to the installed plugins.
//!
//! The crate knows neither the physics traits nor the solvers: it depends
//! on serde and ron only, so the solver crates stay free of the config
//! format.

pub mod params;
pub mod registry;
pub mod variant;

pub use params::{at_parameter, parameter_position, parse_params, ron_options, Params, ParamsText};
pub use registry::{Installed, PluginInfo, Registry};
pub use variant::{deserialize, serialize_plugin, variant_index, PluginEnum, PluginInstance};

/// Builds a plugin's model from the RON text of the parameters a config
/// wrote (a struct such as `(a: 1.0, rate: Jaumann)`, or its fields alone,
/// `a: 1.0, rate: Jaumann`): the model, behind the family's trait, and its
/// parameters as canonical text. The message of an error names the field
/// (an unknown one, a missing one, one of the wrong type, one out of
/// range).
pub type ParseFn<M> = fn(&str) -> Result<(std::sync::Arc<M>, Params), String>;
