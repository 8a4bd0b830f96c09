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
//! - [`particle_sets`]: particle sets chosen by their initial state and
//!   followed through the run (particle gauges).
//! - [`grid_nodes`]: node fields (mass, momentum, force, velocities) on the
//!   whole level's node lattice, structure of arrays.
//! - [`transfer`]: P2G as a deterministic coloured scatter over particles
//!   binned by block, and G2P (seed 001 eqs 18–21, 24–28).
//! - [`step`]: the USF, USL and MUSL explicit steps and the particle stress
//!   update (seed 001 eqs 12–13, 22–30).
//! - [`boundary`]: grid boundary conditions per domain face.
//! - [`conduction`]: heat conduction inside the solids (Fourier's law,
//!   seed 000 eq 3), an option of the solver off by default.
//! - [`inflow`]: particle reservoirs beyond open faces, through which
//!   matter enters (an inflow buffer of particle layers).
//! - [`solver`]: [`MpmSolver`], the method behind the core `Solver` trait.
//! - [`traction`]: prescribed traction or pressure on the particles of a
//!   surface layer (seed 001 eq 20), with a time history.
//! - [`viscosity`]: the artificial bulk viscosity q of shocked particles
//!   (von Neumann–Richtmyer quadratic and Landshoff linear terms).
//! - [`anti_locking`]: the ΔF̄ volume averaging of Coombs et al. (2018)
//!   against volumetric locking (option `AntiLocking::FBar`).
//! - [`generate`]: particles from geometric shapes (box, sphere, cylinder,
//!   cylindrical shell, half-space), `ppc` per cell per direction.
//!
//! The choices the papers leave open are written down in
//! `docs/physics/mpm/shape_functions.md` and
//! `docs/physics/mpm/explicit_mpm.md`. Units are SI throughout.

pub mod anti_locking;
pub mod boundary;
pub mod conduction;
pub mod generate;
pub mod grid_nodes;
pub mod inflow;
pub mod nodes;
pub mod particle_sets;
pub mod particles;
pub mod shape;
pub mod solver;
pub mod step;
pub mod traction;
pub mod transfer;
pub mod viscosity;

pub use anti_locking::AntiLocking;
pub use boundary::GridBoundary;
pub use conduction::{HeatConduction, ThermalProperties};
pub use generate::{fill_shape, fill_shape_in, FillSpec, GenerateError, Shape};
pub use grid_nodes::{GridNodes, NodeLattice};
pub use inflow::{Reservoir, ReservoirKind, ReservoirState};
pub use nodes::patch_node_index;
pub use particle_sets::{ParticleSet, SetQuantity};
pub use particles::{
    matrix_to_voigt, voigt_to_matrix, MaterialId, ParticleError, ParticleInit, Particles,
};
pub use shape::{ShapeError, ShapeFunction, ShapeStencil, MAX_STENCIL_NODES};
pub use solver::{CoupledStep, MemoryUse, MpmOptions, MpmSetupError, MpmSolver};
pub use step::UpdateScheme;
pub use traction::{LoadHistory, SurfaceLoad, SurfaceLoadKind};
pub use viscosity::{BulkViscosity, BulkViscosityState};
