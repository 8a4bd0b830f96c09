//! The implicit-pressure variant of steps 3 and 5 (seed 000 §3.3, last
//! paragraph: "a Poisson equation is solved in the calculation of Δp,
//! which is in turn used to iteratively update the face-centered
//! velocities \[8\]"), after Kashiwa et al., LA-13773-MS (2000), and
//! Uintah's implicit ICE (impICE: the matrix of setupMatrix, the
//! right-hand side of setupRHS and the outer iterations with recomputed
//! face velocities).
//!
//! Eq 20 with the face velocities of eq 19 evaluated at the time-advanced
//! pressure p instead of p_eq reads, per cell,
//!
//! Σ_r θ_r κ_r (p − p_eq)/Δt + Σ_r ∇·(θ*_r u*_r(p)) = 0,
//!
//! with u*_r(p) = ū_r − Δt v̂_r ∇p (eq 19, v̂_r = 2 v_L v_R/(v_L + v_R)),
//! followed by the face exchange. It is solved by outer iterations
//! p^{k+1} = p^k + δp with the Helmholtz equation
//!
//! Σθκ δp/Δt − ∇·(Δt β ∇δp) = −R^k/Δt,
//! R^k = Δt Σ_r ∇·(θ*_r u*_r(p^k)) + Σθκ (p^k − p_eq),
//!
//! β = Σ_r θ_r,f ŵ_r on each face, ŵ the face exchange applied to the
//! v̂_r (the exact linear response of the exchanged face velocities to a
//! pressure difference: with K = 0, β = Σ θ v̂; with K → ∞, β = Σθ/ρ_mix
//! at the face). R is the dimensionless volume misfit of one step; the
//! iteration stops when max |R| ≤ `tolerance`. The face velocities of each
//! iterate are those of [`IceSolver::compute_face_centred_velocities`] and
//! the divergence that of [`IceSolver::compute_pressure_increment`], run
//! with p^k in place of p_eq, so the converged state is eq 19–21's with p
//! on the right-hand side: the explicit step with the pressure waves taken
//! implicitly. The matrix depends only on the state at the step's start
//! and Δt: it is factorised (sparse Cholesky, faer) once per step, and its
//! symbolic analysis once per run.
//!
//! Unknowns are the cells in global order (x fastest). Wall, symmetry and
//! outflow faces hold the face velocity (walls) or the pressure gradient
//! (zero-gradient ghosts) fixed and add nothing to the matrix; periodic
//! faces couple the two ends; a fixed-state face holds its ghost pressure,
//! a Dirichlet term on the diagonal. Everything is summed in global cell
//! order and faer runs sequentially here, so the bits do not depend on the
//! thread count or the patch split.

use brisance_core::{Eos, SolverError};
use faer::linalg::solvers::Solve;
use faer::sparse::linalg::solvers::{Llt, SymbolicLlt};
use faer::sparse::{SparseColMat, Triplet};
use faer::Side;
use serde::{Deserialize, Serialize};

use super::{
    for_each_cell_global, global_of, make_params, CellVolumes, IceSolver, NS, RHO, SOUND, THETA,
    VSP,
};
use crate::equilibration::MAX_MATERIALS;
use crate::exchange::momentum_exchange;
use crate::IceBoundary;
use brisance_core::Geometry;

/// How steps 3 and 5 find the time-advanced pressure.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub enum PressureSolve {
    /// Eq 20 as printed: Δp from the face velocities of eq 19 at p_eq. The
    /// time step is bounded by the sound speed (CFL on |u| + c).
    #[default]
    Explicit,
    /// The pressure Helmholtz equation, iterated with the face velocities
    /// (module documentation). The time step is bounded by the material
    /// velocity alone (CFL on |u|).
    Implicit(ImplicitPressure),
}

