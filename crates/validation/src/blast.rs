//! Free-air blast from a spherical TNT charge: the 1D spherical
//! program-burn detonation of seed 001 §4.1 run far out into the air, with
//! pressure gauges at given distances, and the blast parameters a gauge
//! record gives (peak overpressure, arrival time, positive-phase impulse
//! and duration), the quantities the Kingery–Bulmash fits tabulate
//! ([`super::kingery_bulmash`]). Shared by the tests (coarse) and
//! `cargo xtask validate` (E-FREEAIR, converged).

use brisance_fdm::detonation::{DetonationSetup, RadialDetonation, Symmetry};
use brisance_fdm::FaceLimiter;

/// Density of the seed's TNT (seed 001 §4.1), kg/m³.
pub const TNT_DENSITY: f64 = 1630.0;

/// Radius of a TNT sphere of `mass` kg, m.
pub fn charge_radius(mass: f64) -> f64 {
    (3.0 * mass / (4.0 * std::f64::consts::PI * TNT_DENSITY)).cbrt()
}

/// The blast parameters of one gauge record (side-on overpressure
/// against time).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BlastParameters {
    /// Peak overpressure p − p₀, Pa.
    pub peak_overpressure: f64,
    /// Arrival time: when the overpressure first reaches half its peak
    /// (the middle of the shock, which the scheme spreads over a few
    /// cells), s.
    pub arrival_time: f64,
    /// Positive-phase impulse ∫(p − p₀) dt from the start of the record to
    /// the end of the positive phase, Pa·s.
    pub positive_impulse: f64,
    /// Positive-phase duration: from the arrival to the first time after
    /// the peak that the overpressure falls back to zero, s.
    pub positive_duration: f64,
}

/// The blast parameters of the record `(times, overpressure)` (increasing
/// times, overpressure p − p₀ in Pa), with linear interpolation between
/// samples and the trapezoid rule for the impulse; `None` when the record
/// has no positive overpressure or its positive phase has not ended.
pub fn blast_parameters(times: &[f64], overpressure: &[f64]) -> Option<BlastParameters> {
    let n = times.len().min(overpressure.len());
    let (peak_at, &peak) = overpressure[..n]
        .iter()
        .enumerate()
        .max_by(|a, b| a.1.total_cmp(b.1))?;
    if !(peak > 0.0) {
        return None;
    }
    // Where the record crosses `level` between samples k − 1 and k.
    let cross = |k: usize, level: f64| {
        let (p0, p1) = (overpressure[k - 1], overpressure[k]);
        let s = if p1 == p0 {
            1.0
        } else {
            (level - p0) / (p1 - p0)
        };
        times[k - 1] + s * (times[k] - times[k - 1])
    };
    let half = 0.5 * peak;
    let rise = (0..=peak_at).find(|&k| overpressure[k] >= half)?;
    let arrival_time = if rise == 0 {
        times[0]
    } else {
        cross(rise, half)
    };
    let fall = (peak_at + 1..n).find(|&k| overpressure[k] <= 0.0)?;
    let end = cross(fall, 0.0);
    let mut impulse = 0.0;
    for k in 1..fall {
        impulse += 0.5 * (overpressure[k - 1] + overpressure[k]) * (times[k] - times[k - 1]);
    }
    // The last piece up to the zero crossing: a triangle.
    impulse += 0.5 * overpressure[fall - 1] * (end - times[fall - 1]);
    Some(BlastParameters {
        peak_overpressure: peak,
        arrival_time,
        positive_impulse: impulse,
        positive_duration: end - arrival_time,
    })
}

/// A free-air run: a TNT sphere of `charge_mass` kg detonated at the
/// centre of a 1D spherical grid of `cells` cells out to `domain_radius`,
/// run to `end_time`, with gauges at `gauge_radii`.
#[derive(Debug, Clone, PartialEq)]
pub struct FreeAirSetup {
    /// TNT mass, kg (ρ₀ = 1630 kg/m³).
    pub charge_mass: f64,
    /// Outer radius of the grid, m (zero-gradient outflow there).
    pub domain_radius: f64,
    /// Cells from the centre to `domain_radius`.
    pub cells: usize,
    /// End time, s.
    pub end_time: f64,
    /// Distances of the gauges from the centre, m.
    pub gauge_radii: Vec<f64>,
    /// The face limiter of the FDM step.
    pub limiter: FaceLimiter,
}

/// What a free-air run recorded.
#[derive(Debug, Clone, PartialEq)]
pub struct FreeAirRun {
    /// Cell size, m.
    pub cell_size: f64,
    /// Charge mass of the grid (exact: the surface cell holds its share), kg.
    pub charge_mass: f64,
    /// Ambient pressure p₀, Pa.
    pub ambient_pressure: f64,
    /// Sample times, s (every step, from 0).
    pub times: Vec<f64>,
    /// Overpressure p − p₀ at each gauge, one series per gauge, Pa.
    pub overpressure: Vec<Vec<f64>>,
    /// Steps taken.
    pub steps: u64,
    /// Faces swept, and faces the face limiter changed for positivity and
    /// for the density bounds.
    pub limited_faces: (u64, [u64; 2]),
    /// Wall-clock time of the run, s.
    pub wall_seconds: f64,
}

