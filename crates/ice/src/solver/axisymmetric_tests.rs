//! The ICE solver on axisymmetric (r, z) grids: a uniform state at rest
//! stays at rest to the bit, a closed r–z box conserves mass, axial
//! momentum and total energy to round-off (explicit and implicit
//! pressure, with viscosity and conduction), what crosses the open faces
//! is booked, the bits do not depend on the patch split, and a ring's
//! volume is what the totals count.

use std::f64::consts::PI;

use brisance_core::{ConservationTotals, Geometry, Solver};
use brisance_eos::IdealGas;
use brisance_grid::Level;

use super::{IceSolver, GHOST};
use crate::{
    CellState, ExchangeCoefficients, IceBoundary, IceOptions, ImplicitPressure, MaterialState,
    MaterialTransport, PressureSolve,
};

/// Air (γ 1.4) and a light gas (γ 1.67), c_v 718 and 3116 J/(kg K).
fn gases() -> Vec<IdealGas> {
    vec![
        IdealGas::new(1.4, 718.0, 1.0),
        IdealGas::new(5.0 / 3.0, 3116.0, 1.0),
    ]
}

/// Both gases in every cell: mostly air, with a hot, dense, light-gas-rich
/// blob of radius 0.25 centred at (r, z) = `blob` moving at `u_blob`.
fn blob_state(x: [f64; 3], blob: [f64; 2], u_blob: [f64; 3]) -> CellState {
    let d2 = (x[0] - blob[0]).powi(2) + (x[1] - blob[1]).powi(2);
    let inside = d2 < 0.25 * 0.25;
    let (p, th, u) = if inside {
        (5.0e5, 0.7, u_blob)
    } else {
        (1.0e5, 0.02, [0.0; 3])
    };
    CellState {
        pressure: p,
        materials: vec![
            MaterialState {
                volume_fraction: 1.0 - th,
                density: if inside { 3.0 } else { 1.2 },
                velocity: u,
            },
            MaterialState {
                volume_fraction: th,
                density: if inside { 0.8 } else { 0.17 },
                velocity: u,
            },
        ],
    }
}

/// An (r, z) solver on [0, 1] × [0, 1.5] with `cells` = (Nr, Nz) in
/// `layout` patches.
fn rz_solver(
    cells: [usize; 2],
    layout: [usize; 2],
    bcs: [IceBoundary; 6],
    options: IceOptions,
    state: impl Fn([f64; 3]) -> CellState + Sync,
) -> IceSolver<IdealGas> {
    let level = Level::new(
        [0.0; 3],
        [1.0, 1.5, 1.0 / cells[0] as f64],
        [cells[0], cells[1], 1],
        [layout[0], layout[1], 1],
        GHOST,
    )
    .unwrap();
    on_rings(level, bcs, options, state).unwrap()
}

/// The two gases on `level` read as rings.
fn on_rings(
    level: Level,
    bcs: [IceBoundary; 6],
    options: IceOptions,
    state: impl Fn([f64; 3]) -> CellState + Sync,
) -> Result<IceSolver<IdealGas>, crate::IceError> {
    IceSolver::new(
        gases(),
        level,
        bcs,
        ExchangeCoefficients::uniform(2, 1.0e4, 0.0),
        IceOptions {
            geometry: Geometry::Axisymmetric,
            ..options
        },
        state,
    )
}

/// Axis (symmetry), walls elsewhere.
fn closed() -> [IceBoundary; 6] {
    [
        IceBoundary::Symmetry,
        IceBoundary::FixedVelocity([0.0; 3]),
        IceBoundary::FixedVelocity([0.0; 3]),
        IceBoundary::Symmetry,
        IceBoundary::Symmetry,
        IceBoundary::Symmetry,
    ]
}

fn run(s: &mut IceSolver<IdealGas>, steps: usize) {
    for _ in 0..steps {
        let dt = s.stable_dt().unwrap();
        s.advance(dt).unwrap();
    }
}

