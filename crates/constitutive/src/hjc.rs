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
mod tests {
    use super::*;

    /// μ_plock of HJC 1993: 85μ̄ − 171μ̄² + 208μ̄³ = 0.8 (GPa) at
    /// μ̄ = 0.00959481, μ_plock = 0.1 + 1.1 μ̄ = 0.11055429 (Newton by hand
    /// from μ̄ = 0.8/85 = 0.0094118).
    const MU_PLOCK: f64 = 0.110_554_29;

    struct Point {
        h: Vec<f64>,
        sigma: Mat3,
    }

    impl Point {
        fn new(m: &Hjc) -> Self {
            let mut h = vec![0.0; m.history_len()];
            m.init_history(&mut h);
            Self {
                h,
                sigma: Mat3::zeros(),
            }
        }

        fn step(&mut self, m: &Hjc, l: Mat3, dt: f64) -> StressUpdate {
            let input = StressUpdateInput {
                velocity_gradient: l,
                dt,
                density: m.reference_density,
                temperature: 300.0,
                specific_internal_energy: 0.0,
                stress: self.sigma,
            };
            let out = m.update_stress(&input, &mut self.h);
            self.sigma = out.stress;
            out
        }

        fn mu(&self) -> f64 {
            (-self.h[LOG_VOLUME_INDEX]).exp() - 1.0
        }

        fn pressure(&self) -> f64 {
            -self.sigma.trace() / 3.0
        }
    }

    /// Hydrostatic rate giving ln(V/V₀) += 3 a Δt per step.
    fn hydrostatic(a: f64) -> Mat3 {
        Mat3::identity() * a
    }

    #[test]
    fn locking_strain_solves_the_fully_dense_curve_at_p_lock() {
        let m = Hjc::concrete_48mpa_hjc1993();
        assert!((m.mu_plock() - MU_PLOCK).abs() < 1e-8, "{}", m.mu_plock());
        assert!(m.validate().is_ok());
    }

    #[test]
    fn crush_curve_passes_through_the_crush_and_lock_points() {
        let m = Hjc::concrete_48mpa_hjc1993();
        let mp = m.mu_plock();
        // K_e = 16 MPa/0.001 = 16 GPa.
        assert_eq!(m.elastic_bulk_modulus(), 16.0e9);
        assert!((m.loading_pressure(0.001, mp) - 16.0e6).abs() < 1e-6);
        assert!((m.loading_pressure(0.0005, mp) - 8.0e6).abs() < 1e-6);
        assert!((m.loading_pressure(mp, mp) - 0.8e9).abs() < 1e-3);
        // Just past μ_plock the fully-dense curve continues from p_lock.
        assert!((m.loading_pressure(mp + 1e-12, mp) - 0.8e9).abs() < 1.0);
        // Region 2 at μ = 0.05: 16 MPa + (784 MPa)(0.049)/(0.10955429)
        // = 366.66 MPa.
        let p = m.loading_pressure(0.05, mp);
        assert!((p - 366.657e6).abs() < 1e4, "{p}");
        // Fully dense at μ = 0.2: μ̄ = 0.1/1.1 = 0.090909,
        // p = 85e9 μ̄ − 171e9 μ̄² + 208e9 μ̄³ = 7.7273 − 1.4132 + 0.1563 GPa.
        let x: f64 = 0.1 / 1.1;
        let p3 = 85e9 * x - 171e9 * x * x + 208e9 * x.powi(3);
        assert!((m.loading_pressure(0.2, mp) - p3).abs() < 1.0);
        assert!((p3 - 6.4704e9).abs() < 1e6, "{p3}");
    }

