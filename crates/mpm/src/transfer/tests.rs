use super::*;
use crate::ShapeStencil;
use proptest::prelude::*;

fn grid(cells: [usize; 3]) -> UniformGridGeometry {
    UniformGridGeometry {
        origin: [-0.25, 0.5, 1.0],
        spacing: [0.5, 0.25, 0.75],
        cells,
    }
}

/// Particles scattered over the grid (positions from a low-discrepancy
/// sequence, some on cell faces and on the domain boundary), with
/// non-uniform masses, velocities, volumes and stresses.
fn particles(g: &UniformGridGeometry, n: usize) -> crate::Particles {
    let mut ps = crate::Particles::new(0);
    let upper = g.upper();
    for k in 0..n {
        let t = k as f64;
        let frac = |a: f64| (t * a).fract();
        let mut x: [f64; 3] = std::array::from_fn(|d| {
            g.origin[d]
                + frac([0.618_033_988_75, 0.414_213_562_37, 0.732_050_807_57][d])
                    * (upper[d] - g.origin[d])
        });
        if k % 7 == 3 {
            // On a cell face.
            x[0] = g.origin[0] + (k % g.cells[0]) as f64 * g.spacing[0];
        }
        if k % 11 == 5 {
            x[1] = upper[1];
        }
        ps.push(
            &crate::ParticleInit {
                position: x,
                velocity: [frac(0.3) - 0.5, frac(0.7), -frac(0.9)],
                mass: 1.0 + frac(0.19),
                volume: g.spacing.iter().product::<f64>() / 8.0 * (0.9 + 0.2 * frac(0.23)),
                stress: std::array::from_fn(|c| (frac(0.1 + 0.17 * c as f64) - 0.5) * 1e6),
                // Stretched and sheared, so that cpGIMP's half-widths
                // differ per particle and axis (some reach Δx/2).
                deformation_gradient: [
                    0.6 + 0.8 * frac(0.37),
                    0.1 * frac(0.11),
                    0.0,
                    -0.05,
                    0.7 + 0.9 * frac(0.41),
                    0.02,
                    0.0,
                    0.0,
                    0.8 + 0.4 * frac(0.53),
                ],
                ..Default::default()
            },
            &[],
        )
        .unwrap();
    }
    ps
}

/// Grids with 1, 2 and 3 active axes, every shape, and blocks of 2, 4
/// and 8 bins.
fn setups() -> Vec<(UniformGridGeometry, GridMap)> {
    let mut out = Vec::new();
    for cells in [[6, 5, 4], [7, 4, 1], [9, 1, 1], [1, 5, 3]] {
        for shape in ShapeFunction::ALL {
            for t in [2, 4, 8] {
                let g = grid(cells);
                out.push((g, GridMap::with_block_bins(&g, shape, t)));
            }
        }
    }
    out
}

/// The reference P2G: a plain sequential scatter in the kernel's
/// visiting order, with the weights of `ShapeFunction::evaluate`.
fn reference_p2g(
    map: &GridMap,
    bins: &ParticleBins,
    ps: &crate::Particles,
) -> (Vec<f64>, Vec<[f64; 3]>, Vec<[f64; 3]>) {
    let n = map.lattice.len();
    let (mut m, mut p, mut f) = (vec![0.0; n], vec![[0.0; 3]; n], vec![[0.0; 3]; n]);
    let mut st = ShapeStencil::new();
    for colour in 0..COLOURS {
        for &b in bins.colour_blocks(colour) {
            for &q in bins.block_particles(b as usize) {
                let q = q as usize;
                let lp = bins.half_width(q);
                map.shape
                    .evaluate(&map.grid, ps.position[q], lp, &mut st)
                    .unwrap();
                let mv: [f64; 3] = std::array::from_fn(|k| ps.mass[q] * ps.velocity[q][k]);
                let vs: [f64; 6] = std::array::from_fn(|k| ps.volume[q] * ps.stress[q][k]);
                for (node, w, g) in st.iter() {
                    let i = map.lattice.index(node).unwrap();
                    m[i] += w * ps.mass[q];
                    for k in 0..3 {
                        p[i][k] += w * mv[k];
                    }
                    f[i][0] -= vs[0] * g[0] + vs[5] * g[1] + vs[4] * g[2];
                    f[i][1] -= vs[5] * g[0] + vs[1] * g[1] + vs[3] * g[2];
                    f[i][2] -= vs[4] * g[0] + vs[3] * g[1] + vs[2] * g[2];
                }
            }
        }
    }
    (m, p, f)
}

