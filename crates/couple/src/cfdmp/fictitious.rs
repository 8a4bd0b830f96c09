//! Step 7 of seed 001 §3.5: the fictitious cells of the FDM region beyond
//! the interface, filled from the MPM nodes and particles (eqs 31–36).

use super::*;

impl<E: GasLaw> Cfdmp<E> {
    /// The fictitious cells, layer by layer (FDM-grid indices).
    pub(super) fn fictitious_cells(&self) -> Vec<[usize; 3]> {
        let a = self.regions.axis;
        let n = self.regions.fdm.cells[a];
        let mut out = Vec::new();
        for l in 0..self.layers {
            let i = match self.regions.mpm_side {
                Side::High => n + l,
                Side::Low => self.layers - 1 - l,
            };
            for mut c in self.face_cells() {
                c[a] = i;
                out.push(c);
            }
        }
        out
    }

    /// Step 7: the fictitious cells from the MPM nodes (eqs 31–32, with
    /// the momentum of the update, eq 22) and the internal energy of the
    /// particles in them (eq 33), eqs 34–36, where their MPM cell holds
    /// fluid particles away from a structure; from the fluid particles'
    /// own sums next to a structure; zero gradient where the MPM cell holds
    /// no material, a reflecting wall where it holds only structure
    /// ([`fictitious_source`], [`resolve_fictitious_line`]). Every
    /// fictitious cell gets a state, kept in `values` for the FDM step.
    pub fn update_fictitious_cells(&mut self) -> Result<(), SolverError> {
        let a = self.regions.axis;
        let mg = self.mpm.level().geometry;
        let nodes = self.mpm.grid_nodes();
        let active: Vec<usize> = (0..3).filter(|&d| mg.cells[d] > 1).collect();
        let weight = centre_weight(active.len());
        // The particle sums of the MPM cells of the fictitious layers and
        // of one layer either side (for `structure_near`), one slab of
        // `faces` cells per layer.
        let lines = self.faces.len();
        let first = self.fictitious_mpm_index(0);
        let last = self.fictitious_mpm_index(self.layers.max(1) - 1);
        let lo = first.min(last) - 1;
        let slabs = self.layers + 2;
        self.cells.clear();
        self.cells.resize(slabs * lines, CellParticles::default());
        let fluid = |m: MaterialId| m == self.options.air || Some(m) == self.options.products;
        let ps = self.mpm.particles();
        let window = mg.axis_window(a, lo, lo + slabs as isize - 1);
        for p in 0..ps.len() {
            if !window.admits(ps.position[p][a]) {
                continue;
            }
            let Some(c) = mg.cell_containing(ps.position[p]) else {
                continue;
            };
            let s = c[a] as isize - lo;
            if s < 0 || s >= slabs as isize {
                continue;
            }
            let k = s as usize * lines + self.line_of(c);
            let q = &mut self.cells[k];
            let m = ps.mass[p];
            if fluid(ps.material[p]) {
                // Eq 33, summed particle by particle.
                q.fluid_energy += m * ps.specific_internal_energy[p];
                q.fluid_mass += m;
                for d in 0..3 {
                    q.fluid_momentum[d] += m * ps.velocity[p][d];
                }
                if Some(ps.material[p]) == self.options.products {
                    q.products_mass += m;
                }
            } else {
                q.structure_mass += m;
                q.structure_momentum += m * ps.velocity[p][a];
            }
        }
        let axisymmetric = self.geometry.is_axisymmetric();
        let corners = 1usize << active.len();
        let mut mass = [0.0; 8];
        let mut mom = [[0.0; 3]; 8];
        let fg = self.fdm.level().geometry;
        self.sources.clear();
        for &g in &self.fictitious {
            let mut c = g;
            c[a] = (g[a] as isize + self.mpm_shift) as usize;
            let mut used = 0;
            for corner in 0..corners {
                let mut node = [c[0] as isize, c[1] as isize, c[2] as isize];
                for (bit, &d) in active.iter().enumerate() {
                    node[d] += ((corner >> bit) & 1) as isize;
                }
                if let Some(n) = nodes.lattice.index(node) {
                    let m = nodes.mass[n];
                    mass[used] = m;
                    mom[used] = nodes.velocity_new[n].map(|v| v * m);
                    used += 1;
                }
            }
            let nodal = fictitious_mass_momentum(&mass[..used], &mom[..used], weight);
            let s = (c[a] as isize - lo) as usize;
            let here = self.cells[s * lines + self.line_of(c)];
            // A structure particle in the cell or a neighbour: some corner
            // node carries structure mass.
            let mut near = false;
            for dk in -1isize..=1 {
                for dj in -1isize..=1 {
                    for di in -1isize..=1 {
                        let n = [c[0] as isize + di, c[1] as isize + dj, c[2] as isize + dk];
                        let ok = (0..3).all(|d| {
                            if d == a {
                                true
                            } else {
                                n[d] >= 0 && (n[d] as usize) < fg.cells[d]
                            }
                        });
                        if !ok {
                            continue;
                        }
                        let sn = (n[a] - lo) as usize;
                        let t = [n[0] as usize, n[1] as usize, n[2] as usize];
                        near |= self.cells[sn * lines + self.line_of(t)].structure_mass > 0.0;
                    }
                }
            }
            // On an (r, z) grid a node on the axis stands for a ring of
            // radius 0: eqs 31–32's interpolation of nodal masses, exact
            // for the linear hat at r_I > 0 (Σ_p N_I m_p = ρ 2π r_I Δr Δz),
            // over-weighs the cells of the first column (by 7/6 for a
            // uniform gas); their mass and momentum are the particles' own
            // sums (eq 33's), as next to a structure.
            let particle_sums = near || (axisymmetric && c[0] == 0);
            self.sources.push(fictitious_source(
                &here,
                particle_sums,
                nodal,
                self.volume_at(g),
            ));
        }
        // Per line normal to the interface: the layers from their sources
        // (`resolve_fictitious_line`), unless the FDM region's outflow
        // there is supersonic against them (`fdm_outflow_is_supersonic`):
        // then every fictitious layer takes the last FDM-region cell's
        // state (zero gradient, the FDM's own outflow face).
        let n = self.regions.fdm.cells[a];
        let sign = self.regions.mpm_side.sign();
        let layers = self.layers;
        self.values.clear();
        self.values.resize(self.fictitious.len(), [0.0; 6]);
        let mut inner = std::mem::take(&mut self.line_inner);
        let mut sources = std::mem::take(&mut self.line_sources);
        let mut out = std::mem::take(&mut self.line_out);
        inner.clear();
        inner.resize(layers.min(n), [0.0; 6]);
        sources.clear();
        sources.resize(layers, FictitiousSource::ZeroGradient);
        out.clear();
        out.resize(layers, [0.0; 6]);
        for line in 0..lines {
            for (j, u) in inner.iter_mut().enumerate() {
                let mut g = self.fictitious[line];
                g[a] = match self.regions.mpm_side {
                    Side::High => self.fdm_index(n - 1 - j),
                    Side::Low => self.fdm_index(j),
                };
                *u = self.fdm.cell_conservative(g).unwrap_or([0.0; 6]);
            }
            for (l, q) in sources.iter_mut().enumerate() {
                *q = self.sources[l * lines + line];
            }
            resolve_fictitious_line(&inner, &sources, a, &mut out);
            let normal = |u: &[f64; 6]| {
                let rho = u[0];
                let e = specific_internal_energy(rho, u[1], u[2], u[3], u[4]);
                let y = if E::SPECIES { u[5] / rho } else { 0.0 };
                let gas = self.fdm.gas();
                NormalState {
                    density: rho,
                    velocity: sign * u[1 + a] / rho,
                    pressure: gas.gas_pressure(rho, e, y),
                    sound_speed: gas.gas_sound_speed(rho, e, y),
                }
            };
            let supersonic = fdm_outflow_is_supersonic(&normal(&inner[0]), &normal(&out[0]));
            if supersonic {
                self.totals.supersonic_outflow += 1;
            }
            for (l, &state) in out.iter().enumerate() {
                let k = l * lines + line;
                self.values[k] = if supersonic { inner[0] } else { state };
                match self.sources[k] {
                    FictitiousSource::Mpm(_) => {}
                    FictitiousSource::ZeroGradient => self.totals.zero_gradient += 1,
                    FictitiousSource::Wall(_) => self.totals.wall += 1,
                }
            }
        }
        (self.line_inner, self.line_sources, self.line_out) = (inner, sources, out);
        self.set_fictitious_values()
    }

