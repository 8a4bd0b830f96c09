use super::*;
use crate::load_str;
use brisance_constitutive::SpecificHeat;

const TAYLOR: &str = include_str!("../../../../configs/taylor2d.ron");
const SOD: &str = include_str!("../../../../configs/sod.ron");
const PRODUCTS_TUBE: &str = include_str!("../../../../configs/fdm_products_tube.ron");
const RZ_BLAST: &str = include_str!("../../../../configs/rz_blast.ron");

fn pressure_at(solver: &dyn Solver, x: [f64; 3]) -> f64 {
    let mut out = Vec::new();
    solver.sample(x, &["pressure".into()], &mut out).unwrap();
    out[0]
}

#[test]
fn an_axisymmetric_fdm_scenario_fills_the_rings_of_a_hemisphere_on_the_axis() {
    let loaded = load_str("rz_blast.ron", RZ_BLAST, &[]).unwrap();
    assert!(describe(&loaded.scenario).contains("2D Axisymmetric"));
    let solver = build_solver(&loaded.scenario).unwrap();
    // The sphere at (0, 1, 0) of radius 0.2 is the half disc of the
    // (r, z) plane; points are (r, z, ·), the third coordinate ignored.
    assert_eq!(pressure_at(&*solver, [0.01, 1.0, 0.0]), 1.0e6);
    assert_eq!(pressure_at(&*solver, [0.15, 1.1, 0.015]), 1.0e6);
    assert_eq!(pressure_at(&*solver, [0.25, 1.0, 0.0]), 1.0e5);
    assert_eq!(pressure_at(&*solver, [0.01, 1.25, 0.0]), 1.0e5);
    // Its mass is the ball's, over ring volumes: the cylinder of air
    // π·1²·2 at 1.2 plus (5 − 1.2)·(4/3)π·0.2³, to the staircase of
    // 0.02 m cells (within 2 %).
    let m = solver.conservation_totals().mass;
    let pi = std::f64::consts::PI;
    let (air, ball) = (1.2 * pi * 2.0, 3.8 * 4.0 / 3.0 * pi * 0.008);
    assert!(((m - air) / ball - 1.0).abs() < 0.02, "{m} {air} {ball}");
}

#[test]
fn an_axisymmetric_fdm_scenario_runs_and_conserves_until_the_blast_leaves() {
    let loaded = load_str("rz_blast.ron", RZ_BLAST, &[]).unwrap();
    let mut solver = build_solver(&loaded.scenario).unwrap();
    let t0 = solver.conservation_totals();
    for _ in 0..40 {
        let dt = solver.stable_dt().unwrap();
        solver.advance(dt).unwrap();
    }
    let t1 = solver.conservation_totals();
    assert!(((t1.mass - t0.mass) / t0.mass).abs() < 1e-13);
    assert!(((t1.energy - t0.energy) / t0.energy).abs() < 1e-13);
    // The blast has reached the axis gauge's neighbourhood from the
    // sphere, and the planar run of the same text differs.
    assert!(pressure_at(&*solver, [0.0, 1.3, 0.0]) > 1.05e5);
}

#[test]
fn the_same_text_runs_as_a_planar_grid_with_the_cartesian_geometry() {
    let set = ["domain.geometry=Cartesian".to_string()];
    let planar = load_str("rz_blast.ron", RZ_BLAST, &set).unwrap();
    let axi = load_str("rz_blast.ron", RZ_BLAST, &[]).unwrap();
    let (a, b) = (
        build_solver(&planar.scenario).unwrap(),
        build_solver(&axi.scenario).unwrap(),
    );
    // The box 1 × 2 × 0.02 against the cylinder π·1²·2.
    let (ma, mb) = (a.conservation_totals().mass, b.conservation_totals().mass);
    assert!(ma < 0.1 && mb > 7.0, "{ma} {mb}");
}

