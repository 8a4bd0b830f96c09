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
use crate::limiter::FaceLimiter;
use crate::state::{NVAR, SPECIES};
use crate::viscosity::ArtificialViscosity;

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
pub(crate) const NMAX: usize = NVAR + 1;

/// Number of scratch arrays per slab for `nf` variables: θ, ν, μ, p,
/// Ū (nf), F(Ū) (nf), F* (nf), and the face limiter's work arrays
/// (velocity, 2ρ·ρe, U^L (nf), λF^L (nf)).
pub(crate) const fn nscratch(nf: usize) -> usize {
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

// Declared after `per_var!`, so that its textual scope reaches them.
mod kernels;
mod limiters;
mod low_order;

use kernels::{
    cells_kernel, faces_kernel, hoop_pressure_kernel, predictor_row, predictor_rz_kernel,
    smooth_kernel, species_update_kernel, species_update_rz_kernel, update_kernel,
    update_rz_kernel, update_rz_momentum_kernel, weighted_mu_kernel,
};
use limiters::{bounds_limiter, face_limiter, row_is_positive};

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
