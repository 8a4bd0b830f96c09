//! Verification cases of seed 003 §2.5, shared by the unit tests (reduced)
//! and `cargo xtask validate` (full): V-OSC (temporal order, §2.5.1),
//! V-ROD (spatial convergence, eq 25) and V-IMPEDANCE (waves across a
//! material interface, §2.5.3).

use brisance_eos::MieGruneisenThermal;

use super::geometry::{Dim, Geometry};
use super::law::LatticeMaterial;
use super::model::{Integrator, MsdmError, MsdmLattice, MsdmOptions};

/// A mechanically inert EOS of density `rho` for the purely mechanical
/// cases (thermal off): 𝒢 = 1, s = 0, c₀ = `c`, P₀ = 0.
pub fn inert_eos(rho: f64, c: f64) -> MieGruneisenThermal {
    MieGruneisenThermal {
        gamma: 1.0,
        rho0: rho,
        c0: c,
        s: 0.0,
        cv: 1e-3,
        t0: 300.0,
        p0: 0.0,
    }
}

fn mechanical(integrator: Integrator) -> MsdmOptions {
    MsdmOptions {
        integrator,
        thermal: false,
        solver_tolerance: 1e-14,
        ..MsdmOptions::default()
    }
}

/// V-OSC parameters (seed 003 §2.5.1): k = 0.35 N/m, m = 1/18 kg,
/// v₀ = 0.1 m/s, x(0) = 0.
pub const OSC_K: f64 = 0.35;
/// Oscillator mass, kg.
pub const OSC_M: f64 = 1.0 / 18.0;
/// Oscillator initial velocity, m/s.
pub const OSC_V0: f64 = 0.1;

/// The harmonic oscillator as a lattice: a two-node chain (h = 1 m) whose
/// first node is held fixed; k = E h gives E = 0.35 Pa and the end node's
/// dual volume h·h²/2 = 0.5 m³ gives ρ = 1/9 kg/m³.
pub fn oscillator(integrator: Integrator) -> Result<MsdmLattice, MsdmError> {
    let geom = Geometry::new(Dim::One, [2, 1, 1], 1.0, false, |_, _, _| Some(0));
    let rho = OSC_M / 0.5;
    let mat = LatticeMaterial::elastic("oscillator", OSC_K, inert_eos(rho, (OSC_K / rho).sqrt()));
    let mut lat = MsdmLattice::new(geom, vec![mat], mechanical(integrator))?;
    let fixed = lat.geom.solid_index(0, 0, 0);
    let mass = lat.geom.solid_index(1, 0, 0);
    lat.prescribed[fixed] = true;
    lat.u[0][mass] = OSC_V0;
    Ok(lat)
}

/// √dt-weighted L2 error (√(Σ Δt eₙ²) over t ∈ (0, `t_end`]) of the
/// oscillator's displacement against v₀/ω sin ωt.
pub fn oscillator_error(integrator: Integrator, dt: f64, t_end: f64) -> Result<f64, MsdmError> {
    let mut lat = oscillator(integrator)?;
    let node = lat.geom.solid_index(1, 0, 0);
    let x0 = lat.x[0][node];
    let omega = (OSC_K / OSC_M).sqrt();
    let steps = (t_end / dt).round() as usize;
    let mut sum = 0.0;
    for n in 1..=steps {
        lat.step(dt)?;
        let t = n as f64 * dt;
        let e = (lat.x[0][node] - x0) - OSC_V0 / omega * (omega * t).sin();
        sum += dt * e * e;
    }
    Ok(sum.sqrt())
}

/// Result of one V-ROD resolution.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RodResult {
    /// Nodes in the rod.
    pub nodes: usize,
    /// |u_tip − u_exact(L)| / u_exact(L).
    pub tip_error: f64,
    /// Largest nodal |u − u_exact| / u_exact(L).
    pub nodal_error: f64,
    /// ‖u_h − u‖₂ / ‖u‖₂ over [0, L] with u_h the piecewise-linear
    /// interpolant of the nodal displacements.
    pub l2_error: f64,
    /// Newton iterations of the static solve.
    pub iterations: usize,
}

