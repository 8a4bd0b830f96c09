//! The ICE solver: the fluid steps of seed 000 §3.3 in order, the CFL
//! time step and the [`Solver`] implementation.
//!
//! One call of [`Solver::advance`] is
//! 3. [`IceSolver::compute_face_centred_velocities`] (eq 19 + face exchange),
//! 5. [`IceSolver::compute_pressure_increment`] (eqs 20–21),
//! 6–9. [`IceSolver::compute_lagrangian_values`] (eqs 22–28), with
//! 10. momentum and heat exchange (eqs 29–30) and
//! 11. the specific-volume evolution (eqs 31–32) in the same cell visit,
//! 12. [`IceSolver::advect_fluids`],
//! 2. [`IceSolver::compute_equilibration_pressure`] (eq 7) for the new
//!    state, so that the state between steps (outputs, checkpoints, the
//!    next time step) is always equilibrated.
//!
//! Steps 1, 4, 7, 13 and 14 of the seed concern particles (MPM) and
//! reactions; they belong to the coupled pipeline and the reaction models.
//!
//! Every kernel visits one patch (ghost layers filled by the grid's halo
//! exchange) and writes only that patch; patches run in parallel under
//! rayon, and every value is a function of the cell's neighbourhood alone,
//! so the bits do not depend on the thread count or the patch split.

use brisance_core::{
    CellData, ConservationTotals, Eos, Geometry, ReactionModel, ReactionState, Solver, SolverError,
};
use brisance_grid::{
    BoundaryConditions, Face, FaceBc, FieldKind, FieldSet, HaloExchange, InProcessExchange, Level,
    Patch, PatchFields,
};
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

use crate::advection::{donor_carried, donor_volume_slab, Advection};
use crate::boundary::{holds_back_inflow, outflow_face_velocity};
use crate::equilibration::{
    equilibration_pressure, EquilibrationReport, EquilibrationSettings, MAX_MATERIALS,
};
use crate::exchange::{
    heat_exchange, momentum_exchange, slip_coefficients, slip_momentum_exchange, SolidExchange,
};
use crate::face_velocity::{face_velocity_damped, pressure_term_time};
use crate::lagrangian::{
    isentropic_energy_change, lagrangian_energy, lagrangian_momentum, lagrangian_volume,
    thermal_expansion_term, volume_change_share, volume_shares, VolumeShares,
};
use crate::pressure::{face_pressure, pressure_increment};
use crate::reaction::{transfer_burnt_mass, BurntMass, IceReaction, Parcel, REACTANT_LEFT};
use crate::{CellState, ExchangeCoefficients, IceBoundary, IceError};
use std::sync::atomic::{AtomicBool, Ordering};

/// The solver's [`Params`] from the fields they read. A macro rather
/// than a method: a method would borrow the whole solver, and the passes
/// mutate other fields (state, scratch, press, lag) while they hold the
/// params.
macro_rules! solver_params {
    ($s:expr) => {
        $crate::solver::Params {
            specific_heat: &$s.specific_heat,
            ..make_params(
                &$s.eos,
                &$s.reactions,
                &$s.exchange,
                $s.options,
                &$s.level,
                &$s.lagrangian,
                $s.time,
            )
        }
    };
}

mod build;
mod cell_steps;
mod coupling;
// Viscous stress and heat conduction (seed 000 eqs 2–3).
mod diffusion_pass;
pub mod implicit;
mod par;
mod ranks;
mod solver_trait;
mod steps;

pub use ranks::WholeGridPass;
mod slip;
mod surface;

#[cfg(test)]
mod advection_cold_rule_tests;
#[cfg(test)]
mod axisymmetric_tests;
#[cfg(test)]
mod cold_trace_tests;
#[cfg(test)]
mod gather_tests;
#[cfg(test)]
mod thermal_volume_tests;
#[cfg(test)]
mod time_step_tests;

use cell_steps::*;
use implicit::PressureSolve;
use par::*;

/// Ghost layers the solver needs (van Leer differences of a donor that is
/// itself a ghost cell).
pub const GHOST: usize = 2;

/// Per-material fields of the state group, in storage order.
const RHO: usize = 0;
const VEL: usize = 1;
const ENERGY: usize = 4;
const VSP: usize = 5;
const THETA: usize = 6;
const TEMP: usize = 7;
const SOUND: usize = 8;
/// Fields per material in the state group; the cell's equilibration
/// pressure follows the last material.
const NS: usize = 9;
/// Per-material fields of the Lagrangian group (ρ, u, e, v after steps
/// 8–11).
const L_RHO: usize = 0;
const L_VEL: usize = 1;
const L_ENERGY: usize = 4;
const L_VSP: usize = 5;
const NL: usize = 6;

