//! What the ICE–MPM coupling (seed 000 §3.3, eqs 18 and step 13) reads
//! from and writes into the ICE: the Lagrangian materials' cell values
//! from the particles, their increments back, the burning of particle
//! reactant, and the fluids' fields the particles see.

use super::*;

impl<E: Eos> IceSolver<E> {
    /// Whether particles carry material `r`.
    pub fn is_lagrangian(&self, r: usize) -> bool {
        self.lagrangian.get(r).copied().unwrap_or(false)
    }

    /// Step 1 of seed 000 §3.3 for a Lagrangian material `r`: its cell
    /// state from the particles (in global cell order, x fastest), with
    /// the internal energy its equation of state gives at that specific
    /// volume and temperature. Run
    /// [`IceSolver::compute_equilibration_pressure`] after it: it sets
    /// every material's sound speed in every cell from the equilibrated
    /// state (the sound speed at the imported state, which nothing reads
    /// before that, is not computed here; until then the material keeps
    /// its previous one).
    pub fn import_lagrangian(
        &mut self,
        r: usize,
        cells: &LagrangianCells<'_>,
    ) -> Result<(), SolverError> {
        let count = self.level.geometry.cell_count();
        if !self.is_lagrangian(r) {
            return Err(SolverError::Other(format!(
                "ice: material {} is not Lagrangian",
                r + 1
            )));
        }
        if [
            cells.mass_density.len(),
            cells.velocity.len(),
            cells.specific_volume.map_or(count, |v| v.len()),
            cells.temperature.len(),
        ]
        .iter()
        .any(|&l| l != count)
        {
            return Err(SolverError::Other(format!(
                "ice: Lagrangian cell arrays must hold {count} cells"
            )));
        }
        let time = self.time;
        let geometry = self.level.geometry;
        let bad = (0..count).find(|&g| {
            let (rho, v, t) = (
                cells.mass_density[g],
                cells.specific_volume.map_or(1.0, |v| v[g]),
                cells.temperature[g],
            );
            !(rho > 0.0 && rho.is_finite() && v > 0.0 && v.is_finite() && t > 0.0 && t.is_finite())
                || cells.velocity[g].iter().any(|u| !u.is_finite())
        });
        if let Some(g) = bad {
            let nc = geometry.cells;
            let cell = [g % nc[0], (g / nc[0]) % nc[1], g / (nc[0] * nc[1])];
            return Err(SolverError::NonPhysicalState {
                time,
                cell,
                centre: geometry.cell_centre(cell),
                detail: format!(
                    "material {} from the particles: density {:e} kg/m³, specific volume {:?} m³/kg, \
                     temperature {:e} K, velocity {:?} m/s",
                    r + 1,
                    cells.mass_density[g],
                    cells.specific_volume.map(|v| v[g]),
                    cells.temperature[g],
                    cells.velocity[g]
                ),
            });
        }
        let eos = &self.eos[r];
        let b = r * NS;
        let pidx = self.eos.len() * NS;
        for_each_cell_global(&self.level, &mut self.state, |g, d, c| {
            let t = cells.temperature[g];
            let v = match cells.specific_volume {
                Some(v) => v[g],
                None => match eos.density(d[pidx][c], t) {
                    Ok(rho) if rho > 0.0 && rho.is_finite() => 1.0 / rho,
                    _ => d[b + VSP][c],
                },
            };
            let e = eos.specific_internal_energy_from_temperature(1.0 / v, t);
            d[b + RHO][c] = cells.mass_density[g];
            for a in 0..3 {
                d[b + VEL + a][c] = cells.velocity[g][a];
            }
            d[b + ENERGY][c] = e;
            d[b + VSP][c] = v;
            d[b + THETA][c] = cells.mass_density[g] * v;
            d[b + TEMP][c] = t;
        });
        Ok(())
    }

    /// Fits the Eulerian materials around the Lagrangian ones at the start
    /// of a coupled run: in each cell the Eulerian materials' volume
    /// fractions are scaled (their own densities kept) to fill 1 − θ_L,
    /// θ_L the Lagrangian materials' volume fraction from the particles
    /// (global cell order), and never below `trace` each; then re-
    /// equilibrates. Without it a cell whose centre lies inside the solid
    /// but which the particles fill only in part would hold a trace of
    /// fluid where the fluid must fill the rest.
    pub fn fit_eulerian_volume(
        &mut self,
        lagrangian_fraction: &[f64],
        trace: f64,
    ) -> Result<(), SolverError> {
        assert_eq!(lagrangian_fraction.len(), self.level.geometry.cell_count());
        let n = self.eos.len();
        let lag = self.lagrangian.clone();
        for_each_cell_global(&self.level, &mut self.state, |g, d, c| {
            let room = (1.0 - lagrangian_fraction[g]).max(0.0);
            let fluid: f64 = (0..n)
                .filter(|&r| !lag[r])
                .map(|r| d[r * NS + THETA][c])
                .sum();
            if !(fluid > 0.0) {
                return;
            }
            for r in (0..n).filter(|&r| !lag[r]) {
                let b = r * NS;
                let theta = (d[b + THETA][c] * room / fluid).max(trace);
                d[b + RHO][c] = theta / d[b + VSP][c];
                d[b + THETA][c] = theta;
            }
        });
        self.compute_equilibration_pressure()
    }

