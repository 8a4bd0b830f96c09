//! The transfers of heat conduction ([`crate::conduction`]): the same
//! deterministic coloured scatter and storage-order gather as the
//! momentum transfers of the parent module, over the particles' heat
//! capacity, temperature and temperature gradient.
//!
//! - [`p2g_heat_capacity`]: C_I = Σ_p N_Ip m_p c_p and
//!   H_I = Σ_p N_Ip m_p c_p T_p (one coloured scatter), c_p = c_v(T_p);
//! - [`p2g_heat_flux`]: per particle the gradient ∇T_p = Σ_I (T_I − T_p)
//!   ∇N_Ip, gathered and used at once to scatter the internal heat rate
//!   q_I = −Σ_p V_p k_p ∇T_p · ∇N_Ip (one coloured gather–scatter);
//! - [`g2p_temperature_rate`]: T_p += Δt Σ_I N_Ip Ṫ_I, or through the heat
//!   H(T) for a c_v(T) (storage order);
//! - [`g2p_node_values`]: a node field per material gathered to its
//!   particles, Σ_I N_Ip f_I (storage order; the coupled ICE–MPM step's
//!   temperature change through the nodes).
//!
//! A node receives its contributions in the fixed order of the colouring,
//! so the sums are the same bits for any thread count.

use super::{
    check_footprint, dispatch, zero, GridMap, ParticleBins, SharedSlice, StencilPass,
    PARTICLES_PER_TASK,
};
use crate::conduction::ThermalProperties;
use crate::MaterialId;
use brisance_constitutive::SpecificHeat;
use rayon::prelude::*;

/// The particle quantities the heat transfers read.
#[derive(Debug, Clone, Copy)]
pub struct HeatParticles<'a> {
    /// Positions x_p, m.
    pub position: &'a [[f64; 3]],
    /// Masses m_p, kg (the rings' on an axisymmetric grid).
    pub mass: &'a [f64],
    /// Volumes V_p, m³ (the rings' on an axisymmetric grid).
    pub volume: &'a [f64],
    /// Temperatures T_p, K.
    pub temperature: &'a [f64],
    /// Material of each particle.
    pub material: &'a [MaterialId],
    /// Conductivity and specific heat per material, indexed by
    /// [`MaterialId`].
    pub properties: &'a [ThermalProperties],
}

/// The node sums of [`p2g_heat_capacity`], one value per node each.
pub struct HeatNodeSums<'a> {
    /// C_I = Σ_p N_Ip m_p c_p, J/K.
    pub capacity: &'a mut [f64],
    /// H_I = Σ_p N_Ip m_p c_p T_p, J.
    pub heat: &'a mut [f64],
}

/// Coloured scatter of the nodal heat capacity and heat (zeroed first):
/// C_I = Σ N_Ip m_p c_p and H_I = Σ N_Ip m_p c_p T_p, so
/// that T_I = H_I / C_I is the heat-capacity-weighted mean of the
/// particles' temperatures (the mass-weighted one for one material).
pub fn p2g_heat_capacity(
    map: &GridMap,
    bins: &ParticleBins,
    particles: HeatParticles,
    sums: HeatNodeSums,
) {
    zero(sums.capacity, 0.0);
    zero(sums.heat, 0.0);
    dispatch(
        map,
        Capacity {
            map,
            bins,
            particles,
            capacity: SharedSlice::new(sums.capacity),
            heat: SharedSlice::new(sums.heat),
        },
    );
}

struct Capacity<'a> {
    map: &'a GridMap,
    bins: &'a ParticleBins,
    particles: HeatParticles<'a>,
    capacity: SharedSlice<'a, f64>,
    heat: SharedSlice<'a, f64>,
}

impl StencilPass for Capacity<'_> {
    fn run<const NX: usize, const NY: usize, const NZ: usize>(self) {
        let Self {
            map,
            bins,
            particles: ps,
            capacity,
            heat,
        } = self;
        bins.for_each_coloured(|block, p| {
            let s = map.stencil::<NX, NY, NZ>(ps.position[p], bins.half_width(p));
            check_footprint(map, s.offset, block);
            let c = ps.properties[ps.material[p].0 as usize]
                .specific_heat
                .smoothed_at(ps.temperature[p]);
            let mc = ps.mass[p] * c;
            let mct = mc * ps.temperature[p];
            for c in 0..NZ {
                for b in 0..NY {
                    let row = s.row(b, c);
                    let start = map.row_start(s.base, b, c);
                    // SAFETY: the stencil lies in its block's footprint
                    // (checked above) and blocks of one colour touch
                    // disjoint nodes.
                    let (cr, hr) = unsafe { (capacity.range(start, NX), heat.range(start, NX)) };
                    for a in 0..NX {
                        let w = row.weight(s.x.w[a]);
                        cr[a] += w * mc;
                        hr[a] += w * mct;
                    }
                }
            }
        });
    }
}

