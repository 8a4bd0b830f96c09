//! Solver-level tests: uniform states, conservation, determinism,
//! checkpoints and reduced shock tubes.

use brisance_core::Solver;
use brisance_eos::IdealGas;
use brisance_grid::Level;

use crate::cases::{contact_width, run_to, sod_one, sod_two};
use crate::solver::GHOST;
use crate::{
    Advection, CellState, ExchangeCoefficients, IceBoundary, IceError, IceOptions, IceRate,
    IceReaction, IceSolver, MaterialState, PressureSolve,
};

/// The totals of the cells alone: the conservation totals less what has
/// left through the faces.
fn interior_totals<E: brisance_core::Eos>(s: &IceSolver<E>) -> brisance_core::ConservationTotals {
    let (t, o) = (s.conservation_totals(), s.outflow_sum());
    brisance_core::ConservationTotals {
        mass: t.mass - o.mass,
        momentum: std::array::from_fn(|a| t.momentum[a] - o.momentum[a]),
        energy: t.energy - o.energy,
    }
}

fn mat(theta: f64, density: f64, u: f64) -> MaterialState {
    MaterialState {
        volume_fraction: theta,
        density,
        velocity: [u, 0.0, 0.0],
    }
}

#[test]
fn sod_plateaus_are_close_to_the_exact_star_states() {
    let s = sod_one(200, Advection::VanLeer, 0.2);
    let d = s
        .cell_data(&["density".into(), "pressure".into(), "velocity_x".into()])
        .unwrap();
    let (rho, p, u) = (
        d.field("density").unwrap(),
        d.field("pressure").unwrap(),
        d.field("velocity_x").unwrap(),
    );
    for i in (0..200).step_by(10) {
        eprintln!(
            "{:.3} {:.4} {:.4} {:.4}",
            (i as f64 + 0.5) / 200.0,
            rho[i],
            u[i],
            p[i]
        );
    }
    // Toro's exact star state: p* = 0.30313, u* = 0.92745, ρ*L = 0.42632,
    // ρ*R = 0.26557; x = 0.7 lies between contact (0.685) and shock (0.850).
    let i = 150; // x = 0.7525
                 // With the energy-conserving closure the shock jump is the exact one
                 // (measured at 200 cells: p 0.30317, u 0.92765, ρ 0.26559).
    assert!((p[i] - 0.30313).abs() < 1e-3, "p = {}", p[i]);
    assert!((u[i] - 0.92745).abs() < 1e-3, "u = {}", u[i]);
    assert!((rho[i] - 0.26557).abs() < 1e-3, "rho = {}", rho[i]);
    let i = 120; // x = 0.6025, left plateau (0.42430 measured)
    assert!((rho[i] - 0.42632).abs() < 3e-3, "rho = {}", rho[i]);
}

/// Two-material states used below: an ideal gas γ 1.4 and one γ 1.67.
fn two_gases() -> Vec<IdealGas> {
    vec![
        IdealGas::new(1.4, 717.5, 1.0),
        IdealGas::new(1.67, 3115.0, 1.0),
    ]
}

fn uniform_solver(
    cells: [usize; 3],
    layout: [usize; 3],
    bcs: [IceBoundary; 6],
    velocity: [f64; 3],
) -> IceSolver<IdealGas> {
    let upper = [1.0, 0.8, 0.6].map(|x: f64| x);
    let level = Level::new([0.0; 3], upper, cells, layout, GHOST).unwrap();
    let state = CellState {
        pressure: 1.0e5,
        materials: vec![
            MaterialState {
                volume_fraction: 0.7,
                density: 1.2,
                velocity,
            },
            MaterialState {
                volume_fraction: 0.3,
                density: 0.2,
                velocity,
            },
        ],
    };
    IceSolver::new(
        two_gases(),
        level,
        bcs,
        ExchangeCoefficients::uniform(2, 1e15, 0.0),
        IceOptions::default(),
        |_| state.clone(),
    )
    .unwrap()
}

fn all_fields<E: brisance_core::Eos>(s: &IceSolver<E>) -> Vec<(String, Vec<f64>)> {
    let names: Vec<String> = s.cell_field_names().iter().map(|n| n.to_string()).collect();
    s.cell_data(&names).unwrap().fields
}

#[test]
fn a_uniform_moving_state_is_unchanged_by_every_step() {
    use IceBoundary::*;
    let u = [30.0, -20.0, 10.0];
    let st = CellState {
        pressure: 1.0e5,
        materials: vec![
            MaterialState {
                volume_fraction: 0.7,
                density: 1.2,
                velocity: u,
            },
            MaterialState {
                volume_fraction: 0.3,
                density: 0.2,
                velocity: u,
            },
        ],
    };
    // Outflow faces where the flow leaves (+x, +z): an outflow face lets
    // nothing in, so an inflow face holds the fixed state.
    let bcs = [
        FixedState(st.clone()),
        Outflow,
        Periodic,
        Periodic,
        FixedState(st),
        Outflow,
    ];
    let mut s = uniform_solver([6, 5, 4], [2, 1, 1], bcs, u);
    let before = all_fields(&s);
    for _ in 0..5 {
        let dt = s.stable_dt().unwrap();
        s.advance(dt).unwrap();
    }
    let after = all_fields(&s);
    for ((name, a), (_, b)) in before.iter().zip(&after) {
        for (x, y) in a.iter().zip(b) {
            assert!(
                (x - y).abs() <= 1e-13 * x.abs().max(1e-3),
                "{name}: {x} -> {y}"
            );
        }
    }
}

