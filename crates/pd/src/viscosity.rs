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
//!
//! **Deviatoric viscosity (option `deviatoric`, α_d; 0 by default).** A
//! pair force sees only the pair's stretching rate, of which a uniform
//! expansion is a part, so the terms above resist the products'
//! expansion as much as their shear. The deviatoric term leaves every
//! uniform expansion and rigid motion alone: the viscous analogue of the
//! deviatoric part of the linear peridynamic solid (Silling, Epton,
//! Weckner, Xu & Askari 2007, J. Elasticity 88:151–184, §15; its
//! viscous dashpot form in Mitchell 2011, "A nonlocal, ordinary,
//! state-based viscoelasticity model for peridynamics", Sandia report
//! SAND2011-8064), written on the current bonds y_ij with the weights
//! β_ij V_j of eq 17. Per node, over the family's products nodes,
//!
//! ```text
//! m_i = Σ_j β V_j |y_ij|²,   θ̇_i = (3/m_i) Σ_j β V_j (v_ij · y_ij)
//! ė_ij = v_ij · y_ij / |y_ij|,   ė^d_ij = ė_ij − θ̇_i |y_ij| / 3
//! t_ij = (15 η_i / m_i) ė^d_ij,   η_i = α_d ρ_i c_i h
//! f_i  = Σ_j β V_j (t_ij + t_ji) y_ij / |y_ij|
//! ```
//!
//! (θ̇ the dilatation rate, exact for v = A y with A = (θ̇/3) I + W, W
//! skew, for which every ė^d vanishes; 15η/m is LPS's 15μ/m with the
//! shear modulus μ replaced by the shear viscosity η). The force is
//! central and odd, so momentum and angular momentum are conserved; since
//! Σ_j β V_j |y_ij| ė^d_ij = 0 by the definition of θ̇, the power the pair
//! forces take out is exactly Σ_i V_i D_i with each node's
//! D_i = (15 η_i / m_i) Σ_j β V_j (ė^d_ij)² ≥ 0, returned as heat through
//! the kick like the terms above. A node whose family holds no other
//! products node has no deviatoric term. On several MPI ranks each rank
//! forms (θ̇, 15η/m) over the reach of its nodes (its own and every
//! neighbour in their rows, a contiguous range: `solver::ranks`), so the
//! force pass over its own nodes reads its neighbours' without another
//! exchange.

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
    /// α_d, the coefficient of the deviatoric (shear-only) viscosity
    /// η = α_d ρ c h (module doc); 0 (the default): none.
    #[serde(default)]
    pub deviatoric: f64,
}

