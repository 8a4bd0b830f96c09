//! The lattice state (seed 003 §2.2, U = {m_k, u, V, P, T, e} in
//! structure-of-arrays), the spring forces of eqs 9–10b as bond-based
//! peridynamics (eqs 8–9), their Jacobians (eq 20), the commit of the
//! irreversible spring state (plastic flow, dashpots, fracture) and the
//! energy equation (eqs 10c, 11, 14–15).
//!
//! Every pass is a loop over nodes (or over the bonds each node owns) in
//! which a node writes only its own entries: the forces of a bond are
//! computed once, at its lower node, and gathered with opposite signs at
//! both ends in a fixed order, so the results are the same bits for any
//! number of threads and f_ij = −f_ji exactly.

use rayon::prelude::*;

use super::geometry::{dual_volume, dual_volume_2d, Geometry, NodeKind};
use super::law::{LatticeMaterial, PairLaw, SpringState};
use super::sparse::{CsrMatrix, SolveStats, SolverWork};

mod forces;
mod implicit;

/// Every axis held: the default of [`MsdmLattice::held_axes`].
pub const ALL_AXES: u8 = 0b111;

/// Errors of the lattice model; messages name the offending field.
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum MsdmError {
    /// A parameter is outside its valid range.
    #[error("{0}")]
    Invalid(String),
    /// The implicit linear solve failed.
    #[error("implicit step: {0}")]
    Solve(String),
}

/// Time integrator (seed 003 §2.3).
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub enum Integrator {
    /// Explicit Euler, eqs 16–17.
    ExplicitEuler,
    /// Velocity Verlet, eq 18.
    VelocityVerlet,
    /// Linearised implicit (backward) Euler, eqs 19–21.
    ImplicitEuler,
    /// Linearised implicit second-order Runge–Kutta (trapezoidal), eq 22.
    ImplicitRk2,
}

impl Integrator {
    /// Whether the step solves a linear system over every node.
    pub fn is_implicit(self) -> bool {
        matches!(self, Self::ImplicitEuler | Self::ImplicitRk2)
    }
}

/// The medium the exterior (ghost) nodes stand for.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Surroundings {
    /// Temperature of the ghost nodes, K.
    pub temperature: f64,
    /// Conductivity of the surroundings, W/(m·K); 0 makes surfaces and
    /// cracks adiabatic.
    pub conductivity: f64,
}

/// How the linear systems of the implicit integrators (seed 003 eqs 21–22)
/// are solved.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize, serde::Deserialize)]
pub enum LinearSolver {
    /// Sparse LU with partial pivoting (faer), exact to round-off; the
    /// default.
    #[default]
    Direct,
    /// Jacobi-preconditioned BiCGSTAB to `solver_tolerance`: less memory on
    /// very large lattices.
    Iterative,
}

/// Options of a lattice.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct MsdmOptions {
    /// Time integrator.
    pub integrator: Integrator,
    /// Surroundings (ghost nodes).
    pub surroundings: Surroundings,
    /// Initial temperature of the solid nodes, K.
    pub initial_temperature: f64,
    /// Whether the energy equation (eq 15) is integrated.
    pub thermal: bool,
    /// Linear solver of the implicit steps.
    #[serde(default)]
    pub linear_solver: LinearSolver,
    /// Relative residual of the iterative implicit linear solves.
    pub solver_tolerance: f64,
    /// Safety factor on the explicit stable step.
    pub safety_factor: f64,
    /// Fixed step of the implicit integrators when run as a `Solver`
    /// (`None`: the explicit limit), s.
    pub time_step: Option<f64>,
}

impl Default for MsdmOptions {
    fn default() -> Self {
        Self {
            integrator: Integrator::VelocityVerlet,
            surroundings: Surroundings {
                temperature: 300.0,
                conductivity: 0.0,
            },
            initial_temperature: 300.0,
            thermal: true,
            linear_solver: LinearSolver::Direct,
            solver_tolerance: 1e-12,
            safety_factor: 0.8,
            time_step: None,
        }
    }
}

/// Bond status.
pub(crate) const NO_BOND: u8 = 0;
pub(crate) const INTACT: u8 = 1;
pub(crate) const BROKEN: u8 = 2;

/// What one step did.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct StepReport {
    /// Springs that broke in this step.
    pub broken: usize,
    /// Linear-solver statistics of an implicit step.
    pub solve: Option<SolveStats>,
    /// Wall time of the whole implicit update (force evaluation, assembly,
    /// linear solve and the update of x and u), s; 0 for explicit steps.
    pub solve_seconds: f64,
    /// Wall time of the Jacobian and right-hand-side assembly of an
    /// implicit step (part of `solve_seconds`), s.
    pub assemble_seconds: f64,
    /// Wall time of the linear solve alone of an implicit step (part of
    /// `solve_seconds`), s.
    pub linear_solve_seconds: f64,
}

