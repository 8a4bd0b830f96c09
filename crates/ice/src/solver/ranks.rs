//! The ICE across MPI ranks (docs/cluster.md): a rank owns whole patches
//! and runs every per-patch kernel on its own patches only; ghost layers
//! that border another rank's patch arrive as messages from the halo
//! exchange ([`InProcessExchange::distributed`]).
//!
//! What a pass finds over the whole grid — the first failing cell in
//! global order, step 2's and step 12's cold-rule firings, the face
//! bookings of steps 8–9 and 12, the equilibration statistics — is
//! gathered from every rank as it stands (one message per pass), and
//! every rank then sums it in global cell order, as one rank does: the
//! same bits on every rank and for any rank count. Outputs, totals and
//! checkpoints read every patch as its owner holds it
//! ([`IceSolver::gathered_state`]).
//!
//! A reaction that burns on a surface finds its surface over the whole
//! grid in global order: each rank gives the reactant's fraction and the
//! hottest temperature of its own cells, every rank runs the surface pass
//! on the gathered field (the same bits everywhere), each owner gives the
//! burn rates of its surface cells, and each rank keeps and carries the
//! burn in its own patches (`surface.rs`).
//!
//! The implicit pressure solves its Helmholtz system over the whole grid
//! on every rank, from the cell values each rank gives for its own
//! patches (`IceSolver::gather_cells`): the same system, the same
//! factorisation, the same bits on every rank.
//!
//! Across ranks both pressure solves run, with viscosity, conduction and
//! every reaction; particles (the IceMpm pipeline) are refused with an
//! error.

use std::borrow::Cow;
use std::sync::Arc;

use brisance_grid::comm::{self, Communicator};

use super::*;

/// The ranks a solver's patches are shared among.
#[derive(Debug, Clone)]
pub(super) struct Ranks {
    pub(super) comm: Arc<dyn Communicator>,
    /// The owner rank of every patch ([`comm::patch_owners`]).
    pub(super) owner: Vec<usize>,
    /// Per patch: whether this rank updates it.
    pub(super) owned: Vec<bool>,
}

impl Ranks {
    /// One rank owning all `patches`.
    pub(super) fn serial(patches: usize) -> Self {
        Self {
            comm: Arc::new(comm::Serial),
            owner: vec![0; patches],
            owned: vec![true; patches],
        }
    }

    pub(super) fn several(&self) -> bool {
        self.comm.size() > 1
    }

    /// Values each rank computed for its own cells, `width` per cell, put
    /// in global order on every rank (a collective call on several
    /// ranks): `owners` gives, in global order, the patch of every cell of
    /// the pass (this rank's `mine` holds its own of them in that order),
    /// and `out` gets every cell's values in that order. On one rank
    /// `mine` itself.
    pub(super) fn in_global_order(
        &self,
        owners: impl Iterator<Item = usize>,
        mine: &[f64],
        width: usize,
        out: &mut Vec<f64>,
    ) {
        out.clear();
        if !self.several() {
            out.extend_from_slice(mine);
            return;
        }
        let lists = self.comm.all_gather(mine);
        let mut at = vec![0; lists.len()];
        for pid in owners {
            let r = self.owner[pid];
            out.extend_from_slice(&lists[r][at[r]..at[r] + width]);
            at[r] += width;
        }
    }
}

/// A pass's face bookings as values: (global cell, face, material, the
/// five quantities).
fn pack_booking(list: &FaceBooking) -> Vec<f64> {
    let mut out = Vec::with_capacity(8 * list.len());
    for (g, f, r, q) in list {
        out.extend([*g as f64, *f as f64, *r as f64]);
        out.extend(q);
    }
    out
}

fn unpack_booking(values: &[f64], out: &mut FaceBooking) {
    for x in values.chunks_exact(8) {
        out.push((
            x[0] as usize,
            x[1] as usize,
            x[2] as usize,
            [x[3], x[4], x[5], x[6], x[7]],
        ));
    }
}

