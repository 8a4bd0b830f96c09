//! The `Lattice` pipeline: the thermo-mechanical mass–spring–damper lattice
//! of seed 003 (`brisance_lattice`).
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
//! (seed 003 §2.4, `brisance_lattice::SurfaceRegression`); `regression` says which
//! exterior nodes are fluid. A `pack` replaces the material of the solid
//! nodes by a crystal/binder image (PGM or PNG, one node per pixel) or a random
//! pack of discs (`brisance_lattice::random_disc_pack`).

use std::collections::BTreeMap;

use brisance_eos::EosModel;
use brisance_lattice::{
    area_fraction, random_disc_pack, read_image, Arrhenius, Damping, Dim, Geometry, GrayImage,
    Hysteretic, Integrator, LatticeMaterial, MsdmLattice, MsdmOptions, Plasticity,
    SurfaceRegression, Surroundings,
};
use serde::{Deserialize, Serialize};

use crate::config::{Region, Scenario};

type Problem = (String, String);

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
    pub linear_solver: brisance_lattice::LinearSolver,
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
    s: &Scenario,
    name: &str,
    m: &LatticeMaterialConfig,
) -> Result<LatticeMaterial, Problem> {
    let eos = match s.materials.get(name).and_then(|c| c.eos()) {
        Some(EosModel::MieGruneisenThermal(e)) => *e,
        Some(other) => {
            return Err((
                format!("materials.{name}.eos"),
                format!(
                    "the Lattice pipeline needs a `MieGruneisenThermal` EOS (seed 003 eqs 12–14), `{name}` has {}",
                    brisance_core::Eos::name(other)
                ),
            ))
        }
        None => {
            return Err((
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
        .map_err(|e| (format!("pipeline.materials.{name}"), e))?;
    if let Some(a) = &m.arrhenius {
        let field = format!("pipeline.materials.{name}.arrhenius");
        a.validate(&field).map_err(|e| (field, e))?;
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
    pub fn held_mask(&self, index: usize, dim: usize) -> Result<u8, Problem> {
        let field = format!("pipeline.boundaries.{index}.axes");
        for (a, v) in self.velocity.iter().enumerate() {
            if !v.is_finite() {
                return Err((
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
            return Err((
                field,
                "empty list: name at least one of \"x\", \"y\", \"z\" (or leave `axes` out \
                 to hold every axis)"
                    .into(),
            ));
        }
        let mut mask = 0u8;
        for name in axes {
            let a = match name.as_str() {
                "x" => 0,
                "y" => 1,
                "z" => 2,
                _ => {
                    return Err((
                        field,
                        format!("`{name}` is not an axis, expected \"x\", \"y\" or \"z\""),
                    ))
                }
            };
            if a >= dim {
                return Err((
                    field,
                    format!("axis `{name}` is not one of the lattice's {dim} axes"),
                ));
            }
            if mask & (1 << a) != 0 {
                return Err((field, format!("axis `{name}` is listed twice")));
            }
            mask |= 1 << a;
        }
        Ok(mask)
    }
}

/// Nodes per axis covering [lower, upper] at spacing h.
fn node_counts(s: &Scenario, cfg: &LatticeConfig) -> [usize; 3] {
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
pub fn validate(s: &Scenario, cfg: &LatticeConfig) -> Result<(), Problem> {
    if !(cfg.spacing > 0.0 && cfg.spacing.is_finite()) {
        return Err((
            "pipeline.spacing".into(),
            format!("spacing must be a finite value > 0 m, got {}", cfg.spacing),
        ));
    }
    let n = node_counts(s, cfg);
    let total = n
        .iter()
        .fold(1usize, |p, k| p.saturating_mul(k.saturating_add(2)));
    if total > 200_000_000 {
        return Err((
            "pipeline.spacing".into(),
            format!(
                "spacing {} m gives {n:?} nodes over the domain, more than 2e8",
                cfg.spacing
            ),
        ));
    }
    if !s.outputs.fields.is_empty() {
        return Err((
            "outputs.fields".into(),
            "the Lattice pipeline writes its nodes as particles and has no cell fields: \
             write `fields: []` (point gauges can sample the node fields)"
                .into(),
        ));
    }
    for (name, m) in &cfg.materials {
        lattice_material(s, name, m)?;
    }
    if !cfg.mechanics && cfg.thermal {
        return Err((
            "pipeline.mechanics".into(),
            "`mechanics: false` needs `thermal: false` (the energy equation uses the mechanical \
             volume update)"
                .into(),
        ));
    }
    if let Some(r) = &cfg.regression {
        if !(1.0..=16.0).contains(&r.normal_radius) {
            return Err((
                "pipeline.regression.normal_radius".into(),
                format!("{} spacings, expected a value in [1, 16]", r.normal_radius),
            ));
        }
        if !(r.step_fraction > 0.0 && r.step_fraction <= 1.0) {
            return Err((
                "pipeline.regression.step_fraction".into(),
                format!("{}, expected a value in (0, 1]", r.step_fraction),
            ));
        }
    }
    if let Some(p) = &cfg.pack {
        if cfg.dimension != Dim::Two {
            return Err((
                "pipeline.pack".into(),
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
                    return Err((
                        "pipeline.pack.mass_fraction".into(),
                        format!("{mass_fraction}, expected a value in (0, 1)"),
                    ));
                }
                if !(*diameter > 0.0 && diameter.is_finite()) {
                    return Err((
                        "pipeline.pack.diameter".into(),
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
                return Err((
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
        if !cfg.materials.contains_key(&r.material) {
            return Err((
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
pub fn build(s: &Scenario, cfg: &LatticeConfig) -> Result<MsdmLattice, Problem> {
    validate(s, cfg)?;
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
    let region_of = |p: [f64; 3]| s.initial.iter().position(|r| r.region.contains(p));
    let index_of = |name: &str| names.iter().position(|m| *m == name).unwrap_or(0) as u16;
    let pack = pack_materials(s, cfg, n, &index_of)?;
    let geom = Geometry::new(cfg.dimension, n, h, cfg.diagonals, |ix, iy, iz| {
        region_of(position(ix, iy, iz)).map(|r| match &pack {
            Some(m) => m[ix + n[0] * iy],
            None => index_of(&s.initial[r].material),
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
        .map_err(|e| ("pipeline".into(), e.to_string()))?;
    lat.mechanics = cfg.mechanics;
    let laws: Vec<Option<Arrhenius>> = cfg.materials.values().map(|m| m.arrhenius).collect();
    if laws.iter().any(Option::is_some) {
        let rc = cfg.regression.clone().unwrap_or_default();
        let mut reg = SurfaceRegression::new(&lat, laws, rc.normal_radius, rc.step_fraction)
            .map_err(|e| ("pipeline.regression".to_string(), e.to_string()))?;
        if let Some(fluid) = &rc.fluid {
            let g = lat.geom.clone();
            reg.set_walls(&lat, |i| {
                let p = g.reference_position(i);
                !fluid.iter().any(|r| r.contains(p))
            });
        }
        lat.set_regression(reg)
            .map_err(|e| ("pipeline.regression".to_string(), e.to_string()))?;
    }
    // Initial velocities and prescribed nodes.
    for i in 0..lat.len() {
        if !lat.geom.is_solid(i) {
            continue;
        }
        let p = lat.geom.reference_position(i);
        if let Some(r) = region_of(p) {
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
    // Spread over the ranks of the run (docs/cluster.md): an implicit
    // integrator refuses at its field, too few planes at the spacing.
    let field = if lat.options.integrator.is_implicit() {
        "pipeline.integrator"
    } else {
        "pipeline.spacing"
    };
    lat.distribute(brisance_grid::comm::world())
        .map_err(|e| (field.to_string(), e.to_string()))?;
    Ok(lat)
}

/// Material index of every node of the `n[0]` × `n[1]` solid block from
/// the pack, row-major from the bottom row (`None` without a pack).
fn pack_materials(
    s: &Scenario,
    cfg: &LatticeConfig,
    n: [usize; 3],
    index_of: &dyn Fn(&str) -> u16,
) -> Result<Option<Vec<u16>>, Problem> {
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
                (
                    "pipeline.pack.path".to_string(),
                    format!("cannot read `{path}`: {e}"),
                )
            })?;
            let img: GrayImage =
                read_image(&bytes).map_err(|e| ("pipeline.pack.path".to_string(), e))?;
            if img.width != n[0] || img.height != n[1] {
                return Err((
                    "pipeline.pack.path".into(),
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
            let rho = |name: &str| -> Result<f64, Problem> {
                match s.materials.get(name).and_then(|c| c.eos()) {
                    Some(EosModel::MieGruneisenThermal(e)) => Ok(e.rho0),
                    _ => Err((
                        format!("materials.{name}.eos"),
                        "a pack material needs a `MieGruneisenThermal` EOS".into(),
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
            .map_err(|e| ("pipeline.pack".to_string(), e))?;
            let inside = disc.rasterise(n[0], n[1], cfg.spacing);
            let (p, b) = (index_of(particle), index_of(binder));
            Ok(Some(
                inside.iter().map(|&k| if k { p } else { b }).collect(),
            ))
        }
    }
}

/// One paragraph for `check`.
pub fn describe(s: &Scenario, cfg: &LatticeConfig) -> String {
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
        s.time.end
    )
}

#[cfg(test)]
mod tests {
    use crate::build::build_solver;
    use crate::load_str;

    /// The example scenario loads, validates, builds and steps; a region
    /// naming a material without lattice parameters is reported with its
    /// field path.
    #[test]
    fn lattice_config_loads_builds_and_steps() {
        let text = include_str!("../../../configs/lattice_impact.ron");
        let loaded = load_str("lattice_impact.ron", text, &[]).unwrap();
        let mut solver = build_solver(&loaded.scenario).unwrap();
        assert_eq!(solver.name(), "lattice");
        let before = solver.conservation_totals();
        for _ in 0..5 {
            let dt = solver.stable_dt().unwrap();
            solver.advance(dt).unwrap();
        }
        let after = solver.conservation_totals();
        assert!((after.mass - before.mass).abs() <= 1e-12 * before.mass);
        let p = solver.particle_data().unwrap();
        assert!(p.fields.iter().any(|(n, _)| n == "temperature"));
        let bad = text.replace("\"hmx\": (young", "\"hmx_typo\": (young");
        let err = load_str("lattice_impact.ron", &bad, &[]).unwrap_err();
        assert!(err.to_string().contains("material"), "{err}");
    }

    /// `axes` of a boundary: the masks by hand, the errors naming the
    /// field, and a built slip wall that holds u_x = 0 and leaves u_y to
    /// the initial state (0), where a no-slip wall sets the boundary's 5 m/s.
    #[test]
    fn boundary_axes_hold_only_the_listed_components() {
        use super::LatticeBoundaryConfig;
        let b = |axes: Option<&[&str]>| LatticeBoundaryConfig {
            region: crate::config::Region::Box {
                min: [0.0; 3],
                max: [1.0; 3],
            },
            velocity: [0.0, 5.0, 0.0],
            axes: axes.map(|v| v.iter().map(|s| s.to_string()).collect()),
        };
        assert_eq!(b(None).held_mask(0, 2), Ok(0b011));
        assert_eq!(b(None).held_mask(0, 3), Ok(0b111));
        assert_eq!(b(Some(&["x"])).held_mask(0, 2), Ok(0b001));
        assert_eq!(b(Some(&["z", "y"])).held_mask(0, 3), Ok(0b110));
        for (axes, why) in [
            (&[][..], "empty"),
            (&["w"][..], "`w` is not an axis"),
            (&["z"][..], "not one of the lattice's 2 axes"),
            (&["x", "x"][..], "listed twice"),
        ] {
            let (field, msg) = b(Some(axes)).held_mask(3, 2).unwrap_err();
            assert_eq!(field, "pipeline.boundaries.3.axes");
            assert!(msg.contains(why), "{msg}");
        }
        let mut nan = b(None);
        nan.velocity[1] = f64::NAN;
        assert_eq!(
            nan.held_mask(1, 2).unwrap_err().0,
            "pipeline.boundaries.1.velocity"
        );

        let text = include_str!("../../../configs/lattice_impact.ron");
        let wall = "velocity: (0.0, 0.0, 0.0)),";
        assert!(text.contains(wall));
        let build = |with: &str, integrator: &str| {
            let t = text.replace(wall, with);
            let sets = [format!("pipeline.integrator={integrator}")];
            let loaded = load_str("lattice_impact.ron", &t, &sets).map_err(|e| e.to_string())?;
            let crate::config::Pipeline::Lattice(cfg) = &loaded.scenario.pipeline else {
                return Err("not a lattice".to_string());
            };
            super::build(&loaded.scenario, cfg).map_err(|(f, m)| format!("{f}: {m}"))
        };
        let slip = build(
            "velocity: (0.0, 5.0, 0.0), axes: [\"x\"]),",
            "VelocityVerlet",
        )
        .unwrap();
        let noslip = build("velocity: (0.0, 5.0, 0.0)),", "VelocityVerlet").unwrap();
        let i = slip.geom.index(1, 2, 0);
        assert!(slip.prescribed[i] && noslip.prescribed[i]);
        assert_eq!(
            (slip.held_axes[i], slip.u[0][i], slip.u[1][i]),
            (0b001, 0.0, 0.0)
        );
        assert_eq!(
            (noslip.held_axes[i], noslip.u[0][i], noslip.u[1][i]),
            (0b011, 0.0, 5.0)
        );
        let mut slip = slip;
        for _ in 0..5 {
            let dt = slip.explicit_stable_dt();
            slip.step(dt).unwrap();
        }
        assert_eq!(slip.u[0][i], 0.0);
        let bad = build(
            "velocity: (0.0, 0.0, 0.0), axes: [\"q\"]),",
            "VelocityVerlet",
        );
        assert!(bad.unwrap_err().to_string().contains("boundaries.0.axes"));
        let mut imp = build(
            "velocity: (0.0, 0.0, 0.0), axes: [\"x\"]),",
            "ImplicitEuler",
        )
        .unwrap();
        let dt = imp.explicit_stable_dt();
        assert!(imp.step(dt).unwrap_err().to_string().contains("held_axes"));
    }

    /// The implicit integrator runs the example with either linear solver,
    /// and the two agree to the iterative solver's tolerance.
    #[test]
    fn implicit_lattice_runs_with_the_direct_and_the_iterative_solver() {
        let text = include_str!("../../../configs/lattice_impact.ron");
        let run = |solver_name: &str| {
            let sets = [
                "pipeline.integrator=ImplicitEuler".to_string(),
                format!("pipeline.linear_solver={solver_name}"),
            ];
            let loaded = load_str("lattice_impact.ron", text, &sets).unwrap();
            let mut solver = build_solver(&loaded.scenario).unwrap();
            for _ in 0..3 {
                let dt = solver.stable_dt().unwrap();
                solver.advance(dt).unwrap();
            }
            solver.conservation_totals()
        };
        let direct = run("Direct");
        let iterative = run("Iterative");
        for a in 0..3 {
            let scale = direct.momentum.iter().map(|v| v.abs()).sum::<f64>();
            assert!(
                (direct.momentum[a] - iterative.momentum[a]).abs() <= 1e-8 * scale,
                "axis {a}: {} vs {}",
                direct.momentum[a],
                iterative.momentum[a]
            );
        }
        assert!((direct.energy - iterative.energy).abs() <= 1e-8 * direct.energy.abs());
    }

    /// The burning-propellant example: the random AP pack has the 80 wt %
    /// AP of its configuration to the pixelation error, only the top face
    /// regresses, and the regression conserves mass (burnt + remaining).
    #[test]
    fn propellant_pack_loads_and_regresses_from_the_top() {
        use brisance_core::Solver;
        use brisance_lattice::node_mass_fraction;
        let text = include_str!("../../../configs/lattice_burn.ron");
        let loaded = load_str("lattice_burn.ron", text, &[]).unwrap();
        let crate::config::Pipeline::Lattice(cfg) = &loaded.scenario.pipeline else {
            panic!("not a lattice");
        };
        let mut lat = super::build(&loaded.scenario, cfg).unwrap();
        // Materials are in name order: ap = 0, htpb = 1.
        let w = node_mass_fraction(&lat, 0);
        assert!((w - 0.8).abs() < 0.03, "AP mass fraction {w}");
        let m0: f64 = lat.mass.iter().sum();
        let dt = lat.stable_dt().unwrap();
        // step_fraction 0.05 h at the faster AP speed at 860 K.
        let ap = cfg.materials["ap"].arrhenius.unwrap();
        assert!((dt - 0.05 * 2.4e-5 / ap.speed(1950.0, 860.0)).abs() < 1e-12 * dt);
        let top = lat.geom.n[1] - 3;
        let bottom_y = lat.x[1][lat.geom.solid_index(50, 0, 0)];
        for _ in 0..30 {
            lat.advance(dt).unwrap();
        }
        let reg = lat.regression.as_ref().unwrap();
        assert!(reg.consumed_mass > 0.0);
        let m1: f64 = lat.mass.iter().sum();
        assert!((m1 + reg.consumed_mass - m0).abs() < 1e-12 * m0);
        // The top row has moved, the bottom row has not.
        let i = lat.geom.solid_index(50, top, 0);
        assert!(lat.x[1][i] < top as f64 * 2.4e-5);
        assert_eq!(lat.x[1][lat.geom.solid_index(50, 0, 0)], bottom_y);
        // Field-naming errors.
        let bad = text.replace("particle: \"ap\"", "particle: \"apx\"");
        let err = load_str("lattice_burn.ron", &bad, &[]).unwrap_err();
        assert!(err.to_string().contains("pipeline.pack.particle"), "{err}");
        let bad = text.replace("pre_exponential: 5.0e6", "pre_exponential: -5.0e6");
        let err = load_str("lattice_burn.ron", &bad, &[]).unwrap_err();
        assert!(
            err.to_string()
                .contains("materials.ap.arrhenius.pre_exponential"),
            "{err}"
        );
        let bad = text.replace("thermal: false", "thermal: true");
        let err = load_str("lattice_burn.ron", &bad, &[]).unwrap_err();
        assert!(err.to_string().contains("pipeline.mechanics"), "{err}");
        let bad = text.replace("normal_radius: 1.0", "normal_radius: 0.5");
        let err = load_str("lattice_burn.ron", &bad, &[]).unwrap_err();
        assert!(err.to_string().contains("normal_radius"), "{err}");
        let bad = text.replace("mass_fraction: 0.8", "mass_fraction: 1.2");
        let err = load_str("lattice_burn.ron", &bad, &[]).unwrap_err();
        assert!(
            err.to_string().contains("pipeline.pack.mass_fraction"),
            "{err}"
        );
        let bad = text.replace(
            "activation_energy: 62800.0",
            "activation_energy: 62800.0, omega: 2.0",
        );
        assert!(load_str("lattice_burn.ron", &bad, &[]).is_err());
    }

    /// An image pack: one node per pixel, bright pixels crystal; the mass
    /// fraction is exact (a 3 × 3 image with a bright centre: the crystal
    /// node has the full dual cell, 4 edge nodes ½ and 4 corners ¼), and a
    /// size mismatch names `pipeline.pack.path`.
    #[test]
    fn image_pack_is_one_node_per_pixel() {
        use brisance_lattice::node_mass_fraction;
        let dir = std::env::temp_dir().join(format!("lattice_pack_{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("centre.pgm");
        std::fs::write(&path, b"P2 3 3 255\n0 0 0\n0 255 0\n0 0 0\n").unwrap();
        let text = include_str!("../../../configs/lattice_burn.ron")
            .replace(
                "pack: RandomDiscs(diameter: 2.0e-4, mass_fraction: 0.8, particle: \"ap\", binder: \"htpb\", seed: 17)",
                &format!(
                    "pack: Image(path: {:?}, threshold: 128, crystal: \"ap\", binder: \"htpb\")",
                    path.display().to_string()
                ),
            )
            .replace("upper: (2.4e-3, 2.4e-3, 2.4e-5)", "upper: (4.8e-5, 4.8e-5, 2.4e-5)");
        let loaded = load_str("lattice_burn.ron", &text, &[]).unwrap();
        let crate::config::Pipeline::Lattice(cfg) = &loaded.scenario.pipeline else {
            panic!("not a lattice");
        };
        let lat = super::build(&loaded.scenario, cfg).unwrap();
        assert_eq!(lat.material_of(lat.geom.solid_index(1, 1, 0)), Some(0));
        assert_eq!(lat.material_of(lat.geom.solid_index(0, 1, 0)), Some(1));
        // 1950 · 1 / (1950 · 1 + 920 · 3).
        let w = node_mass_fraction(&lat, 0);
        assert!((w - 1950.0 / (1950.0 + 2760.0)).abs() < 1e-14, "{w}");
        let wrong = text.replace(
            "upper: (4.8e-5, 4.8e-5, 2.4e-5)",
            "upper: (7.2e-5, 4.8e-5, 2.4e-5)",
        );
        let loaded = load_str("lattice_burn.ron", &wrong, &[]).unwrap();
        let err = crate::build::build_solver(&loaded.scenario).err().unwrap();
        assert!(err.to_string().contains("pipeline.pack.path"), "{err}");
        let _ = std::fs::remove_dir_all(&dir);
    }
}
