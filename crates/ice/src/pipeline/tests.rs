//! The Ice pipeline's section on hand-made scenes: its checks name the
//! field, its builder gives each cell the last region's material with the
//! others as traces, and its reactions take the JWL++ default heat.

use brisance_core::{Geometry, Solver};
use brisance_eos::{EosModel, IdealGas, JwlCTerm, Murnaghan};
use brisance_grid::Shape;
use brisance_scene::{BoundaryConfig, Domain, OwnedScene, PipelineSpec, Scene, StateConfig};

use super::*;

/// The section as a scenario writes it (newtype variants unwrapped, as
/// the composer reads them).
fn config(text: &str) -> IceConfig {
    ron::Options::default()
        .with_default_extension(
            ron::extensions::Extensions::IMPLICIT_SOME
                | ron::extensions::Extensions::UNWRAP_VARIANT_NEWTYPES,
        )
        .from_str(text)
        .unwrap()
}

/// A 1D tube of four 0.25 m cells along x with air and helium (ideal
/// gases), ANFO-K1 and its products: air everywhere, helium at 10 bar in
/// x < 0.5.
fn tube() -> OwnedScene {
    let mut o = OwnedScene::new(Domain::cartesian([0.0; 3], [1.0; 3], [4, 1, 1]))
        .with_material(
            "air",
            Some(EosModel::IdealGas(IdealGas::new(1.4, 717.5, 1.2))),
        )
        .with_material(
            "helium",
            Some(EosModel::IdealGas(IdealGas::new(5.0 / 3.0, 3116.0, 0.17))),
        )
        .with_material("anfo", Some(EosModel::Murnaghan(Murnaghan::anfo_k1())))
        .with_material("products", Some(EosModel::JwlCTerm(JwlCTerm::anfo_k1())))
        .with_region(Shape::Everywhere, "air", StateConfig::at_pressure(1.2, 1e5))
        .with_region(
            Shape::Box {
                min: [-1.0; 3],
                max: [0.5, 2.0, 2.0],
            },
            "helium",
            StateConfig::at_pressure(1.5, 1e6),
        );
    o.name = "tube".into();
    o
}

/// Each bad part of the section is reported at its field.
#[test]
fn each_bad_section_names_its_field() {
    let mut o = tube();
    let s = o.scene();
    let field = |text: &str, s: &Scene<'_>| config(text).validate(s).err().map(|e| e.field);
    assert_eq!(field("(materials: [\"air\", \"helium\"])", &s), None);
    assert_eq!(
        field("(materials: [])", &s).as_deref(),
        Some("pipeline.materials")
    );
    assert_eq!(
        field("(materials: [\"air\", \"helium\", \"air\"])", &s).as_deref(),
        Some("pipeline.materials.2")
    );
    assert_eq!(
        field("(materials: [\"air\", \"argon\"])", &s).as_deref(),
        Some("pipeline.materials.1")
    );
    assert_eq!(
        field("(materials: [\"air\", \"helium\"], cfl: 1.5)", &s).as_deref(),
        Some("pipeline.cfl")
    );
    assert_eq!(
        field(
            "(materials: [\"air\", \"helium\"], solid_exchange: Slip)",
            &s
        )
        .as_deref(),
        Some("pipeline.solid_exchange")
    );
    // The fluid side of a coupled pipeline may name the slip exchange.
    assert!(
        config("(materials: [\"air\", \"helium\"], solid_exchange: Slip)")
            .check_fluids(&s)
            .is_ok()
    );
    let e = config("(materials: [\"air\"])").validate(&s).unwrap_err();
    assert_eq!(e.field, "initial.1.material");
    assert_eq!(e.message, "`helium` is not in pipeline.materials (`air`)");
    assert_eq!(
        field(
            "(materials: [\"air\", \"helium\"], reactions: [(reactant: \"air\", product: \"anfo\", model: JwlPlusPlus(g: 1e-7, b: 1.0))])",
            &s
        )
        .as_deref(),
        Some("pipeline.reactions.0.product")
    );
    // A fixed face's state names one of the materials where there are
    // several.
    o.boundaries.x_low = BoundaryConfig::Fixed(StateConfig::at_pressure(1.2, 1e5));
    let s = o.scene();
    assert_eq!(
        field("(materials: [\"air\", \"helium\"])", &s).as_deref(),
        Some("boundaries.x_low")
    );
    // A per-material output field beyond the materials given.
    let mut o = tube();
    o.field_lists = vec![(
        "outputs.gauges.0.fields".into(),
        vec!["pressure".into(), "density_3".into()],
    )];
    let s = o.scene();
    assert_eq!(
        field("(materials: [\"air\", \"helium\"])", &s).as_deref(),
        Some("outputs.gauges.0.fields.1")
    );
}

