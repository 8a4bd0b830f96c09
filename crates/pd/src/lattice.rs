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
//!
//! A perturbed lattice ([`LatticeJitter`], off unless asked for) moves each
//! site by a random offset, uniform in [−a h, a h] along each axis (along x
//! only for a bar), drawn from a ChaCha8 stream keyed by (seed, site
//! index); the site joins the first body that holds its moved position, and
//! keeps the volume h³. A regular lattice cut by a curved surface leaves a
//! staircase that repeats with the lattice's symmetry, and bonds that only
//! point along a few directions; both bias where a peridynamic body cracks
//! (Dipasquale, Sarego, Zaccariotto & Galvanetto, "Dependence of crack
//! paths on the orientation of regular 2D peridynamic grids", Eng. Fract.
//! Mech. 160 (2016) 248–263; Chen & Bobaru, "Selecting the kernel in a
//! peridynamic formulation", Comput. Phys. Commun. 197 (2015) 51–60, use
//! perturbed grids for the same reason). The offsets depend on the site's
//! index, the seed and a only, so a run keeps its bits for any thread or
//! rank count. docs/physics/pd/bond_based.md.

use brisance_grid::Shape;
use rand_chacha::rand_core::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use serde::{Deserialize, Serialize};

/// A perturbed lattice: every site moved by a random offset (module docs).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LatticeJitter {
    /// a: the largest offset along each axis as a fraction of the spacing
    /// (0 ≤ a < 0.5, so two sites never swap places along an axis).
    pub amplitude: f64,
    /// Seed of the offsets.
    #[serde(default)]
    pub seed: u64,
}

impl LatticeJitter {
    /// Checks the amplitude; the error names the field.
    pub fn validate(&self) -> Result<(), String> {
        if !(self.amplitude >= 0.0 && self.amplitude < 0.5) {
            return Err(format!(
                "`jitter.amplitude` = {}: expected 0 <= amplitude < 0.5 (a fraction of the spacing)",
                self.amplitude
            ));
        }
        Ok(())
    }

    /// The offset of lattice site `site` (indices along x, y, z) in units
    /// of the spacing: each component uniform in [−a, a).
    pub fn offset(&self, site: [i64; 3]) -> [f64; 3] {
        let mut key = [0u8; 32];
        key[..8].copy_from_slice(&self.seed.to_le_bytes());
        for d in 0..3 {
            key[8 + 8 * d..16 + 8 * d].copy_from_slice(&site[d].to_le_bytes());
        }
        let mut rng = ChaCha8Rng::from_seed(key);
        let a = self.amplitude;
        std::array::from_fn(|_| {
            let u = (rng.next_u64() >> 11) as f64 * (1.0 / (1u64 << 53) as f64);
            a * (2.0 * u - 1.0)
        })
    }
}

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
    /// A perturbed lattice (None: the regular one).
    pub jitter: Option<LatticeJitter>,
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
    if let Some(j) = spec.jitter {
        j.validate()
            .map_err(|message| LatticeError::InvalidLattice {
                field: "jitter.amplitude",
                message,
            })?;
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
                let mut x = [site(i, 0), site(j, 1), site(k, 2)];
                if let Some(jitter) = spec.jitter {
                    let o = jitter.offset([i, j, k]);
                    let axes = match spec.dimension {
                        Dimension::One => 1,
                        Dimension::Three => 3,
                    };
                    for d in 0..axes {
                        x[d] += o[d] * h;
                    }
                }
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
            jitter: None,
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
            jitter: None,
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

    #[test]
    fn a_jittered_site_moves_by_its_own_offset_within_the_amplitude() {
        let jitter = LatticeJitter {
            amplitude: 0.25,
            seed: 7,
        };
        let h = 0.125;
        let body = BodySpec {
            shape: Shape::Box {
                min: [-1.0; 3],
                max: [2.0; 3],
            },
            material: 0,
            velocity: [0.0; 3],
        };
        let regular = fill_lattice(&spec(h), std::slice::from_ref(&body)).unwrap();
        let moved = fill_lattice(
            &LatticeSpec {
                jitter: Some(jitter),
                ..spec(h)
            },
            &[body],
        )
        .unwrap();
        // A box far larger than the offsets: every site inside, in order.
        assert_eq!(moved.positions.len(), regular.positions.len());
        let mut largest = 0.0f64;
        let mut mean = [0.0f64; 3];
        for (x, y) in moved.positions.iter().zip(&regular.positions) {
            // The site's indices from its regular position, and its offset
            // by hand: the same draw, whatever the node's place in the list.
            let site = [0, 1, 2].map(|d| (y[d] / h - 0.5).round() as i64);
            let o = jitter.offset(site);
            for d in 0..3 {
                assert_eq!(x[d], y[d] + o[d] * h);
                largest = largest.max((x[d] - y[d]).abs());
                mean[d] += o[d];
            }
        }
        assert!(largest <= 0.25 * h && largest > 0.24 * h, "{largest}");
        let n = moved.positions.len() as f64;
        // Uniform on [−a, a): mean 0 within a few standard errors
        // (a/√3/√n = 2.4e-4 for 24³ sites).
        assert!(mean.iter().all(|m| (m / n).abs() < 1.5e-3), "{mean:?}");
        assert!(moved.volumes.iter().all(|&v| v == h * h * h));
        // Another seed, other offsets; amplitude 0, the regular lattice.
        let other = LatticeJitter { seed: 8, ..jitter };
        assert_ne!(other.offset([3, 4, 5]), jitter.offset([3, 4, 5]));
        let still = fill_lattice(
            &LatticeSpec {
                jitter: Some(LatticeJitter {
                    amplitude: 0.0,
                    seed: 7,
                }),
                ..spec(h)
            },
            &[BodySpec {
                shape: Shape::Box {
                    min: [-1.0; 3],
                    max: [2.0; 3],
                },
                material: 0,
                velocity: [0.0; 3],
            }],
        )
        .unwrap();
        assert_eq!(still, regular);
    }

    #[test]
    fn a_jittered_node_lies_inside_its_body() {
        let shell = Shape::Shell {
            base: [0.0; 3],
            axis: [0.0, 0.0, 1.0],
            inner_radius: 0.5,
            outer_radius: 0.75,
            length: 1.0,
        };
        let c = fill_lattice(
            &LatticeSpec {
                jitter: Some(LatticeJitter {
                    amplitude: 0.45,
                    seed: 1,
                }),
                ..spec(0.05)
            },
            &[BodySpec {
                shape: shell.clone(),
                material: 0,
                velocity: [0.0; 3],
            }],
        )
        .unwrap();
        assert!(!c.positions.is_empty());
        assert!(c.positions.iter().all(|&x| shell.contains(x)));
        // About the shell's volume: π(0.75² − 0.5²) = 0.982 m³.
        let v: f64 = c.volumes.iter().sum();
        assert!((v / 0.981_747 - 1.0).abs() < 0.02, "{v}");
    }

    #[test]
    fn a_jitter_of_half_a_spacing_or_more_is_refused() {
        for a in [0.5, -0.1, f64::NAN] {
            let e = fill_lattice(
                &LatticeSpec {
                    jitter: Some(LatticeJitter {
                        amplitude: a,
                        seed: 0,
                    }),
                    ..spec(0.1)
                },
                &[],
            )
            .unwrap_err();
            assert!(
                matches!(
                    e,
                    LatticeError::InvalidLattice {
                        field: "jitter.amplitude",
                        ..
                    }
                ),
                "{e:?}"
            );
        }
    }
}
