//! The passes of the two-step Lax–Wendroff update of a sweep: the fluxes,
//! the switch and the face viscosity, the smoothing, the Richtmyer
//! predictor and the conservative updates (planar and radial).

use super::{cut, opt, opt_mut, NMAX};
use crate::gas::GasLaw;
use crate::state::NVAR;
use crate::viscosity::{adaptive_eta, face_mu, switch_theta, ArtificialViscosity};

/// Flux along `AXIS` of a conservative state (seed 001 eq 2) with partial
/// density `ry` (ignored without a species), and the flux ρY u_d.
#[inline(always)]
fn flux<const AXIS: usize, G: GasLaw>(eos: &G, u: [f64; NVAR], ry: f64) -> ([f64; NVAR], f64) {
    let (f, fy, _) = flux_and_pressure::<AXIS, G>(eos, u, ry);
    (f, fy)
}

/// [`flux`] and the pressure it used.
#[inline(always)]
fn flux_and_pressure<const AXIS: usize, G: GasLaw>(
    eos: &G,
    u: [f64; NVAR],
    ry: f64,
) -> ([f64; NVAR], f64, f64) {
    let rho = u[0];
    let inv = 1.0 / rho;
    let e = (u[4] - 0.5 * (u[1] * u[1] + u[2] * u[2] + u[3] * u[3]) * inv) * inv;
    let y = if G::SPECIES { ry * inv } else { 0.0 };
    let p = eos.gas_pressure_inv(rho, inv, e, y);
    let vn = u[1 + AXIS] * inv;
    let mut f = [
        u[1 + AXIS],
        u[1] * vn,
        u[2] * vn,
        u[3] * vn,
        (u[4] + p) * vn,
    ];
    f[1 + AXIS] += p;
    (f, ry * vn, p)
}

/// Pass 1 on one row: the switch θ (eq 4), the acoustic Courant number
/// ν = λc and the pressure per cell; returns whether every state was
/// physical.
#[inline(never)]
#[allow(clippy::too_many_arguments)]
pub(super) fn cells_kernel<G: GasLaw>(
    eos: &G,
    lambda: f64,
    rho_m: &[f64],
    rho_p: &[f64],
    r: &[f64],
    mx: &[f64],
    my: &[f64],
    mz: &[f64],
    en: &[f64],
    ry: [&[f64]; 3],
    th: &mut [f64],
    nv: &mut [f64],
    pr: &mut [f64],
) -> bool {
    let n = th.len();
    let pr = &mut pr[..n];
    let (rho_m, rho_p, r, mx, my, mz, en, nv) = (
        &rho_m[..n],
        &rho_p[..n],
        &r[..n],
        &mx[..n],
        &my[..n],
        &mz[..n],
        &en[..n],
        &mut nv[..n],
    );
    let (ry_m, ry_0, ry_p) = (opt::<G>(ry[0], n), opt::<G>(ry[1], n), opt::<G>(ry[2], n));
    let mut ok = true;
    for k in 0..n {
        let rho = r[k];
        let inv = 1.0 / rho;
        let e = (en[k] - 0.5 * (mx[k] * mx[k] + my[k] * my[k] + mz[k] * mz[k]) * inv) * inv;
        let y = if G::SPECIES { ry_0[k] * inv } else { 0.0 };
        let (p, c) = eos.gas_pressure_and_sound_speed_inv(rho, inv, e, y);
        ok &= (rho > 0.0) & (p > 0.0) & (p < f64::INFINITY);
        let theta = switch_theta(rho_m[k], rho, rho_p[k]);
        th[k] = if G::SPECIES {
            let ty = switch_theta(ry_m[k] / rho_m[k], y, ry_p[k] / rho_p[k]);
            if ty > theta {
                ty
            } else {
                theta
            }
        } else {
            theta
        };
        nv[k] = lambda * c;
        pr[k] = p;
    }
    ok
}