/// Wall time of the implicit steps, accumulated over the steps since the
/// lattice was built or [`MsdmLattice::reset_implicit_timing`] was called
/// (read with [`MsdmLattice::implicit_timing`]).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct ImplicitTiming {
    /// Implicit steps counted.
    pub steps: u64,
    /// Whole implicit updates (force evaluation, assembly, solve, update).
    pub total: std::time::Duration,
    /// Assembly of the matrix and of the right-hand side.
    pub assemble: std::time::Duration,
    /// Linear solves (sparse LU or BiCGSTAB).
    pub solve: std::time::Duration,
}

/// A mass–spring–damper lattice (seed 003 ch. 2).
#[derive(Debug, Clone)]
pub struct MsdmLattice {
    /// The lattice.
    pub geom: Geometry,
    /// Materials, indexed by [`NodeKind::Solid`]. The spring laws are
    /// derived from them in [`MsdmLattice::new`]; build a new lattice to
    /// change them.
    pub materials: Vec<LatticeMaterial>,
    laws: Vec<PairLaw>,
    /// Options.
    pub options: MsdmOptions,
    /// Time, s.
    pub time: f64,
    /// Positions x, per axis, m. After changing `x`, `u` or `body` between
    /// steps call [`MsdmLattice::mark_modified`].
    pub x: [Vec<f64>; 3],
    /// Velocities u, per axis, m/s.
    pub u: [Vec<f64>; 3],
    /// Component masses m_k (component k = material k), `k · N + i`, kg.
    pub mass_k: Vec<f64>,
    /// Total mass m = Σ m_k, kg.
    pub mass: Vec<f64>,
    /// Dual-mesh volume V, m³.
    pub volume: Vec<f64>,
    /// Pressure P, Pa.
    pub pressure: Vec<f64>,
    /// Temperature T, K.
    pub temperature: Vec<f64>,
    /// Specific internal energy e = c_v T, J/kg.
    pub energy: Vec<f64>,
    /// Component mass rates ṁ_k (eq 10a), `k · N + i`, kg/s; set by the
    /// chemistry (zero by default).
    pub mass_rate: Vec<f64>,
    /// Body force b per node (eq 10b), N.
    pub body: [Vec<f64>; 3],
    /// Nodes whose velocity is prescribed (held at its current value).
    pub prescribed: Vec<bool>,
    /// Axes held on each prescribed node, bit a for axis a ([`ALL_AXES`] by
    /// default). A node with `prescribed[i]` and `held_axes[i] = 0b001` is
    /// a slip wall normal to x: u_x is held, u_y and u_z move freely.
    /// Ignored where `prescribed[i]` is false. Per-axis prescription is
    /// supported by the explicit integrators; the implicit ones refuse it.
    pub held_axes: Vec<u8>,
    pub(crate) status: Vec<u8>,
    pub(crate) spring: Vec<SpringState>,
    bond_force: [Vec<f64>; 3],
    /// Net force on each node at the last force evaluation, N.
    pub force: [Vec<f64>; 3],
    pub(crate) force_prev: [Vec<f64>; 3],
    pub(crate) forces_current: bool,
    has_spring_state: bool,
    scratch: [Vec<f64>; 4],
    pub(crate) matrix: CsrMatrix,
    pub(crate) rhs: Vec<f64>,
    pub(crate) delta: Vec<f64>,
    pub(crate) dof: Vec<usize>,
    pub(crate) work: SolverWork,
    pub(crate) timing: ImplicitTiming,
    /// Surface regression (seed 003 §2.4), if on; see
    /// [`MsdmLattice::set_regression`].
    pub regression: Option<super::regress::SurfaceRegression>,
    /// Whether the momentum equation is solved (default true). Off, a step
    /// only regresses the surface, as in the propellant burns of seed 003
    /// §3.1 ("the momentum equation is not solved"); the energy equation
    /// must then be off too.
    pub mechanics: bool,
    /// Per-node flags of the row-stencil passes ([`super::stencil`]).
    pub(crate) flags: Vec<u8>,
    /// Bond forces of the row-stencil bond pass, by row.
    pub(crate) row_bonds: Vec<f64>,
    /// Whether `flags` were filled in this step, with no change of the
    /// node kinds or bond status since (cleared at the start and end of
    /// each step and by a commit that changes the spring state).
    flags_fresh: bool,
    /// Take the general passes even where the row-stencil passes apply
    /// (the tests compare the two).
    pub(crate) general_passes: bool,
    /// The nodes this rank evaluates, on a run spread over MPI ranks
    /// (`ranks.rs`).
    pub(crate) ranks: brisance_grid::comm::NodeRuns,
}

