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
//!
//! On an axisymmetric (r, z) grid the x sweep is the radial one and takes
//! [`RadialWeights`]: the finite-volume form of the same two steps (seed
//! 001 eqs 3 and 7–9) with the ring faces 2π r_± Δz and the ring volume
//! π(r₊² − r₋²)Δz, whose ratio AΔr/V is α_± = r_±/r_c (r_c the cell's mid
//! radius), and the hoop source p̂(A₊ − A₋)/V of the radial momentum
//! (`docs/physics/axisymmetric.md`):
//!
//! Ū_i = U_i + α₊ μ₊ (U_{i+1} − U_i) − α₋ μ₋ (U_i − U_{i−1})
//!       − ½(μ₊ + μ₋)(α₊ − α₋)² ρu_r e_r,
//! U*_{i+½} = (the planar half step) − ½λβ (H_i + H_{i+1}),
//! U_i^{new} = Ū_i − λ (α₊ F*₊ − α₋ F*₋) + λ (α₊ − α₋) p̂_i e_r,
//!
//! with the hoop term of the vector Laplacian on the radial momentum,
//! the quasi-linear geometric source H = u_r(ρ, ρu, E + p) of the
//! predictor (β = Δr/(2r_f), `predictor_rz_kernel`), and p̂_i the mean
//! of the predictor's pressures at the cell's two faces, time-centred
//! (`hoop_pressure_kernel`); the momentum row is written
//! λ(α₊(F*₊ − p̂_i) − α₋(F*₋ − p̂_i)) so that a uniform gas at rest, whose
//! face fluxes are exactly p̂_i, stays at rest to the bit. Forming p̂ in
//! the first ghost cells takes passes 1–4 one row further
//! ([`GHOST_RZ`]). The axial (y) sweep is the planar one: a ring's two
//! axial faces are the same annulus, A/V = 1/Δz.

use crate::gas::GasLaw;
use crate::limiter::{
    admissible, density_range, density_share, face_share, is_compressive, FaceLimiter, FlowState,
};
use crate::state::{NVAR, SPECIES};
use crate::viscosity::{adaptive_eta, face_mu, switch_theta, ArtificialViscosity};

/// Ghost layers the sweep needs on each side.
pub const GHOST: usize = 4;

/// Ghost layers an axisymmetric grid needs along r: one more than
/// [`GHOST`], since the hoop source's pressure is the mean of the
/// predictor's pressures at a cell's two faces, and the face limiter
/// needs it in the first ghost cell beyond each end of a slab.
pub const GHOST_RZ: usize = GHOST + 1;

/// Ghost layers a level of `geometry` needs: [`GHOST`], or [`GHOST_RZ`] on
/// an axisymmetric grid.
pub fn ghost_layers(geometry: brisance_core::Geometry) -> usize {
    if geometry.is_axisymmetric() {
        GHOST_RZ
    } else {
        GHOST
    }
}

/// Most conservative variables per cell: the five flow variables and ρY.
const NMAX: usize = NVAR + 1;

/// Number of scratch arrays per slab for `nf` variables: θ, ν, μ, p,
/// Ū (nf), F(Ū) (nf), F* (nf), and the face limiter's work arrays
/// (velocity, 2ρ·ρe, U^L (nf), λF^L (nf)).
const fn nscratch(nf: usize) -> usize {
    8 + 5 * nf
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
    /// Whether the slab's low end along the sweep is the domain's low
    /// face: the face limiter counts the faces of the slab's interior
    /// cells on their high side, and the low face only then, so every
    /// face is counted once whatever the patch split.
    pub at_low: bool,
}

impl SlabShape {
    /// Whether the face on the high side of scratch row `i / width`
    /// counts as this slab's (see [`Self::at_low`]).
    #[inline]
    fn owns_face(&self, i: usize) -> bool {
        self.at_low || i / self.width.max(1) >= self.ghost
    }

    fn scratch_len(&self) -> usize {
        self.dims_a * self.width.max(1)
    }
}

/// The ring weights of the cells of a radial (x) sweep on an axisymmetric
/// grid, per row along the sweep (ghosts included, indexed like the
/// slab's rows): α₊ = r₊/r_c and α₋ = r₋/r_c, the ratio of a face's area
/// times Δr to the ring's volume (seed 001 §2.1 in finite-volume form,
/// `docs/physics/axisymmetric.md`); α₊ + α₋ = 2. A ghost row behind a
/// reflective face (the axis, a wall) gets its mirror cell's weights with
/// α₊ and α₋ exchanged, so the mirrored state sweeps as the image of its
/// cell and nothing crosses the face.
#[derive(Debug, Clone, Copy)]
pub struct RadialWeights<'a> {
    /// α₊ of each row.
    pub plus: &'a [f64],
    /// α₋ of each row.
    pub minus: &'a [f64],
    /// β = Δr/(2 r_f) of the face on each row's high side, the weight of
    /// the geometric source of the predictor; 0 at the axis and at a
    /// reflective domain face.
    pub source: &'a [f64],
}

