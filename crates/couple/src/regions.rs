//! The FDM region, the MPM region and their overlap, the bridge region
//! (seed 001 §3.1, Fig. 3).
//!
//! Both regions are axis-aligned boxes on one lattice of cells of the same
//! size. They differ along one axis, the split axis, and coincide along the
//! others. Along the split axis, with the MPM region on the high side:
//!
//! ```text
//!  FDM cells  0 ........................ k | k+1 .. k+F   (fictitious)
//!  MPM cells              k−w+1 ........ k | k+1 ........ m
//!                   k−w   ^ interface (boundary of the MPM region)
//! ```
//!
//! The bridge region is the w cells k−w+1..k both methods cover (seed 001
//! numbers them k−w..k; we keep the overlap w cells wide, as the issue's
//! geometry — FDM to 120 mm, MPM from 110 mm, 2 mm cells, w = 5 — has it).
//! The donor cell of the transport (seed 001 "cell k−w−1") is the last FDM
//! cell outside the MPM region, here k−w, and the first bridge cell
//! (seed 001 "cell k−w") is k−w+1. The FDM grid runs F fictitious cells
//! past k, inside the MPM region, whose values come from the MPM grid each
//! step (eqs 31–36); F is the FDM's ghost depth. The MPM grid gets one
//! halo cell on the FDM side, the donor cell, whose centre carries the FDM
//! cell as a particle onto the interface nodes (eqs 37–39). With the MPM
//! region on the low side everything is mirrored.

use brisance_core::UniformGridGeometry;
use serde::{Deserialize, Serialize};

/// Why the regions cannot be built.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum RegionError {
    /// The boxes do not form a bridge; the message names the field.
    #[error("{0}")]
    Invalid(String),
}

/// An axis-aligned box, m.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct RegionBox {
    /// Low corner, m.
    pub lower: [f64; 3],
    /// High corner, m.
    pub upper: [f64; 3],
}

/// Which side of the FDM region the MPM region lies on along the split axis.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum Side {
    /// MPM at higher coordinates than FDM.
    High,
    /// MPM at lower coordinates than FDM.
    Low,
}

impl Side {
    /// +1 for `High`, −1 for `Low`: the sign of the normal from the FDM
    /// region into the MPM region.
    pub fn sign(self) -> f64 {
        match self {
            Side::High => 1.0,
            Side::Low => -1.0,
        }
    }
}

/// The two regions and their bridge.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct BridgeRegions {
    /// Split axis, 0..3.
    pub axis: usize,
    /// Side of the MPM region.
    pub mpm_side: Side,
    /// Bridge width w, cells.
    pub width: usize,
    /// The FDM region's cells.
    pub fdm: UniformGridGeometry,
    /// The MPM region's cells.
    pub mpm: UniformGridGeometry,
}

const AXES: [&str; 3] = ["x", "y", "z"];

/// Cell count of [lo, hi] in cells of width h, if it is a whole number
/// (to 1e-6 of a cell).
fn whole_cells(lo: f64, hi: f64, h: f64) -> Option<usize> {
    let n = (hi - lo) / h;
    let r = n.round();
    ((n - r).abs() <= 1e-6 && r >= 1.0).then_some(r as usize)
}

