//! The ICE's parallel passes over one patch: rows of cells (runs along x)
//! shared among rayon's threads, each cell or face written by one task
//! only, so that the bits do not depend on the thread count
//! (docs/physics/ice/performance.md).

use super::*;

/// Calls `f(n)` for the storage index of every interior cell of `p`.
#[inline]
pub(super) fn for_interior(p: &Patch, mut f: impl FnMut(usize)) {
    let g = p.ghost;
    for k in g[2]..g[2] + p.size[2] {
        for j in g[1]..g[1] + p.size[1] {
            let base = p.local_index([g[0], j, k]);
            for i in 0..p.size[0] {
                f(base + i);
            }
        }
    }
}

/// A field array of one patch that the cells of a parallel pass read and
/// write through, each storage index from one task only (the pass's own
/// cell or face), so that one patch's cells can run on several threads.
#[derive(Clone, Copy)]
pub(super) struct Disjoint<'a> {
    ptr: *mut f64,
    len: usize,
    _array: std::marker::PhantomData<&'a mut [f64]>,
}

// SAFETY: a `Disjoint` is only handed to the tasks of one pass, which
// touch disjoint indices (see `read` and `write`), while the array's
// mutable borrow `'a` keeps every other access out.
unsafe impl Send for Disjoint<'_> {}
unsafe impl Sync for Disjoint<'_> {}

impl<'a> Disjoint<'a> {
    pub(super) fn new(v: &'a mut [f64]) -> Self {
        Self {
            ptr: v.as_mut_ptr(),
            len: v.len(),
            _array: std::marker::PhantomData,
        }
    }

    /// A stand-in for unused slots of fixed-size arrays (length 0).
    pub(super) fn empty() -> Self {
        Self {
            ptr: std::ptr::NonNull::dangling().as_ptr(),
            len: 0,
            _array: std::marker::PhantomData,
        }
    }

    /// The value at `i`. Only the task that owns index `i` in the pass
    /// may call it, or any task when no task writes `i` in the pass.
    #[inline]
    pub(super) fn read(self, i: usize) -> f64 {
        assert!(i < self.len);
        // SAFETY: in bounds; no other task writes index i during the pass.
        unsafe { *self.ptr.add(i) }
    }

    /// Writes `x` at `i`; only the task that owns index `i` in the pass.
    #[inline]
    pub(super) fn write(self, i: usize, x: f64) {
        assert!(i < self.len);
        // SAFETY: in bounds; index i belongs to this task alone.
        unsafe { *self.ptr.add(i) = x }
    }

    /// The values at `start..start + len`, to read: bounds checked once
    /// for the run. No task may write them during the pass.
    #[inline]
    pub(super) fn slice(self, start: usize, len: usize) -> &'a [f64] {
        assert!(start <= self.len && len <= self.len - start);
        // SAFETY: in bounds; nothing writes these indices during the pass.
        unsafe { std::slice::from_raw_parts(self.ptr.add(start), len) }
    }

    /// The values at `start..start + len`, to write: only the task that
    /// owns all of these indices in the pass, which reads and writes them
    /// through this slice alone.
    #[inline]
    pub(super) fn slice_mut(self, start: usize, len: usize) -> &'a mut [f64] {
        assert!(start <= self.len && len <= self.len - start);
        // SAFETY: in bounds; the indices belong to this task alone.
        unsafe { std::slice::from_raw_parts_mut(self.ptr.add(start), len) }
    }
}

/// Rows of cells (runs along x) handed to one rayon task at least: a row
/// of a 2D (r, z) grid is 40–200 cells of a few microseconds each, so a
/// task of a few rows outweighs the scheduling.
pub(super) const ROWS_PER_TASK: usize = 2;

/// The rows (j, k) with `lo[d] ≤ j, k < hi[d]` (d = 1, 2), as the index of
/// a row, k outer, on rayon's threads. Rows, not k-planes, are what the
/// threads share: a 2D grid is one k-plane, and the (r, z) cases run on
/// such grids.
pub(super) fn par_row_range(
    lo: [usize; 3],
    hi: [usize; 3],
) -> impl IndexedParallelIterator<Item = (usize, usize)> {
    let nj = hi[1] - lo[1];
    let rows = nj * (hi[2] - lo[2]);
    (0..rows)
        .into_par_iter()
        .with_min_len(ROWS_PER_TASK)
        .map(move |r| (lo[1] + r % nj, lo[2] + r / nj))
}

/// The storage indices of the cells `lo[0] ≤ i < hi0` of row (j, k) of
/// `p`, in order, passed to `f`.
#[inline]
pub(super) fn for_row(
    p: &Patch,
    j: usize,
    k: usize,
    lo0: usize,
    hi0: usize,
    mut f: impl FnMut(usize),
) {
    let base = p.local_index([lo0, j, k]);
    for i in 0..hi0 - lo0 {
        f(base + i);
    }
}

