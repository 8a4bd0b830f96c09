//! The `Mpm` pipeline's section of a scenario, its checks and its builder
//! (`brisance_scene::PipelineSpec`): explicit MPM (seed 001 §2.2, seed 000
//! §3.2) with every initial region as particles of its material.
//!
//! ```ron
//! pipeline: Mpm(shape_function: Linear, scheme: Musl, ppc: 2,
//!               bulk_viscosity: On(quadratic: 1.5, linear: 0.06)),
//! ```
//!
//! The section lives here, beside the coupled pipelines, because its
//! particles may take the state of a remapped 1D detonation
//! ([`crate::gas_remap`]), and because the coupled pipelines build their
//! particles with it ([`mpm_parts`]): the `IceMpm` pipeline's solids and
//! the bridge's MPM region are `Mpm` sections of their own.

use brisance_constitutive::{MaterialModel, SpecificHeat};
use brisance_core::Geometry;
use brisance_core::Material;
use brisance_grid::Level;
use brisance_grid::Shape;
use brisance_mpm::{
    AntiLocking, BulkViscosity, GridBoundary, HeatConduction, LoadHistory, MaterialId, MpmOptions,
    MpmSetupError, MpmSolver, ParticleInit, ParticleSet, Particles, Reservoir, ReservoirKind,
    ReservoirState, ShapeFunction, SurfaceLoad, SurfaceLoadKind, ThermalProperties, UpdateScheme,
};
use brisance_scene::{
    fixed_face_material, BoundaryConfig, FieldError, PipelineInfo, PipelineLimits, PipelineSpec,
    Scene, StateConfig, ThermalConfig,
};
use serde::{Deserialize, Serialize};

use crate::gas_remap::{GasRemap, MpmRemapConfig};

/// Options of the MPM pipeline. Every initial region becomes particles of
/// its material, which must name a constitutive `model`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MpmConfig {
    /// Shape function: `Linear`, `Gimp` (uGIMP), `CpGimp` (contiguous-particle
    /// GIMP, docs/physics/mpm/gimp.md) or `QuadraticBSpline`.
    #[serde(default)]
    pub shape_function: ShapeFunction,
    /// Update scheme: `Usf`, `Usl` or `Musl`.
    #[serde(default)]
    pub scheme: UpdateScheme,
    /// Particles per cell per active direction.
    #[serde(default = "default_ppc")]
    pub ppc: usize,
    /// Body force per unit mass (gravity), m/s².
    #[serde(default)]
    pub gravity: [f64; 3],
    /// Nodes lighter than this fraction of the mean particle mass are
    /// treated as empty.
    #[serde(default = "default_mass_cutoff")]
    pub mass_cutoff: f64,
    /// Artificial bulk viscosity of the particles (default `Off`).
    #[serde(default)]
    pub bulk_viscosity: BulkViscosityConfig,
    /// The bulk viscosity of the `Null`-fluid (gas) particles, in place of
    /// `bulk_viscosity` for them: `Some(quadratic: 1.5, linear: 1.0)`
    /// gives a gas shock the linear term it needs without damping the
    /// solids (docs/physics/mpm/bulk_viscosity.md). Default `None`: the
    /// fluids take `bulk_viscosity`.
    #[serde(default)]
    pub fluid_bulk_viscosity: Option<BulkViscosity>,
    /// Volumetric anti-locking of the stress update: `Off` (the default)
    /// or `FBar`, the ΔF̄ volume averaging of Coombs et al. (2018) over
    /// the particles of each cell (docs/physics/mpm/anti_locking.md).
    #[serde(default)]
    pub anti_locking: AntiLocking,
    /// Prescribed tractions on particle surfaces (seed 001 eq 20).
    #[serde(default)]
    pub surface_loads: Vec<SurfaceLoadConfig>,
    /// Gas particles from a remapped 1D detonation, a `brisance remap`
    /// file or a `charge` the run remaps itself: particles of its `air`
    /// and `products` materials inside the remap's grid take their cell's
    /// remapped state (docs/physics/couple/bridge.md, pure MPM).
    #[serde(default)]
    pub remap: Option<MpmRemapConfig>,
}

