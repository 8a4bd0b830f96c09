//! Solver-level tests: invariants, determinism, restart, diagnostics.

use brisance_core::{Solver, SolverError};
use brisance_eos::IdealGas;
use brisance_grid::Level;

use crate::{ArtificialViscosity, FaceLimiter, FdmBoundary, FdmOptions, FdmSolver, PrimitiveState};

fn gas() -> IdealGas {
    IdealGas::new(1.4, 1.0, 1.0)
}

fn state(density: f64, velocity: [f64; 3], pressure: f64) -> PrimitiveState {
    PrimitiveState {
        density,
        velocity,
        pressure,
    }
}

/// A 3D blast: a dense hot sphere off-centre in a box with mixed boundaries.
fn blast(layout: [usize; 3]) -> FdmSolver<IdealGas> {
    blast_on(std::sync::Arc::new(brisance_grid::comm::Serial), layout)
}

/// [`blast`] built with its patches shared among the ranks of `comm`
/// ([`FdmSolver::with_species_on`]).
fn blast_on(
    comm: std::sync::Arc<dyn brisance_grid::comm::Communicator>,
    layout: [usize; 3],
) -> FdmSolver<IdealGas> {
    let level = Level::new(
        [0.0; 3],
        [1.0, 0.8, 0.6],
        [20, 16, 12],
        layout,
        crate::sweep::GHOST,
    )
    .unwrap();
    let bcs = [
        FdmBoundary::Reflective,
        FdmBoundary::Outflow,
        FdmBoundary::Periodic,
        FdmBoundary::Periodic,
        FdmBoundary::Fixed(state(1.0, [0.0, 0.0, 0.1], 1.0)),
        FdmBoundary::Outflow,
    ];
    FdmSolver::with_species_on(comm, gas(), level, bcs, FdmOptions::default(), |x| {
        let r2 = (x[0] - 0.3).powi(2) + (x[1] - 0.4).powi(2) + (x[2] - 0.25).powi(2);
        let s = if r2 < 0.04 {
            state(4.0, [0.1, 0.0, 0.0], 10.0)
        } else {
            state(1.0, [0.0, 0.2 * x[0], 0.0], 1.0)
        };
        (s, 0.0)
    })
    .unwrap()
}

