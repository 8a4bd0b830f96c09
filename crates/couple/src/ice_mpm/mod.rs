//! The ICE–MPM pipeline of seed 000 §3.3: Eulerian fluids (ICE) and a
//! Lagrangian solid (MPM particles) on one grid, sharing one equilibration
//! pressure and exchanging momentum and heat in every cell.
//!
//! One [`Solver::advance`] is the seed's step list:
//!
//! | step | where |
//! |---|---|
//! | 1 particles → nodes (eq 12) → cells (eq 18) | [`MpmSolver::advance_coupled`], [`steps::project_to_cells`] |
//! | 2 equilibration pressure, θ as shares of the materials' volume | [`IceSolver::compute_equilibration_pressure`] |
//! | 3 face velocities with face exchange (eq 19) | [`IceSolver::compute_face_centred_velocities`] |
//! | 4 reactions (fluid reactants) | inside [`IceSolver::compute_lagrangian_values`] |
//! | 5 Δp (eqs 20–21) | [`IceSolver::compute_pressure_increment`] |
//! | 6 face pressure (eq 22) | inside [`IceSolver::compute_lagrangian_values`] |
//! | 7 particle stresses (eq 13); internal force from σ + p I (eq 14) | [`MpmSolver::advance_coupled`] |
//! | 8–11 cell sources, Lagrangian values, exchange, specific volume | [`IceSolver::compute_lagrangian_values`] |
//! | 12 advect fluids | [`IceSolver::advect_fluids`] |
//! | 13 cell changes → nodes | [`steps::cells_to_nodes`] |
//! | 14 particles updated (eqs 16–17) | [`MpmSolver::advance_coupled`] |
//!
//! The solid is one ICE material flagged Lagrangian
//! ([`IceSolver::set_lagrangian`]) whose state in each cell is imported
//! from the particles before the equilibration. Where no particle is near,
//! it is a trace of volume fraction [`TRACE_FRACTION`] at its reference
//! density and temperature (the particles' initial means) with the
//! velocity of the cell's fluids, so that the momentum exchange moves
//! nothing there. Choices the seed leaves open are in
//! `docs/physics/couple/ice_mpm.md`.

pub mod cases;
pub mod steps;

use brisance_core::{
    CellData, ConservationTotals, NodeData, ParticleData, Solver, SolverError, UniformGridGeometry,
};
use brisance_eos::EosModel;
use brisance_ice::{IceSolver, LagrangianCells};
use brisance_mpm::{GridCoupling, GridNodes, MpmSolver, Particles};
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

/// Volume fraction of the solid in cells where no particle is.
pub const TRACE_FRACTION: f64 = 1e-6;

/// Why an [`IceMpm`] cannot be built.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("ICE–MPM: {0}")]
pub struct IceMpmError(pub String);

/// The per-cell and per-node arrays of a coupled step.
#[derive(Debug, Clone, Default)]
struct Scratch {
    cell_mass: Vec<f64>,
    cell_velocity: Vec<[f64; 3]>,
    cell_state: Vec<Option<(f64, f64)>>,
    node_sums: Vec<[f64; 3]>,
    mass_density: Vec<f64>,
    specific_volume: Vec<f64>,
    temperature: Vec<f64>,
    fluid_velocity: Vec<[f64; 3]>,
    trace: Vec<bool>,
    pressure: Vec<f64>,
    cell_change: Vec<[f64; 3]>,
    temperature_change: Vec<f64>,
    /// Per cell, the momentum a trace of the solid took in steps 8–10
    /// beyond what its nodes receive, returned to the fluids.
    trace_momentum: Vec<[f64; 3]>,
}

