//! The "null" material: a fluid carried by material points, so a gas or a
//! liquid can be run in MPM (seed 001 §5 compares MPM with FDM on the same
//! gas problems, which needs the gas as particles).
//!
//! The stress has no strength and no memory:
//!
//! σ_{n+1} = −p(ρ, e) I + 2μ dev(D),
//!
//! with p from the [`EosModel`] at the density ρ (kg/m³) and specific
//! internal energy e (J/kg) handed to the update (seed 001 eq 55 for the
//! ideal gas, eq 54 for detonation products), D = ½(L + Lᵀ) the rate of
//! deformation (1/s) and μ ≥ 0 the optional Newtonian shear viscosity
//! (Pa·s). With μ = 0 this is the inviscid Euler fluid of seed 001 eqs 1–3.
//!
//! The stress depends on the current rate, not on an increment of the
//! previous stress, so it is objective without a stress rate: a rigid
//! spin has D = 0 and leaves σ = −p I. The viscous dissipation
//! Δw = 2μ dev(D):dev(D) Δt ≥ 0 (J/m³) is returned as the step's
//! "plastic work" so that the solver heats the fluid with it, as it does a
//! plastic solid.

use crate::ConstitutiveError;
use crate::{error::non_negative, hypoelastic::deviator, objective::rate_of_deformation};
use brisance_core::{Eos, Mat3, Material, StressUpdate, StressUpdateInput};
use brisance_eos::EosModel;
use serde::{Deserialize, Serialize};

const NAME: &str = "null";

/// A fluid as material points: pressure from an equation of state, zero
/// deviatoric stress or a Newtonian viscous one.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct NullMaterial {
    /// The equation of state p(ρ, e).
    pub eos: EosModel,
    /// Newtonian shear viscosity μ, Pa·s (0: inviscid).
    #[serde(default)]
    pub viscosity: f64,
}

impl NullMaterial {
    /// An inviscid fluid with the given equation of state.
    pub fn inviscid(eos: EosModel) -> Self {
        Self {
            eos,
            viscosity: 0.0,
        }
    }

    /// Air as the γ = 1.4 ideal gas of seed 001 eq 55
    /// ([`brisance_eos::IdealGas::air`]), inviscid.
    pub fn air() -> Self {
        Self::inviscid(EosModel::IdealGas(brisance_eos::IdealGas::air()))
    }

    /// Checks the parameters; the message names the bad field.
    pub fn validate(&self) -> Result<(), ConstitutiveError> {
        non_negative(NAME, "viscosity", self.viscosity)?;
        self.eos
            .validate()
            .map_err(|detail| ConstitutiveError::Eos {
                model: NAME,
                detail,
            })
    }

    /// Whether the deviatoric stress is the viscous 2μ dev(D) (μ > 0): the
    /// stress then depends on the current rate of deformation, not only on
    /// the state.
    pub fn is_viscous(&self) -> bool {
        self.viscosity > 0.0
    }
}

/// The null-material stress −p I + 2μ dev(D) and the viscous dissipation
/// 2μ dev(D):dev(D) Δt (J/m³). `p` in Pa (compression positive), `d` the
/// rate of deformation in 1/s, `viscosity` μ in Pa·s, `dt` in s.
#[inline]
pub fn null_stress(p: f64, d: &Mat3, viscosity: f64, dt: f64) -> (Mat3, f64) {
    let viscous = 2.0 * viscosity * deviator(d);
    let dissipation = viscous.component_mul(&deviator(d)).sum() * dt;
    (viscous - Mat3::identity() * p, dissipation)
}

