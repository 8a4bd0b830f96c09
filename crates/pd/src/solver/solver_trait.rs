//! The [`Solver`] implementation of [`PdSolver`], with the checkpoint it
//! saves.

use super::{distance, PdSolver};
use crate::forces::{for_each_node, NodeForce};
use crate::viscosity::ViscousOut;
use brisance_core::{ConservationTotals, ParticleData, Solver, SolverError};
use serde::{Deserialize, Serialize};
use std::path::Path;

/// The mutable state (what a checkpoint holds).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
struct PdState {
    time: f64,
    steps: u64,
    state: Vec<[f64; 4]>,
    velocity: Vec<[f64; 3]>,
    factor: Vec<f32>,
    plastic: Vec<f32>,
    bond_out: Vec<(f64, f64, f64, f64, u32)>,
    contact: Vec<([f64; 3], f64)>,
    gas: Vec<[f64; 4]>,
    viscous: Vec<ViscousOut>,
    dissipated: f64,
    closing: Vec<f64>,
}

impl PdSolver {
    fn mutable_state(&self) -> PdState {
        PdState {
            time: self.time,
            steps: self.steps,
            state: self.state.clone(),
            velocity: self.velocity.clone(),
            factor: self.factor.clone(),
            plastic: self.gathered_plastic().into_owned(),
            bond_out: self
                .bond_out
                .iter()
                .map(|b| {
                    let m = b.min_stretch as f64;
                    (b.force[0], b.force[1], b.force[2], m, b.intact)
                })
                .collect(),
            contact: self.contact.clone(),
            gas: self.gas.clone(),
            viscous: self.viscous.clone(),
            dissipated: self.dissipated,
            closing: self.closing.clone(),
        }
    }
}

impl Solver for PdSolver {
    fn name(&self) -> &str {
        "pd"
    }

    fn time(&self) -> f64 {
        self.time
    }

    fn stable_dt(&self) -> Result<f64, SolverError> {
        let (dt, at) = self.smallest_node_dt();
        let mut dt = dt * self.options.safety_factor;
        if self.time < self.burn_end {
            dt = dt.min(self.burn_step);
        }
        if !(dt >= self.options.min_dt) {
            let x = self.current_position(at);
            return Err(SolverError::TimeStepCollapse {
                dt,
                min_dt: self.options.min_dt,
                time: self.time,
                detail: format!("limited by node {at} at {x:?} m"),
            });
        }
        Ok(dt)
    }

    /// The node of smallest eq 24 step ([`PdSolver::limiting_node`]) with
    /// its position, or the program burn's step while the burn lasts and
    /// it is the smaller.
    fn time_step_limit(&self) -> Option<String> {
        if self.node_count() == 0 {
            return None;
        }
        let (at, what) = self.limiting_node();
        let node = self.node_dt(at) * self.options.safety_factor;
        if self.time < self.burn_end && self.burn_step < node {
            return Some(format!(
                "PD program burn step {:.3e} s (until {:.3e} s)",
                self.burn_step, self.burn_end
            ));
        }
        let x = self.current_position(at);
        Some(format!(
            "PD {what}, at ({:.4}, {:.4}, {:.4}) m",
            x[0], x[1], x[2]
        ))
    }

    fn advance(&mut self, dt: f64) -> Result<(), SolverError> {
        if !(dt > 0.0 && dt.is_finite()) {
            return Err(SolverError::Other(format!(
                "peridynamics: step {dt} s must be finite and > 0"
            )));
        }
        self.kick(0.5 * dt);
        self.impose_velocities();
        let velocity = &self.velocity;
        for_each_node(&mut self.state, |i, s| {
            for d in 0..3 {
                s[d] += dt * velocity[i][d];
            }
        });
        self.time += dt;
        self.update_node_scalars_moved(dt);
        self.compute_forces();
        self.book_dissipation();
        self.kick(0.5 * dt);
        self.impose_velocities();
        self.steps += 1;
        if let Some(i) = self
            .velocity
            .iter()
            .position(|v| !v.iter().all(|c| c.is_finite()))
        {
            return Err(SolverError::Other(format!(
                "peridynamics: non-finite velocity at node {i} (reference {:?} m) at t = {:e} s",
                &self.reference[i][..3],
                self.time
            )));
        }
        Ok(())
    }

    fn conservation_totals(&self) -> ConservationTotals {
        let mut mass = 0.0;
        let mut momentum = [0.0; 3];
        for i in 0..self.node_count() {
            let m = self.mass(i);
            mass += m;
            for (p, v) in momentum.iter_mut().zip(self.velocity[i]) {
                *p += m * v;
            }
        }
        ConservationTotals {
            mass,
            momentum,
            energy: self.kinetic_energy()
                + self.bond_energy()
                + self.gas_energy()
                + self.contact_energy()
                + self.dissipated_energy(),
        }
    }

