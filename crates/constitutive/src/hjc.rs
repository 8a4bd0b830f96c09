//! Holmquist–Johnson–Cook (HJC) concrete with Jiang's tensile damage,
//! seed 001 §4.3 (eqs 56–58; Holmquist, Johnson & Cook 1993; Jiang 2010).
//!
//! **Strength** (eq 56), normalised by the quasi-static compressive
//! strength f'_c (Pa), p* = p/f'_c, T* = T/f'_c:
//!
//! σ* = [A(1 − D) + B p*^N][1 + C ln ε̇*],  σ* ≤ S_max,
//!
//! with ε̇* = ε̇/ε̇₀ the equivalent deviatoric strain rate √(⅔ dev D:dev D)
//! over the reference rate ε̇₀ (1/s), taken ≥ 1 so the rate factor is ≥ 1
//! (the usual HJC convention; eq 56 is undefined for ε̇ → 0). Eq 56 needs a
//! non-negative p* when N is not an integer; for −T(1 − D) ≤ p < 0 the
//! strength is continued linearly to zero at p = −T,
//! σ* = A(1 − D)(1 + p*/T*) (reconstruction: seed 001 and HJC 1993 give
//! only the tensile pressure limit in tension).
//!
//! **Compression–shear damage** (eq 57):
//! D_c = Σ (Δε_p + Δμ_p)/max(D₁ (p* + T*)^{D₂}, EF_min),
//! with Δε_p the equivalent plastic strain increment and Δμ_p the increment
//! of permanent (crushed) volumetric strain. EF_min is the "third damage
//! constant" of seed 001 line 320, the smallest fracture strain.
//!
//! **Tensile damage** (eq 58, Jiang 2010): Ḋ_t = a D_t (1 − D_t)
//! (σ_s/σ₀ − 1)^γ for σ_s > σ₀, with σ_s = −p the hydrostatic tension
//! (Jiang's "equivalent micro holes" are spherical cavities, driven by the
//! mean stress). The logistic equation is integrated exactly over a step
//! at the step's σ_s: D_t ← D_t e^{rΔt}/(1 − D_t + D_t e^{rΔt}),
//! r = a (σ_s/σ₀ − 1)^γ. Growth needs a seed D_t0 > 0; spall ("the limit of
//! damage", seed 001 line 325) is D_t ≥ D_tc.
//!
//! **Pressure** (three regions, HJC 1993; seed 001 lines 326–329), with
//! μ = ρ/ρ₀ − 1 and μ_max the largest μ reached:
//!
//! 1. elastic, μ ≤ μ_crush: p = K_e μ, K_e = p_crush/μ_crush;
//! 2. compaction, μ_crush < μ ≤ μ_plock: loading along the straight line
//!    from (μ_crush, p_crush) to (μ_plock, p_lock); unloading from μ_max
//!    along p = p(μ_max) − K_u (μ_max − μ) with K_u interpolated between
//!    K_e and K₁ by F = (μ_max − μ_crush)/(μ_plock − μ_crush),
//!    K_u = (1 − F) K_e + F K₁, leaving the permanent crush
//!    μ_max − p(μ_max)/K_u;
//! 3. fully dense, μ > μ_plock: p = K₁ μ̄ + K₂ μ̄² + K₃ μ̄³,
//!    μ̄ = (μ − μ_lock)/(1 + μ_lock), loading and unloading alike, p = K₁ μ̄
//!    for μ̄ < 0.
//!
//! μ_plock, the end of region 2, is where the fully-dense curve reaches
//! p_lock (continuity of the loading curve; HJC 1993 lists p_lock and
//! μ_lock, LS-DYNA's MAT_111 the same construction). Tension is limited to
//! p ≥ −T(1 − D), D = max(D_c, D_t) of the start of the step.
//!
//! The volumetric strain is integrated from the rate of deformation,
//! ln(V/V₀) += tr D Δt, μ = V₀/V − 1 (the same as ρ/ρ₀ − 1 for a point whose
//! density follows its volume), so the path-dependent pressure does not
//! depend on how the solver updates the density.
//!
//! **Step** (unrotated frame of the [`ObjectiveRate`]): pressure from the
//! EOS; trial deviator ŝ* = ŝ_n + 2G dev(d̂) Δt; radial return to σ* f'_c
//! with the damage implicit — Δε_p solves σ̄* − 3GΔε_p = σ_y(D_c(Δε_p))
//! by bisection, so that after the step σ̄ ≤ σ_y at the updated damage;
//! tensile damage; failure when D_c ≥ 1 or D_t ≥ D_tc (seed 001 §5.3:
//! "the particles fail when their damage value reaches unit"). A failed
//! point carries σ = −max(p, 0) I (see [`crate::damage`]).
//!
//! History per point: equivalent plastic strain, D_c, D_t, failed flag,
//! ln(V/V₀), μ_max, then this step's rate factor 1 + C ln ε̇* (a per-step
//! value, not state), then the objective rate's own history.

