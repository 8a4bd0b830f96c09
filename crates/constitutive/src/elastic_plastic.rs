//! Hypoelastic–plastic von Mises (J2) metal with radial return, seed 000
//! §4.2 (and seed 001 §4.5 for the Johnson–Cook steel).
//!
//! One step, in the unrotated frame of the [`ObjectiveRate`]:
//!
//! 1. Trial deviator ŝ* = ŝ_n + 2G dev(d̂) Δt (hypoelastic, constant G).
//! 2. Pressure p_{n+1} from the [`PressureModel`] (seed 000 eq 40 for the
//!    shipped metals).
//! 3. If σ̄* = √(3/2 ŝ*:ŝ*) ≤ σ_y(ε_pⁿ, 0, T_n) the step is elastic.
//!    Otherwise the radial return solves
//!    σ̄* − 3G Δε_p = σ_y(ε_pⁿ + Δε_p, Δε_p/Δt, T_n)
//!    by bracketed Newton on [0, σ̄*/(3G)] and scales ŝ = ŝ*(1 − 3GΔε_p/σ̄*).
//!    The plastic strain and rate are implicit and the temperature is that
//!    of the start of the step, the semi-implicit update of seed 000 §4.2
//!    (its refs [23, 24]).
//! 4. Plastic work Δw_p = ŝ:Δε^p = σ_y Δε_p (J/m³, returned) heats the point
//!    with the Taylor–Quinney coefficient χ = 0.9 (seed 000 §4.2):
//!    ΔT = χ Δw_p/(ρ c_v), stored in the history as this step's temperature
//!    increment. The solver, which owns the temperature, adds either ΔT to
//!    T or χ Δw_p/ρ to e — one of the two, not both.
//! 5. Johnson–Cook damage (seed 000 eq 47, [`JohnsonCookDamage`]) if given.
//! 6. Failure, irreversible: D ≥ 1, or melting — T_n + ΔT ≥ T_melt of the
//!    Johnson–Cook flow stress (seed 000 §4.2 criterion 1; the flow stress
//!    is already zero there). A failed point carries σ = −max(p, 0) I: no
//!    deviatoric and no tensile stress, its pressure in compression (see
//!    [`crate::damage`]).
//!
//! History per point (indices are the `*_INDEX` constants): equivalent
//! plastic strain, plastic strain rate (1/s), damage D, this step's
//! temperature increment (K), failed flag (0 or 1), then the objective
//! rate's own history (F and R for Green–Naghdi).

use crate::{
    error::positive,
    hypoelastic::{deviator, von_mises},
    objective::rate_of_deformation,
    ConstitutiveError, FlowStress, JohnsonCookDamage, ObjectiveRate, PressureModel,
};
use brisance_core::{Eos, Mat3, Material, StressUpdate, StressUpdateInput};
use brisance_eos::{EosModel, MieGruneisenCubic, MieGruneisenLinear};
use serde::{Deserialize, Serialize};

const NAME: &str = "elastic_plastic";

/// History index of the equivalent plastic strain ε_p.
pub const PLASTIC_STRAIN_INDEX: usize = 0;
/// History index of the plastic strain rate ε̇_p, 1/s.
pub const PLASTIC_STRAIN_RATE_INDEX: usize = 1;
/// History index of the Johnson–Cook damage D.
pub const DAMAGE_INDEX: usize = 2;
/// History index of the last step's plastic-heating temperature rise, K.
pub const TEMPERATURE_INCREMENT_INDEX: usize = 3;
/// History index of the failed flag (1 failed, 0 intact).
pub const FAILED_INDEX: usize = 4;
/// Number of history values before the objective rate's own.
pub const SCALAR_HISTORY_LEN: usize = 5;

/// Taylor–Quinney coefficient of seed 000 §4.2.
pub const TAYLOR_QUINNEY_SEED000: f64 = 0.9;

fn default_taylor_quinney() -> f64 {
    TAYLOR_QUINNEY_SEED000
}

/// Radial-return tolerance on the yield residual, relative to the flow
/// stress.
const RETURN_TOLERANCE: f64 = 1.0e-13;