/// A failure as values: none, or (global index, cell, the description's
/// bytes).
fn pack_failure(fail: &Failure) -> Vec<f64> {
    match fail {
        None => Vec::new(),
        Some((g, cell, msg)) => {
            let mut out = vec![*g as f64, cell[0] as f64, cell[1] as f64, cell[2] as f64];
            out.extend(msg.bytes().map(f64::from));
            out
        }
    }
}

fn unpack_failure(values: &[f64]) -> Failure {
    if values.len() < 4 {
        return None;
    }
    let bytes: Vec<u8> = values[4..].iter().map(|&b| b as u8).collect();
    Some((
        values[0] as usize,
        [values[1] as usize, values[2] as usize, values[3] as usize],
        String::from_utf8_lossy(&bytes).into_owned(),
    ))
}

/// Step 2's per-cell cold-rule findings as values: (global cell, then per
/// material whether it fired and ρ_r Δe_r).
fn pack_warm(list: &[(usize, KeptWarmCell)]) -> Vec<f64> {
    let mut out = Vec::with_capacity((1 + 2 * MAX_MATERIALS) * list.len());
    for (g, k) in list {
        out.push(*g as f64);
        out.extend(k.fired.iter().map(|&f| f64::from(u8::from(f))));
        out.extend(k.energy_density);
    }
    out
}

fn unpack_warm(values: &[f64], out: &mut Vec<(usize, KeptWarmCell)>) {
    for x in values.chunks_exact(1 + 2 * MAX_MATERIALS) {
        let mut k = KeptWarmCell::default();
        for r in 0..MAX_MATERIALS {
            k.fired[r] = x[1 + r] != 0.0;
            k.energy_density[r] = x[1 + MAX_MATERIALS + r];
        }
        out.push((x[0] as usize, k));
    }
}

/// What a pass found: the first failing cell, the face bookings, step 2's
/// and step 12's cold-rule firings and the equilibration counts. Given to
/// [`IceSolver::gather_pass`] as this rank found it (moved in, so that one
/// rank hands it back without a copy), returned as every rank found it.
#[derive(Default)]
pub(super) struct Found {
    pub(super) fail: Failure,
    pub(super) booking: FaceBooking,
    pub(super) warm: Vec<(usize, KeptWarmCell)>,
    pub(super) advected_warm: Vec<(usize, usize, f64)>,
    pub(super) stats: EquilibrationStats,
}

/// A part of the ICE step that passes over the whole grid, so that the
/// solver runs on one rank only ([`IceSolver::whole_grid_pass`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum WholeGridPass {
    /// Materials carried by particles (the coupled pipeline).
    Particles,
}

impl WholeGridPass {
    /// The error that refuses this pass on `ranks` ranks.
    pub fn refusal(self, ranks: usize) -> String {
        format!(
            "ice: {} does not run on several ranks ({ranks} here); run it as one process",
            self.describe()
        )
    }

    /// What the error message calls it.
    pub fn describe(self) -> &'static str {
        match self {
            Self::Particles => "materials carried by particles",
        }
    }
}

/// Sections of a pass's message, in order.
const SECTIONS: usize = 5;

