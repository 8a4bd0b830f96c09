//! Tests of the FDM on axisymmetric (r, z) grids: rest, conservation over
//! ring volumes, determinism, restart, and the blast of a sphere on the
//! axis against the same blast on the 3D octant.

use brisance_core::{ConservationTotals, Geometry, Solver};
use brisance_eos::IdealGas;
use brisance_grid::Level;

use crate::{FaceLimiter, FdmBoundary, FdmOptions, FdmSolver, PrimitiveState};

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

fn rz_options() -> FdmOptions {
    FdmOptions {
        geometry: Geometry::Axisymmetric,
        ..Default::default()
    }
}

/// An (r, z) grid from (r0, −0.4) to (1, 1.1) on 24 × 30 cells.
fn rz_level(r0: f64, layout: [usize; 3]) -> Level {
    Level::new(
        [r0, -0.4, 0.0],
        [1.0, 1.1, 0.1],
        [24, 30, 1],
        layout,
        crate::sweep::GHOST_RZ,
    )
    .unwrap()
}

fn run(solver: &mut impl Solver, steps: usize) {
    for _ in 0..steps {
        let dt = solver.stable_dt().unwrap();
        solver.advance(dt).unwrap();
    }
}

fn in_threads(threads: usize, f: impl FnOnce() + Send) {
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap()
        .install(f);
}

fn limited(s: &impl Solver) -> (u64, u64) {
    let g = s.safeguards();
    let by = |name: &str| {
        g.iter()
            .find(|u| u.name.contains(name))
            .map_or(0, |u| u.acted)
    };
    (by("positivity"), by("density"))
}

fn bits(fields: &[Vec<f64>]) -> Vec<Vec<u64>> {
    fields
        .iter()
        .map(|f| f.iter().map(|x| x.to_bits()).collect())
        .collect()
}

#[test]
fn a_uniform_gas_at_rest_stays_at_rest_to_the_bit_in_rz() {
    // On the axis (r from 0) and on an annulus (r from 0.3), walls and
    // open faces: the hoop source p(A₊ − A₋)/V cancels the face pressures
    // exactly, the smoothing sees no differences, and no bit moves.
    let rest = state(1.2345, [0.0; 3], 2.7193);
    for (r0, x_low) in [
        (0.0, FdmBoundary::Reflective),
        (0.3, FdmBoundary::Reflective),
        (0.3, FdmBoundary::Outflow),
    ] {
        for limiter in [FaceLimiter::Off, FaceLimiter::Full] {
            let bcs = [
                x_low,
                FdmBoundary::Outflow,
                FdmBoundary::Reflective,
                FdmBoundary::Fixed(rest),
                FdmBoundary::Outflow,
                FdmBoundary::Outflow,
            ];
            let opts = FdmOptions {
                limiter,
                ..rz_options()
            };
            let mut s =
                FdmSolver::new(gas(), rz_level(r0, [2, 3, 1]), bcs, opts, |_| rest).unwrap();
            let before = bits(&s.conservative_fields());
            let t0 = s.interior_totals();
            run(&mut s, 40);
            assert_eq!(
                bits(&s.conservative_fields()),
                before,
                "r0 {r0} {limiter:?}"
            );
            assert_eq!(s.interior_totals(), t0);
            assert_eq!(limited(&s), (0, 0));
        }
    }
}

#[test]
fn ring_volumes_weigh_the_totals() {
    // The grid [0, 1] × [−0.4, 1.1] holds the cylinder π·1²·1.5.
    let rest = state(2.0, [0.0, 3.0, 0.0], 1.0);
    let s = FdmSolver::new(
        gas(),
        rz_level(0.0, [1, 1, 1]),
        [FdmBoundary::Reflective; 6],
        rz_options(),
        |_| rest,
    )
    .unwrap();
    let v = std::f64::consts::PI * 1.5;
    let t = s.interior_totals();
    assert!((t.mass - 2.0 * v).abs() < 1e-13 * v, "{t:?}");
    assert!((t.momentum[1] - 6.0 * v).abs() < 1e-13 * v, "{t:?}");
    let e = 1.0 / 0.4 + 0.5 * 2.0 * 9.0;
    assert!((t.energy - e * v).abs() < 1e-13 * e * v, "{t:?}");
}

