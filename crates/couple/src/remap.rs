//! Remap of a 1D (planar, cylindrical, spherical) detonation profile onto a
//! 1D/2D/3D FDM grid as its initial state (seed 001 §4.1: "solving an 1D
//! TNT explosion problem first and map the result to the 3D region as the
//! initial condition in FDM region", after AUTODYN's remap).
//!
//! # Method: sub-cell sampling with a per-shell conservative correction
//!
//! The profile is piecewise constant in shells i of width h,
//! [r_i, r_{i+1}] = [i h, (i + 1) h], with conservative values
//! U_i = (ρ, ρu_r, E, ρY). Its exact content inside the remap radius R is
//! C_i = Ω L V_i U_i, with V_i = (r_{i+1}^{α+1} − r_i^{α+1})/(α + 1) the
//! shell volume per unit angle measure (r_{i+1} capped at R), Ω the angle
//! measure (2 for a slab — both sides —, 2π for a cylinder, 4π for a
//! sphere), halved for each symmetry plane through the centre, and L the
//! extent of the grid's inactive directions (its depth per cell).
//!
//! 1. Every target cell is cut into n sub-cells per active direction; a
//!    sub-cell whose centre lies at distance r < R from the charge centre
//!    belongs to shell ⌊r/h⌋. The count N_{c,i} of sub-cells of cell c in
//!    shell i, and the sum of their radial unit vectors Σ r̂, are recorded.
//! 2. The sampled volume of shell i is S_i = δV Σ_c N_{c,i} (δV the
//!    sub-cell volume). A shell too thin to hold a sub-cell centre
//!    (S_i = 0) passes its content to the next sampled shell outwards (or,
//!    at the rim, inwards): C'_i.
//! 3. Cell c receives, per shell, the content C'_i N_{c,i} δV / S_i — the
//!    sampled share of the shell, scaled by V_i^dom/S_i so that the shell's
//!    exact content is placed — for mass, energy and products mass; its
//!    momentum is Σ_i (C'_{ρu_r,i}/S_i) δV Σ r̂. The part of the cell outside
//!    R holds the ambient state.
//!
//! Mass, total energy, products mass and the radial-momentum integral
//! ∫ρu_r dV of the profile inside R are therefore placed exactly, to
//! round-off. The net vector momentum of the profile is zero (a full
//! sphere); the remapped one is zero to round-off when the sampling points
//! are mirror-symmetric about the centre (centre on a cell corner or
//! centre), and otherwise zero to the sampling error. The kinetic energy of
//! a cell is |Σρu|²/(2Σρ), at most the sampled one; the difference stays in
//! the cell's internal energy because the total energy E is what is mapped.
//! The correction factors V_i^dom/S_i are reported ([`RemapReport`]).
//!
//! The remap needs the burn to be complete (F = 1 in every charge cell,
//! eq 53): the 2D/3D FDM grid carries no program burn, so its pressure is
//! the EOS pressure of the mapped state, which equals the 1D pressure only
//! once F = 1.

use brisance_core::{Geometry, UniformGridGeometry};
use brisance_fdm::detonation::{RadialDetonation, Symmetry};
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

/// Why a remap cannot be done.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum RemapError {
    /// A parameter is out of range; the message names it.
    #[error("{0}")]
    Invalid(String),
}

fn invalid<T>(m: String) -> Result<T, RemapError> {
    Err(RemapError::Invalid(m))
}

/// A piecewise-constant radial profile of conservative values.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct RadialProfile {
    /// 0 planar, 1 cylindrical, 2 spherical.
    pub alpha: u8,
    /// Shell width h, m.
    pub cell_size: f64,
    /// (ρ, ρu_r, E, ρY) per shell, from the centre outwards.
    pub cells: Vec<[f64; 4]>,
    /// The undisturbed ambient state (ρ, 0, E, 0) placed outside the remap
    /// radius.
    pub ambient: [f64; 4],
    /// Time of the 1D run, s.
    pub time: f64,
}

/// α of a symmetry: 0, 1, 2 for planar, cylindrical, spherical.
pub fn alpha_of(symmetry: Symmetry) -> u8 {
    match symmetry {
        Symmetry::Planar => 0,
        Symmetry::Cylindrical => 1,
        Symmetry::Spherical => 2,
    }
}

impl RadialProfile {
    /// The profile of a 1D detonation run. Fails while a charge cell is
    /// still burning (F < 1, eq 53).
    pub fn from_detonation(run: &RadialDetonation) -> Result<Self, RemapError> {
        if !run.burn_complete() {
            return invalid(format!(
                "time = {:e} s: the 1D detonation has not burnt completely (F < 1 in a charge cell); \
                 remap after t = charge_radius/D + 1.5 h/D",
                run.time()
            ));
        }
        let s = run.setup();
        let e_air =
            brisance_core::Eos::specific_internal_energy(&s.air, s.air_density, s.air_pressure)
                .map_err(|e| RemapError::Invalid(format!("ambient air state: {e}")))?;
        Ok(Self {
            alpha: alpha_of(s.symmetry),
            cell_size: run.cell_size(),
            cells: (0..s.cells).map(|i| run.conservative(i)).collect(),
            ambient: [s.air_density, 0.0, s.air_density * e_air, 0.0],
            time: run.time(),
        })
    }

