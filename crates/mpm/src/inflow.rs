//! Open faces with a particle reservoir beyond them: the way matter enters
//! an MPM grid.
//!
//! A [`Reservoir`] on a face continues the material across it as layers
//! of particles on the lattice of the initial fill (`ppc` per cell per
//! active direction, the transverse positions of the face's cells),
//! filling a slab beyond the face as deep as any shape function reaches
//! into the grid's node lattice. Each column of the face (a boundary cell
//! and the reservoir behind it) has its own layers:
//!
//! - [`ReservoirKind::Fixed`]: layers of the given state at the fill's
//!   spacing s = Δx/ppc along the normal, which move with the state's
//!   normal velocity: the phase ψ, the distance of the nearest layer beyond
//!   the face, starts at s/2, continuing the initial fill, decreases by
//!   u_n Δt every step, and is kept in checkpoints;
//! - [`ReservoirKind::ZeroGradient`]: the particles of the boundary cell
//!   continued across the face: their mass-weighted velocity, specific
//!   internal energy and temperature, their density Σm/ΣV and stress
//!   ΣVσ/ΣV (without the bulk viscosity), particles of their mean volume
//!   V̄ at the spacing s V̄/V⁰ that volume takes along the normal, the
//!   nearest layer one spacing beyond the nearest particle;
//! - [`ReservoirKind::OutflowOnly`]: as `ZeroGradient`, with the normal
//!   velocity set to zero where it points into the domain.
//!
//! Each step:
//!
//! 1. **inject** — at its start, a fixed reservoir's layers that have
//!    crossed the face (ψ < 0) become particles where they reached, and a
//!    zero-gradient reservoir fills the gap between the face and the
//!    nearest particle with layers one spacing apart where it has grown
//!    beyond a spacing ([`Reservoirs::inject`]); what they bring in is
//!    booked as negative outflow;
//! 2. **share** — the reservoir particles add their mass m N_I, momentum
//!    m N_I v and internal force −V σ ∇N_I to the nodes they reach, as
//!    particles inside would ([`Reservoirs::share`]): the nodes on and next
//!    to the face see the material continue instead of a free surface. The
//!    reservoir is kinematic: the step does not update its particles;
//! 3. **advance** — at the end of the step a fixed reservoir moves by its
//!    normal velocity times Δt ([`Reservoirs::advance`]).
//!
//! This is the inflow buffer of the particle methods: buffer particles
//! beyond the inlet that move at the inflow velocity, take part in the
//! interactions of the particles near it, and turn into ordinary
//! particles when they cross it, a new buffer particle being created
//! behind (Federico, Marrone, Colagrossi, Aristodemo & Antuono 2012,
//! "Simulating 2D open-channel flows through an SPH model", Eur. J. Mech.
//! B/Fluids 34, 35–46; Tafuni, Domínguez, Vacondio & Crespo 2018, "A
//! versatile algorithm for the treatment of open boundary conditions in
//! smoothed particle hydrodynamics GPU models", CMAME 342, 604–624); the
//! MPM code OSParticulas injects particles at an inlet in the same spirit
//! (NairnMPM documentation, "FluidSource custom task" and "Material point
//! reservoir"). For a uniform stream the reservoir particles continue the
//! particle lattice exactly, so the nodes next to the face get what they
//! would get inside and the stream stays uniform to round-off.
//!
//! The zero-gradient reservoir continues the particles as they are, their
//! volume included, not a nominal lattice: a reservoir that copied the
//! boundary pressure onto particles of the fill's volume pushed on the
//! face node with p V⁰ while the particles inside pushed with p V, so an
//! expanding boundary cell was pulled outwards (for a gas, p V falls more
//! slowly than p V⁰ as it expands) and a gas at rest between such a face
//! and a wall ran away from round-off within a few hundred steps.
//!
//! The particles a reservoir injects are booked as negative outflow (their
//! mass, momentum and energy m(e + |v|²/2)); the force its stress exerts
//! on the nodes is added to the surface forces, so its work — the flow
//! work p u A of an Eulerian energy flux — is counted in the external work
//! W. What is left unbooked is the momentum the reservoir's kinematic
//! particles exchange with the nodes they share with the material inside,
//! which vanishes for a uniform stream.
//!
//! Everything here runs serially in a fixed order (columns, layers,
//! transverse positions; particles in storage order for the boundary
//! states), so the bits do not depend on the thread count; the buffers
//! are kept between steps.

use crate::grid_nodes::GridNodes;
use crate::particles::IDENTITY;
use crate::transfer::GridMap;
use crate::viscosity::BulkViscosityState;
use crate::{MaterialId, ParticleInit, Particles, ShapeFunction, ShapeStencil};
use brisance_constitutive::MaterialModel;
use brisance_core::{ConservationTotals, Material, UniformGridGeometry};
use serde::{Deserialize, Serialize};

