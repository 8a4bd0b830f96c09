//! The explicit MPM step of seed 001 §2.2 in its three classical variants.
//!
//! With N_Ip and ∇N_Ip evaluated at the particle positions of the start of
//! the step (x_p^n):
//!
//! - **USL** (update stress last): P2G of m_I (eq 21), p_I (eq 18) and
//!   f_I = f_I^int + f_I^ext (eqs 19, 20, 23) from σ_p^n; nodal
//!   acceleration a_I = f_I/m_I and v_I^{n+1} = v_I^n + a_I Δt (eq 22);
//!   G2P v_p += Σ N_Ip a_I Δt (eq 24) and x_p += Σ N_Ip v_I^{n+1} Δt
//!   (eq 25); velocity gradient L_p = Σ v_I^{n+1} ⊗ ∇N_Ip (eqs 27–28) and
//!   the stress update.
//! - **MUSL** (modified USL): as USL, but before the velocity gradient the
//!   grid velocity is re-mapped from the updated particle velocities,
//!   v_I^{n+1} = Σ m_p N_Ip v_p^{n+1} / m_I (eq 26), the variant of the
//!   seed's step list (its steps 9–13).
//! - **USF** (update stress first): P2G of m_I and p_I; L_p from v_I^n and
//!   the stress update; then P2G of the force from σ_p^{n+1} and the
//!   momentum update and G2P as above.
//!
//! Eq 25 of the seed writes the position update with p_I^n; it is read here
//! as the leapfrog (central-difference) update x_p += Σ N_Ip v_I^{n+1} Δt
//! of the same authors' explicit MPM, which unlike a forward-Euler position
//! update does not feed energy into an oscillating body.
//!
//! Nodes whose mass is below `mass_cutoff` × the reference particle mass
//! get zero velocity and acceleration (see [`StepParams::mass_threshold`]).
//! The grid boundary conditions ([`crate::boundary`]) act on v_I^n, a_I and
//! v_I^{n+1}.
//!
//! The per-particle stress update is in [`update_particle_stress`].

use crate::boundary::GridBoundary;
use crate::grid_nodes::{GridNodes, NodeStage, NodeUpdate};
use crate::transfer::{self, G2pParticles, GridMap, P2gParticles, P2gSums, ParticleBins};
use crate::viscosity::{BulkViscosityState, ViscosityParams};
use crate::{MaterialId, Particles, ShapeFunction};
use brisance_constitutive::MaterialModel;
use brisance_core::{Mat3, Material, StressUpdateInput, UniformGridGeometry};
use rayon::iter::Either;
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

/// Which explicit MPM update scheme a step uses.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default, Serialize, Deserialize)]
pub enum UpdateScheme {
    /// Update stress first: velocity gradient from the start-of-step grid
    /// velocity.
    Usf,
    /// Update stress last: velocity gradient from the momentum-updated grid
    /// velocity (seed 001 eq 22).
    Usl,
    /// Modified USL: velocity gradient from the grid velocity re-mapped from
    /// the updated particle velocities (seed 001 eq 26).
    #[default]
    Musl,
}

/// The fixed parameters of one step.
#[derive(Debug, Clone, Copy)]
pub struct StepParams<'a> {
    /// The grid.
    pub grid: &'a UniformGridGeometry,
    /// Shape function.
    pub shape: ShapeFunction,
    /// Update scheme.
    pub scheme: UpdateScheme,
    /// Body force per unit mass (gravity), m/s².
    pub gravity: [f64; 3],
    /// Face conditions x−, x+, y−, y+, z−, z+.
    pub boundaries: &'a [GridBoundary; 6],
    /// Nodes lighter than this (kg) get zero velocity and acceleration:
    /// `mass_cutoff` × the reference particle mass.
    pub mass_threshold: f64,
    /// On an axisymmetric grid, `[r of node 0, Δr]`, and `mass_threshold`
    /// is per metre of radius ([`NodeUpdate::radial`]).
    pub radial_cutoff: Option<[f64; 2]>,
    /// Light nodes keep p_I/m_I ([`NodeUpdate::light_nodes_move`]): the
    /// coupled ICE–MPM step only.
    pub light_nodes_move: bool,
    /// Constitutive models, indexed by [`MaterialId`].
    pub materials: &'a [MaterialModel],
    /// Time step, s.
    pub dt: f64,
    /// Artificial bulk viscosity of the stress update, if any.
    pub bulk_viscosity: Option<ViscosityParams>,
    /// Nodal forces of the prescribed surface tractions at tⁿ, as (node
    /// storage index, force in N) pairs ([`crate::traction`]), and of the
    /// reservoirs beyond open faces ([`crate::inflow`]); added to f_I
    /// before the momentum update.
    pub surface_forces: &'a [(usize, [f64; 3])],
    /// The mass and momentum the reservoirs beyond open faces add to the
    /// nodes ([`crate::inflow::NodeShare`]), after every P2G of mass and
    /// momentum and after MUSL's re-mapping; empty without reservoirs.
    pub reservoir: &'a [crate::inflow::NodeShare],
    /// The particles `(first, end)` whose stress update (and the G2P fused
    /// with it) this process computes when the particles are spread over
    /// MPI ranks (docs/cluster.md); `None`: every particle.
    pub own: Option<(usize, usize)>,
}

