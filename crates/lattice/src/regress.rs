//! Surface regression of the lattice (seed 003 §2.4, fig. 9): pyrolysis of
//! the nodes exposed to a fluid.
//!
//! A solid node of a material with an Arrhenius law that has an exterior
//! neighbour marked as fluid (along a lattice axis) regresses in one step by
//!
//! r = Ω A exp(−Eₐ/(R T)) Δt / ρ₀
//!
//! (A the pre-exponential factor in kg/(m²·s), Eₐ the activation energy in
//! J/mol, T the node temperature, ρ₀ the material's initial density, Ω the
//! catalytic factor of §3.2), moving by r along the unit vector away from
//! the fluid. The law is [`brisance_reaction::Arrhenius`], a surface-burning
//! [`ReactionModel`]: the lattice asks it for r through the trait (its
//! `rate` at a unit area density and ρ₀). Its density is held constant: the regression sweeps the
//! volume of the node in proportion to the distance it has moved, and the
//! mass of every component falls with it, so m = ρ₀ V. When the volume
//! (hence the mass) vanishes, the node becomes an exterior fluid node and
//! its springs are removed, exposing the nodes behind it.
//!
//! *Choices where the seed is silent* (`docs/physics/lattice/regression.md`):
//!
//! - **Direction.** n̂ points from the node towards the fluid: the sum of
//!   the lattice offsets to the fluid nodes within `normal_radius` spacings.
//!   A radius of 1 is the seed's rule (away from the axial fluid
//!   neighbours); a wider radius gives the normal of the local surface
//!   rather than of its lattice staircase.
//! - **Volume.** The node loses V₀ r / (h max_a |n̂_a|) per step, V₀ its
//!   initial (dual-mesh) volume: it is empty after travelling one lattice
//!   layer along n̂, h max_a |n̂_a| (one row of a face at any angle), when
//!   it has reached the position of the layer behind it. The node's
//!   position is then the surface, and every layer takes the same time
//!   whatever the volume of its nodes' dual cells (cells cut by walls or by
//!   the body's boundary), so a face recedes at r along its normal and
//!   stays planar when n̂ is the face's normal. With the seed's radius 1,
//!   n̂ is the staircase's normal (axis or diagonal), and a front at φ
//!   from an axis recedes at (1 + (√2 − 1) tan φ)/√(1 + tan² φ) of r
//!   (`cases::staircase_rate`: 1 at 0° and 45°, 1.082 at 22.5°). Recomputing the dual-mesh volume of the moved node
//!   instead (the literal reading of §2.4) removes only 3/8 of the swept
//!   area per unit travel and empties the node after 4h/3 of travel,
//!   beyond the next layer. The mass flux is ρ₀ r on interior layers; the
//!   first layer of a body (half cells on a face) releases less.
//! - **Slivers.** A node whose normal sum vanishes (fluid symmetric about
//!   it) does not move and loses V₀ r / h per exposed face.
//! - **Massless nodes.** A solid node without a dual cell (no all-solid
//!   lattice cell around it, e.g. a lone boundary pixel) is converted as
//!   soon as it is exposed.
//! - **Conversion.** A node is converted when its volume falls to 10⁻⁹ of
//!   its initial volume or below. It empties part-way through the step, at
//!   the fraction s = V/ΔV of the step's burning time; the rest of that
//!   time, (1 − s)(Δt + c), is carried to the nodes the conversion exposes
//!   (those with a law that were not exposed at the start of the step),
//!   which burn for Δt + c in their first step (c the largest carry they
//!   received). Without the carry every layer would take a whole number
//!   of steps, ⌈τ/Δt⌉ instead of τ = h max|n̂_a|/ṙ, a rate error of up
//!   to Δt/τ that depends on the direction (through τ) and so distorts a
//!   curved front, and does not vanish as h → 0 at a fixed step fraction.

use brisance_core::{ReactionModel, ReactionState};
pub use brisance_reaction::arrhenius::{Arrhenius, GAS_CONSTANT};
use rayon::prelude::*;

use super::geometry::NodeKind;
use super::model::{MsdmError, MsdmLattice, NO_BOND};

/// Relative volume below which a regressing node is converted to fluid.
const EMPTY: f64 = 1e-9;

/// The speed of a node's surface, m/s: the law's [`ReactionModel::rate`]
/// with a unit area density (dF/dt of a unit depth), at the node's
/// temperature and the material's initial density ρ₀ (held, see the
/// module documentation). For [`Arrhenius`] that is Ω A exp(−Eₐ/(R T))/ρ₀
/// to the bit, and 0 at a temperature without a finite positive flux.
#[inline]
fn front_speed(law: &impl ReactionModel, rho0: f64, temperature: f64) -> f64 {
    law.rate(
        &ReactionState {
            temperature,
            density: rho0,
            surface_area_density: 1.0,
            ..Default::default()
        },
        0.0,
    )
}