impl BridgeRegions {
    /// Builds the regions from the FDM box, the MPM box and the cell size
    /// per axis (the size of an axis with one cell is the boxes' common
    /// extent). `fictitious` is the number of FDM cells past the bridge
    /// that the MPM region must also cover (the FDM's ghost depth).
    pub fn from_boxes(
        fdm: RegionBox,
        mpm: RegionBox,
        spacing: [f64; 3],
        fictitious: usize,
    ) -> Result<Self, RegionError> {
        let bad = |m: String| Err(RegionError::Invalid(m));
        let mut split = None;
        for d in 0..3 {
            let h = spacing[d];
            if !(h > 0.0 && h.is_finite()) {
                return bad(format!(
                    "cell size along {} = {h} m must be positive",
                    AXES[d]
                ));
            }
            let same = (fdm.lower[d] - mpm.lower[d]).abs() <= 1e-9 * h
                && (fdm.upper[d] - mpm.upper[d]).abs() <= 1e-9 * h;
            if !same {
                if split.is_some() {
                    return bad(format!(
                        "fdm and mpm regions differ along more than one axis (also {}): the split must be axis-aligned",
                        AXES[d]
                    ));
                }
                split = Some(d);
            }
            for (name, b) in [("fdm", &fdm), ("mpm", &mpm)] {
                if whole_cells(b.lower[d], b.upper[d], h).is_none() {
                    return bad(format!(
                        "{name} region along {} ({} .. {} m) is not a whole number of {h} m cells",
                        AXES[d], b.lower[d], b.upper[d]
                    ));
                }
            }
        }
        let Some(axis) = split else {
            return bad("fdm and mpm regions coincide: there is no interface".into());
        };
        let h = spacing[axis];
        let (side, overlap_lo, overlap_hi) = if mpm.upper[axis] > fdm.upper[axis] {
            (Side::High, mpm.lower[axis], fdm.upper[axis])
        } else {
            (Side::Low, fdm.lower[axis], mpm.upper[axis])
        };
        let contained = match side {
            Side::High => mpm.lower[axis] <= fdm.lower[axis],
            Side::Low => mpm.upper[axis] >= fdm.upper[axis] || mpm.lower[axis] >= fdm.lower[axis],
        };
        if contained {
            return bad(format!(
                "along {} one region contains the other: the mpm region must overlap one end of the fdm region",
                AXES[axis]
            ));
        }
        let Some(width) = whole_cells(overlap_lo, overlap_hi, h) else {
            return bad(format!(
                "along {} the regions overlap over {} m: the bridge must be at least one whole {h} m cell",
                AXES[axis],
                overlap_hi - overlap_lo
            ));
        };
        let geometry = |b: &RegionBox| UniformGridGeometry {
            origin: b.lower,
            spacing,
            cells: std::array::from_fn(|d| {
                whole_cells(b.lower[d], b.upper[d], spacing[d]).unwrap_or(1)
            }),
        };
        let r = Self {
            axis,
            mpm_side: side,
            width,
            fdm: geometry(&fdm),
            mpm: geometry(&mpm),
        };
        let beyond = r.mpm.cells[axis] - width;
        if beyond < fictitious {
            return bad(format!(
                "the mpm region reaches {beyond} cells past the fdm region along {}: it must cover the {fictitious} fictitious cells",
                AXES[axis]
            ));
        }
        if r.fdm.cells[axis] <= width {
            return bad(format!(
                "the fdm region along {} has {} cells: it needs at least one outside the bridge",
                AXES[axis], r.fdm.cells[axis]
            ));
        }
        Ok(r)
    }

    /// Coordinate of the interface, the boundary of the MPM region inside
    /// the FDM region, m.
    pub fn interface(&self) -> f64 {
        match self.mpm_side {
            Side::High => self.mpm.origin[self.axis],
            Side::Low => self.mpm.upper()[self.axis],
        }
    }

    /// Index along the split axis, in the FDM grid, of the donor cell (the
    /// last FDM cell outside the MPM region; seed 001 "k−w−1").
    pub fn donor_cell(&self) -> usize {
        let n = self.fdm.cells[self.axis];
        match self.mpm_side {
            Side::High => n - self.width - 1,
            Side::Low => self.width,
        }
    }

    /// Index along the split axis, in the FDM grid, of the first bridge
    /// cell (seed 001 "k−w").
    pub fn first_bridge_cell(&self) -> usize {
        let n = self.fdm.cells[self.axis];
        match self.mpm_side {
            Side::High => n - self.width,
            Side::Low => self.width - 1,
        }
    }

    /// The FDM grid extended by `layers` fictitious cells into the MPM
    /// region, and the offset (cells) of the FDM region's first cell in it
    /// along the split axis.
    pub fn fdm_grid(&self, layers: usize) -> (UniformGridGeometry, usize) {
        let mut g = self.fdm;
        g.cells[self.axis] += layers;
        let offset = match self.mpm_side {
            Side::High => 0,
            Side::Low => {
                g.origin[self.axis] -= layers as f64 * g.spacing[self.axis];
                layers
            }
        };
        (g, offset)
    }

    /// The MPM grid with one halo cell on the FDM side (the donor cell),
    /// and the offset (cells) of the MPM region's first cell in it.
    pub fn mpm_grid(&self) -> (UniformGridGeometry, usize) {
        let mut g = self.mpm;
        g.cells[self.axis] += 1;
        match self.mpm_side {
            Side::High => {
                g.origin[self.axis] -= g.spacing[self.axis];
                (g, 1)
            }
            Side::Low => (g, 0),
        }
    }

