use super::*;
use crate::lattice::{BodySpec, Dimension};
use crate::material::{Proportional, ProportionalKind};
use crate::strength::StretchSpread;
use brisance_core::Solver;
use brisance_grid::Shape;
use brisance_reaction::DetonationPoint;

fn steel(kind: ProportionalKind, critical_stretch: f64) -> PdMaterial {
    PdMaterial::Proportional(Proportional {
        density: 7850.0,
        sound_speed: 3212.0,
        yield_strength: f64::INFINITY,
        critical_stretch,
        kind,
        damage_stretch_coefficient: 0.0,
        minimum_stretch_coefficient: 0.0,
        spread: None,
    })
}

/// A free bar along x of `n` spacings, `m` × `m` nodes across (3D) or a 1D
/// bar.
fn bar(dimension: Dimension, n: usize, m: usize, h: f64) -> PdSolver {
    let len = n as f64 * h;
    let half = m as f64 * h / 2.0;
    let shape = match dimension {
        Dimension::One => Shape::Box {
            min: [0.0, -h, -h],
            max: [len, h, h],
        },
        Dimension::Three => Shape::Box {
            min: [0.0, -half, -half],
            max: [len, half, half],
        },
    };
    PdSolver::new(PdSetup {
        options: PdOptions {
            spacing: h,
            origin: match dimension {
                Dimension::One => [0.0; 3],
                Dimension::Three => [0.0, -half, -half],
            },
            dimension,
            cross_section: 1.0e-6,
            contact: None,
            ..PdOptions::default()
        },
        materials: vec![steel(ProportionalKind::MicroElastic, f64::INFINITY)],
        bodies: vec![BodySpec {
            shape,
            material: 0,
            velocity: [0.0; 3],
        }],
        boundaries: vec![],
        detonation: None,
    })
    .unwrap()
}

/// V-PD-WAVE: first free–free mode of a bar started with v = v₀cos(πx/L);
/// returns (measured bar speed 2L/T, √(E/ρ), largest relative energy
/// excursion) over `periods` periods.
fn free_vibration(mut s: PdSolver, len: f64, periods: f64) -> (f64, f64, f64) {
    let v0 = 1.0e-2;
    let k = std::f64::consts::PI / len;
    s.set_velocities(|x| [v0 * (k * x[0]).cos(), 0.0, 0.0]);
    let c_bar = (1.5f64).sqrt() * 3212.0;
    let period = 2.0 * len / c_bar;
    let modal = |s: &PdSolver| {
        let (mut num, mut den) = (0.0, 0.0);
        for i in 0..s.node_count() {
            let w = s.mass(i) * (k * s.reference()[i][0]).cos();
            num += w * s.velocities()[i][0];
            den += w * (k * s.reference()[i][0]).cos();
        }
        num / den
    };
    let e0 = s.conservation_totals().energy;
    let mut drift: f64 = 0.0;
    let mut crossings = Vec::new();
    let mut last = (s.time(), modal(&s));
    while s.time() < periods * period {
        let dt = s.stable_dt().unwrap();
        s.advance(dt).unwrap();
        let q = modal(&s);
        if last.1 > 0.0 && q <= 0.0 || last.1 < 0.0 && q >= 0.0 {
            crossings.push(last.0 + (s.time() - last.0) * last.1 / (last.1 - q));
        }
        last = (s.time(), q);
        if s.steps.is_multiple_of(20) {
            let e = s.conservation_totals().energy;
            drift = drift.max((e - e0).abs() / e0);
        }
    }
    let n = crossings.len();
    assert!(n >= 3, "{crossings:?}");
    let t = 2.0 * (crossings[n - 1] - crossings[0]) / (n - 1) as f64;
    (2.0 * len / t, c_bar, drift)
}

#[test]
fn v_pd_wave_1d_bar_speed_within_two_percent_and_energy_drift_below_one_percent() {
    let h = 1.0e-3;
    let (c, c_ref, drift) = free_vibration(bar(Dimension::One, 200, 1, h), 200.0 * h, 3.0);
    let err = (c - c_ref).abs() / c_ref;
    eprintln!(
        "1D: c = {c:.2} m/s vs {c_ref:.2} ({:.3} %), drift {:.2e}",
        100.0 * err,
        drift
    );
    assert!(err < 0.02, "c = {c} vs {c_ref}");
    assert!(drift < 0.01, "energy drift {drift}");
}

#[test]
fn v_pd_wave_3d_bar_speed_within_two_percent_and_energy_drift_below_one_percent() {
    let h = 1.0e-3;
    let (c, c_ref, drift) = free_vibration(bar(Dimension::Three, 60, 10, h), 60.0 * h, 2.0);
    let err = (c - c_ref).abs() / c_ref;
    eprintln!(
        "3D: c = {c:.2} m/s vs {c_ref:.2} ({:.3} %), drift {:.2e}",
        100.0 * err,
        drift
    );
    assert!(err < 0.02, "c = {c} vs {c_ref}");
    assert!(drift < 0.01, "energy drift {drift}");
}

