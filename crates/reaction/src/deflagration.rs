//! The deflagration model of seed 000 §4.1.2: a surface burn at the
//! pressure-power rate D = A pⁿ (seed 000 eq 38, after Son et al. 2000,
//! seed 000 ref. \[18\]) converted to a mass burn rate Γ = a D ρ_reactant
//! (seed 000 eq 39) in the cells that hold the explosive's surface.
//!
//! The seed leaves two things to the implementation:
//! - which cells hold the surface ("those cells which have the highest
//!   gradient of mass density of the reactant material"): here the cells
//!   that hold reactant and have a face neighbour (nearly) empty of it
//!   ([`detect_surface`]);
//! - the surface area a in such a cell ("estimated based on the direction of
//!   the gradient"): [`SurfaceArea`], three estimates from the unit normal
//!   n = −∇ρ/|∇ρ| and the cell size, and three that read the field. The
//!   default for a fluid reactant, [`SurfaceArea::Column`], is exact for a
//!   plane digitised by the detection rule above (one surface cell per grid
//!   column along the normal's dominant axis); for a particle reactant it is
//!   [`SurfaceArea::Gradient`] ([`Deflagration::surface_area_for`]); see
//!   docs/physics/reaction/deflagration.md.
//!
//! The burn only starts where the surface has reached the ignition
//! temperature (seed: "initiation of the burn depends on reaching a
//! threshold temperature at the surface"); the rate itself does not depend
//! on temperature.
//!
//! Grids are structured, cell-centred, with the x index fastest:
//! cell (i, j, k) is at `i + nx (j + ny k)`. An (r, z) grid is a grid with
//! `n = [nr, nz, 1]` whose areas are rings ([`SurfaceArea::ring_area`]).
//!
//! Units: SI. A in m·s⁻¹·Pa⁻ⁿ, p in Pa, D in m/s, ρ in kg/m³, a in m²,
//! Γ in kg/s.

use brisance_core::{ReactionModel, ReactionState};
use serde::{Deserialize, Serialize};

mod field_estimates;
pub use field_estimates::upwind_area_densities;
use field_estimates::{exposed_face_densities, gradient_densities};

/// Why a deflagration quantity cannot be formed.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum DeflagrationError {
    /// A parameter is out of range; the message names the field.
    #[error("deflagration: field `{field}` = {value}: {expected}")]
    InvalidParameter {
        /// The offending field.
        field: &'static str,
        /// Its value.
        value: f64,
        /// The expected range.
        expected: &'static str,
    },
    /// An estimate that reads the reactant's field (`upwind`,
    /// `exposed_faces`) was asked for where only the surface cells'
    /// normals are given.
    #[error(
        "deflagration: this surface area estimate reads the reactant's field, not only the \
         normals; use `surface_area_densities`"
    )]
    FieldNeeded,
    /// A field or output slice does not match the grid.
    #[error("deflagration: `{field}` has {len} entries, the grid has {cells} cells")]
    LengthMismatch {
        /// The offending slice.
        field: &'static str,
        /// Its length.
        len: usize,
        /// Cells in the grid.
        cells: usize,
    },
}

fn invalid<T>(
    field: &'static str,
    value: f64,
    expected: &'static str,
) -> Result<T, DeflagrationError> {
    Err(DeflagrationError::InvalidParameter {
        field,
        value,
        expected,
    })
}

/// The pressure-power burn law D = A pⁿ (seed 000 eq 38) with an ignition
/// temperature.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Deflagration {
    /// A, m·s⁻¹·Pa⁻ⁿ (eq 38).
    pub a: f64,
    /// n, pressure exponent (eq 38).
    pub n: f64,
    /// Surface temperature below which nothing burns, K.
    pub ignition_temperature: f64,
    /// How the solver estimates the surface's area in a cell from the
    /// reactant's volume fraction (seed 000 §4.1.2 leaves it open;
    /// [`SurfaceArea`]). Unset, the estimate follows the reactant
    /// ([`Deflagration::surface_area_for`]): `gradient` for a particle
    /// reactant, `column` for a fluid one.
    #[serde(default)]
    pub surface_area: Option<SurfaceArea>,
}

impl Deflagration {
    /// PBX-9501 with the constants of Uintah's `Simple_Burn` PBX input
    /// (`StandAlone/inputs/MPMICE/guni2dRT.ups`: mass flux 75.3 kg·m⁻²·s⁻¹
    /// at 101 325 Pa, the exponent 0.778 of `Simple_Burn.cc`, threshold
    /// temperature 450 K, reactant density 1840 kg/m³), converted to
    /// eq 38: A = (75.3 / 1840) · 101 325^−0.778 m·s⁻¹·Pa⁻⁰·⁷⁷⁸. No
    /// strand-burner data were at hand to fit; see
    /// docs/physics/reaction/deflagration.md for the caveat on the
    /// magnitude.
    pub fn pbx_9501() -> Self {
        Self {
            a: PBX_9501_A,
            n: PBX_9501_N,
            ignition_temperature: 450.0,
            surface_area: None,
        }
    }

