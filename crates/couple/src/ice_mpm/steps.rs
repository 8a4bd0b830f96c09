//! The grid transfers of the ICE–MPM step (seed 000 §3.3), each a function
//! of its arrays alone.
//!
//! Nodes are the cell corners of the shared grid: node (i, j, k) of global
//! index i ∈ 0..=n along an active axis of n cells; along an inactive axis
//! (a 1D or 2D model) the single node 0 is the whole thickness. Cell c's
//! corners are the nodes c and c + 1 along each active axis.
//!
//! **Corner weights (eq 18).** w_ic = ½ per active axis (⅛ in 3D), doubled
//! along an axis where the node lies on a face of the domain. The seed
//! doubles them on symmetry planes "to achieve the desired effect"; the
//! effect is that a node on a face collects particle mass from one side
//! only, so a cell full of solid at a face has the mass of a full cell.
//! That holds on every face a particle cannot cross, so the doubling is
//! applied on all six (docs/physics/couple/ice_mpm.md).
//!
//! **Step 13 is the adjoint of eq 18.** The velocity change of node I is
//! Δv_I = Σ_c w_Ic Δu_c with the same weights, so that the momentum the
//! nodes receive, Σ_I m_I Δv_I = Σ_c Δu_c Σ_I w_Ic m_I = Σ_c M_c Δu_c, is
//! exactly the cell-centred momentum change of the solid.

use brisance_core::UniformGridGeometry;
use brisance_mpm::{MaterialId, NodeLattice};
use rayon::prelude::*;

/// The corners of cell `c` (global node indices) with their weights w_ic
/// (eq 18, doubled on domain faces); `count` of the 8 slots are used.
#[derive(Debug, Clone, Copy)]
pub struct Corners {
    /// Global node index of each corner.
    pub node: [[isize; 3]; 8],
    /// w_ic.
    pub weight: [f64; 8],
    /// Number of corners: 2 per active axis.
    pub count: usize,
}

/// Whether axis `d` of `grid` is active (more than one cell).
#[inline]
fn active(grid: &UniformGridGeometry, d: usize) -> bool {
    grid.cells[d] > 1
}

/// The weight factor along axis `d` of global node index `i` for a cell of
/// which it is the `high` corner (else the low one): ½ on an active axis,
/// 1 on a face of the domain, 1 on an inactive axis. Along r of an
/// axisymmetric grid (`rz`) a node's mass is split between its two cells
/// as its tent function's ring-weighted integral is,
/// ∫ N_i 2πr dr over each cell: ½ ∓ Δr/(6 r_i) to the inner (the node is
/// its high corner) and the outer cell (docs/physics/couple/ice_mpm.md).
#[inline]
fn corner_weight(grid: &UniformGridGeometry, rz: bool, d: usize, i: isize, high: bool) -> f64 {
    if !active(grid, d) || i == 0 || i == grid.cells[d] as isize {
        1.0
    } else if rz && d == 0 {
        let r = grid.origin[0] + i as f64 * grid.spacing[0];
        let x = grid.spacing[0] / (6.0 * r);
        if high {
            0.5 - x
        } else {
            0.5 + x
        }
    } else {
        0.5
    }
}

/// The corners of cell `c` and their weights (eq 18).
pub fn corners(grid: &UniformGridGeometry, rz: bool, c: [usize; 3]) -> Corners {
    let mut out = Corners {
        node: [[0; 3]; 8],
        weight: [0.0; 8],
        count: 0,
    };
    let span = |d: usize| if active(grid, d) { 2 } else { 1 };
    for k in 0..span(2) {
        for j in 0..span(1) {
            for i in 0..span(0) {
                let node = [
                    c[0] as isize + i as isize,
                    c[1] as isize + j as isize,
                    c[2] as isize + k as isize,
                ];
                let node = std::array::from_fn(|d| if active(grid, d) { node[d] } else { 0 });
                out.node[out.count] = node;
                let off = [i, j, k];
                out.weight[out.count] = (0..3)
                    .map(|d| corner_weight(grid, rz, d, node[d], off[d] == 1))
                    .product();
                out.count += 1;
            }
        }
    }
    out
}

/// The cell of global linear index `k` (x fastest).
#[inline]
pub fn cell_of(grid: &UniformGridGeometry, k: usize) -> [usize; 3] {
    let n = grid.cells;
    [k % n[0], (k / n[0]) % n[1], k / (n[0] * n[1])]
}

/// The corners of every cell as storage indices of a node lattice, with
/// their weights (eq 18): the table [`corners`] gives cell by cell,
/// without building it (the same nodes, the same order, the same weights —
/// products of ½ and 1, exact in any order; along r of an axisymmetric
/// grid the ring weights of [`corner_weight`]).
#[derive(Debug, Clone, Copy)]
struct CornerWalk {
    grid: UniformGridGeometry,
    rz: bool,
    cells: [usize; 3],
    span: [usize; 3],
    stride: [usize; 3],
    first: [isize; 3],
}

impl CornerWalk {
    fn new(grid: &UniformGridGeometry, rz: bool, lattice: &NodeLattice) -> Self {
        let dims = lattice.dims;
        Self {
            grid: *grid,
            rz,
            cells: grid.cells,
            span: std::array::from_fn(|d| if active(grid, d) { 2 } else { 1 }),
            stride: [1, dims[0], dims[0] * dims[1]],
            first: lattice.first,
        }
    }

    /// Cell `k` (global linear index): the storage index of its first
    /// corner and the weights of its corners along each axis.
    #[inline(always)]
    fn cell(&self, k: usize) -> CellCorners {
        let n = self.cells;
        let c = [k % n[0], (k / n[0]) % n[1], k / (n[0] * n[1])];
        let mut base = 0usize;
        let mut w = [[1.0f64; 2]; 3];
        for d in 0..3 {
            if self.span[d] == 2 {
                // Cell c's corners along d are the nodes c and c + 1; a
                // node on a face of the domain (0 or n) weighs 1, else ½.
                base += (c[d] as isize - self.first[d]) as usize * self.stride[d];
                w[d] = if self.rz && d == 0 {
                    let i = c[0] as isize;
                    [
                        corner_weight(&self.grid, true, 0, i, false),
                        corner_weight(&self.grid, true, 0, i + 1, true),
                    ]
                } else {
                    [
                        if c[d] == 0 { 1.0 } else { 0.5 },
                        if c[d] + 1 == n[d] { 1.0 } else { 0.5 },
                    ]
                };
            } else {
                base += (-self.first[d]) as usize * self.stride[d];
            }
        }
        CellCorners { base, w }
    }

