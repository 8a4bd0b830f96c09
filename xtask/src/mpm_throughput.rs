//! The MPM-THROUGHPUT section of the validation report: particle-steps per
//! second and bytes per particle of the explicit MPM on a million-particle
//! 3D elastic–plastic (J2) block, against the targets of issue 4.
//!
//! The block is `configs/taylor2d.ron`'s copper (J2, σy 70 MPa, Jaumann
//! rate, MUSL) made 3D: 32 × 128 × 32 cells of 0.5 mm with 2 × 2 × 2
//! particles per cell (1 048 576 particles) in a 64 × 140 × 64-cell domain,
//! hitting the rigid wall y = 0 at 190 m/s from the first step (symmetry
//! planes x = 0 and z = 0, so it is a quarter of a 32 × 64 × 32 mm block).
//! The impact stress ρ c v ≈ 6.6 GPa is far above σy, so the particles at
//! the wall yield from the first steps; the report counts them.

use std::fmt::Write as _;
use std::time::Instant;

use anyhow::{bail, Result};
use brisance::compose::build::build_section;
use brisance::compose::load_str;
use brisance::constitutive::elastic_plastic::PLASTIC_STRAIN_INDEX;
use brisance::core::Solver;

use brisance::verification::bridge_blast::resident_bytes;

use crate::Report;

/// Steps before the clock starts (first-touch of the node arrays and
/// scratch buffers).
const WARM_UP_STEPS: usize = 2;
/// Steps timed, each `stable_dt` + `advance`.
const TIMED_STEPS: usize = 30;
/// Smallest particle count the target speaks of.
const MIN_PARTICLES: usize = 1 << 20;
/// Targets of issue 4, particle-steps/s.
const TARGET_LINEAR: f64 = 5.0e6;
const TARGET_BSPLINE: f64 = 2.5e6;
/// Target of issue 4, bytes per particle of the J2 model.
const TARGET_BYTES: f64 = 400.0;

/// The `--set` overrides of `configs/taylor2d.ron` that make the block.
fn overrides(shape: &str) -> Vec<String> {
    [
        "domain.cells=(64,140,64)",
        "domain.upper=(0.032,0.070,0.032)",
        "initial.0.region.max=(0.016,0.064,0.016)",
        "boundaries.x_high=Outflow",
        "boundaries.z_low=Reflective",
        "outputs.gauges=[]",
    ]
    .iter()
    .map(|s| s.to_string())
    .chain([format!("pipeline.shape_function={shape}")])
    .collect()
}

/// One shape function's measurement.
struct Run {
    shape: &'static str,
    particles: usize,
    setup_seconds: f64,
    rate: f64,
    /// CPU time of this process over the timed steps ÷ (wall time ×
    /// threads): 1 when every thread had a core of its own throughout.
    cpu_share: f64,
    particle_bytes: f64,
    grid_bytes: f64,
    resident_growth: f64,
    yielded: usize,
    load_before: String,
    load_after: String,
}

/// CPU time (user + system) this process has used, s (Linux; clock ticks
/// of 1/100 s, the kernel's USER_HZ on the platforms this runs on).
fn process_cpu_seconds() -> Option<f64> {
    let stat = std::fs::read_to_string("/proc/self/stat").ok()?;
    // Fields after the command name, which is in parentheses: utime and
    // stime are fields 14 and 15 of the line, 12 and 13 after the `)`.
    let rest = &stat[stat.rfind(')')? + 2..];
    let fields: Vec<&str> = rest.split_whitespace().collect();
    let ticks: f64 = fields.get(11)?.parse::<f64>().ok()? + fields.get(12)?.parse::<f64>().ok()?;
    Some(ticks / 100.0)
}

/// The 1-, 5- and 15-minute load averages of the machine (Linux).
fn load_average() -> String {
    std::fs::read_to_string("/proc/loadavg")
        .ok()
        .map(|s| s.split_whitespace().take(3).collect::<Vec<_>>().join(" "))
        .unwrap_or_else(|| "n/a".into())
}

fn measure(shape: &'static str) -> Result<Run> {
    let text = include_str!("../../configs/taylor2d.ron");
    let before = resident_bytes();
    let t0 = Instant::now();
    let loaded = load_str("taylor2d.ron", text, &overrides(shape))
        .map_err(|e| anyhow::anyhow!("the throughput block does not load: {e}"))?;
    let Some(section) = loaded
        .scenario
        .pipeline
        .section::<brisance::couple::MpmConfig>()
    else {
        bail!("the throughput block is not an Mpm pipeline");
    };
    let mut solver = build_section(section, &loaded.scenario)
        .map_err(|e| anyhow::anyhow!("the throughput block does not build: {e}"))?;
    let particles = solver.particles().len();
    if particles < MIN_PARTICLES {
        bail!("the throughput block has {particles} particles, fewer than {MIN_PARTICLES}");
    }
    for _ in 0..WARM_UP_STEPS {
        let dt = solver.stable_dt()?;
        solver.advance(dt)?;
    }
    let setup_seconds = t0.elapsed().as_secs_f64();
    let load_before = load_average();
    let mut work = 0.0;
    let cpu0 = process_cpu_seconds();
    let t1 = Instant::now();
    for _ in 0..TIMED_STEPS {
        work += solver.work_per_step().0;
        let dt = solver.stable_dt()?;
        solver.advance(dt)?;
    }
    let seconds = t1.elapsed().as_secs_f64();
    let cpu_share = match (cpu0, process_cpu_seconds()) {
        (Some(a), Some(b)) => (b - a) / (seconds * brisance::rayon_threads() as f64),
        _ => f64::NAN,
    };
    let load_after = load_average();
    let memory = solver.memory_use();
    let n = solver.particles().len() as f64;
    let ps = solver.particles();
    let stride = ps.history_stride();
    let yielded = (0..ps.len())
        .filter(|&p| ps.history[p * stride + PLASTIC_STRAIN_INDEX] > 0.0)
        .count();
    let resident_growth = match (before, resident_bytes()) {
        (Some(a), Some(b)) => (b - a) / n,
        _ => f64::NAN,
    };
    Ok(Run {
        shape,
        particles,
        setup_seconds,
        rate: work / seconds,
        cpu_share,
        particle_bytes: memory.particles as f64 / n,
        grid_bytes: memory.grid as f64 / n,
        resident_growth,
        yielded,
        load_before,
        load_after,
    })
}

