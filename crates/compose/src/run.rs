//! The run loop: stable time step, advance, outputs on schedule (output
//! times hit exactly), point and particle gauges every step, conservation
//! bookkeeping, checkpoints and restart, a progress bar and tracing spans.

use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Instant;

use brisance_core::{ConservationTotals, Solver};
use brisance_io as io;
use indicatif::{ProgressBar, ProgressStyle};
use serde::{Deserialize, Serialize};

use crate::build::build_solver;
use crate::config::{CheckpointLayout, Scenario, VtkLayout};
use crate::error::RunError;
use crate::load::LoadedScenario;

/// How to run.
#[derive(Debug, Clone, Default)]
pub struct RunOptions {
    /// Output directory.
    pub out_dir: PathBuf,
    /// Continue from this checkpoint.
    pub restart: Option<PathBuf>,
    /// Show a progress bar (only drawn on a terminal).
    pub progress: bool,
}

/// The run loop's own state, saved in checkpoints so a restart continues
/// exactly where the interrupted run was.
#[derive(Debug, Clone, Default, Serialize, Deserialize)]
struct RunState {
    steps: u64,
    /// Index of the next scheduled output time.
    next_output: usize,
    gauge_rows: Vec<Vec<(f64, Vec<f64>)>>,
    particle_gauge_rows: Vec<Vec<(f64, Vec<f64>)>>,
    conservation_rows: Vec<(f64, ConservationTotals)>,
    /// The solver's external work at each conservation row (methods that
    /// report one), J.
    external_work_rows: Vec<f64>,
    pvd: io::PvdSeries,
    particle_pvd: io::PvdSeries,
    node_pvd: io::PvdSeries,
    initial_totals: ConservationTotals,
    compute_seconds: f64,
    /// Work done so far in the solver's unit (cell-updates, particle-steps),
    /// summed step by step because the particle count changes when
    /// particles leave through outflow faces.
    work: f64,
    /// The steps taken: first, smallest (and the time it started at) and
    /// last, s; `None` before the first.
    time_steps: Option<TimeSteps>,
}

/// The run's time steps so far, for the summary.
#[derive(Debug, Clone, Copy, Serialize, Deserialize)]
struct TimeSteps {
    first: f64,
    smallest: f64,
    smallest_at: f64,
    last: f64,
}

impl TimeSteps {
    /// These steps and one of `dt` from time `t`.
    fn with(self_: Option<Self>, dt: f64, t: f64) -> Self {
        match self_ {
            None => Self {
                first: dt,
                smallest: dt,
                smallest_at: t,
                last: dt,
            },
            Some(mut s) => {
                if dt < s.smallest {
                    s.smallest = dt;
                    s.smallest_at = t;
                }
                s.last = dt;
                s
            }
        }
    }
}

/// Steps between the snapshots [`LastGood`] takes: a snapshot costs about
/// a copy of the state; one every step slowed a 1D Fdm tube of 40000
/// cells by about a third, one every 64 steps is lost in the noise.
const SNAPSHOT_EVERY: usize = 64;

/// What recovers the state before a failed step: a snapshot of this
/// rank's state ([`Solver::save_snapshot`], nothing gathered) and the
/// time steps taken since.
#[derive(Default)]
struct LastGood {
    state: Option<Vec<u8>>,
    steps: Vec<f64>,
}

/// Output times: 0, Δ, 2Δ, ... below the end, then the end.
pub fn output_times(end: f64, interval: Option<f64>) -> Vec<f64> {
    let mut times = vec![0.0];
    if let Some(iv) = interval {
        let mut k = 1u64;
        loop {
            let t = k as f64 * iv;
            if t >= end * (1.0 - 1e-12) {
                break;
            }
            times.push(t);
            k += 1;
        }
    }
    times.push(end);
    times
}

/// Sample points of a line-out: midpoints of `n` equal segments.
pub fn lineout_points(from: [f64; 3], to: [f64; 3], n: usize) -> Vec<[f64; 3]> {
    (0..n)
        .map(|k| {
            let s = (k as f64 + 0.5) / n as f64;
            std::array::from_fn(|d| from[d] + s * (to[d] - from[d]))
        })
        .collect()
}

/// The step to take toward `remaining` seconds away when the solver allows
/// `stable`: land on the target exactly, and never leave a sliver of a step
/// (halve the remainder when it is less than two stable steps). Returns the
/// step and whether it reaches the target.
pub fn next_step(stable: f64, remaining: f64) -> (f64, bool) {
    if stable >= remaining {
        (remaining, true)
    } else if 2.0 * stable > remaining {
        (0.5 * remaining, false)
    } else {
        (stable, false)
    }
}

