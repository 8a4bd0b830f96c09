//! The `Peridynamics` pipeline: bond-based peridynamics with the detonation
//! model of seed 004 (`brisance_pd`).
//!
//! The scenario's `initial` regions are the bodies, in order (a lattice
//! site belongs to the first region that contains it); each region's
//! `material` names an entry of the pipeline's `materials`, which holds its
//! peridynamic parameters, and its `state.velocity` is the body's initial
//! velocity (the other state fields are checked but not used: the
//! peridynamic material's density is the node density). The `domain` only
//! bounds the output and must contain the bodies.

use std::collections::BTreeMap;

use brisance_eos::Jwl;
use brisance_pd::{
    BodySpec, BurnMethod, ContactOptions, DetonationPoint, DetonationSpec, Dimension, Gas,
    PdBoundary, PdMaterial, PdOptions, PdSetup, PdSolver, ProductsIsentrope, Proportional,
    ProportionalKind, Reactant,
};
use serde::{Deserialize, Serialize};

use crate::config::{Region, Scenario};

/// Options of the Peridynamics pipeline.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PdConfig {
    /// Lattice spacing h, m.
    pub spacing: f64,
    /// Horizon δ as a multiple of h (default 3).
    #[serde(default = "default_horizon_factor")]
    pub horizon_factor: f64,
    /// Safety factor on the stable step of seed 004 eq 24 (default 0.8).
    #[serde(default = "default_safety")]
    pub safety_factor: f64,
    /// Energy-method surface correction of solid bonds (default true).
    #[serde(default = "default_true")]
    pub surface_correction: bool,
    /// Short-range forces (seed 004 eq 27); `None` turns them off.
    #[serde(default = "default_contact")]
    pub contact: Option<PdContactConfig>,
    /// Body force density b, N/m³ (seed 004 eq 9).
    #[serde(default)]
    pub body_force: [f64; 3],
    /// Peridynamic parameters of each material the regions name.
    pub materials: BTreeMap<String, PdMaterialConfig>,
    /// Prescribed node velocities.
    #[serde(default)]
    pub boundaries: Vec<PdBoundaryConfig>,
    /// Program burn (needed when a region is an explosive).
    #[serde(default)]
    pub detonation: Option<PdDetonationConfig>,
    /// Pair viscosity between approaching products nodes, its work returned
    /// as heat (`brisance_pd::GasViscosity`, docs/physics/pd/gas.md):
    /// `gas_viscosity: (linear: 1.0, quadratic: 2.0)`; default none (measured not to
    /// help the cylinder test).
    #[serde(default)]
    pub gas_viscosity: Option<brisance_pd::GasViscosity>,
}

fn default_horizon_factor() -> f64 {
    3.0
}
fn default_safety() -> f64 {
    0.8
}
fn default_true() -> bool {
    true
}
fn default_contact() -> Option<PdContactConfig> {
    Some(PdContactConfig {
        force_factor: 15.0,
        distance_factor: 1.35,
        reference_fraction: 0.9,
    })
}
fn default_reference_fraction() -> f64 {
    0.9
}

/// Short-range force parameters.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PdContactConfig {
    /// F_SR.
    pub force_factor: f64,
    /// p_contact / h, the largest contact distance of a pair (default 1.35).
    pub distance_factor: f64,
    /// A pair's contact distance is at most this fraction of its reference
    /// separation (default 0.9; `docs/physics/pd/contact.md`).
    #[serde(default = "default_reference_fraction")]
    pub reference_fraction: f64,
}

