//! The gas law the FDM kernels evaluate: one species (any [`Eos`]) or
//! detonation products in air carried as a mass fraction Y
//! ([`ProductsInAir`]).
//!
//! # Mixture rule
//!
//! Both components are of Mie–Grüneisen form, affine in e at fixed ρ:
//! p_k(ρ, e) = P_k(ρ) + K_k(ρ) e with P_k = p_k(ρ, 0) and K_k = ∂p_k/∂e
//! (JWL, seed 001 eq 54: P = p_ref(V), K = ωρ; ideal gas: P = 0,
//! K = (γ − 1)ρ). A mixed cell holds mass fraction Y of products and 1 − Y
//! of air at the cell density ρ. We close it with *pressure equilibrium*:
//! both components carry the same pressure p, each at the mixture density,
//! and their specific energies e_k = (p − P_k)/K_k add up by mass to the
//! cell's e = Y e_P + (1 − Y) e_A. Solving for p:
//!
//! p = (e + Y P_P/K_P + (1 − Y) P_A/K_A) / (Y/K_P + (1 − Y)/K_A).
//!
//! This is the inverse-Grüneisen mixing of Shyue (J. Comput. Phys. 171,
//! 2001, "A fluid-mixture type algorithm for compressible multicomponent
//! flow with Mie–Grüneisen equation of state"), 1/Γ and P/Γ averaged, with
//! the mass fraction in place of Shyue's volume fraction (the two agree where
//! the components have equal densities). It reduces exactly to each
//! component's own law at Y = 0 and Y = 1, and it keeps a contact between
//! components of equal density at uniform velocity and pressure exactly
//! isobaric under any conservative linear scheme (the pressure of a convex
//! combination of the two states is the common pressure). Where the density
//! jumps across a species interface a fully conservative mass-fraction scheme
//! cannot stay isobaric with any rule (Abgrall, J. Comput. Phys. 125, 1996);
//! `docs/physics/fdm_mixture.md` gives the measured size of that error.

use brisance_core::{Eos, EosError};
// e^x flushed to 0 for very negative x: the function of `brisance_eos::jwl`,
// so that the JWL terms here are the same bits as the `Eos` methods of `Jwl`.
use brisance_eos::jwl::decaying_exp as jwl_exp;
use brisance_eos::{EosModel, IdealGas, Jwl, JwlCTerm};

/// What the FDM kernels need from the gas: pressure, sound speed and
/// temperature as functions of (ρ, e, Y), Y the products mass fraction.
///
/// Every [`Eos`] is a one-species gas law (`SPECIES = false`, Y ignored and
/// not stored), so the one-species solver is unchanged.
pub trait GasLaw: Send + Sync + std::fmt::Debug {
    /// Whether the solver carries the conservative variable ρY.
    const SPECIES: bool;

    /// Pressure p(ρ, e, Y), Pa.
    fn gas_pressure(&self, rho: f64, e: f64, y: f64) -> f64;

    /// Isentropic sound speed c(ρ, e, Y) at frozen composition, m/s.
    fn gas_sound_speed(&self, rho: f64, e: f64, y: f64) -> f64;

    /// Temperature T(ρ, e, Y), K.
    fn gas_temperature(&self, rho: f64, e: f64, y: f64) -> f64;

    /// (p, c) of one state: [`GasLaw::gas_pressure`] and
    /// [`GasLaw::gas_sound_speed`], the same bits, for a law that can share
    /// the work of the two.
    #[inline(always)]
    fn gas_pressure_and_sound_speed(&self, rho: f64, e: f64, y: f64) -> (f64, f64) {
        (
            self.gas_pressure(rho, e, y),
            self.gas_sound_speed(rho, e, y),
        )
    }

    /// The specific internal energy that gives pressure `p` at density `rho`
    /// and mass fraction `y`.
    fn gas_energy(&self, rho: f64, p: f64, y: f64) -> Result<f64, EosError>;
}

impl<E: Eos> GasLaw for E {
    const SPECIES: bool = false;

