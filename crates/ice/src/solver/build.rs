//! Building an [`IceSolver`]: the checks of the grid's shape, the field
//! sets, the initial state and the ghost values of fixed-state faces.

use std::sync::Arc;

use brisance_grid::comm::{self, Communicator};
use brisance_grid::CellOrder;

use super::*;

/// The shape an axisymmetric grid must have: one cell along z, radii
/// r ≥ 0, the axis (when the grid reaches it) a symmetry face, and no
/// periodic radial pair.
fn check_axisymmetric(level: &Level, boundaries: &[IceBoundary; 6]) -> Result<(), IceError> {
    let g = &level.geometry;
    if g.cells[2] != 1 {
        return Err(IceError::Invalid(format!(
            "ice: an axisymmetric (r, z) grid has one cell along z, got {}",
            g.cells[2]
        )));
    }
    if !(g.origin[0] >= 0.0) {
        return Err(IceError::Invalid(format!(
            "ice: an axisymmetric grid's x is the radius, which starts at r ≥ 0, got {}",
            g.origin[0]
        )));
    }
    if g.origin[0] == 0.0 && boundaries[0] != IceBoundary::Symmetry {
        return Err(IceError::Invalid(
            "ice: the low x face of an axisymmetric grid is the axis r = 0 and must be a symmetry face"
                .into(),
        ));
    }
    if boundaries[0] == IceBoundary::Periodic || boundaries[1] == IceBoundary::Periodic {
        return Err(IceError::Invalid(
            "ice: the radial faces of an axisymmetric grid cannot be periodic".into(),
        ));
    }
    Ok(())
}

/// Field set of `n` materials with `per` fields each (velocity at
/// `vel..vel+3`) and `extra` scalars after them.
fn field_set(n: usize, per: usize, vel: usize, extra: usize) -> FieldSet {
    let mut kinds = Vec::with_capacity(n * per + extra);
    for _ in 0..n {
        for f in 0..per {
            kinds.push(if (vel..vel + 3).contains(&f) {
                FieldKind::VectorComponent(f - vel)
            } else {
                FieldKind::Scalar
            });
        }
    }
    kinds.extend(std::iter::repeat_n(FieldKind::Scalar, extra));
    FieldSet {
        names: vec!["ice"; kinds.len()],
        kinds,
    }
}

impl<E: Eos> IceSolver<E> {
    /// Builds the solver for `eos` (one per material, at most
    /// [`MAX_MATERIALS`]) on `level` (built with [`GHOST`] ghost layers),
    /// with the state `init(cell centre)` in every cell, and equilibrates
    /// it (step 2). It runs on one rank; [`Self::distribute`] spreads it.
    pub fn new(
        eos: Vec<E>,
        level: Level,
        boundaries: [IceBoundary; 6],
        exchange: ExchangeCoefficients,
        options: IceOptions,
        init: impl Fn([f64; 3]) -> CellState + Sync,
    ) -> Result<Self, IceError> {
        let serial: Arc<dyn Communicator> = Arc::new(comm::Serial);
        Self::new_on(serial, eos, level, boundaries, exchange, options, init)
    }

