//! V-OSC, V-ROD and V-IMPEDANCE (seed 003 §2.5) at full length. The case
//! definitions are `brisance::pd::msdm::cases`, shared with the reduced
//! unit tests in `crates/pd/src/msdm/tests.rs`.

use std::fmt::Write as _;
use std::path::Path;
use std::time::Instant;

use anyhow::Result;
use brisance::pd::msdm::cases::{impedance, oscillator_error, rod};
use brisance::pd::msdm::Integrator;

use crate::plot;
use crate::Report;

/// Time steps of V-OSC, s.
const OSC_DT: [f64; 3] = [0.01, 0.005, 0.0025];

/// V-OSC: the harmonic oscillator of seed 003 §2.5.1 over t ∈ [0, 10] s;
/// √dt-weighted L2 displacement error and observed order per integrator.
pub fn v_osc(report: &mut Report, img: &Path) -> Result<()> {
    println!("V-OSC: harmonic oscillator, k 0.35 N/m, m 1/18 kg, v0 0.1 m/s, t in [0, 10] s");
    let _ = writeln!(
        report.md,
        "## V-OSC — harmonic oscillator (lattice, seed 003 §2.5.1)\n\n\
         Two-node chain, first node held, k = 0.35 N/m, m = 1/18 kg, x(0) = 0, v(0) = 0.1 m/s, \
         t ∈ [0, 10] s. Error: √(Σ Δt (x − v₀/ω sin ωt)²) over the steps. Order from the two finest steps.\n\n\
         | integrator | Δt = 0.01 | Δt = 0.005 | Δt = 0.0025 | order (0.01→0.005) | order (0.005→0.0025) |\n\
         |---|---:|---:|---:|---:|---:|"
    );
    let cases = [
        ("explicit Euler", Integrator::ExplicitEuler, 1.0),
        ("velocity Verlet", Integrator::VelocityVerlet, 2.0),
        ("implicit Euler", Integrator::ImplicitEuler, 1.0),
        ("implicit RK2", Integrator::ImplicitRk2, 2.0),
    ];
    let mut rows = Vec::new();
    let mut series = Vec::new();
    for (name, integ, order) in cases {
        let e: Vec<f64> = OSC_DT
            .iter()
            .map(|&dt| oscillator_error(integ, dt, 10.0))
            .collect::<Result<_, _>>()?;
        let p1 = (e[0] / e[1]).log2();
        let p2 = (e[1] / e[2]).log2();
        let _ = writeln!(
            report.md,
            "| {name} | {:.3e} | {:.3e} | {:.3e} | {p1:.3} | {p2:.3} |",
            e[0], e[1], e[2]
        );
        rows.push((name, order, p2));
        series.push((name, OSC_DT.to_vec(), e));
    }
    let _ = writeln!(
        report.md,
        "\n![V-OSC](img/v_osc.png)\n\n| figure of merit | measured | target | verdict |\n|---|---:|---|---|"
    );
    for (name, order, p) in rows {
        report.target(
            &format!("V-OSC observed order, {name}"),
            format!("{p:.3}"),
            if order == 1.0 {
                "1 ± 0.15"
            } else {
                "2 ± 0.15"
            },
            (p - order).abs() <= 0.15,
        );
    }
    let _ = writeln!(report.md);
    let series: Vec<(&str, Vec<f64>, Vec<f64>)> = series;
    plot::plot_convergence(
        &img.join("v_osc.png"),
        "V-OSC: harmonic oscillator, displacement error",
        "Δt [s]",
        "√dt-weighted L2 error [m]",
        &series,
        &[1.0, 2.0],
    )?;
    Ok(())
}

