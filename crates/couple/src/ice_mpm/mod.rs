//! The ICE–MPM pipeline of seed 000 §3.3: Eulerian fluids (ICE) and
//! Lagrangian solids (MPM particles) on one grid, sharing one equilibration
//! pressure and exchanging momentum and heat in every cell.
//!
//! One [`Solver::advance`] is the seed's step list, in `IceMpm::step`:
//!
//! | step | where |
//! |---|---|
//! | 1 particles → nodes (eq 12) → cells (eq 18) | [`CoupledStep::project`], [`steps::project_to_cells`] |
//! | 2 equilibration pressure, θ as shares of the materials' volume | [`IceSolver::compute_equilibration_pressure`] |
//! | 3 face velocities with face exchange (eq 19) | [`IceSolver::compute_face_centred_velocities`] |
//! | 4 reactions: fluid reactants | inside [`IceSolver::compute_lagrangian_values`] |
//! | 4 reactions: solid reactants | [`IceSolver::lagrangian_burn_fraction`] after step 2; the particles' loss after step 14 ([`CoupledStep::consume_particles`]), given to the product by [`IceSolver::add_burnt_particles`] |
//! | 5 Δp (eqs 20–21) | [`IceSolver::compute_pressure_increment`] |
//! | 6 face pressure (eq 22) | inside [`IceSolver::compute_lagrangian_values`] |
//! | 7 particle stresses (eq 13); internal force from σ + p I (eq 14) | [`CoupledStep::internal_forces`]; the stresses with step 14 |
//! | 8–11 cell sources, Lagrangian values, exchange, specific volume | [`IceSolver::compute_lagrangian_values`] |
//! | 12 advect fluids | [`IceSolver::advect_fluids`] |
//! | 13 cell changes → nodes | [`steps::cells_to_nodes`], [`CoupledStep::add_node_velocity_change`] |
//! | 14 particles updated (eqs 16–17) | [`CoupledStep::update_particles`] |
//!
//! Each solid (particle material) is one ICE material flagged Lagrangian
//! ([`IceSolver::set_lagrangian`]) whose state in each cell is imported
//! from its particles before the equilibration; several solids share the
//! nodes' one velocity field. Where none of a solid's particles is near,
//! it is a trace of volume fraction [`TRACE_FRACTION`] at its reference
//! density and temperature (its particles' initial means) moving with what
//! the cell holds, so that the momentum exchange moves nothing there.
//! Choices the seed leaves open are in `docs/physics/couple/ice_mpm.md`.

pub mod burn_rate;
pub mod cases;
mod frame;
pub mod pipeline;
pub mod steps;
pub mod tubes;

use frame::FluidFrame;

use brisance_core::{
    CellData, ConservationTotals, NodeData, ParticleData, Solver, SolverError, UniformGridGeometry,
};
use brisance_eos::EosModel;
use brisance_ice::{BurntMass, IceSolver, LagrangianCells, LagrangianSpecificHeat};
#[cfg(doc)]
use brisance_mpm::CoupledStep;
use brisance_mpm::{GridNodes, MaterialId, MpmSolver, Particles};
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

/// Volume fraction of the solid in cells where no particle is.
pub const TRACE_FRACTION: f64 = 1e-6;

/// A burning particle whose mass falls below this fraction of its
/// material's mean initial particle mass burns whole and is removed.
///
/// One per cent, ten times the nodes' mass cut-off of the MPM step
/// (`MpmOptions::mass_cutoff`, 10⁻³ of the mean particle mass): a sliver
/// of a particle left on nodes near that cut-off took accelerations its
/// mass could not carry. In the 2 mm cook-off (configs/cookoff_rz.ron) a
/// reactant particle burnt down to 1.2 % reached 10⁵–10⁶ m/s and
/// 10¹³–10¹⁵ J/kg within a few steps, its burnt mass carried that energy
/// into the products (10⁶ K, 185 GPa) and the run stopped at 28.6 µs;
/// with the floor at 10⁻² it runs to 186 µs with the total energy within
/// 0.25 % (docs/physics/couple/cookoff.md). The floor burns at most one
/// per cent of a particle one step early; mass, momentum and energy go to
/// the product as for any burnt mass.
pub const BURNT_OUT_FRACTION: f64 = 1e-2;