/// A peridynamic material.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub enum PdMaterialConfig {
    /// A proportional solid (seed 004 eqs 7–8, 28).
    Proportional {
        /// Density, kg/m³.
        density: f64,
        /// Bulk sound speed, m/s.
        sound_speed: f64,
        /// Yield strength, Pa (omit for none).
        #[serde(default)]
        yield_strength: Option<f64>,
        /// Critical stretch (omit for none).
        #[serde(default)]
        critical_stretch: Option<f64>,
        /// `MicroElastic` or `MicroPlastic`.
        kind: ProportionalKind,
        /// Damage-stretch coefficient (default 0).
        #[serde(default)]
        damage_stretch_coefficient: f64,
        /// Minimum-stretch coefficient (default 0).
        #[serde(default)]
        minimum_stretch_coefficient: f64,
    },
    /// An explosive whose products are a JWL gas (seed 004 eq 30), P_S0 from
    /// the volume burn (eqs 20–21); the detonation velocity is the CJ one
    /// unless given.
    JwlExplosive {
        /// JWL parameters.
        jwl: Jwl,
        /// Detonation velocity for program burn, m/s.
        #[serde(default)]
        detonation_velocity: Option<f64>,
        /// The unreacted explosive's Murnaghan response before its
        /// detonation time, `(n: ..., kappa: ...)` (omit for none: the
        /// products then do not push the explosive ahead of the front).
        #[serde(default)]
        reactant: Option<Reactant>,
    },
    /// An explosive with ideal-gas products (seed 004 eq 29).
    IdealGasExplosive {
        /// γ of the products.
        gamma: f64,
        /// Density of the explosive, kg/m³.
        density: f64,
        /// Heat of detonation, J/kg.
        heat: f64,
        /// Detonation velocity for program burn, m/s.
        #[serde(default)]
        detonation_velocity: Option<f64>,
        /// The unreacted explosive's Murnaghan response before its
        /// detonation time, `(n: ..., kappa: ...)` (omit for none: the
        /// products then do not push the explosive ahead of the front).
        #[serde(default)]
        reactant: Option<Reactant>,
    },
}

/// Prescribed velocities of the nodes in a region.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PdBoundaryConfig {
    /// Region (reference positions).
    pub region: Region,
    /// Prescribed components, m/s (`None`: free); `(Some(0), Some(0),
    /// Some(0))` fixes the nodes.
    pub velocity: [Option<f64>; 3],
}

/// Program burn input (the reaction model `ProgramBurn`: the config may
/// write it `ProgramBurn(points: [...], method: Huygens)` or without the
/// name).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, rename = "ProgramBurn")]
pub struct PdDetonationConfig {
    /// Detonation points with their start times.
    pub points: Vec<DetonationPoint>,
    /// `Huygens` (around obstacles, default) or `StraightLine`.
    #[serde(default = "default_burn")]
    pub method: BurnMethod,
}

fn default_burn() -> BurnMethod {
    BurnMethod::Huygens
}

type Problem = (String, String);

fn material(path: &str, m: &PdMaterialConfig) -> Result<PdMaterial, Problem> {
    let err = |field: &str, msg: String| (format!("{path}.{field}"), msg);
    match m {
        PdMaterialConfig::Proportional {
            density,
            sound_speed,
            yield_strength,
            critical_stretch,
            kind,
            damage_stretch_coefficient,
            minimum_stretch_coefficient,
        } => {
            let p = Proportional {
                density: *density,
                sound_speed: *sound_speed,
                yield_strength: yield_strength.unwrap_or(f64::INFINITY),
                critical_stretch: critical_stretch.unwrap_or(f64::INFINITY),
                kind: *kind,
                damage_stretch_coefficient: *damage_stretch_coefficient,
                minimum_stretch_coefficient: *minimum_stretch_coefficient,
            };
            p.validate().map_err(|e| (path.to_string(), e))?;
            Ok(PdMaterial::Proportional(p))
        }
        PdMaterialConfig::JwlExplosive {
            jwl,
            detonation_velocity,
            reactant,
        } => {
            let (isentrope, cj) =
                ProductsIsentrope::from_jwl(jwl).map_err(|e| err("jwl", e.to_string()))?;
            if let Some(r) = reactant {
                r.validate().map_err(|e| err("reactant", e))?;
            }
            let g = Gas {
                density: jwl.rho0,
                detonation_velocity: detonation_velocity.unwrap_or(cj.detonation_velocity),
                isentrope,
                reactant: *reactant,
            };
            PdMaterial::Gas(g)
                .validate()
                .map_err(|e| err("detonation_velocity", e))?;
            Ok(PdMaterial::Gas(g))
        }
        PdMaterialConfig::IdealGasExplosive {
            gamma,
            density,
            heat,
            detonation_velocity,
            reactant,
        } => {
            let (isentrope, cj) = ProductsIsentrope::ideal_gas(*gamma, *density, *heat)
                .map_err(|e| (path.to_string(), e.to_string()))?;
            if let Some(r) = reactant {
                r.validate().map_err(|e| err("reactant", e))?;
            }
            let g = Gas {
                density: *density,
                detonation_velocity: detonation_velocity.unwrap_or(cj.detonation_velocity),
                isentrope,
                reactant: *reactant,
            };
            PdMaterial::Gas(g)
                .validate()
                .map_err(|e| err("detonation_velocity", e))?;
            Ok(PdMaterial::Gas(g))
        }
    }
}

