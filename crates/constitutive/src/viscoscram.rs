//! ViscoSCRAM: the viscoelastic, statistical-crack model of a polymer-bonded
//! explosive (seed 000 §4.1.2, its ref \[19\]: Hackett & Bennett 2000, after
//! Bennett, Haberman, Johnson, Asay & Henson 1998, "A constitutive model for
//! the non-shock ignition and mechanical response of high explosives",
//! J. Mech. Phys. Solids 46:2303).
//!
//! The deviatoric stress S is the sum of the stresses s_n of five Maxwell
//! elements (a spring G_n in series with a dashpot of relaxation time τ_n,
//! in parallel), in series with the compliance of an isotropic array of
//! penny-shaped microcracks of mean radius c: the deviatoric strain rate ė
//! splits into a viscoelastic part and the crack part
//! ė_c = d/dt[(c/a)³ S/(2G)], G = Σ G_n, a the crack-size parameter. Solved
//! for the stress rates:
//!
//! ```text
//! Ṡ   = [2G ė − Σ_m s_m/τ_m − θ S] / (1 + (c/a)³),   θ = 3 (c/a)³ ċ/c,
//! ṡ_n = 2G_n ė − s_n/τ_n − (G_n/G) [θ S + (c/a)³ Ṡ],
//! ```
//!
//! (their sum is Ṡ). The cracks grow at a rate set by the stress intensity
//! K_I = σ_eff √(πc) against the toughness:
//!
//! ```text
//! ċ = v_max (K_I/K₁)^m                  K_I < K',
//! ċ = v_max [1 − (K₀μ/K_I)²]            K_I ≥ K',
//! K' = K₀μ √(1 + 2/m),   K₁ = K' (1 + m/2)^{1/m}
//! ```
//!
//! (the two branches meet at K'). σ_eff is the von Mises stress √(3/2 S:S)
//! under compression (σ_m = tr σ/3 ≤ 0) and √(3/2 σ:σ) under tension. In
//! compression the crack faces rub: the toughness rises to
//! K₀μ = K₀ √(1 + π f (1 + f)) with f = −μ' σ_m √c / K₀ and
//! μ' = μ √(45/(2(3 − 2μ²))), μ the friction coefficient of the faces; in
//! tension K₀μ = K₀.
//!
//! The pressure comes from the [`PressureModel`] (a bulk modulus or the
//! explosive's EOS). The update runs in the unrotated frame of the chosen
//! [`ObjectiveRate`] and integrates (c, s₁…s₅) with the classical
//! fourth-order Runge–Kutta method, the step split so that no substep
//! exceeds half the shortest relaxation time.
//!
//! Heat (returned as the step's dissipated work, J/m³): the dashpots'
//! Σ s_n:s_n/(2G_n τ_n) and the cracks' θ S:S/(4G), the energy released as
//! the cracks grow at fixed stress (the stress power into the crack
//! compliance minus the rise of the energy it stores, (c/a)³ S:S/(4G)).
//! Both are ≥ 0, so the dissipation is too. docs/physics/constitutive/
//! viscoscram.md writes down where the literature leaves a choice.

use crate::{
    error::{non_negative, positive},
    hypoelastic::deviator,
    objective::rate_of_deformation,
    ConstitutiveError, ObjectiveRate, PressureModel,
};
use brisance_core::{Eos, Mat3, Material, StressUpdate, StressUpdateInput};
use serde::{Deserialize, Serialize};

const NAME: &str = "visco_scram";

/// Number of Maxwell elements.
pub const ELEMENTS: usize = 5;

/// History index of the crack radius c, m.
pub const CRACK_RADIUS_INDEX: usize = 0;

/// Values before the objective rate's rotation history: c, then the five
/// element stresses (six Voigt components each: xx, yy, zz, yz, xz, xy).
pub const STATE_HISTORY_LEN: usize = 1 + 6 * ELEMENTS;

/// Largest substep as a fraction of the shortest relaxation time.
const SUBSTEP_FRACTION: f64 = 0.5;

/// Most substeps in one update (a step of 2000 relaxation times; longer
/// steps are integrated with larger substeps, which RK4 keeps stable up to
/// Δt/τ ≈ 2.8).
const MAX_SUBSTEPS: usize = 4000;

