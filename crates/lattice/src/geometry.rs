//! The structured lattice of seed 003 §2.1: nodes on a uniform grid of
//! spacing h, connections found from lattice indexing (no neighbour
//! search), solid nodes surrounded by one layer of exterior (ghost) nodes,
//! and the dual-mesh volume of each solid node (fig. 8).
//!
//! Node `(ix, iy, iz)` of the padded box has the linear index
//! `ix + nx (iy + ny iz)`. The solid region the user describes is padded by
//! one exterior layer on every side of each active axis, so every solid
//! node has all its lattice neighbours (axial and diagonal) inside the box.
//!
//! Each connection is stored once, at its lower node, for the *forward*
//! directions of [`Geometry::directions`]: axial `e_a` (a < dim) and, when
//! diagonal springs are on, the face diagonals `e_a ± e_b` (a < b).
//! Bond `(i, d)` joins node `i` and node `i + offset[d]`; its index is
//! `i · ndir + d`.

/// Spatial dimension of a lattice.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub enum Dim {
    /// A chain (rods, seed 003 §2.5.2–2.5.3); cross-section h² (eq 28).
    One,
    /// A plane lattice of depth h (eq 28).
    Two,
    /// A cubic lattice.
    Three,
}

impl Dim {
    /// Number of active axes.
    pub fn count(self) -> usize {
        match self {
            Dim::One => 1,
            Dim::Two => 2,
            Dim::Three => 3,
        }
    }
}

/// Kind of a lattice node (seed 003 fig. 7).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum NodeKind {
    /// Interior or surface node of material `material` (index into the
    /// lattice's material list).
    Solid(u16),
    /// Exterior (ghost) node: holds the surroundings' state.
    Exterior,
}

/// A lattice direction: integer offset and its linear-index offset.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Direction {
    /// Lattice offset in (x, y, z).
    pub step: [i32; 3],
    /// Offset of the linear node index.
    pub offset: isize,
    /// Whether this is an axial ("parallel", eq 10b f‖) direction.
    pub axial: bool,
}

/// The padded box, its directions and the node kinds.
#[derive(Debug, Clone)]
pub struct Geometry {
    /// Spatial dimension.
    pub dim: Dim,
    /// Nodes per axis of the padded box (1 on inactive axes).
    pub n: [usize; 3],
    /// Lattice spacing h, m.
    pub spacing: f64,
    /// Reference position of solid-block node (0, 0, 0), m.
    pub origin: [f64; 3],
    /// Forward directions (axial first, then diagonals).
    pub directions: Vec<Direction>,
    /// Node kinds, one per box node.
    pub kind: Vec<NodeKind>,
}

impl Geometry {
    /// Builds the padded box around `solid` nodes per axis; `material`
    /// gives the material of solid node `(ix, iy, iz)` (0-based inside the
    /// solid block) or `None` for an exterior node. With `diagonals` the
    /// face-diagonal springs of eq 10b are added.
    pub fn new(
        dim: Dim,
        solid: [usize; 3],
        spacing: f64,
        diagonals: bool,
        mut material: impl FnMut(usize, usize, usize) -> Option<u16>,
    ) -> Self {
        let d = dim.count();
        let mut n = [1usize; 3];
        for a in 0..d {
            n[a] = solid[a].max(1) + 2;
        }
        let stride = [1isize, n[0] as isize, (n[0] * n[1]) as isize];
        let mut directions = Vec::new();
        for a in 0..d {
            let mut step = [0i32; 3];
            step[a] = 1;
            directions.push(Direction {
                step,
                offset: stride[a],
                axial: true,
            });
        }
        if diagonals {
            for a in 0..d {
                for b in a + 1..d {
                    for sb in [1i32, -1] {
                        let mut step = [0i32; 3];
                        step[a] = 1;
                        step[b] = sb;
                        directions.push(Direction {
                            step,
                            offset: stride[a] + sb as isize * stride[b],
                            axial: false,
                        });
                    }
                }
            }
        }
        let total = n[0] * n[1] * n[2];
        let mut kind = vec![NodeKind::Exterior; total];
        let pad = |a: usize| usize::from(a < d);
        for iz in 0..n[2] {
            for iy in 0..n[1] {
                for ix in 0..n[0] {
                    let idx = [ix, iy, iz];
                    let inside = (0..d).all(|a| idx[a] >= 1 && idx[a] + 1 < n[a]);
                    if inside {
                        if let Some(m) = material(ix - pad(0), iy - pad(1), iz - pad(2)) {
                            kind[ix + n[0] * (iy + n[1] * iz)] = NodeKind::Solid(m);
                        }
                    }
                }
            }
        }
        Self {
            dim,
            n,
            spacing,
            origin: [0.0; 3],
            directions,
            kind,
        }
    }