/// [`for_interior`] with the rows of the patch on rayon's threads;
/// `fold` accumulates each row's result from `init()`, and `combine`
/// joins them in the rows' order (it must not depend on how the rows are
/// grouped, e.g. a max, a sum of integers, [`first_failure`] or an
/// in-order concatenation, for the bits to be the same on any number of
/// threads).
pub(super) fn par_interior<A: Send>(
    p: &Patch,
    init: impl Fn() -> A + Sync + Send,
    fold: impl Fn(&mut A, usize) + Sync + Send,
    combine: impl Fn(A, A) -> A + Sync + Send,
) -> A {
    let g = p.ghost;
    let hi = [g[0] + p.size[0], g[1] + p.size[1], g[2] + p.size[2]];
    // Each task joins its own rows as it goes; the tasks' results are then
    // joined once, in order, here. A reduction up rayon's join tree would
    // copy a concatenated list once per level of the tree (log₂ of the
    // rows), which cost 5 % of an (r, z) ICE–MPM step in the kept-warm
    // and rescale lists of step 2.
    let parts: Vec<Option<A>> = par_row_range(g, hi)
        .fold(
            || None,
            |acc: Option<A>, (j, k)| {
                let mut row = init();
                for_row(p, j, k, g[0], hi[0], |c| fold(&mut row, c));
                Some(match acc {
                    None => row,
                    Some(a) => combine(a, row),
                })
            },
        )
        .collect();
    parts
        .into_iter()
        .flatten()
        .reduce(combine)
        .unwrap_or_else(init)
}

/// The interior rows (runs of cells along x) of `p` as `f(storage index
/// of the row's first cell, row length)`, rows on rayon's threads, so
/// that a pass can work on contiguous slices with one bounds check per row.
pub(super) fn par_rows(p: &Patch, f: impl Fn(usize, usize) + Sync + Send) {
    let g = p.ghost;
    let hi = [g[0] + p.size[0], g[1] + p.size[1], g[2] + p.size[2]];
    par_row_range(g, hi).for_each(|(j, k)| f(p.local_index([g[0], j, k]), p.size[0]));
}

/// [`par_interior`] without a result.
pub(super) fn par_cells(p: &Patch, f: impl Fn(usize) + Sync + Send) {
    par_interior(p, || (), |_, c| f(c), |_, _| ());
}

/// Every face whose low side bounds an interior cell along `axis` (the
/// interior cells plus the first ghost cell on the high side) as its
/// high-side storage index, rows on rayon's threads.
pub(super) fn par_faces(p: &Patch, axis: usize, f: impl Fn(usize) + Sync + Send) {
    let g = p.ghost;
    let mut hi = [g[0] + p.size[0], g[1] + p.size[1], g[2] + p.size[2]];
    hi[axis] += 1;
    par_row_range(g, hi).for_each(|(j, k)| for_row(p, j, k, g[0], hi[0], &f));
}

/// Calls `f(global linear cell index, patch data, local index)` for every
/// interior cell of `fields`, patches in parallel; a patch this rank does
/// not store (another rank's, [`PatchFields::is_stored`]) is skipped.
pub(super) fn for_each_cell_global(
    level: &Level,
    fields: &mut [PatchFields],
    f: impl Fn(usize, &mut [Vec<f64>], usize) + Sync,
) {
    let geometry = level.geometry;
    fields
        .par_iter_mut()
        .zip(level.patches.par_iter())
        .filter(|(pf, _)| pf.is_stored())
        .for_each(|(pf, patch)| {
            for_interior(patch, |c| {
                f(geometry.linear_index(global_of(patch, c)), &mut pf.data, c);
            })
        });
}

/// Fills `out` (one entry per cell, global order, x fastest) with
/// `f(patch id, local index)`, rows of cells in parallel: each entry
/// depends on its own cell only, so the bits do not depend on the thread
/// count. The owning patch is looked up once per run of a row inside one
/// patch (the local index then steps by one along x), not once per cell.
pub(super) fn par_gather<T: Send>(
    level: &Level,
    out: &mut [T],
    f: impl Fn(usize, usize) -> T + Sync,
) {
    let n = level.geometry.cells;
    out.par_chunks_mut(n[0])
        .with_min_len((1024 / n[0]).max(1))
        .enumerate()
        .for_each(|(row, o)| {
            let (j, k) = (row % n[1], row / n[1]);
            let mut i = 0;
            while i < n[0] {
                let (pid, c) = level
                    .locate([i, j, k])
                    .expect("every cell of the domain has a patch");
                let p = &level.patches[pid];
                let end = p.lo[0] + p.size[0];
                for (m, o) in o[i..end].iter_mut().enumerate() {
                    *o = f(pid, c + m);
                }
                i = end;
            }
        });
}
