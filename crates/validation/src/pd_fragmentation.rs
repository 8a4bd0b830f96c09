//! E-PD-FRAG: seed 004's fragmenting steel cylinder, built from
//! `configs/pd_fragment_full.ron` through the composer at any lattice
//! spacing, run to the config's end and cut into fragments.

use brisance_pd::cases::{fragment, EnergyBudget, FragmentResult};
use brisance_pd::{CmdPoint, Fragment, PdSolver};

use crate::pd_tube::{CaseWall, Tube};

/// The E-PD-FRAG scenario file (the full 4.25 in tube, to 40 µs).
pub const PD_FRAGMENT_FULL_CONFIG: &str = include_str!("../../../configs/pd_fragment_full.ron");

/// E-PD-FRAG-WEIBULL's scenario file: the same tube with the steel's
/// critical stretch spread over a Weibull grain field
/// (`brisance_pd::strength`).
pub const PD_FRAGMENT_WEIBULL_CONFIG: &str =
    include_str!("../../../configs/validation/pd_fragment_weibull.ron");

/// E-PD-FRAG-PERTURBED's scenario file: the Weibull tube on a perturbed
/// lattice (`brisance_pd::LatticeJitter`).
pub const PD_FRAGMENT_PERTURBED_CONFIG: &str =
    include_str!("../../../configs/validation/pd_fragment_perturbed.ron");

/// The steel's critical stretch: the same everywhere (seed 004 as
/// printed, `configs/pd_fragment_full.ron`) or spread over a Weibull
/// grain field (`configs/validation/pd_fragment_weibull.ron`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Strength {
    /// One critical stretch for every bond.
    Printed,
    /// A Weibull strength factor per grain.
    Weibull,
    /// A Weibull strength factor per grain, on a perturbed lattice.
    WeibullPerturbed,
}

impl Strength {
    /// The variant a study's command line names: `printed`, `weibull` or
    /// `perturbed`.
    pub fn named(name: &str) -> Option<Self> {
        match name {
            "printed" => Some(Self::Printed),
            "weibull" => Some(Self::Weibull),
            "perturbed" => Some(Self::WeibullPerturbed),
            _ => None,
        }
    }