/// The regression state of a lattice (see the module documentation).
#[derive(Debug, Clone)]
pub struct SurfaceRegression {
    /// Arrhenius law per material (`None`: inert).
    pub laws: Vec<Option<Arrhenius>>,
    /// Whether each box node is a fluid (exposing) node; solid nodes are
    /// never fluid, exterior nodes that are not fluid are inert walls.
    pub fluid: Vec<bool>,
    /// Burnable volume of each node, m³ (its dual-mesh volume at the start).
    pub remaining: Vec<f64>,
    /// Initial burnable volume of each node, m³.
    pub initial: Vec<f64>,
    /// Burning time carried into each node's next step from the conversion
    /// of a neighbour part-way through the previous one, s (see the module
    /// documentation).
    pub carry: Vec<f64>,
    /// Lattice offsets within the normal radius (origin excluded).
    stencil: Vec<[i32; 3]>,
    /// Radius of the normal estimate, in spacings.
    pub normal_radius: f64,
    /// Largest regression per step, in spacings (the regression limit of
    /// the stable step).
    pub step_fraction: f64,
    /// Mass converted to gas so far, kg.
    pub consumed_mass: f64,
    /// Nodes converted to fluid so far.
    pub converted: usize,
    /// Per-node move of this step: (Δx, Δy, Δz, ΔV).
    scratch: Vec<[f64; 4]>,
    /// This step's conversions and their leftover burning time, s.
    leftover: Vec<(usize, f64)>,
}

impl SurfaceRegression {
    /// The regression of `lat` with one law per material; every exterior
    /// node is fluid. `normal_radius` ≥ 1 (spacings), `step_fraction` in
    /// (0, 1].
    pub fn new(
        lat: &MsdmLattice,
        laws: Vec<Option<Arrhenius>>,
        normal_radius: f64,
        step_fraction: f64,
    ) -> Result<Self, MsdmError> {
        if laws.len() != lat.materials.len() {
            return Err(MsdmError::Invalid(format!(
                "regression: {} Arrhenius laws for {} materials",
                laws.len(),
                lat.materials.len()
            )));
        }
        for (k, l) in laws.iter().enumerate() {
            if let Some(l) = l {
                l.validate(&format!("materials.{}.arrhenius", lat.materials[k].name))
                    .map_err(MsdmError::Invalid)?;
            }
        }
        if !(1.0..=16.0).contains(&normal_radius) {
            return Err(MsdmError::Invalid(format!(
                "regression: field `normal_radius` = {normal_radius}, expected a value in [1, 16] spacings"
            )));
        }
        if !(step_fraction > 0.0 && step_fraction <= 1.0) {
            return Err(MsdmError::Invalid(format!(
                "regression: field `step_fraction` = {step_fraction}, expected a value in (0, 1]"
            )));
        }
        let d = lat.geom.dim.count();
        let reach = normal_radius.floor() as i32;
        let mut stencil = Vec::new();
        let range = |a: usize| if a < d { -reach..=reach } else { 0..=0 };
        for dz in range(2) {
            for dy in range(1) {
                for dx in range(0) {
                    let q = f64::from(dx * dx + dy * dy + dz * dz);
                    if q > 0.0 && q <= normal_radius * normal_radius + 1e-9 {
                        stencil.push([dx, dy, dz]);
                    }
                }
            }
        }
        let n = lat.len();
        Ok(Self {
            laws,
            fluid: (0..n).map(|i| !lat.geom.is_solid(i)).collect(),
            remaining: lat.volume.clone(),
            initial: lat.volume.clone(),
            carry: vec![0.0; n],
            stencil,
            normal_radius,
            step_fraction,
            consumed_mass: 0.0,
            converted: 0,
            scratch: vec![[0.0; 4]; n],
            leftover: Vec::new(),
        })
    }

    /// Marks the exterior nodes for which `wall(i)` is true as inert walls
    /// (not fluid).
    pub fn set_walls(&mut self, lat: &MsdmLattice, mut wall: impl FnMut(usize) -> bool) {
        for i in 0..lat.len() {
            if !lat.geom.is_solid(i) && wall(i) {
                self.fluid[i] = false;
            }
        }
    }

    /// Whether solid node `i` has a fluid neighbour along a lattice axis.
    #[inline]
    pub fn exposed(&self, lat: &MsdmLattice, i: usize) -> bool {
        let g = &lat.geom;
        (0..g.dim.count()).any(|a| {
            [1i32, -1].iter().any(|&s| {
                let mut step = [0i32; 3];
                step[a] = s;
                self.fluid[g.solid_neighbour(i, step)]
            })
        })
    }

    /// Number of axial fluid neighbours of node `i` (its exposed faces).
    pub fn exposed_faces(&self, lat: &MsdmLattice, i: usize) -> usize {
        let g = &lat.geom;
        let mut faces = 0;
        for a in 0..g.dim.count() {
            for s in [1i32, -1] {
                let mut step = [0i32; 3];
                step[a] = s;
                faces += usize::from(self.fluid[g.solid_neighbour(i, step)]);
            }
        }
        faces
    }