impl<E: Eos> IceSolver<E> {
    /// Spreads the solver's patches over the ranks of `comm` (nothing to
    /// do on one rank): from now on this rank updates only the patches it
    /// owns ([`comm::patch_owners`]), and frees the state and work arrays
    /// of the others. Called once the solver is set up
    /// (materials, reactions, transport); every rank builds the same
    /// solver and calls it. A run builds the ICE spread instead
    /// ([`Self::new_on`]), never holding the whole grid; a solver built
    /// so is refused here.
    ///
    /// Particles (the coupled pipeline) are refused on several ranks; the
    /// implicit pressure and surface burns run their whole-grid passes on
    /// every rank from the gathered cell values.
    pub fn distribute(&mut self, comm: Arc<dyn Communicator>) -> Result<(), IceError> {
        if comm.size() == 1 {
            return Ok(());
        }
        self.single_rank_only(comm.size())?;
        let owner =
            comm::patch_owners(self.level.patches.len(), comm.size()).map_err(IceError::Invalid)?;
        let rank = comm.rank();
        if self.ranks.several()
            || (0..owner.len()).any(|id| owner[id] == rank && !self.state[id].is_stored())
        {
            return Err(IceError::Invalid(
                "ice: the patches are already shared among ranks: distribute a solver built on one rank"
                    .into(),
            ));
        }
        // The other ranks' patches: no storage here (a rank's memory is
        // its share of the grid once built).
        for (id, &o) in owner.iter().enumerate() {
            if o != rank {
                self.state[id].release();
                self.lag[id].release();
                self.press[id].release();
                self.scratch[id].release();
                self.transport.release(id);
            }
        }
        self.halo = InProcessExchange::distributed(comm.clone(), owner.clone());
        self.ranks = Ranks {
            owned: owner.iter().map(|&o| o == rank).collect(),
            owner,
            comm,
        };
        Ok(())
    }

    /// The patches whose state and work arrays this rank stores: its own,
    /// in patch order (every patch on one rank).
    pub fn stored_patches(&self) -> Vec<usize> {
        (0..self.state.len())
            .filter(|&id| {
                self.state[id].is_stored()
                    && self.lag[id].is_stored()
                    && self.press[id].is_stored()
                    && !self.scratch[id].divergence.is_empty()
            })
            .collect()
    }

    /// The first part of this solver's step that passes over the whole
    /// grid, and so keeps it on one rank; `None` when it can spread.
    pub fn whole_grid_pass(&self) -> Option<WholeGridPass> {
        if self.lagrangian.iter().any(|&l| l) {
            Some(WholeGridPass::Particles)
        } else {
            None
        }
    }

    /// An error when this solver cannot run on `ranks` ranks.
    fn single_rank_only(&self, ranks: usize) -> Result<(), IceError> {
        match self.whole_grid_pass() {
            Some(pass) => Err(IceError::Invalid(pass.refusal(ranks))),
            None => Ok(()),
        }
    }

    /// [`Self::single_rank_only`] once the solver is spread over ranks:
    /// the setters call it, so a solver cannot gain a whole-grid pass
    /// after [`Self::distribute`].
    pub(super) fn still_distributable(&self) -> Result<(), IceError> {
        if self.ranks.several() {
            self.single_rank_only(self.ranks.comm.size())
        } else {
            Ok(())
        }
    }

