//! The `Ice` pipeline's section of a scenario (`pipeline: Ice(...)`): the
//! multi-material, cell-centred ICE method of seed 000 §2, §3.1 and §3.3,
//! its schema, its checks against the shared parts of the scenario, its
//! builder and its description ([`brisance_scene::PipelineSpec`]).
//!
//! `materials` lists the scenario materials (each with an EOS) that live in
//! every cell, in the solver's order: output fields `volume_fraction_k`,
//! `density_k`, `temperature_k`, `velocity_x_k` number them from 1. Each
//! initial region names one of them; a cell takes the state of the last
//! region containing its centre, with that material at volume fraction
//! 1 − (N − 1)·10⁻⁶ and every other material as a trace of volume fraction
//! 10⁻⁶ at the region's density, velocity and pressure (the rule of the
//! crate's two-material Sod tube, [`crate::cases::sod_two`]). The
//! region's pressure is found from its state with its material's EOS. A
//! trace material that has no state of positive temperature at the
//! region's density and pressure (JWL++ products at the density of
//! unreacted explosive and 1 atm) takes its own density at the region's
//! pressure and temperature instead, and where it has none at that
//! temperature either (a metal trace in a booster's products at 10 GPa
//! and 19 000 K, whose Mie–Grüneisen thermal pressure alone exceeds
//! 10 GPa) its density at the region's pressure and 300 K, as the IceMpm
//! pipeline's traces do: a trace's temperature carries no mass.
//!
//! `reactions` lists the reactions of step 4 (seed 000 eq 1), each
//! `(reactant: "...", product: "...", model: JwlPlusPlus(g: ..., b: ...))`
//! or `model: Deflagration(a: ..., n: ..., ignition_temperature: ...)` (the
//! surface burn D = A pⁿ of seed 000 eqs 38–39, on the surface the solver
//! finds after each step 2) or `model: Arrhenius(pre_exponential: ...,
//! activation_energy: ...)` (the surface pyrolysis ṁ'' = Ω A exp(−Eₐ/(R T))
//! of seed 003 §2.4, on the same surface at its temperature) between two of
//! `materials`;
//! `heat_of_reaction` (J/kg) may be left out
//! when the reactant is `Murnaghan` and the product `JwlCTerm` with the same
//! ρ₀, and is then the JWL++ detonation energy of the products
//! (`brisance_reaction::jwlpp::detonation_energy`).
//!
//! `transport` gives materials a Newtonian viscosity and a thermal
//! conductivity (seed 000 eqs 2–3, docs/physics/ice/diffusion.md), keyed by
//! material: `transport: {"air": (viscosity: 1.8e-5, thermal_conductivity:
//! 0.026)}`; a material left out, or a field left out, is 0 (no pass).
//!
//! Faces: `Outflow` and `OutflowOnly` → zero-gradient outflow that lets
//! nothing in (`IceBoundary::Outflow`, the face velocity held from
//! pointing inwards), `ZeroGradient` → zero gradient both ways
//! (`IceBoundary::ZeroGradient`), `Fixed(state)` → ghosts holding the
//! state (`IceBoundary::FixedState`, an inflow reservoir; the state is
//! made as an initial region's, of its `material`, which must be given
//! when the pipeline has several), `Reflective` → symmetry plane (slip
//! wall), `Wall` → a fixed wall of velocity 0, `Periodic` → periodic.

use std::sync::Arc;

use brisance_core::{Eos, Geometry};
use brisance_eos::EosModel;
use brisance_grid::comm::Communicator;
use brisance_grid::Level;
use brisance_plugin::{Installed, PluginEnum};
use brisance_reaction::plugin::{PluginReaction, ReactionPlugin};
use brisance_reaction::Arrhenius;
use brisance_scene::{
    fixed_face_material, BoundaryConfig, FieldError, PipelineInfo, PipelineLimits, PipelineSpec,
    Scene, StateConfig,
};
use serde::{Deserialize, Serialize};

use crate::{
    Advection, CellState, Deflagration, ExchangeCoefficients, IceBoundary, IceOptions, IceRate,
    IceReaction, IceSolver, JwlPlusPlus, MaterialState, MaterialTransport, PressureSolve,
    SolidExchange, GHOST, MAX_MATERIALS,
};

/// A problem with a field: its path and what is wrong.
type Problem = (String, String);

/// Volume fraction of a material in cells where it is absent.
pub const TRACE_FRACTION: f64 = 1e-6;