fn inputs(ps: &crate::Particles) -> P2gParticles<'_> {
    P2gParticles {
        position: &ps.position,
        mass: &ps.mass,
        velocity: &ps.velocity,
        volume: &ps.volume,
        stress: &ps.stress,
    }
}

fn in_pool<T: Send>(threads: usize, f: impl FnOnce() -> T + Send) -> T {
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap()
        .install(f)
}

#[test]
fn p2g_equals_the_sequential_scatter_bit_for_bit_on_any_thread_count() {
    for (g, map) in setups() {
        let shape = map.shape;
        let ps = particles(&g, 300);
        let mut bins = ParticleBins::default();
        bins.build_deformed(
            &map,
            &ps.position,
            &ps.initial_volume,
            &ps.deformation_gradient,
        )
        .unwrap();
        let (m, p, f) = reference_p2g(&map, &bins, &ps);
        for threads in [1, 2, 3] {
            let mut nodes = GridNodes::new(map.lattice);
            in_pool(threads, || {
                p2g(&map, &bins, inputs(&ps), &mut nodes, P2gSums::All)
            });
            assert_eq!(
                nodes.mass, m,
                "{shape:?} {:?} mass, {threads} threads",
                g.cells
            );
            assert_eq!(nodes.momentum, p, "{shape:?} {:?} momentum", g.cells);
            assert_eq!(nodes.force, f, "{shape:?} {:?} force", g.cells);
            // The split passes give the same sums.
            let mut split = GridNodes::new(map.lattice);
            in_pool(threads, || {
                p2g(&map, &bins, inputs(&ps), &mut split, P2gSums::MassMomentum);
                p2g(&map, &bins, inputs(&ps), &mut split, P2gSums::Force);
            });
            assert_eq!(
                (split.mass, split.momentum, split.force),
                (m.clone(), p.clone(), f.clone())
            );
        }
    }
}

#[test]
fn p2g_conserves_mass_and_momentum_and_forces_sum_to_zero() {
    for (g, map) in setups() {
        let shape = map.shape;
        let ps = particles(&g, 200);
        let mut bins = ParticleBins::default();
        bins.build_deformed(
            &map,
            &ps.position,
            &ps.initial_volume,
            &ps.deformation_gradient,
        )
        .unwrap();
        let mut nodes = GridNodes::new(map.lattice);
        p2g(&map, &bins, inputs(&ps), &mut nodes, P2gSums::All);
        let total: f64 = ps.mass.iter().sum();
        let m: f64 = nodes.mass.iter().sum();
        assert!(
            (m - total).abs() <= 1e-13 * total,
            "{shape:?}: {m} vs {total}"
        );
        for k in 0..3 {
            let want: f64 = (0..ps.len()).map(|q| ps.mass[q] * ps.velocity[q][k]).sum();
            let got: f64 = nodes.momentum.iter().map(|q| q[k]).sum();
            assert!(
                (got - want).abs() <= 1e-12 * total,
                "{shape:?} p{k}: {got} vs {want}"
            );
            // Σ_I ∇N_Ip = 0 for every particle.
            let f: f64 = nodes.force.iter().map(|q| q[k]).sum();
            let scale: f64 = nodes.force.iter().map(|q| q[k].abs()).sum();
            assert!(f.abs() <= 1e-12 * scale.max(1.0), "{shape:?} f{k}: {f}");
        }
    }
}

