//! Peridynamic materials of seed 004: proportional solids (eqs 7–8, 28) and
//! detonation products as peridynamic gases (eqs 16–19, 29–30).
//!
//! **Proportional solids.** The bond force is g(s) = c · (s − s_p) clamped
//! by the yield stretch (eq 8 with a piecewise-linear g), where c is the
//! micro-modulus:
//!
//! - 3D: c = k_PD = 18K/(πδ⁴) (eq 28), K = ρ c_b² from the bulk sound
//!   speed c_b the seed's examples give;
//! - 1D bar of cross-section A: c = 2E/(Aδ²) (Silling & Askari 2005), with
//!   E = 3K(1 − 2ν) = 3K/2 for the ν = 1/4 of bond-based peridynamics, so
//!   the same (ρ, c_b) describe the same solid in 1D and 3D.
//!
//! The yield stretch is s_Y = σ_Y/E: a bond along the axis of a bar in
//! uniaxial tension yields when the bar reaches σ_Y. A micro-elastic bond
//! follows g = c·clamp(s, −s_Y, s_Y) up and down (reversible); a
//! micro-plastic bond loads the same way but unloads on a line shifted by
//! its plastic stretch s_p (g = c(s − s_p), s_p moved so |s − s_p| ≤ s_Y).
//!
//! **Failure.** A bond breaks irreversibly when s exceeds its critical
//! stretch; a broken bond carries no force again. The bond's critical
//! stretch is min(s_c(x_i), s_c(x_j)) with the node value
//!
//! ```text
//! s_c(x) = s_c0 (1 + α_D φ(x)) − α_min min(s_min(x), 0)
//! ```
//!
//! φ the node's damage (broken fraction of its bonds) and s_min the
//! smallest stretch among its intact bonds at the previous step. Seed 004
//! (footnote c) used a "damage stretch coefficient" α_D and a "minimum
//! stretch coefficient" α_min for its steel and says only that these
//! models "increase the critical \[stretch\] as damage increases or in
//! compression, respectively"; it gives no formula and cites no paper for
//! either (the footnote carries no reference number). So no source is
//! cited here for the damage-stretch term: its form, linear in φ, is
//! Brisance's choice. The minimum-stretch form is that of Silling &
//! Askari, "A meshfree method based on the peridynamic model of solid
//! mechanics", Computers and Structures 83, 1526–1535, 2005 (seed 004
//! ref 3, which the seed cites for the accuracy of eq 10 and the stability
//! condition, not in the footnote): s₀ = s₀₀ − α s_min, α = 0.25 there,
//! here only allowed to raise s_c. Both coefficients default
//! to 0 (plain critical stretch).

use brisance_reaction::ProductsIsentrope;
use serde::{Deserialize, Serialize};

use crate::strength::StretchSpread;

/// How a proportional bond unloads.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum ProportionalKind {
    /// Reversible: unloads along the loading curve.
    MicroElastic,
    /// Unloads on a line shifted by the plastic stretch.
    MicroPlastic,
}

/// A proportional solid (seed 004 eqs 7–8).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Proportional {
    /// Reference density, kg/m³.
    pub density: f64,
    /// Bulk sound speed c_b = √(K/ρ), m/s.
    pub sound_speed: f64,
    /// Yield strength σ_Y, Pa (infinite: no yield).
    pub yield_strength: f64,
    /// Critical stretch s_c0 (infinite: no failure).
    pub critical_stretch: f64,
    /// Micro-elastic or micro-plastic.
    pub kind: ProportionalKind,
    /// Damage-stretch coefficient α_D (≥ 0): the node's critical stretch is
    /// s_c0 (1 + α_D φ), φ its damage. Seed 004 footnote c names the model
    /// without a formula or a reference; the linear form is Brisance's
    /// choice (module docs).
    pub damage_stretch_coefficient: f64,
    /// Minimum-stretch coefficient α_min (≥ 0): the node's critical stretch
    /// gains −α_min min(s_min, 0), s_min the smallest stretch of its intact
    /// bonds (the form of Silling & Askari 2005, seed 004 ref 3; the seed's
    /// footnote c names the model without a reference).
    pub minimum_stretch_coefficient: f64,
    /// A critical stretch that varies over the material (None: the same
    /// s_c0 everywhere, seed 004 as printed): the node's s_c0 is multiplied
    /// by a Weibull strength factor of median 1 drawn per grain
    /// ([`crate::strength`]).
    #[serde(default)]
    pub spread: Option<StretchSpread>,
}

