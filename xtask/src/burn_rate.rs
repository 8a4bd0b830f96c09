//! V-BURNRATE: the deflagration of seed 000 §4.1.2 (D = A pⁿ, eq 38;
//! Γ = a D ρ, eq 39) burning a slab of reactant in the ICE solver at a held
//! pressure (`brisance_ice::burn_rate`): the surface's speed against A pⁿ
//! at the surface's pressure, for a grid-aligned plane, a plane at 45° and
//! a sphere on (r, z) rings; the same shapes with a particle reactant
//! (ICE–MPM, `brisance_couple::ice_mpm::burn_rate`).

use std::fmt::Write as _;

use anyhow::Result;
use brisance::couple::ice_mpm::burn_rate::particle_burn_rate;
use brisance::couple::ice_mpm::tubes;
use brisance::ice::burn_rate::{burn_rate, BurnRate, BurnRateResult, BurnSurface};
use brisance::reaction::SurfaceArea;

use crate::Report;

/// One run of the table.
struct Row {
    label: String,
    cfg: BurnRate,
    result: Result<BurnRateResult, String>,
}

fn run(label: String, cfg: BurnRate) -> Row {
    let result = burn_rate(&cfg);
    print_row(&label, &result);
    Row { label, cfg, result }
}

fn print_row(label: &str, result: &Result<BurnRateResult, String>) {
    match result {
        Ok(r) => println!(
            "  {label:<44} speed {:.5e} m/s, A p^n {:.5e} m/s at {:.4e} Pa: {:+.3} %, area {:+.3} % ({} steps)",
            r.speed,
            r.law_speed,
            r.surface_pressure,
            100.0 * r.error(),
            100.0 * r.area_error,
            r.steps
        ),
        Err(e) => println!("  {label:<44} stopped: {e}"),
    }
}

/// The A/100 row of `surface` with the area estimate `method` (`None`: the
/// reactant's default): PBX-9501's law with A over 100 at 100 MPa, run
/// over one cell.
fn slow(surface: BurnSurface, method: Option<SurfaceArea>) -> BurnRate {
    let mut cfg = BurnRate::a_over_100(surface);
    cfg.law.surface_area = method;
    cfg
}

/// The A/100 shapes with a particle reactant (ICE–MPM), each shape's
/// configuration that of the fluid rows, with a particle reactant's
/// default `gradient` area and with the `column` area.
fn particle_rows() -> Vec<Row> {
    let mut rows = Vec::new();
    for (method, marker) in [(None, ""), (Some(SurfaceArea::Column), ", `column` area")] {
        for surface in [
            BurnSurface::Plane,
            BurnSurface::Diagonal,
            BurnSurface::Sphere,
        ] {
            let cfg = slow(surface, method);
            let label = format!("particles, A/100, 100 MPa, {}{marker}", surface.name());
            let result = particle_burn_rate(&cfg);
            rows.push(Row { label, cfg, result });
        }
    }
    rows
}

