//! The fluid frame of the coupled step: the ICE with the cell arrays that
//! join it to the particles — step 1's projection of the solids to the
//! cells (eq 18), the solids' burn (step 4), the Lagrangian values and
//! exchanges (steps 8–11) with the solids' trace rules, and the adjoint
//! of eq 18 that takes the cells' changes back to the nodes (steps 13–14).

use super::*;

/// The fluid frame within one coupled step: the ICE and the cell arrays
/// that join it to the particles.
pub(super) struct FluidFrame<'a> {
    pub(super) ice: &'a mut IceSolver<EosModel>,
    pub(super) solids: &'a [Solid],
    pub(super) burns: &'a mut [ParticleBurn],
    pub(super) grid: UniformGridGeometry,
    /// Whether the cells are (r, z) rings.
    pub(super) rz: bool,
    /// Each cell's volume (a ring's on an axisymmetric grid), m³.
    pub(super) volumes: &'a [f64],
    pub(super) s: &'a mut Scratch,
}

impl FluidFrame<'_> {
    /// Step 1: each solid's cell state from the nodes (mass, velocity, eq
    /// 18; with several solids, each its share of the mass:
    /// [`steps::materials_to_cells`]) and its particles (specific volume,
    /// temperature), with the trace state where it is absent.
    pub(super) fn project_particles_to_cells(&mut self, nodes: &GridNodes, particles: &Particles) {
        let g = &self.grid;
        let s = &mut *self.s;
        let state = steps::ParticleState {
            position: &particles.position,
            mass: &particles.mass,
            volume: &particles.volume,
            temperature: &particles.temperature,
            material: &particles.material,
        };
        let single = self.solids.len() == 1;
        if single {
            steps::project_to_cells(
                g,
                self.rz,
                &nodes.lattice,
                &nodes.mass,
                &nodes.velocity,
                state,
                &mut s.node_sums,
                &mut s.cell_mass,
                &mut s.cell_velocity,
                &mut s.solids[0].state,
            );
            s.solids[0].mass.copy_from_slice(&s.cell_mass);
        } else {
            steps::nodes_to_cells(
                g,
                self.rz,
                &nodes.lattice,
                &nodes.mass,
                &nodes.velocity,
                &mut s.cell_mass,
                &mut s.cell_velocity,
            );
            // The solids' mass and state arrays lent to the projection
            // (buffers kept between steps: no allocation).
            s.mass_buffers.clear();
            s.state_buffers.clear();
            for c in s.solids.iter_mut() {
                s.mass_buffers.push(std::mem::take(&mut c.mass));
                s.state_buffers.push(std::mem::take(&mut c.state));
            }
            steps::materials_to_cells(
                g,
                self.rz,
                &nodes.lattice,
                state,
                self.solids.len(),
                &s.cell_mass,
                &mut s.node_sums,
                &mut s.mass_buffers,
                &mut s.state_buffers,
            );
            for (c, (m, x)) in s
                .solids
                .iter_mut()
                .zip(s.mass_buffers.drain(..).zip(s.state_buffers.drain(..)))
            {
                c.mass = m;
                c.state = x;
            }
        }
        self.ice.eulerian_velocity(&mut s.fluid_velocity);
        let volumes = self.volumes;
        for (solid, c) in self.solids.iter().zip(s.solids.iter_mut()) {
            let v_ref = solid.reference_volume;
            let t_ref = solid.reference_temperature;
            (
                (c.mass.par_iter(), volumes.par_iter()),
                c.state.par_iter(),
                (s.fluid_velocity.par_iter(), s.cell_velocity.par_iter()),
                c.trace.par_iter_mut(),
                c.mass_density.par_iter_mut(),
                c.specific_volume.par_iter_mut(),
                c.temperature.par_iter_mut(),
                c.velocity.par_iter_mut(),
            )
                .into_par_iter()
                .with_min_len(1024)
                .for_each(
                    |((m, cell_volume), state, (uf, uc), trace, rho_out, v_out, t_out, u_out)| {
                        let rho = m / cell_volume;
                        let (v, t) = state.unwrap_or((v_ref, t_ref));
                        *trace = !(rho * v > TRACE_FRACTION);
                        if *trace {
                            *rho_out = TRACE_FRACTION / v_ref;
                            *v_out = v_ref;
                            *t_out = t_ref;
                            *u_out = *uf;
                        } else {
                            *rho_out = rho;
                            *v_out = v;
                            *t_out = t;
                            *u_out = *uc;
                        }
                    },
                );
        }
        if !single {
            self.ice.eulerian_density(&mut s.fluid_density);
            s.mix_trace_velocities(volumes);
        }
    }

    /// Steps 8–10 done: the velocity change the nodes receive in each cell
    /// (step 13) — with one solid its own, with several their
    /// mass-weighted mean Σ_s M_c,s Δu_s / M_c (one velocity field) — and
    /// the momentum a trace took that no node receives, (ρ_s V − M_c,s)
    /// Δu_s, returned to the cell's fluids: the momentum of both frames is
    /// kept.
    pub(super) fn combine_solid_changes(&mut self) {
        let volumes = self.volumes;
        let s = &mut *self.s;
        s.trace_momentum.fill([0.0; 3]);
        s.trace_excess.fill(0.0);
        for c in &s.solids {
            s.trace_momentum
                .par_iter_mut()
                .zip(s.trace_excess.par_iter_mut())
                .zip(c.trace.par_iter())
                .zip(c.mass_density.par_iter().zip(c.mass.par_iter()))
                .zip(c.change.par_iter().zip(volumes.par_iter()))
                .with_min_len(1024)
                .for_each(|((((dp, mass), trace), (rho, m)), (du, volume))| {
                    if *trace {
                        let excess = rho * volume - m;
                        *mass += excess.abs();
                        for d in 0..3 {
                            dp[d] += excess * du[d];
                        }
                    }
                });
        }
        if s.solids.len() == 1 {
            // `cell_change` reads the solid's own array (no copy).
            return;
        }
        let solids = &s.solids;
        s.cell_change
            .par_iter_mut()
            .zip(s.cell_mass.par_iter())
            .enumerate()
            .with_min_len(1024)
            .for_each(|(k, (du, m))| {
                *du = if *m > 0.0 {
                    let sum = solids.iter().fold([0.0; 3], |acc: [f64; 3], c| {
                        std::array::from_fn(|d| acc[d] + c.mass[k] * c.change[k][d])
                    });
                    sum.map(|x| x / m)
                } else {
                    solids[0].change[k]
                };
            });
    }
}

