//! The `IceMpm` pipeline: Eulerian fluids (ICE) and one Lagrangian solid
//! (MPM particles) on one grid, coupled by the step of seed 000 §3.3
//! (`brisance_couple::ice_mpm`).
//!
//! ```ron
//! pipeline: IceMpm(
//!     ice: (materials: ["reactant", "products", "air"], reactions: [...]),
//!     solid: "copper",
//!     mpm: (shape_function: Linear, scheme: Musl, ppc: 2),
//! ),
//! ```
//!
//! `ice` is an `Ice` pipeline over the fluids (every option of that
//! pipeline, paths `pipeline.ice.*`). `solid` names a scenario material
//! with both an `eos` (its pressure in the equilibration, normally a
//! `SolidThreshold`) and a constitutive `model`; it becomes material
//! N + 1 of the ICE output fields (`volume_fraction_k`, `density_k`, …).
//! `mpm` is an `Mpm` pipeline for its particles (paths `pipeline.mpm.*`;
//! USL or MUSL, no anti-locking). Initial regions of `solid` become
//! particles; the others fill the cells, and the fluids are fitted around
//! the particles before the first step. Particle gauges sample the solid's
//! particles.

use brisance_couple::IceMpm;
use brisance_mpm::{AntiLocking, UpdateScheme};
use serde::{Deserialize, Serialize};

use crate::build::{located, mpm_parts, Built};
use crate::config::{MpmConfig, Pipeline, Scenario};
use crate::ice::IceConfig;

type Problem = (String, String);

/// Options of the IceMpm pipeline.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct IceMpmConfig {
    /// The fluids and the ICE options.
    pub ice: IceConfig,
    /// The Lagrangian material (EOS and constitutive model).
    pub solid: String,
    /// The particle options.
    pub mpm: MpmConfig,
}

/// `(path, message)` with `pipeline.` re-rooted at `pipeline.<sub>.`.
fn under(sub: &str, (path, message): Problem) -> Problem {
    let path = match path.strip_prefix("pipeline") {
        Some(rest) => format!("pipeline.{sub}{rest}"),
        None => path,
    };
    (path, message)
}

/// The scenario the ICE side sees: the fluids and the solid (last).
fn ice_scenario(s: &Scenario, cfg: &IceMpmConfig) -> (Scenario, IceConfig) {
    let mut ice = cfg.ice.clone();
    ice.materials.push(cfg.solid.clone());
    let mut si = s.clone();
    si.pipeline = Pipeline::Ice(ice.clone());
    (si, ice)
}

/// The scenario the particle side sees: the solid and its regions only.
fn mpm_scenario(s: &Scenario, cfg: &IceMpmConfig) -> Scenario {
    let mut sm = s.clone();
    sm.materials.retain(|name, _| *name == cfg.solid);
    sm.initial.retain(|r| r.material == cfg.solid);
    sm.pipeline = Pipeline::Mpm(cfg.mpm.clone());
    sm
}

/// Checks the pipeline; errors carry the field path.
pub fn validate(s: &Scenario, cfg: &IceMpmConfig) -> Result<(), Problem> {
    let solid = s.materials.get(&cfg.solid).ok_or_else(|| {
        (
            "pipeline.solid".to_string(),
            format!("`{}` is not a scenario material", cfg.solid),
        )
    })?;
    if cfg.ice.materials.contains(&cfg.solid) {
        return Err((
            "pipeline.solid".into(),
            format!(
                "`{}` is also in pipeline.ice.materials; list only the fluids there",
                cfg.solid
            ),
        ));
    }
    if cfg.ice.transport.contains_key(&cfg.solid) {
        return Err((
            format!("pipeline.ice.transport.{}", cfg.solid),
            "the solid's stress and heat flux are its particles'; give transport for the fluids only".into(),
        ));
    }
    if solid.eos().is_none() {
        return Err((
            format!("materials.{}.eos", cfg.solid),
            "the solid needs an `eos` for its pressure in the equilibration".into(),
        ));
    }
    if solid.model.is_none() {
        return Err((
            format!("materials.{}.model", cfg.solid),
            "the solid needs a constitutive `model`".into(),
        ));
    }
    if cfg.mpm.scheme == UpdateScheme::Usf {
        return Err((
            "pipeline.mpm.scheme".into(),
            "the coupled step runs `Usl` or `Musl`".into(),
        ));
    }
    if cfg.mpm.anti_locking != AntiLocking::Off {
        return Err((
            "pipeline.mpm.anti_locking".into(),
            "the coupled step has no anti-locking option; use `Off`".into(),
        ));
    }
    if !s.initial.iter().any(|r| r.material == cfg.solid) {
        return Err((
            "initial".into(),
            format!("no initial region is of the solid `{}`", cfg.solid),
        ));
    }
    if cfg.ice.pressure != brisance_ice::PressureSolve::Explicit {
        return Err((
            "pipeline.ice.pressure".into(),
            "the coupled step runs the explicit pressure only; use `Explicit`".into(),
        ));
    }
    let (si, ice) = ice_scenario(s, cfg);
    crate::ice::validate(&si, &ice).map_err(|e| under("ice", e))?;
    Ok(())
}

