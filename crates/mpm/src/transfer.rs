//! Particle-to-grid (P2G) and grid-to-particle (G2P) transfers of seed 001
//! eqs 18–21, 24–28 (seed 000 eqs 12–17).
//!
//! # Kernel design
//!
//! **Stencils.** Every shape function is a tensor product of 1D weights
//! ([`crate::shape`]). A kernel evaluates a particle's three 1D stencils
//! from its position when it visits the particle, into fixed-length arrays
//! of N = 2 (linear) or 3 (GIMP, B-spline; GIMP padded with zero weights)
//! nodes per active axis and 1 per inactive axis. Nothing is stored per
//! particle: recomputing the 1D weights (one division and a few products
//! per axis) costs less than reading a stored stencil back from memory.
//! The kernels are monomorphised for the node counts (NX, NY, NZ) so that
//! the node loops have constant trip counts; the weight and gradient of
//! node (a, b, c) are formed by [`TensorRow`], exactly as
//! [`crate::ShapeFunction::evaluate`] forms them.
//!
//! **Bins and blocks.** A particle's stencil starts at the storage offset
//! `bin` along each active axis: its cell ⌊ξ⌋ for the linear function, its
//! nearest node ⌊ξ + 1/2⌋ for GIMP and the B-spline (ξ = (x − x_min)/Δx;
//! with the lattice's ghost layer that node's left neighbour is stored at
//! offset ⌊ξ + 1/2⌋). Bins are grouped into blocks of T bins per
//! active axis, and [`ParticleBins`] lists the particles of each block
//! (a counting sort, O(N), redone every step; within a block the particles
//! keep their storage order).
//!
//! **Deterministic scatter P2G by colouring.** A particle of block k
//! (along one axis) touches storage nodes kT … kT + T − 1 + N − 1 with
//! T = [`GridMap::block_bins`]; block k + 2 starts at (k + 2)T, past that range
//! whenever T ≥ N − 1. The blocks are coloured by the parity of their
//! three block coordinates (8 colours), so two blocks of one colour touch
//! disjoint nodes. P2G visits the colours one after the other; within a
//! colour the blocks run in parallel and each scatters its particles, in
//! list order, straight into the node arrays. A node therefore receives its
//! contributions in one fixed order — colour by colour, from the single
//! block of each colour that reaches it, particle by particle in the
//! block's list — which depends only on the particles' positions and
//! storage order, never on the thread count or on how the level is split
//! into patches: the sums are the same bits on 1 or 64 threads, without
//! atomics or per-thread copies. The disjointness is checked, not assumed:
//! each coloured visit asserts that the particle's stencil lies in the
//! footprint of the block it is listed in, and every node row written is
//! bounds-checked.
//!
//! **Fused passes.** One coloured pass gathers mass, momentum and internal
//! force together (eqs 18, 19, 21); MUSL's second pass updates each
//! particle's velocity from the nodal acceleration (eq 24) and scatters its
//! new momentum for the re-mapping (eq 26) in the same visit. The passes
//! that only read the grid — position update (eq 25) and velocity gradient
//! (eqs 27–28) — run over the particles in storage order, in parallel, each
//! particle writing only itself.

mod g2p;
pub mod heat;

pub use g2p::{
    g2p, g2p_range, g2p_velocity_and_remap_momentum, g2p_velocity_and_remap_momentum_weighted,
    hoop_rate, G2p, G2pParticles,
};

use crate::grid_nodes::{GridNodes, NodeLattice};
use crate::shape::{bspline, gimp, linear, ShapeError, TensorRow};
use crate::ShapeFunction;
use brisance_core::Geometry;
use brisance_core::{Mat3, UniformGridGeometry};
use rayon::prelude::*;
use std::marker::PhantomData;

/// The default block edge, in bins, of [`GridMap::new`]. The colouring
/// needs a block edge T ≥ N − 1 for stencils of N nodes per axis (N ≤ 3).
pub const BLOCK_BINS: usize = 2;

/// Number of block colours: the parities of the three block coordinates.
pub const COLOURS: usize = 8;

/// Particles a parallel task takes at least, in the storage-order passes.
const PARTICLES_PER_TASK: usize = 512;

