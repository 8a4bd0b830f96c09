//! Noble–Abel co-volume gas: the ideal gas with the volume its molecules
//! occupy taken out, p (v − b) = R T, the equation of state of propellant
//! gases in interior ballistics (Corner, *Theory of the Interior Ballistics
//! of Guns*, Wiley 1950, ch. 2; Johnston, "The Noble–Abel Stiffened-Gas
//! equation of state", Phys. Fluids 17, 096101, 2005, whose NASG form this
//! is with p∞ = 0 and q = 0).
//!
//! With e = c_v T and R = (γ − 1) c_v, v = 1/ρ:
//!
//! - p = (γ − 1) ρ e / (1 − b ρ)
//! - ∂p/∂ρ|ₑ = (γ − 1) e / (1 − b ρ)²,  ∂p/∂e|ρ = (γ − 1) ρ / (1 − b ρ)
//! - Γ = (1/ρ) ∂p/∂e|ρ = (γ − 1)/(1 − b ρ)
//! - c² = ∂p/∂ρ|ₑ + (p/ρ²) ∂p/∂e|ρ = γ p / (ρ (1 − b ρ))
//! - e(ρ, p) = p (1 − b ρ) / ((γ − 1) ρ),  T = e / c_v
//! - ρ(p, T) = p / ((γ − 1) c_v T + b p)   (from p (1 − bρ) = (γ − 1) ρ c_v T)
//! - κ = (1/ρ) ∂ρ/∂p|_T = (1 − b ρ)/p,  α = −(1/ρ) ∂ρ/∂T|_p = (1 − b ρ)/T
//!
//! The model holds for 0 < ρ < 1/b: at ρ = 1/b the gas is packed solid.
//! `check_state`, `specific_internal_energy` and `density` refuse states
//! outside it with [`EosError::OutOfRange`]; `pressure` and the other
//! per-evaluation methods do not check (as for every model, solvers check a
//! state where it enters). Units SI: b m³/kg, c_v J/(kg·K).

use brisance_core::{Eos, EosError};
use brisance_eos::PluginModel;
use serde::{Deserialize, Serialize};

/// Noble–Abel gas p = (γ − 1) ρ e / (1 − b ρ), e = c_v T.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct NobleAbel {
    /// Ratio of specific heats γ (> 1).
    pub gamma: f64,
    /// Co-volume b, m³/kg (≥ 0; 0 is the ideal gas).
    pub covolume: f64,
    /// Specific heat at constant volume c_v, J/(kg·K).
    pub cv: f64,
    /// Reference density, kg/m³ (a scale only; below 1/b).
    pub rho0: f64,
}

impl NobleAbel {
    /// A representative propellant gas: γ = 1.25, b = 1.0 × 10⁻³ m³/kg
    /// (1 cm³/g, the order of the co-volumes Corner 1950 tabulates for
    /// nitrocellulose propellants), c_v = 1320 J/(kg·K) so that
    /// R = (γ − 1) c_v = 330 J/(kg·K) and the propellant force R T is
    /// 0.99 MJ/kg at 3000 K; reference density 100 kg/m³.
    pub fn propellant_gas() -> Self {
        Self {
            gamma: 1.25,
            covolume: 1.0e-3,
            cv: 1320.0,
            rho0: 100.0,
        }
    }

    /// Checks the parameters; the message names the bad field.
    pub fn validate(&self) -> Result<(), String> {
        let checks = [
            ("gamma", self.gamma, self.gamma > 1.0, "> 1"),
            ("covolume", self.covolume, self.covolume >= 0.0, "≥ 0 m³/kg"),
            ("cv", self.cv, self.cv > 0.0, "> 0 J/(kg·K)"),
            (
                "rho0",
                self.rho0,
                self.rho0 > 0.0 && self.covolume * self.rho0 < 1.0,
                "> 0 kg/m³ and below 1/covolume",
            ),
        ];
        for (field, v, ok, want) in checks {
            if !(ok && v.is_finite()) {
                return Err(format!(
                    "noble_abel: field `{field}` = {v}, expected a finite value {want}"
                ));
            }
        }
        Ok(())
    }

    /// 1 − b ρ, the fraction of the volume the molecules leave free.
    #[inline]
    fn free_volume(&self, rho: f64) -> f64 {
        1.0 - self.covolume * rho
    }

    /// Whether ρ lies in (0, 1/b).
    fn density_in_range(&self, rho: f64) -> bool {
        rho.is_finite() && rho > 0.0 && self.free_volume(rho) > 0.0
    }

    fn out_of_range(detail: String) -> EosError {
        EosError::OutOfRange {
            eos: "noble_abel",
            detail,
        }
    }
}

