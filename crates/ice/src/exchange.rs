//! Step 10 of seed 000 §3.3 (and the face exchange of step 3): momentum
//! and heat exchange between the materials of one cell, eqs 29–30, solved
//! pointwise-implicitly.
//!
//! Per unit volume, with f_rs = K_rs θ_r θ_s (u_s − u_r) the exchange force
//! of seed 000 §2 (its example f_12 = K_12 θ_1 θ_2 (u_1 − u_2)), eq 29 reads
//!
//! ρ_r u_r^L = ρ_r u_r^{L−} + Δt Σ_s K_rs θ_r θ_s (u_s^L − u_r^L),
//!
//! a symmetric N×N system (W + Δt L) u^L = W u^{L−} with W = diag(ρ_r)
//! and L the graph Laplacian of the weights K_rs θ_r θ_s. Eq 29 as printed
//! multiplies by m_r; with K in its §2 units (force per volume per
//! velocity) the per-volume form above is the one whose pair forces cancel,
//! so momentum is conserved — it is the form Kashiwa's reports and
//! Uintah's ICE solve. Heat exchange (eq 30) is the same system with
//! W = diag(ρ_r c_v,r), H_rs in place of K_rs and T in place of u.
//!
//! Solving for u directly loses momentum when K is large (K = 10¹⁵ makes
//! the matrix's condition number ~10¹⁵, and the solve's error lies along
//! the common-velocity mode). So the W-weighted mean ū = Σ W_r u_r / Σ W_r
//! — which the exchange cannot change — is taken out first, and the system
//! is solved for the deviations u_r − ū, whose right-hand side has zero
//! W-weighted sum. Momentum is then conserved to round-off and, as K → ∞,
//! every u_r tends to ū with no time-step restriction. The matrix is
//! symmetric positive definite and is factorised by Cholesky on the stack.

use crate::equilibration::MAX_MATERIALS;
use serde::{Deserialize, Serialize};

/// Solves (W + Δt L) q = W q⁻ in place for `C` components per material,
/// where L_rs = −coef_rs θ_r θ_s (r ≠ s) and L_rr = Σ_{s≠r} coef_rs θ_r θ_s.
/// `coef` is N×N row-major and symmetric.
///
/// Two to four materials (the usual cases: an explosive, its products and
/// air, and a coupled run's solid) run a copy compiled for that count,
/// whose loops the compiler unrolls and whose indices it checks once; the
/// arithmetic, and so every bit of the result, is the same.
fn solve_exchange<const C: usize>(
    w: &[f64],
    theta: &[f64],
    coef: &[f64],
    dt: f64,
    q: &mut [[f64; C]],
) {
    match w.len() {
        2 => solve_exchange_n::<C, 2>(w, theta, coef, dt, q),
        3 => solve_exchange_n::<C, 3>(w, theta, coef, dt, q),
        4 => solve_exchange_n::<C, 4>(w, theta, coef, dt, q),
        _ => solve_exchange_n::<C, 0>(w, theta, coef, dt, q),
    }
}

