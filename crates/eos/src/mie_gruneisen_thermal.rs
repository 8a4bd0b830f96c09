//! Mie–Grüneisen EOS of the mass–spring–damper lattice, seed 003 §2.2,
//! eqs 12–14: the linear Uₛ–uₚ Hugoniot about a reference pressure P₀, a
//! constant Grüneisen gamma 𝒢 and e = c_v T.
//!
//! P = (𝒢/λ)(e − e₀) + f(λ)                                          (12)
//! f(λ) = P_H [1 − (𝒢/2λ)(λ₀ − λ)] − (𝒢/2λ) P₀ (λ₀ − λ)               (13a)
//! P_H = P₀ + ρ₀c₀² φ / (1 − sφ)²,  φ = 1 − λ/λ₀                      (13b, c)
//! e = c_v T,  λ = 1/ρ,  e₀ = c_v T₀ (T₀ = 300 K, P₀ = 10⁵ Pa)           (13d, e)
//! dT/dP = λ/(𝒢 c_v)                                                  (14)
//!
//! With μ = ρ/ρ₀ − 1, (𝒢/2λ)(λ₀ − λ) = 𝒢μ/2, so eq 13a is
//! f = P_H(1 − 𝒢μ/2) − 𝒢μP₀/2 = P₀(1 − 𝒢μ) + ρ₀c₀²φ(1 − 𝒢μ/2)/(1 − sφ)²,
//! the textbook p = p_H + Γρ(e − e_H) with e_H = e₀ + ½(P_H + P₀)(λ₀ − λ)
//! and constant Γ = 𝒢. At (ρ₀, T₀) the pressure is P₀.
//!
//! Eq 14 is ∂T/∂P at constant volume: ∂P/∂e|λ = 𝒢/λ and e = c_v T give
//! ∂P/∂T|λ = 𝒢c_v/λ. The lattice uses it in its energy equation (eq 15);
//! [`MieGruneisenThermal::dtemperature_dpressure`] returns it.
//!
//! e is the absolute specific internal energy c_v T (J/kg), so
//! T = e/c_v exactly as in eq 13d.

use crate::mie_gruneisen::{
    check_density_pressure, check_pressure_temperature, check_window, linear_hugoniot,
    solve_density, MAX_RELATIVE_DENSITY, MIN_RELATIVE_DENSITY,
};
use brisance_core::{Eos, EosError};
use serde::{Deserialize, Serialize};

const NAME: &str = "mie_gruneisen_thermal";

/// Reference temperature of seed 003 §2.2, K.
pub const SEED003_T0: f64 = 300.0;

/// Reference pressure of seed 003 §2.2, Pa.
pub const SEED003_P0: f64 = 1.0e5;

/// Parameters of the lattice Mie–Grüneisen EOS (seed 003 eqs 12–14).
///
/// Valid for ρ/ρ₀ in [[`MIN_RELATIVE_DENSITY`], [`MAX_RELATIVE_DENSITY`]]
/// and T ≥ 0; [`MieGruneisenThermal::validate`] checks that the pressure
/// rises with density with c² ≥ 0 there.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MieGruneisenThermal {
    /// Grüneisen gamma 𝒢 (constant), dimensionless.
    pub gamma: f64,
    /// Reference density ρ₀ = 1/λ₀, kg/m³.
    pub rho0: f64,
    /// Sound speed at the reference conditions c₀, m/s.
    pub c0: f64,
    /// Slope s of Uₛ = c₀ + s uₚ, dimensionless (0 gives the linear-elastic
    /// reference curve P_H = P₀ + ρ₀c₀²φ).
    pub s: f64,
    /// Specific heat at constant volume c_v, J/(kg·K).
    pub cv: f64,
    /// Reference temperature T₀ (e₀ = c_v T₀), K.
    pub t0: f64,
    /// Reference pressure P₀, Pa.
    pub p0: f64,
}

impl MieGruneisenThermal {
    /// A seed 003 Table 2–3 material: the tables give 𝒢, ρ, c_v, Young's
    /// modulus E and the isothermal bulk modulus K_T, but no Hugoniot. We
    /// take c₀ = √(K_T/ρ₀), so that ρ₀c₀² = K_T is the stiffness the
    /// lattice's eq 11 integrates, and s = 0 (the reference curve is then
    /// P₀ + K_T φ, exact to first order in φ; for shocks stronger than the
    /// seed's 50–250 m/s impacts set s from Uₛ–uₚ data). Using K_T where a
    /// Hugoniot needs the isentropic K_S = K_T(1 + αΓT) under-states c₀ by a
    /// few per cent. T₀ = 300 K, P₀ = 10⁵ Pa (seed 003 §2.2). E is a lattice
    /// spring property and is not part of the EOS.
    pub fn from_seed003_table(gamma: f64, rho0: f64, cv: f64, bulk_modulus: f64) -> Self {
        Self {
            gamma,
            rho0,
            c0: (bulk_modulus / rho0).sqrt(),
            s: 0.0,
            cv,
            t0: SEED003_T0,
            p0: SEED003_P0,
        }
    }