    /// Number of box nodes (solid and exterior).
    pub fn len(&self) -> usize {
        self.kind.len()
    }

    /// Whether the box has no nodes (never, after [`Geometry::new`]).
    pub fn is_empty(&self) -> bool {
        self.kind.is_empty()
    }

    /// Linear index of box node `(ix, iy, iz)`.
    #[inline]
    pub fn index(&self, ix: usize, iy: usize, iz: usize) -> usize {
        ix + self.n[0] * (iy + self.n[1] * iz)
    }

    /// Box coordinates of node `i`.
    #[inline]
    pub fn coords(&self, i: usize) -> [usize; 3] {
        let ix = i % self.n[0];
        let r = i / self.n[0];
        [ix, r % self.n[1], r / self.n[1]]
    }

    /// Index of the solid-block node `(ix, iy, iz)` (0-based inside the
    /// solid block, as passed to the material closure of [`Geometry::new`]).
    pub fn solid_index(&self, ix: usize, iy: usize, iz: usize) -> usize {
        let d = self.dim.count();
        let p = |a: usize| usize::from(a < d);
        self.index(ix + p(0), iy + p(1), iz + p(2))
    }

    /// The same lattice with solid-block node (0, 0, 0) at `origin`.
    pub fn with_origin(mut self, origin: [f64; 3]) -> Self {
        self.origin = origin;
        self
    }

    /// Reference position of node `i`: `origin + (k − 1) h` on the active
    /// axes (k the box coordinate), `origin` on the others.
    pub fn reference_position(&self, i: usize) -> [f64; 3] {
        let c = self.coords(i);
        let d = self.dim.count();
        let mut x = self.origin;
        for a in 0..d {
            x[a] += (c[a] as f64 - 1.0) * self.spacing;
        }
        x
    }

    /// Whether node `i` is solid.
    #[inline]
    pub fn is_solid(&self, i: usize) -> bool {
        matches!(self.kind[i], NodeKind::Solid(_))
    }

    /// Neighbour of `i` along `step`, if inside the box.
    #[inline]
    pub fn neighbour(&self, i: usize, step: [i32; 3]) -> Option<usize> {
        let c = self.coords(i);
        let mut idx = [0usize; 3];
        for a in 0..3 {
            let v = c[a] as i64 + i64::from(step[a]);
            if v < 0 || v >= self.n[a] as i64 {
                return None;
            }
            idx[a] = v as usize;
        }
        Some(self.index(idx[0], idx[1], idx[2]))
    }

    /// Neighbour of a solid node `i` along `step`: solid nodes never sit
    /// on the box boundary, so the linear offset is always inside the box
    /// (no coordinate arithmetic in the hot loops).
    #[inline]
    pub fn solid_neighbour(&self, i: usize, step: [i32; 3]) -> usize {
        let off = step[0] as isize
            + step[1] as isize * self.n[0] as isize
            + step[2] as isize * (self.n[0] * self.n[1]) as isize;
        (i as isize + off) as usize
    }

