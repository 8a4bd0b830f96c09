//! What the E-PLATE and E-SLAB reports (`plate_cases.rs`,
//! `slab_cases.rs`) share beyond the cases themselves, which live in
//! `brisance::verification::{bridge_blast, plate, slab}`: the splice of a
//! section's rows into docs/validation.md after each case; what a run of
//! some cases keeps of the others is `crate::kept`.

use std::path::Path;

use anyhow::{Context, Result};

use crate::Report;

/// Writes `section`'s rows for the runs so far into docs/validation.md
/// under `root` at once, so that a later case that does not finish does
/// not lose them.
pub(crate) fn splice_now(
    root: &Path,
    section: impl FnOnce(&mut Report) -> Result<()>,
) -> Result<()> {
    let mut partial = Report {
        md: String::new(),
        failures: Vec::new(),
    };
    section(&mut partial)?;
    let path = crate::splice::report_path(root);
    let existing = std::fs::read_to_string(&path).unwrap_or_default();
    std::fs::write(&path, crate::splice::splice(&existing, &partial.md, ""))
        .with_context(|| format!("cannot write {}", path.display()))
}
