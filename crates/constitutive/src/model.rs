//! The registry of constitutive models: one enum whose variant names are
//! what a config writes (`Hypoelastic(...)`, `ElasticPlastic(...)`,
//! `DruckerPrager(...)`, `Hjc(...)`, `Null(...)`, `ViscoScram(...)`),
//! dispatching the core [`Material`] trait with a `match` (no virtual call
//! per point) for the built-in models. Adding a built-in model is a module
//! plus one variant here; a model in its own crate registers itself instead
//! ([`crate::plugin`]) and arrives as the [`MaterialModel::Plugin`] variant
//! under its own name.

use crate::plugin::{self, MaterialPlugin, PluginConstitutive};
use crate::{
    drucker_prager, elastic_plastic, hjc, viscoscram, ConstitutiveError, DruckerPrager,
    ElasticPlastic, Hjc, Hypoelastic, NullMaterial, ViscoScram,
};
use brisance_core::{Eos, Mat3, Material, StressUpdate, StressUpdateInput};
use brisance_plugin::{Installed, PluginEnum, PluginInstance};
use serde::de::{Deserializer, VariantAccess};
use serde::{Deserialize, Serialize, Serializer};

/// Every constitutive model a config can name: the built-in models, and
/// any model a plugin crate registered ([`crate::plugin`]).
#[derive(Debug, Clone, PartialEq)]
pub enum MaterialModel {
    /// Isotropic hypoelastic solid ([`crate::hypoelastic`]).
    Hypoelastic(Hypoelastic),
    /// Hypoelastic–plastic J2 metal with Johnson–Cook flow stress and
    /// damage ([`crate::elastic_plastic`], seed 000 §4.2).
    ElasticPlastic(ElasticPlastic),
    /// Drucker–Prager soil with shear and tension failure
    /// ([`crate::drucker_prager`], seed 001 §4.4).
    DruckerPrager(DruckerPrager),
    /// Holmquist–Johnson–Cook concrete with Jiang's tensile damage
    /// ([`crate::hjc`], seed 001 §4.3).
    Hjc(Hjc),
    /// A fluid as material points: EOS pressure, optional Newtonian
    /// viscosity ([`crate::null_material`]).
    Null(NullMaterial),
    /// A polymer-bonded explosive: five Maxwell elements and statistical
    /// crack growth ([`crate::viscoscram`], seed 000 §4.1.2, ref \[19\]).
    ViscoScram(ViscoScram),
    /// A model from a plugin crate; a config writes it under the name the
    /// crate registered (`SteinbergGuinan(...)`), never as `Plugin`.
    Plugin(PluginConstitutive),
}

macro_rules! dispatch {
    ($self:ident, $m:ident => $e:expr) => {
        match $self {
            MaterialModel::Hypoelastic($m) => $e,
            MaterialModel::ElasticPlastic($m) => $e,
            MaterialModel::DruckerPrager($m) => $e,
            MaterialModel::Hjc($m) => $e,
            MaterialModel::Null($m) => $e,
            MaterialModel::ViscoScram($m) => $e,
            MaterialModel::Plugin($m) => $e,
        }
    };
}

