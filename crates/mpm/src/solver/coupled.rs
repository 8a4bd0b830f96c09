//! The particle half of the coupled fluid–structure step of seed 000 §3.3
//! (the ICE–MPM pipeline of `brisance-couple`).
//!
//! [`MpmSolver::advance_coupled`] is the explicit MPM step of
//! [`crate::step`] (USL or MUSL) with the Eulerian frame called at the two
//! points where the seed's step list needs it:
//!
//! 1. P2G of mass and momentum (eq 12), v_I^n = p_I/m_I; then
//!    [`GridCoupling::before_forces`] — the nodes to cell centres (eq 18),
//!    the equilibration pressure, face velocities and the advanced pressure
//!    p (steps 1–6).
//! 2. The internal force (eq 14) from σ_p + p(x_p) I: the fluid frame
//!    applies the mixture pressure to the solid as −θ_s ∇p* at the cell
//!    centres (eq 24), so the nodes carry only the divergence of the
//!    solid's stress in excess of it, ∇·θ_r(σ_r − σ) with σ = −p I; then
//!    f_I += m_I g, a_I = f_I/m_I and v*_I = v_I^n + a_I Δt (eq 15).
//! 3. [`GridCoupling::after_forces`] — the cell-centred Lagrangian values,
//!    momentum and heat exchange (steps 8–10) — returns the velocity
//!    change Δv_I of every node, which is added to v*_I and, as Δv_I/Δt,
//!    to a_I (step 13), on the nodes above the mass cut-off and the
//!    components no face condition holds.
//! 4. G2P (eqs 16–17) and the stress update from the grid velocity
//!    gradient (eq 13, step 7), the temperature change of the heat
//!    exchange at each particle ([`GridCoupling::temperature_change`]),
//!    and the removal of particles that left through outflow faces
//!    (step 14).
//!
//! Advection of the fluids (step 12) is the pipeline's, after this step.

use super::*;
use crate::step::{G2pParts, NodeVelocity, Transfer};

/// What the Eulerian frame does inside [`MpmSolver::advance_coupled`].
pub trait GridCoupling: Sync + Send {
    /// Steps 1–6 of seed 000 §3.3: `nodes` holds the particles' lumped
    /// mass m_I and velocity v_I^n (eq 12, after the cut-off and the
    /// boundary conditions); `particles` are those of the start of the step.
    fn before_forces(
        &mut self,
        nodes: &GridNodes,
        particles: &Particles,
        dt: f64,
    ) -> Result<(), SolverError>;

    /// The mixture pressure at point `x`, Pa: added to each particle's
    /// stress as +p I in the internal force.
    fn pressure_at(&self, x: [f64; 3]) -> f64;

    /// Steps 8–10 and 13: `nodes.velocity_new` holds v*_I after the
    /// internal and body forces; writes each node's velocity change from
    /// the cell-centred pressure gradient and exchange into `dv` (node
    /// storage order, zeroed on entry).
    fn after_forces(
        &mut self,
        nodes: &GridNodes,
        dt: f64,
        dv: &mut [[f64; 3]],
    ) -> Result<(), SolverError>;

    /// The temperature change of the heat exchange at point `x` over the
    /// step, K.
    fn temperature_change(&self, x: [f64; 3]) -> f64;
}

impl MpmSolver {
    /// One coupled step of Δt = `dt` (see the module doc). USL and MUSL
    /// only; the ΔF̄ anti-locking option is not available here.
    pub fn advance_coupled(
        &mut self,
        dt: f64,
        coupling: &mut impl GridCoupling,
    ) -> Result<(), SolverError> {
        if !(dt > 0.0) || !dt.is_finite() {
            return Err(SolverError::Other(format!(
                "MPM: time step {dt} s must be positive and finite"
            )));
        }
        if self.options.scheme == UpdateScheme::Usf {
            return Err(SolverError::Other(
                "MPM: the coupled ICE–MPM step runs USL or MUSL, not USF (field `scheme`)".into(),
            ));
        }
        if self.options.anti_locking != AntiLocking::Off {
            return Err(SolverError::Other(
                "MPM: the coupled ICE–MPM step has no anti-locking option (field `anti_locking`)"
                    .into(),
            ));
        }
        rayon::scope(|_| self.step_coupled(dt, coupling))
    }

