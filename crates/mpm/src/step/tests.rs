use super::*;
use crate::{fill_shape, FillSpec, Shape};
use brisance_constitutive::{ElasticPlastic, ObjectiveRate};

/// A deforming copper block (J2, Jaumann) binned on a 3D grid, with
/// node velocities and accelerations of a shear-and-squeeze field.
fn setup() -> (UniformGridGeometry, Particles, Vec<MaterialModel>) {
    let grid = UniformGridGeometry {
        origin: [0.0; 3],
        spacing: [1e-3; 3],
        cells: [6, 5, 4],
    };
    let mut m = ElasticPlastic::ofhc_copper_seed000();
    m.rate = ObjectiveRate::Jaumann;
    let mat = MaterialModel::ElasticPlastic(m);
    let mut ps = Particles::new(mat.history_len());
    fill_shape(
        &mut ps,
        &grid,
        &FillSpec {
            shape: Shape::Box {
                min: [1e-3; 3],
                max: [5e-3, 4e-3, 3e-3],
            },
            ppc: 2,
            density: 8930.0,
            material: MaterialId(0),
            velocity: [0.0; 3],
            temperature: 293.0,
            specific_internal_energy: 0.0,
        },
    )
    .unwrap();
    for p in 0..ps.len() {
        mat.init_history(ps.history_of_mut(p));
        // Some particles yielded already.
        ps.stress[p] = [-1e8, 5e7, 0.0, 1e7, 0.0, 4e7 * (p % 3) as f64];
    }
    (grid, ps, vec![mat])
}

#[test]
fn fused_g2p_and_stress_update_equals_the_two_passes_bit_for_bit() {
    for shape in ShapeFunction::ALL {
        let (grid, ps0, materials) = setup();
        let map = GridMap::new(&grid, shape);
        let mut bins = ParticleBins::default();
        bins.build(&map, &ps0.position, &ps0.initial_volume)
            .unwrap();
        let mut nodes = GridNodes::new(map.lattice);
        for (i, (v, a)) in nodes
            .velocity_new
            .iter_mut()
            .zip(nodes.acceleration.iter_mut())
            .enumerate()
        {
            let node = map.lattice.node(i);
            let x = node.map(|k| k as f64 * 1e-3);
            *v = [
                300.0 * x[1] - 50.0 * x[0],
                -80.0 * x[1],
                20.0 * x[2] + 10.0 * x[0],
            ];
            *a = [1e6 * x[2], -2e6 * x[0], 5e5];
        }
        nodes.velocity_remap = nodes
            .velocity_new
            .iter()
            .map(|v| v.map(|c| 0.9 * c))
            .collect();
        let boundaries = [GridBoundary::Free; 6];
        let params = StepParams {
            grid: &grid,
            shape,
            scheme: UpdateScheme::Musl,
            gravity: [0.0; 3],
            boundaries: &boundaries,
            mass_threshold: 0.0,
            radial_cutoff: None,
            light_nodes_move: false,
            materials: &materials,
            dt: 2e-8,
            bulk_viscosity: None,
            surface_forces: &[],
            reservoir: &[],
            own: None,
        };
        let t = Transfer {
            map: &map,
            bins: &bins,
        };
        for parts in [
            G2pParts {
                velocity: false,
                position: true,
                gradient: Some(NodeVelocity::Remapped),
            },
            G2pParts {
                velocity: true,
                position: true,
                gradient: Some(NodeVelocity::End),
            },
        ] {
            let mut a = ps0.clone();
            let mut bulk_a = vec![BulkViscosityState::default(); a.len()];
            let mut l = Vec::new();
            g2p(&t, &mut a, &nodes, params.dt, parts, &mut l);
            let fa = update_stresses(&mut a, &l, &mut bulk_a, &params);
            let mut b = ps0.clone();
            let mut bulk_b = bulk_a.clone();
            bulk_b.fill(BulkViscosityState::default());
            let fb = g2p_and_update_stresses(&t, &mut b, &mut bulk_b, &nodes, &params, parts);
            assert_eq!(fa, fb);
            assert!(a == b, "{shape:?} {parts:?}");
            assert_eq!(bulk_a, bulk_b);
            // The step did something: particles moved and stresses changed.
            assert_ne!(a.position, ps0.position);
            assert_ne!(a.stress, ps0.stress);
        }
    }
}

// ----------------------------------------- fluid points: J, not det F

/// A gas point's model: the γ = 1.4 ideal gas.
fn gas() -> MaterialModel {
    MaterialModel::Null(brisance_constitutive::NullMaterial::air())
}

/// A hypoelastic solid point's model (K 8 GPa, G 3 GPa, Jaumann rate).
fn solid() -> MaterialModel {
    use brisance_constitutive::{Hypoelastic, ObjectiveRate, PressureModel};
    MaterialModel::Hypoelastic(Hypoelastic {
        shear_modulus: 3.0e9,
        pressure: PressureModel::Linear {
            bulk_modulus: 8.0e9,
        },
        rate: ObjectiveRate::Jaumann,
    })
}

