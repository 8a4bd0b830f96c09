//! A rank's own patches in the states the solvers save without a gather:
//! the run loop's in-memory snapshot ([`own_data`], [`put_own_data`]) and
//! the per-patch checkpoint pieces ([`save_interiors`],
//! [`restore_interiors`]). `owner[p]` is the rank that owns patch `p`.

use brisance_core::SolverError;

use crate::{Level, PatchFields};

/// The patches `owner` gives to `rank`, in patch order.
pub fn own_patches(owner: &[usize], rank: usize) -> impl Iterator<Item = usize> + '_ {
    (0..owner.len()).filter(move |&p| owner[p] == rank)
}

/// The data of `rank`'s patches as it holds them (ghosts included), in
/// patch order: a snapshot's patches.
pub fn own_data<'a>(
    fields: &'a [PatchFields],
    owner: &[usize],
    rank: usize,
) -> Vec<&'a Vec<Vec<f64>>> {
    own_patches(owner, rank).map(|p| &fields[p].data).collect()
}

/// Puts back what [`own_data`] gave, or, leaving `fields` as they are,
/// refuses data of other patches or sizes.
pub fn put_own_data(
    fields: &mut [PatchFields],
    owner: &[usize],
    rank: usize,
    data: Vec<Vec<Vec<f64>>>,
) -> Result<(), SolverError> {
    let own: Vec<usize> = own_patches(owner, rank).collect();
    let fits = data.len() == own.len()
        && own.iter().zip(&data).all(|(&p, d)| {
            d.len() == fields[p].data.len()
                && d.iter()
                    .zip(&fields[p].data)
                    .all(|(a, b)| a.len() == b.len())
        });
    if !fits {
        return Err(SolverError::Checkpoint(
            "the snapshot was taken of another solver".into(),
        ));
    }
    for (p, d) in own.into_iter().zip(data) {
        fields[p].data = d;
    }
    Ok(())
}

/// A checkpoint piece for each of `rank`'s patches: `(patch, its
/// interior fields x fastest in bincode)` ([`Level::patch_interior`]).
pub fn save_interiors(
    level: &Level,
    fields: &[PatchFields],
    owner: &[usize],
    rank: usize,
) -> Result<Vec<(usize, Vec<u8>)>, SolverError> {
    own_patches(owner, rank)
        .map(|p| {
            bincode::serialize(&level.patch_interior(p, &fields[p]))
                .map(|bytes| (p, bytes))
                .map_err(|e| SolverError::Checkpoint(e.to_string()))
        })
        .collect()
}

/// Reads the piece of each of `rank`'s patches with `piece(patch)` and
/// puts its interior fields back ([`Level::set_patch_interior`]).
pub fn restore_interiors(
    level: &Level,
    fields: &mut [PatchFields],
    owner: &[usize],
    rank: usize,
    piece: &mut dyn FnMut(usize) -> Result<Vec<u8>, String>,
) -> Result<(), SolverError> {
    for p in own_patches(owner, rank) {
        let bytes = piece(p).map_err(SolverError::Checkpoint)?;
        let interior: Vec<Vec<f64>> = bincode::deserialize(&bytes)
            .map_err(|e| SolverError::Checkpoint(format!("patch {p}: {e}")))?;
        level
            .set_patch_interior(p, &mut fields[p], &interior)
            .map_err(SolverError::Checkpoint)?;
    }
    Ok(())
}
