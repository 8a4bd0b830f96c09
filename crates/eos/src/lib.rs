//! Brisance equations of state, one module per model, each implementing
//! [`brisance_core::Eos`] and joining the contract property tests with one
//! line in its test module.
//!
//! Gases and detonation products:
//! - [`ideal_gas`]: γ-law gas (seed 001 eq 55).
//! - [`jwl`]: JWL detonation products (seed 001 eq 54).
//! - [`jwl_cterm`]: JWL C-term products of JWL++ (seed 000 eq 34, Souers
//!   et al. 2000).
//!
//! Condensed phases:
//! - [`murnaghan`]: unreacted explosive (seed 000 eq 33).
//! - [`mie_gruneisen`]: shared Hugoniots and the (p, T) → ρ solver;
//!   [`mie_gruneisen_cubic`] (seed 001 eqs 65–66),
//!   [`mie_gruneisen_linear`] (seed 000 eq 40),
//!   [`mie_gruneisen_thermal`] (seed 003 eqs 12–14).
//! - [`stiffened_gas`]: the stiffened gas (Le Métayer, Massoni & Saurel
//!   2004) of the water–air shock tube.
//! - [`threshold`]: the solid low-pressure threshold (seed 000 §3.1).
//!
//! Registry and tools:
//! - [`model`]: the [`EosModel`] enum a config names models through.
//! - [`plugin`]: how a model in its own crate registers itself, so that a
//!   config names it like a built-in one.
//! - [`tools`]: CJ state, principal isentrope, Gurney velocity and the
//!   volume-burn reference pressure (seed 004 eqs 20–21).

pub mod ideal_gas;
pub mod jwl;
pub mod jwl_cterm;
pub mod mie_gruneisen;
pub mod mie_gruneisen_cubic;
pub mod mie_gruneisen_linear;
pub mod mie_gruneisen_thermal;
pub mod model;
pub mod murnaghan;
pub mod plugin;
pub mod stiffened_gas;
pub mod threshold;
pub mod tools;

pub use ideal_gas::IdealGas;
pub use jwl::Jwl;
pub use jwl_cterm::JwlCTerm;
pub use mie_gruneisen_cubic::MieGruneisenCubic;
pub use mie_gruneisen_linear::MieGruneisenLinear;
pub use mie_gruneisen_thermal::MieGruneisenThermal;
pub use model::{EosModel, SolidEos};
pub use murnaghan::Murnaghan;
pub use plugin::{EosPlugin, EosRegistry, PluginEos, PluginModel};
pub use stiffened_gas::StiffenedGas;
pub use threshold::SolidThreshold;