/// A blast on the axis: a dense hot sphere centred at (0, 0.3) moving
/// along z, in air flowing along z, with `bcs`.
fn rz_blast(layout: [usize; 3], bcs: [FdmBoundary; 6]) -> FdmSolver<IdealGas> {
    FdmSolver::new(gas(), rz_level(0.0, layout), bcs, rz_options(), |x| {
        let d2 = x[0] * x[0] + (x[1] - 0.3).powi(2);
        if d2 < 0.09 {
            state(4.0, [0.0, 0.3, 0.0], 40.0)
        } else {
            state(1.0, [0.0, 0.1 * x[0], 0.0], 1.0)
        }
    })
    .unwrap()
}

fn closed() -> [FdmBoundary; 6] {
    [FdmBoundary::Reflective; 6]
}

fn open() -> [FdmBoundary; 6] {
    [
        FdmBoundary::Reflective,
        FdmBoundary::Outflow,
        FdmBoundary::Fixed(state(1.0, [0.0, 0.2, 0.0], 1.0)),
        FdmBoundary::Outflow,
        FdmBoundary::Outflow,
        FdmBoundary::Outflow,
    ]
}

/// Relative changes of mass, axial momentum (to the mass times 1 m/s)
/// and energy between `t0` and `t1`.
fn drift(t0: ConservationTotals, t1: ConservationTotals) -> [f64; 3] {
    [
        ((t1.mass - t0.mass) / t0.mass).abs(),
        ((t1.momentum[1] - t0.momentum[1]) / t0.mass).abs(),
        ((t1.energy - t0.energy) / t0.energy).abs(),
    ]
}

#[test]
fn a_closed_rz_box_conserves_mass_axial_momentum_and_energy() {
    // All faces walls: the interior's mass and energy stay, and its
    // axial momentum plus the walls' pressure impulse (booked through
    // the annuli of the z faces).
    let mut s = rz_blast([2, 2, 1], closed());
    let t0 = s.conservation_totals();
    let i0 = s.interior_totals();
    run(&mut s, 300);
    let d = drift(t0, s.conservation_totals());
    let interior = drift(i0, s.interior_totals());
    eprintln!("closed r-z box, 300 steps: relative drift (mass, axial momentum, energy) {d:?}; interior mass {:e}, energy {:e}", interior[0], interior[2]);
    assert!(d.iter().all(|&x| x < 1e-13), "{d:?}");
    assert!(interior[0] < 1e-13 && interior[2] < 1e-13, "{interior:?}");
    // The shock is limited at its density bounds, and it has reached
    // the walls.
    assert!(limited(&s).1 > 0);
    assert!((s.interior_totals().momentum[1] - i0.momentum[1]).abs() > 1e-6 * i0.mass);
}

#[test]
fn open_rz_faces_book_their_ring_weighted_fluxes() {
    // Inflow at z_low, outflow at r = 1 and z_high: the interior plus
    // what crossed the faces (2π r Δz Δr per radial face cell, the ring
    // volume per axial one) is conserved to round-off.
    let mut s = rz_blast([3, 2, 1], open());
    let t0 = s.conservation_totals();
    let i0 = s.interior_totals();
    run(&mut s, 300);
    let d = drift(t0, s.conservation_totals());
    eprintln!("open r-z faces, 300 steps: relative drift (mass, axial momentum, energy) {d:?}");
    assert!(d.iter().all(|&x| x < 1e-13), "{d:?}");
    // Something did cross them.
    assert!(drift(i0, s.interior_totals())[0] > 1e-3);
    assert!(s.outflow().mass.abs() > 1e-3 * i0.mass);
}

#[test]
fn an_open_inner_face_off_the_axis_books_its_ring_fluxes() {
    // An annulus r ∈ [0.3, 1] with its inner face open: a ring of hot gas
    // at r = 0.55 blows out through r = 0.3 as well; the interior plus
    // what crossed the faces (2π·0.3·Δz·Δr per inner face cell) is
    // conserved to round-off.
    let mut bcs = open();
    bcs[0] = FdmBoundary::Outflow;
    let mut s = FdmSolver::new(gas(), rz_level(0.3, [2, 2, 1]), bcs, rz_options(), |x| {
        if (x[0] - 0.55).powi(2) + (x[1] - 0.3).powi(2) < 0.02 {
            state(4.0, [0.0; 3], 40.0)
        } else {
            state(1.0, [0.0; 3], 1.0)
        }
    })
    .unwrap();
    let t0 = s.conservation_totals();
    run(&mut s, 200);
    let d = drift(t0, s.conservation_totals());
    assert!(d.iter().all(|&x| x < 1e-13), "{d:?}");
    let inner = s.outflow_where(|f, _| f == 0);
    assert!(inner.mass > 1e-3 * t0.mass, "{inner:?}");
}

