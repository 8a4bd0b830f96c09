//! The grid-to-particle transfers: MUSL's second transfer with its
//! re-mapped momentum (eqs 24 and 26), the gather of velocity, position
//! and velocity gradient (eqs 16–17 and 13), and the hoop rate of a
//! particle ring.

use super::*;

/// MUSL's second transfer (coloured, see the module doc), one visit per
/// particle: the velocity update of eq 24, v_p += Δt Σ_I N_Ip a_I, then the
/// scatter of the updated momentum for the re-mapping of eq 26, p_I =
/// Σ_p N_Ip m_p v_p^{n+1}, into `nodes.momentum` (zeroed first). The
/// weights are those of the positions of the start of the step.
pub fn g2p_velocity_and_remap_momentum(
    map: &GridMap,
    bins: &ParticleBins,
    position: &[[f64; 3]],
    mass: &[f64],
    velocity: &mut [[f64; 3]],
    nodes: &mut GridNodes,
    dt: f64,
) {
    zero(&mut nodes.momentum, [0.0; 3]);
    dispatch(
        map,
        Remap {
            map,
            bins,
            position,
            mass,
            velocity: SharedSlice::new(velocity),
            acceleration: &nodes.acceleration,
            momentum: SharedSlice::new(&mut nodes.momentum),
            remap_mass: None,
            dt,
        },
    );
}

/// [`g2p_velocity_and_remap_momentum`] with the re-mapping's own masses:
/// p_I = Σ_p N_Ip w_p v_p^{n+1} and m̃_I = Σ_p N_Ip w_p into `remap_mass`
/// (zeroed first, one per node), with `weight` the particles' masses save
/// for particles that load the grid but are not re-mapped (weight 0), so
/// that eq 26's v_I^{n+1} = p_I / m̃_I is the mean of the re-mapped
/// particles' velocities alone.
#[allow(clippy::too_many_arguments)]
pub fn g2p_velocity_and_remap_momentum_weighted(
    map: &GridMap,
    bins: &ParticleBins,
    position: &[[f64; 3]],
    weight: &[f64],
    velocity: &mut [[f64; 3]],
    nodes: &mut GridNodes,
    remap_mass: &mut [f64],
    dt: f64,
) {
    zero(&mut nodes.momentum, [0.0; 3]);
    zero(remap_mass, 0.0);
    dispatch(
        map,
        Remap {
            map,
            bins,
            position,
            mass: weight,
            velocity: SharedSlice::new(velocity),
            acceleration: &nodes.acceleration,
            momentum: SharedSlice::new(&mut nodes.momentum),
            remap_mass: Some(SharedSlice::new(remap_mass)),
            dt,
        },
    );
}

struct Remap<'a> {
    map: &'a GridMap,
    bins: &'a ParticleBins,
    position: &'a [[f64; 3]],
    mass: &'a [f64],
    velocity: SharedSlice<'a, [f64; 3]>,
    acceleration: &'a [[f64; 3]],
    momentum: SharedSlice<'a, [f64; 3]>,
    remap_mass: Option<SharedSlice<'a, f64>>,
    dt: f64,
}

impl StencilPass for Remap<'_> {
    fn run<const NX: usize, const NY: usize, const NZ: usize>(self) {
        let Self {
            map,
            bins,
            position,
            mass,
            velocity,
            acceleration,
            momentum,
            remap_mass,
            dt,
        } = self;
        bins.for_each_coloured(|block, p| {
            let s = map.stencil::<NX, NY, NZ>(position[p], bins.half_width(p));
            check_footprint(map, s.offset, block);
            let mut dv = [0.0; 3];
            for c in 0..NZ {
                for b in 0..NY {
                    let row = s.row(b, c);
                    let start = map.row_start(s.base, b, c);
                    let ar = &acceleration[start..start + NX];
                    for (&wx, acc) in s.x.w.iter().zip(ar) {
                        let w = row.weight(wx);
                        for k in 0..3 {
                            dv[k] += w * acc[k];
                        }
                    }
                }
            }
            // SAFETY: particle p is listed in exactly one block, so no
            // other visit touches its velocity.
            let v = unsafe { &mut velocity.range(p, 1)[0] };
            for k in 0..3 {
                v[k] += dv[k] * dt;
            }
            let m = mass[p];
            let mv = [m * v[0], m * v[1], m * v[2]];
            for c in 0..NZ {
                for b in 0..NY {
                    let row = s.row(b, c);
                    let start = map.row_start(s.base, b, c);
                    // SAFETY: as in the P2G pass, blocks of one colour
                    // touch disjoint nodes.
                    let pr = unsafe { momentum.range(start, NX) };
                    for (&wx, q) in s.x.w.iter().zip(pr) {
                        let w = row.weight(wx);
                        for k in 0..3 {
                            q[k] += w * mv[k];
                        }
                    }
                }
            }
            if let Some(rm) = &remap_mass {
                for c in 0..NZ {
                    for b in 0..NY {
                        let row = s.row(b, c);
                        let start = map.row_start(s.base, b, c);
                        // SAFETY: as for the momentum.
                        let mr = unsafe { rm.range(start, NX) };
                        for (&wx, q) in s.x.w.iter().zip(mr) {
                            *q += row.weight(wx) * m;
                        }
                    }
                }
            }
        });
    }
}