/// An initial state that fails in cells of the last patches: built spread
/// over 1, 2 and 4 thread ranks, every rank meets the error of the first
/// failing cell in patch order, as one rank does, though it evaluates
/// only its own patches' cells.
#[test]
fn a_failing_initial_state_gives_every_rank_the_error_of_one() {
    let build = |comm: std::sync::Arc<dyn brisance_grid::comm::Communicator>| {
        let level = Level::new(
            [0.0; 3],
            [1.0; 3],
            [8, 4, 8],
            [2, 1, 2],
            crate::sweep::GHOST,
        )
        .unwrap();
        let bcs = [FdmBoundary::Outflow; 6];
        FdmSolver::with_species_on(comm, gas(), level, bcs, FdmOptions::default(), |x| {
            // Negative pressure in the upper half of z at x > 0.6 (patch 3)
            // and zero density at x > 0.3 there (patches 2 and 3).
            let p = if x[0] > 0.6 { -1.0 } else { 1.0 };
            let rho = if x[0] > 0.3 && x[2] > 0.5 { 0.0 } else { 1.0 };
            (state(rho, [0.0; 3], if x[2] > 0.5 { p } else { 1.0 }), 0.0)
        })
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

/// A box from the origin to `upper` on `cells` (split into `layout`
/// patches) holding the uniform state `s0`.
fn uniform(
    upper: [f64; 3],
    cells: [usize; 3],
    layout: [usize; 3],
    boundaries: [FdmBoundary; 6],
    s0: PrimitiveState,
) -> FdmSolver<IdealGas> {
    let level = Level::new([0.0; 3], upper, cells, layout, crate::sweep::GHOST).unwrap();
    FdmSolver::new(gas(), level, boundaries, FdmOptions::default(), |_| s0).unwrap()
}

/// Mass and energy unchanged to 1e-13 of themselves, each momentum
/// component to 1e-13 of `momentum_scale`.
fn assert_conserved(
    t0: brisance_core::ConservationTotals,
    t1: brisance_core::ConservationTotals,
    momentum_scale: f64,
) {
    let rel = |a: f64, b: f64| ((b - a) / a).abs();
    assert!(
        rel(t0.mass, t1.mass) < 1e-13,
        "mass {} → {}",
        t0.mass,
        t1.mass
    );
    assert!(
        rel(t0.energy, t1.energy) < 1e-13,
        "energy {} → {}",
        t0.energy,
        t1.energy
    );
    for a in 0..3 {
        assert!(
            (t1.momentum[a] - t0.momentum[a]).abs() < 1e-13 * momentum_scale,
            "momentum {a}: {} → {}",
            t0.momentum[a],
            t1.momentum[a]
        );
    }
}

fn run(solver: &mut impl Solver, steps: usize) {
    for _ in 0..steps {
        let dt = solver.stable_dt().unwrap();
        solver.advance(dt).unwrap();
    }
}

fn all_fields(solver: &impl Solver) -> Vec<(String, Vec<f64>)> {
    let names: Vec<String> = solver
        .cell_field_names()
        .iter()
        .map(|s| s.to_string())
        .collect();
    solver.cell_data(&names).unwrap().fields
}

#[test]
fn fields_are_bit_identical_for_any_patch_split_and_thread_count() {
    let (reference, totals) = {
        let mut s = blast([1, 1, 1]);
        rayon::ThreadPoolBuilder::new()
            .num_threads(1)
            .build()
            .unwrap()
            .install(|| run(&mut s, 8));
        (all_fields(&s), s.conservation_totals())
    };
    for layout in [[2, 1, 1], [2, 2, 2], [1, 2, 1]] {
        for threads in [1, 2] {
            let mut s = blast(layout);
            rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap()
                .install(|| run(&mut s, 8));
            let f = all_fields(&s);
            assert_eq!(
                s.conservation_totals(),
                totals,
                "totals differ for layout {layout:?} on {threads} threads"
            );
            for ((name, a), (_, b)) in reference.iter().zip(&f) {
                let same = a.iter().zip(b).all(|(x, y)| x.to_bits() == y.to_bits());
                assert!(
                    same,
                    "{name} differs for layout {layout:?} on {threads} threads"
                );
            }
        }
    }
}

#[test]
fn a_uniform_moving_state_stays_exactly_uniform() {
    let s0 = state(1.3, [0.3, -0.2, 0.1], 2.0);
    let mut s = uniform(
        [1.0; 3],
        [8, 8, 8],
        [2, 1, 2],
        [FdmBoundary::Periodic; 6],
        s0,
    );
    run(&mut s, 5);
    let d = s
        .cell_data(&["density".into(), "velocity_y".into(), "pressure".into()])
        .unwrap();
    for (name, values) in &d.fields {
        let first = values[0];
        assert!(
            values
                .iter()
                .all(|v| (v - first).abs() <= 1e-14 * first.abs()),
            "{name} not uniform"
        );
    }
    assert!((d.fields[0].1[0] - 1.3).abs() < 1e-14);
}

#[test]
fn periodic_domain_conserves_mass_momentum_and_energy_to_round_off() {
    let level = Level::new(
        [0.0; 3],
        [1.0, 1.0, 1.0],
        [24, 12, 1],
        [2, 2, 1],
        crate::sweep::GHOST,
    )
    .unwrap();
    let mut s = FdmSolver::new(
        gas(),
        level,
        [FdmBoundary::Periodic; 6],
        FdmOptions::default(),
        |x| {
            if (x[0] - 0.5).abs() < 0.2 && (x[1] - 0.5).abs() < 0.2 {
                state(1.0, [0.5, 0.0, 0.0], 1.0)
            } else {
                state(0.125, [0.0, 0.1, 0.0], 0.1)
            }
        },
    )
    .unwrap();
    let t0 = s.conservation_totals();
    run(&mut s, 40);
    assert_conserved(t0, s.conservation_totals(), t0.mass);
}

#[test]
fn restart_from_saved_state_continues_bit_identically() {
    let mut a = blast([2, 1, 1]);
    run(&mut a, 4);
    let saved = a.save_state().unwrap();
    run(&mut a, 4);
    // Restore into a solver with another patch split.
    let mut b = blast([1, 2, 2]);
    b.restore_state(&saved).unwrap();
    assert_eq!(b.time().to_bits(), {
        let mut c = blast([1, 1, 1]);
        run(&mut c, 4);
        c.time().to_bits()
    });
    run(&mut b, 4);
    assert_eq!(a.time().to_bits(), b.time().to_bits());
    // The face outflow goes on from the checkpoint's: the same totals.
    assert_eq!(a.conservation_totals(), b.conservation_totals());
    assert!(a.outflow().mass != 0.0);
    for ((name, x), (_, y)) in all_fields(&a).iter().zip(&all_fields(&b)) {
        assert!(
            x.iter().zip(y).all(|(p, q)| p.to_bits() == q.to_bits()),
            "{name} differs after restart"
        );
    }
}

/// The run loop's snapshot rewinds the solver it was taken of: after
/// steps taken and undone, the same steps give the same bits; a solver
/// of another split refuses it.
#[test]
fn a_snapshot_rewinds_the_solver_bit_identically() {
    let mut a = blast([2, 1, 1]);
    run(&mut a, 3);
    let snapshot = a.save_snapshot().unwrap();
    run(&mut a, 4);
    let (time, totals, fields) = (a.time(), a.conservation_totals(), all_fields(&a));
    a.restore_snapshot(&snapshot).unwrap();
    assert!(a.time() < time);
    run(&mut a, 4);
    assert_eq!(a.time().to_bits(), time.to_bits());
    assert_eq!(a.conservation_totals(), totals);
    assert!(a.outflow().mass != 0.0);
    for ((name, x), (_, y)) in fields.iter().zip(&all_fields(&a)) {
        assert!(
            x.iter().zip(y).all(|(p, q)| p.to_bits() == q.to_bits()),
            "{name} differs after the rewind"
        );
    }
    let mut other = blast([1, 2, 1]);
    assert!(other.restore_snapshot(&snapshot).is_err());
}

#[test]
fn a_vacuum_forming_state_stops_with_a_diagnostic_naming_the_cell() {
    let level = Level::new(
        [0.0; 3],
        [1.0, 1.0, 1.0],
        [40, 1, 1],
        [1, 1, 1],
        crate::sweep::GHOST,
    )
    .unwrap();
    // The scheme as printed: no face limiter.
    let opts = FdmOptions {
        viscosity: ArtificialViscosity::Off,
        limiter: FaceLimiter::Off,
        ..Default::default()
    };
    let mut s = FdmSolver::new(gas(), level, [FdmBoundary::Outflow; 6], opts, |x| {
        let u = if x[0] < 0.5 { -20.0 } else { 20.0 };
        state(1.0, [u, 0.0, 0.0], 0.01)
    })
    .unwrap();
    let mut err = None;
    for _ in 0..200 {
        match s.stable_dt().and_then(|dt| s.advance(dt)) {
            Ok(()) => {}
            Err(e) => {
                err = Some(e);
                break;
            }
        }
    }
    match err {
        Some(SolverError::NonPhysicalState { cell, detail, .. }) => {
            assert!(cell[0] > 10 && cell[0] < 30, "cell {cell:?}");
            assert!(detail.contains("pressure"), "{detail}");
        }
        other => panic!("expected a non-physical state error, got {other:?}"),
    }
}

/// Two streams separating at Mach 200 on a periodic line (they collide
/// again across the wrap), viscosity off, on `layout` patches: the plain
/// Lax–Wendroff sweep leaves a negative internal energy where the
/// near-vacuum forms.
fn separating(limiter: FaceLimiter, layout: [usize; 3]) -> FdmSolver<IdealGas> {
    let level = Level::new(
        [0.0; 3],
        [1.0, 1.0, 1.0],
        [40, 1, 1],
        layout,
        crate::sweep::GHOST,
    )
    .unwrap();
    let opts = FdmOptions {
        viscosity: ArtificialViscosity::Off,
        limiter,
        ..Default::default()
    };
    FdmSolver::new(gas(), level, [FdmBoundary::Periodic; 6], opts, |x| {
        let u = if x[0] < 0.5 { -20.0 } else { 20.0 };
        state(1.0, [u, 0.0, 0.0], 0.01)
    })
    .unwrap()
}

/// The limiter's counts in the run summary: (faces limited for positivity,
/// for the density bounds, faces swept).
fn limited(s: &impl Solver) -> (u64, u64, u64) {
    let g = s.safeguards();
    let by = |name: &str| {
        g.iter()
            .find(|u| u.name.contains(name))
            .map_or(0, |u| u.acted)
    };
    (
        by("positivity"),
        by("density"),
        g.first().map_or(0, |u| u.checked),
    )
}

#[test]
fn the_face_limiter_passes_a_near_vacuum_and_conserves_to_round_off() {
    let mut plain = separating(FaceLimiter::Off, [1, 1, 1]);
    let failed = (0..200).any(|_| plain.stable_dt().and_then(|dt| plain.advance(dt)).is_err());
    assert!(failed, "the plain sweep must stop on this problem");
    for limiter in [FaceLimiter::Positivity, FaceLimiter::Full] {
        let mut s = separating(limiter, [1, 1, 1]);
        let t0 = s.conservation_totals();
        run(&mut s, 200);
        let t1 = s.conservation_totals();
        assert!(((t1.mass - t0.mass) / t0.mass).abs() < 1e-13);
        assert!(((t1.energy - t0.energy) / t0.energy).abs() < 1e-13);
        assert!((t1.momentum[0] - t0.momentum[0]).abs() < 1e-13 * 20.0 * t0.mass);
        // Every cell physical: ρ > 0 and p > 0 (the solver checks p at each
        // sweep; here it is read back).
        let mut out = Vec::new();
        for i in 0..40 {
            out.clear();
            let x = [(i as f64 + 0.5) / 40.0, 0.5, 0.5];
            s.sample(x, &["density".into(), "pressure".into()], &mut out)
                .unwrap();
            assert!(
                out[0] > 0.0 && out[1] > 0.0,
                "{limiter:?} cell {i}: {out:?}"
            );
        }
        // It acted for positivity, and says so: 200 steps of 2 sweeps of
        // 41 faces were swept.
        let (positive, _, faces) = limited(&s);
        assert!(positive > 0, "{limiter:?}");
        assert_eq!(faces, 200 * 2 * 41);
    }
}

#[test]
fn the_face_limiter_gives_the_same_bits_for_any_patch_split_and_thread_count() {
    // Where it acts (the near-vacuum: positivity; the two shocks when the
    // streams meet again across the wrap: density bounds), the limited
    // fluxes at a face shared by two patches are the same on both sides.
    let reference = {
        let mut s = separating(FaceLimiter::Full, [1, 1, 1]);
        in_threads(1, || run(&mut s, 120));
        let (p, b, _) = limited(&s);
        assert!(p > 0 && b > 0, "both bounds act: {p} {b}");
        (all_fields(&s), s.conservation_totals(), limited(&s))
    };
    for layout in [[2, 1, 1], [4, 1, 1], [5, 1, 1]] {
        for threads in [1, 2] {
            let mut s = separating(FaceLimiter::Full, layout);
            in_threads(threads, || run(&mut s, 120));
            assert_eq!(limited(&s), reference.2, "{layout:?} on {threads}");
            assert_eq!(
                s.conservation_totals(),
                reference.1,
                "{layout:?} on {threads}"
            );
            for ((name, a), (_, b)) in reference.0.iter().zip(&all_fields(&s)) {
                let same = a.iter().zip(b).all(|(x, y)| x.to_bits() == y.to_bits());
                assert!(same, "{name} differs for {layout:?} on {threads} threads");
            }
        }
    }
}

/// Runs `f` on a pool of `threads` threads.
fn in_threads(threads: usize, f: impl FnOnce() + Send) {
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap()
        .install(f);
}

#[test]
fn positivity_limiting_changes_nothing_where_the_scheme_is_positive() {
    // The blast never loses positivity: the positivity limiter leaves every
    // bit of the scheme as printed; with the density bounds it acts at the
    // shock and changes the result there.
    let make = |limiter: FaceLimiter| {
        let mut b = blast([2, 1, 1]);
        b.set_limiter(limiter);
        run(&mut b, 10);
        (all_fields(&b), limited(&b))
    };
    let (off, _) = make(FaceLimiter::Off);
    let (positive, counts) = make(FaceLimiter::Positivity);
    assert_eq!(off, positive);
    assert_eq!(counts.0, 0);
    let (full, counts) = make(FaceLimiter::Full);
    assert!(counts.1 > 0 && full != off, "{counts:?}");
}

#[test]
fn cfl_above_the_scheme_limit_is_rejected() {
    let level = Level::new(
        [0.0; 3],
        [1.0; 3],
        [10, 1, 1],
        [1, 1, 1],
        crate::sweep::GHOST,
    )
    .unwrap();
    let opts = FdmOptions {
        cfl: 1.2,
        ..Default::default()
    };
    let err = FdmSolver::new(gas(), level, [FdmBoundary::Outflow; 6], opts, |_| {
        state(1.0, [0.0; 3], 1.0)
    })
    .unwrap_err();
    assert!(err.to_string().contains("cfl = 1.2"));
}

#[test]
fn time_step_follows_the_cfl_formula() {
    // ρ = 1, p = 1, γ = 1.4: c = √1.4; u = 0.5 along x; Δx = 0.1.
    let level = Level::new(
        [0.0; 3],
        [1.0; 3],
        [10, 1, 1],
        [1, 1, 1],
        crate::sweep::GHOST,
    )
    .unwrap();
    let s = FdmSolver::new(
        gas(),
        level,
        [FdmBoundary::Outflow; 6],
        FdmOptions {
            cfl: 0.5,
            ..Default::default()
        },
        |_| state(1.0, [0.5, 0.0, 0.0], 1.0),
    )
    .unwrap();
    let expected = 2.0 * 0.5 * 0.1 / (0.5 + 1.4f64.sqrt());
    assert!((s.stable_dt().unwrap() - expected).abs() < 1e-15);
}

#[test]
fn the_time_step_limit_names_the_fastest_cell() {
    // At rest but for cell 6, which moves at 3 along x: its
    // Δx / (|u| + c) is the smallest, and its centre is x = 0.65.
    let level = Level::new(
        [0.0; 3],
        [1.0; 3],
        [10, 1, 1],
        [2, 1, 1],
        crate::sweep::GHOST,
    )
    .unwrap();
    let s = FdmSolver::new(
        gas(),
        level,
        [FdmBoundary::Outflow; 6],
        FdmOptions::default(),
        |x| {
            let u = if (x[0] - 0.65).abs() < 0.01 { 3.0 } else { 0.0 };
            state(1.0, [u, 0.0, 0.0], 1.0)
        },
    )
    .unwrap();
    let limit = s.time_step_limit().unwrap();
    assert_eq!(
        limit,
        "FDM cell [6, 0, 0] at (0.6500, 0.5000, 0.5000) m: sound speed 1 m/s + |u_x| 3 m/s"
    );
}

mod contract {
    //! Property tests of the `Solver` contract on random initial data.
    use super::*;
    use proptest::prelude::*;

    /// A periodic 2D box with a random box of a second state inside.
    fn random_problem(
        layout: [usize; 3],
        inner: (f64, f64, f64, f64),
        outer: (f64, f64),
        corner: (f64, f64),
    ) -> FdmSolver<IdealGas> {
        let level = Level::new(
            [0.0; 3],
            [1.0, 1.0, 0.1],
            [16, 12, 1],
            layout,
            crate::sweep::GHOST,
        )
        .unwrap();
        let (rho_i, p_i, u_i, v_i) = inner;
        FdmSolver::new(
            gas(),
            level,
            [FdmBoundary::Periodic; 6],
            FdmOptions::default(),
            move |x| {
                if x[0] > corner.0
                    && x[0] < corner.0 + 0.4
                    && x[1] > corner.1
                    && x[1] < corner.1 + 0.4
                {
                    state(rho_i, [u_i, v_i, 0.0], p_i)
                } else {
                    state(outer.0, [0.0; 3], outer.1)
                }
            },
        )
        .unwrap()
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(24))]

        #[test]
        fn random_periodic_flows_conserve_and_stay_physical(
            rho_i in 0.2..5.0f64, p_i in 0.2..5.0f64, u_i in -0.5..0.5f64, v_i in -0.5..0.5f64,
            rho_o in 0.2..5.0f64, p_o in 0.2..5.0f64, cx in 0.0..0.6f64, cy in 0.0..0.6f64,
        ) {
            let mut s = random_problem([1, 1, 1], (rho_i, p_i, u_i, v_i), (rho_o, p_o), (cx, cy));
            let t0 = s.conservation_totals();
            for _ in 0..6 {
                let dt = s.stable_dt().unwrap();
                prop_assert!(dt > 0.0 && dt.is_finite());
                s.advance(dt).unwrap();
            }
            let t1 = s.conservation_totals();
            prop_assert!(((t1.mass - t0.mass) / t0.mass).abs() < 1e-13);
            prop_assert!(((t1.energy - t0.energy) / t0.energy).abs() < 1e-13);
            for a in 0..2 {
                prop_assert!((t1.momentum[a] - t0.momentum[a]).abs() < 1e-12 * (t0.mass + t0.energy));
            }
            let d = s.cell_data(&["density".into(), "pressure".into()]).unwrap();
            prop_assert!(d.fields.iter().all(|(_, v)| v.iter().all(|x| *x > 0.0)));
        }

        #[test]
        fn random_patch_splits_give_the_same_bits(px in 1usize..4, py in 1usize..3, rho_i in 0.2..5.0f64, p_i in 0.2..5.0f64) {
            let run = |layout| {
                let mut s = random_problem(layout, (rho_i, p_i, 0.1, -0.2), (1.0, 1.0), (0.3, 0.2));
                for _ in 0..4 {
                    let dt = s.stable_dt().unwrap();
                    s.advance(dt).unwrap();
                }
                all_fields(&s)
            };
            let a = run([1, 1, 1]);
            let b = run([px, py, 1]);
            for ((name, x), (_, y)) in a.iter().zip(&b) {
                prop_assert!(x.iter().zip(y).all(|(p, q)| p.to_bits() == q.to_bits()), "{} differs", name);
            }
        }
    }
}

