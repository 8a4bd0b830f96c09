//! The steps of seed 000 §3.3 that a time step runs over the grid: the
//! equilibration pressure (step 2), the face-centred velocities (step 3),
//! the pressure increment (steps 4–5), the Lagrangian values (steps 6–11)
//! and the advection of the fluids (steps 12–14); the order and the
//! coupled pipeline's interleaving are in `Solver::advance` and
//! docs/physics/ice/steps.md.

use super::*;

impl<E: Eos> IceSolver<E> {
    #[inline(never)]
    pub fn compute_equilibration_pressure(&mut self) -> Result<(), SolverError> {
        let params = solver_params!(self);
        let time = self.time;
        let geometry = self.level.geometry;
        type Rescaled = Vec<(usize, ConservationTotals)>;
        type Warm = Vec<(usize, KeptWarmCell)>;
        let results: Vec<(EquilibrationStats, Failure, Rescaled, Warm)> = self
            .state
            .par_iter_mut()
            .zip(self.level.patches.par_iter())
            .zip(self.ranks.owned.par_iter())
            .map(|((pf, patch), &own)| {
                if !own {
                    return (EquilibrationStats::default(), None, Vec::new(), Vec::new());
                }
                type Acc = (EquilibrationStats, Failure, Rescaled, Warm);
                let n = params.eos.len();
                let m = n * NS + 1;
                let mut fields = [Disjoint::empty(); MAX_MATERIALS * NS + 1];
                for (w, f) in fields.iter_mut().zip(pf.data.iter_mut()) {
                    *w = Disjoint::new(f);
                }
                let fields = &fields[..m];
                par_interior(
                    patch,
                    || -> Acc { (EquilibrationStats::default(), None, Vec::new(), Vec::new()) },
                    |(stats, fail, rescaled, warm), c| {
                        let mut vals = [0.0; MAX_MATERIALS * NS + 1];
                        for f in 0..m {
                            vals[f] = fields[f].read(c);
                        }
                        match equilibrate_cell(&params, &mut vals[..m]) {
                            Ok((rep, kept)) => {
                                if kept.any() {
                                    let g = geometry.linear_index(global_of(patch, c));
                                    warm.push((g, kept));
                                }
                                stats.max_iterations = stats.max_iterations.max(rep.iterations);
                                stats.max_residual = stats.max_residual.max(rep.residual.abs());
                                stats.total_iterations += rep.iterations as u64;
                                if params.coupled {
                                    let mut t = ConservationTotals::default();
                                    for r in (0..n).filter(|&r| !params.lagrangian[r]) {
                                        let b = r * NS;
                                        let dm = vals[b + RHO] - fields[b + RHO].read(c);
                                        let u: [f64; 3] =
                                            std::array::from_fn(|a| vals[b + VEL + a]);
                                        t.mass += dm;
                                        for a in 0..3 {
                                            t.momentum[a] += dm * u[a];
                                        }
                                        t.energy += dm
                                            * (vals[b + ENERGY]
                                                + 0.5 * (u[0] * u[0] + u[1] * u[1] + u[2] * u[2]));
                                        // A reactant's mass carries its heat
                                        // of reaction in the totals
                                        // (`conservation_totals`), so the mass
                                        // the rescale gives it does too.
                                        for rx in
                                            params.reactions.iter().filter(|x| x.reactant == r)
                                        {
                                            t.energy += dm * rx.heat_of_reaction;
                                        }
                                    }
                                    if t.mass != 0.0 {
                                        let g = geometry.linear_index(global_of(patch, c));
                                        rescaled.push((g, t));
                                    }
                                }
                                for f in 0..m {
                                    fields[f].write(c, vals[f]);
                                }
                            }
                            Err((_, msg)) => {
                                let g = global_of(patch, c);
                                *fail = first_failure(
                                    fail.take(),
                                    Some((geometry.linear_index(g), g, msg)),
                                );
                            }
                        }
                    },
                    |(s1, f1, mut r1, mut w1), (s2, f2, r2, w2)| {
                        r1.extend(r2);
                        w1.extend(w2);
                        (
                            EquilibrationStats {
                                max_iterations: s1.max_iterations.max(s2.max_iterations),
                                max_residual: s1.max_residual.max(s2.max_residual),
                                total_iterations: s1.total_iterations + s2.total_iterations,
                            },
                            first_failure(f1, f2),
                            r1,
                            w1,
                        )
                    },
                )
            })
            .collect();
        let mut stats = EquilibrationStats::default();
        let mut fail = None;
        let mut rescaled: Vec<(usize, ConservationTotals)> = Vec::new();
        let mut warm: Vec<(usize, KeptWarmCell)> = Vec::new();
        for (s, f, r, w) in results {
            stats.max_iterations = stats.max_iterations.max(s.max_iterations);
            stats.max_residual = stats.max_residual.max(s.max_residual);
            stats.total_iterations += s.total_iterations;
            fail = first_failure(fail, f);
            rescaled.extend(r);
            warm.extend(w);
        }
        // Every rank's findings (rescaled: particles, one rank only).
        let ranks::Found {
            fail, warm, stats, ..
        } = self.gather_pass(ranks::Found {
            fail,
            warm,
            stats,
            ..Default::default()
        });
        self.last_equilibration = stats;
        if fail.is_none() {
            self.book_kept_warm(warm);
        }
        if fail.is_none() && !rescaled.is_empty() {
            // Summed in global cell order: the same bits for any split.
            rescaled.sort_unstable_by_key(|x| x.0);
            let vols = self.volumes();
            let t = &mut self.rescaled;
            for (g, d) in &rescaled {
                let vol = vols.cell(*g);
                t.mass += d.mass * vol;
                for a in 0..3 {
                    t.momentum[a] += d.momentum[a] * vol;
                }
                t.energy += d.energy * vol;
            }
        }
        match fail {
            None => self.find_reaction_surfaces().map_err(SolverError::Other),
            Some((_, cell, detail)) => Err(SolverError::NonPhysicalState {
                time,
                cell,
                centre: geometry.cell_centre(cell),
                detail,
            }),
        }
    }

