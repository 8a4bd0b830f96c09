//! Exact solutions the validation suite compares against, written from the physics.

pub mod cases;
pub mod open_faces;
pub mod riemann;
pub mod smooth;
pub mod taylor;
