//! The `Peridynamics` pipeline's section of a scenario (its config
//! schema), its validation against the scenario and its builder
//! ([`PipelineSpec`] for [`PdConfig`]; the composer hands it the
//! scenario's shared parts as a [`Scene`]): bond-based peridynamics with
//! the detonation model of seed 004.
//!
//! The scenario's `initial` regions are the bodies, in order (a lattice
//! site belongs to the first region that contains it); each region's
//! `material` names an entry of the pipeline's `materials`, which holds its
//! peridynamic parameters, and its `state.velocity` is the body's initial
//! velocity (the other state fields are checked by the composer but not
//! used: the peridynamic material's density is the node density). The
//! `domain` only bounds the output and must contain the bodies.

use std::collections::BTreeMap;

use brisance_eos::{Jwl, JwlCTerm};
use brisance_grid::Shape as Region;
use brisance_scene::{FieldError, PipelineInfo, PipelineLimits, PipelineSpec, Scene};
use serde::{Deserialize, Serialize};

use crate::strength::StretchSpread;
use crate::{
    BodySpec, BurnMethod, ContactOptions, DetonationPoint, DetonationSpec, Dimension, Gas,
    PdBoundary, PdMaterial, PdOptions, PdSetup, PdSolver, ProductsIsentrope, Proportional,
    ProportionalKind, Reactant,
};

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
    /// as heat (`crate::GasViscosity`, docs/physics/pd/gas.md):
    /// `gas_viscosity: (linear: 1.0, quadratic: 2.0)`, with the optional
    /// `shear` (receding pairs too) and `deviatoric` (shear only) terms;
    /// default none (measured not to help the cylinder test).
    #[serde(default)]
    pub gas_viscosity: Option<crate::GasViscosity>,
    /// A perturbed lattice, `jitter: (amplitude: 0.2, seed: 1)`: every
    /// node moved by a random offset of at most `amplitude` spacings along
    /// each axis (`crate::LatticeJitter`, docs/physics/pd/bond_based.md);
    /// default none, the regular cubic lattice.
    #[serde(default)]
    pub jitter: Option<crate::LatticeJitter>,
    /// A products node's step is at most this fraction of the shortest
    /// closing time p/ṗ of its family (`crate::CLOSING_STEP_FRACTION`,
    /// docs/physics/pd/gas.md, "Closing pairs"): default `Some(0.25)`;
    /// `None` sizes the step by eq 24 alone, as seed 004 prints it.
    #[serde(default = "default_closing")]
    pub closing_step_fraction: Option<f64>,
    /// Which nodes a products node's family holds (`crate::ProductsFamily`,
    /// docs/physics/pd/gas.md, "The case in the products' families"):
    /// `OwnBody` (default, seed 004 as printed), `WithSolids` (the solid
    /// nodes of other bodies within the horizon too) or `MirroredWall`
    /// (those families, the wall pairs carrying the products node's
    /// coefficient in full; "A mirrored wall").
    #[serde(default)]
    pub products_family: crate::ProductsFamily,
}

fn default_closing() -> Option<f64> {
    Some(crate::CLOSING_STEP_FRACTION)
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
        /// A Weibull-distributed critical stretch on a grain field,
        /// `(weibull_modulus: 4.0, grain_size: 3.0e-3, seed: 1)`
        /// (omit for the same critical stretch everywhere, seed 004 as
        /// printed; `docs/physics/pd/strength.md`).
        #[serde(default)]
        spread: Option<StretchSpread>,
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
    /// An explosive whose products are JWL++'s C-term products (seed 000
    /// §5.2, e.g. QM-100): their reference isentrope is seed 004 eq 30 as
    /// printed, P_S0 = P_S(1); the detonation velocity is the CJ one on it
    /// unless given (`ProductsIsentrope::from_jwl_cterm`).
    JwlCTermExplosive {
        /// The C-term products, `(a: ..., b: ..., c: ..., r1: ..., r2: ...,
        /// omega: ..., rho0: ..., cv: ...)` as the `JwlCTerm` EOS.
        products: JwlCTerm,
        /// Detonation velocity for program burn, m/s.
        #[serde(default)]
        detonation_velocity: Option<f64>,
        /// The unreacted explosive's Murnaghan response before its
        /// detonation time, `(n: ..., kappa: ...)` (omit for none).
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
            spread,
        } => {
            let p = Proportional {
                density: *density,
                sound_speed: *sound_speed,
                yield_strength: yield_strength.unwrap_or(f64::INFINITY),
                critical_stretch: critical_stretch.unwrap_or(f64::INFINITY),
                kind: *kind,
                damage_stretch_coefficient: *damage_stretch_coefficient,
                minimum_stretch_coefficient: *minimum_stretch_coefficient,
                spread: *spread,
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
            explosive(
                path,
                isentrope,
                cj,
                jwl.rho0,
                *detonation_velocity,
                reactant,
            )
        }
        PdMaterialConfig::JwlCTermExplosive {
            products,
            detonation_velocity,
            reactant,
        } => {
            let (isentrope, cj) = ProductsIsentrope::from_jwl_cterm(products)
                .map_err(|e| err("products", e.to_string()))?;
            explosive(
                path,
                isentrope,
                cj,
                products.rho0,
                *detonation_velocity,
                reactant,
            )
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
            explosive(
                path,
                isentrope,
                cj,
                *density,
                *detonation_velocity,
                reactant,
            )
        }
    }
}