impl FluidFrame<'_> {
    /// The momentum the solids' traces took (`trace_momentum`) returned
    /// to real mass at no more than the traces' own velocity change.
    /// Where what takes it — the cell's fluids and the solids present
    /// (not traces), mass R — is at least as heavy as the traces' mass
    /// E = Σ|ρ_s V − M_c,s|, it goes there as before. A lighter R is an
    /// emptied cell: a solid has left it and the fluids that fill it are
    /// traces too. Its traces' velocity change is then the round-off of
    /// their velocity, ε|u| (an exchange with fluids 10¹⁷ times lighter
    /// cannot move them more), and returned in full it gave the fluids
    /// E/R · ε|u|, about 20 |u| a step: on the axis of the cook-off at
    /// h = 1 mm (configs/cookoff_rz.ron) an emptied cell's fluids at
    /// 10⁻¹⁹ kg/m³ went from 4.8 km/s to 7·10¹⁰ m/s in 13 steps and
    /// collapsed the time step at 37 µs. There R/E of it goes to the
    /// fluids and the solids present, the part the traces' own particle
    /// mass M_t = Σ M_c,s can take, min(M_t, E − R)/E, to the nodes
    /// through the cell's velocity change, and what remains,
    /// (E − R − M_t)/E > 0 only where no particle reaches the cell, is
    /// not returned: at most E|Δu_s|, the momentum of a trace the cell's
    /// real mass is too light to carry.
    pub(super) fn bound_trace_momentum(&mut self) {
        fn split(dp: &mut [f64; 3], excess: f64, receivers: f64, traces: f64) -> [f64; 3] {
            if *dp == [0.0; 3] || receivers >= excess {
                return [0.0; 3];
            }
            let to_nodes = traces.min(excess - receivers) / excess;
            let nodes = dp.map(|x| x * to_nodes);
            *dp = dp.map(|x| x * (receivers / excess));
            nodes
        }
        let volumes = self.volumes;
        let s = &mut *self.s;
        self.ice.eulerian_lagrangian_density(&mut s.fluid_mass);
        let masses = (
            s.trace_excess.par_iter(),
            s.fluid_mass.par_iter(),
            volumes.par_iter(),
        );
        if let [one] = s.solids.as_mut_slice() {
            (
                s.trace_momentum.par_iter_mut(),
                masses,
                one.change.par_iter_mut(),
            )
                .into_par_iter()
                .zip(one.mass.par_iter())
                .with_min_len(1024)
                .for_each(|((dp, (excess, rho_f, volume), du), m)| {
                    let nodes = split(dp, *excess, rho_f * volume, *m);
                    if *m > 0.0 {
                        for d in 0..3 {
                            du[d] += nodes[d] / m;
                        }
                    }
                });
            return;
        }
        let solids = &s.solids;
        (
            s.trace_momentum.par_iter_mut(),
            masses,
            s.cell_change.par_iter_mut(),
        )
            .into_par_iter()
            .zip(s.cell_mass.par_iter())
            .enumerate()
            .with_min_len(1024)
            .for_each(|(k, ((dp, (excess, rho_f, volume), du), m))| {
                let (present, traces) = solids.iter().fold((0.0, 0.0), |(p, t), c| {
                    if c.trace[k] {
                        (p, t + c.mass[k])
                    } else {
                        (p + c.mass[k], t)
                    }
                });
                let nodes = split(dp, *excess, rho_f * volume + present, traces);
                if *m > 0.0 {
                    for d in 0..3 {
                        du[d] += nodes[d] / m;
                    }
                }
            });
    }

    /// With several solids, the momentum a solid's trace took
    /// (`trace_momentum`) goes to what holds the cell's mass: the fluids
    /// and the solids present there (not a trace) in proportion to their
    /// masses, M_f / (M_f + M_o) of it to the fluids and the rest to the
    /// nodes through the cell's velocity change (`cell_change`, whose
    /// particles' mass M_c receives it). In a cell another solid fills, the
    /// fluids are traces of almost no mass (10⁻²⁸ of the cell's inside the
    /// cook-off's explosive), and given all of it they took velocities of
    /// 10¹⁰ m/s that collapsed the step. Both frames' momentum is kept as
    /// before.
    pub(super) fn share_trace_momentum(&mut self) {
        let volumes = self.volumes;
        let s = &mut *self.s;
        let solids = &s.solids;
        s.trace_momentum
            .par_iter_mut()
            .zip(s.cell_change.par_iter_mut())
            .zip(s.fluid_mass.par_iter().zip(s.cell_mass.par_iter()))
            .enumerate()
            .with_min_len(1024)
            .for_each(|(k, ((dp, du), (rho_f, m)))| {
                if *dp == [0.0; 3] || !(*m > 0.0) {
                    return;
                }
                let other: f64 = solids
                    .iter()
                    .filter(|c| !c.trace[k])
                    .map(|c| c.mass[k])
                    .sum();
                if !(other > 0.0) {
                    return;
                }
                let fluid = rho_f * volumes[k];
                let to_solids = other / (fluid + other);
                for d in 0..3 {
                    du[d] += dp[d] * to_solids / m;
                    dp[d] -= dp[d] * to_solids;
                }
            });
    }
}

