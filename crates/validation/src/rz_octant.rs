//! V-RZ: a solver on an axisymmetric (r, z) grid against the same problem
//! on the 3D Cartesian octant at the same cell size, and the round-off
//! conservation of a closed r–z box; measured the same way by the
//! integration tests (`tests/rz_octant.rs`) and by `cargo xtask validate`.
//!
//! # The problem
//!
//! A sphere of radius 0.2 centred at the origin (pressure 20, density 4,
//! in a gas at pressure 1 and density 1; ideal gas γ = 1.4, c_v = 1,
//! nondimensional), its edge smoothed over 1.5 cells (a tanh profile) so
//! that both grids sample the same function, run to t = 0.25 (shock at
//! about 0.73) on
//!
//! - the (r, z) quarter plane [0, 1]², the axis r = 0 and the plane z = 0
//!   symmetry faces, the two far faces open;
//! - the 3D octant [0, 1]³, the planes x = 0, y = 0 and z = 0 symmetry
//!   faces, the three far faces open;
//!
//! at the same h = 1/n. The r–z grid's z is the octant's z.
//!
//! # What is compared
//!
//! - Gauges at distance 0.5 from the centre: on the axis, on the plane
//!   z = 0 and on the 45° ray, sampled after every step: the peak pressure
//!   and the arrival (the first time the pressure exceeds ambient by 10 %
//!   of the peak's excess, interpolated between steps).
//! - The pressure along the same three rays at t = 0.25 (cell centres at
//!   the same distances on both grids): the peak and the shock's position
//!   (the outermost point where the pressure crosses half the peak's
//!   overpressure, interpolated).
//!
//! Each comparison is the relative difference, r–z against octant, of the
//! peak overpressure (p − 1) and of the arrival time (rays: the shock's
//! position). The gauges and rays off the axis sit half a cell from the
//! octant's symmetry plane y = 0 (the first cell centres), where the
//! r–z grid has them at the same (r, z).
//!
//! [`compare`] runs any pair of [`Solver`]s built on these grids;
//! [`fdm_pair`] and [`ice_pair`] build the FDM's and the ICE solver's.

use brisance_core::{ConservationTotals, Geometry, Solver};
use brisance_eos::IdealGas;
use brisance_fdm::{ghost_layers, FdmBoundary, FdmOptions, FdmSolver, PrimitiveState};
use brisance_grid::Level;
use brisance_ice::{
    CellState, ExchangeCoefficients, IceBoundary, IceOptions, IceSolver, MaterialState, GHOST,
};

/// Radius of the sphere.
pub const SPHERE_RADIUS: f64 = 0.2;
/// Pressure and density inside the sphere (ambient 1 and 1).
pub const SPHERE_PRESSURE: f64 = 20.0;
pub const SPHERE_DENSITY: f64 = 4.0;
/// Width of the sphere's smoothed edge, cells.
pub const EDGE_CELLS: f64 = 1.5;
/// Ratio of specific heats and c_v of the gas (nondimensional).
pub const GAMMA: f64 = 1.4;
pub const CV: f64 = 1.0;
/// End time of the comparison.
pub const END: f64 = 0.25;
/// Distance of the gauges from the centre.
pub const GAUGE_DISTANCE: f64 = 0.5;

/// The gas of the problem.
pub fn gas() -> IdealGas {
    IdealGas::new(GAMMA, CV, 1.0)
}

/// Fraction of the sphere's state at distance `d` from its centre on a
/// grid of cell size `h`: 1 inside, 0 outside, a tanh over 1.5 cells
/// across the edge.
pub fn sphere_fraction(d: f64, h: f64) -> f64 {
    0.5 * (1.0 - ((d - SPHERE_RADIUS) / (EDGE_CELLS * h)).tanh())
}

/// Pressure and density at distance `d` from the centre.
pub fn sphere_state(d: f64, h: f64) -> (f64, f64) {
    let f = sphere_fraction(d, h);
    (
        1.0 + (SPHERE_PRESSURE - 1.0) * f,
        1.0 + (SPHERE_DENSITY - 1.0) * f,
    )
}