    /// Calls `f(storage index, w_ic)` for each corner of `cell`, in the
    /// order of [`corners`] (x fastest).
    #[inline(always)]
    fn visit(&self, cell: &CellCorners, mut f: impl FnMut(usize, f64)) {
        let w = &cell.w;
        for kk in 0..self.span[2] {
            for jj in 0..self.span[1] {
                for ii in 0..self.span[0] {
                    let idx =
                        cell.base + ii * self.stride[0] + jj * self.stride[1] + kk * self.stride[2];
                    f(idx, w[0][ii] * w[1][jj] * w[2][kk]);
                }
            }
        }
    }
}

/// One cell's corners for [`CornerWalk::visit`].
#[derive(Debug, Clone, Copy)]
struct CellCorners {
    base: usize,
    w: [[f64; 2]; 3],
}

/// Eq 18 at one cell: (M_c, u_c) from the nodal mass and velocity.
#[inline(always)]
fn cell_mass_velocity(
    walk: &CornerWalk,
    cell: &CellCorners,
    node_mass: &[f64],
    node_velocity: &[[f64; 3]],
) -> (f64, [f64; 3]) {
    let (mut mass, mut mom) = (0.0, [0.0; 3]);
    walk.visit(cell, |i, w| {
        let wm = w * node_mass[i];
        mass += wm;
        for d in 0..3 {
            mom[d] += wm * node_velocity[i][d];
        }
    });
    let u = if mass > 0.0 {
        mom.map(|x| x / mass)
    } else {
        [0.0; 3]
    };
    (mass, u)
}

/// The solid's (v_c, T_c) at one cell from the nearest-node sums.
#[inline(always)]
fn cell_state_at(
    walk: &CornerWalk,
    cell: &CellCorners,
    node_sums: &[[f64; 3]],
) -> Option<(f64, f64)> {
    let mut s = [0.0; 3];
    walk.visit(cell, |i, w| {
        for q in 0..3 {
            s[q] += w * node_sums[i][q];
        }
    });
    (s[0] > 0.0).then(|| (s[1] / s[0], s[2] / s[0]))
}

/// Step 1, eq 18: the solid's cell mass M_c = Σ_i w_ic m_i (kg) and
/// mass-weighted velocity u_c = Σ_i w_ic m_i u_i / M_c (m/s; zero where
/// M_c = 0) from the nodal mass and velocity, cells in parallel.
pub fn nodes_to_cells(
    grid: &UniformGridGeometry,
    rz: bool,
    lattice: &NodeLattice,
    node_mass: &[f64],
    node_velocity: &[[f64; 3]],
    cell_mass: &mut [f64],
    cell_velocity: &mut [[f64; 3]],
) {
    let walk = CornerWalk::new(grid, rz, lattice);
    cell_mass
        .par_iter_mut()
        .zip(cell_velocity.par_iter_mut())
        .enumerate()
        .with_min_len(1024)
        .for_each(|(k, (m, u))| {
            (*m, *u) = cell_mass_velocity(&walk, &walk.cell(k), node_mass, node_velocity);
        });
}

/// The nearest-node sums of [`project_to_cells`]: each particle's
/// mass, volume and m·T added to its nearest node, in particle order (so
/// the bits do not depend on the thread count).
fn nearest_node_sums(
    grid: &UniformGridGeometry,
    lattice: &NodeLattice,
    position: &[[f64; 3]],
    mass: &[f64],
    volume: &[f64],
    temperature: &[f64],
    node_sums: &mut Vec<[f64; 3]>,
) {
    node_sums.clear();
    node_sums.resize(lattice.len(), [0.0; 3]);
    for p in 0..position.len() {
        let node: [isize; 3] = std::array::from_fn(|d| {
            if active(grid, d) {
                let s = ((position[p][d] - grid.origin[d]) / grid.spacing[d]).round() as isize;
                s.clamp(0, grid.cells[d] as isize)
            } else {
                0
            }
        });
        if let Some(i) = lattice.index(node) {
            let sums = &mut node_sums[i];
            sums[0] += mass[p];
            sums[1] += volume[p];
            sums[2] += mass[p] * temperature[p];
        }
    }
}

/// The particle data [`project_to_cells`] reads (the start of the step's).
#[derive(Debug, Clone, Copy)]
pub struct ParticleState<'a> {
    /// Positions, m.
    pub position: &'a [[f64; 3]],
    /// Masses, kg.
    pub mass: &'a [f64],
    /// Volumes, m³.
    pub volume: &'a [f64],
    /// Temperatures, K.
    pub temperature: &'a [f64],
    /// Materials (read by [`materials_to_cells`] only).
    pub material: &'a [MaterialId],
}

/// Step 1 in one pass over the cells (each cell's corners visited once):
/// the solid's cell mass and velocity as [`nodes_to_cells`] gives them
/// (same bits), and its specific volume and temperature. For the latter
/// each particle's mass, volume and m·T go to its nearest node (sums in
/// particle order, so the bits do not depend on the thread count), and
/// each cell gathers them with the weights of eq 18: v_c = Σ w V / Σ w m
/// (m³/kg) and T_c = Σ w m T / Σ w m (K). A cell none of whose corners
/// received a particle gets `None` (the caller gives it the trace state).
#[allow(clippy::too_many_arguments)]
pub fn project_to_cells(
    grid: &UniformGridGeometry,
    rz: bool,
    lattice: &NodeLattice,
    node_mass: &[f64],
    node_velocity: &[[f64; 3]],
    particles: ParticleState<'_>,
    node_sums: &mut Vec<[f64; 3]>,
    cell_mass: &mut [f64],
    cell_velocity: &mut [[f64; 3]],
    cell_state: &mut [Option<(f64, f64)>],
) {
    nearest_node_sums(
        grid,
        lattice,
        particles.position,
        particles.mass,
        particles.volume,
        particles.temperature,
        node_sums,
    );
    let walk = CornerWalk::new(grid, rz, lattice);
    let node_sums = &*node_sums;
    (
        cell_mass.par_iter_mut(),
        cell_velocity.par_iter_mut(),
        cell_state.par_iter_mut(),
    )
        .into_par_iter()
        .enumerate()
        .with_min_len(1024)
        .for_each(|(k, (m, u, state))| {
            let cell = walk.cell(k);
            (*m, *u) = cell_mass_velocity(&walk, &cell, node_mass, node_velocity);
            *state = cell_state_at(&walk, &cell, node_sums);
        });
}

