//! Ranks as threads of one process: a [`Communicator`] that needs no MPI
//! library, so that the rank logic of a solver (what it splits, what it
//! sends, how it combines) can be tested by `cargo test` on any machine,
//! against the same solver on one rank. The collectives meet at a barrier;
//! the point-to-point messages go through a shared mailbox, in the order
//! sent per (from, to, tag), as MPI delivers them.
//!
//! Each rank's thread needs a rayon pool of its own, as each MPI process
//! has: a rank that waits at a collective inside a rayon task holds its
//! worker, and ranks sharing one pool could wait there for a worker none
//! of them gives back. [`InProcess::run`] sets that up.

use super::Communicator;
use std::sync::{Arc, Barrier, Condvar, Mutex, MutexGuard, PoisonError};

/// A message in flight: from, to, tag, values.
type Message = (usize, usize, i32, Vec<f64>);

/// What the threads of one in-process world share.
#[derive(Debug)]
struct Shared {
    size: usize,
    barrier: Barrier,
    /// One slot per rank for the collectives.
    values: Mutex<Vec<Vec<f64>>>,
    integers: Mutex<Vec<Vec<u64>>>,
    /// Messages in flight, in the order sent.
    mailbox: Mutex<Vec<Message>>,
    arrived: Condvar,
}

/// One rank of a world of threads ([`InProcess::world`]).
#[derive(Debug, Clone)]
pub struct InProcess {
    rank: usize,
    shared: Arc<Shared>,
}

/// The lock, also after a rank's thread panicked (the test then fails on
/// that panic, not on the poison).
fn lock<T>(m: &Mutex<T>) -> MutexGuard<'_, T> {
    m.lock().unwrap_or_else(PoisonError::into_inner)
}

impl InProcess {
    /// The `size` ranks of one world, rank r at index r: give each to its
    /// own thread, and have every thread call the collectives in the same
    /// order, as MPI ranks do.
    pub fn world(size: usize) -> Vec<Arc<dyn Communicator>> {
        let size = size.max(1);
        let shared = Arc::new(Shared {
            size,
            barrier: Barrier::new(size),
            values: Mutex::new(vec![Vec::new(); size]),
            integers: Mutex::new(vec![Vec::new(); size]),
            mailbox: Mutex::new(Vec::new()),
            arrived: Condvar::new(),
        });
        (0..size)
            .map(|rank| {
                Arc::new(InProcess {
                    rank,
                    shared: shared.clone(),
                }) as Arc<dyn Communicator>
            })
            .collect()
    }

    /// Runs `f` on every rank of a world of `size` threads, each thread
    /// with a rayon pool of its own of `threads` workers (see the module
    /// doc); the results in rank order. A rank's panic is passed on.
    pub fn run<T: Send>(
        size: usize,
        threads: usize,
        f: impl Fn(Arc<dyn Communicator>) -> T + Sync,
    ) -> Vec<T> {
        let world = Self::world(size);
        std::thread::scope(|scope| {
            let handles: Vec<_> = world
                .into_iter()
                .map(|comm| {
                    let f = &f;
                    scope.spawn(move || {
                        rayon::ThreadPoolBuilder::new()
                            .num_threads(threads)
                            .build()
                            .expect("a thread pool for the rank")
                            .install(|| f(comm))
                    })
                })
                .collect();
            handles
                .into_iter()
                .map(|h| h.join().unwrap_or_else(|e| std::panic::resume_unwind(e)))
                .collect()
        })
    }

    /// Puts `mine` in this rank's slot, waits for every rank, and returns
    /// what `read` makes of all slots; the slots stay valid until every
    /// rank has read them.
    fn collect<T>(&self, mine: Vec<f64>, read: impl FnOnce(&[Vec<f64>]) -> T) -> T {
        lock(&self.shared.values)[self.rank] = mine;
        self.shared.barrier.wait();
        let out = read(&lock(&self.shared.values));
        self.shared.barrier.wait();
        out
    }
}

impl Communicator for InProcess {
    fn rank(&self) -> usize {
        self.rank
    }

    fn size(&self) -> usize {
        self.shared.size
    }

    fn exchange(
        &self,
        sends: &[(usize, i32, &[f64])],
        receives: &mut [(usize, i32, &mut Vec<f64>)],
    ) {
        {
            let mut mail = lock(&self.shared.mailbox);
            for &(to, tag, values) in sends {
                mail.push((self.rank, to, tag, values.to_vec()));
            }
        }
        self.shared.arrived.notify_all();
        for (from, tag, buffer) in receives.iter_mut() {
            let mut mail = lock(&self.shared.mailbox);
            loop {
                let found = mail
                    .iter()
                    .position(|m| m.0 == *from && m.1 == self.rank && m.2 == *tag);
                if let Some(k) = found {
                    **buffer = mail.remove(k).3;
                    break;
                }
                mail = self
                    .shared
                    .arrived
                    .wait(mail)
                    .unwrap_or_else(PoisonError::into_inner);
            }
        }
    }

    fn broadcast(&self, root: usize, values: &mut [f64]) {
        let mine = if self.rank == root {
            values.to_vec()
        } else {
            Vec::new()
        };
        self.collect(mine, |all| {
            if self.rank != root {
                values.copy_from_slice(&all[root]);
            }
        });
    }

    fn min(&self, x: f64) -> f64 {
        self.collect(vec![x], |all| {
            all.iter().map(|v| v[0]).fold(f64::INFINITY, f64::min)
        })
    }

    fn sum(&self, values: &mut [u64]) {
        lock(&self.shared.integers)[self.rank] = values.to_vec();
        self.shared.barrier.wait();
        {
            let all = lock(&self.shared.integers);
            for (k, v) in values.iter_mut().enumerate() {
                *v = all.iter().map(|r| r[k]).fold(0u64, u64::wrapping_add);
            }
        }
        self.shared.barrier.wait();
    }

    fn abort(&self, code: i32) -> ! {
        std::process::exit(code)
    }

    fn all_gather(&self, mine: &[f64]) -> Vec<Vec<f64>> {
        self.collect(mine.to_vec(), <[Vec<f64>]>::to_vec)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn collectives_give_every_rank_the_same_answer() {
        let out = InProcess::run(3, 1, |c| {
            let r = c.rank() as f64;
            let mut b = [r, r];
            c.broadcast(1, &mut b);
            let mut s = [c.rank() as u64 + 1, 10];
            c.sum(&mut s);
            let gathered = c.all_gather(&vec![r; c.rank()]);
            (b, c.min(5.0 - r), s, gathered)
        });
        for (b, m, s, g) in out {
            assert_eq!(b, [1.0, 1.0]);
            assert_eq!(m, 3.0);
            assert_eq!(s, [6, 30]);
            assert_eq!(g, vec![vec![], vec![1.0], vec![2.0, 2.0]]);
        }
    }

    #[test]
    fn messages_arrive_in_the_order_sent() {
        let out = InProcess::run(2, 1, |c| {
            let other = 1 - c.rank();
            let me = c.rank() as f64;
            let (a, b) = ([me, 1.0], [me, 2.0]);
            let (mut x, mut y) = (Vec::new(), Vec::new());
            c.exchange(
                &[(other, 7, &a), (other, 7, &b)],
                &mut [(other, 7, &mut x), (other, 7, &mut y)],
            );
            (x, y)
        });
        assert_eq!(out[0], (vec![1.0, 1.0], vec![1.0, 2.0]));
        assert_eq!(out[1], (vec![0.0, 1.0], vec![0.0, 2.0]));
    }
}
