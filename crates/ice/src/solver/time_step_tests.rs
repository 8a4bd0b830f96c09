use super::*;
use brisance_eos::{EosModel, IdealGas};

/// Two cells of air beside a second gas at θ = `theta` moving at `u`
/// (m/s), the second gas Lagrangian or not.
fn solver_at(theta: f64, lagrangian: bool, u: f64) -> IceSolver<EosModel> {
    let air = EosModel::IdealGas(IdealGas::new(1.4, 717.5, 1.0));
    let level = Level::new([0.0; 3], [2.0, 1.0, 1.0], [2, 1, 1], [1, 1, 1], GHOST).unwrap();
    let init = |_| CellState {
        pressure: 1e5,
        materials: vec![
            crate::material::MaterialState {
                volume_fraction: 1.0 - theta,
                density: 1.2,
                velocity: [0.0; 3],
            },
            crate::material::MaterialState {
                volume_fraction: theta,
                density: 1.2,
                velocity: [u, 0.0, 0.0],
            },
        ],
    };
    let mut s = IceSolver::new(
        vec![air; 2],
        level,
        std::array::from_fn(|_| IceBoundary::Symmetry),
        ExchangeCoefficients::uniform(2, 1e15, 0.0),
        IceOptions::default(),
        init,
    )
    .unwrap();
    if lagrangian {
        s.set_lagrangian(&[false, true]).unwrap();
    }
    s
}

/// A collapsed step names the cell whose CFL rate set it, the material
/// whose speed did, and that material's state.
#[test]
fn a_collapsed_step_names_the_cell_and_the_material() {
    let mut s = solver_at(0.5, false, 0.0);
    let err = s.stable_dt();
    assert!(err.is_ok(), "{err:?}");
    // Material 2 of the second cell at 10^15 m/s: Δt = 0.4 · 1 m / 10^15 m/s.
    let state = &mut s.state[0].data;
    let c = s.level.patches[0].index_of_global([1, 0, 0]);
    state[NS + VEL][c] = 1e15;
    let msg = s.stable_dt().unwrap_err().to_string();
    assert!(
        msg.contains("cell [1, 0, 0]")
            && msg.contains("set by material 2")
            && msg.contains("u = (1e15"),
        "{msg}"
    );
}

/// The run summary's limit names the cell whose CFL rate sets the step
/// and the material whose speed does.
#[test]
fn the_time_step_limit_names_the_fastest_cell() {
    let mut s = solver_at(0.5, false, 0.0);
    let c = s.level.patches[0].index_of_global([1, 0, 0]);
    s.state[0].data[NS + VEL][c] = 3e4;
    let limit = s.time_step_limit().unwrap();
    assert!(
        limit.starts_with("ICE cell [1, 0, 0] (centre [1.5, 0.5, 0.5] m)")
            && limit.contains("set by material 2")
            && limit.contains("u = (3e4"),
        "{limit}"
    );
}

/// [`solver_at`] at 30 km/s.
fn solver(theta: f64, lagrangian: bool) -> IceSolver<EosModel> {
    solver_at(theta, lagrangian, 3e4)
}

/// In a coupled run a Lagrangian material's velocity sets Δt where its
/// volume fraction is at least THERMAL_TRACE and not below it (eq 18
/// of light nodes); a fluid trace's velocity always does.
#[test]
fn a_lagrangian_trace_does_not_set_the_time_step() {
    let air_only = solver_at(1e-5, false, 0.0).stable_dt().unwrap();
    let fast = solver(0.5, false).stable_dt().unwrap();
    assert!(fast < 0.1 * air_only, "{fast} {air_only}");
    assert_eq!(solver(1e-5, true).stable_dt().unwrap(), air_only);
    assert_eq!(solver(1e-5, false).stable_dt().unwrap(), fast);
    assert_eq!(solver(2.0 * THERMAL_TRACE, true).stable_dt().unwrap(), fast);
}

/// A fluid that claims its volume only by its heat — its mass would
/// fill less than THERMAL_TRACE of the cell at the cell's pressure and
/// the particles' temperature — takes the particles' temperature, in
/// a cell the particles do not fill and with a mass share far above
/// MASS_TRACE; a hundred times the mass (4.3·10⁻³ of the cell at
/// 300 K: ρ = p/((γ − 1) c_v T) = 1.1614 kg/m³) keeps its own.
#[test]
fn a_fluid_claiming_volume_by_its_heat_alone_is_a_trace() {
    let s = solver_at(0.5, true, 0.0);
    let params = solver_params!(s);
    let n = 2;
    let check = |mass: f64| -> (bool, f64) {
        let mut vals = vec![0.0; n * NS + 1];
        vals[n * NS] = 1e5;
        // The gas at θ = 9·10⁻⁴, the particles at 0.9991 (not full).
        vals[RHO] = mass;
        vals[VSP] = 9e-4 / mass;
        vals[NS + RHO] = 1.2 * 0.9991;
        vals[NS + VSP] = 1.0 / 1.2;
        let rho = [vals[RHO], vals[NS + RHO]];
        let mut temp = [2.5e7, 300.0];
        let mut thermal = [false; MAX_MATERIALS];
        trace_temperature(&params, &vals, &rho, &mut temp, &mut thermal);
        (thermal[0], temp[0])
    };
    assert_eq!(check(5e-5), (true, 300.0));
    assert_eq!(check(5e-3), (false, 2.5e7));
}

