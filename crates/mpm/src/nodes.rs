//! Global node indexing of the MPM background grid.
//!
//! The background grid is the node-centred view of a level
//! ([`brisance_grid::NodeLayout`]): along an active direction d (more than
//! one cell), global node i sits at `x_min[d] + i·Δx[d]` and global cell i
//! lies between nodes i and i + 1, so a level of n cells has nodes
//! 0 ..= n. Shape functions wider than one cell (GIMP, quadratic B-spline)
//! reach node −1 or n + 1 for particles within 1.5 cells of the domain
//! boundary; those are ghost nodes, which is why such shape functions need
//! at least one ghost node layer. Along an inactive direction (one cell) the
//! grid has a single node layer, index 0.
//!
//! Node indices are signed (`isize`) for that reason; a cell index is
//! unsigned and never used as a node index.

use brisance_grid::{NodeLayout, Patch};

/// Storage index in `layout` (the node layout of `patch`) of global node
/// `node`, or `None` if that node is not allocated on the patch (neither an
/// interior nor a ghost node).
#[inline]
pub fn patch_node_index(patch: &Patch, layout: &NodeLayout, node: [isize; 3]) -> Option<usize> {
    let mut local = [0usize; 3];
    for d in 0..3 {
        let l = node[d] - patch.lo[d] as isize + layout.ghost[d] as isize;
        if l < 0 || l >= layout.dims[d] as isize {
            return None;
        }
        local[d] = l as usize;
    }
    Some(layout.index(local))
}

#[cfg(test)]
mod tests {
    use super::*;
    use brisance_grid::Level;

    #[test]
    fn patch_node_index_maps_lowest_interior_node_past_the_ghosts() {
        let level = Level::new([0.0; 3], [1.0; 3], [8, 4, 1], [2, 1, 1], 1).unwrap();
        let p = &level.patches[1];
        let layout = NodeLayout::for_patch(p, [true, true, false]);
        // Patch 1 starts at cell 4, so its first interior node is global node
        // 4, stored after one ghost layer.
        assert_eq!(
            patch_node_index(p, &layout, [4, 0, 0]),
            Some(layout.index([1, 1, 0]))
        );
        assert_eq!(
            patch_node_index(p, &layout, [3, -1, 0]),
            Some(layout.index([0, 0, 0]))
        );
        assert_eq!(
            patch_node_index(p, &layout, [9, 5, 0]),
            Some(layout.index([6, 6, 0]))
        );
        assert_eq!(patch_node_index(p, &layout, [2, 0, 0]), None);
        assert_eq!(patch_node_index(p, &layout, [10, 0, 0]), None);
        assert_eq!(patch_node_index(p, &layout, [4, 0, 1]), None);
    }
}
