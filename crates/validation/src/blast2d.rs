//! E-BLAST2D (seed 001 §5.2): a 50 mm TNT charge (2D, a cylinder) at
//! (0, 250) mm detonates in air and loads a concrete slab through the
//! FDM–MPM bridge (`configs/blast2d.ron`, docs/physics/couple/bridge.md).
//!
//! The runs of the case, each built from its RON config through the
//! composer and run by its run loop: the bridge at widths w = 5, 2 and 8
//! ([`run_bridge`], from the remap `brisance remap` writes into
//! [`REMAP_DIR`]), the w = 5 bridge on finer cells, with linear or cpGIMP
//! shape functions in its MPM region ([`run_refined`]), the
//! same problem as pure MPM ([`run_pure_mpm`], `configs/blast2d_mpm.ron`),
//! and the 1D cylindrical reference ([`reference_1d`]); and what is
//! measured on a gauge's pressure history: the blast's arrival and peak
//! ([`arrival_and_peak`]), its peak averaged over the MPM gas's ringing
//! ([`mean_peak`]) and the oscillation after it ([`oscillation`]).
//! `cargo xtask validate --only blast2d` writes the report's section from
//! them.

use std::path::Path;

use brisance_compose::{load_file, run, RunOptions};
use brisance_fdm::detonation::{DetonationSetup, RadialDetonation, Symmetry};
use brisance_mpm::{BulkViscosity, ShapeFunction};

use crate::bridge_blast::CasePeak;

/// Run time of the bridge runs, s after the remap time (12 µs after
/// initiation): the blast reaches both gauges at about 6 µs, the products
/// follow, and the slab's reflection reaches gauge 2 before this.
pub const END_TIME: f64 = 4.0e-5;

/// Run time of the refined runs, s after the remap time: the blast's peak
/// window has passed both gauges (arrival about 6 µs, window 3 µs).
pub const REFINED_END: f64 = 1.2e-5;

/// Refinements of the 2 mm cells in the h sequence (1 and 0.5 mm).
pub const REFINEMENTS: [usize; 2] = [2, 4];

/// Ambient pressure of the air (ρ 1.225 kg/m³, e 2.0685e5 J/kg, γ 1.4), Pa.
pub const AMBIENT: f64 = 0.4 * 1.225 * 2.0685e5;

/// Window after the blast front within which its peak is taken, s: the
/// blast wave's own peak, before the products and the slab's reflection
/// reach the gauges.
pub const PEAK_WINDOW: f64 = 3.0e-6;

/// The remap's time (`--time` of the `brisance remap` command in
/// `configs/blast2d.ron`'s header): the zero of the 2D runs, s after
/// initiation.
pub const REMAP_TIME: f64 = 1.2e-5;

/// Distance of both gauges from the charge's axis, m.
pub const GAUGE_RADIUS: f64 = 0.125;

/// Cells of the 1D reference runs (to 0.2 m: 125 and 62.5 µm).
pub const REFERENCE_CELLS: [usize; 2] = [1600, 3200];

/// Where the runs read the remap `brisance remap` writes (`--out` of the
/// command in `configs/blast2d.ron`'s header), under the workspace root.
pub const REMAP_DIR: &str = "out/blast2d_remap";

/// A gauge's pressure history.
#[derive(Clone, Debug, PartialEq)]
pub struct History {
    /// Sample times, s.
    pub time: Vec<f64>,
    /// Pressure at each time, Pa.
    pub pressure: Vec<f64>,
}

/// The pressure history a `time,pressure` gauge CSV of the run loop
/// holds (`gauges/<name>.csv`).
pub fn read_gauge(path: &Path) -> Result<History, String> {
    let text = std::fs::read_to_string(path)
        .map_err(|e| format!("cannot read {}: {e}", path.display()))?;
    let mut h = History {
        time: Vec::new(),
        pressure: Vec::new(),
    };
    for (k, line) in text.lines().enumerate().skip(1) {
        let mut cols = line.split(',');
        let (Some(t), Some(p)) = (cols.next(), cols.next()) else {
            return Err(format!(
                "{} line {}: expected time,pressure",
                path.display(),
                k + 1
            ));
        };
        let bad = |e: std::num::ParseFloatError| format!("{} line {}: {e}", path.display(), k + 1);
        h.time.push(t.trim().parse().map_err(bad)?);
        h.pressure.push(p.trim().parse().map_err(bad)?);
    }
    Ok(h)
}