/// A prescribed traction or pressure on the particles that start in
/// `region` (docs/physics/mpm/traction.md): each stands for the area
/// V⁰/h of the surface with outward normal `normal`, carried along by its
/// deformation.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SurfaceLoadConfig {
    /// Name, for messages.
    pub name: String,
    /// Where the loaded particles start (one layer of particles).
    pub region: Shape,
    /// Only particles of this material.
    #[serde(default)]
    pub material: Option<String>,
    /// `Traction((tx, ty, tz))` per unit area or `Pressure(p)`, Pa.
    pub load: SurfaceLoadKind,
    /// Outward normal of the loaded surface at the start (normalised).
    pub normal: [f64; 3],
    /// Thickness h of the loaded particle layer, m (default: the particle
    /// spacing along the normal, 1/Σ_d |n_d| ppc/Δx_d).
    #[serde(default)]
    pub thickness: Option<f64>,
    /// Time factor: `Constant` (default), `Ramp(rise_time: t)` or
    /// `Table([(t, s), ...])`.
    #[serde(default)]
    pub history: LoadHistory,
}

/// The artificial bulk viscosity of the particles
/// (docs/physics/mpm/bulk_viscosity.md): q = ρ l (Q₁ l (tr D)² − Q₂ c tr D)
/// in compression, added to the pressure.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, Default)]
pub enum BulkViscosityConfig {
    /// No bulk viscosity (the default).
    #[default]
    Off,
    /// On, with `quadratic` Q₁ (default 1.5) and `linear` Q₂ (default
    /// 0.06), LS-DYNA's defaults: `On()` or `On(quadratic: 1.5, linear: 0.06)`.
    On(BulkViscosity),
}

/// A section's `fluid_bulk_viscosity`: both coefficients finite and ≥ 0,
/// the error naming `pipeline.fluid_bulk_viscosity.<coefficient>`.
pub fn check_fluid_bulk_viscosity(v: Option<BulkViscosity>) -> Result<(), FieldError> {
    v.map_or(Ok(()), |v| {
        BulkViscosityConfig::On(v).check("pipeline.fluid_bulk_viscosity")
    })
}

/// The section's bulk viscosity in words ("Q1 = 1.5, Q2 = 0.06", "off"),
/// with the fluids' where they differ.
pub fn describe_bulk_viscosity(all: &BulkViscosityConfig, fluid: Option<BulkViscosity>) -> String {
    let words = |v: Option<BulkViscosity>| match v {
        None => "off".to_string(),
        Some(v) => format!("Q1 = {}, Q2 = {}", v.quadratic, v.linear),
    };
    match fluid {
        Some(f) if Some(f) != all.option() => {
            format!("{} (fluids {})", words(all.option()), words(Some(f)))
        }
        _ => words(all.option()),
    }
}

impl BulkViscosityConfig {
    /// The solver option.
    pub fn option(&self) -> Option<BulkViscosity> {
        match self {
            Self::Off => None,
            Self::On(v) => Some(*v),
        }
    }

    /// Both coefficients finite and ≥ 0; the error names the field under
    /// `path` (the section's `bulk_viscosity`).
    pub fn check(&self, path: &str) -> Result<(), FieldError> {
        match self.option().map(|v| v.validate()) {
            Some(Err((name, value))) => Err(FieldError::new(
                format!("{path}.{name}"),
                format!("bulk viscosity coefficient {name} = {value} must be finite and ≥ 0"),
            )),
            _ => Ok(()),
        }
    }
}

fn default_ppc() -> usize {
    2
}

fn default_mass_cutoff() -> f64 {
    1e-5
}

/// The faces the Mpm pipeline takes.
pub const MPM_FACES: &[&str] = &[
    "Outflow",
    "ZeroGradient",
    "OutflowOnly",
    "Fixed",
    "Reflective",
    "Wall",
];

fn finite3(v: &[f64; 3]) -> bool {
    v.iter().all(|x| x.is_finite())
}