impl Scratch {
    fn sized(cells: usize) -> Self {
        Self {
            cell_mass: vec![0.0; cells],
            cell_velocity: vec![[0.0; 3]; cells],
            cell_state: vec![None; cells],
            node_sums: Vec::new(),
            mass_density: vec![0.0; cells],
            specific_volume: vec![0.0; cells],
            temperature: vec![0.0; cells],
            fluid_velocity: vec![[0.0; 3]; cells],
            trace: vec![false; cells],
            pressure: vec![0.0; cells],
            cell_change: vec![[0.0; 3]; cells],
            temperature_change: vec![0.0; cells],
            trace_momentum: vec![[0.0; 3]; cells],
        }
    }
}

/// The fluid frame as the MPM step sees it (the hooks of
/// [`GridCoupling`]).
struct FluidFrame<'a> {
    ice: &'a mut IceSolver<EosModel>,
    solid: usize,
    grid: UniformGridGeometry,
    reference_volume: f64,
    reference_temperature: f64,
    s: &'a mut Scratch,
}

impl FluidFrame<'_> {
    /// Step 1: the solid's cell state from the nodes (mass, velocity, eq
    /// 18) and the particles (specific volume, temperature), with the trace
    /// state where the solid is absent.
    fn project_particles_to_cells(&mut self, nodes: &GridNodes, particles: &Particles) {
        let g = &self.grid;
        let s = &mut *self.s;
        steps::project_to_cells(
            g,
            &nodes.lattice,
            &nodes.mass,
            &nodes.velocity,
            steps::ParticleState {
                position: &particles.position,
                mass: &particles.mass,
                volume: &particles.volume,
                temperature: &particles.temperature,
            },
            &mut s.node_sums,
            &mut s.cell_mass,
            &mut s.cell_velocity,
            &mut s.cell_state,
        );
        self.ice.eulerian_velocity(&mut s.fluid_velocity);
        let cell_volume: f64 = g.spacing.iter().product();
        let v_ref = self.reference_volume;
        let t_ref = self.reference_temperature;
        (
            s.cell_mass.par_iter(),
            s.cell_state.par_iter(),
            s.fluid_velocity.par_iter(),
            s.trace.par_iter_mut(),
            s.mass_density.par_iter_mut(),
            s.specific_volume.par_iter_mut(),
            s.temperature.par_iter_mut(),
            s.cell_velocity.par_iter_mut(),
        )
            .into_par_iter()
            .with_min_len(1024)
            .for_each(|(m, state, uf, trace, rho_out, v_out, t_out, u_out)| {
                let rho = m / cell_volume;
                let (v, t) = state.unwrap_or((v_ref, t_ref));
                *trace = !(rho * v > TRACE_FRACTION);
                if *trace {
                    *rho_out = TRACE_FRACTION / v_ref;
                    *v_out = v_ref;
                    *t_out = t_ref;
                    *u_out = *uf;
                } else {
                    *rho_out = rho;
                    *v_out = v;
                    *t_out = t;
                }
            });
    }
}

