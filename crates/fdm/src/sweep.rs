//! One directional operator L_d(Δt/2) of the Yanenko splitting (seed 001
//! eq 6): the adaptive-viscosity smoothing of eq 3 followed by one
//! second-order Lax–Wendroff step for the flux along d (eqs 7–9).
//!
//! Eqs 7–9 as printed drop the flux Jacobian from the second-order term;
//! the scheme they stand for is implemented here in the two-step Richtmyer
//! form, conservative and second order:
//!
//! U*_{i+½} = ½(Ū_i + Ū_{i+1}) − ½ λ (F(Ū_{i+1}) − F(Ū_i)),
//! U_i^{new} = Ū_i − λ (F(U*_{i+½}) − F(U*_{i−½})),  λ = Δt_s/Δx.
//!
//! The kernel works on a *slab* (one k-plane for x and y sweeps, one j-plane
//! for z sweeps) of one patch and runs five passes over it, each a loop over
//! contiguous slices that the compiler vectorises:
//! 1. per cell: the switch θ (eq 4) and the acoustic Courant number ν;
//! 2. per face: μ = ½ η max(θ) over the four cells around it (eqs 3, 5);
//! 3. per cell: smoothed Ū (eq 3, flux form) and its flux F(Ū);
//! 4. per face: the Richtmyer half-step state and its flux;
//! 5. per cell: the conservative update.
//!
//! Passes 1–4 reach 4, 3, 2 and 1 cells beyond the slab's interior along the
//! sweep, so the patch needs 4 ghost layers ([`GHOST`]).
//!
//! With a second species ([`GasLaw::SPECIES`]) the partial density ρY is a
//! sixth conservative variable, smoothed with the same μ and advanced by the
//! same two-step update (flux ρY u_d); the switch θ of a cell is then the
//! larger of the density and mass-fraction switches, so a species interface
//! at uniform density is smoothed like a contact, and the updated ρY is
//! clipped to [0, ρ]. The one-species kernels compile without any of it
//! (`SPECIES` is a constant), so their arithmetic is unchanged.

use crate::gas::GasLaw;
use crate::state::{NVAR, SPECIES};
use crate::viscosity::{adaptive_eta, face_mu, switch_theta, ArtificialViscosity};

/// Ghost layers the sweep needs on each side.
pub const GHOST: usize = 4;

/// Most conservative variables per cell: the five flow variables and ρY.
const NMAX: usize = NVAR + 1;

/// Number of scratch arrays per slab for `nf` variables: θ, ν, μ, Ū (nf),
/// F(Ū) (nf), F* (nf).
const fn nscratch(nf: usize) -> usize {
    3 + 3 * nf
}

/// Raw pointers to the five (six with a species) conservative arrays of one
/// patch, so that slabs of the same patch can be swept by different threads.
#[derive(Debug, Clone, Copy)]
pub struct PatchPtrs {
    ptr: [*mut f64; NMAX],
    len: usize,
    species: bool,
}

// SAFETY: the pointers are only dereferenced by `sweep_slab`, whose callers
// guarantee that concurrently swept slabs write disjoint cells and read only
// cells no other thread writes during the sweep (see `sweep_slab`).
unsafe impl Send for PatchPtrs {}
unsafe impl Sync for PatchPtrs {}

impl PatchPtrs {
    /// Pointers to the conservative arrays of a patch.
    pub fn new(data: &mut [Vec<f64>]) -> Self {
        let len = data[0].len();
        assert!((data.len() == NVAR || data.len() == NMAX) && data.iter().all(|v| v.len() == len));
        let species = data.len() == NMAX;
        Self {
            ptr: std::array::from_fn(|f| {
                if f < data.len() {
                    data[f].as_mut_ptr()
                } else {
                    std::ptr::null_mut()
                }
            }),
            len,
            species,
        }
    }

    /// The ρY row, or an empty slice without a species.
    ///
    /// # Safety
    /// As [`Self::row`].
    #[inline(always)]
    unsafe fn species_row<G: GasLaw>(&self, start: usize, len: usize) -> &[f64] {
        if G::SPECIES {
            self.row(SPECIES, start, len)
        } else {
            &[]
        }
    }

    /// # Safety
    /// `start + len` within the array and no concurrent writer of the range.
    #[inline(always)]
    unsafe fn row(&self, f: usize, start: usize, len: usize) -> &[f64] {
        debug_assert!(start + len <= self.len);
        std::slice::from_raw_parts(self.ptr[f].add(start), len)
    }

