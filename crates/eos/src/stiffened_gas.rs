//! Stiffened-gas EOS (the water of the water–air shock tube, V-WATER-AIR-ICE).
//!
//! p = (γ − 1) ρ e − γ p∞,  e = c_v T + p∞/ρ,
//! so that the thermal EOS is p + p∞ = (γ − 1) ρ c_v T (Le Métayer, Massoni
//! & Saurel 2004, with the energy reference q = 0). With p∞ = 0 it is the
//! ideal gas of seed 001 eq 55. The seed's ICE method only needs the
//! thermal EOS v(p, T) of eq 7 and its derivatives (eq 20):
//! ρ(p, T) = (p + p∞)/((γ − 1) c_v T), κ = 1/(p + p∞), α = 1/T.
//!
//! It is the EOS of the classical water–air shock tube (Saurel & Abgrall
//! 1999; Murrone & Guillard 2005), whose exact solution
//! `brisance_ice::riemann` gives. A config names it as
//! `StiffenedGas(gamma: 4.4, p_inf: 6.0e8, cv: 1600.0, rho0: 1000.0)`
//! ([`crate::EosModel::StiffenedGas`]).

use brisance_core::{Eos, EosError};
use serde::{Deserialize, Serialize};

/// Stiffened gas p = (γ − 1)ρe − γp∞ with e = c_v T + p∞/ρ.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct StiffenedGas {
    /// γ (> 1).
    pub gamma: f64,
    /// p∞, Pa (≥ 0; 0 is an ideal gas).
    pub p_inf: f64,
    /// c_v, J/(kg·K).
    pub cv: f64,
    /// Reference density, kg/m³ (a scale only).
    pub rho0: f64,
}

impl StiffenedGas {
    /// Water of the water–air tube: γ = 4.4, p∞ = 6 × 10⁸ Pa (Saurel &
    /// Abgrall 1999), c_v = 1600 J/(kg·K) (so 1000 kg/m³ at 10⁹ Pa is 294 K;
    /// the mechanical solution does not depend on c_v).
    pub fn water() -> Self {
        Self {
            gamma: 4.4,
            p_inf: 6.0e8,
            cv: 1600.0,
            rho0: 1000.0,
        }
    }

    /// Air, γ = 1.4, c_v = 717.6 J/(kg·K), p∞ = 0.
    pub fn air() -> Self {
        Self {
            gamma: 1.4,
            p_inf: 0.0,
            cv: 287.05 / 0.4,
            rho0: 1.225,
        }
    }

    /// Checks the parameters; the message names the bad field.
    pub fn validate(&self) -> Result<(), String> {
        let checks = [
            ("gamma", self.gamma, self.gamma > 1.0, "> 1"),
            ("p_inf", self.p_inf, self.p_inf >= 0.0, "≥ 0 Pa"),
            ("cv", self.cv, self.cv > 0.0, "> 0 J/(kg·K)"),
            ("rho0", self.rho0, self.rho0 > 0.0, "> 0 kg/m³"),
        ];
        for (field, v, ok, want) in checks {
            if !(ok && v.is_finite()) {
                return Err(format!(
                    "stiffened_gas: field `{field}` = {v}, expected a finite value {want}"
                ));
            }
        }
        Ok(())
    }

    fn out_of_range(detail: String) -> EosError {
        EosError::OutOfRange {
            eos: "stiffened_gas",
            detail,
        }
    }
}

