//! Row-stencil passes of the 2D lattice step (seed 003 eqs 6, 9–10b, 11,
//! 14–17 and the dual volume of fig. 8) for the common case of one
//! material whose springs carry no internal state (no plasticity,
//! fracture or Maxwell arm).
//!
//! On the structured lattice the neighbour of node i along a direction is
//! i + offset, so every pass is a loop over the interior columns of a row
//! with the neighbours at fixed offsets in contiguous slices. The loops are
//! branch-free (the solid/intact/held tests are selects on a per-node flag
//! byte), so the compiler vectorises them; they are compiled three times
//! (AVX-512, AVX2, baseline) and the widest build the processor runs is
//! taken at run time, as in the PD bond kernel.
//!
//! Each node performs the IEEE operations of the general passes of
//! [`super::model`] ([`super::model::bond_force`], the gather, the explicit
//! Euler update, [`super::geometry::dual_volume_2d`] and the energy
//! update) in the same order on the same operands: vector `sqrt` and
//! division are correctly rounded like the scalar ones, a select keeps
//! exactly the value the branch kept, and no operation is fused or
//! reassociated. So the results are the same bits as the general passes,
//! on any number of threads (each node's arithmetic does not depend on how
//! the rows are split). Two differences of form only:
//!
//! * A bond that is not intact stores +0 instead of being skipped; the
//!   gather then adds +0 or subtracts +0. A running sum that starts at +0
//!   is never −0 under round-to-nearest (x + y is −0 only when both are
//!   −0), and s + (+0) = s, s − (+0) = s for every s ≠ −0, so the sums are
//!   unchanged.
//! * The squared length r₀² + r₁² omits the + 0² of the inactive axis: a
//!   sum of squares is never −0, so adding +0 does not change it.
//!
//! `tests` checks these passes against the general ones bit for bit.

use rayon::prelude::*;

use super::geometry::NodeKind;

/// Node flag: solid node.
pub(crate) const SOLID: u8 = 1;
/// Node flag: velocity component x moves (solid, not held on x, m > 0).
pub(crate) const MOVE_X: u8 = 2;
/// Node flag: velocity component y moves.
pub(crate) const MOVE_Y: u8 = 4;
/// Node flag: bond (i, d) intact is bit `BOND_SHIFT + d`.
pub(crate) const BOND_SHIFT: u32 = 4;
/// Most directions of a 2D lattice (2 axial + 2 diagonals).
pub(crate) const MAX_DIRS: usize = 4;

/// One direction of the 2D lattice with the spring constants of the
/// single material along it.
#[derive(Debug, Clone, Copy, Default)]
pub(crate) struct Dir2 {
    /// Lattice step (x, y): the bond joins i and i + sx + sy·nx.
    pub sx: isize,
    pub sy: isize,
    /// Reference vector ξ (components x, y; z is 0 in 2D).
    pub xi: [f64; 2],
    /// |ξ|.
    pub len0: f64,
    /// Reference unit vector ê₀ (x, y, z).
    pub e0: [f64; 3],
    /// k∞|ξ|, k₁|ξ| and c|ξ| (see [`super::law::PairLaw::axial`]).
    pub k: f64,
    pub k1: f64,
    pub c: f64,
    /// k⊥|ξ| on axial springs, else 0.
    pub kp: f64,
}

/// The shape of the padded 2D box: `nx` nodes per row, `ny` rows.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Box2 {
    pub nx: usize,
    pub ny: usize,
}

impl Box2 {
    fn len(&self) -> usize {
        self.nx * self.ny
    }
    /// Interior columns per row (solid nodes never sit on the box's
    /// boundary).
    fn inner(&self) -> usize {
        self.nx - 2
    }
}

/// Which build of the passes runs.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Isa {
    /// Baseline x86-64 (SSE2) or another architecture.
    Base,
    /// AVX2.
    Avx2,
    /// AVX-512 F/VL.
    Avx512,
}

/// The widest build this processor runs.
pub(crate) fn isa() -> Isa {
    #[cfg(target_arch = "x86_64")]
    {
        if std::arch::is_x86_feature_detected!("avx512f")
            && std::arch::is_x86_feature_detected!("avx512vl")
        {
            return Isa::Avx512;
        }
        if std::arch::is_x86_feature_detected!("avx2") {
            return Isa::Avx2;
        }
    }
    Isa::Base
}