/// Why an [`IceMpm`] cannot be built.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("ICE–MPM: {0}")]
pub struct IceMpmError(pub String);

/// How the temperature change that steps 8–11 give a solid in each cell
/// (its heat exchange with the fluids; with `conserve_total_energy: false`
/// also its share of the kinetic energy the exchanges dissipate) reaches
/// the particles in step 14 (docs/physics/couple/ice_mpm.md, "Heat between
/// the frames"). Without heat exchange (H = 0) and with the total energy
/// conserved (the defaults) that change is zero in every cell and both
/// give the same bits.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
pub enum ParticleHeat {
    /// Through the nodes (the default), as the velocity change of step 13
    /// (Uintah's `interpolateCCToNC` of dT/dt and the particles' gather of
    /// it): ΔT_I = Σ_c w_Ic ΔT_c with the weights of eq 18, then
    /// ΔT_p = Σ_I N_Ip ΔT_I, so Σ_p m_p c ΔT_p = Σ_c M_c c ΔT_c for one
    /// solid of constant c_v (exact with linear shape functions and
    /// several solids too); for a solid whose particles carry a specific
    /// heat the value sent is the heat q_c (J/kg), and Σ_p m_p q_p =
    /// Σ_c M_c q_c whatever its c(T). A solid's trace gives the nodes
    /// nothing.
    #[default]
    Nodes,
    /// Each particle takes the change of the cell it lies in (the rule
    /// before `Nodes`). Not conservative: the solid's cell mass of eq 18
    /// and the particles that hold it need not lie in the same cell (a
    /// cell beside the solid's face holds a share of it through the face's
    /// nodes and no particle), so the heat the fluids exchange with the
    /// solid there is not taken from any particle.
    Cell,
}

/// One Lagrangian material's cell fields of a coupled step.
#[derive(Debug, Clone, Default)]
struct SolidCells {
    /// Its share M_c,s of the cell mass of eq 18, kg.
    mass: Vec<f64>,
    state: Vec<Option<(f64, f64)>>,
    mass_density: Vec<f64>,
    specific_volume: Vec<f64>,
    temperature: Vec<f64>,
    velocity: Vec<[f64; 3]>,
    trace: Vec<bool>,
    change: Vec<[f64; 3]>,
    /// The heat exchange's change of the solid in each cell: a temperature
    /// change (K), or the heat (J/kg) for a solid whose particles carry a
    /// specific heat ([`Solid::carries_heat`]).
    temperature_change: Vec<f64>,
}

impl SolidCells {
    fn sized(cells: usize) -> Self {
        Self {
            mass: vec![0.0; cells],
            state: vec![None; cells],
            mass_density: vec![0.0; cells],
            specific_volume: vec![0.0; cells],
            temperature: vec![0.0; cells],
            velocity: vec![[0.0; 3]; cells],
            trace: vec![false; cells],
            change: vec![[0.0; 3]; cells],
            temperature_change: vec![0.0; cells],
        }
    }
}

/// A Lagrangian material: particle material k is ICE material `ice`.
#[derive(Debug, Clone, Copy)]
struct Solid {
    ice: usize,
    /// The trace's specific volume and temperature (the particles' initial
    /// means).
    reference_volume: f64,
    reference_temperature: f64,
    /// Mean initial particle mass, kg (the burnt-out threshold's scale).
    particle_mass: f64,
    /// Whether its particles carry a specific heat: the heat exchange then
    /// weighs it with theirs and hands them a heat (J/kg), not a
    /// temperature change ([`IceSolver::set_lagrangian_specific_heat`]).
    carries_heat: bool,
}

