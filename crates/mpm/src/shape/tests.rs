//! Property tests shared by every shape function, and hand-computed values.

use super::*;
use crate::nodes::patch_node_index;
use brisance_grid::{Level, NodeLayout};
use proptest::prelude::*;

fn grid(origin: [f64; 3], spacing: [f64; 3], cells: [usize; 3]) -> UniformGridGeometry {
    UniformGridGeometry {
        origin,
        spacing,
        cells,
    }
}

/// A random level (1, 2 or 3 active directions, any spacing) and a particle
/// in it, with positions concentrated on the hard places: on nodes (patch
/// and cell faces), a round-off away from them, at cell centres and on the
/// domain's faces.
#[derive(Debug, Clone)]
struct Case {
    grid: UniformGridGeometry,
    x: [f64; 3],
}

fn fraction() -> impl Strategy<Value = f64> {
    prop_oneof![
        3 => 0.0..1.0f64,
        1 => Just(0.0),
        1 => Just(1e-13),
        1 => Just(0.5),
        1 => Just(1.0 - 1e-13),
    ]
}

fn case() -> impl Strategy<Value = Case> {
    let axis = || {
        (
            1usize..=12,
            1e-3..2.0f64,
            -5.0..5.0f64,
            0usize..12,
            fraction(),
        )
    };
    (axis(), axis(), axis(), any::<bool>()).prop_map(|(ax, ay, az, on_upper)| {
        let mut origin = [0.0; 3];
        let mut spacing = [0.0; 3];
        let mut cells = [0; 3];
        let mut x = [0.0; 3];
        for (d, (n, h, o, c, f)) in [ax, ay, az].into_iter().enumerate() {
            origin[d] = o;
            spacing[d] = h;
            cells[d] = n;
            let c = c % n;
            x[d] = o + (c as f64 + f) * h;
        }
        if on_upper {
            // A particle on the upper face of the domain along x.
            x[0] = origin[0] + cells[0] as f64 * spacing[0];
        }
        Case {
            grid: grid(origin, spacing, cells),
            x,
        }
    })
}

fn half_width(g: &UniformGridGeometry, fraction_of_half_cell: f64) -> [f64; 3] {
    std::array::from_fn(|d| 0.5 * g.spacing[d] * fraction_of_half_cell)
}

fn node_position(g: &UniformGridGeometry, n: [isize; 3]) -> [f64; 3] {
    std::array::from_fn(|d| g.origin[d] + n[d] as f64 * g.spacing[d])
}

fn active_dims(g: &UniformGridGeometry) -> u32 {
    g.cells.iter().filter(|&&n| n > 1).count() as u32
}

fn eval(sf: ShapeFunction, g: &UniformGridGeometry, x: [f64; 3], lp: [f64; 3]) -> ShapeStencil {
    let mut s = ShapeStencil::new();
    sf.evaluate(g, x, lp, &mut s).unwrap();
    s
}