impl GridCoupling for FluidFrame<'_> {
    fn before_forces(
        &mut self,
        nodes: &GridNodes,
        particles: &Particles,
        dt: f64,
    ) -> Result<(), SolverError> {
        self.project_particles_to_cells(nodes, particles);
        let s = &*self.s;
        self.ice.import_lagrangian(
            self.solid,
            &LagrangianCells {
                mass_density: &s.mass_density,
                velocity: &s.cell_velocity,
                specific_volume: None,
                temperature: &s.temperature,
            },
        )?;
        self.ice.compute_equilibration_pressure()?;
        self.ice.compute_face_centred_velocities(dt);
        self.ice.compute_pressure_increment(dt);
        self.ice.advanced_pressure(&mut self.s.pressure);
        Ok(())
    }

    fn pressure_at(&self, x: [f64; 3]) -> f64 {
        steps::interpolate_cell_field(&self.grid, &self.s.pressure, x)
    }

    fn after_forces(
        &mut self,
        nodes: &GridNodes,
        dt: f64,
        dv: &mut [[f64; 3]],
    ) -> Result<(), SolverError> {
        let g = &self.grid;
        let s = &mut *self.s;
        steps::nodes_to_cells(
            g,
            &nodes.lattice,
            &nodes.mass,
            &nodes.velocity_new,
            &mut s.cell_mass,
            &mut s.cell_velocity,
        );
        s.cell_velocity
            .par_iter_mut()
            .zip(s.trace.par_iter().zip(s.fluid_velocity.par_iter()))
            .with_min_len(1024)
            .for_each(|(u, (trace, uf))| {
                if *trace {
                    *u = *uf;
                }
            });
        self.ice
            .set_lagrangian_velocity(self.solid, &s.cell_velocity);
        self.ice.compute_lagrangian_values(dt)?;
        self.ice
            .lagrangian_increments(self.solid, &mut s.cell_change, &mut s.temperature_change);
        // A trace of the solid (no particle near: step 1) took momentum
        // from the fluids in steps 8–10 that no node receives (its nodal
        // mass M_c, often 0, is not the trace's): it goes back to the
        // cell's fluids, so the total momentum of both frames is kept.
        let volume: f64 = g.spacing.iter().product();
        s.trace_momentum
            .par_iter_mut()
            .zip(s.trace.par_iter())
            .zip(s.mass_density.par_iter().zip(s.cell_mass.par_iter()))
            .zip(s.cell_change.par_iter())
            .with_min_len(1024)
            .for_each(|(((dp, trace), (rho, m)), du)| {
                *dp = if *trace {
                    let excess = rho * volume - m;
                    du.map(|x| excess * x)
                } else {
                    [0.0; 3]
                };
            });
        self.ice.add_eulerian_momentum(&s.trace_momentum);
        steps::cells_to_nodes(g, &nodes.lattice, &s.cell_change, dv);
        Ok(())
    }

    fn temperature_change(&self, x: [f64; 3]) -> f64 {
        steps::cell_value_at(&self.grid, &self.s.temperature_change, x)
    }
}

/// The coupled ICE–MPM solver.
#[derive(Debug)]
pub struct IceMpm {
    ice: IceSolver<EosModel>,
    mpm: MpmSolver,
    solid: usize,
    reference_volume: f64,
    reference_temperature: f64,
    scratch: Scratch,
}

/// A checkpoint: both frames'.
#[derive(Serialize, Deserialize)]
struct SavedState {
    ice: Vec<u8>,
    mpm: Vec<u8>,
}

impl IceMpm {
    /// Couples `ice` (whose material `solid` is the particles' material on
    /// the fluid side: its EOS gives the solid's pressure in step 2, and
    /// it must not react) with `mpm` on the same grid. The solid's
    /// reference specific volume (of its trace) is the particles' initial
    /// V/m.
    pub fn new(
        mut ice: IceSolver<EosModel>,
        mpm: MpmSolver,
        solid: usize,
    ) -> Result<Self, IceMpmError> {
        let n = ice.material_count();
        if solid >= n {
            return Err(IceMpmError(format!(
                "solid material index {solid} is not one of the {n} ICE materials"
            )));
        }
        let (gi, gm) = (ice.level().geometry, mpm.level().geometry);
        if gi.cells != gm.cells || gi.origin != gm.origin || gi.spacing != gm.spacing {
            return Err(IceMpmError(
                "the ICE and MPM grids must be the same grid".into(),
            ));
        }
        if mpm.materials().len() != 1 {
            return Err(IceMpmError(format!(
                "{} particle materials given; the pipeline carries one Lagrangian material",
                mpm.materials().len()
            )));
        }
        let ps = mpm.particles();
        if ps.is_empty() {
            return Err(IceMpmError("the solid has no particles".into()));
        }
        let (m, v, mt) = (0..ps.len()).fold((0.0, 0.0, 0.0), |a, p| {
            (
                a.0 + ps.mass[p],
                a.1 + ps.initial_volume[p],
                a.2 + ps.mass[p] * ps.temperature[p],
            )
        });
        let mask: Vec<bool> = (0..n).map(|r| r == solid).collect();
        ice.set_lagrangian(&mask)
            .map_err(|e| IceMpmError(e.to_string()))?;
        let cells = gi.cell_count();
        let mut coupled = Self {
            ice,
            mpm,
            solid,
            reference_volume: v / m,
            reference_temperature: mt / m,
            scratch: Scratch::sized(cells),
        };
        coupled
            .fit_fluids_around_solid()
            .map_err(|e| IceMpmError(format!("initial state: {e}")))?;
        // The particles start in equilibrium with their cells' pressure
        // (their stress is the material's own; a solid in a 1 atm gas
        // carries −1 atm I).
        let mut p = vec![0.0; cells];
        coupled.ice.equilibration_pressure_field(&mut p);
        coupled
            .mpm
            .preload_pressure(|x| steps::cell_value_at(&gi, &p, x));
        Ok(coupled)
    }