    /// Outer radius of the profile, m.
    pub fn outer_radius(&self) -> f64 {
        self.cells.len() as f64 * self.cell_size
    }

    /// Volume per unit angle measure of [a, b]: (b^{α+1} − a^{α+1})/(α+1).
    pub fn shell_volume(&self, a: f64, b: f64) -> f64 {
        let k = i32::from(self.alpha) + 1;
        (b.powi(k) - a.powi(k)) / f64::from(k)
    }

    /// Full angle measure Ω: 2, 2π, 4π.
    pub fn angle_measure(&self) -> f64 {
        match self.alpha {
            0 => 2.0,
            1 => 2.0 * std::f64::consts::PI,
            _ => 4.0 * std::f64::consts::PI,
        }
    }

    fn validate(&self) -> Result<(), RemapError> {
        if self.alpha > 2 {
            return invalid(format!("profile alpha = {} must be 0, 1 or 2", self.alpha));
        }
        if !(self.cell_size > 0.0 && self.cell_size.is_finite()) {
            return invalid(format!(
                "profile cell_size = {} m must be positive",
                self.cell_size
            ));
        }
        if self.cells.is_empty() {
            return invalid("profile has no cells".into());
        }
        if let Some(i) = self
            .cells
            .iter()
            .position(|u| !(u[0] > 0.0) || u.iter().any(|x| !x.is_finite()))
        {
            return invalid(format!(
                "profile cell {i} has density {} (must be positive) or a non-finite value",
                self.cells[i][0]
            ));
        }
        if !(self.ambient[0] > 0.0) || self.ambient.iter().any(|x| !x.is_finite()) {
            return invalid(format!(
                "ambient density {} must be positive and finite",
                self.ambient[0]
            ));
        }
        Ok(())
    }
}

/// Where and how to remap.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RemapTarget {
    /// The target grid; its active directions (more than one cell) must
    /// number 1 for a planar, 2 for a cylindrical, 3 for a spherical
    /// profile.
    pub geometry: UniformGridGeometry,
    /// Charge centre, m (inactive directions ignored).
    pub centre: [f64; 3],
    /// Remap radius R, m (None: the profile's outer radius).
    pub radius: Option<f64>,
    /// Sub-cells per active direction (None: ⌈Δx/h⌉ clamped to [2, 16]).
    pub subsamples: Option<usize>,
    /// How the target's cells are read. `Axisymmetric`: an (r, z) grid
    /// (x = r from r = 0, y = z, one cell along the third direction) of
    /// rings about the axis, onto which a spherical profile centred on the
    /// axis is mapped; every sub-cell then stands for its ring, of volume
    /// 2π r_s δA (δA its cross-section), and the content is the whole
    /// sphere's (Ω = 4π, halved only by a plane z = const through the
    /// centre).
    pub coordinates: Geometry,
}

impl RemapTarget {
    /// Whether the target is an (r, z) grid of rings, after checking what
    /// that needs: one cell along the third direction, r from 0, the
    /// centre on the axis.
    fn geometry_kind_is_rings(&self) -> Result<bool, RemapError> {
        if !self.geometry_is_axisymmetric() {
            return Ok(false);
        }
        let g = &self.geometry;
        if g.cells[2] != 1 {
            return invalid(format!(
                "an Axisymmetric target is (r, z) with one cell along the third direction, got cells {:?}",
                g.cells
            ));
        }
        if g.origin[0] != 0.0 {
            return invalid(format!(
                "an Axisymmetric target's r starts on the axis, r = 0; got lower.0 = {}",
                g.origin[0]
            ));
        }
        if self.centre[0] != 0.0 {
            return invalid(format!(
                "centre.x = {} m: on an Axisymmetric target the charge centre is on the axis (r = 0)",
                self.centre[0]
            ));
        }
        Ok(true)
    }

    fn geometry_is_axisymmetric(&self) -> bool {
        self.coordinates.is_axisymmetric()
    }
}

/// Totals of a remap (each over the whole target grid, J, kg, kg·m/s).
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub struct RemapTotals {
    /// Mass, kg.
    pub mass: f64,
    /// Radial-momentum integral ∫ρu_r dV, kg·m/s.
    pub radial_momentum: f64,
    /// Total energy, J.
    pub energy: f64,
    /// Products mass ∫ρY dV, kg.
    pub products: f64,
}

/// What a remap did.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct RemapReport {
    /// The profile's content inside R restricted to the domain (Ω L Σ V_i U_i).
    pub charge: RemapTotals,
    /// The ambient state's content placed outside R (its radial momentum 0).
    pub ambient: RemapTotals,
    /// Sum over the grid of the mapped cells: mass, momentum vector,
    /// energy, products (Σ U_c V_c).
    pub grid_mass: f64,
    /// Σ (ρu)_c V_c, kg·m/s.
    pub grid_momentum: [f64; 3],
    /// Σ E_c V_c, J.
    pub grid_energy: f64,
    /// Σ (ρY)_c V_c, kg.
    pub grid_products: f64,
    /// Sub-cells per active direction.
    pub subsamples: usize,
    /// Remap radius, m.
    pub radius: f64,
    /// Symmetry planes through the centre (faces of the grid).
    pub symmetry_planes: usize,
    /// Shells too thin to be sampled, merged into a neighbour.
    pub merged_shells: usize,
    /// Largest |V_i^dom/S_i − 1| over the sampled shells.
    pub max_correction: f64,
}

