//! The `FdmMpmBridge` pipeline's section of a scenario, its checks and its
//! builder (`brisance_scene::PipelineSpec`): the coupled finite-difference
//! / material-point method of seed 001 §3 ([`crate::Cfdmp`],
//! docs/physics/couple/bridge.md).
//!
//! The scenario's domain is the union of `fdm_region` and `mpm_region`,
//! two boxes on the domain's cells that differ along one axis and overlap
//! there by the bridge width w, the config's `w` (default 5): boxes whose
//! overlap is not w cells are refused. Initial regions are read per point,
//! the last region containing it winning:
//!
//! - FDM cells take the state of the last region of a gas (`air`, or the
//!   `products` with mass fraction 1) containing their centre; a `remap`
//!   file written by `brisance remap` on the FDM region's grid then replaces
//!   the FDM region's cells (it needs `products`).
//! - MPM particles (`ppc` per cell per active direction) fill the MPM
//!   region: where the last region is a material with a constitutive
//!   `model` (other than the gases), particles of that material; where it is
//!   a gas, air particles (material 0, a `Null` fluid with the air's ideal
//!   gas) or, for the products, products particles (material 1, a `Null`
//!   fluid with the products' EOS) of that state. Inflow from the FDM
//!   becomes products particles where the donor cell is mostly products.
//!
//! Faces: as for `Fdm` on the FDM grid (its face inside the MPM region is
//! an outflow past the fictitious cells) and as for `Mpm` on the MPM grid
//! (`Reflective` a symmetry plane, `Wall` a fixed wall, others outflow; its
//! face inside the FDM region is an outflow).

use brisance_constitutive::{MaterialModel, NullMaterial};
use brisance_core::{Eos, Geometry, Material, Solver};
use brisance_eos::EosModel;
use brisance_fdm::pipeline::{primitive_state, ViscosityConfig};
use brisance_fdm::{
    ArtificialViscosity, FdmBoundary, FdmOptions, FdmSolver, GasLaw, PrimitiveState, ProductsInAir,
};
use brisance_grid::Level;
use brisance_mpm::{
    BulkViscosity, GridBoundary, MaterialId, MpmOptions, MpmSolver, ParticleInit, ParticleSet,
    Particles, ShapeFunction, UpdateScheme,
};
use brisance_scene::{
    BoundaryConfig, FieldError, IntoSolver, PipelineInfo, PipelineLimits, PipelineSpec, Scene,
};
use serde::{Deserialize, Serialize};

use crate::gas_remap::cached_remap;
use crate::mpm_pipeline::{
    check_fluid_bulk_viscosity, describe_bulk_viscosity, BulkViscosityConfig,
};
use crate::{BridgeRegions, Cfdmp, CfdmpOptions, Charge, RegionBox, Remapped, Side};

type Problem = (String, String);

/// An axis-aligned box, m.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BoxConfig {
    /// Low corner, m.
    pub lower: [f64; 3],
    /// High corner, m.
    pub upper: [f64; 3],
}

