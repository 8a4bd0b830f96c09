//! Particles that join and leave an [`MpmSolver`] run: insertion and
//! removal, the reservoirs' inflow, the particles that leave through
//! outflow faces and those mirrored back at walls.

use super::{particle_energy, MpmSetupError, MpmSolver};
use crate::boundary::{GridBoundary, FACE_NAMES, MIRROR_DEPTH};
use crate::viscosity::BulkViscosityState;
use crate::ParticleInit;
use brisance_core::{Material, SolverError};
use rayon::prelude::*;

impl MpmSolver {
    /// Reorders the per-particle arrays the solver keeps beside
    /// [`Particles`] as [`Particles::permute`] did: new i is old `perm[i]`,
    /// through reused buffers (no allocation once they have grown).
    ///
    /// [`Particles`]: crate::Particles
    /// [`Particles::permute`]: crate::Particles::permute
    pub(super) fn permute_own(&mut self, perm: &[usize]) {
        crate::particles::permute_into(&mut self.bulk, perm, &mut self.work.bulk_scratch);
        crate::particles::permute_into(&mut self.ids, perm, &mut self.work.id_scratch);
    }

    /// Removes the particles `leaving` (increasing indices) from
    /// [`Particles`] and the arrays kept beside it, in place: the others
    /// keep their relative order and the arrays their capacity.
    ///
    /// [`Particles`]: crate::Particles
    pub(super) fn remove_sorted(&mut self, leaving: &[usize]) {
        self.particles.remove_sorted(leaving);
        crate::particles::remove_blocks(&mut self.bulk, leaving, 1);
        crate::particles::remove_blocks(&mut self.ids, leaving, 1);
    }

    /// Adds particles during a run (matter a coupling brings into the MPM
    /// region), with their models' initial history and identities after
    /// every identity given so far; returns the first new identity. Fails,
    /// adding nothing, for a particle outside the grid or of an unknown
    /// material.
    pub fn insert_particles(&mut self, new: &[ParticleInit]) -> Result<u32, MpmSetupError> {
        let grid = self.level.geometry;
        self.particles.reserve(new.len());
        self.bulk.reserve(new.len());
        self.ids.reserve(new.len());
        for (i, p) in new.iter().enumerate() {
            let particle = self.particles.len() + i;
            if p.material.0 as usize >= self.materials.len() {
                return Err(MpmSetupError::UnknownMaterial {
                    particle,
                    material: p.material.0,
                    count: self.materials.len(),
                });
            }
            if grid.cell_containing(p.position).is_none() {
                return Err(MpmSetupError::OutsideGrid {
                    particle,
                    position: p.position,
                });
            }
            let finite = p.velocity.iter().all(|v| v.is_finite());
            if !(finite
                && p.mass > 0.0
                && p.volume > 0.0
                && p.mass.is_finite()
                && p.volume.is_finite())
            {
                return Err(MpmSetupError::Shape {
                    particle,
                    detail: format!(
                        "mass {} kg and volume {} m³ must be positive and velocity {:?} m/s finite",
                        p.mass, p.volume, p.velocity
                    ),
                });
            }
        }
        let count = self.particles.len() + new.len();
        let last = u32::try_from(self.next_id as usize + new.len())
            .map_err(|_| MpmSetupError::TooManyParticles { count })?;
        let first = self.next_id;
        for p in new {
            let index = self
                .particles
                .push_zero_history(p)
                .map_err(|e| MpmSetupError::Shape {
                    particle: self.particles.len(),
                    detail: e.to_string(),
                })?;
            let id = p.material.0;
            let m = &self.materials[id as usize];
            let seed = brisance_constitutive::random::point_seed(p.position, id);
            m.init_history_at(
                &mut self.particles.history_of_mut(index)[..m.history_len()],
                seed,
            );
            self.bulk.push(BulkViscosityState::default());
            self.ids.push(self.next_id);
            self.next_id += 1;
        }
        debug_assert_eq!(self.next_id, last);
        Ok(first)
    }

    /// Marks the particles of identities [`first`, `first + count`) as
    /// load-only until changed (`count` 0 clears it): they enter the first
    /// transfer (mass, momentum and internal force at the nodes, seed 001
    /// eqs 18–21) and the momentum update (eq 22), but not MUSL's
    /// re-mapping (eq 26), whose node velocities are then the mean of the
    /// other particles' updated velocities, v_I^{n+1} =
    /// Σ m_p N_Ip v_p^{n+1} / Σ m_p N_Ip over those alone. The FDM–MPM
    /// bridge's donor cells (eqs 37–39) are such particles: the FDM cells
    /// beside the interface, which give the interface nodes the FDM side's
    /// mass, momentum and pressure force, but whose own velocity is the
    /// FDM's, not the MPM's to update and remap. Other schemes than MUSL
    /// ignore the mark (they have no re-mapping). With inflow faces the
    /// mark is ignored too (the reservoirs add momentum to the re-mapping
    /// but no mass to its weights). With GIMP or cpGIMP the marked
    /// particles are points (zero half-width, the linear hat of eq 16:
    /// [`crate::transfer::ParticleBins::point_particles`]), so that a donor at a
    /// cell's centre reaches that cell's nodes alone, as with linear
    /// shape functions, whatever its volume.
    pub fn set_load_only(&mut self, first: u32, count: u32) {
        self.work.load_only = (first, count);
    }

