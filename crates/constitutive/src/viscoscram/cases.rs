//! Verification problems of [`ViscoScram`] that the unit tests and the
//! validation report (V-VISCOSCRAM) share: a single material point under
//! an isochoric uniaxial strain rate ė diag(1, −½, −½), no spin, so every
//! element's deviatoric stress stays a multiple a_n of D = diag(1, −½, −½)
//! and the model reduces to scalar equations that can be solved on their
//! own.

use super::{read_voigt, ViscoScram, CRACK_RADIUS_INDEX, ELEMENTS};
use crate::ObjectiveRate;
use brisance_core::{Mat3, Material, StressUpdateInput};

/// Density of the material point, kg/m³ (PBX-9501; it enters only the
/// pressure model, which an isochoric path leaves at zero).
const DENSITY: f64 = 1840.0;

/// The velocity gradient ė diag(1, −½, −½).
fn uniaxial(rate: f64) -> Mat3 {
    Mat3::new(rate, 0.0, 0.0, 0.0, -0.5 * rate, 0.0, 0.0, 0.0, -0.5 * rate)
}

/// Steps a fresh material point through `phases` of (strain rate, 1/s;
/// duration, s) with steps of `dt`, calling `sample(t, state)` after every
/// step with the crack radius and the xx deviatoric stress of each element
/// (a_n: S_n = a_n D), and returns the heat of every step (J/m³).
fn drive(
    m: &ViscoScram,
    phases: &[(f64, f64)],
    dt: f64,
    mut sample: impl FnMut(f64, f64, &[f64; ELEMENTS], f64),
) {
    let mut h = vec![0.0; m.history_len()];
    m.init_history(&mut h);
    let mut stress = Mat3::zeros();
    let mut t = 0.0;
    for &(rate, duration) in phases {
        let steps = (duration / dt).round() as usize;
        for _ in 0..steps {
            let r = m.update_stress(
                &StressUpdateInput {
                    velocity_gradient: uniaxial(rate),
                    dt,
                    density: DENSITY,
                    temperature: 300.0,
                    specific_internal_energy: 0.0,
                    stress,
                },
                &mut h,
            );
            stress = r.stress;
            t += dt;
            let a: [f64; ELEMENTS] =
                std::array::from_fn(|k| read_voigt(&h[1 + 6 * k..7 + 6 * k])[(0, 0)]);
            sample(t, h[CRACK_RADIUS_INDEX], &a, r.plastic_work);
        }
    }
}

/// PBX-9501 (Uintah's set, [`ViscoScram::pbx_9501`]) with the cracks
/// frozen and negligible: v_max = 0 and c₀ = 1 nm, (c₀/a)³ = 1e-18, so the
/// five Maxwell elements answer on their own.
pub fn pbx_9501_without_cracks() -> ViscoScram {
    let mut m = ViscoScram::pbx_9501(ObjectiveRate::Jaumann);
    m.max_crack_speed = 0.0;
    m.initial_crack_radius = 1.0e-9;
    m
}

/// What [`maxwell_ramp_and_hold`] measured.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MaxwellCheck {
    /// Step, s.
    pub dt: f64,
    /// Largest |S_xx − S_xx(exact)| over the run, over the largest
    /// |S_xx(exact)|.
    pub max_error: f64,
    /// The peak S_xx(exact), Pa.
    pub peak: f64,
}

/// The generalized Maxwell solid (no cracks) under ė = 1000/s for 10 µs,
/// then held (ė = 0) for 20 µs, against its exact response: each element
/// s_n = 2 G_n ė τ_n (1 − e^{−t/τ_n}) D while loading and that value times
/// e^{−(t − t₁)/τ_n} while held (2 G_n ė t and constant for the spring
/// without dashpot).
pub fn maxwell_ramp_and_hold(dt: f64) -> MaxwellCheck {
    let m = pbx_9501_without_cracks();
    let (rate, t1, t2) = (1000.0, 10.0e-6, 20.0e-6);
    let exact = |t: f64| -> f64 {
        (0..ELEMENTS)
            .map(|k| {
                let (g, r) = (m.shear_moduli[k], m.inverse_relaxation_times[k]);
                if r == 0.0 {
                    return 2.0 * g * rate * t.min(t1);
                }
                let loaded = 2.0 * g * rate * (1.0 - (-r * t.min(t1)).exp()) / r;
                loaded * (-r * (t - t1).max(0.0)).exp()
            })
            .sum()
    };
    let (mut worst, mut peak) = (0.0_f64, 0.0_f64);
    drive(&m, &[(rate, t1), (0.0, t2)], dt, |t, _, a, _| {
        let s: f64 = a.iter().sum();
        let e = exact(t);
        worst = worst.max((s - e).abs());
        peak = peak.max(e.abs());
    });
    MaxwellCheck {
        dt,
        max_error: worst / peak,
        peak,
    }
}

