//! V-NOBLE-ABEL: the shock tube of the Noble–Abel propellant gas (the
//! equation of state of its own crate, `crates/eos-noble-abel`, reached
//! through the plugin registry from `configs/noble_abel_shock_tube.ron`)
//! against the gas's exact Riemann solution
//! (`brisance_eos_noble_abel::riemann`, Toro §4.7).

use std::fmt::Write as _;

use anyhow::{anyhow, Result};
use brisance::compose::{build::build_solver, load_file, run::advance_to};
use brisance::verification::cases::observed_orders;
use brisance_eos_noble_abel::riemann::{RiemannProblem, State};

use crate::{workspace_root, Report};

/// Cells of the sequence.
const CELLS: [usize; 4] = [200, 400, 800, 1600];

/// Sub-cells of the exact cell averages.
const SUBCELLS: usize = 64;

/// One run against the exact solution.
struct Run {
    cells: usize,
    steps: u64,
    /// Σ|ρ − ρ_exact| Δx over ∫ρ_exact dx.
    l1: f64,
    /// Mean pressure over the middle half of the star region (between the
    /// fan's tail and the shock), over p*.
    star_pressure: f64,
    /// Relative change of the total mass.
    mass_change: f64,
}

fn run(cells: usize) -> Result<(Run, f64, f64)> {
    let path = workspace_root().join("configs/noble_abel_shock_tube.ron");
    let sets = [
        format!("domain.cells=({cells},1,1)"),
        format!("outputs.lineouts.0.points={cells}"),
    ];
    let loaded = load_file(&path, &sets).map_err(|e| anyhow!("{e}"))?;
    let end = loaded.scenario.time.end;
    let mut solver = build_solver(&loaded.scenario).map_err(|e| anyhow!("{e}"))?;
    let mass0 = solver.conservation_totals().mass;
    let steps = advance_to(solver.as_mut(), end).map_err(|e| anyhow!("{e}"))?;
    let names = ["density", "pressure"].map(String::from);
    let data = solver.cell_data(&names).map_err(|e| anyhow!("{e}"))?;
    let g = data.geometry;
    let dx = g.spacing[0];
    let exact = RiemannProblem {
        gamma: 1.25,
        covolume: 1.0e-3,
        left: State {
            density: 200.0,
            velocity: 0.0,
            pressure: 2.5e8,
        },
        right: State {
            density: 20.0,
            velocity: 0.0,
            pressure: 2.5e6,
        },
    }
    .solve()
    .map_err(anyhow::Error::msg)?;
    let (rho, p) = (&data.fields[0].1, &data.fields[1].1);
    let (mut err, mut norm) = (0.0, 0.0);
    for (i, r) in rho.iter().enumerate() {
        let x = g.cell_centre([i, 0, 0])[0];
        let e = exact.cell_average(x - 0.5 * dx, x + 0.5 * dx, 0.5, end, SUBCELLS);
        err += (r - e.density).abs() * dx;
        norm += e.density * dx;
    }
    // The star region: from the left fan's tail to the shock.
    let star_left = State {
        density: exact.rho_star()[0],
        velocity: exact.u_star(),
        pressure: exact.p_star(),
    };
    let a = (1.25 * star_left.pressure / (star_left.density * (1.0 - 1.0e-3 * star_left.density)))
        .sqrt();
    let tail = 0.5 + (exact.u_star() - a) * end;
    let shock = 0.5
        + exact
            .shock_speed(1)
            .ok_or_else(|| anyhow!("no right shock"))?
            * end;
    let (lo, hi) = (tail + 0.25 * (shock - tail), tail + 0.75 * (shock - tail));
    let inside: Vec<f64> = (0..rho.len())
        .filter(|&i| {
            let x = g.cell_centre([i, 0, 0])[0];
            x > lo && x < hi
        })
        .map(|i| p[i])
        .collect();
    let star_pressure = inside.iter().sum::<f64>() / inside.len() as f64 / exact.p_star();
    let mass_change = (solver.conservation_totals().mass - mass0) / mass0;
    Ok((
        Run {
            cells,
            steps,
            l1: err / norm,
            star_pressure,
            mass_change,
        },
        exact.p_star(),
        shock,
    ))
}

