//! Halo exchange: filling ghost layers from neighbouring patches or from the
//! boundary conditions.
//!
//! The exchange is two-phase, as a message-passing implementation would be:
//! every patch *packs* the values its ghost layers need (from the neighbour's
//! interior or from its own boundary cells) into a buffer, then every patch
//! *unpacks* its buffer into its ghosts. Both phases run in parallel over
//! patches with no shared mutable state, so the result does not depend on
//! the thread count. Buffers are kept between calls, so a step allocates
//! nothing once warmed up.

use rayon::prelude::*;

use crate::{BoundaryConditions, Face, FaceBc, FieldKind, FieldSet, Level, Patch, PatchFields};

/// Fills ghost layers. Implementations: [`InProcessExchange`] (all patches in
/// this process); a message-passing one implements the same calls.
pub trait HaloExchange: Send {
    /// Fills the ghost layers along `axis` of every patch. The planes span
    /// the full allocated extent of the other two axes, so filling x, then y,
    /// then z also fills edges and corners.
    fn fill_axis(
        &mut self,
        level: &Level,
        set: &FieldSet,
        bcs: &BoundaryConditions,
        fields: &mut [PatchFields],
        axis: usize,
    );

    /// Fills every ghost layer (all active axes in order).
    fn fill_all(
        &mut self,
        level: &Level,
        set: &FieldSet,
        bcs: &BoundaryConditions,
        fields: &mut [PatchFields],
    ) {
        for axis in 0..3 {
            if level.is_active(axis) {
                self.fill_axis(level, set, bcs, fields, axis);
            }
        }
    }
}

/// The in-process exchange: patches are entries of one slice.
#[derive(Debug, Default, Clone)]
pub struct InProcessExchange {
    buffers: Vec<[Vec<f64>; 2]>,
}

impl InProcessExchange {
    /// An exchange with no buffers yet (they grow on first use).
    pub fn new() -> Self {
        Self::default()
    }
}

/// Calls `f(range)` for the contiguous runs of storage indices that make up
/// the plane `layer` normal to `axis`, in a fixed order shared by packing
/// and unpacking: whole x rows for planes normal to y or z, single cells
/// for planes normal to x.
#[inline]
fn for_each_run(
    dims: [usize; 3],
    axis: usize,
    layer: usize,
    mut f: impl FnMut(std::ops::Range<usize>),
) {
    let stride = [1, dims[0], dims[0] * dims[1]];
    match axis {
        0 => {
            for c2 in 0..dims[2] {
                for c1 in 0..dims[1] {
                    let n = layer + c1 * stride[1] + c2 * stride[2];
                    f(n..n + 1);
                }
            }
        }
        1 => {
            for c2 in 0..dims[2] {
                let n = layer * stride[1] + c2 * stride[2];
                f(n..n + dims[0]);
            }
        }
        _ => {
            for c1 in 0..dims[1] {
                let n = layer * stride[2] + c1 * stride[1];
                f(n..n + dims[0]);
            }
        }
    }
}

/// The patch next to `patch` on `side` of `axis`, if any (wrapping for
/// periodic boundaries).
fn neighbour(
    level: &Level,
    bcs: &BoundaryConditions,
    patch: &Patch,
    axis: usize,
    side: usize,
) -> Option<usize> {
    let mut idx = patch.index;
    let n = level.layout[axis];
    if side == 0 {
        if idx[axis] == 0 {
            if *bcs.get(Face::of(axis, 0)) != FaceBc::Periodic {
                return None;
            }
            idx[axis] = n - 1;
        } else {
            idx[axis] -= 1;
        }
    } else if idx[axis] + 1 == n {
        if *bcs.get(Face::of(axis, 1)) != FaceBc::Periodic {
            return None;
        }
        idx[axis] = 0;
    } else {
        idx[axis] += 1;
    }
    Some(level.patch_id(idx))
}

/// What packing reads: the level, its fields and their boundary conditions.
struct Source<'a> {
    level: &'a Level,
    set: &'a FieldSet,
    bcs: &'a BoundaryConditions,
    fields: &'a [PatchFields],
}

