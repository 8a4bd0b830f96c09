//! The `Fdm` pipeline's section of a scenario (`pipeline: Fdm(...)`): its
//! schema, its checks against the shared parts of the scenario, its
//! builder and its description ([`brisance_scene::PipelineSpec`]).
//!
//! The pipeline carries one gas (`material`, a key of the scenario's
//! `materials` whose equation of state is a gas law), or that gas and
//! detonation products as a second species (`products`, a JWL; the
//! mixture rule of docs/physics/fdm_mixture.md). Every grid cell takes the
//! state of the last initial region holding its centre (on an (r, z) grid
//! the point (r, z, 0)); a region of the products material holds products
//! (mass fraction Y = 1), all others the gas (Y = 0). The faces are the
//! shared `boundaries`: `Outflow` is this pipeline's two-way zero
//! gradient, `Fixed` a reservoir of the gas.

use std::sync::Arc;

use brisance_core::{Eos, Geometry, Solver};
use brisance_eos::{EosModel, IdealGas};
use brisance_grid::comm::Communicator;
use brisance_grid::Level;
use brisance_scene::{
    fixed_face_material, BoundaryConfig, FieldError, OutputsSummary, PipelineInfo, PipelineLimits,
    PipelineSpec, Scene, StateConfig,
};
use serde::{Deserialize, Serialize};

use crate::{
    ArtificialViscosity, FaceLimiter, FdmBoundary, FdmOptions, FdmSolver, GasLaw, PrimitiveState,
    ProductsInAir,
};

/// Options of the FDM pipeline.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FdmConfig {
    /// The gas (a key of `materials`).
    pub material: String,
    /// Detonation products carried as a second species (a key of
    /// `materials`, a JWL): initial regions of this material hold products
    /// (mass fraction Y = 1), all others the gas `material` (Y = 0); the
    /// pressure of mixed cells follows docs/physics/fdm_mixture.md. None: one
    /// gas.
    #[serde(default)]
    pub products: Option<String>,
    /// Artificial viscosity (seed 001 eqs 3–5).
    #[serde(default)]
    pub viscosity: ViscosityConfig,
    /// The face limiter of the Lax–Wendroff step (docs/physics/fdm.md,
    /// "Face limiter"): `Full` (the default), `Positivity` or `Off`.
    #[serde(default)]
    pub limiter: LimiterConfig,
}

/// The face limiter of the FDM's Lax–Wendroff step.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
pub enum LimiterConfig {
    /// Positivity everywhere and the local density bounds at shocks.
    #[default]
    Full,
    /// Positivity only.
    Positivity,
    /// None: the scheme of seed 001 as printed, which stops at a
    /// non-physical state.
    Off,
}

impl LimiterConfig {
    /// The solver option.
    pub fn option(self) -> FaceLimiter {
        match self {
            Self::Full => FaceLimiter::Full,
            Self::Positivity => FaceLimiter::Positivity,
            Self::Off => FaceLimiter::Off,
        }
    }
}

/// Artificial viscosity law.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, Default)]
pub enum ViscosityConfig {
    /// η = ν(1 − ν) (seed 001 eq 5).
    #[default]
    Adaptive,
    /// A constant η in [0, 0.25].
    Constant(f64),
    /// None.
    Off,
}

impl ViscosityConfig {
    /// The solver option.
    pub fn option(self) -> ArtificialViscosity {
        match self {
            Self::Adaptive => ArtificialViscosity::Adaptive,
            Self::Constant(eta) => ArtificialViscosity::Constant(eta),
            Self::Off => ArtificialViscosity::Off,
        }
    }

    /// A constant η must lie in [0, 0.25] (seed 001 §2.1); the error names
    /// the field at `path`.
    pub fn check(self, path: &str) -> Result<(), FieldError> {
        match self {
            Self::Constant(eta) if !(0.0..=0.25).contains(&eta) => Err(FieldError::new(
                path,
                format!("constant η = {eta} must lie in [0, 0.25]"),
            )),
            _ => Ok(()),
        }
    }
}

/// The faces the Fdm pipeline takes.
pub const FACES: &[&str] = &[
    "Outflow",
    "ZeroGradient",
    "OutflowOnly",
    "Reflective",
    "Periodic",
    "Fixed",
];

/// Output fields of an FDM run with a products species.
const SPECIES_FIELDS: [&str; 11] = {
    let f = FdmSolver::<IdealGas>::FIELDS;
    [
        f[0],
        f[1],
        f[2],
        f[3],
        f[4],
        f[5],
        f[6],
        f[7],
        f[8],
        f[9],
        FdmSolver::<IdealGas>::MASS_FRACTION_FIELD,
    ]
};

/// The primitive state a [`StateConfig`] describes in a material of
/// equation of state `eos`.
pub fn primitive_state<E: Eos + ?Sized>(
    eos: &E,
    s: &StateConfig,
) -> Result<PrimitiveState, String> {
    Ok(PrimitiveState {
        density: s.density,
        velocity: s.velocity,
        pressure: s.pressure_in(eos)?,
    })
}