/// The scalar state of the uniaxial path: crack radius c and the element
/// amplitudes a_n (S_n = a_n D).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ScalarState {
    /// Crack radius, m.
    pub c: f64,
    /// Element amplitudes, Pa.
    pub a: [f64; ELEMENTS],
    /// Heat dissipated so far, J/m³.
    pub heat: f64,
    /// Deviatoric work done so far, ∫ S:ė dt, J/m³.
    pub work: f64,
}

/// The model's equations on the uniaxial path, written out on their own
/// for the scalars (Bennett et al. 1998 with D:D = 3/2, mean stress 0):
/// ċ from the stress intensity K_I = σ_eff √(πc), σ_eff = (3/2)|a|,
/// a = Σ a_n, against K₀ (no friction without compression);
/// ȧ = [2G ė − Σ a_m/τ_m − θ a]/(1 + (c/a_c)³), θ = 3 (c/a_c)³ ċ/c;
/// ȧ_n = 2G_n ė − a_n/τ_n − (G_n/G)[θ a + (c/a_c)³ ȧ]; heat rate
/// (3/2)[Σ a_n²/(2G_n τ_n) + θ a²/(4G)] and work rate (3/2) a ė.
fn scalar_rates(m: &ViscoScram, y: &ScalarState, rate: f64) -> ScalarState {
    let g: f64 = m.shear_moduli.iter().sum();
    let a: f64 = y.a.iter().sum();
    let k_i = 1.5 * a.abs() * (std::f64::consts::PI * y.c).sqrt();
    let (k0, n) = (m.fracture_toughness, m.crack_power);
    let k_prime = k0 * (1.0 + 2.0 / n).sqrt();
    let cdot = if k_i < k_prime {
        m.max_crack_speed * (k_i / (k_prime * (1.0 + 0.5 * n).powf(1.0 / n))).powf(n)
    } else {
        m.max_crack_speed * (1.0 - (k0 / k_i).powi(2))
    };
    let ca3 = (y.c / m.crack_size).powi(3);
    let theta = 3.0 * ca3 * cdot / y.c;
    let relax: f64 = (0..ELEMENTS)
        .map(|k| y.a[k] * m.inverse_relaxation_times[k])
        .sum();
    let adot = (2.0 * g * rate - relax - theta * a) / (1.0 + ca3);
    let viscous: f64 = (0..ELEMENTS)
        .map(|k| y.a[k] * y.a[k] * m.inverse_relaxation_times[k] / (2.0 * m.shear_moduli[k]))
        .sum();
    ScalarState {
        c: cdot,
        a: std::array::from_fn(|k| {
            let gk = m.shear_moduli[k];
            2.0 * gk * rate
                - y.a[k] * m.inverse_relaxation_times[k]
                - (gk / g) * (theta * a + ca3 * adot)
        }),
        heat: 1.5 * (viscous + theta * a * a / (4.0 * g)),
        work: 1.5 * a * rate,
    }
}

/// `y + f·k`.
fn axpy(y: &ScalarState, f: f64, k: &ScalarState) -> ScalarState {
    ScalarState {
        c: y.c + f * k.c,
        a: std::array::from_fn(|n| y.a[n] + f * k.a[n]),
        heat: y.heat + f * k.heat,
        work: y.work + f * k.work,
    }
}

/// The scalar equations of `scalar_rates` integrated over `phases`
/// with `per_step` classical RK4 substeps per step `dt`; the state after
/// every step.
pub fn scalar_reference(
    m: &ViscoScram,
    phases: &[(f64, f64)],
    dt: f64,
    per_step: usize,
) -> Vec<ScalarState> {
    let mut y = ScalarState {
        c: m.initial_crack_radius,
        a: [0.0; ELEMENTS],
        heat: 0.0,
        work: 0.0,
    };
    let h = dt / per_step as f64;
    let mut out = Vec::new();
    for &(rate, duration) in phases {
        for _ in 0..(duration / dt).round() as usize {
            for _ in 0..per_step {
                let k1 = scalar_rates(m, &y, rate);
                let k2 = scalar_rates(m, &axpy(&y, 0.5 * h, &k1), rate);
                let k3 = scalar_rates(m, &axpy(&y, 0.5 * h, &k2), rate);
                let k4 = scalar_rates(m, &axpy(&y, h, &k3), rate);
                let sum = axpy(&axpy(&axpy(&k1, 2.0, &k2), 2.0, &k3), 1.0, &k4);
                y = axpy(&y, h / 6.0, &sum);
            }
            out.push(y);
        }
    }
    out
}

