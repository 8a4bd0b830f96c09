//! Jones–Wilkins–Lee (JWL) equation of state for detonation products,
//! seed 001 eq 54:
//!
//! ```text
//! p = A (1 − ω/(R₁V)) e^{−R₁V} + B (1 − ω/(R₂V)) e^{−R₂V} + ω E / V
//! ```
//!
//! with the relative volume V = v/v₀ = ρ₀/ρ (ρ₀ the density of the
//! unreacted explosive) and E the internal energy per unit *initial* volume,
//! E = ρ₀ e (e the specific internal energy, J/kg). Seed 001 writes the last
//! term as ωE₀/V; E₀ is the value E takes in the unreacted state (the
//! detonation energy per initial volume, 6.993 × 10⁹ J/m³ for TNT), and E is
//! the variable. Since ωE/V = ωρe the model is a Mie–Grüneisen form with a
//! constant Grüneisen parameter Γ = ω:
//!
//! ```text
//! p = p_c(V) + ω ρ (e − e_c(V)),   p_c = A e^{−R₁V} + B e^{−R₂V},
//! e_c = (A/(R₁ρ₀)) e^{−R₁V} + (B/(R₂ρ₀)) e^{−R₂V},
//! ```
//!
//! where (p_c, e_c) is the isentrope of the family with no C V^{−(1+ω)} term
//! (de_c = −p_c dv). The thermal part takes that isentrope as the 0 K
//! reference and a constant specific heat c_v:
//!
//! ```text
//! T = (e − e_c(V)) / c_v,   p = p_c(V) + ω ρ c_v T,
//! ```
//!
//! which is thermodynamically consistent (∂e/∂v|_T = T ∂p/∂T|_v − p) and
//! makes isentropes T ∝ V^{−ω}. The valid range is ρ > 0 with T > 0 (the
//! pressure formula itself is defined for any finite e).
//!
//! Units: A, B, E₀ in Pa (= J/m³); R₁, R₂, ω dimensionless; ρ₀ kg/m³;
//! c_v J/(kg·K).

use brisance_core::EosError;
use serde::{Deserialize, Serialize};

/// JWL parameters (seed 001 eq 54).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Jwl {
    /// A, Pa.
    pub a: f64,
    /// B, Pa.
    pub b: f64,
    /// R₁ (dimensionless).
    pub r1: f64,
    /// R₂ (dimensionless).
    pub r2: f64,
    /// ω, the Grüneisen parameter of the products (dimensionless).
    pub omega: f64,
    /// E₀, detonation energy per unit initial volume, J/m³ (the value of
    /// E = ρ₀ e in the unreacted state; the CJ state is computed from it).
    pub e0: f64,
    /// ρ₀, density of the unreacted explosive, kg/m³ (V = ρ₀/ρ).
    pub rho0: f64,
    /// Specific heat at constant volume of the products, J/(kg·K); sets the
    /// temperature scale only (the pressure does not depend on it).
    pub cv: f64,
}

/// Heat capacity per unit volume, 1.0 × 10⁶ J/(m³·K) (1.0 × 10⁻⁵ Mbar/K),
/// that sets c_v = 10⁶/ρ₀ for the shipped products sets. A JWL fit carries no
/// heat capacity; this is the order of magnitude of detonation-product heat
/// capacities and only fixes the temperature scale.
pub const PRODUCTS_HEAT_CAPACITY_PER_VOLUME: f64 = 1.0e6;

impl Jwl {
    /// TNT at ρ₀ = 1630 kg/m³, seed 001 §4.1 (from Liu, Liu, Lam and Zong
    /// 2003): A = 3.712 × 10¹¹ Pa, B = 3.21 × 10⁹ Pa, R₁ = 4.15, R₂ = 0.95,
    /// ω = 0.3, E₀ = 6.993 × 10⁹ J/m³; detonation velocity 6930 m/s.
    /// c_v = [`PRODUCTS_HEAT_CAPACITY_PER_VOLUME`]/ρ₀.
    pub fn tnt() -> Self {
        Self {
            a: 3.712e11,
            b: 3.21e9,
            r1: 4.15,
            r2: 0.95,
            omega: 0.3,
            e0: 6.993e9,
            rho0: 1630.0,
            cv: PRODUCTS_HEAT_CAPACITY_PER_VOLUME / 1630.0,
        }
    }

