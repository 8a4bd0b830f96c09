//! The equation-of-state trait.

use crate::EosError;

/// Thermodynamics of one material.
///
/// The mechanical part maps (density ρ, specific internal energy e) to
/// pressure and sound speed; the thermal part adds temperature through the
/// specific heat at constant volume, and the (p, T) → ρ inversion,
/// isothermal compressibility and thermal expansivity that the ICE
/// equilibration pressure needs (seed 000 eqs 4–10, 20).
///
/// # Contract (checked for every implementation by the
/// `eos_contract_tests!` macro of the `contracts` feature)
/// - `pressure(ρ, specific_internal_energy(ρ, p)) = p` wherever the model is
///   valid.
/// - `sound_speed_squared(ρ, e) ≥ 0` and equals
///   `∂p/∂ρ|ₑ + (p/ρ²) ∂p/∂e|ρ`.
/// - `dp_drho` and `dp_de` agree with finite differences of `pressure`.
/// - `density(pressure(ρ, e), temperature(ρ, e)) = ρ` (the (p, T) → ρ
///   inversion round-trips), and `temperature` inverts
///   `specific_internal_energy_from_temperature`.
/// - `isothermal_compressibility` and `thermal_expansivity` agree with finite
///   differences of `density(p, T)`, and `density_and_derivatives` returns
///   the three of them.
/// - `gruneisen(ρ, e)` is the model's Γ and equals `(1/ρ) ∂p/∂e|ρ`.
/// - Out-of-range input (ρ ≤ 0, NaN) is an error from `check_state`,
///   `specific_internal_energy` and `density`, never a NaN that flows on.
///
/// Units: ρ kg/m³, e J/kg, p Pa, T K, c m/s.
///
/// Solvers call these in hot loops through a generic parameter (`E: Eos`),
/// so the methods are small and `#[inline]`-able; the trait is also object
/// safe for the registry.
pub trait Eos: Send + Sync + std::fmt::Debug {
    /// Registry name of the model (`ideal_gas`, `jwl`, ...).
    fn name(&self) -> &'static str;

    /// Reference (initial) density ρ₀, kg/m³.
    fn reference_density(&self) -> f64;

    /// Pressure p(ρ, e), Pa.
    fn pressure(&self, rho: f64, e: f64) -> f64;

    /// ∂p/∂ρ at constant e.
    fn dp_drho(&self, rho: f64, e: f64) -> f64;

    /// ∂p/∂e at constant ρ.
    fn dp_de(&self, rho: f64, e: f64) -> f64;

    /// Grüneisen parameter Γ = (1/ρ) ∂p/∂e|ρ (dimensionless). The default
    /// derives it from `dp_de`; models override it with their analytic Γ
    /// (ω for JWL, γ − 1 for an ideal gas, 0 for a barotropic solid), which
    /// the contract tests compare against the finite difference.
    #[inline]
    fn gruneisen(&self, rho: f64, e: f64) -> f64 {
        self.dp_de(rho, e) / rho
    }

    /// Whether (ρ, e) lies where the model may be evaluated. The default
    /// rejects a non-finite or non-positive density and a non-finite energy
    /// with [`EosError::OutOfRange`] naming the model and the value; models
    /// with a narrower valid range override it. Solvers call it where a state
    /// enters (initialisation, after a reaction step), not per evaluation.
    fn check_state(&self, rho: f64, e: f64) -> Result<(), EosError> {
        if !(rho.is_finite() && rho > 0.0) {
            return Err(EosError::OutOfRange {
                eos: self.name(),
                detail: format!("density ρ = {rho} kg/m³ must be finite and > 0"),
            });
        }
        if !e.is_finite() {
            return Err(EosError::OutOfRange {
                eos: self.name(),
                detail: format!("specific internal energy e = {e} J/kg must be finite"),
            });
        }
        Ok(())
    }

    /// Squared isentropic sound speed c² = ∂p/∂ρ|ₑ + (p/ρ²) ∂p/∂e|ρ, m²/s².
    fn sound_speed_squared(&self, rho: f64, e: f64) -> f64 {
        let p = self.pressure(rho, e);
        self.dp_drho(rho, e) + p / (rho * rho) * self.dp_de(rho, e)
    }

    /// Sound speed c, m/s (zero where c² < 0).
    fn sound_speed(&self, rho: f64, e: f64) -> f64 {
        self.sound_speed_squared(rho, e).max(0.0).sqrt()
    }

    /// The specific internal energy that gives pressure `p` at density `rho`.
    fn specific_internal_energy(&self, rho: f64, p: f64) -> Result<f64, EosError>;

    /// Temperature T(ρ, e), K.
    fn temperature(&self, rho: f64, e: f64) -> f64;

    /// Specific internal energy e(ρ, T), J/kg (inverse of `temperature`).
    fn specific_internal_energy_from_temperature(&self, rho: f64, t: f64) -> f64;

    /// Specific heat at constant volume, J/(kg·K).
    fn cv(&self, rho: f64, t: f64) -> f64;

    /// Density at pressure p and temperature T (the thermal EOS v(p, T)
    /// inverted), kg/m³.
    fn density(&self, p: f64, t: f64) -> Result<f64, EosError>;

    /// Isothermal compressibility κ = (1/ρ) ∂ρ/∂p|_T, 1/Pa.
    fn isothermal_compressibility(&self, p: f64, t: f64) -> Result<f64, EosError>;

    /// Thermal expansivity α = (1/v) ∂v/∂T|_p = −(1/ρ) ∂ρ/∂T|_p, 1/K.
    fn thermal_expansivity(&self, p: f64, t: f64) -> Result<f64, EosError>;

    /// `(density(p, T), isothermal_compressibility(p, T),
    /// thermal_expansivity(p, T))` from one call: ρ kg/m³, κ 1/Pa, α 1/K.
    ///
    /// The ICE equilibration (seed 000 eq 7) needs all three at the same
    /// (p, T); a model whose ρ(p, T) is an iterative inversion overrides this
    /// to invert once and evaluate κ and α at that ρ. An override must
    /// return exactly (to the bit) what the three methods return, and the
    /// first of their errors. The default calls the three methods.
    #[inline]
    fn density_and_derivatives(&self, p: f64, t: f64) -> Result<(f64, f64, f64), EosError> {
        Ok((
            self.density(p, t)?,
            self.isothermal_compressibility(p, t)?,
            self.thermal_expansivity(p, t)?,
        ))
    }
}
