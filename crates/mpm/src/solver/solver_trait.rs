//! The [`Solver`] implementation of [`MpmSolver`], with the checkpoint it
//! saves and the cell fields it outputs.

use super::{particle_energy, MpmSolver, CELL_FIELDS, MPM_NODE_FIELDS};
use crate::viscosity::BulkViscosityState;
use crate::{MaterialId, Particles, ShapeFunction};
use brisance_core::{AxisWindow, CellData, ConservationTotals, Material, Solver, SolverError};
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

/// What a checkpoint holds: every particle array, time, step count and the
/// outflow totals.
#[derive(Serialize, Deserialize)]
struct SavedState {
    time: f64,
    steps: u64,
    cells: [usize; 3],
    history_stride: usize,
    outflow: ConservationTotals,
    bulk_viscosity: Vec<BulkViscosityState>,
    ids: Vec<u32>,
    external_work: f64,
    position: Vec<[f64; 3]>,
    velocity: Vec<[f64; 3]>,
    mass: Vec<f64>,
    initial_volume: Vec<f64>,
    volume: Vec<f64>,
    deformation_gradient: Vec<[f64; 9]>,
    stress: Vec<[f64; 6]>,
    temperature: Vec<f64>,
    specific_internal_energy: Vec<f64>,
    material: Vec<MaterialId>,
    history: Vec<f64>,
    failed: Vec<bool>,
    /// The reservoirs' phases ([`Reservoirs::phases`]).
    ///
    /// [`Reservoirs::phases`]: crate::inflow::Reservoirs::phases
    reservoir_phases: Vec<Vec<f64>>,
}

impl MpmSolver {
    /// The half-widths per axis of particle `p`'s domain in the cell
    /// estimator: its GIMP domain as the transfers form it (uGIMP's l_p,
    /// cpGIMP's l_p0 F_ii, from the ring's cross-section on an (r, z)
    /// grid), zero on an axis of one cell, and zero on every axis for the
    /// shapes without a domain (linear, B-spline) and for the load-only
    /// particles, which the transfers treat as points too.
    fn domain_half_widths(&self, p: usize) -> [f64; 3] {
        let shape = self.options.shape;
        if !shape.is_gimp() {
            return [0.0; 3];
        }
        let (first, count) = self.work.load_only;
        let id = self.ids[p];
        if id >= first && id - first < count {
            return [0.0; 3];
        }
        let ps = &self.particles;
        let map = &self.work.map;
        let f = &ps.deformation_gradient[p];
        let v0 = map.planar_volume(ps.initial_volume[p], ps.position[p], f);
        let l = if shape == ShapeFunction::CpGimp {
            map.deformed_half_width(v0, f)
        } else {
            map.half_width(v0).map(|l| [l; 3])
        };
        // The step checked the domain; one it would refuse counts as a
        // point here rather than failing an output.
        let l = l.unwrap_or([0.0; 3]);
        let cells = self.level.geometry.cells;
        std::array::from_fn(|d| if cells[d] > 1 { l[d] } else { 0.0 })
    }

    /// The cells a particle at `x` with domain half-widths `l` shares its
    /// mass with along axis `d`, as an inclusive index range: the cell
    /// that contains `x` for a point (the rule of
    /// `UniformGridGeometry::cell_containing`), every cell its domain
    /// overlaps otherwise, clipped to the grid.
    #[inline]
    fn axis_cells(&self, d: usize, x: f64, l: f64) -> (usize, usize) {
        let g = &self.level.geometry;
        let n = g.cells[d];
        let index = |y: f64| {
            let s = ((y - g.origin[d]) / g.spacing[d]).clamp(0.0, n as f64);
            (s.floor() as usize).min(n - 1)
        };
        if l == 0.0 {
            let i = index(x);
            (i, i)
        } else {
            (index(x - l), index(x + l))
        }
    }

    /// The share of a particle's domain (centre `x`, half-width `l`) that
    /// lies in cell `i` along axis `d`: 1 or 0 for a point (in the cell of
    /// [`MpmSolver::axis_cells`] or not), the overlap of [x − l, x + l]
    /// with the cell over 2l otherwise: the planar share, the one GIMP's
    /// weights integrate, on an (r, z) grid as well.
    #[inline]
    fn axis_share(&self, d: usize, x: f64, l: f64, i: usize) -> f64 {
        if l == 0.0 {
            let (c, _) = self.axis_cells(d, x, 0.0);
            return if c == i { 1.0 } else { 0.0 };
        }
        let g = &self.level.geometry;
        let lo = g.origin[d] + i as f64 * g.spacing[d];
        let hi = lo + g.spacing[d];
        let a = (x - l).max(lo);
        let b = (x + l).min(hi);
        if b > a {
            (b - a) / (2.0 * l)
        } else {
            0.0
        }
    }

