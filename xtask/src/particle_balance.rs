//! MPI-BALANCE: how unevenly the particles of the particle pipelines'
//! cases would fall on ranks that own equal slabs of cells, and how even
//! a cut that balances the particles instead can make them
//! (docs/cluster.md, "Scaling").
//!
//! Each scenario is built as shipped and its particles' initial positions
//! are binned by cell plane along the axis with the most cells. For P
//! ranks, two splits into contiguous runs of whole planes are compared:
//!
//! - **equal cells**: the split the grid pipelines use today (the first
//!   `planes mod P` ranks take one plane more);
//! - **equal particles**: the cut after the plane where the running
//!   particle count first reaches k/P of the total, k = 1 … P − 1 (each
//!   rank keeps at least one plane).
//!
//! The imbalance is the most particles a rank holds over the mean; a step
//! whose cost is the particles' runs at the pace of that rank.

use std::fmt::Write as _;

use anyhow::{anyhow, Result};
use brisance::compose::{build::build_solver, load_file};

use crate::{workspace_root, Report};

/// The cases: (pipeline, config).
const CASES: [(&str, &str); 3] = [
    ("ICE–MPM (3D)", "configs/cylinder_icempm.ron"),
    ("ICE–MPM (r, z)", "configs/cylinder_rz.ron"),
    ("FDM–MPM bridge (3D)", "configs/slab_4kg.ron"),
];

/// Rank counts.
const RANKS: [usize; 5] = [2, 4, 8, 16, 64];

/// Contiguous runs of `planes` planes for `ranks` ranks, the first
/// `planes mod ranks` one plane longer (the split the grid pipelines make
/// of their patches): the first plane of each rank, then `planes`.
fn equal_cells(planes: usize, ranks: usize) -> Vec<usize> {
    brisance::grid::comm::equal_runs(planes, ranks)
}

/// Runs of whole planes cut where the running count of `per_plane` first
/// reaches k/`ranks` of the total: cut k is the first plane boundary c
/// with Σ_{p<c} n_p ≥ k·total/ranks, at least one plane past cut k − 1
/// and leaving a plane for each rank still to come.
fn equal_particles(per_plane: &[usize], ranks: usize) -> Vec<usize> {
    let planes = per_plane.len();
    let mut prefix = vec![0usize; planes + 1];
    for (p, &n) in per_plane.iter().enumerate() {
        prefix[p + 1] = prefix[p] + n;
    }
    let total = prefix[planes];
    let mut starts = vec![0];
    for k in 1..ranks {
        let first = prefix.partition_point(|&c| c * ranks < k * total);
        let cut = first.max(starts[k - 1] + 1).min(planes - (ranks - k));
        starts.push(cut);
    }
    starts.push(planes);
    starts
}

/// The most particles on one rank over the mean, and the ranks with none.
fn imbalance(per_plane: &[usize], starts: &[usize]) -> (f64, usize) {
    let counts: Vec<usize> = starts
        .windows(2)
        .map(|w| per_plane[w[0]..w[1]].iter().sum())
        .collect();
    let total: usize = counts.iter().sum();
    let mean = total as f64 / counts.len() as f64;
    let most = counts.iter().copied().max().unwrap_or(0) as f64;
    (most / mean, counts.iter().filter(|&&c| c == 0).count())
}

/// A case's particles counted per cell plane along each axis, and the
/// axis with the most cells (the one a slab split takes).
struct Binned {
    axis: usize,
    per_plane: [Vec<usize>; 3],
}

fn bin(config: &str) -> Result<Binned> {
    let path = workspace_root().join(config);
    let loaded = load_file(&path, &[]).map_err(|e| anyhow!("{config}: {e}"))?;
    let d = &loaded.scenario.domain;
    let axis = (0..3).max_by_key(|&a| d.cells[a]).unwrap_or(0);
    let solver = build_solver(&loaded.scenario).map_err(|e| anyhow!("{config}: {e}"))?;
    let particles = solver
        .particle_data()
        .ok_or_else(|| anyhow!("{config}: no particles"))?;
    let per_plane = std::array::from_fn(|a| {
        let planes = d.cells[a];
        let (lo, hi) = (d.lower[a], d.upper[a]);
        let mut counts = vec![0usize; planes];
        for x in &particles.positions {
            let f = ((x[a] - lo) / (hi - lo) * planes as f64).floor();
            counts[(f.max(0.0) as usize).min(planes - 1)] += 1;
        }
        counts
    });
    Ok(Binned { axis, per_plane })
}

