//! 1D tubes of 1 mm cells with any number of fluids and solids, the
//! particles' cases of several Lagrangian materials and solid reactants
//! (seed 000 §3.3 steps 1, 4, 13, 14): the tests of `solids_tests` and
//! `cargo xtask validate --only piston` run them.

use super::cases::{air, piston_measure, run, steel_eos, PistonMeasure, P0, STEEL_K, T0};
use super::*;
use brisance_constitutive::{Hypoelastic, MaterialModel, ObjectiveRate, PressureModel};
use brisance_core::Eos;
use brisance_eos::{JwlCTerm, Murnaghan, SolidEos, SolidThreshold};
use brisance_grid::Level;
use brisance_ice::{
    CellState, Deflagration, ExchangeCoefficients, IceBoundary, IceOptions, IceReaction,
    JwlPlusPlus, MaterialState, GHOST,
};
use brisance_mpm::{
    fill_shape, FillSpec, GridBoundary, MpmOptions, Shape, ShapeFunction, UpdateScheme,
};

pub const H: f64 = 1e-3;

/// One Lagrangian material: its EOS on the fluid side and its
/// constitutive model (its density is its EOS's at the tube's pressure).
#[derive(Clone)]
pub struct SolidSpec {
    /// Its EOS on the fluid side.
    pub eos: EosModel,
    /// Its constitutive model.
    pub model: MaterialModel,
}

/// A 1D tube of `cells` cells of 1 mm: the first fluid fills it at
/// pressure `p0` and rest, the other fluids are traces; blocks (x range,
/// solid index, velocity) of the solids; closed ends (symmetry faces).
pub struct Tube {
    /// Cells of 1 mm.
    pub cells: usize,
    /// Pressure, Pa.
    pub p0: f64,
    /// The fluids (the first fills the tube).
    pub fluids: Vec<EosModel>,
    /// The solids (particle material k is `solids[k]`).
    pub solids: Vec<SolidSpec>,
    /// (x from, x to, solid, x velocity) of each block, m and m/s.
    pub blocks: Vec<(f64, f64, usize, f64)>,
    /// Reactions among the ICE materials (fluids first, then solids).
    pub reactions: Vec<IceReaction>,
}

pub fn hypoelastic(bulk: f64, shear: f64) -> MaterialModel {
    MaterialModel::Hypoelastic(Hypoelastic {
        shear_modulus: shear,
        pressure: PressureModel::Linear { bulk_modulus: bulk },
        rate: ObjectiveRate::Jaumann,
    })
}

pub fn steel() -> SolidSpec {
    SolidSpec {
        eos: steel_eos(),
        model: hypoelastic(STEEL_K, 80e9),
    }
}

/// A light metal (K 76 GPa, ρ 2700 kg/m³) on both sides.
pub fn aluminium() -> SolidSpec {
    let k = 76e9;
    SolidSpec {
        eos: EosModel::SolidThreshold(SolidThreshold::with_threshold(
            SolidEos::Murnaghan(Murnaghan {
                n: 4.0,
                kappa: 1.0 / k,
                rho0: 2700.0,
                cv: 900.0,
                t_ref: T0,
            }),
            P0,
        )),
        model: hypoelastic(k, 26e9),
    }
}

/// The QM-100 reactant of seed 000 §5.2 as particles: its Murnaghan EOS
/// (K = 1/κ at ρ₀) on both sides, a small shear modulus.
pub fn qm100_reactant() -> SolidSpec {
    let m = Murnaghan::qm100();
    SolidSpec {
        eos: EosModel::Murnaghan(m),
        model: hypoelastic(1.0 / m.kappa, 1e9),
    }
}

impl Tube {
    /// The coupled solver (panics on a bad tube: the tubes are fixed).
    pub fn build(&self) -> IceMpm {
        let (ice, mpm, solids) = self.frames();
        IceMpm::new(ice, mpm, &solids).unwrap()
    }

