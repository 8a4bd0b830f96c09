//! Verification of the heat conduction: the decay of a cosine mode in a
//! bar and of the first radial Bessel mode of a cylinder against their
//! analytic transients, conservation of the heat, the unchanged step
//! without conductivity, the diffusive time-step limit, determinism across
//! thread counts, and a property test of conservation and the maximum
//! principle.

use super::cases::{alpha, bar_decay, cylinder_decay, solid, CV, J1_FIRST_ZERO, K, RHO, T0};
use super::*;
use crate::{fill_shape_in, FillSpec, MaterialId, MpmOptions, MpmSolver, Shape, ShapeFunction};
use brisance_constitutive::{ElasticPlastic, SpecificHeat};
use brisance_core::{Geometry, Solver};
use brisance_grid::Level;
use proptest::prelude::*;

fn particles_in(
    level: &Level,
    lo: [f64; 3],
    hi: [f64; 3],
    ppc: usize,
    geometry: Geometry,
) -> Particles {
    cases::particles_in(level, lo, hi, ppc, geometry).unwrap()
}

fn solver(
    level: Level,
    ps: Particles,
    shape: ShapeFunction,
    geometry: Geometry,
    k: f64,
) -> MpmSolver {
    cases::conducting_solver(level, ps, shape, geometry, k).unwrap()
}

/// Σ m_p c_v T_p, J.
fn total_heat(s: &MpmSolver) -> f64 {
    let ps = s.particles();
    ps.mass
        .iter()
        .zip(&ps.temperature)
        .map(|(m, t)| m * CV * t)
        .sum()
}

/// The bar's decay-rate error ([`cases::bar_decay`]).
fn bar_error(cells: usize, shape: ShapeFunction) -> f64 {
    bar_decay(cells, shape).unwrap().error()
}

/// The cylinder's decay-rate error ([`cases::cylinder_decay`]).
fn cylinder_error(cells: usize, shape: ShapeFunction) -> f64 {
    cylinder_decay(cells, shape).unwrap().error()
}

/// V-CONDUCTION: the decay rate within 1 % at 32 cells, and an error that
/// falls when the bar is refined. Measured (linear shape functions, 2
/// particles per cell per direction, Δt at cfl 0.4, over one e-folding
/// time): relative errors of the decay rate −0.661 % (16 cells), −0.165 %
/// (32), −0.0412 % (64) — second order (the lumped heat capacity and the
/// particle-to-node average each smooth the mode by O((πh/L)²)).
#[test]
fn bar_cosine_mode_decays_at_the_analytic_rate_and_converges() {
    let e16 = bar_error(16, ShapeFunction::Linear);
    let e32 = bar_error(32, ShapeFunction::Linear);
    let e64 = bar_error(64, ShapeFunction::Linear);
    eprintln!("bar, linear: errors {e16:e} (16), {e32:e} (32), {e64:e} (64)");
    assert!(e32.abs() < 0.01, "32 cells: {e32}");
    assert!(e64.abs() < 0.5 * e32.abs() && e32.abs() < 0.5 * e16.abs());
}

/// The bar with the wider shape functions at 32 cells, each within 1 %.
/// Measured errors of the decay rate: uGIMP and cpGIMP −0.165 % (the
/// linear function's: with 2 particles per cell a particle's domain never
/// straddles a node, where the two coincide), quadratic B-spline
/// −0.404 %.
#[test]
fn bar_cosine_mode_decays_at_the_analytic_rate_with_every_shape() {
    for shape in [
        ShapeFunction::Gimp,
        ShapeFunction::CpGimp,
        ShapeFunction::QuadraticBSpline,
    ] {
        let e = bar_error(32, shape);
        eprintln!("bar, {shape:?}: error {e:e} (32 cells)");
        assert!(e.abs() < 0.01, "{shape:?}: {e}");
    }
}

