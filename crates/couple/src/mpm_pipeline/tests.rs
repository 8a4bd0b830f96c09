use super::*;
use crate::scenario_text::parse;
use brisance_constitutive::NullMaterial;
use brisance_scene::{Domain, OwnedScene};

const RHO: f64 = 1.225;
const P: f64 = 1.0e5;

fn section(ppc: usize) -> MpmConfig {
    parse(&format!("(ppc: {ppc})"))
}

/// Air as particles (`gas`, a Null material on the ideal gas) over `x` in
/// [0, 0.2] m, 2 cells along x, one along y and z, and a material `ghost`
/// with an EOS but no constitutive model.
fn gas_scene() -> OwnedScene {
    let air = NullMaterial::air();
    let eos = air.eos.clone();
    OwnedScene::new(Domain::cartesian([0.0; 3], [0.2, 1.0, 1.0], [2, 1, 1]))
        .with_material("gas", Some(eos.clone()))
        .with_model("gas", MaterialModel::Null(air), None)
        .with_material("ghost", Some(eos))
        .with_region(Shape::Everywhere, "gas", StateConfig::at_pressure(RHO, P))
}

/// ppc points per active direction of every cell become particles at the
/// sub-cell centres, each with ρ V_cell / ppc and the state's energy.
#[test]
fn every_sub_cell_point_becomes_a_particle_of_its_share_of_the_mass() {
    let owned = gas_scene();
    let solver = mpm_parts(&owned.scene(), &section(2), false).expect("builds");
    let p = solver.particles();
    assert_eq!(p.len(), 4);
    for (k, x) in [0.025, 0.075, 0.125, 0.175].into_iter().enumerate() {
        assert!((p.position[k][0] - x).abs() < 1e-15, "{:?}", p.position[k]);
        assert_eq!(p.position[k][1], 0.5);
        assert!((p.mass[k] - RHO * 0.1 / 2.0).abs() < 1e-15, "{}", p.mass[k]);
        // Ideal gas: e = p / ((γ − 1) ρ) with γ = 1.4.
        let e = P / (0.4 * RHO);
        assert!(
            (p.specific_internal_energy[k] - e).abs() < 1e-9 * e,
            "{}",
            p.specific_internal_energy[k]
        );
    }
    assert!(solver.particle_gauges().is_empty());
}

/// A fluid's particles start at their EOS pressure, σ = −p I (their first
/// step pushes as the gas does); a solid's start unstressed.
#[test]
fn fluid_particles_start_at_their_pressure_and_solid_ones_unstressed() {
    use brisance_constitutive::{Hypoelastic, ObjectiveRate, PressureModel};
    let solid = MaterialModel::Hypoelastic(Hypoelastic {
        shear_modulus: 80e9,
        pressure: PressureModel::Linear {
            bulk_modulus: 160e9,
        },
        rate: ObjectiveRate::Jaumann,
    });
    let cold = StateConfig {
        temperature: Some(293.0),
        pressure: None,
        ..StateConfig::at_pressure(7800.0, 0.0)
    };
    let owned = gas_scene().with_model("ghost", solid, None).with_region(
        Shape::Box {
            min: [0.1, 0.0, 0.0],
            max: [0.2, 1.0, 1.0],
        },
        "ghost",
        cold,
    );
    let solver = mpm_parts(&owned.scene(), &section(2), false).expect("builds");
    let p = solver.particles();
    assert_eq!(p.len(), 4);
    for k in 0..2 {
        assert!(p.position[k][0] < 0.1);
        for a in 0..3 {
            assert!((p.stress[k][a] + P).abs() < 1e-9 * P, "{:?}", p.stress[k]);
            assert_eq!(p.stress[k][a + 3], 0.0);
        }
    }
    for k in 2..4 {
        assert!(p.position[k][0] > 0.1);
        assert_eq!(p.stress[k], [0.0; 6]);
    }
}

/// On an (r, z) grid a particle is a ring: its sub-cell's cross-section
/// swept through 2π at its radius.
#[test]
fn an_rz_particle_is_a_ring_about_the_axis() {
    let mut owned = gas_scene();
    owned.domain.geometry = Geometry::Axisymmetric;
    let solver = mpm_parts(&owned.scene(), &section(2), false).expect("builds");
    let p = solver.particles();
    for (k, r) in [0.025, 0.075, 0.125, 0.175].into_iter().enumerate() {
        let volume = 2.0 * std::f64::consts::PI * r * (0.1 / 2.0) * 1.0;
        assert!(
            (p.mass[k] - RHO * volume).abs() < 1e-14 * RHO * volume,
            "{} against {}",
            p.mass[k],
            RHO * volume
        );
    }
    // A cell is the ring it sweeps: the rings' masses over the rings'
    // volumes give the gas's density back.
    use brisance_core::Solver;
    let d = solver.cell_data(&["mass_density".to_string()]).unwrap();
    for &rho in d.field("mass_density").unwrap() {
        assert!((rho - RHO).abs() < 1e-12 * RHO, "{rho}");
    }
}