    /// Every patch's state as its owner holds it: the state itself on one
    /// rank; on several, a copy whose every patch comes from its owner (a
    /// collective call).
    pub(super) fn gathered_state(&self) -> Cow<'_, [PatchFields]> {
        comm::owners_fields(&*self.ranks.comm, &self.ranks.owner, &self.state)
    }

    /// What every rank found in a pass (one message from each rank): the
    /// first failure in global order and the union of the lists. On one
    /// rank the lists are this rank's and nothing is sent. A collective
    /// call on several ranks.
    pub(super) fn gather_pass(&self, found: Found) -> Found {
        if !self.ranks.several() {
            return found;
        }
        let s = found.stats;
        let sections: [Vec<f64>; SECTIONS] = [
            pack_failure(&found.fail),
            pack_booking(&found.booking),
            pack_warm(&found.warm),
            found
                .advected_warm
                .iter()
                .flat_map(|&(c, r, e)| [c as f64, r as f64, e])
                .collect(),
            vec![
                s.max_iterations as f64,
                s.max_residual,
                s.total_iterations as f64,
            ],
        ];
        let mut message: Vec<f64> = sections.iter().map(|s| s.len() as f64).collect();
        for s in &sections {
            message.extend(s);
        }
        let mut g = Found::default();
        for m in self.ranks.comm.all_gather(&message) {
            let lens: Vec<usize> = m[..SECTIONS].iter().map(|&l| l as usize).collect();
            let mut at = SECTIONS;
            let mut part = |k: usize| {
                let s = &m[at..at + lens[k]];
                at += lens[k];
                s
            };
            g.fail = first_failure(g.fail, unpack_failure(part(0)));
            unpack_booking(part(1), &mut g.booking);
            unpack_warm(part(2), &mut g.warm);
            for x in part(3).chunks_exact(3) {
                g.advected_warm.push((x[0] as usize, x[1] as usize, x[2]));
            }
            if let [it, res, total] = *part(4) {
                g.stats.max_iterations = g.stats.max_iterations.max(it as usize);
                g.stats.max_residual = g.stats.max_residual.max(res);
                g.stats.total_iterations += total as u64;
            }
        }
        g
    }

    /// `f(patch, local index)` of every cell in global order into `out`, on
    /// every rank: [`par_gather`] on one rank; on several, each rank
    /// evaluates its own cells and the values are gathered in global order
    /// (a collective call). Each value depends on its own cell only, so
    /// the bits are those of one rank.
    pub(super) fn gather_cells(&self, out: &mut Vec<f64>, f: impl Fn(usize, usize) -> f64 + Sync) {
        let count = self.level.geometry.cell_count();
        if !self.ranks.several() {
            out.resize(count, 0.0);
            par_gather(&self.level, out, f);
            return;
        }
        let owned = &self.ranks.owned;
        let mut mine = Vec::new();
        self.level.for_each_cell_in_order(|_, pid, c| {
            if owned[pid] {
                mine.push(f(pid, c));
            }
        });
        // Each cell's patch, from the level (no list of the grid's size).
        let n = self.level.geometry.cells;
        let patch_of = (0..count).map(|g| {
            let at = [g % n[0], (g / n[0]) % n[1], g / (n[0] * n[1])];
            self.level
                .locate(at)
                .expect("every cell of the domain has a patch")
                .0
        });
        self.ranks.in_global_order(patch_of, &mine, 1, out);
    }

    /// The largest CFL rate over the ranks, NaN when any rank's is NaN (a
    /// collective call on several ranks; the maximum is exact).
    pub(super) fn max_over_ranks(&self, rate: f64) -> f64 {
        if !self.ranks.several() {
            return rate;
        }
        let mut nan = [u64::from(rate.is_nan())];
        self.ranks.comm.sum(&mut nan);
        if nan[0] > 0 {
            return f64::NAN;
        }
        -self.ranks.comm.min(-rate)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use brisance_eos::IdealGas;
    use brisance_grid::Level;

    #[test]
    fn a_pass_report_survives_its_packing() {
        let fail: Failure = Some((42, [2, 3, 0], "material 2 density −1e-3 kg/m³".into()));
        assert_eq!(unpack_failure(&pack_failure(&fail)), fail);
        assert_eq!(unpack_failure(&pack_failure(&None)), None);
        let booking: FaceBooking = vec![(7, 1, 0, [1.0, -2.0, 3.5, 0.0, 1e-300])];
        let mut back = Vec::new();
        unpack_booking(&pack_booking(&booking), &mut back);
        assert_eq!(back, booking);
        let mut k = KeptWarmCell::default();
        k.fired[1] = true;
        k.energy_density[1] = -0.25;
        let mut warm = Vec::new();
        unpack_warm(&pack_warm(&[(9, k)]), &mut warm);
        assert_eq!(warm, vec![(9, k)]);
    }

    /// Rank 0 of two, for the checks [`IceSolver::distribute`] makes
    /// before any message (a collective call would be a test failure).
    #[derive(Debug)]
    struct FirstOfTwo;

    impl Communicator for FirstOfTwo {
        fn rank(&self) -> usize {
            0
        }
        fn size(&self) -> usize {
            2
        }
        fn exchange(&self, _: &[(usize, i32, &[f64])], _: &mut [(usize, i32, &mut Vec<f64>)]) {
            unreachable!("no message before the first step")
        }
        fn broadcast(&self, _: usize, _: &mut [f64]) {
            unreachable!("no message before the first step")
        }
        fn min(&self, _: f64) -> f64 {
            unreachable!("no message before the first step")
        }
        fn sum(&self, _: &mut [u64]) {
            unreachable!("no message before the first step")
        }
        fn abort(&self, _: i32) -> ! {
            unreachable!("no abort")
        }
    }

    /// Two gases at rest on `patches` patches along x.
    fn two_gases(patches: usize, pressure: PressureSolve) -> IceSolver<IdealGas> {
        use crate::{CellState, ExchangeCoefficients, IceBoundary, MaterialState};
        let level = Level::new([0.0; 3], [1.0, 0.1, 0.1], [8, 1, 1], [patches, 1, 1], GHOST)
            .expect("a level");
        let gas = |rho: f64| MaterialState {
            density: rho,
            velocity: [0.0; 3],
            volume_fraction: 0.5,
        };
        IceSolver::new(
            vec![IdealGas::new(1.4, 1.0, 1.0), IdealGas::new(1.67, 3.0, 0.2)],
            level,
            std::array::from_fn(|_| IceBoundary::Symmetry),
            ExchangeCoefficients::uniform(2, 1e15, 0.0),
            IceOptions {
                pressure,
                ..Default::default()
            },
            |_| CellState {
                pressure: 1.0,
                materials: vec![gas(1.0), gas(0.2)],
            },
        )
        .expect("the solver")
    }

    #[test]
    fn what_needs_the_whole_grid_refuses_several_ranks() {
        use brisance_grid::comm::Communicator;
        let two = || -> Arc<dyn Communicator> { Arc::new(FirstOfTwo) };
        // The explicit ICE spreads; rank 0 of two owns the first patch.
        let mut s = two_gases(2, PressureSolve::Explicit);
        s.distribute(two()).unwrap();
        assert_eq!(s.ranks.owned, vec![true, false]);
        // Viscosity and heat conduction spread: the faces' work arrays of
        // the other rank's patch are not stored.
        let viscous = crate::MaterialTransport {
            viscosity: 1e-3,
            ..Default::default()
        };
        s.set_transport(vec![viscous, Default::default()]).unwrap();
        assert_eq!(s.transport.stored(), vec![true, false]);
        // Nothing that needs the whole grid may be added afterwards.
        let e = s.set_lagrangian(&[true, false]).unwrap_err().to_string();
        assert!(e.contains("materials carried by particles"), "{e}");
        // The implicit pressure spreads; a split with fewer patches than
        // ranks does not.
        let implicit = PressureSolve::Implicit(Default::default());
        two_gases(2, implicit).distribute(two()).unwrap();
        let e = two_gases(1, PressureSolve::Explicit)
            .distribute(two())
            .unwrap_err()
            .to_string();
        assert!(e.contains("2 ranks for 1 patches"), "{e}");
    }

    #[test]
    fn one_rank_gathers_its_own_findings_unchanged() {
        let solver = crate::cases::sod_one(8, Advection::VanLeer, 0.1);
        let fail: Failure = Some((3, [3, 0, 0], "x".into()));
        let booking: FaceBooking = vec![(0, 0, 0, [1.0; 5])];
        let g = solver.gather_pass(Found {
            fail: fail.clone(),
            booking: booking.clone(),
            ..Default::default()
        });
        assert_eq!(g.fail, fail);
        assert_eq!(g.booking, booking);
        assert!(g.warm.is_empty() && g.advected_warm.is_empty());
        assert_eq!(solver.max_over_ranks(2.5), 2.5);
        assert!(solver.max_over_ranks(f64::NAN).is_nan());
    }
}