/// The larger V-PD-WAVE 3D case: 90 spacings long, 14 nodes across.
#[test]
#[ignore]
fn v_pd_wave_3d_thick_bar_speed_within_two_percent() {
    let h = 1.0e-3;
    let (c, c_ref, drift) = free_vibration(bar(Dimension::Three, 90, 14, h), 90.0 * h, 2.0);
    let err = (c - c_ref).abs() / c_ref;
    eprintln!(
        "3D thick: c = {c:.2} m/s vs {c_ref:.2} ({:.3} %), drift {:.2e}",
        100.0 * err,
        drift
    );
    assert!(err < 0.02, "c = {c} vs {c_ref}");
    assert!(drift < 0.01, "energy drift {drift}");
}

fn tnt_gas() -> PdMaterial {
    let (isentrope, cj) =
        brisance_reaction::ProductsIsentrope::from_jwl(&brisance_eos::Jwl::tnt()).unwrap();
    PdMaterial::Gas(crate::material::Gas {
        density: 1630.0,
        detonation_velocity: cj.detonation_velocity,
        isentrope,
        reactant: None,
    })
}

/// A micro-plastic block that can break, with a swirl of velocities.
fn block(nx: usize, amplitude: f64, critical_stretch: f64) -> PdSolver {
    let h = 1.0e-3;
    let mut s = PdSolver::new(PdSetup {
        options: PdOptions {
            spacing: h,
            ..PdOptions::default()
        },
        materials: vec![PdMaterial::Proportional(Proportional {
            density: 7850.0,
            sound_speed: 3212.0,
            yield_strength: 750.0e6,
            critical_stretch,
            kind: ProportionalKind::MicroPlastic,
            damage_stretch_coefficient: 0.5,
            minimum_stretch_coefficient: 0.25,
            spread: None,
        })],
        bodies: vec![box_body(
            [0.0; 3],
            [nx as f64 * h, 0.8 * nx as f64 * h, 0.6 * nx as f64 * h],
            0,
        )],
        boundaries: vec![],
        detonation: None,
    })
    .unwrap();
    s.set_velocities(|x| {
        let a = (x[0] * 3.1e3).sin() * (x[1] * 1.7e3).cos();
        [
            amplitude * a,
            amplitude * (x[2] * 2.3e3).sin(),
            -amplitude * a * a,
        ]
    });
    s
}

/// The last finite detonation time of the run's nodes, s (0 with none).
fn last_detonation(s: &PdSolver) -> f64 {
    s.detonation_times()
        .iter()
        .cloned()
        .filter(|t| t.is_finite())
        .fold(0.0, f64::max)
}

fn momentum_scale(s: &PdSolver) -> f64 {
    (0..s.node_count())
        .map(|i| {
            let v = s.velocities()[i];
            s.mass(i) * (v[0].abs() + v[1].abs() + v[2].abs())
        })
        .sum()
}

proptest::proptest! {
    #![proptest_config(proptest::prelude::ProptestConfig::with_cases(8))]
    /// The momentum of an isolated body is conserved to round-off, through
    /// yield, bond failure and contact between the pieces.
    #[test]
    fn momentum_of_an_isolated_body_is_conserved(amplitude in 10.0f64..400.0, sc in 0.002f64..0.05) {
        let mut s = block(6, amplitude, sc);
        let p0 = s.conservation_totals().momentum;
        let scale = momentum_scale(&s);
        for _ in 0..40 {
            let dt = s.stable_dt().unwrap();
            s.advance(dt).unwrap();
        }
        let p1 = s.conservation_totals().momentum;
        for d in 0..3 {
            proptest::prop_assert!((p1[d] - p0[d]).abs() <= 1e-12 * scale, "{p0:?} → {p1:?}");
        }
    }
}

#[test]
fn bonds_break_and_damage_is_the_broken_fraction() {
    let mut s = block(6, 300.0, 0.002);
    for _ in 0..60 {
        let dt = s.stable_dt().unwrap();
        s.advance(dt).unwrap();
    }
    let mut broken_total = 0;
    for i in 0..s.node_count() {
        let row = s.families().row(i);
        let broken = row.clone().filter(|&k| !s.bond_intact(k)).count();
        broken_total += broken;
        let want = broken as f64 / row.len() as f64;
        assert!((s.damage(i) - want).abs() < 1e-15);
    }
    assert!(broken_total > 0, "the block was meant to fail");
}

#[test]
fn results_are_the_same_bits_on_one_and_two_threads() {
    let run = |threads: usize| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap()
            .install(|| {
                let mut s = block(12, 200.0, 0.004);
                for _ in 0..20 {
                    let dt = s.stable_dt().unwrap();
                    s.advance(dt).unwrap();
                }
                (
                    s.state.clone(),
                    s.velocity.clone(),
                    s.factor.clone(),
                    s.plastic.clone(),
                    s.dissipated_energy().to_bits(),
                )
            })
    };
    let (a, b) = (run(1), run(2));
    assert!(a.0.len() > 600);
    let bits = |v: &Vec<[f64; 4]>| v.iter().flatten().map(|x| x.to_bits()).collect::<Vec<_>>();
    assert_eq!(bits(&a.0), bits(&b.0));
    assert_eq!(a.1, b.1);
    assert_eq!(a.2, b.2);
    assert_eq!(a.3, b.3);
    assert_eq!(a.4, b.4);
}