    /// # Safety
    /// `start + len` within the array and no other reader or writer of the
    /// range during the borrow.
    #[inline(always)]
    #[allow(clippy::mut_from_ref)]
    unsafe fn row_mut(&self, f: usize, start: usize, len: usize) -> &mut [f64] {
        debug_assert!(start + len <= self.len);
        std::slice::from_raw_parts_mut(self.ptr[f].add(start), len)
    }
}

/// Shape of the slab a sweep works on.
#[derive(Debug, Clone, Copy)]
pub struct SlabShape {
    /// Cells along the sweep direction, ghosts included.
    pub dims_a: usize,
    /// Ghost layers along the sweep direction.
    pub ghost: usize,
    /// Field-index offset between neighbours along the sweep.
    pub stride_a: usize,
    /// Field index of the first cell of row `a` is `base + a·stride_a`
    /// (x sweep: the line's first cell; y/z sweeps: the first interior x).
    pub base: usize,
    /// Cells per call across the sweep (y/z sweeps: interior x cells; x
    /// sweep: 0, meaning a single line).
    pub width: usize,
}

impl SlabShape {
    fn scratch_len(&self) -> usize {
        self.dims_a * self.width.max(1)
    }
}

/// Where a sweep adds what crossed the domain faces at the two ends of its
/// slab, per lane (one x line, or the cells across a y or z slab, in
/// order): the five flow variables per unit cell volume that left through
/// the face, Φ = λ F*₊½ − μ₊½ (U_{a+1} − U_a) at the high end and −Φ at
/// the low end. A null pointer: that end is no domain face (a patch
/// boundary, or a periodic face, whose fluxes cancel in pairs).
#[derive(Debug, Clone, Copy)]
pub struct FaceOutflow {
    /// The lanes' accumulators at the low end, or null.
    pub low: *mut [f64; NVAR],
    /// The lanes' accumulators at the high end, or null.
    pub high: *mut [f64; NVAR],
}

// SAFETY: as for `PatchPtrs`: concurrently swept slabs are given disjoint
// accumulator ranges (a domain face cell belongs to one slab of a sweep).
unsafe impl Send for FaceOutflow {}
unsafe impl Sync for FaceOutflow {}

impl FaceOutflow {
    /// The accumulators `n` lanes on, an end kept only where its flag is
    /// set (null otherwise).
    ///
    /// # Safety
    /// `n` must lie within the arrays the non-null ends point into.
    pub unsafe fn lanes_on(self, n: usize, low: bool, high: bool) -> Self {
        let at = |p: *mut [f64; NVAR], keep: bool| {
            if keep && !p.is_null() {
                p.add(n)
            } else {
                std::ptr::null_mut()
            }
        };
        Self {
            low: at(self.low, low),
            high: at(self.high, high),
        }
    }
}

/// Runs `f(field_start, scratch_start, len)` for the cells `a ∈ [lo, hi)` of
/// the slab: one call for an x line, one call per row for y/z slabs.
#[inline(always)]
fn for_rows(s: &SlabShape, lo: usize, hi: usize, mut f: impl FnMut(usize, usize, usize)) {
    if s.width == 0 {
        f(s.base + lo, lo, hi - lo);
    } else {
        for a in lo..hi {
            f(s.base + a * s.stride_a, a * s.width, s.width);
        }
    }
}

/// `[e(0), e(1), ..., e(4)]` written out, so inner loops stay free of
/// closure calls (`std::array::from_fn` is not always inlined there).
macro_rules! per_var {
    (|$f:ident| $e:expr) => {
        [
            {
                let $f = 0;
                $e
            },
            {
                let $f = 1;
                $e
            },
            {
                let $f = 2;
                $e
            },
            {
                let $f = 3;
                $e
            },
            {
                let $f = 4;
                $e
            },
        ]
    };
}

/// The `nf` arrays of length `n` stored one after another in `buf`; the
/// species array is empty when `nf == NVAR`.
fn split_vars(buf: &mut [f64], n: usize) -> [&mut [f64]; NMAX] {
    let mut parts = buf.chunks_exact_mut(n);
    std::array::from_fn(|f| match parts.next() {
        Some(p) => p,
        None => {
            assert!(f == SPECIES, "buffer holds NVAR arrays");
            &mut []
        }
    })
}

