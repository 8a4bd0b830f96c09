//! Tensor aliases used by the constitutive and particle code.

/// A 3-vector of `f64` (position, velocity, force).
pub type Vec3 = nalgebra::Vector3<f64>;
/// A 3×3 matrix of `f64` (stress, velocity gradient, deformation gradient).
pub type Mat3 = nalgebra::Matrix3<f64>;
