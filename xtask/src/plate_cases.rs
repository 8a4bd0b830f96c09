//! E-PLATE's report (`cargo xtask validate --only plate`, `plate-rz`):
//! the cases and their runs are `brisance::verification::plate` (seed 001
//! §5.4, Tables 1–2, docs/physics/couple/plate.md); this file chooses which
//! to run, splices each finished case's rows into docs/validation.md at
//! once, and writes the section and its plots.
//!
//! `PLATE_CASES=4` (or `1`, `4,1`) in the environment runs a subset; the
//! section then keeps the other cases' rows, notes and verdicts from the
//! report it replaces (`crate::kept`).
//! `BRISANCE_PLATE_RZ_H` (mm, default `5,1.25`) sets the r–z case 1's h
//! sequence beside the configs' 2.5 mm.

use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use anyhow::{anyhow, bail, Context, Result};
use brisance::verification::plate::{
    make_remap, run_case, Grid, PlateRun, PLATE_CASES, RZ_CELL, TOLERANCE,
};

use brisance::verification::within_relative;

use crate::bridge3d::splice_now;
use crate::kept::{add_kept_verdicts, kept_in_report, write_kept_notes, write_kept_sentence, Kept};
use crate::plot::{self, Panel, Series, SeriesStyle};
use crate::{workspace_root, Report};

pub(crate) fn e_plate(report: &mut Report, img: &Path) -> Result<()> {
    println!("E-PLATE: RHA plates under a spherical TNT air blast through the 3D FDM-MPM bridge");
    // Case 4 first: the largest deflection, the one the budget must reach;
    // then its scaled copies, then case 1's series.
    let runs: Vec<(u8, Grid)> = [4, 5, 6, 1, 2, 3].map(|id| (id, Grid::Quarter)).to_vec();
    run_plates(report, img, &runs, Section::Quarter)
}

/// E-PLATE on (r, z) grids (`--only plate-rz`): the six cases at the r–z
/// configs' cells ([`RZ_CELL`]), then case 1 at twice and half of them.
pub(crate) fn e_plate_rz(report: &mut Report, img: &Path) -> Result<()> {
    println!("E-PLATE r-z: the six plates through the FDM-MPM bridge on axisymmetric grids");
    let mut runs: Vec<(u8, Grid)> = [4, 5, 6, 1, 2, 3]
        .map(|id| (id, Grid::Rz { h4: RZ_CELL }))
        .to_vec();
    // Case 1's h sequence: `BRISANCE_PLATE_RZ_H` (mm, e.g. `5,1.25,0.625`)
    // or 5 and 1.25 mm, beside the configs' 2.5 mm.
    let extra: Vec<f64> = match std::env::var("BRISANCE_PLATE_RZ_H") {
        Ok(list) => list
            .split(',')
            .map(|h| h.trim().parse::<f64>().map(|h| h * 1e-3))
            .collect::<Result<_, _>>()
            .context("BRISANCE_PLATE_RZ_H takes cell sizes in mm, e.g. 5,1.25,0.625")?,
        Err(_) => vec![2.0 * RZ_CELL, 0.5 * RZ_CELL],
    };
    if let Some(bad) = extra.iter().find(|h| !(**h > 0.0 && h.is_finite())) {
        bail!(
            "BRISANCE_PLATE_RZ_H: a cell size must be > 0 mm, got {}",
            bad * 1e3
        );
    }
    runs.extend(
        extra
            .into_iter()
            .filter(|h| (h - RZ_CELL).abs() > 1e-12)
            .map(|h4| (1, Grid::Rz { h4 })),
    );
    run_plates(report, img, &runs, Section::Rz)
}

/// Which E-PLATE section a set of runs writes.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Section {
    Quarter,
    Rz,
}

impl Section {
    /// The start of the section's heading line.
    fn heading(self) -> &'static str {
        match self {
            Self::Quarter => "## E-PLATE — ",
            Self::Rz => "## E-PLATE-RZ — ",
        }
    }

    /// The name its figures of merit start with (then `case <label>`).
    fn name(self) -> &'static str {
        match self {
            Self::Quarter => "E-PLATE",
            Self::Rz => "E-PLATE-RZ",
        }
    }
}

