//! Sets of particles chosen once, by their state at the start of the run,
//! and followed wherever they move: the particle gauges of a run ("the
//! outer-wall particles at z = 25 cm: mean velocity").
//!
//! A [`ParticleSet`] is a membership flag per particle *identity* (the
//! particle's index in the set handed to [`MpmSolver::new`], which
//! [`MpmSolver::particle_ids`] carries through every sort and removal), so
//! the members stay the same material points however the solver reorders
//! them. [`ParticleSet::sample`] reduces the members present in the solver
//! to set averages:
//!
//! | quantity | columns | average |
//! |---|---|---|
//! | `MeanVelocity` | `mean_velocity_x/y/z` | mass-weighted, Σ m v / Σ m (the set's momentum over its mass) |
//! | `MeanPosition` | `mean_position_x/y/z` | centre of mass Σ m x / Σ m |
//! | `MeanDisplacement` | `mean_displacement_x/y/z` | centre of mass minus its value at the start |
//! | `MeanStress` | `mean_stress_xx/yy/zz/yz/xz/xy` | volume-weighted Σ V σ / Σ V of the material stress (without the bulk viscosity q) |
//! | `MeanPressure` | `mean_pressure` | volume-weighted material pressure −tr σ/3 |
//! | `MeanVonMisesStress` | `mean_von_mises_stress` | volume-weighted von Mises stress |
//! | `MeanTemperature` | `mean_temperature` | mass-weighted |
//! | `MeanSpecificInternalEnergy` | `mean_specific_internal_energy` | mass-weighted |
//! | `Mass` | `mass` | Σ m of the members still in the domain |
//!
//! Volume weighting makes the mean stress the stress resultant of the set
//! (∫σ dV / V); mass weighting makes the mean velocity its momentum per
//! unit mass. Sums run in particle order, which depends only on the
//! particle positions, so a sample has the same bits on any number of
//! threads. Members that left through an outflow face no longer count;
//! when none is left every value is NaN (and `Mass` is 0).

use crate::{MaterialId, MpmSolver, Particles};
pub use brisance_core::SetQuantity;

/// A set of particles chosen by their initial state (see the module doc).
#[derive(Debug, Clone, PartialEq)]
pub struct ParticleSet {
    /// Membership by particle identity.
    members: Vec<bool>,
    /// Number of members.
    count: usize,
    /// Centre of mass of the members at selection, m.
    initial_centre: [f64; 3],
}

impl ParticleSet {
    /// The particles of `particles` — in the order they will be handed to
    /// [`MpmSolver::new`], so particle i gets identity i — for which
    /// `select(position, material)` holds.
    pub fn select(particles: &Particles, select: impl Fn([f64; 3], MaterialId) -> bool) -> Self {
        let members: Vec<bool> = (0..particles.len())
            .map(|p| select(particles.position[p], particles.material[p]))
            .collect();
        let mut mass = 0.0;
        let mut moment = [0.0; 3];
        for p in (0..particles.len()).filter(|&p| members[p]) {
            let m = particles.mass[p];
            mass += m;
            for (sum, x) in moment.iter_mut().zip(particles.position[p]) {
                *sum += m * x;
            }
        }
        Self {
            count: members.iter().filter(|&&b| b).count(),
            members,
            initial_centre: moment.map(|x| if mass > 0.0 { x / mass } else { f64::NAN }),
        }
    }

    /// Number of members (at selection).
    pub fn len(&self) -> usize {
        self.count
    }

    /// Whether the set has no member.
    pub fn is_empty(&self) -> bool {
        self.count == 0
    }

    /// Whether the particle of identity `id` is a member.
    #[inline]
    pub fn contains(&self, id: u32) -> bool {
        self.members.get(id as usize).copied().unwrap_or(false)
    }

    /// Centre of mass of the members at selection, m.
    pub fn initial_centre(&self) -> [f64; 3] {
        self.initial_centre
    }

    /// The columns of `quantities`, in order.
    pub fn columns(quantities: &[SetQuantity]) -> Vec<String> {
        quantities
            .iter()
            .flat_map(|q| q.columns().iter().map(|c| c.to_string()))
            .collect()
    }