impl Scratch {
    /// With several solids, a solid's trace takes the mass-weighted
    /// velocity of what the cell holds — its fluids and the solids present
    /// there (at the particles' cell velocity u_c) — not the fluids' alone:
    /// in a cell full of another solid the fluids are traces too, and a
    /// trace moving with them would be dragged to the solid's speed by the
    /// exchange and hand that momentum to them.
    pub(super) fn mix_trace_velocities(&mut self, volumes: &[f64]) {
        for s in 0..self.solids.len() {
            let mut velocity = std::mem::take(&mut self.solids[s].velocity);
            let this = &*self;
            velocity
                .par_iter_mut()
                .enumerate()
                .with_min_len(1024)
                .for_each(|(k, u)| {
                    if !this.solids[s].trace[k] {
                        return;
                    }
                    let present: f64 = (0..this.solids.len())
                        .filter(|&r| r != s && !this.solids[r].trace[k])
                        .map(|r| this.solids[r].mass[k] / volumes[k])
                        .sum();
                    if present > 0.0 {
                        let rho_f = this.fluid_density[k];
                        let (uf, uc) = (this.fluid_velocity[k], this.cell_velocity[k]);
                        *u = std::array::from_fn(|d| {
                            (rho_f * uf[d] + present * uc[d]) / (rho_f + present)
                        });
                    }
                });
            self.solids[s].velocity = velocity;
        }
    }
}

