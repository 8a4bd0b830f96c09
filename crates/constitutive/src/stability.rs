//! Loss of material stability, seed 000 §4.2 failure criterion 3: the
//! Drucker stability postulate (seed 000 ref \[37\]) and the loss of
//! hyperbolicity of the equations of motion (eq 48, refs [38–40]).
//!
//! **Tangent modulus.** Both checks use the co-rotational tangent modulus
//! M of the hypoelastic–plastic J2 metal, σ̂̇ = M : d̂ in the unrotated frame
//! (the continuum tangent of associated von Mises flow):
//!
//! M = K 1⊗1 + 2G (𝕀 − ⅓ 1⊗1) − β N̂⊗N̂,  β = 6G²/(3G + H),
//!
//! with K the bulk modulus, G the shear modulus, N̂ = s/|s| the unit flow
//! direction and H the plastic modulus dσ_y/dε_p (Pa). Elastic: β = 0
//! (H = +∞). It follows from ṡ = 2G(ė − ε̇_p (3/2) s/σ̄) with the
//! consistency condition dσ̄ = H dε_p.
//!
//! **Drucker.** A plastic step is stable in Drucker's sense when
//! σ̇ : ε̇_p ≥ 0; the point fails when σ̇ : ε̇_p < 0, with σ̇ = M : d̂ and
//! ε̇_p = √(3/2) ε̇_p N̂. For the J2 tangent N̂ : M : d̂ = (2G − β) N̂ : d̂ =
//! 2GH/(3G + H) N̂ : d̂, so for loading (N̂ : d̂ > 0) the postulate fails
//! exactly when H < 0: softening. It is evaluated in that closed form
//! ([`TangentModulus::flow_stress_rate`]), so perfect plasticity (H = 0)
//! gives exactly zero — stable — instead of round-off of either sign.
//!
//! **Hyperbolicity** (eq 48). A band with normal n across which the
//! velocity jumps by g can form when R(n) g = 0 has a nonzero solution,
//!
//! R_ij = M_ikjl n_k n_l + M_ilkj n_k n_l − σ_ik n_j n_k,
//!
//! i.e. when det R(n) ≤ 0. As seed 000 (after Becker, Int. J. Solids Struct.
//! 39 (2002) 3555, its ref \[40\]) n is searched only in the plane of the
//! maximum and minimum principal stresses: n = cos θ e_max + sin θ e_min.
//! R is quadratic in n, so R(θ) = P + Q cos 2θ + S sin 2θ with P, Q, S from
//! R at e_max, e_min and e_max + e_min, and det R(θ) is a trigonometric
//! polynomial of degree 3 in 2θ. Its minimum over θ ∈ [0, π) is found by
//! sampling [`PLANE_SAMPLES`] angles and refining every sampled local
//! minimum by golden-section search to 1e-12 rad. For the elastic tangent
//! with zero stress, det R = 8 G² (λ + 2G) for every n; for the J2 tangent
//! in plane strain (N̂ = (e₁e₁ − e₃e₃)/√2, σ = 0) the minimum is at 45°,
//! det R = 8 G (λ + 2G)(G − β/2) = 8 G² (λ + 2G) H/(3G + H), zero for
//! perfect plasticity: the von Mises solid is at the verge of localisation
//! when it stops hardening (Rudnicki & Rice 1975).

use crate::hypoelastic::deviator;
use brisance_core::{Mat3, Vec3};
use serde::{Deserialize, Serialize};

/// Angles sampled over θ ∈ [0, π) before refinement.
pub const PLANE_SAMPLES: usize = 72;

/// Which loss-of-stability checks fail a yielding point (seed 000 §4.2
/// criterion 3). Both default to off.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct StabilityChecks {
    /// Drucker's postulate: fail when σ̇ : ε̇_p < 0.
    #[serde(default)]
    pub drucker: bool,
    /// Loss of hyperbolicity: fail when det R(n) ≤ 0 for a normal n in the
    /// plane of the maximum and minimum principal stresses (eq 48).
    #[serde(default)]
    pub hyperbolicity: bool,
}

