//! A lattice run spread over MPI ranks (docs/cluster.md).
//!
//! Every rank holds every node. A rank owns a slab of the box: whole
//! planes along its slowest axis (rows in 2D, z planes in 3D, single nodes
//! in 1D), as many as the ranks share evenly. It evaluates, for its own
//! nodes only, the passes that cost per spring: the bond forces and their
//! gather (with the explicit Euler update), the commit of the spring state
//! and the volume and energy update. The bond pass also runs over the
//! nodes next to the slab whose springs reach into it (their forces are
//! gathered by the slab's nodes: one plane below, and one above where a
//! diagonal runs down), so no spring force crosses between ranks. What each pass wrote for the slab is then copied to every rank,
//! and the passes that cost one operation per node — the kicks and drift
//! of velocity Verlet, the node masses of the chemistry, the surface
//! regression, the stable step, totals and outputs — run on every rank
//! over every node, on the same values, giving the bits of one rank.

use crate::model::MsdmLattice;
use brisance_core::SolverError;
use brisance_grid::comm::{equal_runs, Communicator, NodeRuns};
use std::ops::Range;
use std::sync::Arc;

/// The first node of each of `ranks` ranks, then `planes · plane` (the
/// node count): contiguous runs of whole planes of `plane` nodes, the
/// first `planes mod ranks` ranks taking one plane more. An error when
/// there are fewer planes than ranks.
pub fn slab_starts(planes: usize, plane: usize, ranks: usize) -> Result<Vec<usize>, String> {
    if ranks == 0 || planes < ranks {
        return Err(format!(
            "{ranks} ranks for a lattice of {planes} nodes along its slowest axis: every rank needs at least one plane of nodes; run on fewer ranks"
        ));
    }
    Ok(equal_runs(planes, ranks)
        .into_iter()
        .map(|p| p * plane)
        .collect())
}

impl MsdmLattice {
    /// Spreads the nodes over the ranks of `comm` (nothing to do on one
    /// rank): from now on this rank evaluates the spring passes of its
    /// slab (`slab_starts`: whole planes, as even as they divide) and
    /// receives the others'. Every rank builds the same lattice and calls
    /// this last. The implicit integrators' assembly and linear solve over
    /// every node run on every rank on the same values (every rank holds
    /// every node), their force, commit and volume passes in slabs.
    pub fn distribute(&mut self, comm: Arc<dyn Communicator>) -> Result<(), SolverError> {
        if comm.size() == 1 {
            return Ok(());
        }
        let n = self.geom.n;
        let (planes, plane) = match self.geom.dim.count() {
            1 => (n[0], 1),
            2 => (n[1], n[0]),
            _ => (n[2], n[0] * n[1]),
        };
        let starts = slab_starts(planes, plane, comm.size()).map_err(SolverError::Other)?;
        self.ranks = NodeRuns::new(comm, starts);
        Ok(())
    }

    /// The nodes this rank owns (all of them on one rank).
    pub fn owned_nodes(&self) -> Range<usize> {
        self.ranks.nodes()
    }

    /// The nodes whose bond forces this rank evaluates: its own and those
    /// whose bonds its nodes gather (node i gathers the bonds of
    /// i − offset along every direction; an offset may be negative, a
    /// diagonal going down one row and across).
    pub(crate) fn bond_nodes(&self) -> Range<usize> {
        let own = self.ranks.nodes();
        let offsets = self.geom.directions.iter().map(|d| d.offset);
        let below = offsets.clone().max().unwrap_or(0).max(0).unsigned_abs();
        let above = offsets.min().unwrap_or(0).min(0).unsigned_abs();
        own.start.saturating_sub(below)..(own.end + above).min(self.len())
    }

    /// Copies the net forces of every rank's nodes to every rank, and with
    /// `moved` their positions and velocities too (the explicit Euler
    /// update of the gather pass).
    pub(crate) fn share_forces(&mut self, moved: bool) {
        let width = if moved { 9 } else { 3 };
        let (f, x, u) = (&self.force, &self.x, &self.u);
        let Some(all) = self.ranks.exchange(width, |i, buf| {
            buf.extend((0..3).map(|a| f[a][i]));
            if moved {
                buf.extend((0..3).map(|a| x[a][i]));
                buf.extend((0..3).map(|a| u[a][i]));
            }
        }) else {
            return;
        };
        for (i, v) in self.ranks.received(&all, width) {
            for a in 0..3 {
                self.force[a][i] = v[a];
                if moved {
                    self.x[a][i] = v[3 + a];
                    self.u[a][i] = v[6 + a];
                }
            }
        }
    }

    /// Copies the spring status and state of every rank's nodes to every
    /// rank after the commit, and sums what the ranks broke and whether
    /// any changed a spring; returns the sums.
    pub(crate) fn share_springs(&mut self, broken: usize, changed: bool) -> (usize, bool) {
        if !self.ranks.several() {
            return (broken, changed);
        }
        let nd = self.geom.directions.len();
        let (status, spring) = (&self.status, &self.spring);
        let width = 4 * nd;
        if let Some(all) = self.ranks.exchange(width, |i, buf| {
            for b in i * nd..(i + 1) * nd {
                let s = spring[b];
                buf.extend([f64::from(status[b]), s.plastic, s.accumulated, s.dashpot]);
            }
        }) {
            for (i, v) in self.ranks.received(&all, width) {
                for (d, w) in v.chunks_exact(4).enumerate() {
                    let b = i * nd + d;
                    self.status[b] = w[0] as u8;
                    self.spring[b] = crate::law::SpringState {
                        plastic: w[1],
                        accumulated: w[2],
                        dashpot: w[3],
                    };
                }
            }
        }
        let mut sums = [broken as u64, u64::from(changed)];
        self.ranks.sum(&mut sums);
        (sums[0] as usize, sums[1] > 0)
    }

    /// Copies the new volume, energy, pressure and temperature of every
    /// rank's nodes (the `new` arrays of the volume and energy update) to
    /// every rank.
    pub(crate) fn share_thermal_state(&self, new: [&mut Vec<f64>; 4]) {
        let [v, e, p, t] = new;
        let all = {
            let (v, e, p, t) = (&*v, &*e, &*p, &*t);
            self.ranks
                .exchange(4, |i, buf| buf.extend([v[i], e[i], p[i], t[i]]))
        };
        let Some(all) = all else {
            return;
        };
        for (i, w) in self.ranks.received(&all, 4) {
            v[i] = w[0];
            e[i] = w[1];
            p[i] = w[2];
            t[i] = w[3];
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn slabs_are_whole_planes_shared_evenly() {
        assert_eq!(slab_starts(7, 10, 1).unwrap(), vec![0, 70]);
        assert_eq!(slab_starts(7, 10, 2).unwrap(), vec![0, 40, 70]);
        assert_eq!(slab_starts(7, 10, 3).unwrap(), vec![0, 30, 50, 70]);
        assert_eq!(
            slab_starts(7, 10, 7).unwrap(),
            (0..=7).map(|p| p * 10).collect::<Vec<_>>()
        );
        let err = slab_starts(7, 10, 8).unwrap_err();
        assert!(err.contains("8 ranks for a lattice of 7 nodes"), "{err}");
    }
}
