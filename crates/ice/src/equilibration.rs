//! Step 2 of seed 000 §3.3: the equilibration pressure.
//!
//! Given the materials' averaged densities ρ_r = M_r/V and temperatures
//! T_r, find the one pressure p at which the thermal equations of state
//! v_r(p, T_r) (seed 000 eq 5) make the materials fill the cell exactly:
//!
//! f(p) = 1 − Σ_r ρ_r v_r(p, T_r) = 0        (seed 000 eq 7)
//!
//! with θ_r = ρ_r v_r (eq 6). Since every v_r falls as p rises, f is
//! increasing, and f'(p) = Σ_r θ_r κ_r with κ_r = (1/ρ)∂ρ/∂p|_T the
//! isothermal compressibility. Newton–Raphson ([seed 000 ref 14]) on f
//! converges quadratically near the root; far from it (a gas, for which
//! f = 1 − A/p, overshoots to negative pressure from any guess above 2A)
//! the step is safeguarded: while no bracket is known a step may change p
//! by at most a factor of 10 in the direction f points to, and once a
//! bracket [p_lo, p_hi] with f(p_lo) < 0 < f(p_hi) is known any step that
//! leaves it, or that failed to halve |f|, is replaced by geometric
//! bisection √(p_lo p_hi) (the pressure spans decades). This is the
//! Newton-with-bisection fallback Kashiwa & Rauenzahn (seed 000 ref 6)
//! recommend and Uintah's ICE uses.

use brisance_core::Eos;

/// The largest number of materials one cell may hold (the per-cell kernels
/// keep their work arrays on the stack).
pub const MAX_MATERIALS: usize = 8;

/// Convergence settings of the equilibration iteration.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct EquilibrationSettings {
    /// Converged when |1 − Σ θ_r| ≤ tolerance (dimensionless).
    pub tolerance: f64,
    /// Iterations before the cell is reported as failed.
    pub max_iterations: usize,
}

impl Default for EquilibrationSettings {
    fn default() -> Self {
        Self {
            tolerance: 1e-12,
            max_iterations: 100,
        }
    }
}

/// How one equilibration went.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct EquilibrationReport {
    /// Newton or bisection iterations spent.
    pub iterations: usize,
    /// Final residual 1 − Σ_r θ_r (eq 7).
    pub residual: f64,
}

/// The equilibration did not converge, or an equation of state refused the
/// state. Carries the cell's state so the run stops with something to read.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error(
    "equilibration pressure (seed 000 eq 7) failed after {iterations} iterations \
     (residual {residual:e}, last pressure {pressure:e} Pa): {reason}; cell state: {state}"
)]
pub struct EquilibrationError {
    /// Iterations spent.
    pub iterations: usize,
    /// Residual 1 − Σθ at the last pressure tried.
    pub residual: f64,
    /// Last pressure tried, Pa.
    pub pressure: f64,
    /// What went wrong.
    pub reason: String,
    /// Every material's ρ_r and T_r, spelled out.
    pub state: String,
}

/// f(p) = 1 − Σ ρ_r v_r(p, T_r), writing v_r and θ_r.
fn residual<E: Eos>(
    eos: &[E],
    rho: &[f64],
    temp: &[f64],
    p: f64,
    vsp: &mut [f64],
    theta: &mut [f64],
) -> Result<f64, String> {
    let mut sum = 0.0;
    for r in 0..eos.len() {
        let rho_micro = eos[r]
            .density(p, temp[r])
            .map_err(|e| format!("material {}: {e}", r + 1))?;
        vsp[r] = 1.0 / rho_micro;
        theta[r] = rho[r] * vsp[r];
        sum += theta[r];
    }
    Ok(1.0 - sum)
}

/// f'(p) = Σ θ_r κ_r at the pressure `theta` was computed at. Only a
/// Newton step needs it, so a cell whose guess already meets the tolerance
/// (most cells in a step) never evaluates κ.
fn residual_slope<E: Eos>(eos: &[E], temp: &[f64], p: f64, theta: &[f64]) -> Result<f64, String> {
    let mut dsum = 0.0;
    for r in 0..eos.len() {
        let kappa = eos[r]
            .isothermal_compressibility(p, temp[r])
            .map_err(|e| format!("material {}: {e}", r + 1))?;
        dsum += theta[r] * kappa;
    }
    Ok(dsum)
}

fn describe(rho: &[f64], temp: &[f64]) -> String {
    let mut s = String::new();
    for r in 0..rho.len() {
        use std::fmt::Write as _;
        let _ = write!(
            s,
            "{}material {}: ρ = {:e} kg/m³, T = {:e} K",
            if r > 0 { "; " } else { "" },
            r + 1,
            rho[r],
            temp[r]
        );
    }
    s
}

