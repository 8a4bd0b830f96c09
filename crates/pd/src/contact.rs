//! Short-range forces, seed 004 eq 27: a repulsion between two nodes closer
//! than their contact distance that are not joined by an intact bond —
//! nodes of different bodies (gas and case, case and target) and nodes of
//! one body whose bond broke (fragments). They are what lets the products
//! push the case (seed 004, "Short-Range Forces").
//!
//! ```text
//! f_ij = F_SR k_PD V_i V_j (p − d_ij) / δ,   p < d_ij,
//! d_ij = min(α |x_j − x_i|, p_contact),
//! ```
//!
//! directed along the current bond, with k_PD = 18K/(πδ⁴) (eq 28). The
//! seed prints eq 27 without the 1/δ; with k_PD in N/m⁶ and volumes in m³
//! the product F_SR k_PD V_i V_j (p − p_contact) has units N·m, so Brisance
//! divides the separation by the horizon to make it a force, as the EMU
//! theory manual (Silling 2005, p 18) and its transcription in LAMMPS
//! (`pair_style peri/pmb`; Parks, Lehoucq, Plimpton & Silling 2008,
//! Comput. Phys. Commun. 179:777) do.
//!
//! The seed leaves p_contact to "the input parameters … for the material
//! and short-range forces". Brisance takes the per-pair contact distance
//! of EMU/LAMMPS: d_ij = min(α r_ij, p_contact) with r_ij = |x_j − x_i| the
//! pair's *reference* separation, α = 0.9 and p_contact = 1.35 h by default.
//! Pairs that start close (lattice neighbours across an interface) are
//! force-free at rest with a margin (d = 0.9 r), while a node coming from
//! further away meets a contact sphere of 1.35 h around every node, so the
//! spheres of the nodes of a lattice face (h apart) overlap and a node
//! cannot pass between them (with d = h it only had to come within 0.71 h
//! of the four nodes of a face). d_ij depends on the pair only, so the
//! force is the gradient of a fixed pair potential ½ F_SR k_PD V_i V_j
//! (p − d_ij)²/δ and the contact conserves energy.
//!
//! For a pair of two materials k_PD uses the larger bulk modulus (a gas has
//! none, so gas–case contact is as stiff as the case). With
//! `PdSolver::set_products_contact(true)` (off by default) an explosive
//! given with a reactant has its K₀ = 1/κ, and then the nodes of one
//! charge repel each other too, bonded or not: eq 19 alone lets two of
//! them come arbitrarily close (its force on a pair grows with the
//! pressure at the nodes' expansion, which is low in expanded products),
//! and the seed gives short-range forces the job of preventing "bonds from
//! compressing indefinitely". Lattice neighbours start force-free
//! (d = 0.9 h). Neighbours are found
//! with a cell list of the *current* positions x + u, rebuilt every step
//! from the reference positions and displacements; the list keeps the
//! current positions in its buckets' order (24 B a node), so a bucket's
//! candidates are read as contiguous runs and tested against the reach
//! eight at a time (docs/physics/pd/kernel.md, "The contact pass beside
//! the bonds").

use crate::cell_list::CellList;
use crate::family::Families;
use crate::forces::{for_each_node, for_each_node_in};

/// Parameters of the short-range forces.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ContactParams {
    /// F_SR, the user's force factor.
    pub force_factor: f64,
    /// p_contact, the largest contact distance, m.
    pub contact_distance: f64,
    /// α: a pair's contact distance is at most α times its reference
    /// separation.
    pub reference_fraction: f64,
    /// Horizon δ, m.
    pub horizon: f64,
}

impl ContactParams {
    /// d_ij = min(α r, p_contact) for a pair whose reference separation
    /// squared is `r2`, m.
    #[inline]
    pub fn pair_distance(&self, r2: f64) -> f64 {
        (self.reference_fraction * r2.sqrt()).min(self.contact_distance)
    }

    /// The reach of the search, 1.5 p_contact (the largest 1.5 d_ij).
    #[inline]
    pub fn reach(&self) -> f64 {
        1.5 * self.contact_distance
    }
}

/// The arrays of the contact pass as given; [`ContactInput::new`] checks
/// that they agree before a pass reads them.
#[derive(Debug, Clone, Copy)]
pub struct ContactParts<'a> {
    /// Reference positions and volumes (x, V).
    pub reference: &'a [[f64; 4]],
    /// Displacements (u, ·): the current position is x + u.
    pub state: &'a [[f64; 4]],
    /// Body of each node.
    pub body: &'a [u32],
    /// Material of each node.
    pub material: &'a [u16],
    /// Bulk modulus used for k_PD, per material, Pa.
    pub bulk_modulus: &'a [f64],
    /// Whether bonds of a material can break (solids); unbreakable bonds
    /// (gases) exclude same-body contact.
    pub breakable: &'a [bool],
    /// Families.
    pub families: &'a Families,
    /// Bond factors (0 = broken).
    pub factor: &'a [f32],
    /// The families' reference cutoff δ + h/2 (`crate::family`): a pair of
    /// one body closer than this in the reference configuration is in both
    /// nodes' rows, one further away in neither. Lets the pass answer the
    /// family test from the reference distance instead of a binary search
    /// (same answer, checked against the search in the tests): "bonded and
    /// intact" for a node whose bonds are all intact, "in no row" for any
    /// node. Anything but a positive finite value always searches.
    pub family_cutoff: f64,
}