/// Advances a solver to time `end` (no outputs), with the run loop's step
/// rule; returns the number of steps taken.
pub fn advance_to(solver: &mut dyn Solver, end: f64) -> Result<u64, brisance_core::SolverError> {
    let mut steps = 0;
    loop {
        let remaining = end - solver.time();
        if remaining <= 0.0 {
            return Ok(steps);
        }
        let (dt, hits) = next_step(solver.stable_dt()?, remaining);
        solver.advance(dt)?;
        steps += 1;
        if hits {
            return Ok(steps);
        }
    }
}

struct Runner<'a> {
    scenario: &'a Scenario,
    text: &'a str,
    out: PathBuf,
    solver: Box<dyn Solver>,
    state: RunState,
    times: Vec<f64>,
    sample: Vec<f64>,
    /// The warnings of this run, for the summary.
    warnings: Vec<String>,
    /// The faces already warned of as holding back an inflow.
    warned: [bool; 6],
    /// Whether this process writes the outputs: the only one, or rank 0
    /// of several ([`brisance_grid::comm`]). Every rank computes what is
    /// written (sums and samples are collective), only this one writes.
    writes: bool,
}

/// The warning for face `face` (config name) whose condition `condition`
/// of pipeline `pipeline` has held back a flow into the domain, by time
/// `time`.
pub fn blocked_inflow_warning(face: &str, condition: &str, pipeline: &str, time: f64) -> String {
    format!(
        "boundaries.{face}: the one-way `{condition}` face of the {pipeline} pipeline held back a flow into the domain by t = {time:e} s: nothing enters there; `ZeroGradient` lets the boundary state in, `Fixed(state)` a given state"
    )
}