#[test]
fn a_wall_moving_with_the_gas_leaves_it_unchanged() {
    use IceBoundary::*;
    let u = [25.0, 0.0, 0.0];
    let bcs = [
        FixedVelocity(u),
        Outflow,
        Symmetry,
        Symmetry,
        Symmetry,
        Symmetry,
    ];
    let mut s = uniform_solver([8, 1, 1], [1, 1, 1], bcs, u);
    let before = all_fields(&s);
    for _ in 0..10 {
        let dt = s.stable_dt().unwrap();
        s.advance(dt).unwrap();
    }
    for ((name, a), (_, b)) in before.iter().zip(&all_fields(&s)) {
        for (x, y) in a.iter().zip(b) {
            assert!(
                (x - y).abs() <= 1e-12 * x.abs().max(1e-3),
                "{name}: {x} -> {y}"
            );
        }
    }
}

/// A gas column with a pressure bump, periodic along x: mass of every
/// material and total momentum are conserved to round-off.
fn bump_solver(layout: [usize; 3], cells: [usize; 3]) -> IceSolver<IdealGas> {
    bump_solver_with(layout, cells, IceOptions::default())
}

fn bump_solver_with(
    layout: [usize; 3],
    cells: [usize; 3],
    options: IceOptions,
) -> IceSolver<IdealGas> {
    bump_solver_on(
        std::sync::Arc::new(brisance_grid::comm::Serial),
        layout,
        cells,
        options,
    )
    .unwrap()
}

/// [`bump_solver_with`] built with its patches shared among the ranks of
/// `comm` ([`IceSolver::new_on`]).
fn bump_solver_on(
    comm: std::sync::Arc<dyn brisance_grid::comm::Communicator>,
    layout: [usize; 3],
    cells: [usize; 3],
    options: IceOptions,
) -> Result<IceSolver<IdealGas>, IceError> {
    let level = Level::new([0.0; 3], [1.0, 0.5, 0.25], cells, layout, GHOST).unwrap();
    let bcs: [IceBoundary; 6] = std::array::from_fn(|f| {
        if f < 2 {
            IceBoundary::Periodic
        } else {
            IceBoundary::Symmetry
        }
    });
    IceSolver::new_on(
        comm,
        two_gases(),
        level,
        bcs,
        ExchangeCoefficients::uniform(2, 1e15, 1e6),
        options,
        |x| {
            let hot = (x[0] - 0.3).abs() < 0.15 && x[1] < 0.3;
            let th = if x[0] < 0.5 { 0.999 } else { 0.001 };
            CellState {
                pressure: if hot { 3.0e5 } else { 1.0e5 },
                materials: vec![
                    MaterialState {
                        volume_fraction: th,
                        density: 1.2,
                        velocity: [5.0, 0.0, 0.0],
                    },
                    MaterialState {
                        volume_fraction: 1.0 - th,
                        density: 0.3,
                        velocity: [5.0, 0.0, 0.0],
                    },
                ],
            }
        },
    )
}

#[test]
fn mass_momentum_and_energy_are_conserved_to_round_off_in_a_periodic_tube() {
    let mut s = bump_solver([1, 1, 1], [40, 1, 1]);
    let t0 = s.conservation_totals();
    for _ in 0..40 {
        let dt = s.stable_dt().unwrap();
        s.advance(dt).unwrap();
    }
    let t1 = s.conservation_totals();
    assert!(
        ((t1.mass - t0.mass) / t0.mass).abs() < 1e-14,
        "{t0:?} {t1:?}"
    );
    // Momentum scale: mass × a sound speed.
    let scale = t0.mass * 400.0;
    assert!(
        ((t1.momentum[0] - t0.momentum[0]) / scale).abs() < 1e-14,
        "{t0:?} {t1:?}"
    );
    let de = (t1.energy - t0.energy) / t0.energy;
    eprintln!("relative energy change over 40 steps: {de:e}");
    assert!(de.abs() < 1e-13, "{de}");
    // The pressure bump really moved something.
    let p = s.cell_data(&["pressure".into()]).unwrap().fields[0]
        .1
        .clone();
    assert!(p.iter().cloned().fold(0.0, f64::max) < 2.9e5);
}

/// Eqs 25 and step 12 taken literally (internal energy only) lose total
/// energy at the pressure pulse; the conservative closure is what removes it.
#[test]
fn the_literal_internal_energy_form_does_not_conserve_energy() {
    let mut s = bump_solver_with(
        [1, 1, 1],
        [40, 1, 1],
        IceOptions {
            conserve_total_energy: false,
            ..Default::default()
        },
    );
    let t0 = s.conservation_totals();
    for _ in 0..40 {
        let dt = s.stable_dt().unwrap();
        s.advance(dt).unwrap();
    }
    let de = (s.conservation_totals().energy - t0.energy) / t0.energy;
    eprintln!("literal form: relative energy change {de:e}");
    assert!(de.abs() > 1e-6, "{de}");
}

#[test]
fn results_do_not_depend_on_patches_or_threads() {
    let run = |layout: [usize; 3], threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        pool.install(|| {
            let mut s = bump_solver(layout, [12, 8, 4]);
            for _ in 0..4 {
                let dt = s.stable_dt().unwrap();
                s.advance(dt).unwrap();
            }
            s.save_state().unwrap()
        })
    };
    let a = run([1, 1, 1], 1);
    assert_eq!(a, run([3, 2, 2], 2));
    assert_eq!(a, run([2, 1, 1], 1));
}