/// Weight of global node `n` in stencil `s` (0 if not touched).
fn weight_of(s: &ShapeStencil, n: [isize; 3]) -> f64 {
    s.iter()
        .find(|(m, _, _)| *m == n)
        .map_or(0.0, |(_, w, _)| w)
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(512))]

    #[test]
    fn floor_equals_the_library_floor(
        x in prop_oneof![
            -1e3..1e3f64,
            -1e17..1e17f64,
            (-1000i64..1000).prop_map(|k| k as f64),
            (-1000i64..1000).prop_map(|k| k as f64 + 0.5),
            (-1000i64..1000).prop_map(|k| k as f64 - 1e-13),
            (-1000i64..1000).prop_map(|k| k as f64 + 1e-13),
            any::<f64>().prop_filter("finite", |x| x.is_finite()),
        ]
    ) {
        prop_assert_eq!(floor(x), x.floor(), "x = {:e}", x);
    }

    #[test]
    fn weights_partition_unity_and_are_non_negative(c in case(), lpf in 0.05..=1.0f64) {
        for sf in ShapeFunction::ALL {
            let s = eval(sf, &c.grid, c.x, half_width(&c.grid, lpf));
            let sum: f64 = s.weights().iter().sum();
            prop_assert!((sum - 1.0).abs() <= 1e-12, "{sf:?}: ΣN = {sum}");
            prop_assert!(s.weights().iter().all(|&w| w >= 0.0), "{sf:?}: negative weight");
        }
    }

    #[test]
    fn gradients_sum_to_zero(c in case(), lpf in 0.05..=1.0f64) {
        let inv_h = c.grid.spacing.iter().fold(0.0f64, |m, h| m.max(1.0 / h));
        for sf in ShapeFunction::ALL {
            let s = eval(sf, &c.grid, c.x, half_width(&c.grid, lpf));
            for d in 0..3 {
                let sum: f64 = s.gradients().iter().map(|g| g[d]).sum();
                prop_assert!(sum.abs() <= 1e-12 * inv_h, "{sf:?}: Σ∂N/∂x{d} = {sum}");
            }
        }
    }

    #[test]
    fn weights_reproduce_linear_fields(c in case(), lpf in 0.05..=1.0f64) {
        for sf in ShapeFunction::ALL {
            let s = eval(sf, &c.grid, c.x, half_width(&c.grid, lpf));
            for d in 0..3 {
                if c.grid.cells[d] <= 1 {
                    continue; // one node layer: x_I is the origin, not x_p
                }
                let sum: f64 = s
                    .iter()
                    .map(|(n, w, _)| w * node_position(&c.grid, n)[d])
                    .sum();
                prop_assert!((sum - c.x[d]).abs() <= 1e-12, "{sf:?}: ΣN x_I = {sum} vs {}", c.x[d]);
            }
        }
    }

    #[test]
    fn gradients_reproduce_the_identity(c in case(), lpf in 0.05..=1.0f64) {
        for sf in ShapeFunction::ALL {
            let s = eval(sf, &c.grid, c.x, half_width(&c.grid, lpf));
            // Round-off scale of Σ ∇N_I x_I: |x_I| / Δx.
            let scale = s
                .iter()
                .flat_map(|(n, _, _)| {
                    let p = node_position(&c.grid, n);
                    (0..3).map(move |d| p[d].abs())
                })
                .fold(1.0f64, f64::max)
                / c.grid.spacing.iter().cloned().fold(f64::INFINITY, f64::min);
            for a in 0..3 {
                for b in 0..3 {
                    let sum: f64 = s
                        .iter()
                        .map(|(n, _, g)| g[a] * node_position(&c.grid, n)[b])
                        .sum();
                    let expected = if a == b && c.grid.cells[a] > 1 { 1.0 } else { 0.0 };
                    prop_assert!(
                        (sum - expected).abs() <= 1e-12 * scale,
                        "{sf:?}: Σ ∂N/∂x{a} x_I{b} = {sum}, expected {expected}"
                    );
                }
            }
        }
    }

    #[test]
    fn stencil_sizes_match_the_active_directions(c in case(), lpf in 0.05..=1.0f64) {
        let dims = active_dims(&c.grid);
        let lin = eval(ShapeFunction::Linear, &c.grid, c.x, [0.0; 3]);
        prop_assert_eq!(lin.len(), 2usize.pow(dims));
        let bs = eval(ShapeFunction::QuadraticBSpline, &c.grid, c.x, [0.0; 3]);
        prop_assert_eq!(bs.len(), 3usize.pow(dims));
        let gi = eval(ShapeFunction::Gimp, &c.grid, c.x, half_width(&c.grid, lpf));
        prop_assert!(gi.len() >= 2usize.pow(dims) && gi.len() <= 3usize.pow(dims));
        for s in [&lin, &bs, &gi] {
            for (n, w, g) in s.iter() {
                for d in 0..3 {
                    if c.grid.cells[d] <= 1 {
                        prop_assert_eq!(n[d], 0);
                        prop_assert_eq!(g[d], 0.0);
                    }
                }
                prop_assert!(w.is_finite());
            }
        }
    }

    #[test]
    fn stencil_nodes_are_allocated_on_the_owning_patch(
        c in case(),
        layout in (1usize..=3, 1usize..=3, 1usize..=3),
        lpf in 0.05..=1.0f64,
    ) {
        for sf in ShapeFunction::ALL {
            let g = &c.grid;
            let upper = g.upper();
            let lay = [layout.0.min(g.cells[0]), layout.1.min(g.cells[1]), layout.2.min(g.cells[2])];
            let level = Level::new(g.origin, upper, g.cells, lay, sf.required_ghost_nodes()).unwrap();
            let Some(cell) = level.geometry.cell_containing(c.x) else {
                continue; // round-off put the particle a hair outside
            };
            let Some((id, _)) = level.locate(cell) else { continue };
            let patch = &level.patches[id];
            let active = std::array::from_fn(|d| level.is_active(d));
            let nodes = NodeLayout::for_patch(patch, active);
            let s = eval(sf, &level.geometry, c.x, half_width(&level.geometry, lpf));
            for (n, _, _) in s.iter() {
                prop_assert!(
                    patch_node_index(patch, &nodes, n).is_some(),
                    "{sf:?}: node {n:?} of particle {:?} not on patch {id}", c.x
                );
            }
        }
    }

    #[test]
    fn gradients_match_finite_differences_of_weights(
        cells in 2usize..8,
        h in 0.01..1.0f64,
        fx in 0.0..1.0f64,
        fy in 0.0..1.0f64,
        lpf in 0.05..=1.0f64,
    ) {
        let g = grid([0.0; 3], [h, 1.3 * h, 1.0], [cells, cells, 1]);
        let x = [(1.0 + fx) * h, (1.0 + fy) * 1.3 * h, 0.5];
        let lp = half_width(&g, lpf);
        let delta = 1e-6 * h;
        for sf in ShapeFunction::ALL {
            if sf == ShapeFunction::Linear && !(0.01..0.99).contains(&fx) {
                continue; // the hat's gradient jumps at nodes
            }
            if sf == ShapeFunction::Linear && !(0.01..0.99).contains(&fy) {
                continue;
            }
            let s = eval(sf, &g, x, lp);
            for d in 0..2 {
                let mut xp = x;
                let mut xm = x;
                xp[d] += delta;
                xm[d] -= delta;
                let sp = eval(sf, &g, xp, lp);
                let sm = eval(sf, &g, xm, lp);
                for (n, _, grad) in s.iter() {
                    let fd = (weight_of(&sp, n) - weight_of(&sm, n)) / (2.0 * delta);
                    prop_assert!(
                        (fd - grad[d]).abs() <= 1e-5 / h,
                        "{sf:?} node {n:?} axis {d}: ∇N = {}, finite difference {fd}", grad[d]
                    );
                }
            }
        }
    }

    #[test]
    fn gimp_equals_linear_while_the_particle_stays_inside_one_cell(
        cell in 1usize..6,
        lpf in 0.05..=1.0f64,
        t in 0.0..=1.0f64,
    ) {
        let h = 0.2;
        let g = grid([0.0; 3], [h, 1.0, 1.0], [8, 1, 1]);
        let lp = 0.5 * h * lpf;
        // Fractions f with l_p ≤ f·h ≤ h − l_p: the particle's box lies in
        // cell `cell`, where the average of the hat over it is the hat itself.
        let f = lp / h + t * (1.0 - 2.0 * lp / h);
        let x = [(cell as f64 + f) * h, 0.5, 0.5];
        let lin = eval(ShapeFunction::Linear, &g, x, [lp; 3]);
        let gi = eval(ShapeFunction::Gimp, &g, x, [lp; 3]);
        for (n, w, grad) in lin.iter() {
            let gw = weight_of(&gi, n);
            prop_assert!((gw - w).abs() <= 1e-12, "node {n:?}: GIMP {gw} vs linear {w}");
            let gg = gi.iter().find(|(m, _, _)| *m == n).map_or(0.0, |(_, _, g)| g[0]);
            prop_assert!((gg - grad[0]).abs() <= 1e-12 / h);
        }
        let extra: f64 = gi
            .iter()
            .filter(|(n, _, _)| lin.nodes().iter().all(|m| m != n))
            .map(|(_, w, _)| w.abs())
            .sum();
        prop_assert!(extra <= 1e-12, "GIMP weight {extra} outside the cell's nodes");
    }
}