impl Eos for NobleAbel {
    fn name(&self) -> &'static str {
        "noble_abel"
    }

    fn reference_density(&self) -> f64 {
        self.rho0
    }

    /// p = (γ − 1) ρ e / (1 − b ρ).
    #[inline]
    fn pressure(&self, rho: f64, e: f64) -> f64 {
        (self.gamma - 1.0) * rho * e / self.free_volume(rho)
    }

    /// ∂p/∂ρ|ₑ = (γ − 1) e / (1 − b ρ)².
    #[inline]
    fn dp_drho(&self, rho: f64, e: f64) -> f64 {
        let f = self.free_volume(rho);
        (self.gamma - 1.0) * e / (f * f)
    }

    /// ∂p/∂e|ρ = (γ − 1) ρ / (1 − b ρ).
    #[inline]
    fn dp_de(&self, rho: f64, _e: f64) -> f64 {
        (self.gamma - 1.0) * rho / self.free_volume(rho)
    }

    /// Γ = (γ − 1)/(1 − b ρ).
    #[inline]
    fn gruneisen(&self, rho: f64, _e: f64) -> f64 {
        (self.gamma - 1.0) / self.free_volume(rho)
    }

    /// Refuses ρ ≤ 0, ρ ≥ 1/b and a non-finite ρ or e.
    fn check_state(&self, rho: f64, e: f64) -> Result<(), EosError> {
        if !self.density_in_range(rho) {
            return Err(Self::out_of_range(format!(
                "density ρ = {rho} kg/m³ must be finite, > 0 and below 1/b = {} kg/m³",
                1.0 / self.covolume
            )));
        }
        if !e.is_finite() {
            return Err(Self::out_of_range(format!(
                "specific internal energy e = {e} J/kg must be finite"
            )));
        }
        Ok(())
    }

    /// c² = γ p / (ρ (1 − b ρ)).
    #[inline]
    fn sound_speed_squared(&self, rho: f64, e: f64) -> f64 {
        self.gamma * self.pressure(rho, e) / (rho * self.free_volume(rho))
    }

    /// e = p (1 − b ρ) / ((γ − 1) ρ).
    fn specific_internal_energy(&self, rho: f64, p: f64) -> Result<f64, EosError> {
        if !(self.density_in_range(rho) && p.is_finite()) {
            return Err(Self::out_of_range(format!(
                "e(ρ, p) needs 0 < ρ < 1/b = {} kg/m³ and a finite p, got ρ = {rho}, p = {p}",
                1.0 / self.covolume
            )));
        }
        Ok(p * self.free_volume(rho) / ((self.gamma - 1.0) * rho))
    }

    /// T = e / c_v.
    #[inline]
    fn temperature(&self, _rho: f64, e: f64) -> f64 {
        e / self.cv
    }

    /// e = c_v T.
    #[inline]
    fn specific_internal_energy_from_temperature(&self, _rho: f64, t: f64) -> f64 {
        self.cv * t
    }

    fn cv(&self, _rho: f64, _t: f64) -> f64 {
        self.cv
    }

    /// ρ = p / ((γ − 1) c_v T + b p), below 1/b for every p, T > 0.
    fn density(&self, p: f64, t: f64) -> Result<f64, EosError> {
        if !(p > 0.0 && t > 0.0 && p.is_finite() && t.is_finite()) {
            return Err(Self::out_of_range(format!(
                "ρ(p, T) needs p > 0 and T > 0, got p = {p}, T = {t}"
            )));
        }
        Ok(p / ((self.gamma - 1.0) * self.cv * t + self.covolume * p))
    }

    /// κ = (1 − b ρ)/p.
    fn isothermal_compressibility(&self, p: f64, t: f64) -> Result<f64, EosError> {
        let rho = self.density(p, t)?;
        Ok(self.free_volume(rho) / p)
    }

    /// α = (1 − b ρ)/T.
    fn thermal_expansivity(&self, p: f64, t: f64) -> Result<f64, EosError> {
        let rho = self.density(p, t)?;
        Ok(self.free_volume(rho) / t)
    }

    /// (ρ, (1 − bρ)/p, (1 − bρ)/T) with ρ formed once.
    fn density_and_derivatives(&self, p: f64, t: f64) -> Result<(f64, f64, f64), EosError> {
        let rho = self.density(p, t)?;
        let f = self.free_volume(rho);
        Ok((rho, f / p, f / t))
    }
}

