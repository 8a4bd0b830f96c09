//! The specific heat c_v(T) a metal heats with: a constant, or the
//! temperature-dependent form of a steel through its Curie point.
//!
//! Seed 000 §5.3 computes "the internal energy and the rate of
//! temperature increase" of its 4340 steel container with a
//! temperature-dependent specific heat, citing Goto et al. (2000, its
//! ref \[44\], the mechanical threshold stress model of HY-100 steel). The
//! seed prints no formula. Brisance takes the form and the 4340 constants
//! of Banerjee (2007), "The Mechanical Threshold Stress model for various
//! tempers of AISI 4340 steel", Int. J. Solids Struct. 44, 834–859 (the
//! MTS line of work the seed's ref \[44\] belongs to, fitted to the 4340
//! data collected there; the same constants are the defaults of Uintah's
//! `SteelCp`), a λ-shaped curve with its peak at the Curie temperature
//! T_c:
//!
//! ```text
//! T < T_c:  c = A₀ − B₀ t + C₀ t^(−n₀),   t = 1 − T/T_c,
//! T > T_c:  c = A₁ + B₁ t + C₁ t^(−n₁),   t = T/T_c − 1,
//! ```
//!
//! with T_c = 1040 K, (A₀, B₀, C₀, n₀) = (190.14, 273.75, 418.30, 0.2) and
//! (A₁, B₁, C₁, n₁) = (465.21, 267.52, 58.16, 0.35) J/(kg·K) for 4340
//! ([`SpecificHeat::steel_4340`]): 443 J/(kg·K) at 300 K, 504 at 451 K,
//! 778 at 900 K, 661 at 1500 K. The peak at T_c is infinite but integrable (n < 1), so
//! the heat H(T) = ∫₀ᵀ c dT' is finite and continuous there and strictly
//! increasing everywhere (docs/physics/constitutive/specific_heat.md).
//!
//! A heat q (J/kg) added to a point at T takes it to the T' with
//! H(T') − H(T) = q ([`SpecificHeat::temperature_rise`]), not to
//! T + q/c(T): the energy booked as heat is the energy the temperature
//! holds, whatever the step. For a constant c the rise is q/c, computed
//! as before to the bit.

use crate::error::ConstitutiveError;
use serde::{Deserialize, Serialize};

/// A specific heat c_v, J/(kg·K): `477.0` in a config, or `Curie(...)`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(untagged)]
pub enum SpecificHeat {
    /// A constant c_v, J/(kg·K).
    Constant(f64),
    /// A temperature-dependent c_v(T) through a Curie point.
    Model(SpecificHeatModel),
}

/// The temperature-dependent forms a config can name.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub enum SpecificHeatModel {
    /// The λ-shaped curve of a steel through its Curie point (module
    /// docs; boxed, so that a model holding a specific heat stays small).
    Curie(Box<CurieSpecificHeat>),
}

/// The constants of c_v(T) through a Curie point (module docs), J/(kg·K)
/// for A, B, C; K for T_c.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CurieSpecificHeat {
    /// Curie temperature T_c, K.
    pub t_c: f64,
    /// A₀, below T_c.
    pub a0: f64,
    /// B₀, below T_c.
    pub b0: f64,
    /// C₀, below T_c.
    pub c0: f64,
    /// n₀ in [0, 1), below T_c.
    pub n0: f64,
    /// A₁, above T_c.
    pub a1: f64,
    /// B₁, above T_c.
    pub b1: f64,
    /// C₁, above T_c.
    pub c1: f64,
    /// n₁ in [0, 1), above T_c.
    pub n1: f64,
}

impl From<f64> for SpecificHeat {
    fn from(c: f64) -> Self {
        Self::Constant(c)
    }
}

/// c t^(−n), zero where c is (so that a zero C needs no power of t = 0).
#[inline]
fn singular(c: f64, t: f64, n: f64) -> f64 {
    if c == 0.0 {
        0.0
    } else {
        c * t.powf(-n)
    }
}

/// ∫₀ᵗ c s^(−n) ds = c t^(1−n)/(1 − n), zero where c is.
#[inline]
fn singular_integral(c: f64, t: f64, n: f64) -> f64 {
    if c == 0.0 {
        0.0
    } else {
        c * t.powf(1.0 - n) / (1.0 - n)
    }
}

