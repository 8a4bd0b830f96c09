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
    interface_state, resolve_fictitious_line, CellParticle, CellParticles, Deposit, FaceInflow,
    FictitiousSource, NewParticle, NormalState, Primitive,
};
use crate::regions::{BridgeRegions, Side};

mod fictitious;
mod transport;

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
    /// Start each row of interface faces inside the bridge (`Some(k)`,
    /// 1 ≤ k < w): the MPM region starts when the shock is k cells into
    /// the bridge (FDM pressure ≥ `activation_pressure` in the k-th
    /// bridge cell from the interface) in some row, and each row joins
    /// the coupling when its own shock gets there: until then its donor
    /// cell pushes with its initial state and its inflow waits in the FDM;
    /// then its air and products particles inside the bridge take the
    /// state of the FDM cell they are in (mass ρ_c V_p at their own volume;
    /// the change booked as inflow). A shock then enters the MPM region
    /// already inside its particles, as the FDM carries it, instead of
    /// being started at the interface by the donor's pressure and the
    /// inflow (docs/physics/couple/bridge.md, "Starting inside the
    /// bridge"). `None`: seed 001's start (`activation_cells` before the
    /// interface, the particles as they are).
    pub start_in_bridge: Option<usize>,
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
    /// Particles given their FDM cell's state as their row joined
    /// (`CfdmpOptions::start_in_bridge`).
    pub restarted: u64,
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
    /// Per interface face, whether its row has joined the coupling
    /// (always, without `start_in_bridge`).
    joined: Vec<bool>,
    /// Per interface face, its donor cell's initial state, the push of a
    /// row that has not joined.
    donor_initial: Vec<Primitive>,
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
    /// Spreads the coupled step over the ranks of `comm` (nothing to do on
    /// one rank; docs/cluster.md): every rank holds the whole FDM grid and
    /// every particle and runs every pass over all of them, except the MPM
    /// step's fused G2P and stress update, which each rank runs for its run
    /// of particles ([`MpmSolver::distribute`]). The FDM's patches are not
    /// split: the bridge's fictitious cells and transport read and write
    /// FDM cells along the whole interface. Every rank builds the same
    /// solver and calls this before the first step.
    pub fn distribute(&mut self, comm: std::sync::Arc<dyn brisance_grid::comm::Communicator>) {
        self.mpm.distribute(comm);
    }

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
        if mpm.options().shape == brisance_mpm::ShapeFunction::QuadraticBSpline {
            return Err(
                "the bridge's donor cells reach the halo cell's nodes alone, which the quadratic B-spline cannot: use shape_function: Linear, Gimp or CpGimp"
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
        if let Some(k) = options.start_in_bridge {
            if k == 0 || k >= regions.width {
                return Err(format!(
                    "start_in_bridge = {k} cells must lie in [1, w) = [1, {}): the shock has to be inside the bridge, short of the FDM region's end",
                    regions.width
                ));
            }
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
            joined: Vec::new(),
            donor_initial: Vec::new(),
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
        s.joined = vec![options.start_in_bridge.is_none(); s.faces.len()];
        let donor = s.fdm_index(s.regions.donor_cell());
        s.donor_initial = (0..s.faces.len())
            .map(|f| {
                let mut c = s.faces[f];
                c[a] = donor;
                s.primitive(c).0
            })
            .collect();
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
        self.geometry.column_cell_volume(&self.regions.fdm, g[0])
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
            // A row that has not joined pushes with its initial state.
            let s = if self.joined[f] {
                self.primitive(c).0
            } else {
                self.donor_initial[f]
            };
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
                let e = self.particle_energy(c, &s, false);
                self.inits.push(particle_init(&cp, e, self.options.air));
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

    /// The specific internal energy of air or products particles made from
    /// FDM cell `c` in state `s`: eq 48's p/((γ − 1)ρ) for air, the cell's
    /// own for `products` (the donors, the transport's new particles and
    /// the particles of a row that joins).
    fn particle_energy(&self, c: [usize; 3], s: &Primitive, products: bool) -> f64 {
        if products {
            let u = self.fdm.cell_conservative(c).unwrap_or([0.0; 6]);
            specific_internal_energy(u[0], u[1], u[2], u[3], u[4])
        } else {
            s.pressure / ((self.options.gamma - 1.0) * s.density)
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
            if (0..self.faces.len()).any(|f| self.reached(f, i as usize)) {
                return true;
            }
        }
        false
    }

    /// Whether the FDM pressure in face `f`'s row at FDM-region cell `i`
    /// along the split axis has reached `activation_pressure`.
    fn reached(&self, f: usize, i: usize) -> bool {
        let mut c = self.faces[f];
        c[self.regions.axis] = self.fdm_index(i);
        self.primitive(c).0.pressure >= self.options.activation_pressure
    }

    /// Whether the FDM pressure of face `f`'s row has reached
    /// `activation_pressure` in the `k`-th bridge cell from the interface
    /// (k = 0: the first bridge cell).
    fn shock_in_bridge(&self, f: usize, k: usize) -> bool {
        let first = self.regions.first_bridge_cell();
        let i = match self.regions.mpm_side {
            Side::High => first + k,
            Side::Low => first - k,
        };
        self.reached(f, i)
    }

    /// With `start_in_bridge`: the rows whose shock has reached the k-th
    /// bridge cell join the coupling, and their air and products
    /// particles inside the bridge take the state of the FDM cell they are
    /// in (mass ρ_c V_p at their own volume, the FDM velocity, air's
    /// specific internal energy by eq 48 and products' the cell's own,
    /// stress −p_c I), the change booked as inflow.
    fn join_rows(&mut self) -> Result<(), SolverError> {
        let Some(k) = self.options.start_in_bridge else {
            return Ok(());
        };
        // Nothing to do (and nothing allocated) on the steps no row joins.
        let joins = |f: usize| !self.joined[f] && self.shock_in_bridge(f, k);
        if !(0..self.faces.len()).any(joins) {
            return Ok(());
        }
        let rows: Vec<bool> = (0..self.faces.len()).map(joins).collect();
        for (j, &r) in self.joined.iter_mut().zip(&rows) {
            *j |= r;
        }
        let a = self.regions.axis;
        let fg = self.fdm.level().geometry;
        // The bridge's FDM-grid cells along the axis, [lo, hi).
        let (lo, hi) = {
            let first = self.fdm_index(self.regions.first_bridge_cell());
            let w = self.regions.width;
            match self.regions.mpm_side {
                Side::High => (first, first + w),
                Side::Low => (first + 1 - w, first + 1),
            }
        };
        let ps = self.mpm.particles();
        self.leaving.clear();
        self.inits.clear();
        let mut change = ConservationTotals::default();
        for p in 0..ps.len() {
            let m = ps.material[p];
            let fluid = m == self.options.air || Some(m) == self.options.products;
            if !fluid {
                continue;
            }
            let Some(c) = fg.cell_containing(ps.position[p]) else {
                continue;
            };
            if c[a] < lo || c[a] >= hi || !rows[self.line_of(c)] {
                continue;
            }
            let (st, y) = self.primitive(c);
            let products = self.options.products.filter(|_| y >= 0.5);
            let e = self.particle_energy(c, &st, products.is_some());
            // The cell's state at the particle's own volume, as a donor
            // cell joins the MPM step (eqs 37–39).
            let cp = fdm_cell_as_particle(
                ps.position[p],
                st.density,
                st.velocity,
                st.pressure,
                ps.volume[p],
            );
            book(&mut change, cp.mass, cp.velocity, e);
            book(
                &mut change,
                -ps.mass[p],
                ps.velocity[p],
                ps.specific_internal_energy[p],
            );
            self.leaving.push(p);
            self.inits
                .push(particle_init(&cp, e, products.unwrap_or(self.options.air)));
        }
        self.mpm.remove_particles(&self.leaving);
        self.mpm
            .insert_particles(&self.inits)
            .map_err(|e| SolverError::Other(format!("bridge rows joining: {e}")))?;
        book_parts(
            &mut self.totals.into_mpm,
            change.mass,
            change.momentum,
            change.energy,
        );
        self.totals.restarted += self.inits.len() as u64;
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
            let start = match self.options.start_in_bridge {
                None => self.shock_near_interface(),
                Some(k) => (0..self.faces.len()).any(|f| self.shock_in_bridge(f, k)),
            };
            if start {
                self.active = true;
                self.activated_at = Some(self.time);
            }
            return Ok(());
        }
        let t = Instant::now();
        self.join_rows()?;
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
    /// Per face, whether its row has joined; the particles restarted.
    joined: Vec<bool>,
    restarted: u64,
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

    /// The FDM's or the MPM's limit, whichever step is the smaller (the
    /// FDM's alone before activation, as in step 1).
    /// A part whose step fails (a collapsed or non-physical one) is named.
    fn time_step_limit(&self) -> Option<String> {
        let Ok(f) = self.fdm.stable_dt() else {
            return self.fdm.time_step_limit();
        };
        match self.active.then(|| self.mpm.stable_dt()) {
            Some(Err(_)) => self.mpm.time_step_limit(),
            Some(Ok(m)) if m < f => self.mpm.time_step_limit(),
            _ => self.fdm.time_step_limit(),
        }
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

    /// The MPM side's particle gauges.
    fn sample_particle_gauge(
        &self,
        k: usize,
        quantities: &[brisance_core::SetQuantity],
        out: &mut Vec<f64>,
    ) -> bool {
        self.mpm().sample_particle_gauge(k, quantities, out)
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
            joined: self.joined.clone(),
            restarted: t.restarted,
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
        // As many faces as `pending` (checked above).
        self.joined = s.joined;
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
            restarted: s.restarted,
        };
        self.particle_steps = s.counts[6];
        Ok(())
    }
}

/// The MPM particle of a cell's state `cp` ([`fdm_cell_as_particle`]) with
/// specific internal energy `e`, of `material`.
fn particle_init(cp: &CellParticle, e: f64, material: MaterialId) -> ParticleInit {
    ParticleInit {
        position: cp.position,
        velocity: cp.velocity,
        mass: cp.mass,
        volume: cp.volume,
        stress: cp.stress,
        specific_internal_energy: e,
        material,
        ..Default::default()
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
mod tests;