/// The ViscoSCRAM parameters.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ViscoScram {
    /// Shear moduli G_n of the Maxwell elements, Pa.
    pub shear_moduli: [f64; ELEMENTS],
    /// Inverse relaxation times 1/τ_n, 1/s (0: a spring without dashpot).
    pub inverse_relaxation_times: [f64; ELEMENTS],
    /// Pressure from a bulk modulus or an equation of state.
    pub pressure: PressureModel,
    /// Crack-size parameter a, m.
    pub crack_size: f64,
    /// Initial mean crack radius c₀, m.
    pub initial_crack_radius: f64,
    /// Exponent m of the slow-growth branch.
    pub crack_power: f64,
    /// Largest crack growth speed v_max, m/s.
    pub max_crack_speed: f64,
    /// Fracture toughness K₀, Pa·√m.
    pub fracture_toughness: f64,
    /// Friction coefficient μ of the crack faces.
    pub crack_friction: f64,
    /// Objective stress rate.
    #[serde(default)]
    pub rate: ObjectiveRate,
}

impl ViscoScram {
    /// PBX-9501 as seed 000's cook-off ran it (§5.3, its ref \[19\]): the
    /// Maxwell spectrum and crack parameters of Uintah's
    /// `ViscoSCRAMPBX9501.xml` (G_n 350, 173.9, 521.2, 908.5, 687.5 MPa;
    /// 1/τ_n 0, 7.32e3, 7.32e4, 7.32e5, 2e6 1/s; a 1 mm, c₀ 30 µm, m 10,
    /// v_max 300 m/s, K₀ 500 Pa√m, μ 0.35) and Poisson's ratio 0.3 for
    /// the bulk modulus, K = 2G(1 + ν)/(3(1 − 2ν)) = 5.72 GPa.
    pub fn pbx_9501(rate: ObjectiveRate) -> Self {
        let shear_moduli = [3.5e8, 1.739e8, 5.212e8, 9.085e8, 6.875e8];
        let g: f64 = shear_moduli.iter().sum();
        let nu = 0.3;
        Self {
            shear_moduli,
            inverse_relaxation_times: [0.0, 7.32e3, 7.32e4, 7.32e5, 2.0e6],
            pressure: PressureModel::Linear {
                bulk_modulus: 2.0 * g * (1.0 + nu) / (3.0 * (1.0 - 2.0 * nu)),
            },
            crack_size: 1.0e-3,
            initial_crack_radius: 3.0e-5,
            crack_power: 10.0,
            max_crack_speed: 300.0,
            fracture_toughness: 500.0,
            crack_friction: 0.35,
            rate,
        }
    }

    /// Checks the parameters; the message names the bad field.
    pub fn validate(&self) -> Result<(), ConstitutiveError> {
        const MODULI: [&str; ELEMENTS] = [
            "shear_moduli.0",
            "shear_moduli.1",
            "shear_moduli.2",
            "shear_moduli.3",
            "shear_moduli.4",
        ];
        const RATES: [&str; ELEMENTS] = [
            "inverse_relaxation_times.0",
            "inverse_relaxation_times.1",
            "inverse_relaxation_times.2",
            "inverse_relaxation_times.3",
            "inverse_relaxation_times.4",
        ];
        for k in 0..ELEMENTS {
            positive(NAME, MODULI[k], self.shear_moduli[k])?;
            non_negative(NAME, RATES[k], self.inverse_relaxation_times[k])?;
        }
        positive(NAME, "crack_size", self.crack_size)?;
        positive(NAME, "initial_crack_radius", self.initial_crack_radius)?;
        positive(NAME, "crack_power", self.crack_power)?;
        non_negative(NAME, "max_crack_speed", self.max_crack_speed)?;
        positive(NAME, "fracture_toughness", self.fracture_toughness)?;
        // 3 − 2μ² > 0 for μ' to exist.
        if !(self.crack_friction.is_finite()
            && self.crack_friction >= 0.0
            && self.crack_friction < 1.5f64.sqrt())
        {
            return Err(ConstitutiveError::InvalidParameter {
                model: NAME,
                field: "crack_friction",
                value: self.crack_friction,
                expected: "a value in [0, √1.5)",
            });
        }
        self.pressure.validate(NAME)
    }

    /// Total shear modulus G = Σ G_n, Pa.
    pub fn shear_modulus(&self) -> f64 {
        self.shear_moduli.iter().sum()
    }

