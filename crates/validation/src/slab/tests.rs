use super::*;
use crate::bridge_blast::workspace_root;
use brisance_compose::build::build_solver;
use brisance_compose::load_file;

#[test]
fn crushing_is_damage_first_seen_at_one_under_compression() {
    let mut onset = DamageOnset::new();
    // Particle 7 reaches D = 1 at p = 30 MPa: crushed, and stays so when
    // its pressure later falls to 0. Particle 8 reaches D = 1 at p = 0
    // (torn in tension): never crushed, even when compressed later.
    // Particle 9 is damaged but below 1: not classified yet.
    let ids = [7.0, 8.0, 9.0];
    let first = crushed_flags(&ids, &[1.0, 1.0, 0.9], &[3e7, 0.0, 5e7], &mut onset);
    assert_eq!(first, [1.0, 0.0, 0.0]);
    let later = crushed_flags(&ids, &[1.0, 1.0, 1.0], &[0.0, 4e7, -1e6], &mut onset);
    assert_eq!(later, [1.0, 0.0, 0.0]);
    assert_eq!(onset.len(), 3);
    assert_eq!((onset[&7], onset[&8], onset[&9]), (true, false, false));
}

#[test]
fn eq67_gives_the_seed_formula() {
    // W = 4 kg, h = 0.5 m: 0.1838 · 4^{1/3} / 0.5 = 0.583 530;
    // D = 0.5 / 3.63 · e^{0.583 530} = 0.246 880 m.
    assert!((eq67_diameter(4.0, 0.5) - 0.246_880).abs() < 1e-6);
    // W = 10 kg: 0.1838 · 2.154 435 / 0.5 = 0.791 990; D = 0.304 097 m.
    assert!((eq67_diameter(10.0, 0.5) - 0.304_097).abs() < 1e-6);
    // W = 0: ln(3.63 D/h) = 0, D = h/3.63.
    assert_eq!(eq67_diameter(0.0, 0.5), 0.5 / 3.63);
}

#[test]
fn charge_radius_remap_time_and_radii() {
    // (3 · 4 / (4π · 1630))^{1/3} = 0.083 674 8 m; / 6930 = 12.074 µs.
    let c = &SLAB_CASES[1];
    assert_eq!(c.charge, 4.0);
    assert!((c.charge_radius() - 0.083_674_8).abs() < 1e-7);
    assert!((c.remap_time() - (0.083_674_8 / 6930.0 + 0.16e-6)).abs() < 1e-11);
    assert!((c.remap_radius() - (1.1 * 0.083_674_8 + 0.002)).abs() < 1e-7);
    // The largest charge's remap stays inside the FDM region (its low
    // z face is 180 mm from the centre; the MPM region starts at 410 mm).
    let big = SLAB_CASES
        .iter()
        .map(SlabCase::remap_radius)
        .fold(0.0, f64::max);
    assert!(big < -FDM_LOWER[2], "{big}");
}

fn layer() -> (Vec<[f64; 3]>, Vec<f64>) {
    // One layer of particles 10 mm apart at z = 0.505, centres at 5, 15,
    // ... mm in x and y, 6 × 6 of them; plus an air particle.
    let mut x = Vec::new();
    for i in 0..6 {
        for j in 0..6 {
            x.push([
                0.005 + 0.01 * f64::from(i),
                0.005 + 0.01 * f64::from(j),
                0.505,
            ]);
        }
    }
    x.push([0.005, 0.005, 0.505]);
    let mut m = vec![CONCRETE; 36];
    m.push(0.0);
    (x, m)
}

#[test]
fn crushing_runs_from_the_axis_to_the_first_ring_less_than_half_failed() {
    let (x, m) = layer();
    // Fail every particle within r < 25 mm. Rings of 10 mm (radii in
    // mm): 0 {(5,5) 7.07}; 1 {(5,15), (15,5) 15.8}; 2 {(15,15) 21.2,
    // (5,25), (25,5) 25.5, (15,25), (25,15) 29.2}; 3 {(25,25) 35.4,
    // (5,35), (35,5) 35.4, (15,35), (35,15) 38.1}; ...
    let failed: Vec<f64> = x
        .iter()
        .zip(&m)
        .map(|(p, mm)| {
            if *mm == CONCRETE && p[0].hypot(p[1]) < 0.025 {
                1.0
            } else {
                0.0
            }
        })
        .collect();
    let c = crushing_diameter(&x, &m, &failed, 0.5, 0.52, 0.01);
    // Rings 0 and 1 all failed; ring 2: 1 of 5 failed → the zone stops
    // there. D = 2 · 20 mm.
    assert_eq!(c.diameter, 0.04);
    assert_eq!(c.failed, 4);
    assert_eq!(c.particles, 36);
    let area = 2.0 * (4.0 * 4.0 * 1e-4 / std::f64::consts::PI).sqrt();
    assert!((c.area_diameter - area).abs() < 1e-15);
    // Out of the layer's z range: nothing counted.
    let none = crushing_diameter(&x, &m, &failed, 0.51, 0.52, 0.01);
    assert_eq!((none.diameter, none.particles), (0.0, 0));
    // An intact axis gives no crushed zone, whatever fails outside.
    let mut ring_only = failed.clone();
    ring_only[0] = 0.0;
    assert_eq!(
        crushing_diameter(&x, &m, &ring_only, 0.5, 0.52, 0.01).diameter,
        0.0
    );
    // Fail one more particle of ring 2, (25, 5): 2 of 5 is less than
    // half, the zone still stops at ring 2.
    let at = |a: f64, b: f64| {
        x.iter()
            .position(|p| (p[0] - a).abs() < 1e-9 && (p[1] - b).abs() < 1e-9)
            .unwrap()
    };
    let mut more = failed;
    more[at(0.025, 0.005)] = 1.0;
    assert_eq!(
        crushing_diameter(&x, &m, &more, 0.5, 0.52, 0.01).diameter,
        0.04
    );
    // And (5, 25): 3 of 5, at least half, ring 2 is crushed; ring 3 has
    // none failed → D = 2 · 30 mm.
    more[at(0.005, 0.025)] = 1.0;
    assert_eq!(
        crushing_diameter(&x, &m, &more, 0.5, 0.52, 0.01).diameter,
        0.06
    );
}