/// A state of the material beyond a face.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct ReservoirState {
    /// The material of its particles.
    pub material: MaterialId,
    /// Density, kg/m³.
    pub density: f64,
    /// Velocity, m/s.
    pub velocity: [f64; 3],
    /// Specific internal energy, J/kg.
    pub specific_internal_energy: f64,
    /// Temperature, K.
    pub temperature: f64,
    /// Cauchy stress in Voigt order (xx, yy, zz, yz, xz, xy), Pa: −p I for
    /// a fluid at pressure p.
    pub stress: [f64; 6],
}

/// What the reservoir beyond a face holds.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub enum ReservoirKind {
    /// The state of the particles in the boundary cell, continued across
    /// the face, both ways: where it moves inwards it enters (the config's
    /// `ZeroGradient`).
    ZeroGradient,
    /// As [`ReservoirKind::ZeroGradient`] with the normal velocity set to
    /// zero where it points into the domain (the FLASH "diode" of the grid
    /// solvers): the reservoir never moves in, so nothing enters, and the
    /// nodes at the face see material at rest in the normal direction
    /// behind it (the config's `OutflowOnly`).
    OutflowOnly,
    /// A given state (the config's `Fixed(state)`).
    Fixed(ReservoirState),
}

/// The reservoir of one face.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Reservoir {
    /// What it holds.
    pub kind: ReservoirKind,
    /// Particles per cell per active direction of its layers, as the
    /// initial fill (1 to 8).
    pub ppc: usize,
}

/// A reservoir particle's share of one node: N m and N m v.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NodeShare {
    /// Storage index of the node.
    pub node: usize,
    /// N_I m, kg.
    pub mass: f64,
    /// N_I m v, kg·m/s.
    pub momentum: [f64; 3],
}

/// Adds the reservoirs' mass and momentum shares to the nodes (after the
/// P2G of the particles' mass and momentum).
pub fn add_mass_and_momentum(shares: &[NodeShare], nodes: &mut GridNodes) {
    for s in shares {
        nodes.mass[s.node] += s.mass;
        for c in 0..3 {
            nodes.momentum[s.node][c] += s.momentum[c];
        }
    }
}

/// Adds the reservoirs' momentum shares to the nodes (after MUSL's
/// re-mapping of the momentum; the reservoir's velocity is not updated by
/// a step).
pub fn add_momentum(shares: &[NodeShare], nodes: &mut GridNodes) {
    for s in shares {
        for c in 0..3 {
            nodes.momentum[s.node][c] += s.momentum[c];
        }
    }
}

/// The share of a boundary particle's sound speed its inward normal
/// velocity must exceed for a one-way face to count as holding back an
/// inflow ([`Reservoirs::blocked_inflow`]), so that round-off drift of
/// material at rest is not reported.
pub const BLOCKED_SPEED_FRACTION: f64 = 1e-3;

/// Sums over the particles of one boundary cell.
#[derive(Debug, Clone, Copy, Default)]
struct ColumnSums {
    count: usize,
    mass: f64,
    volume: f64,
    momentum: [f64; 3],
    energy: f64,
    temperature: f64,
    /// Σ V σ, the material stress σ_p + q_p I (without the bulk
    /// viscosity).
    stress: [f64; 6],
    /// The particle nearest the face: its distance from it and material.
    nearest: Option<(f64, MaterialId)>,
}

impl ColumnSums {
    /// The state of the boundary cell's particles and their mean volume.
    fn state(&self) -> Option<(ReservoirState, f64)> {
        let (_, material) = self.nearest?;
        if !(self.mass > 0.0 && self.volume > 0.0) {
            return None;
        }
        Some((
            ReservoirState {
                material,
                density: self.mass / self.volume,
                velocity: self.momentum.map(|p| p / self.mass),
                specific_internal_energy: self.energy / self.mass,
                temperature: self.temperature / self.mass,
                stress: self.stress.map(|s| s / self.volume),
            },
            self.volume / self.count as f64,
        ))
    }
}

/// The reservoir behind one column of a face this step.
#[derive(Debug, Clone, Copy)]
struct ColumnReservoir {
    state: ReservoirState,
    /// Its particles' stretch J along the normal: their volume is J V⁰,
    /// their deformation gradient the identity with J on the normal.
    stretch: f64,
    /// Its layer spacing along the normal, m.
    spacing: f64,
    /// Distance of its nearest layer beyond the face, m.
    first: f64,
}

