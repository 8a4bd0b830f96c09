//! The copper cylinder test of seed 000 §5.2: the Gurney estimate of its
//! terminal wall velocity (E-CYLINDER on the 3D quarter, E-CYLINDER-RZ on
//! rings, E-PD-CYL-ICEMPM) and E-CYLINDER-RZ's run (configs/cylinder_rz.ron
//! at one cell size: the axis detonation speed, the outer wall's radial
//! velocity at 25 cm, the coupled energy's closure and what the cold-material
//! rules and step 2's rescale added, and the 1D QM-100 column at the same
//! h beside it). `cargo xtask validate --only cylinder-rz` (and
//! `cylinder-rz-slip`, `pd-icempm-cyl`) write the report's tables from it.
//! E-CYLINDER's run on the 3D quarter is [`quarter`]
//! (`cargo xtask validate --only cylinder`).

use std::collections::BTreeSet;
use std::time::Instant;

use brisance_compose::build::build_section;
use brisance_compose::config::Scenario;
use brisance_compose::load_str;
use brisance_core::Solver;
use brisance_couple::IceMpmConfig;
use brisance_eos::tools::gurney::CYLINDER_TEST_RELATIVE_VOLUME;
use brisance_eos::tools::{
    cj_on_jwl_cterm_isentrope, cylinder_wall_velocity, gurney_estimate, CjState, GurneyEstimate,
};
use brisance_eos::{EosModel, JwlCTerm};
use brisance_ice::column::{run_column, Column};
use brisance_mpm::MpmSolver;

use crate::last_tenth_mean;

pub mod quarter;
pub use quarter::{
    cylinder_quarter_run, QuarterRun, QuarterSetup, CYLINDER_QUARTER_CONFIG, QUARTER_GAUGE_Z,
};

/// The scenario, configs/cylinder_rz.ron.
pub const CYLINDER_RZ_CONFIG: &str = include_str!("../../../configs/cylinder_rz.ron");

/// The copper tube of the cylinder test (seed 000 §5.2): inner and outer
/// radius, m, and density, kg/m³.
pub const TUBE: (f64, f64, f64) = (0.0254, 0.0306, 8930.0);

/// The axis gauges of configs/cylinder_rz.ron, m (D between them).
pub const RZ_AXIS: [f64; 2] = [0.20, 0.25];
/// Length of configs/cylinder_rz.ron's charge, m (booster included).
pub const RZ_CHARGE: f64 = 0.35;
/// The (r, z) extent of configs/cylinder_rz.ron's domain, m: a run at
/// cell size h has (extent / h) cells along each.
pub const RZ_DOMAIN: [f64; 2] = [0.08, 0.36];
/// The wall gauge of configs/cylinder_rz.ron: outer-wall particles
/// starting at r 29.6–30.7 mm and within 1 mm of z = 25 cm.
pub const RZ_WALL: ([f64; 2], f64, f64) = ([0.0296, 0.0307], 0.25, 1e-3);
/// The axis pressure at which the detonation counts as arrived, Pa.
pub const ARRIVAL_PRESSURE: f64 = 1e9;

/// The Gurney estimate of the cylinder test's terminal wall velocity
/// (docs/physics/couple/ice_mpm_cylinder_audit.md).
#[derive(Debug, Clone, Copy)]
pub struct TubeGurney {
    /// The scenario's `products` (JWL C-term).
    pub products: JwlCTerm,
    /// Their CJ state on the principal isentrope.
    pub cj: CjState,
    /// The products' Gurney energy from CJ to V = 7.
    pub estimate: GurneyEstimate,
    /// The tube's metal-to-charge mass ratio M/C.
    pub m_over_c: f64,
    /// The open-ended cylinder's wall velocity at that M/C, m/s.
    pub wall: f64,
}

