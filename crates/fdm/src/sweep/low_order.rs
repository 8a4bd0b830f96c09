//! The first-order fluxes a sweep falls back to: the cell fluxes, the
//! Rusanov face fluxes, and the low-order updates (planar and radial).

use super::{cut, opt_mut, NMAX};
use crate::gas::GasLaw;
use crate::limiter::FlowState;
use crate::state::SPECIES;

/// λf(U) along `AXIS` of one cell (flow variables and ρY) and its
/// λ(|u_d| + c), from its velocity along the sweep `v`, pressure `p` and
/// ν = λc: the one expression both limiter paths use, so they agree to the
/// bit.
#[inline(always)]
pub(super) fn cell_flux<const AXIS: usize>(
    lambda: f64,
    u: [f64; NMAX],
    v: f64,
    p: f64,
    nu: f64,
) -> ([f64; NMAX], f64) {
    let lv = lambda * v;
    let mut f = [0.0; NMAX];
    f[0] = lambda * u[1 + AXIS];
    f[1] = u[1] * lv;
    f[2] = u[2] * lv;
    f[3] = u[3] * lv;
    f[1 + AXIS] += lambda * p;
    f[4] = (u[4] + p) * lv;
    f[SPECIES] = u[SPECIES] * lv;
    (f, lv.abs() + nu)
}

/// The Rusanov flux ½(fa + fb) − ½ s (ub − ua) of one variable (scaled
/// by λ, as its arguments), shared by both limiter paths.
#[inline(always)]
pub(super) fn rusanov_face(fa: f64, fb: f64, ua: f64, ub: f64, s: f64) -> f64 {
    0.5 * (fa + fb) - 0.5 * s * (ub - ua)
}

/// Face limiter, per cell of one row: the flux of U along the sweep
/// scaled by λ, λf(U) (flow variables and ρY), and the cell's λ(|u_d| + c)
/// (velocities, ν = λc and p of the cells from the passes before). Each
/// output slice a separate argument, so the loop vectorises.
#[inline(never)]
#[allow(clippy::too_many_arguments)]
pub(super) fn cell_flux_kernel<const AXIS: usize, G: GasLaw>(
    lambda: f64,
    u: [&[f64]; NMAX],
    cells: [&[f64]; 3],
    o0: &mut [f64],
    o1: &mut [f64],
    o2: &mut [f64],
    o3: &mut [f64],
    o4: &mut [f64],
    o5: &mut [f64],
    speed: &mut [f64],
) {
    let n = o0.len();
    let [a0, a1, a2, a3, a4, a5] = cut::<G>(u, n);
    let o5 = opt_mut::<G>(o5, n);
    let [v, p, nu] = cells;
    let (v, p, nu) = (&v[..n], &p[..n], &nu[..n]);
    let (o1, o2, o3, o4, speed) = (
        &mut o1[..n],
        &mut o2[..n],
        &mut o3[..n],
        &mut o4[..n],
        &mut speed[..n],
    );
    for k in 0..n {
        let y = if G::SPECIES { a5[k] } else { 0.0 };
        let (f, sp) = cell_flux::<AXIS>(
            lambda,
            [a0[k], a1[k], a2[k], a3[k], a4[k], y],
            v[k],
            p[k],
            nu[k],
        );
        o0[k] = f[0];
        o1[k] = f[1];
        o2[k] = f[2];
        o3[k] = f[3];
        o4[k] = f[4];
        if G::SPECIES {
            o5[k] = f[SPECIES];
        }
        speed[k] = sp;
    }
}

/// Face limiter, per face a + ½ of one row: the Rusanov flux of U scaled
/// by λ, λF^L = ½(λf(U_a) + λf(U_{a+1})) − ½ λs (U_{a+1} − U_a) with
/// λs = max(λ(|u_d| + c)) of the two cells ([`cell_flux_kernel`]).
#[inline(never)]
#[allow(clippy::too_many_arguments)]
pub(super) fn rusanov_kernel<G: GasLaw>(
    u0: [&[f64]; NMAX],
    up: [&[f64]; NMAX],
    f0: [&[f64]; NMAX],
    fp: [&[f64]; NMAX],
    s0: &[f64],
    sp: &[f64],
    o0: &mut [f64],
    o1: &mut [f64],
    o2: &mut [f64],
    o3: &mut [f64],
    o4: &mut [f64],
    o5: &mut [f64],
) {
    let n = o0.len();
    let [a0, a1, a2, a3, a4, a5] = cut::<G>(u0, n);
    let [b0, b1, b2, b3, b4, b5] = cut::<G>(up, n);
    let [c0, c1, c2, c3, c4, c5] = cut::<G>(f0, n);
    let [d0, d1, d2, d3, d4, d5] = cut::<G>(fp, n);
    let o5 = opt_mut::<G>(o5, n);
    let (s0, sp) = (&s0[..n], &sp[..n]);
    let (o1, o2, o3, o4) = (&mut o1[..n], &mut o2[..n], &mut o3[..n], &mut o4[..n]);
    for k in 0..n {
        let s = if s0[k] > sp[k] { s0[k] } else { sp[k] };
        let face = |fa: f64, fb: f64, ua: f64, ub: f64| rusanov_face(fa, fb, ua, ub, s);
        o0[k] = face(c0[k], d0[k], a0[k], b0[k]);
        o1[k] = face(c1[k], d1[k], a1[k], b1[k]);
        o2[k] = face(c2[k], d2[k], a2[k], b2[k]);
        o3[k] = face(c3[k], d3[k], a3[k], b3[k]);
        o4[k] = face(c4[k], d4[k], a4[k], b4[k]);
        if G::SPECIES {
            o5[k] = face(c5[k], d5[k], a5[k], b5[k]);
        }
    }
}