    /// Unit vector from solid node `i` towards the fluid: the normalised
    /// sum of the lattice offsets to the fluid nodes within the normal
    /// radius (zero if there is none).
    pub fn normal(&self, lat: &MsdmLattice, i: usize) -> [f64; 3] {
        let g = &lat.geom;
        let c = g.coords(i);
        let mut v = [0.0; 3];
        for o in &self.stencil {
            // The stencil may reach past the padded box near its edge;
            // outside the box counts as not fluid.
            let mut inside = true;
            for a in 0..3 {
                let k = c[a] as i64 + i64::from(o[a]);
                inside &= k >= 0 && k < g.n[a] as i64;
            }
            if !inside {
                continue;
            }
            let j = g.solid_neighbour(i, *o);
            let w = if self.fluid[j] { 1.0 } else { 0.0 };
            for a in 0..3 {
                v[a] += w * f64::from(o[a]);
            }
        }
        let len = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
        if len > 0.0 {
            [v[0] / len, v[1] / len, v[2] / len]
        } else {
            [0.0; 3]
        }
    }

    /// Volume node `i` loses per unit of regression distance along the
    /// unit normal `n`: its initial volume over the layer thickness
    /// h max_a |n_a| (see the module documentation), m².
    #[inline]
    pub fn volume_per_distance(&self, i: usize, n: [f64; 3], spacing: f64) -> f64 {
        let top = n[0].abs().max(n[1].abs()).max(n[2].abs());
        if top == 0.0 {
            return 0.0;
        }
        self.initial[i] / (spacing * top)
    }

    /// Largest regression speed over the solid nodes at their current
    /// temperatures, m/s.
    pub fn max_speed(&self, lat: &MsdmLattice) -> f64 {
        (0..lat.len())
            .into_par_iter()
            .filter_map(|i| self.speed_at(lat, i))
            .reduce(|| 0.0, f64::max)
    }

    /// The step of a front at speed `v` on a lattice of spacing `h`:
    /// `step_fraction` h / v, ∞ at zero speed, s.
    fn step_at_speed(&self, h: f64, v: f64) -> f64 {
        if v > 0.0 {
            self.step_fraction * h / v
        } else {
            f64::INFINITY
        }
    }

    /// The regression speed of node `i` at its current temperature, m/s;
    /// `None` for a node outside the solid or of a material that does not
    /// regress.
    fn speed_at(&self, lat: &MsdmLattice, i: usize) -> Option<f64> {
        let m = lat.material_of(i)?;
        let law = self.laws[m]?;
        Some(front_speed(
            &law,
            lat.materials[m].eos.rho0,
            lat.temperature[i],
        ))
    }
}

impl MsdmLattice {
    /// Switches surface regression on (seed 003 §2.4).
    pub fn set_regression(&mut self, regression: SurfaceRegression) -> Result<(), MsdmError> {
        if regression.fluid.len() != self.len() || regression.laws.len() != self.materials.len() {
            return Err(MsdmError::Invalid(format!(
                "regression: built for {} nodes and {} materials, the lattice has {} and {}",
                regression.fluid.len(),
                regression.laws.len(),
                self.len(),
                self.materials.len()
            )));
        }
        self.regression = Some(regression);
        Ok(())
    }

    /// The regression's step and what sets it, for the run summary: the
    /// node of the fastest front (the lowest index among equals), its
    /// temperature and speed; `None` without regression or at zero speed.
    pub(crate) fn regression_limit(&self) -> Option<(f64, String)> {
        let r = self.regression.as_ref()?;
        let (v, i) = (0..self.len())
            .filter_map(|i| r.speed_at(self, i).map(|v| (v, i)))
            .fold((0.0f64, usize::MAX), |a, b| if b.0 > a.0 { b } else { a });
        (v > 0.0).then(|| {
            let m = self.material_of(i).map_or(String::new(), |m| {
                format!(" (`{}`)", self.materials[m].name)
            });
            (
                r.step_at_speed(self.geom.spacing, v),
                format!(
                    "the surface regression at node {:?}{m}: front speed {v:.4e} m/s at {:.1} K, step {} h / speed",
                    self.geom.coords(i),
                    self.temperature[i],
                    r.step_fraction
                ),
            )
        })
    }

    /// Largest step of the regression: `step_fraction` h over the largest
    /// regression speed (∞ without regression or at zero speed), s.
    pub fn regression_dt(&self) -> f64 {
        match &self.regression {
            Some(r) => r.step_at_speed(self.geom.spacing, r.max_speed(self)),
            None => f64::INFINITY,
        }
    }