#[test]
fn axisymmetric_load_errors_name_their_key() {
    for (set, key) in [
        ("domain.cells=(50,100,2)", "domain.cells.2"),
        ("domain.lower=(-0.1,0,0)", "domain.lower.0"),
        ("boundaries.x_low=Outflow", "boundaries.x_low"),
        ("domain.patches=(11,1,1)", "domain.patches.0"),
    ] {
        let err = load_str("rz_blast.ron", RZ_BLAST, &[set.to_string()]).unwrap_err();
        assert_eq!(err.field.as_deref(), Some(key), "{set}: {err}");
    }
    // Off the axis the low radial face may be open.
    let sets = [
        "domain.lower=(0.2,0,0)".to_string(),
        "boundaries.x_low=Outflow".to_string(),
        "outputs.gauges=[]".to_string(),
        "outputs.lineouts=[]".to_string(),
    ];
    let loaded = load_str("rz_blast.ron", RZ_BLAST, &sets).unwrap();
    build_solver(&loaded.scenario).unwrap();
}

#[test]
fn the_products_tube_builds_two_species_and_conserves() {
    let loaded = load_str("fdm_products_tube.ron", PRODUCTS_TUBE, &[]).unwrap();
    let mut solver = build_solver(&loaded.scenario).unwrap();
    assert!(solver
        .cell_field_names()
        .contains(&"products_mass_fraction"));
    let y0 = solver
        .cell_data(&["products_mass_fraction".to_string()])
        .unwrap()
        .fields[0]
        .1
        .clone();
    // Products left of the diaphragm, air right of it.
    assert_eq!((y0[0], y0[99], y0[100], y0[199]), (1.0, 1.0, 0.0, 0.0));
    let p0 = solver.cell_data(&["pressure".to_string()]).unwrap().fields[0].1[0];
    assert!((p0 - 1.0e6).abs() < 1e-6 * 1.0e6, "{p0}");
    let t0 = solver.conservation_totals();
    for _ in 0..20 {
        let dt = solver.stable_dt().unwrap();
        solver.advance(dt).unwrap();
    }
    // Nothing has reached the outflow face yet: mass is conserved.
    let t1 = solver.conservation_totals();
    assert!((t1.mass - t0.mass).abs() < 1e-13 * t0.mass);
    let y = solver
        .cell_data(&["products_mass_fraction".to_string()])
        .unwrap()
        .fields[0]
        .1
        .clone();
    assert!(y.iter().all(|y| (0.0..=1.0).contains(y)));
}

#[test]
fn unknown_products_material_is_named() {
    let err = load_str(
        "fdm_products_tube.ron",
        PRODUCTS_TUBE,
        &["pipeline.products=Some(\"tnt2\")".into()],
    )
    .and_then(|l| build_solver(&l.scenario).map(|_| ()))
    .unwrap_err()
    .to_string();
    assert!(err.contains("products"), "{err}");
}

#[test]
fn the_mpm_scenario_builds_particles_and_steps() {
    // A bar aligned with the 0.5 mm cells: 8 x 50 cells, 2 x 2 particles each.
    let sets = ["initial.0.region.max=(0.004, 0.025, 0.001)".to_string()];
    let loaded = load_str("taylor2d.ron", TAYLOR, &sets).unwrap();
    let mut solver = build_solver(&loaded.scenario).unwrap();
    assert_eq!(solver.name(), "mpm");
    assert_eq!(solver.work_per_step().0, (8 * 50 * 4) as f64);
    let t0 = solver.conservation_totals();
    let expected_mass = 8930.0 * 0.004 * 0.025 * 0.001;
    assert!(
        (t0.mass - expected_mass).abs() < 1e-9 * expected_mass,
        "mass {}",
        t0.mass
    );
    assert!((t0.momentum[1] + 190.0 * expected_mass).abs() < 1e-9 * expected_mass * 190.0);
    for _ in 0..5 {
        let dt = solver.stable_dt().unwrap();
        solver.advance(dt).unwrap();
    }
    assert_eq!(
        solver.conservation_totals().mass.to_bits(),
        t0.mass.to_bits()
    );
}

