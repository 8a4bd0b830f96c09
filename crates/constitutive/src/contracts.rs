//! Property checks of the [`Material`] contract, run for every model by
//! proptest. A model joins with one line in a test module:
//!
//! ```text
//! brisance_constitutive::material_contract_tests!(copper, ElasticPlastic::ofhc_copper_seed000());
//! ```
//!
//! The checks are plain functions over a [`MaterialModel`] so a failing
//! case can be replayed by hand; the macro needs `proptest` as a
//! dev-dependency of the invoking crate.
//!
//! A point is driven through a loading path: a list of velocity gradients
//! L_k applied with step Δt at fixed density ρ (the EOS reference density, or
//! 8000 kg/m³), specific internal energy e = 0 and temperature T.

use crate::MaterialModel;
use brisance_core::{Mat3, Material, StressUpdateInput};

/// Relative tolerance of the objectivity checks: the rotated and unrotated
/// paths differ only by the round-off of ~10 matrix products per step and of
/// the radial-return iteration (converged to 1e-13 of σ_y).
pub const OBJECTIVITY_TOLERANCE: f64 = 1e-9;

/// Relative tolerance of the yield-surface check (σ̄ ≤ σ_y (1 + tol)).
pub const YIELD_TOLERANCE: f64 = 1e-10;

/// Density used for the loading paths, kg/m³.
pub fn path_density(model: &MaterialModel) -> f64 {
    model.eos().map_or(8000.0, |eos| eos.reference_density())
}

/// A point's state: stress and history.
#[derive(Debug, Clone, PartialEq)]
pub struct PointState {
    /// Cauchy stress, Pa.
    pub stress: Mat3,
    /// History values.
    pub history: Vec<f64>,
}

impl PointState {
    /// The initial state of `model`: zero stress, initial history.
    pub fn initial(model: &MaterialModel) -> Self {
        let mut history = vec![0.0; model.history_len()];
        model.init_history(&mut history);
        Self {
            stress: Mat3::zeros(),
            history,
        }
    }

    /// The initial state of the point `seed` of `model`: zero stress, the
    /// history of [`Material::init_history_at`].
    pub fn initial_at(model: &MaterialModel, seed: u64) -> Self {
        let mut history = vec![0.0; model.history_len()];
        model.init_history_at(&mut history, seed);
        Self {
            stress: Mat3::zeros(),
            history,
        }
    }
}

/// Result of one step as the checks see it.
#[derive(Debug, Clone, Copy)]
pub struct StepResult {
    /// Plastic work of the step, J/m³.
    pub plastic_work: f64,
    /// Failed flag returned.
    pub failed: bool,
}

/// Advances `state` by one step of velocity gradient `l`.
pub fn step(
    model: &MaterialModel,
    state: &mut PointState,
    l: &Mat3,
    dt: f64,
    t: f64,
) -> StepResult {
    let input = StressUpdateInput {
        velocity_gradient: *l,
        dt,
        density: path_density(model),
        temperature: t,
        specific_internal_energy: 0.0,
        stress: state.stress,
    };
    let out = model.update_stress(&input, &mut state.history);
    state.stress = out.stress;
    StepResult {
        plastic_work: out.plastic_work,
        failed: out.failed,
    }
}

/// Rotation matrix of the rotation vector `axis_angle` (Rodrigues).
pub fn rotation(axis_angle: [f64; 3]) -> Mat3 {
    let v = brisance_core::Vec3::from(axis_angle);
    nalgebra::Rotation3::from_scaled_axis(v).into_inner()
}

/// Skew tensor of the angular velocity ω, W x = ω × x, 1/s.
pub fn spin_tensor(omega: [f64; 3]) -> Mat3 {
    let [a, b, c] = omega;
    Mat3::new(0.0, -c, b, c, 0.0, -a, -b, a, 0.0)
}

fn rel(a: &Mat3, b: &Mat3, floor: f64) -> f64 {
    (a - b).norm() / a.norm().max(b.norm()).max(floor)
}