/// `a[i][so..so + len]` for each scratch array; the species entry is empty
/// without a species. Written out: no closure calls, no runtime test.
#[inline(always)]
fn rows_at<'a, G: GasLaw>(a: &'a [&mut [f64]; NMAX], so: usize, len: usize) -> [&'a [f64]; NMAX] {
    [
        &a[0][so..][..len],
        &a[1][so..][..len],
        &a[2][so..][..len],
        &a[3][so..][..len],
        &a[4][so..][..len],
        if G::SPECIES { &a[5][so..][..len] } else { &[] },
    ]
}

/// Mutable [`rows_at`].
#[inline(always)]
fn rows_at_mut<'a, G: GasLaw>(
    a: &'a mut [&mut [f64]; NMAX],
    so: usize,
    len: usize,
) -> [&'a mut [f64]; NMAX] {
    let [a0, a1, a2, a3, a4, a5] = a;
    [
        &mut a0[so..][..len],
        &mut a1[so..][..len],
        &mut a2[so..][..len],
        &mut a3[so..][..len],
        &mut a4[so..][..len],
        if G::SPECIES {
            &mut a5[so..][..len]
        } else {
            &mut []
        },
    ]
}

/// `&a[..n]` with a species, an empty slice without (never indexed then).
#[inline(always)]
fn opt<G: GasLaw>(a: &[f64], n: usize) -> &[f64] {
    if G::SPECIES {
        &a[..n]
    } else {
        &a[..0]
    }
}

/// Mutable [`opt`].
#[inline(always)]
fn opt_mut<G: GasLaw>(a: &mut [f64], n: usize) -> &mut [f64] {
    if G::SPECIES {
        &mut a[..n]
    } else {
        &mut a[..0]
    }
}

/// Flux along `AXIS` of a conservative state (seed 001 eq 2) with partial
/// density `ry` (ignored without a species), and the flux ρY u_d.
#[inline(always)]
fn flux<const AXIS: usize, G: GasLaw>(eos: &G, u: [f64; NVAR], ry: f64) -> ([f64; NVAR], f64) {
    let rho = u[0];
    // One division per state: multiply by 1/ρ for e and the normal velocity.
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
    (f, ry * vn)
}

/// Pass 1 on one row: the switch θ (eq 4) and the acoustic Courant number
/// ν = λc per cell; returns whether every state was physical.
#[inline(never)]
#[allow(clippy::too_many_arguments)]
fn cells_kernel<G: GasLaw>(
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
) -> bool {
    let n = th.len();
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
    }
    ok
}

