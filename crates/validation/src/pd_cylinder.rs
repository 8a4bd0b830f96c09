//! E-PD-CYL: seed 004's copper cylinder-expansion test, built from
//! `configs/pd_cylinder_full.ron` through the composer and run with the
//! mid-length wall record of `brisance_pd::cases::run_tube`.

use brisance_pd::cases::{run_tube, run_tube_at, WallHistory};
use brisance_pd::PdSolver;

use crate::pd_tube::{wall_of, CaseWall, Tube};

/// The E-PD-CYL scenario file (the full 25.8 cm tube, to 45 µs).
pub const PD_CYLINDER_FULL_CONFIG: &str = include_str!("../../../configs/pd_cylinder_full.ron");

/// The full tube at lattice spacing `spacing` (m), built
/// ([`Tube::at`]).
pub fn tube(spacing: f64) -> Result<Tube, String> {
    Tube::at(
        "configs/pd_cylinder_full.ron",
        PD_CYLINDER_FULL_CONFIG,
        spacing,
    )
}

/// The config's case wall (its length and radii), read without building
/// the tube.
pub fn wall() -> Result<CaseWall, String> {
    wall_of("configs/pd_cylinder_full.ron", PD_CYLINDER_FULL_CONFIG)
}

/// The full tube at `spacing` run to the config's end (45 µs), the
/// mid-length outer wall (the config's wall's length and outer radius)
/// sampled every `every` steps.
pub fn copper_cylinder(spacing: f64, every: usize) -> Result<(PdSolver, WallHistory), String> {
    copper_cylinder_with(spacing, every, &[])
}

/// [`copper_cylinder`] with further `--set` overrides of the scenario file
/// (`key=value`, [`Tube::at_with`]), e.g.
/// `pipeline.products_family=WithSolids` for the report's second row.
pub fn copper_cylinder_with(
    spacing: f64,
    every: usize,
    overrides: &[String],
) -> Result<(PdSolver, WallHistory), String> {
    let t = Tube::at_with(
        "configs/pd_cylinder_full.ron",
        PD_CYLINDER_FULL_CONFIG,
        spacing,
        overrides,
    )?;
    run_tube(
        t.solver,
        t.wall.length,
        t.wall.outer_radius,
        spacing,
        t.scenario.time.end,
        every,
    )
}

/// Seed 000's copper cylinder test (configs/cylinder_rz.ron's tube and
/// QM-100) in peridynamics, for the side-by-side with ICE–MPM.
pub const PD_SEED000_CONFIG: &str = include_str!("../../../configs/pd_cylinder_seed000.ron");

/// The seed 000 tube at `spacing`, run to the config's end (80 µs), the
/// outer wall at the config's gauge `wall` (z = 25 cm) sampled every
/// `every` steps.
pub fn seed000_cylinder(spacing: f64, every: usize) -> Result<(PdSolver, WallHistory), String> {
    seed000_cylinder_with(spacing, every, &[])
}

