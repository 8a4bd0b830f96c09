//! E-COOKOFF: the fast cook-off of seed 000 §5.3 on (r, z) rings
//! (configs/cookoff_rz.ron): a 4340 steel container of PBX-9501 particles
//! whose whole explosive surface lights at once, run at the cell sizes of
//! `BRISANCE_COOKOFF_H` (mm, comma-separated; default 2, 1, 0.5) to the
//! seed's last frame (0.312 ms) or until the run stops. Each run records
//! the pressure inside, the burnt fraction, the mid-wall hoop strain, the
//! first failed steel particle (rupture), the products outside the
//! container (venting), the hottest products in it, the closure of mass
//! and energy and the wall time; particle frames are drawn at the seed's
//! times (Fig. 6) that the run reached, and at the last step.
//!
//! The case is chaotic at these grids (a 1 mK change of the steel's start
//! moves the burnt fraction at the end by points), so E-COOKOFF-ENSEMBLE
//! ([`e_cookoff_ensemble`]) runs it as ensembles: at each h of
//! `BRISANCE_COOKOFF_ENSEMBLE_H` (default 2, 1), `BRISANCE_COOKOFF_MEMBERS`
//! runs (default [`MEMBERS`]), member k with the steel started k mK
//! warmer, and reports the figures at the end as the members' mean,
//! standard deviation and range.

use std::collections::BTreeSet;
use std::fmt::Write as _;
use std::path::Path;
use std::time::Instant;

use anyhow::{anyhow, Result};
use brisance::compose::build::build_section;
use brisance::compose::load_str;
use brisance::core::Solver;
use brisance::couple::IceMpm;

use crate::plot::{plot_panels, Panel, Series, SeriesStyle};
use crate::Report;

/// The seed's frame times (Fig. 6), s.
const FRAMES: [f64; 5] = [0.0, 1.37e-4, 2.03e-4, 2.59e-4, 3.12e-4];
/// The container: inner radius and half-length, outer radius and
/// half-length, m (configs/cookoff_rz.ron).
const INNER: f64 = 0.0508;
const OUTER: f64 = 0.05715;
/// Mid-wall particles: within this distance of the mid-plane, m.
const MID: f64 = 0.005;
/// Wall-time bound of one run, s: the 20 minutes at h = 0.5 mm
/// (`BRISANCE_COOKOFF_BUDGET` sets another).
const BUDGET_S: f64 = 1200.0;
/// How often the cell fields are read for venting and the hottest
/// products, s of simulated time.
const FIELD_EVERY: f64 = 1e-6;
/// Volume share above which the products count as present in a cell.
const PRESENT: f64 = 1e-4;
/// Members of the ensemble at each h (`BRISANCE_COOKOFF_MEMBERS` sets
/// another; 1 runs none but the plain run).
const MEMBERS: usize = 4;
/// How much warmer member k's steel starts than the scenario's: k times
/// this, K.
const WARMER: f64 = 1.0e-3;

/// One sample of the record.
#[derive(Clone, Copy)]
struct Sample {
    t: f64,
    /// Cell pressure just inside the wall at the mid-plane, Pa.
    p_wall: f64,
    /// Cell pressure on the axis at the mid-plane, Pa.
    p_centre: f64,
    /// Burnt share of the explosive's mass.
    burnt: f64,
    /// Mid-wall hoop strain, mean r / mean r₀ − 1.
    hoop: f64,
    /// Failed steel particles.
    failed: usize,
}

/// One h's curves: label, time, pressure, burnt fraction, hoop strain.
type Curves = (String, Vec<f64>, Vec<f64>, Vec<f64>, Vec<f64>);

/// One h.
struct Run {
    h: f64,
    record: Vec<Sample>,
    /// First failed steel particle: time, s, and where it started (r, z), m.
    rupture: Option<(f64, [f64; 2])>,
    /// Products mass outside the container at the end, kg per radian.
    vented: f64,
    /// Hottest products (θ > [`PRESENT`]) seen, K, time and cell centre.
    hottest: (f64, f64, [f64; 2]),
    /// Largest |M(t)/M(0) − 1| and |E(t)/E(0) − 1| seen.
    mass: f64,
    energy: f64,
    frames: Vec<String>,
    steps: usize,
    wall_s: f64,
    stop: Option<String>,
}

