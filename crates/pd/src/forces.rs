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
//!
//! **Instruction sets.** Solid rows run in groups of eight bonds; the
//! gather and the group arithmetic have portable, AVX2 and AVX-512 forms
//! that perform the same IEEE operations in the same order, so the choice
//! made at run time never changes a bit (tested). Layout, loop, memory
//! and measured throughput: `docs/physics/pd/kernel.md`.

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
    /// Smallest stretch among the node's intact bonds (solids); the
    /// kernel forms stretches in f32, so it is kept at that precision.
    pub min_stretch: f32,
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
    /// A products node's pairs with solid nodes carry its c in full
    /// (`crate::ProductsFamily::MirroredWall`) rather than its own half.
    pub mirror_walls: bool,
}

/// Nodes per parallel task.
const GRAIN: usize = 256;

#[inline(always)]
fn sub3(a: &[f64; 4], b: &[f64; 4]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

/// Bonds per lane group of the solid kernel.
const LANES: usize = 8;

/// The constants of a solid row: the law and the node's own data.
#[derive(Clone, Copy)]
struct SolidRow {
    xi: [f64; 4],
    ui: [f64; 4],
    yield_stretch: f32,
    critical_stretch: f32,
    node_critical_stretch: f32,
    plastic: bool,
}

/// Per-lane running sums of a solid row.
struct SolidSums {
    force: [[f64; LANES]; 3],
    min_stretch: [f32; LANES],
    intact: [u32; LANES],
    /// Σ β r (s_Y |Δs_p| + ψ_broken) V_j: the energy this pass dissipated
    /// in the row's bonds, before the factor ½ c V_i ([`solid_row`]).
    dissipated: [f64; LANES],
}

/// The neighbour data of one group of bonds in structure-of-arrays lanes:
/// reference offsets ξ = x_j − x_i, volumes V_j, displacement differences
/// η = u_j − u_i and the neighbours' scalars σ_j (`state[j][3]`).
struct Gathered {
    x: [[f64; LANES]; 3],
    vol: [f64; LANES],
    u: [[f64; LANES]; 3],
    sigma: [f64; LANES],
}

/// How a group's neighbour data is fetched. Both ways copy the same
/// values, so the choice never changes a bit of the result.
trait Gather {
    /// Fills the lanes with `reference[js[l]] − xi` and `state[js[l]] −
    /// ui` (the last components of `xi` and `ui` are 0); every `js[l]`
    /// must be below `reference.len()` and `state.len()`.
    fn gather(
        reference: &[[f64; 4]],
        state: &[[f64; 4]],
        js: &[usize; LANES],
        xi: [f64; 4],
        ui: [f64; 4],
    ) -> Gathered;

    /// One group of a solid row: [`solid_group`] with this gather, unless
    /// an instruction set has its own form (same bits).
    #[inline(always)]
    fn solid_group(
        row: &SolidRow,
        reference: &[[f64; 4]],
        state: &[[f64; 4]],
        js: &[u32; LANES],
        w_io: &mut [f32; LANES],
        sp_io: &mut [f32; LANES],
        sums: &mut SolidSums,
    ) where
        Self: Sized,
    {
        solid_group::<Self>(row, reference, state, js, w_io, sp_io, sums)
    }
}

/// One element at a time (any processor).
struct ScalarGather;

impl Gather for ScalarGather {
    #[inline(always)]
    #[allow(clippy::needless_range_loop)]
    fn gather(
        reference: &[[f64; 4]],
        state: &[[f64; 4]],
        js: &[usize; LANES],
        xi: [f64; 4],
        ui: [f64; 4],
    ) -> Gathered {
        let mut g = Gathered {
            x: [[0.0; LANES]; 3],
            vol: [0.0; LANES],
            u: [[0.0; LANES]; 3],
            sigma: [0.0; LANES],
        };
        for l in 0..LANES {
            let xj = reference[js[l]];
            let uj = state[js[l]];
            for d in 0..3 {
                g.x[d][l] = xj[d] - xi[d];
                g.u[d][l] = uj[d] - ui[d];
            }
            g.vol[l] = xj[3] - xi[3];
            g.sigma[l] = uj[3] - ui[3];
        }
        g
    }
}

/// Whole 32-byte node records loaded as AVX vectors and transposed four
/// at a time (two unpacks and two lane permutes per four values), instead
/// of one insert per value. Only instantiated inside functions compiled
/// with AVX2, which the dispatch checks at run time.
#[cfg(target_arch = "x86_64")]
struct AvxGather;

#[cfg(target_arch = "x86_64")]
impl Gather for AvxGather {
    #[inline(always)]
    fn gather(
        reference: &[[f64; 4]],
        state: &[[f64; 4]],
        js: &[usize; LANES],
        xi: [f64; 4],
        ui: [f64; 4],
    ) -> Gathered {
        use std::arch::x86_64::*;
        // Every index clamped to both arrays (the identity for the valid
        // indices the trait asks for, and branch-free: an `assert!` over
        // the eight lanes here slowed the kernel by a third).
        let last = reference.len().min(state.len()) - 1;
        let js = &js.map(|j| j.min(last));
        let mut g = Gathered {
            x: [[0.0; LANES]; 3],
            vol: [0.0; LANES],
            u: [[0.0; LANES]; 3],
            sigma: [0.0; LANES],
        };
        // SAFETY: AvxGather is only used by `rows_serial_avx2` and
        // `rows_serial_avx512`, which run after the processor was checked
        // for AVX2; every index is in bounds (clamped above), and the
        // unaligned loads and stores read and write 4 f64 inside
        // `[f64; 4]` records and `[f64; LANES]` arrays at offsets 0 and 4.
        unsafe {
            #[inline(always)]
            unsafe fn transpose(
                rows: [__m256d; 4],
                out: [&mut [f64; LANES]; 4],
                half: usize,
                origin: [f64; 4],
            ) {
                let o = origin.map(|v| _mm256_set1_pd(v));
                let t0 = _mm256_unpacklo_pd(rows[0], rows[1]);
                let t1 = _mm256_unpackhi_pd(rows[0], rows[1]);
                let t2 = _mm256_unpacklo_pd(rows[2], rows[3]);
                let t3 = _mm256_unpackhi_pd(rows[2], rows[3]);
                let [a, b, c, d] = out;
                _mm256_storeu_pd(
                    a.as_mut_ptr().add(4 * half),
                    _mm256_sub_pd(_mm256_permute2f128_pd::<0x20>(t0, t2), o[0]),
                );
                _mm256_storeu_pd(
                    b.as_mut_ptr().add(4 * half),
                    _mm256_sub_pd(_mm256_permute2f128_pd::<0x20>(t1, t3), o[1]),
                );
                _mm256_storeu_pd(
                    c.as_mut_ptr().add(4 * half),
                    _mm256_sub_pd(_mm256_permute2f128_pd::<0x31>(t0, t2), o[2]),
                );
                _mm256_storeu_pd(
                    d.as_mut_ptr().add(4 * half),
                    _mm256_sub_pd(_mm256_permute2f128_pd::<0x31>(t1, t3), o[3]),
                );
            }
            let rp = reference.as_ptr();
            let sp = state.as_ptr();
            for half in 0..2 {
                let j = &js[4 * half..4 * half + 4];
                let r = [0, 1, 2, 3].map(|l| _mm256_loadu_pd(rp.add(j[l]) as *const f64));
                let [x0, x1, x2] = &mut g.x;
                transpose(r, [x0, x1, x2, &mut g.vol], half, xi);
                let s = [0, 1, 2, 3].map(|l| _mm256_loadu_pd(sp.add(j[l]) as *const f64));
                let [u0, u1, u2] = &mut g.u;
                transpose(s, [u0, u1, u2, &mut g.sigma], half, ui);
            }
        }
        g
    }
}

/// The AVX-512 kernel: whole solid groups in explicit 512-bit intrinsics
/// (`forces/avx512.rs`). Only instantiated inside functions compiled with
/// AVX-512F/VL/DQ, which the dispatch checks at run time.
#[cfg(target_arch = "x86_64")]
struct Avx512Gather;

#[cfg(target_arch = "x86_64")]
impl Gather for Avx512Gather {
    #[inline(always)]
    fn gather(
        reference: &[[f64; 4]],
        state: &[[f64; 4]],
        js: &[usize; LANES],
        xi: [f64; 4],
        ui: [f64; 4],
    ) -> Gathered {
        // Not reached by the solid rows (they use the whole-group form
        // below); kept so the trait is complete.
        ScalarGather::gather(reference, state, js, xi, ui)
    }

    #[inline(always)]
    fn solid_group(
        row: &SolidRow,
        reference: &[[f64; 4]],
        state: &[[f64; 4]],
        js: &[u32; LANES],
        w_io: &mut [f32; LANES],
        sp_io: &mut [f32; LANES],
        sums: &mut SolidSums,
    ) {
        let last = reference.len().min(state.len()) - 1;
        let js = js.map(|j| (j as usize).min(last));
        // SAFETY: Avx512Gather is only used by `rows_serial_avx512`, which
        // runs after the processor was checked for AVX-512F/VL/DQ and AVX2;
        // every index was clamped to both arrays just above.
        unsafe { avx512::solid_group(row, reference, state, &js, w_io, sp_io, sums) }
    }
}

/// One group of eight bonds of a solid row (see [`solid_row`]). `js` are
/// the neighbours (already known to be valid indices), `w` and `sp` the
/// bonds' factors and plastic stretches, updated in place.
#[inline(always)]
#[allow(clippy::needless_range_loop)]
fn solid_group<G: Gather>(
    row: &SolidRow,
    reference: &[[f64; 4]],
    state: &[[f64; 4]],
    js: &[u32; LANES],
    w_io: &mut [f32; LANES],
    sp_io: &mut [f32; LANES],
    sums: &mut SolidSums,
) {
    let (xi, ui) = (row.xi, row.ui);
    // Gather, then reference offsets ξ, displacement differences η, V_j
    // and the neighbour's critical stretch. The index is clamped to the
    // arrays, which is the identity for valid rows and lets the compiler
    // drop the bounds checks.
    let last = reference.len().min(state.len()) - 1;
    let g = G::gather(
        reference,
        state,
        &js.map(|j| (j as usize).min(last)),
        [xi[0], xi[1], xi[2], 0.0],
        [ui[0], ui[1], ui[2], 0.0],
    );
    let (dx, de, vol) = (&g.x, &g.u, &g.vol);
    let crit = g.sigma.map(|v| v as f32);
    let w_old = *w_io;
    let mut w = w_old;
    // Lane arithmetic.
    let mut y = [[0.0f64; LANES]; 3];
    let mut s = [0f32; LANES];
    let mut rr = [0f32; LANES];
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
        rr[l] = r;
        any_failure |= (s[l] > row.critical_stretch) & (w[l] != 0.0);
    }
    let mut broke = false;
    if any_failure {
        let sci = row.node_critical_stretch;
        for l in 0..LANES {
            if w[l] != 0.0 && s[l] > row.critical_stretch && s[l] > sci.min(crit[l]) {
                w[l] = 0.0;
                broke = true;
            }
        }
        *w_io = w;
    }
    let sy = row.yield_stretch;
    let mut e = [0f32; LANES];
    // s_Y |Δs_p|: the plastic flow of this pass times the yield stretch.
    let mut flow = [0f32; LANES];
    if row.plastic {
        let mut sp = *sp_io;
        for l in 0..LANES {
            let el = s[l] - sp[l];
            let shifted = if el > sy {
                s[l] - sy
            } else if el < -sy {
                s[l] + sy
            } else {
                sp[l]
            };
            e[l] = s[l] - shifted;
            flow[l] = sy * (shifted - sp[l]).abs();
            // A broken bond keeps its last plastic stretch.
            sp[l] = if w[l] != 0.0 { shifted } else { sp[l] };
        }
        *sp_io = sp;
    } else {
        for l in 0..LANES {
            e[l] = s[l].clamp(-sy, sy);
        }
    }
    // The energy the pass dissipates: the plastic work s_Y |Δs_p| of a
    // yielding bond, and all a bond breaking now held, ψ = |e| (a − |e|/2)
    // with a = |e| (micro-plastic: ½ e²) or |s| (micro-elastic: ½ s²
    // below yield, s_Y (|s| − s_Y/2) above), as `PdSolver::bond_energy`
    // counts it. Bonds broken before this pass (β = 0) add nothing.
    if row.plastic || broke {
        for l in 0..LANES {
            let a = e[l].abs();
            let stretch = if row.plastic { a } else { s[l].abs() };
            let psi = if w[l] == 0.0 {
                a * (stretch - 0.5 * a)
            } else {
                0.0
            };
            sums.dissipated[l] += ((w_old[l] * (flow[l] + psi)) * rr[l]) as f64 * vol[l];
        }
    }
    for l in 0..LANES {
        let g = (w[l] * e[l] * inv_p[l]) as f64 * vol[l];
        for d in 0..3 {
            sums.force[d][l] += g * y[d][l];
        }
        let live = w[l] != 0.0;
        sums.intact[l] += live as u32;
        sums.min_stretch[l] = if live {
            sums.min_stretch[l].min(s[l])
        } else {
            sums.min_stretch[l]
        };
    }
}