    /// Step 3 (seed 000 eq 19): face-centred velocities u*_r of every
    /// material on every face, followed by the implicit momentum exchange
    /// on the face (the seed's "same manner as step 10"), with face volume
    /// fractions and densities the means of the two cells'. On symmetry
    /// and fixed-velocity faces u* is the wall's normal velocity.
    // Kept out of line so that profiles attribute each step's cost.
    #[inline(never)]
    pub fn compute_face_centred_velocities(&mut self, dt: f64) {
        self.fill_state_ghosts();
        let params = solver_params!(self);
        let boundaries = &self.boundaries;
        let cells = self.level.geometry.cells;
        // Faces whose diode held back an inflow this step (any order of
        // setting gives the same flags).
        let blocked: [AtomicBool; 6] = Default::default();
        // Eq 19's pressure term over a Courant-ν* step (explicit pressure
        // only: the implicit step's Δt is not an acoustic one).
        let dt_p = match self.options.pressure {
            PressureSolve::Explicit => {
                pressure_term_time(dt, self.options.cfl, self.options.face_pressure_courant)
            }
            PressureSolve::Implicit(_) => dt,
        };
        self.scratch
            .par_iter_mut()
            .zip(self.state.par_iter())
            .zip(self.level.patches.par_iter())
            .zip(self.ranks.owned.par_iter())
            .for_each(|(((sc, pf), patch), &own)| {
                if !own {
                    return;
                }
                let n = params.eos.len();
                let st = patch.strides();
                let d = &pf.data;
                let pidx = n * NS;
                for a in 0..3 {
                    if !params.active[a] {
                        continue;
                    }
                    let dx = params.spacing[a];
                    let g = params.options.gravity[a];
                    let mut fv = [Disjoint::empty(); MAX_MATERIALS];
                    for (w, f) in fv.iter_mut().zip(sc.face_velocity[a].iter_mut()) {
                        *w = Disjoint::new(f);
                    }
                    let fv = &fv[..n];
                    // Wall faces of this patch along a.
                    let lo_wall = if patch.lo[a] == 0 {
                        boundaries[2 * a].wall_velocity().map(|w| w[a])
                    } else {
                        None
                    };
                    let hi_wall = if patch.lo[a] + patch.size[a] == cells[a] {
                        boundaries[2 * a + 1].wall_velocity().map(|w| w[a])
                    } else {
                        None
                    };
                    // Outflow faces of this patch along a: the outward
                    // normal's sign, so u* is kept non-inward (boundary.rs).
                    let lo_out = (patch.lo[a] == 0 && boundaries[2 * a] == IceBoundary::Outflow)
                        .then_some(-1.0);
                    let hi_out = (patch.lo[a] + patch.size[a] == cells[a]
                        && boundaries[2 * a + 1] == IceBoundary::Outflow)
                        .then_some(1.0);
                    let dims = patch.dims();
                    // Per material: ρ, u_a, v, θ as slices, taken once.
                    let mat = |f: usize| -> [&[f64]; MAX_MATERIALS] {
                        std::array::from_fn(|r| if r < n { &d[r * NS + f][..] } else { &[][..] })
                    };
                    let (rho_s, vel_s, vsp_s, th_s) =
                        (mat(RHO), mat(VEL + a), mat(VSP), mat(THETA));
                    let pe = &d[pidx][..];
                    let solid = slip::SolidFraction::new(&params, d);
                    par_faces(patch, a, |c| {
                        let l = c - st[a];
                        let la = (c / st[a]) % dims[a];
                        let (wall, outward) = if la == patch.ghost[a] {
                            (lo_wall, lo_out)
                        } else if la == patch.ghost[a] + patch.size[a] {
                            (hi_wall, hi_out)
                        } else {
                            (None, None)
                        };
                        if let Some(w) = wall {
                            for v in fv {
                                v.write(c, w);
                            }
                            return;
                        }
                        let mut u = [[0.0; 1]; MAX_MATERIALS];
                        let mut rho_f = [0.0; MAX_MATERIALS];
                        let mut th_f = [0.0; MAX_MATERIALS];
                        let (p_l, p_c) = (pe[l], pe[c]);
                        for r in 0..n {
                            let (rho, th) = (rho_s[r], th_s[r]);
                            u[r][0] = face_velocity_damped(
                                rho[l],
                                vel_s[r][l],
                                vsp_s[r][l],
                                p_l,
                                rho[c],
                                vel_s[r][c],
                                vsp_s[r][c],
                                p_c,
                                dt,
                                dt_p,
                                dx,
                                g,
                            );
                            rho_f[r] = 0.5 * (rho[l] + rho[c]);
                            th_f[r] = 0.5 * (th[l] + th[c]);
                        }
                        // The slip exchange's coefficients on a surface
                        // face, K elsewhere.
                        let slip_k;
                        let k = match solid.as_ref().and_then(|s| s.face_weight(c, a, st)) {
                            Some(w) => {
                                slip_k =
                                    slip::face_coefficients(&params, &rho_f[..n], &th_f[..n], w);
                                &slip_k[..n * n]
                            }
                            None => params.k,
                        };
                        momentum_exchange(&rho_f[..n], &th_f[..n], k, dt, &mut u[..n]);
                        for r in 0..n {
                            let u = match outward {
                                Some(sign) => {
                                    // The boundary cell: c on a low face,
                                    // l on a high one.
                                    let b = if sign < 0.0 { c } else { l };
                                    if holds_back_inflow(
                                        u[r][0],
                                        sign,
                                        th_s[r][b],
                                        pe[b],
                                        vsp_s[r][b],
                                    ) {
                                        let face = 2 * a + usize::from(sign > 0.0);
                                        blocked[face].store(true, Ordering::Relaxed);
                                    }
                                    outflow_face_velocity(u[r][0], sign)
                                }
                                None => u[r][0],
                            };
                            fv[r].write(c, u);
                        }
                    });
                }
            });
        for (held, b) in self.blocked_inflow.iter_mut().zip(&blocked) {
            *held |= b.load(Ordering::Relaxed);
        }
    }

