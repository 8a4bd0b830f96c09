//! V-BURNRATE with a particle reactant (seed 000 §4.1.2, eqs 38–39; §5.3:
//! the cook-off's explosive is particles): the shapes of
//! `brisance_ice::burn_rate` (a grid-aligned plane, a plane at 45° in the
//! corner of two symmetry walls, a hemisphere on (r, z) rings) filled
//! with reactant particles instead of a fluid reactant, at rest in their
//! products at a held pressure. A fluid reactant moves with the gas its
//! burn makes (docs/physics/reaction/deflagration.md); a particle reactant
//! keeps its shape, as a pressed explosive does.

use brisance_core::solver::step_to;
use brisance_core::{Eos, Solver};
use brisance_eos::EosModel;
use brisance_ice::burn_rate::{
    initial_fraction, initially_inside, slab_boundaries, slab_geometry, slab_level, BurnRate,
    BurnRateResult, Regression,
};
use brisance_ice::cases::anfo_k1_jwlpp;
use brisance_ice::{
    CellState, ExchangeCoefficients, IceBoundary, IceOptions, IceReaction, IceSolver, MaterialState,
};
use brisance_mpm::{
    fill_shape_in, FillSpec, GridBoundary, MaterialId, MpmOptions, MpmSolver, Particles, Shape,
    ShapeFunction, UpdateScheme,
};

use super::tubes::hypoelastic;
use super::IceMpm;

/// The reactant particles' temperature, K.
const T_REACTANT: f64 = 298.15;
/// A trace of the other material where a cell holds only one.
const TRACE: f64 = 1.0e-6;

/// The coupled solver of a particle V-BURNRATE case at its start: the
/// products of ANFO-K1 (JWL C-term, ICE material 0) at `cfg.pressure` and
/// `cfg.products_temperature`, the reactant (ANFO-K1's Murnaghan EOS on the
/// fluid side, hypoelastic particles of its bulk modulus and a 1 GPa shear
/// modulus, ICE material 1) at 298.15 K, 2 × 2 particles a cell (in x–y) over
/// the shape of `cfg.surface`, burning by `cfg.law` with ANFO-K1's heat of
/// reaction; the message says what failed.
pub fn particle_slab(cfg: &BurnRate) -> Result<IceMpm, String> {
    let err = |e: &dyn std::fmt::Display| e.to_string();
    let (eos, jwlpp) = anfo_k1_jwlpp()?;
    let (reactant, products) = (eos[0].clone(), eos[1].clone());
    let p0 = cfg.pressure;
    let rho_r = reactant.density(p0, T_REACTANT).map_err(|e| err(&e))?;
    let rho_p = products
        .density(p0, cfg.products_temperature)
        .map_err(|e| err(&e))?;
    let bulk = match &reactant {
        EosModel::Murnaghan(m) => 1.0 / m.kappa,
        _ => return Err("the reactant's EOS is not a Murnaghan form".into()),
    };
    let state = move |theta: f64| CellState {
        pressure: p0,
        materials: vec![
            MaterialState {
                volume_fraction: 1.0 - theta,
                density: rho_p,
                velocity: [0.0; 3],
            },
            MaterialState {
                volume_fraction: theta,
                density: rho_r,
                velocity: [0.0; 3],
            },
        ],
    };
    let level = slab_level(cfg)?;
    let geometry = slab_geometry(cfg.surface);
    let mut ice = IceSolver::new(
        vec![products, reactant],
        level.clone(),
        slab_boundaries(cfg, IceBoundary::FixedState(state(TRACE))),
        ExchangeCoefficients::uniform(2, 1e15, 0.0),
        IceOptions {
            geometry,
            ..Default::default()
        },
        |x| state(initial_fraction(cfg, x).clamp(TRACE, 1.0 - TRACE)),
    )
    .map_err(|e| err(&e))?;
    ice.set_reactions(vec![IceReaction {
        reactant: 1,
        product: 0,
        rate: cfg.law.into(),
        heat_of_reaction: jwlpp.heat_of_reaction,
    }])
    .map_err(|e| err(&e))?;
    // Particles over the reactant's bounding box, then those whose centre
    // lies inside its shape.
    let g = &level.geometry;
    let mut particles = Particles::default();
    fill_shape_in(
        &mut particles,
        g,
        &FillSpec {
            shape: Shape::Box {
                min: g.origin,
                max: std::array::from_fn(|d| g.origin[d] + g.cells[d] as f64 * g.spacing[d]),
            },
            ppc: 2,
            density: rho_r,
            material: MaterialId(0),
            velocity: [0.0; 3],
            temperature: T_REACTANT,
            specific_internal_energy: 0.0,
        },
        geometry,
    )
    .map_err(|e| err(&e))?;
    let keep: Vec<usize> = (0..particles.len())
        .filter(|&p| initially_inside(cfg, particles.position[p]))
        .collect();
    particles.select(&keep);
    let mpm = MpmSolver::new(
        level,
        vec![hypoelastic(bulk, 1e9)],
        particles,
        MpmOptions {
            shape: ShapeFunction::Linear,
            scheme: UpdateScheme::Musl,
            boundaries: [GridBoundary::Symmetry; 6],
            geometry,
            ..Default::default()
        },
    )
    .map_err(|e| err(&e))?;
    IceMpm::new(ice, mpm, &[1]).map_err(|e| err(&e))
}