/// [`solve_exchange`] for `N` materials (`N` = 0: any count, `w.len()`).
#[inline]
fn solve_exchange_n<const C: usize, const N: usize>(
    w: &[f64],
    theta: &[f64],
    coef: &[f64],
    dt: f64,
    q: &mut [[f64; C]],
) {
    let n = if N > 0 { N } else { w.len() };
    debug_assert!(n <= MAX_MATERIALS && theta.len() == n && q.len() == n);
    let (w, theta, coef, q) = (&w[..n], &theta[..n], &coef[..n * n], &mut q[..n]);
    if n < 2 || (0..n).all(|r| (0..n).all(|s| r == s || coef[r * n + s] == 0.0)) {
        return;
    }
    let wsum: f64 = w.iter().sum();
    let mut mean = [0.0; C];
    for r in 0..n {
        for c in 0..C {
            mean[c] += w[r] * q[r][c];
        }
    }
    for m in &mut mean {
        *m /= wsum;
    }
    // A = W + Δt L, lower triangle is enough for Cholesky.
    let mut a = [[0.0; MAX_MATERIALS]; MAX_MATERIALS];
    for r in 0..n {
        let mut diag = w[r];
        for s in 0..n {
            if s != r {
                let b = dt * 0.5 * (coef[r * n + s] + coef[s * n + r]) * theta[r] * theta[s];
                a[r][s] = -b;
                diag += b;
            }
        }
        a[r][r] = diag;
    }
    // Cholesky A = G Gᵀ, G lower, in place.
    for j in 0..n {
        let mut d = a[j][j];
        for k in 0..j {
            d -= a[j][k] * a[j][k];
        }
        let d = d.sqrt();
        a[j][j] = d;
        for i in j + 1..n {
            let mut s = a[i][j];
            for k in 0..j {
                s -= a[i][k] * a[j][k];
            }
            a[i][j] = s / d;
        }
    }
    for c in 0..C {
        let mut x = [0.0; MAX_MATERIALS];
        for r in 0..n {
            x[r] = w[r] * (q[r][c] - mean[c]);
        }
        // G y = b, then Gᵀ x = y.
        for i in 0..n {
            let mut s = x[i];
            for k in 0..i {
                s -= a[i][k] * x[k];
            }
            x[i] = s / a[i][i];
        }
        for i in (0..n).rev() {
            let mut s = x[i];
            for k in i + 1..n {
                s -= a[k][i] * x[k];
            }
            x[i] = s / a[i][i];
        }
        // The exact deviation has Σ w_r x_r = 0 (the rows of A sum to w_r x_r
        // and the right side sums to 0); with K Δt θ_r θ_s ≫ w_r the solve's
        // round-off leaves a weighted sum of order cond(A)·ε. Removing it
        // keeps Σ w_r q_r = Σ w_r q_r⁻ to the round-off of the sums.
        let mut drift = 0.0;
        for r in 0..n {
            drift += w[r] * x[r];
        }
        let drift = drift / wsum;
        for r in 0..n {
            q[r][c] = mean[c] + (x[r] - drift);
        }
    }
}

/// Momentum exchange of one cell or face (seed 000 eq 29, pointwise
/// implicit). `rho[r]` averaged densities (kg/m³), `theta[r]` volume
/// fractions, `k` the N×N exchange coefficients K_rs (kg/(m³·s)),
/// `vel[r]` the velocities u^{L−} in, u^L out (m/s). Returns the kinetic
/// energy per unit volume the exchange dissipated, Σ ½ρ_r(|u^{L−}|² − |u^L|²)
/// ≥ 0 (J/m³), which the solver returns to internal energy.
pub fn momentum_exchange<const C: usize>(
    rho: &[f64],
    theta: &[f64],
    k: &[f64],
    dt: f64,
    vel: &mut [[f64; C]],
) -> f64 {
    let n = rho.len();
    let mut before = [[0.0; C]; MAX_MATERIALS];
    before[..n].copy_from_slice(vel);
    solve_exchange(rho, theta, k, dt, vel);
    let mut dissipated = 0.0;
    for r in 0..n {
        for c in 0..C {
            dissipated += 0.5 * rho[r] * (before[r][c] - vel[r][c]) * (before[r][c] + vel[r][c]);
        }
    }
    dissipated
}

/// How the fluids exchange momentum with a material carried by particles
/// (the coupled pipeline's solids) in the cells of its surface.
///
/// Seed 000 eq 29 is isotropic: K acts on every velocity component, so in
/// a cell the solid's projected volume reaches the fluids are held to the
/// solid's velocity along its surface as well as across it, a no-slip
/// layer one or two cells thick (docs/physics/axisymmetric.md, "The
/// cylinder"). `Slip` keeps eq 29 across the surface and leaves the fluids
/// free along it, the inviscid interface condition (normal velocity
/// continuous, tangential velocity free); the surface's normal is the
/// gradient of the particle materials' volume fraction
/// (docs/physics/couple/ice_mpm.md, "Slip exchange").
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
pub enum SolidExchange {
    /// Seed 000 eq 29 as printed, on every component (the default).
    #[default]
    Isotropic,
    /// Eq 29 on the component along the solid's surface normal; the
    /// tangential components are exchanged among the fluids only.
    Slip,
}