impl MaterialModel {
    /// The config names of the built-in variants.
    pub const VARIANTS: &'static [&'static str] = &[
        "Hypoelastic",
        "ElasticPlastic",
        "DruckerPrager",
        "Hjc",
        "Null",
        "ViscoScram",
    ];

    /// The config name of this model (`ElasticPlastic`, ...; a plugin
    /// model's registered name).
    pub fn variant(&self) -> &'static str {
        match self {
            Self::Hypoelastic(_) => "Hypoelastic",
            Self::ElasticPlastic(_) => "ElasticPlastic",
            Self::DruckerPrager(_) => "DruckerPrager",
            Self::Hjc(_) => "Hjc",
            Self::Null(_) => "Null",
            Self::ViscoScram(_) => "ViscoScram",
            Self::Plugin(m) => m.plugin().name,
        }
    }

    /// Every name a config may write: the built-in variants, then the
    /// installed plugins ([`crate::plugin::install`]).
    pub fn names() -> &'static [&'static str] {
        plugin::names()
    }

    /// Checks the parameters; the message names the bad field.
    pub fn validate(&self) -> Result<(), ConstitutiveError> {
        match self {
            Self::Hypoelastic(m) => m.validate(),
            Self::ElasticPlastic(m) => m.validate(),
            Self::DruckerPrager(m) => m.validate(),
            Self::Hjc(m) => m.validate(),
            Self::Null(m) => m.validate(),
            Self::ViscoScram(m) => m.validate(),
            Self::Plugin(m) => m.validate().map_err(|detail| ConstitutiveError::Plugin {
                model: m.plugin().name,
                detail,
            }),
        }
    }

    /// Whether the model is purely elastic (no plastic flow, no failure,
    /// no dissipation): the hypoelastic solid and the inviscid fluid.
    pub fn is_elastic(&self) -> bool {
        match self {
            Self::Hypoelastic(_) => true,
            Self::Null(m) => !m.is_viscous(),
            Self::Plugin(m) => m.model().is_elastic(),
            Self::ElasticPlastic(_)
            | Self::DruckerPrager(_)
            | Self::Hjc(_)
            | Self::ViscoScram(_) => false,
        }
    }

    /// Whether a state at rest relaxes: the stress of a viscoelastic model
    /// decays at zero strain rate (its dashpots), turning stored energy
    /// into heat, so "zero rate keeps the stress" does not apply; a rigid
    /// spin must then commute with that relaxation instead.
    pub fn relaxes(&self) -> bool {
        match self {
            Self::ViscoScram(m) => m.inverse_relaxation_times.iter().any(|&r| r > 0.0),
            Self::Plugin(m) => m.model().relaxes(),
            _ => false,
        }
    }

    /// Whether the stress depends on the current rate of deformation
    /// rather than being carried from step to step (the viscous fluid,
    /// σ' = 2μ dev D): zero strain rate then removes the viscous stress.
    pub fn is_viscous(&self) -> bool {
        match self {
            Self::Null(m) => m.is_viscous(),
            Self::Plugin(m) => m.model().is_viscous(),
            _ => false,
        }
    }

    /// The flow stress at a point's history and temperature (Pa), for the
    /// J2 metal (the other models' strength depends on the pressure; see
    /// [`MaterialModel::yield_excess`]).
    pub fn flow_stress(&self, history: &[f64], temperature: f64) -> Option<f64> {
        match self {
            Self::ElasticPlastic(m) => Some(m.current_flow_stress(history, temperature)),
            _ => None,
        }
    }

    /// How far a stress lies outside the model's yield surface at the
    /// point's history: (value, scale), value ≤ 0 inside, scale the
    /// magnitude its round-off is relative to (Pa). J2 metal: σ̄ − σ_y, σ_y;
    /// Drucker–Prager: max(f^s, f^t) and the size of their terms; HJC:
    /// σ̄ − σ* f'_c, σ* f'_c. `None` for models without a yield surface
    /// (hypoelastic solid, null fluid).
    pub fn yield_excess(
        &self,
        stress: &Mat3,
        history: &[f64],
        temperature: f64,
    ) -> Option<(f64, f64)> {
        match self {
            Self::ElasticPlastic(m) => {
                let sigma_y = m.current_flow_stress(history, temperature);
                let dev = crate::hypoelastic::deviator(stress);
                Some((crate::hypoelastic::von_mises(&dev) - sigma_y, sigma_y))
            }
            Self::DruckerPrager(m) => Some(m.yield_excess(stress)),
            Self::Hjc(m) => Some(m.yield_excess(stress, history)),
            Self::Plugin(m) => m.model().yield_excess(stress, history, temperature),
            Self::Hypoelastic(_) | Self::Null(_) | Self::ViscoScram(_) => None,
        }
    }

    /// Whether the history records a failed point.
    pub fn is_failed(&self, history: &[f64]) -> bool {
        match self {
            Self::ElasticPlastic(_) => history[elastic_plastic::FAILED_INDEX] != 0.0,
            Self::Hjc(_) => history[hjc::FAILED_INDEX] != 0.0,
            Self::Plugin(m) => m.model().is_failed(history),
            Self::Hypoelastic(_) | Self::DruckerPrager(_) | Self::Null(_) | Self::ViscoScram(_) => {
                false
            }
        }
    }

    /// The damage variables in a point's history, each non-decreasing:
    /// Johnson–Cook D for the metal, D_c and D_t for HJC, none otherwise.
    pub fn damage<'h>(&self, history: &'h [f64]) -> &'h [f64] {
        match self {
            Self::ElasticPlastic(_) => {
                &history[elastic_plastic::DAMAGE_INDEX..=elastic_plastic::DAMAGE_INDEX]
            }
            Self::Hjc(_) => &history[hjc::COMPRESSION_DAMAGE_INDEX..=hjc::TENSILE_DAMAGE_INDEX],
            // The mean crack radius, which never decreases.
            Self::ViscoScram(_) => {
                &history[viscoscram::CRACK_RADIUS_INDEX..=viscoscram::CRACK_RADIUS_INDEX]
            }
            Self::Plugin(m) => m.model().damage(history),
            Self::Hypoelastic(_) | Self::DruckerPrager(_) | Self::Null(_) => &[],
        }
    }

    /// The TEPLA-F porosity in a point's history (non-decreasing, in
    /// [0, 1)): the J2 metal with a `tepla` model, `None` otherwise.
    pub fn porosity(&self, history: &[f64]) -> Option<f64> {
        match self {
            Self::ElasticPlastic(m) if m.tepla.is_some() => {
                Some(history[elastic_plastic::POROSITY_INDEX])
            }
            Self::Plugin(m) => m.model().porosity(history),
            _ => None,
        }
    }

    /// Number of leading history values that are scalar state — unchanged
    /// by a rigid motion — before per-step values and the objective rate's
    /// rotation history.
    pub fn scalar_state_len(&self) -> usize {
        match self {
            Self::Hypoelastic(_) | Self::Null(_) => 0,
            Self::ElasticPlastic(_) => elastic_plastic::SCALAR_HISTORY_LEN,
            Self::DruckerPrager(_) => drucker_prager::SCALAR_HISTORY_LEN,
            Self::Hjc(_) => hjc::STATE_HISTORY_LEN,
            // The crack radius; the element stresses that follow rotate.
            Self::ViscoScram(_) => 1,
            Self::Plugin(m) => m.model().scalar_state_len(),
        }
    }

    /// The temperature rise of the last update from the model's plastic
    /// work, K, which the solver that owns the temperature adds to it: the
    /// J2 metal's χ Δw_p/(ρ c_v) ([`crate::elastic_plastic`], step 4) and a
    /// plugin model's own; `None` for a model that does not heat itself.
    #[inline]
    pub fn temperature_increment(&self, history: &[f64]) -> Option<f64> {
        match self {
            Self::ElasticPlastic(_) => Some(history[elastic_plastic::TEMPERATURE_INCREMENT_INDEX]),
            Self::Plugin(m) => m.model().temperature_increment(history),
            _ => None,
        }
    }

    /// The specific heat the model carries: the J2 metal's (a constant or
    /// one that follows the temperature, [`crate::specific_heat`]) and a
    /// plugin model's own constant, `None` for the others.
    pub fn specific_heat(&self) -> Option<crate::SpecificHeat> {
        match self {
            Self::ElasticPlastic(m) => Some(m.specific_heat.clone()),
            Self::Plugin(m) => m.model().specific_heat().map(crate::SpecificHeat::Constant),
            _ => None,
        }
    }

    /// Whether the model carries a specific heat (constant or following the
    /// temperature): the J2 metal, and a plugin model that gives one.
    pub fn carries_specific_heat(&self) -> bool {
        match self {
            Self::ElasticPlastic(_) => true,
            Self::Plugin(m) => m.model().specific_heat().is_some(),
            _ => false,
        }
    }

    /// The temperature rise (K) of a point of this model at `temperature`
    /// (K) given the heat `q` (J/kg) — q/c_v for a constant specific heat,
    /// the rise whose heat is q for one that follows the temperature
    /// ([`crate::SpecificHeat::temperature_rise`]) — for the models that
    /// carry a specific heat, `None` for the others.
    pub fn temperature_rise(&self, temperature: f64, q: f64) -> Option<f64> {
        match self {
            Self::ElasticPlastic(m) => Some(m.specific_heat.temperature_rise(temperature, q)),
            Self::Plugin(m) => m.model().specific_heat().map(|c| q / c),
            _ => None,
        }
    }
}

