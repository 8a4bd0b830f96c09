use brisance_ice::cases::sod_one;

use crate::build::build_solver;
use crate::load_str;

const SOD: &str = include_str!("../../../../configs/sod_ice.ron");

/// The Sod tube of configs/sod_ice.ron at 100 cells: mass is conserved
/// to round-off (no wave reaches the ends by t = 0.2), the density
/// equals the ICE crate's own Sod case at the same resolution, and the
/// plateau between contact and shock is near Toro's exact ρ*R.
#[test]
fn sod_ice_config_matches_the_crate_case() {
    let loaded = load_str("sod_ice.ron", SOD, &["domain.cells=(100,1,1)".into()]).unwrap();
    let mut solver = build_solver(&loaded.scenario).unwrap();
    let before = solver.conservation_totals();
    // The step sequence of `run_to`, through the trait object.
    let mut steps = 0;
    while solver.time() < 0.2 * (1.0 - 1e-12) {
        let dt = solver.stable_dt().unwrap().min(0.2 - solver.time());
        solver.advance(dt).unwrap();
        steps += 1;
    }
    let after = solver.conservation_totals();
    // Round-off: at most one ulp per cell per step.
    let bound = (steps * 100) as f64 * f64::EPSILON * before.mass;
    assert!(
        (after.mass - before.mass).abs() <= bound,
        "mass {} -> {} in {steps} steps",
        before.mass,
        after.mass
    );
    let rho = solver.cell_data(&["density".into()]).unwrap();
    let rho = rho.field("density").unwrap();
    let reference = sod_one(100, brisance_ice::Advection::VanLeer, 0.2);
    let reference = brisance_core::Solver::cell_data(&reference, &["density".into()]).unwrap();
    let reference = reference.field("density").unwrap();
    assert_eq!(rho.len(), 100);
    let diff = rho
        .iter()
        .zip(reference)
        .map(|(a, b)| (a - b).abs())
        .fold(0.0, f64::max);
    eprintln!(
        "{steps} steps, mass change {:e}, max |ρ − ρ_crate| {diff:e}, ρ(0.755) {}",
        after.mass - before.mass,
        rho[75]
    );
    assert!(diff <= 1e-12, "max |ρ − ρ_crate| = {diff}");
    // x = 0.755, between contact (0.685) and shock (0.850).
    assert!((rho[75] - 0.26557).abs() < 5e-3, "rho = {}", rho[75]);
}

const STICK: &str = include_str!("../../../../configs/ratestick_1d.ron");

/// configs/ratestick_1d.ron at h = 2 mm (50 cells): the 90 m/s impact
/// on the wall starts a detonation that burns the explosive behind it
/// and reaches x = 6 cm by 15 µs (D_CJ = 5899 m/s).
#[test]
fn ratestick_config_detonates() {
    let loaded = load_str("ratestick_1d.ron", STICK, &["domain.cells=(50,1,1)".into()]).unwrap();
    let mut solver = build_solver(&loaded.scenario).unwrap();
    while solver.time() < 1.5e-5 {
        let dt = solver.stable_dt().unwrap();
        solver.advance(dt).unwrap();
    }
    let d = solver
        .cell_data(&["volume_fraction_1".into(), "pressure".into()])
        .unwrap();
    let theta = d.field("volume_fraction_1").unwrap();
    let p = d.field("pressure").unwrap();
    let burnt = theta.iter().take_while(|&&t| t < 0.5).count();
    let p_max = p.iter().cloned().fold(0.0, f64::max);
    eprintln!("burnt cells {burnt} of 50, p max {p_max:e}");
    // 15 µs at ~5 km/s after a ~3 µs start: 5–7 cm burnt.
    assert!((20..=40).contains(&burnt), "{burnt}");
    assert!(p_max > 5e9, "{p_max:e}");
}