/// A gauge's pressure history: the peak (as sampled after each step), its
/// time, and the arrival (first crossing of ambient + 10 % of the peak's
/// excess, interpolated between steps).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GaugeHistory {
    pub peak: f64,
    pub peak_time: f64,
    pub arrival: f64,
}

/// The pressure along a ray at the end: its peak and the shock's position
/// (outermost crossing of ambient + half the peak's excess).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RayProfile {
    pub peak: f64,
    pub shock: f64,
}

/// Runs `s` to `end`, sampling the pressure at `points` after every step.
pub fn gauge_histories(
    s: &mut dyn Solver,
    points: &[[f64; 3]],
    end: f64,
) -> Result<Vec<GaugeHistory>, String> {
    let mut hist: Vec<Vec<(f64, f64)>> = vec![Vec::new(); points.len()];
    let mut v = Vec::new();
    let pressure = ["pressure".to_string()];
    brisance_core::solver::step_to(s, end, |s, _| {
        for (h, &x) in hist.iter_mut().zip(points) {
            s.sample(x, &pressure, &mut v)?;
            h.push((s.time(), v[0]));
        }
        Ok(())
    })
    .map_err(|e| e.to_string())?;
    hist.iter()
        .zip(points)
        .map(|(h, x)| {
            let &(peak_time, peak) = h
                .iter()
                .max_by(|a, b| a.1.total_cmp(&b.1))
                .ok_or("no step taken")?;
            let level = 1.0 + 0.1 * (peak - 1.0);
            let k = h
                .iter()
                .position(|&(_, p)| p > level)
                .filter(|&k| k > 0)
                .ok_or_else(|| format!("no arrival at the gauge {x:?}"))?;
            // Interpolated crossing between samples k − 1 and k.
            let (t0, p0) = h[k - 1];
            let (t1, p1) = h[k];
            Ok(GaugeHistory {
                peak,
                peak_time,
                arrival: t0 + (t1 - t0) * (level - p0) / (p1 - p0),
            })
        })
        .collect()
}

/// The pressure of `s` at `n` points `point(q)`, q = (i + ½)/n along a ray
/// of unit length: its peak and the shock's position.
pub fn ray_profile(
    s: &dyn Solver,
    n: usize,
    point: &dyn Fn(f64) -> [f64; 3],
) -> Result<RayProfile, String> {
    let h = 1.0 / n as f64;
    let mut v = Vec::new();
    let pressure = ["pressure".to_string()];
    let prof = (0..n)
        .map(|i| {
            let q = (i as f64 + 0.5) * h;
            s.sample(point(q), &pressure, &mut v)
                .map_err(|e| e.to_string())?;
            Ok((q, v[0]))
        })
        .collect::<Result<Vec<(f64, f64)>, String>>()?;
    let peak = prof.iter().map(|x| x.1).fold(0.0, f64::max);
    let half = 1.0 + 0.5 * (peak - 1.0);
    let k = prof
        .iter()
        .rposition(|x| x.1 > half)
        .filter(|&k| k + 1 < prof.len())
        .ok_or("no shock inside the ray")?;
    let ((q0, p0), (q1, p1)) = (prof[k], prof[k + 1]);
    Ok(RayProfile {
        peak,
        shock: q0 + (q1 - q0) * (p0 - half) / (p0 - p1),
    })
}

/// One comparison, r–z against octant.
#[derive(Debug, Clone, PartialEq)]
pub struct Difference {
    /// `axis gauge`, `plane gauge`, `45° gauge`, `axis ray`, `plane ray`,
    /// `45° ray`, or a gauge near the axis (`r = 1.5h gauge`, ...).
    pub name: &'static str,
    /// Peak pressure, r–z and octant.
    pub peak: [f64; 2],
    /// Arrival time (gauges) or shock position (rays), r–z and octant.
    pub arrival: [f64; 2],
}

