use super::*;
use proptest::prelude::*;

/// The solid kernel forms stretch and force magnitude in f32 (relative
/// precision ~1e-7, see the module doc); hand values are checked to that.
fn close(a: f64, b: f64) -> bool {
    (a - b).abs() <= 4e-7 * b.abs()
}

const SOLID: BondLaw = BondLaw::Solid {
    micromodulus: 3.0,
    yield_stretch: f64::INFINITY,
    plastic: false,
    critical_stretch: f64::INFINITY,
};

/// Two nodes: 0 at the origin with V = 2, 1 at (2, 0, 0) with V = 0.5.
struct Pair {
    reference: Vec<[f64; 4]>,
    state: Vec<[f64; 4]>,
    factor: Vec<f32>,
    plastic: Vec<f32>,
    out: Vec<NodeForce>,
    laws: Vec<BondLaw>,
}

impl Pair {
    fn new(law: BondLaw, xi: [f64; 3]) -> Self {
        Self {
            reference: vec![[0.0, 0.0, 0.0, 2.0], [xi[0], xi[1], xi[2], 0.5]],
            state: vec![[0.0; 4]; 2],
            factor: vec![1.0; 2],
            plastic: vec![0.0; 2],
            out: vec![NodeForce::default(); 2],
            laws: vec![law],
        }
    }

    fn set(&mut self, eta: [f64; 3], scalar: [f64; 2]) -> [[f64; 3]; 2] {
        self.dissipated(eta, scalar);
        [self.out[0].force, self.out[1].force]
    }

    /// One force pass at displacement `eta` of node 1 and node scalars
    /// `scalar` (the pass that also books dissipation, whose forces are
    /// [`bond_forces`]'): the energy each node's row dissipated.
    fn dissipated(&mut self, eta: [f64; 3], scalar: [f64; 2]) -> [f32; 2] {
        self.state[0] = [0.0, 0.0, 0.0, scalar[0]];
        self.state[1] = [eta[0], eta[1], eta[2], scalar[1]];
        let input = ForceInput {
            reference: &self.reference,
            state: &self.state,
            offsets: &[0, 1, 2],
            neighbours: &[1, 0],
            material: &[0, 0],
            laws: &self.laws,
            mirror_walls: false,
        };
        let mut d = [0f32; 2];
        bond_forces_dissipating_in(
            &input,
            0..2,
            &mut self.factor,
            &mut self.plastic,
            &mut self.out,
            &mut d,
        );
        d
    }
}

#[test]
fn elastic_bond_force_is_c_s_v_by_hand() {
    // r = 2, stretched to 2.2: s = 0.1; on node 0: c s V₁ = 3·0.1·0.5 = 0.15
    // towards node 1; on node 1: c s V₀ = 0.6 towards node 0.
    let mut p = Pair::new(SOLID, [2.0, 0.0, 0.0]);
    let f = p.set([0.2, 0.0, 0.0], [1.0, 1.0]);
    assert!(close(f[0][0], 0.15), "{f:?}");
    assert!(close(f[1][0], -0.6), "{f:?}");
    assert_eq!(f[0][1], 0.0);
    assert_eq!(p.out[0].intact, 1);
    assert!(close(p.out[0].min_stretch as f64, 0.1));
}

#[test]
fn micro_elastic_yield_caps_the_force_and_unloads_reversibly() {
    let law = BondLaw::Solid {
        micromodulus: 3.0,
        yield_stretch: 0.05,
        plastic: false,
        critical_stretch: f64::INFINITY,
    };
    let mut p = Pair::new(law, [2.0, 0.0, 0.0]);
    let f = p.set([0.2, 0.0, 0.0], [1.0, 1.0]);
    assert!(close(f[0][0], 3.0 * 0.05 * 0.5), "{f:?}");
    let f = p.set([0.0; 3], [1.0, 1.0]);
    assert_eq!(f[0], [0.0; 3]);
}