    /// The set averages of `quantities` over the members present in
    /// `solver`, into `out` (cleared first; [`ParticleSet::columns`] names
    /// them).
    pub fn sample(&self, solver: &MpmSolver, quantities: &[SetQuantity], out: &mut Vec<f64>) {
        let ps = solver.particles();
        let ids = solver.particle_ids();
        let bulk = solver.bulk_viscosity();
        let mut mass = 0.0;
        let mut momentum = [0.0; 3];
        let mut moment = [0.0; 3];
        let mut volume = 0.0;
        let mut stress = [0.0; 6];
        let mut von_mises = 0.0;
        let mut temperature = 0.0;
        let mut energy = 0.0;
        for p in 0..ps.len() {
            if !self.contains(ids[p]) {
                continue;
            }
            let (m, v) = (ps.mass[p], ps.volume[p]);
            mass += m;
            volume += v;
            for c in 0..3 {
                momentum[c] += m * ps.velocity[p][c];
                moment[c] += m * ps.position[p][c];
            }
            let q = bulk[p].q;
            let mut s = ps.stress[p];
            for sc in s.iter_mut().take(3) {
                *sc += q;
            }
            for c in 0..6 {
                stress[c] += v * s[c];
            }
            von_mises += v * von_mises_of(&s);
            temperature += m * ps.temperature[p];
            energy += m * ps.specific_internal_energy[p];
        }
        let per_mass = |x: f64| if mass > 0.0 { x / mass } else { f64::NAN };
        let per_volume = |x: f64| if volume > 0.0 { x / volume } else { f64::NAN };
        out.clear();
        for q in quantities {
            match q {
                SetQuantity::MeanVelocity => out.extend(momentum.map(per_mass)),
                SetQuantity::MeanPosition => out.extend(moment.map(per_mass)),
                SetQuantity::MeanDisplacement => {
                    let centre = moment.map(per_mass);
                    out.extend((0..3).map(|c| centre[c] - self.initial_centre[c]));
                }
                SetQuantity::MeanStress => out.extend(stress.map(per_volume)),
                SetQuantity::MeanPressure => {
                    out.push(-per_volume(stress[0] + stress[1] + stress[2]) / 3.0)
                }
                SetQuantity::MeanVonMisesStress => out.push(per_volume(von_mises)),
                SetQuantity::MeanTemperature => out.push(per_mass(temperature)),
                SetQuantity::MeanSpecificInternalEnergy => out.push(per_mass(energy)),
                SetQuantity::Mass => out.push(mass),
            }
        }
    }
}

