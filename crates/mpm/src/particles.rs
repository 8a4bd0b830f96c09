//! The particle state, structure of arrays.
//!
//! Each particle p carries the quantities of seed 001 eqs 14–30 and seed 000
//! eqs 12–17: position x_p, velocity v_p, mass m_p, initial and current
//! volume V_p⁰, V_p, deformation gradient F_p, Cauchy stress σ_p,
//! temperature, specific internal energy, its material, the history
//! variables of its constitutive model and whether it has failed. One
//! `Vec` per quantity; 3-vectors and tensors are stored as fixed-size
//! arrays per particle (`[f64; 3]`, `[f64; 9]`, `[f64; 6]`) so a kernel reads
//! one contiguous stream per quantity.

use brisance_core::{Mat3, UniformGridGeometry};
use rayon::prelude::*;

/// Which material a particle belongs to (an index into the run's material
/// list, not a count).
#[derive(
    Debug,
    Clone,
    Copy,
    PartialEq,
    Eq,
    PartialOrd,
    Ord,
    Hash,
    Default,
    serde::Serialize,
    serde::Deserialize,
)]
pub struct MaterialId(pub u16);

/// Why particles cannot be added or sorted.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ParticleError {
    /// A non-finite position or velocity, or a non-positive mass or volume.
    #[error("particle {index}: {what}")]
    InvalidState {
        /// The particle's index (the one it would get when pushed).
        index: usize,
        /// What is wrong.
        what: String,
    },
    /// A history block whose length differs from the set's stride.
    #[error(
        "particle {index}: history block of {got} values, the set stores {stride} per particle"
    )]
    HistoryLength {
        /// The particle's index.
        index: usize,
        /// Values given.
        got: usize,
        /// Values per particle.
        stride: usize,
    },
    /// A particle outside the grid when sorting by cell.
    #[error("particle {index} at {position:?} m lies outside the grid")]
    OutsideGrid {
        /// The particle's index.
        index: usize,
        /// Its position, m.
        position: [f64; 3],
    },
}

/// The initial state of one particle. `deformation_gradient` defaults to
/// the identity and `stress` to zero.
#[derive(Debug, Clone, PartialEq)]
pub struct ParticleInit {
    /// Position, m.
    pub position: [f64; 3],
    /// Velocity, m/s.
    pub velocity: [f64; 3],
    /// Mass, kg.
    pub mass: f64,
    /// Volume, m³ (initial and current).
    pub volume: f64,
    /// Deformation gradient F, row-major.
    pub deformation_gradient: [f64; 9],
    /// Cauchy stress in Voigt order (xx, yy, zz, yz, xz, xy), Pa.
    pub stress: [f64; 6],
    /// Temperature, K.
    pub temperature: f64,
    /// Specific internal energy, J/kg.
    pub specific_internal_energy: f64,
    /// Material.
    pub material: MaterialId,
}

/// The identity tensor, row-major.
pub const IDENTITY: [f64; 9] = [1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0];

impl Default for ParticleInit {
    fn default() -> Self {
        Self {
            position: [0.0; 3],
            velocity: [0.0; 3],
            mass: 0.0,
            volume: 0.0,
            deformation_gradient: IDENTITY,
            stress: [0.0; 6],
            temperature: 0.0,
            specific_internal_energy: 0.0,
            material: MaterialId(0),
        }
    }
}

/// All particles of one MPM solver, structure of arrays.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Particles {
    /// Position x_p, m.
    pub position: Vec<[f64; 3]>,
    /// Velocity v_p, m/s.
    pub velocity: Vec<[f64; 3]>,
    /// Mass m_p, kg (constant: seed 001 eq 14 carries mass on particles).
    pub mass: Vec<f64>,
    /// Initial volume V_p⁰, m³.
    pub initial_volume: Vec<f64>,
    /// Current volume V_p = det(F_p) V_p⁰, m³.
    pub volume: Vec<f64>,
    /// Deformation gradient F_p, row-major (`F[r][c]` at 3r + c).
    pub deformation_gradient: Vec<[f64; 9]>,
    /// Cauchy stress σ_p, Voigt order (xx, yy, zz, yz, xz, xy), Pa.
    pub stress: Vec<[f64; 6]>,
    /// Temperature, K.
    pub temperature: Vec<f64>,
    /// Specific internal energy, J/kg.
    pub specific_internal_energy: Vec<f64>,
    /// Material of each particle.
    pub material: Vec<MaterialId>,
    /// History variables of the constitutive models, `history_stride`
    /// values per particle (particle p owns `p·stride .. (p+1)·stride`).
    pub history: Vec<f64>,
    /// Whether the particle has failed (irreversible).
    pub failed: Vec<bool>,
    history_stride: usize,
    scratch: PermuteScratch,
}

