//! The one place the program's plugin crates are registered. A model crate
//! joins with one line in [`eos_registry`], [`reaction_registry`] or
//! [`material_registry`] (and a dependency line in this crate's
//! `Cargo.toml`); the config schema, `brisance list`, `brisance check` and
//! the docs links all read the registries built here.

use std::sync::Once;

use brisance_constitutive::MaterialRegistry;
use brisance_eos::EosRegistry;
use brisance_reaction::plugin::ReactionRegistry;
use brisance_scene::plugin::PipelineRegistry;

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

/// The constitutive models that live in their own crates.
pub fn material_registry() -> MaterialRegistry {
    let mut registry = MaterialRegistry::new();
    brisance_constitutive_scg::register(&mut registry);
    registry
}

/// The pipelines, each registered by its own crate, in the order
/// `brisance list` shows them.
pub fn pipeline_registry() -> PipelineRegistry {
    let mut registry = PipelineRegistry::new();
    brisance_fdm::pipeline::register(&mut registry);
    brisance_couple::mpm_pipeline::register(&mut registry);
    brisance_pd::pipeline::register(&mut registry);
    brisance_ice::pipeline::register(&mut registry);
    brisance_couple::ice_mpm::pipeline::register(&mut registry);
    brisance_couple::bridge_pipeline::register(&mut registry);
    brisance_lattice::register(&mut registry);
    registry
}

