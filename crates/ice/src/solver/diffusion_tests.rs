//! Tests of the viscous and heat-conduction pass (seed 000 eqs 2–3) with
//! exact or hand-computed values.

use brisance_core::{Eos, Solver};
use brisance_eos::IdealGas;
use brisance_grid::Level;
use proptest::prelude::*;

use super::super::{for_interior, global_of, IceSolver, ENERGY, GHOST, L_ENERGY, L_RHO, L_VEL};
use super::super::{NL, NS, RHO, TEMP, THETA, VEL};
use crate::diffusion::{shear_wave, temperature_wave};
use crate::{
    CellState, ExchangeCoefficients, IceBoundary, IceOptions, MaterialState, MaterialTransport,
    TimeStepLimit,
};

fn transport(viscosity: f64, thermal_conductivity: f64) -> MaterialTransport {
    MaterialTransport {
        viscosity,
        thermal_conductivity,
    }
}

/// γ = 1.4, c_v = 1: T = e.
fn gas() -> IdealGas {
    IdealGas::new(1.4, 1.0, 1.0)
}

/// A solver on [0, len]³ (inactive axes 1/10 of a cell of the active
/// length) with `n` materials, every cell `state(centre)`.
fn solver<E: Eos + Clone>(
    eos: Vec<E>,
    cells: [usize; 3],
    layout: [usize; 3],
    bcs: [IceBoundary; 6],
    k_exchange: f64,
    cfl: f64,
    state: impl Fn([f64; 3]) -> CellState + Sync,
) -> IceSolver<E> {
    let upper = cells.map(|c| if c > 1 { 1.0 } else { 0.1 });
    let level = Level::new([0.0; 3], upper, cells, layout, GHOST).unwrap();
    let n = eos.len();
    IceSolver::new(
        eos,
        level,
        bcs,
        ExchangeCoefficients::uniform(n, k_exchange, 0.0),
        IceOptions {
            cfl,
            ..Default::default()
        },
        state,
    )
    .unwrap()
}

/// Calls `f(centre, state values of the cell)` for every interior cell and
/// writes the values back (tests only: serial).
fn edit_state<E: Eos>(s: &mut IceSolver<E>, f: impl Fn([f64; 3], &mut [f64])) {
    let geometry = s.level.geometry;
    for (pid, patch) in s.level.patches.iter().enumerate() {
        let data = &mut s.state[pid].data;
        let mut vals = vec![0.0; data.len()];
        for_interior(patch, |c| {
            for (v, d) in vals.iter_mut().zip(data.iter()) {
                *v = d[c];
            }
            f(geometry.cell_centre(global_of(patch, c)), &mut vals);
            for (v, d) in vals.iter().zip(data.iter_mut()) {
                d[c] = *v;
            }
        });
    }
}

/// Per interior cell in global order: the values `f(state, lag, c)`.
fn gather<E: Eos, T>(s: &IceSolver<E>, f: impl Fn(&[Vec<f64>], &[Vec<f64>], usize) -> T) -> Vec<T> {
    let mut out = Vec::new();
    s.level.for_each_cell_in_order(|_, pid, c| {
        out.push(f(&s.state[pid].data, &s.lag[pid].data, c));
    });
    out
}

/// Momentum and total energy of the Lagrangian values, summed in global
/// cell order (per unit cell volume).
fn lag_totals<E: Eos>(s: &IceSolver<E>) -> ([f64; 3], f64) {
    let n = s.eos.len();
    let cells = gather(s, |_, l, c| {
        let mut m = [0.0; 3];
        let mut e = 0.0;
        for r in 0..n {
            let b = r * NL;
            let rho = l[b + L_RHO][c];
            let u: [f64; 3] = std::array::from_fn(|j| l[b + L_VEL + j][c]);
            for j in 0..3 {
                m[j] += rho * u[j];
            }
            e += rho * (l[b + L_ENERGY][c] + 0.5 * (u[0] * u[0] + u[1] * u[1] + u[2] * u[2]));
        }
        (m, e)
    });
    cells.iter().fold(([0.0; 3], 0.0), |(m, e), (cm, ce)| {
        ([m[0] + cm[0], m[1] + cm[1], m[2] + cm[2]], e + ce)
    })
}

/// Steps 3–11 of one step of `dt`, the diffusion pass included.
fn lagrangian_step<E: Eos>(s: &mut IceSolver<E>, dt: f64) {
    s.compute_face_centred_velocities(dt);
    s.compute_pressure_increment(dt);
    s.compute_lagrangian_values(dt).unwrap();
}

