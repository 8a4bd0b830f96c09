//! The Fdm pipeline's section on hand-made scenes: its checks name the
//! field, its builder fills each cell from the last region holding it,
//! and its limits follow the grid.

use brisance_core::Geometry;
use brisance_eos::{EosModel, IdealGas, Jwl, Murnaghan};
use brisance_grid::Shape;
use brisance_scene::{
    Boundaries, BoundaryConfig, Domain, InitialRegion, Material, OutputsSummary, PipelineSpec,
    Scene, StateConfig, OPEN_FACES,
};

use super::*;

fn config(text: &str) -> FdmConfig {
    ron::from_str(text).unwrap()
}

fn state(density: f64, pressure: f64) -> StateConfig {
    StateConfig {
        density,
        velocity: [0.0; 3],
        pressure: Some(pressure),
        specific_internal_energy: None,
        temperature: None,
        material: None,
    }
}

/// The materials of the scenes: an ideal gas (γ = 1.4), the TNT products
/// (JWL) and a solid (Murnaghan).
fn materials() -> Vec<(&'static str, EosModel)> {
    vec![
        ("air", EosModel::IdealGas(IdealGas::new(1.4, 717.5, 1.2))),
        ("tnt", EosModel::Jwl(Jwl::tnt())),
        ("solid", EosModel::Murnaghan(Murnaghan::anfo_k1())),
    ]
}

/// A 1D tube of four 0.25 m cells along x, one patch.
fn scene<'a>(
    eos: &'a [(&'static str, EosModel)],
    initial: &'a [(Shape, &'static str, StateConfig)],
    boundaries: &'a Boundaries,
    geometry: Geometry,
) -> Scene<'a> {
    Scene {
        name: "tube",
        domain: Domain {
            lower: [0.0; 3],
            upper: [1.0, 1.0, 1.0],
            cells: [4, 1, 1],
            patches: [1; 3],
            geometry,
        },
        end_time: 1e-3,
        cfl: 0.5,
        boundaries,
        materials: eos
            .iter()
            .map(|(name, e)| Material { name, eos: Some(e) })
            .collect(),
        initial: initial
            .iter()
            .map(|(region, material, state)| InitialRegion {
                region,
                material,
                state,
            })
            .collect(),
        cell_fields: &[],
        line_outs: 0,
        field_lists: vec![],
        outputs: OutputsSummary::default(),
    }
}

/// Air everywhere at 1 bar, high pressure (10 bar, 5 kg/m³) in x < 0.5.
fn shock_tube(material: &'static str) -> Vec<(Shape, &'static str, StateConfig)> {
    vec![
        (Shape::Everywhere, "air", state(1.2, 1e5)),
        (
            Shape::Box {
                min: [-1.0; 3],
                max: [0.5, 2.0, 2.0],
            },
            material,
            state(5.0, 1e6),
        ),
    ]
}

/// The gas must be a known gas, a constant η must lie in [0, 0.25], every
/// region must hold the gas or the products, and the faces must be the
/// pipeline's: each error names its field.
#[test]
fn each_bad_section_names_its_field() {
    let eos = materials();
    let initial = shock_tube("air");
    let s = scene(&eos, &initial, &OPEN_FACES, Geometry::Cartesian);
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
    let initial = shock_tube("tnt");
    let s = scene(&eos, &initial, &OPEN_FACES, Geometry::Cartesian);
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
    let mut faces = OPEN_FACES.clone();
    faces.x_high = BoundaryConfig::Wall;
    let s = scene(&eos, &initial, &faces, Geometry::Cartesian);
    let e = config("(material: \"air\", products: Some(\"tnt\"))")
        .validate(&s)
        .unwrap_err();
    assert_eq!(e.field, "boundaries.x_high");
    assert!(
        e.message.ends_with("use `Reflective` for a slip wall"),
        "{e}"
    );
    let mut fixed = state(1.2, 1e5);
    fixed.material = Some("tnt".into());
    faces.x_high = BoundaryConfig::Fixed(fixed);
    let s = scene(&eos, &initial, &faces, Geometry::Cartesian);
    assert_eq!(
        field("(material: \"air\", products: Some(\"tnt\"))", &s).as_deref(),
        Some("boundaries.x_high.material")
    );
}

/// Each cell takes the state of the last region holding its centre; with
/// products carried, a products region holds Y = 1.
#[test]
fn the_builder_fills_each_cell_from_the_last_region_holding_it() {
    let eos = materials();
    let initial = shock_tube("air");
    let s = scene(&eos, &initial, &OPEN_FACES, Geometry::Cartesian);
    let solver = config("(material: \"air\")").build(&s).unwrap();
    let data = solver
        .cell_data(&["density".into(), "pressure".into()])
        .unwrap();
    assert_eq!(data.field("density").unwrap(), &[5.0, 5.0, 1.2, 1.2]);
    assert_eq!(data.field("pressure").unwrap(), &[1e6, 1e6, 1e5, 1e5]);
    let initial = shock_tube("tnt");
    let s = scene(&eos, &initial, &OPEN_FACES, Geometry::Cartesian);
    let solver = config("(material: \"air\", products: Some(\"tnt\"))")
        .build(&s)
        .unwrap();
    let y = solver
        .cell_data(&[FdmSolver::<IdealGas>::MASS_FRACTION_FIELD.into()])
        .unwrap();
    assert_eq!(y.fields[0].1, [1.0, 1.0, 0.0, 0.0]);
}

/// A cell in no region is an error naming `initial` and the cell.
#[test]
fn an_uncovered_cell_stops_the_build() {
    let eos = materials();
    let initial = vec![(
        Shape::Box {
            min: [0.0; 3],
            max: [0.6, 2.0, 2.0],
        },
        "air",
        state(1.2, 1e5),
    )];
    let s = scene(&eos, &initial, &OPEN_FACES, Geometry::Cartesian);
    let e = config("(material: \"air\")").build(&s).err().unwrap();
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
    let eos = materials();
    let initial = shock_tube("air");
    let s = scene(&eos, &initial, &OPEN_FACES, Geometry::Cartesian);
    let text = config("(material: \"air\")").describe(&s);
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
