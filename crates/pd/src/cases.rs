//! The seed 004 validation cases, one definition for the test suite
//! (reduced) and `cargo xtask validate` (full): E-PD-CYL, the copper
//! cylinder-expansion test, and E-PD-FRAG, the fragmenting steel cylinder.
//!
//! Both tubes lie along z with their axis through the lattice origin and
//! are filled with TNT detonated on the axis at the z = 0 end. The seed
//! used JWL for the explosive without printing its parameters; Brisance
//! uses the TNT set of seed 001 §4.1 (`brisance_eos::Jwl::tnt()`: A =
//! 371.2 GPa, B = 3.21 GPa, R₁ = 4.15, R₂ = 0.95, ω = 0.3, E₀ =
//! 6.993 GJ/m³, ρ₀ = 1630 kg/m³, after Dobratz & Crawford, LLNL Explosives
//! Handbook), with the products isentrope through the volume-burn
//! reference state (seed 004 eqs 20–21, 30).

use crate::lattice::BodySpec;
use crate::material::{Gas, PdMaterial, Proportional, ProportionalKind, Reactant};
use crate::solver::{BurnMethod, DetonationSpec, PdOptions, PdSetup, PdSetupError, PdSolver};
use crate::Fragment;
use brisance_core::Solver;
use brisance_eos::tools::gurney::CYLINDER_TEST_RELATIVE_VOLUME;
use brisance_eos::tools::{cylinder_wall_velocity, gurney_estimate};
use brisance_eos::Jwl;
use brisance_grid::Shape;
use brisance_reaction::{DetonationPoint, ProductsIsentrope};

/// A tube filled with explosive.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TubeCase {
    /// Length, m.
    pub length: f64,
    /// Inner radius, m.
    pub inner_radius: f64,
    /// Outer radius, m.
    pub outer_radius: f64,
    /// The case material.
    pub metal: Proportional,
    /// Lattice spacing, m.
    pub spacing: f64,
}

/// Length of seed 004's copper tube (E-PD-CYL), m.
pub const COPPER_TUBE_LENGTH: f64 = 0.258;

/// The axial range a tube's figures of the products are taken over: the
/// middle 70 % of a tube of `length` (m), away from the open ends, where
/// the products vent axially.
pub fn middle_of(length: f64) -> (f64, f64) {
    (0.15 * length, 0.85 * length)
}

/// E-PD-CYL: the copper tube of seed 004 (25.8 cm long, inner diameter
/// 2.54 cm, wall 0.26 cm; ρ 8930 kg/m³, bulk sound speed 3602 m/s, yield
/// 324 MPa, critical stretch 2.0), micro-elastic as the seed's "proportional
/// model".
pub fn copper_cylinder(spacing: f64, length: f64) -> TubeCase {
    TubeCase {
        length,
        inner_radius: 0.0127,
        outer_radius: 0.0127 + 0.0026,
        metal: Proportional::seed_004_copper(),
        spacing,
    }
}

/// E-PD-FRAG: the steel tube of seed 004 (4.25 in long, inner diameter
/// 1.0 in, wall 1/8 in; ρ 7850 kg/m³, 3212 m/s, 750 MPa, critical stretch
/// 0.11, micro-plastic), with the damage-stretch and minimum-stretch
/// coefficients the seed's footnote c mentions (values: `alpha_d`,
/// `alpha_min`).
pub fn steel_fragmenting_cylinder(
    spacing: f64,
    length: f64,
    alpha_d: f64,
    alpha_min: f64,
) -> TubeCase {
    TubeCase {
        length,
        inner_radius: 0.0127,
        outer_radius: 0.0127 + 0.003175,
        metal: Proportional {
            density: 7850.0,
            sound_speed: 3212.0,
            yield_strength: 750.0e6,
            critical_stretch: 0.11,
            kind: ProportionalKind::MicroPlastic,
            damage_stretch_coefficient: alpha_d,
            minimum_stretch_coefficient: alpha_min,
            spread: None,
        },
        spacing,
    }
}

/// The TNT products as a peridynamic gas, with the CJ detonation velocity.
pub fn tnt_products() -> Result<Gas, PdSetupError> {
    let (isentrope, cj) =
        ProductsIsentrope::from_jwl(&Jwl::tnt()).map_err(|e| PdSetupError::Invalid {
            field: "explosive".into(),
            message: e.to_string(),
        })?;
    Ok(Gas {
        density: Jwl::tnt().rho0,
        detonation_velocity: cj.detonation_velocity,
        isentrope,
        reactant: Some(Reactant::tnt()),
    })
}