#[test]
fn bulk_viscosity_is_off_by_default_and_on_takes_ls_dyna_defaults() {
    use crate::config::BulkViscosityConfig;
    let loaded = load_str("taylor2d.ron", TAYLOR, &[]).unwrap();
    let Some(mpm) = loaded
        .scenario
        .pipeline
        .section::<brisance_couple::MpmConfig>()
    else {
        panic!("taylor2d is an Mpm scenario");
    };
    assert_eq!(mpm.bulk_viscosity, BulkViscosityConfig::Off);
    for (set, want) in [
        ("pipeline.bulk_viscosity=On()", (1.5, 0.06)),
        ("pipeline.bulk_viscosity=On(linear: 0.2)", (1.5, 0.2)),
        (
            "pipeline.bulk_viscosity=On(quadratic: 2.0, linear: 0.2)",
            (2.0, 0.2),
        ),
    ] {
        let loaded = load_str("taylor2d.ron", TAYLOR, &[set.to_string()]).unwrap();
        let Some(mpm) = loaded
            .scenario
            .pipeline
            .section::<brisance_couple::MpmConfig>()
        else {
            unreachable!()
        };
        let v = mpm.bulk_viscosity.option().unwrap();
        assert_eq!((v.quadratic, v.linear), want, "{set}");
        assert!(describe(&loaded.scenario).contains(&format!("Q1 = {}", want.0)));
    }
    let err = load_str(
        "taylor2d.ron",
        TAYLOR,
        &["pipeline.bulk_viscosity=On(quadratic: -1.0)".to_string()],
    )
    .unwrap_err();
    assert_eq!(
        err.field.as_deref(),
        Some("pipeline.bulk_viscosity.quadratic")
    );
}

#[test]
fn shells_contain_the_annulus_only() {
    let shell = crate::config::Region::Shell {
        base: [0.0; 3],
        axis: [0.0, 0.0, 2.0],
        inner_radius: 1.0,
        outer_radius: 2.0,
        length: 3.0,
    };
    assert!(shell.contains([1.5, 0.0, 1.0]));
    assert!(!shell.contains([0.5, 0.0, 1.0]));
    assert!(!shell.contains([2.5, 0.0, 1.0]));
    assert!(!shell.contains([1.5, 0.0, 3.5]));
}

#[test]
fn pipeline_specific_boundaries_are_rejected_where_they_do_not_apply() {
    let err = load_str("sod.ron", SOD, &["boundaries.x_low=Wall".into()]).unwrap_err();
    assert_eq!(err.field.as_deref(), Some("boundaries.x_low"));
    let err = load_str(
        "taylor2d.ron",
        TAYLOR,
        &[
            "boundaries.x_low=Periodic".into(),
            "boundaries.x_high=Periodic".into(),
        ],
    )
    .unwrap_err();
    assert!(err.message.contains("Mpm pipeline takes"), "{err}");
}

#[test]
fn an_mpm_material_needs_a_constitutive_model() {
    let text = TAYLOR
        .replace(
            "\"copper\": (",
            "\"air\": (library: \"air\"),\n        \"copper\": (",
        )
        .replace("material: \"copper\"", "material: \"air\"");
    let err = load_str("t.ron", &text, &[]).unwrap_err();
    assert_eq!(err.field.as_deref(), Some("initial.0.material"));
    assert!(err.message.contains("constitutive"), "{err}");
}

/// taylor2d.ron with `thermal: <thermal>` on its copper.
fn taylor_with_thermal(thermal: &str) -> String {
    let anchor = "            ),\n        ),\n    },\n    pipeline";
    assert!(TAYLOR.contains(anchor));
    TAYLOR.replace(
        anchor,
        &format!(
            "            ),\n            thermal: {thermal},\n        ),\n    }},\n    pipeline"
        ),
    )
}

/// A pipeline without particles holds no particle gauge; an `Mpm` run
/// holds one per `outputs.particle_gauges` entry, sampled through the
/// boxed solver the run loop drives.
#[test]
fn only_particle_pipelines_sample_particle_gauges() {
    let q = [brisance_mpm::SetQuantity::Mass];
    let mut out = Vec::new();
    let sod = build_solver(&load_str("sod.ron", SOD, &[]).unwrap().scenario).unwrap();
    assert!(!sod.sample_particle_gauge(0, &q, &mut out));
    let gauge = "outputs.particle_gauges=[(name: \"all\", region: Everywhere, quantities: [Mass])]";
    let loaded = load_str("t.ron", TAYLOR, &[gauge.to_string()]).unwrap();
    let mpm = build_solver(&loaded.scenario).unwrap();
    assert!(mpm.sample_particle_gauge(0, &q, &mut out));
    assert!(!mpm.sample_particle_gauge(1, &q, &mut out));
    let total = mpm.conservation_totals().mass;
    assert!(
        (out[0] - total).abs() <= 1e-12 * total,
        "{out:?} vs {total}"
    );
}

