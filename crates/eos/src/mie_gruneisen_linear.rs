//! Mie–Grüneisen EOS on the Hugoniot of the linear shock–particle velocity
//! fit Uₛ = C₀ + S uₚ, seed 000 §4.2, eq 40 (the container metal).
//!
//! **Eq 40 as printed**, with η = ρ/ρ₀ and E the internal energy per unit
//! *reference volume* (J/m³):
//!
//! p = ρ₀C₀²(η − 1)[η − (Γ₀/2)(η − 1)] / [η − S_α(η − 1)]² + Γ₀ E.
//!
//! **Reconciled with the textbook form.** Write χ = 1 − ρ₀/ρ = (η − 1)/η
//! (the volumetric compression). Dividing numerator and denominator by η²,
//!
//! p = p_H(χ) (1 − Γ₀χ/2) + Γ₀ρ₀ e,  p_H(χ) = ρ₀C₀² χ / (1 − S_α χ)²,
//!
//! with e = E/ρ₀ the specific internal energy (J/kg). This is
//! p = p_H + Γρ (e − e_H) about the Hugoniot, with the Hugoniot energy
//! e_H = p_H χ /(2ρ₀) = ½ p_H (1/ρ₀ − 1/ρ) and Γρ = Γ₀ρ₀ (Γ falls as the
//! material is compressed). Both forms give the same numbers; a unit test
//! evaluates eq 40 literally against the code.
//!
//! **Tension.** The Uₛ–uₚ fit is a compression law. Eq 40 is used as printed
//! for χ < 0 too (as Uintah's MPM implementation of it does); on the valid
//! window ρ/ρ₀ ≥ [`MIN_RELATIVE_DENSITY`] it is smooth, rises with density
//! and has c² ≥ 0 for the shipped metals (checked by `validate`).
//!
//! **Thermal part** (not in the seed, whose 4340 steel uses a
//! temperature-dependent specific heat): constant c_v, T = T₀ + e/c_v.

use crate::mie_gruneisen::{
    check_density_pressure, check_pressure_temperature, check_window, linear_hugoniot,
    solve_density, MAX_RELATIVE_DENSITY, MIN_RELATIVE_DENSITY,
};
use brisance_core::{Eos, EosError};
use serde::{Deserialize, Serialize};

const NAME: &str = "mie_gruneisen_linear";

/// Parameters of the linear Uₛ–uₚ Mie–Grüneisen EOS (seed 000 eq 40) with a
/// constant-c_v thermal part.
///
/// Valid for ρ/ρ₀ in [[`MIN_RELATIVE_DENSITY`], [`MAX_RELATIVE_DENSITY`]]
/// and T ≥ 0 (e ≥ −c_v T₀); [`MieGruneisenLinear::validate`] checks that
/// the pole at χ = 1/S lies beyond the window and that the pressure rises
/// with density with c² ≥ 0 on it.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MieGruneisenLinear {
    /// Bulk sound speed C₀ (intercept of Uₛ = C₀ + S uₚ), m/s.
    pub c0: f64,
    /// Slope S_α of Uₛ = C₀ + S uₚ, dimensionless.
    pub s: f64,
    /// Grüneisen coefficient at the reference state Γ₀ (Γρ = Γ₀ρ₀),
    /// dimensionless.
    pub gamma0: f64,
    /// Reference density ρ₀, kg/m³.
    pub rho0: f64,
    /// Specific heat at constant volume c_v, J/(kg·K).
    pub cv: f64,
    /// Reference temperature T₀ (e = 0), K.
    pub t0: f64,
}

impl MieGruneisenLinear {
    /// 4340 steel, seed 000 Table 1: ρ₀ = 7830 kg/m³, C₀ = 3574 m/s,
    /// Γ₀ = 1.69, S_α = 1.92, T₀ = 294 K. The seed's steel has a
    /// temperature-dependent c_v; the constant c_v = 477 J/(kg·K) is the
    /// 4340 value of Johnson & Cook (1983).
    pub fn steel_4340() -> Self {
        Self {
            c0: 3574.0,
            s: 1.92,
            gamma0: 1.69,
            rho0: 7830.0,
            cv: 477.0,
            t0: 294.0,
        }
    }