use crate::{
    error::{non_negative, positive},
    hypoelastic::{deviator, von_mises},
    objective::rate_of_deformation,
    ConstitutiveError, ObjectiveRate,
};
use brisance_core::{Eos, Mat3, Material, StressUpdate, StressUpdateInput};
use serde::{Deserialize, Serialize};

const NAME: &str = "hjc";

/// History index of the equivalent plastic strain ε_p.
pub const PLASTIC_STRAIN_INDEX: usize = 0;
/// History index of the compression–shear damage D_c (eq 57).
pub const COMPRESSION_DAMAGE_INDEX: usize = 1;
/// History index of the tensile damage D_t (eq 58).
pub const TENSILE_DAMAGE_INDEX: usize = 2;
/// History index of the failed flag (1 failed, 0 intact).
pub const FAILED_INDEX: usize = 3;
/// History index of ln(V/V₀), the logarithmic volumetric strain.
pub const LOG_VOLUME_INDEX: usize = 4;
/// History index of μ_max, the largest compression μ reached.
pub const MAX_COMPRESSION_INDEX: usize = 5;
/// Number of history values that are state (unchanged by a rigid motion).
pub const STATE_HISTORY_LEN: usize = 6;
/// History index of this step's strain-rate factor 1 + C ln ε̇*.
pub const RATE_FACTOR_INDEX: usize = 6;
/// Number of history values before the objective rate's own.
pub const SCALAR_HISTORY_LEN: usize = 7;

/// Jiang's tensile damage law (seed 001 eq 58, Jiang 2010).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct JiangTensileDamage {
    /// Micro-crack growth factor a, 1/s.
    pub growth_factor: f64,
    /// Threshold stress σ₀ of micro-void nucleation and growth, Pa.
    pub threshold_stress: f64,
    /// Exponent γ of the over-threshold stress.
    pub exponent: f64,
    /// Initial damage D_t0, in (0, 1) (the law grows no damage from 0).
    pub initial_damage: f64,
    /// Damage at which the point spalls, D_tc, in (D_t0, 1).
    pub critical_damage: f64,
}

impl JiangTensileDamage {
    fn validate(&self) -> Result<(), ConstitutiveError> {
        positive(NAME, "tensile_damage.growth_factor", self.growth_factor)?;
        positive(
            NAME,
            "tensile_damage.threshold_stress",
            self.threshold_stress,
        )?;
        positive(NAME, "tensile_damage.exponent", self.exponent)?;
        let fraction = |field, value: f64, lo: f64| {
            if value > lo && value < 1.0 {
                Ok(())
            } else {
                Err(ConstitutiveError::InvalidParameter {
                    model: NAME,
                    field,
                    value,
                    expected: "a fraction in (0, 1), critical above initial",
                })
            }
        };
        fraction("tensile_damage.initial_damage", self.initial_damage, 0.0)?;
        fraction(
            "tensile_damage.critical_damage",
            self.critical_damage,
            self.initial_damage,
        )
    }

