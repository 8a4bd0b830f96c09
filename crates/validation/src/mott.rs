//! Mott's statistical fragmentation of an expanding shell, the reference
//! E-PD-FRAG compares its fragments with (docs/physics/pd/validation.md,
//! "Mott's fragments").
//!
//! N. F. Mott, *Fragmentation of shell cases*, Proc. R. Soc. Lond. A 189
//! (1947) 300–308, as restated by D. E. Grady, *Fragmentation of Rings and
//! Shells: The Legacy of N. F. Mott* (Springer, 2006): a ring of density ρ
//! and flow stress Y expanding at velocity V from radius r breaks where
//! fractures nucleate with a probability per unit length that rises with
//! the strain as e^{γε}; a fracture unloads the ring around it by a plastic
//! release wave, and the fractures the release waves leave standing are
//! spaced on average
//!
//! x₀ = (2Y/(ργ))^{1/2} · r/V.
//!
//! On a shell the fracture lines cut the surface both ways; Mott's
//! two-dimensional distribution of the fragment masses is
//!
//! N(> m) = N₀ exp(−(m/μ)^{1/2}),
//!
//! with mean fragment mass 2μ (the form of the US DoD Explosives Safety
//! Board's TP-12, N(> m) ∝ exp(−(2m/m₀)^{1/2}) with m₀ the mean mass).
//! Taking the mean fragment as an x₀ × x₀ patch of the wall of thickness t
//! gives 2μ = ρ t x₀².

/// Mott's mean fracture spacing x₀ = (2Y/(ργ))^{1/2} r/V of a ring of
/// density `density` (kg/m³) and flow stress `flow_stress` (Pa) expanding
/// at `velocity` (m/s) from `radius` (m), with Mott's statistical
/// parameter `gamma` (dimensionless): metres.
pub fn fracture_spacing(
    flow_stress: f64,
    density: f64,
    gamma: f64,
    radius: f64,
    velocity: f64,
) -> f64 {
    (2.0 * flow_stress / (density * gamma)).sqrt() * radius / velocity
}

/// Mott's two-dimensional distribution with mean fragment mass 2μ.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MottDistribution {
    /// The distribution's mass scale μ (kg): half the mean fragment mass.
    pub mu: f64,
}

impl MottDistribution {
    /// The distribution whose mean fragment is an x₀ × x₀ patch of a wall
    /// of `thickness` (m) and `density` (kg/m³): 2μ = ρ t x₀².
    pub fn of_patches(spacing: f64, thickness: f64, density: f64) -> Self {
        Self {
            mu: 0.5 * density * thickness * spacing * spacing,
        }
    }

    /// Mean fragment mass 2μ, kg.
    pub fn mean_mass(&self) -> f64 {
        2.0 * self.mu
    }

    /// Share of the fragments heavier than `m`: exp(−(m/μ)^{1/2}).
    pub fn number_fraction_above(&self, m: f64) -> f64 {
        (-(m / self.mu).sqrt()).exp()
    }

    /// Share of the mass in fragments heavier than `m`:
    /// (s² + 2s + 2) e^{−s}/2 with s = (m/μ)^{1/2} (the number density
    /// N₀ e^{−s} ds in s = (m/μ)^{1/2} weighted by m = μ s²).
    pub fn mass_fraction_above(&self, m: f64) -> f64 {
        let s = (m / self.mu).sqrt();
        0.5 * (s * s + 2.0 * s + 2.0) * (-s).exp()
    }

    /// The mass median m₅₀: the fragments heavier than it hold half the
    /// mass; m₅₀ = s₅₀² μ with (s² + 2s + 2) e^{−s} = 1, s₅₀ ≈ 2.67406.
    pub fn mass_median(&self) -> f64 {
        // Newton on g(s) = ln(s² + 2s + 2) − s, decreasing for s > 0.
        let mut s: f64 = 2.5;
        for _ in 0..50 {
            let q = s * s + 2.0 * s + 2.0;
            let g = q.ln() - s;
            let dg = (2.0 * s + 2.0) / q - 1.0;
            let step = g / dg;
            s -= step;
            if step.abs() < 1e-15 * s {
                break;
            }
        }
        s * s * self.mu
    }