/// Pass 2 on one row: μ at each face from the four switches around it.
#[inline(never)]
#[allow(clippy::too_many_arguments)]
fn faces_kernel(
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
fn species_update_kernel(
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
fn update_kernel(lambda: f64, ubar: &[f64], f_minus: &[f64], f_plus: &[f64], out: &mut [f64]) {
    let n = out.len();
    let (ubar, f_minus, f_plus) = (&ubar[..n], &f_minus[..n], &f_plus[..n]);
    for k in 0..n {
        out[k] = ubar[k] - lambda * (f_plus[k] - f_minus[k]);
    }
}

/// Pass 3 on one row: the smoothed state Ū (eq 3, flux form) and its flux.
/// Separate slice arguments tell the compiler the outputs alias nothing,
/// so the loop vectorises.
#[inline(never)]
#[allow(clippy::too_many_arguments)]
fn smooth_kernel<const AXIS: usize, G: GasLaw>(
    eos: &G,
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
            sm(m1[k], c1[k], n1[k]),
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
fn predictor_row<const AXIS: usize, G: GasLaw>(
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

/// |u_d| + c of a conservative state (c = 0 where the state gives none).
#[inline]
fn signal_speed<const AXIS: usize, G: GasLaw>(eos: &G, u: [f64; NVAR], ry: f64) -> f64 {
    let inv = 1.0 / u[0];
    let e = (u[4] - 0.5 * (u[1] * u[1] + u[2] * u[2] + u[3] * u[3]) * inv) * inv;
    let y = if G::SPECIES { ry * inv } else { 0.0 };
    let c = eos.gas_sound_speed(u[0], e, y);
    (u[1 + AXIS] * inv).abs() + if c.is_finite() { c } else { 0.0 }
}

/// Whether the update U = Ū − λ(F*₊ − F*₋) of scratch cell `i` (faces
/// `i − ss` and `i`) keeps ρ > 0 and e > 0.
#[inline]
fn update_is_positive(
    lambda: f64,
    ubar: &[&mut [f64]; NMAX],
    fstar: &[&mut [f64]; NMAX],
    i: usize,
    ss: usize,
) -> bool {
    let u: [f64; NVAR] = per_var!(|f| ubar[f][i] - lambda * (fstar[f][i] - fstar[f][i - ss]));
    state_is_positive(u)
}

/// ρ > 0 and a positive, finite internal energy per volume
/// E − ½|ρu|²/ρ (e > 0 and e < ∞, so NaN fails); `&` rather than `&&` so
/// that a loop over states vectorises.
#[inline(always)]
fn state_is_positive(u: [f64; NVAR]) -> bool {
    let e = u[4] - 0.5 * (u[1] * u[1] + u[2] * u[2] + u[3] * u[3]) / u[0];
    (u[0] > 0.0) & (e > 0.0) & (e < f64::INFINITY)
}

/// Whether every interior update of the sweep keeps ρ > 0 and a positive,
/// finite internal energy: [`update_is_positive`] for all scratch cells
/// `lo..hi` at once. The interior rows are one contiguous range of the
/// scratch (row a at a·ss), so this is one flat loop the compiler
/// vectorises; the cell-by-cell rounds run only when it finds a cell that
/// fails (rare: near a strong rarefaction into vacuum).
fn all_updates_positive(
    lambda: f64,
    ubar: &[&mut [f64]; NMAX],
    fstar: &[&mut [f64]; NMAX],
    lo: usize,
    hi: usize,
    ss: usize,
) -> bool {
    let n = hi - lo;
    let u: [&[f64]; NVAR] = per_var!(|f| &ubar[f][lo..hi]);
    let fp: [&[f64]; NVAR] = per_var!(|f| &fstar[f][lo..hi]);
    let fm: [&[f64]; NVAR] = per_var!(|f| &fstar[f][lo - ss..hi - ss]);
    let mut ok = true;
    for k in 0..n {
        ok &= state_is_positive(per_var!(|f| u[f][k] - lambda * (fp[f][k] - fm[f][k])));
    }
    ok
}

/// The positivity fallback between passes 4 and 5: for every interior
/// cell whose Lax–Wendroff update would leave ρ ≤ 0 or e ≤ 0 (internal
/// energy per volume), the Richtmyer fluxes F* at both its faces are
/// replaced by the local Lax–Friedrichs (Rusanov) flux of the smoothed
/// states, F = ½(F(Ū_L) + F(Ū_R)) − ½ s (Ū_R − Ū_L), s = max(|u_d| + c)
/// of the two (Rusanov 1961; Toro, *Riemann Solvers*, 3rd ed., §10.5.1),
/// positivity preserving for λ s ≤ 1 (Perthame & Shu, Numer. Math. 73,
/// 1996). A face is shared, so the update stays conservative; a neighbour
/// whose update the new face flux spoils is caught by the next of up to
/// three rounds. Cells whose update is positive keep the second-order
/// fluxes, so the scheme is unchanged wherever it is well.
fn positivity_fallback<const AXIS: usize, G: GasLaw>(
    eos: &G,
    lambda: f64,
    shape: &SlabShape,
    ubar: &[&mut [f64]; NMAX],
    fbar: &[&mut [f64]; NMAX],
    fstar: &mut [&mut [f64]; NMAX],
) {
    let g = shape.ghost;
    let hi = shape.dims_a - g;
    let lanes = shape.width.max(1);
    let ss = lanes;
    let nf = if G::SPECIES { NMAX } else { NVAR };
    if all_updates_positive(lambda, ubar, fstar, g * ss, hi * ss, ss) {
        return;
    }
    let state = |i: usize| -> ([f64; NVAR], f64) {
        let u: [f64; NVAR] = per_var!(|f| ubar[f][i]);
        (u, if G::SPECIES { ubar[SPECIES][i] } else { 0.0 })
    };
    for _round in 0..3 {
        let mut changed = false;
        for a in g..hi {
            for j in 0..lanes {
                let i = a * ss + j;
                if update_is_positive(lambda, ubar, fstar, i, ss) {
                    continue;
                }
                // Faces a − ½ (left cell i − ss) and a + ½ (left cell i).
                for left in [i - ss, i] {
                    let right = left + ss;
                    let (ul, yl) = state(left);
                    let (ur, yr) = state(right);
                    let s = signal_speed::<AXIS, G>(eos, ul, yl)
                        .max(signal_speed::<AXIS, G>(eos, ur, yr));
                    for f in 0..nf {
                        fstar[f][left] = 0.5 * (fbar[f][left] + fbar[f][right])
                            - 0.5 * s * (ubar[f][right] - ubar[f][left]);
                    }
                }
                changed = true;
            }
        }
        if !changed {
            break;
        }
    }
}

/// Sweeps one slab along `AXIS` with λ = Δt_s/Δx. Returns `false` if a cell
/// read by the sweep had non-positive density or pressure or a non-finite
/// value (the caller then locates it and stops the run). With `fallback`,
/// a cell whose update would leave ρ ≤ 0 or e ≤ 0 gets the Rusanov flux
/// at both its faces ([`positivity_fallback`]).
///
/// The face fluxes at the slab's two ends, with the fluxes the update
/// uses (after the fallback), are added to `outflow` where it points
/// ([`FaceOutflow`]): the interior's change is exactly their difference,
/// so the domain totals plus the accumulated outflow are conserved to
/// round-off.
///
/// # Safety
/// The caller guarantees that while this runs no other thread writes any
/// cell of this slab (rows `a ∈ [0, dims_a)` at `base + a·stride_a`) and no
/// other thread reads the interior rows this call writes. Slabs of one patch
/// (distinct k-planes for x/y sweeps, distinct j-planes for z sweeps) satisfy
/// this. Non-null `outflow` pointers point to one accumulator per lane
/// that no other thread touches during the call.
#[allow(clippy::too_many_arguments)]
pub unsafe fn sweep_slab<const AXIS: usize, G: GasLaw>(
    eos: &G,
    viscosity: ArtificialViscosity,
    fallback: bool,
    lambda: f64,
    fields: &PatchPtrs,
    shape: &SlabShape,
    outflow: FaceOutflow,
    scratch: &mut Vec<f64>,
) -> bool {
    let n = shape.scratch_len();
    let nf = if G::SPECIES { NMAX } else { NVAR };
    debug_assert_eq!(fields.species, G::SPECIES);
    if scratch.len() < nscratch(nf) * n {
        scratch.resize(nscratch(nf) * n, 0.0);
    }
    let (theta, rest) = scratch.split_at_mut(n);
    let (nu, rest) = rest.split_at_mut(n);
    let (mu, rest) = rest.split_at_mut(n);
    let (ubar, rest) = rest.split_at_mut(nf * n);
    let (fbar, rest) = rest.split_at_mut(nf * n);
    let fstar = &mut rest[..nf * n];
    let g = shape.ghost;
    let hi_cell = shape.dims_a - g; // one past the last interior cell
    let (sa, ss) = (
        shape.stride_a,
        if shape.width == 0 { 1 } else { shape.width },
    );
    let mut ok = true;

    // Pass 1: θ (eq 4) and ν = λc per cell, for a ∈ [g−3, hi+3).
    for_rows(shape, g - 3, hi_cell + 3, |fo, so, len| {
        let rho_m = fields.row(0, fo - sa, len);
        let rho_p = fields.row(0, fo + sa, len);
        let u: [&[f64]; NVAR] = per_var!(|f| fields.row(f, fo, len));
        let th = &mut theta[so..so + len];
        let nv = &mut nu[so..so + len];
        let [r, mx, my, mz, en] = u;
        let ry = [
            fields.species_row::<G>(fo - sa, len),
            fields.species_row::<G>(fo, len),
            fields.species_row::<G>(fo + sa, len),
        ];
        ok &= cells_kernel(eos, lambda, rho_m, rho_p, r, mx, my, mz, en, ry, th, nv);
    });

    // Pass 2: face coefficients μ_{a+½} for a ∈ [g−2, hi+1).
    for_rows(shape, g - 2, hi_cell + 1, |_, so, len| {
        let tm = &theta[so - ss..][..len];
        let t0 = &theta[so..][..len];
        let tp = &theta[so + ss..][..len];
        let tpp = &theta[so + 2 * ss..][..len];
        let (n0, np) = (&nu[so..][..len], &nu[so + ss..][..len]);
        let m = &mut mu[so..][..len];
        faces_kernel(viscosity, tm, t0, tp, tpp, n0, np, m);
    });

    let mut ubar = split_vars(ubar, n);
    let mut fbar = split_vars(fbar, n);
    let mut fstar = split_vars(fstar, n);

    // Pass 3: Ū (eq 3 in flux form) and F(Ū) for a ∈ [g−1, hi+1).
    for_rows(shape, g - 1, hi_cell + 1, |fo, so, len| {
        let um: [&[f64]; NVAR] = per_var!(|f| fields.row(f, fo - sa, len));
        let u0: [&[f64]; NVAR] = per_var!(|f| fields.row(f, fo, len));
        let up: [&[f64]; NVAR] = per_var!(|f| fields.row(f, fo + sa, len));
        let mu_m = &mu[so - ss..][..len];
        let mu_0 = &mu[so..][..len];
        let [p0, p1, p2, p3, p4, p5] = rows_at_mut::<G>(&mut ubar, so, len);
        let [q0, q1, q2, q3, q4, q5] = rows_at_mut::<G>(&mut fbar, so, len);
        let [m0, m1, m2, m3, m4] = um;
        let [c0, c1, c2, c3, c4] = u0;
        let [n0, n1, n2, n3, n4] = up;
        let species = [
            fields.species_row::<G>(fo - sa, len),
            fields.species_row::<G>(fo, len),
            fields.species_row::<G>(fo + sa, len),
        ];
        smooth_kernel::<AXIS, G>(
            eos, mu_m, mu_0, m0, m1, m2, m3, m4, c0, c1, c2, c3, c4, n0, n1, n2, n3, n4, p0, p1,
            p2, p3, p4, q0, q1, q2, q3, q4, species, p5, q5,
        );
    });

    // Pass 4: Richtmyer half step at faces a+½ for a ∈ [g−1, hi).
    let half_lambda = 0.5 * lambda;
    for_rows(shape, g - 1, hi_cell, |_, so, len| {
        let rows = |a, o| rows_at::<G>(a, o, len);
        let (u0, up) = (rows(&ubar, so), rows(&ubar, so + ss));
        let (f0, fp) = (rows(&fbar, so), rows(&fbar, so + ss));
        let out = rows_at_mut::<G>(&mut fstar, so, len);
        predictor_row::<AXIS, G>(eos, half_lambda, u0, up, f0, fp, out);
    });

    if fallback {
        positivity_fallback::<AXIS, G>(eos, lambda, shape, &ubar, &fbar, &mut fstar);
    }

    // What crosses the domain faces: face g − ½ (left row g − 1) and face
    // hi − ½ (left row hi − 1), read before pass 5 overwrites U.
    for (ptr, a, sign) in [(outflow.low, g - 1, -1.0), (outflow.high, hi_cell - 1, 1.0)] {
        if ptr.is_null() {
            continue;
        }
        for j in 0..shape.width.max(1) {
            let (i, fo) = (a * ss + j, shape.base + a * sa + j);
            // SAFETY: one accumulator per lane, this call's alone.
            let acc = &mut *ptr.add(j);
            for (f, out) in acc.iter_mut().enumerate() {
                let (u0, u1) = (fields.row(f, fo, 1)[0], fields.row(f, fo + sa, 1)[0]);
                *out += sign * (lambda * fstar[f][i] - mu[i] * (u1 - u0));
            }
        }
    }

    // Pass 5: conservative update of the interior, a ∈ [g, hi).
    for_rows(shape, g, hi_cell, |fo, so, len| {
        for f in 0..NVAR {
            let out = fields.row_mut(f, fo, len);
            let ub = &ubar[f][so..][..len];
            let fp = &fstar[f][so..][..len];
            let fm = &fstar[f][so - ss..][..len];
            update_kernel(lambda, ub, fm, fp, out);
        }
        if G::SPECIES {
            let out = fields.row_mut(SPECIES, fo, len);
            let rho = fields.row(0, fo, len);
            let ub = &ubar[SPECIES][so..][..len];
            let fp = &fstar[SPECIES][so..][..len];
            let fm = &fstar[SPECIES][so - ss..][..len];
            species_update_kernel(lambda, ub, fm, fp, rho, out);
        }
    });
    ok
}
