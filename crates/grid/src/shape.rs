//! Geometric shapes: where initial regions lie (cells whose centre is
//! inside, for Eulerian methods) and what particles fill (sub-cell points
//! inside, for MPM). One definition serves every method. Lengths in m.

use serde::{Deserialize, Serialize};

/// A region of space. Points on the boundary are inside.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub enum Shape {
    /// All of space.
    Everywhere,
    /// The axis-aligned box min ≤ x ≤ max.
    Box {
        /// Low corner.
        min: [f64; 3],
        /// High corner.
        max: [f64; 3],
    },
    /// The ball |x − centre| ≤ radius.
    Sphere {
        /// Centre.
        centre: [f64; 3],
        /// Radius.
        radius: f64,
    },
    /// The solid cylinder of `radius` around the segment from `base` along
    /// `axis` (any length; only its direction counts) over `length`.
    Cylinder {
        /// Centre of the base disc.
        base: [f64; 3],
        /// Direction of the axis.
        axis: [f64; 3],
        /// Radius.
        radius: f64,
        /// Length along the axis.
        length: f64,
    },
    /// The thick-walled tube inner_radius ≤ r ≤ outer_radius around the same
    /// kind of segment (a cylindrical shell).
    Shell {
        /// Centre of the base annulus.
        base: [f64; 3],
        /// Direction of the axis.
        axis: [f64; 3],
        /// Inner radius (0 gives a solid cylinder).
        inner_radius: f64,
        /// Outer radius.
        outer_radius: f64,
        /// Length along the axis.
        length: f64,
    },
    /// The half-space (x − point)·normal ≥ 0: the normal points into the
    /// region.
    HalfSpace {
        /// A point on the bounding plane.
        point: [f64; 3],
        /// Normal pointing into the region (any length).
        normal: [f64; 3],
    },
}

/// A shape parameter out of range: the field and what is wrong.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("`{field}`: {message}")]
pub struct ShapeError {
    /// The offending field (`radius`, `max`, ...).
    pub field: &'static str,
    /// What is wrong and what is expected.
    pub message: String,
}

fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

fn finite(v: &[f64; 3]) -> bool {
    v.iter().all(|x| x.is_finite())
}

/// Axial coordinate and squared radial distance of `x` from the axis
/// through `base` along `axis` (normalised here).
fn axial_radial(x: [f64; 3], base: [f64; 3], axis: [f64; 3]) -> (f64, f64) {
    let n = dot(axis, axis).sqrt();
    let a = axis.map(|c| c / n);
    let r = sub(x, base);
    let t = dot(r, a);
    (t, (dot(r, r) - t * t).max(0.0))
}

impl Shape {
    /// Checks sizes and directions; the error names the field.
    pub fn validate(&self) -> Result<(), ShapeError> {
        let err = |field, message: String| Err(ShapeError { field, message });
        let nonzero = |v: &[f64; 3]| finite(v) && dot(*v, *v) > 0.0;
        let positive = |v: f64| v > 0.0 && v.is_finite();
        match self {
            Shape::Everywhere => Ok(()),
            Shape::Box { min, max } => {
                if !(finite(min) && finite(max)) || (0..3).any(|d| !(max[d] > min[d])) {
                    return err(
                        "max",
                        format!("box max {max:?} must exceed min {min:?} in every direction"),
                    );
                }
                Ok(())
            }
            Shape::Sphere { centre, radius } => {
                if !finite(centre) {
                    return err("centre", "centre must be finite".into());
                }
                if !positive(*radius) {
                    return err("radius", format!("radius must be positive, got {radius}"));
                }
                Ok(())
            }
            Shape::Cylinder {
                base,
                axis,
                radius,
                length,
            } => {
                if !finite(base) {
                    return err("base", "base must be finite".into());
                }
                if !nonzero(axis) {
                    return err("axis", "axis must be a non-zero finite vector".into());
                }
                if !positive(*radius) {
                    return err("radius", format!("radius must be positive, got {radius}"));
                }
                if !positive(*length) {
                    return err("length", format!("length must be positive, got {length}"));
                }
                Ok(())
            }
            Shape::Shell {
                base,
                axis,
                inner_radius,
                outer_radius,
                length,
            } => {
                if !finite(base) {
                    return err("base", "base must be finite".into());
                }
                if !nonzero(axis) {
                    return err("axis", "axis must be a non-zero finite vector".into());
                }
                if !(positive(*outer_radius) && *inner_radius >= 0.0 && inner_radius < outer_radius)
                {
                    return err(
                        "outer_radius",
                        format!("need 0 ≤ inner_radius < outer_radius, got {inner_radius} and {outer_radius}"),
                    );
                }
                if !positive(*length) {
                    return err("length", format!("length must be positive, got {length}"));
                }
                Ok(())
            }
            Shape::HalfSpace { point, normal } => {
                if !finite(point) {
                    return err("point", "point must be finite".into());
                }
                if !nonzero(normal) {
                    return err("normal", "normal must be a non-zero finite vector".into());
                }
                Ok(())
            }
        }
    }

