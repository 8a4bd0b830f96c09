//! E-PD-CYL: seed 004's copper cylinder-expansion test, built from
//! `configs/pd_cylinder_full.ron` through the composer and run with the
//! mid-length wall record of `brisance_pd::cases::run_tube`.

use brisance_compose::config::Scenario;
use brisance_compose::{build::build_section, load_str};
use brisance_pd::cases::{run_tube, WallHistory};
use brisance_pd::{PdConfig, PdSolver};

/// The E-PD-CYL scenario file (the full 25.8 cm tube, to 45 µs).
pub const PD_CYLINDER_FULL_CONFIG: &str = include_str!("../../../configs/pd_cylinder_full.ron");

/// The tube's length and outer radius, m, as the config's regions give
/// them (25.8 cm, 15.3 mm).
pub const TUBE: (f64, f64) = (0.258, 0.0127 + 0.0026);

/// The scenario of the full tube at lattice spacing `spacing` (m): the
/// config with `pipeline.spacing` set and the detonation point on the axis
/// half a spacing into the charge (the config's own point at its 1.3 mm).
pub fn scenario(spacing: f64) -> Result<Scenario, String> {
    tube_scenario(
        "configs/pd_cylinder_full.ron",
        PD_CYLINDER_FULL_CONFIG,
        spacing,
    )
}

/// A peridynamic tube's scenario file `text` (named `file`) at lattice
/// spacing `spacing` (m), lit on the axis half a spacing into the charge.
pub(crate) fn tube_scenario(file: &str, text: &str, spacing: f64) -> Result<Scenario, String> {
    if !(spacing > 0.0 && spacing.is_finite()) {
        return Err(format!(
            "{file}: spacing {spacing} m must be finite and > 0"
        ));
    }
    let sets = [
        format!("pipeline.spacing={spacing:e}"),
        format!(
            "pipeline.detonation=Some(points: [(position: (0.0, 0.0, {:e}), time: 0.0)], method: Huygens)",
            0.5 * spacing
        ),
    ];
    load_str(file, text, &sets)
        .map(|l| l.scenario)
        .map_err(|e| e.to_string())
}

/// The solver of [`scenario`], built by the `Peridynamics` section.
pub fn solver(spacing: f64) -> Result<PdSolver, String> {
    let s = scenario(spacing)?;
    let pd = s
        .pipeline
        .section::<PdConfig>()
        .ok_or("E-PD-CYL: the config is not a Peridynamics pipeline")?;
    build_section(pd, &s).map_err(|e| e.to_string())
}

/// The full tube at `spacing` run to the config's end (45 µs), the
/// mid-length outer wall sampled every `every` steps.
pub fn copper_cylinder(spacing: f64, every: usize) -> Result<(PdSolver, WallHistory), String> {
    let end = scenario(spacing)?.time.end;
    run_tube(solver(spacing)?, TUBE.0, TUBE.1, spacing, end, every)
}

/// The tube `a` a scenario file built is the library case's `b` node for
/// node: positions, masses and stable step to the bit; the file numbers
/// its two materials in the order of its regions (the charge first), the
/// case the case first.
#[cfg(test)]
pub(crate) fn assert_same_tube(a: &PdSolver, b: &PdSolver) {
    use brisance_core::Solver;
    assert_eq!(a.node_count(), b.node_count());
    assert_eq!(a.reference(), b.reference());
    assert!(a
        .materials()
        .iter()
        .zip(b.materials())
        .all(|(&p, &q)| p == 1 - q));
    assert!((0..a.node_count()).all(|i| a.mass(i) == b.mass(i)));
    assert_eq!(a.stable_dt().unwrap(), b.stable_dt().unwrap());
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The config at 1.3 mm builds the library case node for node
    /// (positions, masses, stable step to the bit; the materials numbered
    /// the other way round), and its tube is [`TUBE`].
    #[test]
    fn the_config_is_the_case() {
        let h = 1.3e-3;
        let a = solver(h).unwrap();
        let case = brisance_pd::cases::copper_cylinder(h, 0.258);
        assert_eq!((case.length, case.outer_radius), TUBE);
        let b = PdSolver::new(case.setup().unwrap()).unwrap();
        assert_same_tube(&a, &b);
        assert_eq!(brisance_pd::cases::case_material(&a), 1);
        assert_eq!(brisance_pd::cases::case_material(&b), 0);
    }

    /// A few steps through the composer's solver and the case's give the
    /// same wall record to the bit: the material numbering changes
    /// nothing.
    #[test]
    fn a_short_run_is_the_case_s_run() {
        let h = 1.3e-3;
        let end = 2.0e-7;
        let (_, a) = run_tube(solver(h).unwrap(), TUBE.0, TUBE.1, h, end, 1).unwrap();
        let case = brisance_pd::cases::copper_cylinder(h, 0.258);
        let (_, b) = brisance_pd::cases::run_cylinder(&case, end, 1).unwrap();
        assert_eq!(a, b);
    }
}
