//! Isentropes of any EOS, in particular the principal isentrope through the
//! CJ state (seed 004 eqs 20, 29–30: the products expand along it).
//!
//! Along an isentrope de = −p dv (first law with ds = 0). Brisance
//! integrates it in s = ln v, de/ds = −p(1/v, e) v = −p/ρ, with classical
//! RK4 and step doubling: each step is taken once whole and once as two
//! halves, the difference (/15) is the local error, the Richardson-extrapolated
//! value is kept, and the step grows or shrinks to hold the error below
//! `tolerance` × (|e| + |p/ρ|) per step.

use super::cj::CjState;
use super::ToolError;
use brisance_core::Eos;

/// Default relative tolerance of the isentrope integration.
pub const DEFAULT_TOLERANCE: f64 = 1e-11;

const MAX_STEPS: usize = 200_000;

/// One point of an isentrope.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct IsentropePoint {
    /// Relative volume V = v/v₀ = ρ₀/ρ (ρ₀ the unreacted density).
    pub relative_volume: f64,
    /// ρ, kg/m³.
    pub density: f64,
    /// e, J/kg.
    pub specific_internal_energy: f64,
    /// p, Pa.
    pub pressure: f64,
}

fn rhs<E: Eos + ?Sized>(eos: &E, s: f64, e: f64) -> f64 {
    let rho = (-s).exp();
    -eos.pressure(rho, e) / rho
}

fn rk4<E: Eos + ?Sized>(eos: &E, s: f64, e: f64, h: f64) -> f64 {
    let k1 = rhs(eos, s, e);
    let k2 = rhs(eos, s + 0.5 * h, e + 0.5 * h * k1);
    let k3 = rhs(eos, s + 0.5 * h, e + 0.5 * h * k2);
    let k4 = rhs(eos, s + h, e + h * k3);
    e + h / 6.0 * (k1 + 2.0 * k2 + 2.0 * k3 + k4)
}

/// The specific internal energy at density `rho_end` on the isentrope
/// through (`rho_start`, `e_start`), J/kg.
pub fn isentrope_energy<E: Eos + ?Sized>(
    eos: &E,
    rho_start: f64,
    e_start: f64,
    rho_end: f64,
    tolerance: f64,
) -> Result<f64, ToolError> {
    eos.check_state(rho_start, e_start)?;
    eos.check_state(rho_end, e_start)?;
    if !(tolerance > 0.0) {
        return Err(ToolError::InvalidInput {
            tool: "isentrope",
            detail: format!("tolerance {tolerance} must be > 0"),
        });
    }
    let (mut s, s_end) = (-rho_start.ln(), -rho_end.ln());
    let mut e = e_start;
    if s == s_end {
        return Ok(e);
    }
    let mut h = (s_end - s) / 32.0;
    for _ in 0..MAX_STEPS {
        let last = (s_end - s).abs() <= h.abs();
        if last {
            h = s_end - s;
        }
        let whole = rk4(eos, s, e, h);
        let half = rk4(eos, s, e, 0.5 * h);
        let halves = rk4(eos, s + 0.5 * h, half, 0.5 * h);
        let err = (halves - whole).abs() / 15.0;
        let scale = e.abs() + (eos.pressure((-s).exp(), e) * (-s).exp().recip()).abs();
        if !err.is_finite() {
            return Err(ToolError::NoSolution {
                tool: "isentrope",
                detail: format!("non-finite state at ρ = {} kg/m³, e = {e} J/kg", (-s).exp()),
            });
        }
        let allowed = tolerance * scale.max(f64::MIN_POSITIVE);
        if err <= allowed {
            s += h;
            e = halves + (halves - whole) / 15.0;
            if last {
                return Ok(e);
            }
        }
        let factor = if err == 0.0 {
            4.0
        } else {
            0.9 * (allowed / err).powf(0.2)
        };
        h *= factor.clamp(0.2, 4.0);
    }
    Err(ToolError::NoSolution {
        tool: "isentrope",
        detail: format!("step limit {MAX_STEPS} reached before ρ = {rho_end} kg/m³"),
    })
}