/// The series J0 of the cylinder's mode: zero at the first zero of J0,
/// and flat (J0′ = −J1 = 0) at [`J1_FIRST_ZERO`], the mode's radius.
#[test]
fn the_bessel_series_has_the_tabulated_zeros() {
    assert!(cases::bessel_j0(2.404_825_557_695_773).abs() < 1e-15);
    let (x, h) = (J1_FIRST_ZERO, 1e-5);
    let slope = (cases::bessel_j0(x + h) - cases::bessel_j0(x - h)) / (2.0 * h);
    assert!(slope.abs() < 1e-9, "{slope}");
    assert!((cases::bessel_j0(x) + 0.402_759_395_702_553).abs() < 1e-14);
}

/// The r–z form: a solid cylinder of radius R with an adiabatic surface,
/// T = T0 + ΔT J0(j₁′ r/R), j₁′ = 3.8317 the first zero of J1, decays as
/// exp(−α (j₁′/R)² t). (The mode of the cylinder held at T0 on its
/// surface, with the first zero 2.4048 of J0, needs a prescribed
/// temperature, which the method does not have.) Within 1 % at 32 cells,
/// converging. Measured (2 particles per cell per direction, cfl 0.4, over
/// one e-folding time): linear −1.24 % (16 cells), −0.308 % (32),
/// −0.0770 % (64); uGIMP −0.308 % (32).
#[test]
fn cylinder_radial_bessel_mode_decays_at_the_analytic_rate() {
    let e16 = cylinder_error(16, ShapeFunction::Linear);
    let e32 = cylinder_error(32, ShapeFunction::Linear);
    let e64 = cylinder_error(64, ShapeFunction::Linear);
    eprintln!("cylinder, linear: errors {e16:e} (16), {e32:e} (32), {e64:e} (64)");
    assert!(e32.abs() < 0.01, "32 cells: {e32}");
    assert!(e64.abs() < 0.5 * e32.abs() && e32.abs() < 0.5 * e16.abs());
    let eg = cylinder_error(32, ShapeFunction::Gimp);
    eprintln!("cylinder, uGIMP: error {eg:e} (32 cells)");
    assert!(eg.abs() < 0.01, "uGIMP: {eg}");
}

/// A 3D block with a random temperature field, or its r–z twin, in a grid
/// larger than itself (every face of the block adiabatic), with c_v [`CV`].
fn insulated_block(shape: ShapeFunction, geometry: Geometry, temps: &[f64]) -> MpmSolver {
    insulated_block_with(shape, geometry, temps, SpecificHeat::Constant(CV))
}

/// The block of [`insulated_block`] conducting through the specific heat
/// `heat`.
fn insulated_block_with(
    shape: ShapeFunction,
    geometry: Geometry,
    temps: &[f64],
    heat: SpecificHeat,
) -> MpmSolver {
    let (level, lo, hi) = match geometry {
        Geometry::Cartesian => (
            Level::new([0.0; 3], [0.75, 0.625, 0.5], [6, 5, 4], [1, 1, 1], 0).unwrap(),
            [0.125, 0.125, 0.125],
            [0.625, 0.5, 0.375],
        ),
        _ => (
            Level::new([0.0; 3], [0.75, 0.625, 0.125], [6, 5, 1], [1, 1, 1], 0).unwrap(),
            [0.0, 0.125, 0.0],
            [0.5, 0.5, 0.125],
        ),
    };
    let mut ps = particles_in(&level, lo, hi, 2, geometry);
    for p in 0..ps.len() {
        ps.temperature[p] = temps[p % temps.len()];
    }
    cases::conducting_solver_with(level, ps, shape, geometry, K, heat).unwrap()
}

const SHAPES: [ShapeFunction; 4] = [
    ShapeFunction::Linear,
    ShapeFunction::Gimp,
    ShapeFunction::CpGimp,
    ShapeFunction::QuadraticBSpline,
];