    /// The volume of a cell in column `i` along x: the box on a Cartesian
    /// grid, the ring π Δr (2 r_lo + Δr) Δz on an (r, z) one, where the
    /// particles' masses are the rings' (`Geometry::cell_volume`).
    #[inline]
    fn cell_volume(&self, i: usize) -> f64 {
        self.options
            .geometry
            .column_cell_volume(&self.level.geometry, i)
    }

    /// The cell fields `names` on the whole grid: in each cell the
    /// mass-weighted mean of the particles' quantities, each particle
    /// weighted by m_p times the share of its domain in the cell (the
    /// whole particle in the cell that holds its centre for the shapes
    /// without a domain), and the mass density Σ m_p share / V_cell.
    fn cell_fields(&self, names: &[usize]) -> Vec<Vec<f64>> {
        let grid = &self.level.geometry;
        let n = grid.cell_count();
        let mut mass = vec![0.0; n];
        let mut sums = vec![vec![0.0; n]; names.len()];
        let ps = &self.particles;
        for p in 0..ps.len() {
            let x = ps.position[p];
            if grid.cell_containing(x).is_none() {
                continue;
            }
            let l = self.domain_half_widths(p);
            let range: [(usize, usize); 3] =
                std::array::from_fn(|d| self.axis_cells(d, x[d], l[d]));
            let m = ps.mass[p];
            for k in range[2].0..=range[2].1 {
                for j in range[1].0..=range[1].1 {
                    for i in range[0].0..=range[0].1 {
                        let w = self.axis_share(0, x[0], l[0], i)
                            * self.axis_share(1, x[1], l[1], j)
                            * self.axis_share(2, x[2], l[2], k);
                        if w == 0.0 {
                            continue;
                        }
                        let c = grid.linear_index([i, j, k]);
                        let mw = m * w;
                        mass[c] += mw;
                        for (s, &f) in sums.iter_mut().zip(names) {
                            s[c] += mw * self.cell_field_quantity(p, f);
                        }
                    }
                }
            }
        }
        for (k, &f) in names.iter().enumerate() {
            for c in 0..n {
                let i = c % grid.cells[0];
                sums[k][c] = cell_field_value(f, sums[k][c], mass[c], self.cell_volume(i));
            }
        }
        sums
    }

    /// The fields `names` of cell `cell` alone, into `out`: the sums of
    /// [`MpmSolver::cell_fields`] for that cell, over the same particles
    /// in the same order with the same shares, so the same bits, without
    /// the whole-grid arrays.
    fn cell_value(&self, cell: [usize; 3], names: &[usize], out: &mut Vec<f64>) {
        let grid = &self.level.geometry;
        out.clear();
        out.resize(names.len(), 0.0);
        let mut mass = 0.0;
        let ps = &self.particles;
        // A domain reaches at most half a cell past its centre; the
        // windows keep a whole cell either side.
        let windows = grid.cell_windows(cell);
        for p in 0..ps.len() {
            let x = ps.position[p];
            if !AxisWindow::admit_all(&windows, x) || grid.cell_containing(x).is_none() {
                continue;
            }
            let l = self.domain_half_widths(p);
            let w = self.axis_share(0, x[0], l[0], cell[0])
                * self.axis_share(1, x[1], l[1], cell[1])
                * self.axis_share(2, x[2], l[2], cell[2]);
            if w == 0.0 {
                continue;
            }
            let mw = ps.mass[p] * w;
            mass += mw;
            for (sum, &f) in out.iter_mut().zip(names) {
                *sum += mw * self.cell_field_quantity(p, f);
            }
        }
        let cell_volume = self.cell_volume(cell[0]);
        for (sum, &f) in out.iter_mut().zip(names) {
            *sum = cell_field_value(f, *sum, mass, cell_volume);
        }
    }