#[test]
fn restore_of_a_saved_state_continues_bit_identically() {
    let mut s = block(6, 200.0, 0.004);
    let step = |s: &mut PdSolver, n: usize| {
        for _ in 0..n {
            let dt = s.stable_dt().unwrap();
            s.advance(dt).unwrap();
        }
    };
    step(&mut s, 10);
    let saved = s.save_state().unwrap();
    step(&mut s, 10);
    let mut r = block(6, 0.0, 0.004);
    r.restore_state(&saved).unwrap();
    step(&mut r, 10);
    assert_eq!(r.time(), s.time());
    assert_eq!(r.velocity, s.velocity);
    assert_eq!(r.factor, s.factor);
    let mut other = block(8, 0.0, 0.004);
    assert!(other.restore_state(&saved).is_err());
}

/// A steel box of `cells` spacings (h = 1 mm) under body force `b`,
/// started at `velocity`, with the given critical stretch and boundaries.
fn steel_box(
    cells: [f64; 3],
    b: [f64; 3],
    critical_stretch: f64,
    velocity: [f64; 3],
    boundaries: Vec<PdBoundary>,
) -> PdSolver {
    let h = 1.0e-3;
    PdSolver::new(PdSetup {
        options: PdOptions {
            spacing: h,
            body_force: b,
            ..PdOptions::default()
        },
        materials: vec![steel(ProportionalKind::MicroElastic, critical_stretch)],
        bodies: vec![BodySpec {
            shape: Shape::Box {
                min: [0.0; 3],
                max: cells.map(|c| c * h),
            },
            material: 0,
            velocity,
        }],
        boundaries,
        detonation: None,
    })
    .unwrap()
}

/// A free micro-elastic block (4 × 3 × 3 nodes, contact on) under a
/// uniform body force b (eq 9): every node gets the same acceleration b/ρ,
/// so the displacements stay equal to the bit, no bond is stretched and
/// the velocity is (b/ρ) t and the displacement ½ (b/ρ) t² (velocity
/// Verlet is exact for a constant acceleration), to round-off.
#[test]
fn a_free_block_under_a_body_force_accelerates_at_b_over_rho_unstretched() {
    let b = [2.0e6, -1.0e6, 0.5e6];
    let rho = 7850.0;
    let mut s = steel_box([4.0, 3.0, 3.0], b, 0.01, [0.0; 3], vec![]);
    assert_eq!(s.node_count(), 36);
    for _ in 0..10 {
        let dt = s.stable_dt().unwrap();
        s.advance(dt).unwrap();
    }
    let t = s.time();
    let (v0, u0) = (s.velocities()[0], s.displacement(0));
    for d in 0..3 {
        let a = b[d] / rho;
        assert!((v0[d] - a * t).abs() <= 1e-13 * (a * t).abs(), "{v0:?}");
        let u = 0.5 * a * t * t;
        assert!((u0[d] - u).abs() <= 1e-12 * u.abs(), "{u0:?} vs {u}");
    }
    for i in 0..s.node_count() {
        assert_eq!(s.velocities()[i], v0, "node {i}");
        assert_eq!(s.displacement(i), u0, "node {i}");
        // Unstretched bonds: no bond or contact force, only b.
        assert_eq!(s.bond_out[i].force, [0.0; 3], "node {i}");
        assert_eq!(s.bond_out[i].min_stretch, 0.0, "node {i}");
        assert_eq!(s.force_density(i), b, "node {i}");
        assert_eq!(s.damage(i), 0.0);
    }
}

/// An 8 × 3 × 3 steel bar thrown at (3, −2, 5) m/s and pulled by a body
/// force, its first two node planes (x < 2h) fixed (velocity 0): the fixed
/// nodes are at rest from the start and stay exactly at their reference
/// positions at every step, while the rest of the bar moves.
#[test]
fn fixed_nodes_stay_exactly_at_their_reference_positions() {
    let h = 1.0e-3;
    let mut s = steel_box(
        [8.0, 3.0, 3.0],
        [1.0e8, 2.0e8, 0.0],
        f64::INFINITY,
        [3.0, -2.0, 5.0],
        vec![PdBoundary {
            region: Shape::Box {
                min: [-h, -h, -h],
                max: [2.0 * h, 4.0 * h, 4.0 * h],
            },
            velocity: [Some(0.0); 3],
        }],
    );
    let fixed: Vec<usize> = (0..s.node_count())
        .filter(|&i| s.reference()[i][0] < 2.0 * h)
        .collect();
    assert_eq!(fixed.len(), 18);
    for &i in &fixed {
        assert_eq!(s.velocities()[i], [0.0; 3]);
    }
    for _ in 0..20 {
        let dt = s.stable_dt().unwrap();
        s.advance(dt).unwrap();
        for &i in &fixed {
            assert_eq!(s.displacement(i), [0.0; 3], "node {i}");
            assert_eq!(s.velocities()[i], [0.0; 3], "node {i}");
            let x = s.reference()[i];
            assert_eq!(s.current_position(i), [x[0], x[1], x[2]]);
        }
    }
    // The free end (x = 7.5h) has moved in every direction.
    for i in (0..s.node_count()).filter(|&i| s.reference()[i][0] > 7.0 * h) {
        let u = s.displacement(i);
        assert!(u.iter().all(|&c| c.abs() > 1.0e-7), "node {i}: {u:?}");
    }
}