/// Step 1 with several particle materials sharing the nodes (one velocity
/// field, Uintah's single-velocity contact): given the cell mass M_c of all
/// particles (eq 18 of the nodal mass), each material s gets the share
/// M_c,s = M_c · Σ_{p∈s} W_pc m_p / Σ_p W_pc m_p, W_pc the share of its
/// mass a particle puts in cell c through linear shape functions and the
/// corner weights of eq 18 ([`particle_cell_weights`]; with linear shape
/// functions Σ_p W_pc m_p is M_c itself), so a solid none of whose
/// particles reaches a cell gets none of it; equal shares only where no
/// particle reaches the cell that way (wider shape functions). Each
/// material's (v_c, T_c) comes from its own particles' nearest-node sums
/// as in [`project_to_cells`]. The shares sum to M_c up to round-off; sums
/// in particle order. `node_sums` holds `materials` sums per node.
#[allow(clippy::too_many_arguments)]
pub fn materials_to_cells(
    grid: &UniformGridGeometry,
    rz: bool,
    lattice: &NodeLattice,
    particles: ParticleState<'_>,
    materials: usize,
    cell_mass: &[f64],
    node_sums: &mut Vec<[f64; 3]>,
    material_mass: &mut [Vec<f64>],
    material_state: &mut [Vec<Option<(f64, f64)>>],
) {
    assert!(material_mass.len() == materials && material_state.len() == materials);
    node_sums.clear();
    node_sums.resize(lattice.len() * materials, [0.0; 3]);
    for m in material_mass.iter_mut() {
        m.fill(0.0);
    }
    for p in 0..particles.position.len() {
        let s = particles.material[p].0 as usize;
        let node: [isize; 3] = std::array::from_fn(|d| {
            if active(grid, d) {
                let x = ((particles.position[p][d] - grid.origin[d]) / grid.spacing[d]).round()
                    as isize;
                x.clamp(0, grid.cells[d] as isize)
            } else {
                0
            }
        });
        if let Some(i) = lattice.index(node) {
            let sums = &mut node_sums[i * materials + s];
            sums[0] += particles.mass[p];
            sums[1] += particles.volume[p];
            sums[2] += particles.mass[p] * particles.temperature[p];
        }
        let m = particles.mass[p];
        let own = &mut material_mass[s];
        particle_cell_weights(grid, rz, particles.position[p], |c, w| own[c] += w * m);
    }
    // Each material's linear-weight mass becomes its share of M_c.
    let cells = cell_mass.len();
    for c in 0..cells {
        let all: f64 = material_mass.iter().map(|m| m[c]).sum();
        for m in material_mass.iter_mut() {
            m[c] = if all > 0.0 {
                cell_mass[c] * (m[c] / all)
            } else {
                cell_mass[c] / materials as f64
            };
        }
    }
    let walk = CornerWalk::new(grid, rz, lattice);
    let node_sums = &*node_sums;
    for (s, state) in material_state.iter_mut().enumerate() {
        state
            .par_iter_mut()
            .enumerate()
            .with_min_len(1024)
            .for_each(|(k, st)| {
                let cell = walk.cell(k);
                let mut own = [0.0; 3];
                walk.visit(&cell, |i, w| {
                    for q in 0..3 {
                        own[q] += w * node_sums[i * materials + s][q];
                    }
                });
                *st = (own[0] > 0.0).then(|| (own[1] / own[0], own[2] / own[0]));
            });
    }
}

/// Step 13: the velocity change of every node, Δv_I = Σ_c w_Ic Δu_c over
/// the cells that have node I as a corner, with the weights of eq 18 (its
/// adjoint: momentum-conserving). Nodes outside the domain's corners get
/// zero. Nodes in parallel.
pub fn cells_to_nodes(
    grid: &UniformGridGeometry,
    rz: bool,
    lattice: &NodeLattice,
    cell_change: &[[f64; 3]],
    node_change: &mut [[f64; 3]],
) {
    adjoint_of_eq18(grid, rz, lattice, node_change, |dv, w, c| {
        for d in 0..3 {
            dv[d] += w * cell_change[c][d];
        }
    });
}

/// Step 14's temperature change through the nodes (Uintah's
/// `interpolateCCToNC` of dT/dt before the particles gather it): the
/// scalar form of [`cells_to_nodes`], ΔT_I = Σ_c w_Ic ΔT_c, so that
/// Σ_I m_I ΔT_I = Σ_c M_c ΔT_c with M_c the cell mass of eq 18 (the heat
/// the cells' exchange gave the solid reaches its nodes whole).
pub fn cell_values_to_nodes(
    grid: &UniformGridGeometry,
    rz: bool,
    lattice: &NodeLattice,
    cell_value: &[f64],
    node_value: &mut [f64],
) {
    adjoint_of_eq18(grid, rz, lattice, node_value, |v, w, c| {
        *v += w * cell_value[c];
    });
}

/// Each node's sum `add(value, w_Ic, c)` over the cells c that have it as a
/// corner, with the weights of eq 18, from a zero `T::default()`; nodes
/// outside the domain's corners keep zero. Nodes in parallel, cells in a
/// fixed order.
fn adjoint_of_eq18<T: Default + Send>(
    grid: &UniformGridGeometry,
    rz: bool,
    lattice: &NodeLattice,
    node_value: &mut [T],
    add: impl Fn(&mut T, f64, usize) + Sync,
) {
    node_value.par_iter_mut().enumerate().for_each(|(idx, dv)| {
        let node = lattice.node(idx);
        *dv = T::default();
        let mut range = [[0isize; 2]; 3];
        for d in 0..3 {
            if active(grid, d) {
                let n = grid.cells[d] as isize;
                if node[d] < 0 || node[d] > n {
                    return;
                }
                range[d] = [(node[d] - 1).max(0), node[d].min(n - 1)];
            }
        }
        let w: f64 = (1..3)
            .map(|d| corner_weight(grid, rz, d, node[d], false))
            .product();
        for k in range[2][0]..=range[2][1] {
            for j in range[1][0]..=range[1][1] {
                for i in range[0][0]..=range[0][1] {
                    let c = grid.linear_index([i as usize, j as usize, k as usize]);
                    // Along x the node is the high corner of cell
                    // node − 1 and the low corner of cell node.
                    let w = w * corner_weight(grid, rz, 0, node[0], i < node[0]);
                    add(dv, w, c);
                }
            }
        }
    });
}

