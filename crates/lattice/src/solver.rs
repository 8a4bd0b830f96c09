//! The lattice behind the core `Solver` trait, so a scenario pipeline can
//! run it: stable step, conservation totals, node output as particles and
//! point sampling.

use brisance_core::{ConservationTotals, ParticleData, Solver, SolverError};
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

use super::geometry::NodeKind;
use super::law::SpringState;
use super::model::{Integrator, MsdmLattice};

/// The evolving state of a lattice, for checkpoints.
#[derive(Serialize, Deserialize)]
struct LatticeState {
    time: f64,
    x: [Vec<f64>; 3],
    u: [Vec<f64>; 3],
    mass_k: Vec<f64>,
    mass: Vec<f64>,
    volume: Vec<f64>,
    pressure: Vec<f64>,
    temperature: Vec<f64>,
    energy: Vec<f64>,
    status: Vec<u8>,
    spring: Vec<SpringState>,
    /// Node kinds (material, or −1 for exterior): regression converts
    /// solid nodes.
    kind: Vec<i32>,
    /// Surface regression, if on.
    regression: Option<RegressionState>,
    /// The net forces of the last evaluation when the next step reuses
    /// them (velocity Verlet): with dashpots they were taken at the
    /// predicted velocity, not the step's final one, so recomputing them
    /// from the restored state would not continue bit-identically.
    force: Option<[Vec<f64>; 3]>,
}

/// The evolving state of a surface regression, for checkpoints.
#[derive(Serialize, Deserialize)]
struct RegressionState {
    fluid: Vec<bool>,
    remaining: Vec<f64>,
    carry: Vec<f64>,
    consumed_mass: f64,
    converted: usize,
}

impl MsdmLattice {
    /// Fields a gauge can sample ([`Solver::sample`]).
    pub const FIELDS: [&'static str; 9] = [
        "displacement_x",
        "displacement_y",
        "displacement_z",
        "velocity_x",
        "velocity_y",
        "velocity_z",
        "temperature",
        "pressure",
        "density",
    ];

    /// Largest explicit step: 2/ω_max times the safety factor, with
    /// ω²_max ≤ max_i Σ_j k_ij (1/m_i + 1/m_j) (Gershgorin; exact for a
    /// uniform chain, 4k/m), k_ij the spring's tangent plus perpendicular
    /// stiffness; and, with the energy equation on, the explicit
    /// conduction limit 2 / max_i Σ_j g_ij (1/C_i + 1/C_j), g = κ_ij h and
    /// C = m c_v. Dashpots are not included (they are assumed light). With
    /// surface regression the step is also at most
    /// [`MsdmLattice::regression_dt`] (not scaled by the safety factor);
    /// without `mechanics` the spring limit does not apply.
    pub fn explicit_stable_dt(&self) -> f64 {
        // Per node, over its springs in both directions; no allocation, and
        // the maximum does not depend on the order. On several ranks each
        // takes its own nodes, and the ranks' maxima are combined (a
        // maximum is exact in any order).
        let own = self.owned_nodes();
        let w2 = own
            .clone()
            .into_par_iter()
            .filter(|&i| self.geom.is_solid(i))
            .map(|i| self.spring_bound(i))
            .reduce(|| 0.0, f64::max);
        let w2 = self.ranks.max(w2);
        let mut dt = if w2 > 0.0 && self.mechanics {
            2.0 / w2.sqrt()
        } else {
            f64::INFINITY
        };
        if self.options.thermal {
            let lam = own
                .filter_map(|i| self.conduction_bound(i))
                .fold(0.0, f64::max);
            let lam = self.ranks.max(lam);
            if lam > 0.0 {
                dt = dt.min(2.0 / lam);
            }
        }
        (dt * self.options.safety_factor).min(self.regression_dt())
    }

    /// Gershgorin's bound on ω² at solid node `i`: Σ_j k_ij (1/m_i + 1/m_j)
    /// over its intact springs in both directions of every lattice
    /// direction, k_ij the tangent plus perpendicular stiffness.
    fn spring_bound(&self, i: usize) -> f64 {
        let nd = self.geom.directions.len();
        let mut sum = 0.0;
        for (d, dir) in self.geom.directions.iter().enumerate() {
            for sign in [1isize, -1] {
                let j = (i as isize + sign * dir.offset) as usize;
                let (lo, bond) = if sign > 0 {
                    (i, i * nd + d)
                } else {
                    (j, j * nd + d)
                };
                if self.status[bond] != super::model::INTACT {
                    continue;
                }
                let b = self.eval_bond(lo, d, self.spring[bond]);
                sum += (b.k_t.abs() + b.k_perp) * (1.0 / self.mass[i] + 1.0 / self.mass[j]);
            }
        }
        sum
    }

