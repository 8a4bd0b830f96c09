//! Reaction models that live in their own crates.
//!
//! A model crate implements [`ReactionModel`] and hands a
//! [`ReactionPlugin`] to [`ReactionRegistry::register`]: its RON name, a
//! one-line summary, its docs page, a RON example and the function that
//! builds the model from the parameters a config wrote. The composer
//! builds the one registry of the program from every plugin crate's
//! `register` and [`install`]s it; from then on a config may write
//! `model: ThermalDecomposition(...)` wherever a pipeline takes a reaction
//! model by name, beside the built-in `JwlPlusPlus(...)`, and the pipeline
//! receives a [`PluginReaction`].
//!
//! The built-in models keep their own enum variants in each pipeline's
//! schema, and the solvers their static dispatch; a plugin model costs a
//! virtual call per evaluation. The registry, its installed slot and the
//! parameters as RON text are `brisance_plugin`'s, shared with the
//! equations of state (`brisance_eos::plugin`) and the constitutive
//! models: a plugin receives the RON text of its parameters, so a
//! parameter holding an enum keeps its variant name.

use std::fmt;
use std::sync::Arc;

use brisance_core::ReactionModel;
use brisance_plugin::{Installed, Params, PluginInfo, PluginInstance, Registry};

/// The names of the built-in reaction models, which no plugin may take.
pub const BUILT_IN: &[&str] = &[
    "JwlPlusPlus",
    "Deflagration",
    "ProgramBurn",
    "ProgramBurnRamp",
    "Arrhenius",
];

/// Builds a model from the RON text of the parameters a config wrote (a
/// struct such as `(z: 5.0e19, activation_energy: 2.2e5)`, or its fields
/// alone): the model and its parameters as canonical text. The message of
/// an error names the field (an unknown one, a missing one, one of the
/// wrong type, one out of range).
pub type ParseFn = brisance_plugin::ParseFn<dyn ReactionModel>;

/// What a plugin crate registers for one reaction model.
#[derive(Clone, Copy)]
pub struct ReactionPlugin {
    /// The name a config writes (`ThermalDecomposition`), in the style of
    /// the built-in models.
    pub name: &'static str,
    /// One line on what it is, with its source, for `brisance list`.
    pub summary: &'static str,
    /// The model's docs page, relative to the repository root.
    pub docs: &'static str,
    /// A RON example of the config value; the composer's tests parse it.
    pub example: &'static str,
    /// Builds the model from its parameters.
    pub parse: ParseFn,
}

impl fmt::Debug for ReactionPlugin {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("ReactionPlugin")
            .field("name", &self.name)
            .field("docs", &self.docs)
            .finish_non_exhaustive()
    }
}

impl PluginInfo for ReactionPlugin {
    const FAMILY: &'static str = "reaction model";
    const BUILT_IN: &'static [&'static str] = BUILT_IN;
    type Model = dyn ReactionModel;
    fn name(&self) -> &'static str {
        self.name
    }
    fn summary(&self) -> &'static str {
        self.summary
    }
    fn docs(&self) -> &'static str {
        self.docs
    }
    fn example(&self) -> &'static str {
        self.example
    }
    fn parse(&self, params: &str) -> Result<(Arc<dyn ReactionModel>, Params), String> {
        (self.parse)(params)
    }
}

/// The plugin reaction models of one program, in registration order;
/// [`Registry::register`] refuses a built-in name or a name registered
/// twice.
pub type ReactionRegistry = Registry<ReactionPlugin>;

static INSTALLED: Installed<ReactionPlugin> = Installed::new();

/// Makes `registry` the program's plugin registry, the one the pipelines'
/// schemas resolve names through. The first call wins; a later one gives
/// its registry back.
pub fn install(registry: ReactionRegistry) -> Result<(), ReactionRegistry> {
    INSTALLED.install(registry)
}

/// The installed registry, if any.
pub fn installed() -> Option<&'static ReactionRegistry> {
    INSTALLED.registry()
}

/// The installed slot, for a pipeline schema's serde
/// ([`brisance_plugin::PluginEnum::installed`]).
pub fn slot() -> &'static Installed<ReactionPlugin> {
    &INSTALLED
}