/// Builds the coupled solver and the particle sets of its gauges.
pub fn build(s: &Scenario, cfg: &IceMpmConfig) -> Result<Built, crate::ConfigError> {
    let located = |(path, message): Problem| located(&path, message);
    validate(s, cfg).map_err(located)?;
    let (si, ice_cfg) = ice_scenario(s, cfg);
    let ice =
        crate::ice::build_with_traces(&si, &ice_cfg, true).map_err(|e| located(under("ice", e)))?;
    let sm = mpm_scenario(s, cfg);
    let (mpm, particle_gauges) = mpm_parts(&sm, &cfg.mpm).map_err(|mut e| {
        if let Some(f) = e.field.take() {
            e.field = Some(under("mpm", (f, String::new())).0);
        }
        e
    })?;
    let solver = IceMpm::new(ice, mpm, cfg.ice.materials.len())
        .map_err(|e| located(("pipeline".into(), e.to_string())))?;
    Ok(Built::IceMpm {
        solver: Box::new(solver),
        particle_gauges,
    })
}

/// One paragraph for `check`.
pub fn describe(s: &Scenario, cfg: &IceMpmConfig) -> String {
    let d = &s.domain;
    format!(
        "scenario `{}`: IceMpm pipeline (ICE–MPM, seed 000 §3.3), {} x {} x {} cells, \
         fluids {}, solid `{}` as particles ({:?}, {:?}, {} per cell per direction), \
         K {} kg/(m³·s)\n  time: to {} s",
        s.name,
        d.cells[0],
        d.cells[1],
        d.cells[2],
        cfg.ice
            .materials
            .iter()
            .map(|m| format!("`{m}`"))
            .collect::<Vec<_>>()
            .join(", "),
        cfg.solid,
        cfg.mpm.shape_function,
        cfg.mpm.scheme,
        cfg.mpm.ppc,
        cfg.ice.momentum_exchange,
        s.time.end
    )
}

#[cfg(test)]
mod tests {
    use crate::build::build;
    use crate::load_str;

    const PISTON: &str = include_str!("../../../configs/piston_icempm.ron");

    /// configs/piston_icempm.ron builds through the pipeline and, at
    /// 100 µs, its shock (p crossing 1.25 bar) is within two cells of the
    /// exact 412.3 m/s piston shock launched from x = 6 cm, and the
    /// piston gauge still reads 100 m/s within 0.5 %.
    #[test]
    fn the_piston_config_drives_the_exact_shock() {
        let loaded = load_str("piston_icempm.ron", PISTON, &[]).unwrap();
        let mut built = build(&loaded.scenario).unwrap();
        while built.time() < 1e-4 * (1.0 - 1e-12) {
            let dt = built.stable_dt().unwrap().min(1e-4 - built.time());
            built.advance(dt).unwrap();
        }
        let mut v = Vec::new();
        assert!(built.sample_particle_gauge(0, &[brisance_mpm::SetQuantity::MeanVelocity], &mut v));
        assert!((v[0] / 100.0 - 1.0).abs() < 5e-3, "piston at {} m/s", v[0]);
        let p = built.cell_data(&["pressure".into()]).unwrap();
        let p = p.field("pressure").unwrap();
        let level = 1.25e5;
        let i = (1..p.len())
            .rev()
            .find(|&i| p[i - 1] >= level && p[i] < level)
            .unwrap();
        let x = 1e-3 * (i as f64 - 0.5) + 1e-3 * (p[i - 1] - level) / (p[i - 1] - p[i]);
        let exact = 0.06 + 412.3 * 1e-4;
        assert!(
            ((x - exact) / 1e-3).abs() < 2.0,
            "shock at {x} m, exact {exact} m"
        );
    }

    #[test]
    fn a_solid_listed_among_the_fluids_is_named() {
        let bad = PISTON.replace(
            "ice: (materials: [\"air\"])",
            "ice: (materials: [\"air\", \"steel\"])",
        );
        let err = load_str("piston_icempm.ron", &bad, &[]).unwrap_err();
        let text = err.to_string();
        assert!(text.contains("pipeline.solid"), "{text}");
    }
}

#[cfg(test)]
mod cylinder_tests {
    use crate::build::build;
    use crate::load_str;

    const CYLINDER: &str = include_str!("../../../configs/cylinder_icempm.ron");

    /// configs/cylinder_icempm.ron builds (four materials, the copper tube
    /// as particles) and takes its first steps with a positive, finite
    /// pressure everywhere and the booster's pressure at the tube's end.
    #[test]
    fn the_cylinder_config_builds_and_steps() {
        let loaded = load_str("cylinder_icempm.ron", CYLINDER, &[]).unwrap();
        let mut built = build(&loaded.scenario).unwrap();
        for _ in 0..3 {
            let dt = built.stable_dt().unwrap();
            built.advance(dt).unwrap();
        }
        let p = built.cell_data(&["pressure".into()]).unwrap();
        let p = p.field("pressure").unwrap();
        assert!(p.iter().all(|x| *x > 0.0 && x.is_finite()));
        // The booster's 10 GPa is there at the start of the tube.
        assert!(p[0] > 1e9, "p at the booster {} Pa", p[0]);
    }
}
