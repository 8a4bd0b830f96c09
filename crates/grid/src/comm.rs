//! Ranks: the processes a run is spread over, and what they say to each
//! other.
//!
//! A level's patches are shared out among the ranks ([`owner_of`]): a rank
//! owns whole patches and updates only those; ghost layers that border
//! another rank's patch arrive as messages holding the very buffers the
//! in-process exchange packs ([`crate::InProcessExchange`]). Everything a
//! result depends on is either computed by one rank and sent as is, or
//! reduced with an operation whose result does not depend on the order
//! (minimum, integer sums, logical and), so a run on N ranks gives the
//! bits of a run on one.
//!
//! Without the cargo feature `mpi` there is one rank ([`Serial`]); with it
//! the program installs an MPI communicator ([`install`]) before it builds
//! a solver, and solvers pick it up with [`world`]. [`InProcess`] makes
//! ranks of threads, to test a solver's rank logic without MPI.

use std::sync::{Arc, OnceLock};

mod in_process;
#[cfg(feature = "mpi")]
pub mod mpi;

pub use in_process::InProcess;

/// The collective and point-to-point operations the solvers need. Every
/// rank calls the collectives (all but [`Communicator::exchange`]'s
/// matching pairs) in the same order.
pub trait Communicator: Send + Sync + std::fmt::Debug {
    /// This process's rank, from 0.
    fn rank(&self) -> usize;

    /// Number of ranks.
    fn size(&self) -> usize;

    /// Sends every `(to rank, tag, values)` of `sends` and receives every
    /// `(from rank, tag, buffer)` of `receives` (the buffer takes the
    /// message's length); returns when all have completed. Messages
    /// between two ranks with one tag arrive in the order sent.
    fn exchange(
        &self,
        sends: &[(usize, i32, &[f64])],
        receives: &mut [(usize, i32, &mut Vec<f64>)],
    );

    /// Copies `values` of rank `root` into `values` of every rank.
    fn broadcast(&self, root: usize, values: &mut [f64]);

    /// The minimum of `x` over the ranks (exact, so order-independent).
    fn min(&self, x: f64) -> f64;

    /// Sums each entry of `values` over the ranks (integers: exact).
    fn sum(&self, values: &mut [u64]);

    /// Ends every rank at once with status `code` (after an error that
    /// only this rank has seen, so that no rank waits for it forever).
    fn abort(&self, code: i32) -> !;

    /// Wall seconds this rank has spent inside the calls above since the
    /// start (waiting for the other ranks included): what the ranks cost
    /// a run. 0 for [`Serial`].
    fn busy_seconds(&self) -> f64 {
        0.0
    }

    /// Every rank's `mine`, in rank order, on every rank (the lists may
    /// differ in length). Values are copied, not combined, so the result
    /// is the same bits on every rank. This default is made of
    /// [`Communicator::broadcast`] (each rank's length, then its values:
    /// 2 × ranks collectives); the MPI world makes it two.
    fn all_gather(&self, mine: &[f64]) -> Vec<Vec<f64>> {
        (0..self.size())
            .map(|root| {
                let mut len = [mine.len() as f64];
                self.broadcast(root, &mut len);
                let mut values = if root == self.rank() {
                    mine.to_vec()
                } else {
                    vec![0.0; len[0] as usize]
                };
                self.broadcast(root, &mut values);
                values
            })
            .collect()
    }
}

/// One rank: every operation is the identity.
#[derive(Debug, Default, Clone, Copy)]
pub struct Serial;

impl Communicator for Serial {
    fn rank(&self) -> usize {
        0
    }

    fn size(&self) -> usize {
        1
    }

    fn exchange(
        &self,
        sends: &[(usize, i32, &[f64])],
        receives: &mut [(usize, i32, &mut Vec<f64>)],
    ) {
        assert!(
            sends.is_empty() && receives.is_empty(),
            "a single rank has nobody to exchange with"
        );
    }

    fn broadcast(&self, _root: usize, _values: &mut [f64]) {}

    fn min(&self, x: f64) -> f64 {
        x
    }

    fn sum(&self, _values: &mut [u64]) {}

    fn abort(&self, code: i32) -> ! {
        std::process::exit(code)
    }
}

static WORLD: OnceLock<Arc<dyn Communicator>> = OnceLock::new();

/// Makes `comm` the communicator [`world`] returns; fails (giving it back)
/// when one is already installed.
pub fn install(comm: Arc<dyn Communicator>) -> Result<(), Arc<dyn Communicator>> {
    WORLD.set(comm)
}

/// The ranks of this run: the installed communicator, or [`Serial`].
pub fn world() -> Arc<dyn Communicator> {
    WORLD.get().cloned().unwrap_or_else(|| Arc::new(Serial))
}

