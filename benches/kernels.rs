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

/// The peridynamic bond-force pass (seed 004 eq 9 with the proportional
/// micro-elastic bond of eq 8) on a 3D block of 28³ nodes with δ = 3h:
/// bond evaluations per second, one evaluation being the force of one bond
/// on one of its two nodes (178 per interior node with the partial-volume
/// cutoff δ + h/2).
fn pd_bond_forces(c: &mut Criterion) {
    use brisance::grid::Shape;
    use brisance::pd::{
        bond_forces, build_families, fill_lattice, partial_volume, spring_constant, BodySpec,
        BondLaw, Dimension, ForceInput, LatticeSpec, NodeForce,
    };
    let (n, h) = (28usize, 1.0e-3);
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
    .expect("benchmark block fills");
    let horizon = 3.0 * h;
    let families = build_families(&cloud.positions, &cloud.body, horizon, h);
    let reference: Vec<[f64; 4]> = cloud
        .positions
        .iter()
        .zip(&cloud.volumes)
        .map(|(x, v)| [x[0], x[1], x[2], *v])
        .collect();
    // A smooth small strain field, so every bond is stretched.
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
    let mut factor: Vec<f32> = (0..cloud.positions.len())
        .flat_map(|i| {
            let row = families.row(i);
            let p = &cloud.positions;
            families.neighbours[row]
                .iter()
                .map(move |&j| {
                    let d: f64 = (0..3).map(|k| (p[j as usize][k] - p[i][k]).powi(2)).sum();
                    partial_volume(d.sqrt(), horizon, h) as f32
                })
                .collect::<Vec<_>>()
        })
        .collect();
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
    let mut group = c.benchmark_group("pd_bond_forces");
    group.throughput(Throughput::Elements(families.bond_count() as u64));
    group.sample_size(20);
    group.bench_function("micro_elastic_block_28cubed", |b| {
        b.iter(|| bond_forces(&input, &mut factor, &mut plastic, &mut out))
    });
    group.finish();
}

criterion_group!(
    benches,
    fdm_lax_wendroff,
    eos_pressure,
    mpm_step,
    pd_bond_forces
);
criterion_main!(benches);