/// Every reason [`update_particle_stress`] gives for refusing an update,
/// so that a failure can cross between ranks as a number.
pub const FAILURE_REASONS: [&str; 4] = [
    "det F is not positive",
    "the updated stress is not finite",
    "the bulk viscosity is not finite",
    "the specific internal energy is not finite",
];

/// Why a particle's stress update was refused.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ParticleFailure {
    /// Particle index (in the sorted order of this step).
    pub index: usize,
    /// det F after the update.
    pub jacobian: f64,
    /// What went wrong.
    pub reason: &'static str,
    /// tr(L) Δt of the refused update: the volumetric strain increment
    /// (below −1 the linear update inverts the volume itself).
    pub trace_l_dt: f64,
    /// max |L_ij| Δt of the refused update: above about 1 the step was
    /// far too long for the velocity differences across the particle.
    pub max_l_dt: f64,
    /// max |F_ij| of the particle's F before the refused update.
    pub max_f_old: f64,
}

impl ParticleFailure {
    /// The failure's reason with J and the velocity-gradient increment
    /// that produced it, for the run's diagnostic.
    pub fn describe(&self) -> String {
        format!(
            "{} (J = det F = {:e}; tr(L) Δt = {:e}, max |L_ij| Δt = {:e}; max |F_ij| before = {:e})",
            self.reason, self.jacobian, self.trace_l_dt, self.max_l_dt, self.max_f_old
        )
    }
}

/// The kernels' view of one step: the grid map and the particles' bins
/// (see [`crate::transfer`]), built at the start of the step from the
/// positions x_p^n.
#[derive(Debug, Clone, Copy)]
pub struct Transfer<'a> {
    /// Grid geometry, lattice and block layout of the shape function.
    pub map: &'a GridMap,
    /// The particles of every block.
    pub bins: &'a ParticleBins,
}

impl StepParams<'_> {
    /// What the node updates need.
    pub(crate) fn node_update(&self) -> NodeUpdate<'_> {
        NodeUpdate {
            boundaries: self.boundaries,
            cells: self.grid.cells,
            mass_threshold: self.mass_threshold,
            radial: self.radial_cutoff,
            light_nodes_move: self.light_nodes_move,
            gravity: self.gravity,
            dt: self.dt,
        }
    }
}

fn p2g_inputs(particles: &Particles) -> P2gParticles<'_> {
    P2gParticles {
        position: &particles.position,
        mass: &particles.mass,
        velocity: &particles.velocity,
        volume: &particles.volume,
        stress: &particles.stress,
    }
}

/// P2G of mass (eq 21) and momentum (eq 18), then v_I^n = p_I/m_I with the
/// cut-off and the boundary conditions (USF's first transfer).
pub fn p2g_velocity(
    t: &Transfer,
    particles: &Particles,
    nodes: &mut GridNodes,
    params: &StepParams,
) {
    transfer::p2g(
        t.map,
        t.bins,
        p2g_inputs(particles),
        nodes,
        P2gSums::MassMomentum,
    );
    crate::inflow::add_mass_and_momentum(params.reservoir, nodes);
    nodes.update(&params.node_update(), NodeStage::Velocity);
}

/// P2G of the internal force f_I = −Σ V_p σ_p ∇N_Ip (eq 19), then the
/// surface tractions f_I += Σ_p N_Ip t_p A_p and the body force
/// f_I += m_I g (eqs 20, 23),
/// a_I = f_I/m_I and v_I^{n+1} = v_I^n + a_I Δt (eq 22), with the cut-off
/// and the boundary conditions (USF's force transfer, from σ_p^{n+1}).
pub fn p2g_integrate(
    t: &Transfer,
    particles: &Particles,
    nodes: &mut GridNodes,
    params: &StepParams,
) {
    p2g_integrate_stress(t, particles, &particles.stress, nodes, params);
}

