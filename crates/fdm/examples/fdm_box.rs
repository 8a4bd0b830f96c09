//! A small 3D blast box for instruction-count comparisons
//! (`valgrind --tool=callgrind`) and bit fingerprints: prints the step
//! count, the totals, a hash of every output field after `steps` steps,
//! the wall time of the steps and the throughput.
//!
//! `cargo run --release -p brisance-fdm --example fdm_box -- [n] [steps] [full|positivity|off] [products]`
//! (the face limiter, `full` by default; `products`: a sphere of TNT
//! products in air, the two-species gas law, instead of one ideal gas).

use brisance_core::Solver;
use brisance_eos::{IdealGas, Jwl};
use brisance_fdm::{
    FaceLimiter, FdmBoundary, FdmOptions, FdmSolver, GasLaw, PrimitiveState, ProductsInAir,
};
use brisance_grid::Level;

fn main() {
    let limiter = match std::env::args().nth(3).as_deref() {
        Some("off") => FaceLimiter::Off,
        Some("positivity") => FaceLimiter::Positivity,
        _ => FaceLimiter::Full,
    };
    let args: Vec<usize> = std::env::args()
        .skip(1)
        .take(2)
        .map(|a| a.parse().expect("integer argument"))
        .collect();
    let n = args.first().copied().unwrap_or(24);
    let steps = args.get(1).copied().unwrap_or(10);
    let level =
        Level::new([0.0; 3], [1.0; 3], [n; 3], [1, 1, 1], brisance_fdm::GHOST).expect("level");
    let options = FdmOptions {
        limiter,
        ..Default::default()
    };
    // A sphere of radius 0.2 off the centre of the unit box.
    let inside =
        |x: [f64; 3]| (x[0] - 0.5).powi(2) + (x[1] - 0.45).powi(2) + (x[2] - 0.55).powi(2) < 0.04;
    let state = |density, pressure| PrimitiveState {
        density,
        velocity: [0.0; 3],
        pressure,
    };
    if std::env::args().nth(4).as_deref() == Some("products") {
        // TNT products (JWL, 20 kg/m³, 200 bar) in air: the two-species
        // gas law.
        let gas = ProductsInAir::new(Jwl::tnt(), IdealGas::air()).expect("gas");
        let solver =
            FdmSolver::with_species(gas, level, [FdmBoundary::Reflective; 6], options, |x| {
                if inside(x) {
                    (state(20.0, 2.0e7), 1.0)
                } else {
                    (state(1.2, 1.0e5), 0.0)
                }
            })
            .expect("solver");
        return run(solver, n, steps);
    }
    let solver = FdmSolver::new(
        IdealGas::air(),
        level,
        [FdmBoundary::Reflective; 6],
        options,
        |x| {
            if inside(x) {
                state(5.0, 1.0e6)
            } else {
                state(1.2, 1.0e5)
            }
        },
    )
    .expect("solver");
    run(solver, n, steps);
}

/// Takes `steps` steps of the n³ box and prints the counts, totals, the
/// hash of every output field, the wall time and the throughput.
fn run<E: GasLaw>(mut solver: FdmSolver<E>, n: usize, steps: usize) {
    let t0 = std::time::Instant::now();
    for _ in 0..steps {
        let dt = solver.stable_dt().expect("dt");
        solver.advance(dt).expect("step");
    }
    let wall = t0.elapsed().as_secs_f64();
    let mut hash: u64 = 0xcbf2_9ce4_8422_2325;
    let names: Vec<String> = solver
        .cell_field_names()
        .iter()
        .map(|s| s.to_string())
        .collect();
    let data = solver.cell_data(&names).expect("fields");
    for (_, values) in &data.fields {
        for v in values {
            hash = (hash ^ v.to_bits()).wrapping_mul(0x100_0000_01b3);
        }
    }
    let t = solver.conservation_totals();
    println!(
        "steps {} time {:e} mass {:e} energy {:e} fields-hash {hash:016x} wall {wall:.3} s ({:.3e} cell-updates/s)",
        solver.steps(),
        solver.time(),
        t.mass,
        t.energy,
        (n * n * n * steps) as f64 / wall
    );
}
