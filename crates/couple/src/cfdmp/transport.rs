//! Step 14 of seed 001 §3.5: the transport of mass, momentum and energy
//! across the interface faces (eqs 40–51), and the particles it creates
//! and absorbs.

use super::*;

impl<E: GasLaw> Cfdmp<E> {
    /// Step 14: at every interface face, the interface state and fluxes
    /// (eqs 40–44); the inflow deposited into the fluid particles of the
    /// face's first bridge cell (`CfdmpOptions::deposit`) or made into new
    /// particles (eqs 45–48); and the particles that crossed to the FDM
    /// side absorbed by the cell they entered (eqs 49–51). The particles
    /// that took a deposit are replaced by their new state, and the donor
    /// particles of the MPM step removed, in the same pass.
    pub fn transport(&mut self, dt: f64) -> Result<(), SolverError> {
        let a = self.regions.axis;
        let side = self.regions.mpm_side;
        let donor = self.fdm_index(self.regions.donor_cell());
        let bridge = self.fdm_index(self.regions.first_bridge_cell());
        let fg = self.fdm.level().geometry;
        let x_face = self.regions.interface();
        let active: [bool; 3] = std::array::from_fn(|d| fg.cells[d] > 1);
        self.created.clear();
        self.inits.clear();
        // Storage indices of the particles to take out (deposits, absorbed
        // particles, donors), gathered before any particle moves.
        self.leaving.clear();
        self.scan_particles(x_face);
        for f in 0..self.faces.len() {
            // A row that has not joined (`start_in_bridge`) takes no
            // inflow: the FDM keeps it until the row joins.
            if !self.joined[f] {
                continue;
            }
            let c = self.faces[f];
            let (mut cd, mut cb) = (c, c);
            cd[a] = donor;
            cb[a] = bridge;
            let (sd, yd) = self.primitive(cd);
            let (sb, _) = self.primitive(cb);
            let face = interface_state(&sd, &sb);
            let (fm, fp) = interface_fluxes(&face, a, side, self.area_at(c), dt);
            if fm > 0.0 {
                let products = self.options.products.is_some() && yd >= 0.5;
                if !products {
                    self.totals.products_as_air += yd * fm;
                }
                let e = self.particle_energy(cd, &sd, products);
                let v2: f64 = face.velocity.iter().map(|v| v * v).sum();
                let q = &mut self.pending[f];
                q.mass += fm;
                for (m, p) in q.momentum.iter_mut().zip(fp) {
                    *m += p;
                }
                q.energy += fm * (e + 0.5 * v2);
                if products {
                    q.products += fm;
                }
                q.length += (side.sign() * face.velocity[a] * dt).min(fg.spacing[a]);
            }
            let q = self.pending[f];
            if q.mass <= 0.0 {
                continue;
            }
            let material = match self.options.products {
                Some(m) if 2.0 * q.products >= q.mass => m,
                _ => self.options.air,
            };
            let y = if material == self.options.air {
                0.0
            } else {
                1.0
            };
            let scale = self.ring_scale(c);
            let existing_mass = (self.options.existing_mass * scale)
                .max(sd.density * self.options.existing_volume * scale);
            if self.options.deposit {
                // Into the particles of the same material in the face's
                // first bridge cell, by shares of their mass.
                let gimp = self.mpm.options().shape.is_gimp();
                let ps = self.mpm.particles();
                let list = &self.members[self.start[f]..self.start[f + 1]];
                let reach = 0.5 * fg.spacing[a];
                let takes = |p: usize| {
                    ps.material[p] == material && (ps.position[p][a] - x_face).abs() <= reach
                };
                let total: f64 = list
                    .iter()
                    .filter(|&&p| takes(p))
                    .map(|&p| ps.mass[p])
                    .sum();
                if total > 0.0 {
                    for &p in list.iter().filter(|&&p| takes(p)) {
                        let w = ps.mass[p] / total;
                        let (dm, dp, de) = (q.mass * w, q.momentum.map(|x| x * w), q.energy * w);
                        let d = deposit_into_particle(
                            Deposit {
                                mass: ps.mass[p],
                                velocity: ps.velocity[p],
                                specific_internal_energy: ps.specific_internal_energy[p],
                                volume: ps.volume[p],
                            },
                            dm,
                            dp,
                            de,
                            sd.density,
                        );
                        let pressure = self.fdm.gas().gas_pressure(
                            d.mass / d.volume,
                            d.specific_internal_energy,
                            y,
                        );
                        // A GIMP particle stands for a domain around
                        // it, which the deposit, entering at the face,
                        // extends towards the face: the particle moves to
                        // the centre of mass of itself and the deposit
                        // along the axis, so that the domains keep tiling
                        // (docs/physics/couple/bridge.md, "cpGIMP in the
                        // MPM region"). A linear particle is a point and
                        // stays.
                        let mut position = ps.position[p];
                        if gimp {
                            position[a] = (ps.mass[p] * position[a] + dm * x_face) / d.mass;
                        }
                        self.inits.push(ParticleInit {
                            position,
                            velocity: d.velocity,
                            mass: d.mass,
                            volume: d.volume,
                            stress: [-pressure, -pressure, -pressure, 0.0, 0.0, 0.0],
                            temperature: ps.temperature[p],
                            specific_internal_energy: d.specific_internal_energy,
                            material,
                            ..Default::default()
                        });
                        self.leaving.push(p);
                        book_parts(&mut self.totals.into_mpm, dm, dp, de);
                        self.totals.deposited += 1;
                    }
                    self.pending[f] = Pending::default();
                    continue;
                }
            } else if q.mass < 4.0 * self.options.min_particle_mass * existing_mass {
                continue;
            }
            // The face's inflow so far as one batch: its mean velocity and
            // the specific internal energy that keeps its total energy
            // (eq 48's, plus the kinetic energy the mean velocity drops).
            let v = q.momentum.map(|p| p / q.mass);
            let vn = side.sign() * v[a];
            if !(vn > 0.0) {
                continue;
            }
            let e = q.energy / q.mass - 0.5 * v.iter().map(|x| x * x).sum::<f64>();
            let mut centre = fg.cell_centre(c);
            centre[a] = x_face;
            let inflow = FaceInflow {
                face_centre: centre,
                spacing: fg.spacing,
                active,
                axis: a,
                side,
                face: Primitive {
                    velocity: v,
                    ..face
                },
                donor: sd,
                axisymmetric: self.geometry.is_axisymmetric(),
                gamma: self.options.gamma,
                existing_mass,
                // Eq 47 over the length the batch filled, the tangential
                // drift kept within a quarter cell (inside the face's
                // cell).
                dt: (0..3)
                    .filter(|&d| d != a && active[d] && v[d] != 0.0)
                    .fold(q.length.min(fg.spacing[a]) / vn, |t, d| {
                        t.min(0.25 * fg.spacing[d] / v[d].abs())
                    }),
            };
            let start = self.created.len();
            create_particles(&inflow, q.mass, &mut self.created);
            let p = self.fdm.gas().gas_pressure(sd.density, e, y);
            for n in &mut self.created[start..] {
                n.specific_internal_energy = e;
                self.inits.push(ParticleInit {
                    position: n.position,
                    velocity: n.velocity,
                    mass: n.mass,
                    volume: n.volume,
                    stress: [-p, -p, -p, 0.0, 0.0, 0.0],
                    specific_internal_energy: e,
                    material,
                    ..Default::default()
                });
                book(&mut self.totals.into_mpm, n.mass, n.velocity, e);
            }
            self.pending[f] = Pending::default();
        }
        self.totals.created += self.created.len() as u64;
        // Absorption: particles on the FDM side of the interface (the
        // donor particles excepted), found by `scan_particles`, into the
        // donor cell of their line (eqs 49–51 with that cell's volume, its
        // ring on an (r, z) grid).
        let ps = self.mpm.particles();
        for &p in &self.outside {
            let (m, v, e) = (ps.mass[p], ps.velocity[p], ps.specific_internal_energy[p]);
            let is_products = Some(ps.material[p]) == self.options.products;
            let Some(mut g) = fg.cell_containing(ps.position[p]) else {
                return Err(SolverError::Other(format!(
                    "bridge: particle at {:?} m left the MPM region outside the FDM grid",
                    ps.position[p]
                )));
            };
            g[a] = donor;
            let volume = self.volume_at(g);
            let mut u = self.fdm.cell_conservative(g).unwrap_or([0.0; 6]);
            absorb_particle(&mut u, volume, m, v, e);
            if is_products {
                u[5] += m / volume;
            }
            self.fdm
                .set_cell_conservative(g, u)
                .map_err(|e| SolverError::Other(e.to_string()))?;
            book(&mut self.totals.into_fdm, m, v, e);
        }
        self.totals.absorbed += self.outside.len() as u64;
        // One removal: the deposits' old states, the absorbed particles and
        // this step's donors; then one insertion of the new states and the
        // created particles.
        self.leaving.extend_from_slice(&self.outside);
        self.leaving.extend_from_slice(&self.donor_slots);
        self.leaving.sort_unstable();
        self.mpm.remove_particles(&self.leaving);
        self.donors = (0, 0);
        self.mpm
            .insert_particles(&self.inits)
            .map_err(|e| SolverError::Other(format!("bridge inflow particles: {e}")))?;
        Ok(())
    }

