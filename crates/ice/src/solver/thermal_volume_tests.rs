use super::*;
use brisance_eos::IdealGas;

/// Eq 31's θβΔT for an ideal gas (β = 1/T): first order for a small
/// change, the exact θ(T₁/T₀ − 1) at constant pressure for a large one
/// (a trace cooled from 19 000 to 300 K keeps 300/19 000 of its
/// volume, where the first-order form would give it −0.98 θ + ...).
#[test]
fn an_ideal_gas_trace_keeps_the_exact_volume_ratio() {
    let gas = IdealGas::air();
    let (p, theta) = (1e8, 1e-6);
    // Small: |βΔT| = 0.5/1000 ≤ 0.01, the first-order form.
    let small = thermal_volume_change(&gas, p, 1000.0, 1000.5, theta).unwrap();
    let beta = gas.thermal_expansivity(p, 1000.5).unwrap();
    assert_eq!(small, theta * beta * 0.5);
    assert!((small / (theta * 0.5 / 1000.5) - 1.0).abs() < 1e-12);
    // Large: the ratio of the densities at (p, T₀) and (p, T₁).
    let large = thermal_volume_change(&gas, p, 19_000.0, 300.0, theta).unwrap();
    let want = theta * (300.0 / 19_000.0 - 1.0);
    assert!(
        (large / want - 1.0).abs() < 1e-12,
        "{large:e} against {want:e}"
    );
    assert!(theta + large > 0.0);
    // The first-order form at the cooled temperature would have
    // removed far more than the trace holds.
    let linear = theta * gas.thermal_expansivity(p, 300.0).unwrap() * (300.0 - 19_000.0);
    assert!(theta + linear < 0.0, "{linear:e}");
}