/// The kinematics and force of one spring.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BondEval {
    /// Force on the lower node, N.
    pub f: [f64; 3],
    /// Unit vector of the deformed bond.
    pub n: [f64; 3],
    /// Deformed length ℓ, m.
    pub len: f64,
    /// Relative velocity w, m/s.
    pub w: [f64; 3],
    /// Extension s = ℓ − |ξ|, m.
    pub s: f64,
    /// Axial force F, N.
    pub axial_force: f64,
    /// ∂F/∂s, N/m.
    pub k_t: f64,
    /// ∂F/∂ṡ, N·s/m.
    pub c_t: f64,
    /// Perpendicular stiffness k⊥ (0 off), N/m.
    pub k_perp: f64,
    /// Reference unit direction ê₀.
    pub e0: [f64; 3],
    /// Spring state after the return mapping.
    pub state: SpringState,
}

/// Force on the lower node of a spring of reference vector `xi`, current
/// vector `r` = x′ − x (so η = r − ξ) and relative velocity `w` = u′ − u,
/// from the committed spring state `st` (seed 003 eq 6, F(η, ξ)[η + ξ]):
/// f = F n with n = r/|r| and F the axial law of [`PairLaw::axial`], plus,
/// on axial springs with k⊥ > 0, the perpendicular corrective force of
/// eq 10b, f⊥ = k⊥ (I − ê₀ê₀ᵀ) η. The upper node receives −f. The
/// function is odd: `bond_force(−ξ, −r, −w)` is exactly −f.
#[inline]
pub fn bond_force(
    law: &PairLaw,
    xi: [f64; 3],
    r: [f64; 3],
    w: [f64; 3],
    st: SpringState,
    axial: bool,
) -> BondEval {
    bond_force_ref(law, &BondRef::new(xi, axial), r, w, st)
}

/// Materials up to which the energy update tabulates conductances.
const MAX_TABLE_MATERIALS: usize = 8;

/// Harmonic mean 2ab/(a + b) of two conductivities (0 when both are 0).
#[inline]
fn harmonic(a: f64, b: f64) -> f64 {
    if a + b > 0.0 {
        2.0 * a * b / (a + b)
    } else {
        0.0
    }
}

/// The reference quantities of a bond direction (ξ, |ξ|, ê₀), formed once
/// per direction by the force loop and per call by [`bond_force`], with
/// the same operations, so both give the same bits.
#[derive(Debug, Clone, Copy, Default)]
pub(crate) struct BondRef {
    xi: [f64; 3],
    len0: f64,
    e0: [f64; 3],
    axial: bool,
}

impl BondRef {
    #[inline]
    pub(crate) fn new(xi: [f64; 3], axial: bool) -> Self {
        let len0 = (xi[0] * xi[0] + xi[1] * xi[1] + xi[2] * xi[2]).sqrt();
        Self {
            xi,
            len0,
            e0: [xi[0] / len0, xi[1] / len0, xi[2] / len0],
            axial,
        }
    }
}

/// [`bond_force`] from the precomputed reference quantities `b`.
#[inline(always)]
pub(crate) fn bond_force_ref(
    law: &PairLaw,
    b: &BondRef,
    r: [f64; 3],
    w: [f64; 3],
    st: SpringState,
) -> BondEval {
    let (xi, len0, e0) = (b.xi, b.len0, b.e0);
    let len = (r[0] * r[0] + r[1] * r[1] + r[2] * r[2]).sqrt();
    let n = if len > 0.0 {
        [r[0] / len, r[1] / len, r[2] / len]
    } else {
        [0.0; 3]
    };
    let s = len - len0;
    let sdot = n[0] * w[0] + n[1] * w[1] + n[2] * w[2];
    let af = law.axial(len0, s, sdot, st);
    let mut f = [af.force * n[0], af.force * n[1], af.force * n[2]];
    let k_perp = if b.axial { law.k_perp * len0 } else { 0.0 };
    if k_perp > 0.0 {
        let eta = [r[0] - xi[0], r[1] - xi[1], r[2] - xi[2]];
        let along = eta[0] * e0[0] + eta[1] * e0[1] + eta[2] * e0[2];
        for a in 0..3 {
            f[a] += k_perp * (eta[a] - along * e0[a]);
        }
    }
    BondEval {
        f,
        n,
        len,
        w,
        s,
        axial_force: af.force,
        k_t: af.stiffness,
        c_t: af.damping,
        k_perp,
        e0,
        state: af.state,
    }
}