    /// As [`Self::new`], the patches shared among the ranks of `comm` from
    /// the start (docs/cluster.md): this rank allocates, evaluates `init`
    /// on, fills and equilibrates its own patches only, so at no time
    /// does it hold the whole grid, and its build costs its share. A
    /// failing initial state stops every rank with the error of the first
    /// failing cell in patch order (one minimum over the ranks), as on one
    /// rank; the equilibration's first failure is gathered from every
    /// rank. Fails when the patches cannot be shared among the ranks
    /// ([`comm::patch_owners`]) or the options need one rank
    /// ([`Self::whole_grid_pass`]); a whole-grid pass set later (reactions,
    /// transport, Lagrangian materials) is refused by its setter.
    pub fn new_on(
        comm: Arc<dyn Communicator>,
        eos: Vec<E>,
        level: Level,
        boundaries: [IceBoundary; 6],
        exchange: ExchangeCoefficients,
        options: IceOptions,
        init: impl Fn([f64; 3]) -> CellState + Sync,
    ) -> Result<Self, IceError> {
        let n = eos.len();
        exchange.validate(n)?;
        if !(options.cfl > 0.0 && options.cfl <= 1.0) {
            return Err(IceError::Invalid(format!(
                "ice: field `cfl` = {}, expected a value in (0, 1]",
                options.cfl
            )));
        }
        if !(0.0..=1.0).contains(&options.face_pressure_courant) {
            return Err(IceError::Invalid(format!(
                "ice: field `face_pressure_courant` = {}, expected a value in [0, 1]",
                options.face_pressure_courant
            )));
        }
        if let PressureSolve::Implicit(s) = options.pressure {
            s.validate()
                .map_err(|e| IceError::Invalid(format!("ice: field `pressure`: {e}")))?;
        }
        if !(options.max_dt > 0.0) {
            return Err(IceError::Invalid(format!(
                "ice: field `max_dt` = {} must be > 0",
                options.max_dt
            )));
        }
        if options.gravity.iter().any(|g| !g.is_finite()) {
            return Err(IceError::Invalid(
                "ice: field `gravity` must be finite".into(),
            ));
        }
        for d in 0..3 {
            if level.is_active(d) && level.patches.iter().any(|p| p.ghost[d] < GHOST) {
                return Err(IceError::Invalid(format!(
                    "ice: the level needs {GHOST} ghost layers"
                )));
            }
        }
        if options.geometry.is_axisymmetric() {
            check_axisymmetric(&level, &boundaries)?;
        }
        let axisymmetric = options.geometry.is_axisymmetric();
        let state_set = field_set(n, NS, VEL, 1);
        let lag_set = field_set(n, NL, L_VEL, 0);
        let press_set = FieldSet {
            names: vec!["pressure"],
            kinds: vec![FieldKind::Scalar],
        };
        let patches = level.patches.len();
        let owner = comm::patch_owners(patches, comm.size()).map_err(IceError::Invalid)?;
        let owned: Vec<bool> = owner.iter().map(|&o| o == comm.rank()).collect();
        // Storage for this rank's own patches only.
        let fields = |p: &Patch, id: usize, count: usize| {
            if owned[id] {
                PatchFields::zeros(p, count)
            } else {
                PatchFields::unstored(p, count)
            }
        };
        let mut solver = Self {
            eos,
            reactions: Vec::new(),
            state: (level.patches.iter().enumerate())
                .map(|(id, p)| fields(p, id, n * NS + 1))
                .collect(),
            lag: (level.patches.iter().enumerate())
                .map(|(id, p)| fields(p, id, n * NL))
                .collect(),
            press: (level.patches.iter().enumerate())
                .map(|(id, p)| fields(p, id, 1))
                .collect(),
            scratch: (level.patches.iter().enumerate())
                .map(|(id, p)| {
                    if owned[id] {
                        PatchScratch::zeros(&level, p, n, axisymmetric)
                    } else {
                        PatchScratch::empty()
                    }
                })
                .collect(),
            level,
            boundaries: boundaries.clone(),
            exchange,
            options,
            state_set,
            lag_set,
            press_set,
            state_bcs: BoundaryConditions::uniform(FaceBc::Outflow),
            lag_bcs: BoundaryConditions::uniform(FaceBc::Outflow),
            press_bcs: BoundaryConditions::uniform(FaceBc::Outflow),
            halo: if comm.size() > 1 {
                InProcessExchange::distributed(comm.clone(), owner.clone())
            } else {
                InProcessExchange::new()
            },
            time: 0.0,
            steps: 0,
            last_equilibration: EquilibrationStats::default(),
            lagrangian: vec![false; n],
            specific_heat: vec![None; n],
            start_on_particles: false,
            rescaled: ConservationTotals::default(),
            kept_warm: [KeptWarmTotals::default(); MAX_MATERIALS],
            kept_warm_advection: [KeptWarmTotals::default(); MAX_MATERIALS],
            transport: Default::default(),
            implicit: Default::default(),
            blocked_inflow: [false; 6],
            outflow: [ConservationTotals::default(); 6],
            surface_pass: Default::default(),
            ranks: if comm.size() > 1 {
                ranks::Ranks {
                    comm: comm.clone(),
                    owner: owner.clone(),
                    owned: owned.clone(),
                }
            } else {
                ranks::Ranks::serial(patches)
            },
        };
        // Boundary conditions per group.
        for (f, b) in boundaries.iter().enumerate() {
            let face = Face::ALL[f];
            let (s, l, p) = match b {
                IceBoundary::Symmetry | IceBoundary::FixedVelocity(_) => {
                    (FaceBc::Reflective, FaceBc::Reflective, FaceBc::Reflective)
                }
                IceBoundary::Outflow | IceBoundary::ZeroGradient => {
                    (FaceBc::Outflow, FaceBc::Outflow, FaceBc::Outflow)
                }
                IceBoundary::Periodic => (FaceBc::Periodic, FaceBc::Periodic, FaceBc::Periodic),
                IceBoundary::FixedState(cs) => {
                    let (sv, lv, pv) = solver.fixed_values(cs).map_err(|e| {
                        IceError::Invalid(format!("ice: fixed state on {}: {e}", face.name()))
                    })?;
                    (
                        FaceBc::Fixed(sv),
                        FaceBc::Fixed(lv),
                        FaceBc::Fixed(vec![pv]),
                    )
                }
            };
            solver.state_bcs.faces[f] = s;
            solver.lag_bcs.faces[f] = l;
            solver.press_bcs.faces[f] = p;
        }
        solver
            .state_bcs
            .validate(n * NS + 1)
            .map_err(IceError::Invalid)?;
        // The options' whole-grid pass (the implicit pressure) refused
        // before any work on several ranks.
        solver.still_distributable()?;
        // Initial state: each rank evaluates and stores its own patches'
        // cells only; the first failure in patch order over all ranks is
        // evaluated again by every rank, so all meet the same error.
        let geometry = solver.level.geometry;
        let cell_values = |eos: &[E], g: [usize; 3]| {
            Self::material_values(eos, &init(geometry.cell_centre(g)))
                .map_err(|e| format!("ice: initial state in cell {g:?}: {e}"))
        };
        let (eos, state) = (&solver.eos, &mut solver.state);
        let failing =
            solver
                .level
                .first_failing_cell(&*comm, &owner, CellOrder::Patches, |g, pid, n| {
                    let Ok(vals) = cell_values(eos, g) else {
                        return false;
                    };
                    for (f, v) in vals.iter().enumerate() {
                        state[pid].data[f][n] = *v;
                    }
                    true
                });
        if let Some(g) = failing {
            cell_values(&solver.eos, g).map_err(IceError::Invalid)?;
            return Err(IceError::Invalid(
                "ice: an initial state failed on another rank but not here".into(),
            ));
        }
        solver
            .compute_equilibration_pressure()
            .map_err(|e| IceError::Invalid(format!("ice: initial state: {e}")))?;
        Ok(solver)
    }

