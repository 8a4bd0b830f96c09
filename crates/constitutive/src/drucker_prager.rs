//! Drucker–Prager soil with shear and tension failure, seed 001 §4.4
//! (eqs 59–63, after the FLAC3D Drucker–Prager model, Itasca 2005).
//!
//! With tension positive, τ = √J₂ the effective shear stress (Pa) and
//! σ_m = I₁/3 the mean ("spheric") stress (Pa), the two yield functions are
//!
//! - shear (eq 62): f^s = τ + q_φ σ_m − k_φ,
//! - tension (eq 63): f^t = σ_m − σ^t,
//!
//! and the corner between them is split by (eqs 59–61)
//!
//! h = τ − τ^p − α^p (σ_m − σ^t),  τ^p = k_φ − q_φ σ^t,
//! α^p = √(1 + q_φ²) − q_φ.
//!
//! One step, in the unrotated frame of the [`ObjectiveRate`] (seed 001
//! eq 30 for Jaumann):
//!
//! 1. Elastic trial ŝ* = ŝ_n + 2G dev(d̂) Δt, σ_m* = σ_m,n + K tr(d̂) Δt.
//! 2. If f^s ≤ 0 and f^t ≤ 0 the step is elastic.
//! 3. Shear return if h > 0 (seed 001: "when h > 0, shear failure is
//!    employed"): the plastic potential g^s = τ + q_ψ σ_m (q_ψ the dilation
//!    coefficient, 0 for a non-dilatant soil, q_φ for associated flow) gives
//!    λ = f^s/(G + K q_φ q_ψ), τ = τ* − G λ, σ_m = σ_m* − K q_ψ λ.
//!    Should that land beyond the tension cutoff (σ_m > σ^t, possible past
//!    the apex), the point returns to the corner (σ^t, τ^p).
//! 4. Tension return otherwise ("if h < 0, tension failure"): σ_m = σ^t and
//!    τ = min(τ*, τ^p) — the deviator is kept unless it lies above the
//!    cone at the cutoff, where it is cut to the corner ("apex return").
//!
//! The deviator is scaled radially, ŝ = ŝ* τ/τ*. The plastic work is
//! Δw_p = σ:Δε^p with Δε^p = C⁻¹(σ* − σ): deviatoric ŝ:(ŝ* − ŝ)/(2G) plus
//! volumetric σ_m (σ_m* − σ_m)/K, J/m³.
//!
//! History per point: the equivalent plastic shear strain
//! ε̄_p = Σ Δτ/(√3 G) (the von Mises measure of Δe^p = Δŝ/(2G)), the
//! plastic volumetric strain Σ (σ_m* − σ_m)/K (dilation positive), then the
//! objective rate's own history.

use crate::{
    error::{non_negative, positive},
    hypoelastic::deviator,
    objective::rate_of_deformation,
    ConstitutiveError, ObjectiveRate,
};
use brisance_core::{Eos, Mat3, Material, StressUpdate, StressUpdateInput};
use serde::{Deserialize, Serialize};

const NAME: &str = "drucker_prager";

/// History index of the equivalent plastic shear strain.
pub const PLASTIC_STRAIN_INDEX: usize = 0;
/// History index of the plastic volumetric strain (dilation positive).
pub const PLASTIC_VOLUMETRIC_STRAIN_INDEX: usize = 1;
/// Number of history values before the objective rate's own.
pub const SCALAR_HISTORY_LEN: usize = 2;

/// How the cone constants (k_φ, q_φ) are fitted to a Mohr–Coulomb
/// cohesion c and friction angle φ (Itasca 2005, FLAC3D Drucker–Prager
/// model; seed 001 §4.4 says only that they "can be obtained from the
/// cohesion and frictional angle").
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum ConeFit {
    /// The cone through the Mohr–Coulomb compression meridian (outer cone):
    /// q_φ = 6 sin φ/(√3 (3 − sin φ)), k_φ = 6 c cos φ/(√3 (3 − sin φ)).
    Compression,
    /// Plane-strain match: q_φ = 3 tan φ/√(9 + 12 tan² φ),
    /// k_φ = 3 c/√(9 + 12 tan² φ).
    PlaneStrain,
}