/// Solver options (`..Default::default()` for the rest).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct IceOptions {
    /// Courant number: Δt = cfl / max over cells of
    /// Σ_d max_r (|u_r,d| + c_r)/Δx_d, and of a surface burn's front
    /// ([`IceSolver::surface_front_rate`]). In (0, 1].
    pub cfl: f64,
    /// Advection scheme of step 12.
    pub advection: Advection,
    /// Gravity, m/s².
    pub gravity: [f64; 3],
    /// Smallest time step before the run is stopped as collapsed, s.
    pub min_dt: f64,
    /// Largest time step, s (> 0; default ∞). The explicit pressure's
    /// acoustic limit is always finite; the implicit pressure's follows the
    /// material velocities, moving walls and a burning front only, and is
    /// infinite for a state at rest without them, where heat exchange or a
    /// volume reaction would then take one unbounded step.
    pub max_dt: f64,
    /// Convergence of the equilibration pressure.
    pub equilibration: EquilibrationSettings,
    /// Conserve total energy (see `docs/physics/ice/steps.md`): the
    /// Lagrangian phase closes each cell's energy budget with the face
    /// pressure work −Δt∇·(p* Σθ*u*), and step 12 advects each material's
    /// total specific energy e + ½|u|² instead of e, so the kinetic energy
    /// numerical dissipation removes stays as heat — which correct shock
    /// jumps need. `false` follows eqs 25 and step 12 literally.
    pub conserve_total_energy: bool,
    /// Step 2 holds each material's specific internal energy fixed and
    /// solves eq 7 with its own pressure law p_r(v_r, e_r)
    /// ([`crate::equilibration::equilibration_pressure_at_fixed_energy`]),
    /// instead of moving it along its isotherm at the temperature of its
    /// old state and keeping e_r. For ideal gases the two agree; for a
    /// stiffened gas or a solid they do not, and the isothermal form can
    /// leave a material off its own EOS (docs/physics/ice/water_air.md).
    /// Off by default: it costs about a third more per step.
    pub fixed_energy_equilibration: bool,
    /// Steps 3 and 5 explicit (eqs 19–21 as printed, Δt at the sound-speed
    /// CFL) or implicit in the pressure ([`implicit`], Δt at the
    /// material-velocity CFL). Explicit by default.
    pub pressure: PressureSolve,
    /// Cartesian cells (the default) or axisymmetric (r, z) rings: x is
    /// the radius, y the axis, one cell along z (docs/physics/axisymmetric.md,
    /// "The ICE in r–z").
    pub geometry: Geometry,
    /// ν* in [0, 1]: the explicit step 3 takes eq 19's pressure term over
    /// a Courant-ν* step when ν* > `cfl`
    /// ([`crate::face_velocity::pressure_term_time`]), so that its damping
    /// of shocks does not fade with Δt. 0 (default): eq 19 as printed.
    /// Ignored with the implicit pressure.
    pub face_pressure_courant: f64,
    /// The momentum exchange between the fluids and the materials carried
    /// by particles in the cells and faces of their surface (steps 3 and
    /// 10): seed 000 eq 29 on every component (`Isotropic`, the default)
    /// or across the surface only (`Slip`, [`crate::exchange`]). Without
    /// particle materials the two are the same.
    pub solid_exchange: SolidExchange,
}

impl Default for IceOptions {
    fn default() -> Self {
        Self {
            cfl: 0.4,
            advection: Advection::VanLeer,
            gravity: [0.0; 3],
            min_dt: 1e-14,
            max_dt: f64::INFINITY,
            equilibration: EquilibrationSettings::default(),
            conserve_total_energy: true,
            fixed_energy_equilibration: false,
            pressure: PressureSolve::Explicit,
            geometry: Geometry::Cartesian,
            face_pressure_courant: 0.0,
            solid_exchange: SolidExchange::Isotropic,
        }
    }
}

/// Work arrays of one patch that no halo exchange touches.
#[derive(Debug, Clone)]
struct PatchScratch {
    /// Σ_r ∇·(θ*_r u*_r) per cell, 1/s (eq 20's numerator).
    divergence: Vec<f64>,
    /// Face velocities u*_r per axis and material, stored at the cell on
    /// the face's high side (the face is that cell's low face).
    face_velocity: [Vec<Vec<f64>>; 3],
    /// Σ_r θ*_r u*_r on the low face of each cell per axis, m/s (the
    /// volume flux of eq 20, kept for the energy-conserving work).
    volume_flux: [Vec<f64>; 3],
    /// Face fluxes of one material along one axis (step 5: one per axis;
    /// step 12: mass, momentum, energy and volume), stored at the cell on
    /// the face's high side: each face is evaluated once and differenced
    /// by the two cells it bounds.
    flux: [Vec<f64>; 6],
    /// The carried energy of one material per cell (e, or e + ½|u|² when
    /// total energy is advected), so that it is formed once per cell.
    carried_energy: Vec<f64>,
    /// Axisymmetric grids: per local x index (ghosts included) the ratios
    /// r₋/r_c and r₊/r_c of the radii of the cell's low and high radial
    /// faces to its centre's ([`ring_weights`]). Empty on Cartesian grids.
    ring_lo: Vec<f64>,
    ring_hi: Vec<f64>,
    /// Per reaction: the reactant's surface (area per unit cell volume a/V
    /// and temperature) for a surface-burning reaction (step 2's
    /// [`IceSolver::find_reaction_surfaces`]); empty for the others.
    surface: Vec<surface::SurfaceCells>,
}