/// The reference G2P of one particle: eqs 24, 25 and 27–28 with the
/// weights of `ShapeFunction::evaluate`, in stencil order.
fn reference_g2p(
    map: &GridMap,
    x: [f64; 3],
    lp: [f64; 3],
    a: &[[f64; 3]],
    vn: &[[f64; 3]],
    vl: &[[f64; 3]],
) -> ([f64; 3], [f64; 3], Mat3) {
    let mut st = ShapeStencil::new();
    map.shape.evaluate(&map.grid, x, lp, &mut st).unwrap();
    let (mut dv, mut dx, mut l) = ([0.0; 3], [0.0; 3], [[0.0; 3]; 3]);
    // Stencil order is the kernel's order, but GIMP's evaluate leaves
    // out zero-weight nodes, which add nothing.
    for (node, w, g) in st.iter() {
        let i = map.lattice.index(node).unwrap();
        for k in 0..3 {
            dv[k] += w * a[i][k];
            dx[k] += w * vn[i][k];
            for j in 0..3 {
                l[k][j] += vl[i][k] * g[j];
            }
        }
    }
    let l = Mat3::new(
        l[0][0], l[0][1], l[0][2], l[1][0], l[1][1], l[1][2], l[2][0], l[2][1], l[2][2],
    );
    (dv, dx, l)
}

fn node_field(n: usize, seed: f64) -> Vec<[f64; 3]> {
    (0..n)
        .map(|i| std::array::from_fn(|k| ((i as f64 + 1.0) * seed + k as f64 * 0.37).sin()))
        .collect()
}

#[test]
fn g2p_passes_equal_the_sequential_gather_bit_for_bit() {
    for (g, map) in setups() {
        let shape = map.shape;
        let ps0 = particles(&g, 150);
        let mut bins = ParticleBins::default();
        bins.build_deformed(
            &map,
            &ps0.position,
            &ps0.initial_volume,
            &ps0.deformation_gradient,
        )
        .unwrap();
        let nn = map.lattice.len();
        let (a, vn, vl) = (
            node_field(nn, 0.7),
            node_field(nn, 1.3),
            node_field(nn, 2.9),
        );
        let dt = 0.125;
        for (vel, pos, grad) in [
            (true, true, true),
            (false, true, true),
            (true, true, false),
            (false, false, true),
        ] {
            let mut ps = ps0.clone();
            let mut l = Vec::new();
            g2p(
                &map,
                &bins,
                G2p {
                    acceleration: &a,
                    velocity_new: &vn,
                    gradient_velocity: &vl,
                    dt,
                    update_velocity: vel,
                    update_position: pos,
                    velocity_gradient: grad,
                },
                G2pParticles {
                    position: &mut ps.position,
                    velocity: &mut ps.velocity,
                    gradient: &mut l,
                },
            );
            for q in 0..ps.len() {
                let (dv, dx, lq) =
                    reference_g2p(&map, ps0.position[q], bins.half_width(q), &a, &vn, &vl);
                let v: [f64; 3] = std::array::from_fn(|k| {
                    if vel {
                        ps0.velocity[q][k] + dv[k] * dt
                    } else {
                        ps0.velocity[q][k]
                    }
                });
                let x: [f64; 3] = std::array::from_fn(|k| {
                    if pos {
                        ps0.position[q][k] + dx[k] * dt
                    } else {
                        ps0.position[q][k]
                    }
                });
                assert_eq!(ps.velocity[q], v, "{shape:?} {:?} particle {q}", g.cells);
                assert_eq!(ps.position[q], x, "{shape:?} {:?} particle {q}", g.cells);
                if grad {
                    assert_eq!(l[q], lq, "{shape:?} {:?} particle {q}", g.cells);
                }
            }
        }
    }
}

