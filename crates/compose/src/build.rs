//! Assembling a solver from a validated scenario.

use brisance_core::Solver;
use brisance_grid::Level;
use brisance_scene::{PipelineSpec, Scene};

use brisance_constitutive::MaterialModel;
use brisance_core::Material;
use brisance_mpm::{
    GridBoundary, HeatConduction, MaterialId, MpmOptions, MpmSolver, ParticleInit, ParticleSet,
    Particles, Reservoir, ReservoirKind, ReservoirState, SetQuantity, SurfaceLoad,
};

use crate::config::{BoundaryConfig, MpmConfig, Pipeline, Scenario, StateConfig};
use crate::error::ConfigError;

pub use brisance_scene::PipelineLimits;

/// The limits of a scenario's pipeline on its grid.
pub fn pipeline_limits(s: &Scenario) -> PipelineLimits {
    let geometry = s.domain.geometry;
    match &s.pipeline {
        Pipeline::FdmMpmBridge(_) => PipelineLimits {
            fields: &crate::bridge::FIELDS,
            max_cfl: brisance_fdm::MAX_CFL,
            ghost: brisance_fdm::GHOST,
            node_fields: &[],
            patch_pieces: false,
            patch_checkpoints: false,
        },
        Pipeline::Ice(ice) => ice.limits(geometry),
        // The fluids' grid with the particles' node fields; the coupled
        // state is checkpointed whole.
        Pipeline::IceMpm(c) => PipelineLimits {
            node_fields: &MpmSolver::NODE_FIELDS,
            patch_checkpoints: false,
            ..c.ice.limits(geometry)
        },
        Pipeline::Lattice(l) => l.limits(geometry),
        Pipeline::Peridynamics(pd) => pd.limits(geometry),
        Pipeline::Mpm(_) => PipelineLimits {
            fields: &MpmSolver::FIELDS,
            max_cfl: 1.0,
            ghost: 1,
            node_fields: &MpmSolver::NODE_FIELDS,
            patch_pieces: false,
            patch_checkpoints: false,
        },
        Pipeline::Fdm(f) => f.limits(geometry),
    }
}

pub use brisance_fdm::pipeline::primitive_state;

pub(crate) fn located(path: &str, message: String) -> ConfigError {
    ConfigError {
        file: String::new(),
        position: None,
        field: Some(path.into()),
        message,
    }
}

/// A built run: the solver, and for the particle pipeline the particle
/// sets of `outputs.particle_gauges` (in that order). Dereferences to the
/// solver.
pub enum Built {
    /// A solver without particle gauges.
    Solver(Box<dyn Solver>),
    /// The MPM solver and the particle sets of its particle gauges.
    Mpm {
        /// The solver.
        solver: Box<MpmSolver>,
        /// One set per particle gauge.
        particle_gauges: Vec<ParticleSet>,
    },
    /// The coupled ICE–MPM solver and the particle sets of its gauges.
    IceMpm {
        /// The solver.
        solver: Box<brisance_couple::IceMpm>,
        /// One set per particle gauge (of the solid's particles).
        particle_gauges: Vec<ParticleSet>,
    },
    /// The FDM–MPM bridge and the particle sets of its gauges.
    Bridge {
        /// The solver.
        solver: Box<dyn crate::bridge::BridgeSolver>,
        /// One set per particle gauge (of the MPM region's particles).
        particle_gauges: Vec<ParticleSet>,
    },
}

impl std::ops::Deref for Built {
    type Target = dyn Solver;
    fn deref(&self) -> &Self::Target {
        match self {
            Built::Solver(s) => s.as_ref(),
            Built::Mpm { solver, .. } => solver.as_ref(),
            Built::IceMpm { solver, .. } => solver.as_ref(),
            Built::Bridge { solver, .. } => solver.as_ref(),
        }
    }
}

impl std::ops::DerefMut for Built {
    fn deref_mut(&mut self) -> &mut Self::Target {
        match self {
            Built::Solver(s) => s.as_mut(),
            Built::Mpm { solver, .. } => solver.as_mut(),
            Built::IceMpm { solver, .. } => solver.as_mut(),
            Built::Bridge { solver, .. } => solver.as_mut(),
        }
    }
}

impl Built {
    /// The solver alone.
    pub fn into_solver(self) -> Box<dyn Solver> {
        match self {
            Built::Solver(s) => s,
            Built::Mpm { solver, .. } => solver,
            Built::IceMpm { solver, .. } => solver,
            Built::Bridge { solver, .. } => solver,
        }
    }

