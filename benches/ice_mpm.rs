//! Criterion benchmark of the coupled ICE–MPM step (seed 000 §3.3) against
//! the two standalone steps it is made of, on the same grid and particles:
//! a 1 mm steel cube (12 mm on a side, 2³ particles per cell) moving at
//! 50 m/s through still air in a 32³-cell box.
//!
//! - `ice_mpm_step/coupled`: one `IceMpm::advance`;
//! - `ice_mpm_step/ice_alone`: one ICE step of the same two materials with
//!   the steel Eulerian;
//! - `ice_mpm_step/mpm_alone`: one MPM step of the particles alone.
//!
//! The target of issue 8: coupled ≤ 1.5 × (ICE alone + MPM alone).
//! Throughput is in cell-updates per second (32³ per step); the particle
//! count is printed. `ICE_MPM_STEPS=n` runs n coupled steps and prints
//! cell-updates and particle-steps per second instead of benchmarking.
//! `ICE_MPM_PROFILE=coupled|ice|mpm:n` builds one of the three cases and
//! runs n of its steps with the bench's Δt, nothing else: the difference
//! of the instruction counts (`valgrind --tool=callgrind`) of n and 0
//! steps is the cost of n steps, free of the set-up.

use brisance::core::Solver;
use brisance_couple::ice_mpm::cases::{build_frames, build_warm, moving_cube, Setup};
use brisance_couple::IceMpm;
use criterion::{criterion_group, BenchmarkId, Criterion, Throughput};

const N: usize = 32;

/// The bench's case (`cases::moving_cube`).
fn setup() -> Setup {
    moving_cube()
}

/// The coupled case after a few steps, so the air already moves.
fn coupled() -> IceMpm {
    build_warm(&setup()).expect("the warm-up steps")
}

fn ice_mpm_step(c: &mut Criterion) {
    let cells = (N * N * N) as u64;
    let mut group = c.benchmark_group("ice_mpm_step");
    group.throughput(Throughput::Elements(cells));
    group.sample_size(10);
    let s0 = coupled();
    let dt = s0.stable_dt().expect("dt");
    println!(
        "ice_mpm_step: {cells} cells, {} particles, dt = {dt:e} s",
        s0.particles_per_step()
    );
    group.bench_function(BenchmarkId::new("coupled", cells), |b| {
        b.iter_batched(
            coupled,
            |mut s| s.advance(dt).expect("coupled step"),
            criterion::BatchSize::LargeInput,
        )
    });
    let (_, mpm) = build_frames(&setup());
    group.bench_function(BenchmarkId::new("ice_alone", cells), |b| {
        b.iter_batched(
            || build_frames(&setup()).0,
            |mut s| s.advance(dt).expect("ice step"),
            criterion::BatchSize::LargeInput,
        )
    });
    group.bench_function(BenchmarkId::new("mpm_alone", cells), |b| {
        b.iter_batched(
            || mpm.clone(),
            |mut s| s.advance(dt).expect("mpm step"),
            criterion::BatchSize::LargeInput,
        )
    });
    group.finish();
}

criterion_group!(benches, ice_mpm_step);

/// `ICE_MPM_PROFILE=case:n`: n steps of one case (see the module doc).
fn profile(spec: &str) {
    let (case, n) = spec.split_once(':').unwrap_or((spec, "1"));
    let n: usize = n.parse().expect("ICE_MPM_PROFILE=case:n, n a count");
    let dt = coupled().stable_dt().expect("dt");
    match case {
        "coupled" => {
            let mut s = coupled();
            for _ in 0..n {
                s.advance(dt).expect("coupled step");
            }
            // The state's bits, to check that a change left them alone.
            let bytes = s.save_state().expect("state");
            let hash = bytes.iter().fold(0xcbf2_9ce4_8422_2325u64, |h, &b| {
                (h ^ b as u64).wrapping_mul(0x0100_0000_01b3)
            });
            println!("coupled after {n} steps: state hash {hash:016x}");
        }
        "ice" => {
            let mut s = build_frames(&setup()).0;
            for _ in 0..n {
                s.advance(dt).expect("ice step");
            }
        }
        "mpm" => {
            let mut s = build_frames(&setup()).1;
            for _ in 0..n {
                s.advance(dt).expect("mpm step");
            }
        }
        _ => panic!("ICE_MPM_PROFILE: case {case} is not coupled, ice or mpm"),
    }
}

fn main() {
    if let Ok(spec) = std::env::var("ICE_MPM_PROFILE") {
        profile(&spec);
        return;
    }
    if let Some(steps) = std::env::var("ICE_MPM_STEPS")
        .ok()
        .and_then(|s| s.parse::<usize>().ok())
    {
        let mut s = coupled();
        let start = std::time::Instant::now();
        for _ in 0..steps {
            let dt = s.stable_dt().expect("dt");
            s.advance(dt).expect("coupled step");
        }
        let wall = start.elapsed().as_secs_f64();
        println!(
            "{steps} coupled steps: {:.3e} cell-updates/s, {:.3e} particle-steps/s",
            (steps * N * N * N) as f64 / wall,
            (steps * s.particles_per_step()) as f64 / wall
        );
        return;
    }
    benches();
    Criterion::default().configure_from_args().final_summary();
}
