//! Brisance first-order Arrhenius thermal decomposition, a reaction model
//! in its own crate (a plugin).
//!
//! The bulk reaction of thermal explosion theory (Frank-Kamenetskii,
//! *Diffusion and Heat Exchange in Chemical Kinetics*, 1955, ch. VI;
//! Semenov 1928): the reactant decomposes everywhere in its volume at the
//! first-order Arrhenius rate
//!
//! ```text
//! dF/dt = Z exp(−E/(R T)) (1 − F),
//! ```
//!
//! Z the pre-exponential factor (1/s), E the activation energy (J/mol), R
//! the gas constant and T the reactant's temperature. It is the global
//! kinetics of one-step cook-off and thermal-explosion models, in which an
//! explosive heated slowly runs away once its heat release outpaces its
//! losses; the seed's cook-off (seed 000 §5.3) ignites by a temperature
//! instead and burns on the surface (`Deflagration`).
//!
//! - [`decomposition`]: the model, its exact step at a fixed temperature,
//!   and the adiabatic induction time of thermal explosion theory.
//! - [`register`]: its entry in the program's reaction registry
//!   (`brisance_reaction::plugin`), under the RON name
//!   `ThermalDecomposition`.
//!
//! Units are SI throughout. docs/physics/reaction/thermal_decomposition.md
//! has the model and its checks.

pub mod decomposition;

pub use decomposition::ThermalDecomposition;

use brisance_reaction::plugin::{parse_params, ReactionPlugin, ReactionRegistry};

/// Registers [`ThermalDecomposition`] as `ThermalDecomposition(z,
/// activation_energy)`.
pub fn register(registry: &mut ReactionRegistry) {
    registry.register(ReactionPlugin {
        name: "ThermalDecomposition",
        summary: "first-order Arrhenius thermal decomposition in the volume, dF/dt = Z exp(-E/(R T)) (1 - F) (Frank-Kamenetskii 1955); a plugin crate; ICE and IceMpm `reactions`",
        docs: "docs/physics/reaction/thermal_decomposition.md",
        example: "ThermalDecomposition(z: 5.0e19, activation_energy: 2.2e5)",
        parse: |v| parse_params::<ThermalDecomposition>(v, ThermalDecomposition::validate),
    });
}
