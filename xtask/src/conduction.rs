//! V-CONDUCTION: heat conduction inside the MPM solids
//! (`brisance_mpm::conduction`) against the analytic decay of a bar's
//! cosine mode and of a solid cylinder's first radial Bessel mode on an
//! (r, z) grid (`brisance_mpm::conduction::cases`), and across a
//! solid–fluid contact in the IceMpm pipeline against the transient of two
//! semi-infinite bodies (`brisance::verification::conduction_contact`).

use std::fmt::Write as _;

use anyhow::{anyhow, Result};
use brisance::mpm::conduction::cases::{
    alpha, bar_decay, cylinder_decay, ModeDecay, CV, J1_FIRST_ZERO, K, RHO,
};
use brisance::mpm::ShapeFunction;
use brisance::verification::cases::observed_orders;
use brisance::verification::conduction_contact::{contact_transient, ContactTransient};

use crate::Report;

/// Cells of the refinement sequences (linear shape functions).
const CELLS: [usize; 3] = [16, 32, 64];

/// The cells at which every shape function is measured and the 1 % target
/// is set.
const TARGET_CELLS: usize = 32;

/// Cells of the contact's sequence (h = 1, 0.5, 0.25, 0.125 mm).
const CONTACT_CELLS: [usize; 4] = [50, 100, 200, 400];

/// One measured row of the table.
struct Row {
    case: &'static str,
    shape: ShapeFunction,
    cells: usize,
    decay: ModeDecay,
    /// The observed order from the previous row of the same sequence.
    order: Option<f64>,
}

/// The linear sequence of `case` (`measure` at [`CELLS`]) with the
/// observed orders between successive resolutions.
fn sequence(
    case: &'static str,
    measure: fn(usize, ShapeFunction) -> Result<ModeDecay, String>,
) -> Result<Vec<Row>> {
    let mut rows = Vec::new();
    for cells in CELLS {
        let decay = measure(cells, ShapeFunction::Linear).map_err(|e| anyhow!("{case}: {e}"))?;
        rows.push(Row {
            case,
            shape: ShapeFunction::Linear,
            cells,
            decay,
            order: None,
        });
    }
    let errors: Vec<f64> = rows.iter().map(|r| r.decay.error().abs()).collect();
    for (k, order) in observed_orders(&CELLS, &errors).into_iter().enumerate() {
        rows[k + 1].order = Some(order);
    }
    Ok(rows)
}

fn shape_name(shape: ShapeFunction) -> &'static str {
    match shape {
        ShapeFunction::Linear => "linear",
        ShapeFunction::Gimp => "uGIMP",
        ShapeFunction::CpGimp => "cpGIMP",
        ShapeFunction::QuadraticBSpline => "quadratic B-spline",
    }
}

