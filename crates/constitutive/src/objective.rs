//! Objective stress rates: how the stress of a material point follows the
//! rotation of the material over a step, so that a rigid rotation rotates
//! the stress and does not strain it.
//!
//! Both rates are implemented the same way: the constitutive update runs in
//! an *unrotated* frame, between a rotation `start` (the frame at t_n) and a
//! rotation `end` (the frame at t_{n+1}),
//!
//! σ̂_n = start^T σ_n start,  d̂ = end^T D end,
//! σ̂_{n+1} = σ̂_n + Δσ̂(d̂ Δt),  σ_{n+1} = end σ̂_{n+1} end^T,
//!
//! with D = ½(L + Lᵀ) and W = ½(L − Lᵀ) from the velocity gradient L
//! (seed 001 eqs 27–28).
//!
//! - [`ObjectiveRate::Jaumann`] (seed 001 eq 30: σ_{n+1} = σ_n + σ ΔΩᵀ +
//!   ΔΩ σ + Δσ, i.e. σ̇ = σ^∇ + Wσ − σW): `start = I` and `end = Q`, the
//!   Hughes–Winget incremental rotation Q = (I − ½WΔt)⁻¹(I + ½WΔt). It
//!   equals eq 30 to first order in WΔt but Q is exactly orthogonal, so a
//!   rigid spin applied over any number of steps preserves the invariants of
//!   the stress to round-off (eq 30 as printed changes them at O(Δt²) per
//!   step). For isotropic elasticity the result is σ_{n+1} = Qσ_nQᵀ + C:DΔt.
//! - [`ObjectiveRate::GreenNaghdi`] (seed 000 §4.2, refs [23, 32]): the frame
//!   is the rotation R of the polar decomposition F = RU of the *total*
//!   deformation gradient. F is carried as history and advanced with the
//!   midpoint (Hughes–Winget) increment F_{n+1} = (I − ½LΔt)⁻¹(I + ½LΔt) F_n,
//!   which is exactly orthogonal for a pure spin; R_{n+1} is the polar
//!   rotation of F_{n+1} (not the product of incremental rotations, whose
//!   result would depend on the path). `start = R_n`, `end = R_{n+1}`.
//!   History: F (9 values, row-major) then R (9 values).

use crate::ConstitutiveError;
use brisance_core::Mat3;
use serde::{Deserialize, Serialize};

/// Number of history values the Green–Naghdi rate carries (F and R).
pub const GREEN_NAGHDI_HISTORY_LEN: usize = 18;

/// Which objective stress rate a model uses.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
pub enum ObjectiveRate {
    /// Jaumann (co-rotational with the spin W), seed 001 eq 30.
    #[default]
    Jaumann,
    /// Green–Naghdi (co-rotational with R of F = RU), seed 000 §4.2.
    GreenNaghdi,
}

/// The rotations bounding the unrotated frame over one step.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CorotationalFrames {
    /// Rotation of the frame at the start of the step.
    pub start: Mat3,
    /// Rotation of the frame at the end of the step.
    pub end: Mat3,
}

impl CorotationalFrames {
    /// The stress at the start of the step in the unrotated frame,
    /// startᵀ σ start.
    #[inline]
    pub fn unrotate_start(&self, sigma: &Mat3) -> Mat3 {
        if self.start == Mat3::identity() {
            // The Jaumann frame: the start of the step is the spatial frame.
            return *sigma;
        }
        self.start.transpose() * sigma * self.start
    }

    /// A rate (the rate of deformation D) in the unrotated frame at the end
    /// of the step, endᵀ D end.
    #[inline]
    pub fn unrotate_end(&self, d: &Mat3) -> Mat3 {
        self.end.transpose() * d * self.end
    }

    /// An unrotated tensor back in the spatial frame at the end of the
    /// step, end σ̂ endᵀ.
    #[inline]
    pub fn rotate_end(&self, sigma_hat: &Mat3) -> Mat3 {
        self.end * sigma_hat * self.end.transpose()
    }
}

