//! [`PdSolver`]: meshfree bond-based peridynamics behind the core `Solver`
//! trait (seed 004).
//!
//! One step (velocity form of the central difference eq 10, i.e. velocity
//! Verlet, identical to eq 10 for a constant step):
//!
//! 1. v ← v + ½Δt a;  prescribed velocity components are imposed;
//! 2. u ← u + Δt v;
//! 3. node scalars: effective critical stretch of solid nodes (damage- and
//!    minimum-stretch refinements), gas expansion X (eq 17), pressure
//!    P_S(X) (eqs 29–30) of nodes past their detonation time;
//! 4. bond forces (eq 9: Σ_j f V_j with eqs 8 and 19), short-range forces
//!    (eq 27), body force b: a = (Σ f V_j + f_SR + b)/ρ;
//! 5. v ← v + ½Δt a; prescribed velocities imposed again.
//!
//! The stable step (eq 24) is min_i √(2ρ_i / Σ_k V_k C_ik) times a safety
//! factor, with C = c/r for proportional bonds (eq 22), |∂f/∂p| of eq 19 for
//! gas bonds (eq 26) with ρ = ρ₀/X (eq 25), and the contact stiffness of
//! the pairs near contact with the node's own ρ₀ (the terms add as
//! stiffness/density); it is recomputed every step.

use crate::cell_list::CellList;
use crate::contact::{
    bin_positions, energies, forces_in, ContactInput, ContactParams, ContactParts,
};
use crate::family::{Families, ForeignBonds, OneSidedPairs};
use crate::forces::{
    bond_forces_dissipating_in, for_each_node, for_each_node_in, for_each_node_pair_in,
    gas_expansion_closing, one_sided_gas_reaction, wall_sum_change, BondLaw, ForceInput, GasRow,
    NodeForce,
};
use crate::fragments::{find_fragments, write_cmd_csv, write_fragments_csv, Fragment};
use crate::material::PdMaterial;
use crate::viscosity::{
    deviatoric_node, viscous_forces_in, DeviatoricNode, GasViscosity, ViscousInput, ViscousNode,
    ViscousOut,
};
use brisance_core::SolverError;
use brisance_core::{ReactionModel, ReactionState};
use brisance_reaction::ProgramBurn;
use rayon::prelude::*;
use std::path::Path;

/// Whether a node whose detonation time is `detonation_time` has burnt by
/// `time`: program burn's burn fraction ([`ProgramBurn`] through the
/// [`ReactionModel`] trait, seed 004's volume burn F = H(t − t_det)) is 1.
/// Every gate of the solver on a node's detonation asks this.
#[inline(always)]
fn detonated(time: f64, detonation_time: f64) -> bool {
    let state = ReactionState {
        time,
        detonation_time,
        surface_area_density: 0.0,
        ..ReactionState::default()
    };
    ProgramBurn.advance(&state, 0.0, 0.0) >= 1.0
}

/// Until the front has run one horizon past the last explosive node (last
/// detonation time + δ/D), the step is at most this fraction of h/D: the
/// program-burn front crosses at most a quarter of a spacing per step, as
/// programmed-burn hydrocodes limit the step so that the front does not
/// skip cells. A node's gas forces switch on at the first
/// step end past its detonation time, all at once; with the step of eq 24
/// alone the front crossed 1.7 spacings per step in a TNT block (h = 1 mm)
/// and the total energy grew by 8 % during the burn (2 % at half that
/// step, 0.2 % at an eighth: an integration error).
pub const BURN_STEP_FRACTION: f64 = 0.25;

/// The default of [`PdOptions::closing_step_fraction`]: a products
/// node's step is at most this fraction of the shortest closing time p/ṗ
/// over its family (the current distance of a pair over
/// the speed at which it closes): no pair of products nodes closes more
/// than a quarter of its gap in one step. Eq 24 sizes the step from the
/// stiffness at the start of the step; a pair closing fast enough raises
/// that stiffness within the step (the pair force of eq 19 grows as r/p²
/// and X falls with p), which eq 24 sees only a step late. In the 12 cm
/// copper tube at h = 1.3 mm eight products nodes by the open end were
/// crushed in one step (X 0.715, 20.8 GPa, a step 16 times the one their
/// new stiffness allowed) and the total energy jumped by 3.8 % of the
/// initial (docs/physics/pd/gas.md, "Closing pairs"). A relative-motion
/// bound of this kind is what particle methods add to the Courant
/// condition (Monaghan 1992, Annu. Rev. Astron. Astrophys. 30, 543, the
/// SPH step's v_sig/h term).
pub const CLOSING_STEP_FRACTION: f64 = 0.25;