impl Proportional {
    /// The copper case of seed 004's cylinder test: ρ 8930 kg/m³, bulk
    /// sound speed 3602 m/s, yield 324 MPa, critical stretch 2.0,
    /// micro-elastic as the seed's "proportional model", no damage terms.
    pub fn seed_004_copper() -> Self {
        Self {
            density: 8930.0,
            sound_speed: 3602.0,
            yield_strength: 324.0e6,
            critical_stretch: 2.0,
            kind: ProportionalKind::MicroElastic,
            damage_stretch_coefficient: 0.0,
            minimum_stretch_coefficient: 0.0,
            spread: None,
        }
    }

    /// Bulk modulus K = ρ c_b², Pa.
    pub fn bulk_modulus(&self) -> f64 {
        self.density * self.sound_speed * self.sound_speed
    }

    /// Young's modulus of bond-based peridynamics, E = 3K/2 (ν = 1/4), Pa.
    pub fn youngs_modulus(&self) -> f64 {
        1.5 * self.bulk_modulus()
    }

    /// Yield stretch s_Y = σ_Y / E.
    pub fn yield_stretch(&self) -> f64 {
        self.yield_strength / self.youngs_modulus()
    }

    /// Checks every parameter; the error names the field.
    pub fn validate(&self) -> Result<(), String> {
        let pos = |field: &str, v: f64| {
            if v > 0.0 && v.is_finite() {
                Ok(())
            } else {
                Err(format!("`{field}` = {v}: expected a finite value > 0"))
            }
        };
        pos("density", self.density)?;
        pos("sound_speed", self.sound_speed)?;
        if !(self.yield_strength > 0.0) {
            return Err(format!(
                "`yield_strength` = {}: expected a value > 0 (inf for none)",
                self.yield_strength
            ));
        }
        if !(self.critical_stretch > 0.0) {
            return Err(format!(
                "`critical_stretch` = {}: expected a value > 0 (inf for none)",
                self.critical_stretch
            ));
        }
        for (f, v) in [
            (
                "damage_stretch_coefficient",
                self.damage_stretch_coefficient,
            ),
            (
                "minimum_stretch_coefficient",
                self.minimum_stretch_coefficient,
            ),
        ] {
            if !(v >= 0.0 && v.is_finite()) {
                return Err(format!("`{f}` = {v}: expected a finite value ≥ 0"));
            }
        }
        if let Some(spread) = &self.spread {
            spread.validate()?;
        }
        Ok(())
    }
}

/// Detonation products as a peridynamic gas (seed 004 eqs 16–19).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Gas {
    /// Density of the unreacted explosive ρ₀, kg/m³ (X = 1 there).
    pub density: f64,
    /// Detonation velocity used by program burn, m/s.
    pub detonation_velocity: f64,
    /// The products isentrope P_S(X).
    pub isentrope: ProductsIsentrope,
    /// The unreacted explosive's response before its detonation time
    /// (None: none; the products then do not push explosive ahead of the
    /// front, `docs/physics/pd/program_burn.md`).
    #[serde(default)]
    pub reactant: Option<Reactant>,
}

/// The unreacted explosive as a peridynamic gas of the Murnaghan equation
/// of state (seed 000 eq 33, the JWL++ reactant; seed 004 is silent on the
/// explosive ahead of the front), written in the expansion X of seed 004
/// eq 17 (X = v/v₀ = ρ₀/ρ):
///
/// ```text
/// P_u(X) = (X^{−n} − 1)/(nκ),
/// W_u(X) = −∫₁^X P_u dX' = [(X^{1−n} − 1)/(n − 1) + X − 1]/(nκ)
/// ```
///
/// per unit reference volume. It goes through the same pair force as the
/// products (eqs 18–19 hold for any P(X)), so the products' push on the
/// explosive ahead of the front is resisted and the pair force stays odd
/// (eq 2). X = 1 is force-free; tension (X > 1) gives the bounded
/// P_u → −1/(nκ).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Reactant {
    /// n = dK/dP, dimensionless (> 1).
    pub n: f64,
    /// κ = 1/K₀, compressibility at zero pressure, 1/Pa.
    pub kappa: f64,
}

