//! Verification problems of the heat conduction that the tests and the
//! validation report (V-CONDUCTION) share: the decay of a cosine mode in a
//! bar and of the first radial Bessel mode of a solid cylinder, each with
//! an adiabatic surface, against their analytic transients.
//!
//! Both use a steel-like solid ([`RHO`], [`CV`], [`K`]) at rest without
//! stress, so that the mechanical step leaves the particles where they are
//! and only the conduction acts, 2 particles per cell per direction, Δt at
//! cfl 0.4 of the diffusive limit, over one e-folding time of the mode. The
//! measured decay rate is −ln(A(t)/A(0))/t, A the mode's amplitude
//! projected from the particles (mass-weighted).

use std::f64::consts::PI;

use brisance_constitutive::{
    Hypoelastic, MaterialModel, ObjectiveRate, PressureModel, SpecificHeat,
};
use brisance_core::{Geometry, Solver};
use brisance_grid::Level;

use super::{diffusive_time_step, HeatConduction};
use crate::{
    fill_shape_in, FillSpec, MaterialId, MpmOptions, MpmSolver, Particles, Shape, ShapeFunction,
};

/// Density of the steel-like solid, kg/m³.
pub const RHO: f64 = 7800.0;
/// Its specific heat c_v, J/(kg·K).
pub const CV: f64 = 477.0;
/// Its conductivity k, W/(m·K).
pub const K: f64 = 50.0;
/// The mean temperature of the modes, K.
pub const T0: f64 = 300.0;
/// The initial amplitude of the modes, K.
pub const DT_AMPLITUDE: f64 = 50.0;
/// The first positive zero of J1 = −J0′: the first radial mode of a
/// cylinder with an adiabatic surface is T = T0 + ΔT J0(j r/R).
pub const J1_FIRST_ZERO: f64 = 3.831_705_970_207_512;
/// The Courant number of the diffusive limit the cases step at.
const CFL: f64 = 0.4;

/// The thermal diffusivity α = k/(ρ c_v) of the solid, m²/s.
pub fn alpha() -> f64 {
    K / (RHO * CV)
}

/// What [`bar_decay`] or [`cylinder_decay`] measured.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ModeDecay {
    /// The measured decay rate −ln(A(t)/A(0))/t, 1/s.
    pub measured: f64,
    /// The analytic rate α κ² (κ the mode's wavenumber), 1/s.
    pub analytic: f64,
    /// Steps taken.
    pub steps: usize,
}

impl ModeDecay {
    /// measured / analytic − 1.
    pub fn error(&self) -> f64 {
        self.measured / self.analytic - 1.0
    }
}

/// A solid at rest without stress: the mechanical step leaves it exactly
/// where it is, so that only the conduction acts.
pub(crate) fn solid() -> MaterialModel {
    MaterialModel::Hypoelastic(Hypoelastic {
        shear_modulus: 1.0e9,
        pressure: PressureModel::Linear {
            bulk_modulus: 2.0e9,
        },
        rate: ObjectiveRate::Jaumann,
    })
}

/// The particles (`ppc` per cell per active direction) of the solid at
/// rest at [`T0`] filling the box `lo`..`hi` of `level`.
pub(crate) fn particles_in(
    level: &Level,
    lo: [f64; 3],
    hi: [f64; 3],
    ppc: usize,
    geometry: Geometry,
) -> Result<Particles, String> {
    let mut ps = Particles::new(0);
    fill_shape_in(
        &mut ps,
        &level.geometry,
        &FillSpec {
            shape: Shape::Box { min: lo, max: hi },
            ppc,
            density: RHO,
            material: MaterialId(0),
            velocity: [0.0; 3],
            temperature: T0,
            specific_internal_energy: 0.0,
        },
        geometry,
    )
    .map_err(|e| e.to_string())?;
    Ok(ps)
}

/// The MPM solver of the solid's particles `ps` with conductivity `k` and
/// specific heat [`CV`].
pub(crate) fn conducting_solver(
    level: Level,
    ps: Particles,
    shape: ShapeFunction,
    geometry: Geometry,
    k: f64,
) -> Result<MpmSolver, String> {
    conducting_solver_with(level, ps, shape, geometry, k, SpecificHeat::Constant(CV))
}

/// [`conducting_solver`] with the specific heat `heat`.
pub(crate) fn conducting_solver_with(
    level: Level,
    ps: Particles,
    shape: ShapeFunction,
    geometry: Geometry,
    k: f64,
    heat: SpecificHeat,
) -> Result<MpmSolver, String> {
    MpmSolver::new(
        level,
        vec![solid()],
        ps,
        MpmOptions {
            shape,
            geometry,
            ..Default::default()
        },
    )
    .map_err(|e| e.to_string())?
    .with_heat_conduction(HeatConduction {
        conductivity: vec![k],
        specific_heat: vec![Some(heat)],
    })
    .map_err(|e| e.to_string())
}

