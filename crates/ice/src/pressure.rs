//! Steps 5 and 6 of seed 000 §3.3: the time-advanced pressure estimate
//! and the face pressure.

/// Pressure increment Δp of one cell (seed 000 eq 20):
///
/// Δp = Δt (Σ_r v_r Γ_r − Σ_r ∇·(θ*_r u*_r)) / Σ_r θ_r κ_r
///
/// `volume_source` is Σ v_r Γ_r (1/s; zero without reactions),
/// `volume_flux_divergence` is Σ_r ∇·(θ*_r u*_r) (1/s) and
/// `theta_kappa` is Σ_r θ_r κ_r (1/Pa). κ_r is the isentropic
/// compressibility v_r/c_r² (Kashiwa & Rauenzahn, seed 000 ref 8, and
/// Uintah's ICE): the increment is an acoustic response, see
/// `docs/physics/ice/steps.md`. The time-advanced pressure is then
/// p = p_eq + Δp (eq 21).
#[inline]
pub fn pressure_increment(
    dt: f64,
    volume_source: f64,
    volume_flux_divergence: f64,
    theta_kappa: f64,
) -> f64 {
    dt * (volume_source - volume_flux_divergence) / theta_kappa
}

/// Face pressure p* between cells L and R (seed 000 eq 22):
///
/// p* = (p_L/ρ_L + p_R/ρ_R) / (1/ρ_L + 1/ρ_R) = (p_L ρ_R + p_R ρ_L)/(ρ_L + ρ_R)
///
/// with ρ the sum of all materials' averaged densities in the cell
/// (kg/m³) and p the time-advanced pressure of eq 21 (Pa). The second form
/// is used: it needs no reciprocal of a small density.
#[inline]
pub fn face_pressure(p_l: f64, rho_l: f64, p_r: f64, rho_r: f64) -> f64 {
    (p_l * rho_r + p_r * rho_l) / (rho_l + rho_r)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn compression_raises_the_pressure() {
        // Net inflow of volume (divergence −2 /s) over Δt = 0.01 s into a
        // mixture with Σθκ = 1e-5 /Pa: Δp = 0.01·2/1e-5 = 2000 Pa.
        assert!((pressure_increment(0.01, 0.0, -2.0, 1e-5) - 2000.0).abs() < 1e-9);
        // A reaction volume source of 1 /s against an outflow of 1 /s: no change.
        assert_eq!(pressure_increment(0.01, 1.0, 1.0, 1e-5), 0.0);
    }

    #[test]
    fn face_pressure_leans_to_the_lighter_side() {
        // (p_L/ρ_L + p_R/ρ_R)/(1/ρ_L + 1/ρ_R) with p 3, 1 and ρ 1, 3:
        // (3 + 1/3)/(1 + 1/3) = 2.5
        assert!((face_pressure(3.0, 1.0, 1.0, 3.0) - 2.5).abs() < 1e-15);
        assert_eq!(face_pressure(2.0, 5.0, 2.0, 5.0), 2.0);
    }
}
