//! Statistical models of hot-spot intensity (seed 003 §4.5).
//!
//! - [`Gumbel`]: the two-parameter Gumbel (maximum) distribution of eq 29,
//!   f(x) = (1/β) exp(−(z + e^{−z})), z = (x − μ)/β, F(x) = exp(−e^{−z})
//!   (eq 29 as printed drops the minus sign in front of e^{−z}; this is
//!   the standard form of the seed's reference \[26\], which integrates to
//!   one).
//! - [`Gumbel::fit`]: maximum-likelihood estimate. The score equations give
//!   β = x̄ − Σ xᵢ e^{−xᵢ/β} / Σ e^{−xᵢ/β} (solved for β, a function
//!   increasing from min x − x̄ < 0 to +∞, so the root is unique) and then
//!   μ = −β ln((1/n) Σ e^{−xᵢ/β}); the exponentials are shifted by min x
//!   so no sample under- or overflows.
//! - [`linear_fit`]: least-squares line of a parameter against impact
//!   velocity (seed fig. 29).
//! - [`bootstrap`]: resampling with replacement (Efron & Tibshirani, the
//!   seed's \[19\]) of a data set, the MLE refitted on each replicate; it
//!   reports the 95 % percentile interval of each parameter and the 95 %
//!   interval of the mean of the replicates (mean ± 1.96 s/√B), which is
//!   what seed 003 Table 5 tabulates ("what range will contain the mean
//!   value of μ and β"). Replicate r draws its indices from the SplitMix64
//!   words of (seed, r), so the result is the same bits for a seed
//!   whatever the number of threads.
//! - [`ks_test`]: one-sample two-sided Kolmogorov–Smirnov test (the seed's
//!   \[41\]) of a held-out data set against a fully specified distribution
//!   (here the Gumbel of the regressed μ and β). The p-value is exact, from
//!   the distribution of Dₙ by Marsaglia, Tsang & Wang (2003) (for n > 99
//!   and p ≲ 10⁻³ their tail approximation); seed 003
//!   used SciPy 0.14's `kstest`, which for small n doubles the one-sided
//!   Smirnov tail, an approximation that can differ in the third digit.
//! - [`velocity_model`]: the seed's procedure — fit each training velocity,
//!   regress μ and β on velocity, test the held-out velocities — with CSV
//!   output ([`VelocityModel::write_csv`]).

use rayon::prelude::*;
use std::io::Write;

use super::model::MsdmError;

/// Gumbel (maximum) distribution, seed 003 eq 29.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Gumbel {
    /// Location μ, K.
    pub mu: f64,
    /// Scale β > 0, K.
    pub beta: f64,
}

impl Gumbel {
    /// Probability density f(x).
    pub fn pdf(&self, x: f64) -> f64 {
        let z = (x - self.mu) / self.beta;
        (-(z + (-z).exp())).exp() / self.beta
    }

    /// Cumulative distribution F(x) = exp(−e^{−(x−μ)/β}).
    pub fn cdf(&self, x: f64) -> f64 {
        (-(-(x - self.mu) / self.beta).exp()).exp()
    }

    /// Quantile F⁻¹(p) = μ − β ln(−ln p), p in (0, 1).
    pub fn quantile(&self, p: f64) -> f64 {
        self.mu - self.beta * (-p.ln()).ln()
    }

    /// Log-likelihood Σ ln f(xᵢ).
    pub fn log_likelihood(&self, x: &[f64]) -> f64 {
        x.iter()
            .map(|&v| {
                let z = (v - self.mu) / self.beta;
                -self.beta.ln() - z - (-z).exp()
            })
            .sum()
    }