/// The grid as the kernels see it: geometry, node lattice and the bin and
/// block layout of the shape function.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GridMap {
    /// The grid.
    pub grid: UniformGridGeometry,
    /// The shape function.
    pub shape: ShapeFunction,
    /// The node lattice.
    pub lattice: NodeLattice,
    /// 1/Δx per axis, 1/m.
    inv_spacing: [f64; 3],
    /// Nodes a particle's stencil spans per axis (1 on an inactive axis).
    pub nodes_per_axis: [usize; 3],
    /// Storage stride of a node step along each axis.
    stride: [usize; 3],
    /// Bins per axis.
    pub bins: [usize; 3],
    /// Bins per block edge along an active axis (T of the module doc), a
    /// power of two.
    pub block_bins: usize,
    /// log₂ of `block_bins`: bins become blocks by a shift, not a division.
    block_shift: u32,
    /// Blocks per axis.
    pub blocks: [usize; 3],
    /// Whether the grid is axisymmetric (r, z): x is the radius, particles
    /// are rings, and the transfers carry the hoop terms
    /// ([`GridMap::with_geometry`]).
    pub axisymmetric: bool,
}

impl GridMap {
    /// The map of `grid` for `shape`, with blocks of [`BLOCK_BINS`] bins.
    pub fn new(grid: &UniformGridGeometry, shape: ShapeFunction) -> Self {
        Self::with_block_bins(grid, shape, BLOCK_BINS)
    }

    /// The block edge, in bins, for a set of `particles` particles: 2 up to
    /// 2¹⁷ particles, 4 up to 2¹⁹, 8 above. Small blocks give each colour
    /// many blocks to share among the threads; large ones keep a block's
    /// nodes in cache while its particles are scattered, which is what
    /// limits a coloured pass over a million particles. A function of the
    /// problem only, never of the thread count, so the summation order
    /// (and the bits) stays fixed.
    pub fn block_bins_for(particles: usize) -> usize {
        if particles < 1 << 17 {
            2
        } else if particles < 1 << 19 {
            4
        } else {
            8
        }
    }

    /// The map of `grid` for `shape` with blocks of `block_bins` bins per
    /// active axis: a power of two, at least 2 (as the colouring needs).
    pub fn with_block_bins(
        grid: &UniformGridGeometry,
        shape: ShapeFunction,
        block_bins: usize,
    ) -> Self {
        assert!(
            block_bins >= 2 && block_bins.is_power_of_two(),
            "blocks of {block_bins} bins: a power of two of at least 2 is needed"
        );
        let lattice = NodeLattice::new(grid, shape);
        let active: [bool; 3] = std::array::from_fn(|d| grid.cells[d] > 1);
        let nodes_per_axis =
            std::array::from_fn(|d| if active[d] { shape.nodes_per_axis() } else { 1 });
        let bins: [usize; 3] = std::array::from_fn(|d| match (active[d], shape) {
            (false, _) => 1,
            (true, ShapeFunction::Linear) => grid.cells[d],
            (
                true,
                ShapeFunction::Gimp | ShapeFunction::CpGimp | ShapeFunction::QuadraticBSpline,
            ) => grid.cells[d] + 1,
        });
        Self {
            grid: *grid,
            shape,
            lattice,
            inv_spacing: std::array::from_fn(|d| 1.0 / grid.spacing[d]),
            nodes_per_axis,
            stride: [1, lattice.dims[0], lattice.dims[0] * lattice.dims[1]],
            bins,
            block_bins,
            block_shift: block_bins.trailing_zeros(),
            blocks: std::array::from_fn(|d| bins[d].div_ceil(block_bins)),
            axisymmetric: false,
        }
    }

    /// This map on a grid of `geometry`. On an axisymmetric (r, z) grid the
    /// particles are rings about x = 0 and P2G and G2P add the hoop terms of
    /// Sulsky & Schreyer (*Axisymmetric form of the material point method
    /// with applications to upsetting and Taylor impact problems*, Comput.
    /// Methods Appl. Mech. Engrg. 139, 1996): the force −V_p σ_θθ N_Ip / r_p
    /// on the radial component, and the hoop velocity gradient
    /// L_θθ = Σ_I N_Ip v_Ir / r_p (docs/physics/mpm/axisymmetric.md).
    pub fn with_geometry(mut self, geometry: Geometry) -> Self {
        self.axisymmetric = geometry.is_axisymmetric();
        self
    }

    /// The volume of a particle's domain in the grid's plane times the
    /// inactive axis' width, from which the GIMP half-widths are formed:
    /// the initial volume `v0` on a Cartesian grid; on an axisymmetric one
    /// the ring's cross-section A_p0 = v0 / (2π r_p0), with the initial
    /// radius r_p0 = r_p / F_θθ, times the width of the third axis.
    #[inline]
    pub fn planar_volume(&self, v0: f64, x: [f64; 3], f: &[f64; 9]) -> f64 {
        if !self.axisymmetric {
            return v0;
        }
        let r0 = x[0] / f[8];
        v0 / (2.0 * std::f64::consts::PI * r0) * self.grid.spacing[2]
    }

    /// Number of blocks.
    pub fn block_count(&self) -> usize {
        self.blocks.iter().product()
    }