/// Proportional-solid row: eq 8 with g = c (s − s_p) clamped by yield, and
/// irreversible failure.
///
/// Bonds are taken eight at a time (`chunks_exact`): the gathers fill
/// structure-of-arrays lanes, and the rest is straight-line arithmetic
/// over the eight lanes that the compiler vectorises. A short last group
/// is padded with copies of the row's last neighbour at weight 0, which
/// add exactly zero. Every lane goes through the same IEEE operations, so
/// a bond gives the same bits wherever it sits in a row, and the two
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
fn solid_row<G: Gather>(
    i: usize,
    input: &ForceInput,
    micromodulus: f64,
    yield_stretch: f64,
    plastic_law: bool,
    critical_stretch: f64,
    neighbours: &[u32],
    factor: &mut [f32],
    plastic: &mut [f32],
) -> (NodeForce, f32) {
    let row = SolidRow {
        xi: input.reference[i],
        ui: input.state[i],
        yield_stretch: yield_stretch as f32,
        critical_stretch: critical_stretch as f32,
        node_critical_stretch: input.state[i][3] as f32,
        plastic: plastic_law,
    };
    // The row's groups compiled twice, with the law's plastic flag a
    // constant in each: no test of it inside the group loop.
    let sums = if plastic_law {
        solid_groups::<G>(
            &SolidRow {
                plastic: true,
                ..row
            },
            input,
            neighbours,
            factor,
            plastic,
        )
    } else {
        solid_groups::<G>(
            &SolidRow {
                plastic: false,
                ..row
            },
            input,
            neighbours,
            factor,
            plastic,
        )
    };
    let mut f = [0.0f64; 3];
    for d in 0..3 {
        for l in 0..LANES {
            f[d] += sums.force[d][l];
        }
    }
    let min_stretch = sums
        .min_stretch
        .iter()
        .fold(f32::INFINITY, |a, &b| a.min(b));
    let dissipated = 0.5 * row.xi[3] * micromodulus * sums.dissipated.iter().sum::<f64>();
    (
        NodeForce {
            force: f.map(|v| v * micromodulus),
            min_stretch,
            intact: sums.intact.iter().sum(),
        },
        dissipated as f32,
    )
}

