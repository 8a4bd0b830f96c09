//! Steps 8, 9 and 11 of seed 000 §3.3: Lagrangian sources and values,
//! and the specific-volume evolution. All quantities are per unit cell
//! volume (the seed's Δ(m)_r/V), so a cell's mass is ρ_r V.

use crate::equilibration::MAX_MATERIALS;

/// f_r^θ = θ_r κ_r / Σ_s θ_s κ_s (seed 000 eq 10): the share of a cell's
/// volume change that material r takes.
#[inline]
pub fn volume_change_share(theta_kappa_r: f64, theta_kappa_sum: f64) -> f64 {
    theta_kappa_r / theta_kappa_sum
}

/// Relative compression x = Δt f_r^θ ∇·Σθ*u* / θ_r beyond which the
/// linear volume response of eq 31 is replaced by [`bounded_compression`].
pub const LINEAR_COMPRESSION_LIMIT: f64 = -0.5;

/// The relative volume change of a material under the pressure rise from
/// p_eq to p (> p_eq > 0), when its linear share of the cell's volume
/// change, x = Δt f_r^θ ∇·Σθ*u* / θ_r = −κ_r (p − p_eq), is below
/// [`LINEAR_COMPRESSION_LIMIT`]: the isentrope with the material's local
/// exponent γ_r = 1/(κ_r p_eq), v^L/v = (p/p_eq)^{−κ_r p_eq}, minus one.
/// It equals x to first order in p − p_eq and never reaches −1.
///
/// The linear share of eq 31 is the tangent of that response. For a gas
/// present as a trace beside a condensed phase (κ larger by 10⁴–10⁵), a
/// pressure rise of many times the gas's own pressure in one step makes the
/// tangent remove more volume than the gas has (x ≈ −R/γ for a pressure
/// ratio R), whereas the gas only shrinks by R^{−1/γ}. Below the limit the
/// response is switched to this form (a jump of at most ½ in relative
/// volume at the switch); above it eq 31 is used as printed. See
/// docs/physics/ice/steps.md.
#[inline]
pub fn bounded_compression(kappa: f64, p_eq: f64, p: f64) -> f64 {
    (-kappa * p_eq * (p / p_eq).ln()).exp() - 1.0
}

/// How a cell's volume change over a step is shared among its materials
/// ([`volume_shares`]), per material.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct VolumeShares {
    /// The share of the cell's change Δt∇·Σθ*u* each free material takes
    /// (0 for a bounded one).
    pub share: [f64; MAX_MATERIALS],
    /// The volume (fraction of the cell) a bounded material loses.
    pub bounded: [Option<f64>; MAX_MATERIALS],
    /// v^L/v of a material whose volume changes by more than half
    /// (bounded, or expanding beyond the limit).
    pub large: [Option<f64>; MAX_MATERIALS],
}