/// The conductivity and specific heat of the particles of `model` that
/// `thermal` (at `path`) gives: k finite and ≥ 0, c_v finite and > 0 when
/// given, and a c_v from the model (the J2 metal's) when not and k > 0.
/// The MPM solver's own resolution, so that the config refuses what the
/// solver would.
pub fn thermal_properties(
    path: &str,
    thermal: &ThermalConfig,
    model: &MaterialModel,
) -> Result<ThermalProperties, FieldError> {
    let k = thermal.conductivity;
    if !(k >= 0.0 && k.is_finite()) {
        return Err(FieldError::new(
            format!("{path}.conductivity"),
            format!("conductivity must be finite and ≥ 0 W/(m·K), got {k}"),
        ));
    }
    if let Some(c) = thermal.specific_heat {
        if !(c > 0.0 && c.is_finite()) {
            return Err(FieldError::new(
                format!("{path}.specific_heat"),
                format!("specific_heat must be finite and > 0 J/(kg·K), got {c}"),
            ));
        }
    }
    let option = HeatConduction {
        conductivity: vec![k],
        specific_heat: vec![thermal.specific_heat.map(SpecificHeat::Constant)],
    };
    match option.resolve(std::slice::from_ref(model)) {
        Ok(mut p) => Ok(p.swap_remove(0)),
        Err(("heat_conduction.specific_heat", ..)) if thermal.specific_heat.is_none() => {
            Err(FieldError::new(
                path,
                format!(
                    "give `specific_heat`: a conducting material needs one, and the `{}` model carries none",
                    model.name()
                ),
            ))
        }
        Err((option, value, expected)) => {
            let field = option.rsplit('.').next().unwrap_or(option);
            Err(FieldError::new(
                format!("{path}.{field}"),
                format!("{field} = {value}: {expected}"),
            ))
        }
    }
}

/// The names of the scene's materials, each in backquotes, for messages.
fn known_materials(s: &Scene<'_>) -> String {
    s.materials
        .iter()
        .map(|m| format!("`{}`", m.name))
        .collect::<Vec<_>>()
        .join(", ")
}

impl MpmConfig {
    /// The checks of the section alone and against the scene that the
    /// particles of the coupled pipelines share (the `IceMpm` solids'
    /// section runs them too): ppc, mass cut-off, gravity, the remap, the
    /// surface loads, the bulk viscosity (paths under `pipeline`), and
    /// that a particle gauge's `material` is a particle material.
    pub fn check_section(&self, s: &Scene<'_>) -> Result<(), FieldError> {
        if self.ppc == 0 || self.ppc > 8 {
            return Err(FieldError::new(
                "pipeline.ppc",
                format!(
                    "ppc = {} must lie in 1..=8 particles per cell per direction",
                    self.ppc
                ),
            ));
        }
        if !(self.mass_cutoff >= 0.0 && self.mass_cutoff < 1.0) {
            return Err(FieldError::new(
                "pipeline.mass_cutoff",
                format!("mass_cutoff = {} must lie in [0, 1)", self.mass_cutoff),
            ));
        }
        if !finite3(&self.gravity) {
            return Err(FieldError::new(
                "pipeline.gravity",
                "gravity must be finite",
            ));
        }
        if let Some(r) = &self.remap {
            r.validate().map_err(|(f, m)| FieldError::new(f, m))?;
        }
        let mut load_names = std::collections::BTreeSet::new();
        for (i, l) in self.surface_loads.iter().enumerate() {
            let path = format!("pipeline.surface_loads.{i}");
            if l.name.is_empty() || !load_names.insert(l.name.clone()) {
                return Err(FieldError::new(
                    format!("{path}.name"),
                    format!(
                        "surface load name `{}` must be non-empty and unique",
                        l.name
                    ),
                ));
            }
            l.region
                .validate()
                .map_err(|e| FieldError::new(format!("{path}.region.{}", e.field), e.message))?;
            if let Some(m) = &l.material {
                if s.material(m).and_then(|m| m.model).is_none() {
                    return Err(FieldError::new(
                        format!("{path}.material"),
                        format!(
                            "surface load `{}`: `{m}` is not a particle material (one with a constitutive `model`); known materials: {}",
                            l.name,
                            known_materials(s)
                        ),
                    ));
                }
            }
            let n2: f64 = l.normal.iter().map(|c| c * c).sum();
            if !finite3(&l.normal) || !(n2 > 0.0) {
                return Err(FieldError::new(
                    format!("{path}.normal"),
                    format!(
                        "surface load `{}`: normal {:?} must be finite and non-zero",
                        l.name, l.normal
                    ),
                ));
            }
            if let Some(h) = l.thickness {
                if !(h > 0.0 && h.is_finite()) {
                    return Err(FieldError::new(
                        format!("{path}.thickness"),
                        format!(
                            "surface load `{}`: thickness {h} m must be positive",
                            l.name
                        ),
                    ));
                }
            }
            let finite = match l.load {
                SurfaceLoadKind::Traction(t) => finite3(&t),
                SurfaceLoadKind::Pressure(p) => p.is_finite(),
            };
            if !finite {
                return Err(FieldError::new(
                    format!("{path}.load"),
                    format!("surface load `{}`: the load must be finite", l.name),
                ));
            }
            l.history.validate().map_err(|m| {
                FieldError::new(
                    format!("{path}.history"),
                    format!("surface load `{}`: {m}", l.name),
                )
            })?;
        }
        self.bulk_viscosity.check("pipeline.bulk_viscosity")?;
        check_fluid_bulk_viscosity(self.fluid_bulk_viscosity)?;
        for (i, g) in s.particle_gauges.iter().enumerate() {
            if let Some(m) = g.material {
                if s.material(m).and_then(|m| m.model).is_none() {
                    return Err(FieldError::new(
                        format!("outputs.particle_gauges.{i}.material"),
                        format!(
                            "particle gauge `{}`: `{m}` is not a particle material (one with a constitutive `model`); known materials: {}",
                            g.name,
                            known_materials(s)
                        ),
                    ));
                }
            }
        }
        Ok(())
    }
}

