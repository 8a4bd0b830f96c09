//! The [`Solver`] implementation of [`FdmSolver`], with the checkpoint it
//! saves and restores.

use brisance_core::{
    CellData, CellPieces, ConservationTotals, SafeguardUse, Solver, SolverError, StatePieces,
};
use brisance_grid::{pieces, FaceBc};
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

use super::{FdmSolver, LimiterCount};
use crate::gas::GasLaw;
use crate::state::{specific_internal_energy, ENERGY, MOM, NVAR, RHO, SPECIES};

/// What a checkpoint holds: the interior conservative fields in global
/// order, so a restart may use another patch split or thread count.
#[derive(Serialize, Deserialize)]
struct SavedState {
    time: f64,
    steps: u64,
    cells: [usize; 3],
    fields: Vec<Vec<f64>>,
    outflow: [Vec<[f64; NVAR]>; 6],
    limiter: LimiterCount,
}

/// The shared part of a checkpoint written per patch
/// ([`Solver::save_pieces`]): a checkpoint without its fields, and the
/// patch layout the pieces belong to.
#[derive(Serialize, Deserialize)]
struct PiecesCommon {
    layout: [usize; 3],
    saved: SavedState,
}

/// `value` in bincode, for a checkpoint.
fn encode<T: Serialize>(value: &T) -> Result<Vec<u8>, SolverError> {
    bincode::serialize(value).map_err(|e| SolverError::Checkpoint(e.to_string()))
}

/// The in-memory snapshot ([`Solver::save_snapshot`]): this rank's
/// patches (ghosts included) and face accumulators as it holds them.
#[derive(Serialize)]
struct SnapshotRef<'a> {
    time: f64,
    steps: u64,
    patches: Vec<&'a Vec<Vec<f64>>>,
    outflow: &'a [Vec<[f64; NVAR]>; 6],
    limiter: LimiterCount,
}

/// [`SnapshotRef`] read back.
#[derive(Deserialize)]
struct Snapshot {
    time: f64,
    steps: u64,
    patches: Vec<Vec<Vec<f64>>>,
    outflow: [Vec<[f64; NVAR]>; 6],
    limiter: LimiterCount,
}

impl<E: GasLaw> FdmSolver<E> {
    /// The pressure and sound speed of a cell from its conserved values
    /// ρ, ρu, E and (with species) ρY, as the stable step and its limit
    /// read them.
    #[inline(always)]
    fn cell_pressure_and_sound_speed(
        &self,
        rho: f64,
        m: [f64; 3],
        energy: f64,
        rho_y: f64,
    ) -> (f64, f64) {
        let e = specific_internal_energy(rho, m[0], m[1], m[2], energy);
        let y = if E::SPECIES { rho_y / rho } else { 0.0 };
        self.eos.gas_pressure_and_sound_speed(rho, e, y)
    }
}

impl<E: GasLaw> Solver for FdmSolver<E> {
    fn name(&self) -> &str {
        "fdm"
    }

    fn time(&self) -> f64 {
        self.time
    }