impl PatchScratch {
    /// The zeroed work arrays of `patch` of `level` for `n` materials (and
    /// its ring weights on an axisymmetric grid).
    fn zeros(level: &Level, p: &Patch, n: usize, axisymmetric: bool) -> Self {
        let cells = p.allocated_cells();
        let (ring_lo, ring_hi) = if axisymmetric {
            ring_weights(level, p)
        } else {
            (Vec::new(), Vec::new())
        };
        Self {
            divergence: vec![0.0; cells],
            face_velocity: std::array::from_fn(|d| {
                if level.is_active(d) {
                    (0..n).map(|_| vec![0.0; cells]).collect()
                } else {
                    Vec::new()
                }
            }),
            volume_flux: std::array::from_fn(|_| vec![0.0; cells]),
            flux: std::array::from_fn(|_| vec![0.0; cells]),
            carried_energy: vec![0.0; cells],
            ring_lo,
            ring_hi,
            surface: Vec::new(),
        }
    }

    /// No arrays: the patch belongs to another rank.
    fn empty() -> Self {
        Self {
            divergence: Vec::new(),
            face_velocity: Default::default(),
            volume_flux: Default::default(),
            flux: Default::default(),
            carried_energy: Vec::new(),
            ring_lo: Vec::new(),
            ring_hi: Vec::new(),
            surface: Vec::new(),
        }
    }

    /// Frees the arrays: the patch belongs to another rank.
    fn release(&mut self) {
        *self = Self::empty();
    }
}

/// The face-radius ratios of [`PatchScratch::ring_lo`] and `ring_hi` for
/// the local columns of `patch` (ghosts included) on an axisymmetric
/// `level`. A ring's volume is 2π r_c Δr Δz
/// with r_c the mid-radius, and its radial faces' areas are 2π r± Δz, so
/// per unit volume a flux F through them counts as F r±/(r_c Δr). Ghost
/// columns at negative radius get 1 (never read).
fn ring_weights(level: &Level, patch: &Patch) -> (Vec<f64>, Vec<f64>) {
    let (origin, dr) = (level.geometry.origin[0], level.geometry.spacing[0]);
    (0..patch.dims()[0])
        .map(|la| {
            let i = patch.lo[0] as f64 + la as f64 - patch.ghost[0] as f64;
            let r_lo = origin + i * dr;
            let r_c = r_lo + 0.5 * dr;
            if r_c > 0.0 {
                (r_lo / r_c, (r_lo + dr) / r_c)
            } else {
                (1.0, 1.0)
            }
        })
        .unzip()
}

/// The volume of each cell by its global linear index: Δx Δy Δz, or the
/// ring π(r₊² − r₋²)Δz = 2π r_c Δr Δz of its column on an axisymmetric grid.
#[derive(Debug, Clone, Copy)]
struct CellVolumes {
    geometry: Geometry,
    origin: f64,
    spacing: [f64; 3],
    columns: usize,
}

impl CellVolumes {
    fn new(level: &Level, geometry: Geometry) -> Self {
        let g = &level.geometry;
        Self {
            geometry,
            origin: g.origin[0],
            spacing: g.spacing,
            columns: g.cells[0],
        }
    }

    /// Volume of the cells of global column `i`.
    #[inline]
    fn column(&self, i: usize) -> f64 {
        let [dx, dy, dz] = self.spacing;
        let r_lo = self.origin + i as f64 * dx;
        self.geometry.cell_volume(r_lo, dx, dy, dz)
    }

    /// Volume of the cell of global linear index `g`.
    #[inline]
    fn cell(&self, g: usize) -> f64 {
        self.column(g % self.columns)
    }
}

/// The cell state of a Lagrangian material from its particles (step 1 of
/// seed 000 §3.3), one value per cell in global order (x fastest).
#[derive(Debug, Clone, Copy)]
pub struct LagrangianCells<'a> {
    /// Mass per cell volume, kg/m³ (> 0: a trace where no particle is).
    pub mass_density: &'a [f64],
    /// Velocity, m/s.
    pub velocity: &'a [[f64; 3]],
    /// Specific volume of the material itself, m³/kg; `None`: its
    /// equation of state's at the cell's last equilibration pressure and
    /// the given temperature (Uintah's MPMICE, whose solid specific volume
    /// is its constitutive model's at the cell pressure).
    pub specific_volume: Option<&'a [f64]>,
    /// Temperature, K.
    pub temperature: &'a [f64],
}

/// Statistics of the last equilibration sweep over the grid.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct EquilibrationStats {
    /// Largest iteration count of any cell.
    pub max_iterations: usize,
    /// Largest |1 − Σθ| of any cell.
    pub max_residual: f64,
    /// Iterations summed over the cells.
    pub total_iterations: u64,
}

/// What step 2's cold-material rule (`kept_warm`) and trace hold did to
/// one material, there and in steps 8–11: the cell-steps in which they
/// replaced the material's specific internal energy by the energy at its
/// held temperature, and the energy that added.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct KeptWarmTotals {
    /// Cell-steps in which the rule fired.
    pub firings: u64,
    /// Energy it added (negative: removed), J: Σ ρ_r Δe_r V_cell.
    pub energy: f64,
}