/// The shares f_r^θ = θ_r κ_r / Σθκ of a cell's volume change (seed 000
/// eq 10, `tk` the θ_r κ_r and `tk_sum` their sum), with the bound on
/// compression: a material whose linear share x = Δt f_r ∇·Σθ*u*/θ_r
/// (`dt`, `divergence`) falls below [`LINEAR_COMPRESSION_LIMIT`] while the
/// pressure rises from `p_eq` to `p` loses the volume of
/// [`bounded_compression`] instead, and the free materials share the rest
/// in proportion to their f_r. A free material whose share of that rest
/// would in turn remove more than the limit (a trace of air beside
/// bounded detonation products at a few kPa: its linear share just inside
/// the limit, its share of the rest three times its volume) is bounded
/// too, until none is (at most one pass per material). Where every
/// material would be bounded, the linear shares stand.
pub fn volume_shares(
    tk: &[f64],
    tk_sum: f64,
    theta: &[f64],
    dt: f64,
    divergence: f64,
    p: f64,
    p_eq: f64,
) -> VolumeShares {
    let n = tk.len();
    let mut share = [0.0; MAX_MATERIALS];
    let mut bounded = [None; MAX_MATERIALS];
    let mut large = [None; MAX_MATERIALS];
    let mut free_share = 0.0;
    let mut bounded_volume = 0.0;
    let compressed = p > p_eq && p_eq > 0.0;
    for r in 0..n {
        share[r] = volume_change_share(tk[r], tk_sum);
        let x = dt * share[r] * divergence / theta[r];
        if x < LINEAR_COMPRESSION_LIMIT && compressed {
            let y = bounded_compression(tk[r] / theta[r], p_eq, p);
            bounded[r] = Some(theta[r] * y);
            large[r] = Some(1.0 + y);
            bounded_volume += theta[r] * y;
        } else {
            free_share += share[r];
            if x > -LINEAR_COMPRESSION_LIMIT && p_eq > 0.0 {
                large[r] = Some(1.0 + x);
            }
        }
    }
    if free_share <= 0.0 {
        // Every material bounded: the linear shares.
        return VolumeShares {
            share,
            bounded: [None; MAX_MATERIALS],
            large,
        };
    }
    if bounded[..n].iter().all(|b| b.is_none()) {
        return VolumeShares {
            share,
            bounded,
            large,
        };
    }
    // Only compression is bounded, so dt·div < bounded_volume < 0.
    let mut scale = (dt * divergence - bounded_volume) / (dt * divergence);
    for _ in 0..n {
        let mut more = false;
        for r in 0..n {
            if bounded[r].is_some() {
                continue;
            }
            let x = dt * share[r] / free_share * scale * divergence / theta[r];
            if x < LINEAR_COMPRESSION_LIMIT && free_share - share[r] > 0.0 {
                let y = bounded_compression(tk[r] / theta[r], p_eq, p);
                bounded[r] = Some(theta[r] * y);
                large[r] = Some(1.0 + y);
                bounded_volume += theta[r] * y;
                free_share -= share[r];
                more = true;
            }
        }
        scale = (dt * divergence - bounded_volume) / (dt * divergence);
        if !more {
            break;
        }
    }
    for r in 0..n {
        share[r] = if bounded[r].is_some() {
            0.0
        } else {
            share[r] / free_share * scale
        };
    }
    VolumeShares {
        share,
        bounded,
        large,
    }
}

/// Specific internal energy change, J/kg, of a material taken from
/// (p₀, v₀) to volume g v₀ along the isentrope p v^γ = const with its local
/// exponent γ = 1/(κ p₀) (κ = v/c²): −∫p dv = p₀v₀ (g^{1−γ} − 1)/(γ − 1),
/// or −p₀v₀ ln g when γ = 1. Used for materials whose linear share of the
/// volume change exceeds ½ in magnitude, where the flow work of eq 25 at
/// one pressure would be far off (a gas trace expanding several-fold would
/// lose more than its internal energy).
#[inline]
pub fn isentropic_energy_change(p0: f64, v0: f64, g: f64, gamma: f64) -> f64 {
    if (gamma - 1.0).abs() < 1e-9 {
        -p0 * v0 * g.ln()
    } else {
        p0 * v0 * (g.powf(1.0 - gamma) - 1.0) / (gamma - 1.0)
    }
}

/// Lagrangian momentum (ρu)^{L−}_r per unit volume (seed 000 eqs 24, 27,
/// without reactions or deviatoric stress):
/// ρ_r u_r − Δt θ_r ∇p* + Δt ρ_r g, kg/(m²·s).
#[inline]
pub fn lagrangian_momentum(
    rho: f64,
    velocity: [f64; 3],
    theta: f64,
    grad_p: [f64; 3],
    gravity: [f64; 3],
    dt: f64,
) -> [f64; 3] {
    std::array::from_fn(|d| rho * velocity[d] - dt * theta * grad_p[d] + dt * rho * gravity[d])
}

/// Lagrangian internal energy (ρe)^{L−}_r per unit volume (seed 000
/// eqs 25, 28): ρ_r e_r − Δt f_r^θ p Σ_s ∇·(θ*_s u*_s), J/m³ — the flow
/// work p dV of material r's share of the cell's volume change.
#[inline]
pub fn lagrangian_energy(
    rho: f64,
    e: f64,
    f_theta: f64,
    pressure: f64,
    volume_flux_divergence: f64,
    dt: f64,
) -> f64 {
    rho * e - dt * f_theta * pressure * volume_flux_divergence
}