/// The checks of the `Mpm` pipeline's own faces, regions and thermal
/// entries (those that do not hold for the coupled pipelines' particles).
fn check_alone(s: &Scene<'_>) -> Result<(), FieldError> {
    let reservoir = |bc: &BoundaryConfig| {
        matches!(
            bc,
            BoundaryConfig::ZeroGradient | BoundaryConfig::OutflowOnly | BoundaryConfig::Fixed(_)
        )
    };
    if s.domain.geometry.is_axisymmetric()
        && s.boundaries.faces().iter().any(|(_, bc)| reservoir(bc))
    {
        return Err(FieldError::new(
            "domain.geometry",
            "the Mpm pipeline's particle reservoirs (faces `ZeroGradient`, `OutflowOnly`, `Fixed`) do not run on Axisymmetric grids yet; use `Outflow`, `Reflective` or `Wall`",
        ));
    }
    for m in &s.materials {
        let Some(thermal) = m.thermal else { continue };
        let path = format!("materials.{}.thermal", m.name);
        let Some(model) = m.model else {
            return Err(FieldError::new(
                path,
                format!(
                    "`{}` has no constitutive `model`, so it is no particle material of the Mpm pipeline; `thermal` is the heat conduction inside the particles of `Mpm` and the solids of `IceMpm`",
                    m.name
                ),
            ));
        };
        thermal_properties(&path, thermal, model)?;
    }
    s.boundaries.check_faces("Mpm", MPM_FACES, |_| "")?;
    let particle_materials: Vec<String> = s
        .materials
        .iter()
        .filter(|m| m.model.is_some())
        .map(|m| m.name.to_string())
        .collect();
    for (face, bc) in s.boundaries.faces() {
        if let BoundaryConfig::Fixed(state) = bc {
            let m = fixed_face_material(face, state, &particle_materials, "particle material")?;
            if s.material(m)
                .and_then(|x| x.model)
                .and_then(|x| x.eos())
                .is_none()
            {
                return Err(FieldError::new(
                    format!("boundaries.{face}"),
                    format!("the particles a `Fixed` face brings in push with their pressure, which needs an equation of state; `{m}`'s model has none"),
                ));
            }
        }
    }
    for (i, r) in s.initial.iter().enumerate() {
        if s.material(r.material).is_some_and(|m| m.model.is_none()) {
            return Err(FieldError::new(
                format!("initial.{i}.material"),
                format!(
                    "`{}` has no constitutive `model`, which Mpm particles need",
                    r.material
                ),
            ));
        }
    }
    Ok(())
}

