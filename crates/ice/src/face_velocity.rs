//! Step 3 of seed 000 §3.3: face-centred velocities for the advection.

/// Face-normal velocity u*_r of one material on the face between cells L
/// and R (seed 000 eq 19):
///
/// u*_r = (ρ_L u_L + ρ_R u_R)/(ρ_L + ρ_R)
///        − (2 v_L v_R Δt/(v_L + v_R)) (p_R − p_L)/Δx + g Δt
///
/// `rho_*` are the material's averaged densities ρ_r (kg/m³), `u_*` its
/// face-normal cell velocities (m/s), `v_*` its specific volumes (m³/kg),
/// `p_*` the cells' equilibration pressures (Pa), `dx` the distance between
/// the cell centres (m) and `g` the face-normal gravity (m/s²). The
/// exchange at faces (seed 000 step 3, last paragraph) is applied
/// afterwards by [`crate::exchange::momentum_exchange`] on the face
/// values.
#[allow(clippy::too_many_arguments)]
#[inline]
pub fn face_velocity(
    rho_l: f64,
    u_l: f64,
    v_l: f64,
    p_l: f64,
    rho_r: f64,
    u_r: f64,
    v_r: f64,
    p_r: f64,
    dt: f64,
    dx: f64,
    g: f64,
) -> f64 {
    face_velocity_damped(rho_l, u_l, v_l, p_l, rho_r, u_r, v_r, p_r, dt, dt, dx, g)
}

/// [`face_velocity`] with the pressure term taken over `dt_pressure`
/// ([`pressure_term_time`]) and gravity over the step `dt`:
/// u*_r = (ρ_L u_L + ρ_R u_R)/(ρ_L + ρ_R)
///        − (2 v_L v_R Δt*/(v_L + v_R)) (p_R − p_L)/Δx + g Δt.
#[allow(clippy::too_many_arguments)]
#[inline]
pub fn face_velocity_damped(
    rho_l: f64,
    u_l: f64,
    v_l: f64,
    p_l: f64,
    rho_r: f64,
    u_r: f64,
    v_r: f64,
    p_r: f64,
    dt: f64,
    dt_pressure: f64,
    dx: f64,
    g: f64,
) -> f64 {
    (rho_l * u_l + rho_r * u_r) / (rho_l + rho_r)
        - (2.0 * v_l * v_r * dt_pressure / (v_l + v_r)) * (p_r - p_l) / dx
        + g * dt
}

/// The time Δt* over which eq 19's pressure term −v Δt* ∇p acts, s:
/// the step Δt, or, when `courant` ν* > 0 exceeds the step's Courant
/// number `cfl`, the step ν*/cfl times longer (a Courant-ν* step):
/// Δt* = Δt · max(1, ν*/cfl). `courant` = 0 gives Δt, eq 19 as printed.
///
/// That term is the scheme's only damping of the pressure–velocity
/// coupling, and it shrinks with Δt at fixed Δx: at cfl 0.4 an inert
/// 17.3 GPa shock in the ANFO-K1 reactant rings to 26 GPa (36 GPa at
/// cfl 0.1), independent of Δx, and a JWL++ reaction zone of a few cells
/// burning in that over-compressed shock becomes a spurious weak
/// detonation (docs/physics/reaction/jwlpp.md, "Convergence of the planar
/// speed"). With ν* = 0.8 the ringing is 20 GPa at any cfl.
#[inline]
pub fn pressure_term_time(dt: f64, cfl: f64, courant: f64) -> f64 {
    if courant > cfl {
        dt * (courant / cfl)
    } else {
        dt
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_pressure_term_time_is_a_courant_nu_step() {
        // Off, or below the step's Courant number: Δt itself.
        assert_eq!(pressure_term_time(2e-8, 0.4, 0.0), 2e-8);
        assert_eq!(pressure_term_time(2e-8, 0.4, 0.3), 2e-8);
        assert_eq!(pressure_term_time(2e-8, 0.4, 0.4), 2e-8);
        // ν* = 0.8 at cfl 0.4: twice the step, 4e-8 s; at cfl 0.2 four
        // times a step half as long, the same 4e-8 s.
        assert!((pressure_term_time(2e-8, 0.4, 0.8) - 4e-8).abs() < 1e-22);
        assert!((pressure_term_time(1e-8, 0.2, 0.8) - 4e-8).abs() < 1e-22);
    }

    #[test]
    fn mass_weighted_mean_without_pressure_jump() {
        // (2·3 + 1·(−3))/3 = 1
        assert_eq!(
            face_velocity(2.0, 3.0, 0.5, 7.0, 1.0, -3.0, 1.0, 7.0, 0.1, 0.5, 0.0),
            1.0
        );
    }

    #[test]
    fn pressure_jump_accelerates_towards_low_pressure() {
        // v harmonic term 2·0.5·1/(1.5) = 2/3; Δt(p_R−p_L)/Δx = 0.1·(−3)/0.5 = −0.6
        // u* = 0 + (2/3)·0.6 + 9.81·0.1
        let u = face_velocity(1.0, 0.0, 0.5, 4.0, 1.0, 0.0, 1.0, 1.0, 0.1, 0.5, 9.81);
        assert!((u - (0.4 + 0.981)).abs() < 1e-15, "{u}");
    }

    #[test]
    fn the_damped_pressure_term_acts_over_its_own_time() {
        // As pressure_jump_accelerates_towards_low_pressure with Δt* = 0.2:
        // (2/3)·0.2·3/0.5 = 0.8 from the pressure, 9.81·0.1 from gravity.
        let u = face_velocity_damped(1.0, 0.0, 0.5, 4.0, 1.0, 0.0, 1.0, 1.0, 0.1, 0.2, 0.5, 9.81);
        assert!((u - (0.8 + 0.981)).abs() < 1e-15, "{u}");
    }

    #[test]
    fn mirrored_cells_give_a_zero_face_velocity() {
        assert_eq!(
            face_velocity(1.3, 2.5, 0.7, 1e5, 1.3, -2.5, 0.7, 1e5, 1e-3, 0.01, 0.0),
            0.0
        );
    }
}
