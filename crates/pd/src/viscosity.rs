//! Pairwise artificial viscosity between detonated products nodes, with
//! the dissipated energy returned to the products as heat.
//!
//! Seed 004 gives the products only the pairwise pressure force of eq 19.
//! That force has no shear stiffness and no dissipation, so node-scale
//! motion excited at the burn front and at the case wall is never damped
//! and holds a large share of the released energy (measured in
//! `docs/physics/pd/gas.md`). Meshfree-particle codes handle this with a
//! pairwise artificial viscosity that acts only while two particles
//! approach (Monaghan & Gingold 1983, J. Comput. Phys. 52:374–389;
//! Monaghan 1992, Annu. Rev. Astron. Astrophys. 30:543–574, eqs 4.1–4.2):
//!
//! ```text
//! μ_ij = h (v_ij · y_ij) / (|y_ij|² + ε h²)     (v_ij · y_ij < 0, else q = 0)
//! q_ij = ρ̄_ij (α c̄_ij |μ_ij| + β μ_ij²)
//! ```
//!
//! with y_ij = y_j − y_i the deformed bond, v_ij = v_j − v_i, ρ̄ and c̄ the
//! means of the two nodes' density ρ₀/X and sound speed, h the lattice
//! spacing and ε = 0.01. Where SPH adds Π_ij = q_ij/ρ̄² beside P_i/ρ_i²
//! and P_j/ρ_j² in its momentum equation, Brisance adds q_ij to the pair
//! pressure of eq 19: the viscous pair force on node i (per unit volume of
//! i and of j) is
//!
//! ```text
//! f_ij = −q_ij ½(a_i + a_j) (r / p²) ê_ij,   a_i = 6 X_i^{4/3} / V_i
//! ```
//!
//! (V_i the family volume of eq 17), i.e. eq 19 with P → q. It is odd and
//! parallel to the bond (eqs 2–4), so momentum and angular momentum are
//! conserved, and it opposes the approach, so the pair dissipates
//!
//! ```text
//! D_ij = −(F_i · v_i + F_j · v_j) = V_i β V_j q_ij ā (r / p³) |v_ij · y_ij| ≥ 0.
//! ```
//!
//! Half of D_ij heats each node (Monaghan 1992 eq 4.3 splits the heating
//! the same way), so the total energy is conserved: a node's heating rate
//! per unit reference volume is H_i = ½ Σ_j β V_j q_ij ā (r/p³)|v_ij · y_ij|.
//! How the heat enters the products' isentrope: `solver.rs`,
//! `products_pressure`, and `docs/physics/pd/gas.md`.
//!
//! **Receding pairs (option `shear`, α_s; 0 by default).** The terms
//! above act only while a pair approaches. With α_s > 0 a linear term
//! acts on every pair, approaching or receding:
//!
//! ```text
//! q_ij = ρ̄_ij (−(α [v_ij·y_ij < 0] + α_s) c̄_ij μ_ij + β [v_ij·y_ij < 0] μ_ij²)
//! ```
//!
//! (for an approaching pair and α_s = 0 this is the q above). On a
//! receding pair q < 0 and the pair force pulls the nodes together: it
//! opposes their relative motion along the bond, so D_ij ≥ 0 still and
//! the heat goes the same way. This is the form SPH uses for a physical
//! viscosity (Monaghan 1992 §4 on the linear term as a viscosity;
//! Monaghan 2005, Rep. Prog. Phys. 68:1703–1759, §4: applied to all
//! pairs, the linear term is in the continuum limit a Navier–Stokes
//! viscosity with kinematic coefficients ∝ α h c): it damps sheets of
//! products sliding past each other through the oblique bonds that
//! recede as well as those that approach, and it damps the products'
//! expansion, the kinetic energy of both going to the products' heat.
//! A departure from seed 004 (whose products have no viscosity),
//! measured in `docs/physics/pd/validation.md`.

use crate::forces::for_each_node_in;
use serde::{Deserialize, Serialize};

/// ε of μ_ij: keeps μ finite as two nodes meet (Monaghan 1992: 0.01).
pub const EPSILON: f64 = 0.01;

