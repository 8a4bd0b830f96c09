//! Flow stress σ_y of a von Mises (J2) metal: constant (perfectly plastic)
//! or Johnson–Cook.
//!
//! Johnson–Cook, seed 000 eqs 41–42 (σ₀ = A) and seed 001 eq 64:
//!
//! σ_y = (A + B ε_pⁿ)(1 + C ln ε̇*)(1 − T*ᵐ),
//! ε̇* = ε̇_p/ε̇₀,  T* = (T − T_room)/(T_melt − T_room).
//!
//! Two guards keep the formula defined everywhere, as seed 001 §4.5 states
//! T* ∈ [0, 1]: T* is clamped to [0, 1] (below room temperature the flow
//! stress stays at its room value; at and above T_melt it is zero — the
//! melted metal carries no shear), and ε̇* is clamped to ≥ 1 so that the
//! rate factor is never below one (ln of a rate below the reference would
//! soften the metal without bound as ε̇_p → 0, and at zero rate be −∞).

use crate::{error::positive, ConstitutiveError};
use serde::{Deserialize, Serialize};

const NAME: &str = "flow_stress";

/// The flow stress of a J2 metal.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub enum FlowStress {
    /// Perfect plasticity at a constant yield stress (the OFHC copper of
    /// seed 000 §5.2, σ_y = 70 MPa).
    Constant {
        /// Yield stress σ_y, Pa.
        sigma_y: f64,
    },
    /// Johnson–Cook, seed 000 eqs 41–42, seed 001 eq 64.
    JohnsonCook {
        /// Yield stress at zero plastic strain A (σ₀), Pa.
        a: f64,
        /// Hardening modulus B, Pa.
        b: f64,
        /// Hardening exponent n.
        n: f64,
        /// Strain-rate coefficient C.
        c: f64,
        /// Thermal-softening exponent m.
        m: f64,
        /// Reference plastic strain rate ε̇₀, 1/s.
        eps_dot0: f64,
        /// Room (reference) temperature T_room (T₀), K.
        t_room: f64,
        /// Melt temperature T_melt (T_m), K.
        t_melt: f64,
    },
}

/// Homologous temperature T* = (T − T_room)/(T_melt − T_room), clamped to
/// [0, 1] (seed 000 eq 42, seed 001 §4.5).
#[inline]
pub fn homologous_temperature(t: f64, t_room: f64, t_melt: f64) -> f64 {
    ((t - t_room) / (t_melt - t_room)).clamp(0.0, 1.0)
}

impl FlowStress {
    /// Johnson–Cook for 4340 steel, seed 000 Table 1: A = 792 MPa,
    /// B = 510 MPa, n = 0.26, C = 0.014, m = 1.03, T₀ = 294 K,
    /// T_m = 1793 K; ε̇₀ = 1 s⁻¹ (the reference rate of Johnson & Cook 1983,
    /// which the table does not list).
    pub fn steel_4340_seed000() -> Self {
        Self::JohnsonCook {
            a: 792.0e6,
            b: 510.0e6,
            n: 0.26,
            c: 0.014,
            m: 1.03,
            eps_dot0: 1.0,
            t_room: 294.0,
            t_melt: 1793.0,
        }
    }

    /// Johnson–Cook for RHA steel, seed 001 §4.5 (from Neuberger, Peles &
    /// Rittel 2007): A = 950 MPa, B = 560 MPa, n = 0.26, C = 0.014, m = 1,
    /// ε̇₀ = 1 s⁻¹. Seed 001 gives no temperatures: T_room = 300 K and
    /// T_melt = 1793 K (the steel melt temperature of Johnson & Cook 1983,
    /// as for 4340 in seed 000 Table 1).
    pub fn rha_steel_seed001() -> Self {
        Self::JohnsonCook {
            a: 950.0e6,
            b: 560.0e6,
            n: 0.26,
            c: 0.014,
            m: 1.0,
            eps_dot0: 1.0,
            t_room: 300.0,
            t_melt: 1793.0,
        }
    }

