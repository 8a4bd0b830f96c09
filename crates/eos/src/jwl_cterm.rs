//! JWL "C-term" form for JWL++ detonation products (seed 000 §4.1.1 eq 34,
//! JWL++ of Souers et al. 2000, seed 000 ref. 16).
//!
//! # What seed 000 prints and what is implemented
//!
//! Seed 000 eq 34 prints p = A e^{−R₁v} + B e^{−R₂v} + C/(ρ₀ κ v^{n−1}) with
//! v = ρ₀/ρ and lists A, B, C, R₁, R₂, ρ₀ and κ as parameters, yet every
//! parameter set it gives (§5.1, §5.2) has A, B, C, R₁, R₂, **ω** and ρ₀ and
//! no κ or n: the κ and n of the last term belong to the Murnaghan reactant
//! (eq 33) and were carried into eq 34 by mistake. The JWL++ products
//! equation of Souers et al. (2000) — the form Uintah's `JWLC` equation of
//! state evaluates with these very parameter names (A, B, C, R1, R2, om,
//! rho0) — is the JWL principal isentrope
//!
//! ```text
//! p_s(V) = A e^{−R₁V} + B e^{−R₂V} + C V^{−(1+ω)},   V = ρ₀/ρ,
//! ```
//!
//! which is also seed 004 eq 30. That is the reference curve implemented here.
//!
//! # Off the isentrope
//!
//! JWL++ as published uses p_s(V) alone (the products stay on the
//! isentrope and ∂p/∂e = 0). A barotropic products EOS cannot take up the
//! chemical energy a reaction deposits or the work of a shock, so Brisance
//! adds the JWL Grüneisen energy term with Γ = ω:
//!
//! ```text
//! p(ρ, e) = p_s(V) + ω ρ (e − e_s(V)),
//! e_s(V) = −∫_∞^v p_s dv = (1/ρ₀)[(A/R₁)e^{−R₁V} + (B/R₂)e^{−R₂V} + (C/ω)V^{−ω}],
//! ```
//!
//! with e_s obtained by integrating −p_s dv analytically from infinite
//! expansion (where e_s → 0). On the isentrope (e = e_s) the pressure is
//! exactly the published JWL++ one; off it, the C terms cancel and the
//! (ρ, e) → p map is the standard JWL (seed 001 eq 54) with the same A, B, R₁,
//! R₂, ω, so this module shares [`crate::jwl`]'s kernel. The C term survives
//! as the model's reference isentrope, and from it the detonation energy
//! (`tools::cj::jwl_cterm_unreacted_state`): the energy e₀ that puts the
//! CJ state on the Rayleigh line tangent to p_s.
//!
//! Thermal part as in [`crate::Jwl`]: T = (e − e_c(V))/c_v with
//! e_c = (1/ρ₀)[(A/R₁)e^{−R₁V} + (B/R₂)e^{−R₂V}] the 0 K isentrope, so on the
//! reference isentrope T_s(V) = C V^{−ω}/(ω ρ₀ c_v). Valid range: ρ > 0 with
//! T > 0.
//!
//! Units: A, B, C in Pa; R₁, R₂, ω dimensionless; ρ₀ kg/m³; c_v J/(kg·K).

use crate::jwl::{positive, JwlCold, PRODUCTS_HEAT_CAPACITY_PER_VOLUME};
use serde::{Deserialize, Serialize};

/// JWL C-term (JWL++ products) parameters, seed 000 eq 34 as corrected
/// above.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct JwlCTerm {
    /// A, Pa.
    pub a: f64,
    /// B, Pa.
    pub b: f64,
    /// C, Pa (the V^{−(1+ω)} term of the reference isentrope).
    pub c: f64,
    /// R₁ (dimensionless).
    pub r1: f64,
    /// R₂ (dimensionless).
    pub r2: f64,
    /// ω (dimensionless), also the Grüneisen Γ off the isentrope.
    pub omega: f64,
    /// ρ₀, density of the unreacted explosive, kg/m³.
    pub rho0: f64,
    /// Specific heat at constant volume, J/(kg·K) (temperature scale only).
    pub cv: f64,
}

impl JwlCTerm {
    /// ANFO-K1 products, seed 000 §5.1: A = 2.9867 × 10¹¹ Pa,
    /// B = 4.11706 × 10⁹ Pa, C = 7.206147 × 10⁸ Pa, R₁ = 4.95, R₂ = 1.15,
    /// ω = 0.35, ρ₀ = 1160 kg/m³. c_v = 10⁶/ρ₀ J/(kg·K)
    /// ([`PRODUCTS_HEAT_CAPACITY_PER_VOLUME`]).
    pub fn anfo_k1() -> Self {
        Self {
            a: 2.9867e11,
            b: 4.11706e9,
            c: 7.206147e8,
            r1: 4.95,
            r2: 1.15,
            omega: 0.35,
            rho0: 1160.0,
            cv: PRODUCTS_HEAT_CAPACITY_PER_VOLUME / 1160.0,
        }
    }

