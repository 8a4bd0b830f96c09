//! Brisance constitutive models: stress updates for solids behind the core
//! [`brisance_core::Material`] trait, one module per model.
//!
//! - [`objective`]: objective stress rates — Jaumann (seed 001 eq 30) and
//!   Green–Naghdi (seed 000 §4.2).
//! - [`pressure`]: the volumetric part, from a bulk modulus or an EOS
//!   (seed 000 eq 40, seed 001 eqs 65–66).
//! - [`hypoelastic`]: isotropic hypoelasticity (seed 000 §4.2).
//! - [`flow_stress`]: constant and Johnson–Cook flow stress (seed 000
//!   eqs 41–42, seed 001 eq 64).
//! - [`elastic_plastic`]: J2 radial return, plastic heating, melting
//!   (seed 000 §4.2).
//! - [`damage`]: Johnson–Cook damage and the failed point (seed 000 eq 47),
//!   with a Gaussian initial damage.
//! - [`tepla`]: TEPLA-F porosity — nucleation, growth — and failure (seed
//!   000 eqs 43–46).
//! - [`stability`]: loss of material stability — Drucker's postulate and
//!   the loss of hyperbolicity (seed 000 §4.2, eq 48).
//! - [`specific_heat`]: c_v constant or through a steel's Curie point
//!   (seed 000 §5.3, ref \[44\]), and the temperature a heat raises.
//! - [`random`]: counter-based random draws of per-point initial values
//!   (Gaussian porosity and damage, seed 000 §5.3).
//! - [`drucker_prager`]: Drucker–Prager soil with shear and tension
//!   failure (seed 001 §4.4, eqs 59–63).
//! - [`hjc`]: Holmquist–Johnson–Cook concrete, its three-region EOS and
//!   Jiang's tensile damage (seed 001 §4.3, eqs 56–58).
//! - [`null_material`]: fluids as material points — EOS pressure, optional
//!   Newtonian viscosity (for seed 001's MPM-vs-FDM comparisons).
//! - [`viscoscram`]: ViscoSCRAM, five Maxwell elements and statistical
//!   crack growth for a polymer-bonded explosive (seed 000 §4.1.2, ref
//!   \[19\]).
//! - [`model`]: the [`MaterialModel`] enum a config names models through.
//! - [`plugin`]: models in their own crates — the [`PluginMaterial`] trait,
//!   their registration and the registry the config reader resolves names
//!   through.
//! - [`contracts`]: the property checks every model passes, and the
//!   `material_contract_tests!` macro that joins a model to them.
//!
//! Units are SI; tension is positive; the pressure is p = −tr(σ)/3.

pub mod contracts;
pub mod damage;
pub mod drucker_prager;
pub mod elastic_plastic;
pub mod error;
pub mod flow_stress;
pub mod hjc;
pub mod hypoelastic;
pub mod model;
pub mod null_material;
pub mod objective;
pub mod plugin;
pub mod pressure;
pub mod random;
pub mod specific_heat;
pub mod stability;
pub mod tepla;
pub mod viscoscram;

pub use damage::JohnsonCookDamage;
pub use drucker_prager::DruckerPrager;
pub use elastic_plastic::ElasticPlastic;
pub use error::ConstitutiveError;
pub use flow_stress::FlowStress;
pub use hjc::Hjc;
pub use hypoelastic::Hypoelastic;
pub use model::MaterialModel;
pub use null_material::NullMaterial;
pub use objective::ObjectiveRate;
pub use plugin::{MaterialPlugin, MaterialRegistry, PluginConstitutive, PluginMaterial};
pub use pressure::PressureModel;
pub use random::Gaussian;
pub use specific_heat::{CurieSpecificHeat, SpecificHeat, SpecificHeatModel};
pub use stability::StabilityChecks;
pub use tepla::Tepla;
pub use viscoscram::ViscoScram;