/// What a storage-order G2P pass reads from the grid and which of its
/// parts run.
#[derive(Debug, Clone, Copy)]
pub struct G2p<'a> {
    /// a_I, for v_p += Δt Σ N_Ip a_I (eq 24).
    pub acceleration: &'a [[f64; 3]],
    /// v_I^{n+1}, for x_p += Δt Σ N_Ip v_I^{n+1} (eq 25).
    pub velocity_new: &'a [[f64; 3]],
    /// The node velocity the gradient L_p = Σ_I v_I ⊗ ∇N_Ip (eqs 27–28) is
    /// formed from.
    pub gradient_velocity: &'a [[f64; 3]],
    /// Time step, s.
    pub dt: f64,
    /// Update the particle velocities (eq 24).
    pub update_velocity: bool,
    /// Update the particle positions (eq 25).
    pub update_position: bool,
    /// Form the velocity gradients.
    pub velocity_gradient: bool,
}

/// The particle arrays a storage-order G2P pass updates.
pub struct G2pParticles<'a> {
    /// Positions: the weights are those of the positions at entry; updated
    /// by eq 25 if asked.
    pub position: &'a mut [[f64; 3]],
    /// Velocities, updated by eq 24 if asked.
    pub velocity: &'a mut [[f64; 3]],
    /// Velocity gradients L_p (`L[i][j]` = Σ v_i ∂N/∂x_j), resized to the
    /// particle count and written if asked.
    pub gradient: &'a mut Vec<Mat3>,
}

/// G2P over the particles in storage order, in parallel, each particle
/// writing only itself: any of the velocity update (eq 24), the position
/// update (eq 25) and the velocity gradient (eqs 27–28), with the weights
/// of the positions at entry. Runs [`g2p_range`] on chunks of particles.
pub fn g2p(map: &GridMap, bins: &ParticleBins, grid: G2p, particles: G2pParticles) {
    let G2pParticles {
        position,
        velocity,
        gradient,
    } = particles;
    let n = position.len();
    assert_eq!(velocity.len(), n, "one velocity per particle");
    let chunk = PARTICLES_PER_TASK;
    let gradients = if grid.velocity_gradient {
        gradient.resize(n, Mat3::zeros());
        rayon::iter::Either::Left(gradient.par_chunks_mut(chunk))
    } else {
        let chunks = n.div_ceil(chunk);
        rayon::iter::Either::Right(
            rayon::iter::repeat_n((), chunks).map(|()| -> &mut [Mat3] { &mut [] }),
        )
    };
    position
        .par_chunks_mut(chunk)
        .zip(velocity.par_chunks_mut(chunk))
        .zip(gradients)
        .enumerate()
        .for_each(|(k, ((x, v), l))| g2p_range(map, bins, grid, k * chunk, x, v, l));
}