#[test]
fn rz_fields_are_bit_identical_for_any_patch_split_and_thread_count_with_the_limiter_acting() {
    let reference = {
        let mut s = rz_blast([1, 1, 1], open());
        in_threads(1, || run(&mut s, 60));
        assert!(limited(&s).1 > 0, "the density bounds act");
        (
            bits(&s.conservative_fields()),
            s.conservation_totals(),
            limited(&s),
        )
    };
    for layout in [[2, 1, 1], [3, 2, 1], [1, 3, 1], [4, 1, 1]] {
        for threads in [1, 2] {
            let mut s = rz_blast(layout, open());
            in_threads(threads, || run(&mut s, 60));
            assert_eq!(limited(&s), reference.2, "{layout:?} on {threads}");
            assert_eq!(s.conservation_totals(), reference.1, "{layout:?}");
            assert!(
                bits(&s.conservative_fields()) == reference.0,
                "fields differ for {layout:?} on {threads} threads"
            );
        }
    }
}

#[test]
fn the_face_limiter_carries_a_strong_rz_blast_that_stops_the_plain_scheme() {
    // A 10⁵ pressure ratio on the axis into a thin gas: the scheme as
    // printed stops; the face limiter (its first-order state with the
    // hoop source) carries it through, every cell physical.
    let make = |limiter| {
        let opts = FdmOptions {
            limiter,
            ..rz_options()
        };
        FdmSolver::new(gas(), rz_level(0.0, [2, 2, 1]), open(), opts, |x| {
            let d2 = x[0] * x[0] + (x[1] - 0.3).powi(2);
            if d2 < 0.04 {
                state(10.0, [0.0; 3], 1e4)
            } else {
                state(0.01, [0.0; 3], 0.1)
            }
        })
        .unwrap()
    };
    let mut plain = make(FaceLimiter::Off);
    let stopped = (0..150).any(|_| plain.stable_dt().and_then(|dt| plain.advance(dt)).is_err());
    assert!(stopped, "the plain scheme must stop on this blast");
    let mut s = make(FaceLimiter::Full);
    let t0 = s.conservation_totals();
    run(&mut s, 150);
    let (positive, bounds) = limited(&s);
    eprintln!("strong r-z blast: faces limited for positivity {positive}, for the density bounds {bounds}");
    assert!(bounds > 0, "{positive} {bounds}");
    let d = drift(t0, s.conservation_totals());
    assert!(d[0] < 1e-13 && d[2] < 1e-13, "{d:?}");
}

#[test]
fn rz_restart_continues_bit_identically_on_another_split() {
    let mut a = rz_blast([1, 1, 1], open());
    run(&mut a, 20);
    let saved = a.save_state().unwrap();
    run(&mut a, 20);
    let mut b = rz_blast([3, 2, 1], open());
    b.restore_state(&saved).unwrap();
    run(&mut b, 20);
    assert_eq!(a.time(), b.time());
    assert!(bits(&a.conservative_fields()) == bits(&b.conservative_fields()));
    assert_eq!(a.conservation_totals(), b.conservation_totals());
}

#[test]
fn an_axisymmetric_grid_is_checked_when_built() {
    let rest = state(1.0, [0.0; 3], 1.0);
    let build = |level: Level, x_low: FdmBoundary| {
        let mut bcs = [FdmBoundary::Outflow; 6];
        bcs[0] = x_low;
        FdmSolver::new(gas(), level, bcs, rz_options(), |_| rest).map(|_| ())
    };
    let three_d = Level::new([0.0; 3], [1.0; 3], [8, 8, 8], [1; 3], 4).unwrap();
    assert!(build(three_d, FdmBoundary::Reflective).is_err());
    let below = Level::new([-0.1, 0.0, 0.0], [1.0; 3], [8, 8, 1], [1; 3], 5).unwrap();
    assert!(build(below.clone(), FdmBoundary::Reflective).is_err());
    let few_ghosts = Level::new([0.0; 3], [1.0; 3], [8, 8, 1], [1; 3], 4).unwrap();
    assert!(build(few_ghosts, FdmBoundary::Reflective).is_err());
    assert!(build(below, FdmBoundary::Reflective).is_err());
    assert!(build(rz_level(0.0, [1; 3]), FdmBoundary::Outflow).is_err());
    assert!(build(rz_level(0.2, [1; 3]), FdmBoundary::Outflow).is_ok());
}

