//! What a [`PdSolver`](super::PdSolver) is built from: its options, the setup and its
//! errors, and the memory report.

use crate::lattice::{BodySpec, Dimension};
use crate::material::PdMaterial;
use brisance_grid::Shape;
use brisance_reaction::DetonationPoint;
use serde::{Deserialize, Serialize};

use super::CLOSING_STEP_FRACTION;

/// Short-range force options (seed 004 eq 27; the contact distance of a
/// pair is d_ij = min(α r_ij, p_contact), see `contact.rs`). The defaults
/// are those of the EMU code as LAMMPS `peri/pmb` transcribes them.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ContactOptions {
    /// F_SR (default 15).
    pub force_factor: f64,
    /// p_contact as a multiple of the spacing (default 1.35).
    pub distance_factor: f64,
    /// α, the largest contact distance of a pair as a fraction of its
    /// reference separation (default 0.9: pairs are force-free at rest).
    pub reference_fraction: f64,
}

impl Default for ContactOptions {
    fn default() -> Self {
        Self {
            force_factor: 15.0,
            distance_factor: 1.35,
            reference_fraction: 0.9,
        }
    }
}

/// Solver options.
#[derive(Debug, Clone, PartialEq)]
pub struct PdOptions {
    /// Lattice spacing h, m.
    pub spacing: f64,
    /// Horizon as a multiple of the spacing (seed 004: "typically three").
    pub horizon_factor: f64,
    /// Lattice origin, m.
    pub origin: [f64; 3],
    /// Dimension.
    pub dimension: Dimension,
    /// Cross-section of a 1D bar, m².
    pub cross_section: f64,
    /// Safety factor on the stable step of eq 24 (0 < f ≤ 1).
    pub safety_factor: f64,
    /// Energy-method surface correction of proportional bonds.
    pub surface_correction: bool,
    /// Short-range forces (None: off).
    pub contact: Option<ContactOptions>,
    /// Body force density b, N/m³ (eq 9), on every node.
    pub body_force: [f64; 3],
    /// Smallest step before the run is stopped, s.
    pub min_dt: f64,
    /// A perturbed lattice (`crate::LatticeJitter`; None: the regular one).
    pub jitter: Option<crate::LatticeJitter>,
    /// A products node's step is at most this fraction of the shortest
    /// closing time of its family (default [`CLOSING_STEP_FRACTION`];
    /// None: eq 24 alone, as seed 004 prints it). 0 < f ≤ 1.
    pub closing_step_fraction: Option<f64>,
    /// Which nodes a products node's family holds ([`ProductsFamily`];
    /// default the printed model's, its own body only).
    pub products_family: ProductsFamily,
}

/// Which nodes a products (gas) node's family holds.
///
/// Seed 004 bonds nodes of one body only (its Fig. 1), so a products node
/// next to the case has a family cut off by the case: its expansion
/// (eq 17) counts only the products side, and eq 19's pair forces push it
/// towards the wall by the sum of its own one-sided family. A uniform
/// products state against a wall is then not at rest
/// (`docs/physics/pd/validation.md`). With `WithSolids` the solid nodes of
/// other bodies within the horizon join the products node's family, as a
/// wall's particles join a fluid particle's neighbourhood in the wall
/// boundary of smoothed particle hydrodynamics (Adami, Hu & Adams 2012,
/// J. Comput. Phys. 231, 7057–7075): eq 17's expansion measures the
/// products against the wall's current positions, and eq 19's pair force
/// on such a pair carries the products node's own half ½ c_i alone (a
/// solid node has no c), with the opposite force on the solid node, so
/// the pair force is still the gradient of the products' energy
/// Σ W(X_i) V_i and momentum and energy are conserved as before
/// (`docs/physics/pd/gas.md`, "The case in the products' families").
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
pub enum ProductsFamily {
    /// Nodes of the products node's own body only, as seed 004 prints it.
    #[default]
    OwnBody,
    /// Its own body's nodes and, within the horizon, the nodes of solid
    /// (non-gas) materials in other bodies.
    WithSolids,
    /// The families of `WithSolids`, and a mirrored wall: a pair of a
    /// products node i and a solid node carries c_i in full, as if the
    /// solid node were products in i's own state (the mirrored wall
    /// pressure of Adami, Hu & Adams 2012), so that a uniform products
    /// state against a wall thicker than the horizon is force-free. The
    /// half of that force the products' energy does not give (the pair's
    /// gradient is ½ c_i) does work on the wall which node i pays from its
    /// heat, so energy is kept to the integrator's order and momentum to
    /// round-off (`docs/physics/pd/gas.md`, "A mirrored wall").
    MirroredWall,
}

