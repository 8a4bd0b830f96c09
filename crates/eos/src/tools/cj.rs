//! Chapman–Jouguet state of a products EOS from an unreacted state, by
//! tangency of the Rayleigh line with the products Hugoniot (seed 004
//! §"Volume Burn Algorithm": "the point where the Rayleigh line and
//! Hugoniot for the detonation products are tangent").
//!
//! With v = 1/ρ and the unreacted state (v₀, p₀, e₀), the Rayleigh line of a
//! steady wave of speed D is p − p₀ = ρ₀²D²(v₀ − v) (seed 004 eq 21) and the
//! products Hugoniot is e − e₀ = ½(p + p₀)(v₀ − v). The CJ state is the
//! Hugoniot point where the Rayleigh slope, hence
//!
//! ```text
//! D²(x) = v₀ (p_H(x) − p₀)/(1 − x),   x = v/v₀,
//! ```
//!
//! is smallest. The Hugoniot pressure at each x is found by Newton's method
//! on h(e) = e − e₀ − ½(p(ρ, e) + p₀)(v₀ − v); D²(x) is scanned on a grid of
//! x from 0.02 to 0.999 to bracket the minimum, which golden-section search
//! then refines. u_CJ = D(1 − x_CJ).
//!
//! Energies are in the products EOS's own reference: e₀ is the specific
//! internal energy the products would have at the unreacted state, i.e. it
//! includes the detonation energy (for JWL, e₀ = E₀/ρ₀).

use super::ToolError;
use crate::JwlCTerm;
use brisance_core::Eos;

/// The state ahead of the detonation.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct UnreactedState {
    /// ρ₀, kg/m³.
    pub density: f64,
    /// e₀ in the products EOS's energy reference, J/kg.
    pub specific_internal_energy: f64,
    /// p₀, Pa.
    pub pressure: f64,
}

/// The Chapman–Jouguet state.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CjState {
    /// Detonation velocity D, m/s.
    pub detonation_velocity: f64,
    /// p_CJ, Pa.
    pub pressure: f64,
    /// ρ_CJ, kg/m³.
    pub density: f64,
    /// v_CJ/v₀ = ρ₀/ρ_CJ.
    pub relative_volume: f64,
    /// Particle velocity u_CJ = D(1 − v_CJ/v₀), m/s.
    pub particle_velocity: f64,
    /// e_CJ, J/kg.
    pub specific_internal_energy: f64,
    /// Sound speed c_CJ of the products at CJ, m/s (= D − u_CJ).
    pub sound_speed: f64,
    /// The unreacted state it was computed from.
    pub unreacted: UnreactedState,
}

const SCAN_POINTS: usize = 500;
const X_MIN: f64 = 0.02;
const X_MAX: f64 = 0.999;

/// Energy on the products Hugoniot centred on `unreacted` at density `rho`,
/// or `None` where no compressive Hugoniot state exists (beyond the
/// compression limit, or p ≤ p₀).
pub fn hugoniot_energy<E: Eos + ?Sized>(
    products: &E,
    unreacted: &UnreactedState,
    rho: f64,
) -> Option<f64> {
    let (rho0, e0, p0) = (
        unreacted.density,
        unreacted.specific_internal_energy,
        unreacted.pressure,
    );
    let dv = 1.0 / rho0 - 1.0 / rho;
    let mut e = e0;
    for _ in 0..100 {
        let p = products.pressure(rho, e);
        let h = e - e0 - 0.5 * (p + p0) * dv;
        let dh = 1.0 - 0.5 * products.dp_de(rho, e) * dv;
        if !(dh > 0.0 && h.is_finite()) {
            return None;
        }
        let step = h / dh;
        e -= step;
        if step.abs() <= 1e-14 * (e.abs() + e0.abs() + 1.0) {
            let p = products.pressure(rho, e);
            return (p > p0 && p.is_finite()).then_some(e);
        }
    }
    None
}

