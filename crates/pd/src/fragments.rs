//! Fragments: connected components of solid nodes over intact bonds
//! (seed 004, "Fragmenting-Cylinder Test"), their masses, velocities and
//! the cumulative mass distribution (CMD).

use crate::family::Families;
use brisance_core::ExactSum;
use std::io::Write;

/// One fragment.
#[derive(Debug, Clone, PartialEq)]
pub struct Fragment {
    /// Mass, kg.
    pub mass: f64,
    /// Mass-weighted mean velocity, m/s.
    pub velocity: [f64; 3],
    /// Number of nodes.
    pub nodes: usize,
    /// Smallest node index (the fragment's label).
    pub label: usize,
}

fn root(parent: &mut [u32], mut i: usize) -> usize {
    while parent[i] as usize != i {
        let p = parent[i] as usize;
        parent[i] = parent[p];
        i = p;
    }
    i
}

/// The fragment of every node: the smallest node index of its connected
/// component over bonds with `factor != 0` among the nodes with
/// `solid[i]` (`usize::MAX` for the others).
pub fn fragment_labels(families: &Families, factor: &[f32], solid: &[bool]) -> Vec<usize> {
    let n = solid.len();
    let mut parent: Vec<u32> = (0..n as u32).collect();
    for i in 0..n {
        if !solid[i] {
            continue;
        }
        for k in families.row(i) {
            let j = families.neighbours[k] as usize;
            if factor[k] == 0.0 || !solid[j] {
                continue;
            }
            let (a, b) = (root(&mut parent, i), root(&mut parent, j));
            if a != b {
                let (lo, hi) = (a.min(b), a.max(b));
                parent[hi] = lo as u32;
            }
        }
    }
    (0..n)
        .map(|i| {
            if solid[i] {
                root(&mut parent, i)
            } else {
                usize::MAX
            }
        })
        .collect()
}

/// Connected components of the nodes with `solid[i]` over bonds with
/// `factor != 0` ([`fragment_labels`]), sorted by decreasing mass (ties by
/// label). Deterministic: a component's label is its smallest node index;
/// each fragment's mass is its nodes' masses summed exactly and rounded
/// once (so the fragments' masses add up to the case's to the rounding of
/// each), its momentum summed in node order.
pub fn find_fragments(
    families: &Families,
    factor: &[f32],
    solid: &[bool],
    mass: &[f64],
    velocity: &[[f64; 3]],
) -> Vec<Fragment> {
    let n = solid.len();
    let labels = fragment_labels(families, factor, solid);
    let mut index = vec![usize::MAX; n];
    let mut out: Vec<Fragment> = Vec::new();
    let mut masses: Vec<ExactSum> = Vec::new();
    for i in 0..n {
        if !solid[i] {
            continue;
        }
        let r = labels[i];
        if index[r] == usize::MAX {
            index[r] = out.len();
            out.push(Fragment {
                mass: 0.0,
                velocity: [0.0; 3],
                nodes: 0,
                label: r,
            });
            masses.push(ExactSum::new());
        }
        masses[index[r]].add(mass[i]);
        let f = &mut out[index[r]];
        f.nodes += 1;
        for (p, v) in f.velocity.iter_mut().zip(velocity[i]) {
            *p += mass[i] * v;
        }
    }
    for (f, m) in out.iter_mut().zip(&masses) {
        f.mass = m.value();
        f.velocity = f.velocity.map(|p| p / f.mass);
    }
    out.sort_by(|a, b| b.mass.total_cmp(&a.mass).then(a.label.cmp(&b.label)));
    out
}

/// One point of the cumulative mass distribution.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CmdPoint {
    /// Fragment mass m, kg.
    pub mass: f64,
    /// Number of fragments with mass ≥ m.
    pub count_at_least: usize,
    /// Fraction of the total fragment mass in fragments of mass ≥ m.
    pub mass_fraction_at_least: f64,
}

/// The CMD of fragments sorted by decreasing mass (as [`find_fragments`]
/// returns them).
pub fn cumulative_mass_distribution(fragments: &[Fragment]) -> Vec<CmdPoint> {
    let total: f64 = fragments.iter().map(|f| f.mass).sum();
    let mut acc = 0.0;
    fragments
        .iter()
        .enumerate()
        .map(|(k, f)| {
            acc += f.mass;
            CmdPoint {
                mass: f.mass,
                count_at_least: k + 1,
                mass_fraction_at_least: acc / total,
            }
        })
        .collect()
}

fn create(path: &std::path::Path) -> std::io::Result<std::io::BufWriter<std::fs::File>> {
    if let Some(dir) = path.parent() {
        std::fs::create_dir_all(dir)?;
    }
    Ok(std::io::BufWriter::new(std::fs::File::create(path)?))
}

