//! Counter-based random draws for the initial history of material points,
//! and the Gaussian distribution a config gives them.
//!
//! Seed 000 §4.2 and §5.3 start every point of the 4340 case with its own
//! porosity and damage, drawn from Gaussians (mean 0.005, standard deviation
//! 0.001 each). A solver initialises its points in any order and on any
//! number of threads, so a draw must depend on nothing but the point: here
//! it is a pure function of a 64-bit seed the solver derives from the point
//! (its initial position and material, [`point_seed`]) and of a stream tag
//! naming the variable. There is no generator state.
//!
//! **Generator.** The k-th 64-bit word of seed s is the SplitMix64 output
//! for the state s + (k + 1)γ, γ = 0x9E3779B97F4A7C15 (Steele, Lea & Flood,
//! *Fast splittable pseudorandom number generators*, OOPSLA 2014 — the
//! generator `java.util.SplittableRandom` uses; [`mix64`] is its output
//! function). A uniform u ∈ (0, 1) takes the top 52 bits plus one half,
//! u = (⌊w/2¹²⌋ + ½) 2⁻⁵², exact in f64 and so never 0 or 1 (with 53 bits
//! the largest value would round to 1). A standard normal is the
//! Box–Muller transform of two such uniforms, z = √(−2 ln u₁) cos(2π u₂)
//! (Box & Muller, Ann. Math. Stat. 29 (1958) 610), the k-th normal using
//! words 2k and 2k + 1; the sine half of the pair is not used, so each
//! normal is a function of its own index alone.
//!
//! **Truncation.** [`Gaussian::sample`] redraws (the next normal of the same
//! stream) until the value lies in [min, max]: the truncated normal, not the
//! folded one. After [`MAX_DRAWS`] rejections in a row — an interval far
//! narrower than the standard deviation — the mean is taken.
//!
//! The bits depend on the seed only; `ln` and `cos` come from the platform's
//! math library, so two platforms may differ in the last bit, but one
//! platform gives the same bits whatever the thread count or point order.

use crate::ConstitutiveError;
use serde::{Deserialize, Serialize};

/// The SplitMix64 increment γ (odd, ≈ 2⁶⁴/φ).
pub const GOLDEN_GAMMA: u64 = 0x9E37_79B9_7F4A_7C15;

/// Draws tried before a truncated sample falls back to the mean.
pub const MAX_DRAWS: u64 = 64;

/// Stream tag of the initial porosity.
pub const STREAM_POROSITY: u64 = 1;
/// Stream tag of the initial damage.
pub const STREAM_DAMAGE: u64 = 2;