    /// Specific detonation energy e₀ = E₀/ρ₀, J/kg.
    pub fn specific_detonation_energy(&self) -> f64 {
        self.e0 / self.rho0
    }

    /// Checks every parameter, naming the bad field and the expected range.
    pub fn validate(&self) -> Result<(), String> {
        positive("jwl", "a", self.a, "Pa")?;
        positive("jwl", "b", self.b, "Pa")?;
        positive("jwl", "r1", self.r1, "")?;
        positive("jwl", "r2", self.r2, "")?;
        positive("jwl", "omega", self.omega, "")?;
        positive("jwl", "e0", self.e0, "J/m³")?;
        positive("jwl", "rho0", self.rho0, "kg/m³")?;
        positive("jwl", "cv", self.cv, "J/(kg·K)")?;
        Ok(())
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

    /// The constant C of the isentrope of this family through (ρ, e):
    /// along it E(V) = (A/R₁)e^{−R₁V} + (B/R₂)e^{−R₂V} + (C/ω)V^{−ω} and
    /// p(V) = A e^{−R₁V} + B e^{−R₂V} + C V^{−(ω+1)} (seed 004 eq 30), so
    /// C = ω V^ω (ρ₀e − (A/R₁)e^{−R₁V} − (B/R₂)e^{−R₂V}), Pa.
    pub fn isentrope_constant(&self, rho: f64, e: f64) -> f64 {
        let v = self.rho0 / rho;
        self.omega * v.powf(self.omega) * self.rho0 * (e - self.cold().energy(v))
    }

    /// Pressure on the isentrope with constant `c` at relative volume
    /// `relative_volume` (seed 004 eq 30), Pa.
    pub fn isentrope_pressure(&self, c: f64, relative_volume: f64) -> f64 {
        let v = relative_volume;
        self.cold().pressure(v) + c * v.powf(-(self.omega + 1.0))
    }

    /// Specific internal energy on the isentrope with constant `c` at
    /// relative volume `relative_volume`, J/kg.
    pub fn isentrope_energy(&self, c: f64, relative_volume: f64) -> f64 {
        let v = relative_volume;
        self.cold().energy(v) + c / (self.omega * self.rho0) * v.powf(-self.omega)
    }
}

pub(crate) fn positive(model: &str, field: &str, value: f64, unit: &str) -> Result<(), String> {
    if value.is_finite() && value > 0.0 {
        Ok(())
    } else {
        Err(format!(
            "{model}.{field} = {value} {unit}: expected a finite value > 0"
        ))
    }
}

/// The shared JWL kernel: the 0 K isentrope p_c(V) = A e^{−R₁V} + B e^{−R₂V},
/// its energy e_c(V), and the thermal Grüneisen term ωρ(e − e_c). Used by
/// [`Jwl`] and [`crate::JwlCTerm`], whose (ρ, e) → p maps coincide.
#[derive(Debug, Clone, Copy)]
pub(crate) struct JwlCold {
    pub a: f64,
    pub b: f64,
    pub r1: f64,
    pub r2: f64,
    pub omega: f64,
    pub rho0: f64,
    pub cv: f64,
}

impl JwlCold {
    /// p_c(V), Pa.
    #[inline]
    pub fn pressure(&self, v: f64) -> f64 {
        self.a * (-self.r1 * v).exp() + self.b * (-self.r2 * v).exp()
    }

    /// e_c(V) = −∫ p_c dv, zero at infinite expansion, J/kg.
    #[inline]
    pub fn energy(&self, v: f64) -> f64 {
        (self.a / self.r1 * (-self.r1 * v).exp() + self.b / self.r2 * (-self.r2 * v).exp())
            / self.rho0
    }

    /// dp_c/dρ = (V/ρ)(A R₁ e^{−R₁V} + B R₂ e^{−R₂V}).
    #[inline]
    pub fn dpressure_drho(&self, rho: f64) -> f64 {
        let v = self.rho0 / rho;
        v / rho
            * (self.a * self.r1 * (-self.r1 * v).exp() + self.b * self.r2 * (-self.r2 * v).exp())
    }