/// Solves seed 000 eq 7 for the equilibration pressure of one cell.
///
/// `eos[r]`, `rho[r]` (averaged density M_r/V, kg/m³) and `temp[r]` (K)
/// describe the materials; `guess` (Pa) starts the iteration (last step's
/// pressure). On success returns p (Pa) and writes the specific volumes
/// `vsp[r] = v_r(p, T_r)` (m³/kg) and volume fractions `theta[r] = ρ_r v_r`.
/// Allocation-free unless it fails.
pub fn equilibration_pressure<E: Eos>(
    eos: &[E],
    rho: &[f64],
    temp: &[f64],
    guess: f64,
    settings: &EquilibrationSettings,
    vsp: &mut [f64],
    theta: &mut [f64],
) -> Result<(f64, EquilibrationReport), EquilibrationError> {
    let fail = |iterations, residual, pressure, reason: String| EquilibrationError {
        iterations,
        residual,
        pressure,
        reason,
        state: describe(rho, temp),
    };
    let mut p = if guess > 0.0 && guess.is_finite() {
        guess
    } else {
        1.0e5
    };
    let mut f = residual(eos, rho, temp, p, vsp, theta).map_err(|e| fail(0, f64::NAN, p, e))?;
    // Bracket: f(lo) < 0 < f(hi); 0 and ∞ mean "not found yet".
    let mut lo = 0.0_f64;
    let mut hi = f64::INFINITY;
    let mut bisect_next = false;
    for it in 1..=settings.max_iterations {
        if f.abs() <= settings.tolerance {
            return Ok((
                p,
                EquilibrationReport {
                    iterations: it - 1,
                    residual: f,
                },
            ));
        }
        if f < 0.0 {
            lo = lo.max(p);
        } else {
            hi = hi.min(p);
        }
        let bracketed = lo > 0.0 && hi.is_finite();
        if bracketed && (hi - lo) <= 4.0 * f64::EPSILON * hi {
            // The bracket has shrunk to round-off: p is the root to the
            // last bit the EOS can resolve.
            return Ok((
                p,
                EquilibrationReport {
                    iterations: it - 1,
                    residual: f,
                },
            ));
        }
        let next = if bracketed && bisect_next {
            (lo * hi).sqrt()
        } else {
            let df = residual_slope(eos, temp, p, theta).map_err(|e| fail(it, f, p, e))?;
            let newton = if df > 0.0 { p - f / df } else { f64::NAN };
            if bracketed {
                if newton > lo && newton < hi {
                    newton
                } else {
                    (lo * hi).sqrt()
                }
            } else if f < 0.0 {
                // The root lies above p.
                if newton > p {
                    newton.min(10.0 * p)
                } else {
                    10.0 * p
                }
            } else if newton > 0.0 && newton < p {
                newton.max(0.1 * p)
            } else {
                0.1 * p
            }
        };
        if !(next > 0.0 && next.is_finite()) {
            return Err(fail(it, f, p, "no positive pressure fills the cell".into()));
        }
        let f_new = residual(eos, rho, temp, next, vsp, theta).map_err(|e| fail(it, f, next, e))?;
        bisect_next = f_new.abs() > 0.5 * f.abs();
        p = next;
        f = f_new;
    }
    if f.abs() <= settings.tolerance {
        return Ok((
            p,
            EquilibrationReport {
                iterations: settings.max_iterations,
                residual: f,
            },
        ));
    }
    Err(fail(settings.max_iterations, f, p, "not converged".into()))
}

#[cfg(test)]
mod tests {
    use super::*;
    use brisance_eos::{EosModel, IdealGas, Murnaghan};

    /// Two ideal gases: p = Σ ρ_r (γ_r − 1) c_v,r T_r (Dalton), θ_r the
    /// partial-pressure ratios.
    #[test]
    fn two_ideal_gases_equilibrate_at_the_sum_of_partial_pressures() {
        let eos = [
            IdealGas::new(1.4, 1000.0, 1.0),
            IdealGas::new(1.67, 500.0, 1.0),
        ];
        // partial pressures: 0.5·0.4·1000·300 = 60 000 and 0.2·0.67·500·600 = 40 200
        let rho = [0.5, 0.2];
        let temp = [300.0, 600.0];
        let (mut v, mut th) = ([0.0; 2], [0.0; 2]);
        for guess in [1.0e-3, 1.0e2, 1.002e5, 3.0e5, 1.0e12] {
            let (p, rep) = equilibration_pressure(
                &eos,
                &rho,
                &temp,
                guess,
                &EquilibrationSettings::default(),
                &mut v,
                &mut th,
            )
            .unwrap();
            assert!(
                (p - 100_200.0).abs() <= 1e-9 * 100_200.0,
                "guess {guess}: p = {p}"
            );
            assert!((th[0] - 60_000.0 / 100_200.0).abs() < 1e-12);
            assert!((th[1] - 40_200.0 / 100_200.0).abs() < 1e-12);
            // v_r = (γ−1) c_v T / p
            assert!((v[0] - 400.0 * 300.0 / 100_200.0).abs() < 1e-12 * v[0]);
            assert!(rep.residual.abs() <= 1e-12);
            assert!(rep.iterations <= 60, "guess {guess}: {rep:?}");
        }
    }