/// Jacobian blocks of a spring's force f (see [`bond_force`]) with respect
/// to r and w: (∂f/∂r, ∂f/∂w), row-major 3 × 3.
///
/// ∂f/∂r = k_t nnᵀ + (F/ℓ)(I − nnᵀ) + (c_t/ℓ) n wᵀ(I − nnᵀ)
///        + k⊥(I − ê₀ê₀ᵀ);  ∂f/∂w = c_t nnᵀ.
pub fn bond_jacobian(b: &BondEval) -> ([[f64; 3]; 3], [[f64; 3]; 3]) {
    let mut kx = [[0.0; 3]; 3];
    let mut cu = [[0.0; 3]; 3];
    let n = b.n;
    let fl = if b.len > 0.0 {
        b.axial_force / b.len
    } else {
        0.0
    };
    let cl = if b.len > 0.0 { b.c_t / b.len } else { 0.0 };
    let wn = b.w[0] * n[0] + b.w[1] * n[1] + b.w[2] * n[2];
    let wp = [b.w[0] - wn * n[0], b.w[1] - wn * n[1], b.w[2] - wn * n[2]];
    for r in 0..3 {
        for c in 0..3 {
            let id = if r == c { 1.0 } else { 0.0 };
            kx[r][c] = b.k_t * n[r] * n[c]
                + fl * (id - n[r] * n[c])
                + cl * n[r] * wp[c]
                + b.k_perp * (id - b.e0[r] * b.e0[c]);
            cu[r][c] = b.c_t * n[r] * n[c];
        }
    }
    (kx, cu)
}

impl MsdmLattice {
    /// A lattice at rest in its reference configuration.
    pub fn new(
        geom: Geometry,
        materials: Vec<LatticeMaterial>,
        options: MsdmOptions,
    ) -> Result<Self, MsdmError> {
        if !(geom.spacing > 0.0 && geom.spacing.is_finite()) {
            return Err(MsdmError::Invalid(format!(
                "lattice: field `spacing` = {}, expected a finite value > 0",
                geom.spacing
            )));
        }
        if materials.is_empty() {
            return Err(MsdmError::Invalid(
                "lattice: field `materials` is empty".into(),
            ));
        }
        for m in &materials {
            m.validate().map_err(MsdmError::Invalid)?;
        }
        for (field, v) in [
            ("surroundings.temperature", options.surroundings.temperature),
            ("initial_temperature", options.initial_temperature),
        ] {
            if !(v > 0.0 && v.is_finite()) {
                return Err(MsdmError::Invalid(format!(
                    "lattice: field `{field}` = {v}, expected a finite value > 0"
                )));
            }
        }
        if !(options.surroundings.conductivity >= 0.0
            && options.surroundings.conductivity.is_finite())
        {
            return Err(MsdmError::Invalid(format!(
                "lattice: field `surroundings.conductivity` = {}, expected a finite value ≥ 0",
                options.surroundings.conductivity
            )));
        }
        if !(options.safety_factor > 0.0 && options.safety_factor <= 1.0) {
            return Err(MsdmError::Invalid(format!(
                "lattice: field `safety_factor` = {}, expected a value in (0, 1]",
                options.safety_factor
            )));
        }
        if let Some(dt) = options.time_step {
            if !(dt > 0.0 && dt.is_finite()) {
                return Err(MsdmError::Invalid(format!(
                    "lattice: field `time_step` = {dt}, expected a finite value > 0"
                )));
            }
        }
        if !(options.solver_tolerance > 0.0 && options.solver_tolerance < 1.0) {
            return Err(MsdmError::Invalid(format!(
                "lattice: field `solver_tolerance` = {}, expected a value in (0, 1)",
                options.solver_tolerance
            )));
        }
        let nm = materials.len();
        for k in &geom.kind {
            if let NodeKind::Solid(m) = k {
                if usize::from(*m) >= nm {
                    return Err(MsdmError::Invalid(format!(
                        "lattice: a node has material {m} but field `materials` has {nm} entries"
                    )));
                }
            }
        }
        let mut laws = Vec::with_capacity(nm * nm);
        for a in &materials {
            for b in &materials {
                laws.push(PairLaw::pair(a, b));
            }
        }
        let n = geom.len();
        let nd = geom.directions.len();
        let mut x = [vec![0.0; n], vec![0.0; n], vec![0.0; n]];
        for i in 0..n {
            let p = geom.reference_position(i);
            for a in 0..3 {
                x[a][i] = p[a];
            }
        }
        let mut status = vec![NO_BOND; n * nd];
        for i in 0..n {
            if !geom.is_solid(i) {
                continue;
            }
            for (d, dir) in geom.directions.iter().enumerate() {
                let j = (i as isize + dir.offset) as usize;
                if geom.is_solid(j) {
                    status[i * nd + d] = INTACT;
                }
            }
        }
        let mut s = Self {
            materials,
            laws,
            options,
            time: 0.0,
            u: [vec![0.0; n], vec![0.0; n], vec![0.0; n]],
            mass_k: vec![0.0; nm * n],
            mass: vec![0.0; n],
            volume: vec![0.0; n],
            pressure: vec![0.0; n],
            temperature: vec![options.surroundings.temperature; n],
            energy: vec![0.0; n],
            mass_rate: vec![0.0; nm * n],
            body: [vec![0.0; n], vec![0.0; n], vec![0.0; n]],
            prescribed: vec![false; n],
            held_axes: vec![ALL_AXES; n],
            status,
            spring: vec![SpringState::default(); n * nd],
            bond_force: [vec![0.0; n * nd], vec![0.0; n * nd], vec![0.0; n * nd]],
            force: [vec![0.0; n], vec![0.0; n], vec![0.0; n]],
            force_prev: [vec![0.0; n], vec![0.0; n], vec![0.0; n]],
            forces_current: false,
            has_spring_state: false,
            scratch: [vec![0.0; n], vec![0.0; n], vec![0.0; n], vec![0.0; n]],
            matrix: CsrMatrix::default(),
            rhs: Vec::new(),
            delta: Vec::new(),
            dof: vec![usize::MAX; n],
            work: SolverWork::default(),
            timing: ImplicitTiming::default(),
            regression: None,
            mechanics: true,
            flags: Vec::new(),
            row_bonds: Vec::new(),
            flags_fresh: false,
            general_passes: false,
            ranks: brisance_grid::comm::NodeRuns::serial(n),
            x,
            geom,
        };
        s.has_spring_state = s
            .laws
            .iter()
            .any(|l| l.yield_strain.is_finite() || l.fracture_strain.is_finite() || l.k_arm > 0.0);
        for i in 0..n {
            if let NodeKind::Solid(m) = s.geom.kind[i] {
                let v = dual_volume(&s.geom, &s.x, i);
                let mat = &s.materials[usize::from(m)];
                s.volume[i] = v;
                s.mass_k[usize::from(m) * n + i] = mat.eos.rho0 * v;
                s.mass[i] = mat.eos.rho0 * v;
                s.temperature[i] = options.initial_temperature;
                s.energy[i] = mat.eos.cv * options.initial_temperature;
                s.pressure[i] = brisance_core::Eos::pressure(&mat.eos, mat.eos.rho0, s.energy[i]);
            }
        }
        Ok(s)
    }

