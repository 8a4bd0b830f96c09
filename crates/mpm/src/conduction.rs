//! Heat conduction inside the MPM solids: Fourier's law j = −k ∇T (seed
//! 000 §2 eq 3, the term −∇·j_r with j_r = −ρ_r b_r ∇T_r, here with the
//! conductivity k = ρ c_v b in W/(m·K)), so that heat reaches the interior
//! of a body whose surface is heated (the cook-off case of seed 000 §5.3).
//!
//! The energy equation ρ c_v ∂T/∂t = ∇·(k ∇T) is discretised as the MPM
//! literature does (Uintah, `Components/MPM/HeatConduction`:
//! `computeInternalHeatRate`, `solveHeatEquations`,
//! `integrateTemperatureRate`, and the temperature update of `SerialMPM`'s
//! `interpolateToParticlesAndUpdate`), with N_Ip and ∇N_Ip at x_pⁿ:
//!
//! 1. C_I = Σ_p N_Ip m_p c_p and T_I = Σ_p N_Ip m_p c_p T_p / C_I (the
//!    mass-weighted mean of one material);
//! 2. ∇T_p = Σ_I T_I ∇N_Ip;
//! 3. the internal heat rate q_I = −Σ_p V_p k_p ∇T_p · ∇N_Ip, W;
//! 4. Ṫ_I = q_I / C_I on every node with C_I > 0;
//! 5. T_p += Δt Σ_I N_Ip Ṫ_I.
//!
//! Σ_p m_p c_p ΔT_p = Δt Σ_I C_I Ṫ_I = Δt Σ_I q_I = 0, since Σ_I ∇N_Ip = 0
//! (partition of unity): the heat moves between particles and its total is
//! kept to round-off.
//!
//! A specific heat that follows the temperature
//! ([`brisance_constitutive::SpecificHeat`], the cook-off steel's c_v(T))
//! enters as the apparent heat capacity of the enthalpy method: c_p =
//! c_v(T_pⁿ) in step 1 (its mean over T ± 1 K within 1 K of the Curie
//! point, [`SpecificHeat::smoothed_at`]), and in step 5 the particle takes the heat
//! q_p = c_p Δt Σ_I N_Ip Ṫ_I and moves to the T' with H(T') − H(T_pⁿ) = q_p
//! (H = ∫ c_v dT), so Σ_p m_p H(T_p) is what is kept. A constant c_v
//! takes step 5 as written (the same bits as before). Every face is adiabatic (the weak form's natural
//! condition, zero flux through the body's surface).
//!
//! On an axisymmetric (r, z) grid the masses and volumes are the rings'
//! (they carry 2πr), ∇ = (∂_r, ∂_z), and steps 1–5 are unchanged: the
//! weak form of (1/r) ∂(r k ∂T/∂r)/∂r + ∂(k ∂T/∂z)/∂z with the ring
//! volume 2πr dr dz has no hoop term for a scalar (unlike the force, whose
//! σ_θθ enters).
//!
//! The update is explicit: Δt ≤ cfl / (2 α Σ_d 1/Δx_d²) with α = k/(ρ c_v)
//! over the active axes d, which is cfl·h²/(2 d α) on cubic cells
//! ([`diffusive_time_step`]). The step runs it before the mechanical
//! transfers (an operator split), from the positions and temperatures of
//! the start of the step. Only the temperature changes: the specific
//! internal energy e_p is left as the mechanics made it, as for the heat
//! exchange of the coupled step. See `docs/physics/mpm/heat_conduction.md`.
//!
//! [`cases`] holds the verification problems (the decay of a bar's cosine
//! mode and of a cylinder's Bessel mode) that the tests and the
//! V-CONDUCTION section of the validation report share.

use crate::transfer::heat::{self, HeatNodeSums, HeatParticles};
use crate::transfer::{GridMap, ParticleBins};
use crate::Particles;
use brisance_constitutive::{MaterialModel, SpecificHeat};
use brisance_core::UniformGridGeometry;
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

/// The heat-conduction option of the MPM solver
/// ([`crate::MpmSolver::with_heat_conduction`]): per material, indexed by
/// [`crate::MaterialId`], its thermal conductivity and, optionally, its
/// specific heat. Off by default (no conductivity anywhere): the step is
/// then the same, bit for bit, as without the option.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
pub struct HeatConduction {
    /// Thermal conductivity k of each material, W/(m·K), finite and ≥ 0;
    /// a material past the end of the list has k = 0.
    #[serde(default)]
    pub conductivity: Vec<f64>,
    /// Specific heat c_v of each material, J/(kg·K): a constant, finite
    /// and > 0, or one that follows the temperature
    /// ([`brisance_constitutive::SpecificHeat`]); `None` or past the end of
    /// the list: the model's own (the J2 metal's `specific_heat`, constant
    /// or not, or a plugin model's). A material with k > 0 needs one; a
    /// material without one takes no part in the conduction (its
    /// temperature is left alone).
    #[serde(default)]
    pub specific_heat: Vec<Option<SpecificHeat>>,
}