/// The blast front at a gauge: (arrival, peak). The peak is the largest
/// pressure within [`PEAK_WINDOW`] of the first sample above twice the
/// ambient pressure; the arrival is the time the pressure first reaches
/// half-way from ambient to that peak (linear between samples).
pub fn arrival_and_peak(h: &History) -> Option<(f64, f64)> {
    let first = h.pressure.iter().position(|&p| p > 2.0 * AMBIENT)?;
    let t0 = h.time[first];
    let peak = h
        .time
        .iter()
        .zip(&h.pressure)
        .skip(first)
        .take_while(|(&t, _)| t <= t0 + PEAK_WINDOW)
        .map(|(_, &p)| p)
        .fold(f64::MIN, f64::max);
    let half = AMBIENT + 0.5 * (peak - AMBIENT);
    let i = h.pressure.iter().position(|&p| p >= half)?;
    if i == 0 {
        return Some((h.time[0], peak));
    }
    let f = (half - h.pressure[i - 1]) / (h.pressure[i] - h.pressure[i - 1]);
    Some((h.time[i - 1] + f * (h.time[i] - h.time[i - 1]), peak))
}

/// Width of the window of [`mean_peak`], s: a few of the MPM gas's
/// pressure oscillations (about 0.2 µs apart at 2 mm).
pub const MEAN_WINDOW: f64 = 0.5e-6;

/// The blast's peak with the particle noise averaged out: the largest
/// time-mean pressure over a [`MEAN_WINDOW`] wide window (trapezoids)
/// that starts within [`PEAK_WINDOW`] of the first sample above twice the
/// ambient pressure.
pub fn mean_peak(h: &History) -> Option<f64> {
    let first = h.pressure.iter().position(|&p| p > 2.0 * AMBIENT)?;
    let t0 = h.time[first];
    let mut best: Option<f64> = None;
    for i in first..h.time.len() {
        if h.time[i] > t0 + PEAK_WINDOW {
            break;
        }
        let end = h.time[i] + MEAN_WINDOW;
        let Some(k) = (i + 1..h.time.len()).find(|&k| h.time[k] >= end) else {
            break;
        };
        let area: f64 = (i..k)
            .map(|m| 0.5 * (h.pressure[m] + h.pressure[m + 1]) * (h.time[m + 1] - h.time[m]))
            .sum();
        let mean = area / (h.time[k] - h.time[i]);
        best = Some(best.map_or(mean, |b: f64| b.max(mean)));
    }
    best
}

/// One bridge run and what it measured.
#[derive(Clone, Debug)]
pub struct BridgeRun {
    /// The run's name in the report ("5", "5, paper's inflow", "1.0 mm",
    /// "pure MPM").
    pub label: String,
    /// Bridge width w, cells (0 for pure MPM).
    pub width: usize,
    /// FDM and MPM wall seconds (`time_split.json`).
    pub split: Option<(f64, f64)>,
    /// MPM particles at the end and their mean over the MPM steps
    /// (`time_split.json`).
    pub particles: Option<(f64, f64)>,
    /// Steps taken.
    pub steps: u64,
    /// Time reached, s after the remap.
    pub final_time: f64,
    /// Wall time of the run loop, s.
    pub wall_seconds: f64,
    /// Peak resident memory of the run (the process's peak reset before
    /// it), bytes.
    pub peak_resident: Option<f64>,
    /// Time the MPM region started (`time_split.json`), s.
    pub activated_at: Option<f64>,
    /// Whether the run reached its end time.
    pub completed: bool,
    /// Why it stopped early, if it did.
    pub stop_reason: Option<String>,
    /// Gauge 1, (−125, 250) mm, in the FDM region.
    pub gauge1: History,
    /// Gauge 2, (125, 250) mm, in the MPM region.
    pub gauge2: History,
}