/// The faces the Ice pipeline takes.
const ICE_FACES: &[&str] = &[
    "Outflow",
    "ZeroGradient",
    "OutflowOnly",
    "Fixed",
    "Reflective",
    "Wall",
    "Periodic",
];

/// Options of the Ice pipeline.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct IceConfig {
    /// The materials (keys of `materials`, each with an EOS), in order.
    pub materials: Vec<String>,
    /// Courant number in (0, 1] (default 0.4, the solver's default; the
    /// scenario's `time.cfl` is not used by this pipeline).
    #[serde(default = "default_cfl")]
    pub cfl: f64,
    /// Advection scheme: `VanLeer` (default) or `DonorCell`.
    #[serde(default)]
    pub advection: Advection,
    /// Momentum exchange coefficient K between every pair of materials,
    /// kg/(m³·s) (default 10¹⁵, the seed's practice; seed 000 eq 29).
    #[serde(default = "default_exchange")]
    pub momentum_exchange: f64,
    /// Heat exchange coefficient H between every pair of materials,
    /// W/(m³·K) (default 0; seed 000 eq 30).
    #[serde(default)]
    pub heat_exchange: f64,
    /// Conserve total energy (default true; see docs/physics/ice/steps.md).
    #[serde(default = "default_true")]
    pub conserve_total_energy: bool,
    /// Reactions between the materials (step 4; default none).
    #[serde(default)]
    pub reactions: Vec<IceReactionConfig>,
    /// Step 2 at fixed specific internal energies instead of along the
    /// isotherms (default false; see docs/physics/ice/water_air.md: needed
    /// for stiffened gases, about a third more per step).
    #[serde(default)]
    pub fixed_energy_equilibration: bool,
    /// Viscosity (Pa·s) and thermal conductivity (W/(m·K)) per material,
    /// keyed by material name (default none: all 0; seed 000 eqs 2–3,
    /// docs/physics/ice/diffusion.md).
    #[serde(default)]
    pub transport: std::collections::BTreeMap<String, MaterialTransport>,
    /// Pressure of steps 3 and 5: `Explicit` (default; Δt at the
    /// sound-speed CFL) or `Implicit(tolerance: 1e-10, max_iterations: 20,
    /// retries: 4)` (every field optional; Δt at the material-velocity CFL,
    /// a failed step retried as two half steps `retries` deep; see
    /// docs/physics/ice/implicit_pressure.md).
    #[serde(default)]
    pub pressure: PressureSolve,
    /// ν* in [0, 1] of the explicit step 3 (default 0: eq 19 as printed,
    /// bit-identical to a text without it): with ν* above `cfl` eq 19's
    /// pressure term is taken over a Courant-ν* step, so that its damping
    /// of shocks does not fade with Δt; 0.8 runs the 1D QM-100 column at
    /// CJ at every h (docs/physics/reaction/jwlpp.md, "Weak detonations at
    /// coarse h"). Ignored with the implicit pressure.
    #[serde(default)]
    pub face_pressure_courant: f64,
    /// Largest time step, s (> 0; default none). The implicit pressure's
    /// step follows the material velocities and is unbounded for a state
    /// at rest; this bounds it (Uintah's `max_delt`).
    #[serde(default)]
    pub max_dt: Option<f64>,
    /// The momentum exchange with the solids carried by particles in the
    /// cells of their surface (the IceMpm pipeline only): `Isotropic`
    /// (default, seed 000 eq 29 as printed) or `Slip` (eq 29 across the
    /// surface, the fluids free along it; docs/physics/couple/ice_mpm.md,
    /// "Slip exchange").
    #[serde(default)]
    pub solid_exchange: SolidExchange,
}

/// One reaction of the Ice pipeline.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct IceReactionConfig {
    /// The reactant (one of `pipeline.materials`).
    pub reactant: String,
    /// The product (one of `pipeline.materials`).
    pub product: String,
    /// The rate law.
    pub model: IceReactionModel,
    /// Chemical energy released per kilogram burnt, J/kg (default: the
    /// JWL++ detonation energy of a `Murnaghan` → `JwlCTerm` pair).
    #[serde(default)]
    pub heat_of_reaction: Option<f64>,
}

/// The reaction models the Ice pipeline can name: the built-in ones, and
/// any model a plugin crate registered (`brisance_reaction::plugin`),
/// which a config writes under its registered name.
#[derive(Debug, Clone, PartialEq)]
pub enum IceReactionModel {
    /// JWL++ (seed 000 §4.1.1 eqs 35–37).
    JwlPlusPlus(JwlPlusPlus),
    /// The surface burn D = A pⁿ of seed 000 §4.1.2 (eqs 38–39).
    Deflagration(Deflagration),
    /// The Arrhenius surface pyrolysis of seed 003 (§2.4, §3.1–3.2), the
    /// lattice's regression law, on the reactant surface the ICE finds.
    Arrhenius(Arrhenius),
    /// A model from a plugin crate (`ThermalDecomposition(...)`), never
    /// written as `Plugin`.
    Plugin(PluginReaction),
}

