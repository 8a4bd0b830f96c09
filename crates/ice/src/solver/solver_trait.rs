//! The [`Solver`] implementation of [`IceSolver`], with the checkpoint it
//! saves and restores.

use super::*;
use crate::diffusion::TimeStepLimit;
use brisance_core::ExactTotals;
use brisance_grid::{comm, pieces};

/// A checkpoint: the interior state fields in global order, and the
/// running totals of the coupled equilibration's rescaling and of step 2's
/// cold-material rule, so that a restarted run books from where it was.
#[derive(Serialize, Deserialize)]
struct SavedState {
    time: f64,
    steps: u64,
    cells: [usize; 3],
    materials: usize,
    fields: Vec<Vec<f64>>,
    rescaled: ConservationTotals,
    /// Per material (firings, energy), step 2's rule and step 12's.
    kept_warm: Vec<(u64, f64)>,
    kept_warm_advection: Vec<(u64, f64)>,
    /// What has left through each domain face ([`IceSolver::outflow`]).
    outflow: [ConservationTotals; 6],
}

/// A checkpoint written before the faces' outflow was booked: read as
/// one with nothing booked yet.
#[derive(Deserialize)]
struct SavedStateWithoutOutflow {
    time: f64,
    steps: u64,
    cells: [usize; 3],
    materials: usize,
    fields: Vec<Vec<f64>>,
    rescaled: ConservationTotals,
    kept_warm: Vec<(u64, f64)>,
    kept_warm_advection: Vec<(u64, f64)>,
}

impl<E: Eos> IceSolver<E> {
    /// [`Solver::stable_dt`] and the viscous and conduction steps it took
    /// the smaller of ([`Self::diffusive_time_steps`], collective on
    /// several ranks, so every rank computes them whatever its own rate).
    pub(super) fn stable_dt_and_diffusive_steps(&self) -> Result<(f64, (f64, f64)), SolverError> {
        let acoustic = if self.options.pressure == PressureSolve::Explicit {
            1.0
        } else {
            0.0
        };
        let params = solver_params!(self);
        let max_rate = self
            .state
            .par_iter()
            .zip(self.level.patches.par_iter())
            .zip(self.ranks.owned.par_iter())
            .map(|((pf, patch), &own)| {
                if !own {
                    return 0.0;
                }
                let d = &pf.data;
                let max_of = |a: f64, b: f64| {
                    if a.is_nan() || b.is_nan() {
                        f64::NAN
                    } else {
                        a.max(b)
                    }
                };
                par_interior(
                    patch,
                    || 0.0_f64,
                    |max_rate, c| {
                        let rate = cell_cfl_rate(&params, d, c, acoustic).0;
                        // NaN propagates as "not finite" through max below.
                        *max_rate = max_of(*max_rate, rate);
                    },
                    max_of,
                )
            })
            .reduce(
                || 0.0,
                |a, b| {
                    if a.is_nan() || b.is_nan() {
                        f64::NAN
                    } else {
                        a.max(b)
                    }
                },
            );
        let max_rate = self.max_over_ranks(max_rate);
        let max_rate = if acoustic == 0.0 {
            max_rate.max(self.wall_rate())
        } else {
            max_rate
        };
        // A burning front moves at most `cfl` of a cell a step; NaN stays
        // NaN.
        let max_rate = if max_rate.is_nan() {
            max_rate
        } else {
            max_rate.max(self.surface_front_rate())
        };
        let dt = if max_rate > 0.0 {
            self.options.cfl / max_rate
        } else if max_rate == 0.0 {
            f64::INFINITY
        } else {
            f64::NAN
        };
        // The viscous and conduction limits (diffusion_pass) and the
        // largest step allowed; NaN stays NaN.
        let (viscous, conduction) = self.diffusive_time_steps();
        let dt = if dt.is_nan() {
            dt
        } else {
            dt.min(viscous.min(conduction)).min(self.options.max_dt)
        };
        if !(dt >= self.options.min_dt) {
            return Err(SolverError::TimeStepCollapse {
                dt,
                min_dt: self.options.min_dt,
                time: self.time,
                detail: format!(
                    "the fastest signal speed of the ICE materials is too large for the cell size: {}",
                    self.fastest_signal()
                ),
            });
        }
        Ok((dt, (viscous, conduction)))
    }
}

impl<E: Eos> Solver for IceSolver<E> {
    fn name(&self) -> &str {
        "ice"
    }

    fn time(&self) -> f64 {
        self.time
    }