    fn cell_field_names(&self) -> Vec<&'static str> {
        Vec::new()
    }

    fn cell_data(&self, fields: &[String]) -> Result<brisance_core::CellData, SolverError> {
        Err(SolverError::Other(format!(
            "peridynamics has no cell fields (asked for {fields:?}); its nodes are written as particles"
        )))
    }

    /// The value at the node nearest `point` (reference positions):
    /// `displacement_x|y|z`, `velocity_x|y|z`, `radial_displacement`
    /// (from the z axis), `damage`, `pressure`, `expansion`.
    fn sample(
        &self,
        point: [f64; 3],
        fields: &[String],
        out: &mut Vec<f64>,
    ) -> Result<(), SolverError> {
        let mut best = (f64::INFINITY, 0);
        for (i, x) in self.reference.iter().enumerate() {
            let d = distance([x[0], x[1], x[2]], point);
            if d < best.0 {
                best = (d, i);
            }
        }
        let i = best.1;
        out.clear();
        for f in fields {
            let u = self.displacement(i);
            let v = self.velocity[i];
            let x = self.reference[i];
            out.push(match f.as_str() {
                "displacement_x" => u[0],
                "displacement_y" => u[1],
                "displacement_z" => u[2],
                "velocity_x" => v[0],
                "velocity_y" => v[1],
                "velocity_z" => v[2],
                "radial_displacement" => {
                    let r0 = x[0].hypot(x[1]);
                    (x[0] + u[0]).hypot(x[1] + u[1]) - r0
                }
                "damage" => self.damage(i),
                "pressure" => self.pressure(i),
                "expansion" => self.expansion(i),
                other => {
                    return Err(SolverError::Other(format!(
                        "peridynamics: unknown field `{other}`; known: displacement_x, displacement_y, displacement_z, velocity_x, velocity_y, velocity_z, radial_displacement, damage, pressure, expansion"
                    )))
                }
            });
        }
        Ok(())
    }

    fn particle_data(&self) -> Option<ParticleData> {
        let n = self.node_count();
        let col = |f: &dyn Fn(usize) -> f64| (0..n).map(f).collect::<Vec<f64>>();
        Some(ParticleData {
            positions: (0..n).map(|i| self.current_position(i)).collect(),
            fields: vec![
                ("damage".into(), col(&|i| self.damage(i))),
                ("velocity_x".into(), col(&|i| self.velocity[i][0])),
                ("velocity_y".into(), col(&|i| self.velocity[i][1])),
                ("velocity_z".into(), col(&|i| self.velocity[i][2])),
                ("displacement_x".into(), col(&|i| self.state[i][0])),
                ("displacement_y".into(), col(&|i| self.state[i][1])),
                ("displacement_z".into(), col(&|i| self.state[i][2])),
                ("pressure".into(), col(&|i| self.pressure(i))),
                ("expansion".into(), col(&|i| self.expansion(i))),
                (
                    "detonation_time".into(),
                    col(&|i| {
                        let t = self.detonation_time[i];
                        if t.is_finite() {
                            t
                        } else {
                            -1.0
                        }
                    }),
                ),
                ("body".into(), col(&|i| self.body[i] as f64)),
                ("material".into(), col(&|i| self.material[i] as f64)),
                ("volume".into(), col(&|i| self.reference[i][3])),
            ],
        })
    }

    fn work_per_step(&self) -> (f64, &'static str) {
        (self.bond_count() as f64, "bond-evaluations")
    }

    /// The fragments of the breakable bodies at this output (one pass over
    /// the bonds, cheaper than a step): `fragments/fragments_<index>.csv`
    /// and `fragments/cmd_<index>.csv`. Nothing when no node can break.
    fn write_output_files(&self, out_dir: &Path, index: usize) -> Result<(), SolverError> {
        if !self.has_breakable_nodes() {
            return Ok(());
        }
        self.write_fragment_files(
            &out_dir.join("fragments"),
            &format!("fragments_{index:05}.csv"),
            &format!("cmd_{index:05}.csv"),
        )
    }

    /// The fragments at the end of the run: `fragments.csv` (rank, mass,
    /// node count, velocity) and `cmd.csv` (cumulative mass distribution).
    fn finish(&mut self, out_dir: &Path) -> Result<(), SolverError> {
        if !self.has_breakable_nodes() {
            return Ok(());
        }
        self.write_fragment_files(out_dir, "fragments.csv", "cmd.csv")
    }

    fn save_state(&self) -> Result<Vec<u8>, SolverError> {
        bincode::serialize(&self.mutable_state())
            .map_err(|e| SolverError::Checkpoint(e.to_string()))
    }

    fn restore_state(&mut self, bytes: &[u8]) -> Result<(), SolverError> {
        let s: PdState =
            bincode::deserialize(bytes).map_err(|e| SolverError::Checkpoint(e.to_string()))?;
        if s.state.len() != self.node_count() || s.factor.len() != self.bond_count() {
            return Err(SolverError::Checkpoint(format!(
                "checkpoint has {} nodes and {} bonds, the scenario {} and {}",
                s.state.len(),
                s.factor.len(),
                self.node_count(),
                self.bond_count()
            )));
        }
        self.time = s.time;
        self.steps = s.steps;
        self.state = s.state;
        self.velocity = s.velocity;
        self.factor = s.factor;
        self.plastic = s.plastic;
        self.bond_out = s
            .bond_out
            .into_iter()
            .map(|(a, b, c, m, k)| NodeForce {
                force: [a, b, c],
                min_stretch: m as f32,
                intact: k,
            })
            .collect();
        if s.viscous.len() != self.viscous.len() {
            return Err(SolverError::Checkpoint(format!(
                "checkpoint has the products' artificial viscosity {}, the scenario {}",
                if s.viscous.is_empty() { "off" } else { "on" },
                if self.viscous.is_empty() { "off" } else { "on" },
            )));
        }
        self.contact = s.contact;
        self.gas = s.gas;
        self.dissipated = s.dissipated;
        if s.closing.len() != self.closing.len() {
            return Err(SolverError::Checkpoint(format!(
                "checkpoint has {} products closing times, the scenario {}",
                s.closing.len(),
                self.closing.len()
            )));
        }
        self.closing = s.closing;
        self.ranks_restored();
        // The viscous pass's node data are formed again from the restored
        // state before they are next read (`update_node_scalars`).
        self.viscous = s.viscous;
        Ok(())
    }
}
