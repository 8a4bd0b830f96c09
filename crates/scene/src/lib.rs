//! What a pipeline crate reads of a scenario, and the trait through which
//! it owns its part of the configuration.
//!
//! A scenario (one RON file) has parts every pipeline shares — the
//! domain, the end time, the materials and their equations of state, the
//! initial regions, the requested cell fields — and one section that
//! belongs to its pipeline (`pipeline: Lattice(...)`). The composer
//! (`brisance_compose`) parses the file, applies `--set`, resolves the
//! material library, and hands the shared parts to the pipeline as a
//! [`Scene`] beside the pipeline's own section, a type of the pipeline's
//! crate that implements [`PipelineSpec`]: the pipeline checks its section
//! against the scene ([`PipelineSpec::validate`]), builds its solver from
//! both ([`PipelineSpec::build`]) and says in a paragraph what it will run
//! ([`PipelineSpec::describe`], for `brisance check`). Its name, summary,
//! RON example and docs page ([`PipelineInfo`]) are what `brisance list`
//! prints. The composer so never names the pipeline's schema or its
//! internals, and the pipeline never sees the RON text.
//!
//! Errors name the offending field by its path in the scenario
//! ([`FieldError`], e.g. `pipeline.materials.hmx.young` or
//! `initial.2.material`); the composer turns the path into the file, line
//! and column it was read from.
//!
//! The crate sits between the model crates and the solvers: it depends on
//! `brisance_core` (the grid geometry), `brisance_grid` (the region shapes),
//! `brisance_eos` (the equations of state) and `brisance_constitutive` (the
//! constitutive models of materials carried by particles), and knows no
//! solver.

use std::fmt;

use brisance_constitutive::MaterialModel;
use brisance_core::Geometry;
use brisance_eos::EosModel;
use brisance_grid::Shape;
use serde::{Deserialize, Serialize};

mod faces;
mod owned;
pub mod plugin;

pub use faces::{fixed_face_material, Boundaries, BoundaryConfig, StateConfig, OPEN_FACES};
pub use owned::OwnedScene;

/// The scenario's domain.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Domain {
    /// Low corner, m.
    pub lower: [f64; 3],
    /// High corner, m.
    pub upper: [f64; 3],
    /// Cells per direction (1 in unused directions).
    pub cells: [usize; 3],
    /// Patches per direction.
    pub patches: [usize; 3],
    /// Cartesian or axisymmetric (r, z).
    pub geometry: Geometry,
}

/// One material of the scenario, by name.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Material<'a> {
    /// The name the scenario gives it (a key of `materials`).
    pub name: &'a str,
    /// Its equation of state, where it has one.
    pub eos: Option<&'a EosModel>,
    /// Its constitutive model, where it has one (the solids a particle
    /// pipeline carries).
    pub model: Option<&'a MaterialModel>,
    /// Heat conduction inside its particles, where it is given.
    pub thermal: Option<&'a ThermalConfig>,
}

/// The thermal properties of a particle material for the heat conduction
/// inside the MPM solids (Fourier's law, seed 000 §2 eq 3):
/// `thermal: (conductivity: 44.5, specific_heat: Some(477.0))`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ThermalConfig {
    /// Thermal conductivity k, W/(m·K), finite and ≥ 0.
    pub conductivity: f64,
    /// Specific heat c_v, J/(kg·K), finite and > 0; `None`: the
    /// constitutive model's own (the `ElasticPlastic` metal's
    /// `specific_heat`), which a conducting material whose model has none
    /// must replace.
    #[serde(default)]
    pub specific_heat: Option<f64>,
}

/// One entry of the scenario's `outputs.particle_gauges`, as far as a
/// particle pipeline selects its particles: the particles that start in
/// `region` (and are of `material`, where given).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ParticleGauge<'a> {
    /// The gauge's name (its file stem).
    pub name: &'a str,
    /// Where its particles start.
    pub region: &'a Shape,
    /// Only particles of this material (a key of `materials`).
    pub material: Option<&'a str>,
}

/// One entry of the scenario's `initial` list (later entries override
/// earlier ones where they overlap).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct InitialRegion<'a> {
    /// Where.
    pub region: &'a Shape,
    /// Which material (a key of `materials`).
    pub material: &'a str,
    /// Its initial state (density, velocity and one of pressure, energy
    /// or temperature).
    pub state: &'a StateConfig,
}

