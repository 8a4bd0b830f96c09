//! Brisance peridynamics (in progress).
