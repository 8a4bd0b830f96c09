//! V-RING: the breathing mode of a free thin elastic ring on an
//! axisymmetric (r, z) MPM grid, built from
//! `configs/validation/ring_breathing_rz.ron` through the composer.

use std::f64::consts::PI;

use brisance_compose::{build::build_solver, load_str};
use brisance_core::{SetQuantity, Solver};
use brisance_mpm::ShapeFunction;

/// The V-RING scenario file.
pub const RING_CONFIG: &str = include_str!("../../../configs/validation/ring_breathing_rz.ron");

/// What [`ring_breathing`] measured.
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

/// The breathing mode of the free thin steel ring of the config (mean
/// radius R = 80 mm, section t × t with t = R/16) with `cells_across` cells
/// across t and the shape function `shape`, run 2.6 periods: its period
/// against ω = c/R with c = √(E/ρ) (Love, *A Treatise on the Mathematical
/// Theory of Elasticity*, §291; the ring's own plane stress, free in r and
/// z). The grid reaches four cells beyond the ring's outer radius and four
/// sections high; the mean radial velocity is the config's particle gauge
/// over the whole ring, sampled after every step.
pub fn ring_breathing(shape: ShapeFunction, cells_across: usize) -> Result<RingBreathing, String> {
    let (k, g, rho): (f64, f64, f64) = (160.0e9, 80.0e9, 7800.0);
    let e = 9.0 * k * g / (3.0 * k + g);
    let (r_mean, t): (f64, f64) = (0.08, 0.005);
    let n = cells_across;
    if n == 0 {
        return Err("V-RING: cells_across must be at least 1".into());
    }
    let h = t / n as f64;
    let nr = ((r_mean + t) / h).round() as usize + 4;
    let shape = match shape {
        ShapeFunction::Linear => "Linear",
        ShapeFunction::Gimp => "Gimp",
        ShapeFunction::CpGimp => "CpGimp",
        ShapeFunction::QuadraticBSpline => "QuadraticBSpline",
    };
    let sets = [
        format!("domain.cells=({nr},{},1)", 4 * n),
        format!("domain.upper=({:e},{:e},0.001)", nr as f64 * h, 4.0 * t),
        format!("pipeline.shape_function={shape}"),
    ];
    let loaded = load_str(
        "configs/validation/ring_breathing_rz.ron",
        RING_CONFIG,
        &sets,
    )
    .map_err(|e| e.to_string())?;
    let mut solver = build_solver(&loaded.scenario).map_err(|e| loaded.locate(e).to_string())?;
    let analytic = 2.0 * PI * r_mean / (e / rho).sqrt();
    let mut sample = Vec::with_capacity(3);
    let mut mean_vr = |s: &dyn Solver| -> Result<f64, String> {
        sample.clear();
        if !s.sample_particle_gauge(0, &[SetQuantity::MeanVelocity], &mut sample) {
            return Err("V-RING: the config's particle gauge is missing".into());
        }
        Ok(sample[0])
    };
    let mut crossings = Vec::new();
    let (mut t_prev, mut v_prev) = (0.0, mean_vr(&*solver)?);
    while solver.time() < 2.6 * analytic {
        let dt = solver.stable_dt().map_err(|e| e.to_string())?;
        solver.advance(dt).map_err(|e| e.to_string())?;
        let v = mean_vr(&*solver)?;
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

#[cfg(test)]
mod tests {
    use super::*;

    /// The breathing mode of a free thin ring of mean radius R: ω = c/R with
    /// c = √(E/ρ), within 1 % for a ring of section t × t, t = R/16, 8 cells
    /// across it, on every shape function. The case runs without a mass
    /// cut-off: as the ring swells, the GIMP domains of its outer particles
    /// reach one node further (by δ ≈ 8 µm, 1.3 % of a cell); that node's
    /// mass ~ (δ/Δx)² m_p lies below the default cut-off, and its share of
    /// the internal force, ~ δ/Δx of a node's, is dropped with it, a net
    /// radial force that shortened the period by 6.5 % here (0.95 % at 4
    /// cells across, 0.15 % at 2) (docs/physics/mpm/axisymmetric.md).
    #[test]
    fn a_thin_ring_breathes_at_its_analytic_frequency() {
        for shape in [
            ShapeFunction::Linear,
            ShapeFunction::Gimp,
            ShapeFunction::CpGimp,
            ShapeFunction::QuadraticBSpline,
        ] {
            let r = ring_breathing(shape, 8).unwrap();
            assert!(
                r.error().abs() < 0.01,
                "{shape:?}: period {:.4e} s against {:.4e} s ({:+.3} %)",
                r.measured,
                r.analytic,
                100.0 * r.error()
            );
        }
    }

    #[test]
    fn no_cells_across_is_an_error() {
        assert!(ring_breathing(ShapeFunction::Linear, 0).is_err());
    }
}