impl IceReactionModel {
    /// The config names of the built-in variants.
    pub const VARIANTS: &'static [&'static str] = &["JwlPlusPlus", "Deflagration", "Arrhenius"];

    /// The config name of this model.
    pub fn variant(&self) -> &'static str {
        match self {
            Self::JwlPlusPlus(_) => "JwlPlusPlus",
            Self::Deflagration(_) => "Deflagration",
            Self::Arrhenius(_) => "Arrhenius",
            Self::Plugin(m) => m.plugin().name,
        }
    }

    /// Every name a config may write: the built-in variants, then the
    /// installed plugins.
    pub fn names() -> Vec<&'static str> {
        let mut names = Self::VARIANTS.to_vec();
        names.extend(brisance_reaction::plugin::plugin_names());
        names
    }

    /// The solver's rate law, checked; the message names the bad field.
    fn rate(&self) -> Result<IceRate, String> {
        match self {
            Self::JwlPlusPlus(m) => m.validate().map(|_| (*m).into()).map_err(|e| e.to_string()),
            Self::Deflagration(m) => m.validate().map(|_| (*m).into()).map_err(|e| e.to_string()),
            Self::Arrhenius(m) => m.validate("Arrhenius").map(|_| (*m).into()),
            Self::Plugin(m) => Ok(IceRate::Model(Arc::clone(m.model()))),
        }
    }
}

impl Serialize for IceReactionModel {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        const NAME: &str = "IceReactionModel";
        match self {
            Self::JwlPlusPlus(m) => s.serialize_newtype_variant(NAME, 0, "JwlPlusPlus", m),
            Self::Deflagration(m) => s.serialize_newtype_variant(NAME, 1, "Deflagration", m),
            Self::Arrhenius(m) => s.serialize_newtype_variant(NAME, 2, "Arrhenius", m),
            Self::Plugin(m) => brisance_plugin::serialize_plugin::<Self, S>(m, s),
        }
    }
}

impl PluginEnum for IceReactionModel {
    type Plugin = ReactionPlugin;
    const NAME: &'static str = "IceReactionModel";
    const VARIANTS: &'static [&'static str] = Self::VARIANTS;
    const EXPECTING: &'static str = "a reaction model such as `JwlPlusPlus(...)`";

    fn installed() -> &'static Installed<ReactionPlugin> {
        brisance_reaction::plugin::slot()
    }

    fn read_builtin<'de, A: serde::de::VariantAccess<'de>>(
        name: &'static str,
        variant: A,
    ) -> Result<Self, A::Error> {
        match name {
            "JwlPlusPlus" => variant.newtype_variant().map(Self::JwlPlusPlus),
            "Deflagration" => variant.newtype_variant().map(Self::Deflagration),
            "Arrhenius" => variant.newtype_variant().map(Self::Arrhenius),
            _ => Err(Self::unknown(name)),
        }
    }

    fn from_plugin(model: PluginReaction) -> Self {
        Self::Plugin(model)
    }

    /// The names this schema takes: the built-in reactions the ICE runs
    /// (not every built-in reaction model), then the plugins.
    fn unknown<E: serde::de::Error>(name: &str) -> E {
        let names: Vec<String> = Self::names().iter().map(|n| format!("`{n}`")).collect();
        E::custom(format!(
            "unknown reaction model `{name}`, expected one of {}",
            names.join(", ")
        ))
    }
}

impl<'de> Deserialize<'de> for IceReactionModel {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        brisance_plugin::deserialize(d)
    }
}

/// The solver's reactions of `cfg`, checked; errors carry the field path.
fn reactions(s: &Scene<'_>, cfg: &IceConfig) -> Result<Vec<IceReaction>, Problem> {
    reactions_of(cfg, &material_eos(s, cfg)?)
}

