//! Materials of the lattice and the scalar force law of one spring
//! (seed 003 §2.1, eqs 5–6, fig. 2).
//!
//! A spring of reference vector ξ carries the axial force
//!
//! F = k∞ (s − s_p) + k₁ (s − δ) + c ṡ,   s = |η + ξ| − |ξ|,  ṡ = n·(u′ − u)
//!
//! with k∞ = E|ξ| (seed 003: k = E|l₀|), a Maxwell arm (k₁ = E₁|ξ|,
//! c₁ = η₁|ξ|, dashpot extension δ), a parallel dashpot c = (η + E″/ω)|ξ|
//! (viscous plus the hysteretic μ = E″|ξ| of eq 5 taken as the equivalent
//! viscous coefficient μ/ω at a reference angular frequency ω), plastic
//! extension s_p with linear hardening (a piecewise-linear force–extension
//! curve, fig. 2) and fracture when s/|ξ| exceeds the fracture strain.
//! The three arrangements of [`Damping`] are special cases.

use brisance_eos::MieGruneisenThermal;
use serde::{Deserialize, Serialize};

/// Arrangement of springs and dashpots in a bond (seed 003 §2.1 "springs
/// and dampers in series and/or parallel").
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub enum Damping {
    /// No dashpot.
    #[default]
    None,
    /// Kelvin–Voigt: spring E|ξ| parallel to a dashpot η|ξ| (eq 5's c).
    KelvinVoigt {
        /// Dashpot modulus η, Pa·s.
        viscosity: f64,
    },
    /// Maxwell: spring E|ξ| in series with a dashpot η|ξ|; relaxation
    /// time η/E.
    Maxwell {
        /// Dashpot modulus η, Pa·s.
        viscosity: f64,
    },
    /// Standard linear solid (Zener): spring E|ξ| parallel to a Maxwell
    /// arm (E₁|ξ| in series with η₁|ξ|).
    StandardLinear {
        /// Arm spring modulus E₁, Pa.
        arm_modulus: f64,
        /// Arm dashpot modulus η₁, Pa·s.
        arm_viscosity: f64,
    },
}

/// Hysteretic damping of eq 5, (k + iμ) with μ = E″|ξ|, used in the time
/// domain as the viscous coefficient μ/ω at the reference angular
/// frequency ω.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Hysteretic {
    /// Loss modulus E″, Pa.
    pub loss_modulus: f64,
    /// Reference angular frequency ω, rad/s.
    pub frequency: f64,
}

/// Piecewise-linear plastic spring (seed 003 fig. 2): elastic slope k up
/// to the yield strain, then slope `hardening_ratio · k`; unloading is
/// elastic and the rest length moves with the plastic extension.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Plasticity {
    /// Yield strain ε_y = s/|ξ| at first yield.
    pub yield_strain: f64,
    /// Plastic slope over elastic slope, in [0, 1).
    pub hardening_ratio: f64,
}

/// A lattice material. In a scenario file every field but `young` and
/// `eos` may be left out (no damping, plasticity, fracture, f⊥, heat
/// conduction or chemistry); `name` is the key of the material map.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LatticeMaterial {
    /// Name, for messages.
    #[serde(default)]
    pub name: String,
    /// Young's modulus E, Pa (k = E|ξ|).
    pub young: f64,
    /// Thermal EOS (seed 003 eqs 12–14); its ρ₀ is the density and
    /// ρ₀c₀² the bulk modulus K of eq 11.
    pub eos: MieGruneisenThermal,
    /// Thermal conductivity κ, W/(m·K).
    #[serde(default)]
    pub conductivity: f64,
    /// Spring/dashpot arrangement.
    #[serde(default)]
    pub damping: Damping,
    /// Hysteretic damping, if any.
    #[serde(default)]
    pub hysteretic: Option<Hysteretic>,
    /// Plastic springs, if any.
    #[serde(default)]
    pub plasticity: Option<Plasticity>,
    /// Fracture strain (tension); `None` for unbreakable springs.
    #[serde(default)]
    pub fracture_strain: Option<f64>,
    /// Modulus of the perpendicular corrective force (eq 10b f⊥), Pa; 0
    /// switches it off.
    #[serde(default)]
    pub perpendicular_modulus: f64,
    /// Chemical enthalpy h_k of this material's component (eq 10c), J/kg.
    #[serde(default)]
    pub enthalpy: f64,
}