/// A prescribed velocity component is imposed exactly and the others stay
/// free: the last two node planes of a bar fixed at its first two move at
/// v_x = 2.5 m/s (velocity to the bit after every step, u_x = v_x t to
/// round-off), while a body force along y moves them in y.
#[test]
fn a_prescribed_velocity_component_is_imposed_exactly() {
    let h = 1.0e-3;
    let vx = 2.5;
    let mut s = steel_box(
        [8.0, 3.0, 3.0],
        [0.0, 1.0e8, 0.0],
        f64::INFINITY,
        [0.0; 3],
        vec![
            PdBoundary {
                region: Shape::Box {
                    min: [-h, -h, -h],
                    max: [2.0 * h, 4.0 * h, 4.0 * h],
                },
                velocity: [Some(0.0); 3],
            },
            PdBoundary {
                region: Shape::Box {
                    min: [6.0 * h, -h, -h],
                    max: [9.0 * h, 4.0 * h, 4.0 * h],
                },
                velocity: [Some(vx), None, None],
            },
        ],
    );
    let driven: Vec<usize> = (0..s.node_count())
        .filter(|&i| s.reference()[i][0] > 6.0 * h)
        .collect();
    assert_eq!(driven.len(), 18);
    for _ in 0..20 {
        let dt = s.stable_dt().unwrap();
        s.advance(dt).unwrap();
        let t = s.time();
        for &i in &driven {
            assert_eq!(s.velocities()[i][0], vx, "node {i}");
            let u = s.displacement(i)[0];
            assert!(
                (u - vx * t).abs() <= 1e-13 * vx * t,
                "node {i}: {u} vs {}",
                vx * t
            );
        }
    }
    // y and z are free: the bar's lateral contraction under the pull and
    // the body force along y move the driven nodes (a free node would
    // move by ½ (b/ρ) t² = 5.3e-8 m in y).
    let mean_y = driven.iter().map(|&i| s.displacement(i)[1]).sum::<f64>() / 18.0;
    eprintln!("mean y displacement of the driven nodes {mean_y:e} m");
    assert!(mean_y > 1.0e-8, "{mean_y}");
    for &i in &driven {
        let v = s.velocities()[i];
        assert!(v[1] != 0.0, "node {i}: {v:?}");
    }
}

/// A 1D steel bar of five nodes (x = 0.5h … 4.5h, δ = 3h) with s_c0 =
/// 0.05, α_D = 0.5, α_min = 0.25; the bond 2–4 is broken and node 3 moved
/// by −0.01 h, so the bonds 2–3, 1–3 and 0–3 have stretches −0.01,
/// −0.01/2 and −0.01/3, and the bond 3–4 +0.01. The node value
/// s_c = s_c0 (1 + α_D φ) − α_min min(s_min, 0) (`update_node_scalars`;
/// seed 004 footnote c), s_min the smallest stretch of the node's intact
/// bonds, is
/// * node 0 (bonds to 1, 2, 3; φ = 0, s_min = −0.01/3):
///   0.05 + 0.25 · 0.01/3 = 0.0508333…;
/// * node 1 (bonds to 0, 2, 3, 4; φ = 0, s_min = −0.005): 0.05125;
/// * node 2 (bonds to 0, 1, 3, 4; φ = 1/4, s_min = −0.01):
///   0.05 · 1.125 + 0.25 · 0.01 = 0.05875;
/// * node 3 (bonds to 0, 1, 2, 4; φ = 0, s_min = −0.01): 0.0525;
/// * node 4 (bonds to 1, 2, 3; φ = 1/3, s_min = 0: its stretched bond
///   does not lower it): 0.05 (1 + 0.5/3) = 0.0583333….
///
/// Stretches are carried in f32, hence the 1e-8 tolerance.
fn bar_with_a_broken_and_a_compressed_bond(spread: Option<StretchSpread>) -> PdSolver {
    let h = 1.0e-3;
    let mut s = PdSolver::new(PdSetup {
        options: PdOptions {
            spacing: h,
            dimension: Dimension::One,
            cross_section: 1.0e-6,
            contact: None,
            ..PdOptions::default()
        },
        materials: vec![PdMaterial::Proportional(Proportional {
            density: 7850.0,
            sound_speed: 3212.0,
            yield_strength: f64::INFINITY,
            critical_stretch: 0.05,
            kind: ProportionalKind::MicroElastic,
            damage_stretch_coefficient: 0.5,
            minimum_stretch_coefficient: 0.25,
            spread,
        })],
        bodies: vec![box_body([0.0, -h, -h], [5.0 * h, h, h], 0)],
        boundaries: vec![],
        detonation: None,
    })
    .unwrap();
    assert_eq!(s.node_count(), 5);
    let rows: Vec<usize> = (0..5).map(|i| s.families().row(i).len()).collect();
    assert_eq!(rows, [3, 4, 4, 4, 3]);
    for (i, j) in [(2, 4), (4, 2)] {
        let k = s.families().find(i, j).unwrap();
        s.factor[k] = 0.0;
    }
    s.state[3][0] = -0.01 * h;
    // The force pass counts the intact bonds and the smallest stretch; the
    // next step's node pass turns them into s_c.
    s.compute_forces();
    s.update_node_scalars();
    s
}

