//! Ideal (γ-law) gas, seed 001 eq 55: p = (γ − 1) ρ e, with a constant
//! specific heat c_v so that T = e / c_v.

use brisance_core::{Eos, EosError};
use serde::{Deserialize, Serialize};

/// Ideal gas p = (γ − 1) ρ e (seed 001 eq 55), e = c_v T.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct IdealGas {
    /// Ratio of specific heats γ (> 1).
    pub gamma: f64,
    /// Specific heat at constant volume c_v, J/(kg·K).
    pub cv: f64,
    /// Reference density, kg/m³ (used only as a scale).
    #[serde(default = "air_density")]
    pub rho0: f64,
}

fn air_density() -> f64 {
    1.225
}

impl IdealGas {
    /// Checks the parameters; the message names the bad field.
    pub fn validate(&self) -> Result<(), String> {
        if !(self.gamma > 1.0 && self.gamma.is_finite()) {
            return Err(format!(
                "ideal_gas: field `gamma` = {}, expected a finite value > 1",
                self.gamma
            ));
        }
        if !(self.cv > 0.0 && self.cv.is_finite()) {
            return Err(format!(
                "ideal_gas: field `cv` = {}, expected a finite value > 0 J/(kg·K)",
                self.cv
            ));
        }
        if !(self.rho0 > 0.0 && self.rho0.is_finite()) {
            return Err(format!(
                "ideal_gas: field `rho0` = {}, expected a finite value > 0 kg/m³",
                self.rho0
            ));
        }
        Ok(())
    }

    /// Air as in seed 001 §4.2: γ = 1.4, ρ₀ = 1.225 kg/m³, and
    /// c_v = R/(γ − 1) with R = 287.05 J/(kg·K), so e₀ = 2.0685e5 J/kg is
    /// 288.3 K and p₀ = 1.0136e5 Pa.
    pub fn air() -> Self {
        Self {
            gamma: 1.4,
            cv: 287.05 / 0.4,
            rho0: 1.225,
        }
    }

    /// A γ-law gas with the given γ and c_v.
    pub fn new(gamma: f64, cv: f64, rho0: f64) -> Self {
        Self { gamma, cv, rho0 }
    }
}

impl Eos for IdealGas {
    fn name(&self) -> &'static str {
        "ideal_gas"
    }

    fn reference_density(&self) -> f64 {
        self.rho0
    }

    /// Seed 001 eq 55.
    #[inline]
    fn pressure(&self, rho: f64, e: f64) -> f64 {
        (self.gamma - 1.0) * rho * e
    }

    #[inline]
    fn dp_drho(&self, _rho: f64, e: f64) -> f64 {
        (self.gamma - 1.0) * e
    }

    #[inline]
    fn dp_de(&self, rho: f64, _e: f64) -> f64 {
        (self.gamma - 1.0) * rho
    }

    /// Γ = γ − 1.
    #[inline]
    fn gruneisen(&self, _rho: f64, _e: f64) -> f64 {
        self.gamma - 1.0
    }

    /// c² = γ (γ − 1) e = γ p / ρ.
    #[inline]
    fn sound_speed_squared(&self, _rho: f64, e: f64) -> f64 {
        self.gamma * (self.gamma - 1.0) * e
    }

    fn specific_internal_energy(&self, rho: f64, p: f64) -> Result<f64, EosError> {
        if !(rho.is_finite() && rho > 0.0) {
            return Err(EosError::OutOfRange {
                eos: "ideal_gas",
                detail: format!("density {rho} must be finite and > 0"),
            });
        }
        if !p.is_finite() {
            return Err(EosError::OutOfRange {
                eos: "ideal_gas",
                detail: format!("pressure {p} must be finite"),
            });
        }
        Ok(p / ((self.gamma - 1.0) * rho))
    }

    fn temperature(&self, _rho: f64, e: f64) -> f64 {
        e / self.cv
    }

    fn specific_internal_energy_from_temperature(&self, _rho: f64, t: f64) -> f64 {
        self.cv * t
    }

    fn cv(&self, _rho: f64, _t: f64) -> f64 {
        self.cv
    }

    /// ρ = p / ((γ − 1) c_v T).
    fn density(&self, p: f64, t: f64) -> Result<f64, EosError> {
        if !(p > 0.0 && t > 0.0 && p.is_finite() && t.is_finite()) {
            return Err(EosError::OutOfRange {
                eos: "ideal_gas",
                detail: format!("ρ(p, T) needs p > 0 and T > 0, got p = {p}, T = {t}"),
            });
        }
        Ok(p / ((self.gamma - 1.0) * self.cv * t))
    }

    /// κ = 1/p.
    fn isothermal_compressibility(&self, p: f64, t: f64) -> Result<f64, EosError> {
        self.density(p, t)?;
        Ok(1.0 / p)
    }

    /// α = 1/T.
    fn thermal_expansivity(&self, p: f64, t: f64) -> Result<f64, EosError> {
        self.density(p, t)?;
        Ok(1.0 / t)
    }

    /// (ρ, 1/p, 1/T) with the state checked once.
    fn density_and_derivatives(&self, p: f64, t: f64) -> Result<(f64, f64, f64), EosError> {
        Ok((self.density(p, t)?, 1.0 / p, 1.0 / t))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn air_at_the_seed_state_is_one_atmosphere() {
        let air = IdealGas::air();
        let p = air.pressure(1.225, 2.0685e5);
        assert!((p - 101_356.5).abs() < 1e-6, "p = {p}");
        let t = air.temperature(1.225, 2.0685e5);
        assert!((t - 288.242_466_4).abs() < 1e-6, "T = {t}");
        // c = sqrt(γ p / ρ) = 340.30 m/s
        assert!((air.sound_speed(1.225, 2.0685e5) - 340.346_999).abs() < 1e-3);
    }

    #[test]
    fn sod_left_state_has_the_textbook_sound_speed() {
        let gas = IdealGas::new(1.4, 1.0, 1.0);
        let e = gas.specific_internal_energy(1.0, 1.0).unwrap();
        assert!((e - 2.5).abs() < 1e-15);
        assert!((gas.sound_speed(1.0, e) - 1.4f64.sqrt()).abs() < 1e-15);
    }

    #[test]
    fn non_positive_inputs_are_errors() {
        let gas = IdealGas::air();
        assert!(gas.density(-1.0, 300.0).is_err());
        assert!(gas.specific_internal_energy(0.0, 1.0).is_err());
    }

    brisance_core::eos_contract_tests!(ideal_gas_air, IdealGas::air(), rho: 1e-3..1e3, e: 1e3..1e8);
    brisance_core::eos_contract_tests!(ideal_gas_monatomic, IdealGas::new(5.0 / 3.0, 312.0, 0.16), rho: 1e-3..1e3, e: 1e2..1e7);
}
