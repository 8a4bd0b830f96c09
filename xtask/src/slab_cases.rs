//! E-SLAB's report (`cargo xtask validate --only slab`): the charges and
//! their runs are `brisance::verification::slab` (seed 001 §5.3;
//! Luccioni & Luege 2006; docs/physics/couple/slab.md); this file chooses
//! which to run, splices each finished charge's rows into
//! docs/validation.md at once, and writes the section and its plots.
//!
//! `SLAB_CHARGES=4,10` (kg; default 4,10,2,20) runs a subset; the section
//! then keeps the other charges' rows, notes and verdicts from the report
//! it replaces (`crate::kept`).

use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use anyhow::{anyhow, bail, Context, Result};
use brisance::verification::slab::{
    axis_impulse, eq67_diameter, make_remap, run_case, SlabRun, HEIGHT, SLAB_CASES, SPACING,
    TOLERANCE,
};
use brisance::verification::within_relative;

use crate::bridge3d::splice_now;
use crate::kept::{add_kept_verdicts, kept_in_report, write_kept_notes, write_kept_sentence, Kept};
use crate::plot::{self, Panel, Series, SeriesStyle};
use crate::{workspace_root, Report};

/// The start of E-SLAB's heading line.
const HEADING: &str = "## E-SLAB — ";

pub(crate) fn e_slab(report: &mut Report, img: &Path) -> Result<()> {
    println!(
        "E-SLAB: concrete slab under spherical TNT charges at 0.5 m through the 3D FDM-MPM bridge"
    );
    let root: PathBuf = workspace_root();
    let charges: Vec<f64> = match std::env::var("SLAB_CHARGES") {
        Ok(list) => list
            .split(',')
            .map(|c| c.trim().parse::<f64>())
            .collect::<Result<_, _>>()
            .context("SLAB_CHARGES takes charge masses in kg, e.g. 4,10")?,
        Err(_) => vec![4.0, 10.0, 2.0, 20.0],
    };
    // The charges left out keep their rows, notes and verdicts from the
    // report this run replaces (read before the first splice).
    let kept = kept_in_report(&root, HEADING, "E-SLAB ", "");
    let mut runs: Vec<SlabRun> = Vec::new();
    for w in charges {
        let Some(case) = SLAB_CASES.iter().find(|c| c.charge == w) else {
            bail!("SLAB_CHARGES: no case of {w} kg (2, 4, 10 and 20 kg are)");
        };
        let remap_dir = root.join(format!("out/slab_{}_remap", case.slug()));
        let remap_line = make_remap(case, &remap_dir).map_err(|e| anyhow!(e))?;
        let sets = vec![
            format!(
                "pipeline.remap=Some(\"{}\")",
                remap_dir.join("remap.bin").display()
            ),
            "pipeline.charge=None".into(),
        ];
        let out = root.join(format!("out/xtask_slab_{}", case.slug()));
        let r = run_case(&root, case, &sets, &out, remap_line, &mut |line| {
            println!("    {line}")
        })
        .map_err(|e| anyhow!(e))?;
        println!(
            "  {}: crushing D = {:.0} mm (area {:.0} mm), back face {} of {} failed, {} steps to {:.0} µs in {:.0} s, split {:?}{}",
            case.label(),
            r.front.diameter * 1e3,
            r.front.area_diameter * 1e3,
            r.back.failed,
            r.back.particles,
            r.steps,
            r.finished.final_time * 1e6,
            r.finished.wall,
            r.finished.split,
            r.stop
                .as_deref()
                .map(|s| format!(" — stopped: {s}"))
                .unwrap_or_default()
        );
        runs.push(r);
        runs.sort_by(|a, b| a.case.charge.total_cmp(&b.case.charge));
        splice_now(&root, |partial| write_section(partial, &runs, &kept))?;
        plot_diameters(img, &runs)?;
        draw_faces(&img.join("e_slab_faces.png"), &runs)?;
    }
    write_section(report, &runs, &kept)?;
    Ok(())
}