/// Rate of deformation D = ½(L + Lᵀ), 1/s (seed 001 eq 27 divided by Δt).
#[inline]
pub fn rate_of_deformation(l: &Mat3) -> Mat3 {
    0.5 * (l + l.transpose())
}

/// Spin W = ½(L − Lᵀ), 1/s (seed 001 eq 28 divided by Δt).
#[inline]
pub fn spin(l: &Mat3) -> Mat3 {
    0.5 * (l - l.transpose())
}

/// The midpoint (Cayley) increment (I − ½AΔt)⁻¹(I + ½AΔt) of a rate A over
/// Δt; for a skew A it is exactly orthogonal (the Hughes–Winget rotation).
/// `None` when I − ½AΔt is singular.
#[inline]
pub fn midpoint_increment(a: &Mat3, dt: f64) -> Option<Mat3> {
    let half = 0.5 * dt * a;
    let inv = (Mat3::identity() - half).try_inverse()?;
    Some(inv * (Mat3::identity() + half))
}

/// Hughes–Winget incremental rotation Q = (I − ½WΔt)⁻¹(I + ½WΔt) of the
/// spin of `l` over `dt`. A skew W has purely imaginary eigenvalues, so
/// I − ½WΔt is never singular and Q always exists.
///
/// Evaluated in closed form, without a matrix inverse: for the skew
/// A = ½WΔt with axial vector a (A v = a × v), A² = a aᵀ − |a|² I and
/// A³ = −|a|² A, so the Cayley transform is
/// (I − A)⁻¹(I + A) = I + 2(A + A²)/(1 + |a|²).
#[inline]
pub fn hughes_winget_rotation(l: &Mat3, dt: f64) -> Mat3 {
    // a = axial vector of ½Δt · ½(L − Lᵀ).
    let h = 0.25 * dt;
    let a = [
        h * (l[(2, 1)] - l[(1, 2)]),
        h * (l[(0, 2)] - l[(2, 0)]),
        h * (l[(1, 0)] - l[(0, 1)]),
    ];
    let s = a[0] * a[0] + a[1] * a[1] + a[2] * a[2];
    let k = 2.0 / (1.0 + s);
    Mat3::new(
        1.0 + k * (a[0] * a[0] - s),
        k * (a[0] * a[1] - a[2]),
        k * (a[0] * a[2] + a[1]),
        k * (a[1] * a[0] + a[2]),
        1.0 + k * (a[1] * a[1] - s),
        k * (a[1] * a[2] - a[0]),
        k * (a[2] * a[0] - a[1]),
        k * (a[2] * a[1] + a[0]),
        1.0 + k * (a[2] * a[2] - s),
    )
}

/// Rotation R of the polar decomposition F = RU, by the scaled Newton
/// iteration X ← ½(γX + (γX)⁻ᵀ), γ = |det X|^(−1/3) (Higham 1986), which
/// converges quadratically for det F > 0. Errors when det F ≤ 0 or F is not
/// finite.
pub fn polar_rotation(f: &Mat3) -> Result<Mat3, ConstitutiveError> {
    let det = f.determinant();
    if !(det.is_finite() && det > 0.0) {
        return Err(ConstitutiveError::InvertedDeformation { det });
    }
    let mut x = *f;
    for _ in 0..60 {
        let d = x.determinant();
        let Some(inv) = x.try_inverse() else {
            return Err(ConstitutiveError::InvertedDeformation { det: d });
        };
        let gamma = if d > 0.0 { d.powf(-1.0 / 3.0) } else { 1.0 };
        let next = 0.5 * (gamma * x + inv.transpose() / gamma);
        let change = (next - x).norm();
        x = next;
        if change <= 4.0 * f64::EPSILON {
            break;
        }
    }
    // A final unscaled step restores orthogonality to round-off.
    match x.try_inverse() {
        Some(inv) => Ok(0.5 * (x + inv.transpose())),
        None => Err(ConstitutiveError::InvertedDeformation { det }),
    }
}

fn read(h: &[f64]) -> Mat3 {
    Mat3::from_row_slice(&h[..9])
}

fn write(m: &Mat3, h: &mut [f64]) {
    for i in 0..3 {
        for j in 0..3 {
            h[3 * i + j] = m[(i, j)];
        }
    }
}