#[test]
fn micro_plastic_unloads_on_a_shifted_line() {
    let law = BondLaw::Solid {
        micromodulus: 3.0,
        yield_stretch: 0.05,
        plastic: true,
        critical_stretch: f64::INFINITY,
    };
    let mut p = Pair::new(law, [2.0, 0.0, 0.0]);
    p.set([0.2, 0.0, 0.0], [1.0, 1.0]);
    assert!((p.plastic[0] - 0.05).abs() < 1e-7 && p.plastic[0] == p.plastic[1]);
    // Back to the reference length: s − s_p = −0.05, a compressive force
    // c·0.05·V₁ = 0.075 pushing node 0 away from node 1 (−x).
    let f = p.set([0.0; 3], [1.0, 1.0]);
    assert!(close(f[0][0], -0.075), "{f:?}");
    // Reloading to s = 0.08 stays elastic: force c(0.08 − 0.05)V₁; s − s_p
    // is a difference of f32 stretches, good to a few f32 ulps of 0.08.
    let f = p.set([0.16, 0.0, 0.0], [1.0, 1.0]);
    assert!((f[0][0] / (3.0 * 0.5) - 0.03).abs() < 3e-8, "{f:?}");
}

#[test]
fn a_broken_bond_never_carries_force_again() {
    let law = BondLaw::Solid {
        micromodulus: 3.0,
        yield_stretch: f64::INFINITY,
        plastic: false,
        critical_stretch: 0.08,
    };
    let mut p = Pair::new(law, [2.0, 0.0, 0.0]);
    // Node scalars hold the effective critical stretch: 0.08 and 0.2.
    let f = p.set([0.2, 0.0, 0.0], [0.08, 0.2]);
    assert_eq!(f, [[0.0; 3]; 2]);
    assert_eq!(p.factor, vec![0.0, 0.0]);
    assert_eq!(p.out[0].intact, 0);
    for eta in [[0.0; 3], [-0.5, 0.0, 0.0], [0.01, 0.0, 0.0]] {
        assert_eq!(p.set(eta, [0.08, 0.2]), [[0.0; 3]; 2]);
    }
}

/// Plastic work by hand: the pair (r = 2, V₀ = 2, V₁ = ½, c = 3) stretched
/// to s = 0.1 past s_Y = 0.05 flows by Δs_p = 0.05; the pair dissipates
/// c β r V₀ V₁ s_Y Δs_p = 3·2·1·0.05·0.05 = 0.015, half booked by each
/// node. Unloading elastically dissipates nothing; compressing to
/// s = −0.02 flows back by 0.02 (from s_p = 0.05 to 0.03: s − s_p = −0.05).
#[test]
fn a_yielding_bond_dissipates_its_plastic_work_by_hand() {
    let law = BondLaw::Solid {
        micromodulus: 3.0,
        yield_stretch: 0.05,
        plastic: true,
        critical_stretch: f64::INFINITY,
    };
    let mut p = Pair::new(law, [2.0, 0.0, 0.0]);
    let d = p.dissipated([0.2, 0.0, 0.0], [1.0, 1.0]);
    for v in d {
        assert!(close(v as f64, 0.0075), "{d:?}");
    }
    assert_eq!(p.dissipated([0.16, 0.0, 0.0], [1.0, 1.0]), [0.0; 2]);
    let d = p.dissipated([-0.04, 0.0, 0.0], [1.0, 1.0]);
    for v in d {
        assert!(close(v as f64, 0.5 * 3.0 * 2.0 * 0.05 * 0.02), "{d:?}");
    }
}

/// A bond breaking books what it held: ½ s² below yield, s_Y (|s| − s_Y/2)
/// above it (micro-elastic), ½ (s − s_p)² (micro-plastic); once broken it
/// books nothing more.
#[test]
fn a_breaking_bond_dissipates_the_energy_it_held_by_hand() {
    let pair = 3.0 * 2.0; // c β r V₀ V₁
    for (yield_stretch, plastic, want) in [
        (f64::INFINITY, false, 0.5 * 0.1 * 0.1),
        (0.04, false, 0.04 * (0.1 - 0.02)),
        // The pass flows by 0.06 (s_p 0 → 0.06) and then breaks: the
        // plastic work 0.04·0.06 and ½·0.04².
        (0.04, true, 0.04 * 0.06 + 0.5 * 0.04 * 0.04),
    ] {
        let law = BondLaw::Solid {
            micromodulus: 3.0,
            yield_stretch,
            plastic,
            critical_stretch: 0.08,
        };
        let mut p = Pair::new(law, [2.0, 0.0, 0.0]);
        let d = p.dissipated([0.2, 0.0, 0.0], [0.08, 0.08]);
        assert_eq!(p.factor, vec![0.0, 0.0]);
        for v in d {
            assert!(
                (v as f64 / (0.5 * pair * want) - 1.0).abs() < 1e-6,
                "{d:?} {want}"
            );
        }
        assert_eq!(p.dissipated([0.3, 0.0, 0.0], [0.08, 0.08]), [0.0; 2]);
    }
}

