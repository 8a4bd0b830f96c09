//! The shock-tube suite: Toro's tests 1–5 on FDM and ICE at 100–800 cells,
//! side by side (`brisance::verification::shock_tubes`, shared with
//! `tests/v_shock_tubes.rs`).

use std::fmt::Write as _;
use std::path::Path;

use anyhow::Result;
use brisance::verification::cases::observed_orders;
use brisance::verification::open_faces::Method;
use brisance::verification::shock_tubes::{shock_tube, toro_case, ShockTubeRun};

use crate::plot::{self, Panel, Series, SeriesStyle};
use crate::Report;

const CELLS: [usize; 4] = [100, 200, 400, 800];

/// The resolution of the figure.
const PLOTTED: usize = 400;

const NAMES: [&str; 5] = [
    "Sod's tube",
    "the \"123\" problem: two rarefactions, near-vacuum between",
    "the strong left blast",
    "the strong right blast",
    "the collision of two strong shocks",
];

fn pct(v: Option<f64>) -> String {
    v.map_or("—".into(), |v| format!("{:.2} %", 100.0 * v))
}

fn sci(v: f64) -> String {
    format!("{v:.3e}")
}

/// The shock overshoots of ρ and p, "—" without a shock.
fn shock(r: &ShockTubeRun) -> String {
    r.shock_overshoot().map_or("—".into(), |(rho, p)| {
        format!("{} / {}", pct(Some(rho)), pct(Some(p)))
    })
}

/// The limiter's faces as "positivity / density bounds at shocks".
fn limiter_faces(r: &ShockTubeRun) -> String {
    let acted: Vec<String> = r
        .outcome
        .safeguards
        .iter()
        .map(|s| s.acted.to_string())
        .collect();
    if acted.is_empty() {
        "—".into()
    } else {
        let checked = r.outcome.safeguards.first().map_or(0, |s| s.checked);
        format!("{} of {checked}", acted.join(" / "))
    }
}

/// The runs of one test: FDM and ICE at each of [`CELLS`].
struct TestRuns {
    number: usize,
    fdm: Vec<ShockTubeRun>,
    ice: Vec<ShockTubeRun>,
}

