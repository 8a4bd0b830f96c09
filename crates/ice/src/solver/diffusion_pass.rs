//! The viscous and heat-conduction pass of the ICE solver (seed 000
//! eqs 2–3, step 8 of §3.3), with the kernels of [`crate::diffusion`]:
//! per material r and axis a, each face's traction θμτ_a· and energy flux
//! τ_a·u_f + θk ∂T/∂x_a once (stored at the face's high-side cell), then
//! each cell differences its two faces into its Lagrangian momentum and
//! total energy. Explicit, from the state at the start of the step (the
//! velocities and temperatures that Uintah's `viscousShearStress` and
//! `accumulateEnergySourceSinks` read from the old data warehouse).
//! See docs/physics/ice/diffusion.md.

use brisance_core::{Eos, SolverError};
use rayon::prelude::*;

use super::{
    book_faces, domain_face_cells, global_of, par_cells, par_faces, par_interior, Disjoint,
    FaceBooking, IceSolver, ENERGY, L_ENERGY, L_RHO, L_VEL, NL, NS, TEMP, THETA, VEL, VSP,
};
use crate::diffusion::{
    apply_increment, conduction_time_step, face_coefficient, inverse_spacing_squared, stress_row,
    viscous_time_step, MaterialTransport, TimeStepLimits,
};
use crate::{IceBoundary, IceError, MAX_MATERIALS};

/// Transport coefficients and the work arrays of the diffusion pass.
#[derive(Debug, Default)]
pub(super) struct Transport {
    /// Per material (empty until [`IceSolver::set_transport`]).
    coefficients: Vec<MaterialTransport>,
    /// Whether any material has a coefficient > 0.
    active: bool,
    /// Per patch: the face traction (3 components) and energy flux of one
    /// material along one axis, at the face's high-side cell (allocated
    /// only when `active`).
    faces: Vec<[Vec<f64>; 4]>,
}

impl Transport {
    /// Frees patch `id`'s face arrays (a patch another rank owns).
    pub(super) fn release(&mut self, id: usize) {
        if let Some(faces) = self.faces.get_mut(id) {
            *faces = Default::default();
        }
    }

    /// Per patch, whether its face arrays are stored (empty while no
    /// material has a coefficient).
    #[cfg(test)]
    pub(super) fn stored(&self) -> Vec<bool> {
        self.faces.iter().map(|f| !f[0].is_empty()).collect()
    }
}

/// What a domain face is for the viscous stress.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Wall {
    /// Symmetry plane: no normal velocity, no shear stress.
    Symmetry,
    /// A wall moving rigidly (no slip): tangential derivatives of the
    /// velocity vanish on it.
    NoSlip,
}

fn wall_of(b: &IceBoundary) -> Option<Wall> {
    match b {
        IceBoundary::Symmetry => Some(Wall::Symmetry),
        IceBoundary::FixedVelocity(_) => Some(Wall::NoSlip),
        _ => None,
    }
}

impl<E: Eos> IceSolver<E> {
    /// Sets each material's viscosity and thermal conductivity (seed 000
    /// eqs 2–3; one entry per material, in the solver's order). A material
    /// with both 0 (the default) is skipped, and with every material at 0
    /// the pass costs nothing. Materials carried by particles are skipped
    /// (their stress and heat are the particles'). Errors name the field.
    pub fn set_transport(&mut self, transport: Vec<MaterialTransport>) -> Result<(), IceError> {
        let n = self.eos.len();
        if transport.len() != n {
            return Err(IceError::Invalid(format!(
                "ice: {} transport entries given for {n} materials",
                transport.len()
            )));
        }
        for (r, t) in transport.iter().enumerate() {
            t.validate(&format!("transport of material {}", r + 1))?;
        }
        let active = transport.iter().any(|t| t.is_active());
        // A patch another rank owns gets no arrays.
        self.transport.faces = if active {
            self.level
                .patches
                .iter()
                .zip(&self.ranks.owned)
                .map(|(p, &own)| {
                    let len = if own { p.allocated_cells() } else { 0 };
                    std::array::from_fn(|_| vec![0.0; len])
                })
                .collect()
        } else {
            Vec::new()
        };
        self.transport.coefficients = transport;
        self.transport.active = active;
        self.still_distributable()
    }

    /// The materials' transport coefficients (empty when never set: all 0).
    pub fn transport(&self) -> &[MaterialTransport] {
        &self.transport.coefficients
    }