/// [`g2p`] of the particles `first .. first + position.len()` (storage
/// order), sequentially: `velocity` holds their velocities and
/// `gradient` receives their velocity gradients (empty when
/// `grid.velocity_gradient` is off). The building block of the passes that
/// go on to use L_p at once (the fused G2P and stress update of
/// [`crate::step`]).
pub fn g2p_range(
    map: &GridMap,
    bins: &ParticleBins,
    grid: G2p,
    first: usize,
    position: &mut [[f64; 3]],
    velocity: &mut [[f64; 3]],
    gradient: &mut [Mat3],
) {
    assert_eq!(velocity.len(), position.len(), "one velocity per particle");
    if grid.velocity_gradient {
        assert_eq!(gradient.len(), position.len(), "one gradient per particle");
    }
    macro_rules! go {
        ($v:literal, $x:literal, $l:literal) => {
            dispatch(
                map,
                G2pRange::<$v, $x, $l> {
                    map,
                    bins,
                    grid,
                    first,
                    position,
                    velocity,
                    gradient,
                },
            )
        };
    }
    match (
        grid.update_velocity,
        grid.update_position,
        grid.velocity_gradient,
    ) {
        (true, true, true) => go!(true, true, true),
        (true, true, false) => go!(true, true, false),
        (true, false, true) => go!(true, false, true),
        (true, false, false) => go!(true, false, false),
        (false, true, true) => go!(false, true, true),
        (false, true, false) => go!(false, true, false),
        (false, false, true) => go!(false, false, true),
        (false, false, false) => {}
    }
}

struct G2pRange<'a, const VEL: bool, const POS: bool, const GRAD: bool> {
    map: &'a GridMap,
    bins: &'a ParticleBins,
    grid: G2p<'a>,
    first: usize,
    position: &'a mut [[f64; 3]],
    velocity: &'a mut [[f64; 3]],
    gradient: &'a mut [Mat3],
}

impl<const VEL: bool, const POS: bool, const GRAD: bool> StencilPass
    for G2pRange<'_, VEL, POS, GRAD>
{
    fn run<const NX: usize, const NY: usize, const NZ: usize>(self) {
        let Self {
            map,
            bins,
            grid,
            first,
            position,
            velocity,
            gradient,
        } = self;
        for (i, (x, v)) in position.iter_mut().zip(velocity.iter_mut()).enumerate() {
            let s = map.stencil::<NX, NY, NZ>(*x, bins.half_width(first + i));
            let mut dv = [0.0; 3];
            let mut dx = [0.0; 3];
            let mut l = [[0.0; 3]; 3];
            // Σ N_Ip v_Ir, for the hoop rate v_r / r of an axisymmetric grid
            // at the radius of the weights (the start of the step).
            let mut v_radial = 0.0;
            let r_weights = x[0];
            for c in 0..NZ {
                for b in 0..NY {
                    let row = s.row(b, c);
                    let r = map.row_start(s.base, b, c);
                    let ar = &grid.acceleration[r..r + if VEL { NX } else { 0 }];
                    let vr = &grid.velocity_new[r..r + if POS { NX } else { 0 }];
                    let gr = &grid.gradient_velocity[r..r + if GRAD { NX } else { 0 }];
                    for a in 0..NX {
                        let (w, g) = row.node(s.x.w[a], s.x.g[a]);
                        if VEL {
                            for k in 0..3 {
                                dv[k] += w * ar[a][k];
                            }
                        }
                        if POS {
                            for k in 0..3 {
                                dx[k] += w * vr[a][k];
                            }
                        }
                        if GRAD {
                            for (li, vi) in l.iter_mut().zip(gr[a]) {
                                for j in 0..3 {
                                    li[j] += vi * g[j];
                                }
                            }
                            v_radial += w * gr[a][0];
                        }
                    }
                }
            }
            if VEL {
                for k in 0..3 {
                    v[k] += dv[k] * grid.dt;
                }
            }
            if POS {
                for k in 0..3 {
                    x[k] += dx[k] * grid.dt;
                }
            }
            if GRAD {
                if map.axisymmetric {
                    l[2][2] = hoop_rate(r_weights, v_radial, l[0][0], map.grid.spacing[0]);
                }
                gradient[i] = Mat3::new(
                    l[0][0], l[0][1], l[0][2], l[1][0], l[1][1], l[1][2], l[2][0], l[2][1], l[2][2],
                );
            }
        }
    }
}

/// The hoop strain rate L_θθ = v_r / r at a particle at radius `r` whose
/// interpolated radial velocity is `vr`; within 10⁻⁹ of a cell `h` of the
/// axis its limit ∂v_r/∂r = `l_rr` (v_r vanishes on the axis), so a particle
/// at r → 0 never divides by zero.
#[inline]
pub fn hoop_rate(r: f64, vr: f64, l_rr: f64, h: f64) -> f64 {
    if r > 1e-9 * h {
        vr / r
    } else {
        l_rr
    }
}
