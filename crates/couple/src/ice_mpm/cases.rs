//! Coupling cases of the ICE–MPM step, built in code: air (γ = 1.4) and
//! steel on one grid — a gas-filled box at rest, a block floating in a
//! uniform stream, a piston driving a shock into air. The tests and
//! `cargo xtask validate --only piston` run them.

use super::*;
use brisance_constitutive::{Hypoelastic, MaterialModel, ObjectiveRate, PressureModel};
use brisance_core::Eos;
use brisance_eos::{IdealGas, Murnaghan, SolidEos, SolidThreshold};
use brisance_grid::Level;
use brisance_ice::{
    CellState, ExchangeCoefficients, IceBoundary, IceOptions, MaterialState, GHOST,
};
use brisance_mpm::{
    fill_shape, FillSpec, GridBoundary, MaterialId, MpmOptions, Shape, ShapeFunction, UpdateScheme,
};

/// Steel as the particles see it (K = 160 GPa, G = 80 GPa, hypoelastic)
/// and as the fluid frame sees it (Murnaghan with the same K at ρ₀, n = 4,
/// under the low-pressure threshold).
pub const STEEL_RHO: f64 = 7850.0;
pub const STEEL_K: f64 = 160e9;
pub const P0: f64 = 101_325.0;
pub const T0: f64 = 300.0;

pub fn steel_eos() -> EosModel {
    EosModel::SolidThreshold(SolidThreshold::with_threshold(
        SolidEos::Murnaghan(Murnaghan {
            n: 4.0,
            kappa: 1.0 / STEEL_K,
            rho0: STEEL_RHO,
            cv: 460.0,
            t_ref: T0,
        }),
        P0,
    ))
}

pub fn air() -> EosModel {
    EosModel::IdealGas(IdealGas::new(1.4, 717.5, 1.225))
}

/// Air density at (P0, T0).
pub fn air_density() -> f64 {
    P0 / (0.4 * 717.5 * T0)
}

pub struct Setup {
    pub lower: [f64; 3],
    pub upper: [f64; 3],
    pub cells: [usize; 3],
    /// The solid block(s).
    pub solids: Vec<([f64; 3], [f64; 3])>,
    pub solid_velocity: [f64; 3],
    pub gas_velocity: [f64; 3],
    pub ice_faces: [IceBoundary; 6],
    pub mpm_faces: [GridBoundary; 6],
}

/// The case of the criterion bench `ice_mpm_step` (benches/ice_mpm.rs)
/// and of the step-cost check of `cargo xtask validate --only piston`: a
/// 12 mm steel cube (1 mm cells, 2³ particles per cell) at 50 m/s through
/// still air in a box of 32³ cells with outflow faces.
pub fn moving_cube() -> Setup {
    const N: usize = 32;
    let h = 1e-3;
    let (a, b) = (10.0 * h, 22.0 * h);
    Setup {
        lower: [0.0; 3],
        upper: [N as f64 * h; 3],
        cells: [N; 3],
        solids: vec![([a, a, a], [b, b, b])],
        solid_velocity: [50.0, 0.0, 0.0],
        gas_velocity: [0.0; 3],
        ice_faces: std::array::from_fn(|_| IceBoundary::Outflow),
        mpm_faces: [GridBoundary::Free; 6],
    }
}

/// Builds the case (panics on a bad setup: the cases are fixed).
pub fn build(s: &Setup) -> IceMpm {
    let (ice, mpm) = build_frames(s);
    IceMpm::new(ice, mpm, &[1]).expect("the coupling cases are consistent")
}

/// Steps the timed coupled case takes first, so that the air already
/// moves (the criterion bench `ice_mpm_step` and V-ICE-MPM's step cost).
pub const WARM_UP_STEPS: usize = 3;

/// The case built and advanced [`WARM_UP_STEPS`] steps, each at its
/// stable Δt: the coupled state the bench and the step cost time.
pub fn build_warm(s: &Setup) -> Result<IceMpm, SolverError> {
    let mut c = build(s);
    for _ in 0..WARM_UP_STEPS {
        let dt = c.stable_dt()?;
        c.advance(dt)?;
    }
    Ok(c)
}

