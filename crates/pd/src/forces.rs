//! The bond-force kernels: the sum in seed 004 eq 9, Σ_j f(η, ξ) V_j, for
//! every node, with proportional solids (eqs 7–8), failure, and the gas
//! pairwise force (eq 19).
//!
//! **Layout.** Node data is two arrays of `[f64; 4]`, one cache line pair
//! per neighbour visit: `reference[j] = (x_j, V_j)` (reference position and
//! volume) and `state[j] = (u_j, σ_j)` (displacement and one scalar per
//! node: the effective critical stretch of a solid node, or the gas
//! coefficient 6 P X^{4/3}/V of a gas node). Bonds are compressed rows
//! (`offsets`, `neighbours: u32`) with two `f32` per bond: `factor` (the
//! bond's quadrature weight β times its surface correction; 0 once broken)
//! and `plastic` (the plastic stretch s_p). That is 12 bytes per bond.
//!
//! **Loop.** One pass over nodes; each node sums its own row and writes
//! only its own outputs and its own copies of the bond state, so there are
//! no atomics and the result does not depend on the thread count. Both
//! copies of a bond see the same stretch bit for bit (|−a| = |a| and the
//! operations are the same), so they yield and break together.
//!
//! **Stretch without cancellation.** s = (p − r)/r is evaluated as
//! s = (2ξ·η + η·η) / (r (p + r)), which keeps full precision for the
//! tiny stretches of elastic waves.

use rayon::prelude::*;

/// The law a node's bonds follow.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum BondLaw {
    /// Proportional solid.
    Solid {
        /// Micro-modulus c, N/m⁶ (3D) — force per volume² per unit stretch.
        micromodulus: f64,
        /// Yield stretch s_Y (infinite: none).
        yield_stretch: f64,
        /// Micro-plastic (true) or micro-elastic (false).
        plastic: bool,
        /// Smallest critical stretch any node of this material can have
        /// (s_c0); below it no bond of the node can break.
        critical_stretch: f64,
    },
    /// Detonation products (eq 19); bonds never break.
    Gas,
}

/// What the force pass returns per node.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct NodeForce {
    /// Σ_j f V_j, N/m³ (force per unit volume of the node).
    pub force: [f64; 3],
    /// Smallest stretch among the node's intact bonds (solids).
    pub min_stretch: f64,
    /// Intact bonds after this pass.
    pub intact: u32,
}

/// Read-only inputs of the force pass.
#[derive(Debug, Clone, Copy)]
pub struct ForceInput<'a> {
    /// (x, V) per node.
    pub reference: &'a [[f64; 4]],
    /// (u, σ) per node.
    pub state: &'a [[f64; 4]],
    /// Row starts.
    pub offsets: &'a [u32],
    /// Neighbour indices.
    pub neighbours: &'a [u32],
    /// Material index per node.
    pub material: &'a [u16],
    /// Law per material.
    pub laws: &'a [BondLaw],
}

/// Nodes per parallel task.
const GRAIN: usize = 256;

