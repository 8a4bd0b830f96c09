//! The JWL++ reactive-flow model of seed 000 §4.1.1 (Souers, Anderson,
//! Mercer, McGuire & Vitello, "JWL++: a simple reactive flow code package
//! for detonation", Propellants Explos. Pyrotech. 25 (2000) 54–58, seed 000
//! ref. 16).
//!
//! JWL++ is a reactant EOS, a products EOS and a rate law:
//! - reactant: Murnaghan, seed 000 eq 33 ([`brisance_eos::Murnaghan`]);
//! - products: JWL C-term form, seed 000 eq 34 as corrected in
//!   `docs/physics/eos/jwl_cterm.md` ([`brisance_eos::JwlCTerm`]);
//! - burn fraction F = ρ_product/(ρ_reactant + ρ_product) (eq 36), growing
//!   at dF/dt = G (p + q)^b (1 − F) (eq 35), with q = 0 as in the seed,
//!   and the mass burn rate Γ = (dF/dt)(ρ_reactant + ρ_product) (eq 37),
//!   kg/(m³·s), ρ here being each material's mass per unit cell volume.
//!
//! The seed's two extra rules: reaction only where p > 200 MPa, and no
//! more than 20 % of a cell's explosive reacts in one time step. The
//! second is read as 20 % of the reactant mass the cell holds at the start
//! of the step ([`JwlPlusPlus::max_burn_fraction`]), which also keeps the
//! reactant from being emptied in one step (see docs/physics/reaction/jwlpp.md
//! for the other reading and why this one is used).
//!
//! The "mixer" of JWL++ (the pressure of a partly burnt cell) is not part of
//! the model: the ICE equilibration pressure (seed 000 eq 7) plays its part,
//! as in the seed.
//!
//! The chemical energy released per kilogram burnt is the energy e₀ that
//! the JWL++ products hold at the unreacted state in their own energy
//! reference (the energy that puts the products Hugoniot through the CJ
//! point of the C-term isentrope, `tools::jwl_cterm_unreacted_state`),
//! less the reactant's energy at that state, which is zero for the
//! Murnaghan reference state (ρ₀, T_ref): [`detonation_energy`].
//!
//! Units: SI. G in s⁻¹·Pa⁻ᵇ, p in Pa, densities kg/m³.

use brisance_core::{ReactionModel, ReactionState};
use brisance_eos::tools::{cj_on_jwl_cterm_isentrope, CjState};
use brisance_eos::{JwlCTerm, Murnaghan};
use serde::{Deserialize, Serialize};

/// Why a JWL++ quantity cannot be formed.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum JwlppError {
    /// A parameter is out of range; the message names the field.
    #[error("jwlpp: field `{field}` = {value}: {expected}")]
    InvalidParameter {
        /// The offending field.
        field: &'static str,
        /// Its value.
        value: f64,
        /// The expected range.
        expected: &'static str,
    },
    /// The CJ state of the products could not be found.
    #[error("jwlpp: {0}")]
    Tool(#[from] brisance_eos::tools::ToolError),
}

/// The JWL++ rate law (seed 000 eqs 35–37) with the seed's threshold and
/// per-step limit.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct JwlPlusPlus {
    /// G, rate constant, s⁻¹·Pa⁻ᵇ (eq 35).
    pub g: f64,
    /// b, pressure exponent (eq 35).
    pub b: f64,
    /// Pressure above which the reaction runs, Pa (seed: 200 MPa).
    #[serde(default = "default_threshold")]
    pub threshold_pressure: f64,
    /// Largest fraction of a cell's reactant mass burnt in one step
    /// (seed: 0.2), in (0, 1).
    #[serde(default = "default_max_burn_fraction")]
    pub max_burn_fraction: f64,
}

fn default_threshold() -> f64 {
    JwlPlusPlus::SEED_THRESHOLD_PRESSURE
}
fn default_max_burn_fraction() -> f64 {
    JwlPlusPlus::SEED_MAX_BURN_FRACTION
}

