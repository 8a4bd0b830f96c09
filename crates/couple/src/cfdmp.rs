//! [`Cfdmp`]: one explicit step of the coupled finite-difference /
//! material-point method, the 14 steps of seed 001 §3.5.
//!
//! The MPM step is the [`MpmSolver`]'s own (it performs steps 2–6 and 9–13
//! in one call); the bridge enters it through the donor cells, which join
//! it as particles for the step (eqs 37–39 are then its own P2G sums, see
//! [`crate::bridge::fdm_cell_as_particle`]) and are taken out again after
//! it. One step from n to n + 1:
//!
//! - step 1: Δt = min of the FDM and MPM CFL limits ([`Cfdmp::stable_dt`]);
//! - steps 2–6 and 9–13: [`Cfdmp::mpm_step`], the donor cells as
//!   particles, the MPM step, the donor particles removed;
//! - step 7: [`Cfdmp::update_fictitious_cells`], eqs 31–36 from the nodes
//!   of the momentum update (eq 22) and the particles' internal energies;
//! - step 8: the FDM step (eq 6) over the FDM region and its fictitious
//!   cells;
//! - step 14: [`Cfdmp::transport`], eqs 40–51 at every interface face.
//!
//! Steps 9–13 run before step 7 here; they change only the particles, and
//! step 7 reads the nodes, so the nodal values are those of step 6 as in
//! the paper, while eq 33 sums the particles' internal energy after their
//! stress update (n + 1) rather than before it.
//!
//! Before activation only the FDM runs, and its fictitious cells keep
//! their initial state: the MPM region starts when the pressure of an FDM
//! cell within `activation_cells` of the interface (donor side) reaches
//! `activation_pressure` (seed 001 §3: "arrival of the shock wave front
//! is detected and the interaction region will be activated").

use std::time::Instant;

use brisance_core::{ConservationTotals, Geometry, Solver, SolverError};
use brisance_fdm::state::specific_internal_energy;
use brisance_fdm::{FdmSolver, GasLaw};
use brisance_mpm::{MaterialId, MpmSolver, ParticleInit};

use crate::bridge::{
    absorb_particle, centre_weight, create_particles, deposit_into_particle, fdm_cell_as_particle,
    fdm_outflow_is_supersonic, fictitious_mass_momentum, fictitious_source, interface_fluxes,
    interface_state, resolve_fictitious_line, CellParticles, Deposit, FaceInflow, FictitiousSource,
    NewParticle, NormalState, Primitive,
};
use crate::regions::{BridgeRegions, Side};

/// Options of the coupling.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CfdmpOptions {
    /// The MPM material of air particles (created ones and donor cells).
    pub air: MaterialId,
    /// The MPM material of detonation products, if the FDM carries them:
    /// inflow from a donor cell with products mass fraction Y ≥ 1/2 becomes
    /// particles of it, with the donor's specific internal energy, and the
    /// fictitious cells' ρY is ρ times the products share of their
    /// particles' mass. `None`: all inflow is air.
    pub products: Option<MaterialId>,
    /// γ of the air (eq 48).
    pub gamma: f64,
    /// Mass m_e of an existing air particle (eq 45), kg. On an (r, z)
    /// grid, where a particle is a ring and its mass grows with its radius,
    /// m_e/r_p, kg/m: a face at radius r takes m_e = `existing_mass` · r.
    pub existing_mass: f64,
    /// Pressure that activates the MPM region, Pa.
    pub activation_pressure: f64,
    /// Cells on the FDM side of the interface watched for activation.
    pub activation_cells: usize,
    /// Smallest mass of a created particle as a fraction of m_e (eqs
    /// 45–46): a face's inflow waits, booked as in transit, until the
    /// s ≥ 4 particles it makes would each weigh at least this much
    /// (`Pending`). 0 is the paper's rule, particles every step with
    /// inflow, at least 4 per face however small f_m is.
    pub min_particle_mass: f64,
    /// Volume V_e of an initial particle, m³: m_e (eq 45) at a face is then
    /// max(`existing_mass`, ρ_donor V_e), so that compressed air and the
    /// dense products enter as particles of the initial particles' size
    /// rather than as ρ/ρ₀ times as many air-mass particles. 0: m_e is
    /// `existing_mass` everywhere (the paper's rule). On an (r, z) grid
    /// V_e/r_p, m²: V_e = `existing_volume` · r at a face at radius r.
    pub existing_volume: f64,
    /// Deposit a face's inflow into the fluid particles of the same
    /// material already in its first bridge cell (mass-weighted shares of
    /// its mass, momentum and total energy), and create particles (eqs
    /// 45–48) only where that cell holds none, at once, without waiting
    /// for `min_particle_mass`: the inflow is inside the MPM region the
    /// step it crosses the interface ([`deposit_into_particle`]). false:
    /// the batches of `min_particle_mass` (or the paper's rule).
    pub deposit: bool,
    /// On an (r, z) grid, the rings each donor cell joins the MPM step as
    /// (eqs 37–39), side by side along r: the MPM's initial particles per
    /// cell along r. The nodal sums of eqs 37–39 then use the quadrature
    /// of the particles across the interface, so that a uniform pressure
    /// pushes a node on the interface equally from both sides (N_I·r is
    /// quadratic in r, and one ring at the cell centre weighs it
    /// differently from two). Ignored on a Cartesian grid (one particle per
    /// cell, exact there).
    pub donor_rings: usize,
}

/// Inflow of one interface face not yet made into particles (sums over
/// the steps since its last particles), so that a small f_m does not make
/// particles far lighter than the existing ones.
#[derive(Debug, Clone, Copy, PartialEq, Default, serde::Serialize, serde::Deserialize)]
pub struct Pending {
    /// Σ f_m, kg.
    pub mass: f64,
    /// Σ f_p (eq 44), kg·m/s.
    pub momentum: [f64; 3],
    /// Σ f_m (e + |v_f|²/2), the total energy the particles will carry, J.
    pub energy: f64,
    /// The part of Σ f_m from donor cells of products (Y ≥ 1/2), kg.
    pub products: f64,
    /// Σ v_n Δt, the length the inflow filled, m.
    pub length: f64,
}

/// Running totals of the transport.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct TransportTotals {
    /// Particles created.
    pub created: u64,
    /// Mass, momentum and energy they carried into the MPM region.
    pub into_mpm: ConservationTotals,
    /// Particles absorbed by FDM cells.
    pub absorbed: u64,
    /// Mass, momentum and energy they carried into the FDM region.
    pub into_fdm: ConservationTotals,
    /// Detonation-products mass of the inflow that entered the MPM region
    /// as air (the MPM region carries no products species), kg.
    pub products_as_air: f64,
    /// Fictitious lines (steps × lines normal to the interface) that took
    /// the FDM region's own outflow state because its outflow was
    /// supersonic against the MPM's state (`fdm_outflow_is_supersonic`).
    pub supersonic_outflow: u64,
    /// Particles that received a deposit of inflow (`CfdmpOptions::deposit`).
    pub deposited: u64,
    /// Fictitious cells (steps × cells) whose MPM cell held no material
    /// and that took the state inside them (zero gradient).
    pub zero_gradient: u64,
    /// Fictitious cells (steps × cells) whose MPM cell held only structure
    /// (a reflecting wall).
    pub wall: u64,
}

/// The coupled solver.
#[derive(Debug)]
pub struct Cfdmp<E: GasLaw> {
    regions: BridgeRegions,
    /// The grids' geometry (both the same): on an (r, z) grid every
    /// volume and area of the exchange is a ring's ([`Cfdmp::volume_at`],
    /// [`Cfdmp::area_at`]).
    geometry: Geometry,
    fdm: FdmSolver<E>,
    mpm: MpmSolver,
    options: CfdmpOptions,
    /// FDM-grid index of FDM-region cell 0 along the split axis.
    fdm_offset: usize,
    /// MPM-grid index minus FDM-grid index along the split axis.
    mpm_shift: isize,
    /// Fictitious layers past the bridge.
    layers: usize,
    /// Their initial conservative values, per (layer, tangential cell).
    fictitious_initial: Vec<[f64; 6]>,
    active: bool,
    activated_at: Option<f64>,
    time: f64,
    steps: u64,
    totals: TransportTotals,
    fdm_seconds: f64,
    mpm_seconds: f64,
    /// Inflow in transit per interface face (`face_cells` order).
    pending: Vec<Pending>,
    /// Tangential FDM-grid cells of one layer normal to the split axis
    /// ([`Cfdmp::face_cells`]).
    faces: Vec<[usize; 3]>,
    /// The fictitious cells, layer by layer ([`Cfdmp::fictitious_cells`]).
    fictitious: Vec<[usize; 3]>,
    /// Identities of this step's donor particles, [first, first + count):
    /// they stay in the MPM after its step until the transport removes
    /// them with the absorbed particles, in one pass.
    donors: (u32, u32),
    /// Σ over the MPM steps of the particles stepped.
    particle_steps: u64,
    /// Reused buffers.
    /// Per-step particle sums of the MPM cells around the fictitious
    /// layers, the fictitious cells' sources and their states (step 7).
    cells: Vec<CellParticles>,
    sources: Vec<FictitiousSource>,
    values: Vec<[f64; 6]>,
    line_inner: Vec<[f64; 6]>,
    line_sources: Vec<FictitiousSource>,
    line_out: Vec<[f64; 6]>,
    created: Vec<NewParticle>,
    inits: Vec<ParticleInit>,
    leaving: Vec<usize>,
    /// Per face, the fluid particles in its first bridge cell:
    /// `members[start[f]..start[f + 1]]` (storage indices, ascending).
    start: Vec<usize>,
    members: Vec<usize>,
    pairs: Vec<(usize, usize)>,
    /// Particles on the FDM side of the interface, donors excepted.
    outside: Vec<usize>,
    /// Storage indices of the donor particles.
    donor_slots: Vec<usize>,
}

impl<E: GasLaw> Cfdmp<E> {
    /// Couples `fdm`, built on `regions.fdm_grid(layers)`, and `mpm`,
    /// built on `regions.mpm_grid()`, whose air particles are `options.air`.
    pub fn new(
        regions: BridgeRegions,
        fdm: FdmSolver<E>,
        mpm: MpmSolver,
        layers: usize,
        options: CfdmpOptions,
    ) -> Result<Self, String> {
        let (fg, fdm_offset) = regions.fdm_grid(layers);
        let (mg, _) = regions.mpm_grid();
        if fdm.level().geometry.cells != fg.cells {
            return Err(format!(
                "the FDM grid has {:?} cells; the bridge needs {:?} (the FDM region and {layers} fictitious layers)",
                fdm.level().geometry.cells,
                fg.cells
            ));
        }
        if mpm.level().geometry.cells != mg.cells {
            return Err(format!(
                "the MPM grid has {:?} cells; the bridge needs {:?} (the MPM region and one halo cell)",
                mpm.level().geometry.cells,
                mg.cells
            ));
        }
        if mpm.options().shape != brisance_mpm::ShapeFunction::Linear {
            return Err(
                "the bridge maps through the linear shape functions of seed 001 eq 16: use shape_function: Linear"
                    .into(),
            );
        }
        if let Some(p) = options.products {
            if p.0 as usize >= mpm.materials().len() || !E::SPECIES {
                return Err(format!(
                    "products material {} needs an MPM material and an FDM gas law with a products species",
                    p.0
                ));
            }
        }
        if options.air.0 as usize >= mpm.materials().len() {
            return Err(format!(
                "air material {} is not an MPM material",
                options.air.0
            ));
        }
        if !(options.gamma > 1.0) {
            return Err(format!("gamma = {} must be > 1", options.gamma));
        }
        if !(0.0..=1.0).contains(&options.min_particle_mass) {
            return Err(format!(
                "min_particle_mass = {} must lie in [0, 1]",
                options.min_particle_mass
            ));
        }
        if !(options.existing_volume >= 0.0 && options.existing_volume.is_finite()) {
            return Err(format!(
                "existing_volume = {} m³ must be non-negative",
                options.existing_volume
            ));
        }
        if !(options.existing_mass > 0.0) {
            return Err(format!(
                "existing_mass = {} kg must be positive",
                options.existing_mass
            ));
        }
        let a = regions.axis;
        let geometry = fdm.geometry();
        if mpm.options().geometry != geometry {
            return Err(format!(
                "the FDM grid is {} and the MPM grid {}: the bridge needs one geometry",
                geometry.name(),
                mpm.options().geometry.name()
            ));
        }
        if geometry.is_axisymmetric() && a != 1 {
            return Err(
                "on an Axisymmetric grid the bridge's regions must be split along z (y): the interface is a plane z = const; a cylindrical interface r = const is not supported yet"
                    .into(),
            );
        }
        let h = fg.spacing[a];
        // The products stream through the FDM region's outflow faces and
        // its fictitious cells at up to Mach 10 (internal energy a few per
        // cent of the total): the sweep's face limiter must keep e positive
        // there (docs/physics/couple/bridge.md), so it is never off.
        let mut fdm = fdm;
        if !fdm.limiter().positivity() {
            fdm.set_limiter(brisance_fdm::FaceLimiter::Positivity);
        }
        let mpm_shift = ((fg.origin[a] - mg.origin[a]) / h).round() as isize;
        let mut s = Self {
            regions,
            geometry,
            fdm,
            mpm,
            options,
            fdm_offset,
            mpm_shift,
            layers,
            fictitious_initial: Vec::new(),
            active: false,
            activated_at: None,
            time: 0.0,
            steps: 0,
            totals: TransportTotals::default(),
            fdm_seconds: 0.0,
            mpm_seconds: 0.0,
            pending: Vec::new(),
            cells: Vec::new(),
            sources: Vec::new(),
            values: Vec::new(),
            line_inner: Vec::new(),
            line_sources: Vec::new(),
            line_out: Vec::new(),
            created: Vec::new(),
            inits: Vec::new(),
            leaving: Vec::new(),
            faces: Vec::new(),
            fictitious: Vec::new(),
            donors: (0, 0),
            particle_steps: 0,
            start: Vec::new(),
            members: Vec::new(),
            pairs: Vec::new(),
            outside: Vec::new(),
            donor_slots: Vec::new(),
        };
        s.faces = s.face_cells();
        s.fictitious = s.fictitious_cells();
        s.pending = vec![Pending::default(); s.faces.len()];
        let cells = s.fictitious.clone();
        s.fictitious_initial = cells
            .iter()
            .map(|&g| s.fdm.cell_conservative(g).unwrap_or([0.0; 6]))
            .collect();
        Ok(s)
    }

