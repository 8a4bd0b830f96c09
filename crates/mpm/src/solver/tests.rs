//! Tests of the explicit MPM solver: the V-BAR validation case, exact
//! conservation and motion properties, determinism across thread counts and
//! checkpoints, outflow bookkeeping and setup errors.

use super::*;
use crate::{fill_shape, FillSpec, ParticleInit, Shape};
use brisance_constitutive::{Hypoelastic, ObjectiveRate, PressureModel};
use brisance_core::Solver;

fn hypoelastic(bulk_modulus: f64, shear_modulus: f64) -> MaterialModel {
    MaterialModel::Hypoelastic(Hypoelastic {
        shear_modulus,
        pressure: PressureModel::Linear { bulk_modulus },
        rate: ObjectiveRate::Jaumann,
    })
}

fn fill(
    particles: &mut Particles,
    level: &Level,
    lo: [f64; 3],
    hi: [f64; 3],
    density: f64,
    velocity: [f64; 3],
    material: u16,
) {
    fill_shape(
        particles,
        &level.geometry,
        &FillSpec {
            shape: Shape::Box { min: lo, max: hi },
            ppc: 2,
            density,
            material: MaterialId(material),
            velocity,
            temperature: 300.0,
            specific_internal_energy: 0.0,
        },
    )
    .unwrap();
}

/// 8 × 8 × 1 cells of 1/8 m (dyadic, so the transfers of dyadic data are
/// exact), with a soft solid.
fn dyadic_level() -> Level {
    Level::new([0.0; 3], [1.0, 1.0, 1.0], [8, 8, 1], [1, 1, 1], 0).unwrap()
}

fn soft() -> MaterialModel {
    hypoelastic(1.0e7, 5.0e6)
}

/// The soft solid's particles `ps` on `level`, every face `Free` but
/// face `face` (in the order of [`FACE_NAMES`]), which is `bc`.
fn soft_with_face(level: Level, ps: Particles, face: usize, bc: GridBoundary) -> MpmSolver {
    let mut boundaries = [GridBoundary::Free; 6];
    boundaries[face] = bc;
    MpmSolver::new(
        level,
        vec![soft()],
        ps,
        MpmOptions {
            boundaries,
            ..Default::default()
        },
    )
    .unwrap()
}

// V-BAR lives in the workspace's validation cases (tests/v_bar.rs,
// brisance::verification::cases::v_bar), shared with `cargo xtask validate`.

// ------------------------------------------------- exact motion properties

#[test]
fn uniform_velocity_block_in_free_space_keeps_velocity_and_momentum_exactly() {
    for scheme in [UpdateScheme::Usf, UpdateScheme::Usl, UpdateScheme::Musl] {
        let level = dyadic_level();
        let mut ps = Particles::new(0);
        let v = [0.5, -0.25, 0.0];
        fill(
            &mut ps,
            &level,
            [0.25, 0.5, 0.0],
            [0.5, 0.75, 1.0],
            1024.0,
            v,
            0,
        );
        let x0 = ps.position.clone();
        let mut solver = MpmSolver::new(
            level,
            vec![soft()],
            ps,
            MpmOptions {
                scheme,
                ..Default::default()
            },
        )
        .unwrap();
        let p0 = solver.conservation_totals().momentum;
        let dt = 1.0 / 4096.0;
        for _ in 0..64 {
            solver.advance(dt).unwrap();
        }
        let ps = solver.particles();
        assert!(ps.velocity.iter().all(|u| *u == v), "{scheme:?}");
        assert_eq!(solver.conservation_totals().momentum, p0, "{scheme:?}");
        assert!(ps.stress.iter().all(|s| *s == [0.0; 6]), "{scheme:?}");
        // Sorted order equals fill order here (the block moves rigidly).
        for (x, x0) in ps.position.iter().zip(&x0) {
            for c in 0..3 {
                assert_eq!(x[c], x0[c] + 64.0 * dt * v[c], "{scheme:?}");
            }
        }
    }
}

#[test]
fn block_at_rest_without_gravity_stays_at_rest() {
    let level = dyadic_level();
    let mut ps = Particles::new(0);
    fill(
        &mut ps,
        &level,
        [0.0; 3],
        [0.5, 0.25, 1.0],
        1024.0,
        [0.0; 3],
        0,
    );
    let x0 = ps.position.clone();
    let mut solver = MpmSolver::new(
        level,
        vec![soft()],
        ps,
        MpmOptions {
            boundaries: [GridBoundary::Fixed; 6],
            ..Default::default()
        },
    )
    .unwrap();
    for _ in 0..20 {
        let dt = solver.stable_dt().unwrap();
        solver.advance(dt).unwrap();
    }
    let ps = solver.particles();
    assert_eq!(ps.position, x0);
    assert!(ps.velocity.iter().all(|v| *v == [0.0; 3]));
    assert!(ps.stress.iter().all(|s| *s == [0.0; 6]));
}

#[test]
fn block_in_free_fall_accelerates_at_gravity() {
    let level = dyadic_level();
    let mut ps = Particles::new(0);
    fill(
        &mut ps,
        &level,
        [0.25, 0.5, 0.0],
        [0.5, 0.75, 1.0],
        1024.0,
        [0.0; 3],
        0,
    );
    let g = [0.0, -9.81, 0.0];
    let mut solver = MpmSolver::new(
        level,
        vec![soft()],
        ps,
        MpmOptions {
            gravity: g,
            ..Default::default()
        },
    )
    .unwrap();
    for _ in 0..50 {
        solver.advance(1.0e-4).unwrap();
    }
    let t = solver.time();
    for v in &solver.particles().velocity {
        // Round-off in Σ ∇N_I = 0 leaves a stress of order 1e-16 of the
        // scale, hence the relative tolerance on both components.
        assert!((v[1] - g[1] * t).abs() < 1e-12 * (g[1] * t).abs(), "{v:?}");
        assert!(v[0].abs() < 1e-12 * (g[1] * t).abs(), "{v:?}");
    }
}