/// [`seed000_cylinder`] with further `--set` overrides of the scenario
/// file (`key=value`, [`Tube::at_with`]), e.g.
/// `pipeline.products_family=MirroredWall`.
pub fn seed000_cylinder_with(
    spacing: f64,
    every: usize,
    overrides: &[String],
) -> Result<(PdSolver, WallHistory), String> {
    let file = "configs/pd_cylinder_seed000.ron";
    let t = Tube::at_with(file, PD_SEED000_CONFIG, spacing, overrides)?;
    let z = t
        .scenario
        .outputs
        .gauges
        .iter()
        .find(|g| g.name == "wall")
        .map(|g| g.point[2])
        .ok_or_else(|| format!("{file}: no gauge `wall`"))?;
    run_tube_at(
        t.solver,
        z,
        t.wall.outer_radius,
        spacing,
        t.scenario.time.end,
        every,
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::pd_tube::assert_same_tube;

    /// The config at 1.3 mm builds the library case node for node
    /// (positions, masses, stable step to the bit; the materials numbered
    /// the other way round), and its wall is the case's tube.
    #[test]
    fn the_config_is_the_case() {
        let h = 1.3e-3;
        let a = tube(h).unwrap();
        let case = brisance_pd::cases::copper_cylinder(h, brisance_pd::cases::COPPER_TUBE_LENGTH);
        assert_eq!(a.wall.length, case.length);
        assert_eq!(wall().unwrap(), a.wall);
        assert!((a.wall.outer_radius - case.outer_radius).abs() <= 1e-15);
        let b = PdSolver::new(case.setup().unwrap()).unwrap();
        assert_same_tube(&a.solver, &b);
        assert_eq!(brisance_pd::cases::case_material(&a.solver), 1);
        assert_eq!(brisance_pd::cases::case_material(&b), 0);
    }

    /// A negative products viscosity, which the solver refuses as it is
    /// built (not when the scenario loads): the error names the file, the
    /// line and column of the field in the text after the overrides, and
    /// the field.
    #[test]
    fn a_tube_that_does_not_build_names_the_file_line_and_field() {
        let file = "configs/pd_cylinder_seed000.ron";
        let set = [
            "pipeline.gas_viscosity=(linear: -1.0, quadratic: 0.0, deviatoric: 0.0)".to_string(),
        ];
        let Err(e) = Tube::at_with(file, PD_SEED000_CONFIG, 4.0e-3, &set) else {
            panic!("a negative products viscosity built");
        };
        let place = e
            .strip_prefix(&format!("{file}:"))
            .unwrap_or_else(|| panic!("{e}"));
        let mut parts = place.splitn(3, ':');
        let line: usize = parts
            .next()
            .unwrap()
            .parse()
            .unwrap_or_else(|_| panic!("{e}"));
        let column: usize = parts
            .next()
            .unwrap()
            .parse()
            .unwrap_or_else(|_| panic!("{e}"));
        assert!(line > 1 && column > 0, "{e}");
        assert!(
            parts
                .next()
                .unwrap()
                .starts_with(" `pipeline.gas_viscosity"),
            "{e}"
        );
    }

    /// The seed 000 file builds seed 000's tube with QM-100's printed
    /// isentrope, and a few steps record its wall at z = 25 cm.
    #[test]
    fn the_seed_000_tube_builds_and_runs() {
        let h = 4.0e-3;
        let t = Tube::at("pd_cylinder_seed000.ron", PD_SEED000_CONFIG, h).unwrap();
        assert_eq!(
            (t.wall.inner_radius, t.wall.outer_radius, t.wall.length),
            (0.0254, 0.0306, 0.35)
        );
        assert_eq!(t.wall.yield_strength, 70.0e6);
        let pd = t
            .scenario
            .pipeline
            .section::<brisance_pd::PdConfig>()
            .unwrap();
        let Some(brisance_pd::PdMaterialConfig::JwlCTermExplosive { products, .. }) =
            pd.materials.get("qm100")
        else {
            panic!("qm100 is not a C-term explosive");
        };
        let q = brisance_eos::JwlCTerm::qm100();
        let printed = |j: &brisance_eos::JwlCTerm| (j.a, j.b, j.c, j.r1, j.r2, j.omega, j.rho0);
        assert_eq!(printed(products), printed(&q));
        let (_, history) = run_tube_at(t.solver, 0.25, t.wall.outer_radius, h, 2.0e-7, 1).unwrap();
        assert!(history.time.len() > 2);
        assert!(history.radial_velocity.iter().all(|v| *v == 0.0));
    }

    /// A few steps through the composer's solver and the case's give the
    /// same wall record to the bit: the material numbering changes
    /// nothing.
    #[test]
    fn a_short_run_is_the_case_s_run() {
        let h = 1.3e-3;
        let end = 2.0e-7;
        let t = tube(h).unwrap();
        let (_, a) = run_tube(t.solver, t.wall.length, t.wall.outer_radius, h, end, 1).unwrap();
        let case = brisance_pd::cases::copper_cylinder(h, brisance_pd::cases::COPPER_TUBE_LENGTH);
        let (_, b) = brisance_pd::cases::run_cylinder(&case, end, 1).unwrap();
        assert_eq!(a, b);
    }

    /// The examples' command line: a positive finite spacing, then the
    /// overrides; anything else is the usage line.
    #[test]
    fn the_examples_take_a_positive_spacing_and_overrides() {
        use crate::pd_tube::{args, spacing_args};
        assert_eq!(
            spacing_args(
                args(&["1.5e-3", "pipeline.products_family=MirroredWall"]),
                "u"
            ),
            Ok((
                1.5e-3,
                vec!["pipeline.products_family=MirroredWall".to_string()]
            ))
        );
        assert_eq!(spacing_args(args(&["2e-3"]), "u"), Ok((2e-3, vec![])));
        for bad in [&[][..], &["0"], &["-1e-3"], &["inf"], &["NaN"], &["mm"]] {
            assert_eq!(
                spacing_args(args(bad), "u"),
                Err("usage: u".into()),
                "{bad:?}"
            );
        }
    }
}