    /// Whether `x` lies inside (boundary included).
    pub fn contains(&self, x: [f64; 3]) -> bool {
        match *self {
            Shape::Everywhere => true,
            Shape::Box { min, max } => (0..3).all(|d| x[d] >= min[d] && x[d] <= max[d]),
            Shape::Sphere { centre, radius } => {
                let r = sub(x, centre);
                dot(r, r) <= radius * radius
            }
            Shape::Cylinder {
                base,
                axis,
                radius,
                length,
            } => {
                let (t, r2) = axial_radial(x, base, axis);
                (0.0..=length).contains(&t) && r2 <= radius * radius
            }
            Shape::Shell {
                base,
                axis,
                inner_radius,
                outer_radius,
                length,
            } => {
                let (t, r2) = axial_radial(x, base, axis);
                (0.0..=length).contains(&t)
                    && r2 >= inner_radius * inner_radius
                    && r2 <= outer_radius * outer_radius
            }
            Shape::HalfSpace { point, normal } => dot(sub(x, point), normal) >= 0.0,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn containment_of_each_shape_is_hand_checked() {
        let b = Shape::Box {
            min: [0.0; 3],
            max: [1.0, 2.0, 3.0],
        };
        assert!(b.contains([1.0, 2.0, 3.0]) && !b.contains([1.0, 2.1, 0.0]));
        let s = Shape::Sphere {
            centre: [1.0, 0.0, 0.0],
            radius: 0.5,
        };
        assert!(s.contains([1.5, 0.0, 0.0]) && !s.contains([1.0, 0.6, 0.0]));
        let c = Shape::Cylinder {
            base: [0.0; 3],
            axis: [0.0, 0.0, 2.0],
            radius: 1.0,
            length: 3.0,
        };
        assert!(
            c.contains([0.6, 0.6, 2.9])
                && !c.contains([0.8, 0.8, 1.0])
                && !c.contains([0.0, 0.0, -0.1])
        );
        let t = Shape::Shell {
            base: [0.0; 3],
            axis: [0.0, 0.0, 2.0],
            inner_radius: 1.0,
            outer_radius: 2.0,
            length: 3.0,
        };
        assert!(
            t.contains([1.5, 0.0, 1.0])
                && !t.contains([0.5, 0.0, 1.0])
                && !t.contains([2.5, 0.0, 1.0])
        );
        let h = Shape::HalfSpace {
            point: [0.5, 0.0, 0.0],
            normal: [2.0, 0.0, 0.0],
        };
        assert!(
            h.contains([0.5, 9.0, 9.0])
                && h.contains([0.7, 0.0, 0.0])
                && !h.contains([0.4, 0.0, 0.0])
        );
        assert!(Shape::Everywhere.contains([1e30, -1e30, 0.0]));
    }

    #[test]
    fn invalid_shapes_name_the_field() {
        let e = Shape::Sphere {
            centre: [0.0; 3],
            radius: -1.0,
        }
        .validate()
        .unwrap_err();
        assert_eq!(e.field, "radius");
        let e = Shape::Box {
            min: [0.0; 3],
            max: [1.0, 0.0, 1.0],
        }
        .validate()
        .unwrap_err();
        assert_eq!(e.field, "max");
        let e = Shape::Shell {
            base: [0.0; 3],
            axis: [0.0, 0.0, 1.0],
            inner_radius: 2.0,
            outer_radius: 1.0,
            length: 1.0,
        }
        .validate()
        .unwrap_err();
        assert_eq!(e.field, "outer_radius");
        let e = Shape::HalfSpace {
            point: [0.0; 3],
            normal: [0.0; 3],
        }
        .validate()
        .unwrap_err();
        assert_eq!(e.field, "normal");
    }
}
