//! E-PD-FRAG: seed 004's fragmenting steel cylinder, built from
//! `configs/pd_fragment_full.ron` through the composer at any lattice
//! spacing, run to the config's end and cut into fragments.

use brisance_pd::cases::{fragment, FragmentResult};
use brisance_pd::PdSolver;

use crate::pd_tube::{CaseWall, Tube};

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

/// The full tube at lattice spacing `spacing` (m), built
/// ([`Tube::at`]).
pub fn tube(spacing: f64) -> Result<Tube, String> {
    Tube::at(
        "configs/pd_fragment_full.ron",
        PD_FRAGMENT_FULL_CONFIG,
        spacing,
    )
}

/// The full E-PD-FRAG tube at lattice spacing `spacing` (m), stepped at its
/// stable step to the config's end time and cut into fragments.
pub fn fragmenting_cylinder(spacing: f64) -> Result<FragmentationRun, String> {
    let t = tube(spacing)?;
    let (solver, result) = fragment(t.solver, t.scenario.time.end)?;
    Ok(FragmentationRun {
        solver,
        result,
        case: t.wall,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::pd_tube::assert_same_tube;

    /// The config at a spacing builds the library case at that spacing
    /// node for node (positions, materials, masses to the bit), so the
    /// report's runs are the case the reduced tests check
    /// (`crates/pd/tests/e_pd.rs`).
    #[test]
    fn the_config_at_a_spacing_is_the_case() {
        let h = 1.3e-3;
        let a = tube(h).unwrap();
        let case = brisance_pd::cases::steel_fragmenting_cylinder(h, 0.10795, 0.0, 0.0);
        assert_eq!(
            (a.wall.inner_radius, a.wall.length),
            (case.inner_radius, case.length)
        );
        let b = PdSolver::new(case.setup().unwrap()).unwrap();
        assert_same_tube(&a.solver, &b);
    }

    #[test]
    fn a_bad_spacing_is_an_error() {
        for h in [0.0, -1e-3, f64::NAN] {
            assert!(fragmenting_cylinder(h).is_err());
        }
    }
}
