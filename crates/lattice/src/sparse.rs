//! A compressed-row sparse matrix and the two solvers of the linearised
//! systems of the implicit steps (seed 003 eqs 21–22): sparse LU with
//! partial pivoting from faer ([`solve_direct`], the default) and a
//! Jacobi-preconditioned BiCGSTAB ([`bicgstab`]).
//!
//! Both give the same bits whatever the thread count: faer runs
//! sequentially here (the crate is built without its rayon feature), and in
//! BiCGSTAB the matrix-vector product is split by rows while the inner
//! products are summed serially in index order.

use rayon::prelude::*;

/// Compressed-row matrix whose rows are filled in order.
#[derive(Debug, Clone, Default)]
pub struct CsrMatrix {
    /// Row starts, `rows + 1` entries.
    pub row_start: Vec<usize>,
    /// Column of each entry.
    pub col: Vec<usize>,
    /// Value of each entry.
    pub val: Vec<f64>,
}

impl CsrMatrix {
    /// Empties the matrix, keeping its storage.
    pub fn clear(&mut self) {
        self.row_start.clear();
        self.row_start.push(0);
        self.col.clear();
        self.val.clear();
    }

    /// Appends an entry to the current row.
    #[inline]
    pub fn push(&mut self, col: usize, val: f64) {
        self.col.push(col);
        self.val.push(val);
    }

    /// Closes the current row.
    #[inline]
    pub fn end_row(&mut self) {
        self.row_start.push(self.col.len());
    }

    /// Number of rows.
    pub fn rows(&self) -> usize {
        self.row_start.len().saturating_sub(1)
    }

    /// y = A x (rows in parallel).
    pub fn mul(&self, x: &[f64], y: &mut [f64]) {
        y.par_iter_mut().enumerate().for_each(|(r, yr)| {
            let mut s = 0.0;
            for k in self.row_start[r]..self.row_start[r + 1] {
                s += self.val[k] * x[self.col[k]];
            }
            *yr = s;
        });
    }

    /// Diagonal entry of row `r` (sum of duplicates), 0 if absent.
    pub fn diagonal(&self, r: usize) -> f64 {
        (self.row_start[r]..self.row_start[r + 1])
            .filter(|&k| self.col[k] == r)
            .map(|k| self.val[k])
            .sum()
    }
}

/// Scratch vectors of the solver, kept between steps.
#[derive(Debug, Clone, Default)]
pub struct SolverWork {
    r: Vec<f64>,
    r0: Vec<f64>,
    p: Vec<f64>,
    v: Vec<f64>,
    s: Vec<f64>,
    t: Vec<f64>,
    y: Vec<f64>,
    z: Vec<f64>,
    dinv: Vec<f64>,
}

/// Outcome of a linear solve.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SolveStats {
    /// BiCGSTAB iterations (0 for the direct solve).
    pub iterations: usize,
    /// Final ‖b − Ax‖/‖b‖.
    pub relative_residual: f64,
}

fn dot(a: &[f64], b: &[f64]) -> f64 {
    // Summed in index order: the same bits for any thread count.
    a.iter().zip(b).map(|(p, q)| p * q).sum()
}

/// ‖b − Ax‖/‖b‖ (0 when b = 0), summed in index order.
fn relative_residual(a: &CsrMatrix, b: &[f64], x: &[f64]) -> f64 {
    let bnorm = dot(b, b).sqrt();
    if bnorm == 0.0 {
        return 0.0;
    }
    let mut ax = vec![0.0; b.len()];
    a.mul(x, &mut ax);
    let r2: f64 = ax.iter().zip(b).map(|(p, q)| (p - q) * (p - q)).sum();
    r2.sqrt() / bnorm
}

