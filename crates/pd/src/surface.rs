//! Surface correction of proportional bonds by the energy method
//! (Madenci & Oterkus, *Peridynamic Theory and Its Applications*, Springer
//! 2014, §4.3; Le & Bobaru 2018, "Surface corrections for peridynamic
//! models in elasticity and fracture", Comput. Mech. 61, 499–518).
//!
//! A node near a free surface misses part of its family and is too soft
//! (the "skin effect"); a thin bar of a few horizons across is then
//! markedly softer than E. For each solid node i and each direction k the
//! strain energy density under a uniform *uniaxial stress* along k (strain
//! ε along k, −νε across, ν = 1/4, so a bond of direction n stretches by
//! s = ε((1 + ν)n_k² − ν)) is compared with the continuum value ½Eε²:
//!
//! ```text
//! g_i^k = W_∞ / W_i^k,   W_i^k ∝ Σ_j β_j ((1 + ν) n_k² − ν)² r_j V_j,
//! W_∞ ∝ ∫_H ((1 + ν) n_k² − ν)² r dV = πδ⁴/6 (3D),   Aδ² (1D),
//! ```
//!
//! (the common factor c ε²/4 cancels). Madenci & Oterkus load by uniaxial
//! *strain* (s = ε n_k²); Brisance loads by uniaxial stress because its
//! bodies are bars, plates and thin tube walls whose surfaces are
//! traction-free: measured on the V-PD-WAVE bar (60 × 10 × 10 nodes) the
//! uniaxial-strain factors make the bar 2.5 % too stiff, the uniaxial-
//! stress factors 1.6 %, and no correction 3.5 % too soft. A bond (i, j) of direction n takes
//! ḡ = (g_i + g_j)/2 and the factor G = [Σ_k (n_k/ḡ_k)²]^{−1/2} (the
//! ellipsoid interpolation of Madenci & Oterkus), which is symmetric in i
//! and j. Because W_∞ is the continuum value, the correction also removes
//! the lattice quadrature error of interior nodes.

use crate::family::Families;
use crate::forces::BondLaw;
use crate::Dimension;

/// Multiplies the weight of every bond between solid nodes by its surface
/// correction factor G.
#[allow(clippy::too_many_arguments)]
pub fn apply_surface_correction(
    reference: &[[f64; 4]],
    families: &Families,
    material: &[u16],
    laws: &[BondLaw],
    dimension: Dimension,
    horizon: f64,
    cross_section: f64,
    factor: &mut [f32],
) {
    let n = reference.len();
    let solid = |i: usize| matches!(laws[material[i] as usize], BondLaw::Solid { .. });
    let w_inf = match dimension {
        Dimension::Three => std::f64::consts::PI * horizon.powi(4) / 6.0,
        Dimension::One => cross_section * horizon * horizon,
    };
    let unit = |i: usize, j: usize| {
        let d = [
            reference[j][0] - reference[i][0],
            reference[j][1] - reference[i][1],
            reference[j][2] - reference[i][2],
        ];
        let r = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
        (d.map(|c| c / r), r)
    };
    let g: Vec<[f64; 3]> = (0..n)
        .map(|i| {
            if !solid(i) {
                return [1.0; 3];
            }
            let mut w = [0.0; 3];
            for k in families.row(i) {
                let j = families.neighbours[k] as usize;
                let (e, r) = unit(i, j);
                let bv = factor[k] as f64 * reference[j][3] * r;
                for d in 0..3 {
                    let s = match dimension {
                        Dimension::One => 1.0,
                        Dimension::Three => 1.25 * e[d] * e[d] - 0.25,
                    };
                    w[d] += bv * s * s;
                }
            }
            w.map(|w| if w > 0.0 { w_inf / w } else { 1.0 })
        })
        .collect();
    for i in 0..n {
        if !solid(i) {
            continue;
        }
        for k in families.row(i) {
            let j = families.neighbours[k] as usize;
            let (e, _) = unit(i, j);
            let gm: [f64; 3] = std::array::from_fn(|d| 0.5 * (g[i][d] + g[j][d]));
            let big_g = match dimension {
                Dimension::One => gm[0],
                Dimension::Three => {
                    let s: f64 = (0..3).map(|d| (e[d] / gm[d]).powi(2)).sum();
                    1.0 / s.sqrt()
                }
            };
            factor[k] = (factor[k] as f64 * big_g) as f32;
        }
    }
}
