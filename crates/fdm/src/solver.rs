//! The FDM solver: Yanenko splitting (seed 001 eq 6), CFL time step,
//! positivity diagnostics and the [`Solver`] implementation.
//!
//! [`Solver`]: brisance_core::Solver

use std::borrow::Cow;
use std::cell::RefCell;
use std::sync::Arc;

use brisance_core::{ConservationTotals, ExactTotals, Geometry, SolverError};
use brisance_grid::comm::{self, Communicator};
use brisance_grid::{
    BoundaryConditions, CellOrder, FaceBc, FieldKind, FieldSet, HaloExchange, InProcessExchange,
    Level, PatchFields,
};
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

use crate::gas::GasLaw;
use crate::limiter::FaceLimiter;
use crate::state::{
    specific_internal_energy, PrimitiveState, CONSERVATIVE_NAMES, ENERGY, MOM, NVAR, RHO, SPECIES,
    SPECIES_NAME,
};
use crate::sweep::{
    sweep_slab, FaceOutflow, LimiterPass, PatchPtrs, RadialWeights, SlabOutcome, SlabShape, GHOST,
    GHOST_RZ,
};
use crate::viscosity::ArtificialViscosity;

mod memory;
mod solver_trait;

pub use memory::FdmMemory;

/// Why the FDM solver cannot be built.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum FdmError {
    /// A parameter is out of range.
    #[error("{0}")]
    Invalid(String),
}

/// Largest per-sweep Courant number for which Lax–Wendroff is stable.
pub const MAX_CFL: f64 = 1.0;

/// Solver options (`..Default::default()` for the rest).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FdmOptions {
    /// Courant number of each directional sweep:
    /// Δt = 2·cfl·min_d min_cells Δx_d / (|u_d| + c), since each sweep
    /// advances Δt/2 (seed 001 eq 6). Must lie in (0, 1].
    pub cfl: f64,
    /// The artificial viscosity law (seed 001 eqs 3–5).
    pub viscosity: ArtificialViscosity,
    /// Smallest time step before the run is stopped as collapsed, s.
    pub min_dt: f64,
    /// The face limiter of the sweep ([`FaceLimiter`], `Full` by
    /// default): at a face where the Lax–Wendroff update would leave a
    /// non-positive density or internal energy, or, at a shock, a density
    /// outside its neighbours' range, the flux is limited towards the
    /// local Lax–Friedrichs (Rusanov) flux (conservative, first order
    /// there only; `docs/physics/fdm.md`, "Face limiter"). Where it never
    /// acts the results are the bits of the scheme without it. `Off`: the
    /// scheme of seed 001 as printed, which stops at a non-physical state.
    pub limiter: FaceLimiter,
    /// How the grid's cells are read: boxes (`Cartesian`, the default) or
    /// rings about the axis x = 0 (`Axisymmetric`, an (r, z) grid with
    /// x = r and y = z): the radial sweep is then the finite-volume form
    /// with ring faces and the hoop source ([`crate::sweep`],
    /// `docs/physics/axisymmetric.md`), and totals are summed over ring
    /// volumes.
    pub geometry: Geometry,
}

impl Default for FdmOptions {
    fn default() -> Self {
        Self {
            cfl: 0.8,
            viscosity: ArtificialViscosity::Adaptive,
            min_dt: 1e-14,
            limiter: FaceLimiter::Full,
            geometry: Geometry::Cartesian,
        }
    }
}

/// A boundary condition of the Euler solver on one face.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum FdmBoundary {
    /// Zero gradient both ways: the ghosts copy the boundary cell, so a
    /// flow leaves freely and, where the boundary cell moves inwards, its
    /// state flows in (the config's `ZeroGradient`, and its `Outflow`).
    Outflow,
    /// Zero gradient for what leaves; where the boundary cell's normal
    /// velocity points into the domain the ghosts hold it at zero with the
    /// cell's density and internal energy (FLASH's "diode",
    /// [`brisance_grid::FaceBc::OutflowOnly`]), so the face holds back
    /// what would enter.
    OutflowOnly,
    /// Slip wall / symmetry plane.
    Reflective,
    /// Periodic (both faces of an axis).
    Periodic,
    /// A fixed inflow/ambient state (pure air, Y = 0, with a species).
    Fixed(PrimitiveState),
}

/// Faces swept and faces whose flux the face limiter changed (for
/// positivity, for the density bounds at a shock), since the start.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
struct LimiterCount {
    faces: u64,
    limited: [u64; 2],
}

/// x lines per work item of an x sweep.
const X_LINES: usize = 8;

/// Cells across the sweep per work item of a y or z sweep.
const CROSS_CELLS: usize = 64;

thread_local! {
    static SCRATCH: RefCell<Vec<f64>> = const { RefCell::new(Vec::new()) };
}