impl CurieSpecificHeat {
    /// c_v at temperature `t` (K), J/(kg·K); infinite at T_c when C₀ or C₁
    /// is not zero.
    pub fn at(&self, temperature: f64) -> f64 {
        if temperature < self.t_c {
            let t = 1.0 - temperature / self.t_c;
            self.a0 - self.b0 * t + singular(self.c0, t, self.n0)
        } else {
            let t = temperature / self.t_c - 1.0;
            self.a1 + self.b1 * t + singular(self.c1, t, self.n1)
        }
    }

    /// H(T) = ∫₀ᵀ c dT', J/kg: below T_c, with t = 1 − T/T_c,
    /// T_c [A₀(1 − t) − B₀(1 − t²)/2 + C₀(1 − t^(1−n₀))/(1 − n₀)]; above,
    /// H(T_c) + T_c [A₁t + B₁t²/2 + C₁t^(1−n₁)/(1 − n₁)] with
    /// t = T/T_c − 1.
    pub fn heat(&self, temperature: f64) -> f64 {
        let below = |t: f64| {
            self.t_c
                * (self.a0 * (1.0 - t) - 0.5 * self.b0 * (1.0 - t * t)
                    + singular_integral(self.c0, 1.0, self.n0)
                    - singular_integral(self.c0, t, self.n0))
        };
        if temperature < self.t_c {
            below(1.0 - temperature / self.t_c)
        } else {
            let t = temperature / self.t_c - 1.0;
            below(0.0)
                + self.t_c
                    * (self.a1 * t + 0.5 * self.b1 * t * t + singular_integral(self.c1, t, self.n1))
        }
    }

    /// The smallest c_v at or above 0 K: A₀ − B₀ + C₀ (at 0 K, where the
    /// branch below T_c, which rises with T, starts), or A₁ (the branch
    /// above T_c exceeds it), whichever is smaller.
    fn lowest(&self) -> f64 {
        (self.a0 - self.b0 + self.c0).min(self.a1)
    }

    fn validate(&self, model: &'static str) -> Result<(), ConstitutiveError> {
        let bad = |field: &'static str, value: f64, expected: &'static str| {
            Err(ConstitutiveError::InvalidParameter {
                model,
                field,
                value,
                expected,
            })
        };
        let fields = [
            ("specific_heat.t_c", self.t_c),
            ("specific_heat.a0", self.a0),
            ("specific_heat.b0", self.b0),
            ("specific_heat.c0", self.c0),
            ("specific_heat.n0", self.n0),
            ("specific_heat.a1", self.a1),
            ("specific_heat.b1", self.b1),
            ("specific_heat.c1", self.c1),
            ("specific_heat.n1", self.n1),
        ];
        for (field, value) in fields {
            if !value.is_finite() {
                return bad(field, value, "a finite value");
            }
        }
        if !(self.t_c > 0.0) {
            return bad("specific_heat.t_c", self.t_c, "a Curie temperature > 0 K");
        }
        for (field, value) in [
            ("specific_heat.b0", self.b0),
            ("specific_heat.c0", self.c0),
            ("specific_heat.b1", self.b1),
            ("specific_heat.c1", self.c1),
        ] {
            if value < 0.0 {
                return bad(field, value, "a value ≥ 0 J/(kg·K)");
            }
        }
        for (field, value) in [("specific_heat.n0", self.n0), ("specific_heat.n1", self.n1)] {
            if !(0.0..1.0).contains(&value) {
                return bad(field, value, "an exponent in [0, 1)");
            }
        }
        if !(self.a1 > 0.0) {
            return bad("specific_heat.a1", self.a1, "a value > 0 J/(kg·K)");
        }
        let at_zero = self.a0 - self.b0 + self.c0;
        if !(at_zero > 0.0) {
            return bad(
                "specific_heat.a0",
                self.a0,
                "A₀ − B₀ + C₀ > 0 (the specific heat at 0 K)",
            );
        }
        Ok(())
    }
}

/// The half-width δ of the temperature span (K) over which
/// [`SpecificHeat::smoothed_at`] averages c_v around its singular point:
/// 1 K.
pub const SMOOTHING_SPAN: f64 = 1.0;

impl SpecificHeat {
    /// The 4340 steel of Banerjee (2007) (module docs).
    pub fn steel_4340() -> Self {
        Self::Model(SpecificHeatModel::Curie(Box::new(CurieSpecificHeat {
            t_c: 1040.0,
            a0: 190.14,
            b0: 273.75,
            c0: 418.30,
            n0: 0.2,
            a1: 465.21,
            b1: 267.52,
            c1: 58.16,
            n1: 0.35,
        })))
    }

