//! Error types shared by the physics crates.

/// A failure inside an equation of state (an inversion that has no solution
/// in the valid range, a state outside the model's domain).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum EosError {
    /// The requested state lies outside the region where the model is valid.
    #[error("{eos}: state outside the valid range: {detail}")]
    OutOfRange {
        /// Name of the equation of state.
        eos: &'static str,
        /// What was out of range, with values.
        detail: String,
    },
    /// An iterative inversion did not converge.
    #[error(
        "{eos}: inversion did not converge after {iterations} iterations (residual {residual:e})"
    )]
    NoConvergence {
        /// Name of the equation of state.
        eos: &'static str,
        /// Iterations spent.
        iterations: usize,
        /// Final residual.
        residual: f64,
    },
}

/// Why a solver refused to go on. Every variant carries enough to locate the
/// problem; the run loop stops, keeps the last good output and prints it.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SolverError {
    /// Non-physical state (negative density or pressure, NaN) in a cell.
    #[error("non-physical state at t = {time:e} s in cell ({}, {}, {}) (centre {:?} m): {detail}", cell[0], cell[1], cell[2], centre)]
    NonPhysicalState {
        /// Simulation time of the failed step.
        time: f64,
        /// Global cell index (i, j, k).
        cell: [usize; 3],
        /// Cell centre.
        centre: [f64; 3],
        /// The offending state, spelled out.
        detail: String,
    },
    /// The stable time step fell below the allowed minimum.
    #[error("time step collapsed to {dt:e} s at t = {time:e} s (minimum {min_dt:e} s): {detail}")]
    TimeStepCollapse {
        /// The step that was computed.
        dt: f64,
        /// The floor it fell below.
        min_dt: f64,
        /// Simulation time.
        time: f64,
        /// Where the limiting cell/particle is.
        detail: String,
    },
    /// A checkpoint does not match this solver.
    #[error("checkpoint mismatch: {0}")]
    Checkpoint(String),
    /// Anything else that must stop the run.
    #[error("{0}")]
    Other(String),
}
