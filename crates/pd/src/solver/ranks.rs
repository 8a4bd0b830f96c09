//! A peridynamic run spread over MPI ranks (docs/cluster.md).
//!
//! Every rank holds every node and bond. A rank owns a contiguous run of
//! nodes (the node order of the lattice build) and evaluates only the
//! passes whose cost grows with the bonds for them: the node scalars
//! (step 3, the gas expansion sums over a family) and the forces (step 4:
//! bonds, short-range contacts, the products' artificial viscosity). What
//! each pass wrote for the owned nodes is then copied to every rank, so
//! the passes that cost one operation per node (the two half kicks, the
//! drift, the stable step, totals and outputs) run on every rank over
//! every node, on the same values, and give the same bits as one rank.
//!
//! What a rank sends per step: after step 3, the node's `state[3]` (the
//! effective critical stretch or gas coefficient), its gas state and the
//! viscous pass's node data; after step 4, its force, minimum stretch and
//! intact-bond count, its contact force and its viscous output, and the
//! bond factors of each of its rows in which a bond broke during the
//! step. The plastic stretches (one per bond) are gathered only when a
//! checkpoint or the bond energy reads them.

use super::PdSolver;
use crate::forces::NodeForce;
use crate::viscosity::ViscousOut;
use brisance_grid::comm::{Communicator, NodeRuns};
use std::borrow::Cow;
use std::ops::Range;
use std::sync::Arc;

/// How the nodes are shared among the ranks.
#[derive(Debug, Clone)]
pub(super) struct Ranks {
    runs: NodeRuns,
    /// The owned nodes and every neighbour in their rows: the nodes whose
    /// per-node values a row pass over the owned nodes reads (all of them
    /// on one rank).
    reach: Range<usize>,
    /// Intact bonds of each owned node after the last exchange, to find
    /// the rows in which a bond broke.
    intact: Vec<u32>,
}

impl Ranks {
    /// One rank owning all `nodes`.
    pub(super) fn serial(nodes: usize) -> Self {
        Self {
            runs: NodeRuns::serial(nodes),
            reach: 0..nodes,
            intact: Vec::new(),
        }
    }

    /// Whether the nodes are spread over more than one rank.
    pub(super) fn several(&self) -> bool {
        self.runs.several()
    }

    /// The nodes this rank owns.
    pub(super) fn nodes(&self) -> Range<usize> {
        self.runs.nodes()
    }

    /// The owned nodes and their rows' neighbours, as one range
    /// ([`row_reach`]).
    pub(super) fn reach(&self) -> Range<usize> {
        self.reach.clone()
    }
}

/// The smallest range of nodes holding `own` and every neighbour in the
/// rows of `own` (families in compressed-row form, `offsets` one longer
/// than the node count): what a pass that reads its neighbours' per-node
/// values needs formed before it runs over `own`.
pub fn row_reach(offsets: &[u32], neighbours: &[u32], own: Range<usize>) -> Range<usize> {
    if own.is_empty() {
        return own;
    }
    let bonds = offsets[own.start] as usize..offsets[own.end] as usize;
    let (low, high) = neighbours[bonds]
        .iter()
        .fold((own.start, own.end), |(low, high), &j| {
            (low.min(j as usize), high.max(j as usize + 1))
        });
    low..high
}

/// The first node of each of `ranks` ranks, then `offsets.len() − 1` (the
/// node count): contiguous runs of nodes holding as nearly equal shares
/// of the bonds as whole rows allow. Rank r starts at the first node whose
/// row begins at or after r/ranks of the bonds. An error when there are
/// fewer nodes than ranks.
pub fn node_starts(offsets: &[u32], ranks: usize) -> Result<Vec<usize>, String> {
    let nodes = offsets.len().saturating_sub(1);
    if ranks == 0 || nodes < ranks {
        return Err(format!(
            "{ranks} ranks for {nodes} peridynamic nodes: every rank needs at least one node; run on fewer ranks"
        ));
    }
    let bonds = u128::from(offsets[nodes]);
    let mut starts = Vec::with_capacity(ranks + 1);
    starts.push(0);
    for r in 1..ranks {
        let share = bonds * r as u128 / ranks as u128;
        let first = offsets.partition_point(|&o| u128::from(o) < share);
        // At least one node per rank, before and after.
        let lowest = starts[r - 1] + 1;
        let highest = nodes - (ranks - r);
        starts.push(first.clamp(lowest, highest));
    }
    starts.push(nodes);
    Ok(starts)
}

/// A viscous output from its six packed values.
fn viscous_out(v: &[f64]) -> ViscousOut {
    ViscousOut {
        force: [v[0], v[1], v[2]],
        heating: v[3],
        damping: v[4],
        stiffness: v[5],
    }
}

/// Appends `a` to `buf`.
fn push<const N: usize>(buf: &mut Vec<f64>, a: &[f64; N]) {
    buf.extend_from_slice(a);
}