/// [`p2g_integrate`] with the internal force formed from `stress` instead
/// of the particles' own (the cell-averaged pressure of the ΔF̄ option,
/// [`crate::anti_locking::PatchAverage::average_pressure`]).
pub fn p2g_integrate_stress(
    t: &Transfer,
    particles: &Particles,
    stress: &[[f64; 6]],
    nodes: &mut GridNodes,
    params: &StepParams,
) {
    p2g_with_force(
        t,
        particles,
        stress,
        nodes,
        params,
        P2gSums::Force,
        NodeStage::Integrate,
    );
}

/// [`p2g_velocity`] and [`p2g_integrate`] fused: mass, momentum and force
/// in one visit of each particle, then v_I^n, a_I and v_I^{n+1} in one
/// pass over the nodes (USL and MUSL, force from σ_p^n).
pub fn p2g_velocity_and_integrate(
    t: &Transfer,
    particles: &Particles,
    nodes: &mut GridNodes,
    params: &StepParams,
) {
    p2g_velocity_and_integrate_stress(t, particles, &particles.stress, nodes, params);
}

/// [`p2g_velocity_and_integrate`] with the internal force formed from
/// `stress` instead of the particles' own (see [`p2g_integrate_stress`]).
pub fn p2g_velocity_and_integrate_stress(
    t: &Transfer,
    particles: &Particles,
    stress: &[[f64; 6]],
    nodes: &mut GridNodes,
    params: &StepParams,
) {
    p2g_with_force(
        t,
        particles,
        stress,
        nodes,
        params,
        P2gSums::All,
        NodeStage::VelocityAndIntegrate,
    );
}

/// The P2G sums `sums` with the internal force from `stress`, the surface
/// loads added to the nodal force, then the node update `stage`.
fn p2g_with_force(
    t: &Transfer,
    particles: &Particles,
    stress: &[[f64; 6]],
    nodes: &mut GridNodes,
    params: &StepParams,
    sums: P2gSums,
    stage: NodeStage,
) {
    let inputs = P2gParticles {
        stress,
        ..p2g_inputs(particles)
    };
    transfer::p2g(t.map, t.bins, inputs, nodes, sums);
    if sums != P2gSums::Force {
        crate::inflow::add_mass_and_momentum(params.reservoir, nodes);
    }
    crate::traction::add_node_forces(params.surface_forces, &mut nodes.force);
    nodes.update(&params.node_update(), stage);
}

/// MUSL: the velocity update of eq 24, v_p += Δt Σ N_Ip a_I, and the
/// re-mapping of eq 26 in one visit of each particle, then
/// v_I^{n+1} = Σ m_p N_Ip v_p^{n+1} / m_I into `nodes.velocity_remap`, with
/// the cut-off and the boundary conditions. The weights are those of x_p^n.
pub fn g2p_velocity_and_remap(
    t: &Transfer,
    particles: &mut Particles,
    nodes: &mut GridNodes,
    params: &StepParams,
) {
    transfer::g2p_velocity_and_remap_momentum(
        t.map,
        t.bins,
        &particles.position,
        &particles.mass,
        &mut particles.velocity,
        nodes,
        params.dt,
    );
    crate::inflow::add_momentum(params.reservoir, nodes);
    nodes.update(&params.node_update(), NodeStage::Remap);
}

/// [`g2p_velocity_and_remap`] with the re-mapping of eq 26 over the
/// particles of nonzero `weight` alone (their masses; zero for particles
/// that load the grid but are not re-mapped):
/// v_I^{n+1} = Σ_p w_p N_Ip v_p^{n+1} / Σ_p w_p N_Ip, the mean velocity of
/// the re-mapped particles at the node, with the cut-off (on that mass)
/// and the boundary conditions. `remap_mass` is a buffer of one value per
/// node. Reservoir shares ([`crate::inflow`]) add their momentum but no
/// mass here, so the solver uses this only without inflow faces.
pub fn g2p_velocity_and_remap_weighted(
    t: &Transfer,
    particles: &mut Particles,
    nodes: &mut GridNodes,
    params: &StepParams,
    weight: &[f64],
    remap_mass: &mut Vec<f64>,
) {
    remap_mass.resize(nodes.mass.len(), 0.0);
    transfer::g2p_velocity_and_remap_momentum_weighted(
        t.map,
        t.bins,
        &particles.position,
        weight,
        &mut particles.velocity,
        nodes,
        remap_mass,
        params.dt,
    );
    // The node update divides by `nodes.mass`: the re-mapping's masses
    // stand in for it, then the lumped masses of eqs 21/37 return.
    std::mem::swap(&mut nodes.mass, remap_mass);
    nodes.update(&params.node_update(), NodeStage::Remap);
    std::mem::swap(&mut nodes.mass, remap_mass);
}