/// Generates the AVX-512, AVX2 and baseline builds of a row kernel and a
/// dispatcher `$name(isa, args…)`.
macro_rules! builds {
    ($name:ident, $body:ident, $avx512:ident, $avx2:ident, ($($arg:ident : $ty:ty),*)) => {
        #[cfg(target_arch = "x86_64")]
        #[target_feature(enable = "avx512f,avx512vl,avx2")]
        #[allow(clippy::too_many_arguments)]
        unsafe fn $avx512($($arg: $ty),*) {
            $body($($arg),*)
        }
        #[cfg(target_arch = "x86_64")]
        #[target_feature(enable = "avx2")]
        #[allow(clippy::too_many_arguments)]
        unsafe fn $avx2($($arg: $ty),*) {
            $body($($arg),*)
        }
        #[inline]
        #[allow(clippy::too_many_arguments)]
        fn $name(isa: Isa, $($arg: $ty),*) {
            match isa {
                // SAFETY: `isa()` found the features these builds use.
                #[cfg(target_arch = "x86_64")]
                Isa::Avx512 => unsafe { $avx512($($arg),*) },
                #[cfg(target_arch = "x86_64")]
                Isa::Avx2 => unsafe { $avx2($($arg),*) },
                _ => $body($($arg),*),
            }
        }
    };
}

/// Per-node flags of a 2D lattice from the node kinds, the bond status
/// (`nd` directions), the prescribed axes and the masses: [`SOLID`],
/// [`MOVE_X`], [`MOVE_Y`] and the intact bits of the node's own bonds.
#[allow(clippy::too_many_arguments)]
pub(crate) fn node_flags(
    b: Box2,
    nd: usize,
    kind: &[NodeKind],
    status: &[u8],
    prescribed: &[bool],
    held: &[u8],
    mass: &[f64],
    flags: &mut [u8],
) {
    assert_eq!(flags.len(), b.len());
    let (nx, ny, l) = (b.nx, b.ny, b.inner());
    flags.par_chunks_mut(nx).enumerate().for_each(|(r, row)| {
        if r == 0 || r + 1 >= ny {
            row.fill(0);
            return;
        }
        row[0] = 0;
        row[nx - 1] = 0;
        let i = r * nx + 1;
        let out = &mut row[1..1 + l];
        let (kind, pre, held, mass) = (
            &kind[i..i + l],
            &prescribed[i..i + l],
            &held[i..i + l],
            &mass[i..i + l],
        );
        match nd {
            2 => row_flags::<2>(kind, &status[i * 2..(i + l) * 2], pre, held, mass, out),
            4 => row_flags::<4>(kind, &status[i * 4..(i + l) * 4], pre, held, mass, out),
            _ => unreachable!("a 2D lattice has 2 or 4 directions"),
        }
    });
}

/// [`node_flags`] of one row of interior nodes with `ND` directions.
#[inline(always)]
fn row_flags<const ND: usize>(
    kind: &[NodeKind],
    status: &[u8],
    pre: &[bool],
    held: &[u8],
    mass: &[f64],
    out: &mut [u8],
) {
    let l = out.len();
    let (kind, status, pre, held, mass) = (
        &kind[..l],
        &status[..l * ND],
        &pre[..l],
        &held[..l],
        &mass[..l],
    );
    for q in 0..l {
        let solid = matches!(kind[q], NodeKind::Solid(_));
        let live = mass[q] > 0.0;
        let hold = if pre[q] { held[q] } else { 0 };
        let mut v = u8::from(solid) * SOLID;
        v |= u8::from(solid && live && hold & 1 == 0) * MOVE_X;
        v |= u8::from(solid && live && hold & 2 == 0) * MOVE_Y;
        for d in 0..ND {
            v |= u8::from(solid && status[q * ND + d] == super::model::INTACT)
                << (BOND_SHIFT + d as u32);
        }
        out[q] = v;
    }
}