/// Meshfree bond-based peridynamics.
#[derive(Debug)]
pub struct PdSolver {
    options: PdOptions,
    horizon: f64,
    materials: Vec<PdMaterial>,
    laws: Vec<BondLaw>,
    bulk_modulus: Vec<f64>,
    breakable: Vec<bool>,
    // Per node, fixed.
    reference: Vec<[f64; 4]>,
    body: Vec<u32>,
    material: Vec<u16>,
    /// ρ₀ per material (not per node).
    material_density: Vec<f64>,
    /// Per node, fixed: the family volume Σ β V_j of a gas node (eq 17),
    /// the bond stiffness Σ c β V_j / r of a solid node (eq 22).
    node_scale: Vec<f64>,
    detonation_time: Vec<f64>,
    /// The last finite detonation time plus δ/D, s (−∞ without explosive):
    /// the end of the burn-limited steps.
    burn_end: f64,
    /// The largest step while explosive is still to detonate,
    /// [`BURN_STEP_FRACTION`] h / D, s.
    burn_step: f64,
    prescribed: Vec<(u32, u8, f64)>,
    families: Families,
    /// Per solid node, the products nodes whose families hold it
    /// ([`ProductsFamily::WithSolids`]); empty otherwise.
    one_sided: OneSidedPairs,
    /// Per products node, the positions in its row of its solid
    /// neighbours ([`ProductsFamily::MirroredWall`]: the wall pairs step 3
    /// books the work of); empty otherwise.
    wall_bonds: ForeignBonds,
    // Per node, evolving.
    time: f64,
    steps: u64,
    state: Vec<[f64; 4]>,
    velocity: Vec<[f64; 3]>,
    bond_out: Vec<NodeForce>,
    /// Per node, the energy its bonds dissipated in the last force pass
    /// (plastic work and what breaking bonds held, J;
    /// [`bond_forces_dissipating_in`]); empty when no bond can yield
    /// plastically or break.
    dissipated_node: Vec<f32>,
    /// The energy the bonds dissipated since the start, J: the steps'
    /// sums of `dissipated_node` in node order.
    dissipated: f64,
    /// Contact force and stiffness per node; empty when contact is off.
    contact: Vec<([f64; 3], f64)>,
    /// (X, gas stiffness, X_d, ΔC) per node, X_d the expansion at the
    /// node's detonation (0 before it), ΔC the heat the artificial
    /// viscosity returned to its products (`products_pressure`); empty when
    /// no material is a gas.
    gas: Vec<[f64; 4]>,
    /// Per node, the shortest closing time p/ṗ over its products family
    /// at the last step 3 (∞ when no pair closes; [`CLOSING_STEP_FRACTION`]);
    /// empty when no material is a gas or the limit is off.
    closing: Vec<f64>,
    /// Artificial viscosity of the products (None: off).
    viscosity: Option<GasViscosity>,
    /// Per node (a, ρ, c, ρ₀) for the viscous pass; empty when it is off.
    viscous_node: Vec<ViscousNode>,
    /// Viscous force, heating, damping and stiffness per node; empty when
    /// the viscosity is off.
    viscous: Vec<ViscousOut>,
    /// Heat per unit volume of the last half kick's viscous work; empty
    /// when the viscosity is off.
    kick_heat: Vec<f64>,
    /// Per node (θ̇, 15η/m) of the deviatoric viscosity at the last force
    /// pass; empty when that term is off.
    deviatoric: Vec<DeviatoricNode>,
    /// Whether the products' force on explosive not yet detonated is left
    /// out (`program_burn.md`).
    hold_unreacted: bool,
    /// Per material: a gas with a reactant (never held).
    has_reactant: Vec<bool>,
    /// Per node, fixed: the strength factor of a spread critical stretch
    /// (`strength.rs`); empty when no material has one (factor 1).
    strength: Vec<f64>,
    // Per bond.
    factor: Vec<f32>,
    plastic: Vec<f32>,
    cells: CellList,
    /// The nodes this rank evaluates, on a run spread over MPI ranks
    /// (`ranks.rs`).
    ranks: ranks::Ranks,
}

impl PdSolver {
    /// The fields [`Solver::sample`] knows (gauges sample the node nearest
    /// the gauge point).
    ///
    /// [`Solver::sample`]: brisance_core::Solver::sample
    pub const FIELDS: [&'static str; 10] = [
        "displacement_x",
        "displacement_y",
        "displacement_z",
        "velocity_x",
        "velocity_y",
        "velocity_z",
        "radial_displacement",
        "damage",
        "pressure",
        "expansion",
    ];

    /// Sets the products' artificial viscosity (`viscosity.rs`; None: off,
    /// the default of [`PdSolver::new`], chosen from the measurements in
    /// `docs/physics/pd/gas.md`) and evaluates the forces of the current
    /// state again. Nothing is allocated when no material is a gas.
    pub fn set_gas_viscosity(
        &mut self,
        viscosity: Option<GasViscosity>,
    ) -> Result<(), PdSetupError> {
        if let Some(v) = viscosity {
            v.validate().map_err(|e| invalid("gas_viscosity", e))?;
        }
        let n = self.node_count();
        let on = viscosity.is_some() && !self.gas.is_empty();
        self.viscosity = if on { viscosity } else { None };
        self.viscous_node = vec![[0.0; 4]; if on { n } else { 0 }];
        self.viscous = vec![ViscousOut::default(); if on { n } else { 0 }];
        self.kick_heat = vec![0.0; if on { n } else { 0 }];
        let deviatoric = on && viscosity.is_some_and(|v| v.deviatoric > 0.0);
        self.deviatoric = vec![[0.0; 2]; if deviatoric { n } else { 0 }];
        self.update_node_scalars();
        self.compute_forces();
        Ok(())
    }

    /// Whether the products' force on explosive not yet detonated is left
    /// out (true, the default) or applied as eq 19 gives it (false: the
    /// pair force stays odd, eq 2, so momentum is conserved through the
    /// burn). See `docs/physics/pd/program_burn.md`.
    pub fn set_hold_unreacted(&mut self, hold: bool) {
        self.hold_unreacted = hold;
    }

    /// Short-range forces (eq 27) between the nodes of one explosive charge
    /// given with a reactant, with its K₀ = 1/κ in k_PD (`contact.rs`);
    /// off by default (then products nodes of one charge have none). Has
    /// no effect without contact or on explosives without a reactant.
    /// Evaluates the forces of the current state again.
    pub fn set_products_contact(&mut self, on: bool) {
        for (k, m) in self.bulk_modulus.iter_mut().zip(&self.materials) {
            *k = match m {
                PdMaterial::Gas(g) if on => g.reactant.map_or(0.0, |r| 1.0 / r.kappa),
                _ => m.contact_bulk_modulus(),
            };
        }
        self.update_node_scalars();
        self.compute_forces();
    }