/// Couette flow between a wall at rest (y = 0) and one moving at U along x
/// (y = H = 1): with the linear profile u_x = U y/H in the cells, every
/// face carries τ_yx = μU/H — the wall faces exactly, through the no-slip
/// ghosts — so no cell feels a net viscous force, and each gains the
/// dissipation μ(U/H)² Δt as heat.
#[test]
fn couette_profile_has_no_net_force_and_the_exact_wall_stress() {
    use IceBoundary::*;
    let (u_wall, mu, cells) = (0.3, 0.02, 16);
    let bcs = [
        Periodic,
        Periodic,
        FixedVelocity([0.0; 3]),
        FixedVelocity([u_wall, 0.0, 0.0]),
        Periodic,
        Periodic,
    ];
    let make = || {
        solver(
            vec![gas()],
            [1, cells, 1],
            [1, 1, 1],
            bcs.clone(),
            0.0,
            0.4,
            |x| CellState::single(1.0, 1.0, [u_wall * x[1], 0.0, 0.0]),
        )
    };
    let mut plain = make();
    let mut viscous = make();
    viscous.set_transport(vec![transport(mu, 0.0)]).unwrap();
    let dt = 1e-3;
    lagrangian_step(&mut plain, dt);
    lagrangian_step(&mut viscous, dt);
    // The wall faces' traction τ_yx (the pass's face array of the y axis).
    let st = viscous.level.patches[0].strides();
    let lo_face = viscous.level.patches[0].local_index([0, GHOST, 0]);
    let hi_face = lo_face + cells * st[1];
    let tau = &viscous.transport.faces[0][0];
    let want = mu * u_wall;
    assert!(
        (tau[lo_face] - want).abs() < 1e-15,
        "{} vs {want}",
        tau[lo_face]
    );
    assert!(
        (tau[hi_face] - want).abs() < 1e-15,
        "{} vs {want}",
        tau[hi_face]
    );
    let a = gather(&plain, |_, l, c| (l[L_VEL][c], l[L_ENERGY][c]));
    let b = gather(&viscous, |_, l, c| (l[L_VEL][c], l[L_ENERGY][c]));
    for (j, (p, v)) in a.iter().zip(&b).enumerate() {
        assert!((v.0 - p.0).abs() < 1e-15, "cell {j}: Δu = {:e}", v.0 - p.0);
        // ρ = 1: Δe = Δt μ (U/H)².
        let heat = dt * mu * u_wall * u_wall;
        assert!(
            ((v.1 - p.1) - heat).abs() < 1e-9 * heat,
            "cell {j}: Δe = {:e}, expected {heat:e}",
            v.1 - p.1
        );
    }
}

/// The decaying shear wave of [`shear_wave`] (u_y = U sin(kx) e^{−νk²t})
/// at 32 and 64 cells: the decay rate against νk², second order.
#[test]
fn the_shear_wave_decays_at_nu_k_squared_with_second_order_convergence() {
    let (r32, r64) = (shear_wave(32).unwrap(), shear_wave(64).unwrap());
    let (e32, b32) = (r32.rate_error, r32.binding);
    let (e64, b64) = (r64.rate_error, r64.binding);
    eprintln!("shear wave: rate error {e32:e} (32 cells), {e64:e} (64 cells)");
    assert_eq!((b32, b64), (TimeStepLimit::Viscous, TimeStepLimit::Viscous));
    assert!(e32.abs() < 5e-4, "{e32:e}");
    assert!(e64.abs() < 1.3e-4, "{e64:e}");
    let order = (e32 / e64).abs().log2();
    assert!((order - 2.0).abs() < 0.15, "order {order}");
}

/// The decaying temperature wave of [`temperature_wave`]
/// (T = T₀ + ΔT sin(kx) e^{−αk²t}, α = k/(ρc_v)) at 32 and 64 cells: the
/// decay rate against αk², second order, and the total energy kept.
#[test]
fn the_temperature_wave_decays_at_alpha_k_squared_with_second_order_convergence() {
    let (r32, r64) = (temperature_wave(32).unwrap(), temperature_wave(64).unwrap());
    let (e32, de32, b32) = (r32.rate_error, r32.energy_change, r32.binding);
    let (e64, de64, b64) = (r64.rate_error, r64.energy_change, r64.binding);
    eprintln!(
        "temperature wave: rate error {e32:e} (32 cells), {e64:e} (64 cells); energy change {de32:e}, {de64:e}"
    );
    assert_eq!(
        (b32, b64),
        (TimeStepLimit::Conduction, TimeStepLimit::Conduction)
    );
    assert!(e32.abs() < 8e-4, "{e32:e}");
    assert!(e64.abs() < 2.2e-4, "{e64:e}");
    let order = (e32 / e64).abs().log2();
    assert!((order - 2.0).abs() < 0.15, "order {order}");
    // Conduction moves energy between cells only.
    assert!(
        de32.abs() < 1e-14 && de64.abs() < 1e-14,
        "{de32:e} {de64:e}"
    );
}

