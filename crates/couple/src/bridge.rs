//! The exchanges of the bridge (seed 001 §3.2–3.4), one named function per
//! equation group, on plain values so that each can be tested alone:
//!
//! - MPM → FDM, the fictitious cells (eqs 31–36):
//!   [`fictitious_mass_momentum`], [`cell_internal_energy`],
//!   [`fictitious_cell_state`];
//! - FDM → MPM, the interface nodes (eqs 37–39): [`fdm_cell_as_particle`]
//!   and [`cell_node_contribution`];
//! - transport (eqs 40–51): [`interface_state`], [`interface_fluxes`],
//!   [`new_particle_count`], [`create_particles`], [`absorb_particle`].
//!
//! Choices the paper leaves open (docs/physics/couple/bridge.md):
//!
//! - Shape functions are the linear ones of eq 16, so N_Ic = 1/2^d at a
//!   cell centre for each of its 2^d corner nodes.
//! - New particles move with the interface velocity v_f of eq 41: their
//!   momentum is then exactly the momentum flux of eq 44
//!   (f_p = f_m v_f). Their density and pressure are the donor cell's
//!   (seed 001: "the same density, velocities and pressure as ... in the
//!   donor cell"), and their internal energy is eq 48.
//! - The count s of eq 45 is rounded up to a multiple of 4; the particles
//!   sit on a lattice of s/2^(d−1) layers along the normal, spread over
//!   the flux length d_1 = v_1 Δt of eq 47 (drifted tangentially by
//!   d_t = v_t Δt), times 2^(d−1) positions across the face, so that they
//!   fill the volume f_m/ρ the flux brought in.

use crate::regions::Side;

/// Weight N_Ic of each corner node at a cell centre for the linear shape
/// functions of seed 001 eq 16: 1/2^d for d active directions.
pub fn centre_weight(active_dims: usize) -> f64 {
    0.5f64.powi(active_dims as i32)
}

/// Seed 001 eqs 31–32: mass m_c = Σ_l m_l N_lc and momentum
/// p_c = Σ_l p_l N_lc of a fictitious cell from its corner nodes, all of
/// weight `weight` ([`centre_weight`]).
pub fn fictitious_mass_momentum(
    node_mass: &[f64],
    node_momentum: &[[f64; 3]],
    weight: f64,
) -> (f64, [f64; 3]) {
    let mut m = 0.0;
    let mut p = [0.0; 3];
    for (mass, mom) in node_mass.iter().zip(node_momentum) {
        m += weight * mass;
        for (a, b) in p.iter_mut().zip(mom) {
            *a += weight * b;
        }
    }
    (m, p)
}

/// Seed 001 eq 33: internal energy of a cell, Σ m_p e_p over the particles
/// in it (masses and specific internal energies), J.
pub fn cell_internal_energy(mass: &[f64], specific_energy: &[f64]) -> f64 {
    mass.iter().zip(specific_energy).map(|(m, e)| m * e).sum()
}

/// Seed 001 eqs 34–36: the conservative state (ρ, ρv, E) of a fictitious
/// cell of volume `volume` from its mass, momentum and internal energy.
/// `None` when the nodes carry no mass (the cell then keeps its own
/// state).
pub fn fictitious_cell_state(
    mass: f64,
    momentum: [f64; 3],
    internal_energy: f64,
    volume: f64,
) -> Option<[f64; 5]> {
    if !(mass > 0.0) {
        return None;
    }
    let rho = mass / volume;
    let v = momentum.map(|p| p / mass);
    let kinetic = 0.5 * mass * (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    Some([
        rho,
        rho * v[0],
        rho * v[1],
        rho * v[2],
        (internal_energy + kinetic) / volume,
    ])
}

/// What the particles of one MPM cell hold, for its fictitious cell
/// ([`fictitious_source`]): sums over the particles in the cell, the fluid
/// ones (air and products) apart from the structure's.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct CellParticles {
    /// Σ m_p of the fluid particles, kg.
    pub fluid_mass: f64,
    /// Σ m_p v_p of the fluid particles, kg·m/s.
    pub fluid_momentum: [f64; 3],
    /// Σ m_p e_p of the fluid particles (eq 33), J.
    pub fluid_energy: f64,
    /// Σ m_p of the products particles, kg.
    pub products_mass: f64,
    /// Σ m_p of the structure particles, kg.
    pub structure_mass: f64,
    /// Σ m_p v_p along the split axis of the structure particles, kg·m/s.
    pub structure_momentum: f64,
}

/// How a fictitious cell is set (docs/physics/couple/bridge.md,
/// "Fictitious cells without fluid, and next to a structure").
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum FictitiousSource {
    /// The MPM's state (ρ, ρv, E, ρY).
    Mpm([f64; 6]),
    /// No material in the MPM cell: the state of the cell inside it along
    /// the line normal to the interface (zero gradient, transmissive).
    ZeroGradient,
    /// Structure and no fluid in the MPM cell: a reflecting wall moving at
    /// this velocity along the split axis, m/s.
    Wall(f64),
}