/// The remapped initial state: (ρ, ρu, ρv, ρw, E, ρY) per cell, global
/// order (x fastest), with the report.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Remapped {
    /// The target grid.
    pub geometry: UniformGridGeometry,
    /// Six arrays of cell values.
    pub fields: Vec<Vec<f64>>,
    /// Totals and diagnostics.
    pub report: RemapReport,
}

impl Remapped {
    /// Writes the remapped state (bincode) to `path`.
    pub fn save(&self, path: &std::path::Path) -> Result<(), RemapError> {
        let bytes = bincode::serialize(self)
            .map_err(|e| RemapError::Invalid(format!("cannot encode the remap: {e}")))?;
        std::fs::write(path, bytes)
            .map_err(|e| RemapError::Invalid(format!("cannot write {}: {e}", path.display())))
    }

    /// Reads a remapped state written by [`Self::save`].
    pub fn load(path: &std::path::Path) -> Result<Self, RemapError> {
        let bytes = std::fs::read(path)
            .map_err(|e| RemapError::Invalid(format!("cannot read {}: {e}", path.display())))?;
        let r: Self = bincode::deserialize(&bytes).map_err(|e| {
            RemapError::Invalid(format!("{} is not a remap file: {e}", path.display()))
        })?;
        let n = r.geometry.cell_count();
        if r.fields.len() != 6 || r.fields.iter().any(|f| f.len() != n) {
            return invalid(format!(
                "{}: expected 6 fields of {n} cells",
                path.display()
            ));
        }
        Ok(r)
    }
}

/// Per cell: shells met by its sub-cells, (shell, count, Σ f r̂, Σ f) with
/// f the sub-cell's volume in units of δV: 1 on a Cartesian grid, 2π r_s
/// (r_s its radius) on an (r, z) grid, where δV is its cross-section δA.
type CellSamples = Vec<(usize, u64, [f64; 3], f64)>;