    /// A validated model; the error names the first bad field.
    pub fn new(a: f64, n: f64, ignition_temperature: f64) -> Result<Self, DeflagrationError> {
        let model = Self {
            a,
            n,
            ignition_temperature,
            surface_area: None,
        };
        model.validate()?;
        Ok(model)
    }

    /// The surface-area estimate the solver uses for a reactant that is
    /// particles (`particles`, a Lagrangian material of the ICE–MPM) or a
    /// fluid: the configured one, or by default
    /// [`SurfaceArea::default_for`].
    pub fn surface_area_for(&self, particles: bool) -> SurfaceArea {
        self.surface_area
            .unwrap_or(SurfaceArea::default_for(particles))
    }

    /// Checks every parameter is finite and > 0, naming the bad field.
    pub fn validate(&self) -> Result<(), DeflagrationError> {
        if !(self.a > 0.0 && self.a.is_finite()) {
            return invalid("a", self.a, "a finite value > 0 (m·s⁻¹·Pa⁻ⁿ)");
        }
        if !(self.n > 0.0 && self.n.is_finite()) {
            return invalid("n", self.n, "a finite value > 0");
        }
        if !(self.ignition_temperature > 0.0 && self.ignition_temperature.is_finite()) {
            return invalid(
                "ignition_temperature",
                self.ignition_temperature,
                "a finite value > 0 (K)",
            );
        }
        Ok(())
    }

    /// Burn-front speed into the reactant D = A pⁿ (seed 000 eq 38), m/s;
    /// 0 where p ≤ 0 or the surface temperature is below the ignition
    /// temperature.
    #[inline]
    pub fn burn_speed(&self, pressure: f64, temperature: f64) -> f64 {
        if pressure > 0.0 && temperature >= self.ignition_temperature {
            self.a * pressure.powf(self.n)
        } else {
            0.0
        }
    }

    /// Mass burn rate Γ = a D ρ_reactant (seed 000 eq 39), kg/s, for a
    /// surface of area `area` (m²) in a cell whose reactant density is
    /// `reactant_density` (kg/m³). Divide by the cell volume for the
    /// source per unit volume of the ICE mass equation. Never negative.
    #[inline]
    pub fn mass_rate(
        &self,
        pressure: f64,
        temperature: f64,
        reactant_density: f64,
        area: f64,
    ) -> f64 {
        (area * self.burn_speed(pressure, temperature) * reactant_density).max(0.0)
    }
}

/// The deflagration as a [`ReactionModel`]: a surface burn
/// ([`ReactionModel::burns_on_a_surface`]), so the solver finds the
/// reactant's surface before each step and hands every cell its area per
/// unit volume a/V in [`ReactionState::surface_area_density`]
/// ([`surface_area_densities`]); [`ReactionState::temperature`] is the
/// surface temperature the ignition threshold is compared with.
///
/// - [`ReactionModel::burnt_density`] is eq 39 per unit cell volume over
///   the step: Γ Δt / V = (a/V) D ρ_reactant Δt with D = A pⁿ (eq 38) and
///   ρ_reactant the explosive's own density ([`ReactionState::density`]),
///   at most the cell's reactant.
/// - [`ReactionModel::rate`] is the same law as a burn fraction of a cell
///   full of reactant: dF/dt = (a/V) D, the fraction of the cell's volume
///   the front sweeps per second (0 once F = 1).
impl ReactionModel for Deflagration {
    fn name(&self) -> &'static str {
        "Deflagration"
    }

    fn burns_on_a_surface(&self) -> bool {
        true
    }

    fn rate(&self, state: &ReactionState, burn_fraction: f64) -> f64 {
        if burn_fraction >= 1.0 || !(state.surface_area_density > 0.0) {
            return 0.0;
        }
        (state.surface_area_density * self.burn_speed(state.pressure, state.temperature)).max(0.0)
    }

    #[inline]
    fn burnt_density(
        &self,
        state: &ReactionState,
        rho_reactant: f64,
        _rho_product: f64,
        dt: f64,
    ) -> f64 {
        // Γ/V of eq 39 with a/V the surface's area density.
        surface_burnt_density(state, rho_reactant, dt, || {
            state.surface_area_density
                * self.burn_speed(state.pressure, state.temperature)
                * state.density
        })
    }
}

/// The burnt mass per unit cell volume over a step of a model that burns
/// on a surface: Γ Δt / V with `gamma` = Γ / V (kg/(m³·s), evaluated only
/// on the surface), at most `rho_reactant`; 0 off the surface
/// (`surface_area_density` ≤ 0), without reactant, for a step ≤ 0 or where
/// Γ / V is not positive. Shared by [`Deflagration`] and
/// [`crate::Arrhenius`].
#[inline]
pub fn surface_burnt_density(
    state: &ReactionState,
    rho_reactant: f64,
    dt: f64,
    gamma: impl FnOnce() -> f64,
) -> f64 {
    if !(rho_reactant > 0.0 && state.surface_area_density > 0.0 && dt > 0.0) {
        return 0.0;
    }
    let gamma = gamma();
    if !(gamma > 0.0) {
        return 0.0;
    }
    (gamma * dt).min(rho_reactant)
}

