//! The `Peridynamics` pipeline through the composer: the shipped
//! scenarios load, validate, build and run, and their errors name their
//! fields. The pipeline's section, validation and builder are
//! `brisance_pd`'s (`brisance_pd::pipeline`); the composer hands it the
//! scenario's shared parts (`crate::scene::scene_of`).

use crate::build::build_solver;
use crate::load_str;

/// Both reduced peridynamic scenarios load, validate, build and step;
/// a misspelt material is reported with its field path.
#[test]
fn pd_configs_load_build_and_step() {
    for (name, text) in [
        (
            "pd_cylinder.ron",
            include_str!("../../../configs/pd_cylinder.ron"),
        ),
        (
            "pd_fragment.ron",
            include_str!("../../../configs/pd_fragment.ron"),
        ),
    ] {
        let loaded = load_str(name, text, &[]).unwrap_or_else(|e| panic!("{name}: {e}"));
        let mut solver = build_solver(&loaded.scenario).unwrap();
        assert_eq!(solver.name(), "pd");
        let m0 = solver.conservation_totals().mass;
        for _ in 0..3 {
            let dt = solver.stable_dt().unwrap();
            solver.advance(dt).unwrap();
        }
        assert_eq!(solver.conservation_totals().mass, m0);
        assert!(solver.particle_data().unwrap().positions.len() > 1000);
    }
    let text = include_str!("../../../configs/pd_fragment.ron");
    let e = load_str("bad.ron", text, &["initial.1.material=\"stele\"".into()]).unwrap_err();
    assert!(e.to_string().contains("initial.1.material"), "{e}");
}

/// The numbers of a shape, for comparisons to a relative 1e-12 (the
/// configs write the steel tube's outer radius 0.015875 m as one
/// decimal, the cases as 0.0127 + 0.003175).
fn shape_numbers(shape: &brisance_grid::Shape) -> (u8, Vec<f64>) {
    use brisance_grid::Shape;
    match shape {
        Shape::Cylinder {
            base,
            axis,
            radius,
            length,
        } => (0, [&base[..], &axis[..], &[*radius, *length]].concat()),
        Shape::Shell {
            base,
            axis,
            inner_radius,
            outer_radius,
            length,
        } => (
            1,
            [
                &base[..],
                &axis[..],
                &[*inner_radius, *outer_radius, *length],
            ]
            .concat(),
        ),
        other => panic!("not a tube shape: {other:?}"),
    }
}

/// Whether the config's setup is the case's: the same spacing, options,
/// detonation and bodies (each with the same material), whatever the
/// order of the materials.
fn assert_same_case(name: &str, a: &brisance_pd::PdSetup, b: &brisance_pd::PdSetup) {
    assert_eq!(a.options, b.options, "{name}: options");
    assert_eq!(a.detonation, b.detonation, "{name}: detonation");
    assert_eq!(a.boundaries, b.boundaries, "{name}: boundaries");
    assert_eq!(a.bodies.len(), b.bodies.len(), "{name}: bodies");
    for body in &a.bodies {
        let (kind, x) = shape_numbers(&body.shape);
        let twin = b
            .bodies
            .iter()
            .find(|c| {
                let (k, y) = shape_numbers(&c.shape);
                k == kind
                    && x.iter()
                        .zip(&y)
                        .all(|(p, q)| (p - q).abs() <= 1e-12 * p.abs().max(q.abs()))
            })
            .unwrap_or_else(|| panic!("{name}: no body of the case is {:?}", body.shape));
        assert_eq!(body.velocity, twin.velocity, "{name}");
        assert_eq!(
            a.materials[usize::from(body.material)],
            b.materials[usize::from(twin.material)],
            "{name}: material of {:?}",
            body.shape
        );
    }
}

