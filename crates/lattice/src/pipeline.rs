//! The `Lattice` pipeline's section of a scenario (its config schema), its
//! validation against the scenario and its builder ([`PipelineSpec`] for
//! [`LatticeConfig`]; the composer hands it the scenario's shared parts as
//! a [`Scene`]).
//!
//! The lattice covers the scenario's `domain` with nodes at
//! `lower + k h` (k = 0, 1, … while inside `upper`) on the active axes of
//! `dimension`; a node is solid with the material of the first `initial`
//! region that contains it (its `state.velocity` is the node's initial
//! velocity) and exterior (a ghost at the surroundings' state) otherwise.
//! Each region's `material` names an entry of the pipeline's `materials`,
//! which holds the lattice parameters (Young's modulus, conductivity,
//! damping, plasticity, fracture); the Mie–Grüneisen EOS of seed 003
//! eqs 12–14 is the scenario material's `MieGruneisenThermal` EOS (e.g. the
//! library's `hmx_crystal`, `estane`).
//!
//! A material with an `arrhenius` law regresses where it meets the fluid
//! (seed 003 §2.4, [`SurfaceRegression`]); `regression` says which
//! exterior nodes are fluid. A `pack` replaces the material of the solid
//! nodes by a crystal/binder image (PGM or PNG, one node per pixel) or a random
//! pack of discs ([`random_disc_pack`]).

use std::collections::BTreeMap;

use brisance_eos::EosModel;
use brisance_grid::Shape as Region;
use brisance_scene::{FieldError, PipelineInfo, PipelineLimits, PipelineSpec, Scene};
use serde::{Deserialize, Serialize};

use crate::{
    area_fraction, random_disc_pack, read_image, Arrhenius, Damping, Dim, Geometry, GrayImage,
    Hysteretic, Integrator, LatticeMaterial, MsdmLattice, MsdmOptions, Plasticity,
    SurfaceRegression, Surroundings,
};

/// Options of the Lattice pipeline.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LatticeConfig {
    /// `One`, `Two` (depth h) or `Three`.
    pub dimension: Dim,
    /// Lattice spacing h, m.
    pub spacing: f64,
    /// Time integrator (default `VelocityVerlet`).
    #[serde(default = "default_integrator")]
    pub integrator: Integrator,
    /// Diagonal springs (eq 10b f_d; default false, as in seed 003).
    #[serde(default)]
    pub diagonals: bool,
    /// Lattice parameters of each material the regions name.
    pub materials: BTreeMap<String, LatticeMaterialConfig>,
    /// Surroundings' temperature (K) and conductivity (W/(m·K)) for the
    /// ghost nodes (default 300 K, adiabatic).
    #[serde(default = "default_surroundings")]
    pub surroundings: Surroundings,
    /// Initial temperature of the solid nodes, K (default 300).
    #[serde(default = "default_temperature")]
    pub initial_temperature: f64,
    /// Energy equation on (default true).
    #[serde(default = "default_true")]
    pub thermal: bool,
    /// Safety factor on the explicit stable step (default 0.8).
    #[serde(default = "default_safety")]
    pub safety_factor: f64,
    /// Step of the implicit integrators, s (default: the explicit limit).
    #[serde(default)]
    pub time_step: Option<f64>,
    /// Linear solver of the implicit integrators: `Direct` (sparse LU,
    /// default) or `Iterative` (BiCGSTAB to a relative residual of 1e-10).
    #[serde(default)]
    pub linear_solver: crate::LinearSolver,
    /// Prescribed node velocities.
    #[serde(default)]
    pub boundaries: Vec<LatticeBoundaryConfig>,
    /// Momentum equation on (default true). Off, the lattice only
    /// regresses (the propellant burns of seed 003 §3.1); `thermal` must
    /// then be false.
    #[serde(default = "default_true")]
    pub mechanics: bool,
    /// Surface regression settings (used when a material has `arrhenius`;
    /// default: every exterior node is fluid, the seed's normal rule).
    #[serde(default)]
    pub regression: Option<RegressionConfig>,
    /// Heterogeneous pack replacing the material of the solid nodes.
    #[serde(default)]
    pub pack: Option<PackConfig>,
}

