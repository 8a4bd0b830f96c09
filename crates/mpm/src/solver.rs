//! [`MpmSolver`]: the explicit MPM of seed 001 §2.2 behind the core
//! [`Solver`] trait.
//!
//! One [`Solver::advance`]:
//!
//! 1. with reservoirs beyond open faces ([`crate::inflow`]), the layers
//!    that enter join the particles, booked as negative outflow;
//! 2. every [`RESORT_INTERVAL`] steps, sort the particles by cell (stable
//!    counting sort; skipped when they are still sorted); every step, bin
//!    them by block for the transfers ([`crate::transfer::ParticleBins`]);
//!    the reservoir particles' node shares and forces are formed;
//! 3. with heat conduction on ([`MpmSolver::with_heat_conduction`]), the
//!    conduction step of [`crate::conduction`] on the temperatures;
//!    then the step of the chosen [`UpdateScheme`] ([`crate::step`]) with the
//!    deterministic coloured-scatter P2G of [`crate::transfer`], G2P and the
//!    stress update in one visit of each particle;
//! 4. particles that crossed an [`GridBoundary::Outflow`] face are removed
//!    and booked; those that crossed a `Symmetry` or `Fixed` face by at
//!    most [`crate::boundary::MIRROR_DEPTH`] cells are mirrored back; a
//!    particle that crossed any other face, or deeper, stops the run;
//!    fixed reservoirs move on.
//!
//! The step runs as one task of the rayon pool; see
//! `docs/physics/mpm/kernels.md` for the loop structure, memory and
//! throughput.
//!
//! # Conservation bookkeeping
//!
//! [`Solver::conservation_totals`] sums, in particle order, mass Σ m_p,
//! momentum Σ m_p v_p and energy Σ m_p (e_p + |v_p|²/2), and adds the
//! *outflow* totals: the same quantities of every particle removed through
//! an outflow face, accumulated when it left, less those of every particle
//! a reservoir brought in. The totals thus stay constant when matter
//! leaves or enters the domain; [`MpmSolver::outflow_totals`] gives the
//! outflow part alone.
//!
//! The prescribed external forces — surface tractions (seed 001 eq 20) and
//! the body force m_I g (eq 23) — add energy; their work is accumulated
//! step by step at the nodes ([`GridNodes::external_work`]:
//! Δt Σ_I f_I^ext · (v_I^n + v_I^{n+1})/2) and reported by
//! [`Solver::external_work`], so that E(t) − W_ext(t) is the quantity the
//! method keeps (up to the dissipation of the scheme itself). Particles
//! carry no potential energy: the work of gravity is in W_ext, not in E.
//!
//! # Node fields
//!
//! [`Solver::node_data`] hands out the background grid's node fields as the
//! last step left them ([`MpmSolver::NODE_FIELDS`]), on the whole node lattice
//! including the ghost layers of the wider shape functions; before the
//! first step, the P2G of the initial particles' mass and momentum.
//!
//! # Cell fields
//!
//! Cell values are mass-weighted averages over the particles whose position
//! lies in the cell: for a particle quantity q, q_cell = Σ m_p q_p / Σ m_p
//! (density ρ_p = m_p/V_p, velocity components, the material's pressure
//! −tr σ_p/3 − q_p without the bulk viscosity q_p, specific internal
//! energy), and zero in a cell without particles.
//! `mass_density` is Σ m_p / V_cell, the particle mass smeared over the cell.
//!
//! [`Solver`]: brisance_core::Solver
//! [`Solver::advance`]: brisance_core::Solver::advance
//! [`Solver::conservation_totals`]: brisance_core::Solver::conservation_totals
//! [`Solver::external_work`]: brisance_core::Solver::external_work
//! [`Solver::node_data`]: brisance_core::Solver::node_data

use crate::anti_locking::{AntiLocking, PatchAverage};
use crate::boundary::GridBoundary;
use crate::conduction::{HeatConduction, HeatWork, ThermalProperties};
use crate::grid_nodes::GridNodes;
use crate::inflow::{Reservoir, Reservoirs};
use crate::step::{self, G2pParts, NodeVelocity, StepParams, UpdateScheme};
use crate::traction::{self, SurfaceLoad};
use crate::transfer::{BinError, GridMap, P2gSums, ParticleBins};
use crate::viscosity::{viscosity_length, BulkViscosity, BulkViscosityState, ViscosityParams};
use crate::{MaterialId, Particles, ShapeFunction};
use brisance_constitutive::MaterialModel;
use brisance_core::Geometry;
use brisance_core::{ConservationTotals, Material, SolverError};
use brisance_grid::Level;
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