#[test]
fn linear_weights_match_seed_001_eq_16_at_a_known_point() {
    let g = grid([-1.0, 0.0, 2.0], [0.5, 0.25, 2.0], [4, 4, 4]);
    // Cell (1, 2, 0); fractions (0.25, 0.5, 0.75) across it.
    let x = [-1.0 + 0.5 * 1.25, 0.25 * 2.5, 2.0 + 2.0 * 0.75];
    let s = eval(ShapeFunction::Linear, &g, x, [0.0; 3]);
    assert_eq!(s.len(), 8);
    let (xi, eta, zeta) = (2.0 * 0.25 - 1.0, 2.0 * 0.5 - 1.0, 2.0 * 0.75 - 1.0);
    for (n, w, grad) in s.iter() {
        let (xi_i, eta_i, zeta_i) = (
            if n[0] == 1 { -1.0 } else { 1.0 },
            if n[1] == 2 { -1.0 } else { 1.0 },
            if n[2] == 0 { -1.0 } else { 1.0 },
        );
        let eq16 = 0.125 * (1.0 + xi * xi_i) * (1.0 + eta * eta_i) * (1.0 + zeta * zeta_i);
        assert!((w - eq16).abs() < 1e-15, "node {n:?}: {w} vs {eq16}");
        // ∂N/∂x = (1/8) ξ_I (1 + η η_I)(1 + ζ ζ_I) · dξ/dx, dξ/dx = 2/Δx.
        let dndx = 0.125 * xi_i * (1.0 + eta * eta_i) * (1.0 + zeta * zeta_i) * 2.0 / 0.5;
        assert!((grad[0] - dndx).abs() < 1e-14);
    }
    // Node (1, 2, 0): (1 − 0.25)(1 − 0.5)(1 − 0.75) = 0.09375.
    assert!((weight_of(&s, [1, 2, 0]) - 0.09375).abs() < 1e-15);
    assert!((weight_of(&s, [2, 3, 1]) - 0.25 * 0.5 * 0.75).abs() < 1e-15);
}

#[test]
fn linear_particle_on_the_upper_boundary_stays_on_grid_nodes() {
    let g = grid([0.0; 3], [0.1, 1.0, 1.0], [10, 1, 1]);
    let s = eval(ShapeFunction::Linear, &g, [1.0, 0.5, 0.5], [0.0; 3]);
    assert_eq!(s.nodes(), &[[9, 0, 0], [10, 0, 0]]);
    assert_eq!(s.weights(), &[0.0, 1.0]);
}