/// The Lax–Wendroff finite-difference Euler solver of seed 001 §2.1 for the
/// gas law `E`: one gas (any `Eos`) or detonation products in air
/// ([`crate::ProductsInAir`], with the partial density ρY stored).
#[derive(Debug)]
pub struct FdmSolver<E: GasLaw> {
    eos: E,
    level: Level,
    set: FieldSet,
    bcs: BoundaryConditions,
    fields: Vec<PatchFields>,
    exchange: InProcessExchange,
    /// The second buffer a sweep writes into (same shapes as `fields`);
    /// the two are swapped after each sweep.
    back: Vec<PatchFields>,
    /// Reused list of (patch, slab, chunk, state, second buffer) work items
    /// of a sweep.
    work_items: Vec<(usize, usize, usize, PatchPtrs, PatchPtrs)>,
    options: FdmOptions,
    /// What has left through each domain face since the start, per face
    /// cell, in the flow variables per unit cell volume ([`FaceOutflow`]);
    /// face 2d + s (s = 0 low, 1 high), its cells in global order of the
    /// two other axes (lower axis fastest). Empty for a periodic face and
    /// for a face of an inactive axis, which no sweep crosses.
    outflow: [Vec<[f64; NVAR]>; 6],
    /// What crossed each domain face in the current sweep attempt, added to
    /// `outflow` when the sweep is kept (same shapes).
    outflow_sweep: [Vec<[f64; NVAR]>; 6],
    /// How often the face limiter acted.
    limited: LimiterCount,
    /// Per patch, the ring weights (α₊, α₋) of the rows of its radial
    /// sweep ([`RadialWeights`]); empty on a Cartesian grid.
    radial: Vec<[Vec<f64>; 3]>,
    /// The ranks the patches are shared among ([`Self::with_species_on`],
    /// [`Self::distribute`]); one rank ([`comm::Serial`]) otherwise.
    comm: Arc<dyn Communicator>,
    /// The owner rank of every patch ([`comm::patch_owners`]). A rank
    /// stores and updates only its own patches; the others' entries of
    /// `fields` and `back` hold no arrays ([`PatchFields::unstored`]).
    owner: Vec<usize>,
    time: f64,
    steps: u64,
}

/// Global index of cell `n` of the accumulator of domain face `face`
/// (2d + s): its cells in global order of the two other axes, the lower
/// axis fastest.
fn face_cell(cells: [usize; 3], face: usize, n: usize) -> [usize; 3] {
    let axis = face / 2;
    let (a, b) = match axis {
        0 => (1, 2),
        1 => (0, 2),
        _ => (0, 1),
    };
    let mut c = [0; 3];
    c[axis] = if face.is_multiple_of(2) {
        0
    } else {
        cells[axis] - 1
    };
    c[a] = n % cells[a];
    c[b] = n / cells[a];
    c
}

/// The cells of a face normal to `axis`: the product of the other two
/// axes' cell counts.
fn face_cells(cells: [usize; 3], axis: usize) -> usize {
    (0..3).filter(|&d| d != axis).map(|d| cells[d]).product()
}

impl<E: GasLaw> FdmSolver<E> {
    /// Number of stored conservative fields (5, or 6 with ρY).
    const NFIELDS: usize = NVAR + E::SPECIES as usize;

    /// Builds the solver on `level` (built with [`GHOST`] ghost layers) with
    /// the initial state `init(cell centre)` (pure air where the gas law
    /// carries a species).
    pub fn new(
        eos: E,
        level: Level,
        boundaries: [FdmBoundary; 6],
        options: FdmOptions,
        init: impl Fn([f64; 3]) -> PrimitiveState + Sync,
    ) -> Result<Self, FdmError> {
        Self::with_species(eos, level, boundaries, options, |x| (init(x), 0.0))
    }

    /// As [`Self::new`] with `init` returning the state and the products
    /// mass fraction Y ∈ [0, 1] (ignored by a one-species gas law).
    pub fn with_species(
        eos: E,
        level: Level,
        boundaries: [FdmBoundary; 6],
        options: FdmOptions,
        init: impl Fn([f64; 3]) -> (PrimitiveState, f64) + Sync,
    ) -> Result<Self, FdmError> {
        let serial: Arc<dyn Communicator> = Arc::new(comm::Serial);
        Self::with_species_on(serial, eos, level, boundaries, options, init)
    }