    /// Adds the isotropic stress −p(x_p) I to every particle's stress:
    /// the coupled pipeline starts its particles in equilibrium with the
    /// pressure of the cells they lie in.
    pub fn preload_pressure(&mut self, pressure: impl Fn([f64; 3]) -> f64) {
        let ps = &mut self.particles;
        for (s, x) in ps.stress.iter_mut().zip(&ps.position) {
            let p = pressure(*x);
            for v in &mut s[..3] {
                *v -= p;
            }
        }
    }

    /// P2G of the particles' mass and momentum onto the nodes (eq 12)
    /// without stepping: the nodal mass the coupled pipeline projects to
    /// the cells before its first step (to fit the fluids around the
    /// solid).
    pub fn project_to_nodes(&mut self) -> Result<&GridNodes, SolverError> {
        self.sort_particles()?;
        let grid = self.level.geometry;
        let params = step_params(
            &self.options,
            &self.materials,
            self.reference_particle_mass,
            &grid,
            0.0,
        );
        let t = Transfer {
            map: &self.work.map,
            bins: &self.work.bins,
        };
        step::p2g_velocity(&t, &self.particles, &mut self.work.nodes, &params);
        Ok(&self.work.nodes)
    }

    fn step_coupled(
        &mut self,
        dt: f64,
        coupling: &mut impl GridCoupling,
    ) -> Result<(), SolverError> {
        self.sort_particles()?;
        let surface_forces = self.take_surface_forces()?;
        let grid = self.level.geometry;
        let params = StepParams {
            surface_forces: &surface_forces,
            ..step_params(
                &self.options,
                &self.materials,
                self.reference_particle_mass,
                &grid,
                dt,
            )
        };
        let work = &mut self.work;
        let t = Transfer {
            map: &work.map,
            bins: &work.bins,
        };
        let nodes = &mut work.nodes;
        let ps = &mut self.particles;
        // 1. Mass and momentum to the nodes; the fluid frame's steps 1–6.
        step::p2g_velocity(&t, ps, nodes, &params);
        coupling.before_forces(nodes, ps, dt)?;
        // 2. Internal force from σ_p + p I, and the momentum update.
        let shifted = &mut work.shifted_stress;
        shifted.clear();
        shifted.resize(ps.len(), [0.0; 6]);
        {
            let c: &dyn GridCoupling = coupling;
            shifted
                .par_iter_mut()
                .zip(ps.stress.par_iter().zip(ps.position.par_iter()))
                .with_min_len(1024)
                .for_each(|(s, (sigma, x))| {
                    let p = c.pressure_at(*x);
                    *s = *sigma;
                    for x in &mut s[..3] {
                        *x += p;
                    }
                });
        }
        step::p2g_integrate_stress(&t, ps, shifted, nodes, &params);
        // 3. The cell-centred changes back to the nodes.
        let dv = &mut work.node_change;
        dv.clear();
        dv.resize(nodes.mass.len(), [0.0; 3]);
        coupling.after_forces(nodes, dt, dv)?;
        nodes.add_velocity_change(dv, &params.node_update());
        // 4. G2P and the stress update.
        let bulk = &mut self.bulk;
        let failure = match params.scheme {
            UpdateScheme::Usl => {
                let parts = G2pParts {
                    velocity: true,
                    position: true,
                    gradient: Some(NodeVelocity::End),
                };
                step::g2p_and_update_stresses(&t, ps, bulk, nodes, &params, parts)
            }
            _ => {
                let parts = G2pParts {
                    velocity: false,
                    position: true,
                    gradient: Some(NodeVelocity::Remapped),
                };
                step::g2p_velocity_and_remap(&t, ps, nodes, &params);
                step::g2p_and_update_stresses(&t, ps, bulk, nodes, &params, parts)
            }
        };
        self.surface_forces = surface_forces;
        if let Some(f) = failure {
            return Err(self.particle_error(
                f.index,
                format!("{} (J = det F = {:e})", f.reason, f.jacobian),
            ));
        }
        {
            let c: &dyn GridCoupling = coupling;
            let ps = &mut self.particles;
            ps.temperature
                .par_iter_mut()
                .zip(ps.position.par_iter())
                .with_min_len(1024)
                .for_each(|(temp, x)| *temp += c.temperature_change(*x));
        }
        self.external_work +=
            self.work
                .nodes
                .external_work(&self.surface_forces, self.options.gravity, dt);
        self.handle_leaving_particles()?;
        self.time += dt;
        self.steps += 1;
        Ok(())
    }
}
