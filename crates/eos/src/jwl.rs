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
        self.a * decaying_exp(-self.r1 * v) + self.b * decaying_exp(-self.r2 * v)
    }

    /// e_c(V) = −∫ p_c dv, zero at infinite expansion, J/kg.
    #[inline]
    pub fn energy(&self, v: f64) -> f64 {
        (self.a / self.r1 * decaying_exp(-self.r1 * v)
            + self.b / self.r2 * decaying_exp(-self.r2 * v))
            / self.rho0
    }

    /// dp_c/dρ = (V/ρ)(A R₁ e^{−R₁V} + B R₂ e^{−R₂V}).
    #[inline]
    pub fn dpressure_drho(&self, rho: f64) -> f64 {
        let v = self.rho0 / rho;
        v / rho
            * (self.a * self.r1 * decaying_exp(-self.r1 * v)
                + self.b * self.r2 * decaying_exp(-self.r2 * v))
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

    /// c² = ∂p/∂ρ|ₑ + (p/ρ²)∂p/∂e|ρ, the trait's default formula term by
    /// term (the same bits), with the two exponentials evaluated once
    /// instead of ten times.
    #[inline]
    pub fn sound_speed_squared(&self, rho: f64, e: f64) -> f64 {
        let v = self.rho0 / rho;
        let ea = decaying_exp(-self.r1 * v);
        let eb = decaying_exp(-self.r2 * v);
        let p_c = self.a * ea + self.b * eb;
        let e_c = (self.a / self.r1 * ea + self.b / self.r2 * eb) / self.rho0;
        let dp_c = v / rho * (self.a * self.r1 * ea + self.b * self.r2 * eb);
        let de_c = p_c / (rho * rho);
        let p = p_c + self.omega * rho * (e - e_c);
        let dp_drho = dp_c + self.omega * (e - e_c) - self.omega * rho * de_c;
        dp_drho + p / (rho * rho) * (self.omega * rho)
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
    #[cfg(test)]
    fn dp_drho_at_t(&self, rho: f64, t: f64) -> f64 {
        self.dpressure_drho(rho) + self.omega * self.cv * t
    }

    /// ρ(p, T): the root of p_c(ρ₀/ρ) + ωρc_vT = p. See
    /// [`JwlCold::density_and_slope`].
    pub fn density(&self, name: &'static str, p: f64, t: f64) -> Result<f64, EosError> {
        Ok(self.density_and_slope(name, p, t)?.rho)
    }

    /// ρ(p, T) and ∂p/∂ρ|_T there, without allocation.
    ///
    /// In the relative volume V = ρ₀/ρ the equation is
    ///
    /// ```text
    /// P(V) = A e^{−R₁V} + B e^{−R₂V} + K/V = p,   K = ω c_v T ρ₀,
    /// ```
    ///
    /// a sum of positive, decreasing, convex and log-convex terms. So both
    /// g = P − p and φ = ln(P/p) are convex and decreasing, and Newton's
    /// method on either, started left of the root (P > p), climbs to it
    /// monotonically without overshooting. The start is the closed-form
    /// bound V_t = K/p (the thermal term alone equals p there, so P(V_t) ≥ p):
    /// where the exponentials have underflowed it is the answer, ρ = p/(ωc_vT),
    /// with no `exp` evaluated. Far from the root (P > 1.1 p) the step is
    /// Newton's on φ, which is almost linear where one exponential dominates;
    /// near it, Newton's on g (no logarithm). Each iteration costs two `exp`
    /// (the derivative reuses them). After a step from the left the error
    /// left is at most (max(R₁, R₂, 2/V)/2)·ΔV² (P''/|P'| of each term is
    /// R₁, R₂ or 2/V), and the iteration stops once that is below half an
    /// ulp of V. The iterates are kept in the bracket [lo, hi] of the last
    /// points found left and right of the root: round-off near the root can
    /// put one on the right, and a step that would leave the bracket is
    /// replaced by bisection.
    pub(crate) fn density_and_slope(
        &self,
        name: &'static str,
        p: f64,
        t: f64,
    ) -> Result<DensitySlope, EosError> {
        if !(p.is_finite() && p > 0.0 && t.is_finite() && t > 0.0) {
            return Err(EosError::OutOfRange {
                eos: name,
                detail: format!("ρ(p, T) needs finite p > 0 and T > 0, got p = {p} Pa, T = {t} K"),
            });
        }
        let thermal_slope = self.omega * self.cv * t; // ∂(ωρc_vT)/∂ρ
        let rho_thermal = p / thermal_slope;
        if !(rho_thermal.is_finite() && rho_thermal > 0.0) {
            return Err(EosError::OutOfRange {
                eos: name,
                detail: format!(
                    "ρ(p, T) = p/(ωc_vT) = {rho_thermal:e} kg/m³ at p = {p} Pa, T = {t} K is outside the floating-point range"
                ),
            });
        }
        // Both exponentials of the 0 K isentrope underflow at V_t: the
        // thermal term alone balances p, exactly.
        if self.r1.min(self.r2) * self.rho0 > -EXP_FLUSH * rho_thermal {
            return Ok(DensitySlope {
                rho: rho_thermal,
                dp_drho: thermal_slope,
                iterations: 0,
            });
        }
        let k = thermal_slope * self.rho0;
        let r_max = self.r1.max(self.r2);
        let mut v = self.rho0 / rho_thermal;
        // Bracket: P(lo) > p > P(hi); P(V_t) ≥ p.
        let mut lo = v;
        let mut hi = f64::INFINITY;
        for it in 1..=DENSITY_MAX_ITERATIONS {
            let ea = self.a * decaying_exp(-self.r1 * v);
            let eb = self.b * decaying_exp(-self.r2 * v);
            let thermal = k / v;
            let big_p = ea + eb + thermal;
            // −dP/dV > 0.
            let slope = self.r1 * ea + self.r2 * eb + thermal / v;
            let excess = big_p - p;
            if excess == 0.0 {
                return Ok(self.density_slope_at(v, slope, it));
            }
            let from_left = excess > 0.0;
            if from_left {
                lo = v;
            } else {
                hi = v;
            }
            let step = if excess > 0.1 * p {
                (excess / p).ln_1p() * big_p / slope
            } else {
                excess / slope
            };
            let next = v + step;
            let converged = if from_left {
                // Error left after a step from the left.
                r_max.max(2.0 / v) * step * step <= f64::EPSILON * next
            } else {
                step.abs() <= 4.0 * f64::EPSILON * v
            };
            if converged {
                // −P'(next) from the terms at v, to second order in the
                // step (the third-order error is below 1e-19).
                let ga = self.r1 * step;
                let gb = self.r2 * step;
                let ea = ea * (1.0 - ga + 0.5 * ga * ga);
                let eb = eb * (1.0 - gb + 0.5 * gb * gb);
                let slope = self.r1 * ea + self.r2 * eb + k / (next * next);
                return Ok(self.density_slope_at(next, slope, it));
            }
            v = if next > lo && next < hi {
                next
            } else if hi.is_finite() {
                0.5 * (lo + hi)
            } else {
                break;
            };
            if hi.is_finite() && hi - lo <= 4.0 * f64::EPSILON * hi {
                let slope = self.r1 * self.a * decaying_exp(-self.r1 * v)
                    + self.r2 * self.b * decaying_exp(-self.r2 * v)
                    + k / (v * v);
                return Ok(self.density_slope_at(v, slope, it));
            }
        }
        Err(EosError::NoConvergence {
            eos: name,
            iterations: DENSITY_MAX_ITERATIONS,
            residual: self.pressure(v) + k / v - p,
        })
    }

    /// ρ = ρ₀/V and ∂p/∂ρ|_T = −P'(V) V²/ρ₀ from −P'(V) = `neg_dp_dv`.
    #[inline]
    fn density_slope_at(&self, v: f64, neg_dp_dv: f64, iterations: usize) -> DensitySlope {
        DensitySlope {
            rho: self.rho0 / v,
            dp_drho: neg_dp_dv * v * v / self.rho0,
            iterations,
        }
    }

    /// κ_T = 1/(ρ ∂p/∂ρ|_T).
    pub fn isothermal_compressibility(
        &self,
        name: &'static str,
        p: f64,
        t: f64,
    ) -> Result<f64, EosError> {
        let s = self.density_and_slope(name, p, t)?;
        Ok(1.0 / (s.rho * s.dp_drho))
    }

    /// α = (1/ρ)(∂p/∂T|_ρ)/(∂p/∂ρ|_T) = ω c_v / ∂p/∂ρ|_T.
    pub fn thermal_expansivity(&self, name: &'static str, p: f64, t: f64) -> Result<f64, EosError> {
        let s = self.density_and_slope(name, p, t)?;
        Ok(self.omega * self.cv / s.dp_drho)
    }

    /// ρ, κ_T and α from one inversion: the same operations as
    /// [`Self::density`], [`Self::isothermal_compressibility`] and
    /// [`Self::thermal_expansivity`], so the same bits.
    pub fn density_and_derivatives(
        &self,
        name: &'static str,
        p: f64,
        t: f64,
    ) -> Result<(f64, f64, f64), EosError> {
        let s = self.density_and_slope(name, p, t)?;
        Ok((
            s.rho,
            1.0 / (s.rho * s.dp_drho),
            self.omega * self.cv / s.dp_drho,
        ))
    }
}

/// ρ(p, T) of the JWL forms with the isothermal slope there.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct DensitySlope {
    /// ρ, kg/m³.
    pub rho: f64,
    /// ∂p/∂ρ|_T at ρ, Pa·m³/kg.
    pub dp_drho: f64,
    /// Newton iterations spent (0: the closed form p/(ωc_vT) was exact).
    pub iterations: usize,
}

