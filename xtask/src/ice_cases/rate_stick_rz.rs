//! E-RATESTICK-RZ: the seed's rate sticks on axisymmetric (r, z) grids,
//! beside the LLNL parabola and seed 000 Fig. 3 (the helpers of
//! E-RATESTICK in the parent module).

use super::*;

/// The radii of the seed's sticks run in r–z (seed 000 §5.1: 4, 6, 8,
/// 12.5, 20 mm), m.
const RZ_RADII: [f64; 5] = [4e-3, 6e-3, 8e-3, 12.5e-3, 20e-3];

/// The cell sizes of the r–z sticks by default, m.
const RZ_H: [f64; 3] = [1e-3, 0.5e-3, 0.25e-3];

/// The cell sizes of the r–z sticks, m: `BRISANCE_RATESTICK_RZ_H` (mm,
/// comma-separated, coarsest first, e.g. `1,0.5,0.25,0.125`) or
/// [`RZ_H`].
fn rz_h() -> Result<Vec<f64>> {
    let Ok(text) = std::env::var("BRISANCE_RATESTICK_RZ_H") else {
        return Ok(RZ_H.to_vec());
    };
    let h = text
        .split(',')
        .map(|v| v.trim().parse::<f64>().map(|mm| mm * 1e-3))
        .collect::<Result<Vec<_>, _>>()
        .map_err(|e| anyhow::anyhow!("BRISANCE_RATESTICK_RZ_H = {text}: {e}"))?;
    if h.len() < 2 || h.windows(2).any(|w| !(w[1] < w[0])) || !(h[h.len() - 1] > 0.0) {
        anyhow::bail!(
            "BRISANCE_RATESTICK_RZ_H = {text}: give two or more positive cell sizes in mm, coarsest first"
        );
    }
    Ok(h)
}

/// A cell size in mm as the report prints it (`0.25`).
fn mm(h: f64) -> String {
    format!("{}", (h * 1e6).round() / 1e3)
}