impl JwlPlusPlus {
    /// Seed 000 §4.1.1: "reaction begins in a cell when the pressure in
    /// that cell exceeds 200 MPa", Pa.
    pub const SEED_THRESHOLD_PRESSURE: f64 = 200.0e6;
    /// Seed 000 §4.1.1: "no more than 20 % of the explosive in a cell is
    /// allowed to react in a given timestep".
    pub const SEED_MAX_BURN_FRACTION: f64 = 0.2;

    /// ANFO-K1, seed 000 §5.1: G = 3.5083 × 10⁻⁷ s⁻¹·Pa⁻ᵇ, b = 1.3, with
    /// the seed's threshold and limit.
    pub fn anfo_k1() -> Self {
        Self {
            g: 3.5083e-7,
            b: 1.3,
            threshold_pressure: Self::SEED_THRESHOLD_PRESSURE,
            max_burn_fraction: Self::SEED_MAX_BURN_FRACTION,
        }
    }

    /// Checks every parameter, naming the bad field.
    pub fn validate(&self) -> Result<(), JwlppError> {
        let bad = |field, value, expected| {
            Err(JwlppError::InvalidParameter {
                field,
                value,
                expected,
            })
        };
        if !(self.g > 0.0 && self.g.is_finite()) {
            return bad("g", self.g, "a finite value > 0 (s⁻¹·Pa⁻ᵇ)");
        }
        if !(self.b > 0.0 && self.b.is_finite()) {
            return bad("b", self.b, "a finite value > 0");
        }
        if !(self.threshold_pressure >= 0.0 && self.threshold_pressure.is_finite()) {
            return bad(
                "threshold_pressure",
                self.threshold_pressure,
                "a finite value ≥ 0 (Pa)",
            );
        }
        if !(self.max_burn_fraction > 0.0 && self.max_burn_fraction < 1.0) {
            return bad(
                "max_burn_fraction",
                self.max_burn_fraction,
                "a value in (0, 1)",
            );
        }
        Ok(())
    }

    /// Burn fraction F = ρ_product/(ρ_reactant + ρ_product) (seed 000
    /// eq 36); 0 for an empty cell.
    #[inline]
    pub fn burn_fraction(rho_reactant: f64, rho_product: f64) -> f64 {
        let total = rho_reactant + rho_product;
        if total > 0.0 {
            rho_product / total
        } else {
            0.0
        }
    }

    /// dF/dt = G p^b (1 − F) (seed 000 eq 35 with q = 0), 1/s; zero at or
    /// below the threshold pressure.
    #[inline]
    pub fn burn_rate(&self, pressure: f64, burn_fraction: f64) -> f64 {
        if pressure > self.threshold_pressure {
            self.g * pressure.powf(self.b) * (1.0 - burn_fraction)
        } else {
            0.0
        }
    }

    /// Mass burn rate Γ = (dF/dt)(ρ_reactant + ρ_product) (seed 000 eq 37),
    /// kg/(m³·s). Since (1 − F)(ρ_reactant + ρ_product) = ρ_reactant this is
    /// G p^b ρ_reactant above the threshold.
    #[inline]
    pub fn mass_burn_rate(&self, pressure: f64, rho_reactant: f64, rho_product: f64) -> f64 {
        let f = Self::burn_fraction(rho_reactant, rho_product);
        self.burn_rate(pressure, f) * (rho_reactant + rho_product)
    }

    /// Mass per unit cell volume burnt over `dt`, kg/m³: Γ Δt, at most
    /// `max_burn_fraction` of the reactant present (the seed's 20 % rule).
    /// Never negative, never more than the reactant.
    #[inline]
    pub fn burnt_density(
        &self,
        pressure: f64,
        rho_reactant: f64,
        rho_product: f64,
        dt: f64,
    ) -> f64 {
        if !(rho_reactant > 0.0) {
            return 0.0;
        }
        let burnt = self.mass_burn_rate(pressure, rho_reactant, rho_product) * dt;
        burnt.min(self.max_burn_fraction * rho_reactant).max(0.0)
    }
}

