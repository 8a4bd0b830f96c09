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
//!    by bracketed Newton on [0, σ̄*/(3G)] and scales ŝ = ŝ* σ_y/σ̄* (equal to
//!    1 − 3GΔε_p/σ̄* at the root, without its cancellation when σ_y ≪ σ̄*).
//!    The plastic strain and rate are implicit and the temperature is that
//!    of the start of the step, the semi-implicit update of seed 000 §4.2
//!    (its refs [23, 24]).
//! 4. Plastic work Δw_p = ŝ:Δε^p = σ_y Δε_p (J/m³, returned) heats the point
//!    with the Taylor–Quinney coefficient χ = 0.9 (seed 000 §4.2):
//!    ΔT = χ Δw_p/(ρ c_v), stored in the history as this step's temperature
//!    increment. The solver, which owns the temperature, adds either ΔT to
//!    T or χ Δw_p/ρ to e — one of the two, not both.
//! 5. Johnson–Cook damage (seed 000 eq 47, [`JohnsonCookDamage`]) if given.
//! 6. TEPLA-F porosity (seed 000 eqs 44–46, [`Tepla`]) if given, on a
//!    yielding step.
//! 7. Failure, irreversible, by the first of (the code stored in the
//!    history, [`FailureMode`]):
//!    1. melting — T_n + ΔT ≥ T_melt of the Johnson–Cook flow stress (seed
//!       000 §4.2 criterion 1; the flow stress is already zero there);
//!    2. damage — D ≥ 1;
//!    3. TEPLA-F — (f/f_c)² + D² ≥ 1 (seed 000 eq 43, criterion 2);
//!    4. Drucker — σ̇ : ε̇_p < 0 on a yielding step (criterion 3), if
//!       enabled in [`StabilityChecks`];
//!    5. loss of hyperbolicity — det R(n) ≤ 0 in the plane of the extreme
//!       principal stresses (eq 48, criterion 3), if enabled.
//!
//!    A failed point carries σ = −max(p, 0) I: no deviatoric and no tensile
//!    stress, its pressure in compression (see [`crate::damage`]), whatever
//!    the criterion.
//!
//! The stability checks ([`crate::stability`]) use the tangent of this
//! update at the end of the step with the adiabatic plastic modulus
//! H = ∂σ_y/∂ε_p + ∂σ_y/∂T · χ σ_y/(ρ c_v): the plastic heating of the
//! step itself softens the metal, which is how adiabatic shear bands form
//! (seed 000 §4.2: containers fail "by adiabatic shear banding"). The bulk
//! modulus is ρ c_bulk² of the pressure model.
//!
//! History per point (indices are the `*_INDEX` constants): equivalent
//! plastic strain, plastic strain rate (1/s), damage D, this step's
//! temperature increment (K), failed flag (0 or 1), porosity f, failure
//! mode code (0 intact), then the objective rate's own history (F and R for
//! Green–Naghdi). The initial damage and porosity are the means of their
//! distributions ([`Material::init_history`]) or the point's own draws
//! ([`Material::init_history_at`]).

use crate::specific_heat::SpecificHeat;
use crate::{
    error::positive,
    hypoelastic::{deviator, von_mises},
    objective::rate_of_deformation,
    random::{Gaussian, STREAM_POROSITY},
    stability::{loses_hyperbolicity, violates_drucker, StabilityChecks, TangentModulus},
    ConstitutiveError, FlowStress, JohnsonCookDamage, ObjectiveRate, PressureModel, Tepla,
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
/// History index of the TEPLA-F porosity f (0 without TEPLA).
pub const POROSITY_INDEX: usize = 5;
/// History index of the failure-mode code ([`FailureMode::code`], 0
/// intact).
pub const FAILURE_MODE_INDEX: usize = 6;
/// Number of history values before the objective rate's own.
pub const SCALAR_HISTORY_LEN: usize = 7;

/// Why a point failed; the first criterion met in a step wins, in this
/// order.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FailureMode {
    /// T ≥ T_melt (seed 000 §4.2 criterion 1).
    Melting,
    /// Johnson–Cook damage D ≥ 1 (seed 000 eq 47).
    Damage,
    /// TEPLA-F, (f/f_c)² + D² ≥ 1 (seed 000 eq 43).
    Tepla,
    /// Drucker's postulate violated, σ̇ : ε̇_p < 0 (seed 000 §4.2).
    Drucker,
    /// Loss of hyperbolicity, det R ≤ 0 (seed 000 eq 48).
    Hyperbolicity,
}

impl FailureMode {
    const ALL: [Self; 5] = [
        Self::Melting,
        Self::Damage,
        Self::Tepla,
        Self::Drucker,
        Self::Hyperbolicity,
    ];

    /// The code stored in the history: 1 … 5 in the order above.
    pub fn code(self) -> f64 {
        match self {
            Self::Melting => 1.0,
            Self::Damage => 2.0,
            Self::Tepla => 3.0,
            Self::Drucker => 4.0,
            Self::Hyperbolicity => 5.0,
        }
    }

