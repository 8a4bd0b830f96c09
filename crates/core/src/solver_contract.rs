//! The [`Solver`] contract, checked on a running solver: the promises of
//! the trait's doc (a step of the stable Δt advances the clock by Δt; a
//! bad step is refused and leaves the last good state; the same input
//! gives the same bits whatever the thread count; a restored checkpoint
//! continues bit-identically; a damaged checkpoint is an error, not a
//! panic) and, where the scheme conserves them on the problem given,
//! mass, momentum and energy.
//!
//! A solver joins with one line in the tests of the crate that builds it
//! (the composer builds every pipeline from a scenario):
//!
//! ```text
//! check_solver(&|| build(&scenario), &SolverContract::new(4, 4).conserving_mass(1e-14))
//! ```

use rayon::ThreadPoolBuilder;

use crate::Solver;

/// How [`check_solver`] exercises a solver.
#[derive(Debug, Clone, PartialEq)]
pub struct SolverContract {
    /// Steps taken before the checkpoint.
    pub before: usize,
    /// Steps taken after it.
    pub after: usize,
    /// Each step is this fraction of the stable Δt (in (0, 1]).
    pub dt_fraction: f64,
    /// Two thread counts whose runs must agree bit for bit.
    pub threads: [usize; 2],
    /// Where the scheme conserves on this problem: the largest relative
    /// change of the mass and of the total energy over the run, and the
    /// largest change of each momentum component relative to Σ|p| at the
    /// start plus the mass times `momentum_scale` m/s.
    pub conserved: Option<Conserved>,
}

/// Tolerances of the conservation check of [`SolverContract`]; `None`:
/// that quantity is not checked (the scheme does not conserve it on the
/// problem, a wall's force on the momentum for instance).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Conserved {
    /// Largest |M(t)/M(0) − 1|.
    pub mass: Option<f64>,
    /// Largest |E(t)/E(0) − 1|.
    pub energy: Option<f64>,
    /// Largest |p_d(t) − p_d(0)| / (Σ_d |p_d(0)| + M(0) · 1 m/s).
    pub momentum: Option<f64>,
}

impl SolverContract {
    /// `before` steps, a checkpoint, `after` steps, each the full stable
    /// Δt, on 1 and 3 threads; no conservation check.
    pub fn new(before: usize, after: usize) -> Self {
        Self {
            before,
            after,
            dt_fraction: 1.0,
            threads: [1, 3],
            conserved: None,
        }
    }

    /// Steps of `fraction` of the stable Δt.
    pub fn with_dt_fraction(mut self, fraction: f64) -> Self {
        self.dt_fraction = fraction;
        self
    }

    /// Checks that the mass changes by at most `tol` (relative).
    pub fn conserving_mass(mut self, tol: f64) -> Self {
        self.conserved.get_or_insert_with(Conserved::default).mass = Some(tol);
        self
    }

    /// Checks that the total energy changes by at most `tol` (relative).
    pub fn conserving_energy(mut self, tol: f64) -> Self {
        self.conserved.get_or_insert_with(Conserved::default).energy = Some(tol);
        self
    }

    /// Checks that each momentum component changes by at most `tol`
    /// (relative to Σ|p(0)| + M(0) · 1 m/s).
    pub fn conserving_momentum(mut self, tol: f64) -> Self {
        self.conserved
            .get_or_insert_with(Conserved::default)
            .momentum = Some(tol);
        self
    }
}

/// Every bit a solver shows: its clock, its conservation totals, every
/// cell field it names and every particle's position and fields.
#[derive(Debug, Clone, PartialEq)]
pub struct Fingerprint {
    /// (what, bits) pairs in a fixed order.
    pub entries: Vec<(String, Vec<u64>)>,
}