#[test]
fn restore_continues_bit_identically() {
    let mut s = bump_solver([1, 1, 1], [16, 4, 1]);
    for _ in 0..3 {
        let dt = s.stable_dt().unwrap();
        s.advance(dt).unwrap();
    }
    let saved = s.save_state().unwrap();
    let mut t = bump_solver([2, 2, 1], [16, 4, 1]);
    t.restore_state(&saved).unwrap();
    for _ in 0..3 {
        let dt = s.stable_dt().unwrap();
        assert_eq!(dt, t.stable_dt().unwrap());
        s.advance(dt).unwrap();
        t.advance(dt).unwrap();
    }
    assert_eq!(s.save_state().unwrap(), t.save_state().unwrap());
    let other = bump_solver([1, 1, 1], [8, 4, 1]);
    let mut other = other;
    assert!(other.restore_state(&saved).is_err());
}

/// The run loop's snapshot rewinds the solver it was taken of, counters
/// included: the steps taken again give the same bits.
#[test]
fn a_snapshot_rewinds_the_solver_bit_identically() {
    let mut s = bump_solver([2, 1, 1], [16, 4, 1]);
    let step = |s: &mut IceSolver<_>| {
        let dt = s.stable_dt().unwrap();
        s.advance(dt).unwrap();
    };
    step(&mut s);
    let snapshot = s.save_snapshot().unwrap();
    for _ in 0..3 {
        step(&mut s);
    }
    let after = s.save_state().unwrap();
    s.restore_snapshot(&snapshot).unwrap();
    assert_ne!(s.save_state().unwrap(), after);
    for _ in 0..3 {
        step(&mut s);
    }
    assert_eq!(s.save_state().unwrap(), after);
    let mut other = bump_solver([1, 1, 1], [8, 4, 1]);
    assert!(other.restore_snapshot(&snapshot).is_err());
}

#[test]
fn contacting_materials_move_together_after_one_step() {
    let level = Level::new([0.0; 3], [1.0, 1.0, 1.0], [4, 1, 1], [1, 1, 1], GHOST).unwrap();
    let mut s = IceSolver::new(
        two_gases(),
        level,
        std::array::from_fn(|_| IceBoundary::Periodic),
        ExchangeCoefficients::uniform(2, 1e15, 0.0),
        IceOptions::default(),
        |_| CellState {
            pressure: 1e5,
            materials: vec![
                MaterialState {
                    volume_fraction: 0.5,
                    density: 1.0,
                    velocity: [10.0, 0.0, 0.0],
                },
                MaterialState {
                    volume_fraction: 0.5,
                    density: 0.5,
                    velocity: [-20.0, 0.0, 0.0],
                },
            ],
        },
    )
    .unwrap();
    let p0 = s.conservation_totals();
    let dt = s.stable_dt().unwrap();
    s.advance(dt).unwrap();
    let d = s
        .cell_data(&["velocity_x_1".into(), "velocity_x_2".into()])
        .unwrap();
    let (u1, u2) = (d.fields[0].1[0], d.fields[1].1[0]);
    // mass-weighted mean (0.5·10 − 0.25·20)/0.75 = 0
    assert!(u1.abs() < 1e-9 && u2.abs() < 1e-9, "{u1} {u2}");
    let p1 = s.conservation_totals();
    // The kinetic energy the exchange dissipated is now internal energy.
    assert!(
        ((p1.energy - p0.energy) / p0.energy).abs() < 1e-14,
        "{p0:?} {p1:?}"
    );
}

#[test]
fn bad_input_is_refused_with_the_field_named() {
    let level = Level::new([0.0; 3], [1.0, 1.0, 1.0], [4, 1, 1], [1, 1, 1], GHOST).unwrap();
    let make = |theta: f64, cfl: f64| {
        IceSolver::new(
            two_gases(),
            level.clone(),
            std::array::from_fn(|_| IceBoundary::Outflow),
            ExchangeCoefficients::uniform(2, 1e15, 0.0),
            IceOptions {
                cfl,
                ..Default::default()
            },
            move |_| CellState {
                pressure: 1e5,
                materials: vec![mat(theta, 1.0, 0.0), mat(0.5, 1.0, 0.0)],
            },
        )
        .map(|_| ())
        .unwrap_err()
        .to_string()
    };
    assert!(make(0.2, 0.4).contains("volume fractions sum"));
    assert!(make(0.5, 1.5).contains("cfl"));
    for nu in [-0.1, 1.5, f64::NAN] {
        let e = IceSolver::new(
            two_gases(),
            level.clone(),
            std::array::from_fn(|_| IceBoundary::Outflow),
            ExchangeCoefficients::uniform(2, 1e15, 0.0),
            IceOptions {
                face_pressure_courant: nu,
                ..Default::default()
            },
            move |_| CellState {
                pressure: 1e5,
                materials: vec![mat(0.5, 1.0, 0.0), mat(0.5, 1.0, 0.0)],
            },
        )
        .map(|_| ())
        .unwrap_err()
        .to_string();
        assert!(e.contains("face_pressure_courant"), "{e}");
    }
}

#[test]
fn two_material_sod_has_no_pressure_spike_and_a_narrow_contact() {
    let s = sod_two(200, Advection::VanLeer, 0.2);
    let m = contact_width(&s).unwrap();
    eprintln!("{m:?}");
    // No spike: pressure within 1 % of the plateau around the contact.
    assert!(m.pressure_excursion < 0.01, "{m:?}");
    // Measured 4.6 cells (θ 0.9 → 0.1) at 200 cells; the V-SOD-ICE target
    // of 3 cells is reported by `cargo xtask validate`. This bound catches
    // a regression to donor-cell smearing (about 13 cells here).
    assert!(m.width_cells < 5.0, "{m:?}");
    let d = sod_two(200, Advection::DonorCell, 0.2);
    let md = contact_width(&d).unwrap();
    eprintln!("donor cell: {md:?}");
    assert!(md.width_cells > m.width_cells, "{md:?}");
}

