//! What this crate tells the program's registry of constitutive models.

use brisance_constitutive::plugin::{parse_params, MaterialPlugin, MaterialRegistry};

use crate::SteinbergGuinan;

/// The registration of [`SteinbergGuinan`] under the RON name
/// `SteinbergGuinan`, also what a preset built in code names as its plugin
/// (`PluginConstitutive::from_model(&STEINBERG_GUINAN, ...)`).
pub static STEINBERG_GUINAN: MaterialPlugin = MaterialPlugin {
    name: "SteinbergGuinan",
    summary: "Steinberg-Cochran-Guinan metal: shear modulus and yield rising with pressure and falling with temperature, work hardening to a cap, no strength above melt, J2 radial return, EOS pressure, plastic heating (Steinberg, Cochran & Guinan 1980); a plugin crate",
    docs: "docs/physics/constitutive/steinberg_guinan.md",
    example: "SteinbergGuinan(g0: 47.7e9, dg_dp_over_g0: 2.83e-11, dg_dt_over_g0: -3.77e-4, y0: 0.12e9, y_max: 0.64e9, beta: 36.0, n: 0.45, melt: Lindemann(t_m0: 1790.0, gamma0: 2.02, a: 1.5), pressure: Eos(MieGruneisenLinear(c0: 3940.0, s: 1.489, gamma0: 2.02, rho0: 8930.0, cv: 383.0, t0: 300.0)), rate: GreenNaghdi, specific_heat: 383.0)",
    parse: parse_params::<SteinbergGuinan>,
};

/// Registers the Steinberg–Cochran–Guinan metal as `SteinbergGuinan`: a
/// config writes `model: SteinbergGuinan(g0: 47.7e9, ...)` wherever it
/// writes `model: ElasticPlastic(...)`.
pub fn register(registry: &mut MaterialRegistry) {
    registry.register(STEINBERG_GUINAN);
}

#[cfg(test)]
mod tests {
    use super::*;
    use brisance_constitutive::{MaterialModel, PluginConstitutive};

    #[test]
    fn the_registered_example_builds_the_copper_preset() {
        let mut r = MaterialRegistry::new();
        register(&mut r);
        let p = r.get("SteinbergGuinan").expect("registered");
        assert!(p.example.starts_with(p.name));
        let args = p.example.strip_prefix(p.name).unwrap();
        let (model, params) = (p.parse)(args).unwrap();
        assert!(model.validate().is_ok());
        assert_eq!(model.name(), "steinberg_guinan");
        // The example is the copper preset, value for value.
        let preset =
            PluginConstitutive::from_model(&STEINBERG_GUINAN, SteinbergGuinan::ofhc_copper())
                .unwrap();
        assert_eq!(&params, preset.params());
        let from_text = PluginConstitutive::new(&STEINBERG_GUINAN, args).unwrap();
        assert_eq!(MaterialModel::from(from_text), MaterialModel::from(preset));
    }
}