/// The solver's reactions of `cfg` with `eos` the EOS of each of its
/// materials ([`material_eos`]), checked.
fn reactions_of(cfg: &IceConfig, eos: &[EosModel]) -> Result<Vec<IceReaction>, Problem> {
    let mut out: Vec<IceReaction> = Vec::new();
    for (k, r) in cfg.reactions.iter().enumerate() {
        let path = |f: &str| format!("pipeline.reactions.{k}.{f}");
        let index = |f: &str, name: &str| {
            cfg.materials.iter().position(|m| m == name).ok_or_else(|| {
                (
                    path(f),
                    format!(
                        "`{name}` is not in pipeline.materials ({})",
                        cfg.materials.join(", ")
                    ),
                )
            })
        };
        let (a, b) = (
            index("reactant", &r.reactant)?,
            index("product", &r.product)?,
        );
        if a == b {
            return Err((path("product"), "the product is the reactant".into()));
        }
        if out.iter().any(|o| o.reactant == a) {
            return Err((
                path("reactant"),
                format!(
                    "`{}` is already the reactant of another reaction",
                    r.reactant
                ),
            ));
        }
        let rate = r.model.rate().map_err(|e| (path("model"), e))?;
        let heat = match r.heat_of_reaction {
            Some(q) => {
                if !(q >= 0.0 && q.is_finite()) {
                    return Err((path("heat_of_reaction"), format!("{q} must be finite and ≥ 0")));
                }
                q
            }
            None => match (&eos[a], &eos[b]) {
                (EosModel::Murnaghan(m), EosModel::JwlCTerm(j)) => {
                    brisance_reaction_energy(m, j).map_err(|e| (path("heat_of_reaction"), e))?
                }
                _ => {
                    return Err((
                        path("heat_of_reaction"),
                        "give heat_of_reaction (J/kg): it has a default only for a Murnaghan reactant and JwlCTerm products".into(),
                    ))
                }
            },
        };
        out.push(IceReaction {
            reactant: a,
            product: b,
            rate,
            heat_of_reaction: heat,
        });
    }
    Ok(out)
}

/// JWL++ detonation energy of a Murnaghan → JwlCTerm pair, J/kg.
fn brisance_reaction_energy(
    m: &brisance_eos::Murnaghan,
    j: &brisance_eos::JwlCTerm,
) -> Result<f64, String> {
    crate::detonation_energy(m, j)
}

fn default_cfl() -> f64 {
    IceOptions::default().cfl
}
fn default_exchange() -> f64 {
    1e15
}
fn default_true() -> bool {
    true
}

/// Every output field name the pipeline can have (mixture fields, then
/// per material for up to [`MAX_MATERIALS`] materials); [`PipelineSpec::validate`]
/// rejects per-material fields beyond the configured count.
pub const FIELDS: [&str; 8 + 4 * MAX_MATERIALS] = [
    "density",
    "velocity_x",
    "velocity_y",
    "velocity_z",
    "pressure",
    "specific_internal_energy",
    "temperature",
    "sound_speed",
    "volume_fraction_1",
    "density_1",
    "temperature_1",
    "velocity_x_1",
    "volume_fraction_2",
    "density_2",
    "temperature_2",
    "velocity_x_2",
    "volume_fraction_3",
    "density_3",
    "temperature_3",
    "velocity_x_3",
    "volume_fraction_4",
    "density_4",
    "temperature_4",
    "velocity_x_4",
    "volume_fraction_5",
    "density_5",
    "temperature_5",
    "velocity_x_5",
    "volume_fraction_6",
    "density_6",
    "temperature_6",
    "velocity_x_6",
    "volume_fraction_7",
    "density_7",
    "temperature_7",
    "velocity_x_7",
    "volume_fraction_8",
    "density_8",
    "temperature_8",
    "velocity_x_8",
];

/// The EOS of each configured material, in order.
fn material_eos(s: &Scene<'_>, cfg: &IceConfig) -> Result<Vec<EosModel>, Problem> {
    cfg.materials
        .iter()
        .enumerate()
        .map(|(k, name)| match s.material(name) {
            None => Err((
                format!("pipeline.materials.{k}"),
                format!(
                    "`{name}` is not a scenario material (known: {})",
                    s.materials
                        .iter()
                        .map(|m| format!("`{}`", m.name))
                        .collect::<Vec<_>>()
                        .join(", ")
                ),
            )),
            Some(m) => m.eos.cloned().ok_or_else(|| {
                (
                    format!("materials.{name}.eos"),
                    format!("the Ice pipeline needs an EOS for `{name}`"),
                )
            }),
        })
        .collect()
}

/// The checks of the Ice pipeline run alone (not as the fluid side of
/// IceMpm): no solid carried by particles, so no slip exchange.
fn check_alone(cfg: &IceConfig) -> Result<(), Problem> {
    if cfg.solid_exchange != SolidExchange::Isotropic {
        return Err((
            "pipeline.solid_exchange".into(),
            "the slip exchange acts between the fluids and solids carried by particles; \
             the Ice pipeline has none (use IceMpm, or leave the field out)"
                .into(),
        ));
    }
    Ok(())
}

