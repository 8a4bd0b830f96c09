//! The `FdmMpmBridge` pipeline through the composer: its shipped
//! scenarios, `--set` paths, remap files and error positions. The
//! section, its checks and its builder are
//! `brisance_couple::bridge_pipeline`'s.

use crate::load_str;

/// A 2D tube: FDM (0, 40) mm, MPM (30, 60) mm at 2 mm (w = 5), a
/// 5-bar region at x < 10 mm and a concrete block in the MPM region.
const TUBE: &str = r#"Scenario(
    name: "bridge2d",
    domain: (lower: (0.0, 0.0, 0.0), upper: (0.06, 0.02, 0.002), cells: (30, 10, 1)),
    boundaries: (x_low: Reflective, x_high: Reflective, y_low: Reflective, y_high: Reflective),
    time: (end: 8.0e-5, cfl: 0.8),
    materials: {"air": (library: "air"), "concrete": (library: "concrete_48mpa")},
    pipeline: FdmMpmBridge(
        fdm_region: (lower: (0.0, 0.0, 0.0), upper: (0.04, 0.02, 0.002)),
        mpm_region: (lower: (0.03, 0.0, 0.0), upper: (0.06, 0.02, 0.002)),
        air: "air",
        bulk_viscosity: On(),
        activation_pressure: 1.1e5,
    ),
    initial: [
        (region: Everywhere, material: "air", state: (density: 1.225, pressure: 1.0e5)),
        (region: HalfSpace(point: (0.01, 0, 0), normal: (-1, 0, 0)), material: "air", state: (density: 4.9, pressure: 5.0e5)),
        (region: Box(min: (0.05, 0.004, 0.0), max: (0.056, 0.016, 0.002)), material: "concrete", state: (density: 2440.0, temperature: 293.15)),
    ],
    outputs: (fields: ["density", "pressure"], vtk: false),
)"#;

#[test]
fn a_2d_bridge_scenario_builds_activates_and_loads_the_concrete() {
    let loaded = load_str("bridge2d.ron", TUBE, &[]).unwrap();
    let described = crate::build::describe(&loaded.scenario);
    assert!(described.contains("w = 5 cells along x"), "{described}");
    let mut solver = crate::build::build_solver(&loaded.scenario).unwrap();
    assert_eq!(solver.name(), "fdm-mpm");
    let m0 = solver.conservation_totals().mass;
    while solver.time() < 8.0e-5 {
        let dt = solver.stable_dt().unwrap();
        solver.advance(dt.min(8.0e-5 - solver.time())).unwrap();
    }
    // The shock crossed the interface (30 mm) and reached the concrete.
    let mut p = Vec::new();
    solver
        .sample([0.045, 0.011, 0.001], &["pressure".to_string()], &mut p)
        .unwrap();
    eprintln!("pressure at 45 mm: {:e} Pa", p[0]);
    assert!(p[0] > 1.6e5, "{}", p[0]);
    let data = solver.cell_data(&["density".to_string()]).unwrap();
    assert_eq!(data.geometry.cells, [30, 10, 1]);
    // Concrete cell (26, 5): the particles' density.
    let rho = data.fields[0].1[26 + 30 * 5];
    assert!((rho - 2440.0).abs() < 50.0, "{rho}");
    let m1 = solver.conservation_totals().mass;
    eprintln!(
        "mass change of the FDM cells outside the MPM region plus particles: {:e}",
        (m1 - m0) / m0
    );
}

/// An (r, z) box, r 0–20 mm, z 0–60 mm at 2 mm: FDM z 0–40 mm, MPM
/// z 30–60 mm (w = 5), closed (the axis, an outer wall and walls at
/// both ends), air at rest, the MPM region started at once (the
/// activation pressure below the ambient's); a steel disc (z 50–56 mm,
/// r < 14 mm) in the MPM region when `PLATE` is appended to `initial`.
const RZ_BOX: &str = r#"Scenario(
    name: "bridge_rz",
    domain: (lower: (0.0, 0.0, 0.0), upper: (0.02, 0.06, 0.002), cells: (10, 30, 1), geometry: Axisymmetric),
    boundaries: (x_low: Reflective, x_high: Reflective, y_low: Reflective, y_high: Wall),
    time: (end: 1.0e-4, cfl: 0.8),
    materials: {"air": (library: "air"), "rha": (library: "rha_steel")},
    pipeline: FdmMpmBridge(
        fdm_region: (lower: (0.0, 0.0, 0.0), upper: (0.02, 0.04, 0.002)),
        mpm_region: (lower: (0.0, 0.03, 0.0), upper: (0.02, 0.06, 0.002)),
        air: "air",
        bulk_viscosity: On(),
        activation_pressure: 5.0e4,
    ),
    initial: [
        (region: Everywhere, material: "air", state: (density: 1.225, pressure: 1.0e5)),
    ],
    outputs: (fields: ["density", "pressure"], vtk: false),
)"#;

