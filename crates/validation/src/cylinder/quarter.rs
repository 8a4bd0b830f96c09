//! E-CYLINDER's run: the reduced copper cylinder test of seed 000 §5.2 on
//! the 3D quarter (configs/cylinder_icempm.ron, the `IceMpm` pipeline).
//! The outer-wall particles that start within 1 mm of the gauge's z are
//! followed by identity; their mean radial velocity against time is the
//! record, its last tenth the terminal figure, set against the Gurney
//! estimate of [`super::tube_gurney`]. Beside it: the detonation's arrival
//! on the axis (products volume fraction above ½) every 5 mm around the
//! gauge, the whole wall slice's kinetic-energy mean radial velocity, how
//! far the wall got, and what the cold-material rules added.

use std::collections::BTreeSet;
use std::time::Instant;

use brisance_compose::build::build_section;
use brisance_compose::load_str;
use brisance_core::Solver;
use brisance_couple::IceMpmConfig;
use brisance_eos::tools::{cylinder_wall_velocity, gurney_estimate};
use brisance_ice::KeptWarmTotals;
use brisance_mpm::MpmSolver;

use super::{tube_gurney, TubeGurney, TUBE};
use crate::last_tenth_mean;

/// configs/cylinder_icempm.ron, the reduced quarter tube.
pub const CYLINDER_QUARTER_CONFIG: &str = include_str!("../../../../configs/cylinder_icempm.ron");

/// The file name the quarter tube's errors give.
const FILE: &str = "configs/cylinder_icempm.ron";

/// Axial position of the wall gauge, m: 15 cm from initiation, 5 cm before
/// the tube's open end (whose rarefaction reaches it after the record).
/// At 5 cm, the first reduced tube's gauge, the detonation was still
/// building up from the booster (docs/physics/couple/ice_mpm_cylinder_audit.md).
pub const QUARTER_GAUGE_Z: f64 = 0.15;

/// How one E-CYLINDER run is set up.
#[derive(Debug, Clone)]
pub struct QuarterSetup {
    /// `--set` overrides of the shipped config.
    pub sets: Vec<String>,
    /// Axial position of the wall gauge, m.
    pub gauge_z: f64,
}

impl QuarterSetup {
    /// The shipped case: no overrides, the gauge at [`QUARTER_GAUGE_Z`].
    pub fn shipped() -> Self {
        Self {
            sets: Vec::new(),
            gauge_z: QUARTER_GAUGE_Z,
        }
    }
}

/// What E-CYLINDER measures in one run.
#[derive(Debug, Clone)]
pub struct QuarterRun {
    /// The largest cell size, m.
    pub h: f64,
    /// The domain's extent along x, y and z, m.
    pub extent: [f64; 3],
    /// Cells of the grid.
    pub cells: usize,
    /// Particles (the pipeline's count per step).
    pub particles: usize,
    /// Steps taken.
    pub steps: usize,
    /// Wall time of the step loop, s.
    pub wall_s: f64,
    /// Time reached, s.
    pub time: f64,
    /// The gauge's axial position, m.
    pub gauge_z: f64,
    /// Detonation arrival on the axis at the gauge (products volume
    /// fraction above ½), s.
    pub arrival: Option<f64>,
    /// Arrivals on the axis every 5 mm from 5 cm before the gauge to 3 cm
    /// after it, inside the domain: (z m, time s).
    pub fronts: Vec<(f64, Option<f64>)>,
    /// The outer-wall gauge's mean radial velocity against time: (s, m/s).
    pub record: Vec<(f64, f64)>,
    /// The whole wall slice at the gauge (every particle starting within
    /// h/2 of its z): its kinetic-energy mean radial velocity at the end,
    /// m/s (the velocity the Gurney relation speaks of; a thick wall's
    /// outer surface moves slower than its mean).
    pub slice_end: f64,
    /// The wall's inner radius at the gauge at the end, m: from the gauge
    /// particles' mean radius scaled to the outer surface and the copper's
    /// area (nearly incompressible).
    pub inner_radius_end: f64,
    /// The products' relative volume (r_in / r_in0)² there.
    pub relative_volume_end: f64,
    /// The Gurney estimate for the tube (QM-100 products to V = 7).
    pub gurney: TubeGurney,
    /// The Gurney wall velocity at the relative volume reached, same M/C
    /// (for reading a record that ends before V = 7), m/s.
    pub gurney_at_end: Option<f64>,
    /// Total energy at the start, J.
    pub energy_start: f64,
    /// Step 2's cold-material rule and trace hold over the run, per
    /// material (the pipeline's fluids, then the solids).
    pub kept_warm: Vec<(String, KeptWarmTotals)>,
    /// Step 12's, per material.
    pub kept_warm_advection: Vec<(String, KeptWarmTotals)>,
    /// The solver's error where the run stopped before its end.
    pub failure: Option<String>,
}