impl TubeCase {
    /// The solver setup: explosive first (it claims the lattice sites on
    /// the inner surface), then the case.
    pub fn setup(&self) -> Result<PdSetup, PdSetupError> {
        let axis = [0.0, 0.0, 1.0];
        Ok(PdSetup {
            options: PdOptions {
                spacing: self.spacing,
                ..PdOptions::default()
            },
            materials: vec![
                PdMaterial::Proportional(self.metal),
                PdMaterial::Gas(tnt_products()?),
            ],
            bodies: vec![
                BodySpec {
                    shape: Shape::Cylinder {
                        base: [0.0; 3],
                        axis,
                        radius: self.inner_radius,
                        length: self.length,
                    },
                    material: 1,
                    velocity: [0.0; 3],
                },
                BodySpec {
                    shape: Shape::Shell {
                        base: [0.0; 3],
                        axis,
                        inner_radius: self.inner_radius,
                        outer_radius: self.outer_radius,
                        length: self.length,
                    },
                    material: 0,
                    velocity: [0.0; 3],
                },
            ],
            boundaries: vec![],
            detonation: Some(DetonationSpec {
                points: vec![DetonationPoint {
                    position: [0.0, 0.0, 0.5 * self.spacing],
                    time: 0.0,
                }],
                method: BurnMethod::Huygens,
            }),
        })
    }

    /// Metal-to-charge mass ratio M/C of the nominal geometry.
    pub fn metal_to_charge(&self) -> f64 {
        let metal = self.metal.density * (self.outer_radius.powi(2) - self.inner_radius.powi(2));
        let charge = Jwl::tnt().rho0 * self.inner_radius.powi(2);
        metal / charge
    }

    /// Gurney wall velocity of the nominal geometry, m/s: √(2E) at the
    /// cylinder-test expansion V = 7 along the TNT principal isentrope
    /// (`brisance_eos::tools::gurney_estimate`), and the open-ended cylinder
    /// relation v = √(2E)(M/C + ½)^{−1/2}.
    pub fn gurney_wall_velocity(&self) -> Result<f64, String> {
        let jwl = Jwl::tnt();
        let (_, cj) = ProductsIsentrope::from_jwl(&jwl).map_err(|e| e.to_string())?;
        let g = gurney_estimate(&jwl, &cj, CYLINDER_TEST_RELATIVE_VOLUME, 1e-11)
            .map_err(|e| e.to_string())?;
        cylinder_wall_velocity(g.gurney_velocity, self.metal_to_charge()).map_err(|e| e.to_string())
    }
}

/// The mid-length outer-wall history of a cylinder run.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct WallHistory {
    /// Times, s.
    pub time: Vec<f64>,
    /// Mean radial displacement of the outermost wall nodes within one
    /// spacing of mid-length, m.
    pub radial_displacement: Vec<f64>,
    /// Their mean radial velocity, m/s.
    pub radial_velocity: Vec<f64>,
    /// The whole wall's kinetic-energy mean radial velocity at mid-length,
    /// m/s: (Σ m v_r|v_r| / Σ m)^{1/2} with the sign of the sum, over
    /// every case node (all radii) within one spacing of mid-length — the
    /// velocity Gurney's model gives the wall as a whole, which a wall
    /// that rings through its thickness or tears does not put on its
    /// outer layer alone.
    pub wall_velocity: Vec<f64>,
    /// Total energy at the start ([`EnergyBudget::total`]), J.
    pub initial_energy: f64,
}

impl WallHistory {
    /// The largest sampled whole-wall velocity ([`Self::wall_velocity`])
    /// and its sample index (index 0 and −∞ for an empty record).
    pub fn wall_peak(&self) -> (usize, f64) {
        largest(&self.wall_velocity)
    }

    /// The largest sampled wall velocity and its sample index (index 0
    /// and −∞ for an empty record).
    pub fn peak(&self) -> (usize, f64) {
        largest(&self.radial_velocity)
    }
}

/// The largest value and its index (0 and −∞ for an empty slice).
fn largest(v: &[f64]) -> (usize, f64) {
    v.iter().copied().enumerate().fold(
        (0, f64::NEG_INFINITY),
        |b, (k, v)| if v > b.1 { (k, v) } else { b },
    )
}

/// Runs `case` to `end_time`, sampling the mid-length outer wall every
/// `every` steps; returns the solver at the end and the history.
pub fn run_cylinder(
    case: &TubeCase,
    end_time: f64,
    every: usize,
) -> Result<(PdSolver, WallHistory), String> {
    let s = PdSolver::new(case.setup().map_err(|e| e.to_string())?).map_err(|e| e.to_string())?;
    run_tube(
        s,
        case.length,
        case.outer_radius,
        case.spacing,
        end_time,
        every,
    )
}

