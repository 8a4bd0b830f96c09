//! Step 12 of seed 000 §3.3: advection of mass, momentum, internal energy
//! and material volume through the cell faces with the face velocities
//! u*_r of step 3.
//!
//! The second-order scheme is van Leer's with "compatible fluxes"
//! (VanderHeyden & Kashiwa, J. Comput. Phys. 146 (1998), seed 000 ref 15):
//! the mass in the slab of the donor cell that crosses a face in Δt is
//! integrated exactly over the donor's limited linear profile of ρ, and
//! every specific quantity φ (velocity, internal energy, specific volume)
//! crosses with that mass at the value of its own limited profile at the
//! slab's centre of mass. A flux of ρφ is therefore (mass flux)·φ̂, so a
//! uniform φ stays uniform exactly and φ̂ stays within the donor's
//! neighbours' values, which is what "compatible" means there. Material
//! volume (θ = ρv per unit volume) is advected as the specific volume v
//! carried by the mass, as the seed's step 12 says ("converted to
//! material volume for advection").
//!
//! Limited differences use van Leer's harmonic mean
//! 2ab/(a + b) (zero at extrema), which keeps the profile inside the
//! neighbouring cell averages. Each face is fluxed from its donor cell
//! along the face normal only (no corner transport), as in Uintah's ICE;
//! the time step honours Σ_d |u_d| Δt/Δx_d ≤ CFL.
//!
//! Donor cell (first order) uses the donor's cell averages.
//!
//! `Compressive` adds interface capturing: the THINC reconstruction of a
//! material's volume fraction in its interface cells (Xiao, Honma & Kono
//! 2005; Shyue & Xiao 2014), see [`donor_volume_slab`].

use serde::{Deserialize, Serialize};

/// The advection scheme of step 12.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
pub enum Advection {
    /// First-order donor cell (upwind).
    DonorCell,
    /// Second-order van Leer with compatible fluxes (seed 000 ref 15).
    #[default]
    VanLeer,
    /// Interface capturing: in a material's interface cells (its volume
    /// fraction strictly between its neighbours' and away from 0 and 1)
    /// the fluxed volume fraction comes from the THINC profile
    /// ([`thinc_slab_fraction`]) and the mass crosses with it at the
    /// donor's material density, in step 12 and in the θ* of step 5 alike;
    /// elsewhere each material's density profile is limited with Roe's
    /// superbee ([`superbee_difference`]). A contact stays within about
    /// two cells. Carried quantities keep van Leer's limiter.
    Compressive,
}

/// Roe's superbee limited difference (Roe 1985; LeVeque, *Finite Volume
/// Methods for Hyperbolic Problems*, 2002, §6.11):
/// sign(a) max(min(2|a|, |b|), min(|a|, 2|b|)) when the backward and
/// forward differences a, b share a sign, zero at an extremum. It is the
/// most compressive limiter of the TVD region, so the profile's face values
/// stay within the neighbouring cell averages.
#[inline]
pub fn superbee_difference(back: f64, forward: f64) -> f64 {
    if back * forward > 0.0 {
        let (a, b) = (back.abs(), forward.abs());
        back.signum() * (2.0 * a).min(b).max(a.min(2.0 * b))
    } else {
        0.0
    }
}

/// The limited difference of a material's density under `scheme`.
#[inline]
pub fn density_difference(scheme: Advection, back: f64, forward: f64) -> f64 {
    match scheme {
        Advection::DonorCell => 0.0,
        Advection::VanLeer => van_leer_difference(back, forward),
        Advection::Compressive => superbee_difference(back, forward),
    }
}

/// The limited difference of a carried specific quantity under `scheme`.
#[inline]
pub fn carried_difference(scheme: Advection, back: f64, forward: f64) -> f64 {
    match scheme {
        Advection::DonorCell => 0.0,
        Advection::VanLeer | Advection::Compressive => van_leer_difference(back, forward),
    }
}

/// van Leer's limited difference of a cell from the backward and forward
/// differences of its neighbours: 2ab/(a + b) when they share a sign,
/// zero at an extremum. Units of the quantity (a difference across one
/// cell width).
#[inline]
pub fn van_leer_difference(back: f64, forward: f64) -> f64 {
    if back * forward > 0.0 {
        2.0 * back * forward / (back + forward)
    } else {
        0.0
    }
}

/// The slab of the donor cell that crosses a face in one step.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FluxedSlab {
    /// Mean density ρ̂ of the slab (units of ρ).
    pub mean_density: f64,
    /// Centre of mass of the slab relative to the donor's centre, in cell
    /// widths (between −½ and ½).
    pub centroid: f64,
}