/// Σ m c_v T is kept to round-off over 20 stable steps, every shape, both
/// geometries. Measured: relative changes of at most 2.4·10⁻¹⁶.
#[test]
fn insulated_block_keeps_its_heat_to_round_off() {
    let temps: Vec<f64> = (0..97).map(|i| 300.0 + (i * 37 % 101) as f64).collect();
    for geometry in [Geometry::Cartesian, Geometry::Axisymmetric] {
        for shape in SHAPES {
            let mut s = insulated_block(shape, geometry, &temps);
            let e0 = total_heat(&s);
            let t0 = s.particles().temperature.clone();
            let dt = s.stable_dt().unwrap();
            for _ in 0..20 {
                s.advance(dt).unwrap();
            }
            let rel = (total_heat(&s) - e0).abs() / e0;
            eprintln!("{geometry:?} {shape:?}: relative change {rel:e}");
            assert!(rel < 1e-14, "{geometry:?} {shape:?}: {rel:e}");
            assert_ne!(s.particles().temperature, t0, "the heat moved");
        }
    }
}

/// Σ m_p H(T_p), J, H = ∫₀ᵀ c dT' of `heat`.
fn total_enthalpy(s: &MpmSolver, heat: &SpecificHeat) -> f64 {
    let ps = s.particles();
    ps.mass
        .iter()
        .zip(&ps.temperature)
        .map(|(m, &t)| m * heat.heat(t))
        .sum()
}

/// With the 4340 steel's c_v(T) and temperatures on both sides of its
/// Curie point (950–1150 K, T_c 1040 K, where c rises without bound; in
/// the Cartesian block particles start at 1040 K exactly, where the weight
/// is the smoothed one of `SpecificHeat::smoothed_at`), the
/// heat Σ m H(T) is kept over 20 stable steps, every shape, both
/// geometries: each particle's H rises by exactly the heat its share of
/// the nodal rates brings, and those shares sum to zero. Measured:
/// relative changes of at most 1.3·10⁻¹⁵. The temperatures differ from
/// those of the constant c_v = c(300 K).
#[test]
fn insulated_block_keeps_its_heat_through_the_curie_point() {
    let temps: Vec<f64> = (0..97)
        .map(|i| 950.0 + 2.0 * (i * 37 % 101) as f64)
        .collect();
    let curve = SpecificHeat::steel_4340();
    for geometry in [Geometry::Cartesian, Geometry::Axisymmetric] {
        for shape in SHAPES {
            let mut s = insulated_block_with(shape, geometry, &temps, curve.clone());
            let c300 = SpecificHeat::Constant(curve.at(300.0));
            let mut flat = insulated_block_with(shape, geometry, &temps, c300);
            let e0 = total_enthalpy(&s, &curve);
            let t0 = s.particles().temperature.clone();
            let dt = s.stable_dt().unwrap();
            for _ in 0..20 {
                s.advance(dt).unwrap();
                flat.advance(dt).unwrap();
            }
            let rel = (total_enthalpy(&s, &curve) - e0).abs() / e0;
            eprintln!("{geometry:?} {shape:?}: relative change {rel:e}");
            assert!(rel < 1e-14, "{geometry:?} {shape:?}: {rel:e}");
            assert_ne!(s.particles().temperature, t0, "the heat moved");
            assert_ne!(s.particles().temperature, flat.particles().temperature);
        }
    }
}

/// A curve that is flat (A₀ = A₁ = 477, B = C = 0: c = 477 on both sides
/// of T_c) conducts as the constant 477 does: the same temperatures to
/// 10⁻¹¹ K after 20 steps of a 300–400 K field (measured 2.8·10⁻¹² K; the
/// curve's rise is the root of H(T') − H(T) = q, the constant's the
/// quotient q/c, so the bits may differ).
#[test]
fn a_flat_curve_conducts_as_its_constant() {
    use brisance_constitutive::{CurieSpecificHeat, SpecificHeatModel};
    let flat = SpecificHeat::Model(SpecificHeatModel::Curie(Box::new(CurieSpecificHeat {
        t_c: 1040.0,
        a0: CV,
        b0: 0.0,
        c0: 0.0,
        n0: 0.2,
        a1: CV,
        b1: 0.0,
        c1: 0.0,
        n1: 0.35,
    })));
    let temps: Vec<f64> = (0..97).map(|i| 300.0 + (i * 37 % 101) as f64).collect();
    for geometry in [Geometry::Cartesian, Geometry::Axisymmetric] {
        let mut curve = insulated_block_with(ShapeFunction::Gimp, geometry, &temps, flat.clone());
        let mut constant = insulated_block(ShapeFunction::Gimp, geometry, &temps);
        let start = constant.particles().temperature.clone();
        let dt = constant.stable_dt().unwrap();
        assert_eq!(curve.stable_dt().unwrap(), dt);
        for _ in 0..20 {
            curve.advance(dt).unwrap();
            constant.advance(dt).unwrap();
        }
        let (a, b) = (curve.particles(), constant.particles());
        let worst = a
            .temperature
            .iter()
            .zip(&b.temperature)
            .map(|(x, y)| (x - y).abs())
            .fold(0.0, f64::max);
        assert!(worst < 1e-11, "{geometry:?}: {worst:e} K");
        assert_ne!(b.temperature, start, "the heat moved");
    }
}

