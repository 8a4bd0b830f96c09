//! The (p, T) → ρ inversion of the three Mie–Grüneisen forms and the
//! fused `density_and_derivatives`: against the bracketed Newton solver the
//! models used before (kept here as the reference), evaluation counts, the
//! curvature bound the step tolerance relies on, and the fused method equal
//! to the three separate ones to the bit.

use super::*;
use crate::threshold::ONE_ATMOSPHERE;
use crate::SolidThreshold;
use crate::{EosModel, MieGruneisenCubic, MieGruneisenLinear, MieGruneisenThermal, SolidEos};
use brisance_core::Eos;
use proptest::prelude::*;

/// The solver before the lazy bracket (both window ends evaluated first,
/// then Newton with bisection, a step tested against the bracket before
/// its size): the reference answer, and how many evaluations it took.
fn reference_solve<F: Fn(f64) -> (f64, f64)>(
    f: F,
    p: f64,
    lo: f64,
    hi: f64,
    guess: f64,
) -> Option<Counted> {
    let mut n = 2;
    let (p_lo, _) = f(lo);
    let (p_hi, _) = f(hi);
    if !(p >= p_lo && p <= p_hi) {
        return None;
    }
    let (mut lo, mut hi) = (lo, hi);
    let mut x = if guess > lo && guess < hi {
        guess
    } else {
        0.5 * (lo + hi)
    };
    for _ in 0..100 {
        let (px, slope) = f(x);
        n += 1;
        let residual = px - p;
        if residual == 0.0 {
            return Some((x, n));
        }
        if residual < 0.0 {
            lo = x;
        } else {
            hi = x;
        }
        let newton = x - residual / slope;
        let next = if slope > 0.0 && newton > lo && newton < hi {
            newton
        } else {
            0.5 * (lo + hi)
        };
        if (next - x).abs() <= 2.0 * f64::EPSILON * x || hi - lo <= 2.0 * f64::EPSILON * hi {
            return Some((next, n));
        }
        x = next;
    }
    None
}

/// The copper of configs/cylinder_icempm.ron (C₀ = √(K/ρ) of its particles).
fn cylinder_copper() -> MieGruneisenLinear {
    MieGruneisenLinear {
        c0: 3619.7,
        ..MieGruneisenLinear::ofhc_copper()
    }
}

/// Every shipped Mie–Grüneisen solid, as the registry's solid enum.
fn shipped() -> Vec<SolidEos> {
    vec![
        SolidEos::MieGruneisenLinear(MieGruneisenLinear::steel_4340()),
        SolidEos::MieGruneisenLinear(MieGruneisenLinear::ofhc_copper()),
        SolidEos::MieGruneisenLinear(MieGruneisenLinear::rha_steel()),
        SolidEos::MieGruneisenLinear(cylinder_copper()),
        SolidEos::MieGruneisenCubic(MieGruneisenCubic::steel_seed001()),
        SolidEos::MieGruneisenThermal(MieGruneisenThermal::hmx_seed003()),
        SolidEos::MieGruneisenThermal(MieGruneisenThermal::rdx_seed003()),
        SolidEos::MieGruneisenThermal(MieGruneisenThermal::petn_seed003()),
        SolidEos::MieGruneisenThermal(MieGruneisenThermal::tkx50_seed003()),
        SolidEos::MieGruneisenThermal(MieGruneisenThermal::estane_seed003()),
        SolidEos::MieGruneisenThermal(MieGruneisenThermal::estane_half_density()),
        SolidEos::MieGruneisenThermal(MieGruneisenThermal::estane_density_matched()),
        SolidEos::MieGruneisenThermal(MieGruneisenThermal::estane_impedance_matched()),
    ]
}

/// ρ and the number of pressure evaluations that found it.
type Counted = (f64, usize);

/// (ρ, evaluations) from the model's solver, and the reference answer from
/// the old solver started where the model used to start it.
fn both(m: &SolidEos, p: f64, t: f64) -> (Result<Counted, EosError>, Option<Counted>) {
    let window = |rho0: f64| (MIN_RELATIVE_DENSITY * rho0, MAX_RELATIVE_DENSITY * rho0);
    match m {
        SolidEos::MieGruneisenLinear(m) => {
            let e = m.cv * (t - m.t0);
            let k0 = m.rho0 * m.c0 * m.c0;
            let guess = m.rho0 * (1.0 + (p - m.gamma0 * m.rho0 * e) / k0);
            let (lo, hi) = window(m.rho0);
            let f = |rho| (m.pressure(rho, e), m.dp_drho(rho, e));
            (
                m.density_counted(p, t),
                reference_solve(f, p, lo, hi, guess),
            )
        }
        SolidEos::MieGruneisenCubic(m) => {
            let e = m.cv * (t - m.t0);
            let k0 = m.rho0 * m.c0 * m.c0;
            let guess = m.rho0 * (1.0 + (p - m.gamma * m.rho0 * e) / k0);
            let (lo, hi) = window(m.rho0);
            let f = |rho| (m.pressure(rho, e), m.dp_drho(rho, e));
            (
                m.density_counted(p, t),
                reference_solve(f, p, lo, hi, guess),
            )
        }
        SolidEos::MieGruneisenThermal(m) => {
            let e = m.cv * t;
            let k0 = m.rho0 * m.c0 * m.c0;
            let guess = m.rho0 * (1.0 + (p - m.pressure(m.rho0, e)) / k0);
            let (lo, hi) = window(m.rho0);
            let f = |rho| (m.pressure(rho, e), m.dp_drho(rho, e));
            (
                m.density_counted(p, t),
                reference_solve(f, p, lo, hi, guess),
            )
        }
        SolidEos::Murnaghan(_) => unreachable!("not a Mie–Grüneisen form"),
    }
}

