//! Volumetric anti-locking: the ΔF̄ method of Coombs, Charlton, Cortis &
//! Augarde (2018), *Overcoming volumetric locking in material point
//! methods*, Comput. Methods Appl. Mech. Engrg. 333, 1–21.
//!
//! With 2ⁿ or more particles per cell, every particle's own volume change
//! ΔJ_p = det ΔF_p, ΔF_p = I + L_p Δt, is a separate constraint on the few
//! nodal velocities around it. Under isochoric (plastic or nearly
//! incompressible) flow the grid cannot satisfy them all with a
//! non-trivial motion, and the body answers too stiffly: *volumetric
//! locking*. Coombs et al. replace each particle's volume change by the
//! volume-weighted mean over the particles of its patch, keeping the
//! particle's own isochoric part:
//!
//! ```text
//!   ΔJ̄ = Σ_q V_qⁿ ΔJ_q / Σ_q V_qⁿ           (q in the patch of p)
//!   ΔF̄_p = (ΔJ̄ / ΔJ_p)^{1/3} ΔF_p
//! ```
//!
//! so that det ΔF̄_p = ΔJ̄ and ΔF̄_p / (det ΔF̄_p)^{1/3} = ΔF_p / ΔJ_p^{1/3}.
//! The patch's total volume change Σ V_qⁿ ΔJ_q is kept exactly; only its
//! distribution among the particles of the patch changes. The stress
//! update then receives the velocity gradient of ΔF̄_p,
//!
//! ```text
//!   L̄_p = (ΔF̄_p − I)/Δt = r L_p + (r − 1)/Δt I,   r = (ΔJ̄/ΔJ_p)^{1/3},
//! ```
//!
//! and advances F_p ← ΔF̄_p F_p, V_p = det F_p V_p⁰ from it as usual
//! ([`crate::step::update_particle_stress`]). A uniform dilation (all ΔJ_q
//! equal) is left as it is.
//!
//! **The force that goes with it.** The grid force f_I = −Σ_p V_p σ_p ∇N_Ip
//! does the work Σ_p V_p σ_p : L_p, while the particles book
//! Σ_p V_p σ_p : D̄_p. The two agree only if the pressure is the same at
//! every particle of a cell; where it is not (the particles keep their own
//! J and e), the difference feeds the volumetric motion the averaging
//! released, and the body gains energy without bound (V-TAYLOR with
//! linear shape functions at 6 cells across the radius: +110 % total
//! energy and a 61 mm foot after 40 µs). As in the B̄ method that
//! F̄ generalises, the force is therefore formed from
//! σ̃_p = σ_p + (p_p − p̄) I, each particle's stress with its pressure
//! p_p = −tr σ_p/3 replaced by the volume-weighted mean p̄ of its cell
//! ([`PatchAverage::average_pressure`]); then
//! Σ_p V_p σ̃_p : L_p = Σ_p V_p (s_p : L_p − p̄ tr L_p) and the particles'
//! Σ_p V_p (s_p : D̄_p − p_p tr D̄_p) agree to O(Δt) (tr D̄_p is the cell's
//! for every particle, dev D̄_p = r dev D_p with r = 1 + O(Δt)).
//!
//! **The patch.** The background cell that holds x_pⁿ, as in Coombs et
//! al., whatever the shape function (its particles at 2 per cell per
//! direction are the 2³ integration points of the cell). The sums
//! Σ V_q and Σ V_q a_q over a cell are formed in one pass over the
//! particles in storage order, so each cell adds its particles in one
//! fixed order: the bits do not depend on the thread count or on how the
//! level is split into patches. That pass is sequential and O(N) (two
//! additions per particle); everything per particle (ΔJ_p, L̄_p, σ̃_p) runs
//! in parallel. The average is over every particle of the cell whatever
//! its material; it is meant for cells of one solid.
//!
//! See `docs/physics/mpm/anti_locking.md`.

use brisance_core::{Mat3, UniformGridGeometry};
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

/// Particles a parallel task takes at least.
const PARTICLES_PER_TASK: usize = 512;