impl ConeFit {
    /// (k_φ in Pa, q_φ) from the cohesion `c` (Pa) and friction angle `phi`
    /// (rad).
    pub fn cone(self, c: f64, phi: f64) -> (f64, f64) {
        match self {
            Self::Compression => {
                let den = 3.0_f64.sqrt() * (3.0 - phi.sin());
                (6.0 * c * phi.cos() / den, 6.0 * phi.sin() / den)
            }
            Self::PlaneStrain => {
                let t = phi.tan();
                let den = (9.0 + 12.0 * t * t).sqrt();
                (3.0 * c / den, 3.0 * t / den)
            }
        }
    }
}

/// Which part of the yield surface a step returned to.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum DpRegime {
    /// Inside both surfaces: elastic.
    Elastic,
    /// Returned to the shear cone f^s = 0 (seed 001 eq 62).
    Shear,
    /// Returned to the tension cutoff f^t = 0 (seed 001 eq 63).
    Tension,
    /// Returned to the corner (σ^t, τ^p) of cone and cutoff.
    Corner,
}

/// The state after the return mapping.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DpReturn {
    /// Deviatoric stress, Pa.
    pub deviator: Mat3,
    /// Mean stress σ_m = I₁/3, Pa (tension positive).
    pub mean_stress: f64,
    /// Which surface was reached.
    pub regime: DpRegime,
}

/// Drucker–Prager soil (seed 001 §4.4).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DruckerPrager {
    /// Shear modulus G, Pa.
    pub shear_modulus: f64,
    /// Bulk modulus K, Pa.
    pub bulk_modulus: f64,
    /// Cone constant k_φ (eq 62), Pa.
    pub k_phi: f64,
    /// Cone slope q_φ (eq 62), dimensionless.
    pub q_phi: f64,
    /// Tensile strength σ^t (eq 63), Pa; at most the apex k_φ/q_φ.
    pub tensile_strength: f64,
    /// Dilation coefficient q_ψ of the shear potential τ + q_ψ σ_m, in
    /// [0, q_φ] (0: no dilation, the FLAC3D default).
    #[serde(default)]
    pub q_psi: f64,
    /// Objective stress rate.
    #[serde(default)]
    pub rate: ObjectiveRate,
}

/// τ = √J₂ = √(½ s:s) of a deviator, Pa.
#[inline]
pub fn effective_shear_stress(s: &Mat3) -> f64 {
    (0.5 * s.component_mul(s).sum()).sqrt()
}

impl DruckerPrager {
    /// The soil of seed 001 §4.4, from Luccioni & Luege (2006): E = 100 MPa,
    /// ν = 0.3, cohesion c = 0.11 MPa, friction angle φ = 20° (ρ = 1200
    /// kg/m³ is the solver's initial density). G = E/(2(1 + ν)),
    /// K = E/(3(1 − 2ν)). The seed does not say how k_φ and q_φ were fitted;
    /// the compression (outer) cone is used. It quotes no tensile strength:
    /// σ^t is the apex k_φ/q_φ = c cot φ, the largest value FLAC3D allows,
    /// so the soil fails in tension only where the cone closes.
    pub fn soil_luccioni_luege_2006() -> Self {
        let (e, nu) = (100.0e6, 0.3);
        Self::from_mohr_coulomb(
            e / (2.0 * (1.0 + nu)),
            e / (3.0 * (1.0 - 2.0 * nu)),
            0.11e6,
            20.0_f64.to_radians(),
            ConeFit::Compression,
        )
    }

