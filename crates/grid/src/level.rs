//! Levels and patches.

use brisance_core::{CellData, CellPiece, CellPieces, SolverError, UniformGridGeometry};

use crate::fields::PatchFields;

/// Why a level cannot be built.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum GridError {
    /// A cell count of zero, or more patches than cells, or a patch thinner
    /// than the ghost layers.
    #[error("{0}")]
    Layout(String),
}

/// One patch: a box of interior cells of the level plus `ghost[d]` layers on
/// each side in every active direction.
#[derive(Debug, Clone, PartialEq)]
pub struct Patch {
    /// Position of the patch in the patch layout.
    pub index: [usize; 3],
    /// Global index of the first interior cell.
    pub lo: [usize; 3],
    /// Interior cells per direction.
    pub size: [usize; 3],
    /// Ghost layers per side per direction (0 in unused directions).
    pub ghost: [usize; 3],
}

impl Patch {
    /// Allocated cells per direction (interior plus ghosts on both sides).
    pub fn dims(&self) -> [usize; 3] {
        std::array::from_fn(|d| self.size[d] + 2 * self.ghost[d])
    }

    /// Number of allocated cells.
    pub fn allocated_cells(&self) -> usize {
        self.dims().iter().product()
    }

    /// Number of interior cells.
    pub fn interior_cells(&self) -> usize {
        self.size.iter().product()
    }

    /// Stride of one step along each direction in the local storage.
    pub fn strides(&self) -> [usize; 3] {
        let d = self.dims();
        [1, d[0], d[0] * d[1]]
    }

    /// Local storage index of local cell (i, j, k), counted from the first
    /// ghost cell.
    #[inline]
    pub fn local_index(&self, l: [usize; 3]) -> usize {
        let d = self.dims();
        l[0] + d[0] * (l[1] + d[1] * l[2])
    }

    /// Local storage index of the interior cell with global index `g`.
    #[inline]
    pub fn index_of_global(&self, g: [usize; 3]) -> usize {
        self.local_index(std::array::from_fn(|d| g[d] - self.lo[d] + self.ghost[d]))
    }

    /// Whether global cell `g` is an interior cell of this patch.
    pub fn contains_global(&self, g: [usize; 3]) -> bool {
        (0..3).all(|d| g[d] >= self.lo[d] && g[d] < self.lo[d] + self.size[d])
    }

    /// Calls `f(global cell, local storage index)` for every interior
    /// cell, x fastest.
    pub fn for_each_interior(&self, mut f: impl FnMut([usize; 3], usize)) {
        for k in self.lo[2]..self.lo[2] + self.size[2] {
            for j in self.lo[1]..self.lo[1] + self.size[1] {
                for i in self.lo[0]..self.lo[0] + self.size[0] {
                    f([i, j, k], self.index_of_global([i, j, k]));
                }
            }
        }
    }

    /// Global index of the interior cell at local storage index `l`.
    pub fn global_of_local(&self, l: [usize; 3]) -> [usize; 3] {
        std::array::from_fn(|d| l[d] + self.lo[d] - self.ghost[d])
    }
}

/// The order in which [`Level::first_failing_cell`] ranks cells.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum CellOrder {
    /// Patch by patch, x fastest within a patch.
    Patches,
    /// Over the whole grid, x fastest ([`UniformGridGeometry::linear_index`]).
    Global,
}

/// A Cartesian level: the grid geometry and its split into patches.
#[derive(Debug, Clone, PartialEq)]
pub struct Level {
    /// Cells, spacing and origin.
    pub geometry: UniformGridGeometry,
    /// Patches per direction.
    pub layout: [usize; 3],
    /// The patches, x-fastest in the layout.
    pub patches: Vec<Patch>,
}

/// Sizes of `parts` nearly equal pieces of `n` cells (the first `n % parts`
/// get one more).
fn split(n: usize, parts: usize) -> Vec<usize> {
    (0..parts)
        .map(|p| n / parts + usize::from(p < n % parts))
        .collect()
}