/// The cells a particle at `x` reaches through the linear (tent) shape
/// functions of its cell's corner nodes and the corner weights of eq 18:
/// W_pc = Σ_i w_ic N_i(x), up to three cells per active axis, weights
/// summing to 1 — the share of the particle's mass step 1 puts in cell c
/// with linear shape functions. Calls `f(cell index, W_pc)` for each cell
/// with a positive weight, x fastest.
pub fn particle_cell_weights(
    grid: &UniformGridGeometry,
    rz: bool,
    x: [f64; 3],
    mut f: impl FnMut(usize, f64),
) {
    // Per axis: (first cell, weights of cells first, first + 1, first + 2).
    let mut first = [0usize; 3];
    let mut w = [[0.0f64; 3]; 3];
    let mut span = [1usize; 3];
    for d in 0..3 {
        let n = grid.cells[d];
        if n <= 1 {
            w[d][0] = 1.0;
            continue;
        }
        let s = ((x[d] - grid.origin[d]) / grid.spacing[d]).clamp(0.0, n as f64);
        let i0 = (s.floor() as usize).min(n - 1);
        let t = s - i0 as f64;
        // Node i0 (weight 1 − t) and node i0 + 1 (weight t); node i gives
        // cells i − 1 and i half each, a node on a face its one cell all.
        let node = |i: usize| -> [(usize, f64); 2] {
            if i == 0 {
                [(0, 1.0), (0, 0.0)]
            } else if i == n {
                [(n - 1, 1.0), (n - 1, 0.0)]
            } else {
                let ii = i as isize;
                [
                    (i - 1, corner_weight(grid, rz, d, ii, true)),
                    (i, corner_weight(grid, rz, d, ii, false)),
                ]
            }
        };
        let lo = i0.saturating_sub(1);
        first[d] = lo;
        span[d] = 3;
        for (i, weight) in [(i0, 1.0 - t), (i0 + 1, t)] {
            for (c, wc) in node(i) {
                w[d][c - lo] += weight * wc;
            }
        }
    }
    for k in 0..span[2] {
        for j in 0..span[1] {
            for i in 0..span[0] {
                let weight = w[0][i] * w[1][j] * w[2][k];
                if weight > 0.0 {
                    f(
                        grid.linear_index([first[0] + i, first[1] + j, first[2] + k]),
                        weight,
                    );
                }
            }
        }
    }
}

/// A cell-centred field at point `x` by trilinear interpolation between
/// cell centres, held constant beyond the outermost centres (the
/// zero-gradient extension): the mixture pressure at a particle.
pub fn interpolate_cell_field(grid: &UniformGridGeometry, field: &[f64], x: [f64; 3]) -> f64 {
    let mut lo = [0usize; 3];
    let mut frac = [0.0; 3];
    for d in 0..3 {
        let n = grid.cells[d];
        if n <= 1 {
            continue;
        }
        let s = ((x[d] - grid.origin[d]) / grid.spacing[d] - 0.5).clamp(0.0, (n - 1) as f64);
        let i = (s.floor() as usize).min(n - 2);
        lo[d] = i;
        frac[d] = s - i as f64;
    }
    let mut value = 0.0;
    for k in 0..2usize {
        for j in 0..2usize {
            for i in 0..2usize {
                let off = [i, j, k];
                let mut w = 1.0;
                let mut c = [0usize; 3];
                for d in 0..3 {
                    if grid.cells[d] <= 1 {
                        if off[d] == 1 {
                            w = 0.0;
                        }
                        continue;
                    }
                    c[d] = lo[d] + off[d];
                    w *= if off[d] == 1 { frac[d] } else { 1.0 - frac[d] };
                }
                if w != 0.0 {
                    value += w * field[grid.linear_index(c)];
                }
            }
        }
    }
    value
}

/// The value of a cell-centred field in the cell containing `x` (the
/// nearest cell for a point outside the grid).
pub fn cell_value_at(grid: &UniformGridGeometry, field: &[f64], x: [f64; 3]) -> f64 {
    let c: [usize; 3] = std::array::from_fn(|d| {
        let s = ((x[d] - grid.origin[d]) / grid.spacing[d]).floor();
        (s.max(0.0) as usize).min(grid.cells[d] - 1)
    });
    field[grid.linear_index(c)]
}

#[cfg(test)]
mod tests {
    use super::*;
    use brisance_mpm::ShapeFunction;
    use proptest::prelude::*;

    fn grid(cells: [usize; 3]) -> UniformGridGeometry {
        UniformGridGeometry {
            origin: [0.0; 3],
            spacing: [0.5, 0.25, 1.0],
            cells,
        }
    }

    #[test]
    fn interior_weights_are_an_eighth_and_face_nodes_count_double() {
        let g = grid([4, 4, 4]);
        let cs = corners(&g, false, [1, 1, 1]);
        assert_eq!(cs.count, 8);
        assert!(cs.weight.iter().all(|&w| w == 0.125));
        let cs = corners(&g, false, [0, 1, 1]);
        // Four corners on the x = 0 face.
        let on_face: Vec<f64> = (0..8)
            .filter(|&s| cs.node[s][0] == 0)
            .map(|s| cs.weight[s])
            .collect();
        assert_eq!(on_face, vec![0.25; 4]);
        // A 2D grid: 4 corners of weight 1/4 inside.
        let g2 = grid([4, 4, 1]);
        let cs = corners(&g2, false, [1, 2, 0]);
        assert_eq!(cs.count, 4);
        assert!(cs.weight[..4].iter().all(|&w| w == 0.25));
        assert!(cs.node[..4].iter().all(|n| n[2] == 0));
    }

    /// A uniformly filled block whose nodes carry the linear-shape masses
    /// (full inside, half on a face, a quarter on an edge): eq 18 with the
    /// face doubling gives every cell the full cell mass.
    #[test]
    fn a_full_block_gives_full_cells_up_to_the_faces() {
        let g = grid([3, 2, 1]);
        let lat = NodeLattice::new(&g, ShapeFunction::Linear);
        let m_cell = 2.0;
        let mut mass = vec![0.0; lat.len()];
        for (idx, m) in mass.iter_mut().enumerate() {
            let n = lat.node(idx);
            let f = |d: usize| {
                if n[d] == 0 || n[d] == g.cells[d] as isize {
                    0.5
                } else {
                    1.0
                }
            };
            *m = m_cell * f(0) * f(1);
        }
        let vel = vec![[1.0, -2.0, 0.5]; lat.len()];
        let mut cm = vec![0.0; g.cell_count()];
        let mut cu = vec![[0.0; 3]; g.cell_count()];
        nodes_to_cells(&g, false, &lat, &mass, &vel, &mut cm, &mut cu);
        for k in 0..g.cell_count() {
            assert!((cm[k] - m_cell).abs() < 1e-14, "cell {k}: {}", cm[k]);
            assert_eq!(cu[k], [1.0, -2.0, 0.5]);
        }
    }

