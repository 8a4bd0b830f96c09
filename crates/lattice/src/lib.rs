//! The mass–spring–damper lattice (MSDM) of seed 003 (Gallagher, ch. 2):
//! bond-based peridynamics on a structured lattice.
//!
//! - [`geometry`]: the lattice from indexing, solid and exterior (ghost)
//!   nodes, the dual-mesh node volume (fig. 8).
//! - [`law`]: materials and the force law of one spring: k = E|ξ|,
//!   hysteretic and viscous damping in Kelvin–Voigt, Maxwell and
//!   standard-linear arrangements (eqs 5–6), piecewise-linear plastic
//!   springs (fig. 2), fracture.
//! - [`model`]: the node state U = {m_k, u, V, P, T, e} (§2.2) in
//!   structure-of-arrays, forces (eqs 9, 10b), Jacobians (eq 20), the
//!   energy equation (eqs 10c, 11–15).
//! - [`integrate`]: explicit Euler, velocity Verlet, implicit Euler and
//!   implicit RK2 (§2.3, eqs 16–22).
//! - [`regress`]: surface regression at Arrhenius rates (§2.4).
//! - [`pack`]: crystal/binder images and random disc packs (§3.1, §4.1).
//! - [`solver`]: the lattice behind the core `Solver` trait.
//! - [`sparse`]: the sparse matrix and iterative solver of the implicit
//!   steps.
//! - [`cases`]: the verification cases V-OSC, V-ROD and V-IMPEDANCE
//!   (§2.5), shared by the tests and `cargo xtask validate`.
//!
//! The choices the seed leaves open are written in
//! `docs/physics/lattice/`.

// Index loops over the 3 axes and over node/dof numbers read closest to
// the equations.
#![allow(clippy::needless_range_loop)]

pub mod cases;
pub mod geometry;
pub mod hotspot;
pub mod integrate;
pub mod law;
pub mod model;
pub mod pack;
pub mod pipeline;
mod ranks;
pub mod regress;
pub mod solver;
pub mod sparse;
pub mod stats;
mod stencil;

pub use geometry::{dual_volume, Dim, Direction, Geometry, NodeKind};
pub use law::{Damping, Hysteretic, LatticeMaterial, PairLaw, Plasticity, SpringState};
pub use model::{
    bond_force, bond_jacobian, BondEval, ImplicitTiming, Integrator, LinearSolver, MsdmError,
    MsdmLattice, MsdmOptions, StepReport, Surroundings,
};
pub use pack::{area_fraction, node_mass_fraction, random_disc_pack, read_image, GrayImage};
pub use pipeline::{
    register, LatticeBoundaryConfig, LatticeConfig, LatticeMaterialConfig, PackConfig,
    RegressionConfig,
};
pub use regress::{Arrhenius, SurfaceRegression};
#[cfg(test)]
mod tests;
