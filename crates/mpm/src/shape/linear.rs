//! The linear (hat) shape function: the 8-node hexahedron of seed 001 eq 16,
//!
//! N_Ip = (1/8)(1 + ξ_p ξ_I)(1 + η_p η_I)(1 + ζ_p ζ_I),  I = 1 … 8,
//!
//! with (ξ_I, η_I, ζ_I) = ±1 at the cell's corners and (ξ_p, η_p, ζ_p) ∈
//! [−1, 1]³ the particle's natural coordinates in the cell that contains it
//! (N_Ip = 0 for nodes of other cells). On a uniform grid each factor is the
//! 1D hat function: with f = (x_p − x_i)/Δx ∈ [0, 1) the particle's fraction
//! across cell i, ξ_p = 2f − 1 and
//!
//! (1 + ξ_p ξ_I)/2 = 1 − f for node i (ξ_I = −1), f for node i + 1 (ξ_I = +1),
//!
//! with derivatives ξ_I/2 · dξ/dx = ∓1/Δx. The gradient jumps across cell
//! faces (the cell-crossing error GIMP and the B-spline remove); a particle
//! exactly on an interior node takes the gradient of the cell above it.

use super::{floor, Stencil1d};

/// The 1D hat weights of seed 001 eq 16 for a particle at grid coordinate
/// `xi` = (x_p − x_min)/Δx on an axis of `cells` cells of width `h` (m):
/// nodes i and i + 1 of the cell i = ⌊xi⌋, weights (1 − f, f), derivatives
/// (−1/h, 1/h) in 1/m. A particle exactly on the upper domain boundary
/// belongs to the last cell (as in `UniformGridGeometry::cell_containing`),
/// so it never touches a node beyond n.
#[inline]
pub fn hat_1d(xi: f64, h: f64, cells: usize) -> Stencil1d {
    hat_1d_scaled(xi, 1.0 / h, cells)
}

/// [`hat_1d`] with the inverse cell width `inv_h` = 1/Δx (1/m) given, so
/// that a kernel evaluating many particles divides once per axis.
#[inline]
pub fn hat_1d_scaled(xi: f64, inv_h: f64, cells: usize) -> Stencil1d {
    let mut out = Stencil1d {
        first: 0,
        len: 2,
        weight: [0.0; 3],
        gradient: [0.0; 3],
    };
    out.first = hat_1d_into(xi, inv_h, cells, &mut out.weight, &mut out.gradient);
    out
}

/// The two weights and derivatives of [`hat_1d_scaled`] written into
/// `weight[..2]` and `gradient[..2]`; returns the first node. The form the
/// transfer kernels evaluate in place.
#[inline(always)]
pub fn hat_1d_into(
    xi: f64,
    inv_h: f64,
    cells: usize,
    weight: &mut [f64],
    gradient: &mut [f64],
) -> isize {
    let mut cell = floor(xi);
    if xi == cells as f64 {
        cell -= 1.0;
    }
    let f = xi - cell;
    weight[0] = 1.0 - f;
    weight[1] = f;
    gradient[0] = -inv_h;
    gradient[1] = inv_h;
    cell as isize
}