/// The SplitMix64 output function: a bijection of u64 whose output bits
/// each depend on every input bit.
#[inline]
pub const fn mix64(z: u64) -> u64 {
    let z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    let z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

/// The `counter`-th word of the SplitMix64 sequence of `seed`.
#[inline]
pub const fn word(seed: u64, counter: u64) -> u64 {
    mix64(seed.wrapping_add(counter.wrapping_add(1).wrapping_mul(GOLDEN_GAMMA)))
}

/// Uniform in (0, 1) from the `counter`-th word of `seed`.
#[inline]
pub fn uniform(seed: u64, counter: u64) -> f64 {
    const SCALE: f64 = 1.0 / (1u64 << 52) as f64;
    ((word(seed, counter) >> 12) as f64 + 0.5) * SCALE
}

/// The `k`-th standard normal of `seed` (Box–Muller on words 2k, 2k + 1).
#[inline]
pub fn standard_normal(seed: u64, k: u64) -> f64 {
    let u1 = uniform(seed, 2 * k);
    let u2 = uniform(seed, 2 * k + 1);
    (-2.0 * u1.ln()).sqrt() * (std::f64::consts::TAU * u2).cos()
}

/// An independent stream of `seed` for the variable tagged `tag`.
#[inline]
pub const fn stream(seed: u64, tag: u64) -> u64 {
    mix64(seed ^ mix64(tag.wrapping_mul(GOLDEN_GAMMA)))
}

/// The seed of a material point from its initial position (m) and material
/// index: every bit of the coordinates counts, −0.0 is read as +0.0, and
/// the result does not depend on where the point sits in any list.
pub fn point_seed(position: [f64; 3], material: u16) -> u64 {
    let mut h = mix64(u64::from(material).wrapping_add(GOLDEN_GAMMA));
    for x in position {
        // x + 0.0 turns −0.0 into +0.0 and leaves every other value as is.
        h = mix64(h ^ (x + 0.0).to_bits());
    }
    h
}

/// A Gaussian distribution of an initial value over the material points,
/// optionally truncated to [min, max].
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Gaussian {
    /// Mean.
    pub mean: f64,
    /// Standard deviation (0: every point takes the mean).
    pub std_dev: f64,
    /// Lower truncation; draws below are redrawn. Default: the variable's
    /// physical lower bound.
    #[serde(default)]
    pub min: Option<f64>,
    /// Upper truncation; draws above are redrawn. Default: the variable's
    /// physical upper bound.
    #[serde(default)]
    pub max: Option<f64>,
    /// Realisation: mixed into every point's seed, so a different value
    /// gives a different, equally distributed, field.
    #[serde(default)]
    pub seed: u64,
}

impl Gaussian {
    /// A distribution with the physical bounds as truncation and
    /// realisation 0.
    pub const fn new(mean: f64, std_dev: f64) -> Self {
        Self {
            mean,
            std_dev,
            min: None,
            max: None,
            seed: 0,
        }
    }

    /// The truncation interval within the physical bounds [lo, hi].
    pub fn bounds(&self, lo: f64, hi: f64) -> (f64, f64) {
        (self.min.unwrap_or(lo), self.max.unwrap_or(hi))
    }

    /// Checks the distribution of the field `field` of `model`, whose
    /// physical range is [lo, hi]: finite mean in the truncation interval,
    /// standard deviation ≥ 0, lo ≤ min < max ≤ hi.
    pub fn validate(
        &self,
        model: &'static str,
        field: &'static str,
        lo: f64,
        hi: f64,
    ) -> Result<(), ConstitutiveError> {
        let bad = |value: f64, expected: &'static str| {
            Err(ConstitutiveError::InvalidParameter {
                model,
                field,
                value,
                expected,
            })
        };
        let (min, max) = self.bounds(lo, hi);
        if !(min.is_finite() && min >= lo) {
            return bad(min, "`min` finite and ≥ the variable's lower bound");
        }
        if !(max.is_finite() && max <= hi && max > min) {
            return bad(
                max,
                "`max` finite, above `min` and ≤ the variable's upper bound",
            );
        }
        if !(self.mean >= min && self.mean <= max) {
            return bad(self.mean, "`mean` inside [min, max]");
        }
        if !(self.std_dev.is_finite() && self.std_dev >= 0.0) {
            return bad(self.std_dev, "`std_dev` finite and ≥ 0");
        }
        Ok(())
    }

    /// The deterministic value: the mean, within [lo, hi] (the point's value
    /// when no seed is given).
    pub fn mean_within(&self, lo: f64, hi: f64) -> f64 {
        let (min, max) = self.bounds(lo, hi);
        self.mean.max(min).min(max)
    }

    /// The value of the point with seed `point` for the variable `tag`,
    /// drawn from the distribution truncated to [min, max] (defaults the
    /// physical bounds [lo, hi]).
    pub fn sample(&self, point: u64, tag: u64, lo: f64, hi: f64) -> f64 {
        let mean = self.mean_within(lo, hi);
        if self.std_dev == 0.0 {
            return mean;
        }
        let (min, max) = self.bounds(lo, hi);
        let s = stream(point ^ mix64(self.seed), tag);
        for k in 0..MAX_DRAWS {
            let x = self.mean + self.std_dev * standard_normal(s, k);
            if x >= min && x <= max {
                return x;
            }
        }
        mean
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const N: u64 = 100_000;

    /// Sample mean and variance of the standard normals 0..N of `seed`.
    fn moments(seed: u64) -> (f64, f64) {
        let (mut s1, mut s2) = (0.0, 0.0);
        for k in 0..N {
            let z = standard_normal(seed, k);
            s1 += z;
            s2 += z * z;
        }
        let mean = s1 / N as f64;
        (mean, s2 / N as f64 - mean * mean)
    }

    #[test]
    fn mix64_matches_the_reference_splitmix64_sequence() {
        // SplitMix64 from state 0: the first outputs of the reference
        // generator (Vigna's splitmix64.c, seed 0).
        assert_eq!(word(0, 0), 0xE220_A839_7B1D_CDAF);
        assert_eq!(word(0, 1), 0x6E78_9E6A_A1B9_65F4);
        assert_eq!(word(0, 2), 0x06C4_5D18_8009_454F);
    }

    /// 1e5 normals: the sample mean is within 5 standard errors
    /// (5/√N = 0.0158) of 0, the variance within 5 standard errors
    /// (5√(2/N) = 0.0224) of 1, and the fraction in [−1, 1] within 5
    /// standard errors (5√(p(1 − p)/N) = 0.0074) of p = 0.682689.
    #[test]
    fn normals_have_unit_variance_and_zero_mean() {
        for seed in [0, 1, 0xDEAD_BEEF, point_seed([0.1, 0.2, 0.3], 4)] {
            let (mean, var) = moments(seed);
            assert!(mean.abs() < 5.0 / (N as f64).sqrt(), "seed {seed}: {mean}");
            assert!(
                (var - 1.0).abs() < 5.0 * (2.0 / N as f64).sqrt(),
                "seed {seed}: {var}"
            );
            let inside = (0..N)
                .filter(|&k| standard_normal(seed, k).abs() <= 1.0)
                .count() as f64
                / N as f64;
            let p = 0.682_689;
            assert!(
                (inside - p).abs() < 5.0 * (p * (1.0 - p) / N as f64).sqrt(),
                "seed {seed}: {inside}"
            );
        }
    }

    #[test]
    fn uniforms_stay_inside_the_open_interval() {
        for k in 0..10_000 {
            let u = uniform(7, k);
            assert!(u > 0.0 && u < 1.0, "{u}");
        }
        // The extreme words map inside (0, 1): 2⁻⁵³ and 1 − 2⁻⁵³.
        const SCALE: f64 = 1.0 / (1u64 << 52) as f64;
        assert_eq!(0.5 * SCALE, 2f64.powi(-53));
        assert_eq!(
            ((u64::MAX >> 12) as f64 + 0.5) * SCALE,
            1.0 - 2f64.powi(-53)
        );
    }

    #[test]
    fn same_seed_same_bits_other_seed_other_draw() {
        let g = Gaussian::new(0.005, 0.001);
        let a = g.sample(point_seed([1e-3, 2e-3, 0.0], 1), STREAM_POROSITY, 0.0, 0.3);
        let b = g.sample(point_seed([1e-3, 2e-3, 0.0], 1), STREAM_POROSITY, 0.0, 0.3);
        assert_eq!(a.to_bits(), b.to_bits());
        // −0.0 and +0.0 are the same coordinate.
        let c = g.sample(point_seed([1e-3, 2e-3, -0.0], 1), STREAM_POROSITY, 0.0, 0.3);
        assert_eq!(a.to_bits(), c.to_bits());
        // Another material, point, stream or realisation draws anew.
        for other in [
            g.sample(point_seed([1e-3, 2e-3, 0.0], 2), STREAM_POROSITY, 0.0, 0.3),
            g.sample(
                point_seed([1e-3, 2.0001e-3, 0.0], 1),
                STREAM_POROSITY,
                0.0,
                0.3,
            ),
            g.sample(point_seed([1e-3, 2e-3, 0.0], 1), STREAM_DAMAGE, 0.0, 0.3),
            Gaussian { seed: 1, ..g }.sample(
                point_seed([1e-3, 2e-3, 0.0], 1),
                STREAM_POROSITY,
                0.0,
                0.3,
            ),
        ] {
            assert_ne!(a, other);
        }
    }

    /// Draws at the seeds of neighbouring points of a grid have the
    /// distribution's moments and no correlation between a point and its
    /// neighbour (|r| within 5/√n of 0).
    #[test]
    fn neighbouring_points_draw_independent_values() {
        let g = Gaussian::new(0.005, 0.001);
        let n = 200usize;
        let draw = |i: usize, j: usize| {
            let x = [(i as f64 + 0.5) * 1e-4, (j as f64 + 0.5) * 1e-4, 5e-5];
            g.sample(point_seed(x, 0), STREAM_POROSITY, 0.0, 0.3)
        };
        let (mut sa, mut sb, mut saa, mut sbb, mut sab) = (0.0, 0.0, 0.0, 0.0, 0.0);
        for i in 0..n {
            for j in 0..n {
                let (a, b) = (draw(i, j), draw(i + 1, j));
                sa += a;
                sb += b;
                saa += a * a;
                sbb += b * b;
                sab += a * b;
            }
        }
        let m = (n * n) as f64;
        let (ma, mb) = (sa / m, sb / m);
        let (va, vb) = (saa / m - ma * ma, sbb / m - mb * mb);
        let r = (sab / m - ma * mb) / (va * vb).sqrt();
        assert!((ma - 0.005).abs() < 5.0 * 0.001 / m.sqrt(), "{ma}");
        assert!(
            (va.sqrt() - 0.001).abs() < 5.0 * 0.001 / (2.0 * m).sqrt(),
            "{va}"
        );
        assert!(r.abs() < 5.0 / m.sqrt(), "correlation {r}");
    }

    /// N(0.005, 0.004) truncated below at 0: every draw ≥ 0 and the mean is
    /// μ + σ φ(α)/(1 − Φ(α)), α = −1.25: φ(−1.25) = 0.182649,
    /// Φ(1.25) = 0.894350, so 0.005 + 0.004 × 0.204225 = 0.0058169; the
    /// standard error of 1e5 draws is below 1.2e-5, the tolerance 5 of them.
    #[test]
    fn truncation_redraws_instead_of_folding() {
        let g = Gaussian::new(0.005, 0.004);
        let mut sum = 0.0;
        for p in 0..N {
            let x = g.sample(mix64(p), STREAM_POROSITY, 0.0, 1.0);
            assert!((0.0..=1.0).contains(&x), "{x}");
            sum += x;
        }
        let mean = sum / N as f64;
        let expected: f64 = 0.005 + 0.004 * 0.182_649 / 0.894_350;
        assert!((expected - 0.005_816_9).abs() < 1e-7);
        assert!((mean - expected).abs() < 6e-5, "{mean} vs {expected}");
        // A narrow interval around the mean: every draw inside.
        let narrow = Gaussian {
            min: Some(0.0049),
            max: Some(0.0051),
            ..Gaussian::new(0.005, 0.001)
        };
        for p in 0..1000 {
            let x = narrow.sample(mix64(p), STREAM_DAMAGE, 0.0, 1.0);
            assert!((0.0049..=0.0051).contains(&x), "{x}");
        }
    }

    #[test]
    fn zero_spread_gives_the_mean_and_validate_names_the_field() {
        let g = Gaussian::new(0.2, 0.0);
        assert_eq!(g.sample(12345, STREAM_DAMAGE, 0.0, 1.0), 0.2);
        assert_eq!(g.mean_within(0.0, 1.0), 0.2);
        assert!(g.validate("m", "initial_damage", 0.0, 1.0).is_ok());
        for bad in [
            Gaussian::new(-0.1, 0.01),
            Gaussian::new(0.1, -0.01),
            Gaussian::new(0.1, f64::NAN),
            Gaussian {
                min: Some(-0.5),
                ..Gaussian::new(0.1, 0.01)
            },
            Gaussian {
                max: Some(2.0),
                ..Gaussian::new(0.1, 0.01)
            },
            Gaussian {
                min: Some(0.2),
                max: Some(0.1),
                ..Gaussian::new(0.15, 0.01)
            },
        ] {
            let msg = bad
                .validate("m", "initial_damage", 0.0, 1.0)
                .unwrap_err()
                .to_string();
            assert!(msg.contains("initial_damage"), "{msg}");
        }
    }
}