/// [`TubeGurney`] for scenario `s` (`config` names it in errors): its
/// `products` on their principal isentrope from CJ to V = 7, and M/C of
/// the copper tube [`TUBE`] filled with products at their ρ₀.
pub fn tube_gurney(s: &Scenario, config: &str) -> Result<TubeGurney, String> {
    let products = match s.materials.get("products").and_then(|m| m.eos()) {
        Some(EosModel::JwlCTerm(j)) => *j,
        _ => return Err(format!("{config}: `products` is not JwlCTerm")),
    };
    let cj = cj_on_jwl_cterm_isentrope(&products).map_err(|e| format!("{config}: CJ: {e}"))?;
    let estimate = gurney_estimate(&products, &cj, CYLINDER_TEST_RELATIVE_VOLUME, 1e-11)
        .map_err(|e| format!("{config}: Gurney: {e}"))?;
    let (r_in, r_out, rho) = TUBE;
    let m_over_c = rho * (r_out * r_out - r_in * r_in) / (products.rho0 * r_in * r_in);
    let wall = cylinder_wall_velocity(estimate.gurney_velocity, m_over_c)
        .map_err(|e| format!("{config}: {e}"))?;
    Ok(TubeGurney {
        products,
        cj,
        estimate,
        m_over_c,
        wall,
    })
}

/// The CJ state and Gurney wall velocity of configs/cylinder_rz.ron as
/// shipped.
pub fn rz_gurney() -> Result<TubeGurney, String> {
    let loaded =
        load_str("configs/cylinder_rz.ron", CYLINDER_RZ_CONFIG, &[]).map_err(|e| e.to_string())?;
    tube_gurney(&loaded.scenario, "configs/cylinder_rz.ron")
}

/// How one E-CYLINDER-RZ run is set up.
#[derive(Debug, Clone)]
pub struct CylinderRzSetup {
    /// Cell size, m (the same in r and z).
    pub h: f64,
    /// `--set` overrides added after the cell count.
    pub sets: Vec<String>,
    /// Wall-time budget, s: the run stops after it with a failure that
    /// says where it got to.
    pub budget_s: f64,
    /// End time, s; the scenario's (80 µs) where `None`.
    pub end: Option<f64>,
    /// Add the fluids' and the particles' stable steps and the fluids'
    /// fastest signal to every progress line.
    pub explain_steps: bool,
    /// Run the 1D QM-100 column at the same h beside the tube.
    pub column: bool,
}

impl CylinderRzSetup {
    /// The shipped case at cell size `h`, with the scenario's end, the
    /// column beside it and `budget_s` of wall time.
    pub fn at(h: f64, budget_s: f64) -> Self {
        Self {
            h,
            sets: Vec::new(),
            budget_s,
            end: None,
            explain_steps: false,
            column: true,
        }
    }
}

/// One h of E-CYLINDER-RZ.
#[derive(Debug, Clone)]
pub struct RzRun {
    /// Cell size, m.
    pub h: f64,
    /// Axis arrivals (pressure above [`ARRIVAL_PRESSURE`]) at the two
    /// gauges of [`RZ_AXIS`], s.
    pub arrival: [Option<f64>; 2],
    /// The 1D QM-100 column's D at the same h and ν*, m/s (`None` where
    /// not run or where it found no front).
    pub column: Option<f64>,
    /// The outer-wall gauge's mean radial velocity against time, s, m/s.
    pub record: Vec<(f64, f64)>,
    /// Largest |E(t)/E(0) − 1| of the coupled total energy, and its end
    /// value.
    pub energy: (f64, f64),
    /// What steps 2 and 12's cold-material rules (with the fluid traces
    /// held at the solid's temperature in steps 2 and 8–11) added over
    /// the run, relative to E(0) (`IceSolver::kept_warm_totals`).
    pub kept_warm: f64,
    /// What step 2's rescale gave the fluids over the run (booked in the
    /// total, heat of reaction included), relative to E(0).
    pub rescaled: f64,
    /// Wall time, s.
    pub wall_s: f64,
    /// Steps taken.
    pub steps: usize,
    /// Why the run stopped before its end: the solver's error or the
    /// spent budget.
    pub failure: Option<String>,
}