    /// The FDM solver.
    pub fn fdm(&self) -> &FdmSolver<E> {
        &self.fdm
    }

    /// The MPM solver.
    pub fn mpm(&self) -> &MpmSolver {
        &self.mpm
    }

    /// The regions.
    pub fn regions(&self) -> &BridgeRegions {
        &self.regions
    }

    /// Whether the MPM region runs.
    pub fn is_active(&self) -> bool {
        self.active
    }

    /// Time of activation, s.
    pub fn activated_at(&self) -> Option<f64> {
        self.activated_at
    }

    /// The transport totals so far.
    pub fn transport_totals(&self) -> TransportTotals {
        self.totals
    }

    /// Wall seconds spent in the FDM and the MPM parts: the FDM step
    /// (step 8) and the FDM-only steps before activation count as FDM; the
    /// MPM step with the donor cells (steps 2–6, 9–13), the fictitious
    /// cells (step 7) and the transport (step 14) count as MPM.
    pub fn split_seconds(&self) -> (f64, f64) {
        (self.fdm_seconds, self.mpm_seconds)
    }

    /// The particle counts so far.
    pub fn particle_counts(&self) -> ParticleCounts {
        ParticleCounts {
            particles: self.mpm.particles().len() as u64,
            particle_steps: self.particle_steps,
            created: self.totals.created,
            deposited: self.totals.deposited,
            absorbed: self.totals.absorbed,
        }
    }

    /// Time, s.
    pub fn time(&self) -> f64 {
        self.time
    }

    /// Steps taken.
    pub fn steps(&self) -> u64 {
        self.steps
    }

    /// Tangential FDM-grid cells of one layer normal to the split axis,
    /// x fastest, with the axis index left 0.
    fn face_cells(&self) -> Vec<[usize; 3]> {
        let g = self.fdm.level().geometry;
        let a = self.regions.axis;
        let mut out = Vec::new();
        for k in 0..if a == 2 { 1 } else { g.cells[2] } {
            for j in 0..if a == 1 { 1 } else { g.cells[1] } {
                for i in 0..if a == 0 { 1 } else { g.cells[0] } {
                    out.push([i, j, k]);
                }
            }
        }
        out
    }

    /// FDM-grid index along the split axis of FDM-region cell `i`.
    fn fdm_index(&self, i: usize) -> usize {
        i + self.fdm_offset
    }

    /// Volume of the cell `g` (FDM-grid or MPM-grid index: they share the
    /// tangential indices), m³: the box, or on an (r, z) grid the ring
    /// π(r₊² − r₋²)Δz the FDM's finite volumes use, = 2π r_c Δr Δz, the
    /// volume an MPM ring particle of that cross-section has at the cell
    /// centre.
    fn volume_at(&self, g: [usize; 3]) -> f64 {
        if !self.geometry.is_axisymmetric() {
            return self.regions.cell_volume();
        }
        let f = &self.regions.fdm;
        let r_lo = f.origin[0] + g[0] as f64 * f.spacing[0];
        self.geometry
            .cell_volume(r_lo, f.spacing[0], f.spacing[1], f.spacing[2])
    }

    /// Area of the interface face of the line through cell `g`, m²: the
    /// box face, or on an (r, z) grid (split along z) the annulus
    /// π(r₊² − r₋²).
    fn area_at(&self, g: [usize; 3]) -> f64 {
        if !self.geometry.is_axisymmetric() {
            return self.regions.face_area();
        }
        let f = &self.regions.fdm;
        let r_lo = f.origin[0] + g[0] as f64 * f.spacing[0];
        self.geometry.y_face_area(r_lo, f.spacing[0], f.spacing[2])
    }

    /// The factor by which the options' per-particle sizes (`existing_mass`,
    /// `existing_volume`) scale at the face of the line through `g`: 1, or
    /// on an (r, z) grid the radius of the face centre (the options are then
    /// per metre of radius).
    fn ring_scale(&self, g: [usize; 3]) -> f64 {
        if !self.geometry.is_axisymmetric() {
            return 1.0;
        }
        let f = &self.regions.fdm;
        f.origin[0] + (g[0] as f64 + 0.5) * f.spacing[0]
    }

    /// The fictitious cells, layer by layer (FDM-grid indices).
    fn fictitious_cells(&self) -> Vec<[usize; 3]> {
        let a = self.regions.axis;
        let n = self.regions.fdm.cells[a];
        let mut out = Vec::new();
        for l in 0..self.layers {
            let i = match self.regions.mpm_side {
                Side::High => n + l,
                Side::Low => self.layers - 1 - l,
            };
            for mut c in self.face_cells() {
                c[a] = i;
                out.push(c);
            }
        }
        out
    }

    /// Primitive state (ρ, v, p) and products mass fraction of an FDM cell.
    fn primitive(&self, g: [usize; 3]) -> (Primitive, f64) {
        let u = self.fdm.cell_conservative(g).unwrap_or([0.0; 6]);
        let rho = u[0];
        let e = specific_internal_energy(rho, u[1], u[2], u[3], u[4]);
        let y = if E::SPECIES { u[5] / rho } else { 0.0 };
        (
            Primitive {
                density: rho,
                velocity: [u[1] / rho, u[2] / rho, u[3] / rho],
                pressure: self.fdm.gas().gas_pressure(rho, e, y),
            },
            y,
        )
    }

    /// Step 1: Δt = min of the two CFL limits (the FDM's alone before
    /// activation).
    pub fn stable_dt(&self) -> Result<f64, SolverError> {
        let f = self.fdm.stable_dt()?;
        if !self.active {
            return Ok(f);
        }
        Ok(f.min(self.mpm.stable_dt()?))
    }

    /// Steps 2–6 and 9–13: the MPM step with the donor cells as particles
    /// (eqs 37–39), which are removed after it.
    pub fn mpm_step(&mut self, dt: f64) -> Result<(), SolverError> {
        let a = self.regions.axis;
        let donor = self.fdm_index(self.regions.donor_cell());
        let geometry = self.fdm.level().geometry;
        self.inits.clear();
        for f in 0..self.faces.len() {
            let mut c = self.faces[f];
            c[a] = donor;
            // Eqs 37–39 with V_c the cell's volume (its ring on an (r, z)
            // grid: the MPM's ring particle of the cell's cross-section).
            let volume = self.volume_at(c);
            let (s, _) = self.primitive(c);
            let centre = geometry.cell_centre(c);
            // One particle, or on an (r, z) grid `donor_rings` rings of
            // the cell's state at r_k = r₋ + (k + ½)Δr/n, V_k = 2π r_k
            // (Δr/n) Δz, which sum to the cell's ring volume exactly.
            let rings = if self.geometry.is_axisymmetric() {
                self.options.donor_rings.max(1)
            } else {
                1
            };
            for k in 0..rings {
                let (mut x, mut v) = (centre, volume);
                if rings > 1 {
                    let dr = geometry.spacing[0] / rings as f64;
                    x[0] = centre[0] - 0.5 * geometry.spacing[0] + (k as f64 + 0.5) * dr;
                    v = volume * x[0] / (centre[0] * rings as f64);
                }
                let cp = fdm_cell_as_particle(x, s.density, s.velocity, s.pressure, v);
                self.inits.push(ParticleInit {
                    position: cp.position,
                    velocity: cp.velocity,
                    mass: cp.mass,
                    volume: cp.volume,
                    stress: cp.stress,
                    specific_internal_energy: s.pressure / ((self.options.gamma - 1.0) * s.density),
                    material: self.options.air,
                    ..Default::default()
                });
            }
        }
        let first = self
            .mpm
            .insert_particles(&self.inits)
            .map_err(|e| SolverError::Other(format!("bridge donor particles: {e}")))?;
        self.donors = (first, self.inits.len() as u32);
        self.particle_steps += self.mpm.particles().len() as u64;
        // The donors give the interface nodes the FDM side's mass,
        // momentum and pressure force (eqs 37–39, steps 3 and 5 of §3.5)
        // and nothing else: the velocity update, the re-mapping of eq 26
        // and the strain increments of eqs 27–28 (steps 9–11) are the MPM
        // particles' alone, the donors' velocity being the FDM's. Re-mapped
        // with the rest, a donor carried the velocity its halo node (which
        // has no other mass) gave it under its one-sided pressure to the
        // interface node, and the first layer's particles expanded at rest
        // (docs/physics/couple/bridge.md, "At rest").
        self.mpm.set_load_only(self.donors.0, self.donors.1);
        let result = self.mpm.advance(dt);
        self.mpm.set_load_only(0, 0);
        if result.is_err() {
            self.remove_donors();
        }
        result
    }

    /// Whether the particle of identity `id` is one of this step's donor
    /// cells.
    fn is_donor(&self, id: u32) -> bool {
        id >= self.donors.0 && id - self.donors.0 < self.donors.1
    }

    /// Removes this step's donor particles (if the transport did not).
    fn remove_donors(&mut self) {
        if self.donors.1 == 0 {
            return;
        }
        self.leaving.clear();
        let ids = self.mpm.particle_ids();
        let (first, count) = self.donors;
        self.leaving
            .extend((0..ids.len()).filter(|&p| ids[p] >= first && ids[p] - first < count));
        self.mpm.remove_particles(&self.leaving);
        self.donors = (0, 0);
    }