/// Artificial-viscosity coefficients of the products (`linear` α,
/// `quadratic` β). The default is Monaghan's α = 1, β = 2 (Monaghan 1992,
/// §4), the values meshfree shock codes use for strong compressions.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct GasViscosity {
    /// α, the coefficient of the term linear in the approach speed.
    pub linear: f64,
    /// β, the coefficient of the quadratic term.
    pub quadratic: f64,
    /// α_s, the coefficient of a linear term on every pair, receding
    /// pairs included (module doc); 0 (the default): approaching pairs only.
    #[serde(default)]
    pub shear: f64,
}

impl Default for GasViscosity {
    fn default() -> Self {
        Self {
            linear: 1.0,
            quadratic: 2.0,
            shear: 0.0,
        }
    }
}

impl GasViscosity {
    /// Checks the coefficients; the error names the field.
    pub fn validate(&self) -> Result<(), String> {
        for (f, v) in [
            ("linear", self.linear),
            ("quadratic", self.quadratic),
            ("shear", self.shear),
        ] {
            if !(v >= 0.0 && v.is_finite()) {
                return Err(format!(
                    "`gas_viscosity.{f}` = {v}: expected a finite value ≥ 0"
                ));
            }
        }
        Ok(())
    }
}

/// The per-node data the viscous pass reads: (a = 6 X^{4/3}/V, ρ = ρ₀/X,
/// c, ρ₀); a = 0 marks a node that takes no part (a solid, or explosive
/// not yet detonated).
pub type ViscousNode = [f64; 4];

/// What the viscous pass returns per node.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub struct ViscousOut {
    /// Σ_j f_ij β V_j, N/m³ (force per unit volume of the node).
    pub force: [f64; 3],
    /// Heating rate H per unit reference volume, W/m³.
    pub heating: f64,
    /// Σ_j |∂(force)/∂(approach speed)| · 2/ρ₀, 1/s: the damping rate for
    /// the stable step (both nodes of a pair move, hence the 2).
    pub damping: f64,
    /// 2 Σ_j 2 q ā r β V_j / p³, N/m⁴ per m³: the stiffness q adds through
    /// the r/p² factor (as P does in eq 26), for the stable step.
    pub stiffness: f64,
}

/// Read-only inputs of the viscous pass.
#[derive(Debug, Clone, Copy)]
pub struct ViscousInput<'a> {
    /// (x, V) per node.
    pub reference: &'a [[f64; 4]],
    /// (u, σ) per node.
    pub state: &'a [[f64; 4]],
    /// Velocities.
    pub velocity: &'a [[f64; 3]],
    /// Row starts of the families.
    pub offsets: &'a [u32],
    /// Neighbour indices.
    pub neighbours: &'a [u32],
    /// Bond factors β (gas bonds never break).
    pub factor: &'a [f32],
    /// Per node, [`ViscousNode`].
    pub node: &'a [ViscousNode],
    /// Lattice spacing h, m.
    pub spacing: f64,
    /// Coefficients.
    pub params: GasViscosity,
}

/// q_ij and ∂q/∂(−s) (s = v_ij · ê, so −s the approach speed) of one
/// pair; (0, 0) when the nodes separate and `shear` is 0, and q < 0 on a
/// receding pair with `shear` > 0. `vr` = v_ij · y_ij, `p2` = |y_ij|².
#[inline]
pub fn pair_pressure(
    params: GasViscosity,
    spacing: f64,
    vr: f64,
    p2: f64,
    rho: f64,
    c: f64,
) -> (f64, f64) {
    let h = spacing;
    let denom = p2 + EPSILON * h * h;
    // μ = h s p/denom with s = vr/p.
    let dmu_ds = h * p2.sqrt() / denom;
    if vr >= 0.0 {
        if params.shear == 0.0 || vr == 0.0 {
            return (0.0, 0.0);
        }
        let mu = h * vr / denom;
        return (
            -rho * params.shear * c * mu,
            rho * params.shear * c * dmu_ds,
        );
    }
    let mu = h * vr / denom;
    let linear = params.linear + params.shear;
    let q = rho * (linear * c * mu.abs() + params.quadratic * mu * mu);
    let dq = rho * (linear * c + 2.0 * params.quadratic * mu.abs()) * dmu_ds;
    (q, dq)
}