/// `items` shared among `ranks` in contiguous runs, the first
/// `items mod ranks` ranks taking one more: the first item of each rank,
/// then `items` (ranks + 1 entries; a rank may get none when there are
/// fewer items than ranks). The split [`owner_of`] makes of patches.
pub fn equal_runs(items: usize, ranks: usize) -> Vec<usize> {
    let ranks = ranks.max(1);
    let (base, extra) = (items / ranks, items % ranks);
    let mut starts = Vec::with_capacity(ranks + 1);
    starts.push(0);
    for r in 0..ranks {
        starts.push(starts[r] + base + usize::from(r < extra));
    }
    starts
}

/// The rank that owns patch `patch` of `patches` shared among `ranks`:
/// contiguous runs of patch ids (x fastest in the layout), the first
/// `patches % ranks` ranks taking one patch more, so neighbouring patches
/// tend to share a rank and the load differs by at most one patch.
pub fn owner_of(patch: usize, patches: usize, ranks: usize) -> usize {
    let (base, extra) = (patches / ranks, patches % ranks);
    // Ranks below `extra` own base + 1 patches each.
    let big = extra * (base + 1);
    if patch < big {
        patch / (base + 1)
    } else {
        extra + (patch - big) / base
    }
}

/// Every patch's fields as its owner holds them: `fields` itself on one
/// rank; on several, a copy whose patch `p` comes from rank `owner[p]`
/// (a collective call: every rank makes it, and each holds a copy of the
/// whole state while the result lives). What outputs, totals and
/// checkpoints read, so that they sum and write in the order and with the
/// bits of one rank.
pub fn owners_fields<'a>(
    comm: &dyn Communicator,
    owner: &[usize],
    fields: &'a [crate::PatchFields],
) -> std::borrow::Cow<'a, [crate::PatchFields]> {
    if comm.size() == 1 {
        return std::borrow::Cow::Borrowed(fields);
    }
    let mut all = fields.to_vec();
    for (f, &o) in all.iter_mut().zip(owner) {
        // A patch this rank does not store gets arrays to receive into.
        let n: usize = f.dims.iter().product();
        for values in &mut f.data {
            values.resize(n, 0.0);
            comm.broadcast(o, values);
        }
    }
    std::borrow::Cow::Owned(all)
}

/// Merges every rank's `sums` into each rank's (one collective over
/// [`brisance_core::ExactSum::WORDS`] words per sum), so that every rank
/// holds the exact sum of what all ranks added: a total each rank sums
/// over its own cells comes out with the bits of one rank summing them
/// all. Nothing is sent on one rank.
pub fn merge_exact(comm: &dyn Communicator, sums: &mut [brisance_core::ExactSum]) {
    if comm.size() == 1 || sums.is_empty() {
        return;
    }
    let mut words: Vec<u64> = sums.iter().flat_map(|s| s.to_words()).collect();
    comm.sum(&mut words);
    for (s, w) in sums
        .iter_mut()
        .zip(words.chunks_exact(brisance_core::ExactSum::WORDS))
    {
        *s = brisance_core::ExactSum::new();
        s.add_words(w);
    }
}

/// The owner of every patch of a level of `patches` patches on `ranks`
/// ranks, or why the split cannot be made.
pub fn patch_owners(patches: usize, ranks: usize) -> Result<Vec<usize>, String> {
    if patches < ranks {
        return Err(format!(
            "{ranks} ranks for {patches} patches: a rank owns whole patches, so split the domain into at least {ranks} patches (domain.patches)"
        ));
    }
    Ok((0..patches).map(|p| owner_of(p, patches, ranks)).collect())
}

/// Items (nodes) shared among the ranks in contiguous runs, every rank
/// holding every item: rank r owns `starts[r]..starts[r + 1]`, works out
/// what costs per bond or spring for its own items and copies the results
/// to every rank ([`NodeRuns::exchange`], [`NodeRuns::received`]), so the
/// per-item passes that follow run on every rank over the same values.
/// What peridynamics and the lattice spread over ranks with.
#[derive(Debug, Clone)]
pub struct NodeRuns {
    comm: Arc<dyn Communicator>,
    /// First item of each rank, then the item count (ranks + 1 entries).
    starts: Vec<usize>,
}

impl NodeRuns {
    /// One rank owning all `items`.
    pub fn serial(items: usize) -> Self {
        Self {
            comm: Arc::new(Serial),
            starts: vec![0, items],
        }
    }

    /// The ranks of `comm` owning the runs that begin at `starts` (one
    /// entry per rank, then the item count).
    pub fn new(comm: Arc<dyn Communicator>, starts: Vec<usize>) -> Self {
        debug_assert_eq!(starts.len(), comm.size() + 1);
        Self { comm, starts }
    }

    /// The communicator.
    pub fn comm(&self) -> &dyn Communicator {
        &*self.comm
    }