const PLATE: &str = r#"(region: Box(min: (0.0, 0.05, -1.0), max: (0.014, 0.056, 1.0)), material: "rha", state: (density: 7850.0, temperature: 300.0)),"#;

/// Largest |v| over the bridge's cells (FDM and MPM), m/s.
fn largest_speed(solver: &dyn brisance_core::Solver) -> f64 {
    let names: Vec<String> = ["velocity_x", "velocity_y", "velocity_z"]
        .iter()
        .map(|s| s.to_string())
        .collect();
    let data = solver.cell_data(&names).unwrap();
    let n = data.fields[0].1.len();
    (0..n)
        .map(|c| {
            (0..3)
                .map(|k| data.fields[k].1[c].powi(2))
                .sum::<f64>()
                .sqrt()
        })
        .fold(0.0, f64::max)
}

#[test]
fn an_rz_bridge_of_gas_at_rest_with_a_plate_at_rest_stays_at_rest() {
    // Gas alone: every exchange of the bridge (donor rings, fictitious
    // rings, inflow and absorption over annuli) balances, and nothing
    // moves beyond round-off of the velocity scale p/(ρc) ≈ 240 m/s
    // (the MPM region starts after step 1); sixty steps in
    // `gas_at_rest_stays_at_rest_through_sixty_coupled_steps_cartesian_and_rz`.
    // With the steel disc: it starts stress-free in 1 bar
    // of air, so it is squeezed elastically; its speeds are of the
    // order p/(ρ_s c_s) ≈ 2.5 mm/s.
    for (plate, steps, bound) in [(false, 3, 1e-9), (true, 3, 1e-2)] {
        let text = if plate {
            RZ_BOX.replace(
                "pressure: 1.0e5)),
    ],",
                &format!(
                    "pressure: 1.0e5)),
        {PLATE}
    ],"
                ),
            )
        } else {
            RZ_BOX.to_string()
        };
        let loaded = load_str("bridge_rz.ron", &text, &[]).unwrap();
        let mut solver = crate::build::build_solver(&loaded.scenario).unwrap();
        for _ in 0..steps {
            let dt = solver.stable_dt().unwrap();
            solver.advance(dt).unwrap();
        }
        let v = largest_speed(&*solver);
        eprintln!(
            "plate {plate}: t = {:e} s, largest speed {v:e} m/s",
            solver.time()
        );
        assert!(v < bound, "plate {plate}: {v} m/s");
    }
}

#[test]
fn gas_at_rest_stays_at_rest_through_sixty_coupled_steps_cartesian_and_rz() {
    // The box of `RZ_BOX` on its (r, z) grid and on the Cartesian grid
    // of the same cells: 60 coupled steps (the MPM region starts after
    // the first). The donor cells load the interface nodes (eqs 37–39)
    // but are kept out of MUSL's re-mapping (eq 26), so the first
    // bridge layer's strain rate sees only its own particles' velocity
    // (zero). Before, its particles expanded at rest from the second
    // coupled step (1.225 → 1.159 → 1.103 kg/m³), the gas reached
    // 60–90 m/s and lost 2.4–2.6 % of its energy by step 60
    // (docs/physics/couple/bridge.md, "At rest"). Now the largest
    // speed stays near 1e-11 m/s and the energy to round-off. The
    // mass is not checked: the FDM cells beside the interface still
    // lose density at constant pressure, fastest at the side walls
    // (−2.4e-4 of the mass by step 60), a defect of their own left
    // open in that section.
    for axisymmetric in [false, true] {
        let text = if axisymmetric {
            RZ_BOX.to_string()
        } else {
            RZ_BOX.replace(", geometry: Axisymmetric", "")
        };
        let loaded = load_str("bridge_rz.ron", &text, &[]).unwrap();
        let mut solver = crate::build::build_solver(&loaded.scenario).unwrap();
        let e0 = solver.conservation_totals().energy;
        let mut fastest = 0.0f64;
        for _ in 0..60 {
            let dt = solver.stable_dt().unwrap();
            solver.advance(dt).unwrap();
            fastest = fastest.max(largest_speed(&*solver));
        }
        let de = (solver.conservation_totals().energy - e0) / e0;
        eprintln!(
            "axisymmetric {axisymmetric}: t = {:e} s, largest speed {fastest:e} m/s, energy change {de:e}",
            solver.time()
        );
        assert!(fastest < 1e-9, "axisymmetric {axisymmetric}: {fastest} m/s");
        assert!(de.abs() < 1e-12, "axisymmetric {axisymmetric}: {de}");
    }
}

