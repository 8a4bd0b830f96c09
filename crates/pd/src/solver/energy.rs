//! The energy budget of a [`PdSolver`]: what the bonds, the products,
//! the contacts and the motion hold, and what the viscosity has
//! dissipated (the run summary's energy balance).

use super::*;

impl PdSolver {
    /// Elastic energy stored in the bonds of proportional solids, J:
    /// Σ_i V_i · ½ Σ_j w V_j with the micro-potential w = r ∫ g ds (eq 6).
    ///
    /// On a run spread over MPI ranks this is a collective call (it
    /// gathers the plastic stretches).
    pub fn bond_energy(&self) -> f64 {
        let plastic_stretch = self.gathered_plastic();
        let mut total = 0.0;
        for i in 0..self.node_count() {
            let BondLaw::Solid {
                micromodulus,
                yield_stretch,
                plastic,
                ..
            } = self.laws[self.material[i] as usize]
            else {
                continue;
            };
            let xi = self.reference[i];
            let ui = self.state[i];
            let mut w_sum = 0.0;
            for k in self.families.row(i) {
                let w = self.factor[k] as f64;
                if w == 0.0 {
                    continue;
                }
                let j = self.families.neighbours[k] as usize;
                let xj = self.reference[j];
                let uj = self.state[j];
                let r = distance([xi[0], xi[1], xi[2]], [xj[0], xj[1], xj[2]]);
                let p = distance(
                    [xi[0] + ui[0], xi[1] + ui[1], xi[2] + ui[2]],
                    [xj[0] + uj[0], xj[1] + uj[1], xj[2] + uj[2]],
                );
                let s = (p - r) / r;
                let e = if plastic {
                    s - plastic_stretch[k] as f64
                } else {
                    s
                };
                let a = e.abs();
                let psi = if plastic || a <= yield_stretch {
                    0.5 * a * a
                } else {
                    yield_stretch * (a - 0.5 * yield_stretch)
                };
                w_sum += micromodulus * w * r * psi * xj[3];
            }
            total += 0.5 * xi[3] * w_sum;
        }
        total
    }

    /// Energy the bonds of proportional solids have dissipated since the
    /// start, J: the plastic work of micro-plastic bonds (c β r s_Y |Δs_p|
    /// V_i V_j per yielding pass) and the energy [`Self::bond_energy`]
    /// counted in each bond when it broke. With it the run's total energy
    /// (kinetic, bond, products, contact and this) is conserved up to the
    /// time integration; 0 when no bond can yield plastically or break.
    pub fn dissipated_energy(&self) -> f64 {
        self.dissipated
    }

    /// Adds the last force pass's per-node dissipation to the total, in
    /// node order (the same bits on any thread or rank count: every rank
    /// holds every node's value after `share_forces`).
    pub(crate) fn book_dissipation(&mut self) {
        let mut step = 0.0;
        for &d in &self.dissipated_node {
            step += d as f64;
        }
        self.dissipated += step;
    }

    /// Energy stored in the products (Σ W(X_i/X_d,i) V_i over detonated
    /// gas nodes, with the viscous heat (ΔC_i/ω)(X_i/X_d,i)^{−ω} V_i, see
    /// `products_pressure`) and chemical energy not yet released
    /// (W(1) V_i), J.
    pub fn gas_energy(&self) -> f64 {
        (0..self.node_count())
            .map(|i| match self.materials[self.material[i] as usize] {
                PdMaterial::Gas(g) => {
                    let [x, _, xd, heat] = self.gas[i];
                    let y = if detonated(self.time, self.detonation_time[i]) && xd > 0.0 {
                        x / xd
                    } else {
                        1.0
                    };
                    let reactant = match g.reactant {
                        Some(r) if xd <= 0.0 => r.energy(x),
                        _ => 0.0,
                    };
                    let w = g.isentrope.energy(y)
                        + reactant
                        + if heat != 0.0 {
                            let e = heat_exponent(&g);
                            heat / e * y.powf(-e)
                        } else {
                            0.0
                        };
                    w * self.reference[i][3]
                }
                _ => 0.0,
            })
            .sum()
    }

    /// Energy stored in the short-range contacts, J: the pair potential of
    /// eq 27 over the pairs closer than their contact distance
    /// ([`crate::contact::contact_energies`]); 0 with contact off. Summed node by node in
    /// node order, so it has the same bits for any thread count.
    pub fn contact_energy(&self) -> f64 {
        let Some(params) = self.contact_params() else {
            return 0.0;
        };
        // A list of its own: the solver's bins the positions of the last
        // force pass, which may not be the current ones.
        let mut cells = CellList::default();
        bin_positions(&mut cells, &self.reference, &self.state, &params);
        let mut per_node = vec![0.0; self.node_count()];
        energies(&self.contact_input(), &cells, &params, &mut per_node);
        per_node.iter().sum()
    }

    /// Kinetic energy, J.
    pub fn kinetic_energy(&self) -> f64 {
        (0..self.node_count())
            .map(|i| {
                let v = self.velocity[i];
                0.5 * self.mass(i) * (v[0] * v[0] + v[1] * v[1] + v[2] * v[2])
            })
            .sum()
    }
}
