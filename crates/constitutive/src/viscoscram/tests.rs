// Element indices run over several parallel arrays.
#![allow(clippy::needless_range_loop)]

use super::*;
use std::f64::consts::PI;

const RHO: f64 = 1840.0;

fn input(l: Mat3, dt: f64, stress: Mat3) -> StressUpdateInput {
    StressUpdateInput {
        velocity_gradient: l,
        dt,
        density: RHO,
        temperature: 300.0,
        specific_internal_energy: 0.0,
        stress,
    }
}

/// PBX-9501 with the cracks frozen (v_max = 0) and made negligible
/// (c₀ = 1 nm, (c₀/a)³ = 1e-18, so the elements decouple) and, with
/// `relax` false, every dashpot removed.
fn frozen(relax: bool) -> ViscoScram {
    let mut m = ViscoScram::pbx_9501(ObjectiveRate::Jaumann);
    m.max_crack_speed = 0.0;
    m.initial_crack_radius = 1.0e-9;
    if !relax {
        m.inverse_relaxation_times = [0.0; ELEMENTS];
    }
    m
}

fn fresh(m: &ViscoScram) -> Vec<f64> {
    let mut h = vec![0.0; m.history_len()];
    m.init_history(&mut h);
    h
}

/// Simple shear v_x = γ̇ y.
fn shear(rate: f64) -> Mat3 {
    let mut l = Mat3::zeros();
    l[(0, 1)] = rate;
    l
}

#[test]
fn pbx_9501_is_valid_and_its_moduli_are_the_cited_ones() {
    let m = ViscoScram::pbx_9501(ObjectiveRate::GreenNaghdi);
    m.validate().unwrap();
    assert!((m.shear_modulus() - 2.6411e9).abs() < 1.0);
    let PressureModel::Linear { bulk_modulus } = m.pressure else {
        panic!("linear pressure")
    };
    // 2 · 2.6411e9 · 1.3 / (3 · 0.4) = 5.72238e9 Pa.
    assert!(
        (bulk_modulus / 5.722383e9 - 1.0).abs() < 1e-6,
        "{bulk_modulus}"
    );
    // c_L = √((K + 4G/3)/ρ) = √(9.243850e9 / 1840) = 2241.4 m/s.
    let c = m.wave_speed(RHO, 0.0);
    assert!((c / 2241.39 - 1.0).abs() < 1e-4, "{c}");
}

#[test]
fn bad_parameters_name_their_field() {
    let mut m = ViscoScram::pbx_9501(ObjectiveRate::Jaumann);
    m.shear_moduli[2] = -1.0;
    assert!(m
        .validate()
        .unwrap_err()
        .to_string()
        .contains("shear_moduli.2"));
    let mut m = ViscoScram::pbx_9501(ObjectiveRate::Jaumann);
    m.inverse_relaxation_times[4] = f64::NAN;
    let e = m.validate().unwrap_err().to_string();
    assert!(e.contains("inverse_relaxation_times.4"), "{e}");
    let mut m = ViscoScram::pbx_9501(ObjectiveRate::Jaumann);
    m.crack_friction = 1.3;
    assert!(m
        .validate()
        .unwrap_err()
        .to_string()
        .contains("crack_friction"));
}

/// Without dashpots and cracks the model is hypoelastic with G = Σ G_n: a
/// shear strain γ in small steps gives σ_xy = G γ (RK4 is exact for a
/// constant rate) and no heat.
#[test]
fn springs_alone_are_hypoelastic_with_the_summed_modulus() {
    let m = frozen(false);
    let mut h = fresh(&m);
    let (rate, dt, steps) = (10.0, 1e-8, 100);
    let mut sigma = Mat3::zeros();
    let mut heat = 0.0;
    for _ in 0..steps {
        let r = m.update_stress(&input(shear(rate), dt, sigma), &mut h);
        sigma = r.stress;
        heat += r.plastic_work;
    }
    let gamma = rate * dt * steps as f64;
    let expected = m.shear_modulus() * gamma;
    // The Jaumann rotation of the shear stress is O(γ²).
    assert!(
        (sigma[(0, 1)] / expected - 1.0).abs() < 1e-5,
        "{} vs {expected}",
        sigma[(0, 1)]
    );
    assert_eq!(heat, 0.0);
    assert_eq!(h[CRACK_RADIUS_INDEX], 1.0e-9);
}

