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
/// the CFL reduction) on a 3D 64³ box: cell-updates per second, with the
/// face limiter `full` (the default), `positivity` only and `off` side by
/// side (docs/physics/fdm.md, "Face limiter").
fn fdm_lax_wendroff(c: &mut Criterion) {
    use brisance::fdm::FaceLimiter;
    let n = 64;
    let mut group = c.benchmark_group("fdm_lax_wendroff");
    group.throughput(Throughput::Elements((n * n * n) as u64));
    group.sample_size(20);
    for (name, limiter) in [
        ("step_64cubed", FaceLimiter::Full),
        ("step_64cubed_limiter_positivity", FaceLimiter::Positivity),
        ("step_64cubed_limiter_off", FaceLimiter::Off),
    ] {
        let mut solver = blast_box(n, [1, 1, 1]).expect("benchmark problem builds");
        solver.set_limiter(limiter);
        group.bench_function(name, |b| {
            b.iter(|| {
                let dt = solver.stable_dt().expect("stable");
                solver.advance(dt).expect("advances");
            })
        });
    }
    group.finish();
}

/// One FDM step on a 512² plane, planar (x, y) and axisymmetric (r, z)
/// side by side (the same blast on the axis): the cost of the ring
/// weights and the hoop source per cell-update
/// (docs/physics/axisymmetric.md, "Cost").
fn fdm_plane(c: &mut Criterion) {
    use brisance::verification::cases::blast_plane;
    let n = 512;
    let mut group = c.benchmark_group("fdm_plane");
    group.throughput(Throughput::Elements((n * n) as u64));
    group.sample_size(20);
    for (name, axisymmetric) in [("step_512sq_planar", false), ("step_512sq_rz", true)] {
        let mut solver = blast_plane(n, axisymmetric).expect("benchmark problem builds");
        group.bench_function(name, |b| {
            b.iter(|| {
                let dt = solver.stable_dt().expect("stable");
                solver.advance(dt).expect("advances");
            })
        });
    }
    group.finish();
}