impl PdSolver {
    /// Spreads the nodes over the ranks of `comm` (nothing to do on one
    /// rank): from now on this rank evaluates the node scalars and forces
    /// of the nodes it owns (`node_starts`: equal shares of the bonds)
    /// and receives the others'. Every rank builds the same solver and
    /// calls this last, after the setters.
    pub fn distribute(&mut self, comm: Arc<dyn Communicator>) -> Result<(), String> {
        if comm.size() == 1 {
            return Ok(());
        }
        let starts = node_starts(&self.families.offsets, comm.size())?;
        let r = comm.rank();
        self.ranks = Ranks {
            reach: row_reach(
                &self.families.offsets,
                &self.families.neighbours,
                starts[r]..starts[r + 1],
            ),
            intact: self.bond_out[starts[r]..starts[r + 1]]
                .iter()
                .map(|b| b.intact)
                .collect(),
            runs: NodeRuns::new(comm, starts),
        };
        Ok(())
    }

    /// The nodes this rank owns (all of them on one rank).
    pub fn owned_nodes(&self) -> Range<usize> {
        self.ranks.nodes()
    }

    /// After a restore: the intact counts the next exchange compares with
    /// are the restored ones.
    pub(super) fn ranks_restored(&mut self) {
        if self.ranks.several() {
            let own = self.ranks.nodes();
            self.ranks.intact = self.bond_out[own].iter().map(|b| b.intact).collect();
        }
    }

    /// Copies what step 3 wrote for each rank's nodes to every rank: the
    /// node's `state[3]`, its gas state and closing time, and its viscous
    /// node data.
    pub(super) fn share_node_scalars(&mut self) {
        let gas = !self.gas.is_empty();
        let viscous = !self.viscous_node.is_empty();
        let closes = !self.closing.is_empty();
        let width = 1 + if gas { 4 } else { 0 } + closes as usize + if viscous { 4 } else { 0 };
        let (state, gas_state, viscous_node) = (&self.state, &self.gas, &self.viscous_node);
        let closing = &self.closing;
        let Some(all) = self.ranks.runs.exchange(width, |i, buf| {
            buf.push(state[i][3]);
            if gas {
                push(buf, &gas_state[i]);
            }
            if closes {
                buf.push(closing[i]);
            }
            if viscous {
                push(buf, &viscous_node[i]);
            }
        }) else {
            return;
        };
        for (i, v) in self.ranks.runs.received(&all, width) {
            self.state[i][3] = v[0];
            let mut at = 1;
            if gas {
                self.gas[i].copy_from_slice(&v[at..at + 4]);
                at += 4;
            }
            if closes {
                self.closing[i] = v[at];
                at += 1;
            }
            if viscous {
                self.viscous_node[i].copy_from_slice(&v[at..at + 4]);
            }
        }
    }

    /// Copies what step 4 wrote for each rank's nodes to every rank: the
    /// node force, minimum stretch and intact count, the energy its bonds
    /// dissipated (when booked), the contact force and
    /// stiffness, the viscous output, and the factors of each row in which
    /// a bond broke (a row's factors change only by breaking, to 0).
    pub(super) fn share_forces(&mut self) {
        if !self.ranks.several() {
            return;
        }
        let own = self.ranks.nodes();
        let contact = !self.contact.is_empty();
        let viscous = !self.viscous.is_empty();
        let dissipating = !self.dissipated_node.is_empty();
        let width =
            5 + if contact { 4 } else { 0 } + if viscous { 6 } else { 0 } + dissipating as usize;
        let mut buf = Vec::with_capacity(width * own.len());
        for i in own.clone() {
            let b = self.bond_out[i];
            push(&mut buf, &b.force);
            buf.push(b.min_stretch as f64);
            buf.push(b.intact as f64);
            if dissipating {
                buf.push(self.dissipated_node[i] as f64);
            }
            if contact {
                let (f, k) = self.contact[i];
                push(&mut buf, &f);
                buf.push(k);
            }
            if viscous {
                let v = self.viscous[i];
                push(&mut buf, &v.force);
                push(&mut buf, &[v.heating, v.damping, v.stiffness]);
            }
        }
        // The rows in which a bond broke: node index, then its factors.
        for (k, i) in own.clone().enumerate() {
            if self.bond_out[i].intact != self.ranks.intact[k] {
                self.ranks.intact[k] = self.bond_out[i].intact;
                buf.push(i as f64);
                buf.extend(self.factor[self.families.row(i)].iter().map(|&w| w as f64));
            }
        }
        let all = self.ranks.runs.comm().all_gather(&buf);
        for (nodes, part) in self.ranks.runs.others(&all) {
            let (fixed, rows) = part.split_at(width * nodes.len());
            for (i, v) in nodes.zip(fixed.chunks_exact(width)) {
                self.bond_out[i] = NodeForce {
                    force: [v[0], v[1], v[2]],
                    min_stretch: v[3] as f32,
                    intact: v[4] as u32,
                };
                let mut at = 5;
                if dissipating {
                    self.dissipated_node[i] = v[at] as f32;
                    at += 1;
                }
                if contact {
                    self.contact[i] = ([v[at], v[at + 1], v[at + 2]], v[at + 3]);
                    at += 4;
                }
                if viscous {
                    self.viscous[i] = viscous_out(&v[at..at + 6]);
                }
            }
            let mut rest = rows;
            while let Some((&i, tail)) = rest.split_first() {
                let row = self.families.row(i as usize);
                let (w, tail) = tail.split_at(row.len());
                for (f, &w) in self.factor[row].iter_mut().zip(w) {
                    *f = w as f32;
                }
                rest = tail;
            }
        }
    }

