//! The Steinberg–Cochran–Guinan model (Steinberg, Cochran & Guinan, J.
//! Appl. Phys. 51 (1980) 1498, "SCG 1980" below; the parameter tables of
//! Steinberg, *Equation of State and Strength Properties of Selected
//! Materials*, UCRL-MA-106439, LLNL 1996).
//!
//! The model (SCG 1980 §II), with η = ρ/ρ₀, p the pressure, T the
//! temperature and ε_p the equivalent plastic strain:
//!
//! ```text
//! G = G₀ [1 + (G'_p/G₀) p η^(−1/3) + (G'_T/G₀)(T − 300 K)]
//! Y = Y₀ [1 + β (ε_p + ε_i)]ⁿ  capped at Y_max,  times G/G₀
//! G = Y = 0  for T ≥ T_m(η)
//! ```
//!
//! The paper writes the yield with its own pressure coefficient Y'_p/Y₀
//! and sets it equal to G'_p/G₀ (the ratio Y/G is then independent of p
//! and T), which is the form above. The melt temperature is either fixed
//! or the paper's modified Lindemann law
//! T_m = T_m0 exp[2a(1 − 1/η)] η^{2(Γ₀ − a − 1/3)} ([`MeltTemperature`]).
//! The model is rate independent: the paper fits it to data at strain
//! rates above about 10⁵ s⁻¹, where the rate dependence of the flow stress
//! has saturated.
//!
//! One step, in the unrotated frame of the [`ObjectiveRate`] (the built-in
//! J2 metal's update, `brisance_constitutive::elastic_plastic`, with its
//! moduli made functions of the state):
//!
//! 1. p_{n+1} from the equation of state at the density and specific
//!    internal energy handed in ([`PressureModel::Eos`]), η = ρ/ρ₀ with ρ₀
//!    the equation of state's reference density.
//! 2. G/G₀ at (p_{n+1}, η, T_n), clamped at zero; zero too when
//!    T_n ≥ T_m(η), the melted metal. The temperature is that of the start
//!    of the step, as for the built-in J2 metal.
//! 3. Trial deviator ŝ* = ŝ_n + 2G dev(d̂) Δt (hypoelastic, at the step's
//!    modulus).
//! 4. If σ̄* = √(3/2 ŝ*:ŝ*) exceeds Y(ε_pⁿ) the radial return
//!    (`brisance_constitutive::elastic_plastic::radial_return_with`) solves
//!    σ̄* − 3GΔε_p = Y(ε_pⁿ + Δε_p) and scales ŝ = ŝ* Y/σ̄*.
//! 5. Plastic work Δw_p = Y Δε_p heats the point by ΔT = χ Δw_p/(ρ c_v)
//!    (`brisance_constitutive::elastic_plastic::plastic_heating`), stored
//!    in the history for the solver that owns the temperature.
//!
//! A melted point carries σ = −p I: no deviator, its pressure (tensile or
//! compressive) from the equation of state. Melting is not failure: a
//! point that cools below T_m has its strength back, with the plastic
//! strain it had.
//!
//! History per point (the `*_INDEX` constants): equivalent plastic strain,
//! the last step's temperature increment (K), the last step's G/G₀ (0 when
//! melted), then the objective rate's own history (F and R for
//! Green–Naghdi).

use brisance_constitutive::{
    elastic_plastic::{plastic_heating, radial_return_with, TAYLOR_QUINNEY_SEED000},
    error::{non_negative, positive},
    hypoelastic::{deviator, von_mises},
    objective::rate_of_deformation,
    ConstitutiveError, ObjectiveRate, PluginMaterial, PressureModel,
};
use brisance_core::{Eos, Mat3, Material, StressUpdate, StressUpdateInput};
use brisance_eos::{EosModel, MieGruneisenLinear};
use serde::{Deserialize, Serialize};

/// The model's name as the [`Material`] trait reports it.
pub const NAME: &str = "steinberg_guinan";

/// The reference temperature of SCG 1980's modulus law, K: G'_T multiplies
/// T − 300 K.
pub const REFERENCE_TEMPERATURE: f64 = 300.0;

/// History index of the equivalent plastic strain ε_p.
pub const PLASTIC_STRAIN_INDEX: usize = 0;
/// History index of the last step's plastic-heating temperature rise, K.
pub const TEMPERATURE_INCREMENT_INDEX: usize = 1;
/// History index of the last step's shear-modulus ratio G/G₀ (0 melted).
pub const MODULUS_RATIO_INDEX: usize = 2;
/// Number of history values before the objective rate's own.
pub const SCALAR_HISTORY_LEN: usize = 3;

fn default_taylor_quinney() -> f64 {
    TAYLOR_QUINNEY_SEED000
}

/// The melt temperature T_m(η), K.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub enum MeltTemperature {
    /// A fixed melt temperature, whatever the compression.
    Constant {
        /// T_m, K.
        t_m: f64,
    },
    /// SCG 1980's modified Lindemann law,
    /// T_m = T_m0 exp[2a(1 − 1/η)] η^{2(Γ₀ − a − 1/3)}, from the volume
    /// dependence of the Grüneisen Γ of Steinberg's equation of state.
    Lindemann {
        /// Melt temperature at the reference density T_m0, K.
        t_m0: f64,
        /// Grüneisen coefficient at the reference density Γ₀.
        gamma0: f64,
        /// First-order volume coefficient a of Γ.
        a: f64,
    },
}