impl LatticeMaterial {
    /// An elastic material without damping, plasticity or fracture.
    pub fn elastic(name: &str, young: f64, eos: MieGruneisenThermal) -> Self {
        Self {
            name: name.to_string(),
            young,
            eos,
            conductivity: 0.0,
            damping: Damping::None,
            hysteretic: None,
            plasticity: None,
            fracture_strain: None,
            perpendicular_modulus: 0.0,
            enthalpy: 0.0,
        }
    }

    /// Checks the parameters; the message names the field.
    pub fn validate(&self) -> Result<(), String> {
        let name = &self.name;
        let pos = |field: &str, v: f64| -> Result<(), String> {
            if v > 0.0 && v.is_finite() {
                Ok(())
            } else {
                Err(format!(
                    "lattice material `{name}`: field `{field}` = {v}, expected a finite value > 0"
                ))
            }
        };
        let nonneg = |field: &str, v: f64| -> Result<(), String> {
            if v >= 0.0 && v.is_finite() {
                Ok(())
            } else {
                Err(format!(
                    "lattice material `{name}`: field `{field}` = {v}, expected a finite value ≥ 0"
                ))
            }
        };
        pos("young", self.young)?;
        self.eos
            .validate()
            .map_err(|e| format!("lattice material `{name}`: field `eos`: {e}"))?;
        nonneg("conductivity", self.conductivity)?;
        nonneg("perpendicular_modulus", self.perpendicular_modulus)?;
        if !self.enthalpy.is_finite() {
            return Err(format!(
                "lattice material `{name}`: field `enthalpy` = {}, expected a finite value",
                self.enthalpy
            ));
        }
        match self.damping {
            Damping::None => {}
            Damping::KelvinVoigt { viscosity } => nonneg("damping.viscosity", viscosity)?,
            Damping::Maxwell { viscosity } => pos("damping.viscosity", viscosity)?,
            Damping::StandardLinear {
                arm_modulus,
                arm_viscosity,
            } => {
                nonneg("damping.arm_modulus", arm_modulus)?;
                pos("damping.arm_viscosity", arm_viscosity)?;
            }
        }
        if let Some(h) = self.hysteretic {
            nonneg("hysteretic.loss_modulus", h.loss_modulus)?;
            pos("hysteretic.frequency", h.frequency)?;
        }
        if let Some(p) = self.plasticity {
            pos("plasticity.yield_strain", p.yield_strain)?;
            if !(0.0..1.0).contains(&p.hardening_ratio) {
                return Err(format!(
                    "lattice material `{name}`: field `plasticity.hardening_ratio` = {}, expected a value in [0, 1)",
                    p.hardening_ratio
                ));
            }
        }
        if let Some(f) = self.fracture_strain {
            pos("fracture_strain", f)?;
        }
        Ok(())
    }

    /// Bulk modulus K = ρ₀c₀² of eq 11, Pa.
    pub fn bulk_modulus(&self) -> f64 {
        self.eos.rho0 * self.eos.c0 * self.eos.c0
    }
}

/// Spring parameters per unit reference length (multiply by |ξ|) for a
/// pair of materials: the bond is two half-springs in series, so moduli
/// combine harmonically; strains take the smaller of the two.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PairLaw {
    /// Equilibrium spring modulus (k∞/|ξ|), Pa.
    pub k_inf: f64,
    /// Maxwell-arm spring modulus (k₁/|ξ|), Pa; 0 without an arm.
    pub k_arm: f64,
    /// Maxwell-arm dashpot modulus (c₁/|ξ|), Pa·s.
    pub c_arm: f64,
    /// Parallel dashpot modulus (c/|ξ|), Pa·s.
    pub c_par: f64,
    /// Yield strain (∞ without plasticity).
    pub yield_strain: f64,
    /// Hardening modulus H/|ξ| (force per extension per length), Pa.
    pub hardening: f64,
    /// Fracture strain (∞ when unbreakable).
    pub fracture_strain: f64,
    /// Perpendicular corrective modulus, Pa.
    pub k_perp: f64,
}

fn series(a: f64, b: f64) -> f64 {
    if a + b > 0.0 {
        2.0 * a * b / (a + b)
    } else {
        0.0
    }
}