impl FreeAirRun {
    /// The blast parameters of gauge `g` ([`blast_parameters`]).
    pub fn parameters(&self, g: usize) -> Option<BlastParameters> {
        blast_parameters(&self.times, &self.overpressure[g])
    }
}

/// The pressure at radius `r` of a run, interpolated linearly between the
/// two nearest cell centres, Pa.
fn pressure_at(run: &RadialDetonation, r: f64) -> f64 {
    let h = run.cell_size();
    let cells = run.setup().cells;
    let x = (r / h - 0.5).clamp(0.0, (cells - 1) as f64);
    let i = (x.floor() as usize).min(cells - 2);
    let s = x - i as f64;
    (1.0 - s) * run.state(i).2 + s * run.state(i + 1).2
}

/// Runs the free-air problem of `setup` (seed 001 TNT JWL products, ideal
/// gas air at 1.225 kg/m³ and 101.36 kPa) and records the gauges every
/// step. Fails where the run stops, naming where and when.
pub fn free_air_run(setup: &FreeAirSetup) -> Result<FreeAirRun, String> {
    let detonation = DetonationSetup {
        limiter: setup.limiter,
        ..DetonationSetup::tnt_in_air(
            Symmetry::Spherical,
            charge_radius(setup.charge_mass),
            setup.domain_radius,
            setup.cells,
        )
    };
    if let Some(r) = setup
        .gauge_radii
        .iter()
        .find(|&&r| !(r > 0.0 && r < setup.domain_radius))
    {
        return Err(format!(
            "gauge radius {r} m lies outside the grid (0, {}) m",
            setup.domain_radius
        ));
    }
    let t0 = std::time::Instant::now();
    let mut run = RadialDetonation::new(detonation).map_err(|e| e.to_string())?;
    let p0 = detonation.air_pressure;
    let (_, _, products) = run.totals();
    let charge_mass = 4.0 * std::f64::consts::PI * products;
    let mut times = vec![0.0];
    let mut overpressure: Vec<Vec<f64>> = setup
        .gauge_radii
        .iter()
        .map(|&r| vec![pressure_at(&run, r) - p0])
        .collect();
    while run.time() < setup.end_time {
        let dt = run.stable_dt().min(setup.end_time - run.time());
        run.step(dt).map_err(|e| e.to_string())?;
        times.push(run.time());
        for (series, &r) in overpressure.iter_mut().zip(&setup.gauge_radii) {
            series.push(pressure_at(&run, r) - p0);
        }
    }
    Ok(FreeAirRun {
        cell_size: run.cell_size(),
        charge_mass,
        ambient_pressure: p0,
        times,
        overpressure,
        steps: run.steps(),
        limited_faces: run.limited_faces(),
        wall_seconds: t0.elapsed().as_secs_f64(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn one_kilogram_of_tnt_is_a_52_7_mm_sphere() {
        // (3/(4π·1630))^(1/3) = 0.0527118 m.
        assert!((charge_radius(1.0) - 0.052_711_8).abs() < 1e-7);
    }

    #[test]
    fn a_triangular_pulse_gives_its_hand_computed_parameters() {
        // Rise from 0 to 100 Pa between 1 and 2 s, fall to −50 Pa at 4 s:
        // half peak at 1.5 s, zero at 2 + 2·(100/150) = 3.333 s, impulse
        // ½·100·(3.333 − 1) = 116.67 Pa·s.
        let t = [0.0, 1.0, 2.0, 4.0, 5.0];
        let p = [0.0, 0.0, 100.0, -50.0, 0.0];
        let b = blast_parameters(&t, &p).unwrap();
        assert_eq!(b.peak_overpressure, 100.0);
        assert!((b.arrival_time - 1.5).abs() < 1e-15);
        let end = 2.0 + 2.0 * 100.0 / 150.0;
        assert!((b.positive_duration - (end - 1.5)).abs() < 1e-14);
        assert!((b.positive_impulse - 0.5 * 100.0 * (end - 1.0)).abs() < 1e-12);
    }

    #[test]
    fn a_record_without_a_finished_positive_phase_gives_none() {
        assert_eq!(blast_parameters(&[0.0, 1.0], &[0.0, 5.0]), None);
        assert_eq!(blast_parameters(&[0.0, 1.0], &[-1.0, -2.0]), None);
        assert_eq!(blast_parameters(&[], &[]), None);
    }

    #[test]
    fn a_gauge_outside_the_grid_is_refused() {
        let setup = FreeAirSetup {
            charge_mass: 1.0,
            domain_radius: 1.0,
            cells: 100,
            end_time: 1e-5,
            gauge_radii: vec![0.5, 2.0],
            limiter: FaceLimiter::Full,
        };
        let err = free_air_run(&setup).unwrap_err();
        assert!(err.contains("gauge radius 2"), "{err}");
    }
}