    /// de_c/dρ = p_c/ρ² (from de_c = −p_c dv).
    #[inline]
    pub fn denergy_drho(&self, rho: f64) -> f64 {
        self.pressure(self.rho0 / rho) / (rho * rho)
    }

    /// p(ρ, e) = p_c + ωρ(e − e_c) (seed 001 eq 54 rearranged).
    #[inline]
    pub fn total_pressure(&self, rho: f64, e: f64) -> f64 {
        let v = self.rho0 / rho;
        self.pressure(v) + self.omega * rho * (e - self.energy(v))
    }

    /// ∂p/∂ρ|ₑ = p_c' + ω(e − e_c) − ωρ e_c'.
    #[inline]
    pub fn dp_drho(&self, rho: f64, e: f64) -> f64 {
        let v = self.rho0 / rho;
        self.dpressure_drho(rho) + self.omega * (e - self.energy(v))
            - self.omega * rho * self.denergy_drho(rho)
    }

    pub fn check_state(&self, name: &'static str, rho: f64, e: f64) -> Result<(), EosError> {
        if !(rho.is_finite() && rho > 0.0) {
            return Err(EosError::OutOfRange {
                eos: name,
                detail: format!("density ρ = {rho} kg/m³ must be finite and > 0"),
            });
        }
        if !e.is_finite() {
            return Err(EosError::OutOfRange {
                eos: name,
                detail: format!("specific internal energy e = {e} J/kg must be finite"),
            });
        }
        Ok(())
    }

    /// e(ρ, p) = e_c + (p − p_c)/(ωρ).
    pub fn specific_internal_energy(
        &self,
        name: &'static str,
        rho: f64,
        p: f64,
    ) -> Result<f64, EosError> {
        self.check_state(name, rho, 0.0)?;
        if !p.is_finite() {
            return Err(EosError::OutOfRange {
                eos: name,
                detail: format!("pressure p = {p} Pa must be finite"),
            });
        }
        let v = self.rho0 / rho;
        Ok(self.energy(v) + (p - self.pressure(v)) / (self.omega * rho))
    }

    /// ∂p/∂ρ at constant T: p_c' + ω c_v T.
    #[inline]
    fn dp_drho_at_t(&self, rho: f64, t: f64) -> f64 {
        self.dpressure_drho(rho) + self.omega * self.cv * t
    }

    /// ρ(p, T): the root of p_c(ρ₀/ρ) + ωρc_vT = p, which is strictly
    /// increasing in ρ for T > 0, by Newton's method safeguarded with a
    /// bracket (no allocation).
    pub fn density(&self, name: &'static str, p: f64, t: f64) -> Result<f64, EosError> {
        if !(p.is_finite() && p > 0.0 && t.is_finite() && t > 0.0) {
            return Err(EosError::OutOfRange {
                eos: name,
                detail: format!("ρ(p, T) needs finite p > 0 and T > 0, got p = {p} Pa, T = {t} K"),
            });
        }
        let f = |rho: f64| self.pressure(self.rho0 / rho) + self.omega * rho * self.cv * t - p;
        // p_c ≥ 0 bounds the root above by the thermal term alone.
        let mut hi = p / (self.omega * self.cv * t);
        let mut lo = 0.5 * hi;
        let mut halvings = 0;
        while f(lo) > 0.0 {
            hi = lo;
            lo *= 0.5;
            halvings += 1;
            if halvings > 2000 {
                return Err(EosError::NoConvergence {
                    eos: name,
                    iterations: halvings,
                    residual: f(lo),
                });
            }
        }
        let mut rho = 0.5 * (lo + hi);
        for _ in 0..200 {
            let r = f(rho);
            if r > 0.0 {
                hi = rho;
            } else {
                lo = rho;
            }
            let d = self.dp_drho_at_t(rho, t);
            let mut next = rho - r / d;
            if !(next > lo && next < hi) {
                next = 0.5 * (lo + hi);
            }
            if (next - rho).abs() <= 4.0 * f64::EPSILON * rho || hi - lo <= 4.0 * f64::EPSILON * hi
            {
                return Ok(next);
            }
            rho = next;
        }
        Err(EosError::NoConvergence {
            eos: name,
            iterations: 200,
            residual: f(rho),
        })
    }