/// The width a = min(|courant|, 1) of the donor's slab that crosses a
/// face, in cell widths.
///
/// A slab is part of its donor cell, so it is at most the whole cell: a
/// face whose Courant number exceeds one (no step of a stable run has one)
/// takes the whole donor, its flux courant · ρ̂ growing linearly in the
/// face velocity instead of quadratically through the reconstruction
/// evaluated outside the cell. The implicit pressure's outer iterations
/// meet such faces on their way to a converged step (the first iterate's
/// face velocities are those of eq 19 at p_eq over a step that is not an
/// acoustic one), and a slab reaching outside its cell there made the
/// iteration diverge (docs/physics/ice/implicit_pressure.md).
#[inline]
pub fn slab_width(courant: f64) -> f64 {
    courant.abs().min(1.0)
}

/// The slab that crosses a face whose Courant number is `courant` =
/// u* Δt/Δx (signed: positive when the donor is the low-side cell), taken
/// from a donor with cell average `rho` and limited difference `drho`
/// (ρ(ξ) = rho + drho·ξ, ξ in cell widths from its centre).
///
/// The slab is ξ ∈ [½ − a, ½] for a = [`slab_width`] on the donor's high
/// side (or its mirror); its mean is ρ(ξ_m) at the slab centre
/// ξ_m = ±(1 − a)/2 and its centre of mass is
/// (rho ξ_m + drho (ξ_m² + a²/12)) / ρ(ξ_m).
#[inline]
pub fn fluxed_slab(courant: f64, rho: f64, drho: f64, scheme: Advection) -> FluxedSlab {
    match scheme {
        Advection::DonorCell => FluxedSlab {
            mean_density: rho,
            centroid: 0.0,
        },
        Advection::VanLeer | Advection::Compressive => {
            let a = slab_width(courant);
            let xi_m = 0.5 * (1.0 - a) * courant.signum();
            let mean = rho + drho * xi_m;
            let centroid = if mean > 0.0 {
                (rho * xi_m + drho * (xi_m * xi_m + a * a / 12.0)) / mean
            } else {
                xi_m
            };
            FluxedSlab {
                mean_density: mean,
                centroid,
            }
        }
    }
}

/// Steepness β of the THINC profile: the value Xiao, Honma & Kono (2005)
/// recommend for sharp interfaces. The jump's 0.1–0.9 rise spans
/// 2 atanh(0.8)/β ≈ 0.63 of a cell. On the two-material Sod tube
/// (docs/physics/ice/steps.md) β = 3.5 kept the pressure within 0.34 % at
/// the contact; β = 2–2.5 left excursions of about 1 % (the mixed cells'
/// temperatures drift further from their sides').
pub const THINC_BETA: f64 = 3.5;

/// Volume fractions within this distance of 0 or 1 are not interface
/// cells (no THINC reconstruction: the trace of an absent material keeps
/// the density profile of [`donor_slab`]).
pub const THINC_CUTOFF: f64 = 1e-4;

/// ln cosh z without overflow: |z| + ln(1 + e^{−2|z|}) − ln 2.
#[inline]
fn ln_cosh(z: f64) -> f64 {
    let a = z.abs();
    a + (-2.0 * a).exp().ln_1p() - std::f64::consts::LN_2
}