    /// Number of nodes of the box (solid and exterior).
    pub fn len(&self) -> usize {
        self.geom.len()
    }

    /// Whether the lattice has no nodes.
    pub fn is_empty(&self) -> bool {
        self.geom.is_empty()
    }

    /// Declares that positions, velocities or body forces were changed
    /// from outside between steps, so the forces kept by velocity Verlet
    /// from the previous step are recomputed.
    pub fn mark_modified(&mut self) {
        self.forces_current = false;
        self.flags_fresh = false;
    }

    /// Whether any spring law has a parallel dashpot (velocity-dependent
    /// forces).
    pub(crate) fn laws_have_dashpots(&self) -> bool {
        self.laws.iter().any(|l| l.c_par > 0.0)
    }

    /// Number of intact springs.
    pub fn intact_springs(&self) -> usize {
        self.status.iter().filter(|&&s| s == INTACT).count()
    }

    /// Number of broken springs.
    pub fn broken_springs(&self) -> usize {
        self.status.iter().filter(|&&s| s == BROKEN).count()
    }

    /// Status of bond `(i, d)`: `None` if no spring was ever there, else
    /// `Some(intact)`.
    pub fn spring_intact(&self, i: usize, d: usize) -> Option<bool> {
        match self.status[i * self.geom.directions.len() + d] {
            NO_BOND => None,
            s => Some(s == INTACT),
        }
    }

    /// Axial force F of spring `(i, d)` at the current state (positive in
    /// tension), `None` if there is no intact spring.
    pub fn spring_force(&self, i: usize, d: usize) -> Option<f64> {
        let b = i * self.geom.directions.len() + d;
        (self.status[b] == INTACT).then(|| self.eval_bond(i, d, self.spring[b]).axial_force)
    }

    /// Material of node `i`, if solid.
    #[inline]
    pub fn material_of(&self, i: usize) -> Option<usize> {
        match self.geom.kind[i] {
            NodeKind::Solid(m) => Some(usize::from(m)),
            NodeKind::Exterior => None,
        }
    }

