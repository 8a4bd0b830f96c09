//! Pipelines that live in their own crates, by registration.
//!
//! A pipeline crate implements [`PipelineSpec`] for its section type and
//! hands a [`PipelinePlugin`] to [`PipelineRegistry::register`]: its RON
//! name, a one-line summary, its docs page, a RON example and the function
//! that reads its section from the parameters a config wrote
//! ([`parse_section`]). The composer builds the one registry of the program
//! from every pipeline crate's `register` and [`install`]s it; from then on
//! a config may write `pipeline: Name(...)` for it, the composer's
//! `Pipeline` reads it into a [`PluginSection`], and checks, builds
//! and describes it through [`DynPipeline`], the object-safe face of
//! [`PipelineSpec`] (one virtual call per run, none per step: the solver
//! it builds runs as every other behind `brisance_core::Solver`). The
//! registry, its installed slot and the parameters as RON text are
//! `brisance_plugin`'s, shared with the model families.

use std::any::Any;
use std::fmt;
use std::sync::Arc;

use brisance_core::{Geometry, Solver};
use brisance_plugin::{Installed, Params, PluginInfo, PluginInstance, Registry};

use crate::{FieldError, IntoSolver, PipelineInfo, PipelineLimits, PipelineSpec, Scene};

/// A pipeline's section behind a virtual call: what the composer does with
/// a registered pipeline. Every [`PipelineSpec`] whose solver is a
/// [`Solver`] is one.
pub trait DynPipeline: Send + Sync + fmt::Debug {
    /// [`PipelineSpec::limits`].
    fn limits(&self, geometry: Geometry) -> PipelineLimits;
    /// [`PipelineSpec::unsupported`].
    fn unsupported(&self, geometry: Geometry) -> Option<&'static str>;
    /// [`PipelineSpec::validate`].
    fn validate(&self, scene: &Scene<'_>) -> Result<(), FieldError>;
    /// [`PipelineSpec::build`], the solver boxed.
    fn build(&self, scene: &Scene<'_>) -> Result<Box<dyn Solver>, FieldError>;
    /// [`PipelineSpec::describe`].
    fn describe(&self, scene: &Scene<'_>) -> String;
    /// The section as its own type (for tests and tools that want its
    /// fields).
    fn as_any(&self) -> &dyn Any;
}

impl<P> DynPipeline for P
where
    P: PipelineSpec + Send + Sync + fmt::Debug + 'static,
    P::Solver: IntoSolver,
{
    fn limits(&self, geometry: Geometry) -> PipelineLimits {
        PipelineSpec::limits(self, geometry)
    }
    fn unsupported(&self, geometry: Geometry) -> Option<&'static str> {
        PipelineSpec::unsupported(self, geometry)
    }
    fn validate(&self, scene: &Scene<'_>) -> Result<(), FieldError> {
        PipelineSpec::validate(self, scene)
    }
    fn build(&self, scene: &Scene<'_>) -> Result<Box<dyn Solver>, FieldError> {
        PipelineSpec::build(self, scene).map(IntoSolver::into_solver)
    }
    fn describe(&self, scene: &Scene<'_>) -> String {
        PipelineSpec::describe(self, scene)
    }
    fn as_any(&self) -> &dyn Any {
        self
    }
}

/// Reads a section from the RON text of the parameters a config wrote (a
/// struct such as `(spacing: 2.0e-5, ...)`, or its fields alone): the
/// section and its parameters as canonical text. The message of an error
/// names the field.
pub type ParseFn = brisance_plugin::ParseFn<dyn DynPipeline>;

/// Pipelines built into the composer rather than registered: none. Every
/// pipeline, the program's own included, joins by its crate's `register`.
pub const BUILT_IN: &[&str] = &[];

/// What a pipeline crate registers for its pipeline.
#[derive(Clone, Copy)]
pub struct PipelinePlugin {
    /// Name, summary, RON example and docs page (the section type's
    /// [`PipelineSpec::INFO`]).
    pub info: PipelineInfo,
    /// Reads the section from its parameters.
    pub parse: ParseFn,
}

impl PipelinePlugin {
    /// The registration of the section type `P`: its [`PipelineSpec::INFO`]
    /// and [`parse_section::<P>`](parse_section).
    pub fn of<P>() -> Self
    where
        P: PipelineSpec
            + Send
            + Sync
            + fmt::Debug
            + serde::Serialize
            + serde::de::DeserializeOwned
            + 'static,
        P::Solver: IntoSolver,
    {
        Self {
            info: P::INFO,
            parse: parse_section::<P>,
        }
    }
}

impl fmt::Debug for PipelinePlugin {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("PipelinePlugin")
            .field("name", &self.info.name)
            .field("docs", &self.info.docs)
            .finish_non_exhaustive()
    }
}

impl PluginInfo for PipelinePlugin {
    const FAMILY: &'static str = "pipeline";
    const BUILT_IN: &'static [&'static str] = BUILT_IN;
    type Model = dyn DynPipeline;
    fn name(&self) -> &'static str {
        self.info.name
    }
    fn summary(&self) -> &'static str {
        self.info.summary
    }
    fn docs(&self) -> &'static str {
        self.info.docs
    }
    fn example(&self) -> &'static str {
        self.info.example
    }
    fn parse(&self, params: &str) -> Result<(Arc<dyn DynPipeline>, Params), String> {
        (self.parse)(params)
    }
}

/// The registered pipelines of one program, in registration order;
/// [`Registry::register`] refuses a built-in name or a name registered
/// twice.
pub type PipelineRegistry = Registry<PipelinePlugin>;

static INSTALLED: Installed<PipelinePlugin> = Installed::new();

/// Makes `registry` the program's pipeline registry, the one the
/// composer's `Pipeline` resolves names through. The first call
/// wins; a later one gives its registry back.
pub fn install(registry: PipelineRegistry) -> Result<(), PipelineRegistry> {
    INSTALLED.install(registry)
}

/// The installed slot, for the composer's `Pipeline` serde.
pub fn slot() -> &'static Installed<PipelinePlugin> {
    &INSTALLED
}

/// The section type `T` read from the RON text of its parameters: the
/// usual [`ParseFn`] of a pipeline crate (see [`PipelinePlugin::of`]).
/// The text may be the struct `(a: 1.0, ...)` or its fields alone; a parse
/// error carries serde's message, which names the field.
pub fn parse_section<T>(params: &str) -> Result<(Arc<dyn DynPipeline>, Params), String>
where
    T: DynPipeline + serde::Serialize + serde::de::DeserializeOwned + 'static,
{
    let (section, params) = brisance_plugin::parse_params::<T>(params)?;
    Ok((Arc::new(section), params))
}

/// A registered pipeline's section as the composer's `Pipeline` holds
/// it: the registration, the parameters as canonical RON text (so that it
/// serializes back and compares by value), and the section.
#[derive(Clone, PartialEq)]
pub struct PluginSection(pub PluginInstance<PipelinePlugin>);

impl PluginSection {
    /// The registration.
    pub fn plugin(&self) -> &'static PipelinePlugin {
        self.0.plugin()
    }

    /// The section, behind [`DynPipeline`].
    pub fn section(&self) -> &dyn DynPipeline {
        &**self.0.model()
    }

    /// The section as its own type `T`, if it is one.
    pub fn downcast<T: 'static>(&self) -> Option<&T> {
        self.section().as_any().downcast_ref()
    }
}

impl fmt::Debug for PluginSection {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        fmt::Debug::fmt(&self.0, f)
    }
}
