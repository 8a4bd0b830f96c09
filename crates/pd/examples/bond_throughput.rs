//! Bond-force throughput of the micro-elastic kernel on a 3D block
//! (δ = 3h), timed on one and two threads: the best and median of repeated
//! passes, in bond evaluations per second. The criterion bench
//! `pd_bond_forces` in the workspace `benches/` is the reference figure;
//! this is a quick check that needs only this crate.
//!
//! `cargo run --release -p brisance-pd --example bond_throughput [n] [passes]`
//!
//! With a few passes it is also the program to count instructions on
//! (`valgrind --tool=callgrind`), which the load of a shared machine does
//! not disturb.

use brisance_pd::{bond_forces, cases::BondBenchBlock, NodeForce};
use std::time::Instant;

fn main() {
    let n: usize = std::env::args()
        .nth(1)
        .and_then(|a| a.parse().ok())
        .unwrap_or(28);
    let passes: usize = std::env::args()
        .nth(2)
        .and_then(|a| a.parse().ok())
        .unwrap_or(30)
        .max(1);
    let mut block = BondBenchBlock::new(n, 1.0e-3);
    let mut factor = std::mem::take(&mut block.factor);
    let mut plastic = vec![0f32; factor.len()];
    let mut out = vec![NodeForce::default(); block.reference.len()];
    let input = block.input();
    let (families, reference) = (&block.families, &block.reference);
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
            (0..passes)
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
        // FNV-1a digest of the force bits, to compare kernels bit for bit.
        let digest = bits.iter().fold(0xcbf2_9ce4_8422_2325u64, |h, b| {
            (h ^ b).wrapping_mul(0x0100_0000_01b3)
        });
        println!(
            "{threads} thread(s): best {:.1} M/s, median {:.1} M/s, same bits as 1 thread: {same}, digest {digest:016x}",
            bonds / times[0] / 1e6,
            bonds / times[times.len() / 2] / 1e6
        );
    }
}