/// Runs one particle V-BURNRATE case and measures it as the fluid one
/// (`brisance_ice::burn_rate::burn_rate`), the reactant's volume being its
/// particles' mass over the reactant EOS's density at the held pressure
/// and 298.15 K (the particles' own volumes follow their hypoelastic
/// model, not that EOS); the message says what failed.
pub fn particle_burn_rate(cfg: &BurnRate) -> Result<BurnRateResult, String> {
    let mut s = particle_slab(cfg)?;
    let (eos, _) = anfo_k1_jwlpp()?;
    let rho_r = eos[0]
        .density(cfg.pressure, T_REACTANT)
        .map_err(|e| e.to_string())?;
    let mut measure = Regression::new(cfg)?;
    let t_end = measure.t_end();
    step_to(&mut s, t_end, |s, dt| {
        let mass: f64 = s.mpm().particles().mass.iter().sum();
        measure.record(s.time(), dt, mass / rho_r, s.ice().burning_surface(0));
        Ok(())
    })
    .map_err(|e| e.to_string())?;
    measure.finish(s.ice().steps())
}

#[cfg(test)]
mod tests {
    use super::*;
    use brisance_ice::burn_rate::BurnSurface;

    /// The particles fill the shape's sub-cells and no other: on the
    /// 45° corner every particle lies inside x + y < c₀ and their mass is
    /// ρ_r times the volume of the sub-cells (h/2)² h inside it.
    #[test]
    fn the_particles_fill_the_shape() {
        let cfg = BurnRate::pbx_9501(1.0e8, BurnSurface::Diagonal);
        let s = particle_slab(&cfg).unwrap();
        let p = s.mpm().particles();
        assert!(p.position.iter().all(|&x| initially_inside(&cfg, x)));
        let h = cfg.h;
        let c0 = (2.0 * cfg.extent_cells as f64 + 0.5) * h;
        // sub-cell centres at (a + ½) h/2 along x and y, a = 0, 1, ...
        let n = (2.0 * c0 / h).ceil() as usize;
        let inside = (0..n)
            .flat_map(|a| (0..n).map(move |b| (a, b)))
            .filter(|&(a, b)| (a as f64 + 0.5 + b as f64 + 0.5) * 0.5 * h < c0)
            .count();
        // (one particle a cell along z: the grid is one cell thick)
        assert_eq!(p.len(), inside);
        let (eos, _) = anfo_k1_jwlpp().unwrap();
        let rho = eos[0].density(1.0e8, T_REACTANT).unwrap();
        let mass: f64 = p.mass.iter().sum();
        let want = rho * inside as f64 * 0.25 * h * h * h;
        assert!(
            (mass / want - 1.0).abs() < 1e-12,
            "{mass:e} against {want:e}"
        );
    }

    /// A grid-aligned particle slab at 100 MPa with PBX-9501's A over 100
    /// regresses one cell at A pⁿ of its surface pressure within 1 %
    /// (V-BURNRATE measures +0.54 %), the surface pass's area (the
    /// default `gradient` estimate of a particle reactant) the slab's
    /// cross-section within 10⁻⁶ at every step (measured 9·10⁻⁸).
    #[test]
    fn a_particle_plane_regresses_at_a_p_to_the_n() {
        let r = particle_burn_rate(&BurnRate::a_over_100(BurnSurface::Plane)).unwrap();
        assert!(r.error().abs() < 0.01, "{r:?}");
        assert!((r.surface_pressure / 1.0e8 - 1.0).abs() < 1e-3, "{r:?}");
        assert!(r.area_error.abs() < 1e-6, "{r:?}");
    }
}
