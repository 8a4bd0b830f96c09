//! Brisance output writers: everything a run puts on disk.
//!
//! - [`atomic`]: crash-safe file replacement ([`write_atomic`]) and
//!   output-directory checks ([`ensure_dir`], [`check_writable_dir`]).
//! - [`vti`]: VTK XML ImageData snapshots of cell fields ([`write_vti`])
//!   and of grid node fields ([`write_vti_nodes`]); cell fields as one
//!   piece per patch ([`write_vti_piece`]) under a `.pvti` master
//!   ([`write_pvti`]).
//! - [`pvd`]: ParaView collections tying snapshots to times ([`PvdSeries`]).
//! - [`csv`]: gauge, line-out and conservation tables, and a reader.
//! - [`summary`]: the end-of-run JSON summary ([`RunSummary`]).
//! - [`checkpoint`]: restart files ([`Checkpoint`]).
//! - [`number`]: exact, compact text for `f64` values ([`format_f64`]).
//! - [`error`]: the shared error type [`IoError`], whose messages always
//!   name the file involved.
//!
//! - [`vtu`]: particle sets as VTK UnstructuredGrid vertices (`.vtu`).
//!
//! Every file is written through [`write_atomic`], so an interrupted run
//! never leaves a half-written output file behind.

pub mod atomic;
pub mod checkpoint;
pub mod csv;
pub mod error;
pub mod number;
pub mod pvd;
pub mod summary;
pub mod vti;
pub mod vtu;

pub use atomic::{check_writable_dir, ensure_dir, write_atomic};
pub use checkpoint::{
    checkpoint_file_name, checkpoint_piece_file_name, checkpoint_pieces_dir_name, read_checkpoint,
    read_checkpoint_piece, write_checkpoint, write_checkpoint_piece, Checkpoint,
    CHECKPOINT_FORMAT_VERSION, CHECKPOINT_MAGIC, PIECE_MAGIC,
};
pub use csv::{
    read_csv, write_conservation_csv, write_conservation_csv_with_work, write_gauge_csv,
    write_lineout_csv,
};
pub use error::IoError;
pub use number::format_f64;
pub use pvd::PvdSeries;
pub use summary::{
    read_summary, relative_change, write_summary, RunSummary, Safeguard, TimeStepSummary, WallPart,
};
pub use vti::{pvti_text, write_pvti, write_vti, write_vti_nodes, write_vti_piece};
pub use vtu::write_vtu;
