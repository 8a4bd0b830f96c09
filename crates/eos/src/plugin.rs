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
//! one more arm of that `match`. The registry, its installed slot and the
//! parameters as RON text are `brisance_plugin`'s, shared with the
//! reaction and constitutive models: a plugin receives the RON text of its
//! parameters, so a parameter holding an enum keeps its variant name.

use std::fmt;
use std::sync::Arc;

use brisance_core::{Eos, EosError};
use brisance_plugin::{Installed, Params, PluginInfo, PluginInstance, Registry};

/// An equation of state a plugin crate provides: the [`Eos`] trait and the
/// check of its parameters that the config loader reports against the
/// material's `eos` field.
pub trait PluginModel: Eos {
    /// Checks the parameters; the message names the bad field.
    fn validate(&self) -> Result<(), String>;
}

/// Builds a model from the RON text of the parameters a config wrote (a
/// struct such as `(gamma: 1.25, covolume: 1.0e-3)`, or its fields alone):
/// the model and its parameters as canonical text. The message of an error
/// names the field (an unknown one, a missing one, one of the wrong type).
pub type ParseFn = brisance_plugin::ParseFn<dyn PluginModel>;

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

impl PluginInfo for EosPlugin {
    const FAMILY: &'static str = "equation of state";
    const BUILT_IN: &'static [&'static str] = crate::EosModel::VARIANTS;
    type Model = dyn PluginModel;
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
    fn parse(&self, params: &str) -> Result<(Arc<dyn PluginModel>, Params), String> {
        (self.parse)(params)
    }
}

/// The plugin equations of state of one program, in registration order;
/// [`Registry::register`] refuses a built-in name or a name registered
/// twice.
pub type EosRegistry = Registry<EosPlugin>;

static INSTALLED: Installed<EosPlugin> = Installed::new();

/// Makes `registry` the program's plugin registry, the one
/// [`crate::EosModel`]'s deserializer resolves names through. The first
/// call wins; a later one gives its registry back.
pub fn install(registry: EosRegistry) -> Result<(), EosRegistry> {
    INSTALLED.install(registry)
}

/// The installed registry, if any.
pub fn installed() -> Option<&'static EosRegistry> {
    INSTALLED.registry()
}

/// The installed slot, for [`crate::EosModel`]'s serde.
pub(crate) fn slot() -> &'static Installed<EosPlugin> {
    &INSTALLED
}

/// Every name a config may write for an equation of state: the built-in
/// variants, then the installed plugins.
pub fn names() -> &'static [&'static str] {
    INSTALLED.names()
}

/// The installed plugin registered under `name`.
pub fn find(name: &str) -> Option<&'static EosPlugin> {
    INSTALLED.find(name)
}

/// A plugin model as [`crate::EosModel`] holds it: the registration, the
/// parameters as canonical RON text (so that it serializes back and
/// compares by value), and the model.
#[derive(Clone, PartialEq)]
pub struct PluginEos(pub(crate) PluginInstance<EosPlugin>);

impl PluginEos {
    /// Builds the model of `plugin` from the RON text of its parameters
    /// (`(gamma: 1.25, ...)` or `gamma: 1.25, ...`); the message of an
    /// error names the field.
    pub fn new(plugin: &'static EosPlugin, params: &str) -> Result<Self, String> {
        PluginInstance::new(plugin, params).map(Self)
    }

    /// The plugin model `model` of `plugin`, built in code rather than
    /// read from a config (a preset of the plugin crate). Its parameters
    /// are `model` serialized, so it equals the model a config with the
    /// same values reads.
    pub fn from_model<T>(plugin: &'static EosPlugin, model: T) -> Result<Self, String>
    where
        T: PluginModel + serde::Serialize + 'static,
    {
        let params = Params::of(&model)?;
        Ok(Self(PluginInstance::from_parts(
            plugin,
            Arc::new(model),
            params,
        )))
    }

    /// The registration this model came from.
    pub fn plugin(&self) -> &'static EosPlugin {
        self.0.plugin()
    }

    /// The parameters, as canonical RON text.
    pub fn params(&self) -> &Params {
        self.0.params()
    }

    /// Checks the parameters; the message names the bad field.
    pub fn validate(&self) -> Result<(), String> {
        self.0.model().validate()
    }
}

impl fmt::Debug for PluginEos {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        fmt::Debug::fmt(&self.0, f)
    }
}

impl Eos for PluginEos {
    fn name(&self) -> &'static str {
        self.0.model().name()
    }
    fn reference_density(&self) -> f64 {
        self.0.model().reference_density()
    }
    #[inline]
    fn pressure(&self, rho: f64, e: f64) -> f64 {
        self.0.model().pressure(rho, e)
    }
    #[inline]
    fn dp_drho(&self, rho: f64, e: f64) -> f64 {
        self.0.model().dp_drho(rho, e)
    }
    #[inline]
    fn dp_de(&self, rho: f64, e: f64) -> f64 {
        self.0.model().dp_de(rho, e)
    }
    fn gruneisen(&self, rho: f64, e: f64) -> f64 {
        self.0.model().gruneisen(rho, e)
    }
    fn check_state(&self, rho: f64, e: f64) -> Result<(), EosError> {
        self.0.model().check_state(rho, e)
    }
    #[inline]
    fn sound_speed_squared(&self, rho: f64, e: f64) -> f64 {
        self.0.model().sound_speed_squared(rho, e)
    }
    #[inline]
    fn sound_speed(&self, rho: f64, e: f64) -> f64 {
        self.0.model().sound_speed(rho, e)
    }
    fn specific_internal_energy(&self, rho: f64, p: f64) -> Result<f64, EosError> {
        self.0.model().specific_internal_energy(rho, p)
    }
    fn temperature(&self, rho: f64, e: f64) -> f64 {
        self.0.model().temperature(rho, e)
    }
    fn specific_internal_energy_from_temperature(&self, rho: f64, t: f64) -> f64 {
        self.0
            .model()
            .specific_internal_energy_from_temperature(rho, t)
    }
    fn cv(&self, rho: f64, t: f64) -> f64 {
        self.0.model().cv(rho, t)
    }
    fn density(&self, p: f64, t: f64) -> Result<f64, EosError> {
        self.0.model().density(p, t)
    }
    fn isothermal_compressibility(&self, p: f64, t: f64) -> Result<f64, EosError> {
        self.0.model().isothermal_compressibility(p, t)
    }
    fn thermal_expansivity(&self, p: f64, t: f64) -> Result<f64, EosError> {
        self.0.model().thermal_expansivity(p, t)
    }
    fn density_and_derivatives(&self, p: f64, t: f64) -> Result<(f64, f64, f64), EosError> {
        self.0.model().density_and_derivatives(p, t)
    }
}

/// Builds a plugin model whose parameters are the serde struct `T`: the
/// usual [`ParseFn`] of a plugin crate, `parse: parse_params::<NobleAbel>`.
/// The text may be the struct `(a: 1.0, ...)` or its fields alone; a
/// parse error carries serde's message, which names the field.
pub fn parse_params<T>(params: &str) -> Result<(Arc<dyn PluginModel>, Params), String>
where
    T: PluginModel + serde::Serialize + serde::de::DeserializeOwned + 'static,
{
    let (model, params) = brisance_plugin::parse_params::<T>(params)?;
    Ok((Arc::new(model), params))
}