#[test]
fn an_rz_bridge_carries_a_shock_onto_a_plate_and_its_cell_data_are_rings() {
    // A 5-bar region z < 10 mm drives a shock through the interface at
    // z = 30–40 mm onto the disc; the whole system's mass is the
    // cylinder's, π r² L ρ, not a slab's.
    let text = rz_shock_with_gauges("");
    let loaded = load_str("bridge_rz.ron", &text, &[]).unwrap();
    let mut solver = crate::build::build_solver(&loaded.scenario).unwrap();
    let m0 = solver.conservation_totals().mass;
    let pi = std::f64::consts::PI;
    let fdm_gas = pi * 0.02f64.powi(2) * (1.225 * 0.026 + 4.9 * 0.01);
    let mpm_gas = pi * 0.02f64.powi(2) * 0.03 * 1.225 - pi * 0.014f64.powi(2) * 0.006 * 1.225;
    let disc = pi * 0.014f64.powi(2) * 0.006 * 7850.0;
    // The FDM cells the bridge owns (z < 32 mm... the donor cell and
    // before) plus the particles: within a cell of gas of the sum.
    let expected = fdm_gas - pi * 0.02f64.powi(2) * 0.004 * 1.225 + mpm_gas + disc;
    assert!(((m0 - expected) / expected).abs() < 1e-3, "{m0} {expected}");
    while solver.time() < 8.0e-5 {
        let dt = solver.stable_dt().unwrap();
        solver.advance(dt.min(8.0e-5 - solver.time())).unwrap();
    }
    let mut p = Vec::new();
    solver
        .sample([0.005, 0.045, 0.001], &["pressure".to_string()], &mut p)
        .unwrap();
    eprintln!("pressure at z = 45 mm: {:e} Pa", p[0]);
    assert!(p[0] > 1.6e5, "{}", p[0]);
}

#[test]
fn an_rz_bridge_split_along_r_is_refused_by_name() {
    let text = RZ_BOX
        .replace(
            "fdm_region: (lower: (0.0, 0.0, 0.0), upper: (0.02, 0.04, 0.002))",
            "fdm_region: (lower: (0.0, 0.0, 0.0), upper: (0.012, 0.06, 0.002))",
        )
        .replace(
            "mpm_region: (lower: (0.0, 0.03, 0.0), upper: (0.02, 0.06, 0.002))",
            "mpm_region: (lower: (0.002, 0.0, 0.0), upper: (0.02, 0.06, 0.002))",
        );
    let e = load_str("bridge_rz.ron", &text, &[])
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("pipeline.mpm_region") && e.contains("split along z"),
        "{e}"
    );
}