impl QuarterRun {
    /// Least-squares detonation velocity over the axis arrivals recorded,
    /// m/s (NaN with fewer than three).
    pub fn detonation_velocity(&self) -> f64 {
        let pts: Vec<(f64, f64)> = self
            .fronts
            .iter()
            .filter_map(|f| f.1.map(|t| (t, f.0)))
            .collect();
        if pts.len() < 3 {
            return f64::NAN;
        }
        let n = pts.len() as f64;
        let (st, sz) = pts.iter().fold((0.0, 0.0), |a, p| (a.0 + p.0, a.1 + p.1));
        let (mt, mz) = (st / n, sz / n);
        let (num, den) = pts.iter().fold((0.0, 0.0), |a, p| {
            (a.0 + (p.0 - mt) * (p.1 - mz), a.1 + (p.0 - mt) * (p.0 - mt))
        });
        num / den
    }

    /// The gauge's terminal radial velocity, the mean over the last tenth
    /// of the record, m/s (NaN where the run stopped or recorded nothing).
    pub fn terminal(&self) -> f64 {
        if self.failure.is_some() || self.record.is_empty() {
            return f64::NAN;
        }
        last_tenth_mean(&self.record, |x| x.1)
    }
}

/// The mean of `f` over the particles whose identities are in `set`
/// (NaN for none).
fn mean_over(m: &MpmSolver, set: &BTreeSet<u32>, f: impl Fn(usize) -> f64) -> f64 {
    let (mut sum, mut n) = (0.0, 0usize);
    for (p, id) in m.particle_ids().iter().enumerate() {
        if set.contains(id) {
            sum += f(p);
            n += 1;
        }
    }
    if n > 0 {
        sum / n as f64
    } else {
        f64::NAN
    }
}