    /// Step 5 (seed 000 eqs 20–21): the volume-flux divergence
    /// Σ_r ∇·(θ*_r u*_r), with θ* carried by the advection scheme of step 12
    /// so the pressure sees the volume the advection will move, and the
    /// time-advanced pressure p = p_eq + Δp.
    // Kept out of line so that profiles attribute each step's cost.
    #[inline(never)]
    pub fn compute_pressure_increment(&mut self, dt: f64) {
        let params = solver_params!(self);
        self.press
            .par_iter_mut()
            .zip(self.scratch.par_iter_mut())
            .zip(self.state.par_iter())
            .zip(self.level.patches.par_iter())
            .zip(self.ranks.owned.par_iter())
            .for_each(|((((pr, sc), pf), patch), &own)| {
                if !own {
                    return;
                }
                let n = params.eos.len();
                let st = patch.strides();
                let d = &pf.data;
                let scheme = params.options.advection;
                let PatchScratch {
                    divergence,
                    face_velocity,
                    volume_flux,
                    flux,
                    ring_lo,
                    ring_hi,
                    ..
                } = sc;
                let (ring_lo, ring_hi) = (&*ring_lo, &*ring_hi);
                let g0 = patch.ghost[0];
                let divergence = Disjoint::new(divergence);
                let pressure = Disjoint::new(&mut pr.data[0]);
                let (fa, vf): ([Disjoint; 3], [Disjoint; 3]) = {
                    let (mut f, mut v) = (flux.iter_mut(), volume_flux.iter_mut());
                    (
                        std::array::from_fn(|_| Disjoint::new(f.next().expect("flux array"))),
                        std::array::from_fn(|_| Disjoint::new(v.next().expect("volume flux"))),
                    )
                };
                // Material by material: each face's volume flux θ*_r u*_r
                // once (stored at the face's high-side cell), then each cell
                // differences its two faces. The sums run over r, then the
                // axes, in the same order for every cell and patch split.
                for r in 0..n {
                    let b = r * NS;
                    for a in 0..3 {
                        if !params.active[a] {
                            continue;
                        }
                        let lam = dt / params.spacing[a];
                        let fv = &face_velocity[a][r];
                        let (fa, vf) = (fa[a], vf[a]);
                        let q = |f: usize| move |i: usize| d[b + f][i];
                        par_faces(patch, a, |m| {
                            let courant = fv[m] * lam;
                            let donor = if courant > 0.0 { m - st[a] } else { m };
                            let (slab, v) =
                                donor_volume_slab(scheme, courant, q(RHO), q(VSP), donor, st[a]);
                            let f = courant * slab.mean_density * v;
                            fa.write(m, f);
                            vf.write(m, if r == 0 { 0.0 } else { vf.read(m) } + f / lam);
                        });
                    }
                    // Row by row on contiguous slices; each cell's sum
                    // runs over the axes in order, as cell by cell.
                    par_rows(patch, |c, len| {
                        let div = divergence.slice_mut(c, len);
                        if r == 0 {
                            div.fill(0.0);
                        }
                        for a in 0..3 {
                            if params.active[a] {
                                let lo = fa[a].slice(c, len);
                                let hi = fa[a].slice(c + st[a], len);
                                if a == 0 && params.axisymmetric {
                                    // Radial faces weighted r±/r_c.
                                    let wl = &ring_lo[g0..g0 + len];
                                    let wh = &ring_hi[g0..g0 + len];
                                    for ((q, (&lo, &hi)), (&wl, &wh)) in
                                        div.iter_mut().zip(lo.iter().zip(hi)).zip(wl.iter().zip(wh))
                                    {
                                        *q += (wh * hi - wl * lo) / dt;
                                    }
                                } else {
                                    for ((q, &lo), &hi) in div.iter_mut().zip(lo).zip(hi) {
                                        *q += (hi - lo) / dt;
                                    }
                                }
                            }
                        }
                    });
                }
                let mat = |f: usize| -> [&[f64]; MAX_MATERIALS] {
                    std::array::from_fn(|r| if r < n { &d[r * NS + f][..] } else { &[][..] })
                };
                let (vsp_s, sound_s, th_s) = (mat(VSP), mat(SOUND), mat(THETA));
                par_cells(patch, |c| {
                    let mut theta_kappa = 0.0;
                    for r in 0..n {
                        let v = vsp_s[r][c];
                        let cs = sound_s[r][c];
                        theta_kappa += th_s[r][c] * v / (cs * cs);
                    }
                    let div = if n == 0 { 0.0 } else { divergence.read(c) };
                    let dp = pressure_increment(dt, 0.0, div, theta_kappa);
                    pressure.write(c, d[n * NS][c] + dp);
                });
            });
    }

