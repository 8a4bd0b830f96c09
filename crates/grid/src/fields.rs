//! Fields stored structure-of-arrays: one contiguous `Vec<f64>` per field per
//! patch, x fastest, ghost layers included.

use crate::level::Patch;

/// How a field transforms under a mirror (reflective boundary).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FieldKind {
    /// A scalar: copied by a mirror.
    Scalar,
    /// Component `d` of a vector (velocity, momentum): negated by a mirror
    /// whose normal is along `d`.
    VectorComponent(usize),
}

/// Names and kinds of the fields a solver stores.
#[derive(Debug, Clone, PartialEq)]
pub struct FieldSet {
    /// Field names, snake_case.
    pub names: Vec<&'static str>,
    /// How each field behaves under a mirror.
    pub kinds: Vec<FieldKind>,
}

impl FieldSet {
    /// Number of fields.
    pub fn len(&self) -> usize {
        self.names.len()
    }

    /// Whether the set is empty.
    pub fn is_empty(&self) -> bool {
        self.names.is_empty()
    }
}

/// The cell-centred fields of one patch.
#[derive(Debug, Clone, PartialEq)]
pub struct PatchFields {
    /// Allocated cells per direction (interior plus ghosts).
    pub dims: [usize; 3],
    /// One array per field, each `dims[0]·dims[1]·dims[2]` long.
    pub data: Vec<Vec<f64>>,
}

impl PatchFields {
    /// Zeroed storage for `n_fields` fields on `patch`.
    pub fn zeros(patch: &Patch, n_fields: usize) -> Self {
        let n = patch.allocated_cells();
        Self {
            dims: patch.dims(),
            data: (0..n_fields).map(|_| vec![0.0; n]).collect(),
        }
    }

    /// `n_fields` fields on `patch` with no storage: the place of a patch
    /// that another rank owns (its arrays are empty; see
    /// [`PatchFields::is_stored`]).
    pub fn unstored(patch: &Patch, n_fields: usize) -> Self {
        Self {
            dims: patch.dims(),
            data: vec![Vec::new(); n_fields],
        }
    }

    /// Whether the arrays hold the patch's values (false for a patch of
    /// another rank, [`PatchFields::unstored`]).
    pub fn is_stored(&self) -> bool {
        let n: usize = self.dims.iter().product();
        self.data.iter().all(|v| v.len() == n)
    }

    /// Frees the arrays (keeping their number and the dims): the patch
    /// now belongs to another rank.
    pub fn release(&mut self) {
        for v in &mut self.data {
            *v = Vec::new();
        }
    }
}

/// Node-centred storage layout for a patch (the MPM background grid): a
/// patch of `size` cells in an active direction has `size + 1` nodes plus
/// `ghost` ghost nodes on each side; a direction with one cell has a single
/// node layer.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct NodeLayout {
    /// Allocated nodes per direction.
    pub dims: [usize; 3],
    /// Ghost node layers per side per direction.
    pub ghost: [usize; 3],
}

impl NodeLayout {
    /// The node layout that matches a cell patch.
    pub fn for_patch(patch: &Patch, active: [bool; 3]) -> Self {
        let dims = std::array::from_fn(|d| {
            if active[d] {
                patch.size[d] + 1 + 2 * patch.ghost[d]
            } else {
                1
            }
        });
        Self {
            dims,
            ghost: patch.ghost,
        }
    }

    /// Number of allocated nodes.
    pub fn len(&self) -> usize {
        self.dims.iter().product()
    }

    /// Whether the layout holds no node.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Storage index of local node (i, j, k).
    #[inline]
    pub fn index(&self, n: [usize; 3]) -> usize {
        n[0] + self.dims[0] * (n[1] + self.dims[1] * n[2])
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Level;

    #[test]
    fn node_layout_has_one_more_node_than_cells_in_active_directions() {
        let level = Level::new([0.0; 3], [1.0; 3], [8, 4, 1], [2, 1, 1], 1).unwrap();
        let p = &level.patches[1];
        let nodes = NodeLayout::for_patch(p, [true, true, false]);
        assert_eq!(nodes.dims, [4 + 1 + 2, 4 + 1 + 2, 1]);
        assert_eq!(nodes.index([1, 2, 0]), 1 + 7 * 2);
        let f = PatchFields::zeros(p, 5);
        assert_eq!(f.data.len(), 5);
        assert_eq!(f.data[0].len(), 6 * 6);
    }
}
