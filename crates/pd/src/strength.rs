//! A critical stretch that varies over the material: Weibull-distributed
//! grain strengths on a grain field fixed in space.
//!
//! Seed 004 gives every bond of its steel the same critical stretch. A
//! uniform strength has no counterpart of the spread of fracture strains
//! that sets the fragment size in Mott's theory of shell break-up
//! (N. F. Mott, "Fragmentation of shell cases", Proc. R. Soc. Lond. A 189
//! (1947) 300–308; D. E. Grady, *Fragmentation of Rings and Shells*,
//! Springer 2006, ch. 2–3), and on a cubic lattice the break-up follows the
//! lattice (docs/physics/pd/validation.md). This module is the documented
//! variant: the node's critical stretch s_c0 is multiplied by a strength
//! factor f(x) drawn once per grain of a grain field,
//!
//! ```text
//! f = (−ln(1 − U) / ln 2)^{1/m},   U uniform on [0, 1),
//! ```
//!
//! a Weibull variable of modulus m and median 1, so s_c0 stays the median
//! critical stretch and m → ∞ recovers the printed model. The Weibull
//! law is the usual one for a spread of fracture strains (Grady 2006
//! §2.4; Weibull, J. Appl. Mech. 18 (1951) 293). Its hazard rises as
//! m/ε near ε = s_c0, the counterpart of Mott's e^{γε}: γ ≈ m / s_c0.
//!
//! **The grain field.** Space is cut into cubes of side ℓ (the grain size,
//! a material property) anchored at the origin; each cube holds one grain
//! centre at a uniform random point of the cube and one strength factor,
//! and a point takes the factor of the nearest centre (a jittered-grid
//! Voronoi tessellation with mean grain volume ℓ³). Every draw comes from a
//! ChaCha8 stream keyed by (seed, cube index), so a node's factor depends
//! on its position, the seed and ℓ only: not on the lattice spacing, node
//! order, thread count or rank split. Refining the lattice samples the
//! same field more finely, which is what lets a fragment size converge.
//! Ties in distance go to the first cube in (x, y, z) order.
//!
//! The bond's critical stretch stays min(s_c(x_i), s_c(x_j)) (module
//! [`crate::material`]): the weaker grain breaks the bond.

use rand_chacha::rand_core::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use serde::{Deserialize, Serialize};

/// Weibull-distributed critical stretch on a grain field.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct StretchSpread {
    /// Weibull modulus m of the strength factor (> 0; larger is narrower).
    pub weibull_modulus: f64,
    /// Grain size ℓ, m: the side of the cube that holds one grain (> 0).
    pub grain_size: f64,
    /// Seed of the grain field.
    #[serde(default)]
    pub seed: u64,
}

impl StretchSpread {
    /// Checks the parameters; the error names the field.
    pub fn validate(&self) -> Result<(), String> {
        for (f, v) in [
            ("weibull_modulus", self.weibull_modulus),
            ("grain_size", self.grain_size),
        ] {
            if !(v > 0.0 && v.is_finite()) {
                return Err(format!("`spread.{f}` = {v}: expected a finite value > 0"));
            }
        }
        Ok(())
    }

    /// The Weibull quantile of median 1: f(U) = (−ln(1 − U)/ln 2)^{1/m}.
    pub fn quantile(&self, u: f64) -> f64 {
        (-(-u).ln_1p() / std::f64::consts::LN_2).powf(1.0 / self.weibull_modulus)
    }

    /// The grain of cube `c`: its centre (m) and strength factor.
    pub fn grain(&self, c: [i64; 3]) -> ([f64; 3], f64) {
        let mut key = [0u8; 32];
        key[..8].copy_from_slice(&self.seed.to_le_bytes());
        for d in 0..3 {
            key[8 + 8 * d..16 + 8 * d].copy_from_slice(&c[d].to_le_bytes());
        }
        let mut rng = ChaCha8Rng::from_seed(key);
        let mut unit = || (rng.next_u64() >> 11) as f64 * (1.0 / (1u64 << 53) as f64);
        let l = self.grain_size;
        let centre = [
            (c[0] as f64 + unit()) * l,
            (c[1] as f64 + unit()) * l,
            (c[2] as f64 + unit()) * l,
        ];
        (centre, self.quantile(unit()))
    }

    /// The strength factor at point `x`: the factor of the nearest grain
    /// centre (the centres of the cubes within two of x's cube; no centre
    /// farther out can be nearer than x's own, at most √3 ℓ away).
    pub fn factor_at(&self, x: [f64; 3]) -> f64 {
        let l = self.grain_size;
        let home = [0, 1, 2].map(|d| (x[d] / l).floor() as i64);
        let mut best = (f64::INFINITY, 1.0);
        for i in -2..=2 {
            for j in -2..=2 {
                for k in -2..=2 {
                    let (g, f) = self.grain([home[0] + i, home[1] + j, home[2] + k]);
                    let r2 = (g[0] - x[0]).powi(2) + (g[1] - x[1]).powi(2) + (g[2] - x[2]).powi(2);
                    if r2 < best.0 {
                        best = (r2, f);
                    }
                }
            }
        }
        best.1
    }