    /// The products' artificial viscosity (None: off).
    pub fn gas_viscosity(&self) -> Option<GasViscosity> {
        self.viscosity
    }

    /// Heat added to the products above the isentropes the nodes detonated
    /// on, J: Σ_i (ΔC_i/ω) (X_i/X_d,i)^{−ω} V_i, the part of `gas_energy`
    /// that the artificial viscosity returned plus, for an explosive with a
    /// reactant, the compression energy its unreacted nodes held when they
    /// detonated, and with a mirrored wall ([`ProductsFamily::MirroredWall`])
    /// the work of the wall pairs' second half (negative while the case
    /// recedes).
    pub fn viscous_heat(&self) -> f64 {
        (0..self.gas.len())
            .map(|i| match self.materials[self.material[i] as usize] {
                PdMaterial::Gas(g) if self.gas[i][3] != 0.0 => {
                    let [x, _, xd, heat] = self.gas[i];
                    let w = heat_exponent(&g);
                    heat / w * (x / xd).powf(-w) * self.reference[i][3]
                }
                _ => 0.0,
            })
            .sum()
    }

    /// Number of nodes.
    pub fn node_count(&self) -> usize {
        self.reference.len()
    }

    /// Number of directed bonds (each bond once per node).
    pub fn bond_count(&self) -> usize {
        self.families.bond_count()
    }

    /// Heap memory of the solver, from the capacities of its arrays. The
    /// contact cell list keeps its buffers private (`cell_list.rs`); they
    /// are counted as the contact pass sizes them for n points
    /// ([`CellList::bytes_for`]: a bucket table of the power of two
    /// ≥ max(2n, 64) plus one `u32` starts, two `u32` and the kept current
    /// position per point).
    pub fn memory_use(&self) -> PdMemory {
        let n = self.node_count();
        let cells = if self.options.contact.is_some() {
            CellList::bytes_for(n, true)
        } else {
            0
        };
        let node_bytes = heap(&self.reference)
            + heap(&self.body)
            + heap(&self.material)
            + heap(&self.node_scale)
            + heap(&self.detonation_time)
            + heap(&self.families.offsets)
            + heap(&self.state)
            + heap(&self.velocity)
            + heap(&self.bond_out)
            + heap(&self.dissipated_node)
            + heap(&self.contact)
            + heap(&self.gas)
            + heap(&self.closing)
            + heap(&self.viscous_node)
            + heap(&self.viscous)
            + heap(&self.kick_heat)
            + heap(&self.deviatoric)
            + cells;
        let bond_bytes = heap(&self.families.neighbours) + heap(&self.factor) + heap(&self.plastic);
        let other_bytes = heap(&self.materials)
            + heap(&self.laws)
            + heap(&self.bulk_modulus)
            + heap(&self.breakable)
            + heap(&self.has_reactant)
            + heap(&self.material_density)
            + heap(&self.prescribed)
            + heap(&self.one_sided.offsets)
            + heap(&self.one_sided.partner)
            + heap(&self.one_sided.bond)
            + heap(&self.wall_bonds.offsets)
            + heap(&self.wall_bonds.bond);
        PdMemory {
            nodes: n,
            bonds: self.bond_count(),
            node_bytes,
            bond_bytes,
            other_bytes,
        }
    }

    /// The horizon δ, m.
    pub fn horizon(&self) -> f64 {
        self.horizon
    }

    /// Reference positions and volumes (x, V).
    pub fn reference(&self) -> &[[f64; 4]] {
        &self.reference
    }

    /// Displacements u.
    pub fn displacement(&self, i: usize) -> [f64; 3] {
        let s = self.state[i];
        [s[0], s[1], s[2]]
    }

    /// Velocities.
    pub fn velocities(&self) -> &[[f64; 3]] {
        &self.velocity
    }

    /// Sets every node's velocity from its reference position (an initial
    /// condition beyond the bodies' uniform velocities); prescribed
    /// components keep their prescribed values.
    pub fn set_velocities(&mut self, field: impl Fn([f64; 3]) -> [f64; 3]) {
        for (v, x) in self.velocity.iter_mut().zip(&self.reference) {
            *v = field([x[0], x[1], x[2]]);
        }
        self.impose_velocities();
        // The viscous force and the products' closing times depend on the
        // velocities.
        self.viscous_pass();
        self.share_viscous();
        if !self.closing.is_empty() {
            self.update_closing();
            self.share_node_scalars();
        }
    }

    /// Body index per node.
    pub fn bodies(&self) -> &[u32] {
        &self.body
    }

    /// Material index per node.
    pub fn materials(&self) -> &[u16] {
        &self.material
    }

    /// Node masses ρ₀V, kg.
    pub fn mass(&self, i: usize) -> f64 {
        self.material_density[self.material[i] as usize] * self.reference[i][3]
    }

    /// Current position x + u of node i, m.
    pub fn current_position(&self, i: usize) -> [f64; 3] {
        let (x, u) = (self.reference[i], self.state[i]);
        [x[0] + u[0], x[1] + u[1], x[2] + u[2]]
    }

    /// Detonation time per node (infinite for inert or unreached nodes), s.
    pub fn detonation_times(&self) -> &[f64] {
        &self.detonation_time
    }

    /// Expansion X of node i (eq 17; 1 for solids).
    pub fn expansion(&self, i: usize) -> f64 {
        self.gas.get(i).map_or(1.0, |g| g[0])
    }

    /// The families.
    pub fn families(&self) -> &Families {
        &self.families
    }

    /// Whether bond `k` (position in the rows) is intact.
    pub fn bond_intact(&self, k: usize) -> bool {
        self.factor[k] != 0.0
    }

    /// The strength factor of node i's critical stretch (`strength.rs`):
    /// 1 unless its material has a spread critical stretch.
    pub fn strength_factor(&self, i: usize) -> f64 {
        self.strength.get(i).copied().unwrap_or(1.0)
    }