/// The case material of a tube run: the material of the node farthest
/// from the z axis in the reference configuration (0 as [`TubeCase::setup`]
/// numbers them; a scenario file numbers its materials in the order of its
/// regions).
pub fn case_material(s: &PdSolver) -> u16 {
    let radius = |x: &[f64; 4]| x[0].hypot(x[1]);
    (0..s.node_count())
        .max_by(|&a, &b| radius(&s.reference()[a]).total_cmp(&radius(&s.reference()[b])))
        .map_or(0, |i| s.materials()[i])
}

/// [`run_cylinder`] on a solver built elsewhere (a scenario file through
/// the composer, say): the tube of `length` (m, from z = 0) and
/// `outer_radius` (m) on the z axis, lattice spacing `h`; the wall ring is
/// [`case_material`]'s outermost nodes within one spacing of mid-length.
pub fn run_tube(
    s: PdSolver,
    length: f64,
    outer_radius: f64,
    h: f64,
    end_time: f64,
    every: usize,
) -> Result<(PdSolver, WallHistory), String> {
    run_tube_at(s, 0.5 * length, outer_radius, h, end_time, every)
}

/// [`run_tube`] with the wall gauge at `gauge_z` (m) instead of
/// mid-length: the ring is the case's outermost nodes within one spacing
/// of it, the whole wall all its case nodes there.
pub fn run_tube_at(
    mut s: PdSolver,
    gauge_z: f64,
    outer_radius: f64,
    h: f64,
    end_time: f64,
    every: usize,
) -> Result<(PdSolver, WallHistory), String> {
    let case_material = case_material(&s);
    let ring: Vec<usize> = (0..s.node_count())
        .filter(|&i| {
            let x = s.reference()[i];
            let r = x[0].hypot(x[1]);
            s.materials()[i] == case_material && (x[2] - gauge_z).abs() <= h && r > outer_radius - h
        })
        .collect();
    if ring.is_empty() {
        return Err(format!("no wall node at z = {gauge_z} m"));
    }
    let slab: Vec<usize> = (0..s.node_count())
        .filter(|&i| {
            s.materials()[i] == case_material && (s.reference()[i][2] - gauge_z).abs() <= h
        })
        .collect();
    let mut history = WallHistory {
        initial_energy: EnergyBudget::of(&s).total(),
        ..WallHistory::default()
    };
    let mut sample = |s: &PdSolver| {
        let (mut u, mut v) = (0.0, 0.0);
        for &i in &ring {
            let (r0, r, vr) = radial(s, i);
            u += r - r0;
            v += vr;
        }
        let n = ring.len() as f64;
        history.time.push(s.time());
        history.radial_displacement.push(u / n);
        history.radial_velocity.push(v / n);
        history
            .wall_velocity
            .push(signed_ke_mean_radial_velocity(s, &slab));
    };
    sample(&s);
    let mut step = 0usize;
    while s.time() < end_time {
        let dt = s.stable_dt().map_err(|e| e.to_string())?;
        s.advance(dt.min(end_time - s.time()).max(1e-15))
            .map_err(|e| e.to_string())?;
        step += 1;
        if step.is_multiple_of(every) {
            sample(&s);
        }
    }
    sample(&s);
    Ok((s, history))
}

/// Node `i`'s reference and current radius about the z axis and its
/// radial velocity along the current radius (0 on the axis).
fn radial(s: &PdSolver, i: usize) -> (f64, f64, f64) {
    let x = s.reference()[i];
    let d = s.displacement(i);
    let (cx, cy) = (x[0] + d[0], x[1] + d[1]);
    let r = cx.hypot(cy);
    let vel = s.velocities()[i];
    let vr = if r > 0.0 {
        (vel[0] * cx + vel[1] * cy) / r
    } else {
        0.0
    };
    (x[0].hypot(x[1]), r, vr)
}

/// (Σ m v_r|v_r| / Σ m)^{1/2}, signed, over `nodes` (v_r along the
/// current position's radius about the z axis; 0 at the axis).
fn signed_ke_mean_radial_velocity(s: &PdSolver, nodes: &[usize]) -> f64 {
    let (mut mv2, mut m) = (0.0, 0.0);
    for &i in nodes {
        let (_, _, vr) = radial(s, i);
        mv2 += s.mass(i) * vr * vr.abs();
        m += s.mass(i);
    }
    if m > 0.0 {
        (mv2 / m).abs().sqrt().copysign(mv2)
    } else {
        0.0
    }
}