/// Runs configs/cylinder_icempm.ron as `setup` says to its end time.
pub fn cylinder_quarter_run(setup: &QuarterSetup) -> Result<QuarterRun, String> {
    let loaded = load_str(FILE, CYLINDER_QUARTER_CONFIG, &setup.sets).map_err(|e| e.to_string())?;
    let s = &loaded.scenario;
    let Some(section) = s.pipeline.section::<IceMpmConfig>() else {
        return Err(format!("{FILE} is not an IceMpm pipeline"));
    };
    let gauge_z = setup.gauge_z;
    if !(gauge_z > s.domain.lower[2] && gauge_z < s.domain.upper[2]) {
        return Err(format!(
            "cylinder quarter: the gauge's z = {gauge_z} m is not inside the domain"
        ));
    }
    let mut solver = build_section(section, s).map_err(|e| loaded.locate(e).to_string())?;
    let t_end = s.time.end;
    let energy_start = Solver::conservation_totals(&solver).energy;
    let (r_in, r_out, _) = TUBE;
    let extent: [f64; 3] = std::array::from_fn(|d| s.domain.upper[d] - s.domain.lower[d]);
    let h = (0..3)
        .map(|d| extent[d] / s.domain.cells[d] as f64)
        .fold(0.0, f64::max);
    // The outer-wall particles at the gauge, by identity.
    let ps = solver.mpm().particles();
    let ids = solver.mpm().particle_ids();
    let r_max = (0..ps.len())
        .map(|p| ps.position[p][0].hypot(ps.position[p][1]))
        .fold(0.0, f64::max);
    let gauge: BTreeSet<u32> = (0..ps.len())
        .filter(|&p| {
            let x = ps.position[p];
            x[0].hypot(x[1]) > r_max - 0.5 * h && (x[2] - gauge_z).abs() < 1e-3
        })
        .map(|p| ids[p])
        .collect();
    if gauge.is_empty() {
        return Err(format!(
            "cylinder quarter: no outer-wall particle at the gauge (z = {gauge_z} m)"
        ));
    }
    let gauge_radius = |m: &MpmSolver| {
        let ps = m.particles();
        mean_over(m, &gauge, |p| ps.position[p][0].hypot(ps.position[p][1]))
    };
    let radial = |m: &MpmSolver| {
        let ps = m.particles();
        mean_over(m, &gauge, |p| {
            let (x, v) = (ps.position[p], ps.velocity[p]);
            (x[0] * v[0] + x[1] * v[1]) / x[0].hypot(x[1])
        })
    };
    let gauge_r0 = gauge_radius(solver.mpm());
    let slice: BTreeSet<u32> = (0..ps.len())
        .filter(|&p| (ps.position[p][2] - gauge_z).abs() < 0.5 * h)
        .map(|p| ids[p])
        .collect();
    let slice_speed = |m: &MpmSolver| -> f64 {
        let (ps, ids) = (m.particles(), m.particle_ids());
        let (mut ke, mut mass) = (0.0, 0.0);
        for (p, id) in ids.iter().enumerate() {
            if slice.contains(id) {
                let (x, v) = (ps.position[p], ps.velocity[p]);
                let vr = (x[0] * v[0] + x[1] * v[1]) / x[0].hypot(x[1]);
                ke += ps.mass[p] * vr * vr;
                mass += ps.mass[p];
            }
        }
        (ke / mass).sqrt()
    };
    let axis = [0.5 * h, 0.5 * h, gauge_z];
    let mut fronts: Vec<(f64, Option<f64>)> = (0..17)
        .map(|i| (gauge_z - 0.05 + 0.005 * i as f64, None))
        .filter(|f| f.0 > 0.0 && f.0 < s.domain.upper[2])
        .collect();
    let fields = ["volume_fraction_2".to_string()];
    let mut sample = Vec::new();
    let mut record = Vec::new();
    let mut slice_end = f64::NAN;
    let mut arrival = None;
    let mut steps = 0usize;
    let mut failure = None;
    let start = Instant::now();
    while solver.time() < t_end * (1.0 - 1e-12) {
        let step = solver
            .stable_dt()
            .and_then(|dt| solver.advance(dt.min(t_end - solver.time())));
        if let Err(e) = step {
            failure = Some(e.to_string());
            break;
        }
        steps += 1;
        for f in fronts.iter_mut().filter(|f| f.1.is_none()) {
            solver
                .sample([0.5 * h, 0.5 * h, f.0], &fields, &mut sample)
                .map_err(|e| e.to_string())?;
            if sample[0] > 0.5 {
                f.1 = Some(solver.time());
            }
        }
        if arrival.is_none() {
            solver
                .sample(axis, &fields, &mut sample)
                .map_err(|e| e.to_string())?;
            if sample[0] > 0.5 {
                arrival = Some(solver.time());
            }
        }
        record.push((solver.time(), radial(solver.mpm())));
        slice_end = slice_speed(solver.mpm());
    }
    let wall_s = start.elapsed().as_secs_f64();
    let r_out_end = gauge_radius(solver.mpm()) * r_out / gauge_r0;
    let inner_radius_end = (r_out_end * r_out_end - (r_out * r_out - r_in * r_in))
        .max(0.0)
        .sqrt();
    let relative_volume_end = (inner_radius_end / r_in).powi(2);
    let gurney = tube_gurney(s, FILE)?;
    let gurney_at_end = if relative_volume_end.is_finite() && relative_volume_end > 1.0 {
        gurney_estimate(&gurney.products, &gurney.cj, relative_volume_end, 1e-11)
            .ok()
            .and_then(|ge| cylinder_wall_velocity(ge.gurney_velocity, gurney.m_over_c).ok())
    } else {
        None
    };
    let names: Vec<String> = section
        .ice
        .materials
        .iter()
        .cloned()
        .chain(section.solid.names().iter().cloned())
        .collect();
    let named = |totals: &[KeptWarmTotals]| -> Vec<(String, KeptWarmTotals)> {
        totals
            .iter()
            .enumerate()
            .map(|(r, k)| (names.get(r).cloned().unwrap_or_else(|| "?".into()), *k))
            .collect()
    };
    Ok(QuarterRun {
        h,
        extent,
        cells: s.domain.cells.iter().product(),
        particles: solver.particles_per_step(),
        steps,
        wall_s,
        time: solver.time(),
        gauge_z,
        arrival,
        fronts,
        record,
        slice_end,
        inner_radius_end,
        relative_volume_end,
        gurney,
        gurney_at_end,
        energy_start,
        kept_warm: named(solver.ice().kept_warm_totals()),
        kept_warm_advection: named(solver.ice().kept_warm_advection_totals()),
        failure,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A run with nothing but the fronts and the record given.
    fn run_with(fronts: Vec<(f64, Option<f64>)>, record: Vec<(f64, f64)>) -> QuarterRun {
        let gurney = super::super::rz_gurney().unwrap();
        QuarterRun {
            h: 2e-3,
            extent: [0.056, 0.056, 0.2],
            cells: 1,
            particles: 1,
            steps: record.len(),
            wall_s: 1.0,
            time: 0.0,
            gauge_z: QUARTER_GAUGE_Z,
            arrival: None,
            fronts,
            record,
            slice_end: f64::NAN,
            inner_radius_end: TUBE.0,
            relative_volume_end: 1.0,
            gurney,
            gurney_at_end: None,
            energy_start: 1.0,
            kept_warm: Vec::new(),
            kept_warm_advection: Vec::new(),
            failure: None,
        }
    }

    #[test]
    fn detonation_velocity_and_terminal_by_hand() {
        // Arrivals at 0, 1, 2 and 3 cm at 0, 2, 4 and 6 µs: 5000 m/s; one
        // front not reached is left out.
        let fronts = vec![
            (0.0, Some(0.0)),
            (0.01, Some(2e-6)),
            (0.02, Some(4e-6)),
            (0.03, Some(6e-6)),
            (0.04, None),
        ];
        // Twenty samples: the last two (the last tenth) at 100 and 300 m/s.
        let mut record: Vec<(f64, f64)> = (0..18).map(|i| (i as f64, 0.0)).collect();
        record.extend([(18.0, 100.0), (19.0, 300.0)]);
        let run = run_with(fronts.clone(), record.clone());
        assert!((run.detonation_velocity() - 5000.0).abs() < 1e-6);
        assert_eq!(run.terminal(), 200.0);
        // Two arrivals are not a fit; a stopped run has no terminal figure.
        let two = run_with(fronts[..2].to_vec(), record);
        assert!(two.detonation_velocity().is_nan());
        let stopped = QuarterRun {
            failure: Some("stopped".into()),
            ..run
        };
        assert!(stopped.terminal().is_nan());
        assert!(run_with(fronts, Vec::new()).terminal().is_nan());
    }

    /// The shipped quarter at its 2 mm cells, shortened to 4 cm of tube
    /// with the gauge at 2 cm, to 6.5 µs: the detonation crosses the gauge,
    /// the outer wall there starts to move out, and the run's bookkeeping
    /// is the pipeline's.
    #[test]
    fn a_short_tube_detonates_past_its_gauge_and_its_wall_moves_out() {
        let setup = QuarterSetup {
            sets: vec![
                "domain.upper=(0.056, 0.056, 0.04)".into(),
                "domain.cells=(28, 28, 20)".into(),
                "time.end=6.5e-6".into(),
                "outputs.gauges=[]".into(),
                "outputs.particle_gauges=[]".into(),
            ],
            gauge_z: 0.02,
        };
        let run = cylinder_quarter_run(&setup).unwrap();
        assert!(run.failure.is_none(), "{:?}", run.failure);
        assert_eq!((run.h, run.cells), (2e-3, 28 * 28 * 20));
        assert_eq!(run.record.len(), run.steps);
        assert!((run.time - 6.5e-6).abs() < 1e-15);
        // The detonation builds up from the booster's 6 mm of products at
        // 10 GPa (docs/physics/couple/ice_mpm_cylinder_audit.md): measured,
        // 2 cm at 4.59 µs, 3 cm at 6.23 µs (6.2 km/s over the last 5 mm).
        let t = run.arrival.unwrap();
        assert!(t > 3.5e-6 && t < 5.5e-6, "{t}");
        // Fronts every 5 mm inside the 4 cm; at 6.5 µs all but the last.
        let zs: Vec<f64> = run.fronts.iter().map(|f| f.0).collect();
        assert_eq!(zs.len(), 7, "{zs:?}");
        assert!(
            run.fronts[..6].iter().all(|f| f.1.is_some()),
            "{:?}",
            run.fronts
        );
        assert!(run.fronts[6].1.is_none(), "{:?}", run.fronts);
        assert_eq!(run.fronts[3].1, run.arrival);
        let d = run.detonation_velocity();
        assert!(d > 3000.0 && d < 9000.0, "{d}");
        // The wall at the gauge moves out, and has not gone far.
        let v = run.record.last().unwrap().1;
        assert!(v > 0.0 && v < run.gurney.wall, "{v}");
        assert!(run.relative_volume_end >= 1.0 && run.relative_volume_end < 1.2);
        assert!(run.terminal().is_finite());
        let names: Vec<&str> = run.kept_warm.iter().map(|k| k.0.as_str()).collect();
        assert_eq!(names, ["qm100", "products", "air", "copper"]);
        assert_eq!(run.kept_warm_advection.len(), 4);
        assert!(run.energy_start > 0.0);
        assert!((run.gurney.m_over_c - 3.199).abs() < 1e-3);
    }

    #[test]
    fn bad_setups_are_refused() {
        let outside = QuarterSetup {
            gauge_z: 0.3,
            ..QuarterSetup::shipped()
        };
        let e = cylinder_quarter_run(&outside).unwrap_err();
        assert!(e.starts_with("cylinder quarter: "), "{e}");
        let bad = QuarterSetup {
            sets: vec!["time.end=-1.0".into()],
            ..QuarterSetup::shipped()
        };
        let e = cylinder_quarter_run(&bad).unwrap_err();
        assert!(e.starts_with(FILE), "{e}");
    }
}