impl ObjectiveRate {
    /// Number of history values this rate carries per point.
    pub const fn history_len(self) -> usize {
        match self {
            Self::Jaumann => 0,
            Self::GreenNaghdi => GREEN_NAGHDI_HISTORY_LEN,
        }
    }

    /// Registry name.
    pub const fn name(self) -> &'static str {
        match self {
            Self::Jaumann => "jaumann",
            Self::GreenNaghdi => "green_naghdi",
        }
    }

    /// Initial history: F = I, R = I for Green–Naghdi, nothing for Jaumann.
    pub fn init_history(self, history: &mut [f64]) {
        if let Self::GreenNaghdi = self {
            write(&Mat3::identity(), &mut history[..9]);
            write(&Mat3::identity(), &mut history[9..18]);
        }
    }

    /// Advances the rotation history over one step of velocity gradient `l`
    /// and returns the frames bounding the unrotated update. The history is
    /// written only on success.
    pub fn advance(
        self,
        l: &Mat3,
        dt: f64,
        history: &mut [f64],
    ) -> Result<CorotationalFrames, ConstitutiveError> {
        match self {
            Self::Jaumann => Ok(CorotationalFrames {
                start: Mat3::identity(),
                end: hughes_winget_rotation(l, dt),
            }),
            Self::GreenNaghdi => {
                let f_old = read(&history[..9]);
                let r_old = read(&history[9..18]);
                let df = midpoint_increment(l, dt).ok_or(ConstitutiveError::SingularIncrement)?;
                let f_new = df * f_old;
                let r_new = polar_rotation(&f_new)?;
                write(&f_new, &mut history[..9]);
                write(&r_new, &mut history[9..18]);
                Ok(CorotationalFrames {
                    start: r_old,
                    end: r_new,
                })
            }
        }
    }
}

