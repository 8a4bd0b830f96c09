//! The face limiter of a sweep: the per-face blend of the second-order
//! and first-order fluxes that keeps the updated states admissible, and
//! the bounds limiter of the density.

use super::kernels::velocity_kernel;
use super::low_order::{
    cell_flux, cell_flux_kernel, low_order_kernel, low_order_rz_kernel, rusanov_face,
    rusanov_kernel,
};
use super::{
    for_rows, rows_at, rows_at_mut, split_vars, PatchPtrs, RadialWeights, SlabShape, NMAX,
};
use crate::gas::GasLaw;
use crate::limiter::{
    admissible, density_range, density_share, face_share, is_compressive, FaceLimiter, FlowState,
};
use crate::state::NVAR;

/// What the face limiter reads at face a + ½ of one row: the cells' U
/// (rows a, a + 1), their first-order states U^L and 2ρ·ρe of those
/// (rows a, a + 1), λF* and λF^L of the face, μ, and the window of
/// densities and velocities along the sweep (rows a − 1 … a + 2) and
/// ν = λc (rows a, a + 1).
#[derive(Clone, Copy)]
struct FaceRows<'a> {
    u0: [&'a [f64]; NMAX],
    up: [&'a [f64]; NMAX],
    low0: [&'a [f64]; NMAX],
    lowp: [&'a [f64]; NMAX],
    q0: &'a [f64],
    qp: &'a [f64],
    flow: [&'a [f64]; NMAX],
    mu: &'a [f64],
    rho: [&'a [f64]; 4],
    vel: [&'a [f64]; 4],
    nu: [&'a [f64]; 2],
}

/// The antidiffusive change λA = λF* − μ(U_{a+1} − U_a) − λF^L of
/// variable `f` at face `k`, with `lf` = λF* there.
#[inline(always)]
fn antidiffusive(r: &FaceRows, lf: f64, f: usize, k: usize) -> f64 {
    lf - r.mu[k] * (r.up[f][k] - r.u0[f][k]) - r.flow[f][k]
}

/// The states of face `k`: the left and right first-order states and the
/// antidiffusive change λA ([`antidiffusive`]), flow variables only; `lf`
/// holds λF* of the face.
#[inline(always)]
fn face_flow(r: &FaceRows, lf: [f64; NVAR], k: usize) -> (FlowState, FlowState, FlowState) {
    let at = |rows: &[&[f64]; NMAX], f: usize| rows[f][k];
    let anti = |f: usize| antidiffusive(r, lf[f], f, k);
    let flow = |g: &dyn Fn(usize) -> f64| FlowState {
        density: g(0),
        momentum: [g(1), g(2), g(3)],
        energy: g(4),
    };
    (
        flow(&|f| at(&r.low0, f)),
        flow(&|f| at(&r.lowp, f)),
        flow(&anti),
    )
}

/// Face limiter, per face of one row: 0 in `flags` where the face keeps
/// the scheme's flux (both half states U^L_a − 2λA and U^L_{a+1} + 2λA
/// admissible and, at a compressive face with `bounds`, within the local
/// density ranges; F* of the row's faces given),
/// 1 where it needs limiting. Every slice is cut to the row's length
/// first, and the choice of bounds is a constant, so the loop runs free of
/// bounds checks and branches and vectorises.
#[inline(never)]
fn flag_faces<const BOUNDS: bool>(
    r: &FaceRows,
    fstar: [&[f64]; NMAX],
    lambda: f64,
    flags: &mut [f64],
) {
    let n = r.mu.len();
    let flags = &mut flags[..n];
    #[inline(always)]
    fn cut5(a: [&[f64]; NMAX], n: usize) -> [&[f64]; NVAR] {
        [&a[0][..n], &a[1][..n], &a[2][..n], &a[3][..n], &a[4][..n]]
    }
    let cut5 = |a| cut5(a, n);
    let (u0, up, l0, lp, fs, fl) = (
        cut5(r.u0),
        cut5(r.up),
        cut5(r.low0),
        cut5(r.lowp),
        cut5(fstar),
        cut5(r.flow),
    );
    let (q0, qp, mu) = (&r.q0[..n], &r.qp[..n], &r.mu[..n]);
    let rho = [
        &r.rho[0][..n],
        &r.rho[1][..n],
        &r.rho[2][..n],
        &r.rho[3][..n],
    ];
    let vel = [
        &r.vel[0][..n],
        &r.vel[1][..n],
        &r.vel[2][..n],
        &r.vel[3][..n],
    ];
    let (n0, np) = (&r.nu[0][..n], &r.nu[1][..n]);
    for k in 0..n {
        let a: [f64; NVAR] =
            per_var!(|f| lambda * fs[f][k] - mu[k] * (up[f][k] - u0[f][k]) - fl[f][k]);
        let flow = |v: [f64; NVAR]| FlowState {
            density: v[0],
            momentum: [v[1], v[2], v[3]],
            energy: v[4],
        };
        let hl = flow(per_var!(|f| l0[f][k] - 2.0 * a[f]));
        let hr = flow(per_var!(|f| lp[f][k] + 2.0 * a[f]));
        let positive = admissible(&hl, l0[0][k], q0[k]) & admissible(&hr, lp[0][k], qp[k]);
        if BOUNDS {
            let (lo_l, hi_l) = density_range([rho[0][k], rho[1][k], rho[2][k]], l0[0][k]);
            let (lo_r, hi_r) = density_range([rho[1][k], rho[2][k], rho[3][k]], lp[0][k]);
            let in_range = (hl.density >= lo_l)
                & (hl.density <= hi_l)
                & (hr.density >= lo_r)
                & (hr.density <= hi_r);
            let nu = if n0[k] < np[k] { n0[k] } else { np[k] };
            let v = [vel[0][k], vel[1][k], vel[2][k], vel[3][k]].map(|x| lambda * x);
            flags[k] = f64::from(u8::from(!(positive & (in_range | !is_compressive(v, nu)))));
        } else {
            flags[k] = f64::from(u8::from(!positive));
        }
    }
}

/// The largest share ℓ of the antidiffusive flux at face `k` that keeps
/// its half states within bounds (positivity by [`face_share`], the
/// density range by [`density_share`] at a compressive face), and the
/// share positivity alone allows.
fn face_limit(r: &FaceRows, lf: [f64; NVAR], lambda: f64, bounds: bool, k: usize) -> (f64, f64) {
    let (l, rt, a) = face_flow(r, lf, k);
    let positive = face_share(&l, 2.0, &rt, 2.0, &a);
    let nu = r.nu[0][k].min(r.nu[1][k]);
    if !(bounds && is_compressive(r.vel.map(|v| lambda * v[k]), nu)) {
        return (positive, positive);
    }
    let (lo_l, hi_l) = density_range([r.rho[0][k], r.rho[1][k], r.rho[2][k]], l.density);
    let (lo_r, hi_r) = density_range([r.rho[1][k], r.rho[2][k], r.rho[3][k]], rt.density);
    let share = positive
        .min(density_share(l.density, -2.0 * a.density, lo_l, hi_l))
        .min(density_share(rt.density, 2.0 * a.density, lo_r, hi_r));
    (share, positive)
}

/// The face limiter between passes 4 and 5 ([`crate::limiter`]): at every
/// face whose half states are not within bounds, the Richtmyer flux
/// becomes F* − (1 − ℓ) A with the largest share ℓ that keeps them within
/// bounds, so the update there is the Rusanov one plus ℓ times the
/// antidiffusive flux. The Rusanov fluxes are of U (the state before the
/// smoothing), with p and c from pass 1. Every face's ℓ depends only on
/// its two cells' stencils, which lie within the ghost layers, so
/// neighbouring patches compute the same ℓ at a face they share. Faces
/// within bounds keep their flux exactly. Returns the number of faces
/// changed for positivity and for the density bounds (a face counts once,
/// under positivity when that bound binds).
///
/// Scratch: `work` holds, per row, the velocity along the sweep, 2ρ·ρe of
/// U^L, U^L (nf arrays) and λF^L (nf arrays), each `n` long; the U^L and
/// 2ρ·ρe arrays hold λf(U) and λ(|u_d| + c) per cell until λF^L is formed.
///
/// # Safety
/// As [`sweep_slab`].
///
/// [`sweep_slab`]: super::sweep_slab
#[allow(clippy::too_many_arguments)]
pub(super) unsafe fn face_limiter<const AXIS: usize, G: GasLaw>(
    limiter: FaceLimiter,
    lambda: f64,
    fields: &PatchPtrs,
    shape: &SlabShape,
    radial: Option<RadialWeights>,
    pres: &[f64],
    psrc: &[f64],
    nu: &[f64],
    mu: &[f64],
    marks: &mut [f64],
    work: &mut [f64],
    fstar: &mut [&mut [f64]; NMAX],
) -> [u64; 2] {
    let n = shape.scratch_len();
    let g = shape.ghost;
    let hi = shape.dims_a - g;
    let (sa, ss) = (shape.stride_a, shape.width.max(1));
    let nf = if G::SPECIES { NMAX } else { NVAR };
    let bounds = limiter.shock_bounds();
    let (vel, rest) = work.split_at_mut(n);
    let (q2, rest) = rest.split_at_mut(n);
    let (low, rest) = rest.split_at_mut(nf * n);
    let mut low = split_vars(low, n);
    let mut flow = split_vars(&mut rest[..nf * n], n);
    let urow = |fo: usize, len: usize| -> [&[f64]; NMAX] {
        [
            fields.row(0, fo, len),
            fields.row(1, fo, len),
            fields.row(2, fo, len),
            fields.row(3, fo, len),
            fields.row(4, fo, len),
            fields.species_row::<G>(fo, len),
        ]
    };
    // Velocities along the sweep, rows a ∈ [g − 2, hi + 2).
    for_rows(shape, g - 2, hi + 2, |fo, so, len| {
        let (r, m) = (fields.row(0, fo, len), fields.row(1 + AXIS, fo, len));
        velocity_kernel(r, m, &mut vel[so..][..len]);
    });
    // λf(U) (in the U^L arrays) and λ(|u_d| + c) (in the 2ρ·ρe array) per
    // cell, rows a ∈ [g − 2, hi + 2), then λF^L at faces a + ½, a ∈ [g − 2, hi].
    for_rows(shape, g - 2, hi + 2, |fo, so, len| {
        let cells = [&vel[so..][..len], &pres[so..][..len], &nu[so..][..len]];
        let [o0, o1, o2, o3, o4, o5] = rows_at_mut::<G>(&mut low, so, len);
        let speed = &mut q2[so..][..len];
        cell_flux_kernel::<AXIS, G>(lambda, urow(fo, len), cells, o0, o1, o2, o3, o4, o5, speed);
    });
    for_rows(shape, g - 2, hi + 1, |fo, so, len| {
        let [o0, o1, o2, o3, o4, o5] = rows_at_mut::<G>(&mut flow, so, len);
        rusanov_kernel::<G>(
            urow(fo, len),
            urow(fo + sa, len),
            rows_at::<G>(&low, so, len),
            rows_at::<G>(&low, so + ss, len),
            &q2[so..][..len],
            &q2[so + ss..][..len],
            o0,
            o1,
            o2,
            o3,
            o4,
            o5,
        );
    });
    // U^L and its 2ρ·ρe, cells a ∈ [g − 1, hi].
    for_rows(shape, g - 1, hi + 1, |fo, so, len| {
        let [o0, o1, o2, o3, o4, o5] = rows_at_mut::<G>(&mut low, so, len);
        let (fm, fp) = (
            rows_at::<G>(&flow, so - ss, len),
            rows_at::<G>(&flow, so, len),
        );
        let q2 = &mut q2[so..][..len];
        match radial {
            None => low_order_kernel::<G>(urow(fo, len), fm, fp, o0, o1, o2, o3, o4, o5, q2),
            Some(w) => {
                let weights = [
                    &w.plus[so..],
                    &w.minus[so..],
                    &psrc[so..],
                    &mu[so - ss..],
                    &mu[so..],
                ];
                low_order_rz_kernel::<G>(
                    lambda,
                    weights,
                    urow(fo, len),
                    fm,
                    fp,
                    o0,
                    o1,
                    o2,
                    o3,
                    o4,
                    o5,
                    q2,
                );
            }
        }
    });
    let mut changed = [0u64; 2];
    // Faces a + ½, a ∈ [g − 1, hi).
    for_rows(shape, g - 1, hi, |fo, so, len| {
        let r = FaceRows {
            u0: urow(fo, len),
            up: urow(fo + sa, len),
            low0: rows_at::<G>(&low, so, len),
            lowp: rows_at::<G>(&low, so + ss, len),
            q0: &q2[so..][..len],
            qp: &q2[so + ss..][..len],
            flow: rows_at::<G>(&flow, so, len),
            mu: &mu[so..][..len],
            rho: [fo - sa, fo, fo + sa, fo + 2 * sa].map(|o| fields.row(0, o, len)),
            vel: [so - ss, so, so + ss, so + 2 * ss].map(|o| &vel[o..][..len]),
            nu: [&nu[so..][..len], &nu[so + ss..][..len]],
        };
        let flags = &mut marks[so..][..len];
        let fs = rows_at::<G>(fstar, so, len);
        if bounds {
            flag_faces::<true>(&r, fs, lambda, flags);
        } else {
            flag_faces::<false>(&r, fs, lambda, flags);
        }
        if flags.iter().all(|&f| f == 0.0) {
            return;
        }
        for k in 0..len {
            if flags[k] == 0.0 {
                continue;
            }
            let lf: [f64; NVAR] = per_var!(|f| lambda * fstar[f][so + k]);
            let (share, positive) = face_limit(&r, lf, lambda, bounds, k);
            if share < 1.0 {
                for (f, star) in fstar.iter_mut().enumerate().take(nf) {
                    let a = antidiffusive(&r, lambda * star[so + k], f, k);
                    star[so + k] -= (1.0 - share) * a / lambda;
                }
                if shape.owns_face(so + k) {
                    changed[usize::from(share < positive)] += 1;
                }
            }
        }
    });
    changed
}

/// Face limiter, first attempt, per cell of one row: the density flux
/// λρu_d and λ(|u_d| + c), as [`cell_flux`] forms them.
#[inline(never)]
fn density_flux_kernel<const AXIS: usize>(
    lambda: f64,
    m: &[f64],
    vel: &[f64],
    nu: &[f64],
    flux: &mut [f64],
    speed: &mut [f64],
) {
    let n = flux.len();
    let (m, vel, nu, speed) = (&m[..n], &vel[..n], &nu[..n], &mut speed[..n]);
    for k in 0..n {
        flux[k] = lambda * m[k];
        speed[k] = (lambda * vel[k]).abs() + nu[k];
    }
}

/// Face limiter, first attempt, per face of one row: the Rusanov density
/// flux λF^L_ρ ([`rusanov_face`]) from the cells' λρu_d and λ(|u_d| + c).
#[inline(never)]
fn density_rusanov_kernel(
    r0: &[f64],
    rp: &[f64],
    f0: &[f64],
    fp: &[f64],
    s0: &[f64],
    sp: &[f64],
    out: &mut [f64],
) {
    let n = out.len();
    let (r0, rp, f0, fp, s0, sp) = (&r0[..n], &rp[..n], &f0[..n], &fp[..n], &s0[..n], &sp[..n]);
    for k in 0..n {
        let s = if s0[k] > sp[k] { s0[k] } else { sp[k] };
        out[k] = rusanov_face(f0[k], fp[k], r0[k], rp[k], s);
    }
}

/// Face limiter, first attempt, per cell of one row: the first-order
/// density U^L_ρ = ρ − (λF^L_ρ,+ − λF^L_ρ,−), as [`low_order_kernel`]
/// forms it.
#[inline(never)]
fn density_low_kernel(rho: &[f64], fm: &[f64], fp: &[f64], out: &mut [f64]) {
    let n = out.len();
    let (rho, fm, fp) = (&rho[..n], &fm[..n], &fp[..n]);
    for k in 0..n {
        out[k] = rho[k] - (fp[k] - fm[k]);
    }
}

/// [`density_low_kernel`] of a radial sweep: U^L_ρ = ρ − (α₊λF^L_ρ,+ −
/// α₋λF^L_ρ,−), as [`low_order_rz_kernel`] forms it.
#[inline(never)]
fn density_low_rz_kernel(
    ap: &[f64],
    am: &[f64],
    rho: &[f64],
    fm: &[f64],
    fp: &[f64],
    out: &mut [f64],
) {
    let n = out.len();
    let (ap, am, rho, fm, fp) = (&ap[..n], &am[..n], &rho[..n], &fm[..n], &fp[..n]);
    for k in 0..n {
        out[k] = rho[k] - (ap[k] * fp[k] - am[k] * fm[k]);
    }
}

/// Face limiter, first attempt, per face of one row: 1 in `flags` where
/// the face is compressive and a half-state density U^L_ρ ∓ 2λA_ρ leaves
/// its local range, 0 elsewhere; the same arithmetic as [`flag_faces`]
/// with bounds, on the density alone.
#[inline(never)]
#[allow(clippy::too_many_arguments)]
fn flag_density_faces(
    lambda: f64,
    rho: [&[f64]; 4],
    vel: [&[f64]; 4],
    nu: [&[f64]; 2],
    low: [&[f64]; 2],
    fstar: &[f64],
    flow: &[f64],
    mu: &[f64],
    flags: &mut [f64],
) {
    let n = flags.len();
    let rho = [&rho[0][..n], &rho[1][..n], &rho[2][..n], &rho[3][..n]];
    let vel = [&vel[0][..n], &vel[1][..n], &vel[2][..n], &vel[3][..n]];
    let (n0, np, l0, lp) = (&nu[0][..n], &nu[1][..n], &low[0][..n], &low[1][..n]);
    let (fstar, flow, mu) = (&fstar[..n], &flow[..n], &mu[..n]);
    for k in 0..n {
        let a = lambda * fstar[k] - mu[k] * (rho[2][k] - rho[1][k]) - flow[k];
        let (hl, hr) = (l0[k] - 2.0 * a, lp[k] + 2.0 * a);
        let (lo_l, hi_l) = density_range([rho[0][k], rho[1][k], rho[2][k]], l0[k]);
        let (lo_r, hi_r) = density_range([rho[1][k], rho[2][k], rho[3][k]], lp[k]);
        let in_range = (hl >= lo_l) & (hl <= hi_l) & (hr >= lo_r) & (hr <= hi_r);
        let nu = if n0[k] < np[k] { n0[k] } else { np[k] };
        let v = [vel[0][k], vel[1][k], vel[2][k], vel[3][k]].map(|x| lambda * x);
        flags[k] = f64::from(u8::from(!in_range & is_compressive(v, nu)));
    }
}

/// The first attempt's face limiter: the local density bounds at
/// compressive faces alone ([`crate::limiter`]), computed on the density
/// only, with the Rusanov flux of every variable formed at the faces that
/// need it. At such a face it gives the same share ℓ as [`face_limiter`]
/// does where positivity does not bind, to the bit, so a sweep that needs
/// no positivity limiting gives the same result either way. Returns the
/// number of faces changed.
///
/// # Safety
/// As [`sweep_slab`].
///
/// [`sweep_slab`]: super::sweep_slab
#[allow(clippy::too_many_arguments)]
pub(super) unsafe fn bounds_limiter<const AXIS: usize, G: GasLaw>(
    lambda: f64,
    fields: &PatchPtrs,
    shape: &SlabShape,
    radial: Option<RadialWeights>,
    pres: &[f64],
    nu: &[f64],
    mu: &[f64],
    marks: &mut [f64],
    work: &mut [f64],
    fstar: &mut [&mut [f64]; NMAX],
) -> u64 {
    let n = shape.scratch_len();
    let g = shape.ghost;
    let hi = shape.dims_a - g;
    let (sa, ss) = (shape.stride_a, shape.width.max(1));
    let nf = if G::SPECIES { NMAX } else { NVAR };
    let (vel, rest) = work.split_at_mut(n);
    let (dflux, rest) = rest.split_at_mut(n);
    let (speed, rest) = rest.split_at_mut(n);
    let (flow, rest) = rest.split_at_mut(n);
    let low = &mut rest[..n];
    // Velocities, λρu_d and λ(|u_d| + c), rows a ∈ [g − 2, hi + 2).
    for_rows(shape, g - 2, hi + 2, |fo, so, len| {
        let (r, m) = (fields.row(0, fo, len), fields.row(1 + AXIS, fo, len));
        velocity_kernel(r, m, &mut vel[so..][..len]);
        density_flux_kernel::<AXIS>(
            lambda,
            m,
            &vel[so..][..len],
            &nu[so..][..len],
            &mut dflux[so..][..len],
            &mut speed[so..][..len],
        );
    });
    // λF^L_ρ at faces a + ½, a ∈ [g − 2, hi]; U^L_ρ of cells [g − 1, hi].
    for_rows(shape, g - 2, hi + 1, |fo, so, len| {
        let (r0, rp) = (fields.row(0, fo, len), fields.row(0, fo + sa, len));
        let (f0, fp) = (&dflux[so..][..len], &dflux[so + ss..][..len]);
        let (s0, sp) = (&speed[so..][..len], &speed[so + ss..][..len]);
        density_rusanov_kernel(r0, rp, f0, fp, s0, sp, &mut flow[so..][..len]);
    });
    for_rows(shape, g - 1, hi + 1, |fo, so, len| {
        let r = fields.row(0, fo, len);
        let (fm, fp) = (&flow[so - ss..][..len], &flow[so..][..len]);
        match radial {
            None => density_low_kernel(r, fm, fp, &mut low[so..][..len]),
            Some(w) => {
                let (ap, am) = (&w.plus[so..], &w.minus[so..]);
                density_low_rz_kernel(ap, am, r, fm, fp, &mut low[so..][..len]);
            }
        }
    });
    let mut changed = 0;
    for_rows(shape, g - 1, hi, |fo, so, len| {
        let rho = [fo - sa, fo, fo + sa, fo + 2 * sa].map(|o| fields.row(0, o, len));
        let flags = &mut marks[so..][..len];
        flag_density_faces(
            lambda,
            rho,
            [so - ss, so, so + ss, so + 2 * ss].map(|o| &vel[o..][..len]),
            [&nu[so..][..len], &nu[so + ss..][..len]],
            [&low[so..][..len], &low[so + ss..][..len]],
            &fstar[0][so..][..len],
            &flow[so..][..len],
            &mu[so..][..len],
            flags,
        );
        if flags.iter().all(|&f| f == 0.0) {
            return;
        }
        for k in 0..len {
            if flags[k] == 0.0 {
                continue;
            }
            let (i, j) = (so + k, so + ss + k);
            let cell = |fo: usize, c: usize| {
                let u: [f64; NMAX] = std::array::from_fn(|f| {
                    if f < nf {
                        fields.row(f, fo, len)[k]
                    } else {
                        0.0
                    }
                });
                let (fl, _) = cell_flux::<AXIS>(lambda, u, vel[c], pres[c], nu[c]);
                (u, fl)
            };
            let ((ua, fa), (ub, fb)) = (cell(fo, i), cell(fo + sa, j));
            let s = if speed[i] > speed[j] {
                speed[i]
            } else {
                speed[j]
            };
            let a_rho = lambda * fstar[0][i] - mu[i] * (ub[0] - ua[0]) - flow[i];
            let (lo_l, hi_l) = density_range([rho[0][k], rho[1][k], rho[2][k]], low[i]);
            let (lo_r, hi_r) = density_range([rho[1][k], rho[2][k], rho[3][k]], low[j]);
            let share = 1.0f64
                .min(density_share(low[i], -2.0 * a_rho, lo_l, hi_l))
                .min(density_share(low[j], 2.0 * a_rho, lo_r, hi_r));
            if share < 1.0 {
                for (f, star) in fstar.iter_mut().enumerate().take(nf) {
                    let fl = rusanov_face(fa[f], fb[f], ua[f], ub[f], s);
                    let a = lambda * star[i] - mu[i] * (ub[f] - ua[f]) - fl;
                    star[i] -= (1.0 - share) * a / lambda;
                }
                if shape.owns_face(i) {
                    changed += 1;
                }
            }
        }
    });
    changed
}

/// Whether every state of one written row keeps ρ > 0 and a positive,
/// finite internal energy (2ρE − |ρu|² > 0, division-free); a flat loop
/// the compiler vectorises.
#[inline(never)]
pub(super) fn row_is_positive(r: &[f64], mx: &[f64], my: &[f64], mz: &[f64], en: &[f64]) -> bool {
    let n = r.len();
    let (mx, my, mz, en) = (&mx[..n], &my[..n], &mz[..n], &en[..n]);
    let mut ok = true;
    for k in 0..n {
        let q2 = 2.0 * r[k] * en[k] - (mx[k] * mx[k] + my[k] * my[k] + mz[k] * mz[k]);
        ok &= (r[k] > 0.0) & (q2 > 0.0) & (q2 < f64::INFINITY);
    }
    ok
}