/// A reaction whose reactant particles carry (seed 000 step 4 on the
/// particles).
#[derive(Debug, Clone)]
struct ParticleBurn {
    /// Index among the ICE reactions.
    reaction: usize,
    /// The reactant's particle material.
    material: MaterialId,
    /// The product (ICE material).
    product: usize,
    /// Heat of reaction, J/kg.
    heat: f64,
    /// Reactant mass not burnt since the start (left through outflow faces
    /// included), kg: its chemical energy is in the totals.
    unburnt: f64,
    /// Per cell, the fraction of the reactant's mass burning this step.
    fraction: Vec<f64>,
    /// Per cell, the reactant's specific volume of step 2, m³/kg.
    specific_volume: Vec<f64>,
    /// Per cell, what the particles lost this step.
    burnt: Vec<BurntMass>,
}

/// The per-cell and per-node arrays of a coupled step.
#[derive(Debug, Clone, Default)]
struct Scratch {
    /// M_c of all particles (eq 18), kg.
    cell_mass: Vec<f64>,
    /// The particles' cell velocity u_c (eq 18), one field for all.
    cell_velocity: Vec<[f64; 3]>,
    node_sums: Vec<[f64; 3]>,
    fluid_velocity: Vec<[f64; 3]>,
    /// The fluids' mass density (with several solids only), kg/m³.
    fluid_density: Vec<f64>,
    pressure: Vec<f64>,
    /// Per cell, the velocity change the nodes receive (step 13): the
    /// solids' mass-weighted mean (several solids only; one solid's own
    /// change is read in place).
    cell_change: Vec<[f64; 3]>,
    /// Per cell, the momentum a trace of a solid took in steps 8–10
    /// beyond what its nodes receive, returned to the fluids (with several
    /// solids, shared with the solids present: `share_trace_momentum`).
    trace_momentum: Vec<[f64; 3]>,
    /// Per cell, the mass Σ |ρ_s V − M_c,s| of the solids' traces whose
    /// momentum `trace_momentum` holds, kg.
    trace_excess: Vec<f64>,
    /// The fluids' Lagrangian mass density, kg/m³.
    fluid_mass: Vec<f64>,
    solids: Vec<SolidCells>,
    /// The outer vectors step 1 lends the solids' arrays through (several
    /// solids only).
    mass_buffers: Vec<Vec<f64>>,
    state_buffers: Vec<Vec<Option<(f64, f64)>>>,
    /// Per solid, the temperature change of steps 8–11 on the nodes
    /// ([`ParticleHeat::Nodes`] only; material-major blocks).
    node_temperature: Vec<f64>,
}

impl Scratch {
    fn sized(cells: usize, solids: usize) -> Self {
        Self {
            cell_mass: vec![0.0; cells],
            cell_velocity: vec![[0.0; 3]; cells],
            node_sums: Vec::new(),
            fluid_velocity: vec![[0.0; 3]; cells],
            fluid_density: if solids > 1 {
                vec![0.0; cells]
            } else {
                Vec::new()
            },
            pressure: vec![0.0; cells],
            cell_change: if solids > 1 {
                vec![[0.0; 3]; cells]
            } else {
                Vec::new()
            },
            trace_momentum: vec![[0.0; 3]; cells],
            trace_excess: vec![0.0; cells],
            fluid_mass: vec![0.0; cells],
            solids: (0..solids).map(|_| SolidCells::sized(cells)).collect(),
            mass_buffers: Vec::with_capacity(solids),
            state_buffers: Vec::with_capacity(solids),
            node_temperature: Vec::new(),
        }
    }
}

/// The coupled ICE–MPM solver.
#[derive(Debug)]
pub struct IceMpm {
    ice: IceSolver<EosModel>,
    mpm: MpmSolver,
    solids: Vec<Solid>,
    burns: Vec<ParticleBurn>,
    scratch: Scratch,
    /// Whether the shared grid is (r, z) rings.
    rz: bool,
    /// Each cell's volume, m³ (global order).
    volumes: Vec<f64>,
    /// How steps 8–11's temperature change reaches the particles.
    particle_heat: ParticleHeat,
    /// This process's rank ([`IceMpm::distribute`]; 0 on one rank): every
    /// rank holds the whole fluid, and rank 0 alone hands out its patch
    /// pieces for output.
    rank: usize,
}

