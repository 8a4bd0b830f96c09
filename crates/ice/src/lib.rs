//! Brisance ICE: the multi-material, cell-centred ICE method of seed 000
//! (Guilkey, Harman & Banerjee 2007) §2, §3.1 and the fluid steps of the
//! §3.3 step list, after Kashiwa & Rauenzahn (seed 000 refs 5, 6, 8).
//!
//! Every material r lives in every cell with its own mass (density ρ_r),
//! velocity u_r, specific internal energy e_r, temperature T_r, specific
//! volume v_r and volume fraction θ_r; the cell has one equilibration
//! pressure p (seed 000 eqs 1–10).
//!
//! One module per step of the seed, each a plain kernel over values or
//! slices that is tested alone:
//! - [`equilibration`]: step 2, the equilibration pressure of eq 7 by a
//!   safeguarded Newton–Raphson iteration on the thermal EOS v_r(p, T_r).
//! - [`face_velocity`]: step 3, face-centred velocities (eq 19).
//! - [`exchange`]: step 10 and the face exchange of step 3, momentum and
//!   heat exchange (eqs 29–30) solved pointwise-implicitly per cell.
//! - [`reaction`]: step 4, reaction sources Γ (eq 1) of the JWL++ model
//!   (§4.1.1), moved exactly from reactant to product.
//! - [`pressure`]: step 5 (eqs 20–21) and step 6 (eq 22).
//! - [`lagrangian`]: steps 8, 9 and 11 (eqs 23–28, 31–32).
//! - [`advection`]: step 12, van Leer compatible fluxes (seed 000 ref 15)
//!   and first-order donor cell.
//! - [`boundary`]: symmetry, outflow, fixed velocity, fixed state.
//! - [`diffusion`]: the optional Newtonian viscous stress and heat
//!   conduction of eqs 2–3 (step 8), per material.
//! - [`riemann`], [`water_air`]: the exact two-stiffened-gas Riemann
//!   solution and the water–air tube (the stiffened gas is
//!   `brisance_eos::StiffenedGas`).
//! - [`solver::implicit`]: the implicit-pressure variant of steps 3 and 5
//!   (end of §3.3), a pressure Helmholtz equation solved with faer and
//!   iterated with the face velocities.
//! - [`solver`]: the [`IceSolver`], the step sequence, the CFL time step and
//!   the `Solver` implementation.
//! - [`pipeline`]: the `Ice` pipeline's section of a scenario
//!   ([`pipeline::IceConfig`]), its checks, builder and description,
//!   through which the composer runs it (and the fluid side of IceMpm).
//!
//! Choices the seed leaves open are written down in `docs/physics/ice/`.

// The kernels index materials r, s and axes d as the equations do.
#![allow(clippy::needless_range_loop)]

pub mod advection;
pub mod boundary;
pub mod burn_rate;
pub mod cases;
pub mod column;
pub mod diffusion;
pub mod equilibration;
pub mod exchange;
pub mod face_velocity;
pub mod lagrangian;
pub mod material;
pub mod pipeline;
pub mod pressure;
pub mod reaction;
pub mod riemann;
pub mod solver;
pub mod water_air;

pub use advection::Advection;
pub use boundary::IceBoundary;
pub use brisance_reaction::jwlpp::JwlPlusPlus;
pub use brisance_reaction::{Deflagration, SurfaceArea};
pub use diffusion::{MaterialTransport, TimeStepLimit, TimeStepLimits};
pub use equilibration::{
    equilibration_pressure, EquilibrationError, EquilibrationReport, EquilibrationSettings,
    MAX_MATERIALS,
};
pub use exchange::SolidExchange;
pub use material::{CellState, ExchangeCoefficients, IceError, MaterialState};
pub use reaction::{detonation_energy, BurntMass, IceRate, IceReaction};
pub use solver::implicit::{ImplicitPressure, PressureSolve, PressureSolveStats, MAX_STEP_RETRIES};
pub use solver::{
    EquilibrationStats, IceOptions, IceSolver, KeptWarmTotals, LagrangianCells,
    LagrangianSpecificHeat, WholeGridPass, GHOST,
};

#[cfg(test)]
mod tests;