impl TestRuns {
    fn by_method(&self) -> [(&'static str, &[ShockTubeRun]); 2] {
        [("FDM", &self.fdm), ("ICE", &self.ice)]
    }
}

/// L1(ρ) of completed runs, and the observed orders between successive
/// resolutions that both completed (as strings, "—" otherwise).
fn l1_and_orders(runs: &[ShockTubeRun]) -> Vec<(String, String)> {
    let l1: Vec<Option<f64>> = runs.iter().map(|r| r.l1_density).collect();
    (0..runs.len())
        .map(|k| {
            let order = match (k.checked_sub(1).and_then(|j| l1[j]), l1[k]) {
                (Some(a), Some(b)) => {
                    format!("{:.2}", observed_orders(&CELLS[k - 1..=k], &[a, b])[0])
                }
                _ => "—".into(),
            };
            (l1[k].map_or("—".into(), sci), order)
        })
        .collect()
}

/// One row's cell for a run that stopped.
fn stopped(r: &ShockTubeRun) -> Option<String> {
    r.outcome
        .stopped
        .as_ref()
        .map(|e| format!("stopped in step {}: {e}", r.outcome.run.steps + 1))
}

fn write_table(md: &mut String, t: &TestRuns) {
    let case = toro_case(t.number).expect("tests 1–5");
    let (l, r) = (case.problem.left, case.problem.right);
    let _ = writeln!(
        md,
        "### Test {} — {}\n\nρ, u, p = {}, {}, {} | {}, {}, {}; x₀ = {}, t = {}.\n",
        t.number,
        NAMES[t.number - 1],
        l.density,
        l.velocity,
        l.pressure,
        r.density,
        r.velocity,
        r.pressure,
        case.diaphragm,
        case.end
    );
    let _ = writeln!(
        md,
        "| cells | steps FDM / ICE | L1(ρ) FDM | order | L1(ρ) ICE | order | shock ρ / p FDM | shock ρ / p ICE | contact ρ FDM / ICE | contact \\|p − p*\\|/p* FDM / ICE | min ρ FDM / ICE | min p FDM / ICE | FDM limiter faces (positivity / shocks) |\n|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|"
    );
    let (fdm_l1, ice_l1) = (l1_and_orders(&t.fdm), l1_and_orders(&t.ice));
    for (k, cells) in CELLS.iter().enumerate() {
        let (f, i) = (&t.fdm[k], &t.ice[k]);
        let _ = writeln!(
            md,
            "| {cells} | {} / {} | {} | {} | {} | {} | {} | {} | {} / {} | {} / {} | {} / {} | {} / {} | {} |",
            f.outcome.run.steps,
            i.outcome.run.steps,
            fdm_l1[k].0,
            fdm_l1[k].1,
            ice_l1[k].0,
            ice_l1[k].1,
            shock(f),
            shock(i),
            pct(f.contact_density_overshoot()),
            pct(i.contact_density_overshoot()),
            pct(f.contact_pressure_excursion),
            pct(i.contact_pressure_excursion),
            sci(f.outcome.min_density),
            sci(i.outcome.min_density),
            sci(f.outcome.min_pressure),
            sci(i.outcome.min_pressure),
            limiter_faces(f)
        );
    }
    for r in t.fdm.iter().chain(&t.ice) {
        if let Some(s) = stopped(r) {
            let _ = writeln!(md, "\n{:?} at {} cells {s}", r.method, r.cells);
        }
    }
    let _ = writeln!(md);
}

/// The section "Shock-tube suite" of the report, its targets and its
/// figure (`docs/img/shock_tubes.png`).
pub fn shock_tubes(report: &mut Report, img: &Path) -> Result<()> {
    println!("Shock-tube suite: Toro's tests 1–5, FDM and ICE, 100–800 cells");
    let mut tests = Vec::new();
    for number in 1..=5 {
        let runs = |method| -> Result<Vec<ShockTubeRun>> {
            CELLS
                .iter()
                .map(|&n| shock_tube(number, method, n, &[]).map_err(anyhow::Error::msg))
                .collect()
        };
        let t = TestRuns {
            number,
            fdm: runs(Method::Fdm)?,
            ice: runs(Method::Ice)?,
        };
        for (name, runs) in t.by_method() {
            for r in runs {
                println!(
                    "  test {number} {name} {:>4} cells  {:>5} steps  L1(ρ) {}  shock ρ, p {}  contact ρ {}  min ρ {:.3e}  min p {:.3e}{}",
                    r.cells,
                    r.outcome.run.steps,
                    r.l1_density.map_or("—".into(), sci),
                    shock(r),
                    pct(r.contact_density_overshoot()),
                    r.outcome.min_density,
                    r.outcome.min_pressure,
                    stopped(r).map(|s| format!("  {s}")).unwrap_or_default()
                );
            }
        }
        tests.push(t);
    }
    let off = shock_tube(
        2,
        Method::Fdm,
        PLOTTED,
        &["pipeline.limiter=Off".to_string()],
    )
    .map_err(anyhow::Error::msg)?;

    let md = &mut report.md;
    let _ = writeln!(md, "## Shock-tube suite — Toro's tests 1–5, FDM and ICE\n");
    let _ = writeln!(
        md,
        "Toro's five Riemann problems (*Riemann Solvers and Numerical Methods for Fluid Dynamics*, 3rd ed., \
         Table 4.1; ideal gas γ = 1.4) on x ∈ [0, 1] at his output times, both ends `ZeroGradient` (test 2 \
         empties through them, test 5 is fed through them), built from scenario text \
         (`brisance::verification::shock_tubes`): FDM `Fdm(material: \"gas\", viscosity: Adaptive)` with the face \
         limiter (`Full`, the default), per-sweep Courant number 0.8; ICE `Ice(materials: [\"gas\"])`, van Leer, \
         CFL 0.4. The diaphragm stands at x₀ = 0.5 for tests 1–4 (test 1 where V-SOD has it) and at 0.4 for \
         test 5 (as V-TORO5); no wave reaches an end. Reference: the exact Riemann solution \
         (`brisance::verification::riemann`) averaged over each cell.\n\n\
         Each wave has a window, from half-way to its neighbour on the left (or the tube's end) to half-way to \
         its neighbour on the right, a fan placed at its tail. The **overshoot** of ρ or p at a wave is the \
         largest excursion of a cell's value in its window outside the interval between the exact states on its \
         two sides, as a fraction of the jump between them (Sod's measure of V-SOD); the shock column gives the \
         worse of two shocks (test 5), \"—\" where there is none (test 2), and so does the contact's density \
         column where the density does not jump (test 2). Pressure does not jump at a contact: its column is \
         the largest |p − p*|/p* in the contact's window (for test 2, the near-vacuum between the fans). Where \
         waves are a few cells apart (tests 3 and 4, contact and shock 0.047 and 0.043 apart) a window also holds \
         its neighbour's smeared edge. **min ρ, min p**: the smallest of any cell at the start and after every \
         step; test 2's are the same at every resolution: with Δt ∝ Δx and no wave at the ends the runs are the \
         same in cell units step by step, and the smallest values come early, within the steps of the coarsest \
         run. **Limiter faces**: the faces at which the FDM's face limiter changed the flux, for positivity and \
         for the density bounds at shocks, of the faces swept over the run (`Solver::safeguards`, \
         docs/physics/fdm.md \"Face limiter\").\n"
    );
    for t in &tests {
        write_table(md, t);
    }
    let _ = writeln!(
        md,
        "Without the face limiter (`pipeline.limiter=Off`, the Lax–Wendroff scheme of seed 001 as printed) the \
         FDM does not get through test 2; at {PLOTTED} cells: {}\n",
        stopped(&off).unwrap_or_else(|| "it completed".into())
    );
    let _ = writeln!(
        md,
        "![Shock tubes at {PLOTTED} cells](img/shock_tubes.png)\n\n| figure of merit | measured | target | verdict |\n|---|---:|---|---|"
    );
    for (k, name) in ["FDM", "ICE"].into_iter().enumerate() {
        let runs: Vec<&ShockTubeRun> = tests.iter().flat_map(|t| t.by_method()[k].1).collect();
        let done = runs.iter().filter(|r| r.completed()).count();
        report.target(
            &format!("Shock tubes {name}: runs completed (tests 1–5, 100–800 cells)"),
            format!("{done} of {}", runs.len()),
            "all",
            done == runs.len(),
        );
        let min_rho = runs
            .iter()
            .map(|r| r.outcome.min_density)
            .fold(f64::INFINITY, f64::min);
        let min_p = runs
            .iter()
            .map(|r| r.outcome.min_pressure)
            .fold(f64::INFINITY, f64::min);
        report.target(
            &format!("Shock tubes {name}: smallest ρ and p, all runs"),
            format!("{min_rho:.2e}, {min_p:.2e}"),
            "> 0",
            min_rho > 0.0 && min_p > 0.0,
        );
        let not_falling: Vec<String> = tests
            .iter()
            .filter(|t| {
                let l1: Vec<Option<f64>> =
                    t.by_method()[k].1.iter().map(|r| r.l1_density).collect();
                !l1.windows(2)
                    .all(|w| matches!(w, [Some(a), Some(b)] if b < a))
            })
            .map(|t| t.number.to_string())
            .collect();
        report.target(
            &format!("Shock tubes {name}: L1(ρ) falls at every refinement"),
            if not_falling.is_empty() {
                "tests 1–5".into()
            } else {
                format!("not in test {}", not_falling.join(", "))
            },
            "tests 1–5",
            not_falling.is_empty(),
        );
    }
    let _ = writeln!(report.md);

    let at = CELLS
        .iter()
        .position(|&n| n == PLOTTED)
        .expect("the plotted resolution is run");
    let fine: Vec<f64> = (0..=2000).map(|i| i as f64 / 2000.0).collect();
    let exact: Vec<Vec<f64>> = tests
        .iter()
        .map(|t| {
            let c = toro_case(t.number).expect("tests 1–5");
            let s = c.problem.solve().map_err(anyhow::Error::msg)?;
            Ok(fine
                .iter()
                .map(|&x| s.sample_at(x, c.diaphragm, c.end).density)
                .collect())
        })
        .collect::<Result<_>>()?;
    let labels: Vec<String> = tests
        .iter()
        .map(|t| {
            let c = toro_case(t.number).expect("tests 1–5");
            format!("density, test {} (t = {})", t.number, c.end)
        })
        .collect();
    let panels: Vec<Panel> = tests
        .iter()
        .zip(&exact)
        .zip(&labels)
        .map(|((t, e), label)| {
            let (f, i) = (&t.fdm[at], &t.ice[at]);
            Panel {
                y_label: label,
                series: vec![
                    Series {
                        label: "exact",
                        x: &fine,
                        y: e,
                        style: SeriesStyle::Line,
                    },
                    Series {
                        label: "FDM",
                        x: &f.outcome.run.x,
                        y: &f.outcome.run.density,
                        style: SeriesStyle::Points,
                    },
                    Series {
                        label: "ICE",
                        x: &i.outcome.run.x,
                        y: &i.outcome.run.density,
                        style: SeriesStyle::Points,
                    },
                ],
            }
        })
        .collect();
    plot::plot_panels(
        &img.join("shock_tubes.png"),
        &format!("Toro's tests 1–5: density at {PLOTTED} cells, FDM and ICE"),
        "x",
        &panels,
    )?;
    Ok(())
}
