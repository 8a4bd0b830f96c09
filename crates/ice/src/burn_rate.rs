//! V-BURNRATE: a slab of reactant burning by the deflagration of seed 000
//! §4.1.2 (D = A pⁿ, eq 38; Γ = a D ρ, eq 39) into its products at a held
//! pressure, in the ICE solver with the surface pass of step 2. The
//! reactant's volume V_r(t) = Σ θ_r V gives the position of its surface,
//! whose speed is compared with A pⁿ at the surface's pressure.
//!
//! Three surfaces:
//! - [`BurnSurface::Plane`]: 1D, reactant on x < x₀ against a symmetry
//!   wall; the surface's position x_s = V_r / A, A the cross-section.
//! - [`BurnSurface::Diagonal`]: 2D, reactant where x + y < c₀ in the corner
//!   of two symmetry walls, the surface at 45° to the grid; V_r = c² h_z / 2
//!   and the surface's distance from the corner is c/√2.
//! - [`BurnSurface::Sphere`]: (r, z) rings, a hemisphere of radius R₀ on
//!   the symmetry plane z = 0; V_r = (2/3) π R³.
//!
//! The products fill the rest at the same pressure and `products_temperature`
//! (above the ignition temperature, so the whole surface burns from the
//! start); the far faces hold that state ([`IceBoundary::FixedState`]), so
//! the gas the burn makes flows out and the pressure stays near the held
//! one. The law is evaluated at the mean pressure of the cells the surface
//! crosses (reactant volume fraction between 10⁻⁴ and 1 − 10⁻³), sampled
//! every step after the start-up window.
//!
//! The reactant and product EOS are ANFO-K1's (Murnaghan, JWL C-term) with
//! their JWL++ heat of reaction: the library holds no PBX-9501 reactant
//! EOS yet, and the EOS only sets how much gas the burn makes, not its law.

use std::f64::consts::{PI, SQRT_2};
use std::sync::Arc;

use brisance_core::solver::step_to;
use brisance_core::{Eos, Geometry, Solver};
use brisance_eos::EosModel;
use brisance_grid::comm::{self, Communicator};
use brisance_grid::Level;
use brisance_reaction::Deflagration;

use crate::cases::anfo_k1_jwlpp;
use crate::solver::GHOST;
use crate::{
    CellState, ExchangeCoefficients, IceBoundary, IceOptions, IceReaction, IceSolver,
    MaterialState, PressureSolve,
};

/// The shape of the burning surface.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum BurnSurface {
    /// A plane normal to x (1D).
    Plane,
    /// A plane at 45° to x and y (2D).
    Diagonal,
    /// A sphere on an (r, z) grid.
    Sphere,
}

impl BurnSurface {
    /// The name the report prints.
    pub fn name(self) -> &'static str {
        match self {
            Self::Plane => "grid-aligned plane",
            Self::Diagonal => "plane at 45°",
            Self::Sphere => "sphere (r–z)",
        }
    }
}

/// Settings of one V-BURNRATE run.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BurnRate {
    /// The burn law.
    pub law: Deflagration,
    /// The held pressure, Pa.
    pub pressure: f64,
    /// The surface.
    pub surface: BurnSurface,
    /// Cell size, m.
    pub h: f64,
    /// The reactant's initial extent (x₀, c₀/√2 or R₀) in cells.
    pub extent_cells: usize,
    /// How far the surface moves at A pⁿ of the held pressure, in cells.
    pub regress_cells: f64,
    /// Temperature of the products, K.
    pub products_temperature: f64,
}

impl BurnRate {
    /// PBX-9501's law ([`Deflagration::pbx_9501`]) at `pressure` on cells
    /// of 0.1 mm, the reactant 8 cells deep, burnt back 3 cells, the
    /// products at 2500 K.
    pub fn pbx_9501(pressure: f64, surface: BurnSurface) -> Self {
        Self {
            law: Deflagration::pbx_9501(),
            pressure,
            surface,
            h: 1.0e-4,
            extent_cells: 8,
            regress_cells: 3.0,
            products_temperature: 2500.0,
        }
    }

    /// V-BURNRATE's A/100 rows: PBX-9501's law with A over 100 (a burn
    /// slow enough that the gas it makes leaves the pressure held) at
    /// 100 MPa on `surface`, burnt back one cell.
    pub fn a_over_100(surface: BurnSurface) -> Self {
        let mut cfg = Self::pbx_9501(1.0e8, surface);
        cfg.law.a /= 100.0;
        cfg.regress_cells = 1.0;
        cfg
    }
}