#[test]
fn the_raised_critical_stretch_of_either_node_is_respected() {
    let law = BondLaw::Solid {
        micromodulus: 3.0,
        yield_stretch: f64::INFINITY,
        plastic: false,
        critical_stretch: 0.08,
    };
    let mut p = Pair::new(law, [2.0, 0.0, 0.0]);
    // s = 0.1 exceeds s_c0 but both nodes' effective values are 0.12.
    p.set([0.2, 0.0, 0.0], [0.12, 0.12]);
    assert_eq!(p.factor, vec![1.0, 1.0]);
}

#[test]
fn gas_pair_force_is_the_mean_of_the_endpoint_values_of_eq_19() {
    // r = 2, p = 2.2, coefficients 4 and 2, β = 1, V₁ = 0.5:
    // on node 0: −½(4 + 2)·2·0.5/2.2³ · 2.2 = −0.619835 along x.
    let mut p = Pair::new(BondLaw::Gas, [2.0, 0.0, 0.0]);
    let f = p.set([0.2, 0.0, 0.0], [4.0, 2.0]);
    let want = -3.0 * 2.0 * 0.5 / 2.2f64.powi(3) * 2.2;
    assert!((f[0][0] - want).abs() < 1e-14, "{f:?}");
    // Before detonation of both (coefficients 0) there is no force.
    assert_eq!(p.set([0.2, 0.0, 0.0], [0.0, 0.0]), [[0.0; 3]; 2]);
}

/// A products node (0, coefficient 4) and a solid node (1) in its
/// family, r = 2, p = 2.2, β = 1: with a mirrored wall the pair carries
/// c₀ in full on both sides, −4·2·V/2.2³ · 2.2 on node 0 (V₁ = 0.5) and
/// the opposite per-volume force on node 1 (V₀ = 2), so V₀f₀ + V₁f₁ = 0;
/// without, c₀/2 (`one_sided_gas_reaction` gives node 1's side).
#[test]
fn a_mirrored_wall_pair_carries_the_products_coefficient_in_full_by_hand() {
    let reference = vec![[0.0, 0.0, 0.0, 2.0], [2.0, 0.0, 0.0, 0.5]];
    let state = vec![[0.0, 0.0, 0.0, 4.0], [0.2, 0.0, 0.0, 0.0]];
    let laws = [BondLaw::Gas, SOLID];
    for (mirror, coef) in [(false, 2.0), (true, 4.0)] {
        let input = ForceInput {
            reference: &reference,
            state: &state,
            offsets: &[0, 1, 1],
            neighbours: &[1],
            material: &[0, 1],
            laws: &laws,
            mirror_walls: mirror,
        };
        let f0 = gas_row(0, &input, &[1], &[1.0]).force;
        let want = -coef * 2.0 * 0.5 / 2.2f64.powi(3) * 2.2;
        assert!((f0[0] - want).abs() < 1e-15, "{mirror}: {f0:?}");
        let (f1, k) = one_sided_gas_reaction(1, &reference, &state, &[0], &[0], &[1.0], mirror);
        assert!(
            (2.0 * f0[0] + 0.5 * f1[0]).abs() < 1e-15,
            "{mirror}: {f1:?}"
        );
        // Stiffness Σ c β V_i r/p³ at the pair's carried coefficient.
        assert!(
            (k - coef * 2.0 * 2.0 * 2.0 / 2.2f64.powi(3)).abs() < 1e-14,
            "{k}"
        );
    }
}