/// Where the energy of a tube run is (J): the products' stored energy
/// W(X)V and chemical energy not yet released, the kinetic energy of the
/// case and of the products, the elastic energy of the case bonds, the
/// energy stored in the short-range contacts (eq 27's pair potential,
/// [`PdSolver::contact_energy`]) and the energy the case bonds dissipated
/// by yielding and breaking ([`PdSolver::dissipated_energy`]) — the terms
/// of the run summary's total.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct EnergyBudget {
    /// Σ W(X_i) V_i over the explosive nodes (W(1) V_i before detonation).
    pub products: f64,
    /// Kinetic energy of the case nodes.
    pub case_kinetic: f64,
    /// Kinetic energy of the products nodes.
    pub products_kinetic: f64,
    /// Bond energy of the case.
    pub bonds: f64,
    /// Energy stored in the short-range contacts (products on the case,
    /// case on case, and products on products where that contact is on).
    pub contact: f64,
    /// Energy the case bonds dissipated: plastic work and what breaking
    /// bonds held.
    pub dissipated: f64,
}

impl EnergyBudget {
    /// The budget of the solver's current state (the case is
    /// [`case_material`]).
    pub fn of(s: &PdSolver) -> Self {
        let (mut case_kinetic, mut products_kinetic) = (0.0, 0.0);
        let case = case_material(s);
        for i in 0..s.node_count() {
            let v = s.velocities()[i];
            let k = 0.5 * s.mass(i) * (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
            if s.materials()[i] == case {
                case_kinetic += k;
            } else {
                products_kinetic += k;
            }
        }
        Self {
            products: s.gas_energy(),
            case_kinetic,
            products_kinetic,
            bonds: s.bond_energy(),
            contact: s.contact_energy(),
            dissipated: s.dissipated_energy(),
        }
    }

    /// The sum of the six parts.
    pub fn total(&self) -> f64 {
        self.products
            + self.case_kinetic
            + self.products_kinetic
            + self.bonds
            + self.contact
            + self.dissipated
    }

    /// Where the released energy went, one line for the studies' output:
    /// `released` (J, the products' initial Σ W V less [`Self::products`])
    /// and each other part as a share of it, then [`Self::total`] over
    /// `initial_total`.
    pub fn shares(&self, released: f64, initial_total: f64) -> String {
        let pc = |x: f64| 100.0 * x / released;
        format!(
            "released {:.1} kJ: case kinetic {:.1} %, products kinetic {:.1} %, case bonds {:.1} %, \
             contacts {:.2} %, dissipated by the case bonds {:.2} %; total / initial {:.4}",
            released * 1e-3,
            pc(self.case_kinetic),
            pc(self.products_kinetic),
            pc(self.bonds),
            pc(self.contact),
            pc(self.dissipated),
            self.total() / initial_total
        )
    }
}

/// The products' kinetic energy split (J) and the axial momentum (N s) of
/// a tube run (the case [`case_material`], the tube along z).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct ProductsMotion {
    /// Σ ½ m v_z² over the products nodes.
    pub axial: f64,
    /// Σ ½ m (v_x² + v_y²) over the products nodes.
    pub transverse: f64,
    /// Σ ½ m |v_i − v_fit(y_i)|² over the products nodes, v_fit the
    /// mass-weighted least-squares affine velocity field v̄ + L (y − ȳ) of
    /// the node's family of products nodes (itself included, current
    /// positions y): the node-scale motion no resolved velocity gradient
    /// explains.
    pub non_affine: f64,
    /// Σ ½ m |v_i − v̄|² with v̄ the family's mean velocity alone: counts a
    /// resolved gradient across the horizon as node-scale motion too.
    pub about_family_mean: f64,
    /// Σ m v_z over the products nodes.
    pub products_momentum_z: f64,
    /// Σ m v_z over all nodes.
    pub total_momentum_z: f64,
}

