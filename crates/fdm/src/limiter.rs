//! The face limiter of the Lax–Wendroff step: at each face, the largest
//! share ℓ ∈ [0, 1] of the scheme's own flux that keeps the cells on both
//! sides of the face within bounds, the rest taken from the first-order
//! local Lax–Friedrichs (Rusanov) flux. Two bounds:
//!
//! - **positivity**, everywhere: ρ > 0 and internal energy per volume
//!   ρe > 0 ([`admissible`]);
//! - **the local density bounds at a shock**: at a compressive face
//!   ([`is_compressive`]) the density of each side stays within the
//!   smallest and largest density of that cell and its two neighbours
//!   before the sweep ([`density_share`]) — flux-corrected transport
//!   (Boris and Book, J. Comput. Phys. 11, 1973; Zalesak, J. Comput. Phys.
//!   31, 1979), applied where Lax–Wendroff's dispersive ripple sits: behind
//!   a shock.
//!
//! The construction is the convex limiting of Guermond, Nazarov, Popov and
//! Tomas (SIAM J. Sci. Comput. 40, 2018) and Kuzmin (Comput. Methods Appl.
//! Mech. Engrg. 361, 2020), with the positivity set of Zhang and Shu
//! (J. Comput. Phys. 229, 2010) and Hu, Adams and Shu (J. Comput. Phys.
//! 242, 2013). With U^L the cell's first-order (Rusanov) update and
//! A_f = G_f − F^L_f the antidiffusive flux at a face (G the scheme's own
//! face flux, F^L the Rusanov one), the limited update of a cell with faces
//! + and − is
//!
//! U = U^L − λ (ℓ₊ A₊ − ℓ₋ A₋) = ½ (U^L − 2λ ℓ₊ A₊) + ½ (U^L + 2λ ℓ₋ A₋),
//!
//! an average of two "half states", each of which depends on one face only.
//! The admissible set is convex (ρe = E − |ρu|²/2ρ is concave in U), and so
//! is an interval of densities, so a cell is within bounds when both its
//! half states are; choosing each ℓ_f as the largest value that keeps the
//! half states on *both* sides of face f within bounds therefore keeps
//! every cell within bounds, face by face, with no iteration and no
//! dependence on anything but the stencils of the face's two cells — so a
//! patch computes the same ℓ at a face it shares with its neighbour, and
//! the result does not depend on the patch split. ℓ = 1 wherever the half
//! states already are within bounds: such a face keeps the scheme's flux,
//! bit for bit.
//!
//! The first-order update itself is admissible for a Courant number
//! λ max(|u| + c) ≤ 1 (Perthame and Shu, Numer. Math. 73, 1996), which the
//! time step keeps at the start of the step. The half states ask more of a
//! face than the cell update does (a factor 2 on its antidiffusive flux),
//! so the limiter may act at a face whose cells would have stayed positive
//! without it: at a sharp initial discontinuity, typically in the first
//! step only.

/// Which bounds the face limiter keeps.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum FaceLimiter {
    /// Positivity everywhere and the local density bounds at compressive
    /// faces (the default).
    #[default]
    Full,
    /// Positivity only.
    Positivity,
    /// None: the scheme of seed 001 as printed, which stops at a
    /// non-physical state.
    Off,
}

impl FaceLimiter {
    /// Whether positivity is kept.
    pub fn positivity(self) -> bool {
        !matches!(self, Self::Off)
    }

    /// Whether the local density bounds are kept at compressive faces.
    pub fn shock_bounds(self) -> bool {
        matches!(self, Self::Full)
    }
}

/// A face is at a shock when the velocity along the sweep falls by more
/// than this fraction of the sound speed across one of the three faces
/// centred on it ([`is_compressive`]): a shock of Mach 1.05 spread over
/// three cells, while acoustic waves of a few per cent in pressure and
/// uniform flow (velocity differences of round-off size) stay below it.
pub const SHOCK_COMPRESSION: f64 = 0.02;