impl Difference {
    /// Relative difference of the peak overpressure, r–z against octant.
    pub fn overpressure(&self) -> f64 {
        (self.peak[0] - 1.0) / (self.peak[1] - 1.0) - 1.0
    }

    /// Relative difference of the arrival (shock position), r–z against
    /// octant.
    pub fn arrival(&self) -> f64 {
        self.arrival[0] / self.arrival[1] - 1.0
    }

    /// Both differences within `tol`.
    pub fn within(&self, tol: f64) -> bool {
        self.overpressure().abs() <= tol && self.arrival().abs() <= tol
    }
}

/// What [`compare`] measures.
#[derive(Debug, Clone, PartialEq)]
pub struct Comparison {
    /// Cells per unit length (h = 1/n).
    pub n: usize,
    /// Steps taken by the r–z and the octant run.
    pub steps: [usize; 2],
    /// The charge's energy (the total less the ambient gas's) on the r–z
    /// half space (×2) and on the octant (×8): what both grids sampled.
    pub energy: [f64; 2],
    /// The axis, plane and 45° gauges, then the three rays.
    pub differences: Vec<Difference>,
    /// Gauges 1, 2 and 5 cells off the axis at the axis gauge's height.
    pub near_axis: Vec<Difference>,
    /// Wall time of the r–z and the octant run, s.
    pub wall: [f64; 2],
}

impl Comparison {
    /// The named difference.
    pub fn get(&self, name: &str) -> Option<&Difference> {
        self.differences.iter().find(|d| d.name == name)
    }

    /// The worst |difference| of the peak overpressures and of the
    /// arrivals over [`Comparison::differences`].
    pub fn worst(&self) -> [f64; 2] {
        self.differences.iter().fold([0.0f64; 2], |w, d| {
            [
                w[0].max(d.overpressure().abs()),
                w[1].max(d.arrival().abs()),
            ]
        })
    }
}

/// Runs `rz` (on the (r, z) quarter plane) and `octant` (on the 3D octant),
/// both built at h = 1/`n` with the sphere of this module at the origin,
/// to `end`, and compares them.
pub fn compare(
    rz: &mut dyn Solver,
    octant: &mut dyn Solver,
    n: usize,
    end: f64,
) -> Result<Comparison, String> {
    let h = 1.0 / n as f64;
    // The charge's energy: the total less the ambient gas's in the
    // domain (π on the quarter plane's rings, 1 on the octant).
    let ambient = 1.0 / (GAMMA - 1.0);
    let energy = [
        2.0 * (rz.conservation_totals().energy - ambient * std::f64::consts::PI),
        8.0 * (octant.conservation_totals().energy - ambient),
    ];
    let c = 0.5 * h;
    let d = GAUGE_DISTANCE;
    let s45 = d * std::f64::consts::FRAC_1_SQRT_2;
    // (r, z) points and their 3D counterparts (z of r–z is the 3D z).
    let mut rz_points = vec![[c, d, 0.0], [d, c, 0.0], [s45, s45, 0.0]];
    let mut xyz_points = vec![[c, c, d], [d, c, c], [s45, c, s45]];
    for k in [1.0, 2.0, 5.0] {
        rz_points.push([c + k * h, d, 0.0]);
        xyz_points.push([c + k * h, c, d]);
    }
    let t0 = std::time::Instant::now();
    let ga = gauge_histories(rz, &rz_points, end)?;
    let wall_rz = t0.elapsed().as_secs_f64();
    let t0 = std::time::Instant::now();
    let gb = gauge_histories(octant, &xyz_points, end)?;
    let wall_oct = t0.elapsed().as_secs_f64();
    let mut rays = Vec::new();
    let diag = std::f64::consts::FRAC_1_SQRT_2;
    let rays_rz: [&dyn Fn(f64) -> [f64; 3]; 3] = [&|q| [c, q, 0.0], &|q| [q, c, 0.0], &|q| {
        [q * diag, q * diag, 0.0]
    }];
    let rays_3d: [&dyn Fn(f64) -> [f64; 3]; 3] =
        [&|q| [c, c, q], &|q| [q, c, c], &|q| [q * diag, c, q * diag]];
    for (k, name) in ["axis ray", "plane ray", "45° ray"].into_iter().enumerate() {
        let a = ray_profile(rz, n, rays_rz[k])?;
        let b = ray_profile(octant, n, rays_3d[k])?;
        rays.push(Difference {
            name,
            peak: [a.peak, b.peak],
            arrival: [a.shock, b.shock],
        });
    }
    let names = [
        "axis gauge",
        "plane gauge",
        "45° gauge",
        "r = 1.5h gauge",
        "r = 2.5h gauge",
        "r = 5.5h gauge",
    ];
    let mut gauges: Vec<Difference> = names
        .iter()
        .zip(ga.iter().zip(&gb))
        .map(|(&name, (a, b))| Difference {
            name,
            peak: [a.peak, b.peak],
            arrival: [a.arrival, b.arrival],
        })
        .collect();
    let near_axis = gauges.split_off(3);
    gauges.extend(rays);
    Ok(Comparison {
        n,
        steps: [0, 0],
        energy,
        differences: gauges,
        near_axis,
        wall: [wall_rz, wall_oct],
    })
}

