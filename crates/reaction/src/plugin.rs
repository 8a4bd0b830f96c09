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
//! virtual call per evaluation. The same scheme serves the equations of
//! state (`brisance_eos::plugin`).

use std::fmt;
use std::sync::{Arc, OnceLock};

use brisance_core::ReactionModel;

/// The names of the built-in reaction models, which no plugin may take.
pub const BUILT_IN: &[&str] = &[
    "JwlPlusPlus",
    "Deflagration",
    "ProgramBurn",
    "ProgramBurnRamp",
    "Arrhenius",
];

/// Builds a model from the parameters a config wrote (a RON struct such as
/// `(z: 5.0e19, activation_energy: 2.2e5)`, here a [`ron::Value`] map);
/// the message of an error names the field (an unknown one, a missing
/// one, one of the wrong type, one out of range).
pub type ParseFn = fn(ron::Value) -> Result<Arc<dyn ReactionModel>, String>;

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

/// The plugin reaction models of one program, in registration order.
#[derive(Debug, Default)]
pub struct ReactionRegistry {
    plugins: Vec<ReactionPlugin>,
}

impl ReactionRegistry {
    /// An empty registry.
    pub fn new() -> Self {
        Self::default()
    }

    /// Adds `plugin`. Panics if its name is a built-in model's or already
    /// registered: two crates claiming one config name is a programming
    /// error that the first test run must show.
    pub fn register(&mut self, plugin: ReactionPlugin) {
        assert!(
            !BUILT_IN.contains(&plugin.name),
            "reaction model `{}` is a built-in model",
            plugin.name
        );
        assert!(
            self.get(plugin.name).is_none(),
            "reaction model `{}` registered twice",
            plugin.name
        );
        self.plugins.push(plugin);
    }

    /// The plugin registered under `name`.
    pub fn get(&self, name: &str) -> Option<&ReactionPlugin> {
        self.plugins.iter().find(|p| p.name == name)
    }

    /// Every registered plugin, in registration order.
    pub fn plugins(&self) -> &[ReactionPlugin] {
        &self.plugins
    }
}

static INSTALLED: OnceLock<ReactionRegistry> = OnceLock::new();

/// Makes `registry` the program's plugin registry, the one the pipelines'
/// schemas resolve names through. The first call wins; a later one gives
/// its registry back.
pub fn install(registry: ReactionRegistry) -> Result<(), ReactionRegistry> {
    INSTALLED.set(registry)
}

/// The installed registry, if any.
pub fn installed() -> Option<&'static ReactionRegistry> {
    INSTALLED.get()
}

/// The installed plugin registered under `name`.
pub fn find(name: &str) -> Option<&'static ReactionPlugin> {
    installed().and_then(|r| r.get(name))
}

/// The names of the installed plugins, in registration order.
pub fn plugin_names() -> Vec<&'static str> {
    installed().map_or_else(Vec::new, |r| r.plugins.iter().map(|p| p.name).collect())
}

/// A plugin model as a pipeline's schema holds it: the registration, the
/// parameters as written (so that it serializes back and compares by
/// value), and the model.
#[derive(Clone)]
pub struct PluginReaction {
    plugin: &'static ReactionPlugin,
    params: Arc<ron::Value>,
    model: Arc<dyn ReactionModel>,
}

impl PluginReaction {
    /// Builds the model of `plugin` from `params`; the message of an
    /// error names the field.
    pub fn new(plugin: &'static ReactionPlugin, params: ron::Value) -> Result<Self, String> {
        let model = (plugin.parse)(params.clone())?;
        Ok(Self {
            plugin,
            params: Arc::new(params),
            model,
        })
    }

    /// The registration this model came from.
    pub fn plugin(&self) -> &'static ReactionPlugin {
        self.plugin
    }

    /// The parameters as the config wrote them.
    pub fn params(&self) -> &ron::Value {
        &self.params
    }

    /// The model, for a solver that takes any [`ReactionModel`].
    pub fn model(&self) -> Arc<dyn ReactionModel> {
        Arc::clone(&self.model)
    }
}

impl fmt::Debug for PluginReaction {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_tuple(self.plugin.name).field(&self.model).finish()
    }
}

impl PartialEq for PluginReaction {
    fn eq(&self, other: &Self) -> bool {
        self.plugin.name == other.plugin.name && self.params == other.params
    }
}

/// Builds a plugin model whose parameters are the serde struct `T`, with
/// its own check: the usual [`ParseFn`] of a plugin crate,
/// `parse: |v| parse_params::<MyModel>(v, MyModel::validate)`.
pub fn parse_params<T>(
    params: ron::Value,
    validate: fn(&T) -> Result<(), String>,
) -> Result<Arc<dyn ReactionModel>, String>
where
    T: ReactionModel + serde::de::DeserializeOwned + 'static,
{
    let model: T = params.into_rust().map_err(|e| e.to_string())?;
    validate(&model)?;
    Ok(Arc::new(model))
}

#[cfg(test)]
mod tests {
    use super::*;
    use brisance_core::ReactionState;
    use serde::Deserialize;

    /// dF/dt = k.
    #[derive(Debug, Deserialize)]
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

    fn params(text: &str) -> ron::Value {
        ron::from_str(text).unwrap()
    }

    #[test]
    fn a_registered_model_builds_from_its_parameters_and_names_a_bad_field() {
        let mut registry = ReactionRegistry::new();
        registry.register(STEADY);
        let plugin = registry.get("Steady").unwrap();
        let leaked: &'static ReactionPlugin = Box::leak(Box::new(*plugin));
        let m = PluginReaction::new(leaked, params("(k: 2.5)")).unwrap();
        let state = ReactionState {
            pressure: 0.0,
            temperature: 300.0,
            density: 1.0,
            time: 0.0,
            detonation_time: f64::INFINITY,
            surface_area_density: 0.0,
        };
        assert_eq!(m.model().rate(&state, 0.0), 2.5);
        assert_eq!(m, PluginReaction::new(leaked, params("(k: 2.5)")).unwrap());
        assert_ne!(m, PluginReaction::new(leaked, params("(k: 2.0)")).unwrap());
        let bad = PluginReaction::new(leaked, params("(k: -1.0)")).unwrap_err();
        assert!(bad.contains("k"), "{bad}");
        let unknown = PluginReaction::new(leaked, params("(k: 1.0, q: 2.0)")).unwrap_err();
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
