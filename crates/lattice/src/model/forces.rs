//! The forces of [`MsdmLattice`]: the bond forces gathered on the nodes,
//! per dimension and on the structured stencil, and the stencil's volume
//! and energy update.

use rayon::prelude::*;

use super::{bond_force_ref, harmonic, BondRef, MsdmLattice, INTACT};
use crate::geometry::NodeKind;
use crate::law::SpringState;
use crate::stencil;

impl MsdmLattice {
    /// Evaluates the bond forces at the current (x, u) and gathers the net
    /// force on every node into [`MsdmLattice::force`] (eq 9 / 10b).
    ///
    /// Two passes over the nodes: each node evaluates the bonds it owns
    /// into the per-bond force arrays, then gathers + for its own bonds and
    /// − for those of its lower neighbours, in a fixed order (f_ij = −f_ji
    /// exactly; the same bits for any number of threads). The passes are
    /// specialised on the dimension: inactive axes, whose position and
    /// velocity differences are exactly 0, are neither read nor stored,
    /// and the reference quantities of each direction are formed once.
    pub fn compute_forces(&mut self) {
        self.forces_and_update(None);
    }

    /// [`MsdmLattice::compute_forces`], and with `euler = Some(dt)` also
    /// the explicit Euler update of eqs 16–17 (x ← x + uⁿΔt, then
    /// u ← u + f/m Δt on the free axes of solid nodes of positive mass) of
    /// each node right after its net force is gathered, in the same pass.
    /// The node updates only its own entries and the bond pass has read
    /// every position and velocity before, so this is the same arithmetic
    /// as a separate update pass.
    pub(crate) fn forces_and_update(&mut self, euler: Option<f64>) {
        if self.stencil_applies() && !self.has_spring_state {
            self.forces_stencil(euler);
            self.forces_current = euler.is_none();
            self.share_forces(euler.is_some());
            return;
        }
        let mut bf = std::mem::take(&mut self.bond_force);
        let mut force = std::mem::take(&mut self.force);
        let mut x = std::mem::take(&mut self.x);
        let mut u = std::mem::take(&mut self.u);
        match self.geom.dim {
            crate::geometry::Dim::One => {
                self.forces_dim::<1>(&mut x, &mut u, &mut bf, &mut force, euler)
            }
            crate::geometry::Dim::Two => {
                self.forces_dim::<2>(&mut x, &mut u, &mut bf, &mut force, euler)
            }
            crate::geometry::Dim::Three => {
                self.forces_dim::<3>(&mut x, &mut u, &mut bf, &mut force, euler)
            }
        }
        self.bond_force = bf;
        self.force = force;
        self.x = x;
        self.u = u;
        self.forces_current = euler.is_none();
        self.share_forces(euler.is_some());
    }