    #[inline(always)]
    fn gas_pressure(&self, rho: f64, e: f64, _y: f64) -> f64 {
        self.pressure(rho, e)
    }

    #[inline(always)]
    fn gas_sound_speed(&self, rho: f64, e: f64, _y: f64) -> f64 {
        self.sound_speed(rho, e)
    }

    #[inline(always)]
    fn gas_temperature(&self, rho: f64, e: f64, _y: f64) -> f64 {
        self.temperature(rho, e)
    }

    fn gas_energy(&self, rho: f64, p: f64, _y: f64) -> Result<f64, EosError> {
        self.specific_internal_energy(rho, p)
    }
}

/// Detonation products `P` (JWL) mixed with air `A` (ideal gas) by mass
/// fraction Y of products, closed by pressure equilibrium at the mixture
/// density (module docs). Both laws must be affine in e at fixed ρ
/// (JWL, ideal gas, linear Mie–Grüneisen); [`ProductsInAir::new`] checks it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ProductsInAir<P: AffineLaw, A: AffineLaw> {
    /// Detonation products.
    pub products: P,
    /// Ambient gas.
    pub air: A,
}

/// The coefficients of a law affine in e at density ρ,
/// p(ρ, e) = P(ρ) + K(ρ) e, and their slopes in ρ.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Affine {
    /// P = p(ρ, 0), Pa.
    pub p: f64,
    /// K = ∂p/∂e|ρ, kg/m³.
    pub k: f64,
    /// ∂p/∂ρ|ₑ at e = 0, m²/s².
    pub dp: f64,
    /// ∂K/∂ρ, as ∂p/∂ρ|ₑ₌₁ − ∂p/∂ρ|ₑ₌₀ (exact for an affine law).
    pub dk: f64,
}

/// A component law of [`ProductsInAir`]: (P, K) and their slopes at a
/// density. The defaults ask the [`Eos`] for p(ρ, 0), ∂p/∂e, ∂p/∂ρ|ₑ₌₀ and
/// ∂p/∂ρ|ₑ₌₁; JWL and the ideal gas give the same numbers, bit for bit,
/// from one evaluation of their two exponentials (the mixture's pressure
/// and sound speed took ten JWL evaluations, twenty `exp` calls, per
/// state before).
pub trait AffineLaw: Eos {
    /// (P, K) at density `rho`.
    #[inline(always)]
    fn affine(&self, rho: f64) -> (f64, f64) {
        (self.pressure(rho, 0.0), self.dp_de(rho, 0.0))
    }

    /// (P, K, ∂P/∂ρ, ∂K/∂ρ) at density `rho`.
    #[inline(always)]
    fn affine_slopes(&self, rho: f64) -> Affine {
        affine_slopes_from_eos(self, rho)
    }
}

/// (P, K, ∂P/∂ρ, ∂K/∂ρ) at density `rho` from the [`Eos`] methods alone,
/// for laws without a fused evaluation.
#[inline(always)]
fn affine_slopes_from_eos<E: Eos + ?Sized>(eos: &E, rho: f64) -> Affine {
    let dp = eos.dp_drho(rho, 0.0);
    Affine {
        p: eos.pressure(rho, 0.0),
        k: eos.dp_de(rho, 0.0),
        dp,
        dk: eos.dp_drho(rho, 1.0) - dp,
    }
}

impl AffineLaw for IdealGas {
    /// P = (γ − 1)ρ·0, K = (γ − 1)ρ, the expressions of [`IdealGas`].
    #[inline(always)]
    fn affine(&self, rho: f64) -> (f64, f64) {
        ((self.gamma - 1.0) * rho * 0.0, (self.gamma - 1.0) * rho)
    }

    #[inline(always)]
    fn affine_slopes(&self, rho: f64) -> Affine {
        let (p, k) = AffineLaw::affine(self, rho);
        let dp = (self.gamma - 1.0) * 0.0;
        Affine {
            p,
            k,
            dp,
            dk: (self.gamma - 1.0) * 1.0 - dp,
        }
    }
}