/// A metal trace in a hot booster: copper has no Mie–Grüneisen state
/// at 10 GPa and the products' 19 000 K (its thermal pressure alone is
/// above 10 GPa), so it takes its density at 10 GPa and 300 K; before,
/// the build stopped at the booster's region.
#[test]
fn a_metal_trace_in_a_hot_booster_takes_room_temperature() {
    let text = r#"Scenario(
        name: "booster",
        domain: (lower: (0, 0, 0), upper: (0.01, 0.001, 0.001), cells: (10, 1, 1)),
        time: (end: 1.0e-6),
        materials: {
            "products": (library: "qm100_products"),
            "copper": (eos: MieGruneisenLinear(c0: 3619.7, s: 1.489, gamma0: 2.02, rho0: 8930.0, cv: 383.0, t0: 300.0)),
        },
        pipeline: Ice(materials: ["products", "copper"]),
        initial: [
            (region: Everywhere, material: "copper", state: (density: 8930.0077, temperature: 300.0)),
            (region: Box(min: (0, -1, -1), max: (0.005, 1, 1)), material: "products", state: (density: 1260.0, pressure: 1.0e10)),
        ],
    )"#;
    let loaded = load_str("booster.ron", text, &[]).unwrap();
    let solver = build_solver(&loaded.scenario).unwrap();
    let d = solver
        .cell_data(&[
            "density_2".into(),
            "volume_fraction_2".into(),
            "temperature_2".into(),
            "pressure".into(),
        ])
        .unwrap();
    let f = |name: &str| d.field(name).unwrap()[0];
    // The booster's cell: the copper trace at 10 GPa and 300 K, its
    // own density (density_2 is θρ) compressed above ρ₀ (on the
    // Us–up Hugoniot 10 GPa is about 9.6·10³ kg/m³).
    let rho = f("density_2") / f("volume_fraction_2");
    assert!(
        (f("pressure") - 1e10).abs() < 1e-6 * 1e10,
        "{}",
        f("pressure")
    );
    assert!(
        (f("temperature_2") - 300.0).abs() < 1e-6,
        "{}",
        f("temperature_2")
    );
    assert!(rho > 9.4e3 && rho < 9.8e3, "{rho}");
}

/// The cylinder test with its copper Eulerian and a heat exchange
/// (H = 10¹⁰ W/(m³·K)): the products trace in the copper beside the
/// booster, cooled by the exchange from 19 000 K and compressed to a
/// few per cent of its volume in the same step, keeps a positive
/// volume (eq 31's thermal term taken of its compressed volume); it
/// stopped the run at its first step before.
#[test]
fn a_heat_exchange_keeps_a_cooled_compressed_trace_positive() {
    let text = include_str!("../../../../configs/cylinder_rz.ron");
    let sets = [
        r#"pipeline=Ice(materials: ["qm100", "products", "air", "copper"], reactions: [(reactant: "qm100", product: "products", model: JwlPlusPlus(g: 9.1e-5, b: 1.0))], heat_exchange: 1e10)"#,
        "outputs.particle_gauges=[]",
    ]
    .map(String::from);
    let loaded = load_str("cylinder_rz.ron", text, &sets).unwrap();
    let mut solver = build_solver(&loaded.scenario).unwrap();
    for _ in 0..3 {
        let dt = solver.stable_dt().unwrap();
        solver.advance(dt).unwrap();
    }
}

/// `model: Deflagration(...)` builds the surface burn (its heat of
/// reaction the JWL++ default of the Murnaghan → JwlCTerm pair), and a
/// bad parameter is reported at the model's field with its name.
#[test]
fn a_config_names_the_deflagration() {
    let law = "model: Deflagration(a: 5.218307e-6, n: 0.778, ignition_temperature: 450.0)";
    let text = STICK.replace("model: JwlPlusPlus(g: 3.5083e-7, b: 1.3)", law);
    let loaded = load_str("ratestick_1d.ron", &text, &[]).unwrap();
    let Some(ice) = loaded
        .scenario
        .pipeline
        .section::<brisance_ice::pipeline::IceConfig>()
    else {
        panic!("an Ice pipeline");
    };
    let rx = super::reactions(&loaded.scenario, ice).unwrap();
    assert_eq!(
        rx[0].rate,
        super::IceRate::Deflagration(brisance_reaction::Deflagration::pbx_9501())
    );
    assert!(rx[0].heat_of_reaction > 0.0);
    let bad = text.replace("n: 0.778", "n: -0.5");
    let err = load_str("ratestick_1d.ron", &bad, &[]).unwrap_err();
    assert_eq!(
        err.field.as_deref(),
        Some("pipeline.reactions.0.model"),
        "{err}"
    );
    assert!(err.to_string().contains("`n`"), "{err}");
    // The surface-area estimate is the model's optional field; a name
    // that is not an estimate is refused at its line, with the names.
    let upwind = text.replace(
        "ignition_temperature: 450.0)",
        "ignition_temperature: 450.0, surface_area: upwind)",
    );
    let loaded = load_str("ratestick_1d.ron", &upwind, &[]).unwrap();
    let Some(ice) = loaded
        .scenario
        .pipeline
        .section::<brisance_ice::pipeline::IceConfig>()
    else {
        panic!("an Ice pipeline");
    };
    let rx = super::reactions(&loaded.scenario, ice).unwrap();
    let super::IceRate::Deflagration(m) = &rx[0].rate else {
        panic!("a deflagration");
    };
    assert_eq!(m.surface_area, Some(brisance_reaction::SurfaceArea::Upwind));
    let bad = text.replace(
        "ignition_temperature: 450.0)",
        "ignition_temperature: 450.0, surface_area: columns)",
    );
    let err = load_str("ratestick_1d.ron", &bad, &[])
        .unwrap_err()
        .to_string();
    assert!(err.starts_with("ratestick_1d.ron:25:"), "{err}");
    assert!(
        err.contains("`columns`") && err.contains("`exposed_faces`"),
        "{err}"
    );
}