    /// Expected fragment count of a wall of mass `total` (kg):
    /// total / (2μ).
    pub fn count(&self, total: f64) -> f64 {
        total / self.mean_mass()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    #[test]
    fn fracture_spacing_by_hand() {
        // (2 · 750e6 / (7850 · 100))^{1/2} = 43.7135 m/s; × 0.0159 / 930.
        let x = fracture_spacing(750e6, 7850.0, 100.0, 0.0159, 930.0);
        let by_hand = (1.5e9f64 / 785_000.0).sqrt() * 0.0159 / 930.0;
        assert_eq!(x, by_hand);
        assert!((x - 7.4736e-4).abs() < 1e-8, "{x}");
        // x₀ ∝ γ^{-1/2}: four times γ, half the spacing.
        let x4 = fracture_spacing(750e6, 7850.0, 400.0, 0.0159, 930.0);
        assert!((x / x4 - 2.0).abs() < 1e-14);
    }

    #[test]
    fn mass_median_solves_its_equation() {
        let d = MottDistribution { mu: 1.0 };
        let m50 = d.mass_median();
        let s: f64 = m50.sqrt();
        assert!(((s * s + 2.0 * s + 2.0) * (-s).exp() - 1.0).abs() < 1e-13);
        assert!((s - 2.674_06).abs() < 1e-5, "{s}");
        assert!((d.mass_fraction_above(m50) - 0.5).abs() < 1e-13);
    }

    #[test]
    fn patches_give_the_mean_mass() {
        // A 2 mm square of a 3.175 mm steel wall: 7850 · 3.175e-3 · 4e-6.
        let d = MottDistribution::of_patches(2e-3, 3.175e-3, 7850.0);
        assert!((d.mean_mass() - 9.9695e-5).abs() < 1e-12);
        assert!((d.count(0.2) - 0.2 / 9.9695e-5).abs() < 1e-9);
    }

    proptest! {
        /// Both fractions fall from 1 at m = 0 to 0, the mass fraction
        /// above the number fraction (heavy fragments hold more than their
        /// share of the mass), and the mean of the number distribution is
        /// 2μ (∫ N(>m) dm / N₀ = 2μ, by Simpson's rule in s).
        #[test]
        fn the_distribution_is_a_distribution(mu in 1e-6f64..1.0, x in 0.0f64..50.0) {
            let d = MottDistribution { mu };
            let m = x * mu;
            let (n, w) = (d.number_fraction_above(m), d.mass_fraction_above(m));
            prop_assert!((0.0..=1.0).contains(&n) && (0.0..=1.0 + 1e-15).contains(&w));
            prop_assert!(w >= n - 1e-15);
            prop_assert!(d.number_fraction_above(m * 1.1 + 1e-12) <= n);
            prop_assert!((d.number_fraction_above(0.0) - 1.0).abs() < 1e-15);
            prop_assert!((d.mass_fraction_above(0.0) - 1.0).abs() < 1e-15);
            // ∫₀^∞ e^{−√(m/μ)} dm = 2μ ∫₀^∞ s e^{−s} ds = 2μ.
            let (k, top) = (4000, 60.0);
            let h = top / k as f64;
            let f = |s: f64| 2.0 * mu * s * (-s).exp();
            let mut sum = f(0.0) + f(top);
            for i in 1..k {
                sum += f(i as f64 * h) * if i % 2 == 1 { 4.0 } else { 2.0 };
            }
            prop_assert!((sum * h / 3.0 / d.mean_mass() - 1.0).abs() < 1e-9);
        }
    }
}