/// Settings of the implicit pressure solve.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct ImplicitPressure {
    /// Largest admitted |R| of any cell, R = Δt Σ_r ∇·(θ*_r u*_r) +
    /// Σθκ (p − p_eq): the volume misfit of one step as a fraction of the
    /// cell (dimensionless, > 0; default 1e-10).
    pub tolerance: f64,
    /// Outer iterations (Helmholtz solves) allowed per step before the
    /// step fails (≥ 1; default 20).
    pub max_iterations: usize,
    /// Times a failed step is retried as two steps of half its Δt (0 to
    /// [`MAX_STEP_RETRIES`]; default 4, down to Δt/16): a solve that does not
    /// converge, diverges or converges to face velocities that move more
    /// than a cell's content in the step. A step that still fails at the
    /// last halving stops the run.
    pub retries: u32,
}

/// The most halvings [`ImplicitPressure::retries`] admits (Δt/2²⁰ ≈ 10⁻⁶ Δt).
pub const MAX_STEP_RETRIES: u32 = 20;

impl Default for ImplicitPressure {
    fn default() -> Self {
        Self {
            tolerance: 1e-10,
            max_iterations: 20,
            retries: 4,
        }
    }
}

impl ImplicitPressure {
    /// Checks the settings; the message names the field.
    pub fn validate(&self) -> Result<(), String> {
        if !(self.tolerance > 0.0 && self.tolerance.is_finite()) {
            return Err(format!(
                "field `tolerance` = {}, expected a finite value > 0",
                self.tolerance
            ));
        }
        if self.max_iterations == 0 {
            return Err("field `max_iterations` = 0, expected at least 1".into());
        }
        if self.retries > MAX_STEP_RETRIES {
            return Err(format!(
                "field `retries` = {}, expected at most {MAX_STEP_RETRIES}",
                self.retries
            ));
        }
        Ok(())
    }
}

/// Iterations and residuals of the implicit pressure solve.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct PressureSolveStats {
    /// Helmholtz solves of the last step.
    pub iterations: usize,
    /// max |R| of the last step at convergence.
    pub residual: f64,
    /// Largest iteration count of any step.
    pub max_iterations: usize,
    /// Largest converged max |R| of any step.
    pub max_residual: f64,
    /// Helmholtz solves summed over the steps.
    pub total_iterations: u64,
    /// Implicit steps taken.
    pub steps: u64,
    /// Symbolic analyses of the matrix (one per run: its sparsity does not
    /// change).
    pub symbolic_factorisations: u64,
    /// Numeric Cholesky factorisations (at most one per step).
    pub numeric_factorisations: u64,
    /// Steps whose solve failed and that were retried as two steps of
    /// half their Δt ([`ImplicitPressure::retries`]).
    pub halved_steps: u64,
}

/// The sparsity of the Helmholtz matrix (lower triangle, CSC) and its
/// symbolic Cholesky analysis, built once per run.
struct Pattern {
    matrix: SparseColMat<usize, f64>,
    symbolic: SymbolicLlt<usize>,
    /// Value slot of each cell's diagonal.
    diag: Vec<usize>,
    /// Faces between two cells: (low cell, high cell, axis, value slot of
    /// the off-diagonal), the low cell's high face (wrapping on periodic
    /// axes), in global order of the low cell, then the axis.
    couplings: Vec<(usize, usize, usize, usize)>,
    /// Fixed-state faces: (cell, axis, side 0 low / 1 high).
    dirichlet: Vec<(usize, usize, usize)>,
}

/// Work arrays of the implicit solve (one value per cell, global order).
#[derive(Default)]
pub(super) struct ImplicitWorkspace {
    pattern: Option<Pattern>,
    /// The state's p_eq columns (ghosts included) during the iteration.
    saved_p_eq: Vec<Vec<f64>>,
    p_eq: Vec<f64>,
    p: Vec<f64>,
    kappa: Vec<f64>,
    divergence: Vec<f64>,
    rhs: Vec<f64>,
    /// β of each cell's high face per axis, and of its low face (used on
    /// a fixed-state low boundary only).
    beta_hi: [Vec<f64>; 3],
    beta_lo: [Vec<f64>; 3],
    pub(super) stats: PressureSolveStats,
}

