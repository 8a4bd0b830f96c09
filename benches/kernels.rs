//! Criterion benchmarks, one group per kernel, each reporting throughput in
//! the kernel's unit.

use brisance::core::Solver;
use brisance::verification::cases::blast_box;
use criterion::{criterion_group, criterion_main, Criterion, Throughput};

/// One full FDM step (six Lax–Wendroff sweeps with viscosity, halo fills and
/// the CFL reduction) on a 3D 64³ box: cell-updates per second.
fn fdm_lax_wendroff(c: &mut Criterion) {
    let n = 64;
    let mut solver = blast_box(n, [1, 1, 1]).expect("benchmark problem builds");
    let mut group = c.benchmark_group("fdm_lax_wendroff");
    group.throughput(Throughput::Elements((n * n * n) as u64));
    group.sample_size(20);
    group.bench_function("step_64cubed", |b| {
        b.iter(|| {
            let dt = solver.stable_dt().expect("stable");
            solver.advance(dt).expect("advances");
        })
    });
    group.finish();
}

criterion_group!(benches, fdm_lax_wendroff);
criterion_main!(benches);