/// Step 2's cold-material rule, or the trace hold of steps 8–11, in one
/// cell: per material, whether it fired and ρ_r Δe_r (J/m³).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
struct KeptWarmCell {
    fired: [bool; MAX_MATERIALS],
    energy_density: [f64; MAX_MATERIALS],
}

impl KeptWarmCell {
    fn any(&self) -> bool {
        self.fired.iter().any(|&f| f)
    }
}

/// The first failing cell of a pass: (global linear index, global cell,
/// description).
type Failure = Option<(usize, [usize; 3], String)>;

fn first_failure(a: Failure, b: Failure) -> Failure {
    match (a, b) {
        (Some(x), Some(y)) => Some(if x.0 <= y.0 { x } else { y }),
        (x, None) => x,
        (None, y) => y,
    }
}

fn global_of(p: &Patch, n: usize) -> [usize; 3] {
    let d = p.dims();
    p.global_of_local([n % d[0], (n / d[0]) % d[1], n / (d[0] * d[1])])
}

/// Local storage indices of `patch`'s interior cells on the domain face
/// `face` (0..6: x_low, x_high, y_low, …) of a grid of `cells` cells; empty
/// where the patch does not touch it.
fn domain_face_cells(patch: &Patch, cells: [usize; 3], face: usize) -> Vec<usize> {
    let (a, high) = (face / 2, face % 2 == 1);
    let touches = if high {
        patch.lo[a] + patch.size[a] == cells[a]
    } else {
        patch.lo[a] == 0
    };
    if !touches {
        return Vec::new();
    }
    let (b, c) = ((a + 1) % 3, (a + 2) % 3);
    let mut out = Vec::with_capacity(patch.size[b] * patch.size[c]);
    for j in 0..patch.size[b] {
        for k in 0..patch.size[c] {
            let mut l = [0; 3];
            l[a] = patch.ghost[a] + if high { patch.size[a] - 1 } else { 0 };
            l[b] = patch.ghost[b] + j;
            l[c] = patch.ghost[c] + k;
            out.push(patch.local_index(l));
        }
    }
    out
}

/// What crossed the domain faces in one pass, per boundary cell: (global
/// linear index, face, material, [mass, momentum x, y, z, energy]) per unit
/// cell volume; summed in that order so that the totals do not depend on
/// the patch split.
type FaceBooking = Vec<(usize, usize, usize, [f64; 5])>;

/// Adds `booking` (per unit cell volume) to the per-face totals `outflow`.
fn book_faces(mut booking: FaceBooking, vols: CellVolumes, outflow: &mut [ConservationTotals; 6]) {
    booking.sort_unstable_by_key(|x| (x.0, x.1, x.2));
    for (g, f, _, q) in booking {
        let vol = vols.cell(g);
        let t = &mut outflow[f];
        t.mass += q[0] * vol;
        for a in 0..3 {
            t.momentum[a] += q[1 + a] * vol;
        }
        t.energy += q[4] * vol;
    }
}

/// Everything a per-cell kernel reads besides the fields.
struct Params<'a, E: Eos> {
    eos: &'a [E],
    reactions: &'a [IceReaction],
    k: &'a [f64],
    h: &'a [f64],
    heat_active: bool,
    options: IceOptions,
    spacing: [f64; 3],
    active: [bool; 3],
    /// Materials whose state is carried by particles (the coupled pipeline,
    /// see [`IceSolver::set_lagrangian`]).
    lagrangian: [bool; MAX_MATERIALS],
    /// Whether any material is Lagrangian.
    coupled: bool,
    /// Whether the cells are (r, z) rings.
    axisymmetric: bool,
    /// The solver's time at the start of the step, s.
    time: f64,
    /// Per material: the specific heat its particles carry, where given
    /// ([`IceSolver::set_lagrangian_specific_heat`]); empty or `None`: the
    /// material's EOS c_v.
    specific_heat: &'a [Option<LagrangianSpecificHeat>],
}

/// The specific heat c_v(T) (J/(kg·K) of the temperature in K) that a
/// Lagrangian material's particles carry, for the heat exchange of steps
/// 8–11 ([`IceSolver::set_lagrangian_specific_heat`]).
#[derive(Clone)]
pub struct LagrangianSpecificHeat(pub std::sync::Arc<dyn Fn(f64) -> f64 + Send + Sync>);

impl LagrangianSpecificHeat {
    /// c_v at `temperature`.
    #[inline]
    pub fn at(&self, temperature: f64) -> f64 {
        (self.0)(temperature)
    }
}

impl std::fmt::Debug for LagrangianSpecificHeat {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("LagrangianSpecificHeat(..)")
    }
}