/// Uintah `Simple_Burn` PBX mass flux at the reference pressure, kg·m⁻²·s⁻¹.
pub const UINTAH_PBX_9501_MASS_FLUX: f64 = 75.3;
/// Uintah `Simple_Burn` reference pressure, Pa.
pub const UINTAH_REFERENCE_PRESSURE: f64 = 101_325.0;
/// PBX-9501 reactant density in the Uintah input, kg/m³.
pub const UINTAH_PBX_9501_DENSITY: f64 = 1840.0;
/// n of [`Deflagration::pbx_9501`] (Uintah `Simple_Burn`).
pub const PBX_9501_N: f64 = 0.778;
/// A of [`Deflagration::pbx_9501`], m·s⁻¹·Pa⁻ⁿ:
/// (75.3 / 1840) · 101 325^−0.778 = 5.2183 × 10⁻⁶ (to 7 digits; the test
/// `pbx_9501_constants_reproduce_the_uintah_law` checks the conversion).
pub const PBX_9501_A: f64 = 5.218_307e-6;

/// How the surface area in a surface cell is estimated from the unit normal
/// ("an estimate of the surface area a is made based on the direction of
/// the gradient", seed 000 §4.1.2; the seed does not say how).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum SurfaceArea {
    /// The plane with the normal, clipped by the infinite column of cells
    /// along the axis k that maximises h_k |n_k|: a = V / max_k(h_k |n_k|).
    /// Exact for a plane digitised by [`detect_surface`], which flags one
    /// cell per such column.
    #[default]
    Column,
    /// The exact area of the polygon in which the plane with the normal
    /// through the cell centre cuts the cell (the largest section of the
    /// cell with that normal).
    ClippedPlane,
    /// The estimate of Uintah's HE burn models (`computeSurfaceArea` in
    /// `CCA/Components/Models/HEChem/Common.cc`):
    /// a = V / (Σ_k h_k |n_k|) · (max_k |n_k|)^(−1/3), the mean section of
    /// the cell over plane offsets times an empirical factor tuned for
    /// Uintah's own surface-cell rule.
    Uintah,
    /// The upwind estimate: in every cell holding reactant,
    /// a/V = Σ_k |n_k| J_k / h_k, J_k the drop of the reactant's volume
    /// fraction from the cell to its face neighbour on the side the normal
    /// points to along k (0 where it rises; a neighbour at or below the
    /// detection threshold counts as empty). The one-sided difference is
    /// the upwind (Godunov) discretisation of the front's level-set
    /// equation ∂θ/∂t + D|∇θ| = 0 (Osher & Sethian 1988, J. Comput. Phys.
    /// 79, 12–49), projected on the normal. Along each grid row the drops
    /// of a monotone front add up to the whole jump, so the summed area is
    /// exact for a plane of any orientation whatever the fractions of its
    /// cells (a ragged, partly burnt front included), and an error δ in the
    /// normal's direction changes it only by a factor cos δ. It reads the
    /// field, not only the normal: it has no per-cell form
    /// ([`SurfaceArea::area`] is `None`); see
    /// [`upwind_area_densities`]. The field must be a volume fraction.
    Upwind,
    /// The exposed faces' flux: on each surface cell of [`detect_surface`]
    /// (every one, not only the outermost of a column),
    /// a = max(0, Σ_f (n·e_f) A_f) over the cell's faces f whose neighbour
    /// is empty, e_f the face's outward unit normal and A_f its area. By
    /// the divergence theorem the exposed faces of a staircase give a
    /// constant n the area of the plane they cover, whatever the
    /// staircase: exact for a digitised plane at any orientation and for
    /// a ragged front (cells of a layer burnt at different times), and an
    /// error δ in the normal changes it by cos δ. It reads the field's
    /// neighbours: no per-cell form ([`SurfaceArea::area`] is `None`).
    ExposedFaces,
    /// The gradient's integral gathered onto the surface cells: every
    /// cell's |∇φ| V (Youngs gradient) goes to the surface cell of
    /// [`detect_surface`] met along the column of the cell's own normal
    /// (outward from a cell holding reactant, inward from an empty one,
    /// within [`GATHER_DEPTH`] cells), and a surface cell's area is the sum
    /// of what it gathers over the span of the field along its normal
    /// (the largest value inward less the smallest outward, within
    /// [`SPAN_DEPTH`] steps; 1 for a front from empty to full). By the
    /// coarea formula ∫|∇φ| dV over a front over that span is the mean
    /// area of its level sets (Federer 1959; the
    /// diffuse-interface area of phase-field and level-set methods): exact
    /// for a plane whatever the width of its profile, and for a curved
    /// front the area of its middle level to second order in the profile's
    /// width when the profile is symmetric. The `Column` estimate counts
    /// the surface where its surface cells lie, the outermost cells holding
    /// reactant; on a spread profile (a particle reactant's projection
    /// onto the cells, about four cells wide) those lie outside the
    /// reactant's face, and a curved surface's area there is too large.
    /// The field must be a volume fraction. No per-cell form
    /// ([`SurfaceArea::area`] is `None`).
    Gradient,
}