/// Read-only inputs of the contact pass: [`ContactParts`] whose lengths
/// and indices agree (one entry per node in `reference`, `state`, `body`
/// and `material`; a material id below the length of `bulk_modulus` and
/// `breakable`, which agree; families of as many nodes with ascending
/// rows of node indices, and one factor per bond), so a pass cannot index
/// past an array. Read the parts through `Deref`.
#[derive(Debug, Clone, Copy)]
pub struct ContactInput<'a> {
    parts: ContactParts<'a>,
}

impl<'a> std::ops::Deref for ContactInput<'a> {
    type Target = ContactParts<'a>;
    fn deref(&self) -> &ContactParts<'a> {
        &self.parts
    }
}

/// Why a [`ContactInput`], or a pass's other arguments, do not fit
/// together: the array named and what was expected of it.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("contact pass: {0}")]
pub struct ContactInputError(pub String);

fn mismatch(what: &str, len: usize, expected: usize, of: &str) -> ContactInputError {
    ContactInputError(format!(
        "`{what}` has {len} entries, expected {expected} ({of})"
    ))
}

impl<'a> ContactInput<'a> {
    /// The parts, checked (once, O(nodes + bonds)): see the type's doc.
    pub fn new(parts: ContactParts<'a>) -> Result<Self, ContactInputError> {
        let n = parts.reference.len();
        for (what, len) in [
            ("state", parts.state.len()),
            ("body", parts.body.len()),
            ("material", parts.material.len()),
        ] {
            if len != n {
                return Err(mismatch(what, len, n, "one per node of `reference`"));
            }
        }
        let materials = parts.bulk_modulus.len();
        if parts.breakable.len() != materials {
            return Err(mismatch(
                "breakable",
                parts.breakable.len(),
                materials,
                "one per material of `bulk_modulus`",
            ));
        }
        if let Some(i) = parts.material.iter().position(|&m| m as usize >= materials) {
            return Err(ContactInputError(format!(
                "node {i} is of material {}, but {materials} materials are given",
                parts.material[i]
            )));
        }
        let f = parts.families;
        if f.offsets.len() != n + 1 {
            return Err(mismatch(
                "families.offsets",
                f.offsets.len(),
                n + 1,
                "one per node and the end",
            ));
        }
        let bonds = f.neighbours.len();
        let rows_fit = f.offsets[0] == 0
            && f.offsets.windows(2).all(|w| w[0] <= w[1])
            && f.offsets[n] as usize == bonds;
        if !rows_fit {
            return Err(ContactInputError(format!(
                "`families.offsets` must rise from 0 to the {bonds} neighbours"
            )));
        }
        for i in 0..n {
            let row = &f.neighbours[f.row(i)];
            if !(row.iter().all(|&j| (j as usize) < n) && row.windows(2).all(|w| w[0] < w[1])) {
                return Err(ContactInputError(format!(
                    "the family of node {i} must list nodes below {n} in ascending order"
                )));
            }
        }
        if parts.factor.len() != bonds {
            return Err(mismatch(
                "factor",
                parts.factor.len(),
                bonds,
                "one per bond of `families`",
            ));
        }
        Ok(Self { parts })
    }

    /// The parts unchecked: for the solver, whose arrays agree by
    /// construction.
    pub(crate) fn trusted(parts: ContactParts<'a>) -> Self {
        Self { parts }
    }

    /// Number of nodes.
    pub fn node_count(&self) -> usize {
        self.parts.reference.len()
    }
}

/// Checks that `cells` binned the current positions of every node of
/// `input` (with [`bin_current_positions`]) and that `out` has one entry a
/// node.
fn check_pass(input: &ContactInput, cells: &CellList, out: usize) -> Result<(), ContactInputError> {
    let n = input.node_count();
    match cells.points_with_positions() {
        Some(m) if m == n => {}
        Some(m) => return Err(mismatch("cells", m, n, "points binned, one per node")),
        None => {
            return Err(ContactInputError(
                "`cells` keeps no positions: bin them with `bin_current_positions`".into(),
            ))
        }
    }
    if out != n {
        return Err(mismatch("out", out, n, "one per node"));
    }
    Ok(())
}

/// Current position x + u of node i, m.
#[inline(always)]
pub fn current_position(reference: &[[f64; 4]], state: &[[f64; 4]], i: usize) -> [f64; 3] {
    let (x, u) = (reference[i], state[i]);
    [x[0] + u[0], x[1] + u[1], x[2] + u[2]]
}

/// Rebuilds `cells` over the current positions of `input`'s nodes with
/// cells of the search reach, keeping the positions in the buckets' order.
pub fn bin_current_positions(cells: &mut CellList, input: &ContactInput, params: &ContactParams) {
    bin_positions(cells, input.reference, input.state, params);
}