/// The section from `runs`; a charge not run keeps its rows, notes and
/// verdicts from `kept` (the report this run replaces), or is marked.
fn write_section(
    report: &mut Report,
    runs: &[SlabRun],
    kept: &BTreeMap<String, Kept>,
) -> Result<()> {
    let kept: Vec<(f64, &Kept)> = SLAB_CASES
        .iter()
        .filter(|c| runs.iter().all(|r| r.case.charge != c.charge))
        .filter_map(|c| Some((c.charge, kept.get(&c.charge.to_string())?)))
        .collect();
    let md = &mut report.md;
    let _ = writeln!(
        md,
        "{HEADING}concrete slab under spherical TNT charges at 0.5 m through the FDM–MPM bridge (3D)\n"
    );
    let _ = writeln!(
        md,
        "`configs/slab_{{4,10}}kg.ron` (seed 001 §5.3; Luccioni & Luege 2006; docs/physics/couple/slab.md): \
         quarter model (x = 0 and y = 0 symmetry planes through the charge centre), slab 150 mm thick, top face \
         h = 0.5 m from the charge centre, 0–0.4 m in x and y, free back and side faces. HJC concrete, f'c = 25 MPa \
         (`concrete_25mpa`: HJC 1993 rescaled, no Jiang tensile law — seed 001 quotes no parameters for it); \
         a particle fails at damage 1 (or at the tension limit's damage), keeping only its compressive pressure; \
         no erosion. FDM region (0, 0, −180) .. (400, 400, 460) mm, MPM region (0, 0, 410) .. (400, 400, 700) mm, \
         bridge w = 5, **10 mm cells** (reduced resolution: 2 particles per cell per direction, 5 mm particles, \
         30 through the thickness), MPM Courant 0.4, bulk viscosity on. The 2 and 20 kg runs use the 4 kg config \
         with their own remap. Crushing diameter: the concrete particles that started in the top-face layer \
         (within 10 mm of the top face, two particles deep; followed by particle identity), rings 5 mm wide \
         about the axis by initial position; the crushed zone runs from the axis to the first ring in which \
         fewer than half the particles are crushed (HJC damage D first seen at 1 while the particle's pressure is \
         positive, sampled every 5 steps; D reached in tension does not count); D = twice its outer radius; \"area D\" is the diameter of the disc with the area of the \
         crushed top-face particles within 200 mm of the axis (each 5 × 5 mm). Back face: particles of the \
         initial bottom layer with tensile damage D_t ≥ 1. Axis pressure: mean pressure of the initial \
         top-layer concrete particles within 10 mm of the axis, every 5 steps; \
         impulse: its time integral over the run. Tolerance, set before the runs: within 20 % \
         of the test (250 / 300 mm) and of eq 67. Wall times on the shared 2-CPU machine under the other work's \
         load; memory: growth of this process's resident set over the build and run, and its peak during the case (the process's peak reset at the build; — where the kernel refuses the reset).\n"
    );
    let _ = writeln!(
        md,
        "| W (kg TNT) | D measured (mm) | area D (mm) | test (mm) | eq 67 (mm) | peak axis pressure (MPa) at (µs) | axis impulse (kPa·s) | back face D_t ≥ 1 / particles | failed concrete particles | end (µs) | steps | wall (s) | FDM / MPM (s) | memory growth / peak (MB) |\n|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|"
    );
    for c in &SLAB_CASES {
        let eq = eq67_diameter(c.charge, HEIGHT) * 1e3;
        let test = c
            .experiment
            .map_or("—".into(), |d| format!("{:.0}", d * 1e3));
        match runs.iter().find(|r| r.case.charge == c.charge) {
            Some(r) => {
                let split = |name: &str| {
                    r.finished
                        .split
                        .iter()
                        .find(|(n, _)| *n == name)
                        .map_or("—".into(), |(_, s)| format!("{s:.0}"))
                };
                let mb = |x: Option<f64>| x.map_or("—".into(), |v| format!("{:.0}", v / 1e6));
                let _ = writeln!(
                    md,
                    "| {} | {:.0}{} | {:.0} | {test} | {eq:.0} | {:.1} at {:.0} | {:.2} | {} / {} | {} / {} | {:.1} | {} | {:.0} | {} / {} | {} / {} |",
                    c.charge,
                    r.front.diameter * 1e3,
                    if r.stop.is_some() { " (stopped)" } else { "" },
                    r.front.area_diameter * 1e3,
                    r.peak_pressure.0 / 1e6,
                    r.peak_pressure.1 * 1e6,
                    axis_impulse(&r.history) / 1e3,
                    r.back.failed,
                    r.back.particles,
                    r.failed_total,
                    r.concrete_total,
                    r.finished.final_time * 1e6,
                    r.steps,
                    r.finished.wall,
                    split("fdm"),
                    split("mpm"),
                    mb(r.finished.resident_growth),
                    mb(r.finished.peak_resident),
                );
            }
            None => match kept.iter().find(|(w, _)| *w == c.charge) {
                Some((_, k)) => k.write_rows(md),
                None => {
                    let _ = writeln!(
                        md,
                        "| {} | not run | — | {test} | {eq:.0} | — | — | — | — | — | — | — | — | — |",
                        c.charge
                    );
                }
            },
        }
    }
    if !kept.is_empty() {
        let ws: Vec<String> = kept.iter().map(|(w, _)| format!("{w} kg")).collect();
        write_kept_sentence(md, &ws.join(", "), "SLAB_CHARGES");
    }
    for r in runs {
        let _ = writeln!(
            md,
            "\n{}: remap {}; {}.",
            r.case.label(),
            r.remap_line,
            match &r.stop {
                Some(s) => format!(
                    "the run stopped at {:.1} µs: {s}",
                    r.finished.final_time * 1e6
                ),
                None => format!(
                    "the run reached its end time {:.1} µs",
                    r.finished.final_time * 1e6
                ),
            }
        );
    }
    write_kept_notes(md, kept.iter().map(|(_, k)| *k));
    let _ = writeln!(
        md,
        "\n![E-SLAB crushing diameter](img/e_slab.png)\n\n![E-SLAB crushing diameter and axis pressure during the runs](img/e_slab_history.png)\n\n![E-SLAB top and back faces](img/e_slab_faces.png)\n\n| figure of merit | measured | target | verdict |\n|---|---:|---|---|"
    );
    for r in runs {
        let c = &r.case;
        let m = r.front.diameter;
        let ok = r.stop.is_none();
        if let Some(exp) = c.experiment {
            report.target(
                &format!(
                    "E-SLAB {} crushing D vs test {:.0} mm",
                    c.label(),
                    exp * 1e3
                ),
                format!("{:.0} mm ({:+.1} %)", m * 1e3, 100.0 * (m - exp) / exp),
                "within 20 %",
                ok && within_relative(m, exp, TOLERANCE),
            );
        }
        let eq = eq67_diameter(c.charge, HEIGHT);
        report.target(
            &format!(
                "E-SLAB {} crushing D vs eq 67 {:.0} mm",
                c.label(),
                eq * 1e3
            ),
            format!("{:.0} mm ({:+.1} %)", m * 1e3, 100.0 * (m - eq) / eq),
            "within 20 %",
            ok && within_relative(m, eq, TOLERANCE),
        );
    }
    add_kept_verdicts(report, kept.iter().map(|(_, k)| *k));
    let _ = writeln!(report.md);
    Ok(())
}