    /// Whether the items are spread over more than one rank.
    pub fn several(&self) -> bool {
        self.comm.size() > 1
    }

    /// The items this rank owns.
    pub fn nodes(&self) -> std::ops::Range<usize> {
        self.nodes_of(self.comm.rank())
    }

    /// The items rank `r` owns.
    pub fn nodes_of(&self, r: usize) -> std::ops::Range<usize> {
        self.starts[r]..self.starts[r + 1]
    }

    /// The largest `x` over the ranks (exact in any order).
    pub fn max(&self, x: f64) -> f64 {
        if self.several() {
            -self.comm.min(-x)
        } else {
            x
        }
    }

    /// Sums `values` over the ranks (integers: exact in any order).
    pub fn sum(&self, values: &mut [u64]) {
        if self.several() {
            self.comm.sum(values);
        }
    }

    /// Every rank's `width` values per owned item, as `pack` writes them
    /// (item by item, in order), on every rank: `None` on one rank or
    /// when `width` is 0. A collective call on several ranks. Store what
    /// arrived with [`NodeRuns::received`].
    pub fn exchange(
        &self,
        width: usize,
        pack: impl Fn(usize, &mut Vec<f64>),
    ) -> Option<Vec<Vec<f64>>> {
        if !self.several() || width == 0 {
            return None;
        }
        let own = self.nodes();
        let mut buf = Vec::with_capacity(width * own.len());
        for i in own {
            pack(i, &mut buf);
        }
        debug_assert_eq!(buf.len(), width * self.nodes().len());
        Some(self.comm.all_gather(&buf))
    }

    /// The other ranks' items and the part each sent, from an all-gather
    /// over these ranks.
    pub fn others<'a>(
        &'a self,
        all: &'a [Vec<f64>],
    ) -> impl Iterator<Item = (std::ops::Range<usize>, &'a [f64])> + 'a {
        let me = self.comm.rank();
        all.iter()
            .enumerate()
            .filter(move |&(r, _)| r != me)
            .map(move |(r, part)| (self.nodes_of(r), part.as_slice()))
    }

    /// The other ranks' items and their `width` values from an
    /// [`NodeRuns::exchange`].
    pub fn received<'a>(
        &'a self,
        all: &'a [Vec<f64>],
        width: usize,
    ) -> impl Iterator<Item = (usize, &'a [f64])> + 'a {
        self.others(all)
            .flat_map(move |(nodes, part)| nodes.zip(part.chunks_exact(width)))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn one_rank_owns_every_node_and_exchanges_nothing() {
        let runs = NodeRuns::serial(5);
        assert!(!runs.several());
        assert_eq!(runs.nodes(), 0..5);
        assert_eq!(runs.max(2.5), 2.5);
        let mut v = [3, 4];
        runs.sum(&mut v);
        assert_eq!(v, [3, 4]);
        assert!(runs
            .exchange(2, |i, buf| buf.extend([i as f64; 2]))
            .is_none());
        // What arrived from the others: none but this rank's own part.
        let all = vec![vec![1.0, 2.0]];
        assert_eq!(runs.received(&all, 2).count(), 0);
    }

    #[test]
    fn equal_runs_are_the_runs_of_owner_of() {
        assert_eq!(equal_runs(10, 4), vec![0, 3, 6, 8, 10]);
        assert_eq!(equal_runs(2, 4), vec![0, 1, 2, 2, 2]);
        assert_eq!(equal_runs(0, 2), vec![0, 0, 0]);
        for (items, ranks) in [(8, 2), (8, 3), (7, 4), (4, 4), (5, 1), (13, 5)] {
            let starts = equal_runs(items, ranks);
            for i in 0..items {
                let r = owner_of(i, items, ranks);
                assert!(
                    (starts[r]..starts[r + 1]).contains(&i),
                    "{i} of {items} on {ranks}"
                );
            }
        }
    }

    #[test]
    fn patches_are_shared_in_contiguous_runs_differing_by_at_most_one() {
        for (patches, ranks) in [(8, 2), (8, 3), (7, 4), (4, 4), (5, 1)] {
            let owners = patch_owners(patches, ranks).unwrap();
            assert!(owners.windows(2).all(|w| w[1] == w[0] || w[1] == w[0] + 1));
            assert_eq!(owners[0], 0);
            assert_eq!(*owners.last().unwrap(), ranks - 1);
            let counts: Vec<usize> = (0..ranks)
                .map(|r| owners.iter().filter(|&&o| o == r).count())
                .collect();
            let (lo, hi) = (counts.iter().min().unwrap(), counts.iter().max().unwrap());
            assert!(hi - lo <= 1, "{patches} patches on {ranks}: {counts:?}");
        }
        assert!(patch_owners(2, 4)
            .unwrap_err()
            .contains("at least 4 patches"));
    }
}