    /// D_t after a step Δt (s) under hydrostatic tension σ_s (Pa): the
    /// exact solution of eq 58 at constant σ_s.
    pub fn advance(&self, d_t: f64, sigma_s: f64, dt: f64) -> f64 {
        if !(sigma_s > self.threshold_stress) || d_t <= 0.0 {
            return d_t;
        }
        let r = self.growth_factor * (sigma_s / self.threshold_stress - 1.0).powf(self.exponent);
        let x = r * dt;
        if x > 700.0 {
            return 1.0;
        }
        let g = x.exp();
        (d_t * g / (1.0 - d_t + d_t * g)).clamp(d_t, 1.0)
    }
}

/// Holmquist–Johnson–Cook concrete (seed 001 §4.3).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Hjc {
    /// Initial density ρ₀, kg/m³ (for μ in the wave speed).
    pub reference_density: f64,
    /// Shear modulus G, Pa.
    pub shear_modulus: f64,
    /// Quasi-static uniaxial compressive strength f'_c, Pa.
    pub compressive_strength: f64,
    /// Maximum tensile hydrostatic pressure T, Pa.
    pub tensile_strength: f64,
    /// Normalised cohesive strength A.
    pub a: f64,
    /// Normalised pressure hardening coefficient B.
    pub b: f64,
    /// Pressure hardening exponent N.
    pub n: f64,
    /// Strain rate coefficient C.
    pub c: f64,
    /// Normalised maximum strength S_max.
    pub s_max: f64,
    /// Reference strain rate ε̇₀, 1/s.
    pub reference_strain_rate: f64,
    /// Damage constant D₁.
    pub d1: f64,
    /// Damage constant D₂.
    pub d2: f64,
    /// Smallest plastic strain to fracture EF_min.
    pub ef_min: f64,
    /// Crushing pressure p_crush, Pa.
    pub p_crush: f64,
    /// Crushing volumetric strain μ_crush.
    pub mu_crush: f64,
    /// Locking pressure p_lock, Pa.
    pub p_lock: f64,
    /// Locking volumetric strain μ_lock (ρ_grain/ρ₀ − 1).
    pub mu_lock: f64,
    /// Fully-dense coefficient K₁, Pa.
    pub k1: f64,
    /// Fully-dense coefficient K₂, Pa.
    pub k2: f64,
    /// Fully-dense coefficient K₃, Pa.
    pub k3: f64,
    /// Jiang's tensile damage (eq 58), if the concrete spalls by it.
    #[serde(default)]
    pub tensile_damage: Option<JiangTensileDamage>,
    /// Objective stress rate.
    #[serde(default)]
    pub rate: ObjectiveRate,
}

impl Hjc {
    /// The 48 MPa concrete of Holmquist, Johnson & Cook (1993), the model
    /// seed 001 §4.3 cites: ρ₀ = 2440 kg/m³, G = 14.86 GPa, A = 0.79,
    /// B = 1.60, N = 0.61, C = 0.007, S_max = 7.0, f'_c = 48 MPa,
    /// T = 4 MPa, ε̇₀ = 1 s⁻¹, EF_min = 0.01, D₁ = 0.04, D₂ = 1.0,
    /// p_crush = 16 MPa, μ_crush = 0.001, K₁ = 85 GPa, K₂ = −171 GPa,
    /// K₃ = 208 GPa, p_lock = 0.80 GPa, μ_lock = 0.10. No tensile damage
    /// (HJC 1993 has none); Jaumann rate (seed 001 eq 30).
    pub fn concrete_48mpa_hjc1993() -> Self {
        Self {
            reference_density: 2440.0,
            shear_modulus: 14.86e9,
            compressive_strength: 48.0e6,
            tensile_strength: 4.0e6,
            a: 0.79,
            b: 1.60,
            n: 0.61,
            c: 0.007,
            s_max: 7.0,
            reference_strain_rate: 1.0,
            d1: 0.04,
            d2: 1.0,
            ef_min: 0.01,
            p_crush: 16.0e6,
            mu_crush: 0.001,
            p_lock: 0.80e9,
            mu_lock: 0.10,
            k1: 85.0e9,
            k2: -171.0e9,
            k3: 208.0e9,
            tensile_damage: None,
            rate: ObjectiveRate::Jaumann,
        }
    }