/// Coloured gather–scatter of the internal heat rate (zeroed first): for
/// each particle of nonzero conductivity, ∇T_p = Σ_I (T_I − T_p) ∇N_Ip over
/// the nodes of positive capacity (equal to Σ_I T_I ∇N_Ip, since
/// Σ_I ∇N_Ip = 0, wherever every node of the stencil has capacity), then
/// q_I −= V_p k_p ∇T_p · ∇N_Ip on every node of the stencil, W.
/// `node_temperature` is T_I and `capacity` C_I.
pub fn p2g_heat_flux(
    map: &GridMap,
    bins: &ParticleBins,
    particles: HeatParticles,
    node_temperature: &[f64],
    capacity: &[f64],
    flux: &mut [f64],
) {
    zero(flux, 0.0);
    dispatch(
        map,
        Flux {
            map,
            bins,
            particles,
            node_temperature,
            capacity,
            flux: SharedSlice::new(flux),
        },
    );
}

struct Flux<'a> {
    map: &'a GridMap,
    bins: &'a ParticleBins,
    particles: HeatParticles<'a>,
    node_temperature: &'a [f64],
    capacity: &'a [f64],
    flux: SharedSlice<'a, f64>,
}

impl StencilPass for Flux<'_> {
    fn run<const NX: usize, const NY: usize, const NZ: usize>(self) {
        let Self {
            map,
            bins,
            particles: ps,
            node_temperature,
            capacity,
            flux,
        } = self;
        bins.for_each_coloured(|block, p| {
            let k = ps.properties[ps.material[p].0 as usize].conductivity;
            if k == 0.0 {
                return;
            }
            let s = map.stencil::<NX, NY, NZ>(ps.position[p], bins.half_width(p));
            check_footprint(map, s.offset, block);
            let tp = ps.temperature[p];
            let mut grad = [0.0; 3];
            for c in 0..NZ {
                for b in 0..NY {
                    let row = s.row(b, c);
                    let start = map.row_start(s.base, b, c);
                    let tr = &node_temperature[start..start + NX];
                    let cr = &capacity[start..start + NX];
                    for a in 0..NX {
                        if cr[a] > 0.0 {
                            let (_, g) = row.node(s.x.w[a], s.x.g[a]);
                            let dt = tr[a] - tp;
                            for d in 0..3 {
                                grad[d] += dt * g[d];
                            }
                        }
                    }
                }
            }
            // V_p k_p ∇T_p: the heat flux −k ∇T times the particle's volume.
            let vk = ps.volume[p] * k;
            let flow = [vk * grad[0], vk * grad[1], vk * grad[2]];
            for c in 0..NZ {
                for b in 0..NY {
                    let row = s.row(b, c);
                    let start = map.row_start(s.base, b, c);
                    // SAFETY: as in the capacity pass.
                    let qr = unsafe { flux.range(start, NX) };
                    for ((&wx, &gx), q) in s.x.w.iter().zip(&s.x.g).zip(qr) {
                        let (_, g) = row.node(wx, gx);
                        *q -= flow[0] * g[0] + flow[1] * g[1] + flow[2] * g[2];
                    }
                }
            }
        });
    }
}

/// The temperature update over the particles in storage order, in
/// parallel, each particle writing only itself: T_p += Δt Σ_I N_Ip Ṫ_I
/// for the particles of a material with a heat capacity (c_p > 0), with
/// the weights of the positions `position`; `rate` is Ṫ_I, K/s. For a
/// c_v(T) the particle takes the heat q_p = c_v(T_p) Δt Σ_I N_Ip Ṫ_I
/// (J/kg, the c_v of [`p2g_heat_capacity`]) and moves to the T' with
/// H(T') − H(T_p) = q_p.
#[allow(clippy::too_many_arguments)]
pub fn g2p_temperature_rate(
    map: &GridMap,
    bins: &ParticleBins,
    position: &[[f64; 3]],
    material: &[MaterialId],
    properties: &[ThermalProperties],
    rate: &[f64],
    dt: f64,
    temperature: &mut [f64],
) {
    let chunk = PARTICLES_PER_TASK;
    temperature
        .par_chunks_mut(chunk)
        .enumerate()
        .for_each(|(k, t)| {
            dispatch(
                map,
                TemperatureRange {
                    map,
                    bins,
                    first: k * chunk,
                    position,
                    material,
                    properties,
                    rate,
                    dt,
                    temperature: t,
                },
            )
        });
}

