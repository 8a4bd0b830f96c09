//! Hot-spot detection (seed 003 §4.3).
//!
//! The temperature fields of a 2D lattice at successive output times are
//! stacked into a 3D data set in (x, y, t). Every voxel whose temperature
//! is strictly above a threshold T* is *hot*; a hot spot is a connected
//! set of hot voxels, voxels being connected when they share a face in
//! (x, y, t): the four in-plane neighbours of the same frame and the same
//! node in the previous and next frame (6-connectivity, the region inside
//! the seed's T* isosurface when the isosurface is drawn through the
//! voxel faces). Diagonal contact does not connect.
//!
//! For each hot spot the detector reports the peak temperature (with its
//! node and time), its footprint area (the area of its projection on the
//! (x, y) plane: the union of the nodes it ever covers, as the seed's
//! fig. 26 shows the isosurfaces "viewed along the time axis"), its
//! largest cross-section area in one frame, its voxel count and the times
//! of its first and last frames. Areas are node counts times the
//! reference area of a node, h² (Lagrangian: the lattice's nodes are
//! material points).
//!
//! The seed chooses T* per impact velocity by hand, as the temperature
//! tangent to the profile through a region without hot spots (fig. 24);
//! here T* is an input. Exterior (ghost) and missing nodes are passed as
//! NaN and are never hot.
//!
//! Frames are processed as they are produced ([`HotSpotDetector::push`]):
//! only the hot voxels are kept, with a union–find over them (union to the
//! lower index, so each hot spot's representative is its first voxel in
//! (t, y, x) order and the hot spots come out in order of first
//! appearance, the same for any frame size or data). Memory is
//! proportional to the number of hot voxels plus two frames of labels.
//!
//! [`run_impact`] drives the impact problem of seed 003 §4.1 (E-HOTSPOT):
//! a random crystal/binder pack of Tables 2–3 hitting a wall, its frames
//! stacked and searched for hot spots (`docs/physics/lattice/hotspots.md`).

use super::geometry::{Dim, NodeKind};
use super::law::LatticeMaterial;
use super::model::{MsdmError, MsdmLattice};

const NONE: u32 = u32::MAX;

/// One hot spot: a face-connected region of voxels above the threshold
/// in (x, y, t).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HotSpot {
    /// Peak temperature over the region, K.
    pub peak_temperature: f64,
    /// Node (ix, iy) of the peak (first in (t, y, x) order on ties).
    pub peak_node: [usize; 2],
    /// Time of the frame of the peak, s.
    pub peak_time: f64,
    /// Time of the first frame the region appears in, s.
    pub first_time: f64,
    /// Time of the last frame the region appears in, s.
    pub last_time: f64,
    /// Number of hot voxels in the region.
    pub voxels: usize,
    /// Area of the projection on the (x, y) plane (nodes ever covered ×
    /// node area), m².
    pub footprint_area: f64,
    /// Largest area of the region within one frame, m².
    pub max_area: f64,
}

/// Streaming detector of hot spots in stacked (x, y, t) frames; see the
/// module documentation.
#[derive(Debug, Clone)]
pub struct HotSpotDetector {
    nx: usize,
    ny: usize,
    node_area: f64,
    threshold: f64,
    times: Vec<f64>,
    // Per hot voxel, in (t, y, x) order.
    parent: Vec<u32>,
    pixel: Vec<u32>,
    frame: Vec<u32>,
    temp: Vec<f64>,
    // Voxel index of each node's hot voxel in the previous / current
    // frame, NONE where not hot.
    prev: Vec<u32>,
    cur: Vec<u32>,
}

fn find(parent: &mut [u32], mut v: u32) -> u32 {
    while parent[v as usize] != v {
        let p = parent[v as usize];
        parent[v as usize] = parent[p as usize];
        v = p;
    }
    v
}

fn union(parent: &mut [u32], a: u32, b: u32) {
    let (ra, rb) = (find(parent, a), find(parent, b));
    if ra < rb {
        parent[rb as usize] = ra;
    } else if rb < ra {
        parent[ra as usize] = rb;
    }
}

impl HotSpotDetector {
    /// A detector for frames of `nx` × `ny` nodes (node `(ix, iy)` at
    /// index `ix + nx · iy`), each node of area `node_area` (m²), hot
    /// above `threshold` (K).
    pub fn new(nx: usize, ny: usize, node_area: f64, threshold: f64) -> Result<Self, MsdmError> {
        if nx == 0 || ny == 0 {
            return Err(MsdmError::Invalid(format!(
                "hot spots: frame size `nx` × `ny` = {nx} × {ny}, expected both > 0"
            )));
        }
        if nx.checked_mul(ny).filter(|&n| n < NONE as usize).is_none() {
            return Err(MsdmError::Invalid(format!(
                "hot spots: frame size `nx` × `ny` = {nx} × {ny} is too large"
            )));
        }
        if !(node_area > 0.0 && node_area.is_finite()) {
            return Err(MsdmError::Invalid(format!(
                "hot spots: field `node_area` = {node_area}, expected a finite value > 0"
            )));
        }
        if !threshold.is_finite() {
            return Err(MsdmError::Invalid(format!(
                "hot spots: field `threshold` = {threshold}, expected a finite value"
            )));
        }
        Ok(Self {
            nx,
            ny,
            node_area,
            threshold,
            times: Vec::new(),
            parent: Vec::new(),
            pixel: Vec::new(),
            frame: Vec::new(),
            temp: Vec::new(),
            prev: vec![NONE; nx * ny],
            cur: vec![NONE; nx * ny],
        })
    }

