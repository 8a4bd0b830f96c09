//! Bond-force throughput of the micro-elastic kernel on a 3D block
//! (δ = 3h), timed on one and two threads: the best and median of repeated
//! passes, in bond evaluations per second. The criterion bench
//! `pd_bond_forces` in the workspace `benches/` is the reference figure;
//! this is a quick check that needs only this crate.
//!
//! `cargo run --release -p brisance-pd --example bond_throughput [n]`

use brisance_grid::Shape;
use brisance_pd::{
    bond_forces, build_families, fill_lattice, partial_volume, spring_constant, BodySpec, BondLaw,
    Dimension, ForceInput, LatticeSpec, NodeForce,
};
use std::time::Instant;

fn main() {
    let n: usize = std::env::args()
        .nth(1)
        .and_then(|a| a.parse().ok())
        .unwrap_or(28);
    let h = 1.0e-3;
    let cloud = fill_lattice(
        &LatticeSpec {
            spacing: h,
            origin: [0.0; 3],
            dimension: Dimension::Three,
            cross_section: 0.0,
        },
        &[BodySpec {
            shape: Shape::Box {
                min: [0.0; 3],
                max: [n as f64 * h; 3],
            },
            material: 0,
            velocity: [0.0; 3],
        }],
    )
    .expect("block fills");
    let horizon = 3.0 * h;
    let families = build_families(&cloud.positions, &cloud.body, horizon, h);
    let reference: Vec<[f64; 4]> = cloud
        .positions
        .iter()
        .zip(&cloud.volumes)
        .map(|(x, v)| [x[0], x[1], x[2], *v])
        .collect();
    let state: Vec<[f64; 4]> = cloud
        .positions
        .iter()
        .map(|x| {
            [
                1e-4 * (x[0] * 300.0).sin(),
                1e-4 * x[1],
                -2e-5 * x[2],
                f64::INFINITY,
            ]
        })
        .collect();
    let mut factor = Vec::with_capacity(families.bond_count());
    for i in 0..cloud.positions.len() {
        for &j in &families.neighbours[families.row(i)] {
            let (a, b) = (cloud.positions[i], cloud.positions[j as usize]);
            let r = ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)).sqrt();
            factor.push(partial_volume(r, horizon, h) as f32);
        }
    }
    let mut plastic = vec![0f32; factor.len()];
    let mut out = vec![NodeForce::default(); reference.len()];
    let laws = [BondLaw::Solid {
        micromodulus: spring_constant(7850.0 * 3212.0 * 3212.0, horizon),
        yield_stretch: f64::INFINITY,
        plastic: false,
        critical_stretch: f64::INFINITY,
    }];
    let material = vec![0u16; reference.len()];
    let input = ForceInput {
        reference: &reference,
        state: &state,
        offsets: &families.offsets,
        neighbours: &families.neighbours,
        material: &material,
        laws: &laws,
    };
    let bonds = families.bond_count() as f64;
    println!(
        "{} nodes, {} bonds ({:.1} per node)",
        reference.len(),
        families.bond_count(),
        bonds / reference.len() as f64
    );
    let mut reference_bits = None;
    for threads in [1, 2] {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .expect("pool");
        let mut times: Vec<f64> = pool.install(|| {
            (0..30)
                .map(|_| {
                    let t = Instant::now();
                    bond_forces(&input, &mut factor, &mut plastic, &mut out);
                    t.elapsed().as_secs_f64()
                })
                .collect()
        });
        times.sort_by(f64::total_cmp);
        let bits: Vec<u64> = out.iter().flat_map(|o| o.force.map(f64::to_bits)).collect();
        let same = reference_bits.get_or_insert_with(|| bits.clone()) == &bits;
        println!(
            "{threads} thread(s): best {:.1} M/s, median {:.1} M/s, same bits as 1 thread: {same}",
            bonds / times[0] / 1e6,
            bonds / times[times.len() / 2] / 1e6
        );
    }
}
