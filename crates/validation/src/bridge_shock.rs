//! V-BRIDGE-SHOCK: a steady planar shock through the FDM–MPM bridge
//! (`configs/bridge_shock_tube.ron`; docs/physics/couple/bridge.md,
//! "Starting inside the bridge"). Air at 35.9 MPa behind a Mach 17.5
//! front runs from x = 0.1 m through the bridge (FDM 0–200 mm, MPM
//! 190–300 mm); behind the front the exact pressure is 35.9 MPa
//! everywhere, so what a gauge past the interface reads beside it is the
//! coupling's error. [`run`] runs the config at 2 mm / `refine` with
//! seed 001's start or the start inside the bridge, and measures each
//! gauge of [`GAUGES`] over 0.3–3 µs after the front ([`deviations`]).
//! `cargo xtask validate --only bridge-shock` runs 2, 1 and 0.5 mm.

use std::path::Path;

use brisance_compose::{build::build_solver, load_file, run::next_step};

/// The exact pressure behind the front, Pa.
pub const P_BEHIND: f64 = 3.59e7;

/// The gauges past the interface (190 mm), m: 40 and 70 mm into the MPM
/// region.
pub const GAUGES: [f64; 2] = [0.23, 0.26];

/// The window after the front's arrival (half the jump) that the
/// deviations cover, s.
pub const WINDOW: (f64, f64) = (3.0e-7, 3.0e-6);

/// A gauge's reading against [`P_BEHIND`] over [`WINDOW`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Deviation {
    /// Time the pressure first passes half of [`P_BEHIND`], s.
    pub arrival: f64,
    /// Largest shortfall, (P − p)/P, ≥ 0 if any sample is under.
    pub under: f64,
    /// Largest excess, (p − P)/P.
    pub over: f64,
    /// Mean of (p − P)/P.
    pub mean: f64,
    /// Samples in the window.
    pub samples: usize,
}

/// The deviation of the pressure history `history` (time, Pa) from
/// [`P_BEHIND`] over [`WINDOW`] after its arrival; `None` when the front
/// does not arrive or the window holds no sample.
pub fn deviations(history: &[(f64, f64)]) -> Option<Deviation> {
    let arrival = history.iter().find(|h| h.1 > 0.5 * P_BEHIND)?.0;
    let inside: Vec<f64> = history
        .iter()
        .filter(|h| h.0 > arrival + WINDOW.0 && h.0 < arrival + WINDOW.1)
        .map(|h| (h.1 - P_BEHIND) / P_BEHIND)
        .collect();
    if inside.is_empty() {
        return None;
    }
    Some(Deviation {
        arrival,
        under: inside.iter().map(|d| -d).fold(f64::MIN, f64::max),
        over: inside.iter().cloned().fold(f64::MIN, f64::max),
        mean: inside.iter().sum::<f64>() / inside.len() as f64,
        samples: inside.len(),
    })
}

/// One run of the tube.
#[derive(Debug, Clone)]
pub struct ShockTubeRun {
    /// Cell size, m.
    pub h: f64,
    /// `start_in_bridge` (cells), `None` for seed 001's start.
    pub start: Option<usize>,
    /// Per gauge of [`GAUGES`].
    pub gauges: Vec<Deviation>,
    /// Steps.
    pub steps: u64,
}