    /// HMX crystal, seed 003 Table 2: 𝒢 = 0.7, ρ = 1580 kg/m³,
    /// c_v = 1757.28 J/(kg·K), K_T = 11.3 GPa (E = 25325 MPa). The table's
    /// density is well below β-HMX's 1900 kg/m³; it is shipped as printed
    /// because Table 3's density-matched binder (1580 kg/m³) and
    /// impedance-matched binder are defined from it.
    pub fn hmx_seed003() -> Self {
        Self::from_seed003_table(0.7, 1580.0, 1757.28, 11.3e9)
    }

    /// RDX crystal, seed 003 Table 2: 𝒢 = 0.93, ρ = 1799 kg/m³,
    /// c_v = 1456 J/(kg·K), K_T = 12.0 GPa (E = 20200 MPa).
    pub fn rdx_seed003() -> Self {
        Self::from_seed003_table(0.93, 1799.0, 1456.0, 12.0e9)
    }

    /// PETN crystal, seed 003 Table 2: 𝒢 = 1.15, ρ = 1770 kg/m³,
    /// c_v = 1009 J/(kg·K), K_T = 11.0 GPa (E = 11800 MPa).
    pub fn petn_seed003() -> Self {
        Self::from_seed003_table(1.15, 1770.0, 1009.0, 11.0e9)
    }

    /// TKX-50 crystal, seed 003 Table 2: 𝒢 = 0.6894, ρ = 1877 kg/m³,
    /// c_v = 1236.44 J/(kg·K), K_T = 32.719 GPa (E = 52194 MPa).
    pub fn tkx50_seed003() -> Self {
        Self::from_seed003_table(0.6894, 1877.0, 1236.44, 32.719e9)
    }

    /// Estane binder, seed 003 Table 3: 𝒢 = 1.0, ρ = 1280 kg/m³,
    /// c_v = 1481.14 J/(kg·K), K_T = 4.3 GPa (E = 6250 MPa).
    pub fn estane_seed003() -> Self {
        Self::from_seed003_table(1.0, 1280.0, 1481.14, 4.3e9)
    }

    /// Half-density Estane, seed 003 Table 3: ρ = 640 kg/m³, K_T = 2.15 GPa
    /// (both halved, so c₀ is Estane's), other values as Estane.
    pub fn estane_half_density() -> Self {
        Self::from_seed003_table(1.0, 640.0, 1481.14, 2.15e9)
    }

    /// Density-matched Estane, seed 003 Table 3: ρ = 1580 kg/m³ (Table 2's
    /// HMX), K_T = 5.31 GPa (4.3 GPa × 1580/1280, rounded), other values as
    /// Estane.
    pub fn estane_density_matched() -> Self {
        Self::from_seed003_table(1.0, 1580.0, 1481.14, 5.31e9)
    }

    /// Impedance-matched Estane, seed 003 Table 3: ρ = 6402.16 kg/m³,
    /// K_T = 21.51 GPa, other values as Estane. The density reproduces
    /// HMX's √(Eρ) with Estane's E (25325 × 1580 / 6250 = 6402.16) and
    /// K_T scales with ρ as in the other variants (4.3 × 6402.16/1280 =
    /// 21.507), which confirms both printed values.
    pub fn estane_impedance_matched() -> Self {
        Self::from_seed003_table(1.0, 6402.16, 1481.14, 21.51e9)
    }