fn deviatoric_norm(s: &Mat3) -> f64 {
    crate::hypoelastic::von_mises(&crate::hypoelastic::deviator(s))
}

/// Objectivity (frame indifference): driving the point along Q L_k Qᵀ for
/// a fixed rotation Q gives Q σ Qᵀ, the same scalar history and the same
/// failed flags as driving it along L_k — for Jaumann and Green–Naghdi
/// alike, from the initial state through the whole path. The plastic work
/// agrees to [`OBJECTIVITY_TOLERANCE`] of the step's stress power ‖σ‖‖L‖Δt.
pub fn check_frame_indifference(
    model: &MaterialModel,
    path: &[Mat3],
    q: &Mat3,
    dt: f64,
    t: f64,
) -> Result<(), String> {
    let mut a = PointState::initial(model);
    let mut b = PointState::initial(model);
    for (k, l) in path.iter().enumerate() {
        let ra = step(model, &mut a, l, dt, t);
        let rb = step(model, &mut b, &(q * l * q.transpose()), dt, t);
        let expected = q * a.stress * q.transpose();
        let err = rel(&b.stress, &expected, 1.0);
        if !(err <= OBJECTIVITY_TOLERANCE) {
            return Err(format!(
                "step {k}: rotated path gives {} but Q σ Qᵀ = {expected} (relative error {err:e})",
                b.stress
            ));
        }
        if ra.failed != rb.failed {
            return Err(format!(
                "step {k}: failed flag {} vs {}",
                ra.failed, rb.failed
            ));
        }
        // Plastic work is compared on the scale of the step's stress power
        // ‖σ‖‖L‖Δt: a trial state on the yield surface to round-off may
        // yield by a hair on one path and not the other.
        let scale = ra
            .plastic_work
            .abs()
            .max(a.stress.norm() * l.norm() * dt)
            .max(1.0);
        if (ra.plastic_work - rb.plastic_work).abs() > OBJECTIVITY_TOLERANCE * scale {
            return Err(format!(
                "step {k}: plastic work {} vs {}",
                ra.plastic_work, rb.plastic_work
            ));
        }
    }
    Ok(())
}