impl RadialWeights<'_> {
    /// The weights [α₊, α₋, β] of the rows of a radial sweep: `dims` rows,
    /// row a the global column `first + a` (< 0 or ≥ `cells` for ghost
    /// rows) of a grid of `cells` columns from r0 on, spaced dr; `mirror`
    /// says whether the low and the high face are reflective.
    pub fn rows(
        r0: f64,
        dr: f64,
        first: i64,
        dims: usize,
        cells: usize,
        mirror: [bool; 2],
    ) -> [Vec<f64>; 3] {
        let n = cells as i64;
        let mut out = [vec![0.0; dims], vec![0.0; dims], vec![0.0; dims]];
        #[allow(clippy::needless_range_loop)]
        for a in 0..dims {
            let i = first + a as i64;
            let (col, swap) = if i < 0 && mirror[0] {
                (-1 - i, true)
            } else if i >= n && mirror[1] {
                (2 * n - 1 - i, true)
            } else {
                (i, false)
            };
            let lo = r0 + col as f64 * dr;
            let (hi, mid) = (lo + dr, lo + 0.5 * dr);
            let (p, m) = (hi.abs() / mid.abs(), lo.abs() / mid.abs());
            (out[0][a], out[1][a]) = if swap { (m, p) } else { (p, m) };
            // The face on the high side of column i, at r0 + (i + 1) dr.
            let face = r0 + (i + 1) as f64 * dr;
            let wall = (i + 1 == 0 && mirror[0]) || (i + 1 == n && mirror[1]);
            out[2][a] = if wall || face <= 0.0 {
                0.0
            } else {
                dr / (2.0 * face)
            };
        }
        out
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

/// The rows of `a` cut to `n`: the five flow-variable rows, and the ρY row
/// with a species (empty without), so a kernel's loop over them runs free
/// of bounds checks and vectorises.
#[inline(always)]
fn cut<G: GasLaw>(a: [&[f64]; NMAX], n: usize) -> [&[f64]; NMAX] {
    [
        &a[0][..n],
        &a[1][..n],
        &a[2][..n],
        &a[3][..n],
        &a[4][..n],
        opt::<G>(a[5], n),
    ]
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

/// Pass 5 of a radial sweep on one row of a variable without a source:
/// U = Ū − λ(α₊F*₊ − α₋F*₋).
#[inline(never)]
#[allow(clippy::too_many_arguments)]
fn update_rz_kernel(
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
fn update_rz_momentum_kernel(
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
fn species_update_rz_kernel(
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
fn hoop_pressure_kernel(p_minus: &[f64], p_plus: &[f64], out: &mut [f64]) {
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
fn weighted_mu_kernel(
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
fn smooth_kernel<const AXIS: usize, const RZ: bool, G: GasLaw>(
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

/// Pass 4 of a radial sweep on one row: the Richtmyer half step with the
/// geometric source of the quasi-linear radial equations
/// ∂U/∂t + ∂F/∂r = −H/r, H = u_r (ρ, ρu_r, ρu_z, ρu_θ, E + p) (ρY u_r),
/// taken at the face r_f from the mean of the two cells' H:
/// U* = ½(Ū_a + Ū_{a+1}) − ½λ(F_{a+1} − F_a) − ½λβ(H_a + H_{a+1}),
/// β = Δr/(2r_f) ([`RadialWeights::source`]). H is F without the
/// pressure: F itself but for the radial momentum, (ρu_r)²/ρ. At rest H
/// is 0 and U* is the planar half step's to the bit.
#[inline(never)]
#[allow(clippy::too_many_arguments)]
fn predictor_rz_kernel<G: GasLaw>(
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
fn velocity_kernel(rho: &[f64], m: &[f64], out: &mut [f64]) {
    let n = out.len();
    let (rho, m) = (&rho[..n], &m[..n]);
    for k in 0..n {
        out[k] = m[k] / rho[k];
    }
}

/// λf(U) along `AXIS` of one cell (flow variables and ρY) and its
/// λ(|u_d| + c), from its velocity along the sweep `v`, pressure `p` and
/// ν = λc: the one expression both limiter paths use, so they agree to the
/// bit.
#[inline(always)]
fn cell_flux<const AXIS: usize>(
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
fn rusanov_face(fa: f64, fb: f64, ua: f64, ub: f64, s: f64) -> f64 {
    0.5 * (fa + fb) - 0.5 * s * (ub - ua)
}

/// Face limiter, per cell of one row: the flux of U along the sweep
/// scaled by λ, λf(U) (flow variables and ρY), and the cell's λ(|u_d| + c)
/// (velocities, ν = λc and p of the cells from the passes before). Each
/// output slice a separate argument, so the loop vectorises.
#[inline(never)]
#[allow(clippy::too_many_arguments)]
fn cell_flux_kernel<const AXIS: usize, G: GasLaw>(
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
fn rusanov_kernel<G: GasLaw>(
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
fn low_order_kernel<G: GasLaw>(
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
fn low_order_rz_kernel<G: GasLaw>(
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
#[allow(clippy::too_many_arguments)]
unsafe fn face_limiter<const AXIS: usize, G: GasLaw>(
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
#[allow(clippy::too_many_arguments)]
unsafe fn bounds_limiter<const AXIS: usize, G: GasLaw>(
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
fn row_is_positive(r: &[f64], mx: &[f64], my: &[f64], mz: &[f64], en: &[f64]) -> bool {
    let n = r.len();
    let (mx, my, mz, en) = (&mx[..n], &my[..n], &mz[..n], &en[..n]);
    let mut ok = true;
    for k in 0..n {
        let q2 = 2.0 * r[k] * en[k] - (mx[k] * mx[k] + my[k] * my[k] + mz[k] * mz[k]);
        ok &= (r[k] > 0.0) & (q2 > 0.0) & (q2 < f64::INFINITY);
    }
    ok
}

/// What the face limiter does in one attempt at a sweep.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum LimiterPass {
    /// Nothing: the scheme of seed 001 as printed.
    Off,
    /// The first attempt: the density bounds at compressive faces when
    /// `bounds` (`bounds_limiter`, [`crate::limiter`]), then a check that every update stays
    /// positive ([`SlabOutcome::positive`]).
    First {
        /// Keep the local density bounds at compressive faces.
        bounds: bool,
    },
    /// The attempt after a first one that failed the check: positivity at
    /// every face and, with `bounds`, the density bounds
    /// (`face_limiter`, [`crate::limiter`]).
    Full {
        /// Keep the local density bounds at compressive faces.
        bounds: bool,
    },
}

/// What the sweep of one slab found.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct SlabOutcome {
    /// Every state the sweep read was physical (ρ > 0, 0 < p < ∞).
    pub physical: bool,
    /// Every update keeps ρ > 0 and e > 0 (true when not checked:
    /// [`LimiterPass::Off`] and [`LimiterPass::Full`]).
    pub positive: bool,
    /// Faces whose flux the face limiter changed: for positivity, and for
    /// the density bounds at a shock.
    pub limited_faces: [u64; 2],
}

impl SlabOutcome {
    /// Both slabs' findings: physical if both were, faces added.
    pub fn and(self, other: Self) -> Self {
        Self {
            physical: self.physical & other.physical,
            positive: self.positive & other.positive,
            limited_faces: [0, 1].map(|b| self.limited_faces[b] + other.limited_faces[b]),
        }
    }

    /// Nothing found yet: the identity of [`Self::and`].
    pub const NONE: Self = Self {
        physical: true,
        positive: true,
        limited_faces: [0; 2],
    };
}

/// Sweeps one slab along `AXIS` with λ = Δt_s/Δx. The outcome is not
/// `physical` if a cell read by the sweep had non-positive density or
/// pressure or a non-finite value (the caller then locates it and stops
/// the run). With a `limiter`, the face fluxes are limited towards the
/// Rusanov flux where the update would leave the bounds
/// (`face_limiter`, [`crate::limiter`]); the outcome counts the faces changed.
///
/// The face fluxes at the slab's two ends, with the fluxes the update
/// uses (after the limiter), are added to `outflow` where it points
/// ([`FaceOutflow`]): the interior's change is exactly their difference,
/// so the domain totals plus the accumulated outflow are conserved to
/// round-off.
///
/// The update is written into `out`, arrays of the same shape as
/// `fields` (the solver's second buffer), so `fields` is left as it was
/// and a sweep can be taken again from it.
///
/// # Safety
/// The caller guarantees that while this runs no other thread writes any
/// cell of this slab (rows `a ∈ [0, dims_a)` at `base + a·stride_a`) in
/// `fields`, that `out` is not `fields`, and that no other thread reads or
/// writes the interior rows this call writes in `out`. Slabs of one patch
/// (distinct k-planes for x/y sweeps, distinct j-planes for z sweeps)
/// satisfy this. Non-null `outflow` pointers point to one accumulator per
/// lane that no other thread touches during the call.
#[allow(clippy::too_many_arguments)]
pub unsafe fn sweep_slab<const AXIS: usize, G: GasLaw>(
    eos: &G,
    viscosity: ArtificialViscosity,
    pass: LimiterPass,
    lambda: f64,
    fields: &PatchPtrs,
    out: &PatchPtrs,
    shape: &SlabShape,
    radial: Option<RadialWeights>,
    outflow: FaceOutflow,
    scratch: &mut Vec<f64>,
) -> SlabOutcome {
    debug_assert!(AXIS == 0 || radial.is_none());
    debug_assert!(radial.is_none_or(|w| w.plus.len() >= shape.dims_a && shape.width == 0));
    let n = shape.scratch_len();
    let nf = if G::SPECIES { NMAX } else { NVAR };
    debug_assert_eq!(fields.species, G::SPECIES);
    if scratch.len() < nscratch(nf) * n {
        scratch.resize(nscratch(nf) * n, 0.0);
    }
    let (theta, rest) = scratch.split_at_mut(n);
    let (nu, rest) = rest.split_at_mut(n);
    let (mu, rest) = rest.split_at_mut(n);
    let (pres, rest) = rest.split_at_mut(n);
    let (ubar, rest) = rest.split_at_mut(nf * n);
    let (fbar, rest) = rest.split_at_mut(nf * n);
    let (fstar, rest) = rest.split_at_mut(nf * n);
    let (work, rest) = rest.split_at_mut((2 + 2 * nf) * n);
    let (pstar, rest) = rest.split_at_mut(n);
    let psrc = &mut rest[..n];
    // A radial sweep reaches one row further for the predictor's
    // pressures at the faces of the first ghost cells ([`GHOST_RZ`]).
    let e = usize::from(radial.is_some());
    let g = shape.ghost;
    let hi_cell = shape.dims_a - g; // one past the last interior cell
    let (sa, ss) = (
        shape.stride_a,
        if shape.width == 0 { 1 } else { shape.width },
    );
    let mut ok = true;

    // Pass 1: θ (eq 4) and ν = λc per cell, for a ∈ [g−3, hi+3).
    for_rows(shape, g - 3 - e, hi_cell + 3 + e, |fo, so, len| {
        let rho_m = fields.row(0, fo - sa, len);
        let rho_p = fields.row(0, fo + sa, len);
        let u: [&[f64]; NVAR] = per_var!(|f| fields.row(f, fo, len));
        let th = &mut theta[so..so + len];
        let nv = &mut nu[so..so + len];
        let pr = &mut pres[so..so + len];
        let [r, mx, my, mz, en] = u;
        let ry = [
            fields.species_row::<G>(fo - sa, len),
            fields.species_row::<G>(fo, len),
            fields.species_row::<G>(fo + sa, len),
        ];
        ok &= cells_kernel(eos, lambda, rho_m, rho_p, r, mx, my, mz, en, ry, th, nv, pr);
    });

    // Pass 2: face coefficients μ_{a+½} for a ∈ [g−2, hi+1).
    for_rows(shape, g - 2 - e, hi_cell + 1 + e, |_, so, len| {
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
    for_rows(shape, g - 1 - e, hi_cell + 1 + e, |fo, so, len| {
        let um: [&[f64]; NVAR] = per_var!(|f| fields.row(f, fo - sa, len));
        let u0: [&[f64]; NVAR] = per_var!(|f| fields.row(f, fo, len));
        let up: [&[f64]; NVAR] = per_var!(|f| fields.row(f, fo + sa, len));
        let (mut mu_m, mut mu_0) = (&mu[so - ss..][..len], &mu[so..][..len]);
        // A radial sweep smooths with α₋μ₋ and α₊μ₊ and the hoop term of
        // the radial momentum (the limiter's work arrays are free until
        // pass 4).
        let mut hoop: &[f64] = &[];
        if let Some(w) = radial {
            let (wm, rest) = work.split_at_mut(n);
            let (wp, wh) = rest.split_at_mut(n);
            let (wm, wp, wh) = (
                &mut wm[so..][..len],
                &mut wp[so..][..len],
                &mut wh[so..][..len],
            );
            weighted_mu_kernel(&w.plus[so..], &w.minus[so..], mu_m, mu_0, wm, wp, wh);
            mu_m = wm;
            mu_0 = wp;
            hoop = wh;
        }
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
        if radial.is_some() {
            smooth_kernel::<AXIS, true, G>(
                eos, hoop, mu_m, mu_0, m0, m1, m2, m3, m4, c0, c1, c2, c3, c4, n0, n1, n2, n3, n4,
                p0, p1, p2, p3, p4, q0, q1, q2, q3, q4, species, p5, q5,
            );
        } else {
            smooth_kernel::<AXIS, false, G>(
                eos, hoop, mu_m, mu_0, m0, m1, m2, m3, m4, c0, c1, c2, c3, c4, n0, n1, n2, n3, n4,
                p0, p1, p2, p3, p4, q0, q1, q2, q3, q4, species, p5, q5,
            );
        }
    });

    // Pass 4: Richtmyer half step at faces a+½ for a ∈ [g−1, hi).
    let half_lambda = 0.5 * lambda;
    for_rows(shape, g - 1 - e, hi_cell + e, |_, so, len| {
        let rows = |a, o| rows_at::<G>(a, o, len);
        let (u0, up) = (rows(&ubar, so), rows(&ubar, so + ss));
        let (f0, fp) = (rows(&fbar, so), rows(&fbar, so + ss));
        let out = rows_at_mut::<G>(&mut fstar, so, len);
        match radial {
            None => predictor_row::<AXIS, G>(eos, half_lambda, u0, up, f0, fp, out),
            Some(w) => {
                let beta = &w.source[so..][..len];
                let ps = &mut pstar[so..][..len];
                predictor_rz_kernel::<G>(eos, half_lambda, beta, u0, up, f0, fp, out, ps);
            }
        }
    });

    // The hoop source's pressure of rows [g − 1, hi]: the mean of the
    // predictor's at the cell's two faces, time-centred as the fluxes.
    if radial.is_some() {
        for_rows(shape, g - 1, hi_cell + 1, |_, so, len| {
            hoop_pressure_kernel(
                &pstar[so - 1..][..len],
                &pstar[so..][..len],
                &mut psrc[so..][..len],
            );
        });
    }
    let psrc = &*psrc;

    // Whether the update is checked for positivity after it is written.
    let (limited, check) = match pass {
        LimiterPass::Off => ([0; 2], false),
        LimiterPass::First { bounds } => {
            let n = if bounds {
                bounds_limiter::<AXIS, G>(
                    lambda, fields, shape, radial, pres, nu, mu, theta, work, &mut fstar,
                )
            } else {
                0
            };
            ([0, n], true)
        }
        LimiterPass::Full { bounds } => {
            let l = if bounds {
                FaceLimiter::Full
            } else {
                FaceLimiter::Positivity
            };
            let n = face_limiter::<AXIS, G>(
                l, lambda, fields, shape, radial, pres, psrc, nu, mu, theta, work, &mut fstar,
            );
            (n, false)
        }
    };

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

    // Pass 5: conservative update of the interior, a ∈ [g, hi), into `out`
    // (checked for positivity row by row on a first attempt).
    let mut positive = true;
    for_rows(shape, g, hi_cell, |fo, so, len| {
        for f in 0..NVAR {
            let out = out.row_mut(f, fo, len);
            let ub = &ubar[f][so..][..len];
            let fp = &fstar[f][so..][..len];
            let fm = &fstar[f][so - ss..][..len];
            match radial {
                None => update_kernel(lambda, ub, fm, fp, out),
                Some(w) => {
                    let (ap, am) = (&w.plus[so..], &w.minus[so..]);
                    if f == 1 {
                        let p = &psrc[so..];
                        update_rz_momentum_kernel(lambda, ap, am, p, ub, fm, fp, out);
                    } else {
                        update_rz_kernel(lambda, ap, am, ub, fm, fp, out);
                    }
                }
            }
        }
        if G::SPECIES {
            let rho = out.row(0, fo, len);
            let out = out.row_mut(SPECIES, fo, len);
            let ub = &ubar[SPECIES][so..][..len];
            let fp = &fstar[SPECIES][so..][..len];
            let fm = &fstar[SPECIES][so - ss..][..len];
            match radial {
                None => species_update_kernel(lambda, ub, fm, fp, rho, out),
                Some(w) => {
                    let (ap, am) = (&w.plus[so..], &w.minus[so..]);
                    species_update_rz_kernel(lambda, ap, am, ub, fm, fp, rho, out);
                }
            }
        }
        if check {
            let [r, mx, my, mz, en] = per_var!(|f| out.row(f, fo, len));
            positive &= row_is_positive(r, mx, my, mz, en);
        }
    });
    SlabOutcome {
        physical: ok,
        positive,
        limited_faces: limited,
    }
}