/// [`bin_current_positions`] from the arrays (`state` as long as
/// `reference`).
pub(crate) fn bin_positions(
    cells: &mut CellList,
    reference: &[[f64; 4]],
    state: &[[f64; 4]],
    params: &ContactParams,
) {
    cells.rebuild_with_positions(reference.len(), params.reach(), |i| {
        current_position(reference, state, i)
    });
}

/// k0 = F_SR · 18/(π δ⁴) / δ: the pair stiffness per unit bulk modulus
/// and per unit volume of both nodes (eq 27 with eq 28's k_PD).
#[inline]
fn stiffness_factor(params: &ContactParams) -> f64 {
    params.force_factor * 18.0 / (std::f64::consts::PI * params.horizon.powi(4)) / params.horizon
}

/// Calls `pair(j, k, p, d_ij, y_j − y_i)` for each node j that acts on
/// node i by contact and lies within 1.5 d_ij of it, in the cell list's
/// order: k = k0 K V_j (N/m³ per metre of overlap), p the current
/// distance. The one place that decides which pairs touch, shared by the
/// forces and the energy.
#[inline(always)]
fn for_each_contact<F: FnMut(usize, f64, f64, f64, [f64; 3])>(
    input: &ContactInput,
    cells: &CellList,
    params: &ContactParams,
    k0: f64,
    i: usize,
    mut pair: F,
) {
    let reach2 = params.reach() * params.reach();
    let yi = current_position(input.reference, input.state, i);
    let xi = input.reference[i];
    let mi = input.material[i] as usize;
    // The family test from the reference distance r: a pair of one body
    // with r² below `bonded2` is in i's row, above `apart2` in no row;
    // between the two (a relative band of 1e-9 around the cutoff, wider
    // than the round-off of the families' own r) the row is searched.
    // Where i has a broken bond, only "in no row" is answered this way.
    let cut2 = if input.family_cutoff.is_finite() && input.family_cutoff > 0.0 {
        input.family_cutoff * input.family_cutoff
    } else {
        0.0
    };
    let (bonded2, apart2) = (cut2 * (1.0 - 1e-9), cut2 * (1.0 + 1e-9));
    let row_intact = input.breakable[mi]
        && cut2 > 0.0
        && input.factor[input.families.row(i)]
            .iter()
            .fold(true, |all, &f| all & (f != 0.0));
    cells.for_each_candidate_within(yi, reach2, |j, d, p2| {
        if j == i {
            return;
        }
        let mj = input.material[j] as usize;
        let xj = input.reference[j];
        let r = [xj[0] - xi[0], xj[1] - xi[1], xj[2] - xi[2]];
        let r2 = r[0] * r[0] + r[1] * r[1] + r[2] * r[2];
        if input.body[i] == input.body[j] {
            if input.breakable[mi] {
                let bonded = if row_intact && r2 < bonded2 {
                    true
                } else if cut2 > 0.0 && r2 > apart2 {
                    false
                } else {
                    input
                        .families
                        .find(i, j)
                        .is_some_and(|k| input.factor[k] != 0.0)
                };
                if bonded {
                    return;
                }
            } else if input.bulk_modulus[mi] == 0.0 {
                return;
            }
            // Otherwise a gas with a contact modulus (an explosive
            // with a reactant): every pair of its nodes, bonded or
            // not — eq 19 alone lets two of them come arbitrarily
            // close.
        }
        let pc = params.pair_distance(r2);
        if p2 >= 2.25 * pc * pc {
            return;
        }
        let k = k0 * input.bulk_modulus[mi].max(input.bulk_modulus[mj]) * xj[3];
        pair(j, k, p2.sqrt(), pc, d);
    });
}

/// The contact force per unit volume on each node (N/m³) and the contact
/// stiffness Σ_j F_SR k_PD V_j / δ over the pairs closer than 1.5 d_ij
/// (for the stable step, so that contacts that start during the next step
/// are already counted). `cells` must bin the current positions
/// ([`bin_current_positions`]); `out` has one entry a node. An error
/// where `cells` or `out` do not fit `input`.
pub fn contact_forces(
    input: &ContactInput,
    cells: &CellList,
    params: &ContactParams,
    out: &mut [([f64; 3], f64)],
) -> Result<(), ContactInputError> {
    contact_forces_in(input, cells, params, 0..out.len(), out)
}

/// [`contact_forces`] for the nodes of `nodes` only (`out` is the whole
/// per-node array; the other entries are left as they are). An error
/// where `cells` or `out` do not fit `input` or `nodes` reaches past them.
pub fn contact_forces_in(
    input: &ContactInput,
    cells: &CellList,
    params: &ContactParams,
    nodes: std::ops::Range<usize>,
    out: &mut [([f64; 3], f64)],
) -> Result<(), ContactInputError> {
    check_pass(input, cells, out.len())?;
    if nodes.start > nodes.end || nodes.end > out.len() {
        return Err(ContactInputError(format!(
            "nodes {nodes:?} reach past the {} nodes",
            out.len()
        )));
    }
    forces_in(input, cells, params, nodes, out);
    Ok(())
}

