//! What the peridynamic tube cases (E-PD-CYL, E-PD-FRAG) share: their
//! scenario file at a lattice spacing, the case wall it describes, and the
//! solver the `Peridynamics` section builds from it.

use brisance_compose::config::Scenario;
use brisance_compose::{build::build_section, load_str, LoadedScenario};
use brisance_grid::Shape;
use brisance_pd::{PdConfig, PdMaterialConfig, PdSolver};

/// The case wall of a tube's scenario file: its `Proportional` material
/// and `Shell` region.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CaseWall {
    /// Density, kg/m³.
    pub density: f64,
    /// Yield strength, Pa.
    pub yield_strength: f64,
    /// Critical stretch.
    pub critical_stretch: f64,
    /// Inner radius, m.
    pub inner_radius: f64,
    /// Outer radius, m.
    pub outer_radius: f64,
    /// Length along the axis, m.
    pub length: f64,
}

/// A tube's scenario, built: the scenario file `text` (named `file`) at
/// lattice spacing `spacing` (m), lit on the axis half a spacing into the
/// charge (the configs' own point at their 1.3 mm).
pub struct Tube {
    /// The scenario with the spacing and the detonation point set.
    pub scenario: Scenario,
    /// The solver the `Peridynamics` section builds from it.
    pub solver: PdSolver,
    /// Its case wall.
    pub wall: CaseWall,
}

impl Tube {
    /// Loads `text` once with the spacing set, reads its wall and builds
    /// its solver.
    pub fn at(file: &str, text: &str, spacing: f64) -> Result<Self, String> {
        Self::at_with(file, text, spacing, &[])
    }

    /// [`Tube::at`] with further `--set` overrides (`key=value`, as the
    /// command line's), applied after the spacing and the detonation point:
    /// the studies of docs/physics/pd/validation.md vary the case this way.
    pub fn at_with(
        file: &str,
        text: &str,
        spacing: f64,
        overrides: &[String],
    ) -> Result<Self, String> {
        let (loaded, wall) = load(file, text, spacing, overrides)?;
        let pd = loaded
            .scenario
            .pipeline
            .section::<PdConfig>()
            .ok_or_else(|| format!("{file}: not a Peridynamics pipeline"))?;
        let solver =
            build_section(pd, &loaded.scenario).map_err(|e| loaded.locate(e).to_string())?;
        Ok(Self {
            scenario: loaded.scenario,
            solver,
            wall,
        })
    }
}

/// The case wall the scenario file `text` (named `file`) describes, read
/// without building its solver.
pub fn wall_of(file: &str, text: &str) -> Result<CaseWall, String> {
    let scenario = load_str(file, text, &[])
        .map_err(|e| e.to_string())?
        .scenario;
    wall_in(file, &scenario)
}

/// `text` loaded with the spacing, the detonation point and `overrides`
/// set (with its text, for the place of a build error), and its wall.
fn load(
    file: &str,
    text: &str,
    spacing: f64,
    overrides: &[String],
) -> Result<(LoadedScenario, CaseWall), String> {
    if !(spacing > 0.0 && spacing.is_finite()) {
        return Err(format!(
            "{file}: spacing {spacing} m must be finite and > 0"
        ));
    }
    let mut sets = vec![
        format!("pipeline.spacing={spacing:e}"),
        format!(
            "pipeline.detonation=Some(points: [(position: (0.0, 0.0, {:e}), time: 0.0)], method: Huygens)",
            0.5 * spacing
        ),
    ];
    sets.extend_from_slice(overrides);
    let loaded = load_str(file, text, &sets).map_err(|e| e.to_string())?;
    let wall = wall_in(file, &loaded.scenario)?;
    Ok((loaded, wall))
}

/// The wall of a loaded scenario ([`case_wall`]), or an error naming the file.
fn wall_in(file: &str, scenario: &Scenario) -> Result<CaseWall, String> {
    let pd = scenario
        .pipeline
        .section::<PdConfig>()
        .ok_or_else(|| format!("{file}: not a Peridynamics pipeline"))?;
    case_wall(scenario, pd).ok_or_else(|| {
        format!("{file}: no Shell region of a Proportional material with a yield strength and a critical stretch")
    })
}

/// The first `Shell` region of a `Proportional` material with a yield
/// strength and a critical stretch.
fn case_wall(scenario: &Scenario, pd: &PdConfig) -> Option<CaseWall> {
    scenario
        .initial
        .iter()
        .find_map(|r| match (pd.materials.get(&r.material), &r.region) {
            (
                Some(PdMaterialConfig::Proportional {
                    density,
                    yield_strength: Some(y),
                    critical_stretch: Some(sc),
                    ..
                }),
                Shape::Shell {
                    inner_radius,
                    outer_radius,
                    length,
                    ..
                },
            ) => Some(CaseWall {
                density: *density,
                yield_strength: *y,
                critical_stretch: *sc,
                inner_radius: *inner_radius,
                outer_radius: *outer_radius,
                length: *length,
            }),
            _ => None,
        })
}

/// A lattice spacing from the command line: a finite positive number of
/// metres, or `None`.
pub(crate) fn parse_spacing(arg: Option<String>) -> Option<f64> {
    arg.and_then(|s| s.parse::<f64>().ok())
        .filter(|h| h.is_finite() && *h > 0.0)
}

/// The command line of the tube examples (`pd_cyl_spacing`,
/// `pd_seed000_side`): `SPACING_M` and the `KEY=VALUE` overrides that
/// follow, or the usage line `usage` as the error.
pub fn spacing_args(
    mut args: impl Iterator<Item = String>,
    usage: &str,
) -> Result<(f64, Vec<String>), String> {
    match parse_spacing(args.next()) {
        Some(h) => Ok((h, args.collect())),
        None => Err(format!("usage: {usage}")),
    }
}

/// A command line of strings, for the tests of [`spacing_args`] and
/// `pd_fragmentation::study_args`.
#[cfg(test)]
pub(crate) fn args(a: &[&str]) -> std::vec::IntoIter<String> {
    a.iter()
        .map(|s| s.to_string())
        .collect::<Vec<_>>()
        .into_iter()
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