    /// Threshold temperature T*, K.
    pub fn threshold(&self) -> f64 {
        self.threshold
    }

    /// Number of frames pushed so far.
    pub fn frames(&self) -> usize {
        self.times.len()
    }

    /// Number of hot voxels so far.
    pub fn hot_voxels(&self) -> usize {
        self.parent.len()
    }

    /// Adds the frame at `time` (s, after the previous frame's time) with
    /// node temperatures `temperature` (K, length nx · ny, NaN where there
    /// is no material).
    pub fn push(&mut self, time: f64, temperature: &[f64]) -> Result<(), MsdmError> {
        let (nx, ny) = (self.nx, self.ny);
        if temperature.len() != nx * ny {
            return Err(MsdmError::Invalid(format!(
                "hot spots: frame {} has {} temperatures, expected nx · ny = {}",
                self.times.len(),
                temperature.len(),
                nx * ny
            )));
        }
        if !time.is_finite() || self.times.last().is_some_and(|&t| !(time > t)) {
            return Err(MsdmError::Invalid(format!(
                "hot spots: frame {} has `time` = {time}, expected a finite value after the previous frame's",
                self.times.len()
            )));
        }
        let f = self.times.len();
        if f >= NONE as usize {
            return Err(MsdmError::Invalid("hot spots: too many frames".into()));
        }
        let fresh = self.parent.len() + nx * ny;
        if fresh >= NONE as usize {
            return Err(MsdmError::Invalid("hot spots: too many hot voxels".into()));
        }
        self.times.push(time);
        self.cur.fill(NONE);
        for iy in 0..ny {
            for ix in 0..nx {
                let p = ix + nx * iy;
                let t = temperature[p];
                if !(t > self.threshold) {
                    continue;
                }
                let id = self.parent.len() as u32;
                self.parent.push(id);
                self.pixel.push(p as u32);
                self.frame.push(f as u32);
                self.temp.push(t);
                self.cur[p] = id;
                if ix > 0 && self.cur[p - 1] != NONE {
                    union(&mut self.parent, id, self.cur[p - 1]);
                }
                if iy > 0 && self.cur[p - nx] != NONE {
                    union(&mut self.parent, id, self.cur[p - nx]);
                }
                if self.prev[p] != NONE {
                    union(&mut self.parent, id, self.prev[p]);
                }
            }
        }
        std::mem::swap(&mut self.prev, &mut self.cur);
        Ok(())
    }

    /// The hot spots of the frames pushed so far, in order of first
    /// appearance ((t, y, x) order of their first voxel).
    pub fn hot_spots(&self) -> Vec<HotSpot> {
        let mut parent = self.parent.clone();
        let nv = parent.len();
        // Component of each voxel; representatives are first voxels.
        let mut comp = vec![0u32; nv];
        let mut count = 0u32;
        for v in 0..nv {
            let r = find(&mut parent, v as u32) as usize;
            comp[v] = if r == v {
                count += 1;
                count - 1
            } else {
                comp[r]
            };
        }
        let nc = count as usize;
        let mut out: Vec<HotSpot> = Vec::with_capacity(nc);
        // Per component: frame being counted and its count.
        let mut in_frame = vec![(NONE, 0usize); nc];
        let mut max_in_frame = vec![0usize; nc];
        for v in 0..nv {
            let c = comp[v] as usize;
            let (f, p, t) = (self.frame[v], self.pixel[v] as usize, self.temp[v]);
            let time = self.times[f as usize];
            let node = [p % self.nx, p / self.nx];
            if c == out.len() {
                out.push(HotSpot {
                    peak_temperature: t,
                    peak_node: node,
                    peak_time: time,
                    first_time: time,
                    last_time: time,
                    voxels: 0,
                    footprint_area: 0.0,
                    max_area: 0.0,
                });
            }
            let h = &mut out[c];
            h.voxels += 1;
            h.last_time = time;
            if t > h.peak_temperature {
                h.peak_temperature = t;
                h.peak_node = node;
                h.peak_time = time;
            }
            let fc = &mut in_frame[c];
            if fc.0 != f {
                *fc = (f, 0);
            }
            fc.1 += 1;
            max_in_frame[c] = max_in_frame[c].max(fc.1);
        }
        // Footprint: distinct nodes per component.
        let mut cover: Vec<(u32, u32)> = comp
            .iter()
            .copied()
            .zip(self.pixel.iter().copied())
            .collect();
        cover.sort_unstable();
        cover.dedup();
        let mut footprint = vec![0usize; nc];
        for (c, _) in cover {
            footprint[c as usize] += 1;
        }
        for (c, h) in out.iter_mut().enumerate() {
            h.footprint_area = footprint[c] as f64 * self.node_area;
            h.max_area = max_in_frame[c] as f64 * self.node_area;
        }
        out
    }
}