impl Serialize for MaterialModel {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        const NAME: &str = "MaterialModel";
        let index = brisance_plugin::variant_index::<Self>(self.variant());
        match self {
            Self::Hypoelastic(m) => s.serialize_newtype_variant(NAME, index, "Hypoelastic", m),
            Self::ElasticPlastic(m) => {
                s.serialize_newtype_variant(NAME, index, "ElasticPlastic", m)
            }
            Self::DruckerPrager(m) => s.serialize_newtype_variant(NAME, index, "DruckerPrager", m),
            Self::Hjc(m) => s.serialize_newtype_variant(NAME, index, "Hjc", m),
            Self::Null(m) => s.serialize_newtype_variant(NAME, index, "Null", m),
            Self::ViscoScram(m) => s.serialize_newtype_variant(NAME, index, "ViscoScram", m),
            Self::Plugin(m) => brisance_plugin::serialize_plugin::<Self, S>(&m.0, s),
        }
    }
}

/// A built-in name reads its variant as the derived code did; any other
/// name is looked up among the installed plugins.
impl PluginEnum for MaterialModel {
    type Plugin = MaterialPlugin;
    const NAME: &'static str = "MaterialModel";
    const VARIANTS: &'static [&'static str] = Self::VARIANTS;
    const EXPECTING: &'static str = "a constitutive model such as `ElasticPlastic(...)`";

    fn installed() -> &'static Installed<MaterialPlugin> {
        plugin::slot()
    }

    fn read_builtin<'de, A: VariantAccess<'de>>(
        name: &'static str,
        variant: A,
    ) -> Result<Self, A::Error> {
        match name {
            "Hypoelastic" => variant.newtype_variant().map(Self::Hypoelastic),
            "ElasticPlastic" => variant.newtype_variant().map(Self::ElasticPlastic),
            "DruckerPrager" => variant.newtype_variant().map(Self::DruckerPrager),
            "Hjc" => variant.newtype_variant().map(Self::Hjc),
            "Null" => variant.newtype_variant().map(Self::Null),
            "ViscoScram" => variant.newtype_variant().map(Self::ViscoScram),
            _ => Err(Self::unknown(name)),
        }
    }

    fn from_plugin(model: PluginInstance<MaterialPlugin>) -> Self {
        Self::Plugin(PluginConstitutive(model))
    }
}