/// The installed plugin registered under `name`.
pub fn find(name: &str) -> Option<&'static ReactionPlugin> {
    INSTALLED.find(name)
}

/// The names of the installed plugins, in registration order.
pub fn plugin_names() -> &'static [&'static str] {
    INSTALLED.plugin_names()
}

/// A plugin model as a pipeline's schema holds it: the registration, the
/// parameters as canonical RON text (so that it serializes back and
/// compares by value), and the model
/// ([`PluginInstance::model`], for a solver that takes any
/// [`ReactionModel`]).
pub type PluginReaction = PluginInstance<ReactionPlugin>;

/// Builds a plugin model whose parameters are the serde struct `T`, with
/// its own check: the usual [`ParseFn`] of a plugin crate,
/// `parse: |v| parse_params::<MyModel>(v, MyModel::validate)`. The text
/// may be the struct `(a: 1.0, ...)` or its fields alone; the message of
/// an error names the field.
pub fn parse_params<T>(
    params: &str,
    validate: fn(&T) -> Result<(), String>,
) -> Result<(Arc<dyn ReactionModel>, Params), String>
where
    T: ReactionModel + serde::Serialize + serde::de::DeserializeOwned + 'static,
{
    let (model, params) = brisance_plugin::parse_params::<T>(params)?;
    validate(&model)?;
    Ok((Arc::new(model), params))
}

#[cfg(test)]
mod tests {
    use super::*;
    use brisance_core::ReactionState;
    use serde::{Deserialize, Serialize};

    /// dF/dt = k.
    #[derive(Debug, Serialize, Deserialize)]
    #[serde(deny_unknown_fields)]
    struct Steady {
        k: f64,
    }

    impl ReactionModel for Steady {
        fn name(&self) -> &'static str {
            "Steady"
        }
        fn rate(&self, _: &ReactionState, _: f64) -> f64 {
            self.k
        }
    }

    fn check(m: &Steady) -> Result<(), String> {
        if m.k >= 0.0 {
            Ok(())
        } else {
            Err(format!("k: must be ≥ 0, got {}", m.k))
        }
    }

    const STEADY: ReactionPlugin = ReactionPlugin {
        name: "Steady",
        summary: "dF/dt = k",
        docs: "docs/physics/reaction/plugins.md",
        example: "Steady(k: 1.0)",
        parse: |v| parse_params::<Steady>(v, check),
    };

    #[test]
    fn a_registered_model_builds_from_its_parameters_and_names_a_bad_field() {
        let mut registry = ReactionRegistry::new();
        registry.register(STEADY);
        let plugin = registry.get("Steady").unwrap();
        let leaked: &'static ReactionPlugin = Box::leak(Box::new(*plugin));
        let m = PluginReaction::new(leaked, "(k: 2.5)").unwrap();
        let state = ReactionState {
            pressure: 0.0,
            temperature: 300.0,
            density: 1.0,
            time: 0.0,
            detonation_time: f64::INFINITY,
            surface_area_density: 0.0,
        };
        assert_eq!(m.model().rate(&state, 0.0), 2.5);
        assert_eq!(m.params(), "(k:2.5)");
        assert_eq!(m, PluginReaction::new(leaked, "(k: 2.5)").unwrap());
        assert_ne!(m, PluginReaction::new(leaked, "(k: 2.0)").unwrap());
        let bad = PluginReaction::new(leaked, "(k: -1.0)").unwrap_err();
        assert!(bad.contains("k"), "{bad}");
        let unknown = PluginReaction::new(leaked, "(k: 1.0, q: 2.0)").unwrap_err();
        assert!(unknown.contains('q'), "{unknown}");
    }

    #[test]
    #[should_panic(expected = "built-in")]
    fn a_plugin_cannot_take_a_built_in_name() {
        ReactionRegistry::new().register(ReactionPlugin {
            name: "JwlPlusPlus",
            ..STEADY
        });
    }

    #[test]
    #[should_panic(expected = "twice")]
    fn a_name_is_registered_once() {
        let mut registry = ReactionRegistry::new();
        registry.register(STEADY);
        registry.register(STEADY);
    }
}
