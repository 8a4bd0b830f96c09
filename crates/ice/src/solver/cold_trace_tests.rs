use super::*;
use brisance_eos::{EosModel, IdealGas, Murnaghan};

/// The QM-100-like Murnaghan reactant of the cold trace.
fn trace() -> Murnaghan {
    Murnaghan {
        n: 7.0,
        kappa: 1e-10,
        rho0: 1260.0,
        cv: 1500.0,
        t_ref: 298.0,
    }
}

/// Air (γ 1.4) and the trace.
fn air_and_trace() -> Vec<EosModel> {
    let air = IdealGas::new(1.4, 717.5, 1.0);
    vec![EosModel::IdealGas(air), EosModel::Murnaghan(trace())]
}

/// Air at 3000 kg/m³ and 300 K (θ 0.999) beside the trace at ρ₀ and
/// 1 K (θ 10⁻³), a start pressure of 10⁵ Pa: the state-group values of
/// one cell.
fn cold_trace_cell() -> Vec<f64> {
    let mut vals = vec![0.0; 2 * NS + 1];
    let (rho_air, rho_t) = (3000.0, 1260.0);
    vals[RHO] = 0.999 * rho_air;
    vals[VSP] = 1.0 / rho_air;
    vals[ENERGY] = 717.5 * 300.0;
    vals[THETA] = 0.999;
    vals[NS + RHO] = 1e-3 * rho_t;
    vals[NS + VSP] = 1.0 / rho_t;
    vals[NS + ENERGY] = trace().specific_internal_energy_from_temperature(rho_t, 1.0);
    vals[NS + THETA] = 1e-3;
    vals[2 * NS] = 1e5;
    vals
}

/// Step 2 on one cell: a Murnaghan trace at 1 K (θ = 10⁻³, near ρ₀)
/// beside air compressed to 2.6·10⁸ Pa. Compressed at fixed e its cold
/// energy rises by p²κ/(2ρ) ≈ 2.7 kJ/kg, which would put it at about
/// −0.8 K; it keeps the 1 K the equilibration found its volume at, with
/// e = e(ρ_new, 1 K), and the air's state is the plain one.
#[test]
fn a_cold_trace_compressed_in_step_2_keeps_its_temperature() {
    let (trace, eos) = (trace(), air_and_trace());
    let level = Level::new([0.0; 3], [1.0; 3], [1, 1, 1], [1, 1, 1], GHOST).unwrap();
    let exchange = ExchangeCoefficients::uniform(2, 1e15, 0.0);
    let params = make_params(
        &eos,
        &[],
        &exchange,
        IceOptions::default(),
        &level,
        &[],
        0.0,
    );
    let mut vals = cold_trace_cell();
    let (rho_t, t_air) = (1260.0, 300.0);
    let e_old = vals[NS + ENERGY];
    let (_, kept) = equilibrate_cell(&params, &mut vals).unwrap();
    let p = vals[2 * NS];
    assert!(p > 2.5e8 && p < 2.7e8, "p = {p:e}");
    let rho_new = 1.0 / vals[NS + VSP];
    assert!(rho_new > 1.02 * rho_t, "trace compressed: {rho_new}");
    // Fixed e would have taken it below 0 K:
    let fixed_e = trace.temperature(
        rho_new,
        trace.specific_internal_energy_from_temperature(rho_t, 1.0),
    );
    assert!(fixed_e < 0.0, "{fixed_e}");
    assert!(
        (vals[NS + TEMP] - 1.0).abs() < 1e-9,
        "T = {}",
        vals[NS + TEMP]
    );
    let e = trace.specific_internal_energy_from_temperature(rho_new, 1.0);
    assert!(
        (vals[NS + ENERGY] - e).abs() <= 1e-9 * e.abs(),
        "{} {e}",
        vals[NS + ENERGY]
    );
    // The air: e kept, T = e/c_v.
    assert_eq!(vals[ENERGY], 717.5 * t_air);
    assert!((vals[TEMP] - t_air).abs() < 1e-9);
    // The rule fired for the trace alone, adding ρ_trace (e − e_old)
    // per unit volume (uncoupled: the trace keeps its mass, 1.26 kg/m³).
    assert_eq!(kept.fired[..2], [false, true]);
    assert_eq!(kept.energy_density[0], 0.0);
    let added = 1e-3 * rho_t * (vals[NS + ENERGY] - e_old);
    assert!(added > 0.0, "{added}");
    assert_eq!(kept.energy_density[1], added);
}