/// What a V-BURNRATE run measured.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BurnRateResult {
    /// The surface's speed into the reactant: the slope of its position
    /// over the measuring window (least squares), m/s.
    pub speed: f64,
    /// The speed the law gives the surface: the time mean over the window
    /// of A pⁿ averaged over the burning surface, each surface cell
    /// weighted by its area, at its own pressure
    /// ([`crate::IceSolver::burning_surface`]), m/s.
    pub law_speed: f64,
    /// The pressure at which A pⁿ is `law_speed`, Pa.
    pub surface_pressure: f64,
    /// A pⁿ at the held pressure, m/s.
    pub held_speed: f64,
    /// The surface pass's summed area over the true area of the surface at
    /// the position the reactant's volume gives, minus 1; the time mean
    /// over the window.
    pub area_error: f64,
    /// Steps taken.
    pub steps: u64,
}

impl BurnRateResult {
    /// speed / law_speed − 1.
    pub fn error(&self) -> f64 {
        self.speed / self.law_speed - 1.0
    }
}

/// Runs one V-BURNRATE case; the message says what failed.
pub fn burn_rate(cfg: &BurnRate) -> Result<BurnRateResult, String> {
    run_slab(cfg, burning_slab(cfg, PressureSolve::Explicit)?)
}

/// The solver of a V-BURNRATE case at its start, its reaction set, with the
/// pressure solve `pressure`; the message says what failed.
pub fn burning_slab(
    cfg: &BurnRate,
    pressure: PressureSolve,
) -> Result<IceSolver<EosModel>, String> {
    burning_slab_on(Arc::new(comm::Serial), cfg, pressure, [1, 1, 1])
}

/// [`burning_slab`] on `patches` patches shared among the ranks of
/// `comm` (docs/cluster.md).
pub fn burning_slab_on(
    comm: Arc<dyn Communicator>,
    cfg: &BurnRate,
    pressure: PressureSolve,
    patches: [usize; 3],
) -> Result<IceSolver<EosModel>, String> {
    let (eos, jwlpp) = anfo_k1_jwlpp()?;
    let p0 = cfg.pressure;
    let rho_r = eos[0].density(p0, 298.15).map_err(|e| e.to_string())?;
    let rho_p = eos[1]
        .density(p0, cfg.products_temperature)
        .map_err(|e| e.to_string())?;
    let state = move |theta: f64| CellState {
        pressure: p0,
        materials: vec![
            MaterialState {
                volume_fraction: theta,
                density: rho_r,
                velocity: [0.0; 3],
            },
            MaterialState {
                volume_fraction: 1.0 - theta,
                density: rho_p,
                velocity: [0.0; 3],
            },
        ],
    };
    let boundaries = slab_boundaries(cfg, IceBoundary::FixedState(state(TRACE)));
    let mut s = IceSolver::new_on(
        comm,
        eos,
        slab_level_in(cfg, patches)?,
        boundaries,
        ExchangeCoefficients::uniform(2, 1e15, 0.0),
        IceOptions {
            geometry: slab_geometry(cfg.surface),
            pressure,
            ..Default::default()
        },
        |x| state(initial_fraction(cfg, x).clamp(TRACE, 1.0 - TRACE)),
    )
    .map_err(|e| e.to_string())?;
    s.set_reactions(vec![IceReaction {
        rate: cfg.law.into(),
        ..jwlpp
    }])
    .map_err(|e| e.to_string())?;
    Ok(s)
}

/// A trace of the other material where a cell holds only one.
const TRACE: f64 = 1.0e-6;

/// The geometry of a V-BURNRATE grid: (r, z) rings for the sphere.
pub fn slab_geometry(surface: BurnSurface) -> Geometry {
    match surface {
        BurnSurface::Sphere => Geometry::Axisymmetric,
        BurnSurface::Plane | BurnSurface::Diagonal => Geometry::Cartesian,
    }
}

/// The grid of a V-BURNRATE case: cells of `h`, the reactant and as much
/// again of products (the corner triangle reaches about twice its extent
/// along each axis), one patch.
pub fn slab_level(cfg: &BurnRate) -> Result<Level, String> {
    slab_level_in(cfg, [1, 1, 1])
}