/// Options of the `FdmMpmBridge` pipeline.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BridgeConfig {
    /// The FDM region.
    pub fdm_region: BoxConfig,
    /// The MPM region; it overlaps one end of the FDM region by whole cells
    /// (the bridge).
    pub mpm_region: BoxConfig,
    /// Bridge width w, cells (default 5): the overlap of `fdm_region` and
    /// `mpm_region` along the split axis must be exactly w cells, or the
    /// config is refused. It checks the boxes and changes nothing else.
    #[serde(default)]
    pub w: Option<usize>,
    /// The air (a key of `materials` with an `IdealGas`): the FDM gas and
    /// the MPM fluid.
    pub air: String,
    /// Detonation products carried by the FDM as a second species (a key of
    /// `materials`, a JWL).
    #[serde(default)]
    pub products: Option<String>,
    /// FDM artificial viscosity (seed 001 eqs 3–5).
    #[serde(default)]
    pub viscosity: ViscosityConfig,
    /// Initial state of the FDM region from `brisance remap` (path relative
    /// to the working directory).
    #[serde(default)]
    pub remap: Option<String>,
    /// The charge whose 1D detonation the run remaps onto the FDM region
    /// itself (instead of a `remap` file): explosive, symmetry, centre,
    /// radius, 1D grid and time. The result is cached by its inputs
    /// ([`crate::remap_cache_dir`]).
    #[serde(default)]
    pub charge: Option<Charge>,
    /// MPM particles per cell per active direction.
    #[serde(default = "default_ppc")]
    pub ppc: usize,
    /// The MPM region's shape functions: `Linear` (default, seed 001 eq
    /// 16) or `CpGimp`. With cpGIMP the donor cells stay points (the
    /// linear hat: they reach the halo cell's nodes alone), a deposit moves
    /// its particle to the common centre of mass, and the fictitious cells
    /// read node values as before (docs/physics/couple/bridge.md, "cpGIMP
    /// in the MPM region"). `Gimp` is refused (uGIMP's fixed domains cannot
    /// take the deposits), `QuadraticBSpline` too (its donors would reach
    /// past the halo cell).
    #[serde(default)]
    pub shape_function: ShapeFunction,
    /// MPM Courant number (the FDM's is `time.cfl`).
    #[serde(default = "default_mpm_cfl")]
    pub mpm_cfl: f64,
    /// MPM artificial bulk viscosity.
    #[serde(default)]
    pub bulk_viscosity: BulkViscosityConfig,
    /// The bulk viscosity of the MPM region's gas particles (air and
    /// products), in place of `bulk_viscosity` for them (default `None`:
    /// theirs is `bulk_viscosity`); see the `Mpm` section's.
    #[serde(default)]
    pub fluid_bulk_viscosity: Option<BulkViscosity>,
    /// Pressure near the interface that starts the MPM region, Pa.
    pub activation_pressure: f64,
    /// FDM cells on the donor side of the interface watched for it.
    #[serde(default = "default_activation_cells")]
    pub activation_cells: usize,
    /// Smallest mass of a particle created by the inflow, as a fraction of
    /// an initial air particle's (eqs 45–46): a face's inflow waits in
    /// transit until its 4 or more particles weigh at least this much
    /// each. 0 is the paper's rule (particles every step, at least 4 per
    /// face however small the inflow).
    #[serde(default = "default_min_particle_mass")]
    pub min_particle_mass: f64,
    /// Size the inflow's particles like the initial ones (default true):
    /// m_e (eq 45) at a face is the larger of an initial air particle's
    /// mass and the donor density times an initial particle's volume.
    /// false: m_e is the air particle's mass everywhere (the paper's
    /// rule), which makes ρ/ρ₀ times as many particles of compressed air
    /// and products.
    #[serde(default = "default_true")]
    pub inflow_particle_volume: bool,
    /// Deposit a face's inflow into the air or products particles already
    /// in its first bridge cell (default true), creating particles only
    /// where that cell holds none of the inflow's material, at once: the
    /// inflow is inside the MPM region the step it crosses the interface
    /// (docs/physics/couple/bridge.md). false: `min_particle_mass` batches
    /// (or, with `min_particle_mass: 0.0` and `inflow_particle_volume:
    /// false`, the paper's rule).
    #[serde(default = "default_true")]
    pub inflow_deposit: bool,
    /// Start the MPM region inside the bridge (`Some(k)`, 1 ≤ k < w): it
    /// starts when the shock is k cells into the bridge in some row of
    /// interface faces, each row joins the coupling when its own shock gets
    /// there, and the air and products particles of the row's bridge cells
    /// then take their FDM cell's state. Until a row joins, its donor cell
    /// pushes with its initial state and it takes no inflow. Default
    /// `None`: seed 001's start, `activation_cells` before the interface
    /// (docs/physics/couple/bridge.md, "Starting inside the bridge").
    #[serde(default)]
    pub start_in_bridge: Option<usize>,
}

/// Bridge width when `w` is omitted, cells (the default).
pub const DEFAULT_BRIDGE_WIDTH: usize = 5;

fn default_ppc() -> usize {
    2
}
fn default_mpm_cfl() -> f64 {
    0.4
}
fn default_activation_cells() -> usize {
    3
}
fn default_true() -> bool {
    true
}
fn default_min_particle_mass() -> f64 {
    0.25
}

/// Output fields.
pub const FIELDS: [&str; 6] = crate::CFDMP_FIELDS;

fn spacing(s: &Scene<'_>) -> [f64; 3] {
    let d = &s.domain;
    std::array::from_fn(|a| (d.upper[a] - d.lower[a]) / d.cells[a] as f64)
}

/// `x` rounded to 1e-12 (for coordinates in messages: 0.11 + 0.01 shows
/// as 0.12).
fn tidy(x: f64) -> f64 {
    (x * 1e12).round() / 1e12
}

fn regions(s: &Scene<'_>, cfg: &BridgeConfig) -> Result<BridgeRegions, Problem> {
    let w = cfg.w.unwrap_or(DEFAULT_BRIDGE_WIDTH);
    if w == 0 {
        return Err((
            "pipeline.w".into(),
            format!(
                "w = 0: the bridge must be at least one cell wide (omit w for the default {DEFAULT_BRIDGE_WIDTH})"
            ),
        ));
    }
    let b = |c: &BoxConfig| RegionBox {
        lower: c.lower,
        upper: c.upper,
    };
    let r = BridgeRegions::from_boxes(
        b(&cfg.fdm_region),
        b(&cfg.mpm_region),
        spacing(s),
        brisance_fdm::GHOST,
    )
    .map_err(|e| ("pipeline.mpm_region".to_string(), e.to_string()))?;
    let a = r.axis;
    let d = &s.domain;
    let lo = cfg.fdm_region.lower[a].min(cfg.mpm_region.lower[a]);
    let hi = cfg.fdm_region.upper[a].max(cfg.mpm_region.upper[a]);
    let h = spacing(s);
    let same = |x: f64, y: f64, h: f64| (x - y).abs() <= 1e-6 * h;
    let union_ok = (0..3).all(|k| {
        if k == a {
            same(d.lower[k], lo, h[k]) && same(d.upper[k], hi, h[k])
        } else {
            same(d.lower[k], cfg.fdm_region.lower[k], h[k])
                && same(d.upper[k], cfg.fdm_region.upper[k], h[k])
        }
    });
    if !union_ok {
        return Err((
            "domain".into(),
            format!(
                "the domain ({:?} .. {:?}) must be the union of fdm_region and mpm_region",
                d.lower, d.upper
            ),
        ));
    }
    if r.width != w {
        return Err(("pipeline.w".into(), width_mismatch(s, cfg, &r, w)));
    }
    Ok(r)
}