/// The compressive option (THINC volume fractions in interface cells)
/// keeps the two-material contact within three cells (measured 1.50 at 200
/// cells, against 4.74 with van Leer) with the pressure within 1 % of the
/// plateau around it (measured 0.14 %).
#[test]
fn compressive_advection_keeps_the_contact_within_three_cells() {
    let s = sod_two(200, Advection::Compressive, 0.2);
    let m = contact_width(&s).unwrap();
    assert!(m.width_cells <= 3.0, "{m:?}");
    let v = sod_two(200, Advection::VanLeer, 0.2);
    assert!(m.width_cells < contact_width(&v).unwrap().width_cells);
    assert!(m.pressure_excursion <= 0.01, "{m:?}");
}

/// Throughput of a full step for three materials on a 3D box (release:
/// `cargo test --release -p brisance-ice throughput -- --ignored --nocapture`).
#[test]
#[ignore]
fn throughput_three_materials_3d() {
    let n = 32;
    for layout in [[1, 1, 1], [1, 1, 2]] {
        let level = Level::new([0.0; 3], [1.0; 3], [n, n, n], layout, GHOST).unwrap();
        let eos = vec![
            IdealGas::new(1.4, 717.5, 1.0),
            IdealGas::new(1.67, 3115.0, 1.0),
            IdealGas::new(1.3, 1000.0, 1.0),
        ];
        let mut s = IceSolver::new(
            eos,
            level,
            std::array::from_fn(|_| IceBoundary::Symmetry),
            ExchangeCoefficients::uniform(3, 1e15, 0.0),
            IceOptions::default(),
            |x| {
                let r2 = (x[0] - 0.5).powi(2) + (x[1] - 0.5).powi(2) + (x[2] - 0.5).powi(2);
                let th = if r2 < 0.04 {
                    [0.98, 0.01, 0.01]
                } else {
                    [0.01, 0.98, 0.01]
                };
                CellState {
                    pressure: if r2 < 0.04 { 1e6 } else { 1e5 },
                    materials: (0..3)
                        .map(|r| MaterialState {
                            volume_fraction: th[r],
                            density: 1.0,
                            velocity: [0.0; 3],
                        })
                        .collect(),
                }
            },
        )
        .unwrap();
        let steps = 10;
        let t = std::time::Instant::now();
        for _ in 0..steps {
            let dt = s.stable_dt().unwrap();
            s.advance(dt).unwrap();
        }
        let rate = (steps * n * n * n) as f64 / t.elapsed().as_secs_f64();
        eprintln!(
            "layout {layout:?}, {} threads: {:.3e} cell-updates/s, equilibration {:?}",
            rayon::current_num_threads(),
            rate,
            s.equilibration_stats()
        );
    }
}

/// A closed box (symmetry on every face) with a pressure bump: the walls
/// pass no mass and do no work, so mass and total energy stay to round-off.
#[test]
fn a_closed_box_conserves_mass_and_energy() {
    let level = Level::new([0.0; 3], [1.0, 0.5, 0.1], [20, 10, 1], [2, 1, 1], GHOST).unwrap();
    let mut s = IceSolver::new(
        two_gases(),
        level,
        std::array::from_fn(|_| IceBoundary::Symmetry),
        ExchangeCoefficients::uniform(2, 1e15, 0.0),
        IceOptions::default(),
        |x| {
            let inside = (x[0] - 0.2).powi(2) + (x[1] - 0.25).powi(2) < 0.01;
            let th = if inside { 0.999 } else { 0.001 };
            CellState {
                pressure: if inside { 5.0e5 } else { 1.0e5 },
                materials: vec![
                    MaterialState {
                        volume_fraction: th,
                        density: 3.0,
                        velocity: [0.0; 3],
                    },
                    MaterialState {
                        volume_fraction: 1.0 - th,
                        density: 0.4,
                        velocity: [0.0; 3],
                    },
                ],
            }
        },
    )
    .unwrap();
    let t0 = s.conservation_totals();
    for _ in 0..60 {
        let dt = s.stable_dt().unwrap();
        s.advance(dt).unwrap();
    }
    let t1 = s.conservation_totals();
    let dm = (t1.mass - t0.mass) / t0.mass;
    let de = (t1.energy - t0.energy) / t0.energy;
    assert!(dm.abs() < 1e-14, "{dm:e}");
    assert!(de.abs() < 1e-13, "{de:e}");
    // The blast reached the walls: something moved.
    let u = s.cell_data(&["velocity_x".into()]).unwrap().fields[0]
        .1
        .clone();
    assert!(u.iter().any(|v| v.abs() > 1.0));
}

/// A wall moving at 50 m/s into still air (FixedVelocity) drives a shock;
/// the gas between wall and shock moves with the wall.
#[test]
fn a_piston_drives_the_gas_at_its_own_speed() {
    let level = Level::new([0.0; 3], [1.0, 0.1, 0.1], [100, 1, 1], [1, 1, 1], GHOST).unwrap();
    let mut s = IceSolver::new(
        vec![IdealGas::air()],
        level,
        [
            IceBoundary::FixedVelocity([50.0, 0.0, 0.0]),
            IceBoundary::Outflow,
            IceBoundary::Symmetry,
            IceBoundary::Symmetry,
            IceBoundary::Symmetry,
            IceBoundary::Symmetry,
        ],
        ExchangeCoefficients::uniform(1, 0.0, 0.0),
        IceOptions::default(),
        |_| CellState {
            pressure: 1.0e5,
            materials: vec![mat(1.0, 1.2, 0.0)],
        },
    )
    .unwrap();
    // Shock speed ≈ c + (γ+1)/4·u_p ≈ 347 + 30 m/s: at 1 ms it is ~0.38 m out.
    run_to(&mut s, 1.0e-3).unwrap();
    let u = s.cell_data(&["velocity_x".into()]).unwrap().fields[0]
        .1
        .clone();
    for (i, v) in u.iter().enumerate().take(30).skip(2) {
        assert!((v - 50.0).abs() < 1.0, "cell {i}: {v}");
    }
    assert!(u[60].abs() < 1e-6, "{}", u[60]);
}

