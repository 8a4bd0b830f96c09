//! A hashed cell list: nodes binned by cells of a given size, found by
//! visiting the 27 cells around a point. Building it is a counting sort
//! (O(N), stable, so every bucket lists its nodes in ascending index) into
//! a table of 2^k buckets, so nodes that fly far apart never make the table
//! grow with the bounding box. Used once for the families (reference
//! positions) and at every step for the short-range forces (current
//! positions); rebuilding reuses the buffers and allocates nothing once
//! they are large enough. [`CellList::rebuild_with_positions`] also keeps
//! each point's position in the buckets' order, one array per component,
//! so the candidates of a bucket are read as contiguous runs and tested
//! against a reach eight at a time ([`CellList::for_each_candidate_within`],
//! the contact pass, `crate::contact`).

/// The cell list.
#[derive(Debug, Clone, Default)]
pub struct CellList {
    cell_size: f64,
    mask: u64,
    start: Vec<u32>,
    sorted: Vec<u32>,
    bucket_of: Vec<u32>,
    /// The points' positions in the order of `sorted`, one array per
    /// component, each followed by `LANES` padding entries so that a
    /// group of lanes starting inside the list can always be loaded
    /// (empty unless built by [`CellList::rebuild_with_positions`]).
    positions: [Vec<f64>; 3],
}

/// Candidates tested against the reach at a time.
const LANES: usize = 8;

#[inline]
fn cell_coord(x: f64, size: f64) -> i64 {
    (x / size).floor() as i64
}

#[inline]
fn hash(c: [i64; 3], mask: u64) -> u32 {
    let h = (c[0] as u64).wrapping_mul(0x9E37_79B9_7F4A_7C15)
        ^ (c[1] as u64).wrapping_mul(0xC2B2_AE3D_27D4_EB4F)
        ^ (c[2] as u64).wrapping_mul(0x1656_67B1_9E37_79F9);
    ((h ^ (h >> 29)) & mask) as u32
}

impl CellList {
    /// Bins `n` points given by `position(i)` into cells of size `cell_size`.
    pub fn rebuild(&mut self, n: usize, cell_size: f64, position: impl Fn(usize) -> [f64; 3]) {
        self.positions.iter_mut().for_each(Vec::clear);
        self.cell_size = cell_size;
        let table = (2 * n).max(64).next_power_of_two();
        self.mask = table as u64 - 1;
        self.start.clear();
        self.start.resize(table + 1, 0);
        self.bucket_of.clear();
        self.bucket_of.extend((0..n).map(|i| {
            let x = position(i);
            hash(x.map(|v| cell_coord(v, cell_size)), self.mask)
        }));
        for &b in &self.bucket_of {
            self.start[b as usize + 1] += 1;
        }
        for b in 0..table {
            self.start[b + 1] += self.start[b];
        }
        self.sorted.clear();
        self.sorted.resize(n, 0);
        // Stable placement: a running cursor per bucket, reusing `start`
        // shifted by one bucket and restored afterwards.
        for i in 0..n {
            let b = self.bucket_of[i] as usize;
            let slot = self.start[b] as usize;
            self.sorted[slot] = i as u32;
            self.start[b] += 1;
        }
        for b in (1..=table).rev() {
            self.start[b] = self.start[b - 1];
        }
        self.start[0] = 0;
    }

    /// [`CellList::rebuild`], keeping each point's position (as
    /// `position(i)` gives it, the same bits) in the buckets' order for
    /// [`CellList::for_each_candidate_within`]: 24 more bytes per point.
    pub fn rebuild_with_positions(
        &mut self,
        n: usize,
        cell_size: f64,
        position: impl Fn(usize) -> [f64; 3],
    ) {
        self.rebuild(n, cell_size, &position);
        // Exactly n + LANES each, so the capacity (and `bytes_for`) is
        // what the list holds, not the next power of two.
        for p in &mut self.positions {
            p.reserve_exact(n + LANES);
        }
        let [px, py, pz] = &mut self.positions;
        for &i in &self.sorted {
            let y = position(i as usize);
            px.push(y[0]);
            py.push(y[1]);
            pz.push(y[2]);
        }
        for p in &mut self.positions {
            p.extend([0.0; LANES]);
        }
    }