    /// Depth (2D) or cross-section (1D) factor that turns the dual length
    /// or area into a volume: h² in 1D, h in 2D, 1 in 3D (seed 003 eq 28:
    /// the representative volume is a cube of edge h).
    pub fn out_of_plane(&self) -> f64 {
        match self.dim {
            Dim::One => self.spacing * self.spacing,
            Dim::Two => self.spacing,
            Dim::Three => 1.0,
        }
    }
}

#[inline]
fn mid(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        0.5 * (a[0] + b[0]),
        0.5 * (a[1] + b[1]),
        0.5 * (a[2] + b[2]),
    ]
}

#[inline]
fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

#[inline]
fn det3(a: [f64; 3], b: [f64; 3], c: [f64; 3]) -> f64 {
    a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0])
        + a[2] * (b[0] * c[1] - b[1] * c[0])
}

/// Dual-mesh volume of solid node `i` at positions `x` (seed 003 fig. 8).
///
/// The dual cell is built from the bond midpoints and the lattice-cell
/// centroids around the node; only lattice cells whose corners are all
/// solid contribute ("computed only within the solid portion of the grid").
/// In 1D each solid neighbour contributes half the current bond length
/// times h²; in 2D each all-solid quadrant contributes the quadrilateral
/// (node, edge midpoint, cell centroid, edge midpoint) times the depth h;
/// in 3D each all-solid octant contributes the hexahedron (node, three edge
/// midpoints, three face centroids, cell centroid), split into six
/// tetrahedra about its node–centroid diagonal. Areas and volumes are
/// signed, so an inverted cell reduces the volume.
pub fn dual_volume(g: &Geometry, x: &[Vec<f64>; 3], i: usize) -> f64 {
    if g.dim == Dim::Two {
        return dual_volume_2d(g, &x[0], &x[1], i);
    }
    dual_volume_general(g, x, i)
}

/// Dual-mesh volume of solid node `i` of a 2D lattice (seed 003 fig. 8):
/// the four quadrilaterals (node, edge midpoint, cell centroid, edge
/// midpoint) of the all-solid lattice cells around the node, times the
/// depth h. The same floating-point operations, in the same order, as the
/// general path (so the same bits), with the neighbours found from the row
/// stride (solid nodes never sit on the padded box's boundary) in 3 × 3
/// windows of positions and kinds read once.
#[inline]
pub fn dual_volume_2d(g: &Geometry, x0: &[f64], x1: &[f64], i: usize) -> f64 {
    debug_assert!(g.is_solid(i), "dual volume of an exterior node");
    let nx = g.n[0];
    // The 3 × 3 windows around the node, rows −y, 0, +y; columns −x, 0, +x
    // (one bounds check per row).
    #[inline(always)]
    fn window<T: Copy>(v: &[T], i: usize, nx: usize) -> [[T; 3]; 3] {
        let row = |j: usize| -> [T; 3] {
            let r = &v[j - 1..j + 2];
            [r[0], r[1], r[2]]
        };
        [row(i - nx), row(i), row(i + nx)]
    }
    let p0 = window(x0, i, nx);
    let p1 = window(x1, i, nx);
    let k = window(&g.kind, i, nx);
    let solid = |r: usize, c: usize| matches!(k[r][c], NodeKind::Solid(_));
    let (xi0, xi1) = (p0[1][1], p1[1][1]);
    // Edge midpoint towards window cell (r, c).
    let mid = |r: usize, c: usize| [0.5 * (xi0 + p0[r][c]), 0.5 * (xi1 + p1[r][c])];
    // Quadrant (sx, sy) as window column cx = 1 + sx and row ry = 1 + sy:
    // neighbours a = (1, cx), b = (ry, 1), diagonal (ry, cx).
    let quadrant = |cx: usize, ry: usize, sign: f64, area: &mut f64| {
        if !(solid(1, cx) && solid(ry, 1) && solid(ry, cx)) {
            return;
        }
        let ma = mid(1, cx);
        let mb = mid(ry, 1);
        let cen = [
            0.25 * (xi0 + p0[1][cx] + p0[ry][1] + p0[ry][cx]),
            0.25 * (xi1 + p1[1][cx] + p1[ry][1] + p1[ry][cx]),
        ];
        let d1 = [cen[0] - xi0, cen[1] - xi1];
        let d2 = [mb[0] - ma[0], mb[1] - ma[1]];
        let signed = 0.5 * (d1[0] * d2[1] - d1[1] * d2[0]);
        *area += signed * sign;
    };
    let mut area = 0.0;
    // The order of the general path: (+,+), (+,−), (−,+), (−,−).
    quadrant(2, 2, 1.0, &mut area);
    quadrant(2, 0, -1.0, &mut area);
    quadrant(0, 2, -1.0, &mut area);
    quadrant(0, 0, 1.0, &mut area);
    area * g.spacing
}

