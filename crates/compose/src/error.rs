//! Errors of loading, validating and running a scenario.

use std::fmt;

/// A problem with the configuration, located in its file when possible.
#[derive(Debug, Clone, PartialEq)]
pub struct ConfigError {
    /// The file (or `<built-in default>`, `--set`).
    pub file: String,
    /// 1-based line and column, when known.
    pub position: Option<(usize, usize)>,
    /// The field path (`domain.cells`), when known.
    pub field: Option<String>,
    /// What is wrong and what was expected.
    pub message: String,
}

impl fmt::Display for ConfigError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}", self.file)?;
        if let Some((line, col)) = self.position {
            write!(f, ":{line}:{col}")?;
        }
        write!(f, ": ")?;
        if let Some(field) = &self.field {
            write!(f, "`{field}`: ")?;
        }
        write!(f, "{}", self.message)
    }
}

impl std::error::Error for ConfigError {}

/// Why a run stopped early.
#[derive(Debug, thiserror::Error)]
pub enum RunError {
    /// The configuration is invalid.
    #[error(transparent)]
    Config(#[from] ConfigError),
    /// An output could not be written.
    #[error(transparent)]
    Io(#[from] brisance_io::IoError),
    /// The solver stopped (non-physical state, collapsed time step, ...).
    #[error("run stopped at step {step}: {source}")]
    Solver {
        /// Steps completed.
        step: u64,
        /// The solver's diagnostic.
        source: brisance_core::SolverError,
    },
    /// A checkpoint cannot be used.
    #[error("{0}")]
    Checkpoint(String),
    /// The run was asked to stop (SIGINT, SIGTERM) and stopped after a
    /// whole step, with a checkpoint of it.
    #[error("interrupted at step {step}, t = {time:e} s; checkpoint {}", checkpoint.display())]
    Interrupted {
        /// Steps completed.
        step: u64,
        /// Simulation time reached, s.
        time: f64,
        /// The checkpoint written at that step.
        checkpoint: std::path::PathBuf,
    },
}