/// The reservoir of one face and its state.
#[derive(Debug, Clone)]
struct FaceReservoir {
    /// Face index (x−, x+, y−, y+, z−, z+).
    face: usize,
    /// Its normal axis.
    axis: usize,
    /// +1 on a low face, −1 on a high one: the inward normal's sign.
    inward: f64,
    kind: ReservoirKind,
    /// Particles per cell along each axis (1 on inactive ones).
    per_axis: [usize; 3],
    /// The fill's layer spacing along the normal, s = Δx/ppc, m.
    spacing: f64,
    /// The fill's particle volume V⁰, m³.
    volume: f64,
    /// The two transverse axes, lower first.
    transverse: [usize; 2],
    /// Per column, a fixed reservoir's ψ: the distance of its nearest layer
    /// beyond the face, m (negative once it has crossed); unused by the
    /// others.
    phase: Vec<f64>,
    /// Per column: the reservoir this step (`None`: none, an empty
    /// boundary cell).
    columns: Vec<Option<ColumnReservoir>>,
    /// Per column: the boundary cell's sums (reused).
    sums: Vec<ColumnSums>,
}

impl FaceReservoir {
    /// The column of the boundary cell `cell`, if it is one of this face.
    fn column(&self, cell: [usize; 3], cells: [usize; 3]) -> Option<usize> {
        let at = if self.inward > 0.0 {
            0
        } else {
            cells[self.axis] - 1
        };
        (cell[self.axis] == at).then(|| {
            let [t1, t2] = self.transverse;
            cell[t1] + cells[t1] * cell[t2]
        })
    }

    /// The position of the particle at outward distance `d` from the face
    /// (negative: inside) and transverse sub-positions `sub` of column
    /// `col`.
    fn position(
        &self,
        grid: &UniformGridGeometry,
        col: usize,
        sub: [usize; 2],
        d: f64,
    ) -> [f64; 3] {
        let [t1, _] = self.transverse;
        let cell = [col % grid.cells[t1], col / grid.cells[t1]];
        let mut x = [0.0; 3];
        for (k, &t) in self.transverse.iter().enumerate() {
            x[t] = grid.origin[t]
                + (cell[k] as f64 + (sub[k] as f64 + 0.5) / self.per_axis[t] as f64)
                    * grid.spacing[t];
        }
        let a = self.axis;
        x[a] = if self.inward > 0.0 {
            grid.origin[a] - d
        } else {
            grid.origin[a] + grid.cells[a] as f64 * grid.spacing[a] + d
        };
        x
    }

    /// The identity with `stretch` on the normal: the deformation gradient
    /// of a reservoir particle of volume `stretch` V⁰.
    fn deformation(&self, stretch: f64) -> [f64; 9] {
        let mut f = IDENTITY;
        f[4 * self.axis] = stretch;
        f
    }

    /// Calls `f` with every transverse sub-position of a layer.
    fn for_each_sub(&self, mut f: impl FnMut([usize; 2])) {
        let [t1, t2] = self.transverse;
        for s2 in 0..self.per_axis[t2] {
            for s1 in 0..self.per_axis[t1] {
                f([s1, s2]);
            }
        }
    }
}

/// Why the reservoirs cannot be set up.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("reservoir on face {face}: {detail}")]
pub struct ReservoirError {
    /// The face index (x−, x+, y−, y+, z−, z+).
    pub face: usize,
    /// What is wrong.
    pub detail: String,
}

/// The reservoirs of a solver, their state and their reused buffers.
#[derive(Debug, Clone, Default)]
pub struct Reservoirs {
    faces: Vec<FaceReservoir>,
    /// This step's node shares (mass, momentum) of every reservoir
    /// particle.
    shares: Vec<NodeShare>,
    /// This step's internal-force contributions, (node, force in N).
    forces: Vec<(usize, [f64; 3])>,
    /// The particles a step injects (reused).
    injected: Vec<ParticleInit>,
    /// Per face: whether a one-way face has held back an inflow.
    blocked: [bool; 6],
    stencil: ShapeStencil,
}