/// Force of bond (i, d) on the lower node i, for a row of interior nodes:
/// [`super::model::bond_force`] with the 2D reference quantities of `d`,
/// the default spring state and (x, y) components; +0 where the bond is
/// not intact.
#[inline(always)]
#[allow(clippy::too_many_arguments)]
fn bond_row_body(
    d: &Dir2,
    bit: u8,
    fl: &[u8],
    xi0: &[f64],
    xj0: &[f64],
    xi1: &[f64],
    xj1: &[f64],
    ui0: &[f64],
    uj0: &[f64],
    ui1: &[f64],
    uj1: &[f64],
    out0: &mut [f64],
    out1: &mut [f64],
) {
    let l = out0.len();
    let (fl, xi0, xj0, xi1, xj1) = (&fl[..l], &xi0[..l], &xj0[..l], &xi1[..l], &xj1[..l]);
    let (ui0, uj0, ui1, uj1, out1) = (&ui0[..l], &uj0[..l], &ui1[..l], &uj1[..l], &mut out1[..l]);
    let (len0, k, k1, c, kp) = (d.len0, d.k, d.k1, d.c, d.kp);
    let ([x0, x1], e0) = (d.xi, d.e0);
    let perp = kp > 0.0;
    for q in 0..l {
        let r0 = xj0[q] - xi0[q];
        let r1 = xj1[q] - xi1[q];
        let w0 = uj0[q] - ui0[q];
        let w1 = uj1[q] - ui1[q];
        let len = (r0 * r0 + r1 * r1).sqrt();
        let (n0, n1) = if len > 0.0 {
            (r0 / len, r1 / len)
        } else {
            (0.0, 0.0)
        };
        let s = len - len0;
        // n₂w₂ = (+0)(+0) of the inactive axis.
        let sdot = n0 * w0 + n1 * w1 + 0.0;
        // PairLaw::axial with s_p = δ = 0 and no yield.
        let force = k * s + k1 * s + c * sdot;
        let mut f0 = force * n0;
        let mut f1 = force * n1;
        if perp {
            let eta0 = r0 - x0;
            let eta1 = r1 - x1;
            // η₂ê₀₂ = (+0)(+0).
            let along = eta0 * e0[0] + eta1 * e0[1] + 0.0;
            f0 += kp * (eta0 - along * e0[0]);
            f1 += kp * (eta1 - along * e0[1]);
        }
        let intact = fl[q] & bit != 0;
        out0[q] = if intact { f0 } else { 0.0 };
        out1[q] = if intact { f1 } else { 0.0 };
    }
}

builds!(
    bond_row,
    bond_row_body,
    bond_row_avx512,
    bond_row_avx2,
    (
        d: &Dir2,
        bit: u8,
        fl: &[u8],
        xi0: &[f64],
        xj0: &[f64],
        xi1: &[f64],
        xj1: &[f64],
        ui0: &[f64],
        uj0: &[f64],
        ui1: &[f64],
        uj1: &[f64],
        out0: &mut [f64],
        out1: &mut [f64]
    )
);

/// The bond pass: the (x, y) force of every bond (i, d) on its lower node
/// into `buf`, laid out by row: entry `((r·nd + d)·2 + a)·nx + c` for node
/// (c, r). Entries of boundary nodes and of bonds that are not intact are
/// +0 (`buf` must start zeroed; the boundary entries are never written).
/// Only the rows of `rows` are evaluated; the others are left as they are.
#[allow(clippy::too_many_arguments)]
pub(crate) fn bond_pass(
    b: Box2,
    dirs: &[Dir2],
    flags: &[u8],
    x0: &[f64],
    x1: &[f64],
    u0: &[f64],
    u1: &[f64],
    buf: &mut [f64],
    rows: std::ops::Range<usize>,
) {
    let (nx, ny, nd, l) = (b.nx, b.ny, dirs.len(), b.inner());
    assert!(nd <= MAX_DIRS && buf.len() == b.len() * nd * 2);
    let isa = isa();
    buf.par_chunks_mut(nd * 2 * nx)
        .enumerate()
        .for_each(|(r, row)| {
            if r == 0 || r + 1 >= ny || !rows.contains(&r) {
                return;
            }
            let i = r * nx + 1;
            for (d, dir) in dirs.iter().enumerate() {
                let j = (i as isize + dir.sx + dir.sy * nx as isize) as usize;
                let (o0, o1) = row[d * 2 * nx..(d + 1) * 2 * nx].split_at_mut(nx);
                bond_row(
                    isa,
                    dir,
                    1 << (BOND_SHIFT + d as u32),
                    &flags[i..i + l],
                    &x0[i..i + l],
                    &x0[j..j + l],
                    &x1[i..i + l],
                    &x1[j..j + l],
                    &u0[i..i + l],
                    &u0[j..j + l],
                    &u1[i..i + l],
                    &u1[j..j + l],
                    &mut o0[1..1 + l],
                    &mut o1[1..1 + l],
                );
            }
        });
}

