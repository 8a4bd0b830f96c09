//! V-ICE-DIFFUSION: the viscous stress and heat conduction of the ICE
//! solver (seed 000 eqs 2–3) on the two decaying waves of
//! `brisance::ice::diffusion` (shared with the unit tests of `crates/ice`):
//! the measured decay rate against νk² and αk² at 32–256 cells, the
//! observed orders, the limit that set Δt, and the total energy.

use std::fmt::Write as _;
use std::time::Instant;

use anyhow::Result;
use brisance::ice::diffusion::{shear_wave, temperature_wave, WaveRun, WAVE_END};
use brisance::verification::cases::observed_orders;

use crate::Report;

const CELLS: [usize; 4] = [32, 64, 128, 256];

pub fn v_ice_diffusion(report: &mut Report) -> Result<()> {
    println!(
        "V-ICE-DIFFUSION: decaying shear and temperature waves, ICE viscous stress and conduction"
    );
    let md = &mut report.md;
    let _ = writeln!(
        md,
        "## V-ICE-DIFFUSION — viscous stress and heat conduction of ICE (seed 000 eqs 2–3)\n"
    );
    let _ = writeln!(
        md,
        "Periodic tubes on [0, 1], k = 2π, full ICE step at the solver's own Δt (cfl 0.4), to t = {WAVE_END}. \
         Shear wave u_y = U sin(kx) e^{{−νk²t}} in a γ = 1.4 gas (ρ = 1, p = 1, μ = 0.05, U = 10⁻³); \
         temperature wave T = T₀ + ΔT sin(kx) e^{{−αk²t}}, α = k/(ρc_v) = 0.05, in a Murnaghan solid without \
         thermal expansion (ρ₀ = 1, κ = 1, c_v = 1000, T₀ = 300 K, ΔT = 10 K). Error = measured decay rate / \
         exact − 1; the leading term is (kΔx)²(cfl·3/16 − 1/12) for the shear wave and (kΔx)²(cfl/4 − 1/12) \
         for the temperature wave (docs/physics/ice/diffusion.md).\n"
    );
    let _ = writeln!(
        md,
        "| wave | cells | rate error | order | Δt limit | Δt | steps | total energy change | wall (s) |\n|---|---:|---:|---:|---|---:|---:|---:|---:|"
    );
    let mut runs: Vec<(&str, Vec<WaveRun>)> = Vec::new();
    for (name, case) in [
        ("shear", shear_wave as fn(usize) -> _),
        ("temperature", temperature_wave),
    ] {
        let mut out = Vec::new();
        for cells in CELLS {
            let start = Instant::now();
            let r = case(cells).map_err(|e| anyhow::anyhow!("{name} wave, {cells} cells: {e}"))?;
            let wall = start.elapsed().as_secs_f64();
            println!(
                "  {name:<11} {cells:>4} cells  rate error {:+.3e}  {:?}-limited  Δt {:.3e}  {} steps  ΔE/E {:.1e}  {wall:.2} s",
                r.rate_error, r.binding, r.dt, r.steps, r.energy_change
            );
            out.push((r, wall));
        }
        let errors: Vec<f64> = out.iter().map(|(r, _)| r.rate_error.abs()).collect();
        let orders = observed_orders(&CELLS, &errors);
        for (i, (r, wall)) in out.iter().enumerate() {
            let order = if i == 0 {
                "–".to_string()
            } else {
                format!("{:.2}", orders[i - 1])
            };
            let _ = writeln!(
                md,
                "| {name} | {} | {:+.3e} | {order} | {:?} | {:.3e} | {} | {:.1e} | {wall:.2} |",
                r.cells, r.rate_error, r.binding, r.dt, r.steps, r.energy_change
            );
        }
        runs.push((name, out.into_iter().map(|(r, _)| r).collect()));
    }
    let _ = writeln!(
        md,
        "\n| check | measured | target | verdict |\n|---|---:|---|---|"
    );
    for (name, rs) in &runs {
        let errors: Vec<f64> = rs.iter().map(|r| r.rate_error.abs()).collect();
        let orders = observed_orders(&CELLS, &errors);
        let worst = orders.iter().cloned().fold(f64::INFINITY, f64::min);
        report.target(
            &format!("V-ICE-DIFFUSION {name} wave: smallest observed order 32–256 cells"),
            format!("{worst:.2}"),
            "≥ 1.8",
            worst >= 1.8,
        );
        let e64 = rs[1].rate_error.abs();
        report.target(
            &format!("V-ICE-DIFFUSION {name} wave: |rate error| at 64 cells"),
            format!("{e64:.2e}"),
            "≤ 5e-4",
            e64 <= 5e-4,
        );
        let diffusive = rs.iter().all(|r| {
            format!("{:?}", r.binding)
                == if *name == "shear" {
                    "Viscous"
                } else {
                    "Conduction"
                }
        });
        report.target(
            &format!("V-ICE-DIFFUSION {name} wave: Δt set by its diffusive limit"),
            if diffusive { "all runs" } else { "not all" }.into(),
            "all runs",
            diffusive,
        );
    }
    let worst_energy = runs
        .iter()
        .flat_map(|(_, rs)| rs.iter().map(|r| r.energy_change.abs()))
        .fold(0.0, f64::max);
    report.target(
        "V-ICE-DIFFUSION: largest |total energy change| (periodic)",
        format!("{worst_energy:.1e}"),
        "≤ 1e-12",
        worst_energy <= 1e-12,
    );
    let _ = writeln!(report.md);
    Ok(())
}
