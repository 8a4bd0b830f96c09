//! Open faces: outflow columns that gain no mass, waves that leave
//! without reflection, zero-gradient faces, and the booked outflow of
//! the conservation totals.

use super::*;

/// One ideal gas (γ 1.4, c_v 717.5) in a 1 m column of `cells` cells along
/// x, 1 m² cross-section, with the given ends and per-cell (ρ, u, p).
fn column(
    cells: usize,
    ends: [IceBoundary; 2],
    state: impl Fn(f64) -> (f64, f64, f64) + Sync,
) -> IceSolver<IdealGas> {
    let level = Level::new([0.0; 3], [1.0; 3], [cells, 1, 1], [1, 1, 1], GHOST).unwrap();
    let [lo, hi] = ends;
    let bcs = [
        lo,
        hi,
        IceBoundary::Symmetry,
        IceBoundary::Symmetry,
        IceBoundary::Symmetry,
        IceBoundary::Symmetry,
    ];
    IceSolver::new(
        vec![IdealGas::new(1.4, 717.5, 1.0)],
        level,
        bcs,
        ExchangeCoefficients::uniform(1, 1e15, 0.0),
        IceOptions::default(),
        |x| {
            let (rho, u, p) = state(x[0]);
            CellState {
                pressure: p,
                materials: vec![mat(1.0, rho, u)],
            }
        },
    )
    .unwrap()
}

/// Two streams meeting in the middle of a column with outflow ends: at both
/// ends the flow points into the domain. Zero gradient alone would feed
/// 2ρU = 144 kg/(m²·s) in; the outflow face lets nothing
/// in, so until the waves from the collision reach the ends the faces carry
/// nothing and mass and energy stay what they were, and afterwards they can
/// only fall.
#[test]
fn a_column_flowing_inwards_at_its_outflow_ends_gains_no_mass() {
    use IceBoundary::Outflow;
    let (rho, u, p) = (1.2, 60.0, 1.0e5);
    let mut s = column(100, [Outflow, Outflow], |x| {
        (rho, if x < 0.5 { u } else { -u }, p)
    });
    let t0 = interior_totals(&s);
    // Sound speed 340.3 m/s: the collision's shocks (≈ 420 m/s) need about
    // 1.2 ms to reach the ends; 1 ms stays clear of them.
    let dt = 1.0e-5;
    for _ in 0..100 {
        s.advance(dt).unwrap();
    }
    let t1 = interior_totals(&s);
    assert!(
        ((t1.mass - t0.mass) / t0.mass).abs() < 1e-14,
        "{t0:?} {t1:?}"
    );
    assert!(
        ((t1.energy - t0.energy) / t0.energy).abs() < 1e-14,
        "{t0:?} {t1:?}"
    );
    // The closed ends act as walls: the streams draw away from them in a
    // rarefaction, so the end cells have slowed and thinned.
    let d = s
        .cell_data(&["velocity_x".into(), "density".into()])
        .unwrap();
    let (v, r) = (d.field("velocity_x").unwrap(), d.field("density").unwrap());
    assert!(v[0] < 0.5 * u && v[99] > -0.5 * u, "{} {}", v[0], v[99]);
    assert!(r[0] < rho && r[99] < rho, "{} {}", r[0], r[99]);
    // On to 5 ms: the reflected pressure pushes gas out; mass and energy
    // never rise from one step to the next.
    let mut last = t1;
    for _ in 0..400 {
        s.advance(dt).unwrap();
        let t = interior_totals(&s);
        assert!(t.mass <= last.mass * (1.0 + 1e-14), "{last:?} -> {t:?}");
        assert!(t.energy <= last.energy * (1.0 + 1e-14), "{last:?} -> {t:?}");
        last = t;
    }
    assert!(last.mass < t0.mass * 0.999, "{t0:?} {last:?}");
    // What left is booked: the totals with it have not moved.
    let t = s.conservation_totals();
    assert!(((t.mass - t0.mass) / t0.mass).abs() < 1e-13, "{t0:?} {t:?}");
    assert!(
        ((t.energy - t0.energy) / t0.energy).abs() < 1e-13,
        "{t0:?} {t:?}"
    );
}