/// One axis of the gather: acc = +0 + v (`Acc::First`), acc += v or
/// acc −= v.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Acc {
    First,
    Add,
    Sub,
}

#[inline(always)]
fn add_row_body(acc: &mut [f64], v: &[f64], op: Acc) {
    let v = &v[..acc.len()];
    match op {
        Acc::First => {
            for (a, v) in acc.iter_mut().zip(v) {
                *a = 0.0 + *v;
            }
        }
        Acc::Add => {
            for (a, v) in acc.iter_mut().zip(v) {
                *a += *v;
            }
        }
        Acc::Sub => {
            for (a, v) in acc.iter_mut().zip(v) {
                *a -= *v;
            }
        }
    }
}

builds!(
    add_row,
    add_row_body,
    add_row_avx512,
    add_row_avx2,
    (acc: &mut [f64], v: &[f64], op: Acc)
);

/// f = body + s on solid nodes (0 elsewhere; z is body + 0) and, with
/// `dt`, the explicit Euler update x ← x + uΔt, u ← u + f/m Δt on the
/// moving axes (eqs 16–17).
#[inline(always)]
#[allow(clippy::too_many_arguments)]
fn update_row_body(
    fl: &[u8],
    body0: &[f64],
    body1: &[f64],
    body2: &[f64],
    mass: &[f64],
    f0: &mut [f64],
    f1: &mut [f64],
    f2: &mut [f64],
    x0: &mut [f64],
    x1: &mut [f64],
    u0: &mut [f64],
    u1: &mut [f64],
    dt: Option<f64>,
) {
    let l = f0.len();
    let (fl, body0, body1, body2, mass) =
        (&fl[..l], &body0[..l], &body1[..l], &body2[..l], &mass[..l]);
    let (f1, f2, x0, x1, u0, u1) = (
        &mut f1[..l],
        &mut f2[..l],
        &mut x0[..l],
        &mut x1[..l],
        &mut u0[..l],
        &mut u1[..l],
    );
    for q in 0..l {
        let solid = fl[q] & SOLID != 0;
        let g0 = body0[q] + f0[q];
        let g1 = body1[q] + f1[q];
        let g2 = body2[q] + 0.0;
        f0[q] = if solid { g0 } else { 0.0 };
        f1[q] = if solid { g1 } else { 0.0 };
        f2[q] = if solid { g2 } else { 0.0 };
    }
    if let Some(dt) = dt {
        for q in 0..l {
            let solid = fl[q] & SOLID != 0;
            let nx0 = x0[q] + u0[q] * dt;
            let nu0 = u0[q] + f0[q] / mass[q] * dt;
            let nx1 = x1[q] + u1[q] * dt;
            let nu1 = u1[q] + f1[q] / mass[q] * dt;
            x0[q] = if solid { nx0 } else { x0[q] };
            u0[q] = if fl[q] & MOVE_X != 0 { nu0 } else { u0[q] };
            x1[q] = if solid { nx1 } else { x1[q] };
            u1[q] = if fl[q] & MOVE_Y != 0 { nu1 } else { u1[q] };
        }
    }
}

builds!(
    update_row,
    update_row_body,
    update_row_avx512,
    update_row_avx2,
    (
        fl: &[u8],
        body0: &[f64],
        body1: &[f64],
        body2: &[f64],
        mass: &[f64],
        f0: &mut [f64],
        f1: &mut [f64],
        f2: &mut [f64],
        x0: &mut [f64],
        x1: &mut [f64],
        u0: &mut [f64],
        u1: &mut [f64],
        dt: Option<f64>
    )
);

