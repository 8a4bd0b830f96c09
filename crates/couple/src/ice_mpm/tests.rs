//! Coupling checks of the ICE–MPM step: a gas-filled box at rest, a block
//! floating in a uniform stream, a piston driving a shock into air, and the
//! bookkeeping of mass, momentum and energy across both frames, and
//! particles leaving through an outflow face.

use super::cases::*;
use brisance_ice::IceBoundary;
use brisance_mpm::GridBoundary;

/// A closed 2D steel box (walls two cells thick) with air inside and out,
/// everything at rest at one atmosphere: after 60 steps no particle and no
/// cell moves faster than 1 mm/s (measured: see the assertion message).
/// The bound is 1/300 of the acoustic velocity p₀/(ρc) = 0.24 m/s of air
/// that a one-atmosphere imbalance would drive.
#[test]
fn a_gas_filled_box_at_rest_stays_at_rest() {
    let (solid, gas) = box_at_rest(60).unwrap();
    assert!(
        solid < 1e-3 && gas < 1e-3,
        "spurious speeds: solid {solid:e} m/s, gas {gas:e} m/s"
    );
}

/// A steel block and the air around it moving together at 20 m/s keep
/// that velocity: after 40 steps every particle's and every cell's x
/// velocity is 20 m/s, and the others zero, within 1 cm/s (0.05 % of the
/// stream). Measured: 1.5 mm/s on the particles, 4.5 mm/s in the air —
/// the noise of the particles crossing cells (docs/physics/couple/ice_mpm.md).
#[test]
fn a_block_floating_in_a_uniform_stream_keeps_its_velocity() {
    let (worst_solid, worst_gas) = floating_block(40).unwrap();
    assert!(
        worst_solid < 1e-2 && worst_gas < 1e-2,
        "deviation from 20 m/s: solid {worst_solid:e}, gas {worst_gas:e} m/s"
    );
}

/// The reduced piston case: a 1 cm steel piston at 100 m/s in a 1D air
/// tube of 1 mm cells. After 100 µs the shock (where p crosses the mean of
/// p₀ and the plateau) is within one cell of the exact position and the
/// piston, 6500 times heavier per area than the air it has swept, still
/// moves at 100 m/s within 0.5 %. The plateau pressure (+0.21 % against
/// the exact 1.498 bar at this resolution) and the piston's exact momentum
/// loss are asserted by `tests/ice_mpm_piston.rs` on the validation case's
/// own tube; `cargo xtask validate --only piston` measures them under
/// refinement.
#[test]
fn a_piston_drives_the_exact_shock() {
    let h = 1e-3;
    let up = 100.0;
    let x0 = 0.06;
    let mut s = build(&Setup {
        lower: [0.0; 3],
        upper: [0.2, h, h],
        cells: [200, 1, 1],
        solids: vec![([x0 - 0.01, 0.0, 0.0], [x0, h, h])],
        solid_velocity: [up, 0.0, 0.0],
        gas_velocity: [0.0; 3],
        ice_faces: std::array::from_fn(|_| IceBoundary::Outflow),
        mpm_faces: [GridBoundary::Free; 6],
    });
    let t = 1e-4;
    run(&mut s, t).unwrap();
    let m = piston_measure(&s, x0, up, t);
    assert!(
        m.shock_error_cells.abs() < 1.0 && (m.piston_velocity / up - 1.0).abs() < 5e-3,
        "{m:?}"
    );
    assert!(m.plateau > P0 && m.plateau_exact > P0 && m.shock > x0 && m.shock_exact > x0);
}

/// A closed tube (walls at both ends) with a steel piston at 100 m/s in
/// air: the bookkeeping of both frames, with the mass the coupled
/// equilibration moves in or out of the fluid booked, closes to round-off
/// for mass, and the total energy (fluid internal + kinetic, particles'
/// internal + kinetic) drifts by less than 0.5 % of the piston's kinetic
/// energy in 200 steps. The booked rescale itself stays below 1 % of the
/// air's mass (the assertion message gives the measured numbers). Until a
/// wave reaches a wall the walls push equally and oppositely, and the
/// total momentum of both frames is the start's to round-off — with the
/// momentum the solid's trace took in air cells returned to the air
/// (without it: −7.8e-7 of the piston's momentum in these 200 steps,
/// growing every step).
#[test]
fn mass_momentum_and_energy_close_across_both_frames() {
    let ClosedTube {
        mass,
        momentum,
        energy,
        rescaled,
        time,
    } = closed_tube(200).unwrap();
    assert!(time < 80e-6, "{time}");
    assert!(momentum.abs() <= 1e-12, "momentum closure {momentum:e}");
    assert!(
        mass.abs() <= 1e-12,
        "mass closure {mass:e} (rescale {rescaled:e} of the air)"
    );
    assert!(
        energy.abs() < 5e-3 && rescaled.abs() < 1e-2,
        "energy drift {energy:e} of the piston's kinetic energy, rescale {rescaled:e} of the air's mass"
    );
}

