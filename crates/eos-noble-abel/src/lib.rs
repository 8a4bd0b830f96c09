//! The Noble–Abel co-volume gas, p = (γ − 1) ρ e / (1 − b ρ): the
//! propellant gas of interior ballistics, as an equation of state in its own
//! crate.
//!
//! - [`noble_abel`]: the model and its [`brisance_core::Eos`] methods.
//! - [`registration`]: [`register`], which names it `NobleAbel` in the
//!   program's registry of equations of state
//!   ([`brisance_eos::EosRegistry`]).
//! - [`riemann`]: the exact Riemann problem of the gas, the reference of
//!   its shock-tube validation (V-NOBLE-ABEL).
//!
//! Docs: `docs/physics/eos/noble_abel.md`.

pub mod noble_abel;
pub mod registration;
pub mod riemann;

pub use noble_abel::NobleAbel;
pub use registration::register;
