//! Isotropic hypoelasticity with an objective stress rate (seed 000 §4.2:
//! "the deviatoric part of the stress is modeled using hypoelasticity" with
//! a constant shear modulus; seed 001 eq 30 for the Jaumann update).
//!
//! In the unrotated frame of the chosen [`ObjectiveRate`],
//!
//! ŝ_{n+1} = ŝ_n + 2G dev(d̂) Δt,  p_{n+1} from the [`PressureModel`],
//! σ_{n+1} = end ŝ_{n+1} endᵀ − p_{n+1} I,
//!
//! with G the shear modulus (Pa), d̂ the unrotated rate of deformation (1/s).
//! With a linear pressure this is σ̂̇ = K tr(d̂) I + 2G dev(d̂).

use crate::{
    error::positive, objective::rate_of_deformation, ConstitutiveError, ObjectiveRate,
    PressureModel,
};
use brisance_core::{Eos, Mat3, Material, StressUpdate, StressUpdateInput};
use serde::{Deserialize, Serialize};

const NAME: &str = "hypoelastic";

/// Deviatoric part of a 3×3 tensor, A − tr(A)/3 I.
#[inline]
pub fn deviator(a: &Mat3) -> Mat3 {
    a - Mat3::identity() * (a.trace() / 3.0)
}

/// Von Mises equivalent stress √(3/2 s:s) of a deviator s, Pa.
#[inline]
pub fn von_mises(s: &Mat3) -> f64 {
    (1.5 * s.component_mul(s).sum()).sqrt()
}

/// Isotropic hypoelastic solid: shear modulus, pressure model, objective
/// rate.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Hypoelastic {
    /// Shear modulus G, Pa.
    pub shear_modulus: f64,
    /// Pressure from a bulk modulus or an equation of state.
    pub pressure: PressureModel,
    /// Objective stress rate.
    #[serde(default)]
    pub rate: ObjectiveRate,
}

impl Hypoelastic {
    /// Checks the parameters; the message names the bad field.
    pub fn validate(&self) -> Result<(), ConstitutiveError> {
        positive(NAME, "shear_modulus", self.shear_modulus)?;
        self.pressure.validate(NAME)
    }

    /// OFHC copper of seed 000 §5.2 without its yield: K = 117 GPa,
    /// G = 43.8 GPa (ρ = 8930 kg/m³ is the solver's initial density).
    pub fn ofhc_copper_seed000(rate: ObjectiveRate) -> Self {
        Self {
            shear_modulus: 43.8e9,
            pressure: PressureModel::Linear {
                bulk_modulus: 117.0e9,
            },
            rate,
        }
    }
}