impl Reservoirs {
    /// The reservoirs `reservoirs` (per face, `None` for none) on `grid`;
    /// faces of inactive directions get none.
    pub fn new(
        reservoirs: &[Option<Reservoir>; 6],
        grid: &UniformGridGeometry,
        materials: usize,
    ) -> Result<Self, ReservoirError> {
        let mut faces = Vec::new();
        for (face, r) in reservoirs.iter().enumerate() {
            let Some(r) = r else { continue };
            let axis = face / 2;
            if grid.cells[axis] <= 1 {
                continue;
            }
            let err = |detail: String| ReservoirError { face, detail };
            if !(1..=8).contains(&r.ppc) {
                return Err(err(format!("ppc = {} must lie in 1..=8", r.ppc)));
            }
            if let ReservoirKind::Fixed(s) = &r.kind {
                let finite = s.velocity.iter().chain(&s.stress).all(|v| v.is_finite())
                    && s.specific_internal_energy.is_finite()
                    && s.temperature.is_finite();
                if !(s.density > 0.0 && s.density.is_finite() && finite) {
                    return Err(err(format!(
                        "density {} kg/m³ must be positive and the state finite",
                        s.density
                    )));
                }
                if s.material.0 as usize >= materials {
                    return Err(err(format!(
                        "material {} beyond the {materials} materials",
                        s.material.0
                    )));
                }
            }
            let per_axis: [usize; 3] =
                std::array::from_fn(|d| if grid.cells[d] > 1 { r.ppc } else { 1 });
            let transverse = match axis {
                0 => [1, 2],
                1 => [0, 2],
                _ => [0, 1],
            };
            let columns = grid.cells[transverse[0]] * grid.cells[transverse[1]];
            let spacing = grid.spacing[axis] / r.ppc as f64;
            faces.push(FaceReservoir {
                face,
                axis,
                inward: if face % 2 == 0 { 1.0 } else { -1.0 },
                kind: r.kind,
                per_axis,
                spacing,
                volume: (0..3)
                    .map(|d| grid.spacing[d] / per_axis[d] as f64)
                    .product(),
                transverse,
                phase: vec![0.5 * spacing; columns],
                columns: vec![None; columns],
                sums: vec![ColumnSums::default(); columns],
            });
        }
        Ok(Self {
            faces,
            ..Default::default()
        })
    }

    /// Whether there is any reservoir.
    pub fn is_empty(&self) -> bool {
        self.faces.is_empty()
    }

    /// This step's node shares of the reservoir particles.
    pub fn shares(&self) -> &[NodeShare] {
        &self.shares
    }

    /// This step's internal forces of the reservoir particles on the
    /// nodes, (node storage index, N).
    pub fn forces(&self) -> &[(usize, [f64; 3])] {
        &self.forces
    }

    /// Per face (x−, x+, y−, y+, z−, z+): whether an
    /// [`ReservoirKind::OutflowOnly`] reservoir has held back a boundary
    /// cell whose material moved inwards faster than
    /// [`BLOCKED_SPEED_FRACTION`] of its sound speed.
    pub fn blocked_inflow(&self) -> [bool; 6] {
        self.blocked
    }

    /// Each reservoir's phases ψ, for a checkpoint.
    pub fn phases(&self) -> Vec<Vec<f64>> {
        self.faces.iter().map(|f| f.phase.clone()).collect()
    }

    /// Restores the phases of [`Reservoirs::phases`]; fails, changing
    /// nothing, when they do not fit the reservoirs.
    pub fn set_phases(&mut self, phases: &[Vec<f64>]) -> Result<(), String> {
        if phases.len() != self.faces.len()
            || phases
                .iter()
                .zip(&self.faces)
                .any(|(p, f)| p.len() != f.phase.len())
        {
            return Err(format!(
                "the checkpoint holds {} reservoir faces, the scenario has {}",
                phases.len(),
                self.faces.len()
            ));
        }
        for (f, p) in self.faces.iter_mut().zip(phases) {
            f.phase.clone_from(p);
        }
        Ok(())
    }

