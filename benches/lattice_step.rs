//! Criterion benchmark `lattice_step`: one explicit-Euler step of the MSDM
//! lattice (seed 003 §2.3, eqs 16–17) with the energy equation (eqs 10c,
//! 11–15) and heat conduction, on the 432 × 432 lattice of the hot-spot
//! problem (§4.2). Throughput is in node-updates per second (432² solid
//! nodes per step); the target of issue 6 is ≥ 30e6. Measured figures:
//! `docs/physics/lattice/hotspots.md`.

use brisance::lattice::{cases::estane_step_block, MsdmLattice};
use criterion::{criterion_group, Criterion, Throughput};

/// The Estane block of `brisance_lattice::cases::estane_step_block`
/// (seed 003 Table 2 EOS, E = 6.25 GPa, κ = 0.2 W/(m·K), h = 10 µm,
/// −100 m/s, axial springs with the perpendicular corrective force of
/// eq 10b, explicit Euler with the energy equation).
fn block(n: usize, diagonals: bool) -> MsdmLattice {
    estane_step_block(n, diagonals).expect("benchmark lattice builds")
}

fn lattice_step(c: &mut Criterion) {
    let n = 432;
    let mut group = c.benchmark_group("lattice_step");
    group.throughput(Throughput::Elements((n * n) as u64));
    group.sample_size(20);
    for (name, diagonals) in [
        ("explicit_euler_432sq", false),
        ("explicit_euler_432sq_diagonals", true),
    ] {
        let mut lat = block(n, diagonals);
        let dt = 0.5 * lat.explicit_stable_dt();
        group.bench_function(name, |b| b.iter(|| lat.step(dt).expect("lattice step")));
    }
    group.finish();
}

criterion_group!(benches, lattice_step);

/// `LATTICE_STEPS=n` runs n steps of the axial-spring lattice and exits
/// instead of benchmarking, for instruction counts that do not depend on
/// the machine's load (`valgrind --tool=callgrind`, the difference between
/// two values of n).
fn main() {
    if let Some(steps) = std::env::var("LATTICE_STEPS")
        .ok()
        .and_then(|s| s.parse::<usize>().ok())
    {
        let mut lat = block(432, false);
        let dt = 0.5 * lat.explicit_stable_dt();
        for _ in 0..steps {
            lat.step(dt).expect("lattice step");
        }
        println!("{steps} steps, t = {:.6e} s", lat.time);
        return;
    }
    benches();
    Criterion::default().configure_from_args().final_summary();
}
