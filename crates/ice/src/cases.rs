//! Shock-tube cases of V-SOD-ICE and the 1D ANFO-K1 rate stick of
//! E-RATESTICK as functions, shared by the unit tests
//! (reduced resolutions) and `cargo xtask validate` (full resolutions).

use brisance_core::{Eos, Geometry, Solver};
use brisance_eos::{EosModel, IdealGas, JwlCTerm, Murnaghan};
use brisance_grid::Level;
use brisance_reaction::jwlpp::{detonation_energy, JwlPlusPlus};

pub use crate::column::Initiation;
use crate::solver::GHOST;
use crate::{
    Advection, CellState, ExchangeCoefficients, IceBoundary, IceOptions, IceReaction, IceSolver,
    MaterialState,
};

fn mat(theta: f64, density: f64, u: f64) -> MaterialState {
    MaterialState {
        volume_fraction: theta,
        density,
        velocity: [u, 0.0, 0.0],
    }
}

/// Advances `s` to `t_end` at its stable step (the last step shortened to land on it).
pub fn run_to<S: Solver>(s: &mut S, t_end: f64) -> Result<(), brisance_core::SolverError> {
    brisance_core::solver::step_to(s, t_end, |_, _| Ok(()))
}

/// Sod tube of one material on `cells` cells to t = `t_end`; returns the solver.
pub fn sod_one(cells: usize, scheme: Advection, t_end: f64) -> IceSolver<IdealGas> {
    let level = Level::new([0.0; 3], [1.0, 0.1, 0.1], [cells, 1, 1], [1, 1, 1], GHOST).unwrap();
    let mut s = IceSolver::new(
        vec![IdealGas::new(1.4, 1.0, 1.0)],
        level,
        std::array::from_fn(|_| IceBoundary::Outflow),
        ExchangeCoefficients::uniform(1, 0.0, 0.0),
        IceOptions {
            advection: scheme,
            ..Default::default()
        },
        |x| {
            if x[0] < 0.5 {
                CellState {
                    pressure: 1.0,
                    materials: vec![mat(1.0, 1.0, 0.0)],
                }
            } else {
                CellState {
                    pressure: 0.1,
                    materials: vec![mat(1.0, 0.125, 0.0)],
                }
            }
        },
    )
    .unwrap();
    run_to(&mut s, t_end).unwrap();
    s
}

/// Two-material Sod tube (γ 1.4 left, 1.67 right), each material present
/// everywhere, a trace 1e-6 where it is absent.
pub fn sod_two(cells: usize, scheme: Advection, t_end: f64) -> IceSolver<IdealGas> {
    let level = Level::new([0.0; 3], [1.0, 0.1, 0.1], [cells, 1, 1], [1, 1, 1], GHOST).unwrap();
    let eps = 1e-6;
    let mut s = IceSolver::new(
        vec![IdealGas::new(1.4, 1.0, 1.0), IdealGas::new(1.67, 1.0, 1.0)],
        level,
        std::array::from_fn(|_| IceBoundary::Outflow),
        ExchangeCoefficients::uniform(2, 1e15, 0.0),
        IceOptions {
            advection: scheme,
            ..Default::default()
        },
        |x| {
            if x[0] < 0.5 {
                CellState {
                    pressure: 1.0,
                    materials: vec![mat(1.0 - eps, 1.0, 0.0), mat(eps, 0.125, 0.0)],
                }
            } else {
                CellState {
                    pressure: 0.1,
                    materials: vec![mat(eps, 1.0, 0.0), mat(1.0 - eps, 0.125, 0.0)],
                }
            }
        },
    )
    .unwrap();
    run_to(&mut s, t_end).unwrap();
    s
}

/// Sharpness of the two-material contact and the pressure around it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ContactMeasure {
    /// Distance, in cells, between where θ_1 crosses 0.9 and 0.1 (linear
    /// interpolation between cell centres).
    pub width_cells: f64,
    /// Cells with 0.01 < θ_1 < 0.99.
    pub mixed_cells: usize,
    /// Index of the first cell with θ_1 < 0.5.
    pub contact_cell: usize,
    /// Largest |p − p_ref|/p_ref within 5 cells of the contact, p_ref the
    /// mean of the pressures 8 cells to either side.
    pub pressure_excursion: f64,
}

