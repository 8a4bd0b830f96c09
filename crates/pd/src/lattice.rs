//! Discretisation: nodes on a regular lattice filling the bodies' shapes
//! (seed 004, "Numerical Method": "the domain is discretized into a set of
//! nodes, each with a known volume in the reference configuration").
//!
//! One cubic lattice of spacing h serves every body: its sites are
//! `origin + (i + ½, j + ½, k + ½) h`, so a box whose faces lie on lattice
//! planes through `origin` is tiled exactly by its nodes' cells. A site
//! belongs to the first body (in input order) whose shape contains it, so
//! an explosive fill and the case around it never put two nodes at one
//! place. Every node's reference volume is h³ (3D) or A·h for a bar of
//! cross-section A (1D, sites on the line y = origin_y, z = origin_z).

use brisance_grid::Shape;
use serde::{Deserialize, Serialize};

/// Spatial dimension of the model.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
pub enum Dimension {
    /// A bar along x of the given cross-section (1D micro-modulus).
    One,
    /// Three dimensions.
    #[default]
    Three,
}

/// A body: a shape filled with one material.
#[derive(Debug, Clone, PartialEq)]
pub struct BodySpec {
    /// The region the body fills.
    pub shape: Shape,
    /// Index of its material in the solver's material list.
    pub material: u16,
    /// Initial velocity, m/s.
    pub velocity: [f64; 3],
}

/// The lattice.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LatticeSpec {
    /// Node spacing h, m.
    pub spacing: f64,
    /// Lattice origin, m (sites at origin + (i + ½) h).
    pub origin: [f64; 3],
    /// Dimension.
    pub dimension: Dimension,
    /// Cross-section of a 1D bar, m² (ignored in 3D).
    pub cross_section: f64,
}

/// Nodes generated from bodies, in lattice order (x fastest) per body.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct NodeCloud {
    /// Reference positions, m.
    pub positions: Vec<[f64; 3]>,
    /// Reference volumes, m³.
    pub volumes: Vec<f64>,
    /// Body index of each node (position in the input list).
    pub body: Vec<u32>,
    /// Material index of each node.
    pub material: Vec<u16>,
    /// Initial velocities, m/s.
    pub velocity: Vec<[f64; 3]>,
}

/// Why nodes cannot be generated; the message names the field.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum LatticeError {
    /// A lattice parameter out of range.
    #[error("lattice: `{field}`: {message}")]
    InvalidLattice {
        /// The offending field.
        field: &'static str,
        /// What is wrong.
        message: String,
    },
    /// A body's shape is invalid or unbounded.
    #[error("body {body}: `{field}`: {message}")]
    InvalidBody {
        /// Body index.
        body: usize,
        /// The offending field.
        field: &'static str,
        /// What is wrong.
        message: String,
    },
}

/// Axis-aligned bounding box of a bounded shape.
pub fn bounding_box(shape: &Shape) -> Option<([f64; 3], [f64; 3])> {
    match *shape {
        Shape::Everywhere | Shape::HalfSpace { .. } => None,
        Shape::Box { min, max } => Some((min, max)),
        Shape::Sphere { centre, radius } => {
            Some((centre.map(|c| c - radius), centre.map(|c| c + radius)))
        }
        Shape::Cylinder {
            base,
            axis,
            radius: r,
            length,
        }
        | Shape::Shell {
            base,
            axis,
            outer_radius: r,
            length,
            ..
        } => {
            let n = (axis[0] * axis[0] + axis[1] * axis[1] + axis[2] * axis[2]).sqrt();
            let top: [f64; 3] = std::array::from_fn(|d| base[d] + axis[d] / n * length);
            Some((
                std::array::from_fn(|d| base[d].min(top[d]) - r),
                std::array::from_fn(|d| base[d].max(top[d]) + r),
            ))
        }
    }
}

