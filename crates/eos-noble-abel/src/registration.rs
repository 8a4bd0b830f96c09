//! What this crate tells the program's registry of equations of state.

use brisance_eos::plugin::{parse_params, EosPlugin, EosRegistry};

use crate::NobleAbel;

/// Registers the Noble–Abel gas as `NobleAbel`: a config writes
/// `eos: NobleAbel(gamma: 1.25, covolume: 1.0e-3, cv: 1320.0, rho0: 100.0)`.
pub fn register(registry: &mut EosRegistry) {
    registry.register(EosPlugin {
        name: "NobleAbel",
        summary: "Noble-Abel co-volume gas p = (gamma-1) rho e / (1 - b rho), propellant gases (Corner 1950; Johnston 2005)",
        docs: "docs/physics/eos/noble_abel.md",
        example: "NobleAbel(gamma: 1.25, covolume: 1.0e-3, cv: 1320.0, rho0: 100.0)",
        gas: true,
        parse: parse_params::<NobleAbel>,
    });
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_registered_example_builds_the_model() {
        let mut r = EosRegistry::new();
        register(&mut r);
        let p = r.get("NobleAbel").expect("registered");
        assert!(p.gas && p.example.starts_with(p.name));
        let args = p.example.strip_prefix(p.name).unwrap();
        let (model, params) = (p.parse)(args).unwrap();
        assert!(model.validate().is_ok());
        assert_eq!(model.name(), "noble_abel");
        // The canonical text reads back to the same parameters.
        assert_eq!((p.parse)(params.as_str()).unwrap().1, params);
    }
}