/// Gas streaming at 50 m/s to the outflow face at x = 1 m, a wall at x = 0.
/// The exact solution is a rarefaction from the wall whose head runs at
/// u + c; ahead of it the gas keeps its state, and an outflow face that
/// reflects nothing leaves the cells next to it exactly in that state. The
/// face carries ρu per unit time and area out, and (ρ(e + ½u²) + p)u of
/// energy (advection and the face-pressure work): the totals close to
/// round-off with those hand-computed fluxes.
#[test]
fn uniform_outflow_leaves_without_reflection_and_its_energy_closes() {
    use IceBoundary::{Outflow, Symmetry};
    let (rho, u, p) = (1.2, 50.0, 1.0e5);
    let mut s = column(100, [Symmetry, Outflow], |_| (rho, u, p));
    let t0 = interior_totals(&s);
    let before = all_fields(&s);
    let dt = 1.0e-5; // Courant (u + c)Δt/Δx = 0.39
    let steps = 10;
    for _ in 0..steps {
        s.advance(dt).unwrap();
    }
    let t = steps as f64 * dt;
    let e = p / (0.4 * rho); // ideal gas: e = p/((γ − 1)ρ)
    let mass_out = rho * u * t;
    let energy_out = (rho * (e + 0.5 * u * u) + p) * u * t;
    let t1 = interior_totals(&s);
    assert!(
        (t1.mass - (t0.mass - mass_out)).abs() < 1e-14 * t0.mass,
        "{} vs {}",
        t1.mass,
        t0.mass - mass_out
    );
    assert!(
        (t1.energy - (t0.energy - energy_out)).abs() < 1e-14 * t0.energy,
        "{} vs {}",
        t1.energy,
        t0.energy - energy_out
    );
    // The booked outflow is those fluxes (with the wall's pressure
    // impulse in the momentum), so the totals close.
    let o = s.outflow();
    assert!(
        (o[1].mass - mass_out).abs() < 1e-12 * mass_out,
        "{:?}",
        o[1]
    );
    assert!(
        (o[1].energy - energy_out).abs() < 1e-12 * energy_out,
        "{:?}",
        o[1]
    );
    let t = s.conservation_totals();
    assert!((t.mass - t0.mass).abs() < 1e-14 * t0.mass);
    assert!((t.energy - t0.energy).abs() < 1e-14 * t0.energy);
    // The wall's rarefaction has moved (u + c)t ≈ 4 cells (its numerical
    // precursor at most a few cells per step); the 50 cells next to the
    // outflow face keep the exact state.
    let after = all_fields(&s);
    for ((name, a), (_, b)) in before.iter().zip(&after) {
        for (x, y) in a[50..].iter().zip(&b[50..]) {
            assert!(
                (x - y).abs() <= 1e-12 * x.abs().max(1e-3),
                "{name}: {x} -> {y}"
            );
        }
    }
    // The wall end did move: this is not a frozen state.
    let d = s.cell_data(&["velocity_x".into()]).unwrap();
    assert!(d.field("velocity_x").unwrap()[0] < 0.9 * u);
}

mod outflow_proptests {
    use super::*;
    use proptest::prelude::*;

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(48))]
        /// Whatever the column's state, faces that are all outflow faces
        /// never raise its mass or its energy.
        #[test]
        fn outflow_faces_never_add_mass_or_energy(
            rho in proptest::collection::vec(0.3f64..3.0, 12),
            u in proptest::collection::vec(-150.0f64..150.0, 12),
            p in proptest::collection::vec(0.5e5f64..3.0e5, 12),
        ) {
            let mut s = column(12, [IceBoundary::Outflow, IceBoundary::Outflow], |x| {
                let i = ((x * 12.0) as usize).min(11);
                (rho[i], u[i], p[i])
            });
            let mut last = s.conservation_totals();
            for _ in 0..6 {
                let dt = s.stable_dt().unwrap();
                s.advance(dt).unwrap();
                let t = s.conservation_totals();
                prop_assert!(t.mass <= last.mass * (1.0 + 1e-14), "{:?} -> {:?}", last, t);
                prop_assert!(t.energy <= last.energy * (1.0 + 1e-14), "{:?} -> {:?}", last, t);
                last = t;
            }
        }
    }
}

/// The far end of the rate stick: a column moving at 50 m/s into the
/// domain through a `ZeroGradient` face is fed with its own state and stays
/// uniform (the exact solution); through an `Outflow` face nothing comes
/// in, so the column draws away from the face in a rarefaction.
#[test]
fn a_zero_gradient_face_feeds_the_column_and_an_outflow_face_does_not() {
    use IceBoundary::{Outflow, ZeroGradient};
    let (rho, u, p) = (1.2, -50.0, 1.0e5);
    let mut fed = column(20, [Outflow, ZeroGradient], |_| (rho, u, p));
    let mut closed = column(20, [Outflow, Outflow], |_| (rho, u, p));
    let before = all_fields(&fed);
    for _ in 0..10 {
        fed.advance(1.0e-5).unwrap();
        closed.advance(1.0e-5).unwrap();
    }
    for ((name, a), (_, b)) in before.iter().zip(&all_fields(&fed)) {
        for (x, y) in a.iter().zip(b) {
            assert!(
                (x - y).abs() <= 1e-12 * x.abs().max(1e-3),
                "{name}: {x} -> {y}"
            );
        }
    }
    let d = closed.cell_data(&["density".into()]).unwrap();
    assert!(d.field("density").unwrap()[19] < 0.99 * rho);
}