impl PipelineSpec for MpmConfig {
    const INFO: PipelineInfo = PipelineInfo {
        name: "Mpm",
        summary: "explicit material point method: USF/USL/MUSL, linear/GIMP/B-spline shapes, optional bulk viscosity (seed 001 §2.2, seed 000 §3.2)",
        example: "Mpm(shape_function: Linear, scheme: Musl, ppc: 2, bulk_viscosity: On(quadratic: 1.5, linear: 0.06))",
        docs: "docs/physics/mpm/explicit_mpm.md",
    };
    type Solver = MpmSolver;

    /// The particles' fields and the nodes' (their background grid); the
    /// time step's Courant number `time.cfl` at most 1; the particles are
    /// checkpointed and written whole.
    fn limits(&self, _geometry: Geometry) -> PipelineLimits {
        PipelineLimits {
            fields: &MpmSolver::FIELDS,
            max_cfl: 1.0,
            ghost: 1,
            node_fields: &MpmSolver::NODE_FIELDS,
            patch_pieces: false,
            patch_checkpoints: false,
            particle_gauges: true,
            heat_conduction: true,
        }
    }

    fn validate(&self, scene: &Scene<'_>) -> Result<(), FieldError> {
        check_alone(scene)?;
        self.check_section(scene)
    }

    /// Builds the solver, its particle updates spread over the ranks of
    /// the run ([`brisance_grid::comm::world`]; docs/cluster.md; nothing
    /// changes on one rank).
    fn build(&self, scene: &Scene<'_>) -> Result<MpmSolver, FieldError> {
        self.validate(scene)?;
        let mut solver = mpm_parts(scene, self, false)?;
        solver.distribute(brisance_grid::comm::world());
        Ok(solver)
    }

    fn describe(&self, s: &Scene<'_>) -> String {
        let d = &s.domain;
        let dims = d.cells.iter().filter(|&&c| c > 1).count();
        let materials: Vec<String> = s
            .materials
            .iter()
            .filter_map(|m| {
                m.model
                    .map(|model| format!("`{}` ({})", m.name, model.name()))
            })
            .collect();
        let o = s.outputs;
        format!(
            "scenario `{}`: Mpm pipeline (explicit MPM, seed 001 §2.2), {dims}D, {:?} shape functions, {:?}, {} particles per cell per direction, bulk viscosity {}\n  \
             grid: {} x {} x {} cells from {:?} to {:?} m\n  \
             materials: {}\n  \
             time: to {} s at cfl {}\n  \
             boundaries: {}\n  \
             initial regions: {}, surface loads: {}\n  \
             outputs: interval {:?}, fields [{}], {} gauges, {} particle gauges, {} line-outs, checkpoints every {:?} steps",
            s.name,
            self.shape_function,
            self.scheme,
            self.ppc,
            describe_bulk_viscosity(&self.bulk_viscosity, self.fluid_bulk_viscosity),
            d.cells[0],
            d.cells[1],
            d.cells[2],
            d.lower,
            d.upper,
            materials.join(", "),
            s.end_time,
            s.cfl,
            s.boundaries.summary(),
            s.initial.len(),
            self.surface_loads.len(),
            o.interval,
            s.cell_fields.join(", "),
            o.gauges,
            s.particle_gauges.len(),
            s.line_outs,
            o.checkpoint_every,
        )
    }
}

/// Registers the explicit MPM as the `Mpm` pipeline: a config writes
/// `pipeline: Mpm(...)`, and the composer checks, builds and describes it
/// through [`PipelineSpec`].
pub fn register(registry: &mut brisance_scene::plugin::PipelineRegistry) {
    registry.register(brisance_scene::plugin::PipelinePlugin::of::<MpmConfig>());
}

/// The temperature and specific internal energy of particles of `model`
/// in state `st` (`path` for the errors), from whichever the state gives,
/// through the model's equation of state when it has one.
fn particle_thermodynamics(
    model: &MaterialModel,
    st: &StateConfig,
    path: &str,
) -> Result<(f64, f64), FieldError> {
    Ok(
        match (
            model.eos(),
            st.temperature,
            st.specific_internal_energy,
            st.pressure,
        ) {
            (Some(eos), Some(t), None, None) => (
                t,
                eos.specific_internal_energy_from_temperature(st.density, t),
            ),
            (Some(eos), None, Some(e), None) => (eos.temperature(st.density, e), e),
            (Some(eos), None, None, Some(p)) => {
                let e = eos
                    .specific_internal_energy(st.density, p)
                    .map_err(|e| FieldError::new(format!("{path}.pressure"), e.to_string()))?;
                (eos.temperature(st.density, e), e)
            }
            (None, Some(t), None, None) => (t, 0.0),
            _ => {
                return Err(FieldError::new(
                    path,
                    "this material has no equation of state: give its `temperature`",
                ))
            }
        },
    )
}

