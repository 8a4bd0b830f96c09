//! The `IceMpm` pipeline's section of a scenario, its checks and its
//! builder (`brisance_scene::PipelineSpec`): Eulerian fluids (ICE) and
//! Lagrangian solids (MPM particles) on one grid, coupled by the step of
//! seed 000 §3.3 ([`super::IceMpm`]).
//!
//! ```ron
//! pipeline: IceMpm(
//!     ice: (materials: ["reactant", "products", "air"], reactions: [...]),
//!     solid: "copper",
//!     mpm: (shape_function: Linear, scheme: Musl, ppc: 2),
//! ),
//! ```
//!
//! `ice` is an `Ice` pipeline over the fluids (every option of that
//! pipeline, paths `pipeline.ice.*`). `solid` names a scenario material
//! with both an `eos` (its pressure in the equilibration, normally a
//! `SolidThreshold`) and a constitutive `model`, or a list of them
//! (`solid: ["copper", "pbx"]`); they become materials N + 1, N + 2, … of
//! the ICE output fields (`volume_fraction_k`, `density_k`, …), in the
//! order given. Several solids share the nodes' one velocity field
//! (single-velocity contact). A solid may be the reactant of one of
//! `ice.reactions` (its particles burn into the fluid product); it cannot
//! be a product.
//! `mpm` is an `Mpm` pipeline for its particles (paths `pipeline.mpm.*`;
//! USL or MUSL, no anti-locking). Initial regions of `solid` become
//! particles; the others fill the cells, and the fluids are fitted around
//! the particles before the first step. Particle gauges sample the solid's
//! particles.

use brisance_core::Geometry;
use brisance_ice::pipeline::IceConfig;
use brisance_mpm::{AntiLocking, MpmSolver, UpdateScheme};
use brisance_scene::{
    BoundaryConfig, FieldError, PipelineInfo, PipelineLimits, PipelineSpec, Scene,
};
use serde::{Deserialize, Serialize};

use super::IceMpm;
use crate::mpm_pipeline::{mpm_parts, thermal_properties, MpmConfig};

/// Options of the IceMpm pipeline.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct IceMpmConfig {
    /// The fluids and the ICE options.
    pub ice: IceConfig,
    /// The Lagrangian material(s) (EOS and constitutive model each).
    pub solid: Solids,
    /// The particle options.
    pub mpm: MpmConfig,
    /// How the temperature change steps 8–11 give a solid in each cell
    /// reaches its particles: `Nodes` (default: through the nodes by the
    /// adjoint of eq 18, heat conserving) or `Cell` (the cell each particle
    /// lies in, the rule before; docs/physics/couple/ice_mpm.md, "Heat
    /// between the frames").
    #[serde(default)]
    pub particle_heat: super::ParticleHeat,
}

/// One Lagrangian material or several.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(untagged)]
pub enum Solids {
    /// `solid: "copper"`.
    One(String),
    /// `solid: ["copper", "pbx"]`.
    Many(Vec<String>),
}

impl Solids {
    /// The names, in the order given.
    pub fn names(&self) -> &[String] {
        match self {
            Solids::One(n) => std::slice::from_ref(n),
            Solids::Many(v) => v,
        }
    }

    /// Whether `name` is one of them.
    pub fn contains(&self, name: &str) -> bool {
        self.names().iter().any(|n| n == name)
    }
}

/// The error with `pipeline.` re-rooted at `pipeline.<sub>.`.
fn under(sub: &str, e: FieldError) -> FieldError {
    match e.field.strip_prefix("pipeline") {
        Some(rest) => FieldError::new(format!("pipeline.{sub}{rest}"), e.message),
        None => e,
    }
}

/// The section the ICE side runs: the fluids and the solids (last, in
/// the order given).
fn ice_section(cfg: &IceMpmConfig) -> IceConfig {
    let mut ice = cfg.ice.clone();
    ice.materials.extend(cfg.solid.names().iter().cloned());
    ice
}

/// The scene the particle side sees: the solids as its only materials (the
/// regions of the fluids are the ICE's, [`mpm_parts`] leaves them out).
fn particle_scene<'a>(s: &Scene<'a>, cfg: &IceMpmConfig) -> Scene<'a> {
    let mut scene = s.clone();
    scene.materials.retain(|m| cfg.solid.contains(m.name));
    scene
}