/// The hot spots of `frames` ((time, temperatures) in increasing time),
/// each of `nx` × `ny` nodes of area `node_area`, above `threshold`.
pub fn detect_hot_spots<'a>(
    frames: impl IntoIterator<Item = (f64, &'a [f64])>,
    nx: usize,
    ny: usize,
    node_area: f64,
    threshold: f64,
) -> Result<Vec<HotSpot>, MsdmError> {
    let mut d = HotSpotDetector::new(nx, ny, node_area, threshold)?;
    for (t, frame) in frames {
        d.push(t, frame)?;
    }
    Ok(d.hot_spots())
}

/// The temperature frame of a 2D lattice for [`HotSpotDetector`]: the
/// solid block without its exterior padding, (nx, ny) = solid nodes per
/// axis, NaN at exterior nodes. `frame` is resized and overwritten.
/// Returns (nx, ny) and the node area h².
pub fn lattice_frame(
    lat: &MsdmLattice,
    frame: &mut Vec<f64>,
) -> Result<([usize; 2], f64), MsdmError> {
    let g = &lat.geom;
    if g.dim != Dim::Two {
        return Err(MsdmError::Invalid(format!(
            "hot spots: the lattice has dimension {:?}, expected Two",
            g.dim
        )));
    }
    let (nx, ny) = (g.n[0] - 2, g.n[1] - 2);
    frame.clear();
    frame.reserve(nx * ny);
    for iy in 0..ny {
        for ix in 0..nx {
            let i = g.index(ix + 1, iy + 1, 0);
            frame.push(match g.kind[i] {
                NodeKind::Solid(_) => lat.temperature[i],
                NodeKind::Exterior => f64::NAN,
            });
        }
    }
    Ok(([nx, ny], g.spacing * g.spacing))
}

/// Energetic crystal of seed 003 Table 2.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Crystal {
    /// HMX: E = 25 325 MPa.
    Hmx,
    /// RDX: E = 20 200 MPa.
    Rdx,
    /// PETN: E = 11 800 MPa.
    Petn,
    /// TKX-50: E = 52 194 MPa.
    Tkx50,
}

/// Binder variant of seed 003 Table 3 (E = 6250 MPa for all).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Binder {
    /// Estane.
    Estane,
    /// Half-density Estane.
    HalfDensity,
    /// Density matched to HMX.
    DensityMatched,
    /// Impedance matched to HMX.
    ImpedanceMatched,
}

impl Crystal {
    /// The lattice material (elastic, no conduction).
    pub fn material(self) -> LatticeMaterial {
        use brisance_eos::MieGruneisenThermal as M;
        let (name, young, eos) = match self {
            Crystal::Hmx => ("HMX", 25_325e6, M::hmx_seed003()),
            Crystal::Rdx => ("RDX", 20_200e6, M::rdx_seed003()),
            Crystal::Petn => ("PETN", 11_800e6, M::petn_seed003()),
            Crystal::Tkx50 => ("TKX-50", 52_194e6, M::tkx50_seed003()),
        };
        LatticeMaterial::elastic(name, young, eos)
    }
}

impl Binder {
    /// The lattice material (elastic, no conduction).
    pub fn material(self) -> LatticeMaterial {
        use brisance_eos::MieGruneisenThermal as M;
        let (name, eos) = match self {
            Binder::Estane => ("Estane", M::estane_seed003()),
            Binder::HalfDensity => ("half-density Estane", M::estane_half_density()),
            Binder::DensityMatched => ("density-matched Estane", M::estane_density_matched()),
            Binder::ImpedanceMatched => ("impedance-matched Estane", M::estane_impedance_matched()),
        };
        LatticeMaterial::elastic(name, 6250e6, eos)
    }
}

/// An impact of a random crystal/binder pack on a rigid wall (seed 003
/// §4.1, E-HOTSPOT); see `docs/physics/lattice/hotspots.md`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ImpactCase {
    /// Crystal material.
    pub crystal: Crystal,
    /// Binder material.
    pub binder: Binder,
    /// Impact velocity, m/s.
    pub velocity: f64,
    /// Nodes per side of the square sample.
    pub nodes: usize,
    /// Lattice spacing h, m.
    pub spacing: f64,
    /// Crystal (disc) diameter, m.
    pub diameter: f64,
    /// Crystal area fraction.
    pub fraction: f64,
    /// Seed of the random pack.
    pub pack_seed: u64,
    /// Simulated time in units of the binder's bar-wave transit time
    /// L/√(E/ρ) through the sample.
    pub transits: f64,
    /// Temperature frames written over the run.
    pub frames: usize,
    /// Threshold factor k: T* = mean + k · std of the heated voxels.
    pub threshold_sigmas: f64,
}