fn make_params<'a, E: Eos>(
    eos: &'a [E],
    reactions: &'a [IceReaction],
    exchange: &'a ExchangeCoefficients,
    options: IceOptions,
    level: &Level,
    lagrangian: &[bool],
    time: f64,
) -> Params<'a, E> {
    Params {
        eos,
        reactions,
        k: &exchange.momentum,
        h: &exchange.heat,
        heat_active: exchange.heat.iter().any(|&h| h > 0.0),
        options,
        spacing: level.geometry.spacing,
        active: std::array::from_fn(|d| level.is_active(d)),
        lagrangian: std::array::from_fn(|r| lagrangian.get(r).copied().unwrap_or(false)),
        coupled: lagrangian.iter().any(|&l| l),
        axisymmetric: options.geometry.is_axisymmetric(),
        time,
        specific_heat: &[],
    }
}

/// The multi-material ICE solver of seed 000 for materials described by
/// `E` (normally [`brisance_eos::EosModel`]).
#[derive(Debug)]
pub struct IceSolver<E: Eos> {
    eos: Vec<E>,
    reactions: Vec<IceReaction>,
    level: Level,
    boundaries: [IceBoundary; 6],
    exchange: ExchangeCoefficients,
    options: IceOptions,
    state: Vec<PatchFields>,
    state_set: FieldSet,
    state_bcs: BoundaryConditions,
    lag: Vec<PatchFields>,
    lag_set: FieldSet,
    lag_bcs: BoundaryConditions,
    press: Vec<PatchFields>,
    press_set: FieldSet,
    press_bcs: BoundaryConditions,
    scratch: Vec<PatchScratch>,
    halo: InProcessExchange,
    time: f64,
    steps: u64,
    last_equilibration: EquilibrationStats,
    /// Per material: whether particles carry it ([`IceSolver::set_lagrangian`]).
    lagrangian: Vec<bool>,
    /// Per material: the specific heat its particles carry
    /// ([`IceSolver::set_lagrangian_specific_heat`]).
    specific_heat: Vec<Option<LagrangianSpecificHeat>>,
    /// Whether a region gave a material carried by particles a start
    /// temperature its cells' (ρ, p) do not carry
    /// ([`IceSolver::start_temperatures_on_particles`]).
    start_on_particles: bool,
    /// Mass, momentum and energy the coupled equilibration gave the
    /// Eulerian materials since the start ([`IceSolver::rescaled_totals`]).
    rescaled: ConservationTotals,
    /// Per material, what step 2's cold-material rule did since the start
    /// ([`IceSolver::kept_warm_totals`]).
    kept_warm: [KeptWarmTotals; MAX_MATERIALS],
    /// Per material, what step 12's cold-material rule did since the start
    /// ([`IceSolver::kept_warm_advection_totals`]).
    kept_warm_advection: [KeptWarmTotals; MAX_MATERIALS],
    /// Viscosities and conductivities ([`IceSolver::set_transport`]).
    transport: diffusion_pass::Transport,
    /// Work arrays and statistics of the implicit pressure solve.
    implicit: implicit::ImplicitWorkspace,
    /// Per face: whether an outflow face has held back a flow into the
    /// domain since the start ([`crate::boundary::holds_back_inflow`]).
    blocked_inflow: [bool; 6],
    /// Per face (x_low, x_high, y_low, …): the mass, momentum and energy
    /// that have left the domain through it since the start (negative for
    /// what came in): step 12's fluxes and the face pressure's impulse and
    /// work of steps 8–9 ([`IceSolver::outflow`]).
    outflow: [ConservationTotals; 6],
    /// Work arrays of the reactant surface pass.
    surface_pass: surface::SurfacePass,
    /// The ranks the patches are shared among ([`IceSolver::distribute`]):
    /// one owning all of them unless distributed.
    ranks: ranks::Ranks,
}

impl<E: Eos> IceSolver<E> {
    /// Sets the reactions of step 4 (seed 000 eq 1; see [`crate::reaction`]).
    /// A material may be the reactant of one reaction only.
    pub fn set_reactions(&mut self, reactions: Vec<IceReaction>) -> Result<(), IceError> {
        let n = self.eos.len();
        for (k, r) in reactions.iter().enumerate() {
            r.validate(n)
                .map_err(|e| IceError::Invalid(format!("ice: reactions[{k}]: {e}")))?;
            if reactions[..k].iter().any(|o| o.reactant == r.reactant) {
                return Err(IceError::Invalid(format!(
                    "ice: reactions[{k}]: field `reactant` = {}: material {} is already the reactant of another reaction",
                    r.reactant,
                    r.reactant + 1
                )));
            }
        }
        if let Some(k) = reactions.iter().position(|r| self.is_lagrangian(r.product)) {
            return Err(IceError::Invalid(format!(
                "ice: reactions[{k}]: the product cannot be a material carried by particles"
            )));
        }
        self.reactions = reactions;
        self.still_distributable()?;
        self.find_reaction_surfaces().map_err(IceError::Invalid)
    }

    /// The reactions of step 4.
    pub fn reactions(&self) -> &[IceReaction] {
        &self.reactions
    }

    /// The level the solver runs on.
    pub fn level(&self) -> &Level {
        &self.level
    }

    /// Number of materials.
    pub fn material_count(&self) -> usize {
        self.eos.len()
    }