/// Surface regression settings (seed 003 §2.4).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RegressionConfig {
    /// Regions whose exterior nodes are fluid; the other exterior nodes are
    /// inert walls. Default: every exterior node is fluid.
    #[serde(default)]
    pub fluid: Option<Vec<Region>>,
    /// Radius of the surface-normal estimate in spacings (default 1: the
    /// seed's rule, away from the axial fluid neighbours).
    #[serde(default = "default_normal_radius")]
    pub normal_radius: f64,
    /// Largest regression per step in spacings (default 0.05).
    #[serde(default = "default_step_fraction")]
    pub step_fraction: f64,
}

impl Default for RegressionConfig {
    fn default() -> Self {
        Self {
            fluid: None,
            normal_radius: default_normal_radius(),
            step_fraction: default_step_fraction(),
        }
    }
}

fn default_normal_radius() -> f64 {
    1.0
}
fn default_step_fraction() -> f64 {
    0.05
}

/// A heterogeneous pack (2D): the material of every solid node from an
/// image pixel or from a random pack of discs.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub enum PackConfig {
    /// A PGM (`P5` or `P2`) or PNG image with one pixel per node of the domain
    /// (width × height = the node counts along x × y; row 0 at the top):
    /// `crystal` where the grey level is at least `threshold`, `binder`
    /// elsewhere. `path` is relative to the working directory.
    Image {
        /// Image file.
        path: String,
        /// Grey level from which a pixel is crystal.
        threshold: u16,
        /// Material of the bright pixels.
        crystal: String,
        /// Material of the dark pixels.
        binder: String,
    },
    /// Discs of one diameter at a mass fraction, placed at random in the
    /// domain's x–y box taken as periodic (RocPack-like; see
    /// `docs/physics/lattice/packs.md`).
    RandomDiscs {
        /// Disc diameter, m.
        diameter: f64,
        /// Mass fraction of the particles, in (0, 1).
        mass_fraction: f64,
        /// Material of the discs.
        particle: String,
        /// Material between the discs.
        binder: String,
        /// Seed of the random stream.
        seed: u64,
    },
}

/// Lattice parameters of a material (seed 003 §2.1); its EOS is the
/// scenario material's.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LatticeMaterialConfig {
    /// Young's modulus E, Pa (springs k = E|ξ|).
    pub young: f64,
    /// Thermal conductivity, W/(m·K) (default 0).
    #[serde(default)]
    pub conductivity: f64,
    /// Spring/dashpot arrangement (default `None`).
    #[serde(default)]
    pub damping: Damping,
    /// Hysteretic damping (default none).
    #[serde(default)]
    pub hysteretic: Option<Hysteretic>,
    /// Plastic springs (default none).
    #[serde(default)]
    pub plasticity: Option<Plasticity>,
    /// Fracture strain (default: unbreakable).
    #[serde(default)]
    pub fracture_strain: Option<f64>,
    /// Perpendicular corrective modulus, Pa (default 0: off).
    #[serde(default)]
    pub perpendicular_modulus: f64,
    /// Chemical enthalpy h_k, J/kg (default 0).
    #[serde(default)]
    pub enthalpy: f64,
    /// Arrhenius pyrolysis law (seed 003 §2.4; default: inert).
    #[serde(default)]
    pub arrhenius: Option<Arrhenius>,
}

/// The lattice material `name`: the pipeline's parameters with the
/// scenario material's Mie–Grüneisen EOS.
fn lattice_material(
    s: &Scene<'_>,
    name: &str,
    m: &LatticeMaterialConfig,
) -> Result<LatticeMaterial, FieldError> {
    let eos = match s.material(name).and_then(|m| m.eos) {
        Some(EosModel::MieGruneisenThermal(e)) => *e,
        Some(other) => {
            return Err(FieldError::new(
                format!("materials.{name}.eos"),
                format!(
                    "the Lattice pipeline needs a `MieGruneisenThermal` EOS (seed 003 eqs 12–14), `{name}` has {}",
                    brisance_core::Eos::name(other)
                ),
            ))
        }
        None => {
            return Err(FieldError::new(
                format!("materials.{name}"),
                format!("`{name}` is in pipeline.materials but not in the scenario's materials"),
            ))
        }
    };
    let mat = LatticeMaterial {
        name: name.to_string(),
        young: m.young,
        eos,
        conductivity: m.conductivity,
        damping: m.damping,
        hysteretic: m.hysteretic,
        plasticity: m.plasticity,
        fracture_strain: m.fracture_strain,
        perpendicular_modulus: m.perpendicular_modulus,
        enthalpy: m.enthalpy,
    };
    mat.validate()
        .map_err(|e| FieldError::new(format!("pipeline.materials.{name}"), e))?;
    if let Some(a) = &m.arrhenius {
        let field = format!("pipeline.materials.{name}.arrhenius");
        a.validate(&field).map_err(|e| FieldError::new(field, e))?;
    }
    Ok(mat)
}