/// Packs the values for the ghost layers on `side` of `axis` of patch `id`.
fn pack(out: &mut Vec<f64>, src: &Source, id: usize, axis: usize, side: usize) {
    let Source {
        level,
        set,
        bcs,
        fields,
    } = *src;
    out.clear();
    let patch = &level.patches[id];
    let g = patch.ghost[axis];
    let size = patch.size[axis];
    if let Some(q) = neighbour(level, bcs, patch, axis, side) {
        let from = &fields[q];
        let qsize = level.patches[q].size[axis];
        for values in &from.data {
            for a in 0..g {
                // Ghost a on the low side is the neighbour's interior layer
                // qsize + a (its top g layers); on the high side its first g.
                let layer = if side == 0 { qsize + a } else { g + a };
                for_each_run(from.dims, axis, layer, |r| {
                    out.extend_from_slice(&values[r])
                });
            }
        }
        return;
    }
    let own = &fields[id];
    match bcs.get(Face::of(axis, side)) {
        FaceBc::Outflow => {
            let layer = if side == 0 { g } else { g + size - 1 };
            for values in &own.data {
                for _ in 0..g {
                    for_each_run(own.dims, axis, layer, |r| out.extend_from_slice(&values[r]));
                }
            }
        }
        FaceBc::Reflective => {
            for (values, kind) in own.data.iter().zip(&set.kinds) {
                let sign = if *kind == FieldKind::VectorComponent(axis) {
                    -1.0
                } else {
                    1.0
                };
                for a in 0..g {
                    // Local ghost layer a mirrors the interior layer at the
                    // same distance from the face.
                    let layer = if side == 0 {
                        2 * g - 1 - a
                    } else {
                        g + size - 1 - a
                    };
                    for_each_run(own.dims, axis, layer, |r| {
                        out.extend(values[r].iter().map(|v| sign * v))
                    });
                }
            }
        }
        FaceBc::Fixed(state) => {
            for &v in state {
                for _ in 0..g {
                    for_each_run(own.dims, axis, 0, |r| {
                        out.extend(std::iter::repeat_n(v, r.len()))
                    });
                }
            }
        }
        // A periodic face always has a neighbour (possibly itself).
        FaceBc::Periodic => unreachable!("periodic faces are resolved as neighbours"),
    }
}

/// Writes a packed buffer into the ghost layers on `side` of `axis`.
fn unpack(buf: &[f64], patch: &Patch, fields: &mut PatchFields, axis: usize, side: usize) {
    let g = patch.ghost[axis];
    let size = patch.size[axis];
    let dims = fields.dims;
    let mut pos = 0;
    for values in &mut fields.data {
        for a in 0..g {
            let layer = if side == 0 { a } else { g + size + a };
            for_each_run(dims, axis, layer, |r| {
                let len = r.len();
                values[r].copy_from_slice(&buf[pos..pos + len]);
                pos += len;
            });
        }
    }
    debug_assert_eq!(pos, buf.len(), "halo buffer matches the ghost layers");
}

