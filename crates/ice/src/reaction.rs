//! Step 4 of seed 000 §3.3: reaction sources Γ between materials (eq 1,
//! and the u_rs⁺Γ_rs, h_rs⁺Γ_rs terms of eqs 2–3), for the JWL++
//! detonation model of §4.1.1 ([`brisance_reaction::jwlpp`]), the
//! deflagration of §4.1.2 ([`brisance_reaction::deflagration`], which burns
//! on the reactant surface step 2 finds), the Arrhenius surface pyrolysis
//! of seed 003 §2.4 ([`brisance_reaction::arrhenius`], on that surface too)
//! or any other [`ReactionModel`] ([`IceRate`]).
//!
//! Each [`IceReaction`] turns material `reactant` into material `product`
//! at its model's rate, called through [`ReactionModel::burnt_density`]
//! with the cell's equilibration pressure, the reactant's temperature and
//! density and the two materials' densities at the start of the step. The
//! burnt mass
//! Δm = Γ Δt (per unit cell volume) carries, as the seed asks ("the
//! momentum, internal energy and volume of the reactant are depleted at the
//! same rate as the mass"), the reactant's momentum Δm u_r, internal energy
//! Δm e_r and volume Δm v_r, and the product receives exactly those plus
//! the chemical energy Δm Q ([`transfer_burnt_mass`]):
//!
//! - reactant: ρ_r ← ρ_r − Δm; u_r, e_r, v_r unchanged (so
//!   ρ_r u_r, ρ_r e_r, θ_r all fall in proportion to the mass);
//! - product: ρ_p ← ρ_p + Δm, ρ_p u_p ← ρ_p u_p + Δm u_r,
//!   θ_p ← θ_p + Δm v_r, and the total energy
//!   ρ_p (e_p + ½|u_p|²) ← ρ_p (e_p + ½|u_p|²) + Δm (e_r + Q + ½|u_r|²),
//!   so the kinetic energy lost when the two velocities mix becomes heat.
//!
//! Energies are in the products' reference: the reactant's internal energy
//! plus Q is its energy in that reference, so the conserved total energy
//! is Σ ρ_r (e_r + ½|u_r|²) + Σ_reactants ρ_r Q (what
//! `IceSolver::conservation_totals` sums) and the transfer conserves mass,
//! momentum and that energy to round-off.
//!
//! The products are born at the reactant's specific volume (the volume the
//! burnt reactant occupied), so Σ_r v_r Γ_r = 0 in eq 20 and the pressure
//! rise of the reaction comes from the deposited energy at the next
//! equilibration (the choice of Uintah's JWL++ model; see
//! `docs/physics/reaction/jwlpp.md`).

use std::sync::Arc;

use brisance_core::{ReactionModel, ReactionState};
use brisance_eos::{JwlCTerm, Murnaghan};
use brisance_reaction::jwlpp::JwlPlusPlus;
use brisance_reaction::{Arrhenius, Deflagration};

/// Chemical energy of a JWL++ reactant → products pair, J/kg
/// ([`brisance_reaction::jwlpp::detonation_energy`]), the message naming
/// what is wrong.
pub fn detonation_energy(reactant: &Murnaghan, products: &JwlCTerm) -> Result<f64, String> {
    brisance_reaction::jwlpp::detonation_energy(reactant, products).map_err(|e| e.to_string())
}

/// The rate law of an [`IceReaction`]: step 4 calls it through
/// [`ReactionModel::burnt_density`] with the cell's equilibration pressure,
/// the reactant's temperature and density and the two materials'
/// macroscopic densities. The built-in models are variants of their own, so
/// the cell loop calls them without an indirect call; any other
/// [`ReactionModel`] (a model crate's own) comes as [`IceRate::Model`].
#[derive(Debug, Clone)]
pub enum IceRate {
    /// JWL++ (seed 000 eqs 35–37).
    JwlPlusPlus(JwlPlusPlus),
    /// The surface burn D = A pⁿ (seed 000 eqs 38–39): the solver finds
    /// the reactant's surface before each step
    /// ([`ReactionModel::burns_on_a_surface`]).
    Deflagration(Deflagration),
    /// The Arrhenius surface pyrolysis ṁ'' = Ω A exp(−Eₐ/(R T)) of seed
    /// 003 (§2.4, §3.1–3.2), on the reactant surface as the deflagration.
    Arrhenius(Arrhenius),
    /// Any other reaction model.
    Model(Arc<dyn ReactionModel>),
}

