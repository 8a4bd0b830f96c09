//! Families (seed 004 Fig. 1: the nodes inside the horizon δ of a node) and
//! the per-bond quadrature weights.
//!
//! Families are found once, in the reference configuration, with a cell
//! list of cell size δ + h/2 (O(N)), and stored in compressed rows: row i
//! is `neighbours[offsets[i]..offsets[i + 1]]`, ascending. A bond joins
//! two nodes of the same body only; different bodies (and a body's
//! fragments once their bonds are broken) interact by short-range forces.
//! Each bond appears in both its nodes' rows, so the force loop can run
//! over nodes without atomics. The one exception is the products'
//! families that take in the solid nodes of other bodies
//! (`crate::ProductsFamily::WithSolids`): those pairs sit in the products
//! node's row only, and the solid node gathers their reaction from a list
//! of its own (`crate::solver`, `docs/physics/pd/gas.md`).
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
    build_families_where(positions, horizon, spacing, |i, j| body[i] == body[j])
}

/// [`build_families`] with the rule of who joins whose family given:
/// j is in i's family when `joins(i, j)` and β(|x_j − x_i|) > 0. The rule
/// need not be symmetric (the products' families that take in the case,
/// `crate::ProductsFamily::WithSolids`, are one-sided).
pub fn build_families_where(
    positions: &[[f64; 3]],
    horizon: f64,
    spacing: f64,
    joins: impl Fn(usize, usize) -> bool + Sync,
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
                if j == i || !joins(i, j) {
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

/// The one-sided pairs of families that take in other bodies' nodes
/// (`crate::ProductsFamily::WithSolids`), seen from the side that does not
/// hold them: for each node j, the nodes i whose rows hold j while j's row
/// does not hold i, and the position k of j in row i. Row j is
/// `partner[offsets[j]..offsets[j + 1]]` (and `bond[..]` alike), ascending
/// in i, so a node sums its pairs in one fixed order. Empty (no offsets)
/// when there is no such pair.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct OneSidedPairs {
    /// Row starts, one per node plus the end; empty without pairs.
    pub offsets: Vec<u32>,
    /// The node whose family holds the row's node.
    pub partner: Vec<u32>,
    /// The bond's position in the partner's row of [`Families`].
    pub bond: Vec<u32>,
}

impl OneSidedPairs {
    /// The pairs of `families` whose row node satisfies `holder` and whose
    /// neighbour does not: with `holder` the products nodes, the solid
    /// nodes in products families.
    pub fn of(families: &Families, holder: impl Fn(usize) -> bool) -> Self {
        let n = families.node_count();
        let mut count = vec![0u32; n + 1];
        for i in (0..n).filter(|&i| holder(i)) {
            for &j in &families.neighbours[families.row(i)] {
                if !holder(j as usize) {
                    count[j as usize + 1] += 1;
                }
            }
        }
        if count.iter().all(|&c| c == 0) {
            return Self::default();
        }
        for j in 0..n {
            count[j + 1] += count[j];
        }
        let total = count[n] as usize;
        let mut next = count.clone();
        let (mut partner, mut bond) = (vec![0u32; total], vec![0u32; total]);
        for i in (0..n).filter(|&i| holder(i)) {
            for k in families.row(i) {
                let j = families.neighbours[k] as usize;
                if !holder(j) {
                    let at = next[j] as usize;
                    partner[at] = i as u32;
                    bond[at] = k as u32;
                    next[j] += 1;
                }
            }
        }
        Self {
            offsets: count,
            partner,
            bond,
        }
    }

    /// Whether there is no pair.
    pub fn is_empty(&self) -> bool {
        self.partner.is_empty()
    }

    /// The pair range of node `j` (empty without pairs).
    #[inline]
    pub fn row(&self, j: usize) -> std::ops::Range<usize> {
        if self.offsets.is_empty() {
            0..0
        } else {
            self.offsets[j] as usize..self.offsets[j + 1] as usize
        }
    }
}

/// For each node that satisfies `holder`, the positions k in its own row
/// of [`Families`] of the neighbours that do not, ascending in k: with
/// `holder` the products nodes, each products node's wall pairs
/// (`crate::ProductsFamily::MirroredWall`), so a pass over them visits
/// them in the row's order without scanning the rest of the row. Row i is
/// `bond[offsets[i]..offsets[i + 1]]`; empty (no offsets) when not built.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct ForeignBonds {
    /// Row starts, one per node plus the end; empty when not built.
    pub offsets: Vec<u32>,
    /// Positions in [`Families::neighbours`].
    pub bond: Vec<u32>,
}