    /// The bound on the conduction's rate at node `i`, 4 d g_max / C_i
    /// (at most 2 d neighbours with g ≤ max(κ) h each, C = m c_v), or
    /// `None` for a node outside the solid.
    fn conduction_bound(&self, i: usize) -> Option<f64> {
        let m = self.material_of(i)?;
        let g = self.materials[m].conductivity * self.geom.spacing;
        let c = self.mass[i] * self.materials[m].eos.cv;
        Some(
            4.0 * self.geom.dim.count() as f64
                * g.max(self.options.surroundings.conductivity * self.geom.spacing)
                / c,
        )
    }

    /// The largest `bound` over this rank's nodes and then over the ranks,
    /// with the lowest node index that attains it (`None` where no node
    /// gives a positive bound): the same on every rank.
    fn largest_bound(&self, bound: impl Fn(usize) -> Option<f64>) -> Option<(f64, usize)> {
        let (value, node) = self
            .owned_nodes()
            .filter_map(|i| bound(i).map(|b| (b, i)))
            .fold((0.0f64, usize::MAX), |a, b| if b.0 > a.0 { b } else { a });
        let value_all = self.ranks.max(value);
        let mine = if value == value_all && node != usize::MAX {
            node as f64
        } else {
            f64::INFINITY
        };
        let node = -self.ranks.max(-mine);
        (value_all > 0.0 && node.is_finite()).then_some((value_all, node as usize))
    }

    /// Node `i` as `node (ix, iy, iz) of `material``, for the run summary.
    fn node_label(&self, i: usize) -> String {
        let material = self.material_of(i).map_or("exterior".to_string(), |m| {
            format!("`{}`", self.materials[m].name)
        });
        format!("node {:?} ({material})", self.geom.coords(i))
    }
}

impl Solver for MsdmLattice {
    fn name(&self) -> &str {
        "lattice"
    }

    fn time(&self) -> f64 {
        self.time
    }

    /// The configured step for the implicit integrators if one is set,
    /// else the explicit limit of [`MsdmLattice::explicit_stable_dt`].
    fn stable_dt(&self) -> Result<f64, SolverError> {
        let dt = match (self.options.integrator, self.options.time_step) {
            (Integrator::ImplicitEuler | Integrator::ImplicitRk2, Some(dt)) => {
                dt.min(self.regression_dt())
            }
            _ => self.explicit_stable_dt(),
        };
        if !(dt > 0.0 && dt.is_finite()) {
            return Err(SolverError::Other(format!(
                "lattice: no finite stable step ({dt} s): no springs and no conduction; set `time_step`"
            )));
        }
        Ok(dt)
    }

    /// What sets the step: the configured `time_step` of an implicit
    /// integrator, the springs of the node of the largest ω² bound, the
    /// conduction at the node of the largest rate bound, or the surface
    /// regression's fastest front, whichever gives the smallest step.
    fn time_step_limit(&self) -> Option<String> {
        let safety = self.options.safety_factor;
        let mut limits: Vec<(f64, String)> = Vec::new();
        match (self.options.integrator, self.options.time_step) {
            (Integrator::ImplicitEuler | Integrator::ImplicitRk2, Some(dt)) => {
                limits.push((dt, format!("the configured time_step ({dt:e} s)")));
            }
            _ => {
                if self.mechanics {
                    let spring =
                        self.largest_bound(|i| self.geom.is_solid(i).then(|| self.spring_bound(i)));
                    if let Some((w2, i)) = spring {
                        limits.push((
                            2.0 * safety / w2.sqrt(),
                            format!(
                                "the springs of {}: Σ k (1/m_i + 1/m_j) = {w2:.4e} s⁻², step 2/√Σ × safety factor {safety}",
                                self.node_label(i)
                            ),
                        ));
                    }
                }
                if self.options.thermal {
                    if let Some((lam, i)) = self.largest_bound(|i| self.conduction_bound(i)) {
                        limits.push((
                            2.0 * safety / lam,
                            format!(
                                "the conduction at {}: 4 d g_max / (m c_v) = {lam:.4e} s⁻¹, step 2/rate × safety factor {safety}",
                                self.node_label(i)
                            ),
                        ));
                    }
                }
            }
        }
        if let Some((dt, text)) = self.regression_limit() {
            limits.push((dt, text));
        }
        limits
            .into_iter()
            .fold(None, |a: Option<(f64, String)>, b| match a {
                Some(a) if a.0 <= b.0 => Some(a),
                _ => Some(b),
            })
            .map(|(_, text)| text)
    }