/// The groups of eight bonds of one solid row ([`solid_row`]), their
/// per-lane sums.
#[inline(always)]
fn solid_groups<G: Gather>(
    row: &SolidRow,
    input: &ForceInput,
    neighbours: &[u32],
    factor: &mut [f32],
    plastic: &mut [f32],
) -> SolidSums {
    let mut sums = SolidSums {
        force: [[0.0; LANES]; 3],
        min_stretch: [f32::INFINITY; LANES],
        intact: [0; LANES],
        dissipated: [0.0; LANES],
    };
    let (reference, state) = (input.reference, input.state);
    let len = neighbours.len().min(factor.len()).min(plastic.len());
    let (neighbours, factor, plastic) =
        (&neighbours[..len], &mut factor[..len], &mut plastic[..len]);
    let mut js = neighbours.chunks_exact(LANES);
    let mut ws = factor.chunks_exact_mut(LANES);
    let mut sps = plastic.chunks_exact_mut(LANES);
    for ((j, w), sp) in (&mut js).zip(&mut ws).zip(&mut sps) {
        // The chunks are exactly LANES long.
        let j: &[u32; LANES] = j.try_into().unwrap_or(&[0; LANES]);
        let w: &mut [f32; LANES] = w.try_into().expect("chunk of LANES");
        let sp: &mut [f32; LANES] = sp.try_into().expect("chunk of LANES");
        G::solid_group(row, reference, state, j, w, sp, &mut sums);
    }
    let (jt, wt, spt) = (js.remainder(), ws.into_remainder(), sps.into_remainder());
    if let Some(&pad) = jt.last() {
        let mut j = [pad; LANES];
        let mut w = [0f32; LANES];
        let mut sp = [0f32; LANES];
        let n = jt.len();
        j[..n].copy_from_slice(jt);
        w[..n].copy_from_slice(wt);
        sp[..n].copy_from_slice(spt);
        G::solid_group(row, reference, state, &j, &mut w, &mut sp, &mut sums);
        wt.copy_from_slice(&w[..n]);
        spt.copy_from_slice(&sp[..n]);
    }
    sums
}