/// [`slab_level`] split into `patches` patches.
pub fn slab_level_in(cfg: &BurnRate, patches: [usize; 3]) -> Result<Level, String> {
    let across = 2 * cfg.extent_cells + 4;
    let cells = match cfg.surface {
        BurnSurface::Plane => [across, 1, 1],
        BurnSurface::Diagonal => {
            let n = 3 * cfg.extent_cells + 4;
            [n, n, 1]
        }
        BurnSurface::Sphere => [across, across, 1],
    };
    Level::new(
        [0.0; 3],
        std::array::from_fn(|d| cells[d] as f64 * cfg.h),
        cells,
        patches,
        GHOST,
    )
    .map_err(|e| e.to_string())
}

/// The faces of a V-BURNRATE grid: x (or r) from a symmetry wall (the
/// axis) to `held`; y (or z) the same in 2D, from the symmetry plane z = 0
/// for the sphere; symmetry elsewhere.
pub fn slab_boundaries(cfg: &BurnRate, held: IceBoundary) -> [IceBoundary; 6] {
    [
        IceBoundary::Symmetry,
        held.clone(),
        IceBoundary::Symmetry,
        if cfg.surface == BurnSurface::Plane {
            IceBoundary::Symmetry
        } else {
            held
        },
        IceBoundary::Symmetry,
        IceBoundary::Symmetry,
    ]
}

/// Whether point `x` lies inside the reactant at the start.
pub fn initially_inside(cfg: &BurnRate, x: [f64; 3]) -> bool {
    let (h, m) = (cfg.h, cfg.extent_cells as f64);
    match cfg.surface {
        BurnSurface::Plane => x[0] < m * h,
        // c₀ = (2m + ½) h: no sampling point lies on the plane, so every
        // cell of a diagonal layer starts with the same volume fraction.
        BurnSurface::Diagonal => x[0] + x[1] < (2.0 * m + 0.5) * h,
        BurnSurface::Sphere => x[0] * x[0] + x[1] * x[1] < (m * h) * (m * h),
    }
}

/// The reactant's volume fraction at the start in the cell centred at
/// `x`, by 8 × 8 points over the cell in x–y (z is one cell thick).
pub fn initial_fraction(cfg: &BurnRate, x: [f64; 3]) -> f64 {
    const SAMPLES: usize = 8;
    let h = cfg.h;
    let mut n_in = 0;
    for a in 0..SAMPLES {
        for b in 0..SAMPLES {
            let dx = (a as f64 + 0.5) / SAMPLES as f64 - 0.5;
            let dy = (b as f64 + 0.5) / SAMPLES as f64 - 0.5;
            let y = if cfg.surface == BurnSurface::Plane {
                x[1]
            } else {
                x[1] + dy * h
            };
            if initially_inside(cfg, [x[0] + dx * h, y, x[2]]) {
                n_in += 1;
            }
        }
    }
    n_in as f64 / (SAMPLES * SAMPLES) as f64
}

/// The measure of a V-BURNRATE run, fed after every step: the surface's
/// position from the reactant's volume, its speed by least squares over
/// the last 80 % of the run, the law's speed and the area error over the
/// same window.
#[derive(Debug, Clone)]
pub struct Regression {
    surface: BurnSurface,
    h: f64,
    law: Deflagration,
    held_speed: f64,
    t_end: f64,
    ts: Vec<f64>,
    xs: Vec<f64>,
    law_sum: f64,
    area_sum: f64,
    window: f64,
}

impl Regression {
    /// The measure of case `cfg`; an error where the law does not burn at
    /// the held pressure.
    pub fn new(cfg: &BurnRate) -> Result<Self, String> {
        let held_speed = cfg.law.burn_speed(cfg.pressure, cfg.products_temperature);
        if !(held_speed > 0.0) {
            return Err("the law gives no burn at the held pressure".into());
        }
        Ok(Self {
            surface: cfg.surface,
            h: cfg.h,
            law: cfg.law,
            held_speed,
            t_end: cfg.regress_cells * cfg.h / held_speed,
            ts: Vec::new(),
            xs: Vec::new(),
            law_sum: 0.0,
            area_sum: 0.0,
            window: 0.0,
        })
    }

    /// The run's length: `regress_cells` at A pⁿ of the held pressure, s.
    pub fn t_end(&self) -> f64 {
        self.t_end
    }

    /// The surface's position for a reactant volume `v` (m³; on (r, z)
    /// rings the whole ring's): plane V/A, 45° the corner triangle's
    /// c/√2, sphere the hemisphere's radius.
    pub fn position(&self, v: f64) -> f64 {
        let h = self.h;
        match self.surface {
            BurnSurface::Plane => v / (h * h),
            BurnSurface::Diagonal => (2.0 * v / h).sqrt() / SQRT_2,
            BurnSurface::Sphere => (1.5 * v / PI).cbrt(),
        }
    }

