//! The RON scenario schema: plain serde types, validated in
//! [`crate::validate`] before anything is built.

use std::collections::BTreeMap;

use brisance_constitutive::MaterialModel;
pub use brisance_core::Geometry;
use brisance_eos::EosModel;
use brisance_mpm::SetQuantity;
use brisance_plugin::{Installed, PluginEnum, PluginInstance};
use brisance_scene::plugin::{PipelinePlugin, PluginSection};
use serde::{Deserialize, Serialize};

pub use brisance_couple::mpm_pipeline::{BulkViscosityConfig, MpmConfig, SurfaceLoadConfig};
pub use brisance_fdm::pipeline::{FdmConfig, LimiterConfig, ViscosityConfig};
pub use brisance_ice::pipeline::{IceConfig, IceReactionConfig, IceReactionModel};
pub use brisance_scene::{Boundaries, BoundaryConfig, StateConfig};

/// A whole scenario: one RON file.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Scenario {
    /// Name used in outputs and the summary.
    pub name: String,
    /// The grid.
    pub domain: Domain,
    /// Boundary conditions per face (`Outflow` where not given).
    #[serde(default)]
    pub boundaries: Boundaries,
    /// End time and step control.
    pub time: TimeControl,
    /// Materials by name.
    pub materials: BTreeMap<String, MaterialConfig>,
    /// The numerical method(s).
    pub pipeline: Pipeline,
    /// Initial regions; later entries override earlier ones.
    pub initial: Vec<InitialRegion>,
    /// What to write and when.
    #[serde(default)]
    pub outputs: Outputs,
}

/// The Cartesian domain.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Domain {
    /// Low corner, m.
    pub lower: [f64; 3],
    /// High corner, m.
    pub upper: [f64; 3],
    /// Cells per direction (1 in unused directions).
    pub cells: [usize; 3],
    /// Patches per direction.
    #[serde(default = "one_patch")]
    pub patches: [usize; 3],
    /// `Cartesian` (the default) or `Axisymmetric`: a 2D (r, z) grid with
    /// x = r ≥ 0, y = z and one cell along z, whose cells are rings about
    /// the axis x = 0 (docs/physics/axisymmetric.md).
    #[serde(default)]
    pub geometry: Geometry,
}

fn one_patch() -> [usize; 3] {
    [1, 1, 1]
}

/// Time control.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TimeControl {
    /// End time, s.
    pub end: f64,
    /// Courant number (per directional sweep for FDM).
    #[serde(default = "default_cfl")]
    pub cfl: f64,
    /// Stop after this many steps even if `end` is not reached.
    #[serde(default)]
    pub max_steps: Option<u64>,
}

fn default_cfl() -> f64 {
    0.8
}

/// A material: its equation of state, given inline or taken from the
/// material library by name (constitutive and reaction models join here
/// later).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MaterialConfig {
    /// A library material (`configs/materials/<name>.ron`, see `brisance list`).
    #[serde(default)]
    pub library: Option<String>,
    /// The equation of state (filled from the library when `library` is given).
    #[serde(default)]
    pub eos: Option<EosModel>,
    /// The constitutive model, for particle (Mpm) pipelines.
    #[serde(default)]
    pub model: Option<MaterialModel>,
    /// Heat conduction inside the material's particles (`Mpm` and the
    /// solids of `IceMpm`; docs/physics/mpm/heat_conduction.md). Absent:
    /// no conduction.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub thermal: Option<ThermalConfig>,
}

/// The thermal properties of a particle material (`materials.<name>.thermal`).
pub use brisance_scene::ThermalConfig;

impl MaterialConfig {
    /// The equation of state (present once the scenario is loaded).
    pub fn eos(&self) -> Option<&EosModel> {
        self.eos.as_ref()
    }
}

/// The numerical method(s) of the run: a pipeline its crate registered
/// (`brisance_scene::plugin`; the program's are listed by
/// [`crate::plugins::pipeline_registry`]), written under its own name
/// (`Fdm(...)`, `IceMpm(...)`, `Lattice(...)`, …).
#[derive(Debug, Clone, PartialEq)]
pub struct Pipeline(pub PluginSection);

