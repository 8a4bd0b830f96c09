//! Brisance validation: exact solutions the validation suite compares
//! against, written from the physics, the empirical Kingery–Bulmash blast
//! fits it compares free-air bursts with, Mott's fragmentation of shells
//! (E-PD-FRAG), and the case drivers the
//! integration tests and `cargo xtask validate` share (the root package
//! re-exports the crate as `brisance::verification`).

pub mod blast;
pub mod cases;
pub mod flyer;
pub mod kingery_bulmash;
pub mod mott;
pub mod open_faces;
pub mod pd_cylinder;
pub mod pd_fragmentation;
pub mod pd_tube;
pub mod riemann;
pub mod ring;
pub mod rz_octant;
pub mod shock_tubes;
pub mod smooth;
pub mod taylor;