#[test]
fn inactive_directions_give_four_nodes_in_2d_and_two_in_1d() {
    let g2 = grid([0.0; 3], [1.0; 3], [4, 4, 1]);
    let s = eval(ShapeFunction::Linear, &g2, [1.5, 2.25, 0.3], [0.0; 3]);
    assert_eq!(s.len(), 4);
    assert!(s.nodes().iter().all(|n| n[2] == 0));
    assert!(s.gradients().iter().all(|g| g[2] == 0.0));
    let g1 = grid([0.0; 3], [1.0; 3], [4, 1, 1]);
    let s = eval(ShapeFunction::Linear, &g1, [1.5, 0.2, 0.3], [0.0; 3]);
    assert_eq!(s.len(), 2);
    assert_eq!(s.weights(), &[0.5, 0.5]);
}

#[test]
fn gimp_at_a_cell_centre_gives_the_linear_weights_for_every_half_width() {
    // At the centre of cell i the two nodes are h/2 away, which lies in the
    // linear branch l_p ≤ |r| ≤ h − l_p for every l_p ≤ h/2, and node i − 1
    // is 3h/2 ≥ h + l_p away.
    let h = 0.5;
    let g = grid([0.0; 3], [h, 1.0, 1.0], [6, 1, 1]);
    for lp in [0.01, 0.125, 0.2, 0.25] {
        let s = eval(ShapeFunction::Gimp, &g, [2.5 * h, 0.5, 0.5], [lp, 0.5, 0.5]);
        assert_eq!(s.nodes(), &[[2, 0, 0], [3, 0, 0]], "l_p = {lp}");
        assert!((s.weights()[0] - 0.5).abs() < 1e-15 && (s.weights()[1] - 0.5).abs() < 1e-15);
        assert!((s.gradients()[0][0] + 1.0 / h).abs() < 1e-14);
        assert!((s.gradients()[1][0] - 1.0 / h).abs() < 1e-14);
    }
}

#[test]
fn gimp_on_a_node_spreads_to_both_neighbours() {
    // l_p = h/4 (two particles per cell), particle on node 3:
    // S(0) = 1 − l_p/(2h) = 7/8, S(±h) = l_p/(4h) = 1/16,
    // S'(0) = 0, S'(±h) = ∓1/(2h).
    let h = 2.0;
    let g = grid([0.0; 3], [h, 1.0, 1.0], [6, 1, 1]);
    let s = eval(
        ShapeFunction::Gimp,
        &g,
        [3.0 * h, 0.5, 0.5],
        [h / 4.0, 0.5, 0.5],
    );
    assert_eq!(s.nodes(), &[[2, 0, 0], [3, 0, 0], [4, 0, 0]]);
    let expected_w = [1.0 / 16.0, 7.0 / 8.0, 1.0 / 16.0];
    let expected_g = [-1.0 / (2.0 * h), 0.0, 1.0 / (2.0 * h)];
    for k in 0..3 {
        assert!((s.weights()[k] - expected_w[k]).abs() < 1e-15);
        assert!((s.gradients()[k][0] - expected_g[k]).abs() < 1e-15);
    }
}

#[test]
fn gimp_gradient_is_continuous_across_a_cell_face_where_linear_jumps() {
    let h = 1.0;
    let g = grid([0.0; 3], [h, 1.0, 1.0], [6, 1, 1]);
    let eps = 1e-9;
    let lp = [0.25, 0.5, 0.5];
    let grad_of_node_3 = |sf: ShapeFunction, x: f64| {
        let s = eval(sf, &g, [x, 0.5, 0.5], lp);
        let g = s.iter().find(|(n, _, _)| n[0] == 3).map(|(_, _, gr)| gr[0]);
        g.unwrap_or(0.0)
    };
    let jump = |sf| (grad_of_node_3(sf, 3.0 + eps) - grad_of_node_3(sf, 3.0 - eps)).abs();
    assert!((jump(ShapeFunction::Linear) - 2.0 / h).abs() < 1e-12);
    assert!(jump(ShapeFunction::Gimp) < 1e-6 / h);
    assert!(jump(ShapeFunction::QuadraticBSpline) < 1e-6 / h);
}

#[test]
fn bspline_weights_at_a_known_point() {
    // ξ = 2.3: nearest node 2, d = 0.3; weights 0.5(0.5 − d)² = 0.02,
    // 0.75 − d² = 0.66, 0.5(0.5 + d)² = 0.32 on nodes 1, 2, 3.
    let h = 0.1;
    let g = grid([1.0, 0.0, 0.0], [h, 1.0, 1.0], [8, 1, 1]);
    let s = eval(
        ShapeFunction::QuadraticBSpline,
        &g,
        [1.0 + 2.3 * h, 0.5, 0.5],
        [0.0; 3],
    );
    assert_eq!(s.nodes(), &[[1, 0, 0], [2, 0, 0], [3, 0, 0]]);
    let expected_w = [0.02, 0.66, 0.32];
    let expected_g = [-0.2 / h, -0.6 / h, 0.8 / h];
    for k in 0..3 {
        assert!((s.weights()[k] - expected_w[k]).abs() < 1e-14);
        assert!((s.gradients()[k][0] - expected_g[k]).abs() < 1e-12);
        // The same from the B-spline of the node distance.
        let xi = 2.3 - (1 + k) as f64;
        assert!((s.weights()[k] - bspline::quadratic_bspline(xi)).abs() < 1e-14);
    }
}

