//! Shock-tube cases of V-SOD-ICE and the 1D ANFO-K1 rate stick of
//! E-RATESTICK as functions, shared by the unit tests
//! (reduced resolutions) and `cargo xtask validate` (full resolutions).

use brisance_core::{Eos, Solver};
use brisance_eos::{EosModel, IdealGas, JwlCTerm, Murnaghan};
use brisance_grid::Level;
use brisance_reaction::jwlpp::{detonation_energy, JwlPlusPlus};

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
    while s.time() < t_end * (1.0 - 1e-12) {
        let dt = s.stable_dt()?.min(t_end - s.time());
        s.advance(dt)?;
    }
    Ok(())
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
            rate: JwlPlusPlus::anfo_k1(),
            heat_of_reaction: q,
        },
    ))
}

/// Settings of the 1D ("infinite radius") ANFO-K1 rate stick of seed 000
/// §5.1: explosive on [0, length] moving at −`impact_velocity` onto a
/// zero-velocity wall at x = 0.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RateStick1d {
    /// Cell size, m.
    pub h: f64,
    /// Length of the stick, m.
    pub length: f64,
    /// Impact speed onto the wall, m/s (seed: 90).
    pub impact_velocity: f64,
    /// The two far-field gauge positions, m.
    pub gauges: [f64; 2],
    /// Arrival is the first time the gauge's pressure exceeds this, Pa.
    pub arrival_pressure: f64,
    /// Reactant compressibility κ, 1/Pa (ANFO-K1: 3.9 × 10⁻¹⁰, see
    /// docs/physics/eos/murnaghan.md).
    pub kappa: f64,
    /// Largest simulated time, s.
    pub t_max: f64,
}

impl RateStick1d {
    /// The seed's stick (10 cm) with gauges at 5 and 9 cm.
    pub fn seed(h: f64) -> Self {
        Self {
            h,
            length: 0.1,
            impact_velocity: 90.0,
            gauges: [0.05, 0.09],
            arrival_pressure: 2.0e9,
            kappa: Murnaghan::anfo_k1().kappa,
            t_max: 60e-6,
        }
    }
}

/// What a 1D rate stick measured.
#[derive(Debug, Clone, PartialEq)]
pub struct RateStickResult {
    /// Arrival times at the two gauges (None: the wave never came), s.
    pub arrival: [Option<f64>; 2],
    /// Detonation velocity (x₂ − x₁)/(t₂ − t₁), m/s, when both arrived.
    pub detonation_velocity: Option<f64>,
    /// Largest pressure seen at the second gauge, Pa.
    pub peak_pressure: f64,
    /// Largest equilibration pressure anywhere at the end of the first step
    /// after the impact, Pa (does the impact cross the 200 MPa threshold?).
    pub impact_pressure: f64,
    /// Fraction of the explosive mass burnt at the end.
    pub burnt_fraction: f64,
    /// Steps taken.
    pub steps: u64,
    /// Simulated time at the end, s.
    pub time: f64,
}

/// Runs the 1D rate stick (reactant + products, JWL++) until the wave has
/// passed the second gauge or `t_max`; arrival times from gauge pressures
/// sampled after every step.
pub fn rate_stick_1d(cfg: &RateStick1d) -> Result<RateStickResult, String> {
    let (mut eos, reaction) = anfo_k1_jwlpp()?;
    if let EosModel::Murnaghan(m) = &mut eos[0] {
        m.kappa = cfg.kappa;
    }
    let cells = (cfg.length / cfg.h).round() as usize;
    let level = Level::new(
        [0.0; 3],
        [cfg.length, cfg.h, cfg.h],
        [cells, 1, 1],
        [1, 1, 1],
        GHOST,
    )
    .map_err(|e| e.to_string())?;
    let p0 = 1.0e5;
    let t0 = 298.15;
    let rho_r = eos[0].density(p0, t0).map_err(|e| e.to_string())?;
    let rho_p = eos[1].density(p0, t0).map_err(|e| e.to_string())?;
    let trace = 1e-6;
    let u = -cfg.impact_velocity;
    let mut s = IceSolver::new(
        eos,
        level,
        [
            IceBoundary::FixedVelocity([0.0; 3]),
            IceBoundary::Outflow,
            IceBoundary::Symmetry,
            IceBoundary::Symmetry,
            IceBoundary::Symmetry,
            IceBoundary::Symmetry,
        ],
        ExchangeCoefficients::uniform(2, 1e15, 0.0),
        IceOptions::default(),
        |_| CellState {
            pressure: p0,
            materials: vec![mat(1.0 - trace, rho_r, u), mat(trace, rho_p, u)],
        },
    )
    .map_err(|e| e.to_string())?;
    s.set_reactions(vec![reaction]).map_err(|e| e.to_string())?;
    let mass0 = explosive_mass(&s)?;
    let fields = ["pressure".to_string()];
    let mut arrival = [None; 2];
    let mut peak: f64 = 0.0;
    let mut impact_pressure = f64::NAN;
    let mut out = Vec::new();
    while s.time() < cfg.t_max && arrival[1].is_none() {
        let dt = s.stable_dt().map_err(|e| e.to_string())?;
        s.advance(dt).map_err(|e| e.to_string())?;
        if s.steps() == 1 {
            let p = s.cell_data(&fields).map_err(|e| e.to_string())?;
            impact_pressure = p.fields[0].1.iter().cloned().fold(0.0, f64::max);
        }
        for (k, x) in cfg.gauges.iter().enumerate() {
            s.sample([*x, 0.5 * cfg.h, 0.5 * cfg.h], &fields, &mut out)
                .map_err(|e| e.to_string())?;
            if k == 1 {
                peak = peak.max(out[0]);
            }
            if arrival[k].is_none() && out[0] > cfg.arrival_pressure {
                arrival[k] = Some(s.time());
            }
        }
    }
    let d = match arrival {
        [Some(a), Some(b)] if b > a => Some((cfg.gauges[1] - cfg.gauges[0]) / (b - a)),
        _ => None,
    };
    let burnt = 1.0 - explosive_mass(&s)?.0 / mass0.0;
    Ok(RateStickResult {
        arrival,
        detonation_velocity: d,
        peak_pressure: peak,
        impact_pressure,
        burnt_fraction: burnt,
        steps: s.steps(),
        time: s.time(),
    })
}

/// (reactant mass, product mass) per unit cross-section area, kg/m².
fn explosive_mass(s: &IceSolver<EosModel>) -> Result<(f64, f64), String> {
    let f = ["density_1".to_string(), "density_2".to_string()];
    let d = s.cell_data(&f).map_err(|e| e.to_string())?;
    let h = s.level().geometry.spacing[0];
    let sum = |k: usize| d.fields[k].1.iter().sum::<f64>() * h;
    Ok((sum(0), sum(1)))
}
