//! Particle-to-grid (P2G) and grid-to-particle (G2P) transfers of seed 001
//! eqs 18–21, 24–26 (seed 000 eqs 12, 16–17).
//!
//! # Deterministic P2G by gathering
//!
//! The textbook P2G is a scatter: every particle adds N_Ip m_p, N_Ip m_p v_p
//! and −V_p σ_p ∇N_Ip into its nodes. Done in parallel that is a data race
//! unless it uses atomics or per-thread copies, and both make the
//! floating-point summation order depend on the scheduling, so the bits
//! change with the thread count. Here P2G is a *gather* instead:
//!
//! 1. The particles are kept sorted by cell (a stable counting sort, redone
//!    every step), and `cell_start[c] .. cell_start[c + 1]` are the
//!    particles of cell c.
//! 2. Each node I = (i, j, k) is computed by exactly one task (rayon over
//!    x-rows of nodes). It visits the cells whose particles can touch it —
//!    along an active axis cells i − 1, i for the linear function and
//!    i − 2 … i + 1 for GIMP and the B-spline, clipped to the grid — in
//!    increasing linear cell index, and within a cell the particles in their
//!    sorted order.
//! 3. For each (node, particle) pair the weight and gradient are the
//!    tensor products N = φx φy φz, ∇N = (φx′ φy φz, φx φy′ φz, φx φy φz′)
//!    of the particle's three 1D stencils (the public 1D kernels of
//!    [`crate::shape`]), formed in the same order as
//!    [`crate::ShapeStencil`] forms them, so the values are bit-identical to
//!    those of [`crate::ShapeFunction::evaluate`]. The 1D stencils are
//!    computed once per particle per step into a reused buffer
//!    ([`compute_stencils`]): recomputing them per pair would give the same
//!    bits at several times the cost.
//!
//! Every node's sums are therefore taken in one fixed order that depends
//! only on the particle positions, never on how the nodes are split among
//! threads: the result is the same on 1 or 64 threads, without atomics.
//!
//! G2P (eqs 24, 25) and the velocity gradient are naturally parallel over
//! particles: each particle reads its nodes and writes only itself.

use crate::grid_nodes::NodeLattice;
use crate::shape::{bspline, gimp, linear, ShapeError, Stencil1d};
use crate::ShapeFunction;
use brisance_core::UniformGridGeometry;
use rayon::prelude::*;

/// The 1D stencils of one particle, one per axis.
pub type AxisStencils = [Stencil1d; 3];

/// The 1D stencil of `shape` along axis `d` for a particle at coordinate
/// `x` (m) with GIMP half-width `lp` (m): the kernels of [`crate::shape`],
/// dispatched as [`ShapeFunction::evaluate`] does.
#[inline]
pub fn axis_stencil(
    shape: ShapeFunction,
    grid: &UniformGridGeometry,
    d: usize,
    x: f64,
    lp: f64,
) -> Result<Stencil1d, ShapeError> {
    if grid.cells[d] <= 1 {
        return Ok(Stencil1d::INACTIVE);
    }
    let h = grid.spacing[d];
    let xi = (x - grid.origin[d]) / h;
    Ok(match shape {
        ShapeFunction::Linear => linear::hat_1d(xi, h, grid.cells[d]),
        ShapeFunction::QuadraticBSpline => bspline::quadratic_bspline_1d(xi, h),
        ShapeFunction::Gimp => {
            if !(lp > 0.0 && lp <= 0.5 * h) {
                return Err(ShapeError::HalfWidth {
                    axis: d,
                    half_width: lp,
                    max: 0.5 * h,
                });
            }
            gimp::ugimp_1d(xi, h, lp)
        }
    })
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

/// Fills `out` with the 1D stencils of every particle (parallel over
/// particles). On failure returns the lowest failing particle index and the
/// reason.
pub fn compute_stencils(
    shape: ShapeFunction,
    grid: &UniformGridGeometry,
    positions: &[[f64; 3]],
    initial_volume: &[f64],
    out: &mut Vec<AxisStencils>,
) -> Result<(), (usize, ShapeError)> {
    out.resize(positions.len(), [Stencil1d::INACTIVE; 3]);
    let first_error = out
        .par_iter_mut()
        .zip(positions.par_iter().zip(initial_volume.par_iter()))
        .enumerate()
        .filter_map(|(p, (s, (x, &v0)))| {
            if x.iter().any(|c| !c.is_finite()) {
                return Some((p, ShapeError::NonFinitePosition { position: *x }));
            }
            let lp = if shape == ShapeFunction::Gimp {
                gimp_half_width(grid, v0)
            } else {
                0.0
            };
            for d in 0..3 {
                match axis_stencil(shape, grid, d, x[d], lp) {
                    Ok(a) => s[d] = a,
                    Err(e) => return Some((p, e)),
                }
            }
            None
        })
        .min_by_key(|(p, _)| *p);
    match first_error {
        Some(e) => Err(e),
        None => Ok(()),
    }
}

/// Counts particles per cell of the sorted cell indices `cells` into
/// `cell_start` (length cell_count + 1): particles of cell c are
/// `cell_start[c] .. cell_start[c + 1]`.
pub fn build_cell_start(cells: &[usize], cell_count: usize, cell_start: &mut Vec<usize>) {
    cell_start.clear();
    cell_start.resize(cell_count + 1, 0);
    for &c in cells {
        cell_start[c + 1] += 1;
    }
    for c in 0..cell_count {
        cell_start[c + 1] += cell_start[c];
    }
}

/// What a gather needs to find the particles of a node.
#[derive(Debug, Clone, Copy)]
pub struct GatherContext<'a> {
    /// The grid.
    pub grid: &'a UniformGridGeometry,
    /// The node lattice.
    pub lattice: &'a NodeLattice,
    /// The shape function (for its reach).
    pub shape: ShapeFunction,
    /// First particle of each cell, cell_count + 1 entries.
    pub cell_start: &'a [usize],
    /// 1D stencils of every particle.
    pub stencils: &'a [AxisStencils],
}