/// JWL++ reaction in a closed box (symmetry on every face) of ANFO-K1
/// reactant above the 200 MPa threshold: mass, momentum and the total
/// energy with the reactant's chemical energy stay to round-off while a
/// good part of the explosive burns.
#[test]
fn a_reacting_closed_box_conserves_mass_momentum_and_energy() {
    use brisance_eos::EosModel;
    let (eos, reaction) = crate::cases::anfo_k1_jwlpp().unwrap();
    let level = Level::new([0.0; 3], [0.02, 0.001, 0.001], [20, 1, 1], [2, 1, 1], GHOST).unwrap();
    let (pr, pl) = (3.0e8, 1.0e9);
    let dens = |e: &EosModel, p: f64| brisance_core::Eos::density(e, p, 298.15).unwrap();
    let rho = [
        [dens(&eos[0], pl), dens(&eos[1], pl)],
        [dens(&eos[0], pr), dens(&eos[1], pr)],
    ];
    let mut s = IceSolver::new(
        eos,
        level,
        std::array::from_fn(|_| IceBoundary::Symmetry),
        ExchangeCoefficients::uniform(2, 1e15, 0.0),
        IceOptions::default(),
        |x| {
            let (p, r) = if x[0] < 0.01 {
                (pl, rho[0])
            } else {
                (pr, rho[1])
            };
            CellState {
                pressure: p,
                materials: vec![mat(1.0 - 1e-6, r[0], 0.0), mat(1e-6, r[1], 0.0)],
            }
        },
    )
    .unwrap();
    s.set_reactions(vec![reaction]).unwrap();
    let t0 = s.conservation_totals();
    let m_prod = |s: &IceSolver<EosModel>| {
        s.cell_data(&["density_2".into()]).unwrap().fields[0]
            .1
            .iter()
            .sum::<f64>()
    };
    let before = m_prod(&s);
    for _ in 0..40 {
        let dt = s.stable_dt().unwrap();
        s.advance(dt).unwrap();
    }
    let t1 = s.conservation_totals();
    let dm = (t1.mass - t0.mass) / t0.mass;
    let de = (t1.energy - t0.energy) / t0.energy;
    let after = m_prod(&s);
    eprintln!(
        "dm {dm:e} de {de:e} Σρ_products {before:e} -> {after:e} kg/m³ at t = {:e} s, momentum {:?}",
        s.time(),
        t1.momentum
    );
    assert!(after > 100.0 * before, "the explosive did not burn");
    assert!(dm.abs() < 1e-14, "{dm:e}");
    assert!(de.abs() < 1e-13, "{de:e}");
    // Momentum: the box is symmetric only in its walls; x-momentum is
    // exchanged with the walls, y and z stay zero.
    assert_eq!(t1.momentum[1], 0.0);
}

/// A reaction model of another crate, handed to the solver as
/// `IceRate::Model`: step 4 calls it through `ReactionModel::burnt_density`
/// with the cell's equilibration pressure, the reactant's temperature and
/// density and the step's end time, and each cell of a uniform box at rest
/// burns exactly k Δt (ρ_r + ρ_p) (dF/dt = k; seed 000 eq 37).
#[test]
fn a_reaction_model_of_another_crate_burns_through_the_trait() {
    use brisance_core::{ReactionModel, ReactionState};
    use brisance_eos::EosModel;
    use std::sync::{Arc, Mutex};
    #[derive(Debug)]
    struct Constant {
        k: f64,
        seen: Mutex<Vec<ReactionState>>,
    }
    impl ReactionModel for Constant {
        fn name(&self) -> &'static str {
            "Constant"
        }
        fn rate(&self, state: &ReactionState, _: f64) -> f64 {
            self.seen.lock().unwrap().push(*state);
            self.k
        }
    }
    let (eos, jwlpp) = crate::cases::anfo_k1_jwlpp().unwrap();
    let model = Arc::new(Constant {
        k: 2.0e4,
        seen: Mutex::new(Vec::new()),
    });
    let level = Level::new([0.0; 3], [0.004, 0.001, 0.001], [4, 1, 1], [1, 1, 1], GHOST).unwrap();
    let p0 = 1.0e8;
    let dens = |e: &EosModel| brisance_core::Eos::density(e, p0, 298.15).unwrap();
    let (rho_r, rho_p) = (dens(&eos[0]), dens(&eos[1]));
    let mut s = IceSolver::new(
        eos,
        level,
        std::array::from_fn(|_| IceBoundary::Symmetry),
        ExchangeCoefficients::uniform(2, 1e15, 0.0),
        IceOptions::default(),
        |_| CellState {
            pressure: p0,
            materials: vec![mat(0.9, rho_r, 0.0), mat(0.1, rho_p, 0.0)],
        },
    )
    .unwrap();
    s.set_reactions(vec![IceReaction {
        rate: IceRate::Model(model.clone()),
        ..jwlpp
    }])
    .unwrap();
    let field =
        |s: &IceSolver<EosModel>, f: &str| s.cell_data(&[f.into()]).unwrap().fields[0].1.clone();
    let (r0, q0) = (field(&s, "density_1"), field(&s, "density_2"));
    let (p_eq, t_r) = (field(&s, "pressure"), field(&s, "temperature_1"));
    let dt = 1e-7;
    s.advance(dt).unwrap();
    let q1 = field(&s, "density_2");
    for c in 0..4 {
        let expect = 2.0e4 * dt * (r0[c] + q0[c]);
        let burnt = q1[c] - q0[c];
        assert!(
            (burnt / expect - 1.0).abs() < 1e-9,
            "cell {c}: {burnt:e} vs {expect:e}"
        );
    }
    let seen = model.seen.lock().unwrap();
    assert_eq!(seen.len(), 4, "one call a cell");
    for st in seen.iter() {
        assert_eq!(st.pressure, p_eq[0]);
        assert!((st.temperature / t_r[0] - 1.0).abs() < 1e-12, "{st:?}");
        assert!((st.density / rho_r - 1.0).abs() < 1e-9, "{st:?}");
        assert_eq!(st.time, dt);
        assert_eq!(st.detonation_time, f64::INFINITY);
    }
}