/// The source of a fictitious cell from its MPM cell's particles `cell`
/// and, for eqs 31–32, the mass and momentum `nodal` of its corner nodes.
/// `structure_near`: a structure particle lies in the cell or one of its
/// 3^d neighbours, i.e. some corner node carries structure mass.
///
/// - Fluid in the cell, no structure near: eqs 31–36 (`nodal`, the fluid's
///   Σ m_p e_p), ρY = ρ · products share of the fluid mass — the paper's
///   rule.
/// - Fluid in the cell, structure near: the corner nodes' mass and momentum
///   are partly the structure's (one velocity field), which eqs 31–32
///   would hand to the gas; eqs 34–36 take the fluid particles' own sums
///   (mass, momentum, eq 33 energy) instead.
/// - No fluid, structure: a reflecting wall at the structure particles'
///   mean velocity along the axis.
/// - Neither (void, or gas particles that have left the cell): zero
///   gradient.
///
/// A cell whose nodes carry no mass (eqs 34–36 undefined) is zero
/// gradient too.
pub fn fictitious_source(
    cell: &CellParticles,
    structure_near: bool,
    nodal: (f64, [f64; 3]),
    volume: f64,
) -> FictitiousSource {
    let with_products = |u: [f64; 5], fluid: f64| {
        let y = cell.products_mass / fluid;
        FictitiousSource::Mpm([u[0], u[1], u[2], u[3], u[4], u[0] * y])
    };
    if cell.fluid_mass > 0.0 {
        let (m, p) = if structure_near {
            (cell.fluid_mass, cell.fluid_momentum)
        } else {
            nodal
        };
        match fictitious_cell_state(m, p, cell.fluid_energy, volume) {
            Some(u) => with_products(u, cell.fluid_mass),
            None => FictitiousSource::ZeroGradient,
        }
    } else if cell.structure_mass > 0.0 {
        FictitiousSource::Wall(cell.structure_momentum / cell.structure_mass)
    } else {
        FictitiousSource::ZeroGradient
    }
}

/// The mirror image of the conservative state `u` (ρ, ρv, E, ρY) in a wall
/// normal to `axis` moving at `wall_velocity` along it: v_a → 2w − v_a,
/// ρ, the tangential velocity, e and Y kept (the reflective boundary of
/// Toro, *Riemann Solvers and Numerical Methods for Fluid Dynamics*, 3rd
/// ed., §6.3.3, for a moving wall).
pub fn mirror_state(u: [f64; 6], axis: usize, wall_velocity: f64) -> [f64; 6] {
    let rho = u[0];
    let v = u[1 + axis] / rho;
    let w = 2.0 * wall_velocity - v;
    let mut out = u;
    out[1 + axis] = rho * w;
    out[4] = u[4] + 0.5 * rho * (w * w - v * v);
    out
}

/// The states of the fictitious cells of one line normal to the interface,
/// layer 0 (next to the FDM region) first, from their `sources` and the
/// FDM-region cells `inner` of the line (`inner[0]` the last one, next to
/// layer 0, `inner[1]` the one before, …): an MPM state as given; zero
/// gradient the state of the layer inside it (of `inner[0]` for layer 0);
/// from the first wall layer l₀ on, every layer l the mirror image
/// ([`mirror_state`]) of the cell at the same distance on the other side of
/// the wall's inner face (layer 2l₀ − 1 − l, or `inner[l − 2l₀]` past layer
/// 0; the deepest of `inner` where the line is shorter).
pub fn resolve_fictitious_line(
    inner: &[[f64; 6]],
    sources: &[FictitiousSource],
    axis: usize,
    out: &mut [[f64; 6]],
) {
    let mut wall: Option<(usize, f64)> = None;
    for l in 0..sources.len() {
        if wall.is_none() {
            if let FictitiousSource::Wall(w) = sources[l] {
                wall = Some((l, w));
            }
        }
        out[l] = match (wall, sources[l]) {
            (Some((l0, w)), _) => {
                let s = 2 * l0 as isize - 1 - l as isize;
                let image = if s >= 0 {
                    out[s as usize]
                } else {
                    inner[((-s - 1) as usize).min(inner.len() - 1)]
                };
                mirror_state(image, axis, w)
            }
            (None, FictitiousSource::Mpm(u)) => u,
            (None, _) => {
                if l == 0 {
                    inner[0]
                } else {
                    out[l - 1]
                }
            }
        };
    }
}

/// One side of the Riemann problem at the end of the FDM region: the
/// density, the velocity along the normal from the FDM region into the
/// MPM region, the pressure and the sound speed.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NormalState {
    /// Density, kg/m³.
    pub density: f64,
    /// Velocity along the normal into the MPM region, m/s.
    pub velocity: f64,
    /// Pressure, Pa.
    pub pressure: f64,
    /// Sound speed, m/s.
    pub sound_speed: f64,
}

/// Whether the fictitious cells must take the FDM region's own outflow
/// state rather than the MPM's (eqs 31–36): true when every wave of the
/// Riemann problem between the last FDM-region cell `fdm` and the MPM's
/// fictitious state `mpm` moves into the MPM region, so that nothing the
/// MPM holds can reach the FDM region (supersonic outflow; imposing the
/// MPM state there over-specifies the boundary of the FDM region). The
/// speed of the wave facing the FDM region is S = u − c q with the
/// pressure p* of the primitive-variable Riemann solver (Toro, *Riemann
/// Solvers and Numerical Methods for Fluid Dynamics*, 3rd ed., eq 9.20),
/// p* = ½(p_F + p_M) − ⅛(u_M − u_F)(ρ_F + ρ_M)(c_F + c_M) clipped at 0,
/// and q = √(1 + (γ + 1)/(2γ)(p*/p_F − 1)) for a shock (p* > p_F), 1 for
/// a rarefaction (eq 10.59), γ = ρ_F c_F²/p_F the FDM cell's isentropic
/// exponent. A state that is not physical (non-positive density, pressure
/// or sound speed, not finite) gives false: the paper's rule stands.
pub fn fdm_outflow_is_supersonic(fdm: &NormalState, mpm: &NormalState) -> bool {
    let ok = |s: &NormalState| {
        s.density > 0.0
            && s.pressure > 0.0
            && s.sound_speed > 0.0
            && s.density.is_finite()
            && s.pressure.is_finite()
            && s.sound_speed.is_finite()
            && s.velocity.is_finite()
    };
    if !(ok(fdm) && ok(mpm)) {
        return false;
    }
    let p_star = (0.5 * (fdm.pressure + mpm.pressure)
        - 0.125
            * (mpm.velocity - fdm.velocity)
            * (fdm.density + mpm.density)
            * (fdm.sound_speed + mpm.sound_speed))
        .max(0.0);
    let q = if p_star > fdm.pressure {
        let gamma = fdm.density * fdm.sound_speed * fdm.sound_speed / fdm.pressure;
        (1.0 + (gamma + 1.0) / (2.0 * gamma) * (p_star / fdm.pressure - 1.0)).sqrt()
    } else {
        1.0
    };
    fdm.velocity - fdm.sound_speed * q >= 0.0
}