/// V-ROD: the rod under uniform axial load (seed 003 eq 25), 2ⁿ nodes.
pub fn v_rod(report: &mut Report, img: &Path) -> Result<()> {
    println!("V-ROD: rod under uniform axial load, 2^n nodes, n = 1..5");
    let _ = writeln!(
        report.md,
        "## V-ROD — rod under uniform axial load (lattice, seed 003 §2.5.2)\n\n\
         L = 1 m, E = 1 GPa, body force 2·10⁷ N/m³ (tip displacement 1 cm), left end held, static \
         equilibrium by Newton's method on the assembled ∂f/∂x. Exact u = (fL/EA)(x/L − x²/2L²) \
         (eq 25). L2: the piecewise-linear interpolant of the nodal displacements against eq 25, \
         relative; with exact nodal values it is h²/(4L²).\n\n\
         | nodes | tip error (rel.) | largest nodal error (rel.) | L2 error (rel.) | h²/4L² | Newton iterations |\n\
         |---:|---:|---:|---:|---:|---:|"
    );
    let mut tip_ok = true;
    let mut falls = true;
    let mut last = f64::INFINITY;
    let mut worst_tip = 0.0f64;
    let (mut hs, mut l2s) = (Vec::new(), Vec::new());
    for n in 1..=5 {
        let r = rod(n, 1.0, 1.0e9, 2.0e7)?;
        let h = 1.0 / (r.nodes - 1) as f64;
        let _ = writeln!(
            report.md,
            "| {} | {:.2e} | {:.2e} | {:.4e} | {:.4e} | {} |",
            r.nodes,
            r.tip_error,
            r.nodal_error,
            r.l2_error,
            0.25 * h * h,
            r.iterations
        );
        worst_tip = worst_tip.max(r.tip_error);
        tip_ok &= r.tip_error <= 1e-12;
        falls &= r.l2_error < last;
        last = r.l2_error;
        hs.push(h);
        l2s.push(r.l2_error);
    }
    let order = plot::fitted_slope(&hs, &l2s).unwrap_or(f64::NAN);
    let _ = writeln!(
        report.md,
        "\n![V-ROD](img/v_rod.png)\n\n| figure of merit | measured | target | verdict |\n|---|---:|---|---|"
    );
    report.target(
        "V-ROD tip displacement, worst relative error over n = 1..5",
        format!("{worst_tip:.1e}"),
        "exact (≤ 1e-12)",
        tip_ok,
    );
    report.target(
        "V-ROD L2 error falls with n (fitted order in h)",
        format!("{order:.3}"),
        "falls at every n",
        falls,
    );
    let _ = writeln!(report.md);
    plot::plot_convergence(
        &img.join("v_rod.png"),
        "V-ROD: rod under uniform axial load",
        "h [m]",
        "relative L2 error",
        &[("MSDM, linear interpolant", hs, l2s)],
        &[2.0],
    )?;
    Ok(())
}

/// V-IMPEDANCE: waves across an interface Z₁/Z₂ = 2 with equal wave speeds
/// (seed 003 §2.5.3), for pulse widths of 25 to 200 nodes.
pub fn v_impedance(report: &mut Report) -> Result<()> {
    println!("V-IMPEDANCE: Z1/Z2 = 2, same wave speed");
    let _ = writeln!(
        report.md,
        "## V-IMPEDANCE — transmission and reflection at Z₁/Z₂ = 2 (lattice, seed 003 §2.5.3)\n\n\
         Chain of 12W nodes, h = 1 mm: E 2 GPa / ρ 2000 kg/m³ on the left half, E 1 GPa / ρ 1000 kg/m³ \
         on the right (both 1000 m/s), free ends, velocity Verlet at Δt = ½h/c, no damping. A right-running \
         cos² velocity pulse of W nodes (strain −v/c) starts at 3W. Amplitudes are taken when the pulses \
         are 2W clear of the interface, relative to the incident pulse; speeds from the velocity-peak \
         positions over 2W of travel. Exact: velocity 4/3 and 1/3, stress 2/3 and −1/3.\n\n\
         | W (nodes) | nodes | steps | v transmitted | v reflected | σ transmitted | σ reflected | U/U₁ | U/U₂ | wall [s] |\n\
         |---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|"
    );
    let mut last = None;
    for w in [25usize, 50, 100, 200] {
        let t0 = Instant::now();
        let r = impedance(w, 1.0)?;
        let wall = t0.elapsed().as_secs_f64();
        let _ = writeln!(
            report.md,
            "| {w} | {} | {} | {:.5} | {:.5} | {:.5} | {:.5} | {:.5} | {:.5} | {wall:.2} |",
            r.nodes,
            r.steps,
            r.velocity_transmitted,
            r.velocity_reflected,
            r.stress_transmitted,
            r.stress_reflected,
            r.speed_ratio_1,
            r.speed_ratio_2
        );
        last = Some(r);
    }
    let Some(r) = last else {
        return Ok(());
    };
    let _ = writeln!(
        report.md,
        "\n| figure of merit (W = 200) | measured | target | verdict |\n|---|---:|---|---|"
    );
    let rel = |a: f64, b: f64| (a - b).abs() / b.abs();
    for (what, got, exact, shown) in [
        (
            "V-IMPEDANCE transmitted velocity",
            r.velocity_transmitted,
            4.0 / 3.0,
            "4/3 ± 1 %",
        ),
        (
            "V-IMPEDANCE reflected velocity",
            r.velocity_reflected,
            1.0 / 3.0,
            "1/3 ± 1 %",
        ),
        (
            "V-IMPEDANCE transmitted stress",
            r.stress_transmitted,
            2.0 / 3.0,
            "2/3 ± 1 %",
        ),
        (
            "V-IMPEDANCE reflected stress",
            r.stress_reflected,
            -1.0 / 3.0,
            "−1/3 ± 1 %",
        ),
        (
            "V-IMPEDANCE wave speed, material 1",
            r.speed_ratio_1,
            1.0,
            "1 ± 1 %",
        ),
        (
            "V-IMPEDANCE wave speed, material 2",
            r.speed_ratio_2,
            1.0,
            "1 ± 1 %",
        ),
    ] {
        report.target(what, format!("{got:.5}"), shown, rel(got, exact) <= 0.01);
    }
    let _ = writeln!(report.md);
    Ok(())
}