impl From<JwlPlusPlus> for IceRate {
    fn from(rate: JwlPlusPlus) -> Self {
        Self::JwlPlusPlus(rate)
    }
}

impl From<Deflagration> for IceRate {
    fn from(rate: Deflagration) -> Self {
        Self::Deflagration(rate)
    }
}

impl From<Arrhenius> for IceRate {
    fn from(rate: Arrhenius) -> Self {
        Self::Arrhenius(rate)
    }
}

impl PartialEq for IceRate {
    /// Built-in laws by their parameters; other models by identity.
    fn eq(&self, other: &Self) -> bool {
        match (self, other) {
            (Self::JwlPlusPlus(a), Self::JwlPlusPlus(b)) => a == b,
            (Self::Deflagration(a), Self::Deflagration(b)) => a == b,
            (Self::Arrhenius(a), Self::Arrhenius(b)) => a == b,
            (Self::Model(a), Self::Model(b)) => Arc::ptr_eq(a, b),
            _ => false,
        }
    }
}

impl IceRate {
    /// Checks the parameters of a built-in law (a model given as
    /// [`IceRate::Model`] was built by its own crate's checks).
    pub fn validate(&self) -> Result<(), String> {
        match self {
            Self::JwlPlusPlus(m) => m.validate().map_err(|e| e.to_string()),
            Self::Deflagration(m) => m.validate().map_err(|e| e.to_string()),
            Self::Arrhenius(m) => m.validate("model"),
            Self::Model(_) => Ok(()),
        }
    }
}

impl ReactionModel for IceRate {
    fn name(&self) -> &'static str {
        match self {
            Self::JwlPlusPlus(m) => m.name(),
            Self::Deflagration(m) => ReactionModel::name(m),
            Self::Arrhenius(m) => m.name(),
            Self::Model(m) => m.name(),
        }
    }

    #[inline]
    fn burns_on_a_surface(&self) -> bool {
        match self {
            Self::JwlPlusPlus(_) => false,
            Self::Deflagration(_) | Self::Arrhenius(_) => true,
            Self::Model(m) => m.burns_on_a_surface(),
        }
    }

    fn rate(&self, state: &ReactionState, burn_fraction: f64) -> f64 {
        match self {
            Self::JwlPlusPlus(m) => ReactionModel::rate(m, state, burn_fraction),
            Self::Deflagration(m) => m.rate(state, burn_fraction),
            Self::Arrhenius(m) => m.rate(state, burn_fraction),
            Self::Model(m) => m.rate(state, burn_fraction),
        }
    }

    fn advance(&self, state: &ReactionState, burn_fraction: f64, dt: f64) -> f64 {
        match self {
            Self::JwlPlusPlus(m) => m.advance(state, burn_fraction, dt),
            Self::Deflagration(m) => m.advance(state, burn_fraction, dt),
            Self::Arrhenius(m) => m.advance(state, burn_fraction, dt),
            Self::Model(m) => m.advance(state, burn_fraction, dt),
        }
    }

    fn mass_converted(&self, initial_mass: f64, f_old: f64, f_new: f64) -> f64 {
        match self {
            Self::JwlPlusPlus(m) => m.mass_converted(initial_mass, f_old, f_new),
            Self::Deflagration(m) => m.mass_converted(initial_mass, f_old, f_new),
            Self::Arrhenius(m) => m.mass_converted(initial_mass, f_old, f_new),
            Self::Model(m) => m.mass_converted(initial_mass, f_old, f_new),
        }
    }

    #[inline]
    fn burnt_density(
        &self,
        state: &ReactionState,
        rho_reactant: f64,
        rho_product: f64,
        dt: f64,
    ) -> f64 {
        match self {
            Self::JwlPlusPlus(m) => {
                ReactionModel::burnt_density(m, state, rho_reactant, rho_product, dt)
            }
            Self::Deflagration(m) => m.burnt_density(state, rho_reactant, rho_product, dt),
            Self::Arrhenius(m) => m.burnt_density(state, rho_reactant, rho_product, dt),
            Self::Model(m) => m.burnt_density(state, rho_reactant, rho_product, dt),
        }
    }
}

/// The share of a cell's reactant that one step leaves at least: step 4
/// burns at most (1 − this) of it, so the reactant never reaches zero
/// mass (its specific volume θ/ρ stays defined) and a cell a surface burn
/// has emptied keeps the trace an absent material holds elsewhere
/// (θ ≤ 10⁻⁶). JWL++'s own cap (20 % a step) lies far below it.
pub const REACTANT_LEFT: f64 = 1.0e-6;