    /// K₀μ, the toughness against the mean stress σ_m (Pa, tension
    /// positive) at crack radius c.
    pub fn toughness(&self, c: f64, mean_stress: f64) -> f64 {
        let k0 = self.fracture_toughness;
        if mean_stress >= 0.0 {
            return k0;
        }
        let mu = self.crack_friction;
        let mu_prime = mu * (45.0 / (2.0 * (3.0 - 2.0 * mu * mu))).sqrt();
        let f = -mu_prime * mean_stress * c.sqrt() / k0;
        k0 * (1.0 + std::f64::consts::PI * f * (1.0 + f)).sqrt()
    }

    /// ċ, m/s, for crack radius c, deviatoric stress S and mean stress σ_m.
    pub fn crack_speed(&self, c: f64, s: &Mat3, mean_stress: f64) -> f64 {
        let ss = s.component_mul(s).sum();
        let sigma2 = if mean_stress > 0.0 {
            ss + 3.0 * mean_stress * mean_stress
        } else {
            ss
        };
        let k_i = (1.5 * sigma2).sqrt() * (std::f64::consts::PI * c).sqrt();
        let m = self.crack_power;
        let k0mu = self.toughness(c, mean_stress);
        let k_prime = k0mu * (1.0 + 2.0 / m).sqrt();
        if k_i < k_prime {
            let k1 = k_prime * (1.0 + 0.5 * m).powf(1.0 / m);
            self.max_crack_speed * (k_i / k1).powf(m)
        } else {
            self.max_crack_speed * (1.0 - (k0mu / k_i).powi(2))
        }
    }

    /// The rates (ċ, ṡ_n) and the dissipation rate (W/m³) at the state
    /// (c, s_n) under the deviatoric strain rate `e` and mean stress σ_m.
    // The element index runs over several parallel arrays.
    #[allow(clippy::needless_range_loop)]
    fn rates(
        &self,
        c: f64,
        s: &[Mat3; ELEMENTS],
        e: &Mat3,
        mean_stress: f64,
    ) -> (f64, [Mat3; ELEMENTS], f64) {
        let g = self.shear_modulus();
        let total: Mat3 = s.iter().sum();
        let cdot = self.crack_speed(c, &total, mean_stress);
        let ca3 = (c / self.crack_size).powi(3);
        let theta = 3.0 * ca3 * cdot / c;
        let mut relax = Mat3::zeros();
        let mut viscous = 0.0;
        for k in 0..ELEMENTS {
            let r = self.inverse_relaxation_times[k];
            relax += s[k] * r;
            viscous += s[k].component_mul(&s[k]).sum() * r / (2.0 * self.shear_moduli[k]);
        }
        let total_rate = (e * (2.0 * g) - relax - total * theta) / (1.0 + ca3);
        let coupling = total * theta + total_rate * ca3;
        let mut sdot = [Mat3::zeros(); ELEMENTS];
        for k in 0..ELEMENTS {
            let gk = self.shear_moduli[k];
            sdot[k] =
                e * (2.0 * gk) - s[k] * self.inverse_relaxation_times[k] - coupling * (gk / g);
        }
        let cracking = theta * total.component_mul(&total).sum() / (4.0 * g);
        (cdot, sdot, viscous + cracking)
    }

    /// One RK4 step of length h from (c, s): the new state and the heat
    /// dissipated over it, J/m³.
    #[allow(clippy::needless_range_loop)]
    fn rk4(
        &self,
        c: f64,
        s: &[Mat3; ELEMENTS],
        e: &Mat3,
        mean_stress: f64,
        h: f64,
    ) -> (f64, [Mat3; ELEMENTS], f64) {
        let shifted = |k: &[Mat3; ELEMENTS], f: f64| {
            let mut out = *s;
            for (o, d) in out.iter_mut().zip(k) {
                *o += d * f;
            }
            out
        };
        let (c1, k1, q1) = self.rates(c, s, e, mean_stress);
        let (c2, k2, q2) = self.rates(c + 0.5 * h * c1, &shifted(&k1, 0.5 * h), e, mean_stress);
        let (c3, k3, q3) = self.rates(c + 0.5 * h * c2, &shifted(&k2, 0.5 * h), e, mean_stress);
        let (c4, k4, q4) = self.rates(c + h * c3, &shifted(&k3, h), e, mean_stress);
        let mut out = *s;
        for k in 0..ELEMENTS {
            out[k] += (k1[k] + (k2[k] + k3[k]) * 2.0 + k4[k]) * (h / 6.0);
        }
        let c_new = c + (c1 + 2.0 * (c2 + c3) + c4) * (h / 6.0);
        // The cracks never heal: each stage rate is ≥ 0.
        (c_new.max(c), out, (q1 + 2.0 * (q2 + q3) + q4) * (h / 6.0))
    }