    /// Per face (x_low, x_high, y_low, y_high, z_low, z_high): the mass
    /// (kg), momentum (kg·m/s) and energy (J, with a reactant's chemical
    /// energy) that have left the domain through it since the start,
    /// negative for what came in: step 12's fluxes through the face and the
    /// face pressure's impulse p*A Δt and work p*(Σθ*u*)A Δt of steps 8–9
    /// (a wall books only the impulse). The conservation totals are the
    /// interior's plus these (docs/physics/ice/README.md, "What crosses
    /// the faces").
    pub fn outflow(&self) -> [ConservationTotals; 6] {
        self.outflow
    }

    /// The faces whose crossings are booked: all but a periodic pair's,
    /// where what leaves one face enters the other.
    fn booked_faces(&self) -> [bool; 6] {
        std::array::from_fn(|f| !matches!(self.boundaries[f], IceBoundary::Periodic))
    }

    /// The six faces' [`IceSolver::outflow`] summed.
    pub fn outflow_sum(&self) -> ConservationTotals {
        let mut t = ConservationTotals::default();
        for o in &self.outflow {
            t.mass += o.mass;
            for a in 0..3 {
                t.momentum[a] += o.momentum[a];
            }
            t.energy += o.energy;
        }
        t
    }

    /// Steps taken so far.
    pub fn steps(&self) -> u64 {
        self.steps
    }

    /// Iterations and residuals of the last equilibration sweep.
    pub fn equilibration_stats(&self) -> EquilibrationStats {
        self.last_equilibration
    }

    /// The cells' volumes (rings on an axisymmetric grid).
    fn volumes(&self) -> CellVolumes {
        CellVolumes::new(&self.level, self.options.geometry)
    }

    /// The solver's options.
    pub fn options(&self) -> &IceOptions {
        &self.options
    }

    /// Declares which materials particles carry (seed 000 §3.3, the ICE–MPM
    /// pipeline): `mask[r]` true makes material r Lagrangian. Its cell
    /// state is then imported from the particles before each equilibration
    /// ([`IceSolver::import_lagrangian`]); the Lagrangian step adds only
    /// the pressure gradient and the exchange to it, advection leaves it,
    /// and the conservation totals leave it to the particles. With any
    /// Lagrangian material the volume fractions of step 2 are shares of
    /// the materials' total volume. A Lagrangian material may be a
    /// reactant (its particles burn: [`IceSolver::lagrangian_burn_fraction`],
    /// [`IceSolver::add_burnt_particles`]), never a product. It clears the
    /// specific heats of [`IceSolver::set_lagrangian_specific_heat`] (set
    /// them after).
    pub fn set_lagrangian(&mut self, mask: &[bool]) -> Result<(), IceError> {
        let n = self.eos.len();
        if mask.len() != n {
            return Err(IceError::Invalid(format!(
                "ice: {} Lagrangian flags given for {n} materials",
                mask.len()
            )));
        }
        if mask.iter().any(|&l| l) && self.options.pressure != PressureSolve::Explicit {
            return Err(IceError::Invalid(
                "ice: field `pressure`: the implicit pressure is not available with materials carried by particles".into(),
            ));
        }
        if mask.iter().all(|&l| l) {
            return Err(IceError::Invalid(
                "ice: at least one material must be Eulerian".into(),
            ));
        }
        for (k, rx) in self.reactions.iter().enumerate() {
            if mask[rx.product] {
                return Err(IceError::Invalid(format!(
                    "ice: reactions[{k}]: the product cannot be a material carried by particles"
                )));
            }
        }
        self.lagrangian = mask.to_vec();
        self.specific_heat = vec![None; n];
        self.still_distributable()
    }

    /// Gives Lagrangian material `r` the specific heat its particles carry
    /// (after [`IceSolver::set_lagrangian`]): the heat exchange of steps
    /// 8–11 then weighs the material's temperature change by ρ c(T) with
    /// this c at its cell temperature instead of its EOS's c_v, and its
    /// Lagrangian energy changes by the heat c(T) ΔT it takes, which
    /// [`IceSolver::lagrangian_heat`] reads back, so that the particles
    /// can take that heat through their own H(T) and the heat the fluids
    /// give is the heat the particles gain (docs/physics/couple/ice_mpm.md,
    /// "Heat between the frames").
    pub fn set_lagrangian_specific_heat(
        &mut self,
        r: usize,
        specific_heat: LagrangianSpecificHeat,
    ) -> Result<(), IceError> {
        if !self.is_lagrangian(r) {
            return Err(IceError::Invalid(format!(
                "ice: material {} is not carried by particles",
                r + 1
            )));
        }
        self.specific_heat[r] = Some(specific_heat);
        Ok(())
    }

    /// Records whether a region gave a material carried by particles a
    /// start temperature its cells' (ρ, p) do not carry (a Murnaghan solid
    /// away from its `t_ref`; the pipeline builder's finding).
    pub fn set_start_temperatures_on_particles(&mut self, on_particles: bool) {
        self.start_on_particles = on_particles;
    }

    /// Whether the start temperature of a material carried by particles is
    /// only on its particles ([`IceSolver::set_start_temperatures_on_particles`]):
    /// the coupled pipeline then gives its cells the particles' state
    /// before the first fit of the fluids around them.
    pub fn start_temperatures_on_particles(&self) -> bool {
        self.start_on_particles
    }