/// A node velocity field of [`GridNodes`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum NodeVelocity {
    /// v_I^n (`velocity`).
    Start,
    /// v_I^{n+1} of eq 22 (`velocity_new`).
    End,
    /// MUSL's re-mapped v_I^{n+1} of eq 26 (`velocity_remap`).
    Remapped,
}

impl NodeVelocity {
    fn of(self, nodes: &GridNodes) -> &[[f64; 3]] {
        match self {
            Self::Start => &nodes.velocity,
            Self::End => &nodes.velocity_new,
            Self::Remapped => &nodes.velocity_remap,
        }
    }
}

/// What one G2P visit of the particles does.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct G2pParts {
    /// v_p += Δt Σ N_Ip a_I (eq 24).
    pub velocity: bool,
    /// x_p += Δt Σ N_Ip v_I^{n+1} (eq 25).
    pub position: bool,
    /// L_p = Σ_I v_I ⊗ ∇N_Ip (eqs 27–28, `L[i][j]` = Σ v_i ∂N/∂x_j) from
    /// this node velocity, into the gradient buffer.
    pub gradient: Option<NodeVelocity>,
}

/// G2P over the particles in storage order (parallel, each particle
/// writing only itself), with the weights of x_p^n: the parts of `parts`,
/// the velocity gradients into `gradient` (resized to the particle count).
pub fn g2p(
    t: &Transfer,
    particles: &mut Particles,
    nodes: &GridNodes,
    dt: f64,
    parts: G2pParts,
    gradient: &mut Vec<Mat3>,
) {
    transfer::g2p(
        t.map,
        t.bins,
        transfer::G2p {
            acceleration: &nodes.acceleration,
            velocity_new: &nodes.velocity_new,
            gradient_velocity: parts.gradient.unwrap_or(NodeVelocity::End).of(nodes),
            dt,
            update_velocity: parts.velocity,
            update_position: parts.position,
            velocity_gradient: parts.gradient.is_some(),
        },
        G2pParticles {
            position: &mut particles.position,
            velocity: &mut particles.velocity,
            gradient,
        },
    );
}

/// The stress update of every particle (parallel over particles), see
/// [`update_particle_stress`]; `bulk` is each particle's bulk-viscosity
/// state (same order as the particles). Returns the failure of the
/// lowest-index particle that failed, if any.
pub fn update_stresses(
    particles: &mut Particles,
    velocity_gradient: &[Mat3],
    bulk: &mut [BulkViscosityState],
    params: &StepParams,
) -> Option<ParticleFailure> {
    assert_eq!(
        velocity_gradient.len(),
        particles.len(),
        "one L per particle"
    );
    for_each_chunk(particles, bulk, params.own, |mut chunk| {
        let l = &velocity_gradient[chunk.first..chunk.first + chunk.len()];
        chunk.update_stresses(l, params)
    })
}

/// G2P (the `parts`, as [`g2p`] makes them) and the stress update
/// ([`update_stresses`]) in one visit of each particle: the velocity
/// gradient is formed for a chunk of particles and used at once, instead of
/// being stored for every particle and read back. The same results as the
/// two passes one after the other. `parts.gradient` must be set.
pub fn g2p_and_update_stresses(
    t: &Transfer,
    particles: &mut Particles,
    bulk: &mut [BulkViscosityState],
    nodes: &GridNodes,
    params: &StepParams,
    parts: G2pParts,
) -> Option<ParticleFailure> {
    let from = parts
        .gradient
        .expect("the stress update needs a velocity gradient");
    let grid = transfer::G2p {
        acceleration: &nodes.acceleration,
        velocity_new: &nodes.velocity_new,
        gradient_velocity: from.of(nodes),
        dt: params.dt,
        update_velocity: parts.velocity,
        update_position: parts.position,
        velocity_gradient: true,
    };
    for_each_chunk(particles, bulk, params.own, |mut chunk| {
        let mut l = [Mat3::zeros(); STRESS_CHUNK];
        let l = &mut l[..chunk.len()];
        transfer::g2p_range(
            t.map,
            t.bins,
            grid,
            chunk.first,
            chunk.position,
            chunk.velocity,
            l,
        );
        chunk.update_stresses(l, params)
    })
}

/// G2P (the `parts`) and the stress update with the ΔF̄ volume averaging
/// of [`crate::anti_locking`]: G2P stores every L_p in
/// `average.gradient`, the volume changes are averaged over each cell
/// (the cells `average` was assigned at the start of the step, from
/// x_pⁿ) with the volumes Vⁿ as weights, and [`update_stresses`] runs on
/// the averaged gradients L̄_p. Three passes instead of the fused one,
/// since a particle's L̄ needs the L of every particle of its cell.
/// `parts.gradient` must be set.
pub fn g2p_average_and_update_stresses(
    t: &Transfer,
    particles: &mut Particles,
    bulk: &mut [BulkViscosityState],
    nodes: &GridNodes,
    params: &StepParams,
    parts: G2pParts,
    average: &mut crate::anti_locking::PatchAverage,
) -> Option<ParticleFailure> {
    assert!(
        parts.gradient.is_some(),
        "the stress update needs a velocity gradient"
    );
    g2p(t, particles, nodes, params.dt, parts, &mut average.gradient);
    average.average(&particles.volume, params.dt);
    update_stresses(particles, &average.gradient, bulk, params)
}