/// D/h against W^{1/3}/h (seed 001 Fig. 15): eq 67, the tests and the
/// runs; and the crushing diameter's history of each run.
fn plot_diameters(img: &Path, runs: &[SlabRun]) -> Result<()> {
    let curve_x: Vec<f64> = (0..=60).map(|i| 1.0 + 5.0 * f64::from(i) / 60.0).collect();
    let curve_y: Vec<f64> = curve_x
        .iter()
        .map(|s| eq67_diameter((s * HEIGHT).powi(3), HEIGHT) / HEIGHT)
        .collect();
    let scaled = |w: f64| w.cbrt() / HEIGHT;
    let test_x: Vec<f64> = SLAB_CASES
        .iter()
        .filter(|c| c.experiment.is_some())
        .map(|c| scaled(c.charge))
        .collect();
    let test_y: Vec<f64> = SLAB_CASES
        .iter()
        .filter_map(|c| c.experiment.map(|d| d / HEIGHT))
        .collect();
    let run_x: Vec<f64> = runs.iter().map(|r| scaled(r.case.charge)).collect();
    let run_y: Vec<f64> = runs.iter().map(|r| r.front.diameter / HEIGHT).collect();
    let hist: Vec<(String, Vec<f64>, Vec<f64>)> = runs
        .iter()
        .map(|r| {
            (
                r.case.label(),
                r.history.iter().map(|h| h.0 * 1e6).collect(),
                r.history.iter().map(|h| h.1 * 1e3).collect(),
            )
        })
        .collect();
    let top = Panel {
        y_label: "D/h [-] vs W^(1/3)/h [kg^(1/3)/m]",
        series: vec![
            Series {
                label: "eq 67",
                x: &curve_x,
                y: &curve_y,
                style: SeriesStyle::Line,
            },
            Series {
                label: "test (Luccioni & Luege 2006)",
                x: &test_x,
                y: &test_y,
                style: SeriesStyle::Points,
            },
            Series {
                label: "this run (10 mm cells)",
                x: &run_x,
                y: &run_y,
                style: SeriesStyle::Points,
            },
        ],
    };
    plot::plot_panels(
        &img.join("e_slab.png"),
        "E-SLAB: crushing diameter over charge height vs scaled charge",
        "W^(1/3)/h [kg^(1/3)/m]",
        &[top],
    )?;
    let pressure: Vec<Vec<f64>> = runs
        .iter()
        .map(|r| r.history.iter().map(|h| h.3 / 1e6).collect())
        .collect();
    let panels = vec![
        Panel {
            y_label: "crushing diameter [mm]",
            series: hist
                .iter()
                .map(|(label, x, y)| Series {
                    label,
                    x,
                    y,
                    style: SeriesStyle::Line,
                })
                .collect(),
        },
        Panel {
            y_label: "top-layer pressure at the axis [MPa]",
            series: hist
                .iter()
                .zip(&pressure)
                .map(|((label, x, _), y)| Series {
                    label,
                    x,
                    y,
                    style: SeriesStyle::Line,
                })
                .collect(),
        },
    ];
    plot::plot_panels(
        &img.join("e_slab_history.png"),
        "E-SLAB: crushing diameter during the run",
        "time after the remap [µs]",
        &panels,
    )
}

