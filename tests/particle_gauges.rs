//! Particle gauges through the whole run loop: a block translating rigidly
//! at (2, −1, 0) m/s beside a block at rest; the gauge of the moving block's
//! starting region writes its mean velocity, displacement and mass to
//! `particle_gauges/moving.csv` every step, a restart continues it
//! bit-identically, and the summary reports particle-steps/s.

use std::fs;
use std::path::Path;

use brisance::compose::{build::build_solver, load_str, run, RunOptions};

/// 8 × 8 cells of 1/8 m, 1/8 m thick; two soft blocks, 2 × 2 particles per
/// cell; free-flying, so no face is touched.
const BLOCKS: &str = r#"Scenario(
    name: "blocks",
    domain: (lower: (0.0, 0.0, 0.0), upper: (1.0, 1.0, 0.125), cells: (8, 8, 1)),
    time: (end: 0.03125, cfl: 0.4),
    materials: {
        "soft": (model: Hypoelastic(shear_modulus: 5.0e6, pressure: Linear(bulk_modulus: 1.0e7), rate: Jaumann)),
        "hard": (model: Hypoelastic(shear_modulus: 5.0e7, pressure: Linear(bulk_modulus: 1.0e8), rate: Jaumann)),
    },
    pipeline: Mpm(shape_function: Linear, scheme: Musl, ppc: 2),
    initial: [
        (region: Box(min: (0.125, 0.25, 0.0), max: (0.375, 0.5, 0.125)), material: "soft",
         state: (density: 1024.0, velocity: (2.0, -1.0, 0.0), temperature: 300.0)),
        (region: Box(min: (0.625, 0.625, 0.0), max: (0.875, 0.875, 0.125)), material: "hard",
         state: (density: 1024.0, temperature: 300.0)),
    ],
    outputs: (
        interval: 0.015625,
        vtk: false,
        fields: [],
        particle_gauges: [
            (name: "moving", region: Box(min: (0.0, 0.0, 0.0), max: (0.5, 0.5, 0.125)),
             quantities: [MeanVelocity, MeanDisplacement, Mass]),
            (name: "hard_block", region: Everywhere, material: Some("hard"),
             quantities: [MeanVelocity]),
        ],
        checkpoint_every: Some(4),
    ),
)"#;

fn read_csv(path: &Path) -> (Vec<String>, Vec<Vec<f64>>) {
    let text = fs::read_to_string(path).unwrap();
    let mut lines = text.lines();
    let header = lines.next().unwrap().split(',').map(String::from).collect();
    let rows = lines
        .map(|l| l.split(',').map(|v| v.parse().unwrap()).collect())
        .collect();
    (header, rows)
}

#[test]
fn a_particle_gauge_follows_a_translating_block_and_survives_a_restart() {
    let dir = tempfile::tempdir().unwrap();
    let loaded = load_str("blocks.ron", BLOCKS, &[]).unwrap();
    let a = dir.path().join("A");
    let summary = run(
        &loaded,
        &RunOptions {
            out_dir: a.clone(),
            ..Default::default()
        },
    )
    .unwrap();
    assert_eq!(summary.throughput_unit, "particle-steps/s");
    assert!(summary.throughput > 0.0);

    let (header, rows) = read_csv(&a.join("particle_gauges/moving.csv"));
    assert_eq!(
        header,
        [
            "time",
            "mean_velocity_x",
            "mean_velocity_y",
            "mean_velocity_z",
            "mean_displacement_x",
            "mean_displacement_y",
            "mean_displacement_z",
            "mass"
        ]
    );
    // One row at t = 0 and one per step.
    assert_eq!(rows.len() as u64, summary.steps + 1);
    // The block: 2 × 2 cells of 1/8 m, 1/8 m thick, at 1024 kg/m³.
    let mass = 1024.0 * 0.25 * 0.25 * 0.125;
    for r in &rows {
        let t = r[0];
        assert!((r[1] - 2.0).abs() < 1e-12, "{r:?}");
        assert!((r[2] + 1.0).abs() < 1e-12, "{r:?}");
        assert!(r[3].abs() < 1e-12, "{r:?}");
        assert!((r[4] - 2.0 * t).abs() < 1e-12, "{r:?}");
        assert!((r[5] + t).abs() < 1e-12, "{r:?}");
        assert!(r[6].abs() < 1e-12, "{r:?}");
        assert!((r[7] - mass).abs() < 1e-12 * mass, "{r:?}");
    }
    assert_eq!(rows.last().unwrap()[0], 0.03125);
    let (_, still) = read_csv(&a.join("particle_gauges/hard_block.csv"));
    assert!(still.iter().all(|r| r[1..].iter().all(|v| v.abs() < 1e-12)));

    // Restart from a checkpoint in the middle: the same gauge file.
    let middle = crate::restart::middle_checkpoint(&a);
    let b = dir.path().join("B");
    run(
        &loaded,
        &RunOptions {
            out_dir: b.clone(),
            restart: Some(middle),
            ..Default::default()
        },
    )
    .unwrap();
    for name in ["moving", "hard_block"] {
        let file = format!("particle_gauges/{name}.csv");
        assert_eq!(
            fs::read(a.join(&file)).unwrap(),
            fs::read(b.join(&file)).unwrap(),
            "{file} after the restart"
        );
    }
}

