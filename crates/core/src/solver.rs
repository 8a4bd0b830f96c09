//! The solver trait: what the run loop drives.

use std::path::Path;

use crate::{
    CellData, CellPieces, ConservationTotals, NodeData, ParticleData, SafeguardUse, SetQuantity,
    SolverError,
};

/// A solver as the run loop drives it, boxed: any [`Solver`], a box of
/// one, or a box of a method's own trait object over [`Solver`] that
/// hands itself over (the FDM–MPM bridge's). What a pipeline's build
/// makes implements it.
pub trait IntoSolver {
    /// The solver, boxed.
    fn into_solver(self) -> Box<dyn Solver>;
}

impl<S: Solver + 'static> IntoSolver for S {
    fn into_solver(self) -> Box<dyn Solver> {
        Box::new(self)
    }
}

impl IntoSolver for Box<dyn Solver> {
    fn into_solver(self) -> Box<dyn Solver> {
        self
    }
}

/// A checkpoint's state split per patch ([`Solver::save_pieces`]).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct StatePieces {
    /// What every rank shares: written once.
    pub common: Vec<u8>,
    /// `(patch id, bytes)` of each patch this rank owns, in patch order.
    pub pieces: Vec<(usize, Vec<u8>)>,
}

/// A numerical method, or a coupled pipeline of methods, that owns its state
/// and advances it in time.
///
/// # Contract
/// - [`Solver::stable_dt`] is the largest step the method takes safely from
///   the current state; the run loop may take a smaller one (to land on an
///   output time exactly) but never a larger one.
/// - [`Solver::advance`] either advances the whole state by `dt` or returns
///   an error and leaves the last good state for output.
/// - Results are deterministic: the same input gives the same bits whatever
///   the thread count or patch split, and
///   [`Solver::restore_state`] of a [`Solver::save_state`] continues
///   bit-identically.
pub trait Solver: Send {
    /// Short name of the method (`fdm`, `mpm`, `ice-mpm`, ...).
    fn name(&self) -> &str;

    /// Current simulation time, s.
    fn time(&self) -> f64;

    /// Largest stable step from the current state, s.
    fn stable_dt(&self) -> Result<f64, SolverError>;

    /// Advances the state by `dt`.
    fn advance(&mut self, dt: f64) -> Result<(), SolverError>;

    /// Totals of mass, momentum and total energy in the domain. A solver
    /// with open boundaries adds what has left through them, so that they
    /// do not read as a loss: the FDM its face fluxes, the MPM the
    /// particles that left its grid (the ICE solver does not yet).
    fn conservation_totals(&self) -> ConservationTotals;

    /// Names of the cell fields this solver can output.
    fn cell_field_names(&self) -> Vec<&'static str>;

    /// The requested cell fields on the whole grid (unknown names are an
    /// error naming the known ones).
    fn cell_data(&self, fields: &[String]) -> Result<CellData, SolverError>;

    /// The requested cell fields as one piece per patch, each rank
    /// holding the pieces of its own patches and nothing gathered (the
    /// `Patches` VTK layout); `None` for methods whose cells are not split
    /// into patches (the default). A call on one rank of several is not
    /// collective: it reads this rank's patches only.
    fn cell_pieces(&self, fields: &[String]) -> Result<Option<CellPieces>, SolverError> {
        let _ = fields;
        Ok(None)
    }

    /// This rank's state as it holds it, for the run loop's in-memory
    /// snapshot that rewinds a failed step: the bytes go back into the
    /// same solver on the same rank ([`Solver::restore_snapshot`]), so
    /// unlike [`Solver::save_state`] nothing needs gathering from other
    /// ranks. The default is [`Solver::save_state`].
    fn save_snapshot(&self) -> Result<Vec<u8>, SolverError> {
        self.save_state()
    }

    /// Puts back a state saved by [`Solver::save_snapshot`] on this rank
    /// of this run. The default is [`Solver::restore_state`].
    fn restore_snapshot(&mut self, bytes: &[u8]) -> Result<(), SolverError> {
        self.restore_state(bytes)
    }

    /// The state for a checkpoint written per patch: a part every rank
    /// shares (time, step count, running totals) and one part per patch
    /// this rank owns, nothing gathered but what is small; `None` for
    /// methods whose cells are not split into patches (the default). A
    /// collective call on several ranks.
    fn save_pieces(&self) -> Result<Option<StatePieces>, SolverError> {
        Ok(None)
    }

    /// Puts back a state saved by [`Solver::save_pieces`] with the same
    /// patches, on any rank count: `common` is the shared part, and
    /// `piece(patch)` reads the part of a patch, which this rank calls
    /// for the patches it owns.
    fn restore_pieces(
        &mut self,
        common: &[u8],
        piece: &mut dyn FnMut(usize) -> Result<Vec<u8>, String>,
    ) -> Result<(), SolverError> {
        let _ = (common, piece);
        Err(SolverError::Checkpoint(format!(
            "the {} solver does not read checkpoints written per patch",
            self.name()
        )))
    }

    /// Values of `fields` at `point` (the containing cell's value for
    /// cell-centred methods), written into `out`.
    fn sample(
        &self,
        point: [f64; 3],
        fields: &[String],
        out: &mut Vec<f64>,
    ) -> Result<(), SolverError>;

