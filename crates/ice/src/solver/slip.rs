//! Where steps 3 and 10 exchange momentum with the particle materials
//! across their surface only ([`SolidExchange::Slip`]): the surface's
//! normal from the gradient of the particle materials' summed volume
//! fraction θ_s, by central differences in a cell and by the face's own
//! difference (and the two cells' central ones across it) on a face
//! (docs/physics/couple/ice_mpm.md, "Slip exchange").

use super::*;
use crate::exchange::{surface_normal, SLIP_FLUID_MIN};

/// The particle materials' volume fraction θ_s of one patch, read from
/// the state's fields (ghosts filled by step 3).
pub(super) struct SolidFraction<'a> {
    theta: [&'a [f64]; MAX_MATERIALS],
    count: usize,
    spacing: [f64; 3],
    active: [bool; 3],
    /// The smallest active spacing, m.
    h: f64,
}

impl<'a> SolidFraction<'a> {
    /// `None` unless the run exchanges with slip and carries a material by
    /// particles.
    pub(super) fn new<E: Eos>(params: &Params<'_, E>, d: &'a [Vec<f64>]) -> Option<Self> {
        if params.options.solid_exchange != SolidExchange::Slip || !params.coupled {
            return None;
        }
        let mut theta: [&[f64]; MAX_MATERIALS] = [&[]; MAX_MATERIALS];
        let mut count = 0;
        for r in (0..params.eos.len()).filter(|&r| params.lagrangian[r]) {
            theta[count] = &d[r * NS + THETA][..];
            count += 1;
        }
        let h = (0..3)
            .filter(|&a| params.active[a])
            .map(|a| params.spacing[a])
            .fold(f64::INFINITY, f64::min);
        Some(Self {
            theta,
            count,
            spacing: params.spacing,
            active: params.active,
            h,
        })
    }

    #[inline]
    fn at(&self, i: usize) -> f64 {
        self.theta[..self.count].iter().map(|t| t[i]).sum()
    }

    /// The surface's unit normal in cell `c` (central differences), or
    /// `None` off the surface ([`surface_normal`]) and inside the solid
    /// (θ_s above 1 − [`SLIP_FLUID_MIN`]).
    pub(super) fn cell_normal(&self, c: usize, st: [usize; 3]) -> Option<[f64; 3]> {
        if !(self.at(c) <= 1.0 - SLIP_FLUID_MIN) {
            return None;
        }
        let mut g = [0.0; 3];
        for a in (0..3).filter(|&a| self.active[a]) {
            g[a] = (self.at(c + st[a]) - self.at(c - st[a])) / (2.0 * self.spacing[a]);
        }
        surface_normal(g, self.h)
    }

    /// n_a² on the face between `c − st[a]` and `c`, the share of the
    /// face's normal velocity that crosses the surface, or `None` off the
    /// surface or inside the solid (the two cells' mean θ_s above
    /// 1 − [`SLIP_FLUID_MIN`]). The gradient's component along `a` is the face's own
    /// difference; the others are the mean of the two cells' central ones.
    pub(super) fn face_weight(&self, c: usize, a: usize, st: [usize; 3]) -> Option<f64> {
        let l = c - st[a];
        if !(0.5 * (self.at(c) + self.at(l)) <= 1.0 - SLIP_FLUID_MIN) {
            return None;
        }
        let mut g = [0.0; 3];
        g[a] = (self.at(c) - self.at(l)) / self.spacing[a];
        for b in (0..3).filter(|&b| b != a && self.active[b]) {
            let s = st[b];
            g[b] = (self.at(c + s) - self.at(c - s) + self.at(l + s) - self.at(l - s))
                / (4.0 * self.spacing[b]);
        }
        surface_normal(g, self.h).map(|n| n[a] * n[a])
    }
}

/// Which materials move with the solid along its surface in a cell or on
/// a face of averaged densities `rho` (kg/m³) and volume fractions
/// `theta`: the particle materials, and the fluids that are traces there
/// ([`is_trace`]: θ below 10⁻⁴ or a mass share below 10⁻⁹;
/// [`crate::exchange::slip_momentum_exchange`] says why).
pub(super) fn with_solid<E: Eos>(
    params: &Params<'_, E>,
    rho: &[f64],
    theta: &[f64],
) -> [bool; MAX_MATERIALS] {
    let n = rho.len();
    let mass: f64 = rho.iter().sum();
    std::array::from_fn(|r| r < n && (params.lagrangian[r] || is_trace(theta[r], rho[r] / mass)))
}

/// The face exchange's coefficients under [`SolidExchange::Slip`] on a face
/// of face-averaged densities `rho` and volume fractions `theta` whose
/// weight [`SolidFraction::face_weight`] is `weight`: K with each pair of
/// one material that moves with the solid ([`with_solid`]) and one that
/// slips scaled by it ([`slip_coefficients`]); the first N×N entries.
pub(super) fn face_coefficients<E: Eos>(
    params: &Params<'_, E>,
    rho: &[f64],
    theta: &[f64],
    weight: f64,
) -> [f64; MAX_MATERIALS * MAX_MATERIALS] {
    let n = rho.len();
    let group = with_solid(params, rho, theta);
    let mut k = [0.0; MAX_MATERIALS * MAX_MATERIALS];
    slip_coefficients(params.k, &group[..n], weight, &mut k[..n * n]);
    k
}