/// The gather of the bond forces into the net force of every node (+ for
/// its own bonds, − for those of its lower neighbours, in direction order),
/// and with `dt` the explicit Euler update, row by row, over the rows of
/// `rows` (the other rows are left as they are; `buf` must hold the bonds
/// of those rows and of the row below them).
#[allow(clippy::too_many_arguments)]
pub(crate) fn gather_pass(
    b: Box2,
    dirs: &[Dir2],
    flags: &[u8],
    buf: &[f64],
    body: [&[f64]; 3],
    mass: &[f64],
    x: [&mut [f64]; 2],
    u: [&mut [f64]; 2],
    force: [&mut [f64]; 3],
    dt: Option<f64>,
    rows: std::ops::Range<usize>,
) {
    let (nx, ny, nd, l) = (b.nx, b.ny, dirs.len(), b.inner());
    let isa = isa();
    let [x0, x1] = x;
    let [u0, u1] = u;
    let [f0, f1, f2] = force;
    let at = |r: usize, d: usize, a: usize| ((r * nd + d) * 2 + a) * nx;
    f0.par_chunks_mut(nx)
        .zip(f1.par_chunks_mut(nx))
        .zip(f2.par_chunks_mut(nx))
        .zip(x0.par_chunks_mut(nx))
        .zip(x1.par_chunks_mut(nx))
        .zip(u0.par_chunks_mut(nx))
        .zip(u1.par_chunks_mut(nx))
        .enumerate()
        .for_each(|(r, ((((((f0, f1), f2), x0), x1), u0), u1))| {
            if !rows.contains(&r) {
                return;
            }
            if r == 0 || r + 1 >= ny {
                f0.fill(0.0);
                f1.fill(0.0);
                f2.fill(0.0);
                return;
            }
            for f in [&mut *f0, &mut *f1, &mut *f2] {
                f[0] = 0.0;
                f[nx - 1] = 0.0;
            }
            let (s0, s1) = (&mut f0[1..1 + l], &mut f1[1..1 + l]);
            // s = +0, then + the own bonds in direction order.
            for d in 0..nd {
                let op = if d == 0 { Acc::First } else { Acc::Add };
                add_row(isa, s0, &buf[at(r, d, 0) + 1..], op);
                add_row(isa, s1, &buf[at(r, d, 1) + 1..], op);
            }
            for (d, dir) in dirs.iter().enumerate() {
                // The lower node of the bond (i − offset, d): row r − sy,
                // column c − sx.
                let rr = (r as isize - dir.sy) as usize;
                let c = (1 - dir.sx) as usize;
                add_row(isa, s0, &buf[at(rr, d, 0) + c..], Acc::Sub);
                add_row(isa, s1, &buf[at(rr, d, 1) + c..], Acc::Sub);
            }
            let i = r * nx + 1;
            update_row(
                isa,
                &flags[i..i + l],
                &body[0][i..i + l],
                &body[1][i..i + l],
                &body[2][i..i + l],
                &mass[i..i + l],
                &mut f0[1..1 + l],
                &mut f1[1..1 + l],
                &mut f2[1..1 + l],
                &mut x0[1..1 + l],
                &mut x1[1..1 + l],
                &mut u0[1..1 + l],
                &mut u1[1..1 + l],
                dt,
            );
        });
}

/// Constants of the energy update of a single-material lattice.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Thermal {
    /// −K = −ρ₀c₀² (eq 11).
    pub neg_bulk: f64,
    /// c_v and 𝒢 of the EOS (eq 14).
    pub cv: f64,
    pub gamma: f64,
    /// Conductance κh of a spring and of a spring to a ghost.
    pub pair: f64,
    pub ghost: f64,
    /// Surroundings' temperature.
    pub t_sur: f64,
    /// Chemical enthalpy h₀ of the component.
    pub enthalpy: f64,
    /// Step, s.
    pub dt: f64,
    /// Lattice spacing h (the depth of the dual cell).
    pub spacing: f64,
    /// Whether the energy equation is on.
    pub on: bool,
}