    /// The mode of a stored code; `None` for 0 (intact) or an unknown code.
    pub fn from_code(code: f64) -> Option<Self> {
        Self::ALL.into_iter().find(|m| m.code() == code)
    }
}

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
    /// TEPLA-F porosity and failure (seed 000 eqs 43–46), if the metal
    /// fails by it.
    #[serde(default)]
    pub tepla: Option<Tepla>,
    /// Loss-of-stability failure checks (seed 000 §4.2 criterion 3); both
    /// off by default.
    #[serde(default)]
    pub stability: StabilityChecks,
    /// Objective stress rate.
    #[serde(default)]
    pub rate: ObjectiveRate,
    /// Fraction χ of plastic work turned into heat (seed 000: 0.9).
    #[serde(default = "default_taylor_quinney")]
    pub taylor_quinney: f64,
    /// Specific heat c_v, J/(kg·K), for the plastic heating (and, in the
    /// MPM, the viscous heating and the heat conduction): a number, or
    /// a temperature-dependent form (`Curie(...)`,
    /// [`crate::specific_heat`]; seed 000 §5.3, ref \[44\]).
    pub specific_heat: SpecificHeat,
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
    radial_return_with(
        |eps, rate, inv_dt| flow.flow_stress_and_slope(eps, rate, inv_dt, t),
        shear_modulus,
        trial_von_mises,
        eps_p,
        dt,
    )
}