    fn advance(&mut self, dt: f64) -> Result<(), SolverError> {
        self.step(dt)
            .map_err(|e| SolverError::Other(format!("lattice: {e}")))?;
        let n = self.len();
        if let Some(i) = (0..n).find(|&i| {
            !(self.u[0][i].is_finite() && self.u[1][i].is_finite() && self.u[2][i].is_finite())
        }) {
            return Err(SolverError::Other(format!(
                "lattice: non-finite velocity at node {:?} at t = {:e} s",
                self.geom.coords(i),
                self.time
            )));
        }
        Ok(())
    }

    /// Mass, momentum, and kinetic + spring + internal (Σ m e) energy.
    fn conservation_totals(&self) -> ConservationTotals {
        let internal: f64 = (0..self.len())
            .filter(|&i| self.geom.is_solid(i))
            .map(|i| self.mass[i] * self.energy[i])
            .sum();
        ConservationTotals {
            mass: self.mass.iter().sum(),
            momentum: self.momentum(),
            energy: self.kinetic_energy() + self.spring_energy() + internal,
        }
    }

    fn work_per_step(&self) -> (f64, &'static str) {
        let solid = (0..self.len()).filter(|&i| self.geom.is_solid(i)).count();
        (solid as f64, "node-updates")
    }

    fn save_state(&self) -> Result<Vec<u8>, SolverError> {
        let s = LatticeState {
            time: self.time,
            x: self.x.clone(),
            u: self.u.clone(),
            mass_k: self.mass_k.clone(),
            mass: self.mass.clone(),
            volume: self.volume.clone(),
            pressure: self.pressure.clone(),
            temperature: self.temperature.clone(),
            energy: self.energy.clone(),
            status: self.status.clone(),
            spring: self.spring.clone(),
            kind: self
                .geom
                .kind
                .iter()
                .map(|k| match k {
                    NodeKind::Solid(m) => i32::from(*m),
                    NodeKind::Exterior => -1,
                })
                .collect(),
            regression: self.regression.as_ref().map(|r| RegressionState {
                fluid: r.fluid.clone(),
                remaining: r.remaining.clone(),
                carry: r.carry.clone(),
                consumed_mass: r.consumed_mass,
                converted: r.converted,
            }),
            force: self.forces_current.then(|| self.force.clone()),
        };
        bincode::serialize(&s).map_err(|e| SolverError::Checkpoint(e.to_string()))
    }

    /// Every length is checked before anything is assigned, so a refused
    /// checkpoint leaves the lattice as it was.
    fn restore_state(&mut self, bytes: &[u8]) -> Result<(), SolverError> {
        let s: LatticeState =
            bincode::deserialize(bytes).map_err(|e| SolverError::Checkpoint(e.to_string()))?;
        let n = self.len();
        if s.mass.len() != n || s.status.len() != self.status.len() {
            return Err(SolverError::Checkpoint(format!(
                "checkpoint has {} nodes and {} bond slots, the lattice {} and {}",
                s.mass.len(),
                s.status.len(),
                n,
                self.status.len()
            )));
        }
        if s.kind.len() != n {
            return Err(SolverError::Checkpoint(format!(
                "checkpoint has {} node kinds, the lattice {} nodes",
                s.kind.len(),
                n
            )));
        }
        let per_node = [&s.x[0], &s.x[1], &s.x[2], &s.u[0], &s.u[1], &s.u[2]]
            .into_iter()
            .chain([&s.volume, &s.pressure, &s.temperature, &s.energy])
            .chain(s.force.iter().flatten());
        if per_node.into_iter().any(|v| v.len() != n)
            || s.mass_k.len() != self.mass_k.len()
            || s.spring.len() != self.spring.len()
        {
            return Err(SolverError::Checkpoint(format!(
                "checkpoint's node or spring arrays do not match the lattice's {n} nodes"
            )));
        }
        match (&self.regression, &s.regression) {
            (Some(_), Some(state)) => {
                if state.carry.len() != n || state.fluid.len() != n || state.remaining.len() != n {
                    return Err(SolverError::Checkpoint(format!(
                        "checkpoint has regression state for {} nodes, the lattice {}",
                        state.fluid.len(),
                        n
                    )));
                }
            }
            (None, None) => {}
            _ => {
                return Err(SolverError::Checkpoint(
                    "checkpoint and lattice differ in whether surface regression is on".into(),
                ))
            }
        }
        self.time = s.time;
        self.x = s.x;
        self.u = s.u;
        self.mass_k = s.mass_k;
        self.mass = s.mass;
        self.volume = s.volume;
        self.pressure = s.pressure;
        self.temperature = s.temperature;
        self.energy = s.energy;
        if let (Some(r), Some(state)) = (&mut self.regression, s.regression) {
            r.fluid = state.fluid;
            r.remaining = state.remaining;
            r.carry = state.carry;
            r.consumed_mass = state.consumed_mass;
            r.converted = state.converted;
        }
        self.status = s.status;
        self.spring = s.spring;
        for (k, v) in self.geom.kind.iter_mut().zip(s.kind) {
            *k = match u16::try_from(v) {
                Ok(m) => NodeKind::Solid(m),
                Err(_) => NodeKind::Exterior,
            };
        }
        self.mark_modified();
        if let Some(force) = s.force {
            self.force = force;
            self.forces_current = true;
        }
        Ok(())
    }

