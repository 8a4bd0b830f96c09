//! The pressure isentrope of detonation products as a function of the
//! expansion X = v/v₀ = ρ₀/ρ (seed 004 eq 11), with the reference pressure
//! P_S0 = P_S(1) fixed by the volume-burn algorithm (seed 004 eqs 20–21).
//!
//! - Ideal gas, seed 004 eq 29: P_S(X) = P_S0 X^{−γ}.
//! - JWL, seed 004 eq 30: P_S(X) = A e^{−R₁X} + B e^{−R₂X} + C X^{−(ω+1)},
//!   with C chosen so that the isentrope carries the volume-burn energy
//!   (C = P_S0 − A e^{−R₁} − B e^{−R₂}).
//!
//! The energy per unit *reference* volume stored in the products at X is
//! W(X) = ∫_X^∞ P_S(X′) dX′ (from de = −P dv with v = X v₀): the energy the
//! gas gives up expanding to infinity, and the W of seed 004 eqs 13–18.

use brisance_eos::tools::{chapman_jouguet, volume_burn_reference, CjState, UnreactedState};
use brisance_eos::{IdealGas, Jwl, JwlCTerm};
use serde::{Deserialize, Serialize};

/// Why an isentrope cannot be built.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ProductsError {
    /// A parameter is out of range; names the field.
    #[error("detonation products: `{field}`: {message}")]
    InvalidInput {
        /// The offending field.
        field: &'static str,
        /// What is wrong.
        message: String,
    },
    /// The CJ state or the volume-burn equation had no solution.
    #[error("detonation products: {0}")]
    Tool(#[from] brisance_eos::tools::ToolError),
}

/// A products isentrope P_S(X).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub enum ProductsIsentrope {
    /// Seed 004 eq 29.
    IdealGas {
        /// Ratio of specific heats γ.
        gamma: f64,
        /// P_S0, Pa.
        reference_pressure: f64,
    },
    /// Seed 004 eq 30.
    Jwl {
        /// A, Pa.
        a: f64,
        /// B, Pa.
        b: f64,
        /// R₁.
        r1: f64,
        /// R₂.
        r2: f64,
        /// ω.
        omega: f64,
        /// C, Pa.
        c: f64,
    },
}

impl ProductsIsentrope {
    /// The JWL products isentrope of `jwl` through the volume-burn reference
    /// state, with the CJ state it was derived from (its detonation velocity
    /// is what program burn uses unless the input overrides it).
    pub fn from_jwl(jwl: &Jwl) -> Result<(Self, CjState), ProductsError> {
        jwl.validate()
            .map_err(|message| ProductsError::InvalidInput {
                field: "jwl",
                message,
            })?;
        let unreacted = UnreactedState {
            density: jwl.rho0,
            specific_internal_energy: jwl.specific_detonation_energy(),
            pressure: 0.0,
        };
        let cj = chapman_jouguet(jwl, &unreacted)?;
        let vb = volume_burn_reference(jwl, &cj, 1e-11)?;
        let c = jwl.isentrope_constant(jwl.rho0, vb.reference_energy);
        Ok((
            ProductsIsentrope::Jwl {
                a: jwl.a,
                b: jwl.b,
                r1: jwl.r1,
                r2: jwl.r2,
                omega: jwl.omega,
                c,
            },
            cj,
        ))
    }

    /// The products isentrope of JWL++'s C-term products (seed 000 §5.2,
    /// Souers et al. 2000), whose pressure is a function of the volume
    /// alone: their reference isentrope A e^{−R₁X} + B e^{−R₂X} + C
    /// X^{−(ω+1)} is seed 004 eq 30 term for term, taken as printed (P_S0 =
    /// P_S(1), the products of a volume burn at the explosive's density),
    /// with the CJ state where the Rayleigh line from the unreacted state
    /// touches it (`cj_on_jwl_cterm_isentrope`).
    pub fn from_jwl_cterm(products: &JwlCTerm) -> Result<(Self, CjState), ProductsError> {
        let cj = brisance_eos::tools::cj_on_jwl_cterm_isentrope(products)?;
        Ok((
            ProductsIsentrope::Jwl {
                a: products.a,
                b: products.b,
                r1: products.r1,
                r2: products.r2,
                omega: products.omega,
                c: products.c,
            },
            cj,
        ))
    }

