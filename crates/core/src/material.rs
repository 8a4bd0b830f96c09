//! The constitutive-model trait.

use crate::{Eos, Mat3};

/// What a stress update sees at one material point.
#[derive(Debug, Clone, Copy)]
pub struct StressUpdateInput {
    /// Velocity gradient L = ∂v/∂x over the step, 1/s.
    pub velocity_gradient: Mat3,
    /// Time step, s.
    pub dt: f64,
    /// Current density, kg/m³.
    pub density: f64,
    /// Current temperature, K.
    pub temperature: f64,
    /// Current specific internal energy, J/kg.
    pub specific_internal_energy: f64,
    /// Cauchy stress at the start of the step, Pa (tension positive).
    pub stress: Mat3,
}

/// What a stress update returns.
#[derive(Debug, Clone, Copy)]
pub struct StressUpdate {
    /// Cauchy stress at the end of the step, Pa.
    pub stress: Mat3,
    /// Plastic work per unit volume done in the step, J/m³ (≥ 0).
    pub plastic_work: f64,
    /// Whether the point has failed (irreversible).
    pub failed: bool,
}

/// A constitutive model: from the velocity gradient, dt, density, temperature
/// and its own history variables, the new Cauchy stress, the plastic work and
/// whether the point has failed.
///
/// # Contract
/// - Objectivity: superposing a rigid rotation on the motion rotates the
///   updated stress and changes nothing else.
/// - For elastic models, zero strain rate leaves the stress unchanged.
/// - After the return mapping the yield surface is never exceeded.
/// - Failure is irreversible: once `failed` is returned for a point it is
///   returned for every later update of that point.
///
/// History variables live in a per-point slice of length
/// [`Material::history_len`], owned by the solver (structure of arrays).
pub trait Material: Send + Sync + std::fmt::Debug {
    /// Registry name of the model.
    fn name(&self) -> &'static str;

    /// Number of `f64` history variables per material point.
    fn history_len(&self) -> usize;

    /// Initial values of the history variables.
    fn init_history(&self, history: &mut [f64]);

    /// Initial values of the history variables of one material point, for
    /// models whose initial state is drawn per point from a distribution
    /// (seed 000 §4.2: Gaussian initial porosity and damage). `seed`
    /// identifies the point; the values must depend on it alone — not on
    /// the order of the calls or on the thread — so a solver that derives
    /// it from the point's initial position and material gets the same bits
    /// whatever its thread count or particle order. Models without per-point
    /// randomness keep this default, [`Material::init_history`].
    fn init_history_at(&self, history: &mut [f64], seed: u64) {
        let _ = seed;
        self.init_history(history);
    }

    /// Advances the stress over one step.
    fn update_stress(&self, input: &StressUpdateInput, history: &mut [f64]) -> StressUpdate;

    /// The equation of state for the volumetric part, if the model has one.
    fn eos(&self) -> Option<&dyn Eos>;

    /// Longitudinal wave speed at the given state, m/s, for the time step.
    fn wave_speed(&self, density: f64, specific_internal_energy: f64) -> f64;
}
