//! One-dimensional (planar, cylindrical or spherical) detonation of a
//! centrally initiated charge in air with program burn (seed 001 §4.1,
//! eqs 52–53): the fine-grid run whose result seeds the 2D/3D FDM grid.
//!
//! Seed 001 runs this 1D problem with MPM; we run it with the FDM scheme of
//! this crate (smoothing of eq 3 with the switch and η of eqs 4–5, then the
//! two-step Lax–Wendroff step) written in finite-volume form on the radial
//! grid, with products and air as two species ([`ProductsInAir`]).
//!
//! Radial finite volumes, α = 0, 1, 2 for planar, cylindrical, spherical:
//! cell i spans [r_{i−½}, r_{i+½}] = [i h, (i+1) h], face area A = r^α,
//! volume V_i = (r_{i+½}^{α+1} − r_{i−½}^{α+1})/(α+1). The update is
//! U_i ← Ū_i − (Δt/V_i)(A_{i+½}F*_{i+½} − A_{i−½}F*_{i−½}) + Δt S_i with
//! the geometric momentum source S_i = p̄_i (A_{i+½} − A_{i−½})/V_i, which
//! keeps a gas at rest and uniform pressure exactly at rest; mass, energy
//! and products mass are conserved to round-off (Σ V_i U_i). The smoothing
//! is the flux form of eq 3 with face areas,
//! Ū_i = U_i + (h/V_i)[A_{i+½}μ_{i+½}(U_{i+1} − U_i) − A_{i−½}μ_{i−½}(U_i − U_{i−1})].
//! The predictor is the planar Richtmyer half step (the geometric source
//! enters the corrector only). `docs/physics/fdm_mixture.md` documents it.
//!
//! Program burn (eqs 52–53): a charge cell at distance r from the centre
//! lights at t_L = r/D and carries p = F p_E with
//! F = min(1, max(0, (t − t_L) D/(1.5 h))), h the cell size; F stays 1 once
//! reached. Before it is lit the charge holds the ambient pressure:
//! p = F p_E + (1 − F) p_a, which differs from eq 52 by at most p_a and
//! keeps the unlit charge–air contact at rest (with p = 0 in the charge,
//! the 1-bar jump across a 1630 : 1.2 density contact drove the first air
//! cell to negative density). At a face the burn fraction is the smaller of its two cells' (the
//! mean would give the half state between an unlit charge cell and an air
//! cell half the charge's pressure). Air
//! cells have F = 1. The smoothing coefficient μ of a face is multiplied by
//! the smaller burn fraction of its two cells: before it is lit the charge
//! is inert and at rest, and smoothing across the charge–air contact would
//! otherwise carry the explosive's chemical energy into the air cells, where
//! it acts at full pressure ahead of the detonation (at 0.125 mm cells this
//! drove the first air cell to negative density).

use brisance_core::{Eos, ReactionModel, ReactionState};
use brisance_eos::{IdealGas, Jwl};
use brisance_reaction::ProgramBurnRamp;

use crate::gas::{GasLaw, ProductsInAir};
use crate::limiter::{
    density_range, density_share, face_share, is_compressive, FaceLimiter, FlowState,
};
use crate::viscosity::{adaptive_eta, face_mu, switch_theta};
use crate::FdmError;

/// Lighting time t_L = distance/D of seed 001 §4.1, s.
pub fn lighting_time(distance: f64, detonation_velocity: f64) -> f64 {
    distance / detonation_velocity
}

/// Burn fraction of seed 001 eq 53, capped at 1:
/// F = min(1, (t − t_L) D/(1.5 h)) for t > t_L, 0 before — the
/// [`ProgramBurnRamp`] reaction model, called through the
/// [`ReactionModel`] trait with t_L as the cell's detonation time.
pub fn burn_fraction(t: f64, t_light: f64, detonation_velocity: f64, h: f64) -> f64 {
    let model = ProgramBurnRamp {
        detonation_velocity,
        cell_size: h,
    };
    let state = ReactionState {
        time: t,
        detonation_time: t_light,
        surface_area_density: 0.0,
        ..ReactionState::default()
    };
    model.advance(&state, 0.0, 0.0)
}

/// Symmetry of the 1D run.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Symmetry {
    /// Slab: α = 0.
    Planar,
    /// Infinite cylinder: α = 1.
    Cylindrical,
    /// Sphere: α = 2.
    Spherical,
}

impl Symmetry {
    fn alpha(self) -> i32 {
        match self {
            Symmetry::Planar => 0,
            Symmetry::Cylindrical => 1,
            Symmetry::Spherical => 2,
        }
    }
}