    /// The viscous and heat-conduction sources of step 8 (seed 000 eqs 2–3)
    /// added to the Lagrangian momentum and energy of every Eulerian
    /// material with a coefficient > 0: Δ(ρu)_r = Δt ∇·(θ_r τ_r) and
    /// Δ(ρE)_r = Δt ∇·(θ_r τ_r·u_r + θ_r k_r ∇T_r) in flux form, the
    /// internal energy taking what the kinetic energy does not (the viscous
    /// dissipation θτ:∇u of eq 3). Run after
    /// [`IceSolver::compute_lagrangian_values`] (which calls it) with the
    /// state's ghost cells filled by
    /// [`IceSolver::compute_face_centred_velocities`] of the same step.
    /// On several ranks each rank updates its own patches (their ghost
    /// layers hold the neighbours' state, corners included) and the faces'
    /// bookings are gathered as the other passes' are, so every rank books
    /// every face.
    // Kept out of line so that profiles attribute each step's cost.
    #[inline(never)]
    pub fn compute_diffusion_sources(&mut self, dt: f64) {
        if !self.transport.active {
            return;
        }
        let n = self.eos.len();
        let spacing = self.level.geometry.spacing;
        let cells = self.level.geometry.cells;
        let active: [bool; 3] = std::array::from_fn(|d| self.level.is_active(d));
        let boundaries = &self.boundaries;
        let coefficients = &self.transport.coefficients;
        let lagrangian = &self.lagrangian;
        let axisymmetric = self.options.geometry.is_axisymmetric();
        let booked = self.booked_faces();
        let geometry = self.level.geometry;
        let (r0, dr) = (self.level.geometry.origin[0], spacing[0]);
        let booking: FaceBooking = self
            .lag
            .par_iter_mut()
            .zip(self.transport.faces.par_iter_mut())
            .zip(self.state.par_iter())
            .zip(self.scratch.par_iter())
            .zip(self.level.patches.par_iter())
            .zip(self.ranks.owned.par_iter())
            .map(|(((((lg, faces), pf), sc), patch), &own)| {
                let mut booking: FaceBooking = Vec::new();
                if !own {
                    return booking;
                }
                let st = patch.strides();
                let dims = patch.dims();
                // Axisymmetric: the centre radius of local column la, and
                // the face weights r±/r_c.
                let r_centre =
                    |la: usize| r0 + ((patch.lo[0] + la) as f64 - patch.ghost[0] as f64 + 0.5) * dr;
                let (ring_lo, ring_hi) = (&sc.ring_lo, &sc.ring_hi);
                let d = &pf.data;
                let mut out = [Disjoint::empty(); MAX_MATERIALS * NL];
                for (w, f) in out.iter_mut().zip(lg.data.iter_mut()) {
                    *w = Disjoint::new(f);
                }
                let fx: [Disjoint; 4] = {
                    let mut it = faces.iter_mut();
                    std::array::from_fn(|_| Disjoint::new(it.next().expect("four face arrays")))
                };
                for r in 0..n {
                    let tr = coefficients[r];
                    if lagrangian[r] || !tr.is_active() {
                        continue;
                    }
                    let (mu, k) = (tr.viscosity, tr.thermal_conductivity);
                    let b = r * NS;
                    let u: [&[f64]; 3] = std::array::from_fn(|j| &d[b + VEL + j][..]);
                    let theta = &d[b + THETA][..];
                    let temp = &d[b + TEMP][..];
                    let bl = r * NL;
                    for a in 0..3 {
                        if !active[a] {
                            continue;
                        }
                        let dx = spacing[a];
                        let lo_wall = if patch.lo[a] == 0 {
                            wall_of(&boundaries[2 * a])
                        } else {
                            None
                        };
                        let hi_wall = if patch.lo[a] + patch.size[a] == cells[a] {
                            wall_of(&boundaries[2 * a + 1])
                        } else {
                            None
                        };
                        par_faces(patch, a, |m| {
                            let l = m - st[a];
                            let la = (m / st[a]) % dims[a];
                            // The wall this face lies on, and its interior cell.
                            let (wall, inner) = if la == patch.ghost[a] {
                                (lo_wall, m)
                            } else if la == patch.ghost[a] + patch.size[a] {
                                (hi_wall, l)
                            } else {
                                (None, m)
                            };
                            let mut traction = [0.0; 3];
                            let mut flux = 0.0;
                            if mu > 0.0 {
                                let mu_f = face_coefficient(theta[l] * mu, theta[m] * mu);
                                // grad[i][j] = ∂u_j/∂x_i on the face: compact
                                // along a; along t ≠ a the mean of the two
                                // cells' centred differences (rows t only
                                // as far as row a of τ needs them).
                                let mut grad = [[0.0; 3]; 3];
                                for j in 0..3 {
                                    grad[a][j] = (u[j][m] - u[j][l]) / dx;
                                }
                                for t in (0..3).filter(|&t| t != a && active[t]) {
                                    let s = st[t];
                                    let centred = |f: &[f64], c: usize| f[c + s] - f[c - s];
                                    let dxt = spacing[t];
                                    match wall {
                                        None => {
                                            grad[t][a] =
                                                (centred(u[a], l) + centred(u[a], m)) / (4.0 * dxt);
                                            grad[t][t] =
                                                (centred(u[t], l) + centred(u[t], m)) / (4.0 * dxt);
                                        }
                                        // The normal velocity is 0 all over
                                        // the plane; the tangential one is
                                        // the mirror's.
                                        Some(Wall::Symmetry) => {
                                            grad[t][t] = centred(u[t], inner) / (2.0 * dxt);
                                        }
                                        // The wall moves rigidly.
                                        Some(Wall::NoSlip) => {}
                                    }
                                }
                                if axisymmetric {
                                    // The hoop strain rate u_r/r in the
                                    // trace (the third diagonal entry; the
                                    // axis face takes its limit ∂u_r/∂r).
                                    grad[2][2] = if a == 0 {
                                        let r_f = r_centre(la) - 0.5 * dr;
                                        if r_f > 0.0 {
                                            0.5 * (u[0][l] + u[0][m]) / r_f
                                        } else {
                                            grad[0][0]
                                        }
                                    } else {
                                        0.5 * (u[0][l] + u[0][m]) / r_centre(m % dims[0])
                                    };
                                }
                                traction = stress_row(mu_f, a, &grad);
                                for j in 0..3 {
                                    flux += traction[j] * 0.5 * (u[j][l] + u[j][m]);
                                }
                            }
                            if k > 0.0 {
                                let k_f = face_coefficient(theta[l] * k, theta[m] * k);
                                flux += k_f * (temp[m] - temp[l]) / dx;
                            }
                            for j in 0..3 {
                                fx[j].write(m, traction[j]);
                            }
                            fx[3].write(m, flux);
                        });
                        let lam = dt / dx;
                        let radial = a == 0 && axisymmetric;
                        // What the domain faces along a take: the traction's
                        // impulse and the energy flux through them (per unit
                        // volume of the cell at the face), so the totals
                        // close with the walls' share booked.
                        for face in [2 * a, 2 * a + 1] {
                            if !booked[face] {
                                continue;
                            }
                            let high = face % 2 == 1;
                            for c in domain_face_cells(patch, cells, face) {
                                let la = c % dims[0];
                                let (m, w) = match (high, radial) {
                                    (true, true) => (c + st[a], -ring_hi[la]),
                                    (true, false) => (c + st[a], -1.0),
                                    (false, true) => (c, ring_lo[la]),
                                    (false, false) => (c, 1.0),
                                };
                                let mut q = [0.0; 5];
                                for j in 0..3 {
                                    q[1 + j] = w * lam * fx[j].read(m);
                                }
                                q[4] = w * lam * fx[3].read(m);
                                booking.push((
                                    geometry.linear_index(global_of(patch, c)),
                                    face,
                                    r,
                                    q,
                                ));
                            }
                        }
                        par_cells(patch, |c| {
                            let h = c + st[a];
                            // Radial faces weighted r±/r_c.
                            let (wl, wh) = if radial {
                                let la = c % dims[0];
                                (ring_lo[la], ring_hi[la])
                            } else {
                                (1.0, 1.0)
                            };
                            let dmom: [f64; 3] = std::array::from_fn(|j| {
                                lam * (wh * fx[j].read(h) - wl * fx[j].read(c))
                            });
                            let denergy = lam * (wh * fx[3].read(h) - wl * fx[3].read(c));
                            let rho = out[bl + L_RHO].read(c);
                            let mut vel: [f64; 3] =
                                std::array::from_fn(|j| out[bl + L_VEL + j].read(c));
                            let mut e = out[bl + L_ENERGY].read(c);
                            apply_increment(rho, &mut vel, &mut e, dmom, denergy);
                            for j in 0..3 {
                                out[bl + L_VEL + j].write(c, vel[j]);
                            }
                            out[bl + L_ENERGY].write(c, e);
                        });
                    }
                    if axisymmetric && mu > 0.0 {
                        // The hoop stress's radial force −θτ_θθ/r per unit
                        // volume, τ_θθ = 2μ u_r/r − (2/3)μ∇·u at the cell
                        // centre. It moves no energy across a face; the
                        // kinetic energy it changes comes from the
                        // internal energy (apply_increment).
                        let (s0, s1) = (st[0], st[1]);
                        par_cells(patch, |c| {
                            let r_c = r_centre(c % dims[0]);
                            let hoop = u[0][c] / r_c;
                            let mut div = (u[0][c + s0] - u[0][c - s0]) / (2.0 * dr) + hoop;
                            if active[1] {
                                div += (u[1][c + s1] - u[1][c - s1]) / (2.0 * spacing[1]);
                            }
                            let tau = theta[c] * mu * (2.0 * hoop - 2.0 / 3.0 * div);
                            let dmom = [-dt * tau / r_c, 0.0, 0.0];
                            let rho = out[bl + L_RHO].read(c);
                            let mut vel: [f64; 3] =
                                std::array::from_fn(|j| out[bl + L_VEL + j].read(c));
                            let mut e = out[bl + L_ENERGY].read(c);
                            apply_increment(rho, &mut vel, &mut e, dmom, 0.0);
                            out[bl + L_VEL].write(c, vel[0]);
                            out[bl + L_ENERGY].write(c, e);
                        });
                    }
                }
                booking
            })
            .reduce(Vec::new, |mut a, b| {
                a.extend(b);
                a
            });
        let booking = self
            .gather_pass(super::ranks::Found {
                booking,
                ..Default::default()
            })
            .booking;
        book_faces(booking, self.volumes(), &mut self.outflow);
    }