/// What E-COOKOFF's plain runs ended with, for E-COOKOFF-ENSEMBLE's
/// member 0 when both cases run in one `cargo xtask validate` (the same
/// run: it is not run twice).
#[derive(Default)]
pub(crate) struct PlainRuns(Vec<End>);

/// What one run of an ensemble ended with.
#[derive(Clone, Copy)]
struct End {
    h: f64,
    /// Time reached, s, and whether that is the end time.
    t: f64,
    finished: bool,
    burnt: f64,
    /// Pressure inside the wall at mid-height at the end, Pa.
    p_wall: f64,
    /// First rupture, s.
    rupture: Option<f64>,
    wall_s: f64,
}

impl End {
    fn of(r: &Run) -> Self {
        let last = r.record.last().copied();
        Self {
            h: r.h,
            t: last.map_or(0.0, |s| s.t),
            finished: r.stop.is_none(),
            burnt: last.map_or(f64::NAN, |s| s.burnt),
            p_wall: last.map_or(f64::NAN, |s| s.p_wall),
            rupture: r.rupture.map(|(t, _)| t),
            wall_s: r.wall_s,
        }
    }
}

/// Mean, sample standard deviation (0 for one value), least and greatest
/// of `x`.
fn spread(x: &[f64]) -> (f64, f64, f64, f64) {
    let n = x.len() as f64;
    let mean = x.iter().sum::<f64>() / n;
    let sd = if x.len() > 1 {
        (x.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (n - 1.0)).sqrt()
    } else {
        0.0
    };
    let lo = x.iter().copied().fold(f64::INFINITY, f64::min);
    let hi = x.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    (mean, sd, lo, hi)
}

/// "mean ± sd (lo–hi)" of `x` scaled by `scale`, with `d` decimals.
fn spread_text(x: &[f64], scale: f64, d: usize) -> String {
    let (m, sd, lo, hi) = spread(x);
    if x.len() == 1 {
        return format!("{:.d$} (one run)", m * scale);
    }
    format!(
        "{:.d$} ± {:.d$} ({:.d$}–{:.d$})",
        m * scale,
        sd * scale,
        lo * scale,
        hi * scale
    )
}

/// Draws the particles of `s` in the (r, z) plane into `path`: steel, the
/// explosive and the steel failed since the start.
fn frame(s: &IceMpm, steel: u16, failed0: &BTreeSet<u32>, path: &Path, title: &str) -> Result<()> {
    let ps = s.mpm().particles();
    let (mut sr, mut sz, mut er, mut ez, mut fr, mut fz) = (
        Vec::new(),
        Vec::new(),
        Vec::new(),
        Vec::new(),
        Vec::new(),
        Vec::new(),
    );
    let ids = s.mpm().particle_ids();
    for (p, id) in ids.iter().enumerate() {
        let (r, z) = (ps.position[p][0] * 1e3, ps.position[p][1] * 1e3);
        if ps.material[p].0 != steel {
            er.push(r);
            ez.push(z);
        } else if ps.failed[p] && !failed0.contains(id) {
            fr.push(r);
            fz.push(z);
        } else {
            sr.push(r);
            sz.push(z);
        }
    }
    let mut series = vec![
        Series {
            label: "steel",
            x: &sr,
            y: &sz,
            style: SeriesStyle::Points,
        },
        Series {
            label: "PBX-9501",
            x: &er,
            y: &ez,
            style: SeriesStyle::Points,
        },
    ];
    if !fr.is_empty() {
        series.push(Series {
            label: "failed steel",
            x: &fr,
            y: &fz,
            style: SeriesStyle::Points,
        });
    }
    plot_panels(
        path,
        title,
        "r [mm]",
        &[Panel {
            y_label: "z [mm]",
            series,
        }],
    )
}