impl Runner<'_> {
    /// Warns, once per face, of the one-way faces that have held back an
    /// inflow since the last call ([`Solver::blocked_inflow`]); `print`
    /// writes the line (around the progress bar).
    fn note_blocked_inflow(&mut self, print: impl Fn(&str)) {
        let blocked = self.solver.blocked_inflow();
        for (k, (face, bc)) in self.scenario.boundaries.faces().iter().enumerate() {
            if blocked[k] && !self.warned[k] {
                self.warned[k] = true;
                let w =
                    blocked_inflow_warning(face, bc.name(), self.solver.name(), self.solver.time());
                print(&w);
                self.warnings.push(w);
            }
        }
    }

    fn record_gauges(&mut self) -> Result<(), RunError> {
        let t = self.solver.time();
        for (k, g) in self.scenario.outputs.gauges.iter().enumerate() {
            self.solver
                .sample(g.point, &g.fields, &mut self.sample)
                .map_err(|source| RunError::Solver {
                    step: self.state.steps,
                    source,
                })?;
            self.state.gauge_rows[k].push((t, self.sample.clone()));
        }
        for (k, g) in self.scenario.outputs.particle_gauges.iter().enumerate() {
            if !self
                .solver
                .sample_particle_gauge(k, &g.quantities, &mut self.sample)
            {
                return Err(RunError::Solver {
                    step: self.state.steps,
                    source: brisance_core::SolverError::Other(format!(
                        "particle gauge `{}` has no particle set (the pipeline carries no particles)",
                        g.name
                    )),
                });
            }
            self.state.particle_gauge_rows[k].push((t, self.sample.clone()));
        }
        Ok(())
    }

    fn lineout_fields(&self, k: usize) -> Vec<String> {
        let l = &self.scenario.outputs.lineouts[k];
        if l.fields.is_empty() {
            self.scenario.outputs.fields.clone()
        } else {
            l.fields.clone()
        }
    }

    fn write_lineouts(&mut self, label: &str) -> Result<(), RunError> {
        for k in 0..self.scenario.outputs.lineouts.len() {
            let l = &self.scenario.outputs.lineouts[k];
            let fields = self.lineout_fields(k);
            let points = lineout_points(l.from, l.to, l.points);
            let mut values = Vec::with_capacity(points.len());
            for p in &points {
                self.solver
                    .sample(*p, &fields, &mut self.sample)
                    .map_err(|source| RunError::Solver {
                        step: self.state.steps,
                        source,
                    })?;
                values.push(self.sample.clone());
            }
            let path = self
                .out
                .join("lineouts")
                .join(format!("{}_{label}.csv", l.name));
            if self.writes {
                io::write_lineout_csv(&path, &fields, &points, &values)?;
            }
        }
        Ok(())
    }

    /// Field output number `index` at the current time.
    fn write_output(&mut self, index: usize) -> Result<(), RunError> {
        let _span = tracing::debug_span!("output", index, time = self.solver.time()).entered();
        let t = self.solver.time();
        let o = &self.scenario.outputs;
        if o.vtk && !o.fields.is_empty() {
            let rel = match o.vtk_layout {
                VtkLayout::Whole => {
                    let data =
                        self.solver
                            .cell_data(&o.fields)
                            .map_err(|source| RunError::Solver {
                                step: self.state.steps,
                                source,
                            })?;
                    let rel = format!("vtk/{}_{index:05}.vti", self.scenario.name);
                    if self.writes {
                        io::write_vti(&self.out.join(&rel), &data)?;
                    }
                    rel
                }
                VtkLayout::Patches => self.write_pieces(index)?,
            };
            self.state.pvd.push(t, rel);
            if self.writes {
                self.state
                    .pvd
                    .write(&self.out.join(format!("{}.pvd", self.scenario.name)))?;
            }
        }
        if o.vtk && !o.node_fields.is_empty() {
            let nodes =
                self.solver
                    .node_data(&o.node_fields)
                    .map_err(|source| RunError::Solver {
                        step: self.state.steps,
                        source,
                    })?;
            if let Some(nodes) = nodes {
                let rel = format!("vtk/{}_nodes_{index:05}.vti", self.scenario.name);
                if self.writes {
                    io::write_vti_nodes(&self.out.join(&rel), &nodes)?;
                }
                self.state.node_pvd.push(t, rel);
                if self.writes {
                    self.state
                        .node_pvd
                        .write(&self.out.join(format!("{}_nodes.pvd", self.scenario.name)))?;
                }
            }
        }
        if o.vtk {
            if let Some(particles) = self.solver.particle_data() {
                let rel = format!("vtk/{}_particles_{index:05}.vtu", self.scenario.name);
                if self.writes {
                    io::write_vtu(&self.out.join(&rel), &particles)?;
                }
                self.state.particle_pvd.push(t, rel);
                if self.writes {
                    self.state.particle_pvd.write(
                        &self
                            .out
                            .join(format!("{}_particles.pvd", self.scenario.name)),
                    )?;
                }
            }
        }
        self.write_lineouts(&index.to_string())?;
        if self.writes {
            self.solver
                .write_output_files(&self.out, index)
                .map_err(|source| RunError::Solver {
                    step: self.state.steps,
                    source,
                })?;
        }
        self.state
            .conservation_rows
            .push((t, self.solver.conservation_totals()));
        if let Some(w) = self.solver.external_work() {
            self.state.external_work_rows.push(w);
        }
        self.write_histories()
    }

    /// Field output number `index` as one `.vti` piece per patch, each
    /// written by the rank that owns the patch, and the `.pvti` master
    /// listing them all (rank 0); the master's path relative to the
    /// output folder.
    fn write_pieces(&self, index: usize) -> Result<String, RunError> {
        let fields = &self.scenario.outputs.fields;
        let step = self.state.steps;
        let pieces = self
            .solver
            .cell_pieces(fields)
            .map_err(|source| RunError::Solver { step, source })?
            .ok_or_else(|| RunError::Solver {
                step,
                source: brisance_core::SolverError::Other(
                    "this pipeline's cells are not split into patches; outputs.vtk_layout must be `Whole`".into(),
                ),
            })?;
        let stem = format!("{}_{index:05}", self.scenario.name);
        let sources: Vec<String> = (0..pieces.extents.len())
            .map(|p| format!("{stem}/{stem}_{p:05}.vti"))
            .collect();
        let vtk = self.out.join("vtk");
        if !pieces.pieces.is_empty() {
            io::ensure_dir(&vtk.join(&stem))?;
        }
        for piece in &pieces.pieces {
            io::write_vti_piece(&vtk.join(&sources[piece.patch]), &pieces.geometry, piece)?;
        }
        if self.writes {
            io::write_pvti(
                &vtk.join(format!("{stem}.pvti")),
                &pieces.geometry,
                fields,
                &pieces.extents,
                &sources,
            )?;
        }
        Ok(format!("vtk/{stem}.pvti"))
    }

    fn write_histories(&self) -> Result<(), RunError> {
        if !self.writes {
            return Ok(());
        }
        for (k, g) in self.scenario.outputs.gauges.iter().enumerate() {
            io::write_gauge_csv(
                &self.out.join("gauges").join(format!("{}.csv", g.name)),
                &g.fields,
                &self.state.gauge_rows[k],
            )?;
        }
        for (k, g) in self.scenario.outputs.particle_gauges.iter().enumerate() {
            io::write_gauge_csv(
                &self
                    .out
                    .join("particle_gauges")
                    .join(format!("{}.csv", g.name)),
                &brisance_mpm::ParticleSet::columns(&g.quantities),
                &self.state.particle_gauge_rows[k],
            )?;
        }
        self.write_plots()?;
        let path = self.out.join("conservation.csv");
        let rows = &self.state.conservation_rows;
        if self.solver.external_work().is_some() {
            io::write_conservation_csv_with_work(&path, rows, &self.state.external_work_rows)?;
        } else {
            io::write_conservation_csv(&path, rows)?;
        }
        Ok(())
    }

    /// `outputs.plots`: each figure from the gauge rows recorded so far,
    /// time in the unit that reads best at the current time.
    fn write_plots(&self) -> Result<(), RunError> {
        use crate::config::PlotSource;
        let o = &self.scenario.outputs;
        if o.plots.is_empty() {
            return Ok(());
        }
        let dir = self.out.join("plots");
        io::ensure_dir(&dir)?;
        let (factor, unit) = brisance_plot::time_unit(self.solver.time());
        for p in &o.plots {
            let mut curves = Vec::with_capacity(p.series.len());
            for c in &p.series {
                let (rows, name) = match &c.from {
                    PlotSource::Gauge(name) => {
                        let k = o.gauges.iter().position(|g| &g.name == name);
                        (k.map(|k| &self.state.gauge_rows[k]), name)
                    }
                    PlotSource::ParticleGauge(name) => {
                        let k = o.particle_gauges.iter().position(|g| &g.name == name);
                        (k.map(|k| &self.state.particle_gauge_rows[k]), name)
                    }
                };
                // Load validation guarantees the gauge and the column.
                let columns = crate::validate::plot_columns(o, &c.from).unwrap_or_default();
                let (Some(rows), Some(j)) = (rows, columns.iter().position(|x| x == &c.column))
                else {
                    continue;
                };
                let t: Vec<f64> = rows.iter().map(|(t, _)| t * factor).collect();
                let y: Vec<f64> = rows.iter().map(|(_, v)| v[j] * c.scale).collect();
                let label = c
                    .label
                    .clone()
                    .unwrap_or_else(|| format!("{name} {}", c.column));
                curves.push((label, t, y));
            }
            if curves.iter().all(|(_, t, _)| t.is_empty()) {
                continue;
            }
            let span = curves
                .iter()
                .flat_map(|(_, t, _)| t.iter().copied())
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), t| {
                    (lo.min(t), hi.max(t))
                });
            for r in &p.references {
                curves.push((r.label.clone(), vec![span.0, span.1], vec![r.value; 2]));
            }
            let panel = brisance_plot::Panel {
                y_label: &p.y_label,
                series: curves
                    .iter()
                    .map(|(label, t, y)| brisance_plot::Series {
                        label,
                        x: t,
                        y,
                        style: brisance_plot::SeriesStyle::Line,
                    })
                    .collect(),
            };
            let title = p.title.as_deref().unwrap_or(&self.scenario.name);
            let path = dir.join(format!("{}.png", p.name));
            brisance_plot::plot_panels(&path, title, &format!("time [{unit}]"), &[panel]).map_err(
                |e| io::IoError::Encode {
                    path: path.clone(),
                    message: format!("{e:#}"),
                },
            )?;
        }
        Ok(())
    }

    fn write_checkpoint(&self) -> Result<PathBuf, RunError> {
        let _span = tracing::debug_span!("checkpoint", step = self.state.steps).entered();
        let run_state =
            bincode::serialize(&self.state).map_err(|e| RunError::Checkpoint(e.to_string()))?;
        let solver_state = match self.scenario.outputs.checkpoint_layout {
            CheckpointLayout::Whole => self.solver.save_state(),
            CheckpointLayout::Patches => self.write_checkpoint_pieces(),
        }
        .map_err(|source| RunError::Solver {
            step: self.state.steps,
            source,
        })?;
        let ck = io::Checkpoint::new(self.text.to_string(), run_state, solver_state);
        let path = self
            .out
            .join("checkpoints")
            .join(io::checkpoint_file_name(self.state.steps));
        if !self.writes {
            return Ok(path);
        }
        io::ensure_dir(&self.out.join("checkpoints"))?;
        io::write_checkpoint(&path, &ck)?;
        tracing::info!(path = %path.display(), "checkpoint written");
        Ok(path)
    }

    /// The pieces of a checkpoint written per patch, each by the rank that
    /// owns the patch, into `checkpoints/checkpoint_<step>/`; returns the
    /// shared part, which rank 0 then writes as the checkpoint file
    /// itself, after every rank has written its pieces (so a checkpoint
    /// file stands for a complete set). A collective call.
    fn write_checkpoint_pieces(&self) -> Result<Vec<u8>, brisance_core::SolverError> {
        use brisance_core::SolverError;
        let pieces = self.solver.save_pieces()?.ok_or_else(|| {
            SolverError::Checkpoint(
                "this pipeline does not write checkpoints per patch; outputs.checkpoint_layout must be `Whole`".into(),
            )
        })?;
        let dir = self
            .out
            .join("checkpoints")
            .join(io::checkpoint_pieces_dir_name(self.state.steps));
        let written = (|| {
            if !pieces.pieces.is_empty() {
                io::ensure_dir(&dir)?;
            }
            for (patch, bytes) in &pieces.pieces {
                io::write_checkpoint_piece(
                    &dir.join(io::checkpoint_piece_file_name(*patch)),
                    bytes,
                )?;
            }
            Ok::<(), io::IoError>(())
        })();
        // Every rank's pieces are on disk (or one failed) before rank 0
        // writes the file that stands for them.
        let ranks = brisance_grid::comm::world();
        let mut failed = [u64::from(written.is_err())];
        ranks.sum(&mut failed);
        written.map_err(|e| SolverError::Checkpoint(e.to_string()))?;
        if failed[0] > 0 {
            return Err(SolverError::Checkpoint(format!(
                "{} of the ranks could not write their pieces into {}",
                failed[0],
                dir.display()
            )));
        }
        Ok(pieces.common)
    }

    /// After a failed step: puts the solver back to the state before it
    /// (the snapshot, then the steps taken since, replayed: the solver is
    /// deterministic) and writes it as the next field output, so the last
    /// output is the last good state rather than a half-updated one.
    /// `drop_last`: the failure was found at the start of a step, in the
    /// state the previous step left, so the state before that step is the
    /// last good one. Best effort: what cannot be restored or written is
    /// skipped with a warning, since the run is already stopping on the
    /// step's error.
    fn write_last_good(&mut self, last_good: &LastGood, drop_last: bool) {
        let Some(bytes) = &last_good.state else {
            return;
        };
        let steps = if drop_last {
            match last_good.steps.split_last() {
                Some((_, before)) => before,
                None => return,
            }
        } else {
            &last_good.steps[..]
        };
        if let Err(e) = self.solver.restore_snapshot(bytes) {
            tracing::warn!("cannot restore the state before the failed step: {e}");
            return;
        }
        for &dt in steps {
            if let Err(e) = self.solver.advance(dt) {
                tracing::warn!("cannot replay the steps before the failed one: {e}");
                return;
            }
        }
        let index = self.state.next_output;
        match self.write_output(index) {
            Ok(()) => self.state.next_output += 1,
            Err(e) => tracing::warn!("cannot write the last good state: {e}"),
        }
    }

    /// The solver's parts of the wall time and, on several ranks, the
    /// time in MPI calls of the rank that spent most there (waiting for
    /// the others included; a collective call).
    fn wall_split(&self) -> Vec<io::WallPart> {
        let mut parts: Vec<io::WallPart> = self
            .solver
            .wall_split()
            .into_iter()
            .map(|(part, seconds)| io::WallPart {
                part: part.to_string(),
                seconds,
            })
            .collect();
        let ranks = brisance_grid::comm::world();
        if ranks.size() > 1 {
            let busiest = -ranks.min(-ranks.busy_seconds());
            parts.push(io::WallPart {
                part: "MPI calls (the busiest rank)".into(),
                seconds: busiest,
            });
        }
        parts
    }

    fn summary(&self, wall: f64, completed: bool, stop_reason: Option<String>) -> io::RunSummary {
        let final_totals = self.solver.conservation_totals();
        let unit = self.solver.work_per_step().1;
        let throughput = if self.state.compute_seconds > 0.0 {
            self.state.work / self.state.compute_seconds
        } else {
            0.0
        };
        io::RunSummary {
            scenario: self.scenario.name.clone(),
            pipeline: self.solver.name().to_string(),
            steps: self.state.steps,
            final_time: self.solver.time(),
            wall_seconds: wall,
            throughput,
            throughput_unit: format!("{unit}/s"),
            initial_totals: self.state.initial_totals,
            final_totals,
            relative_mass_change: io::relative_change(
                self.state.initial_totals.mass,
                final_totals.mass,
            ),
            relative_energy_change: io::relative_change(
                self.state.initial_totals.energy,
                final_totals.energy,
            ),
            threads: rayon::current_num_threads(),
            completed,
            stop_reason,
            outflow: self.solver.outflow_totals(),
            safeguards: self
                .solver
                .safeguards()
                .into_iter()
                .map(|s| io::Safeguard {
                    name: s.name.to_string(),
                    unit: s.unit.to_string(),
                    acted: s.acted,
                    checked: s.checked,
                })
                .collect(),
            wall_split: self.wall_split(),
            time_step: self.state.time_steps.map(|t| io::TimeStepSummary {
                first: t.first,
                smallest: t.smallest,
                smallest_at: t.smallest_at,
                last: t.last,
                limit: self.solver.time_step_limit(),
            }),
            warnings: self.warnings.clone(),
        }
    }
}

