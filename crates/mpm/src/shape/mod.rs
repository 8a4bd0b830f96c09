//! Shape functions N_I(x_p) of the background grid and their gradients
//! ∇N_I(x_p): the S_ip and G_ip of seed 000 eqs 12–17 and the N_Ip of seed
//! 001 eqs 15–30.
//!
//! Every shape function here is a tensor product of one-dimensional weights,
//! N_I(x) = φ(x − x_i) φ(y − y_j) φ(z − z_k), with the 1D weight of each
//! family in its own module:
//!
//! - [`linear`]: the hat function, i.e. the 8-node hexahedron of seed 001
//!   eq 16 (2 nodes per axis);
//! - [`gimp`]: the uGIMP weight of Bardenhagen & Kober 2004 (seed 000
//!   ref 13), the hat function averaged over a particle of half-width l_p
//!   (up to 3 nodes per axis), and its contiguous-particle variant cpGIMP,
//!   whose half-widths follow the deformation (l_p,i = l_p0,i F_ii);
//! - [`bspline`]: the uniform quadratic B-spline (3 nodes per axis).
//!
//! Node indexing is that of [`crate::nodes`]: global node i at
//! x_min + i·Δx. An inactive direction (one cell) has the single node 0 with
//! weight 1 and gradient 0, so the stencil of a 2D level has 4 (linear) or
//! up to 9 nodes and that of a 1D level 2 or up to 3.
//!
//! Evaluation writes into a [`ShapeStencil`] of fixed capacity
//! ([`MAX_STENCIL_NODES`] = 27) that the caller reuses: nothing is
//! allocated per particle.

pub mod bspline;
pub mod gimp;
pub mod linear;

use brisance_core::UniformGridGeometry;
use serde::{Deserialize, Serialize};

/// Most nodes a particle can touch: 3 per axis in 3D.
pub const MAX_STENCIL_NODES: usize = 27;

/// Which interpolation the background grid uses.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default, Serialize, Deserialize)]
pub enum ShapeFunction {
    /// Tri-linear hat functions, the 8-node hexahedron of seed 001 eq 16.
    #[default]
    Linear,
    /// Uniform GIMP (Bardenhagen & Kober 2004, seed 000 ref 13): the hat
    /// function averaged over the particle's undeformed box.
    Gimp,
    /// Contiguous-particle GIMP (Bardenhagen & Kober 2004; Wallstedt &
    /// Guilkey 2008, J. Comput. Phys. 227:9628): the uGIMP average over a
    /// box whose half-widths follow the deformation, l_p,i = l_p0,i F_ii
    /// ([`gimp::cpgimp_half_width`]), so that the particle domains keep
    /// tiling the body as it stretches or compresses.
    CpGimp,
    /// Quadratic B-spline, C¹ with a support of 3 nodes per axis.
    QuadraticBSpline,
}

/// Why a stencil cannot be evaluated.
#[derive(Debug, Clone, Copy, PartialEq, thiserror::Error)]
pub enum ShapeError {
    /// The particle position has a NaN or infinite coordinate.
    #[error("particle position {position:?} m is not finite")]
    NonFinitePosition {
        /// The offending position, m.
        position: [f64; 3],
    },
    /// A GIMP half-width outside (0, Δx/2] along an active direction (a
    /// few ulps above Δx/2 are taken as Δx/2, see
    /// [`gimp::admissible_half_width`]).
    #[error(
        "GIMP particle half-width {half_width} m along axis {axis} must lie in (0, {max}] \
         (half the cell width)"
    )]
    HalfWidth {
        /// The axis, 0 = x.
        axis: usize,
        /// The half-width given, m.
        half_width: f64,
        /// Half the cell width along that axis, m.
        max: f64,
    },
}

/// The weights of one particle against the nodes of one axis: nodes
/// `first .. first + len`, weight φ and derivative dφ/dx (1/m).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Stencil1d {
    /// Global index of the first node touched.
    pub first: isize,
    /// Number of nodes touched (1 to 3).
    pub len: usize,
    /// φ(x_p − x_i) for each node.
    pub weight: [f64; 3],
    /// dφ/dx at x_p for each node, 1/m.
    pub gradient: [f64; 3],
}

impl Stencil1d {
    /// The stencil of an inactive direction: node 0, weight 1, gradient 0.
    pub const INACTIVE: Self = Self {
        first: 0,
        len: 1,
        weight: [1.0, 0.0, 0.0],
        gradient: [0.0; 3],
    };
}