    /// Johnson–Cook for OFHC copper, Johnson & Cook, *A constitutive model
    /// and data for metals subjected to large strains, high strain rates and
    /// high temperatures*, Proc. 7th Int. Symp. Ballistics (1983) 541–547
    /// (seed 000 ref \[31\]): A = 90 MPa, B = 292 MPa, n = 0.31, C = 0.025,
    /// m = 1.09, T_melt = 1356 K, ε̇₀ = 1 s⁻¹, T_room = 294 K.
    pub fn ofhc_copper_johnson_cook_1983() -> Self {
        Self::JohnsonCook {
            a: 90.0e6,
            b: 292.0e6,
            n: 0.31,
            c: 0.025,
            m: 1.09,
            eps_dot0: 1.0,
            t_room: 294.0,
            t_melt: 1356.0,
        }
    }

    /// Checks the parameters; the message names the bad field.
    pub fn validate(&self) -> Result<(), ConstitutiveError> {
        match *self {
            Self::Constant { sigma_y } => positive(NAME, "sigma_y", sigma_y),
            Self::JohnsonCook {
                a,
                b,
                n,
                c,
                m,
                eps_dot0,
                t_room,
                t_melt,
            } => {
                positive(NAME, "a", a)?;
                crate::error::non_negative(NAME, "b", b)?;
                positive(NAME, "n", n)?;
                crate::error::non_negative(NAME, "c", c)?;
                positive(NAME, "m", m)?;
                positive(NAME, "eps_dot0", eps_dot0)?;
                positive(NAME, "t_room", t_room)?;
                positive(NAME, "t_melt", t_melt)?;
                if !(t_melt > t_room) {
                    return Err(ConstitutiveError::InvalidParameter {
                        model: NAME,
                        field: "t_melt",
                        value: t_melt,
                        expected: "a melt temperature above `t_room`, K",
                    });
                }
                Ok(())
            }
        }
    }

    /// Melt temperature, K, where the model has one.
    pub fn melt_temperature(&self) -> Option<f64> {
        match *self {
            Self::Constant { .. } => None,
            Self::JohnsonCook { t_melt, .. } => Some(t_melt),
        }
    }

    /// Flow stress σ_y(ε_p, ε̇_p, T), Pa (seed 000 eqs 41–42).
    #[inline]
    pub fn flow_stress(&self, eps_p: f64, eps_p_rate: f64, t: f64) -> f64 {
        self.flow_stress_and_slope(eps_p, eps_p_rate, 0.0, t).0
    }

    /// Partial derivatives of the flow stress at (ε_p, ε̇_p, T):
    /// (∂σ_y/∂ε_p, ∂σ_y/∂T), Pa and Pa/K, at fixed rate.
    ///
    /// Constant: (0, 0). Johnson–Cook: ∂σ_y/∂ε_p = B n ε_pⁿ⁻¹ R Θ (+∞ at
    /// ε_p = 0 when n < 1) and ∂σ_y/∂T = −(A + B ε_pⁿ) R m T*ᵐ⁻¹/(T_melt −
    /// T_room) for 0 < T* < 1, zero where T* is clamped (the clamped flow
    /// stress is flat there), with R the rate factor and Θ = 1 − T*ᵐ. Both
    /// are zero for a melted point (Θ = 0).
    pub fn partial_derivatives(&self, eps_p: f64, eps_p_rate: f64, t: f64) -> (f64, f64) {
        match *self {
            Self::Constant { .. } => (0.0, 0.0),
            Self::JohnsonCook {
                a,
                b,
                n,
                c,
                m,
                eps_dot0,
                t_room,
                t_melt,
            } => {
                let eps = eps_p.max(0.0);
                let rate_star = eps_p_rate / eps_dot0;
                let rate = if rate_star > 1.0 {
                    1.0 + c * rate_star.ln()
                } else {
                    1.0
                };
                let t_star = homologous_temperature(t, t_room, t_melt);
                let thermal = 1.0 - t_star.powf(m);
                if thermal <= 0.0 {
                    return (0.0, 0.0);
                }
                let d_eps = if eps > 0.0 {
                    b * n * eps.powf(n - 1.0) * rate * thermal
                } else if b > 0.0 && n < 1.0 {
                    f64::INFINITY
                } else if b > 0.0 && n == 1.0 {
                    b * rate * thermal
                } else {
                    0.0
                };
                let d_t = if t_star > 0.0 && t_star < 1.0 {
                    -(a + b * eps.powf(n)) * rate * m * t_star.powf(m - 1.0) / (t_melt - t_room)
                } else {
                    0.0
                };
                (d_eps, d_t)
            }
        }
    }