/// Maps `profile` onto `target` (module doc). Fails naming the field when
/// the grid's dimension does not match the profile's symmetry, or the remap
/// sphere crosses a face of the grid other than through its centre.
pub fn remap(profile: &RadialProfile, target: &RemapTarget) -> Result<Remapped, RemapError> {
    profile.validate()?;
    let g = target.geometry;
    let active: Vec<usize> = (0..3).filter(|&d| g.cells[d] > 1).collect();
    let rings = target.geometry_kind_is_rings()?;
    if rings && profile.alpha != 2 {
        return invalid(format!(
            "an Axisymmetric target takes a spherical profile (a sphere on the axis), not a {} one",
            ["planar", "cylindrical", "spherical"][usize::from(profile.alpha.min(2))]
        ));
    }
    let need = if rings {
        2
    } else {
        usize::from(profile.alpha) + 1
    };
    if active.len() != need {
        return invalid(format!(
            "target grid cells = {:?} has {} active directions; a {} profile needs {need}",
            g.cells,
            active.len(),
            ["planar", "cylindrical", "spherical"][usize::from(profile.alpha)]
        ));
    }
    if g.spacing.iter().any(|s| !(*s > 0.0 && s.is_finite())) {
        return invalid(format!(
            "target grid spacing {:?} must be positive",
            g.spacing
        ));
    }
    let h = profile.cell_size;
    let radius = target.radius.unwrap_or(profile.outer_radius());
    if !(radius > 0.0 && radius <= profile.outer_radius() * (1.0 + 1e-12)) {
        return invalid(format!(
            "radius = {radius} m must lie in (0, {}] (the profile's outer radius)",
            profile.outer_radius()
        ));
    }
    let radius = radius.min(profile.outer_radius());
    let c = target.centre;
    if c.iter().any(|x| !x.is_finite()) {
        return invalid(format!("centre {c:?} must be finite"));
    }
    let upper = g.upper();
    const AXES: [&str; 3] = ["x", "y", "z"];
    let mut planes = 0usize;
    for &d in &active {
        if rings && d == 0 {
            // The axis r = 0 (checked): no symmetry plane, the rings go
            // all the way round.
            continue;
        }
        let tol = 1e-9 * g.spacing[d];
        let on_low = (c[d] - g.origin[d]).abs() <= tol;
        let on_high = (c[d] - upper[d]).abs() <= tol;
        let low_ok = on_low || c[d] - radius >= g.origin[d] - tol;
        let high_ok = on_high || c[d] + radius <= upper[d] + tol;
        if !(low_ok && high_ok) || (on_low && on_high) {
            return invalid(format!(
                "centre.{} = {} m with radius {radius} m: the remap sphere must lie inside the grid \
                 ({} .. {} m) or be cut by a face through its centre (a symmetry plane)",
                AXES[d], c[d], g.origin[d], upper[d]
            ));
        }
        planes += usize::from(on_low || on_high);
    }
    let n = target.subsamples.unwrap_or_else(|| {
        let dx = active.iter().map(|&d| g.spacing[d]).fold(0.0, f64::max);
        ((dx / h).ceil() as usize).clamp(2, 16)
    });
    if n == 0 || n > 64 {
        return invalid(format!("subsamples = {n} must lie in [1, 64]"));
    }
    // On an (r, z) grid the third direction is the ring's revolution, which
    // the sub-cells' 2π r_s carry.
    let inactive_extent: f64 = if rings {
        1.0
    } else {
        (0..3)
            .filter(|d| !active.contains(d))
            .map(|d| g.spacing[d])
            .product()
    };
    let omega = profile.angle_measure() * 0.5f64.powi(planes as i32);
    let shells = ((radius / h).ceil() as usize).clamp(1, profile.cells.len());
    let cell_volume: f64 = if rings {
        g.spacing[0] * g.spacing[1]
    } else {
        g.spacing.iter().product()
    };
    let per_cell = n.pow(active.len() as u32) as u64;
    let sub_volume = cell_volume / per_cell as f64;
    // A cell's volume in units of δV (Σ f over its sub-cells): per_cell,
    // or on an (r, z) grid 2π r_c per_cell (the midpoint rule of ∫2πr dA,
    // exact: the ring π(r₊² − r₋²)Δz).
    let cell_weight = |lin: usize| {
        if rings {
            let i = lin % g.cells[0];
            let r_c = g.origin[0] + (i as f64 + 0.5) * g.spacing[0];
            2.0 * std::f64::consts::PI * r_c * per_cell as f64
        } else {
            per_cell as f64
        }
    };

    // 1. Sampling, in parallel over cells; each cell's list is formed in
    // a fixed order, and shell counts are integers: the same bits whatever
    // the thread count.
    let count = g.cell_count();
    let samples: Vec<CellSamples> = (0..count)
        .into_par_iter()
        .map(|lin| sample_cell(&g, &active, c, radius, h, shells, n, rings, lin))
        .collect();
    let mut shell_count = vec![0u64; shells];
    let mut shell_weight = vec![0.0f64; shells];
    for s in &samples {
        for &(i, k, _, f) in s {
            shell_count[i] += k;
            shell_weight[i] += f;
        }
    }
    // 2. Exact content per shell and the merge of unsampled shells.
    let mut content: Vec<[f64; 4]> = (0..shells)
        .map(|i| {
            let (a, b) = (i as f64 * h, ((i + 1) as f64 * h).min(radius));
            let v = omega * inactive_extent * profile.shell_volume(a, b);
            profile.cells[i].map(|u| u * v)
        })
        .collect();
    let mut charge = RemapTotals::default();
    for q in &content {
        charge.mass += q[0];
        charge.radial_momentum += q[1];
        charge.energy += q[2];
        charge.products += q[3];
    }
    let Some(last_sampled) = (0..shells).rev().find(|&i| shell_count[i] > 0) else {
        return invalid(format!(
            "radius = {radius} m holds no sub-cell centre of the grid; refine subsamples or enlarge the radius"
        ));
    };
    let mut merged = 0;
    for i in 0..shells {
        if shell_count[i] == 0 {
            let to = (i + 1..shells)
                .find(|&j| shell_count[j] > 0)
                .unwrap_or(last_sampled);
            let q = content[i];
            for (t, v) in content[to].iter_mut().zip(q) {
                *t += v;
            }
            content[i] = [0.0; 4];
            merged += 1;
        }
    }
    let mut max_correction: f64 = 0.0;
    let density: Vec<[f64; 4]> = (0..shells)
        .map(|i| {
            if shell_count[i] == 0 {
                return [0.0; 4];
            }
            // Σ f = the count on a Cartesian grid (integers, exact).
            let s = shell_weight[i] * sub_volume;
            let (a, b) = (i as f64 * h, ((i + 1) as f64 * h).min(radius));
            let exact = omega * inactive_extent * profile.shell_volume(a, b);
            max_correction = max_correction.max((exact / s - 1.0).abs());
            content[i].map(|q| q / s)
        })
        .collect();

    // 3. Cell values.
    let amb = profile.ambient;
    let mut fields: Vec<Vec<f64>> = vec![vec![0.0; count]; 6];
    let mut ambient = RemapTotals::default();
    for (lin, s) in samples.iter().enumerate() {
        let mut mass = 0.0;
        let mut mom = [0.0; 3];
        let mut energy = 0.0;
        let mut products = 0.0;
        let mut covered = 0.0f64;
        for &(i, _, dir, f) in s {
            let w = f * sub_volume;
            let q = density[i];
            mass += w * q[0];
            energy += w * q[2];
            products += w * q[3];
            for (m, r) in mom.iter_mut().zip(dir) {
                *m += q[1] * sub_volume * r;
            }
            covered += f;
        }
        let free = (cell_weight(lin) - covered) * sub_volume;
        ambient.mass += free * amb[0];
        ambient.energy += free * amb[2];
        ambient.products += free * amb[3];
        let inv = if rings {
            1.0 / (cell_weight(lin) * sub_volume)
        } else {
            1.0 / cell_volume
        };
        fields[0][lin] = (mass + free * amb[0]) * inv;
        for d in 0..3 {
            fields[1 + d][lin] = mom[d] * inv;
        }
        fields[4][lin] = (energy + free * amb[2]) * inv;
        fields[5][lin] = (products + free * amb[3]) * inv;
    }
    let mut report = RemapReport {
        charge,
        ambient,
        grid_mass: 0.0,
        grid_momentum: [0.0; 3],
        grid_energy: 0.0,
        grid_products: 0.0,
        subsamples: n,
        radius,
        symmetry_planes: planes,
        merged_shells: merged,
        max_correction,
    };
    let sum = |f: &[f64]| {
        if rings {
            f.iter()
                .enumerate()
                .map(|(lin, u)| u * cell_weight(lin) * sub_volume)
                .sum::<f64>()
        } else {
            f.iter().sum::<f64>() * cell_volume
        }
    };
    report.grid_mass = sum(&fields[0]);
    report.grid_momentum = std::array::from_fn(|d| sum(&fields[1 + d]));
    report.grid_energy = sum(&fields[4]);
    report.grid_products = sum(&fields[5]);
    Ok(Remapped {
        geometry: g,
        fields,
        report,
    })
}

