//! V-ICE-IMPLICIT: the implicit-pressure variant of the ICE solver
//! (seed 000 §3.3, last paragraph; docs/physics/ice/implicit_pressure.md)
//! on a low-Mach problem, against the explicit solver.
//!
//! A closed tube of air, x ∈ [0, 1] m, 200 cells, p₀ = 1e5 Pa, T = 300 K
//! with a hot region (T + 150 K, Gaussian of width 5 cm at x = 0.3 m) at
//! the same pressure. Air enters through the left face at u_w = 0.01 c₀
//! (Mach 0.01, a fixed-velocity face) and the right face is a wall; the
//! velocity starts at the quasi-static profile u = u_w (1 − x/L), so that
//! the flow is a slow, uniform compression with no acoustic start-up
//! transient. To leading order in the Mach number p stays uniform and
//! dp/dt = γ p u_w / L (the inflow brings enthalpy h = γ p/((γ−1)ρ) per
//! unit mass into a volume of internal energy p L/(γ−1) per unit area), so
//! p(t) = p₀ exp(γ u_w t / L), whatever the temperature field.
//!
//! The explicit solver runs at its own acoustic step (CFL 0.4 on |u| + c);
//! the implicit one at a fixed Δt of 10 and 30 times the explicit step of
//! the initial state, and at its own material-velocity step (CFL 0.4 on
//! |u|, about 120 times). The explicit solver at 10 times its limit is run
//! too, to show that the limit is real.

use std::fmt::Write as _;
use std::path::Path;
use std::time::Instant;

use anyhow::{anyhow, Result};
use brisance::core::Solver;
use brisance::eos::IdealGas;
use brisance::grid::Level;
use brisance::ice::{
    CellState, ExchangeCoefficients, IceBoundary, IceOptions, IceSolver, ImplicitPressure,
    MaterialState, PressureSolve, PressureSolveStats, GHOST,
};

use crate::plot::{self, Panel, Series, SeriesStyle};
use crate::Report;

const CELLS: usize = 200;
const LENGTH: f64 = 1.0;
const P0: f64 = 1e5;
const T0: f64 = 300.0;
const MACH: f64 = 0.01;
const T_END: f64 = 0.05;
const TOLERANCE: f64 = 1e-10;

fn air() -> IdealGas {
    IdealGas::air()
}

/// Gas constant of the air model, J/(kg·K).
fn gas_constant() -> f64 {
    let a = air();
    a.cv * (a.gamma - 1.0)
}

/// Inflow velocity, m/s: Mach 0.01 of the cold gas.
fn inflow() -> f64 {
    MACH * (air().gamma * gas_constant() * T0).sqrt()
}

fn tube(pressure: PressureSolve) -> Result<IceSolver<IdealGas>> {
    let level = Level::new(
        [0.0; 3],
        [LENGTH, 0.01, 0.01],
        [CELLS, 1, 1],
        [1, 1, 1],
        GHOST,
    )
    .map_err(|e| anyhow!("{e}"))?;
    let mut b: [IceBoundary; 6] = std::array::from_fn(|_| IceBoundary::Symmetry);
    let uw = inflow();
    b[0] = IceBoundary::FixedVelocity([uw, 0.0, 0.0]);
    let r = gas_constant();
    IceSolver::new(
        vec![air()],
        level,
        b,
        ExchangeCoefficients::uniform(1, 0.0, 0.0),
        IceOptions {
            pressure,
            ..Default::default()
        },
        |x| {
            let t = T0 + 150.0 * (-((x[0] - 0.3) / 0.05).powi(2)).exp();
            CellState {
                pressure: P0,
                materials: vec![MaterialState {
                    volume_fraction: 1.0,
                    density: P0 / (r * t),
                    velocity: [uw * (1.0 - x[0] / LENGTH), 0.0, 0.0],
                }],
            }
        },
    )
    .map_err(|e| anyhow!("{e}"))
}