/// A moving, plastically working steel block: the steps with the option
/// absent, with k = 0 given, and with an empty option are the same bits.
#[test]
fn zero_conductivity_leaves_the_step_bit_for_bit_unchanged() {
    let level = Level::new([0.0; 3], [1.0, 1.0, 0.125], [8, 8, 1], [1, 1, 1], 0).unwrap();
    let run = |heat: Option<HeatConduction>| {
        let steel = MaterialModel::ElasticPlastic(ElasticPlastic::steel_4340_seed000());
        let mut ps = Particles::new(brisance_core::Material::history_len(&steel));
        fill_shape_in(
            &mut ps,
            &level.geometry,
            &FillSpec {
                shape: Shape::Box {
                    min: [0.25, 0.25, 0.0],
                    max: [0.75, 0.625, 0.125],
                },
                ppc: 2,
                density: 7850.0,
                material: MaterialId(0),
                velocity: [0.0; 3],
                temperature: 300.0,
                specific_internal_energy: 0.0,
            },
            Geometry::Cartesian,
        )
        .unwrap();
        for p in 0..ps.len() {
            let x = ps.position[p];
            ps.velocity[p] = [200.0 * (x[1] - 0.4), -150.0 * (x[0] - 0.5), 0.0];
            ps.temperature[p] = 300.0 + 100.0 * x[0];
        }
        let mut s = MpmSolver::new(level.clone(), vec![steel], ps, MpmOptions::default()).unwrap();
        if let Some(h) = heat {
            s = s.with_heat_conduction(h).unwrap();
        }
        for _ in 0..10 {
            let dt = s.stable_dt().unwrap();
            s.advance(dt).unwrap();
        }
        s
    };
    let plain = run(None);
    for heat in [
        HeatConduction::default(),
        HeatConduction {
            conductivity: vec![0.0],
            specific_heat: vec![None],
        },
    ] {
        let other = run(Some(heat));
        assert!(other.thermal_properties().is_empty());
        let (a, b) = (plain.particles(), other.particles());
        assert_eq!(a.position, b.position);
        assert_eq!(a.velocity, b.velocity);
        assert_eq!(a.stress, b.stress);
        assert_eq!(a.temperature, b.temperature);
        assert_eq!(a.specific_internal_energy, b.specific_internal_energy);
        assert_eq!(a.history, b.history);
        assert_eq!(plain.stable_dt().unwrap(), other.stable_dt().unwrap());
    }
    // The steel's specific heat is the model's when none is given.
    let conducting = run(Some(HeatConduction {
        conductivity: vec![40.0],
        specific_heat: vec![],
    }));
    assert_eq!(
        conducting.thermal_properties()[0].specific_heat,
        SpecificHeat::Constant(477.0)
    );
    assert_ne!(
        conducting.particles().temperature,
        plain.particles().temperature
    );
}