/// A number of the flat JSON object written by the bridge
/// (`"key": value`), `None` when absent or `null`.
fn json_number(text: &str, key: &str) -> Option<f64> {
    let rest = &text[text.find(&format!("\"{key}\":"))? + key.len() + 3..];
    let end = rest.find([',', '\n', '}']).unwrap_or(rest.len());
    rest[..end].trim().parse().ok()
}

/// The MPM's particles at the end and their mean over the steps, from the
/// text of `time_split.json`.
fn particles_of(text: &str) -> Option<(f64, f64)> {
    let steps = json_number(text, "steps")?;
    Some((
        json_number(text, "particles")?,
        json_number(text, "particle_steps")? / steps.max(1.0),
    ))
}

/// The FDM and MPM wall seconds, from the text of `time_split.json`.
fn split_of(text: &str) -> Option<(f64, f64)> {
    Some((
        json_number(text, "fdm_seconds")?,
        json_number(text, "mpm_seconds")?,
    ))
}

/// The bridge with width `width`; `paper_inflow` takes the paper's rule for
/// the inflow particles (every step, m_e the air particle's mass).
pub fn run_bridge(root: &Path, width: usize, paper_inflow: bool) -> Result<BridgeRun, String> {
    // The MPM region starts at 120 mm − w · 2 mm.
    let lower = 0.12 - 0.002 * width as f64;
    let remap = root.join(REMAP_DIR).join("remap.bin");
    let sets = vec![
        format!("time.end={END_TIME:e}"),
        format!("pipeline.mpm_region.lower=({lower},0.0,0.0)"),
        format!("pipeline.w=Some({width})"),
        format!("pipeline.remap=Some(\"{}\")", remap.display()),
        "pipeline.charge=None".to_string(),
        "outputs.interval=1.0".to_string(),
    ];
    let tag = if paper_inflow { "_paper" } else { "" };
    let label = format!(
        "{width}{}",
        if paper_inflow { ", paper's inflow" } else { "" }
    );
    bridge_run(
        root,
        sets,
        paper_inflow,
        &format!("w{width}{tag}"),
        label,
        width,
    )
}

/// The MPM region's options a refined run takes: its shape functions, its
/// bulk viscosity (quadratic, linear) and the gas particles' own, all
/// stated on the command line whatever the config holds.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RefinedMpm {
    /// Shape functions (`Linear` or `CpGimp`).
    pub shape: ShapeFunction,
    /// Bulk viscosity coefficients.
    pub bulk_viscosity: BulkViscosity,
    /// The gas particles' coefficients in place of `bulk_viscosity`
    /// (`fluid_bulk_viscosity`), if any.
    pub fluid_bulk_viscosity: Option<BulkViscosity>,
}

impl RefinedMpm {
    /// The config's own: cpGIMP, LS-DYNA's bulk viscosity for the slab and
    /// the gas particles' linear term raised to 1.0, which takes the MPM
    /// gas's shock overshoot out (docs/physics/couple/bridge.md, "The
    /// shock's overshoot").
    pub const CONFIG: Self = Self {
        shape: ShapeFunction::CpGimp,
        bulk_viscosity: BulkViscosity::LS_DYNA,
        fluid_bulk_viscosity: Some(BulkViscosity {
            quadratic: 1.5,
            linear: 1.0,
        }),
    };
    /// Seed 001's method: linear shape functions (its eq 16) and LS-DYNA's
    /// default bulk viscosity for every particle.
    pub const SEED: Self = Self {
        shape: ShapeFunction::Linear,
        bulk_viscosity: BulkViscosity::LS_DYNA,
        fluid_bulk_viscosity: None,
    };
    /// cpGIMP with LS-DYNA's default bulk viscosity for every particle.
    pub const CPGIMP_LS_DYNA_Q: Self = Self {
        shape: ShapeFunction::CpGimp,
        bulk_viscosity: BulkViscosity::LS_DYNA,
        fluid_bulk_viscosity: None,
    };

    /// The options by name ("CpGimp, Q 1.5 / 0.06, gas 1.5 / 1.0").
    pub fn name(&self) -> String {
        let v = self.bulk_viscosity;
        let mut name = format!("{:?}, Q {:?} / {:?}", self.shape, v.quadratic, v.linear);
        if let Some(g) = self.fluid_bulk_viscosity {
            name += &format!(", gas {:?} / {:?}", g.quadratic, g.linear);
        }
        name
    }