    /// Writes the fictitious cells' states of step 7 (`values`) into the
    /// FDM grid: before the FDM step, and again after it, so that the
    /// sweeps' own values there (which the bridge does not use) are never
    /// what the FDM's next start-of-step check and CFL limit see.
    pub(super) fn set_fictitious_values(&mut self) -> Result<(), SolverError> {
        for (&g, &u) in self.fictitious.iter().zip(&self.values) {
            self.fdm
                .set_cell_conservative(g, u)
                .map_err(|e| SolverError::Other(e.to_string()))?;
        }
        Ok(())
    }

    /// MPM-grid index along the split axis of fictitious layer `l`.
    pub(super) fn fictitious_mpm_index(&self, l: usize) -> isize {
        let lines = self.faces.len();
        let g = self.fictitious[l * lines];
        g[self.regions.axis] as isize + self.mpm_shift
    }

    /// Index in `faces` of the line through cell `c` (x fastest, the axis
    /// index ignored).
    pub(super) fn line_of(&self, c: [usize; 3]) -> usize {
        let a = self.regions.axis;
        let g = self.fdm.level().geometry;
        let mut t = c;
        t[a] = 0;
        let mut n = g.cells;
        n[a] = 1;
        t[0] + n[0] * (t[1] + n[1] * t[2])
    }

    /// Resets the fictitious cells to their initial state (before
    /// activation).
    pub(super) fn hold_fictitious_cells(&mut self) -> Result<(), SolverError> {
        for (&g, &u) in self.fictitious.iter().zip(&self.fictitious_initial) {
            self.fdm
                .set_cell_conservative(g, u)
                .map_err(|e| SolverError::Other(e.to_string()))?;
        }
        Ok(())
    }
}