/// The solver books the rule's firings and energy per material: the
/// same cell through `compute_equilibration_pressure` on a 2 × 1 × 1
/// grid of 1 m³ cells adds twice the one-cell energy, two firings.
#[test]
fn the_solver_books_the_cold_rule_per_material() {
    let eos = air_and_trace();
    let level = Level::new([0.0; 3], [2.0, 1.0, 1.0], [2, 1, 1], [1, 1, 1], GHOST).unwrap();
    let exchange = ExchangeCoefficients::uniform(2, 1e15, 0.0);
    // Built at a common pressure, then given the test's cell state.
    let init = |_| CellState {
        pressure: 1e5,
        materials: vec![
            crate::material::MaterialState {
                volume_fraction: 0.999,
                density: 1.2,
                velocity: [0.0; 3],
            },
            crate::material::MaterialState {
                volume_fraction: 1e-3,
                // Murnaghan at 1e5 Pa: ρ₀ (1 + nκp)^{1/n}.
                density: 1260.0 * (1.0 + 7.0 * 1e-10 * 1e5_f64).powf(1.0 / 7.0),
                velocity: [0.0; 3],
            },
        ],
    };
    let mut s = IceSolver::new(
        eos,
        level,
        std::array::from_fn(|_| IceBoundary::Symmetry),
        exchange,
        IceOptions::default(),
        init,
    )
    .unwrap();
    let cell = cold_trace_cell();
    for pf in &mut s.state {
        for (field, &v) in pf.data.iter_mut().zip(&cell) {
            field.fill(v);
        }
    }
    assert_eq!(s.kept_warm_totals(), [KeptWarmTotals::default(); 2]);
    s.compute_equilibration_pressure().unwrap();
    let t = s.kept_warm_totals();
    assert_eq!((t[0].firings, t[0].energy), (0, 0.0));
    assert_eq!(t[1].firings, 2);
    // One cell by hand, as the test above.
    let params = make_params(
        &s.eos,
        &[],
        &s.exchange,
        IceOptions::default(),
        &s.level,
        &[],
        0.0,
    );
    let mut vals = cold_trace_cell();
    let (_, kept) = equilibrate_cell(&params, &mut vals).unwrap();
    assert_eq!(t[1].energy, kept.energy_density[1] + kept.energy_density[1]);
    // A checkpoint carries the totals: a fresh solver restored from it
    // reports them.
    let (saved, totals) = (s.save_state().unwrap(), s.kept_warm_totals().to_vec());
    s.kept_warm = [KeptWarmTotals::default(); MAX_MATERIALS];
    s.rescaled = ConservationTotals {
        mass: 1.0,
        ..Default::default()
    };
    s.restore_state(&saved).unwrap();
    assert_eq!(s.kept_warm_totals(), &totals[..]);
    assert_eq!(s.rescaled_totals(), ConservationTotals::default());
}

/// One coupled cell for `lagrangian_cell`: fluids (ideal gases γ 1.4,
/// c_v 717.5, at 2000 K and ρ_micro 1.2) of the given macroscopic
/// densities and volume fractions, then a Lagrangian material (γ 1.67,
/// c_v 3115, ρ_micro 1000, 300 K) filling the rest; all at rest, p 10⁵ Pa.
/// Returns the equations of state and the state values, one cell each.
fn coupled_cell(fluids: &[(f64, f64)]) -> (Vec<EosModel>, Vec<Vec<f64>>) {
    let air = EosModel::IdealGas(IdealGas::new(1.4, 717.5, 1.0));
    let solid = EosModel::IdealGas(IdealGas::new(1.67, 3115.0, 1.0));
    let n = fluids.len() + 1;
    let mut eos = vec![air; fluids.len()];
    eos.push(solid);
    let mut vals = vec![0.0; n * NS + 1];
    let theta_solid = 1.0 - fluids.iter().map(|f| f.1).sum::<f64>();
    for r in 0..n {
        let b = r * NS;
        let (rho, theta, rho_micro, t) = match fluids.get(r) {
            Some(&(rho, theta)) => (rho, theta, 1.2, 2000.0),
            None => (theta_solid * 1000.0, theta_solid, 1000.0, 300.0),
        };
        vals[b + RHO] = rho;
        vals[b + THETA] = theta;
        vals[b + VSP] = 1.0 / rho_micro;
        vals[b + TEMP] = t;
        vals[b + ENERGY] = eos[r].specific_internal_energy_from_temperature(rho_micro, t);
        vals[b + SOUND] = eos[r].sound_speed(rho_micro, vals[b + ENERGY]);
    }
    vals[n * NS] = 1e5;
    (eos, vals.into_iter().map(|v| vec![v]).collect())
}