/// One run's result at T_END.
struct Run {
    label: String,
    dt_ratio: f64,
    steps: u64,
    wall: f64,
    fields: [Vec<f64>; 4],
    stats: PressureSolveStats,
    mass: f64,
}

const FIELDS: [&str; 4] = ["density", "velocity_x", "pressure", "temperature"];

/// Runs to T_END at `dt` (None: the solver's stable step), the last step
/// shortened to land on T_END.
fn run(label: &str, pressure: PressureSolve, dt: Option<f64>, dt_ac: f64) -> Result<Run> {
    let mut s = tube(pressure)?;
    let start = Instant::now();
    let mut dt_max: f64 = 0.0;
    while s.time() < T_END * (1.0 - 1e-12) {
        let step = match dt {
            Some(dt) => dt,
            None => s.stable_dt().map_err(|e| anyhow!("{e}"))?,
        };
        dt_max = dt_max.max(step);
        let step = step.min(T_END - s.time());
        s.advance(step).map_err(|e| anyhow!("{label}: {e}"))?;
    }
    let wall = start.elapsed().as_secs_f64();
    let names: Vec<String> = FIELDS.iter().map(|f| f.to_string()).collect();
    let d = s.cell_data(&names).map_err(|e| anyhow!("{e}"))?;
    let fields = std::array::from_fn(|k| d.fields[k].1.clone());
    Ok(Run {
        label: label.into(),
        dt_ratio: dt_max / dt_ac,
        steps: s.steps(),
        wall,
        fields,
        stats: s.pressure_solve_stats(),
        mass: s.conservation_totals().mass,
    })
}

/// Σ|a − b| / Σ|b|.
fn relative_l1(a: &[f64], b: &[f64]) -> f64 {
    let d: f64 = a.iter().zip(b).map(|(x, y)| (x - y).abs()).sum();
    d / b.iter().map(|y| y.abs()).sum::<f64>()
}

fn mean(v: &[f64]) -> f64 {
    v.iter().sum::<f64>() / v.len() as f64
}

fn load_average() -> String {
    std::fs::read_to_string("/proc/loadavg")
        .ok()
        .and_then(|s| s.split_whitespace().next().map(str::to_string))
        .unwrap_or_else(|| "?".into())
}