/// The message for boxes that overlap by `r.width` cells where the config
/// asks for `w`: both widths, and the moves of the interface-side face of
/// either box (the MPM box's first: it keeps the FDM grid, and with it a
/// remap file) that give w cells while keeping the boxes a valid bridge
/// on the same domain.
fn width_mismatch(s: &Scene<'_>, cfg: &BridgeConfig, r: &BridgeRegions, w: usize) -> String {
    let a = r.axis;
    let axis = ["x", "y", "z"][a];
    let h = spacing(s)[a];
    let b = |c: &BoxConfig| RegionBox {
        lower: c.lower,
        upper: c.upper,
    };
    let (fdm, mpm) = (b(&cfg.fdm_region), b(&cfg.mpm_region));
    let span = w as f64 * h;
    // (region, face, new coordinate, the moved boxes).
    let moves = match r.mpm_side {
        Side::High => {
            let (mut m, mut f) = (mpm, fdm);
            m.lower[a] = fdm.upper[a] - span;
            f.upper[a] = mpm.lower[a] + span;
            [
                ("mpm_region", "lower", m.lower[a], fdm, m),
                ("fdm_region", "upper", f.upper[a], f, mpm),
            ]
        }
        Side::Low => {
            let (mut m, mut f) = (mpm, fdm);
            m.upper[a] = fdm.lower[a] + span;
            f.lower[a] = mpm.upper[a] - span;
            [
                ("mpm_region", "upper", m.upper[a], fdm, m),
                ("fdm_region", "lower", f.lower[a], f, mpm),
            ]
        }
    };
    let valid: Vec<String> = moves
        .iter()
        .filter(|(_, _, _, f, m)| {
            BridgeRegions::from_boxes(*f, *m, spacing(s), brisance_fdm::GHOST)
                .is_ok_and(|moved| moved.width == w)
        })
        .map(|(region, face, at, _, _)| format!("{region}'s {face} {axis} to {}", tidy(*at)))
        .collect();
    let fix = match valid.as_slice() {
        [] => String::new(),
        [one] => format!("move {one} or "),
        [first, second, ..] => format!("move {first} (or {second}) or "),
    };
    format!(
        "the fdm_region and mpm_region overlap by {} {} ({} m) along {axis} but w = {w}; {fix}set w: Some({})",
        r.width,
        if r.width == 1 { "cell" } else { "cells" },
        tidy(r.width as f64 * h),
        r.width
    )
}

fn air_gas(s: &Scene<'_>, cfg: &BridgeConfig) -> Result<brisance_eos::IdealGas, Problem> {
    match s.material(&cfg.air).and_then(|m| m.eos) {
        Some(EosModel::IdealGas(g)) => Ok(*g),
        Some(other) => Err((
            "pipeline.air".into(),
            format!(
                "the bridge's air needs an IdealGas (eq 48); `{}` is `{}`",
                cfg.air,
                other.variant()
            ),
        )),
        None => Err((
            "pipeline.air".into(),
            format!("unknown material `{}` or one without an `eos`", cfg.air),
        )),
    }
}

fn is_gas(cfg: &BridgeConfig, name: &str) -> bool {
    name == cfg.air || cfg.products.as_deref() == Some(name)
}

