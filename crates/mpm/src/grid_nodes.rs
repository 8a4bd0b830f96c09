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

use crate::boundary::GridBoundary;
use crate::ShapeFunction;
use brisance_core::UniformGridGeometry;
use rayon::prelude::*;

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
    /// Acceleration a_I = f_I/m_I, m/s²; on a component a face condition
    /// holds, the velocity change the condition imposes over the step,
    /// a_I = (0 − p_I/m_I)/Δt (see [`GridNodes::update`]), so that the
    /// particle velocity update v_p += Δt Σ N_Ip a_I (eq 24) sees the wall.
    pub acceleration: Vec<[f64; 3]>,
    /// Velocity at the end of the step from the momentum update,
    /// v_I^{n+1} = v_I^n + a_I Δt (eq 22), after the boundary conditions,
    /// m/s; it moves the particles (eq 25).
    pub velocity_new: Vec<[f64; 3]>,
    /// MUSL only: the velocity re-mapped from the updated particle momenta,
    /// v_I^{n+1} = Σ m_p N_Ip v_p^{n+1} / m_I (eq 26), after the boundary
    /// conditions, m/s; the velocity gradient is formed from it.
    pub velocity_remap: Vec<[f64; 3]>,
}

/// What the node updates between the transfers need.
#[derive(Debug, Clone, Copy)]
pub struct NodeUpdate<'a> {
    /// Face conditions x−, x+, y−, y+, z−, z+ ([`crate::boundary`]).
    pub boundaries: &'a [GridBoundary; 6],
    /// Cells per axis.
    pub cells: [usize; 3],
    /// Nodes at or below this mass (kg) get zero velocity and acceleration;
    /// per metre of radius where `radial` is given.
    pub mass_threshold: f64,
    /// On an axisymmetric grid, `[r of node 0, Δr]`: a node's mass, which
    /// carries 2πr, is cut off at `mass_threshold` × max(r_I, Δr/2), so the
    /// light rings at the axis keep their velocities and a far node is held
    /// to the same share of its particles' mass as on a Cartesian grid.
    pub radial: Option<[f64; 2]>,
    /// Whether a node with 0 < m_I ≤ `mass_threshold` keeps the velocity
    /// p_I/m_I (its acceleration still cut off): the coupled ICE–MPM step
    /// (seed 000 §3.3 step 1), where such a node's mass enters the cell
    /// mass of eq 18, M_c = Σ_I w_Ic m_I, so its velocity must be the
    /// particles' too. Zeroed, it gave the leading cell of a moving solid
    /// a velocity near zero against the gas beside it (a full-speed slip
    /// the momentum exchange then removed from the gas), and the particle
    /// next to it a velocity gradient (0 − v)/Δx. Off in standalone MPM.
    pub light_nodes_move: bool,
    /// Body force per unit mass, m/s².
    pub gravity: [f64; 3],
    /// Time step, s.
    pub dt: f64,
}

/// Which node update [`GridNodes::update`] makes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum NodeStage {
    /// v_I^n = p_I/m_I.
    Velocity,
    /// f_I += m_I g, a_I = f_I/m_I, v_I^{n+1} = v_I^n + a_I Δt.
    Integrate,
    /// Both, in one pass.
    VelocityAndIntegrate,
    /// MUSL: the re-mapped v_I^{n+1} = p_I/m_I into `velocity_remap`.
    Remap,
}

impl NodeUpdate<'_> {
    /// `q/m` with the cut-off: zero at or below the threshold (or for a
    /// non-positive mass).
    #[inline(always)]
    fn per_unit_mass(&self, q: [f64; 3], m: f64, threshold: f64) -> [f64; 3] {
        if m > threshold && m > 0.0 {
            [q[0] / m, q[1] / m, q[2] / m]
        } else {
            [0.0; 3]
        }
    }

    /// The node velocity `p/m`: [`Self::per_unit_mass`], except that a
    /// light node (0 < m ≤ threshold) keeps p/m when `light_nodes_move`.
    #[inline(always)]
    fn velocity(&self, p: [f64; 3], m: f64, threshold: f64) -> [f64; 3] {
        if self.light_nodes_move && m > 0.0 {
            [p[0] / m, p[1] / m, p[2] / m]
        } else {
            self.per_unit_mass(p, m, threshold)
        }
    }

    /// The cut-off mass of the node at global x index `i`.
    #[inline(always)]
    fn threshold(&self, i: isize) -> f64 {
        match self.radial {
            None => self.mass_threshold,
            Some([r0, h]) => self.mass_threshold * (r0 + i as f64 * h).max(0.5 * h),
        }
    }

    /// The components the face conditions zero at global node index `i`
    /// along `axis` (see [`crate::boundary::apply_grid_boundaries`]: the
    /// nodes on or beyond a face, of active axes only).
    #[inline(always)]
    fn face_mask(&self, axis: usize, i: isize) -> [bool; 3] {
        let n = self.cells[axis] as isize;
        if n <= 1 {
            return [false; 3];
        }
        let bc = if i <= 0 {
            self.boundaries[2 * axis]
        } else if i >= n {
            self.boundaries[2 * axis + 1]
        } else {
            return [false; 3];
        };
        match bc {
            GridBoundary::Fixed => [true; 3],
            GridBoundary::Symmetry => std::array::from_fn(|c| c == axis),
            GridBoundary::Free | GridBoundary::Outflow => [false; 3],
        }
    }
}