/// The share of a cell's reactant below which the surface pass of a
/// surface burn counts the cell empty of it
/// ([`brisance_reaction::SurfaceDetection::present_threshold`] on the
/// reactant's volume fraction): above the traces absent materials hold
/// (10⁻⁶, and what the equilibration's compression makes of them), at the
/// volume share below which the solver treats a fluid as a trace.
pub const SURFACE_PRESENT: f64 = 1.0e-4;

/// One reaction between two of the solver's materials.
#[derive(Debug, Clone, PartialEq)]
pub struct IceReaction {
    /// Index of the reactant material (0-based, solver order).
    pub reactant: usize,
    /// Index of the product material.
    pub product: usize,
    /// The rate law.
    pub rate: IceRate,
    /// Chemical energy released per kilogram burnt, J/kg (Q ≥ 0).
    pub heat_of_reaction: f64,
}

impl IceReaction {
    /// Checks indices and parameters for `n` materials; the message names
    /// the field.
    pub fn validate(&self, n: usize) -> Result<(), String> {
        if self.reactant >= n {
            return Err(format!(
                "reaction field `reactant` = {} but there are {n} materials",
                self.reactant
            ));
        }
        if self.product >= n {
            return Err(format!(
                "reaction field `product` = {} but there are {n} materials",
                self.product
            ));
        }
        if self.reactant == self.product {
            return Err("reaction fields `reactant` and `product` name the same material".into());
        }
        if !(self.heat_of_reaction >= 0.0 && self.heat_of_reaction.is_finite()) {
            return Err(format!(
                "reaction field `heat_of_reaction` = {}: expected a finite value ≥ 0 J/kg",
                self.heat_of_reaction
            ));
        }
        self.rate.validate()
    }
}

/// One material's Lagrangian state in a cell, per unit cell volume: the
/// averaged density ρ (kg/m³), velocity (m/s), specific internal energy e
/// (J/kg) and material volume θ.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Parcel {
    /// ρ, kg/m³ (mass per unit cell volume).
    pub rho: f64,
    /// u, m/s.
    pub velocity: [f64; 3],
    /// e, J/kg.
    pub energy: f64,
    /// θ, material volume per unit cell volume.
    pub volume: f64,
}

/// What burning particles of a solid reactant gave one cell over a step
/// ([`crate::IceSolver::add_burnt_particles`]): mass, kg; momentum,
/// kg·m/s; total energy (internal + kinetic + heat of reaction, in the
/// product's reference), J; volume, m³.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct BurntMass {
    /// Mass, kg.
    pub mass: f64,
    /// Momentum, kg·m/s.
    pub momentum: [f64; 3],
    /// Total energy, J.
    pub energy: f64,
    /// Volume, m³.
    pub volume: f64,
}