    /// Maximum-likelihood fit to `x` (at least two finite values, not all
    /// equal); see the module documentation.
    pub fn fit(x: &[f64]) -> Result<Self, MsdmError> {
        if x.len() < 2 {
            return Err(MsdmError::Invalid(format!(
                "Gumbel fit: {} samples, expected at least 2",
                x.len()
            )));
        }
        if let Some(v) = x.iter().find(|v| !v.is_finite()) {
            return Err(MsdmError::Invalid(format!(
                "Gumbel fit: sample {v} is not finite"
            )));
        }
        let n = x.len() as f64;
        let lo = x.iter().copied().fold(f64::INFINITY, f64::min);
        let hi = x.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        if !(hi > lo) {
            return Err(MsdmError::Invalid(
                "Gumbel fit: all samples are equal, the scale is zero".into(),
            ));
        }
        // Work with y = x − min ≥ 0 (location equivariance), so every
        // weight e^{−y/β} is in (0, 1] and the sums never overflow.
        let mean = x.iter().map(|v| v - lo).sum::<f64>() / n;
        // g(β) = β − ȳ + Σ y w / Σ w, w = e^{−y/β}; g' = 1 + Var_w(y)/β².
        let g = |beta: f64| -> (f64, f64) {
            let (mut s0, mut s1, mut s2) = (0.0, 0.0, 0.0);
            for &v in x {
                let y = v - lo;
                let w = (-y / beta).exp();
                s0 += w;
                s1 += w * y;
                s2 += w * y * y;
            }
            let m1 = s1 / s0;
            let var = (s2 / s0 - m1 * m1).max(0.0);
            (beta - mean + m1, 1.0 + var / (beta * beta))
        };
        // Bracket: g(β) < 0 as β → 0 and g(β) ≥ β − ȳ > 0 for β > ȳ.
        let mut a = 0.0f64;
        let mut b = mean.max(f64::MIN_POSITIVE) * 2.0;
        // Start from the moment estimate s√6/π.
        let var = x.iter().map(|v| (v - lo - mean).powi(2)).sum::<f64>() / (n - 1.0);
        let mut beta = (var.sqrt() * 6f64.sqrt() / std::f64::consts::PI).clamp(b * 1e-6, b * 0.5);
        for _ in 0..200 {
            let (gv, dg) = g(beta);
            if gv > 0.0 {
                b = beta;
            } else {
                a = beta;
            }
            if gv == 0.0 {
                break;
            }
            let mut next = beta - gv / dg;
            if !(next > a && next < b) {
                next = 0.5 * (a + b);
            }
            if (next - beta).abs() <= 4.0 * f64::EPSILON * beta {
                beta = next;
                break;
            }
            beta = next;
        }
        let s0 = x.iter().map(|v| (-(v - lo) / beta).exp()).sum::<f64>() / n;
        let mu = lo - beta * s0.ln();
        Ok(Self { mu, beta })
    }
}

/// Least-squares line y = intercept + slope · x.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LinearFit {
    /// Intercept.
    pub intercept: f64,
    /// Slope.
    pub slope: f64,
    /// Coefficient of determination R² (1 when the points are collinear).
    pub r_squared: f64,
}

impl LinearFit {
    /// The line at `x`.
    pub fn at(&self, x: f64) -> f64 {
        self.intercept + self.slope * x
    }
}

/// Least-squares line through (x, y); at least two distinct x.
pub fn linear_fit(x: &[f64], y: &[f64]) -> Result<LinearFit, MsdmError> {
    if x.len() != y.len() || x.len() < 2 {
        return Err(MsdmError::Invalid(format!(
            "linear fit: {} abscissae and {} ordinates, expected equal counts ≥ 2",
            x.len(),
            y.len()
        )));
    }
    if x.iter().chain(y).any(|v| !v.is_finite()) {
        return Err(MsdmError::Invalid(
            "linear fit: a point is not finite".into(),
        ));
    }
    let n = x.len() as f64;
    let mx = x.iter().sum::<f64>() / n;
    let my = y.iter().sum::<f64>() / n;
    let sxx: f64 = x.iter().map(|v| (v - mx) * (v - mx)).sum();
    let sxy: f64 = x.iter().zip(y).map(|(a, b)| (a - mx) * (b - my)).sum();
    let syy: f64 = y.iter().map(|v| (v - my) * (v - my)).sum();
    if !(sxx > 0.0) {
        return Err(MsdmError::Invalid(
            "linear fit: all abscissae are equal".into(),
        ));
    }
    let slope = sxy / sxx;
    let intercept = my - slope * mx;
    let ss_res: f64 = x
        .iter()
        .zip(y)
        .map(|(a, b)| (b - intercept - slope * a).powi(2))
        .sum();
    let r_squared = if syy > 0.0 { 1.0 - ss_res / syy } else { 1.0 };
    Ok(LinearFit {
        intercept,
        slope,
        r_squared,
    })
}

/// Bootstrap summary of one parameter.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Interval {
    /// Mean of the replicates.
    pub mean: f64,
    /// Standard deviation of the replicates (the bootstrap standard error).
    pub std_dev: f64,
    /// 2.5 % and 97.5 % percentiles of the replicates.
    pub percentile_95: [f64; 2],
    /// mean ∓ 1.96 std_dev/√B: 95 % interval of the replicates' mean
    /// (seed 003 Table 5).
    pub mean_95: [f64; 2],
}