    /// Adds per-cell firings of the cold-material rule and the trace hold
    /// (global cell, ρ_r Δe_r per material) to [`Self::kept_warm_totals`],
    /// summed in global cell order: the same bits for any split.
    fn book_kept_warm(&mut self, mut warm: Vec<(usize, KeptWarmCell)>) {
        if warm.is_empty() {
            return;
        }
        warm.sort_unstable_by_key(|x| x.0);
        let vols = self.volumes();
        for (g, k) in &warm {
            let vol = vols.cell(*g);
            for (t, (&fired, &e)) in self
                .kept_warm
                .iter_mut()
                .zip(k.fired.iter().zip(&k.energy_density))
            {
                if fired {
                    t.firings += 1;
                    t.energy += e * vol;
                }
            }
        }
    }

    /// Steps 6, 8, 9, 10 and 11 (seed 000 eqs 22–32) in one visit of each
    /// cell: face pressures p* (eq 22) and their gradient, the Lagrangian
    /// momentum and flow-work energy (eqs 23–28), the implicit momentum and
    /// heat exchange (eqs 29–30) with the dissipated kinetic energy
    /// returned to internal energy, and the Lagrangian material volume
    /// (eqs 31–32).
    // Kept out of line so that profiles attribute each step's cost.
    #[inline(never)]
    pub fn compute_lagrangian_values(&mut self, dt: f64) -> Result<(), SolverError> {
        self.carry_surface_burns(dt);
        self.halo.fill_all(
            &self.level,
            &self.press_set,
            &self.press_bcs,
            &mut self.press,
        );
        let params = solver_params!(self);
        let geometry = self.level.geometry;
        let booked = self.booked_faces();
        let fail = self
            .lag
            .par_iter_mut()
            .zip(self.press.par_iter())
            .zip(self.scratch.par_iter())
            .zip(self.state.par_iter())
            .zip(self.level.patches.par_iter())
            .zip(self.ranks.owned.par_iter())
            .map(|(((((lg, pr), sc), pf), patch), &own)| {
                if !own {
                    return (None, Vec::new(), Vec::new());
                }
                let n = params.eos.len();
                let st = patch.strides();
                let d = &pf.data;
                let p = &pr.data[0];
                let mut out = [Disjoint::empty(); MAX_MATERIALS * NL];
                for (w, f) in out.iter_mut().zip(lg.data.iter_mut()) {
                    *w = Disjoint::new(f);
                }
                let rho_s: [&[f64]; MAX_MATERIALS] =
                    std::array::from_fn(|r| if r < n { &d[r * NS + RHO][..] } else { &[][..] });
                let rho_cell = |i: usize| (0..n).map(|r| rho_s[r][i]).sum::<f64>();
                // The face pressure's impulse and work on the domain faces,
                // per unit cell volume: what the interior's momentum and
                // energy lose through them in this step (the cell loop below
                // differences the same p* and volume fluxes).
                let mut booking: FaceBooking = Vec::new();
                for face in 0..6 {
                    let a = face / 2;
                    if !params.active[a] || !booked[face] {
                        continue;
                    }
                    let sign = if face % 2 == 1 { 1.0 } else { -1.0 };
                    for c in domain_face_cells(patch, geometry.cells, face) {
                        let (o, f) = if face % 2 == 1 {
                            (c + st[a], c + st[a])
                        } else {
                            (c - st[a], c)
                        };
                        let (ro, rc) = (rho_cell(o), rho_cell(c));
                        let pf = if face % 2 == 1 {
                            face_pressure(p[c], rc, p[o], ro)
                        } else {
                            face_pressure(p[o], ro, p[c], rc)
                        };
                        // A radial face's area per unit volume of its cell.
                        let w = if a == 0 && params.axisymmetric {
                            let la = c % patch.dims()[0];
                            if face % 2 == 1 {
                                sc.ring_hi[la]
                            } else {
                                sc.ring_lo[la]
                            }
                        } else {
                            1.0
                        };
                        let mut q = [0.0; 5];
                        q[1 + a] = w * sign * dt * pf / params.spacing[a];
                        if params.options.conserve_total_energy {
                            q[4] = w * sign * dt * pf * sc.volume_flux[a][f] / params.spacing[a];
                        }
                        booking.push((geometry.linear_index(global_of(patch, c)), face, 0, q));
                    }
                }
                let dims0 = patch.dims()[0];
                let solid = slip::SolidFraction::new(&params, d);
                let (fail, warm) = par_interior(
                    patch,
                    || (None, Vec::new()),
                    |(fail, warm): &mut (Failure, Vec<(usize, KeptWarmCell)>), c| {
                        let rho_c = rho_cell(c);
                        let mut grad = [0.0; 3];
                        let mut work = 0.0;
                        for a in 0..3 {
                            if params.active[a] {
                                let (lo, hi) = (c - st[a], c + st[a]);
                                let (rl, rh) = (rho_cell(lo), rho_cell(hi));
                                let p_hi = face_pressure(p[c], rho_c, p[hi], rh);
                                let p_lo = face_pressure(p[lo], rl, p[c], rho_c);
                                let w = &sc.volume_flux[a];
                                if a == 0 && params.axisymmetric {
                                    // The ring's radial faces (areas ∝ r±)
                                    // and the hoop source p_c(r₊ − r₋): a
                                    // uniform pressure pushes no ring.
                                    let la = c % dims0;
                                    let (wl, wh) = (sc.ring_lo[la], sc.ring_hi[la]);
                                    grad[0] = (wh * (p_hi - p[c]) - wl * (p_lo - p[c]))
                                        / params.spacing[0];
                                    work -= dt * (wh * p_hi * w[hi] - wl * p_lo * w[c])
                                        / params.spacing[0];
                                } else {
                                    grad[a] = (p_hi - p_lo) / params.spacing[a];
                                    work -= dt * (p_hi * w[hi] - p_lo * w[c]) / params.spacing[a];
                                }
                            }
                        }
                        let work = params.options.conserve_total_energy.then_some(work);
                        let (div, surface) = (sc.divergence[c], &sc.surface);
                        let normal = solid.as_ref().and_then(|s| s.cell_normal(c, st));
                        let cell = CellInputs {
                            p: p[c],
                            divergence: div,
                            grad,
                            pressure_work: work,
                            slip_normal: normal,
                        };
                        match lagrangian_cell(&params, d, c, cell, surface, dt) {
                            Ok((values, kept)) => {
                                for r in 0..n {
                                    for f in 0..NL {
                                        out[r * NL + f].write(c, values[r][f]);
                                    }
                                }
                                if kept.any() {
                                    warm.push((geometry.linear_index(global_of(patch, c)), kept));
                                }
                            }
                            Err(msg) => {
                                let g = global_of(patch, c);
                                *fail = first_failure(
                                    fail.take(),
                                    Some((geometry.linear_index(g), g, msg)),
                                );
                            }
                        }
                    },
                    |(fa, mut wa), (fb, wb)| {
                        wa.extend(wb);
                        (first_failure(fa, fb), wa)
                    },
                );
                (fail, booking, warm)
            })
            .reduce(
                || (None, Vec::new(), Vec::new()),
                |(fa, mut ba, mut wa), (fb, bb, wb)| {
                    ba.extend(bb);
                    wa.extend(wb);
                    (first_failure(fa, fb), ba, wa)
                },
            );
        let (fail, booking, warm) = fail;
        let ranks::Found {
            fail,
            booking,
            warm,
            ..
        } = self.gather_pass(ranks::Found {
            fail,
            booking,
            warm,
            ..Default::default()
        });
        match fail {
            None => {
                book_faces(booking, self.volumes(), &mut self.outflow);
                self.book_kept_warm(warm);
                self.compute_diffusion_sources(dt);
                Ok(())
            }
            Some((_, cell, detail)) => Err(SolverError::NonPhysicalState {
                time: self.time,
                cell,
                centre: geometry.cell_centre(cell),
                detail,
            }),
        }
    }

