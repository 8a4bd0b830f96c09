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

mod single_element;