impl PluginModel for NobleAbel {
    fn validate(&self) -> Result<(), String> {
        NobleAbel::validate(self)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use brisance_eos::IdealGas;

    /// Relative difference, for values computed with a few roundings.
    fn rel(a: f64, b: f64) -> f64 {
        ((a - b) / b).abs()
    }

    #[test]
    fn propellant_gas_state_by_hand() {
        // γ = 1.25, b = 1e-3, c_v = 1320; ρ = 200 so 1 − bρ = 0.8;
        // e = 4e6 J/kg.
        let g = NobleAbel::propellant_gas();
        let (rho, e) = (200.0, 4.0e6);
        // p = 0.25 · 200 · 4e6 / 0.8 = 2.5e8 Pa.
        let p = g.pressure(rho, e);
        assert!(rel(p, 2.5e8) < 1e-15, "p = {p}");
        // ∂p/∂ρ = 0.25 · 4e6 / 0.64 = 1.5625e6; ∂p/∂e = 0.25 · 200 / 0.8 = 62.5.
        assert!(rel(g.dp_drho(rho, e), 1.5625e6) < 1e-15);
        assert!(rel(g.dp_de(rho, e), 62.5) < 1e-15);
        // Γ = 0.25 / 0.8 = 0.3125.
        assert!(rel(g.gruneisen(rho, e), 0.3125) < 1e-15);
        // c² = 1.25 · 2.5e8 / (200 · 0.8) = 1.953125e6 m²/s².
        assert!(rel(g.sound_speed_squared(rho, e), 1.953125e6) < 1e-15);
        // T = 4e6 / 1320 = 3030.30... K.
        let t = g.temperature(rho, e);
        assert!(rel(t, 4.0e6 / 1320.0) < 1e-15);
        // ρ(p, T) = 2.5e8 / (0.25 · 1320 · T + 1e-3 · 2.5e8)
        //         = 2.5e8 / (1e6 + 2.5e5) = 200.
        assert!(rel(g.density(2.5e8, t).unwrap(), 200.0) < 1e-14);
        // κ = 0.8 / 2.5e8 = 3.2e-9 1/Pa; α = 0.8 / T.
        let (_, kappa, alpha) = g.density_and_derivatives(2.5e8, t).unwrap();
        assert!(rel(kappa, 3.2e-9) < 1e-14);
        assert!(rel(alpha, 0.8 / t) < 1e-14);
        // e(ρ, p) = 2.5e8 · 0.8 / (0.25 · 200) = 4e6.
        assert!(rel(g.specific_internal_energy(rho, 2.5e8).unwrap(), 4.0e6) < 1e-15);
    }

    #[test]
    fn zero_covolume_is_the_ideal_gas_to_the_bit() {
        let na = NobleAbel {
            covolume: 0.0,
            ..NobleAbel::propellant_gas()
        };
        let ideal = IdealGas::new(1.25, 1320.0, 100.0);
        for (rho, e) in [(1.2, 2.0e5), (50.0, 5.0e3), (300.0, 1.0e7)] {
            assert_eq!(na.pressure(rho, e), ideal.pressure(rho, e));
            assert_eq!(na.temperature(rho, e), ideal.temperature(rho, e));
        }
        assert_eq!(na.density(1e6, 3000.0), ideal.density(1e6, 3000.0));
    }

    #[test]
    fn the_packed_density_and_beyond_are_refused() {
        let g = NobleAbel::propellant_gas();
        for rho in [1000.0, 1500.0, 0.0, -1.0, f64::NAN] {
            assert!(g.check_state(rho, 1e6).is_err(), "ρ = {rho}");
            assert!(g.specific_internal_energy(rho, 1e6).is_err(), "ρ = {rho}");
        }
        assert!(g.check_state(999.0, 1e6).is_ok());
        assert!(g.check_state(500.0, f64::INFINITY).is_err());
        assert!(g.density(-1.0, 300.0).is_err());
        assert!(g.density(1e5, 0.0).is_err());
    }

    #[test]
    fn bad_parameters_name_the_field() {
        let g = NobleAbel::propellant_gas();
        assert!(g.validate().is_ok());
        for (bad, field) in [
            (NobleAbel { gamma: 1.0, ..g }, "`gamma`"),
            (
                NobleAbel {
                    covolume: -1e-3,
                    ..g
                },
                "`covolume`",
            ),
            (NobleAbel { cv: 0.0, ..g }, "`cv`"),
            (NobleAbel { rho0: 1000.0, ..g }, "`rho0`"),
        ] {
            assert!(bad.validate().unwrap_err().contains(field), "{field}");
        }
    }

    brisance_core::eos_contract_tests!(noble_abel_propellant, NobleAbel::propellant_gas(), rho: 1.0..700.0, t: 300.0..4000.0);
}