/// Measures the contact of a two-material tube along x (material 1 on the left).
pub fn contact_width<S: Solver>(s: &S) -> Result<ContactMeasure, String> {
    let d = s
        .cell_data(&["volume_fraction_1".into(), "pressure".into()])
        .map_err(|e| e.to_string())?;
    let th = d.field("volume_fraction_1").ok_or("no volume fraction")?;
    let p = d.field("pressure").ok_or("no pressure")?;
    let crossing = |level: f64| -> Option<f64> {
        (1..th.len())
            .find(|&i| th[i - 1] >= level && th[i] < level)
            .map(|i| (i - 1) as f64 + (th[i - 1] - level) / (th[i - 1] - th[i]))
    };
    let (a, b) = (
        crossing(0.9).ok_or("θ never falls below 0.9")?,
        crossing(0.1).ok_or("θ never falls below 0.1")?,
    );
    let c = th.iter().position(|&t| t < 0.5).ok_or("no contact")?;
    if c < 8 || c + 8 >= th.len() {
        return Err(format!("contact at cell {c} too close to the end"));
    }
    let reference = 0.5 * (p[c - 8] + p[c + 8]);
    let excursion = p[c - 5..c + 5]
        .iter()
        .map(|x| (x - reference).abs())
        .fold(0.0, f64::max)
        / reference;
    Ok(ContactMeasure {
        width_cells: b - a,
        mixed_cells: th.iter().filter(|&&t| t > 0.01 && t < 0.99).count(),
        contact_cell: c,
        pressure_excursion: excursion,
    })
}

/// The ANFO-K1 JWL++ materials of seed 000 §5.1 (reactant, products) and
/// the reaction between them (material 1 → material 2).
pub fn anfo_k1_jwlpp() -> Result<(Vec<EosModel>, IceReaction), String> {
    let (reactant, products) = (Murnaghan::anfo_k1(), JwlCTerm::anfo_k1());
    let q = detonation_energy(&reactant, &products).map_err(|e| e.to_string())?;
    Ok((
        vec![EosModel::Murnaghan(reactant), EosModel::JwlCTerm(products)],
        IceReaction {
            reactant: 0,
            product: 1,
            rate: JwlPlusPlus::anfo_k1().into(),
            heat_of_reaction: q,
        },
    ))
}

/// Settings of an ANFO-K1 rate stick of seed 000 §5.1: explosive along x
/// on [0, length], started by `initiation` against a zero-velocity wall at
/// x = 0 (the seed: moving at 90 m/s onto it). Without a radius the column
/// is 1D (the "infinite radius" case); with one, a quarter of a cylinder of that radius in air (symmetry planes
/// y = 0 and z = 0, outflow on the other faces), `air` of air beyond it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RateStick {
    /// Cell size, m.
    pub h: f64,
    /// Length of the stick, m.
    pub length: f64,
    /// Radius, m (None: 1D).
    pub radius: Option<f64>,
    /// Air between the stick's surface and the domain's outer faces, m.
    pub air: f64,
    /// How the stick is started: the seed's impact onto the wall
    /// (`Impact(90.0)`), or a booster of products over the stick's whole
    /// section against the wall, the explosive at rest.
    pub initiation: Initiation,
    /// ν* of eq 19's pressure term ([`IceOptions::face_pressure_courant`];
    /// 0: as printed).
    pub face_pressure_courant: f64,
    /// The two far-field gauge positions on the axis, m.
    pub gauges: [f64; 2],
    /// Arrival is the first time the gauge's pressure exceeds this, Pa.
    pub arrival_pressure: f64,
    /// Reactant compressibility κ, 1/Pa (ANFO-K1: 3.9 × 10⁻¹⁰, see
    /// docs/physics/eos/murnaghan.md).
    pub kappa: f64,
    /// Largest simulated time, s.
    pub t_max: f64,
    /// With a radius: the whole stick as rings on an (r, z) grid (the
    /// stick along the axis y, r along x) instead of the 3D quarter.
    pub axisymmetric: bool,
}

impl RateStick {
    /// The seed's 1D stick (10 cm) with gauges at 6 and 9 cm.
    pub fn seed(h: f64) -> Self {
        Self {
            h,
            length: 0.1,
            radius: None,
            air: 0.0,
            initiation: Initiation::Impact(90.0),
            face_pressure_courant: 0.0,
            gauges: [0.06, 0.09],
            arrival_pressure: 1.0e9,
            kappa: Murnaghan::anfo_k1().kappa,
            t_max: 60e-6,
            axisymmetric: false,
        }
    }

    /// A 1D column long enough for a steady detonation: 30 cm, gauges at
    /// 20 and 29 cm.
    pub fn long(h: f64) -> Self {
        Self {
            length: 0.3,
            gauges: [0.2, 0.29],
            t_max: 120e-6,
            ..Self::seed(h)
        }
    }