    /// Step 7: the fictitious cells from the MPM nodes (eqs 31–32, with
    /// the momentum of the update, eq 22) and the internal energy of the
    /// particles in them (eq 33), eqs 34–36, where their MPM cell holds
    /// fluid particles away from a structure; from the fluid particles'
    /// own sums next to a structure; zero gradient where the MPM cell holds
    /// no material, a reflecting wall where it holds only structure
    /// ([`fictitious_source`], [`resolve_fictitious_line`]). Every
    /// fictitious cell gets a state, kept in `values` for the FDM step.
    pub fn update_fictitious_cells(&mut self) -> Result<(), SolverError> {
        let a = self.regions.axis;
        let mg = self.mpm.level().geometry;
        let nodes = self.mpm.grid_nodes();
        let active: Vec<usize> = (0..3).filter(|&d| mg.cells[d] > 1).collect();
        let weight = centre_weight(active.len());
        // The particle sums of the MPM cells of the fictitious layers and
        // of one layer either side (for `structure_near`), one slab of
        // `faces` cells per layer.
        let lines = self.faces.len();
        let first = self.fictitious_mpm_index(0);
        let last = self.fictitious_mpm_index(self.layers.max(1) - 1);
        let lo = first.min(last) - 1;
        let slabs = self.layers + 2;
        self.cells.clear();
        self.cells.resize(slabs * lines, CellParticles::default());
        let fluid = |m: MaterialId| m == self.options.air || Some(m) == self.options.products;
        let ps = self.mpm.particles();
        let window = mg.axis_window(a, lo, lo + slabs as isize - 1);
        for p in 0..ps.len() {
            if !window.admits(ps.position[p][a]) {
                continue;
            }
            let Some(c) = mg.cell_containing(ps.position[p]) else {
                continue;
            };
            let s = c[a] as isize - lo;
            if s < 0 || s >= slabs as isize {
                continue;
            }
            let k = s as usize * lines + self.line_of(c);
            let q = &mut self.cells[k];
            let m = ps.mass[p];
            if fluid(ps.material[p]) {
                // Eq 33, summed particle by particle.
                q.fluid_energy += m * ps.specific_internal_energy[p];
                q.fluid_mass += m;
                for d in 0..3 {
                    q.fluid_momentum[d] += m * ps.velocity[p][d];
                }
                if Some(ps.material[p]) == self.options.products {
                    q.products_mass += m;
                }
            } else {
                q.structure_mass += m;
                q.structure_momentum += m * ps.velocity[p][a];
            }
        }
        let axisymmetric = self.geometry.is_axisymmetric();
        let corners = 1usize << active.len();
        let mut mass = [0.0; 8];
        let mut mom = [[0.0; 3]; 8];
        let fg = self.fdm.level().geometry;
        self.sources.clear();
        for &g in &self.fictitious {
            let mut c = g;
            c[a] = (g[a] as isize + self.mpm_shift) as usize;
            let mut used = 0;
            for corner in 0..corners {
                let mut node = [c[0] as isize, c[1] as isize, c[2] as isize];
                for (bit, &d) in active.iter().enumerate() {
                    node[d] += ((corner >> bit) & 1) as isize;
                }
                if let Some(n) = nodes.lattice.index(node) {
                    let m = nodes.mass[n];
                    mass[used] = m;
                    mom[used] = nodes.velocity_new[n].map(|v| v * m);
                    used += 1;
                }
            }
            let nodal = fictitious_mass_momentum(&mass[..used], &mom[..used], weight);
            let s = (c[a] as isize - lo) as usize;
            let here = self.cells[s * lines + self.line_of(c)];
            // A structure particle in the cell or a neighbour: some corner
            // node carries structure mass.
            let mut near = false;
            for dk in -1isize..=1 {
                for dj in -1isize..=1 {
                    for di in -1isize..=1 {
                        let n = [c[0] as isize + di, c[1] as isize + dj, c[2] as isize + dk];
                        let ok = (0..3).all(|d| {
                            if d == a {
                                true
                            } else {
                                n[d] >= 0 && (n[d] as usize) < fg.cells[d]
                            }
                        });
                        if !ok {
                            continue;
                        }
                        let sn = (n[a] - lo) as usize;
                        let t = [n[0] as usize, n[1] as usize, n[2] as usize];
                        near |= self.cells[sn * lines + self.line_of(t)].structure_mass > 0.0;
                    }
                }
            }
            // On an (r, z) grid a node on the axis stands for a ring of
            // radius 0: eqs 31–32's interpolation of nodal masses, exact
            // for the linear hat at r_I > 0 (Σ_p N_I m_p = ρ 2π r_I Δr Δz),
            // over-weighs the cells of the first column (by 7/6 for a
            // uniform gas); their mass and momentum are the particles' own
            // sums (eq 33's), as next to a structure.
            let particle_sums = near || (axisymmetric && c[0] == 0);
            self.sources.push(fictitious_source(
                &here,
                particle_sums,
                nodal,
                self.volume_at(g),
            ));
        }
        // Per line normal to the interface: the layers from their sources
        // (`resolve_fictitious_line`), unless the FDM region's outflow
        // there is supersonic against them (`fdm_outflow_is_supersonic`):
        // then every fictitious layer takes the last FDM-region cell's
        // state (zero gradient, the FDM's own outflow face).
        let n = self.regions.fdm.cells[a];
        let sign = self.regions.mpm_side.sign();
        let layers = self.layers;
        self.values.clear();
        self.values.resize(self.fictitious.len(), [0.0; 6]);
        let mut inner = std::mem::take(&mut self.line_inner);
        let mut sources = std::mem::take(&mut self.line_sources);
        let mut out = std::mem::take(&mut self.line_out);
        inner.clear();
        inner.resize(layers.min(n), [0.0; 6]);
        sources.clear();
        sources.resize(layers, FictitiousSource::ZeroGradient);
        out.clear();
        out.resize(layers, [0.0; 6]);
        for line in 0..lines {
            for (j, u) in inner.iter_mut().enumerate() {
                let mut g = self.fictitious[line];
                g[a] = match self.regions.mpm_side {
                    Side::High => self.fdm_index(n - 1 - j),
                    Side::Low => self.fdm_index(j),
                };
                *u = self.fdm.cell_conservative(g).unwrap_or([0.0; 6]);
            }
            for (l, q) in sources.iter_mut().enumerate() {
                *q = self.sources[l * lines + line];
            }
            resolve_fictitious_line(&inner, &sources, a, &mut out);
            let normal = |u: &[f64; 6]| {
                let rho = u[0];
                let e = specific_internal_energy(rho, u[1], u[2], u[3], u[4]);
                let y = if E::SPECIES { u[5] / rho } else { 0.0 };
                let gas = self.fdm.gas();
                NormalState {
                    density: rho,
                    velocity: sign * u[1 + a] / rho,
                    pressure: gas.gas_pressure(rho, e, y),
                    sound_speed: gas.gas_sound_speed(rho, e, y),
                }
            };
            let supersonic = fdm_outflow_is_supersonic(&normal(&inner[0]), &normal(&out[0]));
            if supersonic {
                self.totals.supersonic_outflow += 1;
            }
            for (l, &state) in out.iter().enumerate() {
                let k = l * lines + line;
                self.values[k] = if supersonic { inner[0] } else { state };
                match self.sources[k] {
                    FictitiousSource::Mpm(_) => {}
                    FictitiousSource::ZeroGradient => self.totals.zero_gradient += 1,
                    FictitiousSource::Wall(_) => self.totals.wall += 1,
                }
            }
        }
        (self.line_inner, self.line_sources, self.line_out) = (inner, sources, out);
        self.set_fictitious_values()
    }

    /// Writes the fictitious cells' states of step 7 (`values`) into the
    /// FDM grid: before the FDM step, and again after it, so that the
    /// sweeps' own values there (which the bridge does not use) are never
    /// what the FDM's next start-of-step check and CFL limit see.
    fn set_fictitious_values(&mut self) -> Result<(), SolverError> {
        for (&g, &u) in self.fictitious.iter().zip(&self.values) {
            self.fdm
                .set_cell_conservative(g, u)
                .map_err(|e| SolverError::Other(e.to_string()))?;
        }
        Ok(())
    }

    /// MPM-grid index along the split axis of fictitious layer `l`.
    fn fictitious_mpm_index(&self, l: usize) -> isize {
        let lines = self.faces.len();
        let g = self.fictitious[l * lines];
        g[self.regions.axis] as isize + self.mpm_shift
    }

    /// Index in `faces` of the line through cell `c` (x fastest, the axis
    /// index ignored).
    fn line_of(&self, c: [usize; 3]) -> usize {
        let a = self.regions.axis;
        let g = self.fdm.level().geometry;
        let mut t = c;
        t[a] = 0;
        let mut n = g.cells;
        n[a] = 1;
        t[0] + n[0] * (t[1] + n[1] * t[2])
    }

    /// Step 14: at every interface face, the interface state and fluxes
    /// (eqs 40–44); the inflow deposited into the fluid particles of the
    /// face's first bridge cell (`CfdmpOptions::deposit`) or made into new
    /// particles (eqs 45–48); and the particles that crossed to the FDM
    /// side absorbed by the cell they entered (eqs 49–51). The particles
    /// that took a deposit are replaced by their new state, and the donor
    /// particles of the MPM step removed, in the same pass.
    pub fn transport(&mut self, dt: f64) -> Result<(), SolverError> {
        let a = self.regions.axis;
        let side = self.regions.mpm_side;
        let donor = self.fdm_index(self.regions.donor_cell());
        let bridge = self.fdm_index(self.regions.first_bridge_cell());
        let fg = self.fdm.level().geometry;
        let x_face = self.regions.interface();
        let active: [bool; 3] = std::array::from_fn(|d| fg.cells[d] > 1);
        self.created.clear();
        self.inits.clear();
        // Storage indices of the particles to take out (deposits, absorbed
        // particles, donors), gathered before any particle moves.
        self.leaving.clear();
        self.scan_particles(x_face);
        for f in 0..self.faces.len() {
            let c = self.faces[f];
            let (mut cd, mut cb) = (c, c);
            cd[a] = donor;
            cb[a] = bridge;
            let (sd, yd) = self.primitive(cd);
            let (sb, _) = self.primitive(cb);
            let face = interface_state(&sd, &sb);
            let (fm, fp) = interface_fluxes(&face, a, side, self.area_at(c), dt);
            if fm > 0.0 {
                let products = self.options.products.is_some() && yd >= 0.5;
                // The new particles' specific internal energy: eq 48 for
                // air, the donor's own for products.
                let e = if products {
                    let u = self.fdm.cell_conservative(cd).unwrap_or([0.0; 6]);
                    specific_internal_energy(u[0], u[1], u[2], u[3], u[4])
                } else {
                    self.totals.products_as_air += yd * fm;
                    sd.pressure / ((self.options.gamma - 1.0) * sd.density)
                };
                let v2: f64 = face.velocity.iter().map(|v| v * v).sum();
                let q = &mut self.pending[f];
                q.mass += fm;
                for (m, p) in q.momentum.iter_mut().zip(fp) {
                    *m += p;
                }
                q.energy += fm * (e + 0.5 * v2);
                if products {
                    q.products += fm;
                }
                q.length += (side.sign() * face.velocity[a] * dt).min(fg.spacing[a]);
            }
            let q = self.pending[f];
            if q.mass <= 0.0 {
                continue;
            }
            let material = match self.options.products {
                Some(m) if 2.0 * q.products >= q.mass => m,
                _ => self.options.air,
            };
            let y = if material == self.options.air {
                0.0
            } else {
                1.0
            };
            let scale = self.ring_scale(c);
            let existing_mass = (self.options.existing_mass * scale)
                .max(sd.density * self.options.existing_volume * scale);
            if self.options.deposit {
                // Into the particles of the same material in the face's
                // first bridge cell, by shares of their mass.
                let ps = self.mpm.particles();
                let list = &self.members[self.start[f]..self.start[f + 1]];
                let reach = 0.5 * fg.spacing[a];
                let takes = |p: usize| {
                    ps.material[p] == material && (ps.position[p][a] - x_face).abs() <= reach
                };
                let total: f64 = list
                    .iter()
                    .filter(|&&p| takes(p))
                    .map(|&p| ps.mass[p])
                    .sum();
                if total > 0.0 {
                    for &p in list.iter().filter(|&&p| takes(p)) {
                        let w = ps.mass[p] / total;
                        let (dm, dp, de) = (q.mass * w, q.momentum.map(|x| x * w), q.energy * w);
                        let d = deposit_into_particle(
                            Deposit {
                                mass: ps.mass[p],
                                velocity: ps.velocity[p],
                                specific_internal_energy: ps.specific_internal_energy[p],
                                volume: ps.volume[p],
                            },
                            dm,
                            dp,
                            de,
                            sd.density,
                        );
                        let pressure = self.fdm.gas().gas_pressure(
                            d.mass / d.volume,
                            d.specific_internal_energy,
                            y,
                        );
                        self.inits.push(ParticleInit {
                            position: ps.position[p],
                            velocity: d.velocity,
                            mass: d.mass,
                            volume: d.volume,
                            stress: [-pressure, -pressure, -pressure, 0.0, 0.0, 0.0],
                            temperature: ps.temperature[p],
                            specific_internal_energy: d.specific_internal_energy,
                            material,
                            ..Default::default()
                        });
                        self.leaving.push(p);
                        book_parts(&mut self.totals.into_mpm, dm, dp, de);
                        self.totals.deposited += 1;
                    }
                    self.pending[f] = Pending::default();
                    continue;
                }
            } else if q.mass < 4.0 * self.options.min_particle_mass * existing_mass {
                continue;
            }
            // The face's inflow so far as one batch: its mean velocity and
            // the specific internal energy that keeps its total energy
            // (eq 48's, plus the kinetic energy the mean velocity drops).
            let v = q.momentum.map(|p| p / q.mass);
            let vn = side.sign() * v[a];
            if !(vn > 0.0) {
                continue;
            }
            let e = q.energy / q.mass - 0.5 * v.iter().map(|x| x * x).sum::<f64>();
            let mut centre = fg.cell_centre(c);
            centre[a] = x_face;
            let inflow = FaceInflow {
                face_centre: centre,
                spacing: fg.spacing,
                active,
                axis: a,
                side,
                face: Primitive {
                    velocity: v,
                    ..face
                },
                donor: sd,
                axisymmetric: self.geometry.is_axisymmetric(),
                gamma: self.options.gamma,
                existing_mass,
                // Eq 47 over the length the batch filled, the tangential
                // drift kept within a quarter cell (inside the face's
                // cell).
                dt: (0..3)
                    .filter(|&d| d != a && active[d] && v[d] != 0.0)
                    .fold(q.length.min(fg.spacing[a]) / vn, |t, d| {
                        t.min(0.25 * fg.spacing[d] / v[d].abs())
                    }),
            };
            let start = self.created.len();
            create_particles(&inflow, q.mass, &mut self.created);
            let p = self.fdm.gas().gas_pressure(sd.density, e, y);
            for n in &mut self.created[start..] {
                n.specific_internal_energy = e;
                self.inits.push(ParticleInit {
                    position: n.position,
                    velocity: n.velocity,
                    mass: n.mass,
                    volume: n.volume,
                    stress: [-p, -p, -p, 0.0, 0.0, 0.0],
                    specific_internal_energy: e,
                    material,
                    ..Default::default()
                });
                book(&mut self.totals.into_mpm, n.mass, n.velocity, e);
            }
            self.pending[f] = Pending::default();
        }
        self.totals.created += self.created.len() as u64;
        // Absorption: particles on the FDM side of the interface (the
        // donor particles excepted), found by `scan_particles`, into the
        // donor cell of their line (eqs 49–51 with that cell's volume, its
        // ring on an (r, z) grid).
        let ps = self.mpm.particles();
        for &p in &self.outside {
            let (m, v, e) = (ps.mass[p], ps.velocity[p], ps.specific_internal_energy[p]);
            let is_products = Some(ps.material[p]) == self.options.products;
            let Some(mut g) = fg.cell_containing(ps.position[p]) else {
                return Err(SolverError::Other(format!(
                    "bridge: particle at {:?} m left the MPM region outside the FDM grid",
                    ps.position[p]
                )));
            };
            g[a] = donor;
            let volume = self.volume_at(g);
            let mut u = self.fdm.cell_conservative(g).unwrap_or([0.0; 6]);
            absorb_particle(&mut u, volume, m, v, e);
            if is_products {
                u[5] += m / volume;
            }
            self.fdm
                .set_cell_conservative(g, u)
                .map_err(|e| SolverError::Other(e.to_string()))?;
            book(&mut self.totals.into_fdm, m, v, e);
        }
        self.totals.absorbed += self.outside.len() as u64;
        // One removal: the deposits' old states, the absorbed particles and
        // this step's donors; then one insertion of the new states and the
        // created particles.
        self.leaving.extend_from_slice(&self.outside);
        self.leaving.extend_from_slice(&self.donor_slots);
        self.leaving.sort_unstable();
        self.mpm.remove_particles(&self.leaving);
        self.donors = (0, 0);
        self.mpm
            .insert_particles(&self.inits)
            .map_err(|e| SolverError::Other(format!("bridge inflow particles: {e}")))?;
        Ok(())
    }