impl RzRun {
    /// D between the two axis gauges, m/s (NaN until both have arrived).
    pub fn detonation_velocity(&self) -> f64 {
        match self.arrival {
            [Some(a), Some(b)] if b > a => (RZ_AXIS[1] - RZ_AXIS[0]) / (b - a),
            _ => f64::NAN,
        }
    }

    /// Mean over the last 10 % of the record, m/s (NaN if the run stopped
    /// or the wave never reached the gauge).
    pub fn terminal(&self) -> f64 {
        if self.failure.is_some() || self.arrival[1].is_none() || self.record.is_empty() {
            return f64::NAN;
        }
        last_tenth_mean(&self.record, |x| x.1)
    }

    /// The number of (r, z) cells at cell size `h`, m.
    pub fn rings(h: f64) -> usize {
        let [r, z] = rz_cells(h);
        r * z
    }
}

/// The cells along r and along z at cell size `h`, m (the run's
/// `domain.cells`).
fn rz_cells(h: f64) -> [usize; 2] {
    RZ_DOMAIN.map(|l| (l / h).round() as usize)
}

/// Runs configs/cylinder_rz.ron as `setup` says; `progress` gets a line
/// every 1000 steps.
pub fn cylinder_rz_run(
    setup: &CylinderRzSetup,
    progress: &mut dyn FnMut(&str),
) -> Result<RzRun, String> {
    let h = setup.h;
    if !(h.is_finite() && h > 0.0 && h <= RZ_DOMAIN[0]) {
        return Err(format!(
            "cylinder r–z: cell size {h} m is not in (0, {}]",
            RZ_DOMAIN[0]
        ));
    }
    if let Some(e) = setup.end {
        if !(e.is_finite() && e > 0.0) {
            return Err(format!("cylinder r–z: end time {e} s is not positive"));
        }
    }
    let [nr, nz] = rz_cells(h);
    let mut all = vec![format!("domain.cells=({nr},{nz},1)")];
    all.extend_from_slice(&setup.sets);
    let loaded =
        load_str("configs/cylinder_rz.ron", CYLINDER_RZ_CONFIG, &all).map_err(|e| e.to_string())?;
    let s = &loaded.scenario;
    let Some(section) = s.pipeline.section::<IceMpmConfig>() else {
        return Err("configs/cylinder_rz.ron is not an IceMpm pipeline".into());
    };
    let nu = section.ice.face_pressure_courant;
    let mut solver = build_section(section, s).map_err(|e| loaded.locate(e).to_string())?;
    let t_end = setup.end.unwrap_or(s.time.end);
    let e0 = solver.conservation_totals().energy;
    let rescaled0 = solver.rescaled_totals().energy;
    let ps = solver.mpm().particles();
    let ((r_lo, r_hi), z, dz) = ((RZ_WALL.0[0], RZ_WALL.0[1]), RZ_WALL.1, RZ_WALL.2);
    let gauge: BTreeSet<u32> = (0..ps.len())
        .filter(|&p| {
            let x = ps.position[p];
            x[0] > r_lo && x[0] < r_hi && (x[1] - z).abs() < dz
        })
        .map(|p| solver.mpm().particle_ids()[p])
        .collect();
    if gauge.is_empty() {
        return Err(format!(
            "cylinder r–z: no outer-wall particle at the gauge (h = {h} m)"
        ));
    }
    let radial = |m: &MpmSolver| -> f64 {
        let (ps, ids) = (m.particles(), m.particle_ids());
        let (mut sum, mut n) = (0.0, 0usize);
        for (p, id) in ids.iter().enumerate() {
            if gauge.contains(id) {
                sum += ps.velocity[p][0];
                n += 1;
            }
        }
        sum / n as f64
    };
    let mut run = RzRun {
        h,
        arrival: [None; 2],
        column: None,
        record: Vec::new(),
        energy: (0.0, 0.0),
        kept_warm: 0.0,
        rescaled: 0.0,
        wall_s: 0.0,
        steps: 0,
        failure: None,
    };
    let budget_s = setup.budget_s;
    let fields = ["pressure".to_string()];
    let mut sample = Vec::new();
    let mut next_energy = 0.0;
    let start = Instant::now();
    while solver.time() < t_end * (1.0 - 1e-12) {
        let step = solver
            .stable_dt()
            .and_then(|dt| solver.advance(dt.min(t_end - solver.time())));
        if let Err(e) = step {
            run.failure = Some(e.to_string());
            break;
        }
        run.steps += 1;
        let t = solver.time();
        if start.elapsed().as_secs_f64() > budget_s && t < t_end * (1.0 - 1e-12) {
            run.failure = Some(format!(
                "the wall-time budget of {budget_s:.0} s was spent at t = {:.2} µs, step {}, Δt {:.2e} s; the fluids' fastest signal: {}",
                t * 1e6,
                run.steps,
                solver.stable_dt().unwrap_or(f64::NAN),
                solver.ice().fastest_signal()
            ));
            break;
        }
        if run.steps.is_multiple_of(1000) {
            let mut line = format!(
                "    h {:.2} mm: step {}, t = {:.2} µs, {:.0} s",
                h * 1e3,
                run.steps,
                t * 1e6,
                start.elapsed().as_secs_f64()
            );
            if setup.explain_steps {
                line.push_str(&format!(
                    "\n      Δt: fluids {:?}, particles {:?}; fastest: {}",
                    solver.ice().stable_dt(),
                    solver.mpm().stable_dt(),
                    solver.ice().fastest_signal()
                ));
            }
            progress(&line);
        }
        for (k, zk) in RZ_AXIS.iter().enumerate() {
            if run.arrival[k].is_some() {
                continue;
            }
            solver
                .sample([1e-4, *zk, 1e-3], &fields, &mut sample)
                .map_err(|e| e.to_string())?;
            if sample[0] > ARRIVAL_PRESSURE {
                run.arrival[k] = Some(t);
            }
        }
        run.record.push((t, radial(solver.mpm())));
        if t >= next_energy || t >= t_end * (1.0 - 1e-12) {
            let rel = solver.conservation_totals().energy / e0 - 1.0;
            run.energy.1 = rel;
            if !(rel.abs() <= run.energy.0) {
                run.energy.0 = rel.abs();
            }
            next_energy = t + 1e-6;
        }
    }
    run.wall_s = start.elapsed().as_secs_f64();
    run.rescaled = (solver.rescaled_totals().energy - rescaled0) / e0;
    let ice = solver.ice();
    run.kept_warm = ice
        .kept_warm_totals()
        .iter()
        .chain(ice.kept_warm_advection_totals())
        .map(|k| k.energy)
        .sum::<f64>()
        / e0;
    // The column is the tube's charge without the tube: the same 35 cm of
    // QM-100 behind the same booster, D timed between the axis gauges' 20
    // and 25 cm, so the two figures differ only by the wall and the rings.
    if setup.column {
        let column = Column {
            face_pressure_courant: nu,
            length: RZ_CHARGE,
            gauges: [RZ_AXIS[0], 0.22, 0.24, RZ_AXIS[1]],
            ..Column::qm100(h)
        };
        run.column = run_column(&column).ok().and_then(|r| r.detonation_velocity);
    }
    Ok(run)
}