/// The checks of the fluids' section, alone or as the fluid side of
/// IceMpm (with the solids appended to `materials`).
fn check_fluids(s: &Scene<'_>, cfg: &IceConfig) -> Result<(), Problem> {
    checked_fluids(s, cfg).map(|_| ())
}

/// [`check_fluids`], returning what the checks found on the way: the EOS
/// of each material and the reactions, which the builder takes.
fn checked_fluids(
    s: &Scene<'_>,
    cfg: &IceConfig,
) -> Result<(Vec<EosModel>, Vec<IceReaction>), Problem> {
    let n = cfg.materials.len();
    if n == 0 || n > MAX_MATERIALS {
        return Err((
            "pipeline.materials".into(),
            format!("{n} materials given; the Ice pipeline takes 1 to {MAX_MATERIALS}"),
        ));
    }
    for (k, name) in cfg.materials.iter().enumerate() {
        if cfg.materials[..k].contains(name) {
            return Err((
                format!("pipeline.materials.{k}"),
                format!("`{name}` is listed twice"),
            ));
        }
    }
    let eos = material_eos(s, cfg)?;
    let reactions = reactions_of(cfg, &eos)?;
    if !(cfg.cfl > 0.0 && cfg.cfl <= 1.0) {
        return Err((
            "pipeline.cfl".into(),
            format!("cfl = {} must lie in (0, 1]", cfg.cfl),
        ));
    }
    if !(cfg.face_pressure_courant >= 0.0 && cfg.face_pressure_courant <= 1.0) {
        return Err((
            "pipeline.face_pressure_courant".into(),
            format!(
                "face_pressure_courant = {} must lie in [0, 1]",
                cfg.face_pressure_courant
            ),
        ));
    }
    if let Some(v) = cfg.max_dt {
        if !(v > 0.0 && v.is_finite()) {
            return Err((
                "pipeline.max_dt".into(),
                format!("max_dt = {v} must be a finite time > 0 s"),
            ));
        }
    }
    for (path, v) in [
        ("pipeline.momentum_exchange", cfg.momentum_exchange),
        ("pipeline.heat_exchange", cfg.heat_exchange),
    ] {
        if !(v >= 0.0 && v.is_finite()) {
            return Err((path.into(), format!("{v} must be finite and ≥ 0")));
        }
    }
    for (name, t) in &cfg.transport {
        if !cfg.materials.contains(name) {
            return Err((
                format!("pipeline.transport.{name}"),
                format!(
                    "`{name}` is not in pipeline.materials ({})",
                    cfg.materials.join(", ")
                ),
            ));
        }
        for (field, v) in [
            ("viscosity", t.viscosity),
            ("thermal_conductivity", t.thermal_conductivity),
        ] {
            if !(v >= 0.0 && v.is_finite()) {
                return Err((
                    format!("pipeline.transport.{name}.{field}"),
                    format!("{v} must be finite and ≥ 0"),
                ));
            }
        }
    }
    if let PressureSolve::Implicit(p) = cfg.pressure {
        p.validate().map_err(|e| {
            let field = ["max_iterations", "retries"]
                .into_iter()
                .find(|f| e.contains(&format!("`{f}`")))
                .unwrap_or("tolerance");
            (format!("pipeline.pressure.{field}"), e)
        })?;
    }
    s.boundaries.check_faces("Ice", ICE_FACES, |_| "")?;
    for (face, bc) in s.boundaries.faces() {
        if let BoundaryConfig::Fixed(state) = bc {
            fixed_face_material(face, state, &cfg.materials, "material")?;
        }
    }
    for (i, r) in s.initial.iter().enumerate() {
        if !cfg.materials.iter().any(|m| m == r.material) {
            return Err((
                format!("initial.{i}.material"),
                format!(
                    "`{}` is not in pipeline.materials ({})",
                    r.material,
                    cfg.materials
                        .iter()
                        .map(|m| format!("`{m}`"))
                        .collect::<Vec<_>>()
                        .join(", ")
                ),
            ));
        }
    }
    // Per-material fields must name a configured material.
    for (path, fields) in &s.field_lists {
        for (j, f) in fields.iter().enumerate() {
            if let Some(k) = FIELDS.iter().position(|x| x == f) {
                if k >= 8 + 4 * n {
                    return Err((
                        format!("{path}.{j}"),
                        format!("`{f}` names a material beyond the {n} of pipeline.materials"),
                    ));
                }
            }
        }
    }
    Ok((eos, reactions))
}