/// The principal isentrope: the isentrope through the CJ state `cj`,
/// sampled at the given relative volumes V = ρ₀/ρ (any order; each
/// segment continues from the previous point).
pub fn principal_isentrope<E: Eos + ?Sized>(
    eos: &E,
    cj: &CjState,
    relative_volumes: &[f64],
    tolerance: f64,
) -> Result<Vec<IsentropePoint>, ToolError> {
    let rho0 = cj.unreacted.density;
    let (mut rho, mut e) = (cj.density, cj.specific_internal_energy);
    let mut out = Vec::with_capacity(relative_volumes.len());
    for &v in relative_volumes {
        if !(v.is_finite() && v > 0.0) {
            return Err(ToolError::InvalidInput {
                tool: "isentrope",
                detail: format!("relative volume {v} must be finite and > 0"),
            });
        }
        let rho_next = rho0 / v;
        e = isentrope_energy(eos, rho, e, rho_next, tolerance)?;
        rho = rho_next;
        out.push(IsentropePoint {
            relative_volume: v,
            density: rho,
            specific_internal_energy: e,
            pressure: eos.pressure(rho, e),
        });
    }
    Ok(out)
}

/// ∫_v^∞ p dv along the isentrope through (ρ, e), J/kg: RK4 out to a
/// 10⁴-fold expansion, then the polytropic tail p v/(γ − 1) with the local
/// isentropic exponent γ = ρc²/p (exact for a γ-law gas and for JWL, whose
/// isentropes end as p ∝ V^{−(1+ω)}).
pub fn expansion_work_to_infinity<E: Eos + ?Sized>(
    eos: &E,
    rho: f64,
    e: f64,
    tolerance: f64,
) -> Result<f64, ToolError> {
    let rho_far = rho * 1e-4;
    let e_far = isentrope_energy(eos, rho, e, rho_far, tolerance)?;
    let p_far = eos.pressure(rho_far, e_far);
    let gamma = rho_far * eos.sound_speed_squared(rho_far, e_far) / p_far;
    if !(p_far > 0.0 && gamma > 1.0) {
        return Err(ToolError::NoSolution {
            tool: "isentrope",
            detail: format!(
                "expansion tail needs p > 0 and γ = ρc²/p > 1, got p = {p_far} Pa, γ = {gamma}"
            ),
        });
    }
    Ok(e - e_far + p_far / (rho_far * (gamma - 1.0)))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::tools::cj::{chapman_jouguet, UnreactedState};
    use crate::{IdealGas, Jwl};

    #[test]
    fn ideal_gas_isentrope_is_e_proportional_to_rho_to_gamma_minus_one() {
        // e ∝ ρ^{γ−1}: from ρ = 2, e = 3e5 to ρ = 0.5 with γ = 1.4:
        // e = 3e5 · 0.25^{0.4} = 1.72305e5 J/kg.
        let gas = IdealGas::new(1.4, 718.0, 1.0);
        let e = isentrope_energy(&gas, 2.0, 3.0e5, 0.5, DEFAULT_TOLERANCE).unwrap();
        let want = 3.0e5 * 0.25f64.powf(0.4);
        assert!((e - want).abs() < 1e-9 * want, "{e} vs {want}");
    }

    #[test]
    fn jwl_principal_isentrope_matches_the_analytic_c_term_form() {
        let j = Jwl::tnt();
        let u = UnreactedState {
            density: j.rho0,
            specific_internal_energy: j.specific_detonation_energy(),
            pressure: 0.0,
        };
        let cj = chapman_jouguet(&j, &u).unwrap();
        let c = j.isentrope_constant(cj.density, cj.specific_internal_energy);
        let pts = principal_isentrope(&j, &cj, &[1.0, 2.2, 7.2, 20.0], DEFAULT_TOLERANCE).unwrap();
        for pt in pts {
            let p = j.isentrope_pressure(c, pt.relative_volume);
            let e = j.isentrope_energy(c, pt.relative_volume);
            assert!((pt.pressure - p).abs() < 1e-8 * p, "{pt:?} vs p = {p}");
            assert!(
                (pt.specific_internal_energy - e).abs() < 1e-9 * e,
                "{pt:?} vs e = {e}"
            );
        }
    }

    #[test]
    fn expansion_work_to_infinity_is_the_whole_energy_for_a_gamma_law_gas() {
        let gas = IdealGas::new(1.4, 718.0, 1.0);
        let w = expansion_work_to_infinity(&gas, 1.3, 2.0e6, DEFAULT_TOLERANCE).unwrap();
        assert!((w - 2.0e6).abs() < 1e-8 * 2.0e6, "w = {w}");
    }

    #[test]
    fn a_bad_relative_volume_is_an_error() {
        let gas = IdealGas::new(1.4, 718.0, 1.0);
        let u = UnreactedState {
            density: 1.0,
            specific_internal_energy: 1e6,
            pressure: 0.0,
        };
        let cj = chapman_jouguet(&gas, &u).unwrap();
        assert!(principal_isentrope(&gas, &cj, &[2.0, -1.0], DEFAULT_TOLERANCE).is_err());
        assert!(principal_isentrope(&gas, &cj, &[f64::NAN], DEFAULT_TOLERANCE).is_err());
    }
}