fn default_integrator() -> Integrator {
    Integrator::VelocityVerlet
}
fn default_surroundings() -> Surroundings {
    Surroundings {
        temperature: 300.0,
        conductivity: 0.0,
    }
}
fn default_temperature() -> f64 {
    300.0
}
fn default_true() -> bool {
    true
}
fn default_safety() -> f64 {
    0.8
}

/// Prescribed velocity of the solid nodes in a region (reference
/// positions); the velocity is held for the whole run, on every axis or
/// only on the axes listed in `axes`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LatticeBoundaryConfig {
    /// Region.
    pub region: Region,
    /// Velocity, m/s (`(0, 0, 0)` fixes the nodes). Only the components of
    /// the held axes are used.
    pub velocity: [f64; 3],
    /// Held axes, e.g. `Some(["x"])` for a slip wall normal to x (u_x
    /// held, the other components free). Default: every axis (no slip).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub axes: Option<Vec<String>>,
}

impl LatticeBoundaryConfig {
    /// The held axes as a bit mask (bit a for axis a) for a lattice of
    /// `dim` axes; `index` is the boundary's position in
    /// `pipeline.boundaries`, used in the error's field path.
    pub fn held_mask(&self, index: usize, dim: usize) -> Result<u8, FieldError> {
        let field = format!("pipeline.boundaries.{index}.axes");
        for (a, v) in self.velocity.iter().enumerate() {
            if !v.is_finite() {
                return Err(FieldError::new(
                    format!("pipeline.boundaries.{index}.velocity"),
                    format!("component {a} is {v}, expected a finite value"),
                ));
            }
        }
        let all = ((1u16 << dim) - 1) as u8;
        let Some(axes) = &self.axes else {
            return Ok(all);
        };
        if axes.is_empty() {
            return Err(FieldError::new(
                field,
                "empty list: name at least one of \"x\", \"y\", \"z\" (or leave `axes` out \
                 to hold every axis)",
            ));
        }
        let mut mask = 0u8;
        for name in axes {
            let a = match name.as_str() {
                "x" => 0,
                "y" => 1,
                "z" => 2,
                _ => {
                    return Err(FieldError::new(
                        field,
                        format!("`{name}` is not an axis, expected \"x\", \"y\" or \"z\""),
                    ))
                }
            };
            if a >= dim {
                return Err(FieldError::new(
                    field,
                    format!("axis `{name}` is not one of the lattice's {dim} axes"),
                ));
            }
            if mask & (1 << a) != 0 {
                return Err(FieldError::new(
                    field,
                    format!("axis `{name}` is listed twice"),
                ));
            }
            mask |= 1 << a;
        }
        Ok(mask)
    }
}

/// Nodes per axis covering [lower, upper] at spacing h.
fn node_counts(s: &Scene<'_>, cfg: &LatticeConfig) -> [usize; 3] {
    let mut n = [1usize; 3];
    for (a, na) in n.iter_mut().enumerate().take(cfg.dimension.count()) {
        let len = s.domain.upper[a] - s.domain.lower[a];
        // Saturating: a spacing tiny beside the domain gives usize::MAX,
        // which validation refuses as too many nodes.
        *na = ((len / cfg.spacing * (1.0 + 1e-12)).floor() as usize).saturating_add(1);
    }
    n
}