/// JWL++ behind the [`ReactionModel`] trait: dF/dt = G p^b (1 − F) above
/// the threshold (seed 000 eq 35), and a step burns at most
/// `max_burn_fraction` of the reactant left, ΔF ≤ max_burn_fraction (1 − F)
/// (the seed's 20 % rule, as [`JwlPlusPlus::burnt_density`] applies it to
/// densities: ΔF (ρ_r + ρ_p) = burnt density, since (1 − F)(ρ_r + ρ_p) =
/// ρ_r). Its [`ReactionModel::burnt_density`], which the ICE's step 4
/// calls, is [`JwlPlusPlus::burnt_density`]: the same law in the
/// densities' own arithmetic, G p^b ρ_r Δt capped at 20 % of ρ_r.
impl ReactionModel for JwlPlusPlus {
    fn name(&self) -> &'static str {
        "JwlPlusPlus"
    }

    fn rate(&self, state: &ReactionState, burn_fraction: f64) -> f64 {
        self.burn_rate(state.pressure, burn_fraction).max(0.0)
    }

    fn advance(&self, state: &ReactionState, burn_fraction: f64, dt: f64) -> f64 {
        let left = (1.0 - burn_fraction).max(0.0);
        let step = (self.rate(state, burn_fraction) * dt).min(self.max_burn_fraction * left);
        (burn_fraction + step.max(0.0)).clamp(burn_fraction, 1.0)
    }

    fn burnt_density(
        &self,
        state: &ReactionState,
        rho_reactant: f64,
        rho_product: f64,
        dt: f64,
    ) -> f64 {
        JwlPlusPlus::burnt_density(self, state.pressure, rho_reactant, rho_product, dt)
    }
}

/// The CJ state of the JWL++ products (Rayleigh line from (v₀, p = 0)
/// tangent to the C-term isentrope): the ideal, infinite-radius detonation
/// velocity a rate stick tends to.
pub fn cj_state(products: &JwlCTerm) -> Result<CjState, JwlppError> {
    Ok(cj_on_jwl_cterm_isentrope(products)?)
}