/// Moves `burnt` (kg per m³ of cell, 0 ≤ burnt < reactant.rho) from
/// `reactant` to `product` with the reactant's momentum, internal energy
/// and specific volume, and adds `heat` × burnt of chemical energy to the
/// product (seed 000 step 4; see the module comment).
pub fn transfer_burnt_mass(reactant: &mut Parcel, product: &mut Parcel, burnt: f64, heat: f64) {
    if burnt <= 0.0 {
        return;
    }
    let u_r = reactant.velocity;
    let ke = |u: [f64; 3]| 0.5 * (u[0] * u[0] + u[1] * u[1] + u[2] * u[2]);
    let v_r = reactant.volume / reactant.rho;
    let rho_p = product.rho + burnt;
    let mom: [f64; 3] = std::array::from_fn(|d| product.rho * product.velocity[d] + burnt * u_r[d]);
    let total = product.rho * (product.energy + ke(product.velocity))
        + burnt * (reactant.energy + heat + ke(u_r));
    let u_p = mom.map(|m| m / rho_p);
    product.rho = rho_p;
    product.velocity = u_p;
    product.energy = total / rho_p - ke(u_p);
    product.volume += burnt * v_r;
    reactant.rho -= burnt;
    reactant.volume -= burnt * v_r;
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parcels() -> (Parcel, Parcel) {
        (
            Parcel {
                rho: 1000.0,
                velocity: [100.0, 0.0, 0.0],
                energy: 2.0e5,
                volume: 0.8,
            },
            Parcel {
                rho: 40.0,
                velocity: [-50.0, 10.0, 0.0],
                energy: 4.0e6,
                volume: 0.2,
            },
        )
    }

    #[test]
    fn the_transfer_is_the_hand_computed_one() {
        let (mut r, mut p) = parcels();
        transfer_burnt_mass(&mut r, &mut p, 160.0, 3.0e6);
        // Reactant: 840 kg/m³, same u and e, volume 0.8 − 160 · 0.0008 = 0.672.
        assert_eq!(r.rho, 840.0);
        assert_eq!(r.velocity, [100.0, 0.0, 0.0]);
        assert_eq!(r.energy, 2.0e5);
        assert!((r.volume - 0.672).abs() < 1e-15);
        // Product: 200 kg/m³; momentum 40·(−50, 10) + 160·(100, 0) = (14000, 400),
        // u = (70, 2); volume 0.2 + 0.128 = 0.328.
        assert_eq!(p.rho, 200.0);
        assert!((p.velocity[0] - 70.0).abs() < 1e-12 && (p.velocity[1] - 2.0).abs() < 1e-14);
        assert!((p.volume - 0.328).abs() < 1e-15);
        // Energy: 40·(4e6 + ½·2600) + 160·(2e5 + 3e6 + ½·1e4) = 160 052 000 + 512 800 000
        // = 672 852 000; e = 672 852 000/200 − ½·4904 = 3 364 260 − 2452 = 3 361 808 J/kg.
        assert!((p.energy - 3_361_808.0).abs() < 1e-6, "{}", p.energy);
    }

    #[test]
    fn mass_momentum_energy_and_volume_are_conserved_to_round_off() {
        let (r0, p0) = parcels();
        for &burnt in &[1e-9, 0.3, 17.0, 199.9, 999.0] {
            let (mut r, mut p) = (r0, p0);
            let q = 3.448e6;
            transfer_burnt_mass(&mut r, &mut p, burnt, q);
            let tot = |r: &Parcel, p: &Parcel, chem: f64| {
                let ke = |x: &Parcel| 0.5 * x.rho * x.velocity.iter().map(|u| u * u).sum::<f64>();
                (
                    r.rho + p.rho,
                    r.rho * r.velocity[0] + p.rho * p.velocity[0],
                    r.rho * (r.energy + chem) + ke(r) + p.rho * p.energy + ke(p),
                    r.volume + p.volume,
                )
            };
            let (a, b) = (tot(&r0, &p0, q), tot(&r, &p, q));
            let eps = f64::EPSILON;
            assert!((a.0 - b.0).abs() <= 4.0 * eps * a.0);
            assert!((a.1 - b.1).abs() <= 8.0 * eps * 1e5);
            assert!((a.2 - b.2).abs() <= 8.0 * eps * a.2, "{} vs {}", a.2, b.2);
            assert!((a.3 - b.3).abs() <= 4.0 * eps);
            // The reactant keeps its specific volume.
            assert!((r.volume / r.rho - 0.0008).abs() < 1e-12 * 0.0008);
        }
    }

    #[test]
    fn nothing_moves_without_burning() {
        let (r0, p0) = parcels();
        let (mut r, mut p) = (r0, p0);
        transfer_burnt_mass(&mut r, &mut p, 0.0, 3e6);
        assert_eq!((r, p), (r0, p0));
    }

    #[test]
    fn reactions_are_validated_with_the_field_named() {
        let ok = IceReaction {
            reactant: 0,
            product: 1,
            rate: JwlPlusPlus::anfo_k1().into(),
            heat_of_reaction: 3.4e6,
        };
        assert!(ok.validate(2).is_ok());
        let e = IceReaction {
            product: 2,
            ..ok.clone()
        }
        .validate(2)
        .unwrap_err();
        assert!(e.contains("`product`"), "{e}");
        let e = IceReaction {
            product: 0,
            ..ok.clone()
        }
        .validate(2)
        .unwrap_err();
        assert!(e.contains("same material"), "{e}");
        let e = IceReaction {
            heat_of_reaction: -1.0,
            ..ok.clone()
        }
        .validate(2)
        .unwrap_err();
        assert!(e.contains("heat_of_reaction"), "{e}");
        let mut bad = ok;
        bad.rate = JwlPlusPlus {
            g: 0.0,
            ..JwlPlusPlus::anfo_k1()
        }
        .into();
        assert!(bad.validate(2).unwrap_err().contains("`g`"));
    }
}