    /// Step 13 conserves momentum: Σ_I m_I Δv_I = Σ_c M_c Δu_c with M_c
    /// from the same nodes by eq 18, for random masses and changes.
    #[test]
    fn cell_changes_reach_the_nodes_with_their_momentum() {
        proptest!(|(seed in 0u64..1000)| {
            let g = grid([3, 4, 2]);
            let lat = NodeLattice::new(&g, ShapeFunction::Linear);
            let mut rnd = lcg(seed);
            let (mass, cm) = random_masses(&g, false, &lat, &mut rnd);
            let du: Vec<[f64; 3]> = (0..g.cell_count()).map(|_| [rnd() - 0.5, rnd(), -rnd()]).collect();
            let mut dv = vec![[0.0; 3]; lat.len()];
            cells_to_nodes(&g, false, &lat, &du, &mut dv);
            for d in 0..3 {
                let cells: f64 = (0..g.cell_count()).map(|k| cm[k] * du[k][d]).sum();
                let nodes: f64 = (0..lat.len()).map(|i| mass[i] * dv[i][d]).sum();
                prop_assert!((cells - nodes).abs() <= 1e-12 * cells.abs().max(1.0));
            }
        });
    }

    /// The temperature change through the nodes: Σ_I m_I ΔT_I =
    /// Σ_c M_c ΔT_c for any nodal masses (the heat the cells' solid took
    /// reaches its nodes whole), planar and on rings, and each node's value
    /// is the bits of the vector form's component.
    #[test]
    fn cell_temperature_changes_reach_the_nodes_with_their_heat() {
        proptest!(|(seed in 0u64..1000, rz in proptest::bool::ANY)| {
            let g = grid([3, 4, 2]);
            let lat = NodeLattice::new(&g, ShapeFunction::Linear);
            let mut rnd = lcg(seed);
            let (mass, cm) = random_masses(&g, rz, &lat, &mut rnd);
            let dt: Vec<f64> = (0..g.cell_count()).map(|_| 100.0 * (rnd() - 0.5)).collect();
            let mut node_dt = vec![f64::NAN; lat.len()];
            cell_values_to_nodes(&g, rz, &lat, &dt, &mut node_dt);
            let cells: f64 = (0..g.cell_count()).map(|k| cm[k] * dt[k]).sum();
            let nodes: f64 = (0..lat.len()).map(|i| mass[i] * node_dt[i]).sum();
            prop_assert!((cells - nodes).abs() <= 1e-12 * cells.abs().max(1.0));
            let as_vector: Vec<[f64; 3]> = dt.iter().map(|&v| [v, 0.0, 0.0]).collect();
            let mut dv = vec![[0.0; 3]; lat.len()];
            cells_to_nodes(&g, rz, &lat, &as_vector, &mut dv);
            for (a, b) in node_dt.iter().zip(&dv) {
                prop_assert_eq!(a.to_bits(), b[0].to_bits());
            }
        });
    }

    /// Ring (r, z) grid: nodes carrying the tent integrals of a uniform
    /// density, m_i = ρ ∫ N_i 2πr dr Δz (2πρΔr²Δz/6 on the axis, 2πρ r_i
    /// Δr Δz inside, πρ Δr (R − Δr/3) Δz at r = R), give every ring its
    /// mass ρπ(r₊² − r₋²)Δz, the axis ring included, and the uniform
    /// velocity.
    #[test]
    fn rings_of_uniform_density_get_their_ring_mass() {
        use std::f64::consts::PI;
        for origin in [0.0, 0.75] {
            let g = UniformGridGeometry {
                origin: [origin, 0.0, 0.0],
                spacing: [0.5, 0.25, 1.0],
                cells: [5, 3, 1],
            };
            let lat = NodeLattice::new(&g, ShapeFunction::Linear);
            let (dr, dz, rho) = (0.5, 0.25, 3.0);
            let r_max = origin + 5.0 * dr;
            let mut mass = vec![0.0; lat.len()];
            for (idx, m) in mass.iter_mut().enumerate() {
                let n = lat.node(idx);
                if n[0] < 0 || n[0] > 5 || n[1] < 0 || n[1] > 3 {
                    continue;
                }
                let r = origin + n[0] as f64 * dr;
                // ∫ N_i r dr over the part of the tent inside [origin, R].
                let radial = if n[0] == 0 {
                    dr * (r / 2.0 + dr / 6.0)
                } else if n[0] == 5 {
                    dr * (r_max / 2.0 - dr / 6.0)
                } else {
                    r * dr
                };
                let axial = if n[1] == 0 || n[1] == 3 { 0.5 } else { 1.0 };
                *m = rho * 2.0 * PI * radial * axial * dz;
            }
            let vel = vec![[1.0, -2.0, 0.0]; lat.len()];
            let mut cm = vec![0.0; g.cell_count()];
            let mut cu = vec![[0.0; 3]; g.cell_count()];
            nodes_to_cells(&g, true, &lat, &mass, &vel, &mut cm, &mut cu);
            for k in 0..g.cell_count() {
                let i = k % 5;
                let r_lo = origin + i as f64 * dr;
                let want = rho * PI * ((r_lo + dr).powi(2) - r_lo * r_lo) * dz;
                assert!(
                    (cm[k] / want - 1.0).abs() < 1e-14,
                    "{origin} cell {k}: {} vs {want}",
                    cm[k]
                );
                for d in 0..3 {
                    assert!((cu[k][d] - [1.0, -2.0, 0.0][d]).abs() < 1e-14);
                }
            }
        }
    }

