//! The `Lattice` pipeline through the composer: its example scenarios
//! load, validate, build and step, and its errors name their fields. The
//! pipeline's section, validation and builder are `brisance_lattice`'s
//! (`brisance_lattice::pipeline`); the composer hands it the scenario's
//! shared parts (`crate::scene::scene_of`).

use brisance_scene::PipelineSpec;

use crate::build::build_solver;
use crate::load_str;

/// The scenario's `Lattice` section (a registered pipeline), if it has one.
fn lattice_section(s: &crate::Scenario) -> Option<&brisance_lattice::LatticeConfig> {
    s.pipeline.section()
}

/// The example scenario loads, validates, builds and steps; a region
/// naming a material without lattice parameters is reported with its
/// field path.
#[test]
fn lattice_config_loads_builds_and_steps() {
    let text = include_str!("../../../configs/lattice_impact.ron");
    let loaded = load_str("lattice_impact.ron", text, &[]).unwrap();
    let mut solver = build_solver(&loaded.scenario).unwrap();
    assert_eq!(solver.name(), "lattice");
    let before = solver.conservation_totals();
    for _ in 0..5 {
        let dt = solver.stable_dt().unwrap();
        solver.advance(dt).unwrap();
    }
    let after = solver.conservation_totals();
    assert!((after.mass - before.mass).abs() <= 1e-12 * before.mass);
    let p = solver.particle_data().unwrap();
    assert!(p.fields.iter().any(|(n, _)| n == "temperature"));
    let bad = text.replace("\"hmx\": (young", "\"hmx_typo\": (young");
    let err = load_str("lattice_impact.ron", &bad, &[]).unwrap_err();
    assert!(err.to_string().contains("material"), "{err}");
}

/// `axes` of a boundary: the masks by hand, the errors naming the
/// field, and a built slip wall that holds u_x = 0 and leaves u_y to
/// the initial state (0), where a no-slip wall sets the boundary's 5 m/s.
#[test]
fn boundary_axes_hold_only_the_listed_components() {
    use brisance_lattice::LatticeBoundaryConfig;
    let b = |axes: Option<&[&str]>| LatticeBoundaryConfig {
        region: crate::config::Region::Box {
            min: [0.0; 3],
            max: [1.0; 3],
        },
        velocity: [0.0, 5.0, 0.0],
        axes: axes.map(|v| v.iter().map(|s| s.to_string()).collect()),
    };
    assert_eq!(b(None).held_mask(0, 2), Ok(0b011));
    assert_eq!(b(None).held_mask(0, 3), Ok(0b111));
    assert_eq!(b(Some(&["x"])).held_mask(0, 2), Ok(0b001));
    assert_eq!(b(Some(&["z", "y"])).held_mask(0, 3), Ok(0b110));
    for (axes, why) in [
        (&[][..], "empty"),
        (&["w"][..], "`w` is not an axis"),
        (&["z"][..], "not one of the lattice's 2 axes"),
        (&["x", "x"][..], "listed twice"),
    ] {
        let brisance_scene::FieldError {
            field,
            message: msg,
        } = b(Some(axes)).held_mask(3, 2).unwrap_err();
        assert_eq!(field, "pipeline.boundaries.3.axes");
        assert!(msg.contains(why), "{msg}");
    }
    let mut nan = b(None);
    nan.velocity[1] = f64::NAN;
    assert_eq!(
        nan.held_mask(1, 2).unwrap_err().field,
        "pipeline.boundaries.1.velocity"
    );

    let text = include_str!("../../../configs/lattice_impact.ron");
    let wall = "velocity: (0.0, 0.0, 0.0)),";
    assert!(text.contains(wall));
    let build = |with: &str, integrator: &str| {
        let t = text.replace(wall, with);
        let sets = [format!("pipeline.integrator={integrator}")];
        let loaded = load_str("lattice_impact.ron", &t, &sets).map_err(|e| e.to_string())?;
        let Some(cfg) = lattice_section(&loaded.scenario) else {
            return Err("not a lattice".to_string());
        };
        cfg.build(&crate::scene::scene_of(&loaded.scenario))
            .map_err(|e| e.to_string())
    };
    let slip = build(
        "velocity: (0.0, 5.0, 0.0), axes: [\"x\"]),",
        "VelocityVerlet",
    )
    .unwrap();
    let noslip = build("velocity: (0.0, 5.0, 0.0)),", "VelocityVerlet").unwrap();
    let i = slip.geom.index(1, 2, 0);
    assert!(slip.prescribed[i] && noslip.prescribed[i]);
    assert_eq!(
        (slip.held_axes[i], slip.u[0][i], slip.u[1][i]),
        (0b001, 0.0, 0.0)
    );
    assert_eq!(
        (noslip.held_axes[i], noslip.u[0][i], noslip.u[1][i]),
        (0b011, 0.0, 5.0)
    );
    let mut slip = slip;
    for _ in 0..5 {
        let dt = slip.explicit_stable_dt();
        slip.step(dt).unwrap();
    }
    assert_eq!(slip.u[0][i], 0.0);
    let bad = build(
        "velocity: (0.0, 0.0, 0.0), axes: [\"q\"]),",
        "VelocityVerlet",
    );
    assert!(bad.unwrap_err().to_string().contains("boundaries.0.axes"));
    let mut imp = build(
        "velocity: (0.0, 0.0, 0.0), axes: [\"x\"]),",
        "ImplicitEuler",
    )
    .unwrap();
    let dt = imp.explicit_stable_dt();
    assert!(imp.step(dt).unwrap_err().to_string().contains("held_axes"));
}