/// Runs configs/cookoff_rz.ron at cell size `h`.
/// One run at cell size `h` (m) with the steel started `warmer` K above
/// the scenario's temperature, stopped after `budget_s` s of wall time;
/// particle frames into `img` where given.
fn cookoff_run(h: f64, budget_s: f64, img: Option<&Path>, warmer: f64) -> Result<Run> {
    let text = include_str!("../../configs/cookoff_rz.ron");
    let n = (0.09 / h).round() as usize;
    let sets = [format!("domain.cells=({n},{n},1)")];
    let mut loaded = load_str("cookoff_rz.ron", text, &sets)
        .map_err(|e| anyhow!("configs/cookoff_rz.ron: {e}"))?;
    if warmer != 0.0 {
        let mut warmed = 0;
        for region in loaded.scenario.initial.iter_mut() {
            if let (true, Some(t)) = (region.material == "steel", region.state.temperature) {
                region.state.temperature = Some(t + warmer);
                warmed += 1;
            }
        }
        if warmed == 0 {
            return Err(anyhow!(
                "configs/cookoff_rz.ron: no `steel` initial region gives a temperature to start warmer"
            ));
        }
    }
    let s = &loaded.scenario;
    let t_end = s.time.end;
    let Some(section) = s.pipeline.section::<brisance::couple::IceMpmConfig>() else {
        return Err(anyhow!("configs/cookoff_rz.ron is not an IceMpm pipeline"));
    };
    let mut solver = build_section(section, s).map_err(|e| anyhow!("{e}"))?;
    let ps = solver.mpm().particles();
    // The explosive is the material of the particle nearest the origin;
    // the other is the steel.
    let nearest = (0..ps.len())
        .min_by(|&a, &b| {
            let d = |p: usize| ps.position[p][0].hypot(ps.position[p][1]);
            d(a).total_cmp(&d(b))
        })
        .ok_or_else(|| anyhow!("no particles"))?;
    let pbx = ps.material[nearest].0;
    let steel = (0..ps.len())
        .map(|p| ps.material[p].0)
        .find(|&m| m != pbx)
        .ok_or_else(|| anyhow!("no steel particles"))?;
    let ids = solver.mpm().particle_ids();
    // Particles the library's Gaussian initial damage already marks failed
    // are not a rupture.
    let failed0: BTreeSet<u32> = (0..ps.len())
        .filter(|&p| ps.failed[p])
        .map(|p| ids[p])
        .collect();
    let mid: BTreeSet<u32> = (0..ps.len())
        .filter(|&p| {
            ps.material[p].0 == steel && ps.position[p][1] < MID && ps.position[p][0] < OUTER
        })
        .map(|p| ids[p])
        .collect();
    let mid_r = |m: &brisance::mpm::MpmSolver| -> f64 {
        let (ps, ids) = (m.particles(), m.particle_ids());
        let (mut sum, mut w) = (0.0, 0.0);
        for (p, id) in ids.iter().enumerate() {
            if mid.contains(id) {
                sum += ps.mass[p] * ps.position[p][0];
                w += ps.mass[p];
            }
        }
        sum / w
    };
    let pbx_mass = |m: &brisance::mpm::MpmSolver| -> f64 {
        let ps = m.particles();
        (0..ps.len())
            .filter(|&p| ps.material[p].0 == pbx)
            .map(|p| ps.mass[p])
            .sum()
    };
    let (r0, m0) = (mid_r(solver.mpm()), pbx_mass(solver.mpm()));
    let t0 = solver.conservation_totals();
    let fields = ["pressure".to_string()];
    let cell_fields = [
        "volume_fraction_1".to_string(),
        "density_1".to_string(),
        "temperature_1".to_string(),
    ];
    let mut sample = Vec::new();
    let mut run = Run {
        h,
        record: Vec::new(),
        rupture: None,
        vented: 0.0,
        hottest: (0.0, 0.0, [0.0; 2]),
        mass: 0.0,
        energy: 0.0,
        frames: Vec::new(),
        steps: 0,
        wall_s: 0.0,
        stop: None,
    };
    let label = |t: f64| format!("{:.3}", t * 1e3);
    // A frame into img/e_cookoff_<name>.png; its file name (none without
    // `img`).
    let draw = |s: &IceMpm, name: &str, title: &str| -> Result<Option<String>> {
        let Some(img) = img else { return Ok(None) };
        let file = format!("e_cookoff_{name}.png");
        let title = format!("E-COOKOFF r-z, {title}");
        frame(s, steel, &failed0, &img.join(&file), &title)?;
        Ok(Some(file))
    };
    let mut next_frame = 0usize;
    let mut next_fields = 0.0;
    let start = Instant::now();
    loop {
        let t = solver.time();
        // Frames at the seed's times the run has reached.
        while next_frame < FRAMES.len() && t >= FRAMES[next_frame] * (1.0 - 1e-9) {
            let name = format!("{}mm_{}ms", h * 1e3, label(FRAMES[next_frame]));
            let title = format!("h = {} mm, t = {} ms (seed 000 fig. 6)", h * 1e3, label(t));
            run.frames.extend(draw(&solver, &name, &title)?);
            next_frame += 1;
        }
        // The record.
        solver.sample([INNER - 0.5 * h, 0.5 * h, 0.5e-3], &fields, &mut sample)?;
        let p_wall = sample[0];
        solver.sample([0.5 * h, 0.5 * h, 0.5e-3], &fields, &mut sample)?;
        let p_centre = sample[0];
        let ps = solver.mpm().particles();
        let ids = solver.mpm().particle_ids();
        let failed = (0..ps.len())
            .filter(|&p| ps.material[p].0 == steel && ps.failed[p] && !failed0.contains(&ids[p]))
            .count();
        if failed > 0 && run.rupture.is_none() {
            let p = (0..ps.len())
                .find(|&p| ps.material[p].0 == steel && ps.failed[p] && !failed0.contains(&ids[p]))
                .unwrap_or(0);
            run.rupture = Some((t, [ps.position[p][0], ps.position[p][1]]));
        }
        run.record.push(Sample {
            t,
            p_wall,
            p_centre,
            burnt: 1.0 - pbx_mass(solver.mpm()) / m0,
            hoop: mid_r(solver.mpm()) / r0 - 1.0,
            failed,
        });
        let totals = solver.conservation_totals();
        run.mass = run.mass.max((totals.mass / t0.mass - 1.0).abs());
        let de = (totals.energy / t0.energy - 1.0).abs();
        if !(de <= run.energy) {
            run.energy = de;
        }
        // Venting and the hottest products.
        if t >= next_fields {
            let data = solver.cell_data(&cell_fields)?;
            let g = &data.geometry;
            let (theta, rho, temp) = (
                data.field("volume_fraction_1").unwrap_or(&[]),
                data.field("density_1").unwrap_or(&[]),
                data.field("temperature_1").unwrap_or(&[]),
            );
            let (dr, dz) = (g.spacing[0], g.spacing[1]);
            let nr = g.cells[0];
            let mut vented = 0.0;
            for c in 0..theta.len() {
                let (i, j) = (c % nr, c / nr);
                let (r, z) = ((i as f64 + 0.5) * dr, (j as f64 + 0.5) * dz);
                if r > OUTER || z > OUTER {
                    vented += theta[c] * rho[c] * r * dr * dz;
                } else if theta[c] > PRESENT && temp[c] > run.hottest.0 {
                    run.hottest = (temp[c], t, [r, z]);
                }
            }
            run.vented = vented;
            next_fields = t + FIELD_EVERY;
        }
        if t >= t_end * (1.0 - 1e-12) {
            break;
        }
        if start.elapsed().as_secs_f64() > budget_s {
            run.stop = Some(format!(
                "the wall-time budget of {budget_s:.0} s was spent at t = {:.2} µs",
                t * 1e6
            ));
            break;
        }
        let step = solver
            .stable_dt()
            .and_then(|dt| solver.advance(dt.min(t_end - t)));
        if let Err(e) = step {
            run.stop = Some(e.to_string());
            break;
        }
        run.steps += 1;
        if run.steps.is_multiple_of(2000) {
            println!(
                "    h {:.2} mm{}: step {}, t = {:.2} µs, {:.0} s",
                h * 1e3,
                if warmer != 0.0 {
                    format!(" (steel {:.0} mK warmer)", warmer * 1e3)
                } else {
                    String::new()
                },
                run.steps,
                solver.time() * 1e6,
                start.elapsed().as_secs_f64()
            );
        }
    }
    run.wall_s = start.elapsed().as_secs_f64();
    // The state the run ended in.
    if run.stop.is_some() {
        let name = format!("{}mm_stop", h * 1e3);
        let title = format!(
            "h = {} mm: the last step, t = {:.2} µs",
            h * 1e3,
            solver.time() * 1e6
        );
        run.frames.extend(draw(&solver, &name, &title)?);
    }
    Ok(run)
}