#[test]
fn conservative_fields_round_trip_across_patch_splits_and_bad_lengths_are_refused() {
    // Fields taken from a one-patch solver and written into a four-patch
    // one give the same totals and cells; per-cell access agrees with
    // the arrays (x fastest).
    let a = blast([1, 1, 1]);
    let mut b = blast([2, 2, 1]);
    let mut fields = a.conservative_fields();
    assert_eq!(fields.len(), 5);
    fields[0][0] = 7.0;
    b.set_conservative_fields(&fields).unwrap();
    assert_eq!(b.conservative_fields(), fields);
    let g = [3, 5, 2];
    let lin = 3 + 20 * (5 + 16 * 2);
    let c = b.cell_conservative(g).unwrap();
    for f in 0..5 {
        assert_eq!(c[f], fields[f][lin]);
    }
    assert_eq!(c[5], 0.0);
    assert_eq!(b.cell_conservative([0, 0, 0]).unwrap()[0], 7.0);
    b.set_cell_conservative(g, [2.0, 0.5, 0.0, 0.0, 9.0, 0.0])
        .unwrap();
    assert_eq!(b.conservative_fields()[4][lin], 9.0);
    assert!(b.cell_conservative([20, 0, 0]).is_none());
    assert!(b.set_cell_conservative([0, 16, 0], [1.0; 6]).is_err());
    let short = vec![vec![1.0; 10]; 5];
    let e = b.set_conservative_fields(&short).unwrap_err().to_string();
    assert!(e.contains("expected 5 arrays of 3840 values"), "{e}");
}

