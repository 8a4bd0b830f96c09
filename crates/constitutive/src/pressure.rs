//! The volumetric part of a solid's stress: the pressure, either from a
//! constant bulk modulus (hypoelastic) or from an equation of state.

use crate::{error::positive, ConstitutiveError};
use brisance_core::Eos;
use brisance_eos::EosModel;
use serde::{Deserialize, Serialize};

/// How a solid model gets its pressure p (compression positive; the
/// Cauchy stress is σ = s − p I).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub enum PressureModel {
    /// Hypoelastic pressure ṗ = −K tr D: p_{n+1} = p_n − K tr(D) Δt, with
    /// p_n = −tr(σ_n)/3 from the stress handed in.
    Linear {
        /// Bulk modulus K, Pa.
        bulk_modulus: f64,
    },
    /// p = p(ρ, e) from an equation of state at the density and specific
    /// internal energy handed in (seed 000 §4.2: "the pressure behaves
    /// according to an equation of state", eq 40).
    Eos(EosModel),
}

impl PressureModel {
    /// Checks the parameters; the message names the bad field.
    pub fn validate(&self, model: &'static str) -> Result<(), ConstitutiveError> {
        match self {
            Self::Linear { bulk_modulus } => positive(model, "bulk_modulus", *bulk_modulus),
            Self::Eos(eos) => eos
                .validate()
                .map_err(|detail| ConstitutiveError::Eos { model, detail }),
        }
    }

    /// Pressure at the end of the step, Pa.
    ///
    /// `p_old` is −tr(σ_n)/3, `tr_d` the trace of the rate of deformation
    /// (1/s), `rho` (kg/m³) and `e` (J/kg) the state handed to the update.
    #[inline]
    pub fn pressure(&self, p_old: f64, tr_d: f64, dt: f64, rho: f64, e: f64) -> f64 {
        match self {
            Self::Linear { bulk_modulus } => p_old - bulk_modulus * tr_d * dt,
            Self::Eos(eos) => eos.pressure(rho, e),
        }
    }

    /// Longitudinal wave speed c_L = √(c_bulk² + 4G/(3ρ)) of a solid of
    /// shear modulus G (Pa) on this pressure, m/s (0 where c² < 0).
    #[inline]
    pub fn longitudinal_wave_speed(&self, rho: f64, e: f64, shear_modulus: f64) -> f64 {
        let c2 = self.bulk_sound_speed_squared(rho, e) + 4.0 * shear_modulus / (3.0 * rho);
        c2.max(0.0).sqrt()
    }

    /// Squared bulk sound speed, m²/s²: K/ρ or the EOS's c²(ρ, e).
    #[inline]
    pub fn bulk_sound_speed_squared(&self, rho: f64, e: f64) -> f64 {
        match self {
            Self::Linear { bulk_modulus } => bulk_modulus / rho,
            Self::Eos(eos) => eos.sound_speed_squared(rho, e),
        }
    }

    /// The equation of state, if the pressure comes from one.
    pub fn eos(&self) -> Option<&dyn Eos> {
        match self {
            Self::Linear { .. } => None,
            Self::Eos(eos) => Some(eos),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use brisance_eos::MieGruneisenLinear;

    #[test]
    fn linear_pressure_rises_by_k_times_volumetric_compression() {
        let p = PressureModel::Linear {
            bulk_modulus: 117.0e9,
        };
        // tr D Δt = −1e-4 → Δp = 117e9 × 1e-4 = 1.17e7 Pa.
        let got = p.pressure(2.0e6, -1.0e3, 1.0e-7, 8930.0, 0.0);
        assert!((got - (2.0e6 + 1.17e7)).abs() < 1e-6, "{got}");
    }

    #[test]
    fn eos_pressure_is_the_eos_value_and_a_bad_eos_is_named() {
        let mg = MieGruneisenLinear::steel_4340();
        let p = PressureModel::Eos(EosModel::MieGruneisenLinear(mg));
        assert_eq!(
            p.pressure(0.0, 0.0, 1e-7, 8000.0, 1e5),
            mg.pressure(8000.0, 1e5)
        );
        let bad = PressureModel::Eos(EosModel::MieGruneisenLinear(MieGruneisenLinear {
            c0: -1.0,
            ..mg
        }));
        let err = bad.validate("elastic_plastic").unwrap_err().to_string();
        assert!(err.contains("c0"), "{err}");
    }
}