    /// One pass over the particles before the transport changes any:
    /// the donor particles (`donor_slots`), the particles on the FDM side
    /// of the interface `x_face` (`outside`, to be absorbed) and, with
    /// `deposit`, per face the fluid particles of its first bridge cell
    /// (`members[start[f]..start[f + 1]]`), all as ascending storage
    /// indices.
    pub(super) fn scan_particles(&mut self, x_face: f64) {
        let a = self.regions.axis;
        let side = self.regions.mpm_side;
        let mg = self.mpm.level().geometry;
        let fg = self.fdm.level().geometry;
        let bridge = self.fdm_index(self.regions.first_bridge_cell()) as isize + self.mpm_shift;
        let deposit = self.options.deposit;
        let ps = self.mpm.particles();
        let ids = self.mpm.particle_ids();
        self.outside.clear();
        self.donor_slots.clear();
        self.pairs.clear();
        let window = mg.axis_window(a, bridge, bridge);
        for (p, &id) in ids.iter().enumerate() {
            if self.is_donor(id) {
                self.donor_slots.push(p);
                continue;
            }
            let x = ps.position[p];
            let out = match side {
                Side::High => x[a] < x_face,
                Side::Low => x[a] > x_face,
            };
            if out {
                self.outside.push(p);
                continue;
            }
            if !deposit
                || !(ps.material[p] == self.options.air
                    || Some(ps.material[p]) == self.options.products)
                || !window.admits(x[a])
            {
                continue;
            }
            let Some(c) = mg.cell_containing(x) else {
                continue;
            };
            if c[a] as isize != bridge {
                continue;
            }
            // The face's index in `faces` (x fastest, the axis index 0).
            let mut t = c;
            t[a] = 0;
            let mut n = fg.cells;
            n[a] = 1;
            self.pairs.push((t[0] + n[0] * (t[1] + n[1] * t[2]), p));
        }
        // Group by face, storage order kept within a face.
        self.pairs.sort_by_key(|&(f, _)| f);
        let faces = self.faces.len();
        self.start.clear();
        self.start.resize(faces + 1, 0);
        self.members.clear();
        for &(f, p) in &self.pairs {
            self.start[f + 1] += 1;
            self.members.push(p);
        }
        for f in 0..faces {
            self.start[f + 1] += self.start[f];
        }
    }
}