impl Material for NullMaterial {
    fn name(&self) -> &'static str {
        NAME
    }

    fn history_len(&self) -> usize {
        0
    }

    fn init_history(&self, _history: &mut [f64]) {}

    fn update_stress(&self, input: &StressUpdateInput, _history: &mut [f64]) -> StressUpdate {
        let p = self
            .eos
            .pressure(input.density, input.specific_internal_energy);
        let d = rate_of_deformation(&input.velocity_gradient);
        let (stress, dissipation) = null_stress(p, &d, self.viscosity, input.dt);
        StressUpdate {
            stress,
            plastic_work: dissipation.max(0.0),
            failed: false,
        }
    }

    fn eos(&self) -> Option<&dyn Eos> {
        Some(&self.eos)
    }

    /// The EOS sound speed c(ρ, e), m/s: a fluid has no shear stiffness.
    /// (The viscous time-step limit Δt ≤ ρ h²/(2μ) belongs to the solver,
    /// which knows the cell size h.)
    fn wave_speed(&self, density: f64, specific_internal_energy: f64) -> f64 {
        self.eos.sound_speed(density, specific_internal_energy)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use brisance_eos::{IdealGas, Jwl};

    fn update(m: &NullMaterial, l: Mat3, rho: f64, e: f64) -> StressUpdate {
        let input = StressUpdateInput {
            velocity_gradient: l,
            dt: 1e-6,
            density: rho,
            temperature: 300.0,
            specific_internal_energy: e,
            stress: Mat3::new(1.0, 2.0, 3.0, 2.0, 5.0, 6.0, 3.0, 6.0, 9.0),
        };
        m.update_stress(&input, &mut [])
    }

    fn shear_and_stretch() -> Mat3 {
        Mat3::new(300.0, 1000.0, 0.0, -200.0, -100.0, 50.0, 0.0, 0.0, 400.0)
    }

    #[test]
    fn pressure_is_the_eos_pressure_and_the_deviator_is_zero_without_viscosity() {
        let m = NullMaterial::air();
        // Seed 001 eq 55 with ρ = 1.225 kg/m³, e = 2.0685e5 J/kg:
        // p = 0.4 × 1.225 × 2.0685e5 = 101 356.5 Pa.
        let out = update(&m, shear_and_stretch(), 1.225, 2.0685e5);
        let p: f64 = 0.4 * 1.225 * 2.0685e5;
        assert!((p - 101_356.5).abs() < 1e-6);
        for i in 0..3 {
            for j in 0..3 {
                let expected = if i == j { -p } else { 0.0 };
                assert!(
                    (out.stress[(i, j)] - expected).abs() <= 1e-9 * p,
                    "{}",
                    out.stress
                );
            }
        }
        assert_eq!(out.plastic_work, 0.0);
        assert!(!out.failed);
    }

    #[test]
    fn viscous_deviator_is_two_mu_dev_d() {
        let m = NullMaterial {
            viscosity: 1.8e-5,
            ..NullMaterial::air()
        };
        let l = shear_and_stretch();
        let out = update(&m, l, 1.225, 2.0685e5);
        let p = 0.4 * 1.225 * 2.0685e5;
        // D = sym L: diag(300, −100, 400), D_xy = (1000 − 200)/2 = 400,
        // D_yz = 25; tr D/3 = 200 → dev D = diag(100, −300, 200).
        let mu = 1.8e-5;
        let expected = Mat3::new(
            2.0 * mu * 100.0 - p,
            2.0 * mu * 400.0,
            0.0,
            2.0 * mu * 400.0,
            2.0 * mu * -300.0 - p,
            2.0 * mu * 25.0,
            0.0,
            2.0 * mu * 25.0,
            2.0 * mu * 200.0 - p,
        );
        assert!(
            (out.stress - expected).norm() <= 1e-12 * p,
            "{} vs {expected}",
            out.stress
        );
        // Dissipation 2μ dev D : dev D Δt with dev D : dev D =
        // 100² + 300² + 200² + 2(400² + 25²) = 461 250 s⁻².
        let w = 2.0 * mu * 461_250.0 * 1e-6;
        assert!(
            (out.plastic_work - w).abs() <= 1e-12 * w,
            "{}",
            out.plastic_work
        );
    }

    #[test]
    fn stress_ignores_the_previous_stress() {
        let m = NullMaterial::air();
        let a = update(&m, Mat3::zeros(), 1.0, 2.5e5);
        let expected = -Mat3::identity() * (0.4 * 2.5e5);
        assert!((a.stress - expected).norm() <= 1e-12 * 1e5, "{}", a.stress);
    }

    #[test]
    fn wave_speed_is_the_eos_sound_speed() {
        let m = NullMaterial::air();
        let c = m.wave_speed(1.225, 2.0685e5);
        // Ideal gas: c = √(γ p/ρ) = √(1.4 × 0.4 × 2.0685e5) = 340.35 m/s.
        let expected = (1.4_f64 * 0.4 * 2.0685e5).sqrt();
        assert!((c - expected).abs() < 1e-9 * expected, "{c}");
        assert!((c - 340.35).abs() < 0.01, "{c}");
        let products = NullMaterial::inviscid(EosModel::Jwl(Jwl::tnt()));
        assert_eq!(
            products.wave_speed(1630.0, 4e6),
            Jwl::tnt().sound_speed(1630.0, 4e6)
        );
    }

    #[test]
    fn validate_names_the_bad_field() {
        let bad = NullMaterial {
            viscosity: -1.0,
            ..NullMaterial::air()
        };
        assert!(bad
            .validate()
            .unwrap_err()
            .to_string()
            .contains("viscosity"));
        let bad_eos = NullMaterial::inviscid(EosModel::IdealGas(IdealGas::new(0.5, 717.6, 1.225)));
        let msg = bad_eos.validate().unwrap_err().to_string();
        assert!(msg.contains("gamma"), "{msg}");
    }
}