/// The implicit integrator runs the example with either linear solver,
/// and the two agree to the iterative solver's tolerance.
#[test]
fn implicit_lattice_runs_with_the_direct_and_the_iterative_solver() {
    let text = include_str!("../../../configs/lattice_impact.ron");
    let run = |solver_name: &str| {
        let sets = [
            "pipeline.integrator=ImplicitEuler".to_string(),
            format!("pipeline.linear_solver={solver_name}"),
        ];
        let loaded = load_str("lattice_impact.ron", text, &sets).unwrap();
        let mut solver = build_solver(&loaded.scenario).unwrap();
        for _ in 0..3 {
            let dt = solver.stable_dt().unwrap();
            solver.advance(dt).unwrap();
        }
        solver.conservation_totals()
    };
    let direct = run("Direct");
    let iterative = run("Iterative");
    for a in 0..3 {
        let scale = direct.momentum.iter().map(|v| v.abs()).sum::<f64>();
        assert!(
            (direct.momentum[a] - iterative.momentum[a]).abs() <= 1e-8 * scale,
            "axis {a}: {} vs {}",
            direct.momentum[a],
            iterative.momentum[a]
        );
    }
    assert!((direct.energy - iterative.energy).abs() <= 1e-8 * direct.energy.abs());
}

/// The burning-propellant example: the random AP pack has the 80 wt %
/// AP of its configuration to the pixelation error, only the top face
/// regresses, and the regression conserves mass (burnt + remaining).
#[test]
fn propellant_pack_loads_and_regresses_from_the_top() {
    use brisance_core::Solver;
    use brisance_lattice::node_mass_fraction;
    let text = include_str!("../../../configs/lattice_burn.ron");
    let loaded = load_str("lattice_burn.ron", text, &[]).unwrap();
    let Some(cfg) = lattice_section(&loaded.scenario) else {
        panic!("not a lattice");
    };
    let mut lat = cfg
        .build(&crate::scene::scene_of(&loaded.scenario))
        .unwrap();
    // Materials are in name order: ap = 0, htpb = 1.
    let w = node_mass_fraction(&lat, 0);
    assert!((w - 0.8).abs() < 0.03, "AP mass fraction {w}");
    let m0: f64 = lat.mass.iter().sum();
    let dt = lat.stable_dt().unwrap();
    // step_fraction 0.05 h at the faster AP speed at 860 K.
    let ap = cfg.materials["ap"].arrhenius.unwrap();
    assert!((dt - 0.05 * 2.4e-5 / ap.speed(1950.0, 860.0)).abs() < 1e-12 * dt);
    let top = lat.geom.n[1] - 3;
    let bottom_y = lat.x[1][lat.geom.solid_index(50, 0, 0)];
    for _ in 0..30 {
        lat.advance(dt).unwrap();
    }
    let reg = lat.regression.as_ref().unwrap();
    assert!(reg.consumed_mass > 0.0);
    let m1: f64 = lat.mass.iter().sum();
    assert!((m1 + reg.consumed_mass - m0).abs() < 1e-12 * m0);
    // The top row has moved, the bottom row has not.
    let i = lat.geom.solid_index(50, top, 0);
    assert!(lat.x[1][i] < top as f64 * 2.4e-5);
    assert_eq!(lat.x[1][lat.geom.solid_index(50, 0, 0)], bottom_y);
    // Field-naming errors.
    let bad = text.replace("particle: \"ap\"", "particle: \"apx\"");
    let err = load_str("lattice_burn.ron", &bad, &[]).unwrap_err();
    assert!(err.to_string().contains("pipeline.pack.particle"), "{err}");
    let bad = text.replace("pre_exponential: 5.0e6", "pre_exponential: -5.0e6");
    let err = load_str("lattice_burn.ron", &bad, &[]).unwrap_err();
    assert!(
        err.to_string()
            .contains("materials.ap.arrhenius.pre_exponential"),
        "{err}"
    );
    let bad = text.replace("thermal: false", "thermal: true");
    let err = load_str("lattice_burn.ron", &bad, &[]).unwrap_err();
    assert!(err.to_string().contains("pipeline.mechanics"), "{err}");
    let bad = text.replace("normal_radius: 1.0", "normal_radius: 0.5");
    let err = load_str("lattice_burn.ron", &bad, &[]).unwrap_err();
    assert!(err.to_string().contains("normal_radius"), "{err}");
    let bad = text.replace("mass_fraction: 0.8", "mass_fraction: 1.2");
    let err = load_str("lattice_burn.ron", &bad, &[]).unwrap_err();
    assert!(
        err.to_string().contains("pipeline.pack.mass_fraction"),
        "{err}"
    );
    let bad = text.replace(
        "activation_energy: 62800.0",
        "activation_energy: 62800.0, omega: 2.0",
    );
    assert!(load_str("lattice_burn.ron", &bad, &[]).is_err());
}