    /// The seed's quarter-symmetry stick of radius `radius` (10 cm long),
    /// in 6 mm of air, gauges at 6 and 9 cm.
    pub fn quarter(h: f64, radius: f64) -> Self {
        Self {
            radius: Some(radius),
            air: 6e-3,
            ..Self::seed(h)
        }
    }

    /// The same stick as [`RateStick::quarter`] on an axisymmetric (r, z)
    /// grid: r ∈ [0, R + 6 mm] along x, the stick along y.
    pub fn rz(h: f64, radius: f64) -> Self {
        Self {
            axisymmetric: true,
            ..Self::quarter(h, radius)
        }
    }

    /// The same stick started by a 20 GPa, 6 mm booster of products over
    /// its whole section, the explosive at rest, with eq 19's pressure term
    /// over a Courant-0.8 step (ν* = 0.8): the damped ICE, whose planar
    /// wave runs at D_CJ at every h (docs/physics/reaction/jwlpp.md, "Weak
    /// detonations at coarse h"), and which a 90 m/s impact no longer
    /// initiates.
    pub fn damped(self) -> Self {
        Self {
            initiation: Initiation::Booster {
                pressure: 2e10,
                length: 6e-3,
            },
            face_pressure_courant: 0.8,
            ..self
        }
    }

    /// Cells of the stick's grid.
    pub fn cells(&self) -> [usize; 3] {
        let n = (self.length / self.h).round() as usize;
        match self.radius {
            None => [n, 1, 1],
            Some(r) => {
                let nw = ((r + self.air) / self.h).round() as usize;
                if self.axisymmetric {
                    [nw, n, 1]
                } else {
                    [n, nw, nw]
                }
            }
        }
    }
}

/// What a rate stick measured.
#[derive(Debug, Clone, PartialEq)]
pub struct RateStickResult {
    /// Arrival times at the two gauges (None: the wave never came), s.
    pub arrival: [Option<f64>; 2],
    /// Detonation velocity relative to the unreacted explosive, m/s, when
    /// both gauges saw the wave: [`detonation_velocity`] of the arrivals
    /// and of `velocity_ahead` (−90 m/s after the seed's impact: the
    /// explosive runs into the wave; about 0 behind a booster).
    pub detonation_velocity: Option<f64>,
    /// The front's speed in the grid's frame, (x₂ − x₁)/(t₂ − t₁), m/s.
    pub lab_velocity: Option<f64>,
    /// The explosive's axial velocity ahead of the wave, m/s: mean over
    /// the two gauges of the velocity five cells ahead of the gauge (on
    /// the axis, within the stick) when the wave arrives there.
    pub velocity_ahead: Option<f64>,
    /// Largest pressure seen at the second gauge, Pa.
    pub peak_pressure: f64,
    /// Largest pressure in the first 20 cells of the axis during the first
    /// 1 µs (the impact), Pa.
    pub impact_pressure: f64,
    /// Fraction of the explosive mass burnt at the end.
    pub burnt_fraction: f64,
    /// Steps taken.
    pub steps: u64,
    /// Cells of the grid.
    pub cells: usize,
    /// Simulated time at the end, s.
    pub time: f64,
}

/// Detonation velocity relative to the unreacted explosive, m/s, from the
/// arrival times `t` (s) of the front at two gauges at `x` (m) along the
/// direction it runs, and the explosive's velocity `u_ahead` (m/s, same
/// axis) ahead of it: (x₂ − x₁)/(t₂ − t₁) − u_ahead. None unless
/// t₂ > t₁. The detonation velocity of an explosive is its front's speed
/// into the unreacted material; the grid-frame speed alone is short by
/// the 90 m/s the E-RATESTICK explosive moves towards the wall, 1.5 % of
/// D_CJ (docs/physics/reaction/jwlpp.md, "Convergence of the planar speed").
pub fn detonation_velocity(x: [f64; 2], t: [f64; 2], u_ahead: f64) -> Option<f64> {
    (t[1] > t[0]).then(|| (x[1] - x[0]) / (t[1] - t[0]) - u_ahead)
}

