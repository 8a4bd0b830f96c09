//! The solid low-pressure threshold of seed 000 §3.1: a wrapper around any
//! solid EOS that follows it above a threshold pressure p_t (typically one
//! atmosphere) and below p_t replaces it by a curve that is C¹-continuous at
//! the threshold, positive, monotone in specific volume and tends to zero as
//! the volume grows.
//!
//! **Why.** ICE's equilibration pressure (seed 000 eqs 4–10) asks every
//! material in a cell for ρ(p, T) at a common pressure. A gas has states only
//! at p > 0; a solid in tension reports p < 0. Where a stretched solid
//! coexists with gas, the solid's negative pressure is not a state the gas
//! can share. Below the threshold the solid's pressure instead falls
//! steeply but stays positive, so the solid's specific volume decouples
//! from its isotropic stress (which the constitutive model carries), every
//! p > 0 has a solid density, and the equilibration has a positive solution.
//!
//! **The form below the threshold.** With q = p_solid(ρ, e) the wrapped
//! EOS's pressure,
//!
//! p = q                              for q ≥ p_t,
//! p = p_t exp((q − p_t)/p_t)         for q < p_t.
//!
//! At q = p_t both the value (p_t) and the slope (dp/dq = 1) match, so p is
//! C¹ in (ρ, e) jointly wherever the solid EOS is. It is positive, it rises
//! with q and so falls with specific volume wherever the solid's pressure
//! does, and it vanishes as q falls (by p_t·e⁻⁷⁴⁵, 75 MPa of tension for
//! p_t = 1 atm, it is below the smallest positive double).
//!
//! *Relation to the literature.* The seed calls the low-pressure curve "a
//! polynomial chosen to be C¹ continuous at the threshold value and which
//! approaches zero as the specific volume becomes large". Uintah's MPM
//! constitutive models implement it (their "modified EOS" below p_ref) as
//! the power law p = p_t (ρ/ρ_t)ⁿ = p_t (v_t/v)ⁿ with n = K/p_t, K the bulk
//! modulus: value and slope match at the threshold state (ρ_t, p_t). Our
//! form is the same decay measured in the solid's own pressure rather than
//! in ln ρ: where the solid EOS is log-linear, q ≈ p_t + K ln(ρ/ρ_t), it is
//! exactly p_t (ρ/ρ_t)^(K/p_t). Expressing it through q keeps it C¹ at every
//! energy (the threshold density of a Mie–Grüneisen solid moves with e), makes
//! its derivatives exact (dp/dρ = (p/p_t) ∂q/∂ρ) and its inversions closed
//! form, with no second derivatives of the wrapped model.
//!
//! **Energy dependence.** Below the threshold the energy enters only through
//! q, so a hotter solid reaches the threshold at a lower density and its
//! Grüneisen parameter is scaled by the same factor p/p_t. Temperature,
//! c_v and e(ρ, T) are the wrapped model's, unchanged.
//!
//! **Inversions.** q = p_t (1 + ln(p/p_t)) for 0 < p < p_t, so
//! e(ρ, p) and ρ(p, T) are the wrapped model's at q; κ is scaled by
//! dq/dp = p_t/p and α is the wrapped model's at q.
//!
//! **A caveat for finite differences.** For a stiff solid the curve below
//! p_t decays over a relative density change p_t/K (6·10⁻⁷ for steel at one
//! atmosphere), finer than the 10⁻⁶ relative step of the generic contract
//! harness; the tests here check the derivatives with steps scaled to that
//! length and run the generic harness at a higher threshold.

use brisance_core::{Eos, EosError};
use serde::{Deserialize, Serialize};

const NAME: &str = "solid_threshold";

/// One standard atmosphere, Pa: the default threshold (seed 000 §3.1,
/// "typically 1 atmosphere").
pub const ONE_ATMOSPHERE: f64 = 101_325.0;

fn default_threshold_pressure() -> f64 {
    ONE_ATMOSPHERE
}

/// A solid EOS with the low-pressure threshold of seed 000 §3.1.
///
/// Valid wherever the wrapped `solid` EOS is (its `check_state`); the
/// pressure is positive everywhere and exactly the solid's at and above
/// `threshold_pressure`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SolidThreshold<E> {
    /// The solid's full equation of state.
    pub solid: E,
    /// Threshold pressure p_t, Pa (default one atmosphere).
    #[serde(default = "default_threshold_pressure")]
    pub threshold_pressure: f64,
}

