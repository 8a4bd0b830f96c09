//! A V-BURNRATE study around `brisance_ice::burn_rate`: the report's
//! grid-aligned PBX-9501 rows (the law's own A, the products' gas lifting
//! the surface pressure above the held one) at a chosen held pressure,
//! with two measures beside the report's: the surface's speed from the
//! reactant's *mass* (Σ θ_r ρ_r V over the reactant's density in its
//! interior at the first step) as well as from its volume, and the
//! odd–even (cell-to-cell) pressure oscillation inside the reactant, the
//! time mean over the measuring window of |p_i − (p_{i−1} + p_{i+1})/2|
//! over the cells that hold only reactant (θ_r > 0.99, both neighbours
//! too), as a fraction of the held pressure.
//!
//! `cargo run --release -p brisance-ice --example burn_rate_pressure -- PRESSURE_PA [implicit]`
//!
//! `implicit` runs the ICE's implicit pressure solve (default settings)
//! instead of the explicit one.

use brisance_core::solver::step_to;
use brisance_core::Solver;
use brisance_ice::burn_rate::{burning_slab, BurnRate, BurnSurface, Regression};
use brisance_ice::PressureSolve;

fn main() -> Result<(), String> {
    let usage = "usage: burn_rate_pressure PRESSURE_PA [implicit]";
    let p_held: f64 = std::env::args()
        .nth(1)
        .and_then(|s| s.parse().ok())
        .filter(|p: &f64| *p > 0.0 && p.is_finite())
        .ok_or(usage)?;
    let cfg = BurnRate::pbx_9501(p_held, BurnSurface::Plane);
    let solve = match std::env::args().nth(2).as_deref() {
        None => PressureSolve::Explicit,
        Some("implicit") => PressureSolve::Implicit(Default::default()),
        Some(_) => return Err(usage.into()),
    };
    let mut s = burning_slab(&cfg, solve)?;
    let mut by_volume = Regression::new(&cfg)?;
    let mut by_mass = Regression::new(&cfg)?;
    let t_end = by_volume.t_end();
    let cell = cfg.h * cfg.h * cfg.h;
    let mut rho_ref = None;
    let (mut odd_even, mut window) = (0.0, 0.0);
    let fields = [
        "volume_fraction_1".to_string(),
        "density_1".to_string(),
        "pressure".to_string(),
    ];
    step_to(&mut s, t_end, |s, dt| {
        let d = s.cell_data(&fields)?;
        let (theta, rho, p) = (&d.fields[0].1, &d.fields[1].1, &d.fields[2].1);
        let rho_ref = *rho_ref.get_or_insert(rho[0]);
        let volume: f64 = theta.iter().map(|t| t * cell).sum();
        let mass: f64 = theta.iter().zip(rho).map(|(t, r)| t * r * cell).sum();
        let surface = s.burning_surface(0);
        by_volume.record(s.time(), dt, volume, surface);
        by_mass.record(s.time(), dt, mass / rho_ref, surface);
        if by_volume.measuring(s.time()) {
            let jumps: Vec<f64> = (1..p.len() - 1)
                .filter(|&i| theta[i - 1..=i + 1].iter().all(|&t| t > 0.99))
                .map(|i| (p[i] - 0.5 * (p[i - 1] + p[i + 1])).abs())
                .collect();
            if !jumps.is_empty() {
                odd_even += jumps.iter().sum::<f64>() / jumps.len() as f64 * dt;
                window += dt;
            }
        }
        Ok(())
    })
    .map_err(|e| e.to_string())?;
    let v = by_volume.finish(s.steps())?;
    let m = by_mass.finish(s.steps())?;
    println!(
        "held {p_held:e} Pa, {solve:?}: {} steps, A p^n at the surface {:.5e} m/s (surface pressure {:.4} x held); \
         speed by volume {:.5e} m/s ({:+.3} %), by mass {:.5e} m/s ({:+.3} %); \
         odd-even pressure in the reactant {:.3} of the held pressure",
        v.steps,
        v.law_speed,
        v.surface_pressure / p_held,
        v.speed,
        100.0 * v.error(),
        m.speed,
        100.0 * (m.speed / m.law_speed - 1.0),
        if window > 0.0 { odd_even / window / p_held } else { f64::NAN },
    );
    Ok(())
}