/// The checks of the pipeline's options.
fn validate(s: &Scene<'_>, cfg: &BridgeConfig) -> Result<(), Problem> {
    air_gas(s, cfg)?;
    if let Some(p) = &cfg.products {
        match s.material(p).and_then(|m| m.eos) {
            Some(e) if e.is_gas() => {}
            _ => {
                return Err((
                    "pipeline.products".into(),
                    format!("`{p}` must be a material with a gas EOS (Jwl)"),
                ))
            }
        }
    }
    if cfg.remap.is_some() && cfg.products.is_none() {
        return Err((
            "pipeline.remap".into(),
            "a remapped detonation carries products: set `products`".into(),
        ));
    }
    if let Some(charge) = &cfg.charge {
        if cfg.remap.is_some() {
            return Err((
                "pipeline.charge".into(),
                "give the charge (the run remaps it) or a `remap` file, not both".into(),
            ));
        }
        if cfg.products.is_none() {
            return Err((
                "pipeline.charge".into(),
                "a detonated charge carries products: set `products`".into(),
            ));
        }
        charge
            .validate()
            .map_err(|e| ("pipeline.charge".to_string(), e.to_string()))?;
    }
    if cfg.ppc == 0 || cfg.ppc > 8 {
        return Err((
            "pipeline.ppc".into(),
            format!("ppc = {} must lie in 1..=8", cfg.ppc),
        ));
    }
    match cfg.shape_function {
        ShapeFunction::Linear | ShapeFunction::CpGimp => {}
        ShapeFunction::Gimp => {
            return Err((
                "pipeline.shape_function".into(),
                "Gimp: uGIMP's particle domains keep their first size, which the inflow's deposits outgrow (a half-width past half a cell stops the run); use CpGimp, whose domains follow the particles' volume, or Linear".into(),
            ))
        }
        ShapeFunction::QuadraticBSpline => {
            return Err((
                "pipeline.shape_function".into(),
                "QuadraticBSpline: the bridge's donor cells must reach the halo cell's nodes alone, which a B-spline cannot; use Linear or CpGimp".into(),
            ))
        }
    }
    // The MPM region's bulk viscosity, as the Mpm section checks it.
    cfg.bulk_viscosity
        .check("pipeline.bulk_viscosity")
        .and_then(|()| check_fluid_bulk_viscosity(cfg.fluid_bulk_viscosity))
        .map_err(|e| (e.field, e.message))?;
    if !(cfg.mpm_cfl > 0.0 && cfg.mpm_cfl <= 1.0) {
        return Err((
            "pipeline.mpm_cfl".into(),
            format!("mpm_cfl = {} must lie in (0, 1]", cfg.mpm_cfl),
        ));
    }
    if !(cfg.activation_pressure > 0.0 && cfg.activation_pressure.is_finite()) {
        return Err((
            "pipeline.activation_pressure".into(),
            format!("{} Pa must be positive", cfg.activation_pressure),
        ));
    }
    if let Some(k) = cfg.start_in_bridge {
        let w = cfg.w.unwrap_or(DEFAULT_BRIDGE_WIDTH);
        if k == 0 || k >= w {
            return Err((
                "pipeline.start_in_bridge".into(),
                format!("{k} cells must lie in [1, w) = [1, {w}): the rows start once the shock is that far inside the bridge, short of the FDM region's end"),
            ));
        }
    }
    if !(0.0..=1.0).contains(&cfg.min_particle_mass) {
        return Err((
            "pipeline.min_particle_mass".into(),
            format!("{} must lie in [0, 1]", cfg.min_particle_mass),
        ));
    }
    if let ViscosityConfig::Constant(eta) = cfg.viscosity {
        if !(0.0..=0.25).contains(&eta) {
            return Err((
                "pipeline.viscosity".into(),
                format!("constant η = {eta} must lie in [0, 0.25]"),
            ));
        }
    }
    for (i, r) in s.initial.iter().enumerate() {
        let Some(m) = s.material(r.material) else {
            return Err((
                format!("initial.{i}.material"),
                format!("unknown material `{}`", r.material),
            ));
        };
        if !is_gas(cfg, r.material) && m.model.is_none() {
            return Err((
                format!("initial.{i}.material"),
                format!(
                    "`{}` is neither the air, the products nor a material with a constitutive `model`",
                    r.material
                ),
            ));
        }
    }
    for (i, g) in s.particle_gauges.iter().enumerate() {
        let Some(m) = g.material else { continue };
        if !is_gas(cfg, m) && s.material(m).and_then(|m| m.model).is_none() {
            return Err((
                format!("outputs.particle_gauges.{i}.material"),
                format!(
                    "particle gauge `{}`: `{m}` is not a particle material of the bridge (the air, the products or a material with a constitutive `model`)",
                    g.name
                ),
            ));
        }
    }
    if s.domain.geometry.is_axisymmetric() {
        let r = regions(s, cfg)?;
        if r.axis != 1 {
            return Err((
                "pipeline.mpm_region".into(),
                "on an Axisymmetric grid the fdm_region and mpm_region must be split along z (y), the interface a plane z = const; a cylindrical interface r = const is not supported yet".into(),
            ));
        }
    }
    s.boundaries.check_faces(
        "FdmMpmBridge",
        &["Outflow", "Reflective", "Wall"],
        |bc| {
            match bc {
            BoundaryConfig::ZeroGradient | BoundaryConfig::OutflowOnly => {
                "; its `Outflow` is zero gradient in the FDM region and lets particles leave the MPM region"
            }
            _ => "",
        }
        },
    )?;
    regions(s, cfg).map(|_| ())
}