    /// One pass over the particles before the transport changes any:
    /// the donor particles (`donor_slots`), the particles on the FDM side
    /// of the interface `x_face` (`outside`, to be absorbed) and, with
    /// `deposit`, per face the fluid particles of its first bridge cell
    /// (`members[start[f]..start[f + 1]]`), all as ascending storage
    /// indices.
    fn scan_particles(&mut self, x_face: f64) {
        let a = self.regions.axis;
        let side = self.regions.mpm_side;
        let mg = self.mpm.level().geometry;
        let fg = self.fdm.level().geometry;
        let bridge = self.fdm_index(self.regions.first_bridge_cell()) as isize + self.mpm_shift;
        let deposit = self.options.deposit;
        let ps = self.mpm.particles();
        let ids = self.mpm.particle_ids();
        self.outside.clear();
        self.donor_slots.clear();
        self.pairs.clear();
        let window = mg.axis_window(a, bridge, bridge);
        for (p, &id) in ids.iter().enumerate() {
            if self.is_donor(id) {
                self.donor_slots.push(p);
                continue;
            }
            let x = ps.position[p];
            let out = match side {
                Side::High => x[a] < x_face,
                Side::Low => x[a] > x_face,
            };
            if out {
                self.outside.push(p);
                continue;
            }
            if !deposit
                || !(ps.material[p] == self.options.air
                    || Some(ps.material[p]) == self.options.products)
                || !window.admits(x[a])
            {
                continue;
            }
            let Some(c) = mg.cell_containing(x) else {
                continue;
            };
            if c[a] as isize != bridge {
                continue;
            }
            // The face's index in `faces` (x fastest, the axis index 0).
            let mut t = c;
            t[a] = 0;
            let mut n = fg.cells;
            n[a] = 1;
            self.pairs.push((t[0] + n[0] * (t[1] + n[1] * t[2]), p));
        }
        // Group by face, storage order kept within a face.
        self.pairs.sort_by_key(|&(f, _)| f);
        let faces = self.faces.len();
        self.start.clear();
        self.start.resize(faces + 1, 0);
        self.members.clear();
        for &(f, p) in &self.pairs {
            self.start[f + 1] += 1;
            self.members.push(p);
        }
        for f in 0..faces {
            self.start[f + 1] += self.start[f];
        }
    }

    /// Whether an FDM cell within `activation_cells` of the interface
    /// (donor side) has reached the activation pressure.
    fn shock_near_interface(&self) -> bool {
        let a = self.regions.axis;
        let donor = self.regions.donor_cell() as isize;
        let step: isize = match self.regions.mpm_side {
            Side::High => -1,
            Side::Low => 1,
        };
        let n = self.regions.fdm.cells[a] as isize;
        for k in 0..self.options.activation_cells.max(1) as isize {
            let i = donor + step * k;
            if i < 0 || i >= n {
                break;
            }
            for &c in &self.faces {
                let mut c = c;
                c[a] = self.fdm_index(i as usize);
                if self.primitive(c).0.pressure >= self.options.activation_pressure {
                    return true;
                }
            }
        }
        false
    }

    /// Resets the fictitious cells to their initial state (before
    /// activation).
    fn hold_fictitious_cells(&mut self) -> Result<(), SolverError> {
        for (&g, &u) in self.fictitious.iter().zip(&self.fictitious_initial) {
            self.fdm
                .set_cell_conservative(g, u)
                .map_err(|e| SolverError::Other(e.to_string()))?;
        }
        Ok(())
    }

    /// One coupled step of Δt = `dt` (module doc).
    pub fn advance(&mut self, dt: f64) -> Result<(), SolverError> {
        if !self.active {
            self.hold_fictitious_cells()?;
            let t = Instant::now();
            self.fdm.advance(dt)?;
            self.fdm_seconds += t.elapsed().as_secs_f64();
            self.time += dt;
            self.steps += 1;
            if self.shock_near_interface() {
                self.active = true;
                self.activated_at = Some(self.time);
            }
            return Ok(());
        }
        let t = Instant::now();
        self.mpm_step(dt)?;
        self.update_fictitious_cells()?;
        let t1 = Instant::now();
        self.mpm_seconds += (t1 - t).as_secs_f64();
        self.fdm.advance(dt)?;
        self.set_fictitious_values()?;
        let t2 = Instant::now();
        self.fdm_seconds += (t2 - t1).as_secs_f64();
        self.transport(dt)?;
        self.mpm_seconds += t2.elapsed().as_secs_f64();
        self.time += dt;
        self.steps += 1;
        Ok(())
    }
}

/// The file [`Cfdmp`]'s end-of-run hook writes into the output directory:
/// the FDM/MPM split of the wall time ([`time_split_json`]).
pub const TIME_SPLIT_FILE: &str = "time_split.json";

/// The FDM/MPM split as a JSON object: `fdm_seconds` and `mpm_seconds`
/// ([`Cfdmp::split_seconds`]), the `steps` taken, the time the MPM
/// region started (`activated_at`, s, `null` if it never did), and the
/// particle counts of [`ParticleCounts`].
pub fn time_split_json(
    (fdm_seconds, mpm_seconds): (f64, f64),
    steps: u64,
    activated_at: Option<f64>,
    counts: ParticleCounts,
) -> String {
    let num = |x: f64| {
        if x.is_finite() {
            format!("{x:?}")
        } else {
            "null".into()
        }
    };
    format!(
        "{{\n  \"fdm_seconds\": {},\n  \"mpm_seconds\": {},\n  \"steps\": {steps},\n  \"activated_at\": {},\n  \"particles\": {},\n  \"particle_steps\": {},\n  \"created\": {},\n  \"deposited\": {},\n  \"absorbed\": {}\n}}\n",
        num(fdm_seconds),
        num(mpm_seconds),
        activated_at.map_or_else(|| "null".into(), num),
        counts.particles,
        counts.particle_steps,
        counts.created,
        counts.deposited,
        counts.absorbed,
    )
}

/// The particle counts of a run, for [`time_split_json`].
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct ParticleCounts {
    /// MPM particles at the end.
    pub particles: u64,
    /// Σ over the MPM steps of the particles stepped (donors included).
    pub particle_steps: u64,
    /// Particles created by the inflow.
    pub created: u64,
    /// Deposits of inflow into existing particles.
    pub deposited: u64,
    /// Particles absorbed by the FDM.
    pub absorbed: u64,
}

/// Cell fields of the coupled solver: those both methods give.
pub const FIELDS: [&str; 6] = [
    "density",
    "velocity_x",
    "velocity_y",
    "velocity_z",
    "pressure",
    "specific_internal_energy",
];

/// What a checkpoint holds besides the two solvers' own states.
#[derive(serde::Serialize, serde::Deserialize)]
struct SavedState {
    time: f64,
    steps: u64,
    active: bool,
    activated_at: Option<f64>,
    totals: [ConservationTotals; 2],
    /// created, absorbed, supersonic_outflow, deposited, zero_gradient,
    /// wall, and the particle-steps so far.
    counts: [u64; 7],
    products_as_air: f64,
    pending: Vec<Pending>,
    fdm: Vec<u8>,
    mpm: Vec<u8>,
}

impl<E: GasLaw> Cfdmp<E> {
    /// The union of the two regions.
    pub fn domain(&self) -> brisance_core::UniformGridGeometry {
        let (f, m, a) = (self.regions.fdm, self.regions.mpm, self.regions.axis);
        let mut g = f;
        g.origin[a] = f.origin[a].min(m.origin[a]);
        g.cells[a] = f.cells[a] + m.cells[a] - self.regions.width;
        g
    }

    /// The MPM's cell value of `fields` in the cell containing `point`:
    /// `MpmSolver`'s `sample` (the mass-weighted mean over the cell's
    /// particles: density m/V, velocity, the material's pressure
    /// −tr σ/3 − q, specific internal energy; 0 in an empty cell), for the
    /// fields the bridge outputs ([`FIELDS`]).
    fn sample_mpm(
        &self,
        point: [f64; 3],
        fields: &[String],
        out: &mut Vec<f64>,
    ) -> Result<(), SolverError> {
        if let Some(f) = fields.iter().find(|f| !FIELDS.contains(&f.as_str())) {
            return Err(SolverError::Other(format!(
                "unknown field `{f}`; the bridge outputs {}",
                FIELDS.join(", ")
            )));
        }
        self.mpm.sample(point, fields, out)
    }

    /// Whether the MPM gives the output at `x`: `x` lies in the MPM region
    /// and the MPM region runs, or, before activation, `x` lies past the
    /// FDM grid (its fictitious cells), where the MPM's initial state is
    /// the only state there is.
    fn in_mpm(&self, x: [f64; 3]) -> bool {
        let a = self.regions.axis;
        let (lo, hi) = (self.regions.mpm.origin[a], self.regions.mpm.upper()[a]);
        let inside = x[a] >= lo && x[a] <= hi;
        inside && (self.active || self.fdm.level().geometry.cell_containing(x).is_none())
    }

    /// Whether FDM-grid cell index `i` along the split axis lies in the FDM
    /// region outside the MPM region (the donor cell and before).
    /// What left through the domain faces of the FDM cells the bridge
    /// owns ([`Cfdmp::fdm_owns`]); the fictitious cells' faces are the MPM
    /// region's, which counts its own.
    fn owned_fdm_outflow(&self) -> ConservationTotals {
        let a = self.regions.axis;
        self.fdm.outflow_where(|_, cell| self.fdm_owns(cell[a]))
    }

    fn fdm_owns(&self, i: usize) -> bool {
        let donor = self.fdm_index(self.regions.donor_cell());
        match self.regions.mpm_side {
            Side::High => i <= donor,
            Side::Low => {
                i >= donor && i < self.fdm_index(self.regions.fdm.cells[self.regions.axis])
            }
        }
    }
}

impl<E: GasLaw> Solver for Cfdmp<E> {
    fn name(&self) -> &str {
        "fdm-mpm"
    }

    /// The FDM's outflow through the faces of the cells it owns and the
    /// particles that left the MPM grid: the open-boundary parts of
    /// [`Solver::conservation_totals`].
    fn outflow_totals(&self) -> Option<ConservationTotals> {
        let mut t = self.owned_fdm_outflow();
        let m = self.mpm.outflow_totals();
        book_parts(&mut t, m.mass, m.momentum, m.energy);
        Some(t)
    }

    /// The FDM's positivity limiter.
    fn safeguards(&self) -> Vec<brisance_core::SafeguardUse> {
        self.fdm.safeguards()
    }

    /// [`Cfdmp::split_seconds`] as the parts `fdm` and `mpm`.
    fn wall_split(&self) -> Vec<(&'static str, f64)> {
        let (fdm, mpm) = self.split_seconds();
        vec![("fdm", fdm), ("mpm", mpm)]
    }

    fn time(&self) -> f64 {
        self.time
    }

    fn stable_dt(&self) -> Result<f64, SolverError> {
        Cfdmp::stable_dt(self)
    }

    fn advance(&mut self, dt: f64) -> Result<(), SolverError> {
        Cfdmp::advance(self, dt)
    }

    /// The FDM cells outside the MPM region plus the MPM particles (with
    /// their outflow), summed in global order.
    fn conservation_totals(&self) -> ConservationTotals {
        let g = self.fdm.level().geometry;
        let a = self.regions.axis;
        let fields = self.fdm.conservative_fields();
        let axisymmetric = self.geometry.is_axisymmetric();
        let mut t = ConservationTotals::default();
        let rows = fields[0]
            .iter()
            .zip(&fields[1])
            .zip(&fields[2])
            .zip(&fields[3])
            .zip(&fields[4]);
        for (lin, ((((rho, mx), my), mz), e)) in rows.enumerate() {
            let idx = [
                lin % g.cells[0],
                (lin / g.cells[0]) % g.cells[1],
                lin / (g.cells[0] * g.cells[1]),
            ];
            if self.fdm_owns(idx[a]) {
                // The box's volume once at the end; a ring's per cell.
                let v = if axisymmetric {
                    self.volume_at(idx)
                } else {
                    1.0
                };
                t.mass += rho * v;
                t.momentum[0] += mx * v;
                t.momentum[1] += my * v;
                t.momentum[2] += mz * v;
                t.energy += e * v;
            }
        }
        let v = if axisymmetric {
            1.0
        } else {
            self.regions.cell_volume()
        };
        let m = self.mpm.conservation_totals();
        t.mass = t.mass * v + m.mass;
        for d in 0..3 {
            t.momentum[d] = t.momentum[d] * v + m.momentum[d];
        }
        t.energy = t.energy * v + m.energy;
        let o = self.owned_fdm_outflow();
        book_parts(&mut t, o.mass, o.momentum, o.energy);
        // The inflow in transit (`Pending`).
        for q in &self.pending {
            t.mass += q.mass;
            for d in 0..3 {
                t.momentum[d] += q.momentum[d];
            }
            t.energy += q.energy;
        }
        t
    }