/// The buffers [`Particles::permute`] writes the reordered arrays into,
/// one per element type: each array is gathered into the buffer of its
/// type and swapped with it, so the buffer then holds the old array's
/// storage for the next array of that type, and a sort allocates nothing
/// once the buffers have grown to the particle count. Not part of the
/// state: a clone starts with empty buffers and equality ignores them.
#[derive(Default)]
struct PermuteScratch {
    vector: Vec<[f64; 3]>,
    scalar: Vec<f64>,
    tensor: Vec<[f64; 9]>,
    voigt: Vec<[f64; 6]>,
    material: Vec<MaterialId>,
    flag: Vec<bool>,
}

impl Clone for PermuteScratch {
    fn clone(&self) -> Self {
        Self::default()
    }
}

impl PartialEq for PermuteScratch {
    fn eq(&self, _: &Self) -> bool {
        true
    }
}

impl std::fmt::Debug for PermuteScratch {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("PermuteScratch")
    }
}

/// Gathers `v[perm[i]]` into `scratch` (which keeps its capacity: no
/// allocation once it holds `perm.len()` elements) and swaps it with `v`.
pub(crate) fn permute_into<T: Copy + Send + Sync>(
    v: &mut Vec<T>,
    perm: &[usize],
    scratch: &mut Vec<T>,
) {
    scratch.clear();
    scratch.par_extend(perm.par_iter().with_min_len(4096).map(|&p| v[p]));
    std::mem::swap(v, scratch);
}

/// Removes, in place, the elements of blocks `leaving` (increasing block
/// indices, a repeated one removed once; a block is `stride` consecutive
/// elements):
/// the blocks after each removed one move down over it with one
/// `copy_within` per run, so the others keep their relative order and no
/// memory is allocated or freed.
pub(crate) fn remove_blocks<T: Copy>(v: &mut Vec<T>, leaving: &[usize], stride: usize) {
    let Some(&first) = leaving.first() else {
        return;
    };
    let mut write = first * stride;
    for (k, &p) in leaving.iter().enumerate() {
        if leaving.get(k + 1) == Some(&p) {
            continue;
        }
        let start = (p + 1) * stride;
        let end = leaving.get(k + 1).map_or(v.len(), |&q| q * stride);
        v.copy_within(start..end, write);
        write += end - start;
    }
    v.truncate(write);
}

/// Keeps, in place, only the blocks `keep` (strictly increasing block
/// indices), in that order: block i becomes old block `keep[i]`. Since
/// `keep[i] ≥ i`, copying forward never overwrites a block still to be
/// read.
fn keep_blocks<T: Copy>(v: &mut Vec<T>, keep: &[usize], stride: usize) {
    for (i, &p) in keep.iter().enumerate() {
        if i != p {
            v.copy_within(p * stride..(p + 1) * stride, i * stride);
        }
    }
    v.truncate(keep.len() * stride);
}

impl Particles {
    /// An empty set whose particles each carry `history_stride` history
    /// values.
    pub fn new(history_stride: usize) -> Self {
        Self {
            history_stride,
            ..Default::default()
        }
    }

    /// History values per particle.
    pub fn history_stride(&self) -> usize {
        self.history_stride
    }

    /// Number of particles.
    pub fn len(&self) -> usize {
        self.mass.len()
    }

    /// Whether there is no particle.
    pub fn is_empty(&self) -> bool {
        self.mass.is_empty()
    }

    /// Reserves room for `additional` more particles.
    pub fn reserve(&mut self, additional: usize) {
        self.position.reserve(additional);
        self.velocity.reserve(additional);
        self.mass.reserve(additional);
        self.initial_volume.reserve(additional);
        self.volume.reserve(additional);
        self.deformation_gradient.reserve(additional);
        self.stress.reserve(additional);
        self.temperature.reserve(additional);
        self.specific_internal_energy.reserve(additional);
        self.material.reserve(additional);
        self.history.reserve(additional * self.history_stride);
        self.failed.reserve(additional);
    }