impl StabilityChecks {
    /// Whether any check is on.
    pub const fn any(&self) -> bool {
        self.drucker || self.hyperbolicity
    }
}

/// The co-rotational tangent modulus of the hypoelastic–plastic J2 metal.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TangentModulus {
    /// Bulk modulus K, Pa.
    pub bulk_modulus: f64,
    /// Shear modulus G, Pa.
    pub shear_modulus: f64,
    /// Plastic modulus H = dσ_y/dε_p, Pa; +∞ for the elastic tangent.
    pub hardening_modulus: f64,
    /// Unit deviatoric flow direction N̂ (zero for the elastic tangent).
    pub flow_direction: Mat3,
}

impl TangentModulus {
    /// The isotropic elastic modulus.
    pub fn elastic(bulk_modulus: f64, shear_modulus: f64) -> Self {
        Self {
            bulk_modulus,
            shear_modulus,
            hardening_modulus: f64::INFINITY,
            flow_direction: Mat3::zeros(),
        }
    }

    /// The J2 elastic–plastic tangent at the stress `sigma` (its deviator
    /// gives N̂) and the plastic modulus H.
    pub fn elastic_plastic(
        bulk_modulus: f64,
        shear_modulus: f64,
        hardening_modulus: f64,
        sigma: &Mat3,
    ) -> Self {
        let s = deviator(sigma);
        let norm = s.norm();
        let flow_direction = if norm > 0.0 { s / norm } else { Mat3::zeros() };
        Self {
            bulk_modulus,
            shear_modulus,
            hardening_modulus,
            flow_direction,
        }
    }

    /// Whether 3G + H ≤ 0: softening so fast that the continuum tangent
    /// does not exist (β unbounded) — unstable by either check.
    pub fn is_singular(&self) -> bool {
        !(3.0 * self.shear_modulus + self.hardening_modulus > 0.0)
    }

    /// β = 6G²/(3G + H) (0 for H = +∞, +∞ when singular), Pa.
    pub fn plastic_stiffness(&self) -> f64 {
        let (g, h) = (self.shear_modulus, self.hardening_modulus);
        if h == f64::INFINITY {
            0.0
        } else if self.is_singular() {
            f64::INFINITY
        } else {
            6.0 * g * g / (3.0 * g + h)
        }
    }

    /// 2G − β = 2GH/(3G + H) in closed form (2G elastic, exactly 0 for
    /// H = 0, −∞ when singular), Pa.
    pub fn flow_stiffness(&self) -> f64 {
        let (g, h) = (self.shear_modulus, self.hardening_modulus);
        if h == f64::INFINITY {
            2.0 * g
        } else if self.is_singular() {
            f64::NEG_INFINITY
        } else {
            2.0 * g * h / (3.0 * g + h)
        }
    }

    /// M_ijkl, Pa.
    pub fn component(&self, i: usize, j: usize, k: usize, l: usize) -> f64 {
        let delta = |a: usize, b: usize| if a == b { 1.0 } else { 0.0 };
        let (kb, g) = (self.bulk_modulus, self.shear_modulus);
        let n = &self.flow_direction;
        let plastic = if n[(i, j)] == 0.0 || n[(k, l)] == 0.0 {
            0.0
        } else {
            self.plastic_stiffness() * n[(i, j)] * n[(k, l)]
        };
        (kb - 2.0 * g / 3.0) * delta(i, j) * delta(k, l)
            + g * (delta(i, k) * delta(j, l) + delta(i, l) * delta(j, k))
            - plastic
    }

    /// M : d for a symmetric d, Pa/s.
    pub fn contract(&self, d: &Mat3) -> Mat3 {
        let n = &self.flow_direction;
        let beta = self.plastic_stiffness();
        let plastic = if beta == 0.0 {
            Mat3::zeros()
        } else {
            n * (beta * n.component_mul(d).sum())
        };
        Mat3::identity() * (self.bulk_modulus * d.trace())
            + deviator(d) * (2.0 * self.shear_modulus)
            - plastic
    }

