//! Tests of the node mass cut-off's reference particle mass
//! ([`reference_particle_mass`]): the mean particle mass of the lightest
//! material, which for one material is the all-particle mean, bit for bit.

use super::*;
use brisance_constitutive::{Hypoelastic, ObjectiveRate, PressureModel};

fn elastic() -> MaterialModel {
    MaterialModel::Hypoelastic(Hypoelastic {
        shear_modulus: 3.0e7,
        pressure: PressureModel::Linear {
            bulk_modulus: 6.0e7,
        },
        rate: ObjectiveRate::Jaumann,
    })
}

fn particle(x: f64, vx: f64, mass: f64, material: u16) -> ParticleInit {
    ParticleInit {
        position: [x, 0.5, 0.5],
        velocity: [vx, 0.0, 0.0],
        mass,
        volume: 1.0,
        material: MaterialId(material),
        ..Default::default()
    }
}

fn particles(list: &[ParticleInit]) -> Particles {
    let mut ps = Particles::new(0);
    for p in list {
        ps.push(p, &[]).unwrap();
    }
    ps
}

#[test]
fn one_material_reference_is_the_all_particle_mean_to_the_bit() {
    let ps = particles(&[
        particle(0.5, 0.0, 0.1, 0),
        particle(1.5, 0.0, 0.2, 0),
        particle(2.5, 0.0, 0.7, 0),
    ]);
    let r = reference_particle_mass(&ps, 1);
    assert_eq!(r.to_bits(), (ps.total_mass() / 3.0).to_bits());
    assert_eq!(r, (0.1 + 0.2 + 0.7) / 3.0);
}

#[test]
fn two_materials_reference_is_the_lighter_materials_mean() {
    // Steel-like material 1 (1 kg particles) and gas-like material 0
    // (1 g and 3 g): the reference is (0.001 + 0.003)/2 = 0.002, not the
    // all-particle mean 3.004/5.
    let ps = particles(&[
        particle(0.5, 0.0, 1.0, 1),
        particle(1.5, 0.0, 0.001, 0),
        particle(2.5, 0.0, 1.0, 1),
        particle(3.5, 0.0, 0.003, 0),
        particle(3.6, 0.0, 1.0, 1),
    ]);
    assert_eq!(reference_particle_mass(&ps, 2), (0.001 + 0.003) / 2.0);
    // A material with no particles does not count; ids past the model
    // count still do.
    assert_eq!(reference_particle_mass(&ps, 3), (0.001 + 0.003) / 2.0);
    assert_eq!(reference_particle_mass(&ps, 1), (0.001 + 0.003) / 2.0);
    assert_eq!(reference_particle_mass(&particles(&[]), 2), 0.0);
}

/// A 10⁴ kg particle at x = 0.5 m and two 1 kg particles at x = 3.25 and
/// 3.75 m moving at 3 m/s, on a 1D grid of four 1 m cells (linear shape):
/// nodes 3 and 4 each get m = 0.75 + 0.25 = 1 kg and p = 3 kg m/s.
fn heavy_and_light(light_material: u16) -> MpmSolver {
    let level = Level::new([0.0; 3], [4.0, 1.0, 1.0], [4, 1, 1], [1, 1, 1], 0).unwrap();
    let ps = particles(&[
        particle(0.5, 0.0, 1.0e4, 0),
        particle(3.25, 3.0, 1.0, light_material),
        particle(3.75, 3.0, 1.0, light_material),
    ]);
    MpmSolver::new(level, vec![elastic(), elastic()], ps, MpmOptions::default()).unwrap()
}

fn names(fields: &[&str]) -> Vec<String> {
    fields.iter().map(|s| s.to_string()).collect()
}

#[test]
fn a_node_of_light_particles_beside_a_heavy_material_is_not_cut() {
    // Light particles are material 1: reference 1 kg, threshold 1e-3 kg,
    // so the 1 kg nodes 3 and 4 move at p/m = 3 m/s.
    let s = heavy_and_light(1);
    assert_eq!(s.reference_particle_mass, 1.0);
    let d = s
        .node_data(&names(&["mass", "velocity_x", "active"]))
        .unwrap()
        .unwrap();
    assert_eq!(d.field("mass").unwrap(), [5.0e3, 5.0e3, 0.0, 1.0, 1.0]);
    assert_eq!(d.field("velocity_x").unwrap(), [0.0, 0.0, 0.0, 3.0, 3.0]);
    assert_eq!(d.field("active").unwrap(), [1.0, 1.0, 0.0, 1.0, 1.0]);
}

#[test]
fn one_material_keeps_the_mean_particle_mass_cut_off() {
    // All one material: reference (10⁴ + 1 + 1)/3 kg, threshold 3.334 kg
    // above the 1 kg of nodes 3 and 4, which are cut as before.
    let s = heavy_and_light(0);
    assert_eq!(s.reference_particle_mass, (1.0e4 + 1.0 + 1.0) / 3.0);
    let d = s
        .node_data(&names(&["velocity_x", "active"]))
        .unwrap()
        .unwrap();
    assert_eq!(d.field("velocity_x").unwrap(), [0.0; 5]);
    assert_eq!(d.field("active").unwrap(), [1.0, 1.0, 0.0, 0.0, 0.0]);
}
