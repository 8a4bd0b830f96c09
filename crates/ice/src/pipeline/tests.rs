//! The Ice pipeline's section on hand-made scenes: its checks name the
//! field, its builder gives each cell the last region's material with the
//! others as traces, and its reactions take the JWL++ default heat.

use brisance_core::{Geometry, Solver};
use brisance_eos::{EosModel, IdealGas, JwlCTerm, Murnaghan};
use brisance_grid::Shape;
use brisance_scene::{
    BoundaryConfig, Domain, InitialRegion, Material, OutputsSummary, PipelineSpec, Scene,
    StateConfig, OPEN_FACES,
};

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

/// Air and helium (ideal gases), ANFO-K1 and its products.
fn materials() -> Vec<(&'static str, EosModel)> {
    vec![
        ("air", EosModel::IdealGas(IdealGas::new(1.4, 717.5, 1.2))),
        (
            "helium",
            EosModel::IdealGas(IdealGas::new(5.0 / 3.0, 3116.0, 0.17)),
        ),
        ("anfo", EosModel::Murnaghan(Murnaghan::anfo_k1())),
        ("products", EosModel::JwlCTerm(JwlCTerm::anfo_k1())),
    ]
}

/// A 1D tube of four 0.25 m cells along x: air everywhere, helium at
/// 10 bar in x < 0.5.
fn tube() -> Vec<(Shape, &'static str, StateConfig)> {
    vec![
        (Shape::Everywhere, "air", state(1.2, 1e5)),
        (
            Shape::Box {
                min: [-1.0; 3],
                max: [0.5, 2.0, 2.0],
            },
            "helium",
            state(1.5, 1e6),
        ),
    ]
}

fn scene<'a>(
    eos: &'a [(&'static str, EosModel)],
    initial: &'a [(Shape, &'static str, StateConfig)],
    boundaries: &'a brisance_scene::Boundaries,
    field_lists: Vec<(String, &'a [String])>,
) -> Scene<'a> {
    Scene {
        name: "tube",
        domain: Domain {
            lower: [0.0; 3],
            upper: [1.0; 3],
            cells: [4, 1, 1],
            patches: [1; 3],
            geometry: Geometry::Cartesian,
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
        field_lists,
        outputs: OutputsSummary::default(),
    }
}

/// Each bad part of the section is reported at its field.
#[test]
fn each_bad_section_names_its_field() {
    let eos = materials();
    let initial = tube();
    let s = scene(&eos, &initial, &OPEN_FACES, vec![]);
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
    let mut faces = OPEN_FACES.clone();
    faces.x_low = BoundaryConfig::Fixed(state(1.2, 1e5));
    let s = scene(&eos, &initial, &faces, vec![]);
    assert_eq!(
        field("(materials: [\"air\", \"helium\"])", &s).as_deref(),
        Some("boundaries.x_low")
    );
    // A per-material output field beyond the materials given.
    let fields = ["pressure".to_string(), "density_3".to_string()];
    let s = scene(
        &eos,
        &initial,
        &OPEN_FACES,
        vec![("outputs.gauges.0.fields".into(), &fields[..])],
    );
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
    let eos = materials();
    let initial = tube();
    let s = scene(&eos, &initial, &OPEN_FACES, vec![]);
    let solver = config("(materials: [\"air\", \"helium\"])")
        .build(&s)
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
    let eos = materials();
    let initial = vec![(Shape::Everywhere, "anfo", state(1160.0, 1e5))];
    let s = scene(&eos, &initial, &OPEN_FACES, vec![]);
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
    let eos = materials();
    let initial = tube();
    let s = scene(&eos, &initial, &OPEN_FACES, vec![]);
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