    /// N̂ : (M : d) = (2G − β) N̂ : d, with 2G − β in closed form
    /// ([`TangentModulus::flow_stiffness`]), Pa/s.
    pub fn flow_stress_rate(&self, d: &Mat3) -> f64 {
        let nd = self.flow_direction.component_mul(d).sum();
        if nd == 0.0 {
            0.0
        } else {
            self.flow_stiffness() * nd
        }
    }
}

/// Drucker's product σ̇ : ε̇_p (Pa/s²·… the units of the two rates); the
/// postulate holds when it is ≥ 0.
pub fn drucker_product(stress_rate: &Mat3, plastic_strain_rate: &Mat3) -> f64 {
    stress_rate.component_mul(plastic_strain_rate).sum()
}

/// R(n) of eq 48 for the modulus `m` (M_ijkl, Pa), the stress `sigma` (Pa)
/// and the unit normal `n`.
pub fn localization_tensor<F>(m: &F, sigma: &Mat3, n: &Vec3) -> Mat3
where
    F: Fn(usize, usize, usize, usize) -> f64,
{
    let sn = sigma * n;
    Mat3::from_fn(|i, j| {
        let mut v = 0.0;
        for k in 0..3 {
            for l in 0..3 {
                v += (m(i, k, j, l) + m(i, l, k, j)) * n[k] * n[l];
            }
        }
        v - sn[i] * n[j]
    })
}

/// The minimum of det R(n) over n = cos θ e1 + sin θ e3 (e1, e3 orthonormal)
/// and the normal where it is reached: (det, n), Pa³.
pub fn min_determinant_in_plane<F>(m: &F, sigma: &Mat3, e1: &Vec3, e3: &Vec3) -> (f64, Vec3)
where
    F: Fn(usize, usize, usize, usize) -> f64,
{
    let a = localization_tensor(m, sigma, e1);
    let c = localization_tensor(m, sigma, e3);
    let ac = localization_tensor(m, sigma, &(e1 + e3));
    let p = (a + c) * 0.5;
    let q = (a - c) * 0.5;
    let s = (ac - a - c) * 0.5;
    let det = |phi: f64| (p + q * phi.cos() + s * phi.sin()).determinant();
    let step = std::f64::consts::TAU / PLANE_SAMPLES as f64;
    let values: [f64; PLANE_SAMPLES] = std::array::from_fn(|k| det(k as f64 * step));
    let (mut best, mut best_phi) = (f64::INFINITY, 0.0);
    for k in 0..PLANE_SAMPLES {
        let prev = values[(k + PLANE_SAMPLES - 1) % PLANE_SAMPLES];
        let next = values[(k + 1) % PLANE_SAMPLES];
        if !(values[k] <= prev && values[k] <= next) {
            continue;
        }
        let (v, phi) = golden_minimum(&det, (k as f64 - 1.0) * step, (k as f64 + 1.0) * step);
        let (v, phi) = if values[k] < v {
            (values[k], k as f64 * step)
        } else {
            (v, phi)
        };
        if v < best {
            (best, best_phi) = (v, phi);
        }
    }
    if !best.is_finite() {
        // No sampled local minimum (a NaN somewhere): report the samples.
        let k = (0..PLANE_SAMPLES)
            .min_by(|&i, &j| values[i].total_cmp(&values[j]))
            .unwrap_or(0);
        (best, best_phi) = (values[k], k as f64 * step);
    }
    let theta = 0.5 * best_phi;
    (best, e1 * theta.cos() + e3 * theta.sin())
}