impl Level {
    /// Builds a level of `cells` cells between `origin` and `upper`, split
    /// into `layout` patches, with `ghost` layers in every direction that has
    /// more than one cell.
    pub fn new(
        origin: [f64; 3],
        upper: [f64; 3],
        cells: [usize; 3],
        layout: [usize; 3],
        ghost: usize,
    ) -> Result<Self, GridError> {
        const AXES: [char; 3] = ['x', 'y', 'z'];
        for d in 0..3 {
            if cells[d] == 0 {
                return Err(GridError::Layout(format!(
                    "the domain has 0 cells along {}",
                    AXES[d]
                )));
            }
            if !(upper[d] > origin[d]) || !(upper[d] - origin[d]).is_finite() {
                return Err(GridError::Layout(format!(
                    "the domain's upper bound along {} ({}) must be above its lower bound ({})",
                    AXES[d], upper[d], origin[d]
                )));
            }
            if layout[d] == 0 || layout[d] > cells[d] {
                return Err(GridError::Layout(format!(
                    "{} patches along {} for {} cells: need between 1 and the cell count",
                    layout[d], AXES[d], cells[d]
                )));
            }
        }
        let ghost_d: [usize; 3] = std::array::from_fn(|d| if cells[d] > 1 { ghost } else { 0 });
        let sizes: [Vec<usize>; 3] = std::array::from_fn(|d| split(cells[d], layout[d]));
        for d in 0..3 {
            if cells[d] > 1 && sizes[d].iter().any(|&s| s < ghost) {
                return Err(GridError::Layout(format!(
                    "patches along {} would be thinner than the {ghost} ghost layers; use at most {} patches",
                    AXES[d],
                    cells[d] / ghost.max(1)
                )));
            }
        }
        let mut patches = Vec::with_capacity(layout.iter().product());
        for pk in 0..layout[2] {
            for pj in 0..layout[1] {
                for pi in 0..layout[0] {
                    let index = [pi, pj, pk];
                    let lo = std::array::from_fn(|d| sizes[d][..index[d]].iter().sum());
                    let size = std::array::from_fn(|d| sizes[d][index[d]]);
                    patches.push(Patch {
                        index,
                        lo,
                        size,
                        ghost: ghost_d,
                    });
                }
            }
        }
        let geometry = UniformGridGeometry {
            origin,
            spacing: std::array::from_fn(|d| (upper[d] - origin[d]) / cells[d] as f64),
            cells,
        };
        Ok(Self {
            geometry,
            layout,
            patches,
        })
    }

    /// Linear patch id of layout position `index`.
    pub fn patch_id(&self, index: [usize; 3]) -> usize {
        index[0] + self.layout[0] * (index[1] + self.layout[1] * index[2])
    }

    /// Whether direction `d` is active (has more than one cell).
    pub fn is_active(&self, d: usize) -> bool {
        self.geometry.cells[d] > 1
    }

    /// The patch that owns global cell `g`, and the local storage index;
    /// `None` outside the grid. Found from the split of each axis (the
    /// first `cells mod patches` patches one cell longer, as
    /// [`Level::new`] cuts them), not by a scan of the patches, so it
    /// costs the same for any patch count.
    pub fn locate(&self, g: [usize; 3]) -> Option<(usize, usize)> {
        let cells = self.geometry.cells;
        if (0..3).any(|d| g[d] >= cells[d]) {
            return None;
        }
        let index = std::array::from_fn(|d| crate::comm::owner_of(g[d], cells[d], self.layout[d]));
        let mut id = self.patch_id(index);
        if !self.patches.get(id).is_some_and(|p| p.contains_global(g)) {
            // Patches cut otherwise than by `new`: look for the cell.
            id = self.patches.iter().position(|p| p.contains_global(g))?;
        }
        Some((id, self.patches[id].index_of_global(g)))
    }

    /// The patch and local storage index of the cell that contains
    /// `point`, or an error naming the point when it lies outside the
    /// domain.
    pub fn locate_point(&self, point: [f64; 3]) -> Result<(usize, usize), SolverError> {
        let g = self.geometry.cell_containing(point).ok_or_else(|| {
            SolverError::Other(format!("point {point:?} lies outside the domain"))
        })?;
        Ok(self
            .locate(g)
            .expect("every cell of the domain has a patch"))
    }