/// Checks the pipeline; errors carry the field path.
fn check(s: &Scene<'_>, cfg: &LatticeConfig) -> Result<(), FieldError> {
    if !(cfg.spacing > 0.0 && cfg.spacing.is_finite()) {
        return Err(FieldError::new(
            "pipeline.spacing",
            format!("spacing must be a finite value > 0 m, got {}", cfg.spacing),
        ));
    }
    let n = node_counts(s, cfg);
    let total = n
        .iter()
        .fold(1usize, |p, k| p.saturating_mul(k.saturating_add(2)));
    if total > 200_000_000 {
        return Err(FieldError::new(
            "pipeline.spacing",
            format!(
                "spacing {} m gives {n:?} nodes over the domain, more than 2e8",
                cfg.spacing
            ),
        ));
    }
    if !s.cell_fields.is_empty() {
        return Err(FieldError::new(
            "outputs.fields",
            "the Lattice pipeline writes its nodes as particles and has no cell fields: \
             write `fields: []` (point gauges can sample the node fields)",
        ));
    }
    for (name, m) in &cfg.materials {
        lattice_material(s, name, m)?;
    }
    if !cfg.mechanics && cfg.thermal {
        return Err(FieldError::new(
            "pipeline.mechanics",
            "`mechanics: false` needs `thermal: false` (the energy equation uses the mechanical \
             volume update)",
        ));
    }
    if let Some(r) = &cfg.regression {
        if !(1.0..=16.0).contains(&r.normal_radius) {
            return Err(FieldError::new(
                "pipeline.regression.normal_radius",
                format!("{} spacings, expected a value in [1, 16]", r.normal_radius),
            ));
        }
        if !(r.step_fraction > 0.0 && r.step_fraction <= 1.0) {
            return Err(FieldError::new(
                "pipeline.regression.step_fraction",
                format!("{}, expected a value in (0, 1]", r.step_fraction),
            ));
        }
    }
    if let Some(p) = &cfg.pack {
        if cfg.dimension != Dim::Two {
            return Err(FieldError::new(
                "pipeline.pack",
                format!("packs are 2D; `dimension` is {:?}", cfg.dimension),
            ));
        }
        let (names, field): (Vec<&String>, &str) = match p {
            PackConfig::Image {
                crystal, binder, ..
            } => (vec![crystal, binder], "Image"),
            PackConfig::RandomDiscs {
                particle,
                binder,
                diameter,
                mass_fraction,
                ..
            } => {
                if !(*mass_fraction > 0.0 && *mass_fraction < 1.0) {
                    return Err(FieldError::new(
                        "pipeline.pack.mass_fraction",
                        format!("{mass_fraction}, expected a value in (0, 1)"),
                    ));
                }
                if !(*diameter > 0.0 && diameter.is_finite()) {
                    return Err(FieldError::new(
                        "pipeline.pack.diameter",
                        format!("{diameter} m, expected a finite value > 0"),
                    ));
                }
                (vec![particle, binder], "RandomDiscs")
            }
        };
        for (k, name) in names.into_iter().enumerate() {
            if !cfg.materials.contains_key(name) {
                let which = match (field, k) {
                    ("Image", 0) => "crystal",
                    ("RandomDiscs", 0) => "particle",
                    _ => "binder",
                };
                return Err(FieldError::new(
                    format!("pipeline.pack.{which}"),
                    format!("`{name}` has no entry in pipeline.materials"),
                ));
            }
        }
    }
    for (i, b) in cfg.boundaries.iter().enumerate() {
        b.held_mask(i, cfg.dimension.count())?;
    }
    for (i, r) in s.initial.iter().enumerate() {
        if !cfg.materials.contains_key(r.material) {
            return Err(FieldError::new(
                format!("initial.{i}.material"),
                format!(
                    "`{}` has no entry in pipeline.materials (known: {})",
                    r.material,
                    cfg.materials
                        .keys()
                        .map(|k| format!("`{k}`"))
                        .collect::<Vec<_>>()
                        .join(", ")
                ),
            ));
        }
    }
    Ok(())
}

