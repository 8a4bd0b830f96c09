//! E-COOKOFF: the fast cook-off of seed 000 §5.3 on (r, z) rings
//! (configs/cookoff_rz.ron): a 4340 steel container of PBX-9501 particles
//! whose whole explosive surface lights at once, run at the cell sizes of
//! `BRISANCE_COOKOFF_H` (mm, comma-separated; default 2, 1, 0.5) to the
//! seed's last frame (0.312 ms) or until the run stops. The run and its
//! record (pressure inside, burnt fraction, mid-wall hoop strain, first
//! failed steel particle, venting, hottest products, closure of mass and
//! energy, wall time) are `brisance::verification::cookoff::cookoff_run`;
//! this driver draws its particle frames at the seed's times (Fig. 6) that
//! the run reached and at the last step, and writes the report's tables.
//!
//! The case is chaotic at these grids (a 1 mK change of the steel's start
//! moves the burnt fraction at the end by points), so E-COOKOFF-ENSEMBLE
//! ([`e_cookoff_ensemble`]) runs it as ensembles: at each h of
//! `BRISANCE_COOKOFF_ENSEMBLE_H` (default 2, 1), `BRISANCE_COOKOFF_MEMBERS`
//! runs (default [`MEMBERS`]), member k with the steel started k mK
//! warmer, and reports the figures at the end as the members' mean,
//! standard deviation and range.

use std::fmt::Write as _;
use std::path::Path;

use anyhow::{anyhow, Result};
use brisance::verification::cookoff::{
    cookoff_run, mm, spread, CookoffFrame, CookoffGrid, CookoffRun, CookoffSample, CookoffSetup,
    MID, PRESENT,
};

use crate::plot::{plot_panels, Panel, Series, SeriesStyle};
use crate::Report;

/// The wall-time budget a run has, s: E-COOKOFF's 20 minutes at
/// h = 0.5 mm (`BRISANCE_COOKOFF_BUDGET` sets another).
const BUDGET_S: f64 = 1200.0;
/// The wall-time budget of each run of E-COOKOFF-EIGHTH, s
/// (`BRISANCE_COOKOFF_EIGHTH_BUDGET` sets another): the eighth at 3 mm
/// takes about ten minutes on two cores.
const EIGHTH_BUDGET_S: f64 = 3600.0;
/// Members of an ensemble at each h (`BRISANCE_COOKOFF_MEMBERS` sets
/// another; 1 runs none but the plain run).
const MEMBERS: usize = 4;
/// How much warmer each member's steel starts than the one before, K.
const WARMER: f64 = 1.0e-3;

