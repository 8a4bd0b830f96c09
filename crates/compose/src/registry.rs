//! The registry of named components: what `brisance list` prints and what a
//! config may name. Each entry carries a RON example that the tests parse,
//! so the list cannot drift from the schema. The built-in components are
//! [`ENTRIES`]; [`entries`] adds the equations of state, reaction models,
//! constitutive models and pipelines of the plugin crates
//! ([`crate::plugins`]) from their own registration.

use brisance_plugin::{PluginInfo, Registry};

/// One named component.
#[derive(Debug, Clone, Copy)]
pub struct Entry {
    /// Family: `eos`, `material`, `reaction`, `pipeline`, `load`, `history`,
    /// `quantity`, `region`, `boundary`.
    pub family: &'static str,
    /// The name a config uses.
    pub name: &'static str,
    /// One line on what it is, with its seed reference.
    pub summary: &'static str,
    /// A RON example of the config value.
    pub example: &'static str,
    /// The model's or pipeline's docs page, relative to the repository
    /// root, where it has one.
    pub docs: Option<&'static str>,
}

/// Every registered component.
pub const ENTRIES: &[Entry] = &[
    Entry {
        family: "eos",
        name: "IdealGas",
        summary: "gamma-law gas p = (gamma-1) rho e with constant cv (seed 001 eq 55)",
        example: "IdealGas(gamma: 1.4, cv: 717.6, rho0: 1.225)",
        docs: Some("docs/physics/eos/ideal_gas.md"),
    },
    Entry {
        family: "eos",
        name: "Jwl",
        summary: "JWL detonation products, E0 per initial volume (seed 001 eq 54)",
        example: "Jwl(a: 3.712e11, b: 3.21e9, r1: 4.15, r2: 0.95, omega: 0.3, e0: 6.993e9, rho0: 1630.0, cv: 613.5)",
        docs: Some("docs/physics/eos/jwl.md"),
    },
    Entry {
        family: "eos",
        name: "JwlCTerm",
        summary: "JWL C-term products of JWL++ (seed 000 eq 34, Souers et al. 2000)",
        example: "JwlCTerm(a: 2.9867e11, b: 4.11706e9, c: 7.206147e8, r1: 4.95, r2: 1.15, omega: 0.35, rho0: 1160.0, cv: 862.07)",
        docs: Some("docs/physics/eos/jwl_cterm.md"),
    },
    Entry {
        family: "eos",
        name: "Murnaghan",
        summary: "Murnaghan unreacted explosive p = ((rho/rho0)^n - 1)/(n kappa) (seed 000 eq 33)",
        example: "Murnaghan(n: 7.4, kappa: 3.9e-10, rho0: 1160.0, cv: 1700.0, t_ref: 298.15)",
        docs: Some("docs/physics/eos/murnaghan.md"),
    },
    Entry {
        family: "eos",
        name: "MieGruneisenCubic",
        summary: "Mie-Grueneisen on a cubic Hugoniot, compression and tension branches (seed 001 eqs 65-66)",
        example: "MieGruneisenCubic(gamma: 2.17, c0: 4569.0, s: 1.49, rho0: 7850.0, cv: 477.0, t0: 300.0)",
        docs: Some("docs/physics/eos/mie_gruneisen.md"),
    },
    Entry {
        family: "eos",
        name: "MieGruneisenLinear",
        summary: "Mie-Grueneisen on the linear Us-up Hugoniot (seed 000 eq 40)",
        example: "MieGruneisenLinear(c0: 3574.0, s: 1.92, gamma0: 1.69, rho0: 7830.0, cv: 477.0, t0: 294.0)",
        docs: Some("docs/physics/eos/mie_gruneisen.md"),
    },
    Entry {
        family: "eos",
        name: "MieGruneisenThermal",
        summary: "thermal Mie-Grueneisen of the lattice, e = cv T (seed 003 eqs 12-14)",
        example: "MieGruneisenThermal(gamma: 0.7, rho0: 1580.0, c0: 2674.3, s: 0.0, cv: 1757.28, t0: 300.0, p0: 100000.0)",
        docs: Some("docs/physics/eos/mie_gruneisen.md"),
    },
    Entry {
        family: "eos",
        name: "SolidThreshold",
        summary: "a solid EOS with the C1 low-pressure threshold of seed 000 §3.1",
        example: "SolidThreshold(solid: MieGruneisenLinear(c0: 3574.0, s: 1.92, gamma0: 1.69, rho0: 7830.0, cv: 477.0, t0: 294.0), threshold_pressure: 101325.0)",
        docs: Some("docs/physics/eos/threshold.md"),
    },
    Entry {
        family: "eos",
        name: "StiffenedGas",
        summary: "stiffened gas p = (gamma-1) rho e - gamma p_inf, water of the water-air tube (Le Metayer, Massoni & Saurel 2004)",
        example: "StiffenedGas(gamma: 4.4, p_inf: 6.0e8, cv: 1600.0, rho0: 1000.0)",
        docs: Some("docs/physics/eos/stiffened_gas.md"),
    },
    Entry {
        family: "reaction",
        name: "JwlPlusPlus",
        summary: "JWL++ detonation, dF/dt = G p^b (1 - F) above 200 MPa, at most 20 % of a cell's reactant a step (seed 000 eqs 35-37); ICE and IceMpm `reactions`",
        example: "JwlPlusPlus(g: 9.1e-5, b: 1.0)",
        docs: Some("docs/physics/reaction/jwlpp.md"),
    },
    Entry {
        family: "reaction",
        name: "Deflagration",
        summary: "surface burn D = A p^n with an ignition temperature, Gamma = a D rho on the reactant surface found after each equilibration (seed 000 eqs 38-39), optional `surface_area: column | clipped_plane | uintah | exposed_faces | upwind | gradient` (default column for a fluid reactant, gradient for particles); ICE and IceMpm `reactions`",
        example: "Deflagration(a: 5.218307e-6, n: 0.778, ignition_temperature: 450.0)",
        docs: Some("docs/physics/reaction/deflagration.md"),
    },
    Entry {
        family: "reaction",
        name: "Arrhenius",
        summary: "surface pyrolysis mass flux m = Omega A exp(-Ea/(R T)) at the surface's temperature, regression r = m/rho (seed 003 §2.4, §3.1-3.2); Lattice `materials.<name>.arrhenius`, ICE and IceMpm `reactions` (Gamma = a m on the reactant surface, as the deflagration)",
        example: "Arrhenius(pre_exponential: 5.0e6, activation_energy: 92109.6, catalytic_factor: 1.0)",
        docs: Some("docs/physics/reaction/arrhenius.md"),
    },
    Entry {
        family: "reaction",
        name: "ProgramBurn",
        summary: "program burn: each explosive node detonates at its Huygens or straight-line time from the detonation points (seed 004); Peridynamics `detonation`",
        example: "ProgramBurn(points: [(position: (0.0, 0.0, 0.0), time: 0.0)], method: Huygens)",
        docs: Some("docs/physics/pd/program_burn.md"),
    },
    Entry {
        family: "reaction",
        name: "ProgramBurnRamp",
        summary: "program burn of a 1D charge: a cell lit at distance/D burns over 1.5 cells, F = min(1, (t - t_L) D/(1.5 h)) (seed 001 eqs 52-53); the 1D detonation of an FdmMpmBridge `charge` and of `brisance remap`, with the explosive's D and the 1D grid's h",
        example: "ProgramBurnRamp(detonation_velocity: 6930.0, cell_size: 1.0e-4)",
        docs: Some("docs/physics/fdm_detonation.md"),
    },
    Entry {
        family: "material",
        name: "Hypoelastic",
        summary: "isotropic hypoelastic solid (K or an EOS, G) with a Jaumann or Green-Naghdi rate (seed 000 §4.2, seed 001 eq 30)",
        example: "Hypoelastic(shear_modulus: 43.8e9, pressure: Linear(bulk_modulus: 117.0e9), rate: Jaumann)",
        docs: Some("docs/physics/constitutive/hypoelastic.md"),
    },
    Entry {
        family: "material",
        name: "ElasticPlastic",
        summary: "J2 radial return, constant or Johnson-Cook flow stress, Johnson-Cook damage, plastic heating (seed 000 eqs 41-42, 47)",
        example: "ElasticPlastic(shear_modulus: 43.8e9, pressure: Linear(bulk_modulus: 117.0e9), flow_stress: Constant(sigma_y: 70.0e6), damage: None, rate: GreenNaghdi, taylor_quinney: 0.9, specific_heat: 383.0)",
        docs: Some("docs/physics/constitutive/elastic_plastic.md"),
    },
    Entry {
        family: "material",
        name: "DruckerPrager",
        summary: "Drucker-Prager soil, shear cone and tension cutoff with apex return (seed 001 eqs 59-63, soil of Luccioni & Luege 2006)",
        example: "DruckerPrager(shear_modulus: 38.4615e6, bulk_modulus: 83.3333e6, k_phi: 134715.46, q_phi: 0.445749, tensile_strength: 302222.5, q_psi: 0.0, rate: Jaumann)",
        docs: Some("docs/physics/constitutive/drucker_prager.md"),
    },
    Entry {
        family: "material",
        name: "Hjc",
        summary: "Holmquist-Johnson-Cook concrete, three-region crush EOS, Jiang tensile damage (seed 001 eqs 56-58; HJC 1993 constants)",
        example: "Hjc(reference_density: 2440.0, shear_modulus: 14.86e9, compressive_strength: 48.0e6, tensile_strength: 4.0e6, a: 0.79, b: 1.6, n: 0.61, c: 0.007, s_max: 7.0, reference_strain_rate: 1.0, d1: 0.04, d2: 1.0, ef_min: 0.01, p_crush: 16.0e6, mu_crush: 0.001, p_lock: 0.8e9, mu_lock: 0.1, k1: 85.0e9, k2: -171.0e9, k3: 208.0e9, tensile_damage: None, rate: Jaumann)",
        docs: Some("docs/physics/constitutive/hjc.md"),
    },
    Entry {
        family: "material",
        name: "Null",
        summary: "fluid as material points: EOS pressure, zero or Newtonian viscous deviator 2 mu dev D (for MPM-vs-FDM gas runs, seed 001 §5)",
        example: "Null(eos: IdealGas(gamma: 1.4, cv: 717.625, rho0: 1.225), viscosity: 0.0)",
        docs: Some("docs/physics/constitutive/null_material.md"),
    },
    Entry {
        family: "material",
        name: "ViscoScram",
        summary: "polymer-bonded explosive: five Maxwell elements and statistical crack growth with frictional toughness and heating (seed 000 §4.1.2, ref [19]; PBX-9501)",
        example: "ViscoScram(shear_moduli: (3.5e8, 1.739e8, 5.212e8, 9.085e8, 6.875e8), inverse_relaxation_times: (0.0, 7.32e3, 7.32e4, 7.32e5, 2.0e6), pressure: Linear(bulk_modulus: 5.722e9), crack_size: 1.0e-3, initial_crack_radius: 3.0e-5, crack_power: 10.0, max_crack_speed: 300.0, fracture_toughness: 500.0, crack_friction: 0.35, rate: GreenNaghdi)",
        docs: Some("docs/physics/constitutive/viscoscram.md"),
    },
    Entry {
        family: "load",
        name: "Traction",
        summary: "traction vector per unit area on a particle surface layer, Pa (seed 001 eq 20)",
        example: "Traction(1.0e6, 0.0, 0.0)",
        docs: None,
    },
    Entry {
        family: "load",
        name: "Pressure",
        summary: "pressure on a particle surface layer, along the deformed inward normal, Pa (seed 001 eq 20)",
        example: "Pressure(2.0e6)",
        docs: None,
    },
    Entry {
        family: "history",
        name: "Constant",
        summary: "full load from t = 0",
        example: "Constant",
        docs: None,
    },
    Entry {
        family: "history",
        name: "Ramp",
        summary: "load factor rising linearly from 0 to 1 over rise_time",
        example: "Ramp(rise_time: 1.0e-5)",
        docs: None,
    },
    Entry {
        family: "history",
        name: "Table",
        summary: "piecewise-linear load factor through (time, factor) points, held beyond the ends",
        example: "Table([(0.0, 0.0), (1.0e-5, 1.0), (3.0e-5, 0.0)])",
        docs: None,
    },
    Entry {
        family: "quantity",
        name: "MeanVelocity",
        summary: "mass-weighted mean velocity of a particle gauge's particles (their momentum over their mass)",
        example: "MeanVelocity",
        docs: None,
    },
    Entry {
        family: "quantity",
        name: "MeanPosition",
        summary: "centre of mass of a particle gauge's particles",
        example: "MeanPosition",
        docs: None,
    },
    Entry {
        family: "quantity",
        name: "MeanDisplacement",
        summary: "centre of mass of a particle gauge's particles minus its start",
        example: "MeanDisplacement",
        docs: None,
    },
    Entry {
        family: "quantity",
        name: "MeanStress",
        summary: "volume-weighted mean material stress (six Voigt columns) of a particle gauge's particles",
        example: "MeanStress",
        docs: None,
    },
    Entry {
        family: "quantity",
        name: "MeanPressure",
        summary: "volume-weighted mean material pressure of a particle gauge's particles",
        example: "MeanPressure",
        docs: None,
    },
    Entry {
        family: "quantity",
        name: "MeanVonMisesStress",
        summary: "volume-weighted mean von Mises stress of a particle gauge's particles",
        example: "MeanVonMisesStress",
        docs: None,
    },
    Entry {
        family: "quantity",
        name: "MeanTemperature",
        summary: "mass-weighted mean temperature of a particle gauge's particles",
        example: "MeanTemperature",
        docs: None,
    },
    Entry {
        family: "quantity",
        name: "MeanSpecificInternalEnergy",
        summary: "mass-weighted mean specific internal energy of a particle gauge's particles",
        example: "MeanSpecificInternalEnergy",
        docs: None,
    },
    Entry {
        family: "quantity",
        name: "Mass",
        summary: "mass of a particle gauge's particles still in the domain",
        example: "Mass",
        docs: None,
    },
    Entry { family: "region", name: "Everywhere", summary: "the whole domain", example: "Everywhere", docs: None },
    Entry { family: "region", name: "Box", summary: "axis-aligned box", example: "Box(min: (0, 0, 0), max: (1, 1, 1))", docs: None },
    Entry { family: "region", name: "Sphere", summary: "ball", example: "Sphere(centre: (0, 0, 0), radius: 0.1)", docs: None },
    Entry {
        family: "region",
        name: "Cylinder",
        summary: "finite circular cylinder from a base point along an axis",
        example: "Cylinder(base: (0, 0, 0), axis: (0, 0, 1), radius: 0.1, length: 0.5)",
        docs: None,
    },
    Entry {
        family: "region",
        name: "Shell",
        summary: "thick-walled circular tube (cylindrical shell) from a base point along an axis",
        example: "Shell(base: (0, 0, 0), axis: (0, 0, 1), inner_radius: 0.0254, outer_radius: 0.0306, length: 0.35)",
        docs: None,
    },
    Entry {
        family: "region",
        name: "HalfSpace",
        summary: "points on the side of a plane the normal points to",
        example: "HalfSpace(point: (0.5, 0, 0), normal: (1, 0, 0))",
        docs: None,
    },
    Entry {
        family: "boundary",
        name: "Outflow",
        summary: "the pipeline's default open face: ZeroGradient (Fdm), OutflowOnly (Ice), particles leave and none enter (Mpm)",
        example: "Outflow",
        docs: None,
    },
    Entry {
        family: "boundary",
        name: "ZeroGradient",
        summary: "transmissive both ways: what enters is the boundary cell's (or particles') state",
        example: "ZeroGradient",
        docs: None,
    },
    Entry {
        family: "boundary",
        name: "OutflowOnly",
        summary: "zero gradient for what leaves; a wall where the flow at the face points inwards",
        example: "OutflowOnly",
        docs: None,
    },
    Entry { family: "boundary", name: "Reflective", summary: "slip wall / symmetry plane", example: "Reflective", docs: None },
    Entry { family: "boundary", name: "Periodic", summary: "periodic (both faces of an axis)", example: "Periodic", docs: None },
    Entry {
        family: "boundary",
        name: "Wall",
        summary: "rigid no-slip wall for particle pipelines (grid velocity zero)",
        example: "Wall",
        docs: None,
    },
    Entry {
        family: "boundary",
        name: "Fixed",
        summary: "an inflow reservoir: a fixed state beyond the face (Fdm, Ice, Mpm; `material` where there are several)",
        example: "Fixed(density: 1.225, pressure: 101325)",
        docs: None,
    },
];

