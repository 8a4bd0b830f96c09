//! One spacing of the E-PD-FRAG resolution study, outside the report:
//! `cargo run --release -p brisance-validation --example pd_frag_spacing --
//! printed|weibull|perturbed SPACING_M [KEY=VALUE ...]`, the optional arguments
//! `--set` overrides of the scenario (e.g.
//! `pipeline.materials.steel.spread.grain_size=6e-3`, `time.end=5e-5`).
//! Prints the figures of the report's rows (fragments, m₅₀, the share of
//! the ten largest, the census), the fragments' mean speed and where the
//! products' energy went.

use brisance_pd::cumulative_mass_distribution;
use brisance_validation::pd_fragmentation::{
    census, fragmenting_cylinder_set, mass_median, mean_speed, study_args, ten_largest_fraction,
};

fn main() {
    let (strength, spacing, overrides) = match study_args(
        std::env::args().skip(1),
        "pd_frag_spacing printed|weibull|perturbed SPACING_M [KEY=VALUE ...]",
    ) {
        Ok(a) => a,
        Err(e) => {
            eprintln!("{e}");
            std::process::exit(2);
        }
    };
    let t0 = std::time::Instant::now();
    let run = match fragmenting_cylinder_set(strength, spacing, &overrides) {
        Ok(r) => r,
        Err(e) => {
            eprintln!("{e}");
            std::process::exit(1);
        }
    };
    let r = &run.result;
    let cmd = cumulative_mass_distribution(&r.fragments);
    let m50 = mass_median(&cmd);
    let ten = ten_largest_fraction(r);
    let c = census(&run.solver, &run.case, spacing);
    let speed = mean_speed(r);
    println!(
        "{strength:?} h = {spacing:e} m {overrides:?}: {} nodes, {} steps, {:.0} s",
        run.solver.node_count(),
        r.steps,
        t0.elapsed().as_secs_f64()
    );
    println!(
        "fragments {} (>= 2 nodes {}), m50 {:.2} g, ten largest {:.3}, across mid-length {}, full-length {} ({:.1} %), mean speed {:.0} m/s",
        r.fragments.len(),
        r.fragments.iter().filter(|f| f.nodes >= 2).count(),
        m50 * 1e3,
        ten,
        c.across_mid,
        c.full_length,
        100.0 * c.full_length_mass,
        speed
    );
    // Where the products' energy went, and the products nodes outside the
    // case in the middle 70 % of the tube (as E-PD-CYL prints them).
    let e = brisance_pd::cases::EnergyBudget::of(&run.solver);
    let released = run.initial_energy.products - e.products;
    let length = run.case.length;
    let (through, counted) = brisance_pd::cases::products_through_case(
        &run.solver,
        spacing,
        (0.15 * length, 0.85 * length),
    );
    println!(
        "energy: {}; products nodes outside the case {through} of {counted}",
        e.shares(released, run.initial_energy.total())
    );
    let top: Vec<String> = r
        .fragments
        .iter()
        .take(12)
        .map(|f| format!("{:.2}", f.mass * 1e3))
        .collect();
    println!("largest (g): {}", top.join(" "));
}