/// Options of the explicit MPM solver.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct MpmOptions {
    /// Shape function.
    pub shape: ShapeFunction,
    /// Update scheme.
    pub scheme: UpdateScheme,
    /// Courant number of Δt = cfl·min Δx / max(c + |v|), in (0, 1].
    pub cfl: f64,
    /// Body force per unit mass, m/s².
    pub gravity: [f64; 3],
    /// Face conditions x−, x+, y−, y+, z−, z+.
    pub boundaries: [GridBoundary; 6],
    /// Nodes whose mass is below `mass_cutoff` × the mean particle mass at
    /// construction get zero velocity and acceleration (≥ 0).
    pub mass_cutoff: f64,
    /// Smallest acceptable time step, s.
    pub min_dt: f64,
    /// Artificial bulk viscosity of the particles ([`crate::viscosity`]);
    /// `None` (the default) adds none.
    pub bulk_viscosity: Option<BulkViscosity>,
    /// The bulk viscosity of the particles of `Null` fluids (gases), in
    /// place of `bulk_viscosity` for them; `None` (the default): theirs is
    /// `bulk_viscosity`. A gas shock needs a linear term of order one,
    /// which would damp a solid's elastic waves (docs/physics/mpm/bulk_viscosity.md).
    #[serde(default)]
    pub fluid_bulk_viscosity: Option<BulkViscosity>,
    /// Volumetric anti-locking of the stress update
    /// ([`crate::anti_locking`]); `Off` by default.
    #[serde(default)]
    pub anti_locking: AntiLocking,
    /// Per face, the particle reservoir beyond it through which matter
    /// enters ([`crate::inflow`]); only on [`GridBoundary::Outflow`]
    /// faces, whose leaving particles are removed as without one. None by
    /// default.
    #[serde(default)]
    pub reservoirs: [Option<Reservoir>; 6],
    /// `Cartesian`, or `Axisymmetric`: the grid is (r, z) with x = r, the
    /// particles are rings about x = 0 (their masses and volumes are the
    /// rings'), and the transfers carry the hoop terms
    /// (docs/physics/mpm/axisymmetric.md).
    #[serde(default)]
    pub geometry: Geometry,
}

impl Default for MpmOptions {
    fn default() -> Self {
        Self {
            shape: ShapeFunction::Linear,
            scheme: UpdateScheme::Musl,
            cfl: 0.4,
            gravity: [0.0; 3],
            boundaries: [GridBoundary::Free; 6],
            mass_cutoff: 1e-3,
            min_dt: 1e-14,
            bulk_viscosity: None,
            fluid_bulk_viscosity: None,
            anti_locking: AntiLocking::Off,
            reservoirs: [None; 6],
            geometry: Geometry::Cartesian,
        }
    }
}

/// Why an [`MpmSolver`] cannot be built.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum MpmSetupError {
    /// An option out of range.
    #[error("MPM option `{option}` = {value}: {expected}")]
    Option {
        /// The option's name.
        option: &'static str,
        /// Its value, printed.
        value: String,
        /// What is expected.
        expected: &'static str,
    },
    /// No particle.
    #[error("the MPM solver needs at least one particle")]
    NoParticles,
    /// A particle names a material that does not exist.
    #[error("particle {particle} has material {material}, but only {count} materials are given")]
    UnknownMaterial {
        /// Particle index.
        particle: usize,
        /// Its material id.
        material: u16,
        /// Number of materials.
        count: usize,
    },
    /// A material's parameters are invalid.
    #[error("material {index}: {detail}")]
    Material {
        /// Material index.
        index: usize,
        /// The model's message.
        detail: String,
    },
    /// The particle set stores fewer history values than a model needs.
    #[error(
        "material {index} ({name}) needs {needed} history values per particle, the particle set stores {stride}"
    )]
    HistoryStride {
        /// Material index.
        index: usize,
        /// Model name.
        name: &'static str,
        /// Values needed.
        needed: usize,
        /// Values stored.
        stride: usize,
    },
    /// A particle outside the grid.
    #[error("particle {particle} at {position:?} m lies outside the grid")]
    OutsideGrid {
        /// Particle index.
        particle: usize,
        /// Its position, m.
        position: [f64; 3],
    },
    /// A surface load is invalid.
    #[error("surface load {index}: {detail}")]
    SurfaceLoad {
        /// Index of the load.
        index: usize,
        /// What is wrong.
        detail: String,
    },
    /// More particles than a 32-bit particle identity can number.
    #[error("{count} particles: at most {max} are supported", max = u32::MAX)]
    TooManyParticles {
        /// The number given.
        count: usize,
    },
    /// A reservoir that cannot be set up.
    #[error("{0}")]
    Reservoir(#[from] crate::inflow::ReservoirError),
    /// A particle whose shape-function stencil cannot be evaluated.
    #[error("particle {particle}: {detail}")]
    Shape {
        /// Particle index.
        particle: usize,
        /// The reason.
        detail: String,
    },
}

/// Particles are re-sorted by cell (in storage) every this many steps;
/// in between, the transfers find them through the bins of
/// [`crate::transfer`] wherever they lie.
pub const RESORT_INTERVAL: u64 = 32;

/// Buffers reused from step to step.
#[derive(Debug, Clone)]
struct Workspace {
    map: GridMap,
    nodes: GridNodes,
    bins: ParticleBins,
    /// The ΔF̄ buffers (empty unless the option is on).
    average: PatchAverage,
    /// The coupled step's σ_p + p I (empty unless it runs).
    shifted_stress: Vec<[f64; 6]>,
    /// The coupled step's nodal velocity changes (empty unless it runs).
    node_change: Vec<[f64; 3]>,
    /// The coupled step's temperature change per particle gathered from
    /// the nodes (empty unless it runs with that transfer).
    particle_change: Vec<f64>,
    /// The particles the coupled step's fluid frame consumed whole.
    consumed: Vec<usize>,
    /// The buffers the sort gathers the bulk-viscosity states and
    /// identities into (see [`MpmSolver::permute_own`]).
    bulk_scratch: Vec<BulkViscosityState>,
    id_scratch: Vec<u32>,
    /// Identities [first, first + count) of the particles that load the
    /// grid but are not re-mapped ([`MpmSolver::set_load_only`]).
    load_only: (u32, u32),
    /// MUSL's re-mapping weights, one per particle (the masses, zero for
    /// the load-only particles), and its node masses; empty unless used.
    remap_weight: Vec<f64>,
    remap_mass: Vec<f64>,
    /// The node buffers of the heat conduction (empty unless it is on).
    heat: HeatWork,
}