/// The volumetric anti-locking treatment of the MPM stress update.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default, Serialize, Deserialize)]
pub enum AntiLocking {
    /// Each particle deforms with its own velocity gradient (the default).
    #[default]
    Off,
    /// The ΔF̄ method of Coombs et al. (2018): the volume change of each
    /// particle is the volume-weighted mean over the particles of its
    /// cell, and the internal force uses the cell's mean pressure.
    FBar,
}

/// det(I + A) − 1 without the cancellation of forming det(I + A) first:
/// tr A + ½((tr A)² − tr A²) + det A.
pub fn volume_change_minus_one(a: &Mat3) -> f64 {
    let tr = a.trace();
    let tr_sq = (a * a).trace();
    tr + 0.5 * (tr * tr - tr_sq) + a.determinant()
}

/// L̄ of a particle with velocity gradient `l`, own volume change
/// ΔJ_p = 1 + `own` and patch mean ΔJ̄ = 1 + `mean` over Δt = `dt`:
/// r L + (r − 1)/Δt I with r = (ΔJ̄/ΔJ_p)^{1/3}, r − 1 formed as
/// expm1(⅓ ln1p((mean − own)/(1 + own))) to keep its digits.
pub fn averaged_gradient(l: &Mat3, own: f64, mean: f64, dt: f64) -> Mat3 {
    if mean == own || dt <= 0.0 {
        return *l;
    }
    let r_minus_1 = ((mean - own) / (1.0 + own)).ln_1p() / 3.0;
    let r_minus_1 = r_minus_1.exp_m1();
    l * (1.0 + r_minus_1) + Mat3::identity() * (r_minus_1 / dt)
}

/// A particle outside the grid when the cells are assigned.
#[derive(Debug, Clone, Copy, PartialEq, thiserror::Error)]
#[error("particle {index} at {position:?} m lies outside the grid")]
pub struct OutsideGrid {
    /// Particle index.
    pub index: usize,
    /// Its position, m.
    pub position: [f64; 3],
}

/// Buffers of the ΔF̄ averaging, reused from step to step (nothing is
/// allocated once the particle count and the grid stop growing).
#[derive(Debug, Clone, Default)]
pub struct PatchAverage {
    /// Per particle, storage order: its cell (linear index) at the start
    /// of the step.
    slot: Vec<usize>,
    /// Per particle: ΔJ_p − 1 of its own velocity gradient.
    own: Vec<f64>,
    /// Per particle: L_p, replaced by L̄_p by [`Self::average`].
    pub gradient: Vec<Mat3>,
    /// Per particle: the stress the internal force is formed from, σ_p
    /// with its pressure replaced by the cell's mean
    /// ([`Self::average_pressure`]).
    pub stress: Vec<[f64; 6]>,
    /// Per cell: (Σ V_q, Σ V_q a_q) of the quantity a being averaged.
    sums: Vec<[f64; 2]>,
}

impl PatchAverage {
    /// Bytes of the per-particle buffers (cell, ΔJ − 1, gradient and
    /// stress).
    pub fn particle_bytes(&self) -> usize {
        use std::mem::size_of_val;
        size_of_val(self.slot.as_slice())
            + size_of_val(self.own.as_slice())
            + size_of_val(self.gradient.as_slice())
            + size_of_val(self.stress.as_slice())
    }

    /// Bytes of the per-cell sums.
    pub fn cell_bytes(&self) -> usize {
        std::mem::size_of_val(self.sums.as_slice())
    }

    /// Records every particle's cell on `grid` from its position
    /// `position` (those of the start of the step). A particle outside the
    /// grid is an error naming it.
    pub fn assign(
        &mut self,
        grid: &UniformGridGeometry,
        position: &[[f64; 3]],
    ) -> Result<(), OutsideGrid> {
        self.slot.resize(position.len(), 0);
        self.sums.resize(grid.cell_count(), [0.0; 2]);
        let outside = self
            .slot
            .par_chunks_mut(PARTICLES_PER_TASK)
            .zip(position.par_chunks(PARTICLES_PER_TASK))
            .enumerate()
            .filter_map(|(k, (slots, xs))| {
                for (i, (s, x)) in slots.iter_mut().zip(xs).enumerate() {
                    match grid.cell_containing(*x) {
                        Some(c) => *s = grid.linear_index(c),
                        None => return Some(k * PARTICLES_PER_TASK + i),
                    }
                }
                None
            })
            .min();
        match outside {
            Some(index) => Err(OutsideGrid {
                index,
                position: position[index],
            }),
            None => Ok(()),
        }
    }