/// Thermal-expansion part of seed 000 eq 31 for material r:
/// θ_r β_r Ṫ_r − f_r^θ Σ_s θ_s β_s Ṫ_s (1/s), with `theta_beta_tdot[s]` =
/// θ_s β_s Ṫ_s. Sums to zero over the materials, so the cell's volume is
/// only redistributed.
#[inline]
pub fn thermal_expansion_term(theta_beta_tdot: &[f64], r: usize, f_theta: f64) -> f64 {
    let sum: f64 = theta_beta_tdot.iter().sum();
    theta_beta_tdot[r] - f_theta * sum
}

/// Lagrangian material volume (ρv)^L_r = θ^L_r per unit volume (seed 000
/// eqs 31–32, without reactions):
/// θ_r + Δt [f_r^θ Σ_s ∇·(θ*_s u*_s) + thermal], dimensionless.
#[inline]
pub fn lagrangian_volume(
    theta: f64,
    f_theta: f64,
    volume_flux_divergence: f64,
    thermal: f64,
    dt: f64,
) -> f64 {
    theta + dt * (f_theta * volume_flux_divergence + thermal)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn unbounded_shares_are_eq_10() {
        // θκ = 1, 3: f = 0.25, 0.75; x = 1e-3·f·(−10)/θ is far from −½.
        let v = volume_shares(&[1.0, 3.0], 4.0, &[0.5, 0.5], 1e-3, -10.0, 2.0, 1.0);
        assert_eq!(v.share[..2], [0.25, 0.75]);
        assert_eq!(v.bounded[..2], [None, None]);
        assert_eq!(v.large[..2], [None, None]);
    }

    #[test]
    fn a_trace_pushed_past_the_limit_by_the_rest_is_bounded_too() {
        // The cell that stopped an (r, z) rate stick (R = 4 mm, h = 1 mm,
        // t = 6.7 µs): reactant, products and a trace of air at a few kPa.
        let tk = [
            3.8948696623328167e-10,
            2.420672220838459e-7,
            1.689221005248667e-8,
        ];
        let theta = [
            0.9986952596811952,
            0.0012166911798925325,
            8.804913905335996e-5,
        ];
        let (dt, div) = (1.2038007379912812e-7, -5459.50871321745);
        let (p, p_eq) = (6257.250479713726, 3723.150611172584);
        let sum: f64 = tk.iter().sum();
        let v = volume_shares(&tk, sum, &theta, dt, div, p, p_eq);
        // Linear shares: x = −0.504 for the products (bounded), −0.486 for
        // the air (free); the air's share of what the products do not take
        // is 2.99 times its volume: bounded in the second pass.
        let y = |r: usize| bounded_compression(tk[r] / theta[r], p_eq, p);
        assert!((y(1) + 0.319_257_271_774_500_6).abs() < 1e-12);
        assert!((y(2) + 0.309_842_990_314_725).abs() < 1e-12);
        assert_eq!(v.bounded[1], Some(theta[1] * y(1)));
        assert_eq!(v.bounded[2], Some(theta[2] * y(2)));
        assert_eq!(v.bounded[0], None);
        assert_eq!((v.share[1], v.share[2]), (0.0, 0.0));
        // The reactant takes the rest: the volumes add up to the cell's
        // change, and every material keeps a positive volume.
        let dv = dt * div;
        let total = v.share[0] * dv + theta[1] * y(1) + theta[2] * y(2);
        assert!((total - dv).abs() < 1e-14 * dv.abs(), "{total} {dv}");
        assert!(theta[0] + v.share[0] * dv > 0.99);
        // With the first pass alone the air would have lost 2.99 volumes.
        let first = (tk[2] / sum) / (tk[0] / sum + tk[2] / sum) * (dv - theta[1] * y(1)) / theta[2];
        assert!(first < -2.9, "{first}");
    }

    #[test]
    fn where_every_material_would_be_bounded_the_linear_shares_stand() {
        let v = volume_shares(&[1.0, 1.0], 2.0, &[0.5, 0.5], 1.0, -2.0, 3.0, 1.0);
        assert_eq!(v.share[..2], [0.5, 0.5]);
        assert_eq!(v.bounded[..2], [None, None]);
    }

    #[test]
    fn pressure_gradient_decelerates_by_theta() {
        // 2·[1,0,0] − 0.1·0.5·[10,0,−4] + 0.1·2·[0,0,−9.81]
        let m = lagrangian_momentum(
            2.0,
            [1.0, 0.0, 0.0],
            0.5,
            [10.0, 0.0, -4.0],
            [0.0, 0.0, -9.81],
            0.1,
        );
        assert!((m[0] - 1.5).abs() < 1e-15);
        assert_eq!(m[1], 0.0);
        assert!((m[2] - (0.2 - 1.962)).abs() < 1e-15);
    }

    #[test]
    fn expansion_work_lowers_internal_energy() {
        // ρe = 3·2 = 6; work 0.01·0.25·1e5·2 = 500
        assert!((lagrangian_energy(3.0, 2.0, 0.25, 1e5, 2.0, 0.01) - (6.0 - 500.0)).abs() < 1e-12);
    }

    #[test]
    fn bounded_compression_is_the_local_isentrope() {
        // A γ = 1.4 gas at 1e5 Pa (κ = 1/(γp)) taken to 5.7e7 Pa:
        // v^L/v = 570^{−1/1.4} = 0.010735...
        let k = 1.0 / (1.4 * 1e5);
        let y = bounded_compression(k, 1e5, 5.7e7);
        assert!((y + 1.0 - 570f64.powf(-1.0 / 1.4)).abs() < 1e-15, "{y}");
        assert!(y > -1.0);
        // First order: a small rise gives −κΔp.
        let y = bounded_compression(k, 1e5, 1e5 + 1.0);
        assert!((y + k).abs() < 1e-4 * k, "{y}");
    }

    #[test]
    fn isentropic_energy_change_is_the_ideal_gas_one() {
        // γ = 1.4 gas, p₀ = 1e5 Pa, v₀ = 1 m³/kg, e₀ = p₀v₀/(γ−1) = 2.5e5 J/kg.
        // Expanding 5×: e = e₀ · 5^{−0.4}, so Δe = 2.5e5 (5^{−0.4} − 1).
        let de = isentropic_energy_change(1e5, 1.0, 5.0, 1.4);
        assert!((de - 2.5e5 * (5f64.powf(-0.4) - 1.0)).abs() < 1e-9, "{de}");
        // Compressing to 1/10: Δe = 2.5e5 (10^{0.4} − 1) > 0.
        let de = isentropic_energy_change(1e5, 1.0, 0.1, 1.4);
        assert!((de - 2.5e5 * (10f64.powf(0.4) - 1.0)).abs() < 1e-9, "{de}");
        // γ = 1: −p₀v₀ ln g; and a small change is −p₀ Δv.
        assert!((isentropic_energy_change(2.0, 3.0, 2.0, 1.0) + 6.0 * 2f64.ln()).abs() < 1e-12);
        let de = isentropic_energy_change(1e5, 1.0, 1.0 + 1e-6, 3.0);
        assert!((de + 0.1).abs() < 1e-6, "{de}");
    }

    #[test]
    fn volume_shares_and_thermal_terms_redistribute_only() {
        let tk = [2e-6, 6e-6];
        let s = tk[0] + tk[1];
        let f = [volume_change_share(tk[0], s), volume_change_share(tk[1], s)];
        assert_eq!(f, [0.25, 0.75]);
        let tbt = [0.3, -0.1];
        let t0 = thermal_expansion_term(&tbt, 0, f[0]);
        let t1 = thermal_expansion_term(&tbt, 1, f[1]);
        assert!((t0 - (0.3 - 0.25 * 0.2)).abs() < 1e-15);
        assert!((t0 + t1).abs() < 1e-15);
        // θ grows by Δt f Σdiv: 0.4 + 0.1·(0.25·2) = 0.45
        assert!((lagrangian_volume(0.4, 0.25, 2.0, 0.0, 0.1) - 0.45).abs() < 1e-15);
    }
}