    /// Appends one particle with the history block `history` (its length
    /// must equal the stride) and returns its index.
    pub fn push(&mut self, p: &ParticleInit, history: &[f64]) -> Result<usize, ParticleError> {
        let index = self.check(p)?;
        if history.len() != self.history_stride {
            return Err(ParticleError::HistoryLength {
                index,
                got: history.len(),
                stride: self.history_stride,
            });
        }
        self.push_state(p);
        self.history.extend_from_slice(history);
        Ok(index)
    }

    /// Appends one particle with a history block of zeros and returns its
    /// index (as [`Particles::push`], without a history slice to build).
    pub fn push_zero_history(&mut self, p: &ParticleInit) -> Result<usize, ParticleError> {
        let index = self.check(p)?;
        self.push_state(p);
        self.history
            .resize(self.history.len() + self.history_stride, 0.0);
        Ok(index)
    }

    /// Checks the state of a particle to be pushed; returns the index it
    /// will get.
    fn check(&self, p: &ParticleInit) -> Result<usize, ParticleError> {
        let index = self.len();
        let invalid = |what: String| ParticleError::InvalidState { index, what };
        if p.position.iter().chain(&p.velocity).any(|v| !v.is_finite()) {
            return Err(invalid(format!(
                "position {:?} m and velocity {:?} m/s must be finite",
                p.position, p.velocity
            )));
        }
        if !(p.mass > 0.0) || !p.mass.is_finite() {
            return Err(invalid(format!("mass {} kg must be positive", p.mass)));
        }
        if !(p.volume > 0.0) || !p.volume.is_finite() {
            return Err(invalid(format!("volume {} m³ must be positive", p.volume)));
        }
        Ok(index)
    }

    /// Appends every array but the history of a checked particle.
    fn push_state(&mut self, p: &ParticleInit) {
        self.position.push(p.position);
        self.velocity.push(p.velocity);
        self.mass.push(p.mass);
        self.initial_volume.push(p.volume);
        self.volume.push(p.volume);
        self.deformation_gradient.push(p.deformation_gradient);
        self.stress.push(p.stress);
        self.temperature.push(p.temperature);
        self.specific_internal_energy
            .push(p.specific_internal_energy);
        self.material.push(p.material);
        self.failed.push(false);
    }

    /// The history block of particle `p`.
    pub fn history_of(&self, p: usize) -> &[f64] {
        &self.history[p * self.history_stride..(p + 1) * self.history_stride]
    }

    /// The history block of particle `p`, mutable.
    pub fn history_of_mut(&mut self, p: usize) -> &mut [f64] {
        &mut self.history[p * self.history_stride..(p + 1) * self.history_stride]
    }

    /// F_p as a matrix.
    pub fn deformation_gradient_of(&self, p: usize) -> Mat3 {
        Mat3::from_row_slice(&self.deformation_gradient[p])
    }

    /// σ_p as a symmetric matrix, Pa.
    pub fn stress_of(&self, p: usize) -> Mat3 {
        voigt_to_matrix(&self.stress[p])
    }

    /// Bytes the particle arrays hold (their lengths, not capacities): per
    /// particle 211 bytes of state plus 8 per history value.
    pub fn state_bytes(&self) -> usize {
        use std::mem::size_of_val;
        size_of_val(self.position.as_slice())
            + size_of_val(self.velocity.as_slice())
            + size_of_val(self.mass.as_slice())
            + size_of_val(self.initial_volume.as_slice())
            + size_of_val(self.volume.as_slice())
            + size_of_val(self.deformation_gradient.as_slice())
            + size_of_val(self.stress.as_slice())
            + size_of_val(self.temperature.as_slice())
            + size_of_val(self.specific_internal_energy.as_slice())
            + size_of_val(self.material.as_slice())
            + size_of_val(self.history.as_slice())
            + size_of_val(self.failed.as_slice())
    }

    /// Total mass Σ m_p, kg.
    pub fn total_mass(&self) -> f64 {
        self.mass.iter().sum()
    }

    /// The linear index (x fastest) of the grid cell that holds each
    /// particle, written into `cells`.
    pub fn cell_indices(
        &self,
        grid: &UniformGridGeometry,
        cells: &mut Vec<usize>,
    ) -> Result<(), ParticleError> {
        cells.clear();
        cells.reserve(self.len());
        for (index, &x) in self.position.iter().enumerate() {
            let c = grid
                .cell_containing(x)
                .ok_or(ParticleError::OutsideGrid { index, position: x })?;
            cells.push(grid.linear_index(c));
        }
        Ok(())
    }

