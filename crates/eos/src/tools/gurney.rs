//! Gurney velocity estimate from the principal isentrope.
//!
//! The Gurney energy per unit mass of explosive is taken as the mechanical
//! energy of detonation at a stated expansion V (relative volume v/v₀):
//! the work the products do expanding along the principal isentrope from CJ
//! to V, less the kinetic energy the CJ state already carries (put in by the
//! Rayleigh-line compression),
//!
//! ```text
//! E_G(V) = [e_CJ − e_s(V)] − ½ u_CJ²,   ½u_CJ² = ½(p_CJ − p₀)(v₀ − v_CJ),
//! ```
//!
//! which for p₀ = 0 is e₀ − e_s(V), the energy the explosive has given up
//! by the time its products reach V. The Gurney velocity is √(2E_G), and
//! the cylinder (open-ended, long) Gurney relation gives the wall velocity
//!
//! ```text
//! v_wall = √(2E_G) · (M/C + 1/2)^{−1/2},
//! ```
//!
//! with M/C the metal-to-charge mass ratio. The expansion customarily used
//! is the cylinder-test relative volume 7 ([`CYLINDER_TEST_RELATIVE_VOLUME`]).

use super::cj::CjState;
use super::isentrope::isentrope_energy;
use super::ToolError;
use brisance_core::Eos;

/// Relative volume at which the cylinder-test energy is quoted.
pub const CYLINDER_TEST_RELATIVE_VOLUME: f64 = 7.0;

/// The Gurney energy at one expansion.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GurneyEstimate {
    /// The expansion V = v/v₀ it was evaluated at.
    pub relative_volume: f64,
    /// e_CJ − e_s(V): work along the isentrope from CJ to V, J/kg.
    pub expansion_work: f64,
    /// E_G = expansion work − ½u_CJ², J/kg.
    pub gurney_energy: f64,
    /// √(2E_G), m/s.
    pub gurney_velocity: f64,
}

/// The Gurney energy and velocity √(2E_G) at relative volume
/// `relative_volume` along the principal isentrope through `cj`.
pub fn gurney_estimate<E: Eos + ?Sized>(
    products: &E,
    cj: &CjState,
    relative_volume: f64,
    tolerance: f64,
) -> Result<GurneyEstimate, ToolError> {
    if !(relative_volume.is_finite() && relative_volume > cj.relative_volume) {
        return Err(ToolError::InvalidInput {
            tool: "gurney",
            detail: format!(
                "relative volume {relative_volume} must be finite and beyond the CJ volume {}",
                cj.relative_volume
            ),
        });
    }
    let rho = cj.unreacted.density / relative_volume;
    let e = isentrope_energy(
        products,
        cj.density,
        cj.specific_internal_energy,
        rho,
        tolerance,
    )?;
    let work = cj.specific_internal_energy - e;
    let energy = work - 0.5 * cj.particle_velocity * cj.particle_velocity;
    if !(energy > 0.0) {
        return Err(ToolError::NoSolution {
            tool: "gurney",
            detail: format!("no energy released by V = {relative_volume} (E_G = {energy} J/kg)"),
        });
    }
    Ok(GurneyEstimate {
        relative_volume,
        expansion_work: work,
        gurney_energy: energy,
        gurney_velocity: (2.0 * energy).sqrt(),
    })
}

/// Cylinder wall velocity v = √(2E) (M/C + 1/2)^{−1/2}, m/s, for Gurney
/// velocity `gurney_velocity` = √(2E) and metal-to-charge mass ratio
/// `metal_to_charge`.
pub fn cylinder_wall_velocity(
    gurney_velocity: f64,
    metal_to_charge: f64,
) -> Result<f64, ToolError> {
    if !(gurney_velocity.is_finite()
        && gurney_velocity >= 0.0
        && metal_to_charge.is_finite()
        && metal_to_charge >= 0.0)
    {
        return Err(ToolError::InvalidInput {
            tool: "gurney",
            detail: format!(
                "need finite √(2E) ≥ 0 and M/C ≥ 0, got {gurney_velocity} m/s and {metal_to_charge}"
            ),
        });
    }
    Ok(gurney_velocity / (metal_to_charge + 0.5).sqrt())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::tools::cj::{chapman_jouguet, UnreactedState};
    use crate::{IdealGas, Jwl};

    #[test]
    fn cylinder_relation_matches_hand_value() {
        // √(2E) = 2440 m/s, M/C = 1.5: v = 2440/√2 = 1725.34 m/s.
        let v = cylinder_wall_velocity(2440.0, 1.5).unwrap();
        assert!((v - 1725.3405).abs() < 1e-3, "v = {v}");
        assert!(cylinder_wall_velocity(2440.0, -1.0).is_err());
        assert!(cylinder_wall_velocity(f64::NAN, 1.0).is_err());
    }

    #[test]
    fn ideal_gas_gurney_energy_is_q_minus_the_isentrope_energy() {
        // Strong ideal-gas CJ (p₀ = 0): E_G(V) = q − e_s(V), with
        // e_s(V) = e_CJ (V_CJ/V)^{γ−1}, e_CJ = p_CJ v_CJ/(γ − 1).
        let (gamma, q) = (1.4, 4.0e6);
        let gas = IdealGas::new(gamma, 718.0, 1.0);
        let u = UnreactedState {
            density: 1.6,
            specific_internal_energy: q,
            pressure: 0.0,
        };
        let cj = chapman_jouguet(&gas, &u).unwrap();
        let g = gurney_estimate(&gas, &cj, 7.0, 1e-11).unwrap();
        let x = gamma / (gamma + 1.0);
        let d2 = 2.0 * (gamma * gamma - 1.0) * q;
        let e_cj = q + 0.5 * d2 * (1.0 - x) * (1.0 - x);
        let want = q - e_cj * (x / 7.0f64).powf(gamma - 1.0);
        assert!(
            (g.gurney_energy - want).abs() < 1e-6 * want,
            "{g:?} vs {want}"
        );
    }

    #[test]
    fn tnt_gurney_energy_matches_the_analytic_jwl_isentrope() {
        let j = Jwl::tnt();
        let u = UnreactedState {
            density: j.rho0,
            specific_internal_energy: j.specific_detonation_energy(),
            pressure: 0.0,
        };
        let cj = chapman_jouguet(&j, &u).unwrap();
        let g = gurney_estimate(&j, &cj, 7.0, 1e-11).unwrap();
        let c = j.isentrope_constant(cj.density, cj.specific_internal_energy);
        let want = u.specific_internal_energy - j.isentrope_energy(c, 7.0);
        assert!(
            (g.gurney_energy - want).abs() < 1e-7 * want,
            "{g:?} vs {want}"
        );
    }
}