    /// One regression step of length `dt` (seed 003 §2.4): exposed nodes
    /// move by r along −n̂ and lose V₀ r / (h max|n̂_a|) of volume at constant density;
    /// emptied nodes become fluid. Returns the number of nodes converted.
    /// Nothing happens without regression.
    pub fn regress(&mut self, dt: f64) -> usize {
        let Some(mut reg) = self.regression.take() else {
            return 0;
        };
        let n = self.len();
        {
            let this = &*self;
            let mut scratch = std::mem::take(&mut reg.scratch);
            let r = &reg;
            scratch.par_iter_mut().enumerate().for_each(|(i, out)| {
                *out = [0.0; 4];
                let Some(m) = this.material_of(i) else {
                    return;
                };
                let Some(law) = r.laws[m] else {
                    return;
                };
                if !r.exposed(this, i) {
                    return;
                }
                if r.remaining[i] <= 0.0 {
                    // A node without a dual cell (no all-solid lattice cell
                    // around it, e.g. a lone pixel on a boundary) holds no
                    // mass: it goes as soon as it is exposed.
                    *out = [0.0, 0.0, 0.0, f64::INFINITY];
                    return;
                }
                let nrm = r.normal(this, i);
                // This step's burning time, with the time carried over from
                // a neighbour emptied part-way through the previous step.
                let burn = dt + r.carry[i];
                let dist =
                    front_speed(&law, this.materials[m].eos.rho0, this.temperature[i]) * burn;
                let h = this.geom.spacing;
                let per_distance = if nrm == [0.0; 3] {
                    // Fluid all round in a symmetric pattern (a sliver):
                    // it burns from every exposed face without moving.
                    r.exposed_faces(this, i) as f64 * r.initial[i] / h
                } else {
                    r.volume_per_distance(i, nrm, h)
                };
                let dv = dist * per_distance;
                if nrm == [0.0; 3] {
                    *out = [0.0, 0.0, 0.0, dv];
                } else {
                    *out = [-dist * nrm[0], -dist * nrm[1], -dist * nrm[2], dv];
                }
            });
            reg.scratch = scratch;
        }
        let nm = self.materials.len();
        let mut converted = 0;
        let mut moved = false;
        // Burning time left over by this step's conversions, per converted
        // node (read below to hand it to the nodes they expose).
        let mut leftover = std::mem::take(&mut reg.leftover);
        leftover.clear();
        for i in 0..n {
            let [dx, dy, dz, dv] = reg.scratch[i];
            let burn = dt + reg.carry[i];
            reg.carry[i] = 0.0;
            if dv == 0.0 {
                continue;
            }
            moved = true;
            let old = reg.remaining[i];
            let new = old - dv;
            if new <= EMPTY * reg.initial[i] || dv == f64::INFINITY {
                // Emptied at the fraction old/dv of its burning time (0 for
                // a node without mass).
                let s = if dv == f64::INFINITY { 0.0 } else { old / dv };
                leftover.push((i, ((1.0 - s) * burn).max(0.0)));
                reg.consumed_mass += self.mass[i];
                self.convert_to_fluid(i);
                reg.fluid[i] = true;
                reg.remaining[i] = 0.0;
                converted += 1;
                continue;
            }
            let dim = self.geom.dim.count();
            for (a, d) in [dx, dy, dz].into_iter().enumerate().take(dim) {
                self.x[a][i] += d;
            }
            let f = new / old;
            let mut total = 0.0;
            for k in 0..nm {
                let mk = &mut self.mass_k[k * n + i];
                *mk *= f;
                total += *mk;
            }
            reg.consumed_mass += self.mass[i] - total;
            self.mass[i] = total;
            reg.remaining[i] = new;
            if !self.mechanics {
                self.volume[i] = new;
            }
        }
        // The nodes a conversion exposes (solid, with a law, not burning this
        // step) start burning when their neighbour emptied: they burn for
        // Δt + the largest leftover they receive in their next step.
        let d = self.geom.dim.count();
        for &(i, t) in &leftover {
            for a in 0..d {
                for sgn in [1i32, -1] {
                    let mut step = [0i32; 3];
                    step[a] = sgn;
                    let j = self.geom.solid_neighbour(i, step);
                    let burning = reg.scratch[j][3] != 0.0;
                    let burnable = self.material_of(j).is_some_and(|m| reg.laws[m].is_some());
                    if burnable && !burning {
                        reg.carry[j] = reg.carry[j].max(t);
                    }
                }
            }
        }
        reg.leftover = leftover;
        reg.converted += converted;
        self.regression = Some(reg);
        if moved || converted > 0 {
            self.mark_modified();
        }
        converted
    }