    /// (Σ V_q, Σ V_q a_q) over the particles q of every cell into
    /// `self.sums`, `a(q)` the quantity: one pass in storage order
    /// (O(N), touching only the cells that hold particles), so each cell
    /// adds its particles in one fixed order whatever the threads.
    fn cell_sums(&mut self, volume: &[f64], a: impl Fn(usize) -> f64) {
        assert_eq!(self.slot.len(), volume.len(), "one cell per particle");
        for &c in &self.slot {
            self.sums[c] = [0.0; 2];
        }
        for (q, &c) in self.slot.iter().enumerate() {
            let s = &mut self.sums[c];
            let v = volume[q];
            s[0] += v;
            s[1] += v * a(q);
        }
    }

    /// Fills [`Self::stress`] with σ̃_p = σ_p + (p_p − p̄) I: each
    /// particle's stress `stress` (Voigt) with its pressure p_p = −tr σ_p/3
    /// replaced by the volume-weighted mean p̄ = Σ V_q p_q / Σ V_q over its
    /// cell (volumes `volume`). The internal force formed from σ̃ is the
    /// one whose power is Σ_p V_p σ_p : D̄_p with the averaged rates of
    /// [`Self::average`] (the B̄ force that goes with F̄; module doc).
    pub fn average_pressure(&mut self, volume: &[f64], stress: &[[f64; 6]]) {
        let pressure = |s: &[f64; 6]| -(s[0] + s[1] + s[2]) / 3.0;
        self.cell_sums(volume, |q| pressure(&stress[q]));
        self.stress.resize(stress.len(), [0.0; 6]);
        let sums = &self.sums;
        self.stress
            .par_chunks_mut(PARTICLES_PER_TASK)
            .zip(self.slot.par_chunks(PARTICLES_PER_TASK))
            .zip(stress.par_chunks(PARTICLES_PER_TASK))
            .for_each(|((out, slots), stress)| {
                for ((o, &s), sigma) in out.iter_mut().zip(slots).zip(stress) {
                    let [v, vp] = sums[s];
                    *o = *sigma;
                    if v > 0.0 {
                        let shift = pressure(sigma) - vp / v;
                        for d in &mut o[..3] {
                            *d += shift;
                        }
                    }
                }
            });
    }