/// A checkpoint: both frames', and the reactant mass not burnt yet.
#[derive(Serialize, Deserialize)]
struct SavedState {
    ice: Vec<u8>,
    mpm: Vec<u8>,
    unburnt: Vec<f64>,
}

impl IceMpm {
    /// Sets how steps 8–11's temperature change reaches the particles
    /// (config `pipeline.particle_heat`; [`ParticleHeat::Nodes`] unless set).
    pub fn set_particle_heat(&mut self, heat: ParticleHeat) {
        self.particle_heat = heat;
    }

    /// How steps 8–11's temperature change reaches the particles.
    pub fn particle_heat(&self) -> ParticleHeat {
        self.particle_heat
    }

    /// Spreads the coupled step over the ranks of `comm` (nothing to do on
    /// one rank; docs/cluster.md): every rank holds the whole fluid and
    /// every particle and runs every phase over all of them, except the
    /// particles' fused G2P and stress update of step 14, which each rank
    /// runs for its run of particles ([`MpmSolver::distribute`]). The
    /// fluid's patches are not split: the cell passes of the step read the
    /// particles' projection over the whole grid. Every rank builds the
    /// same solver and calls this before the first step.
    pub fn distribute(&mut self, comm: std::sync::Arc<dyn brisance_grid::comm::Communicator>) {
        self.rank = comm.rank();
        self.mpm.distribute(comm);
    }

    /// One time step: seed 000 §3.3's step list in its order (the module
    /// doc's table). The particle phases are [`brisance_mpm::CoupledStep`]'s,
    /// the cell steps [`IceSolver`]'s, and what joins them (eq 18 and its
    /// adjoint, the solids' cell states, the burning particles) the fluid
    /// frame's.
    fn step(&mut self, dt: f64) -> Result<(), SolverError> {
        let particle_heat = self.particle_heat;
        let (mut frame, mpm) = self.frames();
        let mut mpm = mpm.begin_coupled_step(dt)?;
        // 1. Particles → nodes (eq 12) → cells (eq 18): each solid's state
        //    in every cell.
        mpm.project();
        frame.import_solids(mpm.nodes(), mpm.particles())?;
        // 2. The equilibration pressure, θ as shares of the materials'
        //    volume.
        frame.ice.compute_equilibration_pressure()?;
        // 4. Solid reactants: the fraction of the particles' reactant each
        //    cell burns this step (its mass leaves them after step 14).
        frame.burn_fractions(dt);
        // 3. Face-centred velocities with the face exchange (eq 19).
        frame.ice.compute_face_centred_velocities(dt);
        // 5. The pressure increment (eqs 20–21) and the advanced pressure.
        frame.ice.compute_pressure_increment(dt);
        frame.take_advanced_pressure();
        // 7. The internal force from σ_p + p I (eq 14), the nodes' v*_I.
        mpm.internal_forces(|x| frame.pressure_at(x));
        // 6, 8–11. Face pressure (eq 22), cell sources, Lagrangian values,
        //    momentum and heat exchange, specific volume (fluid reactants'
        //    step 4 inside).
        frame.lagrangian_values(mpm.nodes(), dt)?;
        // 13. The cells' changes to the nodes.
        mpm.add_node_velocity_change(|nodes, dv| {
            frame.changes_to_nodes(nodes, dv);
            Ok(())
        })?;
        // 14. The particles from the nodes (eqs 16–17) with their stress
        //     (eq 13, step 7) and the heat exchange's temperature change.
        match particle_heat {
            ParticleHeat::Nodes => {
                let change = frame.temperature_change_to_nodes(mpm.nodes());
                mpm.update_particles_from_nodes(change)?;
            }
            ParticleHeat::Cell => mpm.update_particles(|x, m| frame.temperature_change(x, m))?,
        }
        // 4. Solid reactants: the burnt mass leaves the particles for the
        //    product.
        mpm.consume_particles(|particles, consumed| frame.consume_particles(particles, consumed))?;
        mpm.finish()?;
        // 12. Advection of the fluids.
        self.ice.advect_fluids(dt)?;
        self.ice.finish_coupled_step(dt);
        Ok(())
    }