/// Steps 8–11 on [`coupled_cell`] with the face pressure work `work`
/// (J/m³) into a cell at rest with no volume change: the Lagrangian
/// values and the hold's booking.
fn lagrangian_values(
    eos: &[EosModel],
    d: &[Vec<f64>],
    work: f64,
) -> ([[f64; NL]; MAX_MATERIALS], KeptWarmCell) {
    let n = eos.len();
    let level = Level::new([0.0; 3], [1.0; 3], [1, 1, 1], [1, 1, 1], GHOST).unwrap();
    let exchange = ExchangeCoefficients::uniform(n, 1e15, 0.0);
    let mut lagrangian = vec![false; n];
    lagrangian[n - 1] = true;
    let params = make_params(
        eos,
        &[],
        &exchange,
        IceOptions::default(),
        &level,
        &lagrangian,
        0.0,
    );
    let cell = CellInputs {
        p: 1e5,
        divergence: 0.0,
        grad: [0.0; 3],
        pressure_work: Some(work),
        slip_normal: None,
    };
    lagrangian_cell(&params, d, 0, cell, &[], 1e-6).unwrap()
}

/// A fluid trace in a cell the particles fill (θ = 10⁻⁵, held at their
/// 300 K by step 2) stays held in the Lagrangian values: e = c_v · 300 K,
/// not the cell's residual. Without the hold the face work of 10³ J/m³
/// went to it, the only Eulerian material: +8.3·10⁷ J/kg on its
/// 1.2·10⁻⁵ kg/m³. The residual, left unplaced, and the trace's change
/// ρ c_v (300 − 2000) K are booked: −10³ − 14.637 J/m³.
#[test]
fn a_held_trace_stays_held_through_the_lagrangian_step() {
    let (eos, d) = coupled_cell(&[(1.2e-5, 1e-5)]);
    let (out, kept) = lagrangian_values(&eos, &d, 1e3);
    assert_eq!(out[0][L_ENERGY], 717.5 * 300.0);
    assert_eq!(out[0][L_RHO], 1.2e-5);
    assert_eq!(kept.fired[..2], [true, false]);
    let expected = -1e3 + 1.2e-5 * 717.5 * (300.0 - 2000.0);
    assert!(
        (kept.energy_density[0] - expected).abs() < 1e-12 * expected.abs(),
        "{} {expected}",
        kept.energy_density[0]
    );
    // The cell's energy is the start's, plus the work, plus the booking.
    let energy = |rho: f64, e: f64| rho * e;
    let start = energy(d[RHO][0], d[ENERGY][0]) + energy(d[NS + RHO][0], d[NS + ENERGY][0]);
    let end = energy(out[0][L_RHO], out[0][L_ENERGY]) + energy(out[1][L_RHO], out[1][L_ENERGY]);
    let gap = end - (start + 1e3 + kept.energy_density[0]);
    assert!(gap.abs() < 1e-9 * start, "{gap:e}");
}

/// Beside a fluid that is not a trace (θ 0.3) the held trace (a mass
/// share of 10⁻¹³) takes nothing of the residual: the other fluid takes
/// all 10³ J/m³, and only the trace's own change is booked.
#[test]
fn the_closure_residual_goes_to_the_fluids_that_are_not_held() {
    let (eos, d) = coupled_cell(&[(1e-10, 1e-5), (0.36, 0.3)]);
    let (out, kept) = lagrangian_values(&eos, &d, 1e3);
    assert_eq!(out[0][L_ENERGY], 717.5 * 300.0);
    let gained = 0.36 * (out[1][L_ENERGY] - d[NS + ENERGY][0]);
    assert!((gained / 1e3 - 1.0).abs() < 1e-12, "{gained}");
    assert_eq!(kept.fired[..3], [true, false, false]);
    let own = 1e-10 * 717.5 * (300.0 - 2000.0);
    assert!(
        (kept.energy_density[0] - own).abs() < 1e-9 * own.abs(),
        "{} {own}",
        kept.energy_density[0]
    );
}