/// The amplitude of mode `phi` in the particles' temperature,
/// Σ m (T − T0) φ / Σ m φ² (the masses carry the ring weight r in r–z).
fn amplitude(s: &MpmSolver, phi: impl Fn([f64; 3]) -> f64) -> f64 {
    let ps = s.particles();
    let (mut num, mut den) = (0.0, 0.0);
    for p in 0..ps.len() {
        let f = phi(ps.position[p]);
        num += ps.mass[p] * (ps.temperature[p] - T0) * f;
        den += ps.mass[p] * f * f;
    }
    num / den
}

/// Runs `s` over one e-folding time 1/`analytic` in equal steps of at
/// most the diffusive limit at cfl 0.4, and returns the measured decay
/// rate of mode `phi`.
fn measured_decay(
    mut s: MpmSolver,
    analytic: f64,
    phi: impl Fn([f64; 3]) -> f64 + Copy,
) -> Result<ModeDecay, String> {
    let t_end = 1.0 / analytic;
    let dt_max = diffusive_time_step(alpha(), &s.level().geometry, CFL);
    let steps = (t_end / dt_max).ceil() as usize;
    let dt = t_end / steps as f64;
    let a0 = amplitude(&s, phi);
    for _ in 0..steps {
        s.advance(dt).map_err(|e| e.to_string())?;
    }
    Ok(ModeDecay {
        measured: -(amplitude(&s, phi) / a0).ln() / t_end,
        analytic,
        steps,
    })
}

/// The bar of length L = 1 m along x, `cells` cells, one cell across,
/// with T = T0 + ΔT cos(π x/L): the first mode of a bar with adiabatic
/// ends, whose amplitude decays as exp(−α (π/L)² t). (The sine mode of
/// the bar with ends held at T0 decays at the same rate; the adiabatic
/// ends are the method's natural condition, so no temperature needs to
/// be prescribed.)
pub fn bar(cells: usize, shape: ShapeFunction) -> Result<MpmSolver, String> {
    let h = 1.0 / cells as f64;
    let level = Level::new([0.0; 3], [1.0, h, h], [cells, 1, 1], [1, 1, 1], 0)
        .map_err(|e| e.to_string())?;
    let mut ps = particles_in(&level, [0.0; 3], [1.0, h, h], 2, Geometry::Cartesian)?;
    for p in 0..ps.len() {
        ps.temperature[p] = T0 + DT_AMPLITUDE * (PI * ps.position[p][0]).cos();
    }
    conducting_solver(level, ps, shape, Geometry::Cartesian, K)
}

/// The decay rate of the [`bar`]'s cosine mode over one e-folding time,
/// against the analytic α π² (L = 1 m).
pub fn bar_decay(cells: usize, shape: ShapeFunction) -> Result<ModeDecay, String> {
    measured_decay(bar(cells, shape)?, alpha() * PI * PI, |x| (PI * x[0]).cos())
}

/// J0(x) by its power series Σ (−1)^m (x/2)^{2m} / (m!)², to round-off for
/// 0 ≤ x ≤ 4.
pub fn bessel_j0(x: f64) -> f64 {
    let q = -0.25 * x * x;
    let (mut term, mut sum) = (1.0, 1.0);
    for m in 1..40 {
        term *= q / (m * m) as f64;
        sum += term;
    }
    sum
}

/// The r–z form: a solid cylinder of radius R = 1 m (`cells` cells along
/// r, one along z) with an adiabatic surface, T = T0 + ΔT J0(j₁′ r/R),
/// j₁′ = [`J1_FIRST_ZERO`], whose amplitude decays as exp(−α (j₁′/R)² t):
/// its decay rate over one e-folding time against that. (The mode of the
/// cylinder held at T0 on its surface, with the first zero 2.4048 of J0,
/// needs a prescribed temperature, which the method does not have.)
pub fn cylinder_decay(cells: usize, shape: ShapeFunction) -> Result<ModeDecay, String> {
    let radius = 1.0;
    let h = radius / cells as f64;
    let level = Level::new([0.0; 3], [radius, h, h], [cells, 1, 1], [1, 1, 1], 0)
        .map_err(|e| e.to_string())?;
    let mut ps = particles_in(&level, [0.0; 3], [radius, h, h], 2, Geometry::Axisymmetric)?;
    let mode = move |x: [f64; 3]| bessel_j0(J1_FIRST_ZERO * x[0] / radius);
    for p in 0..ps.len() {
        ps.temperature[p] = T0 + DT_AMPLITUDE * mode(ps.position[p]);
    }
    let s = conducting_solver(level, ps, shape, Geometry::Axisymmetric, K)?;
    measured_decay(s, alpha() * (J1_FIRST_ZERO / radius).powi(2), mode)
}