/// Bootstrap intervals of the Gumbel MLE.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Bootstrap {
    /// Replicates B.
    pub replicates: usize,
    /// Location μ.
    pub mu: Interval,
    /// Scale β.
    pub beta: Interval,
}

const GAMMA: u64 = 0x9E37_79B9_7F4A_7C15;

fn mix64(mut z: u64) -> u64 {
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

/// Word `k` of the SplitMix64 stream of replicate `r` of `seed`.
fn word(seed: u64, r: u64, k: u64) -> u64 {
    let stream = mix64(seed ^ mix64(r.wrapping_add(1).wrapping_mul(GAMMA)));
    mix64(stream.wrapping_add(k.wrapping_add(1).wrapping_mul(GAMMA)))
}

/// Index in 0..n from a 64-bit word (multiply–shift; bias below n/2⁶⁴).
fn index(w: u64, n: usize) -> usize {
    ((u128::from(w) * n as u128) >> 64) as usize
}

fn summarize(mut v: Vec<f64>) -> Interval {
    let b = v.len() as f64;
    let mean = v.iter().sum::<f64>() / b;
    let std_dev = (v.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / (b - 1.0)).sqrt();
    v.sort_unstable_by(f64::total_cmp);
    // Percentile by linear interpolation between order statistics
    // (position p (B − 1)).
    let pct = |p: f64| {
        let pos = p * (b - 1.0);
        let k = pos.floor() as usize;
        let f = pos - k as f64;
        if k + 1 < v.len() {
            v[k] + f * (v[k + 1] - v[k])
        } else {
            v[k]
        }
    };
    let half = 1.959_963_984_540_054 * std_dev / b.sqrt();
    Interval {
        mean,
        std_dev,
        percentile_95: [pct(0.025), pct(0.975)],
        mean_95: [mean - half, mean + half],
    }
}

/// Bootstrap of the Gumbel MLE of `x` with `replicates` resamples drawn
/// from `seed` (deterministic, thread-count independent). A replicate
/// whose resample has all values equal is redrawn from the next words of
/// its stream.
pub fn bootstrap(x: &[f64], replicates: usize, seed: u64) -> Result<Bootstrap, MsdmError> {
    Gumbel::fit(x)?;
    if replicates < 2 {
        return Err(MsdmError::Invalid(format!(
            "bootstrap: field `replicates` = {replicates}, expected at least 2"
        )));
    }
    let n = x.len();
    let fits: Vec<Gumbel> = (0..replicates as u64)
        .into_par_iter()
        .map_init(
            || vec![0.0; n],
            |buf, r| {
                let mut k = 0u64;
                loop {
                    for v in buf.iter_mut() {
                        *v = x[index(word(seed, r, k), n)];
                        k += 1;
                    }
                    if let Ok(g) = Gumbel::fit(buf) {
                        return g;
                    }
                }
            },
        )
        .collect();
    Ok(Bootstrap {
        replicates,
        mu: summarize(fits.iter().map(|g| g.mu).collect()),
        beta: summarize(fits.iter().map(|g| g.beta).collect()),
    })
}

/// Result of a one-sample Kolmogorov–Smirnov test.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct KsTest {
    /// Sample size n.
    pub n: usize,
    /// Dₙ = sup |Fₙ(x) − F(x)|.
    pub statistic: f64,
    /// P(Dₙ ≥ statistic) under the null hypothesis (two-sided, exact).
    pub p_value: f64,
}

/// Two-sided one-sample Kolmogorov–Smirnov test of `x` against the
/// continuous distribution function `cdf`.
pub fn ks_test(x: &[f64], cdf: impl Fn(f64) -> f64) -> Result<KsTest, MsdmError> {
    if x.is_empty() {
        return Err(MsdmError::Invalid("KS test: the sample is empty".into()));
    }
    if x.iter().any(|v| v.is_nan()) {
        return Err(MsdmError::Invalid("KS test: a sample is NaN".into()));
    }
    let mut s = x.to_vec();
    s.sort_unstable_by(f64::total_cmp);
    let n = s.len() as f64;
    let mut d = 0.0f64;
    for (i, &v) in s.iter().enumerate() {
        let f = cdf(v);
        d = d.max((i as f64 + 1.0) / n - f).max(f - i as f64 / n);
    }
    Ok(KsTest {
        n: s.len(),
        statistic: d,
        p_value: (1.0 - kolmogorov_cdf(s.len(), d)).clamp(0.0, 1.0),
    })
}