/// The x = v/v₀ between `X_MIN` and `X_MAX` minimising D²(x) = v₀(p(x) − p₀)/(1 − x)
/// for a pressure curve `p_of_x` (`None` where undefined).
pub(crate) fn rayleigh_tangent(
    v0: f64,
    p0: f64,
    p_of_x: impl Fn(f64) -> Option<f64>,
) -> Result<f64, ToolError> {
    let d2 = |x: f64| match p_of_x(x) {
        Some(p) if p > p0 => v0 * (p - p0) / (1.0 - x),
        _ => f64::INFINITY,
    };
    let dx = (X_MAX - X_MIN) / (SCAN_POINTS - 1) as f64;
    let (mut best, mut best_k) = (f64::INFINITY, 0usize);
    for k in 0..SCAN_POINTS {
        let v = d2(X_MIN + dx * k as f64);
        if v < best {
            (best, best_k) = (v, k);
        }
    }
    if !best.is_finite() {
        return Err(ToolError::NoSolution {
            tool: "cj",
            detail: "no products state above the unreacted pressure on the scanned volumes".into(),
        });
    }
    if best_k == 0 || best_k == SCAN_POINTS - 1 {
        return Err(ToolError::NoSolution {
            tool: "cj",
            detail: format!(
                "the Rayleigh slope has no interior minimum (smallest at v/v₀ = {})",
                X_MIN + dx * best_k as f64
            ),
        });
    }
    // Golden-section refinement on the bracketing grid cells.
    let (mut a, mut b) = (
        X_MIN + dx * (best_k - 1) as f64,
        X_MIN + dx * (best_k + 1) as f64,
    );
    let g = 0.5 * (5f64.sqrt() - 1.0);
    let (mut c, mut d) = (b - g * (b - a), a + g * (b - a));
    let (mut fc, mut fd) = (d2(c), d2(d));
    while b - a > 1e-13 {
        if fc < fd {
            (b, d, fd) = (d, c, fc);
            c = b - g * (b - a);
            fc = d2(c);
        } else {
            (a, c, fc) = (c, d, fd);
            d = a + g * (b - a);
            fd = d2(d);
        }
    }
    Ok(0.5 * (a + b))
}

fn validate_unreacted(u: &UnreactedState) -> Result<(), ToolError> {
    if !(u.density.is_finite()
        && u.density > 0.0
        && u.specific_internal_energy.is_finite()
        && u.pressure.is_finite()
        && u.pressure >= 0.0)
    {
        return Err(ToolError::InvalidInput {
            tool: "cj",
            detail: format!("unreacted state must have finite ρ₀ > 0, e₀ and p₀ ≥ 0, got {u:?}"),
        });
    }
    Ok(())
}

fn cj_state<E: Eos + ?Sized>(
    products: &E,
    unreacted: &UnreactedState,
    x: f64,
    e: f64,
) -> Result<CjState, ToolError> {
    let rho0 = unreacted.density;
    let rho = rho0 / x;
    products.check_state(rho, e)?;
    let p = products.pressure(rho, e);
    let d = (((p - unreacted.pressure) / rho0) / (1.0 - x)).sqrt();
    Ok(CjState {
        detonation_velocity: d,
        pressure: p,
        density: rho,
        relative_volume: x,
        particle_velocity: d * (1.0 - x),
        specific_internal_energy: e,
        sound_speed: products.sound_speed(rho, e),
        unreacted: *unreacted,
    })
}

/// The CJ state of `products` detonating from `unreacted`, by Rayleigh-line
/// tangency with the products Hugoniot.
pub fn chapman_jouguet<E: Eos + ?Sized>(
    products: &E,
    unreacted: &UnreactedState,
) -> Result<CjState, ToolError> {
    validate_unreacted(unreacted)?;
    let rho0 = unreacted.density;
    let p_of_x = |x: f64| {
        let rho = rho0 / x;
        hugoniot_energy(products, unreacted, rho).map(|e| products.pressure(rho, e))
    };
    let x = rayleigh_tangent(1.0 / rho0, unreacted.pressure, p_of_x)?;
    let e =
        hugoniot_energy(products, unreacted, rho0 / x).ok_or_else(|| ToolError::NoSolution {
            tool: "cj",
            detail: format!("no Hugoniot state at the tangency point v/v₀ = {x}"),
        })?;
    cj_state(products, unreacted, x, e)
}

/// The CJ state of JWL++ products as JWL++ defines it: the point where the
/// Rayleigh line from (v₀, p₀ = 0) touches the reference isentrope
/// p_s(V) = A e^{−R₁V} + B e^{−R₂V} + C V^{−(1+ω)} (at CJ the isentrope,
/// the Hugoniot and the Rayleigh line are tangent, seed 004 §"Volume Burn
/// Algorithm").
pub fn cj_on_jwl_cterm_isentrope(products: &JwlCTerm) -> Result<CjState, ToolError> {
    products
        .validate()
        .map_err(|detail| ToolError::InvalidInput { tool: "cj", detail })?;
    let v0 = 1.0 / products.rho0;
    let x = rayleigh_tangent(v0, 0.0, |x| Some(products.isentrope_pressure(x)))?;
    let p = products.isentrope_pressure(x);
    let e = products.isentrope_energy(x);
    let unreacted = UnreactedState {
        density: products.rho0,
        specific_internal_energy: e - 0.5 * p * v0 * (1.0 - x),
        pressure: 0.0,
    };
    cj_state(products, &unreacted, x, e)
}