    /// The constant value, if c_v is constant.
    pub fn constant(&self) -> Option<f64> {
        match self {
            Self::Constant(c) => Some(*c),
            Self::Model(_) => None,
        }
    }

    /// c_v at `temperature` (K), J/(kg·K).
    pub fn at(&self, temperature: f64) -> f64 {
        match self {
            Self::Constant(c) => *c,
            Self::Model(SpecificHeatModel::Curie(m)) => m.at(temperature),
        }
    }

    /// H(T) = ∫₀ᵀ c dT', J/kg (c T for a constant).
    pub fn heat(&self, temperature: f64) -> f64 {
        match self {
            Self::Constant(c) => c * temperature,
            Self::Model(SpecificHeatModel::Curie(m)) => m.heat(temperature),
        }
    }

    /// c_v at `temperature` (K), J/(kg·K), averaged near its singular
    /// point: within δ = [`SMOOTHING_SPAN`] of T_c of a Curie curve, the
    /// mean (H(T + δ) − H(T − δ))/(2δ) over T ± δ (finite, since the
    /// singularity is integrable, n < 1); elsewhere, and for a constant,
    /// c_v itself. The smoothed apparent heat capacity of the enthalpy
    /// method, for a heat capacity used as a weight, which must be finite
    /// and should not outweigh its neighbours by orders of magnitude (the
    /// heat conduction's; docs/physics/mpm/heat_conduction.md). NaN for a
    /// NaN temperature.
    pub fn smoothed_at(&self, temperature: f64) -> f64 {
        match self {
            Self::Constant(c) => *c,
            Self::Model(SpecificHeatModel::Curie(m)) => {
                let d = SMOOTHING_SPAN;
                if (temperature - m.t_c).abs() < d {
                    (m.heat(temperature + d) - m.heat(temperature - d)) / (2.0 * d)
                } else {
                    m.at(temperature)
                }
            }
        }
    }

    /// The temperature rise ΔT (K) of a point at `temperature` (K) given
    /// the heat `q` (J/kg): q/c for a constant c (to the bit as the
    /// quotient), otherwise the ΔT with H(T + ΔT) − H(T) = q. A heat that
    /// would take the point below 0 K takes it to 0 K; a NaN heat or
    /// temperature gives NaN.
    pub fn temperature_rise(&self, temperature: f64, q: f64) -> f64 {
        match self {
            Self::Constant(c) => q / c,
            Self::Model(SpecificHeatModel::Curie(m)) => {
                solve_rise(m, temperature, q).map_or(f64::NAN, |t| t - temperature)
            }
        }
    }

    /// The temperature rise ΔT (K) of plastic heating at `temperature` (K):
    /// the fraction `taylor_quinney` of the plastic work per unit volume
    /// `plastic_work` (J/m³) at `density` (kg/m³) turned into heat (seed
    /// 000 §4.2). For a constant c this is χ w/(ρ c) with the rounding of
    /// [`crate::elastic_plastic::plastic_heating`] (the bits of every model
    /// with a constant c_v), otherwise [`Self::temperature_rise`] of the
    /// heat χ w/ρ.
    pub fn plastic_heating_rise(
        &self,
        temperature: f64,
        taylor_quinney: f64,
        plastic_work: f64,
        density: f64,
    ) -> f64 {
        match self {
            Self::Constant(c) => {
                crate::elastic_plastic::plastic_heating(taylor_quinney, plastic_work, density, *c)
            }
            Self::Model(_) => {
                self.temperature_rise(temperature, taylor_quinney * plastic_work / density)
            }
        }
    }

    /// Checks the constants; the field named is `specific_heat` or one of
    /// its constants.
    pub fn validate(&self, model: &'static str) -> Result<(), ConstitutiveError> {
        match self {
            Self::Constant(c) => crate::error::positive(model, "specific_heat", *c),
            Self::Model(SpecificHeatModel::Curie(m)) => m.validate(model),
        }
    }
}