impl ProductsMotion {
    /// The split of the solver's current state.
    pub fn of(s: &PdSolver) -> Self {
        let case = case_material(s);
        let gas = |i: usize| s.materials()[i] != case;
        let f = s.families();
        let mut out = Self::default();
        for i in 0..s.node_count() {
            let v = s.velocities()[i];
            let m = s.mass(i);
            out.total_momentum_z += m * v[2];
            if !gas(i) {
                continue;
            }
            out.products_momentum_z += m * v[2];
            out.axial += 0.5 * m * v[2] * v[2];
            out.transverse += 0.5 * m * (v[0] * v[0] + v[1] * v[1]);
            let members = || {
                std::iter::once(i).chain(
                    f.row(i)
                        .map(|k| f.neighbours[k] as usize)
                        .filter(|&j| gas(j)),
                )
            };
            let (mut mass, mut ym, mut vm) = (0.0, [0.0; 3], [0.0; 3]);
            for j in members() {
                let w = s.mass(j);
                let (y, vj) = (s.current_position(j), s.velocities()[j]);
                mass += w;
                for d in 0..3 {
                    ym[d] += w * y[d];
                    vm[d] += w * vj[d];
                }
            }
            for d in 0..3 {
                ym[d] /= mass;
                vm[d] /= mass;
            }
            // Moments A = Σ w dy dyᵀ, B = Σ w dv dyᵀ; L = B A⁻¹.
            let (mut a, mut b) = ([[0.0; 3]; 3], [[0.0; 3]; 3]);
            for j in members() {
                let w = s.mass(j);
                let (y, vj) = (s.current_position(j), s.velocities()[j]);
                for r in 0..3 {
                    for c in 0..3 {
                        a[r][c] += w * (y[r] - ym[r]) * (y[c] - ym[c]);
                        b[r][c] += w * (vj[r] - vm[r]) * (y[c] - ym[c]);
                    }
                }
            }
            let yi = s.current_position(i);
            let dyi = [yi[0] - ym[0], yi[1] - ym[1], yi[2] - ym[2]];
            let mut fit = vm;
            if let Some(inv) = inverse3(&a) {
                for d in 0..3 {
                    for c in 0..3 {
                        let l: f64 = (0..3).map(|k| b[d][k] * inv[k][c]).sum();
                        fit[d] += l * dyi[c];
                    }
                }
            }
            out.non_affine += 0.5 * m * (0..3).map(|d| (v[d] - fit[d]).powi(2)).sum::<f64>();
            out.about_family_mean += 0.5 * m * (0..3).map(|d| (v[d] - vm[d]).powi(2)).sum::<f64>();
        }
        out
    }
}

/// The inverse of a 3 × 3 matrix by cofactors (None when singular relative
/// to the size of its entries).
fn inverse3(a: &[[f64; 3]; 3]) -> Option<[[f64; 3]; 3]> {
    let det = a[0][0] * (a[1][1] * a[2][2] - a[1][2] * a[2][1])
        - a[0][1] * (a[1][0] * a[2][2] - a[1][2] * a[2][0])
        + a[0][2] * (a[1][0] * a[2][1] - a[1][1] * a[2][0]);
    let scale = a.iter().flatten().fold(0.0f64, |m, v| m.max(v.abs()));
    if !(det.abs() > 1e-12 * scale * scale * scale) {
        return None;
    }
    let mut inv = [[0.0; 3]; 3];
    for (r, row) in inv.iter_mut().enumerate() {
        for (c, v) in row.iter_mut().enumerate() {
            let (r1, r2) = ((c + 1) % 3, (c + 2) % 3);
            let (c1, c2) = ((r + 1) % 3, (r + 2) % 3);
            *v = (a[r1][c1] * a[r2][c2] - a[r1][c2] * a[r2][c1]) / det;
        }
    }
    Some(inv)
}

/// Products nodes that have gone through the case: those whose current
/// distance from the axis exceeds that of every case node in their axial
/// slab of one spacing and the two slabs beside it, counted over the nodes whose
/// current axial position lies in `z_range` (m). Returns (through,
/// products nodes counted).
pub fn products_through_case(s: &PdSolver, spacing: f64, z_range: (f64, f64)) -> (usize, usize) {
    let n = s.node_count();
    let current = |i: usize| {
        let x = s.reference()[i];
        let u = s.displacement(i);
        [x[0] + u[0], x[1] + u[1], x[2] + u[2]]
    };
    // Largest case radius per axial slab of one spacing (slabs cover z_range
    // with one spare on each side).
    let slabs = ((z_range.1 - z_range.0) / spacing).ceil().max(0.0) as usize + 3;
    let slab = |z: f64| ((z - z_range.0) / spacing + 1.0).floor();
    let mut outer = vec![f64::NEG_INFINITY; slabs];
    let case = case_material(s);
    for i in (0..n).filter(|&i| s.materials()[i] == case) {
        let y = current(i);
        let b = slab(y[2]);
        if b >= 0.0 && (b as usize) < slabs {
            let r = y[0].hypot(y[1]);
            outer[b as usize] = outer[b as usize].max(r);
        }
    }
    let (mut through, mut counted) = (0, 0);
    for i in (0..n).filter(|&i| s.materials()[i] != case) {
        let y = current(i);
        if y[2] < z_range.0 || y[2] > z_range.1 {
            continue;
        }
        counted += 1;
        let b = slab(y[2]) as usize;
        let edge = outer[b - 1].max(outer[b]).max(outer[b + 1]);
        if y[0].hypot(y[1]) > edge {
            through += 1;
        }
    }
    (through, counted)
}