/// ΔS_wall by hand: products node 0 at rest, solid node 1 (V = 0.5)
/// moved from 2 to 2.2 along x by v = 1e3 m/s over dt = 2e-4 s (so the
/// pair was 2.0 long before the drift): 0.5 (2/2.2 − 2/2) = −0.0454…; a
/// gas neighbour is not counted, and at dt = 0 nothing changed.
#[test]
fn the_wall_sum_changes_by_the_solid_pairs_stretch_over_the_drift() {
    let reference = vec![
        [0.0, 0.0, 0.0, 2.0],
        [2.0, 0.0, 0.0, 0.5],
        [0.0, 1.0, 0.0, 0.7],
    ];
    let state = vec![[0.0; 4], [0.2, 0.0, 0.0, 0.0], [0.0, 0.3, 0.0, 0.0]];
    let velocity = vec![[0.0; 3], [1.0e3, 0.0, 0.0], [0.0, 1.5e3, 0.0]];
    let laws = [BondLaw::Gas, SOLID];
    let material = [0u16, 1, 0];
    let ds = |dt: f64| {
        wall_sum_change(
            0,
            &reference,
            &state,
            &velocity,
            dt,
            [(1, 1.0), (2, 1.0)],
            &material,
            &laws,
        )
    };
    let want = 0.5 * (2.0 / 2.2 - 1.0);
    assert!(
        (ds(2.0e-4) - want).abs() < 1e-15,
        "{} against {want}",
        ds(2.0e-4)
    );
    let none = ds(0.0);
    assert_eq!(none, 0.0);
}

/// A products slab beside a solid one, every node in every family within
/// the horizon (the mirrored wall's families), displaced and moving: each
/// products node's ΔS_wall over its wall pairs alone
/// ([`crate::family::ForeignBonds`]) has the bits of the scan over its
/// whole row, and the wall pairs are fewer than the row's.
#[test]
fn the_wall_pairs_alone_give_the_whole_rows_wall_sum_to_the_bit() {
    use crate::family::{build_families_where, ForeignBonds};
    let h = 1.0e-3;
    let mut positions = Vec::new();
    for k in 0..4 {
        for j in 0..4 {
            for i in 0..8 {
                positions.push([
                    (i as f64 + 0.5) * h,
                    (j as f64 + 0.5) * h,
                    (k as f64 + 0.5) * h,
                ]);
            }
        }
    }
    let n = positions.len();
    let material: Vec<u16> = positions
        .iter()
        .map(|x| u16::from(x[0] > 5.0 * h))
        .collect();
    let laws = [BondLaw::Gas, SOLID];
    let is_gas = |i: usize| material[i] == 0;
    let families = build_families_where(&positions, 3.0 * h, h, |_, _| true);
    let wall = ForeignBonds::of(&families, is_gas);
    let wobble = |i: usize, s: f64| ((i as f64 * s).sin() * 1.0e-4, (i as f64 * s * 1.7).cos());
    let reference: Vec<[f64; 4]> = positions
        .iter()
        .map(|x| [x[0], x[1], x[2], h * h * h])
        .collect();
    let state: Vec<[f64; 4]> = (0..n)
        .map(|i| [wobble(i, 0.37).0, wobble(i, 0.11).0, wobble(i, 0.23).0, 0.0])
        .collect();
    let velocity: Vec<[f64; 3]> = (0..n)
        .map(|i| {
            [
                1.0e3 * wobble(i, 0.5).1,
                5.0e2 * wobble(i, 0.9).1,
                -2.0e2 * wobble(i, 1.3).1,
            ]
        })
        .collect();
    let factor: Vec<f32> = (0..families.bond_count())
        .map(|k| {
            if k % 7 == 3 {
                0.0
            } else {
                1.0 - (k % 5) as f32 * 0.1
            }
        })
        .collect();
    let mut compared = 0;
    for i in (0..n).filter(|&i| is_gas(i)) {
        let row = families.row(i);
        let pair = |k: usize| (families.neighbours[k], factor[k]);
        let ds = |pairs: Vec<(u32, f32)>| {
            wall_sum_change(
                i, &reference, &state, &velocity, 2.0e-8, pairs, &material, &laws,
            )
        };
        let whole = ds(row.clone().map(pair).collect());
        let pairs = wall.row(i);
        let alone = ds(pairs.iter().map(|&k| pair(k as usize)).collect());
        assert_eq!(whole.to_bits(), alone.to_bits(), "node {i}");
        assert!(pairs.len() < row.len());
        compared += usize::from(whole != 0.0);
    }
    assert!(compared > 0, "no products node has a wall pair");
}