    /// Calls `f(global cell, patch id, local index)` for every interior
    /// cell in global order (x fastest, then y, then z), whatever the patch
    /// split, so sums and outputs built in this order have the same bits
    /// for any layout.
    pub fn for_each_cell_in_order(&self, mut f: impl FnMut([usize; 3], usize, usize)) {
        let layout = self.layout;
        for pz in 0..layout[2] {
            let p0 = &self.patches[self.patch_id([0, 0, pz])];
            for k in p0.lo[2]..p0.lo[2] + p0.size[2] {
                for py in 0..layout[1] {
                    let p1 = &self.patches[self.patch_id([0, py, pz])];
                    for j in p1.lo[1]..p1.lo[1] + p1.size[1] {
                        for px in 0..layout[0] {
                            let id = self.patch_id([px, py, pz]);
                            let p = &self.patches[id];
                            for i in p.lo[0]..p.lo[0] + p.size[0] {
                                f([i, j, k], id, p.index_of_global([i, j, k]));
                            }
                        }
                    }
                }
            }
        }
    }

    /// Calls `f(global cell, patch id, local index)` for every interior
    /// cell of the patches `mine` accepts, patch by patch (x fastest
    /// within a patch): for sums whose order does not matter
    /// ([`brisance_core::ExactSum`]), which a rank can then take over its
    /// own patches alone.
    pub fn for_each_cell_of(
        &self,
        mine: impl Fn(usize) -> bool,
        mut f: impl FnMut([usize; 3], usize, usize),
    ) {
        for (pid, p) in self.patches.iter().enumerate() {
            if !mine(pid) {
                continue;
            }
            p.for_each_interior(|g, n| f(g, pid, n));
        }
    }

    /// The first interior cell, in `order`, for which `check(global cell,
    /// patch id, local index)` fails (returns false), over the cells of
    /// every rank of `comm`: each rank checks only the cells of its own
    /// patches (`owner[p]` is the rank of patch `p`,
    /// [`crate::comm::patch_owners`]), patch by patch, and one minimum over
    /// the ranks picks the first, so every rank returns the cell one rank
    /// finds. In [`CellOrder::Patches`] a rank stops at its first failure
    /// (`check` may fill the cells it accepts); in [`CellOrder::Global`]
    /// it checks all its cells. A collective call.
    pub fn first_failing_cell(
        &self,
        comm: &dyn crate::comm::Communicator,
        owner: &[usize],
        order: CellOrder,
        mut check: impl FnMut([usize; 3], usize, usize) -> bool,
    ) -> Option<[usize; 3]> {
        let mut first = f64::INFINITY;
        let mut ordinal = 0_usize;
        for (pid, p) in self.patches.iter().enumerate() {
            if owner[pid] == comm.rank() && !(order == CellOrder::Patches && first.is_finite()) {
                let mut m = ordinal;
                p.for_each_interior(|g, n| {
                    let key = match order {
                        CellOrder::Patches if first.is_finite() => return,
                        CellOrder::Patches => m,
                        CellOrder::Global => self.geometry.linear_index(g),
                    };
                    if !check(g, pid, n) {
                        first = first.min(key as f64);
                    }
                    m += 1;
                });
            }
            ordinal += p.interior_cells();
        }
        let first = comm.min(first);
        if !first.is_finite() {
            return None;
        }
        let key = first as usize;
        let unravel = |m: usize, n: [usize; 3]| [m % n[0], m / n[0] % n[1], m / (n[0] * n[1])];
        match order {
            CellOrder::Global => Some(unravel(key, self.geometry.cells)),
            CellOrder::Patches => {
                let mut m = key;
                for p in &self.patches {
                    if m < p.interior_cells() {
                        let l = unravel(m, p.size);
                        return Some(std::array::from_fn(|d| p.lo[d] + l[d]));
                    }
                    m -= p.interior_cells();
                }
                None
            }
        }
    }

    /// An error naming the first cell in global order (x fastest) whose
    /// centre `covered` rejects: every cell must lie in an initial region.
    /// Each rank of `ranks` tests the cells of its own patches
    /// ([`crate::comm::patch_owners`], which must accept the split, else
    /// its message is the error), and one minimum over the ranks finds the
    /// first, so every rank gives the error one rank gives without testing
    /// the whole grid. A collective call.
    pub fn first_uncovered_cell(
        &self,
        ranks: &dyn crate::comm::Communicator,
        covered: impl Fn([f64; 3]) -> bool,
    ) -> Result<(), String> {
        let geometry = self.geometry;
        let owner = crate::comm::patch_owners(self.patches.len(), ranks.size())?;
        let Some([i, j, k]) =
            self.first_failing_cell(ranks, &owner, CellOrder::Global, |g, _, _| {
                covered(geometry.cell_centre(g))
            })
        else {
            return Ok(());
        };
        let x = geometry.cell_centre([i, j, k]);
        Err(format!(
            "cell ({i}, {j}, {k}) at {x:?} is in no initial region; add an `Everywhere` region first"
        ))
    }