/// What an impact produced.
#[derive(Debug, Clone, PartialEq)]
pub struct ImpactResult {
    /// The hot spots, in order of first appearance.
    pub hot_spots: Vec<HotSpot>,
    /// Whether each hot spot's peak node is a crystal node.
    pub peak_in_crystal: Vec<bool>,
    /// Threshold temperature T*, K.
    pub threshold: f64,
    /// Highest temperature of the run, K.
    pub max_temperature: f64,
    /// Time steps taken.
    pub steps: usize,
    /// Crystal area fraction of the lattice nodes.
    pub crystal_fraction: f64,
}

/// The temperature frames of an impact, before hot-spot detection.
#[derive(Debug, Clone, PartialEq)]
pub struct ImpactFrames {
    /// Nodes per side.
    pub nodes: usize,
    /// Lattice spacing h, m.
    pub spacing: f64,
    /// (time, temperature per node, row-major, exterior NaN) per frame.
    pub frames: Vec<(f64, Vec<f64>)>,
    /// Whether each node is crystal.
    pub inside: Vec<bool>,
    /// Initial temperature T₀, K.
    pub initial_temperature: f64,
    /// Time steps taken.
    pub steps: usize,
    /// Crystal area fraction of the lattice nodes.
    pub crystal_fraction: f64,
}

/// Simulates an [`ImpactCase`]: a random disc pack rasterised on the
/// lattice (crystal material 0, binder 1), diagonal springs, every node
/// moving at −`velocity` along x except the column at x = 0, whose normal
/// velocity u_x is held at zero (a rigid slip wall: u_y is free; seed 003
/// §4.1), the other sides free, velocity Verlet with the energy equation,
/// T₀ = 300 K. Frames are recorded at equal time intervals.
pub fn simulate_impact(case: &ImpactCase) -> Result<ImpactFrames, MsdmError> {
    use super::geometry::Geometry;
    use super::model::{Integrator, MsdmOptions};
    let n = case.nodes;
    if n < 3 || case.frames < 2 {
        return Err(MsdmError::Invalid(format!(
            "impact: `nodes` = {n}, `frames` = {}, expected ≥ 3 and ≥ 2",
            case.frames
        )));
    }
    let side = n as f64 * case.spacing;
    let pack =
        super::pack::random_disc_pack(side, side, case.diameter, case.fraction, case.pack_seed)
            .map_err(MsdmError::Invalid)?;
    let inside = pack.rasterise(n, n, case.spacing);
    let crystal_fraction = inside.iter().filter(|&&c| c).count() as f64 / (n * n) as f64;
    let geom = Geometry::new(Dim::Two, [n, n, 1], case.spacing, true, |ix, iy, _| {
        Some(if inside[ix + n * iy] { 0 } else { 1 })
    });
    let binder = case.binder.material();
    let transit = side / (binder.young / binder.eos.rho0).sqrt();
    let mut lat = MsdmLattice::new(
        geom,
        vec![case.crystal.material(), binder],
        MsdmOptions {
            integrator: Integrator::VelocityVerlet,
            ..MsdmOptions::default()
        },
    )?;
    for iy in 0..n {
        for ix in 0..n {
            let i = lat.geom.index(ix + 1, iy + 1, 0);
            if ix == 0 {
                // Slip wall: only the normal velocity u_x = 0 is held.
                lat.prescribed[i] = true;
                lat.held_axes[i] = 0b001;
            } else {
                lat.u[0][i] = -case.velocity;
            }
        }
    }
    lat.mark_modified();
    let dt = lat.explicit_stable_dt();
    let end = case.transits * transit;
    let steps = (end / dt).ceil() as usize;
    let stride = (steps / case.frames).max(1);
    let mut frames: Vec<(f64, Vec<f64>)> = Vec::new();
    let mut frame = Vec::new();
    for k in 1..=steps {
        lat.step(dt)?;
        if k % stride == 0 {
            lattice_frame(&lat, &mut frame)?;
            frames.push((lat.time, frame.clone()));
        }
    }
    Ok(ImpactFrames {
        nodes: n,
        spacing: case.spacing,
        frames,
        inside,
        initial_temperature: lat.options.initial_temperature,
        steps,
        crystal_fraction,
    })
}

/// The threshold T* = mean + k · std over the voxels heated by more than
/// 0.1 K in all frames of all `runs` together (T₀ + 0.1 K when fewer than
/// two are). Pooling runs gives one threshold per impact velocity shared by
/// several crystals, as seed 003 §4.3 does for HMX and RDX. The seed picks
/// T* by hand (fig. 24); this automatic rule is this project's stand-in.
pub fn heated_threshold(runs: &[&ImpactFrames], k: f64) -> f64 {
    let t0 = runs.first().map_or(300.0, |r| r.initial_temperature);
    let (mut s0, mut s1, mut s2) = (0.0f64, 0.0f64, 0.0f64);
    for r in runs {
        for (_, f) in &r.frames {
            for &t in f {
                if t.is_finite() && t - r.initial_temperature > 0.1 {
                    s0 += 1.0;
                    s1 += t;
                    s2 += t * t;
                }
            }
        }
    }
    if s0 > 1.0 {
        let mean = s1 / s0;
        mean + k * ((s2 / s0 - mean * mean).max(0.0)).sqrt()
    } else {
        t0 + 0.1
    }
}