    /// Checks the parameters: 𝒢, ρ₀, c₀, c_v, T₀ positive and finite, s ≥ 0
    /// with its pole beyond the window (s < 3), P₀ ≥ 0 finite, and on the
    /// window at T = 0 ∂P/∂ρ|ₑ > 0 and c² ≥ 0. The message names the field.
    pub fn validate(&self) -> Result<(), String> {
        for (field, value) in [
            ("gamma", self.gamma),
            ("rho0", self.rho0),
            ("c0", self.c0),
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
        if !(self.s >= 0.0 && self.s * chi_max < 1.0) {
            return Err(format!(
                "{NAME}: field `s` = {}, expected 0 ≤ s < {} so that the Hugoniot pole φ = 1/s lies beyond ρ/ρ₀ = {MAX_RELATIVE_DENSITY}",
                self.s,
                1.0 / chi_max
            ));
        }
        if !(self.p0 >= 0.0 && self.p0.is_finite()) {
            return Err(format!(
                "{NAME}: field `p0` = {}, expected a finite value ≥ 0",
                self.p0
            ));
        }
        for i in 0..=200 {
            let x = MIN_RELATIVE_DENSITY
                + (MAX_RELATIVE_DENSITY - MIN_RELATIVE_DENSITY) * f64::from(i) / 200.0;
            let rho = x * self.rho0;
            if !(self.dp_drho(rho, 0.0) > 0.0 && self.sound_speed_squared(rho, 0.0) >= 0.0) {
                return Err(format!(
                    "{NAME}: fields `gamma`, `c0`, `s` give a pressure that does not rise with density (or c² < 0) at ρ/ρ₀ = {x:.3}, T = 0; expected ∂P/∂ρ > 0 and c² ≥ 0 on ρ/ρ₀ ∈ [{MIN_RELATIVE_DENSITY}, {MAX_RELATIVE_DENSITY}]"
                ));
            }
        }
        Ok(())
    }

    /// Seed 003 eq 14: dT/dP = λ/(𝒢 c_v) = 1/(ρ 𝒢 c_v), K/Pa — the
    /// temperature change per unit pressure change at constant volume that
    /// the lattice's energy equation (eq 15) uses.
    #[inline]
    pub fn dtemperature_dpressure(&self, rho: f64) -> f64 {
        1.0 / (rho * self.gamma * self.cv)
    }

    /// f(λ) of eq 13a and its ρ-derivative.
    #[inline]
    fn reference(&self, rho: f64) -> (f64, f64) {
        let mu = rho / self.rho0 - 1.0;
        let phi = 1.0 - self.rho0 / rho;
        let (ph, dph_dphi) = linear_hugoniot(self.rho0, self.c0, self.s, phi);
        let factor = 1.0 - 0.5 * self.gamma * mu;
        let f = self.p0 * (1.0 - self.gamma * mu) + ph * factor;
        let df_drho = -self.gamma * self.p0 / self.rho0
            + dph_dphi * self.rho0 / (rho * rho) * factor
            - 0.5 * self.gamma * ph / self.rho0;
        (f, df_drho)
    }

    #[inline]
    fn e0(&self) -> f64 {
        self.cv * self.t0
    }
}

impl Eos for MieGruneisenThermal {
    fn name(&self) -> &'static str {
        NAME
    }

    fn reference_density(&self) -> f64 {
        self.rho0
    }

    /// Seed 003 eq 12 with eq 13: P = 𝒢ρ(e − e₀) + f(λ).
    #[inline]
    fn pressure(&self, rho: f64, e: f64) -> f64 {
        self.gamma * rho * (e - self.e0()) + self.reference(rho).0
    }

    #[inline]
    fn dp_drho(&self, rho: f64, e: f64) -> f64 {
        self.gamma * (e - self.e0()) + self.reference(rho).1
    }

    #[inline]
    fn dp_de(&self, rho: f64, _e: f64) -> f64 {
        self.gamma * rho
    }

    /// The model's Grüneisen parameter Γ = (1/ρ) ∂P/∂e|ρ = 𝒢 (eq 12).
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

    /// e = e₀ + (P − f(λ)) λ/𝒢.
    fn specific_internal_energy(&self, rho: f64, p: f64) -> Result<f64, EosError> {
        check_density_pressure(NAME, self.rho0, rho, p)?;
        Ok(self.e0() + (p - self.reference(rho).0) / (self.gamma * rho))
    }

    /// T = e/c_v (eq 13d).
    fn temperature(&self, _rho: f64, e: f64) -> f64 {
        e / self.cv
    }

    fn specific_internal_energy_from_temperature(&self, _rho: f64, t: f64) -> f64 {
        self.cv * t
    }

    fn cv(&self, _rho: f64, _t: f64) -> f64 {
        self.cv
    }

    /// Solves P(ρ, c_v T) = P on the valid window by bracketed Newton.
    fn density(&self, p: f64, t: f64) -> Result<f64, EosError> {
        self.density_counted(p, t).map(|(rho, _)| rho)
    }