/// Hypoelastic–plastic J2 metal (seed 000 §4.2).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ElasticPlastic {
    /// Shear modulus G, Pa.
    pub shear_modulus: f64,
    /// Pressure from a bulk modulus or an equation of state.
    pub pressure: PressureModel,
    /// Flow stress σ_y.
    pub flow_stress: FlowStress,
    /// Johnson–Cook damage, if the metal fails by it.
    #[serde(default)]
    pub damage: Option<JohnsonCookDamage>,
    /// Objective stress rate.
    #[serde(default)]
    pub rate: ObjectiveRate,
    /// Fraction χ of plastic work turned into heat (seed 000: 0.9).
    #[serde(default = "default_taylor_quinney")]
    pub taylor_quinney: f64,
    /// Specific heat c_v for the plastic heating, J/(kg·K).
    pub specific_heat: f64,
}

/// Radial return: the plastic strain increment Δε_p solving
/// σ̄* − 3GΔε_p = σ_y(ε_pⁿ + Δε_p, Δε_p/Δt, T), for σ̄* above the flow
/// stress at Δε_p = 0. Bracketed Newton on [0, σ̄*/(3G)] (the residual is
/// positive at 0 and ≤ −σ_y at the upper end, and decreasing); bisection
/// whenever Newton leaves the bracket. Returns (Δε_p, σ_y at Δε_p).
pub fn radial_return(
    flow: &FlowStress,
    shear_modulus: f64,
    trial_von_mises: f64,
    eps_p: f64,
    dt: f64,
    t: f64,
) -> (f64, f64) {
    let three_g = 3.0 * shear_modulus;
    let inv_dt = if dt > 0.0 { 1.0 / dt } else { 0.0 };
    let rate_of = |x: f64| if dt > 0.0 { x / dt } else { 0.0 };
    let (mut lo, mut hi) = (0.0, trial_von_mises / three_g);
    // The perfectly plastic increment is an upper bound (σ_y only rises
    // with Δε_p) and the exact answer for a constant flow stress.
    let sigma0 = flow.flow_stress(eps_p, 0.0, t);
    let mut x = ((trial_von_mises - sigma0) / three_g).clamp(lo, hi);
    let mut sigma_y = sigma0;
    for _ in 0..200 {
        let (s, slope) = flow.flow_stress_and_slope(eps_p + x, rate_of(x), inv_dt, t);
        sigma_y = s;
        let f = trial_von_mises - three_g * x - s;
        if f.abs() <= RETURN_TOLERANCE * s.max(f64::MIN_POSITIVE) {
            return (x, s);
        }
        if f > 0.0 {
            lo = x;
        } else {
            hi = x;
        }
        if hi - lo <= 4.0 * f64::EPSILON * hi {
            break;
        }
        let newton = x + f / (three_g + slope);
        x = if newton > lo && newton < hi && newton.is_finite() {
            newton
        } else {
            0.5 * (lo + hi)
        };
    }
    // Bracket exhausted at round-off: take the side where σ̄ ≤ σ_y.
    let (s, _) = flow.flow_stress_and_slope(eps_p + hi, rate_of(hi), inv_dt, t);
    if trial_von_mises - three_g * hi - s <= 0.0 {
        (hi, s)
    } else {
        (x, sigma_y)
    }
}

impl ElasticPlastic {
    /// Checks the parameters; the message names the bad field.
    pub fn validate(&self) -> Result<(), ConstitutiveError> {
        positive(NAME, "shear_modulus", self.shear_modulus)?;
        self.pressure.validate(NAME)?;
        self.flow_stress.validate()?;
        if let Some(d) = &self.damage {
            d.validate()?;
        }
        if !(self.taylor_quinney >= 0.0 && self.taylor_quinney <= 1.0) {
            return Err(ConstitutiveError::InvalidParameter {
                model: NAME,
                field: "taylor_quinney",
                value: self.taylor_quinney,
                expected: "a fraction in [0, 1]",
            });
        }
        positive(NAME, "specific_heat", self.specific_heat)
    }

    /// The OFHC copper tube of seed 000 §5.2: elastic–perfectly plastic,
    /// K = 117 GPa (linear pressure), G = 43.8 GPa, σ_y = 70 MPa,
    /// ρ = 8930 kg/m³ (the solver's initial density); Green–Naghdi rate
    /// (seed 000 §4.2); c_v = 383 J/(kg·K) (Johnson & Cook 1983).
    pub fn ofhc_copper_seed000() -> Self {
        Self {
            shear_modulus: 43.8e9,
            pressure: PressureModel::Linear {
                bulk_modulus: 117.0e9,
            },
            flow_stress: FlowStress::Constant { sigma_y: 70.0e6 },
            damage: None,
            rate: ObjectiveRate::GreenNaghdi,
            taylor_quinney: TAYLOR_QUINNEY_SEED000,
            specific_heat: 383.0,
        }
    }