    /// QM-100 (ammonium-nitrate emulsion) products, seed 000 §5.2:
    /// A = 4.8702 × 10¹¹ Pa, B = 2.54887 × 10⁹ Pa, C = 5.06568 × 10⁸ Pa,
    /// R₁ = 5.0, R₂ = 1.0, ω = 0.3, ρ₀ = 1260 kg/m³. c_v = 10⁶/ρ₀ J/(kg·K).
    pub fn qm100() -> Self {
        Self {
            a: 4.8702e11,
            b: 2.54887e9,
            c: 5.06568e8,
            r1: 5.0,
            r2: 1.0,
            omega: 0.3,
            rho0: 1260.0,
            cv: PRODUCTS_HEAT_CAPACITY_PER_VOLUME / 1260.0,
        }
    }

    /// Checks every parameter, naming the bad field and the expected range.
    pub fn validate(&self) -> Result<(), String> {
        positive("jwl_cterm", "a", self.a, "Pa")?;
        positive("jwl_cterm", "b", self.b, "Pa")?;
        positive("jwl_cterm", "c", self.c, "Pa")?;
        positive("jwl_cterm", "r1", self.r1, "")?;
        positive("jwl_cterm", "r2", self.r2, "")?;
        positive("jwl_cterm", "omega", self.omega, "")?;
        positive("jwl_cterm", "rho0", self.rho0, "kg/m³")?;
        positive("jwl_cterm", "cv", self.cv, "J/(kg·K)")?;
        Ok(())
    }

    /// Reference isentrope pressure p_s(V) = A e^{−R₁V} + B e^{−R₂V} + C V^{−(1+ω)}
    /// (Souers et al. 2000; seed 004 eq 30), Pa, at relative volume V = ρ₀/ρ.
    #[inline]
    pub fn isentrope_pressure(&self, relative_volume: f64) -> f64 {
        let v = relative_volume;
        self.cold().pressure(v) + self.c * v.powf(-(1.0 + self.omega))
    }

    /// Reference isentrope energy e_s(V) = −∫_∞^v p_s dv, J/kg.
    #[inline]
    pub fn isentrope_energy(&self, relative_volume: f64) -> f64 {
        let v = relative_volume;
        self.cold().energy(v) + self.c / (self.omega * self.rho0) * v.powf(-self.omega)
    }

    fn cold(&self) -> JwlCold {
        JwlCold {
            a: self.a,
            b: self.b,
            r1: self.r1,
            r2: self.r2,
            omega: self.omega,
            rho0: self.rho0,
            cv: self.cv,
        }
    }
}

// p = p_s(V) + ωρ(e − e_s(V)), evaluated in the equivalent form
// p_c(V) + ωρ(e − e_c(V)) where the C terms have cancelled.
crate::jwl::impl_jwl_form_eos!(JwlCTerm, "jwl_cterm");

#[cfg(test)]
mod tests {
    use super::*;
    use brisance_core::Eos;

    #[test]
    fn on_the_reference_isentrope_pressure_is_the_published_cterm_form() {
        // At V = 1 for ANFO-K1: p_s = 2.9867e11 e^{−4.95} + 4.11706e9 e^{−1.15}
        // + 7.206147e8 = 2.11560e9 + 1.30361e9 + 0.72061e9 = 4.13983e9 Pa.
        let m = JwlCTerm::anfo_k1();
        let hand = 2.9867e11 * (-4.95f64).exp() + 4.11706e9 * (-1.15f64).exp() + 7.206147e8;
        assert!((m.isentrope_pressure(1.0) - hand).abs() < 1e-9 * hand);
        assert!((hand - 4.13983e9).abs() < 1e-5 * hand, "hand = {hand}");
        for &v in &[0.6, 1.0, 2.0, 7.0, 30.0] {
            let rho = m.rho0 / v;
            let p = m.pressure(rho, m.isentrope_energy(v));
            let ps = m.isentrope_pressure(v);
            assert!((p - ps).abs() < 1e-10 * ps, "V = {v}: {p} vs {ps}");
        }
    }

    #[test]
    fn isentrope_energy_is_minus_the_integral_of_pressure() {
        // de_s/dV = −p_s/ρ₀ checked by a central difference.
        let m = JwlCTerm::qm100();
        for &v in &[0.7, 1.5, 5.0] {
            let h = 1e-5 * v;
            let de = (m.isentrope_energy(v + h) - m.isentrope_energy(v - h)) / (2.0 * h);
            let want = -m.isentrope_pressure(v) / m.rho0;
            assert!(
                (de - want).abs() < 1e-7 * want.abs(),
                "V = {v}: {de} vs {want}"
            );
        }
    }

    #[test]
    fn off_the_isentrope_the_gruneisen_term_is_omega_rho_delta_e() {
        let m = JwlCTerm::anfo_k1();
        let (v, de) = (0.8, 1.0e6);
        let rho = m.rho0 / v;
        let p = m.pressure(rho, m.isentrope_energy(v) + de);
        let want = m.isentrope_pressure(v) + 0.35 * rho * de;
        assert!((p - want).abs() < 1e-10 * want);
    }

    #[test]
    fn validate_names_the_bad_field() {
        let mut m = JwlCTerm::qm100();
        assert!(m.validate().is_ok());
        m.c = f64::NAN;
        assert!(m.validate().unwrap_err().contains("jwl_cterm.c"));
    }

    brisance_core::eos_contract_tests!(jwl_cterm_anfo_k1, JwlCTerm::anfo_k1(), rho: 20.0..2200.0, t: 100.0..8000.0);
    brisance_core::eos_contract_tests!(jwl_cterm_qm100, JwlCTerm::qm100(), rho: 20.0..2400.0, t: 100.0..8000.0);
}