/// The 1D detonation problem.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DetonationSetup {
    /// Planar, cylindrical or spherical.
    pub symmetry: Symmetry,
    /// Charge radius (half-thickness for planar), m.
    pub charge_radius: f64,
    /// Outer radius of the grid, m (outflow there).
    pub domain_radius: f64,
    /// Number of cells from the centre to `domain_radius`.
    pub cells: usize,
    /// Products law; the unreacted charge is at ρ₀ with e = E₀/ρ₀.
    pub explosive: Jwl,
    /// Detonation velocity D, m/s.
    pub detonation_velocity: f64,
    /// Ambient gas.
    pub air: IdealGas,
    /// Ambient density, kg/m³.
    pub air_density: f64,
    /// Ambient pressure, Pa.
    pub air_pressure: f64,
    /// Courant number, (0, 1].
    pub cfl: f64,
    /// The face limiter of the Lax–Wendroff step ([`crate::limiter`]),
    /// `Full` by default.
    pub limiter: FaceLimiter,
}

impl DetonationSetup {
    /// Seed 001 §4.1–4.2: TNT (ρ₀ = 1630 kg/m³, D = 6930 m/s, JWL of
    /// eq 54) in air (ρ = 1.225 kg/m³, e = 2.0685 × 10⁵ J/kg).
    pub fn tnt_in_air(
        symmetry: Symmetry,
        charge_radius: f64,
        domain_radius: f64,
        cells: usize,
    ) -> Self {
        let air = IdealGas::air();
        Self {
            symmetry,
            charge_radius,
            domain_radius,
            cells,
            explosive: Jwl::tnt(),
            detonation_velocity: 6930.0,
            air,
            air_density: 1.225,
            air_pressure: air.pressure(1.225, 2.0685e5),
            cfl: 0.8,
            limiter: FaceLimiter::Full,
        }
    }
}

/// Ghost cells on each side.
const G: usize = 2;

/// Cells beyond the last disturbed one that a step updates
/// ([`RadialDetonation::active_cells`]): more than the scheme's stencil
/// of 4, so the front never reaches the end of the active cells within a
/// step.
pub const ACTIVE_MARGIN: usize = 8;

/// A cell counts as disturbed when its density, momentum or total energy
/// differs from the ambient air's by more than this fraction of ρ_a,
/// ρ_a c_a or E_a, or it holds products above this fraction of ρ_a.
pub const AMBIENT_TOLERANCE: f64 = 1e-10;

/// The 1D detonation run: conservative (ρ, ρu, E, ρY) per cell.
#[derive(Debug, Clone)]
pub struct RadialDetonation {
    setup: DetonationSetup,
    gas: ProductsInAir<Jwl, IdealGas>,
    h: f64,
    /// Cell volumes (ghosts mirrored at the centre), per unit angle measure.
    vol: Vec<f64>,
    /// Face areas; face j is the left face of padded cell j.
    area: Vec<f64>,
    /// Effective width 2V/(A_left + A_right) of each padded cell, m.
    width: Vec<f64>,
    /// Lighting time per padded cell (−∞ for air: always burnt).
    t_light: Vec<f64>,
    u: [Vec<f64>; 4],
    ubar: [Vec<f64>; 4],
    fbar: [Vec<f64>; 4],
    fstar: [Vec<f64>; 4],
    /// Rusanov fluxes of U at the faces (positivity limiter).
    flow: [Vec<f64>; 4],
    /// First-order update plus the geometric source per cell (positivity
    /// limiter).
    low: [Vec<f64>; 4],
    /// Faces swept, and faces the face limiter changed for positivity and
    /// for the density bounds at a shock, since the start.
    faces: (u64, [u64; 2]),
    /// Velocity and sound speed per cell (face limiter).
    vel: Vec<f64>,
    sound: Vec<f64>,
    /// F* before the face limiter (for a second attempt at a step).
    fstar_saved: [Vec<f64>; 4],
    /// The updated state of a step before it is kept.
    unew: [Vec<f64>; 4],
    /// Padded index of the first cell a step does not update.
    active: usize,
    /// The ambient air: ρ_a, E_a and the momentum scale ρ_a c_a.
    ambient: (f64, f64, f64),
    burn: Vec<f64>,
    theta: Vec<f64>,
    mu: Vec<f64>,
    pbar: Vec<f64>,
    time: f64,
    steps: u64,
}

