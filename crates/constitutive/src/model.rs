//! The registry of constitutive models: one serde enum whose variant names
//! are what a config writes (`Hypoelastic(...)`, `ElasticPlastic(...)`),
//! dispatching the core [`Material`] trait with a `match` (no virtual call
//! per point). Adding a model is a module plus one variant here.

use crate::{elastic_plastic::FAILED_INDEX, ConstitutiveError, ElasticPlastic, Hypoelastic};
use brisance_core::{Eos, Material, StressUpdate, StressUpdateInput};
use serde::{Deserialize, Serialize};

/// Every constitutive model a config can name.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub enum MaterialModel {
    /// Isotropic hypoelastic solid ([`crate::hypoelastic`]).
    Hypoelastic(Hypoelastic),
    /// Hypoelastic–plastic J2 metal with Johnson–Cook flow stress and
    /// damage ([`crate::elastic_plastic`], seed 000 §4.2).
    ElasticPlastic(ElasticPlastic),
}

macro_rules! dispatch {
    ($self:ident, $m:ident => $e:expr) => {
        match $self {
            MaterialModel::Hypoelastic($m) => $e,
            MaterialModel::ElasticPlastic($m) => $e,
        }
    };
}

impl MaterialModel {
    /// The config names of every variant.
    pub const VARIANTS: &'static [&'static str] = &["Hypoelastic", "ElasticPlastic"];

    /// Checks the parameters; the message names the bad field.
    pub fn validate(&self) -> Result<(), ConstitutiveError> {
        dispatch!(self, m => m.validate())
    }

    /// Whether the model is purely elastic (no plastic flow, no failure).
    pub fn is_elastic(&self) -> bool {
        matches!(self, Self::Hypoelastic(_))
    }

    /// The flow stress at a point's history and temperature (Pa), for
    /// plastic models.
    pub fn flow_stress(&self, history: &[f64], temperature: f64) -> Option<f64> {
        match self {
            Self::Hypoelastic(_) => None,
            Self::ElasticPlastic(m) => Some(m.current_flow_stress(history, temperature)),
        }
    }

    /// Whether the history records a failed point.
    pub fn is_failed(&self, history: &[f64]) -> bool {
        match self {
            Self::Hypoelastic(_) => false,
            Self::ElasticPlastic(_) => history[FAILED_INDEX] != 0.0,
        }
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{ElasticPlastic, Hypoelastic, ObjectiveRate};
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
        assert!(h.is_elastic() && h.eos().is_none());
        assert_eq!(MaterialModel::VARIANTS.len(), 2);
        let _ = Mat3::zeros();
    }

    crate::material_contract_tests!(
        hypoelastic_copper_jaumann,
        Hypoelastic::ofhc_copper_seed000(ObjectiveRate::Jaumann)
    );
    crate::material_contract_tests!(
        hypoelastic_copper_green_naghdi,
        Hypoelastic::ofhc_copper_seed000(ObjectiveRate::GreenNaghdi)
    );
    crate::material_contract_tests!(copper_seed000, ElasticPlastic::ofhc_copper_seed000());
    crate::material_contract_tests!(
        copper_johnson_cook,
        ElasticPlastic::ofhc_copper_johnson_cook()
    );
    crate::material_contract_tests!(steel_4340_seed000, ElasticPlastic::steel_4340_seed000());
    crate::material_contract_tests!(rha_steel_seed001, ElasticPlastic::rha_steel_seed001());
}