#[test]
fn bad_bridge_options_are_named() {
    let err = |from: &str, to: &str| {
        let text = TUBE.replace(from, to);
        load_str("bridge2d.ron", &text, &[])
            .unwrap_err()
            .to_string()
    };
    let e = err("upper: (0.04, 0.02, 0.002)", "upper: (0.041, 0.02, 0.002)");
    assert!(
        e.contains("pipeline.mpm_region") && e.contains("whole number"),
        "{e}"
    );
    let e = err("air: \"air\",\n", "air: \"concrete\",\n");
    assert!(e.contains("pipeline.air"), "{e}");
    let e = err("activation_pressure: 1.1e5", "activation_pressure: -1.0");
    assert!(e.contains("pipeline.activation_pressure"), "{e}");
    let e = err(
        "activation_pressure: 1.1e5",
        "activation_pressure: 1.1e5, min_particle_mass: 1.5",
    );
    assert!(e.contains("pipeline.min_particle_mass"), "{e}");
    for k in ["0", "5"] {
        let e = err(
            "activation_pressure: 1.1e5",
            &format!("activation_pressure: 1.1e5, start_in_bridge: Some({k})"),
        );
        assert!(
            e.contains("pipeline.start_in_bridge") && e.contains("[1, 5)"),
            "{e}"
        );
    }
    let e = err(
        "upper: (0.06, 0.02, 0.002), cells: (30",
        "upper: (0.08, 0.02, 0.002), cells: (40",
    );
    assert!(e.contains("union"), "{e}");
}

const BLAST2D: &str = include_str!("../../../configs/blast2d.ron");

/// `text` with `w: {w},` before its `air`.
fn with_w(text: &str, w: &str) -> String {
    let air = "air: \"air\",\n";
    assert!(text.contains(air));
    text.replace(air, &format!("w: {w},\n            {air}"))
}

#[test]
fn the_default_bridge_width_is_5_and_fits_the_blast2d_geometry() {
    // configs/blast2d.ron omits w: FDM to 120 mm, MPM from 110 mm,
    // 2 mm cells.
    assert!(!BLAST2D.contains("w: "));
    let loaded = load_str("blast2d.ron", BLAST2D, &[]).unwrap();
    let Some(b) = loaded
        .scenario
        .pipeline
        .section::<brisance_couple::BridgeConfig>()
    else {
        panic!("blast2d.ron is a bridge");
    };
    assert_eq!(b.w, None);
    let described = crate::build::describe(&loaded.scenario);
    assert!(described.contains("w = 5 cells along x"), "{described}");
    // Written out, the same.
    let set = ["pipeline.w=Some(5)".to_string()];
    let explicit = load_str("blast2d.ron", BLAST2D, &set).unwrap();
    let Some(e) = explicit
        .scenario
        .pipeline
        .section::<brisance_couple::BridgeConfig>()
    else {
        unreachable!()
    };
    assert_eq!(e.w, Some(5));
    assert_eq!(brisance_couple::bridge_pipeline::DEFAULT_BRIDGE_WIDTH, 5);
}

#[test]
fn an_explicit_bridge_width_that_matches_the_overlap_is_accepted() {
    // TUBE's boxes overlap by 5 cells.
    load_str("bridge2d.ron", &with_w(TUBE, "Some(5)"), &[]).unwrap();
    // IMPLICIT_SOME: `w: 5` is the same.
    load_str("bridge2d.ron", &with_w(TUBE, "5"), &[]).unwrap();
    // 8 cells: the MPM region from 24 mm.
    let text = with_w(
        &TUBE.replace("lower: (0.03, 0.0, 0.0)", "lower: (0.024, 0.0, 0.0)"),
        "Some(8)",
    );
    let loaded = load_str("bridge2d.ron", &text, &[]).unwrap();
    let described = crate::build::describe(&loaded.scenario);
    assert!(described.contains("w = 8 cells along x"), "{described}");
    // xtask's E-BLAST2D width study: w = 2 and 8 by --set.
    for (lower, w) in [("0.116", 2), ("0.104", 8)] {
        let sets = [
            format!("pipeline.mpm_region.lower=({lower},0.0,0.0)"),
            format!("pipeline.w=Some({w})"),
        ];
        let loaded = load_str("blast2d.ron", BLAST2D, &sets).unwrap();
        let described = crate::build::describe(&loaded.scenario);
        assert!(
            described.contains(&format!("w = {w} cells along x")),
            "{described}"
        );
        // Without w the default 5 refuses the moved box.
        let e = load_str("blast2d.ron", BLAST2D, &sets[..1]).unwrap_err();
        assert_eq!(e.field.as_deref(), Some("pipeline.w"), "{e}");
    }
}