impl FluidFrame<'_> {
    /// Step 1 from the nodes' mass and velocity v_I^n (eq 12): each
    /// solid's cell state (eq 18, [`FluidFrame::project_particles_to_cells`])
    /// imported into the ICE as its Lagrangian material's.
    pub(super) fn import_solids(
        &mut self,
        nodes: &GridNodes,
        particles: &Particles,
    ) -> Result<(), SolverError> {
        self.project_particles_to_cells(nodes, particles);
        for (solid, c) in self.solids.iter().zip(&self.s.solids) {
            self.ice.import_lagrangian(
                solid.ice,
                &LagrangianCells {
                    mass_density: &c.mass_density,
                    velocity: &c.velocity,
                    specific_volume: None,
                    temperature: &c.temperature,
                },
            )?;
        }
        Ok(())
    }

    /// Step 4 for reactants the particles carry, after step 2: the fraction
    /// of their mass each cell burns this step (taken from the particles in
    /// [`FluidFrame::consume_particles`]).
    pub(super) fn burn_fractions(&mut self, dt: f64) {
        for b in self.burns.iter_mut() {
            self.ice.lagrangian_burn_fraction(
                b.reaction,
                dt,
                &mut b.fraction,
                &mut b.specific_volume,
            );
        }
    }

    /// The advanced pressure of step 5 in every cell, which the particles
    /// feel in the internal force ([`FluidFrame::pressure_at`]).
    pub(super) fn take_advanced_pressure(&mut self) {
        self.ice.advanced_pressure(&mut self.s.pressure);
    }

    /// The mixture pressure at point `x`, Pa: added to each particle's
    /// stress as +p I in the internal force.
    pub(super) fn pressure_at(&self, x: [f64; 3]) -> f64 {
        steps::interpolate_cell_field(&self.grid, &self.s.pressure, x)
    }

    /// Steps 8–11 (6 and the fluid reactants' 4 inside) from the nodes'
    /// v*_I after the internal and body forces: the solids' cell
    /// velocities (eq 18 again), the Lagrangian values with the momentum
    /// and heat exchange, and each solid's cell changes, with the momentum
    /// its trace took returned to the fluids.
    pub(super) fn lagrangian_values(
        &mut self,
        nodes: &GridNodes,
        dt: f64,
    ) -> Result<(), SolverError> {
        let g = self.grid;
        {
            let s = &mut *self.s;
            steps::nodes_to_cells(
                &g,
                self.rz,
                &nodes.lattice,
                &nodes.mass,
                &nodes.velocity_new,
                &mut s.cell_mass,
                &mut s.cell_velocity,
            );
            for c in s.solids.iter_mut() {
                c.velocity
                    .par_iter_mut()
                    .zip(c.trace.par_iter())
                    .zip(s.cell_velocity.par_iter().zip(s.fluid_velocity.par_iter()))
                    .with_min_len(1024)
                    .for_each(|((u, trace), (uc, uf))| {
                        *u = if *trace { *uf } else { *uc };
                    });
            }
            if s.solids.len() > 1 {
                s.mix_trace_velocities(self.volumes);
            }
            for (solid, c) in self.solids.iter().zip(&s.solids) {
                self.ice.set_lagrangian_velocity(solid.ice, &c.velocity);
            }
        }
        self.ice.compute_lagrangian_values(dt)?;
        for (solid, c) in self.solids.iter().zip(self.s.solids.iter_mut()) {
            self.ice
                .lagrangian_velocity_change(solid.ice, &mut c.change);
            if solid.carries_heat {
                // Its particles take the heat through their own H(T).
                self.ice
                    .lagrangian_heat(solid.ice, &mut c.temperature_change);
            } else {
                self.ice
                    .lagrangian_temperature_change(solid.ice, &mut c.temperature_change);
            }
        }
        self.combine_solid_changes();
        self.bound_trace_momentum();
        if self.s.solids.len() > 1 {
            self.share_trace_momentum();
        }
        self.ice.add_eulerian_momentum(&self.s.trace_momentum);
        Ok(())
    }

    /// Step 13: the cells' velocity change to the nodes (the adjoint of eq
    /// 18), written into `dv` (node storage order).
    pub(super) fn changes_to_nodes(&self, nodes: &GridNodes, dv: &mut [[f64; 3]]) {
        let change = match self.s.solids.as_slice() {
            [one] => &one.change,
            _ => &self.s.cell_change,
        };
        steps::cells_to_nodes(&self.grid, self.rz, &nodes.lattice, change, dv);
    }

    /// Step 14's temperature change (or heat, [`Solid::carries_heat`]) on
    /// the nodes ([`ParticleHeat::Nodes`]):
    /// each solid's cell change (zero where it is a trace) by the adjoint of
    /// eq 18 into its block of `node_temperature` (material-major, one
    /// value per node of `nodes`). Empty where no cell changed (no heat
    /// exchange, the total energy conserved): the particles then skip the
    /// gather and keep their bits.
    pub(super) fn temperature_change_to_nodes(&mut self, nodes: &GridNodes) -> &[f64] {
        let count = nodes.mass.len();
        let s = &mut *self.s;
        s.node_temperature.clear();
        let changed = s.solids.iter().any(|c| {
            c.temperature_change
                .par_iter()
                .zip(c.trace.par_iter())
                .any(|(dt, trace)| !*trace && *dt != 0.0)
        });
        if !changed {
            return &s.node_temperature;
        }
        s.node_temperature.resize(count * s.solids.len(), 0.0);
        for (c, block) in s
            .solids
            .iter_mut()
            .zip(s.node_temperature.chunks_mut(count))
        {
            for (dt, trace) in c.temperature_change.iter_mut().zip(&c.trace) {
                if *trace {
                    *dt = 0.0;
                }
            }
            steps::cell_values_to_nodes(
                &self.grid,
                self.rz,
                &nodes.lattice,
                &c.temperature_change,
                block,
            );
        }
        &s.node_temperature
    }

    /// The temperature change of the heat exchange at point `x` over the
    /// step for a particle of `material`, K — the heat, J/kg, for a solid
    /// whose particles carry a specific heat ([`Solid::carries_heat`]).
    pub(super) fn temperature_change(&self, x: [f64; 3], material: MaterialId) -> f64 {
        steps::cell_value_at(
            &self.grid,
            &self.s.solids[material.0 as usize].temperature_change,
            x,
        )
    }

    /// Step 4 on the particles. Cell c burns the fraction φ_c of the
    /// reactant's mass the particles give it through linear shape functions
    /// and the corner weights of eq 18, Σ_p W_pc m_p
    /// ([`steps::particle_cell_weights`], at the positions after the
    /// update; step 1's own M_c for one solid of linear shape functions
    /// whose particles did not move), so particle p gives
    /// cell c the mass W_pc φ_c m_p and loses Σ_c W_pc φ_c m_p, with its
    /// velocity, specific internal energy and specific volume unchanged —
    /// its momentum, energy and volume fall in proportion — and the
    /// product of each cell gains exactly what the particles gave it plus
    /// the heat of reaction ([`IceSolver::add_burnt_particles`]). A
    /// particle left with less than [`BURNT_OUT_FRACTION`] of its
    /// material's mean initial particle mass burns whole (its cells' shares
    /// scaled up) and is removed. Positions are those after the update;
    /// particles in order, so the sums do not depend on the thread count.
    pub(super) fn consume_particles(
        &mut self,
        particles: &mut Particles,
        consumed: &mut Vec<usize>,
    ) -> Result<(), SolverError> {
        if self.burns.is_empty() {
            return Ok(());
        }
        let (g, rz) = (self.grid, self.rz);
        let mut shares = [(0usize, 0.0f64); 27];
        for b in self.burns.iter_mut() {
            b.burnt.fill(BurntMass::default());
            let floor = BURNT_OUT_FRACTION * self.solids[b.material.0 as usize].particle_mass;
            let mut total = 0.0;
            for p in 0..particles.len() {
                if particles.material[p] != b.material {
                    continue;
                }
                let m = particles.mass[p];
                let mut count = 0;
                let mut loss = 0.0;
                steps::particle_cell_weights(&g, rz, particles.position[p], |k, w| {
                    let dm = w * b.fraction[k] * m;
                    if dm > 0.0 {
                        shares[count] = (k, dm);
                        count += 1;
                        loss += dm;
                    }
                });
                let shares = &mut shares[..count];
                if !(loss > 0.0) {
                    continue;
                }
                let whole = m - loss < floor;
                if whole {
                    let scale = m / loss;
                    for x in shares.iter_mut() {
                        x.1 *= scale;
                    }
                    loss = m;
                }
                let v = particles.velocity[p];
                let ke = 0.5 * (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
                let energy = particles.specific_internal_energy[p] + ke + b.heat;
                for &(k, dm) in shares.iter() {
                    let src = &mut b.burnt[k];
                    src.mass += dm;
                    for (q, vd) in src.momentum.iter_mut().zip(v) {
                        *q += dm * vd;
                    }
                    src.energy += dm * energy;
                    src.volume += dm * b.specific_volume[k];
                }
                total += loss;
                if whole {
                    consumed.push(p);
                } else {
                    let keep = (m - loss) / m;
                    particles.mass[p] = m - loss;
                    particles.volume[p] *= keep;
                    particles.initial_volume[p] *= keep;
                }
            }
            b.unburnt -= total;
            self.ice.add_burnt_particles(b.product, &b.burnt);
        }
        consumed.sort_unstable();
        consumed.dedup();
        Ok(())
    }
}