/// Builds the solver, its patches shared among `ranks` from the start;
/// `particle_materials` as [`IceConfig::build_on`]; with any, every trace
/// material takes its
/// own density at the region's pressure and temperature, or at 300 K where
/// it has none at the region's temperature (the IceMpm pipeline, whose
/// solid and gases must not trace each other's density), else the rule of
/// the module doc.
fn build_with_traces(
    s: &Scene<'_>,
    cfg: &IceConfig,
    particle_materials: usize,
    ranks: Arc<dyn Communicator>,
) -> Result<IceSolver<EosModel>, Problem> {
    let own_density = particle_materials > 0;
    let (eos, reactions) = checked_fluids(s, cfg)?;
    let n = eos.len();
    // The last `particle_materials` materials are carried by particles,
    // which carry their own temperature.
    let carried = |m: usize| m + particle_materials >= n;
    // Whether a region gave such a material a temperature its cells'
    // (ρ, p) do not carry (IceSolver::start_temperatures_on_particles).
    let carried_own_temperature = std::sync::atomic::AtomicBool::new(false);
    let d = &s.domain;
    let level = Level::new(d.lower, d.upper, d.cells, d.patches, GHOST)
        .map_err(|e| ("domain.patches".to_string(), e.to_string()))?;
    if ranks.size() > 1 {
        brisance_grid::comm::patch_owners(level.patches.len(), ranks.size())
            .map_err(|e| ("domain.patches".to_string(), e))?;
    }
    // The cell state of material m with state `state` (`path` for the
    // errors): the rule of the module doc, that of every initial region
    // and of the ghosts of a `Fixed` face.
    let cell_state = |path: &str, m: usize, state: &StateConfig| {
        let p = RegionState {
            density: state.density,
            velocity: state.velocity,
            pressure: state
                .pressure_in(&eos[m])
                .map_err(|e| (path.to_string(), e))?,
        };
        let trace = TRACE_FRACTION;
        let mut t_region = eos[m].temperature(
            p.density,
            eos[m]
                .specific_internal_energy(p.density, p.pressure)
                .map_err(|e| (path.to_string(), e.to_string()))?,
        );
        // The cells keep a pressure, not an energy: a temperature the
        // material's (ρ, p) cannot carry would be lost without a word.
        // A material carried by particles keeps its temperature on them
        // (their cells take it from them in step 1), so it may start at
        // any, and the traces beside it take it.
        if let (None, None, Some(t)) = (
            state.pressure,
            state.specific_internal_energy,
            state.temperature,
        ) {
            let carries = (t_region - t).abs() <= 1e-6 * t.abs().max(1.0);
            if carried(m) && !carries {
                t_region = t;
                carried_own_temperature.store(true, std::sync::atomic::Ordering::Relaxed);
            } else if !carries {
                return Err((
                    format!("{path}.temperature"),
                    format!(
                        "`{}` cannot start at {t} K in the Ice pipeline: its cells keep a \
                         pressure, and at density {} its equation of state gives that \
                         pressure the temperature {t_region} K (a pressure that does not \
                         depend on the energy, as a Murnaghan reactant's, leaves the \
                         temperature at its reference); give that temperature or a pressure",
                        cfg.materials[m], p.density
                    ),
                ));
            }
        }
        let materials = (0..n)
            .map(|k| {
                let density = if k == m {
                    p.density
                } else if own_density {
                    // At the region's temperature, else (a solid trace
                    // in hot products) at room temperature.
                    eos[k]
                        .density(p.pressure, t_region)
                        .or_else(|_| eos[k].density(p.pressure, 300.0))
                        .map_err(|e| {
                            (
                                path.to_string(),
                                format!("trace of `{}`: {e}", cfg.materials[k]),
                            )
                        })?
                } else {
                    trace_density(&eos[k], p.density, p.pressure, t_region).map_err(|e| {
                        (
                            path.to_string(),
                            format!("trace of `{}`: {e}", cfg.materials[k]),
                        )
                    })?
                };
                Ok(MaterialState {
                    volume_fraction: if k == m {
                        1.0 - (n - 1) as f64 * trace
                    } else {
                        trace
                    },
                    density,
                    velocity: p.velocity,
                })
            })
            .collect::<Result<Vec<_>, Problem>>()?;
        Ok::<_, Problem>(CellState {
            pressure: p.pressure,
            materials,
        })
    };
    let material_index = |name: &str| {
        cfg.materials
            .iter()
            .position(|x| x == name)
            .expect("checked by validate")
    };
    let mut boundaries: [IceBoundary; 6] = std::array::from_fn(|_| IceBoundary::Outflow);
    for (k, (face, bc)) in s.boundaries.faces().into_iter().enumerate() {
        boundaries[k] = match bc {
            BoundaryConfig::Outflow | BoundaryConfig::OutflowOnly => IceBoundary::Outflow,
            BoundaryConfig::ZeroGradient => IceBoundary::ZeroGradient,
            BoundaryConfig::Reflective => IceBoundary::Symmetry,
            BoundaryConfig::Wall => IceBoundary::FixedVelocity([0.0; 3]),
            BoundaryConfig::Periodic => IceBoundary::Periodic,
            BoundaryConfig::Fixed(state) => {
                let m = fixed_face_material(face, state, &cfg.materials, "material")?;
                IceBoundary::FixedState(cell_state(
                    &format!("boundaries.{face}"),
                    material_index(m),
                    state,
                )?)
            }
        };
    }
    // One cell state per region.
    let states = s
        .initial
        .iter()
        .enumerate()
        .map(|(i, r)| {
            cell_state(
                &format!("initial.{i}.state"),
                material_index(r.material),
                r.state,
            )
        })
        .collect::<Result<Vec<_>, Problem>>()?;
    // Every cell must be covered; on an (r, z) grid a region is tested at
    // the point (r, z, 0) of the half plane through the axis.
    level
        .first_uncovered_cell(&*ranks, |x| s.cell_region(x).is_some())
        .map_err(|e| ("initial".to_string(), e))?;
    let init = |x: [f64; 3]| {
        let idx = s.cell_region(x).unwrap_or(0);
        states[idx].clone()
    };
    let options = IceOptions {
        cfl: cfg.cfl,
        advection: cfg.advection,
        conserve_total_energy: cfg.conserve_total_energy,
        fixed_energy_equilibration: cfg.fixed_energy_equilibration,
        pressure: cfg.pressure,
        geometry: d.geometry,
        face_pressure_courant: cfg.face_pressure_courant,
        max_dt: cfg.max_dt.unwrap_or(f64::INFINITY),
        solid_exchange: cfg.solid_exchange,
        ..Default::default()
    };
    let exchange = ExchangeCoefficients::uniform(n, cfg.momentum_exchange, cfg.heat_exchange);
    let mut solver = IceSolver::new_on(ranks, eos, level, boundaries, exchange, options, init)
        .map_err(|e| ("pipeline".to_string(), e.to_string()))?;
    solver
        .set_reactions(reactions)
        .map_err(|e| ("pipeline.reactions".to_string(), e.to_string()))?;
    solver.set_start_temperatures_on_particles(
        carried_own_temperature.load(std::sync::atomic::Ordering::Relaxed),
    );
    if !cfg.transport.is_empty() {
        let transport = cfg
            .materials
            .iter()
            .map(|m| cfg.transport.get(m).copied().unwrap_or_default())
            .collect();
        solver
            .set_transport(transport)
            .map_err(|e| ("pipeline.transport".to_string(), e.to_string()))?;
    }
    Ok(solver)
}

