//! The particle half of the coupled fluid–structure step of seed 000 §3.3
//! (the ICE–MPM pipeline of `brisance-couple`).
//!
//! [`MpmSolver::advance_coupled`] is the explicit MPM step of
//! [`crate::step`] (USL or MUSL) with the Eulerian frame called at the two
//! points where the seed's step list needs it:
//!
//! 1. P2G of mass and momentum (eq 12), v_I^n = p_I/m_I on every node with
//!    mass, those below the mass cut-off included (their mass enters the
//!    cells of eq 18: [`crate::grid_nodes::NodeUpdate::light_nodes_move`]); then
//!    [`GridCoupling::before_forces`] — the nodes to cell centres (eq 18),
//!    the equilibration pressure, face velocities and the advanced pressure
//!    p (steps 1–6).
//! 2. The internal force (eq 14) from σ_p + p(x_p) I: the fluid frame
//!    applies the mixture pressure to the solid as −θ_s ∇p* at the cell
//!    centres (eq 24), so the nodes carry only the divergence of the
//!    solid's stress in excess of it, ∇·θ_r(σ_r − σ) with σ = −p I; then
//!    f_I += m_I g, a_I = f_I/m_I and v*_I = v_I^n + a_I Δt (eq 15), with
//!    a_I = 0 on the nodes below the cut-off.
//! 3. [`GridCoupling::after_forces`] — the cell-centred Lagrangian values,
//!    momentum and heat exchange (steps 8–10) — returns the velocity
//!    change Δv_I of every node, which is added to v*_I and, as Δv_I/Δt,
//!    to a_I (step 13), on every node with mass and the components no face
//!    condition holds.
//! 4. G2P (eqs 16–17) and the stress update from the grid velocity
//!    gradient (eq 13, step 7; MUSL re-maps v_I^{n+1} on light nodes too),
//!    the temperature change of the heat exchange at each particle
//!    ([`GridCoupling::temperature_change`]), the particles' loss of mass
//!    to the fluids where a solid reactant burns
//!    ([`GridCoupling::consume_particles`], step 4's source applied to the
//!    particles), and the removal of particles that left through outflow
//!    faces (step 14).
//!
//! With heat conduction on ([`crate::conduction`]), the particles'
//! temperatures first conduct over the step, as in the standalone step.
//!
//! Advection of the fluids (step 12) is the pipeline's, after this step.

use super::*;
use crate::step::{G2pParts, NodeVelocity, Transfer};

/// What the Eulerian frame does inside [`MpmSolver::advance_coupled`].
pub trait GridCoupling: Sync + Send {
    /// Steps 1–6 of seed 000 §3.3: `nodes` holds the particles' lumped
    /// mass m_I and velocity v_I^n = p_I/m_I (eq 12, on every node with
    /// mass, after the boundary conditions); `particles` are those of the
    /// start of the step.
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
    /// step for a particle of `material`, K.
    fn temperature_change(&self, x: [f64; 3], material: MaterialId) -> f64;

    /// After G2P and the heat exchange: the Eulerian frame may take mass
    /// from the particles (a solid reactant burning into a fluid product,
    /// seed 000 step 4), changing their mass, volumes and whatever else it
    /// books, and lists in `consumed` (ascending) the particles it took
    /// whole; the solver removes those without booking them anywhere (the
    /// frame has). Nothing by default.
    fn consume_particles(
        &mut self,
        particles: &mut Particles,
        consumed: &mut Vec<usize>,
    ) -> Result<(), SolverError> {
        let _ = (particles, consumed);
        Ok(())
    }
}