/// The radial return of [`radial_return`] for any flow stress that does
/// not fall as the plastic strain grows: `flow(ε_p, ε̇_p, 1/Δt)` gives
/// σ_y at plastic strain ε_p and rate ε̇_p with its slope
/// dσ_y/dΔε_p = ∂σ_y/∂ε_p + ∂σ_y/∂ε̇_p /Δt, both in Pa; the temperature
/// and any other state are fixed over the step inside `flow` (a
/// rate-independent model returns the slope in ε_p alone). Solves
/// σ̄* − 3GΔε_p = σ_y(ε_pⁿ + Δε_p, Δε_p/Δt) for σ̄* above σ_y(ε_pⁿ, 0);
/// returns (Δε_p, σ_y at Δε_p).
pub fn radial_return_with(
    flow: impl Fn(f64, f64, f64) -> (f64, f64),
    shear_modulus: f64,
    trial_von_mises: f64,
    eps_p: f64,
    dt: f64,
) -> (f64, f64) {
    let three_g = 3.0 * shear_modulus;
    let inv_dt = if dt > 0.0 { 1.0 / dt } else { 0.0 };
    let rate_of = |x: f64| if dt > 0.0 { x / dt } else { 0.0 };
    let (mut lo, mut hi) = (0.0, trial_von_mises / three_g);
    // The perfectly plastic increment is an upper bound (σ_y only rises
    // with Δε_p) and the exact answer for a constant flow stress.
    let sigma0 = flow(eps_p, 0.0, 0.0).0;
    let mut x = ((trial_von_mises - sigma0) / three_g).clamp(lo, hi);
    let mut sigma_y = sigma0;
    for _ in 0..200 {
        let (s, slope) = flow(eps_p + x, rate_of(x), inv_dt);
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
    let (s, _) = flow(eps_p + hi, rate_of(hi), inv_dt);
    if trial_von_mises - three_g * hi - s <= 0.0 {
        (hi, s)
    } else {
        (x, sigma_y)
    }
}

/// The temperature rise of plastic heating, ΔT = χ Δw_p/(ρ c_v), K (seed
/// 000 §4.2): the fraction χ (Taylor–Quinney) of the plastic work per unit
/// volume Δw_p (J/m³) turned into heat at density ρ (kg/m³) and specific
/// heat c_v (J/(kg·K)).
#[inline]
pub fn plastic_heating(
    taylor_quinney: f64,
    plastic_work: f64,
    density: f64,
    specific_heat: f64,
) -> f64 {
    taylor_quinney * plastic_work / (density * specific_heat)
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
        if let Some(t) = &self.tepla {
            t.validate()?;
        }
        if !(self.taylor_quinney >= 0.0 && self.taylor_quinney <= 1.0) {
            return Err(ConstitutiveError::InvalidParameter {
                model: NAME,
                field: "taylor_quinney",
                value: self.taylor_quinney,
                expected: "a fraction in [0, 1]",
            });
        }
        self.specific_heat.validate(NAME)
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
            tepla: None,
            stability: StabilityChecks::default(),
            rate: ObjectiveRate::GreenNaghdi,
            taylor_quinney: TAYLOR_QUINNEY_SEED000,
            specific_heat: SpecificHeat::Constant(383.0),
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
            tepla: None,
            stability: StabilityChecks::default(),
            rate: ObjectiveRate::GreenNaghdi,
            taylor_quinney: TAYLOR_QUINNEY_SEED000,
            specific_heat: SpecificHeat::Constant(383.0),
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
            tepla: None,
            stability: StabilityChecks::default(),
            rate: ObjectiveRate::GreenNaghdi,
            taylor_quinney: TAYLOR_QUINNEY_SEED000,
            specific_heat: SpecificHeat::Constant(477.0),
        }
    }

    /// The 4340 steel container of seed 000 §5.3 with the whole failure
    /// treatment of §4.2: [`ElasticPlastic::steel_4340_seed000`] plus a
    /// Gaussian initial damage (mean 0.005, standard deviation 0.001), TEPLA-F
    /// ([`Tepla::steel_4340_seed000`]: initial porosity 0.005 ± 0.001,
    /// f_c = 0.3, ε_n = 0.3, s_n = 0.1, f_n = 0.1), both stability checks
    /// (Drucker and loss of hyperbolicity) and the temperature-dependent
    /// specific heat of §5.3 (ref \[44\]; [`SpecificHeat::steel_4340`]).
    pub fn steel_4340_cookoff_seed000() -> Self {
        Self {
            specific_heat: SpecificHeat::steel_4340(),
            damage: Some(JohnsonCookDamage {
                initial_damage: Some(Gaussian::new(0.005, 0.001)),
                ..JohnsonCookDamage::steel_4340_seed000()
            }),
            tepla: Some(Tepla::steel_4340_seed000()),
            stability: StabilityChecks {
                drucker: true,
                hyperbolicity: true,
            },
            ..Self::steel_4340_seed000()
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
            tepla: None,
            stability: StabilityChecks::default(),
            rate: ObjectiveRate::Jaumann,
            taylor_quinney: TAYLOR_QUINNEY_SEED000,
            specific_heat: SpecificHeat::Constant(477.0),
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

    /// Why the point of this history failed; `None` while intact.
    pub fn failure_mode(history: &[f64]) -> Option<FailureMode> {
        FailureMode::from_code(history[FAILURE_MODE_INDEX])
    }

    /// The adiabatic plastic modulus H = ∂σ_y/∂ε_p + ∂σ_y/∂T · χ σ_y/(ρ c_v)
    /// at plastic strain `eps_p`, rate `eps_p_rate` (1/s), temperature `t`
    /// (K) and density `rho` (kg/m³), Pa.
    pub fn adiabatic_hardening(&self, eps_p: f64, eps_p_rate: f64, t: f64, rho: f64) -> f64 {
        let (d_eps, d_t) = self.flow_stress.partial_derivatives(eps_p, eps_p_rate, t);
        if d_t == 0.0 {
            return d_eps;
        }
        let sigma_y = self.flow_stress.flow_stress(eps_p, eps_p_rate, t);
        d_eps + d_t * self.taylor_quinney * sigma_y / (rho * self.specific_heat.at(t))
    }

    /// The loss-of-stability criterion a yielding step meets, if any:
    /// `s_hat` and `d_hat` are the deviator and the rate of deformation in
    /// the unrotated frame, `p` the pressure, `eps_p` and `eps_rate` the
    /// updated plastic strain and rate, `t` the step's temperature.
    #[allow(clippy::too_many_arguments)]
    fn stability_failure(
        &self,
        s_hat: &Mat3,
        p: f64,
        d_hat: &Mat3,
        eps_p: f64,
        eps_rate: f64,
        t: f64,
        rho: f64,
        e: f64,
    ) -> Option<FailureMode> {
        let k = rho * self.pressure.bulk_sound_speed_squared(rho, e);
        let h = self.adiabatic_hardening(eps_p, eps_rate, t, rho);
        let tangent = TangentModulus::elastic_plastic(k, self.shear_modulus, h, s_hat);
        if self.stability.drucker && violates_drucker(&tangent, eps_rate, d_hat) {
            return Some(FailureMode::Drucker);
        }
        let sigma_hat = s_hat - Mat3::identity() * p;
        if self.stability.hyperbolicity && loses_hyperbolicity(&tangent, &sigma_hat) {
            return Some(FailureMode::Hyperbolicity);
        }
        None
    }

    fn initial_history(&self, history: &mut [f64], seed: Option<u64>) {
        history[..SCALAR_HISTORY_LEN].fill(0.0);
        if let Some(d) = &self.damage {
            history[DAMAGE_INDEX] = d.initial(seed);
        }
        if let Some(t) = &self.tepla {
            let fc = t.critical_porosity;
            history[POROSITY_INDEX] = match seed {
                None => t.initial_porosity.mean_within(0.0, fc),
                Some(s) => t.initial_porosity.sample(s, STREAM_POROSITY, 0.0, fc),
            };
        }
        self.rate.init_history(&mut history[SCALAR_HISTORY_LEN..]);
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

    /// Zero strain and flags; damage and porosity at the means of their
    /// distributions.
    fn init_history(&self, history: &mut [f64]) {
        self.initial_history(history, None);
    }

    /// As [`Material::init_history`], with the initial damage and porosity
    /// drawn for the point `seed` (seed 000 §4.2, §5.3).
    fn init_history_at(&self, history: &mut [f64], seed: u64) {
        self.initial_history(history, Some(seed));
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
        // On the yield surface σ̄ = σ_y: the trial deviator is scaled by
        // σ_y/σ̄*, which equals 1 − 3GΔε_p/σ̄* at the converged return but
        // keeps full relative precision when σ_y ≪ σ̄* (near melting the
        // difference form cancels catastrophically). The work uses the same
        // σ_y (exactly 0 for a melted point).
        let (s_hat, d_eps, sigma_eq, sigma_y) =
            if trial > self.flow_stress.flow_stress(eps_p, 0.0, t) {
                let (d_eps, sigma_y) = radial_return(&self.flow_stress, g, trial, eps_p, dt, t);
                let factor = (sigma_y / trial).max(0.0);
                (s_trial * factor, d_eps, sigma_y, sigma_y)
            } else {
                (s_trial, 0.0, trial, 0.0)
            };

        let eps_rate = if dt > 0.0 { d_eps / dt } else { 0.0 };
        let plastic_work = sigma_y * d_eps;
        let d_temp = self.specific_heat.plastic_heating_rise(
            t,
            self.taylor_quinney,
            plastic_work,
            input.density,
        );
        scalars[PLASTIC_STRAIN_INDEX] = eps_p + d_eps;
        scalars[PLASTIC_STRAIN_RATE_INDEX] = eps_rate;
        scalars[TEMPERATURE_INCREMENT_INDEX] = d_temp;
        if let Some(damage) = &self.damage {
            scalars[DAMAGE_INDEX] =
                damage.accumulate(scalars[DAMAGE_INDEX], d_eps, -p, sigma_eq, eps_rate, t);
        }
        let damage = scalars[DAMAGE_INDEX];
        let melted = self
            .flow_stress
            .melt_temperature()
            .is_some_and(|t_melt| t + d_temp >= t_melt);
        let mut mode = if melted {
            Some(FailureMode::Melting)
        } else if damage >= 1.0 {
            Some(FailureMode::Damage)
        } else {
            None
        };
        if let Some(tepla) = &self.tepla {
            if d_eps > 0.0 {
                scalars[POROSITY_INDEX] =
                    tepla.advance(scalars[POROSITY_INDEX], eps_p, d_eps, d.trace() * dt);
            }
            if mode.is_none() && tepla.fails(scalars[POROSITY_INDEX], damage) {
                mode = Some(FailureMode::Tepla);
            }
        }
        if mode.is_none() && d_eps > 0.0 && self.stability.any() {
            mode = self.stability_failure(
                &s_hat,
                p,
                &frames.unrotate_end(&d),
                eps_p + d_eps,
                eps_rate,
                t,
                input.density,
                input.specific_internal_energy,
            );
        }
        if let Some(mode) = mode {
            scalars[FAILED_INDEX] = 1.0;
            scalars[FAILURE_MODE_INDEX] = mode.code();
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
        self.pressure
            .longitudinal_wave_speed(density, specific_internal_energy, self.shear_modulus)
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
    /// One perfectly plastic shear step of the seed 000 copper (with the
    /// specific heat `c_v`) at temperature `t`: from the yield surface in
    /// pure shear (s_xy = σ_y/√3), the shear rate D_xy chosen so that the
    /// plastic increment is 1e-3 (trial σ̄ = σ_y + 3G Δε_p needs
    /// 2G D_xy Δt √3 = 3G × 1e-3). Returns the update and the history.
    fn plastic_shear_step(c_v: SpecificHeat, t: f64) -> (StressUpdate, Vec<f64>) {
        let m = ElasticPlastic {
            rate: ObjectiveRate::Jaumann,
            specific_heat: c_v,
            ..ElasticPlastic::ofhc_copper_seed000()
        };
        let (g, sy) = (43.8e9, 70.0e6);
        let tau = sy / 3f64.sqrt();
        let sigma = Mat3::new(0.0, tau, 0.0, tau, 0.0, 0.0, 0.0, 0.0, 0.0);
        let dt = 1e-6;
        let d_xy = 3.0 * g * 1e-3 / (2.0 * g * dt * 3f64.sqrt());
        let l = Mat3::new(0.0, d_xy, 0.0, d_xy, 0.0, 0.0, 0.0, 0.0, 0.0);
        let mut h = fresh(&m);
        let out = m.update_stress(&input(l, dt, sigma, t, 8930.0), &mut h);
        (out, h)
    }

    #[test]
    fn plastic_work_heats_with_taylor_quinney_fraction() {
        let (out, h) = plastic_shear_step(SpecificHeat::Constant(383.0), 300.0);
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

    /// With c_v(T) through the Curie point the same step heats the point
    /// by the rise whose heat is χ Δw_p/ρ = 0.9 × 7e4/8930 = 7.0549 J/kg
    /// (H(T + ΔT) − H(T), [`crate::specific_heat`]): at 1000 K, where the
    /// steel's c_v is 982.18 J/(kg·K) (t = 1 − 1000/1040 = 0.0384615,
    /// 190.14 − 10.529 + 418.30/0.521201), about 7.18 mK instead of the
    /// 18.4 mK of the constant 383.
    #[test]
    fn plastic_work_heats_through_a_temperature_dependent_specific_heat() {
        let curie = SpecificHeat::steel_4340();
        let (out, h) = plastic_shear_step(curie.clone(), 1000.0);
        let q = 0.9 * out.plastic_work / 8930.0;
        assert!((q - 7.0549).abs() < 1e-4, "{q}");
        let dtemp = h[TEMPERATURE_INCREMENT_INDEX];
        let held = curie.heat(1000.0 + dtemp) - curie.heat(1000.0);
        assert!((held - q).abs() < 1e-9 * q, "{held} vs {q}");
        assert!(
            (dtemp - q / curie.at(1000.0)).abs() < 1e-4 * dtemp,
            "{dtemp}"
        );
        assert!((dtemp - 7.1829e-3).abs() < 1e-6, "{dtemp}");
        // The model validates the Curie form and a constant alike.
        let m = ElasticPlastic {
            specific_heat: curie,
            ..ElasticPlastic::ofhc_copper_seed000()
        };
        assert!(m.validate().is_ok());
        let bad = ElasticPlastic {
            specific_heat: SpecificHeat::Constant(-1.0),
            ..m
        };
        assert!(matches!(
            bad.validate(),
            Err(ConstitutiveError::InvalidParameter {
                field: "specific_heat",
                ..
            })
        ));
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
                assert_eq!(ElasticPlastic::failure_mode(&h), Some(FailureMode::Damage));
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
        assert_eq!(ElasticPlastic::failure_mode(&h), Some(FailureMode::Melting));
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
            ElasticPlastic::steel_4340_cookoff_seed000(),
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
        let bad = ElasticPlastic {
            tepla: Some(Tepla {
                critical_porosity: 0.0,
                ..Tepla::steel_4340_seed000()
            }),
            ..ElasticPlastic::steel_4340_seed000()
        };
        let msg = bad.validate().unwrap_err().to_string();
        assert!(msg.contains("critical_porosity"), "{msg}");
    }

    #[test]
    fn failure_mode_codes_round_trip() {
        for mode in FailureMode::ALL {
            assert_eq!(FailureMode::from_code(mode.code()), Some(mode));
        }
        assert_eq!(FailureMode::from_code(0.0), None);
        assert_eq!(
            ElasticPlastic::failure_mode(&fresh(&ElasticPlastic::steel_4340_seed000())),
            None
        );
    }

    /// Simple shear to γ = 5 with the Jaumann rate, seed 000 copper
    /// (perfectly plastic, k = σ_y/√3): the stress reaches the steady state
    /// of ṡ = 0 with s^∇ = 2G(D − λ s), s = a(e₁e₁ − e₂e₂) + b(e₁e₂ + e₂e₁):
    /// a² + b² = k² and Ω(a² + b²) = G D₁₂ a with Ω = D₁₂ = γ̇/2, so
    /// a = k²/G = 37290.715 Pa and b = √(k² − a²). With Green–Naghdi the
    /// spin is that of R, Ω = (γ̇/2)/(1 + γ²/4), so quasi-steadily
    /// a = k²/(G(1 + γ²/4)) — 5143.5 Pa at γ = 5 (the exact solution lags
    /// the slowly falling a; measured 3.5e-4 of a, tolerance 1e-3).
    #[test]
    fn simple_shear_with_rotation_reaches_the_hand_computed_steady_state() {
        let (g, sy) = (43.8e9_f64, 70.0e6_f64);
        let k = sy / 3f64.sqrt();
        let (dt, gamma_dot) = (1e-7, 1e3);
        let l = Mat3::new(0.0, gamma_dot, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0);
        for rate in [ObjectiveRate::Jaumann, ObjectiveRate::GreenNaghdi] {
            let m = ElasticPlastic {
                rate,
                ..ElasticPlastic::ofhc_copper_seed000()
            };
            let mut h = fresh(&m);
            let mut sigma = Mat3::zeros();
            for step in 1..=50_000 {
                let out = m.update_stress(&input(l, dt, sigma, 300.0, 8930.0), &mut h);
                sigma = out.stress;
                let gamma = step as f64 * gamma_dot * dt;
                if step % 10_000 != 0 {
                    continue;
                }
                let s = deviator(&sigma);
                assert!(
                    (von_mises(&s) - sy).abs() < 1e-12 * sy,
                    "{rate:?} γ = {gamma}"
                );
                let (a, tol) = match rate {
                    ObjectiveRate::Jaumann => (k * k / g, 1e-8),
                    ObjectiveRate::GreenNaghdi => (k * k / (g * (1.0 + gamma * gamma / 4.0)), 1e-3),
                };
                let b = (k * k - a * a).sqrt();
                assert!(
                    (s[(0, 0)] - a).abs() < tol * a,
                    "{rate:?} γ = {gamma}: {}",
                    s[(0, 0)]
                );
                assert!(
                    (s[(1, 1)] + a).abs() < tol * a,
                    "{rate:?} γ = {gamma}: {}",
                    s[(1, 1)]
                );
                assert!(
                    (s[(0, 1)] - b).abs() < 1e-9 * b,
                    "{rate:?} γ = {gamma}: {}",
                    s[(0, 1)]
                );
            }
            assert!((k * k / g - 37_290.715).abs() < 1e-3);
        }
    }

    /// Per-point initial state of the seed 000 §5.3 container: the mean
    /// without a seed (D₀ = f₀ = 0.005); with one, draws that depend on the
    /// seed alone, inside [0, 1] and [0, f_c], intact, and the
    /// Green–Naghdi history at the identity.
    #[test]
    fn initial_history_draws_damage_and_porosity_per_point() {
        let m = ElasticPlastic::steel_4340_cookoff_seed000();
        let h = fresh(&m);
        assert_eq!((h[DAMAGE_INDEX], h[POROSITY_INDEX]), (0.005, 0.005));
        let at = |seed| {
            let mut h = vec![f64::NAN; m.history_len()];
            m.init_history_at(&mut h, seed);
            h
        };
        let (a, b, c) = (at(11), at(11), at(12));
        let bits = |h: &[f64]| h.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
        assert_eq!(bits(&a), bits(&b));
        assert_ne!(a[DAMAGE_INDEX], c[DAMAGE_INDEX]);
        assert_ne!(a[POROSITY_INDEX], c[POROSITY_INDEX]);
        assert_ne!(a[DAMAGE_INDEX], a[POROSITY_INDEX], "separate streams");
        for h in [&a, &c] {
            assert!((0.0..=1.0).contains(&h[DAMAGE_INDEX]));
            assert!((0.0..=0.3).contains(&h[POROSITY_INDEX]));
            assert_eq!(h[FAILED_INDEX], 0.0);
            assert_eq!(h[FAILURE_MODE_INDEX], 0.0);
            assert_eq!(
                &h[SCALAR_HISTORY_LEN..SCALAR_HISTORY_LEN + 9],
                Mat3::identity().as_slice()
            );
        }
        // A model without distributions ignores the seed.
        let plain = ElasticPlastic::steel_4340_seed000();
        let mut h0 = vec![1.0; plain.history_len()];
        plain.init_history_at(&mut h0, 99);
        assert_eq!(h0, fresh(&plain));
    }

    /// Pure shear (no dilatation) of the perfectly plastic copper with
    /// TEPLA, f₀ = 0.005 exactly: the porosity grows by nucleation alone,
    /// f = f₀ + ∫₀^ε_p A(ε) dε with A the density of eq 46 — the reference
    /// integral by Simpson's rule (20 000 panels), independent of the
    /// model's per-step midpoint rule. ε_p reaches ≈ 0.46.
    #[test]
    fn shear_nucleates_voids_by_the_integral_of_eq_46() {
        let tepla = Tepla {
            initial_porosity: Gaussian::new(0.005, 0.0),
            ..Tepla::steel_4340_seed000()
        };
        let m = ElasticPlastic {
            tepla: Some(tepla),
            rate: ObjectiveRate::Jaumann,
            ..ElasticPlastic::ofhc_copper_seed000()
        };
        let mut h = fresh(&m);
        let (dt, d12) = (1e-7, 1e3);
        let l = Mat3::new(0.0, d12, 0.0, d12, 0.0, 0.0, 0.0, 0.0, 0.0);
        let mut sigma = Mat3::zeros();
        for _ in 0..4000 {
            let out = m.update_stress(&input(l, dt, sigma, 300.0, 8930.0), &mut h);
            assert!(!out.failed);
            sigma = out.stress;
        }
        let eps = h[PLASTIC_STRAIN_INDEX];
        assert!(eps > 0.45 && eps < 0.47, "{eps}");
        let density = |e: f64| {
            0.1 / (0.1 * std::f64::consts::TAU.sqrt()) * (-0.5 * ((e - 0.3) / 0.1).powi(2)).exp()
        };
        let n = 20_000;
        let w = eps / n as f64;
        let simpson = (0..=n)
            .map(|i| {
                let c = if i == 0 || i == n {
                    1.0
                } else if i % 2 == 1 {
                    4.0
                } else {
                    2.0
                };
                c * density(i as f64 * w)
            })
            .sum::<f64>()
            * w
            / 3.0;
        // The model integrates by the midpoint rule per plastic increment
        // Δε_p = 2D₁₂Δt/√3: error ≤ ε_p Δε_p² max|A''|/24, max|A''| =
        // A(ε_n)/s_n² = 39.89 — 1.0e-8 here.
        let d_eps = 2.0 * d12 * dt / 3f64.sqrt();
        let bound = eps * d_eps * d_eps * (density(0.3) / 0.01) / 24.0;
        assert!(bound < 1.1e-8, "{bound}");
        let f = h[POROSITY_INDEX];
        assert!(
            (f - (0.005 + simpson)).abs() < bound,
            "{f} vs {}",
            0.005 + simpson
        );
        // Half the nucleating fraction and more has nucleated past ε_n.
        assert!(simpson > 0.05 && simpson < 0.1, "{simpson}");
    }

    /// Triaxial tension with shear, copper without damage, TEPLA with
    /// f₀ = 0.005 and no nucleation: once yielding, every step grows the
    /// porosity by 1 − f ← (1 − f) e^(−tr d Δt), tr d Δt = 3e-4, so the
    /// point fails by TEPLA (f ≥ f_c = 0.3) ⌈ln(0.995/0.7)/3e-4⌉ = 1173
    /// yielding steps after the first, keeping −max(p, 0) I for good.
    #[test]
    fn dilatation_grows_porosity_to_tepla_failure_at_the_hand_computed_step() {
        let tepla = Tepla {
            initial_porosity: Gaussian::new(0.005, 0.0),
            nucleation_fraction: 0.0,
            ..Tepla::steel_4340_seed000()
        };
        let m = ElasticPlastic {
            tepla: Some(tepla),
            rate: ObjectiveRate::Jaumann,
            ..ElasticPlastic::ofhc_copper_seed000()
        };
        let mut h = fresh(&m);
        let dt = 1e-7;
        let l = Mat3::new(1e3, 2e4, 0.0, 0.0, 1e3, 0.0, 0.0, 0.0, 1e3);
        let needed = ((0.995f64 / 0.7).ln() / 3e-4).ceil() as usize;
        assert_eq!(needed, 1173);
        let mut sigma = Mat3::zeros();
        let mut first_plastic = None;
        let mut failed_at = None;
        for k in 0..3000 {
            let f_before = h[POROSITY_INDEX];
            let out = m.update_stress(&input(l, dt, sigma, 300.0, 8930.0), &mut h);
            sigma = out.stress;
            if first_plastic.is_none() && out.plastic_work > 0.0 {
                first_plastic = Some(k);
            }
            if let Some(k0) = first_plastic {
                if failed_at.is_none() {
                    let grown = 1.0 - (1.0 - f_before) * (-3e-4f64).exp();
                    assert!((h[POROSITY_INDEX] - grown).abs() < 1e-15, "step {k}");
                    let expected = 1.0 - 0.995 * (-3e-4 * (k - k0 + 1) as f64).exp();
                    assert!((h[POROSITY_INDEX] - expected).abs() < 1e-12, "step {k}");
                }
            }
            if out.failed && failed_at.is_none() {
                failed_at = Some(k);
                assert_eq!(ElasticPlastic::failure_mode(&h), Some(FailureMode::Tepla));
                assert!(h[POROSITY_INDEX] >= 0.3);
            }
            if failed_at.is_some() {
                assert!(out.failed);
                assert_eq!(sigma, -Mat3::identity() * (-sigma.trace() / 3.0).max(0.0));
            }
        }
        let k0 = first_plastic.expect("the shear yields");
        assert_eq!(failed_at, Some(k0 + needed - 1));
    }

    /// Adiabatic pure shear of 4340 at D₁₂ = 1e4/s from 294 K with the
    /// temperature fed back as the solver does: the flow stress peaks where
    /// strain hardening and thermal softening balance. An independent
    /// quadrature of σ(ε) = (A + Bεⁿ)(1 + C ln ε̇)(1 − T*ᵐ) with
    /// dT = χσ dε/(ρc_v), ε̇ = 2D₁₂/√3, puts the peak at ε_p = 0.42394,
    /// T = 417.98 K. Drucker's postulate fails at the first step whose
    /// adiabatic modulus H is negative — there; loss of hyperbolicity comes
    /// slightly earlier, where the hand-derived plane-strain determinant
    /// (principal frame of σ = τ(e₁e₂ + e₂e₁), p = 0)
    /// det₂ = 4(a + G)(G − b) − G²τ²/(4ab), a = λ + G, b = 3G²/(3G + H),
    /// turns negative (H ≈ 3Gτ²/(16a(a + G)) ≈ 3e5 Pa).
    #[test]
    fn adiabatic_shear_localises_at_the_hand_computed_strain() {
        let rho = 7830.0;
        let run = |stability: StabilityChecks| {
            let m = ElasticPlastic {
                damage: None,
                stability,
                ..ElasticPlastic::steel_4340_seed000()
            };
            let mut h = fresh(&m);
            let (dt, d12) = (1e-8, 1e4);
            let l = Mat3::new(0.0, d12, 0.0, d12, 0.0, 0.0, 0.0, 0.0, 0.0);
            let (mut sigma, mut t) = (Mat3::zeros(), 294.0);
            // (H, τ) at the state each step's check used.
            let mut checks = Vec::new();
            for _ in 0..10_000 {
                let out = m.update_stress(&input(l, dt, sigma, t, rho), &mut h);
                let (eps, rate) = (h[PLASTIC_STRAIN_INDEX], h[PLASTIC_STRAIN_RATE_INDEX]);
                if eps > 0.0 {
                    let tau = m.flow_stress.flow_stress(eps, rate, t) / 3f64.sqrt();
                    checks.push((m.adiabatic_hardening(eps, rate, t, rho), tau));
                }
                sigma = out.stress;
                if out.failed {
                    return (m, h, t, checks);
                }
                t += h[TEMPERATURE_INCREMENT_INDEX];
            }
            panic!(
                "{stability:?}: no failure by ε_p = {}",
                h[PLASTIC_STRAIN_INDEX]
            );
        };
        let (_, h, t, checks) = run(StabilityChecks {
            drucker: true,
            hyperbolicity: false,
        });
        assert_eq!(ElasticPlastic::failure_mode(&h), Some(FailureMode::Drucker));
        let eps_drucker = h[PLASTIC_STRAIN_INDEX];
        assert!((eps_drucker - 0.42394).abs() < 1e-3, "{eps_drucker}");
        assert!((t - 417.98).abs() < 0.05, "{t}");
        let n = checks.len();
        assert!(
            checks[n - 1].0 < 0.0 && checks[n - 2].0 > 0.0,
            "{:?}",
            &checks[n - 2..]
        );

        let (m, h, _, checks) = run(StabilityChecks {
            drucker: false,
            hyperbolicity: true,
        });
        assert_eq!(
            ElasticPlastic::failure_mode(&h),
            Some(FailureMode::Hyperbolicity)
        );
        assert!(h[PLASTIC_STRAIN_INDEX] < eps_drucker);
        let g = m.shear_modulus;
        let k = rho * m.pressure.bulk_sound_speed_squared(rho, 0.0);
        let a = k - 2.0 * g / 3.0 + g;
        let det2 = |(hh, tau): (f64, f64)| {
            let b = 3.0 * g * g / (3.0 * g + hh);
            4.0 * (a + g) * (g - b) - g * g * tau * tau / (4.0 * a * b)
        };
        let n = checks.len();
        assert!(det2(checks[n - 1]) <= 0.0, "{:?}", checks[n - 1]);
        assert!(det2(checks[n - 2]) > 0.0, "{:?}", checks[n - 2]);
        let h_crit = 3.0 * g * checks[n - 1].1.powi(2) / (16.0 * a * (a + g));
        assert!(h_crit > 2.0e5 && h_crit < 4.0e5, "{h_crit}");
    }

    /// The seed 000 §5.3 container in triaxial tension with shear: the
    /// point fails by TEPLA-F — neither f ≥ f_c nor D ≥ 1 alone, their
    /// quadratic sum (measured: D = 0.858, f = 0.160, sum 1.02) — and stays
    /// failed.
    #[test]
    fn cookoff_steel_fails_in_triaxial_tension_by_tepla() {
        let m = ElasticPlastic::steel_4340_cookoff_seed000();
        let mut h = vec![0.0; m.history_len()];
        m.init_history_at(&mut h, crate::random::point_seed([0.01, 0.02, 0.0], 0));
        let dt = 1e-7;
        let l = Mat3::new(2e4, 3e4, 0.0, 0.0, 2e4, 0.0, 0.0, 0.0, 2e4);
        let (mut sigma, mut rho, mut t) = (Mat3::zeros(), 7830.0, 294.0);
        let mut failed = false;
        for _ in 0..2000 {
            rho /= 1.0 + l.trace() * dt;
            let out = m.update_stress(&input(l, dt, sigma, t, rho), &mut h);
            sigma = out.stress;
            t += h[TEMPERATURE_INCREMENT_INDEX];
            assert!(!failed || out.failed, "recovered");
            failed = out.failed;
        }
        assert!(failed);
        assert_eq!(ElasticPlastic::failure_mode(&h), Some(FailureMode::Tepla));
        let (d, f) = (h[DAMAGE_INDEX], h[POROSITY_INDEX]);
        assert!(d < 1.0 && f < 0.3, "D = {d}, f = {f}");
        assert!((f / 0.3).powi(2) + d * d >= 1.0, "D = {d}, f = {f}");
    }
}
