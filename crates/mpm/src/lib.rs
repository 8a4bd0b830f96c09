//! Brisance MPM: the material point method of seed 001 §2.2 (eqs 10–30) and
//! seed 000 §3.2 (eqs 11–17), as the solid phase of the coupled methods.
//!
//! - [`nodes`]: global node indexing of the background grid and its map to
//!   a patch's node storage.
//! - [`shape`]: shape functions N_I(x_p) and their gradients — linear
//!   hexahedral (seed 001 eq 16), uGIMP (seed 000 ref 13, Bardenhagen &
//!   Kober 2004) and the quadratic B-spline — evaluated into fixed-size
//!   stencils without allocation.
//! - [`particles`]: the particle state, structure of arrays, with a stable
//!   counting sort by cell.
//! - [`generate`]: particles from geometric shapes (box, sphere, cylinder,
//!   cylindrical shell, half-space), `ppc` per cell per direction.
//!
//! The choices the papers leave open are written down in
//! `docs/physics/mpm/shape_functions.md`. Units are SI throughout.

pub mod generate;
pub mod nodes;
pub mod particles;
pub mod shape;

pub use generate::{fill_shape, FillSpec, GenerateError, Shape};
pub use nodes::patch_node_index;
pub use particles::{
    matrix_to_voigt, voigt_to_matrix, MaterialId, ParticleError, ParticleInit, Particles,
};
pub use shape::{ShapeError, ShapeFunction, ShapeStencil, MAX_STENCIL_NODES};