/// The 1D ANFO-K1 rate stick at h = 2 mm, 6 cm long: the 90 m/s impact on
/// the wall initiates a detonation that reaches both gauges.
#[test]
fn reduced_rate_stick_detonates() {
    let mut cfg = crate::cases::RateStick::seed(2.0e-3);
    cfg.length = 0.06;
    cfg.gauges = [0.03, 0.05];
    let r = crate::cases::rate_stick(&cfg).unwrap();
    eprintln!("{r:?}");
    let d = r.detonation_velocity.expect("no detonation");
    assert!(d > 4000.0 && d < 7000.0, "{d}");
}

/// A booster-started, damped (ν* = 0.8) r–z stick at h = 2 mm, R = 20 mm,
/// 6 cm long: the 20 GPa booster initiates a detonation that reaches both
/// gauges into explosive at rest, and the booster's traces (air, reactant,
/// put at its pressure and 298.15 K) do not set the step: the run takes no
/// more steps than the same stick started by the seed's impact (an air
/// trace at ambient density in the booster is shocked to 20 GPa and heated
/// without bound, and took ten times the steps).
#[test]
fn a_booster_starts_a_damped_rz_stick_at_rest() {
    let shorten = |mut c: crate::cases::RateStick| {
        c.length = 0.06;
        c.gauges = [0.03, 0.05];
        c
    };
    let impact = shorten(crate::cases::RateStick::rz(2e-3, 20e-3));
    let booster = shorten(impact.damped());
    assert_eq!(booster.face_pressure_courant, 0.8);
    let a = crate::cases::rate_stick(&impact).unwrap();
    let b = crate::cases::rate_stick(&booster).unwrap();
    eprintln!("impact {a:?}\nbooster {b:?}");
    let d = b.detonation_velocity.expect("no detonation");
    assert!(d > 4000.0 && d < 7000.0, "{d}");
    assert!(b.velocity_ahead.unwrap().abs() < 5.0, "{b:?}");
    assert!((a.velocity_ahead.unwrap() + 90.0).abs() < 5.0, "{a:?}");
    assert!(b.steps <= a.steps, "{} against {}", b.steps, a.steps);
}

/// One quarter-symmetry ANFO-K1 stick at h = 1 mm, radius from the
/// environment variable R in metres (default 12 mm); minutes in release
/// (`R=0.004 cargo test --release -p brisance-ice rate_stick_quarter -- --ignored --nocapture`).
#[test]
#[ignore]
fn rate_stick_quarter() {
    let r = std::env::var("R").map_or(12e-3, |v| v.parse().unwrap());
    let t = std::time::Instant::now();
    let c = crate::cases::RateStick::quarter(1e-3, r);
    let res = crate::cases::rate_stick(&c);
    eprintln!("R {r:e}: {res:?} {:.1} s", t.elapsed().as_secs_f64());
}

/// The 1D sticks of E-RATESTICK at h = 1, 0.5, 0.25 mm, 10 and 30 cm
/// (`cargo test --release -p brisance-ice rate_stick_resolutions -- --ignored --nocapture`).
#[test]
#[ignore]
fn rate_stick_resolutions() {
    for h in [1.0e-3, 0.5e-3, 0.25e-3] {
        for c in [
            crate::cases::RateStick::seed(h),
            crate::cases::RateStick::long(h),
        ] {
            let r = crate::cases::rate_stick(&c).unwrap();
            eprintln!("h {h:e} L {}: {r:?}", c.length);
        }
    }
}