/// Pass 2 on one row: μ at each face from the four switches around it.
#[inline(never)]
#[allow(clippy::too_many_arguments)]
pub(super) fn faces_kernel(
    viscosity: ArtificialViscosity,
    tm: &[f64],
    t0: &[f64],
    tp: &[f64],
    tpp: &[f64],
    n0: &[f64],
    np: &[f64],
    mu: &mut [f64],
) {
    let n = mu.len();
    let (tm, t0, tp, tpp, n0, np) = (&tm[..n], &t0[..n], &tp[..n], &tpp[..n], &n0[..n], &np[..n]);
    // θ and ν are finite here (pass 1 flags any non-finite state), so plain
    // comparisons replace f64::max and the loops vectorise; the law is
    // chosen once per row, not per face.
    let max = |a: f64, b: f64| if a > b { a } else { b };
    let theta_face = |k: usize| max(max(tm[k], t0[k]), max(tp[k], tpp[k]));
    match viscosity {
        ArtificialViscosity::Adaptive => {
            for (k, m) in mu.iter_mut().enumerate() {
                *m = face_mu(adaptive_eta(0.5 * (n0[k] + np[k])), theta_face(k));
            }
        }
        ArtificialViscosity::Constant(eta) => {
            for (k, m) in mu.iter_mut().enumerate() {
                *m = face_mu(eta, theta_face(k));
            }
        }
        ArtificialViscosity::Off => mu.fill(0.0),
    }
}

/// Pass 5 on the ρY row: ρY = Ū − λ(F*₊ − F*₋) clipped to [0, ρ] (the
/// updated density), so Y stays in [0, 1].
#[inline(never)]
pub(super) fn species_update_kernel(
    lambda: f64,
    ubar: &[f64],
    f_minus: &[f64],
    f_plus: &[f64],
    rho: &[f64],
    out: &mut [f64],
) {
    let n = out.len();
    let (ubar, f_minus, f_plus, rho) = (&ubar[..n], &f_minus[..n], &f_plus[..n], &rho[..n]);
    for k in 0..n {
        let v = ubar[k] - lambda * (f_plus[k] - f_minus[k]);
        out[k] = if v < 0.0 {
            0.0
        } else if v > rho[k] {
            rho[k]
        } else {
            v
        };
    }
}

/// Pass 5 on one row of one variable: U = Ū − λ(F*₊ − F*₋).
#[inline(never)]
pub(super) fn update_kernel(
    lambda: f64,
    ubar: &[f64],
    f_minus: &[f64],
    f_plus: &[f64],
    out: &mut [f64],
) {
    let n = out.len();
    let (ubar, f_minus, f_plus) = (&ubar[..n], &f_minus[..n], &f_plus[..n]);
    for k in 0..n {
        out[k] = ubar[k] - lambda * (f_plus[k] - f_minus[k]);
    }
}

/// Pass 5 of a radial sweep on one row of a variable without a source:
/// U = Ū − λ(α₊F*₊ − α₋F*₋).
#[inline(never)]
#[allow(clippy::too_many_arguments)]
pub(super) fn update_rz_kernel(
    lambda: f64,
    ap: &[f64],
    am: &[f64],
    ubar: &[f64],
    f_minus: &[f64],
    f_plus: &[f64],
    out: &mut [f64],
) {
    let n = out.len();
    let (ap, am, ubar, f_minus, f_plus) =
        (&ap[..n], &am[..n], &ubar[..n], &f_minus[..n], &f_plus[..n]);
    for k in 0..n {
        out[k] = ubar[k] - lambda * (ap[k] * f_plus[k] - am[k] * f_minus[k]);
    }
}

/// Pass 5 of a radial sweep on the radial momentum row, with the hoop
/// source: U = Ū − λ(α₊(F*₊ − p̂) − α₋(F*₋ − p̂)), p̂ the hoop pressure
/// ([`hoop_pressure_kernel`]). At rest F*_± is p̂ to the bit, so nothing
/// moves.
#[inline(never)]
#[allow(clippy::too_many_arguments)]
pub(super) fn update_rz_momentum_kernel(
    lambda: f64,
    ap: &[f64],
    am: &[f64],
    p: &[f64],
    ubar: &[f64],
    f_minus: &[f64],
    f_plus: &[f64],
    out: &mut [f64],
) {
    let n = out.len();
    let (ap, am, p, ubar, f_minus, f_plus) = (
        &ap[..n],
        &am[..n],
        &p[..n],
        &ubar[..n],
        &f_minus[..n],
        &f_plus[..n],
    );
    for k in 0..n {
        out[k] = ubar[k] - lambda * (ap[k] * (f_plus[k] - p[k]) - am[k] * (f_minus[k] - p[k]));
    }
}

