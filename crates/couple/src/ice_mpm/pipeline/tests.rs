use super::*;
use crate::scenario_text::parse;
use brisance_constitutive::MaterialModel;
use brisance_eos::EosModel;
use brisance_grid::Shape;
use brisance_scene::{Domain, OwnedScene, StateConfig, ThermalConfig};

const STEEL_EOS: &str = "SolidThreshold(solid: Murnaghan(n: 4.0, kappa: 6.25e-12, rho0: 7850.0, cv: 460.0, t_ref: 300.0), threshold_pressure: 101325.0)";
const STEEL: &str =
    "Hypoelastic(shear_modulus: 80.0e9, pressure: Linear(bulk_modulus: 160.0e9), rate: Jaumann)";

fn section(text: &str) -> IceMpmConfig {
    parse(text)
}

fn piston() -> IceMpmConfig {
    section("(ice: (materials: [\"air\"]), solid: \"steel\", mpm: (ppc: 2))")
}

/// configs/piston_icempm.ron at 1 mm over 2 cm: air everywhere and a
/// 1 mm steel piston at x = 5 mm moving at 100 m/s; `thermal` for the
/// steel where given.
fn piston_scene(thermal: Option<ThermalConfig>) -> OwnedScene {
    let air: EosModel = parse("IdealGas(gamma: 1.4, cv: 717.5, rho0: 1.225)");
    let eos: EosModel = parse(STEEL_EOS);
    let model: MaterialModel = parse(STEEL);
    let mut steel_state = StateConfig::at_pressure(7850.00497, 0.0).moving([100.0, 0.0, 0.0]);
    steel_state.pressure = None;
    steel_state.temperature = Some(300.0);
    OwnedScene::new(Domain::cartesian(
        [0.0; 3],
        [0.02, 0.001, 0.001],
        [20, 1, 1],
    ))
    .with_material("air", Some(air))
    .with_material("steel", Some(eos))
    .with_model("steel", model, thermal)
    .with_region(
        Shape::Everywhere,
        "air",
        StateConfig::at_pressure(1.17659, 101325.0),
    )
    .with_region(
        Shape::Box {
            min: [0.005, -1.0, -1.0],
            max: [0.006, 1.0, 1.0],
        },
        "steel",
        steel_state,
    )
}

/// The section builds from a hand-made scene, without the composer: the
/// solid's one cell holds ppc = 2 particles (the fluids' region is left to
/// the ICE), and a particle gauge over everything takes both.
#[test]
fn a_piston_scene_builds_its_particles_beside_its_fluid() {
    let mut owned = piston_scene(None);
    owned
        .particle_gauges
        .push(("piston".into(), Shape::Everywhere, None));
    let s = owned.scene();
    let cfg = piston();
    cfg.validate(&s).expect("valid");
    let solver = cfg.build(&s).expect("builds");
    let p = solver.mpm().particles();
    assert_eq!(p.len(), 2);
    for (k, x) in [0.00525, 0.00575].into_iter().enumerate() {
        assert!((p.position[k][0] - x).abs() < 1e-15, "{:?}", p.position[k]);
        assert_eq!(p.velocity[k], [100.0, 0.0, 0.0]);
    }
    let gauges = solver.mpm().particle_gauges();
    assert_eq!(gauges.len(), 1);
    assert_eq!(gauges[0].len(), 2);
    assert!(cfg.describe(&s).contains("solid `steel` as particles"));
}

/// The section's checks name their fields, the particle section's at
/// `pipeline.mpm.*`.
#[test]
fn the_checks_name_their_fields() {
    let owned = piston_scene(None);
    let s = owned.scene();
    let field = |text: &str| section(text).validate(&s).unwrap_err().field;
    assert_eq!(
        field("(ice: (materials: [\"air\"]), solid: [\"steel\", \"steel\"], mpm: ())"),
        "pipeline.solid"
    );
    assert_eq!(
        field("(ice: (materials: [\"air\", \"steel\"]), solid: \"steel\", mpm: ())"),
        "pipeline.solid"
    );
    assert_eq!(
        field("(ice: (materials: []), solid: \"air\", mpm: ())"),
        "materials.air.model"
    );
    assert_eq!(
        field("(ice: (materials: [\"air\"]), solid: \"steel\", mpm: (scheme: Usf))"),
        "pipeline.mpm.scheme"
    );
    assert_eq!(
        field("(ice: (materials: [\"air\"]), solid: \"steel\", mpm: (ppc: 0))"),
        "pipeline.mpm.ppc"
    );
    assert_eq!(
        field("(ice: (materials: [\"air\"]), solid: \"steel\", mpm: (mass_cutoff: 2.0))"),
        "pipeline.mpm.mass_cutoff"
    );
}

/// The solids conduct; a fluid given `thermal` is refused at its entry,
/// and a solid's thermal properties are checked.
#[test]
fn a_thermal_fluid_is_refused_and_a_thermal_solid_checked() {
    let k = |conductivity| {
        Some(ThermalConfig {
            conductivity,
            specific_heat: Some(460.0),
        })
    };
    let owned = piston_scene(k(44.5));
    assert!(piston().validate(&owned.scene()).is_ok());
    let owned = piston_scene(k(-1.0));
    assert_eq!(
        piston().validate(&owned.scene()).unwrap_err().field,
        "materials.steel.thermal.conductivity"
    );
    let mut owned = piston_scene(None);
    let air_eos = owned.materials[0].1.clone().unwrap();
    owned.materials.retain(|(n, _)| n != "air");
    let air_model = MaterialModel::Null(brisance_constitutive::NullMaterial::inviscid(
        air_eos.clone(),
    ));
    owned = owned
        .with_material("air", Some(air_eos))
        .with_model("air", air_model, k(0.025));
    let e = piston().validate(&owned.scene()).unwrap_err();
    assert_eq!(e.field, "materials.air.thermal");
    assert!(e.message.contains("not a `solid`"), "{e}");
}