    /// Whether the particles are in increasing order of the linear index of
    /// their cell; `false` if one lies outside the grid.
    pub fn is_sorted_by_cell(&self, grid: &UniformGridGeometry) -> bool {
        let cell = |x: &[f64; 3]| grid.cell_containing(*x).map(|c| grid.linear_index(c));
        self.position
            .par_windows(2)
            .with_min_len(4096)
            .all(|w| matches!((cell(&w[0]), cell(&w[1])), (Some(a), Some(b)) if a <= b))
            && (self.position.len() != 1 || cell(&self.position[0]).is_some())
    }

    /// Sorts the particles by the linear index of their cell with a stable
    /// counting sort (particles of one cell keep their relative order, so
    /// the result is deterministic), and returns the permutation applied:
    /// new particle i is old particle `perm[i]`.
    pub fn sort_by_cell(
        &mut self,
        grid: &UniformGridGeometry,
    ) -> Result<Vec<usize>, ParticleError> {
        let mut cells = Vec::new();
        self.cell_indices(grid, &mut cells)?;
        let mut start = vec![0usize; grid.cell_count() + 1];
        for &c in &cells {
            start[c + 1] += 1;
        }
        for c in 0..grid.cell_count() {
            start[c + 1] += start[c];
        }
        let mut perm = vec![0usize; cells.len()];
        for (p, &c) in cells.iter().enumerate() {
            perm[start[c]] = p;
            start[c] += 1;
        }
        self.permute(&perm);
        Ok(perm)
    }

    /// Keeps only the particles `keep` (strictly increasing indices), in
    /// that order: new particle i is old particle `keep[i]`. In place: no
    /// array is reallocated.
    ///
    /// # Panics
    /// If `keep` is not strictly increasing or names a particle past the
    /// end (a caller's bug, not user input).
    pub fn select(&mut self, keep: &[usize]) {
        assert!(
            keep.windows(2).all(|w| w[0] < w[1]) && keep.last().is_none_or(|&p| p < self.len()),
            "Particles::select: indices must be strictly increasing and below {}",
            self.len()
        );
        keep_blocks(&mut self.position, keep, 1);
        keep_blocks(&mut self.velocity, keep, 1);
        keep_blocks(&mut self.mass, keep, 1);
        keep_blocks(&mut self.initial_volume, keep, 1);
        keep_blocks(&mut self.volume, keep, 1);
        keep_blocks(&mut self.deformation_gradient, keep, 1);
        keep_blocks(&mut self.stress, keep, 1);
        keep_blocks(&mut self.temperature, keep, 1);
        keep_blocks(&mut self.specific_internal_energy, keep, 1);
        keep_blocks(&mut self.material, keep, 1);
        keep_blocks(&mut self.failed, keep, 1);
        keep_blocks(&mut self.history, keep, self.history_stride);
    }

    /// Removes the particles `leaving` (increasing indices; one given
    /// twice is removed once); the others keep their relative order, as with [`Particles::select`] of
    /// the complement. In place: each array's runs of kept particles move
    /// down with one `copy_within` each, and no array is reallocated, so
    /// the capacity stays for the particles pushed next.
    ///
    /// # Panics
    /// If `leaving` is not increasing or names a particle past the end (a
    /// caller's bug, not user input).
    pub fn remove_sorted(&mut self, leaving: &[usize]) {
        assert!(
            leaving.windows(2).all(|w| w[0] <= w[1])
                && leaving.last().is_none_or(|&p| p < self.len()),
            "Particles::remove_sorted: indices must be increasing and below {}",
            self.len()
        );
        remove_blocks(&mut self.position, leaving, 1);
        remove_blocks(&mut self.velocity, leaving, 1);
        remove_blocks(&mut self.mass, leaving, 1);
        remove_blocks(&mut self.initial_volume, leaving, 1);
        remove_blocks(&mut self.volume, leaving, 1);
        remove_blocks(&mut self.deformation_gradient, leaving, 1);
        remove_blocks(&mut self.stress, leaving, 1);
        remove_blocks(&mut self.temperature, leaving, 1);
        remove_blocks(&mut self.specific_internal_energy, leaving, 1);
        remove_blocks(&mut self.material, leaving, 1);
        remove_blocks(&mut self.failed, leaving, 1);
        remove_blocks(&mut self.history, leaving, self.history_stride);
    }