#[test]
fn the_effective_critical_stretch_by_hand() {
    let s = bar_with_a_broken_and_a_compressed_bond(None);
    let want: [f64; 5] = [
        0.05 + 0.25 * 0.01 / 3.0,
        0.05 + 0.25 * 0.005,
        0.05 * (1.0 + 0.5 * 0.25) + 0.25 * 0.01,
        0.05 + 0.25 * 0.01,
        0.05 * (1.0 + 0.5 / 3.0),
    ];
    assert!((want[2] - 0.05875).abs() < 1e-15);
    for (i, w) in want.iter().enumerate() {
        let sc = s.state[i][3];
        assert!((sc - w).abs() < 1e-8, "node {i}: s_c = {sc}, by hand {w}");
    }
}

/// The same bar with a spread critical stretch (`strength.rs`; m = 4,
/// grains of 1.5 mm, so the five nodes 1 mm apart sit in a few grains of
/// different strength): each node's s_c0 is 0.05 times the factor of the
/// grain field at its position, and the damage and compression terms
/// act on that s_c0 as on the plain one. The bond law's first test is the
/// weakest node's s_c0, so no node's own value is cut off by it.
#[test]
fn a_spread_critical_stretch_scales_each_nodes_value() {
    let spread = StretchSpread {
        weibull_modulus: 4.0,
        grain_size: 1.5e-3,
        seed: 3,
    };
    let s = bar_with_a_broken_and_a_compressed_bond(Some(spread));
    let f: Vec<f64> = (0..5)
        .map(|i| {
            let r = s.reference[i];
            spread.factor_at([r[0], r[1], r[2]])
        })
        .collect();
    assert_eq!(s.strength, f);
    // The field varies over the bar (else the test proves nothing).
    assert!(f.iter().any(|&v| v != f[0]), "{f:?}");
    let want: [f64; 5] = [
        0.05 * f[0] + 0.25 * 0.01 / 3.0,
        0.05 * f[1] + 0.25 * 0.005,
        0.05 * f[2] * (1.0 + 0.5 * 0.25) + 0.25 * 0.01,
        0.05 * f[3] + 0.25 * 0.01,
        0.05 * f[4] * (1.0 + 0.5 / 3.0),
    ];
    for (i, w) in want.iter().enumerate() {
        let sc = s.state[i][3];
        assert!((sc - w).abs() < 1e-8, "node {i}: s_c = {sc}, by hand {w}");
    }
    let weakest = f.iter().copied().fold(f64::INFINITY, f64::min);
    match s.laws[0] {
        BondLaw::Solid {
            critical_stretch, ..
        } => assert_eq!(critical_stretch, 0.05 * weakest),
        BondLaw::Gas => unreachable!(),
    }
    // Without a spread the field is not stored.
    assert!(bar_with_a_broken_and_a_compressed_bond(None)
        .strength
        .is_empty());
}

/// A bond of the spread bar breaks at the weaker of its two nodes' s_c:
/// stretch the bond 3–4 (both ends intact, not compressed) between the
/// two values and only the bond of the weaker node's value goes.
#[test]
fn a_bond_breaks_at_its_weaker_nodes_critical_stretch() {
    let spread = StretchSpread {
        weibull_modulus: 4.0,
        grain_size: 1.5e-3,
        seed: 3,
    };
    let mut s = bar_with_a_broken_and_a_compressed_bond(Some(spread));
    let h = 1.0e-3;
    // Release node 3 and pull node 4 out to a stretch halfway between the
    // s_c of nodes 3 and 4.
    s.state[3][0] = 0.0;
    s.compute_forces();
    s.update_node_scalars();
    let (a, b) = (s.state[3][3], s.state[4][3]);
    let lo = a.min(b);
    assert!(
        (a - b).abs() > 1e-3 * lo,
        "the two nodes' values must differ: {a}, {b}"
    );
    let stretch = 0.5 * (a + b);
    s.state[4][0] = stretch * h;
    s.compute_forces();
    let k = s.families().find(3, 4).unwrap();
    assert_eq!(
        s.factor[k], 0.0,
        "s = {stretch}, s_c(3) = {a}, s_c(4) = {b}"
    );
    // Below the weaker value the bond holds.
    let mut t = bar_with_a_broken_and_a_compressed_bond(Some(spread));
    t.state[3][0] = 0.0;
    t.compute_forces();
    t.update_node_scalars();
    t.state[4][0] = 0.9 * lo * h;
    t.compute_forces();
    assert_ne!(t.factor[t.families().find(3, 4).unwrap()], 0.0);
}

