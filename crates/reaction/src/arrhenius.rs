//! The Arrhenius surface regression of seed 003 (§2.4, §3.1–3.2): a solid
//! exposed to a fluid pyrolyses at the mass flux
//!
//! ṁ'' = Ω A exp(−Eₐ/(R T))            kg/(m²·s)
//!
//! (A the pre-exponential factor, Eₐ the activation energy, T the surface's
//! temperature, Ω the catalytic factor of §3.2), so its surface recedes at
//! r = ṁ''/ρ, ρ the solid's density. The MSDM lattice regresses its exposed
//! nodes by it (`brisance_lattice::regress`,
//! docs/physics/lattice/regression.md); as a [`ReactionModel`] it burns on a
//! surface like the deflagration ([`crate::Deflagration`]), Γ = a ṁ'' with
//! a the surface's area in the cell.

use brisance_core::{ReactionModel, ReactionState};
use serde::{Deserialize, Serialize};

use crate::deflagration::surface_burnt_density;

/// Universal gas constant R, J/(mol·K).
pub const GAS_CONSTANT: f64 = 8.314_462_618;

fn one() -> f64 {
    1.0
}

/// Arrhenius pyrolysis law of a material (seed 003 §2.4, §3.1–3.2).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Arrhenius {
    /// Pre-exponential factor A, kg/(m²·s).
    pub pre_exponential: f64,
    /// Activation energy Eₐ, J/mol.
    pub activation_energy: f64,
    /// Catalytic factor Ω multiplying A (§3.2; 1 without additive).
    #[serde(default = "one")]
    pub catalytic_factor: f64,
}

impl Arrhenius {
    /// Mass flux Ω A exp(−Eₐ/(R T)), kg/(m²·s).
    #[inline]
    pub fn mass_flux(&self, temperature: f64) -> f64 {
        self.catalytic_factor
            * self.pre_exponential
            * (-self.activation_energy / (GAS_CONSTANT * temperature)).exp()
    }

    /// Regression speed Ω A exp(−Eₐ/(R T)) / ρ₀, m/s.
    #[inline]
    pub fn speed(&self, rho0: f64, temperature: f64) -> f64 {
        self.mass_flux(temperature) / rho0
    }

    /// Checks the parameters; `field` prefixes the field names.
    pub fn validate(&self, field: &str) -> Result<(), String> {
        for (name, v) in [
            ("pre_exponential", self.pre_exponential),
            ("catalytic_factor", self.catalytic_factor),
        ] {
            if !(v > 0.0 && v.is_finite()) {
                return Err(format!("{field}.{name} = {v}, expected a finite value > 0"));
            }
        }
        if !(self.activation_energy >= 0.0 && self.activation_energy.is_finite()) {
            return Err(format!(
                "{field}.activation_energy = {}, expected a finite value ≥ 0",
                self.activation_energy
            ));
        }
        Ok(())
    }

    /// ṁ'' at a state, 0 where it is not a finite positive number (a
    /// temperature of 0 K or below, a NaN).
    #[inline]
    fn flux_at(&self, state: &ReactionState) -> f64 {
        let m = self.mass_flux(state.temperature);
        if m > 0.0 && m.is_finite() && state.temperature > 0.0 {
            m
        } else {
            0.0
        }
    }
}

