//! Johnson–Cook damage, seed 000 eq 47 (Johnson & Cook 1985, seed 000
//! ref \[36\]).
//!
//! The plastic strain at fracture is
//!
//! ε_p^f = [D₁ + D₂ exp((D₃/3) σ*)] [1 + D₄ ln ε̇*] [1 + D₅ T*],
//! σ* = tr(σ)/σ_eq,
//!
//! so (D₃/3)σ* = D₃ σ_m/σ_eq with σ_m the mean stress (tension positive):
//! triaxial tension (σ* > 0) lowers the fracture strain when D₃ < 0. Damage
//! accumulates as D = Σ Δε_p / ε_p^f (ε_p^f evaluated at the state of each
//! increment) and the point fails when D ≥ 1. As in the flow stress,
//! ε̇* = ε̇_p/ε̇₀ is clamped to ≥ 1 and T* to [0, 1]; ε_p^f is floored at
//! [`MIN_FRACTURE_STRAIN`] so a parameter set with D₁ < 0 cannot give a
//! zero or negative fracture strain.
//!
//! **Initial damage.** Seed 000 §4.2 spreads the fracture strains over the
//! points "by initializing the damage variable to a non-zero value": with
//! `initial_damage` given, each point starts from its own D₀ drawn from that
//! Gaussian (seed 000 §5.3: mean 0.005, standard deviation 0.001), truncated
//! to [0, 1] unless the config narrows it ([`crate::random`]); a point then
//! fails after (1 − D₀) of its fracture strain. Without it D₀ = 0.
//!
//! **The failed point.** Seed 000 §4.2 sets the stress of a failed point to
//! zero ("a free surface has been created"). Here a failed point keeps its
//! pressure in compression and carries no deviatoric and no tensile stress:
//! σ = −max(p, 0) I. A crack then opens freely but closed, failed material
//! still resists interpenetration, as the rubble of a fragmenting case does;
//! this is the usual choice in hydrocodes (LS-DYNA's and AUTODYN's failed
//! elements in compression). Failure is irreversible (the failed flag and D
//! never decrease).

use crate::{
    error::{non_negative, positive},
    flow_stress::homologous_temperature,
    random::{Gaussian, STREAM_DAMAGE},
    ConstitutiveError,
};
use serde::{Deserialize, Serialize};

const NAME: &str = "johnson_cook_damage";

/// Smallest fracture strain the damage rule divides by.
pub const MIN_FRACTURE_STRAIN: f64 = 1.0e-6;

/// Parameters of the Johnson–Cook fracture strain (seed 000 eq 47).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct JohnsonCookDamage {
    /// D₁ (dimensionless).
    pub d1: f64,
    /// D₂ (dimensionless).
    pub d2: f64,
    /// D₃ (dimensionless), multiplies σ*/3.
    pub d3: f64,
    /// D₄ (dimensionless), rate coefficient.
    pub d4: f64,
    /// D₅ (dimensionless), temperature coefficient.
    pub d5: f64,
    /// Reference plastic strain rate ε̇₀, 1/s.
    pub eps_dot0: f64,
    /// Room temperature of T*, K.
    pub t_room: f64,
    /// Melt temperature of T*, K.
    pub t_melt: f64,
    /// Gaussian initial damage D₀ over the points (seed 000 §4.2, §5.3);
    /// none: D₀ = 0.
    #[serde(default)]
    pub initial_damage: Option<Gaussian>,
}

impl JohnsonCookDamage {
    /// 4340 steel, seed 000 Table 1: D₁ = 0.05, D₂ = 3.44, D₃ = −2.12,
    /// D₄ = 0.002, D₅ = 0.61; T₀ = 294 K, T_m = 1793 K, ε̇₀ = 1 s⁻¹.
    pub fn steel_4340_seed000() -> Self {
        Self {
            d1: 0.05,
            d2: 3.44,
            d3: -2.12,
            d4: 0.002,
            d5: 0.61,
            eps_dot0: 1.0,
            t_room: 294.0,
            t_melt: 1793.0,
            initial_damage: None,
        }
    }

