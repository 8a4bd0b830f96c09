//! E-PD-FRAG: seed 004's fragmenting steel cylinder, built from
//! `configs/pd_fragment_full.ron` through the composer at any lattice
//! spacing, run to the config's end and cut into fragments.

use brisance_pd::cases::{fragment, FragmentResult};
use brisance_pd::PdSolver;

use crate::pd_tube::{CaseWall, Tube};

/// The E-PD-FRAG scenario file (the full 4.25 in tube, to 40 µs).
pub const PD_FRAGMENT_FULL_CONFIG: &str = include_str!("../../../configs/pd_fragment_full.ron");

/// E-PD-FRAG-WEIBULL's scenario file: the same tube with the steel's
/// critical stretch spread over a Weibull grain field
/// (`brisance_pd::strength`).
pub const PD_FRAGMENT_WEIBULL_CONFIG: &str =
    include_str!("../../../configs/validation/pd_fragment_weibull.ron");

/// The steel's critical stretch: the same everywhere (seed 004 as
/// printed, `configs/pd_fragment_full.ron`) or spread over a Weibull
/// grain field (`configs/validation/pd_fragment_weibull.ron`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Strength {
    /// One critical stretch for every bond.
    Printed,
    /// A Weibull strength factor per grain.
    Weibull,
}

impl Strength {
    /// The scenario file's path and text.
    pub fn config(self) -> (&'static str, &'static str) {
        match self {
            Self::Printed => ("configs/pd_fragment_full.ron", PD_FRAGMENT_FULL_CONFIG),
            Self::Weibull => (
                "configs/validation/pd_fragment_weibull.ron",
                PD_FRAGMENT_WEIBULL_CONFIG,
            ),
        }
    }
}

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
    tube_with(Strength::Printed, spacing)
}

/// The full tube of `strength`'s scenario file at lattice spacing
/// `spacing` (m), built.
pub fn tube_with(strength: Strength, spacing: f64) -> Result<Tube, String> {
    let (file, text) = strength.config();
    Tube::at(file, text, spacing)
}

/// The full E-PD-FRAG tube at lattice spacing `spacing` (m), stepped at its
/// stable step to the config's end time and cut into fragments.
pub fn fragmenting_cylinder(spacing: f64) -> Result<FragmentationRun, String> {
    fragmenting_cylinder_with(Strength::Printed, spacing)
}

/// [`fragmenting_cylinder`] of `strength`'s scenario file.
pub fn fragmenting_cylinder_with(
    strength: Strength,
    spacing: f64,
) -> Result<FragmentationRun, String> {
    let t = tube_with(strength, spacing)?;
    let (solver, result) = fragment(t.solver, t.scenario.time.end)?;
    Ok(FragmentationRun {
        solver,
        result,
        case: t.wall,
    })
}

/// How the case broke up: the fragments a plane across the tube's middle
/// cuts (the counterpart of Mott's ring fragments, N = 2πr/x₀) and the
/// fragments that run the whole length of the tube.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Census {
    /// Fragments of at least two nodes with a node within half a spacing
    /// of the mid-length plane.
    pub across_mid: usize,
    /// Fragments with nodes within two spacings of both ends of the tube.
    pub full_length: usize,
    /// The full-length fragments' share of the case mass.
    pub full_length_mass: f64,
}