    /// The 25 MPa concrete of seed 001 §5.3 (Luccioni & Luege 2006).
    ///
    /// **Reconstruction.** Seed 001 states that Luccioni & Luege's material
    /// parameters were used but quotes none of them; the only number it
    /// gives is f'_c = 25 MPa (lines 422–423). This set keeps every
    /// normalised constant and the fully-dense EOS of HJC 1993
    /// ([`Hjc::concrete_48mpa_hjc1993`]) and changes what f'_c sets in HJC
    /// 1993's own construction: f'_c = 25 MPa, p_crush = f'_c/3 = 8.33 MPa
    /// (the pressure at the uniaxial crush point, p = σ/3), μ_crush =
    /// p_crush/K_e with HJC 1993's K_e = 16 GPa (5.21e-4), and T scaled with
    /// f'_c (T/f'_c = 4/48 as in HJC 1993: 2.08 MPa). Replace it with the
    /// published values when the source is at hand.
    pub fn concrete_25mpa_seed001() -> Self {
        let base = Self::concrete_48mpa_hjc1993();
        let fc = 25.0e6;
        let k_e = base.p_crush / base.mu_crush;
        let p_crush = fc / 3.0;
        Self {
            compressive_strength: fc,
            tensile_strength: fc * (4.0 / 48.0),
            p_crush,
            mu_crush: p_crush / k_e,
            ..base
        }
    }

    /// Checks the parameters; the message names the bad field.
    pub fn validate(&self) -> Result<(), ConstitutiveError> {
        positive(NAME, "reference_density", self.reference_density)?;
        positive(NAME, "shear_modulus", self.shear_modulus)?;
        positive(NAME, "compressive_strength", self.compressive_strength)?;
        non_negative(NAME, "tensile_strength", self.tensile_strength)?;
        non_negative(NAME, "a", self.a)?;
        non_negative(NAME, "b", self.b)?;
        positive(NAME, "n", self.n)?;
        non_negative(NAME, "c", self.c)?;
        positive(NAME, "s_max", self.s_max)?;
        positive(NAME, "reference_strain_rate", self.reference_strain_rate)?;
        positive(NAME, "d1", self.d1)?;
        non_negative(NAME, "d2", self.d2)?;
        positive(NAME, "ef_min", self.ef_min)?;
        positive(NAME, "p_crush", self.p_crush)?;
        positive(NAME, "mu_crush", self.mu_crush)?;
        positive(NAME, "mu_lock", self.mu_lock)?;
        positive(NAME, "k1", self.k1)?;
        if !self.k2.is_finite() {
            return Err(self.bad("k2", self.k2, "a finite value, Pa"));
        }
        non_negative(NAME, "k3", self.k3)?;
        // The fully-dense tangent K₁ + 2K₂μ̄ + 3K₃μ̄² must stay > 0 for
        // μ̄ ≥ 0: K₂ ≥ 0, or a negative discriminant 4K₂² − 12K₁K₃ < 0.
        if self.k2 < 0.0 && 4.0 * self.k2 * self.k2 >= 12.0 * self.k1 * self.k3 {
            return Err(self.bad(
                "k2",
                self.k2,
                "a fully-dense curve rising for all μ̄ ≥ 0 (K₂² < 3K₁K₃ when K₂ < 0)",
            ));
        }
        if !(self.p_lock.is_finite() && self.p_lock > self.p_crush) {
            return Err(self.bad("p_lock", self.p_lock, "a finite value > p_crush, Pa"));
        }
        if !(self.mu_plock() > self.mu_crush) {
            return Err(self.bad(
                "mu_lock",
                self.mu_lock,
                "a locking strain whose p_lock point lies beyond mu_crush",
            ));
        }
        match &self.tensile_damage {
            Some(j) => j.validate(),
            None => Ok(()),
        }
    }