    /// σ_y and its derivative along a return-mapping increment: with
    /// ε_p = ε_pⁿ + Δε and ε̇_p = Δε/Δt, returns (σ_y, dσ_y/dΔε) where
    /// `inv_dt` = 1/Δt (0 for no rate coupling). Pa and Pa.
    #[inline]
    pub fn flow_stress_and_slope(
        &self,
        eps_p: f64,
        eps_p_rate: f64,
        inv_dt: f64,
        t: f64,
    ) -> (f64, f64) {
        match *self {
            Self::Constant { sigma_y } => (sigma_y, 0.0),
            Self::JohnsonCook {
                a,
                b,
                n,
                c,
                m,
                eps_dot0,
                t_room,
                t_melt,
            } => {
                let eps = eps_p.max(0.0);
                let hardening = a + b * eps.powf(n);
                let d_hardening = if eps > 0.0 {
                    b * n * eps.powf(n - 1.0)
                } else {
                    f64::INFINITY
                };
                let rate_star = eps_p_rate / eps_dot0;
                let (rate, d_rate) = if rate_star > 1.0 {
                    // d/dΔε [1 + C ln(Δε/(Δt ε̇₀))] = C/Δε = C inv_dt/ε̇_p.
                    (1.0 + c * rate_star.ln(), c * inv_dt / eps_p_rate)
                } else {
                    (1.0, 0.0)
                };
                let thermal = 1.0 - homologous_temperature(t, t_room, t_melt).powf(m);
                let sigma = hardening * rate * thermal;
                let slope = if thermal > 0.0 {
                    (d_hardening * rate + hardening * d_rate) * thermal
                } else {
                    0.0
                };
                (sigma, slope)
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn johnson_cook_4340_matches_hand_computed_values() {
        let jc = FlowStress::steel_4340_seed000();
        // Room temperature, reference rate, ε_p = 0: σ_y = A.
        assert!((jc.flow_stress(0.0, 0.0, 294.0) - 792.0e6).abs() < 1e-6);
        // ε_p = 0.1, ε̇ = 1000/s, T = 294 + 0.5 × 1499 = 1043.5 K:
        // (792 + 510 × 0.1^0.26)(1 + 0.014 ln 1000)(1 − 0.5^1.03) MPa.
        let h = 792.0e6 + 510.0e6 * 0.1_f64.powf(0.26);
        let r = 1.0 + 0.014 * 1000.0_f64.ln();
        let th = 1.0 - 0.5_f64.powf(1.03);
        let got = jc.flow_stress(0.1, 1000.0, 1043.5);
        assert!((got - h * r * th).abs() < 1e-6 * got, "{got}");
        // Hand value: 0.1^0.26 = 0.549541, h = 1072.266 MPa, r = 1.096709,
        // th = 0.510290 → 600.08 MPa.
        assert!((got - 600.08e6).abs() < 0.01e6, "{got}");
    }

    #[test]
    fn johnson_cook_flow_stress_vanishes_at_and_above_melt() {
        let jc = FlowStress::ofhc_copper_johnson_cook_1983();
        assert_eq!(jc.flow_stress(0.3, 1e4, 1356.0), 0.0);
        assert_eq!(jc.flow_stress(0.3, 1e4, 2000.0), 0.0);
        assert!(jc.flow_stress(0.3, 1e4, 1300.0) > 0.0);
    }

    #[test]
    fn johnson_cook_rate_factor_is_at_least_one_and_cold_is_room() {
        let jc = FlowStress::rha_steel_seed001();
        let base = jc.flow_stress(0.05, 1.0, 300.0);
        assert_eq!(jc.flow_stress(0.05, 1e-3, 300.0), base);
        assert_eq!(jc.flow_stress(0.05, 0.0, 300.0), base);
        assert_eq!(jc.flow_stress(0.05, 1.0, 200.0), base);
    }

    #[test]
    fn johnson_cook_slope_matches_finite_difference() {
        let jc = FlowStress::steel_4340_seed000();
        let (eps_n, dt, t) = (0.02, 1e-7, 500.0);
        let de = 1e-4;
        let f = |x: f64| jc.flow_stress(eps_n + x, x / dt, t);
        let (_, slope) = jc.flow_stress_and_slope(eps_n + de, de / dt, 1.0 / dt, t);
        let h = 1e-9;
        let fd = (f(de + h) - f(de - h)) / (2.0 * h);
        assert!((slope - fd).abs() < 1e-5 * fd.abs(), "{slope} vs {fd}");
    }

    /// 4340 at ε_p = 0.1, ε̇ = 1000/s, T = 1043.5 K (T* = 0.5):
    /// ∂σ/∂ε = 510e6 × 0.26 × 0.1^(−0.74) × 1.096709 × 0.510290
    /// = 407.80 MPa; ∂σ/∂T = −1072.266e6 × 1.096709 × 1.03 × 0.5^0.03/1499
    /// = −0.79140 MPa/K. Both match central differences.
    #[test]
    fn partial_derivatives_match_hand_values_and_differences() {
        let jc = FlowStress::steel_4340_seed000();
        let (de, dt) = jc.partial_derivatives(0.1, 1000.0, 1043.5);
        let r = 1.0 + 0.014 * 1000.0_f64.ln();
        let th = 1.0 - 0.5_f64.powf(1.03);
        let h = 792.0e6 + 510.0e6 * 0.1_f64.powf(0.26);
        let de_hand = 510.0e6 * 0.26 * 0.1_f64.powf(-0.74) * r * th;
        let dt_hand = -h * r * 1.03 * 0.5_f64.powf(0.03) / 1499.0;
        assert!((de - de_hand).abs() < 1e-9 * de_hand, "{de}");
        assert!((dt - dt_hand).abs() < 1e-9 * dt_hand.abs(), "{dt}");
        assert!((de - 407.80e6).abs() < 0.01e6, "{de}");
        assert!((dt + 0.791_40e6).abs() < 0.000_01e6, "{dt}");
        let f = |e: f64, t: f64| jc.flow_stress(e, 1000.0, t);
        let fd_e = (f(0.1 + 1e-7, 1043.5) - f(0.1 - 1e-7, 1043.5)) / 2e-7;
        let fd_t = (f(0.1, 1043.5 + 1e-3) - f(0.1, 1043.5 - 1e-3)) / 2e-3;
        assert!((de - fd_e).abs() < 1e-6 * de, "{de} vs {fd_e}");
        assert!((dt - fd_t).abs() < 1e-6 * dt.abs(), "{dt} vs {fd_t}");
        // Flat where T* is clamped; zero for a melted point; constant σ_y.
        assert_eq!(jc.partial_derivatives(0.1, 1.0, 200.0).1, 0.0);
        assert_eq!(jc.partial_derivatives(0.1, 1.0, 1793.0), (0.0, 0.0));
        assert_eq!(jc.partial_derivatives(0.0, 1.0, 300.0).0, f64::INFINITY);
        let c = FlowStress::Constant { sigma_y: 1e8 };
        assert_eq!(c.partial_derivatives(0.3, 1e3, 500.0), (0.0, 0.0));
    }

    #[test]
    fn validate_names_the_bad_field() {
        let FlowStress::JohnsonCook {
            a,
            b,
            n,
            c,
            m,
            eps_dot0,
            t_room,
            ..
        } = FlowStress::steel_4340_seed000()
        else {
            unreachable!("a Johnson–Cook set")
        };
        let bad = FlowStress::JohnsonCook {
            a,
            b,
            n,
            c,
            m,
            eps_dot0,
            t_room,
            t_melt: 200.0,
        };
        let msg = bad.validate().unwrap_err().to_string();
        assert!(msg.contains("t_melt"), "{msg}");
        let msg = FlowStress::Constant { sigma_y: -1.0 }
            .validate()
            .unwrap_err()
            .to_string();
        assert!(msg.contains("sigma_y"), "{msg}");
    }
}