    /// The bin of grid coordinate `xi` along axis `d`: the storage offset of
    /// the first node of the stencil (the same floors as the 1D stencils of
    /// [`crate::shape`]). Meaningful for `xi` in [0, cells] only.
    #[inline(always)]
    fn bin(&self, d: usize, xi: f64) -> usize {
        let n = self.grid.cells[d];
        if n <= 1 {
            return 0;
        }
        let b = match self.shape {
            ShapeFunction::Linear => {
                let c = crate::shape::floor(xi);
                if xi == n as f64 {
                    c - 1.0
                } else {
                    c
                }
            }
            ShapeFunction::Gimp | ShapeFunction::CpGimp | ShapeFunction::QuadraticBSpline => {
                crate::shape::floor(xi + 0.5)
            }
        };
        // Clamped, so that a position outside (discarded by the caller)
        // cannot overflow the block index.
        (b as usize).min(self.bins[d] - 1)
    }

    /// The block of a particle at `x`, or `None` when it lies outside the
    /// grid ([0, cells] in grid coordinates on every axis, the test of
    /// `UniformGridGeometry::cell_containing`) or is not finite.
    #[inline]
    pub fn block_of(&self, x: [f64; 3]) -> Option<usize> {
        let mut block = 0;
        let mut inside = true;
        for d in (0..3).rev() {
            let xi = (x[d] - self.grid.origin[d]) / self.grid.spacing[d];
            inside &= xi >= 0.0 && xi <= self.grid.cells[d] as f64;
            block = block * self.blocks[d] + (self.bin(d, xi) >> self.block_shift);
        }
        inside.then_some(block)
    }

    /// The block that holds storage offsets `offset` (the bins of a
    /// stencil).
    #[inline]
    fn block_of_offsets(&self, offset: [usize; 3]) -> usize {
        let t = self.block_shift;
        (offset[0] >> t) + self.blocks[0] * ((offset[1] >> t) + self.blocks[1] * (offset[2] >> t))
    }

    /// The uGIMP half-width of a particle of initial volume `v0` (0 for the
    /// other shapes, which do not use it), checked against (0, Δx/2] on
    /// every active axis; a value a few ulps above Δx/2 (the round-off of
    /// [`gimp_half_width`] at one particle per cell) is taken as Δx/2 (see
    /// [`gimp::admissible_half_width`]). For cpGIMP this is the undeformed
    /// half-width l_p0; [`GridMap::deformed_half_width`] gives the deformed
    /// one.
    #[inline]
    pub fn half_width(&self, v0: f64) -> Result<f64, ShapeError> {
        if !self.shape.is_gimp() {
            return Ok(0.0);
        }
        let lp = gimp_half_width(&self.grid, v0);
        let mut admitted = lp;
        for d in 0..3 {
            let h = self.grid.spacing[d];
            // The plain check first: the round-off rule is the rare case.
            if self.grid.cells[d] > 1 && !(lp > 0.0 && lp <= 0.5 * h) {
                match gimp::admissible_half_width(lp, h) {
                    Some(l) => admitted = admitted.min(l),
                    None => {
                        return Err(ShapeError::HalfWidth {
                            axis: d,
                            half_width: lp,
                            max: 0.5 * h,
                        })
                    }
                }
            }
        }
        Ok(admitted)
    }

    /// The cpGIMP half-widths per axis of a particle of initial volume `v0`
    /// and deformation gradient `f` (row-major): l_p,i = l_p0 F_ii
    /// ([`gimp::cpgimp_half_width`]) on active axes, l_p0 =
    /// [`gimp_half_width`] of `v0`; Δx/2 on inactive ones (unused). Like a
    /// stretched domain, one born wider than a cell (a particle the
    /// FDM–MPM bridge's inflow deposits grew) is capped at Δx/2
    /// (docs/physics/mpm/gimp.md, "Bounds"); a zero, negative or
    /// non-finite l_p0 is refused.
    pub fn deformed_half_width(&self, v0: f64, f: &[f64; 9]) -> Result<[f64; 3], ShapeError> {
        let l0 = gimp_half_width(&self.grid, v0);
        if let Some(d) = (0..3).find(|&d| self.grid.cells[d] > 1) {
            if !(l0 > 0.0 && l0.is_finite()) {
                return Err(ShapeError::HalfWidth {
                    axis: d,
                    half_width: l0,
                    max: 0.5 * self.grid.spacing[d],
                });
            }
        }
        let mut out = [0.0; 3];
        for d in 0..3 {
            let h = self.grid.spacing[d];
            if self.grid.cells[d] <= 1 {
                out[d] = 0.5 * h;
                continue;
            }
            let lp = gimp::cpgimp_half_width(l0, f[4 * d], h);
            out[d] = gimp::admissible_half_width(lp, h).ok_or(ShapeError::HalfWidth {
                axis: d,
                half_width: lp,
                max: 0.5 * h,
            })?;
        }
        Ok(out)
    }