#[test]
fn a_particle_gauge_that_selects_nothing_is_an_error_naming_it() {
    let sets = [
        "outputs.particle_gauges.0.region=Sphere(centre: (0.9, 0.1, 0.06), radius: 0.05)"
            .to_string(),
    ];
    let loaded = load_str("blocks.ron", BLOCKS, &sets).unwrap();
    let err = build_solver(&loaded.scenario).err().unwrap();
    assert_eq!(
        err.field.as_deref(),
        Some("outputs.particle_gauges.0.region")
    );
    assert!(
        err.message.contains("`moving`") && err.message.contains("no particle"),
        "{err}"
    );
    // A material filter that excludes every particle of the region.
    let sets = ["outputs.particle_gauges.0.material=Some(\"hard\")".to_string()];
    let loaded = load_str("blocks.ron", BLOCKS, &sets).unwrap();
    let err = build_solver(&loaded.scenario).err().unwrap();
    assert!(err.message.contains("of material `hard`"), "{err}");
    // Through the run entry point the error is located in the file.
    let dir = tempfile::tempdir().unwrap();
    let err = run(
        &loaded,
        &RunOptions {
            out_dir: dir.path().join("C"),
            ..Default::default()
        },
    )
    .unwrap_err()
    .to_string();
    assert!(
        err.contains("blocks.ron") && err.contains("moving"),
        "{err}"
    );
}

#[test]
fn particle_gauges_are_checked_before_the_run() {
    for (set, field, words) in [
        (
            "outputs.particle_gauges.0.quantities=[]",
            "outputs.particle_gauges.0.quantities",
            "at least one quantity",
        ),
        (
            "outputs.particle_gauges.1.name=\"moving\"",
            "outputs.particle_gauges.1.name",
            "unique",
        ),
        (
            "outputs.particle_gauges.1.material=Some(\"steel\")",
            "outputs.particle_gauges.1.material",
            "not a particle material",
        ),
    ] {
        let err = load_str("blocks.ron", BLOCKS, &[set.to_string()]).unwrap_err();
        assert_eq!(err.field.as_deref(), Some(field), "{set}: {err}");
        assert!(err.message.contains(words), "{set}: {err}");
    }
    // Only particle pipelines have particles to follow.
    let sod = include_str!("../configs/sod.ron");
    let err = load_str(
        "sod.ron",
        sod,
        &[
            "outputs.particle_gauges=[(name: \"g\", region: Everywhere, quantities: [Mass])]"
                .to_string(),
        ],
    )
    .unwrap_err();
    assert_eq!(err.field.as_deref(), Some("outputs.particle_gauges.0"));
    assert!(err.message.contains("Mpm"), "{err}");
}