#[test]
fn remap_pass_equals_the_sequential_update_and_scatter_on_any_thread_count() {
    for (g, map) in setups() {
        let shape = map.shape;
        let ps0 = particles(&g, 200);
        let mut bins = ParticleBins::default();
        bins.build_deformed(
            &map,
            &ps0.position,
            &ps0.initial_volume,
            &ps0.deformation_gradient,
        )
        .unwrap();
        let nn = map.lattice.len();
        let a = node_field(nn, 0.9);
        let dt = 0.25;
        // Reference: every particle's new velocity, then the scatter of
        // its momentum in visiting order.
        let mut v_ref = ps0.velocity.clone();
        for (q, v) in v_ref.iter_mut().enumerate() {
            let (dv, _, _) = reference_g2p(&map, ps0.position[q], bins.half_width(q), &a, &a, &a);
            for k in 0..3 {
                v[k] += dv[k] * dt;
            }
        }
        let mut p_ref = vec![[0.0; 3]; nn];
        let mut st = ShapeStencil::new();
        for colour in 0..COLOURS {
            for &b in bins.colour_blocks(colour) {
                for &q in bins.block_particles(b as usize) {
                    let q = q as usize;
                    let lp = bins.half_width(q);
                    map.shape
                        .evaluate(&map.grid, ps0.position[q], lp, &mut st)
                        .unwrap();
                    let mv: [f64; 3] = std::array::from_fn(|k| ps0.mass[q] * v_ref[q][k]);
                    for (node, w, _) in st.iter() {
                        let i = map.lattice.index(node).unwrap();
                        for k in 0..3 {
                            p_ref[i][k] += w * mv[k];
                        }
                    }
                }
            }
        }
        for threads in [1, 3] {
            let mut ps = ps0.clone();
            let mut nodes = GridNodes::new(map.lattice);
            nodes.acceleration.clone_from(&a);
            nodes.momentum.fill([7.0; 3]);
            in_pool(threads, || {
                g2p_velocity_and_remap_momentum(
                    &map,
                    &bins,
                    &ps.position,
                    &ps.mass,
                    &mut ps.velocity,
                    &mut nodes,
                    dt,
                )
            });
            assert_eq!(ps.velocity, v_ref, "{shape:?} {:?}", g.cells);
            assert_eq!(nodes.momentum, p_ref, "{shape:?} {:?}", g.cells);
        }
        // The weighted pass: every third particle load-only (weight
        // 0); the momentum and the re-mapping's masses are the
        // sequential scatter of the others, the velocities as above.
        let weight: Vec<f64> = (0..ps0.len())
            .map(|q| if q % 3 == 0 { 0.0 } else { ps0.mass[q] })
            .collect();
        let (mut pw_ref, mut mw_ref) = (vec![[0.0; 3]; nn], vec![0.0; nn]);
        for colour in 0..COLOURS {
            for &b in bins.colour_blocks(colour) {
                for &q in bins.block_particles(b as usize) {
                    let q = q as usize;
                    let lp = bins.half_width(q);
                    map.shape
                        .evaluate(&map.grid, ps0.position[q], lp, &mut st)
                        .unwrap();
                    let mv: [f64; 3] = std::array::from_fn(|k| weight[q] * v_ref[q][k]);
                    for (node, w, _) in st.iter() {
                        let i = map.lattice.index(node).unwrap();
                        for k in 0..3 {
                            pw_ref[i][k] += w * mv[k];
                        }
                        mw_ref[i] += w * weight[q];
                    }
                }
            }
        }
        for threads in [1, 3] {
            let mut ps = ps0.clone();
            let mut nodes = GridNodes::new(map.lattice);
            nodes.acceleration.clone_from(&a);
            nodes.momentum.fill([7.0; 3]);
            let mut remap_mass = vec![5.0; nn];
            in_pool(threads, || {
                g2p_velocity_and_remap_momentum_weighted(
                    &map,
                    &bins,
                    &ps.position,
                    &weight,
                    &mut ps.velocity,
                    &mut nodes,
                    &mut remap_mass,
                    dt,
                )
            });
            assert_eq!(ps.velocity, v_ref, "{shape:?} {:?}", g.cells);
            assert_eq!(nodes.momentum, pw_ref, "{shape:?} {:?}", g.cells);
            assert_eq!(remap_mass, mw_ref, "{shape:?} {:?}", g.cells);
        }
    }
}