    /// Whether Lagrangian material `r` carries its own specific heat
    /// ([`IceSolver::set_lagrangian_specific_heat`]).
    pub fn has_lagrangian_specific_heat(&self, r: usize) -> bool {
        self.specific_heat.get(r).is_some_and(|c| c.is_some())
    }

    /// Where the CFL rate of [`Solver::stable_dt`] is largest (first in
    /// global cell order; NaN first): the cell, its centre, and the
    /// material whose |u| + c sets it, with its state: the diagnostic of
    /// a collapsed step, and of what sets the step of a long run. It
    /// visits every cell in order on one thread.
    pub fn fastest_signal(&self) -> String {
        let params = solver_params!(self);
        let acoustic = if self.options.pressure == PressureSolve::Explicit {
            1.0
        } else {
            0.0
        };
        let mut worst: Option<(f64, [usize; 3], usize, usize, usize)> = None;
        let state = self.gathered_state();
        self.level.for_each_cell_in_order(|g, pid, c| {
            let (rate, material) = cell_cfl_rate(&params, &state[pid].data, c, acoustic);
            let worse = match worst {
                None => true,
                Some((w, ..)) => !(rate <= w) && !w.is_nan(),
            };
            if worse {
                worst = Some((rate, g, material, pid, c));
            }
        });
        let Some((rate, g, r, pid, c)) = worst else {
            return "no cells".into();
        };
        let d = &state[pid].data;
        let b = r * NS;
        let centre = self.level.geometry.cell_centre(g);
        let n = self.eos.len();
        let mass: f64 = (0..n).map(|m| d[m * NS + RHO][c]).sum();
        let others: Vec<String> = (0..n)
            .map(|m| {
                format!(
                    "{}{}: θ {:.3e}, mass share {:.3e}, T {:.3e} K",
                    m + 1,
                    if self.lagrangian[m] {
                        " (particles)"
                    } else {
                        ""
                    },
                    d[m * NS + THETA][c],
                    d[m * NS + RHO][c] / mass,
                    d[m * NS + TEMP][c],
                )
            })
            .collect();
        format!(
            "cell {g:?} (centre {centre:?} m), Σ(|u| + c)/Δx = {rate:e} 1/s, set by material {} \
             (θ = {:e}, its density {:e} kg/m³, T = {:e} K, u = ({:e}, {:e}, {:e}) m/s, c = {:e} m/s); \
             the cell's pressure {:e} Pa, its materials: {}",
            r + 1,
            d[b + THETA][c],
            1.0 / d[b + VSP][c],
            d[b + TEMP][c],
            d[b + VEL][c],
            d[b + VEL + 1][c],
            d[b + VEL + 2][c],
            d[b + SOUND][c],
            d[n * NS][c],
            others.join("; "),
        )
    }

    /// What the coupled equilibration (step 2 with Lagrangian materials)
    /// has added to the Eulerian materials since the start — mass,
    /// momentum and total energy, the fluid's state at its rescaled mass —
    /// so that the coupled pipeline's bookkeeping can close. Zero unless
    /// a material is Lagrangian.
    pub fn rescaled_totals(&self) -> ConservationTotals {
        self.rescaled
    }

    /// Per material, the cell-steps in which step 2's cold-material rule
    /// or its trace hold fired, in step 2 or carried through steps 8–11
    /// (a fluid trace held at the particles' temperature keeps it in the
    /// Lagrangian values, and leaves the energy closure's residual to the
    /// fluids that are not held), and the energy they added since the
    /// start of the run (checkpoints carry it): the rules trade energy
    /// conservation for a positive temperature and a bounded trace
    /// (docs/physics/ice/steps.md), and this is their price.
    pub fn kept_warm_totals(&self) -> &[KeptWarmTotals] {
        &self.kept_warm[..self.eos.len()]
    }

    /// The same for step 12's rule (a fast material whose E − ½|u|² after
    /// advection has no positive temperature keeps its temperature of the
    /// step's start): firings and Σ ρ_r Δe_r V_cell per material.
    pub fn kept_warm_advection_totals(&self) -> &[KeptWarmTotals] {
        &self.kept_warm_advection[..self.eos.len()]
    }

    /// Fills the ghosts of the state group and applies moving walls.
    fn fill_state_ghosts(&mut self) {
        self.halo.fill_all(
            &self.level,
            &self.state_set,
            &self.state_bcs,
            &mut self.state,
        );
        apply_moving_walls(
            &self.level,
            &self.boundaries,
            &mut self.state,
            self.eos.len(),
            NS,
            VEL,
        );
    }

