//! Constitutive models that live in their own crates.
//!
//! A model crate implements [`PluginMaterial`] (the core [`Material`]
//! trait plus a parameter check) and hands a [`MaterialPlugin`] to
//! [`MaterialRegistry::register`]: its RON name, a one-line summary, its
//! docs page, a RON example and the function that builds the model from
//! the parameters a config wrote. The composer builds the one registry of
//! the program from every plugin crate's `register` and [`install`]s it;
//! from then on a config may write `model: SteinbergGuinan(...)` wherever
//! it writes `model: ElasticPlastic(...)`, and [`crate::MaterialModel`]
//! deserializes it into its `Plugin` variant.
//!
//! The built-in models keep their enum variants and their `match`
//! dispatch; a plugin model costs one virtual call per stress update,
//! behind one more arm of that `match`. The registry, its installed slot
//! and the parameters as RON text are `brisance_plugin`'s, shared with the
//! equations of state (`brisance_eos::plugin`) and the reaction models
//! (`brisance_reaction::plugin`). A constitutive model's parameters are
//! full of enums (the objective rate, the pressure model and its equation
//! of state); a plugin receives the RON text of its parameters, so they
//! keep their variant names, and parses it with [`parse_params`] into its
//! own type. What the model keeps for comparison and for writing itself
//! back is that type serialized again ([`Params`]).

use std::fmt;
use std::sync::Arc;

use brisance_core::{Eos, Mat3, Material, StressUpdate, StressUpdateInput};
pub use brisance_plugin::{ron_options, Params};
use brisance_plugin::{Installed, PluginInfo, PluginInstance, Registry};
use serde::Serialize;

/// A constitutive model a plugin crate provides: the [`Material`] trait,
/// the check of its parameters that the config loader reports against the
/// material's `model` field, and what the contracts and the solvers ask of
/// a [`crate::MaterialModel`] beyond the trait.
///
/// The provided methods describe an inelastic solid that does not relax at
/// rest, has no yield surface to report, never fails, carries no damage or
/// porosity and does not heat itself; a model overrides what applies to it.
pub trait PluginMaterial: Material {
    /// Checks the parameters; the message names the bad field.
    fn validate(&self) -> Result<(), String>;

    /// Whether the model is purely elastic (no plastic flow, no failure,
    /// no dissipation); see [`crate::MaterialModel::is_elastic`].
    fn is_elastic(&self) -> bool {
        false
    }

    /// Whether a state at rest relaxes (a viscoelastic model); see
    /// [`crate::MaterialModel::relaxes`].
    fn relaxes(&self) -> bool {
        false
    }

    /// Whether the stress depends on the current rate of deformation (a
    /// viscous fluid); see [`crate::MaterialModel::is_viscous`].
    fn is_viscous(&self) -> bool {
        false
    }

    /// How far `stress` lies outside the yield surface at the point's
    /// history and temperature: (value, scale), value ≤ 0 inside; `None`
    /// without a yield surface. See [`crate::MaterialModel::yield_excess`].
    fn yield_excess(&self, stress: &Mat3, history: &[f64], temperature: f64) -> Option<(f64, f64)> {
        let _ = (stress, history, temperature);
        None
    }

    /// Whether the history records a failed point.
    fn is_failed(&self, history: &[f64]) -> bool {
        let _ = history;
        false
    }

    /// The damage variables in a point's history, each non-decreasing.
    fn damage<'h>(&self, history: &'h [f64]) -> &'h [f64] {
        let _ = history;
        &[]
    }

    /// The porosity in a point's history (non-decreasing, in [0, 1)), if
    /// the model carries one.
    fn porosity(&self, history: &[f64]) -> Option<f64> {
        let _ = history;
        None
    }

    /// Number of leading history values that are scalar state, unchanged
    /// by a rigid motion; see [`crate::MaterialModel::scalar_state_len`].
    fn scalar_state_len(&self) -> usize {
        0
    }

    /// The temperature rise of the last update from the model's own
    /// dissipation (plastic work), K, for a solver that owns the
    /// temperature and adds it; `None` for a model that does not heat
    /// itself. See [`crate::MaterialModel::temperature_increment`].
    fn temperature_increment(&self, history: &[f64]) -> Option<f64> {
        let _ = history;
        None
    }

    /// The specific heat the model heats with, J/(kg·K), where it has one.
    fn specific_heat(&self) -> Option<f64> {
        None
    }
}