    /// On rings too, step 13 hands the nodes the cells' momentum and a
    /// uniform change whole; a particle's cell weights sum to 1.
    #[test]
    fn ring_weights_keep_momentum_and_a_uniform_change() {
        let g = UniformGridGeometry {
            origin: [0.0; 3],
            spacing: [0.5, 0.25, 1.0],
            cells: [6, 4, 1],
        };
        let lat = NodeLattice::new(&g, ShapeFunction::Linear);
        let mass: Vec<f64> = (0..lat.len()).map(|i| 1.0 + (i % 7) as f64).collect();
        let vel = vec![[0.0; 3]; lat.len()];
        let mut cm = vec![0.0; g.cell_count()];
        let mut cu = vec![[0.0; 3]; g.cell_count()];
        nodes_to_cells(&g, true, &lat, &mass, &vel, &mut cm, &mut cu);
        let du: Vec<[f64; 3]> = (0..g.cell_count())
            .map(|k| [(k % 5) as f64 - 2.0, 0.5 * (k % 3) as f64, 0.0])
            .collect();
        let mut dv = vec![[0.0; 3]; lat.len()];
        cells_to_nodes(&g, true, &lat, &du, &mut dv);
        for d in 0..2 {
            let cells: f64 = (0..g.cell_count()).map(|k| cm[k] * du[k][d]).sum();
            let nodes: f64 = (0..lat.len()).map(|i| mass[i] * dv[i][d]).sum();
            assert!(
                (cells - nodes).abs() <= 1e-12 * cells.abs().max(1.0),
                "{cells} {nodes}"
            );
        }
        let uniform = vec![[0.5, -1.0, 0.0]; g.cell_count()];
        cells_to_nodes(&g, true, &lat, &uniform, &mut dv);
        for (idx, v) in dv.iter().enumerate() {
            let n = lat.node(idx);
            if (0..=6).contains(&n[0]) && (0..=4).contains(&n[1]) {
                assert!(
                    (v[0] - 0.5).abs() < 1e-14 && (v[1] + 1.0).abs() < 1e-14,
                    "{n:?} {v:?}"
                );
            }
        }
        for x in [
            [0.1, 0.3, 0.0],
            [0.5, 0.6, 0.0],
            [1.37, 0.01, 0.0],
            [2.99, 0.99, 0.0],
        ] {
            let mut sum = 0.0;
            particle_cell_weights(&g, true, x, |_, w| sum += w);
            assert!((sum - 1.0).abs() < 1e-14, "{x:?}: {sum}");
        }
    }

    /// A uniform cell change reaches every node whole, on faces and edges.
    #[test]
    fn a_uniform_change_is_reproduced_at_every_node() {
        for cells in [[3, 4, 2], [5, 3, 1], [6, 1, 1]] {
            let g = grid(cells);
            let lat = NodeLattice::new(&g, ShapeFunction::Linear);
            let du = vec![[0.5, -1.0, 2.0]; g.cell_count()];
            let mut dv = vec![[0.0; 3]; lat.len()];
            cells_to_nodes(&g, false, &lat, &du, &mut dv);
            for v in dv {
                for d in 0..3 {
                    assert!((v[d] - du[0][d]).abs() < 1e-14, "{cells:?}: {v:?}");
                }
            }
        }
    }

    #[test]
    fn interpolation_reproduces_linear_fields_inside_and_holds_outside() {
        let g = grid([4, 3, 2]);
        let f = |x: [f64; 3]| 2.0 + 3.0 * x[0] - x[1] + 0.5 * x[2];
        let field: Vec<f64> = (0..g.cell_count())
            .map(|k| f(g.cell_centre(cell_of(&g, k))))
            .collect();
        for x in [[0.7, 0.3, 0.9], [1.5, 0.55, 1.2], [0.25, 0.125, 0.5]] {
            let v = interpolate_cell_field(&g, &field, x);
            assert!((v - f(x)).abs() < 1e-12, "{x:?}: {v} vs {}", f(x));
        }
        // Beyond the last centre in x (x > 1.75) the value is held.
        let v = interpolate_cell_field(&g, &field, [1.95, 0.3, 0.9]);
        assert!((v - f([1.75, 0.3, 0.9])).abs() < 1e-12);
        assert_eq!(
            cell_value_at(&g, &field, [1.9, 0.7, 1.5]),
            field[g.linear_index([3, 2, 1])]
        );
    }

    /// Uniform numbers in [0, 1) from a fixed LCG started at `seed`.
    fn lcg(seed: u64) -> impl FnMut() -> f64 {
        let mut x = seed.wrapping_mul(6364136223846793005).wrapping_add(1);
        move || {
            x = x
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            ((x >> 11) as f64) / ((1u64 << 53) as f64)
        }
    }

    /// Random nodal masses from `rnd` and the cell masses eq 18 makes of
    /// them (planar or rings).
    fn random_masses(
        g: &UniformGridGeometry,
        rz: bool,
        lat: &NodeLattice,
        rnd: &mut impl FnMut() -> f64,
    ) -> (Vec<f64>, Vec<f64>) {
        let mass: Vec<f64> = (0..lat.len()).map(|_| rnd()).collect();
        let vel = vec![[0.0; 3]; lat.len()];
        let mut cm = vec![0.0; g.cell_count()];
        let mut cu = vec![[0.0; 3]; g.cell_count()];
        nodes_to_cells(g, rz, lat, &mass, &vel, &mut cm, &mut cu);
        (mass, cm)
    }

    /// Random nodal fields and particles on `g` (a fixed LCG from `seed`).
    #[allow(clippy::type_complexity)]
    fn random_case(
        g: &UniformGridGeometry,
        lat: &NodeLattice,
        seed: u64,
    ) -> (
        Vec<f64>,
        Vec<[f64; 3]>,
        Vec<[f64; 3]>,
        Vec<f64>,
        Vec<f64>,
        Vec<f64>,
    ) {
        let mut rnd = lcg(seed);
        // Some nodes empty, so that some cells have no mass.
        let mass: Vec<f64> = (0..lat.len())
            .map(|_| if rnd() < 0.3 { 0.0 } else { rnd() })
            .collect();
        let vel: Vec<[f64; 3]> = (0..lat.len())
            .map(|_| [rnd() - 0.5, rnd(), -rnd()])
            .collect();
        let np = 3 * g.cell_count();
        let upper: [f64; 3] = std::array::from_fn(|d| g.cells[d] as f64 * g.spacing[d]);
        let pos: Vec<[f64; 3]> = (0..np)
            .map(|_| std::array::from_fn(|d| 0.6 * upper[d] * rnd()))
            .collect();
        let pm: Vec<f64> = (0..np).map(|_| 0.5 + rnd()).collect();
        let pv: Vec<f64> = (0..np).map(|_| 0.1 + rnd()).collect();
        let pt: Vec<f64> = (0..np).map(|_| 300.0 + 100.0 * rnd()).collect();
        (mass, vel, pos, pm, pv, pt)
    }