/// The sub-cell samples of cell `lin` (linear index, x fastest).
#[allow(clippy::too_many_arguments)]
fn sample_cell(
    g: &UniformGridGeometry,
    active: &[usize],
    c: [f64; 3],
    radius: f64,
    h: f64,
    shells: usize,
    n: usize,
    rings: bool,
    lin: usize,
) -> CellSamples {
    let idx = [
        lin % g.cells[0],
        (lin / g.cells[0]) % g.cells[1],
        lin / (g.cells[0] * g.cells[1]),
    ];
    // Nearest distance from the cell box to the centre: skip cells
    // entirely outside R.
    let mut near2 = 0.0;
    for &d in active {
        let lo = g.origin[d] + idx[d] as f64 * g.spacing[d];
        let hi = lo + g.spacing[d];
        let q = c[d].clamp(lo, hi) - c[d];
        near2 += q * q;
    }
    let mut out: CellSamples = Vec::new();
    if near2 >= radius * radius {
        return out;
    }
    let dims = active.len();
    let total = n.pow(dims as u32);
    let inv_n = 1.0 / n as f64;
    for s in 0..total {
        let mut r2 = 0.0;
        let mut off = [0.0; 3];
        let mut rest = s;
        for &d in active {
            let k = rest % n;
            rest /= n;
            let x = g.origin[d] + (idx[d] as f64 + (k as f64 + 0.5) * inv_n) * g.spacing[d];
            off[d] = x - c[d];
            r2 += off[d] * off[d];
        }
        let r = r2.sqrt();
        if !(r < radius) {
            continue;
        }
        let shell = ((r / h) as usize).min(shells - 1);
        // The sub-cell's ring on an (r, z) grid (off[0] its radius, the
        // centre on the axis).
        let f = if rings {
            2.0 * std::f64::consts::PI * off[0]
        } else {
            1.0
        };
        let dir = if r > 0.0 {
            off.map(|o| f * (o / r))
        } else {
            [0.0; 3]
        };
        match out.iter_mut().find(|e| e.0 == shell) {
            Some(e) => {
                e.1 += 1;
                e.3 += f;
                for (a, b) in e.2.iter_mut().zip(dir) {
                    *a += b;
                }
            }
            None => out.push((shell, 1, dir, f)),
        }
    }
    out
}

/// A charge stated in a scenario: the 1D TNT detonation (seed 001 §4.1,
/// program burn, eqs 52–53) whose state at `time` a run remaps onto its
/// FDM grid itself (`pipeline.charge`), as `brisance remap` does.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Charge {
    /// The explosive; the 1D detonation knows TNT (seed 001 §4.1) only.
    pub explosive: String,
    /// Symmetry of the 1D run: `Planar` onto a 1D grid, `Cylindrical` onto
    /// 2D, `Spherical` onto 3D or onto an axisymmetric (r, z) grid.
    pub symmetry: ChargeSymmetry,
    /// Charge centre, m.
    pub centre: [f64; 3],
    /// Charge radius, m.
    pub radius: f64,
    /// Outer radius of the 1D grid, m.
    pub radius_1d: f64,
    /// Cells of the 1D grid.
    pub cells_1d: usize,
    /// Time of the 1D run to remap (after the burn is complete), s: the
    /// zero of the scenario's time.
    pub time: f64,
    /// Remap radius, m (default: the 1D grid's outer radius).
    #[serde(default)]
    pub remap_radius: Option<f64>,
    /// Sub-cells per direction (default ⌈Δx/h⌉ within [2, 16]).
    #[serde(default)]
    pub subsamples: Option<usize>,
}

/// [`Charge::symmetry`], as a config writes it.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum ChargeSymmetry {
    /// A slab.
    Planar,
    /// A cylinder.
    Cylindrical,
    /// A sphere.
    Spherical,
}

impl From<ChargeSymmetry> for Symmetry {
    fn from(s: ChargeSymmetry) -> Self {
        match s {
            ChargeSymmetry::Planar => Symmetry::Planar,
            ChargeSymmetry::Cylindrical => Symmetry::Cylindrical,
            ChargeSymmetry::Spherical => Symmetry::Spherical,
        }
    }
}

impl Charge {
    /// Checks the fields before the 1D run; the message names the field.
    pub fn validate(&self) -> Result<(), RemapError> {
        if !self.explosive.eq_ignore_ascii_case("tnt") {
            return invalid(format!(
                "explosive: `{}`: the 1D detonation knows TNT (seed 001 §4.1) only",
                self.explosive
            ));
        }
        for (name, v) in [
            ("radius", self.radius),
            ("radius_1d", self.radius_1d),
            ("time", self.time),
        ] {
            if !(v.is_finite() && v > 0.0) {
                return invalid(format!("{name} = {v} must be positive and finite"));
            }
        }
        if self.radius_1d <= self.radius {
            return invalid(format!(
                "radius_1d = {} must exceed the charge radius {}",
                self.radius_1d, self.radius
            ));
        }
        if self.cells_1d < 4 {
            return invalid(format!(
                "cells_1d = {} needs at least 4 cells",
                self.cells_1d
            ));
        }
        if !self.centre.iter().all(|c| c.is_finite()) {
            return invalid(format!("centre {:?} must be finite", self.centre));
        }
        Ok(())
    }