    /// Removes the particles at storage indices `leaving` (ascending,
    /// distinct) without booking them as outflow: a coupling that takes
    /// their mass, momentum and energy over reads them first. The others
    /// keep their relative order; in place, without allocating (see
    /// [`Particles::remove_sorted`]).
    ///
    /// # Panics
    /// If `leaving` is not increasing or names a particle past the end.
    ///
    /// [`Particles::remove_sorted`]: crate::Particles::remove_sorted
    pub fn remove_particles(&mut self, leaving: &[usize]) {
        self.remove_sorted(leaving);
    }

    /// Step 1 of [`crate::inflow`]: the reservoirs' layers that enter join
    /// the particles, booked as negative outflow.
    pub(super) fn inject(&mut self) -> Result<(), SolverError> {
        let grid = self.level.geometry;
        let new = self.inflow.inject(
            &grid,
            &self.particles,
            &self.bulk,
            &self.materials,
            &mut self.outflow,
        );
        let first = self.particles.len();
        let added = if new.is_empty() {
            Ok(0)
        } else {
            self.insert_particles(&new)
        };
        self.inflow.return_injected(new);
        // A particle continuing a stretched boundary cell carries that
        // stretch in F; its initial volume is V / det F (inflow.rs).
        let ps = &mut self.particles;
        for p in first..ps.len() {
            let f = &ps.deformation_gradient[p];
            let det = f[0] * (f[4] * f[8] - f[5] * f[7]) - f[1] * (f[3] * f[8] - f[5] * f[6])
                + f[2] * (f[3] * f[7] - f[4] * f[6]);
            ps.initial_volume[p] = ps.volume[p] / det;
        }
        added.map(|_| ()).map_err(|e| {
            SolverError::Other(format!(
                "MPM at t = {:e} s: particles entering through a reservoir: {e}",
                self.time
            ))
        })
    }

    /// Marks the plain outflow faces (no reservoir) with a particle in a
    /// boundary cell moving inwards faster than
    /// [`crate::inflow::BLOCKED_SPEED_FRACTION`] of its sound speed:
    /// nothing enters behind it ([`Solver::blocked_inflow`]). Faces already
    /// marked are not looked at again.
    ///
    /// [`Solver::blocked_inflow`]: brisance_core::Solver::blocked_inflow
    pub(super) fn note_inflow_at_plain_outflow_faces(&mut self) {
        let grid = self.level.geometry;
        for face in 0..6 {
            let axis = face / 2;
            if self.held_back[face]
                || grid.cells[axis] <= 1
                || self.options.boundaries[face] != GridBoundary::Outflow
                || self.options.reservoirs[face].is_some()
            {
                continue;
            }
            let inward = if face % 2 == 0 { 1.0 } else { -1.0 };
            let boundary_cell = if face % 2 == 0 {
                0
            } else {
                grid.cells[axis] - 1
            };
            let ps = &self.particles;
            let mats = &self.materials;
            self.held_back[face] = (0..ps.len()).into_par_iter().with_min_len(4096).any(|p| {
                let v_in = inward * ps.velocity[p][axis];
                if !(v_in > 0.0) {
                    return false;
                }
                let s = (ps.position[p][axis] - grid.origin[axis]) / grid.spacing[axis];
                let cell =
                    (crate::shape::floor(s) as isize).clamp(0, grid.cells[axis] as isize - 1);
                if cell as usize != boundary_cell {
                    return false;
                }
                let rho = ps.mass[p] / ps.volume[p];
                let c =
                    mats[ps.material[p].0 as usize].wave_speed(rho, ps.specific_internal_energy[p]);
                v_in > crate::inflow::BLOCKED_SPEED_FRACTION * c
            });
        }
    }