/// A products pair seen from node i: the current bond vector
/// y = x_j + u_j − x_i − u_i, the reference length r and p³ (p = |y|,
/// floored at 1e-15 r so a collapsed pair stays finite). Shared by the
/// gas row and the one-sided reaction on a solid node, so both sides of a
/// pair use the same arithmetic.
#[inline(always)]
fn gas_pair(xi: &[f64; 4], ui: &[f64; 4], xj: &[f64; 4], uj: &[f64; 4]) -> ([f64; 3], f64, f64) {
    let xi_ = sub3(xj, xi);
    let eta = sub3(uj, ui);
    let y = [xi_[0] + eta[0], xi_[1] + eta[1], xi_[2] + eta[2]];
    let r = (xi_[0] * xi_[0] + xi_[1] * xi_[1] + xi_[2] * xi_[2]).sqrt();
    let p2 = (y[0] * y[0] + y[1] * y[1] + y[2] * y[2]).max(1e-30 * r * r);
    (y, r, p2 * p2.sqrt())
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
        // A solid neighbour (a case node in the products' family,
        // `crate::ProductsFamily::WithSolids`) has no c: the pair carries
        // this node's own half alone; with a mirrored wall
        // (`MirroredWall`) it stands in for products in this node's state.
        let cj = match input.laws[input.material[j] as usize] {
            BondLaw::Gas => uj[3],
            BondLaw::Solid { .. } if input.mirror_walls => ui[3],
            BondLaw::Solid { .. } => 0.0,
        };
        let coef = 0.5 * (ui[3] + cj);
        if coef == 0.0 {
            continue;
        }
        let (y, r, p3) = gas_pair(&xi, &ui, &xj, &uj);
        // Force on i, repulsive: −coef r/p² along ê = y/p, times β V_j.
        let g = -coef * r * factor[k] as f64 * xj[3] / p3;
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

/// The reaction on solid node `j` of the eq 19 pair forces of the
/// products nodes whose families hold it (`crate::ProductsFamily::
/// WithSolids`; `partners` and `bonds` its row of
/// [`crate::family::OneSidedPairs`], `factor` the bond weights of the
/// families), N/m³, and the stiffness of those pairs for the stable step,
/// Σ c_i β V_i r/p³ (the pair force's derivative in p at fixed c_i; the
/// products node's own step counts c_i's change, eq 26).
///
/// A products node i pushes its pair with j by its own half ½ c_i of
/// eq 19, −½ c_i r β V_j / p³ · y on i per unit volume (y = x_j + u_j −
/// x_i − u_i, as in its row); j takes +½ c_i r β V_i / p³ · y, so
/// V_i f_i + V_j f_j = 0 and the pair force is the gradient of the
/// products' energy W(X_i) V_i with j in eq 17's sum. With `mirror`
/// (`crate::ProductsFamily::MirroredWall`) the pair carries c_i in full on
/// both sides.
#[inline]
pub fn one_sided_gas_reaction(
    j: usize,
    reference: &[[f64; 4]],
    state: &[[f64; 4]],
    partners: &[u32],
    bonds: &[u32],
    factor: &[f32],
    mirror: bool,
) -> ([f64; 3], f64) {
    let xj = reference[j];
    let uj = state[j];
    let (mut f, mut stiffness) = ([0.0f64; 3], 0.0);
    for (&i, &k) in partners.iter().zip(bonds) {
        let i = i as usize;
        let xi = reference[i];
        let ui = state[i];
        let coef = if mirror { ui[3] } else { 0.5 * ui[3] };
        if coef == 0.0 {
            continue;
        }
        // The pair as the partner's row sees it (`gas_row`).
        let (y, r, p3) = gas_pair(&xi, &ui, &xj, &uj);
        let g = coef * r * factor[k as usize] as f64 * xi[3] / p3;
        f[0] += g * y[0];
        f[1] += g * y[1];
        f[2] += g * y[2];
        stiffness += 2.0 * g;
    }
    (f, stiffness)
}

/// The rows of `nodes`: `out` (and `dissipated`, unless it is empty) hold
/// one entry per node of the range.
#[inline(always)]
fn rows_serial<G: Gather>(
    nodes: std::ops::Range<usize>,
    input: &ForceInput,
    factor: &mut [f32],
    plastic: &mut [f32],
    out: &mut [NodeForce],
    dissipated: &mut [f32],
) {
    let base = input.offsets[nodes.start] as usize;
    for (k, (o, i)) in out.iter_mut().zip(nodes).enumerate() {
        let row = input.offsets[i] as usize - base..input.offsets[i + 1] as usize - base;
        let nb = &input.neighbours[row.start + base..row.end + base];
        let (force, lost) = match input.laws[input.material[i] as usize] {
            BondLaw::Solid {
                micromodulus,
                yield_stretch,
                plastic: pl,
                critical_stretch,
            } => solid_row::<G>(
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
            BondLaw::Gas => (gas_row(i, input, nb, &factor[row]), 0.0),
        };
        *o = force;
        if let Some(d) = dissipated.get_mut(k) {
            *d = lost;
        }
    }
}

/// A serial pass over a node range, compiled for one instruction set.
type RowsFn =
    fn(std::ops::Range<usize>, &ForceInput, &mut [f32], &mut [f32], &mut [NodeForce], &mut [f32]);

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
    dissipated: &mut [f32],
) {
    rows_serial::<AvxGather>(nodes, input, factor, plastic, out, dissipated)
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
    dissipated: &mut [f32],
) {
    rows_serial::<Avx512Gather>(nodes, input, factor, plastic, out, dissipated)
}

/// The widest instruction set the kernels here are built for that this
/// processor runs, found once per process.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
enum Build {
    /// AVX-512 F, VL and DQ (with AVX2).
    Avx512,
    /// AVX2.
    Avx2,
    /// The baseline build.
    Portable,
}

/// [`Build`] of this processor, detected on the first call.
fn this_cpu() -> Build {
    static BUILD: std::sync::OnceLock<Build> = std::sync::OnceLock::new();
    *BUILD.get_or_init(|| {
        #[cfg(target_arch = "x86_64")]
        {
            if std::arch::is_x86_feature_detected!("avx512f")
                && std::arch::is_x86_feature_detected!("avx512vl")
                && std::arch::is_x86_feature_detected!("avx512dq")
                && std::arch::is_x86_feature_detected!("avx2")
            {
                return Build::Avx512;
            }
            if std::arch::is_x86_feature_detected!("avx2") {
                return Build::Avx2;
            }
        }
        Build::Portable
    })
}

/// The widest build of the row pass this processor runs.
fn rows_for_this_cpu() -> RowsFn {
    #[cfg(target_arch = "x86_64")]
    match this_cpu() {
        // SAFETY: the features the function was compiled for are present
        // (`this_cpu`).
        Build::Avx512 => return |n, i, f, p, o, d| unsafe { rows_serial_avx512(n, i, f, p, o, d) },
        // SAFETY: as above.
        Build::Avx2 => return |n, i, f, p, o, d| unsafe { rows_serial_avx2(n, i, f, p, o, d) },
        Build::Portable => {}
    }
    rows_serial::<ScalarGather>
}

#[allow(clippy::too_many_arguments)]
fn rows_parallel(
    rows: RowsFn,
    nodes: std::ops::Range<usize>,
    input: &ForceInput,
    factor: &mut [f32],
    plastic: &mut [f32],
    out: &mut [NodeForce],
    dissipated: &mut [f32],
) {
    if nodes.len() <= GRAIN {
        rows(nodes, input, factor, plastic, out, dissipated);
        return;
    }
    let mid = nodes.start + nodes.len() / 2;
    let split = (input.offsets[mid] - input.offsets[nodes.start]) as usize;
    let (fa, fb) = factor.split_at_mut(split);
    let (pa, pb) = plastic.split_at_mut(split);
    let (oa, ob) = out.split_at_mut(mid - nodes.start);
    let (da, db) = if dissipated.is_empty() {
        (&mut [][..], &mut [][..])
    } else {
        dissipated.split_at_mut(mid - nodes.start)
    };
    rayon::join(
        || rows_parallel(rows, nodes.start..mid, input, fa, pa, oa, da),
        || rows_parallel(rows, mid..nodes.end, input, fb, pb, ob, db),
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
    bond_forces_in(input, 0..out.len(), factor, plastic, out);
}

/// [`bond_forces`] over the rows of `nodes` only (one rank's share of a
/// run spread over MPI ranks): `factor`, `plastic` and `out` are the whole
/// arrays, and only the entries of those rows are read and written. Each
/// row is computed as in the whole pass, so its bits do not depend on the
/// range.
pub fn bond_forces_in(
    input: &ForceInput,
    nodes: std::ops::Range<usize>,
    factor: &mut [f32],
    plastic: &mut [f32],
    out: &mut [NodeForce],
) {
    bond_forces_dissipating_in(input, nodes, factor, plastic, out, &mut []);
}

/// [`bond_forces_in`] that also writes, per node of `nodes`, the energy
/// its row dissipated in this pass (J, into `dissipated`, the whole
/// array like `out`, or empty to skip it): ½ c V_i Σ_j β r V_j
/// (s_Y |Δs_p| + ψ_j), the plastic work of its yielding bonds and what its
/// bonds breaking in this pass held (ψ as in `PdSolver::bond_energy`). Each of
/// a pair's two copies books half. The force bits do not depend on it.
pub fn bond_forces_dissipating_in(
    input: &ForceInput,
    nodes: std::ops::Range<usize>,
    factor: &mut [f32],
    plastic: &mut [f32],
    out: &mut [NodeForce],
    dissipated: &mut [f32],
) {
    let n = out.len();
    assert!(
        dissipated.is_empty() || dissipated.len() == n,
        "one dissipated energy per node, or none"
    );
    assert_eq!(input.offsets.len(), n + 1, "one row per node");
    assert_eq!(factor.len(), input.neighbours.len());
    assert_eq!(plastic.len(), input.neighbours.len());
    assert!(
        nodes.start <= nodes.end && nodes.end <= n,
        "rows within the nodes"
    );
    let bonds = input.offsets[nodes.start] as usize..input.offsets[nodes.end] as usize;
    rows_parallel(
        rows_for_this_cpu(),
        nodes.clone(),
        input,
        &mut factor[bonds.clone()],
        &mut plastic[bonds],
        &mut out[nodes.clone()],
        if dissipated.is_empty() {
            &mut []
        } else {
            &mut dissipated[nodes]
        },
    );
}

/// One products node's row of eq 17: the positions, the family and its
/// bond factors, and (for the closing time) the velocities.
#[derive(Clone, Copy, Debug)]
pub struct GasRow<'a> {
    /// Reference positions and volumes (x, y, z, V) of every node.
    pub reference: &'a [[f64; 4]],
    /// Displacements (u, ·) of every node.
    pub state: &'a [[f64; 4]],
    /// Velocities of every node; `None` leaves the closing time ∞.
    pub velocity: Option<&'a [[f64; 3]]>,
    /// The node's family, in its row's order.
    pub neighbours: &'a [u32],
    /// The family's bond factors β, one per neighbour.
    pub factor: &'a [f32],
    /// The node's family volume V = Σ_j β_j V_j at reference.
    pub family_volume: f64,
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
    let row = GasRow {
        reference,
        state,
        velocity: None,
        neighbours,
        factor,
        family_volume,
    };
    let (x, s3, s4, _) = gas_expansion_closing(i, &row);
    (x, s3, s4)
}

/// [`gas_expansion`] and, in the same pass when the velocities are given,
/// the node's shortest closing time p/ṗ over its intact bonds, s: p the
/// pair's current distance, ṗ = −y·(v_j − v_i)/p the speed at which it
/// closes; ∞ when no pair closes or without velocities
/// (`crate::CLOSING_STEP_FRACTION`). Runs the widest build this
/// processor has, chosen once per process.
#[inline]
pub fn gas_expansion_closing(i: usize, row: &GasRow) -> (f64, f64, f64, f64) {
    #[cfg(target_arch = "x86_64")]
    match this_cpu() {
        // SAFETY: the features the function was compiled for are present
        // (`this_cpu`).
        Build::Avx512 => return unsafe { gas_expansion_closing_avx512(i, row) },
        // SAFETY: as above.
        Build::Avx2 => return unsafe { gas_expansion_closing_avx2(i, row) },
        Build::Portable => {}
    }
    gas_expansion_closing_lanes(i, row)
}

/// [`gas_expansion_closing_lanes`] compiled with AVX-512 (the same IEEE
/// operations, so the same bits, eight lanes at a time).
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx512f,avx512vl,avx512dq,avx2")]
unsafe fn gas_expansion_closing_avx512(i: usize, row: &GasRow) -> (f64, f64, f64, f64) {
    gas_expansion_closing_lanes(i, row)
}

/// [`gas_expansion_closing_lanes`] compiled with AVX2 (same bits).
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
unsafe fn gas_expansion_closing_avx2(i: usize, row: &GasRow) -> (f64, f64, f64, f64) {
    gas_expansion_closing_lanes(i, row)
}

/// One products pair's terms of eq 17 and of the stable step:
/// (q β V, q/p² β V, q²/p² β V) with q = r/p, from the reference bond
/// ξ = x_j − x_i, the relative displacement η = u_j − u_i, the bond
/// factor β and the volume V of node j.
#[inline(always)]
fn gas_pair_terms(xi_: [f64; 3], eta: [f64; 3], beta: f32, vol: f64) -> [f64; 3] {
    let y = [xi_[0] + eta[0], xi_[1] + eta[1], xi_[2] + eta[2]];
    let r = (xi_[0] * xi_[0] + xi_[1] * xi_[1] + xi_[2] * xi_[2]).sqrt();
    let p = (y[0] * y[0] + y[1] * y[1] + y[2] * y[2])
        .sqrt()
        .max(1e-15 * r);
    let bv = beta as f64 * vol;
    let q = r / p;
    [q * bv, q / (p * p) * bv, q * q / (p * p) * bv]
}

/// One products pair's closing time p²/(−d·Δv) where the pair closes
/// (∞ where it does not or its bond is broken), d = x_j − x_i + u_j − u_i
/// summed in that order (x and u differenced first, not reused from
/// y = ξ + η: the closing time keeps the bits it had as a pass of its own).
#[inline(always)]
fn gas_pair_closing(dx: [f64; 3], uj: [f64; 3], ui: [f64; 3], dv: [f64; 3], beta: f32) -> f64 {
    let d = [
        dx[0] + uj[0] - ui[0],
        dx[1] + uj[1] - ui[1],
        dx[2] + uj[2] - ui[2],
    ];
    let approach = -(d[0] * dv[0] + d[1] * dv[1] + d[2] * dv[2]);
    if beta != 0.0 && approach > 0.0 {
        // p/ṗ = p²/(−y·Δv).
        (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]) / approach
    } else {
        f64::INFINITY
    }
}