#[cfg(test)]
mod tests {
    use super::{cylinder_rz_run, rz_gurney, tube_gurney, CylinderRzSetup, RzRun, RZ_AXIS, TUBE};
    use crate::cases::SOD_CONFIG;

    #[test]
    fn the_gurney_estimate_is_the_open_cylinders_of_the_tubes_mass_ratio() {
        let g = rz_gurney().expect("configs/cylinder_rz.ron's products");
        let (r_in, r_out, rho) = TUBE;
        // M/C by hand: the copper annulus over the charge's disc.
        let m_over_c = rho * (r_out * r_out - r_in * r_in) / (g.products.rho0 * r_in * r_in);
        assert_eq!(g.m_over_c, m_over_c);
        // The open-ended cylinder: v = √(2E) (M/C + 1/2)^(−1/2).
        let v = g.estimate.gurney_velocity / (g.m_over_c + 0.5).sqrt();
        assert!((g.wall - v).abs() <= 1e-9 * v, "{} vs {v}", g.wall);
        // The figures the report prints for QM-100 in the copper tube.
        assert!((g.m_over_c - 3.20).abs() < 5e-3, "{}", g.m_over_c);
        assert!((g.cj.detonation_velocity - 6503.0).abs() < 1.0);
        assert!((g.estimate.gurney_velocity - 2080.0).abs() < 1.0);
        assert!((g.wall - 1082.0).abs() < 1.0, "{}", g.wall);
    }