impl Fingerprint {
    /// The first entry where `self` and `other` differ, named.
    pub fn first_difference(&self, other: &Fingerprint) -> Option<String> {
        if self.entries.len() != other.entries.len() {
            return Some(format!(
                "{} entries against {}",
                self.entries.len(),
                other.entries.len()
            ));
        }
        for ((na, a), (nb, b)) in self.entries.iter().zip(&other.entries) {
            if na != nb {
                return Some(format!("entry {na} against {nb}"));
            }
            if a.len() != b.len() {
                return Some(format!("{na}: {} values against {}", a.len(), b.len()));
            }
            if let Some(i) = a.iter().zip(b).position(|(x, y)| x != y) {
                return Some(format!(
                    "{na}[{i}]: {:e} against {:e}",
                    f64::from_bits(a[i]),
                    f64::from_bits(b[i])
                ));
            }
        }
        None
    }
}

/// The [`Fingerprint`] of a solver's present state.
pub fn fingerprint(solver: &dyn Solver) -> Result<Fingerprint, String> {
    let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<u64>>();
    let mut entries = vec![("time".to_string(), bits(&[solver.time()]))];
    let t = solver.conservation_totals();
    entries.push((
        "conservation totals".into(),
        bits(&[
            t.mass,
            t.momentum[0],
            t.momentum[1],
            t.momentum[2],
            t.energy,
        ]),
    ));
    let names: Vec<String> = solver
        .cell_field_names()
        .iter()
        .map(|s| s.to_string())
        .collect();
    if !names.is_empty() {
        let cells = solver
            .cell_data(&names)
            .map_err(|e| format!("{}: cell_data of its own field names: {e}", solver.name()))?;
        for (name, v) in &cells.fields {
            entries.push((format!("cell field {name}"), bits(v)));
        }
    }
    if let Some(p) = solver.particle_data() {
        let flat: Vec<f64> = p.positions.iter().flatten().copied().collect();
        entries.push(("particle positions".into(), bits(&flat)));
        for (name, v) in &p.fields {
            entries.push((format!("particle field {name}"), bits(v)));
        }
    }
    Ok(Fingerprint { entries })
}

/// Takes `n` steps of `fraction` of the stable Δt, checking each: Δt
/// finite and positive, the step accepted, the clock moved by Δt.
fn steps(solver: &mut dyn Solver, n: usize, fraction: f64) -> Result<(), String> {
    let name = solver.name().to_string();
    for k in 0..n {
        let stable = solver
            .stable_dt()
            .map_err(|e| format!("{name}: stable_dt at step {k}: {e}"))?;
        if !(stable.is_finite() && stable > 0.0) {
            return Err(format!("{name}: stable_dt {stable:e} at step {k}"));
        }
        let dt = fraction * stable;
        let t0 = solver.time();
        solver
            .advance(dt)
            .map_err(|e| format!("{name}: a step of {dt:e} s (the stable Δt times {fraction}) failed at step {k}: {e}"))?;
        let moved = solver.time() - t0;
        if !((moved - dt).abs() <= 1e-12 * solver.time().abs().max(dt)) {
            return Err(format!(
                "{name}: a step of {dt:e} s moved the clock by {moved:e} s (step {k})"
            ));
        }
    }
    Ok(())
}

/// Runs `f` on a rayon pool of `threads` threads.
fn on_threads<T: Send>(threads: usize, f: impl FnOnce() -> T + Send) -> Result<T, String> {
    let pool = ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .map_err(|e| format!("a pool of {threads} threads: {e}"))?;
    Ok(pool.install(f))
}