    /// OFHC copper (the tube of seed 000 §5.2, ρ₀ = 8930 kg/m³): C₀ =
    /// 3940 m/s, S = 1.489, Γ₀ = 2.02 from Steinberg, *Equation of state and
    /// strength properties of selected materials*, UCRL-MA-106439 (1996);
    /// c_v = 383 J/(kg·K) from Johnson & Cook (1983); T₀ = 300 K.
    pub fn ofhc_copper() -> Self {
        Self {
            c0: 3940.0,
            s: 1.489,
            gamma0: 2.02,
            rho0: 8930.0,
            cv: 383.0,
            t0: 300.0,
        }
    }

    /// Rolled homogeneous armour steel: the Uₛ–uₚ fit of seed 001 §4.5
    /// (Γ = 2.17, C₀ = 4569 m/s, S = 1.49, which seed 001 applies to the RHA
    /// plates of §5.4) on the linear Hugoniot that seed 001's cubic expands;
    /// ρ₀ = 7850 kg/m³ (nominal RHA, MIL-DTL-12560), c_v = 477 J/(kg·K)
    /// (steel, Johnson & Cook 1983), T₀ = 300 K.
    pub fn rha_steel() -> Self {
        Self {
            c0: 4569.0,
            s: 1.49,
            gamma0: 2.17,
            rho0: 7850.0,
            cv: 477.0,
            t0: 300.0,
        }
    }

    /// Checks the parameters: every one positive and finite; the Hugoniot
    /// pole χ = 1/S beyond the window (S (1 − 1/[`MAX_RELATIVE_DENSITY`]) < 1,
    /// i.e. S < 3); and on the window at T = 0 (where the pressure is least
    /// stiff) ∂p/∂ρ|ₑ > 0 and c² ≥ 0. The message names the field.
    pub fn validate(&self) -> Result<(), String> {
        for (field, value) in [
            ("c0", self.c0),
            ("s", self.s),
            ("gamma0", self.gamma0),
            ("rho0", self.rho0),
            ("cv", self.cv),
            ("t0", self.t0),
        ] {
            if !(value > 0.0 && value.is_finite()) {
                return Err(format!(
                    "{NAME}: field `{field}` = {value}, expected a finite value > 0"
                ));
            }
        }
        let chi_max = 1.0 - 1.0 / MAX_RELATIVE_DENSITY;
        if !(self.s * chi_max < 1.0) {
            return Err(format!(
                "{NAME}: field `s` = {}, expected s < {} so that the Hugoniot pole 1 − ρ₀/ρ = 1/s lies beyond ρ/ρ₀ = {MAX_RELATIVE_DENSITY}",
                self.s,
                1.0 / chi_max
            ));
        }
        let e_cold = -self.cv * self.t0;
        for i in 0..=200 {
            let x = MIN_RELATIVE_DENSITY
                + (MAX_RELATIVE_DENSITY - MIN_RELATIVE_DENSITY) * f64::from(i) / 200.0;
            let rho = x * self.rho0;
            if !(self.dp_drho(rho, e_cold) > 0.0 && self.sound_speed_squared(rho, e_cold) >= 0.0) {
                return Err(format!(
                    "{NAME}: fields `c0`, `s`, `gamma0` give a pressure that does not rise with density (or c² < 0) at ρ/ρ₀ = {x:.3}, T = 0; expected ∂p/∂ρ > 0 and c² ≥ 0 on ρ/ρ₀ ∈ [{MIN_RELATIVE_DENSITY}, {MAX_RELATIVE_DENSITY}]"
                ));
            }
        }
        Ok(())
    }

    /// The reference-curve part p_H (1 − Γ₀χ/2) and its ρ-derivative.
    #[inline]
    fn reference(&self, rho: f64) -> (f64, f64) {
        let chi = 1.0 - self.rho0 / rho;
        let (ph, dph_dchi) = linear_hugoniot(self.rho0, self.c0, self.s, chi);
        let factor = 1.0 - 0.5 * self.gamma0 * chi;
        let dchi_drho = self.rho0 / (rho * rho);
        (
            ph * factor,
            (dph_dchi * factor - 0.5 * self.gamma0 * ph) * dchi_drho,
        )
    }
}

