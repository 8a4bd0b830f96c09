//! Families (seed 004 Fig. 1: the nodes inside the horizon δ of a node) and
//! the per-bond quadrature weights.
//!
//! Families are found once, in the reference configuration, with a cell
//! list of cell size δ + h/2 (O(N)), and stored in compressed rows: row i
//! is `neighbours[offsets[i]..offsets[i + 1]]`, ascending. A bond joins
//! two nodes of the same body only; different bodies (and a body's
//! fragments once their bonds are broken) interact by short-range forces.
//! Each bond appears in both its nodes' rows, so the force loop can run
//! over nodes without atomics.
//!
//! **Partial-volume correction.** A node near the edge of the horizon is
//! only partly inside it. Brisance weights neighbour j's volume by
//!
//! ```text
//! β(r) = 1                        r ≤ δ − h/2
//!      = (δ + h/2 − r) / h        δ − h/2 < r < δ + h/2
//!      = 0                        r ≥ δ + h/2
//! ```
//!
//! the linear partial-volume rule of Silling & Askari (2005, seed 004
//! ref 3) as analysed by Seleson (2014, "Improved one- and two-point
//! quadrature for peridynamic models", CMAME 282, 184–217). It removes the
//! arbitrariness of which lattice nodes at exactly r = δ count (β = ½
//! there), and in 1D with δ = 3h it makes the discrete long-wave modulus
//! equal to the continuum one exactly.

use crate::cell_list::CellList;
use rayon::prelude::*;

/// Families in compressed-row form.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Families {
    /// Row starts, one per node plus the end.
    pub offsets: Vec<u32>,
    /// Neighbour indices, ascending within each row.
    pub neighbours: Vec<u32>,
}

impl Families {
    /// Number of nodes.
    pub fn node_count(&self) -> usize {
        self.offsets.len().saturating_sub(1)
    }

    /// Number of (directed) bonds: each bond counted once per node.
    pub fn bond_count(&self) -> usize {
        self.neighbours.len()
    }

    /// The bond range of node `i`.
    #[inline]
    pub fn row(&self, i: usize) -> std::ops::Range<usize> {
        self.offsets[i] as usize..self.offsets[i + 1] as usize
    }

    /// The position of bond (i, j) in the rows, if i and j are bonded.
    #[inline]
    pub fn find(&self, i: usize, j: usize) -> Option<usize> {
        let row = self.row(i);
        let start = row.start;
        self.neighbours[row]
            .binary_search(&(j as u32))
            .ok()
            .map(|k| start + k)
    }
}

/// Partial-volume weight β(r) of a neighbour at reference distance `r`
/// for horizon `horizon` and spacing `spacing`.
#[inline]
pub fn partial_volume(r: f64, horizon: f64, spacing: f64) -> f64 {
    ((horizon + 0.5 * spacing - r) / spacing).clamp(0.0, 1.0)
}

/// Builds the families of nodes at `positions`: j is in i's family when
/// they belong to the same body and β(|x_j − x_i|) > 0.
pub fn build_families(
    positions: &[[f64; 3]],
    body: &[u32],
    horizon: f64,
    spacing: f64,
) -> Families {
    let n = positions.len();
    let cutoff = horizon + 0.5 * spacing;
    let mut cells = CellList::default();
    cells.rebuild(n, cutoff, |i| positions[i]);
    let rows: Vec<Vec<u32>> = (0..n)
        .into_par_iter()
        .map(|i| {
            let x = positions[i];
            let mut row = Vec::new();
            cells.for_each_candidate(x, |j| {
                if j == i || body[j] != body[i] {
                    return;
                }
                let d = positions[j];
                let r =
                    ((d[0] - x[0]).powi(2) + (d[1] - x[1]).powi(2) + (d[2] - x[2]).powi(2)).sqrt();
                if partial_volume(r, horizon, spacing) > 0.0 {
                    row.push(j as u32);
                }
            });
            row.sort_unstable();
            row
        })
        .collect();
    let mut offsets = Vec::with_capacity(n + 1);
    offsets.push(0u32);
    let total: usize = rows.iter().map(Vec::len).sum();
    let mut neighbours = Vec::with_capacity(total);
    for row in rows {
        neighbours.extend_from_slice(&row);
        offsets.push(neighbours.len() as u32);
    }
    Families {
        offsets,
        neighbours,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cube(n: usize, h: f64) -> Vec<[f64; 3]> {
        let mut x = Vec::new();
        for k in 0..n {
            for j in 0..n {
                for i in 0..n {
                    x.push([i as f64 * h, j as f64 * h, k as f64 * h]);
                }
            }
        }
        x
    }

    #[test]
    fn partial_volume_is_linear_across_the_horizon_edge() {
        assert_eq!(partial_volume(2.4, 3.0, 1.0), 1.0);
        assert_eq!(partial_volume(3.0, 3.0, 1.0), 0.5);
        assert!((partial_volume(3.25, 3.0, 1.0) - 0.25).abs() < 1e-15);
        assert_eq!(partial_volume(3.5, 3.0, 1.0), 0.0);
    }

    #[test]
    fn interior_family_of_a_cubic_lattice_with_delta_3h_has_178_members() {
        // With β > 0 the family is every lattice offset with
        // 0 < |n|² < 12.25, i.e. |n|² ≤ 12: 178 nodes (122 with |n| ≤ 3).
        let h = 0.1;
        let x = cube(9, h);
        let f = build_families(&x, &vec![0; x.len()], 3.0 * h, h);
        let centre = 4 + 9 * (4 + 9 * 4);
        let mut want = 0;
        for a in -3i32..=3 {
            for b in -3i32..=3 {
                for c in -3i32..=3 {
                    let n2 = a * a + b * b + c * c;
                    if n2 > 0 && n2 <= 12 {
                        want += 1;
                    }
                }
            }
        }
        assert_eq!(f.row(centre).len(), want);
        assert_eq!(want, 178);
        // Symmetric: j in row i ⇔ i in row j.
        for i in 0..x.len() {
            for &j in &f.neighbours[f.row(i)] {
                assert!(f.find(j as usize, i).is_some());
            }
        }
    }

    #[test]
    fn bodies_do_not_bond() {
        let x = vec![[0.0; 3], [1.0, 0.0, 0.0], [2.0, 0.0, 0.0]];
        let f = build_families(&x, &[0, 0, 1], 1.5, 1.0);
        assert_eq!(f.neighbours, vec![1, 0]);
        assert_eq!(f.offsets, vec![0, 1, 2, 2]);
    }
}