/// At zero strain rate each element relaxes as s_n(t) = s_n(0) e^{−t/τ_n}
/// and the heat is the spring energy Σ s_n:s_n/(4G_n) they let go.
#[test]
fn at_rest_each_element_relaxes_exponentially_and_its_energy_becomes_heat() {
    let m = frozen(true);
    let mut h = fresh(&m);
    // Load in one short step: every element takes 2G_n ė dt.
    let load_dt = 1e-12;
    let r = m.update_stress(&input(shear(1e6), load_dt, Mat3::zeros()), &mut h);
    let s0: Vec<f64> = (0..ELEMENTS).map(|k| h[1 + 6 * k + 5]).collect();
    for k in 0..ELEMENTS {
        let expected = 2.0 * m.shear_moduli[k] * 0.5 * 1e6 * load_dt;
        assert!(
            (s0[k] / expected - 1.0).abs() < 1e-5,
            "element {k}: {} vs {expected}",
            s0[k]
        );
    }
    let mut sigma = r.stress;
    let (dt, steps) = (1e-8, 100);
    let mut heat = 0.0;
    for _ in 0..steps {
        let r = m.update_stress(&input(Mat3::zeros(), dt, sigma), &mut h);
        sigma = r.stress;
        heat += r.plastic_work;
    }
    let t = dt * steps as f64;
    let mut released = 0.0;
    for k in 0..ELEMENTS {
        let expected = s0[k] * (-t * m.inverse_relaxation_times[k]).exp();
        let got = h[1 + 6 * k + 5];
        assert!(
            (got - expected).abs() <= 1e-8 * s0[k],
            "element {k}: {got} vs {expected}"
        );
        // s:s of a pure shear s_xy = s_yx = x is 2x².
        released += 2.0 * (s0[k] * s0[k] - got * got) / (4.0 * m.shear_moduli[k]);
    }
    assert!((heat / released - 1.0).abs() < 1e-6, "{heat} vs {released}");
    assert!(
        h[1 + 5] == s0[0],
        "the spring without dashpot keeps its stress"
    );
}

/// The crack speed's two branches, by hand at c = 30 µm, m = 10,
/// K₀ = 500 Pa√m in tension-free shear (σ_m = 0): K' = 500 √1.2 =
/// 547.72 Pa√m, K₁ = K' · 6^{0.1} = 655.20 Pa√m; K_I = σ_vm √(πc).
#[test]
fn crack_speed_follows_its_two_branches_and_is_continuous() {
    let m = ViscoScram::pbx_9501(ObjectiveRate::Jaumann);
    let c: f64 = 3.0e-5;
    let k_prime = 500.0 * 1.2f64.sqrt();
    let k1 = k_prime * 6.0f64.powf(0.1);
    assert!((k1 / 655.2028 - 1.0).abs() < 1e-6, "{k1}");
    // A shear s_xy = τ has σ_vm = √3 τ.
    let deviator_for = |k_i: f64| {
        let tau = k_i / ((PI * c).sqrt() * 3f64.sqrt());
        let mut s = Mat3::zeros();
        s[(0, 1)] = tau;
        s[(1, 0)] = tau;
        s
    };
    let slow = m.crack_speed(c, &deviator_for(400.0), 0.0);
    assert!(
        (slow / (300.0 * (400.0 / k1).powi(10)) - 1.0).abs() < 1e-12,
        "{slow}"
    );
    let fast = m.crack_speed(c, &deviator_for(1000.0), 0.0);
    assert!(
        (fast / (300.0 * (1.0 - 0.25)) - 1.0).abs() < 1e-12,
        "{fast}"
    );
    let below = m.crack_speed(c, &deviator_for(k_prime * (1.0 - 1e-12)), 0.0);
    let above = m.crack_speed(c, &deviator_for(k_prime * (1.0 + 1e-12)), 0.0);
    // Both branches give v_max · 2/(m + 2) = 50 m/s at K'.
    assert!((below / 50.0 - 1.0).abs() < 1e-9 && (above / 50.0 - 1.0).abs() < 1e-9);
}