/// Runs a rate stick until the wave has passed the second gauge (and 2 µs
/// more) or `t_max`; arrival times from the gauge pressures sampled after
/// every step, interpolated linearly between steps.
pub fn rate_stick(cfg: &RateStick) -> Result<RateStickResult, String> {
    let (mut eos, reaction) = anfo_k1_jwlpp()?;
    if let EosModel::Murnaghan(m) = &mut eos[0] {
        m.kappa = cfg.kappa;
    }
    let nx = (cfg.length / cfg.h).round() as usize;
    let cells = cfg.cells();
    let rz = cfg.axisymmetric && cfg.radius.is_some();
    // The stick's axis: x, or y on an (r, z) grid.
    let ax = usize::from(rz);
    let (upper, n_mat) = match cfg.radius {
        None => ([cfg.length, cfg.h, cfg.h], 2),
        Some(_) if rz => ([cells[0] as f64 * cfg.h, cfg.length, cfg.h], 3),
        Some(_) => {
            let w = cells[1] as f64 * cfg.h;
            ([cfg.length, w, w], 3)
        }
    };
    if n_mat == 3 {
        eos.push(EosModel::IdealGas(IdealGas::air()));
    }
    let level = Level::new([0.0; 3], upper, cells, [1, 1, 1], GHOST).map_err(|e| e.to_string())?;
    let p0 = 1.0e5;
    let t0 = 298.15;
    let rho: Vec<f64> = eos
        .iter()
        .map(|e| e.density(p0, t0))
        .collect::<Result<_, _>>()
        .map_err(|e| e.to_string())?;
    let trace = 1e-6;
    // The booster's traces (reactant, air) at its pressure and 298.15 K:
    // a trace at the ambient density would be shocked to its pressure in
    // the first steps and heated without bound.
    let (u, booster) = match cfg.initiation {
        Initiation::Impact(v) => (-v, None),
        Initiation::Booster { pressure, length } => {
            let rho_b: Vec<f64> = eos
                .iter()
                .map(|e| e.density(pressure, t0))
                .collect::<Result<_, _>>()
                .map_err(|e| e.to_string())?;
            (0.0, Some((pressure, length, rho_b)))
        }
    };
    let rho_reactant0 = match &eos[0] {
        EosModel::Murnaghan(m) => m.rho0,
        _ => rho[0],
    };
    let side = if n_mat == 3 {
        IceBoundary::Outflow
    } else {
        IceBoundary::Symmetry
    };
    let radius = cfg.radius.unwrap_or(f64::INFINITY);
    let boundaries = if rz {
        [
            // The axis, and the air's outer face.
            IceBoundary::Symmetry,
            IceBoundary::Outflow,
            IceBoundary::FixedVelocity([0.0; 3]),
            IceBoundary::ZeroGradient,
            IceBoundary::Symmetry,
            IceBoundary::Symmetry,
        ]
    } else {
        [
            IceBoundary::FixedVelocity([0.0; 3]),
            // The stick continues beyond its far end and moves in through
            // it (boundary.rs).
            IceBoundary::ZeroGradient,
            IceBoundary::Symmetry,
            side.clone(),
            IceBoundary::Symmetry,
            side,
        ]
    };
    let options = IceOptions {
        geometry: if rz {
            Geometry::Axisymmetric
        } else {
            Geometry::Cartesian
        },
        face_pressure_courant: cfg.face_pressure_courant,
        ..Default::default()
    };
    let mut s = IceSolver::new(
        eos,
        level,
        boundaries,
        ExchangeCoefficients::uniform(n_mat, 1e15, 0.0),
        options,
        |x| {
            let r2 = if rz {
                x[0] * x[0]
            } else {
                x[1] * x[1] + x[2] * x[2]
            };
            let inside = n_mat == 2 || r2 < radius * radius;
            if let Some((p, _, rho_b)) = booster.as_ref().filter(|b| inside && x[ax] < b.1) {
                // Products at the booster's pressure and the reactant's ρ₀.
                return CellState {
                    pressure: *p,
                    materials: (0..n_mat)
                        .map(|k| match k {
                            1 => mat(1.0 - (n_mat - 1) as f64 * trace, rho_reactant0, 0.0),
                            _ => mat(trace, rho_b[k], 0.0),
                        })
                        .collect(),
                };
            }
            let main = if inside { 0 } else { 2 };
            let v = if inside { u } else { 0.0 };
            CellState {
                pressure: p0,
                materials: (0..n_mat)
                    .map(|k| {
                        let th = if k == main {
                            1.0 - (n_mat - 1) as f64 * trace
                        } else {
                            trace
                        };
                        let mut m = mat(th, rho[k], 0.0);
                        m.velocity[ax] = v;
                        m
                    })
                    .collect(),
            }
        },
    )
    .map_err(|e| e.to_string())?;
    s.set_reactions(vec![reaction]).map_err(|e| e.to_string())?;
    let mass0 = explosive_mass(&s)?;
    let along = if rz { "velocity_y" } else { "velocity_x" };
    let fields = ["pressure".to_string(), along.to_string()];
    let mut arrival: [Option<f64>; 2] = [None; 2];
    let mut ahead: [Option<f64>; 2] = [None; 2];
    let mut ahead_sample = Vec::new();
    let mut peak: f64 = 0.0;
    let mut impact_pressure: f64 = 0.0;
    let mut out = Vec::new();
    let mut last = [(0.0, p0); 2];
    let axis = |x: f64| {
        if rz {
            [0.5 * cfg.h, x, 0.5 * cfg.h]
        } else {
            [x, 0.5 * cfg.h, 0.5 * cfg.h]
        }
    };
    // Run on for 2 µs after the second arrival to see the peak pressure.
    while s.time() < arrival[1].map_or(cfg.t_max, |t| (t + 2e-6).min(cfg.t_max)) {
        let dt = s.stable_dt().map_err(|e| e.to_string())?;
        s.advance(dt).map_err(|e| e.to_string())?;
        if s.time() < 1.0e-6 {
            for i in 0..nx.min(20) {
                s.sample(axis((i as f64 + 0.5) * cfg.h), &fields, &mut out)
                    .map_err(|e| e.to_string())?;
                impact_pressure = impact_pressure.max(out[0]);
            }
        }
        for (k, x) in cfg.gauges.iter().enumerate() {
            s.sample(axis(*x), &fields, &mut out)
                .map_err(|e| e.to_string())?;
            if k == 1 {
                peak = peak.max(out[0]);
            }
            let (t_prev, p_prev) = last[k];
            if arrival[k].is_none() && out[0] > cfg.arrival_pressure {
                // Linear interpolation of the crossing between two samples.
                let w = (cfg.arrival_pressure - p_prev) / (out[0] - p_prev);
                arrival[k] = Some(t_prev + w * (s.time() - t_prev));
                // What the wave runs into: the explosive five cells ahead
                // of the gauge (beyond the shock's numerical width).
                let xa = (*x + 5.0 * cfg.h).min(cfg.length - 0.5 * cfg.h);
                s.sample(axis(xa), &fields, &mut ahead_sample)
                    .map_err(|e| e.to_string())?;
                ahead[k] = Some(ahead_sample[1]);
            }
            last[k] = (s.time(), out[0]);
        }
    }
    let lab = match arrival {
        [Some(a), Some(b)] if b > a => Some((cfg.gauges[1] - cfg.gauges[0]) / (b - a)),
        _ => None,
    };
    let velocity_ahead = match ahead {
        [Some(a), Some(b)] => Some(0.5 * (a + b)),
        _ => None,
    };
    let d = match (arrival, velocity_ahead) {
        ([Some(a), Some(b)], Some(v)) => detonation_velocity(cfg.gauges, [a, b], v),
        _ => None,
    };
    let burnt = 1.0 - explosive_mass(&s)?.0 / mass0.0;
    Ok(RateStickResult {
        arrival,
        detonation_velocity: d,
        lab_velocity: lab,
        velocity_ahead,
        peak_pressure: peak,
        impact_pressure,
        burnt_fraction: burnt,
        steps: s.steps(),
        cells: cells.iter().product(),
        time: s.time(),
    })
}