    /// Node damage: the broken fraction of its bonds (0 for gas nodes and
    /// nodes without bonds).
    pub fn damage(&self, i: usize) -> f64 {
        let total = self.families.row(i).len();
        if total == 0 || !self.breakable[self.material[i] as usize] {
            return 0.0;
        }
        1.0 - self.bond_out[i].intact as f64 / total as f64
    }

    /// Current force per unit volume on node i (bonds + contact + body), N/m³.
    pub fn force_density(&self, i: usize) -> [f64; 3] {
        let b = self.bond_out[i].force;
        let c = self.contact.get(i).map_or([0.0; 3], |c| c.0);
        std::array::from_fn(|d| b[d] + c[d] + self.options.body_force[d])
    }

    /// Gas pressure P_S(X/X_d)/X_d of node i; before detonation the
    /// reactant's P_u(X) (0 without a reactant); 0 for solids. Pa.
    pub fn pressure(&self, i: usize) -> f64 {
        match self.materials[self.material[i] as usize] {
            PdMaterial::Gas(g)
                if detonated(self.time, self.detonation_time[i]) || g.reactant.is_some() =>
            {
                let [x, _, xd, heat] = self.gas[i];
                node_pressure(&g, x, xd, heat).0
            }
            _ => 0.0,
        }
    }

    /// Fragments: connected components of solid nodes over intact bonds.
    pub fn fragments(&self) -> Vec<Fragment> {
        let solid = self.solid_nodes();
        let mass: Vec<f64> = (0..self.node_count()).map(|i| self.mass(i)).collect();
        find_fragments(&self.families, &self.factor, &solid, &mass, &self.velocity)
    }

    /// Breaks every bond whose two nodes' reference positions satisfy
    /// `crosses` (a pre-crack or a notch: e.g. the bonds that cross a
    /// plane). Broken bonds stay broken, as bonds broken by stretch.
    pub fn break_bonds(&mut self, crosses: impl Fn([f64; 3], [f64; 3]) -> bool) {
        let at = |r: [f64; 4]| [r[0], r[1], r[2]];
        for i in 0..self.node_count() {
            for k in self.families.row(i) {
                let j = self.families.neighbours[k] as usize;
                if crosses(at(self.reference[i]), at(self.reference[j])) {
                    self.factor[k] = 0.0;
                }
            }
        }
    }

    /// The fragment of every node: the label (smallest node index) of
    /// the fragment it belongs to, `usize::MAX` for nodes that are not
    /// solid ([`crate::fragments::fragment_labels`]).
    pub fn fragment_labels(&self) -> Vec<usize> {
        crate::fragments::fragment_labels(&self.families, &self.factor, &self.solid_nodes())
    }

    /// Per node: whether its material can break (the nodes fragments are
    /// made of).
    fn solid_nodes(&self) -> Vec<bool> {
        self.material
            .iter()
            .map(|&m| self.breakable[m as usize])
            .collect()
    }

    fn has_breakable_nodes(&self) -> bool {
        self.material.iter().any(|&m| self.breakable[m as usize])
    }

    /// Writes the current fragments and their CMD into `dir`.
    fn write_fragment_files(
        &self,
        dir: &Path,
        fragments: &str,
        cmd: &str,
    ) -> Result<(), SolverError> {
        let f = self.fragments();
        let io = |file: &str, e: std::io::Error| {
            SolverError::Other(format!(
                "peridynamics: cannot write {}: {e}",
                dir.join(file).display()
            ))
        };
        write_fragments_csv(&dir.join(fragments), &f).map_err(|e| io(fragments, e))?;
        write_cmd_csv(&dir.join(cmd), &f).map_err(|e| io(cmd, e))
    }

    /// Whether node i is explosive not yet reached by the detonation at the
    /// current time (its products' forces are not applied to it).
    pub fn is_unreacted(&self, i: usize) -> bool {
        matches!(self.laws[self.material[i] as usize], BondLaw::Gas)
            && !detonated(self.time, self.detonation_time[i])
    }

