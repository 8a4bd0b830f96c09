//! Brisance reaction models.
//!
//! The models that burn by a pointwise law implement
//! [`brisance_core::ReactionModel`] (registered for configs in the composer's
//! registry, `brisance list`): [`JwlPlusPlus`] (seed 000 §4.1.1),
//! [`ProgramBurn`] (seed 004) and [`ProgramBurnRamp`] (seed 001 eq 53);
//! [`Deflagration`] (seed 000 §4.1.2) and [`Arrhenius`] (seed 003 §2.4) burn
//! on the reactant's surface, which the solver finds before each step.
//!
//! - [`jwlpp`]: the JWL++ rate law with the seed's threshold and 20 % rule,
//!   its detonation energy and CJ state.
//! - [`program_burn`]: detonation times of explosive nodes by the Huygens
//!   construction over a node graph (detonations go around obstacles,
//!   isolated explosive does not detonate) or by straight lines from the
//!   detonation points (seed 004, "Propagation of Detonation").
//! - [`deflagration`]: the surface burn of seed 000 §4.1.2, D = A pⁿ
//!   (eq 38) and Γ = a D ρ_reactant (eq 39), with the surface cells, their
//!   normals and areas found on a structured grid; the ICE and ICE–MPM
//!   pipelines burn Eulerian reactants with it.
//! - [`arrhenius`]: the Arrhenius pyrolysis of seed 003, ṁ'' =
//!   Ω A exp(−Eₐ/(R T)), by which the MSDM lattice regresses its exposed
//!   nodes.
//! - [`plugin`]: reaction models from their own crates, registered by
//!   their RON name ([`plugin::ReactionRegistry`]).
//! - [`products`]: the pressure isentrope P_S(X) of the detonation products
//!   for an ideal gas (seed 004 eq 29) and JWL (eq 30), with its reference
//!   pressure P_S0 from the volume-burn algorithm (eqs 20–21, computed by
//!   `brisance_eos::tools::volume_burn_reference`).
//!
//! Units are SI throughout.

pub mod arrhenius;
pub mod deflagration;
pub mod jwlpp;
pub mod plugin;
pub mod products;
pub mod program_burn;

pub use arrhenius::Arrhenius;
pub use deflagration::{
    surface_area_densities, upwind_area_densities, Deflagration, DeflagrationError, SurfaceArea,
    SurfaceDetection, SurfaceWork,
};
pub use jwlpp::JwlPlusPlus;
pub use products::{ProductsError, ProductsIsentrope};
pub use program_burn::{
    huygens_detonation_times, straight_line_detonation_times, BurnError, DetonationPoint,
    ProgramBurn, ProgramBurnRamp,
};