/// Whether a face is compressive: with the velocities along the sweep of
/// the cells a − 1, a, a + 1, a + 2 around face a + ½ and `c` the smaller
/// sound speed of its two cells, the velocity falls by more than
/// [`SHOCK_COMPRESSION`]·c across one of the faces a − ½, a + ½, a + 3/2.
#[inline(always)]
pub fn is_compressive(u: [f64; 4], c: f64) -> bool {
    let (d0, d1, d2) = (u[1] - u[0], u[2] - u[1], u[3] - u[2]);
    let min = |x: f64, y: f64| if x < y { x } else { y };
    -min(min(d0, d1), d2) > SHOCK_COMPRESSION * c
}

/// The smallest and largest of three densities (a cell and its two
/// neighbours along the sweep) and the first-order density `low` (which
/// need not lie within the neighbours' range).
#[inline(always)]
pub fn density_range(neighbours: [f64; 3], low: f64) -> (f64, f64) {
    let [a, b, c] = neighbours;
    let min = |x: f64, y: f64| if x < y { x } else { y };
    let max = |x: f64, y: f64| if x > y { x } else { y };
    (min(min(a, b), min(c, low)), max(max(a, b), max(c, low)))
}

/// The largest ℓ ∈ [0, 1] for which the density `low + ℓ·d` stays within
/// `[lo, hi]` ([`density_range`], which contains `low`): exact, the bound
/// is linear.
#[inline]
pub fn density_share(low: f64, d: f64, lo: f64, hi: f64) -> f64 {
    let end = low + d;
    if end > hi {
        ((hi - low) / d).clamp(0.0, 1.0)
    } else if end < lo {
        ((lo - low) / d).clamp(0.0, 1.0)
    } else {
        1.0
    }
}

/// The part of a conservative state the admissible set depends on.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FlowState {
    /// Density ρ, kg/m³.
    pub density: f64,
    /// Momentum per volume ρu, kg/(m² s).
    pub momentum: [f64; 3],
    /// Total energy per volume E, J/m³.
    pub energy: f64,
}

impl FlowState {
    /// Internal energy per volume ρe = E − |ρu|²/(2ρ), J/m³.
    #[inline]
    pub fn internal_energy(&self) -> f64 {
        let m = self.momentum;
        self.energy - 0.5 * (m[0] * m[0] + m[1] * m[1] + m[2] * m[2]) / self.density
    }

    /// 2ρ·ρe = 2ρE − |ρu|², the internal energy per volume without the
    /// division, J kg/m⁶.
    #[inline]
    pub fn twice_rho_internal(&self) -> f64 {
        let m = self.momentum;
        2.0 * self.density * self.energy - (m[0] * m[0] + m[1] * m[1] + m[2] * m[2])
    }

    /// `self + s·d`.
    #[inline]
    pub fn plus(&self, s: f64, d: &Self) -> Self {
        Self {
            density: self.density + s * d.density,
            momentum: std::array::from_fn(|k| self.momentum[k] + s * d.momentum[k]),
            energy: self.energy + s * d.energy,
        }
    }
}

/// Fraction of the first-order state's density and internal energy that a
/// limited half state keeps at least: admissible means ρ ≥ δρ^L and
/// ρe ≥ δ(ρe)^L, with δ this value. It keeps the limited states a
/// round-off margin away from zero without acting where the scheme is
/// merely near a vacuum.
pub const MARGIN: f64 = 1e-10;

/// Whether `w` lies in the admissible set relative to the first-order
/// state of density `low_density` and 2ρ·ρe = `low_q2`
/// ([`FlowState::twice_rho_internal`]): ρ ≥ δρ^L and ρe ≥ δ(ρe)^L
/// (δ = [`MARGIN`]), all finite. Division-free (ρe ≥ δ(ρe)^L is
/// q₂ ρ^L ≥ δ q₂^L ρ for positive densities) and branch-free, so a loop
/// over faces vectorises.
#[inline(always)]
pub fn admissible(w: &FlowState, low_density: f64, low_q2: f64) -> bool {
    let q2 = w.twice_rho_internal();
    (w.density >= MARGIN * low_density)
        & (q2 * low_density >= MARGIN * low_q2 * w.density)
        & (q2 < f64::INFINITY)
}