impl<E: Eos> SolidThreshold<E> {
    /// Wraps `solid` with the default threshold of one atmosphere.
    pub fn new(solid: E) -> Self {
        Self::with_threshold(solid, ONE_ATMOSPHERE)
    }

    /// Wraps `solid` with threshold pressure `threshold_pressure` (Pa).
    pub fn with_threshold(solid: E, threshold_pressure: f64) -> Self {
        Self {
            solid,
            threshold_pressure,
        }
    }

    /// Checks the threshold: finite and > 0. (The wrapped model's own
    /// parameters are checked by its `validate`.)
    pub fn validate(&self) -> Result<(), String> {
        let pt = self.threshold_pressure;
        if !(pt > 0.0 && pt.is_finite()) {
            return Err(format!(
                "{NAME}: field `threshold_pressure` = {pt}, expected a finite value > 0 Pa"
            ));
        }
        Ok(())
    }

    /// The pressure p and dp/dq for the wrapped model's pressure q.
    #[inline]
    pub fn from_solid_pressure(&self, q: f64) -> (f64, f64) {
        let pt = self.threshold_pressure;
        if q >= pt {
            (q, 1.0)
        } else {
            let p = pt * ((q - pt) / pt).exp();
            (p, p / pt)
        }
    }

    /// The wrapped model's pressure q that gives pressure p > 0, and dq/dp.
    #[inline]
    pub fn to_solid_pressure(&self, p: f64) -> (f64, f64) {
        let pt = self.threshold_pressure;
        if p >= pt {
            (p, 1.0)
        } else {
            (pt * (1.0 + (p / pt).ln()), pt / p)
        }
    }

    fn check_positive_pressure(p: f64) -> Result<(), EosError> {
        if !(p > 0.0 && p.is_finite()) {
            return Err(EosError::OutOfRange {
                eos: NAME,
                detail: format!(
                    "pressure {p} Pa: below the threshold the solid's pressure is positive, so only finite p > 0 has a state"
                ),
            });
        }
        Ok(())
    }
}

