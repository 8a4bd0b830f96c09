//! The particle half of the coupled fluid–structure step of seed 000 §3.3
//! (the ICE–MPM pipeline of `brisance-couple`, whose `IceMpm::advance`
//! holds the seed's step list and calls these phases in its order).
//!
//! [`MpmSolver::begin_coupled_step`] opens one explicit MPM step (USL or
//! MUSL: the particles sorted into their bins, heat conducted inside the
//! solids when conduction is on, the surface tractions of the step) as a
//! [`CoupledStep`], whose phases are the MPM parts of the step list:
//!
//! 1. [`CoupledStep::project`]: P2G of mass and momentum (eq 12),
//!    v_I^n = p_I/m_I on every node with mass, those below the mass
//!    cut-off included (their mass enters the cells of eq 18:
//!    [`crate::grid_nodes::NodeUpdate::light_nodes_move`]). The fluid frame
//!    then takes the nodes to the cell centres (eq 18) and runs steps 2–6.
//! 2. [`CoupledStep::internal_forces`] (eq 14) from σ_p + p(x_p) I: the
//!    fluid frame applies the mixture pressure to the solid as −θ_s ∇p* at
//!    the cell centres (eq 24), so the nodes carry only the divergence of
//!    the solid's stress in excess of it, ∇·θ_r(σ_r − σ) with σ = −p I;
//!    then f_I += m_I g, a_I = f_I/m_I and v*_I = v_I^n + a_I Δt (eq 15),
//!    with a_I = 0 on the nodes below the cut-off. The fluid frame then
//!    runs steps 8–11 from v*_I.
//! 3. [`CoupledStep::add_node_velocity_change`] (step 13): the velocity
//!    change Δv_I the fluid frame gives every node is added to v*_I and,
//!    as Δv_I/Δt, to a_I, on every node with mass and the components no
//!    face condition holds.
//! 4. [`CoupledStep::update_particles`] (step 14 and the stress of step
//!    7): G2P (eqs 16–17) and the stress update from the grid velocity
//!    gradient (eq 13; MUSL re-maps v_I^{n+1} on light nodes too), then
//!    the temperature change of the heat exchange at each particle
//!    ([`CoupledStep::update_particles_from_nodes`]: the same with that
//!    change given on the nodes and gathered with the shape functions of
//!    the start of the step).
//! 5. [`CoupledStep::consume_particles`]: the particles' loss of mass to
//!    the fluids where a solid reactant burns (step 4's source applied to
//!    the particles).
//! 6. [`CoupledStep::finish`]: the external work, the removal of the
//!    particles that left through outflow faces, and the step counted.
//!
//! A step dropped before [`CoupledStep::finish`] (an error in a phase)
//! hands its buffer of surface forces back to the solver (rebuilt from the
//! loads every step) and counts no step.

use super::*;
use crate::step::{G2pParts, NodeVelocity, Transfer};

/// One coupled MPM step of Δt in progress (see the module doc): the
/// phases are called in the order of the module doc, each once.
#[derive(Debug)]
pub struct CoupledStep<'a> {
    solver: &'a mut MpmSolver,
    dt: f64,
    /// The surface tractions' nodal forces of this step, taken from the
    /// solver for the step and given back when it ends.
    surface_forces: Vec<(usize, [f64; 3])>,
}

/// The step's parameters and the solver's parts a phase works on,
/// borrowed field by field.
struct Parts<'s> {
    params: StepParams<'s>,
    transfer: Transfer<'s>,
    nodes: &'s mut GridNodes,
    particles: &'s mut Particles,
    bulk: &'s mut Vec<BulkViscosityState>,
    shifted: &'s mut Vec<[f64; 6]>,
    node_change: &'s mut Vec<[f64; 3]>,
}

impl MpmSolver {
    /// Opens one coupled step of Δt = `dt` (see the module doc). USL and
    /// MUSL only; the ΔF̄ anti-locking option is not available here.
    pub fn begin_coupled_step(&mut self, dt: f64) -> Result<CoupledStep<'_>, SolverError> {
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
        self.sort_particles()?;
        // Heat conduction inside the solids, from the state of the start
        // of the step (crate::conduction; temperatures only).
        self.conduct_heat(dt);
        let surface_forces = self.take_surface_forces()?;
        Ok(CoupledStep {
            solver: self,
            dt,
            surface_forces,
        })
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
}