    /// The 1D stencil along axis `d` of a particle at coordinate `x` (m)
    /// with GIMP half-width `lp`, as N weights and derivatives from the
    /// storage offset `offset`.
    #[inline(always)]
    fn axis<const N: usize>(&self, d: usize, x: f64, lp: f64) -> Axis<N> {
        let mut w = [0.0; N];
        let mut g = [0.0; N];
        if N == 1 {
            w[0] = 1.0;
            return Axis { offset: 0, w, g };
        }
        let h = self.grid.spacing[d];
        let xi = (x - self.grid.origin[d]) / h;
        let inv_h = self.inv_spacing[d];
        // In place, so that the weights stay in registers.
        let first = match self.shape {
            ShapeFunction::Linear => {
                linear::hat_1d_into(xi, inv_h, self.grid.cells[d], &mut w, &mut g)
            }
            ShapeFunction::QuadraticBSpline => {
                bspline::quadratic_bspline_1d_into(xi, inv_h, &mut w, &mut g)
            }
            ShapeFunction::Gimp | ShapeFunction::CpGimp => {
                gimp::ugimp_1d_padded_into(xi, h, lp, &mut w, &mut g)
            }
        };
        Axis {
            // A particle outside the lattice wraps to a huge offset, which
            // the bounds checks of the node rows reject.
            offset: (first - self.lattice.first[d]) as usize,
            w,
            g,
        }
    }

    /// The stencil of a particle at `x` with GIMP half-widths `lp` per axis.
    #[inline(always)]
    fn stencil<const NX: usize, const NY: usize, const NZ: usize>(
        &self,
        x: [f64; 3],
        lp: [f64; 3],
    ) -> Stencil<NX, NY, NZ> {
        let sx = self.axis::<NX>(0, x[0], lp[0]);
        let sy = self.axis::<NY>(1, x[1], lp[1]);
        let sz = self.axis::<NZ>(2, x[2], lp[2]);
        Stencil {
            base: sx.offset + self.stride[1] * sy.offset + self.stride[2] * sz.offset,
            offset: [sx.offset, sy.offset, sz.offset],
            x: sx,
            y: sy,
            z: sz,
        }
    }

    /// Storage index of the first node of row (b, c) of a stencil.
    #[inline(always)]
    fn row_start(&self, base: usize, b: usize, c: usize) -> usize {
        base + b * self.stride[1] + c * self.stride[2]
    }
}

/// The uGIMP half-width of a particle of volume `volume` (m³): half the
/// side of a cube of that volume over the active axes, l_p = ½ (V_p /
/// Π_inactive Δx)^(1/n_active). For particles generated `ppc` per cell per
/// direction this is Δx/(2 ppc), the default of
/// [`ShapeFunction::default_half_width`].
pub fn gimp_half_width(grid: &UniformGridGeometry, volume: f64) -> f64 {
    let mut thickness = 1.0;
    let mut active = 0;
    for d in 0..3 {
        if grid.cells[d] > 1 {
            active += 1;
        } else {
            thickness *= grid.spacing[d];
        }
    }
    if active == 0 {
        return f64::INFINITY;
    }
    0.5 * (volume / thickness).powf(1.0 / active as f64)
}

/// One axis of a particle stencil: N weights and derivatives (1/m) from
/// storage offset `offset`.
#[derive(Debug, Clone, Copy)]
struct Axis<const N: usize> {
    offset: usize,
    w: [f64; N],
    g: [f64; N],
}

/// A particle's stencil: its three axes and the storage index of its first
/// node.
#[derive(Debug, Clone, Copy)]
struct Stencil<const NX: usize, const NY: usize, const NZ: usize> {
    base: usize,
    offset: [usize; 3],
    x: Axis<NX>,
    y: Axis<NY>,
    z: Axis<NZ>,
}

impl<const NX: usize, const NY: usize, const NZ: usize> Stencil<NX, NY, NZ> {
    /// The y–z factors of row (b, c).
    #[inline(always)]
    fn row(&self, b: usize, c: usize) -> TensorRow {
        TensorRow::new(self.y.w[b], self.y.g[b], self.z.w[c], self.z.g[c])
    }
}

/// Why particles cannot be binned.
#[derive(Debug, Clone, Copy, PartialEq, thiserror::Error)]
pub enum BinError {
    /// A particle outside the grid or with a non-finite coordinate.
    #[error("particle {index} at {position:?} m lies outside the grid")]
    Outside {
        /// Particle index.
        index: usize,
        /// Its position, m.
        position: [f64; 3],
    },
    /// A particle whose shape function cannot be evaluated.
    #[error("particle {index}: {error}")]
    Shape {
        /// Particle index.
        index: usize,
        /// The reason.
        error: ShapeError,
    },
    /// More particles than the 32-bit particle lists hold.
    #[error("{count} particles exceed the 4 294 967 295 a solver holds")]
    TooMany {
        /// The particle count.
        count: usize,
    },
}