#[test]
fn gas_expansion_is_one_at_rest_and_eight_when_doubled() {
    let reference = vec![
        [0.0, 0.0, 0.0, 1.0],
        [1.0, 0.0, 0.0, 1.0],
        [0.0, 2.0, 0.0, 3.0],
    ];
    let mut state = vec![[0.0; 4]; 3];
    let (x, _, _) = gas_expansion(0, &reference, &state, &[1, 2], &[1.0, 1.0], 4.0);
    assert!((x - 1.0).abs() < 1e-15);
    // Every bond doubled in length: Σ (r/p) V / V = ½, X = 8 (eq 17).
    state[1] = [1.0, 0.0, 0.0, 0.0];
    state[2] = [0.0, 2.0, 0.0, 0.0];
    let (x, _, _) = gas_expansion(0, &reference, &state, &[1, 2], &[1.0, 1.0], 4.0);
    assert!((x - 8.0).abs() < 1e-12, "{x}");
}

fn law_strategy() -> impl Strategy<Value = BondLaw> {
    prop_oneof![
        (0.01f64..0.3, any::<bool>()).prop_map(|(sy, plastic)| BondLaw::Solid {
            micromodulus: 7.0,
            yield_stretch: sy,
            plastic,
            critical_stretch: f64::INFINITY,
        }),
        Just(BondLaw::Gas),
    ]
}

fn vec3(range: f64) -> impl Strategy<Value = [f64; 3]> {
    [-range..range, -range..range, -range..range]
}

proptest! {
    /// Seed 004 eqs 2–4: the pairwise force is odd (f V₀ on node 0 is minus
    /// f V₁ on node 1) and parallel to the deformed bond η + ξ.
    #[test]
    fn pairwise_force_is_odd_and_parallel_to_the_deformed_bond(
        law in law_strategy(),
        xi in vec3(1.0),
        eta in vec3(0.2),
        c0 in 0.1f64..5.0,
        c1 in 0.1f64..5.0,
    ) {
        let r = (xi[0] * xi[0] + xi[1] * xi[1] + xi[2] * xi[2]).sqrt();
        prop_assume!(r > 0.3);
        let mut p = Pair::new(law, xi);
        let f = p.set(eta, [c0, c1]);
        let y = [xi[0] + eta[0], xi[1] + eta[1], xi[2] + eta[2]];
        let scale = f[0].iter().map(|v| v.abs()).fold(0.0, f64::max) + 1e-300;
        for (a, b) in f[0].iter().zip(f[1]) {
            // Node 0 has V = 2, node 1 has V = 0.5: f₀ V₀ = −f₁ V₁.
            prop_assert!((a * 2.0 + b * 0.5).abs() <= 1e-13 * scale * 2.0);
        }
        let cross = [
            f[0][1] * y[2] - f[0][2] * y[1],
            f[0][2] * y[0] - f[0][0] * y[2],
            f[0][0] * y[1] - f[0][1] * y[0],
        ];
        let ny = (y[0] * y[0] + y[1] * y[1] + y[2] * y[2]).sqrt();
        for c in cross {
            prop_assert!(c.abs() <= 1e-13 * scale * ny);
        }
    }

    /// Once a bond breaks, no later deformation gives it force again.
    #[test]
    fn a_bond_that_broke_stays_broken(history in proptest::collection::vec(vec3(0.5), 1..20)) {
        let law = BondLaw::Solid {
            micromodulus: 3.0,
            yield_stretch: 0.02,
            plastic: true,
            critical_stretch: 0.1,
        };
        let mut p = Pair::new(law, [1.0, 0.5, 0.0]);
        let mut broken = false;
        for eta in history {
            let f = p.set(eta, [0.1, 0.1]);
            if broken {
                prop_assert_eq!(f, [[0.0; 3]; 2]);
                prop_assert_eq!(&p.factor, &vec![0.0f32, 0.0]);
            }
            broken = p.factor[0] == 0.0;
            prop_assert_eq!(p.factor[0], p.factor[1]);
        }
    }
}