/// Smallest change of the particle materials' volume fraction across one
/// cell (|∇θ_s| times the smallest spacing) for which a cell or face is
/// on their surface and [`SolidExchange::Slip`] applies; elsewhere
/// (inside the solid, in the fluid away from it) the exchange stays
/// isotropic.
pub const SLIP_MIN_JUMP: f64 = 0.01;

/// Smallest share of a cell's (or face's) volume the fluids must fill for
/// [`SolidExchange::Slip`] to apply there: where the particle materials
/// fill more than 1 − 0.1 of it, the cell is inside the solid, its
/// gradient the particles' noise, and its fluids the remains of a flow
/// the solid has closed over; they keep the isotropic exchange. Let slip
/// in the 1 mm r–z cylinder's copper (θ_s ≈ 0.985, products at a mass
/// share of 2·10⁻⁹, just above the trace rule's 10⁻⁹) they ran at
/// 10⁶ m/s and held the step at 10⁻¹⁰ s (docs/physics/couple/ice_mpm.md,
/// "Slip exchange").
pub const SLIP_FLUID_MIN: f64 = 0.1;

/// The unit normal of the surface whose volume-fraction gradient is `g`
/// (1/m), or `None` where |g| h < [`SLIP_MIN_JUMP`] for the smallest
/// spacing `h` (m).
pub fn surface_normal(g: [f64; 3], h: f64) -> Option<[f64; 3]> {
    let norm = (g[0] * g[0] + g[1] * g[1] + g[2] * g[2]).sqrt();
    (norm * h >= SLIP_MIN_JUMP && norm.is_finite()).then(|| g.map(|x| x / norm))
}

/// The coefficients `k` (N×N) with each pair of one material that moves
/// with the solid (`with_solid[r]`: the particle materials and the fluid
/// traces, [`slip_momentum_exchange`]) and one that slips along it scaled
/// by `weight`, written to `out`: the face exchange of step 3 under
/// [`SolidExchange::Slip`] takes `weight` = n_a², the share of the face's
/// normal velocity that crosses the surface. Pairs within either group
/// keep K.
pub fn slip_coefficients(k: &[f64], with_solid: &[bool], weight: f64, out: &mut [f64]) {
    let n = with_solid.len();
    for r in 0..n {
        for s in 0..n {
            let w = if with_solid[r] != with_solid[s] {
                weight
            } else {
                1.0
            };
            out[r * n + s] = w * k[r * n + s];
        }
    }
}

/// Step 10 under [`SolidExchange::Slip`] in a cell on a solid's surface of
/// unit normal `normal`: eq 29 with the coefficients `k` on each
/// material's normal velocity u_r·n̂, and on the tangential part
/// u_r − (u_r·n̂)n̂ within two groups apart: the materials that move with
/// the solid (`with_solid[r]`) and those that slip along it.
///
/// The particle materials move with the solid, and so do the fluids that
/// are traces in the cell (the caller's test: the solver's trace rule of
/// θ below 10⁻⁴ or a mass share below 10⁻⁹): a trace inside a solid's
/// cells is no flow along its surface, and let slip it took the pressure
/// gradient over its own density, 10⁻⁵ kg/m³ — 10⁶ m/s inside the 1 mm
/// r–z cylinder's copper, whose step it collapsed to 10⁻¹⁰ s
/// (docs/physics/couple/ice_mpm.md, "Slip exchange"; the cells inside
/// the solid are left out by [`SLIP_FLUID_MIN`]). Each part conserves
/// momentum, so the whole does; returns the kinetic energy per unit
/// volume the two dissipated (J/m³), as [`momentum_exchange`] does.
pub fn slip_momentum_exchange(
    rho: &[f64],
    theta: &[f64],
    k: &[f64],
    with_solid: &[bool],
    normal: [f64; 3],
    dt: f64,
    vel: &mut [[f64; 3]],
) -> f64 {
    let n = rho.len();
    let mut un = [[0.0; 1]; MAX_MATERIALS];
    let mut ut = [[0.0; 3]; MAX_MATERIALS];
    for r in 0..n {
        let s = vel[r][0] * normal[0] + vel[r][1] * normal[1] + vel[r][2] * normal[2];
        un[r][0] = s;
        ut[r] = std::array::from_fn(|c| vel[r][c] - s * normal[c]);
    }
    let mut dissipated = momentum_exchange(rho, theta, k, dt, &mut un[..n]);
    // The tangential parts: the slipping fluids among themselves, the
    // materials that move with the solid among themselves, each group
    // solved as its own system so that the removal of the solve's drift
    // (solve_exchange) acts on the group's own common motion, which the
    // exchange cannot change.
    for group in [false, true] {
        let mut idx = [0; MAX_MATERIALS];
        let mut m = 0;
        for r in (0..n).filter(|&r| with_solid[r] == group) {
            idx[m] = r;
            m += 1;
        }
        if m < 2 {
            continue;
        }
        let (mut rg, mut tg, mut kg) = (
            [0.0; MAX_MATERIALS],
            [0.0; MAX_MATERIALS],
            [0.0; MAX_MATERIALS * MAX_MATERIALS],
        );
        let mut vg = [[0.0; 3]; MAX_MATERIALS];
        for (i, &r) in idx[..m].iter().enumerate() {
            rg[i] = rho[r];
            tg[i] = theta[r];
            vg[i] = ut[r];
            for (j, &s) in idx[..m].iter().enumerate() {
                kg[i * m + j] = k[r * n + s];
            }
        }
        dissipated += momentum_exchange(&rg[..m], &tg[..m], &kg[..m * m], dt, &mut vg[..m]);
        for (i, &r) in idx[..m].iter().enumerate() {
            ut[r] = vg[i];
        }
    }
    for r in 0..n {
        vel[r] = std::array::from_fn(|c| ut[r][c] + un[r][0] * normal[c]);
    }
    dissipated
}

