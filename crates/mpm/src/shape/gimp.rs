//! The uGIMP shape function of Bardenhagen & Kober 2004 (seed 000 ref 13,
//! "The generalized interpolation material point method", CMES 5:477–95).
//!
//! GIMP replaces the point value S_i(x_p) of the grid function by its
//! average over the particle's characteristic function χ_p (the paper's
//! definition of the weighting function and its gradient):
//!
//! S_ip = (1/V_p) ∫ χ_p(x) S_i(x) dx,   ∇S_ip = (1/V_p) ∫ χ_p(x) ∇S_i(x) dx,
//!
//! with V_p = ∫ χ_p dx. In uGIMP ("uniform" GIMP) χ_p is 1 on the
//! particle's undeformed box [x_p − l_p, x_p + l_p] (per axis) and S_i is
//! the linear hat of node i, so S_ip is a tensor product of 1D averages.
//! For a particle at r = x_p − x_i from node i, cell width h and
//! 0 < l_p ≤ h/2, the average of the hat function over the particle is the
//! piecewise quadratic/linear function
//!
//! S(r) = 1 − (r² + l_p²)/(2 h l_p)        for |r| < l_p,
//! S(r) = 1 − |r|/h                        for l_p ≤ |r| < h − l_p,
//! S(r) = (h + l_p − |r|)²/(4 h l_p)       for h − l_p ≤ |r| < h + l_p,
//! S(r) = 0                                for |r| ≥ h + l_p,
//!
//! and its derivative with respect to x_p
//!
//! S'(r) = −r/(h l_p),  −sign(r)/h,  −sign(r)(h + l_p − |r|)/(2 h l_p),  0.
//!
//! Both are continuous, so the gradient no longer jumps when a particle
//! crosses a cell face. Where the particle's box lies inside one cell
//! (l_p ≤ |r| ≤ h − l_p for the two nodes of that cell), the weights and
//! gradients are exactly the linear ones of seed 001 eq 16. The equation
//! numbers of the paper are not reproduced here because it is not among the
//! seeds; the closed form above follows from its definition in three lines
//! of integration (see `docs/physics/mpm/shape_functions.md`).
//!
//! # Contiguous-particle GIMP
//!
//! uGIMP keeps l_p fixed, so the particle boxes stop tiling the body once it
//! deforms: where gas expands gaps open between them, where it compresses
//! they overlap.
//! Then Σ_p V_p ∇S_Ip no longer vanishes at interior nodes and the volume
//! update V_p ← V_p (1 + Δt tr L_p) drifts. cpGIMP (Bardenhagen & Kober
//! 2004; Wallstedt & Guilkey 2008, J. Comput. Phys. 227:9628) lets each
//! half-width follow the deformation, l_p,i = l_p0,i F_ii, and evaluates the
//! same closed form with that l_p ([`cpgimp_half_width`]). In 1D the
//! gradient is ∇S_Ip = (S_I(x_p + l_p) − S_I(x_p − l_p))/(2 l_p), so
//! V_p ∇S_Ip = A (S_I(x_p + l_p) − S_I(x_p − l_p)) (A the cross-section):
//! over domains that tile the tube the sum telescopes to zero at every
//! interior node, and the total volume changes only through the tube ends.

use super::{floor, Stencil1d};

/// Relative round-off a half-width may carry above Δx/2 and still be taken
/// as Δx/2: a few ulps, the error of forming l_p = ½ (V_p)^(1/3) from a
/// particle volume of exactly Δx³ (`ppc: 1` in 3D).
pub const HALF_WIDTH_ROUND_OFF: f64 = 4.0 * f64::EPSILON;

/// The half-width `lp` (m) on an axis of cell width `h` (m) as the 1D
/// weights take it: `lp` itself when 0 < lp ≤ h/2, h/2 when `lp` exceeds
/// h/2 by no more than [`HALF_WIDTH_ROUND_OFF`] (relative), `None` otherwise
/// (also for NaN).
#[inline]
pub fn admissible_half_width(lp: f64, h: f64) -> Option<f64> {
    let max = 0.5 * h;
    if lp > 0.0 && lp <= max {
        Some(lp)
    } else if lp > max && lp <= max * (1.0 + HALF_WIDTH_ROUND_OFF) {
        Some(max)
    } else {
        None
    }
}

/// Smallest stretch F_ii a cpGIMP domain follows: below it (strong
/// compression, or a rotation that turns the axis away, where F_ii → 0 or
/// changes sign) the half-width stays at `MIN_STRETCH` · l_p0.
pub const MIN_STRETCH: f64 = 0.01;

/// The cpGIMP half-width along one active axis (Bardenhagen & Kober 2004;
/// Wallstedt & Guilkey 2008, J. Comput. Phys. 227:9628, their "contiguous
/// particle GIMP"): the undeformed half-width `l0` (m) times the stretch
/// F_ii of the deformation gradient along that axis, l_p = l_p0 F_ii, kept
/// in [`MIN_STRETCH`] · l0 … h/2 so that the domain stays inside the three
/// nodes per axis the stencils hold (cell width `h`, m). A non-finite
/// `stretch` gives NaN, which [`admissible_half_width`] rejects.
#[inline]
pub fn cpgimp_half_width(l0: f64, stretch: f64, h: f64) -> f64 {
    if !stretch.is_finite() {
        return f64::NAN;
    }
    (l0 * stretch.max(MIN_STRETCH)).min(0.5 * h)
}

