//! Optional physics of seed 000 eqs 2–3: the Newtonian viscous stress
//! τ_r of each fluid material and its heat conduction j_r.
//!
//! Eq 2 carries ∇·θ_r(σ_r − σ) = ∇·(θ_r τ_r) for a fluid (σ_r = −pI + τ_r,
//! seed 000 §2 after eq 7), eq 3 carries θ_r τ_r : ∇u_r − ∇·j_r with the
//! heat flux j_r = −ρ_r b_r ∇T_r, written here with a conductivity,
//! j_r = −θ_r k_r ∇T_r. Step 8 of §3.3 accumulates them as cell sources;
//! the seed computes fluid stresses "on cell faces based on cell-centred
//! velocities" (step 7) and notes that heat conduction is "at times
//! included" (after eq 25).
//!
//! The kernels here are the face quantities and the limits; the pass over
//! the grid is `IceSolver::compute_diffusion_sources`. The discretisation
//! follows the public ICE component of Uintah (`computeTauComponents`,
//! `q_flux_FC`): face coefficients are the harmonic mean of θ_r μ_r (θ_r k_r)
//! of the two cells, face-normal derivatives are compact differences, and
//! tangential derivatives on a face are the mean of the two cells' centred
//! differences. See docs/physics/ice/diffusion.md.

use brisance_core::{Eos, Solver, SolverError};
use brisance_eos::{IdealGas, Murnaghan};
use brisance_grid::Level;
use serde::{Deserialize, Serialize};

use crate::{CellState, ExchangeCoefficients, IceBoundary, IceError, IceOptions, IceSolver, GHOST};

/// Transport coefficients of one material. Both default to 0, which skips
/// the material in the diffusion pass.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MaterialTransport {
    /// Dynamic (shear) viscosity μ, Pa·s.
    #[serde(default)]
    pub viscosity: f64,
    /// Thermal conductivity k, W/(m·K).
    #[serde(default)]
    pub thermal_conductivity: f64,
}

impl MaterialTransport {
    /// Checks that both coefficients are finite and ≥ 0; the message names
    /// the field and `what` (e.g. "material 2").
    pub fn validate(&self, what: &str) -> Result<(), IceError> {
        for (name, v) in [
            ("viscosity", self.viscosity),
            ("thermal_conductivity", self.thermal_conductivity),
        ] {
            if !(v >= 0.0 && v.is_finite()) {
                return Err(IceError::Invalid(format!(
                    "ice: {what}: field `{name}` = {v}, expected a finite value ≥ 0"
                )));
            }
        }
        Ok(())
    }

    /// Whether the material takes part in the diffusion pass.
    pub fn is_active(&self) -> bool {
        self.viscosity > 0.0 || self.thermal_conductivity > 0.0
    }
}

/// The face coefficient of two cells' coefficients a = θ_L μ (or θ_L k) and
/// b = θ_R μ: the harmonic mean 2ab/(a + b) (Uintah's `q_flux_FC` and
/// `computeTauX`), 0 when both are 0. It is the coefficient of two
/// conductances in series, and never more than twice the smaller one, so a
/// trace beside a full cell diffuses at most twice as fast as in bulk.
#[inline]
pub fn face_coefficient(a: f64, b: f64) -> f64 {
    let s = a + b;
    if s > 0.0 {
        2.0 * a * b / s
    } else {
        0.0
    }
}

/// Row `a` of the Newtonian deviatoric stress (seed 000 eq 2, §2 after
/// eq 7), τ = μ(∇u + ∇uᵀ) − (2/3)μ(∇·u)I, from the velocity gradient
/// `grad[i][j]` = ∂u_j/∂x_i: τ_ab = μ(∂u_b/∂x_a + ∂u_a/∂x_b) − (2/3)μ δ_ab ∇·u.
/// On a face normal to `a` this is the traction the face carries.
#[inline]
pub fn stress_row(mu: f64, a: usize, grad: &[[f64; 3]; 3]) -> [f64; 3] {
    let div = grad[0][0] + grad[1][1] + grad[2][2];
    std::array::from_fn(|b| {
        let shear = mu * (grad[a][b] + grad[b][a]);
        if b == a {
            shear - 2.0 / 3.0 * mu * div
        } else {
            shear
        }
    })
}