/// Heat exchange of one cell (seed 000 eq 30, pointwise implicit).
/// `rho_cv[r]` = ρ_r c_v,r (J/(m³·K)), `theta[r]` volume fractions, `h` the
/// N×N coefficients H_rs (W/(m³·K)), `temp[r]` T^{L−} in, T^L out (K).
/// Σ ρ_r c_v,r T_r is unchanged.
pub fn heat_exchange(rho_cv: &[f64], theta: &[f64], h: &[f64], dt: f64, temp: &mut [[f64; 1]]) {
    solve_exchange(rho_cv, theta, h, dt, temp);
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn huge_k_gives_the_mass_weighted_mean_and_keeps_momentum() {
        let rho = [1.0, 1e-3, 10.0];
        let theta = [0.6, 0.3, 0.1];
        let k = [1e15; 9];
        let mut vel = [[3.0, -1.0, 0.5], [-200.0, 4.0, 0.0], [0.25, 0.0, -7.0]];
        let mom0: Vec<f64> = (0..3)
            .map(|c| (0..3).map(|r| rho[r] * vel[r][c]).sum())
            .collect();
        let ke0: f64 = (0..3)
            .map(|r| 0.5 * rho[r] * vel[r].iter().map(|v| v * v).sum::<f64>())
            .sum();
        // Backward Euler leaves a deviation of order ρ/(Δt K θ_r θ_s) ~ 1e-10
        // of the initial spread.
        let dissipated = momentum_exchange(&rho, &theta, &k, 1e-3, &mut vel);
        let mtot: f64 = rho.iter().sum();
        for c in 0..3 {
            let mean = mom0[c] / mtot;
            for v in &vel {
                assert!((v[c] - mean).abs() <= 1e-7, "{v:?} vs {mean}");
            }
            let mom: f64 = (0..3).map(|r| rho[r] * vel[r][c]).sum();
            assert!(
                (mom - mom0[c]).abs() <= 4.0 * f64::EPSILON * 200.0,
                "{mom} vs {}",
                mom0[c]
            );
        }
        let ke: f64 = (0..3)
            .map(|r| 0.5 * rho[r] * vel[r].iter().map(|v| v * v).sum::<f64>())
            .sum();
        // Kinetic energy lost equals the reported dissipation.
        assert!(
            (ke0 - ke - dissipated).abs() <= 1e-12 * ke0,
            "{ke0} {ke} {dissipated}"
        );
        assert!(dissipated > 0.0);
    }

    #[test]
    fn momentum_is_kept_to_round_off_at_extreme_contrast() {
        // A case found by the proptest below: a 1e-6 kg/m³ trace between two
        // dense materials, K Δt θ_r θ_s up to 1e7 times the smallest weight.
        for dt in [1e-6, 1e-4, 1e-2] {
            let rho = [3917.73, 1e-6, 2566.71];
            let theta = [1e-6, 0.584, 0.417];
            let k = crate::ExchangeCoefficients::uniform(3, 10f64.powf(11.04), 0.0).momentum;
            let mut vel = [[0.0], [0.0], [-174.74]];
            let m0: f64 = (0..3).map(|r| rho[r] * vel[r][0]).sum();
            let scale: f64 = (0..3).map(|r| rho[r] * vel[r][0].abs()).sum();
            momentum_exchange(&rho, &theta, &k, dt, &mut vel);
            let m1: f64 = (0..3).map(|r| rho[r] * vel[r][0]).sum();
            assert!((m1 - m0).abs() <= 1e-13 * scale, "dt {dt}: {m1} vs {m0}");
        }
    }

    #[test]
    fn two_materials_relax_at_the_hand_computed_rate() {
        // ρ1 u1 + b (u1 − u2) = ρ1 u1⁻, ρ2 u2 + b (u2 − u1) = ρ2 u2⁻ with
        // b = Δt K θ1 θ2 = 0.1·10·0.5·0.5 = 0.25, ρ = (1, 1), u⁻ = (1, 0):
        // mean 0.5; deviation d solves (1 + 0.5) d = 0.5 → d = 1/3:
        // u = (0.5 + 1/3, 0.5 − 1/3).
        let mut vel = [[1.0], [0.0]];
        momentum_exchange(
            &[1.0, 1.0],
            &[0.5, 0.5],
            &[0.0, 10.0, 10.0, 0.0],
            0.1,
            &mut vel,
        );
        assert!((vel[0][0] - (0.5 + 1.0 / 3.0)).abs() < 1e-15);
        assert!((vel[1][0] - (0.5 - 1.0 / 3.0)).abs() < 1e-15);
    }

    #[test]
    fn heat_exchange_conserves_energy_and_equalises_with_large_h() {
        let rho_cv = [1.0 * 718.0, 1000.0 * 4186.0];
        let mut t = [[1000.0], [300.0]];
        let e0 = rho_cv[0] * 1000.0 + rho_cv[1] * 300.0;
        heat_exchange(&rho_cv, &[0.5, 0.5], &[0.0, 1e15, 1e15, 0.0], 1.0, &mut t);
        let e1 = rho_cv[0] * t[0][0] + rho_cv[1] * t[1][0];
        assert!((e1 - e0).abs() <= 1e-15 * e0 * 4.0);
        let tm = e0 / (rho_cv[0] + rho_cv[1]);
        // Residual difference ~ ρc_v/(Δt H θθ)·700 K ≈ 1e-5 K.
        assert!(
            (t[0][0] - tm).abs() < 1e-4 && (t[1][0] - tm).abs() < 1e-4,
            "{t:?} vs {tm}"
        );
    }

    #[test]
    fn zero_coefficients_change_nothing() {
        let mut vel = [[1.0, 2.0, 3.0], [4.0, 5.0, 6.0]];
        let d = momentum_exchange(&[1.0, 2.0], &[0.5, 0.5], &[0.0; 4], 1.0, &mut vel);
        assert_eq!(vel, [[1.0, 2.0, 3.0], [4.0, 5.0, 6.0]]);
        assert_eq!(d, 0.0);
    }
}