/// A point of model `m` (mass 1.2e-3 kg, stress −1 bar, 300 K) with
/// deformation `f`, volume `v` and initial volume `v0`, updated with `l`
/// over `dt`: the result and the state after it.
fn update_point(
    m: &MaterialModel,
    f: [f64; 9],
    v: f64,
    v0: f64,
    l: &Mat3,
    dt: f64,
) -> (Result<(), (f64, &'static str)>, [f64; 9], f64) {
    let (mut stress, mut f, mut volume) = ([-1e5, -1e5, -1e5, 0.0, 0.0, 0.0], f, v);
    let (mut t, mut e, mut failed) = (300.0, 2.5e5, false);
    let mut history = vec![0.0; m.history_len()];
    let mut bulk = BulkViscosityState::default();
    let state = ParticleState {
        stress: &mut stress,
        deformation_gradient: &mut f,
        volume: &mut volume,
        temperature: &mut t,
        specific_internal_energy: &mut e,
        failed: &mut failed,
        history: &mut history,
        bulk_viscosity: &mut bulk,
    };
    let r = update_particle_stress(m, MaterialId(0), state, l, 1.2e-3, v0, dt, None);
    (r, f, volume)
}

#[test]
fn a_solid_sheared_past_the_limit_takes_its_volume_from_the_product_rule() {
    // The sheared F of the gas test below (det F = 1 exactly, entries
    // 10⁸ and 10¹⁶): det F evaluates to 0, and the solid, which used
    // to take J = det F, was refused.
    let (a, b) = (1e8, 1e8);
    let f = [1.0 + a * b, a, 0.0, b, 1.0, 0.0, 0.0, 0.0, 1.0];
    assert!(!(Mat3::from_row_slice(&f).determinant() > 0.0));
    assert!(solid_deformation_is_distorted(
        &Mat3::from_row_slice(&f),
        1.0
    ));
    // L = diag(−0.1, 0, 0.05) /s over Δt = 0.1 s: J = 0.99495.
    let l = Mat3::new(-0.1, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.05);
    let (r, f_new, v_new) = update_point(&solid(), f, 1e-3, 1e-3, &l, 0.1);
    assert_eq!(r, Ok(()));
    assert!((v_new - 0.99495e-3).abs() < 1e-18, "{v_new}");
    // A solid keeps its F: (I + L Δt) F.
    let want = Mat3::new(0.99, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.005) * Mat3::from_row_slice(&f);
    assert_eq!(Mat3::from_row_slice(&f_new), want);
}

#[test]
fn a_solid_below_the_limit_keeps_det_f() {
    // F = [[1, a, 0], [0, 1, 0], [0, 0, 1]] with a below 10⁴ (J = 1)
    // and L Δt = [[0, 0, 0], [g, 0, 0], [0, 0, 0]]: J is det F_new as
    // before, not the product rule det(I + L Δt) = 1. The two differ in
    // the last bits for some (a, g), det F_new = 1 + a g − a g; the
    // test takes the first such pair, so that it can tell them apart.
    let mut checked = 0;
    for a in [9000.0, 7777.7, 5432.1, 1234.5, 987.65] {
        for g in [1e-2, 3.3e-3, 7.1e-4, 1.7e-2] {
            let f = [1.0, a, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0];
            assert!(!solid_deformation_is_distorted(
                &Mat3::from_row_slice(&f),
                1.0
            ));
            let l = Mat3::new(0.0, 0.0, 0.0, g, 0.0, 0.0, 0.0, 0.0, 0.0);
            let (r, f_new, v_new) = update_point(&solid(), f, 1e-3, 1e-3, &l, 0.1);
            assert_eq!(r, Ok(()));
            let det = Mat3::from_row_slice(&f_new).determinant();
            if det != 1.0 {
                assert_eq!(v_new, det * 1e-3, "a {a}, g {g}");
                checked += 1;
            }
        }
    }
    assert!(checked > 0, "no pair told the two rules apart");
}

#[test]
fn a_sheared_gas_point_takes_its_volume_from_the_product_rule_not_det_f() {
    // F = [[1 + ab, a, 0], [b, 1, 0], [0, 0, 1]] has det F = 1 exactly,
    // but with a = b = 1e8 the entry 1 + ab rounds to ab and the
    // determinant evaluates to 0: the old update refused this point.
    let (a, b) = (1e8, 1e8);
    let f = [1.0 + a * b, a, 0.0, b, 1.0, 0.0, 0.0, 0.0, 1.0];
    assert!(!(Mat3::from_row_slice(&f).determinant() > 0.0));
    // A small compression, L = diag(−0.1, 0, 0.05) /s over Δt = 0.1 s:
    // det(I + L Δt) = 0.99 · 1 · 1.005 = 0.99495; Vⁿ = V⁰ = 1e-3 m³.
    let l = Mat3::new(-0.1, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.05);
    let (r, f_new, v_new) = update_point(&gas(), f, 1e-3, 1e-3, &l, 0.1);
    assert_eq!(r, Ok(()));
    assert!((v_new - 0.99495e-3).abs() < 1e-18, "{v_new}");
    // The distorted F is re-initialised to J^{1/3} I.
    let c = 0.99495_f64.cbrt();
    for (k, x) in f_new.iter().enumerate() {
        let want = if k % 4 == 0 { c } else { 0.0 };
        assert!((x - want).abs() < 1e-15, "F[{k}] = {x}, want {want}");
    }
}

#[test]
fn a_gas_point_keeps_its_volume_history_and_a_moderate_f() {
    // Vⁿ = 2 V⁰ (J = 2) with F = diag(2, 1, 1): L = [[0, 0.5, 0],
    // [0, −0.2, 0], [0, 0, 0]] /s over Δt = 0.1 s gives
    // I + L Δt = [[1, 0.05, 0], [0, 0.98, 0], [0, 0, 1]], det 0.98,
    // J = 1.96, V = 1.96 V⁰ and F = (I + L Δt) F = [[2, 0.05, 0],
    // [0, 0.98, 0], [0, 0, 1]], kept (no entry beyond 100 J^{1/3}).
    let l = Mat3::new(0.0, 0.5, 0.0, 0.0, -0.2, 0.0, 0.0, 0.0, 0.0);
    let f = [2.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0];
    let (r, f_new, v_new) = update_point(&gas(), f, 2e-3, 1e-3, &l, 0.1);
    assert_eq!(r, Ok(()));
    assert!((v_new - 1.96e-3).abs() < 1e-18, "{v_new}");
    let want = [2.0, 0.05, 0.0, 0.0, 0.98, 0.0, 0.0, 0.0, 1.0];
    for (x, w) in f_new.iter().zip(want) {
        assert!((x - w).abs() < 1e-15, "{f_new:?}");
    }
}

#[test]
fn a_gas_point_whose_volume_would_invert_in_one_step_is_still_refused() {
    // tr(L) Δt = −1.5 along x: det(I + L Δt) = −0.5 < 0.
    let l = Mat3::new(-15.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0);
    let (r, _, _) = update_point(&gas(), crate::particles::IDENTITY, 1e-3, 1e-3, &l, 0.1);
    let (j, reason) = r.unwrap_err();
    assert_eq!(reason, "det F is not positive");
    assert!((j + 0.5).abs() < 1e-15, "{j}");
}

#[test]
fn solid_distortion_limit_is_relative_to_the_volume() {
    let j: f64 = 8.0; // J^{1/3} = 2: entries up to 2·10⁴ pass.
    let ok = Mat3::new(2.0e4, 0.0, 0.0, 0.0, 4e-4, 0.0, 0.0, 0.0, 1.0);
    let bad = Mat3::new(2.0001e4, 0.0, 0.0, 0.0, 4e-4, 0.0, 0.0, 0.0, 1.0);
    assert!(!solid_deformation_is_distorted(&ok, j));
    assert!(solid_deformation_is_distorted(&bad, j));
    // The fluid limit, 100 J^{1/3}, is far below it.
    assert!(fluid_deformation_is_distorted(&ok, j));
}

#[test]
fn fluid_distortion_limit_is_relative_to_the_volume() {
    let j: f64 = 8.0; // J^{1/3} = 2: entries up to 200 pass.
    let ok = Mat3::new(200.0, 0.0, 0.0, 0.0, 0.04, 0.0, 0.0, 0.0, 1.0);
    let bad = Mat3::new(200.5, 0.0, 0.0, 0.0, 0.04, 0.0, 0.0, 0.0, 1.0);
    assert!(!fluid_deformation_is_distorted(&ok, j));
    assert!(fluid_deformation_is_distorted(&bad, j));
    let nan = Mat3::new(f64::NAN, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0);
    assert!(fluid_deformation_is_distorted(&nan, 1.0));
}

proptest::proptest! {
    /// The cube-root-free shortcut gives the exact test's answer,
    /// entries drawn about the limit 100 J^{1/3} (within a few ulp
    /// of it too) over 300 decades of J.
    #[test]
    fn distortion_shortcut_agrees_with_the_cube_root_test(
        log_j in -300.0..300.0f64,
        ratio in 0.0..2.0f64,
        ulps in -4i64..4,
        at in 0usize..9,
    ) {
        let j = 10f64.powf(log_j);
        let limit = FLUID_DISTORTION_LIMIT * j.cbrt();
        let near = f64::from_bits((limit.to_bits() as i64 + ulps) as u64);
        for x in [ratio * limit, near] {
            let mut f = Mat3::identity() * (0.5 * j.cbrt());
            f[at] = x;
            let exact = f.iter().any(|v| !(v.abs() <= limit));
            proptest::prop_assert_eq!(fluid_deformation_is_distorted(&f, j), exact);
        }
    }
}