/// Storage-order gather of a node field per material: each particle's
/// `out[p] = Σ_I N_Ip f_I` with `f` the block of `node_values` for its
/// material (material m's values at `m · nodes .. (m + 1) · nodes`, node
/// storage order). With the particles at the positions the nodes' mass was
/// scattered from, Σ_p m_p out_p = Σ_I m_I f_I for one material: the
/// adjoint of the mass scatter (the coupled ICE–MPM step's temperature
/// change through the nodes, `brisance-couple`). A material with no block
/// (`node_values` too short) gets 0.
pub fn g2p_node_values(
    map: &GridMap,
    bins: &ParticleBins,
    position: &[[f64; 3]],
    material: &[MaterialId],
    node_values: &[f64],
    out: &mut [f64],
) {
    let chunk = PARTICLES_PER_TASK;
    out.par_chunks_mut(chunk).enumerate().for_each(|(k, o)| {
        dispatch(
            map,
            NodeValueRange {
                map,
                bins,
                first: k * chunk,
                position,
                material,
                node_values,
                out: o,
            },
        )
    });
}

/// Σ_I N_Ip f_I of a node field `field` (storage order) at a particle at
/// `x` of GIMP half-width `half_width`, summed row by row in storage
/// order.
#[inline(always)]
fn gather<const NX: usize, const NY: usize, const NZ: usize>(
    map: &GridMap,
    x: [f64; 3],
    half_width: [f64; 3],
    field: &[f64],
) -> f64 {
    let s = map.stencil::<NX, NY, NZ>(x, half_width);
    let mut sum = 0.0;
    for c in 0..NZ {
        for b in 0..NY {
            let row = s.row(b, c);
            let start = map.row_start(s.base, b, c);
            for (&wx, &v) in s.x.w.iter().zip(&field[start..start + NX]) {
                sum += row.weight(wx) * v;
            }
        }
    }
    sum
}

struct NodeValueRange<'a> {
    map: &'a GridMap,
    bins: &'a ParticleBins,
    first: usize,
    position: &'a [[f64; 3]],
    material: &'a [MaterialId],
    node_values: &'a [f64],
    out: &'a mut [f64],
}

impl StencilPass for NodeValueRange<'_> {
    fn run<const NX: usize, const NY: usize, const NZ: usize>(self) {
        let Self {
            map,
            bins,
            first,
            position,
            material,
            node_values,
            out,
        } = self;
        let nodes = map.lattice.len();
        for (i, o) in out.iter_mut().enumerate() {
            let p = first + i;
            let base = material[p].0 as usize * nodes;
            let Some(f) = node_values.get(base..base + nodes) else {
                *o = 0.0;
                continue;
            };
            *o = gather::<NX, NY, NZ>(map, position[p], bins.half_width(p), f);
        }
    }
}

struct TemperatureRange<'a> {
    map: &'a GridMap,
    bins: &'a ParticleBins,
    first: usize,
    position: &'a [[f64; 3]],
    material: &'a [MaterialId],
    properties: &'a [ThermalProperties],
    rate: &'a [f64],
    dt: f64,
    temperature: &'a mut [f64],
}

impl StencilPass for TemperatureRange<'_> {
    fn run<const NX: usize, const NY: usize, const NZ: usize>(self) {
        let Self {
            map,
            bins,
            first,
            position,
            material,
            properties,
            rate,
            dt,
            temperature,
        } = self;
        for (i, t) in temperature.iter_mut().enumerate() {
            let p = first + i;
            let props = &properties[material[p].0 as usize];
            if !props.takes_part() {
                continue;
            }
            let heat = &props.specific_heat;
            let curve = matches!(heat, SpecificHeat::Model(_));
            let dtemp = gather::<NX, NY, NZ>(map, position[p], bins.half_width(p), rate);
            if curve {
                // The heat the particle's share of the nodal rates brings,
                // m_p c_p(Tⁿ) Δt Σ N Ṫ_I (the c_p of the capacity pass), J/kg
                // once divided by m_p, raises H(T) by exactly that much.
                let q = heat.smoothed_at(*t) * (dtemp * dt);
                *t += heat.temperature_rise(*t, q);
            } else {
                *t += dtemp * dt;
            }
        }
    }
}