/// The checks of the section against the scene.
fn check(s: &Scene<'_>, cfg: &IceMpmConfig) -> Result<(), FieldError> {
    let names = cfg.solid.names();
    if names.is_empty() {
        return Err(FieldError::new("pipeline.solid", "name at least one solid"));
    }
    for (k, name) in names.iter().enumerate() {
        if names[..k].contains(name) {
            return Err(FieldError::new(
                "pipeline.solid",
                format!("`{name}` is named twice"),
            ));
        }
        check_solid(s, cfg, name)?;
    }
    // Heat conduction is a part of the particles' step: the solids conduct,
    // the fluids do not.
    for m in &s.materials {
        let Some(thermal) = m.thermal else { continue };
        let path = format!("materials.{}.thermal", m.name);
        if !cfg.solid.contains(m.name) {
            return Err(FieldError::new(
                path,
                format!(
                    "`{}` is not a `solid` of the IceMpm pipeline (the fluids do not conduct); `thermal` is the heat conduction inside the particles of `Mpm` and the solids of `IceMpm`",
                    m.name
                ),
            ));
        }
        if let Some(model) = m.model {
            thermal_properties(&path, thermal, model)?;
        }
    }
    for (k, r) in cfg.ice.reactions.iter().enumerate() {
        if cfg.solid.contains(&r.product) {
            return Err(FieldError::new(
                format!("pipeline.ice.reactions.{k}.product"),
                format!(
                    "`{}` is a solid carried by particles; a product must be a fluid",
                    r.product
                ),
            ));
        }
    }
    if cfg.mpm.scheme == UpdateScheme::Usf {
        return Err(FieldError::new(
            "pipeline.mpm.scheme",
            "the coupled step runs `Usl` or `Musl`",
        ));
    }
    if cfg.mpm.anti_locking != AntiLocking::Off {
        return Err(FieldError::new(
            "pipeline.mpm.anti_locking",
            "the coupled step has no anti-locking option; use `Off`",
        ));
    }
    cfg.mpm
        .check_section(&particle_scene(s, cfg))
        .map_err(|e| under("mpm", e))?;
    if cfg.ice.pressure != brisance_ice::PressureSolve::Explicit {
        return Err(FieldError::new(
            "pipeline.ice.pressure",
            "the coupled step runs the explicit pressure only; use `Explicit`",
        ));
    }
    s.boundaries.check_faces(
        "IceMpm",
        &["Outflow", "Reflective", "Wall", "Periodic"],
        |bc| match bc {
            BoundaryConfig::OutflowOnly => {
                "; its `Outflow` already holds back what would enter the fluids"
            }
            _ => "; its particles have no reservoir to enter from",
        },
    )?;
    ice_section(cfg)
        .check_fluids(s)
        .map_err(|e| under("ice", e))?;
    Ok(())
}

/// The checks of one solid.
fn check_solid(s: &Scene<'_>, cfg: &IceMpmConfig, name: &str) -> Result<(), FieldError> {
    let solid = s.material(name).ok_or_else(|| {
        FieldError::new(
            "pipeline.solid",
            format!("`{name}` is not a scenario material"),
        )
    })?;
    if cfg.ice.materials.iter().any(|m| m == name) {
        return Err(FieldError::new(
            "pipeline.solid",
            format!("`{name}` is also in pipeline.ice.materials; list only the fluids there"),
        ));
    }
    if cfg.ice.transport.contains_key(name) {
        return Err(FieldError::new(
            format!("pipeline.ice.transport.{name}"),
            "the solid's stress and heat flux are its particles'; give transport for the fluids only",
        ));
    }
    if solid.eos.is_none() {
        return Err(FieldError::new(
            format!("materials.{name}.eos"),
            "the solid needs an `eos` for its pressure in the equilibration",
        ));
    }
    if solid.model.is_none() {
        return Err(FieldError::new(
            format!("materials.{name}.model"),
            "the solid needs a constitutive `model`",
        ));
    }
    if !s.initial.iter().any(|r| r.material == name) {
        return Err(FieldError::new(
            "initial",
            format!("no initial region is of the solid `{name}`"),
        ));
    }
    Ok(())
}