/// Solves A x = b by sparse LU with partial pivoting (faer's `sp_lu`,
/// sequential). Duplicate entries of a row are summed. Returns an error
/// message for a singular matrix or a non-finite solution; the residual is
/// reported, not tested, since a direct solve has no tolerance to meet.
pub fn solve_direct(a: &CsrMatrix, b: &[f64], x: &mut [f64]) -> Result<SolveStats, String> {
    use faer::linalg::solvers::Solve;
    use faer::sparse::{SparseColMat, Triplet};
    let n = a.rows();
    if b.len() != n || x.len() != n {
        return Err(format!(
            "matrix has {n} rows but the right-hand side {} and the solution {}",
            b.len(),
            x.len()
        ));
    }
    let mut triplets = Vec::with_capacity(a.val.len());
    for r in 0..n {
        for k in a.row_start[r]..a.row_start[r + 1] {
            triplets.push(Triplet::new(r, a.col[k], a.val[k]));
        }
    }
    let m = SparseColMat::<usize, f64>::try_new_from_triplets(n, n, &triplets)
        .map_err(|e| format!("sparse matrix assembly failed: {e:?}"))?;
    let lu = m
        .sp_lu()
        .map_err(|e| format!("sparse LU failed (singular system?): {e:?}"))?;
    let rhs = faer::Col::<f64>::from_fn(n, |i| b[i]);
    let sol = lu.solve(&rhs);
    for (i, xi) in x.iter_mut().enumerate() {
        *xi = sol[i];
    }
    if !x.iter().all(|v| v.is_finite()) {
        return Err("sparse LU gave a non-finite solution (singular system)".into());
    }
    Ok(SolveStats {
        iterations: 0,
        relative_residual: relative_residual(a, b, x),
    })
}