/// Applies one set of viscous and conductive increments to a material's
/// Lagrangian state in a cell: momentum per unit volume ρu changes by
/// `dmom`, total energy per unit volume ρ(e + ½|u|²) by `denergy`, and
/// what the kinetic energy does not take goes to the internal energy, so
/// that the viscous dissipation (θτ : ∇u of eq 3, to first order in Δt)
/// stays in the material as heat and the total energy is conserved.
/// ρ is unchanged.
#[inline]
pub fn apply_increment(rho: f64, u: &mut [f64; 3], e: &mut f64, dmom: [f64; 3], denergy: f64) {
    let mut kinetic = 0.0;
    for b in 0..3 {
        let old = u[b];
        u[b] = old + dmom[b] / rho;
        // ½ρ(u_new² − u_old²) = ½ Δ(ρu) (u_new + u_old).
        kinetic += 0.5 * dmom[b] * (u[b] + old);
    }
    *e += (denergy - kinetic) / rho;
}

/// Σ_d 1/Δx_d² over the active axes.
#[inline]
pub fn inverse_spacing_squared(spacing: [f64; 3], active: [bool; 3]) -> f64 {
    (0..3)
        .filter(|&d| active[d])
        .map(|d| 1.0 / (spacing[d] * spacing[d]))
        .sum()
}

/// The largest explicit step of the viscous operator for a material of
/// kinematic viscosity ν = μ v (v its specific volume):
/// Δt ≤ 3/(8 ν Σ_d 1/Δx_d²). The discrete operator's largest eigenvalue
/// (the normal stress with its 4/3 and the cross terms, Fourier analysis
/// in docs/physics/ice/diffusion.md) is (4/3)·4ν Σ 1/Δx², and forward Euler
/// is stable while Δt times it is ≤ 2. Infinite when ν = 0.
#[inline]
pub fn viscous_time_step(mu: f64, v: f64, inv_dx2: f64) -> f64 {
    let rate = 8.0 / 3.0 * mu * v * inv_dx2;
    if rate > 0.0 {
        1.0 / rate
    } else {
        f64::INFINITY
    }
}

/// The largest explicit step of heat conduction for a material of
/// diffusivity α = k v / c_v: Δt ≤ 1/(2 α Σ_d 1/Δx_d²) (the three-point
/// Laplacian's eigenvalues reach 4α/Δx² per axis). Infinite when α = 0.
#[inline]
pub fn conduction_time_step(k: f64, v: f64, cv: f64, inv_dx2: f64) -> f64 {
    let rate = 2.0 * k * v / cv * inv_dx2;
    if rate > 0.0 {
        1.0 / rate
    } else {
        f64::INFINITY
    }
}

/// Which limit set the time step.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum TimeStepLimit {
    /// The convective (sound-speed CFL) limit.
    Convective,
    /// The viscous stability limit.
    Viscous,
    /// The heat-conduction stability limit.
    Conduction,
}

/// The time steps of an ICE run, s: the stable one (the smallest of the
/// convective, viscous and conduction limits) and the two diffusive limits
/// (each already multiplied by the Courant number; infinite when no
/// material has that coefficient).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TimeStepLimits {
    /// The stable step, `Solver::stable_dt`.
    pub stable: f64,
    /// cfl · min over cells and materials of [`viscous_time_step`].
    pub viscous: f64,
    /// cfl · min over cells and materials of [`conduction_time_step`].
    pub conduction: f64,
}