/// An initial region's or a fixed face's state with its pressure.
struct RegionState {
    density: f64,
    velocity: [f64; 3],
    pressure: f64,
}

/// Density of a trace material in a region of density `rho`, pressure `p`
/// and temperature `t`: the region's density when the material has a state
/// of positive temperature there, else its own density at (p, t), else
/// at (p, 300 K).
fn trace_density(eos: &EosModel, rho: f64, p: f64, t: f64) -> Result<f64, String> {
    if let Ok(e) = eos.specific_internal_energy(rho, p) {
        let temp = eos.temperature(rho, e);
        if temp > 0.0 && temp.is_finite() {
            return Ok(rho);
        }
    }
    eos.density(p, t)
        .or_else(|_| eos.density(p, 300.0))
        .map_err(|e| e.to_string())
}

/// One paragraph for `check`.
fn description(s: &Scene<'_>, cfg: &IceConfig) -> String {
    let d = &s.domain;
    let eos = material_eos(s, cfg).unwrap_or_default();
    format!(
        "scenario `{}`: Ice pipeline (multi-material ICE, seed 000 §3.3), {} x {} x {} cells, \
         {:?} advection, cfl {}, K {} kg/(m³·s), H {} W/(m³·K), total-energy closure {}, \
         pressure {:?}\n  \
         materials: {}\n  time: to {} s",
        s.name,
        d.cells[0],
        d.cells[1],
        d.cells[2],
        cfg.advection,
        cfg.cfl,
        cfg.momentum_exchange,
        cfg.heat_exchange,
        cfg.conserve_total_energy,
        cfg.pressure,
        cfg.materials
            .iter()
            .zip(eos.iter().map(|e| e.name()).chain(std::iter::repeat("?")))
            .map(|(m, e)| format!("`{m}` ({e})"))
            .collect::<Vec<_>>()
            .join(", "),
        s.end_time
    )
}