/// Two blocks of different density collide; the right one then hits a fixed
/// wall under gravity. Masses are dyadic so every sum is exact.
fn collision(shape: ShapeFunction, scheme: UpdateScheme) -> MpmSolver {
    let level = Level::new([0.0; 3], [1.0, 1.0, 1.0], [16, 16, 1], [1, 1, 1], 0).unwrap();
    let mut ps = Particles::new(0);
    fill(
        &mut ps,
        &level,
        [0.125, 0.25, 0.0],
        [0.375, 0.5, 1.0],
        1024.0,
        [8.0, 1.0, 0.0],
        0,
    );
    fill(
        &mut ps,
        &level,
        [0.4375, 0.25, 0.0],
        [0.75, 0.625, 1.0],
        2048.0,
        [-4.0, 0.0, 0.0],
        1,
    );
    let mut boundaries = [GridBoundary::Symmetry; 6];
    boundaries[1] = GridBoundary::Fixed;
    MpmSolver::new(
        level,
        vec![soft(), hypoelastic(2.0e7, 1.0e7)],
        ps,
        MpmOptions {
            shape,
            scheme,
            gravity: [0.0, -9.81, 0.0],
            boundaries,
            ..Default::default()
        },
    )
    .unwrap()
}

fn run(solver: &mut MpmSolver, steps: usize) {
    for _ in 0..steps {
        let dt = solver.stable_dt().unwrap();
        solver.advance(dt).unwrap();
    }
}

#[test]
fn total_mass_is_conserved_exactly_through_collisions() {
    for shape in ShapeFunction::ALL {
        let mut s = collision(shape, UpdateScheme::Musl);
        let m0 = s.conservation_totals().mass;
        run(&mut s, 100);
        assert_eq!(s.conservation_totals().mass, m0, "{shape:?}");
    }
}

#[test]
fn results_are_bit_identical_on_one_and_two_threads() {
    for shape in ShapeFunction::ALL {
        for scheme in [UpdateScheme::Usf, UpdateScheme::Usl, UpdateScheme::Musl] {
            if (shape, scheme) == (ShapeFunction::Linear, UpdateScheme::Usl) {
                // Linear USL inverts a particle at the contact corner after
                // ~25 steps of this impact (see
                // `linear_usl_inverts_a_contact_corner_particle`).
                continue;
            }
            let state = |threads: usize| {
                let pool = rayon::ThreadPoolBuilder::new()
                    .num_threads(threads)
                    .build()
                    .unwrap();
                pool.install(|| {
                    let mut s = collision(shape, scheme);
                    run(&mut s, 100);
                    s.save_state().unwrap()
                })
            };
            assert!(state(1) == state(2), "{shape:?} {scheme:?}");
        }
    }
}

/// Known failing: with linear shapes, USL forms the velocity gradient from
/// v_I + f_I/m_I Δt at nodes that a corner particle barely touches, and the
/// impact of [`collision`] inverts that particle after about 25 steps
/// (MUSL, USF, GIMP and the B-spline all run it through). When this passes,
/// add Linear USL back to the determinism test.
#[test]
#[ignore = "known failing: linear USL inverts a contact-corner particle (J <= 0) after ~25 steps"]
fn linear_usl_runs_the_block_impact() {
    let mut s = collision(ShapeFunction::Linear, UpdateScheme::Usl);
    let err = (0..100)
        .map(|_| s.stable_dt().and_then(|dt| s.advance(dt)))
        .find_map(Result::err);
    assert!(err.is_none(), "{err:?}");
}

#[test]
fn restore_of_a_saved_state_continues_bit_identically() {
    let mut a = collision(ShapeFunction::QuadraticBSpline, UpdateScheme::Musl);
    run(&mut a, 30);
    let saved = a.save_state().unwrap();
    run(&mut a, 30);
    let mut b = collision(ShapeFunction::QuadraticBSpline, UpdateScheme::Musl);
    b.restore_state(&saved).unwrap();
    assert_eq!(b.time(), a.time() - (a.time() - b.time()));
    run(&mut b, 30);
    assert_eq!(a.time(), b.time());
    assert!(a.save_state().unwrap() == b.save_state().unwrap());
    assert!(b.restore_state(&saved[..saved.len() / 2]).is_err());
}

#[test]
fn collision_conserves_momentum_when_no_wall_or_gravity_acts() {
    // Free faces and no gravity: Σ f_I^int = 0, so momentum is conserved to
    // round-off while the blocks collide.
    let level = Level::new([0.0; 3], [1.0, 1.0, 1.0], [16, 16, 1], [1, 1, 1], 0).unwrap();
    let mut ps = Particles::new(0);
    fill(
        &mut ps,
        &level,
        [0.25, 0.25, 0.0],
        [0.5, 0.5, 1.0],
        1024.0,
        [20.0, 0.0, 0.0],
        0,
    );
    fill(
        &mut ps,
        &level,
        [0.5, 0.25, 0.0],
        [0.75, 0.5, 1.0],
        1024.0,
        [-20.0, 0.0, 0.0],
        0,
    );
    let mut s = MpmSolver::new(level, vec![soft()], ps, MpmOptions::default()).unwrap();
    let scale = s.conservation_totals().mass * 20.0;
    run(&mut s, 200);
    let p = s.conservation_totals().momentum;
    assert!(p.iter().all(|q| q.abs() < 1e-12 * scale), "{p:?}");
    // The blocks did interact: some particle was slowed down.
    assert!(s.particles().velocity.iter().any(|v| v[0].abs() < 19.0));
}

// ---------------------------------------------------------- leaving particles

fn leaving_block(face: GridBoundary) -> MpmSolver {
    let level = dyadic_level();
    let mut ps = Particles::new(0);
    fill(
        &mut ps,
        &level,
        [0.75, 0.25, 0.0],
        [1.0, 0.5, 1.0],
        1024.0,
        [64.0, 0.0, 0.0],
        0,
    );
    soft_with_face(level, ps, 1, face)
}

#[test]
fn particles_crossing_an_outflow_face_are_removed_and_booked() {
    let mut s = leaving_block(GridBoundary::Outflow);
    let t0 = s.conservation_totals();
    let n0 = s.particles().len();
    for _ in 0..16 {
        s.advance(1.0 / 1024.0).unwrap();
    }
    assert!(s.particles().len() < n0);
    let t = s.conservation_totals();
    assert_eq!(t.mass, t0.mass);
    assert!(s.outflow_totals().mass > 0.0);
    assert!((t.momentum[0] - t0.momentum[0]).abs() < 1e-12 * t0.momentum[0]);
}

