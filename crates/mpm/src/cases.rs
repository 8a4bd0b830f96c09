//! Verification problems of the MPM that the tests and the validation
//! report share.

use std::f64::consts::PI;

use brisance_constitutive::{Hypoelastic, MaterialModel, ObjectiveRate, PressureModel};
use brisance_core::{Geometry, Solver};
use brisance_grid::Level;

use crate::generate::fill_shape_in;
use crate::{
    FillSpec, GridBoundary, MaterialId, MpmOptions, MpmSolver, Particles, Shape, ShapeFunction,
    UpdateScheme,
};

/// What [`thin_ring_breathing`] measured.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RingBreathing {
    /// Period between the last two downward zero crossings of the
    /// mass-weighted mean radial velocity, s.
    pub measured: f64,
    /// 2π/ω with ω = c/R, c = √(E/ρ), s.
    pub analytic: f64,
}

impl RingBreathing {
    /// measured / analytic − 1.
    pub fn error(&self) -> f64 {
        self.measured / self.analytic - 1.0
    }
}

/// The breathing mode of a free thin steel ring of mean radius R = 80 mm
/// and section t × t, t = R/16, on an axisymmetric (r, z) grid with
/// `cells_across` cells across t and 2 × 2 particles per cell, set
/// breathing by a uniform 0.5 m/s radial velocity, MUSL, run 2.6 periods:
/// its period against ω = c/R with c = √(E/ρ) (Love, *A Treatise on the
/// Mathematical Theory of Elasticity*, §291; the ring's own plane stress,
/// free in r and z). Hypoelastic steel, K 160 GPa, G 80 GPa, ρ 7800 kg/m³.
/// No mass cut-off (docs/physics/mpm/axisymmetric.md: the default
/// cut-off drops GIMP light-node forces as the ring swells).
pub fn thin_ring_breathing(
    shape: ShapeFunction,
    cells_across: usize,
) -> Result<RingBreathing, String> {
    let (k, g, rho): (f64, f64, f64) = (160.0e9, 80.0e9, 7800.0);
    let e = 9.0 * k * g / (3.0 * k + g);
    let (r_mean, t): (f64, f64) = (0.08, 0.005);
    let h = t / cells_across as f64;
    let nr = ((r_mean + t) / h).round() as usize + 4;
    let nz = 4 * cells_across;
    let level = Level::new(
        [0.0; 3],
        [nr as f64 * h, nz as f64 * h, 0.001],
        [nr, nz, 1],
        [1, 1, 1],
        0,
    )
    .map_err(|e| e.to_string())?;
    let analytic = 2.0 * PI * r_mean / (e / rho).sqrt();
    let mut ps = Particles::new(0);
    let z0 = 0.75 * cells_across as f64 * h;
    fill_shape_in(
        &mut ps,
        &level.geometry,
        &FillSpec {
            shape: Shape::Box {
                min: [r_mean - t / 2.0, z0, 0.0],
                max: [r_mean + t / 2.0, z0 + t, 0.001],
            },
            ppc: 2,
            density: rho,
            material: MaterialId(0),
            velocity: [0.5, 0.0, 0.0],
            temperature: 300.0,
            specific_internal_energy: 0.0,
        },
        Geometry::Axisymmetric,
    )
    .map_err(|e| e.to_string())?;
    let mut faces = [GridBoundary::Free; 6];
    faces[0] = GridBoundary::Symmetry;
    let model = MaterialModel::Hypoelastic(Hypoelastic {
        shear_modulus: g,
        pressure: PressureModel::Linear { bulk_modulus: k },
        rate: ObjectiveRate::Jaumann,
    });
    let mut solver = MpmSolver::new(
        level,
        vec![model],
        ps,
        MpmOptions {
            shape,
            scheme: UpdateScheme::Musl,
            boundaries: faces,
            geometry: Geometry::Axisymmetric,
            mass_cutoff: 0.0,
            ..Default::default()
        },
    )
    .map_err(|e| e.to_string())?;
    let mean_vr = |s: &MpmSolver| {
        let ps = s.particles();
        let m: f64 = ps.mass.iter().sum();
        ps.mass
            .iter()
            .zip(&ps.velocity)
            .map(|(m, v)| m * v[0])
            .sum::<f64>()
            / m
    };
    let mut crossings = Vec::new();
    let (mut t_prev, mut v_prev) = (0.0, mean_vr(&solver));
    while solver.time() < 2.6 * analytic {
        let dt = solver.stable_dt().map_err(|e| e.to_string())?;
        solver.advance(dt).map_err(|e| e.to_string())?;
        let v = mean_vr(&solver);
        if v_prev > 0.0 && v <= 0.0 {
            crossings.push(t_prev + (solver.time() - t_prev) * v_prev / (v_prev - v));
        }
        (t_prev, v_prev) = (solver.time(), v);
    }
    match crossings.as_slice() {
        [.., a, b] => Ok(RingBreathing {
            measured: b - a,
            analytic,
        }),
        _ => Err(format!("the ring did not breathe twice: {crossings:?}")),
    }
}