impl std::fmt::Debug for ImplicitWorkspace {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("ImplicitWorkspace")
            .field("cells", &self.p.len())
            .field("analysed", &self.pattern.is_some())
            .field("stats", &self.stats)
            .finish()
    }
}

/// β of one face (m³/kg): Σ_r θ_r,f ŵ_r, with ŵ the face exchange
/// (eq 29 on the face, face ρ and θ the means of the two cells', as in
/// step 3) applied to v̂_r = 2 v_L v_R/(v_L + v_R), the coefficient of
/// −Δt ∇p in eq 19. The volume flux Σ θ_f u* through the face then
/// changes by −Δt β ∂δp/∂x for a pressure correction δp.
#[allow(clippy::too_many_arguments)]
pub fn face_coefficient(
    rho_l: &[f64],
    rho_r: &[f64],
    theta_l: &[f64],
    theta_r: &[f64],
    v_l: &[f64],
    v_r: &[f64],
    k: &[f64],
    dt: f64,
) -> f64 {
    let n = rho_l.len();
    let mut w = [[0.0; 1]; MAX_MATERIALS];
    let mut rho_f = [0.0; MAX_MATERIALS];
    let mut th_f = [0.0; MAX_MATERIALS];
    for r in 0..n {
        w[r][0] = 2.0 * v_l[r] * v_r[r] / (v_l[r] + v_r[r]);
        rho_f[r] = 0.5 * (rho_l[r] + rho_r[r]);
        th_f[r] = 0.5 * (theta_l[r] + theta_r[r]);
    }
    momentum_exchange(&rho_f[..n], &th_f[..n], k, dt, &mut w[..n]);
    (0..n).map(|r| th_f[r] * w[r][0]).sum()
}

/// Builds the sparsity of the Helmholtz matrix for a grid of `cells`
/// with the given boundaries and active axes, and its symbolic analysis.
fn build_pattern(
    cells: [usize; 3],
    active: [bool; 3],
    boundaries: &[IceBoundary; 6],
) -> Result<Pattern, String> {
    let count = cells[0] * cells[1] * cells[2];
    let stride = [1, cells[0], cells[0] * cells[1]];
    let mut couplings = Vec::new();
    let mut dirichlet = Vec::new();
    let mut triplets: Vec<Triplet<usize, usize, f64>> = Vec::with_capacity(4 * count);
    for g in 0..count {
        let idx = [
            g % cells[0],
            (g / cells[0]) % cells[1],
            g / (cells[0] * cells[1]),
        ];
        triplets.push(Triplet::new(g, g, 0.0));
        for a in 0..3 {
            if !active[a] {
                continue;
            }
            let last = cells[a] - 1;
            if idx[a] == 0 && matches!(boundaries[2 * a], IceBoundary::FixedState(_)) {
                dirichlet.push((g, a, 0));
            }
            let hi = if idx[a] < last {
                Some(g + stride[a])
            } else {
                match boundaries[2 * a + 1] {
                    IceBoundary::Periodic => Some(g - last * stride[a]),
                    IceBoundary::FixedState(_) => {
                        dirichlet.push((g, a, 1));
                        None
                    }
                    _ => None,
                }
            };
            if let Some(h) = hi {
                couplings.push((g, h, a, usize::MAX));
                triplets.push(Triplet::new(g.max(h), g.min(h), 0.0));
            }
        }
    }
    let matrix = SparseColMat::<usize, f64>::try_new_from_triplets(count, count, &triplets)
        .map_err(|e| format!("pressure matrix sparsity: {e:?}"))?;
    let slot = |row: usize, col: usize| -> usize {
        let (sym, _) = matrix.parts();
        let start = sym.col_ptr()[col];
        let rows = &sym.row_idx()[start..sym.col_ptr()[col + 1]];
        start + rows.binary_search(&row).expect("entry of the pattern")
    };
    let diag = (0..count).map(|g| slot(g, g)).collect();
    for c in &mut couplings {
        c.3 = slot(c.0.max(c.1), c.0.min(c.1));
    }
    let symbolic = SymbolicLlt::try_new(matrix.symbolic(), Side::Lower)
        .map_err(|e| format!("pressure matrix symbolic analysis: {e:?}"))?;
    Ok(Pattern {
        matrix,
        symbolic,
        diag,
        couplings,
        dirichlet,
    })
}