    /// The two frames and the ICE index of each particle material.
    pub fn frames(&self) -> (IceSolver<EosModel>, MpmSolver, Vec<usize>) {
        let level = Level::new(
            [0.0; 3],
            [self.cells as f64 * H, H, H],
            [self.cells, 1, 1],
            [1, 1, 1],
            GHOST,
        )
        .unwrap();
        let nf = self.fluids.len();
        let n = nf + self.solids.len();
        let eos: Vec<EosModel> = self
            .fluids
            .iter()
            .cloned()
            .chain(self.solids.iter().map(|s| s.eos.clone()))
            .collect();
        let rho: Vec<f64> = eos
            .iter()
            .map(|e| e.density(self.p0, T0).unwrap())
            .collect();
        let eps = 1e-6;
        let blocks = self.blocks.clone();
        let mut ice = IceSolver::new(
            eos,
            level.clone(),
            std::array::from_fn(|_| IceBoundary::Symmetry),
            ExchangeCoefficients::uniform(n, 1e15, 0.0),
            IceOptions::default(),
            |x| {
                let inside = blocks.iter().find(|b| x[0] >= b.0 && x[0] <= b.1);
                let (full, u) = match inside {
                    Some(b) => (nf + b.2, b.3),
                    None => (0, 0.0),
                };
                CellState {
                    pressure: self.p0,
                    materials: (0..n)
                        .map(|r| MaterialState {
                            volume_fraction: if r == full {
                                1.0 - (n - 1) as f64 * eps
                            } else {
                                eps
                            },
                            density: rho[r],
                            velocity: [u, 0.0, 0.0],
                        })
                        .collect(),
                }
            },
        )
        .unwrap();
        ice.set_reactions(self.reactions.clone()).unwrap();
        let mut particles = Particles::default();
        for &(lo, hi, k, u) in &self.blocks {
            fill_shape(
                &mut particles,
                &level.geometry,
                &FillSpec {
                    shape: Shape::Box {
                        min: [lo, 0.0, 0.0],
                        max: [hi, H, H],
                    },
                    ppc: 2,
                    density: rho[nf + k],
                    material: MaterialId(k as u16),
                    velocity: [u, 0.0, 0.0],
                    temperature: T0,
                    specific_internal_energy: 0.0,
                },
            )
            .unwrap();
        }
        let mpm = MpmSolver::new(
            level,
            self.solids.iter().map(|s| s.model.clone()).collect(),
            particles,
            MpmOptions {
                shape: ShapeFunction::Linear,
                scheme: UpdateScheme::Musl,
                boundaries: [GridBoundary::Symmetry; 6],
                ..Default::default()
            },
        )
        .unwrap();
        (ice, mpm, (nf..n).collect())
    }
}

/// A 1D tube of 200 cells of air with a 1 cm steel piston at 100 m/s
/// whose face starts at 6 cm (the case of `cases::piston`), the piston
/// one material or two materials of the same steel meeting at its middle
/// (so two cells hold both).
pub fn piston_tube(split: bool) -> Tube {
    let blocks = if split {
        vec![(0.05, 0.055, 0, 100.0), (0.055, 0.06, 1, 100.0)]
    } else {
        vec![(0.05, 0.06, 0, 100.0)]
    };
    Tube {
        cells: 200,
        p0: P0,
        fluids: vec![air()],
        solids: if split {
            vec![steel(), steel()]
        } else {
            vec![steel()]
        },
        blocks,
        reactions: Vec::new(),
    }
}

/// The JWL++ burning tube: QM-100 products at `p0` fill 6 cm of 1 mm
/// cells; a 6 mm block of QM-100 reactant particles in the middle moves at
/// `u`; JWL++ rate G (b = 1) with the QM-100 heat of reaction.
pub fn burning_tube(p0: f64, u: f64, g: f64) -> Tube {
    let q =
        brisance_ice::reaction::detonation_energy(&Murnaghan::qm100(), &JwlCTerm::qm100()).unwrap();
    Tube {
        cells: 60,
        p0,
        fluids: vec![EosModel::JwlCTerm(JwlCTerm::qm100())],
        solids: vec![qm100_reactant()],
        blocks: vec![(0.027, 0.033, 0, u)],
        reactions: vec![IceReaction {
            reactant: 1,
            product: 0,
            rate: JwlPlusPlus {
                g,
                b: 1.0,
                threshold_pressure: 2e8,
                max_burn_fraction: 0.2,
            }
            .into(),
            heat_of_reaction: q,
        }],
    }
}

