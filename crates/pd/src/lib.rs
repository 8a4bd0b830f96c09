//! Brisance peridynamics: meshfree bond-based peridynamics with the
//! detonation model of seed 004 (Demmie).
//!
//! - [`cases`]: E-PD-CYL and E-PD-FRAG, shared by tests and `xtask`.
//! - [`lattice`]: nodes on a regular lattice filling the bodies' shapes,
//!   with reference volumes (seed 004 "Numerical Method").
//! - [`cell_list`]: the O(N) hashed cell list for families and contacts.
//! - [`family`]: families within the horizon as compressed rows, with the
//!   partial-volume correction.
//! - [`material`]: proportional micro-elastic and micro-plastic solids
//!   (eqs 7–8, 28), critical stretch with the damage-stretch and
//!   minimum-stretch refinements; detonation products as gases.
//! - [`surface`]: the energy-method surface correction of solid bonds.
//! - [`forces`]: the bond-force kernels of eq 9 (solids, eq 8; gases,
//!   eqs 17–19).
//! - [`contact`]: short-range forces (eq 27).
//! - [`viscosity`]: the products' pairwise artificial viscosity, its heat
//!   returned to the products.
//! - [`fragments`]: fragments as connected components, CMD output.
//! - [`solver`]: [`PdSolver`], the time integration (eq 10 in velocity
//!   form), stable step (eqs 24–26), program burn, behind the core
//!   `Solver` trait.
//!
//! The choices the seed leaves open are written in `docs/physics/pd/`.
//! Units are SI throughout.

pub mod cases;
pub mod cell_list;
pub mod contact;
pub mod family;
pub mod forces;
pub mod fragments;
pub mod lattice;
pub mod material;
pub mod pipeline;
pub mod solver;
pub mod strength;
pub mod surface;
pub mod viscosity;

pub use brisance_reaction::{DetonationPoint, ProductsIsentrope};
pub use family::{build_families, build_families_where, partial_volume, Families};
pub use forces::{bond_forces, bond_forces_dissipating_in, BondLaw, ForceInput, NodeForce};
pub use fragments::{
    cumulative_mass_distribution, write_cmd_csv, write_fragments_csv, CmdPoint, Fragment,
};
pub use lattice::{fill_lattice, BodySpec, Dimension, LatticeJitter, LatticeSpec, NodeCloud};
pub use material::{
    micromodulus, spring_constant, Gas, PdMaterial, Proportional, ProportionalKind, Reactant,
};
pub use pipeline::{
    PdBoundaryConfig, PdConfig, PdContactConfig, PdDetonationConfig, PdMaterialConfig,
};
pub use solver::{
    BurnMethod, ContactOptions, DetonationSpec, PdBoundary, PdOptions, PdSetup, PdSetupError,
    PdSolver, ProductsFamily, CLOSING_STEP_FRACTION,
};
pub use viscosity::GasViscosity;