#[test]
fn bspline_near_the_domain_edge_reaches_one_ghost_node() {
    let g = grid([0.0; 3], [1.0; 3], [4, 1, 1]);
    let s = eval(
        ShapeFunction::QuadraticBSpline,
        &g,
        [0.2, 0.5, 0.5],
        [0.0; 3],
    );
    assert_eq!(s.nodes()[0], [-1, 0, 0]);
    let s = eval(
        ShapeFunction::QuadraticBSpline,
        &g,
        [3.9, 0.5, 0.5],
        [0.0; 3],
    );
    assert_eq!(s.nodes()[2], [5, 0, 0]);
}

#[test]
fn invalid_inputs_are_rejected_with_a_reason() {
    let g = grid([0.0; 3], [1.0; 3], [4, 4, 4]);
    let mut s = ShapeStencil::new();
    let e = ShapeFunction::Linear
        .evaluate(&g, [f64::NAN, 0.0, 0.0], [0.0; 3], &mut s)
        .unwrap_err();
    assert!(matches!(e, ShapeError::NonFinitePosition { .. }));
    let e = ShapeFunction::Gimp
        .evaluate(&g, [1.0; 3], [0.25, 0.75, 0.25], &mut s)
        .unwrap_err();
    assert_eq!(
        e,
        ShapeError::HalfWidth {
            axis: 1,
            half_width: 0.75,
            max: 0.5
        }
    );
    assert!(e.to_string().contains("axis 1"));
    let e = ShapeFunction::Gimp
        .evaluate(&g, [1.0; 3], [0.0, 0.25, 0.25], &mut s)
        .unwrap_err();
    assert!(matches!(e, ShapeError::HalfWidth { axis: 0, .. }));
}

#[test]
fn default_half_width_tiles_the_cell() {
    let g = grid([0.0; 3], [0.2, 0.4, 1.0], [5, 5, 1]);
    assert_eq!(ShapeFunction::default_half_width(&g, 2), [0.05, 0.1, 0.5]);
}

// ------------------------------------------------------------------ cpGIMP

/// Stretches F_ii with the clamped places: strong compression, a sign
/// change (rotation), the identity and stretches that reach h/2.
fn stretch() -> impl Strategy<Value = f64> {
    prop_oneof![
        4 => 0.2..3.0f64,
        1 => Just(1.0),
        1 => Just(1e-4),
        1 => -2.0..0.0f64,
        1 => 4.0..50.0f64,
    ]
}

