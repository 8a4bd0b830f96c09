//! The Steinberg–Cochran–Guinan (SCG) strength model of metals at high
//! strain rate, as a constitutive model in its own crate (a plugin):
//! D. J. Steinberg, S. G. Cochran and M. W. Guinan, *A constitutive model
//! for metals applicable at high-strain rate*, J. Appl. Phys. 51 (1980)
//! 1498–1504.
//!
//! The shear modulus and the yield stress rise with pressure and fall with
//! temperature in proportion, the yield hardens with plastic strain up to
//! a cap, and the metal has no strength at and above its melt temperature.
//! The deviator follows a J2 radial return; the pressure comes from the
//! metal's equation of state, as for the built-in J2 metal
//! (`brisance_constitutive::elastic_plastic`), whose objective rates,
//! radial return and plastic heating it reuses.
//!
//! - [`steinberg_guinan`]: the model, its [`brisance_core::Material`]
//!   update and the OFHC copper preset.
//! - [`registration`]: [`register`], which names it `SteinbergGuinan` in
//!   the program's registry of constitutive models
//!   ([`brisance_constitutive::MaterialRegistry`]).
//!
//! Units are SI; tension is positive; the pressure is p = −tr(σ)/3.
//! Docs: `docs/physics/constitutive/steinberg_guinan.md`.

pub mod registration;
pub mod steinberg_guinan;

pub use registration::register;
pub use steinberg_guinan::{MeltTemperature, SteinbergGuinan};
