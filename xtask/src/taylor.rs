//! The V-TAYLOR section of the validation report: the Taylor impact of an
//! OFHC copper rod against the test of Johnson & Cook (1983), at two
//! resolutions.

use std::fmt::Write as _;
use std::path::Path;
use std::time::Instant;

use anyhow::Result;
use brisance::verification::taylor::{
    bilinear_bar, bilinear_bar_case, taylor_case, TaylorResult, CONFIG_CELLS_ACROSS_RADIUS,
    JOHNSON_COOK_1983_OFHC_190,
};

use crate::plot::{self, Panel, Series, SeriesStyle};
use crate::Report;

/// Cells across the rod's radius: a coarse check and the shipped
/// configuration, whose numbers are the verdict.
const RESOLUTIONS: [usize; 2] = [6, CONFIG_CELLS_ACROSS_RADIUS];

/// Simulated time, s: the rod is at rest well before (kinetic energy below
/// the target in the table).
const END_TIME: f64 = 80e-6;

/// Tolerance on L_f and D_f against the test (validation plan, issue 4).
const TOLERANCE: f64 = 0.05;

/// Largest kinetic energy left at the end, as a fraction of the initial,
/// for the rod to count as at rest.
const REST: f64 = 0.01;

/// Cells across the radius of the bilinear-bar solver check (Δx = 0.4 mm,
/// L₀ = 81 Δx).
const BAR_CELLS: usize = 8;