/// The MPM solver of an `Mpm` scenario, by its section's type.
fn mpm_build(s: &Scenario) -> brisance_mpm::MpmSolver {
    let section = s.pipeline.section::<brisance_couple::MpmConfig>();
    build_section(section.expect("an Mpm pipeline"), s).unwrap()
}

/// The 1-based line and column of the value of the first `key: value`
/// `needle` in `text` (where an error about that field points).
fn line_col_of(text: &str, needle: &str) -> (usize, usize) {
    let value = text.find(needle).unwrap() + needle.find(": ").unwrap() + 2;
    crate::ron_path::line_col(text, value)
}

#[test]
fn a_thermal_entry_turns_on_the_heat_conduction_of_its_particles() {
    // The specific heat is the ElasticPlastic model's (383) unless given.
    for (thermal, c) in [
        ("(conductivity: 386.0)", 383.0),
        ("(conductivity: 386.0, specific_heat: Some(385.0))", 385.0),
        ("(conductivity: 386.0, specific_heat: 385.0)", 385.0),
    ] {
        let loaded = load_str("t.ron", &taylor_with_thermal(thermal), &[]).unwrap();
        let built = mpm_build(&loaded.scenario);
        assert_eq!(
            built.thermal_properties(),
            &[brisance_mpm::ThermalProperties {
                conductivity: 386.0,
                specific_heat: SpecificHeat::Constant(c)
            }],
            "{thermal}"
        );
    }
}

#[test]
fn a_scenario_without_thermal_builds_and_steps_as_before() {
    let run = |text: &str| {
        let loaded = load_str("t.ron", text, &[]).unwrap();
        let mut built = mpm_build(&loaded.scenario);
        for _ in 0..5 {
            let dt = built.stable_dt().unwrap();
            built.advance(dt).unwrap();
        }
        (loaded.scenario, built)
    };
    let (plain_scenario, plain) = run(TAYLOR);
    assert!(plain.thermal_properties().is_empty());
    // Written back, a scenario without the key does not gain it.
    assert!(!ron::to_string(&plain_scenario).unwrap().contains("thermal"));
    // No conductivity: the option stays off and the steps are the same.
    let (_, off) = run(&taylor_with_thermal("(conductivity: 0.0)"));
    assert!(off.thermal_properties().is_empty());
    let (a, b) = (plain.particles(), off.particles());
    assert_eq!(a.position, b.position);
    assert_eq!(a.velocity, b.velocity);
    assert_eq!(a.stress, b.stress);
    assert_eq!(a.temperature, b.temperature);
}

#[test]
fn bad_thermal_values_name_their_field_and_line() {
    for (thermal, field, needle, message) in [
        (
            "(conductivity: -1.0)",
            "materials.copper.thermal.conductivity",
            "conductivity: -1.0",
            "finite and ≥ 0",
        ),
        (
            "(conductivity: inf)",
            "materials.copper.thermal.conductivity",
            "conductivity: inf",
            "finite and ≥ 0",
        ),
        (
            "(conductivity: 386.0, specific_heat: Some(0.0))",
            "materials.copper.thermal.specific_heat",
            "specific_heat: Some(0.0)",
            "finite and > 0",
        ),
    ] {
        let text = taylor_with_thermal(thermal);
        let e = load_str("t.ron", &text, &[]).unwrap_err();
        assert_eq!(e.field.as_deref(), Some(field), "{e}");
        assert_eq!(e.position, Some(line_col_of(&text, needle)), "{e}");
        assert!(e.message.contains(message), "{e}");
        assert!(e.to_string().starts_with("t.ron:"), "{e}");
    }
    // An unknown field inside `thermal` is refused by the parser.
    let e = load_str(
        "t.ron",
        &taylor_with_thermal("(conductivity: 1.0, cp: 383.0)"),
        &[],
    )
    .unwrap_err();
    assert!(e.message.contains("cp"), "{e}");
    // A conducting material whose model has no specific heat must give one.
    let hypo = taylor_with_thermal("(conductivity: 386.0)").replace(
        "ElasticPlastic(\n                shear_modulus: 43.8e9,\n                pressure: Linear(bulk_modulus: 117.0e9),\n                flow_stress: Constant(sigma_y: 70.0e6),\n                damage: None,\n                rate: Jaumann,\n                taylor_quinney: 0.9,\n                specific_heat: 383.0,\n            )",
        "Hypoelastic(shear_modulus: 43.8e9, pressure: Linear(bulk_modulus: 117.0e9))",
    );
    assert!(hypo.contains("Hypoelastic"));
    let e = load_str("t.ron", &hypo, &[]).unwrap_err();
    assert_eq!(e.field.as_deref(), Some("materials.copper.thermal"), "{e}");
    assert!(e.message.contains("give `specific_heat`"), "{e}");
    let text = hypo.replace(
        "(conductivity: 386.0)",
        "(conductivity: 386.0, specific_heat: 385.0)",
    );
    let built = mpm_build(&load_str("t.ron", &text, &[]).unwrap().scenario);
    assert_eq!(
        built.thermal_properties()[0].specific_heat,
        SpecificHeat::Constant(385.0)
    );
}