/// The stable step is the smallest of the limits, with the hand values
/// cfl·3/(8 ν Σ1/Δx²) and cfl·c_v/(2 k v Σ1/Δx²).
#[test]
fn the_time_step_takes_the_diffusive_limits() {
    let cells = 20;
    let mut s = solver(
        vec![gas()],
        [cells, cells, 1],
        [1, 1, 1],
        std::array::from_fn(|_| IceBoundary::Periodic),
        0.0,
        0.5,
        |_| CellState::single(1.0, 2.0, [0.0; 3]),
    );
    // c = √(γp/ρ) = √0.7: convective cfl/(2c/Δx).
    let convective = 0.5 / (2.0 * 0.7f64.sqrt() * cells as f64);
    let l = s.time_step_limits().unwrap();
    assert!((l.stable - convective).abs() < 1e-15 * convective);
    assert_eq!((l.viscous, l.conduction), (f64::INFINITY, f64::INFINITY));
    assert_eq!(l.binding(), TimeStepLimit::Convective);
    assert!(s.time_step_limit().unwrap().starts_with("ICE cell ["));
    s.set_transport(vec![transport(0.4, 0.9)]).unwrap();
    let l = s.time_step_limits().unwrap();
    let inv = 2.0 * (cells * cells) as f64;
    // v = 1/2: ν = 0.2; α = 0.9·0.5/1 = 0.45.
    let viscous = 0.5 * 3.0 / (8.0 * 0.2 * inv);
    let conduction = 0.5 / (2.0 * 0.45 * inv);
    assert!((l.viscous - viscous).abs() < 1e-15 * viscous);
    assert!((l.conduction - conduction).abs() < 1e-15 * conduction);
    assert_eq!(l.stable, l.conduction);
    assert!(conduction < viscous.min(convective));
    assert_eq!(l.binding(), TimeStepLimit::Conduction);
    assert_eq!(s.stable_dt().unwrap(), l.stable);
    assert_eq!(
        s.time_step_limit().unwrap(),
        format!("ICE heat conduction limit {conduction:.3e} s")
    );
}

#[test]
fn bad_transport_is_refused_with_the_field_named() {
    let mut s = solver(
        vec![gas()],
        [4, 1, 1],
        [1, 1, 1],
        std::array::from_fn(|_| IceBoundary::Periodic),
        0.0,
        0.4,
        |_| CellState::single(1.0, 1.0, [0.0; 3]),
    );
    let e = s
        .set_transport(vec![transport(-1.0, 0.0)])
        .unwrap_err()
        .to_string();
    assert!(e.contains("`viscosity`") && e.contains("material 1"), "{e}");
    let e = s
        .set_transport(vec![transport(0.0, f64::NAN)])
        .unwrap_err()
        .to_string();
    assert!(e.contains("`thermal_conductivity`"), "{e}");
    let e = s
        .set_transport(vec![transport(0.0, 0.0); 2])
        .unwrap_err()
        .to_string();
    assert!(e.contains("2 transport entries"), "{e}");
    assert!(s.transport().is_empty());
}

/// A two-dimensional run with both coefficients on every face kind.
fn mixed_run(layout: [usize; 3], transport_on: Option<[MaterialTransport; 2]>) -> Vec<u8> {
    use IceBoundary::*;
    let bcs = [
        FixedVelocity([0.0; 3]),
        Symmetry,
        Periodic,
        Periodic,
        Outflow,
        Outflow,
    ];
    let mut s = solver(
        vec![gas(), IdealGas::new(1.67, 3.0, 1.0)],
        [10, 8, 1],
        layout,
        bcs,
        1e3,
        0.4,
        |x| {
            let w = (6.0 * x[0]).sin() * (2.0 * std::f64::consts::PI * x[1]).cos();
            CellState {
                pressure: 1.0 + 0.1 * w,
                materials: vec![
                    MaterialState {
                        volume_fraction: 0.6 + 0.2 * w,
                        density: 1.0 + 0.2 * x[0],
                        velocity: [0.05 * w, 0.1 * x[0], 0.0],
                    },
                    MaterialState {
                        volume_fraction: 0.4 - 0.2 * w,
                        density: 0.5,
                        velocity: [0.0, 0.05 * w, 0.0],
                    },
                ],
            }
        },
    );
    if let Some(t) = transport_on {
        s.set_transport(t.to_vec()).unwrap();
    }
    for _ in 0..3 {
        let dt = s.stable_dt().unwrap();
        s.advance(dt).unwrap();
    }
    s.save_state().unwrap()
}