impl Eos for MieGruneisenLinear {
    fn name(&self) -> &'static str {
        NAME
    }

    fn reference_density(&self) -> f64 {
        self.rho0
    }

    /// Seed 000 eq 40 in the form p_H(χ)(1 − Γ₀χ/2) + Γ₀ρ₀e.
    #[inline]
    fn pressure(&self, rho: f64, e: f64) -> f64 {
        self.reference(rho).0 + self.gamma0 * self.rho0 * e
    }

    #[inline]
    fn dp_drho(&self, rho: f64, _e: f64) -> f64 {
        self.reference(rho).1
    }

    #[inline]
    fn dp_de(&self, _rho: f64, _e: f64) -> f64 {
        self.gamma0 * self.rho0
    }

    /// The model's Grüneisen parameter Γ = (1/ρ) ∂p/∂e|ρ = Γ₀ρ₀/ρ.
    #[inline]
    fn gruneisen(&self, rho: f64, _e: f64) -> f64 {
        self.gamma0 * self.rho0 / rho
    }

    /// The state (ρ, e) is inside the valid window: ρ/ρ₀ in
    /// [[`MIN_RELATIVE_DENSITY`], [`MAX_RELATIVE_DENSITY`]] and e finite
    /// (NaN and ρ ≤ 0 are rejected).
    fn check_state(&self, rho: f64, e: f64) -> Result<(), EosError> {
        check_window(NAME, self.rho0, rho, e)
    }

    /// e = (p − p_H(1 − Γ₀χ/2)) / (Γ₀ρ₀).
    fn specific_internal_energy(&self, rho: f64, p: f64) -> Result<f64, EosError> {
        check_density_pressure(NAME, self.rho0, rho, p)?;
        Ok((p - self.reference(rho).0) / (self.gamma0 * self.rho0))
    }

    /// T = T₀ + e/c_v.
    fn temperature(&self, _rho: f64, e: f64) -> f64 {
        self.t0 + e / self.cv
    }

    fn specific_internal_energy_from_temperature(&self, _rho: f64, t: f64) -> f64 {
        self.cv * (t - self.t0)
    }

    fn cv(&self, _rho: f64, _t: f64) -> f64 {
        self.cv
    }

    /// Solves p(ρ, c_v(T − T₀)) = p on the valid window: the closed-form
    /// root of [`MieGruneisenLinear::compression_at`] polished by one
    /// bracketed Newton step (the shared Mie–Grüneisen solver).
    fn density(&self, p: f64, t: f64) -> Result<f64, EosError> {
        self.density_counted(p, t).map(|(rho, _)| rho)
    }

    /// κ = 1/(ρ ∂p/∂ρ|_T), and ∂p/∂ρ|_T = ∂p/∂ρ|ₑ because e = c_v(T − T₀).
    fn isothermal_compressibility(&self, p: f64, t: f64) -> Result<f64, EosError> {
        let rho = self.density(p, t)?;
        Ok(1.0 / (rho * self.dp_drho(rho, 0.0)))
    }

    /// α = (∂p/∂T|ρ)/(ρ ∂p/∂ρ|_T) = Γ₀ρ₀ c_v / (ρ ∂p/∂ρ|ₑ).
    fn thermal_expansivity(&self, p: f64, t: f64) -> Result<f64, EosError> {
        let rho = self.density(p, t)?;
        Ok(self.gamma0 * self.rho0 * self.cv / (rho * self.dp_drho(rho, 0.0)))
    }

    /// One inversion for ρ, then κ and α at it by the formulas of
    /// [`Eos::isothermal_compressibility`] and [`Eos::thermal_expansivity`]
    /// (the same operations, so the same bits).
    fn density_and_derivatives(&self, p: f64, t: f64) -> Result<(f64, f64, f64), EosError> {
        let rho = self.density(p, t)?;
        let rho_slope = rho * self.dp_drho(rho, 0.0);
        Ok((
            rho,
            1.0 / rho_slope,
            self.gamma0 * self.rho0 * self.cv / rho_slope,
        ))
    }
}

