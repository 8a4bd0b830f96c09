use super::cases::{build, Setup};
use brisance_core::Solver;
use brisance_ice::IceBoundary;
use brisance_mpm::GridBoundary;

/// A steel cube moving at 50 m/s through still air, 16³ cells of 1 mm
/// (1728 particles), every face open.
fn moving_cube() -> Setup {
    let h = 1e-3;
    Setup {
        lower: [0.0; 3],
        upper: [16.0 * h; 3],
        cells: [16; 3],
        solids: vec![([4.0 * h; 3], [10.0 * h; 3])],
        solid_velocity: [50.0, 0.0, 0.0],
        gas_velocity: [0.0; 3],
        ice_faces: std::array::from_fn(|_| IceBoundary::Outflow),
        mpm_faces: [GridBoundary::Free; 6],
    }
}

/// Three coupled steps of a steel cube moving through air (16³ cells,
/// 1728 particles: the parallel loops split into several chunks)
/// leave both frames' state with the same bits on 1 and 2 threads.
#[test]
fn the_coupled_step_gives_the_same_bits_on_one_and_two_threads() {
    let run = |threads: usize| {
        super::in_pool(threads, || {
            let mut s = build(&moving_cube());
            for _ in 0..3 {
                let dt = s.stable_dt().unwrap();
                s.advance(dt).unwrap();
            }
            s.save_state().unwrap()
        })
    };
    let (one, two) = (run(1), run(2));
    assert!(!one.is_empty());
    assert!(one == two, "the state differs between 1 and 2 threads");
}

/// The same cube spread over 2 and 3 ranks of threads
/// ([`super::IceMpm::distribute`]): after four coupled steps every
/// rank holds the state of one rank, bit for bit, and each received
/// the other ranks' share of the particle updates (at least the 21
/// values of stress, F, volume, temperature, energy, flags and bulk
/// viscosity per particle a step), so the update was split.
#[test]
fn the_coupled_step_on_thread_ranks_gives_the_bits_of_one() {
    const STEPS: usize = 4;
    let run = |ranks: usize| {
        crate::thread_ranks::on_thread_ranks(ranks, |comm| {
            let mut s = build(&moving_cube());
            s.distribute(comm);
            for _ in 0..STEPS {
                let dt = s.stable_dt().unwrap();
                s.advance(dt).unwrap();
            }
            s.save_state().unwrap()
        })
    };
    let (one, none) = run(1).remove(0);
    assert_eq!(none, 0);
    let n = build(&moving_cube()).mpm.particles().len();
    assert_eq!(n, 1728);
    for ranks in [2, 3] {
        let starts = brisance_grid::comm::equal_runs(n, ranks);
        for (r, (state, received)) in run(ranks).into_iter().enumerate() {
            assert!(state == one, "rank {r} of {ranks}: the state differs");
            let others = (n - (starts[r + 1] - starts[r])) as u64;
            assert!(
                received >= STEPS as u64 * 21 * others,
                "rank {r} of {ranks} received {received} values"
            );
        }
    }
}