/// (reactant mass, product mass), kg, over the grid's cells.
fn explosive_mass(s: &IceSolver<EosModel>) -> Result<(f64, f64), String> {
    let f = ["density_1".to_string(), "density_2".to_string()];
    let d = s.cell_data(&f).map_err(|e| e.to_string())?;
    let g = s.level().geometry;
    let sum = |k: usize| {
        if s.options().geometry.is_axisymmetric() {
            // Ring volumes, column by column.
            d.fields[k]
                .1
                .iter()
                .enumerate()
                .map(|(n, rho)| {
                    let r_lo = g.origin[0] + (n % g.cells[0]) as f64 * g.spacing[0];
                    rho * Geometry::Axisymmetric.cell_volume(
                        r_lo,
                        g.spacing[0],
                        g.spacing[1],
                        g.spacing[2],
                    )
                })
                .sum::<f64>()
        } else {
            d.fields[k].1.iter().sum::<f64>() * g.spacing.iter().product::<f64>()
        }
    };
    Ok((sum(0), sum(1)))
}

#[cfg(test)]
mod tests {
    use super::{detonation_velocity, rate_stick, JwlCTerm, RateStick};

    /// The 1D part of E-RATESTICK without the report (release, about a
    /// minute): `cargo test --release -p brisance-ice one_d_rate_sticks --
    /// --ignored --nocapture`.
    #[test]
    #[ignore]
    fn one_d_rate_sticks() {
        let d_cj = brisance_reaction::jwlpp::cj_state(&JwlCTerm::anfo_k1())
            .unwrap()
            .detonation_velocity;
        for (name, make) in [
            (
                "10 cm, gauges 6 and 9 cm",
                RateStick::seed as fn(f64) -> RateStick,
            ),
            ("30 cm, gauges 20 and 29 cm", RateStick::long),
        ] {
            for h in [1e-3, 0.5e-3, 0.25e-3] {
                let r = rate_stick(&make(h)).unwrap();
                let d = r.detonation_velocity.unwrap();
                println!(
                    "{name} h {:.2} mm: D {d:.1} m/s ({:+.2} % of {d_cj:.1}), grid frame {:.1} m/s, ahead {:.2} m/s",
                    h * 1e3,
                    100.0 * (d / d_cj - 1.0),
                    r.lab_velocity.unwrap(),
                    r.velocity_ahead.unwrap()
                );
                assert!((r.velocity_ahead.unwrap() + 90.0).abs() < 1.0);
            }
        }
    }