impl RadialDetonation {
    /// Builds the run; fails naming the bad field.
    pub fn new(setup: DetonationSetup) -> Result<Self, FdmError> {
        let bad = |m: String| Err(FdmError::Invalid(m));
        if setup.cells < 4 {
            return bad(format!("cells = {} must be at least 4", setup.cells));
        }
        if !(setup.charge_radius > 0.0 && setup.domain_radius > setup.charge_radius) {
            return bad(format!(
                "charge_radius = {} m and domain_radius = {} m: need 0 < charge_radius < domain_radius",
                setup.charge_radius, setup.domain_radius
            ));
        }
        if !(setup.detonation_velocity > 0.0) {
            return bad(format!(
                "detonation_velocity = {} m/s must be > 0",
                setup.detonation_velocity
            ));
        }
        if !(setup.cfl > 0.0 && setup.cfl <= 1.0) {
            return bad(format!("cfl = {} must lie in (0, 1]", setup.cfl));
        }
        if !(setup.air_density > 0.0 && setup.air_pressure > 0.0) {
            return bad("air_density and air_pressure must be > 0".into());
        }
        setup.explosive.validate().map_err(FdmError::Invalid)?;
        let gas = ProductsInAir::new(setup.explosive, setup.air).map_err(FdmError::Invalid)?;
        let n = setup.cells + 2 * G;
        let h = setup.domain_radius / setup.cells as f64;
        let a = setup.symmetry.alpha();
        // Padded cell j spans [(j − G) h, (j − G + 1) h]; ghosts left of the
        // centre are mirror images.
        let edge = |j: usize| (j as f64 - G as f64) * h;
        let area: Vec<f64> = (0..=n).map(|j| edge(j).abs().powi(a)).collect();
        let interior_vol = |i: usize| {
            let (lo, hi) = (i as f64 * h, (i + 1) as f64 * h);
            (hi.powi(a + 1) - lo.powi(a + 1)) / (a + 1) as f64
        };
        let vol: Vec<f64> = (0..n)
            .map(|j| {
                if j < G {
                    interior_vol(G - 1 - j)
                } else {
                    interior_vol(j - G)
                }
            })
            .collect();
        let width: Vec<f64> = (0..n)
            .map(|j| 2.0 * vol[j] / (area[j] + area[j + 1]))
            .collect();
        let mut u: [Vec<f64>; 4] = std::array::from_fn(|_| vec![0.0; n]);
        let mut t_light = vec![f64::NEG_INFINITY; n];
        let e_air = setup
            .air
            .specific_internal_energy(setup.air_density, setup.air_pressure)
            .map_err(|e| FdmError::Invalid(format!("air state: {e}")))?;
        // The charge fills its cells exactly: the cell the charge surface
        // cuts holds the charge's volume fraction φ of it (mass, energy and
        // products mass by volume, the rest air), so the charge mass is the
        // same at every resolution. A charge cell lights when the front
        // reaches the middle of its charge part.
        let rc = setup.charge_radius;
        let shell = |lo: f64, hi: f64| (hi.powi(a + 1) - lo.powi(a + 1)) / (a + 1) as f64;
        let rho0 = setup.explosive.rho0;
        let mut active = G;
        for j in G..n - G {
            let (lo, hi) = (edge(j), edge(j + 1));
            let phi = if hi <= rc {
                1.0
            } else if lo < rc {
                shell(lo, rc) / shell(lo, hi)
            } else {
                0.0
            };
            if phi > 0.0 {
                t_light[j] = lighting_time(0.5 * (lo + hi.min(rc)), setup.detonation_velocity);
                active = j + 1;
            }
            u[0][j] = phi * rho0 + (1.0 - phi) * setup.air_density;
            u[2][j] = phi * setup.explosive.e0 + (1.0 - phi) * setup.air_density * e_air;
            u[3][j] = phi * rho0;
        }
        let active = (active + ACTIVE_MARGIN).min(n - G);
        let z = || -> [Vec<f64>; 4] { std::array::from_fn(|_| vec![0.0; n]) };
        Ok(Self {
            setup,
            gas,
            h,
            vol,
            area,
            width,
            t_light,
            u,
            ubar: z(),
            fbar: z(),
            fstar: z(),
            flow: std::array::from_fn(|_| vec![0.0; n + 1]),
            low: z(),
            faces: (0, [0; 2]),
            vel: vec![0.0; n],
            sound: vec![0.0; n],
            fstar_saved: std::array::from_fn(|_| vec![0.0; n + 1]),
            unew: z(),
            active,
            ambient: (
                setup.air_density,
                setup.air_density * e_air,
                setup.air_density * setup.air.sound_speed(setup.air_density, e_air),
            ),
            burn: vec![1.0; n],
            theta: vec![0.0; n],
            mu: vec![0.0; n + 1],
            pbar: vec![0.0; n],
            time: 0.0,
            steps: 0,
        })
    }

    /// Time reached, s.
    pub fn time(&self) -> f64 {
        self.time
    }

    /// Steps taken.
    pub fn steps(&self) -> u64 {
        self.steps
    }

    /// Cell size h, m.
    pub fn cell_size(&self) -> f64 {
        self.h
    }

    /// The problem this run solves.
    pub fn setup(&self) -> &DetonationSetup {
        &self.setup
    }

    /// The products-in-air gas law of the run.
    pub fn gas(&self) -> &ProductsInAir<Jwl, IdealGas> {
        &self.gas
    }

    /// Conservative values (ρ, ρu_r, E, ρY) of interior cell i.
    pub fn conservative(&self, i: usize) -> [f64; 4] {
        let j = i + G;
        std::array::from_fn(|f| self.u[f][j])
    }