impl TimeStepLimits {
    /// The limit that sets the stable step (a diffusive one on a tie).
    pub fn binding(&self) -> TimeStepLimit {
        if self.viscous <= self.stable {
            TimeStepLimit::Viscous
        } else if self.conduction <= self.stable {
            TimeStepLimit::Conduction
        } else {
            TimeStepLimit::Convective
        }
    }
}

/// One run of a decaying-wave case ([`shear_wave`], [`temperature_wave`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WaveRun {
    /// Cells along x.
    pub cells: usize,
    /// Measured decay rate over the exact one, minus 1.
    pub rate_error: f64,
    /// Steps taken.
    pub steps: u64,
    /// The first step's Δt, s.
    pub dt: f64,
    /// The limit that set it.
    pub binding: TimeStepLimit,
    /// Relative change of the total energy over the run.
    pub energy_change: f64,
}

/// Amplitude of the sin(2πx) part of cell values `f` on [0, 1].
pub fn sine_amplitude(f: &[f64]) -> f64 {
    let n = f.len();
    let mean = f.iter().sum::<f64>() / n as f64;
    let k = 2.0 * std::f64::consts::PI;
    2.0 / n as f64
        * f.iter()
            .enumerate()
            .map(|(i, v)| (v - mean) * (k * (i as f64 + 0.5) / n as f64).sin())
            .sum::<f64>()
}

/// Wave number of the cases, k = 2π on [0, 1].
pub const WAVE_NUMBER: f64 = 2.0 * std::f64::consts::PI;
/// End time of the cases.
pub const WAVE_END: f64 = 0.1;

fn periodic_tube<E: Eos>(
    eos: E,
    cells: usize,
    state: impl Fn([f64; 3]) -> CellState + Sync,
    transport: MaterialTransport,
) -> Result<IceSolver<E>, IceError> {
    let level = Level::new([0.0; 3], [1.0, 0.1, 0.1], [cells, 1, 1], [1, 1, 1], GHOST)
        .map_err(|e| IceError::Invalid(e.to_string()))?;
    let mut s = IceSolver::new(
        vec![eos],
        level,
        std::array::from_fn(|_| IceBoundary::Periodic),
        ExchangeCoefficients::uniform(1, 0.0, 0.0),
        IceOptions::default(),
        state,
    )?;
    s.set_transport(vec![transport])?;
    Ok(s)
}

fn run_wave<E: Eos>(
    mut s: IceSolver<E>,
    cells: usize,
    exact_rate: f64,
    amplitude: f64,
    field: &str,
) -> Result<WaveRun, SolverError> {
    let limits = s.time_step_limits()?;
    let e0 = s.conservation_totals().energy;
    crate::cases::run_to(&mut s, WAVE_END)?;
    let e1 = s.conservation_totals().energy;
    let data = s.cell_data(&[field.to_string()])?;
    let f = data.field(field).expect("the field asked for");
    let rate = -(sine_amplitude(f) / amplitude).ln() / WAVE_END;
    Ok(WaveRun {
        cells,
        rate_error: rate / exact_rate - 1.0,
        steps: s.steps(),
        dt: limits.stable,
        binding: limits.binding(),
        energy_change: (e1 - e0) / e0,
    })
}

/// The decaying shear wave u_y = U sin(kx) e^{−νk²t} (k = 2π) in a periodic
/// tube of a γ = 1.4 gas (ρ = 1, p = 1, c_v = 1), μ = 0.05 (ν = 0.05),
/// U = 10⁻³ (the viscous heating is negligible), to t = 0.1 at the
/// solver's own Δt (cfl 0.4).
pub fn shear_wave(cells: usize) -> Result<WaveRun, SolverError> {
    let (mu, u0) = (0.05, 1e-3);
    let k = WAVE_NUMBER;
    let s = periodic_tube(
        IdealGas::new(1.4, 1.0, 1.0),
        cells,
        |x| CellState::single(1.0, 1.0, [0.0, u0 * (k * x[0]).sin(), 0.0]),
        MaterialTransport {
            viscosity: mu,
            thermal_conductivity: 0.0,
        },
    )
    .map_err(|e| SolverError::Other(e.to_string()))?;
    run_wave(s, cells, mu * k * k, u0, "velocity_y")
}