/// The piston of [`piston_tube`] at 100 µs (the measure of
/// [`super::cases::piston`] at 1 mm), with the piston one material and
/// split into two materials of the same steel.
pub fn two_material_piston() -> Result<(PistonMeasure, PistonMeasure), SolverError> {
    let t = 1e-4;
    let measure = |split: bool| -> Result<PistonMeasure, SolverError> {
        let mut s = piston_tube(split).build();
        run(&mut s, t)?;
        Ok(piston_measure(&s, 0.06, 100.0, t))
    };
    Ok((measure(false)?, measure(true)?))
}

/// What [`burning_block`] measures.
#[derive(Clone, Copy, Debug)]
pub struct BurningBlock {
    /// First step: the largest |f_p / (G p Δt) − 1| over the particles, f_p
    /// the fraction of its mass particle p lost.
    pub fraction_error: f64,
    /// Mass of both frames at the end less the start's, over the start's.
    pub mass: f64,
    /// x-momentum change over the block's initial momentum.
    pub momentum: f64,
    /// Total energy change over the heat released.
    pub energy: f64,
    /// Mass the coupled equilibration's rescale moved, over the burnt mass.
    pub rescaled: f64,
    /// Fraction of the reactant burnt.
    pub burnt_fraction: f64,
    /// Time reached, s.
    pub time: f64,
}

/// The burning tube of [`burning_tube`] at 2 GPa, the block at 100 m/s, G
/// 9.1e-5: 20 steps (no wave reaches the walls).
pub fn burning_block() -> Result<BurningBlock, SolverError> {
    let (p0, g) = (2e9, 9.1e-5);
    let mut s = burning_tube(p0, 100.0, g).build();
    let ps0 = s.mpm().particles().clone();
    let m0: f64 = ps0.mass.iter().sum();
    let before = s.conservation_totals();
    let mut p = vec![0.0; s.ice().level().geometry.cell_count()];
    s.ice().equilibration_pressure_field(&mut p);
    let dt = s.stable_dt()?;
    s.advance(dt)?;
    let g_p_dt = |x: [f64; 3]| g * steps::cell_value_at(&s.mpm().level().geometry, &p, x) * dt;
    let ps = s.mpm().particles();
    let fraction_error = (0..ps.len())
        .map(|k| ((1.0 - ps.mass[k] / ps0.mass[k]) / g_p_dt(ps0.position[k]) - 1.0).abs())
        .fold(0.0, f64::max);
    for _ in 1..20 {
        let dt = s.stable_dt()?;
        s.advance(dt)?;
    }
    let after = s.conservation_totals();
    let burnt = m0 - s.unburnt_reactant()[0];
    let heat = burnt * s.burns[0].heat;
    Ok(BurningBlock {
        fraction_error,
        mass: (after.mass - before.mass) / before.mass,
        momentum: (after.momentum[0] - before.momentum[0]) / (m0 * 100.0),
        energy: (after.energy - before.energy) / heat,
        rescaled: s.rescaled_totals().mass / burnt,
        burnt_fraction: burnt / m0,
        time: s.time(),
    })
}