#[cfg(test)]
mod slip_tests {
    use super::*;
    use crate::ExchangeCoefficients;

    /// A fluid beside a solid whose surface faces x, K = 10¹⁵: across the
    /// surface both take the mass-weighted mean of their normal velocities
    /// (hand value 1·2/(2 + 8) = 0.2 m/s); along it the fluid keeps its
    /// 5 m/s and the solid its 0, and the dissipation is the normal
    /// motion's kinetic energy lost, ½·2·1² − ½·10·0.2² = 0.8 J/m³. (With
    /// Δt = 1 s, Δt K θ_r θ_s / ρ_r ~ 10¹⁴: backward Euler is at its limit
    /// to 10⁻¹⁴.)
    #[test]
    fn the_fluid_slips_along_the_solid_and_sticks_across_it() {
        let (rho, theta) = ([2.0, 8.0], [0.5, 0.5]);
        let k = ExchangeCoefficients::uniform(2, 1e15, 0.0).momentum;
        let mut vel = [[1.0, 5.0, -3.0], [0.0, 0.0, 0.0]];
        let d = slip_momentum_exchange(
            &rho,
            &theta,
            &k,
            &[false, true],
            [1.0, 0.0, 0.0],
            1.0,
            &mut vel,
        );
        for v in &vel {
            assert!((v[0] - 0.2).abs() < 1e-12, "{vel:?}");
        }
        assert!((vel[0][1] - 5.0).abs() < 1e-12 && (vel[0][2] + 3.0).abs() < 1e-12);
        assert!(
            vel[1][1].abs() < 1e-15 && vel[1][2].abs() < 1e-15,
            "{vel:?}"
        );
        assert!((d - 0.8).abs() < 1e-9, "{d}");
        // The isotropic exchange holds the fluid on every component.
        let mut iso = [[1.0, 5.0, -3.0], [0.0, 0.0, 0.0]];
        momentum_exchange(&rho, &theta, &k, 1.0, &mut iso);
        assert!((iso[0][1] - 1.0).abs() < 1e-12, "{iso:?}");
    }

