use super::*;
use crate::bridge_blast::{reduced_sets, workspace_root};
use brisance_compose::build::build_solver;
use brisance_compose::load_file;

#[test]
fn charge_radii_and_remap_times_follow_the_tnt_density() {
    // (3 · 1.094 / (4π · 1630))^(1/3) = 0.0543142 m; / 6930 m/s = 7.8376 µs.
    let c4 = &PLATE_CASES[3];
    assert_eq!(c4.id, 4);
    assert!((c4.charge_radius() - 0.054_314_2).abs() < 1e-7);
    assert!((c4.remap_time() - (7.837_55e-6 + 0.16e-6)).abs() < 1e-10);
    let c1 = &PLATE_CASES[0];
    assert!((c1.charge_radius() - 0.040_925_1).abs() < 1e-7);
}

/// The scale-4 case a case is the scaled copy of.
fn base_of(case: &PlateCase) -> &'static PlateCase {
    let id = if case.id <= 3 { 1 } else { 4 };
    PLATE_CASES.iter().find(|c| c.id == id).unwrap()
}

#[test]
fn the_cases_of_a_series_are_the_scale_4_case_scaled() {
    for case in &PLATE_CASES {
        let base = base_of(case);
        let k = case.length_scale();
        assert_eq!(k, f64::from(4 / case.scale), "case {}", case.id);
        assert!((case.diameter - k * base.diameter).abs() < 1e-12);
        assert!((case.standoff - k * base.standoff).abs() < 1e-12);
        assert!((case.cell() - k * CELL).abs() < 1e-15);
        // Table 1's charges: k³ W to 0.2 % (3.75 against 3.744 kg).
        let w = case.charge / (k.powi(3) * base.charge);
        assert!((w - 1.0).abs() < 2.5e-3, "case {}: {w}", case.id);
    }
}

/// Every number of a scaled config is its scale-4 config's number, or
/// that number times k (a length or a time): a typed-in config that
/// does not scale fails here. Comment lines and the lines naming the
/// case are left out.
#[test]
fn the_scaled_configs_are_the_scale_4_configs_with_lengths_and_times_times_k() {
    let numbers = |path: &str| -> Vec<f64> {
        let text = std::fs::read_to_string(workspace_root().join(path)).unwrap();
        text.lines()
            .filter(|l| {
                !l.trim_start().starts_with("//")
                    && !l.contains("plate_case")
                    && !l.contains("charge:")
            })
            .flat_map(|l| {
                l.split(|c: char| !(c.is_ascii_digit() || ".eE+-".contains(c)))
                    .filter_map(|t| t.parse::<f64>().ok())
                    .collect::<Vec<_>>()
            })
            .collect()
    };
    for case in PLATE_CASES.iter().filter(|c| c.scale != 4) {
        let (k, base) = (case.length_scale(), base_of(case));
        let (a, b) = (numbers(base.config), numbers(case.config));
        assert_eq!(a.len(), b.len(), "{}", case.config);
        assert!(a.len() > 40, "{}: {} numbers", case.config, a.len());
        let mut scaled = 0;
        for (x, y) in a.iter().zip(&b) {
            let same = x == y;
            let times_k = (y - k * x).abs() <= 1e-12 * (k * x).abs();
            assert!(
                same || times_k,
                "{}: {y} against {x} (k = {k})",
                case.config
            );
            scaled += usize::from(!same);
        }
        // The non-zero lengths and the time: domain 4, end time 1, FDM
        // and MPM regions 4 + 4, the air and plate boxes 4 + 4, the
        // ring 4 (base z, radii, length), the gauge 3, the centre
        // particle gauge's box 4 (its half-width and its z range).
        assert_eq!(scaled, 32, "{}", case.config);
        let loaded = load_file(&workspace_root().join(case.config), &[]).unwrap();
        assert_eq!(loaded.scenario.domain.cells, [54, 54, 46]);
        assert!((loaded.scenario.time.end - k * 1.5e-3).abs() < 1e-15);
        // The charge: its 1D grid and remap radius k times the base's,
        // its radius and time k times to the charges' 0.2 % (Table 1)
        // and the time's printed digits.
        let charge = |config: &str| {
            let loaded = load_file(&workspace_root().join(config), &[]).unwrap();
            let bridge = loaded
                .scenario
                .pipeline
                .section::<brisance_couple::BridgeConfig>();
            bridge
                .unwrap_or_else(|| panic!("{config} is not a bridge"))
                .charge
                .clone()
                .unwrap()
        };
        let (c0, c) = (charge(base.config), charge(case.config));
        assert_eq!((c.cells_1d, c.centre), (c0.cells_1d, c0.centre));
        let exact = |y: f64, x: f64| (y - k * x).abs() <= 1e-12 * k * x;
        assert!(exact(c.radius_1d, c0.radius_1d), "{}", case.config);
        assert!(exact(c.remap_radius.unwrap(), c0.remap_radius.unwrap()));
        for (y, x) in [(c.radius, c0.radius), (c.time, c0.time)] {
            assert!(
                (y / (k * x) - 1.0).abs() < 5e-3,
                "{}: {y} against {x}",
                case.config
            );
        }
    }
}