/// The T' ≥ 0 with H(T') = H(T) + q: Newton's method on the strictly
/// increasing H, kept inside a bracket and bisecting whenever a Newton
/// step leaves it or stalls (at T_c, where c is infinite). The bracket is
/// [T, T + q/c_min] for q > 0 and [max(0, T + q/c_min), T] for q < 0,
/// c_min the smallest c at or above 0 K. `None` for non-finite input.
fn solve_rise(m: &CurieSpecificHeat, temperature: f64, q: f64) -> Option<f64> {
    if !(temperature.is_finite() && q.is_finite()) {
        return None;
    }
    if q == 0.0 {
        return Some(temperature);
    }
    let target = m.heat(temperature) + q;
    let reach = q / m.lowest();
    let (mut lo, mut hi) = if q > 0.0 {
        (temperature, temperature + reach)
    } else {
        ((temperature + reach).max(0.0), temperature)
    };
    if q < 0.0 && m.heat(lo) >= target {
        // Below 0 K: the point keeps 0 K.
        return Some(lo);
    }
    // Newton from the end of the bracket nearer the answer's linear guess.
    let mut x = temperature + q / m.at(temperature).max(m.lowest());
    if !(x > lo && x < hi) {
        x = 0.5 * (lo + hi);
    }
    for _ in 0..200 {
        let f = m.heat(x) - target;
        if f == 0.0 {
            return Some(x);
        }
        if f > 0.0 {
            hi = x;
        } else {
            lo = x;
        }
        if hi - lo <= 4.0 * f64::EPSILON * hi.abs().max(1.0) {
            break;
        }
        let newton = x - f / m.at(x);
        x = if newton > lo && newton < hi && newton != x {
            newton
        } else {
            0.5 * (lo + hi)
        };
    }
    Some(x)
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    fn steel() -> CurieSpecificHeat {
        match SpecificHeat::steel_4340() {
            SpecificHeat::Model(SpecificHeatModel::Curie(m)) => *m,
            SpecificHeat::Constant(_) => unreachable!(),
        }
    }

    fn rel(a: f64, b: f64) -> f64 {
        (a - b).abs() / b.abs()
    }

    /// By hand:
    ///
    /// - 300 K: t = 1 − 300/1040 = 0.7115385, t^0.2 = 0.9341996,
    ///   c = 190.14 − 273.75·0.7115385 + 418.30/0.9341996
    ///   = 190.14 − 194.7837 + 447.7630 = 443.1193 J/(kg·K);
    /// - 451 K: t = 0.5663462, t^0.2 = 0.8925168,
    ///   c = 190.14 − 155.0373 + 468.6747 = 503.7774;
    /// - 1500 K: t = 1500/1040 − 1 = 0.4423077, t^0.35 = 0.7516291,
    ///   c = 465.21 + 267.52·0.4423077 + 58.16/0.7516291
    ///   = 465.21 + 118.3262 + 77.3786 = 660.9148;
    /// - 0 K: A₀ − B₀ + C₀ = 334.69.
    #[test]
    fn the_steel_curve_has_its_hand_values() {
        let m = steel();
        for (t, c) in [
            (300.0, 443.1193),
            (451.0, 503.7774),
            (1500.0, 660.9148),
            (0.0, 334.69),
        ] {
            assert!(rel(m.at(t), c) < 1e-6, "c({t}) = {}, by hand {c}", m.at(t));
        }
        assert_eq!(m.at(1040.0), f64::INFINITY);
        assert_eq!(m.lowest(), 334.69);
        // A constant is itself everywhere.
        assert_eq!(SpecificHeat::Constant(477.0).at(1234.0), 477.0);
    }

    /// H(T_c) = T_c (A₀ − B₀/2 + C₀/(1 − n₀)), by hand
    /// 1040 · (190.14 − 136.875 + 522.875) = 1040 · 576.14 = 599 185.6 J/kg;
    /// H(0) = 0; H is continuous across T_c and its derivative is c on
    /// both sides.
    #[test]
    fn the_heat_is_the_integral_of_the_specific_heat() {
        let m = steel();
        assert_eq!(m.heat(0.0), 0.0);
        assert!(rel(m.heat(1040.0), 599_185.6) < 1e-12, "{}", m.heat(1040.0));
        // 1 nK below T_c the heat still to come is T_c C₀ t^0.8/0.8 with
        // t = 1e-9/1040: 1.3e-4 J/kg, 2.2e-10 of H(T_c).
        let gap = m.heat(1040.0) - m.heat(1040.0 - 1e-9);
        assert!(gap > 0.0 && gap < 1.5e-4, "{gap}");
        for t in [10.0, 294.0, 451.0, 900.0, 1030.0, 1050.0, 1500.0, 2500.0] {
            let e = 1e-3;
            let slope = (m.heat(t + e) - m.heat(t - e)) / (2.0 * e);
            assert!(rel(slope, m.at(t)) < 1e-6, "T {t}: {slope} vs {}", m.at(t));
        }
        assert_eq!(SpecificHeat::Constant(477.0).heat(2.0), 954.0);
    }

    /// Within 1 K of T_c, where c rises without bound, the smoothed c_v is
    /// the mean over T ± 1 K, (H(T + δ) − H(T − δ))/(2δ): at T_c 1886
    /// J/(kg·K) for the 4340 steel (by hand the singular parts
    /// C₀ T_c (δ/T_c)^0.8/0.8 = 2098 J/kg below and C₁ T_c (δ/T_c)^0.65/0.65
    /// = 1018 J/kg above over the 2 K, plus the regular parts' mean
    /// ≈ (A₀ + A₁)/2 = 327.7), between c at the span's ends (1868 and 1127)
    /// and far below c near T_c (1.06·10⁵ at T_c − 1 nK); elsewhere it is
    /// c.
    #[test]
    fn the_smoothed_specific_heat_near_the_curie_point_is_its_mean_nearby() {
        let s = SpecificHeat::steel_4340();
        let m = steel();
        assert!(s.at(1040.0).is_infinite());
        let c = s.smoothed_at(1040.0);
        let d = SMOOTHING_SPAN;
        let below = 418.30 * 1040.0 * (d / 1040.0_f64).powf(0.8) / 0.8;
        let above = 58.16 * 1040.0 * (d / 1040.0_f64).powf(0.65) / 0.65;
        assert!((below - 2098.0).abs() < 1.0 && (above - 1018.0).abs() < 1.0);
        // The regular parts add about A₀ and A₁ over half the span each
        // (B t is below 0.3 J/(kg·K) there).
        let by_hand = (below + above) / (2.0 * d) + 0.5 * (m.a0 + m.a1);
        assert!(rel(c, by_hand) < 1e-3, "{c} vs {by_hand}");
        assert!((c - 1885.6).abs() < 0.5, "{c}");
        assert!(c > s.at(1040.0 + d) && c < s.at(1040.0 - d) * 1.01, "{c}");
        for t in [1039.5, 1040.0 - 1e-9, 1040.2] {
            let mean = (s.heat(t + d) - s.heat(t - d)) / (2.0 * d);
            assert_eq!(s.smoothed_at(t).to_bits(), mean.to_bits(), "{t}");
            assert!(s.smoothed_at(t) < 0.1 * s.at(1040.0 - 1e-9));
        }
        for t in [300.0, 1038.9, 1041.1, 2000.0] {
            assert_eq!(s.smoothed_at(t).to_bits(), s.at(t).to_bits());
        }
        assert_eq!(SpecificHeat::Constant(477.0).smoothed_at(1040.0), 477.0);
        assert!(s.smoothed_at(f64::NAN).is_nan());
    }

    /// Plastic heating's rise is χ w/(ρ c) for a constant (the bits of
    /// `plastic_heating`) and the rise of the heat χ w/ρ through the curve:
    /// 0.9 × 2·10⁸ J/m³ at 7830 kg/m³ is 22 989 J/kg, 48.194 K at 477 J/(kg·K).
    #[test]
    fn plastic_heating_rises_by_the_heat_it_turns_the_work_into() {
        let (chi, w, rho) = (0.9, 2.0e8, 7830.0);
        let c = SpecificHeat::Constant(477.0);
        let dt = c.plastic_heating_rise(300.0, chi, w, rho);
        assert_eq!(
            dt.to_bits(),
            crate::elastic_plastic::plastic_heating(chi, w, rho, 477.0).to_bits()
        );
        assert!((dt - 48.193_93).abs() < 1e-5, "{dt}");
        let s = SpecificHeat::steel_4340();
        for t in [300.0, 1030.0, 1200.0] {
            let dt = s.plastic_heating_rise(t, chi, w, rho);
            assert_eq!(dt.to_bits(), s.temperature_rise(t, chi * w / rho).to_bits());
            assert!(
                rel(s.heat(t + dt) - s.heat(t), chi * w / rho) < 1e-9,
                "T {t}"
            );
        }
    }

    /// The rise holds the heat given: H(T + ΔT) − H(T) = q, through the
    /// Curie point too; a constant gives q/c to the bit.
    #[test]
    fn a_heat_raises_the_temperature_it_holds() {
        let s = SpecificHeat::steel_4340();
        for (t, q) in [
            (300.0, 1.0),
            (451.0, 5.0e4),
            (1000.0, 5.0e4),
            (1040.0, 10.0),
            (1200.0, 1.0e5),
            (600.0, -2.0e4),
        ] {
            let dt = s.temperature_rise(t, q);
            let held = s.heat(t + dt) - s.heat(t);
            assert!(
                (held - q).abs() <= 1e-9 * q.abs().max(s.heat(t)),
                "T {t} q {q}: {held}"
            );
        }
        // Small heats: the rise is q/c(T).
        let dt = s.temperature_rise(300.0, 1.0e-3);
        assert!(rel(dt, 1.0e-3 / 443.1193) < 1e-6, "{dt}");
        let c = SpecificHeat::Constant(477.0);
        assert_eq!(
            c.temperature_rise(300.0, 123.0).to_bits(),
            (123.0_f64 / 477.0).to_bits()
        );
        // Below 0 K: the point keeps 0 K; NaN stays NaN.
        assert_eq!(s.temperature_rise(10.0, -1.0e6), -10.0);
        assert!(s.temperature_rise(f64::NAN, 1.0).is_nan());
    }

    #[test]
    fn bad_constants_are_refused_by_name() {
        let field =
            |m: CurieSpecificHeat| match SpecificHeat::Model(SpecificHeatModel::Curie(Box::new(m)))
                .validate("ElasticPlastic")
            {
                Err(ConstitutiveError::InvalidParameter { field, .. }) => field,
                other => panic!("{other:?}"),
            };
        let s = steel();
        let cases = [
            (CurieSpecificHeat { t_c: 0.0, ..s }, "specific_heat.t_c"),
            (CurieSpecificHeat { n0: 1.0, ..s }, "specific_heat.n0"),
            (CurieSpecificHeat { n1: -0.1, ..s }, "specific_heat.n1"),
            (CurieSpecificHeat { b1: -1.0, ..s }, "specific_heat.b1"),
            (CurieSpecificHeat { a1: 0.0, ..s }, "specific_heat.a1"),
            (CurieSpecificHeat { a0: -500.0, ..s }, "specific_heat.a0"),
            (CurieSpecificHeat { c0: f64::NAN, ..s }, "specific_heat.c0"),
        ];
        for (m, name) in cases {
            assert_eq!(field(m), name);
        }
        assert!(SpecificHeat::steel_4340()
            .validate("ElasticPlastic")
            .is_ok());
        assert!(SpecificHeat::Constant(0.0)
            .validate("ElasticPlastic")
            .is_err());
    }

    #[test]
    fn a_config_writes_a_number_or_the_curie_form() {
        let c: SpecificHeat = ron::from_str("477.0").unwrap();
        assert_eq!(c, SpecificHeat::Constant(477.0));
        let text = "Curie(t_c: 1040.0, a0: 190.14, b0: 273.75, c0: 418.3, n0: 0.2, \
                    a1: 465.21, b1: 267.52, c1: 58.16, n1: 0.35)";
        let m: SpecificHeat = ron::from_str(text).unwrap();
        assert_eq!(m, SpecificHeat::steel_4340());
        let back: SpecificHeat = ron::from_str(&ron::to_string(&m).unwrap()).unwrap();
        assert_eq!(back, m);
        assert!(ron::from_str::<SpecificHeat>("Curie(t_c: 1040.0)").is_err());
    }

    proptest! {
        /// The contract of any c_v: positive, H increasing, and a heat
        /// q ≥ 0 raising T by the ΔT whose heat is q.
        #[test]
        fn the_steel_curve_keeps_its_contract(t in 1.0..3000.0_f64, q in 0.0..2.0e6_f64) {
            let s = SpecificHeat::steel_4340();
            prop_assert!(s.at(t) > 0.0);
            prop_assert!(s.heat(t + 1.0) > s.heat(t));
            let dt = s.temperature_rise(t, q);
            prop_assert!(dt >= 0.0);
            prop_assert!(dt <= q / 334.69 * (1.0 + 1e-12));
            let held = s.heat(t + dt) - s.heat(t);
            prop_assert!((held - q).abs() <= 1e-9 * s.heat(t + dt), "{held} vs {q}");
        }
    }
}
