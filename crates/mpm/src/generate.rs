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
use brisance_core::Geometry;
use brisance_core::UniformGridGeometry;
pub use brisance_grid::{Shape, ShapeError};

/// Why particles cannot be generated.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum GenerateError {
    /// A shape with a non-positive or non-finite size or a zero direction.
    #[error("invalid shape: {0}")]
    InvalidShape(#[from] ShapeError),
    /// Particles per cell or density out of range.
    #[error("invalid fill: {0}")]
    InvalidSpec(String),
    /// A generated particle was rejected.
    #[error(transparent)]
    Particle(#[from] ParticleError),
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
    fill_shape_in(particles, grid, spec, Geometry::Cartesian)
}

/// [`fill_shape`] on a grid of `geometry`: on an axisymmetric (r, z) grid
/// each particle is the ring its sub-cell sweeps about x = 0, of volume
/// 2π r_p · A_sub (exact for the ring) and mass ρ times that.
pub fn fill_shape_in(
    particles: &mut Particles,
    grid: &UniformGridGeometry,
    spec: &FillSpec,
    geometry: Geometry,
) -> Result<usize, GenerateError> {
    spec.shape.validate()?;
    let shape = &spec.shape;
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
                                if geometry.is_axisymmetric() {
                                    let ring = 2.0 * std::f64::consts::PI * x[0] * volume
                                        / grid.spacing[2];
                                    init.volume = ring;
                                    init.mass = spec.density * ring;
                                }
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
            min: [0.2, 0.2, 0.3],
            max: [0.6, 0.5, 0.7],
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
            min: [0.1, 0.3, -1.0],
            max: [0.4, 0.5, 1.0],
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
            normal: [0.0, 0.0, -2.0],
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
        let shell = Shape::Shell {
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
        };
        s.validate().unwrap();
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
                Shape::Shell {
                    base: [0.0; 3],
                    axis: [0.0, 0.0, 1.0],
                    inner_radius: 0.3,
                    outer_radius: 0.2,
                    length: 1.0,
                },
                "inner_radius",
            ),
            (
                Shape::Box {
                    min: [0.0; 3],
                    max: [1.0, 0.0, 1.0],
                },
                "must exceed min",
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