impl ImplicitWorkspace {
    /// Writes the Helmholtz matrix's values (lower triangle) from κ and β:
    /// diagonal Σθκ/Δt + Σ_faces Δt β/Δx², off-diagonal −Δt β/Δx².
    ///
    /// On an axisymmetric grid (`rings`) each row is the cell's equation
    /// times its ring volume V, so the matrix stays symmetric: diagonal
    /// Σθκ V/Δt + Σ_faces Δt β A_f/Δx, off-diagonal −Δt β A_f/Δx with A_f
    /// the face's area (2π r_f Δz radially, the annulus axially), and the
    /// right-hand side is scaled by V too ([`Self::scale_rhs`]).
    fn assemble(&mut self, dt: f64, spacing: [f64; 3], rings: Option<CellVolumes>) {
        // Each row's weight (1, or the ring's volume) and, per face, what
        // Δt β is divided by: Δx², or Δx/A_f on rings.
        let r_lo = |v: &CellVolumes, i: usize| v.origin + i as f64 * v.spacing[0];
        let row = |g: usize| rings.map_or(1.0, |v| v.cell(g));
        let across = |g: usize, a: usize, side: usize| -> f64 {
            match rings {
                None => spacing[a] * spacing[a],
                Some(v) => {
                    let [dr, dz, _] = v.spacing;
                    let i = g % v.columns;
                    if a == 0 {
                        dr / Geometry::Axisymmetric.x_face_area(r_lo(&v, i + side), dz, 1.0)
                    } else {
                        dz / Geometry::Axisymmetric.y_face_area(r_lo(&v, i), dr, 1.0)
                    }
                }
            }
        };
        let pattern = self.pattern.as_mut().expect("pattern built");
        let val = pattern.matrix.val_mut();
        val.fill(0.0);
        for (g, &k) in self.kappa.iter().enumerate() {
            val[pattern.diag[g]] += k * row(g) / dt;
        }
        for &(g, h, a, s) in &pattern.couplings {
            let c = dt * self.beta_hi[a][g] / across(g, a, 1);
            val[pattern.diag[g]] += c;
            val[pattern.diag[h]] += c;
            val[s] -= c;
        }
        for &(g, a, side) in &pattern.dirichlet {
            let beta = if side == 0 {
                self.beta_lo[a][g]
            } else {
                self.beta_hi[a][g]
            };
            val[pattern.diag[g]] += dt * beta / across(g, a, side);
        }
    }

    /// The right-hand side of an axisymmetric grid's rows, times each
    /// cell's ring volume ([`Self::assemble`]).
    fn scale_rhs(&mut self, vols: CellVolumes) {
        for (g, r) in self.rhs.iter_mut().enumerate() {
            *r *= vols.cell(g);
        }
    }

    /// Numeric Cholesky factorisation of the assembled matrix with the
    /// run's symbolic analysis.
    fn factorise(&mut self) -> Result<Llt<usize, f64>, String> {
        let pattern = self.pattern.as_ref().expect("pattern built");
        self.stats.numeric_factorisations += 1;
        Llt::try_new_with_symbolic(
            pattern.symbolic.clone(),
            pattern.matrix.as_ref(),
            Side::Lower,
        )
        .map_err(|e| format!("pressure matrix is not positive definite: {e:?}"))
    }
}

/// Solves A x = rhs with the factorisation, into `x`.
fn solve_into(llt: &Llt<usize, f64>, rhs: &[f64], x: &mut [f64]) {
    let b = faer::Col::<f64>::from_fn(rhs.len(), |i| rhs[i]);
    let sol = llt.solve(&b);
    for (i, xi) in x.iter_mut().enumerate() {
        *xi = sol[i];
    }
}