/// [`species_update_kernel`] of a radial sweep: ρY = Ū − λ(α₊F*₊ − α₋F*₋)
/// clipped to [0, ρ].
#[inline(never)]
#[allow(clippy::too_many_arguments)]
pub(super) fn species_update_rz_kernel(
    lambda: f64,
    ap: &[f64],
    am: &[f64],
    ubar: &[f64],
    f_minus: &[f64],
    f_plus: &[f64],
    rho: &[f64],
    out: &mut [f64],
) {
    let n = out.len();
    let (ap, am, ubar, f_minus, f_plus, rho) = (
        &ap[..n],
        &am[..n],
        &ubar[..n],
        &f_minus[..n],
        &f_plus[..n],
        &rho[..n],
    );
    for k in 0..n {
        let v = ubar[k] - lambda * (ap[k] * f_plus[k] - am[k] * f_minus[k]);
        out[k] = if v < 0.0 {
            0.0
        } else if v > rho[k] {
            rho[k]
        } else {
            v
        };
    }
}

/// The hoop source's pressure of a radial sweep on one row: the mean of
/// the predictor's pressures at the cell's two faces. At rest both are the
/// cell's pressure to the bit, and so is their mean.
#[inline(never)]
pub(super) fn hoop_pressure_kernel(p_minus: &[f64], p_plus: &[f64], out: &mut [f64]) {
    let n = out.len();
    let (p_minus, p_plus) = (&p_minus[..n], &p_plus[..n]);
    for k in 0..n {
        out[k] = 0.5 * (p_minus[k] + p_plus[k]);
    }
}

/// The smoothing coefficients of a radial sweep on one row: α₊μ₊ and
/// α₋μ₋, the face coefficients of eq 3 times the ring weights, which
/// [`smooth_kernel`] then takes in place of μ₊ and μ₋.
#[inline(never)]
pub(super) fn weighted_mu_kernel(
    ap: &[f64],
    am: &[f64],
    mu_m: &[f64],
    mu_0: &[f64],
    out_m: &mut [f64],
    out_p: &mut [f64],
    out_h: &mut [f64],
) {
    let n = out_m.len();
    let (ap, am, mu_m, mu_0, out_p, out_h) = (
        &ap[..n],
        &am[..n],
        &mu_m[..n],
        &mu_0[..n],
        &mut out_p[..n],
        &mut out_h[..n],
    );
    for k in 0..n {
        out_m[k] = am[k] * mu_m[k];
        out_p[k] = ap[k] * mu_0[k];
        let d = ap[k] - am[k];
        out_h[k] = 0.5 * (mu_m[k] + mu_0[k]) * d * d;
    }
}

/// Pass 3 on one row: the smoothed state Ū (eq 3, flux form) and its flux.
/// Separate slice arguments tell the compiler the outputs alias nothing,
/// so the loop vectorises.
#[inline(never)]
#[allow(clippy::too_many_arguments)]
pub(super) fn smooth_kernel<const AXIS: usize, const RZ: bool, G: GasLaw>(
    eos: &G,
    hoop: &[f64],
    mu_m: &[f64],
    mu_0: &[f64],
    m0: &[f64],
    m1: &[f64],
    m2: &[f64],
    m3: &[f64],
    m4: &[f64],
    c0: &[f64],
    c1: &[f64],
    c2: &[f64],
    c3: &[f64],
    c4: &[f64],
    n0: &[f64],
    n1: &[f64],
    n2: &[f64],
    n3: &[f64],
    n4: &[f64],
    p0: &mut [f64],
    p1: &mut [f64],
    p2: &mut [f64],
    p3: &mut [f64],
    p4: &mut [f64],
    q0: &mut [f64],
    q1: &mut [f64],
    q2: &mut [f64],
    q3: &mut [f64],
    q4: &mut [f64],
    species: [&[f64]; 3],
    p5: &mut [f64],
    q5: &mut [f64],
) {
    let n = p0.len();
    let (m5, c5, n5) = (
        opt::<G>(species[0], n),
        opt::<G>(species[1], n),
        opt::<G>(species[2], n),
    );
    let (p5, q5) = (opt_mut::<G>(p5, n), opt_mut::<G>(q5, n));
    let (mu_m, mu_0) = (&mu_m[..n], &mu_0[..n]);
    let (m0, m1, m2, m3, m4) = (&m0[..n], &m1[..n], &m2[..n], &m3[..n], &m4[..n]);
    let (c0, c1, c2, c3, c4) = (&c0[..n], &c1[..n], &c2[..n], &c3[..n], &c4[..n]);
    let (n0, n1, n2, n3, n4) = (&n0[..n], &n1[..n], &n2[..n], &n3[..n], &n4[..n]);
    let (p1, p2, p3, p4) = (&mut p1[..n], &mut p2[..n], &mut p3[..n], &mut p4[..n]);
    let (q0, q1, q2, q3, q4) = (
        &mut q0[..n],
        &mut q1[..n],
        &mut q2[..n],
        &mut q3[..n],
        &mut q4[..n],
    );
    for k in 0..n {
        let (a, b) = (mu_0[k], mu_m[k]);
        let sm = |m: f64, c: f64, p: f64| c + a * (p - c) - b * (c - m);
        let s = [
            sm(m0[k], c0[k], n0[k]),
            if RZ {
                sm(m1[k], c1[k], n1[k]) - hoop[k] * c1[k]
            } else {
                sm(m1[k], c1[k], n1[k])
            },
            sm(m2[k], c2[k], n2[k]),
            sm(m3[k], c3[k], n3[k]),
            sm(m4[k], c4[k], n4[k]),
        ];
        let s5 = if G::SPECIES {
            sm(m5[k], c5[k], n5[k])
        } else {
            0.0
        };
        let (fl, f5) = flux::<AXIS, G>(eos, s, s5);
        if G::SPECIES {
            p5[k] = s5;
            q5[k] = f5;
        }
        p0[k] = s[0];
        p1[k] = s[1];
        p2[k] = s[2];
        p3[k] = s[3];
        p4[k] = s[4];
        q0[k] = fl[0];
        q1[k] = fl[1];
        q2[k] = fl[2];
        q3[k] = fl[3];
        q4[k] = fl[4];
    }
}