/// [`Affine`] of the JWL form p = p_c(V) + ωρ(e − e_c(V)) (seed 001 eq 54)
/// with its two exponentials evaluated once: the expressions of
/// `brisance_eos::jwl::JwlCold` (`total_pressure`, `dp_drho`), term by term.
#[inline(always)]
fn jwl_affine(a: f64, b: f64, r1: f64, r2: f64, omega: f64, rho0: f64, rho: f64) -> Affine {
    let v = rho0 / rho;
    let ea = jwl_exp(-r1 * v);
    let eb = jwl_exp(-r2 * v);
    let p_c = a * ea + b * eb;
    let e_c = (a / r1 * ea + b / r2 * eb) / rho0;
    let dp_c = v / rho * (a * r1 * ea + b * r2 * eb);
    let de_c = p_c / (rho * rho);
    let p = p_c + omega * rho * (0.0 - e_c);
    let d0 = dp_c + omega * (0.0 - e_c) - omega * rho * de_c;
    let d1 = dp_c + omega * (1.0 - e_c) - omega * rho * de_c;
    Affine {
        p,
        k: omega * rho,
        dp: d0,
        dk: d1 - d0,
    }
}

impl AffineLaw for Jwl {
    /// P = p_c + ωρ(0 − e_c), K = ωρ: `JwlCold::total_pressure` at e = 0.
    #[inline(always)]
    fn affine(&self, rho: f64) -> (f64, f64) {
        let (a, b, r1, r2, omega, rho0) = (self.a, self.b, self.r1, self.r2, self.omega, self.rho0);
        let v = rho0 / rho;
        let ea = jwl_exp(-r1 * v);
        let eb = jwl_exp(-r2 * v);
        let p_c = a * ea + b * eb;
        let e_c = (a / r1 * ea + b / r2 * eb) / rho0;
        (p_c + omega * rho * (0.0 - e_c), omega * rho)
    }

    #[inline(always)]
    fn affine_slopes(&self, rho: f64) -> Affine {
        jwl_affine(self.a, self.b, self.r1, self.r2, self.omega, self.rho0, rho)
    }
}

/// The C terms cancel in (ρ, e) → p; the defaults.
impl AffineLaw for JwlCTerm {}

impl AffineLaw for EosModel {
    #[inline(always)]
    fn affine(&self, rho: f64) -> (f64, f64) {
        match self {
            Self::IdealGas(g) => AffineLaw::affine(g, rho),
            Self::Jwl(j) => AffineLaw::affine(j, rho),
            _ => (self.pressure(rho, 0.0), self.dp_de(rho, 0.0)),
        }
    }

    #[inline(always)]
    fn affine_slopes(&self, rho: f64) -> Affine {
        match self {
            Self::IdealGas(g) => g.affine_slopes(rho),
            Self::Jwl(j) => j.affine_slopes(rho),
            _ => affine_slopes_from_eos(self, rho),
        }
    }
}

/// The pressure-equilibrium rule (module docs) from the components'
/// (P, K): p and S = Y/K_P + (1 − Y)/K_A.
#[inline(always)]
fn mixture_pressure(pp: f64, kp: f64, pa: f64, ka: f64, e: f64, y: f64) -> (f64, f64) {
    let s = y / kp + (1.0 - y) / ka;
    ((e + y * pp / kp + (1.0 - y) * pa / ka) / s, s)
}

impl<P: AffineLaw, A: AffineLaw> ProductsInAir<P, A> {
    /// The mixture of `products` and `air`. Fails (naming the component)
    /// if a law is not affine in e at its reference density, where the
    /// closed-form pressure-equilibrium rule would not hold.
    pub fn new(products: P, air: A) -> Result<Self, String> {
        for (name, eos) in [
            ("products", &products as &dyn Eos),
            ("air", &air as &dyn Eos),
        ] {
            let rho = eos.reference_density();
            let (p0, p1, p2) = (
                eos.pressure(rho, 0.0),
                eos.pressure(rho, 1.0e5),
                eos.pressure(rho, 2.0e5),
            );
            let curvature = (p2 - 2.0 * p1 + p0).abs();
            if !(curvature <= 1e-9 * (p2.abs() + p0.abs() + 1.0)) || !(eos.dp_de(rho, 0.0) > 0.0) {
                return Err(format!(
                    "mixture {name} law `{}` must have a pressure affine in e with ∂p/∂e > 0 (JWL, ideal gas)",
                    eos.name()
                ));
            }
        }
        Ok(Self { products, air })
    }