/// The 1D uGIMP weight S(r) and derivative S'(r) (1/m) of one node at
/// signed distance `r` = x_p − x_i (m), for cell width `h` and particle
/// half-width `lp` with 0 < lp ≤ h/2 (m).
#[inline]
pub fn ugimp_weight(r: f64, h: f64, lp: f64) -> (f64, f64) {
    let a = r.abs();
    if a < lp {
        (1.0 - (r * r + lp * lp) / (2.0 * h * lp), -r / (h * lp))
    } else if a < h - lp {
        (1.0 - a / h, -r.signum() / h)
    } else if a < h + lp {
        let t = h + lp - a;
        (t * t / (4.0 * h * lp), -r.signum() * t / (2.0 * h * lp))
    } else {
        (0.0, 0.0)
    }
}

/// The 1D uGIMP stencil for a particle at grid coordinate `xi` =
/// (x_p − x_min)/h with half-width `lp` (0 < lp ≤ h/2, m): the nodes of
/// ⌊xi + 1/2⌋ − 1 … ⌊xi + 1/2⌋ + 1 whose weight is non-zero (2 or 3).
#[inline]
pub fn ugimp_1d(xi: f64, h: f64, lp: f64) -> Stencil1d {
    let c = floor(xi + 0.5);
    let mut out = Stencil1d {
        first: c as isize - 1,
        len: 0,
        weight: [0.0; 3],
        gradient: [0.0; 3],
    };
    for k in 0..3 {
        let node = c - 1.0 + k as f64;
        let r = (xi - node) * h;
        if r.abs() >= h + lp {
            if out.len == 0 {
                // Outside the support below the particle: start one later.
                out.first += 1;
            }
            continue;
        }
        let (w, g) = ugimp_weight(r, h, lp);
        out.weight[out.len] = w;
        out.gradient[out.len] = g;
        out.len += 1;
    }
    out
}

/// [`ugimp_1d`] padded to its three candidate nodes ⌊xi + 1/2⌋ − 1 …
/// ⌊xi + 1/2⌋ + 1: a node outside the particle's support gets weight and
/// derivative 0 instead of being left out, so the stencil has a fixed
/// length (the form the transfer kernels loop over). The non-zero entries
/// are bit-identical to those of [`ugimp_1d`].
#[inline]
pub fn ugimp_1d_padded(xi: f64, h: f64, lp: f64) -> Stencil1d {
    let mut out = Stencil1d {
        first: 0,
        len: 3,
        weight: [0.0; 3],
        gradient: [0.0; 3],
    };
    out.first = ugimp_1d_padded_into(xi, h, lp, &mut out.weight, &mut out.gradient);
    out
}

/// The three weights and derivatives of [`ugimp_1d_padded`] written into
/// `weight[..3]` and `gradient[..3]`; returns the first node.
///
/// A zero half-width (`lp == 0.0`, a point particle, which
/// [`admissible_half_width`] refuses for ordinary particles) gives the
/// linear hat of seed 001 eq 16 in the same three slots: the limit of the
/// closed form as l_p → 0, whose first and third branches shrink to
/// nothing, evaluated as [`super::linear::hat_1d_into`] does (f = xi −
/// ⌊xi⌋, weights 1 − f and f, derivatives ∓1/h, the cell above for a
/// particle exactly on a node), so that its weights are bit-identical to
/// the hat's and its gradients sum to zero. The MPM gives it to load-only
/// particles (the FDM–MPM bridge's donor cells), which must reach only the
/// nodes of the cell they are in.
#[inline(always)]
pub fn ugimp_1d_padded_into(
    xi: f64,
    h: f64,
    lp: f64,
    weight: &mut [f64],
    gradient: &mut [f64],
) -> isize {
    let c = floor(xi + 0.5);
    if lp == 0.0 {
        // Slots 1, 2 (nodes c, c + 1) when xi lies in the lower half of
        // cell c, slots 0, 1 (nodes c − 1, c) in the upper half of c − 1.
        let lo = if floor(xi) == c { 1 } else { 0 };
        weight[..3].fill(0.0);
        gradient[..3].fill(0.0);
        // The hat itself, without its upper-boundary rule (no cell count
        // here: GIMP's lattice holds the ghost node past the last one).
        let inv_h = 1.0 / h;
        super::linear::hat_1d_into(
            xi,
            inv_h,
            usize::MAX,
            &mut weight[lo..],
            &mut gradient[lo..],
        );
        return c as isize - 1;
    }
    for k in 0..3 {
        let node = c - 1.0 + k as f64;
        let r = (xi - node) * h;
        (weight[k], gradient[k]) = if r.abs() < h + lp {
            ugimp_weight(r, h, lp)
        } else {
            (0.0, 0.0)
        };
    }
    c as isize - 1
}