/// Face limiter, per cell a of one row: the first-order update
/// U^L = U − (λF^L_{a+½} − λF^L_{a−½}) (flow variables and ρY) and its
/// 2ρ·ρe ([`FlowState::twice_rho_internal`]).
#[inline(never)]
#[allow(clippy::too_many_arguments)]
pub(super) fn low_order_kernel<G: GasLaw>(
    u: [&[f64]; NMAX],
    fm: [&[f64]; NMAX],
    fp: [&[f64]; NMAX],
    o0: &mut [f64],
    o1: &mut [f64],
    o2: &mut [f64],
    o3: &mut [f64],
    o4: &mut [f64],
    o5: &mut [f64],
    q2: &mut [f64],
) {
    let n = o0.len();
    let [u0, u1, u2, u3, u4, u5] = cut::<G>(u, n);
    let [m0, m1, m2, m3, m4, m5] = cut::<G>(fm, n);
    let [p0, p1, p2, p3, p4, p5] = cut::<G>(fp, n);
    let o5 = opt_mut::<G>(o5, n);
    let (o1, o2, o3, o4, q2) = (
        &mut o1[..n],
        &mut o2[..n],
        &mut o3[..n],
        &mut o4[..n],
        &mut q2[..n],
    );
    for k in 0..n {
        let w = FlowState {
            density: u0[k] - (p0[k] - m0[k]),
            momentum: [
                u1[k] - (p1[k] - m1[k]),
                u2[k] - (p2[k] - m2[k]),
                u3[k] - (p3[k] - m3[k]),
            ],
            energy: u4[k] - (p4[k] - m4[k]),
        };
        o0[k] = w.density;
        o1[k] = w.momentum[0];
        o2[k] = w.momentum[1];
        o3[k] = w.momentum[2];
        o4[k] = w.energy;
        q2[k] = w.twice_rho_internal();
        if G::SPECIES {
            o5[k] = u5[k] - (p5[k] - m5[k]);
        }
    }
}

/// [`low_order_kernel`] of a radial sweep: the first-order update with the
/// ring weights, the hoop source of the same pressure p̂ the update uses
/// and the smoothing's hoop term,
/// U^L = U − (α₊λF^L₊ − α₋λF^L₋) + λp̂(α₊ − α₋) e_r
/// − ½(μ₊ + μ₋)(α₊ − α₋)² ρu_r e_r, the radial momentum row written
/// α₊(λF^L₊ − λp̂) − α₋(λF^L₋ − λp̂) as in pass 5.
/// The limited update is then U^L − α₊λℓ₊A₊ + α₋λℓ₋A₋, the average with
/// weights α₊/2 and α₋/2 (they sum to 1) of the half states
/// U^L − 2λℓ₊A₊ and U^L + 2λℓ₋A₋: the same half states as on a planar
/// grid, so the limiter's bounds carry over unchanged.
#[inline(never)]
#[allow(clippy::too_many_arguments)]
pub(super) fn low_order_rz_kernel<G: GasLaw>(
    lambda: f64,
    weights: [&[f64]; 5],
    u: [&[f64]; NMAX],
    fm: [&[f64]; NMAX],
    fp: [&[f64]; NMAX],
    o0: &mut [f64],
    o1: &mut [f64],
    o2: &mut [f64],
    o3: &mut [f64],
    o4: &mut [f64],
    o5: &mut [f64],
    q2: &mut [f64],
) {
    let n = o0.len();
    let [ap, am, pr, mu_m, mu_0] = weights;
    let (ap, am, pr, mu_m, mu_0) = (&ap[..n], &am[..n], &pr[..n], &mu_m[..n], &mu_0[..n]);
    let [u0, u1, u2, u3, u4, u5] = cut::<G>(u, n);
    let [m0, m1, m2, m3, m4, m5] = cut::<G>(fm, n);
    let [p0, p1, p2, p3, p4, p5] = cut::<G>(fp, n);
    let o5 = opt_mut::<G>(o5, n);
    let (o1, o2, o3, o4, q2) = (
        &mut o1[..n],
        &mut o2[..n],
        &mut o3[..n],
        &mut o4[..n],
        &mut q2[..n],
    );
    for k in 0..n {
        let (a, b) = (ap[k], am[k]);
        let lp = lambda * pr[k];
        let d = a - b;
        let hoop = 0.5 * (mu_m[k] + mu_0[k]) * d * d;
        let w = FlowState {
            density: u0[k] - (a * p0[k] - b * m0[k]),
            momentum: [
                u1[k] - hoop * u1[k] - (a * (p1[k] - lp) - b * (m1[k] - lp)),
                u2[k] - (a * p2[k] - b * m2[k]),
                u3[k] - (a * p3[k] - b * m3[k]),
            ],
            energy: u4[k] - (a * p4[k] - b * m4[k]),
        };
        o0[k] = w.density;
        o1[k] = w.momentum[0];
        o2[k] = w.momentum[1];
        o3[k] = w.momentum[2];
        o4[k] = w.energy;
        q2[k] = w.twice_rho_internal();
        if G::SPECIES {
            o5[k] = u5[k] - (a * p5[k] - b * m5[k]);
        }
    }
}