/// How far apart two solvers that each stop on a round-off residual may
/// land: 4 ulps of ρ, plus the width of the set of densities whose computed
/// pressure equals p to rounding. p is a sum of a thermal part
/// ∂p/∂e (e(T) − e(T₀)) and a cold part of about the same size and the
/// opposite sign where T is far below T₀, so its rounding is a few ε times
/// |p| + 2 |thermal part|, not ε |p|; dividing by ∂p/∂ρ turns it into
/// density. On a stiff, well-conditioned state this adds well under an
/// ulp; on the cancelling ones (estane compressed 50 % at 6 K) it is what
/// separates the two answers.
fn agreement_bound(m: &SolidEos, rho: f64, t: f64) -> f64 {
    let t0 = match m {
        SolidEos::MieGruneisenLinear(m) => m.t0,
        SolidEos::MieGruneisenCubic(m) => m.t0,
        SolidEos::MieGruneisenThermal(m) => m.t0,
        SolidEos::Murnaghan(_) => unreachable!("not a Mie–Grüneisen form"),
    };
    let e = m.specific_internal_energy_from_temperature(rho, t);
    let thermal = m.dp_de(rho, e) * (e - m.specific_internal_energy_from_temperature(rho, t0));
    let scale = m.pressure(rho, e).abs() + 2.0 * thermal.abs();
    4.0 * f64::EPSILON * (rho + scale / m.dp_drho(rho, e))
}

#[test]
fn a_cancelling_state_agrees_within_its_rounding_not_within_four_ulps() {
    // The 30 states of 2.08 million (13 solids on a 400 × 400 grid of
    // ρ/ρ₀ ∈ [0.8, 1.5], T ∈ [1, 3000] K) where the two answers lie more
    // than 4 ulps apart are all compressed estane far below T₀; the
    // farthest, 8.7 ulps, is this one. Both answers meet the true density
    // to 10⁻¹³ and lie within the conditioning bound (33.8 ulps here; the
    // largest ratio of the grid is 0.66 of it).
    let m = SolidEos::MieGruneisenThermal(MieGruneisenThermal::estane_density_matched());
    let (x, t) = (1.497_147_5, 6.323_225);
    let rho = x * m.reference_density();
    let p = m.pressure(rho, m.specific_internal_energy_from_temperature(rho, t));
    let (new, reference) = both(&m, p, t);
    let (solved, _) = new.unwrap();
    let (reference, _) = reference.unwrap();
    assert!((solved - rho).abs() <= 1e-13 * rho, "{solved} vs {rho}");
    assert!(
        (reference - rho).abs() <= 1e-13 * rho,
        "{reference} vs {rho}"
    );
    let apart = (solved - reference).abs();
    assert!(apart > 4.0 * f64::EPSILON * rho, "{solved} vs {reference}");
    assert!(
        apart <= agreement_bound(&m, solved, t),
        "{solved} vs {reference}"
    );
    // The bound is not loose on a plain state: within 6 ulps of ρ for the
    // 4340 steel at ρ₀ and 300 K.
    let steel = SolidEos::MieGruneisenLinear(MieGruneisenLinear::steel_4340());
    let rho = steel.reference_density();
    assert!(agreement_bound(&steel, rho, 300.0) <= 6.0 * f64::EPSILON * rho);
}

/// Most evaluations one inversion may take: the linear form starts at its
/// closed-form root, so its first Newton step is round-off and ends the
/// iteration; the other two forms start at the root of the linearised
/// isotherm and need more Newton steps the further the state is from ρ₀.
/// Measured on a 201 × 61 grid of ρ/ρ₀ ∈ [0.8, 1.5], T ∈ [1, 3000] K: 1
/// everywhere for the linear form, at most 5 for the cubic and 8 for the
/// thermal form (4.1 to 4.3 on average), against 7.4 to 8.6 on average
/// and 41 to 57 at most for the old solver.
fn evaluation_bound(m: &SolidEos) -> usize {
    match m {
        SolidEos::MieGruneisenLinear(_) => 1,
        _ => 10,
    }
}