impl ForeignBonds {
    /// The bonds of `families` from a node satisfying `holder` to one that
    /// does not.
    pub fn of(families: &Families, holder: impl Fn(usize) -> bool) -> Self {
        let n = families.node_count();
        let mut offsets = Vec::with_capacity(n + 1);
        offsets.push(0u32);
        let mut bond = Vec::new();
        for i in 0..n {
            if holder(i) {
                bond.extend(
                    families
                        .row(i)
                        .filter(|&k| !holder(families.neighbours[k] as usize))
                        .map(|k| k as u32),
                );
            }
            offsets.push(bond.len() as u32);
        }
        Self { offsets, bond }
    }

    /// Node i's bond positions (none when not built).
    #[inline]
    pub fn row(&self, i: usize) -> &[u32] {
        if self.offsets.is_empty() {
            &[]
        } else {
            &self.bond[self.offsets[i] as usize..self.offsets[i + 1] as usize]
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Two products nodes (0, 2) and two solid ones (1, 3), every node in
    /// every other's row: node 0's foreign bonds are its row positions of
    /// 1 and 3, node 2's likewise, the solids' rows are empty; not built,
    /// every row is empty.
    #[test]
    fn foreign_bonds_are_a_holders_row_positions_of_the_others() {
        let families = Families {
            offsets: vec![0, 3, 6, 9, 12],
            neighbours: vec![1, 2, 3, 0, 2, 3, 0, 1, 3, 0, 1, 2],
        };
        let gas = |i: usize| i.is_multiple_of(2);
        let f = ForeignBonds::of(&families, gas);
        assert_eq!(f.row(0), &[0, 2]);
        assert_eq!(f.row(1), &[] as &[u32]);
        assert_eq!(f.row(2), &[7, 8]);
        assert_eq!(f.row(3), &[] as &[u32]);
        for i in 0..4 {
            for &k in f.row(i) {
                assert!(!gas(families.neighbours[k as usize] as usize));
            }
        }
        assert_eq!(ForeignBonds::default().row(3), &[] as &[u32]);
    }

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

    /// Products nodes 0 and 1 (body 0) beside solid nodes 2 and 3
    /// (body 1), on a line at unit spacing, horizon 1.5: with the rule of
    /// `ProductsFamily::WithSolids` node 1's row gains node 2 and node 2's
    /// row does not gain node 1; the one-sided list gives node 2 its
    /// partner 1 and the bond's place in row 1, and nothing to the others.
    #[test]
    fn products_families_take_in_the_solid_one_sidedly() {
        let x = [[0.0; 3], [1.0, 0.0, 0.0], [2.0, 0.0, 0.0], [3.0, 0.0, 0.0]];
        let body = [0u32, 0, 1, 1];
        let gas = [true, true, false, false];
        let f = build_families_where(&x, 1.5, 1.0, |i, j| {
            body[i] == body[j] || (gas[i] && !gas[j])
        });
        assert_eq!(f.offsets, vec![0, 1, 3, 4, 5]);
        assert_eq!(f.neighbours, vec![1, 0, 2, 3, 2]);
        let pairs = OneSidedPairs::of(&f, |i| gas[i]);
        assert_eq!(pairs.offsets, vec![0, 0, 0, 1, 1]);
        assert_eq!(pairs.partner, vec![1]);
        assert_eq!(pairs.bond, vec![2]);
        assert_eq!(f.neighbours[pairs.bond[0] as usize], 2);
        assert_eq!(pairs.row(0), 0..0);
        // Families of one body each: no one-sided pair, nothing stored.
        let own = build_families(&x, &body, 1.5, 1.0);
        let none = OneSidedPairs::of(&own, |i| gas[i]);
        assert!(none.is_empty() && none.offsets.is_empty());
        assert_eq!(none.row(3), 0..0);
    }
}