impl<E: Eos> IceSolver<E> {
    /// Iterations and residuals of the implicit pressure solve
    /// ([`PressureSolve::Implicit`]); all zero with the explicit one.
    pub fn pressure_solve_stats(&self) -> PressureSolveStats {
        self.implicit.stats
    }

    /// The largest rate Σ_d |w_d|/Δx_d of a moving wall (fixed-velocity
    /// face): the implicit time step must not let the wall's inflow cross
    /// more than a fraction cfl of a cell either.
    pub(super) fn wall_rate(&self) -> f64 {
        let spacing = self.level.geometry.spacing;
        self.boundaries
            .iter()
            .filter_map(IceBoundary::wall_velocity)
            .map(|w| {
                (0..3)
                    .filter(|&a| self.level.is_active(a))
                    .map(|a| w[a].abs() / spacing[a])
                    .sum::<f64>()
            })
            .fold(0.0, f64::max)
    }

    /// Steps 3 and 5 with the implicit pressure (module documentation):
    /// the face velocities u*_r and the time-advanced pressure p of the
    /// converged outer iteration, ready for
    /// [`IceSolver::compute_lagrangian_values`]. A step that does not
    /// converge within `max_iterations` stops the run with an error that
    /// names the step, the residual and the cell.
    pub fn compute_implicit_pressure(
        &mut self,
        dt: f64,
        settings: ImplicitPressure,
    ) -> Result<(), SolverError> {
        let n = self.eos.len();
        let pidx = n * NS;
        let mut ws = std::mem::take(&mut self.implicit);
        ws.saved_p_eq.resize_with(self.state.len(), Vec::new);
        for (saved, pf) in ws.saved_p_eq.iter_mut().zip(&self.state) {
            saved.clear();
            saved.extend_from_slice(&pf.data[pidx]);
        }
        let out = self.implicit_iterations(&mut ws, dt, settings);
        // The state keeps p_eq (steps 8–11 read it); p goes to the
        // pressure group.
        for (pf, saved) in self.state.iter_mut().zip(&ws.saved_p_eq) {
            pf.data[pidx].copy_from_slice(saved);
        }
        if out.is_ok() {
            let p = &ws.p;
            for_each_cell_global(&self.level, &mut self.press, |g, d, c| d[0][c] = p[g]);
        }
        self.implicit = ws;
        out
    }