    /// κ = 1/(ρ ∂P/∂ρ|_T), and ∂P/∂ρ|_T = ∂P/∂ρ|ₑ because e = c_v T.
    fn isothermal_compressibility(&self, p: f64, t: f64) -> Result<f64, EosError> {
        let rho = self.density(p, t)?;
        Ok(1.0 / (rho * self.dp_drho(rho, self.cv * t)))
    }

    /// α = (∂P/∂T|ρ)/(ρ ∂P/∂ρ|_T) = 𝒢 c_v / ∂P/∂ρ|ₑ.
    fn thermal_expansivity(&self, p: f64, t: f64) -> Result<f64, EosError> {
        let rho = self.density(p, t)?;
        Ok(self.gamma * self.cv / self.dp_drho(rho, self.cv * t))
    }

    /// One inversion for ρ, then κ and α at it by the formulas of
    /// [`Eos::isothermal_compressibility`] and [`Eos::thermal_expansivity`]
    /// (the same operations, so the same bits).
    fn density_and_derivatives(&self, p: f64, t: f64) -> Result<(f64, f64, f64), EosError> {
        let rho = self.density(p, t)?;
        let slope = self.dp_drho(rho, self.cv * t);
        Ok((rho, 1.0 / (rho * slope), self.gamma * self.cv / slope))
    }
}