/// `model: Arrhenius(...)` builds the surface pyrolysis of seed 003 (the
/// lattice's law) as a surface burn of the ICE, its heat of reaction the
/// JWL++ default of the pair or the one given; a bad parameter is reported
/// at the model's field with its name.
#[test]
fn a_config_names_the_arrhenius_pyrolysis() {
    let law = "model: Arrhenius(pre_exponential: 5.0e6, activation_energy: 92109.6)";
    let text = STICK.replace("model: JwlPlusPlus(g: 3.5083e-7, b: 1.3)", law);
    let loaded = load_str("ratestick_1d.ron", &text, &[]).unwrap();
    let Some(ice) = loaded
        .scenario
        .pipeline
        .section::<brisance_ice::pipeline::IceConfig>()
    else {
        panic!("an Ice pipeline");
    };
    let rx = super::reactions(&loaded.scenario, ice).unwrap();
    let expect = brisance_reaction::Arrhenius {
        pre_exponential: 5.0e6,
        activation_energy: 92_109.6,
        catalytic_factor: 1.0,
    };
    assert_eq!(rx[0].rate, super::IceRate::Arrhenius(expect));
    assert!(brisance_core::ReactionModel::burns_on_a_surface(
        &rx[0].rate
    ));
    assert!(rx[0].heat_of_reaction > 0.0);
    let bad = text.replace("activation_energy: 92109.6", "activation_energy: -1.0");
    let err = load_str("ratestick_1d.ron", &bad, &[]).unwrap_err();
    assert_eq!(
        err.field.as_deref(),
        Some("pipeline.reactions.0.model"),
        "{err}"
    );
    assert!(err.to_string().contains("activation_energy"), "{err}");
    // The law's fields are its own: a deflagration's is refused, naming it.
    let bad = text.replace("activation_energy: 92109.6", "ignition_temperature: 450.0");
    let err = load_str("ratestick_1d.ron", &bad, &[])
        .unwrap_err()
        .to_string();
    assert!(err.contains("ignition_temperature"), "{err}");
}

/// A reaction naming a material outside the pipeline, or products
/// without a default heat of reaction, is reported at its field.
#[test]
fn bad_reactions_name_the_field() {
    let bad = STICK.replace("reactant: \"anfo\"", "reactant: \"tnt\"");
    let err = load_str("ratestick_1d.ron", &bad, &[]).unwrap_err();
    assert_eq!(
        err.field.as_deref(),
        Some("pipeline.reactions.0.reactant"),
        "{err}"
    );
    let bad = STICK.replace("g: 3.5083e-7", "g: -1.0");
    let err = load_str("ratestick_1d.ron", &bad, &[]).unwrap_err();
    assert_eq!(
        err.field.as_deref(),
        Some("pipeline.reactions.0.model"),
        "{err}"
    );
    let bad = STICK.replace("product: \"products\"", "product: \"anfo\"");
    let err = load_str("ratestick_1d.ron", &bad, &[]).unwrap_err();
    assert_eq!(
        err.field.as_deref(),
        Some("pipeline.reactions.0.product"),
        "{err}"
    );
    let bad = STICK.replace(
        "\"products\": (eos: JwlCTerm(a: 2.9867e11, b: 4.11706e9, c: 7.206147e8, r1: 4.95, r2: 1.15, omega: 0.35, rho0: 1160.0, cv: 862.0689655172414)),",
        "\"products\": (eos: IdealGas(gamma: 1.4, cv: 717.6, rho0: 1.2)),",
    );
    let err = load_str("ratestick_1d.ron", &bad, &[]).unwrap_err();
    assert_eq!(
        err.field.as_deref(),
        Some("pipeline.reactions.0.heat_of_reaction"),
        "{err}"
    );
}