/// The solver setup a scenario with a `Peridynamics` pipeline describes;
/// errors name the field path.
pub fn setup(s: &Scenario, pd: &PdConfig) -> Result<PdSetup, Problem> {
    let mut names: Vec<&String> = Vec::new();
    let mut materials = Vec::new();
    let mut bodies = Vec::new();
    for (i, r) in s.initial.iter().enumerate() {
        let index = match names.iter().position(|n| **n == r.material) {
            Some(k) => k,
            None => {
                let m = pd.materials.get(&r.material).ok_or_else(|| {
                    (
                        format!("initial.{i}.material"),
                        format!(
                            "`{}` has no entry in pipeline.materials (known: {})",
                            r.material,
                            pd.materials
                                .keys()
                                .map(|k| format!("`{k}`"))
                                .collect::<Vec<_>>()
                                .join(", ")
                        ),
                    )
                })?;
                materials.push(material(&format!("pipeline.materials.{}", r.material), m)?);
                names.push(&r.material);
                names.len() - 1
            }
        };
        bodies.push(BodySpec {
            shape: r.region.clone(),
            material: index as u16,
            velocity: r.state.velocity,
        });
    }
    Ok(PdSetup {
        options: PdOptions {
            spacing: pd.spacing,
            horizon_factor: pd.horizon_factor,
            origin: [0.0; 3],
            dimension: Dimension::Three,
            cross_section: 0.0,
            safety_factor: pd.safety_factor,
            surface_correction: pd.surface_correction,
            contact: pd.contact.map(|c| ContactOptions {
                force_factor: c.force_factor,
                distance_factor: c.distance_factor,
                reference_fraction: c.reference_fraction,
            }),
            body_force: pd.body_force,
            min_dt: 1.0e-15,
        },
        materials,
        bodies,
        boundaries: pd
            .boundaries
            .iter()
            .map(|b| PdBoundary {
                region: b.region.clone(),
                velocity: b.velocity,
            })
            .collect(),
        detonation: pd.detonation.as_ref().map(|d| DetonationSpec {
            points: d.points.clone(),
            method: d.method,
        }),
    })
}

/// Checks a `Peridynamics` pipeline without building the node lattice.
pub fn validate(s: &Scenario, pd: &PdConfig) -> Result<(), Problem> {
    if !(pd.spacing > 0.0 && pd.spacing.is_finite()) {
        return Err((
            "pipeline.spacing".into(),
            format!("spacing must be a finite value > 0 m, got {}", pd.spacing),
        ));
    }
    if !(pd.horizon_factor >= 1.0 && pd.horizon_factor.is_finite()) {
        return Err((
            "pipeline.horizon_factor".into(),
            format!("horizon_factor must be ≥ 1, got {}", pd.horizon_factor),
        ));
    }
    if !(pd.safety_factor > 0.0 && pd.safety_factor <= 1.0) {
        return Err((
            "pipeline.safety_factor".into(),
            format!("safety_factor must lie in (0, 1], got {}", pd.safety_factor),
        ));
    }
    // The nodes are written as particles; there is no grid to put cell
    // fields or line-outs on (gauges sample the nearest node).
    if !s.outputs.fields.is_empty() {
        return Err((
            "outputs.fields".into(),
            "the Peridynamics pipeline writes its nodes as particles and has no cell fields: \
             write `fields: []` (point gauges can sample the node fields)"
                .into(),
        ));
    }
    if !s.outputs.lineouts.is_empty() {
        return Err((
            "outputs.lineouts".into(),
            "the Peridynamics pipeline has no cell fields to take line-outs of: write `lineouts: []`"
                .into(),
        ));
    }
    let setup = setup(s, pd)?;
    let explosive = setup
        .materials
        .iter()
        .any(|m| matches!(m, PdMaterial::Gas(_)));
    if explosive && pd.detonation.as_ref().is_none_or(|d| d.points.is_empty()) {
        return Err((
            "pipeline.detonation".into(),
            "an explosive region needs detonation points".into(),
        ));
    }
    Ok(())
}

