//! Building a [`PdSolver`] from its [`PdSetup`]: the nodes, families, bond
//! weights and detonation times, and the forces of the initial state.

use super::{distance, invalid, BurnMethod, PdSetup, PdSetupError, PdSolver, BURN_STEP_FRACTION};
use crate::cell_list::CellList;
use crate::family::{
    build_families, build_families_where, partial_volume, ForeignBonds, OneSidedPairs,
};
use crate::forces::{BondLaw, NodeForce};
use crate::lattice::{fill_lattice, LatticeSpec};
use crate::material::{micromodulus, PdMaterial, Proportional, ProportionalKind};
use brisance_reaction::{huygens_detonation_times, straight_line_detonation_times};

impl PdSolver {
    /// Builds the nodes, families, bond weights and detonation times, and
    /// evaluates the forces of the initial state.
    pub fn new(setup: PdSetup) -> Result<Self, PdSetupError> {
        let o = setup.options.clone();
        let h = o.spacing;
        if !(o.horizon_factor >= 1.0 && o.horizon_factor.is_finite()) {
            return Err(invalid(
                "horizon_factor",
                format!("expected a finite value ≥ 1, got {}", o.horizon_factor),
            ));
        }
        if !(o.safety_factor > 0.0 && o.safety_factor <= 1.0) {
            return Err(invalid(
                "safety_factor",
                format!("expected 0 < f ≤ 1, got {}", o.safety_factor),
            ));
        }
        if let Some(f) = o.closing_step_fraction {
            if !(f > 0.0 && f <= 1.0) {
                return Err(invalid(
                    "closing_step_fraction",
                    format!("expected 0 < f ≤ 1, got {f}"),
                ));
            }
        }
        if !o.body_force.iter().all(|b| b.is_finite()) {
            return Err(invalid("body_force", "must be finite"));
        }
        if let Some(c) = o.contact {
            if !(c.force_factor >= 0.0 && c.force_factor.is_finite()) {
                return Err(invalid(
                    "contact.force_factor",
                    "expected a finite value ≥ 0",
                ));
            }
            if !(c.distance_factor > 0.0 && c.distance_factor < o.horizon_factor) {
                return Err(invalid(
                    "contact.distance_factor",
                    format!(
                        "expected 0 < factor < horizon_factor, got {}",
                        c.distance_factor
                    ),
                ));
            }
            if !(c.reference_fraction > 0.0 && c.reference_fraction <= 1.0) {
                return Err(invalid(
                    "contact.reference_fraction",
                    format!(
                        "expected 0 < fraction ≤ 1 (pairs force-free at rest), got {}",
                        c.reference_fraction
                    ),
                ));
            }
        }
        if setup.materials.is_empty() {
            return Err(invalid("materials", "at least one material is needed"));
        }
        for (m, mat) in setup.materials.iter().enumerate() {
            mat.validate()
                .map_err(|e| invalid(format!("materials[{m}]"), e))?;
        }
        for (b, body) in setup.bodies.iter().enumerate() {
            if body.material as usize >= setup.materials.len() {
                return Err(invalid(
                    format!("bodies[{b}].material"),
                    format!(
                        "material {} does not exist ({} materials)",
                        body.material,
                        setup.materials.len()
                    ),
                ));
            }
        }
        let horizon = o.horizon_factor * h;
        let cloud = fill_lattice(
            &LatticeSpec {
                spacing: h,
                origin: o.origin,
                dimension: o.dimension,
                cross_section: o.cross_section,
                jitter: o.jitter,
            },
            &setup.bodies,
        )?;
        let n = cloud.positions.len();
        if n == 0 {
            return Err(invalid("bodies", "the bodies contain no lattice node"));
        }
        let is_gas: Vec<bool> = cloud
            .material
            .iter()
            .map(|&m| matches!(setup.materials[m as usize], PdMaterial::Gas(_)))
            .collect();
        let families = if o.products_family.with_solids() {
            let body = &cloud.body;
            build_families_where(&cloud.positions, horizon, h, |i, j| {
                body[i] == body[j] || (is_gas[i] && !is_gas[j])
            })
        } else {
            build_families(&cloud.positions, &cloud.body, horizon, h)
        };
        let one_sided = if o.products_family.with_solids() {
            OneSidedPairs::of(&families, |i| is_gas[i])
        } else {
            OneSidedPairs::default()
        };
        let wall_bonds = if o.products_family.mirrors_walls() {
            ForeignBonds::of(&families, |i| is_gas[i])
        } else {
            ForeignBonds::default()
        };
        // Strength factors of the materials with a spread critical stretch
        // (`strength.rs`; empty when none has one), and per material the
        // smallest factor among its nodes.
        let spread = |m: u16| match setup.materials[m as usize] {
            PdMaterial::Proportional(Proportional {
                spread: Some(s), ..
            }) => Some(s),
            _ => None,
        };
        let strength: Vec<f64> = if cloud.material.iter().any(|&m| spread(m).is_some()) {
            use rayon::prelude::*;
            cloud
                .positions
                .par_iter()
                .zip(cloud.material.par_iter())
                .map(|(&x, &m)| spread(m).map_or(1.0, |s| s.factor_at(x)))
                .collect()
        } else {
            Vec::new()
        };
        let mut weakest = vec![1.0f64; setup.materials.len()];
        for (i, &f) in strength.iter().enumerate() {
            let w = &mut weakest[cloud.material[i] as usize];
            *w = w.min(f);
        }
        let laws: Vec<BondLaw> = setup
            .materials
            .iter()
            .zip(&weakest)
            .map(|(m, &weakest)| match m {
                PdMaterial::Proportional(p) => BondLaw::Solid {
                    micromodulus: micromodulus(p, o.dimension, horizon, o.cross_section),
                    yield_stretch: p.yield_stretch(),
                    plastic: p.kind == ProportionalKind::MicroPlastic,
                    // The row's first test: no node of the material breaks
                    // a bond below it.
                    critical_stretch: p.critical_stretch * weakest,
                },
                PdMaterial::Gas(_) => BondLaw::Gas,
            })
            .collect();
        let reference: Vec<[f64; 4]> = (0..n)
            .map(|i| {
                let x = cloud.positions[i];
                [x[0], x[1], x[2], cloud.volumes[i]]
            })
            .collect();
        // Bond weights β (and surface correction for solids).
        let mut factor = vec![0f32; families.bond_count()];
        let beta = |i: usize, j: usize| {
            partial_volume(distance(cloud.positions[i], cloud.positions[j]), horizon, h)
        };
        for i in 0..n {
            for k in families.row(i) {
                factor[k] = beta(i, families.neighbours[k] as usize) as f32;
            }
        }
        if o.surface_correction {
            crate::surface::apply_surface_correction(
                &reference,
                &families,
                &cloud.material,
                &laws,
                o.dimension,
                horizon,
                o.cross_section,
                &mut factor,
            );
        }
        let node_scale: Vec<f64> = (0..n)
            .map(|i| match laws[cloud.material[i] as usize] {
                BondLaw::Solid { micromodulus, .. } => families
                    .row(i)
                    .map(|k| {
                        let j = families.neighbours[k] as usize;
                        micromodulus * factor[k] as f64 * reference[j][3]
                            / distance(cloud.positions[i], cloud.positions[j])
                    })
                    .sum(),
                BondLaw::Gas => families
                    .row(i)
                    .map(|k| factor[k] as f64 * reference[families.neighbours[k] as usize][3])
                    .sum(),
            })
            .collect();
        // Program burn.
        let explosive = is_gas;
        let mut detonation_time = vec![f64::INFINITY; n];
        let mut burn_step = f64::INFINITY;
        if explosive.iter().any(|&e| e) {
            let spec = setup.detonation.as_ref().ok_or_else(|| {
                invalid(
                    "detonation",
                    "a body is an explosive (gas material): detonation points are needed",
                )
            })?;
            let speeds: Vec<f64> = setup
                .materials
                .iter()
                .filter_map(|m| match m {
                    PdMaterial::Gas(g) => Some(g.detonation_velocity),
                    _ => None,
                })
                .collect();
            let speed = speeds[0];
            if speeds.iter().any(|&s| s != speed) {
                return Err(invalid(
                    "materials",
                    "all explosive materials must share one detonation velocity",
                ));
            }
            burn_step = BURN_STEP_FRACTION * h / speed;
            detonation_time = match spec.method {
                BurnMethod::Huygens => huygens_detonation_times(
                    &cloud.positions,
                    &families.offsets,
                    &families.neighbours,
                    &explosive,
                    &spec.points,
                    speed,
                    horizon,
                )?,
                BurnMethod::StraightLine => straight_line_detonation_times(
                    &cloud.positions,
                    &explosive,
                    &spec.points,
                    speed,
                )?,
            };
        }
        // Prescribed velocities.
        let mut prescribed = Vec::new();
        for (b, bc) in setup.boundaries.iter().enumerate() {
            bc.region
                .validate()
                .map_err(|e| invalid(format!("boundaries[{b}].region.{}", e.field), e.message))?;
            if !bc.velocity.iter().flatten().all(|v| v.is_finite()) {
                return Err(invalid(
                    format!("boundaries[{b}].velocity"),
                    "must be finite",
                ));
            }
            for (i, x) in cloud.positions.iter().enumerate() {
                if bc.region.contains(*x) {
                    for (d, v) in bc.velocity.iter().enumerate() {
                        if let Some(v) = v {
                            prescribed.push((i as u32, d as u8, *v));
                        }
                    }
                }
            }
        }
        let mut state = vec![[0.0; 4]; n];
        for (i, s) in state.iter_mut().enumerate() {
            if let PdMaterial::Proportional(p) = setup.materials[cloud.material[i] as usize] {
                s[3] = p.critical_stretch * strength.get(i).copied().unwrap_or(1.0);
            }
        }
        let has_gas = laws.iter().any(|l| matches!(l, BondLaw::Gas));
        // Bonds that can yield plastically or break dissipate energy.
        let dissipating = laws.iter().any(|l| match *l {
            BondLaw::Solid {
                yield_stretch,
                plastic,
                critical_stretch,
                ..
            } => (plastic && yield_stretch.is_finite()) || critical_stretch.is_finite(),
            BondLaw::Gas => false,
        });
        let contact_on = o.contact.is_some();
        let has_reactant = setup
            .materials
            .iter()
            .map(|m| matches!(m, PdMaterial::Gas(g) if g.reactant.is_some()))
            .collect();
        let mut solver = Self {
            material_density: setup.materials.iter().map(PdMaterial::density).collect(),
            bulk_modulus: setup
                .materials
                .iter()
                .map(PdMaterial::contact_bulk_modulus)
                .collect(),
            breakable: setup
                .materials
                .iter()
                .map(|m| matches!(m, PdMaterial::Proportional(_)))
                .collect(),
            options: o,
            horizon,
            materials: setup.materials,
            laws,
            reference,
            body: cloud.body,
            material: cloud.material,
            node_scale,
            burn_end: if burn_step.is_finite() {
                detonation_time
                    .iter()
                    .copied()
                    .filter(|t| t.is_finite())
                    .fold(f64::NEG_INFINITY, f64::max)
                    + horizon * burn_step / (BURN_STEP_FRACTION * h)
            } else {
                f64::NEG_INFINITY
            },
            detonation_time,
            burn_step,
            prescribed,
            families,
            one_sided,
            wall_bonds,
            time: 0.0,
            steps: 0,
            state,
            velocity: cloud.velocity,
            bond_out: vec![NodeForce::default(); n],
            dissipated_node: vec![0.0; if dissipating { n } else { 0 }],
            dissipated: 0.0,
            contact: vec![([0.0; 3], 0.0); if contact_on { n } else { 0 }],
            gas: vec![[1.0, 0.0, 0.0, 0.0]; if has_gas { n } else { 0 }],
            closing: vec![
                f64::INFINITY;
                if has_gas && setup.options.closing_step_fraction.is_some() {
                    n
                } else {
                    0
                }
            ],
            viscosity: None,
            hold_unreacted: true,
            has_reactant,
            viscous_node: Vec::new(),
            viscous: Vec::new(),
            kick_heat: Vec::new(),
            deviatoric: Vec::new(),
            plastic: vec![0.0; factor.len()],
            factor,
            strength,
            cells: CellList::default(),
            ranks: super::ranks::Ranks::serial(n),
        };
        // Arrays grown by pushing keep their spare capacity otherwise.
        solver.body.shrink_to_fit();
        solver.material.shrink_to_fit();
        solver.velocity.shrink_to_fit();
        solver.detonation_time.shrink_to_fit();
        solver.prescribed.shrink_to_fit();
        solver.impose_velocities();
        solver.set_gas_viscosity(None)?;
        Ok(solver)
    }
}