/// P(Dₙ < d) for the two-sided one-sample statistic, exact (Marsaglia,
/// Tsang & Wang 2003, J. Stat. Softw. 8(18), the matrix-power algorithm
/// with its exponent rescaling), d in [0, 1].
pub fn kolmogorov_cdf(n: usize, d: f64) -> f64 {
    if n == 0 || d <= 0.0 {
        return 0.0;
    }
    let nf = n as f64;
    if d >= 1.0 {
        return 1.0;
    }
    if d <= 0.5 / nf {
        return 0.0;
    }
    // Far tail of a large sample (P(Dₙ ≥ d) ≲ 1e-3): Marsaglia, Tsang &
    // Wang's approximation, which spares the (2nd)³ matrix products.
    let s = d * d * nf;
    if n > 99 && s > 3.76 {
        return 1.0 - 2.0 * (-(2.000071 + 0.331 / nf.sqrt() + 1.409 / nf) * s).exp();
    }
    let k = (nf * d) as usize + 1;
    let m = 2 * k - 1;
    let h = k as f64 - nf * d;
    let mut hm = vec![0.0; m * m];
    for i in 0..m {
        for j in 0..m {
            hm[i * m + j] = if i + 1 >= j { 1.0 } else { 0.0 };
        }
    }
    for i in 0..m {
        hm[i * m] -= h.powi(i as i32 + 1);
        hm[(m - 1) * m + i] -= h.powi((m - i) as i32);
    }
    hm[(m - 1) * m] += if 2.0 * h - 1.0 > 0.0 {
        (2.0 * h - 1.0).powi(m as i32)
    } else {
        0.0
    };
    for i in 0..m {
        for j in 0..m {
            if i + 1 >= j {
                for g in 1..=(i + 1 - j) {
                    hm[i * m + j] /= g as f64;
                }
            }
        }
    }
    let (q, eq) = matrix_power(&hm, m, n);
    let mut s = q[(k - 1) * m + k - 1];
    let mut e = eq;
    for i in 1..=n {
        s *= i as f64 / nf;
        if s < 1e-140 {
            s *= 1e140;
            e -= 140;
        }
    }
    s * 10f64.powi(e)
}

fn matrix_mul(a: &[f64], b: &[f64], m: usize) -> Vec<f64> {
    let mut c = vec![0.0; m * m];
    for i in 0..m {
        for k in 0..m {
            let aik = a[i * m + k];
            for j in 0..m {
                c[i * m + j] += aik * b[k * m + j];
            }
        }
    }
    c
}

/// Aⁿ as (matrix, decimal exponent), rescaled to avoid overflow.
fn matrix_power(a: &[f64], m: usize, n: usize) -> (Vec<f64>, i32) {
    if n == 1 {
        return (a.to_vec(), 0);
    }
    let (half, e) = matrix_power(a, m, n / 2);
    let mut b = matrix_mul(&half, &half, m);
    let mut eb = 2 * e;
    if n % 2 == 1 {
        b = matrix_mul(a, &b, m);
    }
    if b[(m / 2) * m + m / 2] > 1e140 {
        b.iter_mut().for_each(|v| *v *= 1e-140);
        eb += 140;
    }
    (b, eb)
}

/// Hot-spot peak temperatures at one impact velocity.
#[derive(Debug, Clone, PartialEq)]
pub struct VelocitySample {
    /// Impact velocity, m/s.
    pub velocity: f64,
    /// Peak temperature of each hot spot, K.
    pub peaks: Vec<f64>,
}

/// Fit, bootstrap and KS test of one velocity.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct VelocityFit {
    /// Impact velocity, m/s.
    pub velocity: f64,
    /// Number of hot spots.
    pub n: usize,
    /// Whether the velocity was used to train the regression.
    pub training: bool,
    /// MLE of this velocity's own data.
    pub mle: Gumbel,
    /// Bootstrap intervals of the MLE.
    pub bootstrap: Bootstrap,
    /// The Gumbel of the regressed μ(v), β(v).
    pub regressed: Gumbel,
    /// KS test of the data against `regressed` (meaningful as a test only
    /// for held-out velocities).
    pub ks: KsTest,
}

/// The velocity model of seed 003 §4.5.
#[derive(Debug, Clone, PartialEq)]
pub struct VelocityModel {
    /// μ(v), K against m/s.
    pub mu: LinearFit,
    /// β(v), K against m/s.
    pub beta: LinearFit,
    /// Per velocity, in input order.
    pub fits: Vec<VelocityFit>,
}