#[test]
fn results_do_not_depend_on_patches_or_threads() {
    let t = Some([transport(0.02, 0.05), transport(0.01, 0.2)]);
    let run = |layout, threads| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap()
            .install(|| mixed_run(layout, t))
    };
    let a = run([1, 1, 1], 1);
    assert_eq!(a, run([2, 2, 1], 2));
    assert_eq!(a, run([3, 1, 1], 1));
    // Zero coefficients skip the pass: the same bits as no transport.
    let zero = Some([MaterialTransport::default(); 2]);
    assert_eq!(mixed_run([1, 1, 1], None), mixed_run([1, 1, 1], zero));
    assert_ne!(a, mixed_run([1, 1, 1], None));
}

/// Two materials in every cell (θ = 0.3, 0.7) under one shear wave and one
/// temperature wave: one pass changes the cell's momentum by
/// −Δt (θ₁μ₁ + θ₂μ₂) q U sin(kx) and its internal energy by
/// −Δt (θ₁k₁ + θ₂k₂) q ΔT sin(kx), q = 4 sin²(kΔx/2)/Δx² the discrete
/// Laplacian's eigenvalue: the mixture's viscosity and conductivity are the
/// volume-fraction means Σθ_r μ_r and Σθ_r k_r.
#[test]
fn two_materials_diffuse_with_the_volume_fraction_mean() {
    let cells = 16;
    let (u0, t_amp) = (1e-3, 5.0);
    let k = 2.0 * std::f64::consts::PI;
    let theta = [0.3, 0.7];
    let coeff = [transport(0.02, 0.3), transport(0.05, 0.1)];
    let mut s = solver(
        vec![gas(), IdealGas::new(1.67, 3.0, 1.0)],
        [cells, 1, 1],
        [1, 1, 1],
        std::array::from_fn(|_| IceBoundary::Periodic),
        0.0,
        0.4,
        |_| CellState {
            pressure: 1.0,
            materials: (0..2)
                .map(|r| MaterialState {
                    volume_fraction: theta[r],
                    density: 1.0,
                    velocity: [0.0; 3],
                })
                .collect(),
        },
    );
    s.set_transport(coeff.to_vec()).unwrap();
    // The pass reads u and T of the state (with θ uniform), and writes the
    // Lagrangian values: set both directly.
    edit_state(&mut s, |x, v| {
        for r in 0..2 {
            v[r * NS + VEL + 1] = u0 * (k * x[0]).sin();
            v[r * NS + TEMP] = 300.0 + t_amp * (k * x[0]).sin();
        }
    });
    s.fill_state_ghosts();
    copy_state_to_lag(&mut s);
    // Per cell and material: the Lagrangian (ρ, u_y, e).
    let lagrangian = |s: &IceSolver<_>| {
        gather(s, |_, l, c| {
            (0..2)
                .map(|r| {
                    (
                        l[r * NL + L_RHO][c],
                        l[r * NL + L_VEL + 1][c],
                        l[r * NL + L_ENERGY][c],
                    )
                })
                .collect::<Vec<_>>()
        })
    };
    let before = lagrangian(&s);
    let dt = 1e-3;
    s.compute_diffusion_sources(dt);
    let after = lagrangian(&s);
    let dx = 1.0 / cells as f64;
    let q = 4.0 * (k * dx / 2.0).sin().powi(2) / (dx * dx);
    let mu_mix = theta[0] * coeff[0].viscosity + theta[1] * coeff[1].viscosity;
    let k_mix = theta[0] * coeff[0].thermal_conductivity + theta[1] * coeff[1].thermal_conductivity;
    for i in 0..cells {
        let sin = (k * (i as f64 + 0.5) * dx).sin();
        let dmom: f64 = (0..2)
            .map(|r| after[i][r].0 * (after[i][r].1 - before[i][r].1))
            .sum();
        let want = -dt * mu_mix * q * u0 * sin;
        assert!(
            (dmom - want).abs() < 1e-12 * u0,
            "cell {i}: {dmom:e} vs {want:e}"
        );
        let de: f64 = (0..2)
            .map(|r| after[i][r].0 * (after[i][r].2 - before[i][r].2))
            .sum();
        // The viscous heating is O(μ U² k²) ≈ 10⁻⁶ of the conducted heat.
        let want = -dt * k_mix * q * t_amp * sin;
        assert!(
            (de - want).abs() < 1e-5 * dt * k_mix * q * t_amp,
            "cell {i}: {de:e} vs {want:e}"
        );
    }
}