/// Every registered component: [`ENTRIES`], then the equations of state,
/// the reaction models, the constitutive models and the pipelines (all of
/// them) of the plugin crates,
/// each under the name, summary, example and docs page its crate
/// registered.
pub fn entries() -> Vec<Entry> {
    crate::plugins::install();
    ENTRIES
        .iter()
        .copied()
        .chain(plugin_entries("eos", brisance_eos::plugin::installed()))
        .chain(plugin_entries(
            "reaction",
            brisance_reaction::plugin::installed(),
        ))
        .chain(plugin_entries(
            "material",
            brisance_constitutive::plugin::installed(),
        ))
        .chain(plugin_entries(
            "pipeline",
            brisance_scene::plugin::slot().registry(),
        ))
        .collect()
}

/// The entries of the plugins of one family, in registration order.
fn plugin_entries<P: PluginInfo>(
    family: &'static str,
    registry: Option<&'static Registry<P>>,
) -> impl Iterator<Item = Entry> {
    registry
        .map_or(&[][..], |r| r.plugins())
        .iter()
        .map(move |p| Entry {
            family,
            name: p.name(),
            summary: p.summary(),
            example: p.example(),
            docs: Some(p.docs()),
        })
}

/// Families in display order, with what is still to come.
pub const FAMILIES: &[(&str, &str)] = &[
    ("eos", "equations of state"),
    ("material", "constitutive models"),
    ("reaction", "reaction models"),
    ("pipeline", "pipelines"),
    ("load", "surface loads (Mpm surface_loads)"),
    ("history", "load histories"),
    ("quantity", "particle gauge quantities"),
    ("region", "initial-region shapes"),
    ("boundary", "boundary conditions"),
];