/// Builds the lattice.
fn build_lattice(s: &Scene<'_>, cfg: &LatticeConfig) -> Result<MsdmLattice, FieldError> {
    check(s, cfg)?;
    let names: Vec<&String> = cfg.materials.keys().collect();
    let materials: Vec<LatticeMaterial> = cfg
        .materials
        .iter()
        .map(|(k, m)| lattice_material(s, k, m))
        .collect::<Result<_, _>>()?;
    let n = node_counts(s, cfg);
    let h = cfg.spacing;
    let lower = s.domain.lower;
    let d = cfg.dimension.count();
    let position = |ix: usize, iy: usize, iz: usize| -> [f64; 3] {
        let k = [ix, iy, iz];
        let mut p = [0.0; 3];
        for a in 0..3 {
            p[a] = if a < d {
                lower[a] + k[a] as f64 * h
            } else {
                0.5 * (lower[a] + s.domain.upper[a])
            };
        }
        p
    };
    let index_of = |name: &str| names.iter().position(|m| *m == name).unwrap_or(0) as u16;
    let pack = pack_materials(s, cfg, n, &index_of)?;
    let geom = Geometry::new(cfg.dimension, n, h, cfg.diagonals, |ix, iy, iz| {
        s.region_of(position(ix, iy, iz)).map(|r| match &pack {
            Some(m) => m[ix + n[0] * iy],
            None => index_of(s.initial[r].material),
        })
    })
    .with_origin(position(0, 0, 0));
    let options = MsdmOptions {
        integrator: cfg.integrator,
        surroundings: cfg.surroundings,
        initial_temperature: cfg.initial_temperature,
        thermal: cfg.thermal,
        linear_solver: cfg.linear_solver,
        solver_tolerance: 1e-10,
        safety_factor: cfg.safety_factor,
        time_step: cfg.time_step,
    };
    let mut lat = MsdmLattice::new(geom, materials, options)
        .map_err(|e| FieldError::new("pipeline", e.to_string()))?;
    lat.mechanics = cfg.mechanics;
    let laws: Vec<Option<Arrhenius>> = cfg.materials.values().map(|m| m.arrhenius).collect();
    if laws.iter().any(Option::is_some) {
        let rc = cfg.regression.clone().unwrap_or_default();
        let mut reg = SurfaceRegression::new(&lat, laws, rc.normal_radius, rc.step_fraction)
            .map_err(|e| FieldError::new("pipeline.regression", e.to_string()))?;
        if let Some(fluid) = &rc.fluid {
            let g = lat.geom.clone();
            reg.set_walls(&lat, |i| {
                let p = g.reference_position(i);
                !fluid.iter().any(|r| r.contains(p))
            });
        }
        lat.set_regression(reg)
            .map_err(|e| FieldError::new("pipeline.regression", e.to_string()))?;
    }
    // Initial velocities and prescribed nodes.
    for i in 0..lat.len() {
        if !lat.geom.is_solid(i) {
            continue;
        }
        let p = lat.geom.reference_position(i);
        if let Some(r) = s.region_of(p) {
            for a in 0..d {
                lat.u[a][i] = s.initial[r].state.velocity[a];
            }
        }
        if let Some((k, b)) = cfg
            .boundaries
            .iter()
            .enumerate()
            .find(|(_, b)| b.region.contains(p))
        {
            let mask = b.held_mask(k, d)?;
            lat.prescribed[i] = true;
            lat.held_axes[i] = mask;
            for a in (0..d).filter(|a| mask & (1 << a) != 0) {
                lat.u[a][i] = b.velocity[a];
            }
        }
    }
    lat.mark_modified();
    // Spread over the ranks of the run (docs/cluster.md): too few planes
    // at the spacing is an error at its field.
    lat.distribute(brisance_grid::comm::world())
        .map_err(|e| FieldError::new("pipeline.spacing".to_string(), e.to_string()))?;
    Ok(lat)
}