    /// Total linear momentum Σ m u of the solid nodes.
    pub fn momentum(&self) -> [f64; 3] {
        let mut p = [0.0; 3];
        for i in 0..self.len() {
            for a in 0..3 {
                p[a] += self.mass[i] * self.u[a][i];
            }
        }
        p
    }

    /// Kinetic energy ½ Σ m u², J.
    pub fn kinetic_energy(&self) -> f64 {
        (0..self.len())
            .map(|i| {
                0.5 * self.mass[i]
                    * (self.u[0][i].powi(2) + self.u[1][i].powi(2) + self.u[2][i].powi(2))
            })
            .sum()
    }

    /// Elastic energy ½ Σ k∞ (s − s_p)² + ½ k₁ (s − δ)² of the intact
    /// springs (plus the perpendicular springs), J.
    pub fn spring_energy(&self) -> f64 {
        let nd = self.geom.directions.len();
        let mut e = 0.0;
        for i in 0..self.len() {
            for d in 0..nd {
                if self.status[i * nd + d] != INTACT {
                    continue;
                }
                let b = self.eval_bond(i, d, self.spring[i * nd + d]);
                let law = self.law(i, d);
                let len0 = self.len0(d);
                let st = self.spring[i * nd + d];
                e += 0.5 * law.k_inf * len0 * (b.s - st.plastic).powi(2)
                    + 0.5 * law.k_arm * len0 * (b.s - st.dashpot).powi(2);
                if b.k_perp > 0.0 {
                    let dir = self.geom.directions[d];
                    let h = self.geom.spacing;
                    let j = (i as isize + dir.offset) as usize;
                    let mut eta = [0.0; 3];
                    for a in 0..3 {
                        eta[a] = self.x[a][j] - self.x[a][i] - f64::from(dir.step[a]) * h;
                    }
                    let along = eta[0] * b.e0[0] + eta[1] * b.e0[1] + eta[2] * b.e0[2];
                    let perp2 = eta.iter().map(|v| v * v).sum::<f64>() - along * along;
                    e += 0.5 * b.k_perp * perp2;
                }
            }
        }
        e
    }

    /// Reference length of direction `d`.
    #[inline]
    pub(crate) fn len0(&self, d: usize) -> f64 {
        let s = self.geom.directions[d].step;
        let q = f64::from(s[0] * s[0] + s[1] * s[1] + s[2] * s[2]);
        q.sqrt() * self.geom.spacing
    }

    #[inline]
    fn law(&self, i: usize, d: usize) -> &PairLaw {
        let j = (i as isize + self.geom.directions[d].offset) as usize;
        let nm = self.materials.len();
        let mi = self.material_of(i).unwrap_or(0);
        let mj = self.material_of(j).unwrap_or(0);
        &self.laws[mi * nm + mj]
    }

    /// Force and kinematics of bond `(i, d)` from spring state `st`
    /// (seed 003 eq 6 with eq 10b's f⊥).
    #[inline]
    pub(crate) fn eval_bond(&self, i: usize, d: usize, st: SpringState) -> BondEval {
        let dir = self.geom.directions[d];
        let j = (i as isize + dir.offset) as usize;
        let h = self.geom.spacing;
        let mut xi = [0.0; 3];
        let mut r = [0.0; 3];
        let mut w = [0.0; 3];
        for a in 0..3 {
            xi[a] = f64::from(dir.step[a]) * h;
            r[a] = self.x[a][j] - self.x[a][i];
            w[a] = self.u[a][j] - self.u[a][i];
        }
        bond_force(self.law(i, d), xi, r, w, st, dir.axial)
    }