/// Newton iterations of [`JwlCold::density_and_slope`] before it reports
/// no convergence (it needs at most 7 over p ∈ [10³, 10¹¹] Pa,
/// T ∈ [10², 10⁵] K for the shipped products, 10 up to 10¹² Pa and
/// down to 10 K).
const DENSITY_MAX_ITERATIONS: usize = 100;

/// Below this argument e^x < 3.3 × 10⁻³⁰⁸ (subnormal or zero) and is taken
/// as 0: multiplied by A or B (≤ 10¹² Pa) it is below 10⁻²⁹⁵ Pa, far under
/// the round-off of any pressure the solvers carry, and it spares `exp`'s
/// slow underflow path.
pub const EXP_FLUSH: f64 = -708.0;

/// e^x for the decaying exponentials of the JWL isentrope, with arguments
/// below [`EXP_FLUSH`] flushed to 0. Public so that solvers which evaluate
/// the JWL terms themselves (the FDM's mixture law) take the same bits.
#[inline]
pub fn decaying_exp(x: f64) -> f64 {
    if x < EXP_FLUSH {
        0.0
    } else {
        exp_not_speculated(x)
    }
}

/// `x.exp()` behind a call the optimiser may not hoist above the branch of
/// [`decaying_exp`]: the `exp` intrinsic is marked speculatable, and LLVM
/// turned the branch into a select that evaluated `exp` (on its slow
/// underflow path) and then discarded it.
#[inline(never)]
fn exp_not_speculated(x: f64) -> f64 {
    x.exp()
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

            #[inline]
            fn sound_speed_squared(&self, rho: f64, e: f64) -> f64 {
                self.cold().sound_speed_squared(rho, e)
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

            fn density_and_derivatives(
                &self,
                p: f64,
                t: f64,
            ) -> Result<(f64, f64, f64), brisance_core::EosError> {
                self.cold().density_and_derivatives($name, p, t)
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
    fn fused_density_and_derivatives_equal_the_three_calls_to_the_bit() {
        // One inversion serves ρ, κ_T and α; over p ∈ [10³, 10¹¹] Pa and
        // T ∈ [10², 10⁴] K for both forms, and the error for p ≤ 0.
        let forms: [&dyn Eos; 3] = [
            &Jwl::tnt(),
            &crate::JwlCTerm::anfo_k1(),
            &crate::JwlCTerm::qm100(),
        ];
        for eos in forms {
            for i in 0..=16 {
                for j in 0..=4 {
                    let p = 10f64.powf(3.0 + 0.5 * f64::from(i));
                    let t = 10f64.powf(2.0 + 0.5 * f64::from(j));
                    let (rho, kappa, alpha) = eos.density_and_derivatives(p, t).unwrap();
                    assert_eq!(rho.to_bits(), eos.density(p, t).unwrap().to_bits());
                    let k = eos.isothermal_compressibility(p, t).unwrap();
                    assert_eq!(kappa.to_bits(), k.to_bits());
                    let a = eos.thermal_expansivity(p, t).unwrap();
                    assert_eq!(alpha.to_bits(), a.to_bits());
                }
            }
            assert_eq!(
                eos.density_and_derivatives(-1.0, 300.0).unwrap_err(),
                eos.density(-1.0, 300.0).unwrap_err()
            );
        }
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

    /// The kernels of the shipped products: TNT (seed 001), ANFO-K1 and
    /// QM-100 (seed 000 §5.1, §5.2; the C term does not enter ρ(p, T)).
    fn kernels() -> [JwlCold; 3] {
        let of = |c: crate::JwlCTerm| JwlCold {
            a: c.a,
            b: c.b,
            r1: c.r1,
            r2: c.r2,
            omega: c.omega,
            rho0: c.rho0,
            cv: c.cv,
        };
        [
            Jwl::tnt().cold(),
            of(crate::JwlCTerm::anfo_k1()),
            of(crate::JwlCTerm::qm100()),
        ]
    }

    /// The inversion this module used before the convex-Newton one: Newton
    /// in ρ safeguarded by bisection from the bracket [p/(2ωc_vT),
    /// p/(ωc_vT)], stopped when a step is within 4 ulp. Kept as the
    /// reference the new one must reproduce.
    fn density_by_bisection_newton(j: &JwlCold, p: f64, t: f64) -> f64 {
        let f = |rho: f64| j.pressure(j.rho0 / rho) + j.omega * rho * j.cv * t - p;
        let mut hi = p / (j.omega * j.cv * t);
        let mut lo = 0.5 * hi;
        while f(lo) > 0.0 {
            hi = lo;
            lo *= 0.5;
        }
        let mut rho = 0.5 * (lo + hi);
        for _ in 0..200 {
            let r = f(rho);
            if r > 0.0 {
                hi = rho;
            } else {
                lo = rho;
            }
            let mut next = rho - r / j.dp_drho_at_t(rho, t);
            if !(next > lo && next < hi) {
                next = 0.5 * (lo + hi);
            }
            if (next - rho).abs() <= 4.0 * f64::EPSILON * rho || hi - lo <= 4.0 * f64::EPSILON * hi
            {
                return next;
            }
            rho = next;
        }
        panic!("reference inversion did not converge at p = {p}, T = {t}");
    }

    /// p_c(ρ₀/ρ) + ωρc_vT, the thermal form the inversion solves.
    fn thermal_form(j: &JwlCold, rho: f64, t: f64) -> f64 {
        j.pressure(j.rho0 / rho) + j.omega * rho * j.cv * t
    }

    #[test]
    fn sound_speed_is_the_default_formula_bit_for_bit() {
        // The trait's default c² = ∂p/∂ρ|ₑ + (p/ρ²)∂p/∂e|ρ from the
        // separate methods, against the one-pass override.
        for j in kernels() {
            for rho in [0.5, 1.1, 20.0, 400.0, 1160.0, 1630.0, 2500.0] {
                for e in [1.0e5, 1.0e6, 4.0e6, 1.0e7] {
                    let p = j.total_pressure(rho, e);
                    let default = j.dp_drho(rho, e) + p / (rho * rho) * (j.omega * rho);
                    assert_eq!(j.sound_speed_squared(rho, e), default, "ρ = {rho}, e = {e}");
                }
            }
        }
        // Large expansion: the γ-law gas with γ = 1 + ω, c² = γ(γ − 1)e.
        let j = Jwl::tnt();
        let c2 = j.sound_speed_squared(0.5, 1.0e6);
        assert!((c2 - 1.3 * 0.3 * 1.0e6).abs() < 1e-9 * c2, "{c2}");
    }

    #[test]
    fn expanded_products_take_the_closed_form_without_iterating() {
        // TNT at 10⁵ Pa, 300 K: ρ = p/(ωc_vT) = 10⁵·1630/(0.3·10⁶·300)
        // = 1.81111… kg/m³, V = 900, e^{−R₂V} = e^{−855} underflows.
        let j = Jwl::tnt().cold();
        let s = j.density_and_slope("jwl", 1.0e5, 300.0).unwrap();
        assert_eq!(s.iterations, 0);
        assert!(
            (s.rho - 1.63e8 / 9.0e7).abs() <= 2.0 * f64::EPSILON * s.rho,
            "{s:?}"
        );
        // ∂p/∂ρ|_T = ωc_vT = 0.3·(10⁶/1630)·300 = 55 214.72 Pa·m³/kg.
        assert!((s.dp_drho - 9.0e7 / 1630.0).abs() <= 1e-12 * s.dp_drho);
    }

    #[test]
    fn compressed_products_invert_to_the_hand_density() {
        // TNT at ρ = ρ₀ (V = 1), T = 1000 K:
        // p = 3.712e11 e^{−4.15} + 3.21e9 e^{−0.95} + 0.3·(10⁶/1630)·1000·1630
        //   = 5.85175e9 + 1.24144e9 + 3.0e8 = 7.39319e9 Pa.
        let j = Jwl::tnt().cold();
        let p = 3.712e11 * (-4.15f64).exp() + 3.21e9 * (-0.95f64).exp() + 3.0e8;
        assert!((p - 7.39319e9).abs() < 1e-5 * p, "p = {p}");
        let s = j.density_and_slope("jwl", p, 1000.0).unwrap();
        assert!((s.rho - 1630.0).abs() <= 1e-14 * 1630.0, "{s:?}");
        assert!(s.iterations > 0 && s.iterations <= 7, "{s:?}");
        // ∂p/∂ρ|_T = (V/ρ)(A R₁ e^{−R₁} ... ) + ωc_vT at V = 1.
        let slope = (3.712e11 * 4.15 * (-4.15f64).exp() + 3.21e9 * 0.95 * (-0.95f64).exp())
            / 1630.0
            + 3.0e8 / 1630.0;
        assert!(
            (s.dp_drho - slope).abs() <= 1e-13 * slope,
            "{} vs {slope}",
            s.dp_drho
        );
        // ANFO-K1 products at 2 GPa and 3000 K, the ICE bench's sphere:
        // the old bisection–Newton inversion gives the same density.
        let anfo = kernels()[1];
        let rho = anfo.density("jwl_cterm", 2.0e9, 3000.0).unwrap();
        let reference = density_by_bisection_newton(&anfo, 2.0e9, 3000.0);
        assert!(
            (rho - reference).abs() <= 1e-14 * reference,
            "{rho} vs {reference}"
        );
        assert!((thermal_form(&anfo, rho, 3000.0) / 2.0e9 - 1.0).abs() < 1e-14);
    }

    #[test]
    fn inversion_converges_within_seven_iterations_over_the_working_range() {
        // p from 1 kPa to 1 TPa, T from 10 K to 10⁵ K, every shipped set:
        // the reference's answer everywhere, at most 7 iterations for
        // p ≤ 100 GPa and T ≥ 100 K (up to 10 beyond, at ρ ≫ ρ₀).
        let mut worst = 0;
        for j in kernels() {
            for ip in 0..=36 {
                for it in 0..=40 {
                    let p = 10f64.powf(3.0 + 0.25 * ip as f64);
                    let t = 10f64.powf(1.0 + 0.1 * it as f64);
                    let s = j.density_and_slope("jwl", p, t).unwrap();
                    if p <= 1.01e11 && t >= 99.0 {
                        worst = worst.max(s.iterations);
                    }
                    let reference = density_by_bisection_newton(&j, p, t);
                    assert!(
                        (s.rho - reference).abs() <= 1e-14 * reference,
                        "p = {p}, T = {t}: {} vs {reference}",
                        s.rho
                    );
                }
            }
        }
        assert!(worst <= 7, "{worst} iterations");
    }

    #[test]
    fn inversion_rejects_what_it_cannot_invert() {
        let j = Jwl::tnt().cold();
        for (p, t) in [
            (0.0, 300.0),
            (-1.0, 300.0),
            (f64::NAN, 300.0),
            (1.0e9, 0.0),
            (1.0e9, f64::INFINITY),
            // p/(ωc_vT) overflows or underflows to 0.
            (1.0e300, 1.0e-300),
            (1.0e-320, 1.0e10),
        ] {
            let err = j.density("jwl", p, t).unwrap_err();
            assert!(
                matches!(err, EosError::OutOfRange { .. }),
                "p = {p}, T = {t}: {err}"
            );
        }
    }

    mod inversion_proptests {
        use super::*;
        use proptest::prelude::*;

        proptest! {
            /// p(ρ(p, T), T) = p, for the thermal form and through the
            /// `Eos` (ρ, e) → p map, the slope is ∂p/∂ρ|_T at the root,
            /// and the answer is the reference inversion's.
            #[test]
            fn density_inverts_the_pressure(
                which in 0usize..3,
                log_p in 3.0f64..12.0,
                log_t in 1.0f64..5.0,
            ) {
                let j = kernels()[which];
                let (p, t) = (10f64.powf(log_p), 10f64.powf(log_t));
                let s = j.density_and_slope("jwl", p, t).unwrap();
                prop_assert!((thermal_form(&j, s.rho, t) / p - 1.0).abs() < 1e-14,
                    "thermal form {} vs {}", thermal_form(&j, s.rho, t), p);
                let e = j.energy(j.rho0 / s.rho) + j.cv * t;
                prop_assert!((j.total_pressure(s.rho, e) / p - 1.0).abs() < 1e-12);
                let slope = j.dp_drho_at_t(s.rho, t);
                prop_assert!((s.dp_drho / slope - 1.0).abs() < 1e-14, "{} vs {}", s.dp_drho, slope);
                // Two roots good to an ulp of p differ in ρ by about that
                // ulp over d ln p / d ln ρ, which falls to 10⁻² where the
                // products are compressed far beyond any physical state
                // (ρ ~ 10⁶ kg/m³ at 4·10¹¹ Pa and 10 K): the bound follows
                // that conditioning, and is 10⁻¹⁴ elsewhere.
                let reference = density_by_bisection_newton(&j, p, t);
                let conditioning = s.dp_drho * s.rho / p;
                let bound = 1e-14_f64.max(4.0 * f64::EPSILON / conditioning);
                prop_assert!((s.rho / reference - 1.0).abs() <= bound,
                    "{} vs {} (d ln p/d ln ρ = {conditioning})", s.rho, reference);
            }
        }
    }

    brisance_core::eos_contract_tests!(jwl_tnt, Jwl::tnt(), rho: 20.0..3000.0, t: 100.0..8000.0);
    brisance_core::eos_contract_tests!(jwl_tnt_energy_box, Jwl::tnt(), rho: 100.0..2600.0, e: 1.0e7..5.0e7);
}