/// `specific_heat: Curie(...)` (the 4340 steel's c_v(T), seed 000 §5.3)
/// loads, builds and steps like a number; a bad constant names its field
/// and line, and a conducting material with it conducts through the curve
/// (or through the constant its `thermal` gives).
#[test]
fn a_specific_heat_that_follows_the_temperature_reads_from_a_config() {
    let curie = "Curie(t_c: 1040.0, a0: 190.14, b0: 273.75, c0: 418.3, n0: 0.2, \
                 a1: 465.21, b1: 267.52, c1: 58.16, n1: 0.35)";
    let number = "specific_heat: 383.0,";
    assert!(TAYLOR.contains(number));
    let text = TAYLOR.replace(number, &format!("specific_heat: {curie},"));
    let loaded = load_str("t.ron", &text, &[]).unwrap();
    let mut built = mpm_build(&loaded.scenario);
    for _ in 0..3 {
        let dt = built.stable_dt().unwrap();
        built.advance(dt).unwrap();
    }
    let bad = text.replace("n0: 0.2", "n0: 1.5");
    let e = load_str("t.ron", &bad, &[]).unwrap_err();
    assert!(e.to_string().contains("specific_heat.n0"), "{e}");
    assert!(e.to_string().starts_with("t.ron:"), "{e}");
    let unknown = text.replace("n1: 0.35", "n2: 0.35");
    let e = load_str("t.ron", &unknown, &[]).unwrap_err();
    assert!(e.to_string().starts_with("t.ron:"), "{e}");
    // A conducting material takes the model's curve, unless its `thermal`
    // gives a constant.
    for (thermal, c) in [
        ("(conductivity: 386.0)", SpecificHeat::steel_4340()),
        (
            "(conductivity: 386.0, specific_heat: 385.0)",
            SpecificHeat::Constant(385.0),
        ),
    ] {
        let conducting =
            taylor_with_thermal(thermal).replace(number, &format!("specific_heat: {curie},"));
        let mut built = mpm_build(&load_str("t.ron", &conducting, &[]).unwrap().scenario);
        assert_eq!(built.thermal_properties()[0].specific_heat, c, "{thermal}");
        let dt = built.stable_dt().unwrap();
        built.advance(dt).unwrap();
    }
}

#[test]
fn thermal_on_a_material_without_particles_is_refused() {
    // A gas of the Fdm pipeline.
    let text = SOD.replace(
        "\"gas\": (eos: IdealGas(gamma: 1.4, cv: 1.0, rho0: 1.0)),",
        "\"gas\": (eos: IdealGas(gamma: 1.4, cv: 1.0, rho0: 1.0), thermal: (conductivity: 0.025)),",
    );
    let e = load_str("sod.ron", &text, &[]).unwrap_err();
    assert_eq!(e.field.as_deref(), Some("materials.gas.thermal"), "{e}");
    assert_eq!(e.position, Some(line_col_of(&text, "thermal: ")), "{e}");
    assert!(
        e.message.contains("Fdm pipeline has no heat conduction"),
        "{e}"
    );
    // A material of an Mpm scenario without a constitutive model.
    let text = taylor_with_thermal("(conductivity: 386.0)").replace(
        "\"copper\": (",
        "\"air\": (eos: IdealGas(gamma: 1.4, cv: 717.5), thermal: (conductivity: 0.025)),\n        \"copper\": (",
    );
    let e = load_str("t.ron", &text, &[]).unwrap_err();
    assert_eq!(e.field.as_deref(), Some("materials.air.thermal"), "{e}");
    assert!(e.message.contains("no constitutive `model`"), "{e}");
}