/// `v` with the components of `mask` set to zero.
#[inline(always)]
fn masked(v: [f64; 3], mask: [bool; 3]) -> [f64; 3] {
    std::array::from_fn(|c| if mask[c] { 0.0 } else { v[c] })
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
            velocity_remap: vec![[0.0; 3]; n],
        }
    }

    /// Bytes the node fields hold: 152 per node (mass and six vectors).
    pub fn bytes(&self) -> usize {
        use std::mem::size_of_val;
        size_of_val(self.mass.as_slice())
            + [
                &self.momentum,
                &self.force,
                &self.velocity,
                &self.acceleration,
                &self.velocity_new,
                &self.velocity_remap,
            ]
            .iter()
            .map(|v| size_of_val(v.as_slice()))
            .sum::<usize>()
    }

    /// The node update `stage`, with the mass cut-off and the boundary
    /// conditions applied to every velocity formed (parallel over x-rows of
    /// nodes; each node on its own, so the result does not depend on the
    /// split).
    ///
    /// On a component that a face condition holds at zero, v_I^n, v_I^{n+1}
    /// and the re-mapped velocity are zero, and the acceleration is the
    /// change of velocity the condition makes over the step, from the
    /// node's own p_I/m_I to zero: a_I = −(p_I/m_I)/Δt. The particles take
    /// their velocity change from a_I (eq 24), so a particle moving into a
    /// wall loses the normal velocity its wall nodes carried, as the nodes
    /// did; with a_I = 0 there instead it would keep it, sitting at the
    /// wall with its impact velocity and feeding it back to the grid at the
    /// next P2G. (The free-slip components of a symmetry or roller face
    /// are untouched.)
    pub fn update(&mut self, u: &NodeUpdate, stage: NodeStage) {
        let lattice = self.lattice;
        let nx = lattice.dims[0];
        let (vel, integrate, remap) = match stage {
            NodeStage::Velocity => (true, false, false),
            NodeStage::Integrate => (false, true, false),
            NodeStage::VelocityAndIntegrate => (true, true, false),
            NodeStage::Remap => (false, false, true),
        };
        let g = u.gravity;
        let dt = u.dt;
        (
            self.mass.par_chunks(nx),
            self.momentum.par_chunks(nx),
            self.force.par_chunks_mut(nx),
            self.velocity.par_chunks_mut(nx),
            self.acceleration.par_chunks_mut(nx),
            self.velocity_new.par_chunks_mut(nx),
            self.velocity_remap.par_chunks_mut(nx),
        )
            .into_par_iter()
            .enumerate()
            .for_each(|(row, (m, p, f, v, a, vn, vr))| {
                let first = lattice.node(row * nx);
                let yz: [bool; 3] = {
                    let my = u.face_mask(1, first[1]);
                    let mz = u.face_mask(2, first[2]);
                    std::array::from_fn(|c| my[c] || mz[c])
                };
                for i in 0..nx {
                    let mx = u.face_mask(0, first[0] + i as isize);
                    let mask: [bool; 3] = std::array::from_fn(|c| mx[c] || yz[c]);
                    let thr = u.threshold(first[0] + i as isize);
                    if vel {
                        v[i] = masked(u.velocity(p[i], m[i], thr), mask);
                    }
                    if integrate {
                        let ft: [f64; 3] = std::array::from_fn(|c| f[i][c] + m[i] * g[c]);
                        f[i] = ft;
                        let free = u.per_unit_mass(ft, m[i], thr);
                        let held = if dt > 0.0 {
                            u.per_unit_mass(p[i], m[i], thr).map(|v| -v / dt)
                        } else {
                            [0.0; 3]
                        };
                        a[i] = std::array::from_fn(|c| if mask[c] { held[c] } else { free[c] });
                        vn[i] =
                            std::array::from_fn(
                                |c| {
                                    if mask[c] {
                                        0.0
                                    } else {
                                        v[i][c] + free[c] * dt
                                    }
                                },
                            );
                    }
                    if remap {
                        vr[i] = masked(u.velocity(p[i], m[i], thr), mask);
                    }
                }
            });
    }
}