    /// Half a velocity update, v ← v + Δt_half (f_bond + f_SR + b)/ρ₀, at
    /// the current time. Unreacted explosive: the bond (gas) force is left
    /// out. Seed 004 makes a node's gas forces switch on at its detonation
    /// time and starts its products from the reference state of the volume
    /// burn (X = 1, eqs 20–21); the detonation front outruns every signal
    /// in the explosive ahead of it, which stays undisturbed until the
    /// front arrives. With a horizon δ the products reach δ ahead of the
    /// front and would push those nodes with nothing resisting (doing work
    /// that the volume burn never accounts for, more as h falls); so the
    /// push on an unreacted node is not applied — it keeps its velocity
    /// (short-range forces and body forces still act on it). The products
    /// still feel the unreacted explosive through their own half of the
    /// pair force, as on a wall. See `docs/physics/pd/program_burn.md`.
    ///
    /// With the products' artificial viscosity on, its force f_v joins the
    /// bond force, and the kinetic energy it removed in this half kick is
    /// added to the node's products as heat at its current expansion
    /// (`products_pressure`). The kick changes a node's kinetic energy by
    /// exactly V Δt_half f·v̄ (v̄ the mean of the velocities before and
    /// after it, f the total force per unit volume), so the viscous share
    /// is V Δt_half f_v·v̄ and the heat per unit volume
    /// dq = −Δt_half f_v·v̄: the viscosity conserves the total energy to
    /// round-off whatever the step. (A node pushed by an approaching
    /// neighbour gains kinetic energy and loses that much heat; the pair
    /// together always dissipates, see `viscosity.rs`.)
    fn kick(&mut self, half: f64) {
        let body_force = self.options.body_force;
        let density = &self.material_density;
        let material = &self.material;
        let bond_out = &self.bond_out;
        let contact = &self.contact;
        let viscous = &self.viscous;
        let laws = &self.laws;
        let detonation_time = &self.detonation_time;
        let time = self.time;
        let hold = self.hold_unreacted;
        let has_reactant = &self.has_reactant;
        let update = |i: usize, v: &mut [f64; 3]| {
            let m = material[i] as usize;
            let unreacted = hold
                && matches!(laws[m], BondLaw::Gas)
                && !detonated(time, detonation_time[i])
                && !has_reactant[m];
            let mut b = if unreacted {
                [0.0; 3]
            } else {
                bond_out[i].force
            };
            if let Some(q) = viscous.get(i) {
                for (bd, qd) in b.iter_mut().zip(q.force) {
                    *bd += qd;
                }
            }
            let c = contact.get(i).map_or([0.0; 3], |c| c.0);
            let rho = density[m];
            for d in 0..3 {
                v[d] += half * (b[d] + c[d] + body_force[d]) / rho;
            }
        };
        if self.viscous.is_empty() {
            for_each_node(&mut self.velocity, update);
            return;
        }
        self.velocity
            .par_iter_mut()
            .zip(self.kick_heat.par_iter_mut())
            .enumerate()
            .with_min_len(256)
            .for_each(|(i, (v, dq))| {
                let before = *v;
                update(i, v);
                let f = viscous[i].force;
                *dq = -half * (0..3).map(|d| f[d] * 0.5 * (before[d] + v[d])).sum::<f64>();
            });
        let materials = &self.materials;
        let kick_heat = &self.kick_heat;
        for_each_node(&mut self.gas, |i, g| {
            let dq = kick_heat[i];
            if dq == 0.0 || g[2] <= 0.0 {
                return;
            }
            if let PdMaterial::Gas(gas) = materials[material[i] as usize] {
                // W gains (ΔC/ω) y^{−ω}: ΔC grows by ω y^ω dq at fixed y.
                let w = heat_exponent(&gas);
                let y = g[0] / g[2];
                g[3] += w * y.powf(w) * dq;
            }
        });
    }

    fn impose_velocities(&mut self) {
        for &(i, d, v) in &self.prescribed {
            self.velocity[i as usize][d as usize] = v;
        }
    }

    /// Step 3: effective critical stretch of solid nodes, gas expansion
    /// (eq 17) and the gas coefficient 6 P X^{4/3}/V of eq 19.
    ///
    /// A solid node's critical stretch is
    /// s_c = s_c0 (1 + α_D φ) − α_min min(s_min, 0), with φ its damage and
    /// s_min the smallest stretch of its intact bonds, both from the last
    /// force pass: the damage-stretch and minimum-stretch coefficient
    /// models of seed 004 footnote c, which names them without a formula
    /// or a reference. The minimum-stretch term is the form of Silling &
    /// Askari 2005 (seed 004 ref 3); the linear damage term is Brisance's
    /// choice, with no source (`material.rs`, `bond_based.md`).
    fn update_node_scalars(&mut self) {
        self.update_node_scalars_moved(0.0);
    }

