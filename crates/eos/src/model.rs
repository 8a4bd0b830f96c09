//! The registry of equations of state: one enum whose variant names are
//! what a config writes (`IdealGas(...)`, `Jwl(...)`, ...), and which
//! dispatches the [`Eos`] trait with a `match` (no virtual call) for the
//! built-in models. Adding a built-in model is a module plus one variant
//! here; a model in its own crate registers itself instead
//! ([`crate::plugin`]) and arrives as the [`EosModel::Plugin`] variant under
//! its own name.

use brisance_core::{Eos, EosError};
use brisance_plugin::{Installed, PluginEnum, PluginInstance};
use serde::de::{Deserializer, VariantAccess};
use serde::{Deserialize, Serialize, Serializer};

use crate::plugin::{self, EosPlugin, PluginEos};
use crate::{
    IdealGas, Jwl, JwlCTerm, MieGruneisenCubic, MieGruneisenLinear, MieGruneisenThermal, Murnaghan,
    SolidThreshold, StiffenedGas,
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
        }
    };
}

/// The config names of the variants (`variant()`, `VARIANTS`); with
/// `plugin: Variant`, also the serde of an enum that takes plugin models
/// ([`brisance_plugin::PluginEnum`]): a variant serializes as
/// `Name(fields)`, and a name that is not built in is looked up among the
/// installed plugins.
macro_rules! named_variants {
    ($enum:ident { $($variant:ident),* $(,)? }) => {
        impl $enum {
            /// The config name of this model (`Murnaghan`, ...).
            pub fn variant(&self) -> &'static str {
                match self { $(Self::$variant(_) => stringify!($variant),)* }
            }

            /// The config names of every variant.
            pub const VARIANTS: &'static [&'static str] = &[$(stringify!($variant)),*];
        }
    };
    ($enum:ident { $($variant:ident),* $(,)? } plugin: $plugin:ident) => {
        impl $enum {
            /// The config name of this model (`IdealGas`, `Jwl`, ...; a
            /// plugin model's registered name).
            pub fn variant(&self) -> &'static str {
                match self {
                    $(Self::$variant(_) => stringify!($variant),)*
                    Self::$plugin(m) => m.plugin().name,
                }
            }

            /// The config names of the built-in variants.
            pub const VARIANTS: &'static [&'static str] = &[$(stringify!($variant)),*];
        }

        impl Serialize for $enum {
            fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
                let index = brisance_plugin::variant_index::<$enum>(self.variant());
                match self {
                    $(Self::$variant(m) => {
                        s.serialize_newtype_variant(stringify!($enum), index, stringify!($variant), m)
                    })*
                    Self::$plugin(m) => brisance_plugin::serialize_plugin::<$enum, S>(&m.0, s),
                }
            }
        }

        impl PluginEnum for $enum {
            type Plugin = EosPlugin;
            const NAME: &'static str = stringify!($enum);
            const VARIANTS: &'static [&'static str] = Self::VARIANTS;
            const EXPECTING: &'static str = "an equation of state such as `IdealGas(...)`";
            fn installed() -> &'static Installed<EosPlugin> {
                plugin::slot()
            }
            fn read_builtin<'de, A: VariantAccess<'de>>(
                name: &'static str,
                variant: A,
            ) -> Result<Self, A::Error> {
                match name {
                    $(stringify!($variant) => variant.newtype_variant().map($enum::$variant),)*
                    _ => Err(Self::unknown(name)),
                }
            }
            fn from_plugin(model: PluginInstance<EosPlugin>) -> Self {
                Self::$plugin(PluginEos(model))
            }
        }

        impl<'de> Deserialize<'de> for $enum {
            fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
                brisance_plugin::deserialize(d)
            }
        }
    };
}