/// Fills `bodies` with lattice nodes.
pub fn fill_lattice(spec: &LatticeSpec, bodies: &[BodySpec]) -> Result<NodeCloud, LatticeError> {
    let h = spec.spacing;
    if !(h > 0.0 && h.is_finite()) {
        return Err(LatticeError::InvalidLattice {
            field: "spacing",
            message: format!("must be a finite value > 0 m, got {h}"),
        });
    }
    if !spec.origin.iter().all(|x| x.is_finite()) {
        return Err(LatticeError::InvalidLattice {
            field: "origin",
            message: "must be finite".into(),
        });
    }
    let volume = match spec.dimension {
        Dimension::Three => h * h * h,
        Dimension::One => {
            if !(spec.cross_section > 0.0 && spec.cross_section.is_finite()) {
                return Err(LatticeError::InvalidLattice {
                    field: "cross_section",
                    message: format!(
                        "a 1D bar needs a finite cross-section > 0 m², got {}",
                        spec.cross_section
                    ),
                });
            }
            spec.cross_section * h
        }
    };
    let mut boxes = Vec::with_capacity(bodies.len());
    for (b, body) in bodies.iter().enumerate() {
        body.shape
            .validate()
            .map_err(|e| LatticeError::InvalidBody {
                body: b,
                field: e.field,
                message: e.message,
            })?;
        let bb = bounding_box(&body.shape).ok_or_else(|| LatticeError::InvalidBody {
            body: b,
            field: "shape",
            message: "peridynamic bodies need a bounded shape (Box, Sphere, Cylinder or Shell)"
                .into(),
        })?;
        if !body.velocity.iter().all(|v| v.is_finite()) {
            return Err(LatticeError::InvalidBody {
                body: b,
                field: "velocity",
                message: "must be finite".into(),
            });
        }
        boxes.push(bb);
    }
    if boxes.is_empty() {
        return Ok(NodeCloud::default());
    }
    // Index range of lattice sites over the union of the bounding boxes.
    let mut lo = [i64::MAX; 3];
    let mut hi = [i64::MIN; 3];
    for (min, max) in &boxes {
        for d in 0..3 {
            lo[d] = lo[d].min(((min[d] - spec.origin[d]) / h - 0.5).floor() as i64);
            hi[d] = hi[d].max(((max[d] - spec.origin[d]) / h - 0.5).ceil() as i64);
        }
    }
    if spec.dimension == Dimension::One {
        // Sites on the x line only.
        lo[1] = 0;
        hi[1] = 0;
        lo[2] = 0;
        hi[2] = 0;
    }
    let site = |i: i64, d: usize| -> f64 {
        match spec.dimension {
            Dimension::One if d > 0 => spec.origin[d],
            _ => spec.origin[d] + (i as f64 + 0.5) * h,
        }
    };
    let count: i64 = (0..3).map(|d| hi[d] - lo[d] + 1).product();
    if count > 2_000_000_000 {
        return Err(LatticeError::InvalidLattice {
            field: "spacing",
            message: format!("{count} lattice sites in the bodies' bounding box is too many"),
        });
    }
    let mut cloud = NodeCloud::default();
    for k in lo[2]..=hi[2] {
        for j in lo[1]..=hi[1] {
            for i in lo[0]..=hi[0] {
                let x = [site(i, 0), site(j, 1), site(k, 2)];
                if let Some(b) = bodies.iter().position(|b| b.shape.contains(x)) {
                    cloud.positions.push(x);
                    cloud.volumes.push(volume);
                    cloud.body.push(b as u32);
                    cloud.material.push(bodies[b].material);
                    cloud.velocity.push(bodies[b].velocity);
                }
            }
        }
    }
    if cloud.positions.len() > u32::MAX as usize / 2 {
        return Err(LatticeError::InvalidLattice {
            field: "spacing",
            message: format!("{} nodes exceed the 32-bit index", cloud.positions.len()),
        });
    }
    Ok(cloud)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn spec(h: f64) -> LatticeSpec {
        LatticeSpec {
            spacing: h,
            origin: [0.0; 3],
            dimension: Dimension::Three,
            cross_section: 0.0,
        }
    }

    #[test]
    fn a_box_on_lattice_planes_is_tiled_exactly() {
        let body = BodySpec {
            shape: Shape::Box {
                min: [0.0; 3],
                max: [1.0, 0.5, 0.25],
            },
            material: 0,
            velocity: [1.0, 0.0, 0.0],
        };
        let c = fill_lattice(&spec(0.125), &[body]).unwrap();
        assert_eq!(c.positions.len(), 8 * 4 * 2);
        let v: f64 = c.volumes.iter().sum();
        assert!((v - 0.125).abs() < 1e-15);
        assert_eq!(c.positions[0], [0.0625, 0.0625, 0.0625]);
        assert_eq!(c.positions[1], [0.1875, 0.0625, 0.0625]);
        assert!(c.velocity.iter().all(|v| *v == [1.0, 0.0, 0.0]));
    }

    #[test]
    fn the_first_body_claims_a_shared_site() {
        let inner = BodySpec {
            shape: Shape::Cylinder {
                base: [0.0; 3],
                axis: [0.0, 0.0, 1.0],
                radius: 0.3,
                length: 1.0,
            },
            material: 1,
            velocity: [0.0; 3],
        };
        let outer = BodySpec {
            shape: Shape::Shell {
                base: [0.0; 3],
                axis: [0.0, 0.0, 1.0],
                inner_radius: 0.3,
                outer_radius: 0.5,
                length: 1.0,
            },
            material: 0,
            velocity: [0.0; 3],
        };
        let c = fill_lattice(&spec(0.1), &[inner.clone(), outer.clone()]).unwrap();
        let both = fill_lattice(&spec(0.1), std::slice::from_ref(&inner))
            .unwrap()
            .positions
            .len()
            + fill_lattice(&spec(0.1), &[outer]).unwrap().positions.len();
        // Sites exactly on r = 0.3 (e.g. (0.3, 0.05·k...) are not on this
        // lattice; no site is counted twice.
        assert!(c.positions.len() <= both);
        let mut sorted = c.positions.clone();
        sorted.sort_by(|a, b| a.partial_cmp(b).unwrap());
        sorted.dedup();
        assert_eq!(sorted.len(), c.positions.len());
        assert!(c
            .material
            .iter()
            .zip(&c.body)
            .all(|(m, b)| (*m == 1) == (*b == 0)));
    }

    #[test]
    fn one_dimensional_bar_has_volume_a_h() {
        let s = LatticeSpec {
            spacing: 0.01,
            origin: [0.0; 3],
            dimension: Dimension::One,
            cross_section: 2.0e-4,
        };
        let body = BodySpec {
            shape: Shape::Box {
                min: [0.0, -1.0, -1.0],
                max: [1.0, 1.0, 1.0],
            },
            material: 0,
            velocity: [0.0; 3],
        };
        let c = fill_lattice(&s, &[body]).unwrap();
        assert_eq!(c.positions.len(), 100);
        assert!(c.positions.iter().all(|x| x[1] == 0.0 && x[2] == 0.0));
        assert!((c.volumes[7] - 2.0e-6).abs() < 1e-20);
    }

    #[test]
    fn unbounded_or_invalid_input_names_the_field() {
        let body = BodySpec {
            shape: Shape::Everywhere,
            material: 0,
            velocity: [0.0; 3],
        };
        let e = fill_lattice(&spec(0.1), &[body]).unwrap_err();
        assert!(matches!(
            e,
            LatticeError::InvalidBody { field: "shape", .. }
        ));
        let e = fill_lattice(&spec(-0.1), &[]).unwrap_err();
        assert!(matches!(
            e,
            LatticeError::InvalidLattice {
                field: "spacing",
                ..
            }
        ));
    }
}
