//! Generic property tests for the trait contracts.
//!
//! An equation of state joins the harness with one line in its crate's tests:
//!
//! ```text
//! brisance_core::eos_contract_tests!(ideal_gas_air, IdealGas::air(), rho: 0.01..100.0, e: 1.0e3..1.0e7);
//! ```
//!
//! or, for a model whose valid range is a temperature band rather than an
//! energy band (a JWL state below its cold isentrope has T < 0), over
//! (ρ, T) with e = e(ρ, T):
//!
//! ```text
//! brisance_core::eos_contract_tests!(jwl_tnt, Jwl::tnt(), rho: 200.0..3000.0, t: 300.0..6000.0);
//! ```
//!
//! The checks themselves are plain functions so a failing case can be
//! replayed by hand.

use crate::{Eos, ReactionModel, ReactionState};

/// The [`ReactionModel`] contract at one state: the rate is finite and
/// ≥ 0; one step of `dt` leaves F in [f, 1] (never decreasing, never past
/// fully burnt); a step of zero length changes nothing where no schedule
/// is set (`detonation_time` infinite: a scheduled burn completes once its
/// time has come, whatever the step); a longer step
/// never burns less than a shorter one from the same state; the mass
/// converted is the initial mass times the change of F, and never
/// negative; a cell burns between none and all of its reactant
/// ([`ReactionModel::burnt_density`]).
pub fn check_reaction_model<R: ReactionModel + ?Sized>(
    model: &R,
    state: &ReactionState,
    f: f64,
    dt: f64,
) -> Result<(), String> {
    let rate = model.rate(state, f);
    if !(rate.is_finite() && rate >= 0.0) {
        return Err(format!(
            "{}: rate {rate} at F = {f}, {state:?}",
            model.name()
        ));
    }
    let g = model.advance(state, f, dt);
    if !(g >= f && g <= 1.0) {
        return Err(format!(
            "{}: F = {f} advanced by {dt} s gives {g}, outside [F, 1]",
            model.name()
        ));
    }
    if state.detonation_time == f64::INFINITY && model.advance(state, f, 0.0) != f {
        return Err(format!("{}: a zero step moved F = {f}", model.name()));
    }
    let half = model.advance(state, f, 0.5 * dt);
    if half > g {
        return Err(format!(
            "{}: half a step burns more ({half}) than the whole ({g})",
            model.name()
        ));
    }
    // A cell of 1 kg/m³ of explosive at burn fraction F: between none and
    // all of its reactant 1 − F burns.
    let burnt = model.burnt_density(state, 1.0 - f, f, dt);
    if !(burnt >= 0.0 && burnt <= 1.0 - f) {
        return Err(format!(
            "{}: {burnt} kg/m³ burnt of a reactant density {}",
            model.name(),
            1.0 - f
        ));
    }
    let m = model.mass_converted(2.0, f, g);
    if !(m >= 0.0 && (m - 2.0 * (g - f)).abs() <= 1e-15 * 2.0) {
        return Err(format!(
            "{}: mass converted {m} for F {f} → {g} of 2 kg",
            model.name()
        ));
    }
    Ok(())
}

/// Relative difference scaled by the larger magnitude (and `floor`).
pub fn rel_diff(a: f64, b: f64, floor: f64) -> f64 {
    (a - b).abs() / a.abs().max(b.abs()).max(floor)
}

/// Finite-difference steps in ρ and e at a state: relative 1e-6 of the
/// density and of the state's own energy scale max(|e|, |p|/ρ, c²), so a
/// stiff solid near e = 0 is still differenced well above round-off.
pub fn fd_steps<E: Eos + ?Sized>(eos: &E, rho: f64, e: f64) -> (f64, f64) {
    let p = eos.pressure(rho, e);
    let c2 = eos.sound_speed_squared(rho, e);
    let scale = e.abs().max(p.abs() / rho).max(c2.abs()).max(1.0);
    (1e-6 * rho, 1e-6 * scale)
}

/// p(ρ, e(ρ, p)) = p.
pub fn check_pressure_roundtrip<E: Eos + ?Sized>(eos: &E, rho: f64, e: f64) -> Result<(), String> {
    let p = eos.pressure(rho, e);
    let e2 = eos
        .specific_internal_energy(rho, p)
        .map_err(|err| format!("e(ρ={rho}, p={p}) failed: {err}"))?;
    let p2 = eos.pressure(rho, e2);
    if rel_diff(p, p2, 1e-12 * (rho * e.abs()).max(1.0)) > 1e-9 {
        return Err(format!("p(ρ,e(ρ,p)) = {p2} ≠ p = {p} at ρ={rho}, e={e}"));
    }
    Ok(())
}