/// Δt = cfl / (2 α Σ_d 1/Δx_d²): cfl·h²/(2 d α) on cubic cells, d the
/// active axes, and the smaller of it and the wave limit in `stable_dt`.
#[test]
fn stable_dt_takes_the_diffusive_limit_when_it_is_smaller() {
    let level = Level::new([0.0; 3], [1.0, 1.0, 0.125], [8, 8, 1], [1, 1, 1], 0).unwrap();
    let ps = particles_in(
        &level,
        [0.25, 0.25, 0.0],
        [0.75, 0.75, 0.125],
        2,
        Geometry::Cartesian,
    );
    let h: f64 = 0.125;
    let plain = solver(
        level.clone(),
        ps.clone(),
        ShapeFunction::Linear,
        Geometry::Cartesian,
        0.0,
    );
    let dt_wave = plain.stable_dt().unwrap();
    // k such that the diffusive limit is a tenth of the wave limit (d = 2).
    let k = 0.4 * h * h / (2.0 * 2.0 * 0.1 * dt_wave) * RHO * CV;
    let s = solver(
        level.clone(),
        ps.clone(),
        ShapeFunction::Linear,
        Geometry::Cartesian,
        k,
    );
    let expected = 0.4 * h * h / (2.0 * 2.0 * k / (RHO * CV));
    let dt = s.stable_dt().unwrap();
    assert!((dt / expected - 1.0).abs() < 1e-12, "{dt} vs {expected}");
    assert!((dt / dt_wave - 0.1).abs() < 1e-12);
    // A weak conductor leaves the wave limit alone.
    let weak = solver(
        level.clone(),
        ps.clone(),
        ShapeFunction::Linear,
        Geometry::Cartesian,
        1e-3 * k,
    );
    assert_eq!(weak.stable_dt().unwrap(), dt_wave);
    // Cells of unequal edges: 1/(2α(1/hx² + 1/hy²)).
    let grid = brisance_core::UniformGridGeometry {
        origin: [0.0; 3],
        spacing: [0.1, 0.2, 5.0],
        cells: [4, 3, 1],
    };
    let a = 2.0;
    let dt = diffusive_time_step(a, &grid, 0.5);
    assert!((dt - 0.5 / (2.0 * a * (100.0 + 25.0))).abs() < 1e-15);
    assert_eq!(diffusive_time_step(0.0, &grid, 0.5), f64::INFINITY);
}

/// A random field stepped at `factor` times the diffusive limit (cfl 1)
/// on a bar (`dims` 1) or square (`dims` 2) of `cells` cells per side:
/// the largest deviation from T0 after 400 steps over the initial one.
fn growth(factor: f64, cells: usize, dims: usize, shape: ShapeFunction) -> f64 {
    let h = 1.0 / cells as f64;
    let (upper, n) = if dims == 1 {
        ([1.0, h, h], [cells, 1, 1])
    } else {
        ([1.0, 1.0, h], [cells, cells, 1])
    };
    let level = Level::new([0.0; 3], upper, n, [1, 1, 1], 0).unwrap();
    let mut ps = particles_in(&level, [0.0; 3], upper, 2, Geometry::Cartesian);
    for p in 0..ps.len() {
        ps.temperature[p] = T0 + ((p * 7919 % 1013) as f64 / 1013.0 - 0.5);
    }
    let max_dev = |t: &[f64]| t.iter().fold(0.0_f64, |m, t| m.max((t - T0).abs()));
    let d0 = max_dev(&ps.temperature);
    let mut s = solver(level, ps, shape, Geometry::Cartesian, K);
    let dt = factor * diffusive_time_step(alpha(), &s.level().geometry, 1.0);
    for _ in 0..400 {
        s.advance(dt).unwrap();
    }
    max_dev(&s.particles().temperature) / d0
}

/// At the diffusive limit with cfl = 1 a random field does not grow
/// over 400 steps, with every shape, in 1D and 2D; at four times the
/// limit the bar with linear shape functions blows up. Measured: the
/// largest |T − T0| falls to 0.67 (1D) and 0.96 (2D) of its initial
/// value at the limit (the particles' sub-grid part, which the grid does
/// not see, stays), and is unchanged up to three times the limit with
/// linear functions in 1D (the particle update sees the nodal operator
/// through the consistent-over-lumped mass ratio, whose factor 1/3 on the
/// highest mode moves the method's own limit to 3×); it grows to 10⁸⁷ at
/// four times. The limit is thus safe by a factor 3 or more.
#[test]
fn a_random_field_stays_bounded_at_the_diffusive_limit() {
    for shape in SHAPES {
        for dims in [1, 2] {
            let g = growth(1.0, 16, dims, shape);
            assert!(g <= 1.0, "{shape:?} {dims}D: {g}");
        }
    }
    let g = growth(4.0, 16, 1, ShapeFunction::Linear);
    assert!(g > 1e3, "four times the limit: {g}");
}