pub(crate) fn v_conduction(report: &mut Report) -> Result<()> {
    println!("V-CONDUCTION: heat conduction inside MPM solids against the analytic decay");
    let mut rows = sequence("bar", bar_decay)?;
    for shape in [ShapeFunction::Gimp, ShapeFunction::QuadraticBSpline] {
        let decay = bar_decay(TARGET_CELLS, shape).map_err(|e| anyhow!("bar: {e}"))?;
        rows.push(Row {
            case: "bar",
            shape,
            cells: TARGET_CELLS,
            decay,
            order: None,
        });
    }
    rows.extend(sequence("cylinder (r–z)", cylinder_decay)?);
    for r in &rows {
        println!(
            "  {:<15} {:<19} {:>3} cells  {:>5} steps  rate error {:+.4} %{}",
            r.case,
            shape_name(r.shape),
            r.cells,
            r.decay.steps,
            100.0 * r.decay.error(),
            r.order.map_or(String::new(), |o| format!("  order {o:.2}"))
        );
    }
    let md = &mut report.md;
    let _ = writeln!(
        md,
        "## V-CONDUCTION — heat conduction inside MPM solids and across a solid–fluid contact against analytic transients\n"
    );
    let _ = writeln!(
        md,
        "The explicit MPM conduction step (`brisance_mpm::conduction`, \
         docs/physics/mpm/heat_conduction.md; Fourier's law, seed 000 §2 eq 3) on a steel-like solid at \
         rest without stress (ρ = {RHO} kg/m³, c_v = {CV} J/(kg·K), k = {K} W/(m·K), α = {:.4e} m²/s), \
         2 particles per cell per direction, Δt at 0.4 of the diffusive limit, run over one e-folding time of \
         the mode, every surface adiabatic (`brisance_mpm::conduction::cases`). Bar: L = 1 m, one cell \
         across, T = T0 + ΔT cos(πx/L), analytic decay exp(−α (π/L)² t). Cylinder: an (r, z) grid of radius \
         R = 1 m, one cell along z, T = T0 + ΔT J0(j r/R) with j = {J1_FIRST_ZERO} the first zero of J1, \
         analytic decay exp(−α (j/R)² t). The error is that of the measured decay rate \
         −ln(A(t)/A(0))/t, A the mode's mass-weighted amplitude on the particles; the observed order is \
         ln(|e_coarse|/|e_fine|)/ln 2 between successive resolutions.\n",
        alpha()
    );
    let _ = writeln!(
        md,
        "| case | shape function | cells | steps | decay-rate error | observed order |\n|---|---|---:|---:|---:|---:|"
    );
    for r in &rows {
        let _ = writeln!(
            md,
            "| {} | {} | {} | {} | {:+.4} % | {} |",
            r.case,
            shape_name(r.shape),
            r.cells,
            r.decay.steps,
            100.0 * r.decay.error(),
            r.order.map_or("—".to_string(), |o| format!("{o:.2}"))
        );
    }
    let _ = writeln!(
        md,
        "\n| figure of merit | measured | target | verdict |\n|---|---:|---|---|"
    );
    for case in ["bar", "cylinder (r–z)"] {
        let of_case = || {
            rows.iter()
                .filter(move |r| r.case == case && r.shape == ShapeFunction::Linear)
        };
        let e = of_case()
            .find(|r| r.cells == TARGET_CELLS)
            .map(|r| r.decay.error())
            .ok_or_else(|| anyhow!("{case}: no run at {TARGET_CELLS} cells"))?;
        report.target(
            &format!("V-CONDUCTION {case} decay-rate error at {TARGET_CELLS} cells (linear)"),
            format!("{:+.3} %", 100.0 * e),
            "within 1 %",
            e.abs() <= 0.01,
        );
        let orders: Vec<f64> = of_case().filter_map(|r| r.order).collect();
        let worst = orders.iter().copied().fold(f64::INFINITY, f64::min);
        report.target(
            &format!(
                "V-CONDUCTION {case} observed order {}→{} cells (lowest)",
                CELLS[0],
                CELLS[CELLS.len() - 1]
            ),
            format!("{worst:.2}"),
            "≥ 1.5",
            worst >= 1.5,
        );
    }
    for r in rows.iter().filter(|r| r.shape != ShapeFunction::Linear) {
        let e = r.decay.error();
        report.target(
            &format!(
                "V-CONDUCTION {} decay-rate error at {} cells ({})",
                r.case,
                r.cells,
                shape_name(r.shape)
            ),
            format!("{:+.3} %", 100.0 * e),
            "within 1 %",
            e.abs() <= 0.01,
        );
    }
    contact_rows(report)?;
    let _ = writeln!(report.md);
    Ok(())
}