    /// Pressure and the mass-weighted inverse stiffness S = Y/K_P + (1−Y)/K_A.
    ///
    /// Y is used as given, not clamped to [0, 1]: the intermediate
    /// (smoothed and half-step) states of the Lax–Wendroff step may carry Y
    /// slightly outside, and the rule must stay the same affine function of
    /// the conservative variables there to keep an equal-density species
    /// interface isobaric. The solver clips the stored ρY to [0, ρ] after
    /// each update.
    ///
    /// A component of zero mass fraction (Y = 0 or Y = 1 exactly, the
    /// stored state away from the contact) is not evaluated: its terms
    /// enter multiplied by 0, so (P, K) = (0, 1) in its place gives the
    /// same bits as its own finite values.
    #[inline(always)]
    fn pressure_and_s(&self, rho: f64, e: f64, y: f64) -> (f64, f64) {
        let (pp, kp) = if y == 0.0 {
            (0.0, 1.0)
        } else {
            self.products.affine(rho)
        };
        let (pa, ka) = if y == 1.0 {
            (0.0, 1.0)
        } else {
            self.air.affine(rho)
        };
        mixture_pressure(pp, kp, pa, ka, e, y)
    }

    /// Specific energies (e_P, e_A) of the components at the equilibrium
    /// pressure.
    pub fn component_energies(&self, rho: f64, e: f64, y: f64) -> (f64, f64) {
        let (p, _) = self.pressure_and_s(rho, e, y);
        let (pp, kp) = self.products.affine(rho);
        let (pa, ka) = self.air.affine(rho);
        ((p - pp) / kp, (p - pa) / ka)
    }
}

impl<P: AffineLaw, A: AffineLaw> GasLaw for ProductsInAir<P, A> {
    const SPECIES: bool = true;

    #[inline]
    fn gas_pressure(&self, rho: f64, e: f64, y: f64) -> f64 {
        self.pressure_and_s(rho, e, y).0
    }

    /// c² = ∂p/∂ρ|_{e,Y} + (p/ρ²) ∂p/∂e|_{ρ,Y}, with ∂p/∂e = 1/S and
    /// ∂p/∂ρ = Σ Y_k [P_k'/K_k − (P_k − p) K_k'/K_k²] / S (K_k' from the
    /// change of ∂p_k/∂ρ with e, exact for affine laws).
    #[inline]
    fn gas_sound_speed(&self, rho: f64, e: f64, y: f64) -> f64 {
        self.gas_pressure_and_sound_speed(rho, e, y).1
    }

    /// Both from one evaluation of each component's [`Affine`].
    #[inline]
    fn gas_pressure_and_sound_speed(&self, rho: f64, e: f64, y: f64) -> (f64, f64) {
        // A component of zero mass fraction is skipped as in
        // `pressure_and_s`: its term enters multiplied by 0.
        let unit = Affine {
            p: 0.0,
            k: 1.0,
            dp: 0.0,
            dk: 0.0,
        };
        let pr = if y == 0.0 {
            unit
        } else {
            self.products.affine_slopes(rho)
        };
        let ai = if y == 1.0 {
            unit
        } else {
            self.air.affine_slopes(rho)
        };
        let (p, s) = mixture_pressure(pr.p, pr.k, ai.p, ai.k, e, y);
        let term = |c: &Affine| c.dp / c.k - (c.p - p) * c.dk / (c.k * c.k);
        let dp_drho = (y * term(&pr) + (1.0 - y) * term(&ai)) / s;
        let c2 = dp_drho + p / (rho * rho * s);
        (p, c2.max(0.0).sqrt())
    }