impl FdmConfig {
    /// The output fields: the gas's, and the products mass fraction where
    /// the run carries products.
    pub fn fields(&self) -> &'static [&'static str] {
        if self.products.is_some() {
            &SPECIES_FIELDS
        } else {
            &FdmSolver::<IdealGas>::FIELDS
        }
    }

    /// The gas's equation of state.
    fn gas<'a>(&self, scene: &Scene<'a>) -> Result<&'a EosModel, FieldError> {
        scene
            .material(&self.material)
            .and_then(|m| m.eos)
            .ok_or_else(|| {
                FieldError::new(
                    "pipeline.material",
                    format!(
                        "unknown material `{}`; known materials: {}",
                        self.material,
                        known(scene)
                    ),
                )
            })
    }

    /// The solver on `level` for gas law `law`, `gas` converting the
    /// boundary states, `region_state` giving each initial region's state
    /// and products mass fraction.
    fn solver<E: GasLaw + 'static>(
        &self,
        scene: &Scene<'_>,
        ranks: Arc<dyn Communicator>,
        level: Level,
        law: E,
        gas: &EosModel,
        region_state: impl Fn(&brisance_scene::InitialRegion) -> Result<(PrimitiveState, f64), String>,
    ) -> Result<Box<dyn Solver>, FieldError> {
        let mut boundaries = [FdmBoundary::Outflow; 6];
        for (k, (face, bc)) in scene.boundaries.faces().into_iter().enumerate() {
            boundaries[k] = match bc {
                // The Fdm pipeline's `Outflow` is the two-way zero gradient.
                BoundaryConfig::Outflow | BoundaryConfig::ZeroGradient => FdmBoundary::Outflow,
                BoundaryConfig::OutflowOnly => FdmBoundary::OutflowOnly,
                BoundaryConfig::Reflective => FdmBoundary::Reflective,
                BoundaryConfig::Periodic => FdmBoundary::Periodic,
                BoundaryConfig::Fixed(state) => FdmBoundary::Fixed(
                    primitive_state(gas, state)
                        .map_err(|m| FieldError::new(format!("boundaries.{face}"), m))?,
                ),
                BoundaryConfig::Wall => {
                    return Err(FieldError::new(
                        format!("boundaries.{face}"),
                        "`Wall` is a particle boundary; use `Reflective`",
                    ))
                }
            };
        }
        let states = scene
            .initial
            .iter()
            .enumerate()
            .map(|(i, r)| {
                region_state(r).map_err(|m| FieldError::new(format!("initial.{i}.state"), m))
            })
            .collect::<Result<Vec<_>, _>>()?;
        // Every cell must be covered; find an uncovered one before building.
        level
            .first_uncovered_cell(&*ranks, |x| scene.cell_region(x).is_some())
            .map_err(|e| FieldError::new("initial", e))?;
        let init = |x: [f64; 3]| states[scene.cell_region(x).unwrap_or(0)];
        let options = FdmOptions {
            cfl: scene.cfl,
            viscosity: self.viscosity.option(),
            limiter: self.limiter.option(),
            geometry: scene.domain.geometry,
            ..Default::default()
        };
        let solver = FdmSolver::with_species_on(ranks, law, level, boundaries, options, init)
            .map_err(|e| FieldError::new("pipeline", e.to_string()))?;
        Ok(Box::new(solver))
    }
}

/// The scene's materials, for the messages.
fn known(scene: &Scene<'_>) -> String {
    scene
        .materials
        .iter()
        .map(|m| format!("`{}`", m.name))
        .collect::<Vec<_>>()
        .join(", ")
}

impl PipelineSpec for FdmConfig {
    const INFO: PipelineInfo = PipelineInfo {
        name: "Fdm",
        summary: "3D Lax-Wendroff finite-difference Euler solver, Yanenko splitting, adaptive viscosity (seed 001 §2.1)",
        example: "Fdm(material: \"air\", viscosity: Adaptive)",
        docs: "docs/physics/fdm.md",
    };
    /// The solver's type depends on the gas law (the ideal gas has its
    /// own monomorphic solver), so the pipeline builds a boxed one.
    type Solver = Box<dyn Solver>;

    fn limits(&self, geometry: Geometry) -> PipelineLimits {
        PipelineLimits {
            fields: self.fields(),
            max_cfl: crate::MAX_CFL,
            // An (r, z) grid's radial sweep reaches one ghost layer further.
            ghost: crate::ghost_layers(geometry),
            node_fields: &[],
            patch_pieces: true,
            patch_checkpoints: true,
            particle_gauges: false,
            heat_conduction: false,
        }
    }

