//! Brisance couple: the coupled finite-difference / material-point method
//! (CFDMP) of seed 001 §3 and the detonation remap of seed 001 §4.1.
//!
//! - [`remap`](mod@remap): a 1D (planar, cylindrical, spherical) detonation profile
//!   mapped onto a 1D/2D/3D FDM grid as its initial state, conserving the
//!   charge's mass, energy, products mass and radial momentum to round-off.
//! - [`regions`]: the FDM region, the MPM region and the bridge region of
//!   their overlap (seed 001 §3.1).
//! - [`bridge`]: the exchanges across the bridge, one function per
//!   equation group: fictitious FDM cells from the MPM grid (eqs 31–36),
//!   FDM cells on the MPM interface nodes (eqs 37–39), and the transport of
//!   mass, momentum and energy by created and absorbed particles
//!   (eqs 40–51).
//! - [`ice_mpm`]: the ICE–MPM step of seed 000 §3.3 — Eulerian fluids and
//!   Lagrangian solids on one grid, one equilibration pressure, momentum
//!   and heat exchange in every cell.
//! - [`mpm_pipeline`]: the `Mpm` pipeline's section, checks and builder
//!   (`brisance_scene::PipelineSpec`), whose particles the coupled
//!   pipelines build too ([`mpm_pipeline::mpm_parts`]); the `IceMpm`
//!   pipeline's are [`ice_mpm::pipeline`], the `FdmMpmBridge` pipeline's
//!   [`bridge_pipeline`].
//!
//! Choices the paper leaves open are written down in
//! `docs/physics/couple/remap.md` and `docs/physics/couple/bridge.md`.

pub mod bridge;
pub mod bridge_pipeline;
pub mod cfdmp;
pub mod gas_remap;
pub mod ice_mpm;
pub mod mpm_pipeline;
pub mod regions;
pub mod remap;

pub use bridge_pipeline::{BridgeConfig, BridgeSolver};
pub use cfdmp::{Cfdmp, CfdmpOptions, TransportTotals, FIELDS as CFDMP_FIELDS};
pub use gas_remap::{cached_remap, remap_cache_dir, GasRemap, MpmRemapConfig};
pub use ice_mpm::pipeline::{IceMpmConfig, Solids};
pub use ice_mpm::{IceMpm, IceMpmError, ParticleHeat};
pub use mpm_pipeline::{BulkViscosityConfig, MpmConfig, SurfaceLoadConfig};
pub use regions::{BridgeRegions, RegionBox, RegionError, Side};
pub use remap::{
    remap, Charge, RadialProfile, RemapError, RemapReport, RemapTarget, RemapTotals, Remapped,
};

#[cfg(test)]
mod scenario_text;
#[cfg(test)]
mod thread_ranks;