    /// Reorders every array so that new particle i is old particle
    /// `perm[i]` (a permutation of 0..len). Each array is gathered into a
    /// reused buffer of the set and swapped with it (see
    /// `PermuteScratch`): no allocation once the buffers have grown.
    pub fn permute(&mut self, perm: &[usize]) {
        let sc = &mut self.scratch;
        permute_into(&mut self.position, perm, &mut sc.vector);
        permute_into(&mut self.velocity, perm, &mut sc.vector);
        permute_into(&mut self.mass, perm, &mut sc.scalar);
        permute_into(&mut self.initial_volume, perm, &mut sc.scalar);
        permute_into(&mut self.volume, perm, &mut sc.scalar);
        permute_into(&mut self.deformation_gradient, perm, &mut sc.tensor);
        permute_into(&mut self.stress, perm, &mut sc.voigt);
        permute_into(&mut self.temperature, perm, &mut sc.scalar);
        permute_into(&mut self.specific_internal_energy, perm, &mut sc.scalar);
        permute_into(&mut self.material, perm, &mut sc.material);
        permute_into(&mut self.failed, perm, &mut sc.flag);
        let s = self.history_stride;
        if s > 0 {
            let h = &mut sc.scalar;
            h.clear();
            h.resize(perm.len() * s, 0.0);
            let old = &self.history;
            h.par_chunks_mut(s)
                .zip(perm.par_iter())
                .with_min_len(4096)
                .for_each(|(h, &p)| h.copy_from_slice(&old[p * s..(p + 1) * s]));
            std::mem::swap(&mut self.history, h);
        }
    }
}

/// The symmetric tensor of Voigt components (xx, yy, zz, yz, xz, xy).
pub fn voigt_to_matrix(s: &[f64; 6]) -> Mat3 {
    Mat3::new(s[0], s[5], s[4], s[5], s[1], s[3], s[4], s[3], s[2])
}

/// Voigt components (xx, yy, zz, yz, xz, xy) of the symmetric part of `m`.
pub fn matrix_to_voigt(m: &Mat3) -> [f64; 6] {
    [
        m[(0, 0)],
        m[(1, 1)],
        m[(2, 2)],
        0.5 * (m[(1, 2)] + m[(2, 1)]),
        0.5 * (m[(0, 2)] + m[(2, 0)]),
        0.5 * (m[(0, 1)] + m[(1, 0)]),
    ]
}

#[cfg(test)]
mod tests {
    use super::*;

    fn grid() -> UniformGridGeometry {
        UniformGridGeometry {
            origin: [0.0; 3],
            spacing: [1.0; 3],
            cells: [4, 3, 2],
        }
    }

    fn particle(x: [f64; 3], mass: f64) -> ParticleInit {
        ParticleInit {
            position: x,
            mass,
            volume: 0.5,
            temperature: 300.0,
            ..Default::default()
        }
    }

    #[test]
    fn push_rejects_invalid_particles_with_a_reason() {
        let mut ps = Particles::new(2);
        let e = ps.push(&particle([0.5; 3], 0.0), &[0.0; 2]).unwrap_err();
        assert!(e.to_string().contains("mass"));
        let e = ps
            .push(&particle([f64::NAN, 0.0, 0.0], 1.0), &[0.0; 2])
            .unwrap_err();
        assert!(e.to_string().contains("finite"));
        let e = ps.push(&particle([0.5; 3], 1.0), &[0.0; 3]).unwrap_err();
        assert!(matches!(
            e,
            ParticleError::HistoryLength {
                got: 3,
                stride: 2,
                ..
            }
        ));
        assert!(ps.is_empty());
        assert_eq!(ps.push(&particle([0.5; 3], 1.0), &[1.0, 2.0]), Ok(0));
        assert_eq!(ps.len(), 1);
        assert_eq!(ps.volume[0], ps.initial_volume[0]);
        assert_eq!(ps.deformation_gradient_of(0), Mat3::identity());
    }