/// The [`Census`] of solver `s`'s case (the tube `wall` from z = 0 to
/// its length, lattice spacing `spacing`).
pub fn census(s: &PdSolver, wall: &CaseWall, spacing: f64) -> Census {
    use std::collections::BTreeMap;
    let case = brisance_pd::cases::case_material(s);
    let labels = s.fragment_labels();
    // Per fragment: node count, mass, smallest and largest z.
    let mut frags: BTreeMap<usize, (usize, f64, f64, f64)> = BTreeMap::new();
    let mut total = 0.0;
    for (i, &l) in labels.iter().enumerate() {
        if l == usize::MAX || s.materials()[i] != case {
            continue;
        }
        let z = s.reference()[i][2];
        let e = frags
            .entry(l)
            .or_insert((0, 0.0, f64::INFINITY, f64::NEG_INFINITY));
        e.0 += 1;
        e.1 += s.mass(i);
        e.2 = e.2.min(z);
        e.3 = e.3.max(z);
        total += s.mass(i);
    }
    let mid = 0.5 * wall.length;
    let mut cut = std::collections::BTreeSet::new();
    for (i, &l) in labels.iter().enumerate() {
        if l != usize::MAX
            && s.materials()[i] == case
            && (s.reference()[i][2] - mid).abs() <= 0.5 * spacing
            && frags[&l].0 >= 2
        {
            cut.insert(l);
        }
    }
    let long: Vec<_> = frags
        .values()
        .filter(|f| f.2 <= 2.0 * spacing && f.3 >= wall.length - 2.0 * spacing)
        .collect();
    Census {
        across_mid: cut.len(),
        full_length: long.len(),
        full_length_mass: long.iter().map(|f| f.1).sum::<f64>() / total,
    }
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

    /// The Weibull file is the same tube (nodes, masses, stable step to
    /// the bit) whose case nodes carry the grain field's factors at their
    /// positions (median 1, m = 4, 3 mm grains, seed 1) and whose charge
    /// nodes carry none.
    #[test]
    fn the_weibull_file_is_the_same_tube_with_a_grain_field() {
        use brisance_core::Solver;
        use brisance_pd::strength::StretchSpread;
        let h = 1.3e-3;
        let ta = tube(h).unwrap();
        let a = &ta.solver;
        let b = tube_with(Strength::Weibull, h).unwrap();
        assert_eq!(ta.wall, b.wall);
        assert_eq!(a.reference(), b.solver.reference());
        assert_eq!(a.materials(), b.solver.materials());
        assert_eq!(a.stable_dt().unwrap(), b.solver.stable_dt().unwrap());
        let spread = StretchSpread {
            weibull_modulus: 4.0,
            grain_size: 3.0e-3,
            seed: 1,
        };
        let case = brisance_pd::cases::case_material(&b.solver);
        let (mut n, mut below) = (0usize, 0usize);
        for (i, r) in b.solver.reference().iter().enumerate() {
            let f = b.solver.strength_factor(i);
            if b.solver.materials()[i] == case {
                assert_eq!(f, spread.factor_at([r[0], r[1], r[2]]));
                n += 1;
                below += usize::from(f < 1.0);
            } else {
                assert_eq!(f, 1.0);
                assert_eq!(a.strength_factor(i), 1.0);
            }
        }
        // Roughly half the case below the median (the grains are few
        // hundred, so loosely).
        let share = below as f64 / n as f64;
        assert!((0.3..0.7).contains(&share), "{share}");
    }

    /// The census by hand: the whole tube is one full-length fragment;
    /// cut along the planes x = 0 and y = 0 (no node lies on them) it is
    /// four full-length quarters, each cut by the middle plane; cut across
    /// the middle too, there are eight pieces, none runs the full length,
    /// and the nodes within half a spacing of the middle (one layer, on
    /// one side of the cut at this spacing) lie in four of them.
    #[test]
    fn the_census_by_hand() {
        let h = 3.0e-3;
        let mut t = tube(h).unwrap();
        let whole = census(&t.solver, &t.wall, h);
        assert_eq!(
            whole,
            Census {
                across_mid: 1,
                full_length: 1,
                full_length_mass: 1.0
            }
        );
        t.solver
            .break_bonds(|a, b| a[0] * b[0] < 0.0 || a[1] * b[1] < 0.0);
        let quarters = census(&t.solver, &t.wall, h);
        assert_eq!((quarters.across_mid, quarters.full_length), (4, 4));
        // Summed in node order per fragment and in all: 1 to rounding.
        assert!(
            (quarters.full_length_mass - 1.0).abs() < 1e-13,
            "{quarters:?}"
        );
        assert_eq!(t.solver.fragments().len(), 4);
        let mid = 0.5 * t.wall.length;
        t.solver
            .break_bonds(|a, b| (a[2] - mid) * (b[2] - mid) < 0.0);
        let eighths = census(&t.solver, &t.wall, h);
        assert_eq!(t.solver.fragments().len(), 8);
        assert_eq!((eighths.full_length, eighths.full_length_mass), (0, 0.0));
        assert_eq!(eighths.across_mid, 4);
    }

    #[test]
    fn a_bad_spacing_is_an_error() {
        for h in [0.0, -1e-3, f64::NAN] {
            assert!(fragmenting_cylinder(h).is_err());
        }
    }
}