impl<E: Eos> Eos for SolidThreshold<E> {
    fn name(&self) -> &'static str {
        NAME
    }

    fn reference_density(&self) -> f64 {
        self.solid.reference_density()
    }

    #[inline]
    fn pressure(&self, rho: f64, e: f64) -> f64 {
        self.from_solid_pressure(self.solid.pressure(rho, e)).0
    }

    #[inline]
    fn dp_drho(&self, rho: f64, e: f64) -> f64 {
        let (_, dp_dq) = self.from_solid_pressure(self.solid.pressure(rho, e));
        dp_dq * self.solid.dp_drho(rho, e)
    }

    #[inline]
    fn dp_de(&self, rho: f64, e: f64) -> f64 {
        let (_, dp_dq) = self.from_solid_pressure(self.solid.pressure(rho, e));
        dp_dq * self.solid.dp_de(rho, e)
    }

    /// Γ = (p/p_t) Γ_solid below the threshold, Γ_solid above.
    #[inline]
    fn gruneisen(&self, rho: f64, e: f64) -> f64 {
        let (_, dp_dq) = self.from_solid_pressure(self.solid.pressure(rho, e));
        dp_dq * self.solid.gruneisen(rho, e)
    }

    fn check_state(&self, rho: f64, e: f64) -> Result<(), EosError> {
        self.solid.check_state(rho, e)
    }

    fn specific_internal_energy(&self, rho: f64, p: f64) -> Result<f64, EosError> {
        Self::check_positive_pressure(p)?;
        self.solid
            .specific_internal_energy(rho, self.to_solid_pressure(p).0)
    }

    fn temperature(&self, rho: f64, e: f64) -> f64 {
        self.solid.temperature(rho, e)
    }

    fn specific_internal_energy_from_temperature(&self, rho: f64, t: f64) -> f64 {
        self.solid.specific_internal_energy_from_temperature(rho, t)
    }

    fn cv(&self, rho: f64, t: f64) -> f64 {
        self.solid.cv(rho, t)
    }

    fn density(&self, p: f64, t: f64) -> Result<f64, EosError> {
        Self::check_positive_pressure(p)?;
        self.solid.density(self.to_solid_pressure(p).0, t)
    }

    /// κ = κ_solid(q, T) dq/dp.
    fn isothermal_compressibility(&self, p: f64, t: f64) -> Result<f64, EosError> {
        Self::check_positive_pressure(p)?;
        let (q, dq_dp) = self.to_solid_pressure(p);
        Ok(self.solid.isothermal_compressibility(q, t)? * dq_dp)
    }

    /// α = α_solid(q, T): at fixed p, q is fixed.
    fn thermal_expansivity(&self, p: f64, t: f64) -> Result<f64, EosError> {
        Self::check_positive_pressure(p)?;
        self.solid
            .thermal_expansivity(self.to_solid_pressure(p).0, t)
    }

    /// The wrapped model's fused inversion at q, κ scaled by dq/dp: one
    /// solve, the same bits as the three methods when the wrapped model's
    /// fused method gives its own three.
    fn density_and_derivatives(&self, p: f64, t: f64) -> Result<(f64, f64, f64), EosError> {
        Self::check_positive_pressure(p)?;
        let (q, dq_dp) = self.to_solid_pressure(p);
        let (rho, kappa, alpha) = self.solid.density_and_derivatives(q, t)?;
        Ok((rho, kappa * dq_dp, alpha))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{IdealGas, MieGruneisenCubic, MieGruneisenLinear, MieGruneisenThermal};
    use brisance_core::contracts::{
        check_pressure_roundtrip, check_rejects_out_of_range, check_thermal_roundtrip, rel_diff,
    };
    use proptest::prelude::*;

    #[test]
    fn below_threshold_an_ideal_gas_follows_the_exponential_by_hand() {
        // q = 0.4 ρ e = p_t/2 ⇒ p = p_t e^(−1/2) = 101325 × 0.60653066 = 61456.72 Pa.
        let w = SolidThreshold::new(IdealGas::air());
        let rho = 1.225;
        let e = 0.5 * ONE_ATMOSPHERE / (0.4 * rho);
        let p = w.pressure(rho, e);
        assert!((p - 61_456.72).abs() < 0.01, "p = {p}");
        // dp/dρ = (p/p_t) × 0.4 e
        assert!((w.dp_drho(rho, e) - p / ONE_ATMOSPHERE * 0.4 * e).abs() < 1e-9);
        // and the inversions take it back
        assert!((w.specific_internal_energy(rho, p).unwrap() - e).abs() < 1e-9 * e);
    }

    #[test]
    fn above_threshold_the_solid_is_untouched() {
        let steel = MieGruneisenLinear::steel_4340();
        let w = SolidThreshold::new(steel);
        for (rho, e) in [(7900.0, 0.0), (8500.0, 1e5), (7830.0, 1e3)] {
            assert!(steel.pressure(rho, e) >= ONE_ATMOSPHERE);
            assert_eq!(w.pressure(rho, e), steel.pressure(rho, e));
            assert_eq!(w.dp_drho(rho, e), steel.dp_drho(rho, e));
            assert_eq!(w.gruneisen(rho, e), steel.gruneisen(rho, e));
        }
        assert_eq!(w.density(1e9, 300.0), steel.density(1e9, 300.0));
    }

    #[test]
    fn a_stretched_solid_reports_a_small_positive_pressure() {
        // 4340 steel at 0.1 % tension and T₀: the solid alone gives about
        // −0.1 GPa; the threshold form gives p_t e^(−1000) ≈ 0 but never less.
        let w = SolidThreshold::new(MieGruneisenLinear::steel_4340());
        let q = w.solid.pressure(0.999 * 7830.0, 0.0);
        assert!(q < -9e7, "q = {q}");
        let p = w.pressure(0.999 * 7830.0, 0.0);
        assert!((0.0..1e-300).contains(&p), "p = {p}");
        let p = w.pressure(0.99999 * 7830.0, 0.0);
        assert!(p > 0.0 && p < ONE_ATMOSPHERE, "p = {p}");
    }

    #[test]
    fn non_positive_or_nan_pressures_are_errors() {
        let w = SolidThreshold::new(MieGruneisenLinear::steel_4340());
        assert!(w.density(0.0, 300.0).is_err());
        assert!(w.density(-1.0, 300.0).is_err());
        assert!(w.density(f64::NAN, 300.0).is_err());
        assert!(w.specific_internal_energy(7830.0, 0.0).is_err());
        assert!(w.isothermal_compressibility(-5.0, 300.0).is_err());
        assert!(w.check_state(-1.0, 0.0).is_err());
        let mut bad = w;
        bad.threshold_pressure = 0.0;
        assert!(bad.validate().unwrap_err().contains("`threshold_pressure`"));
    }

    #[test]
    fn threshold_defaults_to_one_atmosphere_when_read() {
        let text = "(solid: (gamma: 1.4, cv: 717.6, rho0: 1.225))";
        let w: SolidThreshold<IdealGas> = match ron::from_str(text) {
            Ok(w) => w,
            Err(err) => panic!("{err}"),
        };
        assert_eq!(w.threshold_pressure, ONE_ATMOSPHERE);
    }

    /// The wrapped solids the property tests run over, at 50–600 K: hotter,
    /// the soft Estane's thermal pressure keeps it above one atmosphere down
    /// to the 20 % tension edge of its valid window (from about 1080 K on).
    #[derive(Debug, Clone, Copy)]
    enum Solid {
        Linear(MieGruneisenLinear),
        Cubic(MieGruneisenCubic),
        Thermal(MieGruneisenThermal),
    }

    fn solids() -> [Solid; 5] {
        [
            Solid::Linear(MieGruneisenLinear::steel_4340()),
            Solid::Linear(MieGruneisenLinear::ofhc_copper()),
            Solid::Cubic(MieGruneisenCubic::steel_seed001()),
            Solid::Thermal(MieGruneisenThermal::hmx_seed003()),
            Solid::Thermal(MieGruneisenThermal::estane_seed003()),
        ]
    }

    /// Runs `f` on the solid wrapped with the default threshold.
    fn with_wrapped<R>(solid: Solid, f: impl Fn(&dyn Eos, &dyn Eos) -> R) -> R {
        match solid {
            Solid::Linear(s) => f(&SolidThreshold::new(s), &s),
            Solid::Cubic(s) => f(&SolidThreshold::new(s), &s),
            Solid::Thermal(s) => f(&SolidThreshold::new(s), &s),
        }
    }

    /// Threshold density ρ_t at temperature t (q(ρ_t, e(T)) = p_t) and the
    /// solid's stiffness K_t = ρ_t ∂q/∂ρ there.
    fn threshold_state(solid: &dyn Eos, t: f64) -> (f64, f64, f64) {
        let rho_t = match solid.density(ONE_ATMOSPHERE, t) {
            Ok(r) => r,
            Err(err) => panic!("no threshold density at T = {t}: {err}"),
        };
        let e = solid.specific_internal_energy_from_temperature(rho_t, t);
        (rho_t, e, rho_t * solid.dp_drho(rho_t, e))
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(64))]

        /// Value and slope from both sides agree at the threshold. Probes at
        /// ±10⁻⁷ of the decay length make the expected mismatch ~10⁻⁷; a
        /// kink or a jump would show as O(1).
        #[test]
        fn threshold_is_c1_at_the_threshold_pressure(which in 0usize..5, t in 50.0f64..600.0) {
            with_wrapped(solids()[which], |w, solid| {
                let (rho_t, e, k_t) = threshold_state(solid, t);
                let d = 1e-7 * ONE_ATMOSPHERE / k_t * rho_t;
                let (below, above) = (rho_t - d, rho_t + d);
                let (p_b, p_a) = (w.pressure(below, e), w.pressure(above, e));
                prop_assert!(rel_diff(p_b, p_a, 0.0) < 1e-6, "p {} vs {}", p_b, p_a);
                prop_assert!(p_b < ONE_ATMOSPHERE && p_a >= ONE_ATMOSPHERE);
                let (s_b, s_a) = (w.dp_drho(below, e), w.dp_drho(above, e));
                prop_assert!(rel_diff(s_b, s_a, 0.0) < 1e-6, "slope {} vs {}", s_b, s_a);
                // One-sided secants over 10⁻⁴ of the decay length: the
                // exponential's curvature makes them differ by ~5·10⁻⁵.
                let h = 1e-4 * ONE_ATMOSPHERE / k_t * rho_t;
                let (lo, hi) = (rho_t - h, rho_t + h);
                let left = (w.pressure(rho_t, e) - w.pressure(lo, e)) / (rho_t - lo);
                let right = (w.pressure(hi, e) - w.pressure(rho_t, e)) / (hi - rho_t);
                prop_assert!(rel_diff(left, right, 0.0) < 1e-4, "secants {} vs {}", left, right);
                Ok(())
            })?;
        }

        /// p falls as v grows (ρ falls), strictly while it is representable,
        /// from above the threshold to 20 % tension.
        #[test]
        fn threshold_pressure_falls_monotonically_with_specific_volume(which in 0usize..5, t in 50.0f64..600.0) {
            with_wrapped(solids()[which], |w, solid| {
                let (rho_t, e, k_t) = threshold_state(solid, t);
                let decay = ONE_ATMOSPHERE / k_t;
                let rho_min = 0.8 * solid.reference_density();
                let mut prev = w.pressure(rho_t * (1.0 + 50.0 * decay), e);
                // 1000 steps of one decay length each through the curve below
                // the threshold, then 1000 more on to 20 % tension.
                let rho_end = rho_t * (1.0 - 950.0 * decay);
                for i in 1..=2000 {
                    let rho = if i <= 1000 {
                        rho_t * (1.0 + 50.0 * decay - decay * f64::from(i))
                    } else {
                        rho_end + (rho_min - rho_end) * f64::from(i - 1000) / 1000.0
                    };
                    let p = w.pressure(rho, e);
                    prop_assert!(p <= prev, "p rose from {} to {} at ρ = {}", prev, p, rho);
                    prop_assert!(p < prev || prev < 1e-300, "p flat at {} at ρ = {}", p, rho);
                    prev = p;
                }
                Ok(())
            })?;
        }

        /// p > 0 down to 600 decay lengths below the threshold (p ≈ p_t e⁻⁶⁰⁰)
        /// and never negative beyond.
        #[test]
        fn threshold_pressure_is_positive_in_tension(which in 0usize..5, t in 50.0f64..600.0, frac in 0.0f64..1.0) {
            with_wrapped(solids()[which], |w, solid| {
                let (rho_t, e, k_t) = threshold_state(solid, t);
                let rho = rho_t * (1.0 - 600.0 * ONE_ATMOSPHERE / k_t * frac);
                prop_assert!(w.pressure(rho, e) > 0.0, "p = {} at ρ = {}", w.pressure(rho, e), rho);
                let far = rho_t + (0.8 * solid.reference_density() - rho_t) * frac;
                prop_assert!(w.pressure(far, e) >= 0.0);
                Ok(())
            })?;
        }

        /// Every positive pressure from 10⁻²⁵⁰ Pa to 100 MPa has a solid density at
        /// every temperature, rising with p — what ICE's equilibration needs.
        #[test]
        fn every_positive_pressure_has_a_density(which in 0usize..5, t in 50.0f64..600.0) {
            with_wrapped(solids()[which], |w, _| {
                let mut prev = 0.0;
                for k in 0..=516 {
                    let p = 10f64.powf(-250.0 + 0.5 * f64::from(k));
                    let rho = match w.density(p, t) {
                        Ok(r) => r,
                        Err(err) => return Err(TestCaseError::fail(format!("ρ(p = {p}, T = {t}): {err}"))),
                    };
                    prop_assert!(rho > prev, "ρ(p) not rising at p = {}", p);
                    prev = rho;
                }
                Ok(())
            })?;
        }

        /// The EOS contract at the default threshold, on both sides of it:
        /// round trips and out-of-range handling from the generic harness,
        /// derivatives against central differences with steps scaled to the
        /// decay length (10⁻³ of it in ρ and e, 10⁻³ p for κ).
        #[test]
        fn contract_holds_at_the_default_threshold(which in 0usize..5, t in 50.0f64..600.0, q_over_pt in -500.0f64..20.0) {
            with_wrapped(solids()[which], |w, solid| {
                let q = q_over_pt * ONE_ATMOSPHERE;
                let rho = solid.density(q, t).map_err(|e| TestCaseError::fail(e.to_string()))?;
                let e = solid.specific_internal_energy_from_temperature(rho, t);
                for result in [
                    check_pressure_roundtrip(w, rho, e),
                    check_thermal_roundtrip(w, rho, e),
                    check_rejects_out_of_range(w, rho, e),
                ] {
                    if let Err(msg) = result {
                        return Err(TestCaseError::fail(msg));
                    }
                }
                let p = w.pressure(rho, e);
                let pt = ONE_ATMOSPHERE;
                let hr = 1e-3 * pt / solid.dp_drho(rho, e);
                let he = 1e-3 * pt / solid.dp_de(rho, e);
                let fd_r = (w.pressure(rho + hr, e) - w.pressure(rho - hr, e)) / (2.0 * hr);
                let fd_e = (w.pressure(rho, e + he) - w.pressure(rho, e - he)) / (2.0 * he);
                prop_assert!(rel_diff(w.dp_drho(rho, e), fd_r, 0.0) < 1e-5, "∂p/∂ρ {} vs {}", w.dp_drho(rho, e), fd_r);
                prop_assert!(rel_diff(w.dp_de(rho, e), fd_e, 0.0) < 1e-5, "∂p/∂e {} vs {}", w.dp_de(rho, e), fd_e);
                prop_assert!(rel_diff(w.gruneisen(rho, e), fd_e / rho, 0.0) < 1e-5);
                let c2 = w.sound_speed_squared(rho, e);
                let c2_fd = fd_r + p / (rho * rho) * fd_e;
                prop_assert!(c2 >= 0.0 && rel_diff(c2, c2_fd, 0.0) < 1e-5, "c² {} vs {}", c2, c2_fd);
                let (hp, ht) = (1e-3 * p, 1e-4 * t);
                let dens = |p: f64, t: f64| w.density(p, t).map_err(|e| TestCaseError::fail(e.to_string()));
                let kappa_fd = (dens(p + hp, t)? - dens(p - hp, t)?) / (2.0 * hp) / rho;
                let alpha_fd = -(dens(p, t + ht)? - dens(p, t - ht)?) / (2.0 * ht) / rho;
                let kappa = w.isothermal_compressibility(p, t).map_err(|e| TestCaseError::fail(e.to_string()))?;
                let alpha = w.thermal_expansivity(p, t).map_err(|e| TestCaseError::fail(e.to_string()))?;
                prop_assert!(rel_diff(kappa, kappa_fd, 0.0) < 1e-5, "κ {} vs {}", kappa, kappa_fd);
                prop_assert!(rel_diff(alpha, alpha_fd, 0.0) < 1e-5, "α {} vs {}", alpha, alpha_fd);
                Ok(())
            })?;
        }
    }

    // The generic harness, over boxes that sample both branches. Its steps
    // are fixed fractions of the state (10⁻⁶ ρ, 10⁻⁶ |e|, 10⁻⁶ |p| with a
    // 10⁻⁶ floor), so the threshold must be high enough that (i) those steps
    // resolve the curve below it (p_t ≳ 10⁻³ K) and (ii) a central
    // difference straddling the threshold, where p is C¹ but not C², errs by
    // less than the harness's 10⁻⁵ (Δq/4p_t with Δq = 10⁻⁶ K: p_t ≳ 2.5·10⁻² K);
    // and p must stay above the 10⁻⁶ Pa pressure step (arguments of the
    // exponential above −20). The default one-atmosphere threshold is
    // checked with scaled steps in `contract_holds_at_the_default_threshold`.
    brisance_core::eos_contract_tests!(threshold_steel_4340_at_5_gpa, SolidThreshold::with_threshold(MieGruneisenLinear::steel_4340(), 5e9), rho: 7715.0..8200.0, t: 100.0..600.0);
    brisance_core::eos_contract_tests!(threshold_estane_at_half_gpa, SolidThreshold::with_threshold(MieGruneisenThermal::estane_seed003(), 5e8), rho: 1220.0..1470.0, t: 200.0..400.0);
}