/// Pass 4 on one row: the Richtmyer half-step state at each face and its
/// flux. Every slice is a separate argument so the compiler knows the
/// outputs alias none of the inputs and vectorises the loop.
#[inline(always)]
pub(super) fn predictor_row<const AXIS: usize, G: GasLaw>(
    eos: &G,
    half_lambda: f64,
    u0: [&[f64]; NMAX],
    up: [&[f64]; NMAX],
    f0: [&[f64]; NMAX],
    fp: [&[f64]; NMAX],
    out: [&mut [f64]; NMAX],
) {
    let [a0, a1, a2, a3, a4, a5] = u0;
    let [b0, b1, b2, b3, b4, b5] = up;
    let [c0, c1, c2, c3, c4, c5] = f0;
    let [d0, d1, d2, d3, d4, d5] = fp;
    let [o0, o1, o2, o3, o4, o5] = out;
    predictor_kernel::<AXIS, G>(
        eos,
        half_lambda,
        a0,
        a1,
        a2,
        a3,
        a4,
        b0,
        b1,
        b2,
        b3,
        b4,
        c0,
        c1,
        c2,
        c3,
        c4,
        d0,
        d1,
        d2,
        d3,
        d4,
        o0,
        o1,
        o2,
        o3,
        o4,
        [a5, b5, c5, d5],
        o5,
    );
}

#[inline(never)]
#[allow(clippy::too_many_arguments)]
fn predictor_kernel<const AXIS: usize, G: GasLaw>(
    eos: &G,
    half_lambda: f64,
    a0: &[f64],
    a1: &[f64],
    a2: &[f64],
    a3: &[f64],
    a4: &[f64],
    b0: &[f64],
    b1: &[f64],
    b2: &[f64],
    b3: &[f64],
    b4: &[f64],
    c0: &[f64],
    c1: &[f64],
    c2: &[f64],
    c3: &[f64],
    c4: &[f64],
    d0: &[f64],
    d1: &[f64],
    d2: &[f64],
    d3: &[f64],
    d4: &[f64],
    o0: &mut [f64],
    o1: &mut [f64],
    o2: &mut [f64],
    o3: &mut [f64],
    o4: &mut [f64],
    species: [&[f64]; 4],
    o5: &mut [f64],
) {
    let n = o0.len();
    let [a5, b5, c5, d5] = species.map(|x| opt::<G>(x, n));
    let o5 = opt_mut::<G>(o5, n);
    let (a0, a1, a2, a3, a4) = (&a0[..n], &a1[..n], &a2[..n], &a3[..n], &a4[..n]);
    let (b0, b1, b2, b3, b4) = (&b0[..n], &b1[..n], &b2[..n], &b3[..n], &b4[..n]);
    let (c0, c1, c2, c3, c4) = (&c0[..n], &c1[..n], &c2[..n], &c3[..n], &c4[..n]);
    let (d0, d1, d2, d3, d4) = (&d0[..n], &d1[..n], &d2[..n], &d3[..n], &d4[..n]);
    let (o1, o2, o3, o4) = (&mut o1[..n], &mut o2[..n], &mut o3[..n], &mut o4[..n]);
    for k in 0..n {
        let h = |a: f64, b: f64, c: f64, d: f64| 0.5 * (a + b) - half_lambda * (d - c);
        let s = [
            h(a0[k], b0[k], c0[k], d0[k]),
            h(a1[k], b1[k], c1[k], d1[k]),
            h(a2[k], b2[k], c2[k], d2[k]),
            h(a3[k], b3[k], c3[k], d3[k]),
            h(a4[k], b4[k], c4[k], d4[k]),
        ];
        let s5 = if G::SPECIES {
            h(a5[k], b5[k], c5[k], d5[k])
        } else {
            0.0
        };
        let (fl, f5) = flux::<AXIS, G>(eos, s, s5);
        if G::SPECIES {
            o5[k] = f5;
        }
        o0[k] = fl[0];
        o1[k] = fl[1];
        o2[k] = fl[2];
        o3[k] = fl[3];
        o4[k] = fl[4];
    }
}