impl GridNodes {
    /// Adds the velocity change `dv` (one per stored node) to v_I^{n+1}
    /// and `dv`/Δt to a_I — the coupled pipeline's cell-centred momentum
    /// changes returned to the nodes as accelerations (seed 000 §3.3 step
    /// 13) — on every node with mass, light ones included (their velocity
    /// is p_I/m_I in the coupled step, [`NodeUpdate::light_nodes_move`],
    /// and Δv_I = Σ_c w_Ic Δu_c is a weighted mean of bounded cell changes),
    /// so that the nodes receive exactly the momentum Σ_c M_c Δu_c, and on
    /// the components no face condition holds, so the conditions stay met.
    pub fn add_velocity_change(&mut self, dv: &[[f64; 3]], u: &NodeUpdate) {
        assert_eq!(dv.len(), self.mass.len(), "one velocity change per node");
        let lattice = self.lattice;
        let nx = lattice.dims[0];
        let dt = u.dt;
        (
            self.mass.par_chunks(nx),
            dv.par_chunks(nx),
            self.acceleration.par_chunks_mut(nx),
            self.velocity_new.par_chunks_mut(nx),
        )
            .into_par_iter()
            .enumerate()
            .for_each(|(row, (m, dv, a, vn))| {
                let first = lattice.node(row * nx);
                let my = u.face_mask(1, first[1]);
                let mz = u.face_mask(2, first[2]);
                for i in 0..nx {
                    if !(m[i] > 0.0) {
                        continue;
                    }
                    let mx = u.face_mask(0, first[0] + i as isize);
                    for c in 0..3 {
                        if !(mx[c] || my[c] || mz[c]) {
                            vn[i][c] += dv[i][c];
                            a[i][c] += dv[i][c] / dt;
                        }
                    }
                }
            });
    }
}