/// Chemical energy released per kilogram burnt, J/kg: the products'
/// energy e₀ at the unreacted state (their own reference), less the
/// reactant's energy at its reference state (ρ₀, T_ref), which is zero for
/// [`Murnaghan`]. The reactant's ρ₀ must be the products' ρ₀.
pub fn detonation_energy(reactant: &Murnaghan, products: &JwlCTerm) -> Result<f64, JwlppError> {
    if reactant.rho0 != products.rho0 {
        return Err(JwlppError::InvalidParameter {
            field: "rho0",
            value: reactant.rho0,
            expected: "the reactant's ρ₀ equal to the products' ρ₀",
        });
    }
    let e0 = cj_state(products)?.unreacted.specific_internal_energy;
    Ok(e0 - reactant.compression_energy(reactant.rho0))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn anfo_k1_rates_are_the_hand_computed_ones() {
        let m = JwlPlusPlus::anfo_k1();
        assert!(m.validate().is_ok());
        // G p^b at p = 1e10 Pa: 3.5083e-7 · (1e10)^1.3 = 3.5083e-7 · 1e13 = 3.5083e6 /s.
        let r = m.burn_rate(1e10, 0.0);
        assert!((r - 3.5083e6).abs() < 1e-6 * 3.5083e6, "{r}");
        // p = 1 GPa, F = 0.25: 3.5083e-7 · 10^11.7 · 0.75 = 3.5083e-7 · 5.011872336e11 · 0.75
        // = 1.3187363788e5 /s.
        let r = m.burn_rate(1e9, 0.25);
        assert!((r - 1.3187363788e5).abs() < 1e-9 * 1.3e5, "{r}");
        // Just above the 200 MPa threshold: 3.5083e-7 · (2e8)^1.3 = 2.16988e4 /s.
        let r = m.burn_rate(2.0000001e8, 0.0);
        assert!((r - 2.16988e4).abs() < 1.0, "{r}");
        // At and below the threshold nothing burns.
        assert_eq!(m.burn_rate(2.0e8, 0.0), 0.0);
        assert_eq!(m.burn_rate(1.0e5, 0.0), 0.0);
        // Fully burnt: no rate.
        assert_eq!(m.burn_rate(1e10, 1.0), 0.0);
    }

    #[test]
    fn burn_fraction_and_mass_rate_follow_eqs_36_and_37() {
        assert_eq!(JwlPlusPlus::burn_fraction(300.0, 100.0), 0.25);
        assert_eq!(JwlPlusPlus::burn_fraction(0.0, 0.0), 0.0);
        let m = JwlPlusPlus::anfo_k1();
        // Γ = dF/dt · (ρ_r + ρ_p) = G p^b (1 − F)(ρ_r + ρ_p) = G p^b ρ_r:
        // 3.5083e6 · 300 = 1.05249e9 kg/(m³·s) at 10 GPa.
        let gamma = m.mass_burn_rate(1e10, 300.0, 100.0);
        assert!((gamma - 1.05249e9).abs() < 1e-6 * 1.05249e9, "{gamma}");
    }

    #[test]
    fn at_most_a_fifth_of_the_reactant_burns_in_a_step() {
        let m = JwlPlusPlus::anfo_k1();
        // 1 GPa, ρ_r = 1000, ρ_p = 0, Δt = 1e-7: Γ Δt = 1.758315e5 · 1000 · 1e-7
        // = 17.58315 kg/m³, below the 200 kg/m³ limit.
        let dm = m.burnt_density(1e9, 1000.0, 0.0, 1e-7);
        assert!((dm - 17.583151717).abs() < 1e-6, "{dm}");
        // 10 GPa, Δt = 1e-7: G p^b Δt = 0.35083 > 0.2, capped at 0.2 · 1000.
        assert_eq!(m.burnt_density(1e10, 1000.0, 0.0, 1e-7), 200.0);
        // No reactant, nothing burnt; below threshold, nothing burnt.
        assert_eq!(m.burnt_density(1e10, 0.0, 50.0, 1e-7), 0.0);
        assert_eq!(m.burnt_density(1e8, 1000.0, 0.0, 1e-7), 0.0);
    }

    /// Through the trait: ΔF = G p^b (1 − F) Δt below the cap, the cap
    /// 0.2 (1 − F) above it, nothing at the threshold; and ΔF (ρ_r + ρ_p)
    /// is the density `burnt_density` gives the ICE step.
    #[test]
    fn the_trait_burns_what_the_ice_step_burns() {
        let m = JwlPlusPlus::anfo_k1();
        assert_eq!(m.name(), "JwlPlusPlus");
        let at = |p: f64| ReactionState {
            pressure: p,
            detonation_time: f64::INFINITY,
            surface_area_density: 0.0,
            ..Default::default()
        };
        // 1 GPa, F = 0.25, Δt = 1e-7: 1.3187363788e5 · 1e-7 = 1.3187363788e-2.
        let f = m.advance(&at(1e9), 0.25, 1e-7);
        assert!((f - 0.25 - 1.3187363788e-2).abs() < 1e-12, "{f}");
        // 10 GPa: G p^b (1 − F) Δt = 0.2631 > 0.2 · 0.75 = 0.15: capped.
        assert!((m.advance(&at(1e10), 0.25, 1e-7) - 0.4).abs() < 1e-15);
        assert_eq!(m.advance(&at(2.0e8), 0.25, 1e-7), 0.25);
        assert_eq!(m.advance(&at(1e10), 1.0, 1e-7), 1.0);
        for &(p, rr, rp, dt) in &[
            (1e9, 1000.0, 0.0, 1e-7),
            (5e9, 300.0, 100.0, 2e-8),
            (1e10, 800.0, 50.0, 1e-7),
        ] {
            let f0 = JwlPlusPlus::burn_fraction(rr, rp);
            let df = m.advance(&at(p), f0, dt) - f0;
            let dm = m.burnt_density(p, rr, rp, dt);
            // The trait's burnt density is that very arithmetic.
            assert_eq!(ReactionModel::burnt_density(&m, &at(p), rr, rp, dt), dm);
            assert!(
                (df * (rr + rp) - dm).abs() <= 1e-12 * dm,
                "{} vs {dm}",
                df * (rr + rp)
            );
        }
    }

    proptest::proptest! {
        /// The `ReactionModel` contract over pressures from below the
        /// threshold to 50 GPa, any burn fraction and step.
        #[test]
        fn jwlpp_keeps_the_reaction_model_contract(
            p in 0.0f64..5e10, f in 0.0f64..=1.0, dt in 0.0f64..1e-6, g in 1e-8f64..1e-4, b in 0.5f64..2.0,
        ) {
            let m = JwlPlusPlus { g, b, ..JwlPlusPlus::anfo_k1() };
            let state = ReactionState { pressure: p, detonation_time: f64::INFINITY, ..Default::default() };
            let r = brisance_core::contracts::check_reaction_model(&m, &state, f, dt);
            proptest::prop_assert!(r.is_ok(), "{:?}", r);
        }
    }

    #[test]
    fn bad_parameters_name_the_field() {
        let mut m = JwlPlusPlus::anfo_k1();
        m.b = -1.0;
        assert!(m.validate().unwrap_err().to_string().contains("`b`"));
        let mut m = JwlPlusPlus::anfo_k1();
        m.max_burn_fraction = 1.0;
        assert!(m
            .validate()
            .unwrap_err()
            .to_string()
            .contains("max_burn_fraction"));
        let mut m = JwlPlusPlus::anfo_k1();
        m.g = f64::NAN;
        assert!(m.validate().unwrap_err().to_string().contains("`g`"));
        let mut m = JwlPlusPlus::anfo_k1();
        m.threshold_pressure = -1.0;
        assert!(m
            .validate()
            .unwrap_err()
            .to_string()
            .contains("threshold_pressure"));
    }

    #[test]
    fn config_defaults_are_the_seed_rules() {
        let m: JwlPlusPlus = ron::from_str("(g: 3.5083e-7, b: 1.3)").unwrap();
        assert_eq!(m, JwlPlusPlus::anfo_k1());
        assert!(ron::from_str::<JwlPlusPlus>("(g: 1.0, b: 1.0, q: 0.0)").is_err());
    }

    #[test]
    fn anfo_k1_detonation_energy_and_cj_velocity() {
        let (r, p) = (Murnaghan::anfo_k1(), JwlCTerm::anfo_k1());
        let q = detonation_energy(&r, &p).unwrap();
        // docs/physics/eos/jwl_cterm.md: e₀ = 3.448 MJ/kg, D_CJ = 5899 m/s.
        assert!((q - 3.448e6).abs() < 1e3, "{q}");
        let d = cj_state(&p).unwrap().detonation_velocity;
        assert!((d - 5899.0).abs() < 1.0, "{d}");
        // The reactant's energy at its reference state is zero, so Q = e₀.
        assert_eq!(r.compression_energy(r.rho0), 0.0);
        let mut other = r;
        other.rho0 = 1000.0;
        assert!(detonation_energy(&other, &p)
            .unwrap_err()
            .to_string()
            .contains("rho0"));
    }
}
