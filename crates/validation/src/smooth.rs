//! Smooth exact solutions of the one-dimensional Euler equations.
//!
//! [`AdvectedSine`]: a density perturbation carried by a uniform flow. With
//! uniform velocity `u0` and pressure `p0` the momentum and energy equations
//! reduce to `ρ_t + u0 ρ_x = 0` (the contact/entropy wave of the Euler
//! system, Toro ch. 3), so any density profile is translated unchanged at
//! speed `u0`, independent of the equation of state. This is the standard
//! smooth problem for measuring a scheme's order of accuracy.
//!
//! Units are those of the caller (e.g. SI: kg/m³, m/s, Pa, m, s).

use super::riemann::PrimitiveState;

/// Exact solution `ρ(x, t) = ρ̄ + A sin(2π (x − u0 t) / L)`, `u = u0`,
/// `p = p0`, on the periodic domain `[x_min, x_min + L)`.
///
/// The phase is measured from `x = 0` (not from `x_min`), exactly as in the
/// formula above; `x_min` only places the periodic domain (see
/// [`AdvectedSine::wrap`]). Positivity requires `|A| < ρ̄` and `p0 > 0`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AdvectedSine {
    /// Mean density ρ̄ (e.g. kg/m³).
    pub mean_density: f64,
    /// Amplitude A of the density perturbation (same unit as ρ̄).
    pub amplitude: f64,
    /// Uniform advection velocity u0 (e.g. m/s).
    pub velocity: f64,
    /// Uniform pressure p0 (e.g. Pa).
    pub pressure: f64,
    /// Period L of the domain and wavelength of the sine (e.g. m).
    pub length: f64,
    /// Left end of the periodic domain `[x_min, x_min + L)` (e.g. m).
    pub x_min: f64,
}

impl AdvectedSine {
    /// Wavenumber `k = 2π / L` (1/length).
    pub fn wavenumber(&self) -> f64 {
        2.0 * std::f64::consts::PI / self.length
    }

    /// Right end `x_min + L` of the periodic domain.
    pub fn x_max(&self) -> f64 {
        self.x_min + self.length
    }

    /// Maps `x` into the periodic domain `[x_min, x_min + L)`.
    pub fn wrap(&self, x: f64) -> f64 {
        let wrapped = self.x_min + (x - self.x_min).rem_euclid(self.length);
        // rem_euclid can round up to exactly L.
        if wrapped >= self.x_max() {
            self.x_min
        } else {
            wrapped
        }
    }

    /// Exact density `ρ(x, t) = ρ̄ + A sin(k (x − u0 t))`, `k = 2π/L`.
    pub fn density(&self, x: f64, t: f64) -> f64 {
        self.mean_density + self.amplitude * (self.wavenumber() * (x - self.velocity * t)).sin()
    }

    /// Exact primitive state `(ρ(x, t), u0, p0)`.
    pub fn state(&self, x: f64, t: f64) -> PrimitiveState {
        PrimitiveState::new(self.density(x, t), self.velocity, self.pressure)
    }

    /// Exact cell average of the density over `[a, b]` at time `t`:
    ///
    /// `(1/(b−a)) ∫_a^b ρ dx = ρ̄ + A sin(k (m − u0 t)) · sin(k h/2) / (k h/2)`
    ///
    /// with `m = (a + b)/2`, `h = b − a` (the antiderivative
    /// `−cos(k(x − u0 t))/k` differenced and rewritten as a product, which
    /// avoids cancellation on small cells). For `a == b` the point value.
    pub fn cell_average_density(&self, a: f64, b: f64, t: f64) -> f64 {
        let k = self.wavenumber();
        let half = 0.5 * k * (b - a);
        let sinc = if half.abs() < 1e-4 {
            // Taylor series of sin(z)/z; error below z⁶/5040 ~ 2e-28.
            1.0 - half * half / 6.0 + half.powi(4) / 120.0
        } else {
            half.sin() / half
        };
        let centre = 0.5 * (a + b);
        self.mean_density + self.amplitude * (k * (centre - self.velocity * t)).sin() * sinc
    }