    /// OFHC copper with Johnson–Cook flow stress (Johnson & Cook 1983) and
    /// damage (Johnson & Cook 1985), the Mie–Grüneisen EOS
    /// [`MieGruneisenLinear::ofhc_copper`] and G = 43.8 GPa (seed 000 §5.2);
    /// Green–Naghdi rate; c_v = 383 J/(kg·K).
    pub fn ofhc_copper_johnson_cook() -> Self {
        Self {
            shear_modulus: 43.8e9,
            pressure: PressureModel::Eos(EosModel::MieGruneisenLinear(
                MieGruneisenLinear::ofhc_copper(),
            )),
            flow_stress: FlowStress::ofhc_copper_johnson_cook_1983(),
            damage: Some(JohnsonCookDamage::ofhc_copper_johnson_cook_1985()),
            rate: ObjectiveRate::GreenNaghdi,
            taylor_quinney: TAYLOR_QUINNEY_SEED000,
            specific_heat: 383.0,
        }
    }

    /// 4340 steel of seed 000 Table 1: μ = G = 80 GPa, Johnson–Cook flow
    /// stress and damage, Mie–Grüneisen EOS (eq 40,
    /// [`MieGruneisenLinear::steel_4340`]); Green–Naghdi rate (§4.2);
    /// c_v = 477 J/(kg·K) (the seed uses a temperature-dependent c_v; this is
    /// the Johnson & Cook 1983 constant). The table's K = 173.3 GPa is not
    /// used: the EOS sets the volumetric response (ρ₀C₀² = 100 GPa at the
    /// reference state).
    pub fn steel_4340_seed000() -> Self {
        Self {
            shear_modulus: 80.0e9,
            pressure: PressureModel::Eos(EosModel::MieGruneisenLinear(
                MieGruneisenLinear::steel_4340(),
            )),
            flow_stress: FlowStress::steel_4340_seed000(),
            damage: Some(JohnsonCookDamage::steel_4340_seed000()),
            rate: ObjectiveRate::GreenNaghdi,
            taylor_quinney: TAYLOR_QUINNEY_SEED000,
            specific_heat: 477.0,
        }
    }

    /// RHA steel of seed 001 §4.5: Johnson–Cook flow stress (eq 64) and the
    /// cubic Mie–Grüneisen EOS (eqs 65–66,
    /// [`MieGruneisenCubic::steel_seed001`]); Jaumann rate (seed 001
    /// eq 30); no damage (seed 001 gives none for steel). Seed 001 gives no
    /// shear modulus: G = 80 GPa, the nominal steel value (as 4340 in seed
    /// 000 Table 1); c_v = 477 J/(kg·K).
    pub fn rha_steel_seed001() -> Self {
        Self {
            shear_modulus: 80.0e9,
            pressure: PressureModel::Eos(EosModel::MieGruneisenCubic(
                MieGruneisenCubic::steel_seed001(),
            )),
            flow_stress: FlowStress::rha_steel_seed001(),
            damage: None,
            rate: ObjectiveRate::Jaumann,
            taylor_quinney: TAYLOR_QUINNEY_SEED000,
            specific_heat: 477.0,
        }
    }

    /// Flow stress at the point's history and temperature T (K), Pa.
    pub fn current_flow_stress(&self, history: &[f64], t: f64) -> f64 {
        self.flow_stress.flow_stress(
            history[PLASTIC_STRAIN_INDEX],
            history[PLASTIC_STRAIN_RATE_INDEX],
            t,
        )
    }

    fn failed_stress(p: f64) -> Mat3 {
        -Mat3::identity() * p.max(0.0)
    }
}

