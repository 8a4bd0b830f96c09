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
//! behind one more arm of that `match`. The same scheme serves the
//! equations of state (`brisance_eos::plugin`) and the reaction models
//! (`brisance_reaction::plugin`).
//!
//! # Parameters as RON text
//!
//! The equation-of-state and reaction plugins read their parameters as a
//! [`ron::Value`]. That value keeps numbers, strings, sequences and maps
//! but drops the names of enum variants (`rate: Jaumann` reads as `()`,
//! `pressure: Eos(MieGruneisenLinear(...))` as a bare sequence), and a
//! constitutive model's parameters hold enums: the objective rate, the
//! pressure model and its equation of state. A plugin material therefore
//! receives the RON text of its parameters, taken from the config through
//! the ron deserializer's raw-value protocol (the one [`ron::value::RawValue`]
//! uses), and parses it into its own type with the reader's RON extensions
//! ([`ron_options`]). What the model keeps for comparison and for writing
//! itself back is that type serialized again: one canonical text per
//! parameter set, whatever the spacing and comments of the config.

use std::fmt;
use std::sync::{Arc, OnceLock};

use brisance_core::{Eos, Mat3, Material, StressUpdate, StressUpdateInput};
use ron::extensions::Extensions;
use serde::de::{self, Deserializer, Visitor};
use serde::{Serialize, Serializer};

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
/// `g0: 47.7e9, y0: 1.2e8, ...`): the model and its parameters written
/// back as canonical RON. The message of an error names the field (an
/// unknown one, a missing one, one of the wrong type).
pub type ParseFn = fn(&str) -> Result<(Arc<dyn PluginMaterial>, String), String>;

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

/// The plugin constitutive models of one program, in registration order.
#[derive(Debug, Default)]
pub struct MaterialRegistry {
    plugins: Vec<MaterialPlugin>,
}

impl MaterialRegistry {
    /// An empty registry.
    pub fn new() -> Self {
        Self::default()
    }

    /// Adds `plugin`. Panics if its name is a built-in model's or already
    /// registered: two crates claiming one config name is a programming
    /// error that the first test run must show.
    pub fn register(&mut self, plugin: MaterialPlugin) {
        assert!(
            !crate::MaterialModel::VARIANTS.contains(&plugin.name),
            "constitutive model `{}` is a built-in model",
            plugin.name
        );
        assert!(
            self.get(plugin.name).is_none(),
            "constitutive model `{}` registered twice",
            plugin.name
        );
        self.plugins.push(plugin);
    }

    /// The plugin registered under `name`.
    pub fn get(&self, name: &str) -> Option<&MaterialPlugin> {
        self.plugins.iter().find(|p| p.name == name)
    }

    /// Every registered plugin, in registration order.
    pub fn plugins(&self) -> &[MaterialPlugin] {
        &self.plugins
    }
}

/// The installed registry and the names a config may write.
struct Installed {
    registry: MaterialRegistry,
    names: Vec<&'static str>,
}

static INSTALLED: OnceLock<Installed> = OnceLock::new();

/// Makes `registry` the program's plugin registry, the one
/// [`crate::MaterialModel`]'s deserializer resolves names through. The
/// first call wins; a later one gives its registry back.
pub fn install(registry: MaterialRegistry) -> Result<(), MaterialRegistry> {
    let mut slot = Some(registry);
    INSTALLED.get_or_init(|| {
        let registry = slot.take().expect("taken once");
        let names = crate::MaterialModel::VARIANTS
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
pub fn installed() -> Option<&'static MaterialRegistry> {
    INSTALLED.get().map(|i| &i.registry)
}

/// Every name a config may write for a constitutive model: the built-in
/// variants, then the installed plugins.
pub fn names() -> &'static [&'static str] {
    INSTALLED
        .get()
        .map_or(crate::MaterialModel::VARIANTS, |i| i.names.as_slice())
}

/// The names of the installed plugins, in registration order.
pub fn plugin_names() -> Vec<&'static str> {
    installed().map_or_else(Vec::new, |r| r.plugins.iter().map(|p| p.name).collect())
}

/// The installed plugin registered under `name`.
pub fn find(name: &str) -> Option<&'static MaterialPlugin> {
    installed().and_then(|r| r.get(name))
}

/// The RON options a plugin reads its parameters with: those of the
/// config reader (`Some(x)` may be written `x`, and `Variant((fields))`
/// may be written `Variant(fields)`).
pub fn ron_options() -> ron::Options {
    ron::Options::default()
        .with_default_extension(Extensions::IMPLICIT_SOME | Extensions::UNWRAP_VARIANT_NEWTYPES)
}

/// A plugin model as [`crate::MaterialModel`] holds it: the registration,
/// the parameters as canonical RON text (so that it serializes back and
/// compares by value), and the model.
#[derive(Clone)]
pub struct PluginConstitutive {
    plugin: &'static MaterialPlugin,
    params: Arc<str>,
    model: Arc<dyn PluginMaterial>,
}

impl PluginConstitutive {
    /// Builds the model of `plugin` from the RON text of its parameters
    /// (`(a: 1.0, ...)` or `a: 1.0, ...`); the message of an error names
    /// the field.
    pub fn new(plugin: &'static MaterialPlugin, params: &str) -> Result<Self, String> {
        let (model, canonical) = (plugin.parse)(params)?;
        Ok(Self {
            plugin,
            params: canonical.into(),
            model,
        })
    }