/// The contact's sequence with `particle_heat: Nodes` (the config's), and
/// the coarsest and finest with `Cell`, into the report.
fn contact_rows(report: &mut Report) -> Result<()> {
    let run = |cells: usize, set: &[String]| -> Result<ContactTransient> {
        contact_transient(cells, set).map_err(|e| anyhow!("contact at {cells} cells: {e}"))
    };
    let nodes: Vec<ContactTransient> = CONTACT_CELLS
        .iter()
        .map(|&n| run(n, &[]))
        .collect::<Result<_>>()?;
    let cell_set = ["pipeline.particle_heat=Cell".to_string()];
    let cell: Vec<ContactTransient> = [CONTACT_CELLS[0], CONTACT_CELLS[CONTACT_CELLS.len() - 1]]
        .iter()
        .map(|&n| run(n, &cell_set))
        .collect::<Result<_>>()?;
    let errors: Vec<f64> = nodes.iter().map(|r| r.error().abs()).collect();
    let orders = observed_orders(&CONTACT_CELLS, &errors);
    for (k, r) in nodes.iter().enumerate() {
        println!(
            "  contact (Nodes) {:>3} cells  {:>5} steps  heat {:.6e} J vs {:.6e} J ({:+.3} %), balance {:+.1e}{}",
            r.cells,
            r.steps,
            r.solid_loss,
            r.analytic,
            100.0 * r.error(),
            r.balance(),
            k.checked_sub(1)
                .map_or(String::new(), |j| format!("  order {:.2}", orders[j]))
        );
    }
    for r in &cell {
        println!(
            "  contact (Cell)  {:>3} cells  particles lose {:.4e} J, liquid gains {:.4e} J",
            r.cells, r.solid_loss, r.fluid_gain
        );
    }
    let md = &mut report.md;
    let _ = writeln!(
        md,
        "\n**Across a solid–fluid contact** (`configs/validation/conduction_contact.ron`, \
         `brisance::verification::conduction_contact`; docs/physics/couple/ice_mpm.md, \
         \"Heat between the frames\"). IceMpm, 1D along x: a block of conducting particles at 400 K \
         (x < 30 mm; k = 8·10⁴ W/(m·K), ρ = 2001 kg/m³, c_v = 1000 J/(kg·K)) against a conducting \
         Eulerian liquid at 300 K (k = 2·10⁴ W/(m·K), ρ = 1001 kg/m³, c_v = 2000 J/(kg·K)), at rest, \
         every face closed and adiabatic; test materials whose Murnaghan pressure does not depend on \
         the temperature and whose acoustic and diffusive steps meet; heat exchange H = 10¹⁸ \
         W/(m³·K) (complete within a step), `particle_heat: Nodes`. The heat that crossed by \
         t = 0.625 ms (the particles' loss Σ m c ΔT) against two semi-infinite bodies in perfect \
         contact, Q = 2ΔT e_s e_f/(e_s + e_f) √(t/π) with e = √(kρc) (Carslaw & Jaeger 1959, §2.15): \
         {:.6e} J over the 1 mm² section; the balance is the liquid's gain (the run's energy \
         change) over the particles' loss − 1. Last two rows: each particle taking its own cell's \
         change (`particle_heat: Cell`, the rule before `Nodes`).\n",
        nodes[0].analytic
    );
    let _ = writeln!(
        md,
        "| transfer | cells | h (mm) | steps | particles' loss (J) | loss / Q − 1 | observed order | liquid's gain / particles' loss − 1 |\n|---|---:|---:|---:|---:|---:|---:|---:|"
    );
    let rows = nodes
        .iter()
        .enumerate()
        .map(|(k, r)| ("Nodes", r, k.checked_sub(1).map(|j| orders[j])))
        .chain(cell.iter().map(|r| ("Cell", r, None)));
    for (transfer, r, order) in rows {
        let _ = writeln!(
            md,
            "| {transfer} | {} | {} | {} | {:.6e} | {:+.3} % | {} | {:+.1e} |",
            r.cells,
            1e3 * r.spacing(),
            r.steps,
            r.solid_loss,
            100.0 * r.error(),
            order.map_or("—".to_string(), |o| format!("{o:.2}")),
            r.balance()
        );
    }
    let _ = writeln!(
        md,
        "\n| figure of merit | measured | target | verdict |\n|---|---:|---|---|"
    );
    let finest = &nodes[nodes.len() - 1];
    report.target(
        &format!(
            "V-CONDUCTION contact heat crossed at {} cells (finest, Nodes) vs Q(t)",
            finest.cells
        ),
        format!("{:+.3} %", 100.0 * finest.error()),
        "within 1 %",
        finest.error().abs() <= 0.01,
    );
    let falls = errors.windows(2).all(|w| w[1] < w[0]);
    let worst = orders.iter().copied().fold(f64::INFINITY, f64::min);
    report.target(
        &format!(
            "V-CONDUCTION contact error falls with h, {}→{} cells (lowest observed order)",
            CONTACT_CELLS[0],
            CONTACT_CELLS[CONTACT_CELLS.len() - 1]
        ),
        format!("{worst:.2}"),
        "falls at every halving, order ≥ 1",
        falls && worst >= 1.0,
    );
    let balance = nodes.iter().map(|r| r.balance().abs()).fold(0.0, f64::max);
    report.target(
        "V-CONDUCTION contact liquid's gain / particles' loss − 1 (Nodes, worst)",
        format!("{balance:.1e}"),
        "≤ 1e-5",
        balance <= 1e-5,
    );
    Ok(())
}