    fn cell_field_names(&self) -> Vec<&'static str> {
        Vec::new()
    }

    fn cell_data(&self, fields: &[String]) -> Result<brisance_core::CellData, SolverError> {
        Err(SolverError::Other(format!(
            "the lattice has no cell fields (asked for {fields:?}); its nodes are written as particles"
        )))
    }

    /// The value at the solid node nearest `point` (reference positions):
    /// `displacement_x|y|z`, `velocity_x|y|z`, `temperature`, `pressure`,
    /// `density`.
    fn sample(
        &self,
        point: [f64; 3],
        fields: &[String],
        out: &mut Vec<f64>,
    ) -> Result<(), SolverError> {
        let mut best = (f64::INFINITY, usize::MAX);
        for i in 0..self.len() {
            if !self.geom.is_solid(i) {
                continue;
            }
            let p = self.geom.reference_position(i);
            let d = (0..3).map(|a| (p[a] - point[a]).powi(2)).sum::<f64>();
            if d < best.0 {
                best = (d, i);
            }
        }
        let i = best.1;
        if i == usize::MAX {
            return Err(SolverError::Other(
                "lattice: no solid node to sample".into(),
            ));
        }
        let p = self.geom.reference_position(i);
        out.clear();
        for f in fields {
            out.push(match f.as_str() {
                "displacement_x" => self.x[0][i] - p[0],
                "displacement_y" => self.x[1][i] - p[1],
                "displacement_z" => self.x[2][i] - p[2],
                "velocity_x" => self.u[0][i],
                "velocity_y" => self.u[1][i],
                "velocity_z" => self.u[2][i],
                "temperature" => self.temperature[i],
                "pressure" => self.pressure[i],
                "density" => self.mass[i] / self.volume[i],
                other => {
                    return Err(SolverError::Other(format!(
                        "lattice: unknown sample field `{other}`; known: displacement_x|y|z, velocity_x|y|z, temperature, pressure, density"
                    )))
                }
            });
        }
        Ok(())
    }

    /// The solid nodes with `velocity_x|y|z`, `temperature`, `pressure`,
    /// `density`, `mass`, `volume`, `material`.
    fn particle_data(&self) -> Option<ParticleData> {
        let ids: Vec<usize> = (0..self.len()).filter(|&i| self.geom.is_solid(i)).collect();
        let col = |f: &dyn Fn(usize) -> f64| ids.iter().map(|&i| f(i)).collect::<Vec<f64>>();
        Some(ParticleData {
            positions: ids
                .iter()
                .map(|&i| [self.x[0][i], self.x[1][i], self.x[2][i]])
                .collect(),
            fields: vec![
                ("velocity_x".into(), col(&|i| self.u[0][i])),
                ("velocity_y".into(), col(&|i| self.u[1][i])),
                ("velocity_z".into(), col(&|i| self.u[2][i])),
                ("temperature".into(), col(&|i| self.temperature[i])),
                ("pressure".into(), col(&|i| self.pressure[i])),
                ("density".into(), col(&|i| self.mass[i] / self.volume[i])),
                ("mass".into(), col(&|i| self.mass[i])),
                ("volume".into(), col(&|i| self.volume[i])),
                (
                    "material".into(),
                    col(&|i| self.material_of(i).map_or(-1.0, |m| m as f64)),
                ),
            ],
        })
    }
}

#[cfg(test)]
mod tests {
    use super::super::cases::oscillator;
    use super::*;