    fn cell_field_names(&self) -> Vec<&'static str> {
        FIELDS.to_vec()
    }

    /// On the union of the regions: the MPM's cell values in the MPM region
    /// once it runs (before, past the FDM grid), the FDM's elsewhere.
    fn cell_data(&self, fields: &[String]) -> Result<brisance_core::CellData, SolverError> {
        if let Some(f) = fields.iter().find(|f| !FIELDS.contains(&f.as_str())) {
            return Err(SolverError::Other(format!(
                "unknown field `{f}`; the bridge outputs {}",
                FIELDS.join(", ")
            )));
        }
        let g = self.domain();
        let fd = self.fdm.cell_data(fields)?;
        let md = self.mpm.cell_data(fields)?;
        let mut out: Vec<(String, Vec<f64>)> = fields
            .iter()
            .map(|f| (f.clone(), Vec::with_capacity(g.cell_count())))
            .collect();
        for k in 0..g.cells[2] {
            for j in 0..g.cells[1] {
                for i in 0..g.cells[0] {
                    let x = g.cell_centre([i, j, k]);
                    let (data, geometry) = if self.in_mpm(x) {
                        (&md, md.geometry)
                    } else {
                        (&fd, fd.geometry)
                    };
                    let c = geometry.cell_containing(x).unwrap_or([0; 3]);
                    let n = geometry.linear_index(c);
                    for (o, (_, v)) in out.iter_mut().zip(&data.fields) {
                        o.1.push(v[n]);
                    }
                }
            }
        }
        Ok(brisance_core::CellData {
            geometry: g,
            fields: out,
        })
    }

    fn sample(
        &self,
        point: [f64; 3],
        fields: &[String],
        out: &mut Vec<f64>,
    ) -> Result<(), SolverError> {
        if self.in_mpm(point) {
            self.sample_mpm(point, fields, out)
        } else {
            self.fdm.sample(point, fields, out)
        }
    }

    fn particle_data(&self) -> Option<brisance_core::ParticleData> {
        self.mpm.particle_data()
    }

    /// Writes [`TIME_SPLIT_FILE`], the FDM/MPM split of the run's wall
    /// time.
    fn finish(&mut self, out_dir: &std::path::Path) -> Result<(), SolverError> {
        let path = out_dir.join(TIME_SPLIT_FILE);
        let text = time_split_json(
            self.split_seconds(),
            self.steps,
            self.activated_at,
            self.particle_counts(),
        );
        std::fs::write(&path, text)
            .map_err(|e| SolverError::Other(format!("cannot write {}: {e}", path.display())))
    }

    fn work_per_step(&self) -> (f64, &'static str) {
        let cells = self.fdm.level().geometry.cell_count() as f64;
        let particles = if self.active {
            self.mpm.particles().len() as f64
        } else {
            0.0
        };
        (cells + particles, "cell- and particle-updates")
    }

    fn save_state(&self) -> Result<Vec<u8>, SolverError> {
        let t = self.totals;
        let saved = SavedState {
            time: self.time,
            steps: self.steps,
            active: self.active,
            activated_at: self.activated_at,
            totals: [t.into_mpm, t.into_fdm],
            counts: [
                t.created,
                t.absorbed,
                t.supersonic_outflow,
                t.deposited,
                t.zero_gradient,
                t.wall,
                self.particle_steps,
            ],
            products_as_air: t.products_as_air,
            pending: self.pending.clone(),
            fdm: self.fdm.save_state()?,
            mpm: self.mpm.save_state()?,
        };
        bincode::serialize(&saved).map_err(|e| SolverError::Checkpoint(e.to_string()))
    }

    fn restore_state(&mut self, bytes: &[u8]) -> Result<(), SolverError> {
        let s: SavedState =
            bincode::deserialize(bytes).map_err(|e| SolverError::Checkpoint(e.to_string()))?;
        self.fdm.restore_state(&s.fdm)?;
        self.mpm.restore_state(&s.mpm)?;
        if s.pending.len() != self.pending.len() {
            return Err(SolverError::Checkpoint(format!(
                "the checkpoint has {} interface faces, this bridge {}",
                s.pending.len(),
                self.pending.len()
            )));
        }
        self.pending = s.pending;
        self.time = s.time;
        self.steps = s.steps;
        self.active = s.active;
        self.activated_at = s.activated_at;
        self.totals = TransportTotals {
            created: s.counts[0],
            into_mpm: s.totals[0],
            absorbed: s.counts[1],
            into_fdm: s.totals[1],
            products_as_air: s.products_as_air,
            supersonic_outflow: s.counts[2],
            deposited: s.counts[3],
            zero_gradient: s.counts[4],
            wall: s.counts[5],
        };
        self.particle_steps = s.counts[6];
        Ok(())
    }
}

fn book_parts(t: &mut ConservationTotals, m: f64, p: [f64; 3], energy: f64) {
    t.mass += m;
    for (q, x) in t.momentum.iter_mut().zip(p) {
        *q += x;
    }
    t.energy += energy;
}