#[test]
fn blocks_of_one_colour_touch_disjoint_nodes() {
    for (g, map) in setups() {
        let shape = map.shape;
        let ps = particles(&g, 400);
        let mut bins = ParticleBins::default();
        bins.build_deformed(
            &map,
            &ps.position,
            &ps.initial_volume,
            &ps.deformation_gradient,
        )
        .unwrap();
        let mut st = ShapeStencil::new();
        for colour in 0..COLOURS {
            // Node → the block of this colour that touched it.
            let mut owner = vec![usize::MAX; map.lattice.len()];
            for &b in bins.colour_blocks(colour) {
                for &q in bins.block_particles(b as usize) {
                    let q = q as usize;
                    let lp = bins.half_width(q);
                    map.shape
                        .evaluate(&map.grid, ps.position[q], lp, &mut st)
                        .unwrap();
                    for node in st.nodes() {
                        let i = map.lattice.index(*node).unwrap();
                        assert!(
                            owner[i] == usize::MAX || owner[i] == b as usize,
                            "{shape:?}: node {node:?} in blocks {} and {b} of colour {colour}",
                            owner[i]
                        );
                        owner[i] = b as usize;
                    }
                }
            }
        }
        // Every particle is listed exactly once.
        let mut seen = vec![0; ps.len()];
        for b in 0..map.block_count() {
            for &q in bins.block_particles(b) {
                seen[q as usize] += 1;
            }
        }
        assert!(seen.iter().all(|&s| s == 1));
    }
}

#[test]
fn a_block_lists_its_particles_in_storage_order() {
    let g = grid([6, 5, 4]);
    let ps = particles(&g, 300);
    let map = GridMap::new(&g, ShapeFunction::Linear);
    let mut bins = ParticleBins::default();
    bins.build_deformed(
        &map,
        &ps.position,
        &ps.initial_volume,
        &ps.deformation_gradient,
    )
    .unwrap();
    for b in 0..map.block_count() {
        let list = bins.block_particles(b);
        assert!(list.windows(2).all(|w| w[0] < w[1]));
        for &q in list {
            assert_eq!(map.block_of(ps.position[q as usize]), Some(b));
        }
    }
}

#[test]
fn binning_names_the_first_particle_outside_or_with_a_bad_half_width() {
    let g = grid([6, 5, 4]);
    let mut ps = particles(&g, 50);
    ps.position[17][2] = g.upper()[2] + 1e-9;
    ps.position[31][0] = f64::NAN;
    let mut bins = ParticleBins::default();
    let map = GridMap::new(&g, ShapeFunction::QuadraticBSpline);
    let e = bins
        .build(&map, &ps.position, &ps.initial_volume)
        .unwrap_err();
    assert_eq!(
        e,
        BinError::Outside {
            index: 17,
            position: ps.position[17]
        }
    );
    let ps = particles(&g, 50);
    let mut v0 = ps.initial_volume.clone();
    v0[40] = 1.0e3;
    v0[44] = 1.0e3;
    let map = GridMap::new(&g, ShapeFunction::Gimp);
    let e = bins.build(&map, &ps.position, &v0).unwrap_err();
    assert!(
        matches!(
            e,
            BinError::Shape {
                index: 40,
                error: ShapeError::HalfWidth { .. }
            }
        ),
        "{e:?}"
    );
    assert!(e.to_string().contains("particle 40"), "{e}");
}