#[test]
fn the_round_off_case_that_fell_into_bisection_is_one_evaluation() {
    // The most frequent solve of the E-CYLINDER copper (p = 1 atm, T one
    // round-off below T₀): the old solver's second Newton step rounded to
    // zero, was rejected as not strictly inside the bracket, and 49
    // bisection steps from the window's far end followed (52 evaluations).
    let cu = cylinder_copper();
    let (p, t) = (101_325.0, 299.999_999_999_988_9);
    let (rho, evaluations) = cu.density_counted(p, t).unwrap();
    assert_eq!(evaluations, 1);
    let (reference, old_evaluations) = match both(&SolidEos::MieGruneisenLinear(cu), p, t).1 {
        Some(r) => r,
        None => panic!("reference solve failed"),
    };
    assert!(old_evaluations > 40, "{old_evaluations}");
    assert!(
        (rho - reference).abs() <= 2.0 * f64::EPSILON * rho,
        "{rho} vs {reference}"
    );
    // And the answer's own round trip: p(ρ, e(T)) = p to round-off of the
    // 1.4e11 Pa stiffness (|Δp| ≤ ρ ∂p/∂ρ × 2ε).
    let e = cu.specific_internal_energy_from_temperature(rho, t);
    let dp = (cu.pressure(rho, e) - p).abs();
    assert!(
        dp <= 2.0 * f64::EPSILON * rho * cu.dp_drho(rho, e),
        "Δp = {dp}"
    );
}

#[test]
fn isotherms_curve_little_enough_for_the_step_tolerance() {
    // c = ρ |∂²p/∂ρ²| / (2 ∂p/∂ρ) on the window (central differences of
    // the analytic slope, step 10⁻⁵ ρ) at 1 K, 300 K and 3000 K: below 100,
    // so a last Newton step of 10⁻¹⁰ ρ leaves an error below 10⁻¹⁸ ρ.
    let mut worst: f64 = 0.0;
    for m in shipped() {
        let rho0 = m.reference_density();
        for t in [1.0, 300.0, 3000.0] {
            for i in 1..1000 {
                let x = MIN_RELATIVE_DENSITY
                    + (MAX_RELATIVE_DENSITY - MIN_RELATIVE_DENSITY) * f64::from(i) / 1000.0;
                let rho = x * rho0;
                let e = m.specific_internal_energy_from_temperature(rho, t);
                let h = 1e-5 * rho;
                let d2 = (m.dp_drho(rho + h, e) - m.dp_drho(rho - h, e)) / (2.0 * h);
                let c = rho * d2.abs() / (2.0 * m.dp_drho(rho, e));
                assert!(
                    c.is_finite() && c < 100.0,
                    "{m:?}: c = {c} at ρ/ρ₀ = {x}, T = {t}"
                );
                worst = worst.max(c);
            }
        }
    }
    assert!(
        worst > 1.0,
        "the check must see real curvature, worst c = {worst}"
    );
}

#[test]
fn out_of_range_pressures_keep_their_message() {
    // Beyond both ends of the window: the same error as before, naming p
    // and the pressures at both ends.
    for m in shipped() {
        let rho0 = m.reference_density();
        let t = 300.0;
        let (lo, hi) = (MIN_RELATIVE_DENSITY * rho0, MAX_RELATIVE_DENSITY * rho0);
        let at = |rho: f64| m.pressure(rho, m.specific_internal_energy_from_temperature(rho, t));
        for p in [2.0 * at(hi).abs(), at(lo) - at(lo).abs()] {
            let expected = EosError::OutOfRange {
                eos: m.name(),
                detail: format!(
                    "pressure {p} Pa outside [{}, {}] Pa reached on the density window [{lo}, {hi}] kg/m³ at this temperature",
                    at(lo),
                    at(hi)
                ),
            };
            assert_eq!(m.density(p, t), Err(expected.clone()), "{m:?}");
            assert_eq!(m.density_and_derivatives(p, t), Err(expected), "{m:?}");
        }
    }
}

/// Asserts `density_and_derivatives` returns the three methods' values to
/// the bit, or their first error.
fn assert_fused_is_separate<E: Eos + ?Sized>(m: &E, p: f64, t: f64) -> Result<(), TestCaseError> {
    let fused = m.density_and_derivatives(p, t);
    let separate = m.density(p, t).and_then(|rho| {
        Ok((
            rho,
            m.isothermal_compressibility(p, t)?,
            m.thermal_expansivity(p, t)?,
        ))
    });
    match (fused, separate) {
        (Ok(a), Ok(b)) => {
            prop_assert!(
                a.0.to_bits() == b.0.to_bits()
                    && a.1.to_bits() == b.1.to_bits()
                    && a.2.to_bits() == b.2.to_bits(),
                "{}: fused {:?} vs separate {:?} at p = {}, T = {}",
                m.name(),
                a,
                b,
                p,
                t
            );
        }
        (a, b) => prop_assert_eq!(a, b),
    }
    Ok(())
}