/// cpGIMP half-widths l_p0 F_ii of a particle of undeformed half-width
/// `l0f` × Δx/2 on `g`.
fn deformed_half_width(g: &UniformGridGeometry, l0f: f64, s: [f64; 3]) -> [f64; 3] {
    std::array::from_fn(|d| {
        let h = g.spacing[d];
        gimp::cpgimp_half_width(0.5 * h * l0f, s[d], h)
    })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(512))]

    #[test]
    fn cpgimp_with_deformed_half_widths_keeps_the_shape_function_contract(
        c in case(),
        l0f in 0.05..=1.0f64,
        s in [stretch(), stretch(), stretch()],
    ) {
        let lp = deformed_half_width(&c.grid, l0f, s);
        for (l, h) in lp.iter().zip(c.grid.spacing) {
            prop_assert!(*l > 0.0 && *l <= 0.5 * h);
        }
        let st = eval(ShapeFunction::CpGimp, &c.grid, c.x, lp);
        // The same weights as uGIMP with those half-widths.
        prop_assert_eq!(&st, &eval(ShapeFunction::Gimp, &c.grid, c.x, lp));
        let sum: f64 = st.weights().iter().sum();
        prop_assert!((sum - 1.0).abs() <= 1e-12, "ΣN = {sum}");
        prop_assert!(st.weights().iter().all(|&w| w >= 0.0));
        let inv_h = c.grid.spacing.iter().fold(0.0f64, |m, h| m.max(1.0 / h));
        let scale = st
            .iter()
            .flat_map(|(n, _, _)| {
                let p = node_position(&c.grid, n);
                (0..3).map(move |d| p[d].abs())
            })
            .fold(1.0f64, f64::max)
            / c.grid.spacing.iter().cloned().fold(f64::INFINITY, f64::min);
        for a in 0..3 {
            let gsum: f64 = st.gradients().iter().map(|g| g[a]).sum();
            prop_assert!(gsum.abs() <= 1e-12 * inv_h, "Σ∂N/∂x{a} = {gsum}");
            if c.grid.cells[a] > 1 {
                let x: f64 = st.iter().map(|(n, w, _)| w * node_position(&c.grid, n)[a]).sum();
                prop_assert!((x - c.x[a]).abs() <= 1e-12, "ΣN x_I = {x} vs {}", c.x[a]);
            }
            for b in 0..3 {
                let gx: f64 = st
                    .iter()
                    .map(|(n, _, g)| g[a] * node_position(&c.grid, n)[b])
                    .sum();
                let expected = if a == b && c.grid.cells[a] > 1 { 1.0 } else { 0.0 };
                prop_assert!((gx - expected).abs() <= 1e-12 * scale, "Σ∂N/∂x{a} x_I{b} = {gx}");
            }
        }
    }

    #[test]
    fn cpgimp_gradients_match_finite_differences_with_unequal_half_widths(
        h in 0.01..1.0f64,
        fx in 0.0..1.0f64,
        fy in 0.0..1.0f64,
        l0f in 0.05..=1.0f64,
        s in [stretch(), stretch(), stretch()],
    ) {
        let g = grid([0.0; 3], [h, 1.3 * h, 1.0], [6, 6, 1]);
        let x = [(2.0 + fx) * h, (2.0 + fy) * 1.3 * h, 0.5];
        let lp = deformed_half_width(&g, l0f, s);
        let st = eval(ShapeFunction::CpGimp, &g, x, lp);
        let delta = 1e-6 * h;
        for d in 0..2 {
            let (mut xp, mut xm) = (x, x);
            xp[d] += delta;
            xm[d] -= delta;
            let (sp, sm) = (eval(ShapeFunction::CpGimp, &g, xp, lp), eval(ShapeFunction::CpGimp, &g, xm, lp));
            for (n, _, grad) in st.iter() {
                let fd = (weight_of(&sp, n) - weight_of(&sm, n)) / (2.0 * delta);
                // The quadratic branches curve by 1/(h l_p): the central
                // difference is exact to δ²/(h l_p) per unit gradient.
                prop_assert!(
                    (fd - grad[d]).abs() <= 1e-5 / h + 1e-3 * delta / (h * lp[d]),
                    "node {n:?} axis {d}: ∇N = {}, finite difference {fd}", grad[d]
                );
            }
        }
    }

    #[test]
    fn cpgimp_half_width_is_l0_times_the_stretch_within_its_bounds(
        h in 1e-3..2.0f64,
        l0f in 0.05..=1.0f64,
        s in stretch(),
    ) {
        let l0 = 0.5 * h * l0f;
        let lp = gimp::cpgimp_half_width(l0, s, h);
        let expected = (l0 * s).clamp(l0 * gimp::MIN_STRETCH, 0.5 * h);
        prop_assert_eq!(lp, expected.min(0.5 * h));
        prop_assert!(gimp::admissible_half_width(lp, h).is_some());
    }
}

#[test]
fn cpgimp_half_width_at_hand_computed_stretches() {
    let (l0, h) = (0.125, 1.0);
    assert_eq!(gimp::cpgimp_half_width(l0, 1.0, h), 0.125);
    assert_eq!(gimp::cpgimp_half_width(l0, 2.0, h), 0.25);
    assert_eq!(gimp::cpgimp_half_width(l0, 0.5, h), 0.0625);
    // Beyond Δx/2 the stencil of three nodes cannot hold the domain.
    assert_eq!(gimp::cpgimp_half_width(l0, 5.0, h), 0.5);
    // Compressed to nothing, or turned over: l0 · 0.01.
    assert_eq!(gimp::cpgimp_half_width(l0, 1e-6, h), 0.00125);
    assert_eq!(gimp::cpgimp_half_width(l0, -1.0, h), 0.00125);
    assert!(gimp::cpgimp_half_width(l0, f64::NAN, h).is_nan());
    assert!(gimp::cpgimp_half_width(l0, f64::INFINITY, h).is_nan());
    let g = grid([0.0; 3], [h; 3], [4, 1, 1]);
    let mut s = ShapeStencil::new();
    let e = ShapeFunction::CpGimp
        .evaluate(&g, [1.0, 0.5, 0.5], [f64::NAN, 0.5, 0.5], &mut s)
        .unwrap_err();
    assert!(matches!(e, ShapeError::HalfWidth { axis: 0, .. }));
}

/// Σ_p V_p ∂S_Ip/∂x over 1D particles of the given domain edges (cross
/// section 1 m²), on the nodes 0 ..= 4 of a grid of 4 cells of 1 m, each
/// particle at the centre of its domain with half-width `lp(p)`.
fn volume_gradient_sums(
    sf: ShapeFunction,
    edges: &[f64],
    lp: impl Fn(usize) -> f64,
) -> ([f64; 5], [f64; 5]) {
    let g = grid([0.0; 3], [1.0; 3], [4, 1, 1]);
    let (mut grad, mut weight) = ([0.0; 5], [0.0; 5]);
    for p in 0..edges.len() - 1 {
        let x = 0.5 * (edges[p] + edges[p + 1]);
        let l = lp(p);
        let v = 2.0 * l;
        let s = eval(sf, &g, [x, 0.5, 0.5], [l, 0.5, 0.5]);
        // (A uGIMP box that pokes out of the tube reaches node −1 or 5.)
        for (n, w, gr) in s.iter().filter(|(n, _, _)| (0..5).contains(&n[0])) {
            grad[n[0] as usize] += v * gr[0];
            weight[n[0] as usize] += v * w;
        }
    }
    (grad, weight)
}