/// A uniform state moving along +x through a tube with flow-out faces:
/// the interior stays uniform, and what crosses each x face after time T
/// is the flux times T times the face's area, in every variable.
#[test]
fn a_uniform_stream_books_its_face_fluxes_exactly() {
    let (rho, u, v, p) = (1.3, 0.4, -0.1, 2.0);
    let s0 = state(rho, [u, v, 0.0], p);
    let bcs = [FdmBoundary::Outflow; 6];
    let mut s = uniform([1.2, 0.5, 0.1], [12, 5, 1], [2, 1, 1], bcs, s0);
    let mut t = 0.0;
    for _ in 0..7 {
        let dt = s.stable_dt().unwrap();
        s.advance(dt).unwrap();
        t += dt;
    }
    // Faces normal to x: area 0.5 × 0.1 m²; normal to y: 1.2 × 0.1 m².
    let e = p / 0.4 + 0.5 * rho * (u * u + v * v);
    for (face, un, area) in [(1, u, 0.05), (3, v, 0.12)] {
        let o = s.outflow_where(|f, _| f == face);
        let want = [rho * un, rho * u * un, rho * v * un, (e + p) * un];
        let got = [o.mass, o.momentum[0], o.momentum[1], o.energy];
        let mut want = want.map(|w| w * t * area);
        // The momentum along the face's normal also carries p.
        want[1 + face / 2] += p * t * area;
        for (g, w) in got.iter().zip(want) {
            assert!(
                (g - w).abs() <= 1e-13 * w.abs().max(1.0),
                "face {face}: {g} against {w}"
            );
        }
        // The opposite face takes in as much.
        let back = s.outflow_where(|f, _| f == face - 1);
        assert!(
            (back.mass + o.mass).abs() <= 1e-14,
            "{} {}",
            back.mass,
            o.mass
        );
    }
    // The run summary reports it: the faces are open.
    assert_eq!(s.outflow_totals(), Some(s.outflow()));
    // Interior plus outflow is the initial total.
    let total = s.conservation_totals();
    let mass = rho * 1.2 * 0.5 * 0.1;
    assert!((total.mass - mass).abs() <= 1e-14 * mass);
    assert_eq!(s.outflow().mass.to_bits(), {
        let o = s.outflow_where(|_, _| true);
        o.mass.to_bits()
    });
}