/// How many cells a cell's gradient travels along its column to the
/// surface cell that gathers it ([`SurfaceArea::Gradient`]); a gradient
/// further from the surface is not counted.
pub const GATHER_DEPTH: usize = 5;

/// How many steps the `Gradient` estimate looks along a surface cell's
/// normal, inward and outward, for the largest and smallest reactant
/// fraction it divides by ([`SurfaceArea::Gradient`]; a step is one cell
/// along the normal's dominant axis): twice the gathering's reach and one
/// more, so that a profile as wide as the gathering reaches is spanned
/// whole from its outermost cell.
pub const SPAN_DEPTH: usize = 2 * GATHER_DEPTH + 1;

impl SurfaceArea {
    /// The estimate a surface burn uses where its model names none:
    /// [`SurfaceArea::Gradient`] for a reactant that is particles
    /// (`particles`, a Lagrangian material of the ICE–MPM), whose
    /// projection spreads their face over about four cells (there the
    /// outermost cells holding reactant lie outside the face, and
    /// [`SurfaceArea::Column`] counts a curved surface too large: +42.6 %
    /// on V-BURNRATE's sphere against +0.4 %), and [`SurfaceArea::Column`]
    /// for a fluid, whose sharp face it digitises exactly when plane
    /// (docs/physics/reaction/deflagration.md).
    pub fn default_for(particles: bool) -> Self {
        if particles {
            Self::Gradient
        } else {
            Self::Column
        }
    }

    /// Area in a box cell of size `cell` (m) with unit normal `normal`, m²;
    /// `None` for [`SurfaceArea::Upwind`] and
    /// [`SurfaceArea::ExposedFaces`], which read the field's neighbours as
    /// well.
    #[inline]
    pub fn area(self, cell: [f64; 3], normal: [f64; 3]) -> Option<f64> {
        match self {
            Self::Column => Some(column_area(cell, normal)),
            Self::ClippedPlane => Some(clipped_plane_area(cell, normal)),
            Self::Uintah => Some(uintah_area(cell, normal)),
            Self::Upwind | Self::ExposedFaces | Self::Gradient => None,
        }
    }

    /// Area in the ring cell of an axisymmetric (r, z) grid, m²: the cell
    /// of size (dr, dz) at centre radius `r_centre` sweeps a ring, and the
    /// surface, a line in (r, z) with unit normal (n_r, n_z), a cone or
    /// disc of area 2π r_c × (its length in the cell, estimated as in 3D
    /// with a unit third side and n_θ = 0); `None` for
    /// [`SurfaceArea::Upwind`].
    #[inline]
    pub fn ring_area(self, dr: f64, dz: f64, r_centre: f64, normal_rz: [f64; 2]) -> Option<f64> {
        let length = self.area([dr, dz, 1.0], [normal_rz[0], normal_rz[1], 0.0])?;
        Some(2.0 * std::f64::consts::PI * r_centre * length)
    }
}

/// Area of the plane with unit normal `normal` clipped by the column of
/// cells along the axis k maximising h_k |n_k|, m²: V / max_k(h_k |n_k|).
pub fn column_area(cell: [f64; 3], normal: [f64; 3]) -> f64 {
    let volume = cell[0] * cell[1] * cell[2];
    let width = (0..3)
        .map(|k| cell[k] * normal[k].abs())
        .fold(0.0, f64::max);
    volume / width
}

/// Uintah's area estimate V / (Σ_k h_k |n_k|) · (max_k |n_k|)^(−1/3), m²
/// (see [`SurfaceArea::Uintah`]).
pub fn uintah_area(cell: [f64; 3], normal: [f64; 3]) -> f64 {
    let volume = cell[0] * cell[1] * cell[2];
    let width: f64 = (0..3).map(|k| cell[k] * normal[k].abs()).sum();
    let largest = normal.iter().fold(0.0_f64, |m, c| m.max(c.abs()));
    volume / width * largest.powf(-1.0 / 3.0)
}

/// Exact area of the section of the box of size `cell` (m) by the plane
/// through its centre with unit normal `normal`, m².
///
/// The section is projected on the coordinate plane normal to the axis k of
/// largest |n_k|: there it is the rectangle of the two other sides cut by
/// the strip |n_u u + n_v v| ≤ |n_k| h_k / 2, and the section's area is the
/// projection's area over |n_k|.
pub fn clipped_plane_area(cell: [f64; 3], normal: [f64; 3]) -> f64 {
    let k = (0..3)
        .max_by(|&a, &b| normal[a].abs().total_cmp(&normal[b].abs()))
        .unwrap_or(0);
    let (u, v) = ((k + 1) % 3, (k + 2) % 3);
    let (hu, hv) = (0.5 * cell[u], 0.5 * cell[v]);
    let nk = normal[k].abs();
    let half_width = nk * 0.5 * cell[k];
    let mut poly = [[0.0; 2]; 8];
    poly[..4].copy_from_slice(&[[-hu, -hv], [hu, -hv], [hu, hv], [-hu, hv]]);
    let mut len = 4;
    let (a, b) = (normal[u], normal[v]);
    len = clip_half_plane(&mut poly, len, a, b, half_width);
    len = clip_half_plane(&mut poly, len, -a, -b, half_width);
    shoelace(&poly[..len]) / nk
}