impl PairLaw {
    /// The law of one material's own springs.
    pub fn single(m: &LatticeMaterial) -> Self {
        let hyst = m.hysteretic.map_or(0.0, |h| h.loss_modulus / h.frequency);
        let (k_inf, k_arm, c_arm, c_visc) = match m.damping {
            Damping::None => (m.young, 0.0, 0.0, 0.0),
            Damping::KelvinVoigt { viscosity } => (m.young, 0.0, 0.0, viscosity),
            Damping::Maxwell { viscosity } => (0.0, m.young, viscosity, 0.0),
            Damping::StandardLinear {
                arm_modulus,
                arm_viscosity,
            } => (m.young, arm_modulus, arm_viscosity, 0.0),
        };
        let (yield_strain, hardening) = match m.plasticity {
            Some(p) => (
                p.yield_strain,
                k_inf * p.hardening_ratio / (1.0 - p.hardening_ratio),
            ),
            None => (f64::INFINITY, 0.0),
        };
        Self {
            k_inf,
            k_arm,
            c_arm,
            c_par: c_visc + hyst,
            yield_strain,
            hardening,
            fracture_strain: m.fracture_strain.unwrap_or(f64::INFINITY),
            k_perp: m.perpendicular_modulus,
        }
    }

    /// The law of a bond joining materials `a` and `b`.
    pub fn pair(a: &LatticeMaterial, b: &LatticeMaterial) -> Self {
        let (la, lb) = (Self::single(a), Self::single(b));
        if a == b {
            return la;
        }
        Self {
            k_inf: series(la.k_inf, lb.k_inf),
            k_arm: series(la.k_arm, lb.k_arm),
            c_arm: series(la.c_arm, lb.c_arm),
            c_par: series(la.c_par, lb.c_par),
            yield_strain: la.yield_strain.min(lb.yield_strain),
            hardening: series(la.hardening, lb.hardening),
            fracture_strain: la.fracture_strain.min(lb.fracture_strain),
            k_perp: series(la.k_perp, lb.k_perp),
        }
    }
}

/// Internal state of one spring.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub struct SpringState {
    /// Plastic extension s_p, m.
    pub plastic: f64,
    /// Accumulated plastic extension, m.
    pub accumulated: f64,
    /// Maxwell-arm dashpot extension δ, m.
    pub dashpot: f64,
}

/// Axial force of a spring and its tangents.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AxialForce {
    /// F, N (positive in tension).
    pub force: f64,
    /// ∂F/∂s, N/m.
    pub stiffness: f64,
    /// ∂F/∂ṡ, N·s/m.
    pub damping: f64,
    /// The plastic state after the return mapping.
    pub state: SpringState,
}

impl PairLaw {
    /// Force of a spring of reference length `len0` at extension `s` and
    /// extension rate `sdot`, from the committed `state`; the dashpot
    /// extension δ is held at its committed value (it is advanced by
    /// [`PairLaw::advance_dashpot`] at the end of a step).
    #[inline]
    pub fn axial(&self, len0: f64, s: f64, sdot: f64, state: SpringState) -> AxialForce {
        let k = self.k_inf * len0;
        let mut st = state;
        let trial = k * (s - st.plastic);
        let mut f_eq = trial;
        let mut k_t = k;
        if self.yield_strain.is_finite() && k > 0.0 {
            let h = self.hardening * len0;
            let limit = k * self.yield_strain * len0 + h * st.accumulated;
            if trial.abs() > limit {
                let dl = (trial.abs() - limit) / (k + h);
                let sign = trial.signum();
                st.plastic += sign * dl;
                st.accumulated += dl;
                f_eq = trial - sign * k * dl;
                k_t = k * h / (k + h);
            }
        }
        let k1 = self.k_arm * len0;
        let c = self.c_par * len0;
        AxialForce {
            force: f_eq + k1 * (s - st.dashpot) + c * sdot,
            stiffness: k_t + k1,
            damping: c,
            state: st,
        }
    }