    /// Before the first step: the solid's volume fraction as step 1 will
    /// see it (nodal mass by eq 12, cells by eq 18, the particles'
    /// specific volume), and the fluids fitted around it
    /// ([`IceSolver::fit_eulerian_volume`]), so that the first
    /// equilibration finds the materials' volumes summing to the cell's.
    fn fit_fluids_around_solid(&mut self) -> Result<(), SolverError> {
        let grid = self.mpm.level().geometry;
        let nodes = self.mpm.project_to_nodes()?.clone();
        let mut frame = FluidFrame {
            ice: &mut self.ice,
            solid: self.solid,
            grid,
            reference_volume: self.reference_volume,
            reference_temperature: self.reference_temperature,
            s: &mut self.scratch,
        };
        frame.project_particles_to_cells(&nodes, self.mpm.particles());
        let s = &self.scratch;
        let theta: Vec<f64> = (0..grid.cell_count())
            .map(|k| s.mass_density[k] * s.specific_volume[k])
            .collect();
        self.ice.fit_eulerian_volume(&theta, TRACE_FRACTION)
    }

    /// The fluid frame.
    pub fn ice(&self) -> &IceSolver<EosModel> {
        &self.ice
    }

    /// The particle frame.
    pub fn mpm(&self) -> &MpmSolver {
        &self.mpm
    }

    /// Index of the solid among the ICE materials.
    pub fn solid(&self) -> usize {
        self.solid
    }

    /// Mass, momentum and energy the coupled equilibration has given the
    /// fluids since the start (negative: taken), the term that closes the
    /// bookkeeping of [`Solver::conservation_totals`].
    pub fn rescaled_totals(&self) -> ConservationTotals {
        self.ice.rescaled_totals()
    }

    /// Particles advanced per step (the second throughput unit).
    pub fn particles_per_step(&self) -> usize {
        self.mpm.particles().len()
    }
}

impl Solver for IceMpm {
    fn name(&self) -> &str {
        "ice_mpm"
    }

    fn time(&self) -> f64 {
        self.mpm.time()
    }

    /// The smaller of the fluid frame's CFL step and the particles'.
    fn stable_dt(&self) -> Result<f64, SolverError> {
        Ok(self.ice.stable_dt()?.min(self.mpm.stable_dt()?))
    }

    fn advance(&mut self, dt: f64) -> Result<(), SolverError> {
        let _span = tracing::trace_span!("ice_mpm_step", dt).entered();
        let mut frame = FluidFrame {
            ice: &mut self.ice,
            solid: self.solid,
            grid: self.mpm.level().geometry,
            reference_volume: self.reference_volume,
            reference_temperature: self.reference_temperature,
            s: &mut self.scratch,
        };
        // Steps 1–11, 13 and 14 (the module doc's table).
        self.mpm.advance_coupled(dt, &mut frame)?;
        // Step 12.
        self.ice.advect_fluids(dt)?;
        self.ice.finish_coupled_step(dt);
        Ok(())
    }

