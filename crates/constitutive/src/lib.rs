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
//! - [`damage`]: Johnson–Cook damage and the failed point (seed 000 eq 47).
//! - [`model`]: the [`MaterialModel`] enum a config names models through.
//! - [`contracts`]: the property checks every model passes, and the
//!   `material_contract_tests!` macro that joins a model to them.
//!
//! Units are SI; tension is positive; the pressure is p = −tr(σ)/3.

pub mod contracts;
pub mod damage;
pub mod elastic_plastic;
pub mod error;
pub mod flow_stress;
pub mod hypoelastic;
pub mod model;
pub mod objective;
pub mod pressure;

pub use damage::JohnsonCookDamage;
pub use elastic_plastic::ElasticPlastic;
pub use error::ConstitutiveError;
pub use flow_stress::FlowStress;
pub use hypoelastic::Hypoelastic;
pub use model::MaterialModel;
pub use objective::ObjectiveRate;
pub use pressure::PressureModel;
