//! V-ICE-MPM: the coupling checks of the ICE–MPM step (seed 000 §3.3) —
//! the piston-driven shock against its exact solution under refinement, a
//! gas-filled box at rest, a block floating in a uniform stream, and the
//! bookkeeping of a closed tube. The cases are
//! `brisance::couple::ice_mpm::cases`, shared with the unit tests.

use std::fmt::Write as _;
use std::time::Instant;

use anyhow::{anyhow, Result};
use brisance::couple::ice_mpm::cases;

use crate::Report;

pub fn v_ice_mpm(report: &mut Report) -> Result<()> {
    println!("V-ICE-MPM: coupling checks of the ICE–MPM step");
    let md = &mut report.md;
    let _ = writeln!(md, "## V-ICE-MPM — coupling checks of the ICE–MPM step\n");
    let _ = writeln!(
        md,
        "Air (γ = 1.4, 1 atm, 300 K) and steel (particles: hypoelastic K = 160 GPa, G = 80 GPa; \
         equilibration: Murnaghan with the same K under the 1 atm threshold), linear shape \
         functions, MUSL, 2 particles per cell per direction, K = 10¹⁵ kg/(m³·s). \
         See docs/physics/couple/ice_mpm.md.\n"
    );
    let _ = writeln!(
        md,
        "**Piston.** A 1 cm steel piston at 100 m/s into air at rest in a 1D tube; at 100 µs, \
         the mean pressure over the middle half between piston face and shock against the exact \
         piston-driven shock (1.498 bar, 412.3 m/s).\n"
    );
    let _ = writeln!(
        md,
        "| Δx (mm) | plateau (bar) | error | shock error (cells) | piston (m/s) | wall (s) |\n|---:|---:|---:|---:|---:|---:|"
    );
    let mut worst_plateau = 0.0_f64;
    let mut worst_shock = 0.0_f64;
    for h in [1e-3, 0.5e-3, 0.25e-3] {
        let start = Instant::now();
        let m = cases::piston(h).map_err(|e| anyhow!("piston at {h} m: {e}"))?;
        let wall = start.elapsed().as_secs_f64();
        println!("  h = {h:e} m: {m:?} ({wall:.1} s)");
        let _ = writeln!(
            md,
            "| {:.2} | {:.4} | {:+.2} % | {:+.2} | {:.2} | {:.1} |",
            h * 1e3,
            m.plateau / 1e5,
            100.0 * m.plateau_error,
            m.shock_error_cells,
            m.piston_velocity,
            wall
        );
        worst_plateau = worst_plateau.max(m.plateau_error.abs());
        worst_shock = worst_shock.max(m.shock_error_cells.abs());
    }
    let _ = writeln!(md);
    let (box_solid, box_gas) = cases::box_at_rest(200).map_err(|e| anyhow!("box at rest: {e}"))?;
    let (block_solid, block_gas) =
        cases::floating_block(200).map_err(|e| anyhow!("floating block: {e}"))?;
    let (mass, energy, rescaled) =
        cases::closed_tube(400).map_err(|e| anyhow!("closed tube: {e}"))?;
    let _ = writeln!(
        md,
        "**Box at rest** (2D steel box, air inside and out, 200 steps): largest particle speed \
         {box_solid:.2e} m/s, largest cell speed {box_gas:.2e} m/s.\n\n\
         **Floating block** (block and air at 20 m/s, 200 steps): largest deviation \
         {block_solid:.2e} m/s on the particles, {block_gas:.2e} m/s in the air.\n\n\
         **Closed tube** (piston at 100 m/s between walls, 400 steps): mass bookkeeping closes to \
         {mass:.1e}; total energy changed by {energy:+.2e} of the piston's kinetic energy; the \
         equilibration moved {rescaled:+.2e} of the air's mass (booked).\n"
    );
    let _ = writeln!(md, "| check | measured | target | |\n|---|---:|---:|---|");
    report.target(
        "piston plateau, worst of 1/0.5/0.25 mm",
        format!("{:.2} %", 100.0 * worst_plateau),
        "≤ 3 %",
        worst_plateau <= 0.03,
    );
    report.target(
        "piston shock position, worst",
        format!("{worst_shock:.2} cells"),
        "≤ 1 cell",
        worst_shock <= 1.0,
    );
    report.target(
        "box at rest: spurious speed",
        format!("{:.2e} m/s", box_solid.max(box_gas)),
        "≤ 1e-3 m/s",
        box_solid.max(box_gas) <= 1e-3,
    );
    report.target(
        "floating block: deviation from 20 m/s",
        format!("{:.2e} m/s", block_solid.max(block_gas)),
        "≤ 1e-2 m/s",
        block_solid.max(block_gas) <= 1e-2,
    );
    report.target(
        "closed tube: energy change / piston kinetic energy",
        format!("{energy:+.2e}"),
        "≤ 5e-3",
        energy.abs() <= 5e-3,
    );
    let _ = writeln!(report.md);
    Ok(())
}