/// The sphere of radius `radius` and its smooth edge (tanh over 1.5 cells
/// of `h`): pressure and density at distance `d` from its centre.
fn sphere(d: f64, radius: f64, h: f64) -> PrimitiveState {
    let f = 0.5 * (1.0 - ((d - radius) / (1.5 * h)).tanh());
    state(1.0 + 3.0 * f, [0.0; 3], 1.0 + 19.0 * f)
}

/// Pressure history at each gauge: (peak, time of the peak, arrival =
/// first time the pressure exceeds ambient by 10 % of the peak's excess).
fn gauge_histories(s: &mut impl Solver, points: &[[f64; 3]], end: f64) -> Vec<(f64, f64, f64)> {
    let mut out = vec![(0.0f64, 0.0, f64::NAN); points.len()];
    let mut hist: Vec<Vec<(f64, f64)>> = vec![Vec::new(); points.len()];
    let mut v = Vec::new();
    while s.time() < end {
        let dt = s.stable_dt().unwrap().min(end - s.time());
        s.advance(dt).unwrap();
        for (h, &x) in hist.iter_mut().zip(points) {
            s.sample(x, &["pressure".into()], &mut v).unwrap();
            h.push((s.time(), v[0]));
        }
    }
    for (o, h) in out.iter_mut().zip(&hist) {
        let &(tp, pk) = h
            .iter()
            .max_by(|a, b| a.1.partial_cmp(&b.1).unwrap())
            .unwrap();
        let level = 1.0 + 0.1 * (pk - 1.0);
        let k = h.iter().position(|&(_, p)| p > level).unwrap();
        // Interpolated crossing between samples k − 1 and k.
        let (t0, p0) = h[k - 1];
        let (t1, p1) = h[k];
        *o = (pk, tp, t0 + (t1 - t0) * (level - p0) / (p1 - p0));
    }
    out
}

