//! Brisance composer: turns a RON scenario into a running pipeline.
//!
//! - [`config`]: the serde schema of a scenario.
//! - [`ron_path`]: dotted-path lookup in RON text (`--set`, error positions).
//! - [`load`]: read → override → parse → validate, errors at file:line:col.
//! - [`validate`]: the checks serde cannot express.
//! - [`registry`]: every named component with a one-line description.
//! - [`plugins`]: the one place model crates register (equations of state
//!   such as `NobleAbel`, reaction models such as `ThermalDecomposition`,
//!   constitutive models such as `SteinbergGuinan`).
//! - [`library`]: the named materials of `configs/materials/`.
//! - [`build`]: assembling the solver for a pipeline: every pipeline's
//!   section, checks and builder are its crate's (`Fdm`: `brisance_fdm`;
//!   `Ice`: `brisance_ice`; `Mpm`, `IceMpm` and `FdmMpmBridge`:
//!   `brisance_couple`; `Lattice`: `brisance_lattice`; `Peridynamics`:
//!   `brisance_pd`), called through `brisance_scene::PipelineSpec` with
//!   the [`scene`] of the scenario.
//! - [`run`](mod@run): the run loop, outputs, checkpoints and restart.

#[cfg(test)]
mod bridge;
pub mod build;
pub mod config;
pub mod error;
#[cfg(test)]
mod ice;
#[cfg(test)]
mod ice_mpm;
#[cfg(test)]
mod lattice;
pub mod library;
pub mod load;
#[cfg(test)]
mod peridynamics;
pub mod plugins;
pub mod registry;
pub mod ron_path;
pub mod run;
pub mod scene;
pub mod validate;

#[cfg(test)]
mod contract_tests;

pub use config::Scenario;
pub use error::{ConfigError, RunError};
pub use load::{load_file, load_str, LoadedScenario, DEFAULT_SCENARIO};
pub use run::{run, run_until_stopped, RunOptions};