impl PluginEnum for Pipeline {
    type Plugin = PipelinePlugin;
    const NAME: &'static str = "Pipeline";
    const VARIANTS: &'static [&'static str] = brisance_scene::plugin::BUILT_IN;
    const EXPECTING: &'static str = "a pipeline such as `Fdm(...)`";

    fn installed() -> &'static Installed<PipelinePlugin> {
        brisance_scene::plugin::slot()
    }

    /// There are no built-in pipelines: every name is a registration's.
    fn read_builtin<'de, A: serde::de::VariantAccess<'de>>(
        name: &'static str,
        _variant: A,
    ) -> Result<Self, A::Error> {
        Err(Self::unknown(name))
    }

    fn from_plugin(section: PluginInstance<PipelinePlugin>) -> Self {
        Self(PluginSection(section))
    }
}

impl<'de> Deserialize<'de> for Pipeline {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        brisance_plugin::deserialize(d)
    }
}

impl Serialize for Pipeline {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        brisance_plugin::serialize_plugin::<Self, S>(&self.0 .0, s)
    }
}

impl Pipeline {
    /// The section as its own crate's type `T` (`brisance_couple::IceMpmConfig`,
    /// say), for a tool that builds that pipeline's solver by its type
    /// ([`crate::build::build_section`]); `None` for another pipeline.
    pub fn section<T: std::any::Any>(&self) -> Option<&T> {
        self.0.downcast()
    }

    /// The section behind the registration's virtual calls: its limits,
    /// checks, builder and description.
    pub fn spec(&self) -> &dyn brisance_scene::plugin::DynPipeline {
        self.0.section()
    }

    /// The name a scenario writes (`Fdm`, `IceMpm`, …).
    pub fn name(&self) -> &'static str {
        self.0.plugin().info.name
    }
}

/// A geometric region: the shapes every method shares (see
/// [`brisance_grid::Shape`]).
pub use brisance_grid::Shape as Region;

/// One initial region.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct InitialRegion {
    /// Where (cells whose centre lies inside).
    pub region: Region,
    /// Which material (a key of `materials`).
    pub material: String,
    /// Its state.
    pub state: StateConfig,
}

/// Outputs.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct Outputs {
    /// Simulation time between field outputs, s (None: start and end only).
    pub interval: Option<f64>,
    /// Cell fields written to VTK and line-outs.
    pub fields: Vec<String>,
    /// Background-grid node fields (Mpm: `mass`, `momentum_x`, ...,
    /// `velocity_x`, ..., `force_x`, ..., `acceleration_x`, ..., `active`)
    /// written to VTK as point data `vtk/<name>_nodes_<k>.vti`, listed in
    /// `<name>_nodes.pvd`; none by default.
    pub node_fields: Vec<String>,
    /// Whether to write VTK files.
    pub vtk: bool,
    /// How the cell fields' VTK files are laid out (default `Whole`).
    pub vtk_layout: VtkLayout,
    /// Point gauges (sampled every step).
    pub gauges: Vec<Gauge>,
    /// Particle gauges (Mpm): averages over a set of particles chosen by
    /// their initial position, sampled every step.
    pub particle_gauges: Vec<ParticleGauge>,
    /// Line-outs (written at every output time).
    pub lineouts: Vec<Lineout>,
    /// Write a checkpoint every this many steps.
    pub checkpoint_every: Option<u64>,
    /// How checkpoints are laid out (default `Whole`).
    pub checkpoint_layout: CheckpointLayout,
    /// Figures of gauge histories against time, `plots/<name>.png`,
    /// redrawn whenever the gauge CSVs are written (so a run that stops
    /// early still has them up to its last good state).
    pub plots: Vec<Plot>,
}

impl Default for Outputs {
    fn default() -> Self {
        Self {
            interval: None,
            fields: [
                "density",
                "velocity_x",
                "velocity_y",
                "velocity_z",
                "pressure",
                "specific_internal_energy",
                "temperature",
                "sound_speed",
            ]
            .map(String::from)
            .to_vec(),
            node_fields: Vec::new(),
            vtk: true,
            vtk_layout: VtkLayout::Whole,
            gauges: Vec::new(),
            particle_gauges: Vec::new(),
            lineouts: Vec::new(),
            checkpoint_every: None,
            checkpoint_layout: CheckpointLayout::Whole,
            plots: Vec::new(),
        }
    }
}