/// The scenario files are the validation's cases: the reduced and the
/// full configs of E-PD-CYL and E-PD-FRAG give the setups of
/// `brisance_pd::cases` at their lengths, and end where the validation
/// reads them (45 µs and 40 µs for the full tubes).
#[test]
fn pd_configs_are_the_cases_the_validation_runs() {
    use brisance_pd::cases::{copper_cylinder, steel_fragmenting_cylinder};
    let h = 1.3e-3;
    for (name, text, case, end) in [
        (
            "pd_cylinder.ron",
            include_str!("../../../configs/pd_cylinder.ron"),
            copper_cylinder(h, 0.03),
            12.0e-6,
        ),
        (
            "pd_cylinder_full.ron",
            include_str!("../../../configs/pd_cylinder_full.ron"),
            copper_cylinder(h, brisance_pd::cases::COPPER_TUBE_LENGTH),
            45.0e-6,
        ),
        (
            "pd_fragment.ron",
            include_str!("../../../configs/pd_fragment.ron"),
            steel_fragmenting_cylinder(h, 0.02, 0.0, 0.0),
            15.0e-6,
        ),
        (
            "pd_fragment_full.ron",
            include_str!("../../../configs/pd_fragment_full.ron"),
            steel_fragmenting_cylinder(h, 0.10795, 0.0, 0.0),
            40.0e-6,
        ),
    ] {
        let loaded = load_str(name, text, &[]).unwrap_or_else(|e| panic!("{name}: {e}"));
        let Some(pd) = loaded.scenario.pipeline.section::<brisance_pd::PdConfig>() else {
            panic!("{name}: not a Peridynamics pipeline");
        };
        let setup = pd.setup(&crate::scene::scene_of(&loaded.scenario)).unwrap();
        assert_same_case(name, &setup, &case.setup().unwrap());
        assert_eq!(loaded.scenario.time.end, end, "{name}");
    }
}