#[test]
fn the_centre_is_the_mean_of_the_steel_particles_near_the_axis() {
    let positions = [
        [0.001, 0.001, 0.10],
        [0.004, 0.002, 0.11],
        [0.006, 0.001, 0.2], // outside x < 5 mm
        [0.001, 0.001, 0.5], // air (material 0)
    ];
    let material = [2.0, 2.0, 2.0, 0.0];
    let vz = [10.0, 20.0, 99.0, 99.0];
    let (z, v, n) = centre_of(&positions, &material, &vz, 0.005, f64::INFINITY).unwrap();
    assert_eq!(n, 2);
    assert!((z - 0.105).abs() < 1e-15);
    assert_eq!(v, 15.0);
    assert!(centre_of(&positions, &[0.0; 4], &vz, 0.005, 1.0).is_none());
}

#[test]
fn ten_percent_is_the_band() {
    let within = |m, exp| crate::within_relative(m, exp, TOLERANCE);
    assert!(within(5.3, 4.85));
    assert!(!within(5.4, 4.85));
    assert!(within(2.35, 2.60));
    assert!(!within(2.3, 2.60));
}

/// The case's config parses and builds, and a few bridge steps run with
/// the clamp's mechanism at work: one particle per cell, no remap, the
/// MPM started at once (activation below ambient), and the plate and
/// ring moving at v0 along z toward the fixed face z = 170 mm. After
/// the first step the wall's nodes are at rest, so a ring particle at
/// the centre of the last cell (z = 167.5 mm, weight ½ on the wall's
/// nodes) has lost exactly half its velocity (eq 24 with a_I = −v0/Δt
/// on the held nodes), while the ring inside (z = 137.5 mm) and the
/// plate's centre keep v0.
#[test]
fn the_plate_config_runs_and_the_fixed_face_holds_the_ring() {
    let v0 = 10.0;
    let mut sets = reduced_sets(None);
    sets.extend((1..=2).map(|r| format!("initial.{r}.state.velocity=(0.0, 0.0, {v0})")));
    let root = workspace_root();
    let loaded = load_file(&root.join("configs/plate_case4.ron"), &sets).unwrap();
    let mut solver = build_solver(&loaded.scenario).unwrap();
    // The first step is the FDM's alone (the bridge checks the
    // activation after it); the second is the MPM's first.
    for _ in 0..2 {
        let dt = solver.stable_dt().unwrap();
        solver.advance(dt).unwrap();
    }
    let data = solver.particle_data().unwrap();
    let field = |name: &str| data.field(name).unwrap();
    let (material, vz) = (field("material"), field("velocity_z"));
    let steel_at = |z: f64| -> Vec<f64> {
        data.positions
            .iter()
            .zip(material.iter().zip(vz))
            .filter(|(x, (m, _))| **m == STEEL && (x[2] - z).abs() < 1e-3)
            .map(|(_, (_, v))| *v)
            .collect()
    };
    // Particles moved by v0 Δt at most: within 1 mm of their start.
    let last = steel_at(0.1675);
    let inner = steel_at(0.1375);
    assert!(!last.is_empty() && !inner.is_empty());
    for v in &last {
        assert!((v - 0.5 * v0).abs() < 1e-9 * v0, "{v}");
    }
    for v in &inner {
        assert!((v - v0).abs() < 1e-9 * v0, "{v}");
    }
    let (_, centre, n) = centre_of(&data.positions, material, vz, CELL, f64::INFINITY).unwrap();
    assert_eq!(n, 2, "one particle per cell, two cells through the plate");
    assert!((centre - v0).abs() < 0.01 * v0, "{centre}");
}