    /// A non-dilatant soil from elastic moduli (Pa), a Mohr–Coulomb
    /// cohesion (Pa) and friction angle (rad); the tension cutoff at the
    /// apex k_φ/q_φ; Jaumann rate.
    pub fn from_mohr_coulomb(
        shear_modulus: f64,
        bulk_modulus: f64,
        cohesion: f64,
        friction_angle: f64,
        fit: ConeFit,
    ) -> Self {
        let (k_phi, q_phi) = fit.cone(cohesion, friction_angle);
        Self {
            shear_modulus,
            bulk_modulus,
            k_phi,
            q_phi,
            tensile_strength: k_phi / q_phi,
            q_psi: 0.0,
            rate: ObjectiveRate::Jaumann,
        }
    }

    /// Checks the parameters; the message names the bad field.
    pub fn validate(&self) -> Result<(), ConstitutiveError> {
        positive(NAME, "shear_modulus", self.shear_modulus)?;
        positive(NAME, "bulk_modulus", self.bulk_modulus)?;
        non_negative(NAME, "k_phi", self.k_phi)?;
        positive(NAME, "q_phi", self.q_phi)?;
        non_negative(NAME, "q_psi", self.q_psi)?;
        if self.q_psi > self.q_phi {
            return Err(ConstitutiveError::InvalidParameter {
                model: NAME,
                field: "q_psi",
                value: self.q_psi,
                expected: "at most q_phi (no more dilation than associated flow)",
            });
        }
        let apex = self.k_phi / self.q_phi;
        if !(self.tensile_strength >= 0.0 && self.tensile_strength <= apex * (1.0 + 1e-12)) {
            return Err(ConstitutiveError::InvalidParameter {
                model: NAME,
                field: "tensile_strength",
                value: self.tensile_strength,
                expected: "a value in [0, k_phi/q_phi] Pa (at most the cone's apex)",
            });
        }
        Ok(())
    }

    /// τ^p = k_φ − q_φ σ^t (seed 001 eq 60), Pa: the cone's τ at the cutoff.
    #[inline]
    pub fn tau_p(&self) -> f64 {
        (self.k_phi - self.q_phi * self.tensile_strength).max(0.0)
    }

    /// α^p = √(1 + q_φ²) − q_φ (seed 001 eq 61).
    #[inline]
    pub fn alpha_p(&self) -> f64 {
        (1.0 + self.q_phi * self.q_phi).sqrt() - self.q_phi
    }

    /// f^s = τ + q_φ σ_m − k_φ (seed 001 eq 62), Pa.
    #[inline]
    pub fn shear_yield(&self, tau: f64, mean_stress: f64) -> f64 {
        tau + self.q_phi * mean_stress - self.k_phi
    }

    /// f^t = σ_m − σ^t (seed 001 eq 63), Pa.
    #[inline]
    pub fn tension_yield(&self, mean_stress: f64) -> f64 {
        mean_stress - self.tensile_strength
    }

    /// h = τ − τ^p − α^p (σ_m − σ^t) (seed 001 eq 59), Pa: > 0 selects the
    /// shear return, ≤ 0 the tension return.
    #[inline]
    pub fn region(&self, tau: f64, mean_stress: f64) -> f64 {
        tau - self.tau_p() - self.alpha_p() * (mean_stress - self.tensile_strength)
    }