impl MeltTemperature {
    /// T_m at compression η = ρ/ρ₀, K.
    pub fn at(&self, eta: f64) -> f64 {
        match *self {
            Self::Constant { t_m } => t_m,
            Self::Lindemann { t_m0, gamma0, a } => {
                t_m0 * (2.0 * a * (1.0 - 1.0 / eta)).exp()
                    * eta.powf(2.0 * (gamma0 - a - 1.0 / 3.0))
            }
        }
    }

    fn validate(&self) -> Result<(), ConstitutiveError> {
        match *self {
            Self::Constant { t_m } => positive(NAME, "melt.t_m", t_m),
            Self::Lindemann { t_m0, gamma0, a } => {
                positive(NAME, "melt.t_m0", t_m0)?;
                finite("melt.gamma0", gamma0)?;
                finite("melt.a", a)
            }
        }
    }
}

/// The Steinberg–Cochran–Guinan metal: pressure- and temperature-dependent
/// shear modulus and yield stress, work hardening to a cap, zero strength
/// above melt (SCG 1980).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SteinbergGuinan {
    /// Shear modulus at the reference state (p = 0, T = 300 K) G₀, Pa.
    pub g0: f64,
    /// Pressure coefficient of the shear modulus G'_p/G₀ = (∂G/∂p)/G₀,
    /// 1/Pa (≥ 0).
    pub dg_dp_over_g0: f64,
    /// Temperature coefficient of the shear modulus G'_T/G₀ = (∂G/∂T)/G₀,
    /// 1/K (≤ 0: the metal softens as it heats).
    pub dg_dt_over_g0: f64,
    /// Yield stress at zero plastic strain and the reference state Y₀, Pa.
    pub y0: f64,
    /// Cap Y_max of the work-hardened yield stress Y₀[1 + β(ε_p + ε_i)]ⁿ,
    /// Pa (≥ Y₀).
    pub y_max: f64,
    /// Work-hardening coefficient β (≥ 0).
    pub beta: f64,
    /// Work-hardening exponent n (≥ 0).
    pub n: f64,
    /// Initial equivalent plastic strain ε_i of the work-hardening law
    /// (≥ 0, default 0).
    #[serde(default)]
    pub eps_i: f64,
    /// Melt temperature law.
    pub melt: MeltTemperature,
    /// The pressure: an equation of state ([`PressureModel::Eos`]), whose
    /// reference density is ρ₀ of η = ρ/ρ₀.
    pub pressure: PressureModel,
    /// Objective stress rate.
    #[serde(default)]
    pub rate: ObjectiveRate,
    /// Fraction χ of plastic work turned into heat (default 0.9, seed 000
    /// §4.2).
    #[serde(default = "default_taylor_quinney")]
    pub taylor_quinney: f64,
    /// Specific heat c_v for the plastic heating, J/(kg·K).
    pub specific_heat: f64,
}

/// Checks that `value` of `field` is finite; the error names the field.
fn finite(field: &'static str, value: f64) -> Result<(), ConstitutiveError> {
    if value.is_finite() {
        Ok(())
    } else {
        Err(ConstitutiveError::InvalidParameter {
            model: NAME,
            field,
            value,
            expected: "a finite value",
        })
    }
}

impl SteinbergGuinan {
    /// OFHC copper (1/2 hard), Steinberg 1996 (UCRL-MA-106439), the set
    /// SCG 1980 fitted: G₀ = 47.7 GPa, G'_p/G₀ = 2.83 Mbar⁻¹ =
    /// 2.83 × 10⁻¹¹ Pa⁻¹, G'_T/G₀ = −0.377 kK⁻¹ = −3.77 × 10⁻⁴ K⁻¹,
    /// Y₀ = 0.12 GPa, Y_max = 0.64 GPa, β = 36, n = 0.45, ε_i = 0;
    /// Lindemann melt T_m0 = 1790 K, Γ₀ = 2.02, a = 1.5; Steinberg's
    /// Mie–Grüneisen copper (C₀ = 3940 m/s, S = 1.489, Γ₀ = 2.02,
    /// ρ₀ = 8930 kg/m³, [`MieGruneisenLinear::ofhc_copper`]); c_v =
    /// 383 J/(kg·K); Green–Naghdi rate; χ = 0.9. The digits are discussed
    /// in docs/physics/constitutive/steinberg_guinan.md.
    pub fn ofhc_copper() -> Self {
        Self {
            g0: 47.7e9,
            dg_dp_over_g0: 2.83e-11,
            dg_dt_over_g0: -3.77e-4,
            y0: 0.12e9,
            y_max: 0.64e9,
            beta: 36.0,
            n: 0.45,
            eps_i: 0.0,
            melt: MeltTemperature::Lindemann {
                t_m0: 1790.0,
                gamma0: 2.02,
                a: 1.5,
            },
            pressure: PressureModel::Eos(EosModel::MieGruneisenLinear(
                MieGruneisenLinear::ofhc_copper(),
            )),
            rate: ObjectiveRate::GreenNaghdi,
            taylor_quinney: TAYLOR_QUINNEY_SEED000,
            specific_heat: 383.0,
        }
    }