    /// Whether a step ending at `time` lies in the measuring window.
    pub fn measuring(&self, time: f64) -> bool {
        time >= 0.2 * self.t_end
    }

    /// The true area of the surface at distance `x` from the wall, the
    /// corner or the centre, m².
    pub fn true_area(&self, x: f64) -> f64 {
        match self.surface {
            BurnSurface::Plane => self.h * self.h,
            BurnSurface::Diagonal => 2.0 * x * self.h,
            BurnSurface::Sphere => 2.0 * PI * x * x,
        }
    }

    /// Records the state after a step of `dt` ending at `time`: the
    /// reactant's volume `v` and the burning surface's (area, mean A pⁿ)
    /// ([`crate::IceSolver::burning_surface`]).
    pub fn record(&mut self, time: f64, dt: f64, v: f64, surface: Option<(f64, f64)>) {
        if !self.measuring(time) {
            return;
        }
        let x = self.position(v);
        self.ts.push(time);
        self.xs.push(x);
        if let Some((area, speed)) = surface {
            self.law_sum += speed * dt;
            self.area_sum += (area / self.true_area(x) - 1.0) * dt;
            self.window += dt;
        }
    }

    /// The result after `steps` steps; an error where the window holds
    /// too few.
    pub fn finish(&self, steps: u64) -> Result<BurnRateResult, String> {
        if self.ts.len() < 3 || !(self.window > 0.0) {
            return Err(format!(
                "too few steps in the measuring window ({} steps, {:e} s with a burning surface, t_end {:e} s)",
                self.ts.len(),
                self.window,
                self.t_end,
            ));
        }
        let law_speed = self.law_sum / self.window;
        Ok(BurnRateResult {
            speed: -least_squares_slope(&self.ts, &self.xs),
            law_speed,
            surface_pressure: (law_speed / self.law.a).powf(1.0 / self.law.n),
            held_speed: self.held_speed,
            area_error: self.area_sum / self.window,
            steps,
        })
    }
}

/// Runs the slab `s` of [`burning_slab`] over the case's time and measures.
fn run_slab(cfg: &BurnRate, mut s: IceSolver<EosModel>) -> Result<BurnRateResult, String> {
    let mut measure = Regression::new(cfg)?;
    let t_end = measure.t_end();
    let h = cfg.h;
    let cells = s.level().geometry.cells;
    let geometry = s.options().geometry;
    let volume_per_cell = |n: usize| {
        let r_lo = (n % cells[0]) as f64 * h;
        geometry.cell_volume(r_lo, h, h, h)
    };
    step_to(&mut s, t_end, |s, dt| {
        if !measure.measuring(s.time()) {
            return Ok(());
        }
        let d = s.cell_data(&["volume_fraction_1".into()])?;
        let v: f64 = d.fields[0]
            .1
            .iter()
            .enumerate()
            .map(|(n, t)| t * volume_per_cell(n))
            .sum();
        measure.record(s.time(), dt, v, s.burning_surface(0));
        Ok(())
    })
    .map_err(|e| e.to_string())?;
    measure.finish(s.steps())
}

