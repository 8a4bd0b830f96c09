//! Checks of a parsed scenario that serde cannot express. Each problem is
//! reported with the path of the offending field so the caller can point at
//! its line and column.

use crate::build::PipelineLimits;
use crate::config::{BoundaryConfig, Region, Scenario};

/// A validation problem: the field path and the message.
pub type Problem = (String, String);

/// A material's `thermal` (at `path`) is for a pipeline whose particles
/// conduct heat (`PipelineLimits::heat_conduction`: the particles of
/// `Mpm`, the solids of `IceMpm`), whose sections check their materials'
/// entries (`brisance_couple::{MpmConfig, IceMpmConfig}`): the heat
/// conduction is a part of the MPM step and of no other method.
fn check_thermal_use(s: &Scenario, limits: &PipelineLimits, path: &str) -> Result<(), Problem> {
    if limits.heat_conduction {
        return Ok(());
    }
    Err((
        path.into(),
        format!(
            "the {} pipeline has no heat conduction; `thermal` is the heat conduction inside the particles of `Mpm` and the solids of `IceMpm`",
            s.pipeline.name()
        ),
    ))
}

/// The axisymmetric grid's shape (one cell along z, r ≥ 0, a reflective
/// axis) and which pipelines run it.
fn check_geometry(s: &Scenario) -> Result<(), Problem> {
    let d = &s.domain;
    if !d.geometry.is_axisymmetric() {
        return Ok(());
    }
    // Each section says which grids it has no form on (bond-based PD and
    // the MSDM lattice: (r, z)); the Mpm section checks its reservoir
    // faces on (r, z) grids and the bridge its split along z with their
    // options.
    let g = d.geometry;
    if let Some(why) = s.pipeline.spec().unsupported(g) {
        return Err(("domain.geometry".into(), why.into()));
    }
    if d.cells[2] != 1 {
        return Err((
            "domain.cells.2".into(),
            format!(
                "an Axisymmetric grid is (r, z) with one cell along the third direction, got {}",
                d.cells[2]
            ),
        ));
    }
    if !(d.lower[0] >= 0.0) {
        return Err((
            "domain.lower.0".into(),
            format!(
                "an Axisymmetric grid's x is the radius r, which starts at r ≥ 0, got {}",
                d.lower[0]
            ),
        ));
    }
    if d.lower[0] == 0.0 && !matches!(s.boundaries.x_low, BoundaryConfig::Reflective) {
        return Err((
            "boundaries.x_low".into(),
            format!(
                "x_low is the axis of symmetry r = 0 of an Axisymmetric grid and must be `Reflective`, got `{}`",
                s.boundaries.x_low.name()
            ),
        ));
    }
    Ok(())
}

fn check_region(path: &str, r: &Region) -> Result<(), Problem> {
    r.validate()
        .map_err(|e| (format!("{path}.{}", e.field), e.message))
}

/// Whether a (validated) region may share a point with the box
/// `lower ..= upper`: false only where a bounding box of the region (for a
/// half-space, its plane) proves it does not.
fn may_meet_box(region: &Region, lower: &[f64; 3], upper: &[f64; 3]) -> bool {
    let overlaps =
        |lo: [f64; 3], hi: [f64; 3]| (0..3).all(|a| lo[a] <= upper[a] && hi[a] >= lower[a]);
    let around_segment = |base: &[f64; 3], axis: &[f64; 3], length: f64, radius: f64| {
        let norm = axis.iter().map(|c| c * c).sum::<f64>().sqrt();
        let end: [f64; 3] = std::array::from_fn(|a| base[a] + axis[a] / norm * length);
        overlaps(
            std::array::from_fn(|a| base[a].min(end[a]) - radius),
            std::array::from_fn(|a| base[a].max(end[a]) + radius),
        )
    };
    match region {
        Region::Everywhere => true,
        Region::Box { min, max } => overlaps(*min, *max),
        Region::Sphere { centre, radius } => overlaps(
            std::array::from_fn(|a| centre[a] - radius),
            std::array::from_fn(|a| centre[a] + radius),
        ),
        Region::Cylinder {
            base,
            axis,
            radius,
            length,
        } => around_segment(base, axis, *length, *radius),
        Region::Shell {
            base,
            axis,
            outer_radius,
            length,
            ..
        } => around_segment(base, axis, *length, *outer_radius),
        Region::HalfSpace { point, normal } => (0..8).any(|corner: usize| {
            (0..3)
                .map(|a| {
                    let x = if corner >> a & 1 == 1 {
                        upper[a]
                    } else {
                        lower[a]
                    };
                    (x - point[a]) * normal[a]
                })
                .sum::<f64>()
                >= 0.0
        }),
    }
}

