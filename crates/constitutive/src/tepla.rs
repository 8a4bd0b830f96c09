//! TEPLA-F porosity and failure, seed 000 §4.2 failure criterion 2
//! (eqs 43–46; Johnson & Addessio, J. Appl. Phys. 64 (1988) 6699, seed 000
//! ref \[33\]).
//!
//! **Porosity** f (void volume fraction) evolves by nucleation and growth,
//!
//! ḟ = ḟ_nucl + ḟ_grow                                        (eq 44)
//! ḟ_grow = (1 − f) tr(D_p)                                    (eq 45)
//! ḟ_nucl = f_n/(s_n √(2π)) exp(−½ (ε_p − ε_n)²/s_n²) ε̇_p      (eq 46)
//!
//! (Chu & Needleman 1980, seed 000 ref \[34\]): f_n is the volume fraction of
//! void-nucleating particles, ε_n and s_n the mean and standard deviation of
//! the nucleation strain.
//!
//! Choices where the seed is silent or inconsistent with its own yield
//! condition, following the implementation of the seed's authors (the
//! `ElasticPlasticHP` model of the Uintah code, Banerjee et al.):
//!
//! - **Growth.** Under the von Mises yield condition of seed 000 §4.2 the
//!   plastic flow is isochoric, tr(D_p) ≡ 0, and eq 45 would never act. As
//!   in that implementation, during a yielding step the dilatation of the
//!   step, tr(d) Δt when positive, is taken as the plastic dilatation; a
//!   compressive step does not close voids (porosity never decreases). The
//!   growth is integrated exactly for a constant tr(d) over the step:
//!   1 − f_{n+1} = (1 − f) exp(−tr(d) Δt), which keeps f < 1.
//! - **Nucleation** is integrated over the step's plastic increment Δε_p by
//!   the midpoint rule, Δf = A(ε_pⁿ + Δε_p/2) Δε_p with A(ε) the factor of
//!   ε̇_p in eq 46 (second order; Δε_p ≪ s_n in practice).
//! - **Yield.** Seed 000 uses the von Mises condition (§4.2); the porosity
//!   does not soften the yield surface (no Gurson term). It enters the
//!   failure criterion only.
//! - **f_n** is not given in seed 000; 0.1 is the default of the seed
//!   authors' implementation (Chu & Needleman used 0.04).
//!
//! **Failure** (eq 43): the point fails when
//!
//! (f/f_c)² + (ε_p/ε_p^f)² ≥ 1,
//!
//! where ε_p/ε_p^f is the Johnson–Cook damage D (seed 000 eq 47, see
//! [`crate::damage`]): D = Σ Δε_p/ε_p^f is ε_p/ε_p^f for a constant
//! fracture strain and carries its history otherwise, and its Gaussian
//! initial value spreads the fracture strains as seed 000 §4.2 describes.
//! Without a damage model the second term is zero and the point fails at
//! f ≥ f_c.
//!
//! **Initial porosity** is Gaussian over the points (seed 000 §4.2, §5.3:
//! mean 0.005, standard deviation 0.001), truncated to [0, f_c] unless the
//! config narrows it (see [`crate::random`]).

use crate::{
    error::{non_negative, positive},
    random::Gaussian,
    ConstitutiveError,
};
use serde::{Deserialize, Serialize};

const NAME: &str = "tepla";

/// Porosity never exceeds this (the point has failed long before).
pub const MAX_POROSITY: f64 = 1.0 - 1.0e-9;

/// TEPLA-F porosity evolution and failure (seed 000 eqs 43–46).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Tepla {
    /// Initial porosity f₀ over the points (default truncation [0, f_c]).
    pub initial_porosity: Gaussian,
    /// Critical porosity f_c of eq 43.
    pub critical_porosity: f64,
    /// Volume fraction of void-nucleating particles f_n (eq 46).
    pub nucleation_fraction: f64,
    /// Mean nucleation strain ε_n (eq 46).
    pub nucleation_strain: f64,
    /// Standard deviation of the nucleation strain s_n (eq 46).
    pub nucleation_std_dev: f64,
}

impl Tepla {
    /// 4340 steel, seed 000 §5.3: initial porosity mean 0.005, standard
    /// deviation 0.001; f_c = 0.3; ε_n = 0.3, s_n = 0.1; f_n = 0.1 (not in
    /// the seed: the default of its authors' implementation).
    pub fn steel_4340_seed000() -> Self {
        Self {
            initial_porosity: Gaussian::new(0.005, 0.001),
            critical_porosity: 0.3,
            nucleation_fraction: 0.1,
            nucleation_strain: 0.3,
            nucleation_std_dev: 0.1,
        }
    }

    /// Checks the parameters; the message names the bad field.
    pub fn validate(&self) -> Result<(), ConstitutiveError> {
        let fc = self.critical_porosity;
        if !(fc > 0.0 && fc < 1.0) {
            return Err(ConstitutiveError::InvalidParameter {
                model: NAME,
                field: "critical_porosity",
                value: fc,
                expected: "a fraction in (0, 1)",
            });
        }
        let fnuc = self.nucleation_fraction;
        if !(0.0..1.0).contains(&fnuc) {
            return Err(ConstitutiveError::InvalidParameter {
                model: NAME,
                field: "nucleation_fraction",
                value: fnuc,
                expected: "a fraction in [0, 1)",
            });
        }
        non_negative(NAME, "nucleation_strain", self.nucleation_strain)?;
        positive(NAME, "nucleation_std_dev", self.nucleation_std_dev)?;
        self.initial_porosity
            .validate(NAME, "initial_porosity", 0.0, fc)
    }

