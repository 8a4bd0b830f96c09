//! Time integration of the lattice (seed 003 §2.3).
//!
//! - Explicit Euler (eqs 16–17): u ← u + a Δt, x ← x + uⁿ Δt.
//! - Velocity Verlet (eq 18): x ← x + uΔt + ½aΔt², u ← u + ½(aⁿ + aⁿ⁺¹)Δt;
//!   velocity-dependent (dashpot) forces at step end use the predicted
//!   velocity uⁿ + aⁿΔt, which keeps second order.
//! - Implicit Euler (eqs 19–21): (M − Δt ∂f/∂u − Δt² ∂f/∂x) Δu =
//!   Δt (fⁿ + Δt ∂f/∂x uⁿ), then Δx = Δt (uⁿ + Δu). Eq 21 multiplied by M.
//! - Implicit RK2 (eq 22): Δu = ½Δt M⁻¹(fⁿ + fⁿ⁺¹) with the same
//!   linearisation fⁿ⁺¹ = fⁿ + ∂f/∂x Δx + ∂f/∂u Δu and the trapezoidal
//!   position update Δx = Δt (uⁿ + ½Δu), which gives
//!   (M − ½Δt ∂f/∂u − ¼Δt² ∂f/∂x) Δu = Δt (fⁿ + ½Δt ∂f/∂x uⁿ).
//!
//! After the mechanical update every integrator commits the spring state
//! (plasticity, dashpots, fracture), recomputes the dual-mesh volumes and
//! advances the energy equation (explicitly, over the same Δt); then the
//! surface regresses (§2.4, [`super::regress`]) if regression is on. With
//! `mechanics` off a step is the regression alone.

use std::time::Instant;

use rayon::prelude::*;

use super::model::{Integrator, MsdmError, MsdmLattice, StepReport};

impl MsdmLattice {
    /// Advances the lattice by `dt` with the configured integrator.
    pub fn step(&mut self, dt: f64) -> Result<StepReport, MsdmError> {
        if !(dt > 0.0 && dt.is_finite()) {
            return Err(MsdmError::Invalid(format!(
                "lattice step: `dt` = {dt}, expected a finite value > 0"
            )));
        }
        let mut report = StepReport::default();
        self.clear_stencil_flags();
        if !self.mechanics {
            if self.options.thermal {
                return Err(MsdmError::Invalid(
                    "lattice: field `mechanics` is false but `thermal` is true; the energy \
                     equation needs the mechanical volume update (set `thermal: false`)"
                        .into(),
                ));
            }
            self.regress(dt);
            self.time += dt;
            return Ok(report);
        }
        match self.options.integrator {
            Integrator::ExplicitEuler => self.explicit_euler(dt),
            Integrator::VelocityVerlet => self.velocity_verlet(dt),
            Integrator::ImplicitEuler => self.implicit(dt, 1.0, &mut report)?,
            Integrator::ImplicitRk2 => self.implicit(dt, 0.5, &mut report)?,
        }
        let (broken, _) = self.commit_springs(dt);
        report.broken = broken;
        self.update_volume_and_energy(dt);
        self.regress(dt);
        self.time += dt;
        Ok(report)
    }

    fn move_positions(&mut self, dt: f64) {
        let dim = self.geom.dim.count();
        let solid: &Vec<_> = &self.geom.kind;
        for a in 0..dim {
            self.x[a]
                .par_iter_mut()
                .zip(self.u[a].par_iter())
                .zip(solid.par_iter())
                .for_each(|((x, u), k)| {
                    if matches!(k, super::geometry::NodeKind::Solid(_)) {
                        *x += u * dt;
                    }
                });
        }
    }

    fn kick(&mut self, dt: f64) {
        let dim = self.geom.dim.count();
        for a in 0..dim {
            let (u, f) = (&mut self.u[a], &self.force[a]);
            let mass = &self.mass;
            let (prescribed, held) = (&self.prescribed[..], &self.held_axes[..]);
            let kind = &self.geom.kind;
            u.par_iter_mut().enumerate().for_each(|(i, ui)| {
                if !(prescribed[i] && held[i] & (1 << a) != 0)
                    && matches!(kind[i], super::geometry::NodeKind::Solid(_))
                    && mass[i] > 0.0
                {
                    *ui += f[i] / mass[i] * dt;
                }
            });
        }
    }

    fn explicit_euler(&mut self, dt: f64) {
        // Forces at (xⁿ, uⁿ), then x ← x + uⁿΔt and u ← u + aΔt per node in
        // the gather pass of the forces.
        self.forces_and_update(Some(dt));
    }