/// The load–unload path of [`crack_path`]: ė = 2000/s for 10 µs (the
/// von Mises stress passes K' of c₀ at about 2 µs and the cracks run),
/// then ė = −2000/s for 10 µs.
pub const CRACK_PATH: [(f64, f64); 2] = [(2000.0, 10.0e-6), (-2000.0, 10.0e-6)];

/// What [`crack_path`] measured.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CrackCheck {
    /// Step, s.
    pub dt: f64,
    /// Largest |c − c_ref| over the run, over c_ref's growth c_end − c₀.
    pub crack_error: f64,
    /// Largest |S_xx − S_xx,ref| over the run, over the largest |S_xx,ref|.
    pub stress_error: f64,
    /// Final crack radius over c₀.
    pub growth: f64,
    /// Crack growth while unloading, over the growth of the whole path
    /// (the cracks keep growing while K_I is high, never heal).
    pub unloading_growth: f64,
    /// |work − stored − heat| at the end over the work done while loading
    /// (the stress power by Simpson's rule over pairs of steps).
    pub energy_error: f64,
    /// The heat at the end over the loading work.
    pub heat_share: f64,
    /// No step decreased c, and no step's heat was negative.
    pub monotone: bool,
}

/// PBX-9501 (cracks on) along [`CRACK_PATH`] with steps `dt`, against
/// [`scalar_reference`] at `reference_substeps` RK4 substeps per step;
/// the crack radius, the stress, the crack growth while unloading and the
/// energy balance (work = stored energy + heat).
pub fn crack_path(dt: f64, reference_substeps: usize) -> CrackCheck {
    crack_path_on(&CRACK_PATH, dt, reference_substeps)
}

/// [`crack_path`] on another path.
pub fn crack_path_on(path: &[(f64, f64); 2], dt: f64, reference_substeps: usize) -> CrackCheck {
    let m = ViscoScram::pbx_9501(ObjectiveRate::Jaumann);
    let reference = scalar_reference(&m, path, dt, reference_substeps);
    let g: f64 = m.shear_moduli.iter().sum();
    let c0 = m.initial_crack_radius;
    let growth_ref = reference.last().map_or(0.0, |y| y.c) - c0;
    let peak_ref = reference
        .iter()
        .map(|y| y.a.iter().sum::<f64>().abs())
        .fold(0.0, f64::max);
    let loading_steps = (path[0].1 / dt).round() as usize;
    let (mut crack_err, mut stress_err) = (0.0_f64, 0.0_f64);
    let mut monotone = true;
    let mut c_prev = c0;
    let (mut heat, mut c_loaded) = (0.0, c0);
    // S_xx amplitude after every step, with 0 at the start, for the work.
    let mut amplitude = vec![0.0];
    let mut rates = Vec::new();
    let mut step = 0;
    let mut last = (c0, [0.0; ELEMENTS]);
    drive(&m, path, dt, |_, c, a, q| {
        let y = &reference[step];
        crack_err = crack_err.max((c - y.c).abs());
        stress_err = stress_err.max((a.iter().sum::<f64>() - y.a.iter().sum::<f64>()).abs());
        monotone &= c >= c_prev && q >= 0.0;
        c_prev = c;
        heat += q;
        amplitude.push(a.iter().sum());
        rates.push(if step < loading_steps {
            path[0].0
        } else {
            path[1].0
        });
        step += 1;
        if step == loading_steps {
            c_loaded = c;
        }
        last = (c, *a);
    });
    // ∫ S:ė dt = (3/2) ∫ a ė dt, Simpson over pairs of steps within each
    // phase (ė constant there).
    let simpson = |from: usize, to: usize, rate: f64| -> f64 {
        (from..to)
            .step_by(2)
            .map(|i| {
                1.5 * rate * dt / 3.0 * (amplitude[i] + 4.0 * amplitude[i + 1] + amplitude[i + 2])
            })
            .sum()
    };
    let total_steps = amplitude.len() - 1;
    let loading_work = simpson(0, loading_steps, rates[0]);
    let work = loading_work + simpson(loading_steps, total_steps, rates[total_steps - 1]);
    let (c, a) = last;
    let total: f64 = a.iter().sum();
    let ca3 = (c / m.crack_size).powi(3);
    let stored = 1.5
        * ((0..ELEMENTS)
            .map(|k| a[k] * a[k] / (4.0 * m.shear_moduli[k]))
            .sum::<f64>()
            + ca3 * total * total / (4.0 * g));
    CrackCheck {
        dt,
        crack_error: crack_err / growth_ref,
        stress_error: stress_err / peak_ref,
        growth: c / c0,
        unloading_growth: (c - c_loaded) / (c - c0),
        energy_error: (work - stored - heat).abs() / loading_work,
        heat_share: heat / loading_work,
        monotone,
    }
}