/// The parts of a scenario every pipeline shares, as the composer has
/// loaded them.
#[derive(Debug, Clone, PartialEq)]
pub struct Scene<'a> {
    /// The scenario's name.
    pub name: &'a str,
    /// The domain.
    pub domain: Domain,
    /// End time, s.
    pub end_time: f64,
    /// The Courant number of the time step (`time.cfl`).
    pub cfl: f64,
    /// The six faces' boundary conditions.
    pub boundaries: &'a Boundaries,
    /// The materials, in the scenario's (name) order.
    pub materials: Vec<Material<'a>>,
    /// The initial regions, in the scenario's order.
    pub initial: Vec<InitialRegion<'a>>,
    /// The cell fields the outputs ask for (`outputs.fields`).
    pub cell_fields: &'a [String],
    /// How many line-outs the outputs ask for (`outputs.lineouts`).
    pub line_outs: usize,
    /// The particle gauges the outputs ask for
    /// (`outputs.particle_gauges`), in order.
    pub particle_gauges: Vec<ParticleGauge<'a>>,
    /// Every list of cell fields the outputs name, with its path:
    /// `outputs.fields`, then `outputs.gauges.k.fields` and
    /// `outputs.lineouts.k.fields` in order.
    pub field_lists: Vec<(String, &'a [String])>,
    /// What else the outputs ask for, as `brisance check` describes it.
    pub outputs: OutputsSummary,
}

/// The outputs of a scenario, as far as a pipeline's description names
/// them.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct OutputsSummary {
    /// Simulation time between field outputs, s (None: start and end
    /// only).
    pub interval: Option<f64>,
    /// How many point gauges.
    pub gauges: usize,
    /// Steps between checkpoints (None: none).
    pub checkpoint_every: Option<u64>,
}

impl OutputsSummary {
    /// `interval …, fields […], n gauges, m line-outs, checkpoints every …`
    /// of `scene`, the outputs line of the pipelines' descriptions.
    pub fn describe(scene: &Scene<'_>) -> String {
        let o = scene.outputs;
        format!(
            "interval {:?}, fields [{}], {} gauges, {} line-outs, checkpoints every {:?} steps",
            o.interval,
            scene.cell_fields.join(", "),
            o.gauges,
            scene.line_outs,
            o.checkpoint_every
        )
    }
}

impl<'a> Scene<'a> {
    /// The material called `name`, if the scenario has one.
    pub fn material(&self, name: &str) -> Option<&Material<'a>> {
        self.materials.iter().find(|m| m.name == name)
    }

    /// The first initial region (in the scenario's order) that contains
    /// the point `p`, by its index in [`Self::initial`].
    pub fn region_of(&self, p: [f64; 3]) -> Option<usize> {
        self.initial.iter().position(|r| r.region.contains(p))
    }

    /// The point at which the initial regions are tested for a cell
    /// centred at `x`: `x` on a Cartesian grid, (r, z, 0) on an (r, z)
    /// grid — the half plane through the axis, so a sphere centred on the
    /// axis at (0, z₀, 0) fills the rings of its hemisphere of that plane.
    pub fn region_point(&self, x: [f64; 3]) -> [f64; 3] {
        if self.domain.geometry.is_axisymmetric() {
            [x[0], x[1], 0.0]
        } else {
            x
        }
    }

    /// The initial region whose state a grid cell centred at `x` takes:
    /// the last (later entries override earlier ones) that contains
    /// [`Self::region_point`] of `x`, by its index in [`Self::initial`].
    pub fn cell_region(&self, x: [f64; 3]) -> Option<usize> {
        let p = self.region_point(x);
        self.initial.iter().rposition(|r| r.region.contains(p))
    }
}

/// A problem with one field of the scenario: its path (`pipeline.spacing`,
/// `initial.0.material`) and what is wrong with it.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct FieldError {
    /// The field's path in the scenario.
    pub field: String,
    /// What is wrong, in a sentence.
    pub message: String,
}

impl FieldError {
    /// The problem `message` with the field at `field`.
    pub fn new(field: impl Into<String>, message: impl Into<String>) -> Self {
        Self {
            field: field.into(),
            message: message.into(),
        }
    }
}

impl fmt::Display for FieldError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}: {}", self.field, self.message)
    }
}

impl std::error::Error for FieldError {}

impl From<FieldError> for (String, String) {
    fn from(e: FieldError) -> Self {
        (e.field, e.message)
    }
}

/// What `brisance list` prints of a pipeline.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct PipelineInfo {
    /// The name a scenario writes (`pipeline: Lattice(...)`).
    pub name: &'static str,
    /// One line on what it is, with its seed reference.
    pub summary: &'static str,
    /// A RON example of the pipeline's section.
    pub example: &'static str,
    /// Its docs page, relative to the repository root.
    pub docs: &'static str,
}