/// A block with two materials (micro-elastic and micro-plastic) deformed
/// so that bonds yield in tension and compression and some break, with
/// node critical stretches that differ, then unloaded: every instruction
/// set's kernel gives the bits of the portable one (forces, smallest
/// stretch, intact count, factors and plastic stretches), pass after pass.
#[test]
fn every_instruction_set_gives_the_bits_of_the_portable_kernel() {
    let block = crate::cases::BondBenchBlock::new(7, 1.0e-3);
    let n = block.reference.len();
    let laws = [
        BondLaw::Solid {
            micromodulus: 2.0e21,
            yield_stretch: 2.0e-3,
            plastic: false,
            critical_stretch: 8.0e-3,
        },
        BondLaw::Solid {
            micromodulus: 3.0e21,
            yield_stretch: 1.5e-3,
            plastic: true,
            critical_stretch: 6.0e-3,
        },
    ];
    let material: Vec<u16> = (0..n).map(|i| (i % 3 == 0) as u16).collect();
    let field = |x: &[f64; 4], a: f64| {
        let sigma = 6.0e-3 * (1.0 + (x[0] * 1.7e3).sin().abs());
        [
            a * 2e-6 * (x[0] * 2.0e3).sin() * (1.0 + x[1] * 1e3),
            a * 1e-6 * (x[2] * 3.0e3).cos(),
            -a * 5e-7 * x[2] * 1e3 * x[2] * 1e3,
            sigma,
        ]
    };
    let rows: &[(&str, RowsFn)] = &[
        ("dispatched", rows_for_this_cpu()),
        #[cfg(target_arch = "x86_64")]
        ("avx2", |n, i, f, p, o, d| {
            if std::arch::is_x86_feature_detected!("avx2") {
                // SAFETY: checked just above.
                unsafe { rows_serial_avx2(n, i, f, p, o, d) }
            } else {
                rows_serial::<ScalarGather>(n, i, f, p, o, d)
            }
        }),
    ];
    let bits = |v: &[f32]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
    for (name, rows) in rows {
        let mut states = [block.factor.clone(), block.factor.clone()];
        let mut plastic = [
            vec![0f32; block.factor.len()],
            vec![0f32; block.factor.len()],
        ];
        let mut out = [vec![NodeForce::default(); n], vec![NodeForce::default(); n]];
        let mut lost = [vec![0f32; n], vec![0f32; n]];
        let mut broken = 0;
        let mut dissipated = 0.0;
        for amplitude in [0.5, 2.0, 4.0, 1.0, -3.0, 0.0] {
            let state: Vec<[f64; 4]> = block
                .reference
                .iter()
                .map(|x| field(x, amplitude))
                .collect();
            let input = ForceInput {
                reference: &block.reference,
                state: &state,
                offsets: &block.families.offsets,
                neighbours: &block.families.neighbours,
                material: &material,
                laws: &laws,
                mirror_walls: false,
            };
            let [f0, f1] = &mut states;
            let [p0, p1] = &mut plastic;
            let [o0, o1] = &mut out;
            let [d0, d1] = &mut lost;
            rows_serial::<ScalarGather>(0..n, &input, f0, p0, o0, d0);
            rows(0..n, &input, f1, p1, o1, d1);
            assert_eq!(bits(d0), bits(d1), "{name}: dissipated energies");
            dissipated += d0.iter().map(|&d| d as f64).sum::<f64>();
            for (a, b) in o0.iter().zip(o1.iter()) {
                assert_eq!(
                    a.force.map(f64::to_bits),
                    b.force.map(f64::to_bits),
                    "{name}"
                );
                assert_eq!(a.min_stretch.to_bits(), b.min_stretch.to_bits(), "{name}");
                assert_eq!(a.intact, b.intact, "{name}");
            }
            assert_eq!(bits(f0), bits(f1), "{name}: factors");
            assert_eq!(bits(p0), bits(p1), "{name}: plastic stretches");
            broken = f0.iter().filter(|&&w| w == 0.0).count();
        }
        // The history did exercise failure and plastic flow.
        // (11748 of 32710 bonds broken, 9214 yielded.)
        let yielded = plastic[0].iter().filter(|&&p| p != 0.0).count();
        assert!(broken > 100 && broken < block.factor.len() / 2, "{broken}");
        assert!(yielded > 100, "{yielded}");
        assert!(dissipated > 0.0, "{dissipated}");
    }
}

