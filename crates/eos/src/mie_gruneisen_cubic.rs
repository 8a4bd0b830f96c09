//! Mie–Grüneisen EOS with the cubic Hugoniot of seed 001 §4.5, eqs 65–66,
//! the pressure of the steel plates in the blast examples.
//!
//! p = p_H (1 − γμ/2) + γ ρ E                                   (eq 65)
//! p_H = ρ₀C₀² [μ + (2S − 1)μ² + (S − 1)(3S − 1)μ³]  for μ > 0   (eq 66)
//! p_H = ρ₀C₀² μ                                      for μ < 0
//! μ = ρ/ρ₀ − 1.
//!
//! **What E is.** With p_H in Pa and ρ in kg/m³, γρE is a pressure only if E
//! is an energy per unit mass (J/kg); E per unit volume would make γρE
//! kg·Pa/m³. E per unit mass also makes eq 65 a Mie–Grüneisen EOS about the
//! Hugoniot with constant Γ = γ: the Hugoniot energy is
//! e_H = ½ p_H (1/ρ₀ − 1/ρ) = p_H μ / (2ρ), so
//! p_H + γρ(E − e_H) = p_H(1 − γμ/2) + γρE, which is eq 65 term for term.
//! Brisance therefore reads E as the specific internal energy e (J/kg),
//! measured from the stress-free reference state (ρ₀, e = 0, p = 0).
//!
//! **Thermal part** (not in the seed): constant c_v and T = T₀ + e/c_v, so
//! e = 0 is the reference temperature T₀. All the energy above the reference
//! state is counted as heat, which over-estimates the temperature of strongly
//! compressed states; within the valid window and for the structural
//! loading of seed 001 it is the usual approximation.

use crate::mie_gruneisen::{
    check_density_pressure, check_pressure_temperature, check_window, cubic_hugoniot,
    solve_density, MAX_RELATIVE_DENSITY, MIN_RELATIVE_DENSITY,
};
use brisance_core::{Eos, EosError};
use serde::{Deserialize, Serialize};

const NAME: &str = "mie_gruneisen_cubic";

/// Parameters of the cubic-Hugoniot Mie–Grüneisen EOS (seed 001 eqs 65–66)
/// with a constant-c_v thermal part.
///
/// Valid for ρ/ρ₀ in [[`MIN_RELATIVE_DENSITY`], [`MAX_RELATIVE_DENSITY`]]
/// (the tension branch μ < 0 included) and T ≥ 0, i.e.
/// e ≥ −c_v T₀; [`MieGruneisenCubic::validate`] checks that the parameters
/// give a pressure that rises with density and c² ≥ 0 on that window.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MieGruneisenCubic {
    /// Grüneisen coefficient γ (constant), dimensionless.
    pub gamma: f64,
    /// Bulk sound speed C₀, m/s.
    pub c0: f64,
    /// Slope S of the shock–particle velocity fit Uₛ = C₀ + S uₚ that the
    /// cubic expands, dimensionless.
    pub s: f64,
    /// Stress-free reference density ρ₀, kg/m³.
    pub rho0: f64,
    /// Specific heat at constant volume c_v, J/(kg·K).
    pub cv: f64,
    /// Reference temperature T₀ (e = 0), K.
    pub t0: f64,
}

impl MieGruneisenCubic {
    /// The steel of seed 001 §4.5 (eqs 65–66): γ = 2.17, C₀ = 4569 m/s,
    /// S = 1.49. Seed 001 uses it for the RHA plates of §5.4 (Neuberger,
    /// Peles & Rittel 2007) but gives no density or heat capacity:
    /// ρ₀ = 7850 kg/m³ is the nominal density of rolled homogeneous armour
    /// (MIL-DTL-12560) and c_v = 477 J/(kg·K) the steel value of Johnson &
    /// Cook (1983); T₀ = 300 K.
    pub fn steel_seed001() -> Self {
        Self {
            gamma: 2.17,
            c0: 4569.0,
            s: 1.49,
            rho0: 7850.0,
            cv: 477.0,
            t0: 300.0,
        }
    }

    /// Checks the parameters: every one positive and finite, and on the
    /// valid window at T = 0 (the lowest energy allowed, where the pressure
    /// is least stiff) ∂p/∂ρ|ₑ > 0 and c² ≥ 0. The message names the field
    /// and the expected range.
    pub fn validate(&self) -> Result<(), String> {
        for (field, value) in [
            ("gamma", self.gamma),
            ("c0", self.c0),
            ("s", self.s),
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
        let e_cold = -self.cv * self.t0;
        for i in 0..=200 {
            let x = MIN_RELATIVE_DENSITY
                + (MAX_RELATIVE_DENSITY - MIN_RELATIVE_DENSITY) * f64::from(i) / 200.0;
            let rho = x * self.rho0;
            if !(self.dp_drho(rho, e_cold) > 0.0 && self.sound_speed_squared(rho, e_cold) >= 0.0) {
                return Err(format!(
                    "{NAME}: fields `gamma`, `c0`, `s` give a pressure that does not rise with density (or c² < 0) at ρ/ρ₀ = {x:.3}, T = 0; expected ∂p/∂ρ > 0 and c² ≥ 0 on ρ/ρ₀ ∈ [{MIN_RELATIVE_DENSITY}, {MAX_RELATIVE_DENSITY}]"
                ));
            }
        }
        Ok(())
    }

    /// The reference-curve part p_H (1 − γμ/2) and its ρ-derivative.
    #[inline]
    fn reference(&self, rho: f64) -> (f64, f64) {
        let mu = rho / self.rho0 - 1.0;
        let (ph, dph_dmu) = cubic_hugoniot(self.rho0, self.c0, self.s, mu);
        let factor = 1.0 - 0.5 * self.gamma * mu;
        (
            ph * factor,
            (dph_dmu * factor - 0.5 * self.gamma * ph) / self.rho0,
        )
    }
}

impl Eos for MieGruneisenCubic {
    fn name(&self) -> &'static str {
        NAME
    }