impl MieGruneisenLinear {
    /// The compression χ = 1 − ρ₀/ρ at which the reference part of the
    /// pressure, p_H(χ)(1 − Γ₀χ/2), equals `p_ref`, in closed form.
    ///
    /// With K₀ = ρ₀C₀², K₀χ(1 − Γ₀χ/2) = p_ref (1 − Sχ)² is the quadratic
    /// (p_ref S² + K₀Γ₀/2) χ² − (K₀ + 2 p_ref S) χ + p_ref = 0, whose
    /// discriminant is K₀ (K₀ + 2 p_ref (2S − Γ₀)). Its root through χ = 0
    /// at p_ref = 0 — the branch the valid window lies on, where p rises
    /// with ρ — is, in the form without cancellation,
    ///
    /// χ = 2 p_ref / (K₀ + 2 p_ref S + √(K₀ (K₀ + 2 p_ref (2S − Γ₀)))).
    ///
    /// `None` where the discriminant is negative or the denominator not
    /// positive (no root on that branch: far outside the window).
    #[inline]
    pub fn compression_at(&self, p_ref: f64) -> Option<f64> {
        let k0 = self.rho0 * self.c0 * self.c0;
        let disc = k0 * (k0 + 2.0 * p_ref * (2.0 * self.s - self.gamma0));
        let den = k0 + 2.0 * p_ref * self.s + disc.sqrt();
        (disc >= 0.0 && den > 0.0).then(|| 2.0 * p_ref / den)
    }