#[test]
fn ugimp_with_one_particle_per_cell_in_3d_takes_half_a_cell() {
    // Regression: l_p = ½ (Δx³)^(1/3) rounds one ulp above Δx/2 for
    // Δx = 0.1 m, and the strict check refused `ppc: 1` in 3D.
    let g = UniformGridGeometry {
        origin: [0.0; 3],
        spacing: [0.1; 3],
        cells: [4, 4, 4],
    };
    let v0 = 0.1 * 0.1 * 0.1;
    assert!(
        gimp_half_width(&g, v0) > 0.05,
        "the round-off this test is about"
    );
    for shape in [ShapeFunction::Gimp, ShapeFunction::CpGimp] {
        let map = GridMap::new(&g, shape);
        assert_eq!(map.half_width(v0), Ok(0.05));
        let mut ps = crate::Particles::new(0);
        crate::fill_shape(
            &mut ps,
            &g,
            &crate::FillSpec {
                shape: crate::Shape::Box {
                    min: [0.0; 3],
                    max: [0.4; 3],
                },
                ppc: 1,
                density: 1.0,
                material: crate::MaterialId(0),
                velocity: [0.0; 3],
                temperature: 300.0,
                specific_internal_energy: 0.0,
            },
        )
        .unwrap();
        assert_eq!(ps.len(), 64);
        let mut bins = ParticleBins::default();
        bins.build(&map, &ps.position, &ps.initial_volume).unwrap();
        assert!((0..64).all(|p| bins.half_width(p) == [0.05; 3]));
        // The shape function takes the rounded value as Δx/2 too.
        let lp = gimp_half_width(&g, v0);
        let (mut a, mut b) = (ShapeStencil::new(), ShapeStencil::new());
        shape
            .evaluate(&g, [0.15, 0.2, 0.05], [lp; 3], &mut a)
            .unwrap();
        shape
            .evaluate(&g, [0.15, 0.2, 0.05], [0.05; 3], &mut b)
            .unwrap();
        assert_eq!(a, b);
        // A real excess is still refused.
        let e = map.half_width(v0 * (1.0 + 1e-9)).unwrap_err();
        assert!(matches!(e, ShapeError::HalfWidth { axis: 0, .. }), "{e:?}");
    }
}