/// Builds the peridynamic solver, its nodes spread over the ranks of the
/// run ([`brisance_grid::comm::world`]; docs/cluster.md).
pub fn build(s: &Scenario, pd: &PdConfig) -> Result<PdSolver, Problem> {
    let setup = setup(s, pd)?;
    let mut solver = PdSolver::new(setup).map_err(|e| ("pipeline".to_string(), e.to_string()))?;
    solver
        .set_gas_viscosity(pd.gas_viscosity)
        .map_err(|e| ("pipeline.gas_viscosity".to_string(), e.to_string()))?;
    solver
        .distribute(brisance_grid::comm::world())
        .map_err(|e| ("pipeline.spacing".to_string(), e))?;
    Ok(solver)
}

/// One paragraph for `check`.
pub fn describe(s: &Scenario, pd: &PdConfig) -> String {
    format!(
        "scenario `{}`: Peridynamics pipeline (bond-based, seed 004), spacing {} m, horizon {} h, \
         safety factor {}, contact {:?}\n  bodies: {}\n  time: to {} s",
        s.name,
        pd.spacing,
        pd.horizon_factor,
        pd.safety_factor,
        pd.contact,
        s.initial
            .iter()
            .map(|r| format!("`{}`", r.material))
            .collect::<Vec<_>>()
            .join(", "),
        s.time.end
    )
}

#[cfg(test)]
mod tests {
    use crate::build::build_solver;
    use crate::load_str;

    /// Both reduced peridynamic scenarios load, validate, build and step;
    /// a misspelt material is reported with its field path.
    #[test]
    fn pd_configs_load_build_and_step() {
        for (name, text) in [
            (
                "pd_cylinder.ron",
                include_str!("../../../configs/pd_cylinder.ron"),
            ),
            (
                "pd_fragment.ron",
                include_str!("../../../configs/pd_fragment.ron"),
            ),
        ] {
            let loaded = load_str(name, text, &[]).unwrap_or_else(|e| panic!("{name}: {e}"));
            let mut solver = build_solver(&loaded.scenario).unwrap();
            assert_eq!(solver.name(), "pd");
            let m0 = solver.conservation_totals().mass;
            for _ in 0..3 {
                let dt = solver.stable_dt().unwrap();
                solver.advance(dt).unwrap();
            }
            assert_eq!(solver.conservation_totals().mass, m0);
            assert!(solver.particle_data().unwrap().positions.len() > 1000);
        }
        let text = include_str!("../../../configs/pd_fragment.ron");
        let e = load_str("bad.ron", text, &["initial.1.material=\"stele\"".into()]).unwrap_err();
        assert!(e.to_string().contains("initial.1.material"), "{e}");
    }

    /// The numbers of a shape, for comparisons to a relative 1e-12 (the
    /// configs write the steel tube's outer radius 0.015875 m as one
    /// decimal, the cases as 0.0127 + 0.003175).
    fn shape_numbers(shape: &brisance_grid::Shape) -> (u8, Vec<f64>) {
        use brisance_grid::Shape;
        match shape {
            Shape::Cylinder {
                base,
                axis,
                radius,
                length,
            } => (0, [&base[..], &axis[..], &[*radius, *length]].concat()),
            Shape::Shell {
                base,
                axis,
                inner_radius,
                outer_radius,
                length,
            } => (
                1,
                [
                    &base[..],
                    &axis[..],
                    &[*inner_radius, *outer_radius, *length],
                ]
                .concat(),
            ),
            other => panic!("not a tube shape: {other:?}"),
        }
    }