impl Material for Hypoelastic {
    fn name(&self) -> &'static str {
        NAME
    }

    fn history_len(&self) -> usize {
        self.rate.history_len()
    }

    fn init_history(&self, history: &mut [f64]) {
        self.rate.init_history(history);
    }

    fn update_stress(&self, input: &StressUpdateInput, history: &mut [f64]) -> StressUpdate {
        let l = &input.velocity_gradient;
        let frames = self.rate.advance_or_jaumann(l, input.dt, history);
        let d = rate_of_deformation(l);
        let p_old = -input.stress.trace() / 3.0;
        let s_hat = deviator(&frames.unrotate_start(&input.stress))
            + 2.0 * self.shear_modulus * input.dt * deviator(&frames.unrotate_end(&d));
        let p = self.pressure.pressure(
            p_old,
            d.trace(),
            input.dt,
            input.density,
            input.specific_internal_energy,
        );
        StressUpdate {
            stress: frames.rotate_end(&s_hat) - Mat3::identity() * p,
            plastic_work: 0.0,
            failed: false,
        }
    }

    fn eos(&self) -> Option<&dyn Eos> {
        self.pressure.eos()
    }

    /// c_L = √(c_bulk² + 4G/(3ρ)), m/s.
    fn wave_speed(&self, density: f64, specific_internal_energy: f64) -> f64 {
        self.pressure
            .longitudinal_wave_speed(density, specific_internal_energy, self.shear_modulus)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const G: f64 = 43.8e9;
    const K: f64 = 117.0e9;

    fn step(m: &Hypoelastic, sigma: Mat3, l: Mat3, dt: f64, h: &mut [f64]) -> Mat3 {
        let input = StressUpdateInput {
            velocity_gradient: l,
            dt,
            density: 8930.0,
            temperature: 300.0,
            specific_internal_energy: 0.0,
            stress: sigma,
        };
        m.update_stress(&input, h).stress
    }

    /// Simple shear v_x = γ̇ y to shear strain γ in `steps` steps.
    fn simple_shear(rate: ObjectiveRate, gamma: f64, steps: usize) -> Mat3 {
        let m = Hypoelastic::ofhc_copper_seed000(rate);
        let mut h = vec![0.0; m.history_len()];
        m.init_history(&mut h);
        let dt = 1e-6;
        let gamma_dot = gamma / (steps as f64 * dt);
        let l = Mat3::new(0.0, gamma_dot, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0);
        let mut sigma = Mat3::zeros();
        for _ in 0..steps {
            sigma = step(&m, sigma, l, dt, &mut h);
        }
        sigma
    }

    #[test]
    fn uniaxial_strain_elastic_slope_is_k_plus_four_thirds_g() {
        let m = Hypoelastic::ofhc_copper_seed000(ObjectiveRate::GreenNaghdi);
        let mut h = vec![0.0; m.history_len()];
        m.init_history(&mut h);
        let (dt, eps_dot) = (1e-7, -1.0e3);
        let l = Mat3::new(eps_dot, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0);
        let mut sigma = Mat3::zeros();
        for _ in 0..100 {
            sigma = step(&m, sigma, l, dt, &mut h);
        }
        // ε = Σ D Δt = −1e-2: σ_xx = (K + 4G/3) ε, σ_yy = (K − 2G/3) ε.
        let eps = -1.0e-2;
        let sxx = (K + 4.0 * G / 3.0) * eps;
        let syy = (K - 2.0 * G / 3.0) * eps;
        assert!((sigma[(0, 0)] - sxx).abs() < 1e-9 * sxx.abs(), "{sigma}");
        assert!((sigma[(1, 1)] - syy).abs() < 1e-9 * syy.abs(), "{sigma}");
        assert!((sigma[(2, 2)] - syy).abs() < 1e-9 * syy.abs(), "{sigma}");
        assert!(sigma[(0, 1)].abs() < 1e-6, "{sigma}");
    }

    /// The Jaumann rate gives the oscillating shear stress of Dienes (1979):
    /// σ_xy = G sin γ, σ_xx = −σ_yy = G(1 − cos γ). The discrete update is
    /// first order in Δγ (measured: 2.0e-4 G at γ = π with Δγ = 2e-4); with
    /// Δγ = 5e-5 the error is below 2e-4 G up to γ = 5.
    #[test]
    fn jaumann_simple_shear_oscillates_as_g_sin_gamma() {
        for gamma in [0.5, 2.0, std::f64::consts::PI, 5.0] {
            let steps = (gamma / 5e-5) as usize;
            let s = simple_shear(ObjectiveRate::Jaumann, gamma, steps);
            let (sxy, sxx) = (G * gamma.sin(), G * (1.0 - gamma.cos()));
            assert!(
                (s[(0, 1)] - sxy).abs() < 2e-4 * G,
                "γ = {gamma}: {} vs {sxy}",
                s[(0, 1)]
            );
            assert!(
                (s[(0, 0)] - sxx).abs() < 2e-4 * G,
                "γ = {gamma}: {} vs {sxx}",
                s[(0, 0)]
            );
            assert!(
                (s[(1, 1)] + sxx).abs() < 2e-4 * G,
                "γ = {gamma}: {}",
                s[(1, 1)]
            );
        }
        // The shear stress falls after γ = π/2 and turns negative past π.
        assert!(simple_shear(ObjectiveRate::Jaumann, 4.0, 20_000)[(0, 1)] < 0.0);
    }

    /// The Green–Naghdi rate gives the monotonic shear stress of Dienes
    /// (1979), with tan β = γ/2:
    /// σ_xy = 2G cos 2β [2β − 2 tan 2β ln(cos β) − tan β],
    /// σ_xx = −σ_yy = 4G [cos 2β ln(cos β) + β sin 2β − sin² β].
    #[test]
    fn green_naghdi_simple_shear_matches_dienes_closed_form() {
        let mut previous = 0.0;
        for gamma in [0.5, 2.0, std::f64::consts::PI, 5.0] {
            let steps = (gamma / 2e-4) as usize;
            let s = simple_shear(ObjectiveRate::GreenNaghdi, gamma, steps);
            let beta = (0.5 * gamma).atan();
            let (c, t2) = (beta.cos(), (2.0 * beta).tan());
            let sxy = 2.0 * G * (2.0 * beta).cos() * (2.0 * beta - 2.0 * t2 * c.ln() - beta.tan());
            let sxx = 4.0
                * G
                * ((2.0 * beta).cos() * c.ln() + beta * (2.0 * beta).sin() - beta.sin().powi(2));
            assert!(
                (s[(0, 1)] - sxy).abs() < 2e-4 * G,
                "γ = {gamma}: {} vs {sxy}",
                s[(0, 1)]
            );
            assert!(
                (s[(0, 0)] - sxx).abs() < 2e-4 * G,
                "γ = {gamma}: {} vs {sxx}",
                s[(0, 0)]
            );
            assert!(
                (s[(1, 1)] + sxx).abs() < 2e-4 * G,
                "γ = {gamma}: {}",
                s[(1, 1)]
            );
            assert!(
                s[(0, 1)] > previous,
                "GN shear stress must rise monotonically"
            );
            previous = s[(0, 1)];
        }
    }

    #[test]
    fn wave_speed_is_the_longitudinal_speed() {
        let m = Hypoelastic::ofhc_copper_seed000(ObjectiveRate::Jaumann);
        let c = m.wave_speed(8930.0, 0.0);
        let expected = ((K + 4.0 * G / 3.0) / 8930.0).sqrt();
        assert!((c - expected).abs() < 1e-9 * expected);
        // (117e9 + 58.4e9)/8930 = 1.96417e7 → 4431.9 m/s.
        assert!((c - 4431.9).abs() < 0.1, "{c}");
    }

    #[test]
    fn validate_names_the_bad_field() {
        let bad = Hypoelastic {
            shear_modulus: f64::NAN,
            ..Hypoelastic::ofhc_copper_seed000(ObjectiveRate::Jaumann)
        };
        let msg = bad.validate().unwrap_err().to_string();
        assert!(msg.contains("shear_modulus"), "{msg}");
    }
}
