//! One peridynamics run of E-PD-CYL-ICEMPM's tube (seed 000's copper
//! cylinder, `configs/pd_cylinder_seed000.ron`) outside the report:
//! `cargo run --release -p brisance-validation --example pd_seed000_side --
//! SPACING_M [KEY=VALUE ...]`, the optional arguments `--set` overrides of
//! the file (e.g. `pipeline.products_family=MirroredWall`). Prints the
//! report's figure, the outer wall's mean radial velocity at z = 25 cm
//! averaged over the last tenth of the 80 µs record, and the whole wall's
//! kinetic-energy mean over the same tenth.

use brisance_validation::last_tenth_mean;
use brisance_validation::pd_cylinder::seed000_cylinder_with;
use brisance_validation::pd_tube::spacing_args;

const USAGE: &str = "pd_seed000_side SPACING_M [KEY=VALUE ...]";

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
    let t0 = std::time::Instant::now();
    let (s, h) = seed000_cylinder_with(spacing, 10, overrides)?;
    let n = h.time.len();
    if n == 0 {
        return Err("the run recorded no wall samples".into());
    }
    println!(
        "h = {:.2} mm, {} nodes, {:.0} s; overrides {overrides:?}",
        spacing * 1e3,
        s.node_count(),
        t0.elapsed().as_secs_f64()
    );
    let (k, v_peak) = h.peak();
    println!(
        "outer wall at z = 25 cm, terminal (last tenth of {:.1} µs): {:.0} m/s; peak {v_peak:.0} m/s at {:.1} µs",
        h.time[n - 1] * 1e6,
        last_tenth_mean(&h.radial_velocity, |v| *v),
        h.time[k] * 1e6
    );
    println!(
        "whole wall at z = 25 cm (kinetic-energy mean), terminal: {:.0} m/s",
        last_tenth_mean(&h.wall_velocity, |v| *v)
    );
    Ok(())
}