/// What [`p2g_integrate`] or [`p2g_velocity_and_integrate`] (per
/// `sums`, [`P2gSums::Force`] or [`P2gSums::All`]) do, with the internal
/// force formed from the cell-averaged pressure when `average` is given
/// (the ΔF̄ option, [`crate::anti_locking`]; `average` assigned to the
/// cells of x_pⁿ).
pub fn p2g_integrate_averaged(
    t: &Transfer,
    particles: &Particles,
    nodes: &mut GridNodes,
    params: &StepParams,
    sums: P2gSums,
    average: Option<&mut crate::anti_locking::PatchAverage>,
) {
    let stress = match average {
        Some(a) => {
            a.average_pressure(&particles.volume, &particles.stress);
            &a.stress
        }
        None => &particles.stress,
    };
    match sums {
        P2gSums::Force => p2g_integrate_stress(t, particles, stress, nodes, params),
        P2gSums::All => p2g_velocity_and_integrate_stress(t, particles, stress, nodes, params),
        P2gSums::MassMomentum => unreachable!("no internal force in a mass-momentum P2G"),
    }
}

/// [`g2p_and_update_stresses`], or [`g2p_average_and_update_stresses`]
/// when `average` is given.
pub fn g2p_and_update_stresses_averaged(
    t: &Transfer,
    particles: &mut Particles,
    bulk: &mut [BulkViscosityState],
    nodes: &GridNodes,
    params: &StepParams,
    parts: G2pParts,
    average: Option<&mut crate::anti_locking::PatchAverage>,
) -> Option<ParticleFailure> {
    match average {
        Some(a) => g2p_average_and_update_stresses(t, particles, bulk, nodes, params, parts, a),
        None => g2p_and_update_stresses(t, particles, bulk, nodes, params, parts),
    }
}

/// Particles per task of the stress-update passes.
const STRESS_CHUNK: usize = 256;

/// The particles `first .. first + len` of the set, every array the
/// stress update and G2P touch.
struct ParticleChunk<'a> {
    first: usize,
    stride: usize,
    position: &'a mut [[f64; 3]],
    velocity: &'a mut [[f64; 3]],
    stress: &'a mut [[f64; 6]],
    deformation_gradient: &'a mut [[f64; 9]],
    volume: &'a mut [f64],
    temperature: &'a mut [f64],
    specific_internal_energy: &'a mut [f64],
    failed: &'a mut [bool],
    history: &'a mut [f64],
    material: &'a [MaterialId],
    mass: &'a [f64],
    initial_volume: &'a [f64],
    bulk: &'a mut [BulkViscosityState],
}

impl ParticleChunk<'_> {
    fn len(&self) -> usize {
        self.stress.len()
    }

    /// [`update_particle_stress`] of every particle of the chunk, with
    /// velocity gradients `l`; the chunk's first failure, if any (every
    /// particle is updated either way).
    fn update_stresses(&mut self, l: &[Mat3], params: &StepParams) -> Option<ParticleFailure> {
        let mut failure = None;
        let s = self.stride;
        for (i, l) in l.iter().enumerate() {
            let mat = self.material[i];
            let state = ParticleState {
                stress: &mut self.stress[i],
                deformation_gradient: &mut self.deformation_gradient[i],
                volume: &mut self.volume[i],
                temperature: &mut self.temperature[i],
                specific_internal_energy: &mut self.specific_internal_energy[i],
                failed: &mut self.failed[i],
                history: &mut self.history[i * s..(i + 1) * s],
                bulk_viscosity: &mut self.bulk[i],
            };
            let material = &params.materials[mat.0 as usize];
            let updated = update_particle_stress(
                material,
                mat,
                state,
                l,
                self.mass[i],
                self.initial_volume[i],
                params.dt,
                params.bulk_viscosity,
            );
            if let (Err((jacobian, reason)), None) = (updated, &failure) {
                failure = Some(ParticleFailure {
                    index: self.first + i,
                    jacobian,
                    reason,
                    trace_l_dt: l.trace() * params.dt,
                    max_l_dt: l.amax() * params.dt,
                    max_f_old: self.deformation_gradient[i]
                        .iter()
                        .fold(0.0, |m: f64, x| m.max(x.abs())),
                });
            }
        }
        failure
    }
}

