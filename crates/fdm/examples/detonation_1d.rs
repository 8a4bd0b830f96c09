//! The 1D program-burn TNT detonation of seed 001 §4.1 at several cell
//! sizes: front position and peak pressure when the front has run half the
//! charge radius, and the totals at the end.
//!
//! `cargo run --release -p brisance-fdm --example detonation_1d -- [spherical|cylindrical|planar]`

use brisance_fdm::detonation::{DetonationSetup, RadialDetonation, Symmetry};

fn main() {
    let sym = match std::env::args().nth(1).as_deref() {
        Some("planar") => Symmetry::Planar,
        Some("cylindrical") => Symmetry::Cylindrical,
        _ => Symmetry::Spherical,
    };
    println!("{sym:?}: 50 mm TNT charge, grid to 0.4 m; at t = 25 mm / D");
    println!("cell (mm)  front (mm)  peak p (GPa)  steps");
    for cells in [400, 800, 1600, 3200] {
        let setup = DetonationSetup::tnt_in_air(sym, 0.05, 0.4, cells);
        let mut run = RadialDetonation::new(setup).expect("setup");
        run.run_until(0.025 / 6930.0).expect("run");
        let radii = run.radii();
        let peak = (0..radii.len())
            .max_by(|&a, &b| run.state(a).2.total_cmp(&run.state(b).2))
            .expect("cells");
        println!(
            "{:9.4}  {:10.3}  {:12.3}  {}",
            run.cell_size() * 1e3,
            radii[peak] * 1e3,
            run.state(peak).2 * 1e-9,
            run.steps()
        );
    }
}