    /// Samples particle gauge `k` of the run (`outputs.particle_gauges`,
    /// in order): the set averages of `quantities` over the gauge's
    /// particles, their columns ([`SetQuantity::columns`]) in order, into
    /// `out`. False when the solver holds no such gauge: methods without
    /// particles (the default), or `k` past the gauges the run was built
    /// with.
    fn sample_particle_gauge(
        &self,
        _k: usize,
        _quantities: &[SetQuantity],
        _out: &mut Vec<f64>,
    ) -> bool {
        false
    }

    /// Every particle (or node) with its state, for methods that carry
    /// them; `None` for purely Eulerian methods.
    fn particle_data(&self) -> Option<ParticleData> {
        None
    }

    /// Names of the background-grid node fields this solver can output;
    /// empty for methods without a node grid (the default).
    fn node_field_names(&self) -> Vec<&'static str> {
        Vec::new()
    }

    /// The requested node fields on the whole node lattice (unknown names
    /// are an error naming the known ones); `None` for methods without a
    /// node grid (the default).
    fn node_data(&self, fields: &[String]) -> Result<Option<NodeData>, SolverError> {
        let _ = fields;
        Ok(None)
    }

    /// Work done on the domain by prescribed external forces (surface
    /// tractions, body forces) since the start, J, so that
    /// E(t) − W_ext(t) stays at E(0); `None` for methods that apply no such
    /// forces (the default).
    fn external_work(&self) -> Option<f64> {
        None
    }

    /// What has left through the open boundaries since the start (a part
    /// of [`Solver::conservation_totals`]), for the run summary; `None`
    /// (the default) for a solver that does not book it or has no open
    /// boundary.
    fn outflow_totals(&self) -> Option<ConservationTotals> {
        None
    }

    /// How often each of the method's safeguards acted since the start (the
    /// FDM's positivity limiter, for instance), for the run summary; empty
    /// (the default) for a method without one.
    fn safeguards(&self) -> Vec<SafeguardUse> {
        Vec::new()
    }

    /// The domain faces (x_low, x_high, y_low, y_high, z_low, z_high) where
    /// a one-way open face (one that lets matter out but not in) has held
    /// back a flow pointing into the domain since the start, so that the
    /// run loop can warn that the face acted as a wall there. All `false`
    /// (the default) for a method without such faces.
    fn blocked_inflow(&self) -> [bool; 6] {
        [false; 6]
    }

    /// What sets [`Solver::stable_dt`] in the current state, in words,
    /// for the run summary: the particle or cell whose signal speed binds
    /// (with where it is and the speed's parts), or the limit that does.
    /// Computed on demand, once a run, outside the step; `None` (the
    /// default) for a method that does not say.
    fn time_step_limit(&self) -> Option<String> {
        None
    }

    /// Wall-clock seconds spent so far in each named part of a method made
    /// of several (the FDM and the MPM of a bridge, for instance), for the
    /// run summary; empty (the default) for a method with one part.
    fn wall_split(&self) -> Vec<(&'static str, f64)> {
        Vec::new()
    }

    /// Writes the method's own output files (those that are neither cell
    /// fields, particles nor gauges: fragment tables, for instance) into the
    /// run's output directory `out_dir`, for field output number `index`.
    /// Called by the run loop at every output time; the default writes
    /// nothing.
    fn write_output_files(&self, out_dir: &Path, index: usize) -> Result<(), SolverError> {
        let _ = (out_dir, index);
        Ok(())
    }

    /// End-of-run hook: called once by the run loop after the last output
    /// of a run that reached its end (or its step limit), to write the
    /// method's final products into `out_dir`. The default does nothing.
    fn finish(&mut self, out_dir: &Path) -> Result<(), SolverError> {
        let _ = out_dir;
        Ok(())
    }

    /// Work done by one step, in the kernel's unit, for throughput figures.
    fn work_per_step(&self) -> (f64, &'static str);

    /// Serialises the full state for a checkpoint.
    fn save_state(&self) -> Result<Vec<u8>, SolverError>;

    /// Restores a state written by [`Solver::save_state`].
    fn restore_state(&mut self, bytes: &[u8]) -> Result<(), SolverError>;
}

/// Refuses a step that is not positive and finite, before anything moves
/// (the [`Solver::advance`] contract: a refused step leaves the state as
/// it was); `method` names the solver in the error.
pub fn check_step(method: &str, dt: f64) -> Result<(), SolverError> {
    if dt > 0.0 && dt.is_finite() {
        Ok(())
    } else {
        Err(SolverError::Other(format!(
            "{method}: time step {dt} s must be positive and finite"
        )))
    }
}

/// Advances `s` to `t_end` at its stable step, the last step shortened to
/// land on it, calling `after_step(s, dt)` after each step; stops at the
/// first error of either.
pub fn step_to<S: Solver + ?Sized>(
    s: &mut S,
    t_end: f64,
    mut after_step: impl FnMut(&mut S, f64) -> Result<(), SolverError>,
) -> Result<(), SolverError> {
    while s.time() < t_end * (1.0 - 1e-12) {
        let dt = s.stable_dt()?.min(t_end - s.time());
        s.advance(dt)?;
        after_step(s, dt)?;
    }
    Ok(())
}