/// The deflagration through step 4: after step 2 finds the reactant's
/// surface (the last reactant cell before the products, a/V = 1/h on a
/// grid-aligned face), one step burns there exactly
/// Γ Δt / V = (1/h) A p_eqⁿ ρ_reactant Δt (seed 000 eqs 38–39) and nowhere
/// else; below the ignition temperature nothing burns.
#[test]
fn deflagration_burns_the_surface_cell_at_a_p_to_the_n() {
    use brisance_eos::EosModel;
    use brisance_reaction::Deflagration;
    let (eos, jwlpp) = crate::cases::anfo_k1_jwlpp().unwrap();
    let h = 1.0e-3;
    let p0 = 1.0e8;
    let dens = |e: &EosModel| brisance_core::Eos::density(e, p0, 298.15).unwrap();
    let (rho_r, rho_p) = (dens(&eos[0]), dens(&eos[1]));
    let build = |ignition: f64| {
        let level = Level::new([0.0; 3], [6.0 * h, h, h], [6, 1, 1], [1, 1, 1], GHOST).unwrap();
        let mut s = IceSolver::new(
            eos.clone(),
            level,
            std::array::from_fn(|_| IceBoundary::Symmetry),
            ExchangeCoefficients::uniform(2, 1e15, 0.0),
            IceOptions::default(),
            |x| {
                let theta = if x[0] < 3.0 * h { 1.0 - 1e-6 } else { 1e-6 };
                CellState {
                    pressure: p0,
                    materials: vec![mat(theta, rho_r, 0.0), mat(1.0 - theta, rho_p, 0.0)],
                }
            },
        )
        .unwrap();
        s.set_reactions(vec![IceReaction {
            rate: Deflagration::new(2.0e-6, 0.8, ignition).unwrap().into(),
            ..jwlpp.clone()
        }])
        .unwrap();
        s
    };
    let field =
        |s: &IceSolver<EosModel>, f: &str| s.cell_data(&[f.into()]).unwrap().fields[0].1.clone();
    let dt = 1.0e-8;
    let mut s = build(250.0);
    let (r0, q0, p_eq) = (
        field(&s, "density_1"),
        field(&s, "density_2"),
        field(&s, "pressure"),
    );
    let theta = field(&s, "volume_fraction_1");
    s.advance(dt).unwrap();
    let q1 = field(&s, "density_2");
    let r1 = field(&s, "density_1");
    for c in 0..6 {
        let burnt = q1[c] - q0[c];
        if c == 2 {
            // ρ_reactant = ρ_1 / θ_1, the explosive's own density.
            let expect = 2.0e-6 * p_eq[c].powf(0.8) * r0[c] / theta[c] * dt / h;
            assert!(
                (burnt / expect - 1.0).abs() < 1e-9,
                "cell {c}: {burnt:e} vs {expect:e}"
            );
            assert!(((r0[c] - r1[c]) / expect - 1.0).abs() < 1e-9);
        } else {
            assert!(burnt.abs() < 1e-12 * q0[c].max(1.0), "cell {c}: {burnt:e}");
        }
    }
    // Every material is at 298 K: an ignition temperature of 300 K lights
    // nothing.
    let mut cold = build(300.0);
    let q0 = field(&cold, "density_2");
    cold.advance(dt).unwrap();
    let q1 = field(&cold, "density_2");
    for c in 0..6 {
        assert!((q1[c] - q0[c]).abs() < 1e-12 * q0[c].max(1.0), "cell {c}");
    }
}

mod lagrangian;
mod open_faces;

/// An initial state that fails in cells of the last patches: built spread
/// over 1, 2 and 4 thread ranks, every rank meets the error of the first
/// failing cell in patch order, as one rank does, though it evaluates
/// only its own patches' cells.
#[test]
fn a_failing_initial_state_gives_every_rank_the_error_of_one() {
    let build = |comm: std::sync::Arc<dyn brisance_grid::comm::Communicator>| {
        let level = Level::new([0.0; 3], [1.0; 3], [8, 4, 8], [2, 1, 2], GHOST).unwrap();
        IceSolver::new_on(
            comm,
            two_gases(),
            level,
            std::array::from_fn(|_| IceBoundary::Symmetry),
            ExchangeCoefficients::uniform(2, 1e15, 1e6),
            IceOptions::default(),
            |x| {
                // No pressure at x > 0.3 in the upper half of z (patches 2
                // and 3).
                let bad = x[0] > 0.3 && x[2] > 0.5;
                let gas = |th: f64| MaterialState {
                    volume_fraction: th,
                    density: 1.2,
                    velocity: [0.0; 3],
                };
                CellState {
                    pressure: if bad { 0.0 } else { 1.0e5 },
                    materials: vec![gas(0.5), gas(0.5)],
                }
            },
        )
        .err()
        .map(|e| e.to_string())
    };
    let one = build(std::sync::Arc::new(brisance_grid::comm::Serial)).expect("fails");
    // Patch 2 (x < 0.5, upper z) holds the first failing cell, (2, 0, 4).
    assert!(one.contains("cell [2, 0, 4]"), "{one}");
    for ranks in [1, 2, 4] {
        for (r, e) in brisance_grid::comm::InProcess::run(ranks, 1, build)
            .into_iter()
            .enumerate()
        {
            assert_eq!(e.as_deref(), Some(one.as_str()), "rank {r} of {ranks}");
        }
    }
}