    /// Advances the Maxwell-arm dashpot over `dt` at the end-of-step
    /// extension `s`: δ̇ = k₁(s − δ)/c₁ solved exactly for constant s.
    #[inline]
    pub fn advance_dashpot(&self, dashpot: f64, s: f64, dt: f64) -> f64 {
        if self.k_arm > 0.0 && self.c_arm > 0.0 {
            s - (s - dashpot) * (-self.k_arm / self.c_arm * dt).exp()
        } else {
            dashpot
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn mat() -> LatticeMaterial {
        LatticeMaterial::elastic("m", 2.0e9, MieGruneisenThermal::estane_seed003())
    }

    #[test]
    fn elastic_spring_is_e_times_length() {
        let law = PairLaw::single(&mat());
        let f = law.axial(0.5, 1e-3, 0.0, SpringState::default());
        // k = 2e9 · 0.5 = 1e9 N/m; F = 1e6 N.
        assert_eq!(f.force, 1.0e6);
        assert_eq!(f.stiffness, 1.0e9);
        assert_eq!(f.damping, 0.0);
    }

    #[test]
    fn plastic_spring_is_piecewise_linear() {
        let mut m = mat();
        m.young = 1.0;
        m.plasticity = Some(Plasticity {
            yield_strain: 0.1,
            hardening_ratio: 0.25,
        });
        let law = PairLaw::single(&m);
        // len0 = 2: k = 2, yield at s = 0.2 (F = 0.4); beyond, slope 0.5.
        let f = law.axial(2.0, 0.2, 0.0, SpringState::default());
        assert!((f.force - 0.4).abs() < 1e-15);
        let f = law.axial(2.0, 0.6, 0.0, SpringState::default());
        assert!((f.force - (0.4 + 0.5 * 0.4)).abs() < 1e-15);
        assert!((f.stiffness - 0.5).abs() < 1e-15);
        // Unload elastically from s = 0.6: s_p = 0.6 − 0.6/2 = 0.3.
        assert!((f.state.plastic - 0.3).abs() < 1e-15);
        let g = law.axial(2.0, 0.5, 0.0, f.state);
        assert!((g.force - 2.0 * (0.5 - 0.3)).abs() < 1e-15);
        assert_eq!(g.stiffness, 2.0);
    }

    #[test]
    fn kelvin_voigt_and_hysteretic_add_a_dashpot() {
        let mut m = mat();
        m.young = 3.0;
        m.damping = Damping::KelvinVoigt { viscosity: 0.5 };
        m.hysteretic = Some(Hysteretic {
            loss_modulus: 2.0,
            frequency: 4.0,
        });
        let law = PairLaw::single(&m);
        // c = (0.5 + 2/4) · 2 = 2; k = 6.
        let f = law.axial(2.0, 0.1, 0.3, SpringState::default());
        assert!((f.force - (0.6 + 0.6)).abs() < 1e-15);
        assert_eq!(f.damping, 2.0);
    }

    #[test]
    fn maxwell_relaxes_exactly() {
        let mut m = mat();
        m.young = 2.0;
        m.damping = Damping::Maxwell { viscosity: 4.0 };
        let law = PairLaw::single(&m);
        // k₁ = 2, c₁ = 4 at len0 1: τ = 2 s. Held at s = 1 from δ = 0.
        let d = law.advance_dashpot(0.0, 1.0, 2.0);
        assert!((d - (1.0 - (-1.0f64).exp())).abs() < 1e-15);
        let f = law.axial(
            1.0,
            1.0,
            0.0,
            SpringState {
                dashpot: d,
                ..SpringState::default()
            },
        );
        assert!((f.force - 2.0 * (-1.0f64).exp()).abs() < 1e-15);
    }

    #[test]
    fn dissimilar_pair_is_two_half_springs_in_series() {
        let a = mat();
        let mut b = mat();
        b.name = "b".into();
        b.young = 6.0e9;
        let law = PairLaw::pair(&a, &b);
        assert!((law.k_inf - 3.0e9).abs() < 1e-3);
    }

    #[test]
    fn validation_names_the_field() {
        let mut m = mat();
        m.young = -1.0;
        assert!(m.validate().unwrap_err().contains("`young`"));
        let mut m = mat();
        m.plasticity = Some(Plasticity {
            yield_strain: 0.1,
            hardening_ratio: 1.0,
        });
        assert!(m
            .validate()
            .unwrap_err()
            .contains("plasticity.hardening_ratio"));
        assert!(mat().validate().is_ok());
    }
}
