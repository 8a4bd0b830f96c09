//! The cost of an axisymmetric (r, z) cell-update against a planar 2D one:
//! the same blast (a sphere of compressed air on the axis x = 0, walls
//! all round) on an n × n grid read as a planar (x, y) slab and as an
//! (r, z) plane, stepped in turns so both see the same machine state.
//! Prints each one's cell-updates per second and their ratio.
//!
//! `cargo run --release -p brisance-fdm --example fdm_plane -- [n] [steps] [rounds]`

use std::time::Instant;

use brisance_core::{Geometry, Solver};
use brisance_eos::IdealGas;
use brisance_fdm::{FdmBoundary, FdmOptions, FdmSolver, PrimitiveState};
use brisance_grid::Level;

fn solver(n: usize, geometry: Geometry) -> FdmSolver<IdealGas> {
    let ghost = brisance_fdm::ghost_layers(geometry);
    let level = Level::new([0.0; 3], [1.0, 1.0, 0.01], [n, n, 1], [1, 1, 1], ghost).expect("level");
    let options = FdmOptions {
        geometry,
        ..Default::default()
    };
    FdmSolver::new(
        IdealGas::air(),
        level,
        [FdmBoundary::Reflective; 6],
        options,
        |x| {
            let inside = x[0] * x[0] + (x[1] - 0.5).powi(2) < 0.04;
            PrimitiveState {
                density: if inside { 5.0 } else { 1.2 },
                velocity: [0.0; 3],
                pressure: if inside { 1.0e6 } else { 1.0e5 },
            }
        },
    )
    .expect("solver")
}

fn main() {
    let args: Vec<usize> = std::env::args()
        .skip(1)
        .map(|a| a.parse().expect("integer argument"))
        .collect();
    let n = args.first().copied().unwrap_or(512);
    let steps = args.get(1).copied().unwrap_or(10);
    let rounds = args.get(2).copied().unwrap_or(5);
    let mut runs = [
        ("planar", solver(n, Geometry::Cartesian), 0.0f64),
        ("r-z", solver(n, Geometry::Axisymmetric), 0.0f64),
    ];
    for _ in 0..rounds {
        for (_, s, wall) in runs.iter_mut() {
            let t = Instant::now();
            for _ in 0..steps {
                let dt = s.stable_dt().expect("stable");
                s.advance(dt).expect("advances");
            }
            *wall += t.elapsed().as_secs_f64();
        }
    }
    let updates = (n * n * steps * rounds) as f64;
    for (name, _, wall) in &runs {
        println!("{name}: {:.3e} cell-updates/s", updates / wall);
    }
    println!(
        "r-z / planar cost per cell-update: {:.3}",
        runs[1].2 / runs[0].2
    );
}
