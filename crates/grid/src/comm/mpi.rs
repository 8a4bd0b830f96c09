//! The [`super::Communicator`] over MPI (the `mpi` crate on the system's Open
//! MPI), for `mpirun -np N brisance run CONFIG`.

use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::Arc;
use std::time::Instant;

use mpi::collective::SystemOperation;
use mpi::datatype::{Equivalence, PartitionMut};
use mpi::environment::Universe;
use mpi::topology::SimpleCommunicator;
use mpi::traits::*;
use mpi::Count;
use mpi::Threading;

use super::Communicator as Ranks;

/// `MPI_COMM_WORLD`. Only the thread that runs the time loop calls MPI
/// (the rayon workers never do: MPI is initialised `FUNNELED`), which is
/// why sharing the handle between threads is sound.
pub struct MpiWorld {
    world: SimpleCommunicator,
    rank: usize,
    size: usize,
    /// Nanoseconds spent in the calls of [`Ranks`] since initialisation.
    busy: AtomicU64,
}

impl MpiWorld {
    /// Runs `f`, adding its wall time to the busy time.
    fn timed<T>(&self, f: impl FnOnce() -> T) -> T {
        let t = Instant::now();
        let out = f();
        let ns = u64::try_from(t.elapsed().as_nanos()).unwrap_or(u64::MAX);
        self.busy.fetch_add(ns, Ordering::Relaxed);
        out
    }
}

// SAFETY: see the type's comment; the handle is `MPI_COMM_WORLD`, valid
// from initialisation to finalisation, and calls come from one thread.
unsafe impl Send for MpiWorld {}
// SAFETY: as above.
unsafe impl Sync for MpiWorld {}

impl std::fmt::Debug for MpiWorld {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "MpiWorld(rank {} of {})", self.rank, self.size)
    }
}

/// Keeps MPI initialised; finalises it when dropped (at the end of
/// `main`).
pub struct MpiSession {
    _universe: Universe,
    world: Arc<MpiWorld>,
}

impl MpiSession {
    /// The world communicator.
    pub fn world(&self) -> Arc<MpiWorld> {
        self.world.clone()
    }
}

/// Initialises MPI and installs its world as [`super::world`]; `None`
/// when MPI was already initialised.
pub fn init() -> Option<MpiSession> {
    let (universe, _threading) = mpi::initialize_with_threading(Threading::Funneled)?;
    let world = universe.world();
    let (rank, size) = (world.rank() as usize, world.size() as usize);
    let world = Arc::new(MpiWorld {
        world,
        rank,
        size,
        busy: AtomicU64::new(0),
    });
    // A second install cannot happen: MPI initialises once.
    let _ = super::install(world.clone());
    Some(MpiSession {
        _universe: universe,
        world,
    })
}

impl Ranks for MpiWorld {
    fn rank(&self) -> usize {
        self.rank
    }

    fn size(&self) -> usize {
        self.size
    }

    fn exchange(
        &self,
        sends: &[(usize, i32, &[f64])],
        receives: &mut [(usize, i32, &mut Vec<f64>)],
    ) {
        self.timed(|| {
            // Sends are posted without waiting, so no pair of ranks can block
            // each other; receives then take each message as it is matched.
            mpi::request::multiple_scope(sends.len(), |scope, pending| {
                for &(to, tag, values) in sends {
                    let req = self
                        .world
                        .process_at_rank(to as i32)
                        .immediate_send_with_tag(scope, values, tag);
                    pending.add(req);
                }
                for (from, tag, buf) in receives.iter_mut() {
                    let (msg, status) = self
                        .world
                        .process_at_rank(*from as i32)
                        .matched_probe_with_tag(*tag);
                    let n = status.count(f64::equivalent_datatype()) as usize;
                    buf.resize(n, 0.0);
                    msg.matched_receive_into(&mut buf[..]);
                }
                let mut done = Vec::with_capacity(sends.len());
                pending.wait_all(&mut done);
            });
        })
    }

    fn broadcast(&self, root: usize, values: &mut [f64]) {
        self.timed(|| {
            self.world
                .process_at_rank(root as i32)
                .broadcast_into(values)
        });
    }

    fn min(&self, x: f64) -> f64 {
        let mut out = x;
        self.timed(|| {
            self.world
                .all_reduce_into(&x, &mut out, SystemOperation::min())
        });
        out
    }

    fn sum(&self, values: &mut [u64]) {
        let send = values.to_vec();
        self.timed(|| {
            self.world
                .all_reduce_into(&send[..], values, SystemOperation::sum())
        });
    }

    /// Two collectives (the lengths, then `MPI_Allgatherv`), whatever the
    /// rank count.
    fn all_gather(&self, mine: &[f64]) -> Vec<Vec<f64>> {
        self.timed(|| {
            let len = mine.len() as Count;
            let mut counts: Vec<Count> = vec![0; self.size];
            self.world.all_gather_into(&len, &mut counts[..]);
            let displs: Vec<Count> = counts
                .iter()
                .scan(0, |at, &c| {
                    let d = *at;
                    *at += c;
                    Some(d)
                })
                .collect();
            let total: usize = counts.iter().map(|&c| c as usize).sum();
            let mut all = vec![0.0; total];
            {
                let mut parts = PartitionMut::new(&mut all[..], &counts[..], &displs[..]);
                self.world.all_gather_varcount_into(mine, &mut parts);
            }
            counts
                .iter()
                .zip(&displs)
                .map(|(&c, &d)| all[d as usize..(d + c) as usize].to_vec())
                .collect()
        })
    }

    fn busy_seconds(&self) -> f64 {
        self.busy.load(Ordering::Relaxed) as f64 * 1e-9
    }

    fn abort(&self, code: i32) -> ! {
        self.world.abort(code)
    }
}