    /// The viscous and conduction limits of the time step (each times the
    /// Courant number; infinite without such a coefficient): per cell and
    /// Eulerian material, [`viscous_time_step`] with the material's own
    /// specific volume and [`conduction_time_step`] with its c_v at the
    /// cell's temperature. Cell-local, so the same for any patch split;
    /// on several ranks each rank takes its own patches and the minimum
    /// over the ranks (exact, so the same bits).
    pub(super) fn diffusive_time_steps(&self) -> (f64, f64) {
        if !self.transport.active {
            return (f64::INFINITY, f64::INFINITY);
        }
        let n = self.eos.len();
        let active: [bool; 3] = std::array::from_fn(|d| self.level.is_active(d));
        let s = inverse_spacing_squared(self.level.geometry.spacing, active);
        let coefficients = &self.transport.coefficients;
        let lagrangian = &self.lagrangian;
        let eos = &self.eos;
        let min2 = |x: (f64, f64), y: (f64, f64)| (x.0.min(y.0), x.1.min(y.1));
        let (v, k) = self
            .state
            .par_iter()
            .zip(self.level.patches.par_iter())
            .zip(self.ranks.owned.par_iter())
            .map(|((pf, patch), &own)| {
                if !own {
                    return (f64::INFINITY, f64::INFINITY);
                }
                let d = &pf.data;
                par_interior(
                    patch,
                    || (f64::INFINITY, f64::INFINITY),
                    |acc, c| {
                        for r in 0..n {
                            let tr = coefficients[r];
                            if lagrangian[r] || !tr.is_active() {
                                continue;
                            }
                            let vsp = d[r * NS + VSP][c];
                            if tr.viscosity > 0.0 {
                                acc.0 = acc.0.min(viscous_time_step(tr.viscosity, vsp, s));
                            }
                            if tr.thermal_conductivity > 0.0 {
                                let cv = eos[r].cv(1.0 / vsp, d[r * NS + TEMP][c]);
                                acc.1 = acc.1.min(conduction_time_step(
                                    tr.thermal_conductivity,
                                    vsp,
                                    cv,
                                    s,
                                ));
                            }
                        }
                    },
                    min2,
                )
            })
            .reduce(|| (f64::INFINITY, f64::INFINITY), min2);
        let (v, k) = if self.ranks.several() {
            (self.ranks.comm.min(v), self.ranks.comm.min(k))
        } else {
            (v, k)
        };
        (self.options.cfl * v, self.options.cfl * k)
    }