    #[test]
    fn a_good_guess_converges_at_once() {
        let eos = [IdealGas::new(1.4, 1000.0, 1.0)];
        let (mut v, mut th) = ([0.0; 1], [0.0; 1]);
        let (p, rep) = equilibration_pressure(
            &eos,
            &[1.0],
            &[250.0],
            1.0e5,
            &EquilibrationSettings::default(),
            &mut v,
            &mut th,
        )
        .unwrap();
        assert_eq!(p, 1.0e5);
        assert_eq!(rep.iterations, 0);
        assert!((th[0] - 1.0).abs() <= 4.0 * f64::EPSILON);
    }

    /// A stiff condensed explosive and air: the residual is met to the
    /// tolerance and the pressure reproduces each material's density.
    #[test]
    fn murnaghan_and_air_share_one_pressure() {
        let eos = [
            EosModel::Murnaghan(Murnaghan::anfo_k1()),
            EosModel::IdealGas(IdealGas::air()),
        ];
        let p_true = 2.0e8;
        let t = [300.0, 900.0];
        let rho_m: Vec<f64> = (0..2)
            .map(|r| eos[r].density(p_true, t[r]).unwrap())
            .collect();
        let theta_true = [0.7, 0.3];
        let rho = [theta_true[0] * rho_m[0], theta_true[1] * rho_m[1]];
        let (mut v, mut th) = ([0.0; 2], [0.0; 2]);
        let (p, rep) = equilibration_pressure(
            &eos,
            &rho,
            &t,
            1.0e5,
            &EquilibrationSettings::default(),
            &mut v,
            &mut th,
        )
        .unwrap();
        assert!((p / p_true - 1.0).abs() < 1e-9, "p = {p}");
        assert!((th[0] + th[1] - 1.0).abs() <= 1e-12);
        assert!((th[0] - 0.7).abs() < 1e-9);
        assert!(rep.iterations > 0 && rep.iterations < 100, "{rep:?}");
    }

    /// An ideal gas that counts its κ evaluations.
    #[derive(Debug)]
    struct CountingGas {
        gas: IdealGas,
        kappa_calls: std::sync::atomic::AtomicUsize,
    }