    /// The nucleation factor A(ε_p) = f_n/(s_n √(2π)) exp(−½ (ε_p −
    /// ε_n)²/s_n²): ḟ_nucl = A ε̇_p (eq 46).
    #[inline]
    pub fn nucleation_factor(&self, eps_p: f64) -> f64 {
        let s = self.nucleation_std_dev;
        let x = (eps_p - self.nucleation_strain) / s;
        self.nucleation_fraction / (s * (std::f64::consts::TAU).sqrt()) * (-0.5 * x * x).exp()
    }

    /// Porosity after a yielding step: nucleation over the plastic increment
    /// `d_eps_p` from `eps_p` (midpoint rule), then growth by the step's
    /// dilatation `dilatation` = tr(d) Δt when positive (exact for constant
    /// tr d). Never decreases, stays below [`MAX_POROSITY`].
    #[inline]
    pub fn advance(&self, porosity: f64, eps_p: f64, d_eps_p: f64, dilatation: f64) -> f64 {
        let nucleated = if d_eps_p > 0.0 {
            porosity + self.nucleation_factor(eps_p + 0.5 * d_eps_p) * d_eps_p
        } else {
            porosity
        };
        let grown = if dilatation > 0.0 {
            1.0 - (1.0 - nucleated) * (-dilatation).exp()
        } else {
            nucleated
        };
        grown.clamp(porosity, MAX_POROSITY.max(porosity))
    }

    /// The TEPLA-F measure (f/f_c)² + D² of eq 43, D the Johnson–Cook
    /// damage (ε_p/ε_p^f).
    #[inline]
    pub fn criterion(&self, porosity: f64, damage: f64) -> f64 {
        let r = porosity / self.critical_porosity;
        r * r + damage * damage
    }

    /// Whether eq 43 is reached: (f/f_c)² + D² ≥ 1.
    #[inline]
    pub fn fails(&self, porosity: f64, damage: f64) -> bool {
        self.criterion(porosity, damage) >= 1.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A(ε_n) = f_n/(s_n √(2π)) = 0.1/(0.1 × 2.5066283) = 0.3989423; one
    /// standard deviation away it is e^(−½) times that, 0.2419707.
    #[test]
    fn nucleation_factor_is_the_gaussian_density_times_f_n() {
        let t = Tepla::steel_4340_seed000();
        assert!((t.nucleation_factor(0.3) - 0.398_942_3).abs() < 1e-7);
        assert!((t.nucleation_factor(0.4) - 0.241_970_7).abs() < 1e-7);
        assert!((t.nucleation_factor(0.2) - 0.241_970_7).abs() < 1e-7);
    }

    /// Nucleation: from f = 0.005 at ε_p = 0.25, Δε_p = 0.01 adds
    /// A(0.255) × 0.01 = 0.3989423 e^(−½ 0.45²) × 0.01 = 0.0036053, with no
    /// growth in an isochoric step.
    #[test]
    fn nucleation_adds_the_midpoint_density_times_the_increment() {
        let t = Tepla::steel_4340_seed000();
        let f = t.advance(0.005, 0.25, 0.01, 0.0);
        let hand = 0.005 + 0.398_942_3 * (-0.5f64 * 0.45 * 0.45).exp() * 0.01;
        assert!((hand - 0.008_605_3).abs() < 1e-7, "{hand}");
        assert!((f - hand).abs() < 1e-9, "{f}");
    }

    /// Growth: f = 0.005 and tr(d) Δt = 1e-3 give 1 − 0.995 e^(−0.001)
    /// = 0.0059945 (forward Euler: 0.005995); compression does nothing.
    #[test]
    fn growth_follows_the_dilatation_and_never_closes_voids() {
        let t = Tepla {
            nucleation_fraction: 0.0,
            ..Tepla::steel_4340_seed000()
        };
        let f = t.advance(0.005, 0.0, 1e-3, 1e-3);
        assert!((f - 0.005_994_503).abs() < 1e-9, "{f}");
        assert_eq!(t.advance(0.005, 0.0, 1e-3, -1e-3), 0.005);
        // A huge dilatation cannot push f to 1.
        let f = t.advance(0.2, 0.0, 1e-3, 1e3);
        assert!((0.2..1.0).contains(&f), "{f}");
    }

    /// Eq 43 with f_c = 0.3: f = 0.15 (f/f_c = ½) and D = √0.75 = 0.866025
    /// sum to 1 (fails); D = 0.8 gives 0.89 (intact); f = f_c alone fails.
    #[test]
    fn tepla_criterion_is_the_quadratic_sum() {
        let t = Tepla::steel_4340_seed000();
        assert!((t.criterion(0.15, 0.8) - 0.89).abs() < 1e-15);
        assert!(!t.fails(0.15, 0.8));
        assert!(t.fails(0.15, 0.75f64.sqrt() + 1e-12));
        assert!(t.fails(0.3, 0.0));
        assert!(!t.fails(0.299, 0.0));
    }

    #[test]
    fn validate_names_the_bad_field() {
        assert!(Tepla::steel_4340_seed000().validate().is_ok());
        for (bad, field) in [
            (
                Tepla {
                    critical_porosity: 1.2,
                    ..Tepla::steel_4340_seed000()
                },
                "critical_porosity",
            ),
            (
                Tepla {
                    nucleation_std_dev: 0.0,
                    ..Tepla::steel_4340_seed000()
                },
                "nucleation_std_dev",
            ),
            (
                Tepla {
                    nucleation_fraction: -0.1,
                    ..Tepla::steel_4340_seed000()
                },
                "nucleation_fraction",
            ),
            (
                Tepla {
                    initial_porosity: Gaussian::new(0.4, 0.001),
                    ..Tepla::steel_4340_seed000()
                },
                "initial_porosity",
            ),
        ] {
            let msg = bad.validate().unwrap_err().to_string();
            assert!(msg.contains(field), "{msg}");
        }
    }
}