    /// The ideal-gas products isentrope (γ-law products of an explosive of
    /// density `rho0` releasing `heat` J/kg), P_S0 from the volume burn (half
    /// the CJ pressure, seed 004 after eq 21), with its CJ state.
    pub fn ideal_gas(gamma: f64, rho0: f64, heat: f64) -> Result<(Self, CjState), ProductsError> {
        let check = |field, v: f64| {
            if v.is_finite() && v > 0.0 {
                Ok(())
            } else {
                Err(ProductsError::InvalidInput {
                    field,
                    message: format!("expected a finite value > 0, got {v}"),
                })
            }
        };
        check("gamma", gamma - 1.0)?;
        check("density", rho0)?;
        check("heat", heat)?;
        let gas = IdealGas::new(gamma, 1.0, rho0);
        let unreacted = UnreactedState {
            density: rho0,
            specific_internal_energy: heat,
            pressure: 0.0,
        };
        let cj = chapman_jouguet(&gas, &unreacted)?;
        let vb = volume_burn_reference(&gas, &cj, 1e-11)?;
        Ok((
            ProductsIsentrope::IdealGas {
                gamma,
                reference_pressure: vb.reference_pressure,
            },
            cj,
        ))
    }

    /// P_S(X), Pa (seed 004 eqs 29–30).
    #[inline]
    pub fn pressure(&self, x: f64) -> f64 {
        match *self {
            ProductsIsentrope::IdealGas {
                gamma,
                reference_pressure,
            } => reference_pressure * x.powf(-gamma),
            ProductsIsentrope::Jwl {
                a,
                b,
                r1,
                r2,
                omega,
                c,
            } => a * (-r1 * x).exp() + b * (-r2 * x).exp() + c * x.powf(-(omega + 1.0)),
        }
    }

    /// dP_S/dX, Pa.
    #[inline]
    pub fn dpressure_dx(&self, x: f64) -> f64 {
        match *self {
            ProductsIsentrope::IdealGas {
                gamma,
                reference_pressure,
            } => -gamma * reference_pressure * x.powf(-gamma - 1.0),
            ProductsIsentrope::Jwl {
                a,
                b,
                r1,
                r2,
                omega,
                c,
            } => {
                -a * r1 * (-r1 * x).exp()
                    - b * r2 * (-r2 * x).exp()
                    - (omega + 1.0) * c * x.powf(-(omega + 2.0))
            }
        }
    }

    /// W(X) = ∫_X^∞ P_S dX′, energy per unit reference volume, J/m³.
    #[inline]
    pub fn energy(&self, x: f64) -> f64 {
        match *self {
            ProductsIsentrope::IdealGas {
                gamma,
                reference_pressure,
            } => reference_pressure * x.powf(1.0 - gamma) / (gamma - 1.0),
            ProductsIsentrope::Jwl {
                a,
                b,
                r1,
                r2,
                omega,
                c,
            } => a / r1 * (-r1 * x).exp() + b / r2 * (-r2 * x).exp() + c / omega * x.powf(-omega),
        }
    }

    /// P_S0 = P_S(1), Pa.
    pub fn reference_pressure(&self) -> f64 {
        self.pressure(1.0)
    }

