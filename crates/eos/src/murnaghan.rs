//! Murnaghan equation of state for unreacted explosive, seed 000 §4.1.1
//! eq 33 (the JWL++ reactant, Souers et al. 2000):
//!
//! ```text
//! p = (1/(nκ)) (1/vⁿ − 1) = (1/(nκ)) ((ρ/ρ₀)ⁿ − 1),   v = ρ₀/ρ,
//! ```
//!
//! with κ the compressibility at zero pressure (1/Pa) and n = dK/dp the
//! pressure derivative of the bulk modulus K = (1 + nκp)/κ. The zero-pressure
//! sound speed is c₀ = 1/√(ρ₀κ).
//!
//! # Thermal part
//!
//! Eq 33 has no energy or temperature dependence (∂p/∂e|ρ = 0, Γ = 0), and
//! the ICE equilibration also needs T, ρ(p, T) and the thermal
//! expansivity. Thermodynamic consistency for p = p(ρ) alone
//! (∂e/∂v|_T = T ∂p/∂T|_v − p = −p) fixes the energy as the elastic
//! compression energy plus a thermal part; with a constant c_v,
//!
//! ```text
//! e(ρ, T) = e_c(ρ) + c_v (T − T_ref),
//! e_c(ρ) = −∫_{v₀}^{v} p dv = (1/(nκ)) [ ((ρ/ρ₀)^{n−1} − 1)/((n − 1)ρ₀) + 1/ρ − 1/ρ₀ ],
//! ```
//!
//! so the unreacted reference state (ρ₀, e = 0) is at T_ref. Consequences:
//! the thermal expansivity is 0, the isothermal and isentropic
//! compressibilities coincide, κ_T = κ/(1 + nκp), and ρ(p, T) = ρ₀(1 + nκp)^{1/n}
//! for p > −1/(nκ). Because p depends on ρ alone, e(ρ, p) exists only when
//! p equals the Murnaghan pressure at ρ; it then returns the energy at T_ref,
//! and otherwise an error.
//!
//! Valid range: any ρ > 0 evaluates (tension p → −1/(nκ) as ρ → 0); the
//! range where the fit means something, and where the contract tests run,
//! is 0.5 ≤ ρ/ρ₀ ≤ 3.
//!
//! Units: κ 1/Pa, n dimensionless, ρ₀ kg/m³, c_v J/(kg·K), T_ref K.

use crate::jwl::positive;
use brisance_core::{Eos, EosError};
use serde::{Deserialize, Serialize};

/// Murnaghan parameters (seed 000 eq 33) with the thermal part above.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Murnaghan {
    /// n, pressure derivative of the bulk modulus (dimensionless, > 1).
    pub n: f64,
    /// κ, compressibility at zero pressure, 1/Pa.
    pub kappa: f64,
    /// ρ₀, density at zero pressure, kg/m³.
    pub rho0: f64,
    /// Specific heat at constant volume, J/(kg·K).
    pub cv: f64,
    /// Temperature of the reference state (ρ₀, e = 0), K.
    pub t_ref: f64,
}

impl Murnaghan {
    /// ANFO-K1 reactant, seed 000 §5.1: n = 7.4, ρ₀ = 1160 kg/m³, and
    /// κ = 3.9 × 10⁻¹⁰ 1/Pa. The seed prints κ = 3.9 × 10¹¹ Pa⁻¹, which
    /// would give c₀ = 1/√(ρ₀κ) = 4.7 × 10⁻⁸ m/s; 3.9 × 10⁻¹⁰ gives
    /// c₀ = 1487 m/s, a sound speed of porous ammonium-nitrate explosive
    /// (see docs/physics/eos/murnaghan.md). c_v = 1700 J/(kg·K), close to
    /// the specific heat of ammonium nitrate (≈ 1.74 kJ/(kg·K)); T_ref =
    /// 298.15 K.
    pub fn anfo_k1() -> Self {
        Self {
            n: 7.4,
            kappa: 3.9e-10,
            rho0: 1160.0,
            cv: 1700.0,
            t_ref: 298.15,
        }
    }