    /// OFHC copper, Johnson & Cook, *Fracture characteristics of three
    /// metals subjected to various strains, strain rates, temperatures and
    /// pressures*, Eng. Fract. Mech. 21 (1985) 31–48 (seed 000 ref \[36\]):
    /// D₁ = 0.54, D₂ = 4.89, D₃ = −3.03, D₄ = 0.014, D₅ = 1.12;
    /// T_room = 294 K, T_melt = 1356 K, ε̇₀ = 1 s⁻¹.
    pub fn ofhc_copper_johnson_cook_1985() -> Self {
        Self {
            d1: 0.54,
            d2: 4.89,
            d3: -3.03,
            d4: 0.014,
            d5: 1.12,
            eps_dot0: 1.0,
            t_room: 294.0,
            t_melt: 1356.0,
            initial_damage: None,
        }
    }

    /// Checks the parameters; the message names the bad field.
    pub fn validate(&self) -> Result<(), ConstitutiveError> {
        for (field, value) in [("d1", self.d1), ("d3", self.d3)] {
            if !value.is_finite() {
                return Err(ConstitutiveError::InvalidParameter {
                    model: NAME,
                    field,
                    value,
                    expected: "a finite value",
                });
            }
        }
        non_negative(NAME, "d2", self.d2)?;
        non_negative(NAME, "d4", self.d4)?;
        non_negative(NAME, "d5", self.d5)?;
        positive(NAME, "eps_dot0", self.eps_dot0)?;
        positive(NAME, "t_room", self.t_room)?;
        positive(NAME, "t_melt", self.t_melt)?;
        if !(self.t_melt > self.t_room) {
            return Err(ConstitutiveError::InvalidParameter {
                model: NAME,
                field: "t_melt",
                value: self.t_melt,
                expected: "a melt temperature above `t_room`, K",
            });
        }
        match &self.initial_damage {
            Some(g) => g.validate(NAME, "initial_damage", 0.0, 1.0),
            None => Ok(()),
        }
    }

    /// The initial damage D₀: the distribution's mean without a seed, the
    /// point's draw with one (seed 000 §4.2); 0 without a distribution.
    pub fn initial(&self, point_seed: Option<u64>) -> f64 {
        match (&self.initial_damage, point_seed) {
            (None, _) => 0.0,
            (Some(g), None) => g.mean_within(0.0, 1.0),
            (Some(g), Some(seed)) => g.sample(seed, STREAM_DAMAGE, 0.0, 1.0),
        }
    }

    /// Plastic strain at fracture ε_p^f (seed 000 eq 47) for the stress
    /// triaxiality σ* = tr(σ)/σ_eq, the plastic strain rate ε̇_p (1/s) and
    /// the temperature T (K).
    #[inline]
    pub fn fracture_strain(&self, sigma_star: f64, eps_p_rate: f64, t: f64) -> f64 {
        let rate_star = (eps_p_rate / self.eps_dot0).max(1.0);
        let t_star = homologous_temperature(t, self.t_room, self.t_melt);
        let eps_f = (self.d1 + self.d2 * (self.d3 / 3.0 * sigma_star).exp())
            * (1.0 + self.d4 * rate_star.ln())
            * (1.0 + self.d5 * t_star);
        eps_f.max(MIN_FRACTURE_STRAIN)
    }