/// How the cell fields of a field output are laid out in VTK files.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
pub enum VtkLayout {
    /// One `vtk/<name>_<k>.vti` of the whole grid, gathered and written by
    /// rank 0.
    #[default]
    Whole,
    /// One `.vti` piece per patch, `vtk/<name>_<k>/<name>_<k>_<patch>.vti`,
    /// each written by the rank that owns the patch (nothing gathered),
    /// under a `vtk/<name>_<k>.pvti` master that ParaView opens as one
    /// dataset. The files do not depend on the rank count. Grid pipelines
    /// (`Fdm`, `Ice`, the `IceMpm` gas) only.
    Patches,
}

/// How a checkpoint is laid out in files.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
pub enum CheckpointLayout {
    /// One `checkpoints/checkpoint_<step>.bin` of the whole state,
    /// gathered and written by rank 0; a restart may change the patch
    /// split as well as the rank count.
    #[default]
    Whole,
    /// `checkpoints/checkpoint_<step>.bin` with the shared part (written
    /// by rank 0, last) and one file per patch in
    /// `checkpoints/checkpoint_<step>/patch_<p>.bin`, written by the rank
    /// that owns it (nothing gathered but the face accumulators); a
    /// restart keeps the patches and may change the rank count. Grid
    /// pipelines (`Fdm`, `Ice`) only.
    Patches,
}

/// A point gauge: one CSV `gauges/<name>.csv`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Gauge {
    /// File stem.
    pub name: String,
    /// Position, m.
    pub point: [f64; 3],
    /// Fields to record.
    pub fields: Vec<String>,
}

/// A particle gauge: one CSV `particle_gauges/<name>.csv` of set averages
/// over the particles whose *initial* position lies in `region` (and, if
/// given, of `material`), followed wherever they move.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ParticleGauge {
    /// File stem.
    pub name: String,
    /// Where the particles start.
    pub region: Region,
    /// Only particles of this material (a key of `materials`).
    #[serde(default)]
    pub material: Option<String>,
    /// What to record: `MeanVelocity`, `MeanPosition`, `MeanDisplacement`,
    /// `MeanStress`, `MeanPressure`, `MeanVonMisesStress`,
    /// `MeanTemperature`, `MeanSpecificInternalEnergy`, `Mass`.
    pub quantities: Vec<SetQuantity>,
}

/// A figure of gauge columns against time: one PNG `plots/<name>.png`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Plot {
    /// File stem.
    pub name: String,
    /// Title above the figure (the scenario's name when absent).
    #[serde(default)]
    pub title: Option<String>,
    /// Y-axis description with its unit, e.g. `"wall velocity [m/s]"`.
    pub y_label: String,
    /// The curves, each a column of a gauge's CSV.
    pub series: Vec<PlotSeries>,
    /// Horizontal reference lines (an estimate, a measurement) drawn
    /// across the whole time axis, in the unit of the scaled series.
    #[serde(default)]
    pub references: Vec<PlotReference>,
}

/// A horizontal line of a [`Plot`].
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PlotReference {
    /// Legend text.
    pub label: String,
    /// Its value.
    pub value: f64,
}

/// One curve of a [`Plot`].
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PlotSeries {
    /// The gauge whose history is drawn.
    pub from: PlotSource,
    /// Its column: a field of a point gauge (`pressure`), or a column of a
    /// particle gauge (`mean_velocity_x`; see the user guide).
    pub column: String,
    /// Legend text (`<gauge> <column>` when absent).
    #[serde(default)]
    pub label: Option<String>,
    /// Factor applied to the values before drawing (e.g. `1e-9` for GPa).
    #[serde(default = "unit_scale")]
    pub scale: f64,
}

fn unit_scale() -> f64 {
    1.0
}

/// Where a [`PlotSeries`] comes from.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub enum PlotSource {
    /// A point gauge of `outputs.gauges`, by name.
    Gauge(String),
    /// A particle gauge of `outputs.particle_gauges`, by name.
    ParticleGauge(String),
}

/// A line-out between two points.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Lineout {
    /// File stem.
    pub name: String,
    /// Start point, m.
    pub from: [f64; 3],
    /// End point, m.
    pub to: [f64; 3],
    /// Number of samples, at the midpoints of equal segments.
    pub points: usize,
    /// Fields to record (the output fields when empty).
    #[serde(default)]
    pub fields: Vec<String>,
}