impl CoupledStep<'_> {
    /// The step's parameters (light nodes move with p_I/m_I: their mass
    /// enters the cells of eq 18) and the parts of the solver a phase
    /// works on.
    fn parts(&mut self) -> Parts<'_> {
        let s = &mut *self.solver;
        let work = &mut s.work;
        Parts {
            params: StepParams {
                surface_forces: &self.surface_forces,
                light_nodes_move: true,
                ..step_params(
                    &s.options,
                    &s.materials,
                    s.reference_particle_mass,
                    &s.level.geometry,
                    self.dt,
                )
            },
            transfer: Transfer {
                map: &work.map,
                bins: &work.bins,
            },
            nodes: &mut work.nodes,
            particles: &mut s.particles,
            bulk: &mut s.bulk,
            shifted: &mut work.shifted_stress,
            node_change: &mut work.node_change,
        }
    }

    /// The nodes: after [`CoupledStep::project`] their mass m_I and
    /// velocity v_I^n (eq 12, on every node with mass, after the boundary
    /// conditions); after [`CoupledStep::internal_forces`] also v*_I.
    pub fn nodes(&self) -> &GridNodes {
        &self.solver.work.nodes
    }

    /// The particles (those of the start of the step until
    /// [`CoupledStep::update_particles`]).
    pub fn particles(&self) -> &Particles {
        &self.solver.particles
    }

    /// Phase 1 (step 1's eq 12): the particles' mass and momentum to the
    /// nodes.
    pub fn project(&mut self) {
        let p = self.parts();
        step::p2g_velocity(&p.transfer, p.particles, p.nodes, &p.params);
    }

    /// Phase 2 (eq 14 of step 7): the internal force from σ_p + p(x_p) I,
    /// with `pressure_at` the mixture pressure at a point (Pa), the body
    /// force and the momentum update v*_I.
    pub fn internal_forces(&mut self, pressure_at: impl Fn([f64; 3]) -> f64 + Sync) {
        let p = self.parts();
        let ps = &*p.particles;
        p.shifted.clear();
        p.shifted.resize(ps.len(), [0.0; 6]);
        p.shifted
            .par_iter_mut()
            .zip(ps.stress.par_iter().zip(ps.position.par_iter()))
            .with_min_len(1024)
            .for_each(|(s, (sigma, x))| {
                let pressure = pressure_at(*x);
                *s = *sigma;
                for x in &mut s[..3] {
                    *x += pressure;
                }
            });
        step::p2g_integrate_stress(&p.transfer, ps, p.shifted, p.nodes, &p.params);
    }

    /// Phase 3 (step 13): `change` writes each node's velocity change from
    /// the cell-centred values into its second argument (node storage
    /// order, zeroed on entry), reading the nodes (v*_I in
    /// `velocity_new`); the change is then added to the nodes.
    pub fn add_node_velocity_change(
        &mut self,
        change: impl FnOnce(&GridNodes, &mut [[f64; 3]]) -> Result<(), SolverError>,
    ) -> Result<(), SolverError> {
        let p = self.parts();
        p.node_change.clear();
        p.node_change.resize(p.nodes.mass.len(), [0.0; 3]);
        change(p.nodes, p.node_change)?;
        p.nodes
            .add_velocity_change(p.node_change, &p.params.node_update());
        Ok(())
    }

    /// Phase 4 (step 14 and the stress update of step 7): G2P and the
    /// stress update, then each particle's temperature change of the heat
    /// exchange, `temperature_change(x_p, material)` in K — or, for a
    /// material given a specific heat by [`MpmSolver::set_coupled_heat`],
    /// the heat in J/kg its temperature rises by through it.
    ///
    /// On several ranks ([`MpmSolver::distribute`]) each rank runs the
    /// fused G2P and stress update for its run of particles and the
    /// updated state crosses to every rank, as in [`MpmSolver`]'s own step
    /// (`solver::ranks`); the rest of the phase runs whole on every rank.
    pub fn update_particles(
        &mut self,
        temperature_change: impl Fn([f64; 3], MaterialId) -> f64 + Sync,
    ) -> Result<(), SolverError> {
        self.g2p_and_stresses()?;
        let s = &mut *self.solver;
        let (ps, heat) = (&mut s.particles, &s.coupled_heat);
        ps.temperature
            .par_iter_mut()
            .zip(ps.position.par_iter().zip(ps.material.par_iter()))
            .with_min_len(1024)
            .for_each(|(temp, (x, m))| {
                add_change(temp, temperature_change(*x, *m), heat_law(heat, *m))
            });
        Ok(())
    }

    /// Phase 4 with the temperature change given on the nodes:
    /// `node_change` holds, per particle material m, a value per node (node
    /// storage order, material m's block at `m · nodes .. (m + 1) · nodes`,
    /// `nodes` = [`GridNodes::mass`]'s length), and each particle takes
    /// ΔT_p = Σ_I N_Ip ΔT_I with the shape functions of the step's start,
    /// the ones its mass reached the nodes with (gathered before G2P moves
    /// it), so Σ_p m_p ΔT_p = Σ_I m_I ΔT_I for one material. The change
    /// is added after the stress update, as in
    /// [`CoupledStep::update_particles`] (a heat in J/kg for a material
    /// given a specific heat by [`MpmSolver::set_coupled_heat`], so that
    /// Σ_p m_p q_p = Σ_I m_I q_I is the heat its particles gain). An empty `node_change` changes no
    /// temperature (no gather).
    pub fn update_particles_from_nodes(&mut self, node_change: &[f64]) -> Result<(), SolverError> {
        if node_change.is_empty() {
            return self.g2p_and_stresses();
        }
        let s = &mut *self.solver;
        let mut change = std::mem::take(&mut s.work.particle_change);
        change.clear();
        change.resize(s.particles.len(), 0.0);
        crate::transfer::heat::g2p_node_values(
            &s.work.map,
            &s.work.bins,
            &s.particles.position,
            &s.particles.material,
            node_change,
            &mut change,
        );
        let result = self.g2p_and_stresses();
        let s = &mut *self.solver;
        if result.is_ok() {
            let (ps, heat) = (&mut s.particles, &s.coupled_heat);
            ps.temperature
                .par_iter_mut()
                .zip(change.par_iter().zip(ps.material.par_iter()))
                .with_min_len(1024)
                .for_each(|(t, (dt, m))| add_change(t, *dt, heat_law(heat, *m)));
        }
        s.work.particle_change = change;
        result
    }

    /// G2P (eqs 16–17) and the stress update of phase 4.
    fn g2p_and_stresses(&mut self) -> Result<(), SolverError> {
        let runs = self.solver.particle_runs();
        let mut p = self.parts();
        p.params.own = runs.as_ref().map(|r| (r.nodes().start, r.nodes().end));
        let (t, ps, nodes, params) = (&p.transfer, &mut *p.particles, p.nodes, &p.params);
        let failure = match params.scheme {
            UpdateScheme::Usl => {
                let parts = G2pParts {
                    velocity: true,
                    position: true,
                    gradient: Some(NodeVelocity::End),
                };
                let failure = step::g2p_and_update_stresses(t, ps, p.bulk, nodes, params, parts);
                share(&runs, ps, p.bulk, parts, failure)
            }
            _ => {
                let parts = G2pParts {
                    velocity: false,
                    position: true,
                    gradient: Some(NodeVelocity::Remapped),
                };
                step::g2p_velocity_and_remap(t, ps, nodes, params);
                let failure = step::g2p_and_update_stresses(t, ps, p.bulk, nodes, params, parts);
                share(&runs, ps, p.bulk, parts, failure)
            }
        };
        match failure {
            Some(f) => Err(self.solver.particle_error(f.index, f.describe())),
            None => Ok(()),
        }
    }

    /// Phase 5: `consume(particles, consumed)` may take mass from the
    /// particles (a solid reactant burning into a fluid product, seed 000
    /// step 4), changing their mass, volumes and whatever else it books,
    /// and lists in `consumed` (ascending) the particles it took whole;
    /// those are removed without being booked anywhere (the caller has).
    pub fn consume_particles(
        &mut self,
        consume: impl FnOnce(&mut Particles, &mut Vec<usize>) -> Result<(), SolverError>,
    ) -> Result<(), SolverError> {
        let s = &mut *self.solver;
        let mut consumed = std::mem::take(&mut s.work.consumed);
        consumed.clear();
        let result = consume(&mut s.particles, &mut consumed);
        if result.is_ok() && !consumed.is_empty() {
            s.remove_sorted(&consumed);
        }
        s.work.consumed = consumed;
        result
    }

    /// Phase 6: the work of the external forces, the particles that left
    /// through outflow faces, and the step counted.
    pub fn finish(mut self) -> Result<(), SolverError> {
        let s = &mut *self.solver;
        s.surface_forces = std::mem::take(&mut self.surface_forces);
        s.external_work +=
            s.work
                .nodes
                .external_work(&s.surface_forces, s.options.gravity, self.dt);
        s.handle_leaving_particles()?;
        s.time += self.dt;
        s.steps += 1;
        Ok(())
    }
}

