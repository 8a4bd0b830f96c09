//! Node fields of the MPM background grid on the whole level's node
//! lattice, structure of arrays: lumped mass m_I (seed 001 eq 21), momentum
//! p_I (eq 18), force f_I = f_I^int + f_I^ext (eqs 19, 20, 23), and the
//! velocities and acceleration derived from them.
//!
//! The lattice is global (not per patch): along an active direction d of n
//! cells it holds nodes −g ..= n + g, with g =
//! [`ShapeFunction::required_ghost_nodes`] (0 for the linear function, 1 for
//! GIMP and the B-spline, which reach one node beyond the boundary); along an
//! inactive direction it holds the single node 0. Storage is x fastest, so
//! an x-row of nodes is one contiguous slice — the unit the parallel P2G
//! gather works on.

use crate::ShapeFunction;
use brisance_core::UniformGridGeometry;

/// Shape of the node lattice of a level: node counts and the global index
/// of the first stored node per direction.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct NodeLattice {
    /// Stored nodes per direction.
    pub dims: [usize; 3],
    /// Global index of stored node 0 per direction (−g or 0).
    pub first: [isize; 3],
}

impl NodeLattice {
    /// The lattice that holds every node a particle inside `grid` can touch
    /// with `shape`.
    pub fn new(grid: &UniformGridGeometry, shape: ShapeFunction) -> Self {
        let g = shape.required_ghost_nodes();
        let dims = std::array::from_fn(|d| {
            if grid.cells[d] > 1 {
                grid.cells[d] + 1 + 2 * g
            } else {
                1
            }
        });
        let first = std::array::from_fn(|d| if grid.cells[d] > 1 { -(g as isize) } else { 0 });
        Self { dims, first }
    }

    /// Number of stored nodes.
    pub fn len(&self) -> usize {
        self.dims.iter().product()
    }

    /// Whether the lattice is empty (never, for a valid grid).
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Storage index of global node `node`, or `None` outside the lattice.
    #[inline]
    pub fn index(&self, node: [isize; 3]) -> Option<usize> {
        let mut idx = 0usize;
        for d in (0..3).rev() {
            let l = node[d] - self.first[d];
            if l < 0 || l >= self.dims[d] as isize {
                return None;
            }
            idx = idx * self.dims[d] + l as usize;
        }
        Some(idx)
    }

    /// Global node (i, j, k) of storage index `n`.
    #[inline]
    pub fn node(&self, n: usize) -> [isize; 3] {
        let i = n % self.dims[0];
        let j = (n / self.dims[0]) % self.dims[1];
        let k = n / (self.dims[0] * self.dims[1]);
        [
            i as isize + self.first[0],
            j as isize + self.first[1],
            k as isize + self.first[2],
        ]
    }
}

/// The node fields, one `Vec` per quantity over the whole lattice, reused
/// from step to step (allocated once).
#[derive(Debug, Clone, PartialEq)]
pub struct GridNodes {
    /// The lattice the fields live on.
    pub lattice: NodeLattice,
    /// Lumped mass m_I = Σ_p N_Ip m_p, kg (seed 001 eq 21).
    pub mass: Vec<f64>,
    /// Momentum p_I = Σ_p m_p N_Ip v_p, kg·m/s (seed 001 eq 18).
    pub momentum: Vec<[f64; 3]>,
    /// Force f_I = −Σ_p V_p σ_p ∇N_Ip + Σ_p m_p N_Ip g, N (eqs 19, 20, 23).
    pub force: Vec<[f64; 3]>,
    /// Velocity at the start of the step, v_I^n = p_I/m_I, m/s.
    pub velocity: Vec<[f64; 3]>,
    /// Acceleration a_I = f_I/m_I after the boundary conditions, m/s².
    pub acceleration: Vec<[f64; 3]>,
    /// Velocity at the end of the step, v_I^{n+1} (eq 22 for USL, eq 26 for
    /// MUSL), after the boundary conditions, m/s.
    pub velocity_new: Vec<[f64; 3]>,
}

impl GridNodes {
    /// Zeroed fields on `lattice`.
    pub fn new(lattice: NodeLattice) -> Self {
        let n = lattice.len();
        Self {
            lattice,
            mass: vec![0.0; n],
            momentum: vec![[0.0; 3]; n],
            force: vec![[0.0; 3]; n],
            velocity: vec![[0.0; 3]; n],
            acceleration: vec![[0.0; 3]; n],
            velocity_new: vec![[0.0; 3]; n],
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lattice_index_and_node_invert_with_ghost_layers() {
        let grid = UniformGridGeometry {
            origin: [0.0; 3],
            spacing: [1.0; 3],
            cells: [4, 3, 1],
        };
        let lat = NodeLattice::new(&grid, ShapeFunction::QuadraticBSpline);
        assert_eq!(lat.dims, [7, 6, 1]);
        assert_eq!(lat.first, [-1, -1, 0]);
        for n in 0..lat.len() {
            assert_eq!(lat.index(lat.node(n)), Some(n));
        }
        assert_eq!(lat.index([-1, -1, 0]), Some(0));
        assert_eq!(lat.index([-2, 0, 0]), None);
        assert_eq!(lat.index([0, 0, 1]), None);
        let lin = NodeLattice::new(&grid, ShapeFunction::Linear);
        assert_eq!(lin.dims, [5, 4, 1]);
        assert_eq!(lin.index([4, 3, 0]), Some(lin.len() - 1));
    }
}