/// Runs `f` on the particles `own` (every particle when `None`, see
/// [`StepParams::own`]) in chunks of [`STRESS_CHUNK`], in parallel;
/// returns the failure of the lowest index that any chunk reported. A
/// particle's update reads and writes only its own state, so which chunk
/// it falls in changes nothing of its bits.
fn for_each_chunk(
    particles: &mut Particles,
    bulk: &mut [BulkViscosityState],
    own: Option<(usize, usize)>,
    f: impl Fn(ParticleChunk) -> Option<ParticleFailure> + Sync + Send,
) -> Option<ParticleFailure> {
    const C: usize = STRESS_CHUNK;
    let n = particles.len();
    assert_eq!(bulk.len(), n, "one bulk-viscosity state per particle");
    let (lo, hi) = own.unwrap_or((0, n));
    assert!(lo <= hi && hi <= n, "particles {lo}..{hi} of {n}");
    let stride = particles.history_stride();
    let history = if stride > 0 {
        Either::Left(particles.history[lo * stride..hi * stride].par_chunks_mut(C * stride))
    } else {
        Either::Right(
            rayon::iter::repeat_n((), (hi - lo).div_ceil(C)).map(|()| -> &mut [f64] { &mut [] }),
        )
    };
    (
        particles.position[lo..hi].par_chunks_mut(C),
        particles.velocity[lo..hi].par_chunks_mut(C),
        particles.stress[lo..hi].par_chunks_mut(C),
        particles.deformation_gradient[lo..hi].par_chunks_mut(C),
        particles.volume[lo..hi].par_chunks_mut(C),
        particles.temperature[lo..hi].par_chunks_mut(C),
        particles.specific_internal_energy[lo..hi].par_chunks_mut(C),
        particles.failed[lo..hi].par_chunks_mut(C),
        history,
        particles.material[lo..hi].par_chunks(C),
        particles.mass[lo..hi].par_chunks(C),
        particles.initial_volume[lo..hi].par_chunks(C),
    )
        .into_par_iter()
        .zip(bulk[lo..hi].par_chunks_mut(C))
        .enumerate()
        .filter_map(
            |(
                k,
                (
                    (
                        position,
                        velocity,
                        stress,
                        f_,
                        volume,
                        t,
                        e,
                        failed,
                        history,
                        material,
                        mass,
                        v0,
                    ),
                    bulk,
                ),
            )| {
                f(ParticleChunk {
                    first: lo + k * C,
                    stride,
                    position,
                    velocity,
                    stress,
                    deformation_gradient: f_,
                    volume,
                    temperature: t,
                    specific_internal_energy: e,
                    failed,
                    history,
                    material,
                    mass,
                    initial_volume: v0,
                    bulk,
                })
            },
        )
        .min_by_key(|failure| failure.index)
}

/// The mutable state of one particle in the stress update.
pub struct ParticleState<'a> {
    /// σ_p, Voigt.
    pub stress: &'a mut [f64; 6],
    /// F_p, row-major.
    pub deformation_gradient: &'a mut [f64; 9],
    /// V_p, m³.
    pub volume: &'a mut f64,
    /// T_p, K.
    pub temperature: &'a mut f64,
    /// e_p, J/kg.
    pub specific_internal_energy: &'a mut f64,
    /// Failed flag.
    pub failed: &'a mut bool,
    /// History block (the set's stride; the model uses its first
    /// `history_len` values).
    pub history: &'a mut [f64],
    /// The bulk viscosity q contained in `stress` and its tr D.
    pub bulk_viscosity: &'a mut BulkViscosityState,
}

/// Largest entry of a fluid particle's isochoric deformation J^{−1/3} F
/// that is kept; beyond it F is re-initialised to J^{1/3} I (see
/// [`fluid_deformation_is_distorted`]).
pub const FLUID_DISTORTION_LIMIT: f64 = 100.0;

/// Whether a fluid particle's F has drifted so far from a pure volume
/// change that it should be re-initialised to J^{1/3} I: any entry of
/// J^{−1/3} F beyond [`FLUID_DISTORTION_LIMIT`] (then det F, a sum of
/// products up to 10⁶ times J, has lost six of its sixteen digits). A
/// fluid has no memory of shape: only J enters its stress, and only the
/// cpGIMP domain reads the rest of F, which for a fluid point sheared into
/// a filament no longer describes a region of the flow. Fluid MPM keeps
/// only the volumetric part of a fluid point's deformation (Stomakhin et
/// al. 2014, "Augmented MPM for phase-change and varied materials", ACM
/// TOG 33(4): F_E projected to J^{1/3} I every step; Hu et al. 2018,
/// "A moving least squares material point method", ACM TOG 37(4): J alone
/// for fluids); here the projection is made only past the limit, so that
/// cpGIMP keeps a fluid point's stretched domain while it means one. In one-dimensional
/// flows, F = diag(J, 1, 1), the limit is reached only at J < 10⁻⁶ or
/// J > 10³, so such runs keep their stretched cpGIMP domains.
pub fn fluid_deformation_is_distorted(f: &Mat3, j: f64) -> bool {
    deformation_beyond(f, j, FLUID_DISTORTION_LIMIT)
}