    fn velocity_verlet(&mut self, dt: f64) {
        if !self.forces_current {
            self.compute_forces();
        }
        self.kick(0.5 * dt);
        self.move_positions(dt);
        // Velocity-dependent forces at step end are evaluated at the
        // predicted uⁿ + aⁿΔt (an error O(Δt²), so the scheme stays second
        // order with dashpots; the half-step velocity would make it first
        // order). Then uⁿ⁺¹ = uⁿ⁺½ + ½aⁿ⁺¹Δt.
        let damped = self.laws_have_dashpots();
        if damped {
            self.kick(0.5 * dt);
            for a in 0..3 {
                self.force_prev[a].copy_from_slice(&self.force[a]);
            }
        }
        self.compute_forces();
        if damped {
            let dim = self.geom.dim.count();
            for a in 0..dim {
                let (u, f, f0) = (&mut self.u[a], &self.force[a], &self.force_prev[a]);
                let mass = &self.mass;
                let (prescribed, held) = (&self.prescribed[..], &self.held_axes[..]);
                let kind = &self.geom.kind;
                u.par_iter_mut().enumerate().for_each(|(i, ui)| {
                    if !(prescribed[i] && held[i] & (1 << a) != 0)
                        && matches!(kind[i], super::geometry::NodeKind::Solid(_))
                        && mass[i] > 0.0
                    {
                        *ui += 0.5 * dt * (f[i] - f0[i]) / mass[i];
                    }
                });
            }
        } else {
            self.kick(0.5 * dt);
        }
        // The forces stay valid for the next step unless the commit changes
        // the spring state (it clears the flag then).
    }

    /// One linearised implicit step; `theta` = 1 for Euler (eq 21), ½ for
    /// RK2 (eq 22). Fills the solver statistics and the wall times of
    /// `report` and adds the times to [`MsdmLattice::implicit_timing`]
    /// (three clock reads and no allocation; the results do not depend on
    /// them).
    fn implicit(&mut self, dt: f64, theta: f64, report: &mut StepReport) -> Result<(), MsdmError> {
        let t_start = Instant::now();
        let all = super::model::ALL_AXES;
        let dim_mask = (1u8 << self.geom.dim.count()) - 1;
        if let Some(i) = (0..self.len())
            .find(|&i| self.prescribed[i] && self.held_axes[i] & dim_mask != all & dim_mask)
        {
            return Err(MsdmError::Invalid(format!(
                "lattice: node {i} holds only some axes (`held_axes` = {:#05b}); per-axis \
                 prescription needs an explicit `integrator` (explicit_euler or velocity_verlet)",
                self.held_axes[i]
            )));
        }
        self.compute_forces();
        let ndof = self.number_dofs();
        let dim = self.geom.dim.count();
        let mut ku = std::mem::take(&mut self.rhs);
        ku.resize(ndof, 0.0);
        let t_assemble = Instant::now();
        self.assemble(1.0, theta * dt, theta * theta * dt * dt, &mut ku);
        // rhs = Δt (fⁿ + θ Δt K uⁿ)
        for i in 0..self.len() {
            let di = self.dof[i];
            if di == usize::MAX {
                continue;
            }
            for a in 0..dim {
                let k = di * dim + a;
                ku[k] = dt * (self.force[a][i] + theta * dt * ku[k]);
            }
        }
        self.rhs = ku;
        let t_solve = Instant::now();
        let stats = self.solve()?;
        let t_solved = Instant::now();
        for i in 0..self.len() {
            let di = self.dof[i];
            for a in 0..dim {
                if di != usize::MAX {
                    let du = self.delta[di * dim + a];
                    self.x[a][i] += dt * (self.u[a][i] + theta * du);
                    self.u[a][i] += du;
                } else if self.geom.is_solid(i) {
                    self.x[a][i] += dt * self.u[a][i];
                }
            }
        }
        self.forces_current = false;
        let t_end = Instant::now();
        let (assemble, solve, total) = (t_solve - t_assemble, t_solved - t_solve, t_end - t_start);
        self.timing.steps += 1;
        self.timing.assemble += assemble;
        self.timing.solve += solve;
        self.timing.total += total;
        report.solve = Some(stats);
        report.assemble_seconds = assemble.as_secs_f64();
        report.linear_solve_seconds = solve.as_secs_f64();
        report.solve_seconds = total.as_secs_f64();
        Ok(())
    }

    /// Wall time of the implicit steps since the lattice was built or the
    /// last [`MsdmLattice::reset_implicit_timing`]: assembly, linear solve
    /// and the whole implicit update, accumulated.
    pub fn implicit_timing(&self) -> super::model::ImplicitTiming {
        self.timing
    }

    /// Zeroes the accumulated [`MsdmLattice::implicit_timing`].
    pub fn reset_implicit_timing(&mut self) {
        self.timing = super::model::ImplicitTiming::default();
    }
}