    /// Δt = 2·cfl·min over cells and active directions of Δx_d/(|u_d| + c):
    /// each of the six sweeps of eq 6 advances Δt/2 at Courant number ≤ cfl.
    fn stable_dt(&self) -> Result<f64, SolverError> {
        let spacing = self.level.geometry.spacing;
        let active: [bool; 3] = std::array::from_fn(|d| self.level.is_active(d));
        // (min over cells, all cells physical); min is exact, so the
        // reduction order cannot change the result. Rows of a patch are
        // spread over the threads too, so that a single-patch grid (a 2D
        // run) does not scan its cells on one thread.
        let (min_t, all_ok) = self
            .level
            .patches
            .par_iter()
            .zip(self.fields.par_iter())
            .enumerate()
            .filter(|(id, _)| self.owns(*id))
            .map(|(_, (p, f))| {
                let d = &f.data;
                (0..p.size[1] * p.size[2])
                    .into_par_iter()
                    .with_min_len(8)
                    .map(|row_id| {
                        let (j, k) = (row_id % p.size[1], row_id / p.size[1]);
                        let mut min_t = f64::INFINITY;
                        let mut ok = true;
                        let start = p.local_index([p.ghost[0], p.ghost[1] + j, p.ghost[2] + k]);
                        let row = |f: usize| &d[f][start..start + p.size[0]];
                        let (r, mx, my, mz, en) =
                            (row(RHO), row(MOM), row(MOM + 1), row(MOM + 2), row(ENERGY));
                        let ry = if E::SPECIES { row(SPECIES) } else { &[][..] };
                        for n in 0..r.len() {
                            let rho = r[n];
                            let m = [mx[n], my[n], mz[n]];
                            let rho_y = if E::SPECIES { ry[n] } else { 0.0 };
                            let (p, c) = self.cell_pressure_and_sound_speed(rho, m, en[n], rho_y);
                            ok &= (rho > 0.0) & (p > 0.0) & (p < f64::INFINITY);
                            for ((&on, dx), mom) in active.iter().zip(spacing).zip(m) {
                                if on {
                                    min_t = min_t.min(dx / ((mom / rho).abs() + c));
                                }
                            }
                        }
                        (min_t, ok)
                    })
                    .reduce(|| (f64::INFINITY, true), |a, b| (a.0.min(b.0), a.1 & b.1))
            })
            .reduce(|| (f64::INFINITY, true), |a, b| (a.0.min(b.0), a.1 & b.1));
        // Over the ranks: the minimum is exact, and every rank learns
        // whether any cell was bad, so all stop with the same error.
        let (min_t, all_ok) = if self.comm.size() > 1 {
            let mut bad = [u64::from(!all_ok)];
            self.comm.sum(&mut bad);
            (self.comm.min(min_t), bad[0] == 0)
        } else {
            (min_t, all_ok)
        };
        if !all_ok {
            return Err(self.non_physical_error("at the start of a step"));
        }
        // A domain with no active direction has no CFL limit.
        let dt = if min_t.is_finite() {
            2.0 * self.options.cfl * min_t
        } else {
            f64::INFINITY
        };
        if !(dt >= self.options.min_dt) {
            return Err(SolverError::TimeStepCollapse {
                dt,
                min_dt: self.options.min_dt,
                time: self.time,
                detail: "the fastest signal speed has become too large for the cell size".into(),
            });
        }
        Ok(dt)
    }

    /// The cell with the smallest Δx_d/(|u_d| + c) (the first in patch
    /// and cell order among equals), with its centre and the speed's
    /// parts. On several MPI ranks a collective call (it reads every
    /// patch as its owner holds it), so every rank names the same cell.
    fn time_step_limit(&self) -> Option<String> {
        let spacing = self.level.geometry.spacing;
        let active: [bool; 3] = std::array::from_fn(|d| self.level.is_active(d));
        // (Δx/(|u|+c), global cell, axis, c, |u_d|)
        let mut best: Option<(f64, [usize; 3], usize, f64, f64)> = None;
        let fields = self.gathered();
        for (p, f) in self.level.patches.iter().zip(fields.iter()) {
            let d = &f.data;
            for k in 0..p.size[2] {
                for j in 0..p.size[1] {
                    for i in 0..p.size[0] {
                        let n = p.local_index([p.ghost[0] + i, p.ghost[1] + j, p.ghost[2] + k]);
                        let rho = d[RHO][n];
                        let m = [d[MOM][n], d[MOM + 1][n], d[MOM + 2][n]];
                        let rho_y = if E::SPECIES { d[SPECIES][n] } else { 0.0 };
                        let (_, c) =
                            self.cell_pressure_and_sound_speed(rho, m, d[ENERGY][n], rho_y);
                        for a in (0..3).filter(|&a| active[a]) {
                            let u = (m[a] / rho).abs();
                            let t = spacing[a] / (u + c);
                            if t.is_finite() && best.is_none_or(|b| t < b.0) {
                                let cell = [p.lo[0] + i, p.lo[1] + j, p.lo[2] + k];
                                best = Some((t, cell, a, c, u));
                            }
                        }
                    }
                }
            }
        }
        let (_, cell, axis, c, u) = best?;
        let x = self.level.geometry.cell_centre(cell);
        Some(format!(
            "FDM cell {cell:?} at ({:.4}, {:.4}, {:.4}) m: sound speed {c:.0} m/s + |u_{}| {u:.0} m/s",
            x[0],
            x[1],
            x[2],
            ["x", "y", "z"][axis]
        ))
    }

    /// U^{n+1} = L_z L_y L_x L_x L_y L_z U^n, each over Δt/2 (seed 001
    /// eq 6); directions with a single cell are skipped.
    fn advance(&mut self, dt: f64) -> Result<(), SolverError> {
        brisance_core::solver::check_step("FDM", dt)?;
        let _span = tracing::trace_span!("fdm_step", step = self.steps, dt).entered();
        for axis in [2, 1, 0, 0, 1, 2] {
            if self.level.is_active(axis) {
                self.sweep(axis, 0.5 * dt)?;
            }
        }
        self.time += dt;
        self.steps += 1;
        Ok(())
    }