impl Material for ElasticPlastic {
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
        let (scalars, rotation) = history.split_at_mut(SCALAR_HISTORY_LEN);
        let l = &input.velocity_gradient;
        let dt = input.dt;
        let frames = self.rate.advance_or_jaumann(l, dt, rotation);
        let d = rate_of_deformation(l);
        let p = self.pressure.pressure(
            -input.stress.trace() / 3.0,
            d.trace(),
            dt,
            input.density,
            input.specific_internal_energy,
        );
        scalars[PLASTIC_STRAIN_RATE_INDEX] = 0.0;
        scalars[TEMPERATURE_INCREMENT_INDEX] = 0.0;
        if scalars[FAILED_INDEX] != 0.0 {
            return StressUpdate {
                stress: Self::failed_stress(p),
                plastic_work: 0.0,
                failed: true,
            };
        }

        let g = self.shear_modulus;
        let t = input.temperature;
        let s_trial = deviator(&frames.unrotate_start(&input.stress))
            + 2.0 * g * dt * deviator(&frames.unrotate_end(&d));
        let trial = von_mises(&s_trial);
        let eps_p = scalars[PLASTIC_STRAIN_INDEX];
        // On the yield surface σ̄ = σ_y; the work uses the σ_y of the return
        // (exactly 0 for a melted point) rather than σ̄, which carries the
        // round-off of the scaling.
        let (s_hat, d_eps, sigma_eq, sigma_y) =
            if trial > self.flow_stress.flow_stress(eps_p, 0.0, t) {
                let (d_eps, sigma_y) = radial_return(&self.flow_stress, g, trial, eps_p, dt, t);
                let factor = (1.0 - 3.0 * g * d_eps / trial).max(0.0);
                (s_trial * factor, d_eps, trial * factor, sigma_y)
            } else {
                (s_trial, 0.0, trial, 0.0)
            };