#[test]
fn a_particle_leaving_through_a_free_face_stops_the_run_naming_the_face() {
    let mut s = leaving_block(GridBoundary::Free);
    let err = (0..16)
        .map(|_| s.advance(1.0 / 1024.0))
        .find_map(Result::err)
        .unwrap();
    let msg = err.to_string();
    assert!(msg.contains("x+") && msg.contains("Outflow"), "{msg}");
}

#[test]
fn an_inverted_particle_stops_the_run_with_its_index_and_jacobian() {
    let level = dyadic_level();
    let mut ps = Particles::new(0);
    fill(
        &mut ps,
        &level,
        [0.25, 0.25, 0.0],
        [0.5, 0.5, 1.0],
        1024.0,
        [0.0; 3],
        0,
    );
    for p in 0..ps.len() {
        // Strong converging flow: L_xx ≈ −1000 1/s.
        ps.velocity[p][0] = -1000.0 * (ps.position[p][0] - 0.375);
    }
    let mut s = MpmSolver::new(level, vec![soft()], ps, MpmOptions::default()).unwrap();
    let err = s.advance(0.01).unwrap_err();
    assert!(matches!(err, SolverError::NonPhysicalState { .. }), "{err}");
    let msg = err.to_string();
    assert!(
        msg.contains("particle") && msg.contains("J = det F"),
        "{msg}"
    );
}

// ----------------------------------------------------------------- setup

#[test]
fn setup_errors_name_the_bad_option_or_particle() {
    let level = dyadic_level();
    let mut ps = Particles::new(0);
    fill(
        &mut ps,
        &level,
        [0.25, 0.25, 0.0],
        [0.5, 0.5, 1.0],
        1024.0,
        [0.0; 3],
        0,
    );
    let e = MpmSolver::new(
        level.clone(),
        vec![soft()],
        ps.clone(),
        MpmOptions {
            cfl: 1.5,
            ..Default::default()
        },
    )
    .unwrap_err();
    assert!(e.to_string().contains("cfl"), "{e}");
    ps.material[3] = MaterialId(4);
    let e = MpmSolver::new(level.clone(), vec![soft()], ps, MpmOptions::default()).unwrap_err();
    assert_eq!(
        e,
        MpmSetupError::UnknownMaterial {
            particle: 3,
            material: 4,
            count: 1
        }
    );
    let e = MpmSolver::new(
        level,
        vec![soft()],
        Particles::new(0),
        MpmOptions::default(),
    )
    .unwrap_err();
    assert_eq!(e, MpmSetupError::NoParticles);
}

#[test]
fn the_time_step_limit_names_the_fastest_particle() {
    let level = dyadic_level();
    let mut ps = Particles::new(0);
    fill(
        &mut ps,
        &level,
        [0.25, 0.25, 0.0],
        [0.5, 0.5, 1.0],
        1024.0,
        [3.0, 4.0, 0.0],
        0,
    );
    // One particle of the block is faster than the rest.
    let fast = ps.len() / 2;
    ps.velocity[fast] = [0.0, 60.0, 0.0];
    let x = ps.position[fast];
    let s = MpmSolver::new(level, vec![soft()], ps, MpmOptions::default()).unwrap();
    let c = ((1.0e7 + 4.0 * 5.0e6 / 3.0) / 1024.0f64).sqrt();
    // The stable step is the fast particle's, and the limit names it.
    let expected = 0.4 * 0.125 / (c + 60.0);
    assert!((s.stable_dt().unwrap() - expected).abs() < 1e-12 * expected);
    let limit = s.time_step_limit().unwrap();
    let head = format!(
        "MPM particle {fast} (material 0, {}) at ({:.4}, {:.4}, {:.4}) m: sound speed {c:.0} m/s + |v| 60 m/s",
        soft().name(),
        x[0],
        x[1],
        x[2]
    );
    assert!(limit.starts_with(&head), "{limit}\n{head}");
    assert!(
        limit.ends_with("density 1.0240e3 kg/m³, V/V₀ 1.000"),
        "{limit}"
    );
}

/// A fixed inflow reservoir faster than every particle sets the step, as
/// in [`Solver::stable_dt`], and the limit says so.
#[test]
fn the_time_step_limit_names_a_faster_inflow_reservoir() {
    use crate::inflow::{ReservoirKind, ReservoirState};
    let level = dyadic_level();
    let mut ps = Particles::new(0);
    fill(
        &mut ps,
        &level,
        [0.25, 0.25, 0.0],
        [0.5, 0.5, 1.0],
        1024.0,
        [0.0; 3],
        0,
    );
    let mut options = MpmOptions::default();
    options.boundaries[0] = GridBoundary::Outflow;
    options.reservoirs[0] = Some(Reservoir {
        kind: ReservoirKind::Fixed(ReservoirState {
            material: MaterialId(0),
            density: 1024.0,
            velocity: [1000.0, 0.0, 0.0],
            specific_internal_energy: 0.0,
            temperature: 300.0,
            stress: [0.0; 6],
        }),
        ppc: 2,
    });
    let s = MpmSolver::new(level, vec![soft()], ps, options).unwrap();
    let c = ((1.0e7 + 4.0 * 5.0e6 / 3.0) / 1024.0f64).sqrt();
    let expected = 0.4 * 0.125 / (c + 1000.0);
    assert!((s.stable_dt().unwrap() - expected).abs() < 1e-12 * expected);
    assert_eq!(
        s.time_step_limit().unwrap(),
        format!(
            "MPM inflow reservoir: signal speed c + |v| {:.0} m/s",
            c + 1000.0
        )
    );
}

#[test]
fn stable_dt_is_cfl_times_cell_over_wave_speed_plus_velocity() {
    let level = dyadic_level();
    let mut ps = Particles::new(0);
    fill(
        &mut ps,
        &level,
        [0.25, 0.25, 0.0],
        [0.5, 0.5, 1.0],
        1024.0,
        [3.0, 4.0, 0.0],
        0,
    );
    let s = MpmSolver::new(level, vec![soft()], ps, MpmOptions::default()).unwrap();
    let c = ((1.0e7 + 4.0 * 5.0e6 / 3.0) / 1024.0f64).sqrt();
    let expected = 0.4 * 0.125 / (c + 5.0);
    assert!((s.stable_dt().unwrap() - expected).abs() < 1e-12 * expected);
}

