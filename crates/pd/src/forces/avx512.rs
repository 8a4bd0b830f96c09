//! The AVX-512 form of one group of eight solid bonds ([`super::solid_group`]),
//! written with explicit intrinsics so that every value stays in a 512-bit
//! (f64) or 256-bit (f32) register from the gather to the sums. Each
//! operation is the IEEE operation of the portable code, in the same
//! order and on the same operands (no fused multiply-add, the same
//! comparisons and blends for `min`, `max`, `clamp` and the branches), so
//! the bits are those of the portable kernel; a test checks this on a
//! block that yields and breaks.

use super::{SolidRow, SolidSums, LANES};
use std::arch::x86_64::*;

/// Loads the eight 32-byte records `base[js[l]]` and returns their four
/// components as lane vectors, each minus `origin[c]`.
///
/// # Safety
/// AVX-512F must be available and every `js[l]` must index the slice
/// `base` points into.
#[inline(always)]
unsafe fn transpose(base: *const [f64; 4], js: &[usize; LANES], origin: [f64; 4]) -> [__m512d; 4] {
    let pair = |a: usize, b: usize| {
        let lo = _mm256_loadu_pd(base.add(js[a]) as *const f64);
        let hi = _mm256_loadu_pd(base.add(js[b]) as *const f64);
        _mm512_insertf64x4::<1>(_mm512_castpd256_pd512(lo), hi)
    };
    let (z01, z23, z45, z67) = (pair(0, 1), pair(2, 3), pair(4, 5), pair(6, 7));
    // [component 0 of records 0..3 | component 1 of records 0..3], ...
    let even = _mm512_setr_epi64(0, 4, 8, 12, 1, 5, 9, 13);
    let odd = _mm512_setr_epi64(2, 6, 10, 14, 3, 7, 11, 15);
    let a = _mm512_permutex2var_pd(z01, even, z23);
    let b = _mm512_permutex2var_pd(z45, even, z67);
    let c = _mm512_permutex2var_pd(z01, odd, z23);
    let d = _mm512_permutex2var_pd(z45, odd, z67);
    let o = origin.map(|v| _mm512_set1_pd(v));
    [
        _mm512_sub_pd(_mm512_shuffle_f64x2::<0x44>(a, b), o[0]),
        _mm512_sub_pd(_mm512_shuffle_f64x2::<0xEE>(a, b), o[1]),
        _mm512_sub_pd(_mm512_shuffle_f64x2::<0x44>(c, d), o[2]),
        _mm512_sub_pd(_mm512_shuffle_f64x2::<0xEE>(c, d), o[3]),
    ]
}

