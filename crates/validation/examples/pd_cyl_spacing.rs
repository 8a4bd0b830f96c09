//! One run of the E-PD-CYL tube outside the report:
//! `cargo run --release -p brisance-validation --example pd_cyl_spacing --
//! SPACING_M [KEY=VALUE ...]`, the optional arguments `--set` overrides of
//! `configs/pd_cylinder_full.ron` (e.g. `pipeline.products_family=WithSolids`,
//! `time.end=3e-5`). Prints the report's figure (the mid-length wall's
//! mean radial velocity at the end against Gurney), its peak and where the
//! released energy went.

use brisance_pd::cases::{copper_cylinder as case_constants, run_tube, EnergyBudget};
use brisance_validation::pd_cylinder::PD_CYLINDER_FULL_CONFIG;
use brisance_validation::pd_tube::Tube;

const USAGE: &str = "pd_cyl_spacing SPACING_M [KEY=VALUE ...]";

fn main() {
    let mut args = std::env::args().skip(1);
    let spacing = match args.next().map(|s| s.parse::<f64>()) {
        Some(Ok(h)) => h,
        _ => {
            eprintln!("usage: {USAGE}");
            std::process::exit(2);
        }
    };
    let overrides: Vec<String> = args.collect();
    if let Err(e) = run(spacing, &overrides) {
        eprintln!("{e}");
        std::process::exit(1);
    }
}

fn run(spacing: f64, overrides: &[String]) -> Result<(), String> {
    let gurney = case_constants(spacing, 0.258).gurney_wall_velocity()?;
    let t = Tube::at_with(
        "configs/pd_cylinder_full.ron",
        PD_CYLINDER_FULL_CONFIG,
        spacing,
        overrides,
    )?;
    let nodes = t.solver.node_count();
    let t0 = std::time::Instant::now();
    let (s, h) = run_tube(
        t.solver,
        t.wall.length,
        t.wall.outer_radius,
        spacing,
        t.scenario.time.end,
        10,
    )?;
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
    let e = EnergyBudget::of(&s);
    let released = h.initial_energy - e.products;
    println!(
        "released {:.1} kJ: case kinetic {:.1} %, products kinetic {:.1} %, bonds {:.1} %, \
         contacts {:.2} %, dissipated {:.2} %; total / initial {:.4}",
        released * 1e-3,
        100.0 * e.case_kinetic / released,
        100.0 * e.products_kinetic / released,
        100.0 * e.bonds / released,
        100.0 * e.contact / released,
        100.0 * e.dissipated / released,
        e.total() / h.initial_energy
    );
    Ok(())
}