    /// Components in pressure but not thermal equilibrium: the reported T is
    /// the heat-capacity-weighted mean Σ Y_k c_k T_k / Σ Y_k c_k of their
    /// temperatures at their own energies (what they would share after
    /// exchanging heat at constant volume, for constant c_v).
    fn gas_temperature(&self, rho: f64, e: f64, y: f64) -> f64 {
        let y = y.clamp(0.0, 1.0);
        let (ep, ea) = self.component_energies(rho, e, y);
        let (tp, ta) = (
            self.products.temperature(rho, ep),
            self.air.temperature(rho, ea),
        );
        let (cp, ca) = (
            y * self.products.cv(rho, tp),
            (1.0 - y) * self.air.cv(rho, ta),
        );
        (cp * tp + ca * ta) / (cp + ca)
    }

    /// e = Y (p − P_P)/K_P + (1 − Y)(p − P_A)/K_A.
    fn gas_energy(&self, rho: f64, p: f64, y: f64) -> Result<f64, EosError> {
        if !(rho.is_finite() && rho > 0.0 && p.is_finite() && (0.0..=1.0).contains(&y)) {
            return Err(EosError::OutOfRange {
                eos: "products_in_air",
                detail: format!(
                    "density {rho} kg/m³, pressure {p} Pa and mass fraction {y}: need ρ > 0, finite p and 0 ≤ Y ≤ 1"
                ),
            });
        }
        let (pp, kp) = self.products.affine(rho);
        let (pa, ka) = self.air.affine(rho);
        Ok(y * (p - pp) / kp + (1.0 - y) * (p - pa) / ka)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use brisance_eos::{IdealGas, Jwl};
    use proptest::prelude::*;

    fn mix() -> ProductsInAir<Jwl, IdealGas> {
        ProductsInAir::new(Jwl::tnt(), IdealGas::air()).unwrap()
    }

    #[test]
    fn pure_air_is_the_ideal_gas() {
        let m = mix();
        let (rho, e) = (1.2, 2.5e5);
        // (γ − 1)ρe = 0.4 · 1.2 · 2.5e5 = 1.2e5 Pa
        let p = m.gas_pressure(rho, e, 0.0);
        assert!((p - 1.2e5).abs() < 1e-9 * 1.2e5, "{p}");
        let c = IdealGas::air().sound_speed(rho, e);
        assert!((m.gas_sound_speed(rho, e, 0.0) - c).abs() < 1e-9 * c);
        assert!((m.gas_energy(rho, 1.2e5, 0.0).unwrap() - e).abs() < 1e-9 * e);
    }

    #[test]
    fn pure_products_are_the_jwl() {
        let m = mix();
        let jwl = Jwl::tnt();
        for (rho, e) in [(1630.0, 4.0e6), (400.0, 2.0e6), (1.0, 3.0e5)] {
            let p = m.gas_pressure(rho, e, 1.0);
            let pj = jwl.pressure(rho, e);
            assert!((p - pj).abs() < 1e-10 * pj.abs(), "{rho}: {p} vs {pj}");
            let c = m.gas_sound_speed(rho, e, 1.0);
            let cj = jwl.sound_speed(rho, e);
            assert!((c - cj).abs() < 1e-9 * cj, "{rho}: {c} vs {cj}");
        }
    }

    #[test]
    fn half_and_half_mix_is_hand_computed() {
        // Two ideal gases (γ = 1.4 and 3, unit ρ₀, cv) so every number is
        // exact: at ρ = 2, K_1 = 0.4·2 = 0.8, K_2 = 2·2 = 4, P_k = 0.
        // S = 0.5/0.8 + 0.5/4 = 0.75; e = 3 → p = 3/0.75 = 4.
        let m =
            ProductsInAir::new(IdealGas::new(3.0, 1.0, 1.0), IdealGas::new(1.4, 1.0, 1.0)).unwrap();
        assert!((m.gas_pressure(2.0, 3.0, 0.5) - 4.0).abs() < 1e-14);
        // component energies: e_P = 4/4 = 1, e_A = 4/0.8 = 5; ½(1 + 5) = 3
        let (ep, ea) = m.component_energies(2.0, 3.0, 0.5);
        assert!((ep - 1.0).abs() < 1e-14 && (ea - 5.0).abs() < 1e-14);
        assert!((m.gas_energy(2.0, 4.0, 0.5).unwrap() - 3.0).abs() < 1e-14);
        // c² = ∂p/∂ρ|e + p/(ρ²S): ∂p/∂ρ = p/ρ = 2 (K_k ∝ ρ), p/(ρ²S) = 4/3
        let c2: f64 = 2.0 + 4.0 / 3.0;
        assert!((m.gas_sound_speed(2.0, 3.0, 0.5) - c2.sqrt()).abs() < 1e-14);
        // T_P = 1/1, T_A = 5/1, equal cv: T = 3
        assert!((m.gas_temperature(2.0, 3.0, 0.5) - 3.0).abs() < 1e-14);
    }

    #[test]
    fn half_and_half_tnt_in_air_is_hand_computed() {
        // Low density, where JWL's exponential terms vanish to round-off:
        // ρ = 1, V = 1630: A e^{−R1 V} = 0 exactly, so P_P = 0, K_P = ω = 0.3,
        // K_A = 0.4. S = 0.5/0.3 + 0.5/0.4 = 35/12; e = 3.5e5 → p = 1.2e5.
        let m = mix();
        let jwl = Jwl::tnt();
        assert_eq!(jwl.pressure(1.0, 0.0), 0.0);
        let p = m.gas_pressure(1.0, 3.5e5, 0.5);
        assert!((p - 1.2e5).abs() < 1e-9 * 1.2e5, "{p}");
        assert!((m.gas_energy(1.0, 1.2e5, 0.5).unwrap() - 3.5e5).abs() < 1e-6);
    }

    #[test]
    fn stiffless_law_is_refused_and_bad_fraction_named() {
        // γ = 1: ∂p/∂e = 0, the rule would divide by zero.
        let err = ProductsInAir::new(Jwl::tnt(), IdealGas::new(1.0, 718.0, 1.2)).unwrap_err();
        assert!(err.contains("air"), "{err}");
        let m = mix();
        let e = m.gas_energy(1.0, 1e5, 1.5).unwrap_err().to_string();
        assert!(e.contains("mass fraction"), "{e}");
    }

    proptest! {
        /// Pressure equilibrium: the component energies at the mixture
        /// pressure add up by mass to the cell energy, and each gives back
        /// the mixture pressure through its own law.
        #[test]
        fn components_share_the_pressure(rho in 0.5..2000.0f64, e in 1.0e5..6.0e6f64, y in 0.0..1.0f64) {
            let m = mix();
            let p = m.gas_pressure(rho, e, y);
            let (ep, ea) = m.component_energies(rho, e, y);
            prop_assert!((y * ep + (1.0 - y) * ea - e).abs() < 1e-9 * e.abs().max(ep.abs()).max(ea.abs()));
            let pa = IdealGas::air().pressure(rho, ea);
            prop_assert!((pa - p).abs() < 1e-8 * p.abs().max(1.0));
        }

        /// The sound speed is √(∂p/∂ρ|s) at frozen Y: compare with a centred
        /// difference along the isentrope de = (p/ρ²) dρ.
        #[test]
        fn sound_speed_matches_the_isentropic_derivative(rho in 1.0..1500.0f64, e in 3.0e5..5.0e6f64, y in 0.0..1.0f64) {
            let m = mix();
            let p = m.gas_pressure(rho, e, y);
            prop_assume!(p > 0.0);
            let h = 1e-5 * rho;
            let de = p / (rho * rho) * h;
            let dp = (m.gas_pressure(rho + h, e + de, y) - m.gas_pressure(rho - h, e - de, y)) / (2.0 * h);
            let c = m.gas_sound_speed(rho, e, y);
            prop_assert!((c * c - dp).abs() < 1e-4 * dp.abs(), "{} vs {}", c * c, dp);
        }
    }
}