#[test]
fn a_bridge_width_that_does_not_match_the_overlap_is_named() {
    // The MPM region from 32 mm: 4 cells of overlap, default w = 5.
    let text = TUBE.replace("lower: (0.03, 0.0, 0.0)", "lower: (0.032, 0.0, 0.0)");
    let e = load_str("bridge2d.ron", &text, &[]).unwrap_err();
    assert_eq!(e.field.as_deref(), Some("pipeline.w"), "{e}");
    assert!(e.position.is_some(), "{e}");
    assert_eq!(
        e.message,
        "the fdm_region and mpm_region overlap by 4 cells (0.008 m) along x but w = 5; \
         move mpm_region's lower x to 0.03 (or fdm_region's upper x to 0.042) or set w: Some(4)"
    );
    assert!(e.to_string().contains("`pipeline.w`"), "{e}");
    // An explicit w, and no move that keeps a valid bridge (20 cells
    // would swallow the FDM region).
    let e = load_str("bridge2d.ron", &with_w(TUBE, "Some(20)"), &[]).unwrap_err();
    assert_eq!(e.field.as_deref(), Some("pipeline.w"), "{e}");
    assert_eq!(
        e.message,
        "the fdm_region and mpm_region overlap by 5 cells (0.01 m) along x but w = 20; set w: Some(5)"
    );
    // Mirrored: the MPM region on the low side, (0, 30) mm, the FDM
    // region (20, 60) mm.
    let text = TUBE
        .replace(
            "fdm_region: (lower: (0.0, 0.0, 0.0), upper: (0.04, 0.02, 0.002))",
            "fdm_region: (lower: (0.02, 0.0, 0.0), upper: (0.06, 0.02, 0.002))",
        )
        .replace(
            "mpm_region: (lower: (0.03, 0.0, 0.0), upper: (0.06, 0.02, 0.002))",
            "mpm_region: (lower: (0.0, 0.0, 0.0), upper: (0.03, 0.02, 0.002)), w: Some(3)",
        );
    let e = load_str("bridge2d.ron", &text, &[]).unwrap_err();
    assert_eq!(e.field.as_deref(), Some("pipeline.w"), "{e}");
    assert_eq!(
        e.message,
        "the fdm_region and mpm_region overlap by 5 cells (0.01 m) along x but w = 3; \
         move mpm_region's upper x to 0.026 (or fdm_region's lower x to 0.024) or set w: Some(5)"
    );
    // Following either suggestion loads.
    for (from, to) in [
        (
            "upper: (0.03, 0.02, 0.002)), w",
            "upper: (0.026, 0.02, 0.002)), w",
        ),
        ("lower: (0.02, 0.0, 0.0)", "lower: (0.024, 0.0, 0.0)"),
    ] {
        assert!(text.contains(from), "{from}");
        load_str("bridge2d.ron", &text.replace(from, to), &[]).unwrap();
    }
}

/// Every bridge config in configs/ states its width or has the
/// default's overlap (the plate cases are w = 4).
#[test]
fn every_bridge_config_has_the_overlap_its_w_says() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../configs");
    let mut bridges = 0;
    for entry in std::fs::read_dir(&dir).unwrap() {
        let path = entry.unwrap().path();
        let text = std::fs::read_to_string(&path).unwrap_or_default();
        if path.extension().is_some_and(|e| e == "ron") && text.contains("FdmMpmBridge(") {
            let loaded =
                crate::load_file(&path, &[]).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
            let Some(b) = loaded
                .scenario
                .pipeline
                .section::<brisance_couple::BridgeConfig>()
            else {
                panic!("{} is a bridge", path.display());
            };
            let w =
                b.w.unwrap_or(brisance_couple::bridge_pipeline::DEFAULT_BRIDGE_WIDTH);
            let described = crate::build::describe(&loaded.scenario);
            assert!(
                described.contains(&format!("w = {w} cells")),
                "{}: {described}",
                path.display()
            );
            bridges += 1;
        }
    }
    assert!(bridges >= 9, "{bridges}");
}

#[test]
fn a_zero_bridge_width_is_refused() {
    let e = load_str("bridge2d.ron", &with_w(TUBE, "Some(0)"), &[]).unwrap_err();
    assert_eq!(e.field.as_deref(), Some("pipeline.w"), "{e}");
    assert!(e.message.contains("w = 0"), "{e}");
    assert!(e.position.is_some(), "{e}");
}