/// The same bits on 1 and 3 threads.
#[test]
fn conduction_is_the_same_bits_on_any_thread_count() {
    // A constant c_v, and the 4340 steel's curve on a field across T_c.
    for (base, heat) in [
        (250.0, SpecificHeat::Constant(CV)),
        (1010.0, SpecificHeat::steel_4340()),
    ] {
        let temps: Vec<f64> = (0..61).map(|i| base + (i * 13 % 61) as f64).collect();
        let run = |threads: usize| {
            rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap()
                .install(|| {
                    let (shape, geometry) = (ShapeFunction::QuadraticBSpline, Geometry::Cartesian);
                    let mut s = insulated_block_with(shape, geometry, &temps, heat.clone());
                    let dt = s.stable_dt().unwrap();
                    for _ in 0..5 {
                        s.advance(dt).unwrap();
                    }
                    s.particles().temperature.clone()
                })
        };
        assert_eq!(run(1), run(3), "{heat:?}");
    }
}

#[test]
fn bad_options_are_refused() {
    let level = Level::new([0.0; 3], [1.0, 1.0, 0.125], [8, 8, 1], [1, 1, 1], 0).unwrap();
    let ps = particles_in(
        &level,
        [0.25, 0.25, 0.0],
        [0.75, 0.75, 0.125],
        2,
        Geometry::Cartesian,
    );
    let s = MpmSolver::new(level, vec![solid()], ps, MpmOptions::default()).unwrap();
    for (heat, option) in [
        (
            HeatConduction {
                conductivity: vec![-1.0],
                specific_heat: vec![Some(SpecificHeat::Constant(1.0))],
            },
            "heat_conduction.conductivity",
        ),
        (
            HeatConduction {
                conductivity: vec![1.0, 1.0],
                specific_heat: vec![],
            },
            "heat_conduction.conductivity",
        ),
        (
            HeatConduction {
                conductivity: vec![1.0],
                specific_heat: vec![Some(SpecificHeat::Constant(0.0))],
            },
            "heat_conduction.specific_heat",
        ),
        // A hypoelastic solid has no specific heat of its own.
        (
            HeatConduction {
                conductivity: vec![1.0],
                specific_heat: vec![],
            },
            "heat_conduction.specific_heat",
        ),
    ] {
        match s.clone().with_heat_conduction(heat) {
            Err(crate::MpmSetupError::Option { option: o, .. }) => assert_eq!(o, option),
            other => panic!("{other:?}"),
        }
    }
}