    /// Whether every charge cell has burnt completely (F = 1, eq 53) at the
    /// current time: t ≥ t_L + 1.5 h/D for the outermost charge cell.
    pub fn burn_complete(&self) -> bool {
        (G..self.u[0].len() - G).all(|j| self.burn_at(j, self.time) >= 1.0)
    }

    /// Cell-centre radii, m.
    pub fn radii(&self) -> Vec<f64> {
        (0..self.setup.cells)
            .map(|i| (i as f64 + 0.5) * self.h)
            .collect()
    }

    /// (ρ, u, p, Y) of interior cell i (p with the burn fraction).
    pub fn state(&self, i: usize) -> (f64, f64, f64, f64) {
        let j = i + G;
        let (rho, m, en, ry) = (self.u[0][j], self.u[1][j], self.u[2][j], self.u[3][j]);
        let y = ry / rho;
        let e = (en - 0.5 * m * m / rho) / rho;
        let f = self.burn_at(j, self.time);
        (
            rho,
            m / rho,
            self.burnt_pressure(f, self.gas.gas_pressure(rho, e, y)),
            y,
        )
    }

    /// p = F p_E + (1 − F) p_a: eq 52 with the unlit charge held at the
    /// ambient pressure p_a (in mechanical equilibrium with the air; the
    /// difference from eq 52 is at most p_a, 10⁻⁵ of the CJ pressure).
    #[inline]
    fn burnt_pressure(&self, f: f64, p_eos: f64) -> f64 {
        f * p_eos + (1.0 - f) * self.setup.air_pressure
    }

    /// Burn fraction of padded cell j at time t.
    fn burn_at(&self, j: usize, t: f64) -> f64 {
        burn_fraction(t, self.t_light[j], self.setup.detonation_velocity, self.h)
    }

    /// (mass, energy, products mass) per unit angle measure: Σ V_i U_i.
    pub fn totals(&self) -> (f64, f64, f64) {
        let mut t = (0.0, 0.0, 0.0);
        for j in G..self.u[0].len() - G {
            t.0 += self.vol[j] * self.u[0][j];
            t.1 += self.vol[j] * self.u[2][j];
            t.2 += self.vol[j] * self.u[3][j];
        }
        t
    }

    /// Δt = cfl · min w_i/(|u| + c), c of the fully burnt mixture, with
    /// the cell's effective width w_i = 2V_i/(A_{i−½} + A_{i+½}): h in
    /// planar symmetry and far from the centre, 2h/3 for the central
    /// sphere and h/2 … for the central cylinder. The first-order (Rusanov)
    /// update of a cell, which the face limiter falls back on, moves
    /// Δt(A₊ + A₋)/V of its content through its faces, and stays positive
    /// when that is at most one cell's worth (Perthame and Shu 1996, for
    /// the planar case; the central cells are where it binds).
    pub fn stable_dt(&self) -> f64 {
        let mut m = f64::INFINITY;
        for j in G..self.u[0].len() - G {
            let (rho, mom, en, ry) = (self.u[0][j], self.u[1][j], self.u[2][j], self.u[3][j]);
            let e = (en - 0.5 * mom * mom / rho) / rho;
            let c = self.gas.gas_sound_speed(rho, e, ry / rho);
            m = m.min(self.width[j] / ((mom / rho).abs() + c));
        }
        self.setup.cfl * m
    }

    /// Fills the ghosts: mirror at the centre (normal momentum negated),
    /// zero gradient at the outer radius.
    fn fill_ghosts(&mut self) {
        let n = self.u[0].len();
        for (f, v) in self.u.iter_mut().enumerate() {
            let sign = if f == 1 { -1.0 } else { 1.0 };
            for g in 0..G {
                v[G - 1 - g] = sign * v[G + g];
                v[n - G + g] = v[n - G - 1];
            }
        }
        for g in 0..G {
            self.t_light[G - 1 - g] = self.t_light[G + g];
            self.t_light[n - G + g] = self.t_light[n - G - 1];
        }
    }

    /// Flux (ρu, ρu² + p, (E + p)u, ρYu) and pressure of a state with burn
    /// fraction `f`.
    fn flux(&self, s: [f64; 4], f: f64) -> ([f64; 4], f64) {
        let inv = 1.0 / s[0];
        let v = s[1] * inv;
        let e = (s[2] - 0.5 * s[1] * v) * inv;
        let p = self.burnt_pressure(f, self.gas.gas_pressure(s[0], e, s[3] * inv));
        ([s[1], s[1] * v + p, (s[2] + p) * v, s[3] * v], p)
    }