/// Installs [`eos_registry`], [`reaction_registry`],
/// [`material_registry`] and [`pipeline_registry`] as the ones every
/// config reader resolves names through; the first call does it, later
/// ones do nothing.
pub fn install() {
    static INSTALL: Once = Once::new();
    INSTALL.call_once(|| {
        // Something else installed a registry first (a test of a model
        // crate's own); keep it rather than mix two.
        let _ = brisance_eos::plugin::install(eos_registry());
        let _ = brisance_reaction::plugin::install(reaction_registry());
        let _ = brisance_constitutive::plugin::install(material_registry());
        let _ = brisance_scene::plugin::install(pipeline_registry());
    });
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::load::ron_options;
    use brisance_constitutive::MaterialModel;
    use brisance_eos::EosModel;

    /// Every plugin's RON example reads, through the config reader, as a
    /// model of its family under its own name, passes its own check, and
    /// writes itself back to an equal model.
    #[test]
    fn every_plugin_example_parses_as_its_model_and_validates() {
        for p in eos_registry().plugins() {
            let m: EosModel = ron_options()
                .from_str(p.example)
                .unwrap_or_else(|e| panic!("{}: {e}", p.name));
            assert_eq!(m.variant(), p.name);
            assert!(m.validate().is_ok(), "{}: {:?}", p.name, m.validate());
            let back = ron_options().to_string(&m).unwrap();
            assert_eq!(ron_options().from_str::<EosModel>(&back).unwrap(), m);
        }
        for p in reaction_registry().plugins() {
            let m: crate::config::IceReactionModel = ron_options()
                .from_str(p.example)
                .unwrap_or_else(|e| panic!("{}: {e}", p.name));
            assert_eq!(m.variant(), p.name);
        }
        let materials = material_registry();
        assert!(!materials.plugins().is_empty());
        for p in materials.plugins() {
            let m: MaterialModel = ron_options()
                .from_str(p.example)
                .unwrap_or_else(|e| panic!("{}: {e}", p.name));
            assert_eq!(m.variant(), p.name);
            assert!(m.validate().is_ok(), "{}: {:?}", p.name, m.validate());
            let back = ron_options().to_string(&m).unwrap();
            assert_eq!(ron_options().from_str::<MaterialModel>(&back).unwrap(), m);
        }
        // Every pipeline, each registered by its crate: its example reads
        // as the composer's `Pipeline` under its name, as the section type
        // the registration names, and writes itself back to an equal one.
        let pipelines = pipeline_registry();
        assert_eq!(pipelines.plugins().len(), 7);
        for p in pipelines.plugins() {
            let name = p.info.name;
            let m: crate::config::Pipeline = ron_options()
                .from_str(p.info.example)
                .unwrap_or_else(|e| panic!("{name}: {e}"));
            assert_eq!(m.name(), name);
            let back = ron_options().to_string(&m).unwrap();
            assert_eq!(
                ron_options()
                    .from_str::<crate::config::Pipeline>(&back)
                    .unwrap(),
                m,
                "{name}"
            );
        }
    }

    const TAYLOR: &str = include_str!("../../../configs/taylor2d.ron");

    /// taylor2d.ron (a copper bar hitting a wall at 190 m/s, plane strain)
    /// with its copper's `model` replaced by `model` and the run cut to
    /// `end` seconds (RON text).
    fn taylor_with(model: &str, end: &str) -> crate::LoadedScenario {
        let start = TAYLOR.find("model: ElasticPlastic(").unwrap();
        let stop = start + TAYLOR[start..].find("\n            ),\n").unwrap() + 14;
        let text = format!("{}model: {model},{}", &TAYLOR[..start], &TAYLOR[stop + 1..]);
        crate::load_str("taylor.ron", &text, &[format!("time.end={end}")])
            .unwrap_or_else(|e| panic!("{e}\n{text}"))
    }

    fn steps(loaded: &crate::LoadedScenario, n: usize) -> brisance_mpm::MpmSolver {
        use brisance_core::Solver;
        let s = &loaded.scenario;
        let section = s.pipeline.section::<brisance_couple::MpmConfig>();
        let mut solver = crate::build::build_section(section.expect("an Mpm pipeline"), s).unwrap();
        for _ in 0..n {
            let dt = solver.stable_dt().unwrap();
            solver.advance(dt).unwrap();
        }
        solver
    }

    const COPPER_EOS: &str = "Eos(MieGruneisenLinear(c0: 3940.0, s: 1.489, gamma0: 2.02, rho0: 8930.0, cv: 383.0, t0: 300.0))";

    /// With no pressure or temperature dependence (G'_p = G'_T = 0), no
    /// hardening (β = 0, Y_max = Y₀) and a melt the bar never reaches, the
    /// Steinberg–Cochran–Guinan metal is the elastic–perfectly plastic J2
    /// metal: through the composer and the MPM solver (one virtual call
    /// per particle) it steps the Taylor bar to the same bits as the
    /// built-in `ElasticPlastic` (a `match`), plastic heating included.
    #[test]
    fn a_plugin_metal_with_constant_moduli_steps_bit_for_bit_as_the_built_in_one() {
        let built_in = taylor_with(
            &format!(
                "ElasticPlastic(shear_modulus: 43.8e9, pressure: {COPPER_EOS}, flow_stress: Constant(sigma_y: 70.0e6), rate: Jaumann, taylor_quinney: 0.9, specific_heat: 383.0)"
            ),
            "1.0e-5",
        );
        let plugin = taylor_with(
            &format!(
                "SteinbergGuinan(g0: 43.8e9, dg_dp_over_g0: 0.0, dg_dt_over_g0: 0.0, y0: 70.0e6, y_max: 70.0e6, beta: 0.0, n: 1.0, melt: Constant(t_m: 1356.0), pressure: {COPPER_EOS}, rate: Jaumann, taylor_quinney: 0.9, specific_heat: 383.0)"
            ),
            "1.0e-5",
        );
        let model = plugin.scenario.materials["copper"].model.as_ref().unwrap();
        assert_eq!(model.variant(), "SteinbergGuinan");
        let (a, b) = (steps(&built_in, 40), steps(&plugin, 40));
        let (a, b) = (a.particles(), b.particles());
        assert_eq!(a.position, b.position);
        assert_eq!(a.velocity, b.velocity);
        assert_eq!(a.stress, b.stress);
        assert_eq!(a.specific_internal_energy, b.specific_internal_energy);
        assert_eq!(a.temperature, b.temperature);
        assert_eq!(a.failed, b.failed);
        // The bar yielded and heated at the wall: the comparison covered
        // the radial return and the plastic heating, not an elastic run.
        assert!((0..b.mass.len()).any(|i| b.history_of(i)[0] > 0.0));
        assert!(b.temperature.iter().any(|&t| t > 293.0));
    }

    /// OFHC copper by Steinberg–Cochran–Guinan (the registered example)
    /// runs the Taylor bar through the whole run loop, and the particles
    /// keep the model's state: the wall end yields and heats, the far end
    /// is still elastic, every particle's stress lies inside its yield
    /// surface Y(ε_p) G/G₀ at the history the solver carries, and the
    /// modulus follows the pressure (stiffer in compression, softer in
    /// tension).
    #[test]
    fn a_steinberg_guinan_copper_bar_runs_end_to_end() {
        use brisance_constitutive_scg::steinberg_guinan::{
            MODULUS_RATIO_INDEX, PLASTIC_STRAIN_INDEX,
        };
        use brisance_constitutive_scg::SteinbergGuinan;
        let example = brisance_constitutive_scg::registration::STEINBERG_GUINAN.example;
        let loaded = taylor_with(&example.replace("GreenNaghdi", "Jaumann"), "2.0e-6");
        let dir = tempfile::tempdir().unwrap();
        let opts = crate::RunOptions {
            out_dir: dir.path().to_path_buf(),
            restart: None,
            progress: false,
        };
        let summary = crate::run(&loaded, &opts).unwrap();
        assert!(summary.completed && summary.steps > 0, "{summary:?}");
        assert!(summary.relative_mass_change.abs() < 1e-12, "{summary:?}");

        let solver = steps(&loaded, summary.steps as usize);
        let p = solver.particles();
        let copper = SteinbergGuinan {
            rate: brisance_constitutive::ObjectiveRate::Jaumann,
            ..SteinbergGuinan::ofhc_copper()
        };
        let (mut yielded_low, mut elastic_high, mut signed) = (0, 0, 0);
        for i in 0..p.mass.len() {
            let h = p.history_of(i);
            let (eps_p, ratio) = (h[PLASTIC_STRAIN_INDEX], h[MODULUS_RATIO_INDEX]);
            let [xx, yy, zz, yz, xz, xy] = p.stress[i];
            let mean = (xx + yy + zz) / 3.0;
            let (sx, sy, sz) = (xx - mean, yy - mean, zz - mean);
            let vm =
                (1.5 * (sx * sx + sy * sy + sz * sz) + 3.0 * (yz * yz + xz * xz + xy * xy)).sqrt();
            let y = copper.yield_stress(eps_p, ratio);
            assert!(
                vm <= y * (1.0 + 1e-9) + 1e-6 * mean.abs(),
                "particle {i}: {vm} > {y}"
            );
            let height = p.position[i][1];
            if height < 1.0e-3 && eps_p > 0.0 {
                yielded_low += 1;
                assert!(p.temperature[i] > 293.0, "{}", p.temperature[i]);
            }
            // G/G₀ − 1 − (G'_T/G₀)(T − 300 K) = (G'_p/G₀) p η^(−1/3) has the
            // sign of the pressure (T is the particle's after the step, a
            // fraction of a kelvin from the update's: 3.77e-4/K times that
            // is far below 2.83e-11/Pa × 0.5 GPa).
            let pressure = -mean;
            if pressure.abs() > 0.5e9 {
                let thermal = copper.dg_dt_over_g0 * (p.temperature[i] - 300.0);
                let pressure_term = ratio - 1.0 - thermal;
                assert_eq!(
                    pressure_term > 0.0,
                    pressure > 0.0,
                    "particle {i}: p = {pressure}, G/G0 = {ratio}"
                );
                signed += 1;
            }
            if height > 0.02 && eps_p == 0.0 {
                elastic_high += 1;
            }
        }
        assert!(
            yielded_low > 0 && elastic_high > 0 && signed > 0,
            "{yielded_low} {elastic_high} {signed}"
        );
    }

    const LATTICE: &str = include_str!("../../../configs/lattice_impact.ron");

    /// Every pipeline is registered by its crate, one line each in
    /// [`pipeline_registry`], in the order `brisance list` shows. The MSDM
    /// lattice so: a scenario names it as `Lattice(...)`, reads into its
    /// section type, writes itself back to an equal scenario, builds
    /// through the registration, and is listed with its docs page.
    #[test]
    fn every_pipeline_is_registered_the_lattice_as_the_others() {
        let registry = pipeline_registry();
        let names: Vec<&str> = registry.plugins().iter().map(|p| p.info.name).collect();
        assert_eq!(
            names,
            [
                "Fdm",
                "Mpm",
                "Peridynamics",
                "Ice",
                "IceMpm",
                "FdmMpmBridge",
                "Lattice"
            ]
        );
        let loaded = crate::load_str("lattice_impact.ron", LATTICE, &[]).unwrap();
        assert_eq!(loaded.scenario.pipeline.name(), "Lattice");
        let cfg: &brisance_lattice::LatticeConfig = loaded
            .scenario
            .pipeline
            .section()
            .expect("a lattice section");
        assert_eq!(cfg.spacing, 2.0e-5);
        let text = ron_options().to_string(&loaded.scenario).unwrap();
        assert!(text.contains("pipeline:Lattice("), "{text}");
        let back: crate::Scenario = ron_options().from_str(&text).unwrap();
        assert_eq!(back, loaded.scenario);
        let solver = crate::build::build_solver(&loaded.scenario).unwrap();
        assert_eq!(solver.name(), "lattice");
        let entry = crate::registry::entries()
            .into_iter()
            .find(|e| e.family == "pipeline" && e.name == "Lattice")
            .expect("listed");
        assert_eq!(entry.docs, Some("docs/physics/lattice/model.md"));
    }

    /// A registered pipeline's errors are located as a built-in one's: a
    /// misspelt field of its section names the field at the section's
    /// line, a check of its section names the field's path, its refusal
    /// of (r, z) grids comes first, and a misspelt pipeline name lists
    /// every pipeline, the registered ones included.
    #[test]
    fn a_registered_pipeline_reports_errors_as_a_built_in_one() {
        let typo = LATTICE.replace("spacing: 2.0e-5", "spacin: 2.0e-5");
        let err = crate::load_str("lattice_impact.ron", &typo, &[]).unwrap_err();
        let text = err.to_string();
        assert!(text.contains("lattice_impact.ron:22:9:"), "{text}");
        assert!(text.contains("spacin"), "{text}");
        let err = crate::load_str(
            "lattice_impact.ron",
            LATTICE,
            &["pipeline.spacing=-1.0".to_string()],
        )
        .unwrap_err();
        assert_eq!(err.field.as_deref(), Some("pipeline.spacing"), "{err}");
        let err = crate::load_str(
            "lattice_impact.ron",
            LATTICE,
            &["domain.geometry=Axisymmetric".to_string()],
        )
        .unwrap_err();
        assert_eq!(err.field.as_deref(), Some("domain.geometry"), "{err}");
        assert!(err.message.contains("no axisymmetric form"), "{err}");
        let wrong = LATTICE.replace("pipeline: Lattice(", "pipeline: Latice(");
        let text = crate::load_str("lattice_impact.ron", &wrong, &[])
            .unwrap_err()
            .to_string();
        assert!(
            text.contains("`Lattice`") && text.contains("`Fdm`"),
            "{text}"
        );
    }
}