/// The Lagrangian values (ρ, u, e) of every material set to the state's.
fn copy_state_to_lag<E: Eos>(s: &mut IceSolver<E>) {
    let n = s.eos.len();
    for (pid, patch) in s.level.patches.iter().enumerate() {
        let (d, l) = (&s.state[pid].data, &mut s.lag[pid].data);
        for_interior(patch, |c| {
            for r in 0..n {
                l[r * NL + L_RHO][c] = d[r * NS + RHO][c];
                for j in 0..3 {
                    l[r * NL + L_VEL + j][c] = d[r * NS + VEL + j][c];
                }
                l[r * NL + L_ENERGY][c] = d[r * NS + ENERGY][c];
            }
        });
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(24))]

    /// For any velocities, temperatures, volume fractions and
    /// coefficients, one pass conserves momentum (periodic faces) and total
    /// energy to round-off; with symmetry planes on x the energy and the
    /// momentum along them (y) are still conserved (no shear stress, no
    /// work, no heat cross them), and with a no-slip wall at rest the
    /// energy is (no work, no heat).
    #[test]
    fn the_pass_conserves_momentum_and_total_energy(
        seed in proptest::collection::vec(-1.0f64..1.0, 4 * 6 * 5),
        mu in proptest::collection::vec(0.0f64..0.1, 2),
        kc in proptest::collection::vec(0.0f64..0.5, 2),
        theta in 0.05f64..0.95,
        walls in 0usize..3,
        layout in 1usize..=2,
    ) {
        use IceBoundary::*;
        let bcs = match walls {
            0 => std::array::from_fn(|_| Periodic),
            1 => [Symmetry, Symmetry, Periodic, Periodic, Periodic, Periodic],
            _ => [FixedVelocity([0.0; 3]), Symmetry, Periodic, Periodic, Periodic, Periodic],
        };
        let mut s = solver(
            vec![gas(), IdealGas::new(1.67, 3.0, 1.0)],
            [6, 5, 1],
            [layout, 1, 1],
            bcs,
            0.0,
            0.4,
            |_| CellState {
                pressure: 1.0,
                materials: vec![
                    MaterialState { volume_fraction: theta, density: 1.0, velocity: [0.0; 3] },
                    MaterialState { volume_fraction: 1.0 - theta, density: 2.0, velocity: [0.0; 3] },
                ],
            },
        );
        s.set_transport(vec![transport(mu[0], kc[0]), transport(mu[1], kc[1])]).unwrap();
        edit_state(&mut s, |x, v| {
            let i = (x[0] * 6.0) as usize + 6 * (x[1] * 5.0) as usize;
            for r in 0..2 {
                let z = &seed[4 * i..4 * i + 4];
                v[r * NS + VEL] = z[0] + 0.3 * r as f64;
                v[r * NS + VEL + 1] = z[1];
                v[r * NS + TEMP] = 300.0 * (1.0 + 0.5 * z[2]);
                v[r * NS + THETA] = if r == 0 { theta * (1.0 + 0.5 * z[3]) } else { 1.0 - theta };
            }
        });
        s.fill_state_ghosts();
        copy_state_to_lag(&mut s);
        let (m0, e0) = lag_totals(&s);
        s.compute_diffusion_sources(1e-3);
        let (m1, e1) = lag_totals(&s);
        prop_assert!((e1 - e0).abs() < 1e-14 * e0, "energy {} -> {}", e0, e1);
        // Along the walls only where they carry no shear stress.
        if walls < 2 {
            prop_assert!((m1[1] - m0[1]).abs() < 1e-13, "y momentum {} -> {}", m0[1], m1[1]);
        }
        if walls == 0 {
            prop_assert!((m1[0] - m0[0]).abs() < 1e-13, "x momentum {} -> {}", m0[0], m1[0]);
        }
        // Something moved (the test can fail).
        let changed = gather(&s, |d, l, c| (l[L_VEL][c] - d[VEL][c]).abs()).iter().cloned().fold(0.0, f64::max);
        prop_assert!(mu[0] == 0.0 || changed > 0.0);
    }
}