#[test]
fn cell_data_gives_mass_weighted_particle_averages() {
    let mut s = collision(ShapeFunction::Linear, UpdateScheme::Musl);
    let names: Vec<String> = ["density", "velocity_x", "mass_density"]
        .iter()
        .map(|s| s.to_string())
        .collect();
    let data = s.cell_data(&names).unwrap();
    let g = s.level().geometry;
    let c = g.linear_index(g.cell_containing([0.2, 0.3, 0.5]).unwrap());
    assert_eq!(data.field("density").unwrap()[c], 1024.0);
    assert_eq!(data.field("velocity_x").unwrap()[c], 8.0);
    assert_eq!(data.field("mass_density").unwrap()[c], 1024.0);
    assert_eq!(data.field("density").unwrap()[0], 0.0);
    let mut out = Vec::new();
    s.sample([0.6, 0.3, 0.5], &names, &mut out).unwrap();
    assert_eq!(out, vec![2048.0, -4.0, 2048.0]);
    assert!(s.cell_data(&["nope".to_string()]).is_err());
    run(&mut s, 1);
}

// ------------------------------------------------------- bulk viscosity

fn viscous(mut s: MpmSolver) -> MpmSolver {
    let mut options = *s.options();
    options.bulk_viscosity = Some(crate::BulkViscosity::LS_DYNA);
    let (level, materials, particles) = (s.level.clone(), s.materials.clone(), s.particles);
    s = MpmSolver::new(level, materials, particles, options).unwrap();
    s
}

#[test]
fn bulk_viscosity_states_follow_their_particles_through_sort_and_outflow() {
    // Particles pushed right block first, so the first sort permutes them;
    // tag each particle's state with its own mass to see that it follows.
    let level = dyadic_level();
    let mut ps = Particles::new(0);
    fill(
        &mut ps,
        &level,
        [0.75, 0.25, 0.0],
        [1.0, 0.5, 1.0],
        2048.0,
        [64.0, 0.0, 0.0],
        0,
    );
    fill(
        &mut ps,
        &level,
        [0.0, 0.25, 0.0],
        [0.25, 0.5, 1.0],
        1024.0,
        [0.0; 3],
        0,
    );
    let mut s = viscous(soft_with_face(level, ps, 1, GridBoundary::Outflow));
    let tag = |s: &mut MpmSolver| {
        for p in 0..s.particles.len() {
            s.bulk[p].trace_d = s.particles.mass[p] + s.particles.position[p][1];
        }
    };
    let check = |s: &MpmSolver| {
        for p in 0..s.particles.len() {
            let want = s.particles.mass[p] + s.particles.position[p][1];
            assert_eq!(s.bulk[p].trace_d, want, "particle {p}");
        }
    };
    tag(&mut s);
    let first = s.particles.mass[0];
    s.sort_particles().unwrap();
    assert_ne!(
        s.particles.mass[0], first,
        "the sort permuted the particles"
    );
    check(&s);
    // Move the fast block out through x+ and remove it.
    let n0 = s.particles.len();
    for p in 0..n0 {
        // The heavy (2048 kg/m³) block: particles of 8 kg, the others 4 kg.
        if s.particles.mass[p] > 6.0 {
            s.particles.position[p][0] += 0.3;
        }
    }
    s.handle_leaving_particles().unwrap();
    assert!(s.particles.len() < n0);
    check(&s);
}

#[test]
fn stable_dt_uses_the_viscous_signal_speed_of_compressed_particles() {
    let level = dyadic_level();
    let mut ps = Particles::new(0);
    fill(
        &mut ps,
        &level,
        [0.25, 0.25, 0.0],
        [0.5, 0.5, 1.0],
        1024.0,
        [3.0, 4.0, 0.0],
        0,
    );
    let mut s = MpmSolver::new(
        level,
        vec![soft()],
        ps,
        MpmOptions {
            bulk_viscosity: Some(crate::BulkViscosity::LS_DYNA),
            ..Default::default()
        },
    )
    .unwrap();
    let c = ((1.0e7 + 4.0 * 5.0e6 / 3.0) / 1024.0f64).sqrt();
    // No compression yet: the plain CFL step.
    let plain = 0.4 * 0.125 / (c + 5.0);
    assert!((s.stable_dt().unwrap() - plain).abs() < 1e-12 * plain);
    // One particle at tr D = −2000 /s: Q = 0.06 c + 1.5 · 0.125 · 2000 (l =
    // 1/8 m, the 2D cell size), speed Q + √(Q² + c²).
    s.bulk[5].trace_d = -2000.0;
    let q = 0.06 * c + 1.5 * 0.125 * 2000.0;
    let expected = 0.4 * 0.125 / (q + (q * q + c * c).sqrt() + 5.0);
    let dt = s.stable_dt().unwrap();
    assert!((dt - expected).abs() < 1e-12 * expected, "{dt} {expected}");
    assert!(dt < 0.2 * plain);
    // Expansion does not shorten the step.
    s.bulk[5].trace_d = 2000.0;
    assert!((s.stable_dt().unwrap() - plain).abs() < 1e-12 * plain);
    // The fluids' coefficients leave a solid's signal speed alone: the
    // same step with Q₂ = 1.0 for fluids; with the fluids' alone, the
    // plain one.
    s.bulk[5].trace_d = -2000.0;
    let strong = Some(crate::BulkViscosity {
        quadratic: 1.5,
        linear: 1.0,
    });
    s.options.fluid_bulk_viscosity = strong;
    assert_eq!(s.stable_dt().unwrap(), dt);
    s.options.bulk_viscosity = None;
    assert!((s.stable_dt().unwrap() - plain).abs() < 1e-12 * plain);
}