/// [`contact_forces_in`] unchecked: for the solver, whose arrays agree by
/// construction.
pub(crate) fn forces_in(
    input: &ContactInput,
    cells: &CellList,
    params: &ContactParams,
    nodes: std::ops::Range<usize>,
    out: &mut [([f64; 3], f64)],
) {
    let k0 = stiffness_factor(params);
    for_each_node_in(out, nodes, |i, o| {
        let mut f = [0.0; 3];
        let mut stiff = 0.0;
        for_each_contact(input, cells, params, k0, i, |_, k, p, pc, d| {
            stiff += k;
            if p < pc && p > 0.0 {
                // Negative: pushes i away from j.
                let g = k * (p - pc) / p;
                f[0] += g * d[0];
                f[1] += g * d[1];
                f[2] += g * d[2];
            }
        });
        *o = (f, stiff);
    });
}

/// Each node's half of the contact energy of its pairs, J: the pair
/// potential ½ F_SR k_PD V_i V_j (p − d_ij)²/δ of eq 27's force (zero
/// beyond d_ij) shared equally by the two nodes, so `out` sums to the
/// energy stored in the contacts. `cells` must bin the current positions;
/// an error where `cells` or `out` do not fit `input`.
pub fn contact_energies(
    input: &ContactInput,
    cells: &CellList,
    params: &ContactParams,
    out: &mut [f64],
) -> Result<(), ContactInputError> {
    check_pass(input, cells, out.len())?;
    energies(input, cells, params, out);
    Ok(())
}