/// A sphere of radius 0.2 centred at the origin (pressure 20, density 4,
/// in a gas at 1 and 1, its edge smoothed over 1.5 cells so that both
/// grids sample the same function), run to t = 0.25 on the (r, z)
/// quarter plane [0, 1]² (axis and z = 0 walls) and on the 3D octant
/// [0, 1]³ (three symmetry planes) at the same h = 1/n. Gauges at
/// distance 0.5 on the axis, on the symmetry plane z = 0 and on the 45°
/// ray (and near the axis), sampled after every step; and the pressure
/// along the three rays at t = 0.25. Prints every number and returns,
/// for the three gauges and then the three rays, the relative
/// differences (r–z against octant) of the peak overpressure and of the
/// arrival time (rays: the shock's position, where the pressure crosses
/// half the peak's overpressure).
fn rz_against_octant(n: usize) -> Vec<[f64; 2]> {
    let h = 1.0 / n as f64;
    let r = 0.2;
    let rz = Level::new([0.0; 3], [1.0, 1.0, h], [n, n, 1], [2, 2, 1], 5).unwrap();
    let mut bcs = [FdmBoundary::Outflow; 6];
    bcs[0] = FdmBoundary::Reflective;
    bcs[2] = FdmBoundary::Reflective;
    let mut a = FdmSolver::new(gas(), rz, bcs, rz_options(), |x| {
        sphere((x[0] * x[0] + x[1] * x[1]).sqrt(), r, h)
    })
    .unwrap();
    let cube = Level::new([0.0; 3], [1.0; 3], [n; 3], [2, 2, 2], 4).unwrap();
    let mut bcs = [FdmBoundary::Outflow; 6];
    for f in [0, 2, 4] {
        bcs[f] = FdmBoundary::Reflective;
    }
    let mut b = FdmSolver::new(gas(), cube, bcs, FdmOptions::default(), |x| {
        sphere((x[0] * x[0] + x[1] * x[1] + x[2] * x[2]).sqrt(), r, h)
    })
    .unwrap();
    // Energies put in (the 3D octant times 8 against the r–z half
    // space times 2).
    let (ea, eb) = (a.interior_totals().energy, b.interior_totals().energy);
    let c = 0.5 * h;
    let d = 0.5;
    let s45 = d * std::f64::consts::FRAC_1_SQRT_2;
    // (r, z) points and their 3D counterparts (z of r–z is the 3D z).
    let mut rz_points = vec![[c, d, 0.0], [d, c, 0.0], [s45, s45, 0.0]];
    let mut xyz_points = vec![[c, c, d], [d, c, c], [s45, c, s45]];
    // Off the axis, 1–5 cells out, at the axis gauge's height.
    for k in [1.0, 2.0, 5.0] {
        rz_points.push([c + k * h, d, 0.0]);
        xyz_points.push([c + k * h, c, d]);
    }
    let end = 0.25;
    let ga = gauge_histories(&mut a, &rz_points, end);
    let gb = gauge_histories(&mut b, &xyz_points, end);
    eprintln!(
        "h = 1/{n}: energy r-z×2 {:.6e}, octant×8 {:.6e} ({:+.2e})",
        2.0 * ea,
        8.0 * eb,
        2.0 * ea / (8.0 * eb) - 1.0
    );
    // Pressure along three rays at the end: cell centres at the same
    // distances on both grids (the axis ray exactly).
    let mut v = Vec::new();
    let mut rays = Vec::new();
    let mut ray = |s: &dyn Solver, f: &dyn Fn(f64) -> [f64; 3]| -> (f64, f64) {
        let prof: Vec<(f64, f64)> = (0..n)
            .map(|i| {
                let q = (i as f64 + 0.5) * h;
                s.sample(f(q), &["pressure".into()], &mut v).unwrap();
                (q, v[0])
            })
            .collect();
        let pk = prof.iter().map(|x| x.1).fold(0.0, f64::max);
        let half = 1.0 + 0.5 * (pk - 1.0);
        let k = prof.iter().rposition(|x| x.1 > half).unwrap();
        let ((q0, p0), (q1, p1)) = (prof[k], prof[k + 1]);
        (pk, q0 + (q1 - q0) * (p0 - half) / (p0 - p1))
    };
    let rays_rz: [&dyn Fn(f64) -> [f64; 3]; 3] = [&|q| [c, q, 0.0], &|q| [q, c, 0.0], &|q| {
        [
            q * std::f64::consts::FRAC_1_SQRT_2,
            q * std::f64::consts::FRAC_1_SQRT_2,
            0.0,
        ]
    }];
    let rays_3d: [&dyn Fn(f64) -> [f64; 3]; 3] = [&|q| [c, c, q], &|q| [q, c, c], &|q| {
        [
            q * std::f64::consts::FRAC_1_SQRT_2,
            c,
            q * std::f64::consts::FRAC_1_SQRT_2,
        ]
    }];
    for (k, name) in ["axis", "plane", "45°"].iter().enumerate() {
        let (pa, sa) = ray(&a, rays_rz[k]);
        let (pb, sb) = ray(&b, rays_3d[k]);
        let (dp, ds) = ((pa - 1.0) / (pb - 1.0) - 1.0, sa / sb - 1.0);
        eprintln!("h = 1/{n}, ray {name} at t = {end}: r-z peak {pa:.5}, shock at {sa:.5}; octant peak {pb:.5}, shock at {sb:.5}; overpressure {:+.3} %, position {:+.3} %", 100.0 * dp, 100.0 * ds);
        rays.push([dp, ds]);
    }
    let mut out = Vec::new();
    let names = ["axis", "plane z=0", "45°", "r=1.5h", "r=2.5h", "r=5.5h"];
    for (name, (x, y)) in names.iter().zip(ga.iter().zip(&gb)) {
        let dp = (x.0 - 1.0) / (y.0 - 1.0) - 1.0;
        let dt = x.2 / y.2 - 1.0;
        eprintln!(
            "h = 1/{n}, gauge {name}: r-z peak {:.5} at {:.5}, arrival {:.5}; octant peak {:.5} at {:.5}, arrival {:.5}; overpressure {:+.3} %, arrival {:+.3} %",
            x.0, x.1, x.2, y.0, y.1, y.2, 100.0 * dp, 100.0 * dt
        );
        out.push([dp, dt]);
    }
    out.truncate(3);
    out.extend(rays);
    out
}