    /// Whether the config's setup is the case's: the same spacing, options,
    /// detonation and bodies (each with the same material), whatever the
    /// order of the materials.
    fn assert_same_case(name: &str, a: &brisance_pd::PdSetup, b: &brisance_pd::PdSetup) {
        assert_eq!(a.options, b.options, "{name}: options");
        assert_eq!(a.detonation, b.detonation, "{name}: detonation");
        assert_eq!(a.boundaries, b.boundaries, "{name}: boundaries");
        assert_eq!(a.bodies.len(), b.bodies.len(), "{name}: bodies");
        for body in &a.bodies {
            let (kind, x) = shape_numbers(&body.shape);
            let twin = b
                .bodies
                .iter()
                .find(|c| {
                    let (k, y) = shape_numbers(&c.shape);
                    k == kind
                        && x.iter()
                            .zip(&y)
                            .all(|(p, q)| (p - q).abs() <= 1e-12 * p.abs().max(q.abs()))
                })
                .unwrap_or_else(|| panic!("{name}: no body of the case is {:?}", body.shape));
            assert_eq!(body.velocity, twin.velocity, "{name}");
            assert_eq!(
                a.materials[usize::from(body.material)],
                b.materials[usize::from(twin.material)],
                "{name}: material of {:?}",
                body.shape
            );
        }
    }

    /// The scenario files are the validation's cases: the reduced and the
    /// full configs of E-PD-CYL and E-PD-FRAG give the setups of
    /// `brisance_pd::cases` at their lengths, and end where the validation
    /// reads them (45 µs and 40 µs for the full tubes).
    #[test]
    fn pd_configs_are_the_cases_the_validation_runs() {
        use brisance_pd::cases::{copper_cylinder, steel_fragmenting_cylinder};
        let h = 1.3e-3;
        for (name, text, case, end) in [
            (
                "pd_cylinder.ron",
                include_str!("../../../configs/pd_cylinder.ron"),
                copper_cylinder(h, 0.03),
                12.0e-6,
            ),
            (
                "pd_cylinder_full.ron",
                include_str!("../../../configs/pd_cylinder_full.ron"),
                copper_cylinder(h, 0.258),
                45.0e-6,
            ),
            (
                "pd_fragment.ron",
                include_str!("../../../configs/pd_fragment.ron"),
                steel_fragmenting_cylinder(h, 0.02, 0.0, 0.0),
                15.0e-6,
            ),
            (
                "pd_fragment_full.ron",
                include_str!("../../../configs/pd_fragment_full.ron"),
                steel_fragmenting_cylinder(h, 0.10795, 0.0, 0.0),
                40.0e-6,
            ),
        ] {
            let loaded = load_str(name, text, &[]).unwrap_or_else(|e| panic!("{name}: {e}"));
            let crate::config::Pipeline::Peridynamics(pd) = &loaded.scenario.pipeline else {
                panic!("{name}: not a Peridynamics pipeline");
            };
            let setup = super::setup(&loaded.scenario, pd).unwrap();
            assert_same_case(name, &setup, &case.setup().unwrap());
            assert_eq!(loaded.scenario.time.end, end, "{name}");
        }
    }