    /// Mirrors back the particles that crossed a wall face (`Symmetry` or
    /// `Fixed`) by at most [`MIRROR_DEPTH`] cells, removes those that left
    /// through outflow faces, and errors for any other crossing.
    ///
    /// A particle within a whisker of a wall crosses it without any fault
    /// of the step: the wall holds the normal velocity of the nodes on the
    /// face, but a light node one layer in, which the particle barely
    /// reaches (weight N ≪ 1), takes an acceleration f_I/m_I ∝ 1/N from
    /// the particle's own stress, and the position update
    /// Δx = Δt Σ_I N_Ip v_I^{n+1} carries N times that: a displacement
    /// Δt² σ/(ρ h) towards the wall for a particle in tension, whatever
    /// its distance to the wall. In the mirrored domain of a symmetry
    /// plane the particle's image does the same from the other side: the
    /// two pass each other, so the particle that left is the image that
    /// came in. It is put at its mirror position, its normal velocity
    /// reversed; its other state is kept (the stress and deformation
    /// components that change sign under the mirror vanish on the plane
    /// by symmetry, and the particle is within half a cell of it). Mass,
    /// kinetic and internal energy are unchanged; the normal momentum
    /// changes as at the wall's nodes, which hold it.
    pub(super) fn handle_leaving_particles(&mut self) -> Result<(), SolverError> {
        let grid = self.level.geometry;
        // Nearly always every particle is still inside: check that first,
        // in parallel, and look for the leavers one by one only if not. The
        // test is that of `cell_containing`, without forming the cell.
        let inside = |x: &[f64; 3]| {
            (0..3).all(|d| {
                let s = (x[d] - grid.origin[d]) / grid.spacing[d];
                s >= 0.0 && s <= grid.cells[d] as f64
            })
        };
        if self
            .particles
            .position
            .par_iter()
            .with_min_len(4096)
            .all(inside)
        {
            return Ok(());
        }
        let upper = grid.upper();
        let mut leaving = Vec::new();
        for p in 0..self.particles.len() {
            let x = self.particles.position[p];
            if grid.cell_containing(x).is_some() {
                continue;
            }
            if x.iter().any(|c| !c.is_finite()) {
                return Err(self.particle_error(p, "position is not finite".into()));
            }
            if self.mirror_at_walls(p) {
                continue;
            }
            let x = self.particles.position[p];
            let mut face = None;
            for d in 0..3 {
                if x[d] < grid.origin[d] {
                    face = Some(2 * d);
                    break;
                }
                if x[d] > upper[d] {
                    face = Some(2 * d + 1);
                    break;
                }
            }
            let face = face.unwrap_or(0);
            let bc = self.options.boundaries[face];
            if bc != GridBoundary::Outflow {
                return Err(SolverError::Other(format!(
                    "MPM at t = {:e} s: particle {p} at {x:?} m (velocity {:?} m/s) left the \
                     domain through face {} (boundary {bc:?}); only Outflow faces let particles \
                     leave, and Symmetry and Fixed faces mirror back those within {MIRROR_DEPTH} \
                     of a cell",
                    self.time, self.particles.velocity[p], FACE_NAMES[face]
                )));
            }
            leaving.push(p);
        }
        if leaving.is_empty() {
            return Ok(());
        }
        let ps = &self.particles;
        for &p in &leaving {
            let (m, v) = (ps.mass[p], ps.velocity[p]);
            self.outflow.mass += m;
            for (q, vc) in self.outflow.momentum.iter_mut().zip(v) {
                *q += m * vc;
            }
            self.outflow.energy += particle_energy(m, v, ps.specific_internal_energy[p]);
        }
        self.remove_sorted(&leaving);
        Ok(())
    }

    /// Puts particle `p`, outside the domain, at its mirror image across
    /// every `Symmetry` or `Fixed` face it crossed by at most
    /// [`MIRROR_DEPTH`] cells, reversing its velocity normal to that face
    /// (see [`Self::handle_leaving_particles`]); true if it is then inside
    /// (if not, it is outside only across the faces it did not cross
    /// mirrored).
    fn mirror_at_walls(&mut self, p: usize) -> bool {
        let grid = self.level.geometry;
        let upper = grid.upper();
        let mut x = self.particles.position[p];
        let mut v = self.particles.velocity[p];
        for d in 0..3 {
            let depth = MIRROR_DEPTH * grid.spacing[d];
            let wall = |face: usize| {
                matches!(
                    self.options.boundaries[face],
                    GridBoundary::Symmetry | GridBoundary::Fixed
                )
            };
            if x[d] < grid.origin[d] && wall(2 * d) && grid.origin[d] - x[d] <= depth {
                x[d] = 2.0 * grid.origin[d] - x[d];
                v[d] = -v[d];
            } else if x[d] > upper[d] && wall(2 * d + 1) && x[d] - upper[d] <= depth {
                x[d] = 2.0 * upper[d] - x[d];
                v[d] = -v[d];
            }
        }
        self.particles.position[p] = x;
        self.particles.velocity[p] = v;
        grid.cell_containing(x).is_some()
    }
}