    #[test]
    fn unloading_from_compaction_leaves_the_interpolated_permanent_crush() {
        let m = Hjc::concrete_48mpa_hjc1993();
        // From μ_max = 0.05: F = 0.049/0.10955429 = 0.447267,
        // K_u = 16 + 0.447267 × 69 = 46.8614 GPa, permanent crush
        // 0.05 − 366.657e6/46.8614e9 = 0.0421757.
        let crush = m.permanent_crush(0.05);
        assert!((crush - 0.042_175_7).abs() < 1e-7, "{crush}");
        assert!(m.eos_pressure(crush, 0.05).abs() < 1e-3);
        let p = m.eos_pressure(0.045, 0.05);
        assert!((p - (366.657e6 - 46.8614e9 * 0.005)).abs() < 2e4, "{p}");
        // Reloading past μ_max follows the virgin curve again.
        assert_eq!(
            m.eos_pressure(0.06, 0.05),
            m.loading_pressure(0.06, m.mu_plock())
        );
        // Below the elastic limit there is no permanent crush.
        assert_eq!(m.permanent_crush(0.0008), 0.0);
        assert!((m.eos_pressure(-0.0001, 0.0008) + 1.6e6).abs() < 1e-6);
    }

    #[test]
    fn hydrostatic_loading_and_unloading_follow_the_documented_paths() {
        let m = Hjc::concrete_48mpa_hjc1993();
        let mut pt = Point::new(&m);
        let dt = 1e-6;
        // Compress by ln(V/V₀) = −3e-4 per step for 150 steps:
        // μ = e^{0.045} − 1 = 0.046028, in region 2.
        for _ in 0..150 {
            pt.step(&m, hydrostatic(-100.0), dt);
        }
        let mu_max = 0.045_f64.exp() - 1.0;
        assert!((pt.mu() - mu_max).abs() < 1e-12);
        let p_load = 16.0e6 + 784.0e6 * (mu_max - 0.001) / (MU_PLOCK - 0.001);
        assert!(
            (pt.pressure() - p_load).abs() < 1e-6 * p_load,
            "{}",
            pt.pressure()
        );
        // A hydrostatic path has no deviator and no plastic shear strain,
        // but the crush damages the concrete (eq 57, Δμ_p only).
        assert!(von_mises(&deviator(&pt.sigma)) < 1e-6);
        assert_eq!(pt.h[PLASTIC_STRAIN_INDEX], 0.0);
        let crush = m.permanent_crush(mu_max);
        assert!(pt.h[COMPRESSION_DAMAGE_INDEX] > 0.0);
        // Unload by 10 steps: μ = e^{0.042} − 1 along K_u (p stays > 0).
        for _ in 0..10 {
            pt.step(&m, hydrostatic(100.0), dt);
        }
        let mu = 0.042_f64.exp() - 1.0;
        let f = (mu_max - 0.001) / (MU_PLOCK - 0.001);
        let k_u = 16.0e9 + f * 69.0e9;
        let p_unload = p_load - k_u * (mu_max - mu);
        assert!(p_unload > 0.1 * p_load, "{p_unload}");
        assert!(
            (pt.pressure() - p_unload).abs() < 1e-6 * p_load,
            "{} vs {p_unload}",
            pt.pressure()
        );
        assert!((crush - (mu_max - p_load / k_u)).abs() < 1e-9, "{crush}");
        // Unloading further crosses p = 0 at the permanent crush and stops at
        // the tension limit −T(1 − D).
        for _ in 0..200 {
            pt.step(&m, hydrostatic(100.0), dt);
        }
        let d = pt.h[COMPRESSION_DAMAGE_INDEX];
        assert!(
            (pt.pressure() + 4.0e6 * (1.0 - d)).abs() < 1e-6,
            "{} with D = {d}",
            pt.pressure()
        );
    }

    #[test]
    fn hydrostatic_crush_damage_is_the_crush_over_the_fracture_strain() {
        let m = Hjc::concrete_48mpa_hjc1993();
        let mut pt = Point::new(&m);
        // One step straight to μ = e^{0.01} − 1 = 0.010050 (region 2).
        pt.step(&m, hydrostatic(-1.0e4 / 3.0), 1e-6);
        let mu = 0.01_f64.exp() - 1.0;
        assert!((pt.mu() - mu).abs() < 1e-12);
        let p = pt.pressure();
        // D_c = Δμ_p/(D₁(p* + T*)^{D₂}) with D₂ = 1, D₁ = 0.04.
        let ef = 0.04 * (p + 4.0e6) / 48.0e6;
        let expected = m.permanent_crush(mu) / ef;
        assert!(
            (pt.h[COMPRESSION_DAMAGE_INDEX] - expected).abs() < 1e-12,
            "{} vs {expected}",
            pt.h[COMPRESSION_DAMAGE_INDEX]
        );
    }