/// The body of [`gas_expansion_closing`]: the pairs in groups of
/// `LANES` (eight), each group's terms formed lane by lane (loops the compiler
/// turns into vector instructions: sqrt and division are exact IEEE
/// operations in any width) and then added to the sums one pair at a
/// time in the row's order, so the sums are those of a pair-by-pair loop
/// to the bit; the rest of the row pair by pair.
#[inline(always)]
fn gas_expansion_closing_lanes(i: usize, row: &GasRow) -> (f64, f64, f64, f64) {
    let GasRow {
        reference,
        state,
        velocity,
        neighbours,
        factor,
        family_volume,
    } = *row;
    let xi = reference[i];
    let ui = state[i];
    let ui3 = [ui[0], ui[1], ui[2]];
    let (mut sum, mut s3, mut s4) = (0.0, 0.0, 0.0);
    let mut closing = f64::INFINITY;
    let groups = neighbours
        .chunks_exact(LANES)
        .zip(factor.chunks_exact(LANES));
    let done = neighbours.len() / LANES * LANES;
    for (js, betas) in groups {
        let mut dx = [[0.0; 3]; LANES];
        let mut uj = [[0.0; 3]; LANES];
        let mut vol = [0.0; LANES];
        for l in 0..LANES {
            let j = js[l] as usize;
            let (x, u) = (reference[j], state[j]);
            dx[l] = [x[0] - xi[0], x[1] - xi[1], x[2] - xi[2]];
            uj[l] = [u[0], u[1], u[2]];
            vol[l] = x[3];
        }
        let mut terms = [[0.0; 3]; LANES];
        for l in 0..LANES {
            let eta = [uj[l][0] - ui[0], uj[l][1] - ui[1], uj[l][2] - ui[2]];
            terms[l] = gas_pair_terms(dx[l], eta, betas[l], vol[l]);
        }
        for t in &terms {
            sum += t[0];
            s3 += t[1];
            s4 += t[2];
        }
        if let Some(v) = velocity {
            let vi = v[i];
            let mut dv = [[0.0; 3]; LANES];
            for l in 0..LANES {
                let vj = v[js[l] as usize];
                dv[l] = [vj[0] - vi[0], vj[1] - vi[1], vj[2] - vi[2]];
            }
            let mut c = [0.0; LANES];
            for l in 0..LANES {
                c[l] = gas_pair_closing(dx[l], uj[l], ui3, dv[l], betas[l]);
            }
            for &c in &c {
                closing = closing.min(c);
            }
        }
    }
    for (&j, &beta) in neighbours[done..].iter().zip(&factor[done..]) {
        let j = j as usize;
        let (xj, uj) = (reference[j], state[j]);
        let dx = [xj[0] - xi[0], xj[1] - xi[1], xj[2] - xi[2]];
        let eta = sub3(&uj, &ui);
        let t = gas_pair_terms(dx, eta, beta, xj[3]);
        sum += t[0];
        s3 += t[1];
        s4 += t[2];
        if let Some(v) = velocity {
            let (vi, vj) = (v[i], v[j]);
            let dv = [vj[0] - vi[0], vj[1] - vi[1], vj[2] - vi[2]];
            closing = closing.min(gas_pair_closing(dx, [uj[0], uj[1], uj[2]], ui3, dv, beta));
        }
    }
    let x = if sum > 0.0 {
        (sum / family_volume).powi(-3)
    } else {
        1.0
    };
    (x, s3, s4, closing)
}