/// The case's two frames before coupling: the ICE solver (air and steel,
/// steel Eulerian) and the MPM solver of the steel particles — the
/// standalone steps the coupled one is compared with.
pub fn build_frames(s: &Setup) -> (IceSolver<EosModel>, MpmSolver) {
    let level = Level::new(s.lower, s.upper, s.cells, [1, 1, 1], GHOST).unwrap();
    let solids = s.solids.clone();
    let inside = move |x: [f64; 3]| {
        solids
            .iter()
            .any(|(lo, hi)| (0..3).all(|d| x[d] >= lo[d] && x[d] <= hi[d]))
    };
    let rho_air = air_density();
    let rho_steel = steel_eos().density(P0, T0).unwrap();
    let eps = 1e-6;
    let (gv, sv) = (s.gas_velocity, s.solid_velocity);
    let ice = IceSolver::new(
        vec![air(), steel_eos()],
        level.clone(),
        s.ice_faces.clone(),
        ExchangeCoefficients::uniform(2, 1e15, 0.0),
        IceOptions::default(),
        |x| {
            let solid = inside(x);
            CellState {
                pressure: P0,
                materials: vec![
                    MaterialState {
                        volume_fraction: if solid { eps } else { 1.0 - eps },
                        density: rho_air,
                        velocity: if solid { sv } else { gv },
                    },
                    MaterialState {
                        volume_fraction: if solid { 1.0 - eps } else { eps },
                        density: rho_steel,
                        velocity: if solid { sv } else { gv },
                    },
                ],
            }
        },
    )
    .unwrap();
    let mut particles = Particles::default();
    for (lo, hi) in &s.solids {
        fill_shape(
            &mut particles,
            &level.geometry,
            &FillSpec {
                shape: Shape::Box { min: *lo, max: *hi },
                ppc: 2,
                density: rho_steel,
                material: MaterialId(0),
                velocity: s.solid_velocity,
                temperature: T0,
                specific_internal_energy: 0.0,
            },
        )
        .unwrap();
    }
    let steel = MaterialModel::Hypoelastic(Hypoelastic {
        shear_modulus: 80e9,
        pressure: PressureModel::Linear {
            bulk_modulus: STEEL_K,
        },
        rate: ObjectiveRate::Jaumann,
    });
    let mpm = MpmSolver::new(
        level,
        vec![steel],
        particles,
        MpmOptions {
            shape: ShapeFunction::Linear,
            scheme: UpdateScheme::Musl,
            boundaries: s.mpm_faces,
            ..Default::default()
        },
    )
    .unwrap();
    (ice, mpm)
}

/// Runs to `t_end`; returns the step count.
pub fn run(s: &mut IceMpm, t_end: f64) -> Result<usize, SolverError> {
    let mut steps = 0;
    while s.time() < t_end * (1.0 - 1e-12) {
        let dt = s.stable_dt()?.min(t_end - s.time());
        s.advance(dt)?;
        steps += 1;
    }
    Ok(steps)
}