    /// Step 12: advects every material's mass, momentum, internal energy
    /// and volume with its face velocities, van Leer compatible fluxes or
    /// donor cell (see [`crate::advection`]), and writes the new state.
    // Kept out of line so that profiles attribute each step's cost.
    #[inline(never)]
    pub fn advect_fluids(&mut self, dt: f64) -> Result<(), SolverError> {
        self.halo
            .fill_all(&self.level, &self.lag_set, &self.lag_bcs, &mut self.lag);
        apply_moving_walls(
            &self.level,
            &self.boundaries,
            &mut self.lag,
            self.eos.len(),
            NL,
            L_VEL,
        );
        let booked = self.booked_faces();
        let params = solver_params!(self);
        let geometry = self.level.geometry;
        // Per patch: the first failure and step 12's cold-rule firings as
        // (global cell, material, ρ_r Δe_r).
        type Warm = Vec<(usize, usize, f64)>;
        let (fail, mut warm, booking): (Failure, Warm, FaceBooking) = self
            .state
            .par_iter_mut()
            .zip(self.lag.par_iter())
            .zip(self.scratch.par_iter_mut())
            .zip(self.level.patches.par_iter())
            .zip(self.ranks.owned.par_iter())
            .map(|((((pf, lg), sc), patch), &own)| {
                if !own {
                    return (None, Vec::new(), Vec::new());
                }
                let mut fail: Failure = None;
                let mut warm: Warm = Vec::new();
                let mut booking: FaceBooking = Vec::new();
                let n = params.eos.len();
                let st = patch.strides();
                let l = &lg.data;
                let scheme = params.options.advection;
                let total = params.options.conserve_total_energy;
                let PatchScratch {
                    face_velocity,
                    flux,
                    carried_energy,
                    ring_lo,
                    ring_hi,
                    ..
                } = sc;
                let (ring_lo, ring_hi) = (&*ring_lo, &*ring_hi);
                let g0 = patch.ghost[0];
                let dims0 = patch.dims()[0];
                let mut state = [Disjoint::empty(); MAX_MATERIALS * NS + 1];
                for (w, f) in state.iter_mut().zip(pf.data.iter_mut()) {
                    *w = Disjoint::new(f);
                }
                let fx: [Disjoint; 6] = {
                    let mut it = flux.iter_mut();
                    std::array::from_fn(|_| Disjoint::new(it.next().expect("six flux arrays")))
                };
                // Conserved per unit volume: ρ, ρu (3), ρe (or ρE), ρv,
                // accumulated in the state's own fields.
                const CONS: [usize; 6] = [RHO, VEL, VEL + 1, VEL + 2, ENERGY, THETA];
                for r in 0..n {
                    if params.lagrangian[r] {
                        // Particles carry it (the coupled pipeline).
                        continue;
                    }
                    let b = r * NL;
                    let s = r * NS;
                    let cons: [Disjoint; 6] = std::array::from_fn(|k| state[s + CONS[k]]);
                    // The Lagrangian fields of material r as slices, taken
                    // once per pass (no double index per access). The
                    // carried energy is e, or e + ½|u|² when total energy
                    // is advected, formed once per cell.
                    let lf: [&[f64]; 5] = [
                        &l[b + L_RHO],
                        &l[b + L_VEL],
                        &l[b + L_VEL + 1],
                        &l[b + L_VEL + 2],
                        &l[b + L_ENERGY],
                    ];
                    let l_vsp: &[f64] = &l[b + L_VSP];
                    carried_energy
                        .par_chunks_mut(4096)
                        .enumerate()
                        .for_each(|(chunk, ce)| {
                            let o = chunk * 4096;
                            let e = &lf[4][o..o + ce.len()];
                            if total {
                                let ux = &lf[1][o..o + ce.len()];
                                let uy = &lf[2][o..o + ce.len()];
                                let uz = &lf[3][o..o + ce.len()];
                                for ((((x, &v), &x1), &y1), &z1) in
                                    ce.iter_mut().zip(e).zip(ux).zip(uy).zip(uz)
                                {
                                    *x = v + 0.5 * (x1 * x1 + y1 * y1 + z1 * z1);
                                }
                            } else {
                                ce.copy_from_slice(e);
                            }
                        });
                    let ce = &*carried_energy;
                    // Carried per unit mass: ρ (for the slab), u (3), the
                    // carried energy, v.
                    let carried: [&[f64]; 6] = [lf[0], lf[1], lf[2], lf[3], ce, l_vsp];
                    let field = |k: usize| {
                        let x = carried[k];
                        move |i: usize| x[i]
                    };
                    par_rows(patch, |c, len| {
                        let rho_l = &carried[0][c..c + len];
                        cons[0].slice_mut(c, len).copy_from_slice(rho_l);
                        for k in 1..6 {
                            let x = &carried[k][c..c + len];
                            for ((q, &r), &x) in cons[k].slice_mut(c, len).iter_mut().zip(rho_l).zip(x)
                            {
                                *q = r * x;
                            }
                        }
                    });
                    for a in 0..3 {
                        if !params.active[a] {
                            continue;
                        }
                        let lam = dt / params.spacing[a];
                        let fv = &face_velocity[a][r];
                        // Flux (per unit volume) through the low face of m,
                        // each face once.
                        par_faces(patch, a, |m| {
                            let courant = fv[m] * lam;
                            if courant == 0.0 {
                                for f in fx {
                                    f.write(m, 0.0);
                                }
                                return;
                            }
                            let donor = if courant > 0.0 { m - st[a] } else { m };
                            let (slab, v) = donor_volume_slab(
                                scheme,
                                courant,
                                field(0),
                                field(5),
                                donor,
                                st[a],
                            );
                            let mass = courant * slab.mean_density;
                            fx[0].write(m, mass);
                            for k in 1..5 {
                                fx[k].write(
                                    m,
                                    mass * donor_carried(scheme, field(k), donor, st[a], &slab),
                                );
                            }
                            fx[5].write(m, mass * v);
                        });
                        // What crosses the domain faces along a: through a
                        // low face the flux enters, through a high one it
                        // leaves. A reactant carries its chemical energy.
                        let q_chem = params
                            .reactions
                            .iter()
                            .find(|rx| rx.reactant == r)
                            .map_or(0.0, |rx| rx.heat_of_reaction);
                        for face in [2 * a, 2 * a + 1] {
                            if !booked[face] {
                                continue;
                            }
                            let high = face % 2 == 1;
                            for c in domain_face_cells(patch, geometry.cells, face) {
                                let (m, sign) = if high { (c + st[a], 1.0) } else { (c, -1.0) };
                                // A radial face's area per unit volume.
                                let sign = if a == 0 && params.axisymmetric {
                                    let la = c % dims0;
                                    sign * if high { ring_hi[la] } else { ring_lo[la] }
                                } else {
                                    sign
                                };
                                let mass = fx[0].read(m);
                                let mut q = [
                                    sign * mass,
                                    sign * fx[1].read(m),
                                    sign * fx[2].read(m),
                                    sign * fx[3].read(m),
                                    0.0,
                                ];
                                if total {
                                    q[4] = sign * (fx[4].read(m) + q_chem * mass);
                                }
                                booking.push((
                                    geometry.linear_index(global_of(patch, c)),
                                    face,
                                    r,
                                    q,
                                ));
                            }
                        }
                        let radial = a == 0 && params.axisymmetric;
                        par_rows(patch, |c, len| {
                            for k in 0..6 {
                                let lo = fx[k].slice(c, len);
                                let hi = fx[k].slice(c + st[a], len);
                                if radial {
                                    // Radial faces weighted r±/r_c.
                                    let wl = &ring_lo[g0..g0 + len];
                                    let wh = &ring_hi[g0..g0 + len];
                                    for ((q, (&lo, &hi)), (&wl, &wh)) in cons[k]
                                        .slice_mut(c, len)
                                        .iter_mut()
                                        .zip(lo.iter().zip(hi))
                                        .zip(wl.iter().zip(wh))
                                    {
                                        *q += wl * lo - wh * hi;
                                    }
                                } else {
                                    for ((q, &lo), &hi) in
                                        cons[k].slice_mut(c, len).iter_mut().zip(lo).zip(hi)
                                    {
                                        *q += lo - hi;
                                    }
                                }
                            }
                        });
                    }
                    let (failed, fired) = par_interior(
                        patch,
                        || (None, Vec::new()),
                        |(fail, fired): &mut (Failure, Warm), c| {
                            let mut cons: [f64; 6] = std::array::from_fn(|k| cons[k].read(c));
                            let rho = cons[0];
                            // The cell's mass is summed only for a density
                            // that could lie below the floor of the densest
                            // cell there could be.
                            let floored = if rho > TRACE_FLOOR * MAX_CELL_DENSITY {
                                None
                            } else {
                                let cell = (0..n).map(|s| l[s * NL + L_RHO][c].abs()).sum();
                                trace_floor(rho, cell)
                            };
                            if let Some(rho) = floored {
                                // A trace the step emptied to round-off, or
                                // drained below the floor: it stays a trace
                                // at the floor, with the state it had before
                                // the advection.
                                cons = [
                                    rho,
                                    rho * lf[1][c],
                                    rho * lf[2][c],
                                    rho * lf[3][c],
                                    rho * ce[c],
                                    rho * l_vsp[c],
                                ];
                            }
                            let rho = cons[0];
                            // The density itself: ρ was accumulated in
                            // place, so a floored density set above is
                            // stored here (the other fields are written
                            // from `cons` below).
                            state[s + RHO].write(c, rho);
                            if !(rho > 0.0 && rho.is_finite()) {
                                let g = global_of(patch, c);
                                *fail = first_failure(
                                    fail.take(),
                                    Some((
                                        geometry.linear_index(g),
                                        g,
                                        format!(
                                            "material {} density {rho:e} kg/m³ after advection (step 12)",
                                            r + 1
                                        ),
                                    )),
                                );
                                return;
                            }
                            for k in 0..3 {
                                state[s + VEL + k].write(c, cons[1 + k] / rho);
                            }
                            let kinetic = if total {
                                let u = [cons[1] / rho, cons[2] / rho, cons[3] / rho];
                                0.5 * (u[0] * u[0] + u[1] * u[1] + u[2] * u[2])
                            } else {
                                0.0
                            };
                            let mut e = cons[4] / rho - kinetic;
                            let v = cons[5] / rho;
                            if total {
                                // E − ½|u|² of a fast, cold material (a gas
                                // whose kinetic energy is many times its
                                // internal energy) can fall below its 0 K
                                // energy when ρE and ρu are limited
                                // separately: keep the material's
                                // temperature of the step's start instead.
                                let t_keep = state[s + TEMP].read(c);
                                let advected = e;
                                e = kept_warm(&params.eos[r], 1.0 / v, e, t_keep).0;
                                if e != advected {
                                    let g = geometry.linear_index(global_of(patch, c));
                                    fired.push((g, r, rho * (e - advected)));
                                }
                            }
                            state[s + ENERGY].write(c, e);
                            state[s + VSP].write(c, v);
                            state[s + THETA].write(c, cons[5]);
                        },
                        |(fa, mut wa), (fb, wb)| {
                            wa.extend(wb);
                            (first_failure(fa, fb), wa)
                        },
                    );
                    fail = first_failure(fail, failed);
                    warm.extend(fired);
                }
                (fail, warm, booking)
            })
            .reduce(
                || (None, Vec::new(), Vec::new()),
                |(fa, mut wa, mut ba), (fb, wb, bb)| {
                    wa.extend(wb);
                    ba.extend(bb);
                    (first_failure(fa, fb), wa, ba)
                },
            );
        let ranks::Found {
            fail,
            booking,
            advected_warm,
            ..
        } = self.gather_pass(ranks::Found {
            fail,
            booking,
            advected_warm: warm,
            ..Default::default()
        });
        warm = advected_warm;
        let vols = self.volumes();
        if fail.is_none() {
            book_faces(booking, vols, &mut self.outflow);
        }
        if fail.is_none() && !warm.is_empty() {
            // Summed in global cell order: the same bits for any split.
            warm.sort_unstable_by_key(|x| (x.0, x.1));
            for &(g, r, e) in &warm {
                let t = &mut self.kept_warm_advection[r];
                t.firings += 1;
                t.energy += e * vols.cell(g);
            }
        }
        match fail {
            None => Ok(()),
            Some((_, cell, detail)) => Err(SolverError::NonPhysicalState {
                time: self.time,
                cell,
                centre: geometry.cell_centre(cell),
                detail,
            }),
        }
    }
}