/// The change over the last drift of the wall part of products node i's
/// eq 17 sum, ΔS_wall = Σ_k β V_k (r/p_k − r/p_k⁰) over the solid nodes k
/// of its family (`crate::ProductsFamily::MirroredWall`), m³: p_k the
/// pair's current length, p_k⁰ its length before the drift, whose bond
/// vector was y − dt (v_k − v_i) with v the half-step velocities the drift
/// moved the nodes with. Negative when the wall recedes. `pairs` gives
/// the family's (neighbour, β) in the row's order; those that are not
/// solid are passed over, so the row's wall pairs alone
/// ([`crate::family::ForeignBonds`]) give the sum of the whole row, to the
/// bit.
#[allow(clippy::too_many_arguments)]
pub fn wall_sum_change(
    i: usize,
    reference: &[[f64; 4]],
    state: &[[f64; 4]],
    velocity: &[[f64; 3]],
    dt: f64,
    pairs: impl IntoIterator<Item = (u32, f32)>,
    material: &[u16],
    laws: &[BondLaw],
) -> f64 {
    let xi = reference[i];
    let ui = state[i];
    let vi = velocity[i];
    let mut ds = 0.0;
    for (j, beta) in pairs {
        let j = j as usize;
        if !matches!(laws[material[j] as usize], BondLaw::Solid { .. }) {
            continue;
        }
        let (xj, uj, vj) = (reference[j], state[j], velocity[j]);
        let xi_ = sub3(&xj, &xi);
        let eta = sub3(&uj, &ui);
        let y = [xi_[0] + eta[0], xi_[1] + eta[1], xi_[2] + eta[2]];
        let y0 = [
            y[0] - dt * (vj[0] - vi[0]),
            y[1] - dt * (vj[1] - vi[1]),
            y[2] - dt * (vj[2] - vi[2]),
        ];
        let r = (xi_[0] * xi_[0] + xi_[1] * xi_[1] + xi_[2] * xi_[2]).sqrt();
        let p = (y[0] * y[0] + y[1] * y[1] + y[2] * y[2])
            .sqrt()
            .max(1e-15 * r);
        let p0 = (y0[0] * y0[0] + y0[1] * y0[1] + y0[2] * y0[2])
            .sqrt()
            .max(1e-15 * r);
        ds += beta as f64 * xj[3] * (r / p - r / p0);
    }
    ds
}

