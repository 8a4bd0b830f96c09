//! V-BAR, reduced: the first mode of an elastic bar in MPM (MUSL, 50 cells,
//! 10 periods). Targets from the validation plan: period within 1 %, total
//! energy drift ≤ 1 % over 10 periods. `cargo xtask validate` runs 200
//! cells with every update scheme.

use brisance::mpm::UpdateScheme;
use brisance::verification::cases::v_bar;

#[test]
fn v_bar_period_within_one_percent_and_energy_drift_within_one_percent() {
    let r = v_bar(50, 10.0, UpdateScheme::Musl).unwrap();
    let period_error = (r.period - r.exact_period).abs() / r.exact_period;
    assert!(
        period_error < 0.01,
        "period {} vs exact {}",
        r.period,
        r.exact_period
    );
    assert!(r.energy_drift <= 0.01, "energy drift {}", r.energy_drift);
}