#[test]
fn viscous_runs_are_deterministic_restartable_and_conserve_mass_and_momentum() {
    let mut s = viscous(collision(ShapeFunction::Gimp, UpdateScheme::Musl));
    let m0 = s.conservation_totals().mass;
    run(&mut s, 40);
    assert!(
        s.bulk_viscosity().iter().any(|b| b.q > 0.0),
        "the impact compresses some particle"
    );
    assert_eq!(s.conservation_totals().mass, m0);
    let saved = s.save_state().unwrap();
    let pressure_and_q: Vec<(f64, f64)> = {
        let data = s.particle_data().unwrap();
        let col = |n: &str| data.field(n).unwrap().to_vec();
        col("pressure")
            .into_iter()
            .zip(col("bulk_viscosity"))
            .collect()
    };
    for (p, &(pressure, q)) in pressure_and_q.iter().enumerate() {
        let st = s.particles.stress[p];
        let total = -(st[0] + st[1] + st[2]) / 3.0;
        assert_eq!(q, s.bulk[p].q);
        assert!((pressure + q - total).abs() <= 1e-12 * total.abs().max(1.0));
    }
    let state = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        pool.install(|| {
            let mut b = viscous(collision(ShapeFunction::Gimp, UpdateScheme::Musl));
            b.restore_state(&saved).unwrap();
            run(&mut b, 30);
            b.save_state().unwrap()
        })
    };
    run(&mut s, 30);
    let reference = s.save_state().unwrap();
    assert!(state(1) == reference);
    assert!(state(2) == reference);
}

#[test]
fn negative_viscosity_coefficients_are_refused_by_name() {
    let level = dyadic_level();
    let mut ps = Particles::new(0);
    fill(
        &mut ps,
        &level,
        [0.25, 0.25, 0.0],
        [0.5, 0.5, 1.0],
        1024.0,
        [0.0; 3],
        0,
    );
    let e = MpmSolver::new(
        level,
        vec![soft()],
        ps,
        MpmOptions {
            bulk_viscosity: Some(crate::BulkViscosity {
                quadratic: 1.5,
                linear: -0.1,
            }),
            ..Default::default()
        },
    )
    .unwrap_err();
    assert!(e.to_string().contains("bulk_viscosity.linear"), "{e}");
    let e = MpmSolver::new(
        dyadic_level(),
        vec![soft()],
        {
            let mut ps = Particles::new(0);
            fill(
                &mut ps,
                &dyadic_level(),
                [0.25, 0.25, 0.0],
                [0.5, 0.5, 1.0],
                1024.0,
                [0.0; 3],
                0,
            );
            ps
        },
        MpmOptions {
            fluid_bulk_viscosity: Some(crate::BulkViscosity {
                quadratic: f64::NAN,
                linear: 1.0,
            }),
            ..Default::default()
        },
    )
    .unwrap_err();
    assert!(
        e.to_string().contains("fluid_bulk_viscosity.quadratic"),
        "{e}"
    );
}

#[test]
fn a_j2_particle_costs_295_bytes_and_the_grid_152_per_node() {
    // 3D J2 copper (Jaumann: 7 history values): 211 bytes of state + 56 of
    // history + 16 of bulk-viscosity state + 4 of identity + 8 of bins.
    use brisance_constitutive::ElasticPlastic;
    let level = Level::new([0.0; 3], [0.008, 0.016, 0.008], [16, 32, 16], [1, 1, 1], 0).unwrap();
    let mut m = ElasticPlastic::ofhc_copper_seed000();
    m.rate = ObjectiveRate::Jaumann;
    let copper = MaterialModel::ElasticPlastic(m);
    let mut ps = Particles::new(copper.history_len());
    fill(
        &mut ps,
        &level,
        [0.0; 3],
        [0.004, 0.012, 0.004],
        8930.0,
        [0.0, -190.0, 0.0],
        0,
    );
    let n = ps.len();
    assert_eq!(n, 8 * 24 * 8 * 8);
    let boundaries = [GridBoundary::Fixed; 6];
    let mut s = MpmSolver::new(
        level,
        vec![copper],
        ps,
        MpmOptions {
            boundaries,
            ..Default::default()
        },
    )
    .unwrap();
    run(&mut s, 2);
    let used = s.memory_use();
    assert_eq!(used.particles, n * 295);
    assert!(used.particles <= n * 400);
    // Linear shapes: 17 × 33 × 17 nodes of 152 bytes, plus 8 bytes per
    // block of 2 × 2 × 2 cells and 4 per non-empty block.
    let nodes = 17 * 33 * 17;
    let blocks = 8 * 16 * 8;
    assert!(used.grid >= nodes * 152 + 4 * (blocks + 1) + 4 * blocks);
    assert!(used.grid <= nodes * 152 + 4 * (blocks + 1) + 8 * blocks);
}

#[test]
fn results_do_not_depend_on_the_patch_split_of_the_level() {
    // The MPM lattice and its blocks are global: splitting the level into
    // patches (with ghost layers) changes nothing, bit for bit.
    for shape in ShapeFunction::ALL {
        let a = collision(shape, UpdateScheme::Musl);
        let split = Level::new([0.0; 3], [1.0, 1.0, 1.0], [16, 16, 1], [4, 2, 1], 1).unwrap();
        let mut b =
            MpmSolver::new(split, a.materials.clone(), a.particles.clone(), a.options).unwrap();
        let mut a = a;
        run(&mut a, 60);
        run(&mut b, 60);
        assert!(
            a.save_state().unwrap() == b.save_state().unwrap(),
            "{shape:?}"
        );
    }
}

#[test]
fn fbar_runs_are_bit_identical_on_one_and_two_threads_and_any_patch_split() {
    // The collision of two blocks with the ΔF̄ averaging on: same bits on
    // 1 and 2 threads and on a level split into 4 × 2 patches; the
    // averaging changed the result; mass is conserved exactly.
    for shape in ShapeFunction::ALL {
        let fbar = |level: Option<Level>| {
            let mut s = collision(shape, UpdateScheme::Musl);
            s.options.anti_locking = AntiLocking::FBar;
            match level {
                Some(l) => {
                    MpmSolver::new(l, s.materials.clone(), s.particles.clone(), s.options).unwrap()
                }
                None => s,
            }
        };
        let state = |threads: usize, level: Option<Level>| {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            pool.install(|| {
                let mut s = fbar(level);
                let m0 = s.conservation_totals().mass;
                run(&mut s, 60);
                assert_eq!(s.conservation_totals().mass, m0);
                s.save_state().unwrap()
            })
        };
        let one = state(1, None);
        assert!(one == state(2, None), "{shape:?}");
        let split = Level::new([0.0; 3], [1.0, 1.0, 1.0], [16, 16, 1], [4, 2, 1], 1).unwrap();
        assert!(one == state(2, Some(split)), "{shape:?}");
        let mut off = collision(shape, UpdateScheme::Musl);
        run(&mut off, 60);
        assert!(one != off.save_state().unwrap(), "{shape:?}");
    }
}