/// The regression as a surface burn (the same contract as
/// [`crate::Deflagration`]'s):
/// - [`ReactionModel::rate`] is dF/dt = (a/V) ṁ''/ρ of a cell full of the
///   solid, the share of its volume the front sweeps per second, with
///   a/V = [`ReactionState::surface_area_density`] (1/m), T the surface's
///   temperature and ρ = [`ReactionState::density`] the solid's own density
///   (0 once F = 1, off the surface, or where ρ ≤ 0). With a/V = 1 it is
///   the surface's speed r in m/s, which is how the lattice asks for it.
/// - [`ReactionModel::burnt_density`] is Γ Δt / V = (a/V) ṁ'' Δt, at most
///   the cell's solid.
impl ReactionModel for Arrhenius {
    fn name(&self) -> &'static str {
        "Arrhenius"
    }

    fn burns_on_a_surface(&self) -> bool {
        true
    }

    fn rate(&self, state: &ReactionState, burn_fraction: f64) -> f64 {
        if burn_fraction >= 1.0 || !(state.surface_area_density > 0.0 && state.density > 0.0) {
            return 0.0;
        }
        (state.surface_area_density * (self.flux_at(state) / state.density)).max(0.0)
    }

    fn burnt_density(
        &self,
        state: &ReactionState,
        rho_reactant: f64,
        _rho_product: f64,
        dt: f64,
    ) -> f64 {
        surface_burnt_density(state, rho_reactant, dt, || {
            state.surface_area_density * self.flux_at(state)
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Ammonium perchlorate of seed 003 §3.1.
    fn ap() -> Arrhenius {
        Arrhenius {
            pre_exponential: 5.0e6,
            activation_energy: 92_109.6,
            catalytic_factor: 1.0,
        }
    }

    fn at(temperature: f64, density: f64, area: f64) -> ReactionState {
        ReactionState {
            temperature,
            density,
            surface_area_density: area,
            ..Default::default()
        }
    }

    #[test]
    fn the_rate_is_the_front_speed_over_the_cell_depth() {
        // AP at 823 K: ṁ'' = 5e6 exp(−92109.6 / (8.314462618 · 823))
        // = 7.128838597305868 kg/(m²·s); ρ 1950 kg/m³; a/V 1/h, h = 1 mm.
        let m = ap();
        let flux = 7.128_838_597_305_868;
        let r = m.rate(&at(823.0, 1950.0, 1e3), 0.0);
        assert!((r - 1e3 * flux / 1950.0).abs() < 1e-12 * r, "{r}");
        // With a/V = 1 the rate is the speed the lattice uses, to the bit.
        assert_eq!(m.rate(&at(823.0, 1950.0, 1.0), 0.3), m.speed(1950.0, 823.0));
        // Nothing off the surface, once burnt, or without a density.
        assert_eq!(m.rate(&at(823.0, 1950.0, 0.0), 0.0), 0.0);
        assert_eq!(m.rate(&at(823.0, 1950.0, 1e3), 1.0), 0.0);
        assert_eq!(m.rate(&at(823.0, 0.0, 1e3), 0.0), 0.0);
        assert_eq!(m.rate(&at(0.0, 1950.0, 1e3), 0.0), 0.0);
    }

    #[test]
    fn the_burnt_density_is_a_over_v_times_the_flux_and_the_step() {
        let m = ap();
        let flux = 7.128_838_597_305_868;
        // a/V = 1e3 1/m, Δt = 1e-4 s: 1e3 · 7.1288 · 1e-4 = 0.71288 kg/m³.
        let b = m.burnt_density(&at(823.0, 1950.0, 1e3), 1950.0, 0.0, 1e-4);
        assert!((b - 0.1 * flux).abs() < 1e-12 * b, "{b}");
        // At most the cell's solid.
        assert_eq!(
            m.burnt_density(&at(823.0, 1950.0, 1e3), 0.5, 0.0, 1e-4),
            0.5
        );
        assert_eq!(
            m.burnt_density(&at(823.0, 1950.0, 0.0), 1950.0, 0.0, 1e-4),
            0.0
        );
        assert!(m.burns_on_a_surface());
        assert_eq!(m.name(), "Arrhenius");
    }

    proptest::proptest! {
        /// The `ReactionModel` contract at any surface temperature, density,
        /// area density, burn fraction and step.
        #[test]
        fn arrhenius_keeps_the_reaction_model_contract(
            t in -10.0_f64..3000.0, rho in 0.0_f64..3000.0,
            a_v in 0.0_f64..1e5, f in 0.0_f64..=1.0, dt in 0.0_f64..1e-3,
            e_a in 0.0_f64..2e5, omega in 0.1_f64..3.0,
        ) {
            let m = Arrhenius { activation_energy: e_a, catalytic_factor: omega, ..ap() };
            let state = at(t, rho, a_v);
            let r = brisance_core::contracts::check_reaction_model(&m, &state, f, dt);
            proptest::prop_assert!(r.is_ok(), "{:?}", r);
        }

        /// ṁ'' grows with the temperature and with Ω.
        #[test]
        fn the_flux_grows_with_the_temperature(
            t in 1.0_f64..3000.0, dt in 0.0_f64..1000.0, e_a in 0.0_f64..2e5,
        ) {
            let m = Arrhenius { activation_energy: e_a, ..ap() };
            proptest::prop_assert!(m.mass_flux(t + dt) >= m.mass_flux(t));
            let c = Arrhenius { catalytic_factor: 1.41, ..m };
            proptest::prop_assert!(c.mass_flux(t) >= m.mass_flux(t));
        }
    }
}