/// Every equation of state a config can name: the built-in models, and
/// any model a plugin crate registered ([`crate::plugin`]).
#[derive(Debug, Clone, PartialEq)]
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
    /// Stiffened gas (Le Métayer, Massoni & Saurel 2004).
    StiffenedGas(StiffenedGas),
    /// A model from a plugin crate; a config writes it under the name the
    /// crate registered (`NobleAbel(...)`), never as `Plugin`.
    Plugin(PluginEos),
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
    StiffenedGas,
    Plugin,
});

named_variants!(EosModel {
    IdealGas,
    Jwl,
    JwlCTerm,
    Murnaghan,
    MieGruneisenCubic,
    MieGruneisenLinear,
    MieGruneisenThermal,
    SolidThreshold,
    StiffenedGas,
} plugin: Plugin);

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

named_variants!(SolidEos {
    Murnaghan,
    MieGruneisenCubic,
    MieGruneisenLinear,
    MieGruneisenThermal
});

impl EosModel {
    /// Whether the model describes a fluid an Euler solver can carry: the
    /// ideal gas, detonation products, the stiffened gas, and a plugin
    /// model registered as a gas.
    pub fn is_gas(&self) -> bool {
        match self {
            Self::IdealGas(_) | Self::Jwl(_) | Self::JwlCTerm(_) | Self::StiffenedGas(_) => true,
            Self::Plugin(p) => p.plugin().gas,
            _ => false,
        }
    }