/// The damage written with the nodes: the particle output carries a
/// `damage` field, one value per node, equal to the broken fraction by
/// hand (the bar above: 1 of node 2's 4 bonds, 1 of node 4's 3).
#[test]
fn particle_output_carries_the_node_damage() {
    let s = bar_with_a_broken_and_a_compressed_bond(None);
    let data = s.particle_data().unwrap();
    assert_eq!(data.positions.len(), 5);
    let damage = data.field("damage").expect("a `damage` field");
    let want = [0.0, 0.0, 0.25, 0.0, 1.0 / 3.0];
    assert_eq!(damage.len(), 5);
    for i in 0..5 {
        assert!((damage[i] - want[i]).abs() < 1e-15, "{damage:?}");
        assert_eq!(damage[i], s.damage(i));
    }
}

/// Two bodies of two steel nodes each (h = 1 mm, no surface correction),
/// B at x = 4–6 mm thrown at A (0–2 mm) at 100 m/s; short-range forces on
/// or off.
fn two_steel_bodies(contact: bool) -> PdSolver {
    let h = 1.0e-3;
    PdSolver::new(PdSetup {
        options: PdOptions {
            spacing: h,
            surface_correction: false,
            contact: contact.then(ContactOptions::default),
            ..PdOptions::default()
        },
        materials: vec![steel(ProportionalKind::MicroElastic, f64::INFINITY)],
        bodies: vec![
            box_body([0.0; 3], [2.0 * h, h, h], 0),
            BodySpec {
                shape: Shape::Box {
                    min: [4.0 * h, 0.0, 0.0],
                    max: [6.0 * h, h, h],
                },
                material: 0,
                velocity: [-100.0, 0.0, 0.0],
            },
        ],
        boundaries: vec![],
        detonation: None,
    })
    .unwrap()
}

/// Two bodies of two steel nodes each (h = 1 mm, δ = 3h, no surface
/// correction), B thrown at A at 100 m/s. Each node's one bond gives
/// S_bond = c h³/h with c = 18K/(πδ⁴) = 5.728730e21 N/m⁶ (eq 28, K = ρc_b²
/// = 8.0988e10 Pa), so apart the step is 0.8 √(2ρ/S_bond) = 1.324374e-6 s
/// (eq 24). Once the facing nodes are within the contact distance
/// (1.35h, eq 27) their pair adds S_contact = F_SR c h³/δ = 5 S_bond, and
/// the step is 0.8 √(2ρ/(6 S_bond)) = 5.406734e-7 s, √6 shorter. Without
/// contact the same approach leaves the step at 1.324374e-6 s.
fn contact_step(contact: bool) -> (f64, f64, f64) {
    let h = 1.0e-3;
    let mut s = two_steel_bodies(contact);
    assert_eq!(s.node_count(), 4);
    let first = s.stable_dt().unwrap();
    let gap = |s: &PdSolver| s.current_position(2)[0] - s.current_position(1)[0];
    while gap(&s) >= 1.35 * h {
        let dt = s.stable_dt().unwrap();
        s.advance(dt).unwrap();
    }
    // Exactly one pair across the bodies within 1.5 × 1.35h (the reach
    // of the step's contact term): nodes 1 and 2.
    let near = [(0, 2), (0, 3), (1, 2), (1, 3)]
        .iter()
        .filter(|&&(i, j)| distance(s.current_position(i), s.current_position(j)) < 2.025 * h)
        .count();
    assert_eq!(near, 1, "gap {}", gap(&s));
    (first, s.stable_dt().unwrap(), gap(&s))
}

#[test]
fn a_contact_pair_shortens_the_stable_step_to_the_hand_value() {
    let h: f64 = 1.0e-3;
    let rho = 7850.0;
    let c = 18.0 * rho * 3212.0 * 3212.0 / (std::f64::consts::PI * (3.0 * h).powi(4));
    assert!((c / 5.728730e21 - 1.0).abs() < 1e-6);
    let s_bond = c * h * h;
    let apart = 0.8 * (2.0 * rho / s_bond).sqrt();
    let touching = 0.8 * (2.0 * rho / (6.0 * s_bond)).sqrt();
    assert!((apart / 1.324374e-6 - 1.0).abs() < 1e-6);
    assert!((touching / 5.406734e-7 - 1.0).abs() < 1e-6);
    let (first, with, gap) = contact_step(true);
    assert!(gap < 1.35 * h && gap > 0.9 * h, "{gap}");
    assert!((first / apart - 1.0).abs() < 1e-14, "{first} vs {apart}");
    assert!(
        (with / touching - 1.0).abs() < 1e-14,
        "{with} vs {touching}"
    );
    let (first, without, _) = contact_step(false);
    assert!((first / apart - 1.0).abs() < 1e-14, "{first} vs {apart}");
    assert!(
        (without / apart - 1.0).abs() < 1e-14,
        "{without} vs {apart}"
    );
    assert!(with < without);
}