    /// The quantity of cell field `f` (an index into [`CELL_FIELDS`]) that
    /// particle `p` carries, to be mass-weighted: density m/V, a velocity
    /// component, pressure, specific internal energy, or 1 (mass density).
    #[inline]
    fn cell_field_quantity(&self, p: usize, f: usize) -> f64 {
        let ps = &self.particles;
        match f {
            0 => ps.mass[p] / ps.volume[p],
            1..=3 => ps.velocity[p][f - 1],
            4 => self.material_pressure(p),
            5 => ps.specific_internal_energy[p],
            _ => 1.0,
        }
    }

    fn field_indices(fields: &[String]) -> Result<Vec<usize>, SolverError> {
        fields
            .iter()
            .map(|f| {
                CELL_FIELDS.iter().position(|n| n == f).ok_or_else(|| {
                    SolverError::Other(format!(
                        "unknown MPM cell field `{f}`; known fields: {}",
                        CELL_FIELDS.join(", ")
                    ))
                })
            })
            .collect()
    }
}

/// The value of cell field `f` from the cell's mass-weighted sum `sum`
/// and its particle mass `mass`: the mass density mass/V_cell for field 6,
/// the mass-weighted mean otherwise (0 in an empty cell).
#[inline]
fn cell_field_value(f: usize, sum: f64, mass: f64, cell_volume: f64) -> f64 {
    if f == 6 {
        mass / cell_volume
    } else if mass > 0.0 {
        sum / mass
    } else {
        0.0
    }
}

impl Solver for MpmSolver {
    fn name(&self) -> &str {
        "mpm"
    }

    fn time(&self) -> f64 {
        self.time
    }

    /// Δt = cfl · min over active axes Δx_d / max over particles (c_p + |v_p|)
    /// with c_p = [`Material::wave_speed`] at ρ_p = m_p/V_p, e_p. With the
    /// bulk viscosity on, c_p is replaced by the signal speed
    /// Q + √(Q² + c_p²) of [`BulkViscosity::signal_speed`] at the particle's
    /// last tr D. With heat conduction on, Δt is also at most the diffusive
    /// limit cfl / (2 α_max Σ_d 1/Δx_d²) of
    /// [`crate::conduction::diffusive_time_step`], α_max the largest
    /// k V_p / (m_p c_p).
    ///
    /// [`BulkViscosity::signal_speed`]: crate::viscosity::BulkViscosity::signal_speed
    fn stable_dt(&self) -> Result<f64, SolverError> {
        let dx_min = self.smallest_active_spacing();
        let ps = &self.particles;
        let mats = &self.materials;
        let viscosity = self.viscosity_params();
        // max is exact, so the reduction order cannot change the result;
        // a NaN speed is reported.
        let (speed, bad) = (0..ps.len())
            .into_par_iter()
            .map(|p| {
                let (_, c, v) = self.signal_speed(p, viscosity);
                let s = c + v;
                if s.is_finite() {
                    (s, usize::MAX)
                } else {
                    (0.0, p)
                }
            })
            .reduce(|| (0.0, usize::MAX), |a, b| (a.0.max(b.0), a.1.min(b.1)));
        // A fixed reservoir's state enters the next step's particles.
        let speed = speed.max(self.inflow.max_signal_speed(mats));
        if bad != usize::MAX {
            return Err(self.particle_error(bad, "wave speed plus |v| is not finite".into()));
        }
        let dt_wave = if speed > 0.0 && dx_min.is_finite() {
            self.options.cfl * dx_min / speed
        } else {
            f64::INFINITY
        };
        // The diffusive limit of the heat conduction (crate::conduction).
        let (dt_heat, alpha) = self.conduction_step().map_err(|p| {
            self.particle_error(p, "thermal diffusivity k V/(m c) is not finite".into())
        })?;
        let dt = dt_wave.min(dt_heat);
        if !(dt >= self.options.min_dt) {
            let detail = if dt_heat < dt_wave {
                format!("largest thermal diffusivity {alpha} m²/s")
            } else {
                format!("fastest particle signal speed {speed} m/s")
            };
            return Err(SolverError::TimeStepCollapse {
                dt,
                min_dt: self.options.min_dt,
                time: self.time,
                detail,
            });
        }
        Ok(dt)
    }