/// The FDM's pair at h = 1/`n`: the (r, z) quarter plane (axis and z = 0
/// reflective, the default options with `Geometry::Axisymmetric`) and the
/// 3D octant (three reflective planes), the face limiter on (the default),
/// far faces outflow.
pub fn fdm_pair(n: usize) -> Result<(FdmSolver<IdealGas>, FdmSolver<IdealGas>), String> {
    let h = 1.0 / n as f64;
    let state = |d: f64| {
        let (pressure, density) = sphere_state(d, h);
        PrimitiveState {
            density,
            velocity: [0.0; 3],
            pressure,
        }
    };
    let rz = Level::new(
        [0.0; 3],
        [1.0, 1.0, h],
        [n, n, 1],
        [2, 2, 1],
        ghost_layers(Geometry::Axisymmetric),
    )
    .map_err(|e| e.to_string())?;
    let mut bcs = [FdmBoundary::Outflow; 6];
    bcs[0] = FdmBoundary::Reflective;
    bcs[2] = FdmBoundary::Reflective;
    let options = FdmOptions {
        geometry: Geometry::Axisymmetric,
        ..Default::default()
    };
    let a = FdmSolver::new(gas(), rz, bcs, options, |x| {
        state((x[0] * x[0] + x[1] * x[1]).sqrt())
    })
    .map_err(|e| e.to_string())?;
    let cube = Level::new(
        [0.0; 3],
        [1.0; 3],
        [n; 3],
        [2, 2, 2],
        ghost_layers(Geometry::Cartesian),
    )
    .map_err(|e| e.to_string())?;
    let mut bcs = [FdmBoundary::Outflow; 6];
    for f in [0, 2, 4] {
        bcs[f] = FdmBoundary::Reflective;
    }
    let b = FdmSolver::new(gas(), cube, bcs, FdmOptions::default(), |x| {
        state((x[0] * x[0] + x[1] * x[1] + x[2] * x[2]).sqrt())
    })
    .map_err(|e| e.to_string())?;
    Ok((a, b))
}

/// One ICE material at pressure `pressure`, density `density`, at rest.
fn ice_state(pressure: f64, density: f64) -> CellState {
    CellState {
        pressure,
        materials: vec![MaterialState {
            volume_fraction: 1.0,
            density,
            velocity: [0.0; 3],
        }],
    }
}