/// Pass 4 of a radial sweep on one row: the Richtmyer half step with the
/// geometric source of the quasi-linear radial equations
/// ∂U/∂t + ∂F/∂r = −H/r, H = u_r (ρ, ρu_r, ρu_z, ρu_θ, E + p) (ρY u_r),
/// taken at the face r_f from the mean of the two cells' H:
/// U* = ½(Ū_a + Ū_{a+1}) − ½λ(F_{a+1} − F_a) − ½λβ(H_a + H_{a+1}),
/// β = Δr/(2r_f) ([`RadialWeights::source`]). H is F without the
/// pressure: F itself but for the radial momentum, (ρu_r)²/ρ. At rest H
/// is 0 and U* is the planar half step's to the bit.
///
/// [`RadialWeights::source`]: super::RadialWeights::source
#[inline(never)]
#[allow(clippy::too_many_arguments)]
pub(super) fn predictor_rz_kernel<G: GasLaw>(
    eos: &G,
    half_lambda: f64,
    beta: &[f64],
    u0: [&[f64]; NMAX],
    up: [&[f64]; NMAX],
    f0: [&[f64]; NMAX],
    fp: [&[f64]; NMAX],
    out: [&mut [f64]; NMAX],
    pstar: &mut [f64],
) {
    let n = beta.len();
    let pstar = &mut pstar[..n];
    let [a0, a1, a2, a3, a4, a5] = cut::<G>(u0, n);
    let [b0, b1, b2, b3, b4, b5] = cut::<G>(up, n);
    let [c0, c1, c2, c3, c4, c5] = cut::<G>(f0, n);
    let [d0, d1, d2, d3, d4, d5] = cut::<G>(fp, n);
    let [o0, o1, o2, o3, o4, o5] = out;
    let o5 = opt_mut::<G>(o5, n);
    let (o0, o1, o2, o3, o4) = (
        &mut o0[..n],
        &mut o1[..n],
        &mut o2[..n],
        &mut o3[..n],
        &mut o4[..n],
    );
    for k in 0..n {
        let hb = half_lambda * beta[k];
        let h = |a: f64, b: f64, c: f64, d: f64, ha: f64, hb_: f64| {
            0.5 * (a + b) - half_lambda * (d - c) - hb * (ha + hb_)
        };
        let (m0, m1) = (a1[k] * a1[k] / a0[k], b1[k] * b1[k] / b0[k]);
        let s = [
            h(a0[k], b0[k], c0[k], d0[k], c0[k], d0[k]),
            h(a1[k], b1[k], c1[k], d1[k], m0, m1),
            h(a2[k], b2[k], c2[k], d2[k], c2[k], d2[k]),
            h(a3[k], b3[k], c3[k], d3[k], c3[k], d3[k]),
            h(a4[k], b4[k], c4[k], d4[k], c4[k], d4[k]),
        ];
        let s5 = if G::SPECIES {
            h(a5[k], b5[k], c5[k], d5[k], c5[k], d5[k])
        } else {
            0.0
        };
        let (fl, f5, p) = flux_and_pressure::<0, G>(eos, s, s5);
        pstar[k] = p;
        if G::SPECIES {
            o5[k] = f5;
        }
        o0[k] = fl[0];
        o1[k] = fl[1];
        o2[k] = fl[2];
        o3[k] = fl[3];
        o4[k] = fl[4];
    }
}

/// Face limiter, per cell: the velocity along the sweep u_d = (ρu_d)/ρ.
#[inline(never)]
pub(super) fn velocity_kernel(rho: &[f64], m: &[f64], out: &mut [f64]) {
    let n = out.len();
    let (rho, m) = (&rho[..n], &m[..n]);
    for k in 0..n {
        out[k] = m[k] / rho[k];
    }
}