    /// Copies the viscous output alone (after a pass that changed only the
    /// velocities).
    pub(super) fn share_viscous(&mut self) {
        if !self.ranks.several() || self.viscous.is_empty() {
            return;
        }
        let viscous = &self.viscous;
        let Some(all) = self.ranks.runs.exchange(6, |i, buf| {
            let ViscousOut {
                force,
                heating,
                damping,
                stiffness,
            } = viscous[i];
            push(buf, &force);
            push(buf, &[heating, damping, stiffness]);
        }) else {
            return;
        };
        for (i, v) in self.ranks.runs.received(&all, 6) {
            self.viscous[i] = viscous_out(v);
        }
    }

    /// Every bond's plastic stretch as its row's owner holds it: the array
    /// itself on one rank; on several, a copy gathered from the owners (a
    /// collective call).
    pub(super) fn gathered_plastic(&self) -> Cow<'_, [f32]> {
        if !self.ranks.several() {
            return Cow::Borrowed(&self.plastic);
        }
        let own = self.ranks.nodes();
        let offsets = &self.families.offsets;
        let bonds = offsets[own.start] as usize..offsets[own.end] as usize;
        let mine: Vec<f64> = self.plastic[bonds].iter().map(|&s| s as f64).collect();
        let all = self.ranks.runs.comm().all_gather(&mine);
        Cow::Owned(all.iter().flatten().map(|&s| s as f32).collect())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A chain of 6 nodes, each bonded to its neighbours within two: the
    /// reach of a run is the run widened by two on each side, cut at the
    /// chain's ends; an empty run reaches nothing.
    #[test]
    fn a_runs_reach_holds_its_rows_neighbours() {
        let mut offsets = vec![0u32];
        let mut neighbours = Vec::new();
        for i in 0..6i64 {
            neighbours.extend(
                (i - 2..=i + 2)
                    .filter(|&j| j != i && (0..6).contains(&j))
                    .map(|j| j as u32),
            );
            offsets.push(neighbours.len() as u32);
        }
        assert_eq!(row_reach(&offsets, &neighbours, 0..6), 0..6);
        assert_eq!(row_reach(&offsets, &neighbours, 0..1), 0..3);
        assert_eq!(row_reach(&offsets, &neighbours, 2..3), 0..5);
        assert_eq!(row_reach(&offsets, &neighbours, 4..6), 2..6);
        assert!(row_reach(&offsets, &neighbours, 3..3).is_empty());
        // A node without bonds reaches itself.
        assert_eq!(row_reach(&[0, 0, 0], &[], 1..2), 1..2);
    }

    #[test]
    fn nodes_are_shared_by_bonds_in_contiguous_runs() {
        // Rows of 1, 1, 1, 1, 4, 4, 4, 4 bonds: 20 bonds, 10 per rank.
        let offsets = [0, 1, 2, 3, 4, 8, 12, 16, 20];
        assert_eq!(node_starts(&offsets, 1).unwrap(), vec![0, 8]);
        // The first row starting at or after bond 10 is node 6 (offset 12).
        assert_eq!(node_starts(&offsets, 2).unwrap(), vec![0, 6, 8]);
        // Shares 5, 10, 15: rows from offset 8 (node 5), 12 (6), 16 (7).
        assert_eq!(node_starts(&offsets, 4).unwrap(), vec![0, 5, 6, 7, 8]);
        // As many ranks as nodes: one node each.
        assert_eq!(
            node_starts(&offsets, 8).unwrap(),
            (0..=8).collect::<Vec<_>>()
        );
        let err = node_starts(&offsets, 9).unwrap_err();
        assert!(err.contains("9 ranks for 8 peridynamic nodes"), "{err}");
    }

    #[test]
    fn rows_without_bonds_still_give_every_rank_a_node() {
        let offsets = [0, 0, 0, 0, 6];
        // Node 3 holds every bond: it is the last rank's alone.
        assert_eq!(node_starts(&offsets, 3).unwrap(), vec![0, 2, 3, 4]);
    }
}