/// A superposed rigid spin rotates the stress: from an elastic state (the
/// path scaled down until the point stays elastic), `steps` steps of the
/// pure spin W give Q σ Qᵀ with Q the product of the Hughes–Winget
/// rotations, do not change the stress invariants (to 1e-12 of their
/// scale), do no plastic work and change no scalar history.
pub fn check_rigid_spin_rotates_stress(
    model: &MaterialModel,
    elastic_path: &[Mat3],
    omega: [f64; 3],
    steps: usize,
    dt: f64,
    t: f64,
) -> Result<(), String> {
    // Skipped for a viscous fluid: its stress −p I + 2μ dev D is set by the
    // current rate, so a spin (D = 0) removes the viscous part instead of
    // rotating it. Its objectivity is checked by the rotated-path check.
    if model.is_viscous() {
        return Ok(());
    }
    let mut s = PointState::initial(model);
    for l in elastic_path {
        let r = step(model, &mut s, l, dt, t);
        // A relaxing model dissipates in its dashpots on any path.
        if (r.plastic_work != 0.0 && !model.relaxes()) || r.failed {
            return Err(format!(
                "the elastic path yielded (plastic work {})",
                r.plastic_work
            ));
        }
    }
    let mut sigma0 = s.stress;
    let mut history0 = s.history.clone();
    // A relaxing model: its twin left at rest over the same steps is what
    // the spin must rotate (stress, dissipation and scalar history alike).
    let mut twin = model.relaxes().then(|| s.clone());
    let w = spin_tensor(omega);
    let q_step = crate::objective::hughes_winget_rotation(&w, dt);
    let mut q = Mat3::identity();
    for _ in 0..steps {
        let r = step(model, &mut s, &w, dt, t);
        q = q_step * q;
        let rest = match twin.as_mut() {
            Some(twin) => step(model, twin, &Mat3::zeros(), dt, t).plastic_work,
            None => 0.0,
        };
        // On the scale of the step's stress power ‖σ‖‖W‖Δt, as in the
        // rotated-path check: the dissipation of a nonlinear law (the
        // crack growth's tenth power) magnifies the round-off between the
        // two runs.
        let scale = rest.abs().max(s.stress.norm() * w.norm() * dt);
        if (r.plastic_work - rest).abs() > OBJECTIVITY_TOLERANCE * scale || r.failed {
            return Err(format!(
                "a rigid spin did plastic work {} (at rest: {rest})",
                r.plastic_work
            ));
        }
    }
    if let Some(twin) = twin {
        sigma0 = twin.stress;
        history0 = twin.history;
    }
    // Against a twin the two runs round differently through a nonlinear
    // law (the crack growth) over many substeps: they agree to the
    // tolerance of the rotated-path check, not to 1e-12.
    let tol = if model.relaxes() {
        OBJECTIVITY_TOLERANCE
    } else {
        1e-12
    };
    let scale = sigma0.norm().max(1.0);
    let expected = q * sigma0 * q.transpose();
    let err = (s.stress - expected).norm() / scale;
    if !(err <= tol) {
        return Err(format!(
            "after {steps} spin steps σ = {} but Q σ₀ Qᵀ = {expected} (relative {err:e})",
            s.stress
        ));
    }
    let inv = |m: &Mat3| {
        [
            m.trace(),
            0.5 * (m.trace().powi(2) - (m * m).trace()),
            m.determinant(),
        ]
    };
    let (i0, i1) = (inv(&sigma0), inv(&s.stress));
    for (k, (a, b)) in i0.iter().zip(i1.iter()).enumerate() {
        let tol = tol * scale.powi(k as i32 + 1);
        if !((a - b).abs() <= tol) {
            return Err(format!("invariant I{} changed: {a:e} → {b:e}", k + 1));
        }
    }
    let scalar_len = history0.len().min(model.scalar_state_len());
    let same = s.history[..scalar_len]
        .iter()
        .zip(&history0[..scalar_len])
        .all(|(a, b)| a == b || (model.relaxes() && (a - b).abs() <= tol * b.abs()));
    if !same {
        return Err(format!(
            "a rigid spin changed the history {:?} → {:?}",
            &history0[..scalar_len],
            &s.history[..scalar_len]
        ));
    }
    Ok(())
}

/// Zero strain rate leaves an elastic state unchanged: after an elastic
/// path, a step with L = 0 returns the same stress (to 1e-13 relative).
pub fn check_zero_rate_keeps_stress(
    model: &MaterialModel,
    elastic_path: &[Mat3],
    dt: f64,
    t: f64,
) -> Result<(), String> {
    // Skipped for a viscous fluid: L = 0 removes its viscous stress 2μ dev D
    // by design (it is not an elastic state carried from step to step).
    if model.is_viscous() {
        return Ok(());
    }
    let mut s = PointState::initial(model);
    for l in elastic_path {
        step(model, &mut s, l, dt, t);
    }
    let before = s.stress;
    let r = step(model, &mut s, &Mat3::zeros(), dt, t);
    if model.relaxes() {
        // A viscoelastic state at rest keeps its pressure, stays finite and
        // turns the energy its dashpots let go into heat (≥ 0). Its
        // deviator may grow: elements relaxing at different rates can
        // leave a sum larger than before (one held against another); the
        // stored energy falls instead, which the model's own tests check.
        // The trace is a sum of components that may be far larger than it:
        // its round-off is on the scale of the whole stress.
        let (p0, p1) = (before.trace(), s.stress.trace());
        let finite = s.stress.iter().all(|x| x.is_finite());
        let scale = before.norm().max(1.0);
        if (p1 - p0).abs() > 1e-13 * scale || !finite || !(r.plastic_work >= 0.0) {
            return Err(format!(
                "L = 0 on a relaxing model: σ {before} → {} (heat {})",
                s.stress, r.plastic_work
            ));
        }
        return Ok(());
    }
    let err = rel(&s.stress, &before, 1.0);
    if !(err <= 1e-13) || r.plastic_work != 0.0 {
        return Err(format!(
            "L = 0 changed σ from {before} to {} (relative {err:e}, plastic work {})",
            s.stress, r.plastic_work
        ));
    }
    Ok(())
}