    /// The particle of the largest signal speed c + |v| (the lowest index
    /// among equals), with its material, position and the speed's parts,
    /// or a fixed inflow reservoir's state or the heat conduction's
    /// diffusive limit where that binds.
    fn time_step_limit(&self) -> Option<String> {
        let ps = &self.particles;
        let viscosity = self.viscosity_params();
        let (speed, p) = (0..ps.len())
            .map(|p| {
                let (_, s, v) = self.signal_speed(p, viscosity);
                (s + v, p)
            })
            .filter(|(s, _)| s.is_finite())
            .fold((f64::NEG_INFINITY, usize::MAX), |a, b| {
                if b.0 > a.0 {
                    b
                } else {
                    a
                }
            });
        let reservoir = self.inflow.max_signal_speed(&self.materials);
        let dx_min = self.smallest_active_spacing();
        let dt_wave = self.options.cfl * dx_min / speed.max(reservoir);
        let (dt_heat, alpha) = self.conduction_step().ok()?;
        if dt_heat < dt_wave {
            return Some(format!(
                "MPM heat conduction: largest thermal diffusivity {alpha:.4e} m²/s"
            ));
        }
        if reservoir > speed.max(0.0) {
            return Some(format!(
                "MPM inflow reservoir: signal speed c + |v| {reservoir:.0} m/s"
            ));
        }
        if p == usize::MAX {
            return None;
        }
        let (c, s, v) = self.signal_speed(p, viscosity);
        let x = ps.position[p];
        let material = ps.material[p].0 as usize;
        let q = if s > c {
            format!(" (bulk viscosity: signal speed {s:.0} m/s)")
        } else {
            String::new()
        };
        Some(format!(
            "MPM particle {p} (material {material}, {}) at ({:.4}, {:.4}, {:.4}) m: \
             sound speed {c:.0} m/s{q} + |v| {v:.0} m/s, density {:.4e} kg/m³, \
             V/V₀ {:.3}",
            self.materials[material].name(),
            x[0],
            x[1],
            x[2],
            ps.mass[p] / ps.volume[p],
            ps.volume[p] / ps.initial_volume[p],
        ))
    }

    fn advance(&mut self, dt: f64) -> Result<(), SolverError> {
        brisance_core::solver::check_step("MPM", dt)?;
        // The whole step runs as one task of the thread pool, so that each of
        // its parallel loops starts on a worker instead of being handed over
        // from this thread and waited for (a wake-up per loop, ~25 a step).
        rayon::scope(|_| self.step(dt))
    }

    fn conservation_totals(&self) -> ConservationTotals {
        let ps = &self.particles;
        let mut t = self.outflow;
        for p in 0..ps.len() {
            let (m, v) = (ps.mass[p], ps.velocity[p]);
            t.mass += m;
            for (q, vc) in t.momentum.iter_mut().zip(v) {
                *q += m * vc;
            }
            t.energy += particle_energy(m, v, ps.specific_internal_energy[p]);
        }
        t
    }

    /// The particles that left the grid, with their state when they left,
    /// less those the reservoirs brought in ([`crate::inflow`]).
    fn outflow_totals(&self) -> Option<ConservationTotals> {
        Some(self.outflow)
    }

    /// One-way faces that held back an inflow: an `OutflowOnly` reservoir
    /// that zeroed an inward velocity, or a plain outflow face whose
    /// boundary particles moved inwards with nothing to follow them.
    fn blocked_inflow(&self) -> [bool; 6] {
        let r = self.inflow.blocked_inflow();
        std::array::from_fn(|f| r[f] || self.held_back[f])
    }