/// Largest entry of a solid particle's isochoric deformation J^{−1/3} F
/// below which its J is det F; beyond it J is carried by the product rule
/// (see [`solid_deformation_is_distorted`]).
pub const SOLID_DISTORTION_LIMIT: f64 = 1.0e4;

/// Whether a solid particle's F is so distorted that det F can no longer
/// be trusted: any entry of J^{−1/3} F beyond [`SOLID_DISTORTION_LIMIT`]
/// (det F is then a sum of products up to 10¹² times J, and has lost
/// twelve of its sixteen digits). Such a particle takes
/// J = det(I + L Δt) Jⁿ, the same quantity formed from a well-conditioned
/// matrix, as fluid points do; its F is kept (its shape, for cpGIMP and the
/// surface tractions). The constitutive updates read L and the density,
/// not F. A solid reaches the limit only where it has flowed like a fluid
/// (a burning explosive particle near the axis of the cook-off, sheared to
/// entries of 10⁸, docs/physics/mpm/explicit_mpm.md); below it J is det F
/// as before.
pub fn solid_deformation_is_distorted(f: &Mat3, j: f64) -> bool {
    deformation_beyond(f, j, SOLID_DISTORTION_LIMIT)
}

/// Whether any entry of J^{−1/3} F lies beyond `limit` (or is not finite).
#[inline]
fn deformation_beyond(f: &Mat3, j: f64, limit: f64) -> bool {
    // Every entry with |x|³ < (1 − 10⁻⁶) limit³ J lies below limit J^{1/3}
    // whatever the rounding of the cube, of the product and of `cbrt`
    // (each a few ulp), so the common undistorted point is settled without
    // the cube root; NaN, overflow, and J too small for the cubes to be
    // trusted (below 10⁻²⁰⁰) take the exact test.
    if j >= 1e-200 {
        let bound = (1.0 - 1e-6) * limit * limit * limit * j;
        if f.iter().all(|x| {
            let a = x.abs();
            a * a * a < bound
        }) {
            return false;
        }
    }
    let limit = limit * j.cbrt();
    f.iter().any(|x| !(x.abs() <= limit))
}