/// The smallest share of its cell's mass density a fluid keeps after
/// step 12: 10⁻¹⁰⁰, far below the rounding of the cell's mass (ε ≈
/// 2·10⁻¹⁶ of it) and far above the floating-point floor. A trace that
/// flows out of a cell with no inflow (the cells on the axis of a radially
/// expanding solid lose a share of it every step) decays geometrically:
/// the cook-off's products trace reached 10⁻³¹⁶ kg/m³, a subnormal, and
/// the next step's energy closure gave it −∞ J/kg. Uintah guards the same
/// limit with an absolute density, `d_TINY_RHO` = 10⁻¹² kg/m³
/// (docs/physics/ice/steps.md, "Step 12").
pub(crate) const TRACE_FLOOR: f64 = 1e-100;

/// A bound on any cell's mass density (kg/m³), above every condensed
/// material (10⁴–10⁵) by far: a density above [`TRACE_FLOOR`] times it
/// cannot be below its cell's floor, so step 12 skips the cell's sum.
const MAX_CELL_DENSITY: f64 = 1e20;

/// The density step 12 stores in place of an advected density `rho` in a
/// cell whose materials held `cell` = Σ|ρ| before the advection, or `None`
/// to keep `rho`: [`TRACE_FLOOR`] `cell` for a positive density below it,
/// and for a negative one within 4 ε of `cell` — zero to round-off (a
/// trace of 10⁻¹⁷⁰ kg/m³ drained by fluxes of its own size goes to
/// −10⁻¹⁷² by their rounding alone). Either change of the cell's mass is
/// below its rounding, so mass closes to round-off as before. Any other
/// non-positive or non-finite density is kept, and stops the run.
#[inline]
fn trace_floor(rho: f64, cell: f64) -> Option<f64> {
    let floor = TRACE_FLOOR * cell;
    let round_off_zero = rho <= 0.0 && rho.is_finite() && -rho <= 4.0 * f64::EPSILON * cell;
    if round_off_zero || (rho > 0.0 && rho < floor) {
        Some(floor.max(rho.abs()).max(f64::MIN_POSITIVE))
    } else {
        None
    }
}