/// One h's curves: label, time, pressure, burnt fraction, hoop strain.
type Curves = (String, Vec<f64>, Vec<f64>, Vec<f64>, Vec<f64>);

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
    fn of(r: &CookoffRun) -> Self {
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

/// Draws the particles of a frame in the (r, z) plane into `path`: steel,
/// the explosive and the steel failed since the start (the eighth's
/// particles at their distance from the axis and height).
fn draw(f: &CookoffFrame<'_>, path: &Path) -> Result<()> {
    let ps = f.solver.mpm().particles();
    let (mut sr, mut sz, mut er, mut ez, mut fr, mut fz) = (
        Vec::new(),
        Vec::new(),
        Vec::new(),
        Vec::new(),
        Vec::new(),
        Vec::new(),
    );
    let ids = f.solver.mpm().particle_ids();
    for (p, id) in ids.iter().enumerate() {
        let x = ps.position[p];
        let (r, z) = (f.grid.radius(x) * 1e3, f.grid.axial(x) * 1e3);
        if ps.material[p].0 != f.steel {
            er.push(r);
            ez.push(z);
        } else if ps.failed[p] && !f.failed_at_start.contains(id) {
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
    let grid = match f.grid {
        CookoffGrid::Rings => "r-z",
        CookoffGrid::Eighth => "eighth, projected on r-z",
    };
    plot_panels(
        path,
        &format!("E-COOKOFF {grid}, {}", f.title),
        "r [mm]",
        &[Panel {
            y_label: "z [mm]",
            series,
        }],
    )
}

/// One run on the (r, z) rings at cell size `h` (m) with the steel
/// started `warmer` K above the scenario's temperature, stopped after
/// `budget_s` s of wall time; particle frames into
/// `img/e_cookoff_<name>.png` where `img` is given.
fn run_at(h: f64, budget_s: f64, img: Option<&Path>, warmer: f64) -> Result<CookoffRun> {
    run_on(CookoffGrid::Rings, h, budget_s, img, warmer, |_| true)
}

/// [`run_at`] on `grid`, drawing only the frames whose name `draw_frame`
/// takes; the eighth's frames are `img/e_cookoff_eighth_<name>.png`.
fn run_on(
    grid: CookoffGrid,
    h: f64,
    budget_s: f64,
    img: Option<&Path>,
    warmer: f64,
    draw_frame: impl Fn(&str) -> bool,
) -> Result<CookoffRun> {
    let setup = CookoffSetup {
        grid,
        h,
        budget_s,
        warmer,
        end: None,
    };
    let mut frame = |f: CookoffFrame<'_>| -> Result<Option<String>, String> {
        let Some(img) = img.filter(|_| draw_frame(&f.name)) else {
            return Ok(None);
        };
        let file = match grid {
            CookoffGrid::Rings => format!("e_cookoff_{}.png", f.name),
            CookoffGrid::Eighth => format!("e_cookoff_eighth_{}.png", f.name),
        };
        draw(&f, &img.join(&file)).map_err(|e| format!("{file}: {e}"))?;
        Ok(Some(file))
    };
    cookoff_run(setup, &mut frame, &mut |line| println!("{line}")).map_err(|e| anyhow!("{e}"))
}

/// Pressure inside the wall, burnt fraction and mid-wall hoop strain of
/// `runs` against time, one curve each labelled by `label`, into `path`.
fn plot_records(
    path: &Path,
    title: &str,
    runs: &[&CookoffRun],
    label: impl Fn(&CookoffRun) -> String,
) -> Result<()> {
    let t_max = runs
        .iter()
        .filter_map(|r| r.record.last().map(|s| s.t))
        .fold(0.0, f64::max);
    let (scale, unit) = crate::plot::time_unit(t_max.max(1e-9));
    let cols: Vec<Curves> = runs
        .iter()
        .map(|r| {
            (
                label(r),
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
        path,
        title,
        &format!("t [{unit}]"),
        &[
            panel(0, "pressure [MPa]"),
            panel(1, "burnt fraction"),
            panel(2, "hoop strain"),
        ],
    )
}

/// One run's figures at its end on the console: steps, wall time, time
/// reached, pressure inside the wall, burnt fraction, hoop strain, failed
/// steel, venting, hottest products and why it stopped.
fn print_summary(r: &CookoffRun) {
    let last = r.record.last().copied();
    println!(
        "  {}h {:.2} mm: {} steps in {:.0} s to t = {:.2} µs; p wall {:.3e} Pa, burnt {:.3e}, hoop {}, failed {}, vented {:.3e} kg/rad, hottest products {:.3e} K; stop {:?}",
        r.grid.label(),
        mm(r.h),
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
}

/// One run's row of the E-COOKOFF table (after `lead`, the cells before
/// h, each followed by " |"; "" for none): h, cells, steps, reached,
/// pressures, burnt, hoop strain, first rupture, venting, hottest
/// products, closure, wall time, stop.
fn write_row(md: &mut String, lead: &str, r: &CookoffRun) {
    let Some(last) = r.record.last() else {
        return;
    };
    let _ = writeln!(
        md,
        "|{lead} {} | {} | {} | {:.2} | {:.3} | {:.3} | {:.3e} | {} | {} | {:.3e} | {:.3e} K at {:.2} µs, (r, z) = ({:.1}, {:.1}) mm | {:.1e} / {:.1e} | {:.0} s | {} |",
            mm(r.h),
            r.grid.cell_count(r.h),
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

/// The first part of a stop message, for the table.
fn short(stop: &str) -> String {
    let first = stop.split(": the fastest").next().unwrap_or(stop);
    let first = first.split("; cell state").next().unwrap_or(first);
    first.chars().take(240).collect()
}

/// The last mid-wall hoop strain of a record: the last finite one, with
/// its time where the mid-wall particles left the domain after it (their
/// mean radius is then undefined), or "—" where there is none.
fn hoop_text(record: &[CookoffSample]) -> String {
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
        let r = run_at(h, budget_s, Some(img), 0.0)?;
        print_summary(&r);
        runs.push(r);
    }
    // Pressure, burnt fraction and hoop strain against time, one curve per h.
    let all: Vec<&CookoffRun> = runs.iter().collect();
    plot_records(
        &img.join("e_cookoff.png"),
        "E-COOKOFF r-z: inside the wall at mid-height, burnt fraction, mid-wall hoop strain",
        &all,
        |r| format!("h = {} mm", mm(r.h)),
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
        write_row(md, "", r);
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
        let _ = writeln!(md, "Frames, h = {} mm: {}.\n", mm(r.h), links.join(", "));
    }
    let _ = writeln!(
        md,
        "| figure | measured | target | verdict |\n|---|---:|---|---|"
    );
    for r in &runs {
        let reached = r.record.last().map_or(0.0, |s| s.t);
        report.target(
            &format!("E-COOKOFF h = {} mm reaches the seed's 0.312 ms", mm(r.h)),
            format!("{:.2} µs", reached * 1e6),
            "312 µs",
            r.stop.is_none(),
        );
        report.target(
            &format!("E-COOKOFF h = {} mm mass closure (max)", mm(r.h)),
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
                println!("  h {:.2} mm, member 0: E-COOKOFF's run", mm(h));
                ends.push(end);
                continue;
            }
            let m = run_at(h, budget_s, None, k as f64 * WARMER)?;
            let end = End::of(&m);
            println!(
                "  h {:.2} mm, steel {} mK warmer: {} steps, {:.0} s, t = {:.2} µs, burnt {:.4}, p wall {:.3e} Pa",
                mm(h),
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
                mm(h),
                ends.len(),
                spread_text(&walls, 1.0, 0)
            );
            continue;
        }
        let _ = writeln!(
            md,
            "| {} | {} of {} | {} | {} | {} | {} |",
            mm(h),
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

/// The burnt fraction of `record` at time `t`: the last sample at or
/// before it (NaN where the record has not reached it).
fn burnt_at(record: &[CookoffSample], t: f64) -> f64 {
    match record.last() {
        Some(last) if last.t >= t * (1.0 - 1e-9) => record
            .iter()
            .rev()
            .find(|s| s.t <= t * (1.0 + 1e-9))
            .map_or(f64::NAN, |s| s.burnt),
        _ => f64::NAN,
    }
}

/// E-COOKOFF-EIGHTH: the cook-off on the seed's own grid, one eighth in 3D
/// (configs/validation/cookoff_eighth.ron), beside the (r, z) rings at the
/// same cell sizes (`BRISANCE_COOKOFF_EIGHTH_H`, mm; default 4.5 and 3),
/// each run to the seed's last frame or its budget
/// (`BRISANCE_COOKOFF_EIGHTH_BUDGET`, s; default [`EIGHTH_BUDGET_S`]).
pub(crate) fn e_cookoff_eighth(report: &mut Report, img: &Path) -> Result<()> {
    println!(
        "E-COOKOFF-EIGHTH: the cook-off on one eighth in 3D beside the (r, z) rings (configs/validation/cookoff_eighth.ron)"
    );
    let hs = crate::env_cell_sizes("BRISANCE_COOKOFF_EIGHTH_H", "4.5,3")?;
    let budget_s = crate::env_seconds("BRISANCE_COOKOFF_EIGHTH_BUDGET", EIGHTH_BUDGET_S)?;
    let mut pairs = Vec::new();
    for &h in &hs {
        let rings = run_on(CookoffGrid::Rings, h, budget_s, None, 0.0, |_| false)?;
        let eighth = run_on(CookoffGrid::Eighth, h, budget_s, Some(img), 0.0, |name| {
            name.ends_with("0.312ms") || name.ends_with("stop")
        })?;
        for r in [&rings, &eighth] {
            print_summary(r);
        }
        pairs.push((rings, eighth));
    }
    // Pressure inside the wall, burnt fraction and hoop strain against
    // time, both grids at every h.
    let runs: Vec<&CookoffRun> = pairs.iter().flat_map(|(a, b)| [a, b]).collect();
    plot_records(
        &img.join("e_cookoff_eighth.png"),
        "E-COOKOFF, one eighth in 3D and r-z rings: inside the wall at mid-height, burnt fraction, mid-wall hoop strain",
        &runs,
        |r| {
            format!(
                "{}, h = {} mm",
                match r.grid {
                    CookoffGrid::Rings => "r-z",
                    CookoffGrid::Eighth => "eighth",
                },
                mm(r.h)
            )
        },
    )?;
    let md = &mut report.md;
    let _ = writeln!(
        md,
        "## E-COOKOFF-EIGHTH — the cook-off on one eighth in 3D beside the (r, z) rings (seed 000 §5.3)\n"
    );
    let _ = writeln!(
        md,
        "configs/validation/cookoff_eighth.ron: E-COOKOFF's container, explosive, burn, solver options and \
         end time on the seed's own grid, one eighth of the container in 3D (its axis along z; x = 0, y = 0 \
         and the mid-plane symmetry planes; x, y and z to 9 cm), run beside configs/cookoff_rz.ron at the \
         same cell sizes (`BRISANCE_COOKOFF_EIGHTH_H`, mm) by `brisance::verification::cookoff::cookoff_run`, \
         which takes the same measures about the container's axis on both grids: r = √(x² + y²) and z on the \
         eighth, the pressure just inside the wall and on the axis at the mid-plane (the eighth's in the \
         plane y = h/2), the mid-wall hoop strain, the first failed steel particle, and the venting per radian \
         (the eighth's products mass outside the container times 8/2π; its square section keeps in its corners, \
         to 12.7 cm from the axis, what the rings' outflow face at 9 cm lets go, so the venting and the late \
         hoop strain do not compare). The cell sizes are coarser than E-COOKOFF's: the eighth has \
         (9 cm / h)³ cells, 27 000 at 3 mm, where the seed's 0.5 mm would be 5.8 million. Each run stops at its budget (`BRISANCE_COOKOFF_EIGHTH_BUDGET`, s; default \
         {EIGHTH_BUDGET_S:.0}). The case is chaotic at these grids (E-COOKOFF-ENSEMBLE: runs a few mK apart \
         end points apart), so the two grids are compared figure by figure, not against a band; the mass \
         closure and the end time are the targets. Wall times on 2 cores shared with other work.\n"
    );
    let _ = writeln!(
        md,
        "| grid | h (mm) | cells | steps | reached (µs) | p inside wall (MPa) | p on axis (MPa) | burnt | hoop strain | first rupture | vented (kg/rad) | hottest products | mass / energy closure (max) | wall time | stop |\n\
         |---|---:|---:|---:|---:|---:|---:|---:|---:|---|---:|---|---:|---:|---|"
    );
    for r in &runs {
        let lead = match r.grid {
            CookoffGrid::Rings => " r–z rings |",
            CookoffGrid::Eighth => " eighth, 3D |",
        };
        write_row(md, lead, r);
    }
    let _ = writeln!(
        md,
        "\nBurnt fraction at the seed's frame times (Fig. 6), eighth / rings:\n\n\
         | h (mm) | 0.137 ms | 0.203 ms | 0.259 ms | 0.312 ms |\n|---:|---:|---:|---:|---:|"
    );
    for (rings, eighth) in &pairs {
        let cells: Vec<String> = brisance::verification::cookoff::FRAMES[1..]
            .iter()
            .map(|&t| {
                format!(
                    "{:.3} / {:.3}",
                    burnt_at(&eighth.record, t),
                    burnt_at(&rings.record, t)
                )
            })
            .collect();
        let _ = writeln!(md, "| {} | {} |", mm(rings.h), cells.join(" | "));
    }
    let _ = writeln!(md, "\n![E-COOKOFF-EIGHTH](img/e_cookoff_eighth.png)\n");
    for (_, eighth) in &pairs {
        if !eighth.frames.is_empty() {
            let links: Vec<String> = eighth
                .frames
                .iter()
                .map(|f| {
                    format!(
                        "[{}](img/{f})",
                        f.trim_start_matches("e_cookoff_eighth_")
                            .trim_end_matches(".png")
                    )
                })
                .collect();
            let _ = writeln!(
                md,
                "Frames of the eighth, its particles at (r, z), h = {} mm: {}.\n",
                mm(eighth.h),
                links.join(", ")
            );
        }
    }
    let _ = writeln!(
        md,
        "| figure | measured | target | verdict |\n|---|---:|---|---|"
    );
    for (_, eighth) in &pairs {
        let reached = eighth.record.last().map_or(0.0, |s| s.t);
        report.target(
            &format!(
                "E-COOKOFF-EIGHTH h = {} mm reaches the seed's 0.312 ms",
                mm(eighth.h)
            ),
            format!("{:.2} µs", reached * 1e6),
            "312 µs",
            eighth.stop.is_none(),
        );
        report.target(
            &format!(
                "E-COOKOFF-EIGHTH h = {} mm mass closure (max)",
                mm(eighth.h)
            ),
            format!("{:.1e}", eighth.mass),
            "≤ 1e-12",
            eighth.mass <= 1e-12,
        );
    }
    let _ = writeln!(report.md);
    Ok(())
}