    /// Δt = cfl / max over cells of Σ_d max_r (|u_r,d| + c_r)/Δx_d: the
    /// unsplit face fluxes move at most a fraction cfl of a cell's content
    /// per step, and pressure waves cross at most that fraction of a cell.
    /// With the implicit pressure c_r is left out (pressure waves are
    /// implicit) and moving walls count with their velocity.
    fn stable_dt(&self) -> Result<f64, SolverError> {
        self.stable_dt_and_diffusive_steps().map(|(dt, _)| dt)
    }

    /// Which limit of [`Solver::stable_dt`] binds: the viscous or the
    /// conduction step, the largest step allowed, a burning front, a
    /// moving wall (implicit pressure), or else the cell of largest
    /// Σ_d max_r (|u_r,d| + c_r)/Δx_d ([`IceSolver::fastest_signal`]). On
    /// several MPI ranks a collective call, as every summary is.
    fn time_step_limit(&self) -> Option<String> {
        let Ok(limits) = self.time_step_limits() else {
            return Some(format!("ICE {}", self.fastest_signal()));
        };
        let dt = limits.stable;
        let binds = |rate: f64| rate > 0.0 && self.options.cfl / rate <= dt;
        Some(match limits.binding() {
            TimeStepLimit::Viscous => format!("ICE viscous limit {:.3e} s", limits.viscous),
            TimeStepLimit::Conduction => {
                format!("ICE heat conduction limit {:.3e} s", limits.conduction)
            }
            TimeStepLimit::Convective if dt >= self.options.max_dt => {
                format!(
                    "ICE largest step allowed (max_dt {:e} s)",
                    self.options.max_dt
                )
            }
            TimeStepLimit::Convective if binds(self.surface_front_rate()) => format!(
                "ICE burning front: {:.3e} 1/s across a cell's depth",
                self.surface_front_rate()
            ),
            TimeStepLimit::Convective
                if self.options.pressure != PressureSolve::Explicit && binds(self.wall_rate()) =>
            {
                format!("ICE moving wall: Σ|w|/Δx {:.3e} 1/s", self.wall_rate())
            }
            TimeStepLimit::Convective => format!("ICE {}", self.fastest_signal()),
        })
    }

    fn advance(&mut self, dt: f64) -> Result<(), SolverError> {
        brisance_core::solver::check_step("ICE", dt)?;
        self.step_halving(dt, 0)
    }

    /// The outflow faces whose diode has held back a flow into the domain
    /// ([`crate::boundary::holds_back_inflow`]).
    ///
    /// Across ranks this is a collective call (every rank calls it).
    fn blocked_inflow(&self) -> [bool; 6] {
        if !self.ranks.several() {
            return self.blocked_inflow;
        }
        let mut any = self.blocked_inflow.map(u64::from);
        self.ranks.comm.sum(&mut any);
        any.map(|n| n > 0)
    }

    /// Totals summed exactly and rounded once ([`ExactTotals`]): the bits
    /// do not depend on the order, so they are the same for any patch
    /// split, thread count or rank count; each rank sums its own patches
    /// and the sums are merged (a collective call on several ranks).
    ///
    /// On an axisymmetric grid each cell counts with its ring's volume:
    /// mass, axial momentum (y) and energy are the whole body's; the
    /// radial momentum (x) is the sum of the rings' ρu_r V, no conserved
    /// quantity (the hoop source changes it).
    fn conservation_totals(&self) -> ConservationTotals {
        let n = self.eos.len();
        let mut sums = ExactTotals::default();
        let axisymmetric = self.options.geometry.is_axisymmetric();
        let vols = self.volumes();
        let rank = self.ranks.comm.rank();
        self.level.for_each_cell_of(
            |pid| self.ranks.owner[pid] == rank,
            |g, pid, c| {
                let d = &self.state[pid].data;
                // Axisymmetric: this cell's totals per unit volume, then
                // times its ring; Cartesian: each term straight into the
                // sums (times the common cell volume at the end).
                let mut ring = ConservationTotals::default();
                for r in 0..n {
                    if self.lagrangian[r] {
                        // Counted on the particles that carry it.
                        continue;
                    }
                    let b = r * NS;
                    let rho = d[b + RHO][c];
                    let u = [d[b + VEL][c], d[b + VEL + 1][c], d[b + VEL + 2][c]];
                    let energy =
                        rho * (d[b + ENERGY][c] + 0.5 * (u[0] * u[0] + u[1] * u[1] + u[2] * u[2]));
                    if axisymmetric {
                        ring.mass += rho;
                        for a in 0..3 {
                            ring.momentum[a] += rho * u[a];
                        }
                        ring.energy += energy;
                    } else {
                        sums.add(rho, u.map(|ua| rho * ua), energy);
                    }
                }
                // Chemical energy of the reactants, in the products'
                // reference. A reactant carried by particles is counted on
                // them.
                for rx in self
                    .reactions
                    .iter()
                    .filter(|rx| !self.lagrangian[rx.reactant])
                {
                    let chemical = d[rx.reactant * NS + RHO][c] * rx.heat_of_reaction;
                    if axisymmetric {
                        ring.energy += chemical;
                    } else {
                        sums.sums[4].add(chemical);
                    }
                }
                if axisymmetric {
                    let v = vols.column(g[0]);
                    sums.add(ring.mass * v, ring.momentum.map(|m| m * v), ring.energy * v);
                }
            },
        );
        comm::merge_exact(&*self.ranks.comm, &mut sums.sums);
        let mut t = sums.totals();
        if !axisymmetric {
            let vol: f64 = self.level.geometry.spacing.iter().product();
            t.mass *= vol;
            t.momentum = t.momentum.map(|m| m * vol);
            t.energy *= vol;
        }
        // What has left through the domain faces belongs to the total.
        let o = self.outflow_sum();
        t.mass += o.mass;
        for a in 0..3 {
            t.momentum[a] += o.momentum[a];
        }
        t.energy += o.energy;
        t
    }