/// Case 1 on `grid`, reduced (no remap, one particle per cell, MPM at
/// once) to 2 samples: the run and its output directory, which the
/// caller removes.
fn reduced_run(grid: Grid, tag: &str) -> (PlateRun, std::path::PathBuf) {
    let out = std::env::temp_dir().join(format!("validation_{tag}_{}", std::process::id()));
    let sets = reduced_sets(Some(2 * SAMPLE_EVERY));
    let r = run_case(
        &workspace_root(),
        &PLATE_CASES[0],
        grid,
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
    (r, out)
}

/// The driver's loop on a few steps of case 1: it stops at the step limit
/// with one sample every SAMPLE_EVERY steps, and writes the centre's
/// history.
#[test]
fn run_case_samples_the_centre_and_writes_its_history() {
    let (r, out) = reduced_run(Grid::Quarter, "plate_run_case");
    assert!(!r.peak_reached);
    assert_eq!(r.particles_sampled, 2);
    assert!(r.finished.final_time > 0.0 && r.finished.wall > 0.0);
    let csv = std::fs::read_to_string(out.join("centre.csv")).unwrap();
    assert_eq!(csv.lines().count(), 4);
    let _ = std::fs::remove_dir_all(&out);
}

/// The r–z config of case 1, reduced as above: the centre is the
/// plate's particles with r < h (one per cell along r with the reduced 1
/// per cell, 4 cells through the thickness).
#[test]
fn on_rings_run_case_samples_the_centre_near_the_axis() {
    let (r, out) = reduced_run(Grid::Rz { h4: RZ_CELL }, "plate_rz_run_case");
    assert_eq!(r.particles_sampled, 4);
    let _ = std::fs::remove_dir_all(&out);
}

#[test]
fn the_rz_grids_keep_the_bridge_20_mm_wide_and_name_their_cells() {
    let case = &PLATE_CASES[1];
    let g = Grid::Rz { h4: 2.0 * RZ_CELL };
    assert_eq!(g.cell(case), 0.01);
    assert_eq!(
        g.sets(),
        vec![
            "domain.cells=(54, 46, 1)".to_string(),
            "pipeline.w=Some(4)".into()
        ]
    );
    assert!(Grid::Rz { h4: RZ_CELL }.sets().is_empty());
    assert_eq!(Grid::Rz { h4: 0.5 * RZ_CELL }.fdm_cells(), [216, 112, 1]);
    assert_eq!(Grid::Quarter.config(case), "configs/plate_case2.ron");
    assert_eq!(
        Grid::Rz { h4: RZ_CELL }.config(case),
        "configs/plate_case2_rz.ron"
    );
}

#[test]
fn cold_gas_counts_the_gas_particles_below_zero_and_finds_the_lowest() {
    let x = [[0.0; 3], [1.0, 0.0, 0.0], [2.0, 0.0, 0.0], [3.0, 0.0, 0.0]];
    // Air −1, products −5, steel −9 (not gas), air +1.
    let found = cold_gas(&x, &[0.0, 1.0, 2.0, 0.0], &[-1.0, -5.0, -9.0, 1.0]).unwrap();
    assert_eq!(
        found,
        ColdGas {
            count: 2,
            lowest: -5.0,
            at: [1.0, 0.0, 0.0]
        }
    );
    assert!(cold_gas(&x, &[0.0; 4], &[1.0; 4]).is_none());
}