/// Confinement toughens the cracks: at σ_m = −10 MPa, c = 30 µm,
/// μ = 0.35, μ' = 0.35 √(45/(2 · 2.755)) = 1.000227, f = μ' · 1e7 ·
/// √(3e-5)/500 = 109.569, K₀μ = 500 √(1 + π f (1 + f)) = 97 547 Pa√m; in
/// tension K₀μ = K₀ and the mean stress adds to σ_eff.
#[test]
fn friction_raises_the_toughness_only_in_compression() {
    let m = ViscoScram::pbx_9501(ObjectiveRate::Jaumann);
    let c: f64 = 3.0e-5;
    let mu_prime = 0.35 * (45.0f64 / (2.0 * (3.0 - 2.0 * 0.35 * 0.35))).sqrt();
    assert!((mu_prime / 1.000227 - 1.0).abs() < 1e-6, "{mu_prime}");
    let f = mu_prime * 1e7 * c.sqrt() / 500.0;
    let expected = 500.0 * (1.0 + PI * f * (1.0 + f)).sqrt();
    assert!((m.toughness(c, -1e7) / expected - 1.0).abs() < 1e-14);
    assert!((expected / 97_546.7 - 1.0).abs() < 1e-5, "{expected}");
    assert_eq!(m.toughness(c, 1e7), 500.0);
    // Pure tension, no deviator: σ_eff = √(3/2 · 3σ_m²) = √4.5 σ_m.
    let v = m.crack_speed(c, &Mat3::zeros(), 1e4);
    let k_i = 4.5f64.sqrt() * 1e4 * (PI * c).sqrt();
    let k_prime = 500.0 * 1.2f64.sqrt();
    let k1 = k_prime * 6.0f64.powf(0.1);
    assert!(k_i < k_prime);
    assert!((v / (300.0 * (k_i / k1).powi(10)) - 1.0).abs() < 1e-12);
    assert_eq!(m.crack_speed(c, &Mat3::zeros(), -1e4), 0.0);
}

/// Energy: along a loading path with the cracks growing, the stress power
/// ∫ S:ė dt equals the rise of the stored energy Σ s_n:s_n/(4G_n) +
/// (c/a)³ S:S/(4G) plus the heat returned, to the integration's accuracy;
/// the cracks only grow.
#[test]
fn stress_power_is_stored_energy_plus_heat_while_the_cracks_grow() {
    let m = ViscoScram::pbx_9501(ObjectiveRate::Jaumann);
    let mut h = fresh(&m);
    let g = m.shear_modulus();
    let stored = |h: &[f64]| {
        let mut w = 0.0;
        let mut total = Mat3::zeros();
        for k in 0..ELEMENTS {
            let s = read_voigt(&h[1 + 6 * k..7 + 6 * k]);
            w += s.component_mul(&s).sum() / (4.0 * m.shear_moduli[k]);
            total += s;
        }
        let ca3 = (h[CRACK_RADIUS_INDEX] / m.crack_size).powi(3);
        w + ca3 * total.component_mul(&total).sum() / (4.0 * g)
    };
    // A stretch and shear at 2000/s (isochoric: no pressure work) over
    // 20 µs: the von Mises stress passes K' for c₀ and the cracks run.
    let mut l = Mat3::zeros();
    l[(0, 0)] = 2000.0;
    l[(1, 1)] = -1000.0;
    l[(2, 2)] = -1000.0;
    l[(0, 1)] = 1500.0;
    let d = crate::objective::rate_of_deformation(&l);
    let e = deviator(&d);
    let (dt, steps) = (1e-9, 20_000);
    let mut sigma = Mat3::zeros();
    let (mut power, mut heat) = (0.0, 0.0);
    let w0 = stored(&h);
    let mut c_prev = h[CRACK_RADIUS_INDEX];
    for _ in 0..steps {
        let before = deviator(&sigma);
        let r = m.update_stress(&input(l, dt, sigma), &mut h);
        let after = deviator(&r.stress);
        // Trapezoid in time of S:ė (the rotation of S is O(Δt²) here).
        power += 0.5 * (before + after).component_mul(&e).sum() * dt;
        heat += r.plastic_work;
        assert!(r.plastic_work >= 0.0);
        assert!(h[CRACK_RADIUS_INDEX] >= c_prev);
        c_prev = h[CRACK_RADIUS_INDEX];
        sigma = r.stress;
    }
    let grown = h[CRACK_RADIUS_INDEX] / m.initial_crack_radius;
    assert!(grown > 1.5, "the cracks grew by {grown}");
    let balance = power - (stored(&h) - w0) - heat;
    assert!(heat > 0.0);
    assert!(
        balance.abs() < 1e-4 * power,
        "power {power}, stored {}, heat {heat}, balance {balance}",
        stored(&h) - w0
    );
}

