//! The linear systems of [`MsdmLattice`]: the free degrees of freedom,
//! the assembled matrix of the implicit step and its solve, and the
//! static equilibrium by Newton's method.

use super::{bond_jacobian, LinearSolver, MsdmError, MsdmLattice, INTACT};
use crate::sparse::{bicgstab, solve_direct, SolveStats};

impl MsdmLattice {
    /// Free degrees of freedom: solid nodes without a prescribed velocity.
    pub(crate) fn number_dofs(&mut self) -> usize {
        let mut k = 0;
        for i in 0..self.len() {
            if self.geom.is_solid(i) && !self.prescribed[i] {
                self.dof[i] = k;
                k += 1;
            } else {
                self.dof[i] = usize::MAX;
            }
        }
        k * self.geom.dim.count()
    }

    /// Assembles A = c_m M − c_c ∂f/∂u − c_k ∂f/∂x on the free degrees of
    /// freedom into [`MsdmLattice::matrix`], and K u (the product of ∂f/∂x
    /// with the current velocities, all nodes) into `ku` (per free dof).
    pub(crate) fn assemble(&mut self, cm: f64, cc: f64, ck: f64, ku: &mut [f64]) {
        let dim = self.geom.dim.count();
        let nd = self.geom.directions.len();
        let mut a = std::mem::take(&mut self.matrix);
        a.clear();
        let mut blocks: [(usize, [[f64; 3]; 3]); 32] = [(0, [[0.0; 3]; 3]); 32];
        for i in 0..self.len() {
            let di = self.dof[i];
            if di == usize::MAX {
                continue;
            }
            let mut diag = [[0.0; 3]; 3];
            let mut kuv = [0.0; 3];
            let mut nb = 0;
            for (d, dir) in self.geom.directions.iter().enumerate() {
                for sign in [1isize, -1] {
                    let j = i as isize + sign * dir.offset;
                    if j < 0 || j as usize >= self.len() {
                        continue;
                    }
                    let j = j as usize;
                    let (lo, bond) = if sign > 0 {
                        (i, i * nd + d)
                    } else {
                        (j, j * nd + d)
                    };
                    if self.status[bond] != INTACT {
                        continue;
                    }
                    let b = self.eval_bond(lo, d, self.spring[bond]);
                    let (kx, cu) = bond_jacobian(&b);
                    let mut g = [[0.0; 3]; 3];
                    for r in 0..3 {
                        for c in 0..3 {
                            g[r][c] = cc * cu[r][c] + ck * kx[r][c];
                            diag[r][c] += g[r][c];
                        }
                    }
                    for r in 0..3 {
                        for c in 0..3 {
                            kuv[r] += kx[r][c] * (self.u[c][j] - self.u[c][i]);
                        }
                    }
                    if self.dof[j] != usize::MAX {
                        blocks[nb] = (self.dof[j], g);
                        nb += 1;
                    }
                }
            }
            for r in 0..dim {
                a.push(di * dim + r, 0.0);
                let first = a.val.len() - 1;
                for c in 0..dim {
                    if c == r {
                        a.val[first] = cm * self.mass[i] + diag[r][r];
                    } else {
                        a.push(di * dim + c, diag[r][c]);
                    }
                }
                for (dj, g) in &blocks[..nb] {
                    for c in 0..dim {
                        a.push(dj * dim + c, -g[r][c]);
                    }
                }
                a.end_row();
                ku[di * dim + r] = kuv[r];
            }
        }
        self.matrix = a;
    }

    /// Solves `matrix · delta = rhs`.
    pub(crate) fn solve(&mut self) -> Result<SolveStats, MsdmError> {
        let n = self.rhs.len();
        self.delta.resize(n, 0.0);
        let tol = self.options.solver_tolerance;
        match self.options.linear_solver {
            LinearSolver::Direct => solve_direct(&self.matrix, &self.rhs, &mut self.delta),
            LinearSolver::Iterative => bicgstab(
                &self.matrix,
                &self.rhs,
                &mut self.delta,
                tol,
                (10 * n).max(100),
                &mut self.work,
            ),
        }
        .map_err(MsdmError::Solve)
    }

    /// Static equilibrium f(x) = 0 by Newton's method with the assembled
    /// ∂f/∂x (velocities zero): at most `max_iter` iterations, until the
    /// largest nodal force is below `tol` times the largest body force or
    /// the Newton update is below round-off of the coordinates.
    /// Returns the number of iterations.
    pub fn solve_static(&mut self, max_iter: usize, tol: f64) -> Result<usize, MsdmError> {
        for a in 0..3 {
            self.u[a].iter_mut().for_each(|v| *v = 0.0);
        }
        let ndof = self.number_dofs();
        let dim = self.geom.dim.count();
        let scale = (0..3)
            .flat_map(|a| self.body[a].iter())
            .fold(0.0f64, |m, v| m.max(v.abs()))
            .max(f64::MIN_POSITIVE);
        let mut ku = vec![0.0; ndof];
        for it in 0..=max_iter {
            self.compute_forces();
            let fmax = (0..self.len())
                .filter(|&i| self.dof[i] != usize::MAX)
                .flat_map(|i| (0..dim).map(move |a| (i, a)))
                .fold(0.0f64, |m, (i, a)| m.max(self.force[a][i].abs()));
            if fmax <= tol * scale {
                self.update_volume_and_energy(0.0);
                return Ok(it);
            }
            if it == max_iter {
                break;
            }
            self.assemble(0.0, 0.0, 1.0, &mut ku);
            self.rhs.resize(ndof, 0.0);
            for i in 0..self.len() {
                let di = self.dof[i];
                if di != usize::MAX {
                    for a in 0..dim {
                        self.rhs[di * dim + a] = self.force[a][i];
                    }
                }
            }
            self.solve()?;
            let mut step_max = 0.0f64;
            let mut x_max = 0.0f64;
            for i in 0..self.len() {
                let di = self.dof[i];
                if di != usize::MAX {
                    for a in 0..dim {
                        let dx = self.delta[di * dim + a];
                        self.x[a][i] += dx;
                        step_max = step_max.max(dx.abs());
                        x_max = x_max.max(self.x[a][i].abs());
                    }
                }
            }
            // Converged to round-off: the update no longer moves a node
            // by more than a few ulps of the coordinates.
            if step_max <= 4.0 * f64::EPSILON * x_max {
                self.compute_forces();
                self.update_volume_and_energy(0.0);
                return Ok(it + 1);
            }
        }
        Err(MsdmError::Solve(format!(
            "static solve did not converge in {max_iter} Newton iterations"
        )))
    }
}
