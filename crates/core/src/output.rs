//! What solvers hand to the output writers and the conservation bookkeeping.

use serde::{Deserialize, Serialize};

/// How often a safeguard of a method acted: a limiter or fallback that
/// replaces the method's own update where it would go wrong (the FDM's
/// positivity limiter, for instance), for the run summary.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct SafeguardUse {
    /// What acted, e.g. `positivity limiter`.
    pub name: &'static str,
    /// What it counts, plural, e.g. `faces`.
    pub unit: &'static str,
    /// How many of them it changed since the start.
    pub acted: u64,
    /// How many it checked since the start.
    pub checked: u64,
}

/// Totals of the conserved quantities over the whole domain.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub struct ConservationTotals {
    /// Total mass, kg.
    pub mass: f64,
    /// Total momentum, kg·m/s.
    pub momentum: [f64; 3],
    /// Total energy (internal + kinetic), J.
    pub energy: f64,
}

/// A range of coordinates along one axis that holds every point whose
/// cell index along it lies in a given range [i0, i1], with a whole cell to
/// spare either side. It refuses only coordinates that
/// [`UniformGridGeometry::cell_containing`] certainly places outside that
/// range, so a scan over particles can skip the far ones with two
/// comparisons and let the exact (three-division) test decide the rest:
/// the same particles as the exact test alone.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AxisWindow {
    lo: f64,
    hi: f64,
}

impl AxisWindow {
    /// False only where `x` lies more than a cell outside the range (and
    /// for NaN, which `cell_containing` refuses too).
    #[inline(always)]
    pub fn admits(&self, x: f64) -> bool {
        x >= self.lo && x <= self.hi
    }

    /// Whether every window of `windows` admits its coordinate of `x`.
    #[inline(always)]
    pub fn admit_all(windows: &[AxisWindow; 3], x: [f64; 3]) -> bool {
        windows[0].admits(x[0]) && windows[1].admits(x[1]) && windows[2].admits(x[2])
    }
}

/// A uniform Cartesian grid: `cells[d]` cells of width `spacing[d]` starting
/// at `origin` (the low corner of cell (0, 0, 0)).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct UniformGridGeometry {
    /// Low corner of the domain, m.
    pub origin: [f64; 3],
    /// Cell widths, m.
    pub spacing: [f64; 3],
    /// Cell counts per direction (1 in unused directions).
    pub cells: [usize; 3],
}

impl UniformGridGeometry {
    /// Total number of cells.
    pub fn cell_count(&self) -> usize {
        self.cells[0] * self.cells[1] * self.cells[2]
    }

    /// Centre of global cell (i, j, k).
    pub fn cell_centre(&self, c: [usize; 3]) -> [f64; 3] {
        std::array::from_fn(|d| self.origin[d] + (c[d] as f64 + 0.5) * self.spacing[d])
    }

    /// The cell that contains `x`, or `None` outside the domain. Points on
    /// the upper boundary belong to the last cell.
    pub fn cell_containing(&self, x: [f64; 3]) -> Option<[usize; 3]> {
        let mut c = [0usize; 3];
        for d in 0..3 {
            let s = (x[d] - self.origin[d]) / self.spacing[d];
            let n = self.cells[d] as f64;
            if !(s >= 0.0 && s <= n) {
                return None;
            }
            c[d] = (s.floor() as usize).min(self.cells[d] - 1);
        }
        Some(c)
    }

    /// A cheap prefilter for "the cell of coordinate `x[d]` has index
    /// i0 ≤ i ≤ i1 along `d`" ([`AxisWindow`]).
    pub fn axis_window(&self, d: usize, i0: isize, i1: isize) -> AxisWindow {
        let (o, h) = (self.origin[d], self.spacing[d]);
        AxisWindow {
            lo: o + (i0 - 1) as f64 * h,
            hi: o + (i1 + 2) as f64 * h,
        }
    }

    /// The [`AxisWindow`]s of cell `c` along every direction: a point
    /// outside any of them is certainly not in `c`.
    pub fn cell_windows(&self, c: [usize; 3]) -> [AxisWindow; 3] {
        std::array::from_fn(|d| self.axis_window(d, c[d] as isize, c[d] as isize))
    }

    /// Linear index of global cell (i, j, k), x fastest.
    pub fn linear_index(&self, c: [usize; 3]) -> usize {
        c[0] + self.cells[0] * (c[1] + self.cells[1] * c[2])
    }

    /// Upper corner of the domain.
    pub fn upper(&self) -> [f64; 3] {
        std::array::from_fn(|d| self.origin[d] + self.cells[d] as f64 * self.spacing[d])
    }
}