/// Gas at rest between reflective walls: no mass or energy crosses, and
/// the momentum booked at each wall is the pressure impulse p T A.
#[test]
fn a_reflective_wall_books_only_the_pressure_impulse() {
    let p = 3.0;
    let walls = [FdmBoundary::Reflective; 6];
    let mut s = uniform(
        [1.0, 0.5, 0.1],
        [10, 5, 1],
        [1, 1, 1],
        walls,
        state(2.0, [0.0; 3], p),
    );
    let mut t = 0.0;
    for _ in 0..5 {
        let dt = s.stable_dt().unwrap();
        s.advance(dt).unwrap();
        t += dt;
    }
    // Between walls the run summary has no outflow line.
    assert_eq!(s.outflow_totals(), None);
    for (face, area) in [(0, 0.05), (1, 0.05), (2, 0.1), (3, 0.1)] {
        let o = s.outflow_where(|f, _| f == face);
        assert_eq!(o.mass, 0.0, "face {face}");
        assert_eq!(o.energy, 0.0, "face {face}");
        let sign = if face % 2 == 0 { -1.0 } else { 1.0 };
        let want = sign * p * t * area;
        let got = o.momentum[face / 2];
        assert!(
            (got - want).abs() <= 1e-13 * want.abs(),
            "face {face}: {got} against {want}"
        );
    }
}