    /// The plugin model `model` of `plugin`, built in code rather than
    /// read from a config (a preset of the plugin crate). Its parameters
    /// are `model` serialized, so it equals the model a config with the
    /// same values reads.
    pub fn from_model<T>(plugin: &'static MaterialPlugin, model: T) -> Result<Self, String>
    where
        T: PluginMaterial + Serialize + 'static,
    {
        let params = canonical_params(&model)?;
        Ok(Self {
            plugin,
            params: params.into(),
            model: Arc::new(model),
        })
    }

    /// The registration this model came from.
    pub fn plugin(&self) -> &'static MaterialPlugin {
        self.plugin
    }

    /// The parameters, as canonical RON text.
    pub fn params(&self) -> &str {
        &self.params
    }

    /// The model.
    pub fn model(&self) -> &dyn PluginMaterial {
        &*self.model
    }

    /// Checks the parameters; the message names the bad field.
    pub fn validate(&self) -> Result<(), String> {
        self.model.validate()
    }

    /// Writes the parameters back as RON: the canonical text verbatim, the
    /// way [`ron::value::RawValue`] does.
    pub(crate) fn serialize_params<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.serialize_newtype_struct(RAW_VALUE_TOKEN, &*self.params)
    }
}

impl fmt::Debug for PluginConstitutive {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_tuple(self.plugin.name).field(&self.model).finish()
    }
}

impl PartialEq for PluginConstitutive {
    fn eq(&self, other: &Self) -> bool {
        self.plugin.name == other.plugin.name && self.params == other.params
    }
}

impl Material for PluginConstitutive {
    fn name(&self) -> &'static str {
        self.model.name()
    }
    fn history_len(&self) -> usize {
        self.model.history_len()
    }
    fn init_history(&self, history: &mut [f64]) {
        self.model.init_history(history)
    }
    fn init_history_at(&self, history: &mut [f64], seed: u64) {
        self.model.init_history_at(history, seed)
    }
    #[inline]
    fn update_stress(&self, input: &StressUpdateInput, history: &mut [f64]) -> StressUpdate {
        self.model.update_stress(input, history)
    }
    fn eos(&self) -> Option<&dyn Eos> {
        self.model.eos()
    }
    #[inline]
    fn wave_speed(&self, density: f64, specific_internal_energy: f64) -> f64 {
        self.model.wave_speed(density, specific_internal_energy)
    }
}

/// The parameters of `model` as canonical RON text, in the dialect of the
/// config reader ([`ron_options`]: implicit `Some`, unwrapped newtype
/// variants), which reads them back.
fn canonical_params<T: Serialize>(model: &T) -> Result<String, String> {
    ron_options().to_string(model).map_err(|e| e.to_string())
}

/// Builds a plugin model whose parameters are the serde struct `T`: the
/// usual [`ParseFn`] of a plugin crate,
/// `parse: parse_params::<SteinbergGuinan>`. The text may be the struct
/// `(a: 1.0, ...)` or its fields alone (how a config writes them inside
/// `Name(...)`); a parse error carries serde's message, which names the
/// field, without the position inside the parameters.
pub fn parse_params<T>(params: &str) -> Result<(Arc<dyn PluginMaterial>, String), String>
where
    T: PluginMaterial + Serialize + de::DeserializeOwned + 'static,
{
    let trimmed = params.trim_start();
    let wrapped;
    let text = if trimmed.starts_with('(') {
        params
    } else {
        wrapped = format!("({params}\n)");
        &wrapped
    };
    let model: T = ron_options()
        .from_str(text)
        .map_err(|e| e.code.to_string())?;
    let canonical = canonical_params(&model)?;
    Ok((Arc::new(model), canonical))
}

/// The newtype name through which the ron deserializer hands a value's
/// text to [`ron::value::RawValue`] (and its serializer writes one back
/// verbatim). The composer's plugin tests read a plugin model's
/// parameters through it, so a change of the name in ron fails them.
const RAW_VALUE_TOKEN: &str = "$ron::private::RawValue";

/// The RON text of a value, as the ron deserializer hands it over: a
/// plugin's parameters, `(a: 1.0, rate: Jaumann)` or, inside an unwrapped
/// variant, `a: 1.0, rate: Jaumann`.
pub(crate) struct ParamsText(pub(crate) String);

impl<'de> serde::Deserialize<'de> for ParamsText {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct TextVisitor;
        impl<'de> Visitor<'de> for TextVisitor {
            type Value = ParamsText;
            fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
                write!(f, "the parameters of a constitutive model, in RON")
            }
            fn visit_borrowed_str<E: de::Error>(self, v: &'de str) -> Result<ParamsText, E> {
                Ok(ParamsText(v.to_string()))
            }
            fn visit_str<E: de::Error>(self, v: &str) -> Result<ParamsText, E> {
                Ok(ParamsText(v.to_string()))
            }
            fn visit_newtype_struct<D: Deserializer<'de>>(
                self,
                _: D,
            ) -> Result<ParamsText, D::Error> {
                Err(de::Error::custom(
                    "a plugin constitutive model reads its parameters from RON text",
                ))
            }
        }
        d.deserialize_newtype_struct(RAW_VALUE_TOKEN, TextVisitor)
    }
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
        assert_eq!(m.params(), canonical_params(&expected).unwrap());
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