/// Writes the fragments as CSV, one row per fragment in the given order
/// (largest first as [`find_fragments`] returns them): rank, mass (kg),
/// node count, mass-weighted velocity (m/s) and speed.
pub fn write_fragments_csv(path: &std::path::Path, fragments: &[Fragment]) -> std::io::Result<()> {
    let mut w = create(path)?;
    writeln!(
        w,
        "rank,mass_kg,nodes,velocity_x,velocity_y,velocity_z,speed"
    )?;
    for (k, f) in fragments.iter().enumerate() {
        let v = f.velocity;
        writeln!(
            w,
            "{},{:e},{},{:e},{:e},{:e},{:e}",
            k + 1,
            f.mass,
            f.nodes,
            v[0],
            v[1],
            v[2],
            (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt(),
        )?;
    }
    w.flush()
}

/// Writes the cumulative mass distribution of `fragments` (sorted by
/// decreasing mass) as CSV: fragment mass m (kg), the number of fragments
/// of mass ≥ m, and the fraction of the fragment mass they hold.
pub fn write_cmd_csv(path: &std::path::Path, fragments: &[Fragment]) -> std::io::Result<()> {
    let mut w = create(path)?;
    writeln!(w, "mass_kg,count_at_least,mass_fraction_at_least")?;
    for c in cumulative_mass_distribution(fragments) {
        writeln!(
            w,
            "{:e},{},{:e}",
            c.mass, c.count_at_least, c.mass_fraction_at_least
        )?;
    }
    w.flush()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_chain_cut_in_two_gives_two_fragments_with_their_momentum() {
        // 0-1-2 | 3-4 : bond 2-3 broken; node 5 is a gas node.
        let f = Families {
            offsets: vec![0, 1, 3, 5, 7, 8, 8],
            neighbours: vec![1, 0, 2, 1, 3, 2, 4, 3],
        };
        let factor = [1.0, 1.0, 1.0, 1.0, 0.0, 0.0, 1.0, 1.0];
        let solid = [true, true, true, true, true, false];
        let mass = [1.0, 2.0, 3.0, 4.0, 5.0, 100.0];
        let v = [
            [1.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.0, 2.0, 0.0],
            [0.0, -1.0, 0.0],
            [9.0; 3],
        ];
        let fr = find_fragments(&f, &factor, &solid, &mass, &v);
        assert_eq!(fr.len(), 2);
        assert_eq!(fr[0].mass, 9.0);
        assert_eq!(fr[0].label, 3);
        assert!((fr[0].velocity[1] - (8.0 - 5.0) / 9.0).abs() < 1e-15);
        assert_eq!(fr[1].mass, 6.0);
        assert_eq!(fr[1].velocity, [1.0, 0.0, 0.0]);
        let cmd = cumulative_mass_distribution(&fr);
        assert_eq!(cmd[1].count_at_least, 2);
        assert!((cmd[0].mass_fraction_at_least - 0.6).abs() < 1e-15);
        assert_eq!(cmd[1].mass_fraction_at_least, 1.0);
    }

    fn two_fragments() -> Vec<Fragment> {
        vec![
            Fragment {
                mass: 3.0,
                velocity: [3.0, 4.0, 0.0],
                nodes: 3,
                label: 0,
            },
            Fragment {
                mass: 1.0,
                velocity: [0.0, 0.0, -2.0],
                nodes: 1,
                label: 5,
            },
        ]
    }

    #[test]
    fn fragment_and_cmd_csv_hold_one_row_per_fragment() {
        let dir = std::env::temp_dir().join(format!("brisance_pd_frag_csv_{}", std::process::id()));
        let f = two_fragments();
        write_fragments_csv(&dir.join("a/fragments.csv"), &f).unwrap();
        write_cmd_csv(&dir.join("a/cmd.csv"), &f).unwrap();
        let frag = std::fs::read_to_string(dir.join("a/fragments.csv")).unwrap();
        assert_eq!(
            frag,
            "rank,mass_kg,nodes,velocity_x,velocity_y,velocity_z,speed\n\
             1,3e0,3,3e0,4e0,0e0,5e0\n\
             2,1e0,1,0e0,0e0,-2e0,2e0\n"
        );
        let cmd = std::fs::read_to_string(dir.join("a/cmd.csv")).unwrap();
        assert_eq!(
            cmd,
            "mass_kg,count_at_least,mass_fraction_at_least\n3e0,1,7.5e-1\n1e0,2,1e0\n"
        );
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