    /// Every field of patch `pid` over its interior cells, x fastest
    /// (a checkpoint piece).
    pub fn patch_interior(&self, pid: usize, fields: &PatchFields) -> Vec<Vec<f64>> {
        let p = &self.patches[pid];
        fields
            .data
            .iter()
            .map(|values| {
                let mut out = Vec::with_capacity(p.interior_cells());
                p.for_each_interior(|_, n| out.push(values[n]));
                out
            })
            .collect()
    }

    /// Writes arrays laid out as [`Level::patch_interior`] gives them
    /// back into the interior cells of patch `pid`, or says why they do
    /// not fit it.
    pub fn set_patch_interior(
        &self,
        pid: usize,
        fields: &mut PatchFields,
        values: &[Vec<f64>],
    ) -> Result<(), String> {
        let p = &self.patches[pid];
        if values.len() != fields.data.len() || values.iter().any(|v| v.len() != p.interior_cells())
        {
            return Err(format!(
                "patch {pid} holds {} fields of {} cells, not {} fields of {:?}",
                values.len(),
                values.first().map_or(0, Vec::len),
                fields.data.len(),
                p.size
            ));
        }
        for (dst, src) in fields.data.iter_mut().zip(values) {
            let mut src = src.iter();
            p.for_each_interior(|_, n| dst[n] = *src.next().expect("sizes checked"));
        }
        Ok(())
    }

    /// Every field of `patches` (one [`PatchFields`] per patch) over the
    /// interior cells in global order, one array per field: a layout that
    /// does not depend on the patch split (checkpoints).
    pub fn gather_fields(&self, patches: &[PatchFields]) -> Vec<Vec<f64>> {
        let n_fields = patches.first().map_or(0, |p| p.data.len());
        let mut out: Vec<Vec<f64>> = (0..n_fields)
            .map(|_| Vec::with_capacity(self.geometry.cell_count()))
            .collect();
        self.for_each_cell_in_order(|_, pid, n| {
            for (f, values) in out.iter_mut().enumerate() {
                values.push(patches[pid].data[f][n]);
            }
        });
        out
    }

    /// Writes arrays laid out as [`Level::gather_fields`] gives them back
    /// into the interior cells of `patches`; the caller has checked that
    /// there is one array per field, each with one value per cell. Patches
    /// without storage (another rank's, [`PatchFields::unstored`]) are
    /// skipped.
    pub fn scatter_fields(&self, patches: &mut [PatchFields], fields: &[Vec<f64>]) {
        let stored: Vec<bool> = patches.iter().map(PatchFields::is_stored).collect();
        let mut i = 0;
        self.for_each_cell_in_order(|_, pid, n| {
            if stored[pid] {
                for (f, values) in fields.iter().enumerate() {
                    patches[pid].data[f][n] = values[i];
                }
            }
            i += 1;
        });
    }

    /// The cell fields `names` (with field ids `ids`, one per name) on the
    /// whole grid in global order, `value(patch id, local index, field id)`
    /// giving each value.
    pub fn gather_cell_data(
        &self,
        names: &[String],
        ids: &[usize],
        value: impl Fn(usize, usize, usize) -> f64,
    ) -> CellData {
        let count = self.geometry.cell_count();
        let mut out: Vec<(String, Vec<f64>)> = names
            .iter()
            .map(|f| (f.clone(), Vec::with_capacity(count)))
            .collect();
        self.for_each_cell_in_order(|_, pid, n| {
            for (slot, &id) in out.iter_mut().zip(ids) {
                slot.1.push(value(pid, n, id));
            }
        });
        CellData {
            geometry: self.geometry,
            fields: out,
        }
    }