    /// Advances by `dt`. Fails where a state turns non-physical.
    ///
    /// Only the cells up to the active end are updated: beyond it the air
    /// is still exactly at rest ([`Self::active_cells`]). With the face
    /// limiter on, the fluxes first keep the density bounds at shocks only;
    /// if an update would then leave a non-positive density or internal
    /// energy, the step's fluxes are limited again with positivity at every
    /// face, as the 2D/3D sweep does (`docs/physics/fdm.md`, "Face
    /// limiter").
    pub fn step(&mut self, dt: f64) -> Result<(), FdmError> {
        self.fill_ghosts();
        let n = self.u[0].len();
        let m = self.active;
        let t_mid = self.time + 0.5 * dt;
        let lambda = dt / self.h;
        for j in 0..n.min(m + G + 2) {
            self.burn[j] = self.burn_at(j, t_mid);
        }
        // Switch θ (eq 4) on ρ and Y, cells 1 .. m + 3.
        for j in 1..(n - 1).min(m + 4) {
            let r = &self.u[0];
            let y = |k: usize| self.u[3][k] / self.u[0][k];
            let t = switch_theta(r[j - 1], r[j], r[j + 1]);
            self.theta[j] = t.max(switch_theta(y(j - 1), y(j), y(j + 1)));
        }
        // Face coefficients μ (eqs 3, 5) for faces 2 .. m + 1 (face j: left
        // of j).
        for j in 2..(n - 1).min(m + 2) {
            let nu = |k: usize| {
                let (rho, m, en, ry) = (self.u[0][k], self.u[1][k], self.u[2][k], self.u[3][k]);
                let e = (en - 0.5 * m * m / rho) / rho;
                lambda * self.gas.gas_sound_speed(rho, e, ry / rho)
            };
            let th = self.theta[j - 2]
                .max(self.theta[j - 1])
                .max(self.theta[j])
                .max(if j + 1 < n { self.theta[j + 1] } else { 0.0 });
            // An unlit charge is inert and at rest: the smoothing acts on
            // burnt material only, scaled by the smaller burn fraction.
            let f = self.burn[j - 1].min(self.burn[j]);
            self.mu[j] = f * face_mu(adaptive_eta(0.5 * (nu(j - 1) + nu(j))), th);
        }
        // Smoothed state and its flux, cells G − 1 ..= m.
        for j in G - 1..(n - G + 1).min(m + 1) {
            let w = self.h / self.vol[j];
            let (ap, am) = (self.area[j + 1] * self.mu[j + 1], self.area[j] * self.mu[j]);
            let mut s = [0.0; 4];
            for (f, sv) in s.iter_mut().enumerate() {
                let v = &self.u[f];
                *sv = v[j] + w * (ap * (v[j + 1] - v[j]) - am * (v[j] - v[j - 1]));
                self.ubar[f][j] = *sv;
            }
            let (fl, p) = self.flux(s, self.burn[j]);
            self.pbar[j] = p;
            for (out, v) in self.fbar.iter_mut().zip(fl) {
                out[j] = v;
            }
        }
        // Richtmyer half step at faces G ..= m (face j between j − 1 and j).
        for j in G..=m {
            let s: [f64; 4] = std::array::from_fn(|f| {
                0.5 * (self.ubar[f][j - 1] + self.ubar[f][j])
                    - 0.5 * lambda * (self.fbar[f][j] - self.fbar[f][j - 1])
            });
            let (fl, _) = self.flux(s, self.burn[j - 1].min(self.burn[j]));
            for (out, v) in self.fstar.iter_mut().zip(fl) {
                out[j] = v;
            }
        }
        let limiter = self.setup.limiter;
        let mut limited = [0; 2];
        if limiter.positivity() {
            for (saved, f) in self.fstar_saved.iter_mut().zip(&self.fstar) {
                saved[G..=m].copy_from_slice(&f[G..=m]);
            }
            limited = self.limit_faces(dt, false);
        }
        let mut bad = self.update_into_new(dt);
        if bad.is_some() && limiter.positivity() {
            for (f, saved) in self.fstar.iter_mut().zip(&self.fstar_saved) {
                f[G..=m].copy_from_slice(&saved[G..=m]);
            }
            limited = self.limit_faces(dt, true);
            bad = self.update_into_new(dt);
        }
        if let Some(j) = bad {
            let (rho, mom, en) = (self.unew[0][j], self.unew[1][j], self.unew[2][j]);
            let e = (en - 0.5 * mom * mom / rho) / rho;
            return Err(FdmError::Invalid(format!(
                "1D detonation: cell {} (r = {:e} m) has density {rho:e} and specific energy {e:e} at t = {:e} s",
                j - G,
                (j - G) as f64 * self.h + 0.5 * self.h,
                self.time
            )));
        }
        for (u, new) in self.u.iter_mut().zip(&self.unew) {
            u[G..m].copy_from_slice(&new[G..m]);
        }
        self.faces.0 += (m - G + 1) as u64;
        for (total, add) in self.faces.1.iter_mut().zip(limited) {
            *total += add;
        }
        self.extend_active();
        self.time += dt;
        self.steps += 1;
        Ok(())
    }