/// The unreacted state (ρ₀, e₀, p₀ = 0) of JWL++ products: e₀ is the
/// detonation energy that puts the products Hugoniot through the
/// isentrope's CJ point, e₀ = e_s(V_CJ) − ½p_CJ v₀(1 − V_CJ). A reaction
/// model converting reactant to these products deposits this energy.
pub fn jwl_cterm_unreacted_state(products: &JwlCTerm) -> Result<UnreactedState, ToolError> {
    Ok(cj_on_jwl_cterm_isentrope(products)?.unreacted)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{IdealGas, Jwl};

    fn strong_ideal_gas(gamma: f64, q: f64) -> (IdealGas, UnreactedState) {
        let gas = IdealGas::new(gamma, 1000.0, 1.0);
        let u = UnreactedState {
            density: 1.2,
            specific_internal_energy: q,
            pressure: 0.0,
        };
        (gas, u)
    }

    #[test]
    fn ideal_gas_cj_matches_the_strong_detonation_closed_form() {
        // p₀ = 0: D² = 2(γ² − 1)q, p_CJ = ρ₀D²/(γ + 1), v_CJ/v₀ = γ/(γ + 1),
        // u_CJ = D/(γ + 1). For γ = 1.4, q = 5e6 J/kg:
        // D = √(2 · 0.96 · 5e6) = 3098.39 m/s, p_CJ = 1.2 · 9.6e6/2.4 = 4.8e6 Pa.
        for &(gamma, q) in &[(1.4, 5.0e6), (3.0, 4.0e6), (1.2, 1.0e6)] {
            let (gas, u) = strong_ideal_gas(gamma, q);
            let cj = chapman_jouguet(&gas, &u).unwrap();
            let d = (2.0 * (gamma * gamma - 1.0) * q).sqrt();
            assert!((cj.detonation_velocity - d).abs() < 1e-9 * d, "{cj:?}");
            let p = 1.2 * d * d / (gamma + 1.0);
            assert!((cj.pressure - p).abs() < 1e-6 * p, "{cj:?}");
            assert!((cj.relative_volume - gamma / (gamma + 1.0)).abs() < 1e-6);
            assert!((cj.particle_velocity - d / (gamma + 1.0)).abs() < 1e-5 * d);
            // CJ is sonic: D = u + c.
            assert!((cj.particle_velocity + cj.sound_speed - d).abs() < 1e-5 * d);
        }
        let (gas, u) = strong_ideal_gas(1.4, 5.0e6);
        let cj = chapman_jouguet(&gas, &u).unwrap();
        assert!((cj.detonation_velocity - 3098.386677).abs() < 1e-5);
        assert!((cj.pressure - 4.8e6).abs() < 1.0);
    }

    #[test]
    fn tnt_cj_is_sonic_and_on_the_hugoniot() {
        let j = Jwl::tnt();
        let u = UnreactedState {
            density: j.rho0,
            specific_internal_energy: j.specific_detonation_energy(),
            pressure: 0.0,
        };
        let cj = chapman_jouguet(&j, &u).unwrap();
        let d = cj.detonation_velocity;
        assert!(
            (cj.particle_velocity + cj.sound_speed - d).abs() < 1e-5 * d,
            "{cj:?}"
        );
        let dv = (1.0 - cj.relative_volume) / j.rho0;
        let rankine =
            cj.specific_internal_energy - u.specific_internal_energy - 0.5 * cj.pressure * dv;
        assert!(rankine.abs() < 1e-9 * cj.specific_internal_energy);
    }

    #[test]
    fn jwl_cterm_hugoniot_cj_equals_the_isentrope_tangency() {
        for m in [JwlCTerm::anfo_k1(), JwlCTerm::qm100()] {
            let on_isentrope = cj_on_jwl_cterm_isentrope(&m).unwrap();
            let via_hugoniot = chapman_jouguet(&m, &on_isentrope.unreacted).unwrap();
            let (d1, d2) = (
                on_isentrope.detonation_velocity,
                via_hugoniot.detonation_velocity,
            );
            assert!((d1 - d2).abs() < 1e-7 * d1, "{d1} vs {d2}");
            let (p1, p2) = (on_isentrope.pressure, via_hugoniot.pressure);
            assert!((p1 - p2).abs() < 1e-5 * p1, "{p1} vs {p2}");
        }
    }

    #[test]
    fn a_non_positive_unreacted_density_is_an_error() {
        let (gas, mut u) = strong_ideal_gas(1.4, 1e6);
        u.density = 0.0;
        assert!(chapman_jouguet(&gas, &u).is_err());
        u.density = f64::NAN;
        assert!(chapman_jouguet(&gas, &u).is_err());
    }
}