/// The ICE solver's pair at h = 1/`n`: one ideal gas, the default options
/// (explicit pressure, CFL 0.4), the (r, z) quarter plane with
/// `Geometry::Axisymmetric` (axis and z = 0 symmetry faces) and the 3D
/// octant (three symmetry planes), far faces outflow.
pub fn ice_pair(n: usize) -> Result<(IceSolver<IdealGas>, IceSolver<IdealGas>), String> {
    let h = 1.0 / n as f64;
    let state = |d: f64| {
        let (p, rho) = sphere_state(d, h);
        ice_state(p, rho)
    };
    let rz = Level::new([0.0; 3], [1.0, 1.0, h], [n, n, 1], [2, 2, 1], GHOST)
        .map_err(|e| e.to_string())?;
    let mut bcs: [IceBoundary; 6] = std::array::from_fn(|_| IceBoundary::Outflow);
    bcs[0] = IceBoundary::Symmetry;
    bcs[2] = IceBoundary::Symmetry;
    // The one cell's thickness (no flux crosses it).
    bcs[4] = IceBoundary::Symmetry;
    bcs[5] = IceBoundary::Symmetry;
    let a = IceSolver::new(
        vec![gas()],
        rz,
        bcs,
        ExchangeCoefficients::uniform(1, 0.0, 0.0),
        IceOptions {
            geometry: Geometry::Axisymmetric,
            ..Default::default()
        },
        |x| state((x[0] * x[0] + x[1] * x[1]).sqrt()),
    )
    .map_err(|e| e.to_string())?;
    let cube =
        Level::new([0.0; 3], [1.0; 3], [n; 3], [2, 2, 2], GHOST).map_err(|e| e.to_string())?;
    let mut bcs: [IceBoundary; 6] = std::array::from_fn(|_| IceBoundary::Outflow);
    for f in [0, 2, 4] {
        bcs[f] = IceBoundary::Symmetry;
    }
    let b = IceSolver::new(
        vec![gas()],
        cube,
        bcs,
        ExchangeCoefficients::uniform(1, 0.0, 0.0),
        IceOptions::default(),
        |x| state((x[0] * x[0] + x[1] * x[1] + x[2] * x[2]).sqrt()),
    )
    .map_err(|e| e.to_string())?;
    Ok((a, b))
}

/// [`compare`] on the FDM's pair at h = 1/`n`, to [`END`].
pub fn fdm_rz_against_octant(n: usize) -> Result<Comparison, String> {
    let (mut a, mut b) = fdm_pair(n)?;
    let mut c = compare(&mut a, &mut b, n, END)?;
    c.steps = [a.steps() as usize, b.steps() as usize];
    Ok(c)
}

/// [`compare`] on the ICE solver's pair at h = 1/`n`, to [`END`].
pub fn ice_rz_against_octant(n: usize) -> Result<Comparison, String> {
    let (mut a, mut b) = ice_pair(n)?;
    let mut c = compare(&mut a, &mut b, n, END)?;
    c.steps = [a.steps() as usize, b.steps() as usize];
    Ok(c)
}

/// Relative drift of a closed box's totals: mass, axial momentum (to the
/// mass times unit speed) and energy.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Drift {
    pub steps: usize,
    pub mass: f64,
    pub axial_momentum: f64,
    pub energy: f64,
    /// The largest overpressure seen in the cell on the axis next to the
    /// far axial wall (z = 1.1): that the blast reached the walls.
    pub wall_overpressure: f64,
}

impl Drift {
    /// Mass, axial momentum and energy drift.
    pub fn all(&self) -> [f64; 3] {
        [self.mass, self.axial_momentum, self.energy]
    }

    fn between(t0: ConservationTotals, t1: ConservationTotals) -> [f64; 3] {
        [
            ((t1.mass - t0.mass) / t0.mass).abs(),
            ((t1.momentum[1] - t0.momentum[1]) / t0.mass).abs(),
            ((t1.energy - t0.energy) / t0.energy).abs(),
        ]
    }
}