/// Least-squares slope of y against x.
fn least_squares_slope(x: &[f64], y: &[f64]) -> f64 {
    let n = x.len() as f64;
    let (mx, my) = (x.iter().sum::<f64>() / n, y.iter().sum::<f64>() / n);
    let (mut sxy, mut sxx) = (0.0, 0.0);
    for (a, b) in x.iter().zip(y) {
        sxy += (a - mx) * (b - my);
        sxx += (a - mx) * (a - mx);
    }
    sxy / sxx
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The position the measure gives for the volume of each shape at a
    /// known distance is that distance, and the true area there is the
    /// shape's: h² (plane), the corner triangle's hypotenuse √2 c times h
    /// (45°), 2πx² (hemisphere).
    #[test]
    fn the_measure_inverts_each_shapes_volume() {
        let x = 7.25e-4;
        for (surface, v, area) in [
            (BurnSurface::Plane, x * 1e-8, 1e-8),
            // c = √2 x, V = c² h / 2
            (BurnSurface::Diagonal, x * x * 1e-4, 2.0 * x * 1e-4),
            (
                BurnSurface::Sphere,
                2.0 / 3.0 * PI * x * x * x,
                2.0 * PI * x * x,
            ),
        ] {
            let m = Regression::new(&BurnRate::pbx_9501(1.0e8, surface)).unwrap();
            assert!((m.position(v) / x - 1.0).abs() < 1e-14, "{surface:?}");
            assert!((m.true_area(x) / area - 1.0).abs() < 1e-14, "{surface:?}");
        }
    }

    #[test]
    fn least_squares_slope_of_a_line_is_exact() {
        let x = [0.0, 1.0, 2.0, 5.0];
        let y: Vec<f64> = x.iter().map(|v| 3.0 - 0.25 * v).collect();
        assert!((least_squares_slope(&x, &y) + 0.25).abs() < 1e-15);
    }

    /// A grid-aligned slab at 100 MPa with PBX-9501's A over 100 (a burn
    /// slow enough that the gas it makes leaves the pressure held)
    /// regresses one cell at A pⁿ of its surface pressure within 0.1 %
    /// (V-BURNRATE measures −0.001 %), and the surface pass's area is the
    /// slab's cross-section.
    #[test]
    fn plane_slab_regresses_at_a_p_to_the_n() {
        let r = burn_rate(&BurnRate::a_over_100(BurnSurface::Plane)).unwrap();
        assert!(r.error().abs() < 1e-3, "{r:?}");
        assert!((r.surface_pressure / 1.0e8 - 1.0).abs() < 1e-3, "{r:?}");
        assert!(r.area_error.abs() < 1e-12, "{r:?}");
    }

    /// The implicit pressure solve takes the burning PBX slab at 100 MPa
    /// step after step: its outer iterations used to diverge at the third
    /// step (the residual 1.3e2 → 4.8e3 → 4.8e8 → NaN, growing with the
    /// square of the pressure iterate through slabs reaching outside their
    /// donor cells, [`crate::advection::slab_width`]); they now converge
    /// (10 iterations at that step, tolerance 1e-10).
    #[test]
    fn the_implicit_solve_converges_on_the_burning_slab_at_100_mpa() {
        let cfg = BurnRate::pbx_9501(1.0e8, BurnSurface::Plane);
        let mut s = burning_slab(&cfg, PressureSolve::Implicit(Default::default())).unwrap();
        for _ in 0..6 {
            let dt = s.stable_dt().unwrap();
            s.advance(dt).unwrap();
        }
        let stats = s.pressure_solve_stats();
        assert_eq!(stats.steps, 6);
        assert!(stats.max_residual <= 1e-10, "{stats:?}");
        assert!(stats.max_iterations < 20, "{stats:?}");
    }

    /// The Arrhenius pyrolysis of seed 003 (§2.4, the lattice's regression
    /// law) burns the grid-aligned slab as a surface burn of the ICE, in
    /// place of the deflagration: Γ = (a/V) ṁ'' with ṁ'' = A exp(−Eₐ/(R T))
    /// at the surface's temperature (the hottest material present around
    /// the surface cell, here the products). The slab regresses one cell at
    /// the speed ṁ''/ρ_r the law gives at that temperature step by step
    /// ([`crate::IceSolver::burning_surface`]) within the V-BURNRATE target
    /// of 1 % (measured +0.68 %), and the surface pass's area is the slab's
    /// cross-section. With A = 10⁵ kg/(m²·s) and AP's Eₐ = 92.1 kJ/mol the
    /// products' 2500 K give 0.99 m/s at the start; the products the burn
    /// makes are hotter (about 3170 K), and the law's speed at the surface
    /// rises to about 2.5 m/s, which the comparison follows step by step.
    #[test]
    fn an_arrhenius_surface_regresses_at_its_mass_flux_over_its_density() {
        let cfg = BurnRate::pbx_9501(1.0e8, BurnSurface::Plane);
        let mut s = burning_slab(&cfg, PressureSolve::Explicit).unwrap();
        let law = brisance_reaction::Arrhenius {
            pre_exponential: 1.0e5,
            activation_energy: 92_109.6,
            catalytic_factor: 1.0,
        };
        let (eos, jwlpp) = anfo_k1_jwlpp().unwrap();
        s.set_reactions(vec![IceReaction {
            rate: law.into(),
            ..jwlpp
        }])
        .unwrap();
        let rho_r = eos[0].density(cfg.pressure, 298.15).unwrap();
        let held = law.speed(rho_r, cfg.products_temperature);
        assert!(held > 0.5 && held < 2.0, "{held}");
        let h = cfg.h;
        let t_end = h / held;
        let (mut ts, mut xs) = (Vec::new(), Vec::new());
        let (mut law_sum, mut area_sum, mut window) = (0.0, 0.0, 0.0);
        step_to(&mut s, t_end, |s, dt| {
            if s.time() < 0.2 * t_end {
                return Ok(());
            }
            let d = s.cell_data(&["volume_fraction_1".into()])?;
            let v: f64 = d.fields[0].1.iter().map(|t| t * h * h * h).sum();
            ts.push(s.time());
            xs.push(v / (h * h));
            if let Some((area, speed)) = s.burning_surface(0) {
                law_sum += speed * dt;
                area_sum += (area / (h * h) - 1.0).abs() * dt;
                window += dt;
            }
            Ok(())
        })
        .unwrap();
        assert!(window > 0.5 * t_end, "{window:e} of {t_end:e} s burning");
        let speed = -least_squares_slope(&ts, &xs);
        let law_speed = law_sum / window;
        let error = speed / law_speed - 1.0;
        eprintln!(
            "Arrhenius slab: {} steps, speed {speed:e} m/s, law {law_speed:e} m/s (held {held:e}), error {error:+e}",
            s.steps()
        );
        assert!(error.abs() < 1e-2, "{error:+e}");
        assert!(area_sum / window < 1e-12, "{}", area_sum / window);
    }

    /// PBX-9501's own law at 100 MPa burns 0.2 % of a cell a step. The
    /// reactant the gas drags out of the burning cell left a sliver of
    /// 10⁻⁴–10⁻³ as the outermost surface cell, and the cell behind it,
    /// where the surface was, did not burn: the slab regressed at 16 % of
    /// A pⁿ. With the burn the sliver cannot supply carried into the cell
    /// behind it (`IceSolver::carry_surface_burns`) it regresses three
    /// cells within 2 % of A pⁿ (V-BURNRATE measures +0.98 %).
    #[test]
    fn a_fast_burn_goes_on_behind_a_sliver() {
        let r = burn_rate(&BurnRate::pbx_9501(1.0e8, BurnSurface::Plane)).unwrap();
        assert!(r.error().abs() < 0.02, "{r:?}");
    }

    /// With the implicit pressure the step follows the material
    /// velocities, and a slab lit at rest had none: Δt was infinite. The
    /// burning front now bounds it by the gas it makes,
    /// Δt = cfl h / (A pⁿ v_p/v_r) for the grid-aligned slab at the held
    /// 100 MPa (its a/V is 1/h), and the explicit step (acoustic, 20 times
    /// shorter) is left as it was.
    #[test]
    fn a_burning_front_bounds_the_implicit_step_at_rest() {
        let cfg = BurnRate::pbx_9501(1.0e8, BurnSurface::Plane);
        let implicit = burning_slab(&cfg, PressureSolve::Implicit(Default::default())).unwrap();
        let dt = implicit.stable_dt().unwrap();
        // The gas leaves at D v_p/v_r, the reactant at 298.15 K, the
        // products at 2500 K.
        let (eos, _) = anfo_k1_jwlpp().unwrap();
        let expansion =
            eos[0].density(1.0e8, 298.15).unwrap() / eos[1].density(1.0e8, 2500.0).unwrap();
        assert!(expansion > 5.0, "{expansion}");
        let front = 0.4 * cfg.h / (cfg.law.burn_speed(1.0e8, 2500.0) * expansion);
        assert!((dt / front - 1.0).abs() < 1e-9, "{dt:e} against {front:e}");
        let explicit = burning_slab(&cfg, PressureSolve::Explicit).unwrap();
        let acoustic = explicit.stable_dt().unwrap();
        assert!(acoustic < 0.1 * front, "{acoustic:e}");
    }

    /// At 10 MPa a surface cell holding 1.6 × 10⁻⁴ of reactant burns to
    /// 10⁻⁶ of that in one step while the cell is compressed: with the
    /// whole reactant's share of the compression left on what remained,
    /// its volume went negative and the run stopped at 0.25 µs. The burnt
    /// share now takes its part of the volume change to the product, and
    /// the slab burns past its first cell.
    #[test]
    fn a_cell_burnt_out_under_compression_keeps_a_positive_volume() {
        let mut cfg = BurnRate::pbx_9501(1.0e7, BurnSurface::Plane);
        cfg.regress_cells = 1.5;
        let r = burn_rate(&cfg).unwrap();
        assert!(r.error().abs() < 0.05, "{r:?}");
    }
}