/// One group of eight bonds; the same contract as the portable
/// [`super::solid_group`].
///
/// # Safety
/// AVX-512F, AVX-512VL and AVX2 must be available (the caller is compiled
/// with them and dispatched after a run-time check), and every `js[l]`
/// must index both `reference` and `state` (the caller clamps them).
#[inline(always)]
pub(super) unsafe fn solid_group(
    row: &SolidRow,
    reference: &[[f64; 4]],
    state: &[[f64; 4]],
    js: &[usize; LANES],
    w_io: &mut [f32; LANES],
    sp_io: &mut [f32; LANES],
    sums: &mut SolidSums,
) {
    // The caller clamps every index to both arrays (`Avx512Gather`); an
    // `assert!` of it here slowed the kernel by a third.
    debug_assert!(js.iter().all(|&j| j < reference.len() && j < state.len()));
    let (xi, ui) = (row.xi, row.ui);
    let [dx0, dx1, dx2, vol] = transpose(reference.as_ptr(), js, [xi[0], xi[1], xi[2], 0.0]);
    let [de0, de1, de2, sig] = transpose(state.as_ptr(), js, [ui[0], ui[1], ui[2], 0.0]);
    let (add, mul) = (
        |a: __m512d, b: __m512d| _mm512_add_pd(a, b),
        |a: __m512d, b: __m512d| _mm512_mul_pd(a, b),
    );
    let y = [add(dx0, de0), add(dx1, de1), add(dx2, de2)];
    let num = add(
        mul(
            _mm512_set1_pd(2.0),
            add(add(mul(dx0, de0), mul(dx1, de1)), mul(dx2, de2)),
        ),
        add(add(mul(de0, de0), mul(de1, de1)), mul(de2, de2)),
    );
    let r2 = add(add(mul(dx0, dx0), mul(dx1, dx1)), mul(dx2, dx2));
    let p2 = add(add(mul(y[0], y[0]), mul(y[1], y[1])), mul(y[2], y[2]));
    let r = _mm256_sqrt_ps(_mm512_cvtpd_ps(r2));
    // f32::max(a, b) returns b when a is NaN, as vmaxps does with b second.
    let p = _mm256_max_ps(
        _mm256_sqrt_ps(_mm512_cvtpd_ps(p2)),
        _mm256_mul_ps(_mm256_set1_ps(1e-6), r),
    );
    let ppr = _mm256_add_ps(p, r);
    let inv = _mm256_div_ps(_mm256_set1_ps(1.0), _mm256_mul_ps(_mm256_mul_ps(r, p), ppr));
    let s = _mm256_mul_ps(_mm512_cvtpd_ps(num), _mm256_mul_ps(p, inv));
    let inv_p = _mm256_mul_ps(_mm256_mul_ps(r, ppr), inv);
    let zero = _mm256_setzero_ps();
    let w_old = _mm256_loadu_ps(w_io.as_ptr());
    let mut w = w_old;
    // `w != 0.0` is true for NaN: not-equal, unordered.
    let live = _mm256_cmp_ps_mask::<_CMP_NEQ_UQ>(w, zero);
    let over = _mm256_cmp_ps_mask::<_CMP_GT_OQ>(s, _mm256_set1_ps(row.critical_stretch));
    let mut broke = false;
    if live & over != 0 {
        let crit = _mm512_cvtpd_ps(sig);
        // sci.min(crit): vminps returns its second operand, sci, when one
        // is NaN; σ_i is never NaN.
        let limit = _mm256_min_ps(crit, _mm256_set1_ps(row.node_critical_stretch));
        let broken = live & over & _mm256_cmp_ps_mask::<_CMP_GT_OQ>(s, limit);
        w = _mm256_mask_blend_ps(broken, w, zero);
        _mm256_storeu_ps(w_io.as_mut_ptr(), w);
        broke = broken != 0;
    }
    let live = _mm256_cmp_ps_mask::<_CMP_NEQ_UQ>(w, zero);
    let sy = _mm256_set1_ps(row.yield_stretch);
    let neg_sy = _mm256_set1_ps(-row.yield_stretch);
    // f32::abs: the sign bit cleared.
    let abs = |a: __m256| _mm256_andnot_ps(_mm256_set1_ps(-0.0), a);
    let (e, flow) = if row.plastic {
        let sp = _mm256_loadu_ps(sp_io.as_ptr());
        let el = _mm256_sub_ps(s, sp);
        let up = _mm256_cmp_ps_mask::<_CMP_GT_OQ>(el, sy);
        let down = _mm256_cmp_ps_mask::<_CMP_LT_OQ>(el, neg_sy);
        let shifted = _mm256_mask_blend_ps(
            up,
            _mm256_mask_blend_ps(down, sp, _mm256_add_ps(s, sy)),
            _mm256_sub_ps(s, sy),
        );
        // A broken bond keeps its last plastic stretch.
        _mm256_storeu_ps(sp_io.as_mut_ptr(), _mm256_mask_blend_ps(live, sp, shifted));
        (
            _mm256_sub_ps(s, shifted),
            _mm256_mul_ps(sy, abs(_mm256_sub_ps(shifted, sp))),
        )
    } else {
        // f32::clamp: below the minimum → minimum, then above the maximum
        // → maximum.
        let x = _mm256_mask_blend_ps(_mm256_cmp_ps_mask::<_CMP_LT_OQ>(s, neg_sy), s, neg_sy);
        (
            _mm256_mask_blend_ps(_mm256_cmp_ps_mask::<_CMP_GT_OQ>(x, sy), x, sy),
            zero,
        )
    };
    // The dissipated energy, as the portable kernel forms it: ψ on the
    // lanes broken now (β = 0 after the pass), β_old (flow + ψ) r.
    if row.plastic || broke {
        let a = abs(e);
        let stretch = if row.plastic { a } else { abs(s) };
        let psi = _mm256_mul_ps(
            a,
            _mm256_sub_ps(stretch, _mm256_mul_ps(_mm256_set1_ps(0.5), a)),
        );
        let psi = _mm256_maskz_mov_ps(!live, psi);
        let t = _mm256_mul_ps(_mm256_mul_ps(w_old, _mm256_add_ps(flow, psi)), r);
        let acc = _mm512_loadu_pd(sums.dissipated.as_ptr());
        _mm512_storeu_pd(
            sums.dissipated.as_mut_ptr(),
            add(acc, mul(_mm512_cvtps_pd(t), vol)),
        );
    }
    let g = mul(
        _mm512_cvtps_pd(_mm256_mul_ps(_mm256_mul_ps(w, e), inv_p)),
        vol,
    );
    for (acc, yd) in sums.force.iter_mut().zip(y) {
        let a = _mm512_loadu_pd(acc.as_ptr());
        _mm512_storeu_pd(acc.as_mut_ptr(), add(a, mul(g, yd)));
    }
    let intact = _mm256_loadu_si256(sums.intact.as_ptr() as *const __m256i);
    let intact = _mm256_mask_add_epi32(intact, live, intact, _mm256_set1_epi32(1));
    _mm256_storeu_si256(sums.intact.as_mut_ptr() as *mut __m256i, intact);
    // min_stretch.min(s) on live lanes: vminps returns the second operand,
    // the running minimum, when s is NaN, as f32::min does.
    let m = _mm256_loadu_ps(sums.min_stretch.as_ptr());
    let m = _mm256_mask_min_ps(m, live, s, m);
    _mm256_storeu_ps(sums.min_stretch.as_mut_ptr(), m);
}
