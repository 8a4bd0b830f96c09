//! Brisance: simulation of explosions of energetic devices and their effect
//! on nearby structures.
//!
//! This facade re-exports the component crates so a program (or the
//! validation tool) can depend on one crate:
//!
//! - [`core`]: the `Eos`, `Material`, `ReactionModel` and `Solver` traits.
//! - [`grid`]: Cartesian levels of patches with ghost layers.
//! - [`eos`]: equations of state.
//! - [`fdm`]: the Lax–Wendroff finite-difference Euler solver.
//! - [`ice`]: the multi-material cell-centred ICE method of seed 000.
//! - [`constitutive`]: stress-update models for solids and particle fluids.
//! - [`mpm`]: the explicit material point method.
//! - [`pd`]: bond-based peridynamics with the detonation model of seed 004.
//! - [`lattice`]: the mass–spring–damper lattice (MSDM) of seed 003.
//! - [`couple`]: the coupled steps — ICE–MPM (seed 000 §3.3) and the
//!   FDM–MPM bridge (seed 001 §3).
//! - [`reaction`]: program burn and the detonation-products isentrope.
//! - [`io`]: VTK, CSV, summary and checkpoint writers.
//! - [`compose`]: the RON scenario schema, registry and run loop.
//! - [`verification`]: exact solutions the validation suite compares
//!   against (the `brisance-validation` crate).

pub use brisance_compose as compose;
pub use brisance_constitutive as constitutive;
pub use brisance_core as core;
pub use brisance_couple as couple;
pub use brisance_eos as eos;
pub use brisance_fdm as fdm;
pub use brisance_grid as grid;
pub use brisance_ice as ice;
pub use brisance_io as io;
pub use brisance_lattice as lattice;
pub use brisance_mpm as mpm;
pub use brisance_pd as pd;
pub use brisance_reaction as reaction;

pub use brisance_validation as verification;

/// Number of threads in the current rayon pool (what the kernels use).
pub fn rayon_threads() -> usize {
    rayon::current_num_threads()
}