/// The first part of a stop message, for the table.
fn short(stop: &str) -> String {
    let first = stop.split(": the fastest").next().unwrap_or(stop);
    let first = first.split("; cell state").next().unwrap_or(first);
    first.chars().take(240).collect()
}

/// The last mid-wall hoop strain of a record: the last finite one, with
/// its time where the mid-wall particles left the domain after it (their
/// mean radius is then undefined), or "—" where there is none.
fn hoop_text(record: &[Sample]) -> String {
    let last_t = record.last().map_or(0.0, |s| s.t);
    record
        .iter()
        .rev()
        .find(|s| s.hoop.is_finite())
        .map_or("—".into(), |s| {
            if s.t < last_t {
                format!(
                    "{:+.3e} (at {:.1} µs; then out of the domain)",
                    s.hoop,
                    s.t * 1e6
                )
            } else {
                format!("{:+.3e}", s.hoop)
            }
        })
}

pub(crate) fn e_cookoff(report: &mut Report, img: &Path) -> Result<PlainRuns> {
    println!("E-COOKOFF: fast cook-off of a steel container of PBX-9501 (configs/cookoff_rz.ron)");
    let hs = crate::env_cell_sizes("BRISANCE_COOKOFF_H", "2,1,0.5")?;
    let budget_s = crate::env_seconds("BRISANCE_COOKOFF_BUDGET", BUDGET_S)?;
    let mut runs = Vec::new();
    for &h in &hs {
        let r = cookoff_run(h, budget_s, Some(img), 0.0)?;
        let last = r.record.last().copied();
        println!(
            "  h {:.2} mm: {} steps in {:.0} s to t = {:.2} µs; p wall {:.3e} Pa, burnt {:.3e}, hoop {}, failed {}, vented {:.3e} kg/rad, hottest products {:.3e} K; stop {:?}",
            h * 1e3,
            r.steps,
            r.wall_s,
            last.map_or(0.0, |s| s.t * 1e6),
            last.map_or(f64::NAN, |s| s.p_wall),
            last.map_or(f64::NAN, |s| s.burnt),
            hoop_text(&r.record),
            last.map_or(0, |s| s.failed),
            r.vented,
            r.hottest.0,
            r.stop
        );
        runs.push(r);
    }
    // Pressure, burnt fraction and hoop strain against time, one curve per h.
    let png = img.join("e_cookoff.png");
    let t_max = runs
        .iter()
        .filter_map(|r| r.record.last().map(|s| s.t))
        .fold(0.0, f64::max);
    let (scale, unit) = crate::plot::time_unit(t_max.max(1e-9));
    let cols: Vec<Curves> = runs
        .iter()
        .map(|r| {
            (
                format!("h = {} mm", r.h * 1e3),
                r.record.iter().map(|s| s.t * scale).collect(),
                r.record.iter().map(|s| s.p_wall / 1e6).collect(),
                r.record.iter().map(|s| s.burnt).collect(),
                r.record.iter().map(|s| s.hoop).collect(),
            )
        })
        .collect();
    let panel = |k: usize, y_label: &'static str| Panel {
        y_label,
        series: cols
            .iter()
            .map(|c| Series {
                label: &c.0,
                x: &c.1,
                y: match k {
                    0 => &c.2,
                    1 => &c.3,
                    _ => &c.4,
                },
                style: SeriesStyle::Line,
            })
            .collect(),
    };
    plot_panels(
        &png,
        "E-COOKOFF r-z: inside the wall at mid-height, burnt fraction, mid-wall hoop strain",
        &format!("t [{unit}]"),
        &[
            panel(0, "pressure [MPa]"),
            panel(1, "burnt fraction"),
            panel(2, "hoop strain"),
        ],
    )?;
    let md = &mut report.md;
    let _ = writeln!(
        md,
        "## E-COOKOFF — fast cook-off of a steel container of PBX-9501, IceMpm on (r, z) rings (seed 000 §5.3)\n"
    );
    let _ = writeln!(
        md,
        "configs/cookoff_rz.ron: the seed's container (4340 steel, `steel_4340_cookoff`: inner diameter and \
         length 10.16 cm, wall and end caps 0.635 cm) filled with PBX-9501 particles (`pbx_9501_reactant`: \
         ViscoSCRAM, Murnaghan pressure), air outside, the steel at 451 K (1 K above the deflagration's \
         ignition temperature), D = A pⁿ with `Deflagration::pbx_9501`'s A and n on the surface the \
         `gradient` area estimate gives (a particle reactant's default) into JWL products \
         (`pbx_9501`, heat of reaction E₀/ρ₀ = 5.54 MJ/kg); r and z to 9 cm (the seed's domain), the \
         mid-plane a symmetry plane, zero-gradient outflow outside; to the seed's last frame, 0.312 ms. \
         Recorded every step: the cell pressure just inside the wall at the mid-plane, the burnt share of \
         the explosive's mass, the mid-wall hoop strain (mass-weighted mean radius of the steel particles \
         within {MID} m of the mid-plane over its start), steel particles failed (TEPLA-F, Johnson–Cook, \
         the stability checks; those the initial damage already fails are not counted); every µs: products \
         mass outside the container (venting, per radian) and the hottest products (θ > {PRESENT}) inside. \
         The seed calls its run a prediction (its Fig. 6: first venting where the side meets the end cap by \
         0.203 ms, a second opening at mid-height by 0.312 ms). Each run stops at the wall-time budget \
         (`BRISANCE_COOKOFF_BUDGET`, s; default the target's {BUDGET_S:.0}); `BRISANCE_COOKOFF_H` sets the \
         cell sizes (mm). Wall times on 2 cores shared with other work.\n"
    );
    let _ = writeln!(
        md,
        "| h (mm) | rings | steps | reached (µs) | p inside wall (MPa) | p on axis (MPa) | burnt | hoop strain | first rupture | vented (kg/rad) | hottest products | mass / energy closure (max) | wall time | stop |\n\
         |---:|---:|---:|---:|---:|---:|---:|---:|---|---:|---|---:|---:|---|"
    );
    for r in &runs {
        let Some(last) = r.record.last() else {
            continue;
        };
        let _ = writeln!(
            md,
            "| {} | {} | {} | {:.2} | {:.3} | {:.3} | {:.3e} | {} | {} | {:.3e} | {:.3e} K at {:.2} µs, (r, z) = ({:.1}, {:.1}) mm | {:.1e} / {:.1e} | {:.0} s | {} |",
            r.h * 1e3,
            (0.09 / r.h).round().powi(2),
            r.steps,
            last.t * 1e6,
            last.p_wall / 1e6,
            last.p_centre / 1e6,
            last.burnt,
            hoop_text(&r.record),
            r.rupture.map_or("none".into(), |(t, x)| format!(
                "{:.2} µs at (r, z) = ({:.1}, {:.1}) mm",
                t * 1e6,
                x[0] * 1e3,
                x[1] * 1e3
            )),
            r.vented,
            r.hottest.0,
            r.hottest.1 * 1e6,
            r.hottest.2[0] * 1e3,
            r.hottest.2[1] * 1e3,
            r.mass,
            r.energy,
            r.wall_s,
            r.stop.as_deref().map_or("reached the end".into(), short)
        );
    }
    let _ = writeln!(md, "\n![E-COOKOFF](img/e_cookoff.png)\n");
    for r in &runs {
        let links: Vec<String> = r
            .frames
            .iter()
            .map(|f| {
                format!(
                    "[{}](img/{f})",
                    f.trim_start_matches("e_cookoff_").trim_end_matches(".png")
                )
            })
            .collect();
        let _ = writeln!(md, "Frames, h = {} mm: {}.\n", r.h * 1e3, links.join(", "));
    }
    let _ = writeln!(
        md,
        "| figure | measured | target | verdict |\n|---|---:|---|---|"
    );
    for r in &runs {
        let reached = r.record.last().map_or(0.0, |s| s.t);
        report.target(
            &format!("E-COOKOFF h = {} mm reaches the seed's 0.312 ms", r.h * 1e3),
            format!("{:.2} µs", reached * 1e6),
            "312 µs",
            r.stop.is_none(),
        );
        report.target(
            &format!("E-COOKOFF h = {} mm mass closure (max)", r.h * 1e3),
            format!("{:.1e}", r.mass),
            "≤ 1e-12",
            r.mass <= 1e-12,
        );
    }
    if let Some(r) = runs.iter().find(|r| (r.h - 5e-4).abs() < 1e-9) {
        report.target(
            "E-COOKOFF h = 0.5 mm through rupture: wall time",
            format!("{:.0} s", r.wall_s),
            "≤ 1200 s, ruptured",
            r.stop.is_none() && r.rupture.is_some() && r.wall_s <= BUDGET_S,
        );
    }
    let _ = writeln!(report.md);
    Ok(PlainRuns(runs.iter().map(End::of).collect()))
}