    fn implicit_iterations(
        &mut self,
        ws: &mut ImplicitWorkspace,
        dt: f64,
        settings: ImplicitPressure,
    ) -> Result<(), SolverError> {
        let n = self.eos.len();
        let pidx = n * NS;
        let geometry = self.level.geometry;
        let count = geometry.cell_count();
        let (step, time) = (self.steps + 1, self.time);
        let fail = move |msg: String| {
            SolverError::Other(format!(
                "ice: implicit pressure, step {step} (t = {time:e} s, Δt = {dt:e} s): {msg}"
            ))
        };
        for v in [
            &mut ws.p_eq,
            &mut ws.p,
            &mut ws.kappa,
            &mut ws.divergence,
            &mut ws.rhs,
        ] {
            v.resize(count, 0.0);
        }
        if ws.pattern.is_none() {
            let active = std::array::from_fn(|d| self.level.is_active(d));
            ws.pattern =
                Some(build_pattern(geometry.cells, active, &self.boundaries).map_err(&fail)?);
            ws.stats.symbolic_factorisations += 1;
        }
        self.gather_cells(&mut ws.p_eq, |pid, c| self.state[pid].data[pidx][c]);
        ws.p.copy_from_slice(&ws.p_eq);
        let mut llt: Option<Llt<usize, f64>> = None;
        let rings = self
            .options
            .geometry
            .is_axisymmetric()
            .then(|| self.volumes());
        let mut k = 0;
        loop {
            if k > 0 {
                let p = &ws.p;
                for_each_cell_global(&self.level, &mut self.state, |g, d, c| d[pidx][c] = p[g]);
            }
            // Eq 19 (and the face exchange) at p^k, then eq 20's divergence.
            self.compute_face_centred_velocities(dt);
            self.compute_pressure_increment(dt);
            self.gather_cells(&mut ws.divergence, |pid, c| self.scratch[pid].divergence[c]);
            if k == 0 {
                self.gather_coefficients(ws, dt);
            }
            let mut worst = (0.0_f64, 0);
            for g in 0..count {
                let r = dt * ws.divergence[g] + ws.kappa[g] * (ws.p[g] - ws.p_eq[g]);
                ws.rhs[g] = -r / dt;
                if !r.is_finite() {
                    worst = (f64::NAN, g);
                    break;
                }
                if r.abs() > worst.0 {
                    worst = (r.abs(), g);
                }
            }
            let cell = |g: usize| {
                let c = geometry.cells;
                [g % c[0], (g / c[0]) % c[1], g / (c[0] * c[1])]
            };
            if worst.0 <= settings.tolerance {
                // The converged face velocities may not move more than a
                // cell's content through a face in the step: the
                // advection (step 12) takes its slabs from one donor cell.
                let (courant, face) = self.largest_face_courant(dt);
                if courant > 1.0 {
                    return Err(fail(format!(
                        "the converged face velocities move {courant:.3} cells' content through the low {} face of cell {:?} in one step (Courant number above 1): lower `time.cfl`",
                        ["x", "y", "z"][face.1],
                        face.0
                    )));
                }
                let s = &mut ws.stats;
                s.iterations = k;
                s.residual = worst.0;
                s.max_iterations = s.max_iterations.max(k);
                s.max_residual = s.max_residual.max(worst.0);
                s.total_iterations += k as u64;
                s.steps += 1;
                return Ok(());
            }
            if worst.0.is_nan() {
                return Err(fail(format!(
                    "non-finite residual in cell {:?} after {k} iterations",
                    cell(worst.1)
                )));
            }
            if k == settings.max_iterations {
                return Err(fail(format!(
                    "not converged after {k} iterations: residual {:e} (tolerance {:e}) in cell {:?}",
                    worst.0,
                    settings.tolerance,
                    cell(worst.1)
                )));
            }
            if llt.is_none() {
                ws.assemble(dt, geometry.spacing, rings);
                llt = Some(ws.factorise().map_err(&fail)?);
            }
            if let Some(vols) = rings {
                ws.scale_rhs(vols);
            }
            let factor = llt.as_ref().expect("factorised");
            // δp into the divergence array (not needed again this pass).
            solve_into(factor, &ws.rhs, &mut ws.divergence);
            for (p, dp) in ws.p.iter_mut().zip(&ws.divergence) {
                *p += dp;
            }
            k += 1;
        }
    }

    /// The largest Courant number |u*_r| Δt/Δx of any material on any face
    /// of the owned patches (the largest over the ranks), and the face:
    /// the global index of the cell on its high side and the axis. Above
    /// 1 (the failure the caller reports) the face is the one a single
    /// rank names, on every rank: the first face with that number in
    /// the scan order of one rank (patch, axis, cell), agreed by one more
    /// minimum over the ranks.
    fn largest_face_courant(&self, dt: f64) -> (f64, ([usize; 3], usize)) {
        // (Courant number, (patch, axis, local cell)); no face until one
        // moves.
        let mut worst = (0.0_f64, None);
        for (pid, ((sc, patch), &own)) in self
            .scratch
            .iter()
            .zip(&self.level.patches)
            .zip(&self.ranks.owned)
            .enumerate()
        {
            if !own {
                continue;
            }
            let (g, st) = (patch.ghost, patch.strides());
            for a in (0..3).filter(|&a| self.level.is_active(a)) {
                let mut hi = [
                    g[0] + patch.size[0],
                    g[1] + patch.size[1],
                    g[2] + patch.size[2],
                ];
                hi[a] += 1;
                let lam = dt / self.level.geometry.spacing[a];
                for k in g[2]..hi[2] {
                    for j in g[1]..hi[1] {
                        for i in g[0]..hi[0] {
                            let c = i + j * st[1] + k * st[2];
                            for fv in &sc.face_velocity[a] {
                                let courant = (fv[c] * lam).abs();
                                if courant > worst.0 || courant.is_nan() {
                                    worst = (courant, Some((pid, a, c)));
                                }
                            }
                        }
                    }
                }
            }
        }
        let largest = self.max_over_ranks(worst.0);
        let mut face = worst.1;
        if largest > 1.0 && self.ranks.several() {
            // The face as one key in the scan order of one rank; exact in
            // an f64 below 2^53 (patches × 3 × allocated cells).
            let span = self
                .level
                .patches
                .iter()
                .map(|p| p.allocated_cells())
                .max()
                .unwrap_or(1);
            let key = match face {
                Some((pid, a, c)) if worst.0 == largest => ((pid * 3 + a) * span + c) as f64,
                _ => f64::INFINITY,
            };
            let first = self.ranks.comm.min(key) as usize;
            face = Some((first / span / 3, first / span % 3, first % span));
        }
        let face = face.map_or(([0; 3], 0), |(pid, a, c)| {
            (global_of(&self.level.patches[pid], c), a)
        });
        (largest, face)
    }