/// A 4 × 2 domain of 1 mm cells, the remap `file` on its cells
/// x = 1..3 (all y), air and TNT products as `Null` fluids, concrete
/// from the library.
fn pure_mpm(file: &str, air: &str) -> String {
    format!(
        r#"Scenario(
    name: "gas_remap",
    domain: (lower: (0.0, 0.0, 0.0), upper: (0.004, 0.002, 0.001), cells: (4, 2, 1)),
    time: (end: 1.0e-6, cfl: 0.4),
    materials: {{
        "air": (model: Null(eos: IdealGas(gamma: 1.4, cv: 717.6, rho0: 1.225))),
        "tnt": (model: Null(eos: Jwl(a: 3.712e11, b: 3.21e9, r1: 4.15, r2: 0.95, omega: 0.3, e0: 6.993e9, rho0: 1630.0, cv: 613.4969325153374))),
        "concrete": (library: "concrete_48mpa"),
    }},
    pipeline: Mpm(ppc: 2, remap: (file: Some("{file}"), air: "{air}", products: "tnt")),
    initial: [
        (region: Everywhere, material: "air", state: (density: 1.225, specific_internal_energy: 2.0685e5)),
        (region: Box(min: (0.003, 0.0, 0.0), max: (0.004, 0.001, 0.001)), material: "concrete", state: (density: 2440.0, temperature: 293.15)),
    ],
    outputs: (fields: ["density"], vtk: false),
)"#
    )
}

/// Writes a remap of 2 × 2 cells of 1 mm from `origin`: cell (0, 0)
/// air (ρ 2, ρu (4, −2, 0), E 10), (1, 0) products (ρ 1000, E 4e9,
/// ρY 800), (0, 1) half products (ρ 1, E 3, ρY 0.5: air), (1, 1) air at
/// rest (ρ 4, E 8).
fn write_remap(tag: &str, origin: [f64; 3]) -> std::path::PathBuf {
    use brisance_couple::{RemapReport, RemapTotals};
    let fields = vec![
        vec![2.0, 1000.0, 1.0, 4.0],
        vec![4.0, 0.0, 0.0, 0.0],
        vec![-2.0, 0.0, 0.0, 0.0],
        vec![0.0; 4],
        vec![10.0, 4.0e9, 3.0, 8.0],
        vec![0.0, 800.0, 0.5, 0.0],
    ];
    let r = brisance_couple::Remapped {
        geometry: brisance_core::UniformGridGeometry {
            origin,
            spacing: [0.001; 3],
            cells: [2, 2, 1],
        },
        fields,
        report: RemapReport {
            charge: RemapTotals::default(),
            ambient: RemapTotals::default(),
            grid_mass: 0.0,
            grid_momentum: [0.0; 3],
            grid_energy: 0.0,
            grid_products: 0.0,
            subsamples: 1,
            radius: 0.0,
            symmetry_planes: 0,
            merged_shells: 0,
            max_correction: 0.0,
        },
    };
    let path = std::env::temp_dir().join(format!(
        "brisance_gas_remap_{}_{tag}.bin",
        std::process::id()
    ));
    r.save(&path).unwrap();
    path
}