/// An FDM cell centre acting as a particle in the P2G of the interface
/// nodes (seed 001 §3.3): mass ρ_c V_c, velocity v_c, volume V_c and
/// stress −p_c I, so that the particle sums of eqs 18, 19, 21 give the
/// second terms of eqs 37, 38, 39.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CellParticle {
    /// Cell centre, m.
    pub position: [f64; 3],
    /// ρ_c V_c, kg.
    pub mass: f64,
    /// v_c, m/s.
    pub velocity: [f64; 3],
    /// V_c, m³.
    pub volume: f64,
    /// −p_c I in Voigt order (xx, yy, zz, yz, xz, xy), Pa.
    pub stress: [f64; 6],
}

/// The FDM cell at `centre` with density, velocity and pressure as a
/// particle (seed 001 eqs 37–39).
pub fn fdm_cell_as_particle(
    centre: [f64; 3],
    density: f64,
    velocity: [f64; 3],
    pressure: f64,
    volume: f64,
) -> CellParticle {
    CellParticle {
        position: centre,
        mass: density * volume,
        velocity,
        volume,
        stress: [-pressure, -pressure, -pressure, 0.0, 0.0, 0.0],
    }
}

/// The second terms of seed 001 eqs 37–39 for one cell and one node:
/// (ρ_c N_Ic V_c, ρ_c V_c v_c N_Ic, N_Ic,i p_c V_c) with the linear shape
/// function of eq 16 of the node at `node` (grid spacing `spacing`,
/// directions `active`), evaluated at the cell centre. Zero when the node
/// is not a corner of the cell's element.
pub fn cell_node_contribution(
    cell: &CellParticle,
    node: [f64; 3],
    spacing: [f64; 3],
    active: [bool; 3],
) -> (f64, [f64; 3], [f64; 3]) {
    let mut n = 1.0;
    let mut factors = [1.0; 3];
    let mut slopes = [0.0; 3];
    for d in 0..3 {
        if !active[d] {
            continue;
        }
        let s = (cell.position[d] - node[d]) / spacing[d];
        if s.abs() >= 1.0 {
            return (0.0, [0.0; 3], [0.0; 3]);
        }
        factors[d] = 1.0 - s.abs();
        slopes[d] = -s.signum() / spacing[d];
        n *= factors[d];
    }
    let grad: [f64; 3] = std::array::from_fn(|i| {
        if !active[i] {
            return 0.0;
        }
        let mut g = slopes[i];
        for d in (0..3).filter(|&d| d != i) {
            g *= factors[d];
        }
        g
    });
    // f_I = −Σ N_I,j σ_ij V, with σ = −p I: N_I,i p V (eq 39).
    let p = -cell.stress[0];
    (
        n * cell.mass,
        cell.velocity.map(|v| n * cell.mass * v),
        grad.map(|g| g * p * cell.volume),
    )
}

/// A primitive state: density, velocity, pressure.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Primitive {
    /// Density, kg/m³.
    pub density: f64,
    /// Velocity, m/s.
    pub velocity: [f64; 3],
    /// Pressure, Pa.
    pub pressure: f64,
}

/// Seed 001 eqs 40–42: the interface state, the mean of the donor cell
/// and the first bridge cell.
pub fn interface_state(donor: &Primitive, bridge: &Primitive) -> Primitive {
    Primitive {
        density: 0.5 * (donor.density + bridge.density),
        velocity: std::array::from_fn(|i| 0.5 * (donor.velocity[i] + bridge.velocity[i])),
        pressure: 0.5 * (donor.pressure + bridge.pressure),
    }
}

/// Seed 001 eqs 43–44: mass flux f_m = ρ_f v_n A Δt and momentum flux
/// f_p = ρ_f v_f v_n A Δt into the MPM region through a face of area `area`
/// normal to `axis`, v_n the velocity component towards the MPM region
/// (`side`). Negative f_m: flow out of the MPM region.
pub fn interface_fluxes(
    face: &Primitive,
    axis: usize,
    side: Side,
    area: f64,
    dt: f64,
) -> (f64, [f64; 3]) {
    let vn = side.sign() * face.velocity[axis];
    let fm = face.density * vn * area * dt;
    (fm, face.velocity.map(|v| fm * v))
}

/// Seed 001 eq 45: s = ⌈f_m/m_e⌉, rounded up to a multiple of 4 (at least
/// 4 for f_m > 0; 0 otherwise).
pub fn new_particle_count(mass_flux: f64, existing_mass: f64) -> usize {
    if !(mass_flux > 0.0 && existing_mass > 0.0) {
        return 0;
    }
    let s = (mass_flux / existing_mass).ceil().max(1.0) as usize;
    s.div_ceil(4) * 4
}