    /// The largest signal speed c + |v| of a fixed reservoir state (the
    /// others are those of particles inside), m/s.
    pub fn max_signal_speed(&self, materials: &[MaterialModel]) -> f64 {
        let mut speed: f64 = 0.0;
        for f in &self.faces {
            if let ReservoirKind::Fixed(s) = &f.kind {
                let c = materials[s.material.0 as usize]
                    .wave_speed(s.density, s.specific_internal_energy);
                let v = s.velocity;
                speed = speed.max(c + (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt());
            }
        }
        speed
    }

    /// Step 1 of the module doc, at the start of a step: every column's
    /// reservoir from the particles `ps` (bulk-viscosity states `bulk`) or
    /// its fixed state, and the particles of the layers that enter, in the
    /// reused buffer (hand it back with [`Reservoirs::return_injected`]);
    /// `booked` takes what they bring in, as negative outflow.
    pub fn inject(
        &mut self,
        grid: &UniformGridGeometry,
        ps: &Particles,
        bulk: &[BulkViscosityState],
        materials: &[MaterialModel],
        booked: &mut ConservationTotals,
    ) -> Vec<ParticleInit> {
        let mut out = std::mem::take(&mut self.injected);
        out.clear();
        self.boundary_sums(grid, ps, bulk);
        for f in &mut self.faces {
            for col in 0..f.columns.len() {
                let reservoir = match f.kind {
                    ReservoirKind::Fixed(state) => {
                        // The layers that crossed enter where they are.
                        let mut psi = f.phase[col];
                        while psi < 0.0 {
                            enter(f, grid, col, psi, &state, 1.0, &mut out, booked);
                            psi += f.spacing;
                        }
                        f.phase[col] = psi;
                        Some(ColumnReservoir {
                            state,
                            stretch: 1.0,
                            spacing: f.spacing,
                            first: psi,
                        })
                    }
                    ReservoirKind::ZeroGradient | ReservoirKind::OutflowOnly => {
                        let sums = f.sums[col];
                        sums.state().map(|(mut state, volume)| {
                            let stretch = volume / f.volume;
                            let spacing = f.spacing * stretch;
                            let mut nearest = sums.nearest.map_or(f64::INFINITY, |n| n.0);
                            let v_in = f.inward * state.velocity[f.axis];
                            if f.kind == ReservoirKind::OutflowOnly {
                                if v_in > 0.0 {
                                    let c = materials[state.material.0 as usize]
                                        .wave_speed(state.density, state.specific_internal_energy);
                                    if v_in > BLOCKED_SPEED_FRACTION * c {
                                        self.blocked[f.face] = true;
                                    }
                                    state.velocity[f.axis] = 0.0;
                                }
                            } else if v_in > 0.0 {
                                // Fill the gap the inflow has opened between
                                // the face and the nearest particle.
                                while nearest > spacing {
                                    nearest -= spacing;
                                    enter(
                                        f, grid, col, -nearest, &state, stretch, &mut out, booked,
                                    );
                                }
                            }
                            ColumnReservoir {
                                state,
                                stretch,
                                spacing,
                                first: spacing - nearest,
                            }
                        })
                    }
                };
                f.columns[col] = reservoir;
            }
        }
        out
    }

    /// Hands back the buffer [`Reservoirs::inject`] returned.
    pub fn return_injected(&mut self, buffer: Vec<ParticleInit>) {
        self.injected = buffer;
    }

    /// Step 2 of the module doc: the reservoir particles' node shares and
    /// internal forces on `map`'s lattice ([`Reservoirs::shares`],
    /// [`Reservoirs::forces`]), from the first step on: a fluid's
    /// particles start at their pressure, so a fixed reservoir pushes
    /// with its state's stress as they do.
    pub fn share(&mut self, map: &GridMap) -> Result<(), String> {
        self.shares.clear();
        self.forces.clear();
        let grid = map.grid;
        // Every particle within (g + 3/2) Δx of the face, g the ghost node
        // layers, can reach a node of the lattice: the linear hat reaches
        // Δx, GIMP Δx + l_p ≤ 3Δx/2 and the B-spline 3Δx/2 from its centre.
        let reach = map.shape.required_ghost_nodes() as f64 + 1.5;
        for f in &self.faces {
            let depth = reach * grid.spacing[f.axis];
            for (col, r) in f.columns.iter().enumerate() {
                let Some(r) = r else { continue };
                let s = &r.state;
                let stress = s.stress;
                // The particles' domains as the transfers form them: uGIMP
                // keeps the half-width of V⁰, cpGIMP stretches it with F.
                let f_r = f.deformation(r.stretch);
                let half_width = match map.shape {
                    ShapeFunction::CpGimp => map.deformed_half_width(f.volume, &f_r),
                    shape if shape.is_gimp() => map.half_width(f.volume).map(|l| [l; 3]),
                    _ => Ok([0.0; 3]),
                }
                .map_err(|e| format!("reservoir particle of stretch {}: {e}", r.stretch))?;
                let volume = r.stretch * f.volume;
                let m = s.density * volume;
                let mv = s.velocity.map(|v| m * v);
                let mut d = r.first;
                while d < depth {
                    let mut failed = None;
                    let (shares, forces, stencil) =
                        (&mut self.shares, &mut self.forces, &mut self.stencil);
                    f.for_each_sub(|sub| {
                        let x = f.position(&grid, col, sub, d);
                        if let Err(e) = map.shape.evaluate(&grid, x, half_width, stencil) {
                            failed = Some(format!("reservoir particle at {x:?} m: {e}"));
                            return;
                        }
                        for (node, w, g) in stencil.iter() {
                            let Some(idx) = map.lattice.index(node) else {
                                continue;
                            };
                            shares.push(NodeShare {
                                node: idx,
                                mass: w * m,
                                momentum: mv.map(|p| w * p),
                            });
                            forces.push((idx, internal_force(&stress, g, volume)));
                        }
                    });
                    if let Some(e) = failed {
                        return Err(e);
                    }
                    d += r.spacing;
                }
            }
        }
        Ok(())
    }

    /// The boundary cells' sums of the zero-gradient and outflow-only
    /// reservoirs, over the particles in storage order.
    fn boundary_sums(
        &mut self,
        grid: &UniformGridGeometry,
        ps: &Particles,
        bulk: &[BulkViscosityState],
    ) {
        let from_particles = |f: &FaceReservoir| !matches!(f.kind, ReservoirKind::Fixed(_));
        if !self.faces.iter().any(from_particles) {
            return;
        }
        for f in &mut self.faces {
            f.sums.fill(ColumnSums::default());
        }
        let upper = grid.upper();
        for p in 0..ps.len() {
            let x = ps.position[p];
            let Some(cell) = grid.cell_containing(x) else {
                continue;
            };
            for f in self.faces.iter_mut().filter(|f| from_particles(f)) {
                let Some(col) = f.column(cell, grid.cells) else {
                    continue;
                };
                let (m, v) = (ps.mass[p], ps.volume[p]);
                let sums = &mut f.sums[col];
                sums.count += 1;
                sums.mass += m;
                sums.volume += v;
                for c in 0..3 {
                    sums.momentum[c] += m * ps.velocity[p][c];
                }
                sums.energy += m * ps.specific_internal_energy[p];
                sums.temperature += m * ps.temperature[p];
                let q = bulk.get(p).map_or(0.0, |b| b.q);
                for (k, s) in sums.stress.iter_mut().enumerate() {
                    let qk = if k < 3 { q } else { 0.0 };
                    *s += v * (ps.stress[p][k] + qk);
                }
                let a = f.axis;
                let d = if f.inward > 0.0 {
                    x[a] - grid.origin[a]
                } else {
                    upper[a] - x[a]
                };
                let nearer = match sums.nearest {
                    Some((n, _)) => d < n,
                    None => true,
                };
                if nearer {
                    sums.nearest = Some((d, ps.material[p]));
                }
            }
        }
    }

    /// Step 3 of the module doc, at the end of a step of Δt = `dt`: the
    /// fixed reservoirs move by their normal velocity.
    pub fn advance(&mut self, dt: f64) {
        for f in &mut self.faces {
            if let ReservoirKind::Fixed(s) = &f.kind {
                let u_in = f.inward * s.velocity[f.axis];
                for psi in &mut f.phase {
                    *psi -= u_in * dt;
                    // A reservoir moving out recedes by whole layers.
                    if *psi >= f.spacing {
                        *psi -= f.spacing * (*psi / f.spacing).floor();
                    }
                }
            }
        }
    }
}

/// Appends the particles of the layer of column `col` of `f` at outward
/// distance `d` (negative: inside) with state `s` and stretch `stretch`
/// along the normal (volume `stretch` V⁰, deformation gradient
/// [`FaceReservoir::deformation`]) to `out`, booking what they bring in as
/// negative outflow. [`ParticleInit::volume`] is their current volume;
/// the solver takes V⁰ = V / det F as their initial one.
#[allow(clippy::too_many_arguments)]
fn enter(
    f: &FaceReservoir,
    grid: &UniformGridGeometry,
    col: usize,
    d: f64,
    s: &ReservoirState,
    stretch: f64,
    out: &mut Vec<ParticleInit>,
    booked: &mut ConservationTotals,
) {
    let volume = stretch * f.volume;
    let deformation_gradient = f.deformation(stretch);
    let m = s.density * volume;
    let v2: f64 = s.velocity.iter().map(|v| v * v).sum();
    f.for_each_sub(|sub| {
        out.push(ParticleInit {
            position: f.position(grid, col, sub, d),
            velocity: s.velocity,
            mass: m,
            volume,
            deformation_gradient,
            stress: s.stress,
            temperature: s.temperature,
            specific_internal_energy: s.specific_internal_energy,
            material: s.material,
        });
        booked.mass -= m;
        for c in 0..3 {
            booked.momentum[c] -= m * s.velocity[c];
        }
        booked.energy -= m * (s.specific_internal_energy + 0.5 * v2);
    });
}

/// The internal force −V σ ∇N of a particle of volume `v` and stress
/// `sigma` (Voigt xx, yy, zz, yz, xz, xy) on a node of shape-function
/// gradient `g` (seed 001 eq 19), formed as the P2G of
/// [`crate::transfer`] forms it, N.
fn internal_force(sigma: &[f64; 6], g: [f64; 3], v: f64) -> [f64; 3] {
    let vs = sigma.map(|s| v * s);
    [
        -(vs[0] * g[0] + vs[5] * g[1] + vs[4] * g[2]),
        -(vs[5] * g[0] + vs[1] * g[1] + vs[3] * g[2]),
        -(vs[4] * g[0] + vs[3] * g[1] + vs[2] * g[2]),
    ]
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::particles::IDENTITY as F_I;
    use crate::ShapeFunction;
    use brisance_constitutive::NullMaterial;

    /// 4 cells of 1/4 m along x, 1/4 m thick: with 2 particles per cell
    /// the spacing is s = 1/8 m and V⁰ = 1/128 m³ (dyadic, so the
    /// sums below are exact).
    fn grid() -> UniformGridGeometry {
        UniformGridGeometry {
            origin: [0.0; 3],
            spacing: [0.25; 3],
            cells: [4, 1, 1],
        }
    }

    fn air() -> Vec<MaterialModel> {
        vec![MaterialModel::Null(NullMaterial::air())]
    }

    fn fixed_state() -> ReservoirState {
        ReservoirState {
            material: MaterialId(0),
            density: 2.0,
            velocity: [0.5, 0.0, 0.0],
            specific_internal_energy: 3.0,
            temperature: 4.0,
            stress: [-1.5, -1.5, -1.5, 0.0, 0.0, 0.0],
        }
    }

    fn on_x_low(kind: ReservoirKind) -> Reservoirs {
        let mut r = [None; 6];
        r[0] = Some(Reservoir { kind, ppc: 2 });
        Reservoirs::new(&r, &grid(), 1).unwrap()
    }

    fn particle(x: f64, mass: f64, u: f64, e: f64, t: f64, p: f64) -> ParticleInit {
        ParticleInit {
            position: [x, 0.125, 0.125],
            velocity: [u, 0.0, 0.0],
            mass,
            volume: 1.0 / 128.0,
            deformation_gradient: F_I,
            stress: [-p, -p, -p, 0.0, 0.0, 0.0],
            temperature: t,
            specific_internal_energy: e,
            material: MaterialId(0),
        }
    }

    /// ψ starts at s/2 = 1/16 m; u Δt = 1/16 m per step of 1/8 s: after
    /// one step ψ = 0, after two ψ = −1/16 m and the layer enters 1/16 m
    /// inside, with m = ρ V⁰ = 1/64 kg, booked as −1/64 kg, −1/128 kg·m/s
    /// and −(1/64)(3 + 1/8) J; ψ becomes 1/16 m again.
    #[test]
    fn a_fixed_reservoir_lets_a_layer_in_each_time_it_has_moved_one_spacing() {
        let mut r = on_x_low(ReservoirKind::Fixed(fixed_state()));
        let none = Particles::new(0);
        let mut booked = ConservationTotals::default();
        assert_eq!(r.phases(), vec![vec![0.0625]]);
        r.advance(0.125);
        let new = r.inject(&grid(), &none, &[], &air(), &mut booked);
        assert!(new.is_empty());
        assert_eq!(r.phases(), vec![vec![0.0]]);
        r.return_injected(new);
        r.advance(0.125);
        let new = r.inject(&grid(), &none, &[], &air(), &mut booked);
        assert_eq!(new.len(), 1);
        let p = &new[0];
        assert_eq!(p.position, [0.0625, 0.125, 0.125]);
        assert_eq!((p.mass, p.volume), (1.0 / 64.0, 1.0 / 128.0));
        assert_eq!(p.velocity, [0.5, 0.0, 0.0]);
        assert_eq!(p.stress, fixed_state().stress);
        assert_eq!((p.specific_internal_energy, p.temperature), (3.0, 4.0));
        assert_eq!(r.phases(), vec![vec![0.0625]]);
        assert_eq!(booked.mass, -1.0 / 64.0);
        assert_eq!(booked.momentum, [-1.0 / 128.0, 0.0, 0.0]);
        assert_eq!(booked.energy, -(3.0 + 0.125) / 64.0);
    }

    /// With linear shape functions the layers at 1/16 and 3/16 m beyond
    /// x_low reach node 0 with N = 3/4 and 1/4 (the one at 5/16 m only
    /// nodes −2 and −1, which the lattice has not): node 0 gets
    /// m = (3/4 + 1/4) ρ V⁰ = 1/64 kg, and the force −V σ ∂N/∂x =
    /// V⁰ · 1.5 Pa · 4 /m = 3/64 N from each, p A = 1.5 · 1/16 in all.
    #[test]
    fn reservoir_particles_give_the_face_node_its_missing_mass_and_pressure() {
        let mut r = on_x_low(ReservoirKind::Fixed(fixed_state()));
        let mut booked = ConservationTotals::default();
        let new = r.inject(&grid(), &Particles::new(0), &[], &air(), &mut booked);
        r.return_injected(new);
        let map = GridMap::new(&grid(), ShapeFunction::Linear);
        r.share(&map).unwrap();
        let node0 = map.lattice.index([0, 0, 0]).unwrap();
        let m = 1.0 / 64.0;
        assert_eq!(
            r.shares(),
            &[
                NodeShare {
                    node: node0,
                    mass: 0.75 * m,
                    momentum: [0.75 * m * 0.5, 0.0, 0.0],
                },
                NodeShare {
                    node: node0,
                    mass: 0.25 * m,
                    momentum: [0.25 * m * 0.5, 0.0, 0.0],
                },
            ]
        );
        assert_eq!(
            r.forces(),
            &[
                (node0, [3.0 / 64.0, 0.0, 0.0]),
                (node0, [3.0 / 64.0, 0.0, 0.0])
            ]
        );
    }

    /// Two particles in the boundary cell, at 3/16 and 7/32 m, of 1/64 kg
    /// and 1/128 m³ each, moving in at 1/2 and 1/4 m/s: the reservoir has
    /// ρ = 2, u = 3/8 m/s, e and T their means, σ the mean −1.5 Pa; the
    /// gap of 3/16 m exceeds one spacing (1/8 m), so a layer enters at
    /// 3/16 − 1/8 = 1/16 m with that state; the particle in cell 1 is not
    /// looked at.
    #[test]
    fn a_zero_gradient_reservoir_fills_the_gap_with_the_boundary_state() {
        let mut ps = Particles::new(0);
        for p in [
            particle(0.1875, 1.0 / 64.0, 0.5, 2.0, 3.0, 1.0),
            particle(0.21875, 1.0 / 64.0, 0.25, 4.0, 6.0, 2.0),
            particle(0.3, 1.0, -7.0, 100.0, 100.0, 100.0),
        ] {
            ps.push(&p, &[]).unwrap();
        }
        let mut r = on_x_low(ReservoirKind::ZeroGradient);
        let mut booked = ConservationTotals::default();
        let new = r.inject(&grid(), &ps, &[], &air(), &mut booked);
        assert_eq!(new.len(), 1);
        let p = &new[0];
        assert_eq!(p.position, [0.0625, 0.125, 0.125]);
        assert_eq!((p.mass, p.volume), (1.0 / 64.0, 1.0 / 128.0));
        assert_eq!(p.velocity, [0.375, 0.0, 0.0]);
        assert_eq!((p.specific_internal_energy, p.temperature), (3.0, 4.5));
        assert_eq!(p.stress, [-1.5, -1.5, -1.5, 0.0, 0.0, 0.0]);
        assert_eq!(booked.mass, -1.0 / 64.0);
        assert_eq!(r.blocked_inflow(), [false; 6]);
        // The one-way reservoir holds the same cell back: nothing enters,
        // and the face is reported.
        let mut r = on_x_low(ReservoirKind::OutflowOnly);
        let mut booked = ConservationTotals::default();
        let new = r.inject(&grid(), &ps, &[], &air(), &mut booked);
        assert!(new.is_empty());
        assert_eq!(booked, ConservationTotals::default());
        assert_eq!(
            r.blocked_inflow(),
            [true, false, false, false, false, false]
        );
        // Its particles are at rest along the normal: no momentum reaches
        // the nodes.
        r.share(&GridMap::new(&grid(), ShapeFunction::Linear))
            .unwrap();
        assert!(r.shares().iter().all(|s| s.momentum == [0.0; 3]));
    }

    #[test]
    fn a_reservoir_needs_a_sensible_ppc_and_state() {
        let mut r = [None; 6];
        r[1] = Some(Reservoir {
            kind: ReservoirKind::ZeroGradient,
            ppc: 0,
        });
        let e = Reservoirs::new(&r, &grid(), 1).unwrap_err();
        assert_eq!(e.face, 1);
        let mut bad = fixed_state();
        bad.density = -1.0;
        r[1] = Some(Reservoir {
            kind: ReservoirKind::Fixed(bad),
            ppc: 2,
        });
        assert!(Reservoirs::new(&r, &grid(), 1).is_err());
        bad.density = 1.0;
        bad.material = MaterialId(3);
        r[1] = Some(Reservoir {
            kind: ReservoirKind::Fixed(bad),
            ppc: 2,
        });
        assert!(Reservoirs::new(&r, &grid(), 1).is_err());
        // Faces of an inactive direction get no reservoir.
        let mut r = [None; 6];
        r[2] = Some(Reservoir {
            kind: ReservoirKind::ZeroGradient,
            ppc: 2,
        });
        assert!(Reservoirs::new(&r, &grid(), 1).unwrap().is_empty());
    }
}