/// What leaves through the open faces is booked: a Sod tube with outflow
/// faces run until its shock and rarefaction have left keeps its
/// conservation totals (interior plus booked outflow) to round-off while
/// the interior alone loses mass and energy.
#[test]
fn interior_plus_outflow_is_conserved_when_waves_leave_the_tube() {
    let mut s = sod_one(100, Advection::VanLeer, 0.0);
    let t0 = s.conservation_totals();
    run_to(&mut s, 0.45).unwrap();
    let t1 = s.conservation_totals();
    let o = s.outflow_sum();
    let interior_mass = t1.mass - o.mass;
    assert!(((interior_mass - t0.mass) / t0.mass).abs() > 1e-3, "{o:?}");
    assert!(
        ((t1.mass - t0.mass) / t0.mass).abs() < 1e-13,
        "{t0:?} {t1:?}"
    );
    let scale = t0.mass * 1.2;
    assert!(
        ((t1.momentum[0] - t0.momentum[0]) / scale).abs() < 1e-13,
        "{t0:?} {t1:?}"
    );
    let de = (t1.energy - t0.energy) / t0.energy;
    assert!(de.abs() < 1e-13, "{de}");
    assert!(s.outflow_totals().is_some());
    // The shock carried mass out at the high face; the one-way low face
    // held back the rarefaction's inflow and booked only p*'s impulse.
    let f = s.outflow();
    assert!(f[1].mass > 0.0 && f[0].mass == 0.0, "{f:?}");
    assert!(f[0].momentum[0] < 0.0, "{f:?}");
}

/// A uniform stream books at each open face exactly ρuAΔt of mass,
/// (ρu² + p)AΔt of momentum and (ρE + p)uAΔt of energy per step, out at
/// the high face and in at the low one; a periodic tube books nothing.
#[test]
fn a_uniform_stream_books_its_face_fluxes_exactly() {
    let (rho, u, p) = (1.2, 50.0, 1.0e5);
    let gas = IdealGas::new(1.4, 1.0, 1.0);
    let level = Level::new([0.0; 3], [1.0, 0.1, 0.1], [20, 1, 1], [1, 1, 1], GHOST).unwrap();
    let mut s = IceSolver::new(
        vec![gas],
        level,
        std::array::from_fn(|f| {
            if f < 2 {
                IceBoundary::ZeroGradient
            } else {
                IceBoundary::Symmetry
            }
        }),
        ExchangeCoefficients::uniform(1, 0.0, 0.0),
        IceOptions::default(),
        |_| CellState {
            pressure: p,
            materials: vec![mat(1.0, rho, u)],
        },
    )
    .unwrap();
    let dt = 1e-5;
    for _ in 0..3 {
        s.advance(dt).unwrap();
    }
    let area = 0.1 * 0.1;
    let t = 3.0 * dt;
    let e_total = p / (0.4 * rho) + 0.5 * u * u;
    let f = s.outflow();
    let close = |a: f64, b: f64| (a - b).abs() <= 1e-11 * b.abs().max(1e-300);
    assert!(close(f[1].mass, rho * u * area * t), "{:?}", f[1]);
    assert!(close(f[0].mass, -rho * u * area * t), "{:?}", f[0]);
    let mom = (rho * u * u + p) * area * t;
    assert!(close(f[1].momentum[0], mom), "{:?}", f[1]);
    assert!(close(f[0].momentum[0], -mom), "{:?}", f[0]);
    let en = (rho * e_total + p) * u * area * t;
    assert!(close(f[1].energy, en), "{} vs {en}", f[1].energy);
    assert!(close(f[0].energy, -en), "{} vs {en}", f[0].energy);
    // The y and z faces are symmetry planes of an inactive direction:
    // nothing.
    for o in &f[2..] {
        assert_eq!(*o, brisance_core::ConservationTotals::default());
    }

    let mut periodic = bump_solver([1, 1, 1], [40, 1, 1]);
    let dt = periodic.stable_dt().unwrap();
    periodic.advance(dt).unwrap();
    assert_eq!(periodic.outflow_totals(), None);
}

/// A checkpoint carries the booked outflow: a tube restarted after its
/// shock began to leave ends with the uninterrupted run's totals, bit for
/// bit.
#[test]
fn a_restart_keeps_the_booked_outflow() {
    let mut a = sod_one(100, Advection::VanLeer, 0.0);
    run_to(&mut a, 0.35).unwrap();
    assert!(a.outflow_sum().mass > 0.0);
    let saved = a.save_state().unwrap();
    let mut b = sod_one(100, Advection::VanLeer, 0.0);
    b.restore_state(&saved).unwrap();
    assert_eq!(a.outflow(), b.outflow());
    run_to(&mut a, 0.45).unwrap();
    run_to(&mut b, 0.45).unwrap();
    assert_eq!(a.conservation_totals(), b.conservation_totals());
}