/// A particle created by the transport.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NewParticle {
    /// Position, m.
    pub position: [f64; 3],
    /// m_p = f_m/s (eq 46), kg.
    pub mass: f64,
    /// v_f, m/s.
    pub velocity: [f64; 3],
    /// m_p/ρ_p, m³.
    pub volume: f64,
    /// Specific internal energy p_p/((γ − 1)ρ_p) (eq 48 per unit mass), J/kg.
    pub specific_internal_energy: f64,
}

/// Where and what the new particles of one interface face are.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FaceInflow {
    /// Centre of the interface face, m.
    pub face_centre: [f64; 3],
    /// Cell size, m.
    pub spacing: [f64; 3],
    /// Active directions.
    pub active: [bool; 3],
    /// Split axis.
    pub axis: usize,
    /// Side of the MPM region.
    pub side: Side,
    /// Interface state (eqs 40–42).
    pub face: Primitive,
    /// Donor-cell density and pressure of the new particles.
    pub donor: Primitive,
    /// Whether the grid is (r, z) (x = r): the particles are then rings,
    /// and those at the face's two radii share its f_m in proportion to
    /// their radii ([`create_particles`]).
    pub axisymmetric: bool,
    /// γ of the air (eq 48).
    pub gamma: f64,
    /// Mass of an existing particle m_e (eq 45), kg.
    pub existing_mass: f64,
    /// Time step, s.
    pub dt: f64,
}

/// Seed 001 eqs 45–48: the particles that carry the mass flux f_m > 0 and
/// momentum flux f_p of one face into the first bridge cell, appended to
/// `out`. Returns the number created (0 when f_m ≤ 0).
///
/// On an (r, z) grid (`inflow.axisymmetric`, x = r tangential to the face)
/// each particle is a ring: eq 46's equal shares m_p = f_m/s become shares
/// in proportion to the particles' radii, m_p = f_m/s · r_p/r̄ with r̄ the
/// mean radius of the layer's particles, so that every ring has the face's
/// density (V_p = m_p/ρ = 2π r_p A_p with one cross-section A_p) and the
/// layer's masses still sum to its share of f_m.
pub fn create_particles(inflow: &FaceInflow, mass_flux: f64, out: &mut Vec<NewParticle>) -> usize {
    let s = new_particle_count(mass_flux, inflow.existing_mass);
    if s == 0 {
        return 0;
    }
    let mass = mass_flux / s as f64;
    let rings = inflow.axisymmetric && inflow.axis != 0;
    let v = inflow.face.velocity;
    let rho = inflow.donor.density;
    let e = inflow.donor.pressure / ((inflow.gamma - 1.0) * rho);
    let a = inflow.axis;
    let tangential: Vec<usize> = (0..3).filter(|&d| d != a && inflow.active[d]).collect();
    let across = 1usize << tangential.len();
    let layers = s / across;
    // Eq 47: the furthest particle is v Δt from the face centre.
    let d: [f64; 3] = v.map(|x| x * inflow.dt);
    for l in 0..layers {
        let f = (l as f64 + 0.5) / layers as f64;
        let first = out.len();
        let mut radii = 0.0;
        for c in 0..across {
            let mut x = inflow.face_centre;
            x[a] += inflow.side.sign() * d[a].abs() * f;
            for (bit, &t) in tangential.iter().enumerate() {
                let off = if (c >> bit) & 1 == 0 { -0.25 } else { 0.25 };
                x[t] += off * inflow.spacing[t] + d[t] * f;
            }
            radii += x[0];
            out.push(NewParticle {
                position: x,
                mass,
                velocity: v,
                volume: mass / rho,
                specific_internal_energy: e,
            });
        }
        if rings && radii > 0.0 {
            let mean = radii / across as f64;
            for n in &mut out[first..] {
                n.mass = mass * (n.position[0] / mean);
                n.volume = n.mass / rho;
            }
        }
    }
    s
}

/// The state of a particle that takes a deposit of inflow.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Deposit {
    /// Mass, kg.
    pub mass: f64,
    /// Velocity, m/s.
    pub velocity: [f64; 3],
    /// Specific internal energy, J/kg.
    pub specific_internal_energy: f64,
    /// Volume, m³.
    pub volume: f64,
}