/// The MPM solver of the scene `s`, holding the particle sets of its
/// gauges ([`MpmSolver::set_particle_gauges`]): every sub-cell point (`ppc` per active direction) inside an initial
/// region of a material with a constitutive model becomes a particle of
/// that region's material (the last region containing the point wins, as
/// for cells); each particle gauge selects the particles that start in its
/// region (and material), and an empty selection is an error naming the
/// gauge. A region of a material without a model is refused at its
/// `material`, unless `fluids_beside` (the coupled pipelines, whose other
/// regions are the fluids'), which leaves it out. Errors name a region by
/// its index in the scenario's `initial`, the section's fields under
/// `pipeline`. The solver runs on this process alone (the caller
/// distributes it).
pub fn mpm_parts(
    s: &Scene<'_>,
    mpm: &MpmConfig,
    fluids_beside: bool,
) -> Result<MpmSolver, FieldError> {
    let d = &s.domain;
    let level = Level::new(d.lower, d.upper, d.cells, d.patches, 1)
        .map_err(|e| FieldError::new("domain.patches", e.to_string()))?;
    let grid = level.geometry;
    // Materials with a constitutive model, numbered in name order.
    let names: Vec<&str> = s
        .materials
        .iter()
        .filter(|m| m.model.is_some())
        .map(|m| m.name)
        .collect();
    let models: Vec<MaterialModel> = s
        .materials
        .iter()
        .filter_map(|m| m.model.cloned())
        .collect();
    let stride = models.iter().map(|m| m.history_len()).max().unwrap_or(0);
    let mut regions = Vec::with_capacity(s.initial.len());
    for (i, r) in s.initial.iter().enumerate() {
        let path = format!("initial.{i}");
        let Some(id) = names.iter().position(|n| *n == r.material) else {
            if fluids_beside {
                continue;
            }
            return Err(FieldError::new(
                format!("{path}.material"),
                "the material has no constitutive `model`",
            ));
        };
        let (temperature, energy) =
            particle_thermodynamics(&models[id], r.state, &format!("{path}.state"))?;
        // A fluid's particles start at their EOS pressure, as the bridge's
        // and the remap's do: σ = −p(ρ, e) I (a solid starts unstressed,
        // its stress built by its constitutive model from the motion).
        let pressure = match (&models[id], models[id].eos()) {
            (MaterialModel::Null(_), Some(eos)) => eos.pressure(r.state.density, energy),
            _ => 0.0,
        };
        if !pressure.is_finite() {
            return Err(FieldError::new(
                format!("{path}.state"),
                format!("the fluid's pressure at this state is {pressure}"),
            ));
        }
        regions.push((r, MaterialId(id as u16), temperature, energy, pressure));
    }
    let ppc = mpm.ppc;
    let active: [bool; 3] = std::array::from_fn(|a| d.cells[a] > 1);
    let per_axis: [usize; 3] = std::array::from_fn(|a| if active[a] { ppc } else { 1 });
    let sub_volume =
        grid.spacing.iter().product::<f64>() / per_axis.iter().product::<usize>() as f64;
    let remap = mpm
        .remap
        .as_ref()
        .map(|r| GasRemap::new(r, &names, &models, &grid, d.geometry))
        .transpose()
        .map_err(|(path, message)| FieldError::new(path, message))?;
    let mut particles = Particles::new(stride);
    let history = vec![0.0; stride];
    for k in 0..d.cells[2] {
        for j in 0..d.cells[1] {
            for i in 0..d.cells[0] {
                for sk in 0..per_axis[2] {
                    for sj in 0..per_axis[1] {
                        for si in 0..per_axis[0] {
                            let idx = [i, j, k];
                            let sub = [si, sj, sk];
                            let x: [f64; 3] = std::array::from_fn(|a| {
                                grid.origin[a]
                                    + (idx[a] as f64 + (sub[a] as f64 + 0.5) / per_axis[a] as f64)
                                        * grid.spacing[a]
                            });
                            let Some(&(r, material, temperature, energy, pressure)) =
                                regions.iter().rev().find(|(r, ..)| r.region.contains(x))
                            else {
                                continue;
                            };
                            // A ring about the axis on an (r, z) grid: its
                            // sub-cell's cross-section swept through 2π at
                            // its centre's radius (exact for the ring).
                            let sub_volume = if d.geometry.is_axisymmetric() {
                                2.0 * std::f64::consts::PI * x[0] * sub_volume / grid.spacing[2]
                            } else {
                                sub_volume
                            };
                            let remapped = match &remap {
                                Some(g) if g.replaces(material) => g
                                    .particle(x, sub_volume)
                                    .map_err(|m| FieldError::new("pipeline.remap.file", m))?,
                                _ => None,
                            };
                            let init = remapped.unwrap_or(ParticleInit {
                                position: x,
                                velocity: r.state.velocity,
                                mass: r.state.density * sub_volume,
                                volume: sub_volume,
                                temperature,
                                specific_internal_energy: energy,
                                material,
                                stress: [-pressure, -pressure, -pressure, 0.0, 0.0, 0.0],
                                ..Default::default()
                            });
                            particles
                                .push(&init, &history)
                                .map_err(|e| FieldError::new("initial", e.to_string()))?;
                        }
                    }
                }
            }
        }
    }
    if particles.is_empty() {
        return Err(FieldError::new(
            "initial",
            "no particle lies in any initial region",
        ));
    }
    // Every open face lets particles leave (GridBoundary::Outflow); the
    // ones that let matter in have a reservoir beyond them.
    let boundary = |bc: &BoundaryConfig| match bc {
        BoundaryConfig::Wall => GridBoundary::Fixed,
        BoundaryConfig::Reflective => GridBoundary::Symmetry,
        _ => GridBoundary::Outflow,
    };
    let faces = s.boundaries.faces();
    let mut reservoirs = [None; 6];
    for (k, (face, bc)) in faces.iter().enumerate() {
        let kind = match bc {
            BoundaryConfig::ZeroGradient => ReservoirKind::ZeroGradient,
            BoundaryConfig::OutflowOnly => ReservoirKind::OutflowOnly,
            BoundaryConfig::Fixed(st) => {
                let path = format!("boundaries.{face}");
                let particle_names: Vec<String> = names.iter().map(|n| n.to_string()).collect();
                let name = fixed_face_material(face, st, &particle_names, "particle material")?;
                let id = names
                    .iter()
                    .position(|n| *n == name)
                    .expect("a particle material");
                let model = &models[id];
                let (temperature, energy) = particle_thermodynamics(model, st, &path)?;
                let eos = model.eos().ok_or_else(|| {
                    FieldError::new(&path, format!("`{name}`'s model has no equation of state for the pressure of the particles it brings in"))
                })?;
                let p = eos.pressure(st.density, energy);
                ReservoirKind::Fixed(ReservoirState {
                    material: MaterialId(id as u16),
                    density: st.density,
                    velocity: st.velocity,
                    specific_internal_energy: energy,
                    temperature,
                    stress: [-p, -p, -p, 0.0, 0.0, 0.0],
                })
            }
            _ => continue,
        };
        reservoirs[k] = Some(Reservoir { kind, ppc });
    }
    let options = MpmOptions {
        shape: mpm.shape_function,
        scheme: mpm.scheme,
        cfl: s.cfl,
        gravity: mpm.gravity,
        boundaries: std::array::from_fn(|k| boundary(faces[k].1)),
        mass_cutoff: mpm.mass_cutoff,
        bulk_viscosity: mpm.bulk_viscosity.option(),
        fluid_bulk_viscosity: mpm.fluid_bulk_viscosity,
        anti_locking: mpm.anti_locking,
        reservoirs,
        geometry: d.geometry,
        ..Default::default()
    };
    let material_id = |name: Option<&str>, path: &str| -> Result<_, FieldError> {
        name.map(|n| {
            names
                .iter()
                .position(|m| *m == n)
                .map(|id| MaterialId(id as u16))
                .ok_or_else(|| FieldError::new(path, format!("`{n}` has no constitutive `model`")))
        })
        .transpose()
    };
    let mut particle_gauges = Vec::with_capacity(s.particle_gauges.len());
    for (i, g) in s.particle_gauges.iter().enumerate() {
        let material = material_id(g.material, &format!("outputs.particle_gauges.{i}.material"))?;
        let set = ParticleSet::select(&particles, |x, m| {
            g.region.contains(x) && (material.is_none() || material == Some(m))
        });
        if set.is_empty() {
            let of = g
                .material
                .map_or(String::new(), |m| format!(" of material `{m}`"));
            return Err(FieldError::new(
                format!("outputs.particle_gauges.{i}.region"),
                format!(
                    "particle gauge `{}`: no particle{of} starts inside its region",
                    g.name
                ),
            ));
        }
        particle_gauges.push(set);
    }
    let mut loads = Vec::with_capacity(mpm.surface_loads.len());
    for (i, l) in mpm.surface_loads.iter().enumerate() {
        let path = format!("pipeline.surface_loads.{i}");
        let material = material_id(l.material.as_deref(), &format!("{path}.material"))?;
        let set = ParticleSet::select(&particles, |x, m| {
            l.region.contains(x) && (material.is_none() || material == Some(m))
        });
        if set.is_empty() {
            let of = l
                .material
                .as_ref()
                .map_or(String::new(), |m| format!(" of material `{m}`"));
            return Err(FieldError::new(
                format!("{path}.region"),
                format!(
                    "surface load `{}`: no particle{of} starts inside its region",
                    l.name
                ),
            ));
        }
        let norm = l.normal.iter().map(|c| c * c).sum::<f64>().sqrt();
        let normal = l.normal.map(|c| c / norm);
        // The particle spacing along the normal: l_d = Δx_d / ppc_d.
        let thickness = l.thickness.unwrap_or_else(|| {
            1.0 / (0..3)
                .map(|d| normal[d].abs() * per_axis[d] as f64 / grid.spacing[d])
                .sum::<f64>()
        });
        loads.push(SurfaceLoad {
            set,
            load: l.load,
            normal,
            thickness,
            history: l.history.clone(),
        });
    }
    let heat = heat_conduction(s, &names, &models)?;
    let solver = MpmSolver::new(level, models, particles, options)
        .map_err(|e| FieldError::new("pipeline", e.to_string()))?
        .with_surface_loads(loads)
        .map_err(|e| match e {
            MpmSetupError::SurfaceLoad { index, detail } => FieldError::new(
                format!("pipeline.surface_loads.{index}"),
                format!("surface load `{}`: {detail}", mpm.surface_loads[index].name),
            ),
            other => FieldError::new("pipeline", other.to_string()),
        })?;
    let mut solver = match heat {
        Some(heat) => solver
            .with_heat_conduction(heat)
            .map_err(|e| FieldError::new("materials", e.to_string()))?,
        None => solver,
    };
    solver.set_particle_gauges(particle_gauges);
    Ok(solver)
}

/// The heat-conduction option of the particle materials `names` (with
/// their `models`, in material-id order) from their `thermal` entries: k
/// and c_v per material, k = 0 for a material without one; `None` when
/// no material has one (the solver is then built as without the option).
fn heat_conduction(
    s: &Scene<'_>,
    names: &[&str],
    models: &[MaterialModel],
) -> Result<Option<HeatConduction>, FieldError> {
    let thermal = |name: &str| s.material(name).and_then(|m| m.thermal);
    if names.iter().all(|n| thermal(n).is_none()) {
        return Ok(None);
    }
    let mut heat = HeatConduction::default();
    for (name, model) in names.iter().zip(models) {
        let (k, c) = match thermal(name) {
            Some(t) => {
                thermal_properties(&format!("materials.{name}.thermal"), t, model)?;
                (t.conductivity, t.specific_heat)
            }
            None => (0.0, None),
        };
        heat.conductivity.push(k);
        heat.specific_heat.push(c.map(SpecificHeat::Constant));
    }
    Ok(Some(heat))
}

#[cfg(test)]
mod tests;
