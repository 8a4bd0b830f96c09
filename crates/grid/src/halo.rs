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
//!
//! With the patches shared among ranks ([`InProcessExchange::distributed`],
//! [`crate::comm`]) a rank packs and unpacks only for the patches it owns;
//! a ghost layer whose neighbour lives on another rank is packed there, by
//! the same code, and arrives as a message.

use std::sync::Arc;

use rayon::prelude::*;

use crate::comm::Communicator;
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

/// The exchange of patches that are entries of one slice: all of them in
/// this process, or ([`Self::distributed`]) those of one rank, the others'
/// entries left unused.
#[derive(Debug, Default, Clone)]
pub struct InProcessExchange {
    /// The ranks the patches are shared among, when there are several.
    ranks: Option<Ranks>,
    buffers: Vec<[Vec<f64>; 2]>,
    /// Per patch and side: whether its last pack held back an inward flow
    /// on an outflow-only face ([`BLOCKED_FLOW_FRACTION`]).
    blocked_sides: Vec<[bool; 2]>,
    /// Per domain face ([`Face`] order): whether an outflow-only face has
    /// held back an inward flow since the exchange was made.
    blocked: [bool; 6],
}

/// The patches' owners and the buffers this rank packs for the others.
#[derive(Debug, Clone)]
struct Ranks {
    comm: Arc<dyn Communicator>,
    /// Owner rank of every patch.
    owner: Vec<usize>,
    /// Ghost values packed here for another rank's patch: (patch, side,
    /// values); kept between calls.
    outgoing: Vec<(usize, usize, Vec<f64>)>,
}

/// The tag of the message that fills the ghost layers on `side` of patch
/// `patch` (unique within one `fill_axis`; messages of successive calls
/// between two ranks arrive in order).
fn tag(patch: usize, side: usize) -> i32 {
    i32::try_from(2 * patch + side).expect("patch count fits an MPI tag")
}

impl InProcessExchange {
    /// An exchange with no buffers yet (they grow on first use).
    pub fn new() -> Self {
        Self::default()
    }

    /// The exchange of this rank of `comm`, patch `p` being owned by rank
    /// `owner[p]` ([`crate::comm::patch_owners`]): only the owned patches'
    /// ghosts are filled; the other patches' fields are neither read nor
    /// written, except where an owned patch's ghosts need them, and those
    /// values come from their owner.
    pub fn distributed(comm: Arc<dyn Communicator>, owner: Vec<usize>) -> Self {
        Self {
            ranks: Some(Ranks {
                comm,
                owner,
                outgoing: Vec::new(),
            }),
            ..Self::default()
        }
    }

    /// Bytes of the pack buffers this exchange holds (they grow on first
    /// use, so this counts what the exchanges so far needed).
    pub fn bytes(&self) -> usize {
        let values: usize = self
            .buffers
            .iter()
            .flat_map(|pair| pair.iter().map(Vec::len))
            .sum::<usize>()
            + self
                .ranks
                .as_ref()
                .map_or(0, |r| r.outgoing.iter().map(|(_, _, v)| v.len()).sum());
        values * std::mem::size_of::<f64>()
    }

    /// The domain faces ([`Face`] order) where a [`FaceBc::OutflowOnly`]
    /// condition has held back an inward flow since the exchange was
    /// made: a ghost whose normal flow it zeroed carried a kinetic energy
    /// of that flow above [`BLOCKED_FLOW_FRACTION`] of its total energy.
    ///
    /// Across ranks this is a collective call (every rank calls it).
    pub fn blocked_inflow(&self) -> [bool; 6] {
        match &self.ranks {
            None => self.blocked,
            Some(r) => {
                let mut any = self.blocked.map(u64::from);
                r.comm.sum(&mut any);
                any.map(|n| n > 0)
            }
        }
    }
}

/// The share of a ghost's total energy E the kinetic energy of its normal
/// flow (ρu_n)²/(2ρ) must exceed for an outflow-only face that zeroes it to
/// count as holding back an inflow ([`InProcessExchange::blocked_inflow`]):
/// a Mach number of about 2·10⁻³ in air at rest, so that round-off drift
/// of a gas at rest is not reported.
pub const BLOCKED_FLOW_FRACTION: f64 = 1e-6;