    /// The factors at many points, in parallel; the same bits as
    /// [`Self::factor_at`] point by point.
    pub fn factors(&self, points: &[[f64; 3]]) -> Vec<f64> {
        use rayon::prelude::*;
        points.par_iter().map(|&x| self.factor_at(x)).collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    fn spread() -> StretchSpread {
        StretchSpread {
            weibull_modulus: 8.0,
            grain_size: 2.0e-3,
            seed: 7,
        }
    }

    #[test]
    fn the_quantile_by_hand() {
        let s = spread();
        // Median 1.
        assert_eq!(s.quantile(0.5), 1.0);
        // U = 1 − 2^{−1.2^8}, 1.2^8 = 4.29981696: f = 1.2.
        let u = 1.0 - 2f64.powf(-4.29981696);
        assert!((s.quantile(u) - 1.2).abs() < 1e-12, "{}", s.quantile(u));
        // U = 0.1: (−ln 0.9 / ln 2)^{1/8} = 0.152003093^{0.125} = 0.790021.
        assert!((s.quantile(0.1) - 0.152003093445_f64.powf(0.125)).abs() < 1e-9);
        assert_eq!(s.quantile(0.0), 0.0);
    }

    #[test]
    fn the_empirical_median_and_spread_are_weibull() {
        // 20 000 grains: the median factor within 2 % of 1, and the share
        // below the 10 % quantile within 1 % of 10 %.
        let s = spread();
        let mut f: Vec<f64> = (0..20_000)
            .map(|n| s.grain([n % 40, (n / 40) % 25, n / 1000]).1)
            .collect();
        f.sort_by(f64::total_cmp);
        assert!((f[10_000] - 1.0).abs() < 0.02, "median {}", f[10_000]);
        let q10 = s.quantile(0.1);
        let below = f.iter().filter(|&&v| v < q10).count() as f64 / 2.0e4;
        assert!((below - 0.1).abs() < 0.01, "{below}");
    }

    #[test]
    fn a_grain_centre_takes_its_own_factor_and_lies_in_its_cube() {
        let s = spread();
        for c in [[0, 0, 0], [-3, 5, 11], [7, -1, -9]] {
            let (g, f) = s.grain(c);
            for d in 0..3 {
                assert!(g[d] >= c[d] as f64 * s.grain_size);
                assert!(g[d] < (c[d] + 1) as f64 * s.grain_size);
            }
            assert_eq!(s.factor_at(g), f);
        }
    }

    #[test]
    fn seeds_give_different_fields() {
        let a = spread();
        let b = StretchSpread { seed: 8, ..a };
        assert_ne!(a.grain([1, 2, 3]), b.grain([1, 2, 3]));
        assert_eq!(a.grain([1, 2, 3]), spread().grain([1, 2, 3]));
    }

    #[test]
    fn a_bad_parameter_names_its_field() {
        let e = StretchSpread {
            weibull_modulus: 0.0,
            ..spread()
        }
        .validate()
        .unwrap_err();
        assert!(e.contains("spread.weibull_modulus"), "{e}");
        let e = StretchSpread {
            grain_size: f64::NAN,
            ..spread()
        }
        .validate()
        .unwrap_err();
        assert!(e.contains("spread.grain_size"), "{e}");
    }

    proptest! {
        /// The field is a nearest-centre tessellation: the factor at any
        /// point is that of the nearest of the 7³ centres around it (a
        /// brute-force search over a wider block), it is positive, and it
        /// does not depend on how many points are asked at once.
        #[test]
        fn the_factor_is_the_nearest_grains(
            x in -0.02f64..0.02, y in -0.02f64..0.02, z in -0.02f64..0.02,
        ) {
            let s = spread();
            let l = s.grain_size;
            let home = [x, y, z].map(|v| (v / l).floor() as i64);
            let mut best = (f64::INFINITY, 0.0);
            for i in -3..=3 {
                for j in -3..=3 {
                    for k in -3..=3 {
                        let (g, f) = s.grain([home[0] + i, home[1] + j, home[2] + k]);
                        let r2 = (g[0] - x).powi(2) + (g[1] - y).powi(2) + (g[2] - z).powi(2);
                        if r2 < best.0 {
                            best = (r2, f);
                        }
                    }
                }
            }
            let f = s.factor_at([x, y, z]);
            prop_assert_eq!(f, best.1);
            prop_assert!(f > 0.0);
            prop_assert_eq!(s.factors(&[[x, y, z], [y, z, x]])[0], f);
        }
    }
}