/// The time step asks the same of a fluid in a cell with particles: one
/// whose mass (5·10⁻⁵ kg/m³) would fill 4·10⁻⁵ of the cell at the cell's
/// pressure and the particles' temperature sets its velocity, not its
/// sound speed (here 10⁶ m/s), and Δt is the other cell's, 0.4 · 1 m / c
/// of the air at rest; a hundred times the mass (4·10⁻³ of the cell) sets
/// Δt = 0.4 · 1 m / 10⁶ m/s.
#[test]
fn a_fluid_claiming_volume_by_its_heat_alone_does_not_set_the_step() {
    let dt_with = |mass: f64| {
        let mut s = solver_at(0.5, true, 0.0);
        let c = s.level.patches[0].index_of_global([1, 0, 0]);
        let d = &mut s.state[0].data;
        let c_air = d[SOUND][c];
        d[RHO][c] = mass;
        d[THETA][c] = 9e-4;
        d[VSP][c] = 9e-4 / mass;
        d[SOUND][c] = 1e6;
        d[NS + RHO][c] = 1.2 * 0.9991;
        d[NS + THETA][c] = 0.9991;
        (s.stable_dt().unwrap(), c_air)
    };
    let (dt, c_air) = dt_with(5e-5);
    assert!(
        (c_air - (1.4f64 * 1e5 / 1.2).sqrt()).abs() < 1e-9 * c_air,
        "{c_air}"
    );
    assert!((dt / (0.4 / c_air) - 1.0).abs() < 1e-12, "{dt} {c_air}");
    let (dt, _) = dt_with(5e-3);
    assert!((dt / (0.4 / 1e6) - 1.0).abs() < 1e-12, "{dt}");
}

/// The rule by hand: traces of a coupled run only; a fluid trace keeps
/// its velocity, not its sound speed; NaN counts.
#[test]
fn trace_speeds_by_hand() {
    let t = 0.5 * THERMAL_TRACE;
    assert_eq!(cfl_speed(false, false, t, 1.0, -3.0, 5.0), 8.0);
    assert_eq!(cfl_speed(true, false, t, 1.0, -3.0, 5.0), 3.0);
    assert_eq!(cfl_speed(true, true, t, 1.0, -3.0, 5.0), 0.0);
    assert_eq!(cfl_speed(true, true, THERMAL_TRACE, 1.0, -3.0, 5.0), 8.0);
    assert_eq!(cfl_speed(true, false, THERMAL_TRACE, 1.0, -3.0, 5.0), 8.0);
    assert_eq!(cfl_speed(true, true, f64::NAN, 1.0, -3.0, 5.0), 8.0);
    // A fluid that claims volume but holds almost no mass (below
    // MASS_TRACE of the cell's) is a trace too; above it, not.
    assert_eq!(
        cfl_speed(true, false, 0.5, 0.5 * MASS_TRACE, -3.0, 5.0),
        3.0
    );
    assert_eq!(
        cfl_speed(true, false, 0.5, 2.0 * MASS_TRACE, -3.0, 5.0),
        8.0
    );
    assert_eq!(cfl_speed(false, false, 0.5, 0.0, -3.0, 5.0), 8.0);
}

/// With the implicit pressure a state at rest has no limit on its step
/// (the acoustic one is off): Δt is infinite unless `max_dt` bounds it; a
/// `max_dt` that is not > 0 is refused by name.
#[test]
fn max_dt_bounds_the_implicit_step_at_rest() {
    let with = |max_dt: f64| {
        let air = EosModel::IdealGas(IdealGas::new(1.4, 717.5, 1.0));
        let level = Level::new([0.0; 3], [2.0, 1.0, 1.0], [2, 1, 1], [1, 1, 1], GHOST).unwrap();
        IceSolver::new(
            vec![air],
            level,
            std::array::from_fn(|_| IceBoundary::Symmetry),
            ExchangeCoefficients::uniform(1, 1e15, 0.0),
            IceOptions {
                pressure: PressureSolve::Implicit(Default::default()),
                max_dt,
                ..Default::default()
            },
            |_| CellState {
                pressure: 1e5,
                materials: vec![crate::material::MaterialState {
                    volume_fraction: 1.0,
                    density: 1.2,
                    velocity: [0.0; 3],
                }],
            },
        )
    };
    assert_eq!(
        with(f64::INFINITY).unwrap().stable_dt().unwrap(),
        f64::INFINITY
    );
    assert_eq!(with(1e-3).unwrap().stable_dt().unwrap(), 1e-3);
    for bad in [0.0, -1.0, f64::NAN] {
        let err = with(bad).unwrap_err().to_string();
        assert!(err.contains("max_dt"), "{err}");
    }
}