/// Each cell holds the last region's material at 1 − 10⁻⁶ of its volume
/// and the other as a trace of 10⁻⁶ at the region's density and pressure
/// (`density_k` is material k's mass per cell volume, θ_k ρ_k).
#[test]
fn the_builder_fills_cells_with_the_region_and_a_trace() {
    let solver = config("(materials: [\"air\", \"helium\"])")
        .build(&tube().scene())
        .unwrap();
    let names = [
        "pressure",
        "volume_fraction_1",
        "volume_fraction_2",
        "density_1",
    ];
    let data = solver.cell_data(&names.map(String::from)).unwrap();
    let f = |n: &str| data.field(n).unwrap().to_vec();
    assert_eq!(f("pressure"), [1e6, 1e6, 1e5, 1e5]);
    // The fractions as stored, to round-off of their sum's normalisation.
    let close =
        |got: Vec<f64>, want: [f64; 4]| got.iter().zip(want).all(|(g, w)| (g - w).abs() <= 1e-15);
    let (full, trace) = (1.0 - TRACE_FRACTION, TRACE_FRACTION);
    assert!(close(f("volume_fraction_1"), [trace, trace, full, full]));
    assert!(close(f("volume_fraction_2"), [full, full, trace, trace]));
    // The trace takes the region's density: air's mass per cell volume
    // θ₁ρ₁ is 10⁻⁶ of the helium's 1.5 kg/m³ in the helium's cells.
    let rel = |got: Vec<f64>, want: [f64; 4]| {
        got.iter()
            .zip(want)
            .all(|(g, w)| (g - w).abs() <= 1e-14 * w)
    };
    assert!(rel(
        f("density_1"),
        [trace * 1.5, trace * 1.5, full * 1.2, full * 1.2]
    ));
}

/// Without `heat_of_reaction` a Murnaghan → JwlCTerm pair releases the
/// JWL++ detonation energy; another pair must give it.
#[test]
fn a_reaction_takes_the_jwlpp_heat_by_default() {
    let mut o = tube();
    o.initial = vec![(
        Shape::Everywhere,
        "anfo".into(),
        StateConfig::at_pressure(1160.0, 1e5),
    )];
    let s = o.scene();
    let rx = config(
        "(materials: [\"anfo\", \"products\"], reactions: [(reactant: \"anfo\", product: \"products\", model: JwlPlusPlus(g: 3.5083e-7, b: 1.3))])",
    )
    .reactions(&s)
    .unwrap();
    let q = crate::detonation_energy(&Murnaghan::anfo_k1(), &JwlCTerm::anfo_k1()).unwrap();
    assert_eq!((rx[0].reactant, rx[0].product), (0, 1));
    assert_eq!(rx[0].heat_of_reaction, q);
    let e = config(
        "(materials: [\"air\", \"helium\"], reactions: [(reactant: \"air\", product: \"helium\", model: JwlPlusPlus(g: 1e-7, b: 1.0))])",
    )
    .reactions(&s)
    .unwrap_err();
    assert_eq!(e.field, "pipeline.reactions.0.heat_of_reaction");
}

/// The limits are the ICE's fields and stencil; the description names
/// the materials with their equations of state.
#[test]
fn limits_and_description() {
    let o = tube();
    let s = o.scene();
    let c = config("(materials: [\"air\", \"helium\"])");
    let l = c.limits(Geometry::Axisymmetric);
    assert_eq!((l.ghost, l.fields.len()), (GHOST, 8 + 4 * MAX_MATERIALS));
    let text = c.describe(&s);
    assert!(text.starts_with("scenario `tube`: Ice pipeline"), "{text}");
    assert!(
        text.contains("materials: `air` (ideal_gas), `helium` (ideal_gas)"),
        "{text}"
    );
}