/// The parts of a scenario a checkpoint must agree with to be continued.
fn same_problem(a: &Scenario, b: &Scenario) -> Result<(), String> {
    // The patch split may change: checkpoints hold global fields.
    let (da, db) = (&a.domain, &b.domain);
    if da.lower != db.lower || da.upper != db.upper || da.cells != db.cells {
        return Err("domain differs".into());
    }
    // The same fields mean other masses on rings than in boxes.
    if da.geometry != db.geometry {
        return Err(format!(
            "domain.geometry differs ({} against {})",
            da.geometry.name(),
            db.geometry.name()
        ));
    }
    if a.pipeline != b.pipeline {
        return Err("pipeline differs".into());
    }
    if a.materials != b.materials {
        return Err("materials differ".into());
    }
    if a.boundaries != b.boundaries {
        return Err("boundaries differ".into());
    }
    if a.time.cfl != b.time.cfl {
        return Err("time.cfl differs".into());
    }
    Ok(())
}

/// What `--restart` takes to mean the newest valid checkpoint of the
/// output folder.
pub const LATEST: &str = "latest";

/// The newest checkpoint under `out_dir/checkpoints` that reads back
/// whole (checksum, format and all); damaged ones are skipped with a
/// warning. An error naming the folder when there is none.
pub fn latest_checkpoint(out_dir: &Path) -> Result<PathBuf, RunError> {
    let dir = out_dir.join("checkpoints");
    let step_of = |p: &Path| -> Option<u64> {
        p.file_name()?
            .to_str()?
            .strip_prefix("checkpoint_")?
            .strip_suffix(".bin")?
            .parse()
            .ok()
    };
    let mut found: Vec<(u64, PathBuf)> = std::fs::read_dir(&dir)
        .map(|rd| {
            rd.filter_map(|e| e.ok())
                .map(|e| e.path())
                .filter_map(|p| step_of(&p).map(|k| (k, p)))
                .collect()
        })
        .unwrap_or_default();
    found.sort();
    for (_, path) in found.iter().rev() {
        match io::read_checkpoint(path) {
            Ok(_) => return Ok(path.clone()),
            Err(e) => tracing::warn!("skipping {e}"),
        }
    }
    Err(RunError::Checkpoint(format!(
        "--restart {LATEST}: no valid checkpoint in {}",
        dir.display()
    )))
}

