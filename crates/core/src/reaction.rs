//! The reaction-model trait.

/// Local state a reaction rate may depend on.
#[derive(Debug, Clone, Copy, Default)]
pub struct ReactionState {
    /// Pressure, Pa.
    pub pressure: f64,
    /// Temperature, K.
    pub temperature: f64,
    /// Reactant density, kg/m³.
    pub density: f64,
    /// Simulation time, s: the end of the step being advanced.
    pub time: f64,
    /// The point's program-burn detonation time, s (`f64::INFINITY`:
    /// never); models that do not burn by a schedule ignore it.
    pub detonation_time: f64,
    /// Area of the reactant's burning surface per unit volume at the
    /// point, 1/m (0 where the point holds no surface): what the solver's
    /// surface pass found for a model whose
    /// [`ReactionModel::burns_on_a_surface`] is true; other models ignore
    /// it.
    pub surface_area_density: f64,
}

/// A mass-conversion model between a reactant and its product: the burn
/// fraction F advances at rate dF/dt (JWL++ `G (p+q)^b (1−F)`, pressure-power
/// deflagration, program burn, Arrhenius regression).
///
/// # Contract
/// - `0 ≤ F ≤ 1` after every advance and F never decreases.
/// - Mass is conserved exactly: the reactant loses what the product gains
///   ([`ReactionModel::mass_converted`]), and a cell burns between none
///   and all of its reactant ([`ReactionModel::burnt_density`]).
pub trait ReactionModel: Send + Sync + std::fmt::Debug {
    /// Registry name of the model.
    fn name(&self) -> &'static str;

    /// Whether the model burns on the reactant's surface (a deflagration):
    /// then the solver finds the surface before each step and gives every
    /// point its area per unit volume in
    /// [`ReactionState::surface_area_density`]. Volume-burning models
    /// (the default) need no surface pass.
    fn burns_on_a_surface(&self) -> bool {
        false
    }

    /// dF/dt at the given state and burn fraction, 1/s (≥ 0).
    fn rate(&self, state: &ReactionState, burn_fraction: f64) -> f64;

    /// Burn fraction after a step of `dt`, clamped to `[f, 1]`.
    fn advance(&self, state: &ReactionState, burn_fraction: f64, dt: f64) -> f64 {
        let f = burn_fraction + self.rate(state, burn_fraction).max(0.0) * dt;
        f.clamp(burn_fraction, 1.0)
    }

    /// Reactant mass converted to product when F goes from `f_old` to
    /// `f_new`, given the initial reactant mass.
    fn mass_converted(&self, initial_mass: f64, f_old: f64, f_new: f64) -> f64 {
        initial_mass * (f_new - f_old)
    }

    /// Reactant mass per unit volume burnt over `dt`, kg/m³, where the
    /// reactant and the product hold `rho_reactant` and `rho_product` of
    /// it (an Eulerian cell's two macroscopic densities): the burn fraction
    /// F = ρ_p/(ρ_r + ρ_p) (seed 000 eq 36) advanced over `dt`, times the
    /// explosive's density ρ_r + ρ_p (eq 37's Γ = (dF/dt)(ρ_r + ρ_p) over
    /// the step). Never negative, never more than `rho_reactant`; 0 where
    /// there is no reactant. A model may give the same law in its own
    /// arithmetic.
    fn burnt_density(
        &self,
        state: &ReactionState,
        rho_reactant: f64,
        rho_product: f64,
        dt: f64,
    ) -> f64 {
        if !(rho_reactant > 0.0) {
            return 0.0;
        }
        let rho_product = rho_product.max(0.0);
        let total = rho_reactant + rho_product;
        let f = rho_product / total;
        let burnt = (self.advance(state, f, dt) - f) * total;
        burnt.clamp(0.0, rho_reactant)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// dF/dt = k, constant.
    #[derive(Debug)]
    struct Constant(f64);

    impl ReactionModel for Constant {
        fn name(&self) -> &'static str {
            "Constant"
        }
        fn rate(&self, _: &ReactionState, _: f64) -> f64 {
            self.0
        }
    }

    #[test]
    fn the_burnt_density_is_the_fraction_advanced_times_the_explosive() {
        let s = ReactionState::default();
        // ρ_r 300, ρ_p 100: F = 0.25; ΔF = 1000 · 1e-4 = 0.1 → 0.1 · 400 = 40.
        let m = Constant(1000.0);
        assert!((m.burnt_density(&s, 300.0, 100.0, 1e-4) - 40.0).abs() < 1e-12);
        // F reaches 1 and stops there: all 300 kg/m³ of reactant, no more.
        assert_eq!(m.burnt_density(&s, 300.0, 100.0, 1.0), 300.0);
        // No reactant, nothing to burn; a zero step burns nothing.
        assert_eq!(m.burnt_density(&s, 0.0, 100.0, 1e-4), 0.0);
        assert_eq!(m.burnt_density(&s, 300.0, 100.0, 0.0), 0.0);
        assert_eq!(Constant(0.0).burnt_density(&s, 300.0, 0.0, 1e-4), 0.0);
    }
}