    /// QM-100 (ammonium-nitrate emulsion) reactant, seed 000 §5.2:
    /// n = 7.0, ρ₀ = 1260 kg/m³, κ = 1.02 × 10⁻⁹ 1/Pa (printed as
    /// "1.02 × ^-9", the power of ten lost), c₀ = 882 m/s. c_v = 2000
    /// J/(kg·K), the mass-weighted heat capacity of an emulsion of ammonium
    /// nitrate, water and oil; T_ref = 298.15 K.
    pub fn qm100() -> Self {
        Self {
            n: 7.0,
            kappa: 1.02e-9,
            rho0: 1260.0,
            cv: 2000.0,
            t_ref: 298.15,
        }
    }

    /// Zero-pressure sound speed c₀ = 1/√(ρ₀κ), m/s.
    pub fn reference_sound_speed(&self) -> f64 {
        1.0 / (self.rho0 * self.kappa).sqrt()
    }

    /// Checks every parameter, naming the bad field and the expected range.
    pub fn validate(&self) -> Result<(), String> {
        if !(self.n.is_finite() && self.n > 1.0) {
            return Err(format!(
                "murnaghan.n = {}: expected a finite value > 1",
                self.n
            ));
        }
        positive("murnaghan", "kappa", self.kappa, "1/Pa")?;
        positive("murnaghan", "rho0", self.rho0, "kg/m³")?;
        positive("murnaghan", "cv", self.cv, "J/(kg·K)")?;
        positive("murnaghan", "t_ref", self.t_ref, "K")?;
        Ok(())
    }

    /// Elastic compression energy e_c(ρ) = −∫_{v₀}^{v} p dv, J/kg.
    #[inline]
    pub fn compression_energy(&self, rho: f64) -> f64 {
        self.compression_energy_from((rho / self.rho0).powf(self.n - 1.0), rho)
    }

    /// e_c(ρ) from η^{n−1} = (ρ/ρ₀)^{n−1}, for callers that have the power.
    #[inline]
    fn compression_energy_from(&self, eta_n1: f64, rho: f64) -> f64 {
        let n = self.n;
        ((eta_n1 - 1.0) / ((n - 1.0) * self.rho0) + 1.0 / rho - 1.0 / self.rho0) / (n * self.kappa)
    }

    fn out_of_range(detail: String) -> EosError {
        EosError::OutOfRange {
            eos: "murnaghan",
            detail,
        }
    }
}

impl Eos for Murnaghan {
    fn name(&self) -> &'static str {
        "murnaghan"
    }

    fn reference_density(&self) -> f64 {
        self.rho0
    }

    /// Seed 000 eq 33.
    #[inline]
    fn pressure(&self, rho: f64, _e: f64) -> f64 {
        ((rho / self.rho0).powf(self.n) - 1.0) / (self.n * self.kappa)
    }

    /// dp/dρ = (ρ/ρ₀)^{n−1}/(κρ₀).
    #[inline]
    fn dp_drho(&self, rho: f64, _e: f64) -> f64 {
        (rho / self.rho0).powf(self.n - 1.0) / (self.kappa * self.rho0)
    }

    #[inline]
    fn dp_de(&self, _rho: f64, _e: f64) -> f64 {
        0.0
    }

    /// Γ = 0: eq 33 has no thermal pressure.
    #[inline]
    fn gruneisen(&self, _rho: f64, _e: f64) -> f64 {
        0.0
    }

    /// The energy at T_ref, e_c(ρ), when `p` is the Murnaghan pressure at ρ
    /// (to 10⁻⁹ relative); any other `p` has no energy and is an error.
    fn specific_internal_energy(&self, rho: f64, p: f64) -> Result<f64, EosError> {
        self.check_state(rho, 0.0)?;
        if !p.is_finite() {
            return Err(Self::out_of_range(format!(
                "pressure p = {p} Pa must be finite"
            )));
        }
        // One power serves the check and the energy: the pressure from
        // η^{n−1}·η is within an ulp or two of `pressure`'s η^n, far inside
        // the 10⁻⁹ tolerance.
        let eta = rho / self.rho0;
        let eta_n1 = eta.powf(self.n - 1.0);
        let pm = (eta_n1 * eta - 1.0) / (self.n * self.kappa);
        let tol = 1e-9 * (p.abs().max(pm.abs()) + 1.0 / (self.n * self.kappa));
        if (p - pm).abs() > tol {
            return Err(Self::out_of_range(format!(
                "pressure depends on density only: at ρ = {rho} kg/m³ it is {pm} Pa, not {p} Pa"
            )));
        }
        Ok(self.compression_energy_from(eta_n1, rho))
    }

    /// c² = ∂p/∂ρ, since ∂p/∂e = 0 (the default's second term vanishes; this
    /// spares its power for p).
    #[inline]
    fn sound_speed_squared(&self, rho: f64, e: f64) -> f64 {
        self.dp_drho(rho, e)
    }

    /// T = T_ref + (e − e_c(ρ))/c_v.
    fn temperature(&self, rho: f64, e: f64) -> f64 {
        self.t_ref + (e - self.compression_energy(rho)) / self.cv
    }

    fn specific_internal_energy_from_temperature(&self, rho: f64, t: f64) -> f64 {
        self.compression_energy(rho) + self.cv * (t - self.t_ref)
    }

    fn cv(&self, _rho: f64, _t: f64) -> f64 {
        self.cv
    }

    /// ρ = ρ₀(1 + nκp)^{1/n}, independent of T.
    fn density(&self, p: f64, t: f64) -> Result<f64, EosError> {
        Ok(self.rho0 * self.tension_base(p, t)?.powf(1.0 / self.n))
    }

    /// κ_T = κ/(1 + nκp).
    fn isothermal_compressibility(&self, p: f64, t: f64) -> Result<f64, EosError> {
        Ok(self.kappa / self.tension_base(p, t)?)
    }

    /// α = 0 (p does not depend on T).
    fn thermal_expansivity(&self, p: f64, t: f64) -> Result<f64, EosError> {
        self.tension_base(p, t)?;
        Ok(0.0)
    }

    /// (ρ, κ_T, 0) from one tension base 1 + nκp.
    fn density_and_derivatives(&self, p: f64, t: f64) -> Result<(f64, f64, f64), EosError> {
        let base = self.tension_base(p, t)?;
        Ok((self.rho0 * base.powf(1.0 / self.n), self.kappa / base, 0.0))
    }
}