// ------------------------------------- particles added and taken by a coupling

#[test]
fn inserted_particles_get_fresh_identities_and_removed_ones_are_not_booked() {
    let level = dyadic_level();
    let mut ps = Particles::new(0);
    fill(
        &mut ps,
        &level,
        [0.25, 0.25, 0.0],
        [0.5, 0.5, 1.0],
        1024.0,
        [0.0; 3],
        0,
    );
    let n0 = ps.len();
    let mut solver = MpmSolver::new(level, vec![soft()], ps, MpmOptions::default()).unwrap();
    let p = ParticleInit {
        position: [0.8, 0.8, 0.5],
        velocity: [1.0, 0.0, 0.0],
        mass: 2.0,
        volume: 1e-3,
        ..Default::default()
    };
    let first = solver.insert_particles(&[p.clone(), p.clone()]).unwrap();
    assert_eq!(first as usize, n0);
    assert_eq!(solver.particles().len(), n0 + 2);
    assert_eq!(solver.particle_ids()[n0 + 1] as usize, n0 + 1);
    let totals = solver.conservation_totals();
    assert_eq!(totals.momentum[0], 4.0);
    // Bad particles are refused, adding nothing.
    let outside = ParticleInit {
        position: [1.5, 0.5, 0.5],
        ..p.clone()
    };
    assert!(matches!(
        solver.insert_particles(&[p.clone(), outside]),
        Err(MpmSetupError::OutsideGrid { particle, .. }) if particle == n0 + 3
    ));
    let massless = ParticleInit {
        mass: 0.0,
        ..p.clone()
    };
    assert!(solver.insert_particles(&[massless]).is_err());
    assert_eq!(solver.particles().len(), n0 + 2);
    // Removing the first of the two: not booked as outflow, and the next
    // identity is not reused.
    solver.remove_particles(&[n0]);
    assert_eq!(solver.particles().len(), n0 + 1);
    assert_eq!(solver.particle_ids()[n0] as usize, n0 + 1);
    assert_eq!(solver.outflow_totals(), ConservationTotals::default());
    assert_eq!(solver.conservation_totals().momentum[0], 2.0);
    assert_eq!(
        solver.insert_particles(std::slice::from_ref(&p)).unwrap() as usize,
        n0 + 2
    );
    let dt = solver.stable_dt().unwrap();
    solver.advance(dt).unwrap();
}

/// Every step, removes every seventh particle (a different seventh each
/// step) and inserts as many again, as the FDM–MPM bridge does; returns
/// the final state.
fn churn(steps: u64) -> Vec<u8> {
    let mut s = viscous(collision(ShapeFunction::Linear, UpdateScheme::Musl));
    let names: Vec<String> = CELL_FIELDS.iter().map(|s| s.to_string()).collect();
    for step in 0..steps {
        let before = s.particles().clone();
        let (ids, bulk) = (s.particle_ids().to_vec(), s.bulk_viscosity().to_vec());
        let n = before.len();
        let leaving: Vec<usize> = (step as usize % 7..n).step_by(7).collect();
        let storage = [
            s.particles().mass.as_ptr() as usize,
            s.particles().deformation_gradient.as_ptr() as usize,
            s.particle_ids().as_ptr() as usize,
            s.bulk_viscosity().as_ptr() as usize,
        ];
        s.remove_particles(&leaving);
        // The others keep their order and every value.
        let kept = (0..n).filter(|p| leaving.binary_search(p).is_err());
        let ps = s.particles();
        assert_eq!(ps.len(), n - leaving.len());
        for (i, k) in kept.enumerate() {
            assert_eq!(ps.position[i], before.position[k]);
            assert_eq!(ps.velocity[i], before.velocity[k]);
            assert_eq!(ps.deformation_gradient[i], before.deformation_gradient[k]);
            assert_eq!(ps.stress[i], before.stress[k]);
            assert_eq!(ps.volume[i], before.volume[k]);
            assert_eq!(s.particle_ids()[i], ids[k]);
            assert_eq!(s.bulk_viscosity()[i], bulk[k]);
        }
        let new: Vec<ParticleInit> = leaving
            .iter()
            .map(|&k| ParticleInit {
                position: before.position[k],
                velocity: before.velocity[k],
                mass: before.mass[k],
                volume: before.volume[k],
                material: before.material[k],
                ..Default::default()
            })
            .collect();
        s.insert_particles(&new).unwrap();
        // Back at the same count: the same storage, nothing reallocated.
        let after = [
            s.particles().mass.as_ptr() as usize,
            s.particles().deformation_gradient.as_ptr() as usize,
            s.particle_ids().as_ptr() as usize,
            s.bulk_viscosity().as_ptr() as usize,
        ];
        assert_eq!(after, storage, "step {step}");
        if step % 8 == 0 {
            // One cell's sample is that cell of the whole-grid fields.
            let data = s.cell_data(&names).unwrap();
            let g = s.level().geometry;
            let mut out = Vec::new();
            for c in 0..g.cell_count() {
                let idx = [c % g.cells[0], (c / g.cells[0]) % g.cells[1], 0];
                let x = std::array::from_fn(|d| g.origin[d] + (idx[d] as f64 + 0.5) * g.spacing[d]);
                s.sample(x, &names, &mut out).unwrap();
                for (k, name) in names.iter().enumerate() {
                    assert_eq!(out[k].to_bits(), data.field(name).unwrap()[c].to_bits());
                }
            }
        }
        run(&mut s, 1);
    }
    s.save_state().unwrap()
}

#[test]
fn removal_and_insertion_each_step_keep_order_and_storage_on_any_thread_count() {
    let state = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        pool.install(|| churn(40))
    };
    assert!(state(1) == state(2));
}