    /// Damage after a plastic increment Δε_p: D + Δε_p/ε_p^f. `mean_stress`
    /// σ_m = tr(σ)/3 and `sigma_eq` the von Mises stress (Pa) at the end of
    /// the increment. With no equivalent stress (σ* undefined) or no
    /// increment, D is unchanged.
    #[inline]
    pub fn accumulate(
        &self,
        damage: f64,
        d_eps_p: f64,
        mean_stress: f64,
        sigma_eq: f64,
        eps_p_rate: f64,
        t: f64,
    ) -> f64 {
        if !(d_eps_p > 0.0 && sigma_eq > 0.0) {
            return damage;
        }
        let sigma_star = 3.0 * mean_stress / sigma_eq;
        damage + d_eps_p / self.fracture_strain(sigma_star, eps_p_rate, t)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fracture_strain_4340_matches_hand_computed_values() {
        let d = JohnsonCookDamage::steel_4340_seed000();
        // Pure shear (σ* = 0), reference rate, room temperature:
        // ε_f = D₁ + D₂ = 3.49.
        assert!((d.fracture_strain(0.0, 1.0, 294.0) - 3.49).abs() < 1e-12);
        // Uniaxial tension σ* = tr σ/σ_eq = 1: 0.05 + 3.44 e^(−2.12/3)
        // = 0.05 + 3.44 × 0.4932857 = 1.746903.
        let got = d.fracture_strain(1.0, 1.0, 294.0);
        assert!((got - 1.746903).abs() < 1e-6, "{got}");
        // Rate 1e4/s and T* = 0.5 multiply by (1 + 0.002 ln 1e4)(1 + 0.305).
        let scaled = d.fracture_strain(1.0, 1e4, 294.0 + 0.5 * 1499.0);
        let factor = (1.0 + 0.002 * 1e4_f64.ln()) * 1.305;
        assert!((scaled - got * factor).abs() < 1e-12, "{scaled}");
    }

    #[test]
    fn damage_accumulates_plastic_strain_over_fracture_strain() {
        let d = JohnsonCookDamage::steel_4340_seed000();
        // Shear: ε_f = 3.49, so Δε_p = 0.349 adds 0.1.
        let next = d.accumulate(0.2, 0.349, 0.0, 500e6, 1.0, 294.0);
        assert!((next - 0.3).abs() < 1e-12, "{next}");
        // No increment, no change.
        assert_eq!(d.accumulate(0.2, 0.0, 1e8, 500e6, 1.0, 294.0), 0.2);
    }

    #[test]
    fn tension_damages_faster_than_compression() {
        let d = JohnsonCookDamage::ofhc_copper_johnson_cook_1985();
        assert!(d.fracture_strain(1.0, 1.0, 294.0) < d.fracture_strain(-1.0, 1.0, 294.0));
    }

    #[test]
    fn validate_names_the_bad_field() {
        let bad = JohnsonCookDamage {
            eps_dot0: 0.0,
            ..JohnsonCookDamage::steel_4340_seed000()
        };
        let msg = bad.validate().unwrap_err().to_string();
        assert!(msg.contains("eps_dot0"), "{msg}");
        let bad = JohnsonCookDamage {
            initial_damage: Some(Gaussian::new(1.5, 0.1)),
            ..JohnsonCookDamage::steel_4340_seed000()
        };
        let msg = bad.validate().unwrap_err().to_string();
        assert!(msg.contains("initial_damage"), "{msg}");
    }

    /// Seed 000 §5.3: D₀ ~ N(0.005, 0.001). Without a seed the mean; with
    /// one, a draw in [0, 1] that depends on the seed only; 2000 points
    /// average within 5 standard errors (5 × 0.001/√2000 = 1.1e-4) of 0.005.
    #[test]
    fn initial_damage_is_the_mean_or_the_point_draw() {
        let d = JohnsonCookDamage {
            initial_damage: Some(Gaussian::new(0.005, 0.001)),
            ..JohnsonCookDamage::steel_4340_seed000()
        };
        assert_eq!(
            JohnsonCookDamage::steel_4340_seed000().initial(Some(3)),
            0.0
        );
        assert_eq!(d.initial(None), 0.005);
        assert_eq!(d.initial(Some(42)).to_bits(), d.initial(Some(42)).to_bits());
        let n = 2000;
        let mean = (0..n)
            .map(|p| d.initial(Some(crate::random::mix64(p))))
            .inspect(|x| assert!((0.0..=1.0).contains(x)))
            .sum::<f64>()
            / n as f64;
        assert!(
            (mean - 0.005).abs() < 5.0 * 0.001 / (n as f64).sqrt(),
            "{mean}"
        );
    }
}