    /// The return mapping of a trial deviator `s_trial` (Pa) and mean
    /// stress `sm_trial` (Pa) to the cone and the tension cutoff (module
    /// doc, steps 2–4).
    pub fn return_map(&self, s_trial: &Mat3, sm_trial: f64) -> DpReturn {
        let tau_trial = effective_shear_stress(s_trial);
        let f_s = self.shear_yield(tau_trial, sm_trial);
        let f_t = self.tension_yield(sm_trial);
        if f_s <= 0.0 && f_t <= 0.0 {
            return DpReturn {
                deviator: *s_trial,
                mean_stress: sm_trial,
                regime: DpRegime::Elastic,
            };
        }
        let (g, k) = (self.shear_modulus, self.bulk_modulus);
        let scaled = |tau: f64| {
            if tau_trial > 0.0 {
                s_trial * (tau / tau_trial)
            } else {
                Mat3::zeros()
            }
        };
        let corner = || DpReturn {
            deviator: scaled(self.tau_p().min(tau_trial)),
            mean_stress: self.tensile_strength,
            regime: DpRegime::Corner,
        };
        // h > 0 (seed 001 eq 59): shear. With f^t ≤ 0 and f^s > 0 the point
        // is always on the shear side of h; testing f^t as well keeps a
        // round-off sign of h from sending it to the cutoff.
        if f_s > 0.0 && (self.region(tau_trial, sm_trial) > 0.0 || f_t <= 0.0) {
            let lambda = f_s / (g + k * self.q_phi * self.q_psi);
            let tau = tau_trial - g * lambda;
            let sm = sm_trial - k * self.q_psi * lambda;
            if tau < 0.0 || self.tension_yield(sm) > 0.0 {
                return corner();
            }
            return DpReturn {
                deviator: scaled(tau),
                mean_stress: sm,
                regime: DpRegime::Shear,
            };
        }
        // Tension (h ≤ 0, f^t > 0): σ_m to the cutoff; a deviator above the
        // cone there goes to the corner.
        if tau_trial > self.tau_p() {
            return corner();
        }
        DpReturn {
            deviator: *s_trial,
            mean_stress: self.tensile_strength,
            regime: DpRegime::Tension,
        }
    }

    /// The larger of f^s and f^t at a stress (Pa), and the scale of their
    /// round-off, τ + (1 + q_φ)|σ_m| + k_φ + σ^t (Pa): the contract checks
    /// the first is ≤ 0 to a small fraction of the second.
    pub fn yield_excess(&self, stress: &Mat3) -> (f64, f64) {
        let tau = effective_shear_stress(&deviator(stress));
        let sm = stress.trace() / 3.0;
        let value = self.shear_yield(tau, sm).max(self.tension_yield(sm));
        let scale = tau + (1.0 + self.q_phi) * sm.abs() + self.k_phi + self.tensile_strength.abs();
        (value, scale)
    }
}

