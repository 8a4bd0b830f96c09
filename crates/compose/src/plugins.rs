//! The one place the program's plugin crates are registered. A model crate
//! joins with one line in [`eos_registry`] or [`reaction_registry`] (and a
//! dependency line in this crate's `Cargo.toml`); the config schema,
//! `brisance list`, `brisance check` and the docs links all read the
//! registries built here.

use std::sync::Once;

use brisance_eos::EosRegistry;
use brisance_reaction::plugin::ReactionRegistry;

/// The equations of state that live in their own crates.
pub fn eos_registry() -> EosRegistry {
    let mut registry = EosRegistry::new();
    brisance_eos_noble_abel::register(&mut registry);
    registry
}

/// The reaction models that live in their own crates.
pub fn reaction_registry() -> ReactionRegistry {
    let mut registry = ReactionRegistry::new();
    brisance_reaction_thermal::register(&mut registry);
    registry
}

/// Installs [`eos_registry`] and [`reaction_registry`] as the ones every
/// config reader resolves model names through; the first call does it,
/// later ones do nothing.
pub fn install() {
    static INSTALL: Once = Once::new();
    INSTALL.call_once(|| {
        // Something else installed a registry first (a test of a model
        // crate's own); keep it rather than mix two.
        let _ = brisance_eos::plugin::install(eos_registry());
        let _ = brisance_reaction::plugin::install(reaction_registry());
    });
}