/// `out[p] = value(p, V_p⁰)` for every particle, in parallel; on failure
/// the error of the lowest particle index, so the report does not depend
/// on the thread count.
fn fill_per_particle<T: Send>(
    out: &mut [T],
    initial_volume: &[f64],
    value: impl Fn(usize, f64) -> Result<T, ShapeError> + Sync,
) -> Result<(), BinError> {
    let bad = out
        .par_iter_mut()
        .zip(initial_volume.par_iter())
        .with_min_len(PARTICLES_PER_TASK)
        .enumerate()
        .filter_map(|(index, (slot, &v0))| match value(index, v0) {
            Ok(v) => {
                *slot = v;
                None
            }
            Err(error) => Some(BinError::Shape { index, error }),
        })
        .min_by_key(|e| match e {
            BinError::Shape { index, .. } => *index,
            _ => usize::MAX,
        });
    bad.map_or(Ok(()), Err)
}

/// The particles of every block, and the non-empty blocks of every colour:
/// the schedule of the coloured passes. Rebuilt every step from the
/// positions (see the module doc).
#[derive(Debug, Clone, Default)]
pub struct ParticleBins {
    /// Block of each particle, storage order.
    block: Vec<u32>,
    /// Particle indices grouped by block; within a block, storage order.
    order: Vec<u32>,
    /// Particles of block b are `order[block_start[b] .. block_start[b + 1]]`.
    block_start: Vec<u32>,
    /// Scratch cursor of the counting sort.
    cursor: Vec<u32>,
    /// Non-empty blocks of each colour, increasing.
    colour_blocks: [Vec<u32>; COLOURS],
    /// uGIMP half-width of each particle (GIMP only), m.
    half_width: Vec<f64>,
    /// cpGIMP half-widths of each particle per axis (cpGIMP only), m.
    deformed_half_width: Vec<[f64; 3]>,
}

impl ParticleBins {
    /// Bins the particles at `position` (with initial volumes
    /// `initial_volume`, used by GIMP). On failure names the lowest failing
    /// particle. cpGIMP particles get their undeformed domains here (F = I);
    /// [`ParticleBins::build_deformed`] gives them the deformed ones.
    pub fn build(
        &mut self,
        map: &GridMap,
        position: &[[f64; 3]],
        initial_volume: &[f64],
    ) -> Result<(), BinError> {
        self.build_deformed(map, position, initial_volume, &[])
    }

    /// [`ParticleBins::build`] with the particles' deformation gradients
    /// `deformation_gradient` (row-major), from which cpGIMP forms each
    /// particle's half-widths l_p,i = l_p0 F_ii
    /// ([`GridMap::deformed_half_width`]); an empty slice stands for F = I.
    /// The other shape functions ignore it.
    pub fn build_deformed(
        &mut self,
        map: &GridMap,
        position: &[[f64; 3]],
        initial_volume: &[f64],
        deformation_gradient: &[[f64; 9]],
    ) -> Result<(), BinError> {
        let n = position.len();
        if n >= u32::MAX as usize {
            return Err(BinError::TooMany { count: n });
        }
        const OUTSIDE: u32 = u32::MAX;
        self.block.resize(n, 0);
        // By chunks, so that each task is one plain loop.
        self.block
            .par_chunks_mut(PARTICLES_PER_TASK)
            .zip(position.par_chunks(PARTICLES_PER_TASK))
            .for_each(|(blocks, xs)| {
                for (b, x) in blocks.iter_mut().zip(xs) {
                    *b = map.block_of(*x).map_or(OUTSIDE, |b| b as u32);
                }
            });
        if let Some(index) = self.block.iter().position(|&b| b == OUTSIDE) {
            return Err(BinError::Outside {
                index,
                position: position[index],
            });
        }
        if map.shape == ShapeFunction::CpGimp {
            self.half_width.clear();
            self.deformed_half_width.resize(n, [0.0; 3]);
            fill_per_particle(
                &mut self.deformed_half_width,
                initial_volume,
                |index, v0| {
                    let f = deformation_gradient
                        .get(index)
                        .unwrap_or(&crate::particles::IDENTITY);
                    map.deformed_half_width(map.planar_volume(v0, position[index], f), f)
                },
            )?;
        } else if map.shape == ShapeFunction::Gimp {
            self.deformed_half_width.clear();
            self.half_width.resize(n, 0.0);
            fill_per_particle(&mut self.half_width, initial_volume, |index, v0| {
                let f = deformation_gradient
                    .get(index)
                    .unwrap_or(&crate::particles::IDENTITY);
                map.half_width(map.planar_volume(v0, position[index], f))
            })?;
        } else {
            self.half_width.clear();
            self.deformed_half_width.clear();
        }
        // Stable counting sort of the particle indices by block.
        let blocks = map.block_count();
        self.block_start.clear();
        self.block_start.resize(blocks + 1, 0);
        for &b in &self.block {
            self.block_start[b as usize + 1] += 1;
        }
        for b in 0..blocks {
            self.block_start[b + 1] += self.block_start[b];
        }
        self.cursor.clear();
        self.cursor.extend_from_slice(&self.block_start[..blocks]);
        self.order.resize(n, 0);
        for (p, &b) in self.block.iter().enumerate() {
            let c = &mut self.cursor[b as usize];
            self.order[*c as usize] = p as u32;
            *c += 1;
        }
        for list in &mut self.colour_blocks {
            list.clear();
        }
        let [bx, by, bz] = map.blocks;
        let mut b = 0;
        for k in 0..bz {
            for j in 0..by {
                for i in 0..bx {
                    if self.block_start[b + 1] > self.block_start[b] {
                        let colour = (i & 1) | (j & 1) << 1 | (k & 1) << 2;
                        self.colour_blocks[colour].push(b as u32);
                    }
                    b += 1;
                }
            }
        }
        Ok(())
    }