/// Runs a loaded scenario to its end time and returns the summary (also
/// written to `summary.json`). Nothing is written before the configuration,
/// the solver and the output directory have all been checked.
pub fn run(loaded: &LoadedScenario, opts: &RunOptions) -> Result<io::RunSummary, RunError> {
    run_until_stopped(loaded, opts, &AtomicBool::new(false))
}

/// [`run`], which also stops when `stop` becomes true (a signal handler
/// sets it): after the step under way, it writes a checkpoint, the
/// histories and the summary, and returns [`RunError::Interrupted`].
/// `opts.restart` may be [`LATEST`]: the newest valid checkpoint of
/// `opts.out_dir`.
pub fn run_until_stopped(
    loaded: &LoadedScenario,
    opts: &RunOptions,
    stop: &AtomicBool,
) -> Result<io::RunSummary, RunError> {
    let resolved;
    let opts = match &opts.restart {
        Some(p) if p.as_os_str() == LATEST && !p.exists() => {
            resolved = RunOptions {
                restart: Some(latest_checkpoint(&opts.out_dir)?),
                ..opts.clone()
            };
            &resolved
        }
        _ => opts,
    };
    let scenario = &loaded.scenario;
    let ranks = brisance_grid::comm::world();
    let writes = ranks.rank() == 0;
    let started = Instant::now();
    let mut solver = {
        let _span = tracing::info_span!("build").entered();
        build_solver(scenario).map_err(|e| loaded.locate(e))?
    };
    let mut state = RunState {
        gauge_rows: vec![Vec::new(); scenario.outputs.gauges.len()],
        particle_gauge_rows: vec![Vec::new(); scenario.outputs.particle_gauges.len()],
        ..Default::default()
    };
    if let Some(path) = &opts.restart {
        let ck = io::read_checkpoint(path)?;
        // The checkpoint holds the scenario's text after `--set`; it is
        // loaded as the run's own was (library materials resolved), so
        // that the two compare as the same problem.
        let old = crate::load_str(&path.display().to_string(), &ck.scenario_ron, &[])
            .map_err(|e| {
                RunError::Checkpoint(format!(
                    "{}: its scenario does not load: {e}",
                    path.display()
                ))
            })?
            .scenario;
        same_problem(&old, scenario).map_err(|why| {
            RunError::Checkpoint(format!(
                "{} was written for another problem: {why}",
                path.display()
            ))
        })?;
        // The run loop's state is encoded by this build's layout; one
        // written by another version of the program (a field added since)
        // does not decode.
        state = bincode::deserialize(&ck.run_state).map_err(|e| {
            RunError::Checkpoint(format!(
                "{}: its run state does not decode ({e}): it was probably written by another version of Brisance; rerun from the start",
                path.display()
            ))
        })?;
        if state.gauge_rows.len() != scenario.outputs.gauges.len()
            || state.particle_gauge_rows.len() != scenario.outputs.particle_gauges.len()
        {
            return Err(RunError::Checkpoint(format!(
                "{}: the gauges differ from the scenario's",
                path.display()
            )));
        }
        // Laid out as the run that wrote it asked.
        let restored = match old.outputs.checkpoint_layout {
            CheckpointLayout::Whole => solver.restore_state(&ck.solver_state),
            CheckpointLayout::Patches => {
                let dir = path.with_extension("");
                solver.restore_pieces(&ck.solver_state, &mut |patch| {
                    io::read_checkpoint_piece(&dir.join(io::checkpoint_piece_file_name(patch)))
                        .map_err(|e| e.to_string())
                })
            }
        };
        restored.map_err(|e| RunError::Checkpoint(format!("{}: {e}", path.display())))?;
    }
    if writes {
        io::check_writable_dir(&opts.out_dir)?;
    }
    let o = &scenario.outputs;
    for (needed, sub) in [
        (o.vtk, "vtk"),
        (!o.gauges.is_empty(), "gauges"),
        (!o.particle_gauges.is_empty(), "particle_gauges"),
        (!o.lineouts.is_empty(), "lineouts"),
        (o.checkpoint_every.is_some(), "checkpoints"),
    ] {
        if needed && writes {
            io::ensure_dir(&opts.out_dir.join(sub))?;
        }
    }
    let mut r = Runner {
        scenario,
        text: &loaded.text,
        out: opts.out_dir.clone(),
        solver,
        state,
        times: output_times(scenario.time.end, scenario.outputs.interval),
        sample: Vec::new(),
        warnings: Vec::new(),
        warned: [false; 6],
        writes,
    };
    if opts.restart.is_none() {
        r.state.initial_totals = r.solver.conservation_totals();
        r.record_gauges()?;
        r.write_output(0)?;
        r.state.next_output = 1;
    }
    let bar = if opts.progress {
        ProgressBar::new(1000)
    } else {
        ProgressBar::hidden()
    };
    bar.set_style(
        ProgressStyle::with_template("{spinner} [{elapsed_precise}] {bar:40} {percent:>3}% {msg}")
            .unwrap_or_else(|_| ProgressStyle::default_bar()),
    );
    let end = scenario.time.end;
    let max_steps = scenario.time.max_steps.unwrap_or(u64::MAX);
    let mut last_good = LastGood::default();
    let outcome: Result<(), RunError> = (|| {
        while r.state.next_output < r.times.len() && r.state.steps < max_steps {
            let target = r.times[r.state.next_output];
            let remaining = target - r.solver.time();
            let t0 = Instant::now();
            let stable = match r.solver.stable_dt() {
                Ok(stable) => stable,
                Err(source) => {
                    // The state the last step left is the bad one.
                    r.write_last_good(&last_good, true);
                    return Err(RunError::Solver {
                        step: r.state.steps,
                        source,
                    });
                }
            };
            let (dt, hits) = next_step(stable, remaining);
            let t_start = r.solver.time();
            let work = r.solver.work_per_step().0;
            {
                let _span = tracing::trace_span!("step", step = r.state.steps, dt).entered();
                if last_good.steps.len() >= SNAPSHOT_EVERY || last_good.state.is_none() {
                    last_good = LastGood {
                        state: r.solver.save_snapshot().ok(),
                        steps: Vec::new(),
                    };
                }
                if let Err(source) = r.solver.advance(dt) {
                    r.write_last_good(&last_good, false);
                    return Err(RunError::Solver {
                        step: r.state.steps,
                        source,
                    });
                }
                last_good.steps.push(dt);
            }
            r.state.compute_seconds += t0.elapsed().as_secs_f64();
            r.state.time_steps = Some(TimeSteps::with(r.state.time_steps, dt, t_start));
            r.state.work += work;
            r.state.steps += 1;
            r.note_blocked_inflow(|w| bar.suspend(|| tracing::warn!("{w}")));
            r.record_gauges()?;
            if hits {
                let index = r.state.next_output;
                r.write_output(index)?;
                r.state.next_output += 1;
            }
            let mut checkpoint = None;
            if let Some(every) = scenario.outputs.checkpoint_every {
                if r.state.steps.is_multiple_of(every) {
                    checkpoint = Some(r.write_checkpoint()?);
                }
            }
            // Each rank catches the signal on its own: they agree on
            // whether to stop after this step.
            let mut stopping = [u64::from(stop.load(Ordering::Relaxed))];
            ranks.sum(&mut stopping);
            if stopping[0] > 0 && r.state.next_output < r.times.len() {
                let checkpoint = match checkpoint {
                    Some(path) => path,
                    None => r.write_checkpoint()?,
                };
                return Err(RunError::Interrupted {
                    step: r.state.steps,
                    time: r.solver.time(),
                    checkpoint,
                });
            }
            bar.set_position((1000.0 * r.solver.time() / end).min(1000.0) as u64);
            bar.set_message(format!(
                "step {} t = {:.4e} s dt = {dt:.3e} s",
                r.state.steps,
                r.solver.time()
            ));
        }
        Ok(())
    })();
    bar.finish_and_clear();
    let wall = started.elapsed().as_secs_f64();
    match outcome {
        Ok(()) => {
            let completed = r.state.next_output >= r.times.len();
            if !completed {
                // Stopped by max_steps: write the state reached.
                let index = r.state.next_output;
                r.write_output(index)?;
            }
            r.write_lineouts("final")?;
            r.write_histories()?;
            let step = r.state.steps;
            if writes {
                r.solver
                    .finish(&opts.out_dir)
                    .map_err(|source| RunError::Solver { step, source })?;
            }
            let reason = (!completed).then(|| format!("max_steps = {max_steps} reached"));
            let summary = r.summary(wall, completed, reason);
            if writes {
                io::write_summary(&r.out.join("summary.json"), &summary)?;
            }
            Ok(summary)
        }
        Err(err) => {
            // Keep the last good outputs; record how far the run got.
            let summary = r.summary(wall, false, Some(err.to_string()));
            r.write_histories()?;
            if writes {
                io::write_summary(&r.out.join("summary.json"), &summary)?;
            }
            Err(err)
        }
    }
}

/// Default output directory for a config path: `out/<config stem>/`.
pub fn default_out_dir(config: Option<&Path>, scenario_name: &str) -> PathBuf {
    let stem = config
        .and_then(|p| p.file_stem())
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_else(|| scenario_name.to_string());
    PathBuf::from("out").join(stem)
}

#[cfg(test)]
mod tests;