    /// The run's name after its cell size ("1.0 mm, CpGimp, Q 1.5 / 0.06,
    /// gas 1.5 / 1.0").
    pub fn label(&self, h_mm: f64) -> String {
        format!("{h_mm:.1} mm, {}", self.name())
    }
}

/// The w = 5 bridge (its MPM region from 110 mm, the bridge 10 mm wide)
/// on cells `refine` times finer than the config's 2 mm, to
/// [`REFINED_END`]; its FDM region from the config's own `charge`, remapped
/// onto the finer grid by the run; the MPM region's options `mpm`
/// (docs/physics/couple/bridge.md, "cpGIMP in the MPM region").
pub fn run_refined(root: &Path, refine: usize, mpm: RefinedMpm) -> Result<BridgeRun, String> {
    let label = mpm.label(2.0 / refine as f64);
    let v = mpm.bulk_viscosity;
    let mut tag = format!("h{refine}_{:?}_q{}_{}", mpm.shape, v.quadratic, v.linear);
    if let Some(g) = mpm.fluid_bulk_viscosity {
        tag += &format!("_gas{}_{}", g.quadratic, g.linear);
    }
    bridge_run(root, refined_sets(refine, mpm), false, &tag, label, 5)
}

/// The `--set` overrides of [`run_refined`].
pub fn refined_sets(refine: usize, mpm: RefinedMpm) -> Vec<String> {
    let on = |v: BulkViscosity| format!("(quadratic: {:?}, linear: {:?})", v.quadratic, v.linear);
    vec![
        format!("time.end={REFINED_END:e}"),
        format!("domain.cells=({}, {}, 1)", 170 * refine, 250 * refine),
        format!("pipeline.w=Some({})", 5 * refine),
        format!("pipeline.shape_function={:?}", mpm.shape),
        format!("pipeline.bulk_viscosity=On{}", on(mpm.bulk_viscosity)),
        match mpm.fluid_bulk_viscosity {
            Some(g) => format!("pipeline.fluid_bulk_viscosity=Some{}", on(g)),
            None => "pipeline.fluid_bulk_viscosity=None".to_string(),
        },
        "outputs.interval=1.0".to_string(),
        "outputs.vtk=false".to_string(),
    ]
}

/// Runs `configs/blast2d.ron` with `sets` into `out/xtask_blast2d_{tag}`.
fn bridge_run(
    root: &Path,
    mut sets: Vec<String>,
    paper_inflow: bool,
    tag: &str,
    label: String,
    width: usize,
) -> Result<BridgeRun, String> {
    if paper_inflow {
        sets.push("pipeline.min_particle_mass=0.0".into());
        sets.push("pipeline.inflow_particle_volume=false".into());
        sets.push("pipeline.inflow_deposit=false".into());
    }
    let out = root.join(format!("out/xtask_blast2d_{tag}"));
    let mut r = run_case(root, "configs/blast2d.ron", &sets, &out, label, width)?;
    let time_split = std::fs::read_to_string(out.join("time_split.json")).ok();
    let time_split = time_split.as_deref();
    r.split = time_split.and_then(split_of);
    r.particles = time_split.and_then(particles_of);
    r.activated_at = time_split.and_then(|t| json_number(t, "activated_at"));
    Ok(r)
}

/// The pure-MPM run of the same problem (`configs/blast2d_mpm.ron`) over
/// the same time.
pub fn run_pure_mpm(root: &Path) -> Result<BridgeRun, String> {
    let remap = root.join(REMAP_DIR).join("remap.bin");
    let sets = vec![
        format!("time.end={END_TIME:e}"),
        format!("pipeline.remap.file=Some(\"{}\")", remap.display()),
        "pipeline.remap.charge=None".to_string(),
        "outputs.interval=1.0".to_string(),
    ];
    let out = root.join("out/xtask_blast2d_mpm");
    run_case(
        root,
        "configs/blast2d_mpm.ron",
        &sets,
        &out,
        "pure MPM".into(),
        0,
    )
}