    fn outflow_totals(&self) -> Option<ConservationTotals> {
        // Walls and symmetry planes book only a pressure impulse; a
        // periodic pair nothing.
        let open = self.boundaries.iter().enumerate().any(|(f, b)| {
            self.level.geometry.cells[f / 2] > 1
                && !matches!(b, IceBoundary::Symmetry | IceBoundary::Periodic)
                && !matches!(b, IceBoundary::FixedVelocity(v) if *v == [0.0; 3])
        });
        open.then(|| self.outflow_sum())
    }

    fn cell_field_names(&self) -> Vec<&'static str> {
        self.field_names()
    }

    fn cell_data(&self, fields: &[String]) -> Result<CellData, SolverError> {
        let ids = fields
            .iter()
            .map(|f| self.field_index(f))
            .collect::<Result<Vec<_>, _>>()?;
        let state = self.gathered_state();
        Ok(self
            .level
            .gather_cell_data(fields, &ids, |pid, n, id| self.derived(&state, pid, n, id)))
    }

    /// This rank's patches from its own copy, which is current for the
    /// patches it owns.
    fn cell_pieces(
        &self,
        fields: &[String],
    ) -> Result<Option<brisance_core::CellPieces>, SolverError> {
        let ids = fields
            .iter()
            .map(|f| self.field_index(f))
            .collect::<Result<Vec<_>, _>>()?;
        let rank = self.ranks.comm.rank();
        Ok(Some(self.level.cell_pieces(
            |pid| self.ranks.owner[pid] == rank,
            fields,
            &ids,
            |pid, c, id| self.derived(&self.state, pid, c, id),
        )))
    }

    fn sample(
        &self,
        point: [f64; 3],
        fields: &[String],
        out: &mut Vec<f64>,
    ) -> Result<(), SolverError> {
        let (pid, c) = self.level.locate_point(point)?;
        out.clear();
        let stored = self.ranks.owned[pid];
        for f in fields {
            let id = self.field_index(f)?;
            out.push(if stored {
                self.derived(&self.state, pid, c, id)
            } else {
                0.0
            });
        }
        // The owner's values (the other ranks do not store the patch).
        if self.ranks.several() {
            self.ranks.comm.broadcast(self.ranks.owner[pid], out);
        }
        Ok(())
    }

    fn work_per_step(&self) -> (f64, &'static str) {
        (self.level.geometry.cell_count() as f64, "cell-updates")
    }

    fn save_state(&self) -> Result<Vec<u8>, SolverError> {
        let fields = self.level.gather_fields(&self.gathered_state());
        bincode::serialize(&self.saved_state(fields))
            .map_err(|e| SolverError::Checkpoint(e.to_string()))
    }

    fn restore_state(&mut self, bytes: &[u8]) -> Result<(), SolverError> {
        let saved: SavedState = match bincode::deserialize(bytes) {
            Ok(s) => s,
            Err(e) => {
                let old: SavedStateWithoutOutflow = bincode::deserialize(bytes)
                    .map_err(|_| SolverError::Checkpoint(e.to_string()))?;
                SavedState {
                    time: old.time,
                    steps: old.steps,
                    cells: old.cells,
                    materials: old.materials,
                    fields: old.fields,
                    rescaled: old.rescaled,
                    kept_warm: old.kept_warm,
                    kept_warm_advection: old.kept_warm_advection,
                    outflow: [ConservationTotals::default(); 6],
                }
            }
        };
        let cells = self.level.geometry.cells;
        let nf = self.eos.len() * NS + 1;
        if saved.cells != cells
            || saved.materials != self.eos.len()
            || saved.fields.len() != nf
            || saved.kept_warm.len() != self.eos.len()
            || saved.kept_warm_advection.len() != self.eos.len()
            || saved
                .fields
                .iter()
                .any(|f| f.len() != cells.iter().product())
        {
            return Err(SolverError::Checkpoint(format!(
                "checkpoint of {} materials on grid {:?} does not match the scenario's {} materials on {:?}",
                saved.materials,
                saved.cells,
                self.eos.len(),
                cells
            )));
        }
        self.level.scatter_fields(&mut self.state, &saved.fields);
        self.restore_counters(&saved)
    }

    /// The shared part: the checkpoint's counters with the patch layout;
    /// a piece: the patch's interior fields.
    fn save_pieces(&self) -> Result<Option<brisance_core::StatePieces>, SolverError> {
        let encode = |bytes: bincode::Result<Vec<u8>>| {
            bytes.map_err(|e| SolverError::Checkpoint(e.to_string()))
        };
        let common = PiecesCommon {
            layout: self.level.layout,
            saved: self.saved_state(Vec::new()),
        };
        Ok(Some(brisance_core::StatePieces {
            common: encode(bincode::serialize(&common))?,
            pieces: pieces::save_interiors(
                &self.level,
                &self.state,
                &self.ranks.owner,
                self.ranks.comm.rank(),
            )?,
        }))
    }

    fn restore_pieces(
        &mut self,
        common: &[u8],
        piece: &mut dyn FnMut(usize) -> Result<Vec<u8>, String>,
    ) -> Result<(), SolverError> {
        let c: PiecesCommon =
            bincode::deserialize(common).map_err(|e| SolverError::Checkpoint(e.to_string()))?;
        let cells = self.level.geometry.cells;
        if c.saved.cells != cells
            || c.layout != self.level.layout
            || c.saved.materials != self.eos.len()
            || c.saved.kept_warm.len() != self.eos.len()
            || c.saved.kept_warm_advection.len() != self.eos.len()
        {
            return Err(SolverError::Checkpoint(format!(
                "checkpoint of {} materials on grid {:?} in {:?} patches does not match the scenario's {} materials on {:?} in {:?}: a checkpoint written per patch restarts with the same patches",
                c.saved.materials,
                c.saved.cells,
                c.layout,
                self.eos.len(),
                cells,
                self.level.layout
            )));
        }
        pieces::restore_interiors(
            &self.level,
            &mut self.state,
            &self.ranks.owner,
            self.ranks.comm.rank(),
            piece,
        )?;
        self.restore_counters(&c.saved)
    }

    /// This rank's own patches (ghosts included) and the run's counters,
    /// with no gather (the patches of other ranks are not read until
    /// their owners send them).
    fn save_snapshot(&self) -> Result<Vec<u8>, SolverError> {
        let rank = self.ranks.comm.rank();
        let snapshot = SnapshotRef {
            counters: self.saved_state(Vec::new()),
            patches: pieces::own_data(&self.state, &self.ranks.owner, rank),
        };
        bincode::serialize(&snapshot).map_err(|e| SolverError::Checkpoint(e.to_string()))
    }

    fn restore_snapshot(&mut self, bytes: &[u8]) -> Result<(), SolverError> {
        let s: Snapshot =
            bincode::deserialize(bytes).map_err(|e| SolverError::Checkpoint(e.to_string()))?;
        let counters_fit = s.counters.kept_warm.len() == self.eos.len()
            && s.counters.kept_warm_advection.len() == self.eos.len();
        if !counters_fit {
            return Err(SolverError::Checkpoint(
                "the snapshot was taken of another solver".into(),
            ));
        }
        pieces::put_own_data(
            &mut self.state,
            &self.ranks.owner,
            self.ranks.comm.rank(),
            s.patches,
        )?;
        self.restore_counters(&s.counters)
    }
}