/// Golden-section minimum of `f` on [lo, hi] to 1e-12: (value, argument).
fn golden_minimum(f: &impl Fn(f64) -> f64, mut lo: f64, mut hi: f64) -> (f64, f64) {
    let r = 0.5 * (5f64.sqrt() - 1.0);
    let mut x1 = hi - r * (hi - lo);
    let mut x2 = lo + r * (hi - lo);
    let (mut f1, mut f2) = (f(x1), f(x2));
    while hi - lo > 1e-12 {
        if f1 <= f2 {
            hi = x2;
            (x2, f2) = (x1, f1);
            x1 = hi - r * (hi - lo);
            f1 = f(x1);
        } else {
            lo = x1;
            (x1, f1) = (x2, f2);
            x2 = lo + r * (hi - lo);
            f2 = f(x2);
        }
    }
    if f1 <= f2 {
        (f1, x1)
    } else {
        (f2, x2)
    }
}

/// The principal directions of the largest and the smallest principal
/// stress of `sigma` (distinct eigenvectors even for equal eigenvalues).
pub fn extreme_principal_directions(sigma: &Mat3) -> (Vec3, Vec3) {
    let sym = (sigma + sigma.transpose()) * 0.5;
    let eig = nalgebra::SymmetricEigen::new(sym);
    let mut order = [0usize, 1, 2];
    order.sort_by(|&i, &j| eig.eigenvalues[i].total_cmp(&eig.eigenvalues[j]));
    let e_max: Vec3 = eig.eigenvectors.column(order[2]).into_owned();
    let e_min: Vec3 = eig.eigenvectors.column(order[0]).into_owned();
    (e_max, e_min)
}

/// The minimum of det R(n) (eq 48) over the plane of the maximum and
/// minimum principal stresses of `sigma`: (det, n), Pa³.
pub fn min_principal_plane_determinant<F>(m: &F, sigma: &Mat3) -> (f64, Vec3)
where
    F: Fn(usize, usize, usize, usize) -> f64,
{
    let (e_max, e_min) = extreme_principal_directions(sigma);
    min_determinant_in_plane(m, sigma, &e_max, &e_min)
}

/// Whether the J2 tangent `tangent` at the stress `sigma` has lost
/// hyperbolicity: det R(n) ≤ 0 for some n in the plane of the maximum and
/// minimum principal stresses, or no tangent exists (3G + H ≤ 0).
pub fn loses_hyperbolicity(tangent: &TangentModulus, sigma: &Mat3) -> bool {
    if tangent.is_singular() {
        return true;
    }
    let m = |i, j, k, l| tangent.component(i, j, k, l);
    let (det, _) = min_principal_plane_determinant(&m, sigma);
    !(det > 0.0)
}

/// Whether a plastic step of rate ε̇_p (1/s) and rate of deformation `d`
/// (unrotated, 1/s) violates Drucker's postulate with the tangent
/// `tangent`: σ̇ : ε̇_p = √(3/2) ε̇_p N̂ : M : d < 0, or no tangent exists.
pub fn violates_drucker(tangent: &TangentModulus, plastic_strain_rate: f64, d: &Mat3) -> bool {
    if tangent.is_singular() {
        return true;
    }
    1.5f64.sqrt() * plastic_strain_rate * tangent.flow_stress_rate(d) < 0.0
}

#[cfg(test)]
mod tests {
    use super::*;

    const K: f64 = 160.0e9;
    const G: f64 = 80.0e9;
    const LAMBDA: f64 = K - 2.0 * G / 3.0;

    fn plane_strain_direction() -> Mat3 {
        Mat3::new(1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, -1.0) / 2f64.sqrt()
    }

    /// Elastic, σ = 0: R = 2[(λ + G) n⊗n + G I] for every n, det R =
    /// 8 G² (λ + 2G) = 8 × 6.4e21 × 2.666667e11 = 1.365333e34 Pa³.
    #[test]
    fn elastic_determinant_is_eight_g_squared_times_p_modulus() {
        let t = TangentModulus::elastic(K, G);
        let m = |i, j, k, l| t.component(i, j, k, l);
        let hand = 8.0 * G * G * (LAMBDA + 2.0 * G);
        assert!((hand - 1.365_333e34).abs() < 1e-6 * hand);
        let n = Vec3::new(0.3, -0.4, 0.5).normalize();
        let r = localization_tensor(&m, &Mat3::zeros(), &n);
        let expected = (n * n.transpose()) * (2.0 * (LAMBDA + G)) + Mat3::identity() * (2.0 * G);
        assert!((r - expected).norm() < 1e-12 * expected.norm(), "{r}");
        let (det, _) = min_determinant_in_plane(&m, &Mat3::zeros(), &Vec3::x(), &Vec3::z());
        assert!((det - hand).abs() < 1e-12 * hand, "{det}");
    }