/// The 3D blast box (a reflective, two flow-out, two periodic and a fixed
/// inflow face): the interior alone gains and loses several per cent, and
/// the interior plus what crossed the faces is conserved to round-off.
#[test]
fn interior_plus_outflow_is_conserved_to_round_off() {
    let mut s = blast([2, 1, 2]);
    let (t0, i0) = (s.conservation_totals(), s.interior_totals());
    run(&mut s, 30);
    let (t1, i1) = (s.conservation_totals(), s.interior_totals());
    assert!(
        ((i1.mass - i0.mass) / i0.mass).abs() > 1e-3,
        "{} {}",
        i0.mass,
        i1.mass
    );
    assert!(((i1.energy - i0.energy) / i0.energy).abs() > 1e-3);
    assert_conserved(t0, t1, t0.mass + t0.energy);
}

/// One rank's fields (name, bits), totals and limiter counts.
type RankResult = (
    Vec<(String, Vec<u64>)>,
    brisance_core::ConservationTotals,
    (u64, u64, u64),
);

/// `make()` on each of `ranks` threads acting as ranks
/// ([`brisance_grid::comm::InProcess`], each with a thread pool of its
/// own), the patches shared among them ([`FdmSolver::distribute`]),
/// `steps` steps: each rank's fields' bits and totals (both read collectively,
/// as the run loop reads them) and limiter counts.
fn on_thread_ranks<E: crate::GasLaw + 'static>(
    ranks: usize,
    make: &(dyn Fn() -> FdmSolver<E> + Sync),
    steps: usize,
) -> Vec<RankResult> {
    on_thread_ranks_built(
        ranks,
        &|comm| {
            let mut s = make();
            s.distribute(comm).unwrap();
            s
        },
        steps,
    )
}

