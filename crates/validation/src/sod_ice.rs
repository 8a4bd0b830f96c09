//! V-SOD-ICE's tubes: an ICE run of the Sod tube on x ∈ [0, 1] (one
//! material, or two of γ 1.4 | 1.67) to t = 0.2 compared with the exact
//! Riemann solution's cell averages ([`ice_tube`]); the solvers are
//! `brisance_ice::cases::{sod_one, sod_two}`, shared with the ICE crate's
//! own tests. `cargo xtask validate --only sod-ice` runs 100–1600 cells.

use std::time::Instant;

use brisance_core::Solver;

use crate::riemann::{l1_distance, PrimitiveState, RiemannProblem};

/// Time of the comparison (Toro's test 1 output time).
pub const SOD_ICE_END: f64 = 0.2;

/// One tube run compared with the exact solution.
pub struct IceTube {
    /// Cells along x.
    pub cells: usize,
    /// Cell centres.
    pub x: Vec<f64>,
    /// Computed mixture density.
    pub density: Vec<f64>,
    /// Exact cell averages of the density.
    pub exact_density: Vec<f64>,
    /// Σ|ρ − ρ_exact| Δx.
    pub l1_density: f64,
    /// Relative change of total mass over the run.
    pub mass_change: f64,
    /// Relative change of total (internal + kinetic) energy.
    pub energy_change: f64,
    /// Volume fraction of material 1 (two-material runs).
    pub theta: Vec<f64>,
    /// Wall time, s.
    pub wall: f64,
}

/// Runs `make(cells, t)` to SOD_ICE_END and compares it with `exact`.
pub fn ice_tube<S: Solver>(
    cells: usize,
    exact: &RiemannProblem,
    make: impl Fn(usize, f64) -> S,
) -> Result<IceTube, String> {
    let t0 = make(cells, 0.0).conservation_totals();
    let start = Instant::now();
    let s = make(cells, SOD_ICE_END);
    let wall = start.elapsed().as_secs_f64();
    let t1 = s.conservation_totals();
    let solution = exact.solve()?;
    let names = ["density".to_string(), "volume_fraction_1".to_string()];
    let two = s.cell_field_names().contains(&"volume_fraction_2");
    let d = s
        .cell_data(&names[..if two { 2 } else { 1 }])
        .map_err(|e| e.to_string())?;
    let density = d.fields[0].1.clone();
    let theta = if two {
        d.fields[1].1.clone()
    } else {
        Vec::new()
    };
    let dx = 1.0 / cells as f64;
    let x: Vec<f64> = (0..cells).map(|i| (i as f64 + 0.5) * dx).collect();
    let exact_density = solution.density_averages(&x, dx, 0.5, SOD_ICE_END);
    let l1_density = l1_distance(&density, &exact_density, dx);
    Ok(IceTube {
        cells,
        x,
        density,
        exact_density,
        l1_density,
        mass_change: (t1.mass - t0.mass) / t0.mass,
        energy_change: (t1.energy - t0.energy) / t0.energy,
        theta,
        wall,
    })
}

/// The two-material tube's exact solution (γ 1.4 | 1.67).
pub fn two_gas_sod() -> RiemannProblem {
    RiemannProblem::new(
        PrimitiveState::new(1.0, 0.0, 1.0),
        PrimitiveState::new(0.125, 0.0, 0.1),
        1.4,
        1.67,
    )
}

#[cfg(test)]
mod tests {
    use brisance_ice::cases::sod_one;
    use brisance_ice::Advection;

    use super::{ice_tube, two_gas_sod, SOD_ICE_END};
    use crate::riemann::sod;

    /// Reduced V-SOD-ICE: L1(ρ) falls between 100 and 200 cells (measured
    /// order 0.76) and van Leer beats donor cell.
    #[test]
    fn v_sod_ice_reduced() {
        let a = ice_tube(100, &sod(), |c, t| sod_one(c, Advection::VanLeer, t)).unwrap();
        let b = ice_tube(200, &sod(), |c, t| sod_one(c, Advection::VanLeer, t)).unwrap();
        let d = ice_tube(100, &sod(), |c, t| sod_one(c, Advection::DonorCell, t)).unwrap();
        let order = (a.l1_density / b.l1_density).ln() / 2f64.ln();
        assert!(b.l1_density < a.l1_density);
        assert!(order > 0.6, "{order}");
        assert!(a.l1_density < d.l1_density);
        // One material: no volume fractions; cell centres of a unit tube.
        assert!(a.theta.is_empty());
        assert_eq!(
            (a.x.len(), a.density.len(), a.exact_density.len()),
            (100, 100, 100)
        );
        assert_eq!((a.x[0], a.x[99]), (0.005, 0.995));
        // The tube's ends are outflow faces, so mass conservation to
        // round-off is checked in crates/ice's closed-tube tests instead.
    }

    #[test]
    fn the_two_gas_tube_is_sods_states_with_two_gammas() {
        let p = two_gas_sod();
        let s = sod();
        assert_eq!((p.left, p.right), (s.left, s.right));
        assert_eq!((p.gamma_left, p.gamma_right), (1.4, 1.67));
        assert_eq!(SOD_ICE_END, 0.2);
    }
}
