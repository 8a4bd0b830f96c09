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
        if history.len() != self.history_stride {
            return Err(ParticleError::HistoryLength {
                index,
                got: history.len(),
                stride: self.history_stride,
            });
        }
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
        self.history.extend_from_slice(history);
        self.failed.push(false);
        Ok(index)
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

    /// Keeps only the particles `keep` (increasing indices), in that order:
    /// new particle i is old particle `keep[i]`.
    pub fn select(&mut self, keep: &[usize]) {
        self.permute(keep);
    }

    /// Reorders every array so that new particle i is old particle
    /// `perm[i]`. `perm` is a permutation of 0..len, or (through
    /// [`Particles::select`]) a subset of it.
    pub fn permute(&mut self, perm: &[usize]) {
        fn apply<T: Copy + Send + Sync>(v: &mut Vec<T>, perm: &[usize]) {
            *v = perm.par_iter().with_min_len(4096).map(|&p| v[p]).collect();
        }
        apply(&mut self.position, perm);
        apply(&mut self.velocity, perm);
        apply(&mut self.mass, perm);
        apply(&mut self.initial_volume, perm);
        apply(&mut self.volume, perm);
        apply(&mut self.deformation_gradient, perm);
        apply(&mut self.stress, perm);
        apply(&mut self.temperature, perm);
        apply(&mut self.specific_internal_energy, perm);
        apply(&mut self.material, perm);
        apply(&mut self.failed, perm);
        let s = self.history_stride;
        if s > 0 {
            let old = std::mem::take(&mut self.history);
            let mut history = vec![0.0; perm.len() * s];
            history
                .par_chunks_mut(s)
                .zip(perm.par_iter())
                .with_min_len(4096)
                .for_each(|(h, &p)| h.copy_from_slice(&old[p * s..(p + 1) * s]));
            self.history = history;
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