impl Drop for CoupledStep<'_> {
    /// The buffer of surface forces goes back to the solver however the
    /// step ends (the next step refills it from the loads).
    fn drop(&mut self) {
        if !self.surface_forces.is_empty() {
            self.solver.surface_forces = std::mem::take(&mut self.surface_forces);
        }
    }
}

/// Material `m`'s specific heat of [`MpmSolver::set_coupled_heat`], if any.
#[inline]
fn heat_law(
    heat: &[Option<brisance_constitutive::SpecificHeat>],
    m: MaterialId,
) -> Option<&brisance_constitutive::SpecificHeat> {
    heat.get(m.0 as usize).and_then(|c| c.as_ref())
}

/// A particle's temperature after the heat exchange's `change`: T + ΔT
/// for a temperature change (`heat` `None`, the bits of T + ΔT), the rise
/// whose heat is `change` (J/kg) through the specific heat `heat`
/// otherwise ([`brisance_constitutive::SpecificHeat::temperature_rise`]);
/// a zero change leaves T as it is.
#[inline]
fn add_change(
    temperature: &mut f64,
    change: f64,
    heat: Option<&brisance_constitutive::SpecificHeat>,
) {
    match heat {
        None => *temperature += change,
        Some(_) if change == 0.0 => {}
        Some(c) => *temperature += c.temperature_rise(*temperature, change),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{fill_shape, FillSpec, Shape};
    use brisance_constitutive::{Hypoelastic, ObjectiveRate, PressureModel};

    /// A soft hypoelastic solid (K 10 MPa, G 5 MPa).
    /// A tube of 8 cells of 0.125 m along x and a block of particles (2 per
    /// cell per direction, 1000 kg/m³) filling cells 2–4 at `velocity` and
    /// `temperature` (K).
    fn block_of_three_cells(velocity: [f64; 3], temperature: f64) -> (Level, Particles) {
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
                velocity,
                temperature,
                specific_internal_energy: 0.0,
            },
        )
        .unwrap();
        (level, particles)
    }

    fn soft_solid() -> MaterialModel {
        MaterialModel::Hypoelastic(Hypoelastic {
            shear_modulus: 5e6,
            pressure: PressureModel::Linear { bulk_modulus: 1e7 },
            rate: ObjectiveRate::Jaumann,
        })
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
            let (level, mut particles) = block_of_three_cells([2.0, 0.0, 0.0], 300.0);
            let h = 0.125;
            // From h/4 and 3h/4 in their cells to just past h/2 and h.
            for x in &mut particles.position {
                x[0] += 0.25 * h + 1e-4 * h;
            }
            let model = soft_solid();
            let options = MpmOptions {
                scheme,
                mass_cutoff: 1e-3,
                ..Default::default()
            };
            let mut s = MpmSolver::new(level, vec![model], particles, options).unwrap();
            let m_p = s.particles().mass[0];
            // A fluid frame that exerts nothing and hands every node the
            // same velocity change, 1 m/s along x; the nodal fields it is
            // shown are recorded.
            let mut step = s.begin_coupled_step(1e-6).unwrap();
            step.project();
            let mass = step.nodes().mass.clone();
            let velocity = step.nodes().velocity.clone();
            step.internal_forces(|_| 0.0);
            let velocity_new = step.nodes().velocity_new.clone();
            step.add_node_velocity_change(|_, dv| {
                dv.fill([1.0, 0.0, 0.0]);
                Ok(())
            })
            .unwrap();
            step.update_particles(|_, _| 0.0).unwrap();
            step.consume_particles(|_, _| Ok(())).unwrap();
            step.finish().unwrap();
            let light: Vec<usize> = (0..mass.len())
                .filter(|&i| mass[i] > 0.0 && mass[i] <= 1e-3 * m_p)
                .collect();
            assert_eq!(light.len(), 1, "{scheme:?}: one light node, {:?}", mass);
            assert!((mass[light[0]] / m_p - 1e-4).abs() < 1e-9);
            for i in (0..mass.len()).filter(|&i| mass[i] > 0.0) {
                for v in [velocity[i], velocity_new[i]] {
                    assert!(
                        (v[0] - 2.0).abs() < 1e-12 && v[1] == 0.0 && v[2] == 0.0,
                        "{scheme:?}: node {i} (mass {:e} kg) at {v:?}",
                        mass[i]
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

    /// A material given a specific heat by `set_coupled_heat` takes the
    /// value handed to it as a heat (J/kg): 4000 J/kg on every node (or
    /// from every cell, `update_particles`) raises each particle of a
    /// block by the ΔT with H(T + ΔT) − H(T) = 4000 J/kg — exactly 8 K for
    /// a constant 500 J/(kg·K), through the Curie peak (1040 K) of the
    /// 4340 steel from 1039.5 K — and a material without one by 4000 K.
    #[test]
    fn a_material_with_a_coupled_specific_heat_takes_the_change_as_heat() {
        use brisance_constitutive::SpecificHeat;
        let laws = [
            Some(SpecificHeat::Constant(500.0)),
            Some(SpecificHeat::steel_4340()),
            None,
        ];
        for law in laws {
            for through_nodes in [true, false] {
                let (level, particles) = block_of_three_cells([0.0; 3], 1039.5);
                let mut s =
                    MpmSolver::new(level, vec![soft_solid()], particles, MpmOptions::default())
                        .unwrap();
                s.set_coupled_heat(vec![law.clone()]);
                let mut step = s.begin_coupled_step(1e-6).unwrap();
                step.project();
                let nodes = step.nodes().mass.len();
                step.internal_forces(|_| 0.0);
                step.add_node_velocity_change(|_, _| Ok(())).unwrap();
                if through_nodes {
                    step.update_particles_from_nodes(&vec![4000.0; nodes])
                        .unwrap();
                } else {
                    step.update_particles(|_, _| 4000.0).unwrap();
                }
                step.consume_particles(|_, _| Ok(())).unwrap();
                step.finish().unwrap();
                for &t in &s.particles().temperature {
                    match &law {
                        Some(SpecificHeat::Constant(_)) => assert_eq!(t, 1047.5),
                        Some(c) => {
                            let q = c.heat(t) - c.heat(1039.5);
                            assert!(t > 1040.0 && (q / 4000.0 - 1.0).abs() < 1e-9, "{t} K: {q}");
                        }
                        None => assert!((t - 5039.5).abs() < 1e-9, "{t}"),
                    }
                }
            }
        }
    }

    /// A temperature change given on the nodes reaches the particles with
    /// the heat the nodes hold, Σ_p m_p ΔT_p = Σ_I m_I ΔT_I, for every
    /// shape function and each of two materials (its own block of node
    /// values), although the particles move a fifth of a cell in the step
    /// (the gather uses the shape functions the mass was scattered with);
    /// a material with no block gets no change.
    #[test]
    fn a_node_temperature_change_reaches_the_particles_with_its_heat() {
        for shape in [
            ShapeFunction::Linear,
            ShapeFunction::Gimp,
            ShapeFunction::CpGimp,
            ShapeFunction::QuadraticBSpline,
        ] {
            let level = Level::new([0.0; 3], [1.0, 0.5, 0.125], [8, 4, 1], [1, 1, 1], 0).unwrap();
            let h = 0.125;
            let fill = |particles: &mut Particles, m: usize| {
                let (lo, hi) = [(2.0, 4.0), (4.0, 6.0)][m];
                fill_shape(
                    particles,
                    &level.geometry,
                    &FillSpec {
                        shape: Shape::Box {
                            min: [lo * h, h, 0.0],
                            max: [hi * h, 3.0 * h, h],
                        },
                        ppc: 2,
                        density: 1000.0 * (1.0 + m as f64),
                        material: MaterialId(m as u16),
                        velocity: [2.5, 0.0, 0.0],
                        temperature: 300.0,
                        specific_internal_energy: 0.0,
                    },
                )
                .unwrap();
            };
            let mut particles = Particles::default();
            fill(&mut particles, 0);
            fill(&mut particles, 1);
            let model = soft_solid();
            let options = MpmOptions {
                shape,
                ..Default::default()
            };
            let models = vec![model.clone(), model];
            // The nodes' mass of each material alone, from the start
            // positions and the same shape functions.
            let alone: Vec<Vec<f64>> = (0..2)
                .map(|m| {
                    let mut own = Particles::default();
                    fill(&mut own, m);
                    let mut one =
                        MpmSolver::new(level.clone(), models.clone(), own, options).unwrap();
                    one.project_to_nodes().unwrap().mass.clone()
                })
                .collect();
            let mut s = MpmSolver::new(level, models, particles, options).unwrap();
            let start: Vec<[f64; 3]> = s.particles().position.clone();
            let mut step = s.begin_coupled_step(0.01).unwrap();
            step.project();
            let nodes = step.nodes().mass.len();
            let values: Vec<f64> = (0..2 * nodes)
                .map(|i| 10.0 * ((i * 7919 % 101) as f64 / 101.0 - 0.5))
                .collect();
            step.internal_forces(|_| 0.0);
            step.add_node_velocity_change(|_, _| Ok(())).unwrap();
            step.update_particles_from_nodes(&values).unwrap();
            step.consume_particles(|_, _| Ok(())).unwrap();
            step.finish().unwrap();
            let ps = s.particles();
            // (The step sorts the particles: compare their mean.)
            let mean = |x: &[[f64; 3]]| x.iter().map(|x| x[0]).sum::<f64>() / x.len() as f64;
            assert!(
                (mean(&ps.position) - mean(&start) - 0.025).abs() < 1e-12,
                "{shape:?}: the particles moved 0.025 m"
            );
            for m in 0..2u16 {
                let heat: f64 = (0..ps.len())
                    .filter(|&p| ps.material[p] == MaterialId(m))
                    .map(|p| ps.mass[p] * (ps.temperature[p] - 300.0))
                    .sum();
                let mass = &alone[m as usize];
                let block = &values[m as usize * nodes..(m as usize + 1) * nodes];
                let nodal: f64 = mass.iter().zip(block).map(|(m, v)| m * v).sum();
                assert!(
                    (heat - nodal).abs() <= 1e-12 * nodal.abs().max(1.0),
                    "{shape:?} material {m}: particles {heat:e}, nodes {nodal:e}"
                );
            }
            // No block for either material: nothing changes.
            let before = s.particles().temperature.clone();
            let mut step = s.begin_coupled_step(1e-6).unwrap();
            step.project();
            step.internal_forces(|_| 0.0);
            step.add_node_velocity_change(|_, _| Ok(())).unwrap();
            step.update_particles_from_nodes(&[]).unwrap();
            step.consume_particles(|_, _| Ok(())).unwrap();
            step.finish().unwrap();
            assert_eq!(s.particles().temperature, before, "{shape:?}");
        }
    }
}