    /// Bulk modulus of the products along the isentrope at X, −X dP/dX, Pa.
    pub fn bulk_modulus(&self, x: f64) -> f64 {
        -x * self.dpressure_dx(x)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ideal_gas_reference_pressure_is_half_the_cj_pressure() {
        let (iso, cj) = ProductsIsentrope::ideal_gas(3.0, 1630.0, 4.29e6).unwrap();
        assert!((iso.reference_pressure() / cj.pressure - 0.5).abs() < 1e-6);
        // Strong-detonation CJ of a γ-law gas: D² = 2(γ² − 1) q.
        let d = (2.0 * (9.0 - 1.0) * 4.29e6f64).sqrt();
        assert!((cj.detonation_velocity - d).abs() < 1e-6 * d);
        // P_S(2) = P_S0 / 8 for γ = 3.
        assert!((iso.pressure(2.0) - iso.reference_pressure() / 8.0).abs() < 1e-6);
    }

    /// QM-100's C-term products (seed 000 §5.2): the isentrope is the
    /// printed one term for term, P_S(1) = A e^{−5} + B e^{−1} + C =
    /// 3.281515e9 + 0.937677e9 + 0.506568e9 = 4.725760e9 Pa by hand, and
    /// the CJ point lies on it where the Rayleigh line from (X = 1, P = 0)
    /// is tangent: P_S(X_CJ) = ρ₀D²(1 − X_CJ) and −dP_S/dX = ρ₀D² there.
    #[test]
    fn qm100_cterm_isentrope_is_the_printed_one_with_its_cj_point() {
        let q = JwlCTerm::qm100();
        let (iso, cj) = ProductsIsentrope::from_jwl_cterm(&q).unwrap();
        let p1 = iso.reference_pressure();
        assert!((p1 / 4.725_760e9 - 1.0).abs() < 1e-6, "{p1}");
        for x in [0.7, 1.0, 2.2, 7.0] {
            let (a, b) = (iso.pressure(x), q.isentrope_pressure(x));
            assert!((a - b).abs() <= 1e-12 * b, "{x}: {a} vs {b}");
        }
        let x = cj.relative_volume;
        let rho_d2 = q.rho0 * cj.detonation_velocity.powi(2);
        assert!((iso.pressure(x) / (rho_d2 * (1.0 - x)) - 1.0).abs() < 1e-6);
        assert!((-iso.dpressure_dx(x) / rho_d2 - 1.0).abs() < 1e-5);
        assert!((cj.pressure / iso.pressure(x) - 1.0).abs() < 1e-6);
    }

    #[test]
    fn tnt_jwl_isentrope_starts_at_the_volume_burn_pressure() {
        let (iso, cj) = ProductsIsentrope::from_jwl(&Jwl::tnt()).unwrap();
        // eos::tools::volume_burn: P_S0 = p(ρ₀, e₀) = 8.37604e9 Pa for TNT.
        assert!((iso.reference_pressure() - 8.37604e9).abs() < 1e-5 * 8.37604e9);
        // W(1) is the detonation energy E₀ = 6.993e9 J/m³: the left side of
        // eq 20 reduces to e₀ for p₀ = 0.
        assert!(
            (iso.energy(1.0) - 6.993e9).abs() < 1e-5 * 6.993e9,
            "{}",
            iso.energy(1.0)
        );
        assert!((cj.detonation_velocity - 6930.0).abs() < 0.03 * 6930.0);
    }

    #[test]
    fn energy_and_pressure_derivatives_are_consistent() {
        let isos = [
            ProductsIsentrope::from_jwl(&Jwl::tnt()).unwrap().0,
            ProductsIsentrope::ideal_gas(1.4, 1000.0, 4.0e6).unwrap().0,
        ];
        for iso in isos {
            for &x in &[0.8, 1.0, 2.5, 7.0] {
                let h = 1e-6 * x;
                let dw = (iso.energy(x + h) - iso.energy(x - h)) / (2.0 * h);
                assert!(
                    (dw + iso.pressure(x)).abs() < 1e-6 * iso.pressure(x),
                    "{iso:?} X = {x}"
                );
                let dp = (iso.pressure(x + h) - iso.pressure(x - h)) / (2.0 * h);
                assert!(
                    (dp - iso.dpressure_dx(x)).abs() < 1e-6 * dp.abs(),
                    "{iso:?}"
                );
            }
        }
    }

    #[test]
    fn bad_parameters_name_the_field() {
        let e = ProductsIsentrope::ideal_gas(0.9, 1000.0, 1e6).unwrap_err();
        assert!(matches!(
            e,
            ProductsError::InvalidInput { field: "gamma", .. }
        ));
        let mut j = Jwl::tnt();
        j.r1 = -1.0;
        assert!(ProductsIsentrope::from_jwl(&j).is_err());
    }
}