/// Material index of every node of the `n[0]` × `n[1]` solid block from
/// the pack, row-major from the bottom row (`None` without a pack).
fn pack_materials(
    s: &Scene<'_>,
    cfg: &LatticeConfig,
    n: [usize; 3],
    index_of: &dyn Fn(&str) -> u16,
) -> Result<Option<Vec<u16>>, FieldError> {
    let Some(pack) = &cfg.pack else {
        return Ok(None);
    };
    match pack {
        PackConfig::Image {
            path,
            threshold,
            crystal,
            binder,
        } => {
            let bytes = std::fs::read(path).map_err(|e| {
                FieldError::new("pipeline.pack.path", format!("cannot read `{path}`: {e}"))
            })?;
            let img: GrayImage =
                read_image(&bytes).map_err(|e| FieldError::new("pipeline.pack.path", e))?;
            if img.width != n[0] || img.height != n[1] {
                return Err(FieldError::new(
                    "pipeline.pack.path",
                    format!(
                        "`{path}` is {} × {} pixels, the lattice {} × {} nodes (one node per pixel: \
                         domain extent / spacing + 1)",
                        img.width, img.height, n[0], n[1]
                    ),
                ));
            }
            let (c, b) = (index_of(crystal), index_of(binder));
            let mut m = Vec::with_capacity(n[0] * n[1]);
            for iy in 0..n[1] {
                for ix in 0..n[0] {
                    m.push(if img.at_lattice(ix, iy) >= *threshold {
                        c
                    } else {
                        b
                    });
                }
            }
            Ok(Some(m))
        }
        PackConfig::RandomDiscs {
            diameter,
            mass_fraction,
            particle,
            binder,
            seed,
        } => {
            let rho = |name: &str| -> Result<f64, FieldError> {
                match s.material(name).and_then(|m| m.eos) {
                    Some(EosModel::MieGruneisenThermal(e)) => Ok(e.rho0),
                    _ => Err(FieldError::new(
                        format!("materials.{name}.eos"),
                        "a pack material needs a `MieGruneisenThermal` EOS",
                    )),
                }
            };
            let phi = area_fraction(*mass_fraction, rho(particle)?, rho(binder)?);
            let width = (n[0] - 1) as f64 * cfg.spacing;
            let height = (n[1] - 1) as f64 * cfg.spacing;
            // The periodic box is the node span plus one spacing, so the
            // pattern repeats with the lattice period.
            let disc = random_disc_pack(
                width + cfg.spacing,
                height + cfg.spacing,
                *diameter,
                phi,
                *seed,
            )
            .map_err(|e| FieldError::new("pipeline.pack", e))?;
            let inside = disc.rasterise(n[0], n[1], cfg.spacing);
            let (p, b) = (index_of(particle), index_of(binder));
            Ok(Some(
                inside.iter().map(|&k| if k { p } else { b }).collect(),
            ))
        }
    }
}

/// One paragraph for `check`.
fn description(s: &Scene<'_>, cfg: &LatticeConfig) -> String {
    let n = node_counts(s, cfg);
    format!(
        "scenario `{}`: Lattice pipeline (mass–spring–damper lattice, seed 003), {:?}, spacing {} m, \
         {n:?} nodes, {:?}, diagonals {}, energy equation {}, mechanics {}, surface regression {}, pack {}\n  materials: {}\n  time: to {} s",
        s.name,
        cfg.dimension,
        cfg.spacing,
        cfg.integrator,
        cfg.diagonals,
        cfg.thermal,
        cfg.mechanics,
        cfg.materials.values().any(|m| m.arrhenius.is_some()),
        match &cfg.pack {
            None => "none",
            Some(PackConfig::Image { .. }) => "image",
            Some(PackConfig::RandomDiscs { .. }) => "random discs",
        },
        cfg.materials
            .keys()
            .map(|k| format!("`{k}`"))
            .collect::<Vec<_>>()
            .join(", "),
        s.end_time
    )
}

impl PipelineSpec for LatticeConfig {
    const INFO: PipelineInfo = PipelineInfo {
        name: "Lattice",
        summary: "thermo-mechanical mass-spring-damper lattice (MSDM): springs k = E|ξ| with damping, plasticity and fracture, energy equation with Mie-Grüneisen heating and conduction; explicit Euler, Verlet, implicit Euler, implicit RK2 (seed 003 ch. 2)",
        example: "Lattice(dimension: Two, spacing: 2e-5, materials: {\"hmx\": (young: 25.325e9, conductivity: 0.4)})",
        docs: "docs/physics/lattice/model.md",
    };
    type Solver = MsdmLattice;

    /// One ghost layer (the node grid's), no patches; the step's own
    /// stability limit is not a Courant number.
    fn limits(&self, _geometry: brisance_core::Geometry) -> PipelineLimits {
        PipelineLimits {
            fields: &MsdmLattice::FIELDS,
            max_cfl: 1.0,
            ghost: 1,
            node_fields: &[],
            patch_pieces: false,
            patch_checkpoints: false,
            particle_gauges: false,
            heat_conduction: false,
        }
    }

