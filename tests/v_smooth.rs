//! The smooth verification case: a density sine wave advected once around a
//! periodic domain. The scheme is second order, so the observed order must
//! reach 1.9 (validation target) with the adaptive viscosity switched on.

use brisance::fdm::ArtificialViscosity;
use brisance::verification::cases::{advected_sine_l1, observed_orders};

#[test]
fn advected_sine_converges_at_second_order_with_adaptive_viscosity() {
    let cells = [50, 100, 200];
    let errors: Vec<f64> = cells
        .iter()
        .map(|&n| advected_sine_l1(n, ArtificialViscosity::Adaptive, 0.8).unwrap())
        .collect();
    let orders = observed_orders(&cells, &errors);
    assert!(orders[1] >= 1.9, "errors {errors:?}, orders {orders:?}");
}

#[test]
fn bare_lax_wendroff_is_second_order_too() {
    let cells = [50, 100, 200];
    let errors: Vec<f64> = cells
        .iter()
        .map(|&n| advected_sine_l1(n, ArtificialViscosity::Off, 0.8).unwrap())
        .collect();
    let orders = observed_orders(&cells, &errors);
    assert!(
        orders.iter().all(|&p| p >= 1.9),
        "errors {errors:?}, orders {orders:?}"
    );
}