/// The listing `brisance list` prints.
pub fn listing() -> String {
    let mut out = String::new();
    let all = entries();
    for (family, title) in FAMILIES {
        out.push_str(&format!("{title} ({family}):\n"));
        let entries: Vec<&Entry> = all.iter().filter(|e| e.family == *family).collect();
        if entries.is_empty() {
            out.push_str("  (none registered yet)\n");
        }
        for e in entries {
            out.push_str(&format!("  {:<20} {}\n", e.name, e.summary));
            if let Some(docs) = e.docs {
                out.push_str(&format!("  {:<20} docs: {docs}\n", ""));
            }
        }
    }
    out.push_str("material library (materials: { \"x\": (library: \"name\") }):\n");
    for name in crate::library::names() {
        match crate::library::get(name) {
            Ok(m) => out.push_str(&format!("  {:<28} {}\n", name, m.description)),
            Err(e) => out.push_str(&format!("  {:<28} (unreadable: {e})\n", name)),
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::config::{BoundaryConfig, Pipeline, Region};
    use crate::load::ron_options;
    use brisance_constitutive::MaterialModel;
    use brisance_eos::EosModel;
    use brisance_mpm::{LoadHistory, SetQuantity, SurfaceLoadKind};

    #[test]
    fn every_example_parses_as_its_family_and_names_its_variant() {
        for e in &entries() {
            let ok = match e.family {
                "eos" => ron_options().from_str::<EosModel>(e.example).map(|_| ()),
                "material" => ron_options()
                    .from_str::<MaterialModel>(e.example)
                    .map(|_| ()),
                "pipeline" => ron_options().from_str::<Pipeline>(e.example).map(|_| ()),
                "reaction" => match e.name {
                    "ProgramBurn" => ron_options()
                        .from_str::<brisance_pd::PdDetonationConfig>(e.example)
                        .map(|_| ()),
                    "ProgramBurnRamp" => ron_options()
                        .from_str::<brisance_reaction::ProgramBurnRamp>(e.example)
                        .map(|_| ()),
                    _ => ron_options()
                        .from_str::<crate::config::IceReactionModel>(e.example)
                        .map(|_| ()),
                },
                "region" => ron_options().from_str::<Region>(e.example).map(|_| ()),
                "load" => ron_options()
                    .from_str::<SurfaceLoadKind>(e.example)
                    .map(|_| ()),
                "history" => ron_options().from_str::<LoadHistory>(e.example).map(|_| ()),
                "quantity" => ron_options().from_str::<SetQuantity>(e.example).map(|_| ()),
                "boundary" => ron_options()
                    .from_str::<BoundaryConfig>(e.example)
                    .map(|_| ()),
                other => panic!("no parser for family {other}"),
            };
            assert!(ok.is_ok(), "{} example `{}`: {:?}", e.name, e.example, ok);
            assert!(
                e.example.starts_with(e.name),
                "{} example must use its name",
                e.name
            );
        }
    }

    #[test]
    fn every_equation_of_state_is_registered() {
        let all = entries();
        // Every plugin of the registry is nameable once installed.
        assert!(EosModel::names().len() > EosModel::VARIANTS.len());
        for v in EosModel::names() {
            assert!(
                all.iter().any(|e| e.family == "eos" && e.name == *v),
                "{v} missing from the registry"
            );
        }
    }

    #[test]
    fn every_reaction_plugin_is_registered() {
        let all = entries();
        let names = crate::config::IceReactionModel::names();
        // The plugin crates' models are nameable once installed.
        assert!(names.len() > crate::config::IceReactionModel::VARIANTS.len());
        for v in names {
            assert!(
                all.iter().any(|e| e.family == "reaction" && e.name == v),
                "{v} missing from the registry"
            );
        }
    }

    #[test]
    fn every_material_plugin_is_registered() {
        let all = entries();
        let names = MaterialModel::names();
        // The plugin crates' models are nameable once installed.
        assert!(names.len() > MaterialModel::VARIANTS.len());
        for v in names {
            assert!(
                all.iter().any(|e| e.family == "material" && e.name == *v),
                "{v} missing from the registry"
            );
        }
    }

    #[test]
    fn every_docs_page_exists() {
        let root = concat!(env!("CARGO_MANIFEST_DIR"), "/../..");
        for e in entries() {
            if let Some(page) = e.docs {
                assert!(
                    std::path::Path::new(root).join(page).is_file(),
                    "{}: no page {page}",
                    e.name
                );
            }
        }
    }

    #[test]
    fn every_constitutive_model_is_registered() {
        for v in brisance_constitutive::MaterialModel::VARIANTS {
            assert!(
                ENTRIES
                    .iter()
                    .any(|e| e.family == "material" && e.name == *v),
                "{v} missing from the registry"
            );
        }
    }

    #[test]
    fn every_boundary_condition_is_registered() {
        for bc in [
            BoundaryConfig::Outflow,
            BoundaryConfig::ZeroGradient,
            BoundaryConfig::OutflowOnly,
            BoundaryConfig::Reflective,
            BoundaryConfig::Periodic,
            BoundaryConfig::Fixed(
                ron_options()
                    .from_str("(density: 1.0, pressure: 1.0)")
                    .expect("a state"),
            ),
            BoundaryConfig::Wall,
        ] {
            assert!(
                ENTRIES
                    .iter()
                    .any(|e| e.family == "boundary" && e.name == bc.name()),
                "{} missing from the registry",
                bc.name()
            );
        }
    }

    #[test]
    fn listing_names_every_entry() {
        let l = listing();
        for e in entries() {
            assert!(l.contains(e.name));
            if let Some(page) = e.docs {
                assert!(l.contains(&format!("docs: {page}")), "{l}");
            }
        }
        assert!(!l.contains("(none registered yet)"), "{l}");
    }

    /// Every `ReactionModel` of the reaction crate is listed under its
    /// trait name, and the models a config names parse there.
    #[test]
    fn every_reaction_model_is_registered() {
        use brisance_core::ReactionModel;
        let names = [
            brisance_reaction::JwlPlusPlus::anfo_k1().name(),
            brisance_reaction::ProgramBurn.name(),
            ReactionModel::name(&brisance_reaction::Deflagration::pbx_9501()),
            brisance_reaction::Arrhenius {
                pre_exponential: 5.0e6,
                activation_energy: 92_109.6,
                catalytic_factor: 1.0,
            }
            .name(),
            brisance_reaction::ProgramBurnRamp {
                detonation_velocity: 6930.0,
                cell_size: 1e-4,
            }
            .name(),
        ];
        for v in names {
            assert!(
                ENTRIES
                    .iter()
                    .any(|e| e.family == "reaction" && e.name == v),
                "{v} missing from the registry"
            );
        }
    }
}
