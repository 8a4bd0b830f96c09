//! Checks of a parsed scenario that serde cannot express. Each problem is
//! reported with the path of the offending field so the caller can point at
//! its line and column.

use crate::build::PipelineLimits;
use crate::config::{BoundaryConfig, Pipeline, Region, Scenario, StateConfig, ViscosityConfig};

/// A validation problem: the field path and the message.
pub type Problem = (String, String);

fn finite3(v: &[f64; 3]) -> bool {
    v.iter().all(|x| x.is_finite())
}

fn check_state(path: &str, s: &StateConfig) -> Result<(), Problem> {
    if !(s.density > 0.0 && s.density.is_finite()) {
        return Err((
            format!("{path}.density"),
            format!("density must be positive and finite, got {}", s.density),
        ));
    }
    if !finite3(&s.velocity) {
        return Err((format!("{path}.velocity"), "velocity must be finite".into()));
    }
    let given: Vec<(&str, f64)> = [
        ("pressure", s.pressure),
        ("specific_internal_energy", s.specific_internal_energy),
        ("temperature", s.temperature),
    ]
    .into_iter()
    .filter_map(|(n, v)| v.map(|v| (n, v)))
    .collect();
    match given.as_slice() {
        [(name, v)] => {
            if !(*v > 0.0 && v.is_finite()) {
                return Err((
                    format!("{path}.{name}"),
                    format!("{name} must be positive and finite, got {v}"),
                ));
            }
            Ok(())
        }
        [] => Err((
            path.into(),
            "give one of `pressure`, `specific_internal_energy` or `temperature`".into(),
        )),
        _ => Err((
            path.into(),
            "give only one of `pressure`, `specific_internal_energy` or `temperature`".into(),
        )),
    }
}

fn check_region(path: &str, r: &Region) -> Result<(), Problem> {
    r.validate()
        .map_err(|e| (format!("{path}.{}", e.field), e.message))
}

fn file_safe(name: &str) -> bool {
    !name.is_empty()
        && name
            .chars()
            .all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '-')
}