/// `pressure: Implicit(...)` reaches the solver's options (fields
/// left out take their defaults); bad settings name their field.
#[test]
fn implicit_pressure_is_reachable_from_the_config() {
    use brisance_ice::{ImplicitPressure, PressureSolve};
    let with = |p: &str| {
        SOD.replace(
            "pipeline: Ice(materials: [\"gas\"]),",
            &format!("pipeline: Ice(materials: [\"gas\"], pressure: {p}),"),
        )
    };
    let cfg = with("Implicit(tolerance: 1e-9)");
    let loaded = load_str("sod_ice.ron", &cfg, &["domain.cells=(20,1,1)".into()]).unwrap();
    let Some(ice) = loaded
        .scenario
        .pipeline
        .section::<brisance_ice::pipeline::IceConfig>()
    else {
        panic!("an Ice pipeline");
    };
    assert_eq!(
        ice.pressure,
        PressureSolve::Implicit(ImplicitPressure {
            tolerance: 1e-9,
            max_iterations: 20,
            retries: 4,
        })
    );
    let solver = super::build(&loaded.scenario, ice).unwrap();
    assert_eq!(solver.options().pressure, ice.pressure);
    let mut solver = build_solver(&loaded.scenario).unwrap();
    let dt = solver.stable_dt().unwrap();
    solver.advance(dt.min(1e-3)).unwrap();
    for (p, field) in [
        ("Implicit(tolerance: -1.0)", "pipeline.pressure.tolerance"),
        (
            "Implicit(max_iterations: 0)",
            "pipeline.pressure.max_iterations",
        ),
        ("Implicit(retries: 21)", "pipeline.pressure.retries"),
    ] {
        let err = load_str("sod_ice.ron", &with(p), &[]).unwrap_err();
        assert_eq!(err.field.as_deref(), Some(field), "{err}");
    }
    assert!(load_str("sod_ice.ron", &with("Implicit(tol: 1.0)"), &[]).is_err());
    let default = load_str("sod_ice.ron", SOD, &[]).unwrap();
    let Some(ice) = default
        .scenario
        .pipeline
        .section::<brisance_ice::pipeline::IceConfig>()
    else {
        panic!("an Ice pipeline");
    };
    assert_eq!(ice.pressure, PressureSolve::Explicit);
}

/// `face_pressure_courant` reaches the solver's options (0 when left
/// out); a value outside [0, 1] is reported at its field.
#[test]
fn face_pressure_courant_is_reachable_from_the_config() {
    let options = |text: &str| {
        let loaded = load_str("sod_ice.ron", text, &["domain.cells=(20,1,1)".into()]).unwrap();
        let Some(ice) = loaded
            .scenario
            .pipeline
            .section::<brisance_ice::pipeline::IceConfig>()
        else {
            panic!("an Ice pipeline");
        };
        *super::build(&loaded.scenario, ice).unwrap().options()
    };
    assert_eq!(options(SOD).face_pressure_courant, 0.0);
    let with = |v: &str| {
        SOD.replace(
            "pipeline: Ice(materials: [\"gas\"]),",
            &format!("pipeline: Ice(materials: [\"gas\"], face_pressure_courant: {v}),"),
        )
    };
    assert_eq!(options(&with("0.8")).face_pressure_courant, 0.8);
    for bad in ["-0.1", "1.5", "NaN"] {
        let err = load_str("sod_ice.ron", &with(bad), &[]).unwrap_err();
        assert_eq!(
            err.field.as_deref(),
            Some("pipeline.face_pressure_courant"),
            "{err}"
        );
    }
}

