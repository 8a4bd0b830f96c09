//! Brisance grid: the Cartesian mesh every Eulerian solver and the MPM
//! background grid live on.
//!
//! - [`level`]: a box of cells (1D, 2D or 3D by cell counts of 1 in unused
//!   directions) split into patches with ghost layers.
//! - [`fields`]: cell-centred and node-centred fields, structure of arrays,
//!   one allocation per field per patch.
//! - [`boundary`]: boundary conditions per domain face.
//! - [`halo`]: the halo-exchange interface and its in-process implementation.
//! - [`comm`]: the ranks a run is spread over and what they exchange
//!   (one rank unless built with the cargo feature `mpi`).
//! - [`shape`]: geometric shapes for initial regions and particle filling.
//!
//! Every kernel works on one patch plus its ghost layers; patches are
//! independent between exchanges, which is what makes results independent of
//! the patch split and thread count.

pub mod boundary;
pub mod comm;
pub mod fields;
pub mod halo;
pub mod level;
pub mod pieces;
pub mod shape;

pub use boundary::{BoundaryConditions, Face, FaceBc};
pub use fields::{FieldKind, FieldSet, NodeLayout, PatchFields};
pub use halo::{close_inward_flow, HaloExchange, InProcessExchange, BLOCKED_FLOW_FRACTION};
pub use level::{CellOrder, GridError, Level, Patch};
pub use shape::{Shape, ShapeError};