    /// The lattice is a 3D network of bonds: no (r, z) form.
    fn unsupported(&self, geometry: brisance_core::Geometry) -> Option<&'static str> {
        geometry.is_axisymmetric().then_some(
            "the MSDM lattice is a 3D network of bonds with no axisymmetric form; run the Lattice pipeline on a 3D Cartesian grid",
        )
    }

    fn validate(&self, scene: &Scene<'_>) -> Result<(), FieldError> {
        check(scene, self)
    }

    /// Builds the lattice and spreads it over the ranks of the run
    /// (docs/cluster.md).
    fn build(&self, scene: &Scene<'_>) -> Result<MsdmLattice, FieldError> {
        build_lattice(scene, self)
    }

    fn describe(&self, scene: &Scene<'_>) -> String {
        description(scene, self)
    }
}

/// Registers the lattice as the `Lattice` pipeline: a config writes
/// `pipeline: Lattice(dimension: Two, spacing: 2e-5, materials: {...})`,
/// and the composer checks, builds and describes it through
/// [`PipelineSpec`].
pub fn register(registry: &mut brisance_scene::plugin::PipelineRegistry) {
    registry.register(brisance_scene::plugin::PipelinePlugin::of::<LatticeConfig>());
}

#[cfg(test)]
mod tests {
    use brisance_eos::IdealGas;
    use brisance_scene::{Domain, OwnedScene, StateConfig};

    use super::*;
    use crate::cases::inert_eos;

    /// The registration reads its own example into a section equal to
    /// the one serde reads, under the name of [`PipelineSpec::INFO`].
    #[test]
    fn the_registered_example_reads_as_the_section() {
        let mut r = brisance_scene::plugin::PipelineRegistry::new();
        register(&mut r);
        let p = r.get("Lattice").expect("registered");
        assert_eq!(p.info, LatticeConfig::INFO);
        let args = p.info.example.strip_prefix("Lattice").unwrap();
        let (section, params) = (p.parse)(args).unwrap();
        let cfg: &LatticeConfig = section.as_any().downcast_ref().unwrap();
        assert_eq!(cfg.spacing, 2e-5);
        assert_eq!(cfg.materials["hmx"].young, 25.325e9);
        assert_eq!((p.parse)(params.as_str()).unwrap().1, params);
        assert!(section
            .unsupported(brisance_core::Geometry::Axisymmetric)
            .is_some());
        assert!(section
            .unsupported(brisance_core::Geometry::Cartesian)
            .is_none());
    }

    /// A 2D box 4 × 2 spacings of 1 mm: 5 × 3 nodes, with the materials
    /// `eos` and the regions `initial` (shape, material, velocity).
    fn scene(
        eos: &[(&str, EosModel)],
        initial: &[(Region, &str, [f64; 3])],
        fields: &[String],
    ) -> OwnedScene {
        let mut o = OwnedScene::new(Domain::cartesian([0.0; 3], [4e-3, 2e-3, 1e-3], [4, 2, 1]));
        for (name, e) in eos {
            o = o.with_material(name, Some(e.clone()));
        }
        for (region, material, velocity) in initial {
            let state = StateConfig::at_pressure(1.0, 1.0).moving(*velocity);
            o = o.with_region(region.clone(), material, state);
        }
        o.name = "box".into();
        o.cell_fields = fields.to_vec();
        o
    }

    fn config(text: &str) -> LatticeConfig {
        ron::from_str(text).unwrap()
    }

    const HMX: &str =
        "(dimension: Two, spacing: 1e-3, thermal: false, materials: {\"hmx\": (young: 1e9)})";