/// The nodes one particle touches, with N_I(x_p) and ∇N_I(x_p), in
/// x-fastest order. Fixed capacity, reused between particles.
#[derive(Debug, Clone, PartialEq)]
pub struct ShapeStencil {
    len: usize,
    nodes: [[isize; 3]; MAX_STENCIL_NODES],
    weights: [f64; MAX_STENCIL_NODES],
    gradients: [[f64; 3]; MAX_STENCIL_NODES],
}

impl Default for ShapeStencil {
    fn default() -> Self {
        Self::new()
    }
}

impl ShapeStencil {
    /// An empty stencil.
    pub const fn new() -> Self {
        Self {
            len: 0,
            nodes: [[0; 3]; MAX_STENCIL_NODES],
            weights: [0.0; MAX_STENCIL_NODES],
            gradients: [[0.0; 3]; MAX_STENCIL_NODES],
        }
    }

    /// Number of nodes touched.
    pub fn len(&self) -> usize {
        self.len
    }

    /// Whether no node is touched (only before the first evaluation).
    pub fn is_empty(&self) -> bool {
        self.len == 0
    }

    /// Global indices (i, j, k) of the nodes touched.
    pub fn nodes(&self) -> &[[isize; 3]] {
        &self.nodes[..self.len]
    }

    /// N_I(x_p), dimensionless.
    pub fn weights(&self) -> &[f64] {
        &self.weights[..self.len]
    }

    /// ∇N_I(x_p), 1/m.
    pub fn gradients(&self) -> &[[f64; 3]] {
        &self.gradients[..self.len]
    }

    /// (node, N_I, ∇N_I) triples.
    pub fn iter(&self) -> impl Iterator<Item = ([isize; 3], f64, [f64; 3])> + '_ {
        (0..self.len).map(|n| (self.nodes[n], self.weights[n], self.gradients[n]))
    }

    /// Fills the stencil with the tensor product of three 1D stencils:
    /// N_I = φx φy φz, ∇N_I = (φx' φy φz, φx φy' φz, φx φy φz'), each
    /// product formed as [`TensorRow`] forms it (the transfer kernels
    /// of [`crate::transfer`] give the same bits).
    fn set_tensor_product(&mut self, axes: &[Stencil1d; 3]) {
        let [sx, sy, sz] = axes;
        let mut n = 0;
        for c in 0..sz.len {
            for b in 0..sy.len {
                let yz = TensorRow::new(sy.weight[b], sy.gradient[b], sz.weight[c], sz.gradient[c]);
                for a in 0..sx.len {
                    self.nodes[n] = [
                        sx.first + a as isize,
                        sy.first + b as isize,
                        sz.first + c as isize,
                    ];
                    let (w, grad) = yz.node(sx.weight[a], sx.gradient[a]);
                    self.weights[n] = w;
                    self.gradients[n] = grad;
                    n += 1;
                }
            }
        }
        self.len = n;
    }
}

/// The y–z factors of one row of a tensor-product stencil: with φy, φy′
/// of node j and φz, φz′ of node k, the products φy φz, φy′ φz and φy φz′
/// that every node (i, j, k) of the row shares.
#[derive(Debug, Clone, Copy)]
pub struct TensorRow {
    wyz: f64,
    gyz: f64,
    wygz: f64,
}

impl TensorRow {
    /// The factors of the row of y-weight `wy` (derivative `gy`) and
    /// z-weight `wz` (derivative `gz`).
    #[inline(always)]
    pub fn new(wy: f64, gy: f64, wz: f64, gz: f64) -> Self {
        Self {
            wyz: wy * wz,
            gyz: gy * wz,
            wygz: wy * gz,
        }
    }

    /// N = φx (φy φz) and ∇N = (φx′ (φy φz), φx (φy′ φz), φx (φy φz′)) of
    /// the node of x-weight `wx` and derivative `gx` on this row.
    #[inline(always)]
    pub fn node(&self, wx: f64, gx: f64) -> (f64, [f64; 3]) {
        (
            wx * self.wyz,
            [gx * self.wyz, wx * self.gyz, wx * self.wygz],
        )
    }

    /// N alone, for transfers that need no gradient.
    #[inline(always)]
    pub fn weight(&self, wx: f64) -> f64 {
        wx * self.wyz
    }
}