/// c² ≥ 0 and c² = ∂p/∂ρ|ₑ + (p/ρ²) ∂p/∂e|ρ with finite-difference derivatives.
pub fn check_sound_speed<E: Eos + ?Sized>(eos: &E, rho: f64, e: f64) -> Result<(), String> {
    let c2 = eos.sound_speed_squared(rho, e);
    if !(c2 >= 0.0) {
        return Err(format!("c² = {c2} < 0 at ρ={rho}, e={e}"));
    }
    let (hr, he) = fd_steps(eos, rho, e);
    let dpdr = (eos.pressure(rho + hr, e) - eos.pressure(rho - hr, e)) / (2.0 * hr);
    let dpde = (eos.pressure(rho, e + he) - eos.pressure(rho, e - he)) / (2.0 * he);
    let p = eos.pressure(rho, e);
    let fd = dpdr + p / (rho * rho) * dpde;
    if rel_diff(c2, fd, 1e-9 * c2.abs().max(1e-30)) > 1e-5 {
        return Err(format!(
            "c² = {c2} but finite differences give {fd} at ρ={rho}, e={e}"
        ));
    }
    Ok(())
}

/// The analytic derivatives agree with central differences.
pub fn check_derivatives<E: Eos + ?Sized>(eos: &E, rho: f64, e: f64) -> Result<(), String> {
    let (hr, he) = fd_steps(eos, rho, e);
    let dpdr = (eos.pressure(rho + hr, e) - eos.pressure(rho - hr, e)) / (2.0 * hr);
    let dpde = (eos.pressure(rho, e + he) - eos.pressure(rho, e - he)) / (2.0 * he);
    let (a, b) = (eos.dp_drho(rho, e), eos.dp_de(rho, e));
    let scale_r = (eos.pressure(rho, e).abs() / rho).max(1e-30);
    if rel_diff(a, dpdr, scale_r) > 1e-5 {
        return Err(format!(
            "∂p/∂ρ = {a} vs finite difference {dpdr} at ρ={rho}, e={e}"
        ));
    }
    if rel_diff(b, dpde, rho * 1e-6) > 1e-5 {
        return Err(format!(
            "∂p/∂e = {b} vs finite difference {dpde} at ρ={rho}, e={e}"
        ));
    }
    Ok(())
}

/// T(ρ, e(ρ, T)) = T and ρ(p(ρ, e), T(ρ, e)) = ρ.
pub fn check_thermal_roundtrip<E: Eos + ?Sized>(eos: &E, rho: f64, e: f64) -> Result<(), String> {
    let t = eos.temperature(rho, e);
    let e2 = eos.specific_internal_energy_from_temperature(rho, t);
    if rel_diff(e, e2, 1e-9 * e.abs().max(1.0)) > 1e-9 {
        return Err(format!("e(ρ, T(ρ,e)) = {e2} ≠ e = {e} at ρ={rho}"));
    }
    let p = eos.pressure(rho, e);
    let rho2 = eos
        .density(p, t)
        .map_err(|err| format!("ρ(p={p}, T={t}) failed: {err}"))?;
    if rel_diff(rho, rho2, 0.0) > 1e-9 {
        return Err(format!("ρ(p, T) = {rho2} ≠ ρ = {rho} (p={p}, T={t})"));
    }
    Ok(())
}

/// Compressibility and expansivity agree with finite differences of ρ(p, T).
pub fn check_thermal_derivatives<E: Eos + ?Sized>(eos: &E, rho: f64, e: f64) -> Result<(), String> {
    let p = eos.pressure(rho, e);
    let t = eos.temperature(rho, e);
    let fail = |what: &str, err: crate::EosError| format!("{what} failed at p={p}, T={t}: {err}");
    let kappa = eos
        .isothermal_compressibility(p, t)
        .map_err(|er| fail("κ", er))?;
    let alpha = eos.thermal_expansivity(p, t).map_err(|er| fail("α", er))?;
    // Pressure step on the scale of the bulk modulus ρc², so ρ moves by
    // ~1e-6 relative even for a stiff solid near p = 0.
    let bulk = rho * eos.sound_speed_squared(rho, e).abs();
    let (hp, ht) = (1e-6 * p.abs().max(bulk).max(1.0), 1e-6 * t.abs().max(1e-3));
    let rho_of = |p: f64, t: f64| eos.density(p, t).map_err(|er| fail("ρ(p,T)", er));
    let kappa_fd = (rho_of(p + hp, t)? - rho_of(p - hp, t)?) / (2.0 * hp) / rho;
    let alpha_fd = -(rho_of(p, t + ht)? - rho_of(p, t - ht)?) / (2.0 * ht) / rho;
    if rel_diff(kappa, kappa_fd, 1e-30) > 1e-5 {
        return Err(format!(
            "κ = {kappa} vs finite difference {kappa_fd} at p={p}, T={t}"
        ));
    }
    if rel_diff(alpha, alpha_fd, 1e-12 / t.abs().max(1e-3)) > 1e-5 {
        return Err(format!(
            "α = {alpha} vs finite difference {alpha_fd} at p={p}, T={t}"
        ));
    }
    Ok(())
}

