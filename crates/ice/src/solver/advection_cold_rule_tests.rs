use super::steps::TRACE_FLOOR;
use super::*;
use brisance_core::Solver;
use brisance_eos::{EosModel, IdealGas};

/// Air at 10 Pa and 1 kg/m³ (e = 25 J/kg, 0.035 K) moving at 3 km/s
/// away from the closed x = 0 wall, beside still air at 10⁵ Pa: the
/// expansion at the wall leaves E − ½|u|² without a positive
/// temperature in step 12, and the rule fires. The closed box conserves
/// total energy except for what the two cold rules add, so the change
/// of the total over the run is their booked energy to round-off: the
/// counter accounts for exactly the energy the rule makes.
#[test]
fn step_12_books_the_energy_its_cold_rule_adds() {
    let level = Level::new([0.0; 3], [0.4, 0.01, 0.01], [40, 1, 1], [1, 1, 1], GHOST).unwrap();
    let eos = vec![EosModel::IdealGas(IdealGas::new(1.4, 717.5, 1.0))];
    let mut s = IceSolver::new(
        eos,
        level,
        std::array::from_fn(|_| IceBoundary::Symmetry),
        ExchangeCoefficients::uniform(1, 1e15, 0.0),
        IceOptions::default(),
        |x| {
            if x[0] < 0.2 {
                CellState::single(10.0, 1.0, [3000.0, 0.0, 0.0])
            } else {
                CellState::single(1e5, 1.2, [0.0; 3])
            }
        },
    )
    .unwrap();
    let e0 = s.conservation_totals().energy;
    for _ in 0..50 {
        let dt = s.stable_dt().unwrap();
        s.advance(dt).unwrap();
    }
    let (adv, eq) = (s.kept_warm_advection_totals()[0], s.kept_warm_totals()[0]);
    assert!(adv.firings >= 1 && adv.energy > 0.0, "{adv:?}");
    let change = s.conservation_totals().energy - e0;
    // E ≈ 95 J; the booked energy is 3.4e-4 J.
    assert!(
        (change - adv.energy - eq.energy).abs() < 1e-12 * e0,
        "change {change:e} J, booked {:e} + {:e} J",
        adv.energy,
        eq.energy
    );
    // A checkpoint carries the count.
    let saved = s.save_state().unwrap();
    s.kept_warm_advection[0] = KeptWarmTotals::default();
    s.restore_state(&saved).unwrap();
    assert_eq!(s.kept_warm_advection_totals()[0], adv);
}

/// Air with a 10⁻⁶⁰ trace of a second gas, at rest. A trace drained to
/// −10⁻³⁰⁰ by rounding alone (set here in the Lagrangian density of one
/// cell; at rest no flux moves it) is a round-off zero: step 12 stores the
/// floor (10⁻¹⁰⁰ of the cell's mass density) with the trace's state before
/// the advection. The density field itself must hold it — a negative
/// density left there (with every other field from the restored values)
/// reached step 8 of the next step, whose exchange made the cell's
/// velocities NaN (the cook-off at 2 mm, 26.5 µs). A trace below the floor
/// (10⁻²⁰⁰ kg/m³ in another cell) goes to the floor the same way.
#[test]
fn step_12_stores_the_floor_for_a_round_off_zero_or_a_drained_trace() {
    let level = Level::new([0.0; 3], [0.05, 0.01, 0.01], [5, 1, 1], [1, 1, 1], GHOST).unwrap();
    let eos = vec![
        EosModel::IdealGas(IdealGas::new(1.4, 717.5, 1.0)),
        EosModel::IdealGas(IdealGas::new(1.3, 1000.0, 1.0)),
    ];
    let trace = 1e-60;
    let mut s = IceSolver::new(
        eos,
        level,
        std::array::from_fn(|_| IceBoundary::Symmetry),
        ExchangeCoefficients::uniform(2, 1e15, 0.0),
        IceOptions::default(),
        |_| CellState {
            pressure: 1e5,
            materials: vec![
                crate::material::MaterialState {
                    volume_fraction: 1.0 - trace,
                    density: 1.2,
                    velocity: [0.0; 3],
                },
                crate::material::MaterialState {
                    volume_fraction: trace,
                    density: 0.9,
                    velocity: [0.0; 3],
                },
            ],
        },
    )
    .unwrap();
    let dt = s.stable_dt().unwrap();
    s.compute_face_centred_velocities(dt);
    s.compute_pressure_increment(dt);
    s.compute_lagrangian_values(dt).unwrap();
    let patch = s.level.patches[0].clone();
    let c = patch.index_of_global([2, 0, 0]);
    let below = patch.index_of_global([4, 0, 0]);
    let l = &mut s.lag[0].data;
    let (e_before, v_before) = (l[NL + L_ENERGY][c], l[NL + L_VSP][c]);
    l[NL + L_RHO][c] = -1e-300;
    l[NL + L_RHO][below] = 1e-200;
    let floor = |x: usize| TRACE_FLOOR * (l[L_RHO][x] + l[NL + L_RHO][x].abs());
    let (floor_c, floor_below) = (floor(c), floor(below));
    s.advect_fluids(dt).unwrap();
    let d = &s.state[0].data;
    assert_eq!(d[NS + RHO][c], floor_c);
    assert_eq!(d[NS + ENERGY][c], e_before);
    assert_eq!(d[NS + VSP][c], v_before);
    assert_eq!(d[NS + THETA][c], floor_c * v_before);
    assert_eq!(d[NS + RHO][below], floor_below);
    assert!((floor_c / 1.2e-100 - 1.0).abs() < 1e-12, "{floor_c:e}");
    // The cells beside it keep their trace.
    for i in [1, 3] {
        let o = patch.index_of_global([i, 0, 0]);
        assert_eq!(d[NS + RHO][o], 0.9 * trace, "cell {i}");
    }
}
