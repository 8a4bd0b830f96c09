//! Mie–Grüneisen equations of state: the pieces the three forms share.
//!
//! A Mie–Grüneisen EOS writes the pressure as a reference curve plus a
//! thermal offset proportional to the energy above that curve,
//!
//! p(ρ, e) = p_H(ρ) + Γ ρ (e − e_H(ρ)),
//!
//! with the shock Hugoniot as the reference curve. Brisance has three forms,
//! one module each:
//!
//! - [`crate::mie_gruneisen_cubic`]: seed 001 eqs 65–66, the Hugoniot as a
//!   cubic in μ = ρ/ρ₀ − 1 with a linear tension branch, constant Γ;
//! - [`crate::mie_gruneisen_linear`]: seed 000 eq 40, the Hugoniot of the
//!   linear shock–particle velocity fit Uₛ = C₀ + S uₚ, with Γρ = Γ₀ρ₀;
//! - [`crate::mie_gruneisen_thermal`]: seed 003 eqs 12–14, the same linear
//!   Hugoniot about a reference pressure P₀, constant Γ and e = c_v T, the
//!   form the lattice uses.
//!
//! This module holds the reference Hugoniots (plain functions of the
//! compression, so they can be tested and plotted alone), the valid density
//! window common to the three forms, and the bracketed Newton iteration that
//! inverts p(ρ, T) for ρ.
//!
//! Units: ρ kg/m³, e J/kg, p Pa, T K, C₀ m/s.

use brisance_core::EosError;

/// Smallest ρ/ρ₀ at which the Mie–Grüneisen forms are evaluated (20 %
/// tension). Below it the Hugoniot fits have no meaning, c² at low
/// temperature turns negative for the shipped metals near ρ/ρ₀ ≈ 0.7, and a
/// real solid has long since spalled.
pub const MIN_RELATIVE_DENSITY: f64 = 0.8;

/// Largest ρ/ρ₀ at which the Mie–Grüneisen forms are evaluated (50 %
/// compression, several hundred GPa for metals). Beyond it the cubic form's
/// factor (1 − Γμ/2) bends the reference curve over and the linear form
/// approaches its pole at χ = 1 − ρ₀/ρ = 1/S.
pub const MAX_RELATIVE_DENSITY: f64 = 1.5;

/// Hugoniot pressure of the linear Uₛ = C₀ + S uₚ fit and its derivative
/// with respect to the volumetric compression χ (seed 000 eq 40, seed 003
/// eq 13b without P₀, where χ is called φ):
///
/// p_H(χ) = ρ₀ C₀² χ / (1 − S χ)²,  χ = 1 − ρ₀/ρ,
/// dp_H/dχ = ρ₀ C₀² (1 + S χ) / (1 − S χ)³.
///
/// Returns `(p_H, dp_H/dχ)` in Pa. Finite for S χ < 1.
#[inline]
pub fn linear_hugoniot(rho0: f64, c0: f64, s: f64, chi: f64) -> (f64, f64) {
    let k0 = rho0 * c0 * c0;
    let d = 1.0 - s * chi;
    (k0 * chi / (d * d), k0 * (1.0 + s * chi) / (d * d * d))
}

/// Hugoniot pressure of seed 001 eq 66 and its derivative with respect to
/// μ = ρ/ρ₀ − 1:
///
/// p_H = ρ₀ C₀² [μ + (2S − 1) μ² + (S − 1)(3S − 1) μ³]  for μ > 0,
/// p_H = ρ₀ C₀² μ                                          for μ ≤ 0.
///
/// The compression branch is the Taylor expansion of
/// [`linear_hugoniot`] to third order in μ; the two branches meet with equal
/// value and slope at μ = 0.
///
/// Returns `(p_H, dp_H/dμ)` in Pa.
#[inline]
pub fn cubic_hugoniot(rho0: f64, c0: f64, s: f64, mu: f64) -> (f64, f64) {
    let k0 = rho0 * c0 * c0;
    if mu > 0.0 {
        let a = 2.0 * s - 1.0;
        let b = (s - 1.0) * (3.0 * s - 1.0);
        (
            k0 * mu * (1.0 + mu * (a + mu * b)),
            k0 * (1.0 + mu * (2.0 * a + 3.0 * b * mu)),
        )
    } else {
        (k0 * mu, k0)
    }
}

