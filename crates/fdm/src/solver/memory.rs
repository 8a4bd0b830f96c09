//! The memory an [`FdmSolver`] holds, counted from its arrays' lengths.

use std::mem::size_of;

use super::{FdmSolver, CROSS_CELLS};
use crate::gas::GasLaw;
use crate::state::NVAR;
use crate::sweep::{nscratch, NMAX};

/// Memory an [`FdmSolver`] holds on this rank, bytes, from its arrays'
/// lengths.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct FdmMemory {
    /// The conserved fields of this rank's patches, ghost layers included.
    pub state: usize,
    /// The second buffer each sweep writes into (the same shapes).
    pub back: usize,
    /// The domain faces' outflow accumulators: the run's and the current
    /// sweep's, one value per flow variable and face cell.
    pub faces: usize,
    /// The ghost exchange's pack buffers (as grown so far) and, on an
    /// axisymmetric grid, the ring weights of the radial sweep.
    pub halo: usize,
    /// The work arrays one sweeping thread holds (thread-local, reused from
    /// sweep to sweep): the largest work item's slab, by the sweeps'
    /// chunking.
    pub scratch_per_thread: usize,
}

impl FdmMemory {
    /// Everything held with `threads` sweeping threads.
    pub fn total(&self, threads: usize) -> usize {
        self.state + self.back + self.faces + self.halo + threads * self.scratch_per_thread
    }
}

impl<E: GasLaw> FdmSolver<E> {
    /// The memory the solver holds (see [`FdmMemory`]).
    pub fn memory_use(&self) -> FdmMemory {
        let f64s = |n: usize| n * size_of::<f64>();
        let stored = |fields: &[brisance_grid::PatchFields]| -> usize {
            fields
                .iter()
                .flat_map(|f| f.data.iter().map(Vec::len))
                .sum()
        };
        let faces: usize = self
            .outflow
            .iter()
            .chain(&self.outflow_sweep)
            .map(|v| v.len() * NVAR)
            .sum();
        let radial: usize = self
            .radial
            .iter()
            .flat_map(|w| w.iter().map(Vec::len))
            .sum();
        // A work item's slab: an x line (one row along x), or up to
        // CROSS_CELLS columns of a y or z sweep's rows; the scratch holds
        // `nscratch` arrays of that many values.
        let rank = self.comm.rank();
        let nf = if E::SPECIES { NMAX } else { NVAR };
        let slab = self
            .level
            .patches
            .iter()
            .zip(&self.owner)
            .filter(|(_, &o)| o == rank)
            .flat_map(|(p, _)| {
                let d = p.dims();
                let across = p.size[0].min(CROSS_CELLS);
                (0..3).filter(|&a| self.level.is_active(a)).map(move |a| {
                    if a == 0 {
                        d[0]
                    } else {
                        d[a] * across
                    }
                })
            })
            .max()
            .unwrap_or(0);
        FdmMemory {
            state: f64s(stored(&self.fields)),
            back: f64s(stored(&self.back)),
            faces: f64s(faces),
            halo: self.exchange.bytes() + f64s(radial),
            scratch_per_thread: f64s(nscratch(nf) * slab),
        }
    }
}

#[cfg(test)]
mod tests {
    use brisance_core::Solver;
    use brisance_eos::IdealGas;
    use brisance_grid::Level;

    use crate::{FdmBoundary, FdmOptions, FdmSolver, PrimitiveState, GHOST};

    /// A gas at rest in an 8 × 6 × 4 box of `layout` patches, walls all
    /// round, with a pressure step so that the sweeps have work.
    fn boxed(layout: [usize; 3]) -> FdmSolver<IdealGas> {
        let level = Level::new([0.0; 3], [1.0; 3], [8, 6, 4], layout, GHOST).expect("level");
        FdmSolver::new(
            IdealGas::new(1.4, 1.0, 1.0),
            level,
            [FdmBoundary::Reflective; 6],
            FdmOptions::default(),
            |x| PrimitiveState {
                density: 1.0,
                velocity: [0.0; 3],
                pressure: if x[0] < 0.5 { 2.0 } else { 1.0 },
            },
        )
        .expect("solver")
    }

    #[test]
    fn one_patch_by_hand() {
        let mut s = boxed([1, 1, 1]);
        let dt = s.stable_dt().expect("dt");
        s.advance(dt).expect("step");
        let m = s.memory_use();
        // 8 + 2·4 by 6 + 2·4 by 4 + 2·4 cells, 5 conserved fields, 8 B.
        let cells = 16 * 14 * 12;
        assert_eq!(m.state, 5 * cells * 8);
        assert_eq!(m.back, m.state);
        // Face cells: x faces 6·4, y faces 8·4, z faces 8·6, two of each,
        // in the run's and the sweep's accumulators, 5 values of 8 B.
        assert_eq!(m.faces, (6 * 4 + 8 * 4 + 8 * 6) * 2 * 2 * 5 * 8);
        // The largest work item: a y sweep's 14 rows by the 8 columns
        // across (a z sweep's 12 by 8, an x line's 16), 33 arrays
        // (θ, ν, μ, p, 5 × Ū, F(Ū), F*, U^L, λF^L, 2 limiter, p*, source).
        assert_eq!(m.scratch_per_thread, 33 * 14 * 8 * 8);
        // The ghost exchange packs one side at a time into a buffer per
        // side, grown to the largest face: the z face's 4 layers of 16 × 14
        // cells, 5 fields.
        assert_eq!(m.halo, 2 * 4 * 16 * 14 * 5 * 8);
        assert_eq!(
            m.total(2),
            m.state + m.back + m.faces + m.halo + 2 * m.scratch_per_thread
        );
    }

    #[test]
    fn two_patches_hold_their_ghosts_and_the_exchange_buffers() {
        let mut one = boxed([1, 1, 1]);
        let mut two = boxed([2, 1, 1]);
        for s in [&mut one, &mut two] {
            let dt = s.stable_dt().expect("dt");
            s.advance(dt).expect("step");
        }
        let (a, b) = (one.memory_use(), two.memory_use());
        // Two patches of 4 + 2·4 along x: 2·12 against 16 allocated.
        assert_eq!(b.state, a.state / 16 * 24);
        assert_eq!(b.back, b.state);
        // The domain's faces do not depend on the split.
        assert_eq!(b.faces, a.faces);
        // Each patch's buffers grow to its largest face, 12 × 14 (x and
        // z faces; y 12 × 12), 4 layers, 5 fields, one per side.
        assert_eq!(b.halo, 2 * 2 * 4 * 12 * 14 * 5 * 8);
        // A y sweep's rows (14) by the 4 columns of a patch.
        assert_eq!(b.scratch_per_thread, 33 * 14 * 4 * 8);
    }
}