#[test]
fn mpm_gas_particles_take_the_remapped_cells_and_conserve_them() {
    use brisance_mpm::MaterialId;
    let path = write_remap("ok", [0.001, 0.0, 0.0]);
    let loaded = load_str(
        "gas_remap.ron",
        &pure_mpm(&path.display().to_string(), "air"),
        &[],
    )
    .unwrap();
    let section = loaded
        .scenario
        .pipeline
        .section::<brisance_couple::MpmConfig>();
    let solver =
        crate::build::build_section(section.expect("an Mpm scenario"), &loaded.scenario).unwrap();
    std::fs::remove_file(&path).unwrap();
    let p = solver.particles();
    // 8 cells × 4 particles; materials numbered by name: air 0,
    // concrete 1, tnt 2.
    assert_eq!(p.len(), 32);
    let v = 1.0e-9 / 4.0;
    // Per remapped cell: (cell x, cell y, material, ρ, u, e).
    let want = [
        (1, 0, 0, 2.0, [2.0, -1.0, 0.0], 2.5),
        (2, 0, 2, 1000.0, [0.0; 3], 4.0e6),
        (1, 1, 0, 1.0, [0.0; 3], 3.0),
        (2, 1, 0, 4.0, [0.0; 3], 2.0),
    ];
    for (i, j, m, rho, u, e) in want {
        let inside: Vec<usize> = (0..p.len())
            .filter(|&k| {
                let x = p.position[k];
                (x[0] * 1e3).floor() as usize == i && (x[1] * 1e3).floor() as usize == j
            })
            .collect();
        assert_eq!(inside.len(), 4);
        for &k in &inside {
            assert_eq!(p.material[k], MaterialId(m));
            assert_eq!(p.mass[k], rho * v);
            assert_eq!(p.velocity[k], u);
            assert_eq!(p.specific_internal_energy[k], e);
        }
        // The cell's mass and total energy E V: 4 m (e + ½|u|²).
        let mass: f64 = inside.iter().map(|&k| p.mass[k]).sum();
        assert!((mass - rho * 1e-9).abs() <= 1e-15 * rho * 1e-9);
        let energy: f64 = inside
            .iter()
            .map(|&k| p.mass[k] * (e + 0.5 * u.iter().map(|c| c * c).sum::<f64>()))
            .sum();
        let total = rho * (e + 0.5 * u.iter().map(|c| c * c).sum::<f64>()) * 1e-9;
        assert!((energy - total).abs() <= 1e-15 * total, "{energy} {total}");
    }
    // The air particle of cell (1, 0): p = 0.4 ρ e = 2 Pa.
    let k = (0..p.len())
        .find(|&k| p.velocity[k] == [2.0, -1.0, 0.0])
        .unwrap();
    assert!((p.stress[k][0] + 2.0).abs() < 1e-14, "{:?}", p.stress[k]);
    assert_eq!(p.stress[k][0], p.stress[k][1]);
    // Outside the remap: the initial regions (air at x < 1 mm, the
    // concrete's cell keeps its material).
    for k in 0..p.len() {
        let x = p.position[k];
        if x[0] < 0.001 {
            assert_eq!((p.material[k], p.mass[k]), (MaterialId(0), 1.225 * v));
            assert_eq!(p.specific_internal_energy[k], 2.0685e5);
        }
        if x[0] > 0.003 && x[1] < 0.001 {
            assert_eq!(p.material[k], MaterialId(1));
        }
    }
}

#[test]
fn a_bad_mpm_remap_is_named() {
    let build_err = |path: &std::path::Path, air: &str| {
        let loaded = load_str(
            "gas_remap.ron",
            &pure_mpm(&path.display().to_string(), air),
            &[],
        )
        .unwrap();
        match crate::build::build_solver(&loaded.scenario) {
            Ok(_) => panic!("built with {} and air `{air}`", path.display()),
            Err(e) => e.to_string(),
        }
    };
    let shifted = write_remap("shifted", [0.0015, 0.0, 0.0]);
    let e = build_err(&shifted, "air");
    assert!(
        e.contains("pipeline.remap.file") && e.contains("does not lie on"),
        "{e}"
    );
    let outside = write_remap("outside", [0.003, 0.0, 0.0]);
    let e = build_err(&outside, "air");
    assert!(e.contains("does not lie on"), "{e}");
    let e = build_err(&outside, "concrete");
    assert!(
        e.contains("pipeline.remap.air") && e.contains("Null"),
        "{e}"
    );
    std::fs::remove_file(&shifted).unwrap();
    std::fs::remove_file(&outside).unwrap();
    let e = build_err(&shifted, "air");
    assert!(
        e.contains("pipeline.remap.file") && e.contains("cannot read"),
        "{e}"
    );
}

/// `RZ_BOX` with the 5-bar region driving a shock onto the disc, and the
/// outputs' `particle_gauges` list `gauges`.
fn rz_shock_with_gauges(gauges: &str) -> String {
    RZ_BOX
        .replace(
            "pressure: 1.0e5)),
    ],",
            &format!("pressure: 1.0e5)),
        (region: HalfSpace(point: (0, 0.01, 0), normal: (0, -1, 0)), material: \"air\", state: (density: 4.9, pressure: 5.0e5)),
        {PLATE}
    ],"),
        )
        .replace("activation_pressure: 5.0e4", "activation_pressure: 1.1e5")
        .replace(
            "vtk: false)",
            &format!("vtk: false, particle_gauges: [{gauges}])"),
        )
}

