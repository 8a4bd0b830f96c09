//! Volume-burn reference pressure, seed 004 eqs 20–21.
//!
//! Energy conservation for the detonation products (eq 20):
//!
//! ```text
//! ∫_{v₀}^{v_CJ} R(v) dv + ∫_{v_CJ}^{∞} P_DP(v) dv = ∫_{v_S0}^{∞} P_S(v) dv,
//! R(v) − P₀ = U²/v₀ − (U²/v₀²) v            (eq 21)
//! ```
//!
//! The first term is the (negative) work along the Rayleigh line from the
//! unreacted state to CJ, −P₀(v₀ − v_CJ) − ½(U/v₀)²(v₀ − v_CJ)², evaluated in
//! closed form; the second is the expansion work along the principal
//! isentrope from CJ to infinite volume; the right side is the expansion work
//! of the reference isentrope P_S through v_S0 = v₀ (seed 004's expansion
//! X = v/v₀ is 1 there, eqs 29–30), whose pressure at v₀ is the reference
//! pressure P_S0. Brisance solves eq 20 for the energy e_S0 of the reference
//! isentrope at v₀ (a secant iteration on the right side) and returns
//! P_S0 = p(ρ₀, e_S0). For an ideal gas the result is half the CJ pressure
//! (seed 004, text after eq 21).

use super::cj::CjState;
use super::isentrope::expansion_work_to_infinity;
use super::ToolError;
use brisance_core::Eos;

/// The volume-burn reference state.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct VolumeBurnReference {
    /// P_S0, Pa: pressure of the reference isentrope at the unreacted volume.
    pub reference_pressure: f64,
    /// e_S0, J/kg: energy of the reference isentrope at the unreacted volume.
    pub reference_energy: f64,
    /// ∫_{v₀}^{v_CJ} R dv, J/kg (negative).
    pub rayleigh_work: f64,
    /// ∫_{v_CJ}^{∞} P_DP dv along the principal isentrope, J/kg.
    pub principal_expansion_work: f64,
}

/// Solves seed 004 eq 20 for the reference isentrope of `products` at the
/// unreacted volume, given the CJ state `cj`.
pub fn volume_burn_reference<E: Eos + ?Sized>(
    products: &E,
    cj: &CjState,
    tolerance: f64,
) -> Result<VolumeBurnReference, ToolError> {
    let rho0 = cj.unreacted.density;
    let v0 = 1.0 / rho0;
    let dv = v0 * (1.0 - cj.relative_volume);
    let u = cj.detonation_velocity;
    // ∫_{v₀}^{v_CJ} [P₀ + (U²/v₀²)(v₀ − v)] dv (eq 21).
    let rayleigh_work = -cj.unreacted.pressure * dv - 0.5 * (u / v0).powi(2) * dv * dv;
    let principal =
        expansion_work_to_infinity(products, cj.density, cj.specific_internal_energy, tolerance)?;
    let target = rayleigh_work + principal;
    if !(target > 0.0) {
        return Err(ToolError::NoSolution {
            tool: "volume_burn",
            detail: format!("left side of eq 20 is {target} J/kg, not positive"),
        });
    }
    let residual = |e: f64| -> Result<f64, ToolError> {
        Ok(expansion_work_to_infinity(products, rho0, e, tolerance)? - target)
    };
    let (mut e_a, mut e_b) = (target, target * (1.0 + 1e-3));
    let (mut r_a, mut r_b) = (residual(e_a)?, residual(e_b)?);
    for _ in 0..60 {
        if r_b.abs() <= 1e2 * tolerance * target || r_a == r_b {
            break;
        }
        let e_c = e_b - r_b * (e_b - e_a) / (r_b - r_a);
        (e_a, r_a) = (e_b, r_b);
        e_b = e_c;
        r_b = residual(e_b)?;
    }
    if !(r_b.abs() <= 1e3 * tolerance * target) {
        return Err(ToolError::NoSolution {
            tool: "volume_burn",
            detail: format!("secant on eq 20 left residual {r_b} J/kg"),
        });
    }
    Ok(VolumeBurnReference {
        reference_pressure: products.pressure(rho0, e_b),
        reference_energy: e_b,
        rayleigh_work,
        principal_expansion_work: principal,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::tools::cj::{chapman_jouguet, UnreactedState};
    use crate::tools::isentrope::DEFAULT_TOLERANCE;
    use crate::{IdealGas, Jwl};

    #[test]
    fn ideal_gas_reference_pressure_is_half_the_cj_pressure() {
        for &gamma in &[1.2, 1.4, 3.0] {
            let gas = IdealGas::new(gamma, 718.0, 1.0);
            let u = UnreactedState {
                density: 1630.0,
                specific_internal_energy: 4.0e6,
                pressure: 0.0,
            };
            let cj = chapman_jouguet(&gas, &u).unwrap();
            let vb = volume_burn_reference(&gas, &cj, DEFAULT_TOLERANCE).unwrap();
            let ratio = vb.reference_pressure / cj.pressure;
            assert!(
                (ratio - 0.5).abs() < 1e-6,
                "γ = {gamma}: P_S0/P_CJ = {ratio}"
            );
        }
    }

    #[test]
    fn tnt_reference_pressure_is_the_constant_volume_explosion_pressure() {
        // Eq 20's left side reduces to e₀ (the Rayleigh work cancels the
        // Hugoniot energy jump), so P_S0 = p(ρ₀, e₀) = 8.37604e9 Pa for TNT.
        let j = Jwl::tnt();
        let u = UnreactedState {
            density: j.rho0,
            specific_internal_energy: j.specific_detonation_energy(),
            pressure: 0.0,
        };
        let cj = chapman_jouguet(&j, &u).unwrap();
        let vb = volume_burn_reference(&j, &cj, DEFAULT_TOLERANCE).unwrap();
        let want = j.pressure(j.rho0, j.specific_detonation_energy());
        assert!((vb.reference_pressure - want).abs() < 1e-6 * want, "{vb:?}");
        assert!((vb.reference_pressure - 8.37604e9).abs() < 1e-5 * 8.37604e9);
        // Seed 004 eq 30 with P_S(1) = P_S0 fixes C = P_S0 − A e^{−R₁} − B e^{−R₂}.
        let c = j.isentrope_constant(j.rho0, vb.reference_energy);
        let c_hand =
            vb.reference_pressure - 3.712e11 * (-4.15f64).exp() - 3.21e9 * (-0.95f64).exp();
        assert!((c - c_hand).abs() < 1e-6 * c_hand);
    }
}