/// The closed box of the conservation check: the (r, z) grid
/// [0, 1] × [−0.4, 1.1] on 24 × 30 cells, all faces walls (the axis
/// r = 0 too); a sphere of radius 0.3 centred at (0, 0.3) at pressure 40,
/// density 4, moving along the axis at 0.3, in the gas at 1, 1 flowing
/// along the axis at 0.1 r.
pub const BOX_CELLS: [usize; 2] = [24, 30];
/// Steps of the closed-box check.
pub const BOX_STEPS: usize = 300;

fn box_level(ghost: usize) -> Result<Level, String> {
    Level::new(
        [0.0, -0.4, 0.0],
        [1.0, 1.1, 0.1],
        [BOX_CELLS[0], BOX_CELLS[1], 1],
        [2, 2, 1],
        ghost,
    )
    .map_err(|e| e.to_string())
}

/// Pressure, density and axial velocity of the closed box at (r, z).
fn box_state(x: [f64; 3]) -> (f64, f64, f64) {
    if x[0] * x[0] + (x[1] - 0.3).powi(2) < 0.09 {
        (40.0, 4.0, 0.3)
    } else {
        (1.0, 1.0, 0.1 * x[0])
    }
}

/// Steps `s` `steps` times at its stable step; the drift of its
/// conservation totals (interior plus what the faces booked).
pub fn closed_box_drift(s: &mut dyn Solver, steps: usize) -> Result<Drift, String> {
    let t0 = s.conservation_totals();
    let wall = [
        0.5 / BOX_CELLS[0] as f64,
        1.1 - 0.75 / BOX_CELLS[1] as f64,
        0.05,
    ];
    let pressure = ["pressure".to_string()];
    let mut v = Vec::new();
    let mut wall_overpressure = 0.0f64;
    for _ in 0..steps {
        let dt = s.stable_dt().map_err(|e| e.to_string())?;
        s.advance(dt).map_err(|e| e.to_string())?;
        s.sample(wall, &pressure, &mut v)
            .map_err(|e| e.to_string())?;
        wall_overpressure = wall_overpressure.max(v[0] - 1.0);
    }
    let [mass, axial_momentum, energy] = Drift::between(t0, s.conservation_totals());
    Ok(Drift {
        steps,
        mass,
        axial_momentum,
        energy,
        wall_overpressure,
    })
}

/// The closed r–z box on the FDM (walls `Reflective`, the default options
/// with `Geometry::Axisymmetric`: the face limiter on).
pub fn fdm_closed_box(steps: usize) -> Result<Drift, String> {
    let level = box_level(ghost_layers(Geometry::Axisymmetric))?;
    let options = FdmOptions {
        geometry: Geometry::Axisymmetric,
        ..Default::default()
    };
    let mut s = FdmSolver::new(gas(), level, [FdmBoundary::Reflective; 6], options, |x| {
        let (pressure, density, uz) = box_state(x);
        PrimitiveState {
            density,
            velocity: [0.0, uz, 0.0],
            pressure,
        }
    })
    .map_err(|e| e.to_string())?;
    closed_box_drift(&mut s, steps)
}

/// The closed r–z box on the ICE solver (one ideal gas, every face a
/// symmetry face — a slip wall —, the default options with
/// `Geometry::Axisymmetric`: explicit pressure).
pub fn ice_closed_box(steps: usize) -> Result<Drift, String> {
    let level = box_level(GHOST)?;
    let mut s = IceSolver::new(
        vec![gas()],
        level,
        std::array::from_fn(|_| IceBoundary::Symmetry),
        ExchangeCoefficients::uniform(1, 0.0, 0.0),
        IceOptions {
            geometry: Geometry::Axisymmetric,
            ..Default::default()
        },
        |x| {
            let (pressure, density, uz) = box_state(x);
            CellState {
                pressure,
                materials: vec![MaterialState {
                    volume_fraction: 1.0,
                    density,
                    velocity: [0.0, uz, 0.0],
                }],
            }
        },
    )
    .map_err(|e| e.to_string())?;
    closed_box_drift(&mut s, steps)
}