/// Top and back face layers of each run, side by side: failed particles
/// red, intact grey; the charge's axis at the lower left corner of each
/// quarter.
fn draw_faces(path: &Path, runs: &[SlabRun]) -> Result<()> {
    use plotters::prelude::*;
    plot::register_font()?;
    let px_per_m = 800.0;
    let side = (0.4 * px_per_m) as i32;
    let (pad, head) = (20i32, 50i32);
    let cell_w = side + 2 * pad;
    let cell_h = side + head + pad;
    let rows = runs.len().max(1) as u32;
    let root =
        BitMapBackend::new(path, (2 * cell_w as u32, cell_h as u32 * rows)).into_drawing_area();
    root.fill(&WHITE)
        .map_err(|e| anyhow!("clearing {}: {e}", path.display()))?;
    let dot = (SPACING * px_per_m / 2.0).ceil() as i32;
    for (k, r) in runs.iter().enumerate() {
        for (col, (name, map)) in [
            ("top face, crushed (D = 1 under p > 0)", &r.front_map),
            ("back face, D_t ≥ 1", &r.back_map),
        ]
        .into_iter()
        .enumerate()
        {
            let (cx, cy) = (col as i32 * cell_w, k as i32 * cell_h);
            let failed = map.iter().filter(|p| p.2).count();
            root.draw(&Text::new(
                format!("{}: {name}: {failed} of {}", r.case.label(), map.len()),
                (cx + pad, cy + 12),
                ("sans-serif", 16).into_font(),
            ))
            .map_err(|e| anyhow!("drawing a label: {e}"))?;
            let (x0, y0) = (cx + pad, cy + head + side);
            root.draw(&Rectangle::new(
                [(x0, y0 - side), (x0 + side, y0)],
                BLACK.stroke_width(1),
            ))
            .map_err(|e| anyhow!("drawing a frame: {e}"))?;
            for &(x, y, f) in map {
                let (u, v) = (x0 + (x * px_per_m) as i32, y0 - (y * px_per_m) as i32);
                let colour = if f {
                    RGBColor(200, 30, 30)
                } else {
                    RGBColor(190, 190, 190)
                };
                root.draw(&Rectangle::new(
                    [(u - dot, v - dot), (u + dot, v + dot)],
                    colour.filled(),
                ))
                .map_err(|e| anyhow!("drawing a particle: {e}"))?;
            }
            if let Some(d) = (col == 0).then_some(r.front.diameter).filter(|d| *d > 0.0) {
                let rad = (0.5 * d * px_per_m) as i32;
                root.draw(&Circle::new((x0, y0), rad, BLUE.stroke_width(2)))
                    .map_err(|e| anyhow!("drawing a circle: {e}"))?;
            }
            if let Some(exp) = r.case.experiment.filter(|_| col == 0) {
                let rad = (0.5 * exp * px_per_m) as i32;
                root.draw(&Circle::new((x0, y0), rad, BLACK.stroke_width(1)))
                    .map_err(|e| anyhow!("drawing a circle: {e}"))?;
            }
        }
    }
    root.present()
        .map_err(|e| anyhow!("writing {}: {e}", path.display()))?;
    Ok(())
}