    /// ρ(p, T) and the number of pressure evaluations it took: the closed
    /// form of [`Self::compression_at`] starts the bracketed Newton solver, whose first
    /// Newton step is then round-off (one evaluation in all). Where the
    /// closed form has no root the start is the window's midpoint and the
    /// bracketed iteration reports the error.
    pub(crate) fn density_counted(&self, p: f64, t: f64) -> Result<(f64, usize), EosError> {
        check_pressure_temperature(NAME, p, t)?;
        let e = self.cv * (t - self.t0);
        let thermal = self.gamma0 * self.rho0 * e;
        let guess = self
            .compression_at(p - thermal)
            .map_or(f64::NAN, |chi| self.rho0 / (1.0 - chi));
        solve_density(
            NAME,
            |rho| {
                let (p_ref, slope) = self.reference(rho);
                (p_ref + thermal, slope)
            },
            p,
            MIN_RELATIVE_DENSITY * self.rho0,
            MAX_RELATIVE_DENSITY * self.rho0,
            guess,
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Seed 000 eq 40 exactly as printed: η = ρ/ρ₀, E per unit reference
    /// volume.
    fn eq40_as_printed(m: &MieGruneisenLinear, rho: f64, e: f64) -> f64 {
        let eta = rho / m.rho0;
        let big_e = m.rho0 * e;
        m.rho0 * m.c0 * m.c0 * (eta - 1.0) * (eta - 0.5 * m.gamma0 * (eta - 1.0))
            / (eta - m.s * (eta - 1.0)).powi(2)
            + m.gamma0 * big_e
    }

    #[test]
    fn pressure_equals_seed000_eq40_as_printed() {
        let steel = MieGruneisenLinear::steel_4340();
        for (x, e) in [
            (0.85, -5e4),
            (0.99, 0.0),
            (1.0, 1e5),
            (1.07, 2e5),
            (1.45, 1e6),
        ] {
            let rho = x * steel.rho0;
            let (a, b) = (steel.pressure(rho, e), eq40_as_printed(&steel, rho, e));
            assert!(
                (a - b).abs() <= 1e-12 * a.abs().max(1e5),
                "{a} vs {b} at ρ/ρ₀ = {x}"
            );
        }
    }

    #[test]
    fn steel_4340_at_ten_percent_compression_matches_hand_value() {
        // ρ = 1.1 ρ₀ ⇒ χ = 1/11; ρ₀C₀² = 7830 × 3574² = 1.000163e11 Pa;
        // p_H = K χ/(1 − 1.92/11)² = 1.000163e11 × 0.0909091/0.681405 = 1.334418e10 Pa;
        // × (1 − 1.69/22) = 0.923182 ⇒ 1.231910e10 Pa at e = 0.
        let steel = MieGruneisenLinear::steel_4340();
        let p = steel.pressure(1.1 * 7830.0, 0.0);
        assert!((p - 1.231_910e10).abs() < 1e5, "p = {p}");
    }

    #[test]
    fn gruneisen_falls_as_gamma0_rho0_over_rho() {
        let steel = MieGruneisenLinear::steel_4340();
        assert_eq!(steel.gruneisen(7830.0, 0.0), 1.69);
        let rho = 1.2 * 7830.0;
        assert!((steel.gruneisen(rho, 0.0) - 1.69 / 1.2).abs() < 1e-15);
        assert!((steel.dp_de(rho, 0.0) / rho - steel.gruneisen(rho, 0.0)).abs() < 1e-15);
    }

    #[test]
    fn reference_state_has_zero_pressure_and_bulk_sound_speed() {
        for m in [
            MieGruneisenLinear::steel_4340(),
            MieGruneisenLinear::ofhc_copper(),
            MieGruneisenLinear::rha_steel(),
        ] {
            assert_eq!(m.pressure(m.rho0, 0.0), 0.0);
            assert!((m.sound_speed(m.rho0, 0.0) - m.c0).abs() < 1e-9 * m.c0);
            assert_eq!(m.temperature(m.rho0, 0.0), m.t0);
        }
    }

    #[test]
    fn expansivity_of_copper_at_ambient_is_near_handbook() {
        // α = Γ₀ ρ₀ c_v / (ρ · ρ₀C₀²) ≈ Γ₀ c_v / C₀² at ρ ≈ ρ₀:
        // 2.02 × 383 / 3940² = 4.9838e-5 /K, the volumetric expansivity of
        // copper being 3 × 16.5e-6 = 4.95e-5 /K.
        let cu = MieGruneisenLinear::ofhc_copper();
        let alpha = cu.thermal_expansivity(101_325.0, 300.0).unwrap();
        assert!((alpha - 4.9838e-5).abs() < 1e-9, "α = {alpha}");
        let kappa = cu.isothermal_compressibility(101_325.0, 300.0).unwrap();
        // κ = 1/(ρ₀C₀²) = 1/1.386257e11 = 7.21367e-12 /Pa
        assert!((kappa - 7.21367e-12).abs() < 1e-16, "κ = {kappa}");
    }

    #[test]
    fn out_of_range_inputs_are_errors() {
        let steel = MieGruneisenLinear::steel_4340();
        assert!(steel.check_state(0.0, 0.0).is_err());
        assert!(steel.check_state(f64::NAN, 0.0).is_err());
        assert!(steel.check_state(7830.0, f64::INFINITY).is_err());
        assert!(steel.check_state(7830.0 * 0.5, 0.0).is_err());
        assert!(steel.specific_internal_energy(-1.0, 0.0).is_err());
        assert!(steel.specific_internal_energy(7830.0, f64::NAN).is_err());
        assert!(steel.density(1e9, 0.0).is_err());
        assert!(steel.density(-1e12, 300.0).is_err());
    }

    #[test]
    fn validate_rejects_a_pole_inside_the_window() {
        let mut bad = MieGruneisenLinear::steel_4340();
        bad.s = 3.5;
        let msg = bad.validate().unwrap_err();
        assert!(msg.contains("`s`"), "{msg}");
        for m in [
            MieGruneisenLinear::steel_4340(),
            MieGruneisenLinear::ofhc_copper(),
            MieGruneisenLinear::rha_steel(),
        ] {
            assert!(m.validate().is_ok(), "{:?}", m.validate());
        }
    }

    // Valid window ρ/ρ₀ ∈ [0.8, 1.5] (kept a little inside for the
    // finite-difference probes), T from about 50 K to 2000 K.
    brisance_core::eos_contract_tests!(linear_steel_4340, MieGruneisenLinear::steel_4340(), rho: 6350.0..11650.0, e: -1.1e5..8.0e5);
    brisance_core::eos_contract_tests!(linear_ofhc_copper, MieGruneisenLinear::ofhc_copper(), rho: 7240.0..13290.0, e: -9.5e4..6.0e5);
    brisance_core::eos_contract_tests!(linear_rha_steel, MieGruneisenLinear::rha_steel(), rho: 6360.0..11700.0, e: -1.1e5..8.0e5);
}