/// E-RATESTICK-RZ section: the seed's sticks (10 cm, R = 4–20 mm, 6 mm of
/// air) on axisymmetric (r, z) grids at h = 1, 0.5 and 0.25 mm
/// (`brisance::ice::cases::RateStick::rz`), twice: as printed (90 m/s
/// impact, eq 19 undamped) and started by a booster with eq 19's pressure
/// term over a Courant-0.8 step (`RateStick::damped`); D(1/R) per h beside
/// the LLNL parabola and the seed's computed points.
pub fn e_ratestick_rz(report: &mut Report, img: &Path) -> Result<()> {
    use brisance::ice::cases::RateStick;
    println!("E-RATESTICK-RZ: ANFO-K1 JWL++ rate sticks on (r, z) grids");
    let llnl = quadratic_fit(&LLNL_ANFO_K1).ok_or_else(|| anyhow::anyhow!("LLNL fit"))?;
    let parabola = |x: f64| llnl[0] + llnl[1] * x + llnl[2] * x * x;
    let x_max = LLNL_ANFO_K1.iter().map(|p| p.0).fold(0.0, f64::max);
    type Make = fn(f64, f64) -> RateStick;
    let sets: [(&str, &str, Make); 2] = [
        ("as printed", "impact, ν* = 0", RateStick::rz),
        ("booster, ν* = 0.8", "booster, ν* = 0.8", |h, r| {
            RateStick::rz(h, r).damped()
        }),
    ];
    let hs = rz_h()?;
    // runs[set][h][radius]
    let mut runs: Vec<Vec<Vec<Option<StickRun>>>> = Vec::new();
    for (name, _, make) in &sets {
        let mut set = Vec::new();
        for &h in &hs {
            let mut row = Vec::new();
            for &r in &RZ_RADII {
                let label = format!("r-z stick R = {:.1} mm, {name}", r * 1e3);
                row.push(match run_stick(&label, &make(h, r)) {
                    Ok(x) => Some(x),
                    Err(e) => {
                        println!("  {label} h {:.2} mm: {e}", h * 1e3);
                        None
                    }
                });
            }
            set.push(row);
        }
        runs.push(set);
    }
    let d_of = |x: &Option<StickRun>| x.as_ref().and_then(|r| r.result.detonation_velocity);
    let h_list = {
        let names: Vec<String> = hs.iter().map(|&h| mm(h)).collect();
        let (last, rest) = names.split_last().expect("two or more cell sizes");
        format!("{} and {last}", rest.join(", "))
    };
    let rings: Vec<usize> = runs
        .iter()
        .flatten()
        .flatten()
        .flatten()
        .map(|r| r.result.cells)
        .collect();
    let (fewest, most) = (
        rings.iter().min().copied().unwrap_or(0),
        rings.iter().max().copied().unwrap_or(0),
    );
    let _ = writeln!(
        report.md,
        "## E-RATESTICK-RZ — the rate sticks on (r, z) grids\n\n\
         The sticks of E-RATESTICK (same ANFO-K1 JWL++ model, 10 cm long, radius R in 6 mm of air, \
         D from the axis gauges at 6 and 9 cm into the unreacted explosive) as rings on an \
         axisymmetric grid (`RateStick::rz`, x = r with the axis a symmetry face, y along the stick; \
         docs/physics/axisymmetric.md, \"The ICE in r–z\"), at h = {h_list} mm: {fewest} to \
         {most} rings, seconds to minutes a stick where the 3D quarter takes minutes to hours \
         (`BRISANCE_RATESTICK_RZ_H` sets the cell sizes, in mm, coarsest first). Two \
         sets. **As printed**: the explosive moving at 90 m/s onto a wall, eq 19 as printed \
         (`face_pressure_courant` 0); the impact's Hugoniot (175 MPa) is below the 200 MPa \
         threshold and what initiates is the undamped shock's ringing at the wall. **Booster, \
         ν* = 0.8** (`RateStick::damped`): a 6 mm booster of products at 20 GPa over the stick's \
         section against the wall, the explosive at rest, and eq 19's pressure term over a \
         Courant-0.8 step, the damping that turns the coarse grids' weak detonations into CJ ones \
         (the planar column then runs at D_CJ at every h; docs/physics/reaction/jwlpp.md, \"Weak \
         detonations at coarse h\"), and under which the impact no longer initiates. \"none\": the \
         wave died out before the second gauge. LLNL: the parabola fitted to the measurements \
         (E-RATESTICK), only inside their range (1/R ≤ {x_max:.3} 1/mm); seed 000 Fig. 3: the \
         seed's computed points (its resolution not named).\n"
    );
    let fig3 = |x: f64| {
        SEED_000_FIG3
            .iter()
            .find(|p| (p.0 - x).abs() < 0.006 && p.0 > 0.0)
            .map(|p| p.1)
    };
    let last = hs.len() - 1;
    let change = |a: Option<f64>, b: Option<f64>| match (a, b) {
        (Some(a), Some(b)) => format!("{:+.1} %", 100.0 * (b / a - 1.0)),
        _ => "—".into(),
    };
    for ((name, _, _), set) in sets.iter().zip(&runs) {
        let mut head = format!("| {name}: R (mm) | 1/R (1/mm) |");
        let mut rule = String::from("|---:|---:|");
        for &h in &hs {
            head.push_str(&format!(" D, h = {} mm (m/s) |", mm(h)));
            rule.push_str("---:|");
        }
        // The change of D per halving of h, coarsest pair first.
        for w in hs.windows(2) {
            head.push_str(&format!(" change {} → {} mm |", mm(w[0]), mm(w[1])));
            rule.push_str("---:|");
        }
        head.push_str(
            " LLNL parabola (m/s) | finest vs LLNL | seed 000 Fig. 3 | finest vs Fig. 3 |",
        );
        rule.push_str("---:|---:|---:|---:|");
        let _ = writeln!(report.md, "{head}\n{rule}");
        for (k, &r) in RZ_RADII.iter().enumerate() {
            let x = 1.0 / (r * 1e3);
            let mut line = format!("| {:.1} | {x:.4} |", r * 1e3);
            for row in set {
                line.push_str(&match d_of(&row[k]) {
                    Some(d) => format!(" {d:.0} |"),
                    None => " none |".to_string(),
                });
            }
            let finest = d_of(&set[last][k]);
            for w in set.windows(2) {
                line.push_str(&format!(" {} |", change(d_of(&w[0][k]), d_of(&w[1][k]))));
            }
            let (llnl_d, vs) = if x <= x_max {
                let p = parabola(x);
                (
                    format!("{p:.0}"),
                    finest.map_or("—".into(), |d| format!("{:+.1} %", 100.0 * (d / p - 1.0))),
                )
            } else {
                ("outside the data".into(), "—".into())
            };
            let (seed, vs_seed) = match fig3(x) {
                Some(f) => (
                    format!("{f:.0}"),
                    finest.map_or("—".into(), |d| format!("{:+.1} %", 100.0 * (d / f - 1.0))),
                ),
                None => ("—".into(), "—".into()),
            };
            let _ = writeln!(report.md, "{line} {llnl_d} | {vs} | {seed} | {vs_seed} |");
        }
        let _ = writeln!(report.md);
    }
    let _ = writeln!(report.md, "| run | h (mm) | rings | steps | peak p at gauge 2 (GPa) | burnt | wall (s) |\n|---|---:|---:|---:|---:|---:|---:|");
    for set in &runs {
        for (row, &h) in set.iter().zip(&hs) {
            for x in row.iter().flatten() {
                let _ = writeln!(
                    report.md,
                    "| {} | {} | {} | {} | {:.2} | {:.3} | {:.1} |",
                    x.label,
                    mm(h),
                    x.result.cells,
                    x.result.steps,
                    x.result.peak_pressure / 1e9,
                    x.result.burnt_fraction,
                    x.wall
                );
            }
        }
    }
    let _ = writeln!(
        report.md,
        "\n![E-RATESTICK-RZ](img/e_ratestick_rz.png)\n\n| figure of merit | measured | target | verdict |\n|---|---:|---|---|"
    );
    // One row per relative difference ("no detonation" where a run has none).
    let mut percent_row = |what: String, v: Option<f64>, target: &str, tolerance: f64| {
        report.target(
            &what,
            v.map_or("no detonation".into(), |v| format!("{:+.2} %", 100.0 * v)),
            target,
            v.is_some_and(|v| v.abs() <= tolerance),
        );
    };
    for ((_, tag, _), set) in sets.iter().zip(&runs) {
        // The change per halving from 0.5 mm down (the target's 0.5 →
        // 0.25 mm, and each finer halving run).
        for (j, w) in hs.windows(2).enumerate() {
            if w[0] > 0.5e-3 * (1.0 + 1e-9) {
                continue;
            }
            for (k, &r) in RZ_RADII.iter().enumerate() {
                if r < 6e-3 {
                    continue;
                }
                let (a, b) = (d_of(&set[j][k]), d_of(&set[j + 1][k]));
                percent_row(
                    format!(
                        "E-RATESTICK-RZ ({tag}) D change {} → {} mm, R = {:.1} mm",
                        mm(w[0]),
                        mm(w[1]),
                        r * 1e3
                    ),
                    a.zip(b).map(|(a, b)| b / a - 1.0),
                    "within ±2 %",
                    0.02,
                );
            }
        }
        for (k, &r) in RZ_RADII.iter().enumerate() {
            let x = 1.0 / (r * 1e3);
            if r < 8e-3 || x > x_max {
                continue;
            }
            percent_row(
                format!(
                    "E-RATESTICK-RZ ({tag}) D vs LLNL parabola at h = {} mm, R = {:.1} mm",
                    mm(hs[last]),
                    r * 1e3
                ),
                d_of(&set[last][k]).map(|d| d / parabola(x) - 1.0),
                "within ±3 %",
                0.03,
            );
        }
    }
    let _ = writeln!(report.md);
    let labels: Vec<String> = hs
        .iter()
        .map(|&h| format!("r–z, h = {} mm", mm(h)))
        .collect();
    let (llnl_x, llnl_y): (Vec<f64>, Vec<f64>) = LLNL_ANFO_K1.iter().copied().unzip();
    let (seed_x, seed_y): (Vec<f64>, Vec<f64>) = SEED_000_FIG3.iter().copied().unzip();
    let mut curves: Vec<Vec<(Vec<f64>, Vec<f64>)>> = Vec::new();
    for set in &runs {
        curves.push(
            set.iter()
                .map(|row| {
                    RZ_RADII
                        .iter()
                        .zip(row)
                        .filter_map(|(&r, s)| d_of(s).map(|d| (1.0 / (r * 1e3), d)))
                        .unzip()
                })
                .collect(),
        );
    }
    let titles = [
        "D (m/s), as printed (impact, ν* = 0)",
        "D (m/s), booster, ν* = 0.8",
    ];
    let panels: Vec<Panel> = curves
        .iter()
        .zip(titles)
        .map(|(set, y_label)| {
            let mut series = vec![
                Series {
                    label: "LLNL experiments (Souers et al. 2000)",
                    x: &llnl_x,
                    y: &llnl_y,
                    style: SeriesStyle::Points,
                },
                Series {
                    label: "seed 000 Fig. 3 (computed)",
                    x: &seed_x,
                    y: &seed_y,
                    style: SeriesStyle::Line,
                },
            ];
            for (label, (x, y)) in labels.iter().zip(set) {
                series.push(Series {
                    label: label.as_str(),
                    x,
                    y,
                    style: SeriesStyle::Points,
                });
            }
            Panel { y_label, series }
        })
        .collect();
    plot::plot_panels(
        &img.join("e_ratestick_rz.png"),
        "E-RATESTICK-RZ: ANFO-K1 rate sticks on (r, z) grids",
        "1/R (1/mm)",
        &panels,
    )?;
    Ok(())
}