/// Cell-centred fields on the whole grid, gathered from all patches, each in
/// global x-fastest order.
#[derive(Debug, Clone, PartialEq)]
pub struct CellData {
    /// The grid the fields live on.
    pub geometry: UniformGridGeometry,
    /// `(name, values)` pairs, snake_case names (`density`, `pressure`, ...).
    pub fields: Vec<(String, Vec<f64>)>,
}

/// The values of the field called `name` in a `(name, values)` list.
fn named_field<'a>(fields: &'a [(String, Vec<f64>)], name: &str) -> Option<&'a [f64]> {
    fields
        .iter()
        .find(|(n, _)| n == name)
        .map(|(_, v)| v.as_slice())
}

impl CellData {
    /// The values of a named field.
    pub fn field(&self, name: &str) -> Option<&[f64]> {
        named_field(&self.fields, name)
    }
}

/// One patch's share of a cell output: the cells `lo .. lo + cells`
/// (global cell indices) of patch `patch`, each field one value per cell
/// in x-fastest order within the patch.
#[derive(Debug, Clone, PartialEq)]
pub struct CellPiece {
    /// The patch's id.
    pub patch: usize,
    /// Global index of the piece's first cell.
    pub lo: [usize; 3],
    /// Cells per direction.
    pub cells: [usize; 3],
    /// `(name, values)` pairs, snake_case names, as in [`CellData`].
    pub fields: Vec<(String, Vec<f64>)>,
}

/// Cell-centred fields as one piece per patch, with no gather: every
/// patch's extent (for a master file that lists them all) and the pieces
/// of the patches this rank owns (every patch on one rank).
#[derive(Debug, Clone, PartialEq)]
pub struct CellPieces {
    /// The whole grid.
    pub geometry: UniformGridGeometry,
    /// `(lo, cells)` of every patch, by patch id.
    pub extents: Vec<([usize; 3], [usize; 3])>,
    /// The pieces of this rank's patches, in patch order.
    pub pieces: Vec<CellPiece>,
}

/// Point data of a particle or node set (MPM particles, PD nodes): one
/// position per point and named per-point fields in the same order.
#[derive(Debug, Clone, PartialEq)]
pub struct ParticleData {
    /// Positions, m.
    pub positions: Vec<[f64; 3]>,
    /// `(name, values)` pairs, one value per point, snake_case names.
    pub fields: Vec<(String, Vec<f64>)>,
}

impl ParticleData {
    /// The values of a named field.
    pub fn field(&self, name: &str) -> Option<&[f64]> {
        named_field(&self.fields, name)
    }
}

/// Fields on the nodes of a uniform lattice (the background grid of a
/// particle method): `nodes[d]` nodes per direction, node (i, j, k) at
/// `origin + (i, j, k) · spacing`, each field one value per node in
/// x-fastest order.
#[derive(Debug, Clone, PartialEq)]
pub struct NodeData {
    /// Position of node (0, 0, 0), m.
    pub origin: [f64; 3],
    /// Node spacing per direction, m.
    pub spacing: [f64; 3],
    /// Nodes per direction (1 in unused directions).
    pub nodes: [usize; 3],
    /// `(name, values)` pairs, snake_case names (`mass`, `velocity_x`, ...).
    pub fields: Vec<(String, Vec<f64>)>,
}

impl NodeData {
    /// Total number of nodes.
    pub fn node_count(&self) -> usize {
        self.nodes[0] * self.nodes[1] * self.nodes[2]
    }

    /// The values of a named field.
    pub fn field(&self, name: &str) -> Option<&[f64]> {
        named_field(&self.fields, name)
    }
}

/// A quantity a particle gauge records: a set average over the particles
/// of a gauge (the table of `brisance_mpm::particle_sets` gives each
/// average's weighting), sampled through [`crate::Solver::sample_particle_gauge`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub enum SetQuantity {
    /// Mass-weighted mean velocity, m/s.
    MeanVelocity,
    /// Centre of mass, m.
    MeanPosition,
    /// Centre of mass minus its initial value, m.
    MeanDisplacement,
    /// Volume-weighted mean material stress (Voigt), Pa.
    MeanStress,
    /// Volume-weighted mean material pressure, Pa.
    MeanPressure,
    /// Volume-weighted mean von Mises stress, Pa.
    MeanVonMisesStress,
    /// Mass-weighted mean temperature, K.
    MeanTemperature,
    /// Mass-weighted mean specific internal energy, J/kg.
    MeanSpecificInternalEnergy,
    /// Mass of the members present, kg.
    Mass,
}