impl Material for DruckerPrager {
    fn name(&self) -> &'static str {
        NAME
    }

    fn history_len(&self) -> usize {
        SCALAR_HISTORY_LEN + self.rate.history_len()
    }

    fn init_history(&self, history: &mut [f64]) {
        history[..SCALAR_HISTORY_LEN].fill(0.0);
        self.rate.init_history(&mut history[SCALAR_HISTORY_LEN..]);
    }

    fn update_stress(&self, input: &StressUpdateInput, history: &mut [f64]) -> StressUpdate {
        let (scalars, rate_history) = history.split_at_mut(SCALAR_HISTORY_LEN);
        let l = &input.velocity_gradient;
        let dt = input.dt;
        let frames = self.rate.advance_or_jaumann(l, dt, rate_history);
        let d_hat = frames.unrotate_end(&rate_of_deformation(l));
        let sigma_hat = frames.unrotate_start(&input.stress);
        let s_trial = deviator(&sigma_hat) + 2.0 * self.shear_modulus * dt * deviator(&d_hat);
        let sm_trial = sigma_hat.trace() / 3.0 + self.bulk_modulus * d_hat.trace() * dt;
        let ret = self.return_map(&s_trial, sm_trial);
        let mut plastic_work = 0.0;
        if ret.regime != DpRegime::Elastic {
            let (g, k) = (self.shear_modulus, self.bulk_modulus);
            let dev_work = ret.deviator.component_mul(&(s_trial - ret.deviator)).sum() / (2.0 * g);
            let vol_work = ret.mean_stress * (sm_trial - ret.mean_stress) / k;
            plastic_work = (dev_work + vol_work).max(0.0);
            let d_tau = effective_shear_stress(&s_trial) - effective_shear_stress(&ret.deviator);
            scalars[PLASTIC_STRAIN_INDEX] += d_tau.max(0.0) / (3.0_f64.sqrt() * g);
            scalars[PLASTIC_VOLUMETRIC_STRAIN_INDEX] += (sm_trial - ret.mean_stress) / k;
        }
        StressUpdate {
            stress: frames.rotate_end(&ret.deviator) + Mat3::identity() * ret.mean_stress,
            plastic_work,
            failed: false,
        }
    }

    fn eos(&self) -> Option<&dyn Eos> {
        None
    }

    /// c_L = √((K + 4G/3)/ρ), m/s.
    fn wave_speed(&self, density: f64, _specific_internal_energy: f64) -> f64 {
        ((self.bulk_modulus + 4.0 * self.shear_modulus / 3.0) / density)
            .max(0.0)
            .sqrt()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    // Seed 001 §4.4 soil: E = 100 MPa, ν = 0.3, c = 0.11 MPa, φ = 20°.
    const G: f64 = 100.0e6 / 2.6;
    const K: f64 = 100.0e6 / 1.2;

    fn drive(
        m: &DruckerPrager,
        l: Mat3,
        dt: f64,
        steps: usize,
        start: Mat3,
    ) -> (Mat3, Vec<f64>, f64) {
        let mut h = vec![0.0; m.history_len()];
        m.init_history(&mut h);
        let mut sigma = start;
        let mut work = 0.0;
        for _ in 0..steps {
            let input = StressUpdateInput {
                velocity_gradient: l,
                dt,
                density: 1200.0,
                temperature: 300.0,
                specific_internal_energy: 0.0,
                stress: sigma,
            };
            let out = m.update_stress(&input, &mut h);
            sigma = out.stress;
            work += out.plastic_work;
        }
        (sigma, h, work)
    }

    fn pure_shear(rate: f64) -> Mat3 {
        Mat3::new(0.0, rate, 0.0, rate, 0.0, 0.0, 0.0, 0.0, 0.0)
    }

    #[test]
    fn soil_cone_constants_are_the_compression_fit_of_c_and_phi() {
        let m = DruckerPrager::soil_luccioni_luege_2006();
        // sin 20° = 0.342020, cos 20° = 0.939693, √3(3 − sin φ) = 4.603757:
        // q_φ = 2.052121/4.603757 = 0.445749,
        // k_φ = 6 × 0.11e6 × 0.939693/4.603757 = 134 715.5 Pa.
        assert!((m.q_phi - 0.445749).abs() < 1e-6, "{}", m.q_phi);
        assert!((m.k_phi - 134_715.46).abs() < 0.1, "{}", m.k_phi);
        // The apex k_φ/q_φ = c cot φ = 0.11e6/tan 20° = 302 222.5 Pa.
        assert!(
            (m.tensile_strength - 302_222.5).abs() < 0.1,
            "{}",
            m.tensile_strength
        );
        assert!((m.shear_modulus - G).abs() < 1e-6 && (m.bulk_modulus - K).abs() < 1e-6);
        assert!(m.validate().is_ok());
    }

    #[test]
    fn pure_shear_saturates_on_the_cone_at_tau_equal_k_phi() {
        let m = DruckerPrager::soil_luccioni_luege_2006();
        // D_xy = 10 s⁻¹, Δt = 1e-5 s: Δσ_xy = 2G × 1e-4 = 7 692.3 Pa per step;
        // σ_m stays 0, so the cone is reached at τ = |σ_xy| = k_φ.
        let (s, h, work) = drive(&m, pure_shear(10.0), 1e-5, 40, Mat3::zeros());
        let k = 134_715.46;
        assert!((s[(0, 1)] - m.k_phi).abs() <= 1e-9 * m.k_phi, "{s}");
        assert!((s[(0, 1)] - k).abs() < 0.1, "{s}");
        assert!(s.trace().abs() <= 1e-9 * k, "{s}");
        // The yield step is the 18th (17 × 7692.3 = 130 769 < k_φ <
        // 138 462 = 18 × 7692.3); 40 steps put
        // 40 × 7692.3 − k_φ = 172 977 Pa of trial stress through the return:
        // ε̄_p = 172 977/(√3 G), plastic work = k_φ × 172 977/G (each
        // plastic step dissipates τ Δτ/G).
        let excess = 40.0 * 2.0 * G * 1e-4 - m.k_phi;
        let eps_p = excess / (3.0_f64.sqrt() * G);
        assert!(
            (h[PLASTIC_STRAIN_INDEX] - eps_p).abs() <= 1e-9 * eps_p,
            "{h:?}"
        );
        let w = m.k_phi * excess / G;
        assert!((work - w).abs() <= 1e-9 * w, "{work} vs {w}");
        assert_eq!(h[PLASTIC_VOLUMETRIC_STRAIN_INDEX], 0.0);
    }

    #[test]
    fn confinement_raises_the_shear_strength_by_q_phi_times_pressure() {
        let m = DruckerPrager::soil_luccioni_luege_2006();
        // Hydrostatic compression ε_v = 3 × (−1e-3) → σ_m = K ε_v = −250 kPa.
        let (confined, _, _) = drive(&m, Mat3::identity() * -100.0, 1e-5, 1, Mat3::zeros());
        assert!(
            (confined.trace() / 3.0 + 250_000.0).abs() < 1e-6,
            "{confined}"
        );
        let (s, _, _) = drive(&m, pure_shear(10.0), 1e-5, 60, confined);
        // τ on the cone: k_φ − q_φ σ_m = 134 715.5 + 0.445749 × 250 000.
        let tau = 134_715.46 + 0.445749 * 250_000.0;
        assert!((s[(0, 1)] - tau).abs() < 0.5, "{s} vs {tau}");
        assert!((s.trace() / 3.0 + 250_000.0).abs() < 1e-6, "{s}");
    }

    #[test]
    fn hydrostatic_extension_stops_at_the_tension_cutoff() {
        let m = DruckerPrager::soil_luccioni_luege_2006();
        // ε_v per step = 3 × 1e-4: Δσ_m = 25 kPa; after 20 steps the trial
        // σ_m = 500 kPa is beyond σ^t = c cot φ = 302 222.5 Pa.
        let (s, h, _) = drive(&m, Mat3::identity() * 10.0, 1e-5, 20, Mat3::zeros());
        for i in 0..3 {
            assert!((s[(i, i)] - 302_222.5).abs() < 0.1, "{s}");
        }
        assert!(effective_shear_stress(&deviator(&s)) <= 1e-9 * 302_222.5);
        // Plastic dilation (500 000 − 302 222.5)/K.
        let ev = (20.0 * 25_000.0 - m.tensile_strength) / K;
        assert!(
            (h[PLASTIC_VOLUMETRIC_STRAIN_INDEX] - ev).abs() <= 1e-9 * ev,
            "{h:?}"
        );
    }

    #[test]
    fn tension_cutoff_below_the_apex_keeps_the_mean_stress_at_sigma_t() {
        let m = DruckerPrager {
            tensile_strength: 50.0e3,
            ..DruckerPrager::soil_luccioni_luege_2006()
        };
        // τ^p = k_φ − q_φ σ^t = 134 715.5 − 0.445749 × 50 000 = 112 428.0 Pa.
        assert!((m.tau_p() - 112_428.0).abs() < 0.1, "{}", m.tau_p());
        // Trial σ_m = 80 kPa, τ = 20 kPa: f^t > 0, h < 0 → tension; the
        // deviator is kept.
        let s_trial = Mat3::new(0.0, 20.0e3, 0.0, 20.0e3, 0.0, 0.0, 0.0, 0.0, 0.0);
        let r = m.return_map(&s_trial, 80.0e3);
        assert_eq!(r.regime, DpRegime::Tension);
        assert_eq!(r.mean_stress, 50.0e3);
        assert_eq!(r.deviator, s_trial);
        // Trial σ_m = 200 kPa, τ = 150 kPa: h = 150 000 − 112 428.0 −
        // α^p 150 000 with α^p = √(1 + q²) − q = 0.649099, h = −59 793 < 0, and
        // τ > τ^p → the corner (σ^t, τ^p).
        let s_big = s_trial * 7.5;
        let r = m.return_map(&s_big, 200.0e3);
        assert_eq!(r.regime, DpRegime::Corner);
        assert_eq!(r.mean_stress, 50.0e3);
        assert!((effective_shear_stress(&r.deviator) - m.tau_p()).abs() < 1e-9 * m.tau_p());
        // Trial σ_m = 60 kPa, τ = 300 kPa: h > 0 → shear; q_ψ = 0 keeps
        // σ_m, τ = k_φ − q_φ × 60 000 = 107 970.5 Pa ... but σ_m > σ^t
        // after the return, so the corner again.
        let r = m.return_map(&(s_trial * 15.0), 60.0e3);
        assert_eq!(r.regime, DpRegime::Corner);
        // Trial σ_m = −100 kPa, τ = 300 kPa: shear return to
        // τ = 134 715.5 + 44 574.9 = 179 290.4 Pa.
        let r = m.return_map(&(s_trial * 15.0), -100.0e3);
        assert_eq!(r.regime, DpRegime::Shear);
        assert!((effective_shear_stress(&r.deviator) - 179_290.4).abs() < 0.1);
        assert_eq!(r.mean_stress, -100.0e3);
    }

    #[test]
    fn dilatant_shear_return_lands_on_the_cone() {
        let m = DruckerPrager {
            q_psi: 0.2,
            ..DruckerPrager::soil_luccioni_luege_2006()
        };
        let s_trial = Mat3::new(0.0, 300.0e3, 0.0, 300.0e3, 0.0, 0.0, 0.0, 0.0, 0.0);
        let r = m.return_map(&s_trial, -100.0e3);
        assert_eq!(r.regime, DpRegime::Shear);
        // λ = f^s/(G + K q_φ q_ψ); σ_m = −100 kPa − K q_ψ λ.
        let f = 300.0e3 - m.q_phi * 100.0e3 - m.k_phi;
        let lambda = f / (G + K * m.q_phi * 0.2);
        assert!((r.mean_stress - (-100.0e3 - K * 0.2 * lambda)).abs() < 1e-6);
        let tau = effective_shear_stress(&r.deviator);
        assert!(m.shear_yield(tau, r.mean_stress).abs() < 1e-9 * m.k_phi);
    }

    #[test]
    fn validate_names_the_bad_field() {
        let soil = DruckerPrager::soil_luccioni_luege_2006();
        let bad = DruckerPrager {
            tensile_strength: 1.0e6,
            ..soil.clone()
        };
        assert!(bad
            .validate()
            .unwrap_err()
            .to_string()
            .contains("tensile_strength"));
        let bad = DruckerPrager { q_psi: 1.0, ..soil };
        assert!(bad.validate().unwrap_err().to_string().contains("q_psi"));
    }

    #[test]
    fn plane_strain_fit_has_the_closed_form_constants() {
        // φ = 30°, c = 1 MPa: tan φ = 0.577350, √(9 + 12 tan² φ) = √13:
        // q_φ = 1.732051/3.605551 = 0.480384, k_φ = 3e6/3.605551 = 832 050.3.
        let (k, q) = ConeFit::PlaneStrain.cone(1.0e6, 30.0_f64.to_radians());
        assert!((q - 0.480384).abs() < 1e-6, "{q}");
        assert!((k - 832_050.3).abs() < 0.1, "{k}");
    }

    /// Uniaxial strain in compression, seed 001 soil (non-dilatant): the
    /// elastic path σ_m = Kε, τ = 2G|ε|/√3 meets the cone τ + q_φσ_m = k_φ
    /// at ε_y = −k_φ/(2G/√3 − q_φK) = −134 715.5/(44.4115e6 − 37.1458e6)
    /// = −0.018541; beyond it σ_m = Kε (no plastic dilation) and
    /// τ = k_φ − q_φKε, so σ_xx = σ_m − (2/√3)τ, σ_yy = σ_m + τ/√3, and
    /// ε̄_p = (2G/√3 − q_φK)(|ε| − |ε_y|)/(√3 G).
    #[test]
    fn uniaxial_strain_follows_the_hand_computed_elastic_then_cone_path() {
        let m = DruckerPrager::soil_luccioni_luege_2006();
        let (k, q) = (m.k_phi, m.q_phi);
        let slope = 2.0 * G / 3f64.sqrt() - q * K;
        let eps_y = -k / slope;
        assert!((eps_y + 0.018_541).abs() < 1e-6, "{eps_y}");
        let (dt, rate) = (1e-5, -10.0);
        let l = Mat3::new(rate, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0);
        let mut h = vec![0.0; m.history_len()];
        m.init_history(&mut h);
        let mut sigma = Mat3::zeros();
        for step in 1..=400 {
            let input = StressUpdateInput {
                velocity_gradient: l,
                dt,
                density: 1200.0,
                temperature: 300.0,
                specific_internal_energy: 0.0,
                stress: sigma,
            };
            sigma = m.update_stress(&input, &mut h).stress;
            let eps = rate * dt * step as f64;
            let sm = K * eps;
            let tau = if eps > eps_y * (1.0 - 1e-9) {
                -2.0 * G * eps / 3f64.sqrt()
            } else if eps < eps_y * (1.0 + 1e-9) {
                k - q * K * eps
            } else {
                continue;
            };
            let (sxx, syy) = (sm - 2.0 * tau / 3f64.sqrt(), sm + tau / 3f64.sqrt());
            let scale = sm.abs().max(tau);
            assert!(
                (sigma[(0, 0)] - sxx).abs() < 1e-9 * scale,
                "ε = {eps}: {sigma}"
            );
            assert!(
                (sigma[(1, 1)] - syy).abs() < 1e-9 * scale,
                "ε = {eps}: {sigma}"
            );
            assert!(
                (sigma[(2, 2)] - syy).abs() < 1e-9 * scale,
                "ε = {eps}: {sigma}"
            );
        }
        let eps_end: f64 = rate * dt * 400.0;
        let eps_p = slope * (eps_end.abs() - eps_y.abs()) / (3f64.sqrt() * G);
        assert!(
            (h[PLASTIC_STRAIN_INDEX] - eps_p).abs() < 1e-9 * eps_p,
            "{h:?} vs {eps_p}"
        );
        assert_eq!(h[PLASTIC_VOLUMETRIC_STRAIN_INDEX], 0.0);
    }

    /// Simple shear with rotation to γ = 2 (Jaumann), seed 001 soil at zero
    /// mean stress: the radial return on the cone at σ_m = 0 is that of a
    /// J2 solid of shear strength k_φ, so the deviator reaches the same
    /// steady state as the J2 metal: s₁₁ = −s₂₂ = k_φ²/G = 471.85 Pa,
    /// s₁₂ = √(k_φ² − (k_φ²/G)²), σ_m = 0 (measured 7.5e-9 of a off the
    /// continuum steady state at Δγ = 2e-4 per step).
    #[test]
    fn simple_shear_with_rotation_reaches_the_steady_state_on_the_cone() {
        let m = DruckerPrager::soil_luccioni_luege_2006();
        let (dt, gamma_dot) = (1e-5, 20.0);
        let l = Mat3::new(0.0, gamma_dot, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0);
        let (sigma, _, _) = drive(&m, l, dt, 10_000, Mat3::zeros());
        let k = m.k_phi;
        let a = k * k / G;
        assert!((a - 471.85).abs() < 0.01, "{a}");
        let b = (k * k - a * a).sqrt();
        assert!((sigma[(0, 0)] - a).abs() < 1e-7 * a, "{sigma}");
        assert!((sigma[(1, 1)] + a).abs() < 1e-7 * a, "{sigma}");
        assert!((sigma[(0, 1)] - b).abs() < 1e-9 * b, "{sigma}");
        assert!(sigma.trace().abs() < 1e-9 * k, "{sigma}");
    }
}
