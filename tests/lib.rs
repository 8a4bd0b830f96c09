//! Workspace-level integration and validation tests (one test binary, so
//! the workspace links once). Each module is named for what it checks;
//! validation cases carry their id from docs/validation.md (`v_sod`).

mod axisymmetric;
mod cli;
mod common;
mod docs_coverage;
mod e_freeair;
mod open_faces;
mod particle_gauges;
mod restart;
mod rz_octant;
mod surface_loads;
mod v_bar;
mod v_flyer;
mod v_shock_tubes;
mod v_smooth;
mod v_sod;
mod v_sod_mpm;
mod v_taylor;
mod v_taylor_rz;
mod v_toro5;