    /// Step 3 after a drift of `dt` (0 when the state is only evaluated
    /// again): with a mirrored wall ([`ProductsFamily::MirroredWall`]) each
    /// products node also pays the work its wall pairs' second half did
    /// over the drift (`wall_work`).
    fn update_node_scalars_moved(&mut self, dt: f64) {
        let mirror = dt > 0.0 && self.options.products_family.mirrors_walls();
        let laws = &self.laws;
        let reference = &self.reference;
        let state = &self.state;
        let families = &self.families;
        let wall_bonds = &self.wall_bonds;
        let factor = &self.factor;
        let material = &self.material;
        let materials = &self.materials;
        let family_volume = &self.node_scale;
        let time = self.time;
        let detonation_time = &self.detonation_time;
        let own = self.ranks.nodes();
        let gas_nodes = if self.gas.is_empty() {
            0..0
        } else {
            own.clone()
        };
        let velocity = &self.velocity;
        // The products' state, and in the same pass over the family the
        // shortest closing time at the half-step velocities the nodes were
        // just moved with (`CLOSING_STEP_FRACTION`), when that limit is on.
        let update = |i: usize, g: &mut [f64; 4], closing: Option<&mut f64>| {
            let PdMaterial::Gas(gas) = materials[material[i] as usize] else {
                if let Some(c) = closing {
                    *c = f64::INFINITY;
                }
                return;
            };
            let row = families.row(i);
            let vf = family_volume[i];
            let gas_row = GasRow {
                reference,
                state,
                velocity: closing.is_some().then_some(&velocity[..]),
                neighbours: &families.neighbours[row.clone()],
                factor: &factor[row.clone()],
                family_volume: vf,
            };
            let (x, s3, s4, c) = gas_expansion_closing(i, &gas_row);
            if let Some(out) = closing {
                *out = c;
            }
            // The expansion at detonation, fixed once the node has
            // detonated (`products_pressure`).
            let xd = if g[2] > 0.0 {
                g[2]
            } else if detonated(time, detonation_time[i]) {
                x
            } else {
                0.0
            };
            // Detonating now: the compression energy the reactant
            // holds, W_u(X_d) per unit reference volume, passes to the
            // products as heat at y = 1 (ΔC = ω W_u), so the switch
            // keeps the node's energy.
            let mut heat = g[3];
            if g[2] <= 0.0 && xd > 0.0 {
                if let Some(r) = gas.reactant {
                    heat += heat_exponent(&gas) * r.energy(xd);
                }
            }
            let x43 = x.powf(4.0 / 3.0);
            if mirror {
                // The work of the wall pairs' second half over the drift,
                // per unit reference volume: ¼ (c_i^n + c_i^{n+1}) ΔS_wall
                // (trapezoidal in c_i, as the kicks are in the force),
                // taken as heat at fixed y (y = 1 before detonation, where
                // it waits in ΔC until the node detonates).
                let ds = wall_sum_change(
                    i,
                    reference,
                    state,
                    velocity,
                    dt,
                    wall_bonds.row(i).iter().map(|&k| {
                        let k = k as usize;
                        (families.neighbours[k], factor[k])
                    }),
                    material,
                    laws,
                );
                if ds != 0.0 {
                    let c_new = 6.0 * node_pressure(&gas, x, xd, heat).0 * x43 / vf;
                    let dq = 0.25 * (state[i][3] + c_new) * ds;
                    let w = heat_exponent(&gas);
                    let y = if xd > 0.0 { x / xd } else { 1.0 };
                    heat += w * y.powf(w) * dq;
                }
            }
            // Eq 26: |∂f/∂p| of eq 19 at the current state, directly
            // through p and through X(p) (eq 17).
            let (p, dp) = node_pressure(&gas, x, xd, heat);
            let dq = (dp * x43 + 4.0 / 3.0 * p * x.powf(1.0 / 3.0)).abs();
            let stiff =
                12.0 * p.abs() * x43 / vf * s3 + 18.0 * dq * x43 * reference[i][3] / (vf * vf) * s4;
            *g = [x, stiff, xd, heat];
        };
        if self.closing.is_empty() {
            for_each_node_in(&mut self.gas, gas_nodes, |i, g| update(i, g, None));
        } else {
            for_each_node_pair_in(&mut self.gas, &mut self.closing, gas_nodes, |i, g, c| {
                update(i, g, Some(c))
            });
        }
        let gas = &self.gas;
        if !self.viscous_node.is_empty() {
            // The viscous pass's node data: a = 6 X^{4/3}/V, ρ = ρ₀/X and
            // the sound speed c² = dP/dρ = −X² (dP/dX)/ρ₀ of detonated
            // products (eq 25's density); a = 0 elsewhere.
            for_each_node_in(&mut self.viscous_node, own.clone(), |i, o| {
                *o = match materials[material[i] as usize] {
                    PdMaterial::Gas(g) if detonated(time, detonation_time[i]) => {
                        let [x, _, xd, heat] = gas[i];
                        let dp = products_pressure(&g, x, xd, heat).1;
                        let c2 = (-x * x * dp / g.density).max(0.0);
                        [
                            6.0 * x.powf(4.0 / 3.0) / family_volume[i],
                            g.density / x,
                            c2.sqrt(),
                            g.density,
                        ]
                    }
                    _ => [0.0; 4],
                };
            });
        }
        let bond_out = &self.bond_out;
        let strength = &self.strength;
        for_each_node_in(&mut self.state, own, |i, s| {
            match materials[material[i] as usize] {
                PdMaterial::Gas(g) => {
                    // Before detonation: the reactant's P_u(X), or 0
                    // without one (`node_pressure`).
                    let [x, _, xd, heat] = gas[i];
                    s[3] = if detonated(time, detonation_time[i]) || g.reactant.is_some() {
                        6.0 * node_pressure(&g, x, xd, heat).0 * x.powf(4.0 / 3.0)
                            / family_volume[i]
                    } else {
                        0.0
                    };
                }
                PdMaterial::Proportional(p) => {
                    let total = families.row(i).len();
                    let damage = if total == 0 {
                        0.0
                    } else {
                        1.0 - bond_out[i].intact as f64 / total as f64
                    };
                    let smin = bond_out[i].min_stretch as f64;
                    let smin = if smin.is_finite() { smin.min(0.0) } else { 0.0 };
                    let s_c0 = p.critical_stretch * strength.get(i).copied().unwrap_or(1.0);
                    s[3] = s_c0 * (1.0 + p.damage_stretch_coefficient * damage)
                        - p.minimum_stretch_coefficient * smin;
                }
            }
        });
        self.share_node_scalars();
    }

    /// The shortest closing time of each products node's family
    /// ([`CLOSING_STEP_FRACTION`]) at the current positions and velocities,
    /// after velocities are set (step 3 forms it with the products' state);
    /// nothing when the limit is off.
    fn update_closing(&mut self) {
        if self.closing.is_empty() {
            return;
        }
        let (reference, state, velocity) = (&self.reference, &self.state, &self.velocity);
        let (families, factor) = (&self.families, &self.factor);
        let (material, materials) = (&self.material, &self.materials);
        let family_volume = &self.node_scale;
        for_each_node_in(&mut self.closing, self.ranks.nodes(), |i, c| {
            *c = match materials[material[i] as usize] {
                PdMaterial::Gas(_) => {
                    let row = families.row(i);
                    let gas_row = GasRow {
                        reference,
                        state,
                        velocity: Some(velocity),
                        neighbours: &families.neighbours[row.clone()],
                        factor: &factor[row],
                        family_volume: family_volume[i],
                    };
                    gas_expansion_closing(i, &gas_row).3
                }
                _ => f64::INFINITY,
            };
        });
    }

