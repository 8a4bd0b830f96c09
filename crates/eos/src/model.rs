//! The registry of equations of state: one serde-tagged enum whose variant
//! names are what a config writes (`IdealGas(...)`, `Jwl(...)`, ...), and
//! which dispatches the [`Eos`] trait with a `match` (no virtual call).
//! Adding a model is a module plus one variant here.

use brisance_core::{Eos, EosError};
use serde::{Deserialize, Serialize};

use crate::{
    IdealGas, Jwl, JwlCTerm, MieGruneisenCubic, MieGruneisenLinear, MieGruneisenThermal, Murnaghan,
    SolidThreshold,
};

/// Forwards a trait method to the model inside each variant.
macro_rules! dispatch_eos {
    ($enum:ident { $($variant:ident),* $(,)? }) => {
        impl Eos for $enum {
            fn name(&self) -> &'static str {
                match self { $(Self::$variant(m) => m.name(),)* }
            }
            fn reference_density(&self) -> f64 {
                match self { $(Self::$variant(m) => m.reference_density(),)* }
            }
            #[inline]
            fn pressure(&self, rho: f64, e: f64) -> f64 {
                match self { $(Self::$variant(m) => m.pressure(rho, e),)* }
            }
            #[inline]
            fn dp_drho(&self, rho: f64, e: f64) -> f64 {
                match self { $(Self::$variant(m) => m.dp_drho(rho, e),)* }
            }
            #[inline]
            fn dp_de(&self, rho: f64, e: f64) -> f64 {
                match self { $(Self::$variant(m) => m.dp_de(rho, e),)* }
            }
            fn gruneisen(&self, rho: f64, e: f64) -> f64 {
                match self { $(Self::$variant(m) => m.gruneisen(rho, e),)* }
            }
            fn check_state(&self, rho: f64, e: f64) -> Result<(), EosError> {
                match self { $(Self::$variant(m) => m.check_state(rho, e),)* }
            }
            #[inline]
            fn sound_speed_squared(&self, rho: f64, e: f64) -> f64 {
                match self { $(Self::$variant(m) => m.sound_speed_squared(rho, e),)* }
            }
            #[inline]
            fn sound_speed(&self, rho: f64, e: f64) -> f64 {
                match self { $(Self::$variant(m) => m.sound_speed(rho, e),)* }
            }
            fn specific_internal_energy(&self, rho: f64, p: f64) -> Result<f64, EosError> {
                match self { $(Self::$variant(m) => m.specific_internal_energy(rho, p),)* }
            }
            fn temperature(&self, rho: f64, e: f64) -> f64 {
                match self { $(Self::$variant(m) => m.temperature(rho, e),)* }
            }
            fn specific_internal_energy_from_temperature(&self, rho: f64, t: f64) -> f64 {
                match self { $(Self::$variant(m) => m.specific_internal_energy_from_temperature(rho, t),)* }
            }
            fn cv(&self, rho: f64, t: f64) -> f64 {
                match self { $(Self::$variant(m) => m.cv(rho, t),)* }
            }
            fn density(&self, p: f64, t: f64) -> Result<f64, EosError> {
                match self { $(Self::$variant(m) => m.density(p, t),)* }
            }
            fn isothermal_compressibility(&self, p: f64, t: f64) -> Result<f64, EosError> {
                match self { $(Self::$variant(m) => m.isothermal_compressibility(p, t),)* }
            }
            fn thermal_expansivity(&self, p: f64, t: f64) -> Result<f64, EosError> {
                match self { $(Self::$variant(m) => m.thermal_expansivity(p, t),)* }
            }
            fn density_and_derivatives(&self, p: f64, t: f64) -> Result<(f64, f64, f64), EosError> {
                match self { $(Self::$variant(m) => m.density_and_derivatives(p, t),)* }
            }
        }

        impl $enum {
            /// Checks the parameters; the message names the bad field.
            pub fn validate(&self) -> Result<(), String> {
                match self { $(Self::$variant(m) => m.validate(),)* }
            }

            /// The config name of this model (`IdealGas`, `Jwl`, ...).
            pub fn variant(&self) -> &'static str {
                match self { $(Self::$variant(_) => stringify!($variant),)* }
            }

            /// The config names of every variant.
            pub const VARIANTS: &'static [&'static str] = &[$(stringify!($variant)),*];
        }
    };
}

/// Every equation of state a config can name.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub enum EosModel {
    /// γ-law gas (seed 001 eq 55).
    IdealGas(IdealGas),
    /// JWL detonation products (seed 001 eq 54).
    Jwl(Jwl),
    /// JWL C-term products of JWL++ (seed 000 eq 34).
    JwlCTerm(JwlCTerm),
    /// Murnaghan unreacted explosive (seed 000 eq 33).
    Murnaghan(Murnaghan),
    /// Mie–Grüneisen on a cubic Hugoniot (seed 001 eqs 65–66).
    MieGruneisenCubic(MieGruneisenCubic),
    /// Mie–Grüneisen on the linear Uₛ–uₚ Hugoniot (seed 000 eq 40).
    MieGruneisenLinear(MieGruneisenLinear),
    /// Thermal Mie–Grüneisen of the lattice (seed 003 eqs 12–14).
    MieGruneisenThermal(MieGruneisenThermal),
    /// A solid EOS with the low-pressure threshold (seed 000 §3.1).
    SolidThreshold(SolidThreshold<SolidEos>),
}

