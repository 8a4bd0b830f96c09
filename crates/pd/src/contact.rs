//! Short-range forces, seed 004 eq 27: a repulsion between two nodes closer
//! than p_contact that are not joined by an intact bond — nodes of different
//! bodies (gas and case, case and target) and nodes of one body whose bond
//! broke (fragments). They are what lets the products push the case
//! (seed 004, "Short-Range Forces").
//!
//! ```text
//! f_ij = F_SR k_PD V_i V_j (p − p_contact) / δ,   p < p_contact,
//! ```
//!
//! directed along the current bond, with k_PD = 18K/(πδ⁴) (eq 28). The
//! seed prints eq 27 without the 1/δ; with k_PD in N/m⁶ and volumes in m³
//! the product F_SR k_PD V_i V_j (p − p_contact) has units N·m, so Brisance
//! divides the separation by the horizon (a stretch-like measure, as the
//! short-range contact model of the Peridigm code does) to make it a force.
//! For a pair of two materials k_PD uses the larger bulk modulus (a gas has
//! none, so gas–case contact is as stiff as the case). Neighbours are found
//! with a cell list of the *current* positions, rebuilt every step.

use crate::cell_list::CellList;
use crate::family::Families;
use crate::forces::for_each_node;

/// Parameters of the short-range forces.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ContactParams {
    /// F_SR, the user's force factor.
    pub force_factor: f64,
    /// p_contact, m.
    pub contact_distance: f64,
    /// Horizon δ, m.
    pub horizon: f64,
}

/// Read-only inputs of the contact pass.
#[derive(Debug, Clone, Copy)]
pub struct ContactInput<'a> {
    /// Current positions, m.
    pub current: &'a [[f64; 3]],
    /// Reference positions and volumes (x, V).
    pub reference: &'a [[f64; 4]],
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
}

/// The contact force per unit volume on each node (N/m³) and the contact
/// stiffness Σ_j F_SR k_PD V_j / δ over the pairs within 1.5 p_contact
/// (for the stable step, so that contacts that start during the next step
/// are already counted).
pub fn contact_forces(
    input: &ContactInput,
    cells: &CellList,
    params: &ContactParams,
    out: &mut [([f64; 3], f64)],
) {
    let pc = params.contact_distance;
    let reach2 = (1.5 * pc) * (1.5 * pc);
    let k0 = params.force_factor * 18.0
        / (std::f64::consts::PI * params.horizon.powi(4))
        / params.horizon;
    for_each_node(out, |i, o| {
        let yi = input.current[i];
        let mut f = [0.0; 3];
        let mut stiff = 0.0;
        let mi = input.material[i] as usize;
        cells.for_each_candidate(yi, |j| {
            if j == i {
                return;
            }
            let yj = input.current[j];
            let d = [yj[0] - yi[0], yj[1] - yi[1], yj[2] - yi[2]];
            let p2 = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
            if p2 >= reach2 {
                return;
            }
            let mj = input.material[j] as usize;
            if input.body[i] == input.body[j] {
                if !input.breakable[mi] {
                    return;
                }
                if let Some(k) = input.families.find(i, j) {
                    if input.factor[k] != 0.0 {
                        return;
                    }
                }
            }
            let k = k0 * input.bulk_modulus[mi].max(input.bulk_modulus[mj]) * input.reference[j][3];
            stiff += k;
            let p = p2.sqrt();
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