pub(crate) fn v_burnrate(report: &mut Report) -> Result<()> {
    println!("V-BURNRATE: a reactant slab deflagrating at a held pressure (ICE)");
    // The particle rows (ICE–MPM) run beside the fluid ones.
    let particle_thread = std::thread::spawn(particle_rows);
    let mut rows = Vec::new();
    for p in [1.0e6, 1.0e7, 1.0e8] {
        let cfg = BurnRate::pbx_9501(p, BurnSurface::Plane);
        rows.push(run(
            format!(
                "PBX-9501 law, {} MPa, {}",
                p / 1e6,
                BurnSurface::Plane.name()
            ),
            cfg,
        ));
    }
    // The default estimate's rows, then the comparison rows of the three
    // estimates that read the field.
    for (method, marker) in [
        (None, ""),
        (Some(SurfaceArea::ExposedFaces), ", `exposed_faces` area"),
        (Some(SurfaceArea::Upwind), ", `upwind` area"),
        (Some(SurfaceArea::Gradient), ", `gradient` area"),
    ] {
        for surface in [
            BurnSurface::Plane,
            BurnSurface::Diagonal,
            BurnSurface::Sphere,
        ] {
            rows.push(run(
                format!("A/100, 100 MPa, {}{marker}", surface.name()),
                slow(surface, method),
            ));
        }
    }
    let particle_shapes = particle_thread
        .join()
        .map_err(|_| anyhow::anyhow!("the particle rows' thread panicked"))?;
    for r in &particle_shapes {
        print_row(&r.label, &r.result);
    }
    rows.extend(particle_shapes);
    let particles = tubes::particle_deflagration();
    match &particles {
        Ok(b) => println!(
            "  particle block (ICE-MPM), closed tube         burnt {:.5e} kg, law {:.5e} kg: {:+.3} %, area {:.1e} ({} steps)",
            b.burnt,
            b.by_law,
            100.0 * b.error(),
            b.area_error,
            b.steps
        ),
        Err(e) => println!("  particle block (ICE-MPM) stopped: {e}"),
    }
    let md = &mut report.md;
    let _ = writeln!(
        md,
        "## V-BURNRATE — a reactant slab deflagrating at a held pressure (ICE)\n"
    );
    let _ = writeln!(
        md,
        "The `Deflagration` reaction (seed 000 §4.1.2, eqs 38–39; docs/physics/reaction/deflagration.md) in \
         the ICE solver: after each step 2 the surface pass finds the reactant's surface cells and their area \
         per unit volume a/V (`Column` estimate, Youngs normal, a cell holds reactant above θ = 10⁻⁴, the \
         outermost surface cell of each column along the normal); before step 4 the part of a surface cell's \
         burn its reactant cannot supply goes on into the cells behind it, and \
         step 4 burns Γ Δt/V = (a/V) A pⁿ ρ Δt there. A reactant slab (ANFO-K1's Murnaghan EOS; its JWL C-term \
         products at 2500 K, above the 450 K ignition temperature) at rest against symmetry walls, the products \
         beyond it, the far faces holding the products' state at the held pressure \
         (`brisance_ice::burn_rate`, h = 0.1 mm, the reactant 8 cells deep). The surface's position comes \
         from the reactant's volume Σθ_r V (plane: V/A; 45°: the corner triangle's c/√2; sphere: the \
         hemisphere's radius) and its speed is the least-squares slope over the last 80 % of the run; A pⁿ is \
         the time mean over the same window of A pⁿ over the burning surface, each surface cell weighted by its \
         area, at its own pressure (`IceSolver::burning_surface`), and the surface pressure the one at which \
         A pⁿ is that mean. The area error is the surface pass's summed area over the true area of the surface \
         at the position the reactant's volume gives, minus 1 (time mean): the part of the speed's error the \
         area estimate makes. The PBX-9501 \
         law is `Deflagration::pbx_9501()` (A = 5.218 × 10⁻⁶ m·s⁻¹·Pa⁻⁰·⁷⁷⁸, n = 0.778), run over 3 cells; \
         the A/100 rows burn 100 times slower, so that the gas made leaves the pressure at the held one, \
         and isolate the surface estimate on each shape, run over 1 cell. The rows marked \
         `exposed_faces`, `upwind` and `gradient` area burn the A/100 shapes with three other estimates, \
         `SurfaceArea::ExposedFaces` (the open faces of every surface cell projected on the normal), \
         `SurfaceArea::Upwind` (the front's area shared between the cells its jump spans) and \
         `SurfaceArea::Gradient` (a particle reactant's default, below; \
         docs/physics/reaction/deflagration.md): a comparison, not figures of merit. The rows marked \
         particles burn the same A/100 shapes with the reactant as particles in the ICE–MPM pipeline \
         (`brisance_couple::ice_mpm::burn_rate`: 2 × 2 particles a cell over the shape, hypoelastic with the \
         reactant's bulk modulus; the reactant's volume is the particles' mass over its EOS density at the \
         held pressure), the cook-off's kind of explosive, which the gas does not move, with a particle \
         reactant's default, the `gradient` area (`SurfaceArea::Gradient`: every cell's |∇θ| V gathered \
         onto the surface cell its column meets; by the coarea formula the mean area of the front's level \
         sets, which does not depend on how far the particles' projection spreads their face), and with the \
         `column` area, the fluids' default, whose surface cells lie outside the particles' spread face. The \
         figures of merit are the rows of each reactant's default estimate.\n"
    );
    let _ = writeln!(
        md,
        "| run | steps | surface speed (m/s) | A pⁿ at the surface (m/s) | surface pressure / held | area error | error |\n|---|---:|---:|---:|---:|---:|---:|"
    );
    for r in &rows {
        match &r.result {
            Ok(x) => {
                let _ = writeln!(
                    md,
                    "| {} | {} | {:.5e} | {:.5e} | {:.4} | {:+.3} % | {:+.3} % |",
                    r.label,
                    x.steps,
                    x.speed,
                    x.law_speed,
                    x.surface_pressure / r.cfg.pressure,
                    100.0 * x.area_error,
                    100.0 * x.error()
                );
            }
            Err(e) => {
                let _ = writeln!(md, "| {} | — | stopped: {e} | — | — | — | — |", r.label);
            }
        }
    }
    let _ = writeln!(
        md,
        "\n**A particle reactant** (`brisance_couple::ice_mpm::tubes::particle_deflagration`): a 6 mm block \
         of QM-100 reactant particles at rest in its products at 100 MPa in the 1D ICE–MPM tube (1 mm cells), \
         burning by PBX-9501's law lit at 250 K for the time A pⁿ of 100 MPa takes to burn one cell from each \
         face, the products shut in the tube. The surface pass finds the block's two faces in the particles' \
         volume fraction on the grid. Over the last 80 % of the run the mass the particles lose is compared \
         with Σ a D ρ_r Δt over the same steps (D the mean of A pⁿ over the burning surface at its cells' own \
         pressure, ρ_r the reactant's density there at 300 K); the area error is the largest |a/(2A_x) − 1| \
         over the steps.\n"
    );
    let _ = writeln!(
        md,
        "| run | steps | burnt (kg) | by the law (kg) | surface pressure at the end / start | area error | error |\n|---|---:|---:|---:|---:|---:|---:|"
    );
    match &particles {
        Ok(b) => {
            let _ = writeln!(
                md,
                "| particle block, closed tube | {} | {:.5e} | {:.5e} | {:.3} | {:.1e} | {:+.3} % |",
                b.steps,
                b.burnt,
                b.by_law,
                b.surface_pressure / b.held_pressure,
                b.area_error,
                100.0 * b.error()
            );
        }
        Err(e) => {
            let _ = writeln!(
                md,
                "| particle block, closed tube | — | stopped: {e} | — | — | — | — |"
            );
        }
    }
    let _ = writeln!(
        md,
        "\n| figure of merit | measured | target | verdict |\n|---|---:|---|---|"
    );
    // The figures of merit: the rows of each reactant's default estimate
    // (`column` for the fluid, `gradient` for particles).
    for r in rows.iter().filter(|r| r.cfg.law.surface_area.is_none()) {
        let (measured, ok) = match &r.result {
            Ok(x) => (
                format!("{:+.3} %", 100.0 * x.error()),
                x.error().abs() <= 0.01,
            ),
            Err(_) => ("stopped".to_string(), false),
        };
        report.target(
            &format!("V-BURNRATE {} speed vs A pⁿ", r.label),
            measured,
            "within 1 %",
            ok,
        );
    }
    let (measured, ok) = match &particles {
        Ok(b) => (
            format!("{:+.3} %", 100.0 * b.error()),
            b.error().abs() <= 0.01,
        ),
        Err(_) => ("stopped".to_string(), false),
    };
    report.target(
        "V-BURNRATE particle block (ICE–MPM) burnt mass vs A pⁿ",
        measured,
        "within 1 %",
        ok,
    );
    let _ = writeln!(report.md);
    Ok(())
}