/// The materials a scenario defines but nothing in it names (neither a
/// region, the pipeline, a face nor an output): a warning each, with the
/// material's field path. A material is counted as used when its quoted
/// name appears anywhere in the scenario outside `materials`.
pub fn unused_materials(s: &Scenario) -> Vec<Problem> {
    let mut rest = s.clone();
    rest.materials.clear();
    let Ok(text) = ron::to_string(&rest) else {
        return Vec::new();
    };
    s.materials
        .keys()
        .filter(|name| !text.contains(&format!("{name:?}")))
        .map(|name| {
            (
                format!("materials.{name}"),
                format!("material `{name}` is defined but nothing uses it"),
            )
        })
        .collect()
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
    // The geometry first: an (r, z) grid's third axis has one cell, which
    // is the thing to say when it has more.
    check_geometry(s)?;
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
    // Each cell holds several f64 fields (40 bytes and more), so 1e10
    // cells is beyond one machine's memory; a count that overflows would
    // panic wherever it is multiplied out.
    const MAX_CELLS: usize = 10_000_000_000;
    let total = d
        .cells
        .iter()
        .try_fold(1usize, |p, &c| p.checked_mul(c))
        .filter(|&n| n <= MAX_CELLS);
    if total.is_none() {
        return Err((
            "domain.cells".into(),
            format!(
                "{:?} cells is more than the {MAX_CELLS:e} a run can hold",
                d.cells
            ),
        ));
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
        if m.thermal.is_some() {
            check_thermal_use(s, limits, &format!("{path}.thermal"))?;
        }
    }
    let known_materials = || {
        s.materials
            .keys()
            .map(|k| format!("`{k}`"))
            .collect::<Vec<_>>()
            .join(", ")
    };
    // Every region's material must exist before the pipelines look it up.
    for (i, r) in s.initial.iter().enumerate() {
        if !s.materials.contains_key(&r.material) {
            return Err((
                format!("initial.{i}.material"),
                format!(
                    "unknown material `{}`; known materials: {}",
                    r.material,
                    known_materials()
                ),
            ));
        }
    }
    s.pipeline.spec().validate(&crate::scene::scene_of(s))?;
    for (face, bc) in s.boundaries.faces() {
        if let BoundaryConfig::Fixed(state) = bc {
            state.check(&format!("boundaries.{face}"))?;
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
        check_region(&format!("{path}.region"), &r.region)?;
        if !may_meet_box(&r.region, &d.lower, &d.upper) {
            return Err((
                format!("{path}.region"),
                format!(
                    "the region lies entirely outside the domain {:?} .. {:?}",
                    d.lower, d.upper
                ),
            ));
        }
        r.state.check(&format!("{path}.state"))?;
        if r.state.material.is_some() {
            return Err((
                format!("{path}.state.material"),
                "a region names its material beside its state (`material: ...`); `material` inside a state is for `Fixed` faces".into(),
            ));
        }
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
    if o.vtk_layout == crate::config::VtkLayout::Patches && !limits.patch_pieces {
        return Err((
            "outputs.vtk_layout".into(),
            "the `Patches` layout writes one piece per patch of a grid: only the Fdm, Ice and IceMpm pipelines split their cells into patches; use `Whole`".into(),
        ));
    }
    if o.checkpoint_layout == crate::config::CheckpointLayout::Patches && !limits.patch_checkpoints
    {
        return Err((
            "outputs.checkpoint_layout".into(),
            "the `Patches` layout writes one checkpoint file per patch of a grid: only the Fdm and Ice pipelines write them; use `Whole`".into(),
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
        if !limits.particle_gauges {
            return Err((
                path,
                format!(
                    "particle gauges follow particles, and the {} pipeline carries none: they need a particle pipeline (Mpm, IceMpm or FdmMpmBridge)",
                    s.pipeline.name()
                ),
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
        // Which materials have particles is the pipeline's to say: its
        // section checks a gauge's `material`.
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
    check_plots(o)
}

/// `outputs.plots`: unique file-safe names, at least one curve each, and
/// every curve a column that one of the gauges writes.
fn check_plots(o: &crate::config::Outputs) -> Result<(), Problem> {
    let mut names = std::collections::BTreeSet::new();
    for (i, p) in o.plots.iter().enumerate() {
        let path = format!("outputs.plots.{i}");
        if !file_safe(&p.name) || !names.insert(p.name.clone()) {
            return Err((
                format!("{path}.name"),
                format!(
                    "plot name `{}` must be unique and use only letters, digits, `_` and `-`",
                    p.name
                ),
            ));
        }
        if p.series.is_empty() {
            return Err((
                format!("{path}.series"),
                format!("plot `{}` needs at least one series", p.name),
            ));
        }
        for (j, r) in p.references.iter().enumerate() {
            if !r.value.is_finite() {
                return Err((
                    format!("{path}.references.{j}.value"),
                    format!("a reference line needs a finite value, got {}", r.value),
                ));
            }
        }
        for (j, c) in p.series.iter().enumerate() {
            let path = format!("{path}.series.{j}");
            let columns = plot_columns(o, &c.from).map_err(|why| (format!("{path}.from"), why))?;
            if !columns.contains(&c.column) {
                return Err((
                    format!("{path}.column"),
                    format!(
                        "`{}` is not a column of that gauge; its columns: {}",
                        c.column,
                        columns.join(", ")
                    ),
                ));
            }
            if !(c.scale.is_finite() && c.scale != 0.0) {
                return Err((
                    format!("{path}.scale"),
                    format!("scale must be finite and non-zero, got {}", c.scale),
                ));
            }
        }
    }
    Ok(())
}

/// The CSV columns (after `time`) of the gauge a plot curve names.
pub(crate) fn plot_columns(
    o: &crate::config::Outputs,
    from: &crate::config::PlotSource,
) -> Result<Vec<String>, String> {
    use crate::config::PlotSource;
    match from {
        PlotSource::Gauge(name) => o
            .gauges
            .iter()
            .find(|g| &g.name == name)
            .map(|g| g.fields.clone())
            .ok_or_else(|| {
                format!(
                    "no point gauge `{name}` in outputs.gauges; gauges: {}",
                    o.gauges
                        .iter()
                        .map(|g| g.name.as_str())
                        .collect::<Vec<_>>()
                        .join(", ")
                )
            }),
        PlotSource::ParticleGauge(name) => o
            .particle_gauges
            .iter()
            .find(|g| &g.name == name)
            .map(|g| brisance_mpm::ParticleSet::columns(&g.quantities))
            .ok_or_else(|| {
                format!(
                    "no particle gauge `{name}` in outputs.particle_gauges; particle gauges: {}",
                    o.particle_gauges
                        .iter()
                        .map(|g| g.name.as_str())
                        .collect::<Vec<_>>()
                        .join(", ")
                )
            }),
    }
}

#[cfg(test)]
mod tests {
    use crate::build::build_solver;
    use crate::load_str;

    const SOD: &str = include_str!("../../../configs/sod.ron");
    const SOD_ICE: &str = include_str!("../../../configs/sod_ice.ron");
    const STICK: &str = include_str!("../../../configs/ratestick_1d.ron");
    const TAYLOR: &str = include_str!("../../../configs/taylor2d.ron");
    const PISTON: &str = include_str!("../../../configs/piston_icempm.ron");
    const BLAST2D: &str = include_str!("../../../configs/blast2d.ron");

    /// `configs/sod.ron` as gas particles (the V-SOD-MPM tube).
    fn sod_mpm(sets: &[&str]) -> Vec<String> {
        let mut all = vec![
            "pipeline=Mpm(shape_function: Linear, ppc: 2)".to_string(),
            "materials.gas=(model: Null(eos: IdealGas(gamma: 1.4, cv: 1.0, rho0: 1.0)))"
                .to_string(),
            "outputs.fields=[\"density\"]".to_string(),
            "outputs.gauges=[]".to_string(),
            "outputs.lineouts=[]".to_string(),
        ];
        all.extend(sets.iter().map(|s| s.to_string()));
        all
    }

    fn sets(s: &[&str]) -> Vec<String> {
        s.iter().map(|s| s.to_string()).collect()
    }

    #[test]
    fn the_open_face_names_load_and_build_for_fdm_ice_and_mpm() {
        let faces = [
            "ZeroGradient",
            "OutflowOnly",
            "Fixed(density: 1.0, velocity: (0.5, 0, 0), pressure: 1.0)",
        ];
        for face in faces {
            let x_low = format!("boundaries.x_low={face}");
            for (name, text, extra) in [
                ("sod", SOD, sets(&[&x_low])),
                ("sod_ice", SOD_ICE, sets(&[&x_low])),
                ("sod_mpm", SOD, sod_mpm(&[&x_low])),
            ] {
                let loaded = load_str(name, text, &extra)
                    .unwrap_or_else(|e| panic!("{name} with {face}: {e}"));
                build_solver(&loaded.scenario)
                    .unwrap_or_else(|e| panic!("{name} with {face}: {e}"));
            }
        }
    }

    #[test]
    fn a_face_a_pipeline_does_not_take_is_a_load_error_listing_what_it_takes() {
        let cases: [(&str, &str, Vec<String>, &str, &str); 6] = [
            (
                "sod",
                SOD,
                sets(&["boundaries.x_low=Wall"]),
                "boundaries.x_low",
                "the Fdm pipeline takes `Outflow`, `ZeroGradient`, `OutflowOnly`, `Reflective`, `Periodic` or `Fixed` faces, not `Wall`; `Wall` is a particle boundary",
            ),
            (
                "taylor2d",
                TAYLOR,
                sets(&["boundaries.x_low=Periodic", "boundaries.x_high=Periodic"]),
                "boundaries.x_low",
                "the Mpm pipeline takes `Outflow`, `ZeroGradient`, `OutflowOnly`, `Fixed`, `Reflective` or `Wall` faces, not `Periodic`",
            ),
            (
                "piston",
                PISTON,
                sets(&["boundaries.x_high=ZeroGradient"]),
                "boundaries.x_high",
                "the IceMpm pipeline takes `Outflow`, `Reflective`, `Wall` or `Periodic` faces, not `ZeroGradient`",
            ),
            (
                "piston",
                PISTON,
                sets(&["boundaries.x_high=OutflowOnly"]),
                "boundaries.x_high",
                "its `Outflow` already holds back",
            ),
            (
                "blast2d",
                BLAST2D,
                sets(&["boundaries=(y_high: ZeroGradient)"]),
                "boundaries.y_high",
                "the FdmMpmBridge pipeline takes `Outflow`, `Reflective` or `Wall` faces, not `ZeroGradient`",
            ),
            (
                "blast2d",
                BLAST2D,
                sets(&["boundaries=(y_high: Fixed(density: 1.2, pressure: 1e5))"]),
                "boundaries.y_high",
                "not `Fixed`",
            ),
        ];
        for (name, text, extra, field, message) in cases {
            let err = load_str(name, text, &extra).unwrap_err();
            assert_eq!(err.field.as_deref(), Some(field), "{name}: {err}");
            assert!(err.message.contains(message), "{name}: {err}");
            assert!(
                err.position.is_some(),
                "{name}: {err} has no line and column"
            );
        }
    }

    /// A `Fixed` face of a pipeline with several materials names its
    /// material; one it does not carry is an error at that field.
    #[test]
    fn a_fixed_face_names_its_material_where_there_are_several() {
        let fixed = "boundaries.x_high=Fixed(density: 1160.045, temperature: 298.15)";
        let err = load_str("stick", STICK, &sets(&[fixed])).unwrap_err();
        assert_eq!(err.field.as_deref(), Some("boundaries.x_high"));
        assert!(err.message.contains("`anfo`, `products`"), "{err}");
        let named = "boundaries.x_high=Fixed(material: \"anfo\", density: 1160.045, velocity: (-90, 0, 0), temperature: 298.15)";
        let loaded = load_str("stick", STICK, &sets(&[named])).unwrap();
        build_solver(&loaded.scenario).unwrap();
        let unknown = "boundaries.x_high=Fixed(material: \"air\", density: 1.0, temperature: 300)";
        let err = load_str("stick", STICK, &sets(&[unknown])).unwrap_err();
        assert_eq!(err.field.as_deref(), Some("boundaries.x_high.material"));
        assert!(
            err.message.contains("not a material of this pipeline"),
            "{err}"
        );
        // The Fdm pipeline's one gas may be named, no other.
        let other = "boundaries.x_low=Fixed(material: \"air\", density: 1.0, pressure: 1.0)";
        let err = load_str("sod", SOD, &sets(&[other])).unwrap_err();
        assert_eq!(err.field.as_deref(), Some("boundaries.x_low.material"));
        // An initial region names its material beside its state.
        let err = load_str("sod", SOD, &sets(&["initial.0.state.material=\"gas\""])).unwrap_err();
        assert_eq!(err.field.as_deref(), Some("initial.0.state.material"));
    }

    /// MPM particles that enter through a `Fixed` face push with the
    /// pressure of their equation of state: a model without one is refused.
    #[test]
    fn an_mpm_fixed_face_needs_a_material_with_an_equation_of_state() {
        let fixed = "boundaries.x_low=Fixed(density: 8930, temperature: 300)";
        let err = load_str("taylor2d", TAYLOR, &sets(&[fixed])).unwrap_err();
        assert_eq!(err.field.as_deref(), Some("boundaries.x_low"), "{err}");
        assert!(err.message.contains("equation of state"), "{err}");
    }
}
