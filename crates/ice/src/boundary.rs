//! Boundary conditions of the ICE solver, one per domain face.
//!
//! They are imposed through the ghost cells that the grid's halo exchange
//! fills (`brisance_grid`), so every step sees them the same way:
//! - [`IceBoundary::Symmetry`]: mirror (scalars copied, the normal velocity
//!   negated); the face velocity of eq 19 is set to zero on the face.
//! - [`IceBoundary::Outflow`]: zero gradient (ghosts copy the boundary
//!   cell), so waves leave with little reflection.
//! - [`IceBoundary::FixedVelocity`]: a wall moving at a given velocity
//!   (zero for the rate stick's wall): mirrored scalars, ghost velocity
//!   2u_w − u_mirror, face velocity u_w·n on the face.
//! - [`IceBoundary::FixedState`]: ghosts hold a given state (inflow or an
//!   ambient reservoir).
//! - [`IceBoundary::Periodic`]: both faces of an axis.

use crate::CellState;

/// A boundary condition on one face of the domain.
#[derive(Debug, Clone, PartialEq)]
pub enum IceBoundary {
    /// Symmetry plane / slip wall.
    Symmetry,
    /// Zero-gradient outflow.
    Outflow,
    /// A wall moving with this velocity, m/s.
    FixedVelocity([f64; 3]),
    /// A fixed state behind the face.
    FixedState(CellState),
    /// Periodic (must be set on both faces of the axis).
    Periodic,
}

impl IceBoundary {
    /// The velocity of the wall for symmetry and fixed-velocity faces.
    pub fn wall_velocity(&self) -> Option<[f64; 3]> {
        match self {
            Self::Symmetry => Some([0.0; 3]),
            Self::FixedVelocity(u) => Some(*u),
            _ => None,
        }
    }
}
