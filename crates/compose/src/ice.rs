//! The `Ice` pipeline: the multi-material, cell-centred ICE method of
//! seed 000 §2, §3.1 and §3.3 (`brisance_ice`).
//!
//! `materials` lists the scenario materials (each with an EOS) that live in
//! every cell, in the solver's order: output fields `volume_fraction_k`,
//! `density_k`, `temperature_k`, `velocity_x_k` number them from 1. Each
//! initial region names one of them; a cell takes the state of the last
//! region containing its centre, with that material at volume fraction
//! 1 − (N − 1)·10⁻⁶ and every other material as a trace of volume fraction
//! 10⁻⁶ at the region's density, velocity and pressure (the rule of the
//! crate's two-material Sod tube, `brisance_ice::cases::sod_two`). The
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
//! finds after each step 2) between two of `materials`;
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

use brisance_core::Eos;
use brisance_eos::EosModel;
use brisance_grid::Level;
use brisance_ice::{
    Advection, CellState, Deflagration, ExchangeCoefficients, IceBoundary, IceOptions, IceRate,
    IceReaction, IceSolver, JwlPlusPlus, MaterialState, MaterialTransport, PressureSolve,
    WholeGridPass, GHOST, MAX_MATERIALS,
};
use brisance_plugin::{Installed, PluginEnum};
use brisance_reaction::plugin::{PluginReaction, ReactionPlugin};
use serde::{Deserialize, Serialize};

use crate::build::primitive_state;
use crate::config::{BoundaryConfig, Scenario};

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
    /// sound-speed CFL) or `Implicit(tolerance: 1e-10, max_iterations: 20)`
    /// (both fields optional; Δt at the material-velocity CFL; see
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
    /// A model from a plugin crate (`ThermalDecomposition(...)`), never
    /// written as `Plugin`.
    Plugin(PluginReaction),
}