/// The energy closure of [`burning_block`] under a smaller time step: the
/// same tube run to `t_end` with Δt = `scale` × the stable step (the last
/// step cut to land on `t_end`). Returns (total energy change over the heat
/// released, heat released in J, steps).
///
/// The coupled step's energy error is a splitting error of the step: it
/// falls with Δt at a fixed end time (docs/physics/couple/ice_mpm.md,
/// "The burning block's energy in Δt").
pub fn burning_block_energy(scale: f64, t_end: f64) -> Result<(f64, f64, u64), SolverError> {
    let (p0, g) = (2e9, 9.1e-5);
    let mut s = burning_tube(p0, 100.0, g).build();
    let m0: f64 = s.mpm().particles().mass.iter().sum();
    let before = s.conservation_totals();
    let mut steps = 0;
    while s.time() < t_end * (1.0 - 1e-12) {
        let dt = (s.stable_dt()? * scale).min(t_end - s.time());
        s.advance(dt)?;
        steps += 1;
    }
    let after = s.conservation_totals();
    let heat = (m0 - s.unburnt_reactant()[0]) * s.burns[0].heat;
    Ok(((after.energy - before.energy) / heat, heat, steps))
}

/// What [`particle_deflagration`] measures.
#[derive(Clone, Copy, Debug)]
pub struct ParticleBurn {
    /// Mass the particles lost over the measuring window, kg.
    pub burnt: f64,
    /// Mass the law burns over the same steps, Σ a D ρ_r Δt, kg: a the
    /// surface pass's area, D the mean of A pⁿ over the burning surface at
    /// its cells' own pressure ([`IceSolver::burning_surface`]), ρ_r the
    /// reactant's density at that pressure and 300 K.
    pub by_law: f64,
    /// The largest |a / (2 A_x) − 1| over the steps, A_x the tube's
    /// cross-section: the block's two faces.
    pub area_error: f64,
    /// The pressure at the start, Pa.
    pub held_pressure: f64,
    /// The surface's pressure at the end (the one at which A pⁿ is the
    /// surface's mean D), Pa.
    pub surface_pressure: f64,
    /// Steps taken.
    pub steps: u64,
}

impl ParticleBurn {
    /// burnt / by_law − 1.
    pub fn error(&self) -> f64 {
        self.burnt / self.by_law - 1.0
    }
}

/// A particle reactant deflagrating (seed 000 §4.1.2, eqs 38–39): the
/// block of [`burning_tube`] (6 mm of QM-100 reactant particles at rest in
/// its products at 100 MPa, 300 K, 1 mm cells) burning by PBX-9501's law
/// ([`Deflagration::pbx_9501`], lit at 250 K, below the tube's 300 K) for
/// the time A pⁿ of 100 MPa takes to burn one cell from each face. The
/// products stay shut in the tube, so the pressure climbs; the window is
/// the last 80 % of the run.
pub fn particle_deflagration() -> Result<ParticleBurn, SolverError> {
    let p0 = 1e8;
    let mut tube = burning_tube(p0, 0.0, 0.0);
    let pbx = Deflagration::pbx_9501();
    let law =
        Deflagration::new(pbx.a, pbx.n, 250.0).map_err(|e| SolverError::Other(e.to_string()))?;
    tube.reactions[0].rate = law.into();
    let mut s = tube.build();
    let eos = qm100_reactant().eos;
    let t_end = H / law.burn_speed(p0, T0);
    let mut mass: f64 = s.mpm().particles().mass.iter().sum();
    let (mut burnt, mut by_law, mut area_error) = (0.0, 0.0, 0.0f64);
    let mut surface_pressure = p0;
    while s.time() < t_end * (1.0 - 1e-12) {
        let dt = s.stable_dt()?.min(t_end - s.time());
        s.advance(dt)?;
        let m: f64 = s.mpm().particles().mass.iter().sum();
        let (area, speed) = s
            .ice()
            .burning_surface(0)
            .ok_or_else(|| SolverError::Other("no burning surface".into()))?;
        area_error = area_error.max((area / (2.0 * H * H) - 1.0).abs());
        if s.time() >= 0.2 * t_end {
            surface_pressure = (speed / law.a).powf(1.0 / law.n);
            let rho = eos
                .density(surface_pressure, T0)
                .map_err(|e| SolverError::Other(e.to_string()))?;
            burnt += mass - m;
            by_law += area * speed * rho * dt;
        }
        mass = m;
    }
    Ok(ParticleBurn {
        burnt,
        by_law,
        area_error,
        held_pressure: p0,
        surface_pressure,
        steps: s.ice().steps(),
    })
}