fn implicit() -> IceOptions {
    IceOptions {
        pressure: PressureSolve::Implicit(ImplicitPressure {
            tolerance: 1e-12,
            max_iterations: 30,
            ..Default::default()
        }),
        cfl: 0.3,
        ..Default::default()
    }
}

/// Every velocity component of every material and the pressure, cell by
/// cell in global order.
fn velocities_and_pressure(s: &IceSolver<IdealGas>) -> (Vec<f64>, Vec<f64>) {
    let names: Vec<String> = ["velocity_x", "velocity_y", "pressure"]
        .iter()
        .map(|n| n.to_string())
        .collect();
    let data = s.cell_data(&names).unwrap();
    let mut v = data.field("velocity_x").unwrap().to_vec();
    v.extend_from_slice(data.field("velocity_y").unwrap());
    (v, data.field("pressure").unwrap().to_vec())
}

#[test]
fn a_uniform_state_at_rest_stays_at_rest_to_the_bit() {
    for options in [IceOptions::default(), implicit()] {
        let uniform = |_: [f64; 3]| blob_state([9.0, 9.0, 0.0], [0.0; 2], [0.0; 3]);
        let mut s = rz_solver([12, 10], [2, 2], closed(), options, uniform);
        s.set_transport(vec![
            MaterialTransport {
                viscosity: 1.8e-5,
                thermal_conductivity: 0.026,
            };
            2
        ])
        .unwrap();
        let (_, p0) = velocities_and_pressure(&s);
        run(&mut s, 20);
        let (v, p) = velocities_and_pressure(&s);
        assert!(v.iter().all(|&u| u == 0.0), "{:?}", options.pressure);
        assert_eq!(p, p0, "{:?}", options.pressure);
    }
}

#[test]
fn the_totals_count_the_rings() {
    // 1.2 kg/m³ of air and 0.17 of the light gas, θ 0.98 and 0.02, in the
    // cylinder r ≤ 1, 0 ≤ z ≤ 1.5: mass ρ̄ π R² L.
    let uniform = |_: [f64; 3]| blob_state([9.0, 9.0, 0.0], [0.0; 2], [0.0; 3]);
    let s = rz_solver([10, 6], [1, 1], closed(), IceOptions::default(), uniform);
    let rho = 0.98 * 1.2 + 0.02 * 0.17;
    let want = rho * PI * 1.5;
    let t = s.conservation_totals();
    assert!((t.mass - want).abs() < 1e-13 * want, "{} vs {want}", t.mass);
}

fn drift(a: ConservationTotals, b: ConservationTotals) -> [f64; 3] {
    [
        (b.mass - a.mass).abs() / a.mass,
        (b.momentum[1] - a.momentum[1]).abs() / a.energy.sqrt().max(1.0),
        (b.energy - a.energy).abs() / a.energy,
    ]
}

#[test]
fn a_closed_rz_box_conserves_mass_axial_momentum_and_energy() {
    // The implicit step runs at the material-velocity Courant number, some
    // five acoustic Courant numbers here: its blob sits on the axis (a
    // sphere), not beside it (a torus whose inner edge would squeeze the
    // axis cells by half their volume in the first step).
    for (name, options, blob, transport) in [
        ("explicit", IceOptions::default(), [0.3, 0.6], false),
        ("implicit", implicit(), [0.0, 0.6], false),
        (
            "explicit, viscous and conducting",
            IceOptions::default(),
            [0.3, 0.6],
            true,
        ),
    ] {
        let mut s = rz_solver([16, 24], [2, 3], closed(), options, |x| {
            blob_state(x, blob, [40.0, -25.0, 0.0])
        });
        if transport {
            s.set_transport(vec![
                MaterialTransport {
                    viscosity: 0.5,
                    thermal_conductivity: 40.0,
                };
                2
            ])
            .unwrap();
        }
        let t0 = s.conservation_totals();
        run(&mut s, 60);
        let t1 = s.conservation_totals();
        let [m, p, e] = drift(t0, t1);
        assert!(m < 1e-13, "{name}: mass {m:e}");
        assert!(p < 1e-12, "{name}: axial momentum {p:e}");
        assert!(e < 1e-13, "{name}: energy {e:e}");
        // Something happened: the blob's pressure reached the walls.
        let (v, _) = velocities_and_pressure(&s);
        assert!(v.iter().any(|u| u.abs() > 1.0), "{name}");
    }
}

