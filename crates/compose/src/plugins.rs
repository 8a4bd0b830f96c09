//! The one place the program's plugin crates are registered. A model crate
//! joins with one line in [`eos_registry`] (and a dependency line in this
//! crate's `Cargo.toml`); the config schema, `brisance list`,
//! `brisance check` and the docs links all read the registry built here.

use std::sync::Once;

use brisance_eos::EosRegistry;

/// The equations of state that live in their own crates.
pub fn eos_registry() -> EosRegistry {
    let mut registry = EosRegistry::new();
    brisance_eos_noble_abel::register(&mut registry);
    registry
}

/// Installs [`eos_registry`] as the one every config reader resolves
/// model names through; the first call does it, later ones do nothing.
pub fn install() {
    static INSTALL: Once = Once::new();
    INSTALL.call_once(|| {
        // Something else installed a registry first (a test of the eos
        // crate's own); keep it rather than mix two.
        let _ = brisance_eos::plugin::install(eos_registry());
    });
}