/// Makes the remaps and runs the cases `planned` ((case, grid), in that
/// order), splicing the section after each; `PLATE_CASES` (e.g.
/// `PLATE_CASES=1` or `4,1`) keeps the runs of those cases only, and the
/// section then keeps the other cases' rows, notes and verdicts from the
/// report it replaces (docs/validation.md as the run found it).
fn run_plates(
    report: &mut Report,
    img: &Path,
    planned: &[(u8, Grid)],
    section: Section,
) -> Result<()> {
    let root: PathBuf = workspace_root();
    let keep: Option<Vec<u8>> = match std::env::var("PLATE_CASES") {
        Ok(list) => Some(
            list.split(',')
                .map(|c| c.trim().parse::<u8>())
                .collect::<Result<_, _>>()
                .context("PLATE_CASES takes case numbers, e.g. 4,1")?,
        ),
        Err(_) => None,
    };
    if let Some(bad) = keep
        .iter()
        .flatten()
        .find(|id| PLATE_CASES.iter().all(|c| c.id != **id))
    {
        bail!("PLATE_CASES: there is no case {bad} (cases 1 to 6)");
    }
    // The cases left out keep their rows, notes and verdicts from the
    // report this run replaces (read before the first splice).
    let kept = kept_in_report(
        &root,
        section.heading(),
        &format!("{} case ", section.name()),
        "Case ",
    );
    let mut prepared = Vec::new();
    for &(id, grid) in planned {
        if keep.as_ref().is_some_and(|k| !k.contains(&id)) {
            continue;
        }
        let Some(case) = PLATE_CASES.iter().find(|c| c.id == id) else {
            bail!("there is no case {id} (cases 1 to 6)");
        };
        let remap_dir = root.join(format!("out/{}_remap", grid.tag(case)));
        let remap_line = make_remap(case, grid, &remap_dir).map_err(|e| anyhow!(e))?;
        prepared.push((id, case, grid, remap_dir, remap_line));
    }
    let mut runs = Vec::new();
    for (id, case, grid, remap_dir, remap_line) in prepared {
        let mut sets = grid.sets();
        sets.push(format!(
            "pipeline.remap=Some(\"{}\")",
            remap_dir.join("remap.bin").display()
        ));
        sets.push("pipeline.charge=None".into());
        let out = root.join(format!("out/xtask_{}", grid.tag(case)));
        let r = run_case(&root, case, grid, &sets, &out, remap_line, &mut |line| {
            println!("    {line}")
        })
        .map_err(|e| anyhow!(e))?;
        println!(
            "  case {id} ({:.2} mm cells): δ/t = {:.3} at {:.0} µs, {} steps to {:.0} µs in {:.0} s, split {:?}{}",
            grid.cell(case) * 1e3,
            r.peak / case.thickness,
            r.peak_time * 1e6,
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
        splice_now(&root, |partial| {
            write_section(partial, &runs, &kept, section)
        })?;
    }
    write_section(report, &runs, &kept, section)?;
    plot_histories(img, &runs, section)?;
    Ok(())
}

fn write_section(
    report: &mut Report,
    runs: &[PlateRun],
    kept: &BTreeMap<String, Kept>,
    section: Section,
) -> Result<()> {
    if section == Section::Rz {
        return write_rz_section(report, runs, kept);
    }
    let md = &mut report.md;
    let _ = writeln!(
        md,
        "{}RHA plates under a spherical TNT air blast through the FDM–MPM bridge (3D)\n",
        Section::Quarter.heading()
    );
    let _ = writeln!(
        md,
        "`configs/plate_case{{1..6}}.ron` (seed 001 §5.4, Tables 1–2; Neuberger, Peles & Rittel 2007; \
         docs/physics/couple/plate.md): quarter model (x = 0 and y = 0 symmetry planes through the charge \
         centre), charge centre at the origin. Johnson–Cook + Mie–Grüneisen RHA of seed 001 §4.5 \
         (`rha_steel`). Scale-4 cases (1, 4): plate t = 10 mm, D = 0.5 m at z = 100–110 mm, FDM region \
         (0, 0, −60) .. (270, 270, 80) mm, MPM region (0, 0, 60) .. (270, 270, 170) mm, bridge w = 4, \
         **5 mm cells** (reduced resolution: the plate is 2 cells, 4 particles, thick; 2 particles per cell \
         per direction), MPM Courant 0.4, bulk viscosity on. Scale 2 (cases 2, 5) and full scale (3, 6): \
         the same configs with every length and time multiplied by k = 2 and 4 (Hopkinson–Cranz; the \
         charges of Table 1 are k³ times the scale-4 ones to 0.2 %), so **10 and 20 mm cells**, the same \
         cells per thickness and the same grid of 54 × 54 × 46 cells: what δ/t changes across a series \
         comes from what does not scale, the strain-rate term of Johnson–Cook (rates are 1/k) and the \
         0.2 %. Clamp: outside r = D/2 the plate is bonded to an RHA ring 6 t thick behind it, held by the \
         fixed MPM face; void behind the plate inside r = D/2. Each FDM region starts from the 1D \
         spherical detonation (800 cells over 80 k mm) remapped at r_c/D + 0.16 k µs. δ is the largest \
         displacement of the centre (mean over the plate particles with x, y < one cell, sampled every 4 \
         steps; seed 001: \"the maximum deflection of the plate δ is measured\"). The centre rings, its \
         velocity turning negative for a few samples before the largest deflection, so the run stops once \
         it has moved 0.5 t and then fallen back below 0.9 δ or not passed δ for half the time it took to \
         reach it; the column \"at the first reversal\" is δ/t where its velocity first turned negative in \
         two samples running, the stop rule of earlier reports. \
         Wall times on the shared 2-CPU machine; memory: growth of this process's resident set over the \
         build and run, and its peak during the case (the process's peak reset at the build; — where the kernel refuses the reset). FDM / MPM: the bridge's split of the wall time \
         (`time_split.json`).\n"
    );
    plate_rows(report, runs, kept, Section::Quarter.name(), "e_plate.png")
}

/// The E-PLATE section on (r, z) grids: what differs from the 3D quarter
/// model, then the rows and verdicts of [`plate_rows`].
fn write_rz_section(
    report: &mut Report,
    runs: &[PlateRun],
    kept: &BTreeMap<String, Kept>,
) -> Result<()> {
    let _ = writeln!(
        report.md,
        "{}the six plates through the FDM–MPM bridge on axisymmetric (r, z) grids\n",
        Section::Rz.heading()
    );
    let _ = writeln!(
        report.md,
        "`configs/plate_case{{1..6}}_rz.ron`: the cases of the 3D section above with the same physics on an \
         axisymmetric (r, z) grid (x = r from the axis through the charge centre, y = z along the plate's \
         normal; docs/physics/couple/bridge.md, \"(r, z) grids\"): every cell and particle a ring, the bridge's \
         exchange (seed 001 eqs 37–51) over ring volumes and annular faces. The same plate, clamp ring \
         6 t thick behind it outside r = D/2 held by the fixed z_high face, void behind the plate, \
         FDM region r 0–270 k mm, z −60 .. 80 k mm, MPM region z 60 .. 170 k mm, bridge 20 k mm wide, \
         2 particles per cell per direction, MPM Courant 0.4, bulk viscosity on. **2.5 k mm cells** \
         (half the quarter's: the plate is 4 cells, 8 particles, thick); case 1 also at other cells \
         (the rows marked with their cells; `BRISANCE_PLATE_RZ_H`, mm, default 5 and 1.25), the FDM region's remap made for each grid \
         (`brisance remap --axisymmetric`: the 1D spherical detonation onto the rings, the charge on \
         the axis). The centre is the plate particles within one cell of the axis; the stop rule and \
         the columns are the 3D section's.\n"
    );
    plate_rows(report, runs, kept, Section::Rz.name(), "e_plate_rz.png")
}

/// A run's case number, with its cells on an (r, z) grid other than the
/// r–z configs' own.
fn label(r: &PlateRun) -> String {
    match r.grid {
        Grid::Rz { h4 } if (h4 - RZ_CELL).abs() > 1e-12 => {
            format!("{} (h {} mm)", r.case.id, r.grid.cell(&r.case) * 1e3)
        }
        _ => r.case.id.to_string(),
    }
}

/// The table of `runs` (a row per run; a case not run has the rows of
/// `kept`, or is marked), the scale and run notes, the plot's link `image`
/// and the verdicts (the kept cases' after the runs'), named `name`.
fn plate_rows(
    report: &mut Report,
    runs: &[PlateRun],
    kept: &BTreeMap<String, Kept>,
    name: &str,
    image: &str,
) -> Result<()> {
    // The cases this section keeps from the earlier report: those not run.
    let kept: Vec<(u8, &Kept)> = PLATE_CASES
        .iter()
        .filter(|c| runs.iter().all(|r| r.case.id != c.id))
        .filter_map(|c| Some((c.id, kept.get(&c.id.to_string())?)))
        .collect();
    let md = &mut report.md;
    let _ = writeln!(
        md,
        "| case | scale | t (m) | D (m) | W (kg) | R (m) | δ/t measured | experiment | seed CFDMP | seed LS-DYNA | peak at (µs) | δ/t at the first reversal (µs) | steps | wall (s) | FDM / MPM (s) | memory growth / peak (MB) |\n|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|"
    );
    for c in &PLATE_CASES {
        let of_case: Vec<&PlateRun> = runs.iter().filter(|r| r.case.id == c.id).collect();
        let opt = |x: Option<f64>| x.map_or("—".into(), |v| format!("{v:.2}"));
        if let Some((_, k)) = kept.iter().find(|(id, _)| *id == c.id) {
            k.write_rows(md);
            continue;
        }
        let rows: Vec<Option<&PlateRun>> = if of_case.is_empty() {
            vec![None]
        } else {
            of_case.into_iter().map(Some).collect()
        };
        for r in rows {
            match r {
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
                    "| {} | {} | {} | {} | {} | {} | {:.2}{} | {} | {} | {} | {:.0} | {} | {} | {:.0} | {} / {} | {} / {} |",
                    label(r),
                    c.scale,
                    c.thickness,
                    c.diameter,
                    c.charge,
                    c.standoff,
                    r.peak / c.thickness,
                    if r.peak_reached { "" } else { " (peak not reached)" },
                    opt(c.experiment),
                    c.cfdmp,
                    opt(c.lsdyna),
                    r.peak_time * 1e6,
                    r.first_reversal.map_or("—".into(), |(t, d)| format!(
                        "{:.2} ({:.0})",
                        d / c.thickness,
                        t * 1e6
                    )),
                    r.steps,
                    r.finished.wall,
                    split("fdm"),
                    split("mpm"),
                    mb(r.finished.resident_growth),
                    mb(r.finished.peak_resident),
                );
                }
                None => {
                    let _ = writeln!(
                    md,
                    "| {} | {} | {} | {} | {} | {} | not run | {} | {} | {} | — | — | — | — | — | — |",
                    c.id,
                    c.scale,
                    c.thickness,
                    c.diameter,
                    c.charge,
                    c.standoff,
                    opt(c.experiment),
                    c.cfdmp,
                    opt(c.lsdyna),
                );
                }
            }
        }
    }
    let kept_ids: Vec<String> = kept.iter().map(|(id, _)| id.to_string()).collect();
    if !kept_ids.is_empty() {
        let what = format!(
            "case{} {}",
            if kept_ids.len() > 1 { "s" } else { "" },
            kept_ids.join(", ")
        );
        write_kept_sentence(md, &what, "PLATE_CASES");
    }
    let not_run: Vec<String> = PLATE_CASES
        .iter()
        .filter(|c| runs.iter().all(|r| r.case.id != c.id))
        .filter(|c| kept.iter().all(|(id, _)| *id != c.id))
        .map(|c| c.id.to_string())
        .collect();
    if !not_run.is_empty() {
        let _ = writeln!(
            md,
            "\nNot run here: {}, left out by `PLATE_CASES` in the run that wrote this section.",
            not_run.join(", ")
        );
    }
    // Each scaled case against its scale-4 case: the scale effect this
    // model gives (the seed's CFDMP: 2.69 / 2.71 / 2.68 and 5.2 / 5.45 / 5.625).
    for series in [[1u8, 2, 3], [4, 5, 6]] {
        // The runs on the section's first grid (the r–z h sequence's
        // other cells aside).
        let ratio = |id: u8| {
            let grid = runs.first()?.grid;
            let base = runs
                .iter()
                .find(|r| r.case.id == series[0] && r.grid == grid)?;
            let r = runs.iter().find(|r| r.case.id == id && r.grid == grid)?;
            Some((r.peak / r.case.thickness) / (base.peak / base.case.thickness))
        };
        let parts: Vec<String> = series[1..]
            .iter()
            .filter_map(|&id| ratio(id).map(|x| format!("case {id} / case {}: {x:.3}", series[0])))
            .collect();
        if !parts.is_empty() {
            let _ = writeln!(
                md,
                "\nScale effect, δ/t over the scale-4 case's: {}.",
                parts.join("; ")
            );
        }
    }
    for r in runs {
        let _ = writeln!(
            md,
            "\nCase {}: remap {}; the centre is {} particles; {}.",
            label(r),
            r.remap_line,
            r.particles_sampled,
            match &r.stop {
                Some(s) => format!(
                    "the run stopped at {:.1} µs: {s}; at the stop {}",
                    r.finished.final_time * 1e6,
                    match r.cold_gas {
                        Some(c) => format!(
                            "{} gas particles of the MPM have a negative specific internal energy, the lowest {:.3e} J/kg at ({:.1}, {:.1}, {:.1}) mm",
                            c.count,
                            c.lowest,
                            c.at[0] * 1e3,
                            c.at[1] * 1e3,
                            c.at[2] * 1e3
                        ),
                        None => "no gas particle of the MPM has a negative specific internal energy".into(),
                    }
                ),
                None if r.peak_reached => format!(
                    "the largest deflection at {:.1} µs, the run stopped at {:.1} µs past it",
                    r.peak_time * 1e6,
                    r.finished.final_time * 1e6
                ),
                None => format!("the run reached its end time {:.1} µs", r.finished.final_time * 1e6),
            }
        );
    }
    write_kept_notes(md, kept.iter().map(|(_, k)| *k));
    let _ = writeln!(
        report.md,
        "\n![{name} centre deflection](img/{image})\n\n| figure of merit | measured | target | verdict |\n|---|---:|---|---|"
    );
    for r in runs {
        let c = &r.case;
        let Some(exp) = c.experiment else { continue };
        let m = r.peak / c.thickness;
        report.target(
            &format!("{name} case {} δ/t vs experiment {exp:.2}", label(r)),
            format!("{m:.2} ({:+.1} %)", 100.0 * (m - exp) / exp),
            "within 10 %",
            r.peak_reached && r.stop.is_none() && within_relative(m, exp, TOLERANCE),
        );
    }
    add_kept_verdicts(report, kept.iter().map(|(_, k)| *k));
    let _ = writeln!(report.md);
    Ok(())
}

