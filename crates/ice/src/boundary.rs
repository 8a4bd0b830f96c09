//! Boundary conditions of the ICE solver, one per domain face.
//!
//! They are imposed through the ghost cells that the grid's halo exchange
//! fills (`brisance_grid`), so every step sees them the same way:
//! - [`IceBoundary::Symmetry`]: mirror (scalars copied, the normal velocity
//!   negated); the face velocity of eq 19 is set to zero on the face.
//! - [`IceBoundary::Outflow`]: zero gradient (ghosts copy the boundary
//!   cell), so waves leave with little reflection, and matter may only
//!   leave: the face velocity u* of eq 19 on the face is kept from
//!   pointing into the domain ([`outflow_face_velocity`]). Zero gradient
//!   alone copies the boundary cell's velocity into the ghost, so where
//!   the flow at the face turns inwards it feeds that cell's state back
//!   in (a QM-100 detonation column with outflow ends gained 4.8 % mass
//!   and 26.9 % energy in 12 µs). The rule is the "diode" boundary of the
//!   FLASH code (Fryxell et al. 2000, ApJS 131, 273; FLASH User's Guide
//!   4.x, Grid boundary conditions: zero gradient with the normal velocity
//!   in the guard cells set to zero where it points into the domain),
//!   applied here to u*, which is what carries every ICE flux: advection
//!   (step 12), the volume flux of eq 20 and the face-pressure work of
//!   the energy closure. Where the flow turns inwards the face acts as a
//!   wall for that step (no flux, no work) and the cell sees its pressure
//!   p* on the face.
//! - [`IceBoundary::ZeroGradient`]: zero gradient both ways, the
//!   behaviour `Outflow` had before: where the flow points inwards the
//!   boundary cell's state is fed in. It is the face of a column that
//!   continues beyond the domain, as the far end of the rate stick, whose
//!   explosive moves at −90 m/s towards the wall and so enters through
//!   that face (a closed far end would pull the explosive into tension;
//!   with `Outflow` there the R = 8 mm quarter stick stopped at 26 µs with
//!   a negative air volume fraction five cells from the end).
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
    /// Zero-gradient outflow that lets nothing in (the face velocity is
    /// never directed into the domain).
    Outflow,
    /// Zero gradient in both directions: the boundary cell's state flows
    /// in where the flow points inwards (a column continuing beyond the
    /// face).
    ZeroGradient,
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

/// The face velocity u* (eq 19, after the face exchange) on an outflow
/// face whose outward normal is `outward` (−1 on a low face, +1 on a high
/// face): u* where it points out of the domain or is zero, else 0, so no
/// volume, mass, momentum or energy is carried in (the "diode" outflow of
/// FLASH, see the module notes).
pub fn outflow_face_velocity(u_star: f64, outward: f64) -> f64 {
    if u_star * outward < 0.0 {
        0.0
    } else {
        u_star
    }
}

/// The share of the boundary cell's √(p v) (about its sound speed over
/// √γ, p the pressure and v the specific volume) an inward face velocity
/// must exceed, in a material filling more than [`BLOCKING_FRACTION`] of
/// that cell, for [`holds_back_inflow`] to report it: round-off drift of
/// a gas at rest and the motion of trace materials are not reported.
pub const BLOCKED_SPEED_FRACTION: f64 = 1e-3;

/// The volume fraction above which a material's held-back inflow is
/// reported ([`holds_back_inflow`]).
pub const BLOCKING_FRACTION: f64 = 1e-2;

/// Whether an outflow face of outward normal sign `outward` holds back a
/// flow into the domain when it stops the face velocity `u_star` of a
/// material of volume fraction `theta`, pressure `p` (Pa) and specific
/// volume `v` (m³/kg) in the boundary cell: u* points inwards faster than
/// [`BLOCKED_SPEED_FRACTION`] · √(p v), and θ > [`BLOCKING_FRACTION`]. The
/// run loop warns of such a face once.
pub fn holds_back_inflow(u_star: f64, outward: f64, theta: f64, p: f64, v: f64) -> bool {
    -u_star * outward > BLOCKED_SPEED_FRACTION * (p * v).max(0.0).sqrt()
        && theta > BLOCKING_FRACTION
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_outflow_face_passes_outward_velocities_and_stops_inward_ones() {
        // High face (outward +x): 3 m/s leaves, −3 m/s would enter.
        assert_eq!(outflow_face_velocity(3.0, 1.0), 3.0);
        assert_eq!(outflow_face_velocity(-3.0, 1.0), 0.0);
        // Low face (outward −x): the other way round.
        assert_eq!(outflow_face_velocity(-2.5, -1.0), -2.5);
        assert_eq!(outflow_face_velocity(2.5, -1.0), 0.0);
        assert_eq!(outflow_face_velocity(0.0, 1.0), 0.0);
    }

    #[test]
    fn only_a_real_inflow_is_reported_as_held_back() {
        // Air at 1 bar and 0.8 m³/kg: √(p v) = √80000 ≈ 282.8 m/s, so the
        // threshold is 0.283 m/s.
        let (p, v) = (1.0e5, 0.8);
        assert!(holds_back_inflow(1.0, -1.0, 1.0, p, v));
        assert!(holds_back_inflow(-1.0, 1.0, 1.0, p, v));
        assert!(!holds_back_inflow(0.25, -1.0, 1.0, p, v));
        // Leaving, or a trace material: nothing to report.
        assert!(!holds_back_inflow(-1.0, -1.0, 1.0, p, v));
        assert!(!holds_back_inflow(1.0, -1.0, 1e-6, p, v));
    }

    #[test]
    fn only_walls_have_a_wall_velocity() {
        assert_eq!(IceBoundary::Symmetry.wall_velocity(), Some([0.0; 3]));
        assert_eq!(
            IceBoundary::FixedVelocity([1.0, 2.0, 3.0]).wall_velocity(),
            Some([1.0, 2.0, 3.0])
        );
        assert_eq!(IceBoundary::Outflow.wall_velocity(), None);
        assert_eq!(IceBoundary::ZeroGradient.wall_velocity(), None);
        assert_eq!(IceBoundary::Periodic.wall_velocity(), None);
    }
}
