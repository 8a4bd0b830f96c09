//! V-TAYLOR: the Taylor impact of an OFHC copper rod (L₀ 25.4 mm, D₀
//! 7.62 mm, 190 m/s) on a rigid wall, 3D quarter rod, Johnson–Cook copper
//! (`configs/taylor3d.ron`, `brisance::verification::taylor`). Target: final
//! length and foot diameter within 5 % of the test of Johnson & Cook (1983).
//! `cargo xtask validate` runs the same case and reports both resolutions.

use brisance::verification::taylor::{
    bilinear_bar, bilinear_bar_case, taylor_case, CONFIG_CELLS_ACROSS_RADIUS,
    JOHNSON_COOK_1983_OFHC_190,
};

/// The first 10 µs on a coarse grid (3 cells across the radius): the rod
/// shortens and spreads at the wall, its mass is the generated mass, no
/// particle leaves, and the total energy only falls, by about the kinetic
/// energy of the particles whose velocity the wall nodes stop at impact:
/// with 2 particles per cell per direction the first two layers (z = Δx/4
/// and 3Δx/4, inside the reach Δx + Δx/4 of the wall nodes), 2 of the 40
/// layers of the rod, 5 % (measured 4.97 %; 2.23 % at 6 cells, first order
/// in Δx). The wall does no work; the loss is that of the impulsive
/// kinematic contact, as for a finite-element node layer held on a wall.
#[test]
fn v_taylor_reduced_first_ten_microseconds_shorten_and_spread_the_rod() {
    let test = JOHNSON_COOK_1983_OFHC_190;
    let r = taylor_case(3, 10e-6, &[]).unwrap();
    let s = &r.shape;
    // By 10 µs the wall has stopped the foot; the rear still moves at
    // about 190 m/s, so the rod is at most 1.9 mm shorter.
    assert!(
        s.length < test.length && s.length > test.length - 190.0 * 10e-6,
        "length {} m",
        s.length
    );
    assert!(s.diameter > test.diameter, "diameter {} m", s.diameter);
    assert!(
        s.widest_at < 0.25 * test.length,
        "widest at z = {}",
        s.widest_at
    );
    assert!(r.kinetic_energy_ratio < 1.0);
    assert!(
        r.energy_change < 0.0 && r.energy_change > -0.055,
        "energy change {}",
        r.energy_change
    );
    assert!(r.max_plastic_strain > 0.0);
}

/// Not met: L_f 17.30 mm (+6.78 %) and D_f 14.64 mm (+7.90 %) at 12 cells
/// across the radius (docs/validation.md); docs/physics/mpm/taylor.md finds
/// no solver error behind it (the bilinear bar below lands on its
/// reference) and puts it on the Johnson–Cook model against this test.
#[test]
#[ignore = "known failing (Lf +6.78 %, Df +7.90 %) and slow (minutes); cargo xtask validate --only taylor reports it"]
fn v_taylor_final_length_and_diameter_within_five_percent_of_the_test() {
    let test = JOHNSON_COOK_1983_OFHC_190;
    let r = taylor_case(CONFIG_CELLS_ACROSS_RADIUS, 80e-6, &[]).unwrap();
    let length_error = (r.shape.length - test.final_length()) / test.final_length();
    let diameter_error = (r.shape.diameter - test.final_diameter()) / test.final_diameter();
    assert!(
        r.kinetic_energy_ratio <= 0.01,
        "not at rest: KE/KE0 = {}",
        r.kinetic_energy_ratio
    );
    assert!(
        length_error.abs() <= 0.05,
        "Lf {} mm vs {} mm: {:+.2} %",
        1e3 * r.shape.length,
        1e3 * test.final_length(),
        100.0 * length_error
    );
    assert!(
        diameter_error.abs() <= 0.05,
        "Df {} mm vs {} mm: {:+.2} %",
        1e3 * r.shape.diameter,
        1e3 * test.final_diameter(),
        100.0 * diameter_error
    );
}

/// The solver without the Johnson–Cook model: the elastic, linearly
/// hardening copper bar (Wilkins & Guinan 1973, Kamoulakos 1990) at 8 cells
/// across the radius with the shipped solver options (contiguous-particle
/// GIMP, MUSL, 2 particles per cell per direction). Its finite-element
/// reference solutions end 21.42–21.47 mm long with a mushroom radius of
/// 7.0–7.13 mm: the length within 1 % of 21.45 mm, the radius within 4 % of
/// 7.07 mm (the radius measure stands up to half a particle width, 0.1 mm
/// or 1.4 %, outside a smooth surface). Measured 21.466 mm and 7.252 mm;
/// with uGIMP the radius is 5.81 mm (−18 %).
#[test]
#[ignore = "slow (about 2 minutes in release); cargo xtask validate --only taylor reports it"]
fn bilinear_bar_ends_at_the_reference_length_and_mushroom_radius() {
    use bilinear_bar as b;
    let r = bilinear_bar_case(8, &[]).unwrap();
    let (lf, rf) = (r.shape.length, 0.5 * r.shape.diameter);
    assert!(
        (lf / b::REFERENCE_LENGTH - 1.0).abs() <= 0.01,
        "L_f {} mm",
        1e3 * lf
    );
    assert!(
        (rf / b::REFERENCE_RADIUS - 1.0).abs() <= 0.04,
        "mushroom radius {} mm",
        1e3 * rf
    );
}