/// The conductivity and specific heat of one material as the kernels use
/// them: k (W/(m·K)) and c_v (J/(kg·K)); c_v the constant 0 for a
/// material that takes no part in the conduction.
#[derive(Debug, Clone, PartialEq)]
pub struct ThermalProperties {
    /// k, W/(m·K).
    pub conductivity: f64,
    /// c_v, J/(kg·K): a constant, or one that follows the temperature.
    pub specific_heat: SpecificHeat,
}

impl Default for ThermalProperties {
    fn default() -> Self {
        Self {
            conductivity: 0.0,
            specific_heat: SpecificHeat::Constant(0.0),
        }
    }
}

impl ThermalProperties {
    /// Whether the material's temperature takes part in the conduction
    /// (it has a specific heat).
    #[inline]
    pub fn takes_part(&self) -> bool {
        match &self.specific_heat {
            SpecificHeat::Constant(c) => *c > 0.0,
            SpecificHeat::Model(_) => true,
        }
    }
}

/// Why a [`HeatConduction`] option cannot be used: the option's name, its
/// value printed and what is expected.
pub type ConductionError = (&'static str, String, &'static str);

impl HeatConduction {
    /// Whether any material conducts.
    pub fn is_on(&self) -> bool {
        self.conductivity.iter().any(|&k| k != 0.0)
    }

    /// The properties of every material of `materials`, or why not. The
    /// specific heat comes from the option, else from the model (the J2
    /// metal's), else is 0 (no part in the conduction).
    pub fn resolve(
        &self,
        materials: &[MaterialModel],
    ) -> Result<Vec<ThermalProperties>, ConductionError> {
        if self.conductivity.len() > materials.len() {
            return Err((
                "heat_conduction.conductivity",
                format!("{} entries", self.conductivity.len()),
                "at most one per material",
            ));
        }
        if self.specific_heat.len() > materials.len() {
            return Err((
                "heat_conduction.specific_heat",
                format!("{} entries", self.specific_heat.len()),
                "at most one per material",
            ));
        }
        materials
            .iter()
            .enumerate()
            .map(|(i, model)| {
                let k = self.conductivity.get(i).copied().unwrap_or(0.0);
                if !(k >= 0.0 && k.is_finite()) {
                    return Err((
                        "heat_conduction.conductivity",
                        k.to_string(),
                        "must be finite and ≥ 0",
                    ));
                }
                let given = self.specific_heat.get(i).cloned().flatten();
                match &given {
                    Some(SpecificHeat::Constant(c)) if !(*c > 0.0 && c.is_finite()) => {
                        return Err((
                            "heat_conduction.specific_heat",
                            c.to_string(),
                            "must be finite and > 0",
                        ));
                    }
                    Some(curve) => curve.validate("HeatConduction").map_err(|e| {
                        (
                            "heat_conduction.specific_heat",
                            e.to_string(),
                            "valid constants of the curve",
                        )
                    })?,
                    None => {}
                }
                let c = given
                    .or_else(|| model.specific_heat())
                    .unwrap_or(SpecificHeat::Constant(0.0));
                let properties = ThermalProperties {
                    conductivity: k,
                    specific_heat: c,
                };
                if k > 0.0 && !properties.takes_part() {
                    return Err((
                        "heat_conduction.specific_heat",
                        format!("none for material {i} ({})", model_name(model)),
                        "a specific heat for every conducting material whose model has none",
                    ));
                }
                Ok(properties)
            })
            .collect()
    }
}

fn model_name(model: &MaterialModel) -> &'static str {
    use brisance_core::Material;
    model.name()
}

/// The node buffers of [`conduct`], reused from step to step (they grow
/// once to the lattice's node count).
#[derive(Debug, Clone, Default)]
pub struct HeatWork {
    /// C_I, J/K.
    pub capacity: Vec<f64>,
    /// T_I, K (H_I, J, until divided by C_I).
    pub temperature: Vec<f64>,
    /// Ṫ_I, K/s (q_I, W, until divided by C_I).
    pub rate: Vec<f64>,
}

impl HeatWork {
    /// Bytes held.
    pub fn bytes(&self) -> usize {
        8 * (self.capacity.len() + self.temperature.len() + self.rate.len())
    }

    fn resize(&mut self, n: usize) {
        for v in [&mut self.capacity, &mut self.temperature, &mut self.rate] {
            v.resize(n, 0.0);
        }
    }
}