    /// The reduced configs run to their end through the run loop: the
    /// copper tube's wall gauge moves outward, never back, and stays below
    /// the Gurney velocity; the steel tube's fragments (written at the
    /// end) hold the case's mass.
    #[test]
    fn reduced_pd_configs_run_to_their_end() {
        let dir = std::env::temp_dir().join(format!("brisance_pd_configs_{}", std::process::id()));
        let run_config = |name: &str, text: &str| {
            let loaded = load_str(name, text, &[]).unwrap();
            let out = dir.join(name);
            let summary = crate::run(
                &loaded,
                &crate::RunOptions {
                    out_dir: out.clone(),
                    restart: None,
                    progress: false,
                },
            )
            .unwrap();
            assert!(summary.completed, "{name}: {summary:?}");
            assert_eq!(summary.final_time, loaded.scenario.time.end, "{name}");
            out
        };
        let rows = |path: std::path::PathBuf| -> Vec<Vec<f64>> {
            std::fs::read_to_string(&path)
                .unwrap_or_else(|e| panic!("{}: {e}", path.display()))
                .lines()
                .skip(1)
                .map(|l| l.split(',').map(|c| c.parse().unwrap()).collect())
                .collect()
        };
        let out = run_config(
            "pd_cylinder.ron",
            include_str!("../../../configs/pd_cylinder.ron"),
        );
        // time, radial_displacement, velocity_x of the node nearest the
        // gauge point on the outer wall (x axis: v_x is radial there).
        let wall = rows(out.join("gauges").join("wall.csv"));
        let gurney = brisance_pd::cases::copper_cylinder(1.3e-3, 0.03)
            .gurney_wall_velocity()
            .unwrap();
        let last = wall.last().unwrap();
        assert!(last[1] > 0.5e-3, "wall displacement {:?}", last);
        for w in wall.windows(2) {
            assert!(w[1][1] >= w[0][1] - 1e-6, "{:?}", w);
        }
        assert!(last[2] > 0.0 && last[2] < gurney, "{last:?} {gurney}");
        let out = run_config(
            "pd_fragment.ron",
            include_str!("../../../configs/pd_fragment.ron"),
        );
        // rank, mass, nodes, vx, vy, vz, speed
        let fragments = rows(out.join("fragments.csv"));
        let total: f64 = fragments.iter().map(|f| f[1]).sum();
        let nodes: f64 = fragments.iter().map(|f| f[2]).sum();
        // Every steel node is in a fragment, each of mass ρ h³.
        let case = brisance_pd::cases::steel_fragmenting_cylinder(1.3e-3, 0.02, 0.0, 0.0);
        let solver = brisance_pd::PdSolver::new(case.setup().unwrap()).unwrap();
        let steel = solver.materials().iter().filter(|&&m| m == 0).count();
        assert_eq!(nodes, steel as f64);
        let case_mass = 7850.0 * 1.3e-3f64.powi(3) * steel as f64;
        assert!(
            (total - case_mass).abs() <= 1e-12 * case_mass,
            "{total} {case_mass}"
        );
        std::fs::remove_dir_all(&dir).unwrap();
    }

    /// `gas_viscosity` reaches the solver from the config, and a negative
    /// coefficient is refused naming the field.
    #[test]
    fn gas_viscosity_is_read_and_checked() {
        let text = include_str!("../../../configs/pd_cylinder.ron");
        let ok = "pipeline.gas_viscosity=(linear: 1.0, quadratic: 2.0)";
        let loaded = load_str("v.ron", text, &[ok.into()]).unwrap();
        let crate::config::Pipeline::Peridynamics(pd) = &loaded.scenario.pipeline else {
            panic!("not a Peridynamics pipeline");
        };
        assert_eq!(
            pd.gas_viscosity,
            Some(brisance_pd::GasViscosity {
                linear: 1.0,
                quadratic: 2.0
            })
        );
        let bad = "pipeline.gas_viscosity=(linear: -1.0, quadratic: 2.0)";
        let e = load_str("v.ron", text, &[bad.into()])
            .and_then(|l| crate::build::build_solver(&l.scenario).map(|_| ()))
            .unwrap_err();
        assert_eq!(e.field.as_deref(), Some("pipeline.gas_viscosity"), "{e}");
    }

    /// The explosive's `reactant` reaches the solver from the config, and
    /// an invalid one is refused naming the field.
    #[test]
    fn reactant_is_read_and_checked() {
        let text = include_str!("../../../configs/pd_cylinder.ron");
        let loaded = load_str("r.ron", text, &[]).unwrap();
        let crate::config::Pipeline::Peridynamics(pd) = &loaded.scenario.pipeline else {
            panic!("not a Peridynamics pipeline");
        };
        let Some(super::PdMaterialConfig::JwlExplosive { reactant, .. }) = pd.materials.get("tnt")
        else {
            panic!("no JWL explosive `tnt`");
        };
        assert_eq!(*reactant, Some(brisance_pd::Reactant::tnt()));
        let bad = "pipeline.materials.tnt.reactant=(n: 0.5, kappa: 1.0e-10)";
        let e = load_str("r.ron", text, &[bad.into()])
            .and_then(|l| crate::build::build_solver(&l.scenario).map(|_| ()))
            .unwrap_err();
        assert_eq!(
            e.field.as_deref(),
            Some("pipeline.materials.tnt.reactant"),
            "{e}"
        );
    }