    #[test]
    fn sort_by_cell_is_stable_and_permutes_every_array() {
        let g = grid();
        let mut ps = Particles::new(1);
        // Cells (linear index): 3·4+1 = 13, 0, 13, 23, 0.
        let xs = [
            [1.5, 0.5, 1.5],
            [0.2, 0.2, 0.2],
            [1.7, 0.1, 1.1],
            [3.5, 2.5, 1.5],
            [0.9, 0.9, 0.9],
        ];
        for (k, &x) in xs.iter().enumerate() {
            let mut p = particle(x, 1.0 + k as f64);
            p.velocity = [k as f64, 0.0, 0.0];
            p.stress = [k as f64; 6];
            p.material = MaterialId(k as u16);
            ps.push(&p, &[10.0 * k as f64]).unwrap();
        }
        ps.failed[2] = true;
        let perm = ps.sort_by_cell(&g).unwrap();
        assert_eq!(perm, vec![1, 4, 0, 2, 3]);
        for (new, &old) in perm.iter().enumerate() {
            assert_eq!(ps.position[new], xs[old]);
            assert_eq!(ps.mass[new], 1.0 + old as f64);
            assert_eq!(ps.velocity[new][0], old as f64);
            assert_eq!(ps.stress[new][3], old as f64);
            assert_eq!(ps.material[new], MaterialId(old as u16));
            assert_eq!(ps.history_of(new), &[10.0 * old as f64]);
            assert_eq!(ps.failed[new], old == 2);
        }
        let mut cells = Vec::new();
        ps.cell_indices(&g, &mut cells).unwrap();
        assert!(cells.windows(2).all(|w| w[0] <= w[1]));
        assert!(ps.is_sorted_by_cell(&g));
        ps.position.swap(0, 4);
        assert!(!ps.is_sorted_by_cell(&g));
        ps.position.swap(0, 4);
        ps.position[0] = [-1.0, 0.5, 0.5];
        assert!(
            !ps.is_sorted_by_cell(&g),
            "a particle outside is not sorted"
        );
    }

    /// `count` particles whose every array holds values made from the index
    /// k, so a test can say which old particle sits where.
    fn numbered(count: usize) -> Particles {
        let mut ps = Particles::new(2);
        for k in 0..count {
            let f = k as f64;
            let mut p = particle([0.5 + f, 0.25 * f, 0.5], 1.0 + f);
            p.velocity = [f, -f, 2.0 * f];
            p.volume = 0.5 + f;
            p.deformation_gradient = [f; 9];
            p.stress = [-f; 6];
            p.temperature = 300.0 + f;
            p.specific_internal_energy = 1e3 * f;
            p.material = MaterialId(k as u16);
            ps.push(&p, &[10.0 * f, 10.0 * f + 1.0]).unwrap();
            ps.volume[k] = 0.25 + f;
            ps.failed[k] = k == 3 || k == 5;
        }
        ps
    }

    /// Whether new particle i of `ps` holds exactly old particle `old[i]`
    /// of a set made by `numbered`.
    fn assert_holds(ps: &Particles, old: &[usize]) {
        assert_eq!(ps.len(), old.len());
        assert_eq!(ps.history.len(), 2 * old.len());
        let fresh = numbered(7);
        for (i, &k) in old.iter().enumerate() {
            assert_eq!(ps.position[i], fresh.position[k]);
            assert_eq!(ps.velocity[i], fresh.velocity[k]);
            assert_eq!(ps.mass[i], 1.0 + k as f64);
            assert_eq!(ps.initial_volume[i], 0.5 + k as f64);
            assert_eq!(ps.volume[i], 0.25 + k as f64);
            assert_eq!(ps.deformation_gradient[i], [k as f64; 9]);
            assert_eq!(ps.stress[i], [-(k as f64); 6]);
            assert_eq!(ps.temperature[i], 300.0 + k as f64);
            assert_eq!(ps.specific_internal_energy[i], 1e3 * k as f64);
            assert_eq!(ps.material[i], MaterialId(k as u16));
            assert_eq!(ps.history_of(i), &[10.0 * k as f64, 10.0 * k as f64 + 1.0]);
            assert_eq!(ps.failed[i], k == 3 || k == 5);
        }
    }

    #[test]
    fn remove_sorted_keeps_the_others_in_order_in_place() {
        let mut ps = numbered(7);
        let position = ps.position.as_ptr();
        let history = ps.history.as_ptr();
        ps.remove_sorted(&[0, 2, 3, 6]);
        assert_holds(&ps, &[1, 4, 5]);
        assert_eq!(ps.position.as_ptr(), position, "no reallocation");
        assert_eq!(ps.history.as_ptr(), history, "no reallocation");
        assert!(ps.mass.capacity() >= 7, "the capacity stays");

        let mut ps = numbered(7);
        ps.remove_sorted(&[]);
        assert_holds(&ps, &[0, 1, 2, 3, 4, 5, 6]);
        ps.remove_sorted(&[4, 4, 5]);
        assert_holds(&ps, &[0, 1, 2, 3, 6]);
        ps.remove_sorted(&[0, 1, 2, 3, 4]);
        assert!(ps.is_empty() && ps.history.is_empty());
    }