    /// Replaces every particle's velocity gradient in
    /// [`Self::gradient`] by L̄_p of the module doc, with the volumes
    /// `volume` (Vⁿ) as weights and the cells of [`Self::assign`].
    pub fn average(&mut self, volume: &[f64], dt: f64) {
        let n = self.gradient.len();
        assert_eq!(volume.len(), n, "one volume per particle");
        // ΔJ_p − 1 of every particle, in parallel, kept in `own` for the
        // sums and the update.
        self.own.resize(n, 0.0);
        self.own
            .par_chunks_mut(PARTICLES_PER_TASK)
            .zip(self.gradient.par_chunks(PARTICLES_PER_TASK))
            .for_each(|(own, ls)| {
                for (o, l) in own.iter_mut().zip(ls) {
                    *o = volume_change_minus_one(&(l * dt));
                }
            });
        let own = std::mem::take(&mut self.own);
        self.cell_sums(volume, |q| own[q]);
        self.own = own;
        let sums = &self.sums;
        self.gradient
            .par_chunks_mut(PARTICLES_PER_TASK)
            .zip(self.slot.par_chunks(PARTICLES_PER_TASK))
            .zip(self.own.par_chunks(PARTICLES_PER_TASK))
            .for_each(|((ls, slots), own)| {
                for ((l, &s), &own) in ls.iter_mut().zip(slots).zip(own) {
                    let [v, vdj] = sums[s];
                    if v > 0.0 {
                        *l = averaged_gradient(l, own, vdj / v, dt);
                    }
                }
            });
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use brisance_core::UniformGridGeometry;

    fn det_increment(l: &Mat3, dt: f64) -> f64 {
        (Mat3::identity() + l * dt).determinant()
    }

    /// 4 × 4 × 4 cells of 1 mm.
    fn grid() -> UniformGridGeometry {
        UniformGridGeometry {
            origin: [0.0; 3],
            spacing: [1e-3; 3],
            cells: [4, 4, 4],
        }
    }

    /// Averages `l` of particles at `x` with volumes `v` over Δt = `dt`.
    fn run(x: &[[f64; 3]], v: &[f64], l: &[Mat3], dt: f64) -> Vec<Mat3> {
        let mut avg = PatchAverage::default();
        avg.assign(&grid(), x).unwrap();
        avg.gradient = l.to_vec();
        avg.average(v, dt);
        avg.gradient
    }

    #[test]
    fn volume_change_minus_one_is_det_minus_one() {
        // A = diag(0.5, 0.25, -0.5) plus a shear: det(I + A) = 1.5 · 1.25 ·
        // 0.5 − 0 = 0.9375 (the shear 0.125 in (0, 1) on an upper
        // triangle leaves the determinant alone).
        let a = Mat3::new(0.5, 0.125, 0.0, 0.0, 0.25, 0.0, 0.0, 0.0, -0.5);
        assert_eq!(volume_change_minus_one(&a), 0.9375 - 1.0);
        // Small increments keep their digits: (1 + 1e-12)³ − 1 = 3e-12 +
        // 3e-24 + 1e-36, where det(I + A) − 1 would keep about 4 digits.
        let a = Mat3::identity() * 1e-12;
        let d = volume_change_minus_one(&a);
        assert!((d - 3.000000000003e-12).abs() <= 1e-27, "{d}");
        assert!(((Mat3::identity() + a).determinant() - 1.0 - 3e-12).abs() > 1e-17);
    }

    #[test]
    fn two_particles_in_one_cell_get_the_volume_weighted_mean_volume_change() {
        // Linear shapes: both particles in cell (1, 1, 1). Particle 0
        // (V = 1) compresses along x, ΔJ₀ = 1 − 0.25 = 0.75; particle 1
        // (V = 3) shears only, ΔJ₁ = 1. ΔJ̄ = (0.75 + 3)/4 = 0.9375.
        let dt = 1.0;
        let l0 = Mat3::new(-0.25, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0);
        let l1 = Mat3::new(0.0, 0.5, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0);
        let x = [[1.25e-3, 1.5e-3, 1.5e-3], [1.75e-3, 1.5e-3, 1.5e-3]];
        let out = run(&x, &[1.0, 3.0], &[l0, l1], dt);
        for (p, (lb, l)) in out.iter().zip([l0, l1]).enumerate() {
            let j = det_increment(lb, dt);
            assert!((j - 0.9375).abs() <= 4.0 * f64::EPSILON, "{p}: {j}");
            // The isochoric part ΔF/ΔJ^{1/3} is the particle's own.
            let own = (Mat3::identity() + l * dt) / det_increment(&l, dt).cbrt();
            let new = (Mat3::identity() + lb * dt) / j.cbrt();
            assert!((own - new).abs().max() <= 4.0 * f64::EPSILON, "{p}");
        }
        // Hand values: r₀ = (0.9375/0.75)^{1/3} = 1.25^{1/3} scales ΔF₀ =
        // diag(0.75, 1, 1); r₁ = 0.9375^{1/3} scales ΔF₁.
        let r0 = 1.25f64.cbrt();
        let r1 = 0.9375f64.cbrt();
        let expect0 = Mat3::new(
            0.75 * r0 - 1.0,
            0.0,
            0.0,
            0.0,
            r0 - 1.0,
            0.0,
            0.0,
            0.0,
            r0 - 1.0,
        );
        let expect1 = Mat3::new(
            r1 - 1.0,
            0.5 * r1,
            0.0,
            0.0,
            r1 - 1.0,
            0.0,
            0.0,
            0.0,
            r1 - 1.0,
        );
        assert!((out[0] - expect0).abs().max() <= 1e-15, "{}", out[0]);
        assert!((out[1] - expect1).abs().max() <= 1e-15, "{}", out[1]);
        // The patch keeps its total volume change: Σ V ΔJ̄ = Σ V ΔJ.
        let total = det_increment(&out[0], dt) + 3.0 * det_increment(&out[1], dt);
        assert!((total - (0.75 + 3.0)).abs() <= 1e-14);
    }

    #[test]
    fn a_uniform_dilation_is_left_alone_whatever_the_shear() {
        // Eight particles at the sub-cell centres of cell (1, 2, 1), each
        // with the same dilation plus its own shear on the upper triangle
        // (which leaves det(I + L Δt) alone): ΔJ is the same bits for all,
        // so L̄ = L up to the round-off of the weighted mean of equal
        // values, |L̄ − L| ≤ 1e-13 |L|.
        let dt = 1e-6;
        let mut x = Vec::new();
        let mut l = Vec::new();
        for k in 0..8 {
            let o = [(k & 1) as f64, (k >> 1 & 1) as f64, (k >> 2 & 1) as f64];
            x.push([
                (1.25 + 0.5 * o[0]) * 1e-3,
                (2.25 + 0.5 * o[1]) * 1e-3,
                (1.25 + 0.5 * o[2]) * 1e-3,
            ]);
            let w = 1e3 * k as f64;
            l.push(Mat3::new(
                2e3,
                w,
                0.5 * w, //
                0.0,
                2e3,
                -w, //
                0.0,
                0.0,
                2e3,
            ));
        }
        let own: Vec<f64> = l
            .iter()
            .map(|l| volume_change_minus_one(&(l * dt)))
            .collect();
        assert!(own.iter().all(|&d| d == own[0]));
        let equal = [0.125; 8];
        let unequal: Vec<f64> = (0..8).map(|k| 0.1 + 0.37 * k as f64).collect();
        for v in [&equal[..], &unequal[..]] {
            let out = run(&x, v, &l, dt);
            for (a, b) in out.iter().zip(&l) {
                assert!((a - b).abs().max() <= 1e-13 * b.abs().max(), "{a} {b}");
            }
        }
        // Exactly equal means (one particle per cell) change nothing, bit
        // for bit.
        let out = run(&x[..1], &[0.3], &l[..1], dt);
        assert_eq!(out, l[..1].to_vec());
    }

    #[test]
    fn the_deviatoric_part_of_the_increment_is_untouched() {
        // Eight particles in one cell with random velocity gradients: each
        // ΔF̄ has the patch's volume change and the particle's own
        // isochoric part ΔF/ΔJ^{1/3}; and the rotation of the increment
        // (skew part of L̄) is r times the particle's own, r = (ΔJ̄/ΔJ)^{1/3}.
        let dt = 1e-6;
        let mut s = 0x2545_f491_4f6c_dd1d_u64;
        let mut next = || {
            s = s
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (s >> 11) as f64 / (1u64 << 53) as f64 - 0.5
        };
        let mut x = Vec::new();
        let mut l = Vec::new();
        let mut v = Vec::new();
        for k in 0..8 {
            let o = [(k & 1) as f64, (k >> 1 & 1) as f64, (k >> 2 & 1) as f64];
            x.push([
                (1.25 + 0.5 * o[0]) * 1e-3,
                (1.25 + 0.5 * o[1]) * 1e-3,
                (1.25 + 0.5 * o[2]) * 1e-3,
            ]);
            l.push(Mat3::from_fn(|_, _| next() * 2e4));
            v.push(1.0 + next());
        }
        let out = run(&x, &v, &l, dt);
        let dj: Vec<f64> = l.iter().map(|l| det_increment(l, dt)).collect();
        let mean = dj.iter().zip(&v).map(|(j, v)| j * v).sum::<f64>() / v.iter().sum::<f64>();
        for p in 0..8 {
            let j = det_increment(&out[p], dt);
            assert!((j - mean).abs() <= 1e-14, "{p}: {j} {mean}");
            let own = (Mat3::identity() + l[p] * dt) / dj[p].cbrt();
            let new = (Mat3::identity() + out[p] * dt) / j.cbrt();
            assert!((own - new).abs().max() <= 1e-15, "{p}");
            let r = (mean / dj[p]).cbrt();
            let skew = |m: &Mat3| 0.5 * (m - m.transpose());
            assert!((skew(&out[p]) - skew(&l[p]) * r).abs().max() <= 1e-9 * l[p].abs().max());
        }
    }

    #[test]
    fn particles_of_different_cells_do_not_mix() {
        // Same two particles as in the two-particle test, but in cells
        // (1, 1, 1) and (2, 1, 1): each keeps its own L.
        let dt = 1.0;
        let l0 = Mat3::new(-0.25, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0);
        let l1 = Mat3::new(0.0, 0.5, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0);
        let x = [[1.75e-3, 1.5e-3, 1.5e-3], [2.25e-3, 1.5e-3, 1.5e-3]];
        let out = run(&x, &[1.0, 3.0], &[l0, l1], dt);
        assert_eq!(out, vec![l0, l1]);
        // A particle on the upper domain face belongs to the last cell.
        let x = [[3.5e-3, 1.5e-3, 1.5e-3], [4e-3, 1.5e-3, 1.5e-3]];
        let out = run(&x, &[1.0, 3.0], &[l0, l1], dt);
        let j = det_increment(&out[1], dt);
        assert!((j - 0.9375).abs() <= 4.0 * f64::EPSILON, "{j}");
        // One outside is refused by index.
        let mut avg = PatchAverage::default();
        let x = [[1e-3; 3], [1e-3, 4.5e-3, 0.0]];
        assert_eq!(
            avg.assign(&grid(), &x),
            Err(OutsideGrid {
                index: 1,
                position: x[1]
            })
        );
    }

    #[test]
    fn the_pressure_of_the_force_is_the_cell_mean_and_the_deviator_is_kept() {
        // Two particles in cell (1, 1, 1), V = 1 and 3, pressures 4 and 8
        // Pa: p̄ = (4 + 24)/4 = 7; the deviators and shears stay. A third
        // particle alone in cell (3, 3, 3) keeps its stress.
        let x = [
            [1.25e-3, 1.5e-3, 1.5e-3],
            [1.75e-3, 1.5e-3, 1.5e-3],
            [3.5e-3, 3.5e-3, 3.5e-3],
        ];
        let stress = [
            [-5.0, -4.0, -3.0, 1.0, 2.0, 3.0],
            [-6.0, -8.0, -10.0, -1.0, 0.0, 0.5],
            [-1.0, -2.0, -3.0, 0.25, 0.5, 0.75],
        ];
        let mut avg = PatchAverage::default();
        avg.assign(&grid(), &x).unwrap();
        avg.average_pressure(&[1.0, 3.0, 2.0], &stress);
        assert_eq!(
            avg.stress,
            vec![
                [-8.0, -7.0, -6.0, 1.0, 2.0, 3.0],
                [-5.0, -7.0, -9.0, -1.0, 0.0, 0.5],
                stress[2],
            ]
        );
    }

    #[test]
    fn the_average_does_not_depend_on_threads() {
        // 512 particles scattered over the grid with varied L and V: the
        // same bits on 1 and 2 threads.
        let mut x = Vec::new();
        let mut l = Vec::new();
        let mut v = Vec::new();
        let mut s = 0x9e37_79b9_7f4a_7c15_u64;
        let mut next = || {
            s = s
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (s >> 11) as f64 / (1u64 << 53) as f64
        };
        for _ in 0..512 {
            x.push([next() * 4e-3, next() * 4e-3, next() * 4e-3]);
            l.push(Mat3::from_fn(|_, _| (next() - 0.5) * 1e4));
            v.push(0.5 + next());
        }
        let on = |threads: usize| {
            rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap()
                .install(|| run(&x, &v, &l, 1e-6))
        };
        let a = on(1);
        assert!(a == on(2));
        assert!(a != l, "the average changed something");
    }
}