    /// Commits the spring state at the end of a step of length `dt`:
    /// plastic return mapping, dashpot relaxation, and fracture when the
    /// tensile strain exceeds the fracture strain (irreversible). Returns
    /// the number of springs broken and whether any state changed.
    pub fn commit_springs(&mut self, dt: f64) -> (usize, bool) {
        if !self.has_spring_state {
            // Elastic, unbreakable springs without Maxwell arms: nothing
            // to commit.
            return (0, false);
        }
        let nd = self.geom.directions.len();
        let mut status = std::mem::take(&mut self.status);
        let mut spring = std::mem::take(&mut self.spring);
        let own = self.owned_nodes();
        let (broken, changed) = {
            let this = &*self;
            status
                .par_chunks_mut(nd)
                .zip(spring.par_chunks_mut(nd))
                .enumerate()
                .map(|(i, (st, sp))| {
                    let mut broken = 0usize;
                    let mut changed = false;
                    if !own.contains(&i) {
                        return (broken, changed);
                    }
                    for d in 0..nd {
                        if st[d] != INTACT {
                            continue;
                        }
                        let b = this.eval_bond(i, d, sp[d]);
                        let law = this.law(i, d);
                        let len0 = this.len0(d);
                        let mut new = b.state;
                        new.dashpot = law.advance_dashpot(sp[d].dashpot, b.s, dt);
                        if new != sp[d] {
                            changed = true;
                            sp[d] = new;
                        }
                        if b.s > law.fracture_strain * len0 {
                            st[d] = BROKEN;
                            broken += 1;
                            changed = true;
                        }
                    }
                    (broken, changed)
                })
                .reduce(|| (0, false), |a, b| (a.0 + b.0, a.1 || b.1))
        };
        self.status = status;
        self.spring = spring;
        let (broken, changed) = self.share_springs(broken, changed);
        if changed {
            self.forces_current = false;
            self.flags_fresh = false;
        }
        (broken, changed)
    }

    /// Recomputes the dual-mesh volumes and advances the energy equation
    /// over `dt` (seed 003 eqs 10a, 10c, 11, 14, 15):
    ///
    /// - ΔP = −K ΔV / V (eq 11), K = ρ₀c₀² of the node's material;
    /// - Δe = c_v (dT/dP) ΔP + Σ_k h_k ṁ_k Δt / m + Q Δt / m, with dT/dP =
    ///   V/(m𝒢c_v) from the EOS (eq 14) and Q the conducted power;
    /// - T = e/c_v (eq 13d); m_k += ṁ_k Δt (eq 10a).
    ///
    /// Q is the centred difference along the axial springs,
    /// Q_i = Σ_j κ_ij h (T_j − T_i) (= V ∇·(κ∇T) on an interior node), with
    /// κ_ij the harmonic mean of the two conductivities; across an exterior
    /// neighbour or a broken spring the neighbour is a ghost at the
    /// surroundings' temperature and conductivity.
    pub fn update_volume_and_energy(&mut self, dt: f64) {
        let n = self.len();
        // Chemistry on at all (the sum below is +0 when every rate is 0).
        let chem_on = self.mass_rate.iter().any(|&r| r != 0.0);
        if self.stencil_applies() {
            self.volume_energy_stencil(dt, chem_on);
            return;
        }
        let [mut v_new, mut e_new, mut p_new, mut t_new] = std::mem::take(&mut self.scratch);
        // Conductances per material pair, formed once per step as
        // [`MsdmLattice::conduction`] forms them per spring (same bits).
        let nm = self.materials.len();
        let table = (nm <= MAX_TABLE_MATERIALS).then(|| {
            let h = self.geom.spacing;
            let sur = self.options.surroundings;
            let mut pair = [0.0; MAX_TABLE_MATERIALS * MAX_TABLE_MATERIALS];
            let mut ghost = [0.0; MAX_TABLE_MATERIALS];
            for a in 0..nm {
                let ka = self.materials[a].conductivity;
                for b in 0..nm {
                    pair[a * nm + b] = harmonic(ka, self.materials[b].conductivity) * h;
                }
                ghost[a] = harmonic(ka, sur.conductivity) * h;
            }
            (pair, ghost)
        });
        // The axial directions (index, linear offset), in direction order.
        let mut axial = [(0usize, 0isize); 3];
        let mut n_axial = 0;
        for (d, dir) in self.geom.directions.iter().enumerate() {
            if dir.axial {
                axial[n_axial] = (d, dir.offset);
                n_axial += 1;
            }
        }
        let axial = &axial[..n_axial];
        let two = self.geom.dim == super::geometry::Dim::Two;
        let own = self.owned_nodes();
        {
            let this = &*self;
            v_new
                .par_iter_mut()
                .zip(e_new.par_iter_mut())
                .zip(p_new.par_iter_mut())
                .zip(t_new.par_iter_mut())
                .enumerate()
                .for_each(|(i, (((v, e), p), t))| {
                    if !own.contains(&i) {
                        return;
                    }
                    let Some(m) = this.material_of(i) else {
                        *v = 0.0;
                        *e = this.energy[i];
                        *p = this.pressure[i];
                        *t = this.temperature[i];
                        return;
                    };
                    *v = if two {
                        dual_volume_2d(&this.geom, &this.x[0], &this.x[1], i)
                    } else {
                        dual_volume(&this.geom, &this.x, i)
                    };
                    if !this.options.thermal {
                        *e = this.energy[i];
                        *p = this.pressure[i];
                        *t = this.temperature[i];
                        return;
                    }
                    let mat = &this.materials[m];
                    let v_old = this.volume[i];
                    let mass = this.mass[i];
                    let dp = -mat.bulk_modulus() * (*v - v_old) / v_old;
                    let mut de = mat.eos.cv * mat.eos.dtemperature_dpressure(mass / v_old) * dp;
                    let mut chem = 0.0;
                    if chem_on {
                        for k in 0..nm {
                            chem += this.materials[k].enthalpy * this.mass_rate[k * n + i];
                        }
                    }
                    let q = match &table {
                        Some((pair, ghost)) => {
                            this.conduction_by(i, m, axial, |a, b| pair[a * nm + b], |a| ghost[a])
                        }
                        None => this.conduction(i),
                    };
                    de += (chem + q) * dt / mass;
                    *e = this.energy[i] + de;
                    *p = this.pressure[i] + dp;
                    *t = *e / mat.eos.cv;
                });
        }
        self.commit_thermal_state([v_new, e_new, p_new, t_new], chem_on, nm, dt);
    }

