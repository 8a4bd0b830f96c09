//! First-order Arrhenius decomposition: dF/dt = Z exp(−E/(R T)) (1 − F).

use brisance_core::{ReactionModel, ReactionState};
use brisance_reaction::arrhenius::GAS_CONSTANT;
use serde::{Deserialize, Serialize};

/// First-order Arrhenius decomposition of a reactant in its volume.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ThermalDecomposition {
    /// Pre-exponential factor Z, 1/s.
    pub z: f64,
    /// Activation energy E, J/mol.
    pub activation_energy: f64,
}

impl ThermalDecomposition {
    /// Checks the parameters; the message names the bad field.
    pub fn validate(&self) -> Result<(), String> {
        if !(self.z.is_finite() && self.z > 0.0) {
            return Err(format!(
                "z: must be a finite rate > 0 (1/s), got {}",
                self.z
            ));
        }
        if !(self.activation_energy.is_finite() && self.activation_energy >= 0.0) {
            return Err(format!(
                "activation_energy: must be finite and ≥ 0 (J/mol), got {}",
                self.activation_energy
            ));
        }
        Ok(())
    }

    /// The rate constant k(T) = Z exp(−E/(R T)), 1/s; 0 at a temperature
    /// that is not positive and finite.
    pub fn rate_constant(&self, temperature: f64) -> f64 {
        if !(temperature.is_finite() && temperature > 0.0) {
            return 0.0;
        }
        self.z * (-self.activation_energy / (GAS_CONSTANT * temperature)).exp()
    }

    /// The adiabatic induction time of thermal explosion theory at the
    /// initial temperature `t0` (Frank-Kamenetskii 1955; large activation
    /// energy, no reactant consumption): t_ad = c_v R T₀² / (Q E k(T₀)),
    /// for a specific heat `cv` (J/(kg·K)) and heat of reaction `q` (J/kg).
    pub fn adiabatic_induction_time(&self, t0: f64, cv: f64, q: f64) -> f64 {
        cv * GAS_CONSTANT * t0 * t0 / (q * self.activation_energy * self.rate_constant(t0))
    }
}