/// The pass over contiguous node ranges (one rank's share each, as a run
/// spread over MPI ranks evaluates them) writes, range by range, the bits
/// of the pass over all nodes, and leaves every entry outside its range
/// as it was: rows are independent of the range they are evaluated in.
#[test]
fn passes_over_node_ranges_give_the_bits_of_the_whole_pass() {
    let block = crate::cases::BondBenchBlock::new(6, 1.0e-3);
    let n = block.reference.len();
    let laws = [BondLaw::Solid {
        micromodulus: 3.0e21,
        yield_stretch: 1.5e-3,
        plastic: true,
        critical_stretch: 6.0e-3,
    }];
    let material = vec![0u16; n];
    let state: Vec<[f64; 4]> = block
        .reference
        .iter()
        .map(|x| {
            [
                4e-6 * (x[0] * 2.0e3).sin(),
                2e-6 * (x[2] * 3.0e3).cos(),
                -1e-6 * x[1] * 1e3,
                6.0e-3,
            ]
        })
        .collect();
    let input = ForceInput {
        reference: &block.reference,
        state: &state,
        offsets: &block.families.offsets,
        neighbours: &block.families.neighbours,
        material: &material,
        laws: &laws,
        mirror_walls: false,
    };
    let bonds = block.factor.len();
    let (mut f0, mut p0) = (block.factor.clone(), vec![0f32; bonds]);
    let mut o0 = vec![NodeForce::default(); n];
    bond_forces(&input, &mut f0, &mut p0, &mut o0);
    assert!(f0.contains(&0.0), "some bonds break");
    assert!(p0.iter().any(|&s| s != 0.0), "some bonds yield");
    let bits = |v: &[f32]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
    let marker = NodeForce {
        force: [7.0; 3],
        min_stretch: 7.0,
        intact: 7,
    };
    let cuts = [0, 1, n / 3, n / 3 + 1, 2 * n / 3, n];
    for range in cuts.windows(2).map(|w| w[0]..w[1]) {
        let (mut f1, mut p1) = (block.factor.clone(), vec![0f32; bonds]);
        let mut o1 = vec![marker; n];
        bond_forces_in(&input, range.clone(), &mut f1, &mut p1, &mut o1);
        let rows = block.families.offsets[range.start] as usize
            ..block.families.offsets[range.end] as usize;
        for i in 0..n {
            let (a, b) = (o0[i], o1[i]);
            if range.contains(&i) {
                assert_eq!(a.force.map(f64::to_bits), b.force.map(f64::to_bits));
                assert_eq!(a.min_stretch.to_bits(), b.min_stretch.to_bits());
                assert_eq!(a.intact, b.intact);
            } else {
                assert_eq!(b.intact, 7, "node {i} outside {range:?} untouched");
            }
        }
        assert_eq!(bits(&f0[rows.clone()]), bits(&f1[rows.clone()]));
        assert_eq!(bits(&p0[rows.clone()]), bits(&p1[rows.clone()]));
        assert_eq!(bits(&f1[..rows.start]), bits(&block.factor[..rows.start]));
        assert_eq!(bits(&f1[rows.end..]), bits(&block.factor[rows.end..]));
    }
}