/// Weight and gradient of one 1D stencil at global node `i`, if it touches
/// it.
#[inline]
fn weight_at(s: &Stencil1d, i: isize) -> Option<(f64, f64)> {
    let k = i - s.first;
    if k >= 0 && (k as usize) < s.len {
        Some((s.weight[k as usize], s.gradient[k as usize]))
    } else {
        None
    }
}

impl GatherContext<'_> {
    /// The range of cells (inclusive) along `d` whose particles can touch
    /// node `i`.
    #[inline]
    fn cell_range(&self, d: usize, i: isize) -> Option<(usize, usize)> {
        let n = self.grid.cells[d] as isize;
        if n <= 1 {
            return Some((0, 0));
        }
        // A particle of cell c touches nodes c − lo ..= c + hi.
        let (lo, hi) = match self.shape {
            ShapeFunction::Linear => (0, 1),
            ShapeFunction::Gimp | ShapeFunction::QuadraticBSpline => (1, 2),
        };
        let a = (i - hi).max(0);
        let b = (i + lo).min(n - 1);
        (a <= b).then_some((a as usize, b as usize))
    }

    /// For every node of `out` (parallel over x-rows of nodes), resets it
    /// to `T::default()` and calls `add(value, p, N_Ip, ∇N_Ip)` for every
    /// particle p that touches it, in the fixed order of the module doc.
    pub fn gather<T, F>(&self, out: &mut [T], add: F)
    where
        T: Default + Send,
        F: Fn(&mut T, usize, f64, [f64; 3]) + Sync,
    {
        let nx = self.lattice.dims[0];
        let cells = self.grid.cells;
        out.par_chunks_mut(nx)
            .enumerate()
            .for_each(|(row, values)| {
                for (a, value) in values.iter_mut().enumerate() {
                    *value = T::default();
                    let node = self.lattice.node(row * nx + a);
                    let (Some(rx), Some(ry), Some(rz)) = (
                        self.cell_range(0, node[0]),
                        self.cell_range(1, node[1]),
                        self.cell_range(2, node[2]),
                    ) else {
                        continue;
                    };
                    for cz in rz.0..=rz.1 {
                        for cy in ry.0..=ry.1 {
                            // Cells rx.0 ..= rx.1 of one x-row are consecutive,
                            // so their particles are one contiguous range.
                            let c0 = rx.0 + cells[0] * (cy + cells[1] * cz);
                            let c1 = rx.1 + cells[0] * (cy + cells[1] * cz);
                            for p in self.cell_start[c0]..self.cell_start[c1 + 1] {
                                let [sx, sy, sz] = &self.stencils[p];
                                let (Some((wx, gx)), Some((wy, gy)), Some((wz, gz))) = (
                                    weight_at(sx, node[0]),
                                    weight_at(sy, node[1]),
                                    weight_at(sz, node[2]),
                                ) else {
                                    continue;
                                };
                                let w = wx * wy * wz;
                                let grad = [gx * wy * wz, wx * gy * wz, wx * wy * gz];
                                add(value, p, w, grad);
                            }
                        }
                    }
                }
            });
    }
}