/// Fits a Gumbel to each sample, regresses μ and β linearly on the
/// velocities not in `held_out`, and tests every sample (the held-out ones
/// are the real test) against the regressed Gumbel; `replicates` bootstrap
/// resamples per velocity from `seed`.
pub fn velocity_model(
    samples: &[VelocitySample],
    held_out: &[f64],
    replicates: usize,
    seed: u64,
) -> Result<VelocityModel, MsdmError> {
    let mut mles = Vec::with_capacity(samples.len());
    for (k, s) in samples.iter().enumerate() {
        if !s.velocity.is_finite() {
            return Err(MsdmError::Invalid(format!(
                "velocity model: sample {k} has `velocity` = {}",
                s.velocity
            )));
        }
        let g = Gumbel::fit(&s.peaks).map_err(|e| {
            MsdmError::Invalid(format!("velocity model: velocity {}: {e}", s.velocity))
        })?;
        mles.push(g);
    }
    let train: Vec<usize> = (0..samples.len())
        .filter(|&k| !held_out.contains(&samples[k].velocity))
        .collect();
    let v: Vec<f64> = train.iter().map(|&k| samples[k].velocity).collect();
    let mu = linear_fit(&v, &train.iter().map(|&k| mles[k].mu).collect::<Vec<_>>())
        .map_err(|e| MsdmError::Invalid(format!("velocity model: μ(v): {e}")))?;
    let beta = linear_fit(&v, &train.iter().map(|&k| mles[k].beta).collect::<Vec<_>>())
        .map_err(|e| MsdmError::Invalid(format!("velocity model: β(v): {e}")))?;
    let mut fits = Vec::with_capacity(samples.len());
    for (k, s) in samples.iter().enumerate() {
        let regressed = Gumbel {
            mu: mu.at(s.velocity),
            beta: beta.at(s.velocity),
        };
        if !(regressed.beta > 0.0) {
            return Err(MsdmError::Invalid(format!(
                "velocity model: the regressed β at {} m/s is {}, expected > 0",
                s.velocity, regressed.beta
            )));
        }
        fits.push(VelocityFit {
            velocity: s.velocity,
            n: s.peaks.len(),
            training: train.contains(&k),
            mle: mles[k],
            bootstrap: bootstrap(&s.peaks, replicates, seed.wrapping_add(k as u64))?,
            regressed,
            ks: ks_test(&s.peaks, |x| regressed.cdf(x))?,
        });
    }
    Ok(VelocityModel { mu, beta, fits })
}

impl VelocityModel {
    /// Writes one CSV row per velocity (header first).
    pub fn write_csv(&self, mut w: impl Write) -> std::io::Result<()> {
        writeln!(
            w,
            "velocity_m_s,n,training,mu_mle_K,beta_mle_K,mu_regressed_K,beta_regressed_K,\
             mu_boot_mean_K,mu_pct2.5_K,mu_pct97.5_K,mu_mean95_lo_K,mu_mean95_hi_K,\
             beta_boot_mean_K,beta_pct2.5_K,beta_pct97.5_K,beta_mean95_lo_K,beta_mean95_hi_K,\
             ks_D,ks_p"
        )?;
        for f in &self.fits {
            let (bm, bb) = (f.bootstrap.mu, f.bootstrap.beta);
            writeln!(
                w,
                "{},{},{},{:.6},{:.6},{:.6},{:.6},{:.6},{:.6},{:.6},{:.6},{:.6},{:.6},{:.6},{:.6},{:.6},{:.6},{:.6},{:.6}",
                f.velocity,
                f.n,
                f.training,
                f.mle.mu,
                f.mle.beta,
                f.regressed.mu,
                f.regressed.beta,
                bm.mean,
                bm.percentile_95[0],
                bm.percentile_95[1],
                bm.mean_95[0],
                bm.mean_95[1],
                bb.mean,
                bb.percentile_95[0],
                bb.percentile_95[1],
                bb.mean_95[0],
                bb.mean_95[1],
                f.ks.statistic,
                f.ks.p_value
            )?;
        }
        Ok(())
    }

    /// Writes the two regressions as CSV (parameter, intercept, slope, R²).
    pub fn write_regression_csv(&self, mut w: impl Write) -> std::io::Result<()> {
        writeln!(w, "parameter,intercept_K,slope_K_per_m_s,r_squared")?;
        for (name, f) in [("mu", self.mu), ("beta", self.beta)] {
            writeln!(
                w,
                "{name},{:.6},{:.9},{:.6}",
                f.intercept, f.slope, f.r_squared
            )?;
        }
        Ok(())
    }
}