/// The THINC reconstruction of a volume fraction (Xiao, Honma & Kono,
/// *A simple algebraic interface capturing scheme using hyperbolic tangent
/// function*, Int. J. Numer. Meth. Fluids 48 (2005) 1023–1040, eqs 5–9;
/// Shyue & Xiao, J. Comput. Phys. 268 (2014) 326–354, §4): in a donor
/// cell whose average θ lies strictly between its neighbours' (and
/// between [`THINC_CUTOFF`] and 1 − [`THINC_CUTOFF`]), the profile
///
/// θ(X) = ½ (1 + α tanh(β (X − X̃))),  X ∈ [0, 1] across the cell,
///
/// with α = sign(θ_forward − θ_back), β = [`THINC_BETA`] and the jump's
/// position X̃ fixed by the cell average, tanh(βX̃) = (cosh β − e^D)/sinh β,
/// D = β(2θ − 1)/α. Returns the mean of θ(X) over the slab that crosses
/// a face with Courant number `courant` (X ∈ [1 − a, 1] for courant > 0,
/// [0, a] for courant < 0, a = [`slab_width`]):
///
/// ½ [1 + α/(β a) (ln cosh β(X₁ − X̃) − ln cosh β(X₀ − X̃))],
///
/// or `None` where the cell is not an interface cell. For two materials
/// with θ₂ = 1 − θ₁ the two reconstructions are complementary
/// (θ₂(X) = 1 − θ₁(X)), so their slab fractions sum to one.
pub fn thinc_slab_fraction(courant: f64, back: f64, theta: f64, forward: f64) -> Option<f64> {
    let monotone = (back < theta && theta < forward) || (back > theta && theta > forward);
    if !(monotone && theta > THINC_CUTOFF && theta < 1.0 - THINC_CUTOFF) || courant == 0.0 {
        return None;
    }
    let beta = THINC_BETA;
    let alpha = if forward > back { 1.0 } else { -1.0 };
    let d = beta * (2.0 * theta - 1.0) / alpha;
    let t = (beta.cosh() - d.exp()) / beta.sinh();
    let x_jump = t.atanh() / beta;
    let a = slab_width(courant);
    let (x0, x1) = if courant > 0.0 {
        (1.0 - a, 1.0)
    } else {
        (0.0, a)
    };
    let integral = ln_cosh(beta * (x1 - x_jump)) - ln_cosh(beta * (x0 - x_jump));
    Some((0.5 * (1.0 + alpha * integral / (beta * a))).clamp(0.0, 1.0))
}

/// The backward and forward differences of `q` (a value per storage
/// index) at `donor`, neighbours `stride` apart.
#[inline]
fn one_sided(q: &impl Fn(usize) -> f64, donor: usize, stride: usize) -> (f64, f64) {
    let c = q(donor);
    (c - q(donor - stride), q(donor + stride) - c)
}

/// The slab a face with Courant number `courant` takes from `donor`,
/// whose material density is `rho(i)` per storage index: [`fluxed_slab`]
/// with the donor's [`density_difference`].
#[inline]
pub fn donor_slab(
    scheme: Advection,
    courant: f64,
    rho: impl Fn(usize) -> f64,
    donor: usize,
    stride: usize,
) -> FluxedSlab {
    let (back, forward) = one_sided(&rho, donor, stride);
    fluxed_slab(
        courant,
        rho(donor),
        density_difference(scheme, back, forward),
        scheme,
    )
}

/// The slab a face takes from `donor` and the specific volume it carries
/// (so its material volume is courant · mean density · that volume), from
/// the material's density `rho(i)` and specific volume `vsp(i)` per
/// storage index.
///
/// Under [`Advection::Compressive`], where the donor is an interface cell
/// of the material's volume fraction θ = ρv ([`thinc_slab_fraction`]), the
/// slab's volume fraction θ̂ comes from the THINC profile and the slab
/// carries the donor's own specific volume v_d: mass θ̂/v_d per unit slab
/// volume, material volume θ̂ — mass and volume cross together, at the
/// material's density in the donor, and the slab's centre of mass is taken
/// at its centre for the carried quantities. Elsewhere, and under the other
/// schemes, it is [`donor_slab`] with [`donor_carried`] of v.
#[inline]
pub fn donor_volume_slab(
    scheme: Advection,
    courant: f64,
    rho: impl Fn(usize) -> f64,
    vsp: impl Fn(usize) -> f64,
    donor: usize,
    stride: usize,
) -> (FluxedSlab, f64) {
    if scheme == Advection::Compressive {
        let theta = |i: usize| rho(i) * vsp(i);
        let v = vsp(donor);
        if let Some(f) = thinc_slab_fraction(
            courant,
            theta(donor - stride),
            theta(donor),
            theta(donor + stride),
        ) {
            let slab = FluxedSlab {
                mean_density: f / v,
                centroid: 0.5 * (1.0 - slab_width(courant)) * courant.signum(),
            };
            return (slab, v);
        }
    }
    let slab = donor_slab(scheme, courant, &rho, donor, stride);
    let v = donor_carried(scheme, &vsp, donor, stride, &slab);
    (slab, v)
}

/// The value of the specific quantity `phi(i)` that `slab` carries out of
/// `donor`: [`carried_value`] with the donor's [`carried_difference`].
#[inline]
pub fn donor_carried(
    scheme: Advection,
    phi: impl Fn(usize) -> f64,
    donor: usize,
    stride: usize,
    slab: &FluxedSlab,
) -> f64 {
    let (back, forward) = one_sided(&phi, donor, stride);
    carried_value(phi(donor), carried_difference(scheme, back, forward), slab)
}