impl Default for GasViscosity {
    fn default() -> Self {
        Self {
            linear: 1.0,
            quadratic: 2.0,
            shear: 0.0,
            deviatoric: 0.0,
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
            ("deviatoric", self.deviatoric),
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

/// Per node, what the deviatoric term reads of it: (θ̇, 15η/m), the
/// dilatation rate and the force-state coefficient (module doc); 15η/m = 0
/// marks a node without the term.
pub type DeviatoricNode = [f64; 2];

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
    /// Per node, [`DeviatoricNode`] from [`deviatoric_node`]; empty when
    /// the deviatoric term is off.
    pub deviatoric: &'a [DeviatoricNode],
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

/// Bond k from node i (reference position and volume, displacement
/// `xu`, velocity `vi`) to node j: the reference bond ξ = x_j − x_i, the
/// current bond y = ξ + u_j − u_i, the relative velocity v_j − v_i and
/// the weight β V_j.
#[inline(always)]
fn pair(
    input: &ViscousInput,
    xu: [[f64; 4]; 2],
    vi: [f64; 3],
    k: usize,
    j: usize,
) -> ([f64; 3], [f64; 3], [f64; 3], f64) {
    let [xi, ui] = xu;
    let (xj, uj, vj) = (input.reference[j], input.state[j], input.velocity[j]);
    let xi_ = [xj[0] - xi[0], xj[1] - xi[1], xj[2] - xi[2]];
    let y = [
        xi_[0] + uj[0] - ui[0],
        xi_[1] + uj[1] - ui[1],
        xi_[2] + uj[2] - ui[2],
    ];
    let v = [vj[0] - vi[0], vj[1] - vi[1], vj[2] - vi[2]];
    (xi_, y, v, input.factor[k] as f64 * xj[3])
}

/// Node i's (θ̇, 15η/m) for the deviatoric term (module doc), from the
/// positions and velocities of `input` (its `deviatoric` is not read):
/// [0, 0] when `deviatoric` is 0, when the node takes no part, or when
/// no other products node of its family has moved apart from it.
#[inline]
pub fn deviatoric_node(input: &ViscousInput, i: usize) -> DeviatoricNode {
    let ni = input.node[i];
    if input.params.deviatoric == 0.0 || ni[0] == 0.0 {
        return [0.0; 2];
    }
    let xi = input.reference[i];
    let ui = input.state[i];
    let vi = input.velocity[i];
    let (mut m, mut s) = (0.0, 0.0);
    for k in input.offsets[i] as usize..input.offsets[i + 1] as usize {
        let j = input.neighbours[k] as usize;
        if input.node[j][0] == 0.0 {
            continue;
        }
        let (_, y, v, bv) = pair(input, [xi, ui], vi, k, j);
        m += bv * (y[0] * y[0] + y[1] * y[1] + y[2] * y[2]);
        s += bv * (v[0] * y[0] + v[1] * y[1] + v[2] * y[2]);
    }
    if !(m > 0.0) {
        return [0.0; 2];
    }
    let eta = input.params.deviatoric * ni[1] * ni[2] * input.spacing;
    [3.0 * s / m, 15.0 * eta / m]
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
        let (xi_, y, v, bv) = pair(input, [xi, ui], vi, k, j);
        let vr = v[0] * y[0] + v[1] * y[1] + v[2] * y[2];
        if let (Some(di), Some(dj)) = (input.deviatoric.get(i), input.deviatoric.get(j)) {
            let py = (y[0] * y[0] + y[1] * y[1] + y[2] * y[2]).sqrt();
            if py > 0.0 && (di[1] > 0.0 || dj[1] > 0.0) {
                // t_ij + t_ji along ê = y/|y|, ė = v·y/|y| the same both ways.
                let rate = vr / py;
                let tij = di[1] * (rate - di[0] * py / 3.0);
                let tji = dj[1] * (rate - dj[0] * py / 3.0);
                let g = bv * (tij + tji) / py;
                for (fd, yd) in o.force.iter_mut().zip(y) {
                    *fd += g * yd;
                }
                // The node's own dissipation D_i = Σ β V t_ij ė_ij (module doc).
                o.heating += bv * tij * rate;
                o.damping += 4.0 * bv * (di[1] + dj[1]) / ni[3];
            }
        }
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
            deviatoric: &[],
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

    /// The deviatoric pass over `nodes` (all mutual neighbours, β = 1) at
    /// their reference positions with the given velocities; every node
    /// (a, ρ, c, ρ₀) = (6, 2000, 3000, 2000), h = 1 mm, only α_d on.
    fn deviatoric_cloud(
        reference: &[[f64; 4]],
        velocity: &[[f64; 3]],
        alpha_d: f64,
    ) -> (Vec<ViscousOut>, Vec<DeviatoricNode>) {
        let n = reference.len();
        let mut offsets = vec![0u32];
        let mut neighbours = Vec::new();
        for i in 0..n {
            neighbours.extend((0..n as u32).filter(|&j| j as usize != i));
            offsets.push(neighbours.len() as u32);
        }
        let factor = vec![1.0f32; neighbours.len()];
        let node = vec![[6.0, 2000.0, 3000.0, 2000.0]; n];
        let state = vec![[0.0; 4]; n];
        let mut input = ViscousInput {
            reference,
            state: &state,
            velocity,
            offsets: &offsets,
            neighbours: &neighbours,
            factor: &factor,
            node: &node,
            deviatoric: &[],
            spacing: 1e-3,
            params: GasViscosity {
                linear: 0.0,
                quadratic: 0.0,
                shear: 0.0,
                deviatoric: alpha_d,
            },
        };
        let dev: Vec<DeviatoricNode> = (0..n).map(|i| deviatoric_node(&input, i)).collect();
        input.deviatoric = &dev;
        let mut out = vec![ViscousOut::default(); n];
        viscous_forces(&input, &mut out);
        (out, dev)
    }

    /// Three mutual neighbours at (0, 0), (h, 0), (0, h) (h = 1 mm,
    /// V = 1e-9 m³) in the pure shear v = (a x, −a y, 0), a = 1e5 1/s,
    /// α_d = 0.1 (η = 0.1 · 2000 · 3000 · 1e-3 = 600 Pa·s), by hand:
    /// m₀ = 2e-15, θ̇₀ = 0, 15η/m₀ = 4.5e18; m₁ = m₂ = 3e-15 m⁵,
    /// θ̇₁ = +1e5, θ̇₂ = −1e5 1/s, 15η/m = 3e18. Pair (0, 1): ė = 100 m/s,
    /// t₀₁ = 4.5e18 · 100 = 4.5e20, t₁₀ = 3e18 (100 − 1e5 · 1e-3/3) =
    /// 2e20, force on 0: 1e-9 · 6.5e20 along +x = 6.5e11 N/m³; pair (0, 2)
    /// the mirror image along −y; pair (1, 2): ė = 0, t₁₂ = −t₂₁, no force.
    /// Heating D_i = Σ β V t_ij ė_ij: 9e13, 2e13, 2e13 W/m³; their sum
    /// times V is the power the forces take out, 1.3e5 W.
    #[test]
    fn deviatoric_term_by_hand() {
        let h = 1e-3;
        let reference = [
            [0.0, 0.0, 0.0, 1e-9],
            [h, 0.0, 0.0, 1e-9],
            [0.0, h, 0.0, 1e-9],
        ];
        let velocity = [[0.0; 3], [100.0, 0.0, 0.0], [0.0, -100.0, 0.0]];
        let (out, dev) = deviatoric_cloud(&reference, &velocity, 0.1);
        let close = |a: f64, b: f64| (a - b).abs() <= 1e-12 * b.abs().max(1.0);
        assert!(close(dev[0][0], 0.0) && close(dev[0][1], 4.5e18), "{dev:?}");
        assert!(close(dev[1][0], 1e5) && close(dev[1][1], 3e18), "{dev:?}");
        assert!(close(dev[2][0], -1e5) && close(dev[2][1], 3e18), "{dev:?}");
        let f = 6.5e11;
        for (o, e) in out
            .iter()
            .zip([[f, -f, 0.0], [-f, 0.0, 0.0], [0.0, f, 0.0]])
        {
            for d in 0..3 {
                assert!(
                    (o.force[d] - e[d]).abs() <= 1e-12 * f,
                    "{:?} vs {e:?}",
                    o.force
                );
            }
        }
        for (o, e) in out.iter().zip([9e13, 2e13, 2e13]) {
            assert!(close(o.heating, e), "{} vs {e}", o.heating);
            assert_eq!(o.stiffness, 0.0);
        }
        // Damping of node 0: 4 Σ_j β V (15η/m_0 + 15η/m_j)/ρ₀ = 3e7 1/s.
        assert!(close(out[0].damping, 3e7), "{}", out[0].damping);
        let power: f64 = out
            .iter()
            .zip(&velocity)
            .map(|(o, v)| 1e-9 * (0..3).map(|d| o.force[d] * v[d]).sum::<f64>())
            .sum();
        assert!(close(power, -1.3e5), "{power}");
        // Off: nothing at all.
        let (out, dev) = deviatoric_cloud(&reference, &velocity, 0.0);
        assert_eq!(dev, vec![[0.0; 2]; 3]);
        assert_eq!(out, vec![ViscousOut::default(); 3]);
    }

    fn cloud() -> impl Strategy<Value = (Vec<[f64; 4]>, Vec<[f64; 3]>)> {
        (3usize..8).prop_flat_map(|n| {
            (
                prop::collection::vec(
                    (
                        -2e-3..2e-3f64,
                        -2e-3..2e-3f64,
                        -2e-3..2e-3f64,
                        0.5e-9..2e-9f64,
                    )
                        .prop_map(|(x, y, z, v)| [x, y, z, v]),
                    n,
                ),
                prop::collection::vec(
                    (-300.0..300.0f64, -300.0..300.0f64, -300.0..300.0f64)
                        .prop_map(|(a, b, c)| [a, b, c]),
                    n,
                ),
            )
        })
    }

    /// Cross product.
    fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
        [
            a[1] * b[2] - a[2] * b[1],
            a[2] * b[0] - a[0] * b[2],
            a[0] * b[1] - a[1] * b[0],
        ]
    }

    use proptest::prelude::*;

    proptest! {
        /// The deviatoric term's contract on any cloud and motion: it
        /// conserves momentum and angular momentum, takes out exactly the
        /// power its heating books, each node's own dissipation is ≥ 0,
        /// and any uniform expansion with a rigid rotation (v = (θ̇/3) y +
        /// ω × y + v₀) feels nothing.
        #[test]
        fn deviatoric_term_conserves_and_dissipates((reference, velocity) in cloud(),
                                                    rate in -1e5..1e5f64,
                                                    spin in prop::array::uniform3(-1e5..1e5f64)) {
            let (out, _) = deviatoric_cloud(&reference, &velocity, 0.3);
            let scale: f64 = out
                .iter()
                .zip(&reference)
                .map(|(o, x)| x[3] * o.force.iter().map(|f| f.abs()).sum::<f64>())
                .sum::<f64>()
                .max(1e-300);
            let (mut momentum, mut angular) = ([0.0; 3], [0.0; 3]);
            let (mut power, mut heat) = (0.0, 0.0);
            for ((o, x), v) in out.iter().zip(&reference).zip(&velocity) {
                let r = [x[0], x[1], x[2]];
                let t = cross(r, o.force);
                for d in 0..3 {
                    momentum[d] += x[3] * o.force[d];
                    angular[d] += x[3] * t[d];
                    power += x[3] * o.force[d] * v[d];
                }
                heat += x[3] * o.heating;
                prop_assert!(o.heating >= -1e-12 * o.heating.abs().max(1.0), "{}", o.heating);
            }
            for d in 0..3 {
                prop_assert!(momentum[d].abs() <= 1e-12 * scale, "{momentum:?} {scale}");
                prop_assert!(angular[d].abs() <= 1e-12 * scale * 4e-3, "{angular:?} {scale}");
            }
            prop_assert!((power + heat).abs() <= 1e-10 * heat.abs().max(1e-300), "{power} {heat}");
            // Uniform expansion, rotation and translation.
            let rigid: Vec<[f64; 3]> = reference
                .iter()
                .map(|x| {
                    let w = cross(spin, [x[0], x[1], x[2]]);
                    [
                        rate / 3.0 * x[0] + w[0] + 10.0,
                        rate / 3.0 * x[1] + w[1] - 20.0,
                        rate / 3.0 * x[2] + w[2] + 5.0,
                    ]
                })
                .collect();
            let (out, dev) = deviatoric_cloud(&reference, &rigid, 0.3);
            let c = dev.iter().map(|d| d[1]).fold(0.0, f64::max);
            // Forces of the size round-off leaves: 15η/m · V · |v| ~ c 1e-9 · 1e-12 · 1e3.
            for o in &out {
                for d in 0..3 {
                    prop_assert!(o.force[d].abs() <= c * 1e-9 * 1e-9, "{:?} (c {c})", o.force);
                }
            }
            for (d, x) in dev.iter().zip(&reference) {
                let _ = x;
                prop_assert!((d[0] - rate).abs() <= 1e-9 * rate.abs().max(1.0) + 1e-6, "{} vs {rate}", d[0]);
            }
        }
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
        let v = GasViscosity {
            deviatoric: f64::INFINITY,
            ..GasViscosity::default()
        };
        assert!(v
            .validate()
            .unwrap_err()
            .contains("gas_viscosity.deviatoric"));
    }
}