/// Along any path, from the initial state of the point `seed` (or the
/// model's mean initial state for `None`): the initial history is finite
/// and the same bits for the same seed; stress and history stay finite;
/// plastic work ≥ 0; an elastic model never yields or fails; for a model
/// with a yield surface the stress after the return mapping lies inside it
/// at the updated history to [`YIELD_TOLERANCE`] of its scale
/// ([`MaterialModel::yield_excess`]: σ̄ ≤ σ_y (1 + tol) for the J2 metal);
/// once failed the point stays failed and carries no deviatoric and no
/// tensile stress; no damage variable ever decreases; a porosity stays in
/// [0, 1) and never decreases.
pub fn check_loading_path(
    model: &MaterialModel,
    path: &[Mat3],
    dt: f64,
    t: f64,
    seed: Option<u64>,
) -> Result<(), String> {
    let mut s = match seed {
        Some(seed) => {
            let a = PointState::initial_at(model, seed);
            let b = PointState::initial_at(model, seed);
            let bits = |h: &[f64]| h.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
            if bits(&a.history) != bits(&b.history) {
                return Err(format!(
                    "seed {seed}: two initialisations differ: {:?} vs {:?}",
                    a.history, b.history
                ));
            }
            a
        }
        None => PointState::initial(model),
    };
    if !s.history.iter().all(|x| x.is_finite()) {
        return Err(format!("non-finite initial history {:?}", s.history));
    }
    let mut was_failed = false;
    let mut damage = model.damage(&s.history).to_vec();
    let mut porosity = model.porosity(&s.history);
    if let Some(f) = porosity {
        if !(0.0..1.0).contains(&f) {
            return Err(format!("initial porosity {f} outside [0, 1)"));
        }
    }
    for (k, l) in path.iter().enumerate() {
        let r = step(model, &mut s, l, dt, t);
        if !(s.stress.iter().all(|x| x.is_finite()) && s.history.iter().all(|x| x.is_finite())) {
            return Err(format!(
                "step {k}: non-finite state {} {:?}",
                s.stress, s.history
            ));
        }
        if !(r.plastic_work >= 0.0) {
            return Err(format!("step {k}: plastic work {} < 0", r.plastic_work));
        }
        if model.is_elastic() && (r.plastic_work != 0.0 || r.failed) {
            return Err(format!("step {k}: an elastic model yielded or failed"));
        }
        if was_failed && !r.failed {
            return Err(format!("step {k}: a failed point recovered"));
        }
        if r.failed != model.is_failed(&s.history) {
            return Err(format!(
                "step {k}: returned failed = {} but history disagrees",
                r.failed
            ));
        }
        for (old, &new) in damage.iter_mut().zip(model.damage(&s.history)) {
            if new < *old {
                return Err(format!("step {k}: damage fell from {old} to {new}"));
            }
            *old = new;
        }
        let new_porosity = model.porosity(&s.history);
        if let (Some(old), Some(new)) = (porosity, new_porosity) {
            if !(new >= old && new < 1.0) {
                return Err(format!(
                    "step {k}: porosity went from {old} to {new} (must not fall, must stay < 1)"
                ));
            }
        }
        porosity = new_porosity;
        if r.failed {
            // No deviatoric stress means σ = −p I exactly: equal diagonal,
            // zero off-diagonal (computing σ̄ of −p I would add the
            // round-off of tr σ/3 to an exactly isotropic stress).
            let m = &s.stress;
            let isotropic = m[(0, 0)] == m[(1, 1)]
                && m[(1, 1)] == m[(2, 2)]
                && (0..3).all(|i| (0..3).all(|j| i == j || m[(i, j)] == 0.0));
            let trace = m.trace();
            if !isotropic || trace > 0.0 {
                return Err(format!(
                    "step {k}: failed point carries σ̄ = {:e}, tr σ = {trace:e}",
                    deviatoric_norm(m)
                ));
            }
        } else if let Some((excess, scale)) = model.yield_excess(&s.stress, &s.history, t) {
            // Models without a yield surface (hypoelastic solid, null
            // fluid) return None and skip this check.
            if !(excess <= YIELD_TOLERANCE * scale) {
                return Err(format!(
                    "step {k}: σ = {} lies {excess:e} Pa outside the yield surface (scale {scale:e})",
                    s.stress
                ));
            }
        }
        was_failed = r.failed;
    }
    Ok(())
}