dispatch_eos!(EosModel {
    IdealGas,
    Jwl,
    JwlCTerm,
    Murnaghan,
    MieGruneisenCubic,
    MieGruneisenLinear,
    MieGruneisenThermal,
    SolidThreshold,
});

/// The solid equations of state the low-pressure threshold can wrap.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub enum SolidEos {
    /// Murnaghan (seed 000 eq 33).
    Murnaghan(Murnaghan),
    /// Mie–Grüneisen, cubic Hugoniot (seed 001 eqs 65–66).
    MieGruneisenCubic(MieGruneisenCubic),
    /// Mie–Grüneisen, linear Uₛ–uₚ (seed 000 eq 40).
    MieGruneisenLinear(MieGruneisenLinear),
    /// Thermal Mie–Grüneisen (seed 003 eqs 12–14).
    MieGruneisenThermal(MieGruneisenThermal),
}

dispatch_eos!(SolidEos {
    Murnaghan,
    MieGruneisenCubic,
    MieGruneisenLinear,
    MieGruneisenThermal
});

impl EosModel {
    /// Whether the model describes a gas (ideal gas or detonation
    /// products), the materials an Euler solver can carry.
    pub fn is_gas(&self) -> bool {
        matches!(self, Self::IdealGas(_) | Self::Jwl(_) | Self::JwlCTerm(_))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{JwlCTerm, MieGruneisenCubic, MieGruneisenThermal};

    fn ron() -> ron::Options {
        ron::Options::default().with_default_extension(
            ron::extensions::Extensions::IMPLICIT_SOME
                | ron::extensions::Extensions::UNWRAP_VARIANT_NEWTYPES,
        )
    }

    #[test]
    fn variants_dispatch_to_their_models() {
        let air = IdealGas::air();
        let m = EosModel::IdealGas(air);
        assert_eq!(m.name(), air.name());
        assert_eq!(m.pressure(1.2, 2e5), air.pressure(1.2, 2e5));
        let tnt = EosModel::Jwl(Jwl::tnt());
        assert_eq!(tnt.pressure(2000.0, 4e6), Jwl::tnt().pressure(2000.0, 4e6));
        assert!(tnt.is_gas());
        assert!(!EosModel::Murnaghan(Murnaghan::anfo_k1()).is_gas());
    }

    #[test]
    fn a_config_names_the_model_by_its_variant() {
        let m: EosModel = ron()
            .from_str("IdealGas(gamma: 1.4, cv: 717.6, rho0: 1.225)")
            .unwrap();
        assert_eq!(m, EosModel::IdealGas(IdealGas::new(1.4, 717.6, 1.225)));
        let err = ron()
            .from_str::<EosModel>("PerfectGas(gamma: 1.4)")
            .unwrap_err();
        assert!(err.to_string().contains("IdealGas"), "{err}");
        assert_eq!(EosModel::VARIANTS.len(), 8);
    }

    #[test]
    fn every_variant_fuses_density_and_derivatives_to_the_bit() {
        // Each model's density_and_derivatives against its three separate
        // calls, through the registry, at states inside and outside each
        // model's domain (errors must be the first separate call's).
        let models = [
            EosModel::IdealGas(IdealGas::air()),
            EosModel::Jwl(Jwl::tnt()),
            EosModel::JwlCTerm(JwlCTerm::qm100()),
            EosModel::Murnaghan(Murnaghan::anfo_k1()),
            EosModel::MieGruneisenCubic(MieGruneisenCubic::steel_seed001()),
            EosModel::MieGruneisenLinear(MieGruneisenLinear::ofhc_copper()),
            EosModel::MieGruneisenThermal(MieGruneisenThermal::hmx_seed003()),
            EosModel::SolidThreshold(SolidThreshold::new(SolidEos::MieGruneisenLinear(
                MieGruneisenLinear::ofhc_copper(),
            ))),
        ];
        assert_eq!(models.len(), EosModel::VARIANTS.len());
        for m in &models {
            for p in [-3e9, -1.0, 0.0, 1.0, 101_325.0, 1e8, 1e10, 1e12, f64::NAN] {
                for t in [0.0, 1.0, 300.0, 3000.0, 1e5] {
                    let fused = m.density_and_derivatives(p, t);
                    let separate = m.density(p, t).and_then(|rho| {
                        Ok((
                            rho,
                            m.isothermal_compressibility(p, t)?,
                            m.thermal_expansivity(p, t)?,
                        ))
                    });
                    match (&fused, &separate) {
                        (Ok(a), Ok(b)) => assert!(
                            a.0.to_bits() == b.0.to_bits()
                                && a.1.to_bits() == b.1.to_bits()
                                && a.2.to_bits() == b.2.to_bits(),
                            "{}: {a:?} vs {b:?} at p = {p}, T = {t}",
                            m.variant()
                        ),
                        _ => assert_eq!(fused, separate, "{} at p = {p}, T = {t}", m.variant()),
                    }
                }
            }
        }
    }

    #[test]
    fn the_threshold_wraps_a_named_solid() {
        let m = EosModel::SolidThreshold(SolidThreshold::new(SolidEos::Murnaghan(
            Murnaghan::anfo_k1(),
        )));
        let back: EosModel = ron().from_str(&ron().to_string(&m).unwrap()).unwrap();
        assert_eq!(back, m);
        assert!(m.validate().is_ok());
        assert!(m.pressure(1160.0, 0.0) > 0.0);
    }
}