#[test]
fn fused_equals_separate_at_hand_picked_states() {
    // Copper at 1 atm and 300 K (κ = 1/(ρ₀C₀²) = 7.21367e-12 /Pa,
    // α = Γ₀c_v/C₀² = 4.9838e-5 /K by hand for OFHC), at 10 GPa and 1500 K,
    // below the threshold, and the errors at T = 0 and p = NaN.
    let cu = MieGruneisenLinear::ofhc_copper();
    let (rho, kappa, alpha) = cu.density_and_derivatives(101_325.0, 300.0).unwrap();
    assert!((kappa - 7.21367e-12).abs() < 1e-16, "κ = {kappa}");
    assert!((alpha - 4.9838e-5).abs() < 1e-9, "α = {alpha}");
    assert!(
        (rho / 8930.0 - 1.0 - 101_325.0 * 7.21367e-12).abs() < 1e-12,
        "ρ = {rho}"
    );
    let wrapped = SolidThreshold::new(SolidEos::MieGruneisenLinear(cu));
    let model = EosModel::SolidThreshold(wrapped);
    for (p, t) in [
        (101_325.0, 300.0),
        (1e10, 1500.0),
        (1e3, 300.0),
        (1e-200, 50.0),
        (101_325.0, 0.0),
        (f64::NAN, 300.0),
        (-1.0, 300.0),
    ] {
        for m in shipped() {
            assert_fused_is_separate(&m, p, t).unwrap();
            assert_fused_is_separate(&SolidThreshold::new(m), p, t).unwrap();
        }
        assert_fused_is_separate(&model, p, t).unwrap();
        assert_fused_is_separate(&cu, p, t).unwrap();
    }
    // Below the threshold κ carries dq/dp = p_t/p: at p = p_t/10, ten times
    // the solid's κ at q = p_t(1 − ln 10).
    let p = 0.1 * ONE_ATMOSPHERE;
    let q = ONE_ATMOSPHERE * (1.0 - 10f64.ln());
    let (_, k_w, a_w) = model.density_and_derivatives(p, 300.0).unwrap();
    let (_, k_s, a_s) = cu.density_and_derivatives(q, 300.0).unwrap();
    assert!((k_w - 10.0 * k_s).abs() <= 1e-12 * k_w, "{k_w} vs {k_s}");
    assert_eq!(a_w, a_s);
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    /// For a state (ρ, T) on the window, ρ(p(ρ, e(T)), T) returns ρ within
    /// 10⁻¹³ relative, as close to the old solver's answer as the rounding
    /// of p allows (`agreement_bound`), and in at most `evaluation_bound`
    /// pressure evaluations.
    #[test]
    fn inversion_round_trips_and_matches_the_old_solver(
        which in 0usize..13,
        x in 0.8f64..1.5,
        t in 1.0f64..3000.0,
    ) {
        let m = shipped()[which];
        let rho = x * m.reference_density();
        let p = m.pressure(rho, m.specific_internal_energy_from_temperature(rho, t));
        let (new, reference) = both(&m, p, t);
        let (solved, evaluations) = new.map_err(|e| TestCaseError::fail(e.to_string()))?;
        prop_assert!((solved - rho).abs() <= 1e-13 * rho, "{:?}: ρ = {} from {}", m, solved, rho);
        let (reference, _) = reference.ok_or_else(|| TestCaseError::fail("reference failed"))?;
        let bound = agreement_bound(&m, solved, t);
        prop_assert!(
            (solved - reference).abs() <= bound,
            "{:?}: {} vs old {} (bound {})", m, solved, reference, bound
        );
        prop_assert!(evaluations <= evaluation_bound(&m), "{:?}: {} evaluations", m, evaluations);
    }

    /// The fused method equals the three separate ones to the bit, for the
    /// bare solids, their threshold wrappers and through the registry enum,
    /// over pressures from 10⁻³ Pa (below the threshold) to 100 GPa and
    /// beyond the window (errors compared too).
    #[test]
    fn fused_equals_separate_to_the_bit(
        which in 0usize..13,
        log_p in -3.0f64..11.0,
        t in 1.0f64..3000.0,
    ) {
        let m = shipped()[which];
        let p = 10f64.powf(log_p);
        assert_fused_is_separate(&m, p, t)?;
        assert_fused_is_separate(&SolidThreshold::new(m), p, t)?;
        assert_fused_is_separate(&EosModel::SolidThreshold(SolidThreshold::new(m)), p, t)?;
    }
}