impl GridNodes {
    /// Work done on the grid in one step of Δt = `dt` by the external nodal
    /// forces: the surface tractions `surface_forces` ((node, force) pairs
    /// of [`crate::traction::surface_node_forces`], seed 001 eq 20) and the
    /// body force m_I g (eq 23),
    ///
    /// W = Δt Σ_I f_I^ext · (v_I^n + v_I^{n+1}) / 2,
    ///
    /// with `velocity` (v_I^n) and `velocity_new` (v_I^{n+1}) as the step
    /// left them, after the cut-off and the boundary conditions. With
    /// v_I^{n+1} = v_I^n + Δt f_I/m_I this is the kinetic energy a force
    /// f_I^ext alone gives node I, ½ m_I (|v_I^{n+1}|² − |v_I^n|²); a force
    /// on a node held by a wall or below the cut-off does no work.
    ///
    /// The traction pairs are summed in list order; the body-force sum (only
    /// when g ≠ 0) is taken per x-row of nodes, rows in parallel, and the
    /// row sums added in row order: the same bits on any number of threads.
    pub fn external_work(
        &self,
        surface_forces: &[(usize, [f64; 3])],
        gravity: [f64; 3],
        dt: f64,
    ) -> f64 {
        let power = |f: [f64; 3], i: usize| {
            let (a, b) = (self.velocity[i], self.velocity_new[i]);
            0.5 * (f[0] * (a[0] + b[0]) + f[1] * (a[1] + b[1]) + f[2] * (a[2] + b[2]))
        };
        let mut w: f64 = surface_forces.iter().map(|&(i, f)| power(f, i)).sum();
        if gravity != [0.0; 3] {
            let nx = self.lattice.dims[0];
            let rows: Vec<f64> = self
                .mass
                .par_chunks(nx)
                .enumerate()
                .map(|(row, m)| {
                    let first = row * nx;
                    (0..m.len())
                        .map(|i| power(gravity.map(|g| m[i] * g), first + i))
                        .sum()
                })
                .collect();
            w += rows.iter().sum::<f64>();
        }
        w * dt
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::boundary::apply_grid_boundaries;

    /// Every combination of the four conditions on the six faces of a 3D
    /// and a 2D lattice (with ghost layers): the node update forms the
    /// per-unit-mass quantities with the cut-off and applies the face
    /// conditions exactly as `apply_grid_boundaries` does.
    #[test]
    fn node_update_matches_the_step_by_step_definition() {
        let kinds = [
            GridBoundary::Fixed,
            GridBoundary::Symmetry,
            GridBoundary::Free,
            GridBoundary::Outflow,
        ];
        for cells in [[3, 4, 2], [4, 3, 1]] {
            let grid = UniformGridGeometry {
                origin: [0.0; 3],
                spacing: [1.0; 3],
                cells,
            };
            for shape in [ShapeFunction::Linear, ShapeFunction::QuadraticBSpline] {
                let lat = NodeLattice::new(&grid, shape);
                let n = lat.len();
                let mut nodes = GridNodes::new(lat);
                for i in 0..n {
                    let t = i as f64;
                    // Some nodes below the cut-off, one massless.
                    nodes.mass[i] = if i % 5 == 0 { 0.01 } else { 1.0 + 0.1 * t };
                    nodes.mass[n / 2] = 0.0;
                    nodes.momentum[i] = [t.sin(), t.cos(), 0.3 * t];
                    nodes.force[i] = [(2.0 * t).sin(), -t, 0.5];
                }
                for code in 0..4usize.pow(6) {
                    let bcs: [GridBoundary; 6] =
                        std::array::from_fn(|f| kinds[(code >> (2 * f)) & 3]);
                    let u = NodeUpdate {
                        boundaries: &bcs,
                        cells,
                        mass_threshold: 0.05,
                        radial: None,
                        light_nodes_move: false,
                        gravity: [0.5, -9.75, 0.25],
                        dt: 0.125,
                    };
                    let mut got = nodes.clone();
                    got.update(&u, NodeStage::VelocityAndIntegrate);
                    got.update(&u, NodeStage::Remap);
                    let unit = |q: &[[f64; 3]]| -> Vec<[f64; 3]> {
                        (0..n)
                            .map(|i| {
                                let m = nodes.mass[i];
                                if m > 0.05 {
                                    std::array::from_fn(|c| q[i][c] / m)
                                } else {
                                    [0.0; 3]
                                }
                            })
                            .collect()
                    };
                    let f: Vec<[f64; 3]> = (0..n)
                        .map(|i| {
                            std::array::from_fn(|c| {
                                nodes.force[i][c] + nodes.mass[i] * u.gravity[c]
                            })
                        })
                        .collect();
                    // The held components: those the conditions zero in a
                    // field of ones.
                    let mut held = vec![[1.0; 3]; n];
                    apply_grid_boundaries(&bcs, &lat, cells, &mut [&mut held]);
                    let free_v = unit(&nodes.momentum);
                    let free_a = unit(&f);
                    let mut v = free_v.clone();
                    let mut vr = v.clone();
                    apply_grid_boundaries(&bcs, &lat, cells, &mut [&mut v, &mut vr]);
                    // Held: v^{n+1} = 0 and a = (0 − p/m)/Δt; free: a = f/m
                    // and v^{n+1} = v^n + a Δt.
                    let a: Vec<[f64; 3]> = (0..n)
                        .map(|i| {
                            std::array::from_fn(|c| {
                                if held[i][c] == 0.0 {
                                    -free_v[i][c] / u.dt
                                } else {
                                    free_a[i][c]
                                }
                            })
                        })
                        .collect();
                    let vn: Vec<[f64; 3]> = (0..n)
                        .map(|i| {
                            std::array::from_fn(|c| {
                                if held[i][c] == 0.0 {
                                    0.0
                                } else {
                                    v[i][c] + a[i][c] * u.dt
                                }
                            })
                        })
                        .collect();
                    assert_eq!(got.velocity, v, "{cells:?} {bcs:?}");
                    assert_eq!(got.force, f);
                    assert_eq!(got.acceleration, a, "{cells:?} {bcs:?}");
                    assert_eq!(got.velocity_new, vn);
                    assert_eq!(got.velocity_remap, vr);
                    // The stages one at a time give the same.
                    let mut one = nodes.clone();
                    one.update(&u, NodeStage::Velocity);
                    one.update(&u, NodeStage::Integrate);
                    assert_eq!(one.velocity_new, vn);
                }
            }
        }
    }

    /// A particle moving at −v into a symmetry (roller) face, one cell of
    /// 1 m, linear functions, at x_p = 0.25: N₀ = 0.75 on the wall node,
    /// N₁ = 0.25. No force acts. The wall node's free velocity p₀/m₀ = −v
    /// is stopped over the step, a₀ = v/Δt, and the particle's velocity
    /// update Δt Σ N_I a_I = 0.75 v leaves it −0.25 v, the velocity the grid
    /// moves it with (Σ N_I v_I^{n+1} = 0.25 × −v). With a₀ = 0 it would
    /// keep −v at the wall.
    #[test]
    fn a_particle_moving_into_a_wall_loses_the_velocity_its_wall_node_had() {
        let grid = UniformGridGeometry {
            origin: [0.0; 3],
            spacing: [1.0; 3],
            cells: [4, 1, 1],
        };
        let mut nodes = GridNodes::new(NodeLattice::new(&grid, ShapeFunction::Linear));
        let (mass, v, dt) = (2.0, 3.0, 0.125);
        let weights = [0.75, 0.25];
        for (i, w) in weights.iter().enumerate() {
            nodes.mass[i] = w * mass;
            nodes.momentum[i] = [w * mass * -v, w * mass * 0.5, 0.0];
        }
        let mut bcs = [GridBoundary::Free; 6];
        bcs[0] = GridBoundary::Symmetry;
        let u = NodeUpdate {
            boundaries: &bcs,
            cells: grid.cells,
            mass_threshold: 0.0,
            radial: None,
            light_nodes_move: false,
            gravity: [0.0; 3],
            dt,
        };
        nodes.update(&u, NodeStage::VelocityAndIntegrate);
        assert_eq!(nodes.velocity[0], [0.0, 0.5, 0.0]);
        assert_eq!(nodes.velocity_new[0], [0.0, 0.5, 0.0]);
        assert_eq!(nodes.acceleration[0], [v / dt, 0.0, 0.0]);
        assert_eq!(nodes.acceleration[1], [0.0; 3]);
        assert_eq!(nodes.velocity_new[1], [-v, 0.5, 0.0]);
        let dv: f64 = (0..2)
            .map(|i| weights[i] * nodes.acceleration[i][0] * dt)
            .sum();
        let pic: f64 = (0..2).map(|i| weights[i] * nodes.velocity_new[i][0]).sum();
        assert_eq!(-v + dv, -0.25 * v);
        assert_eq!(-v + dv, pic);
        // The tangential velocity slides freely.
        let dvy: f64 = (0..2)
            .map(|i| weights[i] * nodes.acceleration[i][1] * dt)
            .sum();
        assert_eq!(dvy, 0.0);
    }

    #[test]
    fn external_work_is_the_force_times_the_mean_node_velocity() {
        // Four nodes along x (three cells of 1 m, linear): hand values.
        let grid = UniformGridGeometry {
            origin: [0.0; 3],
            spacing: [1.0; 3],
            cells: [3, 1, 1],
        };
        let mut nodes = GridNodes::new(NodeLattice::new(&grid, ShapeFunction::Linear));
        assert_eq!(nodes.mass.len(), 4);
        nodes.mass = vec![2.0, 1.0, 0.5, 0.0];
        nodes.velocity = vec![[1.0, 0.0, 0.0], [0.0, 2.0, 0.0], [0.0; 3], [5.0; 3]];
        nodes.velocity_new = vec![[3.0, 0.0, 0.0], [0.0, 4.0, 1.0], [0.0; 3], [5.0; 3]];
        let dt = 0.5;
        // Traction only: node 0 gets (1, 0, 0) N, mean velocity (2, 0, 0):
        // 2 W; node 1 gets (0, 3, 2) N twice (two loaded particles), mean
        // velocity (0, 3, 0.5): 2 × 10 W; node 2 is held (zero velocity).
        let forces = [
            (0, [1.0, 0.0, 0.0]),
            (1, [0.0, 3.0, 2.0]),
            (1, [0.0, 3.0, 2.0]),
            (2, [7.0, 7.0, 7.0]),
        ];
        assert_eq!(nodes.external_work(&forces, [0.0; 3], dt), 0.5 * 22.0);
        // Gravity (0, −10, 1): node 0: 2 kg × (0·2 − 10·0 + 1·0) = 0;
        // node 1: 1 kg × (−10·3 + 1·0.5) = −29.5; node 3 (massless): 0.
        assert_eq!(nodes.external_work(&[], [0.0, -10.0, 1.0], dt), 0.5 * -29.5);
        assert_eq!(
            nodes.external_work(&forces, [0.0, -10.0, 1.0], dt),
            0.5 * (22.0 - 29.5)
        );
    }

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
