//! Particles from geometric shapes.
//!
//! Every background cell is divided into `ppc` sub-cells per active
//! direction (one along an inactive direction); a particle is created at
//! each sub-cell centre that lies inside the shape, with
//!
//! m_p = ρ · V_cell / ppc^dim,   V_p⁰ = V_cell / ppc^dim,
//!
//! where V_cell = Δx Δy Δz (an inactive direction counts with its cell
//! width, i.e. a 2D run has the depth of its single cell) and dim is the
//! number of active directions. The particles of a cell filled entirely
//! then tile it, which is also what the default uGIMP half-width
//! l_p = Δx/(2·ppc) assumes. The shape's mass is recovered exactly when its
//! faces lie on cell faces and converges with resolution otherwise.

use crate::particles::{MaterialId, ParticleError, ParticleInit, Particles};
use brisance_core::UniformGridGeometry;
use serde::{Deserialize, Serialize};

/// A region of space to fill with material. Lengths in m.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub enum Shape {
    /// The axis-aligned box lo ≤ x ≤ hi.
    Box {
        /// Low corner.
        lo: [f64; 3],
        /// High corner.
        hi: [f64; 3],
    },
    /// The ball |x − centre| ≤ radius.
    Sphere {
        /// Centre.
        centre: [f64; 3],
        /// Radius.
        radius: f64,
    },
    /// The solid cylinder of `radius` around the segment from `base` along
    /// `axis` (any length, normalised) over `length`.
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
    /// The tube inner_radius ≤ r ≤ outer_radius around the same segment.
    CylindricalShell {
        /// Centre of the base annulus.
        base: [f64; 3],
        /// Direction of the axis.
        axis: [f64; 3],
        /// Inner radius.
        inner_radius: f64,
        /// Outer radius.
        outer_radius: f64,
        /// Length along the axis.
        length: f64,
    },
    /// The half-space (x − point)·normal ≤ 0: material lies on the side the
    /// normal points away from.
    HalfSpace {
        /// A point on the bounding plane.
        point: [f64; 3],
        /// Outward normal of the material (any length).
        normal: [f64; 3],
    },
}

/// Why particles cannot be generated.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum GenerateError {
    /// A shape with a non-positive or non-finite size or a zero direction.
    #[error("invalid shape: {0}")]
    InvalidShape(String),
    /// Particles per cell or density out of range.
    #[error("invalid fill: {0}")]
    InvalidSpec(String),
    /// A generated particle was rejected.
    #[error(transparent)]
    Particle(#[from] ParticleError),
}

fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

fn finite(v: &[f64]) -> bool {
    v.iter().all(|x| x.is_finite())
}

fn unit(v: [f64; 3], what: &str) -> Result<[f64; 3], GenerateError> {
    let n = dot(v, v).sqrt();
    if !(n > 0.0) || !n.is_finite() {
        return Err(GenerateError::InvalidShape(format!(
            "{what} {v:?} must be a finite non-zero vector"
        )));
    }
    Ok([v[0] / n, v[1] / n, v[2] / n])
}

fn positive(v: f64, what: &str) -> Result<(), GenerateError> {
    if v > 0.0 && v.is_finite() {
        Ok(())
    } else {
        Err(GenerateError::InvalidShape(format!(
            "{what} {v} m must be positive"
        )))
    }
}

/// Axial coordinate and squared radial distance of `x` from the axis
/// through `base` along the unit vector `axis`.
fn axial_radial(x: [f64; 3], base: [f64; 3], axis: [f64; 3]) -> (f64, f64) {
    let r = sub(x, base);
    let t = dot(r, axis);
    (t, (dot(r, r) - t * t).max(0.0))
}