    #[test]
    #[should_panic(expected = "increasing")]
    fn remove_sorted_rejects_unsorted_indices() {
        numbered(4).remove_sorted(&[2, 1]);
    }

    #[test]
    #[should_panic(expected = "below 4")]
    fn remove_sorted_rejects_an_index_past_the_end() {
        numbered(4).remove_sorted(&[1, 4]);
    }

    #[test]
    fn select_keeps_the_given_particles_in_place() {
        let mut ps = numbered(7);
        let stress = ps.stress.as_ptr();
        ps.select(&[1, 2, 5]);
        assert_holds(&ps, &[1, 2, 5]);
        assert_eq!(ps.stress.as_ptr(), stress);
        let mut other = numbered(7);
        other.remove_sorted(&[0, 3, 4, 6]);
        assert_eq!(
            ps, other,
            "select and remove_sorted of the complement agree"
        );
    }

    #[test]
    fn permute_reorders_every_array_and_reuses_its_buffers() {
        let mut ps = numbered(7);
        let perm = [6, 0, 5, 1, 4, 2, 3];
        ps.permute(&perm);
        assert_holds(&ps, &perm);
        // The buffers now hold the old arrays' storage; permuting back
        // allocates nothing and restores the set.
        let mut back = [0; 7];
        for (i, &p) in perm.iter().enumerate() {
            back[p] = i;
        }
        let before = [
            ps.scratch.vector.as_ptr() as usize,
            ps.position.as_ptr() as usize,
            ps.velocity.as_ptr() as usize,
        ];
        ps.permute(&back);
        assert_holds(&ps, &[0, 1, 2, 3, 4, 5, 6]);
        let mut after = [
            ps.scratch.vector.as_ptr() as usize,
            ps.position.as_ptr() as usize,
            ps.velocity.as_ptr() as usize,
        ];
        let mut before = before;
        before.sort_unstable();
        after.sort_unstable();
        assert_eq!(before, after, "the 3-vector arrays trade three buffers");
        assert_eq!(ps, numbered(7), "the buffers are not part of equality");
    }

    #[test]
    fn push_zero_history_checks_and_appends_zeros() {
        let mut ps = numbered(2);
        let e = ps.push_zero_history(&particle([0.5; 3], -1.0)).unwrap_err();
        assert!(e.to_string().contains("mass"));
        assert_eq!(ps.len(), 2);
        assert_eq!(ps.push_zero_history(&particle([0.5; 3], 1.0)), Ok(2));
        assert_eq!(ps.history_of(2), &[0.0, 0.0]);
        assert_eq!(ps.history.len(), 6);
    }

    #[test]
    fn sort_by_cell_rejects_a_particle_outside_the_grid() {
        let mut ps = Particles::new(0);
        ps.push(&particle([0.5; 3], 1.0), &[]).unwrap();
        ps.push(&particle([5.0, 0.5, 0.5], 1.0), &[]).unwrap();
        let e = ps.sort_by_cell(&grid()).unwrap_err();
        assert!(matches!(e, ParticleError::OutsideGrid { index: 1, .. }));
    }

    #[test]
    fn state_bytes_count_every_array() {
        let mut ps = Particles::new(7);
        for k in 0..3 {
            ps.push(&particle([0.5 + k as f64, 0.5, 0.5], 1.0), &[0.0; 7])
                .unwrap();
        }
        // 3·(24 + 24 + 8 + 8 + 8 + 72 + 48 + 8 + 8 + 2 + 1) + 3·7·8.
        assert_eq!(ps.state_bytes(), 3 * 211 + 3 * 56);
    }

    #[test]
    fn voigt_and_matrix_forms_invert() {
        let s = [1.0, 2.0, 3.0, 4.0, 5.0, 6.0];
        let m = voigt_to_matrix(&s);
        assert_eq!(m, m.transpose());
        assert_eq!(m[(0, 1)], 6.0);
        assert_eq!(m[(1, 2)], 4.0);
        assert_eq!(matrix_to_voigt(&m), s);
    }
}