    fn reference_density(&self) -> f64 {
        self.rho0
    }

    /// Seed 001 eq 65 with eq 66, E = e per unit mass.
    #[inline]
    fn pressure(&self, rho: f64, e: f64) -> f64 {
        self.reference(rho).0 + self.gamma * rho * e
    }

    #[inline]
    fn dp_drho(&self, rho: f64, e: f64) -> f64 {
        self.reference(rho).1 + self.gamma * e
    }

    #[inline]
    fn dp_de(&self, rho: f64, _e: f64) -> f64 {
        self.gamma * rho
    }

    /// The model's Grüneisen parameter Γ = (1/ρ) ∂p/∂e|ρ = γ (seed 001
    /// eq 65: the energy term is γρE).
    #[inline]
    fn gruneisen(&self, _rho: f64, _e: f64) -> f64 {
        self.gamma
    }

    /// The state (ρ, e) is inside the valid window: ρ/ρ₀ in
    /// [[`MIN_RELATIVE_DENSITY`], [`MAX_RELATIVE_DENSITY`]] and e finite
    /// (NaN and ρ ≤ 0 are rejected).
    fn check_state(&self, rho: f64, e: f64) -> Result<(), EosError> {
        check_window(NAME, self.rho0, rho, e)
    }

    /// e = (p − p_H(1 − γμ/2)) / (γρ).
    fn specific_internal_energy(&self, rho: f64, p: f64) -> Result<f64, EosError> {
        check_density_pressure(NAME, self.rho0, rho, p)?;
        Ok((p - self.reference(rho).0) / (self.gamma * rho))
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

    /// Solves p(ρ, c_v(T − T₀)) = p on the valid window by bracketed Newton.
    fn density(&self, p: f64, t: f64) -> Result<f64, EosError> {
        self.density_counted(p, t).map(|(rho, _)| rho)
    }

    /// κ = 1/(ρ ∂p/∂ρ|_T); along an isotherm e is fixed, so ∂p/∂ρ|_T = ∂p/∂ρ|ₑ.
    fn isothermal_compressibility(&self, p: f64, t: f64) -> Result<f64, EosError> {
        let rho = self.density(p, t)?;
        let e = self.cv * (t - self.t0);
        Ok(1.0 / (rho * self.dp_drho(rho, e)))
    }

    /// α = (∂p/∂T|ρ)/(ρ ∂p/∂ρ|_T) = γ c_v / ∂p/∂ρ|ₑ.
    fn thermal_expansivity(&self, p: f64, t: f64) -> Result<f64, EosError> {
        let rho = self.density(p, t)?;
        let e = self.cv * (t - self.t0);
        Ok(self.gamma * self.cv / self.dp_drho(rho, e))
    }

    /// One inversion for ρ, then κ and α at it by the formulas of
    /// [`Eos::isothermal_compressibility`] and [`Eos::thermal_expansivity`]
    /// (the same operations, so the same bits).
    fn density_and_derivatives(&self, p: f64, t: f64) -> Result<(f64, f64, f64), EosError> {
        let rho = self.density(p, t)?;
        let slope = self.dp_drho(rho, self.cv * (t - self.t0));
        Ok((rho, 1.0 / (rho * slope), self.gamma * self.cv / slope))
    }
}

impl MieGruneisenCubic {
    /// ρ(p, T) and the number of pressure evaluations the bracketed Newton
    /// solve took.
    pub(crate) fn density_counted(&self, p: f64, t: f64) -> Result<(f64, usize), EosError> {
        check_pressure_temperature(NAME, p, t)?;
        let e = self.cv * (t - self.t0);
        let k0 = self.rho0 * self.c0 * self.c0;
        let guess = self.rho0 * (1.0 + (p - self.gamma * self.rho0 * e) / k0);
        // `pressure` and `dp_drho` with their shared reference curve
        // evaluated once (the same operations, so the same bits).
        solve_density(
            NAME,
            |rho| {
                let (f, df) = self.reference(rho);
                (f + self.gamma * rho * e, df + self.gamma * e)
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

    #[test]
    fn reference_state_has_zero_pressure_and_bulk_sound_speed() {
        let steel = MieGruneisenCubic::steel_seed001();
        assert_eq!(steel.pressure(7850.0, 0.0), 0.0);
        // c² = C₀² at μ = 0, e = 0 (p = 0, ∂p/∂ρ = C₀²).
        assert!((steel.sound_speed(7850.0, 0.0) - 4569.0).abs() < 1e-9);
        assert_eq!(steel.temperature(7850.0, 0.0), 300.0);
    }

    #[test]
    fn ten_percent_compression_matches_hand_value() {
        // μ = 0.1: p_H = 1.638747e11 × 0.1215003 = 1.991083e10 Pa;
        // factor 1 − 2.17 × 0.05 = 0.8915 ⇒ 1.775050e10 Pa;
        // plus γρe = 2.17 × 8635 × 1e5 = 1.873795e9 Pa ⇒ 1.962430e10 Pa.
        let steel = MieGruneisenCubic::steel_seed001();
        let k0 = 7850.0 * 4569.0_f64.powi(2);
        let expected = k0 * 0.121_500_3 * 0.8915 + 2.17 * 8635.0 * 1e5;
        let p = steel.pressure(8635.0, 1e5);
        assert!((p - expected).abs() < 1e-6 * expected, "p = {p}");
        assert!((p - 1.962_430e10).abs() < 1e5, "p = {p}");
    }

    #[test]
    fn tension_branch_is_linear_hugoniot_times_the_gruneisen_factor() {
        // μ = −0.01: p = ρ₀C₀²(−0.01)(1 + 2.17 × 0.005) at e = 0.
        let steel = MieGruneisenCubic::steel_seed001();
        let k0 = 7850.0 * 4569.0_f64.powi(2);
        let p = steel.pressure(7850.0 * 0.99, 0.0);
        let expected = k0 * -0.01 * 1.010_85;
        assert!((p - expected).abs() < 1e-9 * expected.abs(), "p = {p}");
    }

    #[test]
    fn pressure_and_slope_are_continuous_across_mu_zero() {
        let steel = MieGruneisenCubic::steel_seed001();
        let (below, above) = (7850.0 * (1.0 - 1e-12), 7850.0 * (1.0 + 1e-12));
        assert!((steel.pressure(below, 1e4) - steel.pressure(above, 1e4)).abs() < 1.0);
        let (s1, s2) = (steel.dp_drho(below, 1e4), steel.dp_drho(above, 1e4));
        assert!((s1 - s2).abs() < 1e-9 * s1, "{s1} vs {s2}");
    }

    #[test]
    fn gruneisen_is_gamma_and_matches_dp_de_over_rho() {
        let steel = MieGruneisenCubic::steel_seed001();
        let rho = 8000.0;
        assert_eq!(steel.gruneisen(rho, 0.0), 2.17);
        assert!((steel.dp_de(rho, 0.0) / rho - 2.17).abs() < 1e-15);
    }

    #[test]
    fn density_at_ambient_is_just_above_reference() {
        // At T₀ (e = 0), p = 101325 Pa ⇒ μ ≈ p/(ρ₀C₀²) = 6.183e-7.
        let steel = MieGruneisenCubic::steel_seed001();
        let rho = steel.density(101_325.0, 300.0).unwrap();
        let mu = rho / 7850.0 - 1.0;
        assert!(
            (mu - 101_325.0 / (7850.0 * 4569.0_f64.powi(2))).abs() < 1e-12,
            "μ = {mu}"
        );
    }

    #[test]
    fn out_of_range_inputs_are_errors() {
        let steel = MieGruneisenCubic::steel_seed001();
        assert!(steel.check_state(-1.0, 0.0).is_err());
        assert!(steel.check_state(f64::NAN, 0.0).is_err());
        assert!(steel.check_state(7850.0, f64::NAN).is_err());
        assert!(steel.check_state(7850.0 * 1.6, 0.0).is_err());
        assert!(steel.check_state(7850.0 * 1.2, 1e5).is_ok());
        assert!(steel.specific_internal_energy(0.0, 1e5).is_err());
        assert!(steel.density(f64::NAN, 300.0).is_err());
        assert!(steel.density(1e5, -1.0).is_err());
        // beyond the window's pressure range
        assert!(matches!(
            steel.density(1e14, 300.0),
            Err(EosError::OutOfRange { .. })
        ));
    }

    #[test]
    fn validate_names_the_bad_field() {
        let mut bad = MieGruneisenCubic::steel_seed001();
        bad.c0 = -1.0;
        let msg = bad.validate().unwrap_err();
        assert!(msg.contains("`c0`"), "{msg}");
        assert!(MieGruneisenCubic::steel_seed001().validate().is_ok());
    }

    // Valid window ρ/ρ₀ ∈ [0.8, 1.5], kept a little inside so that the
    // finite-difference probes of ρ(p ± h, T) stay in it; T from 50 K to 2300 K.
    brisance_core::eos_contract_tests!(cubic_steel_seed001, MieGruneisenCubic::steel_seed001(), rho: 6300.0..11700.0, e: -1.2e5..9.5e5);
}