/// Value of a specific quantity φ carried by the slab's mass: the donor's
/// limited profile φ + dφ·ξ at the slab's centre of mass.
#[inline]
pub fn carried_value(phi: f64, dphi: f64, slab: &FluxedSlab) -> f64 {
    phi + dphi * slab.centroid
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn superbee_is_the_most_compressive_tvd_difference() {
        // a = 1, b = 3: max(min(2, 3), min(1, 6)) = 2; a = 1, b = 1.5:
        // max(min(2, 1.5), min(1, 3)) = 1.5; signs kept; zero at extrema.
        assert_eq!(superbee_difference(1.0, 3.0), 2.0);
        assert_eq!(superbee_difference(-1.0, -3.0), -2.0);
        assert_eq!(superbee_difference(1.0, 1.5), 1.5);
        assert_eq!(superbee_difference(2.0, 2.0), 2.0);
        assert_eq!(superbee_difference(1.0, -1.0), 0.0);
        assert_eq!(superbee_difference(0.0, 1.0), 0.0);
        // van Leer's harmonic mean of (1, 3) is 1.5, less than superbee's.
        assert_eq!(density_difference(Advection::VanLeer, 1.0, 3.0), 1.5);
        assert_eq!(density_difference(Advection::Compressive, 1.0, 3.0), 2.0);
        assert_eq!(carried_difference(Advection::Compressive, 1.0, 3.0), 1.5);
        assert_eq!(density_difference(Advection::DonorCell, 1.0, 3.0), 0.0);
    }

    #[test]
    fn van_leer_difference_is_the_harmonic_mean_and_zero_at_extrema() {
        assert!((van_leer_difference(1.0, 3.0) - 1.5).abs() < 1e-15);
        assert_eq!(van_leer_difference(-1.0, 3.0), 0.0);
        assert_eq!(van_leer_difference(0.0, 3.0), 0.0);
        assert!((van_leer_difference(-2.0, -2.0) + 2.0).abs() < 1e-15);
    }

    #[test]
    fn donor_cell_flux_by_hand() {
        // Courant 0.3, donor ρ = 2, φ = 5: mass crossing per unit volume
        // 0.3·2 = 0.6, carrying 0.6·5 = 3 of ρφ.
        let s = fluxed_slab(0.3, 2.0, 0.7, Advection::DonorCell);
        assert_eq!(0.3 * s.mean_density, 0.6);
        assert_eq!(0.3 * s.mean_density * carried_value(5.0, 1.0, &s), 3.0);
    }

    #[test]
    fn van_leer_slab_integrates_the_linear_profile_exactly() {
        // ρ = 1 + 0.2ξ over ξ ∈ [0, 0.5]: mean 0.525/0.5 = 1.05; centre of
        // mass (0.125 + 0.2·0.125/3)/0.525.
        let s = fluxed_slab(0.5, 1.0, 0.2, Advection::VanLeer);
        assert!((s.mean_density - 1.05).abs() < 1e-15);
        let xc = (0.125 + 0.2 * 0.125 / 3.0) / 0.525;
        assert!((s.centroid - xc).abs() < 1e-15);
        // Mirror: donor on the high side, slab ξ ∈ [−0.5, 0].
        let m = fluxed_slab(-0.5, 1.0, -0.2, Advection::VanLeer);
        assert!((m.mean_density - 1.05).abs() < 1e-15);
        assert!((m.centroid + xc).abs() < 1e-15);
    }

    /// A slab is at most its donor cell: past a Courant number of one the
    /// slab (mean, centre of mass, THINC fraction) is the whole cell's, so
    /// the flux courant · ρ̂ grows linearly in the face velocity. Without
    /// the bound, ρ = 1 + 0.2ξ at courant 3 gave ρ̂ = 1 + 0.2·(−1) = 0.8 and
    /// at courant 6 a negative slab density.
    #[test]
    fn a_slab_is_at_most_its_donor_cell() {
        for scheme in [Advection::VanLeer, Advection::Compressive] {
            let whole = fluxed_slab(1.0, 1.0, 0.2, scheme);
            assert_eq!(whole.mean_density, 1.0);
            assert_eq!(whole.centroid, 0.2 / 12.0);
            for courant in [1.0 + 1e-12, 3.0, 6.0, 1e8] {
                assert_eq!(fluxed_slab(courant, 1.0, 0.2, scheme), whole);
                let m = fluxed_slab(-courant, 1.0, -0.2, scheme);
                assert_eq!(m.mean_density, 1.0);
                assert_eq!(m.centroid, -0.2 / 12.0);
            }
        }
        let f = thinc_slab_fraction(1.0, 0.1, 0.3, 0.9).unwrap();
        for courant in [2.0, 50.0] {
            assert_eq!(thinc_slab_fraction(courant, 0.1, 0.3, 0.9), Some(f));
            assert_eq!(slab_width(-courant), 1.0);
        }
        assert_eq!(slab_width(-0.25), 0.25);
    }

    #[test]
    fn a_uniform_specific_quantity_is_carried_unchanged() {
        let s = fluxed_slab(0.8, 3.0, -1.0, Advection::VanLeer);
        assert_eq!(carried_value(7.25, 0.0, &s), 7.25);
    }

    #[test]
    fn thinc_slab_fraction_by_hand() {
        // θ = ½ between 0 and 1: the jump sits at the centre (X̃ = ½), and
        // a slab of half a cell on the high side holds
        // ½[1 + (1/(β·½)) ln cosh(β/2)] of its volume.
        let b = THINC_BETA;
        let want = 0.5 * (1.0 + (0.5 * b).cosh().ln() / (0.5 * b));
        let f = thinc_slab_fraction(0.5, 0.0, 0.5, 1.0).unwrap();
        assert!((f - want).abs() < 1e-14, "{f} vs {want}");
        // The low-side slab (flow to −x) of the same cell is its mirror.
        let g = thinc_slab_fraction(-0.5, 0.0, 0.5, 1.0).unwrap();
        assert!((g - (1.0 - want)).abs() < 1e-14, "{g}");
        // A slab of the whole cell returns the cell average.
        let w = thinc_slab_fraction(1.0, 0.1, 0.3, 0.9).unwrap();
        assert!((w - 0.3).abs() < 1e-14, "{w}");
    }

    #[test]
    fn thinc_reconstructions_of_two_materials_are_complementary() {
        for (back, theta, forward) in [(0.0, 0.2, 1.0), (0.99, 0.7, 0.01), (0.3, 0.5, 0.6)] {
            for courant in [0.05, 0.4, -0.3, -0.01] {
                let f1 = thinc_slab_fraction(courant, back, theta, forward).unwrap();
                let f2 =
                    thinc_slab_fraction(courant, 1.0 - back, 1.0 - theta, 1.0 - forward).unwrap();
                assert!((f1 + f2 - 1.0).abs() < 1e-13, "{f1} + {f2}");
                // The slab never holds more than the cell: a f ≤ θ.
                assert!(courant.abs() * f1 <= theta * (1.0 + 1e-14));
                assert!((0.0..=1.0).contains(&f1));
            }
        }
    }

    #[test]
    fn thinc_only_in_interface_cells() {
        // An extremum, a plateau, a trace and a zero velocity: no THINC.
        assert_eq!(thinc_slab_fraction(0.3, 0.2, 0.5, 0.1), None);
        assert_eq!(thinc_slab_fraction(0.3, 0.5, 0.5, 0.6), None);
        assert_eq!(thinc_slab_fraction(0.3, 1e-6, 5e-5, 1e-3), None);
        assert_eq!(thinc_slab_fraction(0.0, 0.0, 0.5, 1.0), None);
        // Compressive outside interface cells is superbee's slab with van
        // Leer's carried volume; inside, the slab carries the donor's v.
        // θ = ρv = 1, 1, 0.5, 0.01: cell 1 is on a plateau, cell 2 an
        // interface cell.
        let rho = [1.0, 1.0, 0.25, 0.005];
        let vsp = [1.0, 1.0, 2.0, 2.0];
        let (slab, v) =
            donor_volume_slab(Advection::Compressive, 0.4, |i| rho[i], |i| vsp[i], 1, 1);
        assert_eq!(slab, fluxed_slab(0.4, 1.0, 0.0, Advection::Compressive));
        assert_eq!(v, 1.0);
        let (slab, v) =
            donor_volume_slab(Advection::Compressive, 0.4, |i| rho[i], |i| vsp[i], 2, 1);
        let f = thinc_slab_fraction(0.4, 1.0, 0.5, 0.01).unwrap();
        assert_eq!(v, 2.0);
        assert_eq!(slab.mean_density, f / 2.0);
        // van Leer never reconstructs with THINC.
        let (slab, _) = donor_volume_slab(Advection::VanLeer, 0.4, |i| rho[i], |i| vsp[i], 2, 1);
        assert_eq!(slab, donor_slab(Advection::VanLeer, 0.4, |i| rho[i], 2, 1));
    }
}