    /// Makes the new volume, energy, pressure and temperature the state
    /// (the old arrays become the scratch of the next step) and, with the
    /// chemistry on, advances the `nm` component masses by their rates over
    /// `dt` (never below 0) and sums them into the node masses.
    fn commit_thermal_state(
        &mut self,
        [mut v_new, mut e_new, mut p_new, mut t_new]: [Vec<f64>; 4],
        chem_on: bool,
        nm: usize,
        dt: f64,
    ) {
        self.share_thermal_state([&mut v_new, &mut e_new, &mut p_new, &mut t_new]);
        std::mem::swap(&mut self.volume, &mut v_new);
        std::mem::swap(&mut self.energy, &mut e_new);
        std::mem::swap(&mut self.pressure, &mut p_new);
        std::mem::swap(&mut self.temperature, &mut t_new);
        self.scratch = [v_new, e_new, p_new, t_new];
        if chem_on {
            let n = self.len();
            for k in 0..nm {
                for i in 0..n {
                    let mk = &mut self.mass_k[k * n + i];
                    *mk = (*mk + self.mass_rate[k * n + i] * dt).max(0.0);
                }
            }
            for i in 0..n {
                self.mass[i] = (0..nm).map(|k| self.mass_k[k * n + i]).sum();
            }
        }
    }

    /// Conducted power into node `i`, W (see
    /// [`MsdmLattice::update_volume_and_energy`]).
    #[inline]
    pub fn conduction(&self, i: usize) -> f64 {
        let Some(m) = self.material_of(i) else {
            return 0.0;
        };
        let h = self.geom.spacing;
        let sur = self.options.surroundings;
        let k = |a: usize| self.materials[a].conductivity;
        let mut axial = [(0usize, 0isize); 3];
        let mut n_axial = 0;
        for (d, dir) in self.geom.directions.iter().enumerate() {
            if dir.axial {
                axial[n_axial] = (d, dir.offset);
                n_axial += 1;
            }
        }
        self.conduction_by(
            i,
            m,
            &axial[..n_axial],
            |a, b| harmonic(k(a), k(b)) * h,
            |a| harmonic(k(a), sur.conductivity) * h,
        )
    }

    /// The sum of [`MsdmLattice::conduction`] at solid node `i` of
    /// material `m`, with the conductance κ_ij h of a spring between
    /// materials (a, b) from `pair` and that to a ghost from `ghost`;
    /// `axial` lists the axial directions (index, linear offset) in
    /// direction order.
    #[inline(always)]
    fn conduction_by(
        &self,
        i: usize,
        m: usize,
        axial: &[(usize, isize)],
        pair: impl Fn(usize, usize) -> f64,
        ghost: impl Fn(usize) -> f64,
    ) -> f64 {
        let nd = self.geom.directions.len();
        let sur = self.options.surroundings;
        let ti = self.temperature[i];
        let mut q = 0.0;
        for &(d, offset) in axial {
            for sign in [1isize, -1] {
                let j = (i as isize + sign * offset) as usize;
                let bond = if sign > 0 { i * nd + d } else { j * nd + d };
                if self.status[bond] == INTACT {
                    let mj = self.material_of(j).unwrap_or(m);
                    q += pair(m, mj) * (self.temperature[j] - ti);
                } else {
                    q += ghost(m) * (sur.temperature - ti);
                }
            }
        }
        q
    }

    /// Whether node `i`'s velocity component `a` is held (prescribed with
    /// axis `a` in its [`MsdmLattice::held_axes`]).
    #[inline]
    pub fn is_held(&self, i: usize, a: usize) -> bool {
        self.prescribed[i] && self.held_axes[i] & (1 << a) != 0
    }
}