/// Whether `rho` lies in the valid window
/// [`MIN_RELATIVE_DENSITY`]·ρ₀ ..= [`MAX_RELATIVE_DENSITY`]·ρ₀ and `e` is
/// finite; the error names the model and the offending value.
pub(crate) fn check_window(eos: &'static str, rho0: f64, rho: f64, e: f64) -> Result<(), EosError> {
    let (lo, hi) = (MIN_RELATIVE_DENSITY * rho0, MAX_RELATIVE_DENSITY * rho0);
    if !(rho >= lo && rho <= hi) {
        return Err(EosError::OutOfRange {
            eos,
            detail: format!("density {rho} kg/m³ outside the valid window [{lo}, {hi}] kg/m³"),
        });
    }
    if !e.is_finite() {
        return Err(EosError::OutOfRange {
            eos,
            detail: format!("specific internal energy {e} J/kg is not finite"),
        });
    }
    Ok(())
}

/// Rejects a density outside the valid window or a non-finite pressure
/// (the e(ρ, p) entry points).
pub(crate) fn check_density_pressure(
    eos: &'static str,
    rho0: f64,
    rho: f64,
    p: f64,
) -> Result<(), EosError> {
    check_window(eos, rho0, rho, 0.0)?;
    if !p.is_finite() {
        return Err(EosError::OutOfRange {
            eos,
            detail: format!("pressure {p} Pa is not finite"),
        });
    }
    Ok(())
}

/// Rejects a non-finite pressure or a temperature that is not positive and
/// finite (the (p, T) → ρ entry points).
pub(crate) fn check_pressure_temperature(
    eos: &'static str,
    p: f64,
    t: f64,
) -> Result<(), EosError> {
    if !(p.is_finite() && t > 0.0 && t.is_finite()) {
        return Err(EosError::OutOfRange {
            eos,
            detail: format!(
                "ρ(p, T) needs a finite p and a finite T > 0, got p = {p} Pa, T = {t} K"
            ),
        });
    }
    Ok(())
}

/// Maximum iterations of [`solve_density`]; Newton from the models' starts
/// converges in one to four, bisection alone would need about sixty.
const MAX_ITERATIONS: usize = 100;

/// A Newton step smaller than this fraction of ρ ends the iteration, the
/// step taken. Newton's relative error after a step δ is about c (δ/ρ)²,
/// with c = ρ |∂²p/∂ρ²| / (2 ∂p/∂ρ) the relative curvature of the isotherm;
/// a unit test checks c ≤ 100 on the shipped models' windows, so after a
/// step of at most 10⁻¹⁰ ρ the error is below 10⁻¹⁸ ρ, under the round-off
/// of ρ itself (1.1 × 10⁻¹⁶ ρ): the step that would follow cannot change
/// the answer and is not taken. A step that rounds to zero (the residual is
/// round-off) ends the iteration here too, before the bracket is
/// consulted: tested against a bracket end it equals, it used to be
/// replaced by bisection from the window's far end (about 50 evaluations
/// instead of 4 for most solves of the E-CYLINDER copper).
pub(crate) const NEWTON_STEP_TOLERANCE: f64 = 1e-10;