/// `n` Gumbel(μ, β) variates from `seed` by inversion (for tests and
/// synthetic checks).
pub fn gumbel_sample(g: Gumbel, n: usize, seed: u64) -> Vec<f64> {
    (0..n as u64)
        .map(|k| {
            // U in (0, 1): 53 random bits, offset by half an ulp.
            let u = ((word(seed, u64::MAX, k) >> 11) as f64 + 0.5) / (1u64 << 53) as f64;
            g.quantile(u)
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    #[test]
    fn gumbel_density_distribution_and_quantile() {
        let g = Gumbel {
            mu: 400.0,
            beta: 20.0,
        };
        // At x = μ: F = e^{-1}, f = e^{-1}/β.
        assert_eq!(g.cdf(400.0), (-1.0f64).exp());
        assert!((g.pdf(400.0) - (-1.0f64).exp() / 20.0).abs() < 1e-18);
        // Median μ − β ln ln 2.
        assert!((g.quantile(0.5) - (400.0 - 20.0 * 2f64.ln().ln())).abs() < 1e-12);
        assert!((g.cdf(g.quantile(0.9)) - 0.9).abs() < 1e-14);
        // The density integrates to one (trapezoid on ±30β).
        let (a, b, m) = (400.0 - 200.0, 400.0 + 600.0, 200_000);
        let h = (b - a) / m as f64;
        let integral: f64 = (0..=m)
            .map(|k| {
                let w = if k == 0 || k == m { 0.5 } else { 1.0 };
                w * g.pdf(a + k as f64 * h)
            })
            .sum::<f64>()
            * h;
        assert!((integral - 1.0).abs() < 1e-9, "{integral}");
    }

    #[test]
    fn mle_recovers_known_parameters_from_a_large_sample() {
        // n = 20 000 from Gumbel(400, 20): asymptotic standard errors
        // 1.0533 β/√n = 0.149 K for μ and 0.7797 β/√n = 0.110 K for β;
        // the tolerance is 4 standard errors.
        let truth = Gumbel {
            mu: 400.0,
            beta: 20.0,
        };
        let n = 20_000;
        let x = gumbel_sample(truth, n, 7);
        let g = Gumbel::fit(&x).unwrap();
        let se_mu = 1.0533 * 20.0 / (n as f64).sqrt();
        let se_beta = 0.7797 * 20.0 / (n as f64).sqrt();
        assert!((g.mu - 400.0).abs() < 4.0 * se_mu, "μ = {}", g.mu);
        assert!((g.beta - 20.0).abs() < 4.0 * se_beta, "β = {}", g.beta);
    }

    #[test]
    fn mle_solves_the_score_equations() {
        // ∂ℓ/∂μ = (n − Σ e^{−z})/β = 0 and
        // ∂ℓ/∂β = (−n + Σ z − Σ z e^{−z})/β = 0 at the estimate.
        let x = [351.2, 348.7, 356.0, 349.9, 362.3, 347.1, 353.8];
        let g = Gumbel::fit(&x).unwrap();
        let z: Vec<f64> = x.iter().map(|v| (v - g.mu) / g.beta).collect();
        let n = x.len() as f64;
        let d_mu = n - z.iter().map(|z| (-z).exp()).sum::<f64>();
        let d_beta = -n + z.iter().map(|z| z - z * (-z).exp()).sum::<f64>();
        assert!(d_mu.abs() < 1e-12, "{d_mu}");
        assert!(d_beta.abs() < 1e-12, "{d_beta}");
        // And it is a maximum: nudging either parameter lowers ℓ.
        let l = g.log_likelihood(&x);
        for (dm, db) in [(1e-3, 0.0), (-1e-3, 0.0), (0.0, 1e-3), (0.0, -1e-3)] {
            let h = Gumbel {
                mu: g.mu + dm,
                beta: g.beta + db,
            };
            assert!(h.log_likelihood(&x) < l);
        }
    }

    #[test]
    fn mle_rejects_degenerate_samples() {
        assert!(Gumbel::fit(&[1.0])
            .unwrap_err()
            .to_string()
            .contains("at least 2"));
        assert!(Gumbel::fit(&[3.0, 3.0])
            .unwrap_err()
            .to_string()
            .contains("equal"));
        assert!(Gumbel::fit(&[3.0, f64::NAN]).is_err());
    }

    #[test]
    fn linear_fit_matches_the_hand_computation() {
        // x̄ = 1, ȳ = 8/3, Sxy = 3, Sxx = 2: slope 3/2, intercept 7/6;
        // residuals −1/6, 1/3, −1/6: SSres = 1/6, SStot = 14/3, R² = 27/28.
        let f = linear_fit(&[0.0, 1.0, 2.0], &[1.0, 3.0, 4.0]).unwrap();
        assert!((f.slope - 1.5).abs() < 1e-15);
        assert!((f.intercept - 7.0 / 6.0).abs() < 1e-15);
        assert!((f.r_squared - 27.0 / 28.0).abs() < 1e-15);
        assert_eq!(f.at(2.0), f.intercept + 2.0 * f.slope);
        let exact = linear_fit(&[50.0, 100.0], &[10.0, 20.0]).unwrap();
        assert_eq!(
            (exact.slope, exact.intercept, exact.r_squared),
            (0.2, 0.0, 1.0)
        );
        assert!(linear_fit(&[1.0, 1.0], &[1.0, 2.0]).is_err());
        assert!(linear_fit(&[1.0], &[1.0]).is_err());
    }

    #[test]
    fn ks_statistic_matches_the_hand_computation() {
        // Sample 0.1, 0.4, 0.7 against U(0, 1): D⁺ = max(1/3 − 0.1,
        // 2/3 − 0.4, 1 − 0.7) = 0.3, D⁻ = max(0.1, 0.4 − 1/3, 0.7 − 2/3)
        // = 0.1, D = 0.3.
        let t = ks_test(&[0.7, 0.1, 0.4], |x| x).unwrap();
        assert!((t.statistic - 0.3).abs() < 1e-15);
        assert_eq!(t.n, 3);
        // For 1/(2n) ≤ d ≤ 1/n, P(Dₙ < d) = n! (2d − 1/n)ⁿ: here
        // 6 (0.6 − 1/3)³, p = 1 − 0.113 777…
        let exact = 1.0 - 6.0 * (0.6 - 1.0 / 3.0f64).powi(3);
        assert!(
            (t.p_value - exact).abs() < 1e-14,
            "{} vs {exact}",
            t.p_value
        );
    }

    #[test]
    fn kolmogorov_distribution_exact_small_n() {
        // n = 1: D = max(U, 1 − U), P(D < d) = 2d − 1 on [1/2, 1].
        for d in [0.5, 0.6, 0.75, 0.9] {
            assert!(
                (kolmogorov_cdf(1, d) - (2.0 * d - 1.0)).abs() < 1e-14,
                "d = {d}"
            );
        }
        // n = 2, d ∈ [1/4, 1/2]: u₁ ∈ (1/2 − d, d), u₂ ∈ (1 − d, 1/2 + d),
        // density 2 on u₁ < u₂: P = 2 (2d − 1/2)² (the n! (2d − 1/n)ⁿ
        // of 1/(2n) ≤ d ≤ 1/n).
        for d in [0.25, 0.3, 0.4, 0.5] {
            let exact = 2.0 * (2.0 * d - 0.5f64).powi(2);
            assert!((kolmogorov_cdf(2, d) - exact).abs() < 1e-14, "d = {d}");
        }
        // Below 1/(2n) the probability is zero, at 1 it is one.
        assert_eq!(kolmogorov_cdf(5, 0.09), 0.0);
        assert_eq!(kolmogorov_cdf(5, 1.0), 1.0);
        // The example of Marsaglia, Tsang & Wang (2003): K(10, 0.274).
        assert!((kolmogorov_cdf(10, 0.274) - 0.628_479_615_456_504_3).abs() < 1e-13);
    }

    #[test]
    fn bootstrap_is_deterministic_for_a_seed_and_brackets_the_mle() {
        let truth = Gumbel {
            mu: 350.0,
            beta: 6.0,
        };
        let x = gumbel_sample(truth, 25, 3);
        let g = Gumbel::fit(&x).unwrap();
        let a = bootstrap(&x, 400, 11).unwrap();
        let b = rayon::ThreadPoolBuilder::new()
            .num_threads(1)
            .build()
            .unwrap()
            .install(|| bootstrap(&x, 400, 11).unwrap());
        assert_eq!(a, b);
        let c = bootstrap(&x, 400, 12).unwrap();
        assert_ne!(a, c);
        assert!(a.mu.percentile_95[0] < g.mu && g.mu < a.mu.percentile_95[1]);
        assert!(a.beta.percentile_95[0] < g.beta && g.beta < a.beta.percentile_95[1]);
        // The interval of the mean is narrower by √B than ±1.96 s.
        let w = a.mu.mean_95[1] - a.mu.mean_95[0];
        assert!((w - 2.0 * 1.959_963_984_540_054 * a.mu.std_dev / 20.0).abs() < 1e-12);
        // The bootstrap standard error of μ is near the asymptotic
        // 1.0533 β/√n = 1.26 K (a 25-point sample: within a factor 1.6).
        let se = 1.0533 * g.beta / 5.0;
        assert!(
            a.mu.std_dev > se / 1.6 && a.mu.std_dev < se * 1.6,
            "{} vs {se}",
            a.mu.std_dev
        );
    }

    #[test]
    fn velocity_model_recovers_linear_parameters_and_writes_csv() {
        // Synthetic hot spots with μ = 300 + v, β = 0.2 v: the held-out
        // 150 and 250 m/s sets follow the regressed model.
        let samples: Vec<VelocitySample> = [50.0, 100.0, 150.0, 200.0, 250.0]
            .iter()
            .enumerate()
            .map(|(k, &v)| VelocitySample {
                velocity: v,
                peaks: gumbel_sample(
                    Gumbel {
                        mu: 300.0 + v,
                        beta: 0.2 * v,
                    },
                    2000,
                    100 + k as u64,
                ),
            })
            .collect();
        let m = velocity_model(&samples, &[150.0, 250.0], 50, 1).unwrap();
        // Standard errors of the slopes from the asymptotic MLE errors
        // (1.0533 β/√n, 0.7797 β/√n) at 50, 100, 200 m/s: 0.0069 for μ,
        // 0.0051 for β; tolerance 4 standard errors.
        assert!((m.mu.slope - 1.0).abs() < 0.028, "{:?}", m.mu);
        assert!((m.beta.slope - 0.2).abs() < 0.02, "{:?}", m.beta);
        let held: Vec<_> = m.fits.iter().filter(|f| !f.training).collect();
        assert_eq!(held.len(), 2);
        for f in held {
            assert!(f.ks.p_value > 0.01, "{f:?}");
        }
        let mut csv = Vec::new();
        m.write_csv(&mut csv).unwrap();
        let csv = String::from_utf8(csv).unwrap();
        assert_eq!(csv.lines().count(), 6);
        assert!(csv.lines().nth(3).unwrap().starts_with("150,2000,false,"));
        let mut reg = Vec::new();
        m.write_regression_csv(&mut reg).unwrap();
        assert_eq!(String::from_utf8(reg).unwrap().lines().count(), 3);
        // A sample from a different distribution is rejected.
        let wrong = ks_test(&samples[4].peaks, |x| m.fits[0].regressed.cdf(x)).unwrap();
        assert!(wrong.p_value < 1e-6);
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(64))]

        #[test]
        fn gumbel_cdf_is_monotone_in_unit_interval(
            mu in -1e3f64..1e3, beta in 0.01f64..100.0, a in -50f64..50.0, b in -50f64..50.0,
        ) {
            let g = Gumbel { mu, beta };
            let (lo, hi) = if a < b { (a, b) } else { (b, a) };
            let (fl, fh) = (g.cdf(mu + lo * beta), g.cdf(mu + hi * beta));
            prop_assert!((0.0..=1.0).contains(&fl) && (0.0..=1.0).contains(&fh));
            prop_assert!(fl <= fh);
        }

        #[test]
        fn mle_is_location_and_scale_equivariant(
            seed in 0u64..1000, shift in -500f64..500.0, scale in 0.1f64..10.0,
        ) {
            let x = gumbel_sample(Gumbel { mu: 10.0, beta: 2.0 }, 15, seed);
            let g = Gumbel::fit(&x).unwrap();
            let y: Vec<f64> = x.iter().map(|v| v * scale + shift).collect();
            let h = Gumbel::fit(&y).unwrap();
            prop_assert!((h.mu - (g.mu * scale + shift)).abs() < 1e-9 * (1.0 + h.mu.abs()), "{:?} {:?}", g, h);
            prop_assert!((h.beta - g.beta * scale).abs() < 1e-9 * h.beta, "{:?} {:?}", g, h);
        }

        #[test]
        fn ks_statistic_bounds_and_p_value_monotone(
            x in proptest::collection::vec(0.0f64..1.0, 1..30), d1 in 0.0f64..1.0, d2 in 0.0f64..1.0,
        ) {
            let t = ks_test(&x, |v| v).unwrap();
            let n = x.len() as f64;
            prop_assert!(t.statistic >= 0.5 / n - 1e-15 && t.statistic <= 1.0);
            prop_assert!((0.0..=1.0).contains(&t.p_value));
            let (lo, hi) = if d1 < d2 { (d1, d2) } else { (d2, d1) };
            prop_assert!(kolmogorov_cdf(x.len(), lo) <= kolmogorov_cdf(x.len(), hi) + 1e-12);
        }
    }
}