impl Reactant {
    /// Cast TNT from its shock Hugoniot U_s = c₀ + s u_p, c₀ = 2390 m/s,
    /// s = 2.05 (LASL Shock Hugoniot Data, Marsh 1980, TNT at
    /// 1.614 g/cm³): K₀ = ρ₀c₀² at the JWL set's ρ₀ = 1630 kg/m³
    /// (9.311 GPa) and n = 4s − 1 = 7.2, the Murnaghan slope with the same
    /// first-order Hugoniot (K' = 4s − 1).
    pub fn tnt() -> Self {
        Self {
            n: 7.2,
            kappa: 1.0 / (1630.0 * 2390.0 * 2390.0),
        }
    }

    /// P_u(X), Pa.
    pub fn pressure(&self, x: f64) -> f64 {
        (x.powf(-self.n) - 1.0) / (self.n * self.kappa)
    }

    /// dP_u/dX, Pa.
    pub fn dpressure_dx(&self, x: f64) -> f64 {
        -x.powf(-self.n - 1.0) / self.kappa
    }

    /// W_u(X), J per m³ of reference volume.
    pub fn energy(&self, x: f64) -> f64 {
        ((x.powf(1.0 - self.n) - 1.0) / (self.n - 1.0) + x - 1.0) / (self.n * self.kappa)
    }

    /// Checks the parameters (errors name the field).
    pub fn validate(&self) -> Result<(), String> {
        if !(self.n > 1.0 && self.n.is_finite()) {
            return Err(format!(
                "`reactant.n` = {}: expected a finite value > 1",
                self.n
            ));
        }
        if !(self.kappa > 0.0 && self.kappa.is_finite()) {
            return Err(format!("`reactant.kappa` = {}: expected > 0", self.kappa));
        }
        Ok(())
    }
}

/// A material of the peridynamic solver.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub enum PdMaterial {
    /// Proportional solid.
    Proportional(Proportional),
    /// Detonation products.
    Gas(Gas),
}

impl PdMaterial {
    /// Reference density, kg/m³.
    pub fn density(&self) -> f64 {
        match self {
            PdMaterial::Proportional(p) => p.density,
            PdMaterial::Gas(g) => g.density,
        }
    }

    /// Bulk modulus the short-range forces use for k_PD (eq 27–28), Pa: the
    /// solid's K; 0 for a gas (a gas–solid pair takes the solid's).
    pub fn contact_bulk_modulus(&self) -> f64 {
        match self {
            PdMaterial::Proportional(p) => p.bulk_modulus(),
            PdMaterial::Gas(_) => 0.0,
        }
    }

    /// Checks the parameters.
    pub fn validate(&self) -> Result<(), String> {
        match self {
            PdMaterial::Proportional(p) => p.validate(),
            PdMaterial::Gas(g) => {
                if !(g.density > 0.0 && g.density.is_finite()) {
                    return Err(format!("`density` = {}: expected > 0", g.density));
                }
                if !(g.detonation_velocity > 0.0 && g.detonation_velocity.is_finite()) {
                    return Err(format!(
                        "`detonation_velocity` = {}: expected > 0",
                        g.detonation_velocity
                    ));
                }
                if !(g.isentrope.reference_pressure() > 0.0) {
                    return Err("products isentrope has no positive reference pressure".into());
                }
                if let Some(r) = g.reactant {
                    r.validate()?;
                }
                Ok(())
            }
        }
    }
}

/// The micro-modulus c of a proportional solid: 18K/(πδ⁴) in 3D (seed 004
/// eq 28), 2E/(Aδ²) in 1D with E = 3K/2.
pub fn micromodulus(
    material: &Proportional,
    dimension: crate::Dimension,
    horizon: f64,
    cross_section: f64,
) -> f64 {
    match dimension {
        crate::Dimension::Three => spring_constant(material.bulk_modulus(), horizon),
        crate::Dimension::One => {
            2.0 * material.youngs_modulus() / (cross_section * horizon * horizon)
        }
    }
}