    /// Checks the parameters; the error names the bad field.
    pub fn check(&self) -> Result<(), ConstitutiveError> {
        positive(NAME, "g0", self.g0)?;
        non_negative(NAME, "dg_dp_over_g0", self.dg_dp_over_g0)?;
        if !(self.dg_dt_over_g0 <= 0.0 && self.dg_dt_over_g0.is_finite()) {
            return Err(ConstitutiveError::InvalidParameter {
                model: NAME,
                field: "dg_dt_over_g0",
                value: self.dg_dt_over_g0,
                expected: "a finite value ≤ 0, 1/K (a modulus that does not rise with temperature)",
            });
        }
        positive(NAME, "y0", self.y0)?;
        positive(NAME, "y_max", self.y_max)?;
        if !(self.y_max >= self.y0) {
            return Err(ConstitutiveError::InvalidParameter {
                model: NAME,
                field: "y_max",
                value: self.y_max,
                expected: "a cap at or above `y0`, Pa",
            });
        }
        non_negative(NAME, "beta", self.beta)?;
        non_negative(NAME, "n", self.n)?;
        non_negative(NAME, "eps_i", self.eps_i)?;
        self.melt.validate()?;
        if !matches!(self.pressure, PressureModel::Eos(_)) {
            return Err(ConstitutiveError::Eos {
                model: NAME,
                detail: "give an equation of state, `Eos(...)`: its reference density is ρ₀ of \
                         η = ρ/ρ₀ in the shear modulus and the melt temperature"
                    .into(),
            });
        }
        self.pressure.validate(NAME)?;
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

    /// The compression η = ρ/ρ₀ at density `rho`, ρ₀ the equation of
    /// state's reference density (1 without an equation of state, which
    /// [`SteinbergGuinan::check`] refuses).
    pub fn compression(&self, rho: f64) -> f64 {
        self.pressure
            .eos()
            .map_or(1.0, |eos| rho / eos.reference_density())
    }

    /// G/G₀ = 1 + (G'_p/G₀) p η^(−1/3) + (G'_T/G₀)(T − 300 K) at pressure
    /// `p` (Pa), compression `eta` and temperature `t` (K), clamped at zero
    /// (SCG 1980 §II); not yet zeroed for melt
    /// ([`SteinbergGuinan::strength_ratio`] is).
    pub fn shear_modulus_ratio(&self, p: f64, eta: f64, t: f64) -> f64 {
        let ratio = 1.0
            + self.dg_dp_over_g0 * p * eta.powf(-1.0 / 3.0)
            + self.dg_dt_over_g0 * (t - REFERENCE_TEMPERATURE);
        ratio.max(0.0)
    }

    /// G/G₀ of a point at (p, η, T): [`SteinbergGuinan::shear_modulus_ratio`],
    /// or 0 at and above the melt temperature T_m(η); it scales the yield
    /// stress as well as the modulus.
    pub fn strength_ratio(&self, p: f64, eta: f64, t: f64) -> f64 {
        if t >= self.melt.at(eta) {
            0.0
        } else {
            self.shear_modulus_ratio(p, eta, t)
        }
    }

    /// The work-hardened yield stress at the reference state,
    /// min(Y₀[1 + β(ε_p + ε_i)]ⁿ, Y_max), and its slope in ε_p (zero on
    /// the cap), Pa.
    pub fn work_hardening(&self, eps_p: f64) -> (f64, f64) {
        let base = 1.0 + self.beta * (eps_p + self.eps_i);
        let y = self.y0 * base.powf(self.n);
        if y >= self.y_max {
            (self.y_max, 0.0)
        } else {
            (y, self.y0 * self.n * self.beta * base.powf(self.n - 1.0))
        }
    }

    /// The yield stress Y = min(Y₀[1 + β(ε_p + ε_i)]ⁿ, Y_max) · G/G₀ at
    /// plastic strain `eps_p` and strength ratio `ratio` (Pa).
    pub fn yield_stress(&self, eps_p: f64, ratio: f64) -> f64 {
        self.work_hardening(eps_p).0 * ratio
    }

    /// An upper bound of the shear modulus at density `rho` and specific
    /// internal energy `e`, for the wave speed: the pressure term at the
    /// equation of state's pressure (when compressive) and the temperature
    /// term at 0 K, Pa.
    pub fn shear_modulus_bound(&self, rho: f64, e: f64) -> f64 {
        let eta = self.compression(rho);
        let p = self
            .pressure
            .eos()
            .map_or(0.0, |eos| eos.pressure(rho, e).max(0.0));
        let ratio = self.shear_modulus_ratio(p, eta, 0.0);
        // NaN (a state outside the equation of state) falls back to G₀.
        if ratio.is_finite() {
            self.g0 * ratio
        } else {
            self.g0
        }
    }
}

impl Material for SteinbergGuinan {
    fn name(&self) -> &'static str {
        NAME
    }