fn assert_within_one_percent(n: usize) {
    let d = rz_against_octant(n);
    let off: Vec<_> = d
        .iter()
        .zip(["axis", "plane", "45°", "axis ray", "plane ray", "45° ray"])
        .filter(|(d, _)| d[0].abs() >= 0.01 || d[1].abs() >= 0.01)
        .collect();
    assert!(off.is_empty(), "beyond 1 %: {off:?}");
}

#[test]
#[ignore = "fails: at h = 1/40 the peak overpressures differ by up to 5 % (45° ray), see docs/physics/axisymmetric.md; run with --release --ignored --nocapture"]
fn a_sphere_on_the_axis_blasts_as_on_the_3d_octant() {
    assert_within_one_percent(40);
}

#[test]
#[ignore = "fails: at h = 1/80 the 45° gauge's peak differs by 2.9 % and its arrival by 1.2 %, see docs/physics/axisymmetric.md; the 3D octant has 512 000 cells: run with --release --ignored --nocapture"]
fn a_sphere_on_the_axis_blasts_as_on_the_3d_octant_fine() {
    assert_within_one_percent(80);
}

#[test]
fn a_sphere_on_the_axis_blasts_about_as_on_the_3d_octant_and_closer_on_a_finer_grid() {
    // What does hold at h = 1/40 (the 3D octant 64 000 cells): the shock's
    // arrival and position within 1.5 %, the peaks within 6 % (1 % is
    // the target; the two tests above say where it is missed).
    let d = rz_against_octant(40);
    for [dp, dt] in &d {
        assert!(dp.abs() < 0.06 && dt.abs() < 0.015, "{dp:e} {dt:e}");
    }
}

#[test]
fn detonation_products_on_the_axis_conserve_over_rings() {
    // The two-species gas law in r–z: a sphere of TNT products on the
    // axis in a closed box; mass, axial momentum (to the mass times
    // 100 m/s, the flow's speeds being km/s) and energy stay to
    // round-off, and Y stays in [0, 1]. The products mass changes by the
    // clipping of ρY to [0, ρ] (docs/physics/fdm_mixture.md), as on a
    // planar grid: 0.49 % here, 0.43 % for the same grid read as planar.
    use crate::ProductsInAir;
    use brisance_eos::Jwl;
    let law = ProductsInAir::new(Jwl::tnt(), IdealGas::air()).unwrap();
    let level = Level::new(
        [0.0; 3],
        [0.5, 1.0, 0.01],
        [25, 50, 1],
        [2, 2, 1],
        crate::sweep::GHOST_RZ,
    )
    .unwrap();
    let mut s = FdmSolver::with_species(law, level, closed(), rz_options(), |x| {
        if x[0] * x[0] + (x[1] - 0.4).powi(2) < 0.01 {
            (state(20.0, [0.0; 3], 2.0e7), 1.0)
        } else {
            (state(1.2, [0.0; 3], 1.0e5), 0.0)
        }
    })
    .unwrap();
    let (t0, y0) = (s.conservation_totals(), s.products_mass());
    // 0.1 m of TNT products at 20 kg/m³ over the ball's rings.
    let ball = 20.0 * 4.0 / 3.0 * std::f64::consts::PI * 1e-3;
    assert!((y0 / ball - 1.0).abs() < 0.05, "{y0} {ball}");
    run(&mut s, 150);
    let mut d = drift(t0, s.conservation_totals());
    d[1] /= 100.0;
    let dy = (s.products_mass() / y0 - 1.0).abs();
    eprintln!("products in r-z, 150 steps: drift (mass, axial momentum, energy) {d:?}, products mass {dy:e}");
    assert!(d.iter().all(|&x| x < 1e-13) && dy < 0.01, "{d:?} {dy:e}");
    let y = s
        .cell_data(&["products_mass_fraction".into()])
        .unwrap()
        .fields[0]
        .1
        .clone();
    assert!(y.iter().all(|&v| (0.0..=1.0).contains(&v)));
    assert!(y.iter().filter(|&&v| v > 0.0 && v < 1.0).count() > 10);
}