#[test]
fn particle_data_gives_each_models_damage_and_the_particle_identity() {
    use brisance_constitutive::{elastic_plastic, hjc, ElasticPlastic, Hjc};
    let level = dyadic_level();
    let metal = MaterialModel::ElasticPlastic(ElasticPlastic::ofhc_copper_seed000());
    let concrete = MaterialModel::Hjc(Hjc::concrete_25mpa_seed001());
    let stride = metal.history_len().max(concrete.history_len());
    let mut ps = Particles::new(stride);
    fill(
        &mut ps,
        &level,
        [0.0; 3],
        [0.25, 0.25, 1.0],
        8930.0,
        [0.0; 3],
        0,
    );
    let n_metal = ps.len();
    fill(
        &mut ps,
        &level,
        [0.5, 0.5, 0.0],
        [0.75, 0.75, 1.0],
        2400.0,
        [0.0; 3],
        1,
    );
    fill(
        &mut ps,
        &level,
        [0.75, 0.0, 0.0],
        [1.0, 0.25, 1.0],
        1024.0,
        [0.0; 3],
        2,
    );
    let materials = vec![metal, concrete, soft()];
    let mut s = MpmSolver::new(level, materials, ps, MpmOptions::default()).unwrap();
    // Known damage in one particle of each damaged model.
    let (m, c) = (1, n_metal + 2);
    s.particles.history_of_mut(m)[elastic_plastic::DAMAGE_INDEX] = 0.25;
    s.particles.history_of_mut(c)[hjc::COMPRESSION_DAMAGE_INDEX] = 0.5;
    s.particles.history_of_mut(c)[hjc::TENSILE_DAMAGE_INDEX] = 0.75;
    let data = s.particle_data().unwrap();
    let col = |n: &str| data.field(n).unwrap().to_vec();
    let (damage, tensile, id) = (col("damage"), col("tensile_damage"), col("id"));
    for p in 0..s.particles.len() {
        let (d, t) = match p {
            _ if p == m => (0.25, 0.0),
            _ if p == c => (0.5, 0.75),
            _ => (0.0, 0.0),
        };
        assert_eq!((damage[p], tensile[p]), (d, t), "particle {p}");
        assert_eq!(id[p], f64::from(s.particle_ids()[p]));
    }
    // Identities are those of creation order before any step.
    assert!(id.iter().enumerate().all(|(p, &i)| i == p as f64));
}

/// `make()` on each of `ranks` threads acting as ranks
/// ([`brisance_grid::comm::InProcess`]; each with a thread pool of its
/// own), the particle updates spread over
/// them ([`MpmSolver::distribute`]), `steps` steps at the stable Δt: each
/// rank's saved state, or its first error.
fn on_thread_ranks(
    ranks: usize,
    make: &(dyn Fn() -> MpmSolver + Sync),
    steps: usize,
) -> Vec<Result<Vec<u8>, String>> {
    brisance_grid::comm::InProcess::run(ranks, 2, |comm| {
        let mut s = make();
        s.distribute(comm);
        for _ in 0..steps {
            let dt = s.stable_dt().map_err(|e| e.to_string())?;
            s.advance(dt).map_err(|e| e.to_string())?;
        }
        s.save_state().map_err(|e| e.to_string())
    })
}

/// [`collision`] with the ΔF̄ averaging (its G2P runs on every rank, the
/// stress update on each rank's share).
fn averaged(mut s: MpmSolver) -> MpmSolver {
    let mut options = *s.options();
    options.anti_locking = AntiLocking::FBar;
    let (level, materials, particles) = (s.level.clone(), s.materials.clone(), s.particles);
    s = MpmSolver::new(level, materials, particles, options).unwrap();
    s
}

#[test]
fn particle_updates_spread_over_ranks_give_the_bits_of_one() {
    type Variant = fn(MpmSolver) -> MpmSolver;
    let variants: [(&str, Variant); 3] =
        [("plain", |s| s), ("viscous", viscous), ("FBar", averaged)];
    for shape in ShapeFunction::ALL {
        for scheme in [UpdateScheme::Usf, UpdateScheme::Usl, UpdateScheme::Musl] {
            if (shape, scheme) == (ShapeFunction::Linear, UpdateScheme::Usl) {
                continue; // inverts a particle: the next test
            }
            for (name, variant) in variants {
                let make = || variant(collision(shape, scheme));
                let one = on_thread_ranks(1, &make, 60).remove(0).unwrap();
                for ranks in [2, 3] {
                    for (r, state) in on_thread_ranks(ranks, &make, 60).into_iter().enumerate() {
                        assert!(
                            state.as_ref() == Ok(&one),
                            "{shape:?} {scheme:?} {name}: rank {r} of {ranks}"
                        );
                    }
                }
            }
        }
    }
}

/// Linear USL inverts a contact-corner particle of [`collision`] after
/// about 25 steps ([`linear_usl_runs_the_block_impact`]): on several ranks
/// every rank stops at the same step with the error of one rank, whichever
/// rank's share holds the particle.
#[test]
fn a_failed_particle_update_on_ranks_stops_every_rank_with_the_error_of_one() {
    let make = || collision(ShapeFunction::Linear, UpdateScheme::Usl);
    let one = on_thread_ranks(1, &make, 60).remove(0).unwrap_err();
    assert!(one.contains("J = det F"), "{one}");
    let index: usize = one
        .split("particle ")
        .nth(1)
        .and_then(|s| s.split(' ').next())
        .and_then(|s| s.parse().ok())
        .unwrap_or_else(|| panic!("a particle index in {one}"));
    let n = make().particles.len();
    let mut owners = Vec::new();
    for ranks in [2, 3, 5] {
        let starts = brisance_grid::comm::equal_runs(n, ranks);
        owners.push(starts.partition_point(|&s| s <= index) - 1);
        for (r, got) in on_thread_ranks(ranks, &make, 60).into_iter().enumerate() {
            assert_eq!(got.as_ref(), Err(&one), "rank {r} of {ranks}");
        }
    }
    // The failing particle lies outside rank 0's share at least once, so
    // the failure crossed between ranks.
    assert!(owners.iter().any(|&o| o > 0), "owners {owners:?}");
}

// ------------------------------------------------------------- walls

/// A soft strip one particle row thick on a symmetry plane y = 0 (face
/// y−), the row `gap` above the plane.
fn strip_on_a_symmetry_plane(gap: f64) -> MpmSolver {
    let level = dyadic_level();
    let mut ps = Particles::new(0);
    fill(
        &mut ps,
        &level,
        [0.25, 0.0, 0.0],
        [0.75, 0.0625, 1.0],
        1024.0,
        [0.0; 3],
        0,
    );
    for x in &mut ps.position {
        if x[1] < 0.0625 {
            x[1] = gap;
        }
    }
    soft_with_face(level, ps, 2, GridBoundary::Symmetry)
}

