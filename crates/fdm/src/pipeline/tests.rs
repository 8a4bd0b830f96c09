//! The Fdm pipeline's section on hand-made scenes: its checks name the
//! field, its builder fills each cell from the last region holding it,
//! and its limits follow the grid.

use brisance_core::Geometry;
use brisance_eos::{EosModel, IdealGas, Jwl, Murnaghan};
use brisance_grid::Shape;
use brisance_scene::{BoundaryConfig, Domain, OwnedScene, PipelineSpec, Scene, StateConfig};

use super::*;

fn config(text: &str) -> FdmConfig {
    ron::from_str(text).unwrap()
}

/// A 1D tube of four 0.25 m cells along x with an ideal gas (`air`,
/// γ = 1.4), the TNT products (`tnt`, JWL) and a solid (`solid`,
/// Murnaghan): air everywhere at 1 bar, and `material` at 10 bar and
/// 5 kg/m³ in x < 0.5.
fn shock_tube(material: &str) -> OwnedScene {
    let mut o = OwnedScene::new(Domain::cartesian([0.0; 3], [1.0; 3], [4, 1, 1]))
        .with_material(
            "air",
            Some(EosModel::IdealGas(IdealGas::new(1.4, 717.5, 1.2))),
        )
        .with_material("tnt", Some(EosModel::Jwl(Jwl::tnt())))
        .with_material("solid", Some(EosModel::Murnaghan(Murnaghan::anfo_k1())))
        .with_region(Shape::Everywhere, "air", StateConfig::at_pressure(1.2, 1e5))
        .with_region(
            Shape::Box {
                min: [-1.0; 3],
                max: [0.5, 2.0, 2.0],
            },
            material,
            StateConfig::at_pressure(5.0, 1e6),
        );
    o.name = "tube".into();
    o
}

/// The gas must be a known gas, a constant η must lie in [0, 0.25], every
/// region must hold the gas or the products, and the faces must be the
/// pipeline's: each error names its field.
#[test]
fn each_bad_section_names_its_field() {
    let air = shock_tube("air");
    let s = air.scene();
    let field = |text: &str, s: &Scene<'_>| config(text).validate(s).err().map(|e| e.field);
    assert_eq!(field("(material: \"air\")", &s), None);
    let e = config("(material: \"argon\")").validate(&s).unwrap_err();
    assert_eq!(e.field, "pipeline.material");
    assert_eq!(
        e.message,
        "unknown material `argon`; known materials: `air`, `tnt`, `solid`"
    );
    let e = config("(material: \"solid\")").validate(&s).unwrap_err();
    assert_eq!(e.field, "pipeline.material");
    assert!(e.message.ends_with("`solid` is `Murnaghan`"), "{e}");
    assert_eq!(
        field("(material: \"air\", viscosity: Constant(0.3))", &s).as_deref(),
        Some("pipeline.viscosity")
    );
    assert_eq!(
        field("(material: \"air\", viscosity: Constant(0.25))", &s),
        None
    );
    // A region of the products is the gas's unless the products are named.
    let mut tnt = shock_tube("tnt");
    let s = tnt.scene();
    let e = config("(material: \"air\")").validate(&s).unwrap_err();
    assert_eq!(
        (e.field.as_str(), e.message.as_str()),
        (
            "initial.1.material",
            "the Fdm pipeline carries one gas, `air`"
        )
    );
    assert_eq!(
        field("(material: \"air\", products: Some(\"tnt\"))", &s),
        None
    );
    // A particle wall is no face of this pipeline; a fixed face's state is
    // the gas's.
    tnt.boundaries.x_high = BoundaryConfig::Wall;
    let s = tnt.scene();
    let e = config("(material: \"air\", products: Some(\"tnt\"))")
        .validate(&s)
        .unwrap_err();
    assert_eq!(e.field, "boundaries.x_high");
    assert!(
        e.message.ends_with("use `Reflective` for a slip wall"),
        "{e}"
    );
    let mut fixed = StateConfig::at_pressure(1.2, 1e5);
    fixed.material = Some("tnt".into());
    tnt.boundaries.x_high = BoundaryConfig::Fixed(fixed);
    let s = tnt.scene();
    assert_eq!(
        field("(material: \"air\", products: Some(\"tnt\"))", &s).as_deref(),
        Some("boundaries.x_high.material")
    );
}

/// Each cell takes the state of the last region holding its centre; with
/// products carried, a products region holds Y = 1.
#[test]
fn the_builder_fills_each_cell_from_the_last_region_holding_it() {
    let solver = config("(material: \"air\")")
        .build(&shock_tube("air").scene())
        .unwrap();
    let data = solver
        .cell_data(&["density".into(), "pressure".into()])
        .unwrap();
    assert_eq!(data.field("density").unwrap(), &[5.0, 5.0, 1.2, 1.2]);
    assert_eq!(data.field("pressure").unwrap(), &[1e6, 1e6, 1e5, 1e5]);
    let solver = config("(material: \"air\", products: Some(\"tnt\"))")
        .build(&shock_tube("tnt").scene())
        .unwrap();
    let y = solver
        .cell_data(&[FdmSolver::<IdealGas>::MASS_FRACTION_FIELD.into()])
        .unwrap();
    assert_eq!(y.fields[0].1, [1.0, 1.0, 0.0, 0.0]);
}

/// A cell in no region is an error naming `initial` and the cell.
#[test]
fn an_uncovered_cell_stops_the_build() {
    let mut o = shock_tube("air");
    o.initial = vec![(
        Shape::Box {
            min: [0.0; 3],
            max: [0.6, 2.0, 2.0],
        },
        "air".into(),
        StateConfig::at_pressure(1.2, 1e5),
    )];
    let e = config("(material: \"air\")")
        .build(&o.scene())
        .err()
        .unwrap();
    assert_eq!(e.field, "initial");
    assert!(e.message.starts_with("cell (2, 0, 0) at [0.625, "), "{e}");
}

/// The products species adds its mass fraction to the fields; an (r, z)
/// grid's radial sweep needs one more ghost layer.
#[test]
fn the_limits_follow_the_species_and_the_grid() {
    let one = config("(material: \"air\")");
    let two = config("(material: \"air\", products: Some(\"tnt\"))");
    assert_eq!(one.limits(Geometry::Cartesian).fields.len(), 10);
    assert_eq!(
        two.limits(Geometry::Cartesian).fields.last(),
        Some(&"products_mass_fraction")
    );
    assert_eq!(one.limits(Geometry::Cartesian).ghost, crate::GHOST);
    assert_eq!(one.limits(Geometry::Axisymmetric).ghost, crate::GHOST_RZ);
    const { assert!(crate::GHOST_RZ > crate::GHOST) };
}

/// `brisance check`'s paragraph names the gas, its law, the faces and the
/// outputs.
#[test]
fn the_description_names_gas_faces_and_outputs() {
    let text = config("(material: \"air\")").describe(&shock_tube("air").scene());
    assert!(text.starts_with("scenario `tube`: Fdm pipeline"), "{text}");
    assert!(
        text.contains("gas: `air` (IdealGas), viscosity Adaptive"),
        "{text}"
    );
    assert!(
        text.contains("boundaries: x_low=outflow x_high=outflow"),
        "{text}"
    );
    assert!(
        text.contains("outputs: interval None, fields [], 0 gauges, 0 line-outs"),
        "{text}"
    );
}
