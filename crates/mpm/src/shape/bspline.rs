//! The quadratic B-spline shape function on the node-centred grid.
//!
//! The 1D weight of node i for a particle at distance r = x_p − x_i, in
//! units of the cell width (ξ = r/Δx), is the uniform quadratic B-spline
//! centred on the node:
//!
//! φ(ξ) = 3/4 − ξ²           for |ξ| ≤ 1/2,
//! φ(ξ) = (1/2)(3/2 − |ξ|)²  for 1/2 ≤ |ξ| ≤ 3/2,
//! φ(ξ) = 0                  otherwise,
//!
//! C¹ with support 3Δx, so a particle touches the nearest node c = ⌊ξ_p +
//! 1/2⌋ and its two neighbours. With d = ξ_p − c ∈ [−1/2, 1/2) the three
//! weights are ((1/2 − d)²/2, 3/4 − d², (1/2 + d)²/2) and their
//! x-derivatives (−(1/2 − d), −2d, 1/2 + d)/Δx. These functions are smoother
//! replacements for the tri-linear S_ip of seed 000 eq 12 (the "smoother
//! interpolants" the seed refers to); the uniform basis is used up to the
//! domain boundary, where it reaches one ghost node (no boundary-modified
//! splines), which keeps partition of unity and linear reproduction exact
//! everywhere.

use super::{floor, Stencil1d};

/// The three 1D quadratic B-spline weights and derivatives (1/m) for a
/// particle at grid coordinate `xi` = (x_p − x_min)/Δx on an axis of cell
/// width `h` (m). The first node is ⌊xi + 1/2⌋ − 1.
#[inline]
pub fn quadratic_bspline_1d(xi: f64, h: f64) -> Stencil1d {
    quadratic_bspline_1d_scaled(xi, 1.0 / h)
}

/// [`quadratic_bspline_1d`] with the inverse cell width `inv_h` = 1/Δx
/// (1/m) given: the derivatives are (−(1/2 − d), −2d, 1/2 + d)·inv_h.
#[inline]
pub fn quadratic_bspline_1d_scaled(xi: f64, inv_h: f64) -> Stencil1d {
    let mut out = Stencil1d {
        first: 0,
        len: 3,
        weight: [0.0; 3],
        gradient: [0.0; 3],
    };
    out.first = quadratic_bspline_1d_into(xi, inv_h, &mut out.weight, &mut out.gradient);
    out
}

/// The three weights and derivatives of [`quadratic_bspline_1d_scaled`]
/// written into `weight[..3]` and `gradient[..3]`; returns the first node.
/// The form the transfer kernels evaluate in place.
#[inline(always)]
pub fn quadratic_bspline_1d_into(
    xi: f64,
    inv_h: f64,
    weight: &mut [f64],
    gradient: &mut [f64],
) -> isize {
    let c = floor(xi + 0.5);
    let d = xi - c;
    let lo = 0.5 - d;
    let hi = 0.5 + d;
    weight[0] = 0.5 * lo * lo;
    weight[1] = 0.75 - d * d;
    weight[2] = 0.5 * hi * hi;
    gradient[0] = -lo * inv_h;
    gradient[1] = -2.0 * d * inv_h;
    gradient[2] = hi * inv_h;
    c as isize - 1
}

/// The quadratic B-spline φ(ξ) of one node at distance ξ (in cells).
pub fn quadratic_bspline(xi: f64) -> f64 {
    let a = xi.abs();
    if a <= 0.5 {
        0.75 - a * a
    } else if a <= 1.5 {
        0.5 * (1.5 - a) * (1.5 - a)
    } else {
        0.0
    }
}