/// Runs `config` (a path under `root`) with `sets` into `out` through the
/// composer's run loop, the process's peak memory reset before it, and
/// reads its two gauges; no bridge figures (`split`, `particles`,
/// `activated_at` are `None`).
fn run_case(
    root: &Path,
    config: &str,
    sets: &[String],
    out: &Path,
    label: String,
    width: usize,
) -> Result<BridgeRun, String> {
    let loaded =
        load_file(&root.join(config), sets).map_err(|e| format!("{config} does not load: {e}"))?;
    let peak = CasePeak::start();
    let summary = run(
        &loaded,
        &RunOptions {
            out_dir: out.to_path_buf(),
            restart: None,
            progress: false,
        },
    )
    .map_err(|e| format!("blast2d {label}: {e}"))?;
    Ok(BridgeRun {
        label,
        width,
        split: None,
        particles: None,
        steps: summary.steps,
        final_time: summary.final_time,
        wall_seconds: summary.wall_seconds,
        peak_resident: peak.bytes(),
        activated_at: None,
        completed: summary.completed,
        stop_reason: summary.stop_reason,
        gauge1: read_gauge(&out.join("gauges/gauge1.csv"))?,
        gauge2: read_gauge(&out.join("gauges/gauge2.csv"))?,
    })
}

/// Oscillation of a gauge after its blast peak: over the samples from
/// [`PEAK_WINDOW`] after the first above twice ambient to the end, the
/// total variation Σ|p_{k+1} − p_k| per µs divided by the blast peak
/// (1/µs), and the share of those samples below half the ambient pressure
/// (an empty cell: the MPM's particles have left it).
pub fn oscillation(h: &History) -> Option<(f64, f64)> {
    let (_, peak) = arrival_and_peak(h)?;
    let first = h.pressure.iter().position(|&p| p > 2.0 * AMBIENT)?;
    let t0 = h.time[first] + PEAK_WINDOW;
    let k0 = h.time.iter().position(|&t| t > t0)?;
    let p = &h.pressure[k0..];
    let span = h.time[h.time.len() - 1] - h.time[k0];
    if p.len() < 2 || span <= 0.0 {
        return None;
    }
    let tv: f64 = p.windows(2).map(|w| (w[1] - w[0]).abs()).sum();
    let empty = p.iter().filter(|&&x| x < 0.5 * AMBIENT).count() as f64 / p.len() as f64;
    Some((tv / (span * 1e6) / peak, empty))
}