    /// Turns solid node `i` into an exterior node: no mass, volume or
    /// velocity, the surroundings' temperature, and no springs.
    fn convert_to_fluid(&mut self, i: usize) {
        let n = self.len();
        self.geom.kind[i] = NodeKind::Exterior;
        for k in 0..self.materials.len() {
            self.mass_k[k * n + i] = 0.0;
            self.mass_rate[k * n + i] = 0.0;
        }
        self.mass[i] = 0.0;
        self.volume[i] = 0.0;
        self.pressure[i] = 0.0;
        self.energy[i] = 0.0;
        self.temperature[i] = self.options.surroundings.temperature;
        self.prescribed[i] = false;
        self.held_axes[i] = super::model::ALL_AXES;
        for a in 0..3 {
            self.u[a][i] = 0.0;
            self.force[a][i] = 0.0;
        }
        let nd = self.geom.directions.len();
        for (d, dir) in self.geom.directions.iter().enumerate() {
            self.status[i * nd + d] = NO_BOND;
            let j = i as isize - dir.offset;
            if j >= 0 && (j as usize) < n {
                self.status[j as usize * nd + d] = NO_BOND;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::super::cases::inert_eos;
    use super::super::geometry::{Dim, Geometry};
    use super::super::law::LatticeMaterial;
    use super::super::model::MsdmOptions;
    use super::*;
    use brisance_core::Solver;

    const H: f64 = 1e-4;
    const RHO: f64 = 1000.0;

    /// A `nx` × `ny` block of one material with an Arrhenius law of speed
    /// 1 mm/s at any temperature (Eₐ = 0, A = ρ · 1e-3), mechanics and the
    /// energy equation off, fluid above the top row only (walls on the
    /// other sides) unless `all_fluid`.
    fn block(nx: usize, ny: usize, radius: f64, all_fluid: bool) -> MsdmLattice {
        let geom = Geometry::new(Dim::Two, [nx, ny, 1], H, false, |_, _, _| Some(0));
        let mat = LatticeMaterial::elastic("fuel", 1e9, inert_eos(RHO, 1000.0));
        let opts = MsdmOptions {
            thermal: false,
            ..MsdmOptions::default()
        };
        let mut lat = MsdmLattice::new(geom, vec![mat], opts).unwrap();
        lat.mechanics = false;
        let law = Arrhenius {
            pre_exponential: RHO * 1e-3,
            activation_energy: 0.0,
            catalytic_factor: 1.0,
        };
        let mut reg = SurfaceRegression::new(&lat, vec![Some(law)], radius, 0.1).unwrap();
        if !all_fluid {
            let top = lat.geom.n[1] - 1;
            let g = lat.geom.clone();
            reg.set_walls(&lat, |i| g.coords(i)[1] != top);
        }
        lat.set_regression(reg).unwrap();
        lat
    }

    #[test]
    fn arrhenius_flux_and_speed_by_hand() {
        // AP of seed 003 §3.1 at 823 K: 5e6 exp(−92109.6 / (8.314462618 · 823)).
        let ap = Arrhenius {
            pre_exponential: 5.0e6,
            activation_energy: 92_109.6,
            catalytic_factor: 1.0,
        };
        let expect = 7.128_838_597_305_868;
        assert!((ap.mass_flux(823.0) - expect).abs() < 1e-13 * expect);
        assert!((ap.speed(1950.0, 823.0) - expect / 1950.0).abs() < 1e-16);
        let cat = Arrhenius {
            catalytic_factor: 1.41,
            ..ap
        };
        assert!((cat.mass_flux(823.0) - 1.41 * expect).abs() < 1e-13 * expect);
        assert_eq!(
            Arrhenius {
                activation_energy: 0.0,
                ..ap
            }
            .mass_flux(300.0),
            5.0e6
        );
        let bad = Arrhenius {
            catalytic_factor: 0.0,
            ..ap
        };
        assert!(bad
            .validate("materials.ap.arrhenius")
            .unwrap_err()
            .contains("materials.ap.arrhenius.catalytic_factor"));
        let bad = Arrhenius {
            activation_energy: f64::NAN,
            ..ap
        };
        assert!(bad
            .validate("x")
            .unwrap_err()
            .contains("x.activation_energy"));
    }

    /// One step of r = 1e-3 · 0.01 = 0.1 h on a flat top face: the middle
    /// node (dual volume h³/2) moves down by r and loses r/h of its volume,
    /// r h²/2; the corner against the wall, r h²/4 of its h³/4; the row
    /// below does not move.
    #[test]
    fn flat_face_regresses_by_r_at_constant_density() {
        for radius in [1.0, 3.0] {
            let mut lat = block(5, 4, radius, false);
            let mid = lat.geom.solid_index(2, 3, 0);
            let corner = lat.geom.solid_index(0, 3, 0);
            let below = lat.geom.solid_index(2, 2, 0);
            let y0 = lat.x[1][mid];
            let r = 1e-3 * 0.01;
            lat.step(0.01).unwrap();
            assert!((lat.x[1][mid] - (y0 - r)).abs() < 1e-18, "radius {radius}");
            assert_eq!(lat.x[0][mid], 2.0 * H);
            let v = H * H * H / 2.0 - r * H * H / 2.0;
            assert!((lat.volume[mid] - v).abs() < 1e-15 * H * H * H);
            assert!((lat.mass[mid] - RHO * v).abs() < 1e-15 * RHO * v);
            assert!((lat.mass_k[mid] - RHO * v).abs() < 1e-15 * RHO * v);
            // The seed's rule (radius 1) sees the fluid above the corner
            // only; a wider stencil also sees the fluid corner of the
            // padding and tilts the normal there.
            if radius == 1.0 {
                let vc = H * H * H / 4.0 - r * H * H / 4.0;
                assert!((lat.volume[corner] - vc).abs() < 1e-15 * H * H * H);
            }
            assert_eq!(lat.x[1][below], 2.0 * H);
            assert_eq!(lat.volume[below], H * H * H);
            let reg = lat.regression.as_ref().unwrap();
            // Five top nodes, three of h³/2 and two corners of h³/4, each
            // lose r/h of their volume: 2 r h².
            let consumed = RHO * 2.0 * r * H * H;
            if radius == 1.0 {
                assert!((reg.consumed_mass - consumed).abs() < 1e-13 * consumed);
            }
        }
    }

    /// With every exterior node fluid the corner of the block is exposed
    /// on +x and +y: it moves along −(1, 1)/√2 and loses r/(h/√2) of its
    /// h³/4 (its layer along the diagonal is h/√2 thick).
    #[test]
    fn exposed_corner_moves_along_the_diagonal() {
        let mut lat = block(5, 4, 1.0, true);
        let c = lat.geom.solid_index(4, 3, 0);
        let (x0, y0) = (lat.x[0][c], lat.x[1][c]);
        let r = 1e-3 * 0.01;
        lat.step(0.01).unwrap();
        let s = r / 2f64.sqrt();
        assert!((lat.x[0][c] - (x0 - s)).abs() < 1e-18);
        assert!((lat.x[1][c] - (y0 - s)).abs() < 1e-18);
        let v = H * H * H / 4.0 - r * H * H * 2f64.sqrt() / 4.0;
        assert!((lat.volume[c] - v).abs() < 1e-15 * H * H * H);
        // An interior node sees no fluid along an axis and stays.
        let inner = lat.geom.solid_index(2, 1, 0);
        assert_eq!(lat.volume[inner], H * H * H);
    }

    /// The face recedes one layer per h/r whatever the volume of the
    /// layer's nodes: the top row (h³/2) and the next (h³) each empty in 10
    /// steps of 0.1 h, and the consumed mass is exactly the mass of the
    /// emptied rows.
    #[test]
    fn emptied_nodes_become_fluid_one_layer_per_h_over_r() {
        let mut lat = block(3, 6, 1.0, false);
        let m0: f64 = lat.mass.iter().sum();
        let row_mass = |lat: &MsdmLattice, iy: usize| -> f64 {
            (0..3)
                .map(|ix| lat.mass[lat.geom.solid_index(ix, iy, 0)])
                .sum()
        };
        let top_row = row_mass(&lat, 5);
        let next_row = row_mass(&lat, 4);
        let mut converted = Vec::new();
        for k in 1..=20 {
            let before = lat.regression.as_ref().unwrap().converted;
            lat.step(0.01).unwrap();
            if lat.regression.as_ref().unwrap().converted > before {
                converted.push(k);
            }
        }
        assert_eq!(converted, vec![10, 20]);
        let reg = lat.regression.as_ref().unwrap();
        assert_eq!(reg.converted, 6);
        assert!((reg.consumed_mass - (top_row + next_row)).abs() < 1e-12 * m0);
        let left: f64 = lat.mass.iter().sum();
        assert!((left + reg.consumed_mass - m0).abs() < 1e-12 * m0);
        // The emptied nodes are fluid exterior nodes without springs.
        let gone = lat.geom.solid_index(1, 4, 0);
        assert!(!lat.geom.is_solid(gone));
        assert!(reg.fluid[gone]);
        assert_eq!(lat.spring_intact(gone, 1), None);
        let below = gone - lat.geom.n[0];
        assert_eq!(lat.spring_intact(below, 1), None);
        // The new surface row has not moved yet.
        assert_eq!(lat.x[1][lat.geom.solid_index(1, 3, 0)], 3.0 * H);
        // Particles are the remaining solid nodes.
        assert_eq!(lat.particle_data().unwrap().positions.len(), 12);
    }

    /// At r = 0.3 h per step a layer takes 3⅓ steps. The top row empties
    /// a third of the way through step 4; the row below starts burning
    /// then, so after step 5 it has burnt for 1⅔ steps (0.5 h) and holds
    /// half its volume, empties at 6⅔ steps (step 7) and the third row at
    /// exactly 10 steps: three rows in 10 steps, the Arrhenius rate.
    /// Without the carried time each row takes 4 whole steps (rows gone at
    /// steps 4, 8, 12: 25 % slow at this step).
    #[test]
    fn a_layer_emptied_mid_step_hands_its_leftover_time_to_the_next() {
        let mut lat = block(3, 6, 1.0, false);
        let row_mass = |lat: &MsdmLattice, iy: usize| -> f64 {
            (0..3)
                .map(|ix| lat.mass[lat.geom.solid_index(ix, iy, 0)])
                .sum()
        };
        let m0: f64 = lat.mass.iter().sum();
        let rows: f64 = (3..6).map(|iy| row_mass(&lat, iy)).sum();
        let mid = lat.geom.solid_index(1, 4, 0);
        let mut converted = Vec::new();
        for k in 1..=10 {
            let before = lat.regression.as_ref().unwrap().converted;
            lat.step(0.03).unwrap();
            if lat.regression.as_ref().unwrap().converted > before {
                converted.push(k);
            }
            if k == 4 {
                // Exposed for the last 2/3 of step 4: carried 0.02 s.
                let c = lat.regression.as_ref().unwrap().carry[mid];
                assert!((c - 0.02).abs() < 1e-15, "carry {c}");
            }
            if k == 5 {
                let left = lat.regression.as_ref().unwrap().remaining[mid];
                assert!((left - 0.5 * H * H * H).abs() < 1e-12 * H * H * H, "{left}");
                assert!((lat.x[1][mid] - 3.5 * H).abs() < 1e-12 * H);
            }
        }
        assert_eq!(converted, vec![4, 7, 10]);
        let reg = lat.regression.as_ref().unwrap();
        assert_eq!(reg.converted, 9);
        assert!((reg.consumed_mass - rows).abs() < 1e-12 * m0);
    }

    /// A burning block exposed on every side (corners, carried times,
    /// conversions) gives the same bits on 1 and 3 threads.
    #[test]
    fn regression_is_the_same_on_any_number_of_threads() {
        let run = |threads: usize| {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            pool.install(|| {
                let mut lat = block(7, 5, 1.0, true);
                let mut carried = 0usize;
                for _ in 0..20 {
                    lat.step(0.013).unwrap();
                    let reg = lat.regression.as_ref().unwrap();
                    carried += reg.carry.iter().filter(|&&c| c > 0.0).count();
                }
                let reg = lat.regression.as_ref().unwrap();
                let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<u64>>();
                (
                    bits(&lat.x[0]),
                    bits(&lat.x[1]),
                    bits(&reg.remaining),
                    bits(&reg.carry),
                    reg.consumed_mass.to_bits(),
                    reg.converted,
                    carried,
                )
            })
        };
        let one = run(1);
        // Nodes were converted and times carried, and some solid is left.
        assert!(one.5 > 0 && one.6 > 0 && one.2.iter().any(|&v| v != 0));
        assert_eq!(one, run(3));
    }

    #[test]
    fn stable_step_limit_checkpoint_and_field_errors() {
        let mut lat = block(3, 6, 1.0, false);
        // step_fraction 0.1 of h at 1 mm/s.
        assert!((lat.stable_dt().unwrap() - 0.1 * H / 1e-3).abs() < 1e-15);
        let saved = lat.save_state().unwrap();
        for _ in 0..7 {
            lat.step(0.01).unwrap();
        }
        let after = (lat.x.clone(), lat.mass.clone(), lat.geom.kind.clone());
        lat.restore_state(&saved).unwrap();
        assert!(lat.geom.is_solid(lat.geom.solid_index(1, 5, 0)));
        for _ in 0..7 {
            lat.step(0.01).unwrap();
        }
        assert_eq!(
            (lat.x.clone(), lat.mass.clone(), lat.geom.kind.clone()),
            after
        );
        lat.options.thermal = true;
        assert!(lat
            .step(0.01)
            .unwrap_err()
            .to_string()
            .contains("`mechanics`"));
        let plain = block(2, 2, 1.0, false);
        assert!(SurfaceRegression::new(&plain, vec![None], 0.5, 0.1)
            .unwrap_err()
            .to_string()
            .contains("normal_radius"));
        assert!(SurfaceRegression::new(&plain, vec![None], 1.0, 0.0)
            .unwrap_err()
            .to_string()
            .contains("step_fraction"));
        assert!(SurfaceRegression::new(&plain, vec![], 1.0, 0.1).is_err());
    }

    /// With mechanics on, the regression runs after the mechanical step:
    /// a block at rest (below the explicit limit, ~h/c = 1e-7 s) regresses
    /// as without mechanics on its first step, up to the round-off forces
    /// of the reference lattice.
    #[test]
    fn regression_also_runs_with_mechanics() {
        let mut a = block(4, 4, 3.0, false);
        let mut b = block(4, 4, 3.0, false);
        b.mechanics = true;
        let dt = 1e-8;
        let r = 1e-3 * dt;
        a.step(dt).unwrap();
        b.step(dt).unwrap();
        let i = a.geom.solid_index(1, 3, 0);
        assert!((a.x[1][i] - (3.0 * H - r)).abs() < 1e-6 * r);
        assert!(
            (a.x[1][i] - b.x[1][i]).abs() < 1e-3 * r,
            "{} vs {}",
            a.x[1][i],
            b.x[1][i]
        );
        assert_eq!(a.mass[i], b.mass[i]);
    }

    /// Reduced V-REGRESS (20 nodes across, the seed's normal rule): the
    /// 30° face stays planar and the disc round within a spacing, both
    /// receding within 10 % of the Arrhenius speed (the full case is in
    /// `cargo xtask validate`).
    #[test]
    fn reduced_v_regress() {
        use super::super::cases::{regress_disc, regress_rotated_square};
        let face = regress_rotated_square(20, 1.0).unwrap();
        assert!(
            face.rms <= face.spacing,
            "face RMS {}",
            face.rms / face.spacing
        );
        assert!(
            (face.rate_ratio - 1.0).abs() <= 0.1,
            "face rate {}",
            face.rate_ratio
        );
        let disc = regress_disc(20, 1.0).unwrap();
        assert!(
            disc.spread <= disc.spacing,
            "disc spread {}",
            disc.spread / disc.spacing
        );
        assert!(
            (disc.rate_ratio - 1.0).abs() <= 0.1,
            "disc rate {}",
            disc.rate_ratio
        );
        // Half the radius gone: the exposed nodes sit at R₀/2 to a spacing.
        assert!((disc.mean - 0.25e-3).abs() <= disc.spacing, "{}", disc.mean);
    }

    /// The seed's normal rule on a straight front: the staircase rate is
    /// 1 at 0° and 45° and √(4 − 2√2) = 1.082 392 at 22.5° (tan = √2 − 1);
    /// the 45° face (every surface node a corner, layer h/√2) recedes at
    /// the Arrhenius speed and the 22.5° face near the staircase rate.
    #[test]
    fn seed_rule_on_a_straight_front_follows_the_staircase_rate() {
        use super::super::cases::{regress_rotated_square_with, staircase_rate};
        assert_eq!(staircase_rate(0.0), 1.0);
        assert!((staircase_rate(45.0) - 1.0).abs() < 1e-15);
        let peak = (4.0 - 2.0 * 2f64.sqrt()).sqrt();
        assert!((staircase_rate(22.5) - peak).abs() < 1e-15);
        assert!((peak - 1.082_392).abs() < 1e-6);
        // 20 nodes across: 45° measured 1.0016, 22.5° 1.0663 (1.5 % under
        // the steady staircase, whose corners are not all in place).
        let diag = regress_rotated_square_with(20, 1.0, 45.0, 0.05).unwrap();
        assert!((diag.rate_ratio - 1.0).abs() < 0.01, "{}", diag.rate_ratio);
        let mid = regress_rotated_square_with(20, 1.0, 22.5, 0.05).unwrap();
        assert!(
            (mid.rate_ratio / peak - 1.0).abs() < 0.025,
            "{}",
            mid.rate_ratio
        );
        assert!(regress_rotated_square_with(20, 1.0, 50.0, 0.05).is_err());
    }

    /// Reduced E-APHTPB (a 1.2 mm slice, 51 nodes, 908 K): the pack burns
    /// no faster than its faster component (AP) and no slower than HTPB,
    /// the catalyst on AP speeds it up by less than its factor 1.41, and
    /// the pack holds 80 wt % AP to the pixelation.
    #[test]
    fn reduced_ap_htpb_burn_lies_between_its_components() {
        use super::super::cases::{aphtpb_burn, AP_ARRHENIUS, AP_HTPB_DENSITY, HTPB_ARRHENIUS};
        let t = 908.0;
        let speed = |(a, e): (f64, f64), rho: f64| {
            Arrhenius {
                pre_exponential: a,
                activation_energy: e,
                catalytic_factor: 1.0,
            }
            .speed(rho, t)
        };
        let ap = speed(AP_ARRHENIUS, AP_HTPB_DENSITY.0);
        let htpb = speed(HTPB_ARRHENIUS, AP_HTPB_DENSITY.1);
        let plain = aphtpb_burn(1.2e-3, 51, t, 1.0, 5).unwrap();
        assert!(
            (plain.ap_mass_fraction - 0.8).abs() < 0.03,
            "{}",
            plain.ap_mass_fraction
        );
        assert!(
            plain.rate > htpb && plain.rate < ap,
            "{} not in ({htpb}, {ap})",
            plain.rate
        );
        let cat = aphtpb_burn(1.2e-3, 51, t, 1.41, 5).unwrap();
        let gain = cat.rate / plain.rate;
        assert!(gain > 1.0 && gain < 1.41, "{gain}");
        // Burnt nodes are marked.
        assert!(cat.materials.contains(&-1));
    }

    proptest::proptest! {
        #![proptest_config(proptest::prelude::ProptestConfig::with_cases(24))]
        /// Whatever the block, normal radius and step: mass is only moved
        /// from the nodes to the consumed tally (to round-off), volumes stay
        /// non-negative, solid nodes only disappear, and nodes only move
        /// away from the fluid (down, with fluid above only).
        #[test]
        fn regression_conserves_mass_and_only_removes(
            nx in 2usize..7,
            ny in 2usize..7,
            radius in 1.0f64..4.0,
            steps in 1usize..40,
            fraction in 0.01f64..0.5,
            all_fluid in proptest::bool::ANY,
        ) {
            let mut lat = block(nx, ny, radius, all_fluid);
            let m0: f64 = lat.mass.iter().sum();
            let y0 = lat.x[1].clone();
            let dt = fraction * H / 1e-3;
            let mut solid = (0..lat.len()).filter(|&i| lat.geom.is_solid(i)).count();
            for _ in 0..steps {
                lat.step(dt).unwrap();
                let now = (0..lat.len()).filter(|&i| lat.geom.is_solid(i)).count();
                proptest::prop_assert!(now <= solid);
                solid = now;
            }
            let reg = lat.regression.as_ref().unwrap();
            let m1: f64 = lat.mass.iter().sum();
            proptest::prop_assert!((m1 + reg.consumed_mass - m0).abs() <= 1e-12 * m0);
            proptest::prop_assert!(reg.remaining.iter().all(|&v| v >= 0.0));
            if !all_fluid {
                for i in 0..lat.len() {
                    if lat.geom.is_solid(i) {
                        proptest::prop_assert!(lat.x[1][i] <= y0[i]);
                    }
                }
            }
        }
    }
}