    /// Gives the particles whose identity (`ids`, storage order) lies in
    /// [`first`, `first + count`) a zero GIMP half-width on every axis: the
    /// linear hat of seed 001 eq 16 in GIMP's stencil
    /// ([`gimp::ugimp_1d_padded_into`]), so that they reach only the nodes
    /// of the cell they are in. For the MPM's load-only particles
    /// ([`crate::MpmSolver::set_load_only`]); nothing to do for the shapes
    /// without a half-width.
    pub fn point_particles(&mut self, ids: &[u32], first: u32, count: u32) {
        let point = |id: u32| id >= first && id - first < count;
        // Only one of the two is filled (uGIMP's or cpGIMP's).
        for (l, &id) in self.half_width.iter_mut().zip(ids) {
            if point(id) {
                *l = 0.0;
            }
        }
        for (l, &id) in self.deformed_half_width.iter_mut().zip(ids) {
            if point(id) {
                *l = [0.0; 3];
            }
        }
    }

    /// Bytes of the per-particle arrays: each particle's block and its
    /// place in the lists, 8 bytes (16 with uGIMP's half-widths, 32 with
    /// cpGIMP's three).
    pub fn particle_bytes(&self) -> usize {
        use std::mem::size_of_val;
        size_of_val(self.block.as_slice())
            + size_of_val(self.order.as_slice())
            + size_of_val(self.half_width.as_slice())
            + size_of_val(self.deformed_half_width.as_slice())
    }

    /// Bytes of the per-block arrays (list starts, sort cursor, colour
    /// lists).
    pub fn block_bytes(&self) -> usize {
        use std::mem::size_of_val;
        size_of_val(self.block_start.as_slice())
            + size_of_val(self.cursor.as_slice())
            + self
                .colour_blocks
                .iter()
                .map(|c| size_of_val(c.as_slice()))
                .sum::<usize>()
    }

    /// Number of particles binned.
    pub fn len(&self) -> usize {
        self.block.len()
    }

    /// Whether no particle is binned.
    pub fn is_empty(&self) -> bool {
        self.block.is_empty()
    }

    /// The particles of block `b`, in the order the scatter visits them.
    pub fn block_particles(&self, b: usize) -> &[u32] {
        &self.order[self.block_start[b] as usize..self.block_start[b + 1] as usize]
    }

    /// The non-empty blocks of colour `c`, increasing.
    pub fn colour_blocks(&self, c: usize) -> &[u32] {
        &self.colour_blocks[c]
    }

    /// GIMP half-widths of particle `p` per axis (0 for the shapes that
    /// use none): uGIMP's one l_p on every axis, cpGIMP's deformed l_p,i.
    #[inline(always)]
    fn half_width(&self, p: usize) -> [f64; 3] {
        if let Some(&l) = self.half_width.get(p) {
            [l; 3]
        } else {
            self.deformed_half_width.get(p).copied().unwrap_or([0.0; 3])
        }
    }