    /// Exact cell averages of the conserved variables `[ρ, ρu, E]` over
    /// `[a, b]` at time `t` for an ideal gas with ratio of specific heats γ:
    /// `ρ̄_cell`, `u0 ρ̄_cell`, `p0/(γ − 1) + ½ u0² ρ̄_cell` (u and p are
    /// uniform, so these are linear in the density average).
    pub fn cell_average_conserved(&self, a: f64, b: f64, t: f64, gamma: f64) -> [f64; 3] {
        let rho = self.cell_average_density(a, b, t);
        [
            rho,
            rho * self.velocity,
            self.pressure / (gamma - 1.0) + 0.5 * rho * self.velocity * self.velocity,
        ]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn wave() -> AdvectedSine {
        AdvectedSine {
            mean_density: 1.0,
            amplitude: 0.2,
            velocity: 1.3,
            pressure: 1.0,
            length: 2.0,
            x_min: -1.0,
        }
    }

    fn midpoint_average(w: &AdvectedSine, a: f64, b: f64, t: f64, n: usize) -> f64 {
        let h = (b - a) / n as f64;
        (0..n)
            .map(|i| w.density(a + (i as f64 + 0.5) * h, t))
            .sum::<f64>()
            / n as f64
    }

    #[test]
    fn cell_average_matches_fine_midpoint_sum() {
        let w = wave();
        for &t in &[0.0, 0.37, 2.9] {
            for cell in 0..16 {
                let a = w.x_min + cell as f64 * w.length / 16.0;
                let b = a + w.length / 16.0;
                let exact = w.cell_average_density(a, b, t);
                let mid = midpoint_average(&w, a, b, t, 4096);
                // Midpoint error ≤ (b−a)² max|ρ''| / 24 / n².
                assert!(
                    (exact - mid).abs() < 1e-9,
                    "t {t} cell {cell}: {exact} vs {mid}"
                );
            }
        }
    }

    #[test]
    fn cell_average_of_whole_period_is_the_mean() {
        let w = wave();
        let avg = w.cell_average_density(w.x_min, w.x_max(), 0.81);
        assert!((avg - w.mean_density).abs() < 1e-14);
    }

    #[test]
    fn tiny_cells_reduce_to_point_values() {
        let w = wave();
        let x = 0.123;
        assert_eq!(w.cell_average_density(x, x, 0.4), w.density(x, 0.4));
        let avg = w.cell_average_density(x - 1e-7, x + 1e-7, 0.4);
        assert!((avg - w.density(x, 0.4)).abs() < 1e-13);
    }

    #[test]
    fn profile_is_translated_at_the_flow_speed_and_periodic() {
        let w = wave();
        let t = 0.7;
        for i in 0..50 {
            let x = w.x_min + 0.04 * i as f64;
            assert!((w.density(x + w.velocity * t, t) - w.density(x, 0.0)).abs() < 1e-14);
            assert!((w.density(x + w.length, t) - w.density(x, t)).abs() < 1e-13);
            let y = w.wrap(x + 3.0 * w.length);
            assert!(y >= w.x_min && y < w.x_max());
            assert!((y - x).abs() < 1e-12);
        }
        // One period later the initial profile is back.
        let period = w.length / w.velocity;
        assert!((w.density(0.3, period) - w.density(0.3, 0.0)).abs() < 1e-14);
    }

    #[test]
    fn conserved_averages_follow_from_density() {
        let w = wave();
        let [rho, mom, e] = w.cell_average_conserved(0.1, 0.3, 0.2, 1.4);
        assert_eq!(rho, w.cell_average_density(0.1, 0.3, 0.2));
        assert!((mom - rho * 1.3).abs() < 1e-15);
        assert!((e - (1.0 / 0.4 + 0.5 * rho * 1.69)).abs() < 1e-14);
        let s = w.state(0.1, 0.2);
        assert_eq!(s.velocity, 1.3);
        assert_eq!(s.pressure, 1.0);
    }
}
