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
}

/// A mass-conversion model between a reactant and its product: the burn
/// fraction F advances at rate dF/dt (JWL++ `G (p+q)^b (1−F)`, pressure-power
/// deflagration, program burn, Arrhenius regression).
///
/// # Contract
/// - `0 ≤ F ≤ 1` after every advance and F never decreases.
/// - Mass is conserved exactly: the reactant loses what the product gains
///   ([`ReactionModel::mass_converted`]).
pub trait ReactionModel: Send + Sync + std::fmt::Debug {
    /// Registry name of the model.
    fn name(&self) -> &'static str;

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
}
