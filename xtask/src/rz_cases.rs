//! The V-RZ section of the validation report: the FDM and the ICE solver on
//! axisymmetric (r, z) grids against the same blast on the 3D octant at the
//! same h, and the round-off conservation of a closed r–z box
//! (`brisance::verification::rz_octant`).

use std::fmt::Write as _;

use anyhow::Result;
use brisance::verification::rz_octant::{
    fdm_closed_box, fdm_rz_against_octant, ice_closed_box, ice_rz_against_octant, Comparison,
    Drift, BOX_CELLS, BOX_STEPS, END, GAUGE_DISTANCE,
};

use crate::Report;

/// Cells per unit length of the FDM comparison (the octant at 1/80 has
/// 512 000 cells).
const FDM_RESOLUTIONS: [usize; 2] = [40, 80];
/// Cells per unit length of the ICE comparison.
const ICE_RESOLUTIONS: [usize; 2] = [40, 80];
/// Target on every difference, r–z against octant.
const TOLERANCE: f64 = 0.01;
/// Target on the closed box's relative drifts.
const DRIFT: f64 = 1e-12;

pub(crate) fn v_rz(report: &mut Report) -> Result<()> {
    println!("V-RZ: r-z against the 3D octant, FDM and ICE; closed r-z box");
    let mut runs: Vec<(&str, Comparison)> = Vec::new();
    for (solver, resolutions, case) in [
        (
            "FDM",
            &FDM_RESOLUTIONS[..],
            fdm_rz_against_octant as fn(usize) -> Result<Comparison, String>,
        ),
        ("ICE", &ICE_RESOLUTIONS[..], ice_rz_against_octant),
    ] {
        for &n in resolutions {
            let c = case(n).map_err(anyhow::Error::msg)?;
            println!(
                "  {solver} h = 1/{n}: {} + {} steps, {:.1} s + {:.1} s; worst peak {:.2} %, arrival {:.2} %",
                c.steps[0],
                c.steps[1],
                c.wall[0],
                c.wall[1],
                100.0 * c.worst()[0],
                100.0 * c.worst()[1]
            );
            for d in c.differences.iter().chain(&c.near_axis) {
                println!(
                    "    {:<16} peak {:+.2} %  arrival {:+.2} %",
                    d.name,
                    100.0 * d.overpressure(),
                    100.0 * d.arrival()
                );
            }
            runs.push((solver, c));
        }
    }
    let boxes: Vec<(&str, Drift)> = vec![
        (
            "FDM",
            fdm_closed_box(BOX_STEPS).map_err(anyhow::Error::msg)?,
        ),
        (
            "ICE",
            ice_closed_box(BOX_STEPS).map_err(anyhow::Error::msg)?,
        ),
    ];
    for (solver, d) in &boxes {
        println!(
            "  {solver} closed r-z box, {} steps: drift mass {:.1e}, axial momentum {:.1e}, energy {:.1e}",
            d.steps, d.mass, d.axial_momentum, d.energy
        );
    }

    let md = &mut report.md;
    let _ = writeln!(
        md,
        "## V-RZ — axisymmetric (r, z) runs against the 3D octant (FDM, ICE)\n"
    );
    let _ = writeln!(
        md,
        "`brisance::verification::rz_octant`: a sphere of radius 0.2 (pressure 20, density 4, in a gas at 1, 1; \
         ideal gas γ = 1.4, c_v = 1; its edge smoothed over 1.5 cells so both grids sample one function) at the \
         origin, on the (r, z) quarter plane [0, 1]² (axis and z = 0 symmetry faces) and on the 3D octant [0, 1]³ \
         (three symmetry planes) at the same h, far faces open, t = {END}. Default options of each solver (FDM: \
         face limiter on; ICE: explicit pressure, CFL 0.4). Gauges at distance {GAUGE_DISTANCE} on the axis, on \
         the plane z = 0 and on the 45° ray (peak as sampled after each step; arrival at 10 % of the peak's \
         overpressure), and the pressure along the three rays at t = {END} (peak; shock position at half the \
         peak's overpressure). Δ: r–z against octant, of the peak overpressure p − 1 and of the arrival time \
         (rays: the shock's position). The gauges near the axis (1, 2 and 5 cells out, at the axis gauge's \
         height) are shown, not targets. docs/physics/axisymmetric.md, \"Against the 3D octant\".\n"
    );
    let _ = writeln!(
        md,
        "| solver | h | r–z steps | octant steps | octant cells | r–z wall (s) | octant wall (s) | charge energy, r–z × 2 vs octant × 8 |\n\
         |---|---|---:|---:|---:|---:|---:|---:|"
    );
    for (solver, c) in &runs {
        let _ = writeln!(
            md,
            "| {solver} | 1/{} | {} | {} | {} | {:.1} | {:.1} | {:+.1e} |",
            c.n,
            c.steps[0],
            c.steps[1],
            c.n.pow(3),
            c.wall[0],
            c.wall[1],
            c.energy[0] / c.energy[1] - 1.0
        );
    }
    let _ = writeln!(
        md,
        "\n| solver | h | where | r–z peak | octant peak | Δ peak overpressure | r–z arrival / shock | octant arrival / shock | Δ arrival / shock |\n\
         |---|---|---|---:|---:|---:|---:|---:|---:|"
    );
    for (solver, c) in &runs {
        for d in c.differences.iter().chain(&c.near_axis) {
            let _ = writeln!(
                md,
                "| {solver} | 1/{} | {} | {:.4} | {:.4} | {:+.2} % | {:.4} | {:.4} | {:+.2} % |",
                c.n,
                d.name,
                d.peak[0],
                d.peak[1],
                100.0 * d.overpressure(),
                d.arrival[0],
                d.arrival[1],
                100.0 * d.arrival()
            );
        }
    }
    let _ = writeln!(
        md,
        "\nClosed r–z box: [0, 1] × [−0.4, 1.1] on {} × {} rings, every face a wall (FDM `Reflective`, ICE \
         `Symmetry`), a sphere of radius 0.3 at (0, 0.3) at pressure 40, density 4, moving along the axis at 0.3, \
         in the gas at 1, 1 flowing along the axis at 0.1 r; {BOX_STEPS} steps. Relative drift of the totals over \
         ring volumes plus what the faces booked (the walls' pressure impulse): mass, axial momentum (to the mass \
         times unit speed), energy; and the largest overpressure seen in the cell on the axis next to the far \
         wall z = 1.1, that the blast reached it.\n\n\
         | solver | steps | mass | axial momentum | energy | largest overpressure at the far wall |\n\
         |---|---:|---:|---:|---:|---:|",
        BOX_CELLS[0], BOX_CELLS[1]
    );
    for (solver, d) in &boxes {
        let _ = writeln!(
            md,
            "| {solver} | {} | {:.1e} | {:.1e} | {:.1e} | {:.3} |",
            d.steps, d.mass, d.axial_momentum, d.energy, d.wall_overpressure
        );
    }
    // The MPM's thin ring (V-RING, configs/validation/ring_breathing_rz.ron).
    use brisance::mpm::ShapeFunction;
    use brisance::verification::ring::ring_breathing;
    let mut ring_rows = Vec::new();
    for shape in [
        ShapeFunction::Linear,
        ShapeFunction::Gimp,
        ShapeFunction::CpGimp,
        ShapeFunction::QuadraticBSpline,
    ] {
        let r = ring_breathing(shape, 8).map_err(anyhow::Error::msg)?;
        println!("  MPM ring {shape:?}: period {:+.3} %", 100.0 * r.error());
        ring_rows.push((shape, r));
    }
    let _ = writeln!(
        md,
        "\n**MPM, a thin elastic ring breathing** (`configs/validation/ring_breathing_rz.ron` through the composer, `brisance::verification::ring`): a free steel ring \
         (K 160 GPa, G 80 GPa, ρ 7800 kg/m³) of mean radius R = 80 mm and section 5 × 5 mm on an (r, z) grid, 8 cells \
         across the section, 2 × 2 particles per cell, MUSL, no mass cut-off, set breathing by 0.5 m/s outwards; the \
         period between the last two downward zero crossings of the mean radial velocity in 2.6 periods, against \
         2π/ω with ω = c/R, c = √(E/ρ) (Love, §291). The MPM's r–z runs are compared with its 3D ones in V-TAYLOR \
         (the r–z rows there); no ICE–MPM r–z comparison with the 3D quarter exists yet.\n\n\
         | shape function | period (µs) | analytic (µs) | difference |\n|---|---:|---:|---:|"
    );
    for (shape, r) in &ring_rows {
        let _ = writeln!(
            md,
            "| {shape:?} | {:.3} | {:.3} | {:+.3} % |",
            r.measured * 1e6,
            r.analytic * 1e6,
            100.0 * r.error()
        );
    }
    let _ = writeln!(md);
    let _ = writeln!(
        md,
        "| figure of merit | measured | target | verdict |\n|---|---:|---|---|"
    );
    for (solver, c) in &runs {
        for d in &c.differences {
            report.target(
                &format!("V-RZ {solver} r–z vs octant, {}, h = 1/{}", d.name, c.n),
                format!(
                    "peak {:+.2} %, {} {:+.2} %",
                    100.0 * d.overpressure(),
                    if d.name.ends_with("ray") {
                        "shock"
                    } else {
                        "arrival"
                    },
                    100.0 * d.arrival()
                ),
                "within 1 %",
                d.within(TOLERANCE),
            );
        }
    }
    for (solver, d) in &boxes {
        for (what, v) in [
            ("mass", d.mass),
            ("axial momentum", d.axial_momentum),
            ("energy", d.energy),
        ] {
            report.target(
                &format!(
                    "V-RZ {solver} closed r–z box, {what} drift ({} steps)",
                    d.steps
                ),
                format!("{v:.1e}"),
                &format!("≤ {DRIFT:.0e}"),
                v <= DRIFT,
            );
        }
    }
    for (shape, r) in &ring_rows {
        report.target(
            &format!("V-RZ MPM thin ring breathing period, {shape:?}, 8 cells across"),
            format!("{:+.3} %", 100.0 * r.error()),
            "within 1 %",
            r.error().abs() <= 0.01,
        );
    }
    let _ = writeln!(report.md);
    Ok(())
}
