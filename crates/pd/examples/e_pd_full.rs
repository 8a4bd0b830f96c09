//! Runs the full-length E-PD-CYL and E-PD-FRAG cases at given spacings and
//! prints their figures of merit (the same functions `cargo xtask validate`
//! calls).
//!
//! `cargo run --release -p brisance-pd --example e_pd_full -- cyl 1.3e-3`
//! `cargo run --release -p brisance-pd --example e_pd_full -- frag 1.3e-3`

use brisance_pd::cases::{
    copper_cylinder, run_cylinder, run_fragmentation, steel_fragmenting_cylinder,
    COPPER_TUBE_LENGTH,
};
use brisance_pd::cumulative_mass_distribution;

fn main() -> Result<(), String> {
    let args: Vec<String> = std::env::args().collect();
    let which = args.get(1).map(String::as_str).unwrap_or("cyl");
    let h: f64 = args.get(2).and_then(|a| a.parse().ok()).unwrap_or(1.3e-3);
    let t = std::time::Instant::now();
    match which {
        "cyl" => {
            let case = copper_cylinder(h, COPPER_TUBE_LENGTH);
            let gurney = case.gurney_wall_velocity()?;
            let (s, hist) = run_cylinder(&case, 45.0e-6, 20)?;
            for k in 0..hist.time.len() {
                println!(
                    "{:.3e},{:.6e},{:.2}",
                    hist.time[k], hist.radial_displacement[k], hist.radial_velocity[k]
                );
            }
            let n = hist.time.len();
            println!(
                "nodes {} bonds {} terminal {:.1} m/s Gurney {gurney:.1} m/s ({:+.1} %) wall {:.1} s",
                s.node_count(),
                s.bond_count(),
                hist.radial_velocity[n - 1],
                100.0 * (hist.radial_velocity[n - 1] / gurney - 1.0),
                t.elapsed().as_secs_f64()
            );
        }
        _ => {
            let case = steel_fragmenting_cylinder(h, 0.10795, 0.0, 0.0);
            let (s, r) = run_fragmentation(&case, 40.0e-6)?;
            for c in cumulative_mass_distribution(&r.fragments).iter().take(40) {
                println!(
                    "{:.4e},{},{:.4}",
                    c.mass, c.count_at_least, c.mass_fraction_at_least
                );
            }
            println!(
                "nodes {} steps {} fragments {} (≥ 10 nodes: {}) mass {:.6e} of {:.6e} wall {:.1} s",
                s.node_count(),
                r.steps,
                r.fragments.len(),
                r.fragments.iter().filter(|f| f.nodes >= 10).count(),
                r.fragment_mass,
                r.case_mass,
                t.elapsed().as_secs_f64()
            );
        }
    }
    Ok(())
}