    /// κ_T = 1/(ρ ∂p/∂ρ|_T).
    pub fn isothermal_compressibility(
        &self,
        name: &'static str,
        p: f64,
        t: f64,
    ) -> Result<f64, EosError> {
        let rho = self.density(name, p, t)?;
        Ok(1.0 / (rho * self.dp_drho_at_t(rho, t)))
    }

    /// α = (1/ρ)(∂p/∂T|_ρ)/(∂p/∂ρ|_T) = ω c_v / ∂p/∂ρ|_T.
    pub fn thermal_expansivity(&self, name: &'static str, p: f64, t: f64) -> Result<f64, EosError> {
        let rho = self.density(name, p, t)?;
        Ok(self.omega * self.cv / self.dp_drho_at_t(rho, t))
    }
}

/// The `Eos` implementation shared by the JWL forms whose pressure is
/// p = p_c(V) + ωρ(e − e_c(V)) with a constant Grüneisen ω and heat
/// capacity c_v ([`Jwl`], seed 001 eq 54, and
/// [`crate::jwl_cterm::JwlCTerm`], seed 000 eq 35, where the C terms
/// cancel). The type provides `cold() -> JwlCold` and the fields `rho0`,
/// `omega`, `cv`.
macro_rules! impl_jwl_form_eos {
    ($ty:ty, $name:literal) => {
        impl brisance_core::Eos for $ty {
            fn name(&self) -> &'static str {
                $name
            }

            fn reference_density(&self) -> f64 {
                self.rho0
            }

            /// p = p_c(V) + ωρ(e − e_c(V)), V = ρ₀/ρ.
            #[inline]
            fn pressure(&self, rho: f64, e: f64) -> f64 {
                self.cold().total_pressure(rho, e)
            }

            #[inline]
            fn dp_drho(&self, rho: f64, e: f64) -> f64 {
                self.cold().dp_drho(rho, e)
            }

            /// ∂p/∂e|ρ = ωρ.
            #[inline]
            fn dp_de(&self, rho: f64, _e: f64) -> f64 {
                self.omega * rho
            }

            /// Γ = ω.
            #[inline]
            fn gruneisen(&self, _rho: f64, _e: f64) -> f64 {
                self.omega
            }

            fn check_state(&self, rho: f64, e: f64) -> Result<(), brisance_core::EosError> {
                self.cold().check_state($name, rho, e)
            }

            fn specific_internal_energy(
                &self,
                rho: f64,
                p: f64,
            ) -> Result<f64, brisance_core::EosError> {
                self.cold().specific_internal_energy($name, rho, p)
            }

            /// T = (e − e_c(V))/c_v.
            fn temperature(&self, rho: f64, e: f64) -> f64 {
                (e - self.cold().energy(self.rho0 / rho)) / self.cv
            }

            fn specific_internal_energy_from_temperature(&self, rho: f64, t: f64) -> f64 {
                self.cold().energy(self.rho0 / rho) + self.cv * t
            }

            fn cv(&self, _rho: f64, _t: f64) -> f64 {
                self.cv
            }

            fn density(&self, p: f64, t: f64) -> Result<f64, brisance_core::EosError> {
                self.cold().density($name, p, t)
            }

            fn isothermal_compressibility(
                &self,
                p: f64,
                t: f64,
            ) -> Result<f64, brisance_core::EosError> {
                self.cold().isothermal_compressibility($name, p, t)
            }

            fn thermal_expansivity(&self, p: f64, t: f64) -> Result<f64, brisance_core::EosError> {
                self.cold().thermal_expansivity($name, p, t)
            }
        }
    };
}
pub(crate) use impl_jwl_form_eos;

// Seed 001 eq 54 with V = ρ₀/ρ and E = ρ₀e, written as
// p = p_c(V) + ωρ(e − e_c(V)) (algebraically identical).
impl_jwl_form_eos!(Jwl, "jwl");

#[cfg(test)]
mod tests {
    use super::*;
    use brisance_core::Eos;