    #[test]
    fn strength_is_eq_56_with_the_cap_and_the_tension_continuation() {
        let m = Hjc::concrete_48mpa_hjc1993();
        // p* = 1: σ* = 0.79 + 1.6 = 2.39 → 114.72 MPa; with D = 0.5:
        // 0.395 + 1.6 = 1.995 → 95.76 MPa.
        assert!((m.strength(48.0e6, 0.0, 1.0) - 114.72e6).abs() < 1.0);
        assert!((m.strength(48.0e6, 0.5, 1.0) - 95.76e6).abs() < 1.0);
        // Rate factor at ε̇ = 100 s⁻¹: 1 + 0.007 ln 100 = 1.032236.
        let d = Mat3::new(100.0, 0.0, 0.0, 0.0, -50.0, 0.0, 0.0, 0.0, -50.0);
        assert!((m.rate_factor(&d) - (1.0 + 0.007 * 100.0_f64.ln())).abs() < 1e-12);
        // Capped at S_max f'_c = 336 MPa for large p* (p* = 100: 0.79 +
        // 1.6 × 100^0.61 = 26.2 > 7).
        assert_eq!(m.strength(4.8e9, 0.0, 1.0), 336.0e6);
        // Tension: A(1 − D)(1 + p*/T*), zero at p = −T.
        assert!((m.strength(-2.0e6, 0.0, 1.0) - 0.79 * 0.5 * 48.0e6).abs() < 1e-6);
        assert_eq!(m.strength(-4.0e6, 0.0, 1.0), 0.0);
    }

    #[test]
    fn shear_under_confinement_returns_to_the_damaged_strength() {
        let m = Hjc::concrete_48mpa_hjc1993();
        let mut pt = Point::new(&m);
        let dt = 1e-6;
        // Confine elastically to μ = e^{3e-4} − 1 (p = 16 GPa × μ = 4.8 MPa),
        // then shear with D_xy = 1000 s⁻¹ (Δσ_xy = 29.72 MPa per step).
        pt.step(&m, hydrostatic(-100.0), dt);
        let shear = Mat3::new(0.0, 1000.0, 0.0, 1000.0, 0.0, 0.0, 0.0, 0.0, 0.0);
        for _ in 0..5 {
            pt.step(&m, shear, dt);
            let (excess, strength) = m.yield_excess(&pt.sigma, &pt.h);
            assert!(excess <= 1e-12 * strength, "{excess} over {strength}");
        }
        // Now plastic: D_c > 0 and σ̄ equals the strength at that damage.
        let d = pt.h[COMPRESSION_DAMAGE_INDEX];
        assert!(d > 0.0 && pt.h[PLASTIC_STRAIN_INDEX] > 0.0);
        let p = pt.pressure();
        let rf = 1.0 + 0.007 * (1000.0 * 2.0 / 3.0_f64.sqrt()).ln();
        let expected = 48.0e6 * (0.79 * (1.0 - d) + 1.6 * (p / 48.0e6).powf(0.61)) * rf;
        let vm = von_mises(&deviator(&pt.sigma));
        assert!(
            (vm - expected).abs() < 1e-9 * expected,
            "{vm} vs {expected}"
        );
        // And the damage is the plastic strain over the fracture strain
        // (no crush: μ < μ_crush).
        let ef = (0.04 * (p + 4.0e6) / 48.0e6).max(0.01);
        assert!((d - pt.h[PLASTIC_STRAIN_INDEX] / ef).abs() < 1e-12 * d.max(1e-300) + 1e-15);
    }