/// V-ROD (seed 003 §2.5.2, eqs 23–25): a rod of length `length`, 2ⁿ nodes,
/// left end fixed, uniform axial body force density `b` (N/m³, so f/L =
/// bA), modulus `young`. Solved statically; exact
/// u(x) = (b/E)(Lx − x²/2) = (fL/EA)(x/L − x²/2L²).
pub fn rod(n: u32, length: f64, young: f64, b: f64) -> Result<RodResult, MsdmError> {
    let nodes = 1usize << n;
    let h = length / (nodes - 1) as f64;
    let geom = Geometry::new(Dim::One, [nodes, 1, 1], h, false, |_, _, _| Some(0));
    let rho = 1000.0;
    let mat = LatticeMaterial::elastic("rod", young, inert_eos(rho, (young / rho).sqrt()));
    let mut lat = MsdmLattice::new(geom, vec![mat], mechanical(Integrator::ImplicitEuler))?;
    let first = lat.geom.solid_index(0, 0, 0);
    lat.prescribed[first] = true;
    for k in 0..nodes {
        let i = lat.geom.solid_index(k, 0, 0);
        lat.body[0][i] = b * lat.volume[i];
    }
    let iterations = lat.solve_static(5, 1e-10)?;
    let exact = |x: f64| b / young * (length * x - 0.5 * x * x);
    let tip = exact(length);
    let disp: Vec<f64> = (0..nodes)
        .map(|k| {
            let i = lat.geom.solid_index(k, 0, 0);
            lat.x[0][i] - k as f64 * h
        })
        .collect();
    let tip_error = (disp[nodes - 1] - tip).abs() / tip;
    let nodal_error = (0..nodes)
        .map(|k| (disp[k] - exact(k as f64 * h)).abs() / tip)
        .fold(0.0, f64::max);
    // Three-point Gauss on each segment: exact for the quartic (u_h − u)².
    let gp = [-(0.6f64).sqrt(), 0.0, (0.6f64).sqrt()];
    let gw = [5.0 / 9.0, 8.0 / 9.0, 5.0 / 9.0];
    let (mut num, mut den) = (0.0, 0.0);
    for k in 0..nodes - 1 {
        for (p, w) in gp.iter().zip(gw) {
            let xi = 0.5 * (1.0 + p);
            let x = (k as f64 + xi) * h;
            let uh = disp[k] * (1.0 - xi) + disp[k + 1] * xi;
            let ue = exact(x);
            num += 0.5 * h * w * (uh - ue).powi(2);
            den += 0.5 * h * w * ue * ue;
        }
    }
    Ok(RodResult {
        nodes,
        tip_error,
        nodal_error,
        l2_error: (num / den).sqrt(),
        iterations,
    })
}

/// Result of V-IMPEDANCE.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ImpedanceResult {
    /// Transmitted over incident velocity amplitude (exact 4/3).
    pub velocity_transmitted: f64,
    /// Reflected over incident velocity amplitude (exact 1/3).
    pub velocity_reflected: f64,
    /// Transmitted over incident stress amplitude (exact 2/3).
    pub stress_transmitted: f64,
    /// Reflected over incident stress amplitude (exact −1/3).
    pub stress_reflected: f64,
    /// Measured wave speed over √(E/ρ) in material 1.
    pub speed_ratio_1: f64,
    /// Measured wave speed over √(E/ρ) in material 2.
    pub speed_ratio_2: f64,
    /// Nodes in the chain.
    pub nodes: usize,
    /// Time steps taken.
    pub steps: usize,
}

/// Position of the velocity peak among nodes `range` (parabolic fit
/// through the largest sample and its neighbours), m, and its value.
fn peak(lat: &MsdmLattice, range: std::ops::Range<usize>, h: f64) -> (f64, f64) {
    let v = |k: usize| lat.u[0][lat.geom.solid_index(k, 0, 0)];
    let kmax = range
        .clone()
        .max_by(|&a, &b| v(a).total_cmp(&v(b)))
        .unwrap_or(range.start);
    if kmax == 0 || kmax + 1 >= range.end {
        return (kmax as f64 * h, v(kmax));
    }
    let (a, b, c) = (v(kmax - 1), v(kmax), v(kmax + 1));
    let den = a - 2.0 * b + c;
    let off = if den != 0.0 { 0.5 * (a - c) / den } else { 0.0 };
    ((kmax as f64 + off) * h, b - 0.25 * (a - c) * off)
}