    /// The interior's totals plus what has left through the domain faces
    /// ([`FdmSolver::outflow`]), so a flow-out or inflow face does not read
    /// as a loss: the sum is conserved to round-off. Summed in global cell
    /// order so the bits do not depend on the patch split or thread count.
    fn conservation_totals(&self) -> ConservationTotals {
        let t = self.interior_totals();
        let o = self.outflow();
        ConservationTotals {
            mass: t.mass + o.mass,
            momentum: std::array::from_fn(|d| t.momentum[d] + o.momentum[d]),
            energy: t.energy + o.energy,
        }
    }

    /// [`FdmSolver::outflow`] where a face is open; `None` between walls
    /// and periodic faces, where it is only a wall's pressure impulse and
    /// round-off.
    fn outflow_totals(&self) -> Option<ConservationTotals> {
        let open = self.bcs.faces.iter().enumerate().any(|(f, bc)| {
            self.level.is_active(f / 2)
                && matches!(
                    bc,
                    FaceBc::Outflow | FaceBc::OutflowOnly { .. } | FaceBc::Fixed(_)
                )
        });
        open.then(|| self.outflow())
    }

    /// The faces the face limiter changed ([`FdmOptions::limiter`]), for
    /// positivity and for the density bounds at a shock, when it is on.
    ///
    /// [`FdmOptions::limiter`]: crate::FdmOptions::limiter
    fn safeguards(&self) -> Vec<SafeguardUse> {
        let l = self.options.limiter;
        let count = |name, acted| SafeguardUse {
            name,
            unit: "faces",
            acted,
            checked: self.limited.faces,
        };
        let mut out = Vec::new();
        if l.positivity() {
            out.push(count("face limiter, positivity", self.limited.limited[0]));
        }
        if l.shock_bounds() {
            out.push(count(
                "face limiter, density bounds at shocks",
                self.limited.limited[1],
            ));
        }
        out
    }

    /// The outflow-only faces whose ghosts have zeroed an inward flow
    /// ([`brisance_grid::InProcessExchange::blocked_inflow`]).
    fn blocked_inflow(&self) -> [bool; 6] {
        self.exchange.blocked_inflow()
    }