    /// Two fluids and a solid, the surface's normal at 45° in the x–y
    /// plane: the fluids' tangential velocities take their own
    /// mass-weighted mean (the solid's is left alone), the normal ones the
    /// mean of all three; momentum is kept on every axis.
    #[test]
    fn tangential_motion_is_exchanged_among_the_fluids_only() {
        let (rho, theta) = ([1.0, 3.0, 6.0], [0.3, 0.3, 0.4]);
        let k = ExchangeCoefficients::uniform(3, 1e15, 0.0).momentum;
        let s = std::f64::consts::FRAC_1_SQRT_2;
        let (n, t) = ([s, s, 0.0], [-s, s, 0.0]);
        let start = [[4.0, 0.0, 1.0], [0.0, -2.0, 0.0], [1.0, 1.0, 0.0]];
        let mut vel = start;
        slip_momentum_exchange(&rho, &theta, &k, &[false, false, true], n, 1.0, &mut vel);
        let dot = |a: [f64; 3], b: [f64; 3]| a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
        let mean = |f: &dyn Fn(usize) -> f64, rs: &[usize]| {
            rs.iter().map(|&r| rho[r] * f(r)).sum::<f64>() / rs.iter().map(|&r| rho[r]).sum::<f64>()
        };
        let normal = mean(&|r| dot(start[r], n), &[0, 1, 2]);
        let tangent = mean(&|r| dot(start[r], t), &[0, 1]);
        let z = mean(&|r| start[r][2], &[0, 1]);
        for r in 0..3 {
            assert!((dot(vel[r], n) - normal).abs() < 1e-12, "{vel:?}");
        }
        for r in 0..2 {
            assert!((dot(vel[r], t) - tangent).abs() < 1e-12, "{vel:?}");
            assert!((vel[r][2] - z).abs() < 1e-12, "{vel:?}");
        }
        assert!((dot(vel[2], t) - dot(start[2], t)).abs() < 1e-12);
        assert!(vel[2][2].abs() < 1e-12);
        for c in 0..3 {
            let (a, b): (f64, f64) = (
                (0..3).map(|r| rho[r] * start[r][c]).sum(),
                (0..3).map(|r| rho[r] * vel[r][c]).sum(),
            );
            assert!((a - b).abs() < 1e-12, "axis {c}: {a} vs {b}");
        }
    }