impl IceConfig {
    /// The solver's reactions of the section (step 4), checked against the
    /// scene's materials; the heat of reaction the given one or the JWL++
    /// default.
    pub fn reactions(&self, scene: &Scene<'_>) -> Result<Vec<IceReaction>, FieldError> {
        reactions(scene, self).map_err(|(f, m)| FieldError::new(f, m))
    }

    /// The checks of the section as the fluid side of a coupled pipeline
    /// (IceMpm, whose solids the caller appends to `materials`): those of
    /// [`PipelineSpec::validate`] but the one that forbids the slip
    /// exchange, which acts on the solids.
    pub fn check_fluids(&self, scene: &Scene<'_>) -> Result<(), FieldError> {
        check_fluids(scene, self).map_err(|(f, m)| FieldError::new(f, m))
    }

    /// Builds the solver, its patches shared among `ranks` from the start
    /// (each rank allocates and fills only its own). `particle_materials`
    /// is the number of the section's last materials that particles carry
    /// (the IceMpm pipeline's solids; 0 for the Ice pipeline). With any,
    /// every trace material takes its own density at the region's
    /// pressure and temperature, or at 300 K where it has none at the
    /// region's temperature (whose solid and gases must not trace each
    /// other's density), else the rule of the module doc; and a region of
    /// a material the particles carry may give it any temperature (the
    /// particles keep it), where the Ice pipeline refuses one that its
    /// equation of state cannot give the region's pressure.
    pub fn build_on(
        &self,
        scene: &Scene<'_>,
        particle_materials: usize,
        ranks: Arc<dyn Communicator>,
    ) -> Result<IceSolver<EosModel>, FieldError> {
        build_with_traces(scene, self, particle_materials, ranks)
            .map_err(|(f, m)| FieldError::new(f, m))
    }
}

impl PipelineSpec for IceConfig {
    const INFO: PipelineInfo = PipelineInfo {
        name: "Ice",
        summary: "multi-material cell-centred ICE: equilibration pressure, momentum and heat exchange, van Leer or donor-cell advection, total-energy closure (seed 000 §3.3)",
        example: "Ice(materials: [\"air\", \"products\"], cfl: 0.4, advection: VanLeer, momentum_exchange: 1e15)",
        docs: "docs/physics/ice/README.md",
    };
    type Solver = IceSolver<EosModel>;

    /// The ICE's own Courant number is `pipeline.cfl`, checked with the
    /// section; the scenario's `time.cfl` is not used, so its limit is 1.
    fn limits(&self, _geometry: Geometry) -> PipelineLimits {
        PipelineLimits {
            fields: &FIELDS,
            max_cfl: 1.0,
            ghost: GHOST,
            node_fields: &[],
            patch_pieces: true,
            patch_checkpoints: true,
            particle_gauges: false,
            heat_conduction: false,
        }
    }

    fn validate(&self, scene: &Scene<'_>) -> Result<(), FieldError> {
        check_alone(self)
            .and_then(|()| check_fluids(scene, self))
            .map_err(|(f, m)| FieldError::new(f, m))
    }

    /// Builds the solver, its patches spread over the ranks of the run
    /// ([`brisance_grid::comm::world`]; docs/cluster.md) from the start.
    fn build(&self, scene: &Scene<'_>) -> Result<IceSolver<EosModel>, FieldError> {
        check_alone(self).map_err(|(f, m)| FieldError::new(f, m))?;
        self.build_on(scene, 0, brisance_grid::comm::world())
    }

    fn describe(&self, scene: &Scene<'_>) -> String {
        description(scene, self)
    }
}

/// Registers the multi-material ICE as the `Ice` pipeline: a config writes
/// `pipeline: Ice(...)`, and the composer checks, builds and describes it
/// through [`PipelineSpec`].
pub fn register(registry: &mut brisance_scene::plugin::PipelineRegistry) {
    registry.register(brisance_scene::plugin::PipelinePlugin::of::<IceConfig>());
}

#[cfg(test)]
mod tests;
