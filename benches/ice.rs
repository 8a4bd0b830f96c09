//! Criterion benchmarks of the multi-material ICE solver (seed 000 §3.3):
//! - `ice_step`: one full step (steps 2–12) of three materials (ANFO-K1
//!   Murnaghan reactant, its JWL C-term products, air) on a 64³ box with a
//!   2 GPa products sphere in air beside a slab of reactant; throughput in
//!   cell-updates per second (64³ per step; target of issue 7 ≥ 1e6).
//! - `ice_equilibration`: the equilibration pressure (eq 7) of 64³
//!   three-material cells alone, serial; throughput in cells per second.
//!
//! `ICE_STEPS=n` runs n steps of the `ice_step` box and exits instead of
//! benchmarking (for `valgrind --tool=callgrind` instruction counts).

use brisance::core::{Eos, Solver};
use brisance::eos::{EosModel, IdealGas, JwlCTerm, Murnaghan};
use brisance::grid::Level;
use brisance::ice::{
    equilibration_pressure, CellState, EquilibrationSettings, ExchangeCoefficients, IceBoundary,
    IceOptions, IceSolver, MaterialState, GHOST,
};
use criterion::{criterion_group, BenchmarkId, Criterion, Throughput};

const N: usize = 64;
const P0: f64 = 1.0e5;
const T0: f64 = 298.15;
const P_SPHERE: f64 = 2.0e9;
const T_SPHERE: f64 = 3000.0;

fn materials() -> Vec<EosModel> {
    vec![
        EosModel::Murnaghan(Murnaghan::anfo_k1()),
        EosModel::JwlCTerm(JwlCTerm::anfo_k1()),
        EosModel::IdealGas(IdealGas::air()),
    ]
}

/// Which material fills the point `x` of the unit box, at what pressure
/// and temperature.
fn region(x: [f64; 3]) -> (usize, f64, f64) {
    let r2: f64 = x.iter().map(|c| (c - 0.5) * (c - 0.5)).sum();
    if r2 < 0.2 * 0.2 {
        (1, P_SPHERE, T_SPHERE)
    } else if x[0] < 0.2 {
        (0, P0, T0)
    } else {
        (2, P0, T0)
    }
}

/// The 64³ box, 1 m on a side, outflow on every face.
fn ice_box(n: usize) -> IceSolver<EosModel> {
    let eos = materials();
    let level = Level::new([0.0; 3], [1.0; 3], [n; 3], [1, 1, 1], GHOST).expect("level");
    let trace = 1e-6;
    IceSolver::new(
        eos.clone(),
        level,
        std::array::from_fn(|_| IceBoundary::Outflow),
        ExchangeCoefficients::uniform(3, 1e15, 0.0),
        IceOptions::default(),
        |x| {
            let (main, p, t) = region(x);
            CellState {
                pressure: p,
                materials: (0..3)
                    .map(|k| {
                        let tk = if k == 1 { t.max(T0) } else { T0 };
                        MaterialState {
                            volume_fraction: if k == main { 1.0 - 2.0 * trace } else { trace },
                            density: eos[k].density(p, tk).expect("density at the initial state"),
                            velocity: [0.0; 3],
                        }
                    })
                    .collect(),
            }
        },
    )
    .expect("benchmark box builds")
}

fn ice_step(c: &mut Criterion) {
    let mut group = c.benchmark_group("ice_step");
    group.throughput(Throughput::Elements((N * N * N) as u64));
    group.sample_size(10);
    let mut s = ice_box(N);
    let dt = s.stable_dt().expect("stable dt");
    group.bench_function("three_materials_64cubed", |b| {
        b.iter(|| s.advance(dt).expect("ice step"))
    });
    group.finish();
}

/// Per cell: averaged densities and temperatures of the three materials,
/// from the box's initial state perturbed cell by cell so that the
/// iteration starts away from the answer.
fn equilibration_cells(n: usize) -> Vec<([f64; 3], [f64; 3], f64)> {
    let eos = materials();
    (0..n * n * n)
        .map(|i| {
            let x = [
                ((i % n) as f64 + 0.5) / n as f64,
                ((i / n % n) as f64 + 0.5) / n as f64,
                ((i / (n * n)) as f64 + 0.5) / n as f64,
            ];
            let (main, p, t) = region(x);
            let w = 0.5 + (i % 7) as f64 / 7.0;
            let mut rho = [0.0; 3];
            let mut temp = [0.0; 3];
            for k in 0..3 {
                let tk = if k == 1 { t.max(T0) } else { T0 };
                let th = if k == main { 0.6 } else { 0.2 };
                rho[k] = th * eos[k].density(p, tk).expect("density");
                temp[k] = tk * w;
            }
            (rho, temp, p)
        })
        .collect()
}

fn ice_equilibration(c: &mut Criterion) {
    let eos = materials();
    let cells = equilibration_cells(N);
    let settings = EquilibrationSettings::default();
    let mut group = c.benchmark_group("ice_equilibration");
    group.throughput(Throughput::Elements(cells.len() as u64));
    group.sample_size(10);
    group.bench_function(BenchmarkId::new("three_materials", cells.len()), |b| {
        b.iter(|| {
            let (mut vsp, mut theta) = ([0.0; 3], [0.0; 3]);
            let mut sum = 0.0;
            for (rho, temp, guess) in &cells {
                let (p, _) = equilibration_pressure(
                    &eos, rho, temp, *guess, &settings, &mut vsp, &mut theta,
                )
                .expect("equilibration");
                sum += p;
            }
            sum
        })
    });
    group.finish();
}

criterion_group!(benches, ice_step, ice_equilibration);

fn main() {
    if let Some(steps) = std::env::var("ICE_STEPS")
        .ok()
        .and_then(|s| s.parse::<usize>().ok())
    {
        let n = std::env::var("ICE_N")
            .ok()
            .and_then(|s| s.parse().ok())
            .unwrap_or(N);
        let mut s = ice_box(n);
        let start = std::time::Instant::now();
        for _ in 0..steps {
            let dt = s.stable_dt().expect("stable dt");
            s.advance(dt).expect("ice step");
        }
        let wall = start.elapsed().as_secs_f64();
        let st = s.equilibration_stats();
        println!(
            "{steps} steps of {n}³, t = {:.6e} s, {:.3e} cell-updates/s, equilibration max {} iterations, mean {:.2}",
            s.time(),
            (steps * n * n * n) as f64 / wall,
            st.max_iterations,
            st.total_iterations as f64 / (n * n * n) as f64
        );
        // The state's totals to the last bit, to compare builds.
        let tot = s.conservation_totals();
        println!(
            "totals: mass {:e}, momentum {:e} {:e} {:e}, energy {:e}",
            tot.mass, tot.momentum[0], tot.momentum[1], tot.momentum[2], tot.energy
        );
        return;
    }
    benches();
    Criterion::default().configure_from_args().final_summary();
}