    /// Seed 001 eq 54 exactly as printed, for comparison.
    fn eq54(j: &Jwl, rho: f64, e: f64) -> f64 {
        let v = j.rho0 / rho;
        let big_e = j.rho0 * e;
        j.a * (1.0 - j.omega / (j.r1 * v)) * (-j.r1 * v).exp()
            + j.b * (1.0 - j.omega / (j.r2 * v)) * (-j.r2 * v).exp()
            + j.omega * big_e / v
    }

    #[test]
    fn tnt_pressure_at_initial_volume_matches_hand_value() {
        // V = 1, E = E₀: 3.712e11(1 − 0.3/4.15)e^{−4.15}
        //   + 3.21e9(1 − 0.3/0.95)e^{−0.95} + 0.3·6.993e9
        // = 5.42873e9 + 0.84941e9 + 2.09790e9 = 8.37604e9 Pa.
        let j = Jwl::tnt();
        let p = j.pressure(j.rho0, j.specific_detonation_energy());
        let hand = 3.712e11 * (1.0 - 0.3 / 4.15) * (-4.15f64).exp()
            + 3.21e9 * (1.0 - 0.3 / 0.95) * (-0.95f64).exp()
            + 0.3 * 6.993e9;
        assert!((p - hand).abs() < 1e-6 * hand, "p = {p}, hand = {hand}");
        assert!((p - 8.37604e9).abs() < 1e-5 * 8.37604e9, "p = {p}");
    }

    #[test]
    fn jwl_pressure_equals_seed_equation_54_as_printed() {
        let j = Jwl::tnt();
        for &(rho, e) in &[
            (1630.0, 4.29e6),
            (2200.0, 6.0e6),
            (400.0, 1.0e6),
            (50.0, 2.0e5),
        ] {
            let (p, p54) = (j.pressure(rho, e), eq54(&j, rho, e));
            assert!(
                (p - p54).abs() <= 1e-12 * p54.abs().max(1.0),
                "{p} vs {p54}"
            );
        }
    }

    #[test]
    fn jwl_pressure_roundtrips_through_energy() {
        let j = Jwl::tnt();
        let e = j.specific_internal_energy(2000.0, 2.0e10).unwrap();
        assert!((j.pressure(2000.0, e) - 2.0e10).abs() < 1e-3);
    }

    #[test]
    fn isentrope_constant_reproduces_the_state() {
        let j = Jwl::tnt();
        let (rho, e) = (2200.0, 6.5e6);
        let c = j.isentrope_constant(rho, e);
        let v = j.rho0 / rho;
        assert!((j.isentrope_energy(c, v) - e).abs() < 1e-9 * e);
        assert!(
            (j.isentrope_pressure(c, v) - j.pressure(rho, e)).abs() < 1e-9 * j.pressure(rho, e)
        );
    }

    #[test]
    fn large_expansion_tends_to_a_gamma_law_gas_with_gamma_one_plus_omega() {
        // At V = 50 the exponentials are below 1e-20 of the ωρe term.
        let j = Jwl::tnt();
        let rho = j.rho0 / 50.0;
        let p = j.pressure(rho, 1.0e6);
        assert!((p - 0.3 * rho * 1.0e6).abs() < 1e-12 * p);
    }

    #[test]
    fn validate_names_the_bad_field() {
        let mut j = Jwl::tnt();
        assert!(j.validate().is_ok());
        j.r2 = -1.0;
        let msg = j.validate().unwrap_err();
        assert!(msg.contains("r2"), "{msg}");
    }

    #[test]
    fn density_from_pressure_and_temperature_inverts_the_thermal_form() {
        let j = Jwl::tnt();
        let (rho, t) = (1800.0, 3000.0);
        let e = j.specific_internal_energy_from_temperature(rho, t);
        let r = j.density(j.pressure(rho, e), t).unwrap();
        assert!((r - rho).abs() < 1e-10 * rho);
        assert!(j.density(-1.0, 300.0).is_err());
        assert!(j.density(1e9, 0.0).is_err());
    }

    brisance_core::eos_contract_tests!(jwl_tnt, Jwl::tnt(), rho: 20.0..3000.0, t: 100.0..8000.0);
    brisance_core::eos_contract_tests!(jwl_tnt_energy_box, Jwl::tnt(), rho: 100.0..2600.0, e: 1.0e7..5.0e7);
}