/// The dual volume (fig. 8) and energy update of one row of interior
/// nodes, in the operations of [`super::geometry::dual_volume_2d`] and
/// [`super::model::MsdmLattice::update_volume_and_energy`]. Slices with a
/// suffix m/p hold the row below/above (offset ∓nx), w/e the columns
/// left/right (offset ∓1).
#[inline(always)]
#[allow(clippy::too_many_arguments)]
fn energy_row_body(
    th: &Thermal,
    xrows: [&[f64]; 3],
    yrows: [&[f64]; 3],
    frows: [&[u8]; 3],
    trows: [&[f64]; 3],
    volume: &[f64],
    mass: &[f64],
    energy: &[f64],
    pressure: &[f64],
    rate: Option<&[f64]>,
    v_new: &mut [f64],
    e_new: &mut [f64],
    p_new: &mut [f64],
    t_new: &mut [f64],
) {
    let l = v_new.len();
    // Windows: row m (−y), 0, p (+y); each slice starts one column left
    // of the row's first interior node.
    fn w(s: &[f64], l: usize) -> &[f64] {
        &s[..l + 2]
    }
    let (xm, x0, xp) = (w(xrows[0], l), w(xrows[1], l), w(xrows[2], l));
    let (ym, y0, yp) = (w(yrows[0], l), w(yrows[1], l), w(yrows[2], l));
    let (tm, t0, tp) = (w(trows[0], l), w(trows[1], l), w(trows[2], l));
    let (fm, f0, fp) = (&frows[0][..l + 2], &frows[1][..l + 2], &frows[2][..l + 2]);
    let (volume, mass, energy, pressure) = (&volume[..l], &mass[..l], &energy[..l], &pressure[..l]);
    let (e_new, p_new, t_new) = (&mut e_new[..l], &mut p_new[..l], &mut t_new[..l]);
    let rate = rate.map(|r| &r[..l]);
    let sol = |f: u8| f & SOLID != 0;
    for q in 0..l {
        let c = q + 1;
        let (xi0, xi1) = (x0[c], y0[c]);
        // Window [row][col] of positions and solidity; rows −y, 0, +y.
        let p0 = [
            [xm[c - 1], xm[c], xm[c + 1]],
            [x0[c - 1], xi0, x0[c + 1]],
            [xp[c - 1], xp[c], xp[c + 1]],
        ];
        let p1 = [
            [ym[c - 1], ym[c], ym[c + 1]],
            [y0[c - 1], xi1, y0[c + 1]],
            [yp[c - 1], yp[c], yp[c + 1]],
        ];
        let k = [
            [sol(fm[c - 1]), sol(fm[c]), sol(fm[c + 1])],
            [sol(f0[c - 1]), sol(f0[c]), sol(f0[c + 1])],
            [sol(fp[c - 1]), sol(fp[c]), sol(fp[c + 1])],
        ];
        let mid = |r: usize, c: usize| [0.5 * (xi0 + p0[r][c]), 0.5 * (xi1 + p1[r][c])];
        let quadrant = |cx: usize, ry: usize, sign: f64, area: f64| -> f64 {
            let ma = mid(1, cx);
            let mb = mid(ry, 1);
            let cen = [
                0.25 * (xi0 + p0[1][cx] + p0[ry][1] + p0[ry][cx]),
                0.25 * (xi1 + p1[1][cx] + p1[ry][1] + p1[ry][cx]),
            ];
            let d1 = [cen[0] - xi0, cen[1] - xi1];
            let d2 = [mb[0] - ma[0], mb[1] - ma[1]];
            let signed = 0.5 * (d1[0] * d2[1] - d1[1] * d2[0]);
            let next = area + signed * sign;
            if k[1][cx] && k[ry][1] && k[ry][cx] {
                next
            } else {
                area
            }
        };
        let mut area = 0.0;
        area = quadrant(2, 2, 1.0, area);
        area = quadrant(2, 0, -1.0, area);
        area = quadrant(0, 2, -1.0, area);
        area = quadrant(0, 0, 1.0, area);
        let v = area * th.spacing;
        let solid = k[1][1];
        v_new[q] = if solid { v } else { 0.0 };
        if !th.on {
            continue;
        }
        let v_old = volume[q];
        let m = mass[q];
        let dp = th.neg_bulk * (v - v_old) / v_old;
        // c_v · dT/dP(ρ) · ΔP with dT/dP = 1/(ρ𝒢c_v) (eq 14).
        let rho = m / v_old;
        let mut de = th.cv * (1.0 / (rho * th.gamma * th.cv)) * dp;
        let mut chem = 0.0;
        if let Some(rate) = rate {
            chem += th.enthalpy * rate[q];
        }
        // Conduction along the axial springs, x then y, + then −; the
        // bonds (i, 0), (i − 1, 0), (i, 1), (i − nx, 1).
        let ti = t0[c];
        let fi = f0[c];
        let term = |intact: bool, tj: f64| {
            if intact {
                th.pair * (tj - ti)
            } else {
                th.ghost * (th.t_sur - ti)
            }
        };
        let b0 = 1 << BOND_SHIFT;
        let b1 = 1 << (BOND_SHIFT + 1);
        let mut qc = 0.0;
        qc += term(fi & b0 != 0, t0[c + 1]);
        qc += term(f0[c - 1] & b0 != 0, t0[c - 1]);
        qc += term(fi & b1 != 0, tp[c]);
        qc += term(fm[c] & b1 != 0, tm[c]);
        de += (chem + qc) * th.dt / m;
        let e = energy[q] + de;
        let p = pressure[q] + dp;
        let t = e / th.cv;
        e_new[q] = if solid { e } else { energy[q] };
        p_new[q] = if solid { p } else { pressure[q] };
        t_new[q] = if solid { t } else { t0[c] };
    }
    if !th.on {
        e_new.copy_from_slice(energy);
        p_new.copy_from_slice(pressure);
        t_new.copy_from_slice(&t0[1..1 + l]);
    }
}