    fn bad(&self, field: &'static str, value: f64, expected: &'static str) -> ConstitutiveError {
        ConstitutiveError::InvalidParameter {
            model: NAME,
            field,
            value,
            expected,
        }
    }

    /// Elastic bulk modulus K_e = p_crush/μ_crush, Pa.
    #[inline]
    pub fn elastic_bulk_modulus(&self) -> f64 {
        self.p_crush / self.mu_crush
    }

    /// Fully-dense pressure K₁μ̄ + K₂μ̄² + K₃μ̄³ (K₁μ̄ for μ̄ < 0), Pa.
    #[inline]
    pub fn fully_dense_pressure(&self, mu: f64) -> f64 {
        let x = (mu - self.mu_lock) / (1.0 + self.mu_lock);
        if x < 0.0 {
            self.k1 * x
        } else {
            x * (self.k1 + x * (self.k2 + x * self.k3))
        }
    }

    /// μ_plock: where the fully-dense curve reaches p_lock (Newton on the
    /// cubic from p_lock/K₁, safeguarded by bisection).
    pub fn mu_plock(&self) -> f64 {
        let f = |x: f64| x * (self.k1 + x * (self.k2 + x * self.k3)) - self.p_lock;
        let (mut lo, mut hi) = (0.0, 1.0);
        while f(hi) < 0.0 && hi < 1e6 {
            hi *= 2.0;
        }
        let mut x = (self.p_lock / self.k1).clamp(lo, hi);
        for _ in 0..100 {
            let fx = f(x);
            if fx == 0.0 {
                break;
            }
            if fx < 0.0 {
                lo = x;
            } else {
                hi = x;
            }
            let slope = self.k1 + x * (2.0 * self.k2 + 3.0 * self.k3 * x);
            let newton = x - fx / slope;
            x = if newton > lo && newton < hi {
                newton
            } else {
                0.5 * (lo + hi)
            };
            if hi - lo <= 4.0 * f64::EPSILON * hi {
                break;
            }
        }
        self.mu_lock + x * (1.0 + self.mu_lock)
    }

    /// Loading (virgin) pressure curve p(μ), Pa (regions 1–3).
    pub fn loading_pressure(&self, mu: f64, mu_plock: f64) -> f64 {
        if mu <= self.mu_crush {
            self.elastic_bulk_modulus() * mu
        } else if mu <= mu_plock {
            self.p_crush
                + (self.p_lock - self.p_crush) * (mu - self.mu_crush) / (mu_plock - self.mu_crush)
        } else {
            self.fully_dense_pressure(mu)
        }
    }

    /// Unloading modulus K_u from μ_max in region 2, Pa.
    #[inline]
    fn unloading_modulus(&self, mu_max: f64, mu_plock: f64) -> f64 {
        let f = ((mu_max - self.mu_crush) / (mu_plock - self.mu_crush)).clamp(0.0, 1.0);
        (1.0 - f) * self.elastic_bulk_modulus() + f * self.k1
    }

    /// Pressure of the three-region EOS at μ after the largest compression
    /// μ_max (≥ 0), before the tension limit, Pa.
    pub fn eos_pressure(&self, mu: f64, mu_max: f64) -> f64 {
        self.eos_pressure_with(mu, mu_max, self.mu_plock())
    }

    fn eos_pressure_with(&self, mu: f64, mu_max: f64, mu_plock: f64) -> f64 {
        if mu_max > mu_plock {
            self.fully_dense_pressure(mu)
        } else if mu >= mu_max || mu_max <= self.mu_crush {
            self.loading_pressure(mu, mu_plock)
        } else {
            let p_max = self.loading_pressure(mu_max, mu_plock);
            p_max - self.unloading_modulus(mu_max, mu_plock) * (mu_max - mu)
        }
    }

    /// Permanent crush: the μ at which the unloading path from μ_max
    /// reaches p = 0 (0 in region 1, μ_lock once fully dense).
    pub fn permanent_crush(&self, mu_max: f64) -> f64 {
        self.permanent_crush_with(mu_max, self.mu_plock())
    }