    /// The conservative update with the geometric pressure source of the
    /// active cells into the second buffer, ρY clipped to [0, ρ]; the
    /// first cell whose density or internal energy is not positive, if
    /// any.
    fn update_into_new(&mut self, dt: f64) -> Option<usize> {
        let mut bad = None;
        for j in G..self.active {
            let k = dt / self.vol[j];
            let (ap, am) = (self.area[j + 1], self.area[j]);
            for f in 0..4 {
                let mut v =
                    self.ubar[f][j] - k * (ap * self.fstar[f][j + 1] - am * self.fstar[f][j]);
                if f == 1 {
                    v += k * self.pbar[j] * (ap - am);
                }
                self.unew[f][j] = v;
            }
            let rho = self.unew[0][j];
            self.unew[3][j] = self.unew[3][j].clamp(0.0, rho.max(0.0));
            let (m, en) = (self.unew[1][j], self.unew[2][j]);
            let q2 = 2.0 * rho * en - m * m;
            if bad.is_none() && !(rho > 0.0 && q2 > 0.0 && q2 < f64::INFINITY) {
                bad = Some(j);
            }
        }
        bad
    }

    /// Cells updated by a step (padded index of the first one not updated):
    /// every cell up to [`ACTIVE_MARGIN`] cells beyond the last one that
    /// differs from the ambient air by more than [`AMBIENT_TOLERANCE`].
    /// The cells beyond are exactly the ambient state; the scheme's stencil
    /// reaches 4 cells, so updating them would only add round-off and the
    /// exponentially small precursor of the Lax–Wendroff step ahead of the
    /// shock. The grid out to many times the charge radius then costs
    /// only what the blast has reached.
    pub fn active_cells(&self) -> usize {
        self.active - G
    }

    /// Moves the active end out to [`ACTIVE_MARGIN`] cells beyond the last
    /// cell that differs from the ambient air.
    fn extend_active(&mut self) {
        let n = self.u[0].len();
        let last = (G..self.active).rev().find(|&j| self.disturbed(j));
        if let Some(j) = last {
            self.active = self.active.max((j + 1 + ACTIVE_MARGIN).min(n - G));
        }
    }

    /// Whether padded cell j differs from the ambient air by more than
    /// [`AMBIENT_TOLERANCE`] (relative to ρ_a, ρ_a c_a and E_a).
    fn disturbed(&self, j: usize) -> bool {
        let (rho_a, e_a, mom_a) = self.ambient;
        let tol = AMBIENT_TOLERANCE;
        (self.u[0][j] - rho_a).abs() > tol * rho_a
            || self.u[1][j].abs() > tol * mom_a
            || (self.u[2][j] - e_a).abs() > tol * e_a
            || self.u[3][j] > tol * rho_a
    }