/// V-ICE-IMPLICIT section of the report.
pub fn v_ice_implicit(report: &mut Report, img: &Path) -> Result<()> {
    println!("V-ICE-IMPLICIT: low-Mach compression tube, implicit vs explicit pressure");
    let implicit = PressureSolve::Implicit(ImplicitPressure {
        tolerance: TOLERANCE,
        max_iterations: 20,
        ..Default::default()
    });
    let dt_ac = tube(PressureSolve::Explicit)?
        .stable_dt()
        .map_err(|e| anyhow!("{e}"))?;
    let load_before = load_average();
    let explicit = run(
        "explicit, acoustic CFL 0.4",
        PressureSolve::Explicit,
        None,
        dt_ac,
    )?;
    let mut runs = vec![];
    for k in [10.0, 30.0] {
        runs.push(run(
            &format!("implicit, Δt = {k:.0} Δt_ac"),
            implicit,
            Some(k * dt_ac),
            dt_ac,
        )?);
    }
    runs.push(run(
        "implicit, material-velocity CFL 0.4",
        implicit,
        None,
        dt_ac,
    )?);
    let load_after = load_average();
    let blowup = match run(
        "explicit, Δt = 10 Δt_ac",
        PressureSolve::Explicit,
        Some(10.0 * dt_ac),
        dt_ac,
    ) {
        Ok(r) => {
            let dp = relative_l1(&r.fields[2], &explicit.fields[2]);
            format!(
                "ran to the end; L1(p) differs from the reference by {:.2e} (relative)",
                dp
            )
        }
        Err(e) => format!("stopped: {e}"),
    };
    let uw = inflow();
    let gamma = air().gamma;
    let p_exact = P0 * (gamma * uw * T_END / LENGTH).exp();
    let md = &mut report.md;
    let _ = writeln!(
        md,
        "## V-ICE-IMPLICIT — implicit pressure on a low-Mach compression tube\n"
    );
    let _ = writeln!(
        md,
        "Air (γ = 1.4) in a closed tube of 1 m, {CELLS} cells, p₀ = 1e5 Pa, T = 300 K with a hot region \
         (+150 K Gaussian, width 5 cm, at 0.3 m) at the same pressure. Air enters through the left face at \
         u_w = {uw:.3} m/s (Mach {MACH}); the right face is a wall; the velocity starts at the quasi-static \
         profile u_w(1 − x/L). At t = {T_END} s the quasi-static pressure is p₀ exp(γ u_w t/L) = {p_exact:.1} Pa. \
         The explicit run steps at its acoustic CFL (0.4 on |u| + c, Δt_ac = {dt_ac:.3e} s at the start); the \
         implicit runs (docs/physics/ice/implicit_pressure.md; tolerance {TOLERANCE:e} on the volume misfit \
         per step) at 10 and 30 Δt_ac and at their own CFL (0.4 on |u| and the inflow speed). Differences are \
         Σ|q − q_explicit| / Σ|q_explicit| over the cells at t = {T_END} s; for p also relative to the \
         explicit pressure rise. Wall times on {} logical CPUs, {} rayon threads, load average {load_before} \
         before and {load_after} after the timed runs (shared machine: noisy).\n",
        std::thread::available_parallelism()
            .map(|n| n.get())
            .unwrap_or(1),
        brisance::rayon_threads(),
    );
    let _ = writeln!(
        md,
        "| run | Δt / Δt_ac | steps | wall [s] | iterations max / mean | residual max | mean p [Pa] | \
         ρ | u | p | T | p / rise |\n|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|"
    );
    let e = &explicit;
    let rise_e = mean(&e.fields[2]) - P0;
    let _ = writeln!(
        md,
        "| {} | {:.2} | {} | {:.2} | — | — | {:.1} | — | — | — | — | — |",
        e.label,
        e.dt_ratio,
        e.steps,
        e.wall,
        mean(&e.fields[2])
    );
    println!(
        "  {:<40} Δt/Δt_ac {:>7.2}  steps {:>6}  wall {:>7.2} s  mean p {:.1} Pa (quasi-static {p_exact:.1})",
        e.label,
        e.dt_ratio,
        e.steps,
        e.wall,
        mean(&e.fields[2])
    );
    let mut diffs = Vec::new();
    for r in &runs {
        let d: [f64; 4] = std::array::from_fn(|k| relative_l1(&r.fields[k], &e.fields[k]));
        let dp_rise = r.fields[2]
            .iter()
            .zip(&e.fields[2])
            .map(|(a, b)| (a - b).abs())
            .sum::<f64>()
            / (CELLS as f64 * rise_e);
        let st = r.stats;
        let _ = writeln!(
            md,
            "| {} | {:.1} | {} | {:.2} | {} / {:.2} | {:.1e} | {:.1} | {:.2e} | {:.2e} | {:.2e} | {:.2e} | {:.2e} |",
            r.label,
            r.dt_ratio,
            r.steps,
            r.wall,
            st.max_iterations,
            st.total_iterations as f64 / st.steps.max(1) as f64,
            st.max_residual,
            mean(&r.fields[2]),
            d[0],
            d[1],
            d[2],
            d[3],
            dp_rise
        );
        println!(
            "  {:<40} Δt/Δt_ac {:>7.1}  steps {:>6}  wall {:>7.2} s  iterations ≤ {} (mean {:.2})  \
             L1 ρ {:.2e} u {:.2e} p {:.2e} T {:.2e}  p/rise {:.2e}  mean p {:.1}",
            r.label,
            r.dt_ratio,
            r.steps,
            r.wall,
            st.max_iterations,
            st.total_iterations as f64 / st.steps.max(1) as f64,
            d[0],
            d[1],
            d[2],
            d[3],
            dp_rise,
            mean(&r.fields[2])
        );
        diffs.push((d, dp_rise));
    }
    let _ = writeln!(md);
    let _ = writeln!(
        md,
        "Explicit solver at 10 Δt_ac: {blowup}.\n\nMass at t = {T_END} s: explicit {:.9e} kg, implicit at 30 \
         Δt_ac {:.9e} kg (the inflow adds mass; relative difference {:.1e}).\n",
        e.mass,
        runs[1].mass,
        (runs[1].mass - e.mass).abs() / e.mass
    );
    println!("  explicit at 10 Δt_ac: {blowup}");
    let _ = writeln!(
        md,
        "| figure of merit | measured | target | verdict |\n|---|---:|---|---|"
    );
    let (d30, rise30) = diffs[1];
    report.target(
        "V-ICE-IMPLICIT time step of the implicit run",
        format!("{:.1} Δt_ac", runs[1].dt_ratio),
        "≥ 10 Δt_ac",
        runs[1].dt_ratio >= 10.0,
    );
    let worst = d30.iter().copied().fold(0.0, f64::max);
    report.target(
        "V-ICE-IMPLICIT largest L1 difference of ρ, u, p, T at 30 Δt_ac",
        format!("{:.3} %", 100.0 * worst),
        "≤ 1 % (Mach 0.01)",
        worst <= 0.01,
    );
    report.target(
        "V-ICE-IMPLICIT L1(p) difference at 30 Δt_ac over the pressure rise",
        format!("{:.3} %", 100.0 * rise30),
        "≤ 1 %",
        rise30 <= 0.01,
    );
    let p_err = (mean(&runs[1].fields[2]) - p_exact).abs() / (p_exact - P0);
    report.target(
        "V-ICE-IMPLICIT mean p at 30 Δt_ac vs quasi-static, over the rise",
        format!("{:.4} %", 100.0 * p_err),
        "≤ 1 % (O(Mach))",
        p_err <= 0.01,
    );
    report.target(
        "V-ICE-IMPLICIT outer iterations converged (max residual, all runs)",
        format!(
            "{:.1e}",
            runs.iter()
                .map(|r| r.stats.max_residual)
                .fold(0.0, f64::max)
        ),
        &format!("≤ {TOLERANCE:e}"),
        runs.iter().all(|r| r.stats.max_residual <= TOLERANCE),
    );
    let speedup = e.wall / runs[1].wall;
    report.target(
        "V-ICE-IMPLICIT wall-time ratio explicit / implicit at 30 Δt_ac",
        format!("{speedup:.1}"),
        "> 1",
        speedup > 1.0,
    );
    let _ = writeln!(
        report.md,
        "\n![V-ICE-IMPLICIT profiles](img/v_ice_implicit.png)\n"
    );
    let x: Vec<f64> = (0..CELLS)
        .map(|i| (i as f64 + 0.5) * LENGTH / CELLS as f64)
        .collect();
    let labels = [
        "density [kg/m³]",
        "velocity [m/s]",
        "pressure [Pa]",
        "temperature [K]",
    ];
    let panels: Vec<Panel> = (0..4)
        .map(|k| Panel {
            y_label: labels[k],
            series: vec![
                Series {
                    label: "explicit",
                    x: &x,
                    y: &explicit.fields[k],
                    style: SeriesStyle::Line,
                },
                Series {
                    label: "implicit 30 Δt_ac",
                    x: &x,
                    y: &runs[1].fields[k],
                    style: SeriesStyle::Points,
                },
            ],
        })
        .collect();
    plot::plot_panels(
        &img.join("v_ice_implicit.png"),
        &format!("V-ICE-IMPLICIT: Mach {MACH} compression tube at t = {T_END} s"),
        "x [m]",
        &panels,
    )?;
    Ok(())
}