#[test]
fn cpgimp_volume_gradients_vanish_at_interior_nodes_of_tiling_domains() {
    // Nine particles of unequal sizes whose domains tile [0, 4] m (half-
    // widths 0.15, 0.1, 0.35, 0.2, 0.2, 0.45, 0.05, 0.25, 0.25, all ≤ Δx/2):
    // V_p ∂S_Ip/∂x = S_I(x_p + l_p) − S_I(x_p − l_p), which telescopes to
    // S_I(4) − S_I(0): −1 at node 0, +1 at node 4, 0 inside. Likewise
    // V_p S_Ip = ∫ S_I over the domain, which sums to ∫₀⁴ S_I = ½ Δx at the
    // end nodes and Δx inside.
    let edges = [0.0, 0.3, 0.5, 1.2, 1.6, 2.0, 2.9, 3.0, 3.5, 4.0];
    let lp = |p: usize| 0.5 * (edges[p + 1] - edges[p]);
    let (grad, weight) = volume_gradient_sums(ShapeFunction::CpGimp, &edges, lp);
    let expected_grad = [-1.0, 0.0, 0.0, 0.0, 1.0];
    let expected_weight = [0.5, 1.0, 1.0, 1.0, 0.5];
    for i in 0..5 {
        assert!(
            (grad[i] - expected_grad[i]).abs() < 1e-14,
            "node {i}: {}",
            grad[i]
        );
        assert!(
            (weight[i] - expected_weight[i]).abs() < 1e-14,
            "node {i}: {}",
            weight[i]
        );
    }
    // uGIMP at the same positions, every particle with the mean half-width
    // l = 2/9 m (the same total volume): the boxes overlap and leave gaps,
    // and the interior sums no longer vanish. Node 1 (Δx = 1 m) is reached
    // by the particles at 0.15, 0.4, 0.85, 1.4 and 1.8 m, r = −0.85, −0.6,
    // −0.15, 0.4, 0.8; with the branches of gimp.rs their S' are
    // (0.15 + l)/(2l), 1, 0.15/l, −1, −(0.2 + l)/(2l),
    // and Σ 2l S' = (0.15 + l) + 2l + 0.3 − 2l − (0.2 + l) = 0.25.
    let l = 2.0 / 9.0;
    let (grad_u, _) = volume_gradient_sums(ShapeFunction::Gimp, &edges, |_| l);
    assert!(
        (grad_u[1] - 0.25).abs() < 1e-14,
        "uGIMP Σ V ∂S/∂x at node 1 = {}",
        grad_u[1]
    );
}

/// A closed 1D Sod tube of gas particles: [0, 1] m in 50 cells, 4
/// particles per cell, ρ = 1, p = 1 left of 0.5 m and ρ = 0.125, p = 0.1
/// right of it (γ = 1.4), rigid ends, the LS-DYNA bulk viscosity, run for
/// `steps` steps at the solver's stable Δt. Returns |Σ V_p − V_tube| /
/// V_tube after each step.
fn closed_tube_volume_error(
    shape: ShapeFunction,
    scheme: crate::UpdateScheme,
    steps: usize,
) -> Vec<f64> {
    use crate::{
        fill_shape, BulkViscosity, FillSpec, GridBoundary, MaterialId, MpmOptions, MpmSolver,
        Particles, Shape,
    };
    use brisance_constitutive::{MaterialModel, NullMaterial};
    use brisance_core::Solver;
    let (dy, dz) = (0.01, 0.01);
    let level = Level::new([0.0; 3], [1.0, dy, dz], [50, 1, 1], [1, 1, 1], 1).unwrap();
    let mut ps = Particles::new(8);
    for (lo, hi, density, pressure) in [(0.0, 0.5, 1.0, 1.0), (0.5, 1.0, 0.125, 0.1)] {
        fill_shape(
            &mut ps,
            &level.geometry,
            &FillSpec {
                shape: Shape::Box {
                    min: [lo, 0.0, 0.0],
                    max: [hi, dy, dz],
                },
                ppc: 4,
                density,
                material: MaterialId(0),
                velocity: [0.0; 3],
                temperature: 300.0,
                specific_internal_energy: pressure / (0.4 * density),
            },
        )
        .unwrap();
    }
    let mut boundaries = [GridBoundary::Symmetry; 6];
    boundaries[0] = GridBoundary::Fixed;
    boundaries[1] = GridBoundary::Fixed;
    let options = MpmOptions {
        shape,
        scheme,
        boundaries,
        bulk_viscosity: Some(BulkViscosity::LS_DYNA),
        ..Default::default()
    };
    let gas = MaterialModel::Null(NullMaterial::air());
    let mut solver = MpmSolver::new(level, vec![gas], ps, options).unwrap();
    let tube = dy * dz;
    (0..steps)
        .map(|_| {
            let dt = solver.stable_dt().unwrap();
            solver.advance(dt).unwrap();
            let v: f64 = solver.particles().volume.iter().sum();
            (v - tube).abs() / tube
        })
        .collect()
}