    /// The r–z sticks at one cell size (release): `cargo test --release -p
    /// brisance-ice rz_rate_sticks -- --ignored --nocapture`, the cell size
    /// in mm from BRISANCE_RZ_H (default 1); BRISANCE_RZ_DAMPED=1 runs
    /// [`RateStick::damped`], BRISANCE_RZ_R a list of radii in mm.
    #[test]
    #[ignore]
    fn rz_rate_sticks() {
        let h = std::env::var("BRISANCE_RZ_H")
            .ok()
            .and_then(|v| v.parse::<f64>().ok())
            .unwrap_or(1.0)
            * 1e-3;
        let damped = std::env::var("BRISANCE_RZ_DAMPED").is_ok_and(|v| v == "1");
        let radii: Vec<f64> = std::env::var("BRISANCE_RZ_R")
            .ok()
            .map(|v| v.split(',').filter_map(|x| x.parse::<f64>().ok()).collect())
            .unwrap_or_else(|| vec![4.0, 6.0, 8.0, 12.5, 20.0])
            .into_iter()
            .map(|r| r * 1e-3)
            .collect();
        for radius in radii {
            let t = std::time::Instant::now();
            let cfg = if damped {
                RateStick::rz(h, radius).damped()
            } else {
                RateStick::rz(h, radius)
            };
            let r = match rate_stick(&cfg) {
                Ok(r) => r,
                Err(e) => {
                    println!("r-z R {:.1} mm h {:.3} mm: {e}", radius * 1e3, h * 1e3);
                    continue;
                }
            };
            println!(
                "r-z R {:.1} mm h {:.3} mm: D {:?} m/s, peak {:.2} GPa, burnt {:.3}, {} cells, {} steps, {:.1} s",
                radius * 1e3,
                h * 1e3,
                r.detonation_velocity,
                r.peak_pressure * 1e-9,
                r.burnt_fraction,
                r.cells,
                r.steps,
                t.elapsed().as_secs_f64()
            );
        }
    }

    #[test]
    fn the_detonation_velocity_is_taken_in_the_explosives_frame() {
        // Gauges 9 cm apart crossed 15.3 µs apart: 5882.35 m/s on the grid;
        // the explosive runs into the wave at −90 m/s, so 5972.35 m/s into it.
        let d = detonation_velocity([0.2, 0.29], [40.0e-6, 55.3e-6], -90.0).unwrap();
        assert!((d - (0.09 / 15.3e-6 + 90.0)).abs() < 1e-9, "{d}");
        assert!((d - 5_972.352_941).abs() < 1e-5, "{d}");
        // An explosive at rest: the grid speed.
        let d0 = detonation_velocity([0.03, 0.14], [0.0, 20e-6], 0.0).unwrap();
        assert!((d0 - 5500.0).abs() < 1e-9);
        // No speed without an ordered pair of arrivals.
        assert!(detonation_velocity([0.0, 0.1], [2e-6, 2e-6], 0.0).is_none());
        assert!(detonation_velocity([0.0, 0.1], [3e-6, 2e-6], 0.0).is_none());
    }
}