/// The run summary's limit names the node of the smallest step with its
/// position: apart, one of the four nodes (equal to round-off) at the
/// hand step √(2ρ/S_bond) = 1.655467e-6 s before the safety factor (see
/// `contact_step`) and no contact stiffness; in contact, one of the
/// touching pair (nodes 1 and 2) with a contact stiffness.
#[test]
fn the_time_step_limit_names_the_node_that_sets_the_step() {
    let h = 1.0e-3;
    let mut s = two_steel_bodies(true);
    let named = |s: &PdSolver| {
        let limit = s.time_step_limit().unwrap();
        let i: usize = limit
            .strip_prefix("PD node ")
            .and_then(|r| r.split(' ').next())
            .and_then(|n| n.parse().ok())
            .unwrap_or_else(|| panic!("{limit}"));
        let x = s.current_position(i);
        let tail = format!(", at ({:.4}, {:.4}, {:.4}) m", x[0], x[1], x[2]);
        assert!(limit.ends_with(&tail), "{limit}");
        assert_eq!(s.limiting_node().0, i);
        let dt: f64 = limit
            .split(" dt ")
            .nth(1)
            .and_then(|r| r.split(' ').next())
            .and_then(|d| d.parse().ok())
            .unwrap_or_else(|| panic!("{limit}"));
        (i, dt, limit)
    };
    let (_, dt, apart) = named(&s);
    assert!((dt / 1.655467e-6 - 1.0).abs() < 1e-6, "{apart}");
    assert!(apart.contains("contact 0e0"), "{apart}");
    while s.current_position(2)[0] - s.current_position(1)[0] >= 1.35 * h {
        let dt = s.stable_dt().unwrap();
        s.advance(dt).unwrap();
    }
    let (i, _, touching) = named(&s);
    assert!(i == 1 || i == 2, "{touching}");
    assert!(!touching.contains("contact 0e0"), "{touching}");
}

/// The two two-node steel bodies of `contact_step`, B thrown at A at
/// 100 m/s, through their whole collision at a step `1/refine` of the
/// stable one: the largest relative change of the booked total (kinetic +
/// bond + contact energy) and the contact energy at the deepest approach.
fn collision_energy(refine: f64) -> (f64, f64, f64) {
    let h = 1.0e-3;
    let mut s = two_steel_bodies(true);
    let e0 = s.conservation_totals().energy;
    let gap = |s: &PdSolver| s.current_position(2)[0] - s.current_position(1)[0];
    let (mut worst, mut deepest, mut touched) = (0.0_f64, (f64::INFINITY, 0.0), false);
    for _ in 0..200_000 {
        let dt = s.stable_dt().unwrap() / refine;
        s.advance(dt).unwrap();
        let e = s.conservation_totals().energy;
        worst = worst.max((e / e0 - 1.0).abs());
        let g = gap(&s);
        if g < deepest.0 {
            deepest = (g, s.contact_energy());
        }
        touched |= g < 1.35 * h;
        if touched && g > 1.35 * h && s.velocity[2][0] > 0.0 {
            break;
        }
    }
    assert!(touched && gap(&s) > 1.35 * h, "the bodies did not part");
    (e0, worst, deepest.1)
}

/// Counting the contact energy closes the budget of a collision: the
/// booked total's error falls as Δt² (velocity Verlet) while the contact
/// holds a large share of the energy at the deepest approach, the share a
/// budget without it reads as lost. At the stable step itself the stiff
/// contact is crossed in two or three steps and the total changes by
/// tens of per cent (measured: 31 %).
#[test]
fn a_collision_keeps_its_energy_once_the_contact_energy_is_counted() {
    let (e0, coarse, _) = collision_energy(1.0);
    assert!(
        (e0 / (0.5 * 2.0 * 7850.0e-9 * 1.0e4) - 1.0).abs() < 1e-12,
        "{e0}"
    );
    let (_, medium, _) = collision_energy(8.0);
    let (_, fine, stored) = collision_energy(32.0);
    eprintln!(
        "collision energy error at 1, 1/8, 1/32 of the stable step: {coarse:e} {medium:e} {fine:e}"
    );
    assert!(
        stored > 0.2 * e0,
        "contact energy at the deepest approach {stored}"
    );
    assert!(fine < 2e-3, "{fine:e}");
    assert!(fine < medium / 8.0, "{medium:e} -> {fine:e}");
}