/// Generates a proptest module checking the [`Material`] contract for one
/// [`MaterialModel`] (anything `Into<MaterialModel>`).
#[macro_export]
macro_rules! material_contract_tests {
    ($name:ident, $model:expr) => {
        mod $name {
            #[allow(unused_imports)]
            use super::*;
            use $crate::contracts as c;
            use brisance_core::Mat3;
            use proptest::prelude::*;

            fn model() -> $crate::MaterialModel {
                ($model).into()
            }

            fn path(entries: &[[f64; 9]], strain_per_step: f64, dt: f64) -> Vec<Mat3> {
                entries
                    .iter()
                    .map(|e| Mat3::from_row_slice(e) * (strain_per_step / dt))
                    .collect()
            }

            fn gradients(n: usize) -> impl Strategy<Value = Vec<[f64; 9]>> {
                proptest::collection::vec(proptest::array::uniform9(-1.0f64..1.0), n)
            }

            proptest! {
                #![proptest_config(ProptestConfig::with_cases(64))]

                #[test]
                fn rotated_path_gives_rotated_stress(
                    entries in gradients(6),
                    strain in 1e-5f64..2e-2,
                    dt in 1e-8f64..1e-5,
                    axis in proptest::array::uniform3(-3.0f64..3.0),
                    t in 250.0f64..2000.0,
                ) {
                    let m = model();
                    let q = c::rotation(axis);
                    if let Err(msg) = c::check_frame_indifference(&m, &path(&entries, strain, dt), &q, dt, t) {
                        prop_assert!(false, "{}", msg);
                    }
                }

                #[test]
                fn rigid_spin_rotates_stress_and_keeps_invariants(
                    entries in gradients(3),
                    omega in proptest::array::uniform3(-1e5f64..1e5),
                    dt in 1e-8f64..1e-6,
                    steps in 1usize..400,
                ) {
                    let m = model();
                    if let Err(msg) = c::check_rigid_spin_rotates_stress(
                        &m, &path(&entries, 1e-6, dt), omega, steps, dt, 300.0,
                    ) {
                        prop_assert!(false, "{}", msg);
                    }
                }

                #[test]
                fn zero_strain_rate_leaves_elastic_stress_unchanged(
                    entries in gradients(3),
                    dt in 1e-8f64..1e-5,
                ) {
                    let m = model();
                    if let Err(msg) = c::check_zero_rate_keeps_stress(&m, &path(&entries, 1e-6, dt), dt, 300.0) {
                        prop_assert!(false, "{}", msg);
                    }
                }

                #[test]
                fn loading_path_respects_yield_failure_and_finiteness(
                    entries in gradients(40),
                    strain in 1e-4f64..5e-2,
                    dt in 1e-8f64..1e-5,
                    t in 250.0f64..2000.0,
                    seed in proptest::option::of(any::<u64>()),
                ) {
                    let m = model();
                    if let Err(msg) = c::check_loading_path(&m, &path(&entries, strain, dt), dt, t, seed) {
                        prop_assert!(false, "{}", msg);
                    }
                }
            }
        }
    };
}