    /// As [`Self::with_species`], the patches shared among the ranks of
    /// `comm` from the start (docs/cluster.md): this rank stores the
    /// fields of its own patches only, so a rank's memory is its share of
    /// the grid, and evaluates `init` on its own cells only, so its build
    /// costs its share. An initial state that fails stops every rank
    /// with the error of the first failing cell in patch order (found by
    /// one minimum over the ranks), as on one rank.
    pub fn with_species_on(
        comm: Arc<dyn Communicator>,
        eos: E,
        level: Level,
        boundaries: [FdmBoundary; 6],
        options: FdmOptions,
        init: impl Fn([f64; 3]) -> (PrimitiveState, f64) + Sync,
    ) -> Result<Self, FdmError> {
        if !(options.cfl > 0.0 && options.cfl <= MAX_CFL) {
            return Err(FdmError::Invalid(format!(
                "cfl = {} is outside (0, {MAX_CFL}]: the Lax-Wendroff sweep is unstable above a Courant number of 1",
                options.cfl
            )));
        }
        if let ArtificialViscosity::Constant(eta) = options.viscosity {
            if !(0.0..=0.25).contains(&eta) {
                return Err(FdmError::Invalid(format!(
                    "constant viscosity η = {eta} must lie in [0, 0.25]"
                )));
            }
        }
        for d in 0..3 {
            if level.is_active(d) && level.patches.iter().any(|p| p.ghost[d] < GHOST) {
                return Err(FdmError::Invalid(format!(
                    "the level needs {GHOST} ghost layers"
                )));
            }
        }
        if options.geometry.is_axisymmetric() {
            let g = &level.geometry;
            if g.cells[2] != 1 {
                return Err(FdmError::Invalid(format!(
                    "an axisymmetric (r, z) grid has one cell along z, got {}",
                    g.cells[2]
                )));
            }
            if !(g.origin[0] >= 0.0) {
                return Err(FdmError::Invalid(format!(
                    "an axisymmetric grid's x is the radius, which starts at r ≥ 0, got {}",
                    g.origin[0]
                )));
            }
            if g.origin[0] == 0.0 && !matches!(boundaries[0], FdmBoundary::Reflective) {
                return Err(FdmError::Invalid(
                    "the low x face of an axisymmetric grid is the axis r = 0 and must be reflective"
                        .into(),
                ));
            }
            if level.patches.iter().any(|p| p.ghost[0] < GHOST_RZ) {
                return Err(FdmError::Invalid(format!(
                    "an axisymmetric level needs {GHOST_RZ} ghost layers along r"
                )));
            }
            if matches!(boundaries[0], FdmBoundary::Periodic) {
                return Err(FdmError::Invalid(
                    "the radius of an axisymmetric grid cannot be periodic".into(),
                ));
            }
        }
        let mut set = FieldSet {
            names: CONSERVATIVE_NAMES.to_vec(),
            kinds: vec![
                FieldKind::Scalar,
                FieldKind::VectorComponent(0),
                FieldKind::VectorComponent(1),
                FieldKind::VectorComponent(2),
                FieldKind::Scalar,
            ],
        };
        if E::SPECIES {
            set.names.push(SPECIES_NAME);
            set.kinds.push(FieldKind::Scalar);
        }
        let mut faces: Vec<FaceBc> = Vec::with_capacity(6);
        for b in boundaries {
            faces.push(match b {
                FdmBoundary::Outflow => FaceBc::Outflow,
                FdmBoundary::OutflowOnly => FaceBc::OutflowOnly {
                    density: RHO,
                    energy: ENERGY,
                },
                FdmBoundary::Reflective => FaceBc::Reflective,
                FdmBoundary::Periodic => FaceBc::Periodic,
                FdmBoundary::Fixed(s) => FaceBc::Fixed({
                    let (u, ry) = s
                        .to_conservative_mixed(&eos, 0.0)
                        .map_err(|e| FdmError::Invalid(format!("fixed boundary state: {e}")))?;
                    let mut v = u.to_vec();
                    if E::SPECIES {
                        v.push(ry);
                    }
                    v
                }),
            });
        }
        let bcs = BoundaryConditions {
            faces: faces.try_into().expect("six faces"),
        };
        bcs.validate(Self::NFIELDS).map_err(FdmError::Invalid)?;

        let geometry = level.geometry;
        let outflow: [Vec<[f64; NVAR]>; 6] = std::array::from_fn(|f| {
            let axis = f / 2;
            if level.is_active(axis) && !matches!(boundaries[f], FdmBoundary::Periodic) {
                vec![[0.0; NVAR]; face_cells(geometry.cells, axis)]
            } else {
                Vec::new()
            }
        });
        let (owner, exchange) = patch_ranks(&level, &comm)?;
        // The conservative values (and ρY) of global cell `g`, or why its
        // initial state is not one.
        let cell_values = |g: [usize; 3]| -> Result<([f64; 5], f64), FdmError> {
            let (state, y) = init(geometry.cell_centre(g));
            if !(state.density > 0.0 && state.pressure > 0.0) {
                return Err(FdmError::Invalid(format!(
                    "initial state in cell {g:?} has density {} and pressure {}: both must be positive",
                    state.density, state.pressure
                )));
            }
            let y = if E::SPECIES { y } else { 0.0 };
            if !(0.0..=1.0).contains(&y) {
                return Err(FdmError::Invalid(format!(
                    "initial products mass fraction in cell {g:?} is {y}: it must lie in [0, 1]"
                )));
            }
            state
                .to_conservative_mixed(&eos, y)
                .map_err(|e| FdmError::Invalid(format!("initial state in cell {g:?}: {e}")))
        };
        // Each rank evaluates and stores its own patches' cells only; the
        // first failure in patch order over all ranks is evaluated again
        // by every rank, so all meet the same error.
        let mut fields: Vec<PatchFields> = (level.patches.iter().enumerate())
            .map(|(id, patch)| {
                if owner[id] == comm.rank() {
                    PatchFields::zeros(patch, Self::NFIELDS)
                } else {
                    PatchFields::unstored(patch, Self::NFIELDS)
                }
            })
            .collect();
        let failing = level.first_failing_cell(&*comm, &owner, CellOrder::Patches, |g, id, n| {
            let Ok((u, ry)) = cell_values(g) else {
                return false;
            };
            let pf = &mut fields[id];
            for (values, v) in pf.data.iter_mut().zip(u) {
                values[n] = v;
            }
            if E::SPECIES {
                pf.data[SPECIES][n] = ry;
            }
            true
        });
        if let Some(g) = failing {
            cell_values(g)?;
            return Err(FdmError::Invalid(
                "an initial state failed on another rank but not here".into(),
            ));
        }
        let radial = if options.geometry.is_axisymmetric() {
            let g = &level.geometry;
            level
                .patches
                .iter()
                .map(|p| {
                    // Row a of the patch's x sweep is global cell
                    // lo + a − ghost.
                    let first = p.lo[0] as i64 - p.ghost[0] as i64;
                    let mirror = [0, 1].map(|s| matches!(boundaries[s], FdmBoundary::Reflective));
                    RadialWeights::rows(
                        g.origin[0],
                        g.spacing[0],
                        first,
                        p.dims()[0],
                        g.cells[0],
                        mirror,
                    )
                })
                .collect()
        } else {
            Vec::new()
        };
        Ok(Self {
            eos,
            level,
            set,
            bcs,
            back: fields.clone(),
            fields,
            exchange,
            work_items: Vec::new(),
            options,
            outflow_sweep: outflow.clone(),
            outflow,
            limited: LimiterCount::default(),
            radial,
            comm,
            owner,
            time: 0.0,
            steps: 0,
        })
    }