impl Shape {
    /// Checks sizes and directions, and returns the shape with its
    /// directions normalised.
    pub fn validated(&self) -> Result<Shape, GenerateError> {
        let mut s = self.clone();
        match &mut s {
            Shape::Box { lo, hi } => {
                if !finite(lo) || !finite(hi) || (0..3).any(|d| !(hi[d] > lo[d])) {
                    return Err(GenerateError::InvalidShape(format!(
                        "box corners {lo:?}, {hi:?} must be finite with hi > lo on every axis"
                    )));
                }
            }
            Shape::Sphere { centre, radius } => {
                if !finite(centre) {
                    return Err(GenerateError::InvalidShape(format!(
                        "sphere centre {centre:?} must be finite"
                    )));
                }
                positive(*radius, "sphere radius")?;
            }
            Shape::Cylinder {
                base,
                axis,
                radius,
                length,
            } => {
                if !finite(base) {
                    return Err(GenerateError::InvalidShape(format!(
                        "cylinder base {base:?} must be finite"
                    )));
                }
                *axis = unit(*axis, "cylinder axis")?;
                positive(*radius, "cylinder radius")?;
                positive(*length, "cylinder length")?;
            }
            Shape::CylindricalShell {
                base,
                axis,
                inner_radius,
                outer_radius,
                length,
            } => {
                if !finite(base) {
                    return Err(GenerateError::InvalidShape(format!(
                        "shell base {base:?} must be finite"
                    )));
                }
                *axis = unit(*axis, "shell axis")?;
                positive(*outer_radius, "shell outer radius")?;
                positive(*length, "shell length")?;
                if !(*inner_radius >= 0.0 && *inner_radius < *outer_radius) {
                    return Err(GenerateError::InvalidShape(format!(
                        "shell inner radius {inner_radius} m must lie in [0, {outer_radius})"
                    )));
                }
            }
            Shape::HalfSpace { point, normal } => {
                if !finite(point) {
                    return Err(GenerateError::InvalidShape(format!(
                        "half-space point {point:?} must be finite"
                    )));
                }
                *normal = unit(*normal, "half-space normal")?;
            }
        }
        Ok(s)
    }

    /// Whether `x` lies inside (boundary included). Directions are used as
    /// given: call on a [`Shape::validated`] shape.
    pub fn contains(&self, x: [f64; 3]) -> bool {
        match *self {
            Shape::Box { lo, hi } => (0..3).all(|d| x[d] >= lo[d] && x[d] <= hi[d]),
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
                t >= 0.0 && t <= length && r2 <= radius * radius
            }
            Shape::CylindricalShell {
                base,
                axis,
                inner_radius,
                outer_radius,
                length,
            } => {
                let (t, r2) = axial_radial(x, base, axis);
                t >= 0.0
                    && t <= length
                    && r2 >= inner_radius * inner_radius
                    && r2 <= outer_radius * outer_radius
            }
            Shape::HalfSpace { point, normal } => dot(sub(x, point), normal) <= 0.0,
        }
    }
}

/// What to fill a shape with.
#[derive(Debug, Clone, PartialEq)]
pub struct FillSpec {
    /// The region.
    pub shape: Shape,
    /// Particles per cell per active direction (≥ 1).
    pub ppc: usize,
    /// Density, kg/m³.
    pub density: f64,
    /// Material of the particles.
    pub material: MaterialId,
    /// Initial velocity, m/s.
    pub velocity: [f64; 3],
    /// Initial temperature, K.
    pub temperature: f64,
    /// Initial specific internal energy, J/kg.
    pub specific_internal_energy: f64,
}