    /// The number of points binned by [`CellList::rebuild_with_positions`],
    /// whose positions the list keeps; `None` for a list built without
    /// them (by [`CellList::rebuild`], or never built), which
    /// [`CellList::for_each_candidate_within`] cannot search.
    pub fn points_with_positions(&self) -> Option<usize> {
        let n = self.sorted.len();
        (self.positions.iter().all(|p| p.len() == n + LANES) && !self.start.is_empty()).then_some(n)
    }

    /// Heap bytes of the buffers as [`CellList::rebuild`] sizes them for
    /// `n` points (a bucket table of the power of two ≥ max(2n, 64) plus
    /// one `u32` starts, two `u32` per point), with the kept positions and
    /// their padding when `with_positions`.
    pub fn bytes_for(n: usize, with_positions: bool) -> usize {
        let table = (2 * n).max(64).next_power_of_two();
        let positions = if with_positions {
            (n + LANES) * std::mem::size_of::<[f64; 3]>()
        } else {
            0
        };
        (table + 1 + 2 * n) * std::mem::size_of::<u32>() + positions
    }

    /// Calls `bucket(range)` for the slots (ranges of `sorted`) of the
    /// distinct buckets of the 27 cells around `x`, in a fixed order.
    #[inline(always)]
    fn for_each_bucket(&self, x: [f64; 3], mut bucket: impl FnMut(std::ops::Range<usize>)) {
        let c = x.map(|v| cell_coord(v, self.cell_size));
        let mut seen = [u32::MAX; 27];
        let mut count = 0;
        for dz in -1..=1 {
            for dy in -1..=1 {
                for dx in -1..=1 {
                    let b = hash([c[0] + dx, c[1] + dy, c[2] + dz], self.mask);
                    if seen[..count].contains(&b) {
                        continue;
                    }
                    seen[count] = b;
                    count += 1;
                    bucket(self.start[b as usize] as usize..self.start[b as usize + 1] as usize);
                }
            }
        }
    }

    /// Calls `visit(j)` for every node binned in the 27 cells around `x`
    /// (each bucket once, even where two cells share a bucket). Candidates
    /// only: the caller checks distances.
    #[inline]
    pub fn for_each_candidate(&self, x: [f64; 3], mut visit: impl FnMut(usize)) {
        self.for_each_bucket(x, |range| {
            for &j in &self.sorted[range] {
                visit(j as usize);
            }
        });
    }