/// The axis along which the particles occupy the most planes.
fn widest(b: &Binned) -> usize {
    (0..3)
        .max_by_key(|&a| b.per_plane[a].iter().filter(|&&n| n > 0).count())
        .unwrap_or(b.axis)
}

pub(crate) fn particle_balance(report: &mut Report) -> Result<()> {
    println!("MPI-BALANCE: particles per rank on slabs of equal cells and of equal particles");
    let md = &mut report.md;
    let _ = writeln!(
        md,
        "## MPI-BALANCE — particles per rank on slabs of whole cell planes\n\n\
         Each scenario as shipped, its particles at t = 0 binned by cell plane along the axis \
         with the most cells; P ranks own contiguous runs of planes, split either into equal \
         numbers of planes (as the grid pipelines split today) or where the running particle \
         count reaches k/P of the total. The figure is the most particles on one rank over the \
         mean (1 is even; a step paced by its particles runs that much slower than an even \
         split), with the number of ranks that hold none in brackets. Where the particles \
         occupy more planes along another axis, the particle cut along that axis is shown too. `cargo xtask validate \
         --only mpi-balance` repeats it.\n"
    );
    let header: String = RANKS.iter().map(|p| format!(" P = {p} |")).collect();
    let rule: String = RANKS.iter().map(|_| "---:|").collect();
    let _ = writeln!(
        md,
        "| case | split axis (planes) | split |{header}\n|---|---|---|{rule}"
    );
    for (pipeline, config) in CASES {
        let b = bin(config)?;
        let best = widest(&b);
        let mut splits = vec![("equal cells", b.axis), ("equal particles", b.axis)];
        if best != b.axis {
            splits.push(("equal particles", best));
        }
        for (split, axis) in splits {
            let per_plane = &b.per_plane[axis];
            let planes = per_plane.len();
            let total: usize = per_plane.iter().sum();
            let occupied = per_plane.iter().filter(|&&n| n > 0).count();
            let mut cells = String::new();
            for &p in &RANKS {
                if p > planes {
                    cells.push_str(" — |");
                    continue;
                }
                let starts = if split == "equal cells" {
                    equal_cells(planes, p)
                } else {
                    equal_particles(per_plane, p)
                };
                let (ratio, empty) = imbalance(per_plane, &starts);
                println!(
                    "  {pipeline}, {split} along {}: P = {p}: {ratio:.2} ({empty} empty)",
                    ["x", "y", "z"][axis]
                );
                if empty > 0 {
                    let _ = write!(cells, " {ratio:.2} ({empty}) |");
                } else {
                    let _ = write!(cells, " {ratio:.2} |");
                }
            }
            let _ = writeln!(
                md,
                "| {pipeline}, `{config}`, {total} particles | {} ({planes}, {occupied} holding particles) | {split} |{cells}",
                ["x", "y", "z"][axis]
            );
        }
    }
    let _ = writeln!(md);
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn equal_cell_runs_differ_by_at_most_one_plane() {
        assert_eq!(equal_cells(10, 4), vec![0, 3, 6, 8, 10]);
        assert_eq!(equal_cells(4, 4), vec![0, 1, 2, 3, 4]);
    }

    #[test]
    fn particle_cuts_follow_the_running_count() {
        // 12 particles: 6 per rank for 2, cut after plane 1 (running 6).
        let per_plane = [0, 6, 0, 0, 6, 0];
        assert_eq!(equal_particles(&per_plane, 2), vec![0, 2, 6]);
        assert_eq!(imbalance(&per_plane, &[0, 2, 6]), (1.0, 0));
        // The same planes cut evenly: 6 | 6, by luck even too.
        assert_eq!(imbalance(&per_plane, &equal_cells(6, 2)), (1.0, 0));
        // Four ranks on two occupied planes: two hold all, two none.
        let s = equal_particles(&per_plane, 4);
        assert_eq!(s.len(), 5);
        let (ratio, empty) = imbalance(&per_plane, &s);
        assert_eq!(ratio, 2.0);
        assert_eq!(empty, 2);
    }

    #[test]
    fn every_rank_keeps_a_plane_when_the_particles_sit_at_one_end() {
        let per_plane = [0, 0, 0, 10];
        let s = equal_particles(&per_plane, 4);
        assert_eq!(s, vec![0, 1, 2, 3, 4]);
    }
}
