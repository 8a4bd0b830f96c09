//! The adaptive artificial viscosity of seed 001 eqs 3–5 (Zhang 2010).
//!
//! Eq 3 smooths U before each directional operator,
//! Ū_i = U_i + ½ η θ_i (U_{i+1} − 2U_i + U_{i−1}), with the switch θ of
//! eq 4 built from density jumps and η from eq 5. We apply it in
//! conservative flux form,
//! Ū_i = U_i + μ_{i+½}(U_{i+1} − U_i) − μ_{i−½}(U_i − U_{i−1}),
//! μ_{i+½} = ½ η_{i+½} max(θ_{i−1}, θ_i, θ_{i+1}, θ_{i+2}),
//! which equals eq 3 wherever θ and η are locally constant and, unlike the
//! pointwise form, conserves mass, momentum and energy to round-off. The
//! switch is taken over the four cells around the face because Harten's θ
//! vanishes in the middle of a shock smeared over a few cells, exactly where
//! Lax–Wendroff's dispersive overshoot sits (Sod at 400 cells: 6.8 % density
//! overshoot with the two-cell maximum, 5.3 % with four).
//! `docs/physics/fdm.md` gives the reasoning.

use serde::{Deserialize, Serialize};

/// How η of seed 001 eq 3 is chosen.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, Default)]
pub enum ArtificialViscosity {
    /// η = ν(1 − ν) with the local acoustic Courant number ν = c Δt/Δx
    /// (seed 001 eq 5), averaged over the two cells of a face.
    #[default]
    Adaptive,
    /// A constant η "adjusted empirically" (the alternative in seed 001 §2.1).
    Constant(f64),
    /// No smoothing: the bare Lax–Wendroff scheme.
    Off,
}

/// The switch θ_i of seed 001 eq 4 from the density at i−1, i, i+1.
///
/// As printed, eq 4 has no outer absolute value and would turn negative
/// (anti-diffusive) where the density jump shrinks; we use Harten's switch
/// θ = ||Δ₊| − |Δ₋|| / (|Δ₊| + |Δ₋|) ∈ [0, 1], which is what the printed
/// form intends (θ → 1 at a jump, → 0 in smooth flow), and θ = 0 where the
/// density is uniform.
#[inline(always)]
pub fn switch_theta(rho_m: f64, rho_0: f64, rho_p: f64) -> f64 {
    let dp = (rho_p - rho_0).abs();
    let dm = (rho_0 - rho_m).abs();
    // Branch-free so the kernel vectorises: where both jumps vanish the
    // numerator is 0 and the floor only avoids 0/0.
    (dp - dm).abs() / (dp + dm).max(f64::MIN_POSITIVE)
}

/// η of seed 001 eq 5 for an acoustic Courant number ν (clamped to [0, 1]).
#[inline(always)]
#[allow(clippy::manual_clamp)]
pub fn adaptive_eta(nu: f64) -> f64 {
    // Plain comparisons rather than f64::clamp so the kernel loop vectorises.
    let nu = if nu < 0.0 {
        0.0
    } else if nu > 1.0 {
        1.0
    } else {
        nu
    };
    nu * (1.0 - nu)
}

/// μ = ½ η θ, the face coefficient of the flux-form eq 3.
#[inline(always)]
pub fn face_mu(eta: f64, theta_face: f64) -> f64 {
    0.5 * eta * theta_face
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    #[test]
    fn switch_is_one_at_a_step_and_zero_on_a_linear_ramp() {
        assert_eq!(switch_theta(1.0, 1.0, 0.125), 1.0);
        assert_eq!(switch_theta(1.0, 2.0, 3.0), 0.0);
        assert_eq!(switch_theta(5.0, 5.0, 5.0), 0.0);
        // |Δ₊| = 1, |Δ₋| = 3: θ = 2/4
        assert_eq!(switch_theta(0.0, 3.0, 4.0), 0.5);
    }

    #[test]
    fn adaptive_eta_is_the_gap_between_upwind_and_lax_wendroff_diffusion() {
        assert_eq!(adaptive_eta(0.5), 0.25);
        assert_eq!(adaptive_eta(1.0), 0.0);
        assert_eq!(adaptive_eta(0.0), 0.0);
        assert_eq!(adaptive_eta(1.5), 0.0);
        assert!((adaptive_eta(0.8) - 0.16).abs() < 1e-15);
    }

    proptest! {
        #[test]
        fn switch_lies_in_unit_interval(a in -1e3..1e3f64, b in -1e3..1e3f64, c in -1e3..1e3f64) {
            let t = switch_theta(a, b, c);
            prop_assert!((0.0..=1.0).contains(&t));
        }

        #[test]
        fn face_coefficient_keeps_the_smoothing_monotone(t in 0.0..1.0f64, n1 in 0.0..1.0f64, n2 in 0.0..1.0f64) {
            // μ ≤ 1/8 keeps Ū a convex combination of neighbours.
            let mu = face_mu(adaptive_eta(0.5 * (n1 + n2)), t);
            prop_assert!((0.0..=0.125).contains(&mu));
        }
    }
}