    /// The fluids' totals (ICE, the solid's trace left out) plus the
    /// particles' (with what left through outflow faces), less what the
    /// coupled equilibration gave the fluids
    /// ([`IceSolver::rescaled_totals`]): a closed bookkeeping, whose
    /// rescale term [`IceMpm::rescaled_totals`] reports apart.
    fn conservation_totals(&self) -> ConservationTotals {
        let (a, b, r) = (
            self.ice.conservation_totals(),
            self.mpm.conservation_totals(),
            self.ice.rescaled_totals(),
        );
        ConservationTotals {
            mass: a.mass + b.mass - r.mass,
            momentum: std::array::from_fn(|d| a.momentum[d] + b.momentum[d] - r.momentum[d]),
            energy: a.energy + b.energy - r.energy,
        }
    }

    fn cell_field_names(&self) -> Vec<&'static str> {
        self.ice.cell_field_names()
    }

    fn cell_data(&self, fields: &[String]) -> Result<CellData, SolverError> {
        self.ice.cell_data(fields)
    }

    fn sample(
        &self,
        point: [f64; 3],
        fields: &[String],
        out: &mut Vec<f64>,
    ) -> Result<(), SolverError> {
        self.ice.sample(point, fields, out)
    }

    fn particle_data(&self) -> Option<ParticleData> {
        self.mpm.particle_data()
    }

    fn node_field_names(&self) -> Vec<&'static str> {
        self.mpm.node_field_names()
    }

    fn node_data(&self, fields: &[String]) -> Result<Option<NodeData>, SolverError> {
        self.mpm.node_data(fields)
    }

    fn external_work(&self) -> Option<f64> {
        self.mpm.external_work()
    }

    fn work_per_step(&self) -> (f64, &'static str) {
        self.ice.work_per_step()
    }

    fn save_state(&self) -> Result<Vec<u8>, SolverError> {
        let saved = SavedState {
            ice: self.ice.save_state()?,
            mpm: self.mpm.save_state()?,
        };
        bincode::serialize(&saved).map_err(|e| SolverError::Checkpoint(e.to_string()))
    }

    fn restore_state(&mut self, bytes: &[u8]) -> Result<(), SolverError> {
        let saved: SavedState =
            bincode::deserialize(bytes).map_err(|e| SolverError::Checkpoint(e.to_string()))?;
        self.ice.restore_state(&saved.ice)?;
        self.mpm.restore_state(&saved.mpm)
    }
}

#[cfg(test)]
mod tests;

#[cfg(test)]
mod determinism_tests {
    use super::cases::{build, Setup};
    use brisance_core::Solver;
    use brisance_ice::IceBoundary;
    use brisance_mpm::GridBoundary;

    /// Three coupled steps of a steel cube moving through air (16³ cells,
    /// 1728 particles: the parallel loops split into several chunks)
    /// leave both frames' state with the same bits on 1 and 2 threads.
    #[test]
    fn the_coupled_step_gives_the_same_bits_on_one_and_two_threads() {
        let run = |threads: usize| {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            pool.install(|| {
                let h = 1e-3;
                let mut s = build(&Setup {
                    lower: [0.0; 3],
                    upper: [16.0 * h; 3],
                    cells: [16; 3],
                    solids: vec![([4.0 * h; 3], [10.0 * h; 3])],
                    solid_velocity: [50.0, 0.0, 0.0],
                    gas_velocity: [0.0; 3],
                    ice_faces: std::array::from_fn(|_| IceBoundary::Outflow),
                    mpm_faces: [GridBoundary::Free; 6],
                });
                for _ in 0..3 {
                    let dt = s.stable_dt().unwrap();
                    s.advance(dt).unwrap();
                }
                s.save_state().unwrap()
            })
        };
        let (one, two) = (run(1), run(2));
        assert!(!one.is_empty());
        assert!(one == two, "the state differs between 1 and 2 threads");
    }
}