/// The viscous pass over all nodes (deterministic, allocation-free): each
/// node sums its own row and writes only its own output.
pub fn viscous_forces(input: &ViscousInput, out: &mut [ViscousOut]) {
    viscous_forces_in(input, 0..out.len(), out);
}

/// [`viscous_forces`] for the nodes of `nodes` only (`out` is the whole
/// per-node array; the other entries are left as they are).
pub fn viscous_forces_in(
    input: &ViscousInput,
    nodes: std::ops::Range<usize>,
    out: &mut [ViscousOut],
) {
    assert_eq!(input.offsets.len(), out.len() + 1, "one row per node");
    for_each_node_in(out, nodes, |i, o| *o = viscous_row(input, i));
}

/// One node's row of [`viscous_forces`].
#[inline]
pub fn viscous_row(input: &ViscousInput, i: usize) -> ViscousOut {
    let mut o = ViscousOut::default();
    let ni = input.node[i];
    if ni[0] == 0.0 {
        return o;
    }
    let xi = input.reference[i];
    let ui = input.state[i];
    let vi = input.velocity[i];
    let row = input.offsets[i] as usize..input.offsets[i + 1] as usize;
    for k in row {
        let j = input.neighbours[k] as usize;
        let nj = input.node[j];
        if nj[0] == 0.0 {
            continue;
        }
        let xj = input.reference[j];
        let uj = input.state[j];
        let vj = input.velocity[j];
        let xi_ = [xj[0] - xi[0], xj[1] - xi[1], xj[2] - xi[2]];
        let y = [
            xi_[0] + uj[0] - ui[0],
            xi_[1] + uj[1] - ui[1],
            xi_[2] + uj[2] - ui[2],
        ];
        let v = [vj[0] - vi[0], vj[1] - vi[1], vj[2] - vi[2]];
        let vr = v[0] * y[0] + v[1] * y[1] + v[2] * y[2];
        if vr >= 0.0 && (input.params.shear == 0.0 || vr == 0.0) {
            continue;
        }
        let r = (xi_[0] * xi_[0] + xi_[1] * xi_[1] + xi_[2] * xi_[2]).sqrt();
        let p2 = (y[0] * y[0] + y[1] * y[1] + y[2] * y[2]).max(1e-30 * r * r);
        let p = p2.sqrt();
        let rho = 0.5 * (ni[1] + nj[1]);
        let c = 0.5 * (ni[2] + nj[2]);
        let (q, dq) = pair_pressure(input.params, input.spacing, vr, p2, rho, c);
        let abar = 0.5 * (ni[0] + nj[0]);
        let bv = input.factor[k] as f64 * xj[3];
        // Force on i, repulsive: −q ā r/p² along ê = y/p, times β V_j.
        let g = -q * abar * r * bv / (p2 * p);
        for (fd, yd) in o.force.iter_mut().zip(y) {
            *fd += g * yd;
        }
        // g vr > 0 (g < 0 approaching, g > 0 receding): half the pair's
        // dissipation per unit volume.
        o.heating += 0.5 * g * vr;
        o.damping += 2.0 * dq * abar * r * bv / p2 / ni[3];
        o.stiffness += 4.0 * q.abs() * abar * r * bv / (p2 * p);
    }
    o
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The viscous pass over two nodes 1 mm apart on x (V = 1e-9 m³, one
    /// bond each way, β = 1, h = 1 mm, at their reference positions) with
    /// the given velocities, per-node data and coefficients.
    fn two_nodes(
        velocity: [[f64; 3]; 2],
        node: [ViscousNode; 2],
        params: GasViscosity,
    ) -> [ViscousOut; 2] {
        let input = ViscousInput {
            reference: &[[0.0, 0.0, 0.0, 1e-9], [1e-3, 0.0, 0.0, 1e-9]],
            state: &[[0.0; 4]; 2],
            velocity: &velocity,
            offsets: &[0, 1, 2],
            neighbours: &[1, 0],
            factor: &[1.0, 1.0],
            node: &node,
            spacing: 1e-3,
            params,
        };
        let mut out = [ViscousOut::default(); 2];
        viscous_forces(&input, &mut out);
        out
    }

    /// Two nodes 1 mm apart on x, approaching at 100 m/s each (v_ij·y_ij =
    /// −200 m/s · 1 mm), ρ = 2000 kg/m³, c = 3000 m/s, a = 6, V = 1e-9 m³,
    /// β = 1, h = 1 mm, α = 1, β_q = 2, by hand:
    /// μ = 1e-3 · (−0.2)/(1e-6 + 1e-8) = −198.0198 m/s,
    /// q = 2000 (3000 · 198.0198 + 2 · 198.0198²) = 1.344966e9 Pa,
    /// f_x on node 0 = −q · 6 · 1e-3 · 1e-9 · 1e-3/1e-9 = −8.069797e3 N/m³,
    /// H = ½ |f_x| · 200 m/s = 8.069797e5 W/m³ on each node.
    #[test]
    fn pair_force_and_heating_by_hand() {
        let mu: f64 = 1e-3 * -0.2 / (1e-6 + 1e-8);
        assert!((mu + 198.019_801_98).abs() < 1e-8);
        let q = 2000.0 * (3000.0 * mu.abs() + 2.0 * mu * mu);
        assert!((q / 1.344_966_179_786e9 - 1.0).abs() < 1e-12, "{q}");
        let out = two_nodes(
            [[100.0, 0.0, 0.0], [-100.0, 0.0, 0.0]],
            [[6.0, 2000.0, 3000.0, 2000.0]; 2],
            GasViscosity::default(),
        );
        let fx = -8.069_797_078_718e3;
        assert!((out[0].force[0] / fx - 1.0).abs() < 1e-12, "{:?}", out[0]);
        assert_eq!(out[0].force[1], 0.0);
        assert_eq!(out[1].force[0], -out[0].force[0]);
        assert!((out[0].heating / 8.069_797_078_718e5 - 1.0).abs() < 1e-12);
        assert_eq!(out[0].heating, out[1].heating);
        // Power: F_0·v_0 + F_1·v_1 (per unit volume times V) = −(H_0 + H_1)V.
        let power = (out[0].force[0] * 100.0 + out[1].force[0] * -100.0) * 1e-9;
        assert!((power + (out[0].heating + out[1].heating) * 1e-9).abs() < 1e-18);
    }

    /// Separating nodes, nodes moving side by side (v ⟂ y) and a node that
    /// has not detonated (a = 0) feel nothing.
    #[test]
    fn no_viscosity_unless_the_pair_approaches_and_both_take_part() {
        let cases: [([[f64; 3]; 2], f64); 3] = [
            ([[-100.0, 0.0, 0.0], [100.0, 0.0, 0.0]], 6.0),
            ([[0.0, 50.0, 0.0], [0.0, -50.0, 0.0]], 6.0),
            ([[100.0, 0.0, 0.0], [-100.0, 0.0, 0.0]], 0.0),
        ];
        for (velocity, a1) in cases {
            let node = [[6.0, 2000.0, 3000.0, 2000.0], [a1, 2000.0, 3000.0, 2000.0]];
            let out = two_nodes(velocity, node, GasViscosity::default());
            assert_eq!(out, [ViscousOut::default(); 2], "{velocity:?} {a1}");
        }
    }

    /// ∂q/∂(−s) matches a finite difference of q in the approach speed,
    /// approaching and (with `shear`) receding.
    #[test]
    fn pair_pressure_derivative_is_consistent() {
        let (p2, rho, c, h): (f64, f64, f64, f64) = (1.2e-6, 1800.0, 4000.0, 1e-3);
        let p = p2.sqrt();
        let shear = GasViscosity {
            shear: 0.5,
            ..GasViscosity::default()
        };
        for params in [GasViscosity::default(), shear] {
            for s in [-10.0, -300.0, -2000.0, 10.0, 2000.0] {
                if s > 0.0 && params.shear == 0.0 {
                    continue;
                }
                let (_, dq) = pair_pressure(params, h, s * p, p2, rho, c);
                let d = 1e-3;
                let qa = pair_pressure(params, h, (s - d) * p, p2, rho, c).0;
                let qb = pair_pressure(params, h, (s + d) * p, p2, rho, c).0;
                let fd = (qa - qb) / (2.0 * d);
                assert!((fd / dq - 1.0).abs() < 1e-6, "{params:?} {s}: {fd} vs {dq}");
            }
            assert_eq!(pair_pressure(params, h, 0.0, p2, rho, c), (0.0, 0.0));
        }
        assert_eq!(
            pair_pressure(GasViscosity::default(), h, 2000.0 * p, p2, rho, c),
            (0.0, 0.0)
        );
    }

    /// The receding pair of `pair_force_and_heating_by_hand` (velocities
    /// reversed) with α_s = 0.5, by hand: μ = +198.0198 m/s,
    /// q = −2000 · 0.5 · 3000 · 198.0198 = −5.940594e8 Pa (a pull),
    /// f_x on node 0 = −q · 6 · 1e-3 · 1e-9 · 1e-3/1e-9 = +3.564356e3 N/m³
    /// (towards node 1), H = ½ f_x · 200 m/s = 3.564356e5 W/m³ per node;
    /// approaching, α + α_s = 1.5 in the linear term.
    #[test]
    fn receding_pairs_feel_the_shear_term_by_hand() {
        let params = GasViscosity {
            shear: 0.5,
            ..GasViscosity::default()
        };
        let run = |velocity| two_nodes(velocity, [[6.0, 2000.0, 3000.0, 2000.0]; 2], params);
        let out = run([[-100.0, 0.0, 0.0], [100.0, 0.0, 0.0]]);
        let fx = 3.564_356_435_644e3;
        assert!((out[0].force[0] / fx - 1.0).abs() < 1e-12, "{:?}", out[0]);
        assert_eq!(out[1].force[0], -out[0].force[0]);
        assert!((out[0].heating / 3.564_356_435_644e5 - 1.0).abs() < 1e-12);
        let power = (out[0].force[0] * -100.0 + out[1].force[0] * 100.0) * 1e-9;
        assert!((power + (out[0].heating + out[1].heating) * 1e-9).abs() < 1e-18);
        assert!(out[0].stiffness > 0.0 && out[0].damping > 0.0);
        // Approaching: q = 2000 (1.5 · 3000 · 198.0198 + 2 · 198.0198²).
        let out = run([[100.0, 0.0, 0.0], [-100.0, 0.0, 0.0]]);
        let mu: f64 = 1e-3 * 0.2 / (1e-6 + 1e-8);
        let q = 2000.0 * (1.5 * 3000.0 * mu + 2.0 * mu * mu);
        let fx = -q * 6.0 * 1e-3 * 1e-9 * 1e-3 / 1e-9;
        assert!((out[0].force[0] / fx - 1.0).abs() < 1e-12, "{:?}", out[0]);
        // Side by side (v ⟂ y): nothing, with or without the shear term.
        assert_eq!(
            run([[0.0, 50.0, 0.0], [0.0, -50.0, 0.0]]),
            [ViscousOut::default(); 2]
        );
    }

    #[test]
    fn invalid_coefficients_name_the_field() {
        let v = GasViscosity {
            linear: -1.0,
            ..GasViscosity::default()
        };
        assert!(v.validate().unwrap_err().contains("gas_viscosity.linear"));
        let v = GasViscosity {
            quadratic: f64::NAN,
            ..GasViscosity::default()
        };
        assert!(v
            .validate()
            .unwrap_err()
            .contains("gas_viscosity.quadratic"));
        let v = GasViscosity {
            shear: -0.1,
            ..GasViscosity::default()
        };
        assert!(v.validate().unwrap_err().contains("gas_viscosity.shear"));
    }
}