/// As [`on_thread_ranks`], each rank's solver `make(comm)`, already spread
/// over `comm`.
fn on_thread_ranks_built<E: crate::GasLaw + 'static>(
    ranks: usize,
    make: &(dyn Fn(std::sync::Arc<dyn brisance_grid::comm::Communicator>) -> FdmSolver<E> + Sync),
    steps: usize,
) -> Vec<RankResult> {
    brisance_grid::comm::InProcess::run(ranks, 2, |comm| {
        let rank = comm.rank();
        let mut s = make(comm);
        let own = s.cell_pieces(&["density".into()]).unwrap().unwrap();
        // The rank updates its share of the patches, and stores those only.
        let mine: Vec<usize> = own.pieces.iter().map(|p| p.patch).collect();
        let all = own.extents.len();
        assert!(ranks == 1 || mine.len() < all, "rank {rank}: {mine:?}");
        assert_eq!(s.stored_patches(), mine, "rank {rank} of {ranks}");
        run(&mut s, steps);
        assert_eq!(s.stored_patches(), mine, "rank {rank} of {ranks}");
        let bits = all_fields(&s)
            .into_iter()
            .map(|(name, v)| (name, v.iter().map(|x| x.to_bits()).collect()))
            .collect();
        (bits, s.conservation_totals(), limited(&s))
    })
}