    /// The section as a scenario writes it, with its defaults; the spec's
    /// registration is the one `brisance list` prints.
    #[test]
    fn the_section_reads_with_its_defaults() {
        let c = config(HMX);
        assert_eq!(c.integrator, Integrator::VelocityVerlet);
        assert_eq!(c.safety_factor, 0.8);
        assert_eq!(c.initial_temperature, 300.0);
        assert!(c.mechanics && !c.diagonals && c.pack.is_none());
        assert!(ron::from_str::<LatticeConfig>(&HMX.replace("young", "yung")).is_err());
        assert_eq!(LatticeConfig::INFO.name, "Lattice");
        let example: String = LatticeConfig::INFO.example["Lattice".len()..].into();
        assert!(ron::from_str::<LatticeConfig>(&example).is_ok());
    }

    /// Built from the scene alone: nodes at lower + k h, the first region
    /// holding a node gives its material and velocity, nodes in no region
    /// are exterior.
    #[test]
    fn a_scene_builds_the_lattice_its_regions_describe() {
        let eos = [(
            "hmx",
            EosModel::MieGruneisenThermal(inert_eos(1900.0, 2000.0)),
        )];
        let initial = [
            (
                Region::Box {
                    min: [-1.0, -1.0, -1.0],
                    max: [2.5e-3, 1.0, 1.0],
                },
                "hmx",
                [3.0, -1.0, 0.0],
            ),
            (
                Region::Box {
                    min: [2.5e-3, -1.0, -1.0],
                    max: [3.5e-3, 1.0, 1.0],
                },
                "hmx",
                [0.0; 3],
            ),
        ];
        let o = scene(&eos, &initial, &[]);
        let s = o.scene();
        let c = config(HMX);
        c.validate(&s).unwrap();
        let lat = c.build(&s).unwrap();
        // 5 × 3 nodes and the ring of exterior nodes around them.
        assert_eq!(lat.geom.n[..2], [7, 5]);
        // x = 0, 1, 2 mm in the first box, 3 mm in the second, 4 mm in none.
        for iy in 0..3 {
            for (ix, solid, u) in [
                (0, true, 3.0),
                (2, true, 3.0),
                (3, true, 0.0),
                (4, false, 0.0),
            ] {
                let i = lat.geom.index(ix + 1, iy + 1, 0);
                assert_eq!(lat.geom.is_solid(i), solid, "node ({ix}, {iy})");
                if solid {
                    assert_eq!(lat.u[0][i], u);
                    assert_eq!(lat.u[1][i], if u > 0.0 { -1.0 } else { 0.0 });
                }
            }
        }
        let d = c.describe(&s);
        assert!(d.contains("[5, 3, 1] nodes") && d.contains("`hmx`"), "{d}");
    }

    /// What the scene must give the section, each refusal naming its field.
    #[test]
    fn the_scene_is_checked_field_by_field() {
        let region = Region::Everywhere;
        let hmx = [(
            "hmx",
            EosModel::MieGruneisenThermal(inert_eos(1900.0, 2000.0)),
        )];
        let gas = [("hmx", EosModel::IdealGas(IdealGas::new(1.4, 717.6, 1.2)))];
        let fields = ["density".to_string()];
        let field = |eos: &[(&str, EosModel)], material: &str, fields: &[String], text: &str| {
            let initial = [(region.clone(), material, [0.0; 3])];
            config(text)
                .validate(&scene(eos, &initial, fields).scene())
                .unwrap_err()
                .field
        };
        assert_eq!(field(&hmx, "hmx", &fields, HMX), "outputs.fields");
        assert_eq!(field(&hmx, "rdx", &[], HMX), "initial.0.material");
        assert_eq!(field(&gas, "hmx", &[], HMX), "materials.hmx.eos");
        assert_eq!(field(&[], "hmx", &[], HMX), "materials.hmx");
        let zero = HMX.replace("spacing: 1e-3", "spacing: 0.0");
        assert_eq!(field(&hmx, "hmx", &[], &zero), "pipeline.spacing");
        let fine = HMX.replace("spacing: 1e-3", "spacing: 1e-9");
        assert_eq!(field(&hmx, "hmx", &[], &fine), "pipeline.spacing");
        let soft = HMX.replace("young: 1e9", "young: -1e9");
        assert_eq!(field(&hmx, "hmx", &[], &soft), "pipeline.materials.hmx");
        let no_mechanics = HMX.replace("thermal: false", "thermal: true, mechanics: false");
        assert_eq!(field(&hmx, "hmx", &[], &no_mechanics), "pipeline.mechanics");
    }
}