    /// Samples particle gauge `k` (its set averages of `quantities`, see
    /// [`ParticleSet::sample`]) into `out`; false when there is no such
    /// gauge.
    pub fn sample_particle_gauge(
        &self,
        k: usize,
        quantities: &[SetQuantity],
        out: &mut Vec<f64>,
    ) -> bool {
        match self {
            Built::Mpm {
                solver,
                particle_gauges,
            } if k < particle_gauges.len() => {
                particle_gauges[k].sample(solver, quantities, out);
                true
            }
            Built::IceMpm {
                solver,
                particle_gauges,
            } if k < particle_gauges.len() => {
                particle_gauges[k].sample(solver.mpm(), quantities, out);
                true
            }
            Built::Bridge {
                solver,
                particle_gauges,
            } if k < particle_gauges.len() => {
                particle_gauges[k].sample(solver.mpm(), quantities, out);
                true
            }
            _ => false,
        }
    }
}

/// Builds the solver a scenario describes. Errors carry the field path;
/// the caller fills in the file and position.
pub fn build_solver(s: &Scenario) -> Result<Box<dyn Solver>, ConfigError> {
    build(s).map(Built::into_solver)
}

/// Builds the solver a scenario describes with its particle gauges. Errors
/// carry the field path; the caller fills in the file and position.
pub fn build(s: &Scenario) -> Result<Built, ConfigError> {
    match &s.pipeline {
        Pipeline::Fdm(fdm) => fdm
            .build(&crate::scene::scene_of(s))
            .map(Built::Solver)
            .map_err(|e| located(&e.field, e.message)),
        Pipeline::Mpm(mpm) => build_mpm(s, mpm),
        Pipeline::Peridynamics(pd) => build_owned(pd, s),
        Pipeline::Lattice(l) => build_owned(l, s),
        Pipeline::FdmMpmBridge(b) => crate::bridge::build(s, b)
            .map(|(solver, particle_gauges)| Built::Bridge {
                solver,
                particle_gauges,
            })
            .map_err(|(path, message)| located(&path, message)),
        Pipeline::IceMpm(c) => crate::ice_mpm::build(s, c),
        Pipeline::Ice(ice) => build_owned(ice, s),
    }
}

/// The solver of a pipeline whose crate owns its section
/// ([`PipelineSpec`]), built from the scenario's [`crate::scene`].
fn build_owned<P: PipelineSpec>(p: &P, s: &Scenario) -> Result<Built, ConfigError>
where
    P::Solver: Solver + 'static,
{
    p.build(&crate::scene::scene_of(s))
        .map(|solver| Built::Solver(Box::new(solver)))
        .map_err(|e| located(&e.field, e.message))
}

/// A one-paragraph description of the assembled pipeline (for `check`).
pub fn describe(s: &Scenario) -> String {
    match &s.pipeline {
        Pipeline::Fdm(fdm) => fdm.describe(&crate::scene::scene_of(s)),
        Pipeline::Mpm(mpm) => describe_mpm(s, mpm),
        Pipeline::Peridynamics(pd) => pd.describe(&crate::scene::scene_of(s)),
        Pipeline::Lattice(l) => l.describe(&crate::scene::scene_of(s)),
        Pipeline::Ice(ice) => ice.describe(&crate::scene::scene_of(s)),
        Pipeline::IceMpm(c) => crate::ice_mpm::describe(s, c),
        Pipeline::FdmMpmBridge(b) => crate::bridge::describe(s, b),
    }
}

/// The temperature and specific internal energy of particles of `model`
/// in state `st` (`path` for the errors), from whichever the state gives,
/// through the model's equation of state when it has one.
fn particle_thermodynamics(
    model: &MaterialModel,
    st: &StateConfig,
    path: &str,
) -> Result<(f64, f64), ConfigError> {
    Ok(
        match (
            model.eos(),
            st.temperature,
            st.specific_internal_energy,
            st.pressure,
        ) {
            (Some(eos), Some(t), None, None) => (
                t,
                eos.specific_internal_energy_from_temperature(st.density, t),
            ),
            (Some(eos), None, Some(e), None) => (eos.temperature(st.density, e), e),
            (Some(eos), None, None, Some(p)) => {
                let e = eos
                    .specific_internal_energy(st.density, p)
                    .map_err(|e| located(&format!("{path}.pressure"), e.to_string()))?;
                (eos.temperature(st.density, e), e)
            }
            (None, Some(t), None, None) => (t, 0.0),
            _ => {
                return Err(located(
                    path,
                    "this material has no equation of state: give its `temperature`".into(),
                ))
            }
        },
    )
}