    fn validate(&self, scene: &Scene<'_>) -> Result<(), FieldError> {
        let eos = self.gas(scene)?;
        if !eos.is_gas() {
            return Err(FieldError::new(
                "pipeline.material",
                format!(
                    "the Fdm pipeline carries a gas ({}); `{}` is `{}`",
                    EosModel::gas_names().join(", "),
                    self.material,
                    eos.variant()
                ),
            ));
        }
        self.viscosity.check("pipeline.viscosity")?;
        scene.boundaries.check_faces("Fdm", FACES, |bc| {
            if matches!(bc, BoundaryConfig::Wall) {
                "; `Wall` is a particle boundary: use `Reflective` for a slip wall"
            } else {
                ""
            }
        })?;
        for (face, bc) in scene.boundaries.faces() {
            if let BoundaryConfig::Fixed(state) = bc {
                fixed_face_material(face, state, std::slice::from_ref(&self.material), "gas")?;
            }
        }
        for (i, r) in scene.initial.iter().enumerate() {
            if r.material != self.material && self.products.as_deref() != Some(r.material) {
                return Err(FieldError::new(
                    format!("initial.{i}.material"),
                    match &self.products {
                        None => format!("the Fdm pipeline carries one gas, `{}`", self.material),
                        Some(p) => format!(
                            "the Fdm pipeline carries the gas `{}` and the products `{p}`",
                            self.material
                        ),
                    },
                ));
            }
        }
        Ok(())
    }

    /// Builds the solver and spreads its patches over the ranks of the
    /// run (docs/cluster.md), each rank storing its own.
    fn build(&self, scene: &Scene<'_>) -> Result<Box<dyn Solver>, FieldError> {
        let d = &scene.domain;
        let level = Level::new(
            d.lower,
            d.upper,
            d.cells,
            d.patches,
            crate::ghost_layers(d.geometry),
        )
        .map_err(|e| FieldError::new("domain.patches", e.to_string()))?;
        let ranks = brisance_grid::comm::world();
        brisance_grid::comm::patch_owners(level.patches.len(), ranks.size())
            .map_err(|e| FieldError::new("domain.patches", e))?;
        let eos = self.gas(scene)?;
        if let Some(products) = &self.products {
            let products_eos = scene
                .material(products)
                .and_then(|m| m.eos)
                .ok_or_else(|| {
                    FieldError::new(
                        "pipeline.products",
                        format!("unknown material `{products}`"),
                    )
                })?;
            let mixture = ProductsInAir::new(products_eos.clone(), eos.clone())
                .map_err(|m| FieldError::new("pipeline.products", m))?;
            let state = |r: &brisance_scene::InitialRegion| {
                let burnt = r.material == products;
                let law = if burnt { products_eos } else { eos };
                primitive_state(law, r.state).map(|p| (p, if burnt { 1.0 } else { 0.0 }))
            };
            return self.solver(scene, ranks, level, mixture, eos, state);
        }
        let state =
            |r: &brisance_scene::InitialRegion| primitive_state(eos, r.state).map(|p| (p, 0.0));
        // The ideal gas gets its own monomorphic solver; other gases go
        // through the model enum.
        match eos {
            EosModel::IdealGas(gas) => self.solver(scene, ranks, level, *gas, eos, state),
            other => self.solver(scene, ranks, level, other.clone(), eos, state),
        }
    }

    fn describe(&self, scene: &Scene<'_>) -> String {
        let d = &scene.domain;
        let dims = d.cells.iter().filter(|&&c| c > 1).count();
        format!(
            "scenario `{}`: Fdm pipeline (Lax-Wendroff Euler, seed 001 §2.1), {dims}D {}\n  \
             grid: {} x {} x {} cells = {} cells in {} x {} x {} patches, from {:?} to {:?} m\n  \
             gas: `{}` ({}), viscosity {:?}\n  \
             time: to {} s at cfl {}\n  \
             boundaries: {}\n  \
             initial regions: {}\n  \
             outputs: {}",
            scene.name,
            d.geometry.name(),
            d.cells[0],
            d.cells[1],
            d.cells[2],
            d.cells.iter().product::<usize>(),
            d.patches[0],
            d.patches[1],
            d.patches[2],
            d.lower,
            d.upper,
            self.material,
            scene
                .material(&self.material)
                .and_then(|m| m.eos)
                .map_or("?", |e| e.variant()),
            self.viscosity,
            scene.end_time,
            scene.cfl,
            scene.boundaries.summary(),
            scene.initial.len(),
            OutputsSummary::describe(scene),
        )
    }
}

/// Registers the Lax–Wendroff Euler solver as the `Fdm` pipeline: a config
/// writes `pipeline: Fdm(...)`, and the composer checks, builds and
/// describes it through [`PipelineSpec`].
pub fn register(registry: &mut brisance_scene::plugin::PipelineRegistry) {
    registry.register(brisance_scene::plugin::PipelinePlugin::of::<FdmConfig>());
}

#[cfg(test)]
mod tests;