    /// The cell passes visit the corners of [`corners`] in its order with
    /// its weights: the same bits as eq 18 summed from that table, on 3D,
    /// 2D and 1D grids, for the nodal pass alone and the fused one.
    #[test]
    fn the_cell_passes_sum_eq_18_over_the_corner_table_bit_for_bit() {
        for cells in [[5, 4, 3], [6, 3, 1], [7, 1, 1]] {
            let g = grid(cells);
            let lat = NodeLattice::new(&g, ShapeFunction::Linear);
            let (mass, vel, pos, pm, pv, pt) = random_case(&g, &lat, 7);
            let nc = g.cell_count();
            let (mut cm, mut cu) = (vec![0.0; nc], vec![[0.0; 3]; nc]);
            nodes_to_cells(&g, false, &lat, &mass, &vel, &mut cm, &mut cu);
            let (mut fm, mut fu, mut state) = (vec![0.0; nc], vec![[0.0; 3]; nc], vec![None; nc]);
            let mut sums = Vec::new();
            project_to_cells(
                &g,
                false,
                &lat,
                &mass,
                &vel,
                ParticleState {
                    position: &pos,
                    mass: &pm,
                    volume: &pv,
                    temperature: &pt,
                    material: &[],
                },
                &mut sums,
                &mut fm,
                &mut fu,
                &mut state,
            );
            for k in 0..nc {
                let cs = corners(&g, false, cell_of(&g, k));
                let (mut m, mut mom, mut s) = (0.0, [0.0; 3], [0.0; 3]);
                for c in 0..cs.count {
                    let i = lat.index(cs.node[c]).unwrap();
                    let wm = cs.weight[c] * mass[i];
                    m += wm;
                    for d in 0..3 {
                        mom[d] += wm * vel[i][d];
                        s[d] += cs.weight[c] * sums[i][d];
                    }
                }
                let u = if m > 0.0 {
                    mom.map(|x| x / m)
                } else {
                    [0.0; 3]
                };
                assert_eq!(cm[k].to_bits(), m.to_bits(), "{cells:?} cell {k}");
                assert_eq!(cu[k].map(f64::to_bits), u.map(f64::to_bits));
                let st = (s[0] > 0.0).then(|| (s[1] / s[0], s[2] / s[0]));
                assert_eq!(state[k], st, "{cells:?} cell {k}");
            }
            assert!(state.iter().any(|s| s.is_none()) && state.iter().any(|s| s.is_some()));
            assert_eq!(
                fm.iter().map(|x| x.to_bits()).collect::<Vec<_>>(),
                cm.iter().map(|x| x.to_bits()).collect::<Vec<_>>()
            );
            assert_eq!(fu, cu);
        }
    }

    /// Step 1 and step 13 give the same bits on 1 and 2 threads.
    #[test]
    fn the_transfers_give_the_same_bits_on_one_and_two_threads() {
        let g = grid([24, 20, 9]);
        let lat = NodeLattice::new(&g, ShapeFunction::Linear);
        let (mass, vel, pos, pm, pv, pt) = random_case(&g, &lat, 11);
        let run = |threads: usize| {
            crate::ice_mpm::in_pool(threads, || {
                let nc = g.cell_count();
                let (mut m, mut u, mut st) = (vec![0.0; nc], vec![[0.0; 3]; nc], vec![None; nc]);
                let mut sums = Vec::new();
                project_to_cells(
                    &g,
                    false,
                    &lat,
                    &mass,
                    &vel,
                    ParticleState {
                        position: &pos,
                        mass: &pm,
                        volume: &pv,
                        temperature: &pt,
                        material: &[],
                    },
                    &mut sums,
                    &mut m,
                    &mut u,
                    &mut st,
                );
                let mut dv = vec![[0.0; 3]; lat.len()];
                cells_to_nodes(&g, false, &lat, &u, &mut dv);
                let bits = |v: &[[f64; 3]]| -> Vec<[u64; 3]> {
                    v.iter().map(|x| x.map(f64::to_bits)).collect()
                };
                (
                    m.iter().map(|x| x.to_bits()).collect::<Vec<_>>(),
                    bits(&u),
                    st,
                    bits(&dv),
                )
            })
        };
        assert_eq!(run(1), run(2));
    }

    #[test]
    fn nearest_node_state_gives_specific_volume_and_temperature() {
        let g = grid([2, 2, 1]);
        let lat = NodeLattice::new(&g, ShapeFunction::Linear);
        // Two particles near node (1, 1): m 1 and 3 kg, V 0.1 and 0.5 m³,
        // T 300 and 500 K.
        let pos = [[0.45, 0.24, 0.5], [0.55, 0.26, 0.5]];
        let mut sums = Vec::new();
        let (mut m, mut u, mut state) = (vec![0.0; 4], vec![[0.0; 3]; 4], vec![None; 4]);
        project_to_cells(
            &g,
            false,
            &lat,
            &vec![0.0; lat.len()],
            &vec![[0.0; 3]; lat.len()],
            ParticleState {
                position: &pos,
                mass: &[1.0, 3.0],
                volume: &[0.1, 0.5],
                temperature: &[300.0, 500.0],
                material: &[],
            },
            &mut sums,
            &mut m,
            &mut u,
            &mut state,
        );
        for s in state {
            let (v, t) = s.unwrap();
            assert!((v - 0.6 / 4.0).abs() < 1e-15);
            assert!((t - 1800.0 / 4.0).abs() < 1e-12);
        }
    }

    /// Two materials near node (1, 1) of a 2 × 2 grid (every cell has it
    /// as a corner): material 0 of 1 kg (V 0.1 m³, 300 K) at (0.45, 0.24),
    /// material 1 of 3 kg (0.5 m³, 500 K) at (0.55, 0.26). Each cell of mass
    /// M_c gives each material its linear-weight share of it — by hand,
    /// with the cells' weights W_pc of each particle — and each material
    /// its own V/m and T.
    #[test]
    fn materials_share_the_cell_mass_by_their_linear_weights() {
        let g = grid([2, 2, 1]);
        let lat = NodeLattice::new(&g, ShapeFunction::Linear);
        let pos = [[0.45, 0.24, 0.5], [0.55, 0.26, 0.5]];
        let cell_mass = [8.0, 4.0, 2.0, 1.0];
        let mut sums = Vec::new();
        let mut mass = vec![vec![0.0; 4]; 2];
        let mut state = vec![vec![None; 4]; 2];
        materials_to_cells(
            &g,
            false,
            &lat,
            ParticleState {
                position: &pos,
                mass: &[1.0, 3.0],
                volume: &[0.1, 0.5],
                temperature: &[300.0, 500.0],
                material: &[MaterialId(0), MaterialId(1)],
            },
            2,
            &cell_mass,
            &mut sums,
            &mut mass,
            &mut state,
        );
        // Along x (0.5 m cells, 2 cells: nodes 0, 1, 2 with 0 and 2 on
        // faces): x = 0.45 is s = 0.9, node 0 weight 0.1 (all to cell 0),
        // node 1 weight 0.9 (half to each): cells 0.55, 0.45. x = 0.55:
        // s = 1.1, cells 0.45, 0.55. Along y (0.25 m cells): y = 0.24 is
        // s = 0.96: cells 0.52, 0.48; y = 0.26, s = 1.04: 0.48, 0.52.
        let w0 = [0.55 * 0.52, 0.45 * 0.52, 0.55 * 0.48, 0.45 * 0.48];
        let w1 = [0.45 * 0.48, 0.55 * 0.48, 0.45 * 0.52, 0.55 * 0.52];
        for k in 0..4 {
            let (a, b) = (1.0 * w0[k], 3.0 * w1[k]);
            assert!(
                (mass[0][k] - cell_mass[k] * a / (a + b)).abs() < 1e-14,
                "{k}"
            );
            assert!(
                (mass[1][k] - cell_mass[k] * b / (a + b)).abs() < 1e-14,
                "{k}"
            );
            assert!((mass[0][k] + mass[1][k] - cell_mass[k]).abs() < 1e-14);
            assert_eq!(state[0][k], Some((0.1, 300.0)));
            let (v, t) = state[1][k].unwrap();
            assert!((v - 0.5 / 3.0).abs() < 1e-15 && (t - 500.0).abs() < 1e-12);
        }
    }