impl IceReactionModel {
    /// The config names of the built-in variants.
    pub const VARIANTS: &'static [&'static str] = &["JwlPlusPlus", "Deflagration"];

    /// The config name of this model.
    pub fn variant(&self) -> &'static str {
        match self {
            Self::JwlPlusPlus(_) => "JwlPlusPlus",
            Self::Deflagration(_) => "Deflagration",
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
fn reactions(s: &Scenario, cfg: &IceConfig) -> Result<Vec<IceReaction>, Problem> {
    let eos = material_eos(s, cfg)?;
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
    brisance_ice::reaction::detonation_energy(m, j)
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
/// per material for up to [`MAX_MATERIALS`] materials); [`validate`]
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
fn material_eos(s: &Scenario, cfg: &IceConfig) -> Result<Vec<EosModel>, Problem> {
    cfg.materials
        .iter()
        .enumerate()
        .map(|(k, name)| match s.materials.get(name) {
            None => Err((
                format!("pipeline.materials.{k}"),
                format!(
                    "`{name}` is not a scenario material (known: {})",
                    s.materials
                        .keys()
                        .map(|m| format!("`{m}`"))
                        .collect::<Vec<_>>()
                        .join(", ")
                ),
            )),
            Some(m) => m.eos().cloned().ok_or_else(|| {
                (
                    format!("materials.{name}.eos"),
                    format!("the Ice pipeline needs an EOS for `{name}`"),
                )
            }),
        })
        .collect()
}

/// Checks the pipeline; errors carry the field path.
pub fn validate(s: &Scenario, cfg: &IceConfig) -> Result<(), Problem> {
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
    material_eos(s, cfg)?;
    reactions(s, cfg)?;
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
            let field = if e.contains("`max_iterations`") {
                "max_iterations"
            } else {
                "tolerance"
            };
            (format!("pipeline.pressure.{field}"), e)
        })?;
    }
    crate::validate::check_faces(s, "Ice", ICE_FACES, |_| "")?;
    for (face, bc) in s.boundaries.faces() {
        if let BoundaryConfig::Fixed(state) = bc {
            crate::validate::fixed_face_material(face, state, &cfg.materials, "material")?;
        }
    }
    for (i, r) in s.initial.iter().enumerate() {
        if !cfg.materials.contains(&r.material) {
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
    let o = &s.outputs;
    let lists = std::iter::once(("outputs.fields".to_string(), &o.fields))
        .chain(
            o.gauges
                .iter()
                .enumerate()
                .map(|(k, g)| (format!("outputs.gauges.{k}.fields"), &g.fields)),
        )
        .chain(
            o.lineouts
                .iter()
                .enumerate()
                .map(|(k, l)| (format!("outputs.lineouts.{k}.fields"), &l.fields)),
        );
    for (path, fields) in lists {
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
    Ok(())
}

/// Builds the solver, its patches spread over the ranks of the run
/// ([`brisance_grid::comm::world`]; docs/cluster.md).
pub fn build(s: &Scenario, cfg: &IceConfig) -> Result<IceSolver<EosModel>, Problem> {
    let mut solver = build_with_traces(s, cfg, false)?;
    let ranks = brisance_grid::comm::world();
    if ranks.size() > 1 {
        // What the ICE cannot spread over ranks, named at its field.
        let field = match solver.whole_grid_pass() {
            Some(WholeGridPass::ImplicitPressure) => "pipeline.pressure",
            Some(WholeGridPass::Transport) => "pipeline.transport",
            Some(WholeGridPass::SurfaceBurn) => "pipeline.reactions",
            Some(WholeGridPass::Particles) => "pipeline",
            None => "domain.patches",
        };
        solver
            .distribute(ranks)
            .map_err(|e| (field.to_string(), e.to_string()))?;
    }
    Ok(solver)
}

/// Builds the solver; with `own_density` every trace material takes its
/// own density at the region's pressure and temperature, or at 300 K where
/// it has none at the region's temperature (the IceMpm pipeline, whose
/// solid and gases must not trace each other's density), else the rule of
/// the module doc.
pub(crate) fn build_with_traces(
    s: &Scenario,
    cfg: &IceConfig,
    own_density: bool,
) -> Result<IceSolver<EosModel>, Problem> {
    validate(s, cfg)?;
    let eos = material_eos(s, cfg)?;
    let n = eos.len();
    let d = &s.domain;
    let level = Level::new(d.lower, d.upper, d.cells, d.patches, GHOST)
        .map_err(|e| ("domain.patches".to_string(), e.to_string()))?;
    // The cell state of material m with state `state` (`path` for the
    // errors): the rule of the module doc, that of every initial region
    // and of the ghosts of a `Fixed` face.
    let cell_state = |path: &str, m: usize, state: &crate::config::StateConfig| {
        let p = primitive_state(&eos[m], state).map_err(|e| (path.to_string(), e))?;
        let trace = TRACE_FRACTION;
        let t_region = eos[m].temperature(
            p.density,
            eos[m]
                .specific_internal_energy(p.density, p.pressure)
                .map_err(|e| (path.to_string(), e.to_string()))?,
        );
        // The cells keep a pressure, not an energy: a temperature the
        // material's (ρ, p) cannot carry would be lost without a word.
        if let (None, None, Some(t)) = (
            state.pressure,
            state.specific_internal_energy,
            state.temperature,
        ) {
            if !((t_region - t).abs() <= 1e-6 * t.abs().max(1.0)) {
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
                let m =
                    crate::validate::fixed_face_material(face, state, &cfg.materials, "material")?;
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
                material_index(&r.material),
                &r.state,
            )
        })
        .collect::<Result<Vec<_>, Problem>>()?;
    // Every cell must be covered. On an (r, z) grid a region is tested at
    // the point (r, z, 0) of the half plane through the axis.
    let geometry = level.geometry;
    let axisymmetric = d.geometry.is_axisymmetric();
    let plane = move |x: [f64; 3]| {
        if axisymmetric {
            [x[0], x[1], 0.0]
        } else {
            x
        }
    };
    for k in 0..d.cells[2] {
        for j in 0..d.cells[1] {
            for i in 0..d.cells[0] {
                let x = geometry.cell_centre([i, j, k]);
                if !s.initial.iter().any(|r| r.region.contains(plane(x))) {
                    return Err(("initial".into(), format!("cell ({i}, {j}, {k}) at {x:?} is in no initial region; add an `Everywhere` region first")));
                }
            }
        }
    }
    let init = |x: [f64; 3]| {
        let x = plane(x);
        let idx = s
            .initial
            .iter()
            .rposition(|r| r.region.contains(x))
            .unwrap_or(0);
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
        ..Default::default()
    };
    let exchange = ExchangeCoefficients::uniform(n, cfg.momentum_exchange, cfg.heat_exchange);
    let reactions = reactions(s, cfg)?;
    let mut solver = IceSolver::new(eos, level, boundaries, exchange, options, init)
        .map_err(|e| ("pipeline".to_string(), e.to_string()))?;
    solver
        .set_reactions(reactions)
        .map_err(|e| ("pipeline.reactions".to_string(), e.to_string()))?;
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
pub fn describe(s: &Scenario, cfg: &IceConfig) -> String {
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
        s.time.end
    )
}

#[cfg(test)]
mod tests {
    use brisance_ice::cases::sod_one;

    use crate::build::build_solver;
    use crate::load_str;

    const SOD: &str = include_str!("../../../configs/sod_ice.ron");

    /// The Sod tube of configs/sod_ice.ron at 100 cells: mass is conserved
    /// to round-off (no wave reaches the ends by t = 0.2), the density
    /// equals the ICE crate's own Sod case at the same resolution, and the
    /// plateau between contact and shock is near Toro's exact ρ*R.
    #[test]
    fn sod_ice_config_matches_the_crate_case() {
        let loaded = load_str("sod_ice.ron", SOD, &["domain.cells=(100,1,1)".into()]).unwrap();
        let mut solver = build_solver(&loaded.scenario).unwrap();
        let before = solver.conservation_totals();
        // The step sequence of `run_to`, through the trait object.
        let mut steps = 0;
        while solver.time() < 0.2 * (1.0 - 1e-12) {
            let dt = solver.stable_dt().unwrap().min(0.2 - solver.time());
            solver.advance(dt).unwrap();
            steps += 1;
        }
        let after = solver.conservation_totals();
        // Round-off: at most one ulp per cell per step.
        let bound = (steps * 100) as f64 * f64::EPSILON * before.mass;
        assert!(
            (after.mass - before.mass).abs() <= bound,
            "mass {} -> {} in {steps} steps",
            before.mass,
            after.mass
        );
        let rho = solver.cell_data(&["density".into()]).unwrap();
        let rho = rho.field("density").unwrap();
        let reference = sod_one(100, brisance_ice::Advection::VanLeer, 0.2);
        let reference = brisance_core::Solver::cell_data(&reference, &["density".into()]).unwrap();
        let reference = reference.field("density").unwrap();
        assert_eq!(rho.len(), 100);
        let diff = rho
            .iter()
            .zip(reference)
            .map(|(a, b)| (a - b).abs())
            .fold(0.0, f64::max);
        eprintln!(
            "{steps} steps, mass change {:e}, max |ρ − ρ_crate| {diff:e}, ρ(0.755) {}",
            after.mass - before.mass,
            rho[75]
        );
        assert!(diff <= 1e-12, "max |ρ − ρ_crate| = {diff}");
        // x = 0.755, between contact (0.685) and shock (0.850).
        assert!((rho[75] - 0.26557).abs() < 5e-3, "rho = {}", rho[75]);
    }

    const STICK: &str = include_str!("../../../configs/ratestick_1d.ron");

    /// configs/ratestick_1d.ron at h = 2 mm (50 cells): the 90 m/s impact
    /// on the wall starts a detonation that burns the explosive behind it
    /// and reaches x = 6 cm by 15 µs (D_CJ = 5899 m/s).
    #[test]
    fn ratestick_config_detonates() {
        let loaded =
            load_str("ratestick_1d.ron", STICK, &["domain.cells=(50,1,1)".into()]).unwrap();
        let mut solver = build_solver(&loaded.scenario).unwrap();
        while solver.time() < 1.5e-5 {
            let dt = solver.stable_dt().unwrap();
            solver.advance(dt).unwrap();
        }
        let d = solver
            .cell_data(&["volume_fraction_1".into(), "pressure".into()])
            .unwrap();
        let theta = d.field("volume_fraction_1").unwrap();
        let p = d.field("pressure").unwrap();
        let burnt = theta.iter().take_while(|&&t| t < 0.5).count();
        let p_max = p.iter().cloned().fold(0.0, f64::max);
        eprintln!("burnt cells {burnt} of 50, p max {p_max:e}");
        // 15 µs at ~5 km/s after a ~3 µs start: 5–7 cm burnt.
        assert!((20..=40).contains(&burnt), "{burnt}");
        assert!(p_max > 5e9, "{p_max:e}");
    }

    /// A metal trace in a hot booster: copper has no Mie–Grüneisen state
    /// at 10 GPa and the products' 19 000 K (its thermal pressure alone is
    /// above 10 GPa), so it takes its density at 10 GPa and 300 K; before,
    /// the build stopped at the booster's region.
    #[test]
    fn a_metal_trace_in_a_hot_booster_takes_room_temperature() {
        let text = r#"Scenario(
            name: "booster",
            domain: (lower: (0, 0, 0), upper: (0.01, 0.001, 0.001), cells: (10, 1, 1)),
            time: (end: 1.0e-6),
            materials: {
                "products": (library: "qm100_products"),
                "copper": (eos: MieGruneisenLinear(c0: 3619.7, s: 1.489, gamma0: 2.02, rho0: 8930.0, cv: 383.0, t0: 300.0)),
            },
            pipeline: Ice(materials: ["products", "copper"]),
            initial: [
                (region: Everywhere, material: "copper", state: (density: 8930.0077, temperature: 300.0)),
                (region: Box(min: (0, -1, -1), max: (0.005, 1, 1)), material: "products", state: (density: 1260.0, pressure: 1.0e10)),
            ],
        )"#;
        let loaded = load_str("booster.ron", text, &[]).unwrap();
        let solver = build_solver(&loaded.scenario).unwrap();
        let d = solver
            .cell_data(&[
                "density_2".into(),
                "volume_fraction_2".into(),
                "temperature_2".into(),
                "pressure".into(),
            ])
            .unwrap();
        let f = |name: &str| d.field(name).unwrap()[0];
        // The booster's cell: the copper trace at 10 GPa and 300 K, its
        // own density (density_2 is θρ) compressed above ρ₀ (on the
        // Us–up Hugoniot 10 GPa is about 9.6·10³ kg/m³).
        let rho = f("density_2") / f("volume_fraction_2");
        assert!(
            (f("pressure") - 1e10).abs() < 1e-6 * 1e10,
            "{}",
            f("pressure")
        );
        assert!(
            (f("temperature_2") - 300.0).abs() < 1e-6,
            "{}",
            f("temperature_2")
        );
        assert!(rho > 9.4e3 && rho < 9.8e3, "{rho}");
    }

    /// The cylinder test with its copper Eulerian and a heat exchange
    /// (H = 10¹⁰ W/(m³·K)): the products trace in the copper beside the
    /// booster, cooled by the exchange from 19 000 K and compressed to a
    /// few per cent of its volume in the same step, keeps a positive
    /// volume (eq 31's thermal term taken of its compressed volume); it
    /// stopped the run at its first step before.
    #[test]
    fn a_heat_exchange_keeps_a_cooled_compressed_trace_positive() {
        let text = include_str!("../../../configs/cylinder_rz.ron");
        let sets = [
            r#"pipeline=Ice(materials: ["qm100", "products", "air", "copper"], reactions: [(reactant: "qm100", product: "products", model: JwlPlusPlus(g: 9.1e-5, b: 1.0))], heat_exchange: 1e10)"#,
            "outputs.particle_gauges=[]",
        ]
        .map(String::from);
        let loaded = load_str("cylinder_rz.ron", text, &sets).unwrap();
        let mut solver = build_solver(&loaded.scenario).unwrap();
        for _ in 0..3 {
            let dt = solver.stable_dt().unwrap();
            solver.advance(dt).unwrap();
        }
    }

    /// `model: Deflagration(...)` builds the surface burn (its heat of
    /// reaction the JWL++ default of the Murnaghan → JwlCTerm pair), and a
    /// bad parameter is reported at the model's field with its name.
    #[test]
    fn a_config_names_the_deflagration() {
        let law = "model: Deflagration(a: 5.218307e-6, n: 0.778, ignition_temperature: 450.0)";
        let text = STICK.replace("model: JwlPlusPlus(g: 3.5083e-7, b: 1.3)", law);
        let loaded = load_str("ratestick_1d.ron", &text, &[]).unwrap();
        let crate::config::Pipeline::Ice(ice) = &loaded.scenario.pipeline else {
            panic!("an Ice pipeline");
        };
        let rx = super::reactions(&loaded.scenario, ice).unwrap();
        assert_eq!(
            rx[0].rate,
            super::IceRate::Deflagration(brisance_reaction::Deflagration::pbx_9501())
        );
        assert!(rx[0].heat_of_reaction > 0.0);
        let bad = text.replace("n: 0.778", "n: -0.5");
        let err = load_str("ratestick_1d.ron", &bad, &[]).unwrap_err();
        assert_eq!(
            err.field.as_deref(),
            Some("pipeline.reactions.0.model"),
            "{err}"
        );
        assert!(err.to_string().contains("`n`"), "{err}");
    }

    /// A reaction naming a material outside the pipeline, or products
    /// without a default heat of reaction, is reported at its field.
    #[test]
    fn bad_reactions_name_the_field() {
        let bad = STICK.replace("reactant: \"anfo\"", "reactant: \"tnt\"");
        let err = load_str("ratestick_1d.ron", &bad, &[]).unwrap_err();
        assert_eq!(
            err.field.as_deref(),
            Some("pipeline.reactions.0.reactant"),
            "{err}"
        );
        let bad = STICK.replace("g: 3.5083e-7", "g: -1.0");
        let err = load_str("ratestick_1d.ron", &bad, &[]).unwrap_err();
        assert_eq!(
            err.field.as_deref(),
            Some("pipeline.reactions.0.model"),
            "{err}"
        );
        let bad = STICK.replace("product: \"products\"", "product: \"anfo\"");
        let err = load_str("ratestick_1d.ron", &bad, &[]).unwrap_err();
        assert_eq!(
            err.field.as_deref(),
            Some("pipeline.reactions.0.product"),
            "{err}"
        );
        let bad = STICK.replace(
            "\"products\": (eos: JwlCTerm(a: 2.9867e11, b: 4.11706e9, c: 7.206147e8, r1: 4.95, r2: 1.15, omega: 0.35, rho0: 1160.0, cv: 862.0689655172414)),",
            "\"products\": (eos: IdealGas(gamma: 1.4, cv: 717.6, rho0: 1.2)),",
        );
        let err = load_str("ratestick_1d.ron", &bad, &[]).unwrap_err();
        assert_eq!(
            err.field.as_deref(),
            Some("pipeline.reactions.0.heat_of_reaction"),
            "{err}"
        );
    }

    /// `pressure: Implicit(...)` reaches the solver's options (fields
    /// left out take their defaults); bad settings name their field.
    #[test]
    fn implicit_pressure_is_reachable_from_the_config() {
        use brisance_ice::{ImplicitPressure, PressureSolve};
        let with = |p: &str| {
            SOD.replace(
                "pipeline: Ice(materials: [\"gas\"]),",
                &format!("pipeline: Ice(materials: [\"gas\"], pressure: {p}),"),
            )
        };
        let cfg = with("Implicit(tolerance: 1e-9)");
        let loaded = load_str("sod_ice.ron", &cfg, &["domain.cells=(20,1,1)".into()]).unwrap();
        let crate::config::Pipeline::Ice(ice) = &loaded.scenario.pipeline else {
            panic!("an Ice pipeline");
        };
        assert_eq!(
            ice.pressure,
            PressureSolve::Implicit(ImplicitPressure {
                tolerance: 1e-9,
                max_iterations: 20
            })
        );
        let solver = super::build(&loaded.scenario, ice).unwrap();
        assert_eq!(solver.options().pressure, ice.pressure);
        let mut solver = build_solver(&loaded.scenario).unwrap();
        let dt = solver.stable_dt().unwrap();
        solver.advance(dt.min(1e-3)).unwrap();
        for (p, field) in [
            ("Implicit(tolerance: -1.0)", "pipeline.pressure.tolerance"),
            (
                "Implicit(max_iterations: 0)",
                "pipeline.pressure.max_iterations",
            ),
        ] {
            let err = load_str("sod_ice.ron", &with(p), &[]).unwrap_err();
            assert_eq!(err.field.as_deref(), Some(field), "{err}");
        }
        assert!(load_str("sod_ice.ron", &with("Implicit(tol: 1.0)"), &[]).is_err());
        let default = load_str("sod_ice.ron", SOD, &[]).unwrap();
        let crate::config::Pipeline::Ice(ice) = &default.scenario.pipeline else {
            panic!("an Ice pipeline");
        };
        assert_eq!(ice.pressure, PressureSolve::Explicit);
    }

    /// `face_pressure_courant` reaches the solver's options (0 when left
    /// out); a value outside [0, 1] is reported at its field.
    #[test]
    fn face_pressure_courant_is_reachable_from_the_config() {
        let options = |text: &str| {
            let loaded = load_str("sod_ice.ron", text, &["domain.cells=(20,1,1)".into()]).unwrap();
            let crate::config::Pipeline::Ice(ice) = &loaded.scenario.pipeline else {
                panic!("an Ice pipeline");
            };
            *super::build(&loaded.scenario, ice).unwrap().options()
        };
        assert_eq!(options(SOD).face_pressure_courant, 0.0);
        let with = |v: &str| {
            SOD.replace(
                "pipeline: Ice(materials: [\"gas\"]),",
                &format!("pipeline: Ice(materials: [\"gas\"], face_pressure_courant: {v}),"),
            )
        };
        assert_eq!(options(&with("0.8")).face_pressure_courant, 0.8);
        for bad in ["-0.1", "1.5", "NaN"] {
            let err = load_str("sod_ice.ron", &with(bad), &[]).unwrap_err();
            assert_eq!(
                err.field.as_deref(),
                Some("pipeline.face_pressure_courant"),
                "{err}"
            );
        }
    }

    /// `max_dt` bounds the solver's step (none when left out); a value that
    /// is not a finite time > 0 is reported at its field.
    #[test]
    fn max_dt_bounds_the_step() {
        use brisance_core::Solver;
        let build = |text: &str| {
            let loaded = load_str("sod_ice.ron", text, &["domain.cells=(20,1,1)".into()]).unwrap();
            let crate::config::Pipeline::Ice(ice) = &loaded.scenario.pipeline else {
                panic!("an Ice pipeline");
            };
            super::build(&loaded.scenario, ice).unwrap()
        };
        let free = build(SOD);
        assert_eq!(free.options().max_dt, f64::INFINITY);
        let dt = free.stable_dt().unwrap();
        let with = |v: &str| {
            SOD.replace(
                "pipeline: Ice(materials: [\"gas\"]),",
                &format!("pipeline: Ice(materials: [\"gas\"], max_dt: {v}),"),
            )
        };
        let bounded = build(&with(&format!("{:e}", 0.5 * dt)));
        assert_eq!(bounded.stable_dt().unwrap(), 0.5 * dt);
        assert_eq!(
            build(&with(&format!("{:e}", 2.0 * dt)))
                .stable_dt()
                .unwrap(),
            dt
        );
        for bad in ["0.0", "-1e-6", "inf", "NaN"] {
            let err = load_str("sod_ice.ron", &with(bad), &[]).unwrap_err();
            assert_eq!(err.field.as_deref(), Some("pipeline.max_dt"), "{err}");
        }
    }

    /// Unknown names and a material without EOS are reported at their field.
    #[test]
    fn bad_materials_name_the_field() {
        let err = load_str(
            "sod_ice.ron",
            SOD,
            &["pipeline.materials=[\"gas\", \"air\"]".into()],
        )
        .unwrap_err();
        assert_eq!(err.field.as_deref(), Some("pipeline.materials.1"), "{err}");
        let bad = SOD.replace(
            "material: \"gas\", state: (density: 0.125",
            "material: \"air\", state: (density: 0.125",
        );
        let err = load_str("sod_ice.ron", &bad, &[]).unwrap_err();
        assert_eq!(err.field.as_deref(), Some("initial.1.material"), "{err}");
        let bad = SOD.replace(
            "\"gas\": (eos: IdealGas(gamma: 1.4, cv: 1.0, rho0: 1.0)),",
            "\"gas\": (eos: IdealGas(gamma: 1.4, cv: 1.0, rho0: 1.0)), \"steel\": (model: Null(eos: IdealGas(gamma: 1.4, cv: 1.0, rho0: 1.0), viscosity: 0.0)),",
        );
        let err = load_str(
            "sod_ice.ron",
            &bad,
            &["pipeline.materials=[\"gas\", \"steel\"]".into()],
        )
        .unwrap_err();
        assert_eq!(err.field.as_deref(), Some("materials.steel.eos"), "{err}");
    }

    /// `transport` reaches the solver per material (a field left out is
    /// 0), and a bad entry is reported at its field.
    #[test]
    fn transport_reaches_the_solver_and_bad_values_name_the_field() {
        let with = |t: &str| {
            SOD.replace(
                "pipeline: Ice(materials: [\"gas\"]),",
                &format!("pipeline: Ice(materials: [\"gas\"], transport: {t}),"),
            )
        };
        let cfg = with("{\"gas\": (viscosity: 0.01, thermal_conductivity: 0.02)}");
        let loaded = load_str("sod_ice.ron", &cfg, &["domain.cells=(20,1,1)".into()]).unwrap();
        let crate::config::Pipeline::Ice(ice) = &loaded.scenario.pipeline else {
            panic!("an Ice pipeline");
        };
        let solver = super::build(&loaded.scenario, ice).unwrap();
        assert_eq!(solver.transport().len(), 1);
        assert_eq!(solver.transport()[0].viscosity, 0.01);
        assert_eq!(solver.transport()[0].thermal_conductivity, 0.02);
        let limits = solver.time_step_limits().unwrap();
        assert!(limits.viscous.is_finite() && limits.conduction.is_finite());
        let cfg = with("{\"gas\": (thermal_conductivity: 0.5)}");
        let loaded = load_str("sod_ice.ron", &cfg, &[]).unwrap();
        let crate::config::Pipeline::Ice(ice) = &loaded.scenario.pipeline else {
            panic!("an Ice pipeline");
        };
        assert_eq!(ice.transport["gas"].viscosity, 0.0);
        for (t, field) in [
            ("{\"air\": (viscosity: 1.0)}", "pipeline.transport.air"),
            (
                "{\"gas\": (viscosity: -1.0)}",
                "pipeline.transport.gas.viscosity",
            ),
            (
                "{\"gas\": (thermal_conductivity: inf)}",
                "pipeline.transport.gas.thermal_conductivity",
            ),
        ] {
            let err = load_str("sod_ice.ron", &with(t), &[]).unwrap_err();
            assert_eq!(err.field.as_deref(), Some(field), "{err}");
        }
    }

    /// A reaction model of a plugin crate, named in RON: QM-100 reactant
    /// in a closed 1D box decomposes by `ThermalDecomposition`
    /// (crates/reaction-thermal, registered in `crate::plugins`). Over
    /// 0.1 µs the burnt fraction is 1.4·10⁻⁴, too little to move the
    /// reactant's temperature (298.15 K, the reference temperature, the
    /// only one an Eulerian Murnaghan reactant can start at: 550 K is
    /// refused at its field), so every cell's F is the exact
    /// 1 − exp(−k t) of k(298.15 K); the model writes back as it was read,
    /// and a bad parameter is reported at its field.
    #[test]
    fn a_plugin_reaction_model_burns_by_its_registered_name() {
        use brisance_reaction_thermal::ThermalDecomposition;

        const BOX: &str = r#"Scenario(
            name: "decomposition",
            domain: (lower: (0.0, 0.0, 0.0), upper: (0.004, 0.001, 0.001), cells: (4, 1, 1)),
            boundaries: (x_low: Reflective, x_high: Reflective),
            time: (end: 1.0e-7),
            materials: {"qm100": (library: "qm100_reactant"), "products": (library: "qm100_products")},
            pipeline: Ice(
                materials: ["qm100", "products"],
                reactions: [(reactant: "qm100", product: "products", model: ThermalDecomposition(z: 1.0e7, activation_energy: 2.2e4))],
            ),
            initial: [(region: Everywhere, material: "qm100", state: (density: 1260.1302, temperature: 298.15))],
        )"#;
        let loaded = load_str("box.ron", BOX, &[]).unwrap();
        let crate::config::Pipeline::Ice(ice) = &loaded.scenario.pipeline else {
            panic!("an Ice pipeline");
        };
        let model = &ice.reactions[0].model;
        assert_eq!(model.variant(), "ThermalDecomposition");
        let text = ron::to_string(model).unwrap();
        let back: super::IceReactionModel = crate::load::ron_options().from_str(&text).unwrap();
        assert_eq!(&back, model, "{text}");
        let mut solver = build_solver(&loaded.scenario).unwrap();
        let t_end = loaded.scenario.time.end;
        while solver.time() < t_end * (1.0 - 1e-12) {
            let dt = solver.stable_dt().unwrap().min(t_end - solver.time());
            solver.advance(dt).unwrap();
        }
        let law = ThermalDecomposition {
            z: 1.0e7,
            activation_energy: 2.2e4,
        };
        let exact = -(-law.rate_constant(298.15) * t_end).exp_m1();
        let names = ["density_1", "density_2", "temperature_1"];
        let d = solver.cell_data(&names.map(String::from)).unwrap();
        let field = |name: &str| d.field(name).unwrap().to_vec();
        let (r1, r2, t1) = (field(names[0]), field(names[1]), field(names[2]));
        for c in 0..4 {
            // The cell's macroscopic densities: F = ρ_p/(ρ_r + ρ_p).
            let f = r2[c] / (r1[c] + r2[c]);
            assert!((t1[c] - 298.15).abs() < 0.05, "cell {c}: T = {}", t1[c]);
            assert!(
                (f / exact - 1.0).abs() < 1e-3,
                "cell {c}: F = {f}, exact {exact}"
            );
        }
        // The Murnaghan reactant cannot start at 550 K: its cells keep a
        // pressure, which carries no temperature for it.
        let hot = BOX.replace("temperature: 298.15", "temperature: 550.0");
        let loaded = load_str("box.ron", &hot, &[]).unwrap();
        let err = crate::build::build(&loaded.scenario)
            .err()
            .expect("refused");
        assert_eq!(
            err.field.as_deref(),
            Some("initial.0.state.temperature"),
            "{err}"
        );
        assert!(err.to_string().contains("298.15"), "{err}");
        let bad = BOX.replace("z: 1.0e7", "z: -1.0");
        let err = load_str("box.ron", &bad, &[]).unwrap_err();
        assert!(err.to_string().contains("z:"), "{err}");
    }
}