    /// State-group values (before equilibration) of a cell state.
    fn material_values(eos: &[E], cs: &CellState) -> Result<Vec<f64>, String> {
        let n = eos.len();
        if cs.materials.len() != n {
            return Err(format!(
                "{} material states given for {n} materials",
                cs.materials.len()
            ));
        }
        if !(cs.pressure > 0.0 && cs.pressure.is_finite()) {
            return Err(format!(
                "pressure {} Pa must be finite and > 0",
                cs.pressure
            ));
        }
        let sum: f64 = cs.materials.iter().map(|m| m.volume_fraction).sum();
        if (sum - 1.0).abs() > 1e-6 {
            return Err(format!(
                "volume fractions sum to {sum}, expected 1 (give absent materials a trace)"
            ));
        }
        let mut vals = vec![0.0; n * NS + 1];
        for (r, m) in cs.materials.iter().enumerate() {
            if !(m.volume_fraction > 0.0 && m.volume_fraction <= 1.0) {
                return Err(format!(
                    "material {}: volume_fraction {} must lie in (0, 1]",
                    r + 1,
                    m.volume_fraction
                ));
            }
            if m.velocity.iter().any(|u| !u.is_finite()) {
                return Err(format!("material {}: velocity must be finite", r + 1));
            }
            let rho_micro = m.density;
            let e = eos[r]
                .specific_internal_energy(rho_micro, cs.pressure)
                .map_err(|e| format!("material {}: {e}", r + 1))?;
            let b = r * NS;
            vals[b + RHO] = m.volume_fraction * rho_micro;
            for d in 0..3 {
                vals[b + VEL + d] = m.velocity[d];
            }
            vals[b + ENERGY] = e;
            vals[b + VSP] = 1.0 / rho_micro;
            vals[b + THETA] = m.volume_fraction;
            vals[b + TEMP] = eos[r].temperature(rho_micro, e);
            vals[b + SOUND] = eos[r].sound_speed(rho_micro, e);
        }
        vals[n * NS] = cs.pressure;
        Ok(vals)
    }

    /// Ghost values of a fixed-state face for the three field groups.
    fn fixed_values(&self, cs: &CellState) -> Result<(Vec<f64>, Vec<f64>, f64), String> {
        let n = self.eos.len();
        let mut vals = Self::material_values(&self.eos, cs)?;
        let params = solver_params!(self);
        equilibrate_cell(&params, &mut vals).map_err(|e| e.1)?;
        let mut lag = vec![0.0; n * NL];
        for r in 0..n {
            lag[r * NL + L_RHO] = vals[r * NS + RHO];
            for d in 0..3 {
                lag[r * NL + L_VEL + d] = vals[r * NS + VEL + d];
            }
            lag[r * NL + L_ENERGY] = vals[r * NS + ENERGY];
            lag[r * NL + L_VSP] = vals[r * NS + VSP];
        }
        let p = vals[n * NS];
        Ok((vals, lag, p))
    }
}