    /// Calls `visit(block, particle)` for every particle, colour by colour;
    /// the blocks of one colour run in parallel, the particles of a block
    /// in list order on one thread.
    #[inline]
    fn for_each_coloured(&self, visit: impl Fn(usize, usize) + Sync) {
        let threads = rayon::current_num_threads().max(1);
        for colour in 0..COLOURS {
            let blocks = &self.colour_blocks[colour];
            if blocks.is_empty() {
                continue;
            }
            let min_len = (blocks.len() / (4 * threads)).max(1);
            blocks.par_iter().with_min_len(min_len).for_each(|&b| {
                for &p in self.block_particles(b as usize) {
                    visit(b as usize, p as usize);
                }
            });
        }
    }
}

/// A slice the blocks of one colour write through concurrently, each to
/// node (or particle) ranges that no other block of the colour touches.
#[derive(Clone, Copy)]
struct SharedSlice<'a, T> {
    ptr: *mut T,
    len: usize,
    _borrow: PhantomData<&'a mut [T]>,
}

// SAFETY: the slice is only accessed through `range`, whose callers
// guarantee that concurrently running blocks access disjoint ranges (the
// colouring of the module doc, asserted per particle by
// `check_footprint`).
unsafe impl<T: Send> Send for SharedSlice<'_, T> {}
unsafe impl<T: Send> Sync for SharedSlice<'_, T> {}

impl<'a, T> SharedSlice<'a, T> {
    fn new(s: &'a mut [T]) -> Self {
        Self {
            ptr: s.as_mut_ptr(),
            len: s.len(),
            _borrow: PhantomData,
        }
    }

    /// `start .. start + n` of the slice, bounds-checked.
    ///
    /// # Safety
    /// No other thread reads or writes the range while the borrow lives.
    #[inline(always)]
    #[allow(clippy::mut_from_ref)]
    unsafe fn range(&self, start: usize, n: usize) -> &mut [T] {
        assert!(
            start <= self.len && n <= self.len - start,
            "node row out of the lattice"
        );
        // SAFETY: in bounds (just checked); exclusive by the caller's
        // guarantee.
        unsafe { std::slice::from_raw_parts_mut(self.ptr.add(start), n) }
    }
}

/// A pass generic over the stencil's node counts per axis.
trait StencilPass {
    fn run<const NX: usize, const NY: usize, const NZ: usize>(self);
}

/// Runs `pass` monomorphised for the node counts of `map`.
fn dispatch(map: &GridMap, pass: impl StencilPass) {
    match map.nodes_per_axis {
        [2, 2, 2] => pass.run::<2, 2, 2>(),
        [2, 2, 1] => pass.run::<2, 2, 1>(),
        [2, 1, 2] => pass.run::<2, 1, 2>(),
        [1, 2, 2] => pass.run::<1, 2, 2>(),
        [2, 1, 1] => pass.run::<2, 1, 1>(),
        [1, 2, 1] => pass.run::<1, 2, 1>(),
        [1, 1, 2] => pass.run::<1, 1, 2>(),
        [3, 3, 3] => pass.run::<3, 3, 3>(),
        [3, 3, 1] => pass.run::<3, 3, 1>(),
        [3, 1, 3] => pass.run::<3, 1, 3>(),
        [1, 3, 3] => pass.run::<1, 3, 3>(),
        [3, 1, 1] => pass.run::<3, 1, 1>(),
        [1, 3, 1] => pass.run::<1, 3, 1>(),
        [1, 1, 3] => pass.run::<1, 1, 3>(),
        [1, 1, 1] => pass.run::<1, 1, 1>(),
        other => unreachable!("stencil node counts {other:?}"),
    }
}

/// Panics unless the stencil at `offset` lies in the footprint of block `b`
/// (the colouring's disjointness rests on it).
#[inline(always)]
fn check_footprint(map: &GridMap, offset: [usize; 3], b: usize) {
    assert_eq!(
        map.block_of_offsets(offset),
        b,
        "particle stencil outside its block"
    );
}

/// The particle quantities P2G reads.
#[derive(Debug, Clone, Copy)]
pub struct P2gParticles<'a> {
    /// Positions x_p, m.
    pub position: &'a [[f64; 3]],
    /// Masses m_p, kg.
    pub mass: &'a [f64],
    /// Velocities v_p, m/s.
    pub velocity: &'a [[f64; 3]],
    /// Volumes V_p, m³.
    pub volume: &'a [f64],
    /// Cauchy stresses σ_p, Voigt (xx, yy, zz, yz, xz, xy), Pa.
    pub stress: &'a [[f64; 6]],
}

/// Which sums a P2G pass forms.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum P2gSums {
    /// m_I and p_I (eqs 21, 18).
    MassMomentum,
    /// f_I^int (eq 19).
    Force,
    /// All three in one visit.
    All,
}