    /// Step 2 (seed 000 eq 7): the equilibration pressure of every cell,
    /// with new specific volumes, volume fractions, temperatures and sound
    /// speeds. A cell that fails stops the run with its state.
    // Kept out of line so that profiles attribute each step's cost.
    /// Output field names: mixture fields, then per material k (1-based).
    pub fn field_names(&self) -> Vec<&'static str> {
        let mut v = MIXTURE_FIELDS.to_vec();
        for k in 0..self.eos.len() {
            v.extend([
                VOLUME_FRACTION[k],
                MATERIAL_DENSITY[k],
                MATERIAL_TEMPERATURE[k],
                MATERIAL_VELOCITY_X[k],
            ]);
        }
        v
    }

    fn field_index(&self, name: &str) -> Result<usize, SolverError> {
        let names = self.field_names();
        names.iter().position(|f| *f == name).ok_or_else(|| {
            SolverError::Other(format!(
                "unknown field `{name}`; known fields: {}",
                names.join(", ")
            ))
        })
    }

    /// Value of output field `field` at storage index `c` of patch `pid`
    /// of `state` (the solver's, or [`Self::gathered_state`]).
    fn derived(&self, state: &[PatchFields], pid: usize, c: usize, field: usize) -> f64 {
        let n = self.eos.len();
        let d = &state[pid].data;
        let rho: f64 = (0..n).map(|r| d[r * NS + RHO][c]).sum();
        let mean = |f: usize| {
            (0..n)
                .map(|r| d[r * NS + RHO][c] * d[r * NS + f][c])
                .sum::<f64>()
                / rho
        };
        match field {
            0 => rho,
            1..=3 => mean(VEL + field - 1),
            4 => d[n * NS][c],
            5 => mean(ENERGY),
            6 => mean(TEMP),
            7 => {
                let tk: f64 = (0..n)
                    .map(|r| {
                        let cs = d[r * NS + SOUND][c];
                        d[r * NS + THETA][c] * d[r * NS + VSP][c] / (cs * cs)
                    })
                    .sum();
                1.0 / (rho * tk).sqrt()
            }
            _ => {
                let k = (field - MIXTURE_FIELDS.len()) / 4;
                let b = k * NS;
                match (field - MIXTURE_FIELDS.len()) % 4 {
                    0 => d[b + THETA][c],
                    1 => d[b + RHO][c],
                    2 => d[b + TEMP][c],
                    _ => d[b + VEL][c],
                }
            }
        }
    }
}

/// Mixture output fields, in the order `derived` numbers them.
const MIXTURE_FIELDS: [&str; 8] = [
    "density",
    "velocity_x",
    "velocity_y",
    "velocity_z",
    "pressure",
    "specific_internal_energy",
    "temperature",
    "sound_speed",
];
const VOLUME_FRACTION: [&str; MAX_MATERIALS] = [
    "volume_fraction_1",
    "volume_fraction_2",
    "volume_fraction_3",
    "volume_fraction_4",
    "volume_fraction_5",
    "volume_fraction_6",
    "volume_fraction_7",
    "volume_fraction_8",
];
const MATERIAL_DENSITY: [&str; MAX_MATERIALS] = [
    "density_1",
    "density_2",
    "density_3",
    "density_4",
    "density_5",
    "density_6",
    "density_7",
    "density_8",
];
const MATERIAL_TEMPERATURE: [&str; MAX_MATERIALS] = [
    "temperature_1",
    "temperature_2",
    "temperature_3",
    "temperature_4",
    "temperature_5",
    "temperature_6",
    "temperature_7",
    "temperature_8",
];
const MATERIAL_VELOCITY_X: [&str; MAX_MATERIALS] = [
    "velocity_x_1",
    "velocity_x_2",
    "velocity_x_3",
    "velocity_x_4",
    "velocity_x_5",
    "velocity_x_6",
    "velocity_x_7",
    "velocity_x_8",
];

/// Ghost velocities of fixed-velocity walls: after the mirror fill, set
/// u_ghost = 2u_w − u_mirror for every component, so the wall moves at u_w.
fn apply_moving_walls(
    level: &Level,
    boundaries: &[IceBoundary; 6],
    fields: &mut [PatchFields],
    n: usize,
    per: usize,
    vel: usize,
) {
    for (f, b) in boundaries.iter().enumerate() {
        let IceBoundary::FixedVelocity(w) = b else {
            continue;
        };
        let (a, side) = (f / 2, f % 2);
        if !level.is_active(a) {
            continue;
        }
        for (patch, pf) in level.patches.iter().zip(fields.iter_mut()) {
            let touches = if side == 0 {
                patch.lo[a] == 0
            } else {
                patch.lo[a] + patch.size[a] == level.geometry.cells[a]
            };
            if !touches {
                continue;
            }
            let dims = patch.dims();
            let g = patch.ghost[a];
            for m in 0..g {
                let layer = if side == 0 { m } else { g + patch.size[a] + m };
                for k in 0..dims[2] {
                    for j in 0..dims[1] {
                        for i in 0..dims[0] {
                            let l = [i, j, k];
                            if l[a] != layer {
                                continue;
                            }
                            let idx = patch.local_index(l);
                            for r in 0..n {
                                for comp in 0..3 {
                                    let x = &mut pf.data[r * per + vel + comp][idx];
                                    // The mirror negated the normal component.
                                    *x = if comp == a {
                                        *x + 2.0 * w[comp]
                                    } else {
                                        2.0 * w[comp] - *x
                                    };
                                }
                            }
                        }
                    }
                }
            }
        }
    }
}