/// The diode of [`FaceBc::OutflowOnly`] on packed ghost values: `buf`
/// holds the fields one after another, `block` values each (ghost layers
/// of one plane of cells); where the normal momentum (field `momentum`)
/// points into the domain (its sign times `inward` is positive), it is set
/// to zero and its kinetic energy (ρu_n)²/(2ρ) is taken from the total
/// energy (field `energy`), keeping the internal energy. Returns whether a
/// zeroed flow carried more than [`BLOCKED_FLOW_FRACTION`] of its ghost's
/// total energy.
pub fn close_inward_flow(
    buf: &mut [f64],
    block: usize,
    density: usize,
    momentum: usize,
    energy: usize,
    inward: f64,
) -> bool {
    let mut blocked = false;
    for q in 0..block {
        let m = buf[momentum * block + q];
        if m * inward > 0.0 {
            let rho = buf[density * block + q];
            let kinetic = 0.5 * m * m / rho;
            let e = &mut buf[energy * block + q];
            blocked |= kinetic > BLOCKED_FLOW_FRACTION * *e;
            *e -= kinetic;
            buf[momentum * block + q] = 0.0;
        }
    }
    blocked
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

/// Packs the values for the ghost layers on `side` of `axis` of patch `id`;
/// returns whether an outflow-only face held back an inward flow
/// ([`close_inward_flow`]).
fn pack(out: &mut Vec<f64>, src: &Source, id: usize, axis: usize, side: usize) -> bool {
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
        return false;
    }
    let own = &fields[id];
    match bcs.get(Face::of(axis, side)) {
        FaceBc::Outflow => pack_boundary_layer(out, own, axis, side, g, size),
        FaceBc::OutflowOnly { density, energy } => {
            pack_boundary_layer(out, own, axis, side, g, size);
            let normal = set
                .kinds
                .iter()
                .position(|k| *k == FieldKind::VectorComponent(axis));
            if let Some(momentum) = normal {
                let block = out.len() / own.data.len();
                let inward = if side == 0 { 1.0 } else { -1.0 };
                return close_inward_flow(out, block, *density, momentum, *energy, inward);
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
    false
}

/// Packs `g` copies of the boundary layer on `side` of `axis` (interior
/// size `size`) of every field of `own`: the zero-gradient ghosts.
fn pack_boundary_layer(
    out: &mut Vec<f64>,
    own: &PatchFields,
    axis: usize,
    side: usize,
    g: usize,
    size: usize,
) {
    let layer = if side == 0 { g } else { g + size - 1 };
    for values in &own.data {
        for _ in 0..g {
            for_each_run(own.dims, axis, layer, |r| out.extend_from_slice(&values[r]));
        }
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
        self.blocked_sides.resize(level.patches.len(), [false; 2]);
        if self.ranks.is_some() {
            self.fill_axis_distributed(level, set, bcs, fields, axis);
            return;
        }
        let src = Source {
            level,
            set,
            bcs,
            fields,
        };
        self.buffers
            .par_iter_mut()
            .zip(self.blocked_sides.par_iter_mut())
            .enumerate()
            .for_each(|(id, (bufs, blocked))| {
                for (side, buf) in bufs.iter_mut().enumerate() {
                    blocked[side] = pack(buf, &src, id, axis, side);
                }
            });
        Self::record_blocked(&mut self.blocked, &self.blocked_sides, axis);
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

impl InProcessExchange {
    /// Adds a pass's held-back inflows (`sides`, per patch) to the faces
    /// of `axis` in `blocked`.
    fn record_blocked(blocked: &mut [bool; 6], sides: &[[bool; 2]], axis: usize) {
        for b in sides {
            for (side, &held) in b.iter().enumerate() {
                blocked[Face::of(axis, side) as usize] |= held;
            }
        }
    }

    /// [`HaloExchange::fill_axis`] for the patches of this rank: pack the
    /// owned patches' ghosts that are boundary conditions or owned
    /// neighbours, and the other ranks' ghosts that an owned patch feeds;
    /// send and receive those; unpack the owned patches.
    fn fill_axis_distributed(
        &mut self,
        level: &Level,
        set: &FieldSet,
        bcs: &BoundaryConditions,
        fields: &mut [PatchFields],
        axis: usize,
    ) {
        let Some(ranks) = self.ranks.as_mut() else {
            return;
        };
        let me = ranks.comm.rank();
        let owner = &ranks.owner;
        let src = Source {
            level,
            set,
            bcs,
            fields,
        };
        let remote = |id: usize, side: usize| {
            neighbour(level, bcs, &level.patches[id], axis, side).filter(|&q| owner[q] != me)
        };
        self.buffers
            .par_iter_mut()
            .zip(self.blocked_sides.par_iter_mut())
            .enumerate()
            .for_each(|(id, (bufs, blocked))| {
                *blocked = [false; 2];
                if owner[id] != me {
                    return;
                }
                for (side, buf) in bufs.iter_mut().enumerate() {
                    if remote(id, side).is_none() {
                        blocked[side] = pack(buf, &src, id, axis, side);
                    }
                }
            });
        // What the other ranks' patches need from ours.
        let mut n_out = 0;
        for id in (0..level.patches.len()).filter(|&id| owner[id] != me) {
            for side in 0..2 {
                let feeds = neighbour(level, bcs, &level.patches[id], axis, side)
                    .is_some_and(|q| owner[q] == me);
                if feeds {
                    if ranks.outgoing.len() == n_out {
                        ranks.outgoing.push((id, side, Vec::new()));
                    }
                    let slot = &mut ranks.outgoing[n_out];
                    (slot.0, slot.1) = (id, side);
                    pack(&mut slot.2, &src, id, axis, side);
                    n_out += 1;
                }
            }
        }
        let sends: Vec<(usize, i32, &[f64])> = ranks.outgoing[..n_out]
            .iter()
            .map(|(p, side, values)| (owner[*p], tag(*p, *side), &values[..]))
            .collect();
        let mut receives: Vec<(usize, i32, &mut Vec<f64>)> = Vec::new();
        for (id, bufs) in self.buffers.iter_mut().enumerate() {
            if owner[id] != me {
                continue;
            }
            for (side, buf) in bufs.iter_mut().enumerate() {
                if let Some(q) = remote(id, side) {
                    receives.push((owner[q], tag(id, side), buf));
                }
            }
        }
        ranks.comm.exchange(&sends, &mut receives);
        drop(receives);
        Self::record_blocked(&mut self.blocked, &self.blocked_sides, axis);
        fields
            .par_iter_mut()
            .zip(self.buffers.par_iter())
            .zip(level.patches.par_iter())
            .enumerate()
            .for_each(|(id, ((f, bufs), patch))| {
                if owner[id] == me {
                    for (side, buf) in bufs.iter().enumerate() {
                        unpack(buf, patch, f, axis, side);
                    }
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

    /// The diode by hand: ρ = 2, ρu = 3 (inwards at x_low), ρv = 1,
    /// E = 10 in the low boundary cell gives ghosts ρu = 0, ρv = 1 and
    /// E = 10 − 3²/(2·2) = 7.75; ρu = 4 leaving through x_high is copied
    /// as is; ρu = −2 entering through x_high with ρ = 1, E = 5 gives
    /// E = 5 − 2 = 3. Only the faces that held back a flow are reported.
    #[test]
    fn outflow_only_ghosts_zero_an_inward_normal_flow_and_keep_the_internal_energy() {
        let set = FieldSet {
            names: vec!["rho", "mx", "my", "e"],
            kinds: vec![
                FieldKind::Scalar,
                FieldKind::VectorComponent(0),
                FieldKind::VectorComponent(1),
                FieldKind::Scalar,
            ],
        };
        let level = Level::new([0.0; 3], [1.0; 3], [4, 1, 1], [1, 1, 1], 2).unwrap();
        let bc = FaceBc::OutflowOnly {
            density: 0,
            energy: 3,
        };
        let bcs = BoundaryConditions::uniform(bc);
        assert_eq!(bcs.validate(4), Ok(()));
        let patch = &level.patches[0];
        let run = |low: [f64; 4], high: [f64; 4]| {
            let mut f = vec![PatchFields::zeros(patch, 4)];
            for i in 0..4 {
                let state = if i < 2 { low } else { high };
                let n = patch.local_index([2 + i, 0, 0]);
                for (k, v) in state.iter().enumerate() {
                    f[0].data[k][n] = *v;
                }
            }
            let mut ex = InProcessExchange::new();
            ex.fill_all(&level, &set, &bcs, &mut f);
            let ghost = |i: usize| -> [f64; 4] {
                let n = patch.local_index([i, 0, 0]);
                std::array::from_fn(|k| f[0].data[k][n])
            };
            (ghost(0), ghost(1), ghost(6), ghost(7), ex.blocked_inflow())
        };
        let (l0, l1, h0, h1, blocked) = run([2.0, 3.0, 1.0, 10.0], [1.0, 4.0, 0.5, 9.0]);
        assert_eq!(l0, [2.0, 0.0, 1.0, 7.75]);
        assert_eq!(l1, l0);
        assert_eq!(h0, [1.0, 4.0, 0.5, 9.0]);
        assert_eq!(h1, h0);
        assert_eq!(blocked, [true, false, false, false, false, false]);
        let (l0, _, h0, _, blocked) = run([2.0, -3.0, 1.0, 10.0], [1.0, -2.0, 0.0, 5.0]);
        assert_eq!(l0, [2.0, -3.0, 1.0, 10.0]);
        assert_eq!(h0, [1.0, 0.0, 0.0, 3.0]);
        assert_eq!(blocked, [false, true, false, false, false, false]);
        // A flow too slow to matter is zeroed but not reported.
        let (l0, _, _, _, blocked) = run([1.0, 1e-4, 0.0, 2.5e2], [1.0, 0.0, 0.0, 2.5e2]);
        assert_eq!(l0[1], 0.0);
        assert_eq!(blocked, [false; 6]);
    }

    #[test]
    fn outflow_only_needs_two_distinct_fields_in_range() {
        let bad = BoundaryConditions::uniform(FaceBc::OutflowOnly {
            density: 0,
            energy: 5,
        });
        assert!(bad.validate(5).unwrap_err().contains("x_low"));
        let same = BoundaryConditions::uniform(FaceBc::OutflowOnly {
            density: 1,
            energy: 1,
        });
        assert!(same.validate(5).is_err());
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
