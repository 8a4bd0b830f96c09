//! The coordinate system of a grid: Cartesian, or axisymmetric (r, z).
//!
//! An axisymmetric grid is a 2D grid of cells `(Nr, Nz, 1)` with x = r ≥ 0
//! and y = z; the axis of symmetry is x = 0. Each cell stands for the ring
//! it sweeps about the axis, so volumes and face areas carry 2πr
//! (docs/physics/axisymmetric.md). Quantities are for the whole ring (a
//! cell's mass is the ring's mass), not per radian.

use std::f64::consts::PI;

use serde::{Deserialize, Serialize};

use crate::UniformGridGeometry;

/// How a grid's cells are to be read.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
pub enum Geometry {
    /// Cells are boxes (the default).
    #[default]
    Cartesian,
    /// Cells are rings about the axis x = 0: x is the radius r, y the axial
    /// coordinate z, and the third direction has one cell.
    Axisymmetric,
}

impl Geometry {
    /// The name a scenario writes.
    pub fn name(self) -> &'static str {
        match self {
            Self::Cartesian => "Cartesian",
            Self::Axisymmetric => "Axisymmetric",
        }
    }

    /// Whether this is the axisymmetric (r, z) geometry.
    pub fn is_axisymmetric(self) -> bool {
        matches!(self, Self::Axisymmetric)
    }

    /// Volume of the cell spanning `[r_lo, r_lo + dr] × dy × dz`: the box
    /// `dr·dy·dz` for Cartesian cells, the ring `π((r_lo + dr)² − r_lo²)·dy`
    /// for axisymmetric ones (`dz` is ignored there).
    #[inline]
    pub fn cell_volume(self, r_lo: f64, dr: f64, dy: f64, dz: f64) -> f64 {
        match self {
            Self::Cartesian => dr * dy * dz,
            Self::Axisymmetric => PI * dr * (2.0 * r_lo + dr) * dy,
        }
    }

    /// Volume of a cell of `grid` in column `i` along x (from
    /// [`Self::cell_volume`]: its lower radius `origin + i Δx`): the box,
    /// or the ring about the axis on an (r, z) grid.
    #[inline]
    pub fn column_cell_volume(self, grid: &UniformGridGeometry, i: usize) -> f64 {
        let [dr, dy, dz] = grid.spacing;
        self.cell_volume(grid.origin[0] + i as f64 * dr, dr, dy, dz)
    }

    /// Area of the face normal to x at `x = r` of a cell `dy × dz` wide:
    /// `dy·dz`, or the cylinder `2π r·dy`.
    #[inline]
    pub fn x_face_area(self, r: f64, dy: f64, dz: f64) -> f64 {
        match self {
            Self::Cartesian => dy * dz,
            Self::Axisymmetric => 2.0 * PI * r * dy,
        }
    }

    /// Area of the face normal to y of the cell spanning `[r_lo, r_lo + dr]`:
    /// `dr·dz`, or the annulus `π((r_lo + dr)² − r_lo²)`.
    #[inline]
    pub fn y_face_area(self, r_lo: f64, dr: f64, dz: f64) -> f64 {
        match self {
            Self::Cartesian => dr * dz,
            Self::Axisymmetric => PI * dr * (2.0 * r_lo + dr),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cartesian_is_the_box() {
        let g = Geometry::Cartesian;
        assert_eq!(g.cell_volume(3.0, 0.5, 0.25, 2.0), 0.25);
        assert_eq!(g.x_face_area(3.0, 0.25, 2.0), 0.5);
        assert_eq!(g.y_face_area(3.0, 0.5, 2.0), 1.0);
    }

    #[test]
    fn a_column_s_cell_starts_at_its_lower_radius() {
        // Column 2 of a grid from r = 1 m in steps of 0.5 m spans r 2–2.5 m.
        let grid = UniformGridGeometry {
            origin: [1.0, 0.0, 0.0],
            spacing: [0.5, 0.25, 2.0],
            cells: [4, 3, 1],
        };
        assert_eq!(Geometry::Cartesian.column_cell_volume(&grid, 2), 0.25);
        let ring = Geometry::Axisymmetric.column_cell_volume(&grid, 2);
        assert!((ring - PI * (2.5f64.powi(2) - 2.0f64.powi(2)) * 0.25).abs() < 1e-14);
    }

    #[test]
    fn axisymmetric_rings_sum_to_the_cylinder() {
        // Ten rings of width 0.1 from the axis make the cylinder of radius 1.
        let g = Geometry::Axisymmetric;
        let dy = 0.3;
        let v: f64 = (0..10)
            .map(|i| g.cell_volume(i as f64 * 0.1, 0.1, dy, 7.0))
            .sum();
        assert!((v - PI * dy).abs() < 1e-14);
        // The outer face is the cylinder's side, the annuli its end.
        assert!((g.x_face_area(1.0, dy, 7.0) - 2.0 * PI * dy).abs() < 1e-15);
        let ends: f64 = (0..10)
            .map(|i| g.y_face_area(i as f64 * 0.1, 0.1, 7.0))
            .sum();
        assert!((ends - PI).abs() < 1e-14);
        // The axis has no area.
        assert_eq!(g.x_face_area(0.0, dy, 7.0), 0.0);
    }

    #[test]
    fn ring_faces_and_hoop_source() {
        // V = (r₊A₊ − r₋A₋)/2 for the ring (the divergence theorem on r/2),
        // and the radial faces of a ring differ by 2π·dr·dy: the force a
        // uniform pressure puts on them, p(A₊ − A₋), is what the hoop source
        // p·2π·dr·dy of a finite-volume r–z scheme must balance.
        let g = Geometry::Axisymmetric;
        for &(r, dr) in &[(0.0, 0.1), (0.35, 0.05), (2.0, 0.5)] {
            let dy = 0.2;
            let (a_lo, a_hi) = (g.x_face_area(r, dy, 1.0), g.x_face_area(r + dr, dy, 1.0));
            let lhs = 0.5 * ((r + dr) * a_hi - r * a_lo);
            assert!((lhs - g.cell_volume(r, dr, dy, 1.0)).abs() < 1e-14);
            assert!((a_hi - a_lo - 2.0 * PI * dr * dy).abs() < 1e-14);
        }
    }
}