/// One particle's update over Δt from its velocity gradient L:
///
/// 1. F ← (I + L Δt) F; J = det F must be positive and finite (for a
///    fluid, J = det(I + L Δt) Vⁿ/V⁰, and F is re-initialised to J^{1/3} I
///    once its isochoric part is distorted, [`fluid_deformation_is_distorted`];
///    for a solid whose Fⁿ is distorted beyond
///    [`solid_deformation_is_distorted`]'s limit, the same J, F kept);
/// 2. V = J V⁰ and ρ = m/V = ρ₀/J (seed 001 eqs 12, 29);
/// 3. σ from [`Material::update_stress`] (the Jaumann rate of eq 30 or the
///    model's own objective rate) at the new density;
/// 4. specific internal energy from the stress power of eq 13,
///    Δe = Δt (σⁿ + σⁿ⁺¹)/2 : D / ρ^{n+½} with D = sym L and
///    ρ^{n+½} = 2m/(Vⁿ + Vⁿ⁺¹) — this already contains the plastic work, so
///    plastic heating enters the temperature only: T += ΔT, the increment
///    the elastic–plastic model (or a plugin model that heats itself)
///    reports ([`MaterialModel::temperature_increment`]);
/// 5. the failed flag from the update (irreversible).
///
/// With an artificial bulk viscosity ([`crate::viscosity`]) the stored
/// stress is σ − q I: the material's own stress σ minus the viscous
/// pressure q. The model is given σⁿ = σ_storedⁿ + qⁿ I, the new
/// qⁿ⁺¹ = q(tr D, ρⁿ⁺¹, c(ρⁿ⁺¹, eⁿ), l) is subtracted from its σⁿ⁺¹, and the
/// stress power of step 4 uses the stored (total) stresses, so the work of
/// q, Δt (qⁿ + qⁿ⁺¹)/2 |tr D| / ρ^{n+½}, heats the particle. A model that
/// tracks its temperature apart from e (the elastic–plastic one, a plugin
/// model with a temperature increment and a specific heat) also gets that
/// work as ΔT = w_q / c_v, or, where c_v follows the temperature, as the
/// rise whose heat is w_q (`MaterialModel::temperature_rise`).
///
/// Returns (J, reason) when the new state is not physical; the particle is
/// then left partly updated and the step must be abandoned.
#[allow(clippy::too_many_arguments)]
pub fn update_particle_stress(
    material: &MaterialModel,
    _id: MaterialId,
    state: ParticleState,
    l: &Mat3,
    mass: f64,
    initial_volume: f64,
    dt: f64,
    viscosity: Option<ViscosityParams>,
) -> Result<(), (f64, &'static str)> {
    let f_old = Mat3::from_row_slice(&state.deformation_gradient[..]);
    let increment = Mat3::identity() + l * dt;
    let mut f_new = increment * f_old;
    let v_old = *state.volume;
    let fluid = matches!(material, MaterialModel::Null(_));
    let j_old = v_old / initial_volume;
    let j = if fluid || solid_deformation_is_distorted(&f_old, j_old) {
        // A fluid's F has no elastic meaning and, in a vortical flow, its
        // isochoric part grows without bound; det F then comes from the
        // difference of products many orders of magnitude larger than
        // itself and loses every digit (E-PLATE: J = −0.2 from a step with
        // |L_ij Δt| < 0.007). J is carried instead by the product rule
        // det(F + L Δt F) = det(I + L Δt) · Jⁿ with Jⁿ = Vⁿ/V⁰, the
        // volume-only update of fluid material points. A solid whose F
        // has distorted as far takes the same rule.
        v_old / initial_volume * increment.determinant()
    } else {
        f_new.determinant()
    };
    if !(j > 0.0) || !j.is_finite() {
        return Err((j, FAILURE_REASONS[0]));
    }
    if fluid && fluid_deformation_is_distorted(&f_new, j) {
        f_new = Mat3::identity() * j.cbrt();
    }
    let v_new = j * initial_volume;
    let rho = mass / v_new;
    // The stored stress: the material's minus the viscous pressure.
    let sigma_old = crate::voigt_to_matrix(state.stress);
    let q_old = state.bulk_viscosity.q;
    let sigma_material_old = if q_old != 0.0 {
        sigma_old + Mat3::identity() * q_old
    } else {
        sigma_old
    };
    let hlen = material.history_len();
    let history = &mut state.history[..hlen];
    let update = material.update_stress(
        &StressUpdateInput {
            velocity_gradient: *l,
            dt,
            density: rho,
            temperature: *state.temperature,
            specific_internal_energy: *state.specific_internal_energy,
            stress: sigma_material_old,
        },
        history,
    );
    if update.stress.iter().any(|s| !s.is_finite()) {
        return Err((j, FAILURE_REASONS[1]));
    }
    let d = 0.5 * (l + l.transpose());
    let trace_d = d.trace();
    let q_new = match viscosity.and_then(|v| v.coefficients(fluid)) {
        Some((model, length)) => {
            let c = material.wave_speed(rho, *state.specific_internal_energy);
            model.pressure(trace_d, rho, c, length)
        }
        None => 0.0,
    };
    if !q_new.is_finite() {
        return Err((j, FAILURE_REASONS[2]));
    }
    let sigma_new = if q_new != 0.0 {
        update.stress - Mat3::identity() * q_new
    } else {
        update.stress
    };
    let power = 0.5 * (sigma_old + sigma_new).component_mul(&d).sum();
    let rho_mid = 2.0 * mass / (v_old + v_new);
    let e_new = *state.specific_internal_energy + dt * power / rho_mid;
    if !e_new.is_finite() {
        return Err((j, FAILURE_REASONS[3]));
    }
    if let (Some(d_temp), true) = (
        material.temperature_increment(history),
        material.carries_specific_heat(),
    ) {
        *state.temperature += d_temp;
        if q_old != 0.0 || q_new != 0.0 {
            let viscous_work = -dt * 0.5 * (q_old + q_new) * trace_d / rho_mid;
            if let Some(rise) = material.temperature_rise(*state.temperature, viscous_work) {
                *state.temperature += rise;
            }
        }
    }
    *state.specific_internal_energy = e_new;
    *state.stress = crate::matrix_to_voigt(&sigma_new);
    *state.bulk_viscosity = BulkViscosityState { q: q_new, trace_d };
    state
        .deformation_gradient
        .copy_from_slice(f_new.transpose().as_slice());
    *state.volume = v_new;
    *state.failed |= update.failed;
    Ok(())
}

#[cfg(test)]
mod tests;