/// A bridge solver, seen as its solver and its MPM side (what particle
/// gauges follow).
pub trait BridgeSolver: Solver {
    /// The MPM side: the particles of the MPM region.
    fn mpm(&self) -> &MpmSolver;
    /// The solver as the run loop drives it.
    fn into_solver(self: Box<Self>) -> Box<dyn Solver>;
}

impl<E: GasLaw + 'static> BridgeSolver for Cfdmp<E> {
    fn mpm(&self) -> &MpmSolver {
        Cfdmp::mpm(self)
    }
    fn into_solver(self: Box<Self>) -> Box<dyn Solver> {
        self
    }
}

impl IntoSolver for Box<dyn BridgeSolver> {
    fn into_solver(self) -> Box<dyn Solver> {
        BridgeSolver::into_solver(self)
    }
}

/// Builds the coupled solver with the particle sets of its particle
/// gauges ([`MpmSolver::set_particle_gauges`]): each follows the MPM region's particles that start inside its
/// region (tested at (r, z, 0) on an (r, z) grid, as the initial regions
/// are) and, with a `material`, are of that material (a structure, or the
/// `air` or `products` gas).
fn build(s: &Scene<'_>, cfg: &BridgeConfig) -> Result<Box<dyn BridgeSolver>, Problem> {
    let regions = regions(s, cfg)?;
    let air = air_gas(s, cfg)?;
    let air_eos = EosModel::IdealGas(air);
    match &cfg.products {
        Some(p) => {
            let products =
                s.material(p).and_then(|m| m.eos).cloned().ok_or_else(|| {
                    ("pipeline.products".to_string(), format!("`{p}` has no eos"))
                })?;
            let law = ProductsInAir::new(products.clone(), air_eos.clone())
                .map_err(|m| ("pipeline.products".to_string(), m))?;
            build_with(s, cfg, regions, law, |name| {
                if name == p {
                    Some((&products, 1.0))
                } else if name == cfg.air {
                    Some((&air_eos, 0.0))
                } else {
                    None
                }
            })
        }
        None => build_with(s, cfg, regions, air, |name| {
            (name == cfg.air).then_some((&air_eos, 0.0))
        }),
    }
}