/// ⌊x⌋ for every finite x, without the libm call that `f64::floor` is on
/// x86-64 targets without SSE4.1: adding and subtracting 1.5·2⁵² rounds x
/// to the nearest integer (exact for |x| < 2⁵¹), which is then corrected
/// down where it rounded up. Larger magnitudes (never a grid coordinate)
/// take the library floor.
#[inline(always)]
pub fn floor(x: f64) -> f64 {
    const ROUND: f64 = 6_755_399_441_055_744.0;
    if x.abs() < 2_251_799_813_685_248.0 {
        let r = (x + ROUND) - ROUND;
        if r > x {
            r - 1.0
        } else {
            r
        }
    } else {
        x.floor()
    }
}

impl ShapeFunction {
    /// All variants, for tests and listings.
    pub const ALL: [ShapeFunction; 4] = [
        ShapeFunction::Linear,
        ShapeFunction::Gimp,
        ShapeFunction::CpGimp,
        ShapeFunction::QuadraticBSpline,
    ];

    /// Whether the shape function averages over a particle box of
    /// half-width l_p (uGIMP and cpGIMP).
    #[inline(always)]
    pub fn is_gimp(self) -> bool {
        matches!(self, ShapeFunction::Gimp | ShapeFunction::CpGimp)
    }

    /// Ghost node layers a patch needs so that every particle in its
    /// interior cells finds all its nodes allocated: 0 for the linear
    /// function (a particle in cell i touches nodes i and i + 1), 1 for GIMP
    /// and the B-spline (which reach one node further).
    pub fn required_ghost_nodes(self) -> usize {
        match self {
            ShapeFunction::Linear => 0,
            ShapeFunction::Gimp | ShapeFunction::CpGimp | ShapeFunction::QuadraticBSpline => 1,
        }
    }

    /// Most nodes one particle touches along an active axis.
    pub fn nodes_per_axis(self) -> usize {
        match self {
            ShapeFunction::Linear => 2,
            ShapeFunction::Gimp | ShapeFunction::CpGimp | ShapeFunction::QuadraticBSpline => 3,
        }
    }

    /// The default uGIMP particle half-width l_p = Δx/(2·ppc) per axis: the
    /// particles generated `ppc` per cell per direction then tile the cell
    /// without gap or overlap. Inactive directions get Δx/2 (unused).
    pub fn default_half_width(grid: &UniformGridGeometry, ppc: usize) -> [f64; 3] {
        let ppc = ppc.max(1) as f64;
        std::array::from_fn(|d| {
            if grid.cells[d] > 1 {
                grid.spacing[d] / (2.0 * ppc)
            } else {
                0.5 * grid.spacing[d]
            }
        })
    }

    /// Evaluates N_I(x_p) and ∇N_I(x_p) for the particle at `position` (m)
    /// into `out`. `half_width` (m) is the particle half-width l_p per axis,
    /// used by [`ShapeFunction::Gimp`] and [`ShapeFunction::CpGimp`] only (it
    /// must lie in (0, Δx/2] along active axes, up to the round-off of
    /// [`gimp::admissible_half_width`]) and ignored by the others. For
    /// cpGIMP it is the deformed half-width ([`gimp::cpgimp_half_width`]).
    ///
    /// Positions outside the domain are not rejected: they give nodes
    /// outside 0 ..= n, which the caller must handle (a particle that left
    /// the grid).
    #[inline]
    pub fn evaluate(
        self,
        grid: &UniformGridGeometry,
        position: [f64; 3],
        half_width: [f64; 3],
        out: &mut ShapeStencil,
    ) -> Result<(), ShapeError> {
        if position.iter().any(|x| !x.is_finite()) {
            return Err(ShapeError::NonFinitePosition { position });
        }
        let mut axes = [Stencil1d::INACTIVE; 3];
        for d in 0..3 {
            if grid.cells[d] <= 1 {
                continue;
            }
            let h = grid.spacing[d];
            let xi = (position[d] - grid.origin[d]) / h;
            axes[d] = match self {
                ShapeFunction::Linear => linear::hat_1d(xi, h, grid.cells[d]),
                ShapeFunction::QuadraticBSpline => bspline::quadratic_bspline_1d(xi, h),
                ShapeFunction::Gimp | ShapeFunction::CpGimp => {
                    let lp = half_width[d];
                    let Some(lp) = gimp::admissible_half_width(lp, h) else {
                        return Err(ShapeError::HalfWidth {
                            axis: d,
                            half_width: lp,
                            max: 0.5 * h,
                        });
                    };
                    gimp::ugimp_1d(xi, h, lp)
                }
            };
        }
        out.set_tensor_product(&axes);
        Ok(())
    }
}

#[cfg(test)]
mod tests;