/// The reduced configs run to their end through the run loop: the
/// copper tube's wall gauge moves outward, never back, and stays below
/// the Gurney velocity; the steel tube's fragments (written at the
/// end) hold the case's mass.
#[test]
fn reduced_pd_configs_run_to_their_end() {
    let dir = std::env::temp_dir().join(format!("brisance_pd_configs_{}", std::process::id()));
    let run_config = |name: &str, text: &str| {
        let loaded = load_str(name, text, &[]).unwrap();
        let out = dir.join(name);
        let summary = crate::run(
            &loaded,
            &crate::RunOptions {
                out_dir: out.clone(),
                restart: None,
                progress: false,
            },
        )
        .unwrap();
        assert!(summary.completed, "{name}: {summary:?}");
        assert_eq!(summary.final_time, loaded.scenario.time.end, "{name}");
        out
    };
    let rows = |path: std::path::PathBuf| -> Vec<Vec<f64>> {
        std::fs::read_to_string(&path)
            .unwrap_or_else(|e| panic!("{}: {e}", path.display()))
            .lines()
            .skip(1)
            .map(|l| l.split(',').map(|c| c.parse().unwrap()).collect())
            .collect()
    };
    let out = run_config(
        "pd_cylinder.ron",
        include_str!("../../../configs/pd_cylinder.ron"),
    );
    // time, radial_displacement, velocity_x of the node nearest the
    // gauge point on the outer wall (x axis: v_x is radial there).
    let wall = rows(out.join("gauges").join("wall.csv"));
    let gurney = brisance_pd::cases::copper_cylinder(1.3e-3, 0.03)
        .gurney_wall_velocity()
        .unwrap();
    let last = wall.last().unwrap();
    assert!(last[1] > 0.5e-3, "wall displacement {:?}", last);
    for w in wall.windows(2) {
        assert!(w[1][1] >= w[0][1] - 1e-6, "{:?}", w);
    }
    assert!(last[2] > 0.0 && last[2] < gurney, "{last:?} {gurney}");
    let out = run_config(
        "pd_fragment.ron",
        include_str!("../../../configs/pd_fragment.ron"),
    );
    // rank, mass, nodes, vx, vy, vz, speed
    let fragments = rows(out.join("fragments.csv"));
    let total: f64 = fragments.iter().map(|f| f[1]).sum();
    let nodes: f64 = fragments.iter().map(|f| f[2]).sum();
    // Every steel node is in a fragment, each of mass ρ h³.
    let case = brisance_pd::cases::steel_fragmenting_cylinder(1.3e-3, 0.02, 0.0, 0.0);
    let solver = brisance_pd::PdSolver::new(case.setup().unwrap()).unwrap();
    let steel = solver.materials().iter().filter(|&&m| m == 0).count();
    assert_eq!(nodes, steel as f64);
    let case_mass = 7850.0 * 1.3e-3f64.powi(3) * steel as f64;
    assert!(
        (total - case_mass).abs() <= 1e-12 * case_mass,
        "{total} {case_mass}"
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

/// `gas_viscosity` reaches the solver from the config, and a negative
/// coefficient is refused naming the field.
#[test]
fn gas_viscosity_is_read_and_checked() {
    let text = include_str!("../../../configs/pd_cylinder.ron");
    let ok = "pipeline.gas_viscosity=(linear: 1.0, quadratic: 2.0)";
    let loaded = load_str("v.ron", text, &[ok.into()]).unwrap();
    let Some(pd) = loaded.scenario.pipeline.section::<brisance_pd::PdConfig>() else {
        panic!("not a Peridynamics pipeline");
    };
    assert_eq!(
        pd.gas_viscosity,
        Some(brisance_pd::GasViscosity {
            linear: 1.0,
            quadratic: 2.0,
            shear: 0.0,
            deviatoric: 0.0,
        })
    );
    let shear = "pipeline.gas_viscosity=(linear: 1.0, quadratic: 2.0, shear: 0.5)";
    let loaded = load_str("v.ron", text, &[shear.into()]).unwrap();
    let Some(pd) = loaded.scenario.pipeline.section::<brisance_pd::PdConfig>() else {
        panic!("not a Peridynamics pipeline");
    };
    assert_eq!(pd.gas_viscosity.map(|v| v.shear), Some(0.5));
    let deviatoric = "pipeline.gas_viscosity=(linear: 0.0, quadratic: 0.0, deviatoric: 0.1)";
    let loaded = load_str("v.ron", text, &[deviatoric.into()]).unwrap();
    let Some(pd) = loaded.scenario.pipeline.section::<brisance_pd::PdConfig>() else {
        panic!("not a Peridynamics pipeline");
    };
    assert_eq!(pd.gas_viscosity.map(|v| v.deviatoric), Some(0.1));
    let bad = "pipeline.gas_viscosity=(linear: 0.0, quadratic: 0.0, deviatoric: -0.1)";
    let e = load_str("v.ron", text, &[bad.into()])
        .and_then(|l| crate::build::build_solver(&l.scenario).map(|_| ()))
        .unwrap_err();
    assert_eq!(e.field.as_deref(), Some("pipeline.gas_viscosity"), "{e}");
    assert!(e.to_string().contains("deviatoric"), "{e}");
    let bad = "pipeline.gas_viscosity=(linear: -1.0, quadratic: 2.0)";
    let e = load_str("v.ron", text, &[bad.into()])
        .and_then(|l| crate::build::build_solver(&l.scenario).map(|_| ()))
        .unwrap_err();
    assert_eq!(e.field.as_deref(), Some("pipeline.gas_viscosity"), "{e}");
}

/// The explosive's `reactant` reaches the solver from the config, and
/// an invalid one is refused naming the field.
#[test]
fn reactant_is_read_and_checked() {
    let text = include_str!("../../../configs/pd_cylinder.ron");
    let loaded = load_str("r.ron", text, &[]).unwrap();
    let Some(pd) = loaded.scenario.pipeline.section::<brisance_pd::PdConfig>() else {
        panic!("not a Peridynamics pipeline");
    };
    let Some(brisance_pd::PdMaterialConfig::JwlExplosive { reactant, .. }) =
        pd.materials.get("tnt")
    else {
        panic!("no JWL explosive `tnt`");
    };
    assert_eq!(*reactant, Some(brisance_pd::Reactant::tnt()));
    let bad = "pipeline.materials.tnt.reactant=(n: 0.5, kappa: 1.0e-10)";
    let e = load_str("r.ron", text, &[bad.into()])
        .and_then(|l| crate::build::build_solver(&l.scenario).map(|_| ()))
        .unwrap_err();
    assert_eq!(
        e.field.as_deref(),
        Some("pipeline.materials.tnt.reactant"),
        "{e}"
    );
}

/// `boundaries` reach the solver: in an 8 × 3 × 3 steel bar (h = 1 mm)
/// thrown at (3, −2, 5) m/s, the nodes of the first two planes (fixed)
/// stay at rest at their reference positions, and those of the last
/// two move at exactly v_x = 2.5 m/s, u_x = v_x t, their y and z
/// free.
#[test]
fn boundaries_reach_the_solver() {
    let text = r#"Scenario(
name: "pinned_bar",
domain: (lower: (-0.01, -0.01, -0.01), upper: (0.02, 0.01, 0.01), cells: (3, 2, 2)),
time: (end: 1.0e-6),
materials: {"steel": (library: "steel_4340")},
pipeline: Peridynamics(
    spacing: 1.0e-3,
    materials: {"steel": Proportional(density: 7850.0, sound_speed: 3212.0, kind: MicroElastic)},
    boundaries: [
        (region: Box(min: (-0.001, -0.001, -0.001), max: (0.002, 0.004, 0.004)), velocity: (Some(0.0), Some(0.0), Some(0.0))),
        (region: Box(min: (0.006, -0.001, -0.001), max: (0.009, 0.004, 0.004)), velocity: (Some(2.5), None, None)),
    ],
),
initial: [
    (region: Box(min: (0.0, 0.0, 0.0), max: (0.008, 0.003, 0.003)), material: "steel", state: (density: 7850.0, velocity: (3.0, -2.0, 5.0), pressure: 1.0e5)),
],
outputs: (interval: 1.0e-6, fields: [], vtk: false),
)"#;
    let loaded = load_str("pinned_bar.ron", text, &[]).unwrap();
    let Some(pd) = loaded.scenario.pipeline.section::<brisance_pd::PdConfig>() else {
        panic!("not a Peridynamics pipeline");
    };
    let setup = pd.setup(&crate::scene::scene_of(&loaded.scenario)).unwrap();
    assert_eq!(setup.boundaries.len(), 2);
    assert_eq!(setup.boundaries[0].velocity, [Some(0.0); 3]);
    assert_eq!(setup.boundaries[1].velocity, [Some(2.5), None, None]);
    let mut solver = build_solver(&loaded.scenario).unwrap();
    for _ in 0..10 {
        let dt = solver.stable_dt().unwrap();
        solver.advance(dt).unwrap();
    }
    let t = solver.time();
    let data = solver.particle_data().unwrap();
    assert_eq!(data.positions.len(), 72);
    let field = |name: &str| {
        data.field(name)
            .unwrap_or_else(|| panic!("no field `{name}`"))
    };
    let (ux, uy, uz) = (
        field("displacement_x"),
        field("displacement_y"),
        field("displacement_z"),
    );
    let (vx, vy, vz) = (
        field("velocity_x"),
        field("velocity_y"),
        field("velocity_z"),
    );
    let (mut fixed, mut driven) = (0, 0);
    for (i, y) in data.positions.iter().enumerate() {
        let x0 = y[0] - ux[i];
        if x0 < 0.002 {
            fixed += 1;
            assert_eq!([ux[i], uy[i], uz[i]], [0.0; 3], "node {i}");
            assert_eq!([vx[i], vy[i], vz[i]], [0.0; 3], "node {i}");
        } else if x0 > 0.006 {
            driven += 1;
            assert_eq!(vx[i], 2.5, "node {i}");
            assert!((ux[i] - 2.5 * t).abs() <= 1e-13 * 2.5 * t, "node {i}");
            // Free in z: the initial 5 m/s carries it on.
            assert!(uz[i] > 0.0, "node {i}");
        }
    }
    assert_eq!((fixed, driven), (18, 18));
}

/// Cell fields and line-outs have no grid to live on: asking for them
/// is refused at load time, naming the field, instead of failing at
/// the first output.
#[test]
fn cell_fields_and_lineouts_are_refused_at_load_time() {
    let text = include_str!("../../../configs/pd_fragment.ron");
    let e = load_str("f.ron", text, &["outputs.fields=[\"damage\"]".into()]).unwrap_err();
    assert_eq!(e.field.as_deref(), Some("outputs.fields"), "{e}");
    assert!(e.message.contains("no cell fields"), "{e}");
    let line = "outputs.lineouts=[(name: \"l\", from: (0.0, 0.0, 0.0), to: (0.01, 0.0, 0.0), points: 4, fields: [\"damage\"])]";
    let e = load_str("l.ron", text, &[line.into()]).unwrap_err();
    assert_eq!(e.field.as_deref(), Some("outputs.lineouts"), "{e}");
}

/// The run loop writes the fragments: two separate steel blocks (27
/// and 8 nodes of h = 1 mm, further apart than the horizon, so no
/// bond or contact joins them) flying apart at ±10 m/s are two
/// fragments of exactly 27ρh³ and 8ρh³ whose velocities stay ±10 m/s;
/// `fragments.csv` and `cmd.csv` are written at the end and
/// `fragments/*_<index>.csv` at every output.
#[test]
fn run_loop_writes_fragments_and_cmd() {
    let text = r#"Scenario(
name: "two_blocks",
domain: (lower: (-0.01, -0.01, -0.01), upper: (0.02, 0.01, 0.01), cells: (3, 2, 2)),
time: (end: 2.0e-7),
materials: {"steel": (library: "steel_4340")},
pipeline: Peridynamics(
    spacing: 1.0e-3,
    materials: {"steel": Proportional(density: 7850.0, sound_speed: 3212.0, critical_stretch: Some(0.11), kind: MicroElastic)},
),
initial: [
    (region: Box(min: (0.0, 0.0, 0.0), max: (0.003, 0.003, 0.003)), material: "steel", state: (density: 7850.0, velocity: (10.0, 0.0, 0.0), pressure: 1.0e5)),
    (region: Box(min: (0.01, 0.0, 0.0), max: (0.012, 0.002, 0.002)), material: "steel", state: (density: 7850.0, velocity: (-10.0, 0.0, 0.0), pressure: 1.0e5)),
],
outputs: (interval: 1.0e-7, fields: [], vtk: false),
)"#;
    let loaded = load_str("two_blocks.ron", text, &[]).unwrap();
    let dir = std::env::temp_dir().join(format!("brisance_pd_run_{}", std::process::id()));
    let summary = crate::run(
        &loaded,
        &crate::RunOptions {
            out_dir: dir.clone(),
            restart: None,
            progress: false,
        },
    )
    .unwrap();
    assert!(summary.completed);
    let read = |f: &str| std::fs::read_to_string(dir.join(f)).unwrap();
    let m = |n: f64| 7850.0 * n * 1.0e-9;
    let rows: Vec<Vec<f64>> = read("fragments.csv")
        .lines()
        .skip(1)
        .map(|l| l.split(',').map(|c| c.parse().unwrap()).collect())
        .collect();
    assert_eq!(rows.len(), 2);
    // rank, mass, nodes, vx, vy, vz, speed
    assert_eq!(rows[0][2], 27.0);
    assert!(
        (rows[0][1] - m(27.0)).abs() <= 1e-15 * m(27.0),
        "{:?}",
        rows[0]
    );
    assert_eq!(&rows[0][3..], &[10.0, 0.0, 0.0, 10.0]);
    assert_eq!(rows[1][2], 8.0);
    assert!(
        (rows[1][1] - m(8.0)).abs() <= 1e-15 * m(8.0),
        "{:?}",
        rows[1]
    );
    assert_eq!(&rows[1][3..], &[-10.0, 0.0, 0.0, 10.0]);
    let cmd: Vec<Vec<f64>> = read("cmd.csv")
        .lines()
        .skip(1)
        .map(|l| l.split(',').map(|c| c.parse().unwrap()).collect())
        .collect();
    assert_eq!(cmd.len(), 2);
    assert_eq!((cmd[0][1], cmd[1][1]), (1.0, 2.0));
    assert!((cmd[0][2] - 27.0 / 35.0).abs() < 1e-15);
    assert_eq!(cmd[1][2], 1.0);
    for k in 0..3 {
        assert_eq!(
            read(&format!("fragments/fragments_{k:05}.csv"))
                .lines()
                .count(),
            3
        );
        assert_eq!(
            read(&format!("fragments/cmd_{k:05}.csv")).lines().count(),
            3
        );
    }
    std::fs::remove_dir_all(&dir).unwrap();
}