impl ProductsFamily {
    /// Whether solid nodes of other bodies join the products' families.
    pub fn with_solids(self) -> bool {
        matches!(self, Self::WithSolids | Self::MirroredWall)
    }

    /// Whether a products node's pairs with solid nodes carry its
    /// coefficient in full (`MirroredWall`).
    pub fn mirrors_walls(self) -> bool {
        self == Self::MirroredWall
    }
}

impl Default for PdOptions {
    fn default() -> Self {
        Self {
            spacing: 1.0e-3,
            horizon_factor: 3.0,
            origin: [0.0; 3],
            dimension: Dimension::Three,
            cross_section: 0.0,
            safety_factor: 0.8,
            surface_correction: true,
            contact: Some(ContactOptions::default()),
            body_force: [0.0; 3],
            min_dt: 1.0e-15,
            jitter: None,
            closing_step_fraction: Some(CLOSING_STEP_FRACTION),
            products_family: ProductsFamily::OwnBody,
        }
    }
}

/// Prescribed velocity components on the nodes inside a region (a fixed
/// boundary is velocity 0).
#[derive(Debug, Clone, PartialEq)]
pub struct PdBoundary {
    /// Region (reference positions).
    pub region: Shape,
    /// Prescribed components, m/s (None: free).
    pub velocity: [Option<f64>; 3],
}

/// How detonation times are computed.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum BurnMethod {
    /// Huygens construction over the families.
    Huygens,
    /// Straight lines from the points.
    StraightLine,
}

/// Program burn input.
#[derive(Debug, Clone, PartialEq)]
pub struct DetonationSpec {
    /// Detonation points.
    pub points: Vec<DetonationPoint>,
    /// Method.
    pub method: BurnMethod,
}

/// Everything the solver is built from.
#[derive(Debug, Clone, PartialEq)]
pub struct PdSetup {
    /// Options.
    pub options: PdOptions,
    /// Materials, indexed by the bodies.
    pub materials: Vec<PdMaterial>,
    /// Bodies.
    pub bodies: Vec<BodySpec>,
    /// Prescribed velocities.
    pub boundaries: Vec<PdBoundary>,
    /// Program burn (needed when a body is a gas).
    pub detonation: Option<DetonationSpec>,
}

/// Why the solver cannot be built; messages name the field.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum PdSetupError {
    /// A parameter is out of range.
    #[error("peridynamics: `{field}`: {message}")]
    Invalid {
        /// The field.
        field: String,
        /// What is wrong.
        message: String,
    },
    /// The lattice could not be filled.
    #[error("peridynamics: {0}")]
    Lattice(#[from] crate::lattice::LatticeError),
    /// Program burn failed.
    #[error("peridynamics: {0}")]
    Burn(#[from] brisance_reaction::BurnError),
}

pub(super) fn invalid(field: impl Into<String>, message: impl Into<String>) -> PdSetupError {
    PdSetupError::Invalid {
        field: field.into(),
        message: message.into(),
    }
}

/// Heap memory of a [`PdSolver`](super::PdSolver), summed from the capacities of its arrays.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct PdMemory {
    /// Nodes.
    pub nodes: usize,
    /// Directed bonds (each bond once per node).
    pub bonds: usize,
    /// Bytes of the arrays with one entry per node: node data, row starts,
    /// and, with contact on, the contact forces and the contact cell list.
    pub node_bytes: usize,
    /// Bytes of the arrays with one entry per bond: neighbour index, bond
    /// factor and plastic stretch.
    pub bond_bytes: usize,
    /// Everything else: materials, laws, prescribed velocities.
    pub other_bytes: usize,
}

impl PdMemory {
    /// Node-array bytes per node.
    pub fn bytes_per_node(&self) -> f64 {
        self.node_bytes as f64 / self.nodes.max(1) as f64
    }

    /// Bond-array bytes per bond.
    pub fn bytes_per_bond(&self) -> f64 {
        self.bond_bytes as f64 / self.bonds.max(1) as f64
    }

    /// All bytes.
    pub fn total(&self) -> usize {
        self.node_bytes + self.bond_bytes + self.other_bytes
    }
}

/// Heap bytes of a vector's allocation.
pub(super) fn heap<T>(v: &Vec<T>) -> usize {
    v.capacity() * std::mem::size_of::<T>()
}
