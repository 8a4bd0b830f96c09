//! The solver's memory count (`PdSolver::memory_use`) against hand counts.

use super::*;
use crate::lattice::BodySpec;
use crate::material::{Proportional, ProportionalKind};
use brisance_grid::Shape;

/// A micro-elastic steel block of n³ nodes, δ = 3h, as the bond-force
/// bench uses, with or without short-range forces.
fn block(n: usize, contact: Option<ContactOptions>) -> PdSolver {
    let h = 1.0e-3;
    PdSolver::new(PdSetup {
        options: PdOptions {
            spacing: h,
            contact,
            ..PdOptions::default()
        },
        materials: vec![PdMaterial::Proportional(Proportional {
            density: 7850.0,
            sound_speed: 3212.0,
            yield_strength: f64::INFINITY,
            critical_stretch: f64::INFINITY,
            kind: ProportionalKind::MicroElastic,
            damage_stretch_coefficient: 0.0,
            minimum_stretch_coefficient: 0.0,
            spread: None,
        })],
        bodies: vec![BodySpec {
            shape: Shape::Box {
                min: [0.0; 3],
                max: [n as f64 * h; 3],
            },
            material: 0,
            velocity: [0.0; 3],
        }],
        boundaries: vec![],
        detonation: None,
    })
    .unwrap()
}

/// Per node: reference (x, V) 32, state (u, σ) 32, velocity 24, bond
/// output 32 (force 24, smallest stretch 4, intact count 4), body 4,
/// material 2, node scale 8, detonation time 8, row start 4: 146 bytes,
/// plus the one extra row start. Per bond: neighbour 4, factor 4,
/// plastic stretch 4.
#[test]
fn a_micro_elastic_block_takes_146_bytes_per_node_and_12_per_bond() {
    let s = block(12, None);
    let m = s.memory_use();
    let (n, b) = (12 * 12 * 12, s.bond_count());
    assert_eq!((m.nodes, m.bonds), (n, b));
    assert_eq!(m.node_bytes, 146 * n + 4);
    assert_eq!(m.bond_bytes, 12 * b);
    assert!(m.bytes_per_node() <= 200.0, "{}", m.bytes_per_node());
    assert!(m.bytes_per_bond() <= 12.0);
    // One material: its parameters, law, bulk modulus, breakable flag,
    // reactant flag and density.
    assert_eq!(
        m.other_bytes,
        std::mem::size_of::<PdMaterial>() + std::mem::size_of::<BondLaw>() + 8 + 1 + 1 + 8
    );
    assert_eq!(m.total(), m.node_bytes + m.bond_bytes + m.other_bytes);
}

/// Short-range forces add, per node, the contact force and stiffness (32)
/// and the cell list: 2 u32 and the kept current position (24) per node,
/// a table of 4096 + 1 u32 starts for 1728 nodes and 8 positions of
/// padding.
#[test]
fn contact_adds_its_arrays_and_cell_list() {
    let n = 12 * 12 * 12;
    let m = block(12, Some(ContactOptions::default())).memory_use();
    assert_eq!(
        m.node_bytes,
        (146 + 32 + 8 + 24) * n + 4 + 4097 * 4 + 8 * 24
    );
}
