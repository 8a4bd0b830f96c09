//! Criterion benchmarks, one group per kernel, each reporting throughput in
//! the kernel's unit.

use brisance::core::{Eos, Solver};
use brisance::eos::{
    EosModel, IdealGas, Jwl, JwlCTerm, MieGruneisenCubic, MieGruneisenLinear, Murnaghan, SolidEos,
    SolidThreshold,
};
use brisance::verification::cases::blast_box;
use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use std::hint::black_box;

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

/// Pressure evaluations per second for every equation of state, through the
/// registry enum (as the solvers see them) on 1024 states around each
/// model's reference density.
fn eos_pressure(c: &mut Criterion) {
    let models: Vec<(&str, EosModel, f64)> = vec![
        ("ideal_gas", EosModel::IdealGas(IdealGas::air()), 2.0e5),
        ("jwl", EosModel::Jwl(Jwl::tnt()), 4.0e6),
        ("jwl_cterm", EosModel::JwlCTerm(JwlCTerm::anfo_k1()), 3.0e6),
        ("murnaghan", EosModel::Murnaghan(Murnaghan::anfo_k1()), 0.0),
        (
            "mie_gruneisen_cubic",
            EosModel::MieGruneisenCubic(MieGruneisenCubic::steel_seed001()),
            1.0e4,
        ),
        (
            "mie_gruneisen_linear",
            EosModel::MieGruneisenLinear(MieGruneisenLinear::steel_4340()),
            1.0e4,
        ),
        (
            "solid_threshold",
            EosModel::SolidThreshold(SolidThreshold::new(SolidEos::MieGruneisenLinear(
                MieGruneisenLinear::steel_4340(),
            ))),
            1.0e4,
        ),
    ];
    let n = 1024;
    let mut group = c.benchmark_group("eos_pressure");
    group.throughput(Throughput::Elements(n as u64));
    for (name, eos, e) in &models {
        let rho0 = eos.reference_density();
        let states: Vec<(f64, f64)> = (0..n)
            .map(|k| (rho0 * (0.9 + 0.2 * k as f64 / n as f64), *e))
            .collect();
        group.bench_with_input(BenchmarkId::from_parameter(name), &states, |b, states| {
            b.iter(|| {
                states
                    .iter()
                    .map(|&(rho, e)| eos.pressure(black_box(rho), black_box(e)))
                    .sum::<f64>()
            })
        });
    }
    group.finish();
}

/// One explicit MPM step (MUSL) of a 3D elastic-plastic copper block with
/// 2 x 2 x 2 particles per cell: particle-steps per second, for linear and
/// quadratic B-spline shape functions.
fn mpm_step(c: &mut Criterion) {
    use brisance::compose::{build::build_solver, load_str};
    let text = include_str!("../configs/taylor2d.ron");
    let mut group = c.benchmark_group("mpm_step");
    group.sample_size(10);
    for shape in ["Linear", "QuadraticBSpline"] {
        let sets = [
            "domain.cells=(16,32,16)".to_string(),
            "domain.upper=(0.008,0.016,0.008)".to_string(),
            "initial.0.region.max=(0.004,0.012,0.004)".to_string(),
            "boundaries.z_low=Reflective".to_string(),
            "outputs.gauges=[]".to_string(),
            format!("pipeline.shape_function={shape}"),
        ];
        let loaded = load_str("taylor2d.ron", text, &sets).expect("benchmark scenario loads");
        let mut solver = build_solver(&loaded.scenario).expect("benchmark scenario builds");
        group.throughput(Throughput::Elements(solver.work_per_step().0 as u64));
        group.bench_function(BenchmarkId::from_parameter(shape), |b| {
            b.iter(|| {
                let dt = solver.stable_dt().expect("stable");
                solver.advance(dt).expect("advances");
            })
        });
    }
    group.finish();
}

criterion_group!(benches, fdm_lax_wendroff, eos_pressure, mpm_step);
criterion_main!(benches);