/// An image pack: one node per pixel, bright pixels crystal; the mass
/// fraction is exact (a 3 × 3 image with a bright centre: the crystal
/// node has the full dual cell, 4 edge nodes ½ and 4 corners ¼), and a
/// size mismatch names `pipeline.pack.path`.
#[test]
fn image_pack_is_one_node_per_pixel() {
    use brisance_lattice::node_mass_fraction;
    let dir = std::env::temp_dir().join(format!("lattice_pack_{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("centre.pgm");
    std::fs::write(&path, b"P2 3 3 255\n0 0 0\n0 255 0\n0 0 0\n").unwrap();
    let text = include_str!("../../../configs/lattice_burn.ron")
        .replace(
            "pack: RandomDiscs(diameter: 2.0e-4, mass_fraction: 0.8, particle: \"ap\", binder: \"htpb\", seed: 17)",
            &format!(
                "pack: Image(path: {:?}, threshold: 128, crystal: \"ap\", binder: \"htpb\")",
                path.display().to_string()
            ),
        )
        .replace("upper: (2.4e-3, 2.4e-3, 2.4e-5)", "upper: (4.8e-5, 4.8e-5, 2.4e-5)");
    let loaded = load_str("lattice_burn.ron", &text, &[]).unwrap();
    let Some(cfg) = lattice_section(&loaded.scenario) else {
        panic!("not a lattice");
    };
    let lat = cfg
        .build(&crate::scene::scene_of(&loaded.scenario))
        .unwrap();
    assert_eq!(lat.material_of(lat.geom.solid_index(1, 1, 0)), Some(0));
    assert_eq!(lat.material_of(lat.geom.solid_index(0, 1, 0)), Some(1));
    // 1950 · 1 / (1950 · 1 + 920 · 3).
    let w = node_mass_fraction(&lat, 0);
    assert!((w - 1950.0 / (1950.0 + 2760.0)).abs() < 1e-14, "{w}");
    let wrong = text.replace(
        "upper: (4.8e-5, 4.8e-5, 2.4e-5)",
        "upper: (7.2e-5, 4.8e-5, 2.4e-5)",
    );
    let loaded = load_str("lattice_burn.ron", &wrong, &[]).unwrap();
    let err = crate::build::build_solver(&loaded.scenario).err().unwrap();
    assert!(err.to_string().contains("pipeline.pack.path"), "{err}");
    let _ = std::fs::remove_dir_all(&dir);
}
