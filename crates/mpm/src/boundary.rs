//! Boundary conditions of the MPM background grid, one per domain face.
//!
//! Faces are ordered x−, x+, y−, y+, z−, z+. A condition acts on the nodes
//! on the face plane and on the ghost nodes beyond it (global node index
//! ≤ 0 on a low face, ≥ n on a high face of n cells), after the nodal
//! velocity and acceleration are formed and before they are interpolated
//! back to the particles (a held velocity component is zero; the held
//! component of the acceleration is the change of velocity the condition
//! makes over the step, see [`crate::grid_nodes::GridNodes::update`], so
//! that the particles' velocity update feels the wall):
//!
//! - [`GridBoundary::Fixed`]: every velocity component is held at zero (a
//!   clamped, no-slip wall);
//! - [`GridBoundary::Symmetry`]: the normal component is held at zero, the
//!   tangential ones are free (a roller, or a plane of symmetry);
//! - [`GridBoundary::Free`]: nothing is imposed (traction-free);
//! - [`GridBoundary::Outflow`]: nothing is imposed on the grid, and a
//!   particle that crosses the face is removed from the set, its mass,
//!   momentum and energy booked as outflow (see [`crate::solver`]). Alone
//!   it lets nothing in; with a reservoir beyond it
//!   ([`crate::MpmOptions::reservoirs`], [`crate::inflow`]) matter enters
//!   through it.
//!
//! A particle that crosses a `Symmetry` or `Fixed` face by at most
//! [`MIRROR_DEPTH`] cells is put back at its mirror image, its normal
//! velocity reversed (a particle within a whisker of a wall can cross it
//! in one step; see `MpmSolver`'s `handle_leaving_particles`); one that
//! crosses deeper, or crosses a `Free` face, stops the run with an error.
//! Faces of inactive directions (one cell) impose nothing: the single node
//! layer there is the whole thickness of a 1D or 2D model.

use crate::grid_nodes::NodeLattice;
use serde::{Deserialize, Serialize};

/// The farthest, in cells of the face's axis, a particle may cross a
/// `Symmetry` or `Fixed` face in one step and be mirrored back; deeper
/// crossings stop the run.
pub const MIRROR_DEPTH: f64 = 0.5;

/// The condition on one face of the domain.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default, Serialize, Deserialize)]
pub enum GridBoundary {
    /// All velocity components zero.
    Fixed,
    /// Normal velocity component zero (roller / symmetry plane).
    Symmetry,
    /// Traction-free; particles may not leave through it.
    #[default]
    Free,
    /// Traction-free; particles that cross it are removed and booked as
    /// outflow.
    Outflow,
}

/// Face names in the order of the `[GridBoundary; 6]` arrays.
pub const FACE_NAMES: [&str; 6] = ["x-", "x+", "y-", "y+", "z-", "z+"];

/// Zeroes the held components of the node vectors `fields` (velocities) on
/// `lattice` of a grid with `cells` cells.
pub fn apply_grid_boundaries(
    boundaries: &[GridBoundary; 6],
    lattice: &NodeLattice,
    cells: [usize; 3],
    fields: &mut [&mut [[f64; 3]]],
) {
    for axis in 0..3 {
        if cells[axis] <= 1 {
            continue;
        }
        for side in 0..2 {
            let bc = boundaries[2 * axis + side];
            let components: &[usize] = match bc {
                GridBoundary::Fixed => &[0, 1, 2],
                GridBoundary::Symmetry => std::slice::from_ref(&[0usize, 1, 2][axis]),
                GridBoundary::Free | GridBoundary::Outflow => continue,
            };
            let n = cells[axis] as isize;
            for_each_face_node(lattice, axis, side, n, |idx| {
                for field in fields.iter_mut() {
                    for &c in components {
                        field[idx][c] = 0.0;
                    }
                }
            });
        }
    }
}

/// Calls `f` with the storage index of every node on or beyond face
/// (`axis`, `side`) of an axis of `n` cells.
fn for_each_face_node(
    lattice: &NodeLattice,
    axis: usize,
    side: usize,
    n: isize,
    mut f: impl FnMut(usize),
) {
    for idx in 0..lattice.len() {
        let i = lattice.node(idx)[axis];
        let on_face = if side == 0 { i <= 0 } else { i >= n };
        if on_face {
            f(idx);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ShapeFunction;
    use brisance_core::UniformGridGeometry;

    #[test]
    fn symmetry_zeroes_only_the_normal_component_and_fixed_zeroes_all() {
        let grid = UniformGridGeometry {
            origin: [0.0; 3],
            spacing: [1.0; 3],
            cells: [2, 2, 1],
        };
        let lat = NodeLattice::new(&grid, ShapeFunction::Linear);
        let mut v = vec![[1.0, 2.0, 3.0]; lat.len()];
        let mut bcs = [GridBoundary::Free; 6];
        bcs[0] = GridBoundary::Symmetry;
        bcs[3] = GridBoundary::Fixed;
        apply_grid_boundaries(&bcs, &lat, grid.cells, &mut [&mut v]);
        let at = |n: [isize; 3]| v[lat.index(n).unwrap()];
        assert_eq!(at([0, 0, 0]), [0.0, 2.0, 3.0]);
        assert_eq!(at([0, 2, 0]), [0.0; 3]);
        assert_eq!(at([1, 1, 0]), [1.0, 2.0, 3.0]);
        assert_eq!(at([2, 0, 0]), [1.0, 2.0, 3.0]);
        assert_eq!(at([1, 2, 0]), [0.0; 3]);
    }
}