    /// Runs the 1D detonation to `time` and remaps it onto `target`'s grid
    /// (whose centre, radius and sub-cells this charge sets): the run (for
    /// its profile and report) and the remapped state.
    pub fn detonate_and_remap(
        &self,
        geometry: UniformGridGeometry,
        coordinates: Geometry,
    ) -> Result<(RadialDetonation, Remapped), RemapError> {
        self.validate()?;
        let setup = brisance_fdm::detonation::DetonationSetup::tnt_in_air(
            self.symmetry.into(),
            self.radius,
            self.radius_1d,
            self.cells_1d,
        );
        let mut run =
            RadialDetonation::new(setup).map_err(|e| RemapError::Invalid(e.to_string()))?;
        run.run_until(self.time)
            .map_err(|e| RemapError::Invalid(e.to_string()))?;
        let profile = RadialProfile::from_detonation(&run)?;
        let target = RemapTarget {
            geometry,
            centre: self.centre,
            radius: self.remap_radius,
            subsamples: self.subsamples,
            coordinates,
        };
        let mapped = remap(&profile, &target)?;
        Ok((run, mapped))
    }

    /// A key of everything the remap of this charge onto `geometry`
    /// depends on (the charge, the grid, its coordinates and the program's
    /// version), for caching its result: FNV-1a over their exact text.
    pub fn cache_key(&self, geometry: &UniformGridGeometry, coordinates: Geometry) -> u64 {
        let text = format!(
            "{self:?}|{:?}|{:?}|{:?}|{coordinates:?}|{}",
            geometry.origin,
            geometry.spacing,
            geometry.cells,
            env!("CARGO_PKG_VERSION")
        );
        text.bytes().fold(0xcbf2_9ce4_8422_2325_u64, |h, b| {
            (h ^ u64::from(b)).wrapping_mul(0x0000_0100_0000_01b3)
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use brisance_fdm::detonation::DetonationSetup;

    fn geometry(origin: [f64; 3], spacing: [f64; 3], cells: [usize; 3]) -> UniformGridGeometry {
        UniformGridGeometry {
            origin,
            spacing,
            cells,
        }
    }

    #[test]
    fn planar_profile_onto_a_line_is_the_hand_computed_average() {
        // Shells of 1 mm with distinct values; target cells of 2 mm from
        // −4 to 4 mm: cell [0, 2] mm holds shells 0 and 1 exactly, so it is
        // their mean; cell [−2, 0] mm is its mirror image, momentum negated.
        let profile = RadialProfile {
            alpha: 0,
            cell_size: 1e-3,
            cells: vec![
                [4.0, 8.0, 100.0, 4.0],
                [2.0, 6.0, 50.0, 1.0],
                [1.0, 1.0, 10.0, 0.0],
                [1.0, 0.0, 10.0, 0.0],
            ],
            ambient: [1.0, 0.0, 10.0, 0.0],
            time: 0.0,
        };
        let target = RemapTarget {
            geometry: geometry([-4e-3, 0.0, 0.0], [2e-3, 1.0, 1.0], [4, 1, 1]),
            centre: [0.0; 3],
            radius: None,
            subsamples: Some(4),
            coordinates: Geometry::Cartesian,
        };
        let r = remap(&profile, &target).unwrap();
        let f = &r.fields;
        let close = |a: f64, b: f64| assert!((a - b).abs() <= 1e-14 * b.abs(), "{a} vs {b}");
        // Cell 2 = [0, 2] mm: ρ = (4 + 2)/2, ρu = (8 + 6)/2, E = 75, ρY = 2.5.
        close(f[0][2], 3.0);
        close(f[1][2], 7.0);
        close(f[4][2], 75.0);
        close(f[5][2], 2.5);
        close(f[1][1], -7.0);
        close(f[0][1], 3.0);
        // Cell 3 = [2, 4] mm: shells 2 and 3: ρ = 1, ρu = 0.5.
        close(f[0][3], 1.0);
        close(f[1][3], 0.5);
        assert!(r.report.max_correction < 1e-14);
        assert!(r.report.grid_momentum[0].abs() < 1e-14);
    }

    #[test]
    fn cylindrical_cell_inside_one_shell_holds_its_value_times_the_correction() {
        // A uniform profile: every cell entirely inside R holds the profile
        // value scaled by the correction V/S of the shells it meets; with
        // one shell spanning R that factor is the same for all of them, and
        // the grid total is the exact disc content π R² L U.
        let u = [2.0, 0.0, 7.0, 1.5];
        let profile = RadialProfile {
            alpha: 1,
            cell_size: 0.01,
            cells: vec![u],
            ambient: [1.0, 0.0, 3.0, 0.0],
            time: 0.0,
        };
        let target = RemapTarget {
            geometry: geometry([-0.02, -0.02, 0.0], [0.004, 0.004, 0.5], [10, 10, 1]),
            centre: [0.0; 3],
            radius: None,
            subsamples: Some(8),
            coordinates: Geometry::Cartesian,
        };
        let r = remap(&profile, &target).unwrap();
        let exact_area = std::f64::consts::PI * 0.01 * 0.01;
        // The centre cell [−0.004, 0]² lies entirely inside R = 0.01.
        let centre_cell = 4 + 10 * 4;
        let rho = r.fields[0][centre_cell];
        let e = r.fields[4][centre_cell];
        // Both fields carry the same factor V/S.
        assert!((rho / u[0] - e / u[2]).abs() < 1e-14);
        let sampled_area = exact_area / (rho / u[0]);
        // The sampled area is a whole number of sub-cells of 0.5 mm².
        let subs = sampled_area / (0.0005 * 0.0005);
        assert!((subs - subs.round()).abs() < 1e-6, "{subs}");
        let mass = r.report.grid_mass - r.report.ambient.mass;
        assert!((mass - u[0] * exact_area * 0.5).abs() < 1e-14 * mass);
    }

    #[test]
    fn spherical_detonation_remap_conserves_the_charge_to_round_off() {
        // 10 mm TNT sphere burnt through, onto a 3D grid with the centre on
        // a cell corner (full sphere) and on a face (half sphere).
        let setup = DetonationSetup::tnt_in_air(Symmetry::Spherical, 0.01, 0.03, 120);
        let mut run = RadialDetonation::new(setup).unwrap();
        run.run_until(2.2e-6).unwrap();
        let profile = RadialProfile::from_detonation(&run).unwrap();
        let (m1, e1, p1) = run.totals();
        for (centre, planes) in [([0.0, 0.0, 0.0], 0usize), ([0.0, -0.032, 0.0], 1)] {
            let target = RemapTarget {
                geometry: geometry([-0.032, -0.032, -0.032], [0.002; 3], [32, 32, 32]),
                centre,
                radius: None,
                subsamples: Some(6),
                coordinates: Geometry::Cartesian,
            };
            let r = remap(&profile, &target).unwrap();
            let rep = r.report;
            assert_eq!(rep.symmetry_planes, planes);
            let omega = 4.0 * std::f64::consts::PI / (1 << planes) as f64;
            let rel = |a: f64, b: f64| (a - b).abs() / b.abs();
            let mass = rep.grid_mass - rep.ambient.mass;
            let energy = rep.grid_energy - rep.ambient.energy;
            let products = rep.grid_products - rep.ambient.products;
            eprintln!(
                "planes {planes}: mass {:.3e}, energy {:.3e}, products {:.3e}, correction {:.3e}, merged {}",
                rel(mass, omega * m1),
                rel(energy, omega * e1),
                rel(products, omega * p1),
                rep.max_correction,
                rep.merged_shells
            );
            assert!(rel(mass, omega * m1) < 1e-12);
            assert!(rel(energy, omega * e1) < 1e-12);
            assert!(rel(products, omega * p1) < 1e-12);
            if planes == 0 {
                // Sub-cells mirror-symmetric about the centre: no net momentum.
                let scale = rep.charge.radial_momentum.abs();
                for m in rep.grid_momentum {
                    assert!(m.abs() < 1e-12 * scale, "{m} vs {scale}");
                }
            } else {
                // Cut by y = y_min: only the +y half, so net +y momentum.
                assert!(rep.grid_momentum[1] > 0.0);
            }
        }
    }

    #[test]
    fn an_unburnt_run_and_a_mismatched_grid_are_refused_naming_the_field() {
        let setup = DetonationSetup::tnt_in_air(Symmetry::Cylindrical, 0.01, 0.03, 60);
        let run = RadialDetonation::new(setup).unwrap();
        let e = RadialProfile::from_detonation(&run)
            .unwrap_err()
            .to_string();
        assert!(e.contains("burnt"), "{e}");
        let profile = RadialProfile {
            alpha: 1,
            cell_size: 1e-3,
            cells: vec![[1.0, 0.0, 1.0, 0.0]; 10],
            ambient: [1.0, 0.0, 1.0, 0.0],
            time: 0.0,
        };
        let mut target = RemapTarget {
            geometry: geometry([0.0; 3], [1e-3; 3], [20, 20, 20]),
            centre: [0.01, 0.01, 0.01],
            radius: None,
            subsamples: None,
            coordinates: Geometry::Cartesian,
        };
        let e = remap(&profile, &target).unwrap_err().to_string();
        assert!(e.contains("active directions"), "{e}");
        target.geometry.cells = [20, 20, 1];
        target.centre = [0.005, 0.01, 0.0];
        let e = remap(&profile, &target).unwrap_err().to_string();
        assert!(e.contains("centre.x"), "{e}");
        target.centre = [0.01, 0.01, 0.0];
        assert!(remap(&profile, &target).is_ok());
        target.radius = Some(0.02);
        let e = remap(&profile, &target).unwrap_err().to_string();
        assert!(e.contains("radius"), "{e}");
    }

    #[test]
    fn a_sphere_on_the_axis_of_an_rz_grid_places_its_content_in_rings() {
        // A spherical profile (shells of 1 mm, distinct values, radius
        // 10 mm) centred on the axis at z = 12 mm of an (r, z) grid of
        // 1.5 mm rings: the rings hold the whole sphere's mass, energy and
        // products to round-off (Ω = 4π, every sub-cell its ring 2π r_s δA),
        // the axial momentum is zero to the sampling's symmetry about
        // z = 12 mm, and the radial momentum Σ (ρu_r) V is positive. The
        // same remap onto the 3D quarter grid of the same spacing (two
        // symmetry planes) places the quarter sphere: the content agrees
        // after ×4.
        let cells: Vec<[f64; 4]> = (0..10)
            .map(|i| {
                let x = i as f64;
                [10.0 - x, 50.0 + x, 1.0e6 * (10.0 - x), 9.0 - x * 0.5]
            })
            .collect();
        let profile = RadialProfile {
            alpha: 2,
            cell_size: 1e-3,
            cells,
            ambient: [1.2, 0.0, 2.5e5, 0.0],
            time: 0.0,
        };
        let h = 1.5e-3;
        let rz = RemapTarget {
            geometry: geometry([0.0; 3], [h, h, 1.0], [10, 16, 1]),
            centre: [0.0, 0.012, 0.0],
            radius: None,
            subsamples: Some(6),
            coordinates: Geometry::Axisymmetric,
        };
        let r = remap(&profile, &rz).unwrap();
        let rep = r.report;
        assert_eq!(rep.symmetry_planes, 0);
        let close =
            |a: f64, b: f64, tol: f64| assert!((a - b).abs() <= tol * b.abs(), "{a} vs {b}");
        close(rep.grid_mass, rep.charge.mass + rep.ambient.mass, 1e-13);
        close(
            rep.grid_energy,
            rep.charge.energy + rep.ambient.energy,
            1e-13,
        );
        close(
            rep.grid_products,
            rep.charge.products + rep.ambient.products,
            1e-13,
        );
        let pi = std::f64::consts::PI;
        let sphere_mass: f64 = (0..10)
            .map(|i| {
                let (a, b) = (i as f64 * 1e-3, (i + 1) as f64 * 1e-3);
                4.0 * pi * (b.powi(3) - a.powi(3)) / 3.0 * (10.0 - i as f64)
            })
            .sum();
        close(rep.charge.mass, sphere_mass, 1e-13);
        assert!(rep.grid_momentum[0] > 0.0);
        assert!(rep.grid_momentum[1].abs() <= 1e-12 * rep.grid_momentum[0]);
        // Against the 3D quarter.
        let quarter = RemapTarget {
            geometry: geometry([0.0, 0.0, 0.0], [h; 3], [10, 10, 16]),
            centre: [0.0, 0.0, 0.012],
            radius: None,
            subsamples: Some(6),
            coordinates: Geometry::Cartesian,
        };
        let q = remap(&profile, &quarter).unwrap().report;
        close(4.0 * q.charge.mass, rep.charge.mass, 1e-13);
        close(4.0 * q.charge.energy, rep.charge.energy, 1e-13);
        // Refusals name what is wrong.
        let mut bad = rz;
        bad.centre = [0.001, 0.012, 0.0];
        let e = remap(&profile, &bad).unwrap_err().to_string();
        assert!(e.contains("axis"), "{e}");
        let mut cyl = profile.clone();
        cyl.alpha = 1;
        let e = remap(&cyl, &rz).unwrap_err().to_string();
        assert!(e.contains("spherical"), "{e}");
    }
}

#[cfg(test)]
mod remapped_run {
    use super::*;
    use brisance_core::Solver;
    use brisance_eos::{IdealGas, Jwl};
    use brisance_fdm::{FdmBoundary, FdmOptions, FdmSolver, PrimitiveState, ProductsInAir};
    use brisance_grid::Level;

    /// The remapped E-BLAST2D state (BRISANCE_REMAP = path of a remap.bin)
    /// run by the FDM alone on its grid with outflow faces and the
    /// face limiter the bridge uses, to 30 µs (or BRISANCE_END
    /// seconds).
    #[test]
    #[ignore = "needs a remap file from `brisance remap`; run by hand"]
    fn remapped_blast_runs_in_the_fdm_alone() {
        let path = std::env::var("BRISANCE_REMAP").expect("set BRISANCE_REMAP");
        let r = Remapped::load(std::path::Path::new(&path)).unwrap();
        let g = r.geometry;
        let level =
            Level::new(g.origin, g.upper(), g.cells, [1, 1, 1], brisance_fdm::GHOST).unwrap();
        let gas = ProductsInAir::new(Jwl::tnt(), IdealGas::air()).unwrap();
        let ambient = PrimitiveState {
            density: 1.225,
            velocity: [0.0; 3],
            pressure: 1.0e5,
        };
        let mut fdm = FdmSolver::new(
            gas,
            level,
            [FdmBoundary::Outflow; 6],
            FdmOptions::default(),
            |_| ambient,
        )
        .unwrap();
        fdm.set_conservative_fields(&r.fields).unwrap();
        let end: f64 = std::env::var("BRISANCE_END")
            .ok()
            .and_then(|s| s.parse().ok())
            .unwrap_or(3.0e-5);
        let mut steps = 0;
        let result = loop {
            if fdm.time() >= end {
                break Ok(());
            }
            let dt = match fdm.stable_dt() {
                Ok(dt) => dt,
                Err(e) => break Err(e),
            };
            if let Err(e) = fdm.advance(dt) {
                break Err(e);
            }
            steps += 1;
        };
        eprintln!(
            "FDM alone: {steps} steps to t = {:e} s: {result:?}",
            fdm.time()
        );
    }
}