/// Parallel map over nodes writing one output each (deterministic).
pub fn for_each_node<T: Send>(out: &mut [T], f: impl Fn(usize, &mut T) + Sync) {
    out.par_iter_mut()
        .with_min_len(GRAIN)
        .enumerate()
        .for_each(|(i, o)| f(i, o));
}

/// [`for_each_node_in`] writing two per-node arrays at once (each the
/// whole array; `f` gets the node's index and its entries of both).
pub fn for_each_node_pair_in<A: Send, B: Send>(
    a: &mut [A],
    b: &mut [B],
    nodes: std::ops::Range<usize>,
    f: impl Fn(usize, &mut A, &mut B) + Sync,
) {
    let start = nodes.start;
    a[nodes.clone()]
        .par_iter_mut()
        .zip(b[nodes].par_iter_mut())
        .with_min_len(GRAIN)
        .enumerate()
        .for_each(|(k, (x, y))| f(start + k, x, y));
}

/// [`for_each_node`] over the nodes of `nodes` only: `out` is the whole
/// per-node array, `f` gets the node's index in it.
pub fn for_each_node_in<T: Send>(
    out: &mut [T],
    nodes: std::ops::Range<usize>,
    f: impl Fn(usize, &mut T) + Sync,
) {
    let start = nodes.start;
    out[nodes]
        .par_iter_mut()
        .with_min_len(GRAIN)
        .enumerate()
        .for_each(|(k, o)| f(start + k, o));
}

#[cfg(target_arch = "x86_64")]
mod avx512;
#[cfg(test)]
mod tests;