impl<'de> Deserialize<'de> for MaterialModel {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        brisance_plugin::deserialize(d)
    }
}

impl Material for MaterialModel {
    fn name(&self) -> &'static str {
        dispatch!(self, m => m.name())
    }

    fn history_len(&self) -> usize {
        dispatch!(self, m => m.history_len())
    }

    fn init_history(&self, history: &mut [f64]) {
        dispatch!(self, m => m.init_history(history))
    }

    fn init_history_at(&self, history: &mut [f64], seed: u64) {
        dispatch!(self, m => m.init_history_at(history, seed))
    }

    #[inline]
    fn update_stress(&self, input: &StressUpdateInput, history: &mut [f64]) -> StressUpdate {
        dispatch!(self, m => m.update_stress(input, history))
    }

    fn eos(&self) -> Option<&dyn Eos> {
        dispatch!(self, m => m.eos())
    }

    #[inline]
    fn wave_speed(&self, density: f64, specific_internal_energy: f64) -> f64 {
        dispatch!(self, m => m.wave_speed(density, specific_internal_energy))
    }
}

impl From<Hypoelastic> for MaterialModel {
    fn from(m: Hypoelastic) -> Self {
        Self::Hypoelastic(m)
    }
}

impl From<ElasticPlastic> for MaterialModel {
    fn from(m: ElasticPlastic) -> Self {
        Self::ElasticPlastic(m)
    }
}

impl From<ViscoScram> for MaterialModel {
    fn from(m: ViscoScram) -> Self {
        Self::ViscoScram(m)
    }
}

impl From<DruckerPrager> for MaterialModel {
    fn from(m: DruckerPrager) -> Self {
        Self::DruckerPrager(m)
    }
}

impl From<Hjc> for MaterialModel {
    fn from(m: Hjc) -> Self {
        Self::Hjc(m)
    }
}

impl From<NullMaterial> for MaterialModel {
    fn from(m: NullMaterial) -> Self {
        Self::Null(m)
    }
}