impl SetQuantity {
    /// The CSV column names of the quantity.
    pub fn columns(self) -> &'static [&'static str] {
        match self {
            Self::MeanVelocity => &["mean_velocity_x", "mean_velocity_y", "mean_velocity_z"],
            Self::MeanPosition => &["mean_position_x", "mean_position_y", "mean_position_z"],
            Self::MeanDisplacement => &[
                "mean_displacement_x",
                "mean_displacement_y",
                "mean_displacement_z",
            ],
            Self::MeanStress => &[
                "mean_stress_xx",
                "mean_stress_yy",
                "mean_stress_zz",
                "mean_stress_yz",
                "mean_stress_xz",
                "mean_stress_xy",
            ],
            Self::MeanPressure => &["mean_pressure"],
            Self::MeanVonMisesStress => &["mean_von_mises_stress"],
            Self::MeanTemperature => &["mean_temperature"],
            Self::MeanSpecificInternalEnergy => &["mean_specific_internal_energy"],
            Self::Mass => &["mass"],
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn geometry() -> UniformGridGeometry {
        UniformGridGeometry {
            origin: [0.0, -1.0, 0.0],
            spacing: [0.1, 0.5, 1.0],
            cells: [10, 4, 1],
        }
    }

    #[test]
    fn cell_containing_maps_centres_back_to_their_cell() {
        let g = geometry();
        for c in [[0, 0, 0], [9, 3, 0], [4, 2, 0]] {
            assert_eq!(g.cell_containing(g.cell_centre(c)), Some(c));
        }
        assert_eq!(g.cell_containing([1.0, 1.0, 1.0]), Some([9, 3, 0]));
        assert_eq!(g.cell_containing([1.01, 0.0, 0.5]), None);
        assert_eq!(g.cell_containing([f64::NAN, 0.0, 0.5]), None);
    }

    #[test]
    fn node_data_counts_nodes_and_finds_fields() {
        let d = NodeData {
            origin: [0.0; 3],
            spacing: [1.0; 3],
            nodes: [3, 2, 1],
            fields: vec![("mass".into(), vec![1.0, 2.0, 3.0, 4.0, 5.0, 6.0])],
        };
        assert_eq!(d.node_count(), 6);
        assert_eq!(d.field("mass").map(|m| m[5]), Some(6.0));
        assert_eq!(d.field("velocity_x"), None);
    }

    #[test]
    fn particle_data_finds_fields_by_name() {
        let d = ParticleData {
            positions: vec![[0.0; 3], [1.0, 0.0, 0.0]],
            fields: vec![
                ("id".into(), vec![7.0, 8.0]),
                ("mass".into(), vec![0.5, 0.25]),
            ],
        };
        assert_eq!(d.field("mass"), Some(&[0.5, 0.25][..]));
        assert_eq!(d.field("id").map(|v| v[1]), Some(8.0));
        assert_eq!(d.field("Mass"), None);
    }

    #[test]
    fn axis_window_spans_the_cells_with_one_to_spare() {
        let g = geometry();
        // x: h = 0.1 from 0; cells 3..=4 span [0.3, 0.5] → [0.2, 0.6].
        let w = g.axis_window(0, 3, 4);
        assert!(w.admits(0.2) && w.admits(0.45) && w.admits(0.6));
        assert!(!w.admits(0.19) && !w.admits(0.61) && !w.admits(f64::NAN));
        // y: h = 0.5 from −1; cell 0 → [−1.5, 0.0].
        let ws = g.cell_windows([9, 0, 0]);
        assert!(AxisWindow::admit_all(&ws, [0.95, -0.9, 0.5]));
        assert!(!AxisWindow::admit_all(&ws, [0.95, 0.1, 0.5]));
    }

    proptest::proptest! {
        /// The window never refuses a point `cell_containing` puts in its
        /// range, the upper boundary (clamped into the last cell) included.
        #[test]
        fn axis_window_admits_every_point_of_its_cells(
            x in -0.2..1.2f64,
            i0 in -1isize..10,
            len in 0isize..3,
        ) {
            let g = geometry();
            let w = g.axis_window(0, i0, i0 + len);
            for x in [x, 1.0, 0.0] {
                if let Some(c) = g.cell_containing([x, 0.0, 0.5]) {
                    let i = c[0] as isize;
                    if i >= i0 && i <= i0 + len {
                        proptest::prop_assert!(w.admits(x), "{} in cell {}", x, i);
                    }
                }
            }
        }
    }

    #[test]
    fn linear_index_is_x_fastest() {
        let g = geometry();
        assert_eq!(g.linear_index([1, 0, 0]), 1);
        assert_eq!(g.linear_index([0, 1, 0]), 10);
        assert_eq!(g.cell_count(), 40);
    }
}
