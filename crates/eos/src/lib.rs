//! Brisance equations of state, one module per model, each implementing
//! [`brisance_core::Eos`] and joining the contract property tests with one
//! line in its test module.
//!
//! - [`ideal_gas`]: γ-law gas (seed 001 eq 55).

pub mod ideal_gas;

pub use ideal_gas::IdealGas;
