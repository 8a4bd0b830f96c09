//! V-ICE-MPM's step cost: the coupled ICE–MPM step (seed 000 §3.3) timed
//! against the two standalone steps it is made of, on the same grid and
//! particles (the case of the criterion bench `ice_mpm_step`,
//! benches/ice_mpm.rs: `brisance_couple::ice_mpm::cases::moving_cube`).
//! The figure of merit is coupled / (ICE + MPM); `cargo xtask validate
//! --only piston` reports it against its target (≤ 1.5).

use std::time::Instant;

use brisance_core::Solver;
use brisance_couple::ice_mpm::cases::{build_frames, build_warm, Setup};

/// Seconds per step of the three steps, and the coupled case's particles.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StepCost {
    /// The coupled ICE–MPM step.
    pub coupled: f64,
    /// The ICE step of the same two materials, the solid Eulerian.
    pub ice_alone: f64,
    /// The MPM step of the solid's particles alone.
    pub mpm_alone: f64,
    /// The particles the coupled step moves.
    pub particles: usize,
}

impl StepCost {
    /// coupled / (ICE alone + MPM alone).
    pub fn ratio(&self) -> f64 {
        self.coupled / (self.ice_alone + self.mpm_alone)
    }
}

/// The step cost of `setup`: each of the three steps timed over `steps`
/// steps at the Δt of the coupled case after
/// [`WARM_UP_STEPS`](brisance_couple::ice_mpm::cases::WARM_UP_STEPS) steps, the
/// best of `repeats` timings (each on a freshly built case, the building
/// outside the timing), per step. Fails with the solver's message if a
/// step fails, or if `steps` or `repeats` is 0.
pub fn step_cost(setup: &Setup, steps: usize, repeats: usize) -> Result<StepCost, String> {
    if steps == 0 || repeats == 0 {
        return Err(format!(
            "step cost: steps ({steps}) and repeats ({repeats}) must be at least 1"
        ));
    }
    let warm = || build_warm(setup).map_err(|e| e.to_string());
    let s0 = warm()?;
    let dt = s0.stable_dt().map_err(|e| e.to_string())?;
    let particles = s0.particles_per_step();
    let timed = |s: &mut dyn Solver| -> Result<f64, String> {
        let t = Instant::now();
        for _ in 0..steps {
            s.advance(dt).map_err(|e| e.to_string())?;
        }
        Ok(t.elapsed().as_secs_f64())
    };
    let best = |one: &mut dyn FnMut() -> Result<f64, String>| -> Result<f64, String> {
        let mut t = f64::INFINITY;
        for _ in 0..repeats {
            t = t.min(one()?);
        }
        Ok(t / steps as f64)
    };
    let coupled = best(&mut || timed(&mut warm()?))?;
    let ice_alone = best(&mut || timed(&mut build_frames(setup).0))?;
    let mpm_alone = best(&mut || timed(&mut build_frames(setup).1))?;
    Ok(StepCost {
        coupled,
        ice_alone,
        mpm_alone,
        particles,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use brisance_couple::ice_mpm::cases::moving_cube;

    /// The bench's case shrunk to 8³ cells of 1 mm with a 4 mm cube: three
    /// positive finite times and the cube's 4³ cells × 2³ particles.
    #[test]
    fn a_small_cube_s_step_cost_is_three_positive_times() {
        let h = 1e-3;
        let setup = Setup {
            upper: [8.0 * h; 3],
            cells: [8; 3],
            solids: vec![([2.0 * h; 3], [6.0 * h; 3])],
            ..moving_cube()
        };
        let c = step_cost(&setup, 1, 1).unwrap();
        for t in [c.coupled, c.ice_alone, c.mpm_alone] {
            assert!(t > 0.0 && t.is_finite(), "{c:?}");
        }
        assert_eq!(c.particles, 512, "{c:?}");
        assert!(c.ratio() > 0.0 && c.ratio().is_finite());
        let e = step_cost(&setup, 0, 1).unwrap_err();
        assert!(e.contains("steps (0)"), "{e}");
    }
}
