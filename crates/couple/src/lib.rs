//! Brisance couple: the coupled finite-difference / material-point method
//! (CFDMP) of seed 001 §3 and the detonation remap of seed 001 §4.1.
//!
//! - [`remap`]: a 1D (planar, cylindrical, spherical) detonation profile
//!   mapped onto a 1D/2D/3D FDM grid as its initial state, conserving the
//!   charge's mass, energy, products mass and radial momentum to round-off.

pub mod remap;

pub use remap::{remap, RadialProfile, RemapError, RemapReport, RemapTarget, Remapped};