/// V-IMPEDANCE (seed 003 §2.5.3): a chain of 12W nodes (h = 1 mm),
/// material 1 (E = 2 GPa, ρ = 2000 kg/m³) on the left half, material 2
/// (E = 1 GPa, ρ = 1000 kg/m³) on the right: the same wave speed 1000 m/s
/// and Z₁/Z₂ = 2. A right-running cos² velocity pulse of width W nodes
/// and amplitude `v0` (strain −v/c, so that it runs one way) starts at 3W,
/// with both ends free. Velocity Verlet, Δt = ½h/c, no damping.
/// Amplitudes are measured when the pulses are 2W clear of the interface,
/// speeds from the peak positions over 2W of travel in each material.
pub fn impedance(width: usize, v0: f64) -> Result<ImpedanceResult, MsdmError> {
    let h = 1.0e-3;
    let (e1, r1, e2, r2): (f64, f64, f64, f64) = (2.0e9, 2000.0, 1.0e9, 1000.0);
    let c = (e1 / r1).sqrt();
    let nodes = 12 * width;
    let interface = 6 * width;
    let geom = Geometry::new(Dim::One, [nodes, 1, 1], h, false, |k, _, _| {
        Some(u16::from(k >= interface))
    });
    let mats = vec![
        LatticeMaterial::elastic("impedance-1", e1, inert_eos(r1, c)),
        LatticeMaterial::elastic("impedance-2", e2, inert_eos(r2, c)),
    ];
    let mut lat = MsdmLattice::new(geom, mats, mechanical(Integrator::VelocityVerlet))?;
    let w = width as f64 * h;
    let centre = 3.0 * w;
    let pulse = |x: f64| -> f64 {
        let z = (x - centre) / w;
        if z.abs() < 0.5 {
            v0 * (std::f64::consts::PI * z).cos().powi(2)
        } else {
            0.0
        }
    };
    // Displacement d(x) = −(1/c) ∫ v: exact integral of the cos² profile.
    let disp = |x: f64| -> f64 {
        let z = ((x - centre) / w).clamp(-0.5, 0.5);
        let integral = v0
            * w
            * (0.5 * (z + 0.5)
                + (2.0 * std::f64::consts::PI * z).sin() / (4.0 * std::f64::consts::PI));
        -integral / c
    };
    for k in 0..nodes {
        let i = lat.geom.solid_index(k, 0, 0);
        let x = k as f64 * h;
        lat.x[0][i] = x + disp(x);
        lat.u[0][i] = pulse(x);
    }
    let stress = |lat: &MsdmLattice, k: usize| -> f64 {
        let i = lat.geom.solid_index(k, 0, 0);
        lat.spring_force(i, 0).unwrap_or(0.0) / (h * h)
    };
    let sigma_inc = (0..nodes - 1).map(|k| stress(&lat, k)).fold(0.0, f64::min);
    let (x_a, v_inc) = peak(&lat, 0..interface, h);
    let dt = 0.5 * h / c;
    let transit = w / c; // time to cross W
    let mut steps = 0usize;
    let mut run_to = |lat: &mut MsdmLattice, t: f64| -> Result<(), MsdmError> {
        while lat.time < t - 0.5 * dt {
            lat.step(dt)?;
            steps += 1;
        }
        Ok(())
    };
    run_to(&mut lat, 2.0 * transit)?;
    let (x_b, _) = peak(&lat, 0..interface, h);
    let t_b = lat.time;
    run_to(&mut lat, 5.0 * transit)?;
    let t_c = lat.time;
    let (x_c, v_tr) = peak(&lat, interface..nodes, h);
    let (_, v_re) = peak(&lat, 0..interface, h);
    let s_tr = (interface..nodes - 1)
        .map(|k| stress(&lat, k))
        .fold(0.0, f64::min);
    let s_re = (0..interface - 1)
        .map(|k| stress(&lat, k))
        .fold(0.0, f64::max);
    run_to(&mut lat, 7.0 * transit)?;
    let (x_d, _) = peak(&lat, interface..nodes, h);
    let t_d = lat.time;
    Ok(ImpedanceResult {
        velocity_transmitted: v_tr / v_inc,
        velocity_reflected: v_re / v_inc,
        stress_transmitted: s_tr / sigma_inc,
        stress_reflected: s_re / sigma_inc,
        speed_ratio_1: (x_b - x_a) / t_b / c,
        speed_ratio_2: (x_d - x_c) / (t_d - t_c) / c,
        nodes,
        steps,
    })
}