    /// The scenario file's path and text.
    pub fn config(self) -> (&'static str, &'static str) {
        match self {
            Self::Printed => ("configs/pd_fragment_full.ron", PD_FRAGMENT_FULL_CONFIG),
            Self::Weibull => (
                "configs/validation/pd_fragment_weibull.ron",
                PD_FRAGMENT_WEIBULL_CONFIG,
            ),
            Self::WeibullPerturbed => (
                "configs/validation/pd_fragment_perturbed.ron",
                PD_FRAGMENT_PERTURBED_CONFIG,
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
    /// Where the energy was at the start (the products' W(1) V and the
    /// rest zero; [`EnergyBudget`]).
    pub initial_energy: EnergyBudget,
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
    fragmenting_cylinder_set(strength, spacing, &[])
}

/// [`fragmenting_cylinder_with`] with further `--set` overrides of the
/// scenario (`key=value`; [`Tube::at_with`]), for studies outside the
/// report.
pub fn fragmenting_cylinder_set(
    strength: Strength,
    spacing: f64,
    overrides: &[String],
) -> Result<FragmentationRun, String> {
    let (file, text) = strength.config();
    fragment_tube(Tube::at_with(file, text, spacing, overrides)?)
}

/// Tube `t`, already built, stepped at its stable step to its scenario's
/// end time and cut into fragments.
pub fn fragment_tube(t: Tube) -> Result<FragmentationRun, String> {
    let initial_energy = EnergyBudget::of(&t.solver);
    let (solver, result) = fragment(t.solver, t.scenario.time.end)?;
    Ok(FragmentationRun {
        solver,
        result,
        case: t.wall,
        initial_energy,
    })
}

/// The command line of the study examples (`pd_frag_spacing`,
/// `pd_frag_angles`): `printed|weibull|perturbed SPACING_M` and what
/// follows, or the usage line `usage` as the error.
pub fn study_args(
    mut args: impl Iterator<Item = String>,
    usage: &str,
) -> Result<(Strength, f64, Vec<String>), String> {
    let strength = args.next().as_deref().and_then(Strength::named);
    let spacing = crate::pd_tube::parse_spacing(args.next());
    match (strength, spacing) {
        (Some(st), Some(h)) => Ok((st, h, args.collect())),
        _ => Err(format!("usage: {usage}")),
    }
}

/// The fragments' kinetic-energy mean speed, m/s: (Σ m v² / Σ m)^{1/2}
/// (Mott's V in the report's comparison).
pub fn mean_speed(r: &FragmentResult) -> f64 {
    (r.fragments
        .iter()
        .map(|f| f.mass * f.velocity.iter().map(|v| v * v).sum::<f64>())
        .sum::<f64>()
        / r.fragment_mass)
        .sqrt()
}

/// Median of the fragment masses by count, kg, of `fragments` sorted by
/// decreasing mass (as the fragment search returns them): the middle one,
/// or the mean of the middle two; NaN without fragments.
pub fn median_mass(fragments: &[Fragment]) -> f64 {
    let n = fragments.len();
    match n {
        0 => f64::NAN,
        _ if n % 2 == 1 => fragments[n / 2].mass,
        _ => 0.5 * (fragments[n / 2 - 1].mass + fragments[n / 2].mass),
    }
}

/// Mass-median fragment mass m₅₀, kg, from the cumulative mass
/// distribution `cmd` (`brisance_pd::cumulative_mass_distribution`): the
/// smallest fragment mass such that the fragments at least this heavy hold
/// half the fragments' mass (the case's to round-off); 0 for an empty
/// distribution.
pub fn mass_median(cmd: &[CmdPoint]) -> f64 {
    cmd.iter()
        .find(|c| c.mass_fraction_at_least >= 0.5)
        .map_or(0.0, |c| c.mass)
}

/// The share of the case mass in the ten largest fragments (in all of
/// them when there are fewer): E-PD-FRAG's figure of merit for
/// convergence beside m₅₀.
pub fn ten_largest_fraction(r: &FragmentResult) -> f64 {
    r.fragments.iter().take(10).map(|f| f.mass).sum::<f64>() / r.case_mass
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
        // Folded from +0 (a float sum of nothing is −0, printed "-0.0").
        full_length_mass: long.iter().fold(0.0, |m, f| m + f.1) / total,
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

    /// The perturbed file is the Weibull tube with every node moved by
    /// its lattice site's offset (a quarter spacing at most along each
    /// axis, seed 1), the grain field's factors taken at the moved
    /// positions.
    #[test]
    fn the_perturbed_file_is_the_weibull_tube_on_a_jittered_lattice() {
        use brisance_pd::LatticeJitter;
        let h = 1.3e-3;
        let a = tube_with(Strength::Weibull, h).unwrap();
        let b = tube_with(Strength::WeibullPerturbed, h).unwrap();
        assert_eq!(a.wall, b.wall);
        let jitter = LatticeJitter {
            amplitude: 0.25,
            seed: 1,
        };
        // Sites by their regular positions (lattice origin 0, sites at
        // (i + ½) h), and the moved nodes looked up by site.
        let site = |x: &[f64; 4]| [0, 1, 2].map(|d| (x[d] / h - 0.5).round() as i64);
        let moved: std::collections::HashMap<[i64; 3], usize> = b
            .solver
            .reference()
            .iter()
            .enumerate()
            .map(|(i, x)| (site(x), i))
            .collect();
        assert_eq!(moved.len(), b.solver.node_count());
        let mut same = 0usize;
        for (i, x) in a.solver.reference().iter().enumerate() {
            let k = site(x);
            let Some(&j) = moved.get(&k) else { continue };
            let y = b.solver.reference()[j];
            let o = jitter.offset(k);
            assert!((0..3).all(|d| y[d] == x[d] + o[d] * h));
            same += usize::from(a.solver.materials()[i] == b.solver.materials()[j]);
        }
        // Sites near a surface may move out of (or into) a body: the
        // counts differ by a few per cent at most.
        let (na, nb) = (a.solver.node_count(), b.solver.node_count());
        assert!((na as f64 / nb as f64 - 1.0).abs() < 0.02, "{na} {nb}");
        assert!(same as f64 > 0.95 * na as f64, "{same} of {na}");
    }

    /// The mean speed by hand: 1 kg at (3, 4, 0) m/s and 3 kg at
    /// (0, 0, 1) m/s give (28 / 4)^{1/2} = √7 m/s; the study's names.
    #[test]
    fn the_mean_speed_and_the_names_by_hand() {
        use brisance_pd::Fragment;
        let r = FragmentResult {
            fragments: vec![
                Fragment {
                    mass: 3.0,
                    velocity: [0.0, 0.0, 1.0],
                    nodes: 3,
                    label: 0,
                },
                Fragment {
                    mass: 1.0,
                    velocity: [3.0, 4.0, 0.0],
                    nodes: 1,
                    label: 3,
                },
            ],
            case_mass: 4.0,
            fragment_mass: 4.0,
            steps: 1,
        };
        assert!((mean_speed(&r) - 7f64.sqrt()).abs() < 1e-15);
        assert_eq!(Strength::named("printed"), Some(Strength::Printed));
        assert_eq!(Strength::named("weibull"), Some(Strength::Weibull));
        assert_eq!(
            Strength::named("perturbed"),
            Some(Strength::WeibullPerturbed)
        );
        assert_eq!(Strength::named("regular"), None);
        use crate::pd_tube::args;
        assert_eq!(
            study_args(args(&["perturbed", "1.3e-3", "time.end=5e-5"]), "u"),
            Ok((
                Strength::WeibullPerturbed,
                1.3e-3,
                vec!["time.end=5e-5".to_string()]
            ))
        );
        assert_eq!(study_args(args(&["weibull"]), "u"), Err("usage: u".into()));
        assert_eq!(
            study_args(args(&["x", "1e-3"]), "u"),
            Err("usage: u".into())
        );
        for bad in ["0", "-1e-3", "inf", "NaN"] {
            assert_eq!(
                study_args(args(&["printed", bad]), "u"),
                Err("usage: u".into()),
                "{bad}"
            );
        }
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
        // +0, so the report prints "0.0 %", not "-0.0 %".
        assert!(eighths.full_length_mass.is_sign_positive());
        assert_eq!(eighths.across_mid, 4);
    }

    #[test]
    fn a_bad_spacing_is_an_error() {
        for h in [0.0, -1e-3, f64::NAN] {
            assert!(fragmenting_cylinder(h).is_err());
        }
    }

    /// The three measures by hand on five fragments of 5, 4, 3, 2, 1 kg
    /// (case 15 kg): median by count 3 kg (and 3.5 kg without the last),
    /// m₅₀ 4 kg (5 + 4 = 9 of 15 kg is the first share ≥ ½), the ten
    /// largest all of them; twelve 1 kg fragments hold 10 of 12 kg in
    /// their ten largest; no fragments give NaN, 0 and 0.
    #[test]
    fn the_fragment_measures_by_hand() {
        let frag = |mass: f64| Fragment {
            mass,
            velocity: [0.0; 3],
            nodes: 1,
            label: 0,
        };
        let five: Vec<Fragment> = [5.0, 4.0, 3.0, 2.0, 1.0].map(frag).to_vec();
        assert_eq!(median_mass(&five), 3.0);
        assert_eq!(median_mass(&five[..4]), 3.5);
        let cmd = brisance_pd::cumulative_mass_distribution(&five);
        assert_eq!(mass_median(&cmd), 4.0);
        let result = |fragments: Vec<Fragment>| FragmentResult {
            case_mass: fragments.iter().map(|f| f.mass).sum(),
            fragment_mass: fragments.iter().map(|f| f.mass).sum(),
            fragments,
            steps: 1,
        };
        assert_eq!(ten_largest_fraction(&result(five)), 1.0);
        let twelve = result(vec![frag(1.0); 12]);
        assert!((ten_largest_fraction(&twelve) - 10.0 / 12.0).abs() < 1e-15);
        assert!(median_mass(&[]).is_nan());
        assert_eq!(mass_median(&[]), 0.0);
        assert!(ten_largest_fraction(&result(Vec::new())).is_nan());
    }
}