impl From<PluginConstitutive> for MaterialModel {
    fn from(m: PluginConstitutive) -> Self {
        Self::Plugin(m)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{
        DruckerPrager, ElasticPlastic, Hjc, Hypoelastic, NullMaterial, ObjectiveRate, ViscoScram,
    };
    use brisance_core::Mat3;

    #[test]
    fn variants_dispatch_to_their_models() {
        let inner = ElasticPlastic::steel_4340_seed000();
        let m = MaterialModel::from(inner.clone());
        assert_eq!(m.name(), "elastic_plastic");
        assert_eq!(m.history_len(), inner.history_len());
        assert_eq!(m.wave_speed(7830.0, 0.0), inner.wave_speed(7830.0, 0.0));
        assert!(m.eos().is_some());
        assert!(!m.is_elastic());
        let h = MaterialModel::from(Hypoelastic::ofhc_copper_seed000(ObjectiveRate::Jaumann));
        assert_eq!(h.history_len(), 0);
        assert!(h.is_elastic() && h.eos().is_none() && !h.relaxes());
        assert_eq!(MaterialModel::VARIANTS.len(), 6);
        let pbx = MaterialModel::from(ViscoScram::pbx_9501(ObjectiveRate::Jaumann));
        assert_eq!(pbx.name(), "visco_scram");
        assert_eq!(pbx.history_len(), 31);
        assert!(!pbx.is_elastic() && pbx.relaxes() && pbx.eos().is_none());
        let mut h = vec![0.0; pbx.history_len()];
        pbx.init_history(&mut h);
        assert_eq!(pbx.damage(&h), &[3.0e-5]);
        let soil = MaterialModel::from(DruckerPrager::soil_luccioni_luege_2006());
        assert_eq!(soil.name(), "drucker_prager");
        assert!(!soil.is_elastic() && soil.eos().is_none());
        let concrete = MaterialModel::from(Hjc::concrete_48mpa_hjc1993());
        assert_eq!(concrete.name(), "hjc");
        assert_eq!(
            concrete.damage(&[0.0, 0.1, 0.2, 0.0, 0.0, 0.0, 1.0]),
            &[0.1, 0.2]
        );
        let air = MaterialModel::from(NullMaterial::air());
        assert_eq!(air.name(), "null");
        assert!(air.is_elastic() && !air.is_viscous() && air.eos().is_some());
        assert_eq!(
            air.wave_speed(1.225, 2.0685e5),
            NullMaterial::air().wave_speed(1.225, 2.0685e5)
        );
        let _ = Mat3::zeros();
    }

    #[test]
    fn every_variant_validates_and_names_a_bad_field() {
        for m in [
            MaterialModel::from(DruckerPrager::soil_luccioni_luege_2006()),
            Hjc::concrete_48mpa_hjc1993().into(),
            Hjc::concrete_25mpa_seed001().into(),
            NullMaterial::air().into(),
        ] {
            assert!(m.validate().is_ok(), "{m:?}");
        }
        let bad = MaterialModel::from(NullMaterial {
            viscosity: f64::NAN,
            ..NullMaterial::air()
        });
        assert!(bad
            .validate()
            .unwrap_err()
            .to_string()
            .contains("viscosity"));
    }

    /// The hand-written serde of the enum reads and writes the built-in
    /// models as the derived one did: `Name(fields)`, the same values back,
    /// and an unknown name refused with the list of names.
    #[test]
    fn built_in_models_read_and_write_under_their_variant_names() {
        let options = crate::plugin::ron_options();
        for m in [
            MaterialModel::from(Hypoelastic::ofhc_copper_seed000(ObjectiveRate::Jaumann)),
            ElasticPlastic::steel_4340_cookoff_seed000().into(),
            DruckerPrager::soil_luccioni_luege_2006().into(),
            Hjc::concrete_48mpa_hjc1993().into(),
            NullMaterial::air().into(),
            ViscoScram::pbx_9501(ObjectiveRate::GreenNaghdi).into(),
        ] {
            for options in [ron::Options::default(), options.clone()] {
                let text = options.to_string(&m).unwrap();
                assert!(text.starts_with(&format!("{}(", m.variant())), "{text}");
                assert_eq!(options.from_str::<MaterialModel>(&text).unwrap(), m);
            }
        }
        let err = ron::from_str::<MaterialModel>("Elastic(shear_modulus: 1.0)").unwrap_err();
        for name in MaterialModel::VARIANTS {
            assert!(err.to_string().contains(&format!("`{name}`")), "{err}");
        }
    }

    crate::material_contract_tests!(
        hypoelastic_copper_jaumann,
        Hypoelastic::ofhc_copper_seed000(ObjectiveRate::Jaumann)
    );
    crate::material_contract_tests!(
        hypoelastic_copper_green_naghdi,
        Hypoelastic::ofhc_copper_seed000(ObjectiveRate::GreenNaghdi)
    );
    crate::material_contract_tests!(
        pbx_9501_viscoscram_jaumann,
        ViscoScram::pbx_9501(ObjectiveRate::Jaumann)
    );
    crate::material_contract_tests!(
        pbx_9501_viscoscram_green_naghdi,
        ViscoScram::pbx_9501(ObjectiveRate::GreenNaghdi)
    );
    crate::material_contract_tests!(copper_seed000, ElasticPlastic::ofhc_copper_seed000());
    crate::material_contract_tests!(
        copper_johnson_cook,
        ElasticPlastic::ofhc_copper_johnson_cook()
    );
    crate::material_contract_tests!(steel_4340_seed000, ElasticPlastic::steel_4340_seed000());
    crate::material_contract_tests!(
        steel_4340_cookoff_seed000,
        ElasticPlastic::steel_4340_cookoff_seed000()
    );
    crate::material_contract_tests!(
        copper_johnson_cook_tepla_drucker_jaumann,
        ElasticPlastic {
            tepla: Some(crate::Tepla {
                initial_porosity: crate::Gaussian {
                    min: Some(0.001),
                    max: Some(0.02),
                    seed: 7,
                    ..crate::Gaussian::new(0.01, 0.005)
                },
                ..crate::Tepla::steel_4340_seed000()
            }),
            stability: crate::StabilityChecks {
                drucker: true,
                hyperbolicity: false,
            },
            rate: ObjectiveRate::Jaumann,
            ..ElasticPlastic::ofhc_copper_johnson_cook()
        }
    );
    crate::material_contract_tests!(
        steel_4340_cookoff_hyperbolicity_jaumann,
        ElasticPlastic {
            stability: crate::StabilityChecks {
                drucker: false,
                hyperbolicity: true,
            },
            rate: ObjectiveRate::Jaumann,
            ..ElasticPlastic::steel_4340_cookoff_seed000()
        }
    );
    crate::material_contract_tests!(
        copper_tepla_without_damage_hyperbolicity,
        ElasticPlastic {
            damage: None,
            tepla: Some(crate::Tepla::steel_4340_seed000()),
            stability: crate::StabilityChecks {
                drucker: false,
                hyperbolicity: true,
            },
            ..ElasticPlastic::ofhc_copper_johnson_cook()
        }
    );
    crate::material_contract_tests!(rha_steel_seed001, ElasticPlastic::rha_steel_seed001());
    crate::material_contract_tests!(
        soil_drucker_prager,
        DruckerPrager::soil_luccioni_luege_2006()
    );
    crate::material_contract_tests!(
        soil_drucker_prager_dilatant_green_naghdi,
        DruckerPrager {
            q_psi: 0.2,
            tensile_strength: 50.0e3,
            rate: ObjectiveRate::GreenNaghdi,
            ..DruckerPrager::soil_luccioni_luege_2006()
        }
    );
    crate::material_contract_tests!(concrete_hjc1993, Hjc::concrete_48mpa_hjc1993());
    crate::material_contract_tests!(
        concrete_25mpa_jiang_green_naghdi,
        Hjc {
            tensile_damage: Some(crate::hjc::JiangTensileDamage {
                growth_factor: 1.0e6,
                threshold_stress: 1.0e6,
                exponent: 1.0,
                initial_damage: 0.01,
                critical_damage: 0.5,
            }),
            rate: ObjectiveRate::GreenNaghdi,
            ..Hjc::concrete_25mpa_seed001()
        }
    );
    crate::material_contract_tests!(null_air, NullMaterial::air());
    crate::material_contract_tests!(
        null_viscous_tnt_products,
        NullMaterial {
            eos: brisance_eos::EosModel::Jwl(brisance_eos::Jwl::tnt()),
            viscosity: 1.0e-3,
        }
    );
}