    /// The area of a cell face normal to the split axis, m².
    pub fn face_area(&self) -> f64 {
        (0..3)
            .filter(|&d| d != self.axis)
            .map(|d| self.fdm.spacing[d])
            .product()
    }

    /// The cell volume, m³.
    pub fn cell_volume(&self) -> f64 {
        self.fdm.spacing.iter().product()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn b(lower: [f64; 3], upper: [f64; 3]) -> RegionBox {
        RegionBox { lower, upper }
    }

    #[test]
    fn the_blast2d_geometry_gives_a_five_cell_bridge() {
        // Seed 001 §5.2: FDM (−180, 120) × (0, 500) mm, MPM (110, 160) ×
        // (0, 500) mm, 2 mm cells.
        let r = BridgeRegions::from_boxes(
            b([-0.18, 0.0, 0.0], [0.12, 0.5, 0.002]),
            b([0.11, 0.0, 0.0], [0.16, 0.5, 0.002]),
            [0.002; 3],
            4,
        )
        .unwrap();
        assert_eq!((r.axis, r.mpm_side, r.width), (0, Side::High, 5));
        assert_eq!(r.fdm.cells, [150, 250, 1]);
        assert_eq!(r.mpm.cells, [25, 250, 1]);
        assert_eq!(r.interface(), 0.11);
        // Donor [108, 110] mm is FDM cell 144; first bridge cell [110, 112] is 145.
        assert_eq!((r.donor_cell(), r.first_bridge_cell()), (144, 145));
        let (g, off) = r.fdm_grid(4);
        assert_eq!((g.cells[0], off), (154, 0));
        let (m, off) = r.mpm_grid();
        assert_eq!((m.cells[0], off), (26, 1));
        assert!((m.origin[0] - 0.108).abs() < 1e-15);
        assert!((r.face_area() - 0.002 * 0.002).abs() < 1e-18);
    }

    #[test]
    fn a_mirrored_split_puts_the_donor_on_the_other_side() {
        // MPM (0, 10) mm, FDM (6, 20) mm along y, 1 mm cells: w = 4.
        let r = BridgeRegions::from_boxes(
            b([0.0, 0.006, 0.0], [0.004, 0.02, 0.004]),
            b([0.0, 0.0, 0.0], [0.004, 0.01, 0.004]),
            [0.001; 3],
            4,
        )
        .unwrap();
        assert_eq!((r.axis, r.mpm_side, r.width), (1, Side::Low, 4));
        assert_eq!(r.interface(), 0.01);
        // FDM cells along y: 14, [6, 7] mm is 0; [10, 11] mm (donor) is 4.
        assert_eq!((r.donor_cell(), r.first_bridge_cell()), (4, 3));
        let (g, off) = r.fdm_grid(4);
        assert_eq!((g.cells[1], off), (18, 4));
        assert!((g.origin[1] - 0.002).abs() < 1e-15);
        let (m, off) = r.mpm_grid();
        assert_eq!((m.cells[1], off), (11, 0));
    }

    #[test]
    fn bad_splits_are_refused_naming_the_problem() {
        let h = [0.001; 3];
        let e = |f: RegionBox, m: RegionBox| {
            BridgeRegions::from_boxes(f, m, h, 4)
                .unwrap_err()
                .to_string()
        };
        let f = b([0.0; 3], [0.02, 0.01, 0.001]);
        assert!(e(f, f).contains("coincide"));
        assert!(e(f, b([0.015, 0.0, 0.0], [0.03, 0.02, 0.001])).contains("more than one axis"));
        assert!(e(f, b([0.0205, 0.0, 0.0], [0.03, 0.01, 0.001])).contains("whole number"));
        assert!(e(f, b([0.021, 0.0, 0.0], [0.03, 0.01, 0.001])).contains("whole"));
        assert!(e(f, b([0.018, 0.0, 0.0], [0.021, 0.01, 0.001])).contains("fictitious"));
        assert!(e(f, b([-0.01, 0.0, 0.0], [0.03, 0.01, 0.001])).contains("contains"));
    }
}