/// Eq 17's sums and the closing time pair by pair, as the kernel was
/// written before its pairs were grouped in lanes: the oracle the grouped
/// kernel must match bit for bit.
fn gas_expansion_closing_by_pairs(
    i: usize,
    reference: &[[f64; 4]],
    state: &[[f64; 4]],
    velocity: &[[f64; 3]],
    neighbours: &[u32],
    factor: &[f32],
    family_volume: f64,
) -> (f64, f64, f64, f64) {
    let (xi, ui) = (reference[i], state[i]);
    let (mut sum, mut s3, mut s4, mut closing) = (0.0, 0.0, 0.0, f64::INFINITY);
    for (k, &j) in neighbours.iter().enumerate() {
        let j = j as usize;
        let (xj, uj) = (reference[j], state[j]);
        let xi_ = sub3(&xj, &xi);
        let eta = sub3(&uj, &ui);
        let y = [xi_[0] + eta[0], xi_[1] + eta[1], xi_[2] + eta[2]];
        let r = (xi_[0] * xi_[0] + xi_[1] * xi_[1] + xi_[2] * xi_[2]).sqrt();
        let p = (y[0] * y[0] + y[1] * y[1] + y[2] * y[2])
            .sqrt()
            .max(1e-15 * r);
        let bv = factor[k] as f64 * xj[3];
        let q = r / p;
        sum += q * bv;
        s3 += q / (p * p) * bv;
        s4 += q * q / (p * p) * bv;
        if factor[k] != 0.0 {
            let (vi, vj) = (velocity[i], velocity[j]);
            let d = [
                xj[0] - xi[0] + uj[0] - ui[0],
                xj[1] - xi[1] + uj[1] - ui[1],
                xj[2] - xi[2] + uj[2] - ui[2],
            ];
            let approach =
                -(d[0] * (vj[0] - vi[0]) + d[1] * (vj[1] - vi[1]) + d[2] * (vj[2] - vi[2]));
            if approach > 0.0 {
                closing = closing.min((d[0] * d[0] + d[1] * d[1] + d[2] * d[2]) / approach);
            }
        }
    }
    let x = if sum > 0.0 {
        (sum / family_volume).powi(-3)
    } else {
        1.0
    };
    (x, s3, s4, closing)
}

proptest! {
    /// Rows of every length around the lane width (whole groups, a rest,
    /// a rest alone), with broken and partly damaged bonds, displaced and
    /// moving nodes: the grouped kernel, on whatever instruction set this
    /// processor has, gives the pair-by-pair sums and closing time to the
    /// bit, with and without velocities.
    #[test]
    fn grouped_gas_pairs_give_the_bits_of_the_pair_by_pair_sums(
        len in 0usize..27,
        seed in any::<u64>(),
    ) {
        let n = len + 1;
        let mut s = seed | 1;
        let mut rnd = || {
            s = s
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (s >> 11) as f64 / (1u64 << 53) as f64 - 0.5
        };
        let reference: Vec<[f64; 4]> = (0..n)
            .map(|_| [3e-3 * rnd(), 3e-3 * rnd(), 3e-3 * rnd(), 1e-9 * (1.5 + rnd())])
            .collect();
        let state: Vec<[f64; 4]> = (0..n)
            .map(|_| [1e-3 * rnd(), 1e-3 * rnd(), 1e-3 * rnd(), 0.0])
            .collect();
        let velocity: Vec<[f64; 3]> = (0..n)
            .map(|_| [500.0 * rnd(), 500.0 * rnd(), 500.0 * rnd()])
            .collect();
        let neighbours: Vec<u32> = (1..n as u32).collect();
        let factor: Vec<f32> = (0..len)
            .map(|k| match k % 4 {
                0 => 0.0,
                1 => 0.5,
                _ => 1.0,
            })
            .collect();
        let expected = gas_expansion_closing_by_pairs(
            0, &reference, &state, &velocity, &neighbours, &factor, 3e-8,
        );
        let row = GasRow {
            reference: &reference,
            state: &state,
            velocity: Some(&velocity),
            neighbours: &neighbours,
            factor: &factor,
            family_volume: 3e-8,
        };
        let got = gas_expansion_closing(0, &row);
        let bits = |t: (f64, f64, f64, f64)| [t.0, t.1, t.2, t.3].map(f64::to_bits);
        prop_assert_eq!(bits(got), bits(expected));
        let no_velocity = gas_expansion_closing(0, &GasRow { velocity: None, ..row });
        prop_assert_eq!(
            bits(no_velocity),
            bits((expected.0, expected.1, expected.2, f64::INFINITY))
        );
        // The portable grouped body, whatever the processor.
        let portable = gas_expansion_closing_lanes(0, &row);
        prop_assert_eq!(bits(portable), bits(expected));
    }
}