/// Clips the convex polygon `poly[..len]` by a u + b v ≤ c in place;
/// returns the new vertex count (a rectangle cut twice has at most 6).
fn clip_half_plane(poly: &mut [[f64; 2]; 8], len: usize, a: f64, b: f64, c: f64) -> usize {
    let mut out = [[0.0; 2]; 8];
    let mut m = 0;
    for i in 0..len {
        let p = poly[i];
        let q = poly[(i + 1) % len];
        let fp = a * p[0] + b * p[1] - c;
        let fq = a * q[0] + b * q[1] - c;
        if fp <= 0.0 {
            out[m] = p;
            m += 1;
        }
        if (fp < 0.0 && fq > 0.0) || (fp > 0.0 && fq < 0.0) {
            let t = fp / (fp - fq);
            out[m] = [p[0] + t * (q[0] - p[0]), p[1] + t * (q[1] - p[1])];
            m += 1;
        }
    }
    poly[..m].copy_from_slice(&out[..m]);
    m
}

fn shoelace(poly: &[[f64; 2]]) -> f64 {
    let n = poly.len();
    let twice: f64 = (0..n)
        .map(|i| {
            let (p, q) = (poly[i], poly[(i + 1) % n]);
            p[0] * q[1] - q[0] * p[1]
        })
        .sum();
    0.5 * twice.abs()
}

/// A structured cell-centred grid: `n` cells along x, y, z of size
/// `spacing` (m); x index fastest.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CellGrid {
    /// Cells along x, y, z (use 1 for a 2D or (r, z) grid).
    pub n: [usize; 3],
    /// Cell size along x, y, z, m.
    pub spacing: [f64; 3],
}

impl CellGrid {
    /// Number of cells.
    #[inline]
    pub fn cells(&self) -> usize {
        self.n[0] * self.n[1] * self.n[2]
    }

    /// Linear index of cell (i, j, k).
    #[inline]
    pub fn index(&self, i: usize, j: usize, k: usize) -> usize {
        i + self.n[0] * (j + self.n[1] * k)
    }

    /// Cell volume, m³.
    #[inline]
    pub fn cell_volume(&self) -> f64 {
        self.spacing[0] * self.spacing[1] * self.spacing[2]
    }
}

/// The finite-difference stencil of the reactant gradient.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum GradientStencil {
    /// (φ_{i+1} − φ_{i−1}) / 2h along each axis.
    Central,
    /// The central difference averaged over the 3 × 3 transverse cells with
    /// weights (1/4, 1/2, 1/4) in each transverse direction (Youngs'
    /// gradient; the same as Uintah's difference of node masses, each
    /// node the mean of its 8 cells). Far less noisy on a steep field.
    #[default]
    Youngs,
}

/// Options of [`detect_surface`].
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct SurfaceDetection {
    /// A cell holds reactant where its field value exceeds this; a
    /// neighbour at or below it counts as empty (same units as the field;
    /// for a volume fraction, a fraction).
    pub present_threshold: f64,
    /// Stencil of the gradient that gives the normal.
    pub stencil: GradientStencil,
    /// Keep only the outermost surface cell of each grid column along the
    /// normal's dominant axis: a flagged cell whose neighbour along that
    /// axis, on the side the normal points to, still holds reactant is
    /// dropped (the surface of its column lies further out). The `Column`
    /// estimate counts one cell per column; on a ragged front (a burn that
    /// has emptied some cells of a layer and not others) the rule without
    /// this flags two cells in a column and counts the area twice.
    pub outermost_in_column: bool,
    /// On an axisymmetric (r, z) grid (`n = [nr, nz, 1]`), the first
    /// cell's inner radius, m: [`SurfaceArea::Gradient`] weighs each
    /// cell's gradient by its ring's volume, 2π r_c Δr Δz, against the
    /// gathering cell's. `None` on a Cartesian grid.
    pub ring_inner_radius: Option<f64>,
}

impl Default for SurfaceDetection {
    fn default() -> Self {
        Self {
            present_threshold: 1.0e-6,
            stencil: GradientStencil::default(),
            outermost_in_column: false,
            ring_inner_radius: None,
        }
    }
}