    /// Sets material `r`'s temperature to `temperature(cell centre)` at its
    /// present specific volume (the energy from its EOS), then
    /// re-equilibrates (step 2): an initial temperature field that a
    /// [`crate::CellState`] (a pressure and densities) cannot give, as for a
    /// material whose pressure does not depend on its temperature.
    pub fn set_temperature(
        &mut self,
        r: usize,
        temperature: impl Fn([f64; 3]) -> f64 + Sync,
    ) -> Result<(), SolverError> {
        assert!(r < self.eos.len(), "material {r} out of range");
        let eos = &self.eos[r];
        let geometry = self.level.geometry;
        let nc = geometry.cells;
        let b = r * NS;
        super::for_each_cell_global(&self.level, &mut self.state, |g, d, c| {
            let cell = [g % nc[0], (g / nc[0]) % nc[1], g / (nc[0] * nc[1])];
            let t = temperature(geometry.cell_centre(cell));
            d[b + ENERGY][c] =
                eos.specific_internal_energy_from_temperature(1.0 / d[b + VSP][c], t);
        });
        self.compute_equilibration_pressure()
    }

    /// The stable time step and the viscous and conduction limits, so that
    /// a run can report which one set Δt ([`TimeStepLimits::binding`]).
    pub fn time_step_limits(&self) -> Result<TimeStepLimits, SolverError> {
        let (stable, (viscous, conduction)) = self.stable_dt_and_diffusive_steps()?;
        Ok(TimeStepLimits {
            stable,
            viscous,
            conduction,
        })
    }
}

#[cfg(test)]
#[path = "diffusion_tests.rs"]
mod tests;