/// The Murnaghan solid of the temperature wave: ρ₀ = 1, κ = 1 (c₀ = 1),
/// n = 7, c_v = 1000, T_ref = 1 K. Its pressure depends on ρ alone (no
/// thermal expansion), so heat conducts at constant volume and
/// ρ c_v ∂T/∂t = k ∇²T holds exactly.
pub fn wave_solid() -> Murnaghan {
    Murnaghan {
        n: 7.0,
        kappa: 1.0,
        rho0: 1.0,
        cv: 1000.0,
        t_ref: 1.0,
    }
}

/// The decaying temperature wave T = T₀ + ΔT sin(kx) e^{−αk²t}
/// (α = k/(ρ c_v) = 0.05, T₀ = 300 K, ΔT = 10 K) in a periodic tube of
/// [`wave_solid`] at ρ = 1.01, to t = 0.1 at the solver's own Δt (cfl 0.4).
pub fn temperature_wave(cells: usize) -> Result<WaveRun, SolverError> {
    let m = wave_solid();
    let rho = 1.01;
    let (alpha, t0, dtemp) = (0.05, 300.0, 10.0);
    let k = WAVE_NUMBER;
    let mut s = periodic_tube(
        m,
        cells,
        |_| CellState::single(m.pressure(rho, 0.0), rho, [0.0; 3]),
        MaterialTransport {
            viscosity: 0.0,
            thermal_conductivity: alpha * rho * m.cv,
        },
    )
    .map_err(|e| SolverError::Other(e.to_string()))?;
    s.set_temperature(0, |x| t0 + dtemp * (k * x[0]).sin())?;
    run_wave(s, cells, alpha * k * k, dtemp, "temperature")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn validation_names_the_field() {
        let ok = MaterialTransport {
            viscosity: 1.8e-5,
            thermal_conductivity: 0.026,
        };
        assert!(ok.validate("material 1").is_ok());
        assert!(ok.is_active());
        assert!(!MaterialTransport::default().is_active());
        let e = MaterialTransport {
            viscosity: -1.0,
            ..ok
        }
        .validate("material 2")
        .unwrap_err()
        .to_string();
        assert!(e.contains("`viscosity`") && e.contains("material 2"), "{e}");
        for bad in [f64::NAN, f64::INFINITY, -1e-9] {
            let e = MaterialTransport {
                thermal_conductivity: bad,
                ..ok
            }
            .validate("material 1")
            .unwrap_err()
            .to_string();
            assert!(e.contains("`thermal_conductivity`"), "{e}");
        }
    }

    #[test]
    fn face_coefficient_is_the_harmonic_mean() {
        assert_eq!(face_coefficient(2.0, 2.0), 2.0);
        // 2·1·3/4 = 1.5
        assert_eq!(face_coefficient(1.0, 3.0), 1.5);
        assert_eq!(face_coefficient(0.0, 0.0), 0.0);
        assert_eq!(face_coefficient(0.0, 5.0), 0.0);
        // A trace of 1e-6 beside 1: 2e-6/(1 + 1e-6), below twice the trace.
        let f = face_coefficient(1e-6, 1.0);
        assert!((f - 2e-6 / (1.0 + 1e-6)).abs() < 1e-21 && f < 2e-6);
    }

    #[test]
    fn stress_row_is_newtonian() {
        // ∂u_j/∂x_i: ∇·u = 1 + 4 + (−2) = 3.
        let g = [[1.0, 2.0, 3.0], [5.0, 4.0, 0.5], [-1.0, 7.0, -2.0]];
        let mu = 0.5;
        // Row x: τ_xx = 2·0.5·1 − (2/3)·0.5·3 = 0; τ_xy = 0.5(2 + 5) = 3.5;
        // τ_xz = 0.5(3 − 1) = 1.
        let t = stress_row(mu, 0, &g);
        assert!(t[0].abs() < 1e-15 && t[1] == 3.5 && t[2] == 1.0, "{t:?}");
        // Row y: τ_yx = 3.5 (symmetric); τ_yy = 4 − 1 = 3; τ_yz = 0.5(0.5 + 7).
        let t = stress_row(mu, 1, &g);
        assert!(
            t[0] == 3.5 && (t[1] - 3.0).abs() < 1e-15 && t[2] == 3.75,
            "{t:?}"
        );
        // Row z: τ_zz = −2 − 1 = −3.
        let t = stress_row(mu, 2, &g);
        assert!((t[2] + 3.0).abs() < 1e-15 && t[0] == 1.0 && t[1] == 3.75);
        // Trace-free: τ_xx + τ_yy + τ_zz = 0.
        let tr = stress_row(mu, 0, &g)[0] + stress_row(mu, 1, &g)[1] + stress_row(mu, 2, &g)[2];
        assert!(tr.abs() < 1e-14);
        // A rigid rotation carries no stress.
        let rot = [[0.0, 1.0, 0.0], [-1.0, 0.0, 0.0], [0.0, 0.0, 0.0]];
        assert_eq!(stress_row(3.0, 0, &rot), [0.0; 3]);
    }

    #[test]
    fn an_increment_moves_momentum_and_total_energy_exactly() {
        let rho = 2.0;
        let mut u = [1.0, -3.0, 0.5];
        let mut e = 100.0;
        let total =
            |u: &[f64; 3], e: f64| rho * (e + 0.5 * (u[0] * u[0] + u[1] * u[1] + u[2] * u[2]));
        let before = total(&u, e);
        apply_increment(rho, &mut u, &mut e, [0.2, 0.4, -1.0], 0.75);
        // u = u + Δ(ρu)/ρ = (1.1, −2.8, 0.0)
        assert!((u[0] - 1.1).abs() < 1e-15 && (u[1] + 2.8).abs() < 1e-15 && u[2] == 0.0);
        assert!((total(&u, e) - before - 0.75).abs() < 1e-13);
        // KE before 2·½(1 + 9 + 0.25) = 10.25, after 2·½(1.21 + 7.84) = 9.05:
        // ρe grows by 0.75 + 1.2.
        assert!((rho * e - 200.0 - 1.95).abs() < 1e-12, "{e}");
    }

    #[test]
    fn limits_are_the_hand_values() {
        let s = inverse_spacing_squared([0.1, 0.2, 1.0], [true, true, false]);
        assert!((s - 125.0).abs() < 1e-12);
        // ν = 0.5·2 = 1: 3/(8·125)
        assert!((viscous_time_step(0.5, 2.0, s) - 3.0 / 1000.0).abs() < 1e-18);
        // α = 0.3·2/1.5 = 0.4: 1/(2·0.4·125) = 0.01
        assert!((conduction_time_step(0.3, 2.0, 1.5, s) - 0.01).abs() < 1e-17);
        assert_eq!(viscous_time_step(0.0, 2.0, s), f64::INFINITY);
        assert_eq!(conduction_time_step(0.0, 2.0, 1.0, s), f64::INFINITY);
        let l = TimeStepLimits {
            stable: 0.5,
            viscous: 0.5,
            conduction: 0.7,
        };
        assert_eq!(l.binding(), TimeStepLimit::Viscous);
        let l = TimeStepLimits {
            stable: 0.2,
            viscous: 0.5,
            conduction: 0.2,
        };
        assert_eq!(l.binding(), TimeStepLimit::Conduction);
        let l = TimeStepLimits { stable: 0.1, ..l };
        assert_eq!(l.binding(), TimeStepLimit::Convective);
    }
}