    /// The cell fields `names` (field ids `ids`) as one piece per patch
    /// for the patches `mine` accepts, each piece's cells in x-fastest
    /// order within the patch, `value(patch id, local index, field id)`
    /// giving each value; no value of another patch is read, so a rank
    /// needs only its own patches to be current.
    pub fn cell_pieces(
        &self,
        mine: impl Fn(usize) -> bool,
        names: &[String],
        ids: &[usize],
        value: impl Fn(usize, usize, usize) -> f64,
    ) -> CellPieces {
        let pieces = self
            .patches
            .iter()
            .enumerate()
            .filter(|&(pid, _)| mine(pid))
            .map(|(pid, p)| {
                let count = p.interior_cells();
                let mut fields: Vec<(String, Vec<f64>)> = names
                    .iter()
                    .map(|f| (f.clone(), Vec::with_capacity(count)))
                    .collect();
                p.for_each_interior(|_, n| {
                    for (slot, &id) in fields.iter_mut().zip(ids) {
                        slot.1.push(value(pid, n, id));
                    }
                });
                CellPiece {
                    patch: pid,
                    lo: p.lo,
                    cells: p.size,
                    fields,
                }
            })
            .collect();
        CellPieces {
            geometry: self.geometry,
            extents: self.patches.iter().map(|p| (p.lo, p.size)).collect(),
            pieces,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Two patches along x: cell (5, 0, 0) of patch 1 comes first in
    /// global order, (1, 1, 0) of patch 0 first in patch order; each
    /// order finds its own, and with the patches on two thread ranks each
    /// rank finds the same cell.
    #[test]
    fn the_first_failing_cell_in_either_order_on_one_rank_or_two() {
        let level = Level::new([0.0; 3], [1.0; 3], [8, 2, 1], [2, 1, 1], 0).unwrap();
        let fails = |g: [usize; 3]| g == [5, 0, 0] || g == [1, 1, 0] || g == [7, 1, 0];
        let first = |comm: &dyn crate::comm::Communicator, order| {
            let owner: Vec<usize> = (0..2).map(|p| p % comm.size()).collect();
            let mut checked = 0;
            let cell = level.first_failing_cell(comm, &owner, order, |g, _, _| {
                checked += 1;
                !fails(g)
            });
            (cell, checked)
        };
        let serial = crate::comm::Serial;
        // Patch order stops at the first failure: patch 0's cells up to
        // (1, 1, 0), the sixth.
        assert_eq!(first(&serial, CellOrder::Patches), (Some([1, 1, 0]), 6));
        assert_eq!(first(&serial, CellOrder::Global), (Some([5, 0, 0]), 16));
        for order in [CellOrder::Patches, CellOrder::Global] {
            let one = first(&serial, order).0;
            for got in crate::comm::InProcess::run(2, 1, |comm| first(&*comm, order).0) {
                assert_eq!(got, one, "{order:?}");
            }
        }
        let none = level.first_failing_cell(&serial, &[0, 0], CellOrder::Patches, |_, _, _| true);
        assert_eq!(none, None);
    }

    #[test]
    fn cell_pieces_hold_each_patch_in_its_own_x_fastest_order() {
        let level = Level::new([0.0; 3], [1.0; 3], [5, 3, 2], [2, 1, 2], 1).unwrap();
        // The value of a cell is its global linear index.
        let global = |pid: usize, n: usize| {
            let p = &level.patches[pid];
            let d = p.dims();
            let l = [n % d[0], (n / d[0]) % d[1], n / (d[0] * d[1])];
            level.geometry.linear_index(p.global_of_local(l)) as f64
        };
        let names = ["index".to_string(), "twice".to_string()];
        let all = level.cell_pieces(
            |_| true,
            &names,
            &[0, 1],
            |pid, n, id| global(pid, n) * (id + 1) as f64,
        );
        assert_eq!(all.geometry, level.geometry);
        assert_eq!(
            all.extents,
            vec![
                ([0, 0, 0], [3, 3, 1]),
                ([3, 0, 0], [2, 3, 1]),
                ([0, 0, 1], [3, 3, 1]),
                ([3, 0, 1], [2, 3, 1]),
            ]
        );
        assert_eq!(all.pieces.len(), 4);
        // Patch 1 holds cells i = 3, 4 of rows j = 0, 1, 2 in plane k = 0.
        let p1 = &all.pieces[1];
        assert_eq!((p1.patch, p1.lo, p1.cells), (1, [3, 0, 0], [2, 3, 1]));
        assert_eq!(p1.fields[0].0, "index");
        assert_eq!(p1.fields[0].1, vec![3.0, 4.0, 8.0, 9.0, 13.0, 14.0]);
        assert_eq!(p1.fields[1].1, vec![6.0, 8.0, 16.0, 18.0, 26.0, 28.0]);
        // Every cell once, over all pieces.
        let mut seen: Vec<f64> = all
            .pieces
            .iter()
            .flat_map(|p| p.fields[0].1.iter().copied())
            .collect();
        seen.sort_by(f64::total_cmp);
        assert_eq!(seen, (0..30).map(|i| i as f64).collect::<Vec<_>>());
        // A rank's share: its patches only, every extent still listed.
        let odd = level.cell_pieces(|pid| pid % 2 == 1, &names, &[0, 1], |_, _, _| 0.0);
        assert_eq!(odd.extents, all.extents);
        let ids: Vec<usize> = odd.pieces.iter().map(|p| p.patch).collect();
        assert_eq!(ids, vec![1, 3]);
    }

    #[test]
    fn cells_are_visited_in_global_order_whatever_the_patch_split() {
        for layout in [[1, 1, 1], [3, 2, 1], [2, 1, 2]] {
            let level = Level::new([0.0; 3], [1.0; 3], [7, 5, 4], layout, 2).unwrap();
            let mut seen = Vec::new();
            level.for_each_cell_in_order(|g, pid, n| {
                assert_eq!(level.locate(g), Some((pid, n)));
                seen.push(level.geometry.linear_index(g));
            });
            assert_eq!(seen, (0..140).collect::<Vec<_>>(), "layout {layout:?}");
            assert_eq!(level.locate([7, 0, 0]), None);
            assert_eq!(level.locate([0, 5, 0]), None);
            assert_eq!(level.locate([0, 0, 4]), None);
        }
    }

    #[test]
    fn gathered_cell_data_and_points_follow_the_global_order() {
        let level = Level::new([0.0; 3], [1.0; 3], [4, 3, 1], [2, 3, 1], 1).unwrap();
        // A value that names its cell: 10 × global linear index + field id.
        let value = |pid: usize, n: usize, id: usize| {
            let p = &level.patches[pid];
            let (s, d) = (p.strides(), p.dims());
            let g = p.global_of_local([n % d[0], (n / s[1]) % d[1], n / s[2]]);
            10.0 * level.geometry.linear_index(g) as f64 + id as f64
        };
        let names = ["a".to_string(), "b".to_string()];
        let data = level.gather_cell_data(&names, &[0, 1], value);
        assert_eq!(data.fields[0].0, "a");
        for c in 0..12 {
            assert_eq!(data.fields[0].1[c], 10.0 * c as f64);
            assert_eq!(data.fields[1].1[c], 10.0 * c as f64 + 1.0);
        }
        // The point (0.6, 0.5) is in cell (2, 1): global index 6.
        let (pid, n) = level.locate_point([0.6, 0.5, 0.5]).unwrap();
        assert_eq!(value(pid, n, 0), 60.0);
        assert!(level
            .locate_point([1.5, 0.5, 0.5])
            .unwrap_err()
            .to_string()
            .contains("outside the domain"));
    }

    #[test]
    fn fields_gathered_in_global_order_scatter_back_on_another_split() {
        let a = Level::new([0.0; 3], [1.0; 3], [6, 4, 1], [2, 2, 1], 1).unwrap();
        let b = Level::new([0.0; 3], [1.0; 3], [6, 4, 1], [3, 1, 1], 1).unwrap();
        let mut pa: Vec<PatchFields> = a.patches.iter().map(|p| PatchFields::zeros(p, 2)).collect();
        a.for_each_cell_in_order(|g, pid, n| {
            let c = a.geometry.linear_index(g) as f64;
            pa[pid].data[0][n] = c;
            pa[pid].data[1][n] = -c;
        });
        let gathered = a.gather_fields(&pa);
        assert_eq!(gathered[0], (0..24).map(|c| c as f64).collect::<Vec<_>>());
        assert_eq!(
            gathered[1],
            (0..24).map(|c| -(c as f64)).collect::<Vec<_>>()
        );
        let mut pb: Vec<PatchFields> = b.patches.iter().map(|p| PatchFields::zeros(p, 2)).collect();
        b.scatter_fields(&mut pb, &gathered);
        assert_eq!(b.gather_fields(&pb), gathered);
    }

    #[test]
    fn patches_tile_the_level_without_overlap() {
        let level = Level::new([0.0; 3], [1.0; 3], [10, 7, 1], [3, 2, 1], 3).unwrap();
        let mut owner = vec![usize::MAX; 70];
        for (id, p) in level.patches.iter().enumerate() {
            assert_eq!(p.ghost, [3, 3, 0]);
            for k in 0..p.size[2] {
                for j in 0..p.size[1] {
                    for i in 0..p.size[0] {
                        let g = [p.lo[0] + i, p.lo[1] + j, p.lo[2] + k];
                        let n = level.geometry.linear_index(g);
                        assert_eq!(owner[n], usize::MAX, "cell {g:?} owned twice");
                        owner[n] = id;
                    }
                }
            }
        }
        assert!(owner.iter().all(|&o| o != usize::MAX));
        assert_eq!(level.patches[0].size, [4, 4, 1]);
        assert_eq!(level.patches[5].lo, [7, 4, 0]);
    }

    #[test]
    fn local_and_global_indices_invert() {
        let level = Level::new([0.0; 3], [1.0; 3], [8, 8, 8], [2, 2, 2], 2).unwrap();
        let p = &level.patches[7];
        let g = [6, 5, 7];
        let l = p.index_of_global(g);
        let d = p.dims();
        let local = [l % d[0], (l / d[0]) % d[1], l / (d[0] * d[1])];
        assert_eq!(p.global_of_local(local), g);
        assert_eq!(level.locate(g), Some((7, l)));
    }

    #[test]
    fn bad_layouts_are_rejected_with_a_reason() {
        let e = Level::new([0.0; 3], [1.0; 3], [0, 1, 1], [1, 1, 1], 3).unwrap_err();
        assert!(e.to_string().contains("0 cells along x"));
        let e = Level::new([0.0; 3], [1.0; 3], [10, 1, 1], [4, 1, 1], 3).unwrap_err();
        assert!(e.to_string().contains("thinner"));
        let e = Level::new([0.0; 3], [0.0, 1.0, 1.0], [10, 1, 1], [1, 1, 1], 3).unwrap_err();
        assert!(e.to_string().contains("upper bound"));
    }

    /// The first cell outside every initial region, in global order, is the
    /// same on one rank and on 1, 2 and 4 thread ranks that each test only
    /// their own patches.
    #[test]
    fn the_first_uncovered_cell_is_found_alike_on_thread_ranks() {
        let level = Level::new([0.0; 3], [1.0; 3], [8, 4, 8], [2, 1, 2], 2).unwrap();
        // Uncovered in the upper half of z: at x > 0.6 (patch 3), and in the
        // column x = 0.3125 at y > 0.25 (patch 2). Patch 2's first, (2, 1, 4),
        // comes first in patch order; the first in global order (x fastest)
        // is patch 3's (5, 0, 4), found by the rank that owns patch 3.
        let covered = |x: [f64; 3]| {
            !(x[2] > 0.5 && (x[0] > 0.6 || (x[0] > 0.25 && x[0] < 0.375 && x[1] > 0.25)))
        };
        let one = level
            .first_uncovered_cell(&crate::comm::Serial, covered)
            .unwrap_err();
        assert!(one.starts_with("cell (5, 0, 4) at "), "{one}");
        for ranks in [1, 2, 4] {
            let got = crate::comm::InProcess::run(ranks, 1, |comm| {
                level.first_uncovered_cell(&*comm, covered).err()
            });
            for (r, e) in got.into_iter().enumerate() {
                assert_eq!(e.as_deref(), Some(one.as_str()), "rank {r} of {ranks}");
            }
        }
        // Covered everywhere: no error on any rank.
        for e in crate::comm::InProcess::run(4, 1, |comm| {
            level.first_uncovered_cell(&*comm, |_| true).err()
        }) {
            assert_eq!(e, None);
        }
    }
}
