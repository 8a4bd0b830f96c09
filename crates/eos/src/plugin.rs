//! Equations of state that live in their own crates.
//!
//! A model crate implements [`PluginModel`] (the [`Eos`] trait plus a
//! parameter check) and hands an [`EosPlugin`] to
//! [`EosRegistry::register`]: its RON name, a one-line summary, its docs
//! page, a RON example and the function that builds the model from the
//! parameters a config wrote. The composer builds the one registry of the
//! program from every plugin crate's `register` and [`install`]s it; from
//! then on a config may write `eos: NobleAbel(gamma: 1.25, ...)` wherever it
//! writes `eos: IdealGas(...)`, and [`crate::EosModel`] deserializes it into
//! its `Plugin` variant.
//!
//! The built-in models keep their enum variants and their `match`
//! dispatch; a plugin model costs one virtual call per evaluation, behind
//! one more arm of that `match`.

use std::fmt;
use std::sync::{Arc, OnceLock};

use brisance_core::{Eos, EosError};

/// An equation of state a plugin crate provides: the [`Eos`] trait and the
/// check of its parameters that the config loader reports against the
/// material's `eos` field.
pub trait PluginModel: Eos {
    /// Checks the parameters; the message names the bad field.
    fn validate(&self) -> Result<(), String>;
}

/// Builds a model from the parameters a config wrote (a RON struct such as
/// `(gamma: 1.25, covolume: 1.0e-3)`, here a [`ron::Value`] map); the
/// message of an error names the field (an unknown one, a missing one, one
/// of the wrong type).
pub type ParseFn = fn(ron::Value) -> Result<Arc<dyn PluginModel>, String>;

/// What a plugin crate registers for one equation of state.
#[derive(Clone, Copy)]
pub struct EosPlugin {
    /// The name a config writes (`NobleAbel`), in the style of the built-in
    /// variants.
    pub name: &'static str,
    /// One line on what it is, with its source, for `brisance list`.
    pub summary: &'static str,
    /// The model's docs page, relative to the repository root.
    pub docs: &'static str,
    /// A RON example of the config value; the composer's tests parse it.
    pub example: &'static str,
    /// Whether the model describes a gas that an Euler solver (the `Fdm`
    /// pipeline) can carry.
    pub gas: bool,
    /// Builds the model from its parameters.
    pub parse: ParseFn,
}

impl fmt::Debug for EosPlugin {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("EosPlugin")
            .field("name", &self.name)
            .field("docs", &self.docs)
            .field("gas", &self.gas)
            .finish_non_exhaustive()
    }
}

/// The plugin equations of state of one program, in registration order.
#[derive(Debug, Default)]
pub struct EosRegistry {
    plugins: Vec<EosPlugin>,
}

impl EosRegistry {
    /// An empty registry.
    pub fn new() -> Self {
        Self::default()
    }

    /// Adds `plugin`. Panics if its name is a built-in model's or already
    /// registered: two crates claiming one config name is a programming
    /// error that the first test run must show.
    pub fn register(&mut self, plugin: EosPlugin) {
        assert!(
            !crate::EosModel::VARIANTS.contains(&plugin.name),
            "equation of state `{}` is a built-in model",
            plugin.name
        );
        assert!(
            self.get(plugin.name).is_none(),
            "equation of state `{}` registered twice",
            plugin.name
        );
        self.plugins.push(plugin);
    }

    /// The plugin registered under `name`.
    pub fn get(&self, name: &str) -> Option<&EosPlugin> {
        self.plugins.iter().find(|p| p.name == name)
    }

    /// Every registered plugin, in registration order.
    pub fn plugins(&self) -> &[EosPlugin] {
        &self.plugins
    }
}

/// The installed registry and the names a config may write.
struct Installed {
    registry: EosRegistry,
    names: Vec<&'static str>,
}

static INSTALLED: OnceLock<Installed> = OnceLock::new();

/// Makes `registry` the program's plugin registry, the one
/// [`crate::EosModel`]'s deserializer resolves names through. The first
/// call wins; a later one gives its registry back.
pub fn install(registry: EosRegistry) -> Result<(), EosRegistry> {
    let mut slot = Some(registry);
    INSTALLED.get_or_init(|| {
        let registry = slot.take().expect("taken once");
        let names = crate::EosModel::VARIANTS
            .iter()
            .copied()
            .chain(registry.plugins.iter().map(|p| p.name))
            .collect();
        Installed { registry, names }
    });
    match slot {
        None => Ok(()),
        Some(r) => Err(r),
    }
}

/// The installed registry, if any.
pub fn installed() -> Option<&'static EosRegistry> {
    INSTALLED.get().map(|i| &i.registry)
}