impl PipelineSpec for IceMpmConfig {
    const INFO: PipelineInfo = PipelineInfo {
        name: "IceMpm",
        summary: "ICE fluids and one MPM solid on one grid: one equilibration pressure, momentum and heat exchange in every cell, solid stress from σ + p I (seed 000 §3.3)",
        example: "IceMpm(ice: (materials: [\"air\"]), solid: \"steel\", mpm: (shape_function: Linear, scheme: Musl, ppc: 2))",
        docs: "docs/physics/couple/ice_mpm.md",
    };
    type Solver = IceMpm;

    /// The fluids' grid with the particles' node fields; the coupled state
    /// is checkpointed whole; the solids' particles take particle gauges
    /// and conduct heat.
    fn limits(&self, geometry: Geometry) -> PipelineLimits {
        PipelineLimits {
            node_fields: &MpmSolver::NODE_FIELDS,
            patch_checkpoints: false,
            particle_gauges: true,
            heat_conduction: true,
            ..self.ice.limits(geometry)
        }
    }

    fn validate(&self, scene: &Scene<'_>) -> Result<(), FieldError> {
        check(scene, self)
    }

    /// Builds the coupled solver: the ICE over the fluids and the solids
    /// (last, in the order given) on this process, the particles of the
    /// solids ([`mpm_parts`]), their updates spread over the ranks of the
    /// run ([`brisance_grid::comm::world`]; docs/cluster.md; nothing
    /// changes on one rank).
    fn build(&self, scene: &Scene<'_>) -> Result<IceMpm, FieldError> {
        check(scene, self)?;
        let ice = ice_section(self)
            .build_on(
                scene,
                self.solid.names().len(),
                std::sync::Arc::new(brisance_grid::comm::Serial),
            )
            .map_err(|e| under("ice", e))?;
        let mpm = mpm_parts(&particle_scene(scene, self), &self.mpm, true)
            .map_err(|e| under("mpm", e))?;
        // Particle materials are numbered in name order (mpm_parts); the
        // solids are ICE materials N + 1, … in the order given.
        let mut sorted: Vec<&String> = self.solid.names().iter().collect();
        sorted.sort();
        let fluids = self.ice.materials.len();
        let solids: Vec<usize> = sorted
            .iter()
            .map(|n| fluids + self.solid.names().iter().position(|m| m == *n).unwrap_or(0))
            .collect();
        let mut solver = IceMpm::new(ice, mpm, &solids)
            .map_err(|e| FieldError::new("pipeline", e.to_string()))?;
        solver.set_particle_heat(self.particle_heat);
        solver.distribute(brisance_grid::comm::world());
        Ok(solver)
    }

    fn describe(&self, s: &Scene<'_>) -> String {
        let d = &s.domain;
        let quoted = |names: &[String]| {
            names
                .iter()
                .map(|m| format!("`{m}`"))
                .collect::<Vec<_>>()
                .join(", ")
        };
        format!(
            "scenario `{}`: IceMpm pipeline (ICE–MPM, seed 000 §3.3), {} x {} x {} cells, \
             fluids {}, solid {} as particles ({:?}, {:?}, {} per cell per direction), \
             K {} kg/(m³·s) ({:?} at the solids' surface)\n  time: to {} s",
            s.name,
            d.cells[0],
            d.cells[1],
            d.cells[2],
            quoted(&self.ice.materials),
            quoted(self.solid.names()),
            self.mpm.shape_function,
            self.mpm.scheme,
            self.mpm.ppc,
            self.ice.momentum_exchange,
            self.ice.solid_exchange,
            s.end_time
        ) + match self.particle_heat {
            super::ParticleHeat::Nodes => "",
            super::ParticleHeat::Cell => {
                "\n  particle heat: each particle its cell's change (`Cell`)"
            }
        }
    }
}

/// Registers the coupled ICE–MPM as the `IceMpm` pipeline: a config writes
/// `pipeline: IceMpm(...)`, and the composer checks, builds and describes
/// it through [`PipelineSpec`].
pub fn register(registry: &mut brisance_scene::plugin::PipelineRegistry) {
    registry.register(brisance_scene::plugin::PipelinePlugin::of::<IceMpmConfig>());
}

#[cfg(test)]
mod tests;