/// A node has burnt from its detonation time on, and never without one:
/// program burn's step F = H(t − t_det), asked through the trait.
#[test]
fn a_node_detonates_at_its_time_through_program_burn() {
    use super::detonated;
    assert!(detonated(2.0e-6, 2.0e-6));
    assert!(detonated(3.0e-6, 2.0e-6));
    assert!(!detonated(1.999_999e-6, 2.0e-6));
    assert!(!detonated(1.0, f64::INFINITY));
    assert!(detonated(0.0, 0.0));
}

/// A body filling the box from `min` to `max` with `material`, at rest.
fn box_body(min: [f64; 3], max: [f64; 3], material: u16) -> BodySpec {
    BodySpec {
        shape: Shape::Box { min, max },
        material,
        velocity: [0.0; 3],
    }
}

mod products;
mod wall;

/// [`block`] (bonds yield and break) on `ranks` threads acting as ranks
/// ([`brisance_grid::comm::InProcess`], each with a thread pool of its
/// own), the nodes spread over them ([`PdSolver::distribute`]), 20 steps:
/// each rank's saved state.
fn block_on_thread_ranks(ranks: usize) -> Vec<Vec<u8>> {
    brisance_grid::comm::InProcess::run(ranks, 2, |comm| {
        let mut s = block(12, 200.0, 0.004);
        s.distribute(comm).unwrap();
        // The rank evaluates its share of the nodes.
        assert!(ranks == 1 || s.owned_nodes().len() < s.node_count());
        for _ in 0..20 {
            let dt = s.stable_dt().unwrap();
            s.advance(dt).unwrap();
        }
        s.save_state().unwrap()
    })
}

/// The rank logic of `ranks.rs` without MPI: a block whose bonds break,
/// spread over 2 and 3 ranks, ends with the bits of one rank on every
/// rank (the rows in which bonds broke and the plastic stretches cross).
#[test]
fn nodes_spread_over_ranks_give_the_bits_of_one() {
    let one = block_on_thread_ranks(1).remove(0);
    let mut s = block(12, 200.0, 0.004);
    for _ in 0..20 {
        let dt = s.stable_dt().unwrap();
        s.advance(dt).unwrap();
    }
    assert!(
        s.save_state().unwrap() == one,
        "one thread rank is one rank"
    );
    assert!(
        (0..s.node_count()).any(|i| s.damage(i) > 0.0),
        "bonds were meant to break"
    );
    for ranks in [2, 3] {
        for (r, state) in block_on_thread_ranks(ranks).into_iter().enumerate() {
            assert!(state == one, "rank {r} of {ranks}");
        }
    }
}

/// The micro-plastic [`block`] of 6 spacings thrown apart at `amplitude`
/// through 60 steps of `1/refine` of the stable step (for refine > 1, 60 ×
/// refine steps: the same time): the largest relative change of the
/// booked total energy (kinetic, bond, contact and dissipated), the same
/// without the dissipated energy, and the dissipated energy at the end
/// over the initial total.
fn yielding_block_energy(refine: usize) -> (f64, f64, f64) {
    let mut s = block(6, 300.0, 0.02);
    let e0 = s.conservation_totals().energy;
    let (mut worst, mut unbooked) = (0.0_f64, 0.0_f64);
    let dt = s.stable_dt().unwrap() / refine as f64;
    for _ in 0..60 * refine {
        s.advance(dt).unwrap();
        let e = s.conservation_totals().energy;
        worst = worst.max((e / e0 - 1.0).abs());
        unbooked = unbooked.max(((e - s.dissipated_energy()) / e0 - 1.0).abs());
    }
    assert!(
        (0..s.node_count()).any(|i| s.damage(i) > 0.0),
        "bonds were meant to break"
    );
    (worst, unbooked, s.dissipated_energy() / e0)
}

/// Booking the bonds' plastic work and the energy of breaking bonds closes
/// the budget of a block that yields and breaks: the booked total's error
/// falls with Δt while the dissipated energy is a large share of the
/// initial kinetic energy, which a budget without it reads as lost.
#[test]
fn a_yielding_breaking_block_keeps_its_energy_once_dissipation_is_booked() {
    let (coarse, lost_coarse, share) = yielding_block_energy(1);
    let (fine, lost_fine, _) = yielding_block_energy(4);
    let (finest, _, _) = yielding_block_energy(16);
    eprintln!(
        "booked energy error at 1, 1/4, 1/16 of the step: {coarse:e} {fine:e} {finest:e}; without the dissipated energy {lost_coarse:e} {lost_fine:e}; dissipated share {share}"
    );
    assert!(share > 0.1, "dissipated {share}");
    assert!(lost_fine > 0.5 * share, "{lost_fine}");
    assert!(fine < 0.1 * share, "{fine:e}");
    assert!(
        fine < 0.5 * coarse && finest < 0.5 * fine,
        "{coarse:e} -> {fine:e} -> {finest:e}"
    );
}