fn plot_histories(img: &Path, runs: &[PlateRun], section: Section) -> Result<()> {
    let data: Vec<(String, Vec<f64>, Vec<f64>)> = runs
        .iter()
        .map(|r| {
            (
                match r.case.experiment {
                    Some(e) => format!("case {} (experiment {e:.2})", label(r)),
                    None => format!(
                        "case {} (full scale, seed CFDMP {:.2})",
                        label(r),
                        r.case.cfdmp
                    ),
                },
                r.history
                    .iter()
                    .map(|h| h.0 * 1e6 / r.case.length_scale())
                    .collect(),
                r.history.iter().map(|h| h.1 / r.case.thickness).collect(),
            )
        })
        .collect();
    let panels = vec![Panel {
        y_label: "centre deflection δ/t [-]",
        series: data
            .iter()
            .map(|(label, x, y)| Series {
                label,
                x,
                y,
                style: SeriesStyle::Line,
            })
            .collect(),
    }];
    let (file, title) = match section {
        Section::Quarter => (
            "e_plate.png",
            "E-PLATE: plate-centre deflection over thickness",
        ),
        Section::Rz => (
            "e_plate_rz.png",
            "E-PLATE r-z: plate-centre deflection over thickness",
        ),
    };
    plot::plot_panels(
        &img.join(file),
        title,
        "time after the remap / k [µs] (k = 1, 2, 4 at scale 4, 2, 1)",
        &panels,
    )
}