    /// Sets the velocity of Lagrangian material `r` (global cell order) to
    /// the grid's after the particles' internal and body forces, the
    /// velocity the Lagrangian step (eqs 24, 27) starts from.
    pub fn set_lagrangian_velocity(&mut self, r: usize, velocity: &[[f64; 3]]) {
        assert!(self.is_lagrangian(r), "material {r} is not Lagrangian");
        assert_eq!(velocity.len(), self.level.geometry.cell_count());
        let b = r * NS;
        for_each_cell_global(&self.level, &mut self.state, |g, d, c| {
            for a in 0..3 {
                d[b + VEL + a][c] = velocity[g][a];
            }
        });
    }

    /// After [`IceSolver::compute_lagrangian_values`]: the cell-centred
    /// changes of Lagrangian material `r` over steps 8–10 (global cell
    /// order) — the velocity change of the pressure gradient and the
    /// momentum exchange, and the temperature change of the heat exchange
    /// and of the kinetic energy the exchange dissipated, through its EOS's
    /// T(e) — for step 13. For a material given its particles' specific
    /// heat ([`IceSolver::set_lagrangian_specific_heat`]) the heat is the
    /// change to use ([`IceSolver::lagrangian_heat`]); its temperature
    /// change here is the EOS's T(e) of the changed energy, that heat over
    /// the EOS's c_v for an EOS of constant c_v.
    pub fn lagrangian_increments(&self, r: usize, dv: &mut [[f64; 3]], dtemp: &mut [f64]) {
        self.lagrangian_velocity_change(r, dv);
        self.lagrangian_temperature_change(r, dtemp);
    }

    /// The velocity half of [`IceSolver::lagrangian_increments`]: the
    /// change of Lagrangian material `r`'s cell velocity over steps 8–10
    /// (global cell order).
    pub fn lagrangian_velocity_change(&self, r: usize, dv: &mut [[f64; 3]]) {
        assert!(self.is_lagrangian(r), "material {r} is not Lagrangian");
        assert_eq!(dv.len(), self.level.geometry.cell_count());
        par_gather(&self.level, dv, |pid, c| {
            let (d, l) = (&self.state[pid].data, &self.lag[pid].data);
            let (b, bl) = (r * NS, r * NL);
            std::array::from_fn(|a| l[bl + L_VEL + a][c] - d[b + VEL + a][c])
        });
    }

    /// The temperature half of [`IceSolver::lagrangian_increments`]: the
    /// change of Lagrangian material `r`'s temperature over steps 8–10
    /// through its EOS's T(e) (global cell order). A material whose
    /// particles carry their own specific heat takes
    /// [`IceSolver::lagrangian_heat`] instead.
    pub fn lagrangian_temperature_change(&self, r: usize, dtemp: &mut [f64]) {
        assert!(self.is_lagrangian(r), "material {r} is not Lagrangian");
        assert_eq!(dtemp.len(), self.level.geometry.cell_count());
        let eos = &self.eos[r];
        par_gather(&self.level, dtemp, |pid, c| {
            let (d, l) = (&self.state[pid].data, &self.lag[pid].data);
            let (b, bl) = (r * NS, r * NL);
            let rho_micro = 1.0 / d[b + VSP][c];
            eos.temperature(rho_micro, l[bl + L_ENERGY][c]) - d[b + TEMP][c]
        });
    }

    /// After [`IceSolver::compute_lagrangian_values`]: the heat (J/kg) that
    /// Lagrangian material `r` took in each cell over steps 8–10 (global
    /// cell order), the change of its Lagrangian specific energy — the
    /// heat exchange's c ΔT with the specific heat its particles carry
    /// ([`IceSolver::set_lagrangian_specific_heat`]) and the kinetic
    /// energy the exchange dissipated into it — for step 14's particles to
    /// take through their own H(T). Exactly 0 in a cell where neither
    /// changed it.
    pub fn lagrangian_heat(&self, r: usize, heat: &mut [f64]) {
        assert!(self.is_lagrangian(r), "material {r} is not Lagrangian");
        assert_eq!(heat.len(), self.level.geometry.cell_count());
        par_gather(&self.level, heat, |pid, c| {
            let (d, l) = (&self.state[pid].data, &self.lag[pid].data);
            l[r * NL + L_ENERGY][c] - d[r * NS + ENERGY][c]
        });
    }