/// The rank logic without MPI: the blast on 2 × 2 × 2 patches and the
/// separating streams whose face limiter acts on 4 patches, spread over
/// thread ranks, give on every rank the bits of one rank (fields, exact
/// totals, limiter counts).
#[test]
fn patches_spread_over_thread_ranks_give_the_bits_of_one() {
    let blast_8 = || blast([2, 2, 2]);
    let one = on_thread_ranks(1, &blast_8, 8).remove(0);
    for ranks in [2, 3, 4] {
        for (r, got) in on_thread_ranks(ranks, &blast_8, 8).into_iter().enumerate() {
            assert!(got == one, "blast: rank {r} of {ranks}");
        }
    }
    // Built spread (FdmSolver::with_species_on), never storing the others'
    // patches: the same bits.
    let built = |comm| blast_on(comm, [2, 2, 2]);
    for ranks in [1, 3] {
        for (r, got) in on_thread_ranks_built(ranks, &built, 8)
            .into_iter()
            .enumerate()
        {
            assert!(got == one, "blast built on ranks: rank {r} of {ranks}");
        }
    }
    let streams = || separating(FaceLimiter::Full, [4, 1, 1]);
    let one = on_thread_ranks(1, &streams, 120).remove(0);
    assert!(one.2 .0 > 0 && one.2 .1 > 0, "the limiter acts");
    for ranks in [2, 4] {
        for (r, got) in on_thread_ranks(ranks, &streams, 120)
            .into_iter()
            .enumerate()
        {
            assert!(got == one, "streams: rank {r} of {ranks}");
        }
    }
}