    fn permanent_crush_with(&self, mu_max: f64, mu_plock: f64) -> f64 {
        if mu_max <= self.mu_crush {
            0.0
        } else if mu_max > mu_plock {
            self.mu_lock
        } else {
            mu_max
                - self.loading_pressure(mu_max, mu_plock) / self.unloading_modulus(mu_max, mu_plock)
        }
    }

    /// Normalised strength σ* f'_c (eq 56, with the tension continuation
    /// of the module doc and the S_max cap), Pa, at pressure `p` (Pa),
    /// compression–shear damage `d` and rate factor `rate_factor`.
    pub fn strength(&self, p: f64, d: f64, rate_factor: f64) -> f64 {
        let p_star = p / self.compressive_strength;
        let intact = self.a * (1.0 - d);
        let base = if p_star >= 0.0 {
            intact + self.b * p_star.powf(self.n)
        } else {
            let t_star = self.tensile_strength / self.compressive_strength;
            if t_star > 0.0 {
                (intact * (1.0 + p_star / t_star)).max(0.0)
            } else {
                0.0
            }
        };
        self.compressive_strength * (base * rate_factor).min(self.s_max)
    }

    /// Rate factor 1 + C ln ε̇* with ε̇* = max(ε̇/ε̇₀, 1), ε̇ = √(⅔ dev D:dev D).
    pub fn rate_factor(&self, d: &Mat3) -> f64 {
        let dd = deviator(d);
        let rate = (2.0 / 3.0 * dd.component_mul(&dd).sum()).sqrt();
        1.0 + self.c * (rate / self.reference_strain_rate).max(1.0).ln()
    }

    /// Plastic strain to fracture max(D₁(p* + T*)^{D₂}, EF_min) (eq 57).
    pub fn fracture_strain(&self, p: f64) -> f64 {
        let x = (p + self.tensile_strength) / self.compressive_strength;
        let ef = if x > 0.0 {
            self.d1 * x.powf(self.d2)
        } else {
            0.0
        };
        ef.max(self.ef_min)
    }

    /// The von Mises stress minus the strength at a stress and history, and
    /// the strength (Pa): the contract checks the first is ≤ 0 to a small
    /// fraction of the second. The pressure is −tr σ/3; the rate factor the
    /// one of the step that produced the stress.
    pub fn yield_excess(&self, stress: &Mat3, history: &[f64]) -> (f64, f64) {
        let strength = self.strength(
            -stress.trace() / 3.0,
            history[COMPRESSION_DAMAGE_INDEX],
            history[RATE_FACTOR_INDEX],
        );
        (von_mises(&deviator(stress)) - strength, strength)
    }

    fn failed_stress(p: f64) -> Mat3 {
        -Mat3::identity() * p.max(0.0)
    }
}