/// Solves p(ρ) = `p` for ρ in [`lo`, `hi`] by Newton's method safeguarded by
/// bisection, starting from `guess` (clamped to the window; its midpoint if
/// `guess` is not finite).
///
/// `pressure_and_slope(ρ)` returns (p(ρ), dp/dρ) along the isotherm; it
/// must increase with ρ on the window (the models check this in `validate`).
///
/// The window's ends are evaluated lazily: the bracket [a, b] starts as the
/// window, each iterate replaces the end its residual's sign says, and
/// p(lo), p(hi) are computed only when a Newton step leaves the bracket (or
/// the slope is not positive) and the step is to be replaced by bisection —
/// then a window end the iterates have not yet replaced must be checked to
/// hold the root. A pressure outside [p(lo), p(hi)] is `OutOfRange` (the
/// message gives both, as before); running out of iterations is
/// `NoConvergence`. Convergence: a zero residual, a Newton step below
/// [`NEWTON_STEP_TOLERANCE`] ρ (the step is taken; the answer is clamped
/// to the window), or a bracket collapsed to round-off.
///
/// Returns ρ and how many times `pressure_and_slope` was evaluated (the
/// tests bound it). Allocation-free except in the error path.
pub(crate) fn solve_density<F>(
    eos: &'static str,
    pressure_and_slope: F,
    p: f64,
    lo: f64,
    hi: f64,
    guess: f64,
) -> Result<(f64, usize), EosError>
where
    F: Fn(f64) -> (f64, f64),
{
    let out_of_range = |p_lo: f64, p_hi: f64| {
        EosError::OutOfRange {
        eos,
        detail: format!(
            "pressure {p} Pa outside [{p_lo}, {p_hi}] Pa reached on the density window [{lo}, {hi}] kg/m³ at this temperature"
        ),
    }
    };
    if p.is_nan() {
        return Err(out_of_range(
            pressure_and_slope(lo).0,
            pressure_and_slope(hi).0,
        ));
    }
    let mut evaluations = 0;
    // Bracket [a, b]; `a_known`/`b_known`: p(a) < p resp. p(b) > p has been
    // seen (by an iterate, or by evaluating the window end).
    let (mut a, mut b) = (lo, hi);
    let (mut a_known, mut b_known) = (false, false);
    // A start outside the window (the closed-form root of a state at the
    // window's edge can land there by round-off) begins at the nearer end.
    let mut x = if guess.is_finite() {
        guess.clamp(lo, hi)
    } else {
        0.5 * (lo + hi)
    };
    let mut residual = f64::NAN;
    for _ in 0..MAX_ITERATIONS {
        let (px, slope) = pressure_and_slope(x);
        evaluations += 1;
        residual = px - p;
        if residual == 0.0 {
            return Ok((x, evaluations));
        }
        if residual < 0.0 {
            a = x;
            a_known = true;
        } else {
            b = x;
            b_known = true;
        }
        let newton = x - residual / slope;
        if slope > 0.0 && (newton - x).abs() <= NEWTON_STEP_TOLERANCE * x {
            return Ok((newton.clamp(lo, hi), evaluations));
        }
        let next = if slope > 0.0 && newton > a && newton < b {
            newton
        } else {
            if !(a_known && b_known) {
                let p_lo = if a_known {
                    None
                } else {
                    evaluations += 1;
                    Some(pressure_and_slope(lo).0)
                };
                let p_hi = if b_known {
                    None
                } else {
                    evaluations += 1;
                    Some(pressure_and_slope(hi).0)
                };
                let below = p_lo.is_some_and(|p_lo| !(p >= p_lo));
                let above = p_hi.is_some_and(|p_hi| !(p <= p_hi));
                if below || above {
                    return Err(out_of_range(
                        p_lo.unwrap_or_else(|| pressure_and_slope(lo).0),
                        p_hi.unwrap_or_else(|| pressure_and_slope(hi).0),
                    ));
                }
                if p_lo == Some(p) {
                    return Ok((lo, evaluations));
                }
                if p_hi == Some(p) {
                    return Ok((hi, evaluations));
                }
                (a_known, b_known) = (true, true);
            }
            0.5 * (a + b)
        };
        if b - a <= 2.0 * f64::EPSILON * b {
            return Ok((next, evaluations));
        }
        x = next;
    }
    Err(EosError::NoConvergence {
        eos,
        iterations: MAX_ITERATIONS,
        residual,
    })
}