/// Builds the MPM solver: every sub-cell point (ppc per direction) inside an
/// initial region becomes a particle of that region's material (the last
/// region containing the point wins, as for cells). Each particle gauge
/// selects the particles that start in its region (and material); an empty
/// selection is an error naming the gauge.
fn build_mpm(s: &Scenario, mpm: &MpmConfig) -> Result<Built, ConfigError> {
    let (mut solver, particle_gauges) = mpm_parts(&crate::scene::scene_of(s), mpm, false)?;
    // The particle updates spread over the ranks of the run
    // (docs/cluster.md); nothing changes on one rank.
    solver.distribute(brisance_grid::comm::world());
    Ok(Built::Mpm {
        solver: Box::new(solver),
        particle_gauges,
    })
}

/// The MPM solver of the scene `s` (every initial region of a material with
/// a constitutive model becomes particles) and the particle sets of its
/// gauges. A region of a material without one is refused at its
/// `material`, unless `fluids_beside` (the coupled pipelines, whose other
/// regions are the fluids'), which leaves it out; errors name a region by
/// its index in the scenario's `initial`.
pub(crate) fn mpm_parts(
    s: &Scene<'_>,
    mpm: &MpmConfig,
    fluids_beside: bool,
) -> Result<(MpmSolver, Vec<ParticleSet>), ConfigError> {
    let d = &s.domain;
    let level = Level::new(d.lower, d.upper, d.cells, d.patches, 1)
        .map_err(|e| located("domain.patches", e.to_string()))?;
    let grid = level.geometry;
    // Materials with a constitutive model, numbered in name order.
    let names: Vec<&str> = s
        .materials
        .iter()
        .filter(|m| m.model.is_some())
        .map(|m| m.name)
        .collect();
    let models: Vec<MaterialModel> = s
        .materials
        .iter()
        .filter_map(|m| m.model.cloned())
        .collect();
    let stride = models.iter().map(|m| m.history_len()).max().unwrap_or(0);
    let mut regions = Vec::with_capacity(s.initial.len());
    for (i, r) in s.initial.iter().enumerate() {
        let path = format!("initial.{i}");
        let Some(id) = names.iter().position(|n| *n == r.material) else {
            if fluids_beside {
                continue;
            }
            return Err(located(
                &format!("{path}.material"),
                "the material has no constitutive `model`".into(),
            ));
        };
        let (temperature, energy) =
            particle_thermodynamics(&models[id], r.state, &format!("{path}.state"))?;
        regions.push((r, MaterialId(id as u16), temperature, energy));
    }
    let ppc = mpm.ppc;
    let active: [bool; 3] = std::array::from_fn(|a| d.cells[a] > 1);
    let per_axis: [usize; 3] = std::array::from_fn(|a| if active[a] { ppc } else { 1 });
    let sub_volume =
        grid.spacing.iter().product::<f64>() / per_axis.iter().product::<usize>() as f64;
    let remap = mpm
        .remap
        .as_ref()
        .map(|r| brisance_couple::GasRemap::new(r, &names, &models, &grid, d.geometry))
        .transpose()
        .map_err(|(path, message)| located(&path, message))?;
    let mut particles = Particles::new(stride);
    let history = vec![0.0; stride];
    for k in 0..d.cells[2] {
        for j in 0..d.cells[1] {
            for i in 0..d.cells[0] {
                for sk in 0..per_axis[2] {
                    for sj in 0..per_axis[1] {
                        for si in 0..per_axis[0] {
                            let idx = [i, j, k];
                            let sub = [si, sj, sk];
                            let x: [f64; 3] = std::array::from_fn(|a| {
                                grid.origin[a]
                                    + (idx[a] as f64 + (sub[a] as f64 + 0.5) / per_axis[a] as f64)
                                        * grid.spacing[a]
                            });
                            let Some(&(r, material, temperature, energy)) =
                                regions.iter().rev().find(|(r, ..)| r.region.contains(x))
                            else {
                                continue;
                            };
                            // A ring about the axis on an (r, z) grid: its
                            // sub-cell's cross-section swept through 2π at
                            // its centre's radius (exact for the ring).
                            let sub_volume = if d.geometry.is_axisymmetric() {
                                2.0 * std::f64::consts::PI * x[0] * sub_volume / grid.spacing[2]
                            } else {
                                sub_volume
                            };
                            let remapped = match &remap {
                                Some(g) if g.replaces(material) => g
                                    .particle(x, sub_volume)
                                    .map_err(|m| located("pipeline.remap.file", m))?,
                                _ => None,
                            };
                            let init = remapped.unwrap_or(ParticleInit {
                                position: x,
                                velocity: r.state.velocity,
                                mass: r.state.density * sub_volume,
                                volume: sub_volume,
                                temperature,
                                specific_internal_energy: energy,
                                material,
                                ..Default::default()
                            });
                            particles
                                .push(&init, &history)
                                .map_err(|e| located("initial", e.to_string()))?;
                        }
                    }
                }
            }
        }
    }
    if particles.is_empty() {
        return Err(located(
            "initial",
            "no particle lies in any initial region".into(),
        ));
    }
    // Every open face lets particles leave (GridBoundary::Outflow); the
    // ones that let matter in have a reservoir beyond them.
    let boundary = |bc: &BoundaryConfig| match bc {
        BoundaryConfig::Wall => GridBoundary::Fixed,
        BoundaryConfig::Reflective => GridBoundary::Symmetry,
        _ => GridBoundary::Outflow,
    };
    let faces = s.boundaries.faces();
    let mut reservoirs = [None; 6];
    for (k, (face, bc)) in faces.iter().enumerate() {
        let kind = match bc {
            BoundaryConfig::ZeroGradient => ReservoirKind::ZeroGradient,
            BoundaryConfig::OutflowOnly => ReservoirKind::OutflowOnly,
            BoundaryConfig::Fixed(st) => {
                let path = format!("boundaries.{face}");
                let particle_names: Vec<String> = names.iter().map(|n| n.to_string()).collect();
                let name = brisance_scene::fixed_face_material(
                    face,
                    st,
                    &particle_names,
                    "particle material",
                )
                .map_err(|e| located(&e.field, e.message))?;
                let id = names
                    .iter()
                    .position(|n| *n == name)
                    .expect("a particle material");
                let model = &models[id];
                let (temperature, energy) = particle_thermodynamics(model, st, &path)?;
                let eos = model.eos().ok_or_else(|| {
                    located(&path, format!("`{name}`'s model has no equation of state for the pressure of the particles it brings in"))
                })?;
                let p = eos.pressure(st.density, energy);
                ReservoirKind::Fixed(ReservoirState {
                    material: MaterialId(id as u16),
                    density: st.density,
                    velocity: st.velocity,
                    specific_internal_energy: energy,
                    temperature,
                    stress: [-p, -p, -p, 0.0, 0.0, 0.0],
                })
            }
            _ => continue,
        };
        reservoirs[k] = Some(Reservoir { kind, ppc });
    }
    let options = MpmOptions {
        shape: mpm.shape_function,
        scheme: mpm.scheme,
        cfl: s.cfl,
        gravity: mpm.gravity,
        boundaries: std::array::from_fn(|k| boundary(faces[k].1)),
        mass_cutoff: mpm.mass_cutoff,
        bulk_viscosity: mpm.bulk_viscosity.option(),
        anti_locking: mpm.anti_locking,
        reservoirs,
        geometry: d.geometry,
        ..Default::default()
    };
    let mut particle_gauges = Vec::with_capacity(s.particle_gauges.len());
    for (i, g) in s.particle_gauges.iter().enumerate() {
        let material = match g.material {
            Some(name) => Some(
                names
                    .iter()
                    .position(|n| *n == name)
                    .map(|id| MaterialId(id as u16))
                    .ok_or_else(|| {
                        located(
                            &format!("outputs.particle_gauges.{i}.material"),
                            format!("`{name}` has no constitutive `model`"),
                        )
                    })?,
            ),
            None => None,
        };
        let set = ParticleSet::select(&particles, |x, m| {
            g.region.contains(x) && (material.is_none() || material == Some(m))
        });
        if set.is_empty() {
            let of = g
                .material
                .map_or(String::new(), |m| format!(" of material `{m}`"));
            return Err(located(
                &format!("outputs.particle_gauges.{i}.region"),
                format!(
                    "particle gauge `{}`: no particle{of} starts inside its region",
                    g.name
                ),
            ));
        }
        particle_gauges.push(set);
    }
    let material_id = |name: &Option<String>, path: &str| -> Result<_, ConfigError> {
        name.as_ref()
            .map(|n| {
                names
                    .iter()
                    .position(|m| *m == n.as_str())
                    .map(|id| MaterialId(id as u16))
                    .ok_or_else(|| located(path, format!("`{n}` has no constitutive `model`")))
            })
            .transpose()
    };
    let mut loads = Vec::with_capacity(mpm.surface_loads.len());
    for (i, l) in mpm.surface_loads.iter().enumerate() {
        let path = format!("pipeline.surface_loads.{i}");
        let material = material_id(&l.material, &format!("{path}.material"))?;
        let set = ParticleSet::select(&particles, |x, m| {
            l.region.contains(x) && (material.is_none() || material == Some(m))
        });
        if set.is_empty() {
            let of = l
                .material
                .as_ref()
                .map_or(String::new(), |m| format!(" of material `{m}`"));
            return Err(located(
                &format!("{path}.region"),
                format!(
                    "surface load `{}`: no particle{of} starts inside its region",
                    l.name
                ),
            ));
        }
        let norm = l.normal.iter().map(|c| c * c).sum::<f64>().sqrt();
        let normal = l.normal.map(|c| c / norm);
        // The particle spacing along the normal: l_d = Δx_d / ppc_d.
        let thickness = l.thickness.unwrap_or_else(|| {
            1.0 / (0..3)
                .map(|d| normal[d].abs() * per_axis[d] as f64 / grid.spacing[d])
                .sum::<f64>()
        });
        loads.push(SurfaceLoad {
            set,
            load: l.load,
            normal,
            thickness,
            history: l.history.clone(),
        });
    }
    let heat = heat_conduction(s, &names, &models)?;
    let solver = MpmSolver::new(level, models, particles, options)
        .map_err(|e| located("pipeline", e.to_string()))?
        .with_surface_loads(loads)
        .map_err(|e| match e {
            brisance_mpm::MpmSetupError::SurfaceLoad { index, detail } => located(
                &format!("pipeline.surface_loads.{index}"),
                format!("surface load `{}`: {detail}", mpm.surface_loads[index].name),
            ),
            other => located("pipeline", other.to_string()),
        })?;
    let solver = match heat {
        Some(heat) => solver
            .with_heat_conduction(heat)
            .map_err(|e| located("materials", e.to_string()))?,
        None => solver,
    };
    Ok((solver, particle_gauges))
}