/// Axial position of the wall gauge, m: 5 cm from initiation, 5 cm before
/// the tube's open end (the end's rarefaction reaches it about 19 µs after
/// the detonation does, later than the record).
const GAUGE_Z: f64 = 0.05;

/// E-CYLINDER: configs/cylinder_icempm.ron (the seed 000 §5.2 copper
/// cylinder test, reduced): the mean radial velocity of the outer-wall
/// particles that start within 1 mm of z = GAUGE_Z, time-shifted to the
/// detonation's arrival there (products volume fraction on the axis above
/// 1/2), and its terminal value against the Gurney estimate.
pub fn e_cylinder(report: &mut Report, img: &std::path::Path) -> Result<()> {
    use brisance::compose::build::{build, Built};
    use brisance::compose::load_str;
    use brisance::core::Solver;
    use brisance::eos::tools::gurney::CYLINDER_TEST_RELATIVE_VOLUME;
    use brisance::eos::tools::{
        cj_on_jwl_cterm_isentrope, cylinder_wall_velocity, gurney_estimate,
    };
    use brisance::eos::JwlCTerm;

    println!("E-CYLINDER: copper cylinder test on the IceMpm pipeline (reduced)");
    let text = include_str!("../../configs/cylinder_icempm.ron");
    let loaded = load_str("cylinder_icempm.ron", text, &[])
        .map_err(|e| anyhow!("configs/cylinder_icempm.ron: {e}"))?;
    let s = &loaded.scenario;
    let Built::IceMpm { solver, .. } = build(s).map_err(|e| anyhow!("{e}"))? else {
        return Err(anyhow!(
            "configs/cylinder_icempm.ron is not an IceMpm pipeline"
        ));
    };
    let mut solver = solver;
    let t_end = s.time.end;
    // The outer-wall particles at the gauge, by identity.
    let (r_in, r_out) = (0.0254, 0.0306);
    let h = s
        .domain
        .cells
        .iter()
        .zip(0..3)
        .map(|(n, d)| (s.domain.upper[d] - s.domain.lower[d]) / *n as f64)
        .fold(0.0, f64::max);
    let ps = solver.mpm().particles();
    let ids = solver.mpm().particle_ids();
    let r_max = (0..ps.len())
        .map(|p| ps.position[p][0].hypot(ps.position[p][1]))
        .fold(0.0, f64::max);
    let gauge: std::collections::BTreeSet<u32> = (0..ps.len())
        .filter(|&p| {
            let x = ps.position[p];
            x[0].hypot(x[1]) > r_max - 0.5 * h && (x[2] - GAUGE_Z).abs() < 1e-3
        })
        .map(|p| ids[p])
        .collect();
    if gauge.is_empty() {
        return Err(anyhow!("no outer-wall particle at the gauge"));
    }
    let gauge_radius = |m: &brisance::mpm::MpmSolver| -> f64 {
        let (ps, ids) = (m.particles(), m.particle_ids());
        let (mut sum, mut n) = (0.0, 0);
        for (p, id) in ids.iter().enumerate() {
            if gauge.contains(id) {
                sum += ps.position[p][0].hypot(ps.position[p][1]);
                n += 1;
            }
        }
        sum / n as f64
    };
    let gauge_r0 = gauge_radius(solver.mpm());
    let radial = |m: &brisance::mpm::MpmSolver| -> f64 {
        let (ps, ids) = (m.particles(), m.particle_ids());
        let (mut sum, mut n) = (0.0, 0);
        for (p, id) in ids.iter().enumerate() {
            if gauge.contains(id) {
                let (x, v) = (ps.position[p], ps.velocity[p]);
                let r = x[0].hypot(x[1]);
                sum += (x[0] * v[0] + x[1] * v[1]) / r;
                n += 1;
            }
        }
        if n > 0 {
            sum / n as f64
        } else {
            f64::NAN
        }
    };
    let axis = [0.5 * h, 0.5 * h, GAUGE_Z];
    let start = Instant::now();
    let mut times = Vec::new();
    let mut speeds = Vec::new();
    let mut arrival = None;
    let mut sample = Vec::new();
    let mut steps = 0usize;
    let mut failure = None;
    while solver.time() < t_end * (1.0 - 1e-12) {
        let dt = match solver.stable_dt() {
            Ok(dt) => dt.min(t_end - solver.time()),
            Err(e) => {
                failure = Some(e.to_string());
                break;
            }
        };
        if let Err(e) = solver.advance(dt) {
            failure = Some(e.to_string());
            break;
        }
        steps += 1;
        if arrival.is_none() {
            solver.sample(axis, &["volume_fraction_2".into()], &mut sample)?;
            if sample[0] > 0.5 {
                arrival = Some(solver.time());
            }
        }
        times.push(solver.time());
        speeds.push(radial(solver.mpm()));
    }
    let wall = start.elapsed().as_secs_f64();
    let cells: usize = s.domain.cells.iter().product();
    let particles = solver.particles_per_step();
    let cell_rate = (cells * steps) as f64 / wall;
    let particle_rate = (particles * steps) as f64 / wall;
    // How far the wall got: the gauge particles' mean radius scaled to the
    // outer surface, the inner radius from the copper's area (its volume
    // per length, nearly incompressible), and the products' relative
    // volume V = (r_in/r_in0)² there.
    let r_out_end = gauge_radius(solver.mpm()) * r_out / gauge_r0;
    let r_in_end = (r_out_end * r_out_end - (r_out * r_out - r_in * r_in))
        .max(0.0)
        .sqrt();
    let v_end = (r_in_end / r_in).powi(2);
    // Gurney: QM-100 products on their principal isentrope to V = 7, the
    // reduced tube's metal-to-charge ratio.
    let products: JwlCTerm = match s.materials.get("products").and_then(|m| m.eos()) {
        Some(brisance::eos::EosModel::JwlCTerm(j)) => *j,
        _ => {
            return Err(anyhow!(
                "configs/cylinder_icempm.ron: `products` is not JwlCTerm"
            ))
        }
    };
    let cj = cj_on_jwl_cterm_isentrope(&products).map_err(|e| anyhow!("CJ: {e}"))?;
    let g = gurney_estimate(&products, &cj, CYLINDER_TEST_RELATIVE_VOLUME, 1e-11)
        .map_err(|e| anyhow!("Gurney: {e}"))?;
    let m_over_c = 8930.0 * (r_out * r_out - r_in * r_in) / (products.rho0 * r_in * r_in);
    let gurney = cylinder_wall_velocity(g.gurney_velocity, m_over_c).map_err(|e| anyhow!("{e}"))?;
    // The Gurney estimate at the expansion the run reached (for reading
    // the terminal value of a record that ends before V = 7).
    let gurney_at_end = if v_end.is_finite() && v_end > 1.0 {
        gurney_estimate(&products, &cj, v_end, 1e-11)
            .ok()
            .and_then(|ge| cylinder_wall_velocity(ge.gurney_velocity, m_over_c).ok())
    } else {
        None
    };
    let t0 = arrival.unwrap_or(f64::NAN);
    let terminal = if failure.is_none() {
        // Mean over the last 10 % of the record.
        let k = speeds.len() - speeds.len() / 10;
        speeds[k..].iter().sum::<f64>() / (speeds.len() - k) as f64
    } else {
        f64::NAN
    };
    println!(
        "  {steps} steps in {wall:.0} s ({cell_rate:.3e} cell-updates/s, {particle_rate:.3e} particle-steps/s, {cells} cells, {particles} particles), arrival at z = {:.1} cm {t0:e} s, terminal {terminal:.0} m/s, Gurney {gurney:.0} m/s (at the V = {v_end:.2} reached: {gurney_at_end:?}), failure {failure:?}",
        GAUGE_Z * 100.0
    );
    // Plot v_r against t − t_arrival.
    let shifted: Vec<f64> = times.iter().map(|t| (t - t0) * 1e6).collect();
    let png = img.join("e_cylinder.png");
    if arrival.is_some() {
        use crate::plot::{plot_panels, Panel, Series, SeriesStyle};
        let g = vec![gurney; shifted.len()];
        plot_panels(
            &png,
            &format!(
                "E-CYLINDER: outer wall at z = {:.1} cm (IceMpm, reduced)",
                GAUGE_Z * 100.0
            ),
            "t − t_arrival [µs]",
            &[Panel {
                y_label: "radial velocity [m/s]",
                series: vec![
                    Series {
                        label: "IceMpm",
                        x: &shifted,
                        y: &speeds,
                        style: SeriesStyle::Line,
                    },
                    Series {
                        label: "Gurney estimate",
                        x: &shifted,
                        y: &g,
                        style: SeriesStyle::Line,
                    },
                ],
            }],
        )?;
    }
    let md = &mut report.md;
    let _ = writeln!(
        md,
        "## E-CYLINDER — copper cylinder test, IceMpm (seed 000 §5.2)\n"
    );
    let _ = writeln!(
        md,
        "configs/cylinder_icempm.ron: OFHC copper tube r 25.4–30.6 mm (ρ 8930, K 117 GPa, G 43.8 GPa, \
         σy 70 MPa) filled with QM-100 (JWL++), air outside, quarter symmetry, 6 mm booster of products \
         at 10 GPa at z = 0. **Reduced:** 10 cm of tube at h = 2 mm in a {:.0} × {:.0} mm quarter section \
         (the seed: 35 cm at 0.5 mm; the wall is 2.6 cells thick here), gauge at z = {:.1} cm instead of 25 cm. \
         {steps} steps to {:.1} µs, {wall:.0} s wall (2 cores, shared): {cells} cells and {particles} particles, \
         {cell_rate:.3e} cell-updates/s, {particle_rate:.3e} particle-steps/s. At the end the wall at the gauge \
         had expanded to an inner radius of {:.1} mm, products relative volume V = {v_end:.2}{}.{}\n",
        (s.domain.upper[0] - s.domain.lower[0]) * 1e3,
        (s.domain.upper[1] - s.domain.lower[1]) * 1e3,
        GAUGE_Z * 100.0,
        solver.time() * 1e6,
        r_in_end * 1e3,
        gurney_at_end.map_or(String::new(), |v| format!(
            " (the Gurney estimate at that V, same M/C: {v:.0} m/s)"
        )),
        failure
            .as_ref()
            .map_or(String::new(), |f| format!(" **The run stopped:** {f}"))
    );
    let _ = writeln!(
        md,
        "Detonation arrival at the gauge (products θ > ½ on the axis): {}. Gurney: √(2E_G) = {:.0} m/s at \
         V = 7 on the QM-100 principal isentrope, M/C = {m_over_c:.2}, open-ended cylinder: {gurney:.0} m/s. \
         The LLNL shot K260-581 of seed 000 fig. 5 is not tabulated in the seed and no published QM-100 \
         cylinder velocity was found to compare with; only the Gurney estimate is used.\n",
        arrival.map_or("not reached".into(), |t| format!("{:.2} µs", t * 1e6)),
        g.gurney_velocity
    );
    if arrival.is_some() {
        let _ = writeln!(md, "![E-CYLINDER wall velocity](img/e_cylinder.png)\n");
    }
    let _ = writeln!(md, "| check | measured | target | |\n|---|---:|---:|---|");
    let err = terminal / gurney - 1.0;
    report.target(
        "E-CYLINDER terminal wall velocity vs Gurney",
        if terminal.is_finite() {
            format!("{terminal:.0} m/s ({:+.1} %)", 100.0 * err)
        } else {
            "run stopped".into()
        },
        "±10 %",
        terminal.is_finite() && err.abs() <= 0.10,
    );
    let _ = writeln!(report.md);
    Ok(())
}