#[test]
fn what_leaves_through_the_open_faces_is_booked() {
    let open = [
        IceBoundary::Symmetry,
        IceBoundary::Outflow,
        IceBoundary::Outflow,
        IceBoundary::Outflow,
        IceBoundary::Symmetry,
        IceBoundary::Symmetry,
    ];
    let mut s = rz_solver([12, 18], [2, 2], open, IceOptions::default(), |x| {
        blob_state(x, [0.0, 0.75], [0.0; 3])
    });
    let t0 = s.conservation_totals();
    run(&mut s, 150);
    let t1 = s.conservation_totals();
    let out = s.outflow_sum();
    assert!(out.mass > 1e-4 * t0.mass, "nothing left: {}", out.mass);
    let [m, p, e] = drift(t0, t1);
    assert!(m < 1e-13, "mass {m:e}");
    assert!(p < 1e-12, "axial momentum {p:e}");
    assert!(e < 1e-13, "energy {e:e}");
}

#[test]
fn the_bits_do_not_depend_on_the_patch_split() {
    let go = |layout: [usize; 2]| {
        let mut s = rz_solver([14, 15], layout, closed(), IceOptions::default(), |x| {
            blob_state(x, [0.2, 0.5], [10.0, 30.0, 0.0])
        });
        run(&mut s, 25);
        (velocities_and_pressure(&s), s.conservation_totals())
    };
    let one = go([1, 1]);
    for layout in [[2, 1], [3, 2], [1, 4]] {
        let other = go(layout);
        assert_eq!(one.0, other.0, "{layout:?}");
        assert_eq!(one.1, other.1, "{layout:?}");
    }
}

#[test]
fn a_ring_off_the_axis_and_a_grid_that_starts_there() {
    // A grid from r = 0.5: the low face is a wall, not the axis.
    let level = Level::new(
        [0.5, 0.0, 0.0],
        [1.5, 1.0, 0.1],
        [10, 10, 1],
        [1, 1, 1],
        GHOST,
    )
    .unwrap();
    let mut bcs = closed();
    bcs[0] = IceBoundary::FixedVelocity([0.0; 3]);
    let mut s = on_rings(level, bcs, IceOptions::default(), |x| {
        blob_state(x, [1.0, 0.5], [0.0; 3])
    })
    .unwrap();
    let t0 = s.conservation_totals();
    // The annulus 0.5 ≤ r ≤ 1.5, 1 long.
    let rho = 0.98 * 1.2 + 0.02 * 0.17;
    let blob_free = rho * PI * (1.5f64.powi(2) - 0.25);
    assert!(t0.mass > blob_free, "{} vs {blob_free}", t0.mass);
    run(&mut s, 40);
    let [m, p, e] = drift(t0, s.conservation_totals());
    assert!(m < 1e-13 && p < 1e-12 && e < 1e-13, "{m:e} {p:e} {e:e}");
}

#[test]
fn the_axis_must_be_a_symmetry_face_and_the_grid_one_cell_thick() {
    let make = |cells: [usize; 3], bcs: [IceBoundary; 6]| {
        let level = Level::new([0.0; 3], [1.0, 1.0, 0.1], cells, [1, 1, 1], GHOST).unwrap();
        on_rings(level, bcs, IceOptions::default(), |x| {
            blob_state(x, [0.0, 0.5], [0.0; 3])
        })
        .map(|_| ())
        .unwrap_err()
        .to_string()
    };
    let mut bcs = closed();
    bcs[0] = IceBoundary::Outflow;
    assert!(make([8, 8, 1], bcs).contains("axis"));
    assert!(make([8, 8, 2], closed()).contains("one cell along z"));
    let mut bcs = closed();
    bcs[0] = IceBoundary::Periodic;
    bcs[1] = IceBoundary::Periodic;
    assert!(make([8, 8, 1], bcs).contains("axis"));
}