    /// Shares the patches of a solver built on one rank among the ranks
    /// of `comm` (ranks of threads, `brisance_grid::comm::InProcess`, in
    /// tests; a run builds with [`Self::with_species_on`] instead, never
    /// holding the whole grid) and frees the fields of the patches other
    /// ranks own. Every rank builds the same solver and calls this before
    /// the first step. Fails when the patches cannot be shared, or when
    /// the solver was already spread (a patch it would own is not
    /// stored here).
    pub fn distribute(&mut self, comm: Arc<dyn Communicator>) -> Result<(), FdmError> {
        let (owner, exchange) = patch_ranks(&self.level, &comm)?;
        let rank = comm.rank();
        if (0..owner.len()).any(|id| owner[id] == rank && !self.fields[id].is_stored()) {
            return Err(FdmError::Invalid(
                "the patches are already shared among ranks: distribute a solver built on one rank"
                    .into(),
            ));
        }
        for (id, &o) in owner.iter().enumerate() {
            if o != rank {
                self.fields[id].release();
                self.back[id].release();
            }
        }
        self.owner = owner;
        self.exchange = exchange;
        self.comm = comm;
        Ok(())
    }

    /// The patches whose fields this rank stores: its own, in patch order
    /// (every patch on one rank).
    pub fn stored_patches(&self) -> Vec<usize> {
        (0..self.fields.len())
            .filter(|&id| self.fields[id].is_stored() && self.back[id].is_stored())
            .collect()
    }

    /// Whether this rank updates patch `id`.
    fn owns(&self, id: usize) -> bool {
        self.owner[id] == self.comm.rank()
    }