/// Memory an [`MpmSolver`] holds, bytes, from its arrays' lengths.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct MemoryUse {
    /// Every per-particle array: the particle state ([`Particles`]), the
    /// bulk-viscosity state and identity kept beside it, and the transfer
    /// bins.
    pub particles: usize,
    /// The grid: node fields and the per-block lists of the bins.
    pub grid: usize,
}

/// The explicit material point method on one level.
#[derive(Debug, Clone)]
pub struct MpmSolver {
    level: Level,
    materials: Vec<MaterialModel>,
    particles: Particles,
    options: MpmOptions,
    reference_particle_mass: f64,
    time: f64,
    steps: u64,
    outflow: ConservationTotals,
    work: Workspace,
    /// Per particle, in particle order: the bulk viscosity in its stress.
    bulk: Vec<BulkViscosityState>,
    /// Per particle, in particle order: its index in the set handed to
    /// [`MpmSolver::new`] (its identity through sorts and removals).
    ids: Vec<u32>,
    /// Identity of the next particle added by [`MpmSolver::insert_particles`].
    next_id: u32,
    /// Prescribed surface tractions ([`crate::traction`]).
    loads: Vec<SurfaceLoad>,
    /// Their nodal forces of the current step (reused buffer).
    surface_forces: Vec<(usize, [f64; 3])>,
    /// Work of the external forces (tractions, gravity) since the start, J.
    external_work: f64,
    /// The reservoirs beyond open faces ([`crate::inflow`]).
    inflow: Reservoirs,
    /// Per face: whether a plain outflow face (no reservoir) has had
    /// particles in its boundary cells moving inwards, which nothing
    /// follows in ([`MpmSolver::note_inflow_at_plain_outflow_faces`]).
    held_back: [bool; 6],
    /// The conductivity and specific heat of every material
    /// ([`crate::conduction`]); empty when no material conducts.
    thermal: Vec<ThermalProperties>,
    /// Per material: the specific heat through which the coupled step's
    /// heat exchange change is a heat (J/kg) rather than a temperature
    /// change ([`MpmSolver::set_coupled_heat`]); empty: temperature
    /// changes for every material.
    coupled_heat: Vec<Option<brisance_constitutive::SpecificHeat>>,
    /// The ranks the particle updates are spread over
    /// ([`MpmSolver::distribute`]); `None` on one rank.
    comm: Option<std::sync::Arc<dyn brisance_grid::comm::Communicator>>,
    /// The particle sets of the run's particle gauges, in order
    /// ([`MpmSolver::set_particle_gauges`]).
    gauges: Vec<crate::ParticleSet>,
}

/// The node fields of [`MpmSolver::NODE_FIELDS`].
const MPM_NODE_FIELDS: [&str; 14] = [
    "mass",
    "momentum_x",
    "momentum_y",
    "momentum_z",
    "velocity_x",
    "velocity_y",
    "velocity_z",
    "force_x",
    "force_y",
    "force_z",
    "acceleration_x",
    "acceleration_y",
    "acceleration_z",
    "active",
];

const CELL_FIELDS: [&str; 7] = [
    "density",
    "velocity_x",
    "velocity_y",
    "velocity_z",
    "pressure",
    "specific_internal_energy",
    "mass_density",
];