    impl Eos for CountingGas {
        fn name(&self) -> &'static str {
            "counting_gas"
        }
        fn reference_density(&self) -> f64 {
            self.gas.reference_density()
        }
        fn pressure(&self, rho: f64, e: f64) -> f64 {
            self.gas.pressure(rho, e)
        }
        fn dp_drho(&self, rho: f64, e: f64) -> f64 {
            self.gas.dp_drho(rho, e)
        }
        fn dp_de(&self, rho: f64, e: f64) -> f64 {
            self.gas.dp_de(rho, e)
        }
        fn specific_internal_energy(
            &self,
            rho: f64,
            p: f64,
        ) -> Result<f64, brisance_core::EosError> {
            self.gas.specific_internal_energy(rho, p)
        }
        fn temperature(&self, rho: f64, e: f64) -> f64 {
            self.gas.temperature(rho, e)
        }
        fn specific_internal_energy_from_temperature(&self, rho: f64, t: f64) -> f64 {
            self.gas.specific_internal_energy_from_temperature(rho, t)
        }
        fn cv(&self, rho: f64, t: f64) -> f64 {
            self.gas.cv(rho, t)
        }
        fn density(&self, p: f64, t: f64) -> Result<f64, brisance_core::EosError> {
            self.gas.density(p, t)
        }
        fn isothermal_compressibility(
            &self,
            p: f64,
            t: f64,
        ) -> Result<f64, brisance_core::EosError> {
            self.kappa_calls
                .fetch_add(1, std::sync::atomic::Ordering::Relaxed);
            self.gas.isothermal_compressibility(p, t)
        }
        fn thermal_expansivity(&self, p: f64, t: f64) -> Result<f64, brisance_core::EosError> {
            self.gas.thermal_expansivity(p, t)
        }
    }

    /// κ is evaluated for Newton steps only: not at all when the guess
    /// already fills the cell, once per material per Newton step otherwise.
    #[test]
    fn compressibility_is_evaluated_only_for_newton_steps() {
        let eos = [
            CountingGas {
                gas: IdealGas::new(1.4, 1000.0, 1.0),
                kappa_calls: 0.into(),
            },
            CountingGas {
                gas: IdealGas::new(1.67, 500.0, 1.0),
                kappa_calls: 0.into(),
            },
        ];
        let (rho, temp) = ([0.5, 0.2], [300.0, 600.0]);
        let (mut v, mut th) = ([0.0; 2], [0.0; 2]);
        let settings = EquilibrationSettings::default();
        let calls = |eos: &[CountingGas; 2]| {
            eos.each_ref()
                .map(|g| g.kappa_calls.load(std::sync::atomic::Ordering::Relaxed))
        };
        // Dalton's pressure 100 200 Pa (see the test above) as the guess.
        let (p, rep) =
            equilibration_pressure(&eos, &rho, &temp, 100_200.0, &settings, &mut v, &mut th)
                .unwrap();
        assert_eq!(p, 100_200.0);
        assert_eq!(rep.iterations, 0);
        assert_eq!(calls(&eos), [0, 0]);
        // From 10⁵ Pa (f = 1 − 1.002 = −0.002) Newton steps converge; each
        // asks every material for κ once, and the final residual
        // evaluation asks for none.
        let (p, rep) =
            equilibration_pressure(&eos, &rho, &temp, 1.0e5, &settings, &mut v, &mut th).unwrap();
        assert!((p - 100_200.0).abs() < 1e-9 * p, "p = {p}");
        let newton_steps = calls(&eos)[0];
        assert_eq!(calls(&eos), [newton_steps, newton_steps]);
        assert!(
            newton_steps >= 1 && newton_steps <= rep.iterations,
            "{rep:?}"
        );
    }

    #[test]
    fn failure_carries_the_cell_state() {
        let eos = [IdealGas::new(1.4, 1000.0, 1.0)];
        let (mut v, mut th) = ([0.0; 1], [0.0; 1]);
        let err = equilibration_pressure(
            &eos,
            &[1.0],
            &[-5.0],
            1.0e5,
            &EquilibrationSettings::default(),
            &mut v,
            &mut th,
        )
        .unwrap_err();
        let msg = err.to_string();
        assert!(msg.contains("T = -5e0 K"), "{msg}");
        assert!(msg.contains("eq 7"), "{msg}");
        let err = equilibration_pressure(
            &eos,
            &[1.0],
            &[300.0],
            1.0e5,
            &EquilibrationSettings {
                tolerance: 0.0,
                max_iterations: 2,
            },
            &mut v,
            &mut th,
        );
        // Either exactly converged at 2 iterations or reported not converged
        // with the iteration count.
        if let Err(e) = err {
            assert_eq!(e.iterations, 2);
            assert!(e.to_string().contains("not converged"));
        }
    }
}

#[cfg(test)]
mod proptests {
    use super::*;
    use brisance_eos::IdealGas;
    use proptest::prelude::*;

    proptest! {
        /// Any mixture of up to four ideal gases, from any guess,
        /// equilibrates at Dalton's pressure with Σθ = 1.
        #[test]
        fn ideal_gas_mixtures_equilibrate_at_daltons_pressure(
            n in 1usize..=4,
            gamma in proptest::collection::vec(1.1f64..1.9, 4),
            rho in proptest::collection::vec(1e-6f64..1e3, 4),
            temp in proptest::collection::vec(10.0f64..1e4, 4),
            log_guess in -3.0f64..12.0,
        ) {
            let eos: Vec<IdealGas> = (0..n).map(|r| IdealGas::new(gamma[r], 700.0, 1.0)).collect();
            let dalton: f64 = (0..n).map(|r| rho[r] * (gamma[r] - 1.0) * 700.0 * temp[r]).sum();
            let (mut v, mut th) = ([0.0; 4], [0.0; 4]);
            let (p, rep) = equilibration_pressure(
                &eos, &rho[..n], &temp[..n], 10f64.powf(log_guess),
                &EquilibrationSettings::default(), &mut v[..n], &mut th[..n],
            ).unwrap();
            prop_assert!((p / dalton - 1.0).abs() < 1e-9, "{} vs {}", p, dalton);
            prop_assert!(rep.residual.abs() <= 1e-10, "{:?}", rep);
            prop_assert!(rep.iterations <= 100);
            let sum: f64 = th[..n].iter().sum();
            prop_assert!((sum - 1.0).abs() < 1e-9);
        }
    }
}
