//! E-PD-FRAG: seed 004's fragmenting steel cylinder, built from
//! `configs/pd_fragment_full.ron` through the composer at any lattice
//! spacing, run to the config's end and cut into fragments.

use brisance_compose::build::build_section;
use brisance_compose::config::Scenario;

use crate::pd_cylinder::tube_scenario;
use brisance_grid::Shape;
use brisance_pd::cases::{fragment, FragmentResult};
use brisance_pd::{PdConfig, PdMaterialConfig, PdSolver};

/// The E-PD-FRAG scenario file (the full 4.25 in tube, to 40 µs).
pub const PD_FRAGMENT_FULL_CONFIG: &str = include_str!("../../../configs/pd_fragment_full.ron");

/// What [`fragmenting_cylinder`] measured.
pub struct FragmentationRun {
    /// The solver at the end of the run.
    pub solver: PdSolver,
    /// The fragments, their masses and the steps taken.
    pub result: FragmentResult,
    /// The case as the config gives it (for Mott's comparison).
    pub case: CaseWall,
}

/// The steel wall of the config: its `Proportional` material and `Shell`
/// region.
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
}

/// The scenario of the full tube at lattice spacing `spacing` (m): the
/// config with `pipeline.spacing` set and the detonation point on the axis
/// half a spacing into the charge (the config's own point at its 1.3 mm).
pub fn scenario(spacing: f64) -> Result<Scenario, String> {
    tube_scenario(
        "configs/pd_fragment_full.ron",
        PD_FRAGMENT_FULL_CONFIG,
        spacing,
    )
}

/// The full E-PD-FRAG tube at lattice spacing `spacing` (m): the config
/// with `pipeline.spacing` set and the detonation point on the axis half a
/// spacing into the charge (the config's own point at its 1.3 mm), built
/// by the `Peridynamics` section's builder and stepped at its stable step
/// to the config's end time.
pub fn fragmenting_cylinder(spacing: f64) -> Result<FragmentationRun, String> {
    let scenario = &scenario(spacing)?;
    let pd = scenario
        .pipeline
        .section::<PdConfig>()
        .ok_or("E-PD-FRAG: the config is not a Peridynamics pipeline")?;
    let wall = scenario
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
                    ..
                },
            ) => Some(CaseWall {
                density: *density,
                yield_strength: *y,
                critical_stretch: *sc,
                inner_radius: *inner_radius,
                outer_radius: *outer_radius,
            }),
            _ => None,
        })
        .ok_or("E-PD-FRAG: no Shell region of a Proportional material with a yield strength and a critical stretch")?;
    let s = build_section(pd, scenario).map_err(|e| e.to_string())?;
    let (solver, result) = fragment(s, scenario.time.end)?;
    Ok(FragmentationRun {
        solver,
        result,
        case: wall,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The config at a spacing builds the library case at that spacing
    /// node for node (positions, materials, masses to the bit), so the
    /// report's runs are the case the reduced tests check
    /// (`crates/pd/tests/e_pd.rs`).
    #[test]
    fn the_config_at_a_spacing_is_the_case() {
        let h = 1.3e-3;
        let loaded = scenario(h).unwrap();
        let pd = loaded.pipeline.section::<PdConfig>().unwrap();
        let a = build_section(pd, &loaded).unwrap();
        let case = brisance_pd::cases::steel_fragmenting_cylinder(h, 0.10795, 0.0, 0.0);
        let b = PdSolver::new(case.setup().unwrap()).unwrap();
        crate::pd_cylinder::assert_same_tube(&a, &b);
    }

    #[test]
    fn a_bad_spacing_is_an_error() {
        for h in [0.0, -1e-3, f64::NAN] {
            assert!(fragmenting_cylinder(h).is_err());
        }
    }
}
