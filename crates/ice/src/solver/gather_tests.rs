use super::*;

/// The row-wise gather hands every global cell its own patch and
/// local index, whatever the patch split (patches of unequal sizes
/// along x included) and on 1 or 2 threads.
#[test]
fn par_gather_maps_every_cell_to_its_own_patch_cell() {
    for layout in [[1, 1, 1], [3, 2, 1], [2, 1, 2], [3, 2, 2]] {
        let cells = [7, 5, 4];
        // 7 cells along x in 3 patches: runs of unequal length.
        let level = Level::new([0.0; 3], [1.0; 3], cells, layout, 2).unwrap();
        let count = level.geometry.cell_count();
        for threads in [1, 2] {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            let mut out = vec![usize::MAX; count];
            pool.install(|| {
                par_gather(&level, &mut out, |pid, c| {
                    level
                        .geometry
                        .linear_index(global_of(&level.patches[pid], c))
                })
            });
            let want: Vec<usize> = (0..count).collect();
            assert_eq!(out, want, "layout {layout:?}, {threads} threads");
        }
    }
}