builds!(
    energy_row,
    energy_row_body,
    energy_row_avx512,
    energy_row_avx2,
    (
        th: &Thermal,
        xrows: [&[f64]; 3],
        yrows: [&[f64]; 3],
        frows: [&[u8]; 3],
        trows: [&[f64]; 3],
        volume: &[f64],
        mass: &[f64],
        energy: &[f64],
        pressure: &[f64],
        rate: Option<&[f64]>,
        v_new: &mut [f64],
        e_new: &mut [f64],
        p_new: &mut [f64],
        t_new: &mut [f64]
    )
);

/// The dual volumes and the energy update of every node into the `new`
/// arrays (V, e, P, T), row by row over the rows of `own_rows` (the other rows
/// are left as they are); exterior nodes get V = 0 and keep e, P and T.
#[allow(clippy::too_many_arguments)]
pub(crate) fn energy_pass(
    b: Box2,
    th: &Thermal,
    flags: &[u8],
    x: [&[f64]; 2],
    temperature: &[f64],
    volume: &[f64],
    mass: &[f64],
    energy: &[f64],
    pressure: &[f64],
    rate: Option<&[f64]>,
    new: [&mut [f64]; 4],
    own_rows: std::ops::Range<usize>,
) {
    let (nx, ny, l) = (b.nx, b.ny, b.inner());
    let isa = isa();
    let [v_new, e_new, p_new, t_new] = new;
    v_new
        .par_chunks_mut(nx)
        .zip(e_new.par_chunks_mut(nx))
        .zip(p_new.par_chunks_mut(nx))
        .zip(t_new.par_chunks_mut(nx))
        .enumerate()
        .for_each(|(r, (((v, e), p), t))| {
            if !own_rows.contains(&r) {
                return;
            }
            let row = r * nx;
            if r == 0 || r + 1 >= ny {
                v.fill(0.0);
                e.copy_from_slice(&energy[row..row + nx]);
                p.copy_from_slice(&pressure[row..row + nx]);
                t.copy_from_slice(&temperature[row..row + nx]);
                return;
            }
            for c in [0, nx - 1] {
                v[c] = 0.0;
                e[c] = energy[row + c];
                p[c] = pressure[row + c];
                t[c] = temperature[row + c];
            }
            fn rows(s: &[f64], row: usize, nx: usize) -> [&[f64]; 3] {
                [&s[row - nx..], &s[row..], &s[row + nx..]]
            }
            let i = row + 1;
            energy_row(
                isa,
                th,
                rows(x[0], row, nx),
                rows(x[1], row, nx),
                [&flags[row - nx..], &flags[row..], &flags[row + nx..]],
                rows(temperature, row, nx),
                &volume[i..i + l],
                &mass[i..i + l],
                &energy[i..i + l],
                &pressure[i..i + l],
                rate.map(|r| &r[i..i + l]),
                &mut v[1..1 + l],
                &mut e[1..1 + l],
                &mut p[1..1 + l],
                &mut t[1..1 + l],
            );
        });
}