#[cfg(test)]
mod inversion_tests;

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{IdealGas, MieGruneisenCubic, MieGruneisenLinear, MieGruneisenThermal};
    use serde::Deserialize;

    #[test]
    fn cubic_hugoniot_is_the_taylor_expansion_of_the_linear_one() {
        // μ = 0.01 ⇒ χ = μ/(1 + μ); the two differ at O(μ⁴) only.
        let (rho0, c0, s) = (7850.0, 4569.0, 1.49);
        let mu: f64 = 0.01;
        let (pc, _) = cubic_hugoniot(rho0, c0, s, mu);
        let (pl, _) = linear_hugoniot(rho0, c0, s, mu / (1.0 + mu));
        let k0 = rho0 * c0 * c0;
        assert!((pc - pl).abs() < 2.0 * k0 * mu.powi(4), "{pc} vs {pl}");
    }

    #[test]
    fn cubic_hugoniot_at_ten_percent_compression_matches_hand_value() {
        // ρ₀C₀² = 7850 × 4569² = 1.638747e11 Pa; bracket
        // 0.1 + 1.98 × 0.01 + 0.49 × 3.47 × 0.001 = 0.1215003.
        let (p, dp) = cubic_hugoniot(7850.0, 4569.0, 1.49, 0.1);
        let k0 = 7850.0 * 4569.0_f64.powi(2);
        assert!((p / k0 - 0.121_500_3).abs() < 1e-12, "p = {p}");
        // derivative: 1 + 2 × 1.98 × 0.1 + 3 × 1.7003 × 0.01 = 1.447009
        assert!((dp / k0 - 1.447_009).abs() < 1e-12, "dp = {dp}");
    }

    #[test]
    fn linear_hugoniot_matches_hand_value() {
        // χ = 0.1, S = 2: p = K χ / 0.64 = 0.15625 K; slope K × 1.2/0.512.
        let (p, dp) = linear_hugoniot(1000.0, 1000.0, 2.0, 0.1);
        assert!((p - 0.156_25e9).abs() < 1e-3);
        assert!((dp - 1.2e9 / 0.512).abs() < 1e-3);
    }

    #[test]
    fn solve_density_inverts_a_monotone_curve_and_rejects_out_of_bracket() {
        let f = |rho: f64| (rho * rho * rho, 3.0 * rho * rho);
        let (rho, _) = solve_density("test", f, 8.0, 1.0, 3.0, 1.5).unwrap();
        assert!((rho - 2.0).abs() < 1e-15);
        // Above and below the window: the message gives p at both ends, as
        // before the ends were evaluated lazily (1 = 1³, 27 = 3³).
        for p in [100.0, 0.5] {
            let err = solve_density("test", f, p, 1.0, 3.0, 1.5).unwrap_err();
            assert_eq!(
                err,
                EosError::OutOfRange {
                    eos: "test",
                    detail: format!("pressure {p} Pa outside [1, 27] Pa reached on the density window [1, 3] kg/m³ at this temperature"),
                }
            );
        }
        assert!(solve_density("test", f, f64::NAN, 1.0, 3.0, 1.5).is_err());
        // The window's ends are roots too.
        assert_eq!(
            solve_density("test", f, 27.0, 1.0, 3.0, 2.9).unwrap().0,
            3.0
        );
        assert_eq!(solve_density("test", f, 1.0, 1.0, 3.0, 1.1).unwrap().0, 1.0);
    }

    #[test]
    fn solve_density_counts_newton_steps_from_a_close_start() {
        // p = ρ³ from ρ = 2(1 + 10⁻⁴): Newton's relative errors are
        // 10⁻⁴, 10⁻⁸ (c = 1 for ρ³), 10⁻¹⁶: the third step is below the
        // step tolerance and is the last, with no window-end evaluation.
        let f = |rho: f64| (rho * rho * rho, 3.0 * rho * rho);
        let (rho, evaluations) = solve_density("test", f, 8.0, 1.0, 3.0, 2.0002).unwrap();
        assert_eq!(evaluations, 3);
        assert!((rho - 2.0).abs() <= 2.0 * f64::EPSILON * 2.0, "{rho}");
        // A start that is not a number begins at the window's midpoint,
        // ρ = 2: exact; one outside the window at its nearer end.
        assert_eq!(
            solve_density("test", f, 8.0, 1.0, 3.0, f64::NAN).unwrap(),
            (2.0, 1)
        );
        assert_eq!(
            solve_density("test", f, 27.0, 1.0, 3.0, 7.0).unwrap(),
            (3.0, 1)
        );
        // A Newton step leaving the bracket (slope 0 at ρ = 0 ⇒ infinite
        // step) falls back on bisection, which evaluates the window's ends.
        let (rho, evaluations) = solve_density("test", f, 8.0, 0.0, 3.0, 1e-300).unwrap();
        assert!((rho - 2.0).abs() <= 4.0 * f64::EPSILON * 2.0, "{rho}");
        assert!(evaluations > 3, "{evaluations}");
    }

    #[test]
    fn linear_compression_at_matches_hand_value() {
        // ρ₀ = 1000, C₀ = 1000 (K₀ = 10⁹), S = 2, Γ₀ = 2, χ = 0.1:
        // p_ref = 0.15625 K₀ × (1 − 0.1) = 0.140625 K₀; √disc = K₀√1.5625
        // = 1.25 K₀; χ = 0.28125 / (1 + 0.5625 + 1.25) = 0.1.
        let m = MieGruneisenLinear {
            c0: 1000.0,
            s: 2.0,
            gamma0: 2.0,
            rho0: 1000.0,
            cv: 1.0,
            t0: 300.0,
        };
        let chi = m.compression_at(0.140_625e9).unwrap();
        assert!((chi - 0.1).abs() < 1e-16, "{chi}");
        assert_eq!(m.compression_at(0.0), Some(0.0));
        // Deep tension: disc = K₀(K₀ + 2p(2S − Γ₀)) < 0 below −K₀/4.
        assert_eq!(m.compression_at(-0.3e9), None);
    }

    /// The `eos` part of a material file, as the future `EosModel` enum will
    /// read it (variants named like the structs).
    #[derive(Debug, Deserialize)]
    enum EosForTest {
        IdealGas(IdealGas),
        MieGruneisenCubic(MieGruneisenCubic),
        MieGruneisenLinear(MieGruneisenLinear),
        MieGruneisenThermal(MieGruneisenThermal),
    }

    #[derive(Debug, Deserialize)]
    #[serde(deny_unknown_fields)]
    #[allow(dead_code)] // description and source are read by people, not by the test
    struct MaterialFile {
        name: String,
        description: String,
        source: String,
        density: f64,
        eos: EosForTest,
        /// The constitutive model of a solid entry (read by the composer).
        #[serde(default)]
        model: Option<serde::de::IgnoredAny>,
    }

    fn parse(text: &str) -> MaterialFile {
        let options = ron::Options::default().with_default_extension(
            ron::extensions::Extensions::IMPLICIT_SOME
                | ron::extensions::Extensions::UNWRAP_VARIANT_NEWTYPES,
        );
        match options.from_str(text) {
            Ok(m) => m,
            Err(err) => panic!("material file does not parse: {err}"),
        }
    }

    macro_rules! material_file {
        ($stem:literal) => {
            (
                $stem,
                include_str!(concat!("../../../configs/materials/", $stem, ".ron")),
            )
        };
    }

    #[test]
    fn every_material_file_parses_validates_and_matches_its_constructor() {
        let files = [
            material_file!("air"),
            material_file!("ofhc_copper"),
            material_file!("steel_4340"),
            material_file!("rha_steel"),
            material_file!("steel_seed001"),
            material_file!("hmx_crystal"),
            material_file!("rdx_crystal"),
            material_file!("petn_crystal"),
            material_file!("tkx_50_crystal"),
            material_file!("estane"),
            material_file!("estane_half_density"),
            material_file!("estane_density_matched"),
            material_file!("estane_impedance_matched"),
        ];
        for (stem, text) in files {
            let m = parse(text);
            assert_eq!(m.name, stem, "file {stem}.ron names itself {}", m.name);
            let (rho0, expected_equal) = match &m.eos {
                EosForTest::IdealGas(g) => (
                    g.rho0,
                    stem != "air" || *g == IdealGas::new(1.4, 717.6, 1.225),
                ),
                EosForTest::MieGruneisenCubic(eos) => {
                    eos.validate().unwrap_or_else(|e| panic!("{stem}: {e}"));
                    (
                        eos.rho0,
                        stem != "steel_seed001" || *eos == MieGruneisenCubic::steel_seed001(),
                    )
                }
                EosForTest::MieGruneisenLinear(eos) => {
                    eos.validate().unwrap_or_else(|e| panic!("{stem}: {e}"));
                    let reference = match stem {
                        "ofhc_copper" => MieGruneisenLinear::ofhc_copper(),
                        "steel_4340" => MieGruneisenLinear::steel_4340(),
                        "rha_steel" => MieGruneisenLinear::rha_steel(),
                        other => panic!("no constructor for {other}"),
                    };
                    (eos.rho0, *eos == reference)
                }
                EosForTest::MieGruneisenThermal(eos) => {
                    eos.validate().unwrap_or_else(|e| panic!("{stem}: {e}"));
                    let reference = match stem {
                        "hmx_crystal" => MieGruneisenThermal::hmx_seed003(),
                        "rdx_crystal" => MieGruneisenThermal::rdx_seed003(),
                        "petn_crystal" => MieGruneisenThermal::petn_seed003(),
                        "tkx_50_crystal" => MieGruneisenThermal::tkx50_seed003(),
                        "estane" => MieGruneisenThermal::estane_seed003(),
                        "estane_half_density" => MieGruneisenThermal::estane_half_density(),
                        "estane_density_matched" => MieGruneisenThermal::estane_density_matched(),
                        "estane_impedance_matched" => {
                            MieGruneisenThermal::estane_impedance_matched()
                        }
                        other => panic!("no constructor for {other}"),
                    };
                    (eos.rho0, *eos == reference)
                }
            };
            assert_eq!(m.density, rho0, "{stem}: density and the EOS's rho0 differ");
            assert!(
                expected_equal,
                "{stem}.ron differs from its constructor: {:?}",
                m.eos
            );
        }
    }
}