fn build_with<'a, E: GasLaw + 'static>(
    s: &'a Scene<'_>,
    cfg: &BridgeConfig,
    regions: BridgeRegions,
    law: E,
    gas_of: impl Fn(&str) -> Option<(&'a EosModel, f64)>,
) -> Result<Box<dyn BridgeSolver>, Problem> {
    use brisance_fdm::GHOST;
    let air = air_gas(s, cfg)?;
    let a = regions.axis;
    // On an (r, z) grid (x = r, y = z) a region is tested at (r, z, 0), the
    // half plane through the axis, as the other pipelines do, and every
    // cell and particle is a ring (docs/physics/couple/bridge.md).
    let geometry = s.domain.geometry;
    let axisymmetric = geometry.is_axisymmetric();
    let plane = move |x: [f64; 3]| {
        if axisymmetric {
            [x[0], x[1], 0.0]
        } else {
            x
        }
    };
    let faces = s.boundaries.faces();
    let inner_fdm = match regions.mpm_side {
        Side::High => 2 * a + 1,
        Side::Low => 2 * a,
    };
    let inner_mpm = match regions.mpm_side {
        Side::High => 2 * a,
        Side::Low => 2 * a + 1,
    };
    // FDM.
    let (fg, offset) = regions.fdm_grid(GHOST);
    let ghost = brisance_fdm::ghost_layers(geometry);
    let level = Level::new(fg.origin, fg.upper(), fg.cells, [1, 1, 1], ghost)
        .map_err(|e| ("pipeline.fdm_region".to_string(), e.to_string()))?;
    let boundaries: [FdmBoundary; 6] = std::array::from_fn(|k| match faces[k].1 {
        BoundaryConfig::Reflective | BoundaryConfig::Wall if k != inner_fdm => {
            FdmBoundary::Reflective
        }
        _ => FdmBoundary::Outflow,
    });
    let mut states = Vec::with_capacity(s.initial.len());
    for (i, r) in s.initial.iter().enumerate() {
        states.push(match gas_of(r.material) {
            Some((eos, y)) => Some((
                primitive_state(eos, r.state).map_err(|m| (format!("initial.{i}.state"), m))?,
                y,
            )),
            None => None,
        });
    }
    let gas_at = |x: [f64; 3]| -> Option<(PrimitiveState, f64)> {
        s.initial
            .iter()
            .zip(&states)
            .rev()
            .find(|(r, st)| st.is_some() && r.region.contains(plane(x)))
            .and_then(|(_, st)| *st)
    };
    for k in 0..fg.cells[2] {
        for j in 0..fg.cells[1] {
            for i in 0..fg.cells[0] {
                let x = fg.cell_centre([i, j, k]);
                if gas_at(x).is_none() {
                    return Err((
                        "initial".into(),
                        format!("FDM cell at {x:?} is in no region of a gas; add an `Everywhere` region of the air first"),
                    ));
                }
            }
        }
    }
    let options = FdmOptions {
        cfl: s.cfl,
        viscosity: match cfg.viscosity {
            ViscosityConfig::Adaptive => ArtificialViscosity::Adaptive,
            ViscosityConfig::Constant(eta) => ArtificialViscosity::Constant(eta),
            ViscosityConfig::Off => ArtificialViscosity::Off,
        },
        geometry,
        ..Default::default()
    };
    let mut fdm = FdmSolver::with_species(law, level, boundaries, options, |x| {
        gas_at(x).expect("checked above")
    })
    .map_err(|e| ("pipeline".to_string(), e.to_string()))?;
    let remapped = match (&cfg.remap, &cfg.charge) {
        (Some(path), _) => Some((
            "pipeline.remap",
            path.clone(),
            Remapped::load(std::path::Path::new(path))
                .map_err(|e| ("pipeline.remap".to_string(), e.to_string()))?,
        )),
        (None, Some(charge)) => Some((
            "pipeline.charge",
            "the charge's remap".to_string(),
            cached_remap(charge, regions.fdm, geometry)
                .map_err(|e| ("pipeline.charge".to_string(), e))?,
        )),
        (None, None) => None,
    };
    if let Some((field, path, r)) = remapped {
        let want = regions.fdm;
        let same_origin =
            (0..3).all(|d| (r.geometry.origin[d] - want.origin[d]).abs() <= 1e-6 * want.spacing[d]);
        if r.geometry.cells != want.cells || !same_origin {
            return Err((
                field.into(),
                format!(
                    "{path} was remapped onto {:?} cells from {:?}; the FDM region has {:?} cells from {:?}",
                    r.geometry.cells, r.geometry.origin, want.cells, want.origin
                ),
            ));
        }
        let mut fields = fdm.conservative_fields();
        for k in 0..want.cells[2] {
            for j in 0..want.cells[1] {
                for i in 0..want.cells[0] {
                    let src = want.linear_index([i, j, k]);
                    let mut g = [i, j, k];
                    g[a] += offset;
                    let dst = fg.linear_index(g);
                    for (f, values) in fields.iter_mut().enumerate() {
                        values[dst] = r.fields[f][src];
                    }
                }
            }
        }
        fdm.set_conservative_fields(&fields)
            .map_err(|e| (field.to_string(), e.to_string()))?;
    }
    // MPM: the air first, then the other modelled materials in name order.
    let structures: Vec<&str> = s
        .materials
        .iter()
        .filter(|m| !is_gas(cfg, m.name) && m.model.is_some())
        .map(|m| m.name)
        .collect();
    let eos_of = |name: &str| s.material(name).and_then(|m| m.eos).cloned();
    let mut models = vec![MaterialModel::Null(NullMaterial::inviscid(
        eos_of(&cfg.air).expect("validated"),
    ))];
    // Products as MPM particles (material 1) when the FDM carries them.
    let products_eos = cfg.products.as_deref().and_then(eos_of);
    if let Some(eos) = &products_eos {
        models.push(MaterialModel::Null(NullMaterial::inviscid(eos.clone())));
    }
    let first_structure = models.len();
    models.extend(
        structures
            .iter()
            .filter_map(|n| s.material(n).and_then(|m| m.model).cloned()),
    );
    let stride = models.iter().map(|m| m.history_len()).max().unwrap_or(0);
    let (mg, _) = regions.mpm_grid();
    let mpm_level = Level::new(mg.origin, mg.upper(), mg.cells, [1, 1, 1], 1)
        .map_err(|e| ("pipeline.mpm_region".to_string(), e.to_string()))?;
    let m = regions.mpm;
    let active: [bool; 3] = std::array::from_fn(|d| m.cells[d] > 1);
    let per: [usize; 3] = std::array::from_fn(|d| if active[d] { cfg.ppc } else { 1 });
    let sub_volume = m.spacing.iter().product::<f64>() / per.iter().product::<usize>() as f64;
    // A particle's volume at `x`: the sub-cell's, or on an (r, z) grid the
    // ring its cross-section sweeps at its centre's radius, 2π r_p A_p
    // (exact for the ring; docs/physics/mpm/axisymmetric.md).
    let volume_at = |x: [f64; 3]| {
        if axisymmetric {
            2.0 * std::f64::consts::PI * x[0] * sub_volume / m.spacing[2]
        } else {
            sub_volume
        }
    };
    // What m_e and V_e (eq 45) are per: a particle, or on an (r, z) grid a
    // metre of its radius (`CfdmpOptions::existing_mass`).
    let per_particle = |x: [f64; 3]| if axisymmetric { x[0] } else { 1.0 };
    let mut particles = Particles::new(stride);
    let history = vec![0.0; stride];
    let (mut air_mass, mut air_count) = (0.0, 0usize);
    for k in 0..m.cells[2] * per[2] {
        for j in 0..m.cells[1] * per[1] {
            for i in 0..m.cells[0] * per[0] {
                let sub = [i, j, k];
                let x: [f64; 3] = std::array::from_fn(|d| {
                    m.origin[d] + (sub[d] as f64 + 0.5) / per[d] as f64 * m.spacing[d]
                });
                let Some((idx, r)) = s
                    .initial
                    .iter()
                    .enumerate()
                    .rev()
                    .find(|(_, r)| r.region.contains(plane(x)))
                else {
                    continue;
                };
                let sub_volume = volume_at(x);
                let init = if let Some((st, y)) = states[idx] {
                    let p = st.pressure;
                    let products = y > 0.5 && products_eos.is_some();
                    let (e, material) = match (&products_eos, products) {
                        (Some(eos), true) => (
                            eos.specific_internal_energy(st.density, p)
                                .map_err(|e| (format!("initial.{idx}.state"), e.to_string()))?,
                            MaterialId(1),
                        ),
                        _ => {
                            air_mass += st.density * sub_volume / per_particle(x);
                            air_count += 1;
                            (
                                air.specific_internal_energy(st.density, p)
                                    .map_err(|e| (format!("initial.{idx}.state"), e.to_string()))?,
                                MaterialId(0),
                            )
                        }
                    };
                    ParticleInit {
                        position: x,
                        velocity: st.velocity,
                        mass: st.density * sub_volume,
                        volume: sub_volume,
                        stress: [-p, -p, -p, 0.0, 0.0, 0.0],
                        temperature: if products {
                            293.15
                        } else {
                            air.temperature(st.density, e)
                        },
                        specific_internal_energy: e,
                        material,
                        ..Default::default()
                    }
                } else {
                    let id = first_structure
                        + structures
                            .iter()
                            .position(|n| *n == r.material)
                            .expect("validated");
                    let model = &models[id];
                    let t = r.state.temperature.unwrap_or(293.15);
                    let e = match (model.eos(), r.state.specific_internal_energy) {
                        (_, Some(e)) => e,
                        (Some(eos), None) => {
                            eos.specific_internal_energy_from_temperature(r.state.density, t)
                        }
                        (None, None) => 0.0,
                    };
                    ParticleInit {
                        position: x,
                        velocity: r.state.velocity,
                        mass: r.state.density * sub_volume,
                        volume: sub_volume,
                        temperature: t,
                        specific_internal_energy: e,
                        material: MaterialId(id as u16),
                        ..Default::default()
                    }
                };
                particles
                    .push(&init, &history)
                    .map_err(|e| ("initial".to_string(), e.to_string()))?;
            }
        }
    }
    if air_count == 0 {
        return Err((
            "initial".into(),
            "the MPM region holds no air particle: the bridge needs air at the interface".into(),
        ));
    }
    // The particle gauges' sets, by the particles' identities (their
    // order here).
    let mut particle_gauges = Vec::with_capacity(s.particle_gauges.len());
    for (i, g) in s.particle_gauges.iter().enumerate() {
        let path = format!("outputs.particle_gauges.{i}");
        let material = match g.material {
            None => None,
            Some(name) if name == cfg.air => Some(MaterialId(0)),
            Some(name) if products_eos.is_some() && cfg.products.as_deref() == Some(name) => {
                Some(MaterialId(1))
            }
            Some(name) => Some(
                structures
                    .iter()
                    .position(|n| *n == name)
                    .map(|k| MaterialId((first_structure + k) as u16))
                    .ok_or_else(|| {
                        (
                            format!("{path}.material"),
                            format!(
                                "particle gauge `{}`: `{name}` has no particles in the bridge's MPM region (the air, the products or a material with a constitutive `model`)",
                                g.name
                            ),
                        )
                    })?,
            ),
        };
        let set = ParticleSet::select(&particles, |x, m| {
            g.region.contains(plane(x)) && (material.is_none() || material == Some(m))
        });
        if set.is_empty() {
            let of = g
                .material
                .map_or(String::new(), |m| format!(" of material `{m}`"));
            return Err((
                format!("{path}.region"),
                format!(
                    "particle gauge `{}`: no particle{of} of the MPM region starts inside its region",
                    g.name
                ),
            ));
        }
        particle_gauges.push(set);
    }
    let boundary = |k: usize| match faces[k].1 {
        _ if k == inner_mpm => GridBoundary::Outflow,
        BoundaryConfig::Wall => GridBoundary::Fixed,
        BoundaryConfig::Reflective => GridBoundary::Symmetry,
        _ => GridBoundary::Outflow,
    };
    let mut mpm = MpmSolver::new(
        mpm_level,
        models,
        particles,
        MpmOptions {
            shape: cfg.shape_function,
            scheme: UpdateScheme::Musl,
            cfl: cfg.mpm_cfl,
            boundaries: std::array::from_fn(boundary),
            bulk_viscosity: cfg.bulk_viscosity.option(),
            fluid_bulk_viscosity: cfg.fluid_bulk_viscosity,
            geometry,
            ..Default::default()
        },
    )
    .map_err(|e| ("pipeline".to_string(), e.to_string()))?;
    mpm.set_particle_gauges(particle_gauges);
    let mut coupled = Cfdmp::new(
        regions,
        fdm,
        mpm,
        GHOST,
        CfdmpOptions {
            air: MaterialId(0),
            products: products_eos.as_ref().map(|_| MaterialId(1)),
            gamma: air.gamma,
            existing_mass: air_mass / air_count as f64,
            activation_pressure: cfg.activation_pressure,
            activation_cells: cfg.activation_cells,
            min_particle_mass: cfg.min_particle_mass,
            existing_volume: if cfg.inflow_particle_volume {
                // V_e of a particle at radius r is this times r on an
                // (r, z) grid.
                volume_at([1.0, 0.0, 0.0])
            } else {
                0.0
            },
            deposit: cfg.inflow_deposit,
            donor_rings: per[0],
            start_in_bridge: cfg.start_in_bridge,
        },
    )
    .map_err(|m| ("pipeline".to_string(), m))?;
    // The particle updates spread over the ranks of the run
    // (docs/cluster.md); nothing changes on one rank.
    coupled.distribute(brisance_grid::comm::world());
    Ok(Box::new(coupled))
}

/// A one-paragraph description (for `check`).
fn describe(s: &Scene<'_>, cfg: &BridgeConfig) -> String {
    match regions(s, cfg) {
        Ok(r) => format!(
            "FdmMpmBridge (seed 001 §3): FDM {:?} cells, MPM {:?} cells, bridge w = {} cells along {}, \
             air `{}`{}, {} particles per cell per direction, {:?} shape functions, bulk viscosity {}, \
             MPM starts at {:e} Pa near the interface{}",
            r.fdm.cells,
            r.mpm.cells,
            r.width,
            ["x", "y", "z"][r.axis],
            cfg.air,
            cfg.products
                .as_ref()
                .map(|p| format!(", products `{p}`"))
                .unwrap_or_default(),
            cfg.ppc,
            cfg.shape_function,
            describe_bulk_viscosity(&cfg.bulk_viscosity, cfg.fluid_bulk_viscosity),
            cfg.activation_pressure,
            cfg.remap
                .as_ref()
                .map(|p| format!(", FDM initial state from {p}"))
                .unwrap_or_default()
        ),
        Err((_, m)) => format!("FdmMpmBridge: {m}"),
    }
}

impl PipelineSpec for BridgeConfig {
    const INFO: PipelineInfo = PipelineInfo {
        name: "FdmMpmBridge",
        summary: "coupled FDM-MPM (CFDMP): FDM far field, MPM near structures, a bridge region w cells wide, activation by the shock's arrival, optional remapped 1D detonation (seed 001 §3)",
        example: "FdmMpmBridge(fdm_region: (lower: (-0.18, 0.0, 0.0), upper: (0.12, 0.5, 0.002)), mpm_region: (lower: (0.11, 0.0, 0.0), upper: (0.16, 0.5, 0.002)), air: \"air\", products: Some(\"tnt\"), activation_pressure: 1.2e5)",
        docs: "docs/physics/couple/bridge.md",
    };
    type Solver = Box<dyn BridgeSolver>;

    /// The FDM's fields, Courant limit (`time.cfl` is the FDM's; the
    /// MPM's is `mpm_cfl`) and ghost layers; one patch, written and
    /// checkpointed whole.
    fn limits(&self, _geometry: Geometry) -> PipelineLimits {
        PipelineLimits {
            fields: &FIELDS,
            max_cfl: brisance_fdm::MAX_CFL,
            ghost: brisance_fdm::GHOST,
            node_fields: &[],
            patch_pieces: false,
            patch_checkpoints: false,
            particle_gauges: true,
            heat_conduction: false,
        }
    }

    fn validate(&self, scene: &Scene<'_>) -> Result<(), FieldError> {
        validate(scene, self).map_err(|(f, m)| FieldError::new(f, m))
    }

    fn build(&self, scene: &Scene<'_>) -> Result<Box<dyn BridgeSolver>, FieldError> {
        validate(scene, self)
            .and_then(|()| build(scene, self))
            .map_err(|(f, m)| FieldError::new(f, m))
    }

    fn describe(&self, scene: &Scene<'_>) -> String {
        describe(scene, self)
    }
}

/// Registers the coupled FDM–MPM as the `FdmMpmBridge` pipeline: a config
/// writes `pipeline: FdmMpmBridge(...)`, and the composer checks, builds
/// and describes it through [`PipelineSpec`].
pub fn register(registry: &mut brisance_scene::plugin::PipelineRegistry) {
    registry.register(brisance_scene::plugin::PipelinePlugin::of::<BridgeConfig>());
}

#[cfg(test)]
mod tests;