    fn history_len(&self) -> usize {
        SCALAR_HISTORY_LEN + self.rate.history_len()
    }

    /// Zero plastic strain and heating, G/G₀ = 1 (the reference state).
    fn init_history(&self, history: &mut [f64]) {
        history[PLASTIC_STRAIN_INDEX] = 0.0;
        history[TEMPERATURE_INCREMENT_INDEX] = 0.0;
        history[MODULUS_RATIO_INDEX] = 1.0;
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
        let t = input.temperature;
        let ratio = self.strength_ratio(p, self.compression(input.density), t);
        scalars[TEMPERATURE_INCREMENT_INDEX] = 0.0;
        scalars[MODULUS_RATIO_INDEX] = ratio;
        if !(ratio > 0.0) {
            // Melted (or a modulus driven to zero): no deviator.
            return StressUpdate {
                stress: -Mat3::identity() * p,
                plastic_work: 0.0,
                failed: false,
            };
        }

        let g = self.g0 * ratio;
        let s_trial = deviator(&frames.unrotate_start(&input.stress))
            + 2.0 * g * dt * deviator(&frames.unrotate_end(&d));
        let trial = von_mises(&s_trial);
        let eps_p = scalars[PLASTIC_STRAIN_INDEX];
        let flow = |eps: f64| {
            let (y, slope) = self.work_hardening(eps);
            (y * ratio, slope * ratio)
        };
        let (s_hat, d_eps, y) = if trial > flow(eps_p).0 {
            let (d_eps, y) = radial_return_with(|eps, _, _| flow(eps), g, trial, eps_p, dt);
            (s_trial * (y / trial).max(0.0), d_eps, y)
        } else {
            (s_trial, 0.0, 0.0)
        };
        let plastic_work = y * d_eps;
        scalars[PLASTIC_STRAIN_INDEX] = eps_p + d_eps;
        scalars[TEMPERATURE_INCREMENT_INDEX] = plastic_heating(
            self.taylor_quinney,
            plastic_work,
            input.density,
            self.specific_heat,
        );
        StressUpdate {
            stress: frames.rotate_end(&s_hat) - Mat3::identity() * p,
            plastic_work,
            failed: false,
        }
    }

    fn eos(&self) -> Option<&dyn Eos> {
        self.pressure.eos()
    }

    /// c_L = √(c_bulk² + 4G/(3ρ)) with G bounded from above
    /// ([`SteinbergGuinan::shear_modulus_bound`]), m/s.
    fn wave_speed(&self, density: f64, specific_internal_energy: f64) -> f64 {
        let g = self.shear_modulus_bound(density, specific_internal_energy);
        self.pressure
            .longitudinal_wave_speed(density, specific_internal_energy, g)
    }
}

impl PluginMaterial for SteinbergGuinan {
    fn validate(&self) -> Result<(), String> {
        self.check().map_err(|e| e.to_string())
    }

    /// σ̄ − Y at the history's plastic strain and last G/G₀, on the scale
    /// of the larger of Y and |p| (the deviator of a state with no
    /// strength is the round-off of tr σ/3).
    fn yield_excess(
        &self,
        stress: &Mat3,
        history: &[f64],
        _temperature: f64,
    ) -> Option<(f64, f64)> {
        let y = self.yield_stress(history[PLASTIC_STRAIN_INDEX], history[MODULUS_RATIO_INDEX]);
        let excess = von_mises(&deviator(stress)) - y;
        Some((excess, y.max((stress.trace() / 3.0).abs())))
    }

    fn scalar_state_len(&self) -> usize {
        SCALAR_HISTORY_LEN
    }

    fn temperature_increment(&self, history: &[f64]) -> Option<f64> {
        Some(history[TEMPERATURE_INCREMENT_INDEX])
    }