impl ReactionModel for ThermalDecomposition {
    fn name(&self) -> &'static str {
        "ThermalDecomposition"
    }

    fn rate(&self, state: &ReactionState, burn_fraction: f64) -> f64 {
        self.rate_constant(state.temperature) * (1.0 - burn_fraction).max(0.0)
    }

    /// The exact step at the state's temperature: 1 − F falls by
    /// exp(−k Δt), so the step never overshoots F = 1 and its error is the
    /// temperature's change over the step alone.
    fn advance(&self, state: &ReactionState, burn_fraction: f64, dt: f64) -> f64 {
        let k = self.rate_constant(state.temperature);
        let left = (1.0 - burn_fraction).max(0.0);
        // F + (1 − F)(1 − e^{−kΔt}), with e^{−x} − 1 taken whole so that a
        // zero step leaves F to the bit.
        let f = burn_fraction - left * (-k * dt.max(0.0)).exp_m1();
        f.clamp(burn_fraction, 1.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    const HMX_LIKE: ThermalDecomposition = ThermalDecomposition {
        z: 5.0e19,
        activation_energy: 2.2e5,
    };

    fn at(temperature: f64) -> ReactionState {
        ReactionState {
            pressure: 1.0e5,
            temperature,
            density: 1800.0,
            time: 0.0,
            detonation_time: f64::INFINITY,
            surface_area_density: 0.0,
        }
    }

    #[test]
    fn the_rate_is_the_arrhenius_law_by_hand() {
        // k(500 K) = 5e19 exp(−2.2e5/(8.314462618 × 500))
        //          = 5e19 exp(−52.9198) = 5e19 × 1.0404e-23 = 5.202e-4 1/s.
        let k = HMX_LIKE.rate_constant(500.0);
        let by_hand = 5.0e19 * (-2.2e5_f64 / (8.314_462_618 * 500.0)).exp();
        assert_eq!(k, by_hand);
        assert!((k - 5.202e-4).abs() < 1e-7, "{k}");
        // Half burnt: half the rate.
        assert_eq!(HMX_LIKE.rate(&at(500.0), 0.5), 0.5 * k);
        // E = 0: the rate is Z at any temperature.
        let flat = ThermalDecomposition {
            activation_energy: 0.0,
            ..HMX_LIKE
        };
        assert_eq!(flat.rate(&at(300.0), 0.0), 5.0e19);
        assert_eq!(HMX_LIKE.rate(&at(0.0), 0.0), 0.0);
        assert_eq!(HMX_LIKE.rate(&at(f64::NAN), 0.0), 0.0);
    }

    #[test]
    fn a_step_is_the_exact_exponential_at_fixed_temperature() {
        let k = HMX_LIKE.rate_constant(600.0);
        let dt = 0.3 / k;
        let f = HMX_LIKE.advance(&at(600.0), 0.2, dt);
        assert!((f - (1.0 - 0.8 * (-0.3_f64).exp())).abs() < 1e-15);
        // Two half steps make one whole one.
        let half = HMX_LIKE.advance(&at(600.0), 0.2, 0.5 * dt);
        let two = HMX_LIKE.advance(&at(600.0), half, 0.5 * dt);
        assert!((two - f).abs() < 1e-15);
        // A very long step burns everything and no more.
        assert_eq!(HMX_LIKE.advance(&at(600.0), 0.2, 1e6 / k), 1.0);
    }

    #[test]
    fn the_induction_time_is_frank_kamenetskii_by_hand() {
        // c_v 1000 J/(kg K), Q 5 MJ/kg, T₀ 500 K:
        // t = 1000 × 8.314 × 500² / (5e6 × 2.2e5 × k(500)).
        let k = HMX_LIKE.rate_constant(500.0);
        let t = HMX_LIKE.adiabatic_induction_time(500.0, 1000.0, 5.0e6);
        let by_hand = 1000.0 * 8.314_462_618 * 250_000.0 / (5.0e6 * 2.2e5 * k);
        assert!((t / by_hand - 1.0).abs() < 1e-14);
    }

    #[test]
    fn bad_parameters_name_their_field() {
        let e = ThermalDecomposition { z: 0.0, ..HMX_LIKE }
            .validate()
            .unwrap_err();
        assert!(e.starts_with("z:"), "{e}");
        let e = ThermalDecomposition {
            activation_energy: -1.0,
            ..HMX_LIKE
        }
        .validate()
        .unwrap_err();
        assert!(e.starts_with("activation_energy:"), "{e}");
        assert!(HMX_LIKE.validate().is_ok());
    }

    #[test]
    fn registered_and_parsed_from_ron() {
        let mut registry = brisance_reaction::plugin::ReactionRegistry::new();
        crate::register(&mut registry);
        let p = registry.get("ThermalDecomposition").unwrap();
        let (m, params) = (p.parse)("(z: 5.0e19, activation_energy: 2.2e5)").unwrap();
        assert_eq!(m.rate(&at(500.0), 0.0), HMX_LIKE.rate_constant(500.0));
        assert_eq!(
            (p.parse)("z: 5e19,activation_energy: 220000.0").unwrap().1,
            params
        );
        let bad = "(z: -1.0, activation_energy: 2.2e5)";
        assert!((p.parse)(bad).unwrap_err().contains("z:"));
        let unknown = "(z: 1.0, activation_energy: 2.2e5, n: 1.0)";
        assert!((p.parse)(unknown).unwrap_err().contains('n'));
    }

    proptest! {
        #[test]
        fn thermal_decomposition_keeps_the_reaction_model_contract(
            log_z in 0.0f64..25.0,
            e in 0.0f64..3.0e5,
            t in 1.0f64..5000.0,
            f in 0.0f64..=1.0,
            dt in 0.0f64..1.0,
        ) {
            let m = ThermalDecomposition { z: 10f64.powf(log_z), activation_energy: e };
            let r = brisance_core::contracts::check_reaction_model(&m, &at(t), f, dt);
            prop_assert!(r.is_ok(), "{:?}", r);
        }
    }
}