/// P2G (coloured scatter, see the module doc): zeroes the sums `which`
/// of `nodes` and adds m_I = Σ N_Ip m_p, p_I = Σ N_Ip m_p v_p and
/// f_I^int = −Σ V_p σ_p ∇N_Ip into `nodes.mass`, `nodes.momentum` and
/// `nodes.force`.
pub fn p2g(
    map: &GridMap,
    bins: &ParticleBins,
    particles: P2gParticles,
    nodes: &mut GridNodes,
    which: P2gSums,
) {
    let (mom, force) = match which {
        P2gSums::MassMomentum => (true, false),
        P2gSums::Force => (false, true),
        P2gSums::All => (true, true),
    };
    if mom {
        zero(&mut nodes.mass, 0.0);
        zero(&mut nodes.momentum, [0.0; 3]);
    }
    if force {
        zero(&mut nodes.force, [0.0; 3]);
    }
    let targets = P2gTargets {
        mass: SharedSlice::new(&mut nodes.mass),
        momentum: SharedSlice::new(&mut nodes.momentum),
        force: SharedSlice::new(&mut nodes.force),
    };
    match (mom, force) {
        (true, true) => dispatch(
            map,
            P2g::<true, true> {
                map,
                bins,
                particles,
                targets,
            },
        ),
        (true, false) => dispatch(
            map,
            P2g::<true, false> {
                map,
                bins,
                particles,
                targets,
            },
        ),
        _ => dispatch(
            map,
            P2g::<false, true> {
                map,
                bins,
                particles,
                targets,
            },
        ),
    }
}

/// Fills `v` with `value` in parallel.
fn zero<T: Copy + Send + Sync>(v: &mut [T], value: T) {
    v.par_chunks_mut(4096).for_each(|c| c.fill(value));
}

#[derive(Clone, Copy)]
struct P2gTargets<'a> {
    mass: SharedSlice<'a, f64>,
    momentum: SharedSlice<'a, [f64; 3]>,
    force: SharedSlice<'a, [f64; 3]>,
}

struct P2g<'a, const MOM: bool, const FORCE: bool> {
    map: &'a GridMap,
    bins: &'a ParticleBins,
    particles: P2gParticles<'a>,
    targets: P2gTargets<'a>,
}

impl<const MOM: bool, const FORCE: bool> StencilPass for P2g<'_, MOM, FORCE> {
    fn run<const NX: usize, const NY: usize, const NZ: usize>(self) {
        let Self {
            map,
            bins,
            particles: ps,
            targets: t,
        } = self;
        bins.for_each_coloured(|block, p| {
            let s = map.stencil::<NX, NY, NZ>(ps.position[p], bins.half_width(p));
            check_footprint(map, s.offset, block);
            let m = ps.mass[p];
            let v = ps.velocity[p];
            let mv = [m * v[0], m * v[1], m * v[2]];
            let vol = ps.volume[p];
            let sg = ps.stress[p];
            // V_p σ_p, Voigt.
            let vs: [f64; 6] = std::array::from_fn(|k| vol * sg[k]);
            // The hoop force per unit weight, V_p σ_θθ / r_p (zero on a
            // Cartesian grid). V_p ∝ r_p, so the ratio stays finite as
            // r_p → 0; a particle on the axis itself has no ring.
            let hoop = if map.axisymmetric && ps.position[p][0] > 0.0 {
                vol / ps.position[p][0] * sg[2]
            } else {
                0.0
            };
            for c in 0..NZ {
                for b in 0..NY {
                    let row = s.row(b, c);
                    let start = map.row_start(s.base, b, c);
                    // SAFETY: the stencil lies in its block's footprint
                    // (checked above), and blocks of one colour have
                    // disjoint footprints, so no other thread touches these
                    // nodes during this colour.
                    let (mr, pr, fr) = unsafe {
                        (
                            t.mass.range(start, if MOM { NX } else { 0 }),
                            t.momentum.range(start, if MOM { NX } else { 0 }),
                            t.force.range(start, if FORCE { NX } else { 0 }),
                        )
                    };
                    for a in 0..NX {
                        let (w, g) = row.node(s.x.w[a], s.x.g[a]);
                        if MOM {
                            mr[a] += w * m;
                            for k in 0..3 {
                                pr[a][k] += w * mv[k];
                            }
                        }
                        if FORCE {
                            fr[a][0] -= vs[0] * g[0] + vs[5] * g[1] + vs[4] * g[2];
                            if map.axisymmetric {
                                fr[a][0] -= hoop * w;
                            }
                            fr[a][1] -= vs[5] * g[0] + vs[1] * g[1] + vs[3] * g[2];
                            fr[a][2] -= vs[4] * g[0] + vs[3] * g[1] + vs[2] * g[2];
                        }
                    }
                }
            }
        });
    }
}

#[cfg(test)]
#[allow(clippy::needless_range_loop)]
mod tests;