impl ObjectiveRate {
    /// [`ObjectiveRate::advance`], falling back to the Jaumann frames (and
    /// leaving the history untouched) when the Green–Naghdi kinematics fail:
    /// a singular increment or det F ≤ 0, i.e. an inverted point the solver
    /// should already have stopped on. The step stays objective and finite
    /// either way; no NaN enters the stress.
    #[inline]
    pub fn advance_or_jaumann(self, l: &Mat3, dt: f64, history: &mut [f64]) -> CorotationalFrames {
        let jaumann = || CorotationalFrames {
            start: Mat3::identity(),
            end: hughes_winget_rotation(l, dt),
        };
        match self {
            // Directly: the Jaumann frames cannot fail.
            Self::Jaumann => jaumann(),
            Self::GreenNaghdi => self.advance(l, dt, history).unwrap_or_else(|_| jaumann()),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn rigid_spin(omega: [f64; 3]) -> Mat3 {
        let [a, b, c] = omega;
        Mat3::new(0.0, -c, b, c, 0.0, -a, -b, a, 0.0)
    }

    fn invariants(s: &Mat3) -> [f64; 3] {
        [
            s.trace(),
            0.5 * (s.trace().powi(2) - (s * s).trace()),
            s.determinant(),
        ]
    }

    fn rotate_by_spin_for_steps(rate: ObjectiveRate, steps: usize) -> (Mat3, Mat3) {
        let sigma0 = Mat3::new(
            3.0e8, 1.2e8, -0.7e8, 1.2e8, -1.0e8, 0.4e8, -0.7e8, 0.4e8, 2.0e8,
        );
        let w = rigid_spin([3.0e5, -1.0e5, 2.0e5]);
        let dt = 1.0e-7;
        let mut h = [0.0; GREEN_NAGHDI_HISTORY_LEN];
        rate.init_history(&mut h);
        let mut sigma = sigma0;
        for _ in 0..steps {
            let frames = rate.advance(&w, dt, &mut h).expect("a spin has a rotation");
            sigma = frames.rotate_end(&frames.unrotate_start(&sigma));
        }
        (sigma0, sigma)
    }

    #[test]
    fn rigid_spin_over_many_steps_preserves_stress_invariants() {
        for rate in [ObjectiveRate::Jaumann, ObjectiveRate::GreenNaghdi] {
            let (s0, s) = rotate_by_spin_for_steps(rate, 5000);
            let (i0, i1) = (invariants(&s0), invariants(&s));
            let scale = s0.norm();
            assert!(
                (i0[0] - i1[0]).abs() <= 1e-12 * scale,
                "{rate:?} I1 {i0:?} {i1:?}"
            );
            assert!(
                (i0[1] - i1[1]).abs() <= 1e-12 * scale * scale,
                "{rate:?} I2 {i0:?} {i1:?}"
            );
            assert!(
                (i0[2] - i1[2]).abs() <= 1e-12 * scale.powi(3),
                "{rate:?} I3 {i0:?} {i1:?}"
            );
            // The stress did rotate (5000 × 3.7e-2 rad ≈ 187 rad of spin).
            assert!((s - s0).norm() > 1e-3 * scale, "{rate:?} did not rotate");
        }
    }

    #[test]
    fn both_rates_agree_for_a_rigid_spin() {
        let (_, sj) = rotate_by_spin_for_steps(ObjectiveRate::Jaumann, 200);
        let (_, sg) = rotate_by_spin_for_steps(ObjectiveRate::GreenNaghdi, 200);
        assert!((sj - sg).norm() <= 1e-10 * sj.norm(), "{sj} vs {sg}");
    }

    #[test]
    fn closed_form_hughes_winget_rotation_equals_the_cayley_transform() {
        // Against (I − ½WΔt)⁻¹(I + ½WΔt) by a matrix inverse, for velocity
        // gradients with any spin, stretch and magnitude.
        for k in 0..200 {
            let t = k as f64;
            let l = Mat3::from_fn(|i, j| ((t + 1.0) * (3 * i + j + 1) as f64 * 0.731).sin() * 1e5);
            for dt in [1e-9, 1e-6, 1e-5, 3e-5] {
                let q = hughes_winget_rotation(&l, dt);
                let reference = midpoint_increment(&spin(&l), dt).unwrap();
                assert!((q - reference).norm() <= 1e-15, "{q} vs {reference}");
                assert!((q * q.transpose() - Mat3::identity()).norm() <= 1e-15);
            }
        }
        assert_eq!(
            hughes_winget_rotation(&Mat3::zeros(), 1.0),
            Mat3::identity()
        );
    }

    #[test]
    fn hughes_winget_rotation_of_a_plane_spin_has_the_cayley_angle() {
        // W = ω(e2⊗e1 − e1⊗e2): Q is a rotation about z by θ = 2 atan(ωΔt/2).
        let (omega, dt) = (1.0e4, 1.0e-4);
        let q = hughes_winget_rotation(&rigid_spin([0.0, 0.0, omega]), dt);
        let theta = 2.0 * (0.5 * omega * dt).atan();
        assert!((q[(0, 0)] - theta.cos()).abs() < 1e-15);
        assert!((q[(1, 0)] - theta.sin()).abs() < 1e-15);
        assert!((q.determinant() - 1.0).abs() < 1e-15);
    }

    #[test]
    fn polar_rotation_of_simple_shear_has_the_closed_form_angle() {
        // F = I + γ e1⊗e2: R rotates by −β about z, tan β = γ/2.
        let gamma = 1.5;
        let f = Mat3::new(1.0, gamma, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0);
        let r = polar_rotation(&f).expect("det F = 1");
        let beta = (0.5 * gamma).atan();
        assert!((r[(0, 0)] - beta.cos()).abs() < 1e-14, "{r}");
        assert!((r[(0, 1)] - beta.sin()).abs() < 1e-14, "{r}");
        let u = r.transpose() * f;
        assert!((u - u.transpose()).norm() < 1e-14, "U not symmetric: {u}");
    }

    #[test]
    fn polar_rotation_rejects_an_inverted_point() {
        let f = Mat3::new(-1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0);
        assert!(matches!(
            polar_rotation(&f),
            Err(ConstitutiveError::InvertedDeformation { .. })
        ));
    }
}