#[test]
fn particle_gauges_follow_the_bridge_particles_of_a_structure_and_of_the_air() {
    // The disc (r 0–14 mm, z 50–56 mm, its edges on sub-cell boundaries)
    // and the air particles that start between z = 40 and 50 mm. The
    // disc's gauge has its whole mass, π r² L ρ, and the mass-weighted mean
    // velocity of the MPM's steel particles; the shock moves it along +z.
    let text = rz_shock_with_gauges(
        r#"(name: "disc", region: Box(min: (0.0, 0.05, -1.0), max: (0.014, 0.056, 1.0)), material: Some("rha"), quantities: [Mass, MeanVelocity]),
           (name: "air", region: Box(min: (0.0, 0.04, -1.0), max: (0.02, 0.05, 1.0)), material: Some("air"), quantities: [Mass])"#,
    );
    let loaded = load_str("bridge_rz.ron", &text, &[]).unwrap();
    let section = loaded
        .scenario
        .pipeline
        .section::<brisance_couple::BridgeConfig>();
    let mut built =
        crate::build::build_section(section.expect("a bridge scenario"), &loaded.scenario).unwrap();
    let quantities = [
        brisance_mpm::SetQuantity::Mass,
        brisance_mpm::SetQuantity::MeanVelocity,
    ];
    let mut out = Vec::new();
    assert!(built.sample_particle_gauge(0, &quantities, &mut out));
    let pi = std::f64::consts::PI;
    let disc = pi * 0.014f64.powi(2) * 0.006 * 7850.0;
    assert!(
        (out[0] - disc).abs() <= 1e-12 * disc,
        "{} vs {disc}",
        out[0]
    );
    assert_eq!(&out[1..], &[0.0, 0.0, 0.0]);
    assert!(built.sample_particle_gauge(1, &quantities[..1], &mut out));
    let air = pi * 0.02f64.powi(2) * 0.01 * 1.225;
    assert!((out[0] - air).abs() <= 1e-12 * air, "{} vs {air}", out[0]);
    assert!(!built.sample_particle_gauge(2, &quantities, &mut out));
    // The run loop's solver, boxed as any pipeline's, samples the same.
    let boxed = crate::build::build_solver(&loaded.scenario).unwrap();
    let mut again = Vec::new();
    assert!(boxed.sample_particle_gauge(1, &quantities[..1], &mut again));
    assert_eq!(again, out);
    while built.time() < 8.0e-5 {
        let dt = built.stable_dt().unwrap().min(8.0e-5 - built.time());
        built.advance(dt).unwrap();
    }
    assert!(built.sample_particle_gauge(0, &quantities, &mut out));
    let p = built.mpm().particles();
    let steel = (0..p.len()).filter(|&i| p.material[i].0 == 1);
    let (m, mv) = steel.fold((0.0, 0.0), |(m, mv), i| {
        (m + p.mass[i], mv + p.mass[i] * p.velocity[i][1])
    });
    eprintln!("disc: mass {} kg, mean v_z {} m/s", out[0], out[2]);
    assert!((out[0] - m).abs() <= 1e-12 * m);
    assert!((out[2] - mv / m).abs() <= 1e-12 * (mv / m).abs());
    assert!(out[2] > 0.0, "{}", out[2]);
}

#[test]
fn a_bridge_particle_gauge_without_particles_is_named() {
    // A region in the FDM's part only (z < 30 mm) holds no particle.
    let text = rz_shock_with_gauges(
        r#"(name: "low", region: Box(min: (0.0, 0.0, -1.0), max: (0.02, 0.02, 1.0)), material: Some("air"), quantities: [Mass])"#,
    );
    let loaded = load_str("bridge_rz.ron", &text, &[]).unwrap();
    let e = crate::build::build_solver(&loaded.scenario).err().unwrap();
    assert_eq!(
        e.field.as_deref(),
        Some("outputs.particle_gauges.0.region"),
        "{e}"
    );
    assert!(
        e.to_string().contains("no particle of material `air`"),
        "{e}"
    );
}