/// E-COOKOFF-ENSEMBLE: E-COOKOFF at the cell sizes of
/// `BRISANCE_COOKOFF_ENSEMBLE_H` (mm; default 2, 1), each as an ensemble of
/// `BRISANCE_COOKOFF_MEMBERS` runs (default [`MEMBERS`]), member k with the
/// steel started k·[`WARMER`] warmer: the figures at the end as the
/// members' mean, standard deviation and range, and the mean burnt
/// fraction's change in h against its standard error.
pub(crate) fn e_cookoff_ensemble(report: &mut Report, plain: &PlainRuns) -> Result<()> {
    println!("E-COOKOFF-ENSEMBLE: the cook-off as ensembles of runs a few mK apart");
    let hs = crate::env_cell_sizes("BRISANCE_COOKOFF_ENSEMBLE_H", "2,1")?;
    let budget_s = crate::env_seconds("BRISANCE_COOKOFF_BUDGET", BUDGET_S)?;
    let members = match std::env::var("BRISANCE_COOKOFF_MEMBERS") {
        Ok(v) => v
            .trim()
            .parse::<usize>()
            .map_err(|e| anyhow!("BRISANCE_COOKOFF_MEMBERS: {e}"))?
            .max(1),
        Err(_) => MEMBERS,
    };
    let mut ensembles: Vec<Vec<End>> = Vec::new();
    for &h in &hs {
        let mut ends = Vec::new();
        for k in 0..members {
            let same = plain.0.iter().find(|e| (e.h - h).abs() <= 1e-9 * h);
            if let (0, Some(&end)) = (k, same) {
                println!("  h {:.2} mm, member 0: E-COOKOFF's run", h * 1e3);
                ends.push(end);
                continue;
            }
            let m = cookoff_run(h, budget_s, None, k as f64 * WARMER)?;
            let end = End::of(&m);
            println!(
                "  h {:.2} mm, steel {} mK warmer: {} steps, {:.0} s, t = {:.2} µs, burnt {:.4}, p wall {:.3e} Pa",
                h * 1e3,
                k,
                m.steps,
                m.wall_s,
                end.t * 1e6,
                end.burnt,
                end.p_wall
            );
            ends.push(end);
        }
        ensembles.push(ends);
    }
    let md = &mut report.md;
    let _ = writeln!(
        md,
        "## E-COOKOFF-ENSEMBLE — the cook-off's figures at the end over runs a few mK apart\n"
    );
    let mut changes = Vec::new();
    let _ = writeln!(
        md,
        "E-COOKOFF's figures at the end move by points under a change of the start far below any that \
         an experiment controls (docs/physics/couple/cookoff.md), so a figure at one h is a sample. Here the \
         case is run {members} times at each h (`BRISANCE_COOKOFF_ENSEMBLE_H`, mm; \
         `BRISANCE_COOKOFF_MEMBERS`), member k with the steel (wall and cap) started k mK warmer than the \
         scenario's 451 K (member 0 is E-COOKOFF's run), each with E-COOKOFF's wall-time budget. Mean ± \
         sample standard deviation (least–greatest) over the members that reached the end time; the \
         figure of merit is the mean burnt fraction at the end, converged in h when its change between \
         successive h is within two standard errors of that change. Wall times on 2 cores, one member at \
         a time.\n"
    );
    let _ = writeln!(
        md,
        "| h (mm) | members at the end time | burnt at the end | p inside wall at the end (MPa) | first rupture (µs) | wall time a member (s) |\n\
         |---:|---:|---|---|---|---|"
    );
    // Per h: (h, mean, sd, members at the end, members run).
    let mut means = Vec::new();
    for ends in &ensembles {
        let done: Vec<&End> = ends.iter().filter(|e| e.finished).collect();
        let col = |f: fn(&End) -> f64| done.iter().map(|e| f(e)).collect::<Vec<f64>>();
        let burnt = col(|e| e.burnt);
        let ruptures: Vec<f64> = done.iter().filter_map(|e| e.rupture).collect();
        let walls: Vec<f64> = ends.iter().map(|e| e.wall_s).collect();
        let h = ends[0].h;
        if done.is_empty() {
            means.push((h, f64::NAN, f64::NAN, 0, ends.len()));
            let _ = writeln!(
                md,
                "| {} | 0 of {} | — | — | — | {} |",
                h * 1e3,
                ends.len(),
                spread_text(&walls, 1.0, 0)
            );
            continue;
        }
        let _ = writeln!(
            md,
            "| {} | {} of {} | {} | {} | {} | {} |",
            h * 1e3,
            done.len(),
            ends.len(),
            spread_text(&burnt, 1.0, 3),
            spread_text(&col(|e| e.p_wall), 1e-6, 1),
            if ruptures.is_empty() {
                "none".to_string()
            } else {
                spread_text(&ruptures, 1e6, 2)
            },
            spread_text(&walls, 1.0, 0)
        );
        let (m, sd, ..) = spread(&burnt);
        means.push((h, m, sd, burnt.len(), ends.len()));
    }
    let _ = writeln!(md);
    // Successive h in the order run; a pair is judged only when both
    // have two members or more at the end time (a sample standard
    // deviation needs two).
    for w in means.windows(2) {
        let ((h0, m0, s0, n0, r0), (h1, m1, s1, n1, r1)) = (w[0], w[1]);
        let pair = format!("{} → {} mm", h0 * 1e3, h1 * 1e3);
        if n0 < 2 || n1 < 2 {
            let _ = writeln!(
                md,
                "Mean burnt fraction {pair}: not judged, {n0} of {r0} and {n1} of {r1} members reached the end time (two or more needed at each h).\n"
            );
            changes.push((pair, None));
            continue;
        }
        let se = (s0 * s0 / n0 as f64 + s1 * s1 / n1 as f64).sqrt();
        let how_many = if se > 0.0 {
            format!("{:.1} standard errors", (m1 - m0).abs() / se)
        } else {
            "the members did not spread at all: the perturbation moved nothing".to_string()
        };
        let _ = writeln!(
            md,
            "Mean burnt fraction from {} to {} mm: {:+.3}, against a standard error of the difference of {:.3} ({how_many}).\n",
            h0 * 1e3,
            h1 * 1e3,
            m1 - m0,
            se,
        );
        changes.push((pair, Some((m1 - m0, se))));
    }
    if means.len() < 2 {
        changes.push(("(one h only)".into(), None));
    }
    let _ = writeln!(
        md,
        "| figure | measured | target | verdict |\n|---|---:|---|---|"
    );
    for (pair, judged) in changes {
        let name = format!("E-COOKOFF-ENSEMBLE mean burnt fraction, {pair}");
        match judged {
            Some((change, se)) => report.target(
                &name,
                format!("{change:+.3} (standard error {se:.3})"),
                "within 2 standard errors",
                change.abs() <= 2.0 * se,
            ),
            None => report.target(
                &name,
                "not judged (too few members at the end, or one h)".into(),
                "within 2 standard errors",
                false,
            ),
        }
    }
    let _ = writeln!(report.md);
    Ok(())
}