#[test]
fn cpgimp_keeps_the_particle_volume_of_a_closed_gas_tube_closer_than_ugimp() {
    use crate::UpdateScheme;
    let steps = 60;
    let max = |e: &[f64]| e.iter().cloned().fold(0.0, f64::max);
    for scheme in [UpdateScheme::Usl, UpdateScheme::Musl] {
        let cp = closed_tube_volume_error(ShapeFunction::CpGimp, scheme, steps);
        let u = closed_tube_volume_error(ShapeFunction::Gimp, scheme, steps);
        // The first step starts from tiling domains: Σ_p V_p ∇S_Ip vanishes
        // at every interior node, the end nodes do not move, and the total
        // volume changes by round-off only.
        assert!(cp[0] <= 1e-14, "{scheme:?}: first step {:e}", cp[0]);
        if scheme == UpdateScheme::Usl {
            // Afterwards the domains tile only approximately (a domain that
            // straddles a node moves with the average of a kinked velocity,
            // its edges with the end values), but far better than uGIMP's
            // fixed boxes: measured 3.0e-4 against 4.5e-3.
            assert!(
                max(&cp) <= 0.2 * max(&u),
                "USL: cpGIMP {:e}, uGIMP {:e}",
                max(&cp),
                max(&u)
            );
        } else {
            // MUSL moves the particles with v_I^{n+1} but forms L_p (and so
            // the domain sizes and volumes) from the re-mapped velocity:
            // the domain edges of neighbours drift apart whatever the shape
            // function, and over these first steps cpGIMP's drift stays
            // that of uGIMP (measured
            // 3.7e-3 and 3.0e-3; docs/physics/mpm/gimp.md). This documents
            // the limitation: should it fail, the scheme has become
            // consistent and the page needs updating.
            assert!(max(&cp) > 0.5 * max(&u), "MUSL: cpGIMP {:e}", max(&cp));
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(512))]

    /// A zero half-width (the MPM's load-only particles under GIMP) is the
    /// linear hat of seed 001 eq 16, bit for bit, in GIMP's three slots:
    /// the same nodes, weights and derivatives, zero in the third slot,
    /// also exactly on a node (the cell above, as the hat takes it).
    #[test]
    fn zero_half_width_is_the_linear_hat_bit_for_bit(
        cell in 0usize..7,
        f in fraction(),
        h in 1e-3..2.0f64,
    ) {
        let xi = cell as f64 + f;
        let mut w = [f64::NAN; 3];
        let mut g = [f64::NAN; 3];
        let first = gimp::ugimp_1d_padded_into(xi, h, 0.0, &mut w, &mut g);
        let hat = linear::hat_1d(xi, h, 8);
        let k = (hat.first - first) as usize;
        prop_assert!(k <= 1, "hat from node {} outside the slots from {}", hat.first, first);
        for j in 0..3usize {
            let (hw, hg): (f64, f64) = match j.checked_sub(k) {
                Some(i) if i < 2 => (hat.weight[i], hat.gradient[i]),
                _ => (0.0, 0.0),
            };
            prop_assert_eq!(w[j].to_bits(), hw.to_bits(), "weight of slot {} at xi = {}", j, xi);
            prop_assert_eq!(g[j].to_bits(), hg.to_bits(), "gradient of slot {} at xi = {}", j, xi);
        }
        prop_assert_eq!(g.iter().sum::<f64>(), 0.0);
    }
}

#[test]
fn zero_half_width_at_hand_computed_points() {
    // xi = 2.25 on h = 0.5: slots from node 1 (⌊2.75⌋ − 1); the hat of
    // cell 2 in slots 1, 2: weights 0.75 and 0.25, derivatives ∓2 1/m.
    let (mut w, mut g) = ([9.0; 3], [9.0; 3]);
    assert_eq!(
        gimp::ugimp_1d_padded_into(2.25, 0.5, 0.0, &mut w, &mut g),
        1
    );
    assert_eq!((w, g), ([0.0, 0.75, 0.25], [0.0, -2.0, 2.0]));
    // xi = 2.75: slots from node 2; the hat of cell 2 in slots 0, 1.
    assert_eq!(
        gimp::ugimp_1d_padded_into(2.75, 0.5, 0.0, &mut w, &mut g),
        2
    );
    assert_eq!((w, g), ([0.25, 0.75, 0.0], [-2.0, 2.0, 0.0]));
    // Next to node 3 a positive half-width reaches node 4 beyond it; a
    // point does not.
    assert_eq!(
        gimp::ugimp_1d_padded_into(2.999, 0.5, 0.01, &mut w, &mut g),
        2
    );
    assert!(w[2] > 0.0);
    gimp::ugimp_1d_padded_into(2.999, 0.5, 0.0, &mut w, &mut g);
    assert_eq!(w[2], 0.0);
}