    /// Step 4: bond and short-range forces of the current state.
    fn compute_forces(&mut self) {
        let input = ForceInput {
            reference: &self.reference,
            state: &self.state,
            offsets: &self.families.offsets,
            neighbours: &self.families.neighbours,
            material: &self.material,
            laws: &self.laws,
            mirror_walls: self.options.products_family.mirrors_walls(),
        };
        let own = self.ranks.nodes();
        bond_forces_dissipating_in(
            &input,
            own.clone(),
            &mut self.factor,
            &mut self.plastic,
            &mut self.bond_out,
            &mut self.dissipated_node,
        );
        if !self.one_sided.is_empty() {
            // The solid nodes in products families take the reaction of
            // those pairs, each summing its own list in a fixed order.
            let (reference, state, factor) = (&self.reference, &self.state, &self.factor);
            let pairs = &self.one_sided;
            let mirror = self.options.products_family.mirrors_walls();
            for_each_node_in(&mut self.bond_out, own.clone(), |j, o| {
                let row = pairs.row(j);
                if row.is_empty() {
                    return;
                }
                let (f, _) = one_sided_gas_reaction(
                    j,
                    reference,
                    state,
                    &pairs.partner[row.clone()],
                    &pairs.bond[row],
                    factor,
                    mirror,
                );
                for (o, f) in o.force.iter_mut().zip(f) {
                    *o += f;
                }
            });
        }
        if let Some(params) = self.contact_params() {
            bin_positions(&mut self.cells, &self.reference, &self.state, &params);
            // Taken out for the pass (no copy) so the inputs can borrow
            // the solver.
            let mut out = std::mem::take(&mut self.contact);
            forces_in(&self.contact_input(), &self.cells, &params, own, &mut out);
            self.contact = out;
        }
        self.viscous_pass();
        self.share_forces();
    }

    /// The products' artificial viscosity at the current positions and
    /// velocities (nothing when it is off).
    fn viscous_pass(&mut self) {
        if let Some(params) = self.viscosity {
            let mut deviatoric = std::mem::take(&mut self.deviatoric);
            let mut input = ViscousInput {
                reference: &self.reference,
                state: &self.state,
                velocity: &self.velocity,
                offsets: &self.families.offsets,
                neighbours: &self.families.neighbours,
                factor: &self.factor,
                node: &self.viscous_node,
                deviatoric: &[],
                spacing: self.options.spacing,
                params,
            };
            if !deviatoric.is_empty() {
                // The owned nodes' and their neighbours': the force pass
                // over the owned nodes reads the neighbours'
                // (viscosity.rs). Entries outside are not read.
                let reach = self.ranks.reach();
                for_each_node_in(&mut deviatoric, reach, |i, d| {
                    *d = deviatoric_node(&input, i)
                });
            }
            input.deviatoric = &deviatoric;
            viscous_forces_in(&input, self.ranks.nodes(), &mut self.viscous);
            self.deviatoric = deviatoric;
        }
    }

    /// Stable step of node i without the safety factor (eq 24), s:
    /// √(2 / Σ (stiffness / density)) over the bond, gas and contact terms.
    /// The gas pairwise force (eq 26) uses the density ρ₀/X of eq 25; the
    /// short-range forces act on the node's own inertia, ρ₀ (its mass ρ₀V
    /// does not change as the gas expands).
    ///
    /// The products' artificial viscosity adds the stiffness its pair
    /// pressure q has through r/p² (like P in eq 26, density ρ₀/X) and a
    /// damping rate γ (`ViscousOut::damping`); for the central difference
    /// with damping the stable step of ẍ + γẋ + ω²x = 0 is
    /// (2/ω)(√(1 + ζ²) − ζ), ζ = γ/(2ω) (Belytschko, Liu & Moran 2000,
    /// Nonlinear Finite Elements, §6.2.4), written here as
    /// 2/(√(ω² + γ²/4) + γ/2), which is 2/γ when ω = 0. Eq 24's
    /// √(2ρ/ΣC) is that limit without damping for ω² = 2ΣC/ρ, so the
    /// undamped step is exactly eq 24's.
    fn node_dt(&self, i: usize) -> f64 {
        let rho = self.material_density[self.material[i] as usize];
        let mut omega2 = self.contact.get(i).map_or(0.0, |c| c.1) / rho;
        let mut gamma = 0.0;
        match self.laws[self.material[i] as usize] {
            BondLaw::Solid { .. } => {
                omega2 += self.node_scale[i] / rho;
                let row = self.one_sided.row(i);
                if !row.is_empty() {
                    let (_, k) = one_sided_gas_reaction(
                        i,
                        &self.reference,
                        &self.state,
                        &self.one_sided.partner[row.clone()],
                        &self.one_sided.bond[row],
                        &self.factor,
                        self.options.products_family.mirrors_walls(),
                    );
                    omega2 += k / rho;
                }
            }
            BondLaw::Gas => {
                omega2 += self.gas[i][1] * self.gas[i][0] / rho;
                if let Some(v) = self.viscous.get(i) {
                    omega2 += v.stiffness * self.gas[i][0] / rho;
                    gamma = v.damping;
                }
            }
        }
        // Eq 24 is √(2/S) with S = omega2 here, i.e. 2/ω with the
        // oscillator's ω² = 2S; with damping 2/(√(ω² + γ²/4) + γ/2).
        let dt = if gamma > 0.0 {
            2.0 / ((2.0 * omega2 + 0.25 * gamma * gamma).sqrt() + 0.5 * gamma)
        } else if omega2 > 0.0 {
            (2.0 / omega2).sqrt()
        } else {
            f64::INFINITY
        };
        // Products pairs close at most a fraction of their gap per step.
        match (self.closing.get(i), self.options.closing_step_fraction) {
            (Some(&c), Some(f)) if f * c < dt => f * c,
            _ => dt,
        }
    }

    /// The smallest eq 24 step over the nodes (without the safety factor)
    /// and the first node that has it; (∞, 0) without nodes.
    pub(crate) fn smallest_node_dt(&self) -> (f64, usize) {
        let mut best = (f64::INFINITY, 0);
        for i in 0..self.node_count() {
            let d = self.node_dt(i);
            if d < best.0 {
                best = (d, i);
            }
        }
        best
    }