/// The largest ℓ ∈ [0, 1] for which `low + ℓ·d` is admissible (ρ and ρe at
/// least [`MARGIN`] times those of `low`), or 0 when `low` itself is not
/// (ρ ≤ 0, ρe ≤ 0 or a value not finite).
///
/// The density bound is linear in ℓ and solved exactly; ρe(ℓ) is concave,
/// so the ℓ it allows form an interval [0, ℓ*], found by 60 bisections
/// (ℓ* to 1e-18; the result is the lower, admissible end).
pub fn largest_admissible_share(low: &FlowState, d: &FlowState) -> f64 {
    let (rho0, q0) = (low.density, low.twice_rho_internal());
    if !(rho0 > 0.0 && q0 > 0.0 && q0 < f64::INFINITY) {
        return 0.0;
    }
    let mut top = 1.0f64;
    if d.density < 0.0 {
        top = top.min((1.0 - MARGIN) * rho0 / -d.density);
    }
    let ok = |s: f64| admissible(&low.plus(s, d), rho0, q0);
    if ok(top) {
        return top;
    }
    let (mut lo, mut hi) = (0.0, top);
    for _ in 0..60 {
        let mid = 0.5 * (lo + hi);
        if ok(mid) {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    lo
}

/// ℓ at one face from the half states of its two cells: the left cell's
/// first-order state `low_left` moved by −`w_left`·A and the right cell's
/// `low_right` moved by +`w_right`·A, where A is the antidiffusive change
/// per unit weight. 1 when both half states are admissible as they are.
pub fn face_share(
    low_left: &FlowState,
    w_left: f64,
    low_right: &FlowState,
    w_right: f64,
    a: &FlowState,
) -> f64 {
    let scaled = |s: f64| FlowState {
        density: s * a.density,
        momentum: a.momentum.map(|m| s * m),
        energy: s * a.energy,
    };
    let dl = scaled(-w_left);
    let dr = scaled(w_right);
    largest_admissible_share(low_left, &dl).min(largest_admissible_share(low_right, &dr))
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    fn st(density: f64, u: f64, energy: f64) -> FlowState {
        FlowState {
            density,
            momentum: [density * u, 0.0, 0.0],
            energy,
        }
    }

    #[test]
    fn internal_energy_is_total_minus_kinetic() {
        // ρ = 2, u = 3: ½ρu² = 9; E = 10 → ρe = 1.
        assert!((st(2.0, 3.0, 10.0).internal_energy() - 1.0).abs() < 1e-15);
    }

    #[test]
    fn an_admissible_step_is_kept_whole() {
        let low = st(1.0, 0.0, 2.5);
        let d = st(0.1, 0.0, 0.1);
        assert_eq!(largest_admissible_share(&low, &d), 1.0);
    }

    #[test]
    fn the_density_bound_is_solved_exactly() {
        // ρ = 1 + ℓ(−4): zero at ℓ = 0.25; energy kept positive by a large E.
        let low = st(1.0, 0.0, 100.0);
        let d = st(-4.0, 0.0, 0.0);
        let l = largest_admissible_share(&low, &d);
        assert!((l - 0.25 * (1.0 - MARGIN)).abs() < 1e-15, "{l}");
        assert!(low.plus(l, &d).density > 0.0);
    }

    #[test]
    fn the_internal_energy_bound_is_found_by_bisection() {
        // ρ = 1, m = 0, E = 1 at rest; d adds momentum 2 and no energy:
        // ρe(ℓ) = 1 − (2ℓ)²/2 = 1 − 2ℓ², zero at ℓ = 1/√2.
        let low = st(1.0, 0.0, 1.0);
        let d = FlowState {
            density: 0.0,
            momentum: [2.0, 0.0, 0.0],
            energy: 0.0,
        };
        let l = largest_admissible_share(&low, &d);
        let exact = ((1.0 - MARGIN) / 2.0f64).sqrt();
        assert!(l <= exact && exact - l < 1e-15, "{l} vs {exact}");
    }

    #[test]
    fn an_inadmissible_first_order_state_gives_zero() {
        assert_eq!(
            largest_admissible_share(&st(-1.0, 0.0, 1.0), &st(0.0, 0.0, 0.0)),
            0.0
        );
        assert_eq!(
            largest_admissible_share(&st(1.0, 2.0, 1.0), &st(0.0, 0.0, 0.0)),
            0.0
        );
        let nan = st(1.0, 0.0, f64::NAN);
        assert_eq!(largest_admissible_share(&nan, &st(0.0, 0.0, 0.0)), 0.0);
    }

    #[test]
    fn a_face_takes_the_smaller_share_of_its_two_sides() {
        // Left loses density −A·w_left: ρ_L = 1 − 2ℓ (ℓ ≤ ½); the right
        // gains it and is fine.
        let a = FlowState {
            density: 1.0,
            momentum: [0.0; 3],
            energy: 0.0,
        };
        let l = face_share(&st(1.0, 0.0, 10.0), 2.0, &st(1.0, 0.0, 10.0), 2.0, &a);
        assert!((l - 0.5 * (1.0 - MARGIN)).abs() < 1e-15, "{l}");
    }

    #[test]
    fn a_shock_is_a_fall_of_velocity_across_the_face_window() {
        // c = 1: a fall of 0.03 across the middle face is a shock, 0.01 is not.
        assert!(is_compressive([1.0, 1.0, 0.97, 0.97], 1.0));
        assert!(!is_compressive([1.0, 1.0, 0.99, 0.99], 1.0));
        // An expansion is not, whatever its size.
        assert!(!is_compressive([0.0, 0.5, 1.0, 1.5], 1.0));
        // The fall may be at either outer face of the window.
        assert!(is_compressive([1.0, 0.9, 0.9, 0.9], 1.0));
        assert!(is_compressive([1.0, 1.0, 1.0, 0.9], 1.0));
        // Uniform flow with round-off is not.
        assert!(!is_compressive([1.0, 1.0 + 2e-16, 1.0 - 2e-16, 1.0], 1.0));
    }

    #[test]
    fn the_density_share_keeps_the_local_bounds() {
        // ρ^L = 1 within [0.5, 2]: +3 would reach 4, allowed up to 2 → ℓ = 1/3.
        assert!((density_share(1.0, 3.0, 0.5, 2.0) - 1.0 / 3.0).abs() < 1e-15);
        // −1 would reach 0, allowed down to 0.5 → ℓ = 0.5.
        assert_eq!(density_share(1.0, -1.0, 0.5, 2.0), 0.5);
        // Within bounds: the whole step.
        assert_eq!(density_share(1.0, 0.5, 0.5, 2.0), 1.0);
        // A first-order density outside the neighbours' range widens it:
        // ρ^L = 3 above [0.5, 2] may stay at 3 but not rise.
        assert_eq!(density_range([0.5, 2.0, 1.0], 3.0), (0.5, 3.0));
        let (lo, hi) = density_range([0.5, 2.0, 1.0], 3.0);
        assert_eq!(density_share(3.0, 1.0, lo, hi), 0.0);
        assert_eq!(density_share(3.0, -1.0, lo, hi), 1.0);
    }

    proptest! {
        /// Whatever the step, the limited state is admissible whenever the
        /// first-order state is, and the share lies in [0, 1].
        #[test]
        fn the_limited_state_is_admissible(
            rho in 1e-6f64..1e3, u in -1e4f64..1e4, f in 1e-6f64..1e3,
            dr in -1e3f64..1e3, dm in -1e6f64..1e6, de in -1e9f64..1e9,
        ) {
            // Internal energy a share f of the kinetic (plus 1 J/m³), so
            // that it is not lost to round-off in E.
            let kinetic = 0.5 * rho * u * u;
            let low = FlowState { density: rho, momentum: [rho * u, 0.0, 0.0], energy: f * (kinetic + 1.0) + kinetic };
            let d = FlowState { density: dr, momentum: [dm, 0.0, 0.0], energy: de };
            let l = largest_admissible_share(&low, &d);
            prop_assert!((0.0..=1.0).contains(&l));
            let w = low.plus(l, &d);
            prop_assert!(w.density > 0.0, "{w:?}");
            prop_assert!(w.internal_energy() > 0.0, "{w:?}");
        }
    }
}