pub(crate) fn v_taylor(report: &mut Report, img: &Path) -> Result<()> {
    let test = JOHNSON_COOK_1983_OFHC_190;
    println!("V-TAYLOR: Taylor impact of an OFHC copper rod at 190 m/s, 3D MPM");
    let mut runs: Vec<(TaylorResult, f64)> = Vec::new();
    for &n in &RESOLUTIONS {
        let t0 = Instant::now();
        let r = taylor_case(n, END_TIME, &[]).map_err(anyhow::Error::msg)?;
        let wall = t0.elapsed().as_secs_f64();
        println!(
            "  {n:>3} cells across R  {:>7} particles  {:>5} steps  Lf {:.3} mm  Df {:.3} mm  KE/KE0 {:.2e}  {wall:.0} s",
            r.particles,
            r.steps,
            1e3 * r.shape.length,
            1e3 * r.shape.diameter,
            r.kinetic_energy_ratio
        );
        runs.push((r, wall));
    }
    let t0 = Instant::now();
    let bar = bilinear_bar_case(BAR_CELLS, &[]).map_err(anyhow::Error::msg)?;
    let bar_wall = t0.elapsed().as_secs_f64();
    println!(
        "  bilinear bar, {BAR_CELLS} cells across R: Lf {:.3} mm  Rf {:.3} mm  {bar_wall:.0} s",
        1e3 * bar.shape.length,
        0.5e3 * bar.shape.diameter
    );
    let md = &mut report.md;
    let _ = writeln!(
        md,
        "## V-TAYLOR — Taylor impact of an OFHC copper rod (3D MPM)\n"
    );
    let _ = writeln!(
        md,
        "`configs/taylor3d.ron`: a rod L₀ = {:.1} mm, D₀ = {:.2} mm at {:.0} m/s onto a frictionless rigid wall \
         (quarter rod, symmetry planes through the axis), MUSL, contiguous-particle GIMP, 2 particles per cell per direction, \
         Courant number 0.4, t = {:.0} µs. Copper: J2 plasticity with the Johnson–Cook flow stress of Johnson & \
         Cook (1983) (A 90 MPa, B 292 MPa, n 0.31, C 0.025, m 1.09, T_melt 1356 K), no damage, Mie–Grüneisen \
         pressure (`ofhc_copper`), G 43.8 GPa, plastic heating 0.9. Reference: {}: L_f/L₀ = {}, D_f/D₀ = {}. \
         L_f is the highest particle face above the wall, D_f twice the largest radial particle face, each \
         particle being the cube V₀^(1/3) deformed by its F (`docs/physics/mpm/taylor.md`).\n",
        1e3 * test.length,
        1e3 * test.diameter,
        test.velocity,
        1e6 * END_TIME,
        test.source,
        test.final_length_ratio,
        test.final_diameter_ratio
    );
    let _ = writeln!(
        md,
        "| cells across R | Δx (mm) | particles | steps | L₀; D₀ as measured (mm) | L_f (mm) | error | D_f (mm) | error | widest at z (mm) | KE/KE₀ at end | energy change | mass error | max ε_p | max T (K) | wall time (s) |\n\
         |---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|"
    );
    let err_l = |r: &TaylorResult| (r.shape.length - test.final_length()) / test.final_length();
    let err_d =
        |r: &TaylorResult| (r.shape.diameter - test.final_diameter()) / test.final_diameter();
    for (r, wall) in &runs {
        let _ = writeln!(
            md,
            "| {} | {:.4} | {} | {} | {:.3}; {:.3} | {:.3} | {:+.2} % | {:.3} | {:+.2} % | {:.3} | {:.2e} | {:.1e} | {:+.2} % | {:.2} | {:.0} | {:.0} |",
            r.cells_across_radius,
            1e3 * r.cell_size,
            r.particles,
            r.steps,
            1e3 * r.initial_length,
            1e3 * r.initial_diameter,
            1e3 * r.shape.length,
            100.0 * err_l(r),
            1e3 * r.shape.diameter,
            100.0 * err_d(r),
            1e3 * r.shape.widest_at,
            r.kinetic_energy_ratio,
            r.energy_change,
            100.0 * r.mass_error,
            r.max_plastic_strain,
            r.max_temperature,
            wall
        );
    }
    let _ = writeln!(
        md,
        "| test | | | | {:.3}; {:.3} | {:.3} | | {:.3} | | | | | | | | |",
        1e3 * test.length,
        1e3 * test.diameter,
        1e3 * test.final_length(),
        1e3 * test.final_diameter()
    );
    {
        use bilinear_bar as b;
        let (lf, rf) = (bar.shape.length, 0.5 * bar.shape.diameter);
        let _ = writeln!(
            md,
            "\nSolver check without the Johnson–Cook model: the elastic, linearly hardening copper bar of Wilkins & \
             Guinan (1973) and Kamoulakos (1990) (L₀ {:.1} mm, R₀ {:.1} mm, {:.0} m/s, E {:.0} GPa, ν {}, σ_y {:.0} MPa, \
             E_t {:.0} MPa, {:.0} µs; `bilinear_bar_case`), same solver options, {BAR_CELLS} cells across R₀. Reference: \
             the finite-element solutions quoted for the benchmark, L_f 21.42–21.47 mm and mushroom radius 7.0–7.13 mm \
             (errors against {:.2} and {:.2} mm).\n\n\
             | L_f (mm) | error | mushroom radius (mm) | error | max ε_p | KE/KE₀ at end | energy change | wall time (s) |\n\
             |---:|---:|---:|---:|---:|---:|---:|---:|\n\
             | {:.3} | {:+.2} % | {:.3} | {:+.2} % | {:.2} | {:.2e} | {:.1e} | {:.0} |",
            1e3 * b::LENGTH,
            1e3 * b::RADIUS,
            b::VELOCITY,
            1e-9 * b::YOUNG,
            b::POISSON,
            1e-6 * b::YIELD,
            1e-6 * b::TANGENT,
            1e6 * b::END,
            1e3 * b::REFERENCE_LENGTH,
            1e3 * b::REFERENCE_RADIUS,
            1e3 * lf,
            100.0 * (lf / b::REFERENCE_LENGTH - 1.0),
            1e3 * rf,
            100.0 * (rf / b::REFERENCE_RADIUS - 1.0),
            bar.max_plastic_strain,
            bar.kinetic_energy_ratio,
            bar.energy_change,
            bar_wall
        );
    }
    let _ = writeln!(
        md,
        "\n| figure of merit | measured | target | verdict |\n|---|---:|---|---|"
    );
    let (fine, _) = runs.last().expect("two resolutions");
    let n = fine.cells_across_radius;
    report.target(
        &format!(
            "V-TAYLOR rod at rest at {:.0} µs ({n} cells across R)",
            1e6 * END_TIME
        ),
        format!("KE/KE₀ {:.2e}", fine.kinetic_energy_ratio),
        &format!("≤ {REST:.0e}"),
        fine.kinetic_energy_ratio <= REST,
    );
    let el = err_l(fine);
    report.target(
        &format!("V-TAYLOR final length L_f ({n} cells across R)"),
        format!("{:.3} mm ({:+.2} %)", 1e3 * fine.shape.length, 100.0 * el),
        &format!("{:.2} mm ± 5 %", 1e3 * test.final_length()),
        el.abs() <= TOLERANCE,
    );
    let ed = err_d(fine);
    report.target(
        &format!("V-TAYLOR foot diameter D_f ({n} cells across R)"),
        format!("{:.3} mm ({:+.2} %)", 1e3 * fine.shape.diameter, 100.0 * ed),
        &format!("{:.2} mm ± 5 %", 1e3 * test.final_diameter()),
        ed.abs() <= TOLERANCE,
    );

    // Profile plot: radius against height, mm.
    let mm = |v: &[f64]| v.iter().map(|x| 1e3 * x).collect::<Vec<f64>>();
    let profiles: Vec<(String, Vec<f64>, Vec<f64>)> = runs
        .iter()
        .map(|(r, _)| {
            (
                format!("MPM, {} cells across R", r.cells_across_radius),
                mm(&r.shape.profile_z),
                mm(&r.shape.profile_r),
            )
        })
        .collect();
    let (r0, l0) = (0.5e3 * test.diameter, 1e3 * test.length);
    let initial = ([0.0, l0], [r0, r0]);
    let published = (
        [0.0, 1e3 * test.final_length()],
        [0.5e3 * test.final_diameter(), r0],
    );
    let mut series = vec![Series {
        label: "initial rod",
        x: &initial.0,
        y: &initial.1,
        style: SeriesStyle::Line,
    }];
    for (label, z, r) in &profiles {
        series.push(Series {
            label,
            x: z,
            y: r,
            style: SeriesStyle::Line,
        });
    }
    series.push(Series {
        label: "test: foot radius D_f/2 at z = 0, rear face L_f at r = R",
        x: &published.0,
        y: &published.1,
        style: SeriesStyle::Points,
    });
    plot::plot_panels(
        &img.join("taylor_profile.png"),
        "Taylor impact, OFHC copper, 190 m/s: final profile",
        "height above the wall z [mm]",
        &[Panel {
            y_label: "radius r [mm]",
            series,
        }],
    )?;
    let _ = writeln!(
        report.md,
        "\nThe profile is the largest radial particle face in slices of one particle height. The test's rear \
         face is drawn at r = R (the rear of the rod stays elastic).\n\n![Taylor profile](img/taylor_profile.png)\n"
    );
    Ok(())
}