/// `max_dt` bounds the solver's step (none when left out); a value that
/// is not a finite time > 0 is reported at its field.
#[test]
fn max_dt_bounds_the_step() {
    use brisance_core::Solver;
    let build = |text: &str| {
        let loaded = load_str("sod_ice.ron", text, &["domain.cells=(20,1,1)".into()]).unwrap();
        let Some(ice) = loaded
            .scenario
            .pipeline
            .section::<brisance_ice::pipeline::IceConfig>()
        else {
            panic!("an Ice pipeline");
        };
        super::build(&loaded.scenario, ice).unwrap()
    };
    let free = build(SOD);
    assert_eq!(free.options().max_dt, f64::INFINITY);
    let dt = free.stable_dt().unwrap();
    let with = |v: &str| {
        SOD.replace(
            "pipeline: Ice(materials: [\"gas\"]),",
            &format!("pipeline: Ice(materials: [\"gas\"], max_dt: {v}),"),
        )
    };
    let bounded = build(&with(&format!("{:e}", 0.5 * dt)));
    assert_eq!(bounded.stable_dt().unwrap(), 0.5 * dt);
    assert_eq!(
        build(&with(&format!("{:e}", 2.0 * dt)))
            .stable_dt()
            .unwrap(),
        dt
    );
    for bad in ["0.0", "-1e-6", "inf", "NaN"] {
        let err = load_str("sod_ice.ron", &with(bad), &[]).unwrap_err();
        assert_eq!(err.field.as_deref(), Some("pipeline.max_dt"), "{err}");
    }
}

/// Unknown names and a material without EOS are reported at their field.
#[test]
fn bad_materials_name_the_field() {
    let err = load_str(
        "sod_ice.ron",
        SOD,
        &["pipeline.materials=[\"gas\", \"air\"]".into()],
    )
    .unwrap_err();
    assert_eq!(err.field.as_deref(), Some("pipeline.materials.1"), "{err}");
    let bad = SOD.replace(
        "material: \"gas\", state: (density: 0.125",
        "material: \"air\", state: (density: 0.125",
    );
    let err = load_str("sod_ice.ron", &bad, &[]).unwrap_err();
    assert_eq!(err.field.as_deref(), Some("initial.1.material"), "{err}");
    let bad = SOD.replace(
        "\"gas\": (eos: IdealGas(gamma: 1.4, cv: 1.0, rho0: 1.0)),",
        "\"gas\": (eos: IdealGas(gamma: 1.4, cv: 1.0, rho0: 1.0)), \"steel\": (model: Null(eos: IdealGas(gamma: 1.4, cv: 1.0, rho0: 1.0), viscosity: 0.0)),",
    );
    let err = load_str(
        "sod_ice.ron",
        &bad,
        &["pipeline.materials=[\"gas\", \"steel\"]".into()],
    )
    .unwrap_err();
    assert_eq!(err.field.as_deref(), Some("materials.steel.eos"), "{err}");
}

/// `transport` reaches the solver per material (a field left out is
/// 0), and a bad entry is reported at its field.
#[test]
fn transport_reaches_the_solver_and_bad_values_name_the_field() {
    let with = |t: &str| {
        SOD.replace(
            "pipeline: Ice(materials: [\"gas\"]),",
            &format!("pipeline: Ice(materials: [\"gas\"], transport: {t}),"),
        )
    };
    let cfg = with("{\"gas\": (viscosity: 0.01, thermal_conductivity: 0.02)}");
    let loaded = load_str("sod_ice.ron", &cfg, &["domain.cells=(20,1,1)".into()]).unwrap();
    let Some(ice) = loaded
        .scenario
        .pipeline
        .section::<brisance_ice::pipeline::IceConfig>()
    else {
        panic!("an Ice pipeline");
    };
    let solver = super::build(&loaded.scenario, ice).unwrap();
    assert_eq!(solver.transport().len(), 1);
    assert_eq!(solver.transport()[0].viscosity, 0.01);
    assert_eq!(solver.transport()[0].thermal_conductivity, 0.02);
    let limits = solver.time_step_limits().unwrap();
    assert!(limits.viscous.is_finite() && limits.conduction.is_finite());
    let cfg = with("{\"gas\": (thermal_conductivity: 0.5)}");
    let loaded = load_str("sod_ice.ron", &cfg, &[]).unwrap();
    let Some(ice) = loaded
        .scenario
        .pipeline
        .section::<brisance_ice::pipeline::IceConfig>()
    else {
        panic!("an Ice pipeline");
    };
    assert_eq!(ice.transport["gas"].viscosity, 0.0);
    for (t, field) in [
        ("{\"air\": (viscosity: 1.0)}", "pipeline.transport.air"),
        (
            "{\"gas\": (viscosity: -1.0)}",
            "pipeline.transport.gas.viscosity",
        ),
        (
            "{\"gas\": (thermal_conductivity: inf)}",
            "pipeline.transport.gas.thermal_conductivity",
        ),
    ] {
        let err = load_str("sod_ice.ron", &with(t), &[]).unwrap_err();
        assert_eq!(err.field.as_deref(), Some(field), "{err}");
    }
}