    /// The stress term: n = e₁, σ = diag(σ₁, σ₂, σ₃) gives
    /// R = diag(2(λ + 2G) − σ₁, 2G, 2G).
    #[test]
    fn stress_term_subtracts_sigma_n_outer_n() {
        let t = TangentModulus::elastic(K, G);
        let m = |i, j, k, l| t.component(i, j, k, l);
        let sigma = Mat3::from_diagonal(&Vec3::new(2.0e9, -1.0e9, 0.5e9));
        let r = localization_tensor(&m, &sigma, &Vec3::x());
        let expected = Mat3::from_diagonal(&Vec3::new(
            2.0 * (LAMBDA + 2.0 * G) - 2.0e9,
            2.0 * G,
            2.0 * G,
        ));
        assert!((r - expected).norm() < 1e-12 * expected.norm(), "{r}");
    }

    /// J2 tangent in plane strain (N̂ = (e₁e₁ − e₃e₃)/√2, σ = 0): the minimum
    /// over the (e₁, e₃) plane is at 45° with det R = 8G²(λ + 2G)H/(3G + H);
    /// zero at H = 0, negative for softening.
    #[test]
    fn plane_strain_j2_tangent_localises_when_hardening_stops() {
        for h in [0.05 * G, 1.0e9, 0.0, -0.01 * G] {
            let t = TangentModulus {
                bulk_modulus: K,
                shear_modulus: G,
                hardening_modulus: h,
                flow_direction: plane_strain_direction(),
            };
            let m = |i, j, k, l| t.component(i, j, k, l);
            let (det, n) = min_determinant_in_plane(&m, &Mat3::zeros(), &Vec3::x(), &Vec3::z());
            let hand = 8.0 * G * G * (LAMBDA + 2.0 * G) * h / (3.0 * G + h);
            let scale = 8.0 * G * G * (LAMBDA + 2.0 * G);
            assert!(
                (det - hand).abs() < 1e-10 * scale,
                "H = {h}: {det} vs {hand}"
            );
            assert!((n.x.abs() - n.z.abs()).abs() < 1e-5, "H = {h}: n = {n}");
        }
        // With a principal plane from a stress coaxial with N̂.
        let sigma = plane_strain_direction() * 1.0e9;
        let soft = TangentModulus::elastic_plastic(K, G, -1.0e9, &sigma);
        let hard = TangentModulus::elastic_plastic(K, G, 5.0e9, &sigma);
        assert!(loses_hyperbolicity(&soft, &sigma));
        assert!(!loses_hyperbolicity(&hard, &sigma));
        assert!(!loses_hyperbolicity(&TangentModulus::elastic(K, G), &sigma));
        let singular = TangentModulus::elastic_plastic(K, G, -3.0 * G, &sigma);
        assert!(singular.is_singular() && loses_hyperbolicity(&singular, &sigma));
    }