    fn cell_field_names(&self) -> Vec<&'static str> {
        CELL_FIELDS.to_vec()
    }

    fn cell_data(&self, fields: &[String]) -> Result<CellData, SolverError> {
        let idx = Self::field_indices(fields)?;
        let values = self.cell_fields(&idx);
        Ok(CellData {
            geometry: self.level.geometry,
            fields: fields.iter().cloned().zip(values).collect(),
        })
    }

    fn node_field_names(&self) -> Vec<&'static str> {
        MPM_NODE_FIELDS.to_vec()
    }

    /// The node fields of the last step on the whole node lattice (module
    /// doc); node (0, 0, 0) of the data is the lattice's first stored node,
    /// a ghost node below the domain for GIMP and the B-spline.
    fn node_data(&self, fields: &[String]) -> Result<Option<brisance_core::NodeData>, SolverError> {
        let idx: Vec<usize> = fields
            .iter()
            .map(|f| {
                MPM_NODE_FIELDS.iter().position(|n| n == f).ok_or_else(|| {
                    SolverError::Other(format!(
                        "unknown MPM node field `{f}`; known node fields: {}",
                        MPM_NODE_FIELDS.join(", ")
                    ))
                })
            })
            .collect::<Result<_, _>>()?;
        let threshold = self.options.mass_cutoff * self.reference_particle_mass;
        let initial;
        let nodes = if self.steps == 0 {
            initial = self.initial_nodes(threshold);
            &initial
        } else {
            &self.work.nodes
        };
        let grid = &self.level.geometry;
        let lattice = nodes.lattice;
        let values = idx
            .iter()
            .map(|&k| -> Vec<f64> {
                let c = (k + 2) % 3;
                match k {
                    0 => nodes.mass.clone(),
                    1..=3 => nodes.momentum.iter().map(|v| v[c]).collect(),
                    4..=6 => nodes.velocity_new.iter().map(|v| v[c]).collect(),
                    7..=9 => nodes.force.iter().map(|v| v[c]).collect(),
                    10..=12 => nodes.acceleration.iter().map(|v| v[c]).collect(),
                    _ => nodes
                        .mass
                        .iter()
                        .map(|&m| if m > threshold && m > 0.0 { 1.0 } else { 0.0 })
                        .collect(),
                }
            })
            .collect::<Vec<_>>();
        Ok(Some(brisance_core::NodeData {
            origin: std::array::from_fn(|d| {
                grid.origin[d] + lattice.first[d] as f64 * grid.spacing[d]
            }),
            spacing: grid.spacing,
            nodes: lattice.dims,
            fields: fields.iter().cloned().zip(values).collect(),
        }))
    }

    fn external_work(&self) -> Option<f64> {
        Some(self.external_work)
    }

    /// The value of the cell that contains `point` (mass-weighted particle
    /// averages, see the module doc).
    fn sample(
        &self,
        point: [f64; 3],
        fields: &[String],
        out: &mut Vec<f64>,
    ) -> Result<(), SolverError> {
        let grid = &self.level.geometry;
        let idx = Self::field_indices(fields)?;
        let cell = grid.cell_containing(point).ok_or_else(|| {
            SolverError::Other(format!(
                "MPM sample point {point:?} m lies outside the grid"
            ))
        })?;
        self.cell_value(cell, &idx, out);
        Ok(())
    }

    fn work_per_step(&self) -> (f64, &'static str) {
        (self.particles.len() as f64, "particle-steps")
    }

    /// The set averages of particle gauge `k`
    /// ([`crate::ParticleSet::sample`]).
    fn sample_particle_gauge(
        &self,
        k: usize,
        quantities: &[brisance_core::SetQuantity],
        out: &mut Vec<f64>,
    ) -> bool {
        match self.gauges.get(k) {
            Some(set) => {
                set.sample(self, quantities, out);
                true
            }
            None => false,
        }
    }

    /// Every particle with its mass, volume, density, velocity, pressure
    /// p = −tr σ/3 − q (the material's, without the bulk viscosity), von
    /// Mises stress, temperature, specific internal energy, material id,
    /// failed flag (1 or 0) and bulk viscosity q.
    fn particle_data(&self) -> Option<brisance_core::ParticleData> {
        let p = &self.particles;
        let n = p.len();
        let col = |f: &dyn Fn(usize) -> f64| (0..n).map(f).collect::<Vec<f64>>();
        let von_mises = |s: &[f64; 6]| {
            let (a, b, c) = (s[0] - s[1], s[1] - s[2], s[2] - s[0]);
            (0.5 * (a * a + b * b + c * c) + 3.0 * (s[3] * s[3] + s[4] * s[4] + s[5] * s[5])).sqrt()
        };
        let fields = vec![
            ("mass".to_string(), p.mass.clone()),
            ("volume".to_string(), p.volume.clone()),
            ("density".to_string(), col(&|i| p.mass[i] / p.volume[i])),
            ("velocity_x".to_string(), col(&|i| p.velocity[i][0])),
            ("velocity_y".to_string(), col(&|i| p.velocity[i][1])),
            ("velocity_z".to_string(), col(&|i| p.velocity[i][2])),
            ("pressure".to_string(), col(&|i| self.material_pressure(i))),
            (
                "von_mises_stress".to_string(),
                col(&|i| von_mises(&p.stress[i])),
            ),
            ("temperature".to_string(), p.temperature.clone()),
            (
                "specific_internal_energy".to_string(),
                p.specific_internal_energy.clone(),
            ),
            ("material".to_string(), col(&|i| f64::from(p.material[i].0))),
            (
                "failed".to_string(),
                col(&|i| if p.failed[i] { 1.0 } else { 0.0 }),
            ),
            ("bulk_viscosity".to_string(), col(&|i| self.bulk[i].q)),
            // The model's damage variables (Johnson–Cook D; HJC's D_c and
            // D_t): the first as `damage`, the second as `tensile_damage`,
            // 0 for a model without them.
            ("damage".to_string(), col(&|i| self.damage_entry(i, 0))),
            (
                "tensile_damage".to_string(),
                col(&|i| self.damage_entry(i, 1)),
            ),
            // The particle's identity (`particle_ids`): follows a point
            // through sorting, removals and insertions.
            ("id".to_string(), col(&|i| f64::from(self.ids[i]))),
        ];
        Some(brisance_core::ParticleData {
            positions: p.position.clone(),
            fields,
        })
    }

    fn save_state(&self) -> Result<Vec<u8>, SolverError> {
        let ps = &self.particles;
        let saved = SavedState {
            time: self.time,
            steps: self.steps,
            cells: self.level.geometry.cells,
            history_stride: ps.history_stride(),
            outflow: self.outflow,
            bulk_viscosity: self.bulk.clone(),
            ids: self.ids.clone(),
            external_work: self.external_work,
            position: ps.position.clone(),
            velocity: ps.velocity.clone(),
            mass: ps.mass.clone(),
            initial_volume: ps.initial_volume.clone(),
            volume: ps.volume.clone(),
            deformation_gradient: ps.deformation_gradient.clone(),
            stress: ps.stress.clone(),
            temperature: ps.temperature.clone(),
            specific_internal_energy: ps.specific_internal_energy.clone(),
            material: ps.material.clone(),
            history: ps.history.clone(),
            failed: ps.failed.clone(),
            reservoir_phases: self.inflow.phases(),
        };
        bincode::serialize(&saved).map_err(|e| SolverError::Checkpoint(e.to_string()))
    }

    fn restore_state(&mut self, bytes: &[u8]) -> Result<(), SolverError> {
        let s: SavedState =
            bincode::deserialize(bytes).map_err(|e| SolverError::Checkpoint(e.to_string()))?;
        if s.cells != self.level.geometry.cells {
            return Err(SolverError::Checkpoint(format!(
                "checkpoint grid {:?} does not match the scenario's {:?}",
                s.cells, self.level.geometry.cells
            )));
        }
        let n = s.mass.len();
        let history_rows = if s.history_stride == 0 {
            if s.history.is_empty() {
                n
            } else {
                usize::MAX
            }
        } else if s.history.len().is_multiple_of(s.history_stride) {
            s.history.len() / s.history_stride
        } else {
            usize::MAX
        };
        let lengths = [
            s.position.len(),
            s.velocity.len(),
            s.initial_volume.len(),
            s.volume.len(),
            s.deformation_gradient.len(),
            s.stress.len(),
            s.temperature.len(),
            s.specific_internal_energy.len(),
            s.material.len(),
            s.failed.len(),
            s.bulk_viscosity.len(),
            s.ids.len(),
            history_rows,
        ];
        if lengths.iter().any(|&l| l != n) {
            return Err(SolverError::Checkpoint(format!(
                "particle arrays of unequal length in the checkpoint ({n} masses)"
            )));
        }
        if let Some(m) = s
            .material
            .iter()
            .find(|m| m.0 as usize >= self.materials.len())
        {
            return Err(SolverError::Checkpoint(format!(
                "checkpoint particle material {} not among the {} materials",
                m.0,
                self.materials.len()
            )));
        }
        self.inflow
            .set_phases(&s.reservoir_phases)
            .map_err(SolverError::Checkpoint)?;
        let mut ps = Particles::new(s.history_stride);
        ps.position = s.position;
        ps.velocity = s.velocity;
        ps.mass = s.mass;
        ps.initial_volume = s.initial_volume;
        ps.volume = s.volume;
        ps.deformation_gradient = s.deformation_gradient;
        ps.stress = s.stress;
        ps.temperature = s.temperature;
        ps.specific_internal_energy = s.specific_internal_energy;
        ps.material = s.material;
        ps.history = s.history;
        ps.failed = s.failed;
        self.particles = ps;
        self.bulk = s.bulk_viscosity;
        self.ids = s.ids;
        self.next_id = self.ids.iter().max().map_or(0, |m| m.saturating_add(1));
        self.time = s.time;
        self.steps = s.steps;
        self.outflow = s.outflow;
        self.external_work = s.external_work;
        Ok(())
    }
}