/// Runs `configs/bridge_shock_tube.ron` under `root` at 2 mm / `refine`
/// (w = 5 · `refine`, the bridge 10 mm at every h) with the MPM region
/// started `start_mm` into the bridge (rounded to whole cells), or with
/// seed 001's start for `None`, to its end with the run loop's step
/// rule, sampling the gauges after every step.
pub fn run(root: &Path, refine: usize, start_mm: Option<f64>) -> Result<ShockTubeRun, String> {
    let h = 0.002 / refine as f64;
    let start = start_mm.map(|mm| (1e-3 * mm / h).round() as usize);
    let sets = vec![
        format!("domain.cells=({},1,1)", 150 * refine),
        format!("pipeline.w=Some({})", 5 * refine),
        match start {
            Some(k) => format!("pipeline.start_in_bridge=Some({k})"),
            None => "pipeline.start_in_bridge=None".to_string(),
        },
    ];
    let path = root.join("configs/bridge_shock_tube.ron");
    let loaded = load_file(&path, &sets).map_err(|e| e.to_string())?;
    let end = loaded.scenario.time.end;
    let mut solver = build_solver(&loaded.scenario).map_err(|e| loaded.locate(e).to_string())?;
    let names = ["pressure".to_string()];
    let mut histories = vec![Vec::new(); GAUGES.len()];
    let mut p = Vec::new();
    let mut steps = 0;
    loop {
        let remaining = end - solver.time();
        if remaining <= 0.0 {
            break;
        }
        let dt = solver.stable_dt().map_err(|e| e.to_string())?;
        let (dt, hits) = next_step(dt, remaining);
        solver.advance(dt).map_err(|e| e.to_string())?;
        steps += 1;
        for (x, history) in GAUGES.iter().zip(histories.iter_mut()) {
            p.clear();
            solver
                .sample([*x, 0.5 * h, 0.5 * h], &names, &mut p)
                .map_err(|e| e.to_string())?;
            history.push((solver.time(), p[0]));
        }
        if hits {
            break;
        }
    }
    let gauges = histories
        .iter()
        .zip(GAUGES)
        .map(|(history, x)| {
            deviations(history).ok_or(format!("the front did not pass the gauge at {x} m"))
        })
        .collect::<Result<Vec<_>, _>>()?;
    Ok(ShockTubeRun {
        h,
        start,
        gauges,
        steps,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Hand values: a front at 1 µs (the first sample past half the
    /// jump), then 34, 36, 37 MPa inside the window and one sample past it.
    #[test]
    fn deviations_are_the_hand_values() {
        let p = P_BEHIND;
        let history = [
            (0.0, 1.0e5),
            (1.0e-6, 0.6 * p),
            (1.2e-6, 3.0e7), // before the window (arrival + 0.3 µs)
            (1.5e-6, 3.4e7),
            (2.0e-6, 3.6e7),
            (3.5e-6, 3.7e7),
            (4.5e-6, 1.0e7), // past the window (arrival + 3 µs)
        ];
        let d = deviations(&history).unwrap();
        assert_eq!(d.arrival, 1.0e-6);
        assert_eq!(d.samples, 3);
        assert!((d.under - (p - 3.4e7) / p).abs() < 1e-15);
        assert!((d.over - (3.7e7 - p) / p).abs() < 1e-15);
        let mean = ((3.4e7 - p) + (3.6e7 - p) + (3.7e7 - p)) / (3.0 * p);
        assert!((d.mean - mean).abs() < 1e-15);
        // No front, or nothing in the window: no figure.
        assert_eq!(deviations(&history[..1]), None);
        assert_eq!(deviations(&history[..3]), None);
    }

    /// The shipped config at 2 mm: with the start inside the bridge the
    /// gauge 70 mm past the interface stays within 8 % under the exact
    /// pressure (measured 5.5 %); seed 001's start leaves a dip of more
    /// than 25 % (measured 33 %).
    #[test]
    fn the_start_inside_the_bridge_takes_out_the_dip() {
        let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
        let inside = run(&root, 1, Some(4.0)).unwrap();
        let seed = run(&root, 1, None).unwrap();
        assert_eq!((inside.start, seed.start), (Some(2), None));
        let (a, b) = (inside.gauges[1], seed.gauges[1]);
        eprintln!("260 mm: inside {a:?}; seed {b:?}");
        assert!(a.under < 0.08, "{a:?}");
        assert!(b.under > 0.25, "{b:?}");
    }
}