/// Validates a scenario; `known_fields` are the output fields of its
/// pipeline and `max_cfl` the scheme's stability limit.
/// Validates a scenario against its pipeline's limits (output fields,
/// Courant-number limit, ghost layers per patch).
pub fn validate(s: &Scenario, limits: &PipelineLimits) -> Result<(), Problem> {
    let (known_fields, max_cfl, ghost) = (limits.fields, limits.max_cfl, limits.ghost);
    const AXES: [&str; 3] = ["x", "y", "z"];
    if !file_safe(&s.name) {
        return Err((
            "name".into(),
            format!(
                "`{}` must be non-empty and use only letters, digits, `_` and `-`",
                s.name
            ),
        ));
    }
    let d = &s.domain;
    for (a, axis) in AXES.iter().enumerate() {
        if d.cells[a] == 0 {
            return Err((
                format!("domain.cells.{a}"),
                format!("the domain is empty: 0 cells along {}", axis),
            ));
        }
        if !(d.lower[a].is_finite() && d.upper[a].is_finite() && d.upper[a] > d.lower[a]) {
            return Err((
                format!("domain.upper.{a}"),
                format!(
                    "upper bound {} must exceed lower bound {} along {}",
                    d.upper[a], d.lower[a], axis
                ),
            ));
        }
        if d.patches[a] == 0 || d.patches[a] > d.cells[a] {
            return Err((
                format!("domain.patches.{a}"),
                format!(
                    "{} patches along {}: need between 1 and the {} cells",
                    d.patches[a], axis, d.cells[a]
                ),
            ));
        }
        // Every patch must hold the stencil's ghost layers (the smallest
        // patch has cells / patches cells, rounded down).
        if d.cells[a] > 1 && d.cells[a] / d.patches[a] < ghost {
            return Err((
                format!("domain.patches.{a}"),
                format!(
                    "{} patches along {axis} leave patches thinner than the {ghost} ghost layers the scheme needs; use at most {}",
                    d.patches[a],
                    d.cells[a] / ghost
                ),
            ));
        }
    }
    let t = &s.time;
    if !(t.end > 0.0 && t.end.is_finite()) {
        return Err((
            "time.end".into(),
            format!("end time must be positive, got {}", t.end),
        ));
    }
    if !(t.cfl > 0.0 && t.cfl <= max_cfl) {
        return Err((
            "time.cfl".into(),
            format!(
                "cfl = {} is outside (0, {max_cfl}], the scheme's stability limit",
                t.cfl
            ),
        ));
    }
    if t.max_steps == Some(0) {
        return Err((
            "time.max_steps".into(),
            "max_steps must be at least 1".into(),
        ));
    }
    for (name, m) in &s.materials {
        let path = format!("materials.{name}");
        if m.eos().is_none() && m.model.is_none() {
            return Err((
                path,
                "give `eos`, `library` or a constitutive `model`".into(),
            ));
        }
        if let Some(eos) = m.eos() {
            eos.validate().map_err(|msg| (format!("{path}.eos"), msg))?;
        }
        if let Some(model) = &m.model {
            model
                .validate()
                .map_err(|msg| (format!("{path}.model"), msg.to_string()))?;
        }
    }
    let known_materials = || {
        s.materials
            .keys()
            .map(|k| format!("`{k}`"))
            .collect::<Vec<_>>()
            .join(", ")
    };
    match &s.pipeline {
        Pipeline::Fdm(fdm) => {
            match s.materials.get(&fdm.material).and_then(|m| m.eos()) {
                None => {
                    return Err((
                        "pipeline.material".into(),
                        format!(
                            "unknown material `{}`; known materials: {}",
                            fdm.material,
                            known_materials()
                        ),
                    ));
                }
                Some(eos) if !eos.is_gas() => {
                    return Err((
                        "pipeline.material".into(),
                        format!(
                        "the Fdm pipeline carries a gas (IdealGas, Jwl or JwlCTerm); `{}` is `{}`",
                        fdm.material,
                        eos.variant()
                    ),
                    ));
                }
                Some(_) => {}
            }
            if let ViscosityConfig::Constant(eta) = fdm.viscosity {
                if !(0.0..=0.25).contains(&eta) {
                    return Err((
                        "pipeline.viscosity".into(),
                        format!("constant η = {eta} must lie in [0, 0.25]"),
                    ));
                }
            }
            for (face, bc) in s.boundaries.faces() {
                if matches!(bc, BoundaryConfig::Wall) {
                    return Err((
                        format!("boundaries.{face}"),
                        "`Wall` is a particle boundary; the Fdm pipeline uses `Reflective` for a slip wall".into(),
                    ));
                }
            }
        }
        Pipeline::Peridynamics(pd) => crate::peridynamics::validate(s, pd)?,
        Pipeline::Lattice(l) => crate::lattice::validate(s, l)?,
        Pipeline::Ice(ice) => crate::ice::validate(s, ice)?,
        Pipeline::IceMpm(c) => crate::ice_mpm::validate(s, c)?,
        Pipeline::FdmMpmBridge(b) => crate::bridge::validate(s, b)?,
        Pipeline::Mpm(mpm) => {
            if mpm.ppc == 0 || mpm.ppc > 8 {
                return Err((
                    "pipeline.ppc".into(),
                    format!(
                        "ppc = {} must lie in 1..=8 particles per cell per direction",
                        mpm.ppc
                    ),
                ));
            }
            if !(mpm.mass_cutoff >= 0.0 && mpm.mass_cutoff < 1.0) {
                return Err((
                    "pipeline.mass_cutoff".into(),
                    format!("mass_cutoff = {} must lie in [0, 1)", mpm.mass_cutoff),
                ));
            }
            if !finite3(&mpm.gravity) {
                return Err(("pipeline.gravity".into(), "gravity must be finite".into()));
            }
            let mut load_names = std::collections::BTreeSet::new();
            for (i, l) in mpm.surface_loads.iter().enumerate() {
                let path = format!("pipeline.surface_loads.{i}");
                if l.name.is_empty() || !load_names.insert(l.name.clone()) {
                    return Err((
                        format!("{path}.name"),
                        format!(
                            "surface load name `{}` must be non-empty and unique",
                            l.name
                        ),
                    ));
                }
                check_region(&format!("{path}.region"), &l.region)?;
                if let Some(m) = &l.material {
                    if s.materials.get(m).and_then(|m| m.model.as_ref()).is_none() {
                        return Err((
                            format!("{path}.material"),
                            format!(
                                "surface load `{}`: `{m}` is not a particle material (one with a constitutive `model`); known materials: {}",
                                l.name,
                                known_materials()
                            ),
                        ));
                    }
                }
                let n2: f64 = l.normal.iter().map(|c| c * c).sum();
                if !finite3(&l.normal) || !(n2 > 0.0) {
                    return Err((
                        format!("{path}.normal"),
                        format!(
                            "surface load `{}`: normal {:?} must be finite and non-zero",
                            l.name, l.normal
                        ),
                    ));
                }
                if let Some(h) = l.thickness {
                    if !(h > 0.0 && h.is_finite()) {
                        return Err((
                            format!("{path}.thickness"),
                            format!(
                                "surface load `{}`: thickness {h} m must be positive",
                                l.name
                            ),
                        ));
                    }
                }
                let finite = match l.load {
                    brisance_mpm::SurfaceLoadKind::Traction(t) => finite3(&t),
                    brisance_mpm::SurfaceLoadKind::Pressure(p) => p.is_finite(),
                };
                if !finite {
                    return Err((
                        format!("{path}.load"),
                        format!("surface load `{}`: the load must be finite", l.name),
                    ));
                }
                l.history.validate().map_err(|m| {
                    (
                        format!("{path}.history"),
                        format!("surface load `{}`: {m}", l.name),
                    )
                })?;
            }
            if let Some(Err((name, value))) = mpm.bulk_viscosity.option().map(|v| v.validate()) {
                return Err((
                    format!("pipeline.bulk_viscosity.{name}"),
                    format!("bulk viscosity coefficient {name} = {value} must be finite and ≥ 0"),
                ));
            }
            for (face, bc) in s.boundaries.faces() {
                if matches!(bc, BoundaryConfig::Periodic | BoundaryConfig::Fixed(_)) {
                    return Err((
                        format!("boundaries.{face}"),
                        "the Mpm pipeline takes `Wall`, `Reflective` (roller) or `Outflow`".into(),
                    ));
                }
            }
        }
    }
    for (face, bc) in s.boundaries.faces() {
        if let BoundaryConfig::Fixed(state) = bc {
            check_state(&format!("boundaries.{face}"), state)?;
        }
    }
    for (a, pair) in s.boundaries.faces().chunks(2).enumerate() {
        let lo = matches!(pair[0].1, BoundaryConfig::Periodic);
        let hi = matches!(pair[1].1, BoundaryConfig::Periodic);
        if lo != hi {
            let missing = if lo { pair[1].0 } else { pair[0].0 };
            return Err((
                format!("boundaries.{missing}"),
                format!("periodic along {} needs `Periodic` on both faces", AXES[a]),
            ));
        }
    }
    if s.initial.is_empty() {
        return Err((
            "initial".into(),
            "at least one initial region is needed".into(),
        ));
    }
    for (i, r) in s.initial.iter().enumerate() {
        let path = format!("initial.{i}");
        if !s.materials.contains_key(&r.material) {
            return Err((
                format!("{path}.material"),
                format!(
                    "unknown material `{}`; known materials: {}",
                    r.material,
                    known_materials()
                ),
            ));
        }
        match &s.pipeline {
            Pipeline::Fdm(fdm)
                if r.material != fdm.material && fdm.products.as_ref() != Some(&r.material) =>
            {
                return Err((
                    format!("{path}.material"),
                    match &fdm.products {
                        None => format!("the Fdm pipeline carries one gas, `{}`", fdm.material),
                        Some(p) => format!(
                            "the Fdm pipeline carries the gas `{}` and the products `{p}`",
                            fdm.material
                        ),
                    },
                ));
            }
            Pipeline::Mpm(_) if s.materials[&r.material].model.is_none() => {
                return Err((
                    format!("{path}.material"),
                    format!(
                        "`{}` has no constitutive `model`, which Mpm particles need",
                        r.material
                    ),
                ));
            }
            _ => {}
        }
        check_region(&format!("{path}.region"), &r.region)?;
        check_state(&format!("{path}.state"), &r.state)?;
    }
    let o = &s.outputs;
    if let Some(iv) = o.interval {
        if !(iv > 0.0 && iv.is_finite()) {
            return Err((
                "outputs.interval".into(),
                format!("output interval must be positive, got {iv}"),
            ));
        }
    }
    let check_fields = |path: String, fields: &[String]| -> Result<(), Problem> {
        for (k, f) in fields.iter().enumerate() {
            if !known_fields.contains(&f.as_str()) {
                return Err((
                    format!("{path}.{k}"),
                    format!(
                        "unknown field `{f}`; known fields: {}",
                        known_fields.join(", ")
                    ),
                ));
            }
        }
        Ok(())
    };
    check_fields("outputs.fields".into(), &o.fields)?;
    let node_fields = limits.node_fields;
    if node_fields.is_empty() && !o.node_fields.is_empty() {
        return Err((
            "outputs.node_fields".into(),
            "node fields are those of a background grid of nodes: only the Mpm pipeline has one"
                .into(),
        ));
    }
    for (k, f) in o.node_fields.iter().enumerate() {
        if !node_fields.contains(&f.as_str()) {
            return Err((
                format!("outputs.node_fields.{k}"),
                format!(
                    "unknown node field `{f}`; known node fields: {}",
                    node_fields.join(", ")
                ),
            ));
        }
    }
    let inside = |p: &[f64; 3]| (0..3).all(|a| p[a] >= d.lower[a] && p[a] <= d.upper[a]);
    let mut names = std::collections::BTreeSet::new();
    for (i, g) in o.gauges.iter().enumerate() {
        let path = format!("outputs.gauges.{i}");
        if !file_safe(&g.name) || !names.insert(g.name.clone()) {
            return Err((
                format!("{path}.name"),
                format!(
                    "gauge name `{}` must be unique and use only letters, digits, `_` and `-`",
                    g.name
                ),
            ));
        }
        if !inside(&g.point) {
            return Err((
                format!("{path}.point"),
                format!("gauge point {:?} lies outside the domain", g.point),
            ));
        }
        if g.fields.is_empty() {
            return Err((
                format!("{path}.fields"),
                "a gauge needs at least one field".into(),
            ));
        }
        check_fields(format!("{path}.fields"), &g.fields)?;
    }
    let mut names = std::collections::BTreeSet::new();
    for (i, g) in o.particle_gauges.iter().enumerate() {
        let path = format!("outputs.particle_gauges.{i}");
        if !matches!(s.pipeline, Pipeline::Mpm(_) | Pipeline::IceMpm(_)) {
            return Err((
                path,
                "particle gauges follow particles: they need the Mpm or IceMpm pipeline".into(),
            ));
        }
        if !file_safe(&g.name) || !names.insert(g.name.clone()) {
            return Err((
                format!("{path}.name"),
                format!(
                    "particle gauge name `{}` must be unique and use only letters, digits, `_` and `-`",
                    g.name
                ),
            ));
        }
        check_region(&format!("{path}.region"), &g.region)?;
        if let Some(m) = &g.material {
            if s.materials.get(m).and_then(|m| m.model.as_ref()).is_none() {
                return Err((
                    format!("{path}.material"),
                    format!(
                        "particle gauge `{}`: `{m}` is not a particle material (one with a constitutive `model`); known materials: {}",
                        g.name,
                        known_materials()
                    ),
                ));
            }
        }
        if g.quantities.is_empty() {
            return Err((
                format!("{path}.quantities"),
                format!("particle gauge `{}` needs at least one quantity", g.name),
            ));
        }
    }
    let mut names = std::collections::BTreeSet::new();
    for (i, l) in o.lineouts.iter().enumerate() {
        let path = format!("outputs.lineouts.{i}");
        if !file_safe(&l.name) || !names.insert(l.name.clone()) {
            return Err((
                format!("{path}.name"),
                format!(
                    "line-out name `{}` must be unique and use only letters, digits, `_` and `-`",
                    l.name
                ),
            ));
        }
        if !inside(&l.from) {
            return Err((
                format!("{path}.from"),
                format!("line-out start {:?} lies outside the domain", l.from),
            ));
        }
        if !inside(&l.to) {
            return Err((
                format!("{path}.to"),
                format!("line-out end {:?} lies outside the domain", l.to),
            ));
        }
        if l.points == 0 {
            return Err((
                format!("{path}.points"),
                "a line-out needs at least one point".into(),
            ));
        }
        check_fields(format!("{path}.fields"), &l.fields)?;
    }
    if o.checkpoint_every == Some(0) {
        return Err((
            "outputs.checkpoint_every".into(),
            "checkpoint interval must be at least 1 step".into(),
        ));
    }
    Ok(())
}