    /// Couples `ice` with `mpm` on the same grid; particle material k is
    /// ICE material `solids[k]` (its EOS gives that solid's pressure in
    /// step 2). Several particle materials share the nodes' one velocity
    /// field (Uintah's single-velocity contact) and are separate materials
    /// on the fluid side. A solid may be the reactant of an ICE reaction
    /// (its particles burn into the Eulerian product), never the product.
    /// A solid's trace state is its particles' initial mean V/m and
    /// temperature.
    pub fn new(
        mut ice: IceSolver<EosModel>,
        mut mpm: MpmSolver,
        solids: &[usize],
    ) -> Result<Self, IceMpmError> {
        let n = ice.material_count();
        if let Some(&r) = solids.iter().find(|&&r| r >= n) {
            return Err(IceMpmError(format!(
                "solid material index {r} is not one of the {n} ICE materials"
            )));
        }
        if (1..solids.len()).any(|k| solids[..k].contains(&solids[k])) {
            return Err(IceMpmError(format!(
                "solid material indices {solids:?} name an ICE material twice"
            )));
        }
        let (gi, gm) = (ice.level().geometry, mpm.level().geometry);
        if gi.cells != gm.cells || gi.origin != gm.origin || gi.spacing != gm.spacing {
            return Err(IceMpmError(
                "the ICE and MPM grids must be the same grid".into(),
            ));
        }
        if mpm.materials().len() != solids.len() || solids.is_empty() {
            return Err(IceMpmError(format!(
                "{} particle materials given for {} Lagrangian ICE materials",
                mpm.materials().len(),
                solids.len()
            )));
        }
        let ps = mpm.particles();
        let mut sums = vec![(0.0, 0.0, 0.0, 0usize); solids.len()];
        for p in 0..ps.len() {
            let a = &mut sums[ps.material[p].0 as usize];
            a.0 += ps.mass[p];
            a.1 += ps.initial_volume[p];
            a.2 += ps.mass[p] * ps.temperature[p];
            a.3 += 1;
        }
        if let Some(k) = sums.iter().position(|a| a.3 == 0) {
            return Err(IceMpmError(format!(
                "the solid {} (ICE material {}) has no particles",
                k,
                solids[k] + 1
            )));
        }
        let mut solid_list: Vec<Solid> = solids
            .iter()
            .zip(&sums)
            .map(|(&r, &(m, v, mt, count))| Solid {
                ice: r,
                reference_volume: v / m,
                reference_temperature: mt / m,
                particle_mass: m / count as f64,
                carries_heat: false,
            })
            .collect();
        let mut mask = vec![false; n];
        for &r in solids {
            mask[r] = true;
        }
        ice.set_lagrangian(&mask)
            .map_err(|e| IceMpmError(e.to_string()))?;
        // A solid whose particles carry a specific heat (their conduction's
        // or their model's) exchanges heat with it, and its particles take
        // the heat through it (docs/physics/couple/ice_mpm.md, "Heat
        // between the frames").
        let laws: Vec<_> = (0..solids.len())
            .map(|k| mpm.specific_heat(MaterialId(k as u16)))
            .collect();
        for ((law, solid), &r) in laws.iter().zip(&mut solid_list).zip(solids) {
            if let Some(c) = law.clone() {
                ice.set_lagrangian_specific_heat(
                    r,
                    LagrangianSpecificHeat(std::sync::Arc::new(move |t| c.smoothed_at(t))),
                )
                .map_err(|e| IceMpmError(e.to_string()))?;
                solid.carries_heat = true;
            }
        }
        mpm.set_coupled_heat(laws);
        let cells = gi.cell_count();
        let burns = ice
            .reactions()
            .iter()
            .enumerate()
            .filter_map(|(k, rx)| {
                let s = solids.iter().position(|&r| r == rx.reactant)?;
                Some(ParticleBurn {
                    reaction: k,
                    material: MaterialId(s as u16),
                    product: rx.product,
                    heat: rx.heat_of_reaction,
                    unburnt: sums[s].0,
                    fraction: vec![0.0; cells],
                    specific_volume: vec![0.0; cells],
                    burnt: vec![BurntMass::default(); cells],
                })
            })
            .collect();
        let geometry = ice.options().geometry;
        if mpm.options().geometry != geometry {
            return Err(IceMpmError(format!(
                "the ICE grid is {} and the MPM grid {}: they must be the same",
                geometry.name(),
                mpm.options().geometry.name()
            )));
        }
        let volumes = (0..cells)
            .map(|k| geometry.column_cell_volume(&gi, k % gi.cells[0]))
            .collect();
        let mut coupled = Self {
            ice,
            mpm,
            solids: solid_list,
            burns,
            scratch: Scratch::sized(cells, solids.len()),
            rz: geometry.is_axisymmetric(),
            volumes,
            particle_heat: ParticleHeat::Nodes,
            rank: 0,
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

    /// The fluid frame and the particle solver, borrowed side by side.
    fn frames(&mut self) -> (FluidFrame<'_>, &mut MpmSolver) {
        (
            FluidFrame {
                ice: &mut self.ice,
                solids: &self.solids,
                burns: &mut self.burns,
                grid: self.mpm.level().geometry,
                rz: self.rz,
                volumes: &self.volumes,
                s: &mut self.scratch,
            },
            &mut self.mpm,
        )
    }

    /// Before the first step: the solids' volume fraction as step 1 will
    /// see it (nodal mass by eq 12, cells by eq 18, the particles'
    /// specific volume), and the fluids fitted around it
    /// ([`IceSolver::fit_eulerian_volume`]), so that the first
    /// equilibration finds the materials' volumes summing to the cell's.
    fn fit_fluids_around_solid(&mut self) -> Result<(), SolverError> {
        let (mut frame, mpm) = self.frames();
        let grid = frame.grid;
        let nodes = mpm.project_to_nodes()?.clone();
        if frame.ice.start_temperatures_on_particles() {
            // A solid that starts at a temperature its cells' (ρ, p) do
            // not carry (a Murnaghan solid away from its t_ref): its cells
            // take the particles' state before the fit, so that the fluid
            // traces held at its temperature and the first output see the
            // particles' (step 1 does the same every step).
            frame.import_solids(&nodes, mpm.particles())?;
        } else {
            frame.project_particles_to_cells(&nodes, mpm.particles());
        }
        let s = &self.scratch;
        let theta: Vec<f64> = (0..grid.cell_count())
            .map(|k| {
                s.solids
                    .iter()
                    .map(|c| c.mass_density[k] * c.specific_volume[k])
                    .sum()
            })
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

    /// Index among the ICE materials of particle material k.
    pub fn solids(&self) -> Vec<usize> {
        self.solids.iter().map(|s| s.ice).collect()
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

    /// Per reaction whose reactant particles carry: the reactant mass not
    /// burnt since the start (what left through outflow faces included),
    /// kg.
    pub fn unburnt_reactant(&self) -> Vec<f64> {
        self.burns.iter().map(|b| b.unburnt).collect()
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

    /// The fluids' outflow faces that have held back an inflow.
    fn blocked_inflow(&self) -> [bool; 6] {
        self.ice.blocked_inflow()
    }

    /// The fluids' limit or the particles', whichever gives the smaller
    /// step (the one whose step fails, if one does).
    fn time_step_limit(&self) -> Option<String> {
        match (self.ice.stable_dt(), self.mpm.stable_dt()) {
            (Err(_), _) => self.ice.time_step_limit(),
            (_, Err(_)) => self.mpm.time_step_limit(),
            (Ok(i), Ok(m)) if m < i => self.mpm.time_step_limit(),
            _ => self.ice.time_step_limit(),
        }
    }

    fn advance(&mut self, dt: f64) -> Result<(), SolverError> {
        let _span = tracing::trace_span!("ice_mpm_step", dt).entered();
        // The whole step runs as one task of the thread pool, so that each
        // of its parallel loops starts on a worker instead of being handed
        // over from this thread and waited for.
        rayon::scope(|_| self.step(dt))
    }

    /// The fluids' totals (ICE, the solids' traces left out) plus the
    /// particles' (with what left through outflow faces) and the chemical
    /// energy of the reactant particles not burnt yet, less what the
    /// coupled equilibration gave the fluids
    /// ([`IceSolver::rescaled_totals`]): a closed bookkeeping, whose
    /// rescale term [`IceMpm::rescaled_totals`] reports apart.
    fn conservation_totals(&self) -> ConservationTotals {
        let (a, b, r) = (
            self.ice.conservation_totals(),
            self.mpm.conservation_totals(),
            self.ice.rescaled_totals(),
        );
        let chemical: f64 = self.burns.iter().map(|x| x.unburnt * x.heat).sum();
        ConservationTotals {
            mass: a.mass + b.mass - r.mass,
            momentum: std::array::from_fn(|d| a.momentum[d] + b.momentum[d] - r.momentum[d]),
            energy: a.energy + b.energy + chemical - r.energy,
        }
    }

    fn cell_field_names(&self) -> Vec<&'static str> {
        self.ice.cell_field_names()
    }

    fn cell_data(&self, fields: &[String]) -> Result<CellData, SolverError> {
        self.ice.cell_data(fields)
    }

    /// The fluid's patch pieces: all of them on rank 0, none on the
    /// others (each holds the same whole fluid: [`IceMpm::distribute`]).
    fn cell_pieces(
        &self,
        fields: &[String],
    ) -> Result<Option<brisance_core::CellPieces>, SolverError> {
        let mut pieces = self.ice.cell_pieces(fields)?;
        if self.rank != 0 {
            if let Some(p) = &mut pieces {
                p.pieces.clear();
            }
        }
        Ok(pieces)
    }

    fn sample(
        &self,
        point: [f64; 3],
        fields: &[String],
        out: &mut Vec<f64>,
    ) -> Result<(), SolverError> {
        self.ice.sample(point, fields, out)
    }

    /// The MPM side's particle gauges.
    fn sample_particle_gauge(
        &self,
        k: usize,
        quantities: &[brisance_core::SetQuantity],
        out: &mut Vec<f64>,
    ) -> bool {
        self.mpm().sample_particle_gauge(k, quantities, out)
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
            unburnt: self.unburnt_reactant(),
        };
        bincode::serialize(&saved).map_err(|e| SolverError::Checkpoint(e.to_string()))
    }

    fn restore_state(&mut self, bytes: &[u8]) -> Result<(), SolverError> {
        let saved: SavedState = bincode::deserialize(bytes).map_err(|e| {
            SolverError::Checkpoint(format!(
                "not an ICE–MPM checkpoint of this version (one written before the pipeline \
                 carried the unburnt reactant of burning particles cannot be read): {e}"
            ))
        })?;
        if saved.unburnt.len() != self.burns.len() {
            return Err(SolverError::Checkpoint(format!(
                "the checkpoint holds {} burning reactants, the run {}",
                saved.unburnt.len(),
                self.burns.len()
            )));
        }
        self.ice.restore_state(&saved.ice)?;
        self.mpm.restore_state(&saved.mpm)?;
        for (b, u) in self.burns.iter_mut().zip(saved.unburnt) {
            b.unburnt = u;
        }
        Ok(())
    }
}

#[cfg(test)]
mod solids_tests;
#[cfg(test)]
mod tests;

/// `f` run on a pool of `threads` threads: the determinism tests' runs on
/// 1 and 2 threads.
#[cfg(test)]
fn in_pool<T: Send>(threads: usize, f: impl FnOnce() -> T + Send) -> T {
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap()
        .install(f)
}

#[cfg(test)]
mod determinism_tests;