    /// `boundaries` reach the solver: in an 8 × 3 × 3 steel bar (h = 1 mm)
    /// thrown at (3, −2, 5) m/s, the nodes of the first two planes (fixed)
    /// stay at rest at their reference positions, and those of the last
    /// two move at exactly v_x = 2.5 m/s, u_x = v_x t, their y and z
    /// free.
    #[test]
    fn boundaries_reach_the_solver() {
        let text = r#"Scenario(
    name: "pinned_bar",
    domain: (lower: (-0.01, -0.01, -0.01), upper: (0.02, 0.01, 0.01), cells: (3, 2, 2)),
    time: (end: 1.0e-6),
    materials: {"steel": (library: "steel_4340")},
    pipeline: Peridynamics(
        spacing: 1.0e-3,
        materials: {"steel": Proportional(density: 7850.0, sound_speed: 3212.0, kind: MicroElastic)},
        boundaries: [
            (region: Box(min: (-0.001, -0.001, -0.001), max: (0.002, 0.004, 0.004)), velocity: (Some(0.0), Some(0.0), Some(0.0))),
            (region: Box(min: (0.006, -0.001, -0.001), max: (0.009, 0.004, 0.004)), velocity: (Some(2.5), None, None)),
        ],
    ),
    initial: [
        (region: Box(min: (0.0, 0.0, 0.0), max: (0.008, 0.003, 0.003)), material: "steel", state: (density: 7850.0, velocity: (3.0, -2.0, 5.0), pressure: 1.0e5)),
    ],
    outputs: (interval: 1.0e-6, fields: [], vtk: false),
)"#;
        let loaded = load_str("pinned_bar.ron", text, &[]).unwrap();
        let crate::config::Pipeline::Peridynamics(pd) = &loaded.scenario.pipeline else {
            panic!("not a Peridynamics pipeline");
        };
        let setup = super::setup(&loaded.scenario, pd).unwrap();
        assert_eq!(setup.boundaries.len(), 2);
        assert_eq!(setup.boundaries[0].velocity, [Some(0.0); 3]);
        assert_eq!(setup.boundaries[1].velocity, [Some(2.5), None, None]);
        let mut solver = build_solver(&loaded.scenario).unwrap();
        for _ in 0..10 {
            let dt = solver.stable_dt().unwrap();
            solver.advance(dt).unwrap();
        }
        let t = solver.time();
        let data = solver.particle_data().unwrap();
        assert_eq!(data.positions.len(), 72);
        let field = |name: &str| {
            &data
                .fields
                .iter()
                .find(|(n, _)| n == name)
                .unwrap_or_else(|| panic!("no field `{name}`"))
                .1
        };
        let (ux, uy, uz) = (
            field("displacement_x"),
            field("displacement_y"),
            field("displacement_z"),
        );
        let (vx, vy, vz) = (
            field("velocity_x"),
            field("velocity_y"),
            field("velocity_z"),
        );
        let (mut fixed, mut driven) = (0, 0);
        for (i, y) in data.positions.iter().enumerate() {
            let x0 = y[0] - ux[i];
            if x0 < 0.002 {
                fixed += 1;
                assert_eq!([ux[i], uy[i], uz[i]], [0.0; 3], "node {i}");
                assert_eq!([vx[i], vy[i], vz[i]], [0.0; 3], "node {i}");
            } else if x0 > 0.006 {
                driven += 1;
                assert_eq!(vx[i], 2.5, "node {i}");
                assert!((ux[i] - 2.5 * t).abs() <= 1e-13 * 2.5 * t, "node {i}");
                // Free in z: the initial 5 m/s carries it on.
                assert!(uz[i] > 0.0, "node {i}");
            }
        }
        assert_eq!((fixed, driven), (18, 18));
    }

    /// Cell fields and line-outs have no grid to live on: asking for them
    /// is refused at load time, naming the field, instead of failing at
    /// the first output.
    #[test]
    fn cell_fields_and_lineouts_are_refused_at_load_time() {
        let text = include_str!("../../../configs/pd_fragment.ron");
        let e = load_str("f.ron", text, &["outputs.fields=[\"damage\"]".into()]).unwrap_err();
        assert_eq!(e.field.as_deref(), Some("outputs.fields"), "{e}");
        assert!(e.message.contains("no cell fields"), "{e}");
        let line = "outputs.lineouts=[(name: \"l\", from: (0.0, 0.0, 0.0), to: (0.01, 0.0, 0.0), points: 4, fields: [\"damage\"])]";
        let e = load_str("l.ron", text, &[line.into()]).unwrap_err();
        assert_eq!(e.field.as_deref(), Some("outputs.lineouts"), "{e}");
    }

    /// The run loop writes the fragments: two separate steel blocks (27
    /// and 8 nodes of h = 1 mm, further apart than the horizon, so no
    /// bond or contact joins them) flying apart at ±10 m/s are two
    /// fragments of exactly 27ρh³ and 8ρh³ whose velocities stay ±10 m/s;
    /// `fragments.csv` and `cmd.csv` are written at the end and
    /// `fragments/*_<index>.csv` at every output.
    #[test]
    fn run_loop_writes_fragments_and_cmd() {
        let text = r#"Scenario(
    name: "two_blocks",
    domain: (lower: (-0.01, -0.01, -0.01), upper: (0.02, 0.01, 0.01), cells: (3, 2, 2)),
    time: (end: 2.0e-7),
    materials: {"steel": (library: "steel_4340")},
    pipeline: Peridynamics(
        spacing: 1.0e-3,
        materials: {"steel": Proportional(density: 7850.0, sound_speed: 3212.0, critical_stretch: Some(0.11), kind: MicroElastic)},
    ),
    initial: [
        (region: Box(min: (0.0, 0.0, 0.0), max: (0.003, 0.003, 0.003)), material: "steel", state: (density: 7850.0, velocity: (10.0, 0.0, 0.0), pressure: 1.0e5)),
        (region: Box(min: (0.01, 0.0, 0.0), max: (0.012, 0.002, 0.002)), material: "steel", state: (density: 7850.0, velocity: (-10.0, 0.0, 0.0), pressure: 1.0e5)),
    ],
    outputs: (interval: 1.0e-7, fields: [], vtk: false),
)"#;
        let loaded = load_str("two_blocks.ron", text, &[]).unwrap();
        let dir = std::env::temp_dir().join(format!("brisance_pd_run_{}", std::process::id()));
        let summary = crate::run(
            &loaded,
            &crate::RunOptions {
                out_dir: dir.clone(),
                restart: None,
                progress: false,
            },
        )
        .unwrap();
        assert!(summary.completed);
        let read = |f: &str| std::fs::read_to_string(dir.join(f)).unwrap();
        let m = |n: f64| 7850.0 * n * 1.0e-9;
        let rows: Vec<Vec<f64>> = read("fragments.csv")
            .lines()
            .skip(1)
            .map(|l| l.split(',').map(|c| c.parse().unwrap()).collect())
            .collect();
        assert_eq!(rows.len(), 2);
        // rank, mass, nodes, vx, vy, vz, speed
        assert_eq!(rows[0][2], 27.0);
        assert!(
            (rows[0][1] - m(27.0)).abs() <= 1e-15 * m(27.0),
            "{:?}",
            rows[0]
        );
        assert_eq!(&rows[0][3..], &[10.0, 0.0, 0.0, 10.0]);
        assert_eq!(rows[1][2], 8.0);
        assert!(
            (rows[1][1] - m(8.0)).abs() <= 1e-15 * m(8.0),
            "{:?}",
            rows[1]
        );
        assert_eq!(&rows[1][3..], &[-10.0, 0.0, 0.0, 10.0]);
        let cmd: Vec<Vec<f64>> = read("cmd.csv")
            .lines()
            .skip(1)
            .map(|l| l.split(',').map(|c| c.parse().unwrap()).collect())
            .collect();
        assert_eq!(cmd.len(), 2);
        assert_eq!((cmd[0][1], cmd[1][1]), (1.0, 2.0));
        assert!((cmd[0][2] - 27.0 / 35.0).abs() < 1e-15);
        assert_eq!(cmd[1][2], 1.0);
        for k in 0..3 {
            assert_eq!(
                read(&format!("fragments/fragments_{k:05}.csv"))
                    .lines()
                    .count(),
                3
            );
            assert_eq!(
                read(&format!("fragments/cmd_{k:05}.csv")).lines().count(),
                3
            );
        }
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