/// The heat-conduction option of the particle materials `names` (with
/// their `models`, in material-id order) from their `thermal` entries: k
/// and c_v per material, k = 0 for a material without one; `None` when
/// no material has one (the solver is then built as without the option).
fn heat_conduction(
    s: &Scene<'_>,
    names: &[&str],
    models: &[MaterialModel],
) -> Result<Option<HeatConduction>, ConfigError> {
    let thermal = |name: &str| s.material(name).and_then(|m| m.thermal);
    if names.iter().all(|n| thermal(n).is_none()) {
        return Ok(None);
    }
    let mut heat = HeatConduction::default();
    for (name, model) in names.iter().zip(models) {
        let (k, c) = match thermal(name) {
            Some(t) => {
                crate::validate::thermal_properties(&format!("materials.{name}.thermal"), t, model)
                    .map_err(|(path, message)| located(&path, message))?;
                (t.conductivity, t.specific_heat)
            }
            None => (0.0, None),
        };
        heat.conductivity.push(k);
        heat.specific_heat.push(c);
    }
    Ok(Some(heat))
}

fn describe_mpm(s: &Scenario, mpm: &MpmConfig) -> String {
    let d = &s.domain;
    let dims = d.cells.iter().filter(|&&c| c > 1).count();
    let materials: Vec<String> = s
        .materials
        .iter()
        .filter_map(|(n, m)| {
            m.model
                .as_ref()
                .map(|model| format!("`{n}` ({})", model.name()))
        })
        .collect();
    format!(
        "scenario `{}`: Mpm pipeline (explicit MPM, seed 001 §2.2), {dims}D, {:?} shape functions, {:?}, {} particles per cell per direction, bulk viscosity {}\n  \
         grid: {} x {} x {} cells from {:?} to {:?} m\n  \
         materials: {}\n  \
         time: to {} s at cfl {}\n  \
         boundaries: {}\n  \
         initial regions: {}, surface loads: {}\n  \
         outputs: interval {:?}, fields [{}], {} gauges, {} particle gauges, {} line-outs, checkpoints every {:?} steps",
        s.name,
        mpm.shape_function,
        mpm.scheme,
        mpm.ppc,
        match mpm.bulk_viscosity.option() {
            None => "off".to_string(),
            Some(v) => format!("Q1 = {}, Q2 = {}", v.quadratic, v.linear),
        },
        d.cells[0],
        d.cells[1],
        d.cells[2],
        d.lower,
        d.upper,
        materials.join(", "),
        s.time.end,
        s.time.cfl,
        s.boundaries.summary(),
        s.initial.len(),
        mpm.surface_loads.len(),
        s.outputs.interval,
        s.outputs.fields.join(", "),
        s.outputs.gauges.len(),
        s.outputs.particle_gauges.len(),
        s.outputs.lineouts.len(),
        s.outputs.checkpoint_every,
    )
}

#[cfg(test)]
mod tests;
