//! Brisance core: the traits every physics component implements and the
//! small shared types they exchange.
//!
//! - [`Eos`]: thermodynamics of one material (all seeds' equations of state).
//! - [`Material`]: a constitutive (stress-update) model.
//! - [`ReactionModel`]: mass conversion between a reactant and its products.
//! - [`Solver`]: a method (or a coupled pipeline) that owns its state and
//!   advances it in time; the run loop in `brisance-compose` drives any
//!   `Solver` without knowing which it is.
//!
//! Units are SI everywhere (kg, m, s, Pa, J/kg, K).

pub mod eos;
pub mod error;
pub mod exact_sum;
pub mod geometry;
pub mod material;
pub mod output;
pub mod reaction;
pub mod solver;
pub mod tensor;

#[cfg(any(test, feature = "contracts"))]
pub mod contracts;
#[cfg(any(test, feature = "contracts"))]
pub mod solver_contract;

pub use eos::Eos;
pub use error::{EosError, SolverError};
pub use exact_sum::{ExactSum, ExactTotals};
pub use geometry::Geometry;
pub use material::{Material, StressUpdate, StressUpdateInput};
pub use output::{
    AxisWindow, CellData, CellPiece, CellPieces, ConservationTotals, NodeData, ParticleData,
    SafeguardUse, SetQuantity, UniformGridGeometry,
};
pub use reaction::{ReactionModel, ReactionState};
pub use solver::{IntoSolver, Solver, StatePieces};
pub use tensor::{Mat3, Vec3};