/// A region of a material without a constitutive model is refused at its
/// `material`, except beside fluids (the coupled pipelines), where it is
/// left to them.
#[test]
fn a_region_without_a_model_is_refused_alone_and_left_out_beside_fluids() {
    let mut owned = gas_scene();
    owned.initial.clear();
    let half = |lo: f64| Shape::Box {
        min: [lo, 0.0, 0.0],
        max: [lo + 0.1, 1.0, 1.0],
    };
    let owned = owned
        .with_region(half(0.0), "gas", StateConfig::at_pressure(RHO, P))
        .with_region(half(0.1), "ghost", StateConfig::at_pressure(RHO, P));
    let s = owned.scene();
    let e = section(1).validate(&s).expect_err("refused");
    assert_eq!(e.field, "initial.1.material");
    assert!(e.message.contains("no constitutive `model`"), "{e}");
    let e = mpm_parts(&s, &section(1), false).expect_err("refused");
    assert_eq!(e.field, "initial.1.material");
    let solver = mpm_parts(&s, &section(1), true).expect("the fluids' region is left out");
    assert_eq!(solver.particles().len(), 1);
    assert!((solver.particles().position[0][0] - 0.05).abs() < 1e-15);
}

/// The section's own fields and the scene's parts it owns are checked with
/// their paths.
#[test]
fn the_checks_name_their_fields() {
    let owned = gas_scene();
    let s = owned.scene();
    assert!(section(2).validate(&s).is_ok());
    assert_eq!(section(0).validate(&s).unwrap_err().field, "pipeline.ppc");
    assert_eq!(section(9).validate(&s).unwrap_err().field, "pipeline.ppc");
    let mut cut = section(2);
    cut.mass_cutoff = 1.0;
    assert_eq!(cut.validate(&s).unwrap_err().field, "pipeline.mass_cutoff");
    let mut fall = section(2);
    fall.gravity[1] = f64::NAN;
    assert_eq!(fall.validate(&s).unwrap_err().field, "pipeline.gravity");
    let mut q: MpmConfig = parse("(bulk_viscosity: On(quadratic: -1.0, linear: 0.06))");
    assert_eq!(
        q.validate(&s).unwrap_err().field,
        "pipeline.bulk_viscosity.quadratic"
    );
    q.bulk_viscosity = BulkViscosityConfig::Off;
    assert!(q.validate(&s).is_ok());
    q.fluid_bulk_viscosity = Some(BulkViscosity {
        quadratic: 1.5,
        linear: f64::INFINITY,
    });
    assert_eq!(
        q.validate(&s).unwrap_err().field,
        "pipeline.fluid_bulk_viscosity.linear"
    );
    let fluids: MpmConfig = parse("(fluid_bulk_viscosity: Some(quadratic: 1.5, linear: 1.0))");
    assert!(fluids.validate(&s).is_ok());
    assert_eq!(
        describe_bulk_viscosity(&fluids.bulk_viscosity, fluids.fluid_bulk_viscosity),
        "off (fluids Q1 = 1.5, Q2 = 1)"
    );
    assert_eq!(
        describe_bulk_viscosity(
            &BulkViscosityConfig::On(BulkViscosity::LS_DYNA),
            Some(BulkViscosity::LS_DYNA)
        ),
        "Q1 = 1.5, Q2 = 0.06"
    );

    // Heat conduction is for particle materials.
    let mut warm = gas_scene();
    warm.models.clear();
    let air = NullMaterial::air();
    warm = warm.with_model(
        "gas",
        MaterialModel::Null(air),
        Some(ThermalConfig {
            conductivity: -1.0,
            specific_heat: Some(717.0),
        }),
    );
    assert_eq!(
        section(2).validate(&warm.scene()).unwrap_err().field,
        "materials.gas.thermal.conductivity"
    );

    // Reservoir faces do not run on (r, z) grids.
    let mut rz = gas_scene();
    rz.domain.geometry = Geometry::Axisymmetric;
    assert!(section(2).validate(&rz.scene()).is_ok());
    rz.boundaries.x_high = BoundaryConfig::ZeroGradient;
    assert_eq!(
        section(2).validate(&rz.scene()).unwrap_err().field,
        "domain.geometry"
    );
    // A particle gauge's material is a particle material.
    let mut gauged = gas_scene();
    gauged
        .particle_gauges
        .push(("g".into(), Shape::Everywhere, Some("ghost".into())));
    assert_eq!(
        section(2).validate(&gauged.scene()).unwrap_err().field,
        "outputs.particle_gauges.0.material"
    );
    // … and a periodic face is no MPM face at all.
    let mut periodic = gas_scene();
    periodic.boundaries.y_low = BoundaryConfig::Periodic;
    periodic.boundaries.y_high = BoundaryConfig::Periodic;
    let e = section(2).validate(&periodic.scene()).unwrap_err();
    assert!(e.field.starts_with("boundaries.y_"), "{e}");
}

/// A particle gauge selects the particles that start in its region; an
/// empty one is an error naming the gauge's region.
#[test]
fn a_particle_gauge_takes_the_particles_that_start_in_its_region() {
    let mut owned = gas_scene();
    let left = Shape::Box {
        min: [0.0, 0.0, 0.0],
        max: [0.1, 1.0, 1.0],
    };
    owned.particle_gauges.push(("left".into(), left, None));
    let solver = mpm_parts(&owned.scene(), &section(2), false).expect("builds");
    assert_eq!(solver.particle_gauges().len(), 1);
    assert_eq!(solver.particle_gauges()[0].len(), 2);
    let outside = Shape::Box {
        min: [1.0, 0.0, 0.0],
        max: [2.0, 1.0, 1.0],
    };
    owned.particle_gauges.push(("away".into(), outside, None));
    let e = mpm_parts(&owned.scene(), &section(2), false).expect_err("an empty gauge");
    assert_eq!(e.field, "outputs.particle_gauges.1.region");
    assert!(e.message.contains("`away`"), "{e}");
}