/// The dimension-independent dual volume (1D, 2D and 3D); the reference
/// [`dual_volume_2d`] is checked against.
pub(crate) fn dual_volume_general(g: &Geometry, x: &[Vec<f64>; 3], i: usize) -> f64 {
    let p = |j: usize| [x[0][j], x[1][j], x[2][j]];
    debug_assert!(g.is_solid(i), "dual volume of an exterior node");
    let solid = |j: usize| g.is_solid(j).then_some(j);
    match g.dim {
        Dim::One => {
            let mut len = 0.0;
            for s in [1i32, -1] {
                if let Some(j) = solid(g.solid_neighbour(i, [s, 0, 0])) {
                    len += 0.5 * f64::from(s) * (x[0][j] - x[0][i]);
                }
            }
            len * g.out_of_plane()
        }
        Dim::Two => {
            let mut area = 0.0;
            let xi = p(i);
            for sx in [1i32, -1] {
                for sy in [1i32, -1] {
                    let (Some(a), Some(b), Some(c)) = (
                        solid(g.solid_neighbour(i, [sx, 0, 0])),
                        solid(g.solid_neighbour(i, [0, sy, 0])),
                        solid(g.solid_neighbour(i, [sx, sy, 0])),
                    ) else {
                        continue;
                    };
                    let (xa, xb, xc) = (p(a), p(b), p(c));
                    let ma = mid(xi, xa);
                    let mb = mid(xi, xb);
                    let cen = [
                        0.25 * (xi[0] + xa[0] + xb[0] + xc[0]),
                        0.25 * (xi[1] + xa[1] + xb[1] + xc[1]),
                        0.0,
                    ];
                    // Shoelace of (xi, ma, cen, mb): half the cross product
                    // of the diagonals.
                    let d1 = sub(cen, xi);
                    let d2 = sub(mb, ma);
                    let signed = 0.5 * (d1[0] * d2[1] - d1[1] * d2[0]);
                    area += signed * f64::from(sx * sy);
                }
            }
            area * g.out_of_plane()
        }
        Dim::Three => {
            let mut vol = 0.0;
            let x0 = p(i);
            for sx in [1i32, -1] {
                for sy in [1i32, -1] {
                    for sz in [1i32, -1] {
                        let corner = |a: i32, b: i32, c: i32| -> Option<[f64; 3]> {
                            if a == 0 && b == 0 && c == 0 {
                                return Some(x0);
                            }
                            solid(g.solid_neighbour(i, [a * sx, b * sy, c * sz])).map(p)
                        };
                        let mut c = [[0.0; 3]; 8];
                        let mut ok = true;
                        for (k, ck) in c.iter_mut().enumerate() {
                            match corner((k & 1) as i32, ((k >> 1) & 1) as i32, (k >> 2) as i32) {
                                Some(v) => *ck = v,
                                None => ok = false,
                            }
                        }
                        if !ok {
                            continue;
                        }
                        let avg = |ks: &[usize]| -> [f64; 3] {
                            let mut s = [0.0; 3];
                            for &k in ks {
                                for a in 0..3 {
                                    s[a] += c[k][a];
                                }
                            }
                            let w = 1.0 / ks.len() as f64;
                            [s[0] * w, s[1] * w, s[2] * w]
                        };
                        // Hexahedron vertices v(abc), a/b/c along the
                        // octant's x/y/z: node, edge midpoints, face
                        // centroids, cell centroid.
                        let v100 = avg(&[0, 1]);
                        let v010 = avg(&[0, 2]);
                        let v001 = avg(&[0, 4]);
                        let v110 = avg(&[0, 1, 2, 3]);
                        let v101 = avg(&[0, 1, 4, 5]);
                        let v011 = avg(&[0, 2, 4, 6]);
                        let v111 = avg(&[0, 1, 2, 3, 4, 5, 6, 7]);
                        let tets = [
                            (v100, v110),
                            (v110, v010),
                            (v010, v011),
                            (v011, v001),
                            (v001, v101),
                            (v101, v100),
                        ];
                        let g0 = sub(v111, x0);
                        let mut six = 0.0;
                        for (a, b) in tets {
                            six += det3(sub(a, x0), sub(b, x0), g0);
                        }
                        vol += six / 6.0 * f64::from(sx * sy * sz);
                    }
                }
            }
            vol
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn positions(g: &Geometry) -> [Vec<f64>; 3] {
        let mut x = [vec![0.0; g.len()], vec![0.0; g.len()], vec![0.0; g.len()]];
        for i in 0..g.len() {
            let p = g.reference_position(i);
            for a in 0..3 {
                x[a][i] = p[a];
            }
        }
        x
    }

    #[test]
    fn box_is_padded_and_indexed() {
        let g = Geometry::new(Dim::Two, [3, 2, 0], 0.5, true, |_, _, _| Some(0));
        assert_eq!(g.n, [5, 4, 1]);
        assert_eq!(g.len(), 20);
        // Ghost layer all round: 20 − 6 solid.
        assert_eq!(
            g.kind.iter().filter(|k| **k == NodeKind::Exterior).count(),
            14
        );
        assert_eq!(g.directions.len(), 4);
        assert_eq!(g.directions[2].offset, 1 + 5);
        assert_eq!(g.directions[3].offset, 1 - 5);
        let i = g.solid_index(2, 1, 0);
        assert_eq!(g.coords(i), [3, 2, 0]);
        assert_eq!(g.reference_position(i), [1.0, 0.5, 0.0]);
        let g3 = Geometry::new(Dim::Three, [2, 2, 2], 1.0, true, |_, _, _| Some(0));
        // 3 axial + 6 face diagonals.
        assert_eq!(g3.directions.len(), 9);
    }

    #[test]
    fn dual_volumes_of_a_block_sum_to_its_volume() {
        // 2D block 4 × 3 nodes, h = 0.5: solid area 1.5 × 1.0, depth 0.5.
        let g = Geometry::new(Dim::Two, [4, 3, 0], 0.5, false, |_, _, _| Some(0));
        let x = positions(&g);
        let total: f64 = (0..g.len())
            .filter(|&i| g.is_solid(i))
            .map(|i| dual_volume(&g, &x, i))
            .sum();
        assert!((total - 1.5 * 1.0 * 0.5).abs() < 1e-15);
        // Interior node: full h³; corner: quarter; edge: half.
        assert!((dual_volume(&g, &x, g.solid_index(1, 1, 0)) - 0.125).abs() < 1e-16);
        assert!((dual_volume(&g, &x, g.solid_index(0, 0, 0)) - 0.03125).abs() < 1e-16);
        assert!((dual_volume(&g, &x, g.solid_index(1, 0, 0)) - 0.0625).abs() < 1e-16);
        // 3D block 3 × 3 × 3, h = 2: 4³ = 64; centre 8, corner 1.
        let g = Geometry::new(Dim::Three, [3, 3, 3], 2.0, false, |_, _, _| Some(0));
        let x = positions(&g);
        let total: f64 = (0..g.len())
            .filter(|&i| g.is_solid(i))
            .map(|i| dual_volume(&g, &x, i))
            .sum();
        assert!((total - 64.0).abs() < 1e-12);
        assert!((dual_volume(&g, &x, g.solid_index(1, 1, 1)) - 8.0).abs() < 1e-14);
        assert!((dual_volume(&g, &x, g.solid_index(0, 0, 0)) - 1.0).abs() < 1e-14);
        // 1D chain of 5 nodes, h = 0.1: 0.4 × 0.01.
        let g = Geometry::new(Dim::One, [5, 0, 0], 0.1, false, |_, _, _| Some(0));
        let x = positions(&g);
        let total: f64 = (0..g.len())
            .filter(|&i| g.is_solid(i))
            .map(|i| dual_volume(&g, &x, i))
            .sum();
        assert!((total - 0.004).abs() < 1e-17);
    }

    #[test]
    fn dual_volume_follows_a_homogeneous_deformation() {
        // x → F x with det F = 1.2 · 0.9 − 0.1 · 0.05 on the 2D interior node;
        // an affine map scales every dual area by det F.
        let g = Geometry::new(Dim::Two, [3, 3, 0], 1.0, false, |_, _, _| Some(0));
        let mut x = positions(&g);
        let f = [[1.2, 0.1], [0.05, 0.9]];
        for i in 0..g.len() {
            let (a, b) = (x[0][i], x[1][i]);
            x[0][i] = f[0][0] * a + f[0][1] * b;
            x[1][i] = f[1][0] * a + f[1][1] * b;
        }
        let det = 1.2 * 0.9 - 0.1 * 0.05;
        let v = dual_volume(&g, &x, g.solid_index(1, 1, 0));
        assert!((v - det).abs() < 1e-14, "{v}");
        // 3D: a diagonal stretch (1.1, 0.8, 1.3) scales by its product.
        let g = Geometry::new(Dim::Three, [3, 3, 3], 1.0, false, |_, _, _| Some(0));
        let mut x = positions(&g);
        let s = [1.1, 0.8, 1.3];
        for i in 0..g.len() {
            for a in 0..3 {
                x[a][i] *= s[a];
            }
        }
        let v = dual_volume(&g, &x, g.solid_index(1, 1, 1));
        assert!((v - 1.1 * 0.8 * 1.3).abs() < 1e-14, "{v}");
    }

    proptest::proptest! {
        #![proptest_config(proptest::prelude::ProptestConfig::with_cases(48))]
        /// The specialised 2D dual volume is the general path, bit for bit,
        /// on perturbed lattices with exterior holes (every solid node).
        #[test]
        fn dual_volume_2d_is_the_general_path_bit_for_bit(
            holes in proptest::collection::vec(proptest::bool::weighted(0.25), 6 * 5),
            jitter in proptest::collection::vec(-0.3f64..0.3, 2 * 8 * 7),
            spacing in 0.01f64..3.0,
        ) {
            let g = Geometry::new(Dim::Two, [6, 5, 0], spacing, false, |ix, iy, _| {
                (!holes[ix + 6 * iy]).then_some(0)
            });
            let mut x = positions(&g);
            for i in 0..g.len() {
                x[0][i] += jitter[2 * i] * spacing;
                x[1][i] += jitter[2 * i + 1] * spacing;
            }
            for i in (0..g.len()).filter(|&i| g.is_solid(i)) {
                let fast = dual_volume_2d(&g, &x[0], &x[1], i);
                let general = dual_volume_general(&g, &x, i);
                proptest::prop_assert_eq!(fast.to_bits(), general.to_bits(), "node {}", i);
            }
        }
    }

    #[test]
    fn exterior_neighbours_do_not_contribute() {
        // An L-shaped solid: node (1,1) of a 3 × 3 block with (2,2) exterior
        // loses the (+,+) quadrant.
        let g = Geometry::new(Dim::Two, [3, 3, 0], 1.0, false, |ix, iy, _| {
            (!(ix == 2 && iy == 2)).then_some(0)
        });
        let x = positions(&g);
        let v = dual_volume(&g, &x, g.solid_index(1, 1, 0));
        assert!((v - 0.75).abs() < 1e-15);
    }
}
