//! A hashed cell list: nodes binned by cells of a given size, found by
//! visiting the 27 cells around a point. Building it is a counting sort
//! (O(N), stable, so every bucket lists its nodes in ascending index) into
//! a table of 2^k buckets, so nodes that fly far apart never make the table
//! grow with the bounding box. Used once for the families (reference
//! positions) and at every step for the short-range forces (current
//! positions); rebuilding reuses the buffers and allocates nothing once
//! they are large enough.

/// The cell list.
#[derive(Debug, Clone, Default)]
pub struct CellList {
    cell_size: f64,
    mask: u64,
    start: Vec<u32>,
    sorted: Vec<u32>,
    bucket_of: Vec<u32>,
}

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

    /// Calls `visit(j)` for every node binned in the 27 cells around `x`
    /// (each bucket once, even where two cells share a bucket). Candidates
    /// only: the caller checks distances.
    #[inline]
    pub fn for_each_candidate(&self, x: [f64; 3], mut visit: impl FnMut(usize)) {
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
                    let range =
                        self.start[b as usize] as usize..self.start[b as usize + 1] as usize;
                    for &j in &self.sorted[range] {
                        visit(j as usize);
                    }
                }
            }
        }
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
}