/// The PD spring constant k_PD = 18K/(πδ⁴), N/m⁶ (seed 004 eq 28).
pub fn spring_constant(bulk_modulus: f64, horizon: f64) -> f64 {
    18.0 * bulk_modulus / (std::f64::consts::PI * horizon.powi(4))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn copper() -> Proportional {
        Proportional::seed_004_copper()
    }

    #[test]
    fn copper_moduli_and_yield_stretch_by_hand() {
        let c = copper();
        // K = 8930 · 3602² = 1.15861427720e11 Pa, E = 1.5 K.
        assert!((c.bulk_modulus() - 1.158_614_277_2e11).abs() < 1.0);
        assert!((c.youngs_modulus() - 1.737_921_415_8e11).abs() < 1.0);
        // s_Y = 324e6 / 1.73792e11 = 1.864296e-3.
        assert!((c.yield_stretch() - 1.864_296e-3).abs() < 1e-9);
    }

    #[test]
    fn spring_constant_is_eq_28() {
        // K = 1e11 Pa, δ = 3 mm: 18e11/(π·8.1e-11) = 7.07355e21 N/m⁶.
        let k = spring_constant(1.0e11, 3.0e-3);
        assert!((k / 7.073_553_026e21 - 1.0).abs() < 1e-9, "{k}");
        let m = micromodulus(&copper(), crate::Dimension::One, 0.03, 1e-4);
        assert!((m - 2.0 * copper().youngs_modulus() / (1e-4 * 9e-4)).abs() < 1.0);
    }

    #[test]
    fn tnt_reactant_by_hand() {
        let r = Reactant::tnt();
        // K₀ = 1630 · 2390² = 9.310723e9 Pa, n = 7.2.
        assert!((1.0 / r.kappa - 9.310_723e9).abs() < 1.0);
        assert_eq!(r.n, 7.2);
        assert_eq!(r.pressure(1.0), 0.0);
        assert_eq!(r.energy(1.0), 0.0);
        // X = 0.8: (0.8^−7.2 − 1)/(7.2 κ) = (4.987... − 1) K₀/7.2.
        let k0 = 1.0 / r.kappa;
        let p = (0.8f64.powf(-7.2) - 1.0) * k0 / 7.2;
        assert!((r.pressure(0.8) / p - 1.0).abs() < 1e-14);
        assert!((r.dpressure_dx(1.0) + k0).abs() < 1e-3);
        // W = [(0.8^−6.2 − 1)/6.2 − 0.2] K₀/7.2.
        let w = ((0.8f64.powf(-6.2) - 1.0) / 6.2 - 0.2) * k0 / 7.2;
        assert!((r.energy(0.8) / w - 1.0).abs() < 1e-13);
    }

    #[test]
    fn reactant_energy_is_minus_the_integral_of_its_pressure() {
        let r = Reactant::tnt();
        for x in [0.7, 0.9, 1.1, 1.5] {
            let h = 1e-6;
            let dw = (r.energy(x + h) - r.energy(x - h)) / (2.0 * h);
            assert!((dw + r.pressure(x)).abs() < 1e-6 * (1.0 / r.kappa), "{x}");
            let dp = (r.pressure(x + h) - r.pressure(x - h)) / (2.0 * h);
            assert!((dp / r.dpressure_dx(x) - 1.0).abs() < 1e-6, "{x}");
        }
    }

    #[test]
    fn reactant_matches_the_eos_crate_murnaghan() {
        // Seed 000 eq 33 in ρ: p(ρ) with ρ = ρ₀/X; e_c(ρ) ρ₀ = W_u(X).
        use brisance_core::Eos;
        let r = Reactant::tnt();
        let m = brisance_eos::Murnaghan {
            n: r.n,
            kappa: r.kappa,
            rho0: 1630.0,
            cv: 1000.0,
            t_ref: 300.0,
        };
        for x in [0.75, 0.95, 1.2] {
            let rho = 1630.0 / x;
            let p = m.pressure(rho, m.compression_energy(rho));
            assert!((p - r.pressure(x)).abs() < 1e-9 * (1.0 / r.kappa), "{x}");
            let w = m.compression_energy(rho) * 1630.0;
            assert!((w - r.energy(x)).abs() < 1e-9 * (1.0 / r.kappa), "{x}");
        }
    }

    #[test]
    fn invalid_reactant_names_the_field() {
        let r = Reactant {
            n: 0.5,
            kappa: 1e-10,
        };
        assert!(r.validate().unwrap_err().contains("reactant.n"));
        let r = Reactant {
            n: 7.0,
            kappa: -1.0,
        };
        assert!(r.validate().unwrap_err().contains("reactant.kappa"));
    }

    #[test]
    fn invalid_material_names_the_field() {
        let mut c = copper();
        c.sound_speed = -1.0;
        assert!(c.validate().unwrap_err().contains("sound_speed"));
        let mut c = copper();
        c.minimum_stretch_coefficient = f64::NAN;
        assert!(c
            .validate()
            .unwrap_err()
            .contains("minimum_stretch_coefficient"));
    }
}