#[test]
fn cpgimp_half_widths_follow_the_diagonal_of_f() {
    let g = grid([6, 5, 4]);
    let map = GridMap::new(&g, ShapeFunction::CpGimp);
    // l_p0 = ½ (0.2³)^(1/3) = 0.1 m; Δx/2 = (0.25, 0.125, 0.375) m.
    let v0 = 0.2 * 0.2 * 0.2;
    let l0 = map.half_width(v0).unwrap();
    assert!((l0 - 0.1).abs() < 1e-16);
    let f = [1.2, 0.3, -0.4, 0.1, 0.5, 0.2, 0.7, -0.1, 3.0];
    let x = [[0.9, 1.1, 2.0], [0.1, 0.6, 1.5], [1.0, 1.0, 2.5]];
    let fs = [f, crate::particles::IDENTITY, [f64::NAN; 9]];
    let mut bins = ParticleBins::default();
    bins.build_deformed(&map, &x[..2], &[v0; 2], &fs[..2])
        .unwrap();
    // l_p,i = l_p0 F_ii: 0.12, 0.05 and 0.3 m (below Δx/2 = 0.375).
    let lp = bins.half_width(0);
    let expected = [l0 * 1.2, l0 * 0.5, l0 * 3.0];
    assert_eq!(lp, expected);
    assert_eq!(bins.half_width(1), [l0; 3]);
    // Without F (build): the undeformed domain.
    bins.build(&map, &x[..2], &[v0; 2]).unwrap();
    assert_eq!(bins.half_width(0), [l0; 3]);
    // A non-finite F names its particle.
    let e = bins.build_deformed(&map, &x, &[v0; 3], &fs).unwrap_err();
    assert!(matches!(e, BinError::Shape { index: 2, .. }), "{e:?}");
    // On a 1D grid the inactive axes get Δx/2.
    let g1 = grid([9, 1, 1]);
    let map1 = GridMap::new(&g1, ShapeFunction::CpGimp);
    // l_p0 = ½ V/(Δy Δz) = 0.1 m.
    let v1 = 0.2 * 0.25 * 0.75;
    bins.build_deformed(&map1, &[[1.0, 0.6, 1.2]], &[v1], &[f])
        .unwrap();
    let lp = bins.half_width(0);
    assert!((lp[0] - 0.12).abs() < 1e-15, "{lp:?}");
    assert_eq!([lp[1], lp[2]], [0.125, 0.375]);
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    /// The bin a particle is listed under is the offset its stencil
    /// starts at, for positions anywhere in the grid — on nodes, a
    /// round-off off them, on the domain faces.
    #[test]
    fn the_bin_of_a_particle_is_where_its_stencil_starts(
        cells in prop::array::uniform3(1usize..9),
        cell in prop::array::uniform3(0usize..9),
        frac in prop::array::uniform3(prop_oneof![
            3 => 0.0..1.0f64, 1 => Just(0.0), 1 => Just(0.5),
            1 => Just(1e-15), 1 => Just(1.0 - 1e-15), 1 => Just(1.0)
        ]),
        spacing in prop::array::uniform3(1e-3..3.0f64),
        origin in prop::array::uniform3(-5.0..5.0f64),
    ) {
        let g = UniformGridGeometry { origin, spacing, cells };
        let x: [f64; 3] = std::array::from_fn(|d| {
            origin[d] + ((cell[d] % cells[d]) as f64 + frac[d]) * spacing[d]
        });
        prop_assume!(g.cell_containing(x).is_some());
        for (shape, t) in ShapeFunction::ALL.into_iter().flat_map(|s| [(s, 2), (s, 8)]) {
            let map = GridMap::with_block_bins(&g, shape, t);
            let lp = 0.25 * spacing.iter().cloned().fold(f64::INFINITY, f64::min);
            let offset: [usize; 3] = std::array::from_fn(|d| match map.nodes_per_axis[d] {
                1 => map.axis::<1>(d, x[d], lp).offset,
                2 => map.axis::<2>(d, x[d], lp).offset,
                _ => map.axis::<3>(d, x[d], lp).offset,
            });
            prop_assert_eq!(map.block_of(x), Some(map.block_of_offsets(offset)), "{:?}", shape);
            // And the stencil is on the lattice.
            for d in 0..3 {
                prop_assert!(offset[d] + map.nodes_per_axis[d] <= map.lattice.dims[d]);
            }
        }
    }
}

#[test]
fn a_cpgimp_particle_born_wider_than_a_cell_is_capped_and_a_bad_volume_refused() {
    let g = grid([6, 5, 4]);
    let map = GridMap::new(&g, ShapeFunction::CpGimp);
    // Δx/2 = (0.25, 0.125, 0.375) m. A particle of (0.6 m)³: l_p0 = 0.3 m,
    // past Δx/2 on x and y, capped there as a stretched domain is; uGIMP
    // refuses the same particle.
    let v0 = 0.6 * 0.6 * 0.6;
    let lp = map
        .deformed_half_width(v0, &crate::particles::IDENTITY)
        .unwrap();
    assert_eq!(lp, [0.25, 0.125, 0.3]);
    assert!(GridMap::new(&g, ShapeFunction::Gimp)
        .half_width(v0)
        .is_err());
    for bad in [0.0, -1.0, f64::NAN, f64::INFINITY] {
        let e = map
            .deformed_half_width(bad, &crate::particles::IDENTITY)
            .unwrap_err();
        assert!(
            matches!(e, ShapeError::HalfWidth { axis: 0, .. }),
            "{bad}: {e:?}"
        );
    }
}