    /// Adds momentum `dp` (kg·m/s per cell, global order) to the Eulerian
    /// materials' Lagrangian values of each cell — after
    /// [`IceSolver::compute_lagrangian_values`], before
    /// [`IceSolver::advect_fluids`] — shared in proportion to their
    /// Lagrangian mass, so that each takes the same velocity change
    /// dp / Σ_r m_r and the cell's fluids gain exactly dp. The coupled
    /// pipeline returns there what a Lagrangian material's trace took from
    /// them in steps 8–10 (the trace is not a body: no particle receives
    /// it). A cell whose Eulerian materials hold no mass is left as it is.
    pub fn add_eulerian_momentum(&mut self, dp: &[[f64; 3]]) {
        let geometry = self.level.geometry;
        assert_eq!(dp.len(), geometry.cell_count());
        let vols = self.volumes();
        let n = self.eos.len();
        let lag = &self.lagrangian;
        for_each_cell_global(&self.level, &mut self.lag, |g, l, c| {
            if dp[g] == [0.0; 3] {
                return;
            }
            let volume = vols.cell(g);
            let mass: f64 = (0..n)
                .filter(|&r| !lag[r])
                .map(|r| l[r * NL + L_RHO][c])
                .sum::<f64>()
                * volume;
            if !(mass > 0.0) {
                return;
            }
            let du = dp[g].map(|x| x / mass);
            for r in (0..n).filter(|&r| !lag[r]) {
                for a in 0..3 {
                    l[r * NL + L_VEL + a][c] += du[a];
                }
            }
        });
    }

    /// Step 4 for reaction `k` (of [`IceSolver::reactions`]) whose reactant
    /// particles carry: the fraction of the reactant's mass in each cell
    /// (global order) that burns over Δt = `dt`, Γ Δt / ρ_r with the
    /// reaction's rate at the cell's equilibration pressure (a surface burn
    /// on the surface step 2 found in the particles' volume fraction) and
    /// the reactant's and product's densities of step 2 — the burnt mass an
    /// Eulerian reactant of the same state would lose in
    /// [`IceSolver::compute_lagrangian_values`] (at most the rate's
    /// `max_burn_fraction`, and never more than 1 − `REACTANT_LEFT`). Run after
    /// [`IceSolver::compute_equilibration_pressure`]; a surface burn first
    /// carries what a surface cell cannot supply into the cells behind it
    /// ([`IceSolver::carry_surface_burns`]). The coupled pipeline
    /// takes that fraction of each particle's mass, volume, momentum and
    /// energy (seed 000 step 4: "decrementing particle mass carries its
    /// momentum and energy") and hands the product what the particles lost
    /// through [`IceSolver::add_burnt_particles`].
    ///
    /// `volume` receives the reactant's specific volume of step 2 (m³/kg,
    /// its EOS at the equilibration pressure): the volume the burnt mass
    /// held in this frame, which the product is born with.
    pub fn lagrangian_burn_fraction(
        &mut self,
        k: usize,
        dt: f64,
        out: &mut [f64],
        volume: &mut [f64],
    ) {
        // A surface burn goes on behind a surface cell its reactant cannot
        // feed, as for a fluid reactant in step 4 (the carry is the same
        // when step 8 runs it again).
        self.carry_surface_burns(dt);
        let rx = &self.reactions[k];
        assert!(
            self.is_lagrangian(rx.reactant),
            "reaction {k}'s reactant is not Lagrangian"
        );
        let count = self.level.geometry.cell_count();
        assert!(out.len() == count && volume.len() == count);
        let params = solver_params!(self);
        let (a, b) = (rx.reactant * NS + RHO, rx.product * NS + RHO);
        par_gather(&self.level, out, |pid, c| {
            let d = &self.state[pid].data;
            let rho_r = d[a][c];
            if !(rho_r > 0.0) {
                return 0.0;
            }
            let at = surface::surface_at(&self.scratch[pid].surface, k, c);
            let state = reaction_state(&params, rx, |i| d[i][c], at, dt);
            let burnt = rx.rate.burnt_density(&state, rho_r, d[b][c], dt) / rho_r;
            burnt.min(1.0 - REACTANT_LEFT)
        });
        let v = rx.reactant * NS + VSP;
        par_gather(&self.level, volume, |pid, c| self.state[pid].data[v][c]);
    }

