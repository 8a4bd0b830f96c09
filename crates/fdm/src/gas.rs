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
pub struct ProductsInAir<P: Eos, A: Eos> {
    /// Detonation products.
    pub products: P,
    /// Ambient gas.
    pub air: A,
}

/// (P_k, K_k, ∂P_k/∂ρ, ∂K_k/∂ρ) of an affine-in-e law at density ρ.
#[inline(always)]
fn affine<E: Eos>(eos: &E, rho: f64) -> (f64, f64) {
    (eos.pressure(rho, 0.0), eos.dp_de(rho, 0.0))
}

impl<P: Eos, A: Eos> ProductsInAir<P, A> {
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
    #[inline(always)]
    fn pressure_and_s(&self, rho: f64, e: f64, y: f64) -> (f64, f64) {
        let (pp, kp) = affine(&self.products, rho);
        let (pa, ka) = affine(&self.air, rho);
        let s = y / kp + (1.0 - y) / ka;
        ((e + y * pp / kp + (1.0 - y) * pa / ka) / s, s)
    }

    /// Specific energies (e_P, e_A) of the components at the equilibrium
    /// pressure.
    pub fn component_energies(&self, rho: f64, e: f64, y: f64) -> (f64, f64) {
        let (p, _) = self.pressure_and_s(rho, e, y);
        let (pp, kp) = affine(&self.products, rho);
        let (pa, ka) = affine(&self.air, rho);
        ((p - pp) / kp, (p - pa) / ka)
    }
}

impl<P: Eos, A: Eos> GasLaw for ProductsInAir<P, A> {
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
        let (p, s) = self.pressure_and_s(rho, e, y);
        let term = |eos: &dyn Eos| {
            let (pk, kk) = (eos.pressure(rho, 0.0), eos.dp_de(rho, 0.0));
            let dpk = eos.dp_drho(rho, 0.0);
            let dkk = eos.dp_drho(rho, 1.0) - dpk;
            dpk / kk - (pk - p) * dkk / (kk * kk)
        };
        let dp_drho = (y * term(&self.products) + (1.0 - y) * term(&self.air)) / s;
        let c2 = dp_drho + p / (rho * rho * s);
        c2.max(0.0).sqrt()
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
        let (pp, kp) = affine(&self.products, rho);
        let (pa, ka) = affine(&self.air, rho);
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