impl Eos for StiffenedGas {
    fn name(&self) -> &'static str {
        "stiffened_gas"
    }

    fn reference_density(&self) -> f64 {
        self.rho0
    }

    #[inline]
    fn pressure(&self, rho: f64, e: f64) -> f64 {
        (self.gamma - 1.0) * rho * e - self.gamma * self.p_inf
    }

    #[inline]
    fn dp_drho(&self, _rho: f64, e: f64) -> f64 {
        (self.gamma - 1.0) * e
    }

    #[inline]
    fn dp_de(&self, rho: f64, _e: f64) -> f64 {
        (self.gamma - 1.0) * rho
    }

    #[inline]
    fn gruneisen(&self, _rho: f64, _e: f64) -> f64 {
        self.gamma - 1.0
    }

    /// c² = γ (p + p∞)/ρ.
    #[inline]
    fn sound_speed_squared(&self, rho: f64, e: f64) -> f64 {
        self.gamma * (self.pressure(rho, e) + self.p_inf) / rho
    }

    fn specific_internal_energy(&self, rho: f64, p: f64) -> Result<f64, EosError> {
        if !(rho.is_finite() && rho > 0.0 && p.is_finite()) {
            return Err(Self::out_of_range(format!(
                "e(ρ, p) needs a finite ρ > 0 and a finite p, got ρ = {rho}, p = {p}"
            )));
        }
        Ok((p + self.gamma * self.p_inf) / ((self.gamma - 1.0) * rho))
    }

    #[inline]
    fn temperature(&self, rho: f64, e: f64) -> f64 {
        (e - self.p_inf / rho) / self.cv
    }

    #[inline]
    fn specific_internal_energy_from_temperature(&self, rho: f64, t: f64) -> f64 {
        self.cv * t + self.p_inf / rho
    }

    fn cv(&self, _rho: f64, _t: f64) -> f64 {
        self.cv
    }

    /// ρ = (p + p∞)/((γ − 1) c_v T).
    #[inline]
    fn density(&self, p: f64, t: f64) -> Result<f64, EosError> {
        if !(p + self.p_inf > 0.0 && t > 0.0 && p.is_finite() && t.is_finite()) {
            return Err(Self::out_of_range(format!(
                "ρ(p, T) needs p + p∞ > 0 and T > 0, got p = {p}, T = {t}"
            )));
        }
        Ok((p + self.p_inf) / ((self.gamma - 1.0) * self.cv * t))
    }

    /// κ = 1/(p + p∞).
    #[inline]
    fn isothermal_compressibility(&self, p: f64, t: f64) -> Result<f64, EosError> {
        self.density(p, t)?;
        Ok(1.0 / (p + self.p_inf))
    }

    /// α = 1/T.
    #[inline]
    fn thermal_expansivity(&self, p: f64, t: f64) -> Result<f64, EosError> {
        self.density(p, t)?;
        Ok(1.0 / t)
    }

    /// (ρ, 1/(p + p∞), 1/T) with the state checked once.
    fn density_and_derivatives(&self, p: f64, t: f64) -> Result<(f64, f64, f64), EosError> {
        Ok((self.density(p, t)?, 1.0 / (p + self.p_inf), 1.0 / t))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn water_state_by_hand() {
        let w = StiffenedGas::water();
        // e(1000, 1e9) = (1e9 + 4.4·6e8)/(3.4·1000) = 3.64e9/3.4e3.
        let e = w.specific_internal_energy(1000.0, 1.0e9).unwrap();
        assert!((e - 3.64e9 / 3.4e3).abs() < 1e-9 * e);
        // c² = 4.4·1.6e9/1000 = 7.04e6.
        assert!((w.sound_speed_squared(1000.0, e) - 7.04e6).abs() < 1e-6);
        // T = 1.6e9/(3.4·1000·1600) = 294.1176... K, and ρ(p, T) returns 1000.
        let t = w.temperature(1000.0, e);
        assert!((t - 1.6e9 / (3.4e3 * 1600.0)).abs() < 1e-9);
        assert!((w.density(1.0e9, t).unwrap() - 1000.0).abs() < 1e-9);
        assert_eq!(w.isothermal_compressibility(1.0e9, t).unwrap(), 1.0 / 1.6e9);
    }

    #[test]
    fn zero_p_inf_is_the_ideal_gas() {
        let a = StiffenedGas::air();
        let g = crate::IdealGas::air();
        for (rho, e) in [(1.2, 2.0e5), (50.0, 5.0e3), (0.1, 1.0e7)] {
            assert_eq!(a.pressure(rho, e), g.pressure(rho, e));
            assert_eq!(a.temperature(rho, e), g.temperature(rho, e));
        }
    }

    #[test]
    fn bad_input_is_an_error_naming_the_field() {
        let w = StiffenedGas::water();
        assert!(w.density(-7.0e8, 300.0).is_err());
        assert!(w.specific_internal_energy(0.0, 1e5).is_err());
        let bad = StiffenedGas { gamma: 1.0, ..w };
        assert!(bad.validate().unwrap_err().contains("`gamma`"));
        let bad = StiffenedGas { p_inf: -1.0, ..w };
        assert!(bad.validate().unwrap_err().contains("`p_inf`"));
        assert!(w.validate().is_ok());
    }

    brisance_core::eos_contract_tests!(stiffened_water, StiffenedGas::water(), rho: 800.0..1300.0, t: 150.0..2000.0);
    brisance_core::eos_contract_tests!(stiffened_air, StiffenedGas::air(), rho: 1e-2..1e2, t: 5.0..3000.0);
}