/// What the composer's checks of the shared parts need to know about a
/// pipeline: which output fields it writes, its stability limit and its
/// patches' stencil.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PipelineLimits {
    /// Output field names.
    pub fields: &'static [&'static str],
    /// Largest Courant number the scheme is stable at.
    pub max_cfl: f64,
    /// Ghost layers each patch must hold.
    pub ghost: usize,
    /// Background-grid node field names (empty: the pipeline has no node
    /// grid).
    pub node_fields: &'static [&'static str],
    /// Whether its cells are split into patches that can be written as
    /// VTK pieces, one per patch.
    pub patch_pieces: bool,
    /// Whether its state can be checkpointed per patch.
    pub patch_checkpoints: bool,
    /// Whether its solver carries particles that the scenario's
    /// `outputs.particle_gauges` can follow
    /// ([`brisance_core::Solver::sample_particle_gauge`]).
    pub particle_gauges: bool,
    /// Whether a material's `thermal` entry means something to it: heat
    /// conduction inside its particles.
    pub heat_conduction: bool,
}

pub use brisance_core::solver::IntoSolver;

/// A pipeline's section of the scenario (its config schema, a serde type
/// of the pipeline's crate), with what the pipeline does with it.
pub trait PipelineSpec {
    /// Name, summary, example and docs page.
    const INFO: PipelineInfo;
    /// What [`Self::build`] makes.
    type Solver;

    /// What the composer's checks need to know (output fields, Courant
    /// limit, ghost layers) for this section on `geometry`'s grid.
    fn limits(&self, geometry: Geometry) -> PipelineLimits;

    /// Why the pipeline has no form on `geometry`'s grids, if it has
    /// none: the composer refuses the scenario at `domain.geometry` with
    /// this sentence before it checks the grid's shape. None by default.
    fn unsupported(&self, _geometry: Geometry) -> Option<&'static str> {
        None
    }

    /// Checks the section against the scene; the error names the field.
    fn validate(&self, scene: &Scene<'_>) -> Result<(), FieldError>;

    /// Builds the solver (validating first).
    fn build(&self, scene: &Scene<'_>) -> Result<Self::Solver, FieldError>;

    /// One paragraph on what the run will do, for `brisance check`.
    fn describe(&self, scene: &Scene<'_>) -> String;
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Materials `a` and `b` (no EOS), a region of each over `shapes`.
    fn scene(shapes: &[Shape]) -> OwnedScene {
        let mut o = OwnedScene::new(Domain::cartesian([0.0; 3], [1.0; 3], [1; 3]))
            .with_material("a", None)
            .with_material("b", None);
        for (shape, m) in shapes.iter().zip(["a", "b"]) {
            o = o.with_region(shape.clone(), m, StateConfig::at_pressure(1.0, 1.0));
        }
        o
    }

    /// Materials are found by name; a point takes the first region that
    /// holds it, in the scenario's order.
    #[test]
    fn materials_by_name_and_regions_in_order() {
        let shapes = [
            Shape::Box {
                min: [0.0; 3],
                max: [0.5, 1.0, 1.0],
            },
            Shape::Everywhere,
        ];
        let o = scene(&shapes);
        let s = o.scene();
        assert_eq!(s.material("b").map(|m| m.name), Some("b"));
        assert!(s.material("c").is_none());
        assert_eq!(s.region_of([0.25, 0.5, 0.5]), Some(0));
        assert_eq!(s.region_of([0.75, 0.5, 0.5]), Some(1));
        // A grid cell takes the last region that holds it.
        assert_eq!(s.cell_region([0.25, 0.5, 0.5]), Some(1));
        assert_eq!(s.cell_region([0.25, 0.5, 2.0]), Some(1));
    }

    /// On an (r, z) grid a cell's region is tested in the half plane
    /// through the axis.
    #[test]
    fn an_rz_cell_is_tested_at_r_z_0() {
        let shapes = [Shape::Box {
            min: [0.0, 0.0, -0.1],
            max: [1.0, 1.0, 0.1],
        }];
        let mut o = scene(&shapes);
        assert_eq!(o.scene().cell_region([0.5, 0.5, 0.5]), None);
        o.domain.geometry = Geometry::Axisymmetric;
        let s = o.scene();
        assert_eq!(s.region_point([0.5, 0.5, 0.5]), [0.5, 0.5, 0.0]);
        assert_eq!(s.cell_region([0.5, 0.5, 0.5]), Some(0));
    }

    /// A field error prints its path first and converts to the composer's
    /// (path, message) pair.
    #[test]
    fn a_field_error_names_its_path() {
        let e = FieldError::new("pipeline.spacing", "must be > 0");
        assert_eq!(e.to_string(), "pipeline.spacing: must be > 0");
        let (f, m): (String, String) = e.into();
        assert_eq!(
            (f.as_str(), m.as_str()),
            ("pipeline.spacing", "must be > 0")
        );
    }
}
