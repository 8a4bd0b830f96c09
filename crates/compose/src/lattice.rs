//! The `Lattice` pipeline: the thermo-mechanical mass–spring–damper lattice
//! of seed 003 (`brisance_pd::msdm`).
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

use std::collections::BTreeMap;

use brisance_eos::EosModel;
use brisance_pd::msdm::{
    Damping, Dim, Geometry, Hysteretic, Integrator, LatticeMaterial, MsdmLattice, MsdmOptions,
    Plasticity, Surroundings,
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
    pub linear_solver: brisance_pd::msdm::LinearSolver,
    /// Prescribed node velocities.
    #[serde(default)]
    pub boundaries: Vec<LatticeBoundaryConfig>,
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
/// positions); the velocity is held for the whole run.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LatticeBoundaryConfig {
    /// Region.
    pub region: Region,
    /// Velocity, m/s (`(0, 0, 0)` fixes the nodes).
    pub velocity: [f64; 3],
}

/// Nodes per axis covering [lower, upper] at spacing h.
fn node_counts(s: &Scenario, cfg: &LatticeConfig) -> [usize; 3] {
    let mut n = [1usize; 3];
    for (a, na) in n.iter_mut().enumerate().take(cfg.dimension.count()) {
        let len = s.domain.upper[a] - s.domain.lower[a];
        *na = (len / cfg.spacing * (1.0 + 1e-12)).floor() as usize + 1;
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
    let total: usize = n.iter().map(|k| k + 2).product();
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
    let geom = Geometry::new(cfg.dimension, n, h, cfg.diagonals, |ix, iy, iz| {
        region_of(position(ix, iy, iz)).map(|r| {
            names
                .iter()
                .position(|m| **m == s.initial[r].material)
                .unwrap_or(0) as u16
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
        if let Some(b) = cfg.boundaries.iter().find(|b| b.region.contains(p)) {
            lat.prescribed[i] = true;
            for a in 0..d {
                lat.u[a][i] = b.velocity[a];
            }
        }
    }
    lat.mark_modified();
    Ok(lat)
}

/// One paragraph for `check`.
pub fn describe(s: &Scenario, cfg: &LatticeConfig) -> String {
    let n = node_counts(s, cfg);
    format!(
        "scenario `{}`: Lattice pipeline (mass–spring–damper lattice, seed 003), {:?}, spacing {} m, \
         {n:?} nodes, {:?}, diagonals {}, energy equation {}\n  materials: {}\n  time: to {} s",
        s.name,
        cfg.dimension,
        cfg.spacing,
        cfg.integrator,
        cfg.diagonals,
        cfg.thermal,
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
}