/// Every name a config may write for an equation of state: the built-in
/// variants, then the installed plugins.
pub fn names() -> &'static [&'static str] {
    INSTALLED
        .get()
        .map_or(crate::EosModel::VARIANTS, |i| i.names.as_slice())
}

/// The installed plugin registered under `name`.
pub fn find(name: &str) -> Option<&'static EosPlugin> {
    installed().and_then(|r| r.get(name))
}

/// A plugin model as [`crate::EosModel`] holds it: the registration, the
/// parameters as written (so that it serializes back and compares by
/// value), and the model.
#[derive(Clone)]
pub struct PluginEos {
    plugin: &'static EosPlugin,
    params: Arc<ron::Value>,
    model: Arc<dyn PluginModel>,
}

impl PluginEos {
    /// Builds the model of `plugin` from `params`.
    pub fn new(plugin: &'static EosPlugin, params: ron::Value) -> Result<Self, String> {
        let model = (plugin.parse)(params.clone())?;
        Ok(Self {
            plugin,
            params: Arc::new(params),
            model,
        })
    }

    /// The registration this model came from.
    pub fn plugin(&self) -> &'static EosPlugin {
        self.plugin
    }

    /// The parameters as the config wrote them.
    pub fn params(&self) -> &ron::Value {
        &self.params
    }

    /// Checks the parameters; the message names the bad field.
    pub fn validate(&self) -> Result<(), String> {
        self.model.validate()
    }
}

impl fmt::Debug for PluginEos {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_tuple(self.plugin.name).field(&self.model).finish()
    }
}

impl PartialEq for PluginEos {
    fn eq(&self, other: &Self) -> bool {
        self.plugin.name == other.plugin.name && self.params == other.params
    }
}

impl Eos for PluginEos {
    fn name(&self) -> &'static str {
        self.model.name()
    }
    fn reference_density(&self) -> f64 {
        self.model.reference_density()
    }
    #[inline]
    fn pressure(&self, rho: f64, e: f64) -> f64 {
        self.model.pressure(rho, e)
    }
    #[inline]
    fn dp_drho(&self, rho: f64, e: f64) -> f64 {
        self.model.dp_drho(rho, e)
    }
    #[inline]
    fn dp_de(&self, rho: f64, e: f64) -> f64 {
        self.model.dp_de(rho, e)
    }
    fn gruneisen(&self, rho: f64, e: f64) -> f64 {
        self.model.gruneisen(rho, e)
    }
    fn check_state(&self, rho: f64, e: f64) -> Result<(), EosError> {
        self.model.check_state(rho, e)
    }
    #[inline]
    fn sound_speed_squared(&self, rho: f64, e: f64) -> f64 {
        self.model.sound_speed_squared(rho, e)
    }
    #[inline]
    fn sound_speed(&self, rho: f64, e: f64) -> f64 {
        self.model.sound_speed(rho, e)
    }
    fn specific_internal_energy(&self, rho: f64, p: f64) -> Result<f64, EosError> {
        self.model.specific_internal_energy(rho, p)
    }
    fn temperature(&self, rho: f64, e: f64) -> f64 {
        self.model.temperature(rho, e)
    }
    fn specific_internal_energy_from_temperature(&self, rho: f64, t: f64) -> f64 {
        self.model.specific_internal_energy_from_temperature(rho, t)
    }
    fn cv(&self, rho: f64, t: f64) -> f64 {
        self.model.cv(rho, t)
    }
    fn density(&self, p: f64, t: f64) -> Result<f64, EosError> {
        self.model.density(p, t)
    }
    fn isothermal_compressibility(&self, p: f64, t: f64) -> Result<f64, EosError> {
        self.model.isothermal_compressibility(p, t)
    }
    fn thermal_expansivity(&self, p: f64, t: f64) -> Result<f64, EosError> {
        self.model.thermal_expansivity(p, t)
    }
    fn density_and_derivatives(&self, p: f64, t: f64) -> Result<(f64, f64, f64), EosError> {
        self.model.density_and_derivatives(p, t)
    }
}

/// Builds a plugin model whose parameters are the serde struct `T`: the
/// usual [`ParseFn`] of a plugin crate,
/// `parse: |v| parse_params::<NobleAbel>(v)`.
pub fn parse_params<T>(params: ron::Value) -> Result<Arc<dyn PluginModel>, String>
where
    T: PluginModel + serde::de::DeserializeOwned + 'static,
{
    params
        .into_rust::<T>()
        .map(|m| Arc::new(m) as Arc<dyn PluginModel>)
        .map_err(|e| e.to_string())
}
