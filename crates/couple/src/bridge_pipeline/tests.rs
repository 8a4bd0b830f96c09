use super::*;
use crate::scenario_text::parse;
use brisance_grid::Shape;
use brisance_scene::{Domain, OwnedScene, StateConfig};

/// A 1D tube at 2 mm: FDM (0, 40) mm, MPM (30, 60) mm, overlapping by
/// 5 cells; `extra` adds options to the section.
fn section(extra: &str) -> BridgeConfig {
    parse(&format!(
        "(fdm_region: (lower: (0.0, 0.0, 0.0), upper: (0.04, 0.002, 0.002)), \
          mpm_region: (lower: (0.03, 0.0, 0.0), upper: (0.06, 0.002, 0.002)), \
          air: \"air\", activation_pressure: 1.1e5{extra})"
    ))
}

/// Air at 1 bar everywhere in the tube of [`section`].
fn tube() -> OwnedScene {
    let air: EosModel = parse("IdealGas(gamma: 1.4, cv: 717.5, rho0: 1.225)");
    OwnedScene::new(Domain::cartesian(
        [0.0; 3],
        [0.06, 0.002, 0.002],
        [30, 1, 1],
    ))
    .with_material("air", Some(air))
    .with_region(
        Shape::Everywhere,
        "air",
        StateConfig::at_pressure(1.225, 1.0e5),
    )
}

/// The section builds from a hand-made scene, without the composer: the
/// MPM region's 15 cells hold ppc = 2 air particles each, every one of
/// ρ Δx A / 2, and a gauge over the tube takes them all.
#[test]
fn a_tube_of_air_builds_its_two_regions() {
    let mut owned = tube();
    owned
        .particle_gauges
        .push(("all".into(), Shape::Everywhere, Some("air".into())));
    let s = owned.scene();
    let cfg = section("");
    cfg.validate(&s).expect("valid");
    assert!(cfg.describe(&s).contains("w = 5 cells along x"));
    let solver = cfg.build(&s).expect("builds");
    assert_eq!(solver.name(), "fdm-mpm");
    let p = solver.mpm().particles();
    assert_eq!(p.len(), 30);
    let m = 1.225 * 0.002 * 0.002 * 0.002 / 2.0;
    assert!(p.mass.iter().all(|&x| (x - m).abs() < 1e-15 * m));
    assert!((p.position[0][0] - 0.0305).abs() < 1e-15);
    assert_eq!(solver.mpm().particle_gauges()[0].len(), 30);
}

/// The section's checks name their fields.
#[test]
fn the_checks_name_their_fields() {
    let owned = tube();
    let s = owned.scene();
    let field = |extra: &str| section(extra).validate(&s).unwrap_err().field;
    assert_eq!(field(", ppc: 0"), "pipeline.ppc");
    assert_eq!(
        field(", shape_function: QuadraticBSpline"),
        "pipeline.shape_function"
    );
    assert_eq!(field(", shape_function: Gimp"), "pipeline.shape_function");
    for shape in ["Linear", "CpGimp"] {
        let cfg = section(&format!(", shape_function: {shape}"));
        cfg.validate(&s).expect(shape);
    }
    assert_eq!(field(", w: Some(4)"), "pipeline.w");
    assert_eq!(field(", mpm_cfl: 1.5"), "pipeline.mpm_cfl");
    assert_eq!(
        field(", bulk_viscosity: On(quadratic: 1.5, linear: -0.06)"),
        "pipeline.bulk_viscosity.linear"
    );
    assert_eq!(
        field(", bulk_viscosity: On(quadratic: NaN, linear: 0.06)"),
        "pipeline.bulk_viscosity.quadratic"
    );
    assert_eq!(
        field(", fluid_bulk_viscosity: Some(quadratic: 1.5, linear: -1.0)"),
        "pipeline.fluid_bulk_viscosity.linear"
    );
    section(", fluid_bulk_viscosity: Some(linear: 1.0)")
        .validate(&s)
        .expect("the fluids' own coefficients");
    assert_eq!(
        field(", min_particle_mass: 2.0"),
        "pipeline.min_particle_mass"
    );
    assert_eq!(field(", remap: Some(\"tube.remap\")"), "pipeline.remap");
    // A region of a material that is neither a gas nor modelled.
    let stone: EosModel = parse("IdealGas(gamma: 1.4, cv: 717.5, rho0: 1.225)");
    let owned = tube().with_material("stone", Some(stone)).with_region(
        Shape::Box {
            min: [0.05, 0.0, 0.0],
            max: [0.06, 0.002, 0.002],
        },
        "stone",
        StateConfig::at_pressure(1.225, 1.0e5),
    );
    let e = section("").validate(&owned.scene()).unwrap_err();
    assert_eq!(e.field, "initial.1.material");
    // The air must be an ideal gas.
    let mut owned = tube();
    owned.materials[0].1 = Some(parse(
        "Murnaghan(n: 4.0, kappa: 6.25e-12, rho0: 7850.0, cv: 460.0, t_ref: 300.0)",
    ));
    assert_eq!(
        section("").validate(&owned.scene()).unwrap_err().field,
        "pipeline.air"
    );
    // A particle gauge follows the air, the products or a modelled
    // material.
    let mut owned = tube().with_material("stone", None);
    owned
        .particle_gauges
        .push(("g".into(), Shape::Everywhere, Some("stone".into())));
    assert_eq!(
        section("").validate(&owned.scene()).unwrap_err().field,
        "outputs.particle_gauges.0.material"
    );
    owned.particle_gauges[0].2 = Some("air".into());
    assert!(section("").validate(&owned.scene()).is_ok());
}