    #[test]
    fn jiang_law_integrates_the_logistic_exactly() {
        let j = JiangTensileDamage {
            growth_factor: 1.0e5,
            threshold_stress: 2.0e6,
            exponent: 2.0,
            initial_damage: 0.01,
            critical_damage: 0.9,
        };
        // σ_s = 3 MPa: r = 1e5 × 0.5² = 2.5e4 s⁻¹; Δt = 1e-4 → rΔt = 2.5:
        // D = 0.01 e^{2.5}/(0.99 + 0.01 e^{2.5}) = 0.121825/1.111825 = 0.109572.
        let d = j.advance(0.01, 3.0e6, 1.0e-4);
        assert!((d - 0.109_572).abs() < 1e-6, "{d}");
        // Two half steps give the same (the exact flow composes).
        let d2 = j.advance(j.advance(0.01, 3.0e6, 0.5e-4), 3.0e6, 0.5e-4);
        assert!((d - d2).abs() < 1e-14);
        // Below the threshold nothing grows.
        assert_eq!(j.advance(0.01, 1.9e6, 1.0), 0.01);
    }

    #[test]
    fn hydrostatic_tension_spalls_by_tensile_damage() {
        let m = Hjc {
            tensile_damage: Some(JiangTensileDamage {
                growth_factor: 1.0e6,
                threshold_stress: 1.0e6,
                exponent: 1.0,
                initial_damage: 0.01,
                critical_damage: 0.5,
            }),
            ..Hjc::concrete_48mpa_hjc1993()
        };
        let mut pt = Point::new(&m);
        let mut failed_at = None;
        for k in 0..100 {
            let out = pt.step(&m, hydrostatic(20.0), 1e-6);
            if out.failed {
                failed_at.get_or_insert(k);
                assert!(pt.sigma.trace() <= 0.0 && von_mises(&deviator(&pt.sigma)) == 0.0);
            }
        }
        assert!(failed_at.is_some(), "D_t = {}", pt.h[TENSILE_DAMAGE_INDEX]);
        assert!(pt.h[TENSILE_DAMAGE_INDEX] >= 0.5);
        assert_eq!(pt.h[FAILED_INDEX], 1.0);
    }

    #[test]
    fn reconstructed_25mpa_set_scales_the_crush_point_with_fc() {
        let m = Hjc::concrete_25mpa_seed001();
        assert_eq!(m.compressive_strength, 25.0e6);
        assert!((m.p_crush - 8.333_333e6).abs() < 1.0);
        assert!((m.elastic_bulk_modulus() - 16.0e9).abs() < 1e-3);
        assert!((m.tensile_strength - 2.083_333e6).abs() < 1.0);
        assert!(m.validate().is_ok());
    }

    #[test]
    fn validate_names_the_bad_field() {
        let bad = Hjc {
            k2: -500.0e9,
            ..Hjc::concrete_48mpa_hjc1993()
        };
        assert!(bad.validate().unwrap_err().to_string().contains("k2"));
        let bad = Hjc {
            p_lock: 1.0e6,
            ..Hjc::concrete_48mpa_hjc1993()
        };
        assert!(bad.validate().unwrap_err().to_string().contains("p_lock"));
    }

    #[test]
    fn wave_speed_uses_the_stiffest_modulus() {
        let m = Hjc::concrete_48mpa_hjc1993();
        // At ρ₀: K = max(K_e = 16, K₁/(1 + μ_lock) = 77.3, K₁ = 85) GPa
        // = 85 GPa, c = √((85e9 + 19.813e9)/2440) = 6554.1 m/s.
        let c = m.wave_speed(2440.0, 0.0);
        let expected = ((85.0e9 + 4.0 * 14.86e9 / 3.0) / 2440.0_f64).sqrt();
        assert!((c - expected).abs() < 1e-9 * expected, "{c}");
        assert!((c - 6554.1).abs() < 0.05, "{c}");
    }
}