    /// Every name a config may write: the built-in variants, then the
    /// installed plugins ([`crate::plugin::install`]).
    pub fn names() -> &'static [&'static str] {
        plugin::names()
    }

    /// The names of the models an Euler solver can carry, for messages.
    pub fn gas_names() -> Vec<&'static str> {
        let mut v = vec!["IdealGas", "Jwl", "JwlCTerm", "StiffenedGas"];
        if let Some(r) = plugin::installed() {
            v.extend(r.plugins().iter().filter(|p| p.gas).map(|p| p.name));
        }
        v
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
        assert_eq!(EosModel::VARIANTS.len(), 9);
    }

    #[test]
    fn the_stiffened_gas_is_named_from_a_config() {
        let m: EosModel = ron()
            .from_str("StiffenedGas(gamma: 4.4, p_inf: 6.0e8, cv: 1600.0, rho0: 1000.0)")
            .unwrap();
        assert_eq!(m, EosModel::StiffenedGas(StiffenedGas::water()));
        assert!(m.is_gas() && m.validate().is_ok());
        let back: EosModel = ron().from_str(&ron().to_string(&m).unwrap()).unwrap();
        assert_eq!(back, m);
        let err = ron()
            .from_str::<EosModel>("StiffenedGas(gamma: 4.4, p_infinity: 6.0e8, cv: 1.0, rho0: 1.0)")
            .unwrap_err();
        assert!(err.to_string().contains("p_infinity"), "{err}");
    }

    impl crate::PluginModel for IdealGas {
        fn validate(&self) -> Result<(), String> {
            IdealGas::validate(self)
        }
    }

    /// A plugin made of the ideal gas under another name, installed once
    /// for this test binary.
    fn install_test_plugin() {
        let mut r = crate::EosRegistry::new();
        r.register(crate::EosPlugin {
            name: "TestGas",
            summary: "the ideal gas under another name",
            docs: "docs/physics/eos/ideal_gas.md",
            example: "TestGas(gamma: 1.4, cv: 717.6)",
            gas: true,
            parse: crate::plugin::parse_params::<IdealGas>,
        });
        r.register(crate::EosPlugin {
            name: "TestSolid",
            summary: "the threshold-wrapped solid under another name",
            docs: "docs/physics/eos/threshold.md",
            example: "TestSolid(solid: Murnaghan(n: 7.4, kappa: 2.0e-10, rho0: 1160.0, cv: 1000.0, t_ref: 300.0))",
            gas: false,
            parse: crate::plugin::parse_params::<SolidThreshold<SolidEos>>,
        });
        let _ = crate::plugin::install(r);
    }

    impl crate::PluginModel for SolidThreshold<SolidEos> {
        fn validate(&self) -> Result<(), String> {
            SolidThreshold::validate(self)
        }
    }

    /// A plugin's parameter holding an enum (the wrapped solid, by its
    /// variant name) reaches the plugin by name, compares by value and
    /// writes itself back.
    #[test]
    fn a_plugin_parameter_keeps_its_enum_variant_name() {
        install_test_plugin();
        let solid = SolidThreshold::with_threshold(
            SolidEos::MieGruneisenLinear(MieGruneisenLinear::ofhc_copper()),
            2.0e5,
        );
        let text = "TestSolid(solid: MieGruneisenLinear(c0: 3940.0, s: 1.489, gamma0: 2.02, rho0: 8930.0, cv: 383.0, t0: 300.0), threshold_pressure: 2.0e5)";
        let m: EosModel = ron().from_str(text).unwrap();
        let EosModel::Plugin(p) = &m else {
            panic!("{m:?} is not a plugin model")
        };
        assert!(
            p.params().as_str().contains("MieGruneisenLinear("),
            "{:?}",
            p.params()
        );
        assert_eq!(m.pressure(9500.0, 1e5), solid.pressure(9500.0, 1e5));
        let preset = crate::PluginEos::from_model(p.plugin(), solid).unwrap();
        assert_eq!(m, EosModel::Plugin(preset));
        // Spacing and comments do not matter; the variant does.
        let spaced = text.replace(", ", ",\n  // a comment\n  ");
        assert_eq!(ron().from_str::<EosModel>(&spaced).unwrap(), m);
        let back = ron().to_string(&m).unwrap();
        assert_eq!(ron().from_str::<EosModel>(&back).unwrap(), m);
        let other = text.replace("MieGruneisenLinear", "MieGruneisenCubic");
        let err = ron().from_str::<EosModel>(&other).unwrap_err().to_string();
        assert!(
            err.contains("TestSolid: ") && err.contains("MieGruneisenCubic"),
            "{err}"
        );
    }

    #[test]
    fn a_registered_plugin_is_named_like_a_built_in_model() {
        install_test_plugin();
        let m: EosModel = ron()
            .from_str("TestGas(gamma: 1.4, cv: 717.6, rho0: 1.2)")
            .unwrap();
        let EosModel::Plugin(p) = &m else {
            panic!("{m:?} is not a plugin model")
        };
        assert_eq!(p.plugin().name, "TestGas");
        assert_eq!(m.variant(), "TestGas");
        assert!(m.is_gas() && m.validate().is_ok());
        let gas = IdealGas::new(1.4, 717.6, 1.2);
        assert_eq!(m.pressure(1.1, 2e5), gas.pressure(1.1, 2e5));
        assert_eq!(m.density(1e5, 300.0), gas.density(1e5, 300.0));
        assert_eq!(m.name(), "ideal_gas");
        // It writes itself back under its name and reads back equal.
        let text = ron().to_string(&m).unwrap();
        assert!(text.starts_with("TestGas("), "{text}");
        assert_eq!(ron().from_str::<EosModel>(&text).unwrap(), m);
        // The plugin's own checks and serde's messages reach the user.
        let bad: EosModel = ron().from_str("TestGas(gamma: 0.5, cv: 1.0)").unwrap();
        assert!(bad.validate().unwrap_err().contains("`gamma`"));
        let err = ron()
            .from_str::<EosModel>("TestGas(gamma: 1.4, c_v: 1.0)")
            .unwrap_err();
        assert!(err.to_string().contains("c_v"), "{err}");
        let err = ron().from_str::<EosModel>("NoGas(gamma: 1.4)").unwrap_err();
        assert!(err.to_string().contains("TestGas"), "{err}");
        assert!(EosModel::names().contains(&"TestGas"));
        assert!(EosModel::gas_names().contains(&"TestGas"));
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
            EosModel::StiffenedGas(StiffenedGas::water()),
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
