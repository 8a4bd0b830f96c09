//! RZ-COST: what a cell update costs on an axisymmetric (r, z) grid
//! against the same 2D grid taken as planar (x, y), for the FDM, the ICE
//! and the ICE–MPM pipelines, timed side by side in one run.
//!
//! Each pair is one shipped scenario loaded twice, once as written
//! (`domain.geometry: Axisymmetric`) and once with
//! `domain.geometry=Cartesian` (the same cells, the same initial regions,
//! planar), stepped a fixed number of steps from the start. The two are
//! timed in alternation, `REPEATS` times each, and the medians compared:
//! the machine's load then reaches both alike. The planar run is a
//! different flow (a slab, not a ring), so what is compared is the cost of
//! a step's arithmetic, not of a solution; the iteration counts of the
//! ICE equilibration may differ a little with the state.

use std::fmt::Write as _;
use std::time::Instant;

use anyhow::{anyhow, Result};
use brisance::compose::{build::build_solver, load_file};

use crate::{workspace_root, Report};

/// Timed repetitions of each geometry (alternating).
const REPEATS: usize = 5;

/// The target on the ratio (issue: an r–z cell update costs at most 1.2
/// planar ones).
const TARGET: f64 = 1.2;

/// One pair: the pipeline, the config, its overrides, the steps timed.
struct Pair {
    pipeline: &'static str,
    config: &'static str,
    sets: &'static [&'static str],
    steps: usize,
}

const PAIRS: [Pair; 3] = [
    Pair {
        pipeline: "FDM",
        config: "configs/rz_blast.ron",
        sets: &["domain.cells=(200,400,1)"],
        steps: 40,
    },
    Pair {
        pipeline: "ICE",
        config: "configs/rz_blast.ron",
        sets: &[
            "domain.cells=(100,200,1)",
            "pipeline=Ice(materials: [\"air\"])",
            "time.cfl=0.4",
        ],
        steps: 40,
    },
    Pair {
        pipeline: "ICE–MPM",
        config: "configs/cylinder_rz.ron",
        sets: &[],
        steps: 40,
    },
];

/// Seconds per cell update of `steps` steps of `config` with `sets`, after
/// building (not timed).
fn time_steps(config: &str, sets: &[String], steps: usize) -> Result<(f64, f64)> {
    let path = workspace_root().join(config);
    let loaded = load_file(&path, sets).map_err(|e| anyhow!("{config}: {e}"))?;
    let mut solver = build_solver(&loaded.scenario).map_err(|e| anyhow!("{config}: {e}"))?;
    let cells = solver.work_per_step().0;
    let start = Instant::now();
    for _ in 0..steps {
        let dt = solver.stable_dt().map_err(|e| anyhow!("{config}: {e}"))?;
        solver.advance(dt).map_err(|e| anyhow!("{config}: {e}"))?;
    }
    let wall = start.elapsed().as_secs_f64();
    Ok((wall / (cells * steps as f64), cells))
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

pub(crate) fn rz_cost(report: &mut Report) -> Result<()> {
    println!("RZ-COST: an (r, z) cell update against a planar one");
    let mut rows = Vec::new();
    for pair in &PAIRS {
        let base: Vec<String> = pair.sets.iter().map(|s| s.to_string()).collect();
        let mut planar_sets = base.clone();
        planar_sets.push("domain.geometry=Cartesian".into());
        let (mut rz, mut planar) = (Vec::new(), Vec::new());
        let mut cells = 0.0;
        for _ in 0..REPEATS {
            let (t, n) = time_steps(pair.config, &base, pair.steps)?;
            rz.push(t);
            cells = n;
            planar.push(time_steps(pair.config, &planar_sets, pair.steps)?.0);
        }
        let (a, b) = (median(rz), median(planar));
        println!(
            "  {}: r-z {:.3e} s, planar {:.3e} s per cell update, ratio {:.3}",
            pair.pipeline,
            a,
            b,
            a / b
        );
        rows.push((pair, cells, a, b));
    }
    let md = &mut report.md;
    let _ = writeln!(
        md,
        "## RZ-COST — an (r, z) cell update against a planar (x, y) one\n\n\
         Each pipeline's shipped (r, z) scenario loaded as written and again with \
         `domain.geometry=Cartesian` (the same cells and regions, planar), {REPEATS} \
         alternating timings of a fixed number of steps from the start each (build not \
         timed), the medians compared: seconds per cell update, all threads of this machine. \
         The planar run is a different flow (a slab, not a ring); what is compared is a \
         step's arithmetic.\n"
    );
    let _ = writeln!(
        md,
        "| pipeline | scenario | cells | steps | r–z (s/cell-update) | planar (s/cell-update) | ratio |\n\
         |---|---|---:|---:|---:|---:|---:|"
    );
    for (pair, cells, a, b) in &rows {
        let sets = if pair.sets.is_empty() {
            String::new()
        } else {
            format!(" `--set {}`", pair.sets.join("` `--set "))
        };
        let _ = writeln!(
            md,
            "| {} | {}{sets} | {cells:.0} | {} | {a:.3e} | {b:.3e} | {:.3} |",
            pair.pipeline,
            pair.config,
            pair.steps,
            a / b
        );
    }
    let _ = writeln!(
        md,
        "\n| figure of merit | measured | target | verdict |\n|---|---:|---|---|"
    );
    for (pair, _, a, b) in &rows {
        report.target(
            &format!("RZ-COST {} r–z over planar cell-update cost", pair.pipeline),
            format!("{:.3}", a / b),
            &format!("≤ {TARGET}"),
            a / b <= TARGET,
        );
    }
    Ok(())
}