/// Builds a model from the RON text of the parameters a config wrote (a
/// struct such as `(g0: 47.7e9, y0: 1.2e8, ...)`, or its fields alone,
/// `g0: 47.7e9, y0: 1.2e8, ...`): the model and its parameters as
/// canonical text. The message of an error names the field (an unknown
/// one, a missing one, one of the wrong type).
pub type ParseFn = brisance_plugin::ParseFn<dyn PluginMaterial>;

/// What a plugin crate registers for one constitutive model.
#[derive(Clone, Copy)]
pub struct MaterialPlugin {
    /// The name a config writes (`SteinbergGuinan`), in the style of the
    /// built-in variants.
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

impl fmt::Debug for MaterialPlugin {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("MaterialPlugin")
            .field("name", &self.name)
            .field("docs", &self.docs)
            .finish_non_exhaustive()
    }
}

impl PluginInfo for MaterialPlugin {
    const FAMILY: &'static str = "constitutive model";
    const BUILT_IN: &'static [&'static str] = crate::MaterialModel::VARIANTS;
    type Model = dyn PluginMaterial;
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
    fn parse(&self, params: &str) -> Result<(Arc<dyn PluginMaterial>, Params), String> {
        (self.parse)(params)
    }
}

/// The plugin constitutive models of one program, in registration order;
/// [`Registry::register`] refuses a built-in name or a name registered
/// twice.
pub type MaterialRegistry = Registry<MaterialPlugin>;

static INSTALLED: Installed<MaterialPlugin> = Installed::new();

/// Makes `registry` the program's plugin registry, the one
/// [`crate::MaterialModel`]'s deserializer resolves names through. The
/// first call wins; a later one gives its registry back.
pub fn install(registry: MaterialRegistry) -> Result<(), MaterialRegistry> {
    INSTALLED.install(registry)
}

/// The installed registry, if any.
pub fn installed() -> Option<&'static MaterialRegistry> {
    INSTALLED.registry()
}

/// The installed slot, for [`crate::MaterialModel`]'s serde.
pub(crate) fn slot() -> &'static Installed<MaterialPlugin> {
    &INSTALLED
}

/// Every name a config may write for a constitutive model: the built-in
/// variants, then the installed plugins.
pub fn names() -> &'static [&'static str] {
    INSTALLED.names()
}

/// The names of the installed plugins, in registration order.
pub fn plugin_names() -> &'static [&'static str] {
    INSTALLED.plugin_names()
}

/// The installed plugin registered under `name`.
pub fn find(name: &str) -> Option<&'static MaterialPlugin> {
    INSTALLED.find(name)
}

/// A plugin model as [`crate::MaterialModel`] holds it: the registration,
/// the parameters as canonical RON text (so that it serializes back and
/// compares by value), and the model.
#[derive(Clone, PartialEq)]
pub struct PluginConstitutive(pub(crate) PluginInstance<MaterialPlugin>);

impl PluginConstitutive {
    /// Builds the model of `plugin` from the RON text of its parameters
    /// (`(a: 1.0, ...)` or `a: 1.0, ...`); the message of an error names
    /// the field.
    pub fn new(plugin: &'static MaterialPlugin, params: &str) -> Result<Self, String> {
        PluginInstance::new(plugin, params).map(Self)
    }

    /// The plugin model `model` of `plugin`, built in code rather than
    /// read from a config (a preset of the plugin crate). Its parameters
    /// are `model` serialized, so it equals the model a config with the
    /// same values reads.
    pub fn from_model<T>(plugin: &'static MaterialPlugin, model: T) -> Result<Self, String>
    where
        T: PluginMaterial + Serialize + 'static,
    {
        let params = Params::of(&model)?;
        Ok(Self(PluginInstance::from_parts(
            plugin,
            Arc::new(model),
            params,
        )))
    }

    /// The registration this model came from.
    pub fn plugin(&self) -> &'static MaterialPlugin {
        self.0.plugin()
    }

    /// The parameters, as canonical RON text.
    pub fn params(&self) -> &Params {
        self.0.params()
    }

    /// The model.
    pub fn model(&self) -> &dyn PluginMaterial {
        &**self.0.model()
    }