        let eps_rate = if dt > 0.0 { d_eps / dt } else { 0.0 };
        let plastic_work = sigma_y * d_eps;
        let d_temp = self.taylor_quinney * plastic_work / (input.density * self.specific_heat);
        scalars[PLASTIC_STRAIN_INDEX] = eps_p + d_eps;
        scalars[PLASTIC_STRAIN_RATE_INDEX] = eps_rate;
        scalars[TEMPERATURE_INCREMENT_INDEX] = d_temp;
        if let Some(damage) = &self.damage {
            scalars[DAMAGE_INDEX] =
                damage.accumulate(scalars[DAMAGE_INDEX], d_eps, -p, sigma_eq, eps_rate, t);
        }
        let melted = self
            .flow_stress
            .melt_temperature()
            .is_some_and(|t_melt| t + d_temp >= t_melt);
        if melted || scalars[DAMAGE_INDEX] >= 1.0 {
            scalars[FAILED_INDEX] = 1.0;
            return StressUpdate {
                stress: Self::failed_stress(p),
                plastic_work,
                failed: true,
            };
        }
        StressUpdate {
            stress: frames.rotate_end(&s_hat) - Mat3::identity() * p,
            plastic_work,
            failed: false,
        }
    }

    fn eos(&self) -> Option<&dyn Eos> {
        self.pressure.eos()
    }

    /// c_L = √(c_bulk² + 4G/(3ρ)), m/s.
    fn wave_speed(&self, density: f64, specific_internal_energy: f64) -> f64 {
        let c2 = self
            .pressure
            .bulk_sound_speed_squared(density, specific_internal_energy)
            + 4.0 * self.shear_modulus / (3.0 * density);
        c2.max(0.0).sqrt()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn input(l: Mat3, dt: f64, sigma: Mat3, t: f64, rho: f64) -> StressUpdateInput {
        StressUpdateInput {
            velocity_gradient: l,
            dt,
            density: rho,
            temperature: t,
            specific_internal_energy: 0.0,
            stress: sigma,
        }
    }

    fn fresh(m: &ElasticPlastic) -> Vec<f64> {
        let mut h = vec![0.0; m.history_len()];
        m.init_history(&mut h);
        h
    }

    /// Uniaxial strain in compression of the seed 000 §5.2 copper
    /// (K = 117 GPa, G = 43.8 GPa, σ_y = 70 MPa): elastic slope
    /// σ_xx = (K + 4G/3) ε up to |ε_y| = σ_y/(2G) = 7.9909e-4, then the
    /// perfectly plastic plateau σ_xx = Kε − 2σ_y/3, σ_yy = Kε + σ_y/3.
    #[test]
    fn uniaxial_strain_yields_at_hand_computed_strain_then_plateaus() {
        let m = ElasticPlastic::ofhc_copper_seed000();
        let (k, g, sy): (f64, f64, f64) = (117.0e9, 43.8e9, 70.0e6);
        let eps_y = sy / (2.0 * g);
        assert!((eps_y - 7.990_868_5e-4).abs() < 1e-10);
        let mut h = fresh(&m);
        let (dt, eps_dot) = (1e-8, -1.0e3);
        let l = Mat3::new(eps_dot, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0);
        let mut sigma = Mat3::zeros();
        let mut eps: f64 = 0.0;
        for _ in 0..500 {
            let out = m.update_stress(&input(l, dt, sigma, 300.0, 8930.0), &mut h);
            sigma = out.stress;
            eps += eps_dot * dt;
            let (sxx, syy) = (sigma[(0, 0)], sigma[(1, 1)]);
            if eps.abs() < eps_y * (1.0 - 1e-9) {
                assert_eq!(out.plastic_work, 0.0, "yielded early at ε = {eps}");
                let expected = (k + 4.0 * g / 3.0) * eps;
                assert!(
                    (sxx - expected).abs() < 1e-9 * expected.abs(),
                    "ε = {eps}: {sxx}"
                );
            } else if eps.abs() > eps_y * (1.0 + 1e-9) {
                let (exx, eyy) = (k * eps - 2.0 * sy / 3.0, k * eps + sy / 3.0);
                assert!(
                    (sxx - exx).abs() < 1e-9 * exx.abs(),
                    "ε = {eps}: {sxx} vs {exx}"
                );
                assert!(
                    (syy - eyy).abs() < 1e-9 * eyy.abs(),
                    "ε = {eps}: {syy} vs {eyy}"
                );
            }
        }
        // 500 steps of 1e-5: ε = −5e-3 is past yield; ε_p = 2(|ε| − ε_y)/3.
        let ep = h[PLASTIC_STRAIN_INDEX];
        assert!((ep - 2.0 * (5e-3 - eps_y) / 3.0).abs() < 1e-12, "{ep}");
    }

    /// Plastic work σ_y Δε_p heats the point by χ σ_y Δε_p/(ρ c_v): a
    /// perfectly plastic shear step of Δε_p = 1e-3 in copper gives
    /// Δw_p = 70e6 × 1e-3 = 7e4 J/m³ and ΔT = 0.9 × 7e4/(8930 × 383) =
    /// 0.018420 K.
    #[test]
    fn plastic_work_heats_with_taylor_quinney_fraction() {
        let m = ElasticPlastic {
            rate: ObjectiveRate::Jaumann,
            ..ElasticPlastic::ofhc_copper_seed000()
        };
        let (g, sy) = (43.8e9, 70.0e6);
        // Start on the yield surface in pure shear: s_xy = σ_y/√3.
        let tau = sy / 3f64.sqrt();
        let sigma = Mat3::new(0.0, tau, 0.0, tau, 0.0, 0.0, 0.0, 0.0, 0.0);
        // Shear rate D_xy chosen so the plastic increment is 1e-3:
        // trial σ̄ = σ_y + 3G Δε_p needs 2G D_xy Δt √3 = 3G × 1e-3.
        let dt = 1e-6;
        let d_xy = 3.0 * g * 1e-3 / (2.0 * g * dt * 3f64.sqrt());
        let l = Mat3::new(0.0, d_xy, 0.0, d_xy, 0.0, 0.0, 0.0, 0.0, 0.0);
        let mut h = fresh(&m);
        let out = m.update_stress(&input(l, dt, sigma, 300.0, 8930.0), &mut h);
        assert!(
            (h[PLASTIC_STRAIN_INDEX] - 1e-3).abs() < 1e-15,
            "{}",
            h[PLASTIC_STRAIN_INDEX]
        );
        assert!(
            (out.plastic_work - 7.0e4).abs() < 1e-6,
            "{}",
            out.plastic_work
        );
        let dtemp = h[TEMPERATURE_INCREMENT_INDEX];
        assert!(
            (dtemp - 0.9 * 7.0e4 / (8930.0 * 383.0)).abs() < 1e-15,
            "{dtemp}"
        );
        assert!((dtemp - 0.018_420).abs() < 1e-6, "{dtemp}");
        assert!((h[PLASTIC_STRAIN_RATE_INDEX] - 1e3).abs() < 1e-9);
    }

    /// Johnson–Cook return: after a large shear step of 4340 steel the
    /// von Mises stress equals the flow stress at the new plastic strain and
    /// rate, and the plastic strain is below the perfectly plastic bound.
    #[test]
    fn johnson_cook_return_lands_on_the_rate_dependent_surface() {
        let m = ElasticPlastic::steel_4340_seed000();
        let mut h = fresh(&m);
        let dt = 1e-7;
        let l = Mat3::new(0.0, 1e5, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0);
        let out = m.update_stress(&input(l, dt, Mat3::zeros(), 294.0, 7830.0), &mut h);
        let s = crate::hypoelastic::deviator(&out.stress);
        let vm = crate::hypoelastic::von_mises(&s);
        let ep = h[PLASTIC_STRAIN_INDEX];
        let rate = h[PLASTIC_STRAIN_RATE_INDEX];
        let sy = m.flow_stress.flow_stress(ep, rate, 294.0);
        assert!(ep > 0.0 && rate > 1.0, "{ep} {rate}");
        assert!((vm - sy).abs() <= 1e-12 * sy, "{vm} vs {sy}");
        assert!(
            sy > 792.0e6 * (1.0 + 0.014 * rate.ln()),
            "hardening adds to A"
        );
        // Trial σ̄ = √3 G γ = √3 × 80e9 × 1e-2.
        let trial = 3f64.sqrt() * 80.0e9 * 1e-2;
        assert!(ep < (trial - 792.0e6) / (3.0 * 80.0e9));
    }

    #[test]
    fn tension_to_fracture_fails_the_point_for_good() {
        let m = ElasticPlastic::steel_4340_seed000();
        let mut h = fresh(&m);
        let dt = 1e-7;
        // Triaxial tension plus shear: ε_f ≈ 0.05 + 3.44 e^(−2.12 σ_m/σ̄).
        let l = Mat3::new(2e4, 1e5, 0.0, 0.0, 2e4, 0.0, 0.0, 0.0, 2e4);
        let mut sigma = Mat3::zeros();
        let mut rho = 7830.0;
        let mut failed_at = None;
        for k in 0..2000 {
            rho /= 1.0 + l.trace() * dt;
            let out = m.update_stress(&input(l, dt, sigma, 294.0, rho), &mut h);
            sigma = out.stress;
            if let Some(k0) = failed_at {
                assert!(out.failed, "recovered at step {k} after failing at {k0}");
                assert_eq!(
                    crate::hypoelastic::von_mises(&crate::hypoelastic::deviator(&sigma)),
                    0.0
                );
                assert!(sigma.trace() <= 0.0, "failed point in tension: {sigma}");
            } else if out.failed {
                assert!(h[DAMAGE_INDEX] >= 1.0);
                failed_at = Some(k);
            }
        }
        assert!(
            failed_at.is_some(),
            "D = {} after 2000 steps",
            h[DAMAGE_INDEX]
        );
    }

    #[test]
    fn melting_fails_the_point_and_removes_shear_stress() {
        let m = ElasticPlastic::ofhc_copper_johnson_cook();
        let mut h = fresh(&m);
        let l = Mat3::new(0.0, 1e3, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0);
        let out = m.update_stress(&input(l, 1e-7, Mat3::zeros(), 1356.0, 9500.0), &mut h);
        assert!(out.failed);
        // Compressed (ρ > ρ₀): keeps its pressure, no deviator.
        let p = m.pressure.pressure(0.0, 0.0, 0.0, 9500.0, 0.0);
        assert!(p > 0.0);
        assert_eq!(out.stress, -Mat3::identity() * p);
    }

    #[test]
    fn validate_accepts_shipped_sets_and_names_bad_fields() {
        for m in [
            ElasticPlastic::ofhc_copper_seed000(),
            ElasticPlastic::ofhc_copper_johnson_cook(),
            ElasticPlastic::steel_4340_seed000(),
            ElasticPlastic::rha_steel_seed001(),
        ] {
            assert!(m.validate().is_ok(), "{m:?}: {:?}", m.validate());
        }
        let bad = ElasticPlastic {
            taylor_quinney: 1.5,
            ..ElasticPlastic::steel_4340_seed000()
        };
        let msg = bad.validate().unwrap_err().to_string();
        assert!(msg.contains("taylor_quinney"), "{msg}");
    }
}
