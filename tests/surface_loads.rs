//! Surface loads from a scenario file: a free bar pulled at one end by a
//! constant traction accelerates as the load over its mass (read by a
//! particle gauge over the whole bar), and bad loads are refused naming the
//! field.

use std::fs;

use brisance::compose::{build::build_solver, load_str, run, RunOptions};

/// A bar 0 ≤ x ≤ 1 m, 0.25 m² section, 1000 kg/m³ (250 kg), on a 1D grid
/// of 0.025 m cells, 2 particles per cell, pulled on its last particle
/// layer (x > 0.9875) by 1e5 Pa along +x: 2.5e4 N, 100 m/s².
const BAR: &str = r#"Scenario(
    name: "bar",
    domain: (lower: (0.0, 0.0, 0.0), upper: (1.25, 0.5, 0.5), cells: (50, 1, 1)),
    time: (end: 2.0e-3, cfl: 0.4),
    materials: {
        "rubberish": (model: Hypoelastic(shear_modulus: 3.0e7, pressure: Linear(bulk_modulus: 6.0e7), rate: Jaumann)),
    },
    pipeline: Mpm(
        shape_function: Linear, scheme: Musl, ppc: 2,
        surface_loads: [
            (name: "pull", region: Box(min: (0.9875, 0.0, 0.0), max: (1.0, 0.5, 0.5)),
             load: Traction(1.0e5, 0.0, 0.0), normal: (1.0, 0.0, 0.0)),
        ],
    ),
    initial: [
        (region: Box(min: (0.0, 0.0, 0.0), max: (1.0, 0.5, 0.5)), material: "rubberish",
         state: (density: 1000.0, temperature: 300.0)),
    ],
    outputs: (
        vtk: false,
        fields: [],
        particle_gauges: [(name: "bar", region: Everywhere, quantities: [MeanVelocity, Mass])],
    ),
)"#;

#[test]
fn a_free_bar_pulled_at_one_end_accelerates_at_force_over_mass() {
    let dir = tempfile::tempdir().unwrap();
    let loaded = load_str("bar.ron", BAR, &[]).unwrap();
    run(
        &loaded,
        &RunOptions {
            out_dir: dir.path().to_path_buf(),
            ..Default::default()
        },
    )
    .unwrap();
    let text = fs::read_to_string(dir.path().join("particle_gauges/bar.csv")).unwrap();
    let rows: Vec<Vec<f64>> = text
        .lines()
        .skip(1)
        .map(|l| l.split(',').map(|v| v.parse().unwrap()).collect())
        .collect();
    assert!(rows.len() > 10);
    for r in &rows {
        let (t, vx, mass) = (r[0], r[1], r[4]);
        assert_eq!(mass, 250.0);
        assert!(
            (vx - 100.0 * t).abs() <= 1e-10 * (100.0 * t).max(1e-30),
            "t = {t}: mean vx {vx}, expected {}",
            100.0 * t
        );
        assert_eq!((r[2], r[3]), (0.0, 0.0));
    }
    assert_eq!(rows.last().unwrap()[0], 2.0e-3);
}

#[test]
fn the_default_layer_thickness_is_the_particle_spacing_along_the_normal() {
    // With the thickness given as that spacing (0.0125 m) the run is the
    // same to the bit.
    let mut a = build_solver(&load_str("bar.ron", BAR, &[]).unwrap().scenario)
        .ok()
        .unwrap();
    let sets = ["pipeline.surface_loads.0.thickness=Some(0.0125)".to_string()];
    let mut b = build_solver(&load_str("bar.ron", BAR, &sets).unwrap().scenario)
        .ok()
        .unwrap();
    for _ in 0..50 {
        let dt = a.stable_dt().unwrap();
        a.advance(dt).unwrap();
        b.advance(dt).unwrap();
    }
    assert!(a.save_state().unwrap() == b.save_state().unwrap());
    // Half the thickness doubles each particle's area, and the pull.
    let sets = ["pipeline.surface_loads.0.thickness=Some(0.00625)".to_string()];
    let mut c = build_solver(&load_str("bar.ron", BAR, &sets).unwrap().scenario)
        .ok()
        .unwrap();
    let dt = 1e-5;
    c.advance(dt).unwrap();
    let p = c.conservation_totals().momentum[0];
    assert!((p - 5.0e4 * dt).abs() < 1e-10 * 5.0e4 * dt, "{p}");
}

#[test]
fn bad_surface_loads_are_refused_naming_the_field() {
    for (set, field, words) in [
        (
            "pipeline.surface_loads.0.normal=(0.0, 0.0, 0.0)",
            "pipeline.surface_loads.0.normal",
            "non-zero",
        ),
        (
            "pipeline.surface_loads.0.thickness=Some(-1.0)",
            "pipeline.surface_loads.0.thickness",
            "positive",
        ),
        (
            "pipeline.surface_loads.0.history=Table([(1.0, 0.0), (0.5, 1.0)])",
            "pipeline.surface_loads.0.history",
            "increase",
        ),
        (
            "pipeline.surface_loads.0.history=Ramp(rise_time: 0.0)",
            "pipeline.surface_loads.0.history",
            "rise_time",
        ),
        (
            "pipeline.surface_loads.0.material=Some(\"steel\")",
            "pipeline.surface_loads.0.material",
            "not a particle material",
        ),
    ] {
        let err = load_str("bar.ron", BAR, &[set.to_string()]).unwrap_err();
        assert_eq!(err.field.as_deref(), Some(field), "{set}: {err}");
        assert!(err.message.contains(words), "{set}: {err}");
    }
    // A region no particle starts in: an error naming the load.
    let sets = [
        "pipeline.surface_loads.0.region=Box(min: (1.1, 0.0, 0.0), max: (1.2, 0.5, 0.5))"
            .to_string(),
    ];
    let loaded = load_str("bar.ron", BAR, &sets).unwrap();
    let err = build_solver(&loaded.scenario).err().unwrap();
    assert_eq!(
        err.field.as_deref(),
        Some("pipeline.surface_loads.0.region")
    );
    assert!(
        err.message.contains("`pull`") && err.message.contains("no particle"),
        "{err}"
    );
}
