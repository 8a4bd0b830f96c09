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