impl Murnaghan {
    /// 1 + nκp, after checking that (p, T) is a state ρ(p, T) exists for
    /// (finite p above the tension limit −1/(nκ), finite T > 0); shared by
    /// ρ(p, T) and κ_T so that κ_T needs no power.
    fn tension_base(&self, p: f64, t: f64) -> Result<f64, EosError> {
        if !(p.is_finite() && t.is_finite() && t > 0.0) {
            return Err(Self::out_of_range(format!(
                "ρ(p, T) needs finite p and T > 0, got p = {p} Pa, T = {t} K"
            )));
        }
        let base = 1.0 + self.n * self.kappa * p;
        if !(base > 0.0) {
            return Err(Self::out_of_range(format!(
                "p = {p} Pa is below the tension limit −1/(nκ) = {} Pa",
                -1.0 / (self.n * self.kappa)
            )));
        }
        Ok(base)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reference_sound_speeds_follow_from_kappa() {
        // c₀ = 1/√(1160 · 3.9e-10) = 1486.75 m/s; 1/√(1260 · 1.02e-9) = 882.09 m/s.
        assert!((Murnaghan::anfo_k1().reference_sound_speed() - 1486.75).abs() < 0.01);
        assert!((Murnaghan::qm100().reference_sound_speed() - 882.09).abs() < 0.01);
        let m = Murnaghan::anfo_k1();
        let c = m.sound_speed(m.rho0, 0.0);
        assert!((c - 1486.75).abs() < 0.01, "c = {c}");
    }

    #[test]
    fn ten_percent_compression_gives_the_hand_pressure() {
        // ANFO-K1 at ρ = 1.1ρ₀: p = (1.1^7.4 − 1)/(7.4 · 3.9e-10)
        // = (2.024444 − 1)/2.886e-9 = 3.54970e8 Pa.
        let m = Murnaghan::anfo_k1();
        let p = m.pressure(1.1 * m.rho0, 0.0);
        let hand = (1.1f64.powf(7.4) - 1.0) / (7.4 * 3.9e-10);
        assert!((p - hand).abs() < 1e-6 * hand);
        assert!((p - 3.54970e8).abs() < 1e-5 * 3.54970e8, "p = {p}");
    }

    #[test]
    fn compression_energy_is_minus_the_integral_of_pressure() {
        let m = Murnaghan::qm100();
        // de_c/dρ = p/ρ² by a central difference, and e_c(ρ₀) = 0.
        assert_eq!(m.compression_energy(m.rho0), 0.0);
        for &rho in &[900.0, 1300.0, 2500.0] {
            let h = 1e-4 * rho;
            let d = (m.compression_energy(rho + h) - m.compression_energy(rho - h)) / (2.0 * h);
            let want = m.pressure(rho, 0.0) / (rho * rho);
            assert!(
                (d - want).abs() < 1e-6 * want.abs(),
                "ρ = {rho}: {d} vs {want}"
            );
        }
    }

    #[test]
    fn energy_of_a_pressure_off_the_curve_is_an_error() {
        let m = Murnaghan::anfo_k1();
        assert!(m.specific_internal_energy(m.rho0, 1.0e8).is_err());
        let e = m.specific_internal_energy(m.rho0, 0.0).unwrap();
        assert!((m.temperature(m.rho0, e) - 298.15).abs() < 1e-12);
    }

    #[test]
    fn density_below_the_tension_limit_is_an_error() {
        let m = Murnaghan::anfo_k1();
        let p = -1.0 / (7.4 * 3.9e-10) * 1.01;
        assert!(m.density(p, 300.0).is_err());
        assert!(m.isothermal_compressibility(p, 300.0).is_err());
        assert!(m.thermal_expansivity(p, 300.0).is_err());
        assert!(m.isothermal_compressibility(1.0e9, 0.0).is_err());
        assert!(m.isothermal_compressibility(f64::NAN, 300.0).is_err());
    }

    #[test]
    fn sound_speed_is_the_default_formula_with_one_power() {
        // c² = ∂p/∂ρ + (p/ρ²)·∂p/∂e with ∂p/∂e = 0; at ρ₀,
        // c₀² = 1/(ρ₀κ) = 1/(1160·3.9e-10) = 2.2104e6 m²/s².
        let m = Murnaghan::anfo_k1();
        assert!((m.sound_speed_squared(1160.0, 0.0) - 1.0 / (1160.0 * 3.9e-10)).abs() < 1e-6);
        for rho in [600.0, 1160.0, 1500.0, 3000.0] {
            let default =
                m.dp_drho(rho, 0.0) + m.pressure(rho, 0.0) / (rho * rho) * m.dp_de(rho, 0.0);
            assert_eq!(m.sound_speed_squared(rho, 0.0), default);
        }
    }

    #[test]
    fn energy_from_pressure_is_the_compression_energy() {
        let m = Murnaghan::anfo_k1();
        for rho in [600.0, 1160.0, 1500.0, 3000.0] {
            let e = m
                .specific_internal_energy(rho, m.pressure(rho, 0.0))
                .unwrap();
            assert_eq!(e, m.compression_energy(rho));
        }
    }

    #[test]
    fn compressibility_at_one_gigapascal_matches_hand_value() {
        // ANFO-K1 at 1 GPa: 1 + nκp = 1 + 7.4·3.9e-10·1e9 = 3.886,
        // κ_T = 3.9e-10/3.886 = 1.003602e-10 Pa⁻¹, ρ = 1160·3.886^{1/7.4}
        // = 1160·e^{ln(3.886)/7.4} = 1160·1.20133 = 1393.54 kg/m³; κ_T is
        // (1/ρ)dρ/dp of that density.
        let m = Murnaghan::anfo_k1();
        let kappa = m.isothermal_compressibility(1.0e9, 300.0).unwrap();
        assert!(
            (kappa - 1.003602e-10).abs() < 1e-6 * 1.003602e-10,
            "{kappa}"
        );
        let rho = m.density(1.0e9, 300.0).unwrap();
        assert!((rho - 1393.54).abs() < 0.01, "{rho}");
        let h = 1.0e3;
        let fd = (m.density(1.0e9 + h, 300.0).unwrap() - m.density(1.0e9 - h, 300.0).unwrap())
            / (2.0 * h * rho);
        assert!((fd / kappa - 1.0).abs() < 1e-6, "{fd} vs {kappa}");
        assert_eq!(m.thermal_expansivity(1.0e9, 300.0).unwrap(), 0.0);
    }

    #[test]
    fn validate_names_the_bad_field() {
        let mut m = Murnaghan::anfo_k1();
        assert!(m.validate().is_ok());
        m.n = 0.5;
        assert!(m.validate().unwrap_err().contains("murnaghan.n"));
    }

    brisance_core::eos_contract_tests!(murnaghan_anfo_k1, Murnaghan::anfo_k1(), rho: 580.0..3480.0, t: 100.0..2000.0);
    brisance_core::eos_contract_tests!(murnaghan_qm100, Murnaghan::qm100(), rho: 630.0..3780.0, t: 100.0..2000.0);
}