impl MpmSolver {
    /// One coupled step of Δt = `dt` (see the module doc). USL and MUSL
    /// only; the ΔF̄ anti-locking option is not available here.
    pub fn advance_coupled(
        &mut self,
        dt: f64,
        coupling: &mut impl GridCoupling,
    ) -> Result<(), SolverError> {
        brisance_core::solver::check_step("MPM", dt)?;
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
        let params = StepParams {
            light_nodes_move: true,
            ..step_params(
                &self.options,
                &self.materials,
                self.reference_particle_mass,
                &grid,
                0.0,
            )
        };
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
        // Heat conduction inside the solids, from the state of the start
        // of the step (crate::conduction; temperatures only).
        self.conduct_heat(dt);
        let surface_forces = self.take_surface_forces()?;
        let grid = self.level.geometry;
        let params = StepParams {
            surface_forces: &surface_forces,
            light_nodes_move: true,
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
        // Light nodes (below the mass cut-off) keep p_I/m_I: their mass
        // enters the cells of eq 18 (NodeUpdate::light_nodes_move).
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
            return Err(self.particle_error(f.index, f.describe()));
        }
        {
            let c: &dyn GridCoupling = coupling;
            let ps = &mut self.particles;
            ps.temperature
                .par_iter_mut()
                .zip(ps.position.par_iter().zip(ps.material.par_iter()))
                .with_min_len(1024)
                .for_each(|(temp, (x, m))| *temp += c.temperature_change(*x, *m));
        }
        let mut consumed = std::mem::take(&mut self.work.consumed);
        consumed.clear();
        coupling.consume_particles(&mut self.particles, &mut consumed)?;
        if !consumed.is_empty() {
            self.remove_sorted(&consumed);
        }
        self.work.consumed = consumed;
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{fill_shape, FillSpec, Shape};
    use brisance_constitutive::{Hypoelastic, ObjectiveRate, PressureModel};

    /// A fluid frame that exerts nothing and hands every node the same
    /// velocity change `dv`; it records the nodal fields it is shown.
    struct Recorder {
        dv: [f64; 3],
        mass: Vec<f64>,
        velocity: Vec<[f64; 3]>,
        velocity_new: Vec<[f64; 3]>,
    }

    impl GridCoupling for Recorder {
        fn before_forces(
            &mut self,
            nodes: &GridNodes,
            _: &Particles,
            _: f64,
        ) -> Result<(), SolverError> {
            self.mass.clone_from(&nodes.mass);
            self.velocity.clone_from(&nodes.velocity);
            Ok(())
        }
        fn pressure_at(&self, _: [f64; 3]) -> f64 {
            0.0
        }
        fn after_forces(
            &mut self,
            nodes: &GridNodes,
            _: f64,
            dv: &mut [[f64; 3]],
        ) -> Result<(), SolverError> {
            self.velocity_new.clone_from(&nodes.velocity_new);
            dv.fill(self.dv);
            Ok(())
        }
        fn temperature_change(&self, _: [f64; 3], _: MaterialId) -> f64 {
            0.0
        }
    }

    /// A stress-free 1D bar at 2 m/s whose leading particle lies 10⁻⁴ of a
    /// cell past a node (8 cells of 1/8 m, 2 particles per cell, cut-off
    /// 10⁻³ of a particle's mass): the node ahead of it holds 10⁻⁴ of a
    /// particle's mass, below the cut-off. Every node with mass shows the
    /// fluid frame the particles' velocity, 2 m/s exactly, before and
    /// after the internal force — the light node included (zeroed by the
    /// cut-off, it gave the coupled pipeline's leading cell a near-zero
    /// solid velocity beside a gas at the solid's speed) — and a uniform
    /// velocity change of 1 m/s from the fluid frame reaches every
    /// particle whole, so the nodes took exactly the momentum the cells
    /// gave (the light node's share included).
    #[test]
    fn light_nodes_carry_the_particles_velocity_and_their_share_of_the_change() {
        for scheme in [UpdateScheme::Usl, UpdateScheme::Musl] {
            let level = Level::new([0.0; 3], [1.0, 0.125, 0.125], [8, 1, 1], [1, 1, 1], 0).unwrap();
            let h = 0.125;
            let mut particles = Particles::default();
            fill_shape(
                &mut particles,
                &level.geometry,
                &FillSpec {
                    shape: Shape::Box {
                        min: [2.0 * h, 0.0, 0.0],
                        max: [5.0 * h, h, h],
                    },
                    ppc: 2,
                    density: 1000.0,
                    material: MaterialId(0),
                    velocity: [2.0, 0.0, 0.0],
                    temperature: 300.0,
                    specific_internal_energy: 0.0,
                },
            )
            .unwrap();
            // From h/4 and 3h/4 in their cells to just past h/2 and h.
            for x in &mut particles.position {
                x[0] += 0.25 * h + 1e-4 * h;
            }
            let model = MaterialModel::Hypoelastic(Hypoelastic {
                shear_modulus: 5e6,
                pressure: PressureModel::Linear { bulk_modulus: 1e7 },
                rate: ObjectiveRate::Jaumann,
            });
            let options = MpmOptions {
                scheme,
                mass_cutoff: 1e-3,
                ..Default::default()
            };
            let mut s = MpmSolver::new(level, vec![model], particles, options).unwrap();
            let m_p = s.particles().mass[0];
            let mut frame = Recorder {
                dv: [1.0, 0.0, 0.0],
                mass: Vec::new(),
                velocity: Vec::new(),
                velocity_new: Vec::new(),
            };
            s.advance_coupled(1e-6, &mut frame).unwrap();
            let light: Vec<usize> = (0..frame.mass.len())
                .filter(|&i| frame.mass[i] > 0.0 && frame.mass[i] <= 1e-3 * m_p)
                .collect();
            assert_eq!(
                light.len(),
                1,
                "{scheme:?}: one light node, {:?}",
                frame.mass
            );
            assert!((frame.mass[light[0]] / m_p - 1e-4).abs() < 1e-9);
            for i in (0..frame.mass.len()).filter(|&i| frame.mass[i] > 0.0) {
                for v in [frame.velocity[i], frame.velocity_new[i]] {
                    assert!(
                        (v[0] - 2.0).abs() < 1e-12 && v[1] == 0.0 && v[2] == 0.0,
                        "{scheme:?}: node {i} (mass {:e} kg) at {v:?}",
                        frame.mass[i]
                    );
                }
            }
            for (p, v) in s.particles().velocity.iter().enumerate() {
                assert!(
                    (v[0] - 3.0).abs() < 1e-12,
                    "{scheme:?}: particle {p} at {v:?}"
                );
            }
        }
    }
}