    /// The two passes of [`MsdmLattice::forces_and_update`] on the
    /// positions `x` and velocities `u` (taken out of `self` for the call).
    fn forces_dim<const D: usize>(
        &self,
        x: &mut [Vec<f64>; 3],
        u: &mut [Vec<f64>; 3],
        bf: &mut [Vec<f64>; 3],
        force: &mut [Vec<f64>; 3],
        euler: Option<f64>,
    ) {
        let nd = self.geom.directions.len();
        let n = self.len();
        let h = self.geom.spacing;
        // At most 3 axial + 6 face-diagonal directions.
        let mut refs = [BondRef::default(); 9];
        let mut offsets = [0isize; 9];
        for (d, dir) in self.geom.directions.iter().enumerate() {
            let mut xi = [0.0; 3];
            for a in 0..3 {
                xi[a] = f64::from(dir.step[a]) * h;
            }
            refs[d] = BondRef::new(xi, dir.axial);
            offsets[d] = dir.offset;
        }
        let refs = &refs[..nd];
        let offsets = &offsets[..nd];
        let status = &self.status[..];
        let kind = &self.geom.kind[..];
        let nm = self.materials.len();
        let laws = &self.laws[..];
        let single = nm == 1;
        let has_state = self.has_spring_state;
        let spring = &self.spring[..];
        // This rank's nodes, and those below whose bonds they gather.
        let (own, bond_nodes) = (self.owned_nodes(), self.bond_nodes());
        {
            let (xr, ur) = (&*x, &*u);
            let [b0, b1, b2] = bf;
            b0.par_chunks_mut(nd)
                .zip(b1.par_chunks_mut(nd))
                .zip(b2.par_chunks_mut(nd))
                .enumerate()
                .for_each(|(i, ((c0, c1), c2))| {
                    if !bond_nodes.contains(&i) {
                        return;
                    }
                    let NodeKind::Solid(mi) = kind[i] else {
                        return;
                    };
                    for d in 0..nd {
                        if status[i * nd + d] != INTACT {
                            continue;
                        }
                        let j = (i as isize + offsets[d]) as usize;
                        let mut r = [0.0; 3];
                        let mut w = [0.0; 3];
                        for a in 0..D {
                            r[a] = xr[a][j] - xr[a][i];
                            w[a] = ur[a][j] - ur[a][i];
                        }
                        let st = if has_state {
                            spring[i * nd + d]
                        } else {
                            SpringState::default()
                        };
                        // An intact spring joins two solid nodes.
                        let law = if single {
                            &laws[0]
                        } else {
                            let mj = match kind[j] {
                                NodeKind::Solid(m) => usize::from(m),
                                NodeKind::Exterior => 0,
                            };
                            &laws[usize::from(mi) * nm + mj]
                        };
                        let f = bond_force_ref(law, &refs[d], r, w, st).f;
                        c0[d] = f[0];
                        if D > 1 {
                            c1[d] = f[1];
                        }
                        if D > 2 {
                            c2[d] = f[2];
                        }
                    }
                });
        }
        let bf = &*bf;
        let body = &self.body;
        let (mass, prescribed, held) = (&self.mass[..], &self.prescribed[..], &self.held_axes[..]);
        // Fixed chunks of nodes: each node's arithmetic does not depend on
        // the chunking, so neither do the bits.
        const CHUNK: usize = 512;
        let [f0, f1, f2] = force;
        let [x0, x1, x2] = x;
        let [u0, u1, u2] = u;
        f0.par_chunks_mut(CHUNK)
            .zip(f1.par_chunks_mut(CHUNK))
            .zip(f2.par_chunks_mut(CHUNK))
            .zip(x0.par_chunks_mut(CHUNK))
            .zip(x1.par_chunks_mut(CHUNK))
            .zip(x2.par_chunks_mut(CHUNK))
            .zip(u0.par_chunks_mut(CHUNK))
            .zip(u1.par_chunks_mut(CHUNK))
            .zip(u2.par_chunks_mut(CHUNK))
            .enumerate()
            .for_each(|(c, ((((((((f0, f1), f2), x0), x1), x2), u0), u1), u2))| {
                let fc = [f0, f1, f2];
                let xc = [x0, x1, x2];
                let uc = [u0, u1, u2];
                for k in 0..fc[0].len() {
                    let i = c * CHUNK + k;
                    if !own.contains(&i) {
                        continue;
                    }
                    if !matches!(kind[i], NodeKind::Solid(_)) {
                        for a in 0..3 {
                            fc[a][k] = 0.0;
                        }
                        continue;
                    }
                    // Components a ≥ D stay +0 (a sum of ±0 from +0 is +0).
                    let mut s = [0.0; 3];
                    for d in 0..nd {
                        if status[i * nd + d] == INTACT {
                            for a in 0..D {
                                s[a] += bf[a][i * nd + d];
                            }
                        }
                    }
                    for d in 0..nd {
                        let j = i as isize - offsets[d];
                        if j >= 0 && (j as usize) < n {
                            let b = j as usize * nd + d;
                            if status[b] == INTACT {
                                for a in 0..D {
                                    s[a] -= bf[a][b];
                                }
                            }
                        }
                    }
                    let mut f = [0.0; 3];
                    for a in 0..3 {
                        f[a] = body[a][i] + s[a];
                        fc[a][k] = f[a];
                    }
                    if let Some(dt) = euler {
                        for a in 0..D {
                            xc[a][k] += uc[a][k] * dt;
                            if !(prescribed[i] && held[i] & (1 << a) != 0) && mass[i] > 0.0 {
                                uc[a][k] += f[a] / mass[i] * dt;
                            }
                        }
                    }
                }
            });
    }

    /// Whether the row-stencil passes of [`crate::stencil`] apply: a 2D
    /// lattice of one material (the force pass also needs springs without
    /// internal state).
    pub(super) fn stencil_applies(&self) -> bool {
        !self.general_passes
            && self.geom.dim == crate::geometry::Dim::Two
            && self.materials.len() == 1
            && self.geom.directions.len() <= stencil::MAX_DIRS
            && self.geom.n[0] >= 3
            && self.geom.n[1] >= 3
    }

    /// Forgets the per-node flags of the row-stencil passes (at the start
    /// of a step: the kinds, status, masses or held axes may have changed
    /// since they were filled).
    pub(crate) fn clear_stencil_flags(&mut self) {
        self.flags_fresh = false;
    }

    /// The box shape of a 2D lattice.
    fn box2(&self) -> stencil::Box2 {
        stencil::Box2 {
            nx: self.geom.n[0],
            ny: self.geom.n[1],
        }
    }