/// Fragment statistics of a fragmenting run.
#[derive(Debug, Clone, PartialEq)]
pub struct FragmentResult {
    /// Fragments, largest first.
    pub fragments: Vec<Fragment>,
    /// Mass of every case node, kg.
    pub case_mass: f64,
    /// Σ fragment masses, kg.
    pub fragment_mass: f64,
    /// Steps taken.
    pub steps: u64,
}

/// Runs `case` to `end_time` and counts the fragments of the case.
pub fn run_fragmentation(
    case: &TubeCase,
    end_time: f64,
) -> Result<(PdSolver, FragmentResult), String> {
    let s = PdSolver::new(case.setup().map_err(|e| e.to_string())?).map_err(|e| e.to_string())?;
    fragment(s, end_time)
}

/// [`run_fragmentation`] on a solver built elsewhere (a scenario file
/// through the composer, say): runs it to `end_time` at its stable step
/// and cuts the case ([`case_material`]) into fragments.
pub fn fragment(mut s: PdSolver, end_time: f64) -> Result<(PdSolver, FragmentResult), String> {
    let mut steps = 0;
    while s.time() < end_time {
        let dt = s.stable_dt().map_err(|e| e.to_string())?;
        s.advance(dt.min(end_time - s.time()).max(1e-15))
            .map_err(|e| e.to_string())?;
        steps += 1;
    }
    let fragments = s.fragments();
    let case = case_material(&s);
    // Both sums exact, rounded once: their difference is the fragments'
    // own rounding (≤ ε/2 of the case mass) unless mass is lost.
    let mut case_mass = brisance_core::ExactSum::new();
    for i in (0..s.node_count()).filter(|&i| s.materials()[i] == case) {
        case_mass.add(s.mass(i));
    }
    let case_mass = case_mass.value();
    let mut fragment_mass = brisance_core::ExactSum::new();
    for f in &fragments {
        fragment_mass.add(f.mass);
    }
    let fragment_mass = fragment_mass.value();
    Ok((
        s,
        FragmentResult {
            fragments,
            case_mass,
            fragment_mass,
            steps,
        },
    ))
}

/// The micro-elastic 3D block that measures bond-force throughput (the
/// criterion bench `pd_bond_forces` and the `bond_throughput` example):
/// n³ nodes of spacing h in one steel-like body (ρc² = 7850 · 3212² Pa),
/// δ = 3h, under a smooth small displacement field so every bond is
/// stretched; no bond yields or breaks.
#[derive(Debug, Clone)]
pub struct BondBenchBlock {
    /// (x, V) per node.
    pub reference: Vec<[f64; 4]>,
    /// (u, σ) per node.
    pub state: Vec<[f64; 4]>,
    /// The bond families.
    pub families: crate::Families,
    /// Material index per node (all 0).
    pub material: Vec<u16>,
    /// The one micro-elastic law.
    pub laws: [crate::BondLaw; 1],
    /// Partial-volume factor per bond (the kernel's mutable bond state).
    pub factor: Vec<f32>,
}