/// The pressure at [`GAUGE_RADIUS`] in a 1D cylindrical run of the
/// remap's detonation (seed 001 §4.1: a 50 mm TNT charge, program burn,
/// in air) on `cells` cells to 0.2 m: linear between the two cell centres
/// around it, every step from [`REMAP_TIME`] until the blast has passed
/// (10 µs after it), times after [`REMAP_TIME`].
pub fn reference_1d(cells: usize) -> Result<History, String> {
    let setup = DetonationSetup::tnt_in_air(Symmetry::Cylindrical, 0.05, 0.2, cells);
    let mut run = RadialDetonation::new(setup).map_err(|e| format!("1D reference: {e}"))?;
    let x = GAUGE_RADIUS / run.cell_size() - 0.5;
    let (i, f) = (x.floor() as usize, x - x.floor());
    if !(x >= 0.0) || i + 1 >= cells {
        return Err(format!(
            "1D reference: {cells} cells to 0.2 m have no two cell centres around r = {GAUGE_RADIUS} m"
        ));
    }
    let end = REMAP_TIME + 1.0e-5;
    let mut h = History {
        time: Vec::new(),
        pressure: Vec::new(),
    };
    while run.time() < end {
        let dt = run.stable_dt().min(end - run.time());
        run.step(dt).map_err(|e| format!("1D reference: {e}"))?;
        if run.time() >= REMAP_TIME {
            h.time.push(run.time() - REMAP_TIME);
            h.pressure
                .push((1.0 - f) * run.state(i).2 + f * run.state(i + 1).2);
        }
    }
    Ok(h)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn arrival_is_the_half_rise_and_the_peak_stays_in_its_window() {
        // Ambient until 1 µs, 2·p0 + 4e6 at 2 µs (peak of the front, the
        // window runs to 5 µs), a larger later pulse at 6 µs (outside it).
        let p0 = AMBIENT;
        let h = History {
            time: vec![0.0, 1.0e-6, 2.0e-6, 3.0e-6, 6.0e-6],
            pressure: vec![p0, p0, p0 + 4.0e6, p0 + 1.0e6, p0 + 9.0e6],
        };
        let (t, peak) = arrival_and_peak(&h).unwrap();
        assert_eq!(peak, p0 + 4.0e6);
        // Half-way p0 + 2e6 is reached half-way between 1 and 2 µs.
        assert!((t - 1.5e-6).abs() < 1e-18, "{t}");
        let flat = History {
            time: vec![0.0, 1.0],
            pressure: vec![p0, p0],
        };
        assert!(arrival_and_peak(&flat).is_none());
    }

    #[test]
    fn the_mean_peak_averages_a_ringing_peak_over_its_window() {
        // From 1 µs the pressure rings between p0 + 4e6 and p0 + 2e6 every
        // 0.25 µs, then falls to p0: the best 0.5 µs mean is p0 + 3e6
        // (two trapezoids of mean p0 + 3e6), the plain peak p0 + 4e6.
        let p0 = AMBIENT;
        let h = History {
            time: vec![0.0, 1.0e-6, 1.25e-6, 1.5e-6, 1.75e-6, 2.0e-6, 5.0e-6],
            pressure: vec![p0, p0 + 4.0e6, p0 + 2.0e6, p0 + 4.0e6, p0 + 2.0e6, p0, p0],
        };
        let mean = mean_peak(&h).unwrap();
        assert!((mean - (p0 + 3.0e6)).abs() <= 1e-9 * mean, "{mean}");
        assert_eq!(arrival_and_peak(&h).unwrap().1, p0 + 4.0e6);
        let flat = History {
            time: vec![0.0, 1.0],
            pressure: vec![p0, p0],
        };
        assert!(mean_peak(&flat).is_none());
    }

    #[test]
    fn oscillation_is_the_variation_after_the_peak_window() {
        // Blast at 1 µs (peak p0 + 4e6 inside the 3 µs window), then from
        // 5 µs: p0, 0, p0 + 1e6, p0 over 3 µs.
        let p0 = AMBIENT;
        let h = History {
            time: vec![0.0, 1.0e-6, 2.0e-6, 5.0e-6, 6.0e-6, 7.0e-6, 8.0e-6],
            pressure: vec![p0, p0 + 4.0e6, p0, p0, 0.0, p0 + 1.0e6, p0],
        };
        let (tv, empty) = oscillation(&h).unwrap();
        // Σ|Δp| = p0 + (p0 + 1e6) + 1e6 over 3 µs, over the peak.
        let want = (2.0 * p0 + 2.0e6) / 3.0 / (p0 + 4.0e6);
        assert!((tv - want).abs() < 1e-15, "{tv} {want}");
        assert_eq!(empty, 0.25);
    }

    #[test]
    fn the_split_is_read_from_the_bridges_json() {
        let text = "{\n  \"fdm_seconds\": 1.5,\n  \"mpm_seconds\": 2e-3,\n  \"steps\": 4,\n  \"activated_at\": null\n}\n";
        assert_eq!(json_number(text, "fdm_seconds"), Some(1.5));
        assert_eq!(json_number(text, "mpm_seconds"), Some(2e-3));
        assert_eq!(json_number(text, "steps"), Some(4.0));
        assert_eq!(json_number(text, "activated_at"), None);
        assert_eq!(json_number(text, "wall"), None);
    }

    #[test]
    fn a_gauge_file_is_read_and_a_bad_line_is_named() {
        let dir = std::env::temp_dir().join(format!("brisance_blast2d_{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let good = dir.join("good.csv");
        std::fs::write(&good, "time,pressure\n0,101325\n1e-6,2.5e6\n").unwrap();
        let h = read_gauge(&good).unwrap();
        assert_eq!(h.time, vec![0.0, 1e-6]);
        assert_eq!(h.pressure, vec![101325.0, 2.5e6]);
        let bad = dir.join("bad.csv");
        std::fs::write(&bad, "time,pressure\n0,101325\n1e-6\n").unwrap();
        let e = read_gauge(&bad).unwrap_err();
        assert!(e.contains("bad.csv line 3: expected time,pressure"), "{e}");
        std::fs::write(&bad, "time,pressure\n0,one\n").unwrap();
        let e = read_gauge(&bad).unwrap_err();
        assert!(e.contains("bad.csv line 2: invalid float"), "{e}");
        let e = read_gauge(&dir.join("missing.csv")).unwrap_err();
        assert!(e.starts_with("cannot read "), "{e}");
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn a_run_without_its_config_says_which_config() {
        let root = Path::new("/nonexistent-brisance-root");
        let e = run_bridge(root, 5, false).unwrap_err();
        assert!(e.starts_with("configs/blast2d.ron does not load"), "{e}");
        let e = run_pure_mpm(root).unwrap_err();
        assert!(
            e.starts_with("configs/blast2d_mpm.ron does not load"),
            "{e}"
        );
    }

    /// The MPM options a loaded bridge or pure-MPM config holds.
    fn mpm_options(loaded: &brisance_compose::LoadedScenario) -> RefinedMpm {
        let pipeline = &loaded.scenario.pipeline;
        let (shape, viscosity, fluid) =
            if let Some(b) = pipeline.section::<brisance_couple::BridgeConfig>() {
                (
                    b.shape_function,
                    b.bulk_viscosity.option(),
                    b.fluid_bulk_viscosity,
                )
            } else if let Some(m) = pipeline.section::<brisance_couple::MpmConfig>() {
                (
                    m.shape_function,
                    m.bulk_viscosity.option(),
                    m.fluid_bulk_viscosity,
                )
            } else {
                panic!("neither a bridge nor MPM");
            };
        RefinedMpm {
            shape,
            bulk_viscosity: viscosity.expect("bulk viscosity on"),
            fluid_bulk_viscosity: fluid,
        }
    }

    #[test]
    fn the_configs_hold_the_reports_mpm_options() {
        // The report's rows of configs/blast2d.ron and blast2d_mpm.ron
        // are said to run `RefinedMpm::CONFIG`.
        let root = crate::bridge_blast::workspace_root();
        for config in ["configs/blast2d.ron", "configs/blast2d_mpm.ron"] {
            let loaded = load_file(&root.join(config), &[]).expect("loads");
            assert_eq!(mpm_options(&loaded), RefinedMpm::CONFIG, "{config}");
        }
    }

    #[test]
    fn the_refined_runs_load_with_either_shape_and_ugimp_is_refused() {
        let config = crate::bridge_blast::workspace_root().join("configs/blast2d.ron");
        for mpm in [
            RefinedMpm::CONFIG,
            RefinedMpm::SEED,
            RefinedMpm::CPGIMP_LS_DYNA_Q,
        ] {
            let loaded = load_file(&config, &refined_sets(2, mpm)).expect("loads");
            assert_eq!(loaded.scenario.domain.cells, [340, 500, 1]);
            assert_eq!(mpm_options(&loaded), mpm);
        }
        assert_eq!(RefinedMpm::SEED.label(1.0), "1.0 mm, Linear, Q 1.5 / 0.06");
        assert_eq!(RefinedMpm::CPGIMP_LS_DYNA_Q.name(), "CpGimp, Q 1.5 / 0.06");
        assert_eq!(
            RefinedMpm::CONFIG.label(0.5),
            "0.5 mm, CpGimp, Q 1.5 / 0.06, gas 1.5 / 1.0"
        );
        let ugimp = RefinedMpm {
            shape: ShapeFunction::Gimp,
            ..RefinedMpm::SEED
        };
        let e = load_file(&config, &refined_sets(2, ugimp)).unwrap_err();
        assert!(e.to_string().contains("pipeline.shape_function"), "{e}");
    }

    #[test]
    fn a_reference_too_coarse_for_its_gauge_is_refused() {
        for cells in [0, 1] {
            assert!(reference_1d(cells).is_err(), "{cells} cells");
        }
        let e = reference_1d(1).unwrap_err();
        assert!(e.starts_with("1D reference: "), "{e}");
    }
}