fn book(t: &mut ConservationTotals, m: f64, v: [f64; 3], e: f64) {
    t.mass += m;
    for (q, x) in t.momentum.iter_mut().zip(v) {
        *q += m * x;
    }
    t.energy += m * (e + 0.5 * (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]));
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::regions::RegionBox;
    use brisance_constitutive::{MaterialModel, NullMaterial};
    use brisance_core::Eos;
    use brisance_eos::IdealGas;
    use brisance_fdm::sweep::GHOST;
    use brisance_fdm::{FdmBoundary, FdmOptions, PrimitiveState};
    use brisance_grid::Level;
    use brisance_mpm::{BulkViscosity, GridBoundary, MpmOptions, Particles};

    const H: f64 = 0.002;
    const P0: f64 = 1.0e5;
    const RHO0: f64 = 1.225;

    /// Shock-tube initial state: 5 bar, 4.9 kg/m³ for x < 0.1 m.
    fn initial(x: [f64; 3]) -> PrimitiveState {
        let (density, pressure) = if x[0] < 0.1 { (4.9, 5.0e5) } else { (RHO0, P0) };
        PrimitiveState {
            density,
            velocity: [0.0; 3],
            pressure,
        }
    }

    /// The tube on an FDM grid: a wall at x = 0, `x_high` at the other end.
    fn fdm_on(
        lower: [f64; 3],
        upper: [f64; 3],
        cells: [usize; 3],
        x_high: FdmBoundary,
    ) -> FdmSolver<IdealGas> {
        let level = Level::new(lower, upper, cells, [1, 1, 1], GHOST).unwrap();
        let mut bcs = [FdmBoundary::Outflow; 6];
        bcs[0] = FdmBoundary::Reflective;
        bcs[1] = x_high;
        FdmSolver::new(IdealGas::air(), level, bcs, FdmOptions::default(), initial).unwrap()
    }

    /// The coupled 1D tube: FDM (0, 0.3) m, MPM (0.29, 0.4) m, w = 5.
    fn coupled() -> Cfdmp<IdealGas> {
        coupled_with(0.25)
    }

    /// [`coupled`] with the given `min_particle_mass`.
    fn coupled_with(min_particle_mass: f64) -> Cfdmp<IdealGas> {
        coupled_inflow(min_particle_mass, false)
    }

    /// [`coupled`] with the given inflow rule.
    fn coupled_inflow(min_particle_mass: f64, deposit: bool) -> Cfdmp<IdealGas> {
        coupled_of(min_particle_mass, deposit, 1)
    }

    /// [`coupled_inflow`] with `materials` MPM materials, air the first.
    fn coupled_of(min_particle_mass: f64, deposit: bool, materials: usize) -> Cfdmp<IdealGas> {
        let regions = BridgeRegions::from_boxes(
            RegionBox {
                lower: [0.0; 3],
                upper: [0.3, H, H],
            },
            RegionBox {
                lower: [0.29, 0.0, 0.0],
                upper: [0.4, H, H],
            },
            [H; 3],
            GHOST,
        )
        .unwrap();
        let (fg, _) = regions.fdm_grid(GHOST);
        let fdm = fdm_on(fg.origin, fg.upper(), fg.cells, FdmBoundary::Outflow);
        let (mg, _) = regions.mpm_grid();
        let first = regions.mpm.origin[0];
        let mpm = mpm_tube_of(
            mg,
            first,
            regions.mpm.upper()[0],
            GridBoundary::Outflow,
            materials,
        );
        let m = RHO0 * H * H * H / 2.0;
        let air = IdealGas::air();
        Cfdmp::new(
            regions,
            fdm,
            mpm,
            GHOST,
            CfdmpOptions {
                air: MaterialId(0),
                products: None,
                gamma: air.gamma,
                existing_mass: m,
                activation_pressure: 1.05 * P0,
                activation_cells: 3,
                min_particle_mass,
                existing_volume: 0.0,
                deposit,
                donor_rings: 1,
            },
        )
        .unwrap()
    }

    /// Air particles (2 per cell) of the tube state between `from` and `to`
    /// on the grid `g`, with `x_low` at the low end and a slip wall at the
    /// high end.
    fn mpm_tube(
        g: brisance_core::UniformGridGeometry,
        from: f64,
        to: f64,
        x_low: GridBoundary,
    ) -> MpmSolver {
        mpm_tube_of(g, from, to, x_low, 1)
    }

    /// [`mpm_tube`] with `materials` copies of the air model (material 0
    /// the particles').
    fn mpm_tube_of(
        g: brisance_core::UniformGridGeometry,
        from: f64,
        to: f64,
        x_low: GridBoundary,
        materials: usize,
    ) -> MpmSolver {
        let level = Level::new(g.origin, g.upper(), g.cells, [1, 1, 1], 0).unwrap();
        let air = IdealGas::air();
        let mut ps = Particles::new(0);
        let ppc = 2;
        let cells = ((to - from) / H).round() as usize;
        for c in 0..cells {
            for s in 0..ppc {
                let x = from + (c as f64 + (s as f64 + 0.5) / ppc as f64) * H;
                let st = initial([x, 0.0, 0.0]);
                let (rho, p) = (st.density, st.pressure);
                let v = H * H * H / ppc as f64;
                ps.push(
                    &ParticleInit {
                        position: [x, 0.5 * H, 0.5 * H],
                        mass: rho * v,
                        volume: v,
                        stress: [-p, -p, -p, 0.0, 0.0, 0.0],
                        specific_internal_energy: air.specific_internal_energy(rho, p).unwrap(),
                        ..Default::default()
                    },
                    &[],
                )
                .unwrap();
            }
        }
        MpmSolver::new(
            level,
            vec![MaterialModel::Null(NullMaterial::air()); materials],
            ps,
            MpmOptions {
                boundaries: [
                    x_low,
                    GridBoundary::Symmetry,
                    GridBoundary::Free,
                    GridBoundary::Free,
                    GridBoundary::Free,
                    GridBoundary::Free,
                ],
                bulk_viscosity: Some(BulkViscosity::default()),
                ..Default::default()
            },
        )
        .unwrap()
    }

    fn sample(s: &impl Solver, x: f64) -> f64 {
        let mut out = Vec::new();
        s.sample([x, 0.5 * H, 0.5 * H], &["pressure".to_string()], &mut out)
            .unwrap();
        out[0]
    }

    /// (arrival time at half the jump, peak) of a pressure history.
    fn arrival_and_peak(t: &[f64], p: &[f64]) -> (f64, f64) {
        let peak = p.iter().cloned().fold(f64::MIN, f64::max);
        let half = P0 + 0.5 * (peak - P0);
        let i = p.iter().position(|&x| x >= half).unwrap();
        let f = (half - p[i - 1]) / (p[i] - p[i - 1]);
        (t[i - 1] + f * (t[i] - t[i - 1]), peak)
    }

    /// After one MPM step of the tube, the storage indices of the
    /// particles in the MPM cell of fictitious layer `l`, and the FDM cell
    /// and MPM cell index of each layer.
    fn layer_cells(c: &Cfdmp<IdealGas>) -> Vec<([usize; 3], usize)> {
        (0..c.layers)
            .map(|l| {
                let g = c.fictitious[l];
                (g, (g[0] as isize + c.mpm_shift) as usize)
            })
            .collect()
    }

    fn particles_in(c: &Cfdmp<IdealGas>, cell: usize) -> Vec<usize> {
        let mg = c.mpm.level().geometry;
        let ps = c.mpm.particles();
        (0..ps.len())
            .filter(|&p| mg.cell_containing(ps.position[p]).map(|q| q[0]) == Some(cell))
            .collect()
    }

    /// Eqs 31–36 by hand for the 1D tube's MPM cell `cell`: the two corner
    /// nodes (N = ½) and the particles in the cell.
    fn eqs_31_36(c: &Cfdmp<IdealGas>, cell: usize) -> [f64; 5] {
        let nodes = c.mpm.grid_nodes();
        let (mut m, mut p) = ([0.0; 2], [[0.0; 3]; 2]);
        for k in 0..2 {
            let n = nodes.lattice.index([(cell + k) as isize, 0, 0]).unwrap();
            m[k] = nodes.mass[n];
            p[k] = nodes.velocity_new[n].map(|v| v * m[k]);
        }
        let (mc, pc) = fictitious_mass_momentum(&m, &p, 0.5);
        let ps = c.mpm.particles();
        let mut e = 0.0;
        for q in particles_in(c, cell) {
            e += ps.mass[q] * ps.specific_internal_energy[q];
        }
        crate::bridge::fictitious_cell_state(mc, pc, e, H * H * H).unwrap()
    }

    fn conservative5(c: &Cfdmp<IdealGas>, g: [usize; 3]) -> [f64; 5] {
        let u = c.fdm.cell_conservative(g).unwrap();
        [u[0], u[1], u[2], u[3], u[4]]
    }

    #[test]
    fn an_empty_mpm_cell_gives_its_fictitious_cell_the_state_inside_it() {
        let mut c = coupled();
        let dt = c.mpm.stable_dt().unwrap().min(c.fdm.stable_dt().unwrap());
        c.mpm_step(dt).unwrap();
        let cells = layer_cells(&c);
        // Empty the MPM cell of layer 2 (the gas has left it).
        let gone = particles_in(&c, cells[2].1);
        assert_eq!(gone.len(), 2);
        c.mpm.remove_particles(&gone);
        // What the FDM sweep left there is not kept.
        c.fdm
            .set_cell_conservative(cells[2].0, [1.0, 0.0, 0.0, 0.0, -5.0, 0.0])
            .unwrap();
        c.update_fictitious_cells().unwrap();
        // Full cells: eqs 31–36 exactly, as before.
        for l in [0, 1, 3] {
            assert_eq!(
                conservative5(&c, cells[l].0),
                eqs_31_36(&c, cells[l].1),
                "layer {l}"
            );
        }
        // The empty one: layer 1's state (zero gradient), bit for bit.
        assert_eq!(conservative5(&c, cells[2].0), conservative5(&c, cells[1].0));
        let t = c.transport_totals();
        assert_eq!((t.zero_gradient, t.wall, t.supersonic_outflow), (1, 0, 0));
        // The FDM step leaves the fictitious cells as step 7 set them.
        c.active = true;
        let set: Vec<_> = cells.iter().map(|&(g, _)| conservative5(&c, g)).collect();
        c.fdm.advance(dt).unwrap();
        assert_ne!(conservative5(&c, cells[3].0), set[3]);
        c.set_fictitious_values().unwrap();
        for (l, &(g, _)) in cells.iter().enumerate() {
            assert_eq!(conservative5(&c, g), set[l], "layer {l}");
        }
    }

    #[test]
    fn a_structure_in_the_fictitious_layers_is_a_reflecting_wall() {
        let mut c = coupled_of(0.25, false, 2);
        let dt = c.mpm.stable_dt().unwrap().min(c.fdm.stable_dt().unwrap());
        c.mpm_step(dt).unwrap();
        let cells = layer_cells(&c);
        // Layer 2's MPM cell: its air replaced by one particle of
        // material 1 (a structure) moving at 3 m/s.
        let gone = particles_in(&c, cells[2].1);
        c.mpm.remove_particles(&gone);
        let mg = c.mpm.level().geometry;
        let x = mg.cell_centre([cells[2].1, 0, 0]);
        c.mpm
            .insert_particles(&[ParticleInit {
                position: x,
                velocity: [3.0, 0.0, 0.0],
                mass: 1.0e-3,
                volume: H * H * H,
                material: MaterialId(1),
                ..Default::default()
            }])
            .unwrap();
        c.update_fictitious_cells().unwrap();
        let u = |l: usize| conservative5(&c, cells[l].0);
        // Layer 0: no structure in its neighbours, eqs 31–36.
        assert_eq!(u(0), eqs_31_36(&c, cells[0].1));
        // Layer 1: next to the structure, the air particles' own sums.
        let ps = c.mpm.particles();
        let (mut m, mut p, mut e) = (0.0, [0.0; 3], 0.0);
        for q in particles_in(&c, cells[1].1) {
            e += ps.mass[q] * ps.specific_internal_energy[q];
            m += ps.mass[q];
            for (pd, v) in p.iter_mut().zip(ps.velocity[q]) {
                *pd += ps.mass[q] * v;
            }
        }
        let own = crate::bridge::fictitious_cell_state(m, p, e, H * H * H).unwrap();
        assert_eq!(u(1), own);
        // Layers 2 and 3: the mirror images of layers 1 and 0 in a wall
        // moving at 3 m/s.
        let mirror = |v: [f64; 5]| {
            let w = crate::bridge::mirror_state([v[0], v[1], v[2], v[3], v[4], 0.0], 0, 3.0);
            [w[0], w[1], w[2], w[3], w[4]]
        };
        assert_eq!(u(2), mirror(u(1)));
        assert_eq!(u(3), mirror(u(0)));
        let t = c.transport_totals();
        assert_eq!((t.zero_gradient, t.wall), (0, 1));
    }

    #[test]
    fn before_activation_the_mpm_region_past_the_fdm_grid_reads_the_mpm() {
        let c = coupled();
        assert!(!c.is_active());
        // x = 0.35 m: in the MPM region, past the fictitious cells (0.308
        // m), where the FDM grid has no cell. The MPM's air particles
        // start at p = P0, q = 0: −tr σ/3 = P0 exactly.
        assert_eq!(sample(&c, 0.35), P0);
        // A fictitious cell stays the FDM's.
        let mut fdm = Vec::new();
        c.fdm
            .sample(
                [0.305, 0.5 * H, 0.5 * H],
                &["pressure".to_string()],
                &mut fdm,
            )
            .unwrap();
        assert_eq!(sample(&c, 0.305), fdm[0]);
        // The cell data: the cell at 0.351 m from the MPM, P0.
        let d = c.cell_data(&["pressure".to_string()]).unwrap();
        let i = d
            .geometry
            .cell_containing([0.351, 0.5 * H, 0.5 * H])
            .unwrap();
        assert_eq!(d.fields[0].1[d.geometry.linear_index(i)], P0);
        // The shock tube's driver, x < 0.1 m, from the FDM: 5 bar.
        let i = d
            .geometry
            .cell_containing([0.05, 0.5 * H, 0.5 * H])
            .unwrap();
        assert_eq!(d.fields[0].1[d.geometry.linear_index(i)], 5.0e5);
    }

    #[test]
    fn a_shock_passes_the_bridge_as_it_passes_a_pure_fdm_tube() {
        let t_end = 7.0e-4;
        let (xf, xm) = (0.22, 0.33);
        let mut c = coupled();
        let m0 = c.mpm().conservation_totals().mass;
        let mut reference = fdm_on([0.0; 3], [0.4, H, H], [200, 1, 1], FdmBoundary::Reflective);
        let (mut tc, mut pf, mut pm) = (vec![0.0], vec![P0], vec![P0]);
        while c.time() < t_end {
            let dt = c.stable_dt().unwrap().min(t_end - c.time());
            c.advance(dt).unwrap();
            tc.push(c.time());
            pf.push(sample(c.fdm(), xf));
            pm.push(if c.is_active() {
                sample(c.mpm(), xm)
            } else {
                P0
            });
        }
        let (mut tr, mut rf, mut rm) = (vec![0.0], vec![P0], vec![P0]);
        while reference.time() < t_end {
            let dt = reference.stable_dt().unwrap().min(t_end - reference.time());
            reference.advance(dt).unwrap();
            tr.push(reference.time());
            rf.push(sample(&reference, xf));
            rm.push(sample(&reference, xm));
        }
        let whole = brisance_core::UniformGridGeometry {
            origin: [0.0; 3],
            spacing: [H; 3],
            cells: [200, 1, 1],
        };
        let mut pure = mpm_tube(whole, 0.0, 0.4, GridBoundary::Symmetry);
        let (mut tp, mut pp) = (vec![0.0], vec![P0]);
        while pure.time() < t_end {
            let dt = pure.stable_dt().unwrap().min(t_end - pure.time());
            pure.advance(dt).unwrap();
            tp.push(pure.time());
            pp.push(sample(&pure, xm));
        }
        let (tq, pq) = arrival_and_peak(&tp, &pp);
        eprintln!(
            "pure MPM gauge: arrival {tq:.4e} s, peak {pq:.4e} Pa; {} steps",
            tp.len() - 1
        );
        if std::env::var("BRIDGE_SERIES").is_ok() {
            for i in (0..tp.len()).step_by(10) {
                eprintln!("M {:.4e} {:.4e}", tp[i], pp[i]);
            }
        }
        let (ta, pa) = arrival_and_peak(&tc, &pm);
        let (tb, pb) = arrival_and_peak(&tr, &rm);
        let (tfa, pfa) = arrival_and_peak(&tc, &pf);
        let (tfb, pfb) = arrival_and_peak(&tr, &rf);
        // Mean pressure over the 150 µs after arrival (the MPM gauges
        // oscillate about it by ±10 % in the pure MPM run as well).
        let plateau = |t: &[f64], p: &[f64], from: f64| {
            let w: Vec<f64> = t
                .iter()
                .zip(p)
                .filter(|(&x, _)| x > from + 1.0e-5 && x < from + 1.6e-4)
                .map(|(_, &y)| y)
                .collect();
            w.iter().sum::<f64>() / w.len() as f64
        };
        let (qa, qq, qb) = (
            plateau(&tc, &pm, ta),
            plateau(&tp, &pp, tq),
            plateau(&tr, &rm, tb),
        );
        // After the shock has passed the FDM gauge, any wave reflected by
        // the interface shows as a departure from the reference there.
        let interp = |t: f64| {
            let i = tr.partition_point(|&x| x < t).clamp(1, tr.len() - 1);
            let f = (t - tr[i - 1]) / (tr[i] - tr[i - 1]);
            rf[i - 1] + f * (rf[i] - rf[i - 1])
        };
        let jump = pfb - P0;
        let reflected = tc
            .iter()
            .zip(&pf)
            .filter(|(&t, _)| t > tfb + 2.0e-5)
            .map(|(&t, &p)| (p - interp(t)).abs() / jump)
            .fold(0.0, f64::max);
        let tt = c.transport_totals();
        let pct = |a: f64, b: f64| 100.0 * (a - b) / b;
        eprintln!(
            "activated at {:?} s, {} steps, split FDM/MPM {:?} s\n\
             MPM gauge x = {xm} m: arrival {ta:.4e} s (pure MPM {tq:.4e}, FDM {tb:.4e}: {:+.2} %, {:+.2} %), \
             peak {pa:.4e} Pa (pure MPM {pq:.4e}, FDM {pb:.4e}: {:+.2} %, {:+.2} %), \
             plateau {qa:.4e} Pa (pure MPM {qq:.4e}, FDM {qb:.4e}: {:+.2} %, {:+.2} %)\n\
             FDM gauge x = {xf} m: arrival {:+.3} %, peak {:+.3} %, largest departure after the shock {:.3} % of the jump\n\
             created {} particles ({:.4e} kg), absorbed {}",
            c.activated_at(),
            c.steps(),
            c.split_seconds(),
            pct(ta, tq),
            pct(ta, tb),
            pct(pa, pq),
            pct(pa, pb),
            pct(qa, qq),
            pct(qa, qb),
            pct(tfa, tfb),
            pct(pfa, pfb),
            100.0 * reflected,
            tt.created,
            tt.into_mpm.mass,
            tt.absorbed,
        );
        assert!(c.activated_at().is_some());
        assert!(pb > 1.5 * P0, "the shock must reach the MPM gauge");
        // The interface leaves the MPM region's shock as the pure MPM run
        // has it, and reflects nothing visible into the FDM region.
        assert!(pct(ta, tq).abs() < 2.0);
        assert!(pct(qa, qq).abs() < 5.0);
        assert!(reflected < 0.01);
        // Mass booked by the transport is the MPM's mass change, to round-off.
        let m1 = c.mpm().conservation_totals().mass;
        let booked = m0 + tt.into_mpm.mass - tt.into_fdm.mass;
        assert!((m1 - booked).abs() < 1e-13 * m1, "{m1} vs {booked}");
    }

    /// A uniform air stream at Mach 2.9 through the 1D bridge of
    /// [`coupled`]: FDM (0, 0.3) m, MPM (0.29, 0.4) m, outflow at both ends.
    fn supersonic_stream() -> Cfdmp<IdealGas> {
        let u = 1000.0;
        let uniform = |_: [f64; 3]| PrimitiveState {
            density: RHO0,
            velocity: [u, 0.0, 0.0],
            pressure: P0,
        };
        let regions = BridgeRegions::from_boxes(
            RegionBox {
                lower: [0.0; 3],
                upper: [0.3, H, H],
            },
            RegionBox {
                lower: [0.29, 0.0, 0.0],
                upper: [0.4, H, H],
            },
            [H; 3],
            GHOST,
        )
        .unwrap();
        let (fg, _) = regions.fdm_grid(GHOST);
        let level = Level::new(fg.origin, fg.upper(), fg.cells, [1, 1, 1], GHOST).unwrap();
        let fdm = FdmSolver::new(
            IdealGas::air(),
            level,
            [FdmBoundary::Outflow; 6],
            FdmOptions::default(),
            uniform,
        )
        .unwrap();
        let (mg, _) = regions.mpm_grid();
        let level = Level::new(mg.origin, mg.upper(), mg.cells, [1, 1, 1], 0).unwrap();
        let air = IdealGas::air();
        let mut ps = Particles::new(0);
        let v = H * H * H / 2.0;
        for k in 0..110 {
            let x = 0.29 + (k as f64 + 0.5) * 0.5 * H;
            ps.push(
                &ParticleInit {
                    position: [x, 0.5 * H, 0.5 * H],
                    velocity: [u, 0.0, 0.0],
                    mass: RHO0 * v,
                    volume: v,
                    stress: [-P0, -P0, -P0, 0.0, 0.0, 0.0],
                    specific_internal_energy: air.specific_internal_energy(RHO0, P0).unwrap(),
                    ..Default::default()
                },
                &[],
            )
            .unwrap();
        }
        let mut boundaries = [GridBoundary::Free; 6];
        boundaries[0] = GridBoundary::Outflow;
        boundaries[1] = GridBoundary::Outflow;
        let mpm = MpmSolver::new(
            level,
            vec![MaterialModel::Null(NullMaterial::air())],
            ps,
            MpmOptions {
                boundaries,
                bulk_viscosity: Some(BulkViscosity::default()),
                ..Default::default()
            },
        )
        .unwrap();
        Cfdmp::new(
            regions,
            fdm,
            mpm,
            GHOST,
            CfdmpOptions {
                air: MaterialId(0),
                products: None,
                gamma: air.gamma,
                existing_mass: RHO0 * v,
                // Below the stream's pressure: the MPM runs from step 1.
                activation_pressure: 0.5 * P0,
                activation_cells: 3,
                min_particle_mass: 0.25,
                existing_volume: 0.0,
                deposit: false,
                donor_rings: 1,
            },
        )
        .unwrap()
    }

    #[test]
    fn a_supersonic_stream_leaves_the_fdm_region_exactly_uniform() {
        // Nothing travels upstream in a Mach 2.9 stream, so the fictitious
        // cells take the FDM's own outflow state rather than the MPM's
        // (which differs from the stream by the MPM's discretisation): the
        // FDM region keeps the uniform state to the last bit.
        let mut c = supersonic_stream();
        let want = c.fdm().cell_conservative([10, 0, 0]).unwrap();
        for _ in 0..60 {
            let dt = c.stable_dt().unwrap();
            c.advance(dt).unwrap();
        }
        assert!(c.is_active());
        let lines = c.transport_totals().supersonic_outflow;
        assert_eq!(lines, 59, "one line per active step");
        let n = c.regions().fdm.cells[0];
        for i in 0..n {
            let got = c.fdm().cell_conservative([i + c.fdm_offset, 0, 0]).unwrap();
            assert_eq!(got, want, "FDM cell {i}");
        }
        // The MPM took in the stream: created particles carried f_m > 0.
        assert!(c.transport_totals().into_mpm.mass > 0.0);
    }

    #[test]
    fn in_a_stream_the_fdm_gives_up_the_enthalpy_flux_the_transport_and_donors_carry() {
        // The uniform stream, step by step after activation: the FDM
        // cells the bridge owns lose exactly (E + p) u Δt A a step, the
        // transport's E u Δt A (eqs 43–48) plus the pressure work p u Δt A
        // that the donor cells, as particles of the MPM step (eqs 37–39),
        // are to do on the MPM. The work they do is measured from their
        // own energy change over the MPM step and reported in
        // docs/physics/couple/bridge.md ("What the totals count").
        let mut c = supersonic_stream();
        let (mut transported, mut pressure_work, mut fdm_change) = (0.0, 0.0, 0.0);
        let mut active_steps = 0;
        for _ in 0..401 {
            let dt = c.stable_dt().unwrap();
            if !c.is_active() {
                c.advance(dt).unwrap();
                continue;
            }
            let (f0, tt0) = (fdm_owned_totals(&c), c.transport_totals());
            c.mpm_step(dt).unwrap();
            let donor = &c.inits[0];
            pressure_work += -donor.stress[0] * donor.velocity[0] * dt * c.regions.face_area();
            c.update_fictitious_cells().unwrap();
            c.fdm.advance(dt).unwrap();
            c.set_fictitious_values().unwrap();
            c.transport(dt).unwrap();
            c.time += dt;
            c.steps += 1;
            let tt = c.transport_totals();
            transported += tt.into_mpm.energy - tt0.into_mpm.energy;
            assert_eq!(tt.into_fdm.energy, tt0.into_fdm.energy, "no absorption");
            fdm_change += fdm_owned_totals(&c).energy - f0.energy;
            active_steps += 1;
        }
        assert!(active_steps >= 400);
        let given = transported + pressure_work;
        assert!(
            (fdm_change + given).abs() <= 1e-12 * given,
            "the FDM lost {} against {given}",
            -fdm_change
        );
        assert!(pressure_work > 0.1 * transported);
    }

    #[test]
    fn the_totals_balance_a_stream_through_both_regions() {
        // The stream enters the FDM region through its flow-out face at
        // x = 0 and leaves the MPM region at x = 0.4 m: the bridge's
        // totals book the first through the FDM's face outflow and the
        // second through the MPM's, so they hold to round-off in mass
        // while more than half the coupled tube's content passes through.
        let mut c = supersonic_stream();
        let dt = c.stable_dt().unwrap();
        c.advance(dt).unwrap();
        assert!(c.is_active());
        let t0 = Solver::conservation_totals(&c);
        let inflow0 = c.fdm().outflow_where(|f, _| f == 0);
        for _ in 0..400 {
            let dt = c.stable_dt().unwrap();
            c.advance(dt).unwrap();
        }
        let t1 = Solver::conservation_totals(&c);
        let inflow = -(c.fdm().outflow_where(|f, _| f == 0).mass - inflow0.mass);
        assert!(inflow > 0.5 * t0.mass, "{inflow} {}", t0.mass);
        assert!(
            (t1.mass - t0.mass).abs() <= 1e-13 * t0.mass,
            "{} → {}",
            t0.mass,
            t1.mass
        );
        // Energy is not held to round-off here: the pressure work across
        // the interface reaches the MPM through the fictitious cells and
        // nodes, not the transport, and the totals drift by −0.84 % over
        // these 400 steps (docs/physics/couple/bridge.md, "What the
        // totals count").
    }

    #[test]
    fn restart_continues_bit_identically_and_outputs_cover_the_union() {
        let mut c = coupled();
        while !c.is_active() || c.steps() < 200 {
            let dt = Solver::stable_dt(&c).unwrap();
            Solver::advance(&mut c, dt).unwrap();
        }
        let saved = c.save_state().unwrap();
        let run = |c: &mut Cfdmp<IdealGas>| {
            for _ in 0..30 {
                let dt = Solver::stable_dt(c).unwrap();
                Solver::advance(c, dt).unwrap();
            }
            let f = ["pressure".to_string(), "density".to_string()];
            (
                c.cell_data(&f).unwrap(),
                c.conservation_totals(),
                c.transport_totals(),
            )
        };
        let first = run(&mut c);
        let steps_first = c.particle_counts().particle_steps;
        c.restore_state(&saved).unwrap();
        let second = run(&mut c);
        assert_eq!(first.0, second.0);
        assert_eq!(first.1, second.1);
        assert_eq!(first.2, second.2);
        // The particle-steps count (the run summary's throughput) goes on
        // from the checkpoint's, not from where the first run ended.
        assert_eq!(c.particle_counts().particle_steps, steps_first);
        // The union: 150 FDM + 55 MPM − 5 bridge cells; x = 0.35 m reads
        // the MPM, x = 0.1 m the FDM.
        let data = first.0;
        assert_eq!(data.geometry.cells, [200, 1, 1]);
        let mut mpm = Vec::new();
        c.mpm()
            .sample([0.351, 0.001, 0.001], &["pressure".to_string()], &mut mpm)
            .unwrap();
        assert_eq!(data.fields[0].1[175], mpm[0]);
        let mut fdm = Vec::new();
        c.fdm()
            .sample([0.101, 0.001, 0.001], &["pressure".to_string()], &mut fdm)
            .unwrap();
        assert_eq!(data.fields[0].1[50], fdm[0]);
        let e = c.cell_data(&["mass_density".to_string()]).unwrap_err();
        assert!(e.to_string().contains("unknown field"), "{e}");
    }

    #[test]
    fn the_time_split_is_json_with_every_part_named() {
        let counts = ParticleCounts {
            particles: 7,
            particle_steps: 70,
            created: 4,
            deposited: 3,
            absorbed: 1,
        };
        assert_eq!(
            time_split_json((1.5, 0.25), 12, Some(3.0e-6), counts),
            "{\n  \"fdm_seconds\": 1.5,\n  \"mpm_seconds\": 0.25,\n  \"steps\": 12,\n  \"activated_at\": 3e-6,\n  \"particles\": 7,\n  \"particle_steps\": 70,\n  \"created\": 4,\n  \"deposited\": 3,\n  \"absorbed\": 1\n}\n"
        );
        let none = ParticleCounts::default();
        assert!(time_split_json((0.0, 0.0), 0, None, none).contains("\"activated_at\": null"));
        assert!(time_split_json((f64::NAN, 1.0), 0, None, none).contains("\"fdm_seconds\": null"));
    }

    #[test]
    fn finish_writes_the_split_of_a_run() {
        let mut c = coupled();
        while !c.is_active() {
            let dt = Solver::stable_dt(&c).unwrap();
            Solver::advance(&mut c, dt).unwrap();
        }
        for _ in 0..3 {
            let dt = Solver::stable_dt(&c).unwrap();
            Solver::advance(&mut c, dt).unwrap();
        }
        let (fdm, mpm) = c.split_seconds();
        assert!(fdm > 0.0 && mpm > 0.0, "{fdm} {mpm}");
        // The run summary's split is the same pair, named.
        assert_eq!(Solver::wall_split(&c), vec![("fdm", fdm), ("mpm", mpm)]);
        let dir = std::env::temp_dir().join(format!("brisance_split_{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        c.finish(&dir).unwrap();
        let text = std::fs::read_to_string(dir.join(TIME_SPLIT_FILE)).unwrap();
        std::fs::remove_dir_all(&dir).unwrap();
        assert_eq!(
            text,
            time_split_json((fdm, mpm), c.steps(), c.activated_at(), c.particle_counts())
        );
        assert!(
            text.contains(&format!("\"steps\": {}", c.steps())),
            "{text}"
        );
    }

    #[test]
    fn inflow_batches_make_fewer_particles_of_at_least_half_m_e() {
        // Threshold 4 m_e: every batch holds at least 4 m_e, so its
        // s = 4⌈M/4m_e⌉ particles weigh M/s ≥ m_e/2 each.
        let m_e = RHO0 * H * H * H / 2.0;
        let run = |min: f64| {
            let mut c = coupled_with(min);
            let first = c.mpm().particles().len() as u32;
            while c.time() < 5.5e-4 {
                let dt = Solver::stable_dt(&c).unwrap();
                Solver::advance(&mut c, dt).unwrap();
            }
            let ps = c.mpm().particles();
            let ids = c.mpm().particle_ids();
            let lightest = (0..ps.len())
                .filter(|&p| ids[p] >= first)
                .map(|p| ps.mass[p])
                .fold(f64::INFINITY, f64::min);
            let in_transit: f64 = c.pending.iter().map(|q| q.mass).sum();
            assert_eq!(c.pending.len(), 1, "one face in the 1D tube");
            (c.transport_totals(), lightest, in_transit)
        };
        let (paper, paper_lightest, none) = run(0.0);
        let (batched, lightest, in_transit) = run(1.0);
        assert_eq!(none, 0.0);
        assert!(paper.created > 0 && batched.created > 0);
        assert!(
            batched.created < paper.created,
            "{} vs {}",
            batched.created,
            paper.created
        );
        assert!(lightest >= 0.5 * m_e, "{lightest} {m_e}");
        assert!(paper_lightest < 0.5 * m_e, "{paper_lightest} {m_e}");
        // What waits is less than one batch.
        assert!(in_transit < 4.0 * m_e, "{in_transit}");
    }

    #[test]
    fn deposited_inflow_is_in_the_mpm_region_the_step_it_arrives() {
        // The deposit rule: after every step nothing is in transit, and the
        // MPM's mass, momentum and energy change by exactly what the
        // transport booked plus what the MPM step itself did; the mass,
        // which the MPM step keeps, to round-off.
        let mut c = coupled_inflow(0.25, true);
        let m0 = c.mpm().conservation_totals().mass;
        let first = c.mpm().particles().len() as u32;
        let mut steps_with_inflow = 0;
        while c.time() < 5.5e-4 {
            let dt = Solver::stable_dt(&c).unwrap();
            let before = c.transport_totals().into_mpm.mass;
            Solver::advance(&mut c, dt).unwrap();
            if c.transport_totals().into_mpm.mass > before {
                steps_with_inflow += 1;
            }
            assert!(c.pending.iter().all(|q| q.mass == 0.0), "{:?}", c.pending);
            let tt = c.transport_totals();
            let m1 = c.mpm().conservation_totals().mass;
            let booked = m0 + tt.into_mpm.mass - tt.into_fdm.mass;
            assert!((m1 - booked).abs() < 1e-13 * m1, "{m1} vs {booked}");
        }
        let tt = c.transport_totals();
        assert!(steps_with_inflow > 10, "{steps_with_inflow}");
        // Inflow went into existing particles far more often than into new
        // ones, and the new ones grew by the deposits that followed.
        assert!(tt.deposited > 0 && tt.created > 0, "{tt:?}");
        assert!(tt.deposited > tt.created, "{tt:?}");
        let (paper, _, _) = {
            let mut p = coupled_with(0.0);
            while p.time() < 5.5e-4 {
                let dt = Solver::stable_dt(&p).unwrap();
                Solver::advance(&mut p, dt).unwrap();
            }
            (p.transport_totals(), 0, 0)
        };
        assert!(
            tt.created < paper.created,
            "{} vs {}",
            tt.created,
            paper.created
        );
        let ps = c.mpm().particles();
        let ids = c.mpm().particle_ids();
        let m_e = RHO0 * H * H * H / 2.0;
        let heaviest = (0..ps.len())
            .filter(|&p| ids[p] >= first)
            .map(|p| ps.mass[p])
            .fold(0.0, f64::max);
        assert!(heaviest > m_e, "{heaviest} {m_e}");
    }

    /// The FDM region's own cells (fictitious cells excepted) as totals.
    fn fdm_owned_totals(c: &Cfdmp<IdealGas>) -> ConservationTotals {
        let mut t = Solver::conservation_totals(c);
        let m = c.mpm().conservation_totals();
        book_parts(&mut t, -m.mass, m.momentum.map(|x| -x), -m.energy);
        for q in &c.pending {
            book_parts(&mut t, -q.mass, q.momentum.map(|x| -x), -q.energy);
        }
        t
    }

    /// The MPM region's particles without this step's donor cells.
    fn mpm_totals_without_donors(c: &Cfdmp<IdealGas>) -> ConservationTotals {
        let mut t = c.mpm().conservation_totals();
        let ps = c.mpm().particles();
        let ids = c.mpm().particle_ids();
        for p in (0..ps.len()).filter(|&p| c.is_donor(ids[p])) {
            // A particle of mass −m takes its mass, momentum and energy out.
            book(
                &mut t,
                -ps.mass[p],
                ps.velocity[p],
                ps.specific_internal_energy[p],
            );
        }
        t
    }

    fn difference(a: ConservationTotals, b: ConservationTotals) -> [f64; 5] {
        [
            a.mass - b.mass,
            a.momentum[0] - b.momentum[0],
            a.momentum[1] - b.momentum[1],
            a.momentum[2] - b.momentum[2],
            a.energy - b.energy,
        ]
    }

    #[test]
    fn the_transport_moves_mass_momentum_and_energy_between_the_frames_to_round_off() {
        // Step 14 alone, on the coupled tube through the shock's arrival,
        // with both inflow rules: the MPM region changes by exactly the
        // inflow it booked less the particles the FDM absorbed, the FDM
        // region by exactly what it absorbed, in mass, every momentum
        // component and energy (`Cfdmp::advance`'s sequence, written out so
        // that the totals can be taken just before the transport).
        for deposit in [false, true] {
            transport_balances(coupled_inflow(0.25, deposit), deposit, 1.2e-3);
        }
    }

    /// The coupled tube along z of an (r, z) grid, r 0–6H (6 rings, the
    /// axis and a slip wall at r = 6H): FDM z (0, 0.3) m, MPM (0.29, 0.4) m,
    /// w = 5, the shock tube's state along z; ring particles, 2 × 2 per
    /// cell, and donor cells as 2 rings each.
    fn coupled_rz(deposit: bool) -> Cfdmp<IdealGas> {
        let regions = BridgeRegions::from_boxes(
            RegionBox {
                lower: [0.0; 3],
                upper: [6.0 * H, 0.3, H],
            },
            RegionBox {
                lower: [0.0, 0.29, 0.0],
                upper: [6.0 * H, 0.4, H],
            },
            [H; 3],
            GHOST,
        )
        .unwrap();
        let (fg, _) = regions.fdm_grid(GHOST);
        let along_z = |x: [f64; 3]| initial([x[1], 0.0, 0.0]);
        let level = Level::new(
            fg.origin,
            fg.upper(),
            fg.cells,
            [1, 1, 1],
            brisance_fdm::sweep::GHOST_RZ,
        )
        .unwrap();
        let mut bcs = [FdmBoundary::Outflow; 6];
        bcs[0] = FdmBoundary::Reflective;
        bcs[1] = FdmBoundary::Reflective;
        bcs[2] = FdmBoundary::Reflective;
        let fdm = FdmSolver::new(
            IdealGas::air(),
            level,
            bcs,
            FdmOptions {
                geometry: Geometry::Axisymmetric,
                ..Default::default()
            },
            along_z,
        )
        .unwrap();
        let (mg, _) = regions.mpm_grid();
        let level = Level::new(mg.origin, mg.upper(), mg.cells, [1, 1, 1], 0).unwrap();
        let air = IdealGas::air();
        let mut ps = Particles::new(0);
        let ppc = 2;
        let first = regions.mpm.origin[1];
        let cells = ((regions.mpm.upper()[1] - first) / H).round() as usize;
        let mut per_radius = (0.0, 0);
        for c in 0..cells * ppc {
            for i in 0..6 * ppc {
                let z = first + (c as f64 + 0.5) / ppc as f64 * H;
                let r = (i as f64 + 0.5) / ppc as f64 * H;
                let st = along_z([r, z, 0.0]);
                let (rho, p) = (st.density, st.pressure);
                let v = 2.0 * std::f64::consts::PI * r * H * H / (ppc * ppc) as f64;
                if rho == RHO0 {
                    per_radius = (per_radius.0 + rho * v / r, per_radius.1 + 1);
                }
                ps.push(
                    &ParticleInit {
                        position: [r, z, 0.5 * H],
                        mass: rho * v,
                        volume: v,
                        stress: [-p, -p, -p, 0.0, 0.0, 0.0],
                        specific_internal_energy: air.specific_internal_energy(rho, p).unwrap(),
                        ..Default::default()
                    },
                    &[],
                )
                .unwrap();
            }
        }
        let mpm = MpmSolver::new(
            level,
            vec![MaterialModel::Null(NullMaterial::air())],
            ps,
            MpmOptions {
                boundaries: [
                    GridBoundary::Symmetry,
                    GridBoundary::Symmetry,
                    GridBoundary::Outflow,
                    GridBoundary::Symmetry,
                    GridBoundary::Free,
                    GridBoundary::Free,
                ],
                bulk_viscosity: Some(BulkViscosity::default()),
                geometry: Geometry::Axisymmetric,
                ..Default::default()
            },
        )
        .unwrap();
        Cfdmp::new(
            regions,
            fdm,
            mpm,
            GHOST,
            CfdmpOptions {
                air: MaterialId(0),
                products: None,
                gamma: air.gamma,
                existing_mass: per_radius.0 / per_radius.1 as f64,
                activation_pressure: 1.05 * P0,
                activation_cells: 3,
                min_particle_mass: 0.25,
                existing_volume: 0.0,
                deposit,
                donor_rings: 2,
            },
        )
        .unwrap()
    }

    #[test]
    fn on_rings_the_transport_moves_mass_axial_momentum_and_energy_to_round_off() {
        // The same check on an (r, z) grid: every volume and area of the
        // exchange a ring's (eqs 40–51 with 2πr), the totals the rings'.
        for deposit in [false, true] {
            transport_balances(coupled_rz(deposit), deposit, 1.2e-3);
        }
    }

    #[test]
    fn on_rings_a_geometry_mismatch_is_refused() {
        let c = coupled_rz(false);
        let (regions, fdm, mpm) = (c.regions, c.fdm, c.mpm);
        let mut options = c.options;
        options.donor_rings = 1;
        let cartesian_fdm = fdm_on(
            fdm.level().geometry.origin,
            fdm.level().geometry.upper(),
            fdm.level().geometry.cells,
            FdmBoundary::Outflow,
        );
        let e = Cfdmp::new(regions, cartesian_fdm, mpm, GHOST, options).unwrap_err();
        assert!(e.contains("one geometry"), "{e}");
    }

    /// Runs `c` to `end` with step 14 checked against its bookings (the
    /// body of the transport tests).
    fn transport_balances(mut c: Cfdmp<IdealGas>, deposit: bool, end: f64) {
        {
            let (mut transports, mut moved) = (0, [0u64; 2]);
            let mut worst = 0.0f64;
            while c.time() < end {
                let dt = c.stable_dt().unwrap();
                if !c.is_active() {
                    c.advance(dt).unwrap();
                    continue;
                }
                c.mpm_step(dt).unwrap();
                c.update_fictitious_cells().unwrap();
                c.fdm.advance(dt).unwrap();
                c.set_fictitious_values().unwrap();
                let (mpm0, fdm0, tt0) = (
                    mpm_totals_without_donors(&c),
                    fdm_owned_totals(&c),
                    c.transport_totals(),
                );
                c.transport(dt).unwrap();
                c.time += dt;
                c.steps += 1;
                let tt = c.transport_totals();
                let into_mpm = difference(tt.into_mpm, tt0.into_mpm);
                let into_fdm = difference(tt.into_fdm, tt0.into_fdm);
                let d_mpm = difference(c.mpm().conservation_totals(), mpm0);
                let d_fdm = difference(fdm_owned_totals(&c), fdm0);
                // Scales: the region's own totals (momentum by the mass
                // times the largest speed in the tube, 500 m/s).
                let m = mpm0.mass.max(fdm0.mass);
                let scale = [
                    m,
                    500.0 * m,
                    500.0 * m,
                    500.0 * m,
                    mpm0.energy.max(fdm0.energy),
                ];
                for k in 0..5 {
                    let tol = 1e-13 * scale[k];
                    let expected = into_mpm[k] - into_fdm[k];
                    worst = worst
                        .max((d_mpm[k] - expected).abs() / scale[k])
                        .max((d_fdm[k] - into_fdm[k]).abs() / scale[k]);
                    assert!(
                        (d_mpm[k] - expected).abs() <= tol,
                        "deposit {deposit}, t {}: MPM component {k} changed by {} against {expected} booked",
                        c.time,
                        d_mpm[k]
                    );
                    assert!(
                        (d_fdm[k] - into_fdm[k]).abs() <= tol,
                        "deposit {deposit}, t {}: FDM component {k} changed by {} against {} absorbed",
                        c.time,
                        d_fdm[k],
                        into_fdm[k]
                    );
                }
                transports += 1;
                moved[0] += u64::from(into_mpm[0] > 0.0);
                moved[1] += u64::from(into_fdm[0] > 0.0);
            }
            // The check saw traffic both ways.
            eprintln!(
                "deposit {deposit}: {transports} transports, inflow in {}, absorption in {}, largest imbalance {worst:e} of the scale",
                moved[0], moved[1]
            );
            assert!(transports > 50, "{transports}");
            assert!(
                moved[0] > 10 && moved[1] > 0,
                "deposit {deposit}: {moved:?}"
            );
        }
    }

    #[test]
    fn the_mpm_region_starts_the_step_the_shock_reaches_the_watched_cells() {
        // Before activation the coupled FDM is the tube's FDM (its
        // fictitious cells held at the undisturbed state the shock has not
        // reached): a pure FDM tube stepped with the same steps reads the
        // pressure of the watched cells (the donor cell and the two before
        // it) independently. The MPM region must start at the end of the
        // first step where one of them reaches 1.05 P0, and not before;
        // until then its particles do not move.
        let mut c = coupled();
        let mut reference = fdm_on([0.0; 3], [0.4, H, H], [200, 1, 1], FdmBoundary::Reflective);
        let positions = c.mpm().particles().position.clone();
        let donor_x =
            c.fdm()
                .level()
                .geometry
                .cell_centre([c.fdm_index(c.regions().donor_cell()), 0, 0])[0];
        let watched: Vec<f64> = (0..3).map(|k| donor_x - k as f64 * H).collect();
        let mut steps = 0;
        loop {
            assert!(!c.is_active());
            assert_eq!(c.activated_at(), None);
            let dt = c.stable_dt().unwrap();
            c.advance(dt).unwrap();
            reference.advance(dt).unwrap();
            steps += 1;
            let reached = watched
                .iter()
                .any(|&x| sample(&reference, x) >= c.options.activation_pressure);
            assert_eq!(c.is_active(), reached, "step {steps}, t {}", c.time());
            if reached {
                assert_eq!(c.activated_at(), Some(c.time()));
                break;
            }
            assert_eq!(c.mpm().particles().position, positions);
            assert_eq!(c.mpm().time(), 0.0);
            assert!(steps < 10_000);
        }
        // The shock of the 5:1 tube (about 530 m/s) runs the 0.184 m from
        // the diaphragm to the first watched cell in about 350 µs.
        let t = c.activated_at().unwrap();
        assert!((2.5e-4..4.5e-4).contains(&t), "{t}");
        // After it, the step is the smaller of the two CFL limits.
        let f = c.fdm().stable_dt().unwrap();
        let m = c.mpm().stable_dt().unwrap();
        assert_eq!(c.stable_dt().unwrap(), f.min(m));
        assert!(m != f);
    }
}
