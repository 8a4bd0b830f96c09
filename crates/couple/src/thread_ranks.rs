//! Test support: the coupled pipelines on ranks of threads
//! ([`brisance_grid::comm::InProcess`]), each rank's communicator counting
//! the values it received, so that a test can tell a split that happened
//! from one that did nothing.

use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::Arc;

use brisance_grid::comm::{Communicator, InProcess};

/// A communicator that counts the values [`Communicator::all_gather`]
/// brings this rank from the others.
#[derive(Debug)]
struct Counting {
    inner: Arc<dyn Communicator>,
    received: Arc<AtomicU64>,
}

impl Communicator for Counting {
    fn rank(&self) -> usize {
        self.inner.rank()
    }

    fn size(&self) -> usize {
        self.inner.size()
    }

    fn exchange(
        &self,
        sends: &[(usize, i32, &[f64])],
        receives: &mut [(usize, i32, &mut Vec<f64>)],
    ) {
        self.inner.exchange(sends, receives)
    }

    fn broadcast(&self, root: usize, values: &mut [f64]) {
        self.inner.broadcast(root, values)
    }

    fn min(&self, x: f64) -> f64 {
        self.inner.min(x)
    }

    fn sum(&self, values: &mut [u64]) {
        self.inner.sum(values)
    }

    fn abort(&self, code: i32) -> ! {
        self.inner.abort(code)
    }

    fn all_gather(&self, mine: &[f64]) -> Vec<Vec<f64>> {
        let all = self.inner.all_gather(mine);
        let others: usize = all
            .iter()
            .enumerate()
            .filter(|&(r, _)| r != self.rank())
            .map(|(_, v)| v.len())
            .sum();
        self.received.fetch_add(others as u64, Ordering::Relaxed);
        all
    }
}

/// `f(comm)` on each of `ranks` threads acting as ranks (two worker
/// threads each): per rank, what `f` returned and the number of values
/// its `all_gather`s received from the other ranks.
pub fn on_thread_ranks<T: Send>(
    ranks: usize,
    f: impl Fn(Arc<dyn Communicator>) -> T + Sync,
) -> Vec<(T, u64)> {
    InProcess::run(ranks, 2, |comm| {
        let received = Arc::new(AtomicU64::new(0));
        let counting: Arc<dyn Communicator> = Arc::new(Counting {
            inner: comm,
            received: received.clone(),
        });
        let out = f(counting);
        (out, received.load(Ordering::Relaxed))
    })
}