/// The in-memory snapshot ([`Solver::save_snapshot`]): the counters of a
/// checkpoint (without its fields) and this rank's patches as it holds
/// them.
#[derive(Serialize)]
struct SnapshotRef<'a> {
    counters: SavedState,
    patches: Vec<&'a Vec<Vec<f64>>>,
}

/// The shared part of a checkpoint written per patch
/// ([`Solver::save_pieces`]): a checkpoint without its fields, and the
/// patch layout the pieces belong to.
#[derive(Serialize, Deserialize)]
struct PiecesCommon {
    layout: [usize; 3],
    saved: SavedState,
}

/// [`SnapshotRef`] read back.
#[derive(Deserialize)]
struct Snapshot {
    counters: SavedState,
    patches: Vec<Vec<Vec<f64>>>,
}

impl<E: Eos> IceSolver<E> {
    /// A checkpoint's content with the interior `fields` given.
    fn saved_state(&self, fields: Vec<Vec<f64>>) -> SavedState {
        SavedState {
            time: self.time,
            steps: self.steps,
            cells: self.level.geometry.cells,
            materials: self.eos.len(),
            fields,
            rescaled: self.rescaled,
            kept_warm: self
                .kept_warm_totals()
                .iter()
                .map(|t| (t.firings, t.energy))
                .collect(),
            kept_warm_advection: self
                .kept_warm_advection_totals()
                .iter()
                .map(|t| (t.firings, t.energy))
                .collect(),
            outflow: self.outflow,
        }
    }