pub(crate) fn v_noble_abel(report: &mut Report) -> Result<()> {
    println!("V-NOBLE-ABEL: Noble-Abel propellant-gas shock tube against its exact solution");
    let mut runs = Vec::new();
    let (mut p_star, mut shock) = (0.0, 0.0);
    for n in CELLS {
        let (r, p, s) = run(n)?;
        println!(
            "  {n:>5} cells  {:>4} steps  L1(ρ)/∫ρ {:.4e}  star pressure {:+.3} %",
            r.steps,
            r.l1,
            100.0 * (r.star_pressure - 1.0)
        );
        (p_star, shock) = (p, s);
        runs.push(r);
    }
    let l1: Vec<f64> = runs.iter().map(|r| r.l1).collect();
    let orders = observed_orders(&CELLS, &l1);
    let md = &mut report.md;
    let _ = writeln!(
        md,
        "## V-NOBLE-ABEL — shock tube of the Noble–Abel propellant gas (a plugin equation of state, FDM)\n"
    );
    let _ = writeln!(
        md,
        "`configs/noble_abel_shock_tube.ron` (docs/physics/eos/noble_abel.md): the co-volume gas of \
         `crates/eos-noble-abel`, named `NobleAbel` in the config and reached through the plugin registry; \
         γ = 1.25, b = 1.0e-3 m³/kg; ρ 200 / 20 kg/m³, p 2.5e8 / 2.5e6 Pa, u = 0, diaphragm at x = 0.5 m, \
         t = 150 µs, reflective left end, outflow right end (no wave reaches either), adaptive viscosity, \
         per-sweep Courant number 0.8. Reference: the exact Riemann solution of the co-volume gas \
         (`brisance_eos_noble_abel::riemann`, Toro §4.7: p* = {:.6e} Pa, the shock at x = {:.4} m) averaged \
         over each cell on {SUBCELLS} sub-cells. L1(ρ) is Σ|ρ − ρ_exact| Δx over ∫ρ_exact dx; star pressure: \
         the mean cell pressure over the middle half between the fan's tail and the shock, over p*.\n",
        p_star, shock
    );
    let _ = writeln!(
        md,
        "| cells | steps | L1(ρ) / ∫ρ | observed order | star pressure vs p* | mass change |\n|---:|---:|---:|---:|---:|---:|"
    );
    for (k, r) in runs.iter().enumerate() {
        let order = if k == 0 {
            "—".to_string()
        } else {
            format!("{:.3}", orders[k - 1])
        };
        let _ = writeln!(
            md,
            "| {} | {} | {:.4e} | {order} | {:+.3} % | {:.1e} |",
            r.cells,
            r.steps,
            r.l1,
            100.0 * (r.star_pressure - 1.0),
            r.mass_change
        );
    }
    let _ = writeln!(
        md,
        "\n| figure of merit | measured | target | verdict |\n|---|---:|---|---|"
    );
    let r400 = &runs[1];
    report.target(
        "V-NOBLE-ABEL L1(ρ)/∫ρ at 400 cells",
        format!("{:.3e}", r400.l1),
        "≤ 1e-2",
        r400.l1 <= 1e-2,
    );
    let order = (l1[0] / l1[3]).ln() / 8f64.ln();
    report.target(
        "V-NOBLE-ABEL observed order 200→1600 cells",
        format!("{order:.3}"),
        "≥ 0.8",
        order >= 0.8,
    );
    let finest = &runs[runs.len() - 1];
    let dp = finest.star_pressure - 1.0;
    report.target(
        "V-NOBLE-ABEL star pressure vs p* at 1600 cells",
        format!("{:+.3} %", 100.0 * dp),
        "within 0.5 %",
        dp.abs() <= 5e-3,
    );
    let worst_mass = runs.iter().map(|r| r.mass_change.abs()).fold(0.0, f64::max);
    report.target(
        "V-NOBLE-ABEL relative mass change (worst)",
        format!("{worst_mass:.1e}"),
        "≤ 1e-13",
        worst_mass <= 1e-13,
    );
    Ok(())
}