#[inline(always)]
fn sub3(a: &[f64; 4], b: &[f64; 4]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

/// Bonds per lane group of the solid kernel.
const LANES: usize = 8;

/// Proportional-solid row: eq 8 with g = c (s − s_p) clamped by yield, and
/// irreversible failure.
///
/// Bonds are taken eight at a time: the gathers fill structure-of-arrays
/// lanes (a short last group is padded with inert lanes of weight 0), and
/// the rest is straight-line arithmetic over the eight lanes that the
/// compiler vectorises. Every lane goes through the same IEEE operations,
/// so a bond gives the same bits wherever it sits in a row, and the two
/// copies of a bond (in rows i and j) agree.
///
/// The stretch s = (2ξ·η + η·η)/(r(p + r)) (eq 7 without cancellation)
/// has its numerator formed in f64 from the f64 positions and is then
/// carried in f32 with r, p and 1/p: s keeps a relative precision of about
/// 10⁻⁷ however small it is, and the force magnitude is good to the same.
/// The force vector is accumulated in f64 per lane and summed over the
/// lanes in a fixed order at the end of the row.
#[inline(always)]
#[allow(clippy::too_many_arguments, clippy::needless_range_loop)]
fn solid_row(
    i: usize,
    input: &ForceInput,
    micromodulus: f64,
    yield_stretch: f64,
    plastic_law: bool,
    critical_stretch: f64,
    neighbours: &[u32],
    factor: &mut [f32],
    plastic: &mut [f32],
) -> NodeForce {
    let xi = input.reference[i];
    let ui = input.state[i];
    let sy = yield_stretch as f32;
    let sc0 = critical_stretch as f32;
    let sci = ui[3] as f32;
    let mut acc = [[0.0f64; LANES]; 3];
    let mut min_lane = [f32::INFINITY; LANES];
    let mut intact = 0u32;
    let len = neighbours.len();
    let mut start = 0;
    while start < len {
        let width = LANES.min(len - start);
        // Gather: reference offsets ξ, displacement differences η, V_j,
        // the neighbour's critical stretch and the bond state.
        let mut dx = [[0.0f64; LANES]; 3];
        let mut de = [[0.0f64; LANES]; 3];
        let mut vol = [0.0f64; LANES];
        let mut crit = [0f32; LANES];
        let mut w = [0f32; LANES];
        let mut sp = [0f32; LANES];
        dx[0] = [1.0; LANES];
        for l in 0..width {
            let j = neighbours[start + l] as usize;
            let xj = input.reference[j];
            let uj = input.state[j];
            for d in 0..3 {
                dx[d][l] = xj[d] - xi[d];
                de[d][l] = uj[d] - ui[d];
            }
            vol[l] = xj[3];
            crit[l] = uj[3] as f32;
            w[l] = factor[start + l];
            sp[l] = plastic[start + l];
        }
        // Lane arithmetic.
        let mut y = [[0.0f64; LANES]; 3];
        let mut s = [0f32; LANES];
        let mut inv_p = [0f32; LANES];
        let mut any_failure = false;
        for l in 0..LANES {
            for d in 0..3 {
                y[d][l] = dx[d][l] + de[d][l];
            }
            let num = 2.0 * (dx[0][l] * de[0][l] + dx[1][l] * de[1][l] + dx[2][l] * de[2][l])
                + (de[0][l] * de[0][l] + de[1][l] * de[1][l] + de[2][l] * de[2][l]);
            let r2 = dx[0][l] * dx[0][l] + dx[1][l] * dx[1][l] + dx[2][l] * dx[2][l];
            let p2 = y[0][l] * y[0][l] + y[1][l] * y[1][l] + y[2][l] * y[2][l];
            let r = (r2 as f32).sqrt();
            let p = (p2 as f32).sqrt().max(1e-6 * r);
            let inv = 1.0 / (r * p * (p + r));
            s[l] = (num as f32) * (p * inv);
            inv_p[l] = r * (p + r) * inv;
            any_failure |= (s[l] > sc0) & (w[l] != 0.0);
        }
        if any_failure {
            for l in 0..width {
                if w[l] != 0.0 && s[l] > sc0 && s[l] > sci.min(crit[l]) {
                    w[l] = 0.0;
                    factor[start + l] = 0.0;
                }
            }
        }
        let mut e = [0f32; LANES];
        if plastic_law {
            for l in 0..LANES {
                let el = s[l] - sp[l];
                let shifted = if el > sy {
                    s[l] - sy
                } else if el < -sy {
                    s[l] + sy
                } else {
                    sp[l]
                };
                sp[l] = shifted;
                e[l] = s[l] - shifted;
            }
            for l in 0..width {
                if w[l] != 0.0 {
                    plastic[start + l] = sp[l];
                }
            }
        } else {
            for l in 0..LANES {
                e[l] = s[l].clamp(-sy, sy);
            }
        }
        for l in 0..LANES {
            let g = (w[l] * e[l] * inv_p[l]) as f64 * vol[l];
            for d in 0..3 {
                acc[d][l] += g * y[d][l];
            }
            let live = w[l] != 0.0;
            intact += live as u32;
            min_lane[l] = if live {
                min_lane[l].min(s[l])
            } else {
                min_lane[l]
            };
        }
        start += width;
    }
    let mut f = [0.0f64; 3];
    for d in 0..3 {
        for l in 0..LANES {
            f[d] += acc[d][l];
        }
    }
    let min_stretch = min_lane.iter().fold(f32::INFINITY, |a, &b| a.min(b));
    NodeForce {
        force: f.map(|v| v * micromodulus),
        min_stretch: min_stretch as f64,
        intact,
    }
}

/// Gas row: the pair force between gas nodes i and j is the mean of the two
/// endpoint values of eq 19, ½(f_i + f_j), with f_i = −6 P_i r (X_i)^{4/3}
/// /(V_i p²) — odd, parallel to the bond, and exactly −∂/∂y of the stored
/// energy Σ W(X_i) V_i (see `docs/physics/pd/gas.md`). `state[j][3]` holds
/// 6 P_j X_j^{4/3}/V_j (0 before detonation).
#[inline(always)]
fn gas_row(i: usize, input: &ForceInput, neighbours: &[u32], factor: &[f32]) -> NodeForce {
    let xi = input.reference[i];
    let ui = input.state[i];
    let mut f = [0.0f64; 3];
    for (k, &j) in neighbours.iter().enumerate() {
        let j = j as usize;
        let xj = input.reference[j];
        let uj = input.state[j];
        let coef = 0.5 * (ui[3] + uj[3]);
        if coef == 0.0 {
            continue;
        }
        let xi_ = sub3(&xj, &xi);
        let eta = sub3(&uj, &ui);
        let y = [xi_[0] + eta[0], xi_[1] + eta[1], xi_[2] + eta[2]];
        let r = (xi_[0] * xi_[0] + xi_[1] * xi_[1] + xi_[2] * xi_[2]).sqrt();
        let p2 = (y[0] * y[0] + y[1] * y[1] + y[2] * y[2]).max(1e-30 * r * r);
        let p = p2.sqrt();
        // Force on i, repulsive: −coef r/p² along ê = y/p, times β V_j.
        let g = -coef * r * factor[k] as f64 * xj[3] / (p2 * p);
        f[0] += g * y[0];
        f[1] += g * y[1];
        f[2] += g * y[2];
    }
    NodeForce {
        force: f,
        min_stretch: 0.0,
        intact: neighbours.len() as u32,
    }
}

#[inline(always)]
fn rows_serial(
    nodes: std::ops::Range<usize>,
    input: &ForceInput,
    factor: &mut [f32],
    plastic: &mut [f32],
    out: &mut [NodeForce],
) {
    let base = input.offsets[nodes.start] as usize;
    for (o, i) in out.iter_mut().zip(nodes) {
        let row = input.offsets[i] as usize - base..input.offsets[i + 1] as usize - base;
        let nb = &input.neighbours[row.start + base..row.end + base];
        *o = match input.laws[input.material[i] as usize] {
            BondLaw::Solid {
                micromodulus,
                yield_stretch,
                plastic: pl,
                critical_stretch,
            } => solid_row(
                i,
                input,
                micromodulus,
                yield_stretch,
                pl,
                critical_stretch,
                nb,
                &mut factor[row.clone()],
                &mut plastic[row],
            ),
            BondLaw::Gas => gas_row(i, input, nb, &factor[row]),
        };
    }
}

/// A serial pass over a node range, compiled for one instruction set.
type RowsFn = fn(std::ops::Range<usize>, &ForceInput, &mut [f32], &mut [f32], &mut [NodeForce]);

/// [`rows_serial`] compiled with AVX2 (the same IEEE operations: Rust
/// never fuses a multiply and an add on its own, so the bits are those of
/// the baseline build, only computed four or eight lanes at a time).
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
unsafe fn rows_serial_avx2(
    nodes: std::ops::Range<usize>,
    input: &ForceInput,
    factor: &mut [f32],
    plastic: &mut [f32],
    out: &mut [NodeForce],
) {
    rows_serial(nodes, input, factor, plastic, out)
}

/// [`rows_serial`] compiled with AVX-512 (same bits, see above).
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx512f,avx512vl,avx512dq,avx2")]
unsafe fn rows_serial_avx512(
    nodes: std::ops::Range<usize>,
    input: &ForceInput,
    factor: &mut [f32],
    plastic: &mut [f32],
    out: &mut [NodeForce],
) {
    rows_serial(nodes, input, factor, plastic, out)
}

/// The widest build of the row pass this processor runs.
fn rows_for_this_cpu() -> RowsFn {
    #[cfg(target_arch = "x86_64")]
    {
        if std::arch::is_x86_feature_detected!("avx512f")
            && std::arch::is_x86_feature_detected!("avx512vl")
            && std::arch::is_x86_feature_detected!("avx512dq")
        {
            // SAFETY: the features the function was compiled for are present.
            return |n, i, f, p, o| unsafe { rows_serial_avx512(n, i, f, p, o) };
        }
        if std::arch::is_x86_feature_detected!("avx2") {
            // SAFETY: as above.
            return |n, i, f, p, o| unsafe { rows_serial_avx2(n, i, f, p, o) };
        }
    }
    rows_serial
}

fn rows_parallel(
    rows: RowsFn,
    nodes: std::ops::Range<usize>,
    input: &ForceInput,
    factor: &mut [f32],
    plastic: &mut [f32],
    out: &mut [NodeForce],
) {
    if nodes.len() <= GRAIN {
        rows(nodes, input, factor, plastic, out);
        return;
    }
    let mid = nodes.start + nodes.len() / 2;
    let split = (input.offsets[mid] - input.offsets[nodes.start]) as usize;
    let (fa, fb) = factor.split_at_mut(split);
    let (pa, pb) = plastic.split_at_mut(split);
    let (oa, ob) = out.split_at_mut(mid - nodes.start);
    rayon::join(
        || rows_parallel(rows, nodes.start..mid, input, fa, pa, oa),
        || rows_parallel(rows, mid..nodes.end, input, fb, pb, ob),
    );
}

/// The bond-force pass over all nodes: fills `out` (one entry per node),
/// breaks bonds (factor → 0) and updates plastic stretches. Deterministic
/// and allocation-free.
pub fn bond_forces(
    input: &ForceInput,
    factor: &mut [f32],
    plastic: &mut [f32],
    out: &mut [NodeForce],
) {
    let n = out.len();
    assert_eq!(input.offsets.len(), n + 1, "one row per node");
    assert_eq!(factor.len(), input.neighbours.len());
    assert_eq!(plastic.len(), input.neighbours.len());
    rows_parallel(rows_for_this_cpu(), 0..n, input, factor, plastic, out);
}

/// Gas state of a node from its family (seed 004 eq 17):
/// X = [Σ_j (r_j/p_j) β_j V_j / V]^{−3}, V = Σ_j β_j V_j.
/// Returns (X, Σ_j β_j V_j r_j / p_j³ · r_j-weighted stiffness terms) as
/// (X, Σ_j β_j V_j r_j/p_j³, Σ_j β_j V_j r_j²/p_j⁴) for the stable step.
#[inline]
pub fn gas_expansion(
    i: usize,
    reference: &[[f64; 4]],
    state: &[[f64; 4]],
    neighbours: &[u32],
    factor: &[f32],
    family_volume: f64,
) -> (f64, f64, f64) {
    let xi = reference[i];
    let ui = state[i];
    let (mut sum, mut s3, mut s4) = (0.0, 0.0, 0.0);
    for (k, &j) in neighbours.iter().enumerate() {
        let j = j as usize;
        let xj = reference[j];
        let uj = state[j];
        let xi_ = sub3(&xj, &xi);
        let eta = sub3(&uj, &ui);
        let y = [xi_[0] + eta[0], xi_[1] + eta[1], xi_[2] + eta[2]];
        let r = (xi_[0] * xi_[0] + xi_[1] * xi_[1] + xi_[2] * xi_[2]).sqrt();
        let p = (y[0] * y[0] + y[1] * y[1] + y[2] * y[2])
            .sqrt()
            .max(1e-15 * r);
        let bv = factor[k] as f64 * xj[3];
        let q = r / p;
        sum += q * bv;
        s3 += q / (p * p) * bv;
        s4 += q * q / (p * p) * bv;
    }
    let x = if sum > 0.0 {
        (sum / family_volume).powi(-3)
    } else {
        1.0
    };
    (x, s3, s4)
}

/// Parallel map over nodes writing one output each (deterministic).
pub fn for_each_node<T: Send>(out: &mut [T], f: impl Fn(usize, &mut T) + Sync) {
    out.par_iter_mut()
        .with_min_len(GRAIN)
        .enumerate()
        .for_each(|(i, o)| f(i, o));
}

#[cfg(test)]
mod tests;