impl HaloExchange for InProcessExchange {
    fn fill_axis(
        &mut self,
        level: &Level,
        set: &FieldSet,
        bcs: &BoundaryConditions,
        fields: &mut [PatchFields],
        axis: usize,
    ) {
        if !level.is_active(axis) {
            return;
        }
        self.buffers
            .resize_with(level.patches.len(), Default::default);
        let src = Source {
            level,
            set,
            bcs,
            fields,
        };
        self.buffers
            .par_iter_mut()
            .enumerate()
            .for_each(|(id, bufs)| {
                for (side, buf) in bufs.iter_mut().enumerate() {
                    pack(buf, &src, id, axis, side);
                }
            });
        fields
            .par_iter_mut()
            .zip(self.buffers.par_iter())
            .zip(level.patches.par_iter())
            .for_each(|((f, bufs), patch)| {
                for (side, buf) in bufs.iter().enumerate() {
                    unpack(buf, patch, f, axis, side);
                }
            });
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn set() -> FieldSet {
        FieldSet {
            names: vec!["a", "u"],
            kinds: vec![FieldKind::Scalar, FieldKind::VectorComponent(0)],
        }
    }

    /// Fills interior cells with f(global index) and ghosts with NaN.
    fn filled(level: &Level) -> Vec<PatchFields> {
        level
            .patches
            .iter()
            .map(|p| {
                let mut f = PatchFields::zeros(p, 2);
                let d = p.dims();
                for k in 0..d[2] {
                    for j in 0..d[1] {
                        for i in 0..d[0] {
                            let n = p.local_index([i, j, k]);
                            let interior = (0..3).all(|a| {
                                let l = [i, j, k][a];
                                l >= p.ghost[a] && l < p.ghost[a] + p.size[a]
                            });
                            let gi: [i64; 3] = std::array::from_fn(|a| {
                                [i, j, k][a] as i64 + p.lo[a] as i64 - p.ghost[a] as i64
                            });
                            let v = (gi[0] + 100 * gi[1] + 10000 * gi[2]) as f64;
                            f.data[0][n] = if interior { v } else { f64::NAN };
                            f.data[1][n] = if interior { v + 0.5 } else { f64::NAN };
                        }
                    }
                }
                f
            })
            .collect()
    }

    fn value(
        level: &Level,
        fields: &[PatchFields],
        pid: usize,
        l: [usize; 3],
        field: usize,
    ) -> f64 {
        fields[pid].data[field][level.patches[pid].local_index(l)]
    }

    #[test]
    fn neighbour_ghosts_copy_the_neighbours_interior() {
        let level = Level::new([0.0; 3], [1.0; 3], [8, 6, 1], [2, 2, 1], 2).unwrap();
        let bcs = BoundaryConditions::uniform(FaceBc::Outflow);
        let mut fields = filled(&level);
        InProcessExchange::new().fill_all(&level, &set(), &bcs, &mut fields);
        // Patch 3 (upper right) ghost at local (0, 0) is global (2, 1).
        assert_eq!(value(&level, &fields, 3, [0, 0, 0], 0), (2 + 100) as f64);
        // Every ghost is filled, corners included.
        for f in &fields {
            assert!(f.data.iter().flatten().all(|v| v.is_finite()));
        }
    }

    #[test]
    fn reflective_mirrors_and_negates_the_normal_component() {
        let level = Level::new([0.0; 3], [1.0; 3], [6, 1, 1], [1, 1, 1], 3).unwrap();
        let bcs = BoundaryConditions::uniform(FaceBc::Reflective);
        let mut fields = filled(&level);
        InProcessExchange::new().fill_all(&level, &set(), &bcs, &mut fields);
        // Low side: ghost local 2 mirrors interior local 3 (global 0).
        assert_eq!(value(&level, &fields, 0, [2, 0, 0], 0), 0.0);
        assert_eq!(value(&level, &fields, 0, [0, 0, 0], 0), 2.0);
        assert_eq!(value(&level, &fields, 0, [0, 0, 0], 1), -2.5);
        // High side: ghost local 9 mirrors global 5; local 11 mirrors global 3.
        assert_eq!(value(&level, &fields, 0, [9, 0, 0], 0), 5.0);
        assert_eq!(value(&level, &fields, 0, [11, 0, 0], 1), -3.5);
    }

    #[test]
    fn outflow_periodic_and_fixed_ghosts() {
        let level = Level::new([0.0; 3], [1.0; 3], [6, 1, 1], [2, 1, 1], 3).unwrap();
        let mut bcs = BoundaryConditions::uniform(FaceBc::Periodic);
        let mut fields = filled(&level);
        InProcessExchange::new().fill_all(&level, &set(), &bcs, &mut fields);
        // Patch 0's low ghosts wrap to globals 3, 4, 5.
        assert_eq!(value(&level, &fields, 0, [0, 0, 0], 0), 3.0);
        assert_eq!(value(&level, &fields, 1, [8, 0, 0], 0), 2.0);

        bcs.faces[0] = FaceBc::Fixed(vec![7.0, 8.0]);
        bcs.faces[1] = FaceBc::Outflow;
        let mut fields = filled(&level);
        InProcessExchange::new().fill_all(&level, &set(), &bcs, &mut fields);
        assert_eq!(value(&level, &fields, 0, [1, 0, 0], 1), 8.0);
        assert_eq!(value(&level, &fields, 1, [8, 0, 0], 0), 5.0);
    }

    #[test]
    fn mismatched_periodic_faces_are_rejected() {
        let mut bcs = BoundaryConditions::uniform(FaceBc::Outflow);
        bcs.faces[2] = FaceBc::Periodic;
        assert!(bcs.validate(2).unwrap_err().contains("y_high"));
    }

    proptest::proptest! {
        #![proptest_config(proptest::prelude::ProptestConfig::with_cases(64))]

        /// With periodic faces every ghost cell, corners included, holds the
        /// interior value of the cell it stands for, for any patch split.
        #[test]
        fn periodic_ghosts_hold_the_wrapped_interior_value(
            nx in 2usize..12, ny in 1usize..9, nz in 1usize..5,
            px in 1usize..4, py in 1usize..3, pz in 1usize..3, g in 1usize..3,
        ) {
            let cells = [nx, ny, nz];
            let layout = [px.min(nx / g), py.min((ny / g).max(1)), pz.min((nz / g).max(1))];
            proptest::prop_assume!(layout.iter().all(|&l| l >= 1));
            let Ok(level) = Level::new([0.0; 3], [1.0; 3], cells, layout, g) else {
                return Ok(());
            };
            let mut fields = filled(&level);
            let bcs = BoundaryConditions::uniform(FaceBc::Periodic);
            InProcessExchange::new().fill_all(&level, &set(), &bcs, &mut fields);
            for (pid, p) in level.patches.iter().enumerate() {
                let d = p.dims();
                for k in 0..d[2] {
                    for j in 0..d[1] {
                        for i in 0..d[0] {
                            let gi: [i64; 3] = std::array::from_fn(|a| {
                                let x = [i, j, k][a] as i64 + p.lo[a] as i64 - p.ghost[a] as i64;
                                x.rem_euclid(cells[a] as i64)
                            });
                            let want = (gi[0] + 100 * gi[1] + 10000 * gi[2]) as f64;
                            proptest::prop_assert_eq!(value(&level, &fields, pid, [i, j, k], 0), want);
                        }
                    }
                }
            }
        }
    }
}
