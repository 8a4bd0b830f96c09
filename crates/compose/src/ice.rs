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
//! region's pressure is found from its state with its material's EOS.
//!
//! Faces: `Outflow` → zero-gradient outflow, `Reflective` → symmetry plane
//! (slip wall), `Wall` → a fixed wall of velocity 0, `Periodic` → periodic;
//! `Fixed` states are not supported by this pipeline.

use brisance_core::Eos;
use brisance_eos::EosModel;
use brisance_grid::Level;
use brisance_ice::{
    Advection, CellState, ExchangeCoefficients, IceBoundary, IceOptions, IceSolver, MaterialState,
    GHOST, MAX_MATERIALS,
};
use serde::{Deserialize, Serialize};

use crate::build::primitive_state;
use crate::config::{BoundaryConfig, Scenario};

type Problem = (String, String);

/// Volume fraction of a material in cells where it is absent.
pub const TRACE_FRACTION: f64 = 1e-6;

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
    if !(cfg.cfl > 0.0 && cfg.cfl <= 1.0) {
        return Err((
            "pipeline.cfl".into(),
            format!("cfl = {} must lie in (0, 1]", cfg.cfl),
        ));
    }
    for (path, v) in [
        ("pipeline.momentum_exchange", cfg.momentum_exchange),
        ("pipeline.heat_exchange", cfg.heat_exchange),
    ] {
        if !(v >= 0.0 && v.is_finite()) {
            return Err((path.into(), format!("{v} must be finite and ≥ 0")));
        }
    }
    for (face, bc) in s.boundaries.faces() {
        if matches!(bc, BoundaryConfig::Fixed(_)) {
            return Err((
                format!("boundaries.{face}"),
                "the Ice pipeline takes `Outflow`, `Reflective`, `Wall` or `Periodic`".into(),
            ));
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

/// Builds the solver.
pub fn build(s: &Scenario, cfg: &IceConfig) -> Result<IceSolver<EosModel>, Problem> {
    validate(s, cfg)?;
    let eos = material_eos(s, cfg)?;
    let n = eos.len();
    let d = &s.domain;
    let level = Level::new(d.lower, d.upper, d.cells, d.patches, GHOST)
        .map_err(|e| ("domain.patches".to_string(), e.to_string()))?;
    let mut boundaries: [IceBoundary; 6] = std::array::from_fn(|_| IceBoundary::Outflow);
    for (k, (_, bc)) in s.boundaries.faces().into_iter().enumerate() {
        boundaries[k] = match bc {
            BoundaryConfig::Outflow => IceBoundary::Outflow,
            BoundaryConfig::Reflective => IceBoundary::Symmetry,
            BoundaryConfig::Wall => IceBoundary::FixedVelocity([0.0; 3]),
            BoundaryConfig::Periodic => IceBoundary::Periodic,
            BoundaryConfig::Fixed(_) => unreachable!("rejected by validate"),
        };
    }
    // One cell state per region.
    let states = s
        .initial
        .iter()
        .enumerate()
        .map(|(i, r)| {
            let m = cfg
                .materials
                .iter()
                .position(|x| *x == r.material)
                .expect("checked by validate");
            let p = primitive_state(&eos[m], &r.state)
                .map_err(|e| (format!("initial.{i}.state"), e))?;
            let trace = TRACE_FRACTION;
            let materials = (0..n)
                .map(|k| MaterialState {
                    volume_fraction: if k == m {
                        1.0 - (n - 1) as f64 * trace
                    } else {
                        trace
                    },
                    density: p.density,
                    velocity: p.velocity,
                })
                .collect();
            Ok(CellState {
                pressure: p.pressure,
                materials,
            })
        })
        .collect::<Result<Vec<_>, Problem>>()?;
    // Every cell must be covered.
    let geometry = level.geometry;
    for k in 0..d.cells[2] {
        for j in 0..d.cells[1] {
            for i in 0..d.cells[0] {
                let x = geometry.cell_centre([i, j, k]);
                if !s.initial.iter().any(|r| r.region.contains(x)) {
                    return Err(("initial".into(), format!("cell ({i}, {j}, {k}) at {x:?} is in no initial region; add an `Everywhere` region first")));
                }
            }
        }
    }
    let init = |x: [f64; 3]| {
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
        ..Default::default()
    };
    let exchange = ExchangeCoefficients::uniform(n, cfg.momentum_exchange, cfg.heat_exchange);
    IceSolver::new(eos, level, boundaries, exchange, options, init)
        .map_err(|e| ("pipeline".into(), e.to_string()))
}

/// One paragraph for `check`.
pub fn describe(s: &Scenario, cfg: &IceConfig) -> String {
    let d = &s.domain;
    let eos = material_eos(s, cfg).unwrap_or_default();
    format!(
        "scenario `{}`: Ice pipeline (multi-material ICE, seed 000 §3.3), {} x {} x {} cells, \
         {:?} advection, cfl {}, K {} kg/(m³·s), H {} W/(m³·K), total-energy closure {}\n  \
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
}