    /// Without a material carried by particles the slip exchange is the
    /// isotropic one (to round-off: it solves the normal and tangential
    /// parts apart).
    #[test]
    fn without_particles_slip_is_the_isotropic_exchange() {
        let (rho, theta) = ([1.2, 1.8e3, 8.9e3], [0.41, 0.33, 0.26]);
        let k = ExchangeCoefficients::uniform(3, 1e9, 0.0).momentum;
        let start = [[3.0, -1.0, 0.5], [-20.0, 4.0, 0.0], [0.25, 0.0, -7.0]];
        let (mut a, mut b) = (start, start);
        let n = [0.6, 0.0, 0.8];
        let da = slip_momentum_exchange(&rho, &theta, &k, &[false; 3], n, 1e-6, &mut a);
        let db = momentum_exchange(&rho, &theta, &k, 1e-6, &mut b);
        assert_ne!(a, start, "nothing was exchanged");
        for (x, y) in a.iter().zip(&b) {
            for c in 0..3 {
                assert!((x[c] - y[c]).abs() < 1e-12 * 20.0, "{a:?} vs {b:?}");
            }
        }
        assert!((da - db).abs() <= 1e-12 * db.abs(), "{da} vs {db}");
    }

    /// The face weights: a solid–fluid pair scaled, fluid–fluid and
    /// solid–solid pairs kept.
    #[test]
    fn face_coefficients_scale_the_solid_fluid_pairs_only() {
        let k = [0.0, 1.0, 2.0, 1.0, 0.0, 3.0, 2.0, 3.0, 0.0];
        let mut out = [0.0; 9];
        slip_coefficients(&k, &[false, false, true], 0.25, &mut out);
        assert_eq!(out, [0.0, 1.0, 0.5, 1.0, 0.0, 0.75, 0.5, 0.75, 0.0]);
        slip_coefficients(&k, &[true, false, true], 0.25, &mut out);
        assert_eq!(out, [0.0, 0.25, 2.0, 0.25, 0.0, 0.75, 2.0, 0.75, 0.0]);
    }

    /// A surface is one where the fraction changes by 1 % a cell or more.
    #[test]
    fn surface_normal_needs_a_jump_of_one_percent_a_cell() {
        assert_eq!(surface_normal([0.0, 3.0, 4.0], 2e-3), Some([0.0, 0.6, 0.8]));
        assert_eq!(surface_normal([0.0, 3.0, 4.0], 1e-3), None);
        assert_eq!(surface_normal([0.0; 3], 1.0), None);
        assert_eq!(surface_normal([f64::NAN, 0.0, 0.0], 1.0), None);
    }
}

#[cfg(test)]
mod proptests {
    use super::*;
    use crate::ExchangeCoefficients;
    use proptest::prelude::*;

    /// The copies compiled for 2, 3 and 4 materials give the bits of the
    /// any-count path.
    #[test]
    fn compiled_copies_give_the_generic_bits() {
        fn check<const N: usize>() {
            let rho = [1.2, 1.8e3, 8.9e3, 3.1e-4];
            let theta = [0.41, 0.33, 0.26, 1e-5];
            let k = ExchangeCoefficients::uniform(N, 1e12, 0.0).momentum;
            let start: Vec<[f64; 3]> = (0..N)
                .map(|r| {
                    [
                        100.0 * r as f64 - 7.0,
                        3.0 - 40.0 * r as f64,
                        1.5 * r as f64,
                    ]
                })
                .collect();
            let (mut a, mut b) = (start.clone(), start);
            solve_exchange_n::<3, N>(&rho[..N], &theta[..N], &k, 2e-8, &mut a);
            solve_exchange_n::<3, 0>(&rho[..N], &theta[..N], &k, 2e-8, &mut b);
            assert_ne!(a[0], [-7.0, 3.0, 0.0], "nothing was exchanged");
            for (x, y) in a.iter().zip(&b) {
                for c in 0..3 {
                    assert_eq!(x[c].to_bits(), y[c].to_bits(), "N = {N}");
                }
            }
        }
        check::<2>();
        check::<3>();
        check::<4>();
    }

