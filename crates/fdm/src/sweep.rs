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

use brisance_core::Eos;

use crate::state::NVAR;
use crate::viscosity::{switch_theta, ArtificialViscosity};

/// Ghost layers the sweep needs on each side.
pub const GHOST: usize = 4;

/// Number of scratch arrays per slab: θ, ν, μ, Ū (5), F(Ū) (5), F* (5).
const NSCRATCH: usize = 3 + 3 * NVAR;

/// Raw pointers to the five conservative arrays of one patch, so that slabs
/// of the same patch can be swept by different threads.
#[derive(Debug, Clone, Copy)]
pub struct PatchPtrs {
    ptr: [*mut f64; NVAR],
    len: usize,
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
        assert!(data.len() == NVAR && data.iter().all(|v| v.len() == len));
        Self {
            ptr: std::array::from_fn(|f| data[f].as_mut_ptr()),
            len,
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

/// The `NVAR` arrays of length `n` stored one after another in `buf`.
fn split_vars(buf: &mut [f64], n: usize) -> [&mut [f64]; NVAR] {
    let mut parts = buf.chunks_exact_mut(n);
    std::array::from_fn(|_| parts.next().expect("buffer holds NVAR arrays"))
}

/// Flux along `AXIS` of a conservative state (seed 001 eq 2), and pressure.
#[inline(always)]
fn flux<const AXIS: usize, E: Eos>(eos: &E, u: [f64; NVAR]) -> [f64; NVAR] {
    let rho = u[0];
    // One division per state: multiply by 1/ρ for e and the normal velocity.
    let inv = 1.0 / rho;
    let e = (u[4] - 0.5 * (u[1] * u[1] + u[2] * u[2] + u[3] * u[3]) * inv) * inv;
    let p = eos.pressure(rho, e);
    let vn = u[1 + AXIS] * inv;
    let mut f = [
        u[1 + AXIS],
        u[1] * vn,
        u[2] * vn,
        u[3] * vn,
        (u[4] + p) * vn,
    ];
    f[1 + AXIS] += p;
    f
}

/// Sweeps one slab along `AXIS` with λ = Δt_s/Δx. Returns `false` if a cell
/// read by the sweep had non-positive density or pressure or a non-finite
/// value (the caller then locates it and stops the run).
///
/// # Safety
/// The caller guarantees that while this runs no other thread writes any
/// cell of this slab (rows `a ∈ [0, dims_a)` at `base + a·stride_a`) and no
/// other thread reads the interior rows this call writes. Slabs of one patch
/// (distinct k-planes for x/y sweeps, distinct j-planes for z sweeps) satisfy
/// this.
#[allow(clippy::too_many_arguments)]
pub unsafe fn sweep_slab<const AXIS: usize, E: Eos>(
    eos: &E,
    viscosity: ArtificialViscosity,
    lambda: f64,
    fields: &PatchPtrs,
    shape: &SlabShape,
    scratch: &mut Vec<f64>,
) -> bool {
    let n = shape.scratch_len();
    if scratch.len() < NSCRATCH * n {
        scratch.resize(NSCRATCH * n, 0.0);
    }
    let (theta, rest) = scratch.split_at_mut(n);
    let (nu, rest) = rest.split_at_mut(n);
    let (mu, rest) = rest.split_at_mut(n);
    let (ubar, rest) = rest.split_at_mut(NVAR * n);
    let (fbar, rest) = rest.split_at_mut(NVAR * n);
    let fstar = &mut rest[..NVAR * n];
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
        for k in 0..len {
            let rho = u[0][k];
            let inv = 1.0 / rho;
            let e = (u[4][k]
                - 0.5 * (u[1][k] * u[1][k] + u[2][k] * u[2][k] + u[3][k] * u[3][k]) * inv)
                * inv;
            let p = eos.pressure(rho, e);
            ok &= (rho > 0.0) & (p > 0.0) & (p < f64::INFINITY);
            th[k] = switch_theta(rho_m[k], rho, rho_p[k]);
            nv[k] = lambda * eos.sound_speed(rho, e);
        }
    });

    // Pass 2: face coefficients μ_{a+½} for a ∈ [g−2, hi+1).
    for_rows(shape, g - 2, hi_cell + 1, |_, so, len| {
        let tm = &theta[so - ss..][..len];
        let t0 = &theta[so..][..len];
        let tp = &theta[so + ss..][..len];
        let tpp = &theta[so + 2 * ss..][..len];
        let (n0, np) = (&nu[so..][..len], &nu[so + ss..][..len]);
        let m = &mut mu[so..][..len];
        for k in 0..len {
            let theta_face = tm[k].max(t0[k]).max(tp[k]).max(tpp[k]);
            m[k] = viscosity.face_coefficient(theta_face, n0[k], np[k]);
        }
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
        let ub = ubar.each_mut().map(|a| &mut a[so..][..len]);
        let fb = fbar.each_mut().map(|a| &mut a[so..][..len]);
        for k in 0..len {
            let (a, b) = (mu_0[k], mu_m[k]);
            let s: [f64; NVAR] =
                per_var!(|f| u0[f][k] + a * (up[f][k] - u0[f][k]) - b * (u0[f][k] - um[f][k]));
            let fl = flux::<AXIS, E>(eos, s);
            ub[0][k] = s[0];
            ub[1][k] = s[1];
            ub[2][k] = s[2];
            ub[3][k] = s[3];
            ub[4][k] = s[4];
            fb[0][k] = fl[0];
            fb[1][k] = fl[1];
            fb[2][k] = fl[2];
            fb[3][k] = fl[3];
            fb[4][k] = fl[4];
        }
    });

    // Pass 4: Richtmyer half step at faces a+½ for a ∈ [g−1, hi).
    let half_lambda = 0.5 * lambda;
    for_rows(shape, g - 1, hi_cell, |_, so, len| {
        let u0: [&[f64]; NVAR] = per_var!(|f| &ubar[f][so..][..len]);
        let up: [&[f64]; NVAR] = per_var!(|f| &ubar[f][so + ss..][..len]);
        let f0: [&[f64]; NVAR] = per_var!(|f| &fbar[f][so..][..len]);
        let fp: [&[f64]; NVAR] = per_var!(|f| &fbar[f][so + ss..][..len]);
        let fs = fstar.each_mut().map(|a| &mut a[so..][..len]);
        for k in 0..len {
            let s: [f64; NVAR] =
                per_var!(|f| 0.5 * (u0[f][k] + up[f][k]) - half_lambda * (fp[f][k] - f0[f][k]));
            let fl = flux::<AXIS, E>(eos, s);
            fs[0][k] = fl[0];
            fs[1][k] = fl[1];
            fs[2][k] = fl[2];
            fs[3][k] = fl[3];
            fs[4][k] = fl[4];
        }
    });

    // Pass 5: conservative update of the interior, a ∈ [g, hi).
    for_rows(shape, g, hi_cell, |fo, so, len| {
        for f in 0..NVAR {
            let out = fields.row_mut(f, fo, len);
            let ub = &ubar[f][so..][..len];
            let fp = &fstar[f][so..][..len];
            let fm = &fstar[f][so - ss..][..len];
            for k in 0..len {
                out[k] = ub[k] - lambda * (fp[k] - fm[k]);
            }
        }
    });
    ok
}