    /// Number of substeps for a step `dt`.
    fn substeps(&self, dt: f64) -> usize {
        let fastest = self
            .inverse_relaxation_times
            .iter()
            .fold(0.0_f64, |a, &b| a.max(b));
        let n = (dt * fastest / SUBSTEP_FRACTION).ceil();
        if n.is_finite() && n >= 1.0 {
            (n as usize).min(MAX_SUBSTEPS)
        } else {
            1
        }
    }
}

/// Reads the symmetric tensor stored as Voigt xx, yy, zz, yz, xz, xy.
fn read_voigt(v: &[f64]) -> Mat3 {
    Mat3::new(v[0], v[5], v[4], v[5], v[1], v[3], v[4], v[3], v[2])
}

/// Writes the symmetric part of `m` as Voigt xx, yy, zz, yz, xz, xy.
fn write_voigt(m: &Mat3, v: &mut [f64]) {
    v[0] = m[(0, 0)];
    v[1] = m[(1, 1)];
    v[2] = m[(2, 2)];
    v[3] = 0.5 * (m[(1, 2)] + m[(2, 1)]);
    v[4] = 0.5 * (m[(0, 2)] + m[(2, 0)]);
    v[5] = 0.5 * (m[(0, 1)] + m[(1, 0)]);
}

impl Material for ViscoScram {
    fn name(&self) -> &'static str {
        NAME
    }

    fn history_len(&self) -> usize {
        STATE_HISTORY_LEN + self.rate.history_len()
    }

    fn init_history(&self, history: &mut [f64]) {
        history[..STATE_HISTORY_LEN].fill(0.0);
        history[CRACK_RADIUS_INDEX] = self.initial_crack_radius;
        self.rate.init_history(&mut history[STATE_HISTORY_LEN..]);
    }

    fn update_stress(&self, input: &StressUpdateInput, history: &mut [f64]) -> StressUpdate {
        let l = &input.velocity_gradient;
        let (state, rotation) = history.split_at_mut(STATE_HISTORY_LEN);
        let frames = self.rate.advance_or_jaumann(l, input.dt, rotation);
        let d = rate_of_deformation(l);
        let e = deviator(&frames.unrotate_end(&d));
        let mut s = [Mat3::zeros(); ELEMENTS];
        for (k, sk) in s.iter_mut().enumerate() {
            *sk = frames.unrotate_start(&read_voigt(&state[1 + 6 * k..7 + 6 * k]));
        }
        let mean_stress = input.stress.trace() / 3.0;
        let mut c = state[CRACK_RADIUS_INDEX];
        let n = self.substeps(input.dt);
        let h = input.dt / n as f64;
        let mut heat = 0.0;
        for _ in 0..n {
            let (c_new, s_new, q) = self.rk4(c, &s, &e, mean_stress, h);
            c = c_new;
            s = s_new;
            heat += q;
        }
        let mut total = Mat3::zeros();
        state[CRACK_RADIUS_INDEX] = c;
        for (k, sk) in s.iter().enumerate() {
            let spatial = frames.rotate_end(sk);
            write_voigt(&spatial, &mut state[1 + 6 * k..7 + 6 * k]);
            total += read_voigt(&state[1 + 6 * k..7 + 6 * k]);
        }
        let p = self.pressure.pressure(
            -mean_stress,
            d.trace(),
            input.dt,
            input.density,
            input.specific_internal_energy,
        );
        StressUpdate {
            stress: total - Mat3::identity() * p,
            plastic_work: heat.max(0.0),
            failed: false,
        }
    }

    fn eos(&self) -> Option<&dyn Eos> {
        self.pressure.eos()
    }

    /// c_L = √(c_bulk² + 4G/(3ρ)) with the instantaneous (unrelaxed)
    /// G = Σ G_n, m/s.
    fn wave_speed(&self, density: f64, specific_internal_energy: f64) -> f64 {
        self.pressure.longitudinal_wave_speed(
            density,
            specific_internal_energy,
            self.shear_modulus(),
        )
    }
}

pub mod cases;

#[cfg(test)]
mod tests;