/// Viscosity and heat conduction (step 8) on ranks: the pressure bump of
/// [`patches_spread_over_thread_ranks_give_the_bits_of_one`] with both
/// gases viscous and conducting, strongly enough that the diffusive limits
/// set the step, spread over 2 and 4 thread ranks (the face stencil reads
/// the ghost layers' edges and corners; the time step's limit and the
/// faces' bookings are reduced over the ranks): every rank ends with the
/// saved state and the conservation totals of one rank.
#[test]
fn viscosity_and_conduction_spread_over_thread_ranks_give_the_bits_of_one() {
    let transport = crate::MaterialTransport {
        viscosity: 20.0,
        thermal_conductivity: 400.0,
    };
    let build = |comm| {
        let mut s = bump_solver_on(comm, [3, 2, 2], [12, 8, 4], IceOptions::default()).unwrap();
        s.set_transport(vec![transport; 2]).unwrap();
        s
    };
    let steps = |s: &mut IceSolver<IdealGas>| {
        let limits = s.time_step_limits().unwrap();
        for _ in 0..4 {
            let dt = s.stable_dt().unwrap();
            s.advance(dt).unwrap();
        }
        (limits, s.save_state().unwrap(), s.conservation_totals())
    };
    let (limits, one, totals) = steps(&mut build(std::sync::Arc::new(brisance_grid::comm::Serial)));
    // The transport is felt: a diffusive limit sets the step, and the
    // state differs from the inviscid bump's.
    assert!(
        limits.viscous.min(limits.conduction) <= limits.stable,
        "{limits:?}"
    );
    let mut inviscid = bump_solver([3, 2, 2], [12, 8, 4]);
    for _ in 0..4 {
        let dt = inviscid.stable_dt().unwrap();
        inviscid.advance(dt).unwrap();
    }
    assert!(inviscid.save_state().unwrap() != one);
    for ranks in [2, 4] {
        let runs = brisance_grid::comm::InProcess::run(ranks, 2, |comm| steps(&mut build(comm)));
        for (r, (l, state, t)) in runs.into_iter().enumerate() {
            assert_eq!(l, limits, "rank {r} of {ranks}");
            assert!(state == one, "rank {r} of {ranks}");
            assert_eq!(t, totals, "rank {r} of {ranks}");
        }
    }
}

/// The rank logic of `solver/ranks.rs` without MPI: the pressure bump on
/// 3 × 2 × 2 patches spread over 2, 3 and 4 thread ranks
/// ([`brisance_grid::comm::InProcess`], each with a thread pool of its
/// own; ghost layers cross through its mailbox) ends, on every rank, with
/// the saved state of one rank.
#[test]
fn patches_spread_over_thread_ranks_give_the_bits_of_one() {
    let steps = |s: &mut IceSolver<IdealGas>| {
        for _ in 0..4 {
            let dt = s.stable_dt().unwrap();
            s.advance(dt).unwrap();
        }
        s.save_state().unwrap()
    };
    let one = steps(&mut bump_solver([3, 2, 2], [12, 8, 4]));
    for ranks in [2, 3, 4] {
        let states = brisance_grid::comm::InProcess::run(ranks, 2, |comm| {
            let mut s = bump_solver([3, 2, 2], [12, 8, 4]);
            s.distribute(comm).unwrap();
            // The rank updates its share of the 12 patches, not all of
            // them, and stores those only, before and after the steps.
            let own = s.cell_pieces(&["pressure".into()]).unwrap().unwrap();
            assert!(own.pieces.len() <= 12_usize.div_ceil(ranks));
            let mine: Vec<usize> = own.pieces.iter().map(|p| p.patch).collect();
            assert_eq!(s.stored_patches(), mine);
            let state = steps(&mut s);
            assert_eq!(s.stored_patches(), mine);
            state
        });
        for (r, state) in states.into_iter().enumerate() {
            assert!(state == one, "rank {r} of {ranks}");
        }
    }
    // Built spread (IceSolver::new_on), never storing the others'
    // patches: the same bits; a solver built spread is not spread again.
    for ranks in [1, 3] {
        let states = brisance_grid::comm::InProcess::run(ranks, 2, |comm| {
            let rank = comm.rank();
            let mut s =
                bump_solver_on(comm.clone(), [3, 2, 2], [12, 8, 4], IceOptions::default()).unwrap();
            let owners = brisance_grid::comm::patch_owners(12, ranks).unwrap();
            let mine: Vec<usize> = (0..12).filter(|&id| owners[id] == rank).collect();
            assert_eq!(s.stored_patches(), mine, "rank {rank} of {ranks}");
            if ranks > 1 {
                assert!(s.distribute(comm).is_err());
            }
            let state = steps(&mut s);
            assert_eq!(s.stored_patches(), mine, "rank {rank} of {ranks}");
            state
        });
        for (r, state) in states.into_iter().enumerate() {
            assert!(state == one, "built spread: rank {r} of {ranks}");
        }
    }
}

/// The implicit pressure on ranks (its outer iterations' cell values
/// gathered from their owners, one solve over the whole grid on every
/// rank): the pressure bump on 3 × 2 × 2 patches built spread over 2, 3
/// and 4 thread ranks ends, on every rank, with the saved state and the
/// solver statistics of one rank.
#[test]
fn the_implicit_pressure_spread_over_thread_ranks_gives_the_bits_of_one() {
    let options = IceOptions {
        pressure: PressureSolve::Implicit(Default::default()),
        ..Default::default()
    };
    let steps = |s: &mut IceSolver<IdealGas>| {
        for _ in 0..4 {
            let dt = s.stable_dt().unwrap();
            s.advance(dt).unwrap();
        }
        (s.save_state().unwrap(), s.pressure_solve_stats())
    };
    let build = |comm| bump_solver_on(comm, [3, 2, 2], [12, 8, 4], options).unwrap();
    let one = steps(&mut build(std::sync::Arc::new(brisance_grid::comm::Serial)));
    // The solve iterated.
    assert!(one.1.total_iterations >= 4, "{:?}", one.1);
    // One rank gives the bits of one patch.
    let whole = steps(
        &mut bump_solver_on(
            std::sync::Arc::new(brisance_grid::comm::Serial),
            [1, 1, 1],
            [12, 8, 4],
            options,
        )
        .unwrap(),
    );
    assert!(whole.0 == one.0);
    for ranks in [2, 3, 4] {
        let runs = brisance_grid::comm::InProcess::run(ranks, 2, |comm| steps(&mut build(comm)));
        for (r, (state, stats)) in runs.into_iter().enumerate() {
            assert!(state == one.0, "rank {r} of {ranks}");
            assert_eq!(stats, one.1, "rank {r} of {ranks}");
        }
    }
}