/// The model's Grüneisen Γ equals (1/ρ) ∂p/∂e|ρ from a central difference.
pub fn check_gruneisen<E: Eos + ?Sized>(eos: &E, rho: f64, e: f64) -> Result<(), String> {
    let (_, he) = fd_steps(eos, rho, e);
    let dpde = (eos.pressure(rho, e + he) - eos.pressure(rho, e - he)) / (2.0 * he);
    let fd = dpde / rho;
    let gamma = eos.gruneisen(rho, e);
    if !gamma.is_finite() || rel_diff(gamma, fd, 1e-6) > 1e-5 {
        return Err(format!(
            "Γ = {gamma} but (1/ρ)∂p/∂e by finite differences = {fd} at ρ={rho}, e={e}"
        ));
    }
    Ok(())
}

/// Out-of-range input is an error, never a NaN that flows on: `check_state`
/// rejects ρ ≤ 0 and NaN in either argument, `specific_internal_energy`
/// rejects ρ ≤ 0 or NaN and a NaN pressure, `density` rejects a NaN pressure
/// or temperature. `(rho, e)` is a valid state supplying the other argument.
pub fn check_rejects_out_of_range<E: Eos + ?Sized>(
    eos: &E,
    rho: f64,
    e: f64,
) -> Result<(), String> {
    let p = eos.pressure(rho, e);
    let t = eos.temperature(rho, e);
    eos.check_state(rho, e)
        .map_err(|err| format!("check_state rejected the valid state ρ={rho}, e={e}: {err}"))?;
    for bad_rho in [0.0, -rho, f64::NAN, f64::INFINITY] {
        if eos.check_state(bad_rho, e).is_ok() {
            return Err(format!("check_state accepted ρ = {bad_rho}"));
        }
        if let Ok(e2) = eos.specific_internal_energy(bad_rho, p) {
            return Err(format!(
                "specific_internal_energy(ρ = {bad_rho}, p = {p}) returned {e2}, not an error"
            ));
        }
    }
    if eos.check_state(rho, f64::NAN).is_ok() {
        return Err(format!("check_state accepted e = NaN at ρ={rho}"));
    }
    if let Ok(e2) = eos.specific_internal_energy(rho, f64::NAN) {
        return Err(format!(
            "specific_internal_energy(ρ = {rho}, p = NaN) returned {e2}, not an error"
        ));
    }
    if let Ok(r) = eos.density(f64::NAN, t) {
        return Err(format!(
            "density(p = NaN, T = {t}) returned {r}, not an error"
        ));
    }
    if let Ok(r) = eos.density(p, f64::NAN) {
        return Err(format!(
            "density(p = {p}, T = NaN) returned {r}, not an error"
        ));
    }
    Ok(())
}

/// Every contract check at one state.
pub fn check_all<E: Eos + ?Sized>(eos: &E, rho: f64, e: f64) -> Result<(), String> {
    check_pressure_roundtrip(eos, rho, e)?;
    check_sound_speed(eos, rho, e)?;
    check_derivatives(eos, rho, e)?;
    check_gruneisen(eos, rho, e)?;
    check_thermal_roundtrip(eos, rho, e)?;
    check_thermal_derivatives(eos, rho, e)?;
    check_rejects_out_of_range(eos, rho, e)
}

/// Every contract check at the state (ρ, e(ρ, T)).
pub fn check_all_at_temperature<E: Eos + ?Sized>(eos: &E, rho: f64, t: f64) -> Result<(), String> {
    let e = eos.specific_internal_energy_from_temperature(rho, t);
    check_all(eos, rho, e).map_err(|msg| format!("{msg} (state built from T = {t} K)"))
}

/// Generates a proptest module checking the [`Eos`] contract for one
/// implementation over a box of (ρ, e) states — or, with `t:` in place of
/// `e:`, a box of (ρ, T) states — where the model is valid.
///
/// The invoking crate needs `proptest` as a dev-dependency and
/// `brisance-core` with the `contracts` feature.
#[macro_export]
macro_rules! eos_contract_tests {
    ($name:ident, $eos:expr, rho: $rho:expr, e: $e:expr) => {
        mod $name {
            #[allow(unused_imports)]
            use super::*;
            use proptest::prelude::*;
            proptest! {
                #![proptest_config(ProptestConfig::with_cases(256))]
                #[test]
                fn eos_contract_holds(rho in $rho, e in $e) {
                    let eos = $eos;
                    if let Err(msg) = $crate::contracts::check_all(&eos, rho, e) {
                        prop_assert!(false, "{}", msg);
                    }
                }
            }
        }
    };
    ($name:ident, $eos:expr, rho: $rho:expr, t: $t:expr) => {
        mod $name {
            #[allow(unused_imports)]
            use super::*;
            use proptest::prelude::*;
            proptest! {
                #![proptest_config(ProptestConfig::with_cases(256))]
                #[test]
                fn eos_contract_holds(rho in $rho, t in $t) {
                    let eos = $eos;
                    if let Err(msg) = $crate::contracts::check_all_at_temperature(&eos, rho, t) {
                        prop_assert!(false, "{}", msg);
                    }
                }
            }
        }
    };
}