    fn specific_heat(&self) -> Option<f64> {
        Some(self.specific_heat)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use brisance_eos::Murnaghan;

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

    fn fresh(m: &SteinbergGuinan) -> Vec<f64> {
        let mut h = vec![0.0; m.history_len()];
        m.init_history(&mut h);
        h
    }

    fn close(a: f64, b: f64, rel: f64) -> bool {
        (a - b).abs() <= rel * b.abs()
    }

    /// Copper at p = 10 GPa, η = 1.1, T = 600 K:
    /// η^(−1/3) = exp(−ln 1.1/3) = 0.9687293,
    /// G/G₀ = 1 + 2.83e-11 × 1e10 × 0.9687293 − 3.77e-4 × 300
    ///      = 1 + 0.2741504 − 0.1131 = 1.1610504,
    /// G = 47.7 GPa × 1.1610504 = 55.38210 GPa.
    #[test]
    fn shear_modulus_at_hand_computed_pressure_and_temperature() {
        let m = SteinbergGuinan::ofhc_copper();
        let ratio = m.shear_modulus_ratio(1e10, 1.1, 600.0);
        assert!(close(ratio, 1.161_050_4, 1e-7), "{ratio}");
        assert!(close(m.g0 * ratio, 55.382_10e9, 1e-6), "{}", m.g0 * ratio);
        // At the reference state the ratio is exactly one.
        assert_eq!(m.shear_modulus_ratio(0.0, 1.0, 300.0), 1.0);
        // Hot enough, the modulus is clamped at zero rather than negative:
        // 1 − 3.77e-4 (T − 300) < 0 above T = 2952.5 K.
        assert_eq!(m.shear_modulus_ratio(0.0, 1.0, 3000.0), 0.0);
    }

    /// Copper: Y(ε_p) = 0.12 GPa (1 + 36 ε_p)^0.45 below the 0.64 GPa cap.
    /// ε_p = 0.01: 1.36^0.45 = exp(0.45 × 0.3074847) = 1.1483982, Y =
    /// 137.8078 MPa, slope 0.12e9 × 0.45 × 36 × 1.36^(−0.55) =
    /// 1.944e9 × 0.8444105 = 1.641534 GPa. ε_p = 1: 37^0.45 =
    /// exp(0.45 × 3.6109179) = 5.0779775, Y = 609.3573 MPa. ε_p = 2:
    /// 73^0.45 = 6.89 > 5.333 = 0.64/0.12: capped, slope zero.
    #[test]
    fn yield_stress_hardens_to_its_cap_and_scales_with_the_modulus() {
        let m = SteinbergGuinan::ofhc_copper();
        let (y, slope) = m.work_hardening(0.01);
        assert!(close(y, 137.8078e6, 1e-6), "{y}");
        assert!(close(slope, 1.641_534e9, 1e-6), "{slope}");
        assert!(close(m.work_hardening(1.0).0, 609.3573e6, 1e-6));
        assert_eq!(m.work_hardening(2.0), (0.64e9, 0.0));
        assert_eq!(m.work_hardening(0.0), (0.12e9, 0.12e9 * 0.45 * 36.0));
        // Y scales with G/G₀ (SCG 1980: Y'_p/Y₀ = G'_p/G₀).
        assert_eq!(m.yield_stress(0.01, 0.5), y * 0.5);
        // ε_i shifts the hardening curve.
        let pre = SteinbergGuinan {
            eps_i: 0.01,
            ..SteinbergGuinan::ofhc_copper()
        };
        assert_eq!(pre.work_hardening(0.0).0, y);
    }

    /// The Lindemann melt of copper at η = 1.05:
    /// exp(2 × 1.5 × (1 − 1/1.05)) = exp(0.1428571) = 1.1535650,
    /// 1.05^(2 (2.02 − 1.5 − 1/3)) = exp(0.3733333 × 0.0487902) =
    /// 1.0183819, T_m = 1790 × 1.1535650 × 1.0183819 = 2102.838 K.
    #[test]
    fn melt_temperature_follows_the_lindemann_law() {
        let m = SteinbergGuinan::ofhc_copper();
        assert_eq!(m.melt.at(1.0), 1790.0);
        let t_m = m.melt.at(1.05);
        assert!(close(t_m, 2102.838, 1e-6), "{t_m}");
        assert!(m.strength_ratio(0.0, 1.05, 2102.0) > 0.0);
        assert_eq!(m.strength_ratio(0.0, 1.05, 2103.0), 0.0);
        let fixed = MeltTemperature::Constant { t_m: 1356.0 };
        assert_eq!(fixed.at(1.3), 1356.0);
    }

    /// A copper-like metal on a Murnaghan EOS p = (ηⁿ − 1)/(n κ) (n = 4,
    /// κ = 1/137.9 GPa), with G independent of pressure (G'_p = 0) at
    /// T = 300 K, compressed in uniaxial strain (L = diag(ε̇, 0, 0)):
    /// the deviator s_xx = (4/3) G₀ ε is elastic until σ̄ = 2G₀|ε| reaches
    /// Y₀, at |ε_y| = Y₀/(2G₀) = 0.12e9/(2 × 47.7e9) = 1.2578616e-3, the
    /// Hugoniot elastic limit σ_xx = −p(η_y) − (2/3) Y₀. Beyond it
    /// σ̄ = Y(ε_p) with ε_p from 3G₀((2/3)|ε| − ε_p) = Y₀(1 + β ε_p)ⁿ.
    #[test]
    fn uniaxial_strain_yields_at_the_hand_computed_hugoniot_elastic_limit() {
        let (n, kappa, rho0) = (4.0, 1.0 / 137.9e9, 8930.0);
        let m = SteinbergGuinan {
            dg_dp_over_g0: 0.0,
            pressure: PressureModel::Eos(EosModel::Murnaghan(Murnaghan {
                n,
                kappa,
                rho0,
                cv: 383.0,
                t_ref: 300.0,
            })),
            rate: ObjectiveRate::Jaumann,
            ..SteinbergGuinan::ofhc_copper()
        };
        assert!(m.check().is_ok());
        let (g0, y0) = (47.7e9, 0.12e9);
        let eps_y: f64 = y0 / (2.0 * g0);
        assert!((eps_y - 1.257_861_6e-3).abs() < 1e-10);
        let pressure = |eta: f64| (eta.powf(n) - 1.0) / (n * kappa);
        let (dt, eps_dot) = (1e-8, -1.0e3);
        let l = Mat3::new(eps_dot, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0);
        let mut h = fresh(&m);
        let mut sigma = Mat3::zeros();
        let (mut eps, mut first_yield) = (0.0f64, None);
        for k in 0..400 {
            eps += eps_dot * dt;
            // ρ = ρ₀/J, J = e^ε for the log strain the rate integrates.
            let eta = (-eps).exp();
            let out = m.update_stress(&input(l, dt, sigma, 300.0, rho0 * eta), &mut h);
            sigma = out.stress;
            let p = pressure(eta);
            let sxx = sigma[(0, 0)] + p;
            if eps.abs() < eps_y * (1.0 - 1e-9) {
                assert_eq!(out.plastic_work, 0.0, "yielded early at ε = {eps}");
                let expected = 4.0 / 3.0 * g0 * eps;
                assert!(close(sxx, expected, 1e-9), "ε = {eps}: {sxx} vs {expected}");
            } else if eps.abs() > eps_y * (1.0 + 1e-9) {
                first_yield.get_or_insert(k);
                // Bisection on the hand-derived return condition.
                let f = |ep: f64| {
                    3.0 * g0 * (2.0 / 3.0 * eps.abs() - ep) - y0 * (1.0 + 36.0 * ep).powf(0.45)
                };
                let (mut lo, mut hi) = (0.0, eps.abs());
                for _ in 0..200 {
                    let mid = 0.5 * (lo + hi);
                    if f(mid) > 0.0 {
                        lo = mid;
                    } else {
                        hi = mid;
                    }
                }
                let ep = 0.5 * (lo + hi);
                assert!(
                    close(h[PLASTIC_STRAIN_INDEX], ep, 1e-9),
                    "{} vs {ep}",
                    h[PLASTIC_STRAIN_INDEX]
                );
                let y = y0 * (1.0 + 36.0 * ep).powf(0.45);
                assert!(
                    close(sxx, -2.0 / 3.0 * y, 1e-9),
                    "ε = {eps}: {sxx} vs {}",
                    -2.0 / 3.0 * y
                );
                assert!(close(sigma[(1, 1)] + p, y / 3.0, 1e-9));
                assert!(out.plastic_work > 0.0);
            }
        }
        // The limit is crossed at step ⌈ε_y/(|ε̇|Δt)⌉ − 1 = 125 (0-based):
        // |ε| = 1.26e-3 > 1.2578616e-3 > 1.25e-3.
        assert_eq!(first_yield, Some(125));
        // The Hugoniot elastic limit, hand-computed at |ε_y| (η_y = e^ε_y):
        // p = (e^{4 × 1.2578616e-3} − 1) × 137.9e9/4 = 173.896 MPa,
        // σ_HEL = −(p + (2/3) 0.12 GPa) = −253.896 MPa.
        let hel = -(pressure(eps_y.exp()) + 2.0 / 3.0 * y0);
        assert!(close(hel, -253.896e6, 1e-6), "{hel}");
    }

    /// The step's modulus: from rest at p = 10 GPa on copper's EOS
    /// (compressed copper, T = 300 K), a small shear step γ̇Δt = 1e-6 adds
    /// s_xy = G γ̇ Δt with G = G₀(1 + 2.83e-11 p η^(−1/3)) at the EOS
    /// pressure of the step's density.
    #[test]
    fn the_deviator_grows_with_the_pressure_stiffened_modulus() {
        let m = SteinbergGuinan::ofhc_copper();
        let eos = MieGruneisenLinear::ofhc_copper();
        let rho = 1.05 * 8930.0;
        let p = eos.pressure(rho, 0.0);
        let g = 47.7e9 * (1.0 + 2.83e-11 * p * 1.05f64.powf(-1.0 / 3.0));
        assert!(g > 47.7e9 * 1.03, "{p} {g}");
        let dt = 1e-8;
        let l = Mat3::new(0.0, 1e-6 / dt, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0);
        let m = SteinbergGuinan {
            rate: ObjectiveRate::Jaumann,
            ..m
        };
        let mut h = fresh(&m);
        let sigma0 = -Mat3::identity() * p;
        let out = m.update_stress(&input(l, dt, sigma0, 300.0, rho), &mut h);
        // Jaumann: the spin rotates −p I into itself; s_xy = 2G D_xy Δt.
        assert!(
            close(out.stress[(0, 1)], g * 1e-6, 1e-9),
            "{}",
            out.stress[(0, 1)]
        );
        assert!(close(-out.stress.trace() / 3.0, p, 1e-12));
        assert!(close(h[MODULUS_RATIO_INDEX], g / 47.7e9, 1e-12));
    }

    /// Plastic work Y Δε_p heats the point by χ Y Δε_p/(ρ c_v): from the
    /// yield surface in pure shear (s_xy = Y₀/√3) a shear step of
    /// 2G₀ D_xy Δt = 95.4 MPa returns to σ̄ = Y(Δε_p), and the stored
    /// increment is 0.9 Y Δε_p/(8930 × 383).
    #[test]
    fn plastic_work_heats_with_the_taylor_quinney_fraction() {
        let m = SteinbergGuinan {
            rate: ObjectiveRate::Jaumann,
            ..SteinbergGuinan::ofhc_copper()
        };
        let tau = 0.12e9 / 3f64.sqrt();
        let sigma = Mat3::new(0.0, tau, 0.0, tau, 0.0, 0.0, 0.0, 0.0, 0.0);
        let dt = 1e-7;
        let l = Mat3::new(0.0, 1e4, 0.0, 1e4, 0.0, 0.0, 0.0, 0.0, 0.0);
        let mut h = fresh(&m);
        let out = m.update_stress(&input(l, dt, sigma, 300.0, 8930.0), &mut h);
        let ep = h[PLASTIC_STRAIN_INDEX];
        assert!(ep > 0.0);
        let y = m.yield_stress(ep, 1.0);
        let vm = von_mises(&deviator(&out.stress));
        assert!(close(vm, y, 1e-12), "{vm} vs {y}");
        assert!(close(out.plastic_work, y * ep, 1e-15));
        let d_temp = h[TEMPERATURE_INCREMENT_INDEX];
        assert!(close(d_temp, 0.9 * y * ep / (8930.0 * 383.0), 1e-15));
        assert_eq!(m.temperature_increment(&h), Some(d_temp));
        assert_eq!(PluginMaterial::specific_heat(&m), Some(383.0));
    }

    /// Above melt the metal carries no shear: a sheared point stepped at
    /// T = 1800 K ≥ T_m(1) = 1790 K keeps its EOS pressure and loses its
    /// deviator; cooled again, it has its strength back.
    #[test]
    fn a_melted_point_has_zero_strength_and_regains_it_below_melt() {
        let m = SteinbergGuinan {
            rate: ObjectiveRate::Jaumann,
            ..SteinbergGuinan::ofhc_copper()
        };
        let rho = 1.02 * 8930.0;
        let p = MieGruneisenLinear::ofhc_copper().pressure(rho, 0.0);
        // At η = 1.02: T_m = 1790 exp(3 (1 − 1/1.02)) 1.02^0.37333 =
        // 1790 × 1.06059 × 1.00742 = 1912.5 K: melted at 2000 K.
        assert!(m.melt.at(1.02) > 1900.0 && m.melt.at(1.02) < 2000.0);
        let tau = 50.0e6;
        let sigma = Mat3::new(-p, tau, 0.0, tau, -p, 0.0, 0.0, 0.0, -p);
        let l = Mat3::new(0.0, 1e3, 0.0, 1e3, 0.0, 0.0, 0.0, 0.0, 0.0);
        let mut h = fresh(&m);
        let out = m.update_stress(&input(l, 1e-8, sigma, 2000.0, rho), &mut h);
        assert_eq!(out.stress, -Mat3::identity() * p);
        assert_eq!(out.plastic_work, 0.0);
        assert!(!out.failed);
        assert_eq!(h[MODULUS_RATIO_INDEX], 0.0);
        let (excess, scale) = m.yield_excess(&out.stress, &h, 2000.0).unwrap();
        assert!(excess <= 1e-10 * scale, "{excess} {scale}");
        // Cooled below melt, a shear step loads elastically again.
        let out = m.update_stress(&input(l, 1e-8, out.stress, 300.0, rho), &mut h);
        assert!(out.stress[(0, 1)] > 0.0 && !out.failed);
        assert!(h[MODULUS_RATIO_INDEX] > 1.0);
    }

    #[test]
    fn validation_names_each_bad_field() {
        let ok = SteinbergGuinan::ofhc_copper();
        assert!(ok.check().is_ok());
        let cases: Vec<(SteinbergGuinan, &str)> = vec![
            (
                SteinbergGuinan {
                    g0: 0.0,
                    ..ok.clone()
                },
                "`g0`",
            ),
            (
                SteinbergGuinan {
                    dg_dp_over_g0: -1e-11,
                    ..ok.clone()
                },
                "`dg_dp_over_g0`",
            ),
            (
                SteinbergGuinan {
                    dg_dt_over_g0: 1e-4,
                    ..ok.clone()
                },
                "`dg_dt_over_g0`",
            ),
            (
                SteinbergGuinan {
                    y0: f64::NAN,
                    ..ok.clone()
                },
                "`y0`",
            ),
            (
                SteinbergGuinan {
                    y_max: 0.1e9,
                    ..ok.clone()
                },
                "`y_max`",
            ),
            (
                SteinbergGuinan {
                    beta: -1.0,
                    ..ok.clone()
                },
                "`beta`",
            ),
            (
                SteinbergGuinan {
                    n: f64::INFINITY,
                    ..ok.clone()
                },
                "`n`",
            ),
            (
                SteinbergGuinan {
                    eps_i: -0.1,
                    ..ok.clone()
                },
                "`eps_i`",
            ),
            (
                SteinbergGuinan {
                    melt: MeltTemperature::Constant { t_m: -5.0 },
                    ..ok.clone()
                },
                "`melt.t_m`",
            ),
            (
                SteinbergGuinan {
                    melt: MeltTemperature::Lindemann {
                        t_m0: 1790.0,
                        gamma0: f64::NAN,
                        a: 1.5,
                    },
                    ..ok.clone()
                },
                "`melt.gamma0`",
            ),
            (
                SteinbergGuinan {
                    pressure: PressureModel::Linear { bulk_modulus: 1e11 },
                    ..ok.clone()
                },
                "`pressure`",
            ),
            (
                SteinbergGuinan {
                    pressure: PressureModel::Eos(EosModel::MieGruneisenLinear(
                        MieGruneisenLinear {
                            c0: -1.0,
                            ..MieGruneisenLinear::ofhc_copper()
                        },
                    )),
                    ..ok.clone()
                },
                "c0",
            ),
            (
                SteinbergGuinan {
                    taylor_quinney: 1.5,
                    ..ok.clone()
                },
                "`taylor_quinney`",
            ),
            (
                SteinbergGuinan {
                    specific_heat: 0.0,
                    ..ok.clone()
                },
                "`specific_heat`",
            ),
        ];
        for (m, field) in cases {
            let err = PluginMaterial::validate(&m).unwrap_err();
            assert!(err.contains(field), "{field}: {err}");
            assert!(err.starts_with(NAME), "{err}");
        }
    }

    mod properties {
        use super::*;
        use proptest::prelude::*;

        /// Mostly values a parameter may take (so that accepted sets are
        /// common), with zero, negatives and non-finite values among them.
        fn any_f64() -> impl Strategy<Value = f64> {
            prop_oneof![
                1 => Just(0.0),
                1 => Just(-1.0),
                1 => Just(f64::NAN),
                1 => Just(f64::INFINITY),
                1 => Just(f64::NEG_INFINITY),
                1 => -1e12f64..0.0,
                40 => 1e-12f64..1e12,
            ]
        }

        proptest! {
            #![proptest_config(ProptestConfig::with_cases(256))]

            /// Any parameter values: validation answers without panicking,
            /// naming a field when it refuses; an accepted set updates a
            /// point without panicking and with a finite stress.
            #[test]
            fn validation_never_panics_and_accepted_sets_update_finitely(
                g0 in any_f64(), dp in any_f64(), dtemp in any_f64(), y0 in any_f64(),
                y_max in any_f64(), beta in any_f64(), n in any_f64(), eps_i in any_f64(),
                t_m0 in any_f64(), gamma0 in any_f64(), a in any_f64(),
            ) {
                // G'_T/G₀ is ≤ 0 for an accepted set: draw its magnitude.
                let m = SteinbergGuinan {
                    g0, dg_dp_over_g0: dp, dg_dt_over_g0: -dtemp, y0, y_max, beta, n, eps_i,
                    melt: MeltTemperature::Lindemann { t_m0, gamma0, a },
                    ..SteinbergGuinan::ofhc_copper()
                };
                match PluginMaterial::validate(&m) {
                    Err(e) => prop_assert!(e.contains("field `"), "{}", e),
                    Ok(()) => {
                        let mut h = fresh(&m);
                        let l = Mat3::new(-1e4, 3e4, 0.0, 0.0, 2e3, 0.0, 0.0, 0.0, 0.0);
                        let mut sigma = Mat3::zeros();
                        for k in 0..20 {
                            let rho = 8930.0 * (1.0 + 1e-3 * k as f64);
                            let out = m.update_stress(&input(l, 1e-7, sigma, 300.0, rho), &mut h);
                            sigma = out.stress;
                            prop_assert!(sigma.iter().all(|x| x.is_finite()), "{}", sigma);
                            prop_assert!(out.plastic_work >= 0.0);
                        }
                        prop_assert!(m.wave_speed(8930.0, 0.0).is_finite());
                    }
                }
            }
        }
    }
}

/// The [`Material`] contract (`brisance_constitutive::contracts`) for the
/// model as the program holds it, a plugin [`brisance_constitutive::MaterialModel`].
#[cfg(test)]
mod contract {
    use super::*;
    use brisance_constitutive::PluginConstitutive;

    fn plugin(m: SteinbergGuinan) -> PluginConstitutive {
        PluginConstitutive::from_model(&crate::registration::STEINBERG_GUINAN, m)
            .expect("serializes")
    }

    brisance_constitutive::material_contract_tests!(
        ofhc_copper_green_naghdi,
        plugin(SteinbergGuinan::ofhc_copper())
    );
    brisance_constitutive::material_contract_tests!(
        ofhc_copper_jaumann_fixed_melt,
        plugin(SteinbergGuinan {
            rate: ObjectiveRate::Jaumann,
            melt: MeltTemperature::Constant { t_m: 1356.0 },
            eps_i: 0.05,
            ..SteinbergGuinan::ofhc_copper()
        })
    );
}
