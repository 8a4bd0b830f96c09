//! An MPM run spread over MPI ranks (docs/cluster.md).
//!
//! Every rank holds every particle and the whole node lattice, and runs
//! every pass that the grid shares among the particles — the binning, the
//! P2G sums (seed 001 eqs 18–21), the node update, MUSL's re-mapping, heat
//! conduction, the stable step, totals and outputs — over all of them, on
//! the same values, so their bits are those of one rank. What is split is
//! the pass that costs most per particle: the G2P fused with the stress
//! update (eqs 24–30 and the constitutive model), which reads the grid and
//! writes only the particle's own state. A rank runs it for a contiguous
//! run of particles in storage order (`comm::equal_runs`: equal counts,
//! the first ranks taking one more), then sends what the pass wrote for its run to every rank
//! (one `MPI_Allgatherv`), which copies it in: copied, not combined, so the
//! result is the bits of one rank for any rank count.
//!
//! The coupled pipelines' particle update
//! ([`crate::CoupledStep::update_particles`]) splits the same pass the
//! same way.
//!
//! The failure of an update crosses with the state: each rank sends its
//! lowest failing particle (if any) in front of its run, and every rank
//! takes the lowest over the ranks, which is the one a single rank finds.

use super::MpmSolver;
use crate::step::{G2pParts, ParticleFailure, FAILURE_REASONS};
use crate::viscosity::BulkViscosityState;
use crate::Particles;
use brisance_grid::comm::{equal_runs, Communicator, NodeRuns};
use std::sync::Arc;

/// Values in front of each rank's run: whether it failed, then the
/// failure's index, J, tr(L) Δt, max |L| Δt, max |F| and reason.
const HEADER: usize = 7;

impl MpmSolver {
    /// Spreads the particle updates over the ranks of `comm` (nothing to
    /// do on one rank): from the next step this rank updates the stresses
    /// of its run of particles and receives the others'. Every rank builds
    /// the same solver and calls this last, after the setters.
    pub fn distribute(&mut self, comm: Arc<dyn Communicator>) {
        self.comm = (comm.size() > 1).then_some(comm);
    }

    /// The runs of particles of this step's count over the ranks; `None`
    /// on one rank.
    pub(super) fn particle_runs(&self) -> Option<NodeRuns> {
        let comm = self.comm.as_ref()?;
        let starts = equal_runs(self.particles.len(), comm.size());
        Some(NodeRuns::new(comm.clone(), starts))
    }
}

/// Copies what the fused G2P and stress update wrote for each rank's run
/// of particles to every rank: the position and velocity when `parts`
/// moved them, and the stress, F, volume, temperature, specific internal
/// energy, failed flag, history and bulk-viscosity state; returns the
/// failure with the lowest index over the ranks. A collective call.
pub(super) fn share_updated(
    runs: &NodeRuns,
    ps: &mut Particles,
    bulk: &mut [BulkViscosityState],
    parts: G2pParts,
    failure: Option<ParticleFailure>,
) -> Option<ParticleFailure> {
    let stride = ps.history_stride();
    let (moved, accelerated) = (parts.position, parts.velocity);
    let width = 21 + stride + 3 * usize::from(moved) + 3 * usize::from(accelerated);
    let own = runs.nodes();
    let mut buf = Vec::with_capacity(HEADER + width * own.len());
    match &failure {
        Some(f) => buf.extend([
            1.0,
            f.index as f64,
            f.jacobian,
            f.trace_l_dt,
            f.max_l_dt,
            f.max_f_old,
            reason_number(f.reason) as f64,
        ]),
        None => buf.extend([0.0; HEADER]),
    }
    for p in own {
        if moved {
            buf.extend_from_slice(&ps.position[p]);
        }
        if accelerated {
            buf.extend_from_slice(&ps.velocity[p]);
        }
        buf.extend_from_slice(&ps.stress[p]);
        buf.extend_from_slice(&ps.deformation_gradient[p]);
        buf.extend([
            ps.volume[p],
            ps.temperature[p],
            ps.specific_internal_energy[p],
            f64::from(u8::from(ps.failed[p])),
            bulk[p].q,
            bulk[p].trace_d,
        ]);
        buf.extend_from_slice(&ps.history[p * stride..(p + 1) * stride]);
    }
    let all = runs.comm().all_gather(&buf);
    let mut lowest = None;
    for (r, part) in all.iter().enumerate() {
        let (head, rest) = part.split_at(HEADER);
        if lowest.is_none() && head[0] != 0.0 {
            lowest = Some(ParticleFailure {
                index: head[1] as usize,
                jacobian: head[2],
                trace_l_dt: head[3],
                max_l_dt: head[4],
                max_f_old: head[5],
                reason: FAILURE_REASONS
                    .get(head[6] as usize)
                    .copied()
                    .unwrap_or("the stress update failed"),
            });
        }
        if r == runs.comm().rank() {
            continue;
        }
        for (p, v) in runs.nodes_of(r).zip(rest.chunks_exact(width)) {
            let mut at = 0;
            let mut take = |n: usize| {
                let s = &v[at..at + n];
                at += n;
                s
            };
            if moved {
                ps.position[p].copy_from_slice(take(3));
            }
            if accelerated {
                ps.velocity[p].copy_from_slice(take(3));
            }
            ps.stress[p].copy_from_slice(take(6));
            ps.deformation_gradient[p].copy_from_slice(take(9));
            let s = take(6);
            ps.volume[p] = s[0];
            ps.temperature[p] = s[1];
            ps.specific_internal_energy[p] = s[2];
            ps.failed[p] = s[3] != 0.0;
            bulk[p] = BulkViscosityState {
                q: s[4],
                trace_d: s[5],
            };
            ps.history[p * stride..(p + 1) * stride].copy_from_slice(take(stride));
        }
    }
    lowest
}

/// The position of `reason` in [`FAILURE_REASONS`] (one past the end for
/// a reason not listed).
fn reason_number(reason: &str) -> usize {
    FAILURE_REASONS
        .iter()
        .position(|r| *r == reason)
        .unwrap_or(FAILURE_REASONS.len())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_failure_reason_has_its_number() {
        for (k, r) in FAILURE_REASONS.iter().enumerate() {
            assert_eq!(reason_number(r), k);
        }
        assert_eq!(reason_number("something else"), FAILURE_REASONS.len());
    }
}