/// √(3 J₂) of a Voigt stress.
fn von_mises_of(s: &[f64; 6]) -> f64 {
    let (a, b, c) = (s[0] - s[1], s[1] - s[2], s[2] - s[0]);
    (0.5 * (a * a + b * b + c * c) + 3.0 * (s[3] * s[3] + s[4] * s[4] + s[5] * s[5])).sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{fill_shape, FillSpec, GridBoundary, MpmOptions, Shape};
    use brisance_constitutive::{Hypoelastic, MaterialModel, ObjectiveRate, PressureModel};
    use brisance_core::Solver;
    use brisance_grid::Level;

    fn soft() -> MaterialModel {
        MaterialModel::Hypoelastic(Hypoelastic {
            shear_modulus: 5.0e6,
            pressure: PressureModel::Linear {
                bulk_modulus: 1.0e7,
            },
            rate: ObjectiveRate::Jaumann,
        })
    }

    fn block(ps: &mut Particles, lo: [f64; 3], hi: [f64; 3], density: f64, v: [f64; 3]) {
        fill_shape(
            ps,
            &Level::new([0.0; 3], [1.0; 3], [8, 8, 1], [1, 1, 1], 0)
                .unwrap()
                .geometry,
            &FillSpec {
                shape: Shape::Box { min: lo, max: hi },
                ppc: 2,
                density,
                material: MaterialId(0),
                velocity: v,
                temperature: 300.0,
                specific_internal_energy: 0.0,
            },
        )
        .unwrap();
    }

    fn solver(ps: Particles, boundaries: [GridBoundary; 6]) -> MpmSolver {
        let level = Level::new([0.0; 3], [1.0; 3], [8, 8, 1], [1, 1, 1], 0).unwrap();
        MpmSolver::new(
            level,
            vec![soft()],
            ps,
            MpmOptions {
                boundaries,
                ..Default::default()
            },
        )
        .unwrap()
    }

    fn in_box(lo: [f64; 3], hi: [f64; 3]) -> impl Fn([f64; 3], MaterialId) -> bool {
        move |x, _| (0..3).all(|d| x[d] >= lo[d] && x[d] <= hi[d])
    }

    #[test]
    fn a_rigidly_translating_block_has_its_velocity_and_displacement() {
        // A block moving at (0.5, −0.25) m/s far from a block at rest, on
        // the dyadic 1/8 m grid (the transfers of a uniform velocity are
        // exact): the gauge of the moving block reads its velocity exactly
        // and its displacement v t to round-off, the other block reads 0.
        let mut ps = Particles::new(0);
        let v = [0.5, -0.25, 0.0];
        block(
            &mut ps,
            [0.625, 0.625, 0.0],
            [0.875, 0.875, 1.0],
            1024.0,
            [0.0; 3],
        );
        block(&mut ps, [0.125, 0.25, 0.0], [0.375, 0.5, 1.0], 1024.0, v);
        let moving = ParticleSet::select(&ps, in_box([0.0; 3], [0.5, 0.5, 1.0]));
        let still = ParticleSet::select(&ps, in_box([0.5, 0.5, 0.0], [1.0; 3]));
        assert_eq!((moving.len(), still.len()), (16, 16));
        // Centre of the moving block at selection: (0.25, 0.375, 0.5).
        assert_eq!(moving.initial_centre(), [0.25, 0.375, 0.5]);
        let mut s = solver(ps, [GridBoundary::Free; 6]);
        let q = [SetQuantity::MeanVelocity, SetQuantity::MeanDisplacement];
        assert_eq!(
            ParticleSet::columns(&q),
            [
                "mean_velocity_x",
                "mean_velocity_y",
                "mean_velocity_z",
                "mean_displacement_x",
                "mean_displacement_y",
                "mean_displacement_z"
            ]
        );
        let dt = 1.0 / 1024.0;
        for _ in 0..64 {
            s.advance(dt).unwrap();
        }
        let t = s.time();
        let mut out = Vec::new();
        moving.sample(&s, &q, &mut out);
        assert_eq!(&out[..3], &v);
        for c in 0..3 {
            assert!((out[3 + c] - v[c] * t).abs() < 1e-14, "{out:?}");
        }
        assert!((out[3] - 1.0 / 32.0).abs() < 1e-14);
        still.sample(&s, &q, &mut out);
        assert_eq!(out, vec![0.0; 6]);
        // The solver holding the sets samples them as the run loop does,
        // through the trait object, by the gauges' order; there is no
        // third gauge.
        let mut direct = Vec::new();
        moving.sample(&s, &q, &mut direct);
        s.set_particle_gauges(vec![still.clone(), moving.clone()]);
        let dyn_solver: &dyn Solver = &s;
        let mut through = Vec::new();
        assert!(dyn_solver.sample_particle_gauge(1, &q, &mut through));
        assert_eq!(through, direct);
        assert!(dyn_solver.sample_particle_gauge(0, &q, &mut through));
        assert_eq!(through, vec![0.0; 6]);
        assert!(!dyn_solver.sample_particle_gauge(2, &q, &mut through));
    }

    #[test]
    fn stress_pressure_and_temperature_are_volume_or_mass_weighted() {
        // Two particles of volumes 1 and 3 (m³) with hand-set stresses:
        // mean σ_xx = (1·(−4) + 3·(−8))/4 = −7, mean p = (1·4 + 3·8)/4 = 7
        // (hydrostatic), mean von Mises = (1·0 + 3·9)/4 (the second has a
        // shear σ_xy = √27: √(3·27) = 9).
        let level = Level::new([0.0; 3], [8.0; 3], [8, 8, 8], [1, 1, 1], 0).unwrap();
        let mut ps = Particles::new(0);
        let shear = 27.0_f64.sqrt();
        for (x, vol, s) in [
            ([1.5; 3], 1.0, [-4.0, -4.0, -4.0, 0.0, 0.0, 0.0]),
            ([4.5; 3], 3.0, [-8.0, -8.0, -8.0, 0.0, 0.0, shear]),
        ] {
            let init = crate::ParticleInit {
                position: x,
                mass: 2.0 * vol,
                volume: vol,
                stress: s,
                temperature: 100.0 * vol,
                ..Default::default()
            };
            ps.push(&init, &[]).unwrap();
        }
        let set = ParticleSet::select(&ps, |_, _| true);
        let s = MpmSolver::new(level, vec![soft()], ps, MpmOptions::default()).unwrap();
        let mut out = Vec::new();
        let q = [
            SetQuantity::MeanStress,
            SetQuantity::MeanPressure,
            SetQuantity::MeanVonMisesStress,
            SetQuantity::MeanTemperature,
            SetQuantity::Mass,
            SetQuantity::MeanPosition,
        ];
        set.sample(&s, &q, &mut out);
        let vm = 27.0 / 4.0;
        let expected = [
            -7.0,
            -7.0,
            -7.0,
            0.0,
            0.0,
            3.0 * shear / 4.0,
            7.0,
            vm,
            (2.0 * 100.0 + 6.0 * 300.0) / 8.0,
            8.0,
            (2.0 * 1.5 + 6.0 * 4.5) / 8.0,
            (2.0 * 1.5 + 6.0 * 4.5) / 8.0,
            (2.0 * 1.5 + 6.0 * 4.5) / 8.0,
        ];
        assert_eq!(out.len(), expected.len());
        for (k, (a, b)) in out.iter().zip(expected).enumerate() {
            assert!(
                (a - b).abs() < 1e-13 * b.abs().max(1.0),
                "column {k}: {a} vs {b}"
            );
        }
    }

    #[test]
    fn the_material_pressure_of_a_viscous_impact_leaves_q_out() {
        // Two blocks collide with the bulk viscosity on: the set pressure is
        // the volume-weighted particle `pressure` output (the material's),
        // not −tr σ_stored/3, which contains q.
        let mut ps = Particles::new(0);
        block(
            &mut ps,
            [0.125, 0.25, 0.0],
            [0.375, 0.5, 1.0],
            1024.0,
            [20.0, 0.0, 0.0],
        );
        block(
            &mut ps,
            [0.375, 0.25, 0.0],
            [0.625, 0.5, 1.0],
            1024.0,
            [-20.0, 0.0, 0.0],
        );
        let set = ParticleSet::select(&ps, |_, _| true);
        let level = Level::new([0.0; 3], [1.0; 3], [8, 8, 1], [1, 1, 1], 0).unwrap();
        let mut s = MpmSolver::new(
            level,
            vec![soft()],
            ps,
            MpmOptions {
                bulk_viscosity: Some(crate::BulkViscosity::LS_DYNA),
                ..Default::default()
            },
        )
        .unwrap();
        for _ in 0..3 {
            let dt = s.stable_dt().unwrap();
            s.advance(dt).unwrap();
        }
        assert!(s.bulk_viscosity().iter().any(|b| b.q > 0.0));
        let data = s.particle_data().unwrap();
        let col = |n: &str| data.field(n).unwrap();
        let (p, v) = (col("pressure"), col("volume"));
        let expected: f64 =
            p.iter().zip(v).map(|(p, v)| p * v).sum::<f64>() / v.iter().sum::<f64>();
        let mut out = Vec::new();
        set.sample(&s, &[SetQuantity::MeanPressure], &mut out);
        assert!(
            (out[0] - expected).abs() < 1e-12 * expected.abs(),
            "{} {expected}",
            out[0]
        );
    }

    #[test]
    fn members_are_followed_through_sorting_and_lost_through_outflow() {
        // Heavy particles pushed first (so the first step re-sorts them),
        // moving out through an outflow face.
        let mut ps = Particles::new(0);
        block(
            &mut ps,
            [0.75, 0.25, 0.0],
            [1.0, 0.5, 1.0],
            2048.0,
            [64.0, 0.0, 0.0],
        );
        block(
            &mut ps,
            [0.0, 0.25, 0.0],
            [0.25, 0.5, 1.0],
            1024.0,
            [0.0; 3],
        );
        let heavy = ParticleSet::select(&ps, in_box([0.5, 0.0, 0.0], [1.0; 3]));
        let light = ParticleSet::select(&ps, in_box([0.0; 3], [0.5, 1.0, 1.0]));
        let mut boundaries = [GridBoundary::Free; 6];
        boundaries[1] = GridBoundary::Outflow;
        let mut s = solver(ps, boundaries);
        let q = [SetQuantity::Mass, SetQuantity::MeanVelocity];
        let mut out = Vec::new();
        s.advance(1.0 / 4096.0).unwrap();
        assert_ne!(s.particle_ids()[0], 0, "the step re-sorted the particles");
        heavy.sample(&s, &q, &mut out);
        assert_eq!(out[0], 16.0 * 8.0);
        assert_eq!(out[1], 64.0);
        light.sample(&s, &q, &mut out);
        assert_eq!(out, vec![16.0 * 4.0, 0.0, 0.0, 0.0]);
        for _ in 0..16 {
            s.advance(1.0 / 1024.0).unwrap();
        }
        heavy.sample(&s, &q, &mut out);
        assert_eq!(out[0], 0.0, "every heavy particle left");
        assert!(out[1..].iter().all(|v| v.is_nan()));
        light.sample(&s, &q, &mut out);
        assert_eq!(out[0], 16.0 * 4.0);
    }
}