    #[test]
    fn a_scenario_without_jwl_c_term_products_has_no_estimate() {
        let loaded = brisance_compose::load_str("sod.ron", SOD_CONFIG, &[]).unwrap();
        let e = tube_gurney(&loaded.scenario, "sod.ron").unwrap_err();
        assert_eq!(e, "sod.ron: `products` is not JwlCTerm");
    }

    #[test]
    fn a_coarse_tube_detonates_past_both_gauges_and_moves_its_wall() {
        // 2 mm cells (the report's coarsest) to 60 µs, past the arrival
        // at 25 cm (about 50 µs).
        let setup = CylinderRzSetup {
            column: false,
            end: Some(6e-5),
            ..CylinderRzSetup::at(2e-3, 1e9)
        };
        let mut lines = 0;
        let run = cylinder_rz_run(&setup, &mut |_| lines += 1).expect("the coarse tube runs");
        assert_eq!(RzRun::rings(2e-3), 40 * 180);
        assert!(run.failure.is_none(), "{:?}", run.failure);
        assert_eq!(run.record.len(), run.steps);
        assert_eq!(lines, run.steps / 1000);
        assert!((run.record.last().unwrap().0 - 6e-5).abs() < 1e-12);
        let [Some(a), Some(b)] = run.arrival else {
            panic!("arrivals {:?}", run.arrival)
        };
        assert!(a < b);
        assert_eq!(
            run.detonation_velocity(),
            (RZ_AXIS[1] - RZ_AXIS[0]) / (b - a)
        );
        // The axis runs below D_CJ at this h (the report's 2 mm row:
        // 5024 m/s, −22.7 %), the wall is moving out by 60 µs and the
        // coupled energy holds within a few per cent.
        let g = rz_gurney().unwrap();
        let d = run.detonation_velocity() / g.cj.detonation_velocity;
        assert!((0.7..1.02).contains(&d), "D/D_CJ {d}");
        let v = run.terminal();
        assert!(v > 0.2 * g.wall && v < 1.2 * g.wall, "{v}");
        assert!(run.energy.0 < 0.05 && run.energy.0 >= run.energy.1.abs());
        assert!(run.column.is_none());
    }

    #[test]
    fn a_grid_too_coarse_for_the_wall_gauge_names_the_file_line_and_field() {
        // At 4 mm no copper particle starts inside the config's outer-wall
        // gauge: the build refuses it, at the gauge's place in the file.
        let e = cylinder_rz_run(&CylinderRzSetup::at(4e-3, 1.0), &mut |_| {}).unwrap_err();
        let text = super::CYLINDER_RZ_CONFIG;
        let line = 1 + text[..text.find("outer_wall_250").unwrap()]
            .matches('\n')
            .count();
        assert!(
            e.starts_with(&format!("configs/cylinder_rz.ron:{line}:")),
            "{e}"
        );
        assert!(e.contains("`outputs.particle_gauges.0.region`"), "{e}");
    }

    #[test]
    fn bad_setups_are_refused() {
        for (h, end) in [
            (0.0, None),
            (f64::INFINITY, None),
            (0.1, None),
            (2e-3, Some(0.0)),
        ] {
            let setup = CylinderRzSetup {
                end,
                ..CylinderRzSetup::at(h, 1.0)
            };
            let e = cylinder_rz_run(&setup, &mut |_| {}).unwrap_err();
            assert!(e.starts_with("cylinder r–z: "), "{e}");
        }
    }
}