/// Finds the surface cells of the reactant and their unit outward normals
/// n = −∇φ/|∇φ| (seed 000 §4.1.2: "the surface is assumed to lie within
/// those cells which have the highest gradient of mass density of the
/// reactant").
///
/// `reactant` is the reactant's mass density or volume fraction per cell.
/// A cell is a surface cell when it holds reactant (φ > threshold) and at
/// least one of its six face neighbours is empty (φ ≤ threshold): on a
/// sharp field these are the reactant cells on which the gradient is
/// largest, one layer thick, one cell per grid column along the normal's
/// dominant axis. Outside the grid the field is continued by its edge
/// value (a grid edge is neither a surface nor an empty neighbour).
///
/// Writes `on_surface` and `normal` (structure of arrays, zero normal off
/// the surface) and returns the number of surface cells. Where the
/// gradient vanishes on a surface cell (a sliver one cell thick) the
/// normal points to its empty neighbours (their mean direction, or the
/// first of them if they cancel).
pub fn detect_surface(
    grid: &CellGrid,
    reactant: &[f64],
    options: &SurfaceDetection,
    on_surface: &mut [bool],
    normal: [&mut [f64]; 3],
) -> Result<usize, DeflagrationError> {
    same_lengths(
        grid,
        &[
            ("reactant", reactant.len()),
            ("on_surface", on_surface.len()),
            ("normal[0]", normal[0].len()),
            ("normal[1]", normal[1].len()),
            ("normal[2]", normal[2].len()),
        ],
    )?;
    check_grid(grid, options)?;
    let [nx_out, ny_out, nz_out] = normal;
    let threshold = options.present_threshold;
    let field = Field { grid, reactant };
    let mut count = 0;
    for k in 0..grid.n[2] {
        for j in 0..grid.n[1] {
            for i in 0..grid.n[0] {
                let c = grid.index(i, j, k);
                let at = [i as isize, j as isize, k as isize];
                let empty = if reactant[c] > threshold {
                    field.empty_neighbours(at, threshold)
                } else {
                    None
                };
                let Some((toward_empty, first_empty)) = empty else {
                    on_surface[c] = false;
                    nx_out[c] = 0.0;
                    ny_out[c] = 0.0;
                    nz_out[c] = 0.0;
                    continue;
                };
                let g = field.gradient(at, options.stencil);
                let unit = outward_normal(g, Some((toward_empty, first_empty)));
                on_surface[c] = true;
                if options.outermost_in_column {
                    // The dominant axis (largest h_k |n_k|, the first on a
                    // tie) and the neighbour the normal points to along it.
                    let mut axis = 0;
                    for a in 1..3 {
                        if grid.spacing[a] * unit[a].abs() > grid.spacing[axis] * unit[axis].abs() {
                            axis = a;
                        }
                    }
                    let s = if unit[axis] >= 0.0 { 1 } else { -1 };
                    if field.neighbour(at, axis, s).is_some_and(|v| v > threshold) {
                        on_surface[c] = false;
                        nx_out[c] = 0.0;
                        ny_out[c] = 0.0;
                        nz_out[c] = 0.0;
                        continue;
                    }
                }
                count += 1;
                nx_out[c] = unit[0];
                ny_out[c] = unit[1];
                nz_out[c] = unit[2];
            }
        }
    }
    Ok(count)
}

/// Checks the cell sizes and the detection threshold, naming the bad one.
fn check_grid(grid: &CellGrid, options: &SurfaceDetection) -> Result<(), DeflagrationError> {
    for (axis, &h) in grid.spacing.iter().enumerate() {
        if !(h > 0.0 && h.is_finite()) {
            return invalid(
                ["spacing[0]", "spacing[1]", "spacing[2]"][axis],
                h,
                "a finite value > 0 (m)",
            );
        }
    }
    if !options.present_threshold.is_finite() {
        return invalid(
            "present_threshold",
            options.present_threshold,
            "a finite value",
        );
    }
    Ok(())
}

/// The field of [`detect_surface`] on its grid, continued outside the grid
/// by its edge value.
struct Field<'a> {
    grid: &'a CellGrid,
    reactant: &'a [f64],
}

const AXES: [[isize; 3]; 3] = [[1, 0, 0], [0, 1, 0], [0, 0, 1]];

impl Field<'_> {
    /// The value at cell `at`, clamped into the grid.
    fn at(&self, at: [isize; 3]) -> f64 {
        let n = self.grid.n;
        let c = |x: isize, m: usize| x.clamp(0, m as isize - 1) as usize;
        self.reactant[self
            .grid
            .index(c(at[0], n[0]), c(at[1], n[1]), c(at[2], n[2]))]
    }

    /// The value in the face neighbour of `at` at s·e_axis, where it lies
    /// inside the grid.
    fn neighbour(&self, at: [isize; 3], axis: usize, s: isize) -> Option<f64> {
        let mut p = at;
        p[axis] += s;
        let inside = (0..3).all(|d| p[d] >= 0 && (p[d] as usize) < self.grid.n[d]);
        inside.then(|| self.at(p))
    }

    /// Where cell `at` has face neighbours inside the grid at or below
    /// `threshold`: the sum of their directions and the first of them.
    fn empty_neighbours(&self, at: [isize; 3], threshold: f64) -> Option<([f64; 3], (usize, f64))> {
        let mut toward_empty = [0.0; 3];
        let mut first_empty = None;
        for (axis, toward) in toward_empty.iter_mut().enumerate() {
            for s in [1_isize, -1] {
                if self.neighbour(at, axis, s).is_some_and(|v| v <= threshold) {
                    *toward += s as f64;
                    first_empty.get_or_insert((axis, s as f64));
                }
            }
        }
        first_empty.map(|first| (toward_empty, first))
    }

    /// The gradient of the field at cell `at` by `stencil`, per metre.
    fn gradient(&self, at: [isize; 3], stencil: GradientStencil) -> [f64; 3] {
        let mut g = [0.0; 3];
        for (axis, e) in AXES.iter().enumerate() {
            let diff = |a: isize, b: isize| {
                // offsets a, b along the two transverse axes
                let (t1, t2) = (AXES[(axis + 1) % 3], AXES[(axis + 2) % 3]);
                let p = |s: isize| {
                    self.at(std::array::from_fn(|d| {
                        at[d] + s * e[d] + a * t1[d] + b * t2[d]
                    }))
                };
                p(1) - p(-1)
            };
            let d = match stencil {
                GradientStencil::Central => diff(0, 0),
                GradientStencil::Youngs => {
                    const W: [f64; 3] = [0.25, 0.5, 0.25];
                    let mut sum = 0.0;
                    for (wa, a) in W.iter().zip(-1..=1) {
                        for (wb, b) in W.iter().zip(-1..=1) {
                            sum += wa * wb * diff(a, b);
                        }
                    }
                    sum
                }
            };
            g[axis] = d / (2.0 * self.grid.spacing[axis]);
        }
        g
    }
}