/// Nodes per parallel task of the node passes.
const NODES_PER_TASK: usize = 4096;

/// One explicit conduction step of Δt = `dt` (steps 1–5 of the module
/// doc) on the particles binned in `bins`, with the material properties
/// `properties` (indexed by material id). Every node with a heat capacity
/// gets its rate, however light: the mass cut-off of the momentum update
/// is not applied, since a light node's large Ṫ_I reaches a particle only
/// times that particle's small weight N_Ip there, and a cut-off would
/// drop the node's q_I from the balance. Deterministic: the same bits for
/// any thread count. Allocates only when `work` first grows.
pub fn conduct(
    map: &GridMap,
    bins: &ParticleBins,
    particles: &mut Particles,
    properties: &[ThermalProperties],
    work: &mut HeatWork,
    dt: f64,
) {
    work.resize(map.lattice.len());
    let hp = HeatParticles {
        position: &particles.position,
        mass: &particles.mass,
        volume: &particles.volume,
        temperature: &particles.temperature,
        material: &particles.material,
        properties,
    };
    heat::p2g_heat_capacity(
        map,
        bins,
        hp,
        HeatNodeSums {
            capacity: &mut work.capacity,
            heat: &mut work.temperature,
        },
    );
    // T_I = H_I / C_I.
    work.temperature
        .par_chunks_mut(NODES_PER_TASK)
        .zip(work.capacity.par_chunks(NODES_PER_TASK))
        .for_each(|(t, c)| {
            for (t, &c) in t.iter_mut().zip(c) {
                *t = if c > 0.0 { *t / c } else { 0.0 };
            }
        });
    heat::p2g_heat_flux(
        map,
        bins,
        hp,
        &work.temperature,
        &work.capacity,
        &mut work.rate,
    );
    // Ṫ_I = q_I / C_I on every node with a heat capacity.
    work.rate
        .par_chunks_mut(NODES_PER_TASK)
        .zip(work.capacity.par_chunks(NODES_PER_TASK))
        .for_each(|(q, c)| {
            for (q, &c) in q.iter_mut().zip(c) {
                *q = if c > 0.0 { *q / c } else { 0.0 };
            }
        });
    heat::g2p_temperature_rate(
        map,
        bins,
        &particles.position,
        &particles.material,
        properties,
        &work.rate,
        dt,
        &mut particles.temperature,
    );
}

/// The largest thermal diffusivity α_p = k V_p / (m_p c_p) over the
/// particles of a conducting material (c_p at the particle's temperature),
/// m²/s (0 if none), or the index of the lowest particle whose α is not
/// finite.
pub fn max_diffusivity(
    particles: &Particles,
    properties: &[ThermalProperties],
) -> Result<f64, usize> {
    let ps = particles;
    let (alpha, bad) = (0..ps.len())
        .into_par_iter()
        .with_min_len(4096)
        .map(|p| {
            let th = &properties[ps.material[p].0 as usize];
            if th.conductivity == 0.0 {
                return (0.0, usize::MAX);
            }
            let c = th.specific_heat.smoothed_at(ps.temperature[p]);
            let a = th.conductivity * ps.volume[p] / (ps.mass[p] * c);
            if a.is_finite() {
                (a, usize::MAX)
            } else {
                (0.0, p)
            }
        })
        // max and min are exact: the order of the reduction cannot matter.
        .reduce(|| (0.0, usize::MAX), |a, b| (a.0.max(b.0), a.1.min(b.1)));
    if bad != usize::MAX {
        Err(bad)
    } else {
        Ok(alpha)
    }
}

/// The diffusive limit of the explicit update, Δt = cfl / (2 α Σ_d 1/Δx_d²)
/// over the active axes d of `grid` (cells > 1), s; cfl·h²/(2 d α) on
/// cells of edge h. Infinite for α = 0. The forward-Euler update of the
/// lumped heat equation with linear elements is stable for cfl ≤ 1 (the
/// largest eigenvalue of M_L⁻¹K is 4α Σ 1/Δx_d²); GIMP and the B-spline,
/// smoother, have smaller ones.
pub fn diffusive_time_step(alpha: f64, grid: &UniformGridGeometry, cfl: f64) -> f64 {
    let inv_h2: f64 = (0..3)
        .filter(|&d| grid.cells[d] > 1)
        .map(|d| 1.0 / (grid.spacing[d] * grid.spacing[d]))
        .sum();
    if alpha > 0.0 && inv_h2 > 0.0 {
        cfl / (2.0 * alpha * inv_h2)
    } else {
        f64::INFINITY
    }
}

pub mod cases;

#[cfg(test)]
mod tests;