/// Σ m c_v T², J·K.
fn heat_square(s: &MpmSolver) -> f64 {
    let ps = s.particles();
    ps.mass
        .iter()
        .zip(&ps.temperature)
        .map(|(m, t)| m * CV * t * t)
        .sum()
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(24))]

    /// For a random temperature field in an insulated block, one step at
    /// the diffusive limit keeps Σ m c_v T to round-off and does not raise
    /// Σ m c_v T² (the discrete form of the second law: the particle
    /// update is −Δt W⁻¹ Sᵀ K S T, self-adjoint and non-positive in the
    /// heat-capacity inner product W = diag(m_p c_p), with S the
    /// particle-to-node average and K the stiffness Σ_p V_p k ∇N ∇N, so
    /// the variance of T about its conserved mean falls while Δt is below
    /// twice the inverse of its largest eigenvalue). A strict maximum
    /// principle for the particles does not hold for this update (the
    /// particle takes the interpolated nodal rate, not the nodal value):
    /// overshoots of about 10⁻⁹ of the temperature range were seen, which
    /// is why the contract is the quadratic one.
    #[test]
    fn one_stable_step_conserves_heat_and_dissipates_its_variance(
        temps in prop::collection::vec(200.0f64..800.0, 8..40),
        shape in prop::sample::select(SHAPES.to_vec()),
        axisymmetric in any::<bool>(),
    ) {
        let geometry = if axisymmetric { Geometry::Axisymmetric } else { Geometry::Cartesian };
        let mut s = insulated_block(shape, geometry, &temps);
        let e0 = total_heat(&s);
        let q0 = heat_square(&s);
        let dt = s.stable_dt().unwrap();
        s.advance(dt).unwrap();
        let rel = (total_heat(&s) - e0).abs() / e0;
        prop_assert!(rel < 1e-14, "relative change {rel:e}");
        let q1 = heat_square(&s);
        prop_assert!(q1 <= q0 * (1.0 + 1e-14), "Σ m c T² rose from {q0} to {q1}");
    }

    /// The same contract's first half through a specific heat that follows
    /// the temperature: a random field on both sides of the 4340 steel's
    /// Curie point keeps Σ m H(T) over one stable step.
    #[test]
    fn one_stable_step_keeps_the_heat_of_a_curve(
        temps in prop::collection::vec(600.0f64..1400.0, 8..40),
        shape in prop::sample::select(SHAPES.to_vec()),
        axisymmetric in any::<bool>(),
    ) {
        let geometry = if axisymmetric { Geometry::Axisymmetric } else { Geometry::Cartesian };
        let curve = SpecificHeat::steel_4340();
        let mut s = insulated_block_with(shape, geometry, &temps, curve.clone());
        let e0 = total_enthalpy(&s, &curve);
        let dt = s.stable_dt().unwrap();
        s.advance(dt).unwrap();
        let rel = (total_enthalpy(&s, &curve) - e0).abs() / e0;
        prop_assert!(rel < 1e-14, "relative change {rel:e}");
    }
}

/// One step at 0.9 of the diffusive limit of a bar at 1100 K with one
/// particle at T_c − 1 µK (the 4340 steel's c_v(T), linear shape
/// functions, 16 particles): the hottest particle after the step, and the
/// cold one's temperature. The interpolated-increment update overshoots
/// the neighbours' 1100 K even for a constant c_v (no strict maximum
/// principle, above); a weight of c_v(T_p) near T_c (10⁵ J/(kg·K) and
/// more) let the cold particle take nearly all of its nodes' heat and
/// pass them, at 1123.2 K. With the weight smoothed over T_c ± 1 K it
/// stays below the constant c_v's hottest (c_v(1100 K) = 638.6 J/(kg·K)):
/// measured 1107.19 K against 1110.13 K.
#[test]
fn a_particle_at_the_curie_point_does_not_take_its_neighbours_heat_and_pass_them() {
    let level = Level::new([0.0; 3], [0.5, 0.0625, 0.0625], [8, 1, 1], [1, 1, 1], 0).unwrap();
    let hottest = |heat: SpecificHeat| {
        let mut ps = particles_in(
            &level,
            [0.0; 3],
            [0.5, 0.0625, 0.0625],
            2,
            Geometry::Cartesian,
        );
        let mid = ps.len() / 2;
        for (p, t) in ps.temperature.iter_mut().enumerate() {
            *t = if p == mid { 1040.0 - 1e-6 } else { 1100.0 };
        }
        let mut s = MpmSolver::new(level.clone(), vec![solid()], ps, MpmOptions::default())
            .unwrap()
            .with_heat_conduction(HeatConduction {
                conductivity: vec![K],
                specific_heat: vec![Some(heat)],
            })
            .unwrap();
        let alpha = max_diffusivity(s.particles(), s.thermal_properties()).unwrap();
        s.advance(diffusive_time_step(alpha, &level.geometry, 0.9))
            .unwrap();
        let t = &s.particles().temperature;
        (t.iter().copied().fold(f64::MIN, f64::max), t[mid])
    };
    let (curve, cold) = hottest(SpecificHeat::steel_4340());
    let (constant, _) = hottest(SpecificHeat::Constant(638.6));
    assert!(curve <= constant, "{curve} K vs {constant} K");
    assert!(cold > 1060.0 && cold < 1070.0, "{cold}");
    assert!((constant - 1110.125).abs() < 1e-3, "{constant}");
}