impl MieGruneisenThermal {
    /// ρ(p, T) and the number of pressure evaluations the bracketed Newton
    /// solve took.
    pub(crate) fn density_counted(&self, p: f64, t: f64) -> Result<(f64, usize), EosError> {
        check_pressure_temperature(NAME, p, t)?;
        let e = self.cv * t;
        let k0 = self.rho0 * self.c0 * self.c0;
        let guess = self.rho0 * (1.0 + (p - self.pressure(self.rho0, e)) / k0);
        // `pressure` and `dp_drho` with their shared reference curve
        // evaluated once (the same operations, so the same bits).
        let de = e - self.e0();
        solve_density(
            NAME,
            |rho| {
                let (f, df) = self.reference(rho);
                (self.gamma * rho * de + f, self.gamma * de + df)
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

    /// Seed 003 eqs 12–13 exactly as printed, in λ = 1/ρ.
    fn eq12_as_printed(m: &MieGruneisenThermal, rho: f64, e: f64) -> f64 {
        let (lambda, lambda0) = (1.0 / rho, 1.0 / m.rho0);
        let phi = 1.0 - lambda / lambda0;
        let ph = m.p0 + m.rho0 * m.c0 * m.c0 * phi / (1.0 - m.s * phi).powi(2);
        let g2l = m.gamma / (2.0 * lambda);
        let f = ph * (1.0 - g2l * (lambda0 - lambda)) - g2l * m.p0 * (lambda0 - lambda);
        m.gamma / lambda * (e - m.cv * m.t0) + f
    }

    #[test]
    fn pressure_equals_seed003_eq12_as_printed() {
        let mut with_slope = MieGruneisenThermal::hmx_seed003();
        with_slope.s = 2.0;
        for m in [MieGruneisenThermal::hmx_seed003(), with_slope] {
            for (x, t) in [(0.85, 50.0), (1.0, 300.0), (1.1, 600.0), (1.45, 1500.0)] {
                let (rho, e) = (x * m.rho0, m.cv * t);
                let (a, b) = (m.pressure(rho, e), eq12_as_printed(&m, rho, e));
                assert!((a - b).abs() <= 1e-12 * a.abs().max(1e5), "{a} vs {b}");
            }
        }
    }

    #[test]
    fn reference_state_is_p0_at_t0() {
        for m in [
            MieGruneisenThermal::hmx_seed003(),
            MieGruneisenThermal::tkx50_seed003(),
            MieGruneisenThermal::estane_impedance_matched(),
        ] {
            let p = m.pressure(m.rho0, m.cv * 300.0);
            assert!((p - 1.0e5).abs() < 1e-6, "P = {p}");
            assert!((m.temperature(m.rho0, m.cv * 300.0) - 300.0).abs() < 1e-12);
        }
    }

    #[test]
    fn hmx_one_percent_compression_at_t0_matches_hand_value() {
        // ρ = 1.01 ρ₀: μ = 0.01, φ = 0.01/1.01 = 0.00990099; K_T = 11.3e9.
        // f = 1e5 (1 − 0.007) + 11.3e9 × 0.00990099 × (1 − 0.0035)
        //   = 99300 + 1.118812e8 × 0.9965 = 1.1158890e8 Pa.
        let hmx = MieGruneisenThermal::hmx_seed003();
        let p = hmx.pressure(1.01 * 1580.0, hmx.cv * 300.0);
        let expected = 1e5 * (1.0 - 0.7 * 0.01) + 11.3e9 * (0.01 / 1.01) * (1.0 - 0.35 * 0.01);
        assert!(
            (p - expected).abs() < 1e-6 * expected,
            "P = {p}, expected {expected}"
        );
        assert!((p - 1.115_889_0e8).abs() < 1e1, "P = {p}");
    }

    #[test]
    fn eq14_slope_is_lambda_over_gamma_cv_and_matches_the_eos() {
        // dT/dP = 1/(ρ𝒢c_v) = 1/(1580 × 0.7 × 1757.28) = 5.145219e-7 K/Pa.
        let hmx = MieGruneisenThermal::hmx_seed003();
        let slope = hmx.dtemperature_dpressure(1580.0);
        assert!((slope - 5.145_219e-7).abs() < 1e-12, "{slope}");
        // Same number from the EOS: ∂T/∂P at constant ρ = c_v⁻¹ / (∂P/∂e).
        let (rho, e) = (1600.0, hmx.cv * 400.0);
        let from_eos = 1.0 / (hmx.cv * hmx.dp_de(rho, e));
        assert!((from_eos - hmx.dtemperature_dpressure(rho)).abs() < 1e-20);
    }

    #[test]
    fn seed003_sound_speeds_come_from_the_bulk_modulus() {
        // c₀ = √(K_T/ρ₀): Estane √(4.3e9/1280) = 1832.86 m/s, and the
        // half-density variant (K and ρ both halved) has the same c₀.
        let estane = MieGruneisenThermal::estane_seed003();
        assert!((estane.c0 - 1832.86).abs() < 0.01);
        assert_eq!(estane.c0, MieGruneisenThermal::estane_half_density().c0);
        let hmx = MieGruneisenThermal::hmx_seed003();
        assert!((hmx.rho0 * hmx.c0 * hmx.c0 - 11.3e9).abs() < 1.0);
    }

    #[test]
    fn out_of_range_inputs_are_errors() {
        let m = MieGruneisenThermal::estane_seed003();
        assert!(m.check_state(-1.0, 1e5).is_err());
        assert!(m.check_state(f64::NAN, 1e5).is_err());
        assert!(m.check_state(1280.0, f64::NAN).is_err());
        assert!(m.specific_internal_energy(0.0, 1e5).is_err());
        assert!(m.density(1e5, 0.0).is_err());
        assert!(m.density(f64::NAN, 300.0).is_err());
    }

    #[test]
    fn validate_accepts_every_table_material_and_names_bad_fields() {
        for m in [
            MieGruneisenThermal::hmx_seed003(),
            MieGruneisenThermal::rdx_seed003(),
            MieGruneisenThermal::petn_seed003(),
            MieGruneisenThermal::tkx50_seed003(),
            MieGruneisenThermal::estane_seed003(),
            MieGruneisenThermal::estane_half_density(),
            MieGruneisenThermal::estane_density_matched(),
            MieGruneisenThermal::estane_impedance_matched(),
        ] {
            assert!(m.validate().is_ok(), "{:?}", m.validate());
        }
        let mut bad = MieGruneisenThermal::hmx_seed003();
        bad.p0 = f64::NAN;
        assert!(bad.validate().unwrap_err().contains("`p0`"));
        bad = MieGruneisenThermal::hmx_seed003();
        bad.s = -1.0;
        assert!(bad.validate().unwrap_err().contains("`s`"));
    }

    // Valid window ρ/ρ₀ ∈ [0.8, 1.5] (a little inside), T from 20 K to 1500 K.
    brisance_core::eos_contract_tests!(thermal_hmx, MieGruneisenThermal::hmx_seed003(), rho: 1280.0..2350.0, e: 3.6e4..2.6e6);
    brisance_core::eos_contract_tests!(thermal_tkx50, MieGruneisenThermal::tkx50_seed003(), rho: 1520.0..2790.0, e: 2.5e4..1.8e6);
    brisance_core::eos_contract_tests!(thermal_estane, MieGruneisenThermal::estane_seed003(), rho: 1040.0..1900.0, e: 3.0e4..2.2e6);
    brisance_core::eos_contract_tests!(thermal_hmx_with_slope, MieGruneisenThermal { s: 2.0, ..MieGruneisenThermal::hmx_seed003() }, rho: 1280.0..2350.0, e: 3.6e4..2.6e6);
}