    proptest! {
        /// For any masses, volume fractions, coefficients and step, the
        /// exchange conserves momentum, dissipates kinetic energy, and
        /// leaves every velocity within the range it started in.
        #[test]
        fn exchange_conserves_momentum_and_stays_bounded(
            n in 2usize..=5,
            rho in proptest::collection::vec(1e-6f64..1e4, 5),
            theta in proptest::collection::vec(1e-6f64..1.0, 5),
            u in proptest::collection::vec(-1e3f64..1e3, 5),
            log_k in 0.0f64..15.0,
            dt in 1e-9f64..1e-2,
        ) {
            let k = ExchangeCoefficients::uniform(n, 10f64.powf(log_k), 0.0).momentum;
            let mut vel: Vec<[f64; 1]> = u[..n].iter().map(|&x| [x]).collect();
            let m0: f64 = (0..n).map(|r| rho[r] * u[r]).sum();
            let scale: f64 = (0..n).map(|r| rho[r] * u[r].abs()).sum::<f64>().max(1e-300);
            let diss = momentum_exchange(&rho[..n], &theta[..n], &k, dt, &mut vel);
            let m1: f64 = (0..n).map(|r| rho[r] * vel[r][0]).sum();
            prop_assert!((m1 - m0).abs() <= 1e-13 * scale, "{} vs {}", m1, m0);
            prop_assert!(diss >= -1e-12 * scale * 1e3);
            let (lo, hi) = u[..n].iter().fold((f64::INFINITY, f64::NEG_INFINITY), |a, &x| (a.0.min(x), a.1.max(x)));
            for v in &vel {
                prop_assert!(v[0] >= lo - 1e-9 * (hi - lo).max(1.0) && v[0] <= hi + 1e-9 * (hi - lo).max(1.0));
            }
        }

        /// For any masses, fractions, coefficients, step, normal and choice
        /// of solid, the slip exchange keeps momentum on every axis,
        /// dissipates kinetic energy, and leaves the solid's tangential
        /// velocity where it was when one solid faces only fluids.
        #[test]
        fn slip_exchange_conserves_momentum_and_dissipates(
            n in 2usize..=4,
            rho in proptest::collection::vec(1e-3f64..1e4, 4),
            theta in proptest::collection::vec(1e-3f64..1.0, 4),
            u in proptest::collection::vec(-1e3f64..1e3, 12),
            normal in proptest::collection::vec(-1.0f64..1.0, 3),
            solid in 0usize..4,
            log_k in 0.0f64..15.0,
            dt in 1e-9f64..1e-2,
        ) {
            let norm = (normal[0].powi(2) + normal[1].powi(2) + normal[2].powi(2)).sqrt();
            prop_assume!(norm > 1e-3);
            let nh = [normal[0] / norm, normal[1] / norm, normal[2] / norm];
            let solid = solid % n;
            let lagrangian: Vec<bool> = (0..n).map(|r| r == solid).collect();
            let k = ExchangeCoefficients::uniform(n, 10f64.powf(log_k), 0.0).momentum;
            let start: Vec<[f64; 3]> = (0..n).map(|r| [u[3 * r], u[3 * r + 1], u[3 * r + 2]]).collect();
            let mut vel = start.clone();
            let diss = slip_momentum_exchange(&rho[..n], &theta[..n], &k, &lagrangian, nh, dt, &mut vel);
            let scale: f64 = (0..n).map(|r| rho[r] * 1e3).sum();
            for c in 0..3 {
                let m0: f64 = (0..n).map(|r| rho[r] * start[r][c]).sum();
                let m1: f64 = (0..n).map(|r| rho[r] * vel[r][c]).sum();
                prop_assert!((m1 - m0).abs() <= 1e-12 * scale, "axis {}: {} vs {}", c, m1, m0);
            }
            let ke = |v: &[[f64; 3]]| (0..n).map(|r| 0.5 * rho[r] * (v[r][0].powi(2) + v[r][1].powi(2) + v[r][2].powi(2))).sum::<f64>();
            prop_assert!(diss >= -1e-12 * scale * 1e3);
            prop_assert!((ke(&start) - ke(&vel) - diss).abs() <= 1e-9 * scale * 1e3);
            let tang = |v: [f64; 3]| {
                let s = v[0] * nh[0] + v[1] * nh[1] + v[2] * nh[2];
                [v[0] - s * nh[0], v[1] - s * nh[1], v[2] - s * nh[2]]
            };
            let (a, b) = (tang(start[solid]), tang(vel[solid]));
            for c in 0..3 {
                prop_assert!((a[c] - b[c]).abs() <= 1e-12 * 1e3, "{:?} vs {:?}", a, b);
            }
        }
    }
}