    fn cell_field_names(&self) -> Vec<&'static str> {
        Self::field_names()
    }

    fn cell_data(&self, fields: &[String]) -> Result<CellData, SolverError> {
        let ids = fields
            .iter()
            .map(|f| Self::field_index(f))
            .collect::<Result<Vec<_>, _>>()?;
        let data = self.gathered();
        Ok(self
            .level
            .gather_cell_data(fields, &ids, |pid, n, id| self.derived(&data, pid, n, id)))
    }

    /// This rank's patches from its own copy, which is current for the
    /// patches it owns.
    fn cell_pieces(&self, fields: &[String]) -> Result<Option<CellPieces>, SolverError> {
        let ids = fields
            .iter()
            .map(|f| Self::field_index(f))
            .collect::<Result<Vec<_>, _>>()?;
        let rank = self.comm.rank();
        Ok(Some(self.level.cell_pieces(
            |pid| self.owner[pid] == rank,
            fields,
            &ids,
            |pid, n, id| self.derived(&self.fields, pid, n, id),
        )))
    }

    /// Values of `fields` in the cell that contains `point`; on an
    /// axisymmetric grid `point` is (r, z, ·), its third coordinate
    /// ignored.
    fn sample(
        &self,
        point: [f64; 3],
        fields: &[String],
        out: &mut Vec<f64>,
    ) -> Result<(), SolverError> {
        let mut point = point;
        if self.options.geometry.is_axisymmetric() {
            let g = &self.level.geometry;
            point[2] = g.origin[2] + 0.5 * g.spacing[2];
        }
        let (pid, n) = self.level.locate_point(point)?;
        out.clear();
        let stored = self.owns(pid);
        for f in fields {
            let id = Self::field_index(f)?;
            out.push(if stored {
                self.derived(&self.fields, pid, n, id)
            } else {
                0.0
            });
        }
        // The owner's values (the other ranks do not store the patch).
        if self.comm.size() > 1 {
            self.comm.broadcast(self.owner[pid], out);
        }
        Ok(())
    }

    fn work_per_step(&self) -> (f64, &'static str) {
        (self.level.geometry.cell_count() as f64, "cell-updates")
    }

    fn save_state(&self) -> Result<Vec<u8>, SolverError> {
        let fields = self.level.gather_fields(&self.gathered());
        let saved = SavedState {
            time: self.time,
            steps: self.steps,
            cells: self.level.geometry.cells,
            fields,
            outflow: self.gathered_outflow().into_owned(),
            limiter: self.limited,
        };
        bincode::serialize(&saved).map_err(|e| SolverError::Checkpoint(e.to_string()))
    }

    /// This rank's own patches and accumulators, with no gather (the
    /// patches of other ranks are not read until their owners send them).
    fn save_snapshot(&self) -> Result<Vec<u8>, SolverError> {
        let rank = self.comm.rank();
        let snapshot = SnapshotRef {
            time: self.time,
            steps: self.steps,
            patches: pieces::own_data(&self.fields, &self.owner, rank),
            outflow: &self.outflow,
            limiter: self.limited,
        };
        bincode::serialize(&snapshot).map_err(|e| SolverError::Checkpoint(e.to_string()))
    }

    fn restore_snapshot(&mut self, bytes: &[u8]) -> Result<(), SolverError> {
        let s: Snapshot =
            bincode::deserialize(bytes).map_err(|e| SolverError::Checkpoint(e.to_string()))?;
        let outflow_fits = s
            .outflow
            .iter()
            .zip(&self.outflow)
            .all(|(a, b)| a.len() == b.len());
        if !outflow_fits {
            return Err(SolverError::Checkpoint(
                "the snapshot was taken of another solver".into(),
            ));
        }
        pieces::put_own_data(&mut self.fields, &self.owner, self.comm.rank(), s.patches)?;
        self.outflow = s.outflow;
        self.limited = s.limiter;
        self.time = s.time;
        self.steps = s.steps;
        Ok(())
    }

    /// The shared part: the checkpoint's counters and face accumulators
    /// (gathered: one value set per face cell) with the patch layout;
    /// a piece: the patch's interior fields.
    fn save_pieces(&self) -> Result<Option<StatePieces>, SolverError> {
        let common = PiecesCommon {
            layout: self.level.layout,
            saved: SavedState {
                time: self.time,
                steps: self.steps,
                cells: self.level.geometry.cells,
                fields: Vec::new(),
                outflow: self.gathered_outflow().into_owned(),
                limiter: self.limited,
            },
        };
        Ok(Some(StatePieces {
            common: encode(&common)?,
            pieces: pieces::save_interiors(
                &self.level,
                &self.fields,
                &self.owner,
                self.comm.rank(),
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
        if c.saved.cells != cells || c.layout != self.level.layout {
            return Err(SolverError::Checkpoint(format!(
                "checkpoint of grid {:?} in {:?} patches does not match the scenario's {:?} in {:?}: a checkpoint written per patch restarts with the same patches",
                c.saved.cells, c.layout, cells, self.level.layout
            )));
        }
        if c.saved
            .outflow
            .iter()
            .zip(&self.outflow)
            .any(|(a, b)| a.len() != b.len())
        {
            return Err(SolverError::Checkpoint(
                "checkpoint face accumulators do not match the grid".into(),
            ));
        }
        pieces::restore_interiors(
            &self.level,
            &mut self.fields,
            &self.owner,
            self.comm.rank(),
            piece,
        )?;
        self.outflow = c.saved.outflow;
        self.limited = c.saved.limiter;
        self.time = c.saved.time;
        self.steps = c.saved.steps;
        Ok(())
    }

    fn restore_state(&mut self, bytes: &[u8]) -> Result<(), SolverError> {
        let saved: SavedState =
            bincode::deserialize(bytes).map_err(|e| SolverError::Checkpoint(e.to_string()))?;
        let cells = self.level.geometry.cells;
        if saved.cells != cells
            || saved.fields.len() != Self::NFIELDS
            || saved
                .outflow
                .iter()
                .zip(&self.outflow)
                .any(|(a, b)| a.len() != b.len())
            || saved
                .fields
                .iter()
                .any(|f| f.len() != cells.iter().product())
        {
            return Err(SolverError::Checkpoint(format!(
                "checkpoint grid {:?} does not match the scenario's {:?}",
                saved.cells, cells
            )));
        }
        self.level.scatter_fields(&mut self.fields, &saved.fields);
        self.outflow = saved.outflow;
        self.limited = saved.limiter;
        self.time = saved.time;
        self.steps = saved.steps;
        Ok(())
    }
}