/// The fluid frame alone (the same tube, the steel Eulerian too, no
/// particles) keeps the total momentum to round-off until a wave reaches a
/// wall, as the coupled tube must.
#[test]
fn the_fluid_frame_alone_keeps_the_closed_tube_s_momentum() {
    use brisance_core::Solver;
    let (mut ice, _) = build_frames(&closed_tube_setup());
    let before = ice.conservation_totals().momentum[0];
    for _ in 0..200 {
        let dt = ice.stable_dt().unwrap();
        ice.advance(dt).unwrap();
    }
    assert!(ice.time() < 80e-6, "{}", ice.time());
    let change = ice.conservation_totals().momentum[0] - before;
    assert!(change.abs() <= 1e-12 * before, "{change:e} of {before:e}");
}

/// Particles that cross an outflow face leave the coupled run with their
/// mass, momentum and energy booked in the particles' totals (which the
/// pipeline's `conservation_totals`, and so `conservation.csv`, include):
/// a steel block at 200 m/s 2 mm from the x+ face of a 1D tube of 1 mm
/// cells, outflow for the air and the particles; after 20 µs some
/// particles have gone, the booked mass is exactly theirs, its momentum
/// is that mass at about 200 m/s, and the particles plus what left are the
/// start's mass to round-off.
#[test]
fn particles_leaving_through_an_outflow_face_are_booked() {
    use brisance_core::Solver;
    let h = 1e-3;
    let mut faces = [GridBoundary::Symmetry; 6];
    faces[1] = GridBoundary::Outflow;
    let mut s = build(&Setup {
        lower: [0.0; 3],
        upper: [0.04, h, h],
        cells: [40, 1, 1],
        solids: vec![([0.03, 0.0, 0.0], [0.038, h, h])],
        solid_velocity: [200.0, 0.0, 0.0],
        gas_velocity: [0.0; 3],
        ice_faces: std::array::from_fn(|_| IceBoundary::Outflow),
        mpm_faces: faces,
    });
    let (n0, m0) = {
        let ps = s.mpm().particles();
        (ps.len(), ps.mass.iter().sum::<f64>())
    };
    while s.time() < 20e-6 {
        let dt = s.stable_dt().unwrap();
        s.advance(dt).unwrap();
    }
    let ps = s.mpm().particles();
    let (n1, m1) = (ps.len(), ps.mass.iter().sum::<f64>());
    assert!(n1 < n0 && n1 > 0, "{n0} → {n1} particles");
    let gone = s.mpm().outflow_totals();
    assert!(
        (gone.mass - (m0 - m1)).abs() <= 1e-12 * m0,
        "{} vs {}",
        gone.mass,
        m0 - m1
    );
    let v = gone.momentum[0] / gone.mass;
    assert!((v - 200.0).abs() < 10.0, "{gone:?}");
    assert!(gone.energy >= 0.5 * gone.mass * v * v * 0.99, "{gone:?}");
    let particles = s.mpm().conservation_totals().mass;
    assert!((particles - m0).abs() <= 1e-12 * m0, "{particles} vs {m0}");
}

/// The run summary's limit is the particles' when their step is the
/// smaller (a steel block at 200 m/s in air at rest: steel's sound speed
/// against air's) and names the particle.
#[test]
fn the_time_step_limit_is_the_smaller_step_s_part() {
    use brisance_core::Solver;
    let h = 1e-3;
    let s = build(&Setup {
        lower: [0.0; 3],
        upper: [0.04, h, h],
        cells: [40, 1, 1],
        solids: vec![([0.03, 0.0, 0.0], [0.038, h, h])],
        solid_velocity: [200.0, 0.0, 0.0],
        gas_velocity: [0.0; 3],
        ice_faces: std::array::from_fn(|_| IceBoundary::Outflow),
        mpm_faces: [GridBoundary::Symmetry; 6],
    });
    let (ice, mpm) = (s.ice().stable_dt().unwrap(), s.mpm().stable_dt().unwrap());
    assert!(mpm < ice, "{mpm:e} {ice:e}");
    assert_eq!(s.stable_dt().unwrap(), mpm);
    let limit = s.time_step_limit().unwrap();
    assert_eq!(Some(limit.clone()), s.mpm().time_step_limit());
    assert!(
        limit.starts_with("MPM particle ") && limit.contains("|v| 200 m/s"),
        "{limit}"
    );
}