    /// The search is frame indifferent: rotating the stress and the flow
    /// direction leaves the minimum determinant unchanged.
    #[test]
    fn principal_plane_minimum_is_frame_indifferent() {
        let sigma = Mat3::new(
            0.9e9, 0.2e9, -0.1e9, 0.2e9, -0.3e9, 0.25e9, -0.1e9, 0.25e9, 0.1e9,
        );
        let t = TangentModulus::elastic_plastic(K, G, 0.02 * G, &sigma);
        let m = |i, j, k, l| t.component(i, j, k, l);
        let (det, n) = min_principal_plane_determinant(&m, &sigma);
        let q = nalgebra::Rotation3::from_scaled_axis(Vec3::new(0.4, -1.1, 0.7)).into_inner();
        let sigma_q = q * sigma * q.transpose();
        let tq = TangentModulus::elastic_plastic(K, G, 0.02 * G, &sigma_q);
        let mq = |i, j, k, l| tq.component(i, j, k, l);
        let (det_q, _) = min_principal_plane_determinant(&mq, &sigma_q);
        assert!((det - det_q).abs() < 1e-9 * det.abs(), "{det} vs {det_q}");
        // The minimising normal lies in the plane of the extreme stresses.
        let (e_max, e_min) = extreme_principal_directions(&sigma);
        let e_mid = e_max.cross(&e_min);
        assert!(n.dot(&e_mid).abs() < 1e-12, "{n}");
        // And it is the minimum: no sampled normal of the plane goes lower.
        for k in 0..360 {
            let th = k as f64 * std::f64::consts::PI / 360.0;
            let nk = e_max * th.cos() + e_min * th.sin();
            assert!(localization_tensor(&m, &sigma, &nk).determinant() >= det * (1.0 - 1e-12));
        }
    }

    /// M : d from the components equals the closed form, and the Drucker
    /// product σ̇ : ε̇_p of the tangent stress rate equals
    /// √(3/2) ε̇_p 2GH/(3G + H) N̂ : d. Hand value: N̂ = (e₁e₂ + e₂e₁)/√2,
    /// d = 1e3 (e₁e₂ + e₂e₁) /s, so N̂ : d = √2 × 1e3; H = 1 GPa:
    /// 2GH/(3G + H) = 1.6e20/2.41e11 = 6.639004e8 Pa, ε̇_p = 500/s →
    /// √1.5 × 500 × 6.639004e8 × 1414.2136 = 5.749e14.
    #[test]
    fn drucker_product_has_the_sign_of_the_hardening() {
        let n = Mat3::new(0.0, 1.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 0.0) / 2f64.sqrt();
        let d = Mat3::new(0.0, 1e3, 0.0, 1e3, 0.0, 0.0, 0.0, 0.0, 0.0) + Mat3::identity() * 2e2;
        let t = TangentModulus {
            bulk_modulus: K,
            shear_modulus: G,
            hardening_modulus: 1.0e9,
            flow_direction: n,
        };
        let from_components = Mat3::from_fn(|i, j| {
            (0..3)
                .flat_map(|k| (0..3).map(move |l| (k, l)))
                .map(|(k, l)| t.component(i, j, k, l) * d[(k, l)])
                .sum()
        });
        let closed = t.contract(&d);
        assert!((from_components - closed).norm() < 1e-12 * closed.norm());
        let eps_rate = 500.0;
        let general = drucker_product(&closed, &(n * (1.5f64.sqrt() * eps_rate)));
        let hand = 1.5f64.sqrt() * eps_rate * (2.0 * G * 1e9 / (3.0 * G + 1e9)) * 2f64.sqrt() * 1e3;
        assert!((general - hand).abs() < 1e-9 * hand, "{general} vs {hand}");
        assert!((hand - 5.749e14).abs() < 0.001e14, "{hand}");
        assert!(!violates_drucker(&t, eps_rate, &d));
        let soft = TangentModulus {
            hardening_modulus: -1.0e9,
            ..t
        };
        assert!(violates_drucker(&soft, eps_rate, &d));
        // Perfect plasticity: exactly zero, stable.
        let perfect = TangentModulus {
            hardening_modulus: 0.0,
            ..t
        };
        assert_eq!(perfect.flow_stress_rate(&d), 0.0);
        assert!(!violates_drucker(&perfect, eps_rate, &d));
    }

    #[test]
    fn checks_default_off() {
        let c = StabilityChecks::default();
        assert!(!c.any() && !c.drucker && !c.hyperbolicity);
        let on = StabilityChecks { drucker: true, ..c };
        assert!(on.any());
    }
}