#[test]
fn the_impulse_integrates_the_samples_by_trapezoids() {
    // p = 0, 2, 2 MPa at t = 0, 1, 3 µs: 1 + 4 = 5 Pa·s.
    let h = [(0.0, 0.0, 0, 0.0), (1e-6, 0.0, 0, 2e6), (3e-6, 0.0, 0, 2e6)];
    assert!((axis_impulse(&h) - 5.0).abs() < 1e-12);
    assert_eq!(axis_impulse(&h[..1]), 0.0);
}

#[test]
fn the_area_diameter_counts_only_failures_near_the_axis() {
    // Two failed particles, one at r = 0.1 m, one at 0.3 m (beyond
    // AREA_RADIUS): one 1 cm² particle counts, D = 2 √(4 · 1e-4 / π).
    let x = [[0.1, 0.0, 0.505], [0.3, 0.0, 0.505]];
    let c = crushing_diameter(&x, &[CONCRETE; 2], &[1.0; 2], 0.5, 0.51, 0.01);
    assert!((c.area_diameter - 2.0 * (4e-4 / std::f64::consts::PI).sqrt()).abs() < 1e-15);
    assert_eq!((c.failed, c.diameter), (2, 0.0));
}

#[test]
fn twenty_percent_is_the_band() {
    let within = |m, reference| crate::within_relative(m, reference, TOLERANCE);
    assert!(within(0.30, 0.25));
    assert!(!within(0.301, 0.25));
    assert!(within(0.24, 0.30));
    assert!(!within(0.239, 0.30));
}

/// The driver's loop on a few steps of the 4 kg config (no remap, one
/// particle per cell, MPM at once): it stops at the step limit with one
/// sample every SAMPLE_EVERY steps, nothing crushed, and writes the
/// history.
#[test]
fn run_case_samples_the_slab_and_writes_its_history() {
    let out = std::env::temp_dir().join(format!("validation_slab_run_case_{}", std::process::id()));
    let sets = crate::bridge_blast::reduced_sets(Some(2 * SAMPLE_EVERY));
    let r = run_case(
        &workspace_root(),
        &SLAB_CASES[1],
        &sets,
        &out,
        "none".into(),
        &mut |_| {},
    )
    .unwrap();
    assert_eq!(
        (r.steps, r.history.len(), r.stop.as_deref()),
        (2 * SAMPLE_EVERY, 3, None)
    );
    assert_eq!((r.front.failed, r.front.diameter), (0, 0.0));
    assert_eq!(r.concrete_total, 40 * 40 * 15);
    assert!(r.finished.final_time > 0.0 && r.finished.wall > 0.0);
    let csv = std::fs::read_to_string(out.join("crushing.csv")).unwrap();
    assert_eq!(csv.lines().count(), 4);
    let _ = std::fs::remove_dir_all(&out);
}

/// Both configs parse and build, and a few bridge steps run with the
/// concrete in place: one particle per cell, no remap, the MPM started
/// at once (activation below ambient). The slab's particles start
/// intact, fill 0.5–0.65 m, and the top layer is 40 × 40 particles.
#[test]
fn the_slab_configs_build_and_step() {
    let sets = crate::bridge_blast::reduced_sets(None);
    let root = workspace_root();
    for config in ["configs/slab_4kg.ron", "configs/slab_10kg.ron"] {
        let loaded = load_file(&root.join(config), &sets).unwrap();
        let mut solver = build_solver(&loaded.scenario).unwrap();
        for _ in 0..2 {
            let dt = solver.stable_dt().unwrap();
            solver.advance(dt).unwrap();
        }
        let initial = initial_positions(solver.as_ref()).unwrap();
        let s = sample(solver.as_ref(), &initial, &mut DamageOnset::new()).unwrap();
        let concrete: Vec<&[f64; 3]> = s
            .initial
            .iter()
            .zip(&s.material)
            .filter(|(_, m)| **m == CONCRETE)
            .map(|(x, _)| x)
            .collect();
        // 150 mm at 10 mm cells and one particle per cell: centres at
        // 505, 515, ..., 645 (15 layers of 40 × 40).
        assert_eq!(concrete.len(), 40 * 40 * 15, "{config}");
        assert!(concrete.iter().all(|x| x[2] > TOP && x[2] < BACK));
        let c = crushing_diameter(&s.initial, &s.material, &s.crushed, 0.5, 0.51, 0.01);
        assert_eq!(
            (c.particles, c.failed, c.diameter),
            (1600, 0, 0.0),
            "{config}"
        );
    }
}