    /// Checks the parameters; the message names the bad field.
    pub fn validate(&self) -> Result<(), String> {
        self.0.model().validate()
    }
}

impl fmt::Debug for PluginConstitutive {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        fmt::Debug::fmt(&self.0, f)
    }
}

impl Material for PluginConstitutive {
    fn name(&self) -> &'static str {
        self.0.model().name()
    }
    fn history_len(&self) -> usize {
        self.0.model().history_len()
    }
    fn init_history(&self, history: &mut [f64]) {
        self.0.model().init_history(history)
    }
    fn init_history_at(&self, history: &mut [f64], seed: u64) {
        self.0.model().init_history_at(history, seed)
    }
    #[inline]
    fn update_stress(&self, input: &StressUpdateInput, history: &mut [f64]) -> StressUpdate {
        self.0.model().update_stress(input, history)
    }
    fn eos(&self) -> Option<&dyn Eos> {
        self.0.model().eos()
    }
    #[inline]
    fn wave_speed(&self, density: f64, specific_internal_energy: f64) -> f64 {
        self.0.model().wave_speed(density, specific_internal_energy)
    }
}

/// Builds a plugin model whose parameters are the serde struct `T`: the
/// usual [`ParseFn`] of a plugin crate,
/// `parse: parse_params::<SteinbergGuinan>`. The text may be the struct
/// `(a: 1.0, ...)` or its fields alone (how a config writes them inside
/// `Name(...)`); a parse error carries serde's message, which names the
/// field, without the position inside the parameters.
pub fn parse_params<T>(params: &str) -> Result<(Arc<dyn PluginMaterial>, Params), String>
where
    T: PluginMaterial + Serialize + serde::de::DeserializeOwned + 'static,
{
    let (model, params) = brisance_plugin::parse_params::<T>(params)?;
    Ok((Arc::new(model), params))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{Hypoelastic, MaterialModel, ObjectiveRate, PressureModel};

    impl PluginMaterial for Hypoelastic {
        fn validate(&self) -> Result<(), String> {
            Hypoelastic::validate(self).map_err(|e| e.to_string())
        }
        fn is_elastic(&self) -> bool {
            true
        }
    }

    /// The hypoelastic solid under another name: its parameters hold two
    /// enums (the pressure model and the objective rate), which must reach
    /// the model by name.
    const TEST_SOLID: MaterialPlugin = MaterialPlugin {
        name: "TestSolid",
        summary: "the hypoelastic solid under another name",
        docs: "docs/physics/constitutive/hypoelastic.md",
        example: "TestSolid(shear_modulus: 43.8e9, pressure: Linear(bulk_modulus: 117.0e9), rate: GreenNaghdi)",
        parse: parse_params::<Hypoelastic>,
    };

    /// Installs a registry holding [`TEST_SOLID`], once for this test
    /// binary.
    fn install_test_plugin() {
        let mut r = MaterialRegistry::new();
        r.register(TEST_SOLID);
        let _ = install(r);
    }

    fn leaked() -> &'static MaterialPlugin {
        Box::leak(Box::new(TEST_SOLID))
    }

    #[test]
    fn parameters_keep_their_enum_names_and_compare_by_value() {
        let plugin = leaked();
        let text = "shear_modulus: 43.8e9, // G\n pressure: Linear(bulk_modulus: 117.0e9),\n rate: GreenNaghdi";
        let m = PluginConstitutive::new(plugin, text).unwrap();
        let expected = Hypoelastic {
            shear_modulus: 43.8e9,
            pressure: PressureModel::Linear {
                bulk_modulus: 117.0e9,
            },
            rate: ObjectiveRate::GreenNaghdi,
        };
        assert_eq!(m.history_len(), expected.history_len());
        assert_eq!(m.params(), &Params::of(&expected).unwrap());
        // The same values however written, and the preset built in code.
        let spaced = PluginConstitutive::new(
            plugin,
            "(rate: GreenNaghdi, shear_modulus: 4.38e10, pressure: Linear(bulk_modulus: 1.17e11))",
        )
        .unwrap();
        assert_eq!(m, spaced);
        assert_eq!(
            m,
            PluginConstitutive::from_model(plugin, expected.clone()).unwrap()
        );
        // Another rate is another model.
        let jaumann = PluginConstitutive::new(plugin, &text.replace("GreenNaghdi", "Jaumann"));
        assert_ne!(m, jaumann.unwrap());
        // Errors name the field.
        let unknown = PluginConstitutive::new(plugin, "shear_modulus: 1.0, bulk: 2.0").unwrap_err();
        assert!(unknown.contains("bulk"), "{unknown}");
        let missing = PluginConstitutive::new(plugin, "(rate: Jaumann)").unwrap_err();
        assert!(missing.contains("shear_modulus"), "{missing}");
        let enum_name = PluginConstitutive::new(
            plugin,
            "shear_modulus: 1.0, pressure: Linear(bulk_modulus: 1.0), rate: Truesdell",
        )
        .unwrap_err();
        assert!(enum_name.contains("Truesdell"), "{enum_name}");
    }

    #[test]
    fn a_registered_plugin_is_named_like_a_built_in_model() {
        install_test_plugin();
        let text = "TestSolid(shear_modulus: 43.8e9, pressure: Linear(bulk_modulus: 117.0e9), rate: GreenNaghdi)";
        let m: MaterialModel = ron_options().from_str(text).unwrap();
        let MaterialModel::Plugin(p) = &m else {
            panic!("{m:?} is not a plugin model")
        };
        assert_eq!(p.plugin().name, "TestSolid");
        assert_eq!(m.variant(), "TestSolid");
        assert!(m.validate().is_ok() && m.is_elastic());
        // It updates exactly as the built-in model with the same values.
        let built_in: MaterialModel = ron_options()
            .from_str(&text.replace("TestSolid", "Hypoelastic"))
            .unwrap();
        let (mut ha, mut hb) = (vec![0.0; m.history_len()], vec![0.0; m.history_len()]);
        m.init_history(&mut ha);
        built_in.init_history(&mut hb);
        let input = StressUpdateInput {
            velocity_gradient: Mat3::new(1e3, 2e2, 0.0, -1e2, 0.0, 0.0, 0.0, 0.0, -5e2),
            dt: 1e-7,
            density: 8930.0,
            temperature: 300.0,
            specific_internal_energy: 0.0,
            stress: Mat3::from_diagonal_element(-1e6),
        };
        let (a, b) = (
            m.update_stress(&input, &mut ha),
            built_in.update_stress(&input, &mut hb),
        );
        assert_eq!(a.stress, b.stress);
        assert_eq!(ha, hb);
        assert_eq!(m.name(), "hypoelastic");
        // It writes itself back under its name and reads back equal.
        let back = ron_options().to_string(&m).unwrap();
        assert!(back.starts_with("TestSolid("), "{back}");
        assert_eq!(ron_options().from_str::<MaterialModel>(&back).unwrap(), m);
        // Its own checks and serde's messages reach the user, under its name.
        let bad: MaterialModel = ron_options()
            .from_str(&text.replace("43.8e9", "-1.0"))
            .unwrap();
        let err = bad.validate().unwrap_err().to_string();
        assert!(err.contains("`shear_modulus`"), "{err}");
        let err = ron_options()
            .from_str::<MaterialModel>(&text.replace("shear_modulus", "g"))
            .unwrap_err();
        assert!(
            err.to_string().contains("TestSolid") && err.to_string().contains("`g`"),
            "{err}"
        );
        // An unknown name lists the built-in and the plugin names.
        let err = ron_options()
            .from_str::<MaterialModel>("NoSolid(shear_modulus: 1.0)")
            .unwrap_err();
        assert!(err.to_string().contains("`TestSolid`"), "{err}");
        assert!(err.to_string().contains("`ElasticPlastic`"), "{err}");
        assert!(names().contains(&"TestSolid"));
        assert_eq!(plugin_names(), ["TestSolid"]);
    }

    #[test]
    #[should_panic(expected = "built-in")]
    fn a_plugin_cannot_take_a_built_in_name() {
        MaterialRegistry::new().register(MaterialPlugin {
            name: "ElasticPlastic",
            ..TEST_SOLID
        });
    }

    #[test]
    #[should_panic(expected = "twice")]
    fn a_name_is_registered_once() {
        let mut registry = MaterialRegistry::new();
        registry.register(TEST_SOLID);
        registry.register(TEST_SOLID);
    }
}