    /// Every patch's fields as its owner holds them: `fields` itself on
    /// one rank; on several, a copy whose every patch comes from its owner
    /// (a collective call: every rank makes it, and each holds a copy of
    /// the whole state while the result lives). What outputs, totals and
    /// checkpoints read, so that they sum and write in the order and with
    /// the bits of one rank.
    fn gathered(&self) -> Cow<'_, [PatchFields]> {
        comm::owners_fields(&*self.comm, &self.owner, &self.fields)
    }

    /// The face accumulators of [`Self::outflow`] as their owners hold
    /// them: each face cell's entry from the rank that owns its patch (a
    /// collective call on several ranks).
    fn gathered_outflow(&self) -> Cow<'_, [Vec<[f64; NVAR]>; 6]> {
        if self.comm.size() == 1 {
            return Cow::Borrowed(&self.outflow);
        }
        let cells = self.level.geometry.cells;
        let mut merged = self.outflow.clone();
        for (f, acc) in merged.iter_mut().enumerate() {
            if acc.is_empty() {
                continue;
            }
            let owners: Vec<usize> = (0..acc.len())
                .map(|n| {
                    let (pid, _) = self
                        .level
                        .locate(face_cell(cells, f, n))
                        .expect("a face cell lies in the grid");
                    self.owner[pid]
                })
                .collect();
            let mut buf = Vec::new();
            for root in 0..self.comm.size() {
                buf.clone_from(&self.outflow[f]);
                self.comm.broadcast(root, buf.as_flattened_mut());
                for ((a, b), &o) in acc.iter_mut().zip(&buf).zip(&owners) {
                    if o == root {
                        *a = *b;
                    }
                }
            }
        }
        Cow::Owned(merged)
    }

    /// The level the solver runs on.
    pub fn level(&self) -> &Level {
        &self.level
    }

    /// How the cells are read: boxes, or rings about the axis x = 0
    /// ([`FdmOptions::geometry`]).
    pub fn geometry(&self) -> Geometry {
        self.options.geometry
    }

    /// Steps taken so far.
    pub fn steps(&self) -> u64 {
        self.steps
    }

    /// The face limiter of the sweep ([`FdmOptions::limiter`]).
    pub fn limiter(&self) -> FaceLimiter {
        self.options.limiter
    }

    /// Sets the face limiter of the sweep ([`FdmOptions::limiter`]).
    pub fn set_limiter(&mut self, limiter: FaceLimiter) {
        self.options.limiter = limiter;
    }

    /// The gas law.
    pub fn gas(&self) -> &E {
        &self.eos
    }

    /// The stored conservative fields (ρ, ρu, ρv, ρw, E and, with a
    /// species, ρY) over the interior cells in global order (x fastest),
    /// one array per field.
    pub fn conservative_fields(&self) -> Vec<Vec<f64>> {
        self.level.gather_fields(&self.gathered())
    }

    /// Overwrites the conservative fields with arrays laid out as
    /// [`Self::conservative_fields`] gives them (an initial state remapped
    /// from another grid, or values set by a coupling). Fails, changing
    /// nothing, when the number of arrays or their lengths do not match.
    pub fn set_conservative_fields(&mut self, fields: &[Vec<f64>]) -> Result<(), FdmError> {
        let cells = self.level.geometry.cell_count();
        if fields.len() != Self::NFIELDS || fields.iter().any(|f| f.len() != cells) {
            return Err(FdmError::Invalid(format!(
                "conservative fields: expected {} arrays of {cells} values, got {} arrays of lengths {:?}",
                Self::NFIELDS,
                fields.len(),
                fields.iter().map(Vec::len).collect::<Vec<_>>()
            )));
        }
        self.level.scatter_fields(&mut self.fields, fields);
        Ok(())
    }

    /// The stored conservative values of global cell `g` (5, or 6 with
    /// ρY), or `None` outside the grid.
    pub fn cell_conservative(&self, g: [usize; 3]) -> Option<[f64; 6]> {
        let (pid, n) = self.level.locate(g)?;
        let fields = self.gathered();
        let d = &fields[pid].data;
        Some(std::array::from_fn(|f| d.get(f).map_or(0.0, |v| v[n])))
    }

    /// Overwrites the stored conservative values of global cell `g` (the
    /// sixth value, ρY, is ignored without a species); on several ranks
    /// the rank that owns the cell's patch stores them. Fails outside the
    /// grid.
    pub fn set_cell_conservative(
        &mut self,
        g: [usize; 3],
        values: [f64; 6],
    ) -> Result<(), FdmError> {
        let (pid, n) = self
            .level
            .locate(g)
            .ok_or_else(|| FdmError::Invalid(format!("cell {g:?} lies outside the FDM grid")))?;
        if self.owns(pid) {
            for (f, v) in self.fields[pid].data.iter_mut().enumerate() {
                v[n] = values[f];
            }
        }
        Ok(())
    }

    /// One directional operator L_axis(Δt/2) on every patch (seed 001 eq 6
    /// factor), after filling the ghost layers along `axis`. The update is
    /// written into the second buffer, so the sweep can be taken again: with
    /// the face limiter on, the first attempt keeps only the density bounds
    /// at shocks and checks that every update stays positive; if one cell
    /// anywhere does not, the whole sweep is taken again with the limiter
    /// keeping positivity at every face (`docs/physics/fdm.md`, "Face
    /// limiter"). The choice is the same whatever the patch split or thread
    /// count (a cell fails or not), and a sweep that needs no positivity
    /// limiting costs one vectorised check.
    fn sweep(&mut self, axis: usize, dt_sweep: f64) -> Result<(), SolverError> {
        self.exchange
            .fill_axis(&self.level, &self.set, &self.bcs, &mut self.fields, axis);
        let lambda = dt_sweep / self.level.geometry.spacing[axis];
        let limiter = self.options.limiter;
        let first = if limiter.positivity() {
            LimiterPass::First {
                bounds: limiter.shock_bounds(),
            }
        } else {
            LimiterPass::Off
        };
        let mut outcome = self.sweep_attempt(axis, lambda, first);
        if !outcome.physical {
            return Err(
                self.non_physical_error(&format!("during the {} sweep", ["x", "y", "z"][axis]))
            );
        }
        if !outcome.positive {
            let full = LimiterPass::Full {
                bounds: limiter.shock_bounds(),
            };
            outcome = self.sweep_attempt(axis, lambda, full);
        }
        // The second buffer holds the result: make it the state, and book
        // what crossed the domain faces.
        for (front, back) in self.fields.iter_mut().zip(self.back.iter_mut()) {
            std::mem::swap(&mut front.data, &mut back.data);
        }
        for f in [2 * axis, 2 * axis + 1] {
            for (acc, add) in self.outflow[f].iter_mut().zip(&self.outflow_sweep[f]) {
                for (a, b) in acc.iter_mut().zip(add) {
                    *a += b;
                }
            }
        }
        // Faces swept: (n_axis + 1) per line, over the lines across.
        let cells = self.level.geometry.cells;
        let lines = face_cells(cells, axis) as u64;
        self.limited.faces += lines * (cells[axis] as u64 + 1);
        for (total, n) in self.limited.limited.iter_mut().zip(outcome.limited_faces) {
            *total += n;
        }
        Ok(())
    }

    /// One attempt at the sweep along `axis` with λ = Δt_s/Δx and the face
    /// limiter's `pass`: reads the state, writes the second buffer and, in
    /// the sweep's accumulators (cleared first), what crosses the domain
    /// faces.
    fn sweep_attempt(&mut self, axis: usize, lambda: f64, pass: LimiterPass) -> SlabOutcome {
        let (eos, visc) = (&self.eos, self.options.viscosity);
        // Work items: (patch, slab, chunk). x and y sweeps slab by
        // k-planes, z sweeps by j-planes; within a slab, an x sweep's lines
        // are taken X_LINES at a time and a y or z sweep's columns
        // CROSS_CELLS at a time, so that a 2D grid (a single k-plane) still
        // spreads over the threads. Items write disjoint cells, and every
        // cell's arithmetic is the same whatever the chunk, so the result
        // is the same bits for any thread count.
        let slab_axis = if axis == 2 { 1 } else { 2 };
        // Lines across which an item spans: j for x sweeps, i otherwise.
        let (across, chunk) = if axis == 0 {
            (1, X_LINES)
        } else {
            (0, CROSS_CELLS)
        };
        // The list is rebuilt in place, so a warmed-up step allocates nothing.
        let mut items = std::mem::take(&mut self.work_items);
        items.clear();
        let rank = self.comm.rank();
        for (id, (f, b)) in self.fields.iter_mut().zip(self.back.iter_mut()).enumerate() {
            if self.owner[id] != rank {
                continue;
            }
            let (ptrs, out) = (PatchPtrs::new(&mut f.data), PatchPtrs::new(&mut b.data));
            let size = self.level.patches[id].size;
            let n = size[slab_axis];
            let chunks = size[across].div_ceil(chunk);
            items.extend((0..n).flat_map(|s| (0..chunks).map(move |c| (id, s, c, ptrs, out))));
        }
        let level = &self.level;
        let radial = &self.radial;
        let cells = level.geometry.cells;
        let [low, high] = [2 * axis, 2 * axis + 1].map(|f| {
            let v = &mut self.outflow_sweep[f];
            v.fill([0.0; NVAR]);
            if v.is_empty() {
                std::ptr::null_mut()
            } else {
                v.as_mut_ptr()
            }
        });
        let faces = FaceOutflow { low, high };
        let outcome = items
            .par_iter()
            .map(|&(id, slab, c, ptrs, out)| {
                let p = &level.patches[id];
                let (g, d, st) = (p.ghost, p.dims(), p.strides());
                let lo = c * chunk;
                let hi = (lo + chunk).min(p.size[across]);
                // The item's first face cell: global (j, k) of its first x
                // line (line j adds j − lo), (i, k) or (i, j) of a y or z
                // slab.
                let first = match axis {
                    0 => p.lo[1] + lo + cells[1] * (p.lo[2] + slab),
                    1 => p.lo[0] + lo + cells[0] * (p.lo[2] + slab),
                    _ => p.lo[0] + lo + cells[0] * (p.lo[1] + slab),
                };
                let at_low = p.lo[axis] == 0;
                let at_high = p.lo[axis] + p.size[axis] == cells[axis];
                // SAFETY (of the `add`s): `first` + the item's lanes lie
                // within the face's array, and no other item shares them.
                let outflow =
                    |offset: usize| unsafe { faces.lanes_on(first + offset, at_low, at_high) };
                let shape = match axis {
                    0 => SlabShape {
                        dims_a: d[0],
                        ghost: g[0],
                        stride_a: 1,
                        base: 0,
                        width: 0,
                        at_low,
                    },
                    1 => SlabShape {
                        dims_a: d[1],
                        ghost: g[1],
                        stride_a: st[1],
                        base: p.local_index([g[0] + lo, 0, g[2] + slab]),
                        width: hi - lo,
                        at_low,
                    },
                    _ => SlabShape {
                        dims_a: d[2],
                        ghost: g[2],
                        stride_a: st[2],
                        base: p.local_index([g[0] + lo, g[1] + slab, 0]),
                        width: hi - lo,
                        at_low,
                    },
                };
                SCRATCH.with(|s| {
                    let mut scratch = s.borrow_mut();
                    if axis == 0 {
                        let weights = radial.get(id).map(|[plus, minus, source]| RadialWeights {
                            plus,
                            minus,
                            source,
                        });
                        let mut ok = SlabOutcome::NONE;
                        for j in lo..hi {
                            let line = SlabShape {
                                base: p.local_index([0, g[1] + j, g[2] + slab]),
                                ..shape
                            };
                            // SAFETY: x lines of distinct (j, k) are disjoint.
                            ok = ok.and(unsafe {
                                sweep_slab::<0, E>(
                                    eos,
                                    visc,
                                    pass,
                                    lambda,
                                    &ptrs,
                                    &out,
                                    &line,
                                    weights,
                                    outflow(j - lo),
                                    &mut scratch,
                                )
                            });
                        }
                        ok
                    } else if axis == 1 {
                        // SAFETY: distinct k-planes are disjoint.
                        unsafe {
                            sweep_slab::<1, E>(
                                eos,
                                visc,
                                pass,
                                lambda,
                                &ptrs,
                                &out,
                                &shape,
                                None,
                                outflow(0),
                                &mut scratch,
                            )
                        }
                    } else {
                        // SAFETY: distinct j-planes are disjoint.
                        unsafe {
                            sweep_slab::<2, E>(
                                eos,
                                visc,
                                pass,
                                lambda,
                                &ptrs,
                                &out,
                                &shape,
                                None,
                                outflow(0),
                                &mut scratch,
                            )
                        }
                    }
                })
            })
            .reduce(|| SlabOutcome::NONE, SlabOutcome::and);
        self.work_items = items;
        if self.comm.size() == 1 {
            return outcome;
        }
        // The whole grid's finding, so that every rank takes the same
        // branch (a second attempt, or the error).
        let mut v = [
            u64::from(!outcome.physical),
            u64::from(!outcome.positive),
            outcome.limited_faces[0],
            outcome.limited_faces[1],
        ];
        self.comm.sum(&mut v);
        SlabOutcome {
            physical: v[0] == 0,
            positive: v[1] == 0,
            limited_faces: [v[2], v[3]],
        }
    }

    /// Mass (kg), momentum (kg m/s) and energy (J) of the interior cells,
    /// each summed exactly and rounded once ([`ExactTotals`]), so the bits
    /// do not depend on the order: each rank sums its own patches and the
    /// sums are merged (a collective call on several ranks).
    ///
    /// On an axisymmetric grid each cell counts with its ring volume
    /// π(r₊² − r₋²)Δz: the mass, the axial momentum (y) and the energy
    /// are the whole body's; the radial momentum (x) is the sum of the
    /// rings' ρu_r V, which is no conserved quantity (the hoop source
    /// changes it; by symmetry the body's momentum normal to the axis is
    /// zero), and the third component stays 0.
    pub fn interior_totals(&self) -> ConservationTotals {
        let rank = self.comm.rank();
        let axisymmetric = self.options.geometry.is_axisymmetric();
        let mut t = ExactTotals::default();
        self.level.for_each_cell_of(
            |pid| self.owner[pid] == rank,
            |g, pid, n| {
                let d = &self.fields[pid].data;
                if axisymmetric {
                    let v = self.ring_volume(g[0]);
                    t.add(
                        d[RHO][n] * v,
                        std::array::from_fn(|a| d[MOM + a][n] * v),
                        d[ENERGY][n] * v,
                    );
                } else {
                    t.add(
                        d[RHO][n],
                        std::array::from_fn(|a| d[MOM + a][n]),
                        d[ENERGY][n],
                    );
                }
            },
        );
        comm::merge_exact(&*self.comm, &mut t.sums);
        if axisymmetric {
            t.totals()
        } else {
            self.scaled_by_cell_volume(t.totals())
        }
    }

    /// Volume of the ring of an axisymmetric grid's cells in column `i`,
    /// π(r₊² − r₋²)Δz ([`Geometry::cell_volume`]).
    fn ring_volume(&self, i: usize) -> f64 {
        self.options
            .geometry
            .column_cell_volume(&self.level.geometry, i)
    }

    /// What one unit of a face accumulator of [`Self::outflow`] stands
    /// for on an axisymmetric grid: the accumulators hold λΦ per unit
    /// area of the face (Φ the flux per unit area over the sweep, λ =
    /// Δt/Δx), so the amount through a face cell is the value times the
    /// face's area times the spacing across it: 2π r_f Δz·Δr at a radial
    /// face, the annulus times Δz (the ring's volume) at an axial one.
    fn ring_face_weight(&self, face: usize, cell: [usize; 3]) -> f64 {
        let g = &self.level.geometry;
        let geometry = self.options.geometry;
        match face / 2 {
            0 => {
                let i = if face.is_multiple_of(2) {
                    0
                } else {
                    g.cells[0]
                };
                let r = g.origin[0] + i as f64 * g.spacing[0];
                geometry.x_face_area(r, g.spacing[1], g.spacing[2]) * g.spacing[0]
            }
            _ => self.ring_volume(cell[0]),
        }
    }

    /// What has left through the domain faces since the start: mass (kg),
    /// momentum (kg m/s) and energy (J), negative for what came in. The
    /// flux of every sweep through a non-periodic domain face, with the
    /// fluxes its update used (the smoothing's and the Richtmyer step's,
    /// after any positivity fallback), accumulated per face cell. At a
    /// reflective face no mass or energy crosses, and the momentum is the
    /// wall's pressure impulse.
    pub fn outflow(&self) -> ConservationTotals {
        self.outflow_where(|_, _| true)
    }

    /// [`Self::outflow`] through the face cells `keep(face, cell)` accepts:
    /// `face` = 2d + s (s = 0 the low face normal to axis d, 1 the high
    /// one) and `cell` the global index of the interior cell at it. Summed
    /// exactly, each face cell's entry by the rank that owns its patch (a
    /// collective call on several ranks).
    pub fn outflow_where(&self, keep: impl Fn(usize, [usize; 3]) -> bool) -> ConservationTotals {
        let cells = self.level.geometry.cells;
        let axisymmetric = self.options.geometry.is_axisymmetric();
        let several = self.comm.size() > 1;
        let rank = self.comm.rank();
        let mut t = ExactTotals::default();
        for (f, acc) in self.outflow.iter().enumerate() {
            for (n, u) in acc.iter().enumerate() {
                let c = face_cell(cells, f, n);
                // Each face cell's entry from the rank that owns it.
                let mine = !several || {
                    let (pid, _) = self.level.locate(c).expect("a face cell lies in the grid");
                    self.owner[pid] == rank
                };
                if mine && keep(f, c) {
                    let w = if axisymmetric {
                        self.ring_face_weight(f, c)
                    } else {
                        1.0
                    };
                    t.add(
                        w * u[RHO],
                        std::array::from_fn(|d| w * u[MOM + d]),
                        w * u[ENERGY],
                    );
                }
            }
        }
        comm::merge_exact(&*self.comm, &mut t.sums);
        if axisymmetric {
            return t.totals();
        }
        self.scaled_by_cell_volume(t.totals())
    }

    fn scaled_by_cell_volume(&self, mut t: ConservationTotals) -> ConservationTotals {
        let vol: f64 = self.level.geometry.spacing.iter().product();
        t.mass *= vol;
        t.momentum = t.momentum.map(|m| m * vol);
        t.energy *= vol;
        t
    }

    /// Products mass fraction Y of the interior cell `n` of patch `pid` (0
    /// without a species).
    fn mass_fraction(fields: &[PatchFields], pid: usize, n: usize) -> f64 {
        if E::SPECIES {
            let d = &fields[pid].data;
            d[SPECIES][n] / d[RHO][n]
        } else {
            0.0
        }
    }

    /// Primitive values of the interior cell at storage index `n` of patch
    /// `pid` of `fields`: (ρ, u, e, p).
    fn primitive(&self, fields: &[PatchFields], pid: usize, n: usize) -> (f64, [f64; 3], f64, f64) {
        let d = &fields[pid].data;
        let rho = d[RHO][n];
        let m = [d[MOM][n], d[MOM + 1][n], d[MOM + 2][n]];
        let e = specific_internal_energy(rho, m[0], m[1], m[2], d[ENERGY][n]);
        let y = Self::mass_fraction(fields, pid, n);
        (rho, m.map(|x| x / rho), e, self.eos.gas_pressure(rho, e, y))
    }

    /// Locates the first non-physical interior cell (global order) and
    /// describes it.
    fn non_physical_error(&self, when: &str) -> SolverError {
        let mut found = None;
        let fields = self.gathered();
        self.level.for_each_cell_in_order(|g, pid, n| {
            if found.is_none() {
                let (rho, u, e, p) = self.primitive(&fields, pid, n);
                let bad =
                    !(rho > 0.0 && p > 0.0 && p.is_finite() && u.iter().all(|x| x.is_finite()));
                if bad {
                    found = Some((g, rho, u, e, p));
                }
            }
        });
        match found {
            Some((cell, rho, u, e, p)) => SolverError::NonPhysicalState {
                time: self.time,
                cell,
                centre: self.level.geometry.cell_centre(cell),
                detail: format!(
                    "density {rho:e} kg/m³, velocity ({:e}, {:e}, {:e}) m/s, specific internal energy {e:e} J/kg, pressure {p:e} Pa ({when})",
                    u[0], u[1], u[2]
                ),
            },
            // The bad value sat in a ghost cell fed by a fixed boundary state.
            None => SolverError::Other(format!("non-physical ghost state at t = {:e} s ({when})", self.time)),
        }
    }

    /// Value of a named output field at interior cell `n` of patch `pid`
    /// of `fields`.
    fn derived(&self, fields: &[PatchFields], pid: usize, n: usize, field: usize) -> f64 {
        let (rho, u, e, p) = self.primitive(fields, pid, n);
        let y = Self::mass_fraction(fields, pid, n);
        match field {
            0 => rho,
            1..=3 => u[field - 1],
            4 => p,
            5 => e,
            6 => self.eos.gas_temperature(rho, e, y),
            7 => self.eos.gas_sound_speed(rho, e, y),
            8 => fields[pid].data[ENERGY][n],
            9 => {
                let c = self.eos.gas_sound_speed(rho, e, y);
                (u[0] * u[0] + u[1] * u[1] + u[2] * u[2]).sqrt() / c
            }
            _ => y,
        }
    }

    /// Name of the products mass fraction output field (species runs only).
    pub const MASS_FRACTION_FIELD: &'static str = "products_mass_fraction";

    /// Output field names, in the order `derived` numbers them.
    pub const FIELDS: [&'static str; 10] = [
        "density",
        "velocity_x",
        "velocity_y",
        "velocity_z",
        "pressure",
        "specific_internal_energy",
        "temperature",
        "sound_speed",
        "total_energy_density",
        "mach_number",
    ];

    fn field_index(name: &str) -> Result<usize, SolverError> {
        if E::SPECIES && name == Self::MASS_FRACTION_FIELD {
            return Ok(Self::FIELDS.len());
        }
        Self::FIELDS.iter().position(|f| *f == name).ok_or_else(|| {
            SolverError::Other(format!(
                "unknown field `{name}`; known fields: {}",
                Self::field_names().join(", ")
            ))
        })
    }

    /// The output fields of this gas law: [`Self::FIELDS`], and the products
    /// mass fraction with a species.
    pub fn field_names() -> Vec<&'static str> {
        let mut names = Self::FIELDS.to_vec();
        if E::SPECIES {
            names.push(Self::MASS_FRACTION_FIELD);
        }
        names
    }

    /// Total mass of detonation products Σ ρY ΔV, kg (0 without a species),
    /// summed in global cell order.
    pub fn products_mass(&self) -> f64 {
        if !E::SPECIES {
            return 0.0;
        }
        let mut m = 0.0;
        let fields = self.gathered();
        if self.options.geometry.is_axisymmetric() {
            self.level.for_each_cell_in_order(|g, pid, n| {
                m += fields[pid].data[SPECIES][n] * self.ring_volume(g[0])
            });
            return m;
        }
        self.level
            .for_each_cell_in_order(|_, pid, n| m += fields[pid].data[SPECIES][n]);
        m * self.level.geometry.spacing.iter().product::<f64>()
    }
}

/// The owner of every patch of `level` among the ranks of `comm`
/// ([`comm::patch_owners`]) and the ghost exchange between them.
fn patch_ranks(
    level: &Level,
    comm: &Arc<dyn Communicator>,
) -> Result<(Vec<usize>, InProcessExchange), FdmError> {
    if comm.size() > 1 {
        let owner =
            comm::patch_owners(level.patches.len(), comm.size()).map_err(FdmError::Invalid)?;
        let exchange = InProcessExchange::distributed(comm.clone(), owner.clone());
        Ok((owner, exchange))
    } else {
        Ok((vec![0; level.patches.len()], InProcessExchange::new()))
    }
}