/// Adds inflow of mass `dm`, momentum `dp` and total energy `de`
/// (internal plus kinetic), arriving at density `rho`, to a particle
/// (the deposit rule of docs/physics/couple/bridge.md): mass and momentum
/// add, m' = m + dm, v' = (m v + dp)/m'; the total energy adds,
/// m'(e' + |v'|²/2) = m(e + |v|²/2) + de, so the kinetic energy the merged
/// velocity drops becomes internal energy (an inelastic merge, e' ≥ the
/// mass mean of e and the inflow's e); the volume grows by the inflow's
/// own, V' = V + dm/ρ.
pub fn deposit_into_particle(
    particle: Deposit,
    dm: f64,
    dp: [f64; 3],
    de: f64,
    rho: f64,
) -> Deposit {
    let m = particle.mass + dm;
    let v: [f64; 3] = std::array::from_fn(|d| (particle.mass * particle.velocity[d] + dp[d]) / m);
    let v0 = particle.velocity;
    let k0 = 0.5 * (v0[0] * v0[0] + v0[1] * v0[1] + v0[2] * v0[2]);
    let energy = particle.mass * (particle.specific_internal_energy + k0) + de;
    let k = 0.5 * (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    Deposit {
        mass: m,
        velocity: v,
        specific_internal_energy: energy / m - k,
        volume: particle.volume + dm / rho,
    }
}

/// Seed 001 eqs 49–51: adds a particle of mass `mass`, velocity `velocity`
/// and specific internal energy `specific_energy` leaving the MPM region
/// into the FDM cell `cell` = (ρ, ρu, ρv, ρw, E, ρY) of volume `volume`
/// (the particle is air: ρY is unchanged).
pub fn absorb_particle(
    cell: &mut [f64; 6],
    volume: f64,
    mass: f64,
    velocity: [f64; 3],
    specific_energy: f64,
) {
    let inv = 1.0 / volume;
    cell[0] += mass * inv;
    for d in 0..3 {
        cell[1 + d] += mass * velocity[d] * inv;
    }
    let v2 = velocity[0] * velocity[0] + velocity[1] * velocity[1] + velocity[2] * velocity[2];
    cell[4] += mass * (specific_energy + 0.5 * v2) * inv;
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    #[test]
    fn fictitious_cell_of_a_2d_element_is_hand_computed() {
        // Four corner nodes of a 2D element, N = 1/4 each.
        let w = centre_weight(2);
        assert_eq!(w, 0.25);
        let (m, p) = fictitious_mass_momentum(
            &[1.0, 2.0, 3.0, 2.0],
            &[
                [4.0, 0.0, 0.0],
                [0.0, 8.0, 0.0],
                [4.0, 4.0, 0.0],
                [0.0, 0.0, 0.0],
            ],
            w,
        );
        assert_eq!((m, p), (2.0, [2.0, 3.0, 0.0]));
        let e = cell_internal_energy(&[0.5, 1.5], &[2.0, 4.0]);
        assert_eq!(e, 7.0);
        // V = 0.5: ρ = 4, ρv = (4, 6, 0), E = (7 + ½·2·(1 + 2.25))/0.5 = 20.5.
        let u = fictitious_cell_state(m, p, e, 0.5).unwrap();
        assert_eq!(u, [4.0, 4.0, 6.0, 0.0, 20.5]);
        assert_eq!(fictitious_cell_state(0.0, [0.0; 3], 1.0, 1.0), None);
    }

    #[test]
    fn fictitious_sources_follow_what_the_mpm_cell_holds() {
        // Air and products particles: Σm = 2, Σmv = (4, 0, −2), Σme = 6,
        // products 0.5; the nodes give m = 4, p = (8, 0, 0). V = 0.5.
        let full = CellParticles {
            fluid_mass: 2.0,
            fluid_momentum: [4.0, 0.0, -2.0],
            fluid_energy: 6.0,
            products_mass: 0.5,
            ..Default::default()
        };
        let nodal = (4.0, [8.0, 0.0, 0.0]);
        // Away from a structure, eqs 31–36: ρ = 8, ρv = (16, 0, 0),
        // E = (6 + ½·4·4)/0.5 = 28, ρY = 8 · 0.25 = 2.
        assert_eq!(
            fictitious_source(&full, false, nodal, 0.5),
            FictitiousSource::Mpm([8.0, 16.0, 0.0, 0.0, 28.0, 2.0])
        );
        // Next to one, the particles' own sums: ρ = 4, v = (2, 0, −1),
        // E = (6 + ½·2·5)/0.5 = 22, ρY = 1.
        let near = CellParticles {
            structure_mass: 30.0,
            ..full
        };
        assert_eq!(
            fictitious_source(&near, true, nodal, 0.5),
            FictitiousSource::Mpm([4.0, 8.0, 0.0, -4.0, 22.0, 1.0])
        );
        // Only structure: a wall at its mean velocity 90/30 = 3 m/s.
        let steel = CellParticles {
            structure_mass: 30.0,
            structure_momentum: 90.0,
            ..Default::default()
        };
        assert_eq!(
            fictitious_source(&steel, true, nodal, 0.5),
            FictitiousSource::Wall(3.0)
        );
        // Nothing in the cell (its nodes may carry the neighbours' mass),
        // or fluid whose nodes carry none: zero gradient.
        let empty = CellParticles::default();
        assert_eq!(
            fictitious_source(&empty, false, nodal, 0.5),
            FictitiousSource::ZeroGradient
        );
        assert_eq!(
            fictitious_source(&full, false, (0.0, [0.0; 3]), 0.5),
            FictitiousSource::ZeroGradient
        );
    }

    #[test]
    fn a_mirror_state_reverses_the_normal_velocity_about_the_wall() {
        // ρ = 2, v = (3, 4, −5), E = 100, ρY = 1; wall along z at 1 m/s:
        // v_z → 2 − (−5) = 7, E → 100 + ½·2·(49 − 25) = 124.
        let u = [2.0, 6.0, 8.0, -10.0, 100.0, 1.0];
        assert_eq!(mirror_state(u, 2, 1.0), [2.0, 6.0, 8.0, 14.0, 124.0, 1.0]);
        // A wall at rest: v_x → −3, E unchanged.
        assert_eq!(mirror_state(u, 0, 0.0), [2.0, -6.0, 8.0, -10.0, 100.0, 1.0]);
    }

    #[test]
    fn fictitious_lines_resolve_layer_by_layer() {
        let cell = |x: f64| [x, 2.0 * x, 0.0, 0.0, 10.0 * x, 0.0];
        let inner = [cell(1.0), cell(2.0)];
        let (a, b) = (cell(5.0), cell(7.0));
        let mut out = [[0.0; 6]; 4];
        use FictitiousSource::{Mpm, Wall, ZeroGradient as Zg};
        // Zero gradient copies the layer inside it, or the last FDM cell.
        resolve_fictitious_line(&inner, &[Zg, Mpm(a), Zg, Zg], 0, &mut out);
        assert_eq!(out, [inner[0], a, a, a]);
        resolve_fictitious_line(&inner, &[Mpm(a), Mpm(b), Zg, Mpm(a)], 0, &mut out);
        assert_eq!(out, [a, b, b, a]);
        // A wall at layer 1 mirrors layer 0, then the FDM cells, whatever
        // the layers past it hold.
        resolve_fictitious_line(&inner, &[Mpm(a), Wall(0.5), Mpm(b), Zg], 0, &mut out);
        assert_eq!(
            out,
            [
                a,
                mirror_state(a, 0, 0.5),
                mirror_state(inner[0], 0, 0.5),
                mirror_state(inner[1], 0, 0.5)
            ]
        );
        // A wall at layer 0 past a line of two FDM cells: the deepest
        // repeats.
        resolve_fictitious_line(&inner, &[Wall(0.0), Zg, Mpm(a), Mpm(b)], 0, &mut out);
        let m = |u| mirror_state(u, 0, 0.0);
        assert_eq!(out, [m(inner[0]), m(inner[1]), m(inner[1]), m(inner[1])]);
    }

    proptest! {
        #[test]
        fn a_mirror_state_keeps_density_and_internal_energy(
            rho in 0.01f64..1.0e3,
            v in proptest::array::uniform3(-3.0e3f64..3.0e3),
            e in 1.0e3f64..1.0e7,
            w in -1.0e3f64..1.0e3,
            axis in 0usize..3,
        ) {
            let ke = 0.5 * rho * (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
            let u = [rho, rho * v[0], rho * v[1], rho * v[2], rho * e + ke, 0.3 * rho];
            let m = mirror_state(u, axis, w);
            prop_assert_eq!(m[0], rho);
            prop_assert_eq!(m[5], u[5]);
            let vm = [m[1] / rho, m[2] / rho, m[3] / rho];
            let em = (m[4] - 0.5 * rho * (vm[0] * vm[0] + vm[1] * vm[1] + vm[2] * vm[2])) / rho;
            prop_assert!((em - e).abs() <= 1e-9 * (e + (ke / rho)));
            prop_assert!((vm[axis] + v[axis] - 2.0 * w).abs() <= 1e-9 * (1.0 + v[axis].abs() + w.abs()));
        }
    }

    #[test]
    fn supersonic_outflow_ignores_a_downstream_state_it_cannot_feel() {
        // Products at Mach 5.8 leaving the FDM region into ambient air:
        // PVRS p* = ½(3e6 + 1e5) − ⅛(0 − 2900)(17 + 1.2)(500 + 340)
        // = 1.55e6 + 5.5419e6 = 7.0919e6 > p_F; γ = 17·500²/3e6 = 1.41667,
        // q = √(1 + 0.85294·(p*/3e6 − 1)) = 1.47084, S = 2900 − 735 > 0:
        // the FDM keeps its own outflow.
        let fdm = NormalState {
            density: 17.0,
            velocity: 2900.0,
            pressure: 3.0e6,
            sound_speed: 500.0,
        };
        let ambient = NormalState {
            density: 1.2,
            velocity: 0.0,
            pressure: 1.0e5,
            sound_speed: 340.0,
        };
        assert!(fdm_outflow_is_supersonic(&fdm, &ambient));
        // A shock reflected by a wall (u = 0, p = 1e8) faces it: p* =
        // 5.15e7 + 0.125·2900·217·1500 = 1.6949e8, q = √(1 + 0.85294·55.50)
        // = 6.9524, S = 2900 − 3476 < 0: the MPM's state is imposed.
        let reflected = NormalState {
            density: 200.0,
            velocity: 0.0,
            pressure: 1.0e8,
            sound_speed: 1000.0,
        };
        assert!(!fdm_outflow_is_supersonic(&fdm, &reflected));
        // The same stream as both states: S = u − c = 2400 > 0.
        assert!(fdm_outflow_is_supersonic(&fdm, &fdm));
        // Subsonic outflow (u < c) and inflow: the paper's rule.
        let slow = NormalState {
            velocity: 499.0,
            ..fdm
        };
        assert!(!fdm_outflow_is_supersonic(&slow, &slow));
        let back = NormalState {
            velocity: -2900.0,
            ..fdm
        };
        assert!(!fdm_outflow_is_supersonic(&back, &ambient));
        // Exactly sonic with equal states: S = 0 counts as outflow.
        let sonic = NormalState {
            velocity: 500.0,
            ..fdm
        };
        assert!(fdm_outflow_is_supersonic(&sonic, &sonic));
        // A non-physical MPM state leaves the paper's rule in place.
        let empty = NormalState {
            pressure: 0.0,
            ..ambient
        };
        assert!(!fdm_outflow_is_supersonic(&fdm, &empty));
        let nan = NormalState {
            sound_speed: f64::NAN,
            ..ambient
        };
        assert!(!fdm_outflow_is_supersonic(&fdm, &nan));
    }

    #[test]
    fn a_cell_centre_pushes_its_interface_node_with_p_v_over_h() {
        // 1D, h = 2: the cell [0, 2] has its centre at 1; its right node at
        // 2 (the interface) gets N = 1/2 and N,x = +1/2: mass ρV/2,
        // momentum ρVv/2 and force p V/2 along +x, into the MPM region.
        let c = fdm_cell_as_particle([1.0, 0.5, 0.5], 3.0, [10.0, 0.0, 0.0], 8.0, 2.0);
        assert_eq!(c.mass, 6.0);
        let active = [true, false, false];
        let (m, p, f) = cell_node_contribution(&c, [2.0, 0.0, 0.0], [2.0, 1.0, 1.0], active);
        assert_eq!(m, 3.0);
        assert_eq!(p, [30.0, 0.0, 0.0]);
        assert_eq!(f, [8.0, 0.0, 0.0]);
        // The left node is pushed the other way; a far node gets nothing.
        let (_, _, f) = cell_node_contribution(&c, [0.0; 3], [2.0, 1.0, 1.0], active);
        assert_eq!(f, [-8.0, 0.0, 0.0]);
        let far = cell_node_contribution(&c, [4.0, 0.0, 0.0], [2.0, 1.0, 1.0], active);
        assert_eq!(far, (0.0, [0.0; 3], [0.0; 3]));
        // 2D, corner (2, 2) of [0, 2]²: N = 1/4, N,x = N,y = (1/h)(1/2) = 1/4,
        // f = ∇N p V = (4, 4).
        let c = fdm_cell_as_particle([1.0, 1.0, 0.5], 1.0, [0.0; 3], 8.0, 2.0);
        let (m, _, f) =
            cell_node_contribution(&c, [2.0, 2.0, 0.0], [2.0, 2.0, 1.0], [true, true, false]);
        assert_eq!(m, 0.5);
        assert_eq!(f, [4.0, 4.0, 0.0]);
    }

    #[test]
    fn interface_state_and_fluxes_are_eqs_40_to_44() {
        let a = Primitive {
            density: 2.0,
            velocity: [100.0, 20.0, 0.0],
            pressure: 3.0e5,
        };
        let b = Primitive {
            density: 1.0,
            velocity: [50.0, 0.0, 0.0],
            pressure: 1.0e5,
        };
        let f = interface_state(&a, &b);
        assert_eq!(f.density, 1.5);
        assert_eq!(f.velocity, [75.0, 10.0, 0.0]);
        assert_eq!(f.pressure, 2.0e5);
        // f_m = 1.5 · 75 · 4e-6 · 1e-6 = 4.5e-10 kg.
        let (fm, fp) = interface_fluxes(&f, 0, Side::High, 4e-6, 1e-6);
        assert!((fm - 4.5e-10).abs() < 1e-24);
        assert_eq!(fp, [fm * 75.0, fm * 10.0, 0.0]);
        // The same face with the MPM region on the low side: outflow.
        let (fm_low, _) = interface_fluxes(&f, 0, Side::Low, 4e-6, 1e-6);
        assert_eq!(fm_low, -fm);
    }

    #[test]
    fn particle_count_is_a_multiple_of_four() {
        assert_eq!(new_particle_count(1.0, 1.0), 4);
        assert_eq!(new_particle_count(4.0, 1.0), 4);
        assert_eq!(new_particle_count(4.01, 1.0), 8);
        assert_eq!(new_particle_count(0.01, 1.0), 4);
        assert_eq!(new_particle_count(-1.0, 1.0), 0);
        assert_eq!(new_particle_count(0.0, 1.0), 0);
    }

    fn inflow(v: [f64; 3], active: [bool; 3]) -> FaceInflow {
        FaceInflow {
            face_centre: [0.11, 0.251, 0.001],
            spacing: [0.002, 0.002, 0.002],
            active,
            axis: 0,
            side: Side::High,
            face: Primitive {
                density: 1.5,
                velocity: v,
                pressure: 2.0e5,
            },
            donor: Primitive {
                density: 2.0,
                velocity: v,
                pressure: 3.0e5,
            },
            axisymmetric: false,
            gamma: 1.4,
            existing_mass: 1.0e-9,
            dt: 1.0e-6,
        }
    }

    #[test]
    fn new_particles_fill_the_flux_volume_inside_the_bridge_cell() {
        let f = inflow([200.0, -40.0, 0.0], [true, true, false]);
        let (fm, _) = interface_fluxes(&f.face, 0, Side::High, 0.002 * 0.002, f.dt);
        // f_m = 1.5 · 200 · 4e-6 · 1e-6 = 1.2e-9: s = ⌈1.2⌉ = 2 → 4.
        let mut out = Vec::new();
        assert_eq!(create_particles(&f, fm, &mut out), 4);
        // 2D: 2 across the face × 2 layers over d_1 = 0.2 mm.
        let xs: Vec<f64> = out.iter().map(|p| p.position[0] - 0.11).collect();
        for (x, want) in xs.iter().zip([0.05e-3, 0.05e-3, 0.15e-3, 0.15e-3]) {
            assert!((x - want).abs() < 1e-15, "{x} vs {want}");
        }
        // Across: ±h/4 about the face centre plus the drift v_y Δt f.
        assert!((out[0].position[1] - (0.251 - 0.0005 - 40e-6 * 0.25)).abs() < 1e-15);
        assert!((out[1].position[1] - (0.251 + 0.0005 - 40e-6 * 0.25)).abs() < 1e-15);
        // e = p/((γ − 1)ρ) of the donor: 3e5/(0.4 · 2).
        assert!((out[0].specific_internal_energy - 3.75e5).abs() < 1e-9);
        assert!((out[0].volume - fm / 4.0 / 2.0).abs() < 1e-25);
    }

    #[test]
    fn a_deposit_is_hand_computed() {
        // m = 2 at v = (3, 0, 0), e = 5, V = 1; inflow dm = 2 with momentum
        // (2, 4, 0) and total energy 10 at ρ = 4.
        // m' = 4, v' = ((6, 0, 0) + (2, 4, 0))/4 = (2, 1, 0);
        // energy 2(5 + 4.5) + 10 = 29, e' = 29/4 − ½(4 + 1) = 4.75;
        // V' = 1 + 2/4 = 1.5.
        let d = deposit_into_particle(
            Deposit {
                mass: 2.0,
                velocity: [3.0, 0.0, 0.0],
                specific_internal_energy: 5.0,
                volume: 1.0,
            },
            2.0,
            [2.0, 4.0, 0.0],
            10.0,
            4.0,
        );
        assert_eq!(
            d,
            Deposit {
                mass: 4.0,
                velocity: [2.0, 1.0, 0.0],
                specific_internal_energy: 4.75,
                volume: 1.5,
            }
        );
    }

    proptest! {
        /// A deposit adds exactly the inflow's mass, momentum and total
        /// energy to the particle's, and the merge only heats it: e' is at
        /// least the mass mean of the two specific internal energies.
        #[test]
        fn a_deposit_conserves_mass_momentum_and_energy(
            m in 1e-9f64..1e-5, v in prop::array::uniform3(-3000.0f64..3000.0),
            e in 1e4f64..1e7, vol in 1e-10f64..1e-8,
            dm in 1e-12f64..1e-5, u in prop::array::uniform3(-3000.0f64..3000.0),
            ei in 1e4f64..1e7, rho in 0.1f64..100.0,
        ) {
            let dp = u.map(|x| dm * x);
            let de = dm * (ei + 0.5 * (u[0] * u[0] + u[1] * u[1] + u[2] * u[2]));
            let before = Deposit { mass: m, velocity: v, specific_internal_energy: e, volume: vol };
            let d = deposit_into_particle(before, dm, dp, de, rho);
            let ke = |q: &Deposit| 0.5 * q.mass * q.velocity.iter().map(|x| x * x).sum::<f64>();
            let total = |q: &Deposit| q.mass * q.specific_internal_energy + ke(q);
            prop_assert!((d.mass - (m + dm)).abs() <= 1e-15 * d.mass);
            for k in 0..3 {
                let want = m * v[k] + dp[k];
                let scale = m * v[k].abs() + dp[k].abs() + 1e-30;
                prop_assert!((d.mass * d.velocity[k] - want).abs() <= 1e-14 * scale);
            }
            let want = total(&before) + de;
            prop_assert!((total(&d) - want).abs() <= 1e-12 * want, "{} vs {}", total(&d), want);
            let mean = (m * e + dm * ei) / (m + dm);
            prop_assert!(d.specific_internal_energy >= mean * (1.0 - 1e-9));
            prop_assert!((d.volume - (vol + dm / rho)).abs() <= 1e-15 * d.volume);
        }

        #[test]
        fn created_particles_carry_exactly_the_fluxes(
            rho in 0.1f64..10.0, vn in 1.0f64..800.0, vt in -300.0f64..300.0,
            p in 1e4f64..1e7, me in 1e-11f64..1e-8, dt in 1e-8f64..2e-6,
            three_d in any::<bool>(),
        ) {
            let active = [true, true, three_d];
            let mut f = inflow([vn, vt, 0.5 * vt], active);
            f.face.density = rho;
            f.donor.pressure = p;
            f.existing_mass = me;
            f.dt = dt;
            let (fm, fp) = interface_fluxes(&f.face, 0, Side::High, 4e-6, dt);
            let mut out = Vec::new();
            let s = create_particles(&f, fm, &mut out);
            prop_assert_eq!(s % 4, 0);
            prop_assert_eq!(out.len(), s);
            let m: f64 = out.iter().map(|q| q.mass).sum();
            prop_assert!((m - fm).abs() <= 4.0 * f64::EPSILON * s as f64 * fm);
            for (i, fpi) in fp.iter().enumerate() {
                let pi: f64 = out.iter().map(|q| q.mass * q.velocity[i]).sum();
                prop_assert!((pi - fpi).abs() <= 8.0 * f64::EPSILON * s as f64 * fm * vn.max(vt.abs()));
            }
            // Energy: internal (eq 48, linear in mass) plus kinetic.
            let e: f64 = out.iter().map(|q| q.mass * (q.specific_internal_energy
                + 0.5 * (q.velocity[0].powi(2) + q.velocity[1].powi(2) + q.velocity[2].powi(2)))).sum();
            let v2 = vn * vn + vt * vt + 0.25 * vt * vt;
            let want = fm * (p / ((f.gamma - 1.0) * f.donor.density) + 0.5 * v2);
            prop_assert!((e - want).abs() <= 16.0 * f64::EPSILON * s as f64 * want);
            // Every particle inside the first bridge cell.
            for q in &out {
                prop_assert!(q.position[0] > 0.11 && q.position[0] < 0.112);
            }
        }

        #[test]
        fn absorbing_a_particle_conserves_the_cell_plus_particle(
            rho in 0.1f64..10.0, u in -500.0f64..500.0, e in 1e4f64..1e7,
            m in 1e-12f64..1e-8, vx in -500.0f64..500.0, vy in -500.0f64..500.0, ep in 1e4f64..1e7,
        ) {
            let vol = 8e-9;
            let mut cell = [rho, rho * u, 0.0, 0.0, rho * (e + 0.5 * u * u), 0.3 * rho];
            let before = cell.map(|x| x * vol);
            absorb_particle(&mut cell, vol, m, [vx, vy, 0.0], ep);
            let after = cell.map(|x| x * vol);
            let tol = |x: f64| 4.0 * f64::EPSILON * x.abs().max(1e-30);
            prop_assert!((after[0] - before[0] - m).abs() <= tol(after[0]));
            prop_assert!((after[1] - before[1] - m * vx).abs() <= tol(after[1].abs() + (m * vx).abs()));
            prop_assert!((after[2] - before[2] - m * vy).abs() <= tol(after[2].abs() + (m * vy).abs()));
            let ek = m * (ep + 0.5 * (vx * vx + vy * vy));
            prop_assert!((after[4] - before[4] - ek).abs() <= tol(after[4]));
            prop_assert_eq!(after[5], before[5]);
        }
    }
}