    /// Adds to Eulerian material `product`'s Lagrangian values — after
    /// [`IceSolver::compute_lagrangian_values`], before
    /// [`IceSolver::advect_fluids`] — what burning particles gave each cell
    /// (global order): mass (kg), momentum (kg·m/s), total energy (J: the
    /// particles' internal and kinetic energy plus the heat of reaction,
    /// in the product's reference) and volume (m³, the burnt solid's, at
    /// which the product is born: Σ v Γ = 0 in eq 20, as for a fluid
    /// reactant). The product's density, velocity, specific energy and
    /// specific volume become the mass-weighted mixture of the two, so the
    /// cell gains exactly what the particles lost. A cell with nothing
    /// burnt is left as it is.
    pub fn add_burnt_particles(&mut self, product: usize, burnt: &[BurntMass]) {
        assert!(!self.is_lagrangian(product), "the product must be Eulerian");
        let geometry = self.level.geometry;
        assert_eq!(burnt.len(), geometry.cell_count());
        let vols = self.volumes();
        let bl = product * NL;
        for_each_cell_global(&self.level, &mut self.lag, |g, l, c| {
            let src = &burnt[g];
            if !(src.mass > 0.0) {
                return;
            }
            let volume = vols.cell(g);
            let rho = l[bl + L_RHO][c];
            let u = [l[bl + L_VEL][c], l[bl + L_VEL + 1][c], l[bl + L_VEL + 2][c]];
            let drho = src.mass / volume;
            let rho_new = rho + drho;
            let mom: [f64; 3] = std::array::from_fn(|a| rho * u[a] + src.momentum[a] / volume);
            let u_new = mom.map(|m| m / rho_new);
            let total = rho * (l[bl + L_ENERGY][c] + 0.5 * dot(u, u)) + src.energy / volume;
            l[bl + L_RHO][c] = rho_new;
            for a in 0..3 {
                l[bl + L_VEL + a][c] = u_new[a];
            }
            l[bl + L_ENERGY][c] = total / rho_new - 0.5 * dot(u_new, u_new);
            l[bl + L_VSP][c] = (rho * l[bl + L_VSP][c] + src.volume / volume) / rho_new;
        });
    }

    /// The mass-weighted velocity of the Eulerian materials of every cell,
    /// in global order: the velocity a Lagrangian material takes as a trace
    /// where no particle is, so that the exchange moves nothing there.
    pub fn eulerian_velocity(&self, velocity: &mut [[f64; 3]]) {
        assert_eq!(velocity.len(), self.level.geometry.cell_count());
        let n = self.eos.len();
        par_gather(&self.level, velocity, |pid, c| {
            let d = &self.state[pid].data;
            let (mut m, mut mu) = (0.0, [0.0; 3]);
            for r in (0..n).filter(|&r| !self.lagrangian[r]) {
                let rho = d[r * NS + RHO][c];
                m += rho;
                for a in 0..3 {
                    mu[a] += rho * d[r * NS + VEL + a][c];
                }
            }
            mu.map(|x| x / m)
        });
    }

    /// The Eulerian materials' mass density Σ_r ρ_r of every cell (kg/m³,
    /// global order).
    pub fn eulerian_density(&self, density: &mut [f64]) {
        assert_eq!(density.len(), self.level.geometry.cell_count());
        let n = self.eos.len();
        par_gather(&self.level, density, |pid, c| {
            let d = &self.state[pid].data;
            (0..n)
                .filter(|&r| !self.lagrangian[r])
                .map(|r| d[r * NS + RHO][c])
                .sum()
        });
    }

    /// The Eulerian materials' Lagrangian mass density Σ_r (ρ_r)^L of every
    /// cell (kg/m³, global order): what they hold after
    /// [`IceSolver::compute_lagrangian_values`], the mass
    /// [`IceSolver::add_eulerian_momentum`] shares momentum over.
    pub fn eulerian_lagrangian_density(&self, density: &mut [f64]) {
        assert_eq!(density.len(), self.level.geometry.cell_count());
        let n = self.eos.len();
        par_gather(&self.level, density, |pid, c| {
            let l = &self.lag[pid].data;
            (0..n)
                .filter(|&r| !self.lagrangian[r])
                .map(|r| l[r * NL + L_RHO][c])
                .sum()
        });
    }

    /// The time-advanced pressure p = p_eq + Δp of step 5 (eq 21), per
    /// cell in global order, into `out`.
    pub fn advanced_pressure(&self, out: &mut [f64]) {
        let geometry = self.level.geometry;
        assert_eq!(out.len(), geometry.cell_count());
        par_gather(&self.level, out, |pid, c| self.press[pid].data[0][c]);
    }

    /// The equilibration pressure of step 2 per cell in global order.
    pub fn equilibration_pressure_field(&self, out: &mut [f64]) {
        let geometry = self.level.geometry;
        assert_eq!(out.len(), geometry.cell_count());
        let n = self.eos.len();
        par_gather(&self.level, out, |pid, c| self.state[pid].data[n * NS][c]);
    }

    /// Ends a step the coupled pipeline drove through the step functions:
    /// time and step count advance by one step of Δt = `dt`.
    pub fn finish_coupled_step(&mut self, dt: f64) {
        self.time += dt;
        self.steps += 1;
    }
}