impl Material for Hjc {
    fn name(&self) -> &'static str {
        NAME
    }

    fn history_len(&self) -> usize {
        SCALAR_HISTORY_LEN + self.rate.history_len()
    }

    fn init_history(&self, history: &mut [f64]) {
        history[..SCALAR_HISTORY_LEN].fill(0.0);
        history[RATE_FACTOR_INDEX] = 1.0;
        if let Some(j) = &self.tensile_damage {
            history[TENSILE_DAMAGE_INDEX] = j.initial_damage;
        }
        self.rate.init_history(&mut history[SCALAR_HISTORY_LEN..]);
    }

    fn update_stress(&self, input: &StressUpdateInput, history: &mut [f64]) -> StressUpdate {
        let (h, rate_history) = history.split_at_mut(SCALAR_HISTORY_LEN);
        let l = &input.velocity_gradient;
        let dt = input.dt;
        let frames = self.rate.advance_or_jaumann(l, dt, rate_history);
        let d = rate_of_deformation(l);

        // Pressure from the three-region EOS.
        h[LOG_VOLUME_INDEX] += d.trace() * dt;
        let mu = (-h[LOG_VOLUME_INDEX]).exp() - 1.0;
        let mu_max_old = h[MAX_COMPRESSION_INDEX];
        let mu_max = mu_max_old.max(mu);
        h[MAX_COMPRESSION_INDEX] = mu_max;
        let mu_plock = self.mu_plock();
        let d_mu_p = (self.permanent_crush_with(mu_max, mu_plock)
            - self.permanent_crush_with(mu_max_old, mu_plock))
        .max(0.0);
        let (d_c, d_t) = (h[COMPRESSION_DAMAGE_INDEX], h[TENSILE_DAMAGE_INDEX]);
        let p_min = -self.tensile_strength * (1.0 - d_c.max(d_t));
        let p = self.eos_pressure_with(mu, mu_max, mu_plock).max(p_min);
        let rate_factor = self.rate_factor(&d);
        h[RATE_FACTOR_INDEX] = rate_factor;
        if h[FAILED_INDEX] != 0.0 {
            return StressUpdate {
                stress: Self::failed_stress(p),
                plastic_work: 0.0,
                failed: true,
            };
        }

        // Radial return with the damage of eq 57 implicit in Δε_p.
        let g = self.shear_modulus;
        let s_trial = deviator(&frames.unrotate_start(&input.stress))
            + 2.0 * g * dt * deviator(&frames.unrotate_end(&d));
        let trial = von_mises(&s_trial);
        let ef = self.fracture_strain(p);
        let damage_at = |d_eps: f64| (d_c + (d_eps + d_mu_p) / ef).min(1.0);
        let yield_at = |d_eps: f64| self.strength(p, damage_at(d_eps), rate_factor);
        let (s_hat, d_eps, sigma_eq) = if trial > yield_at(0.0) {
            // r(x) = σ̄* − 3Gx − σ_y(x): r(0) > 0, r(σ̄*/3G) = −σ_y ≤ 0.
            let r = |x: f64| trial - 3.0 * g * x - yield_at(x);
            let (mut lo, mut hi) = (0.0, trial / (3.0 * g));
            for _ in 0..200 {
                let mid = 0.5 * (lo + hi);
                if !(mid > lo && mid < hi) {
                    break;
                }
                if r(mid) > 0.0 {
                    lo = mid;
                } else {
                    hi = mid;
                }
            }
            let sigma_eq = (trial - 3.0 * g * hi).min(yield_at(hi)).max(0.0);
            (s_trial * (sigma_eq / trial), hi, sigma_eq)
        } else {
            (s_trial, 0.0, trial)
        };
        h[PLASTIC_STRAIN_INDEX] += d_eps;
        h[COMPRESSION_DAMAGE_INDEX] = damage_at(d_eps).max(d_c);
        let plastic_work = sigma_eq * d_eps;

        let mut failed = h[COMPRESSION_DAMAGE_INDEX] >= 1.0;
        if let Some(j) = &self.tensile_damage {
            h[TENSILE_DAMAGE_INDEX] = j.advance(d_t, -p, dt);
            failed |= h[TENSILE_DAMAGE_INDEX] >= j.critical_damage;
        }
        if failed {
            h[FAILED_INDEX] = 1.0;
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
        None
    }

    /// c_L = √((K + 4G/3)/ρ) with K the stiffest modulus the EOS can show
    /// at μ = ρ/ρ₀ − 1: the larger of K_e, K₁ (unloading from full
    /// compaction) and the fully-dense tangent there, m/s.
    fn wave_speed(&self, density: f64, _specific_internal_energy: f64) -> f64 {
        let mu = density / self.reference_density - 1.0;
        let x = ((mu - self.mu_lock) / (1.0 + self.mu_lock)).max(0.0);
        let tangent = (self.k1 + x * (2.0 * self.k2 + 3.0 * self.k3 * x)) / (1.0 + self.mu_lock);
        let k = self.elastic_bulk_modulus().max(self.k1).max(tangent);
        ((k + 4.0 * self.shear_modulus / 3.0) / density)
            .max(0.0)
            .sqrt()
    }
}

#[cfg(test)]
mod tests;