    #[test]
    fn stable_step_of_a_chain_is_two_over_omega_max() {
        // Oscillator: one free node of mass m on a spring k to a held node
        // of mass m/…: Gershgorin gives k(1/m₀ + 1/m₁) on each end; the
        // held node is a real node of the chain (mass ρ·0.5).
        let mut lat = oscillator(Integrator::VelocityVerlet).unwrap();
        lat.options.safety_factor = 1.0;
        let m = lat.mass[lat.geom.solid_index(1, 0, 0)];
        let m0 = lat.mass[lat.geom.solid_index(0, 0, 0)];
        let w2 = 0.35 * (1.0 / m + 1.0 / m0);
        assert!((lat.explicit_stable_dt() - 2.0 / w2.sqrt()).abs() < 1e-14);
        lat.options.integrator = Integrator::ImplicitEuler;
        lat.options.time_step = Some(0.5);
        assert_eq!(lat.stable_dt().unwrap(), 0.5);
    }

    /// The summary's limit: the springs of the node of the largest ω²
    /// bound (both ends of the oscillator's spring carry the same, so the
    /// lower index), then the conduction where it binds, then an implicit
    /// integrator's configured step; each the step stable_dt takes.
    #[test]
    fn the_time_step_limit_names_the_springs_the_conduction_or_the_configured_step() {
        let mut lat = oscillator(Integrator::VelocityVerlet).unwrap();
        lat.options.safety_factor = 0.5;
        let (a, b) = (lat.geom.solid_index(0, 0, 0), lat.geom.solid_index(1, 0, 0));
        let w2 = 0.35 * (1.0 / lat.mass[a] + 1.0 / lat.mass[b]);
        let first = a.min(b);
        let text = lat.time_step_limit().unwrap();
        assert!(text.starts_with("the springs of node"), "{text}");
        assert!(
            text.contains(&format!("node {:?}", lat.geom.coords(first))),
            "{text}"
        );
        assert!(text.contains(&format!("{w2:.4e} s⁻²")), "{text}");
        assert!((lat.stable_dt().unwrap() - 2.0 * 0.5 / w2.sqrt()).abs() < 1e-15);
        // κ = 1 W/(m K), h = 1 m, c_v = 1e-3: rate 4 κ h / (m c_v), the
        // lighter node's, far above ω.
        lat.options.thermal = true;
        lat.materials[0].conductivity = 1.0;
        let cv = lat.materials[0].eos.cv;
        let rate = |i: usize| 4.0 / (lat.mass[i] * cv);
        let hot = if rate(a) > rate(b) {
            a
        } else if rate(b) > rate(a) {
            b
        } else {
            first
        };
        let text = lat.time_step_limit().unwrap();
        assert!(text.starts_with("the conduction at node"), "{text}");
        assert!(
            text.contains(&format!("node {:?}", lat.geom.coords(hot))),
            "{text}"
        );
        assert!(text.contains(&format!("{:.4e} s⁻¹", rate(hot))), "{text}");
        assert!((lat.stable_dt().unwrap() - 2.0 * 0.5 / rate(hot)).abs() < 1e-18);
        lat.options.integrator = Integrator::ImplicitEuler;
        lat.options.time_step = Some(0.5);
        assert_eq!(
            lat.time_step_limit().unwrap(),
            "the configured time_step (5e-1 s)"
        );
    }

    #[test]
    fn totals_sample_and_particles() {
        let mut lat = oscillator(Integrator::VelocityVerlet).unwrap();
        let t = lat.conservation_totals();
        assert!((t.mass - 1.0 / 9.0).abs() < 1e-15);
        assert!((t.momentum[0] - 0.1 / 18.0).abs() < 1e-16);
        let mut out = Vec::new();
        lat.sample([1.0, 0.0, 0.0], &["velocity_x".into()], &mut out)
            .unwrap();
        assert_eq!(out, vec![0.1]);
        assert!(lat
            .sample([1.0, 0.0, 0.0], &["nope".into()], &mut out)
            .unwrap_err()
            .to_string()
            .contains("`nope`"));
        let p = lat.particle_data().unwrap();
        assert_eq!(p.positions.len(), 2);
        let saved = lat.save_state().unwrap();
        Solver::advance(&mut lat, 0.01).unwrap();
        assert!((lat.time - 0.01).abs() < 1e-16);
        let after = (lat.x.clone(), lat.u.clone());
        lat.restore_state(&saved).unwrap();
        assert_eq!(lat.time, 0.0);
        Solver::advance(&mut lat, 0.01).unwrap();
        assert_eq!((lat.x.clone(), lat.u.clone()), after);
    }
}