/// Appends to `particles` one particle at every sub-cell centre of `grid`
/// inside `spec.shape` (zero history values) and returns how many were
/// created. Cells are visited x fastest, so the particles come out sorted
/// by cell.
pub fn fill_shape(
    particles: &mut Particles,
    grid: &UniformGridGeometry,
    spec: &FillSpec,
) -> Result<usize, GenerateError> {
    let shape = spec.shape.validated()?;
    if spec.ppc == 0 {
        return Err(GenerateError::InvalidSpec(
            "particles per cell must be at least 1".into(),
        ));
    }
    if !(spec.density > 0.0) || !spec.density.is_finite() {
        return Err(GenerateError::InvalidSpec(format!(
            "density {} kg/m³ must be positive",
            spec.density
        )));
    }
    let per_axis: [usize; 3] =
        std::array::from_fn(|d| if grid.cells[d] > 1 { spec.ppc } else { 1 });
    let per_cell = per_axis.iter().product::<usize>() as f64;
    let volume = grid.spacing.iter().product::<f64>() / per_cell;
    let history = vec![0.0; particles.history_stride()];
    let mut init = ParticleInit {
        velocity: spec.velocity,
        mass: spec.density * volume,
        volume,
        temperature: spec.temperature,
        specific_internal_energy: spec.specific_internal_energy,
        material: spec.material,
        ..Default::default()
    };
    let before = particles.len();
    for k in 0..grid.cells[2] {
        for j in 0..grid.cells[1] {
            for i in 0..grid.cells[0] {
                let cell = [i, j, k];
                for c in 0..per_axis[2] {
                    for b in 0..per_axis[1] {
                        for a in 0..per_axis[0] {
                            let sub_index = [a, b, c];
                            let x: [f64; 3] = std::array::from_fn(|d| {
                                grid.origin[d]
                                    + (cell[d] as f64
                                        + (sub_index[d] as f64 + 0.5) / per_axis[d] as f64)
                                        * grid.spacing[d]
                            });
                            if shape.contains(x) {
                                init.position = x;
                                particles.push(&init, &history)?;
                            }
                        }
                    }
                }
            }
        }
    }
    Ok(particles.len() - before)
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    /// Bound on the relative mass error of a curved shape filled with
    /// sub-cell width `s`: one tenth of the relative volume of one layer of
    /// sub-cells over the curved surface, 0.1·(A/V)·s. Every sub-cell that
    /// straddles the surface is counted either wholly in or wholly out, so a
    /// full layer is the scale of the worst case; the counting errors of
    /// opposite sign cancel, and the test asks that at least 90 % of that
    /// layer cancels.
    fn layer_bound(area_over_volume: f64, sub_cell: f64) -> f64 {
        0.1 * area_over_volume * sub_cell
    }

    fn cube_grid(n: usize, cells: [usize; 3]) -> UniformGridGeometry {
        UniformGridGeometry {
            origin: [0.0; 3],
            spacing: std::array::from_fn(|d| 1.0 / cells[d].min(n) as f64),
            cells,
        }
    }

    fn spec(shape: Shape, ppc: usize, density: f64) -> FillSpec {
        FillSpec {
            shape,
            ppc,
            density,
            material: MaterialId(3),
            velocity: [1.0, 0.0, 0.0],
            temperature: 300.0,
            specific_internal_energy: 0.0,
        }
    }

    /// Mass of `shape` filled on an n³ grid of the unit cube.
    fn mass_3d(shape: &Shape, n: usize, ppc: usize, rho: f64) -> f64 {
        let g = cube_grid(n, [n; 3]);
        let mut ps = Particles::new(0);
        fill_shape(&mut ps, &g, &spec(shape.clone(), ppc, rho)).unwrap();
        ps.total_mass()
    }

    #[test]
    fn cell_aligned_box_gets_ppc_cubed_particles_per_cell_and_its_exact_mass() {
        let g = cube_grid(10, [10; 3]);
        let rho = 7850.0;
        let shape = Shape::Box {
            lo: [0.2, 0.2, 0.3],
            hi: [0.6, 0.5, 0.7],
        };
        let mut ps = Particles::new(4);
        let n = fill_shape(&mut ps, &g, &spec(shape, 2, rho)).unwrap();
        assert_eq!(n, 4 * 3 * 4 * 8);
        assert_eq!(ps.len(), n);
        let exact = rho * 0.4 * 0.3 * 0.4;
        assert!((ps.total_mass() - exact).abs() <= 1e-12 * exact);
        let v: f64 = ps.initial_volume.iter().sum();
        assert!((v - 0.4 * 0.3 * 0.4).abs() <= 1e-14);
        assert!(ps.material.iter().all(|&m| m == MaterialId(3)));
        assert_eq!(ps.history.len(), 4 * n);
        // Generated cell by cell: already sorted.
        let perm = ps.sort_by_cell(&g).unwrap();
        assert!(perm.iter().enumerate().all(|(i, &p)| i == p));
    }

    #[test]
    fn cell_aligned_box_in_2d_gets_ppc_squared_particles_per_cell() {
        let g = UniformGridGeometry {
            origin: [0.0; 3],
            spacing: [0.1, 0.1, 0.05],
            cells: [10, 10, 1],
        };
        let shape = Shape::Box {
            lo: [0.1, 0.3, -1.0],
            hi: [0.4, 0.5, 1.0],
        };
        let mut ps = Particles::new(0);
        let n = fill_shape(&mut ps, &g, &spec(shape, 3, 1000.0)).unwrap();
        assert_eq!(n, 3 * 2 * 9);
        // Unit depth of the 2D slab is its one cell, 0.05 m.
        let exact = 1000.0 * 0.3 * 0.2 * 0.05;
        assert!((ps.total_mass() - exact).abs() <= 1e-12 * exact);
        assert!(ps.position.iter().all(|x| x[2] == 0.025));
    }

    #[test]
    fn cell_aligned_half_space_gets_its_exact_mass() {
        let g = cube_grid(8, [8; 3]);
        let shape = Shape::HalfSpace {
            point: [0.0, 0.0, 0.25],
            normal: [0.0, 0.0, 2.0],
        };
        let mut ps = Particles::new(0);
        let n = fill_shape(&mut ps, &g, &spec(shape, 2, 1.0)).unwrap();
        assert_eq!(n, 8 * 8 * 2 * 8);
        assert!((ps.total_mass() - 0.25).abs() <= 1e-14);
    }

    #[test]
    fn sphere_mass_converges_to_the_exact_mass() {
        let rho = 1630.0;
        let r = 0.3;
        let shape = Shape::Sphere {
            centre: [0.5, 0.5, 0.5],
            radius: r,
        };
        let exact = rho * 4.0 / 3.0 * PI * r * r * r;
        let coarse = ((mass_3d(&shape, 10, 2, rho) - exact) / exact).abs();
        let fine = ((mass_3d(&shape, 40, 2, rho) - exact) / exact).abs();
        eprintln!("sphere relative mass error: 10 cells {coarse:.3e}, 40 cells {fine:.3e}");
        assert!(fine < coarse, "{fine} !< {coarse}");
        // A/V = 3/r; sub-cell width 1/(40·2).
        let bound = layer_bound(3.0 / r, 1.0 / 80.0);
        assert!(
            fine < bound,
            "relative error {fine} at 40 cells, bound {bound}"
        );
    }

    #[test]
    fn shell_and_cylinder_masses_converge_to_the_exact_masses() {
        let rho = 8930.0;
        let cyl = Shape::Cylinder {
            base: [0.5, 0.5, 0.1],
            axis: [0.0, 0.0, 3.0],
            radius: 0.3,
            length: 0.8,
        };
        let shell = Shape::CylindricalShell {
            base: [0.5, 0.5, 0.1],
            axis: [0.0, 0.0, 1.0],
            inner_radius: 0.2,
            outer_radius: 0.3,
            length: 0.8,
        };
        // Caps at z = 0.1 and 0.9 lie on sub-cell faces at both resolutions,
        // so only the curved surfaces count: A/V = 2r/r² for the cylinder,
        // 2(r_o + r_i)/(r_o² − r_i²) for the shell.
        let cases = [
            (cyl, PI * 0.09, 2.0 / 0.3),
            (shell, PI * (0.09 - 0.04), 2.0 * 0.5 / 0.05),
        ];
        for (shape, area, area_over_volume) in cases {
            let exact = rho * area * 0.8;
            let coarse = ((mass_3d(&shape, 10, 2, rho) - exact) / exact).abs();
            let fine = ((mass_3d(&shape, 40, 2, rho) - exact) / exact).abs();
            eprintln!("{shape:?}: relative mass error 10 cells {coarse:.3e}, 40 cells {fine:.3e}");
            assert!(fine < coarse, "{fine} !< {coarse}");
            let bound = layer_bound(area_over_volume, 1.0 / 80.0);
            assert!(
                fine < bound,
                "relative error {fine} at 40 cells, bound {bound}"
            );
        }
    }

    #[test]
    fn tilted_cylinder_contains_points_along_its_axis_only_up_to_its_radius() {
        let s = Shape::Cylinder {
            base: [0.0; 3],
            axis: [1.0, 1.0, 0.0],
            radius: 0.1,
            length: 1.0,
        }
        .validated()
        .unwrap();
        let on_axis = [0.5, 0.5, 0.0];
        assert!(s.contains(on_axis));
        assert!(s.contains([0.5, 0.5, 0.099]));
        assert!(!s.contains([0.5, 0.5, 0.101]));
        assert!(!s.contains([-0.01, -0.01, 0.0]));
        assert!(!s.contains([0.71, 0.71, 0.0]));
    }

    #[test]
    fn invalid_shapes_and_specs_are_rejected_with_a_reason() {
        let g = cube_grid(4, [4; 3]);
        let mut ps = Particles::new(0);
        let bad = [
            (
                Shape::Sphere {
                    centre: [0.5; 3],
                    radius: -1.0,
                },
                "radius",
            ),
            (
                Shape::Cylinder {
                    base: [0.0; 3],
                    axis: [0.0; 3],
                    radius: 1.0,
                    length: 1.0,
                },
                "axis",
            ),
            (
                Shape::CylindricalShell {
                    base: [0.0; 3],
                    axis: [0.0, 0.0, 1.0],
                    inner_radius: 0.3,
                    outer_radius: 0.2,
                    length: 1.0,
                },
                "inner radius",
            ),
            (
                Shape::Box {
                    lo: [0.0; 3],
                    hi: [1.0, 0.0, 1.0],
                },
                "hi > lo",
            ),
        ];
        for (shape, word) in bad {
            let e = fill_shape(&mut ps, &g, &spec(shape, 2, 1.0)).unwrap_err();
            assert!(e.to_string().contains(word), "{e}");
        }
        let ok = Shape::Sphere {
            centre: [0.5; 3],
            radius: 0.2,
        };
        let e = fill_shape(&mut ps, &g, &spec(ok.clone(), 0, 1.0)).unwrap_err();
        assert!(e.to_string().contains("at least 1"));
        let e = fill_shape(&mut ps, &g, &spec(ok, 2, f64::NAN)).unwrap_err();
        assert!(e.to_string().contains("density"));
        assert!(ps.is_empty());
    }
}