    /// Fills the per-node flags of the row-stencil passes.
    fn fill_flags(&mut self) {
        let n = self.len();
        let mut flags = std::mem::take(&mut self.flags);
        flags.resize(n, 0);
        stencil::node_flags(
            self.box2(),
            self.geom.directions.len(),
            &self.geom.kind,
            &self.status,
            &self.prescribed,
            &self.held_axes,
            &self.mass,
            &mut flags,
        );
        self.flags = flags;
        self.flags_fresh = true;
    }

    /// [`MsdmLattice::forces_and_update`] by the row-stencil passes of
    /// [`crate::stencil`] (same bits).
    fn forces_stencil(&mut self, euler: Option<f64>) {
        debug_assert!(self.stencil_applies() && !self.has_spring_state);
        let b = self.box2();
        let n = self.len();
        let nd = self.geom.directions.len();
        let h = self.geom.spacing;
        let law = &self.laws[0];
        // No plastic yield and no Maxwell arm without spring state.
        debug_assert!(!law.yield_strain.is_finite() && law.k_arm == 0.0);
        let mut dirs = [stencil::Dir2::default(); stencil::MAX_DIRS];
        for (d, dir) in self.geom.directions.iter().enumerate() {
            let mut xi = [0.0; 3];
            for a in 0..3 {
                xi[a] = f64::from(dir.step[a]) * h;
            }
            let r = BondRef::new(xi, dir.axial);
            dirs[d] = stencil::Dir2 {
                sx: dir.step[0] as isize,
                sy: dir.step[1] as isize,
                xi: [xi[0], xi[1]],
                len0: r.len0,
                e0: r.e0,
                k: law.k_inf * r.len0,
                k1: law.k_arm * r.len0,
                c: law.c_par * r.len0,
                kp: if dir.axial { law.k_perp * r.len0 } else { 0.0 },
            };
        }
        let dirs = &dirs[..nd];
        self.fill_flags();
        if self.row_bonds.len() != n * nd * 2 {
            self.row_bonds = vec![0.0; n * nd * 2];
        }
        let rows = |r: std::ops::Range<usize>| r.start / b.nx..r.end.div_ceil(b.nx);
        let (bond_rows, own_rows) = (rows(self.bond_nodes()), rows(self.owned_nodes()));
        let [x0, x1, _] = &mut self.x;
        let [u0, u1, _] = &mut self.u;
        stencil::bond_pass(
            b,
            dirs,
            &self.flags,
            x0,
            x1,
            u0,
            u1,
            &mut self.row_bonds,
            bond_rows,
        );
        let (x, u) = ([&mut x0[..], &mut x1[..]], [&mut u0[..], &mut u1[..]]);
        let [f0, f1, f2] = &mut self.force;
        stencil::gather_pass(
            b,
            dirs,
            &self.flags,
            &self.row_bonds,
            [&self.body[0], &self.body[1], &self.body[2]],
            &self.mass,
            x,
            u,
            [f0, f1, f2],
            euler,
            own_rows,
        );
    }

    /// [`MsdmLattice::update_volume_and_energy`] by the row-stencil pass of
    /// [`crate::stencil`] (same bits).
    pub(super) fn volume_energy_stencil(&mut self, dt: f64, chem_on: bool) {
        let n = self.len();
        let mat = &self.materials[0];
        let h = self.geom.spacing;
        let sur = self.options.surroundings;
        let th = stencil::Thermal {
            neg_bulk: -mat.bulk_modulus(),
            cv: mat.eos.cv,
            gamma: mat.eos.gamma,
            pair: harmonic(mat.conductivity, mat.conductivity) * h,
            ghost: harmonic(mat.conductivity, sur.conductivity) * h,
            t_sur: sur.temperature,
            enthalpy: mat.enthalpy,
            dt,
            spacing: h,
            on: self.options.thermal,
        };
        if !self.flags_fresh {
            self.fill_flags();
        }
        self.flags_fresh = false;
        let [mut v_new, mut e_new, mut p_new, mut t_new] = std::mem::take(&mut self.scratch);
        let own = self.owned_nodes();
        let own_rows = own.start / self.geom.n[0]..own.end.div_ceil(self.geom.n[0]);
        stencil::energy_pass(
            self.box2(),
            &th,
            &self.flags,
            [&self.x[0], &self.x[1]],
            &self.temperature,
            &self.volume,
            &self.mass,
            &self.energy,
            &self.pressure,
            chem_on.then_some(&self.mass_rate[..n]),
            [&mut v_new, &mut e_new, &mut p_new, &mut t_new],
            own_rows,
        );
        self.commit_thermal_state([v_new, e_new, p_new, t_new], chem_on, 1, dt);
    }
}
