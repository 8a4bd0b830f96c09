//! A V-BURNRATE study around `brisance_ice::burn_rate`: one of the report's
//! A/100 rows (PBX-9501's law with A over 100 at 100 MPa, burnt over one
//! cell of 0.1 mm) with the reactant's extent in cells chosen, so that the
//! surface-area estimate's error can be followed as the curved surface
//! (the sphere) is resolved by more cells.
//!
//! `cargo run --release -p brisance-ice --example burn_rate_study -- \
//!    SURFACE EXTENT_CELLS [ESTIMATE]`
//!
//! SURFACE is `plane`, `diagonal` or `sphere`; ESTIMATE one of the
//! deflagration's `surface_area` names (`column`, the fluid's default, when
//! left out). Prints the surface's speed, A pⁿ at the surface, the area
//! error and the speed's error, as the report's rows do.

use brisance_ice::burn_rate::{burn_rate, BurnRate, BurnSurface};
use brisance_reaction::SurfaceArea;

fn main() -> Result<(), String> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let usage = "usage: burn_rate_study SURFACE EXTENT_CELLS [ESTIMATE]";
    let surface = match args.first().map(String::as_str) {
        Some("plane") => BurnSurface::Plane,
        Some("diagonal") => BurnSurface::Diagonal,
        Some("sphere") => BurnSurface::Sphere,
        _ => return Err(usage.into()),
    };
    let extent: usize = args
        .get(1)
        .and_then(|s| s.parse().ok())
        .filter(|&n| n >= 2)
        .ok_or(usage)?;
    let estimate: Option<SurfaceArea> = match args.get(2) {
        Some(name) => Some(ron::from_str(name).map_err(|e| format!("estimate `{name}`: {e}"))?),
        None => None,
    };
    let mut cfg = BurnRate::a_over_100(surface);
    cfg.law.surface_area = estimate;
    cfg.extent_cells = extent;
    let r = burn_rate(&cfg)?;
    println!(
        "{} extent {extent} cells, estimate {:?}: {} steps, speed {:.5e} m/s, A p^n {:.5e} m/s, area error {:+.3} %, error {:+.3} %",
        surface.name(),
        cfg.law.surface_area_for(false),
        r.steps,
        r.speed,
        r.law_speed,
        100.0 * r.area_error,
        100.0 * r.error()
    );
    Ok(())
}