    /// The face limiter of [`crate::limiter`] in finite-volume form,
    /// between the Richtmyer step and the update. With the total face flux
    /// Φ_f = Δt F*_f − h μ_f (U_R − U_L) (the smoothing of eq 3 is a flux
    /// too), the update is U_i − (A₊Φ₊ − A₋Φ₋)/V_i + Δt S_i. The
    /// first-order state is B_i = U_i − (Δt/V_i)(A₊F^L₊ − A₋F^L₋) + Δt S_i
    /// with the Rusanov flux F^L of U and the same geometric source S_i;
    /// the antidiffusive flux is A_f = Φ_f − Δt F^L_f. With the weights
    /// A₊/(A₊ + A₋) and A₋/(A₊ + A₋), the update is the average of the
    /// half states B_i ∓ ((A₊ + A₋)/V_i) ℓ_f A_f, one per face, so each
    /// face's ℓ keeps its two cells within bounds: positivity, and at a
    /// compressive face the density range of each cell and its two
    /// neighbours. A face within bounds keeps F*; on the others F* becomes
    /// F* − (1 − ℓ) A_f/Δt.
    ///
    /// With `positivity` false only the density bounds are kept (the
    /// first attempt at a step); where positivity does not bind, the share
    /// is the same to the bit either way. Returns the faces changed for
    /// positivity and for the density bounds.
    fn limit_faces(&mut self, dt: f64, positivity: bool) -> [u64; 2] {
        let m = self.active;
        let bounds = self.setup.limiter.shock_bounds();
        let state = |u: &[Vec<f64>; 4], j: usize| FlowState {
            density: u[0][j],
            momentum: [u[1][j], 0.0, 0.0],
            energy: u[2][j],
        };
        // Velocity and sound speed per cell (c of the fully burnt mixture,
        // as in the time step; 0 where it is not finite).
        for j in 0..=m + 1 {
            let (rho, m, en, ry) = (self.u[0][j], self.u[1][j], self.u[2][j], self.u[3][j]);
            let e = (en - 0.5 * m * m / rho) / rho;
            let c = self.gas.gas_sound_speed(rho, e, ry / rho);
            self.vel[j] = m / rho;
            self.sound[j] = if c.is_finite() { c } else { 0.0 };
        }
        // Rusanov fluxes of U at faces G − 1 ..= m + 1 (face j: left of
        // cell j).
        for j in G - 1..=m + 1 {
            let f = self.burn[j - 1].min(self.burn[j]);
            let flux = |k: usize| self.flux(std::array::from_fn(|v| self.u[v][k]), f).0;
            let (fl, fr) = (flux(j - 1), flux(j));
            let a =
                (self.vel[j - 1].abs() + self.sound[j - 1]).max(self.vel[j].abs() + self.sound[j]);
            for v in 0..4 {
                self.flow[v][j] =
                    0.5 * (fl[v] + fr[v]) - 0.5 * a * (self.u[v][j] - self.u[v][j - 1]);
            }
        }
        // B_i for cells G − 1 ..= m.
        for j in G - 1..=m {
            let k = dt / self.vol[j];
            let (ap, am) = (self.area[j + 1], self.area[j]);
            for v in 0..4 {
                let mut b = self.u[v][j] - k * (ap * self.flow[v][j + 1] - am * self.flow[v][j]);
                if v == 1 {
                    b += k * self.pbar[j] * (ap - am);
                }
                self.low[v][j] = b;
            }
        }
        let weight = |j: usize| (self.area[j + 1] + self.area[j]) / self.vol[j];
        let range = |j: usize, low: f64| {
            let r = &self.u[0];
            density_range([r[j - 1], r[j], r[j + 1]], low)
        };
        let mut changed = [0; 2];
        for j in G..=m {
            let anti: [f64; 4] = std::array::from_fn(|v| {
                let jump = self.u[v][j] - self.u[v][j - 1];
                dt * self.fstar[v][j] - self.h * self.mu[j] * jump - dt * self.flow[v][j]
            });
            let a = FlowState {
                density: anti[0],
                momentum: [anti[1], 0.0, 0.0],
                energy: anti[2],
            };
            let (low_l, low_r) = (state(&self.low, j - 1), state(&self.low, j));
            let (wl, wr) = (weight(j - 1), weight(j));
            let positive = if positivity {
                face_share(&low_l, wl, &low_r, wr, &a)
            } else {
                1.0
            };
            let mut share = positive;
            let window = [j - 2, j - 1, j, j + 1].map(|k| self.vel[k]);
            if bounds && is_compressive(window, self.sound[j - 1].min(self.sound[j])) {
                let (lo_l, hi_l) = range(j - 1, low_l.density);
                let (lo_r, hi_r) = range(j, low_r.density);
                share = share
                    .min(density_share(low_l.density, -wl * a.density, lo_l, hi_l))
                    .min(density_share(low_r.density, wr * a.density, lo_r, hi_r));
            }
            if share < 1.0 {
                for (f, a) in self.fstar.iter_mut().zip(anti) {
                    f[j] -= (1.0 - share) * a / dt;
                }
                changed[usize::from(share < positive)] += 1;
            }
        }
        changed
    }

    /// Faces swept, and faces whose flux the face limiter changed for
    /// positivity and for the density bounds at a shock, since the start.
    pub fn limited_faces(&self) -> (u64, [u64; 2]) {
        self.faces
    }