    /// Puts back the time, the step count and the running totals of
    /// `saved`, then finds the reaction surfaces of the restored state.
    fn restore_counters(&mut self, saved: &SavedState) -> Result<(), SolverError> {
        self.time = saved.time;
        self.steps = saved.steps;
        self.rescaled = saved.rescaled;
        self.outflow = saved.outflow;
        for (t, &(firings, energy)) in self.kept_warm.iter_mut().zip(&saved.kept_warm) {
            *t = KeptWarmTotals { firings, energy };
        }
        for (t, &(firings, energy)) in self
            .kept_warm_advection
            .iter_mut()
            .zip(&saved.kept_warm_advection)
        {
            *t = KeptWarmTotals { firings, energy };
        }
        self.find_reaction_surfaces().map_err(SolverError::Other)
    }
}

impl<E: Eos> IceSolver<E> {
    /// One step of `dt` (steps 3–12, then step 2 of the next). With the
    /// implicit pressure a step whose solve fails (not converged, diverged,
    /// a converged face moving more than a cell's content) is taken again
    /// as two steps of Δt/2, up to [`ImplicitPressure::retries`] halvings
    /// deep, as Uintah's implicit ICE restarts a time step with a smaller
    /// Δt (docs/physics/ice/implicit_pressure.md, "Retried steps"). A
    /// failed solve leaves the state as the step found it (p_eq is put
    /// back, the face velocities and Δp are the step's scratch), so the
    /// two halves give the bits of two steps of Δt/2 taken in turn.
    fn step_halving(&mut self, dt: f64, halvings: u32) -> Result<(), SolverError> {
        let _span = tracing::trace_span!("ice_step", step = self.steps, dt).entered();
        match self.options.pressure {
            PressureSolve::Explicit => {
                self.compute_face_centred_velocities(dt);
                self.compute_pressure_increment(dt);
            }
            PressureSolve::Implicit(s) => {
                let blocked = self.blocked_inflow;
                if let Err(e) = self.compute_implicit_pressure(dt, s) {
                    if halvings >= s.retries {
                        return Err(match e {
                            SolverError::Other(m) if halvings > 0 => SolverError::Other(format!(
                                "{m} (the step of Δt = {:e} s, halved {halvings} times)",
                                dt * f64::from(1u32 << halvings)
                            )),
                            e => e,
                        });
                    }
                    // The diode flags of the failed attempt are not the
                    // step's.
                    self.blocked_inflow = blocked;
                    self.implicit.stats.halved_steps += 1;
                    let t0 = self.time;
                    self.step_halving(0.5 * dt, halvings + 1)?;
                    self.step_halving(0.5 * dt, halvings + 1)?;
                    self.time = t0 + dt;
                    return Ok(());
                }
            }
        }
        self.compute_lagrangian_values(dt)?;
        self.advect_fluids(dt)?;
        self.time += dt;
        self.steps += 1;
        self.compute_equilibration_pressure()
    }
}