/// Calls `f(node storage index, N_Ip, ∇N_Ip)` for every node particle `s`
/// touches, x fastest (the order of [`crate::ShapeStencil`]).
#[inline]
pub fn for_each_node(
    lattice: &NodeLattice,
    s: &AxisStencils,
    mut f: impl FnMut(usize, f64, [f64; 3]),
) {
    let [sx, sy, sz] = s;
    for c in 0..sz.len {
        for b in 0..sy.len {
            for a in 0..sx.len {
                let (wx, wy, wz) = (sx.weight[a], sy.weight[b], sz.weight[c]);
                let node = [
                    sx.first + a as isize,
                    sy.first + b as isize,
                    sz.first + c as isize,
                ];
                if let Some(idx) = lattice.index(node) {
                    let grad = [
                        sx.gradient[a] * wy * wz,
                        wx * sy.gradient[b] * wz,
                        wx * wy * sz.gradient[c],
                    ];
                    f(idx, wx * wy * wz, grad);
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ShapeStencil;

    fn grid() -> UniformGridGeometry {
        UniformGridGeometry {
            origin: [0.0; 3],
            spacing: [0.5, 0.25, 1.0],
            cells: [6, 5, 1],
        }
    }

    /// Positions, initial volumes, stencils, cell starts and lattice.
    type Setup = (
        Vec<[f64; 3]>,
        Vec<f64>,
        Vec<AxisStencils>,
        Vec<usize>,
        NodeLattice,
    );

    /// Sorted particles of a few cells, their stencils and cell starts.
    fn setup(shape: ShapeFunction) -> Setup {
        let g = grid();
        let mut xs: Vec<[f64; 3]> = (0..40)
            .map(|k| {
                let t = k as f64 * 0.618_033_988_75;
                [
                    (t.fract() * 3.0).min(2.999),
                    ((t * 7.3).fract() * 1.25).min(1.249),
                    0.5,
                ]
            })
            .collect();
        xs.sort_by_key(|x| g.linear_index(g.cell_containing(*x).unwrap()));
        let v0 = vec![0.5 * 0.25 / 4.0; xs.len()];
        let mut st = Vec::new();
        compute_stencils(shape, &g, &xs, &v0, &mut st).unwrap();
        let cells: Vec<usize> = xs
            .iter()
            .map(|x| g.linear_index(g.cell_containing(*x).unwrap()))
            .collect();
        let mut cs = Vec::new();
        build_cell_start(&cells, g.cell_count(), &mut cs);
        (xs, v0, st, cs, NodeLattice::new(&g, shape))
    }

    #[test]
    fn gathered_weights_equal_the_scattered_stencil_weights_bit_for_bit() {
        let g = grid();
        for shape in ShapeFunction::ALL {
            let (xs, v0, st, cs, lat) = setup(shape);
            let ctx = GatherContext {
                grid: &g,
                lattice: &lat,
                shape,
                cell_start: &cs,
                stencils: &st,
            };
            // Node → list of (particle, N, ∇N) from the gather.
            let mut gathered: Vec<Vec<(usize, f64, [f64; 3])>> = vec![Vec::new(); lat.len()];
            ctx.gather(&mut gathered, |v, p, w, grad| v.push((p, w, grad)));
            // The same pairs from ShapeFunction::evaluate, particle by particle.
            let mut scattered: Vec<Vec<(usize, f64, [f64; 3])>> = vec![Vec::new(); lat.len()];
            let mut stencil = ShapeStencil::new();
            for (p, x) in xs.iter().enumerate() {
                let lp = gimp_half_width(&g, v0[p]);
                shape.evaluate(&g, *x, [lp; 3], &mut stencil).unwrap();
                for (node, w, grad) in stencil.iter() {
                    let idx = lat.index(node).unwrap();
                    scattered[idx].push((p, w, grad));
                }
            }
            assert_eq!(gathered, scattered, "{shape:?}");
        }
    }

    #[test]
    fn gathered_mass_is_identical_on_one_and_three_threads() {
        let g = grid();
        let (_, _, st, cs, lat) = setup(ShapeFunction::QuadraticBSpline);
        let run = |threads: usize| {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            pool.install(|| {
                let ctx = GatherContext {
                    grid: &g,
                    lattice: &lat,
                    shape: ShapeFunction::QuadraticBSpline,
                    cell_start: &cs,
                    stencils: &st,
                };
                let mut m = vec![0.0f64; lat.len()];
                ctx.gather(&mut m, |v, p, w, _| *v += w * (1.0 + 0.1 * p as f64));
                m
            })
        };
        let a = run(1);
        assert_eq!(a, run(3));
        let total: f64 = a.iter().sum();
        let expected: f64 = (0..40).map(|p| 1.0 + 0.1 * p as f64).sum();
        assert!((total - expected).abs() < 1e-12 * expected);
    }
}