/// The unit outward normal −g/|g|; where the gradient vanishes (a sliver
/// one cell thick), the mean direction of the empty neighbours, or the
/// first of them if they cancel (along +x without either).
fn outward_normal(g: [f64; 3], empty: Option<([f64; 3], (usize, f64))>) -> [f64; 3] {
    let mut m = [-g[0], -g[1], -g[2]];
    let mut len = norm(m);
    if !(len > 0.0) {
        let (toward_empty, (axis, s)) = empty.unwrap_or(([0.0; 3], (0, 1.0)));
        m = toward_empty;
        len = norm(m);
        if !(len > 0.0) {
            m = [0.0; 3];
            m[axis] = s;
            len = 1.0;
        }
    }
    [m[0] / len, m[1] / len, m[2] / len]
}

fn norm(v: [f64; 3]) -> f64 {
    (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt()
}

/// Refuses the estimates that read the field ([`SurfaceArea::Upwind`],
/// [`SurfaceArea::ExposedFaces`]) where only the surface cells' normals
/// are given.
fn cell_form(method: SurfaceArea) -> Result<(), DeflagrationError> {
    match method {
        SurfaceArea::Upwind | SurfaceArea::ExposedFaces | SurfaceArea::Gradient => {
            Err(DeflagrationError::FieldNeeded)
        }
        _ => Ok(()),
    }
}

/// Surface area in each cell from [`detect_surface`]'s output, m² (0 off
/// the surface); returns the total. For an (r, z) grid use
/// [`ring_surface_areas`]. [`SurfaceArea::Upwind`] and
/// [`SurfaceArea::ExposedFaces`] read the field, not only the normals:
/// refused here ([`surface_area_densities`] takes them).
pub fn surface_areas(
    grid: &CellGrid,
    method: SurfaceArea,
    on_surface: &[bool],
    normal: [&[f64]; 3],
    area: &mut [f64],
) -> Result<f64, DeflagrationError> {
    check_lengths(grid, on_surface, normal, area)?;
    cell_form(method)?;
    let mut total = 0.0;
    for c in 0..grid.cells() {
        area[c] = if on_surface[c] {
            method
                .area(grid.spacing, [normal[0][c], normal[1][c], normal[2][c]])
                .unwrap_or(0.0)
        } else {
            0.0
        };
        total += area[c];
    }
    Ok(total)
}

/// Ring surface area in each cell of an axisymmetric grid (`n = [nr, nz,
/// 1]`, r along the first axis, the first cell's inner radius `r_min`),
/// m²; returns the total. The estimates that read the field are refused,
/// as by [`surface_areas`].
pub fn ring_surface_areas(
    grid: &CellGrid,
    r_min: f64,
    method: SurfaceArea,
    on_surface: &[bool],
    normal: [&[f64]; 3],
    area: &mut [f64],
) -> Result<f64, DeflagrationError> {
    check_lengths(grid, on_surface, normal, area)?;
    cell_form(method)?;
    let [dr, dz, _] = grid.spacing;
    let mut total = 0.0;
    for k in 0..grid.n[2] {
        for j in 0..grid.n[1] {
            for i in 0..grid.n[0] {
                let c = grid.index(i, j, k);
                let r_centre = r_min + (i as f64 + 0.5) * dr;
                area[c] = if on_surface[c] {
                    method
                        .ring_area(dr, dz, r_centre, [normal[0][c], normal[1][c]])
                        .unwrap_or(0.0)
                } else {
                    0.0
                };
                total += area[c];
            }
        }
    }
    Ok(total)
}

/// Work arrays of [`surface_area_densities`] for a grid of `cells` cells,
/// kept between steps so that the surface pass allocates nothing.
#[derive(Debug, Clone, Default)]
pub struct SurfaceWork {
    /// Whether each cell is a surface cell.
    pub on_surface: Vec<bool>,
    /// The unit outward normal per cell (structure of arrays).
    pub normal: [Vec<f64>; 3],
}

impl SurfaceWork {
    /// Work arrays for `cells` cells.
    pub fn new(cells: usize) -> Self {
        Self {
            on_surface: vec![false; cells],
            normal: std::array::from_fn(|_| vec![0.0; cells]),
        }
    }
}

/// The reactant's surface area per unit cell volume a/V in every cell of
/// `grid`, 1/m (0 off the surface), from the field `reactant` (volume
/// fraction or density): [`detect_surface`], then `method`'s area over
/// the cell volume; [`SurfaceArea::ExposedFaces`] and
/// [`SurfaceArea::Upwind`] read the field's neighbours (the latter needs
/// a volume fraction; [`upwind_area_densities`]). The same a/V holds on
/// an axisymmetric (r, z) grid (`n = [nr, nz, 1]`): a ring's surface area
/// 2π r_c ℓ ([`SurfaceArea::ring_area`]) and its volume 2π r_c Δr Δz carry
/// the same 2π r_c, and ℓ/(Δr Δz) is the area density of the (r, z) cell
/// taken as a Cartesian one (for the two field estimates, a ring's faces
/// at r_c ± Δr/2 taken at r_c: an error of order Δr / r_c). Returns the
/// number of surface cells.
pub fn surface_area_densities(
    grid: &CellGrid,
    method: SurfaceArea,
    options: &SurfaceDetection,
    reactant: &[f64],
    work: &mut SurfaceWork,
    out: &mut [f64],
) -> Result<usize, DeflagrationError> {
    let cells = grid.cells();
    if work.on_surface.len() != cells {
        *work = SurfaceWork::new(cells);
    }
    same_lengths(grid, &[("out", out.len())])?;
    let [nx, ny, nz] = &mut work.normal;
    if method == SurfaceArea::Upwind {
        return upwind_area_densities(
            grid,
            reactant,
            options,
            &mut work.on_surface,
            [nx, ny, nz],
            out,
        );
    }
    if method == SurfaceArea::ExposedFaces {
        return exposed_face_densities(grid, reactant, options, work, out);
    }
    if method == SurfaceArea::Gradient {
        return gradient_densities(grid, reactant, options, work, out);
    }
    let count = detect_surface(grid, reactant, options, &mut work.on_surface, [nx, ny, nz])?;
    let volume = grid.cell_volume();
    for (c, a) in out.iter_mut().enumerate() {
        *a = if work.on_surface[c] {
            let n = [work.normal[0][c], work.normal[1][c], work.normal[2][c]];
            method.area(grid.spacing, n).unwrap_or(0.0) / volume
        } else {
            0.0
        };
    }
    Ok(count)
}

fn check_lengths(
    grid: &CellGrid,
    on_surface: &[bool],
    normal: [&[f64]; 3],
    area: &[f64],
) -> Result<(), DeflagrationError> {
    same_lengths(
        grid,
        &[
            ("on_surface", on_surface.len()),
            ("normal[0]", normal[0].len()),
            ("normal[1]", normal[1].len()),
            ("normal[2]", normal[2].len()),
            ("area", area.len()),
        ],
    )
}

/// The first of the named slice lengths that is not the grid's cell count,
/// as an error naming it.
fn same_lengths(
    grid: &CellGrid,
    slices: &[(&'static str, usize)],
) -> Result<(), DeflagrationError> {
    let cells = grid.cells();
    match slices.iter().find(|&&(_, len)| len != cells) {
        Some(&(field, len)) => Err(DeflagrationError::LengthMismatch { field, len, cells }),
        None => Ok(()),
    }
}

/// Least-squares fit of log D = log A + n log p over (p, D) pairs (Pa,
/// m/s); returns (A, n) and the residuals of log₁₀ D. Used to document the
/// constants of [`Deflagration::pbx_9501`]; needs two distinct pressures.
pub fn fit_power_law(points: &[(f64, f64)]) -> Option<(f64, f64, Vec<f64>)> {
    let m = points.len() as f64;
    if points.len() < 2 || points.iter().any(|&(p, d)| !(p > 0.0 && d > 0.0)) {
        return None;
    }
    let xs: Vec<f64> = points.iter().map(|&(p, _)| p.ln()).collect();
    let ys: Vec<f64> = points.iter().map(|&(_, d)| d.ln()).collect();
    let (mx, my) = (xs.iter().sum::<f64>() / m, ys.iter().sum::<f64>() / m);
    let sxx: f64 = xs.iter().map(|x| (x - mx).powi(2)).sum();
    let sxy: f64 = xs.iter().zip(&ys).map(|(x, y)| (x - mx) * (y - my)).sum();
    if !(sxx > 0.0) {
        return None;
    }
    let n = sxy / sxx;
    let ln_a = my - n * mx;
    let residuals = xs
        .iter()
        .zip(&ys)
        .map(|(x, y)| (y - (ln_a + n * x)) / std::f64::consts::LN_10)
        .collect();
    Some((ln_a.exp(), n, residuals))
}

#[cfg(test)]
mod tests;