/// Solves A x = b by BiCGSTAB with the Jacobi preconditioner, from x = 0,
/// to the relative residual `tol`. Returns an error message when it does
/// not converge in `max_iter` iterations or breaks down.
pub fn bicgstab(
    a: &CsrMatrix,
    b: &[f64],
    x: &mut [f64],
    tol: f64,
    max_iter: usize,
    w: &mut SolverWork,
) -> Result<SolveStats, String> {
    let n = a.rows();
    for v in [
        &mut w.r,
        &mut w.r0,
        &mut w.p,
        &mut w.v,
        &mut w.s,
        &mut w.t,
        &mut w.y,
        &mut w.z,
        &mut w.dinv,
    ] {
        v.clear();
        v.resize(n, 0.0);
    }
    for (r, d) in w.dinv.iter_mut().enumerate() {
        let diag = a.diagonal(r);
        *d = if diag != 0.0 { 1.0 / diag } else { 1.0 };
    }
    x.iter_mut().for_each(|v| *v = 0.0);
    let bnorm = dot(b, b).sqrt();
    if bnorm == 0.0 {
        return Ok(SolveStats {
            iterations: 0,
            relative_residual: 0.0,
        });
    }
    w.r.copy_from_slice(b);
    w.r0.copy_from_slice(b);
    let (mut rho, mut alpha, mut omega) = (1.0, 1.0, 1.0);
    for it in 1..=max_iter {
        let rho_new = dot(&w.r0, &w.r);
        if rho_new == 0.0 || omega == 0.0 {
            return Err(format!("BiCGSTAB broke down at iteration {it}"));
        }
        let beta = rho_new / rho * alpha / omega;
        rho = rho_new;
        for k in 0..n {
            w.p[k] = w.r[k] + beta * (w.p[k] - omega * w.v[k]);
            w.y[k] = w.dinv[k] * w.p[k];
        }
        a.mul(&w.y, &mut w.v);
        let r0v = dot(&w.r0, &w.v);
        if r0v == 0.0 {
            return Err(format!("BiCGSTAB broke down at iteration {it}"));
        }
        alpha = rho / r0v;
        for k in 0..n {
            w.s[k] = w.r[k] - alpha * w.v[k];
        }
        let snorm = dot(&w.s, &w.s).sqrt();
        if snorm <= tol * bnorm {
            for k in 0..n {
                x[k] += alpha * w.y[k];
            }
            return Ok(SolveStats {
                iterations: it,
                relative_residual: snorm / bnorm,
            });
        }
        for k in 0..n {
            w.z[k] = w.dinv[k] * w.s[k];
        }
        a.mul(&w.z, &mut w.t);
        let tt = dot(&w.t, &w.t);
        omega = if tt > 0.0 { dot(&w.t, &w.s) / tt } else { 0.0 };
        for k in 0..n {
            x[k] += alpha * w.y[k] + omega * w.z[k];
            w.r[k] = w.s[k] - omega * w.t[k];
        }
        let rnorm = dot(&w.r, &w.r).sqrt();
        if rnorm <= tol * bnorm {
            return Ok(SolveStats {
                iterations: it,
                relative_residual: rnorm / bnorm,
            });
        }
    }
    Err(format!(
        "BiCGSTAB did not converge in {max_iter} iterations (relative residual {:.3e})",
        relative_residual(a, b, x)
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A = tridiag(−1, 4, −2), n = 50, x* = (1, 2, …, 50); returns
    /// (n, A, x*, b = A x*).
    fn tridiagonal_system() -> (usize, CsrMatrix, Vec<f64>, Vec<f64>) {
        let n = 50;
        let mut a = CsrMatrix::default();
        a.clear();
        for r in 0..n {
            if r > 0 {
                a.push(r - 1, -1.0);
            }
            a.push(r, 4.0);
            if r + 1 < n {
                a.push(r + 1, -2.0);
            }
            a.end_row();
        }
        let xs: Vec<f64> = (0..n).map(|k| (k + 1) as f64).collect();
        let mut b = vec![0.0; n];
        a.mul(&xs, &mut b);
        (n, a, xs, b)
    }

    #[test]
    fn solves_a_nonsymmetric_tridiagonal_system() {
        let (n, a, xs, b) = tridiagonal_system();
        let mut x = vec![0.0; n];
        let mut w = SolverWork::default();
        let st = bicgstab(&a, &b, &mut x, 1e-13, 200, &mut w).unwrap();
        assert!(st.relative_residual <= 1e-13);
        for k in 0..n {
            assert!((x[k] - xs[k]).abs() < 1e-10 * xs[k], "{k}: {}", x[k]);
        }
    }

    #[test]
    fn reports_non_convergence() {
        let mut a = CsrMatrix::default();
        a.clear();
        // Singular: [[1, 1], [1, 1]] with an inconsistent right-hand side.
        for _ in 0..2 {
            a.push(0, 1.0);
            a.push(1, 1.0);
            a.end_row();
        }
        let mut x = vec![0.0; 2];
        let mut w = SolverWork::default();
        assert!(bicgstab(&a, &[1.0, -1.0], &mut x, 1e-13, 20, &mut w).is_err());
    }

    #[test]
    fn direct_solve_of_a_hand_system_with_duplicate_entries() {
        // [[2, 1], [1, 3]] with the (0,0) entry given as 1.5 + 0.5:
        // x = (1, 2) ⇒ b = (4, 7).
        let mut a = CsrMatrix::default();
        a.clear();
        a.push(0, 1.5);
        a.push(1, 1.0);
        a.push(0, 0.5);
        a.end_row();
        a.push(0, 1.0);
        a.push(1, 3.0);
        a.end_row();
        let mut x = vec![0.0; 2];
        let st = solve_direct(&a, &[4.0, 7.0], &mut x).unwrap();
        assert_eq!(st.iterations, 0);
        assert!(
            (x[0] - 1.0).abs() < 1e-15 && (x[1] - 2.0).abs() < 1e-15,
            "{x:?}"
        );
        assert!(st.relative_residual < 1e-15);
    }

    #[test]
    fn direct_and_iterative_solves_agree_on_the_tridiagonal_system() {
        let (n, a, xs, b) = tridiagonal_system();
        let mut x = vec![0.0; n];
        let st = solve_direct(&a, &b, &mut x).unwrap();
        assert!(st.relative_residual < 1e-14, "{}", st.relative_residual);
        for k in 0..n {
            assert!((x[k] - xs[k]).abs() < 1e-12 * xs[k], "{k}: {}", x[k]);
        }
    }

    #[test]
    fn direct_solve_refuses_a_singular_system_and_a_size_mismatch() {
        let mut a = CsrMatrix::default();
        a.clear();
        for _ in 0..2 {
            a.push(0, 1.0);
            a.push(1, 1.0);
            a.end_row();
        }
        let mut x = vec![0.0; 2];
        assert!(solve_direct(&a, &[1.0, -1.0], &mut x).is_err());
        let mut short = vec![0.0; 1];
        assert!(solve_direct(&a, &[1.0, -1.0], &mut short)
            .unwrap_err()
            .contains("2 rows"));
    }
}