    /// The node that limits the stable step and a description of why
    /// (material, expansion, stiffness sums), for diagnostics.
    pub fn limiting_node(&self) -> (usize, String) {
        let (dt, i) = self.smallest_node_dt();
        (
            i,
            format!(
                "node {i} material {} dt {:e} s: X = {:.4}, gas stiffness {:e}, contact {:e}, solid {:e}, detonated {}",
                self.material[i],
                dt,
                self.expansion(i),
                self.gas.get(i).map_or(0.0, |g| g[1]),
                self.contact.get(i).map_or(0.0, |c| c.1),
                match self.laws[self.material[i] as usize] {
                    BondLaw::Solid { .. } => self.node_scale[i],
                    BondLaw::Gas => 0.0,
                },
                detonated(self.time, self.detonation_time[i])
            ),
        )
    }

    /// The short-range force parameters; `None` with contact off.
    fn contact_params(&self) -> Option<ContactParams> {
        self.options.contact.map(|c| ContactParams {
            force_factor: c.force_factor,
            contact_distance: c.distance_factor * self.options.spacing,
            reference_fraction: c.reference_fraction,
            horizon: self.horizon,
        })
    }

    /// The contact pass's view of the nodes.
    fn contact_input(&self) -> ContactInput<'_> {
        ContactInput::trusted(ContactParts {
            reference: &self.reference,
            state: &self.state,
            body: &self.body,
            material: &self.material,
            bulk_modulus: &self.bulk_modulus,
            breakable: &self.breakable,
            families: &self.families,
            factor: &self.factor,
            family_cutoff: self.horizon + 0.5 * self.options.spacing,
        })
    }
}

mod build;
mod energy;
mod ranks;
mod setup;
mod solver_trait;

use setup::{heap, invalid};
pub use setup::{
    BurnMethod, ContactOptions, DetonationSpec, PdBoundary, PdMemory, PdOptions, PdSetup,
    PdSetupError, ProductsFamily,
};

#[cfg(test)]
mod memory_tests;
#[cfg(test)]
mod tests;

/// Pressure of a products node and its derivative in X, (P, dP/dX), Pa.
///
/// Seed 004 starts the products of a node from the volume-burn reference
/// state (X = 1, P_S0; eqs 20–21) at its detonation time, so that each
/// node releases W(1)V — its chemical energy. The discrete node may not be
/// exactly at X = 1 then (its family has already moved with the products
/// behind the front), and taking W(X) there would create or destroy
/// W(X_d) − W(1) per node. Brisance measures the node's expansion from its
/// volume at detonation: with X_d the expansion (eq 17) at that instant,
/// the stored energy is W(X/X_d) V and, from dE/d(XV) = −P,
///
/// ```text
/// P = P_S(X/X_d) / X_d,   dP/dX = P_S'(X/X_d) / X_d².
/// ```
///
/// X_d = 1 gives the seed's eqs 29–30 unchanged. `xd = 0` (not yet
/// detonated) is read as 1.
///
/// **Viscous heat.** The products' artificial viscosity (`viscosity.rs`)
/// returns the energy it dissipates to the node as internal energy. The
/// JWL isentropes (eq 30) of one product gas differ only in C, the
/// coefficient of the Grüneisen term: JWL is P = f(v) + ω e/v, so on an
/// isentrope de/dv = −P gives e = e_ref(v) + (C/ω) v^{−ω} with C set by
/// the entropy (Lee, Hornig & Kury 1968, UCRL-50422; Menikoff 2015,
/// LA-UR-15-29536, "JWL equation of state", §3). The ideal gas of eq 29 is
/// the same with ω = γ − 1 and A = B = 0. Heat dq per unit reference
/// volume added at fixed y = X/X_d moves the node to the isentrope with
/// C + ΔC, ΔC += ω y^ω dq, so that
///
/// ```text
/// W = W_S(y) + (ΔC/ω) y^{−ω},   P = [P_S(y) + ΔC y^{−(ω+1)}] / X_d,
/// dP/dX = [P_S'(y) − (ω + 1) ΔC y^{−(ω+2)}] / X_d²,
/// ```
///
/// still with P = −dW/dy / X_d. `heat` is ΔC (0 without viscosity).
#[inline]
fn products_pressure(g: &crate::material::Gas, x: f64, xd: f64, heat: f64) -> (f64, f64) {
    let xd = if xd > 0.0 { xd } else { 1.0 };
    let y = x / xd;
    let (mut p, mut dp) = (g.isentrope.pressure(y), g.isentrope.dpressure_dx(y));
    if heat != 0.0 {
        let w = heat_exponent(g);
        let t = heat * y.powf(-(w + 1.0));
        p += t;
        dp -= (w + 1.0) * t / y;
    }
    (p / xd, dp / (xd * xd))
}

/// Pressure and dP/dX of an explosive node: the products'
/// (`products_pressure`) once it has detonated (X_d > 0), the reactant's
/// P_u(X) before (0 without a reactant).
#[inline]
fn node_pressure(g: &crate::material::Gas, x: f64, xd: f64, heat: f64) -> (f64, f64) {
    if xd > 0.0 {
        products_pressure(g, x, xd, heat)
    } else {
        match g.reactant {
            Some(r) => (r.pressure(x), r.dpressure_dx(x)),
            None => (0.0, 0.0),
        }
    }
}

/// ω of the products' Grüneisen term: ω of JWL (eq 30), γ − 1 of the ideal
/// gas (eq 29); see `products_pressure`.
#[inline]
fn heat_exponent(g: &crate::material::Gas) -> f64 {
    match g.isentrope {
        brisance_reaction::ProductsIsentrope::IdealGas { gamma, .. } => gamma - 1.0,
        brisance_reaction::ProductsIsentrope::Jwl { omega, .. } => omega,
    }
}

fn distance(a: [f64; 3], b: [f64; 3]) -> f64 {
    ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)).sqrt()
}