/// An explosive's gas from its products isentrope and CJ state: density
/// `density`, the detonation velocity given or the CJ one, the reactant
/// checked; errors name `path`'s field.
fn explosive(
    path: &str,
    isentrope: ProductsIsentrope,
    cj: brisance_eos::tools::CjState,
    density: f64,
    detonation_velocity: Option<f64>,
    reactant: &Option<Reactant>,
) -> Result<PdMaterial, Problem> {
    let err = |field: &str, msg: String| (format!("{path}.{field}"), msg);
    if let Some(r) = reactant {
        r.validate().map_err(|e| err("reactant", e))?;
    }
    let g = Gas {
        density,
        detonation_velocity: detonation_velocity.unwrap_or(cj.detonation_velocity),
        isentrope,
        reactant: *reactant,
    };
    PdMaterial::Gas(g)
        .validate()
        .map_err(|e| err("detonation_velocity", e))?;
    Ok(PdMaterial::Gas(g))
}

/// The solver setup a scenario with a `Peridynamics` pipeline describes;
/// errors name the field path.
fn setup_of(s: &Scene<'_>, pd: &PdConfig) -> Result<PdSetup, Problem> {
    let mut names: Vec<&str> = Vec::new();
    let mut materials = Vec::new();
    let mut bodies = Vec::new();
    for (i, r) in s.initial.iter().enumerate() {
        let index = match names.iter().position(|n| *n == r.material) {
            Some(k) => k,
            None => {
                let m = pd.materials.get(r.material).ok_or_else(|| {
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
                names.push(r.material);
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
            jitter: pd.jitter,
            closing_step_fraction: pd.closing_step_fraction,
            products_family: pd.products_family,
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
fn check(s: &Scene<'_>, pd: &PdConfig) -> Result<(), Problem> {
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
    if let Some(j) = pd.jitter {
        j.validate()
            .map_err(|e| ("pipeline.jitter.amplitude".to_string(), e))?;
    }
    if !(pd.safety_factor > 0.0 && pd.safety_factor <= 1.0) {
        return Err((
            "pipeline.safety_factor".into(),
            format!("safety_factor must lie in (0, 1], got {}", pd.safety_factor),
        ));
    }
    if let Some(f) = pd.closing_step_fraction {
        if !(f > 0.0 && f <= 1.0) {
            return Err((
                "pipeline.closing_step_fraction".into(),
                format!("closing_step_fraction must lie in (0, 1], got {f}"),
            ));
        }
    }
    // The nodes are written as particles; there is no grid to put cell
    // fields or line-outs on (gauges sample the nearest node).
    if !s.cell_fields.is_empty() {
        return Err((
            "outputs.fields".into(),
            "the Peridynamics pipeline writes its nodes as particles and has no cell fields: \
             write `fields: []` (point gauges can sample the node fields)"
                .into(),
        ));
    }
    if s.line_outs > 0 {
        return Err((
            "outputs.lineouts".into(),
            "the Peridynamics pipeline has no cell fields to take line-outs of: write `lineouts: []`"
                .into(),
        ));
    }
    let setup = setup_of(s, pd)?;
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
fn build_solver(s: &Scene<'_>, pd: &PdConfig) -> Result<PdSolver, Problem> {
    let setup = setup_of(s, pd)?;
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
fn description(s: &Scene<'_>, pd: &PdConfig) -> String {
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
        s.end_time
    )
}

impl PdConfig {
    /// The solver setup the section and `scene` describe (the bodies, their
    /// materials, the options), without building the node lattice.
    pub fn setup(&self, scene: &Scene<'_>) -> Result<PdSetup, FieldError> {
        setup_of(scene, self).map_err(located)
    }
}

/// A (field path, message) pair as a [`FieldError`].
fn located((field, message): Problem) -> FieldError {
    FieldError::new(field, message)
}

impl PipelineSpec for PdConfig {
    const INFO: PipelineInfo = PipelineInfo {
        name: "Peridynamics",
        summary: "bond-based peridynamics: proportional micro-elastic/plastic solids with critical stretch, JWL or ideal-gas products as PD gases, program burn, short-range forces, fragments (seed 004)",
        example: "Peridynamics(spacing: 0.001, materials: {\"steel\": Proportional(density: 7850, sound_speed: 3212, yield_strength: Some(7.5e8), critical_stretch: Some(0.11), kind: MicroPlastic)})",
        docs: "docs/physics/pd/bond_based.md",
    };
    type Solver = PdSolver;

    /// One ghost layer (the node grid's), no patches; the step's own
    /// stability limit is not a Courant number.
    fn limits(&self, _geometry: brisance_core::Geometry) -> PipelineLimits {
        PipelineLimits {
            fields: &PdSolver::FIELDS,
            max_cfl: 1.0,
            ghost: 1,
            node_fields: &[],
            patch_pieces: false,
            patch_checkpoints: false,
            particle_gauges: false,
            heat_conduction: false,
        }
    }

    /// Checks the section without building the node lattice.
    /// Bond-based peridynamics joins two points, not two rings: no
    /// (r, z) form.
    fn unsupported(&self, geometry: brisance_core::Geometry) -> Option<&'static str> {
        geometry.is_axisymmetric().then_some(
            "bond-based peridynamics has no axisymmetric form (a bond joins two points, not two rings); run the Peridynamics pipeline on a 3D Cartesian grid",
        )
    }

    fn validate(&self, scene: &Scene<'_>) -> Result<(), FieldError> {
        check(scene, self).map_err(located)
    }

    /// Builds the peridynamic solver, its nodes spread over the ranks of
    /// the run ([`brisance_grid::comm::world`]; docs/cluster.md).
    fn build(&self, scene: &Scene<'_>) -> Result<PdSolver, FieldError> {
        build_solver(scene, self).map_err(located)
    }

    fn describe(&self, scene: &Scene<'_>) -> String {
        description(scene, self)
    }
}

/// Registers bond-based peridynamics as the `Peridynamics` pipeline: a config
/// writes `pipeline: Peridynamics(...)`, and the composer checks, builds
/// and describes it through [`PipelineSpec`].
pub fn register(registry: &mut brisance_scene::plugin::PipelineRegistry) {
    registry.register(brisance_scene::plugin::PipelinePlugin::of::<PdConfig>());
}

#[cfg(test)]
mod tests {
    use brisance_scene::{Domain, OwnedScene, StateConfig};

    use super::*;

    const STEEL: &str = "(spacing: 1e-3, materials: {\"steel\": Proportional(density: 7850, \
        sound_speed: 3212, kind: MicroElastic), \"tnt\": IdealGasExplosive(gamma: 3.0, \
        density: 1630.0, heat: 4.2e6)})";

    fn config(text: &str) -> PdConfig {
        ron::from_str(text).unwrap()
    }

    /// A 1 cm box with the material `steel` (no EOS) and the regions
    /// `initial` (shape, material, velocity).
    fn scene(
        initial: &[(Region, &str, [f64; 3])],
        fields: &[String],
        line_outs: usize,
    ) -> OwnedScene {
        let mut o = OwnedScene::new(Domain::cartesian([0.0; 3], [1e-2; 3], [1; 3]))
            .with_material("steel", None);
        for (region, material, velocity) in initial {
            let state = StateConfig::at_pressure(1.0, 1.0).moving(*velocity);
            o = o.with_region(region.clone(), material, state);
        }
        o.name = "pd".into();
        o.cell_fields = fields.to_vec();
        o.line_outs = line_outs;
        o
    }

    fn cube(lo: f64, hi: f64) -> Region {
        Region::Box {
            min: [lo; 3],
            max: [hi; 3],
        }
    }

    /// The bodies are the initial regions in order, each with its
    /// region's velocity; two regions of one material share its entry.
    #[test]
    fn the_scene_s_regions_are_the_bodies() {
        let initial = [
            (cube(0.0, 2e-3), "steel", [10.0, 0.0, 0.0]),
            (cube(4e-3, 6e-3), "steel", [0.0, -5.0, 0.0]),
        ];
        let setup = config(STEEL)
            .setup(&scene(&initial, &[], 0).scene())
            .unwrap();
        assert_eq!(setup.materials.len(), 1);
        assert_eq!(setup.bodies.len(), 2);
        assert_eq!(setup.bodies[1].velocity, [0.0, -5.0, 0.0]);
        assert_eq!(setup.bodies[1].material, 0);
        assert_eq!(setup.options.spacing, 1e-3);
        assert!(setup.options.contact.is_some());
        let d = config(STEEL).describe(&scene(&initial, &[], 0).scene());
        assert!(d.contains("bodies: `steel`, `steel`"), "{d}");
        assert_eq!(PdConfig::INFO.name, "Peridynamics");
    }

    /// `JwlCTermExplosive` gives the C-term products' printed isentrope,
    /// its density and the CJ velocity on it (or the one given); bad
    /// products and a bad reactant are refused naming the field.
    #[test]
    fn a_cterm_explosive_is_its_printed_isentrope() {
        let q = JwlCTerm::qm100();
        let text = "JwlCTermExplosive(products: (a: 4.8702e11, b: 2.54887e9, c: 5.06568e8, \
            r1: 5.0, r2: 1.0, omega: 0.3, rho0: 1260.0, cv: 793.65), \
            reactant: Some((n: 7.0, kappa: 1.02e-9)))";
        let m: PdMaterialConfig = ron::from_str(text).unwrap();
        let PdMaterial::Gas(g) = material("pipeline.materials.qm", &m).unwrap() else {
            panic!("not a gas");
        };
        let (iso, cj) = ProductsIsentrope::from_jwl_cterm(&q).unwrap();
        assert_eq!(g.isentrope, iso);
        assert_eq!(g.density, 1260.0);
        assert_eq!(g.detonation_velocity, cj.detonation_velocity);
        assert_eq!(g.reactant.map(|r| r.n), Some(7.0));
        let given: PdMaterialConfig = ron::from_str(
            &text.replace("reactant:", "detonation_velocity: Some(6000.0), reactant:"),
        )
        .unwrap();
        let PdMaterial::Gas(g) = material("m", &given).unwrap() else {
            panic!("not a gas");
        };
        assert_eq!(g.detonation_velocity, 6000.0);
        let bad: PdMaterialConfig =
            ron::from_str(&text.replace("a: 4.8702e11", "a: -1.0")).unwrap();
        assert_eq!(material("m", &bad).unwrap_err().0, "m.products");
        let bad: PdMaterialConfig = ron::from_str(&text.replace("n: 7.0", "n: -7.0")).unwrap();
        assert_eq!(material("m", &bad).unwrap_err().0, "m.reactant");
    }

    /// What the scene must give the section, each refusal naming its field.
    #[test]
    fn the_scene_is_checked_field_by_field() {
        let field = |text: &str, material: &str, fields: &[String], line_outs: usize| {
            let initial = [(cube(0.0, 2e-3), material, [0.0; 3])];
            config(text)
                .validate(&scene(&initial, fields, line_outs).scene())
                .unwrap_err()
                .field
        };
        let density = ["density".to_string()];
        assert_eq!(field(STEEL, "steel", &density, 0), "outputs.fields");
        assert_eq!(field(STEEL, "steel", &[], 1), "outputs.lineouts");
        assert_eq!(field(STEEL, "copper", &[], 0), "initial.0.material");
        assert_eq!(field(STEEL, "tnt", &[], 0), "pipeline.detonation");
        let zero = STEEL.replace("spacing: 1e-3", "spacing: 0.0");
        assert_eq!(field(&zero, "steel", &[], 0), "pipeline.spacing");
        let slow = STEEL.replace("sound_speed: 3212", "sound_speed: -1");
        assert_eq!(field(&slow, "steel", &[], 0), "pipeline.materials.steel");
        let shaken = STEEL.replace(
            "spacing: 1e-3",
            "spacing: 1e-3, jitter: Some((amplitude: 0.5))",
        );
        assert_eq!(field(&shaken, "steel", &[], 0), "pipeline.jitter.amplitude");
        for bad in ["0.0", "1.5", "-0.1"] {
            let rushed = STEEL.replace(
                "spacing: 1e-3",
                &format!("spacing: 1e-3, closing_step_fraction: Some({bad})"),
            );
            assert_eq!(
                field(&rushed, "steel", &[], 0),
                "pipeline.closing_step_fraction"
            );
        }
    }

    /// The solver options the steel block's config `text` builds.
    fn steel_options(text: &str) -> crate::PdOptions {
        let initial = [(cube(0.0, 4e-3), "steel", [0.0; 3])];
        config(text)
            .setup(&scene(&initial, &[], 0).scene())
            .unwrap()
            .options
    }

    /// The steel block's config with `field: value` added to its section.
    fn steel_with(field: &str, value: &str) -> String {
        STEEL.replace("spacing: 1e-3", &format!("spacing: 1e-3, {field}: {value}"))
    }

    /// `closing_step_fraction` reaches the solver options: ¼ by default,
    /// the value given, or off with `None`.
    #[test]
    fn the_closing_step_fraction_reaches_the_options() {
        let fraction = |text: &str| steel_options(text).closing_step_fraction;
        let set = |v: &str| steel_with("closing_step_fraction", v);
        assert_eq!(fraction(STEEL), Some(crate::CLOSING_STEP_FRACTION));
        assert_eq!(fraction(&set("Some(0.5)")), Some(0.5));
        assert_eq!(fraction(&set("None")), None);
    }

    /// `products_family` reaches the solver options: `OwnBody` by default,
    /// `WithSolids` or `MirroredWall` when given; an unknown variant does
    /// not parse.
    #[test]
    fn the_products_family_reaches_the_options() {
        let family = |text: &str| steel_options(text).products_family;
        let set = |v: &str| steel_with("products_family", v);
        assert_eq!(family(STEEL), crate::ProductsFamily::OwnBody);
        assert_eq!(
            family(&set("WithSolids")),
            crate::ProductsFamily::WithSolids
        );
        assert_eq!(family(&set("OwnBody")), crate::ProductsFamily::OwnBody);
        assert_eq!(
            family(&set("MirroredWall")),
            crate::ProductsFamily::MirroredWall
        );
        assert!(ron::from_str::<PdConfig>(&set("AllBodies")).is_err());
    }

    /// `jitter` reaches the lattice: the section's nodes are the regular
    /// lattice's, each moved by its site's offset.
    #[test]
    fn a_jitter_in_the_config_moves_the_nodes() {
        let initial = [(cube(0.0, 4e-3), "steel", [0.0; 3])];
        let text = STEEL.replace(
            "spacing: 1e-3",
            "spacing: 1e-3, jitter: Some((amplitude: 0.2, seed: 3))",
        );
        let setup = config(&text)
            .setup(&scene(&initial, &[], 0).scene())
            .unwrap();
        let jitter = crate::LatticeJitter {
            amplitude: 0.2,
            seed: 3,
        };
        assert_eq!(setup.options.jitter, Some(jitter));
        assert_eq!(config(STEEL).jitter, None);
        let moved = PdSolver::new(setup).unwrap();
        let regular = PdSolver::new(
            config(STEEL)
                .setup(&scene(&initial, &[], 0).scene())
                .unwrap(),
        )
        .unwrap();
        // Every node of the 4 mm cube stays inside it (offsets ≤ 0.2 mm
        // from sites 0.5 mm inside), in the same order.
        assert_eq!(moved.node_count(), 64);
        for (x, y) in moved.reference().iter().zip(regular.reference()) {
            let site = [0, 1, 2].map(|d| (y[d] / 1e-3 - 0.5).round() as i64);
            let o = jitter.offset(site);
            for d in 0..3 {
                assert_eq!(x[d], y[d] + o[d] * 1e-3);
            }
        }
    }
}