/// The whole contract (module doc) on solvers made by `make`, which must
/// give the same initial state on every call. Returns the first broken
/// promise, named.
pub fn check_solver(
    make: &(dyn Fn() -> Box<dyn Solver> + Sync),
    c: &SolverContract,
) -> Result<(), String> {
    if !(c.dt_fraction > 0.0 && c.dt_fraction <= 1.0) {
        return Err(format!("dt_fraction {} is not in (0, 1]", c.dt_fraction));
    }
    let total = c.before + c.after;
    // Construction is deterministic.
    let first = make();
    let name = first.name().to_string();
    let start = fingerprint(first.as_ref())?;
    if let Some(d) = start.first_difference(&fingerprint(make().as_ref())?) {
        return Err(format!("{name}: two solvers made alike differ: {d}"));
    }
    let totals0 = first.conservation_totals();
    drop(first);

    // Bad steps are refused and change nothing.
    let mut s = make();
    steps(s.as_mut(), 1, c.dt_fraction)?;
    let good = fingerprint(s.as_ref())?;
    for bad in [f64::NAN, -1e-9, 0.0, f64::INFINITY] {
        if s.advance(bad).is_ok() {
            return Err(format!("{name}: a step of {bad:e} s was accepted"));
        }
        if let Some(d) = good.first_difference(&fingerprint(s.as_ref())?) {
            return Err(format!(
                "{name}: a refused step of {bad:e} s changed the state: {d}"
            ));
        }
    }

    // The same bits on either thread count, and conservation on the way.
    let run = |threads: usize| -> Result<Fingerprint, String> {
        on_threads(threads, || -> Result<Fingerprint, String> {
            let mut s = make();
            for k in 0..total {
                steps(s.as_mut(), 1, c.dt_fraction)?;
                if let Some(tol) = c.conserved {
                    let t = s.conservation_totals();
                    let dm = (t.mass / totals0.mass - 1.0).abs();
                    let de = (t.energy / totals0.energy - 1.0).abs();
                    let scale =
                        totals0.momentum.iter().map(|p| p.abs()).sum::<f64>() + totals0.mass;
                    let dp = (0..3)
                        .map(|d| (t.momentum[d] - totals0.momentum[d]).abs() / scale)
                        .fold(0.0, f64::max);
                    for (what, change, limit) in [
                        ("mass", dm, tol.mass),
                        ("energy", de, tol.energy),
                        ("momentum", dp, tol.momentum),
                    ] {
                        if let Some(limit) = limit {
                            if !(change <= limit) {
                                return Err(format!(
                                    "{name}: after step {k} the {what} changed by {change:e} \
                                     (relative; at most {limit:e})"
                                ));
                            }
                        }
                    }
                }
            }
            fingerprint(s.as_ref())
        })?
    };
    let [ta, tb] = c.threads;
    let reference = run(ta)?;
    if let Some(d) = reference.first_difference(&run(tb)?) {
        return Err(format!(
            "{name}: {total} steps on {ta} and on {tb} threads differ: {d}"
        ));
    }

    // A restored checkpoint continues bit-identically.
    let mut a = make();
    steps(a.as_mut(), c.before, c.dt_fraction)?;
    let saved = a
        .save_state()
        .map_err(|e| format!("{name}: save_state: {e}"))?;
    let mut b = make();
    b.restore_state(&saved)
        .map_err(|e| format!("{name}: restore_state of its own checkpoint: {e}"))?;
    if let Some(d) = fingerprint(a.as_ref())?.first_difference(&fingerprint(b.as_ref())?) {
        return Err(format!(
            "{name}: the restored state differs from the saved one: {d}"
        ));
    }
    steps(a.as_mut(), c.after, c.dt_fraction)?;
    steps(b.as_mut(), c.after, c.dt_fraction)?;
    let fa = fingerprint(a.as_ref())?;
    if let Some(d) = fa.first_difference(&fingerprint(b.as_ref())?) {
        return Err(format!(
            "{name}: {} steps after a restore differ from the uninterrupted run: {d}",
            c.after
        ));
    }
    if let Some(d) = fa.first_difference(&reference) {
        return Err(format!(
            "{name}: the checkpointed run differs from the run in one go: {d}"
        ));
    }

    // A cut or empty checkpoint is an error, and the solver keeps its
    // state.
    for bytes in [&saved[..saved.len() / 2], &[][..]] {
        if b.restore_state(bytes).is_ok() {
            return Err(format!(
                "{name}: a checkpoint cut to {} of {} bytes was restored",
                bytes.len(),
                saved.len()
            ));
        }
        if let Some(d) = fa.first_difference(&fingerprint(b.as_ref())?) {
            return Err(format!(
                "{name}: a refused checkpoint changed the state: {d}"
            ));
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{CellData, ConservationTotals, SolverError, UniformGridGeometry};

    /// A decaying scalar on two cells: u' = −u, explicit Euler, Δt ≤ 1.
    #[derive(Clone)]
    struct Decay {
        t: f64,
        u: [f64; 2],
        /// Breaks a promise on purpose.
        flaw: Flaw,
    }

    #[derive(Clone, Copy, PartialEq)]
    enum Flaw {
        None,
        AcceptsNan,
        ForgetsOnRestore,
        ClockDrift,
    }

    impl Solver for Decay {
        fn name(&self) -> &str {
            "decay"
        }
        fn time(&self) -> f64 {
            self.t
        }
        fn stable_dt(&self) -> Result<f64, SolverError> {
            Ok(0.5)
        }
        fn advance(&mut self, dt: f64) -> Result<(), SolverError> {
            if self.flaw != Flaw::AcceptsNan && !(dt > 0.0 && dt <= 1.0) {
                return Err(SolverError::Other(format!("dt {dt}")));
            }
            for u in &mut self.u {
                *u -= dt * *u;
            }
            self.t += if self.flaw == Flaw::ClockDrift {
                1.5 * dt
            } else {
                dt
            };
            Ok(())
        }
        fn conservation_totals(&self) -> ConservationTotals {
            ConservationTotals {
                mass: 1.0,
                momentum: [0.0; 3],
                energy: self.u[0] + self.u[1],
            }
        }
        fn cell_field_names(&self) -> Vec<&'static str> {
            vec!["u"]
        }
        fn cell_data(&self, _fields: &[String]) -> Result<CellData, SolverError> {
            Ok(CellData {
                geometry: UniformGridGeometry {
                    origin: [0.0; 3],
                    spacing: [1.0; 3],
                    cells: [2, 1, 1],
                },
                fields: vec![("u".into(), self.u.to_vec())],
            })
        }
        fn sample(
            &self,
            _point: [f64; 3],
            _fields: &[String],
            out: &mut Vec<f64>,
        ) -> Result<(), SolverError> {
            out.clear();
            Ok(())
        }
        fn work_per_step(&self) -> (f64, &'static str) {
            (2.0, "cells")
        }
        fn save_state(&self) -> Result<Vec<u8>, SolverError> {
            let mut b = Vec::new();
            for x in [self.t, self.u[0], self.u[1]] {
                b.extend_from_slice(&x.to_le_bytes());
            }
            Ok(b)
        }
        fn restore_state(&mut self, bytes: &[u8]) -> Result<(), SolverError> {
            if bytes.len() != 24 {
                return Err(SolverError::Checkpoint("size".into()));
            }
            let x = |k: usize| f64::from_le_bytes(bytes[8 * k..8 * k + 8].try_into().unwrap());
            self.t = x(0);
            self.u = [
                x(1),
                if self.flaw == Flaw::ForgetsOnRestore {
                    0.0
                } else {
                    x(2)
                },
            ];
            Ok(())
        }
    }

    fn make(flaw: Flaw) -> impl Fn() -> Box<dyn Solver> + Sync {
        move || {
            Box::new(Decay {
                t: 0.0,
                u: [1.0, 2.0],
                flaw,
            })
        }
    }

    #[test]
    fn a_solver_that_keeps_its_promises_passes() {
        check_solver(&make(Flaw::None), &SolverContract::new(3, 2)).unwrap();
    }

    #[test]
    fn each_broken_promise_is_named() {
        let c = SolverContract::new(3, 2);
        let e = check_solver(&make(Flaw::AcceptsNan), &c).unwrap_err();
        assert!(e.contains("was accepted"), "{e}");
        let e = check_solver(&make(Flaw::ForgetsOnRestore), &c).unwrap_err();
        assert!(e.contains("restored state differs"), "{e}");
        let e = check_solver(&make(Flaw::ClockDrift), &c).unwrap_err();
        assert!(e.contains("moved the clock"), "{e}");
        // The decay loses "energy": a conservation check catches it.
        let e = check_solver(&make(Flaw::None), &c.clone().conserving_energy(1e-3)).unwrap_err();
        assert!(e.contains("energy"), "{e}");
        let e = check_solver(&make(Flaw::None), &c.with_dt_fraction(0.0)).unwrap_err();
        assert!(e.contains("dt_fraction"), "{e}");
    }
}
