//! One run of the E-PD-CYL tube outside the report:
//! `cargo run --release -p brisance-validation --example pd_cyl_spacing --
//! SPACING_M [KEY=VALUE ...]`, the optional arguments `--set` overrides of
//! `configs/pd_cylinder_full.ron` (e.g. `pipeline.products_family=WithSolids`,
//! `time.end=3e-5`). Prints the report's figure (the mid-length wall's
//! mean radial velocity at the end against Gurney), its peak, the whole
//! wall's kinetic-energy mean radial velocity at mid-length and where the
//! released energy went.

use brisance_pd::cases::{case_material, copper_cylinder as case_constants, EnergyBudget};
use brisance_validation::pd_cylinder::{copper_cylinder_with, wall};
use brisance_validation::pd_tube::spacing_args;

const USAGE: &str = "pd_cyl_spacing SPACING_M [KEY=VALUE ...]";

fn main() {
    let (spacing, overrides) = match spacing_args(std::env::args().skip(1), USAGE) {
        Ok(a) => a,
        Err(e) => {
            eprintln!("{e}");
            std::process::exit(2);
        }
    };
    if let Err(e) = run(spacing, &overrides) {
        eprintln!("{e}");
        std::process::exit(1);
    }
}

fn run(spacing: f64, overrides: &[String]) -> Result<(), String> {
    let tube = wall()?;
    let gurney = case_constants(spacing, tube.length).gurney_wall_velocity()?;
    let t0 = std::time::Instant::now();
    let (s, h) = copper_cylinder_with(spacing, 10, overrides)?;
    let nodes = s.node_count();
    let n = h.time.len();
    let v_end = h.radial_velocity[n - 1];
    let (k, v_peak) = h.peak();
    println!(
        "h = {:.3} mm, {nodes} nodes, {:.0} s; overrides {overrides:?}",
        spacing * 1e3,
        t0.elapsed().as_secs_f64()
    );
    println!(
        "wall at {:.1} µs: {v_end:.0} m/s vs Gurney {gurney:.0} m/s ({:+.1} %); peak {v_peak:.0} m/s at {:.1} µs",
        h.time[n - 1] * 1e6,
        100.0 * (v_end / gurney - 1.0),
        h.time[k] * 1e6
    );
    let (kw, w_peak) = h.wall_peak();
    println!(
        "whole wall at mid-length (kinetic-energy mean): {:.0} m/s at {:.1} µs ({:+.1} %); peak {w_peak:.0} m/s at {:.1} µs ({:+.1} %)",
        h.wall_velocity[n - 1],
        h.time[n - 1] * 1e6,
        100.0 * (h.wall_velocity[n - 1] / gurney - 1.0),
        h.time[kw] * 1e6,
        100.0 * (w_peak / gurney - 1.0)
    );
    // The products of the middle fifth of the tube: how much of their mass
    // is still there, and how far along z the rest has gone.
    let case = case_material(&s);
    let length = tube.length;
    let middle = |z: f64| (z - 0.5 * length).abs() <= 0.1 * length;
    let (mut start, mut now, mut kept) = (0.0, 0.0, 0.0);
    for i in (0..s.node_count()).filter(|&i| s.materials()[i] != case) {
        let z0 = s.reference()[i][2];
        let z = z0 + s.displacement(i)[2];
        let m = s.mass(i);
        if middle(z0) {
            start += m;
            if middle(z) {
                kept += m;
            }
        }
        if middle(z) {
            now += m;
        }
    }
    println!(
        "products in the middle fifth of the tube: {:.1} g at the end against {:.1} g at the start \
         ({:.1} % of those still there)",
        now * 1e3,
        start * 1e3,
        100.0 * kept / start
    );
    let e = EnergyBudget::of(&s);
    let released = h.initial_energy - e.products;
    println!("{}", e.shares(released, h.initial_energy));
    Ok(())
}