#[cfg(test)]
mod round_off_tests {
    use super::{trace_floor, TRACE_FLOOR};

    /// In a cell of 1840 kg/m³: −10⁻¹⁷² and −10⁻¹³ kg/m³ are zero to
    /// round-off (below 4 ε · 1840 = 1.6·10⁻¹²) and go to the floor
    /// 1.84·10⁻⁹⁷; so does a positive 10⁻³¹⁶ (a subnormal). −10⁻¹¹ there, a
    /// negative density in an empty cell, or a non-finite one are kept (and
    /// stop the run), and so is anything at or above the floor.
    #[test]
    fn a_density_below_the_floor_or_the_cells_rounding_goes_to_the_floor() {
        let cell = 1840.0 + 1e-170 + 1e-6;
        let floor = TRACE_FLOOR * cell;
        assert_eq!(trace_floor(-1e-172, cell), Some(floor));
        assert_eq!(trace_floor(-1e-13, cell), Some(1e-13));
        assert_eq!(trace_floor(1e-316, cell), Some(floor));
        assert_eq!(trace_floor(0.0, cell), Some(floor));
        assert_eq!(trace_floor(-1e-11, cell), None);
        assert_eq!(trace_floor(-1e-300, 0.0), None);
        assert_eq!(trace_floor(f64::NEG_INFINITY, cell), None);
        assert_eq!(trace_floor(f64::NAN, cell), None);
        assert_eq!(trace_floor(floor, cell), None);
        assert_eq!(trace_floor(1e-90, cell), None);
    }
}