/// The FDM's two-species gas law (TNT products in air, pressure
/// equilibrium, docs/physics/fdm_mixture.md) as the bridge's kernels call
/// it, through the registry enum: (p, c) and p alone, per second, on 1024
/// states from the dense products (1630 kg/m³) to ambient air (1 kg/m³),
/// log-spaced, with products fractions spread over [0, 1].
fn fdm_mixture(c: &mut Criterion) {
    use brisance::fdm::{GasLaw, ProductsInAir};
    let gas = ProductsInAir::new(
        EosModel::Jwl(Jwl::tnt()),
        EosModel::IdealGas(IdealGas::air()),
    )
    .expect("mixture builds");
    let n = 1024;
    let states: Vec<(f64, f64, f64)> = (0..n)
        .map(|k| {
            let s = k as f64 / (n - 1) as f64;
            let rho = 1630f64.powf(1.0 - s);
            let y = ((k * 37) % n) as f64 / (n - 1) as f64;
            (rho, 5.0e5 + 4.0e6 * (1.0 - s), y)
        })
        .collect();
    let mut group = c.benchmark_group("fdm_mixture");
    group.throughput(Throughput::Elements(n as u64));
    group.bench_function("pressure_and_sound_speed", |b| {
        b.iter(|| {
            states
                .iter()
                .map(|&(rho, e, y)| {
                    let inv = 1.0 / black_box(rho);
                    let (p, c) = gas.gas_pressure_and_sound_speed_inv(rho, inv, e, y);
                    p + c
                })
                .sum::<f64>()
        })
    });
    group.bench_function("pressure", |b| {
        b.iter(|| {
            states
                .iter()
                .map(|&(rho, e, y)| gas.gas_pressure_inv(rho, 1.0 / black_box(rho), e, y))
                .sum::<f64>()
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

/// The copper of the E-CYLINDER ICE–MPM run (configs/cylinder_icempm.ron):
/// Mie–Grüneisen on the linear Uₛ–uₚ Hugoniot under the one-atmosphere
/// solid threshold, through the registry enum as the ICE solver sees it.
fn cylinder_copper() -> EosModel {
    EosModel::SolidThreshold(SolidThreshold::new(SolidEos::MieGruneisenLinear(
        MieGruneisenLinear {
            c0: 3619.7,
            s: 1.489,
            gamma0: 2.02,
            rho0: 8930.0,
            cv: 383.0,
            t0: 300.0,
        },
    )))
}

/// ρ(p, T) inversions per second of the E-CYLINDER copper: `density` alone,
/// the three calls the ICE equilibration makes at one (p, T) (`density`,
/// `isothermal_compressibility`, `thermal_expansivity`), and the fused
/// `density_and_derivatives` that answers all three from one inversion.
/// Two sets of 1024 states: `ambient` cycles the eight (p, T) pairs that
/// make up 65 % of the run's copper solves (1 atm and T within round-off
/// of 300 K, sampled from a 2 µs run), `spread` covers 1 kPa to 10 GPa
/// (log-spaced, below and above the threshold) at 300 to 1500 K.
fn eos_density_inversion(c: &mut Criterion) {
    let copper = cylinder_copper();
    let n = 1024;
    let hot = [
        (101_325.0, 299.999_999_999_988_9),
        (101_338.600_180_481_56, 299.999_999_999_988_9),
        (101_324.999_998_941_48, 299.999_999_999_988_9),
        (101_324.999_996_751_62, 299.999_999_999_988_9),
        (101_338.304_379_088_66, 300.0),
        (101_325.000_001_605_24, 299.999_999_999_988_9),
        (101_338.436_150_204_72, 300.0),
        (101_338.418_287_095_57, 299.999_999_999_988_9),
    ];
    let ambient: Vec<(f64, f64)> = (0..n).map(|k| hot[k % hot.len()]).collect();
    let spread: Vec<(f64, f64)> = (0..n)
        .map(|k| {
            let f = k as f64 / n as f64;
            let g = ((k * 37) % n) as f64 / n as f64;
            (10f64.powf(3.0 + 7.0 * f), 300.0 + 1200.0 * g)
        })
        .collect();
    let mut group = c.benchmark_group("eos_density_inversion");
    group.throughput(Throughput::Elements(n as u64));
    for (set, states) in [("ambient", &ambient), ("spread", &spread)] {
        group.bench_with_input(BenchmarkId::new("density", set), states, |b, states| {
            b.iter(|| {
                states
                    .iter()
                    .map(|&(p, t)| copper.density(black_box(p), black_box(t)).unwrap_or(0.0))
                    .sum::<f64>()
            })
        });
        group.bench_with_input(BenchmarkId::new("three_calls", set), states, |b, states| {
            b.iter(|| {
                states
                    .iter()
                    .map(|&(p, t)| {
                        let (p, t) = (black_box(p), black_box(t));
                        copper.density(p, t).unwrap_or(0.0)
                            + copper.isothermal_compressibility(p, t).unwrap_or(0.0)
                            + copper.thermal_expansivity(p, t).unwrap_or(0.0)
                    })
                    .sum::<f64>()
            })
        });
        group.bench_with_input(BenchmarkId::new("fused", set), states, |b, states| {
            b.iter(|| {
                states
                    .iter()
                    .map(|&(p, t)| {
                        copper
                            .density_and_derivatives(black_box(p), black_box(t))
                            .map_or(0.0, |(rho, kappa, alpha)| rho + kappa + alpha)
                    })
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

/// The 3D elastic-plastic copper block of the MPM benchmarks (`mpm_step`'s
/// problem: 16 x 32 x 16 cells of 0.5 mm, a 4 x 12 x 4 mm block of
/// 2 x 2 x 2 particles per cell hitting a rigid wall at 190 m/s), after
/// `steps` steps of the full solver, so the kernels see a deforming,
/// partly plastic state.
fn mpm_bench_block(shape: &str, steps: usize) -> brisance::mpm::MpmSolver {
    use brisance::compose::{build::build_section, load_str};
    let text = include_str!("../configs/taylor2d.ron");
    let sets = [
        "domain.cells=(16,32,16)".to_string(),
        "domain.upper=(0.008,0.016,0.008)".to_string(),
        "initial.0.region.max=(0.004,0.012,0.004)".to_string(),
        "boundaries.z_low=Reflective".to_string(),
        "outputs.gauges=[]".to_string(),
        format!("pipeline.shape_function={shape}"),
    ];
    let loaded = load_str("taylor2d.ron", text, &sets).expect("benchmark scenario loads");
    let section = loaded
        .scenario
        .pipeline
        .section::<brisance::couple::MpmConfig>();
    let section = section.expect("the benchmark scenario is an Mpm pipeline");
    let mut solver = build_section(section, &loaded.scenario).expect("benchmark scenario builds");
    for _ in 0..steps {
        let dt = solver.stable_dt().expect("stable");
        solver.advance(dt).expect("advances");
    }
    solver
}

/// The transfer kernels' inputs for one state of [`mpm_bench_block`].
struct MpmKernelState {
    particles: brisance::mpm::Particles,
    map: brisance::mpm::transfer::GridMap,
    bins: brisance::mpm::transfer::ParticleBins,
    nodes: brisance::mpm::GridNodes,
    options: brisance::mpm::MpmOptions,
    grid: brisance::core::UniformGridGeometry,
}

impl MpmKernelState {
    fn new(shape: &str) -> Self {
        use brisance::mpm::transfer::{GridMap, ParticleBins};
        let solver = mpm_bench_block(shape, 40);
        let particles = solver.particles().clone();
        let grid = solver.level().geometry;
        let options = *solver.options();
        let map = GridMap::new(&grid, options.shape);
        let mut bins = ParticleBins::default();
        bins.build(&map, &particles.position, &particles.initial_volume)
            .expect("benchmark particles bin");
        let nodes = brisance::mpm::GridNodes::new(map.lattice);
        Self {
            particles,
            map,
            bins,
            nodes,
            options,
            grid,
        }
    }

    /// P2G of mass, momentum and internal force (seed 001 eqs 18, 19, 21)
    /// and the node update to v_I^n, a_I and v_I^{n+1} (eq 22), as a USL or
    /// MUSL step makes it.
    fn p2g(&mut self, dt: f64) {
        use brisance::mpm::grid_nodes::{NodeStage, NodeUpdate};
        use brisance::mpm::transfer::{p2g, P2gParticles, P2gSums};
        let ps = &self.particles;
        p2g(
            &self.map,
            &self.bins,
            P2gParticles {
                position: &ps.position,
                mass: &ps.mass,
                velocity: &ps.velocity,
                volume: &ps.volume,
                stress: &ps.stress,
            },
            &mut self.nodes,
            P2gSums::All,
        );
        let reference_mass = ps.total_mass() / ps.len() as f64;
        self.nodes.update(
            &NodeUpdate {
                boundaries: &self.options.boundaries,
                cells: self.grid.cells,
                mass_threshold: self.options.mass_cutoff * reference_mass,
                radial: None,
                light_nodes_move: false,
                gravity: self.options.gravity,
                dt,
            },
            NodeStage::VelocityAndIntegrate,
        );
    }
}

/// The MPM kernels one at a time, on [`mpm_bench_block`] after 40 steps
/// (12 288 particles), particle-steps per second: `mpm_p2g` (mass, momentum
/// and internal force to the grid and the node update), `mpm_g2p` (velocity
/// and position update and velocity gradient from the grid, eqs 24, 25,
/// 27–28; Δt = 0 so the particles stay where they were binned) and
/// `mpm_stress_update` (F, volume, J2 radial return with the Jaumann rate
/// and energy of every particle, from the velocity gradient of that state;
/// each iteration starts from the same state).
fn mpm_kernels(c: &mut Criterion) {
    use brisance::mpm::step::{update_stresses, StepParams};
    use brisance::mpm::transfer::{g2p, G2p, G2pParticles};
    use brisance::mpm::BulkViscosityState;
    use criterion::BatchSize;
    for shape in ["Linear", "QuadraticBSpline"] {
        let mut k = MpmKernelState::new(shape);
        let n = k.particles.len() as u64;
        let dt = 1e-9;
        let mut group = c.benchmark_group("mpm_p2g");
        group.sample_size(10);
        group.throughput(Throughput::Elements(n));
        group.bench_function(BenchmarkId::from_parameter(shape), |b| b.iter(|| k.p2g(dt)));
        group.finish();

        k.p2g(dt);
        let mut gradient = Vec::new();
        let mut group = c.benchmark_group("mpm_g2p");
        group.sample_size(10);
        group.throughput(Throughput::Elements(n));
        group.bench_function(BenchmarkId::from_parameter(shape), |b| {
            b.iter(|| {
                let nodes = &k.nodes;
                g2p(
                    &k.map,
                    &k.bins,
                    G2p {
                        acceleration: &nodes.acceleration,
                        velocity_new: &nodes.velocity_new,
                        gradient_velocity: &nodes.velocity_new,
                        dt: 0.0,
                        update_velocity: true,
                        update_position: true,
                        velocity_gradient: true,
                    },
                    G2pParticles {
                        position: &mut k.particles.position,
                        velocity: &mut k.particles.velocity,
                        gradient: &mut gradient,
                    },
                )
            })
        });
        group.finish();

        if shape != "Linear" {
            continue;
        }
        // The stress update does not depend on the shape function.
        let solver = mpm_bench_block(shape, 40);
        let params = StepParams {
            grid: &k.grid,
            shape: k.options.shape,
            scheme: k.options.scheme,
            gravity: k.options.gravity,
            boundaries: &k.options.boundaries,
            mass_threshold: 0.0,
            radial_cutoff: None,
            light_nodes_move: false,
            materials: solver.materials(),
            dt: 0.2 * solver.stable_dt().expect("stable"),
            bulk_viscosity: None,
            surface_forces: &[],
            reservoir: &[],
            own: None,
        };
        let mut group = c.benchmark_group("mpm_stress_update");
        group.sample_size(10);
        group.throughput(Throughput::Elements(n));
        group.bench_function("elastic_plastic_jaumann", |b| {
            b.iter_batched_ref(
                || {
                    (
                        k.particles.clone(),
                        vec![BulkViscosityState::default(); n as usize],
                    )
                },
                |(ps, bulk)| {
                    let failure = update_stresses(ps, &gradient, bulk, &params);
                    assert!(failure.is_none(), "{failure:?}");
                },
                BatchSize::LargeInput,
            )
        });
        group.finish();
    }
}

/// One explicit heat-conduction step inside the MPM solid
/// (`brisance::mpm::conduction::conduct`: capacity scatter, flux
/// gather–scatter, temperature gather) on [`mpm_bench_block`] after 40
/// steps (12 288 particles, linear shape functions) with a temperature
/// field of 950–1150 K, particle-steps per second: `constant` with the
/// steel's c_v = 477 J/(kg·K), `curie` with the 4340 steel's c_v(T)
/// through its Curie point (the capacity takes c_v(T_p), the update the
/// rise through H(T)). Each iteration starts from the same temperatures.
fn mpm_conduction(c: &mut Criterion) {
    use brisance::constitutive::SpecificHeat;
    use brisance::mpm::conduction::{conduct, HeatWork};
    use brisance::mpm::ThermalProperties;
    let mut k = MpmKernelState::new("Linear");
    let n = k.particles.len();
    for (p, t) in k.particles.temperature.iter_mut().enumerate() {
        *t = 950.0 + 2.0 * ((p * 37) % 101) as f64;
    }
    let start = k.particles.temperature.clone();
    let mut group = c.benchmark_group("mpm_conduction");
    group.sample_size(20);
    group.throughput(Throughput::Elements(n as u64));
    for (name, heat) in [
        ("constant", SpecificHeat::Constant(477.0)),
        ("curie", SpecificHeat::steel_4340()),
    ] {
        let properties = [ThermalProperties {
            conductivity: 44.5,
            specific_heat: heat,
        }];
        let mut work = HeatWork::default();
        group.bench_function(name, |b| {
            b.iter(|| {
                k.particles.temperature.copy_from_slice(&start);
                conduct(
                    &k.map,
                    &k.bins,
                    &mut k.particles,
                    &properties,
                    &mut work,
                    1e-6,
                );
            })
        });
    }
    group.finish();
}

/// The peridynamic bond-force pass (seed 004 eq 9 with the proportional
/// micro-elastic bond of eq 8) on a 3D block of 28³ nodes with δ = 3h:
/// bond evaluations per second, one evaluation being the force of one bond
/// on one of its two nodes (178 per interior node with the partial-volume
/// cutoff δ + h/2, 154.6 per node on average: 3 392 752 in all). Kernel
/// layout, memory and measured figures: `docs/physics/pd/kernel.md`.
fn pd_bond_forces(c: &mut Criterion) {
    use brisance::pd::{bond_forces, cases::BondBenchBlock, NodeForce};
    let mut block = BondBenchBlock::new(28, 1.0e-3);
    let mut factor = std::mem::take(&mut block.factor);
    let mut plastic = vec![0f32; factor.len()];
    let mut out = vec![NodeForce::default(); block.reference.len()];
    let input = block.input();
    let mut group = c.benchmark_group("pd_bond_forces");
    group.throughput(Throughput::Elements(block.families.bond_count() as u64));
    group.sample_size(20);
    group.bench_function("micro_elastic_block_28cubed", |b| {
        b.iter(|| bond_forces(&input, &mut factor, &mut plastic, &mut out))
    });
    group.finish();
}

/// The peridynamic short-range (contact) pass of seed 004 eq 27 as a run
/// steps it: the current positions binned into the cell list, then each
/// node's contact force over the candidates of the 27 cells around it
/// (`brisance_pd::contact`). The 28³ block of `pd_bond_forces`, split at
/// mid-x into two bodies: a breakable solid (K = 1.4e11 Pa, same-body
/// pairs skipped where their bond is intact, which takes a family lookup)
/// and an explosive with a contact modulus (K = 9e9 Pa, every pair within
/// reach, as TNT with its reactant in E-PD-CYL), so the three kinds of
/// pair of a cased charge are all there. Nodes per second; in the full
/// E-PD-CYL tube this pass takes about half of a one-thread step
/// (docs/physics/pd/kernel.md).
fn pd_contact_forces(c: &mut Criterion) {
    use brisance::pd::cases::BondBenchBlock;
    use brisance::pd::cell_list::CellList;
    use brisance::pd::contact::{
        bin_current_positions, contact_forces, ContactInput, ContactParams, ContactParts,
    };
    let h = 1.0e-3;
    let block = BondBenchBlock::new(28, h);
    let n = block.reference.len();
    let half = 14.0 * h;
    let body: Vec<u32> = block
        .reference
        .iter()
        .map(|x| u32::from(x[0] >= half))
        .collect();
    let material: Vec<u16> = body.iter().map(|&b| b as u16).collect();
    let params = ContactParams {
        force_factor: 15.0,
        contact_distance: 1.35 * h,
        reference_fraction: 0.9,
        horizon: 3.0 * h,
    };
    let input = ContactInput::new(ContactParts {
        reference: &block.reference,
        state: &block.state,
        body: &body,
        material: &material,
        bulk_modulus: &[1.4e11, 9.0e9],
        breakable: &[true, false],
        families: &block.families,
        factor: &block.factor,
        family_cutoff: 3.5 * h,
    })
    .expect("the bench block's arrays agree");
    let mut cells = CellList::default();
    let mut out = vec![([0.0; 3], 0.0); n];
    let mut group = c.benchmark_group("pd_contact_forces");
    group.throughput(Throughput::Elements(n as u64));
    group.sample_size(20);
    group.bench_function("solid_and_explosive_block_28cubed", |b| {
        b.iter(|| {
            bin_current_positions(&mut cells, &input, &params);
            contact_forces(&input, &cells, &params, &mut out).expect("arrays agree");
            black_box(&out);
        })
    });
    group.finish();
}

criterion_group!(
    benches,
    fdm_lax_wendroff,
    fdm_plane,
    fdm_mixture,
    eos_pressure,
    eos_density_inversion,
    mpm_step,
    mpm_kernels,
    mpm_conduction,
    pd_bond_forces,
    pd_contact_forces
);
criterion_main!(benches);