/// A reaction model of a plugin crate, named in RON: QM-100 reactant
/// in a closed 1D box decomposes by `ThermalDecomposition`
/// (crates/reaction-thermal, registered in `crate::plugins`). Over
/// 0.1 µs the burnt fraction is 1.4·10⁻⁴, too little to move the
/// reactant's temperature (298.15 K, the reference temperature, the
/// only one an Eulerian Murnaghan reactant can start at: 550 K is
/// refused at its field), so every cell's F is the exact
/// 1 − exp(−k t) of k(298.15 K); the model writes back as it was read,
/// and a bad parameter is reported at its field.
#[test]
fn a_plugin_reaction_model_burns_by_its_registered_name() {
    use brisance_reaction_thermal::ThermalDecomposition;

    const BOX: &str = r#"Scenario(
        name: "decomposition",
        domain: (lower: (0.0, 0.0, 0.0), upper: (0.004, 0.001, 0.001), cells: (4, 1, 1)),
        boundaries: (x_low: Reflective, x_high: Reflective),
        time: (end: 1.0e-7),
        materials: {"qm100": (library: "qm100_reactant"), "products": (library: "qm100_products")},
        pipeline: Ice(
            materials: ["qm100", "products"],
            reactions: [(reactant: "qm100", product: "products", model: ThermalDecomposition(z: 1.0e7, activation_energy: 2.2e4))],
        ),
        initial: [(region: Everywhere, material: "qm100", state: (density: 1260.1302, temperature: 298.15))],
    )"#;
    let loaded = load_str("box.ron", BOX, &[]).unwrap();
    let Some(ice) = loaded
        .scenario
        .pipeline
        .section::<brisance_ice::pipeline::IceConfig>()
    else {
        panic!("an Ice pipeline");
    };
    let model = &ice.reactions[0].model;
    assert_eq!(model.variant(), "ThermalDecomposition");
    let text = ron::to_string(model).unwrap();
    let back: super::IceReactionModel = crate::load::ron_options().from_str(&text).unwrap();
    assert_eq!(&back, model, "{text}");
    let mut solver = build_solver(&loaded.scenario).unwrap();
    let t_end = loaded.scenario.time.end;
    while solver.time() < t_end * (1.0 - 1e-12) {
        let dt = solver.stable_dt().unwrap().min(t_end - solver.time());
        solver.advance(dt).unwrap();
    }
    let law = ThermalDecomposition {
        z: 1.0e7,
        activation_energy: 2.2e4,
    };
    let exact = -(-law.rate_constant(298.15) * t_end).exp_m1();
    let names = ["density_1", "density_2", "temperature_1"];
    let d = solver.cell_data(&names.map(String::from)).unwrap();
    let field = |name: &str| d.field(name).unwrap().to_vec();
    let (r1, r2, t1) = (field(names[0]), field(names[1]), field(names[2]));
    for c in 0..4 {
        // The cell's macroscopic densities: F = ρ_p/(ρ_r + ρ_p).
        let f = r2[c] / (r1[c] + r2[c]);
        assert!((t1[c] - 298.15).abs() < 0.05, "cell {c}: T = {}", t1[c]);
        assert!(
            (f / exact - 1.0).abs() < 1e-3,
            "cell {c}: F = {f}, exact {exact}"
        );
    }
    // The Murnaghan reactant cannot start at 550 K: its cells keep a
    // pressure, which carries no temperature for it.
    let hot = BOX.replace("temperature: 298.15", "temperature: 550.0");
    let loaded = load_str("box.ron", &hot, &[]).unwrap();
    let err = crate::build::build_solver(&loaded.scenario)
        .err()
        .expect("refused");
    assert_eq!(
        err.field.as_deref(),
        Some("initial.0.state.temperature"),
        "{err}"
    );
    assert!(err.to_string().contains("298.15"), "{err}");
    let bad = BOX.replace("z: 1.0e7", "z: -1.0");
    let err = load_str("box.ron", &bad, &[]).unwrap_err();
    assert!(err.to_string().contains("z:"), "{err}");
}