/// The largest particle speed and the largest cell (mixture) speed, m/s.
pub fn max_speed(s: &IceMpm) -> (f64, f64) {
    let ps = s.mpm().particles();
    let solid = ps
        .velocity
        .iter()
        .map(|v| (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt())
        .fold(0.0, f64::max);
    let d = s
        .cell_data(&["velocity_x".into(), "velocity_y".into()])
        .unwrap();
    let (u, v) = (
        d.field("velocity_x").unwrap(),
        d.field("velocity_y").unwrap(),
    );
    let gas = u
        .iter()
        .zip(v)
        .map(|(a, b)| (a * a + b * b).sqrt())
        .fold(0.0, f64::max);
    (solid, gas)
}

/// The exact piston-driven shock in a γ-law gas: shock speed and pressure
/// behind it for a piston at `up` into gas (ρ₀, p₀).
pub fn piston_shock(gamma: f64, rho0: f64, p0: f64, up: f64) -> (f64, f64) {
    let c0 = (gamma * p0 / rho0).sqrt();
    let a = (gamma + 1.0) / 4.0 * up;
    let s = a + (a * a + c0 * c0).sqrt();
    (s, p0 + rho0 * s * up)
}

/// What the piston case measures.
#[derive(Debug)]
pub struct PistonMeasure {
    /// Mean pressure over the middle half between piston face and shock, Pa.
    pub plateau: f64,
    /// Exact plateau pressure, Pa.
    pub plateau_exact: f64,
    /// plateau / exact − 1.
    pub plateau_error: f64,
    /// Shock position, m.
    pub shock: f64,
    /// Exact shock position, m.
    pub shock_exact: f64,
    /// (shock − exact)/Δx.
    pub shock_error_cells: f64,
    /// Mean particle velocity of the piston, m/s.
    pub piston_velocity: f64,
}

/// Measures the piston case at time `t` (piston face initially at `x0`,
/// speed `up`).
pub fn piston_measure(s: &IceMpm, x0: f64, up: f64, t: f64) -> PistonMeasure {
    let (speed, p_exact) = piston_shock(1.4, air_density(), P0, up);
    let g = s.ice().level().geometry;
    let d = s.cell_data(&["pressure".into()]).unwrap();
    let p = d.field("pressure").unwrap();
    let ps = s.mpm().particles();
    let face = ps.position.iter().map(|x| x[0]).fold(f64::MIN, f64::max);
    let piston_velocity = ps.velocity.iter().map(|v| v[0]).sum::<f64>() / ps.len() as f64;
    let shock_exact = x0 + speed * t;
    // Plateau: mean over the middle half between the piston face and the
    // exact shock.
    let (a, b) = (
        face + 0.25 * (shock_exact - face),
        face + 0.75 * (shock_exact - face),
    );
    let cells: Vec<usize> = (0..g.cells[0])
        .filter(|&i| {
            let x = g.cell_centre([i, 0, 0])[0];
            x > a && x < b
        })
        .collect();
    let plateau = cells.iter().map(|&i| p[i]).sum::<f64>() / cells.len() as f64;
    let level = 0.5 * (P0 + plateau);
    let i = (1..g.cells[0])
        .rev()
        .find(|&i| p[i - 1] >= level && p[i] < level)
        .unwrap_or(0);
    let xa = g.cell_centre([i - 1, 0, 0])[0];
    let shock = xa + g.spacing[0] * (p[i - 1] - level) / (p[i - 1] - p[i]);
    PistonMeasure {
        plateau,
        plateau_exact: p_exact,
        plateau_error: plateau / p_exact - 1.0,
        shock,
        shock_exact,
        shock_error_cells: (shock - shock_exact) / g.spacing[0],
        piston_velocity,
    }
}

/// The piston case: a 1 cm steel piston at 100 m/s driving a shock into
/// air at rest in a 1D tube 0.2 m long with cells of `h` (m), measured at
/// t = 100 µs.
pub fn piston(h: f64) -> Result<PistonMeasure, SolverError> {
    let up = 100.0;
    let x0 = 0.06;
    let cells = (0.2 / h).round() as usize;
    let mut s = build(&Setup {
        lower: [0.0; 3],
        upper: [0.2, h, h],
        cells: [cells, 1, 1],
        solids: vec![([x0 - 0.01, 0.0, 0.0], [x0, h, h])],
        solid_velocity: [up, 0.0, 0.0],
        gas_velocity: [0.0; 3],
        ice_faces: std::array::from_fn(|_| IceBoundary::Outflow),
        mpm_faces: [GridBoundary::Free; 6],
    });
    let t = 1e-4;
    run(&mut s, t)?;
    Ok(piston_measure(&s, x0, up, t))
}

/// The box-at-rest case: a closed 2D steel box (walls two 1 mm cells
/// thick, 20 × 20 cells, symmetry faces) with air inside and out at one
/// atmosphere, all at rest; after `steps` steps, the largest particle
/// speed and the largest cell speed, m/s.
pub fn box_at_rest(steps: usize) -> Result<(f64, f64), SolverError> {
    let h = 1e-3;
    let walls = vec![
        ([4.0 * h, 4.0 * h, 0.0], [16.0 * h, 6.0 * h, h]),
        ([4.0 * h, 14.0 * h, 0.0], [16.0 * h, 16.0 * h, h]),
        ([4.0 * h, 6.0 * h, 0.0], [6.0 * h, 14.0 * h, h]),
        ([14.0 * h, 6.0 * h, 0.0], [16.0 * h, 14.0 * h, h]),
    ];
    let mut s = build(&Setup {
        lower: [0.0; 3],
        upper: [20.0 * h, 20.0 * h, h],
        cells: [20, 20, 1],
        solids: walls,
        solid_velocity: [0.0; 3],
        gas_velocity: [0.0; 3],
        ice_faces: std::array::from_fn(|_| IceBoundary::Symmetry),
        mpm_faces: [GridBoundary::Symmetry; 6],
    });
    for _ in 0..steps {
        let dt = s.stable_dt()?;
        s.advance(dt)?;
    }
    Ok(max_speed(&s))
}

/// The floating-block case: a 4 × 4 mm steel block and the air around it
/// moving together at 20 m/s (24 × 12 cells of 1 mm, zero-gradient faces:
/// the stream enters at x = 0, which the one-way `Outflow` face would
/// refuse); after `steps` steps, the largest deviation from (20, 0, 0) m/s
/// of any particle and of any cell, m/s.
pub fn floating_block(steps: usize) -> Result<(f64, f64), SolverError> {
    let h = 1e-3;
    let u = [20.0, 0.0, 0.0];
    let mut s = build(&Setup {
        lower: [0.0; 3],
        upper: [24.0 * h, 12.0 * h, h],
        cells: [24, 12, 1],
        solids: vec![([8.0 * h, 4.0 * h, 0.0], [12.0 * h, 8.0 * h, h])],
        solid_velocity: u,
        gas_velocity: u,
        ice_faces: std::array::from_fn(|_| IceBoundary::ZeroGradient),
        mpm_faces: [GridBoundary::Free; 6],
    });
    for _ in 0..steps {
        let dt = s.stable_dt()?;
        s.advance(dt)?;
    }
    let ps = s.mpm().particles();
    let solid = ps
        .velocity
        .iter()
        .map(|v| (v[0] - u[0]).abs().max(v[1].abs()))
        .fold(0.0, f64::max);
    let d = s.cell_data(&["velocity_x".into(), "velocity_y".into()])?;
    let (vx, vy) = (
        d.field("velocity_x").unwrap_or(&[]),
        d.field("velocity_y").unwrap_or(&[]),
    );
    let gas = vx
        .iter()
        .zip(vy)
        .map(|(a, b)| (a - u[0]).abs().max(b.abs()))
        .fold(0.0, f64::max);
    Ok((solid, gas))
}

/// The closed piston tube of [`closed_tube`]: 8 cm of air in 1 mm cells,
/// walls at both ends, a 1 cm steel piston at x = 3–4 cm moving at
/// 100 m/s.
pub fn closed_tube_setup() -> Setup {
    let h = 1e-3;
    Setup {
        lower: [0.0; 3],
        upper: [0.08, h, h],
        cells: [80, 1, 1],
        solids: vec![([0.03, 0.0, 0.0], [0.04, h, h])],
        solid_velocity: [100.0, 0.0, 0.0],
        gas_velocity: [0.0; 3],
        ice_faces: std::array::from_fn(|_| IceBoundary::Symmetry),
        mpm_faces: [GridBoundary::Symmetry; 6],
    }
}

/// What [`closed_tube`] measures.
#[derive(Clone, Copy, Debug)]
pub struct ClosedTube {
    /// Relative closure of the mass bookkeeping.
    pub mass: f64,
    /// Total x-momentum change (fluid + particles) over the piston's
    /// initial momentum.
    pub momentum: f64,
    /// Total energy change over the piston's initial kinetic energy.
    pub energy: f64,
    /// Mass the equilibration moved, over the air's mass.
    pub rescaled: f64,
    /// Time reached, s.
    pub time: f64,
}

/// The closed piston tube: a 1 cm steel piston at 100 m/s in an 8 cm air
/// tube of 1 mm cells with walls at both ends, `steps` steps. Until the
/// piston's shock (412 m/s from x = 4 cm) or its rarefaction (347 m/s from
/// x = 3 cm) reaches a wall, about 86 µs, both walls hold the same
/// undisturbed air and push equally and oppositely: the total momentum is
/// then that of the start.
pub fn closed_tube(steps: usize) -> Result<ClosedTube, SolverError> {
    let h = 1e-3;
    let mut s = build(&closed_tube_setup());
    let before = s.conservation_totals();
    let piston_mass = STEEL_RHO * 0.01 * h * h;
    let kinetic = 0.5 * piston_mass * 100.0 * 100.0;
    for _ in 0..steps {
        let dt = s.stable_dt()?;
        s.advance(dt)?;
    }
    let after = s.conservation_totals();
    let air_mass = air_density() * 0.07 * h * h;
    Ok(ClosedTube {
        mass: (after.mass - before.mass) / before.mass,
        momentum: (after.momentum[0] - before.momentum[0]) / (piston_mass * 100.0),
        energy: (after.energy - before.energy) / kinetic,
        rescaled: s.rescaled_totals().mass / air_mass,
        time: s.time(),
    })
}

/// What [`detonation_column`] measures.
#[derive(Clone, Copy, Debug)]
pub struct DetonationColumn {
    /// Arrival times (pressure first above 1 GPa) at x = 4 and 9 cm, s.
    pub arrival: [f64; 2],
    /// Detonation velocity between the gauges, m/s.
    pub detonation_velocity: f64,
    /// Fraction of the reactant mass burnt at the end (the Eulerian run's;
    /// `None` for particles, whose solver is behind the `Solver` trait here).
    pub burnt_fraction: Option<f64>,
    /// Steps taken.
    pub steps: usize,
}

/// A planar QM-100 detonation (seed 000 §5.2's explosive: Murnaghan
/// reactant, JWL C-term products, JWL++ G 9.1e-5, b 1) in a 1D column
/// 10 cm long with closed ends, cells of `h`: a 6 mm booster of products at
/// 10 GPa, the reactant at rest at 1 atm beyond it — carried by particles
/// (`particles`: the ICE–MPM pipeline, the reactant a hypoelastic solid
/// whose pressure is its Murnaghan EOS's, with a shear modulus of 10⁻³ of
/// its bulk modulus at rest) or Eulerian (the
/// ICE solver alone). Run until the wave passes 9 cm; the detonation
/// velocity between 4 and 9 cm (3.4 cm of run from the booster), arrival
/// by linear interpolation of the pressure in time.
pub fn detonation_column(h: f64, particles: bool) -> Result<DetonationColumn, SolverError> {
    use brisance_eos::JwlCTerm;
    let err = |e: String| SolverError::Other(e);
    let (reactant, products) = (Murnaghan::qm100(), JwlCTerm::qm100());
    let q = brisance_ice::reaction::detonation_energy(&reactant, &products).map_err(err)?;
    let length = 0.1;
    let n = (length / h).round() as usize;
    let level = Level::new([0.0; 3], [length, h, h], [n, 1, 1], [1, 1, 1], GHOST)
        .map_err(|e| err(e.to_string()))?;
    let t0 = 298.15;
    let rho_r = reactant.density(P0, t0).map_err(|e| err(e.to_string()))?;
    let rho_r_boost = reactant.density(1e10, t0).map_err(|e| err(e.to_string()))?;
    let rho_p = products.density(P0, t0).map_err(|e| err(e.to_string()))?;
    let booster = 0.006;
    let eos = vec![EosModel::JwlCTerm(products), EosModel::Murnaghan(reactant)];
    let eps = 1e-6;
    let mut ice = IceSolver::new(
        eos,
        level.clone(),
        std::array::from_fn(|_| IceBoundary::Symmetry),
        ExchangeCoefficients::uniform(2, 1e15, 0.0),
        IceOptions::default(),
        |x| {
            let boost = x[0] < booster;
            CellState {
                pressure: if boost { 1e10 } else { P0 },
                materials: vec![
                    MaterialState {
                        volume_fraction: if boost { 1.0 - eps } else { eps },
                        density: if boost { 1260.0 } else { rho_p },
                        velocity: [0.0; 3],
                    },
                    MaterialState {
                        volume_fraction: if boost { eps } else { 1.0 - eps },
                        density: if boost { rho_r_boost } else { rho_r },
                        velocity: [0.0; 3],
                    },
                ],
            }
        },
    )
    .map_err(|e| err(e.to_string()))?;
    ice.set_reactions(vec![brisance_ice::IceReaction {
        reactant: 1,
        product: 0,
        rate: brisance_ice::JwlPlusPlus {
            g: 9.1e-5,
            b: 1.0,
            ..brisance_ice::JwlPlusPlus::anfo_k1()
        }
        .into(),
        heat_of_reaction: q,
    }])
    .map_err(|e| err(e.to_string()))?;
    let mut solver: Box<dyn brisance_core::Solver> = if particles {
        let mut ps = Particles::default();
        fill_shape(
            &mut ps,
            &level.geometry,
            &FillSpec {
                shape: Shape::Box {
                    min: [booster, 0.0, 0.0],
                    max: [length, h, h],
                },
                ppc: 2,
                density: rho_r,
                material: MaterialId(0),
                velocity: [0.0; 3],
                temperature: t0,
                specific_internal_energy: 0.0,
            },
        )
        .map_err(|e| err(e.to_string()))?;
        let model = MaterialModel::Hypoelastic(Hypoelastic {
            shear_modulus: 1e-3 / reactant.kappa,
            pressure: PressureModel::Eos(EosModel::Murnaghan(reactant)),
            rate: ObjectiveRate::Jaumann,
        });
        let mpm = MpmSolver::new(
            level.clone(),
            vec![model],
            ps,
            MpmOptions {
                shape: ShapeFunction::Linear,
                scheme: UpdateScheme::Musl,
                boundaries: [GridBoundary::Symmetry; 6],
                ..Default::default()
            },
        )
        .map_err(|e| err(e.to_string()))?;
        Box::new(IceMpm::new(ice, mpm, &[1]).map_err(|e| err(e.to_string()))?)
    } else {
        Box::new(ice)
    };
    let reactant_mass = |s: &dyn brisance_core::Solver| -> f64 {
        let d = s
            .cell_data(&["density_2".into()])
            .unwrap_or_else(|_| unreachable!());
        d.field("density_2")
            .map_or(0.0, |r| r.iter().sum::<f64>() * h * h * h)
    };
    let m0 = if particles {
        0.0
    } else {
        reactant_mass(solver.as_ref())
    };
    let gauges = [0.04, 0.09];
    let cell = |x: f64| (x / h) as usize;
    let level_p = 1e9;
    let mut arrival = [f64::NAN; 2];
    let mut prev: Option<(f64, [f64; 2])> = None;
    let mut steps = 0;
    let t_max = 40e-6;
    while arrival[1].is_nan() && solver.time() < t_max {
        let dt = solver.stable_dt()?;
        solver.advance(dt)?;
        steps += 1;
        let d = solver.cell_data(&["pressure".into()])?;
        let p = d.field("pressure").unwrap_or(&[]);
        let now = [p[cell(gauges[0])], p[cell(gauges[1])]];
        let t = solver.time();
        if let Some((t_prev, p_prev)) = prev {
            for g in 0..2 {
                if arrival[g].is_nan() && now[g] > level_p {
                    let f = (level_p - p_prev[g]) / (now[g] - p_prev[g]);
                    arrival[g] = t_prev + f.clamp(0.0, 1.0) * (t - t_prev);
                }
            }
        }
        prev = Some((t, now));
    }
    let burnt_fraction = (!particles).then(|| 1.0 - reactant_mass(solver.as_ref()) / m0);
    Ok(DetonationColumn {
        arrival,
        detonation_velocity: (gauges[1] - gauges[0]) / (arrival[1] - arrival[0]),
        burnt_fraction,
        steps,
    })
}