/// [`contact_energies`] unchecked: for the solver.
pub(crate) fn energies(
    input: &ContactInput,
    cells: &CellList,
    params: &ContactParams,
    out: &mut [f64],
) {
    let k0 = stiffness_factor(params);
    for_each_node(out, |i, o| {
        let vi = input.reference[i][3];
        let mut e = 0.0;
        for_each_contact(input, cells, params, k0, i, |_, k, p, pc, _| {
            if p < pc {
                e += 0.25 * k * vi * (pc - p) * (pc - p);
            }
        });
        *o = e;
    });
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::family::build_families;

    const H: f64 = 1.0e-3;
    /// Bulk modulus of the solid material 0, Pa (material 1 is a gas: 0).
    const K: f64 = 1.0e11;

    fn params() -> ContactParams {
        ContactParams {
            force_factor: 15.0,
            contact_distance: 1.35 * H,
            reference_fraction: 0.9,
            horizon: 3.0 * H,
        }
    }

    /// F_SR k_PD V_j / δ for V_j = h³, K = 1e11 Pa, δ = 3 mm:
    /// 15 · 18 · 1e11 · 1e-9 / (π · (3e-3)⁵) = 27000 / (π · 2.43e-13)
    /// = 3.536776e16 N/m⁴ per unit volume of node i.
    const STIFFNESS: f64 = 27000.0 / (std::f64::consts::PI * 2.43e-13);

    /// Contact forces of nodes with the given reference positions, current
    /// positions, bodies and materials (all of volume h³); all bonds intact
    /// unless `broken`.
    fn forces(
        reference: &[[f64; 3]],
        current: &[[f64; 3]],
        body: &[u32],
        material: &[u16],
        broken: bool,
    ) -> Vec<([f64; 3], f64)> {
        forces_with_gas_modulus(reference, current, body, material, broken, 0.0)
    }

    /// As `forces`, the gas (material 1) with contact modulus `gas_k`.
    fn forces_with_gas_modulus(
        reference: &[[f64; 3]],
        current: &[[f64; 3]],
        body: &[u32],
        material: &[u16],
        broken: bool,
        gas_k: f64,
    ) -> Vec<([f64; 3], f64)> {
        with_input(
            reference,
            current,
            body,
            material,
            broken,
            gas_k,
            |input, cells, p| {
                let mut out = vec![([0.0; 3], 0.0); reference.len()];
                contact_forces(input, cells, p, &mut out).unwrap();
                out
            },
        )
    }

    /// Each node's share of the contact energy, as `forces` (no gas
    /// modulus).
    fn energies(reference: &[[f64; 3]], current: &[[f64; 3]], body: &[u32]) -> Vec<f64> {
        let material = vec![0; reference.len()];
        with_input(
            reference,
            current,
            body,
            &material,
            false,
            0.0,
            |input, cells, p| {
                let mut out = vec![0.0; reference.len()];
                contact_energies(input, cells, p, &mut out).unwrap();
                out
            },
        )
    }

    /// Builds the contact pass's inputs for nodes of volume h³ and hands
    /// them to `pass`.
    fn with_input<T>(
        reference: &[[f64; 3]],
        current: &[[f64; 3]],
        body: &[u32],
        material: &[u16],
        broken: bool,
        gas_k: f64,
        pass: impl FnOnce(&ContactInput, &CellList, &ContactParams) -> T,
    ) -> T {
        let p = params();
        let families = build_families(reference, body, p.horizon, H);
        let factor = vec![if broken { 0.0 } else { 1.0 }; families.bond_count()];
        let refs: Vec<[f64; 4]> = reference
            .iter()
            .map(|x| [x[0], x[1], x[2], H * H * H])
            .collect();
        let state: Vec<[f64; 4]> = reference
            .iter()
            .zip(current)
            .map(|(x, y)| [y[0] - x[0], y[1] - x[1], y[2] - x[2], 0.0])
            .collect();
        let bulk_modulus = [K, gas_k];
        let input = ContactInput::new(ContactParts {
            reference: &refs,
            state: &state,
            body,
            material,
            bulk_modulus: &bulk_modulus,
            breakable: &[true, false],
            families: &families,
            factor: &factor,
            family_cutoff: p.horizon + 0.5 * H,
        })
        .unwrap();
        let mut cells = CellList::default();
        bin_current_positions(&mut cells, &input, &p);
        pass(&input, &cells, &p)
    }

    /// Arrays that do not agree are refused by `ContactInput::new`, each
    /// by the array's name, and a pass given cells or an output that do
    /// not fit its input returns an error instead of indexing past an
    /// array (the earlier struct literal panicked in the row scan).
    #[test]
    fn arrays_that_do_not_agree_are_refused_by_name() {
        let p = params();
        let reference: Vec<[f64; 3]> = (0..6).map(|i| [i as f64 * H, 0.0, 0.0]).collect();
        let body = [0u32; 6];
        let material = [0u16, 0, 0, 1, 1, 1];
        let families = build_families(&reference, &body, p.horizon, H);
        let factor = vec![1.0f32; families.bond_count()];
        let refs: Vec<[f64; 4]> = reference.iter().map(|x| [x[0], x[1], x[2], 1e-9]).collect();
        let state = vec![[0.0; 4]; 6];
        let good = ContactParts {
            reference: &refs,
            state: &state,
            body: &body,
            material: &material,
            bulk_modulus: &[K, 0.0],
            breakable: &[true, false],
            families: &families,
            factor: &factor,
            family_cutoff: p.horizon + 0.5 * H,
        };
        let input = ContactInput::new(good).unwrap();
        assert_eq!(input.node_count(), 6);
        let short_families = build_families(&reference[..5], &body[..5], p.horizon, H);
        let mut unsorted = families.clone();
        let row = unsorted.row(0);
        unsorted.neighbours[row].reverse();
        let mut past = families.clone();
        past.neighbours[0] = 6;
        let cases: [(ContactParts, &str); 9] = [
            (
                ContactParts {
                    state: &state[..5],
                    ..good
                },
                "`state`",
            ),
            (
                ContactParts {
                    body: &body[..4],
                    ..good
                },
                "`body`",
            ),
            (
                ContactParts {
                    material: &material[1..],
                    ..good
                },
                "`material`",
            ),
            (
                ContactParts {
                    breakable: &[true],
                    ..good
                },
                "`breakable`",
            ),
            (
                ContactParts {
                    bulk_modulus: &[K],
                    breakable: &[true],
                    ..good
                },
                "node 3 is of material 1",
            ),
            (
                ContactParts {
                    families: &short_families,
                    ..good
                },
                "`families.offsets`",
            ),
            (
                ContactParts {
                    families: &unsorted,
                    ..good
                },
                "family of node 0",
            ),
            (
                ContactParts {
                    families: &past,
                    ..good
                },
                "family of node 0",
            ),
            (
                ContactParts {
                    factor: &factor[1..],
                    ..good
                },
                "`factor`",
            ),
        ];
        for (parts, name) in cases {
            let e = ContactInput::new(parts).unwrap_err();
            assert!(e.to_string().contains(name), "{name}: {e}");
        }
        // The passes: cells never binned, binned for another count, an
        // output of the wrong length, a node range past the end.
        let mut out = vec![([0.0; 3], 0.0); 6];
        let mut energy = vec![0.0; 6];
        let unbinned = CellList::default();
        let e = contact_forces(&input, &unbinned, &p, &mut out).unwrap_err();
        assert!(e.to_string().contains("bin_current_positions"), "{e}");
        let short_factor = vec![1.0; short_families.bond_count()];
        let other = ContactInput::new(ContactParts {
            reference: &refs[..5],
            state: &state[..5],
            body: &body[..5],
            material: &material[..5],
            families: &short_families,
            factor: &short_factor,
            ..good
        })
        .unwrap();
        let mut cells = CellList::default();
        bin_current_positions(&mut cells, &other, &p);
        let e = contact_energies(&input, &cells, &p, &mut energy).unwrap_err();
        assert!(e.to_string().contains("`cells` has 5 entries"), "{e}");
        bin_current_positions(&mut cells, &input, &p);
        let e = contact_forces(&input, &cells, &p, &mut out[..5]).unwrap_err();
        assert!(e.to_string().contains("`out` has 5 entries"), "{e}");
        let e = contact_forces_in(&input, &cells, &p, 4..7, &mut out).unwrap_err();
        assert!(e.to_string().contains("4..7"), "{e}");
        contact_forces_in(&input, &cells, &p, 2..4, &mut out).unwrap();
        contact_energies(&input, &cells, &p, &mut energy).unwrap();
    }

    /// The pair of `a_node_from_afar_meets_the_full_contact_distance`
    /// (0.35h inside its contact distance) stores ½ k V (0.35h)² with
    /// k V = 3.536776e16 · 1e-9 N/m: 2.166276 J, half on each node; apart
    /// it stores nothing.
    #[test]
    fn a_contact_pair_stores_its_potential_half_on_each_node() {
        let reference = [[0.0; 3], [2.0 * H, 0.0, 0.0]];
        let e = energies(&reference, &[[0.0; 3], [H, 0.0, 0.0]], &[0, 1]);
        let expected = 0.5 * STIFFNESS * H * H * H * (0.35 * H) * (0.35 * H);
        assert!((expected / 2.166276 - 1.0).abs() < 1e-6, "{expected}");
        assert!(
            close(e[0], 0.5 * expected) && close(e[1], 0.5 * expected),
            "{e:?}"
        );
        let apart = energies(&reference, &[[0.0; 3], [1.4 * H, 0.0, 0.0]], &[0, 1]);
        assert_eq!(apart, [0.0, 0.0]);
    }

    /// The energy is the potential of the force: moving one node of a
    /// compressed pair of a small cluster by ±ε changes the total by
    /// −F·2ε (F in newtons, the force per volume times h³) to the
    /// central difference's O(ε²).
    #[test]
    fn the_contact_force_is_minus_the_gradient_of_the_contact_energy() {
        let reference = [
            [0.0; 3],
            [2.0 * H, 0.0, 0.0],
            [2.0 * H, 2.0 * H, 0.0],
            [0.0, 2.0 * H, 2.0 * H],
        ];
        let current = [
            [0.0; 3],
            [1.1 * H, 0.2 * H, -0.1 * H],
            [0.9 * H, 0.8 * H, 0.3 * H],
            [0.1 * H, 0.5 * H, 1.0 * H],
        ];
        let body = [0, 1, 2, 3];
        let material = [0; 4];
        let f = forces(&reference, &current, &body, &material, false);
        let total = |c: &[[f64; 3]]| energies(&reference, c, &body).iter().sum::<f64>();
        let eps = 1.0e-9;
        for node in 0..4 {
            for axis in 0..3 {
                let mut plus = current;
                let mut minus = current;
                plus[node][axis] += eps;
                minus[node][axis] -= eps;
                let derivative = (total(&plus) - total(&minus)) / (2.0 * eps);
                let force = f[node].0[axis] * H * H * H;
                assert!(
                    (derivative + force).abs() <= 1e-6 * force.abs().max(1e3),
                    "node {node} axis {axis}: dU/dx {derivative}, F {force}"
                );
            }
        }
        assert!(total(&current) > 0.0);
    }

    fn close(a: f64, b: f64) -> bool {
        (a - b).abs() <= 1e-12 * b.abs().max(1e-300)
    }

    #[test]
    fn the_pair_distance_is_the_smaller_of_0_9_r_and_p_contact() {
        let p = params();
        // r = h: 0.9 h; r = 1.2 h: 1.08 h; r = 2h and 10h: p_contact = 1.35h.
        assert!(close(p.pair_distance(H * H), 0.9 * H));
        assert!(close(p.pair_distance(1.44 * H * H), 1.08 * H));
        assert!(close(p.pair_distance(4.0 * H * H), 1.35 * H));
        assert!(close(p.pair_distance(100.0 * H * H), 1.35 * H));
        assert!(close(p.reach(), 2.025 * H));
    }

    /// A gas node that started 2h from a case node and has come within
    /// h of it is pushed back by F_SR k_PD V V (h − 1.35h)/δ: per unit
    /// volume −0.35e-3 · 3.536776e16 = −1.237872e13 N/m³ on the gas node
    /// (the case node gets the opposite), and the pair counts once in
    /// each node's stiffness.
    #[test]
    fn a_node_from_afar_meets_the_full_contact_distance() {
        let reference = [[0.0; 3], [2.0 * H, 0.0, 0.0]];
        let current = [[0.0; 3], [H, 0.0, 0.0]];
        let out = forces(&reference, &current, &[0, 1], &[0, 1], false);
        let expected = -0.35 * H * STIFFNESS;
        assert!((expected / -1.237872e13 - 1.0).abs() < 1e-6);
        assert!(close(out[0].0[0], expected), "{:?}", out[0]);
        assert!(close(out[1].0[0], -expected), "{:?}", out[1]);
        assert_eq!((out[0].0[1], out[0].0[2]), (0.0, 0.0));
        assert!(close(out[0].1, STIFFNESS) && close(out[1].1, STIFFNESS));
    }

    /// Two bonded nodes of one gas body: no short-range force without a
    /// contact modulus (the products of an explosive given without a
    /// reactant); with the reactant's K₀ = 1e10 Pa they repel like any
    /// pair once closer than 0.9 h: at 0.5 h, k (0.5h − 0.9h) with k =
    /// 3.536776e16 · 0.1 = 3.536776e15 N/m⁴, i.e. −1.414710e12 N/m³.
    #[test]
    fn nodes_of_one_gas_body_repel_only_with_a_contact_modulus() {
        let reference = [[0.0; 3], [H, 0.0, 0.0]];
        let current = [[0.0; 3], [0.5 * H, 0.0, 0.0]];
        let none = forces_with_gas_modulus(&reference, &current, &[0, 0], &[1, 1], false, 0.0);
        assert_eq!(none, vec![([0.0; 3], 0.0); 2]);
        let out = forces_with_gas_modulus(&reference, &current, &[0, 0], &[1, 1], false, 1.0e10);
        let k = STIFFNESS * 1.0e10 / K;
        let expected = k * (0.5 * H - 0.9 * H);
        assert!((expected / -1.414_710e12 - 1.0).abs() < 1e-6, "{expected}");
        assert!(close(out[0].0[0], expected), "{:?}", out[0]);
        assert!(close(out[1].0[0], -expected), "{:?}", out[1]);
        assert!(close(out[0].1, k));
    }

    /// Lattice neighbours across an interface (reference separation h)
    /// are force-free down to 0.9 h, and at 0.8 h repel with
    /// k (0.8h − 0.9h) = −0.1e-3 · 3.536776e16 = −3.536776e12 N/m³.
    #[test]
    fn lattice_neighbours_are_force_free_at_rest_and_down_to_0_9_h() {
        let reference = [[0.0; 3], [0.0, H, 0.0]];
        for y in [H, 0.95 * H, 0.9000001 * H] {
            let out = forces(
                &reference,
                &[[0.0; 3], [0.0, y, 0.0]],
                &[0, 1],
                &[0, 1],
                false,
            );
            assert_eq!(out[0].0, [0.0; 3], "at {y}");
            assert_eq!(out[1].0, [0.0; 3], "at {y}");
        }
        let out = forces(
            &reference,
            &[[0.0; 3], [0.0, 0.8 * H, 0.0]],
            &[0, 1],
            &[0, 1],
            false,
        );
        assert!(close(out[0].0[1], -0.1 * H * STIFFNESS), "{:?}", out[0]);
        assert!(close(out[1].0[1], 0.1 * H * STIFFNESS), "{:?}", out[1]);
    }

    /// A node cannot pass through the middle of a lattice face: at the
    /// face centre it is 0.7071 h from each of the four nodes, and a node
    /// that came from 2h away is pushed by all four with
    /// k (0.7071h − 1.35h) each (the old p_contact = h left 0.29 h).
    #[test]
    fn a_node_at_the_centre_of_a_face_is_pushed_by_all_four_corners() {
        let mut reference = vec![];
        for (y, z) in [(0.0, 0.0), (H, 0.0), (0.0, H), (H, H)] {
            reference.push([0.0, y, z]);
        }
        reference.push([-2.0 * H, 0.5 * H, 0.5 * H]);
        let mut current = reference.clone();
        // The visitor is a tenth of a spacing before the face plane.
        current[4] = [-0.1 * H, 0.5 * H, 0.5 * H];
        let out = forces(
            &reference,
            &current,
            &[0, 0, 0, 0, 1],
            &[0, 0, 0, 0, 1],
            false,
        );
        // Each corner pushes along the line joining them; the y and z
        // parts cancel and the x parts add: 4 k (p − 1.35h)(0.1h/p) with
        // p = √0.51 h = 0.714143 h: 4 · 3.536776e16 · (−0.635857e-3) ·
        // 0.140028 = −1.259627e13 N/m³.
        let p = 0.51f64.sqrt() * H;
        let expected = 4.0 * STIFFNESS * (p - 1.35 * H) * 0.1 * H / p;
        assert!((expected / -1.259627e13 - 1.0).abs() < 1e-6, "{expected}");
        assert!(
            (out[4].0[0] / expected - 1.0).abs() < 1e-12,
            "{:?} vs {expected}",
            out[4]
        );
        assert!(out[4].0[1].abs() < 1e-9 * expected.abs());
        assert!(out[4].0[2].abs() < 1e-9 * expected.abs());
    }

    /// The pass as it was before the cell list kept the current positions
    /// (each candidate's position formed from x + u, the family test by
    /// binary search for every same-body solid pair): the oracle the pass
    /// must match bit for bit.
    fn forces_by_lookup(input: &ContactInput, params: &ContactParams) -> Vec<([f64; 3], f64)> {
        let n = input.reference.len();
        let mut cells = CellList::default();
        cells.rebuild(n, params.reach(), |i| {
            current_position(input.reference, input.state, i)
        });
        let k0 = stiffness_factor(params);
        let reach2 = params.reach() * params.reach();
        (0..n)
            .map(|i| {
                let yi = current_position(input.reference, input.state, i);
                let xi = input.reference[i];
                let mi = input.material[i] as usize;
                let (mut f, mut stiff) = ([0.0; 3], 0.0);
                cells.for_each_candidate(yi, |j| {
                    if j == i {
                        return;
                    }
                    let yj = current_position(input.reference, input.state, j);
                    let d = [yj[0] - yi[0], yj[1] - yi[1], yj[2] - yi[2]];
                    let p2 = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
                    if p2 >= reach2 {
                        return;
                    }
                    let mj = input.material[j] as usize;
                    if input.body[i] == input.body[j] {
                        if input.breakable[mi] {
                            if let Some(k) = input.families.find(i, j) {
                                if input.factor[k] != 0.0 {
                                    return;
                                }
                            }
                        } else if input.bulk_modulus[mi] == 0.0 {
                            return;
                        }
                    }
                    let xj = input.reference[j];
                    let r = [xj[0] - xi[0], xj[1] - xi[1], xj[2] - xi[2]];
                    let pc = params.pair_distance(r[0] * r[0] + r[1] * r[1] + r[2] * r[2]);
                    if p2 >= 2.25 * pc * pc {
                        return;
                    }
                    let k = k0 * input.bulk_modulus[mi].max(input.bulk_modulus[mj]) * xj[3];
                    let p = p2.sqrt();
                    stiff += k;
                    if p < pc && p > 0.0 {
                        let g = k * (p - pc) / p;
                        f[0] += g * d[0];
                        f[1] += g * d[1];
                        f[2] += g * d[2];
                    }
                });
                (f, stiff)
            })
            .collect()
    }

    /// A 10³ block of three bodies (two breakable solids side by side and
    /// an explosive with a contact modulus), squeezed along x and shaken by
    /// up to ±0.45 h, with a third of the nodes' rows fully intact and the
    /// rest holding broken and partly damaged bonds: the pass gives the
    /// oracle's forces and stiffnesses to the bit, on every thread count.
    #[test]
    fn the_pass_matches_the_lookup_oracle_bit_for_bit() {
        let n1 = 10;
        let mut reference = Vec::new();
        let (mut body, mut material) = (Vec::new(), Vec::new());
        for k in 0..n1 {
            for j in 0..n1 {
                for i in 0..n1 {
                    reference.push([i as f64 * H, j as f64 * H, k as f64 * H]);
                    let (b, m) = match i {
                        0..=3 => (0, 0),
                        4..=6 => (2, 0),
                        _ => (1, 1),
                    };
                    body.push(b);
                    material.push(m);
                }
            }
        }
        let p = params();
        let families = build_families(&reference, &body, p.horizon, H);
        let mut factor = vec![1.0f32; families.bond_count()];
        for i in 0..reference.len() {
            if i % 3 != 0 {
                for (m, k) in families.row(i).enumerate() {
                    factor[k] = match (i + m) % 5 {
                        0 => 0.0,
                        1 => 0.5,
                        _ => 1.0,
                    };
                }
            }
        }
        let mut s = 0x2545_f491_4f6c_dd1du64;
        let mut rnd = || {
            s = s
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (s >> 11) as f64 / (1u64 << 53) as f64 - 0.5
        };
        let refs: Vec<[f64; 4]> = reference
            .iter()
            .map(|x| [x[0], x[1], x[2], H * H * H])
            .collect();
        let state: Vec<[f64; 4]> = reference
            .iter()
            .map(|x| {
                let squeeze = -0.12 * (x[0] - 4.5 * H);
                [
                    squeeze + 0.9 * H * rnd(),
                    0.9 * H * rnd(),
                    0.9 * H * rnd(),
                    0.0,
                ]
            })
            .collect();
        let parts = ContactParts {
            reference: &refs,
            state: &state,
            body: &body,
            material: &material,
            bulk_modulus: &[K, 9.0e9],
            breakable: &[true, false],
            families: &families,
            factor: &factor,
            family_cutoff: p.horizon + 0.5 * H,
        };
        let input = ContactInput::new(parts).unwrap();
        let expected = forces_by_lookup(&input, &p);
        let touching = expected.iter().filter(|o| o.0 != [0.0; 3]).count();
        assert!(touching > reference.len() / 2, "{touching}");
        // Threads, and the family test by search alone (no cutoff given).
        let searching = ContactInput::new(ContactParts {
            family_cutoff: 0.0,
            ..parts
        })
        .unwrap();
        for (threads, input) in [(1, input), (2, input), (3, input), (2, searching)] {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            let out = pool.install(|| {
                let mut cells = CellList::default();
                bin_current_positions(&mut cells, &input, &p);
                let mut out = vec![([0.0; 3], 0.0); refs.len()];
                contact_forces(&input, &cells, &p, &mut out).unwrap();
                out
            });
            for (i, (a, b)) in out.iter().zip(&expected).enumerate() {
                assert_eq!(
                    (a.0.map(f64::to_bits), a.1.to_bits()),
                    (b.0.map(f64::to_bits), b.1.to_bits()),
                    "node {i} on {threads} threads, cutoff {}",
                    input.family_cutoff
                );
            }
        }
    }

    /// Same body: gas nodes never touch; solid nodes only where their
    /// bond broke.
    #[test]
    fn same_body_contact_only_across_broken_solid_bonds() {
        let reference = [[0.0; 3], [H, 0.0, 0.0]];
        let current = [[0.0; 3], [0.5 * H, 0.0, 0.0]];
        let gas = forces(&reference, &current, &[0, 0], &[1, 1], true);
        assert_eq!(gas[0], ([0.0; 3], 0.0));
        let intact = forces(&reference, &current, &[0, 0], &[0, 0], false);
        assert_eq!(intact[0], ([0.0; 3], 0.0));
        let broken = forces(&reference, &current, &[0, 0], &[0, 0], true);
        assert!(
            close(broken[0].0[0], -0.4 * H * STIFFNESS),
            "{:?}",
            broken[0]
        );
    }
}