pub(crate) fn mpm_throughput(report: &mut Report) -> Result<()> {
    println!("MPM-THROUGHPUT: 3D J2 copper block, 2x2x2 particles per cell, onto a rigid wall");
    let threads = brisance::rayon_threads();
    let mut runs = Vec::new();
    for shape in ["Linear", "QuadraticBSpline"] {
        let r = measure(shape)?;
        println!(
            "  {shape:<16} {} particles  {:.2e} particle-steps/s  CPU share {:.2} (rate / share {:.2e})  \
             {:.0} B/particle (+{:.0} grid)  {} yielded  load {} -> {}",
            r.particles,
            r.rate,
            r.cpu_share,
            r.rate / r.cpu_share,
            r.particle_bytes,
            r.grid_bytes,
            r.yielded,
            r.load_before,
            r.load_after
        );
        runs.push(r);
    }
    let md = &mut report.md;
    let _ = writeln!(
        md,
        "## MPM-THROUGHPUT — explicit MPM on a million-particle 3D J2 block\n"
    );
    let _ = writeln!(
        md,
        "`configs/taylor2d.ron`'s copper (J2, σy 70 MPa, K 117 GPa, G 43.8 GPa, Jaumann rate, MUSL) as a 3D \
         block of 32 × 128 × 32 cells of 0.5 mm with 2 × 2 × 2 particles per cell, in a 64 × 140 × 64-cell \
         domain (symmetry planes x = 0 and z = 0), hitting the rigid wall y = 0 at 190 m/s from the first step. \
         {TIMED_STEPS} steps timed (`stable_dt` + `advance`) after {WARM_UP_STEPS} warm-up steps; building the \
         particles and the warm-up are not timed. {threads} threads. Bytes per particle are the lengths of the \
         solver's per-particle arrays (`MpmSolver::memory_use`: particle state, bulk-viscosity state, identity, \
         bin entries); the grid (node fields and block lists) is given beside them per particle, and the growth \
         of resident memory while building and stepping as a check (freed memory of the first run may be \
         reused by the second). The machine's load average (1, 5, 15 min) \
         is printed before and after the timed steps, and the CPU share: this process's CPU time over the timed \
         steps ÷ (wall time × threads), 1 when every thread had a core of its own. This machine has 2 vCPUs \
         shared with other work, so the throughput is that of the load shown; the figures of merit are these \
         wall-clock rates. The column \"÷ CPU share\" divides the rate by the CPU share: what the same CPU \
         time per particle-step would give with a core for every thread — an estimate for an idle machine \
         (pessimistic where waiting threads spin), not a measurement.\n"
    );
    let _ = writeln!(
        md,
        "| shape function | particles | particles yielded at the end | setup + warm-up (s) | particle-steps/s | CPU share | ÷ CPU share | bytes/particle (arrays) | grid bytes/particle | resident growth/particle | load before | load after |\n\
         |---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---|---|"
    );
    for r in &runs {
        let _ = writeln!(
            md,
            "| {} | {} | {} | {:.1} | {:.2e} | {:.2} | {:.2e} | {:.0} | {:.0} | {:.0} | {} | {} |",
            r.shape,
            r.particles,
            r.yielded,
            r.setup_seconds,
            r.rate,
            r.cpu_share,
            r.rate / r.cpu_share,
            r.particle_bytes,
            r.grid_bytes,
            r.resident_growth,
            r.load_before,
            r.load_after
        );
    }
    let _ = writeln!(
        md,
        "\n| figure of merit | measured | target | verdict |\n|---|---:|---|---|"
    );
    for r in &runs {
        let (what, target) = if r.shape == "Linear" {
            ("MPM throughput, 3D J2, linear", TARGET_LINEAR)
        } else {
            ("MPM throughput, 3D J2, quadratic B-spline", TARGET_BSPLINE)
        };
        report.target(
            what,
            format!("{:.2e} particle-steps/s", r.rate),
            &format!("≥ {target:.1e}"),
            r.rate >= target,
        );
    }
    let worst = runs
        .iter()
        .map(|r| r.particle_bytes)
        .fold(0.0_f64, f64::max);
    report.target(
        "MPM memory per particle, J2",
        format!("{worst:.0} B"),
        &format!("≤ {TARGET_BYTES:.0} B"),
        worst <= TARGET_BYTES,
    );
    let _ = writeln!(report.md);
    Ok(())
}