    /// Steps until `t_end`.
    pub fn run_until(&mut self, t_end: f64) -> Result<(), FdmError> {
        while self.time < t_end {
            let dt = self.stable_dt().min(t_end - self.time);
            self.step(dt)?;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lighting_time_and_burn_fraction_are_eqs_52_53() {
        // t_L = 0.0693 m / 6930 m/s = 10 µs
        assert!((lighting_time(0.0693, 6930.0) - 1.0e-5).abs() < 1e-18);
        let (d, h) = (6930.0, 1.0e-3);
        assert_eq!(burn_fraction(0.9e-5, 1.0e-5, d, h), 0.0);
        assert_eq!(burn_fraction(1.0e-5, 1.0e-5, d, h), 0.0);
        // (t − t_L) D/(1.5h) = 1e-7 · 6930 / 1.5e-3 = 0.462
        assert!((burn_fraction(1.01e-5, 1.0e-5, d, h) - 0.462).abs() < 1e-9);
        // 1.5h/D = 216.45 ns to full burn; capped at 1 after.
        assert_eq!(burn_fraction(1.03e-5, 1.0e-5, d, h), 1.0);
    }

    #[test]
    fn gas_at_rest_stays_at_rest_in_every_symmetry() {
        // A charge of radius 1e-300 m holds no mass to speak of (none at
        // all once its volume underflows): air at rest everywhere; the
        // geometric source must balance the face pressures exactly, also in
        // the cells next to the centre.
        for sym in [Symmetry::Planar, Symmetry::Cylindrical, Symmetry::Spherical] {
            let s = DetonationSetup::tnt_in_air(sym, 1e-300, 1.0, 50);
            let mut run = RadialDetonation::new(s).unwrap();
            let dt = run.stable_dt();
            for _ in 0..20 {
                run.step(dt).unwrap();
            }
            for i in 0..50 {
                let (rho, u, p, _) = run.state(i);
                assert!(
                    (rho - 1.225).abs() < 1e-12 && u.abs() < 1e-9,
                    "{sym:?} {i}: {rho} {u}"
                );
                assert!((p - s.air_pressure).abs() < 1e-9 * p, "{sym:?} {i}: {p}");
            }
        }
    }

    #[test]
    fn spherical_tnt_detonation_conserves_and_runs_at_d() {
        // 50 mm TNT sphere, 0.5 mm cells, grid to 0.4 m.
        let setup = DetonationSetup::tnt_in_air(Symmetry::Spherical, 0.05, 0.4, 800);
        let mut run = RadialDetonation::new(setup).unwrap();
        let (m0, e0, p0) = run.totals();
        // Half the charge radius burnt: t = 25 mm / D.
        let t_half = 0.025 / 6930.0;
        run.run_until(t_half).unwrap();
        let radii = run.radii();
        let peak = (0..radii.len())
            .max_by(|&a, &b| run.state(a).2.total_cmp(&run.state(b).2))
            .unwrap();
        let p_peak = run.state(peak).2;
        eprintln!(
            "front at r = {:.2} mm (D t = 25 mm), peak pressure {:.3e} Pa",
            radii[peak] * 1e3,
            p_peak
        );
        assert!(
            (radii[peak] - 0.025).abs() < 4.0 * run.cell_size(),
            "front at {}",
            radii[peak]
        );
        // Through the charge and into the air.
        run.run_until(2.0e-5).unwrap();
        let (m1, e1, p1) = run.totals();
        assert!((m1 - m0).abs() < 1e-12 * m0, "mass {m0} → {m1}");
        assert!((e1 - e0).abs() < 1e-12 * e0, "energy {e0} → {e1}");
        eprintln!("products mass change {:e}", (p1 - p0).abs() / p0);
        assert!((p1 - p0).abs() < 1e-3 * p0);
        for i in 0..radii.len() {
            let (rho, _, p, y) = run.state(i);
            assert!(
                rho > 0.0 && p >= 0.0 && (0.0..=1.0).contains(&y),
                "cell {i}"
            );
        }
    }
    #[test]
    fn the_charge_mass_is_exact_at_any_resolution() {
        // A 52.7 mm sphere of TNT (ρ₀ = 1630 kg/m³) holds ρ₀R³/3 per
        // steradian whether or not its surface falls on a face.
        let r: f64 = 0.0527;
        let exact = 1630.0 * r.powi(3) / 3.0;
        for cells in [50, 73, 200] {
            let s = DetonationSetup::tnt_in_air(Symmetry::Spherical, r, 1.0, cells);
            let run = RadialDetonation::new(s).unwrap();
            let (_, _, products) = run.totals();
            assert!(
                (products - exact).abs() < 1e-14 * exact,
                "{cells}: {products} vs {exact}"
            );
        }
    }

    #[test]
    fn a_free_air_tnt_sphere_runs_through_its_over_expansion() {
        // 1 kg of TNT (52.7 mm) at 5 mm cells on a 4 m grid: without the
        // face limiter the run stops (the internal energy of the first
        // burning cell turns negative in the second step); with it the run
        // reaches 5 ms (the shock at 3.3 m, still inside the grid),
        // conserving mass and energy, with only cells the blast has
        // reached updated.
        let setup = DetonationSetup::tnt_in_air(Symmetry::Spherical, 0.0527, 4.0, 800);
        let mut plain = RadialDetonation::new(DetonationSetup {
            limiter: FaceLimiter::Off,
            ..setup
        })
        .unwrap();
        let err = plain.run_until(5e-3).unwrap_err().to_string();
        assert!(err.contains("specific energy"), "{err}");
        // Positivity alone acts and suffices; the full limiter keeps the
        // density bounds at the shocks (and needs no positivity limiting
        // here).
        for limiter in [FaceLimiter::Positivity, FaceLimiter::Full] {
            let mut run = RadialDetonation::new(DetonationSetup { limiter, ..setup }).unwrap();
            let (m0, e0, _) = run.totals();
            run.run_until(5e-3).unwrap();
            let (m1, e1, _) = run.totals();
            assert!(
                (m1 - m0).abs() < 1e-12 * m0,
                "{limiter:?}: mass {m0} → {m1}"
            );
            assert!(
                (e1 - e0).abs() < 1e-12 * e0,
                "{limiter:?}: energy {e0} → {e1}"
            );
            let (faces, [positivity, bounds]) = run.limited_faces();
            assert!(faces > 0);
            match limiter {
                FaceLimiter::Positivity => assert!(positivity > 0 && bounds == 0),
                _ => assert!(bounds > 0),
            }
            assert!(run.active_cells() < 800, "{}", run.active_cells());
            for i in 0..800 {
                let (rho, _, p, y) = run.state(i);
                assert!(rho > 0.0 && p > 0.0 && (0.0..=1.0).contains(&y), "cell {i}");
            }
        }
    }
}