impl MpmSolver {
    /// The cell fields the solver outputs.
    pub const FIELDS: [&'static str; 7] = CELL_FIELDS;

    /// The node fields the solver outputs: lumped mass m_I (kg), momentum
    /// p_I (kg·m/s), velocity v_I^{n+1} of the momentum update (eq 22,
    /// after the boundary conditions; p_I/m_I before the first step, m/s),
    /// force f_I = f_I^int + f_I^ext + m_I g (N), acceleration a_I (m/s²),
    /// and `active`: 1 where m_I is above the mass cut-off, else 0.
    pub const NODE_FIELDS: [&'static str; 14] = MPM_NODE_FIELDS;

    /// Builds the solver; the particles' history blocks are initialised by
    /// their models ([`Material::init_history`]).
    pub fn new(
        level: Level,
        materials: Vec<MaterialModel>,
        mut particles: Particles,
        options: MpmOptions,
    ) -> Result<Self, MpmSetupError> {
        let bad = |option, value: f64, expected| MpmSetupError::Option {
            option,
            value: value.to_string(),
            expected,
        };
        if !(options.cfl > 0.0 && options.cfl <= 1.0) {
            return Err(bad("cfl", options.cfl, "must lie in (0, 1]"));
        }
        if !(options.mass_cutoff >= 0.0) || !options.mass_cutoff.is_finite() {
            return Err(bad(
                "mass_cutoff",
                options.mass_cutoff,
                "must be finite and ≥ 0",
            ));
        }
        if !(options.min_dt >= 0.0) || !options.min_dt.is_finite() {
            return Err(bad("min_dt", options.min_dt, "must be finite and ≥ 0"));
        }
        if let Some(g) = options.gravity.iter().find(|g| !g.is_finite()) {
            return Err(bad("gravity", *g, "components must be finite"));
        }
        for (field, viscosity) in [
            ("bulk_viscosity", options.bulk_viscosity),
            ("fluid_bulk_viscosity", options.fluid_bulk_viscosity),
        ] {
            if let Some(Err((name, value))) = viscosity.map(|v| v.validate()) {
                let option = match (field, name) {
                    ("bulk_viscosity", "linear") => "bulk_viscosity.linear",
                    ("bulk_viscosity", _) => "bulk_viscosity.quadratic",
                    (_, "linear") => "fluid_bulk_viscosity.linear",
                    _ => "fluid_bulk_viscosity.quadratic",
                };
                return Err(bad(option, value, "must be finite and ≥ 0"));
            }
        }
        if particles.is_empty() {
            return Err(MpmSetupError::NoParticles);
        }
        if u32::try_from(particles.len()).is_err() {
            return Err(MpmSetupError::TooManyParticles {
                count: particles.len(),
            });
        }
        for (index, m) in materials.iter().enumerate() {
            m.validate().map_err(|e| MpmSetupError::Material {
                index,
                detail: e.to_string(),
            })?;
            if m.history_len() > particles.history_stride() {
                return Err(MpmSetupError::HistoryStride {
                    index,
                    name: m.name(),
                    needed: m.history_len(),
                    stride: particles.history_stride(),
                });
            }
        }
        if let Some((particle, id)) = particles
            .material
            .iter()
            .enumerate()
            .find(|(_, id)| id.0 as usize >= materials.len())
        {
            return Err(MpmSetupError::UnknownMaterial {
                particle,
                material: id.0,
                count: materials.len(),
            });
        }
        let grid = level.geometry;
        for (face, r) in options.reservoirs.iter().enumerate() {
            if r.is_some() && options.boundaries[face] != GridBoundary::Outflow {
                return Err(crate::inflow::ReservoirError {
                    face,
                    detail: format!(
                        "a reservoir needs an Outflow face, which lets particles leave; this face is {:?}",
                        options.boundaries[face]
                    ),
                }
                .into());
            }
        }
        let inflow = Reservoirs::new(&options.reservoirs, &grid, materials.len())?;
        if let Some((particle, &position)) = particles
            .position
            .iter()
            .enumerate()
            .find(|(_, x)| grid.cell_containing(**x).is_none())
        {
            return Err(MpmSetupError::OutsideGrid { particle, position });
        }
        let block_bins = GridMap::block_bins_for(particles.len());
        if options.geometry.is_axisymmetric() {
            check_axisymmetric(&grid, &options, &particles)?;
        }
        let map = GridMap::with_block_bins(&grid, options.shape, block_bins)
            .with_geometry(options.geometry);
        let mut bins = ParticleBins::default();
        let f = &particles.deformation_gradient;
        bins.build_deformed(&map, &particles.position, &particles.initial_volume, f)
            .map_err(|e| match e {
                BinError::Outside { index, position } => MpmSetupError::OutsideGrid {
                    particle: index,
                    position,
                },
                BinError::Shape { index, error } => MpmSetupError::Shape {
                    particle: index,
                    detail: error.to_string(),
                },
                BinError::TooMany { count } => MpmSetupError::Option {
                    option: "particles",
                    value: count.to_string(),
                    expected: "at most 4294967294 particles",
                },
            })?;
        for p in 0..particles.len() {
            let id = particles.material[p].0;
            let m = &materials[id as usize];
            let len = m.history_len();
            // Per-point initial draws (seed 000 §4.2) seeded by the initial
            // position and material alone: the same bits whatever the
            // thread count or particle order.
            let seed = brisance_constitutive::random::point_seed(particles.position[p], id);
            m.init_history_at(&mut particles.history_of_mut(p)[..len], seed);
        }
        // Per metre of radius on an axisymmetric grid, where a ring's mass
        // carries its radius (NodeUpdate::radial).
        let reference_particle_mass = if options.geometry.is_axisymmetric() {
            let per_radius: f64 = (0..particles.len())
                .map(|p| particles.mass[p] / particles.position[p][0])
                .sum();
            per_radius / particles.len() as f64
        } else {
            particles.total_mass() / particles.len() as f64
        };
        let bulk = vec![BulkViscosityState::default(); particles.len()];
        let ids: Vec<u32> = (0..particles.len() as u32).collect();
        Ok(Self {
            external_work: 0.0,
            level,
            materials,
            particles,
            options,
            reference_particle_mass,
            time: 0.0,
            steps: 0,
            outflow: ConservationTotals::default(),
            work: Workspace {
                map,
                nodes: GridNodes::new(map.lattice),
                bins,
                average: PatchAverage::default(),
                shifted_stress: Vec::new(),
                node_change: Vec::new(),
                particle_change: Vec::new(),
                consumed: Vec::new(),
                bulk_scratch: Vec::new(),
                id_scratch: Vec::new(),
                load_only: (0, 0),
                remap_weight: Vec::new(),
                remap_mass: Vec::new(),
                heat: HeatWork::default(),
            },
            bulk,
            next_id: ids.len() as u32,
            ids,
            loads: Vec::new(),
            surface_forces: Vec::new(),
            inflow,
            held_back: [false; 6],
            thermal: Vec::new(),
            coupled_heat: Vec::new(),
            comm: None,
            gauges: Vec::new(),
        })
    }

    /// Hands the solver the particle sets of the run's particle gauges
    /// (`outputs.particle_gauges`, in order), which
    /// [`brisance_core::Solver::sample_particle_gauge`] samples; they
    /// replace any held before.
    pub fn set_particle_gauges(&mut self, gauges: Vec<crate::ParticleSet>) {
        self.gauges = gauges;
    }

    /// The particle sets of the run's particle gauges, in order.
    pub fn particle_gauges(&self) -> &[crate::ParticleSet] {
        &self.gauges
    }

    /// One step of heat conduction inside the solids
    /// ([`crate::conduction`]) on the particles' start-of-step positions
    /// and temperatures; nothing when no material conducts.
    pub(crate) fn conduct_heat(&mut self, dt: f64) {
        if !self.thermal.is_empty() {
            crate::conduction::conduct(
                &self.work.map,
                &self.work.bins,
                &mut self.particles,
                &self.thermal,
                &mut self.work.heat,
                dt,
            );
        }
    }

    /// Turns on heat conduction inside the solids ([`crate::conduction`])
    /// with each material's conductivity and specific heat; with no
    /// conductivity anywhere it stays off and the steps are unchanged, bit
    /// for bit.
    pub fn with_heat_conduction(
        mut self,
        conduction: HeatConduction,
    ) -> Result<Self, MpmSetupError> {
        let thermal =
            conduction
                .resolve(&self.materials)
                .map_err(|(option, value, expected)| MpmSetupError::Option {
                    option,
                    value,
                    expected,
                })?;
        self.thermal = if conduction.is_on() {
            thermal
        } else {
            Vec::new()
        };
        Ok(self)
    }

    /// The conductivity and specific heat of every material, indexed by
    /// [`MaterialId`]; empty when heat conduction is off.
    pub fn thermal_properties(&self) -> &[ThermalProperties] {
        &self.thermal
    }

    /// The specific heat material `material` carries: its conduction's
    /// ([`MpmSolver::with_heat_conduction`], where it takes part), else its
    /// model's (the J2 metal's, constant or following the temperature, or
    /// a plugin model's); `None` for a model without one.
    pub fn specific_heat(
        &self,
        material: MaterialId,
    ) -> Option<brisance_constitutive::SpecificHeat> {
        let m = material.0 as usize;
        match self.thermal.get(m) {
            Some(t) if t.takes_part() => Some(t.specific_heat.clone()),
            _ => self.materials.get(m)?.specific_heat(),
        }
    }

    /// Per material (indexed by [`MaterialId`]; past the end: `None`): the
    /// specific heat through which the heat exchange's change that the
    /// coupled step hands each particle ([`CoupledStep::update_particles`],
    /// [`CoupledStep::update_particles_from_nodes`]) is a heat q in J/kg,
    /// the particle's temperature rising by the ΔT with
    /// H(T + ΔT) − H(T) = q; `None`: the change is a temperature change in
    /// K (the default for every material).
    pub fn set_coupled_heat(&mut self, heat: Vec<Option<brisance_constitutive::SpecificHeat>>) {
        self.coupled_heat = heat;
    }

    /// Adds prescribed surface tractions ([`crate::traction`]); their
    /// particle sets must have been chosen from the particle set handed to
    /// [`MpmSolver::new`].
    pub fn with_surface_loads(mut self, loads: Vec<SurfaceLoad>) -> Result<Self, MpmSetupError> {
        for (index, load) in loads.iter().enumerate() {
            load.validate()
                .map_err(|detail| MpmSetupError::SurfaceLoad { index, detail })?;
        }
        self.loads = loads;
        Ok(self)
    }

    /// The prescribed surface tractions.
    pub fn surface_loads(&self) -> &[SurfaceLoad] {
        &self.loads
    }

    /// The particles, in storage order: sorted by cell at the last re-sort
    /// (every [`RESORT_INTERVAL`] steps), and in that order since.
    pub fn particles(&self) -> &Particles {
        &self.particles
    }

    /// The level.
    pub fn level(&self) -> &Level {
        &self.level
    }

    /// The options.
    pub fn options(&self) -> &MpmOptions {
        &self.options
    }

    /// The constitutive models, indexed by [`MaterialId`].
    pub fn materials(&self) -> &[MaterialModel] {
        &self.materials
    }

    /// Steps taken.
    pub fn steps(&self) -> u64 {
        self.steps
    }

    /// The node fields of the last step.
    pub fn grid_nodes(&self) -> &GridNodes {
        &self.work.nodes
    }

    /// The memory the solver holds (see [`MemoryUse`]).
    pub fn memory_use(&self) -> MemoryUse {
        use std::mem::size_of_val;
        MemoryUse {
            particles: self.particles.state_bytes()
                + size_of_val(self.bulk.as_slice())
                + size_of_val(self.ids.as_slice())
                + self.work.bins.particle_bytes()
                + self.work.average.particle_bytes(),
            grid: self.work.nodes.bytes()
                + self.work.bins.block_bytes()
                + self.work.average.cell_bytes()
                + self.work.heat.bytes(),
        }
    }

    /// The node fields before the first step: the P2G of the particles'
    /// mass and momentum (eqs 18, 21) and v_I = p_I/m_I with the cut-off
    /// `threshold` and the boundary conditions, in `velocity_new` as well;
    /// force and acceleration zero.
    fn initial_nodes(&self, threshold: f64) -> GridNodes {
        let ps = &self.particles;
        let mut nodes = GridNodes::new(self.work.map.lattice);
        crate::transfer::p2g(
            &self.work.map,
            &self.work.bins,
            crate::transfer::P2gParticles {
                position: &ps.position,
                mass: &ps.mass,
                velocity: &ps.velocity,
                volume: &ps.volume,
                stress: &ps.stress,
            },
            &mut nodes,
            crate::transfer::P2gSums::MassMomentum,
        );
        let update = crate::grid_nodes::NodeUpdate {
            boundaries: &self.options.boundaries,
            cells: self.level.geometry.cells,
            mass_threshold: threshold,
            radial: radial_cutoff(&self.options, &self.level.geometry),
            light_nodes_move: false,
            gravity: self.options.gravity,
            dt: 0.0,
        };
        nodes.update(&update, crate::grid_nodes::NodeStage::Velocity);
        nodes.velocity_new.clone_from(&nodes.velocity);
        nodes
    }

    /// Mass, momentum and energy carried out through outflow faces so far.
    pub fn outflow_totals(&self) -> ConservationTotals {
        self.outflow
    }

    /// Each particle's identity, in particle order: its index in the set
    /// handed to [`MpmSolver::new`]. Particles are re-sorted by cell and
    /// removed through outflow faces; the identity follows them (see
    /// [`crate::ParticleSet`]).
    pub fn particle_ids(&self) -> &[u32] {
        &self.ids
    }

    /// Entry `k` of particle `p`'s damage variables
    /// ([`MaterialModel::damage`]), 0 when its model has fewer.
    fn damage_entry(&self, p: usize, k: usize) -> f64 {
        let ps = &self.particles;
        let model = &self.materials[ps.material[p].0 as usize];
        model
            .damage(ps.history_of(p))
            .get(k)
            .copied()
            .unwrap_or(0.0)
    }

    /// Each particle's bulk-viscosity state (q and tr D), in particle order.
    pub fn bulk_viscosity(&self) -> &[BulkViscosityState] {
        &self.bulk
    }

    /// The material's own pressure of particle `p`, −tr σ/3 − q (the stored
    /// stress contains −q I), Pa.
    fn material_pressure(&self, p: usize) -> f64 {
        let s = &self.particles.stress[p];
        -(s[0] + s[1] + s[2]) / 3.0 - self.bulk[p].q
    }

    /// The viscosity parameters of a step, if the option is on.
    fn viscosity_params(&self) -> Option<ViscosityParams> {
        viscosity_params(&self.options, &self.level.geometry)
    }

    /// Particle `p`'s sound speed [`Material::wave_speed`] at ρ = m/V and
    /// its e, the signal speed the step takes for it (the bulk viscosity's
    /// Q + √(Q² + c²) at its last tr D when `viscosity` is on, else c) and
    /// its |v|, m/s: what [`Solver::stable_dt`] and
    /// [`Solver::time_step_limit`] read.
    #[inline]
    fn signal_speed(&self, p: usize, viscosity: Option<ViscosityParams>) -> (f64, f64, f64) {
        let ps = &self.particles;
        let rho = ps.mass[p] / ps.volume[p];
        let material = &self.materials[ps.material[p].0 as usize];
        let c = material.wave_speed(rho, ps.specific_internal_energy[p]);
        let fluid = matches!(material, MaterialModel::Null(_));
        let s = viscosity
            .and_then(|v| v.coefficients(fluid))
            .map_or(c, |(model, length)| {
                model.signal_speed(self.bulk[p].trace_d, c, length)
            });
        let v = ps.velocity[p];
        (c, s, (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt())
    }

    /// The smallest cell size over the axes with more than one cell, m
    /// (infinite on a grid of one cell).
    fn smallest_active_spacing(&self) -> f64 {
        let grid = &self.level.geometry;
        (0..3)
            .filter(|&d| grid.cells[d] > 1)
            .map(|d| grid.spacing[d])
            .fold(f64::INFINITY, f64::min)
    }

    /// The diffusive limit of the heat conduction
    /// ([`crate::conduction::diffusive_time_step`]) and the largest thermal
    /// diffusivity k V/(m c) that sets it, m²/s: (∞, 0) when no material
    /// conducts. The error is the first particle whose diffusivity is not
    /// finite.
    fn conduction_step(&self) -> Result<(f64, f64), usize> {
        let alpha = if self.thermal.is_empty() {
            0.0
        } else {
            crate::conduction::max_diffusivity(&self.particles, &self.thermal)?
        };
        let dt =
            crate::conduction::diffusive_time_step(alpha, &self.level.geometry, self.options.cfl);
        Ok((dt, alpha))
    }

    /// Every [`RESORT_INTERVAL`] steps, sorts the particles by cell (a
    /// stable counting sort, skipped when they are sorted); every step, bins
    /// them for the transfers (see [`crate::transfer`]).
    fn sort_particles(&mut self) -> Result<(), SolverError> {
        let grid = self.level.geometry;
        let time = self.time;
        let outside = |index: usize, position: [f64; 3]| {
            SolverError::Other(format!(
                "MPM at t = {time:e} s: particle {index} at {position:?} m lies outside the grid"
            ))
        };
        if self.steps.is_multiple_of(RESORT_INTERVAL) && !self.particles.is_sorted_by_cell(&grid) {
            let perm = self.particles.sort_by_cell(&grid).map_err(|e| match e {
                crate::ParticleError::OutsideGrid { index, position } => outside(index, position),
                other => SolverError::Other(other.to_string()),
            })?;
            self.permute_own(&perm);
        }
        let ps = &self.particles;
        let binned = self.work.bins.build_deformed(
            &self.work.map,
            &ps.position,
            &ps.initial_volume,
            &ps.deformation_gradient,
        );
        binned.map_err(|e| match e {
            BinError::Outside { index, position } => outside(index, position),
            BinError::Shape { index, error } => self.particle_error(index, error.to_string()),
            BinError::TooMany { .. } => SolverError::Other(e.to_string()),
        })?;
        let (first, count) = self.work.load_only;
        if count > 0 && self.options.shape.is_gimp() {
            self.work.bins.point_particles(&self.ids, first, count);
        }
        Ok(())
    }

    /// The nodal forces of the surface tractions at the current time, in
    /// the reused buffer (hand it back to `self.surface_forces` after the
    /// step).
    fn take_surface_forces(&mut self) -> Result<Vec<(usize, [f64; 3])>, SolverError> {
        let mut surface_forces = std::mem::take(&mut self.surface_forces);
        if let Err((p, why)) = traction::surface_node_forces(
            &self.loads,
            self.time,
            &self.work.map,
            &self.particles,
            &self.ids,
            &mut surface_forces,
        ) {
            return Err(self.particle_error(p, why));
        }
        Ok(surface_forces)
    }

    /// One explicit step of Δt = `dt` (see the module doc): bin, transfer,
    /// update the stresses, remove the particles that left.
    fn step(&mut self, dt: f64) -> Result<(), SolverError> {
        if !self.inflow.is_empty() {
            self.inject()?;
        }
        self.sort_particles()?;
        if !self.inflow.is_empty() {
            if let Err(e) = self.inflow.share(&self.work.map) {
                return Err(SolverError::Other(format!(
                    "MPM at t = {:e} s: {e}",
                    self.time
                )));
            }
        }
        if self.options.anti_locking == AntiLocking::FBar {
            let grid = &self.level.geometry;
            if let Err(e) = self.work.average.assign(grid, &self.particles.position) {
                return Err(self.particle_error(e.index, e.to_string()));
            }
        }
        // Heat conduction first, from the positions and temperatures of
        // the start of the step (crate::conduction; it changes the
        // temperatures only, which nothing before the stress update reads).
        self.conduct_heat(dt);
        let mut surface_forces = self.take_surface_forces()?;
        surface_forces.extend_from_slice(self.inflow.forces());
        let grid = self.level.geometry;
        let runs = self.particle_runs();
        let params = StepParams {
            surface_forces: &surface_forces,
            reservoir: self.inflow.shares(),
            own: runs.as_ref().map(|r| (r.nodes().start, r.nodes().end)),
            ..step_params(
                &self.options,
                &self.materials,
                self.reference_particle_mass,
                &grid,
                dt,
            )
        };
        let work = &mut self.work;
        let t = step::Transfer {
            map: &work.map,
            bins: &work.bins,
        };
        let nodes = &mut work.nodes;
        let ps = &mut self.particles;
        let bulk = &mut self.bulk;
        // G2P and the stress update share one visit of each particle
        // (step::g2p_and_update_stresses): L_p is not stored. With the ΔF̄
        // averaging (crate::anti_locking), L_p of every particle is stored
        // and averaged over its cell first, and the internal force is formed
        // with the cell-averaged pressure; the cells are those of x_pⁿ.
        let mut average = match self.options.anti_locking {
            AntiLocking::Off => None,
            AntiLocking::FBar => Some(&mut work.average),
        };
        let failure = match params.scheme {
            UpdateScheme::Usf => {
                let parts = G2pParts {
                    velocity: false,
                    position: false,
                    gradient: Some(NodeVelocity::Start),
                };
                step::p2g_velocity(&t, ps, nodes, &params);
                let failure = step::g2p_and_update_stresses_averaged(
                    &t,
                    ps,
                    bulk,
                    nodes,
                    &params,
                    parts,
                    average.as_deref_mut(),
                );
                let failure = share(&runs, ps, bulk, parts, failure);
                if failure.is_none() {
                    let parts = G2pParts {
                        velocity: true,
                        position: true,
                        gradient: None,
                    };
                    step::p2g_integrate_averaged(&t, ps, nodes, &params, P2gSums::Force, average);
                    step::g2p(&t, ps, nodes, dt, parts, &mut Vec::new());
                }
                failure
            }
            UpdateScheme::Usl => {
                let parts = G2pParts {
                    velocity: true,
                    position: true,
                    gradient: Some(NodeVelocity::End),
                };
                let all = P2gSums::All;
                step::p2g_integrate_averaged(&t, ps, nodes, &params, all, average.as_deref_mut());
                let failure = step::g2p_and_update_stresses_averaged(
                    &t, ps, bulk, nodes, &params, parts, average,
                );
                share(&runs, ps, bulk, parts, failure)
            }
            UpdateScheme::Musl => {
                let parts = G2pParts {
                    velocity: false,
                    position: true,
                    gradient: Some(NodeVelocity::Remapped),
                };
                let all = P2gSums::All;
                step::p2g_integrate_averaged(&t, ps, nodes, &params, all, average.as_deref_mut());
                let (first, count) = work.load_only;
                if count > 0 && params.reservoir.is_empty() {
                    let ids = &self.ids;
                    work.remap_weight.clear();
                    work.remap_weight
                        .extend(ps.mass.iter().zip(ids).map(|(&m, &id)| {
                            if id >= first && id - first < count {
                                0.0
                            } else {
                                m
                            }
                        }));
                    step::g2p_velocity_and_remap_weighted(
                        &t,
                        ps,
                        nodes,
                        &params,
                        &work.remap_weight,
                        &mut work.remap_mass,
                    );
                } else {
                    step::g2p_velocity_and_remap(&t, ps, nodes, &params);
                }
                let failure = step::g2p_and_update_stresses_averaged(
                    &t, ps, bulk, nodes, &params, parts, average,
                );
                share(&runs, ps, bulk, parts, failure)
            }
        };
        self.surface_forces = surface_forces;
        if let Some(f) = failure {
            return Err(self.particle_error(f.index, f.describe()));
        }
        self.external_work +=
            self.work
                .nodes
                .external_work(&self.surface_forces, self.options.gravity, dt);
        self.handle_leaving_particles()?;
        self.inflow.advance(dt);
        self.note_inflow_at_plain_outflow_faces();
        self.time += dt;
        self.steps += 1;
        Ok(())
    }

    fn particle_error(&self, index: usize, detail: String) -> SolverError {
        let grid = &self.level.geometry;
        let x = self
            .particles
            .position
            .get(index)
            .copied()
            .unwrap_or([f64::NAN; 3]);
        let cell = grid.cell_containing(x).unwrap_or([0; 3]);
        SolverError::NonPhysicalState {
            time: self.time,
            cell,
            centre: grid.cell_centre(cell),
            detail: format!("particle {index} at {x:?} m: {detail}"),
        }
    }
}

/// [`ranks::share_updated`] on several ranks; `failure` unchanged on one.
fn share(
    runs: &Option<brisance_grid::comm::NodeRuns>,
    ps: &mut Particles,
    bulk: &mut [BulkViscosityState],
    parts: G2pParts,
    failure: Option<step::ParticleFailure>,
) -> Option<step::ParticleFailure> {
    match runs {
        Some(runs) => ranks::share_updated(runs, ps, bulk, parts, failure),
        None => failure,
    }
}

/// `[r of node 0, Δr]` on an axisymmetric grid ([`NodeUpdate::radial`]).
///
/// [`NodeUpdate::radial`]: crate::grid_nodes::NodeUpdate::radial
fn radial_cutoff(
    options: &MpmOptions,
    grid: &brisance_core::UniformGridGeometry,
) -> Option<[f64; 2]> {
    options
        .geometry
        .is_axisymmetric()
        .then_some([grid.origin[0], grid.spacing[0]])
}

/// What an axisymmetric MPM run needs: one cell along the third axis,
/// r ≥ 0, every particle off the axis (a ring of radius 0 has no mass), no
/// particle reservoirs (whose particles are not rings yet).
fn check_axisymmetric(
    grid: &brisance_core::UniformGridGeometry,
    options: &MpmOptions,
    particles: &Particles,
) -> Result<(), MpmSetupError> {
    let bad = |value: String, expected: &'static str| {
        Err(MpmSetupError::Option {
            option: "geometry",
            value,
            expected,
        })
    };
    if grid.cells[2] != 1 || grid.origin[0] < 0.0 {
        return bad(
            format!(
                "Axisymmetric on cells {:?} from x = {}",
                grid.cells, grid.origin[0]
            ),
            "an (r, z) grid: one cell along z, and x = r ≥ 0",
        );
    }
    if options.reservoirs.iter().any(Option::is_some) {
        return bad(
            "Axisymmetric with particle reservoirs".into(),
            "no reservoirs beyond open faces on an axisymmetric grid (their particles are not rings)",
        );
    }
    if let Some(p) = particles.position.iter().position(|x| !(x[0] > 0.0)) {
        return bad(
            format!(
                "Axisymmetric with particle {p} at r = {}",
                particles.position[p][0]
            ),
            "every particle at r > 0",
        );
    }
    Ok(())
}

/// The parameters of a step of Δt = `dt` on `grid` (a copy of the
/// level's geometry), without surface forces; free of `self` so that the
/// step can borrow the work arrays mutably beside it.
fn step_params<'a>(
    options: &'a MpmOptions,
    materials: &'a [MaterialModel],
    reference_particle_mass: f64,
    grid: &'a brisance_core::UniformGridGeometry,
    dt: f64,
) -> StepParams<'a> {
    StepParams {
        grid,
        shape: options.shape,
        scheme: options.scheme,
        gravity: options.gravity,
        boundaries: &options.boundaries,
        mass_threshold: options.mass_cutoff * reference_particle_mass,
        radial_cutoff: radial_cutoff(options, grid),
        light_nodes_move: false,
        materials,
        dt,
        bulk_viscosity: viscosity_params(options, grid),
        surface_forces: &[],
        reservoir: &[],
        own: None,
    }
}

/// The bulk-viscosity parameters of a step on `grid`, if the option is on.
fn viscosity_params(
    options: &MpmOptions,
    grid: &brisance_core::UniformGridGeometry,
) -> Option<ViscosityParams> {
    (options.bulk_viscosity.is_some() || options.fluid_bulk_viscosity.is_some()).then(|| {
        ViscosityParams {
            model: options.bulk_viscosity,
            fluid: options.fluid_bulk_viscosity,
            length: viscosity_length(grid),
        }
    })
}

/// m (e + |v|²/2), J.
#[inline]
fn particle_energy(m: f64, v: [f64; 3], e: f64) -> f64 {
    m * (e + 0.5 * (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]))
}

mod coupled;
mod particle_flow;
mod ranks;
mod solver_trait;
pub use coupled::CoupledStep;

#[cfg(test)]
mod tests;

#[cfg(test)]
mod axisymmetric_tests;

#[cfg(test)]
mod output_tests;