#[test]
fn a_particle_in_tension_a_whisker_from_a_symmetry_plane_is_mirrored_back() {
    // The row sits 2.5e-4 m (2e-3 of a cell) above the plane, every
    // particle in a tension of 1 MPa. The node row one cell up, which only
    // this row reaches, carries its weight N = 2e-3 (above the mass
    // cut-off, 1e-3) and takes the tension's whole force towards the plane
    // (the plane's nodes hold): the position update moves the row towards
    // the plane by about Δt² σ/(ρ h) = 1e-6 · 1e6 / (1024 · 0.125) ≈
    // 7.8e-3 m whatever its distance, so it crosses, and comes back
    // mirrored.
    //
    // MUSL (the coupled pipeline's scheme): its velocity gradient comes
    // from the re-mapped node velocities; USL's, from v_I^{n+1}, would
    // invert the particle first (L Δt ≈ Δy/(N h) > 1).
    let scheme = UpdateScheme::Musl;
    let mut s = strip_on_a_symmetry_plane(2.5e-4);
    s.options.scheme = scheme;
    for sigma in &mut s.particles.stress {
        *sigma = [1.0e6, 1.0e6, 1.0e6, 0.0, 0.0, 0.0];
    }
    let low: Vec<usize> = (0..s.particles.len())
        .filter(|&p| s.particles.position[p][1] < 0.0625)
        .collect();
    let n0 = s.particles.len();
    let m0 = s.conservation_totals().mass;
    s.advance(1.0e-3).unwrap();
    assert_eq!(s.particles.len(), n0);
    assert_eq!(s.conservation_totals().mass, m0);
    // Every particle of the row crossed and was mirrored: it is above
    // the plane, moving away from it.
    let mut mirrored = 0;
    for p in 0..s.particles.len() {
        let (x, v) = (s.particles.position[p], s.particles.velocity[p]);
        assert!(x[1] >= 0.0, "{scheme:?}: particle {p} at {x:?}");
        if x[1] < 0.0625 && v[1] > 0.0 {
            mirrored += 1;
            assert!(x[1] > 2.5e-4 && x[1] < 0.0625, "{scheme:?}: {x:?}");
        }
    }
    assert_eq!(mirrored, low.len(), "{scheme:?}");
}

#[test]
fn a_wall_mirrors_a_shallow_crossing_and_refuses_a_deep_one() {
    let mut s = strip_on_a_symmetry_plane(0.01);
    // Across the symmetry face by 1e-3 m: mirrored, normal velocity
    // reversed, the rest kept.
    s.particles.position[0] = [0.3, -1.0e-3, 0.5];
    s.particles.velocity[0] = [2.0, -3.0, 0.0];
    s.handle_leaving_particles().unwrap();
    assert_eq!(s.particles.position[0], [0.3, 1.0e-3, 0.5]);
    assert_eq!(s.particles.velocity[0], [2.0, 3.0, 0.0]);
    // Deeper than half a cell (0.0625 m): the run stops naming the face.
    s.particles.position[0] = [0.3, -0.07, 0.5];
    let msg = s.handle_leaving_particles().unwrap_err().to_string();
    assert!(msg.contains("y-") && msg.contains("Symmetry"), "{msg}");
    // A free face mirrors nothing.
    let mut s = strip_on_a_symmetry_plane(0.01);
    s.particles.position[0] = [-1.0e-3, 0.01, 0.5];
    let msg = s.handle_leaving_particles().unwrap_err().to_string();
    assert!(msg.contains("x-") && msg.contains("Free"), "{msg}");
}

/// The nodes that carry mass after one step of a solver on
/// [`dyadic_level`] (cells of 0.125 m) with `shape`: a soft block in the
/// low corner and one particle of a whole cell's volume at 0.3 of cell
/// (5, 5), load-only if `load_only`; the block's nodes (i, j < 4) left out.
fn nodes_of_a_cell_sized_particle(shape: ShapeFunction, load_only: bool) -> Vec<[isize; 2]> {
    let level = dyadic_level();
    let mut ps = Particles::new(0);
    fill(
        &mut ps,
        &level,
        [0.0; 3],
        [0.125, 0.125, 1.0],
        1024.0,
        [0.0; 3],
        0,
    );
    let options = MpmOptions {
        shape,
        ..MpmOptions::default()
    };
    let mut solver = MpmSolver::new(level, vec![soft()], ps, options).unwrap();
    let h = 0.125;
    let p = ParticleInit {
        position: [(5.3) * h, (5.3) * h, 0.5],
        mass: 2.0,
        volume: h * h,
        ..Default::default()
    };
    let first = solver.insert_particles(&[p]).unwrap();
    if load_only {
        solver.set_load_only(first, 1);
    }
    solver.advance(1e-6).unwrap();
    let nodes = solver.grid_nodes();
    let mut out = Vec::new();
    for j in 4..=8 {
        for i in 4..=8 {
            let n = nodes.lattice.index([i, j, 0]).unwrap();
            if nodes.mass[n] > 0.0 {
                out.push([i, j]);
            }
        }
    }
    out
}

#[test]
fn load_only_particles_are_points_under_gimp() {
    let cell = vec![[5, 5], [6, 5], [5, 6], [6, 6]];
    // Linear: the cell's four nodes, load-only or not.
    assert_eq!(
        nodes_of_a_cell_sized_particle(ShapeFunction::Linear, false),
        cell
    );
    assert_eq!(
        nodes_of_a_cell_sized_particle(ShapeFunction::Linear, true),
        cell
    );
    for shape in [ShapeFunction::Gimp, ShapeFunction::CpGimp] {
        // A cell-sized GIMP particle 0.3 into its cell reaches node 4
        // (1.3 h away, inside h + l_p = 1.5 h): nine nodes.
        let spread = nodes_of_a_cell_sized_particle(shape, false);
        assert_eq!(spread.len(), 9, "{shape:?}: {spread:?}");
        // Load-only, it is a point: its cell's four nodes, as linear.
        assert_eq!(
            nodes_of_a_cell_sized_particle(shape, true),
            cell,
            "{shape:?}"
        );
    }
}