    /// A solid none of whose particles reaches a cell gets none of its
    /// mass, even where the cell's corners hold no particle at their
    /// nearest node: one particle of material 2 at s = 1.5 (x = 0.75 m,
    /// nearest node 2) reaches cells 0–2 through nodes 1 and 2, and cell 0
    /// (corners 0 and 1) is all material 2 — the nearest-node shares gave
    /// it a third to each absent material. Cell 3, which no particle
    /// reaches, splits its mass equally.
    #[test]
    fn an_absent_solid_takes_no_share() {
        let g = grid([4, 1, 1]);
        let lat = NodeLattice::new(&g, ShapeFunction::Linear);
        let mut sums = Vec::new();
        let mut mass = vec![vec![0.0; 4]; 3];
        let mut state = vec![vec![None; 4]; 3];
        let cell_mass = [1.0, 2.0, 1.0, 3.0];
        materials_to_cells(
            &g,
            false,
            &lat,
            ParticleState {
                position: &[[0.75, 0.1, 0.5]],
                mass: &[2.0],
                volume: &[0.1],
                temperature: &[300.0],
                material: &[MaterialId(2)],
            },
            3,
            &cell_mass,
            &mut sums,
            &mut mass,
            &mut state,
        );
        for k in 0..3 {
            assert_eq!(
                [mass[0][k], mass[1][k], mass[2][k]],
                [0.0, 0.0, cell_mass[k]],
                "cell {k}"
            );
        }
        for m in &mass {
            assert_eq!(m[3], 1.0);
        }
        assert!(state[2][0].is_none() && state[2][1].is_some() && state[2][2].is_some());
        assert!(state[2][3].is_none() && state[0][1].is_none());
    }

    /// W_pc by hand on a 4-cell axis of 0.5 m cells (cells 0..3, nodes
    /// 0..4): a particle at x = 0.6 m (s = 1.2: node 1 weight 0.8, node 2
    /// weight 0.2) gives cell 0 ½·0.8 = 0.4, cell 1 ½·0.8 + ½·0.2 = 0.5,
    /// cell 2 ½·0.2 = 0.1; at x = 0.1 m (node 0 weight 0.8, a face node,
    /// all to cell 0; node 1 weight 0.2) cell 0 0.9, cell 1 0.1.
    #[test]
    fn particle_cell_weights_by_hand() {
        let g = grid([4, 1, 1]);
        let collect = |x: f64| {
            let mut w = vec![0.0; 4];
            particle_cell_weights(&g, false, [x, 0.1, 0.5], |c, v| w[c] += v);
            w
        };
        let close = |a: &[f64], b: &[f64]| a.iter().zip(b).all(|(x, y)| (x - y).abs() < 1e-15);
        assert!(
            close(&collect(0.6), &[0.4, 0.5, 0.1, 0.0]),
            "{:?}",
            collect(0.6)
        );
        assert!(
            close(&collect(0.1), &[0.9, 0.1, 0.0, 0.0]),
            "{:?}",
            collect(0.1)
        );
        assert!(
            close(&collect(1.95), &[0.0, 0.0, 0.05, 0.95]),
            "{:?}",
            collect(1.95)
        );
    }

    /// The weights of any point of a 3D grid are positive, at most 27
    /// cells, and sum to 1; and they are eq 18's projection of the tent
    /// functions: Σ_c W_pc f_c = Σ_i N_i(x) Σ_c w_ic f_c for any cell field.
    #[test]
    fn particle_cell_weights_sum_to_one_and_are_eq_18_of_the_tents() {
        let g = grid([5, 4, 3]);
        proptest!(|(x in 0.0..2.5f64, y in 0.0..1.0f64, z in 0.0..3.0f64)| {
            let field = |c: usize| (c as f64 * 0.37).sin();
            let mut weights = Vec::new();
            particle_cell_weights(&g, false, [x, y, z], |c, w| weights.push((c, w)));
            prop_assert!(weights.len() <= 27 && weights.iter().all(|x| x.1 > 0.0));
            let sum: f64 = weights.iter().map(|x| x.1).sum();
            prop_assert!((sum - 1.0).abs() < 1e-14);
            let dot: f64 = weights.iter().map(|&(c, w)| w * field(c)).sum();
            // Tents of the corner nodes of the containing cell.
            let s = [x / 0.5, y / 0.25, z / 1.0];
            let mut expect = 0.0;
            let n_cells = g.cells;
            let i0: [usize; 3] = std::array::from_fn(|d| (s[d].floor() as usize).min(n_cells[d] - 1));
            for k in 0..2 { for j in 0..2 { for i in 0..2 {
                let node = [i0[0] + i, i0[1] + j, i0[2] + k];
                let tent: f64 = (0..3).map(|d| {
                    let t = s[d] - i0[d] as f64;
                    if node[d] == i0[d] { 1.0 - t } else { t }
                }).product();
                let c = corners_of_node(&g, node);
                expect += tent * c.iter().map(|&(cell, w)| w * field(cell)).sum::<f64>();
            }}}
            prop_assert!((dot - expect).abs() < 1e-13, "{} vs {}", dot, expect);
        });
    }

    /// The cells around node `node` with its eq 18 weights w_ic.
    fn corners_of_node(g: &UniformGridGeometry, node: [usize; 3]) -> Vec<(usize, f64)> {
        let mut out = Vec::new();
        for k in 0..g.cells[2] {
            for j in 0..g.cells[1] {
                for i in 0..g.cells[0] {
                    let c = corners(g, false, [i, j, k]);
                    for q in 0..c.count {
                        if c.node[q] == node.map(|x| x as isize) {
                            out.push((g.linear_index([i, j, k]), c.weight[q]));
                        }
                    }
                }
            }
        }
        out
    }
}