/// Grown cracks soften the response: the same shear path gives a lower
/// stress once the cracks have grown (the compliance (c/a)³/(2G)).
#[test]
fn grown_cracks_soften_the_shear_response() {
    let m = frozen(false);
    let mut cracked = m.clone();
    cracked.initial_crack_radius = 0.8e-3; // (c/a)³ = 0.512
    let run = |m: &ViscoScram| {
        let mut h = fresh(m);
        let mut sigma = Mat3::zeros();
        for _ in 0..100 {
            sigma = m
                .update_stress(&input(shear(10.0), 1e-8, sigma), &mut h)
                .stress;
        }
        sigma[(0, 1)]
    };
    let ratio = run(&cracked) / run(&m);
    // Frozen cracks: S = 2G ė t / (1 + (c/a)³).
    assert!((ratio * 1.512 - 1.0).abs() < 1e-9, "{ratio}");
}

/// Many relaxation times in one step: the update splits it (no substep
/// longer than half the shortest relaxation time, at most MAX_SUBSTEPS)
/// and relaxes each element as e^{−t/τ_n}: after 1 ms the slowest
/// dashpot keeps e^{−7.32} of its stress, the faster ones nothing (below
/// 1e-12 of it), the spring all of it.
#[test]
fn a_long_step_is_split_and_stays_stable() {
    let m = frozen(true);
    assert_eq!(m.substeps(1e-9), 1);
    assert_eq!(m.substeps(1e-6), 4);
    assert_eq!(m.substeps(1.0), MAX_SUBSTEPS);
    let mut h = fresh(&m);
    let r = m.update_stress(&input(shear(1e3), 1e-9, Mat3::zeros()), &mut h);
    let s0: Vec<f64> = (0..ELEMENTS).map(|k| h[1 + 6 * k + 5]).collect();
    let r = m.update_stress(&input(Mat3::zeros(), 1e-3, r.stress), &mut h);
    assert!(r.stress.iter().all(|x| x.is_finite()) && r.plastic_work > 0.0);
    assert_eq!(h[1 + 5], s0[0]);
    {
        let k = 1;
        let expected = s0[k] * (-1e-3 * m.inverse_relaxation_times[k]).exp();
        let got = h[1 + 6 * k + 5];
        assert!(
            (got / expected - 1.0).abs() < 1e-6,
            "element {k}: {got} vs {expected}"
        );
    }
    for k in 2..ELEMENTS {
        assert!(
            h[1 + 6 * k + 5].abs() < 1e-12 * s0[k],
            "element {k}: {}",
            h[1 + 6 * k + 5]
        );
    }
}

/// The ramp-and-hold of the generalized Maxwell solid against its exact
/// response, at the report's finest step: within 1e-6 of the peak, and
/// fourth order in the step (RK4) between 1e-7 and 5e-8 s.
#[test]
fn without_cracks_the_elements_follow_the_exact_maxwell_response() {
    use super::cases::maxwell_ramp_and_hold;
    let coarse = maxwell_ramp_and_hold(1.0e-7);
    let fine = maxwell_ramp_and_hold(5.0e-8);
    let finest = maxwell_ramp_and_hold(2.5e-8);
    assert!(finest.max_error <= 1e-6, "{finest:?}");
    let order = (coarse.max_error / fine.max_error).log2();
    assert!(
        order > 3.5 && order < 4.5,
        "{coarse:?} {fine:?} order {order}"
    );
    // The peak: Σ 2 G_n ė τ_n (1 − e^{−t₁/τ_n}) + 2 G₁ ė t₁ at t₁ = 10 µs.
    assert!(finest.peak > 2.0 * 3.5e8 * 1000.0 * 1e-5);
}

/// Along the load–unload path with the cracks running, the model against
/// the scalar equations integrated on their own at 1/64 of its step (the
/// report's finest step, 2.5 ns): the
/// crack radius and stress agree, the cracks never heal and keep growing
/// a little while unloading, and work = stored energy + heat.
#[test]
fn with_cracks_the_model_follows_an_independent_integration() {
    use super::cases::crack_path;
    let r = crack_path(2.5e-9, 64);
    assert!(r.growth > 2.0, "{r:?}");
    assert!(r.monotone, "{r:?}");
    assert!(r.crack_error <= 1e-5, "{r:?}");
    assert!(r.stress_error <= 1e-5, "{r:?}");
    assert!(
        r.unloading_growth > 0.0 && r.unloading_growth < 0.5,
        "{r:?}"
    );
    assert!(r.energy_error <= 1e-6, "{r:?}");
    assert!(r.heat_share > 0.0 && r.heat_share < 1.0, "{r:?}");
}