impl BondBenchBlock {
    /// The block of n³ nodes of spacing `h` (m).
    pub fn new(n: usize, h: f64) -> Self {
        let cloud = crate::fill_lattice(
            &crate::LatticeSpec {
                spacing: h,
                origin: [0.0; 3],
                dimension: crate::Dimension::Three,
                cross_section: 0.0,
                jitter: None,
            },
            &[BodySpec {
                shape: Shape::Box {
                    min: [0.0; 3],
                    max: [n as f64 * h; 3],
                },
                material: 0,
                velocity: [0.0; 3],
            }],
        )
        .expect("a box of positive size fills with nodes");
        let horizon = 3.0 * h;
        let families = crate::build_families(&cloud.positions, &cloud.body, horizon, h);
        let reference = cloud
            .positions
            .iter()
            .zip(&cloud.volumes)
            .map(|(x, v)| [x[0], x[1], x[2], *v])
            .collect();
        let state = cloud
            .positions
            .iter()
            .map(|x| {
                [
                    1e-4 * (x[0] * 300.0).sin(),
                    1e-4 * x[1],
                    -2e-5 * x[2],
                    f64::INFINITY,
                ]
            })
            .collect();
        let mut factor = Vec::with_capacity(families.bond_count());
        for (i, a) in cloud.positions.iter().enumerate() {
            for &j in &families.neighbours[families.row(i)] {
                let b = cloud.positions[j as usize];
                let r =
                    ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)).sqrt();
                factor.push(crate::partial_volume(r, horizon, h) as f32);
            }
        }
        let material = vec![0u16; cloud.positions.len()];
        let laws = [crate::BondLaw::Solid {
            micromodulus: crate::spring_constant(7850.0 * 3212.0 * 3212.0, horizon),
            yield_stretch: f64::INFINITY,
            plastic: false,
            critical_stretch: f64::INFINITY,
        }];
        Self {
            reference,
            state,
            families,
            material,
            laws,
            factor,
        }
    }

    /// The kernel's read-only input.
    pub fn input(&self) -> crate::ForceInput<'_> {
        crate::ForceInput {
            reference: &self.reference,
            state: &self.state,
            offsets: &self.families.offsets,
            neighbours: &self.families.neighbours,
            material: &self.material,
            laws: &self.laws,
            mirror_walls: false,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A 5.2 mm slice of the copper tube at h = 1.3 mm.
    fn slice() -> (TubeCase, PdSolver) {
        let case = copper_cylinder(1.3e-3, 5.2e-3);
        let s = PdSolver::new(case.setup().unwrap()).unwrap();
        (case, s)
    }

    /// A radial field v = k (x, y, 0) on the slice at rest: every case
    /// node moves outward at k r, so the whole wall's kinetic-energy mean
    /// radial velocity is k (Σ m r² / Σ m)^{1/2}, negative for k < 0; a
    /// uniform axial velocity adds nothing.
    #[test]
    fn the_wall_velocity_is_the_kinetic_energy_mean_of_the_radial_velocity() {
        let (_, mut s) = slice();
        let case = case_material(&s);
        let nodes: Vec<usize> = (0..s.node_count())
            .filter(|&i| s.materials()[i] == case)
            .collect();
        let (mut mr2, mut m) = (0.0, 0.0);
        for &i in &nodes {
            let x = s.reference()[i];
            mr2 += s.mass(i) * (x[0] * x[0] + x[1] * x[1]);
            m += s.mass(i);
        }
        let rms_r = (mr2 / m).sqrt();
        assert!(rms_r > 0.0127 && rms_r < 0.0153);
        for k in [4.0e4, -2.5e4] {
            s.set_velocities(|x| [k * x[0], k * x[1], 300.0]);
            let v = signed_ke_mean_radial_velocity(&s, &nodes);
            assert!(
                (v - k * rms_r).abs() <= 1e-12 * (k * rms_r).abs(),
                "{v} vs {}",
                k * rms_r
            );
        }
    }

    /// The shares line reads each part against the released energy, by
    /// hand: 10 kJ released, case 3 kJ (30.0 %), products 5 kJ (50.0 %),
    /// bonds 0.5 kJ (5.0 %), contacts 25 J (0.25 %), dissipated 125 J
    /// (1.25 %); the total 12 kJ of 12.5 kJ initially (0.9600).
    #[test]
    fn the_shares_line_is_the_parts_over_the_released_energy() {
        let e = EnergyBudget {
            products: 3350.0,
            case_kinetic: 3000.0,
            products_kinetic: 5000.0,
            bonds: 500.0,
            contact: 25.0,
            dissipated: 125.0,
        };
        assert_eq!(e.total(), 12_000.0);
        assert_eq!(
            e.shares(10_000.0, 12_500.0),
            "released 10.0 kJ: case kinetic 30.0 %, products kinetic 50.0 %, case bonds 5.0 %, \
             contacts 0.25 %, dissipated by the case bonds 1.25 %; total / initial 0.9600"
        );
    }

    /// An affine velocity field v = v₀ + L x has no non-affine part; it
    /// has a part about the family mean (the gradient across the horizon),
    /// and the axial and transverse parts are ½ m v_z² and ½ m (v_x² +
    /// v_y²). One node kicked by 10 m/s along x on top of a uniform field
    /// adds non-affine energy below ½ m 10² (the fit takes some of it).
    #[test]
    fn products_motion_separates_affine_flow_from_node_scale_motion() {
        let (_, mut s) = slice();
        s.set_velocities(|x| [100.0 + 2.0e4 * x[0], -3.0e4 * x[2], 50.0 + 1.0e4 * x[1]]);
        let m = ProductsMotion::of(&s);
        let (mut ax, mut tr, mut pz) = (0.0, 0.0, 0.0);
        for i in (0..s.node_count()).filter(|&i| s.materials()[i] == 1) {
            let v = s.velocities()[i];
            ax += 0.5 * s.mass(i) * v[2] * v[2];
            tr += 0.5 * s.mass(i) * (v[0] * v[0] + v[1] * v[1]);
            pz += s.mass(i) * v[2];
        }
        assert!((m.axial - ax).abs() <= 1e-12 * ax && (m.transverse - tr).abs() <= 1e-12 * tr);
        assert!((m.products_momentum_z - pz).abs() <= 1e-12 * pz.abs());
        assert!(m.non_affine < 1e-20 * (ax + tr), "{m:?}");
        assert!(m.about_family_mean > 1e-6 * (ax + tr), "{m:?}");
        let k = (0..s.node_count())
            .find(|&i| s.materials()[i] == 1)
            .unwrap();
        let xk = s.reference()[k];
        s.set_velocities(|x| {
            let here = x[0] == xk[0] && x[1] == xk[1] && x[2] == xk[2];
            [if here { 10.0 } else { 0.0 }, 0.0, 5.0]
        });
        let m = ProductsMotion::of(&s);
        let half_m_dv2 = 0.5 * s.mass(k) * 100.0;
        assert!(
            m.non_affine > 0.1 * half_m_dv2 && m.non_affine < 1.5 * half_m_dv2,
            "{} vs {half_m_dv2}",
            m.non_affine
        );
    }

    #[test]
    fn energy_budget_at_rest_is_the_chemical_energy_and_moving_adds_half_m_v2() {
        let (_, mut s) = slice();
        let b = EnergyBudget::of(&s);
        let gas = tnt_products().unwrap();
        let volume: f64 = (0..s.node_count())
            .filter(|&i| s.materials()[i] == 1)
            .map(|i| s.reference()[i][3])
            .sum();
        let w1 = gas.isentrope.energy(1.0) * volume;
        assert!((b.products - w1).abs() <= 1e-12 * w1, "{b:?} vs {w1}");
        assert_eq!(
            (b.case_kinetic, b.products_kinetic, b.bonds, b.contact),
            (0.0, 0.0, 0.0, 0.0)
        );
        s.set_velocities(|_| [3.0, 0.0, 4.0]);
        let b = EnergyBudget::of(&s);
        let (mut mc, mut mg) = (0.0, 0.0);
        for i in 0..s.node_count() {
            if s.materials()[i] == 0 {
                mc += s.mass(i);
            } else {
                mg += s.mass(i);
            }
        }
        assert!((b.case_kinetic - 12.5 * mc).abs() <= 1e-12 * 12.5 * mc);
        assert!((b.products_kinetic - 12.5 * mg).abs() <= 1e-12 * 12.5 * mg);
        assert!((b.total() - (w1 + 12.5 * (mc + mg))).abs() <= 1e-12 * b.total());
    }

    /// The budget is the run summary's total
    /// (`Solver::conservation_totals`), the contact energy included: a
    /// slice squeezed radially until its products press on the case
    /// within the contact distance holds energy in the contacts, and the
    /// two totals agree to round-off.
    #[test]
    fn the_budget_counts_the_contact_energy_as_the_run_summary_does() {
        let (_, mut s) = slice();
        s.set_velocities(|x| [-4.0e4 * x[0], -4.0e4 * x[1], 0.0]);
        let e0 = s.conservation_totals().energy;
        let mut steps = 0;
        while s.contact_energy() <= 1e-6 * e0 && steps < 400 {
            let dt = s.stable_dt().unwrap();
            s.advance(dt).unwrap();
            steps += 1;
        }
        let b = EnergyBudget::of(&s);
        assert!(
            b.contact > 1e-6 * e0,
            "{} J in contacts after {steps} steps",
            b.contact
        );
        let e = s.conservation_totals().energy;
        assert!(
            (b.total() - e).abs() <= 1e-12 * e.abs(),
            "{b:?}: {} vs {e}",
            b.total()
        );
        assert!((b.total() - b.contact - e).abs() > 1e-7 * e.abs());
    }

    #[test]
    fn a_products_node_thrown_through_the_case_is_counted() {
        let (case, mut s) = slice();
        let z = (0.0, case.length);
        let (through, counted) = products_through_case(&s, case.spacing, z);
        let gas = (0..s.node_count())
            .filter(|&i| s.materials()[i] == 1)
            .count();
        assert_eq!((through, counted), (0, gas));
        // One products node near mid-length on the +x side, 10⁷ m/s outward
        // for 1 ns: 10 mm, well past the 15.3 mm outer radius.
        let pick = (0..s.node_count())
            .filter(|&i| s.materials()[i] == 1)
            .max_by(|&a, &b| {
                let key = |i: usize| s.reference()[i][0] - (s.reference()[i][2] - 2.6e-3).abs();
                key(a).total_cmp(&key(b))
            })
            .unwrap();
        let target = s.reference()[pick];
        s.set_velocities(|x| {
            if x == [target[0], target[1], target[2]] {
                [1.0e7, 0.0, 0.0]
            } else {
                [0.0; 3]
            }
        });
        s.advance(1.0e-9).unwrap();
        assert_eq!(products_through_case(&s, case.spacing, z), (1, gas));
    }
}
