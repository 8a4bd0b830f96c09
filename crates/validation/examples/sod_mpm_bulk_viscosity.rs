//! V-SOD-MPM with cpGIMP at 200, 400 and 800 cells for several artificial
//! bulk viscosities: the shock's density and pressure overshoot (a
//! fraction of the jump), L1(ρ) and the plateau oscillation. The table of
//! docs/physics/mpm/bulk_viscosity.md, "The linear term and the shock's
//! overshoot":
//!
//! `cargo run --release -p brisance-validation --example sod_mpm_bulk_viscosity`

use brisance_validation::cases::sod_mpm_case_with;

fn main() {
    let settings = [
        "On(quadratic: 1.5, linear: 0.06)",
        "On(quadratic: 1.5, linear: 0.3)",
        "On(quadratic: 3.0, linear: 0.3)",
        "On(quadratic: 1.5, linear: 1.0)",
    ];
    println!("| bulk viscosity | cells | L1(ρ) | shock overshoot ρ | p | plateau osc. |");
    println!("|---|---:|---:|---:|---:|---:|");
    for q in settings {
        for cells in [200usize, 400, 800] {
            match sod_mpm_case_with(cells, "CpGimp", q) {
                Ok(r) => println!(
                    "| {q} | {cells} | {:.3e} | {:.1} % | {:.1} % | {:.1} % |",
                    r.l1_density,
                    100.0 * r.shock_overshoot,
                    100.0 * r.shock_pressure_overshoot,
                    100.0 * r.plateau_oscillation
                ),
                Err(e) => println!("| {q} | {cells} | failed: {e} | | | |"),
            }
        }
    }
}