    /// Σθκ per cell and β on every face (global order), from the state at
    /// the step's start; the state's ghosts must be filled (step 3 fills
    /// them).
    fn gather_coefficients(&self, ws: &mut ImplicitWorkspace, dt: f64) {
        let n = self.eos.len();
        let params = solver_params!(self);
        let count = self.level.geometry.cell_count();
        self.gather_cells(&mut ws.kappa, |pid, c| {
            let d = &self.state[pid].data;
            (0..n)
                .map(|r| {
                    let b = r * NS;
                    let cs = d[b + SOUND][c];
                    d[b + THETA][c] * d[b + VSP][c] / (cs * cs)
                })
                .sum()
        });
        // The face exchange of step 3, with its slip weights where step 3
        // takes them (super::slip).
        let solids: Vec<_> = self
            .state
            .iter()
            .map(|pf| super::slip::SolidFraction::new(&params, &pf.data))
            .collect();
        let face = |pid: usize, l: usize, h: usize, a: usize| {
            let d = &self.state[pid].data;
            let get = |f: usize, i: usize| -> [f64; MAX_MATERIALS] {
                std::array::from_fn(|r| if r < n { d[r * NS + f][i] } else { 0.0 })
            };
            let (rho_l, rho_h, th_l, th_h) =
                (get(RHO, l), get(RHO, h), get(THETA, l), get(THETA, h));
            let st = self.level.patches[pid].strides();
            let slip_k;
            let k = match solids[pid].as_ref().and_then(|s| s.face_weight(h, a, st)) {
                Some(w) => {
                    let rho: [f64; MAX_MATERIALS] =
                        std::array::from_fn(|r| 0.5 * (rho_l[r] + rho_h[r]));
                    let theta: [f64; MAX_MATERIALS] =
                        std::array::from_fn(|r| 0.5 * (th_l[r] + th_h[r]));
                    slip_k = super::slip::face_coefficients(&params, &rho[..n], &theta[..n], w);
                    &slip_k[..n * n]
                }
                None => params.k,
            };
            face_coefficient(
                &rho_l[..n],
                &rho_h[..n],
                &th_l[..n],
                &th_h[..n],
                &get(VSP, l)[..n],
                &get(VSP, h)[..n],
                k,
                dt,
            )
        };
        for a in 0..3 {
            if !params.active[a] {
                ws.beta_hi[a].clear();
                ws.beta_lo[a].clear();
                continue;
            }
            ws.beta_hi[a].resize(count, 0.0);
            ws.beta_lo[a].resize(count, 0.0);
            self.gather_cells(&mut ws.beta_hi[a], |pid, c| {
                let st = self.level.patches[pid].strides();
                face(pid, c, c + st[a], a)
            });
            self.gather_cells(&mut ws.beta_lo[a], |pid, c| {
                let p = &self.level.patches[pid];
                if global_of(p, c)[a] == 0 {
                    face(pid, c - p.strides()[a], c, a)
                } else {
                    0.0
                }
            });
        }
    }
}

#[cfg(test)]
mod tests;