/// Detects the hot spots of `run` above `threshold` (K) in its stacked
/// frames and classes each peak node as crystal or binder.
pub fn detect_impact(run: &ImpactFrames, threshold: f64) -> Result<ImpactResult, MsdmError> {
    let n = run.nodes;
    let mut tmax = run.initial_temperature;
    for (_, f) in &run.frames {
        for &t in f {
            if t.is_finite() {
                tmax = tmax.max(t);
            }
        }
    }
    let hot_spots = detect_hot_spots(
        run.frames.iter().map(|(t, f)| (*t, f.as_slice())),
        n,
        n,
        run.spacing * run.spacing,
        threshold,
    )?;
    let peak_in_crystal = hot_spots
        .iter()
        .map(|h| run.inside[h.peak_node[0] + n * h.peak_node[1]])
        .collect();
    Ok(ImpactResult {
        hot_spots,
        peak_in_crystal,
        threshold,
        max_temperature: tmax,
        steps: run.steps,
        crystal_fraction: run.crystal_fraction,
    })
}

/// Runs an [`ImpactCase`] ([`simulate_impact`]) and detects its hot spots
/// above its own [`heated_threshold`] with k = `threshold_sigmas`.
pub fn run_impact(case: &ImpactCase) -> Result<ImpactResult, MsdmError> {
    let run = simulate_impact(case)?;
    let threshold = heated_threshold(&[&run], case.threshold_sigmas);
    detect_impact(&run, threshold)
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    /// Frames from ASCII art: '#' = 500 K, a digit d = 400 + 10 d K,
    /// '.' = 300 K, 'x' = NaN.
    fn art(rows: &[&str]) -> (usize, usize, Vec<f64>) {
        let ny = rows.len();
        let nx = rows[0].len();
        let mut v = Vec::new();
        // Row 0 of the art is iy = 0.
        for r in rows {
            assert_eq!(r.len(), nx);
            for ch in r.chars() {
                v.push(match ch {
                    '#' => 500.0,
                    '.' => 300.0,
                    'x' => f64::NAN,
                    d => 400.0 + 10.0 * f64::from(d.to_digit(10).unwrap()),
                });
            }
        }
        (nx, ny, v)
    }

    fn run(frames: &[&[&str]], threshold: f64) -> Vec<HotSpot> {
        let fr: Vec<_> = frames.iter().map(|f| art(f)).collect();
        let (nx, ny) = (fr[0].0, fr[0].1);
        detect_hot_spots(
            fr.iter()
                .enumerate()
                .map(|(k, f)| (k as f64 * 0.5, f.2.as_slice())),
            nx,
            ny,
            2.0,
            threshold,
        )
        .unwrap()
    }

    #[test]
    fn no_hot_voxels_no_hot_spots() {
        assert!(run(&[&["....", "...."], &["....", "x..."]], 350.0).is_empty());
    }

    #[test]
    fn two_blobs_in_one_frame() {
        let h = run(&[&["##....", "#3..9.", "....##"]], 420.0);
        assert_eq!(h.len(), 2);
        // First blob: (0,0),(1,0),(0,1),(1,1)=430 → 4 voxels, peak 500 at (0,0).
        assert_eq!(h[0].voxels, 4);
        assert_eq!(h[0].peak_temperature, 500.0);
        assert_eq!(h[0].peak_node, [0, 0]);
        assert_eq!(h[0].footprint_area, 8.0);
        assert_eq!(h[0].max_area, 8.0);
        // Second: (4,1)=490, (4,2), (5,2) = 500; first in scan order is (4,1).
        assert_eq!(h[1].voxels, 3);
        assert_eq!(h[1].peak_temperature, 500.0);
        assert_eq!(h[1].peak_node, [4, 2]);
        assert_eq!(
            (h[1].first_time, h[1].last_time, h[1].peak_time),
            (0.0, 0.0, 0.0)
        );
    }

    #[test]
    fn threshold_is_strict_and_nan_is_never_hot() {
        // 420 K is not above 420 K; NaN never hot.
        let h = run(&[&["2x.", "..."]], 420.0);
        assert!(h.is_empty());
        let h = run(&[&["2x.", "..."]], 419.0);
        assert_eq!(h.len(), 1);
        assert_eq!(h[0].peak_temperature, 420.0);
    }

    #[test]
    fn diagonal_contact_does_not_connect() {
        let h = run(&[&["#.", ".#"]], 400.0);
        assert_eq!(h.len(), 2);
        assert_eq!(h[0].peak_node, [0, 0]);
        assert_eq!(h[1].peak_node, [1, 1]);
    }

    #[test]
    fn a_moving_blob_is_one_hot_spot_with_union_footprint() {
        // The blob shifts one node right per frame, always overlapping the
        // previous frame's position, and heats up.
        let h = run(
            &[
                &["11...", "....."],
                &[".22..", ".2..."],
                &["..#3.", "....."],
            ],
            400.0,
        );
        assert_eq!(h.len(), 1);
        let h = h[0];
        assert_eq!(h.voxels, 7);
        assert_eq!(h.peak_temperature, 500.0);
        assert_eq!(h.peak_node, [2, 0]);
        assert_eq!(h.peak_time, 1.0);
        assert_eq!((h.first_time, h.last_time), (0.0, 1.0));
        // Nodes covered: (0,0),(1,0),(2,0),(3,0),(1,1) → 5 × 2 m².
        assert_eq!(h.footprint_area, 10.0);
        // Largest frame: 3 nodes in frame 1.
        assert_eq!(h.max_area, 6.0);
    }

    #[test]
    fn blobs_that_merge_later_are_one_hot_spot() {
        // Two separate blobs in frame 0 joined by a bridge in frame 1: one
        // region in (x, y, t), represented by the first blob.
        let h = run(&[&["#.#", "..."], &["###", "..."]], 400.0);
        assert_eq!(h.len(), 1);
        assert_eq!(h[0].voxels, 5);
        assert_eq!(h[0].footprint_area, 6.0);
        assert_eq!(h[0].max_area, 6.0);
        assert_eq!(h[0].peak_node, [0, 0]);
        assert_eq!(h[0].peak_time, 0.0);
    }

    #[test]
    fn a_gap_in_time_separates_hot_spots() {
        let h = run(&[&["#.", ".."], &["..", ".."], &["5.", ".."]], 400.0);
        assert_eq!(h.len(), 2);
        assert_eq!((h[0].first_time, h[0].last_time), (0.0, 0.0));
        assert_eq!((h[1].first_time, h[1].last_time), (1.0, 1.0));
        assert_eq!(h[1].peak_temperature, 450.0);
    }

    #[test]
    fn a_u_shape_within_a_frame_merges_late_in_the_scan() {
        // Arms at x = 0 and x = 2 join only at the last row: the union of
        // two provisional labels inside one frame.
        let h = run(&[&["#.#", "#.#", "###"]], 400.0);
        assert_eq!(h.len(), 1);
        assert_eq!(h[0].voxels, 7);
    }

    #[test]
    fn invalid_input_is_an_error_naming_the_field() {
        let e = HotSpotDetector::new(0, 3, 1.0, 400.0).unwrap_err();
        assert!(e.to_string().contains("nx"), "{e}");
        let e = HotSpotDetector::new(2, 2, -1.0, 400.0).unwrap_err();
        assert!(e.to_string().contains("node_area"), "{e}");
        let e = HotSpotDetector::new(2, 2, 1.0, f64::NAN).unwrap_err();
        assert!(e.to_string().contains("threshold"), "{e}");
        let mut d = HotSpotDetector::new(2, 2, 1.0, 400.0).unwrap();
        let e = d.push(0.0, &[0.0; 3]).unwrap_err();
        assert!(e.to_string().contains("nx · ny"), "{e}");
        d.push(1.0, &[0.0; 4]).unwrap();
        let e = d.push(1.0, &[0.0; 4]).unwrap_err();
        assert!(e.to_string().contains("time"), "{e}");
        assert_eq!(d.frames(), 1);
    }

    #[test]
    fn lattice_frame_strips_the_padding_and_marks_exterior_nodes() {
        use crate::{Geometry, LatticeMaterial, MsdmOptions};
        let geom = Geometry::new(Dim::Two, [3, 2, 1], 1e-3, false, |ix, iy, _| {
            (!(ix == 2 && iy == 1)).then_some(0)
        });
        let mat = LatticeMaterial::elastic(
            "m",
            1e9,
            brisance_eos::MieGruneisenThermal::estane_seed003(),
        );
        let mut lat = MsdmLattice::new(geom, vec![mat], MsdmOptions::default()).unwrap();
        let i = lat.geom.index(2, 1, 0);
        lat.temperature[i] = 700.0;
        let mut f = Vec::new();
        let (n, area) = lattice_frame(&lat, &mut f).unwrap();
        assert_eq!(n, [3, 2]);
        assert_eq!(area, 1e-6);
        assert_eq!(f.len(), 6);
        assert_eq!(f[1], 700.0);
        assert!(f[5].is_nan());
        assert_eq!(f[0], 300.0);
        let h = detect_hot_spots([(0.0, f.as_slice())], 3, 2, area, 400.0).unwrap();
        assert_eq!(h.len(), 1);
        assert_eq!(h[0].peak_node, [1, 0]);
    }

    fn small_impact(velocity: f64, binder: Binder) -> ImpactCase {
        ImpactCase {
            crystal: Crystal::Hmx,
            binder,
            velocity,
            nodes: 24,
            spacing: 5e-6,
            diameter: 6.0 * 5e-6,
            fraction: 0.5,
            pack_seed: 3,
            transits: 0.8,
            frames: 8,
            threshold_sigmas: 2.0,
        }
    }

    fn frames_of(temps: &[f64]) -> ImpactFrames {
        ImpactFrames {
            nodes: 2,
            spacing: 1e-3,
            frames: vec![(0.0, temps.to_vec())],
            inside: vec![true, false, false, false],
            initial_temperature: 300.0,
            steps: 1,
            crystal_fraction: 0.5,
        }
    }

    #[test]
    fn heated_threshold_pools_runs_by_hand() {
        // Heated (> T₀ + 0.1 K): 301 and 303; mean 302, std 1; k = 2 → 304.
        let a = frames_of(&[300.0, 301.0, 303.0, f64::NAN]);
        assert_eq!(heated_threshold(&[&a], 2.0), 304.0);
        // Pooled with 305 and 307: mean 304, variance (9+1+1+9)/4 = 5.
        let b = frames_of(&[307.0, 300.05, 300.0, 305.0]);
        let t = heated_threshold(&[&a, &b], 1.0);
        assert!((t - (304.0 + 5f64.sqrt())).abs() < 1e-12, "{t}");
        // Nothing heated: T₀ + 0.1 K.
        assert_eq!(heated_threshold(&[&frames_of(&[300.0; 4])], 3.0), 300.1);
        // Detection at a given threshold: 307 (node (0, 0), crystal) and 305
        // (node (1, 1), binder) touch only diagonally: two hot spots.
        let r = detect_impact(&b, 304.0).unwrap();
        assert_eq!(r.hot_spots.len(), 2);
        assert_eq!(r.max_temperature, 307.0);
        let mut crystal = r.peak_in_crystal.clone();
        crystal.sort();
        assert_eq!(crystal, vec![false, true]);
    }

    #[test]
    fn impact_heats_more_at_higher_velocity_and_is_deterministic() {
        let a = run_impact(&small_impact(50.0, Binder::Estane)).unwrap();
        let b = run_impact(&small_impact(150.0, Binder::Estane)).unwrap();
        assert!(a.max_temperature > 300.5, "{}", a.max_temperature);
        assert!(b.max_temperature - 300.0 > 2.0 * (a.max_temperature - 300.0));
        assert!(a.crystal_fraction > 0.35 && a.crystal_fraction < 0.65);
        assert!(!a.hot_spots.is_empty());
        assert_eq!(a.peak_in_crystal.len(), a.hot_spots.len());
        for h in &a.hot_spots {
            assert!(h.peak_temperature > a.threshold && h.peak_temperature <= a.max_temperature);
        }
        let again = rayon::ThreadPoolBuilder::new()
            .num_threads(1)
            .build()
            .unwrap()
            .install(|| run_impact(&small_impact(50.0, Binder::Estane)).unwrap());
        assert_eq!(a, again);
        let mut bad = small_impact(50.0, Binder::Estane);
        bad.frames = 1;
        assert!(run_impact(&bad).unwrap_err().to_string().contains("frames"));
    }

    /// E-HOTSPOT (seed 003 §4): 432 × 432 packs of HMX and RDX in Estane at
    /// 50–250 m/s, the Gumbel model of §4.5 with 150 and 250 m/s held out,
    /// the binder variants at 50 m/s and the PETN/TKX-50 hot-spot locations.
    /// Writes CSV under `target/e_hotspot/`. Run with
    /// `cargo test --release -p brisance-lattice --lib -- --ignored e_hotspot --nocapture`.
    #[test]
    #[ignore]
    fn e_hotspot() {
        use crate::stats::{velocity_model, VelocitySample};
        let base = ImpactCase {
            crystal: Crystal::Hmx,
            binder: Binder::Estane,
            velocity: 50.0,
            nodes: 432,
            spacing: 5e-6,
            diameter: 24.0 * 5e-6,
            fraction: 0.6,
            pack_seed: 2015,
            transits: 1.0,
            frames: 40,
            threshold_sigmas: 3.0,
        };
        let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../target/e_hotspot");
        std::fs::create_dir_all(&dir).unwrap();
        let mut spots = String::from("crystal,binder,velocity_m_s,threshold_K,peak_K,peak_x,peak_y,peak_time_s,footprint_m2,max_area_m2,voxels,in_crystal\n");
        // One threshold per velocity shared by HMX and RDX (seed 003 §4.3);
        // the other runs get their own.
        let mut run = |case: ImpactCase,
                       frames: &ImpactFrames,
                       threshold: f64,
                       t: std::time::Instant| {
            let r = detect_impact(frames, threshold).unwrap();
            let inc = r.peak_in_crystal.iter().filter(|&&c| c).count();
            eprintln!(
                "{:?}/{:?} {:5.0} m/s: {} steps, crystal fraction {:.3}, max T {:.2} K, T* {:.2} K, {} hot spots ({} peak in crystal), {:.0} s",
                case.crystal, case.binder, case.velocity, r.steps, r.crystal_fraction, r.max_temperature,
                r.threshold, r.hot_spots.len(), inc, t.elapsed().as_secs_f64()
            );
            for (h, c) in r.hot_spots.iter().zip(&r.peak_in_crystal) {
                spots += &format!(
                    "{:?},{:?},{},{:.4},{:.4},{},{},{:.6e},{:.6e},{:.6e},{},{}\n",
                    case.crystal,
                    case.binder,
                    case.velocity,
                    r.threshold,
                    h.peak_temperature,
                    h.peak_node[0],
                    h.peak_node[1],
                    h.peak_time,
                    h.footprint_area,
                    h.max_area,
                    h.voxels,
                    c
                );
            }
            r
        };
        let mut samples = Vec::new();
        for v in [50.0, 100.0, 150.0, 200.0, 250.0] {
            let cases = [Crystal::Hmx, Crystal::Rdx].map(|crystal| ImpactCase {
                crystal,
                velocity: v,
                ..base
            });
            let t = std::time::Instant::now();
            let frames: Vec<ImpactFrames> =
                cases.iter().map(|c| simulate_impact(c).unwrap()).collect();
            let pooled =
                heated_threshold(&frames.iter().collect::<Vec<_>>(), base.threshold_sigmas);
            let mut peaks = Vec::new();
            for (case, f) in cases.into_iter().zip(&frames) {
                let r = run(case, f, pooled, t);
                peaks.extend(r.hot_spots.iter().map(|h| h.peak_temperature));
            }
            samples.push(VelocitySample { velocity: v, peaks });
        }
        for binder in [
            Binder::HalfDensity,
            Binder::DensityMatched,
            Binder::ImpedanceMatched,
        ] {
            let t = std::time::Instant::now();
            let case = ImpactCase { binder, ..base };
            let f = simulate_impact(&case).unwrap();
            run(case, &f, heated_threshold(&[&f], case.threshold_sigmas), t);
        }
        for crystal in [Crystal::Petn, Crystal::Tkx50] {
            let t = std::time::Instant::now();
            let case = ImpactCase {
                crystal,
                velocity: 100.0,
                ..base
            };
            let f = simulate_impact(&case).unwrap();
            run(case, &f, heated_threshold(&[&f], case.threshold_sigmas), t);
        }
        std::fs::write(dir.join("hot_spots.csv"), &spots).unwrap();
        match velocity_model(&samples, &[150.0, 250.0], 10_000, 2015) {
            Ok(m) => {
                let mut csv = Vec::new();
                m.write_csv(&mut csv).unwrap();
                let mut reg = Vec::new();
                m.write_regression_csv(&mut reg).unwrap();
                std::fs::write(dir.join("gumbel.csv"), &csv).unwrap();
                std::fs::write(dir.join("regression.csv"), &reg).unwrap();
                eprintln!(
                    "{}{}",
                    String::from_utf8(csv).unwrap(),
                    String::from_utf8(reg).unwrap()
                );
            }
            Err(e) => eprintln!("velocity model: {e}"),
        }
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(64))]

        /// Every hot voxel lies in exactly one hot spot, peaks are the
        /// largest values, and reversing time (or transposing x and y)
        /// gives the same hot spots up to order.
        #[test]
        fn voxels_are_partitioned_and_symmetries_hold(
            cells in proptest::collection::vec(0u8..4, 4 * 4 * 3),
        ) {
            let (nx, ny, nt) = (4, 4, 3);
            let temp = |c: u8| [300.0, f64::NAN, 450.0, 520.0][c as usize];
            let frames: Vec<Vec<f64>> = (0..nt)
                .map(|t| (0..nx * ny).map(|p| temp(cells[t * nx * ny + p])).collect())
                .collect();
            let hot = frames.iter().flatten().filter(|&&t| t > 400.0).count();
            let key = |h: &[HotSpot]| {
                let mut k: Vec<_> = h
                    .iter()
                    .map(|h| (h.voxels, h.peak_temperature.to_bits(), h.footprint_area.to_bits(), h.max_area.to_bits()))
                    .collect();
                k.sort_unstable();
                k
            };
            let fwd = detect_hot_spots(
                frames.iter().enumerate().map(|(k, f)| (k as f64, f.as_slice())),
                nx, ny, 1.0, 400.0,
            ).unwrap();
            prop_assert_eq!(fwd.iter().map(|h| h.voxels).sum::<usize>(), hot);
            for h in &fwd {
                prop_assert!(h.peak_temperature > 400.0);
                prop_assert!(h.max_area <= h.footprint_area);
                prop_assert!(h.footprint_area <= h.voxels as f64);
            }
            let rev = detect_hot_spots(
                frames.iter().rev().enumerate().map(|(k, f)| (k as f64, f.as_slice())),
                nx, ny, 1.0, 400.0,
            ).unwrap();
            prop_assert_eq!(key(&fwd), key(&rev));
            let transposed: Vec<Vec<f64>> = frames
                .iter()
                .map(|f| (0..nx * ny).map(|p| f[(p / nx) + nx * (p % nx)]).collect())
                .collect();
            let tr = detect_hot_spots(
                transposed.iter().enumerate().map(|(k, f)| (k as f64, f.as_slice())),
                nx, ny, 1.0, 400.0,
            ).unwrap();
            prop_assert_eq!(key(&fwd), key(&tr));
        }
    }
}