    /// The candidates of [`CellList::for_each_candidate`] within a reach:
    /// `visit(j, d, p²)` for every node j binned in the 27 cells around
    /// `x` whose kept position y_j gives d = y_j − x with
    /// p² = d₀² + d₁² + d₂² not ≥ `reach2` (so NaN passes, as a scalar
    /// `if p2 >= reach2 { skip }` lets it), in the order of
    /// [`CellList::for_each_candidate`]. A bucket's candidates are tested
    /// eight (`LANES`) at a time on the contiguous kept positions and the ones
    /// within reach visited in order, so the caller sees what a
    /// candidate-by-candidate test would give, to the bit. The list must
    /// have been built by [`CellList::rebuild_with_positions`] (checked: a
    /// list built without positions is a programming error, not an input
    /// one).
    #[inline]
    pub fn for_each_candidate_within(
        &self,
        x: [f64; 3],
        reach2: f64,
        mut visit: impl FnMut(usize, [f64; 3], f64),
    ) {
        let [px, py, pz] = &self.positions;
        assert_eq!(
            px.len(),
            self.sorted.len() + LANES,
            "cell list built without positions"
        );
        self.for_each_bucket(x, |range| {
            let mut start = range.start;
            while start < range.end {
                let lanes = start..start + LANES;
                let (ax, ay, az) = (&px[lanes.clone()], &py[lanes.clone()], &pz[lanes]);
                let mut d = [[0.0; LANES]; 3];
                let mut p2 = [0.0; LANES];
                let mut within = 0u32;
                for l in 0..LANES {
                    let dl = [ax[l] - x[0], ay[l] - x[1], az[l] - x[2]];
                    let q = dl[0] * dl[0] + dl[1] * dl[1] + dl[2] * dl[2];
                    d[0][l] = dl[0];
                    d[1][l] = dl[1];
                    d[2][l] = dl[2];
                    p2[l] = q;
                    within |= u32::from(!(q >= reach2)) << l;
                }
                let live = (range.end - start).min(LANES);
                within &= (1u32 << live) - 1;
                while within != 0 {
                    let l = within.trailing_zeros() as usize;
                    within &= within - 1;
                    visit(
                        self.sorted[start + l] as usize,
                        [d[0][l], d[1][l], d[2][l]],
                        p2[l],
                    );
                }
                start += LANES;
            }
        });
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_pair_within_the_cell_size_is_a_candidate() {
        // Pseudo-random points; brute force agrees with the cell list.
        let mut s = 12345u64;
        let mut rnd = || {
            s = s
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (s >> 11) as f64 / (1u64 << 53) as f64
        };
        let pts: Vec<[f64; 3]> = (0..400)
            .map(|_| [rnd() * 3.0, rnd() * 2.0, rnd() - 5.0])
            .collect();
        let mut cl = CellList::default();
        cl.rebuild(pts.len(), 0.3, |i| pts[i]);
        for (i, &x) in pts.iter().enumerate() {
            let mut found = Vec::new();
            cl.for_each_candidate(x, |j| {
                let d = (0..3)
                    .map(|k| (pts[j][k] - x[k]).powi(2))
                    .sum::<f64>()
                    .sqrt();
                if d < 0.3 {
                    found.push(j);
                }
            });
            found.sort();
            let before = found.len();
            found.dedup();
            assert_eq!(before, found.len(), "node {i} visited twice");
            let brute: Vec<usize> = (0..pts.len())
                .filter(|&j| {
                    (0..3)
                        .map(|k| (pts[j][k] - x[k]).powi(2))
                        .sum::<f64>()
                        .sqrt()
                        < 0.3
                })
                .collect();
            assert_eq!(found, brute);
        }
    }

    #[test]
    fn candidates_within_reach_come_in_order_with_the_bits_of_a_scalar_test() {
        let pts: Vec<[f64; 3]> = (0..300)
            .map(|i| {
                let t = i as f64;
                [(t * 0.37).sin() * 2.0, (t * 0.11).cos(), t * 0.01 - 1.0]
            })
            .collect();
        let mut plain = CellList::default();
        plain.rebuild(pts.len(), 0.25, |i| pts[i]);
        let mut kept = CellList::default();
        kept.rebuild_with_positions(pts.len(), 0.25, |i| pts[i]);
        let reach2 = 0.2 * 0.2;
        let mut pairs = 0;
        for &x in &pts {
            let mut a = Vec::new();
            plain.for_each_candidate(x, |j| {
                let d = [0, 1, 2].map(|c| pts[j][c] - x[c]);
                let p2 = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
                if !(p2 >= reach2) {
                    a.push((j, d.map(f64::to_bits), p2.to_bits()));
                }
            });
            let mut b = Vec::new();
            kept.for_each_candidate_within(x, reach2, |j, d, p2| {
                b.push((j, d.map(f64::to_bits), p2.to_bits()));
            });
            assert_eq!(a, b);
            pairs += a.len();
        }
        // Each point meets itself, and one point in two another.
        assert!(pairs > pts.len() + pts.len() / 2, "{pairs}");
        // Every candidate with an infinite reach.
        let x = pts[17];
        let mut a = Vec::new();
        plain.for_each_candidate(x, |j| a.push(j));
        let mut b = Vec::new();
        kept.for_each_candidate_within(x, f64::INFINITY, |j, _, _| b.push(j));
        assert_eq!(a, b);
        // A plain rebuild drops the kept positions.
        kept.rebuild(pts.len(), 0.25, |i| pts[i]);
        assert!(kept.positions.iter().all(Vec::is_empty));
        assert_eq!(
            CellList::bytes_for(pts.len(), true) - CellList::bytes_for(pts.len(), false),
            24 * (pts.len() + LANES)
        );
    }
}
