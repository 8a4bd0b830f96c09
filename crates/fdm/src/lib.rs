//! Brisance FDM: the explicit three-dimensional finite-difference Euler
//! solver of seed 001 §2.1.
//!
//! - [`state`]: conservative variables U = (ρ, ρu, ρv, ρw, E) (seed 001
//!   eq 2) and primitive states.
//! - [`gas`]: the gas law of the kernels: one species, or detonation
//!   products in air carried as a mass fraction with a pressure-equilibrium
//!   mixture rule.
//! - [`detonation`]: the 1D (planar, cylindrical, spherical) program-burn
//!   detonation of seed 001 §4.1 (eqs 52–53).
//! - [`viscosity`]: the adaptive artificial viscosity of seed 001 eqs 3–5.
//! - [`sweep`]: one directional operator L_d(Δt/2): smoothing (eq 3) then a
//!   two-step (Richtmyer) Lax–Wendroff step (the scheme eqs 7–9 stand for).
//! - [`solver`]: the [`FdmSolver`], the Yanenko splitting of eq 6, the CFL
//!   time step and the `Solver` implementation.
//! - [`pipeline`]: the `Fdm` pipeline's section of a scenario
//!   ([`FdmConfig`]), its checks, builder and description, through which
//!   the composer runs it.
//!
//! A grid built for the solver needs [`ghost_layers`] ghost layers
//! ([`GHOST`], or [`GHOST_RZ`] on an (r, z) grid), and its Courant number
//! is at most [`MAX_CFL`]; builders outside this crate take them from the
//! crate root, not from the modules that use them.
//!
//! The numerical choices the paper leaves open are written down in
//! `docs/physics/fdm.md`.

pub mod detonation;
pub mod gas;
pub mod limiter;
pub mod pipeline;
pub mod solver;
pub mod state;
pub mod sweep;
pub mod viscosity;

pub use gas::{GasLaw, ProductsInAir};
pub use limiter::FaceLimiter;
pub use pipeline::FdmConfig;
pub use solver::{FdmBoundary, FdmError, FdmMemory, FdmOptions, FdmSolver, MAX_CFL};
pub use state::PrimitiveState;
pub use sweep::{ghost_layers, GHOST, GHOST_RZ};
pub use viscosity::ArtificialViscosity;

#[cfg(test)]
mod rz_tests;
#[cfg(test)]
mod species_tests;
#[cfg(test)]
mod tests;
