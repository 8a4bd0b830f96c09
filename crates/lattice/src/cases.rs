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

/// Arrhenius speed of the V-REGRESS material, m/s (A = 1 kg/(m²·s),
/// Eₐ = 0, ρ₀ = 1000 kg/m³).
pub const REGRESS_SPEED: f64 = 1e-3;

/// What a V-REGRESS run measured.
#[derive(Debug, Clone, PartialEq)]
pub struct RegressResult {
    /// Solid nodes at the start.
    pub nodes: usize,
    /// Lattice spacing h, m.
    pub spacing: f64,
    /// Regression steps taken.
    pub steps: usize,
    /// Recession rate of the exposed nodes (mean normal position for the
    /// face, mean radius for the disc) between 10 % and 100 % of the run,
    /// over the Arrhenius speed.
    pub rate_ratio: f64,
    /// The same from the remaining volume.
    pub rate_ratio_volume: f64,
    /// RMS deviation of the exposed nodes from their mean (normal distance
    /// for the face, radius for the disc) at the end, m.
    pub rms: f64,
    /// Largest minus smallest of the same, m.
    pub spread: f64,
    /// Mean of the same at the end, m (face: recession along the normal;
    /// disc: radius).
    pub mean: f64,
    /// The same from the remaining volume (face: (V₀ − V)/(L h); disc:
    /// √(V/(π h))), m.
    pub mean_from_volume: f64,
    /// Exposed node positions at the start and at the end, m.
    pub surfaces: [Vec<[f64; 2]>; 2],
}

fn regress_lattice(
    geom: Geometry,
    radius: f64,
    step_fraction: f64,
    wall: impl FnMut(usize) -> bool,
) -> Result<MsdmLattice, MsdmError> {
    use super::regress::{Arrhenius, SurfaceRegression};
    let mat = LatticeMaterial::elastic("fuel", 1e9, inert_eos(1000.0, 1000.0));
    let opts = MsdmOptions {
        thermal: false,
        ..MsdmOptions::default()
    };
    let mut lat = MsdmLattice::new(geom, vec![mat], opts)?;
    lat.mechanics = false;
    let law = Arrhenius {
        pre_exponential: 1000.0 * REGRESS_SPEED,
        activation_energy: 0.0,
        catalytic_factor: 1.0,
    };
    let mut reg = SurfaceRegression::new(&lat, vec![Some(law)], radius, step_fraction)?;
    reg.set_walls(&lat, wall);
    lat.set_regression(reg)?;
    Ok(lat)
}

/// (x, y) of the exposed nodes: the surface drawn in the V-REGRESS plots.
fn exposed_positions(lat: &MsdmLattice) -> Vec<[f64; 2]> {
    exposed_nodes(lat)
        .into_iter()
        .map(|i| [lat.x[0][i], lat.x[1][i]])
        .collect()
}

/// Exposed solid nodes of a lattice with regression.
fn exposed_nodes(lat: &MsdmLattice) -> Vec<usize> {
    let reg = lat.regression.as_ref().expect("regression on");
    (0..lat.len())
        .filter(|&i| lat.geom.is_solid(i) && reg.exposed(lat, i))
        .collect()
}

fn total_volume(lat: &MsdmLattice) -> f64 {
    lat.regression
        .as_ref()
        .map_or(0.0, |r| r.remaining.iter().sum())
}

fn mean_rms_spread(v: &[f64]) -> (f64, f64, f64) {
    let n = v.len().max(1) as f64;
    let mean = v.iter().sum::<f64>() / n;
    let rms = (v.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / n).sqrt();
    let lo = v.iter().copied().fold(f64::INFINITY, f64::min);
    let hi = v.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    (mean, rms, hi - lo)
}

/// A probe reading: time and two measures.
type Probe = (f64, [f64; 2]);

/// Runs a regression to `t_end` at its stable step, recording `probe` at
/// `t1` (the first step ending at or after it); returns the steps and the
/// probe values at `t1` and at the end with their times.
fn run_regression(
    lat: &mut MsdmLattice,
    t1: f64,
    t_end: f64,
    probe: impl Fn(&MsdmLattice) -> [f64; 2],
) -> Result<(usize, [Probe; 2]), MsdmError> {
    let dt = lat.regression_dt();
    let mut first = None;
    let mut steps = 0;
    while lat.time < t_end * (1.0 - 1e-12) {
        lat.step(dt.min(t_end - lat.time))?;
        steps += 1;
        if first.is_none() && lat.time >= t1 {
            first = Some((lat.time, probe(lat)));
        }
    }
    let first = first.unwrap_or((lat.time, probe(lat)));
    Ok((steps, [first, (lat.time, probe(lat))]))
}

/// V-REGRESS, face (seed 003 §2.6, fig. 15): a square of side 1 mm and
/// `n` nodes per side rotated by 30° about the origin, only the face whose
/// normal is (−sin 30°, cos 30°) exposed to fluid (the other exterior
/// nodes are walls), regressed by half its side at 1 mm/s with the normal
/// estimated over `radius` spacings, 0.05 h per step. Surface statistics
/// over the exposed nodes more than 2h from the side walls.
pub fn regress_rotated_square(n: usize, radius: f64) -> Result<RegressResult, MsdmError> {
    regress_rotated_square_with(n, radius, 30.0, 0.05)
}

/// [`regress_rotated_square`] with the square rotated by `angle` degrees
/// (in [0, 45]) and `step_fraction` h of regression per step.
pub fn regress_rotated_square_with(
    n: usize,
    radius: f64,
    angle: f64,
    step_fraction: f64,
) -> Result<RegressResult, MsdmError> {
    if !(0.0..=45.0).contains(&angle) {
        return Err(MsdmError::Invalid(format!(
            "V-REGRESS face: angle = {angle}°, expected a value in [0, 45]"
        )));
    }
    let side = 1e-3;
    let h = side / n as f64;
    let (s, c) = (angle.to_radians().sin(), angle.to_radians().cos());
    let local = |p: [f64; 3]| [c * p[0] + s * p[1], -s * p[0] + c * p[1]];
    let normal = [-s, c];
    let origin = [-side * s - h, -h, 0.0];
    let extent = side * (s + c) + 2.0 * h;
    let nb = (extent / h).ceil() as usize + 1;
    let tol = 1e-9 * h;
    let geom = Geometry::new(Dim::Two, [nb, nb, 1], h, false, |ix, iy, _| {
        let q = local([origin[0] + ix as f64 * h, origin[1] + iy as f64 * h, 0.0]);
        (q[0] >= -tol && q[0] <= side + tol && q[1] >= -tol && q[1] <= side + tol).then_some(0)
    })
    .with_origin(origin);
    let g = geom.clone();
    let mut lat = regress_lattice(geom, radius, step_fraction, |i| {
        let q = local(g.reference_position(i));
        !(q[1] > side && q[0] >= 0.0 && q[0] <= side)
    })?;
    let nodes = (0..lat.len()).filter(|&i| lat.geom.is_solid(i)).count();
    let v0 = total_volume(&lat);
    let depth = lat.geom.out_of_plane();
    let inner = move |l: &MsdmLattice| -> Vec<f64> {
        exposed_nodes(l)
            .into_iter()
            .filter(|&i| {
                let q = local(l.geom.reference_position(i));
                q[0] >= 2.0 * h && q[0] <= side - 2.0 * h
            })
            .map(|i| normal[0] * l.x[0][i] + normal[1] * l.x[1][i])
            .collect()
    };
    let probe = move |l: &MsdmLattice| {
        [
            (v0 - total_volume(l)) / (side * depth),
            side - mean_rms_spread(&inner(l)).0,
        ]
    };
    let start = exposed_positions(&lat);
    let t_end = 0.5 * side / REGRESS_SPEED;
    let (steps, [(t1, p1), (t2, p2)]) = run_regression(&mut lat, 0.1 * t_end, t_end, probe)?;
    let (mean, rms, spread) = mean_rms_spread(&inner(&lat));
    Ok(RegressResult {
        nodes,
        spacing: h,
        steps,
        rate_ratio: (p2[1] - p1[1]) / (t2 - t1) / REGRESS_SPEED,
        rate_ratio_volume: (p2[0] - p1[0]) / (t2 - t1) / REGRESS_SPEED,
        rms,
        spread,
        // Initial face at normal distance `side` from the origin.
        mean: side - mean,
        mean_from_volume: p2[0],
        surfaces: [start, exposed_positions(&lat)],
    })
}

/// Recession rate over the Arrhenius speed of a straight front at `angle`
/// degrees (in [0, 45]) from a lattice axis under the seed's normal rule
/// (radius 1): a column's top node is a face node (normal along the axis,
/// layer h, empty after h/ṙ) or, on the fraction tan φ of the columns
/// that end in a step, a corner (diagonal normal, layer h/√2), so a
/// column drops at ṙ (1 + (√2 − 1) tan φ) while the front must drop at
/// ṙ/cos φ: (1 + (√2 − 1) tan φ)/√(1 + tan² φ). Exact at 0° and 45°,
/// largest at 22.5° (1.0824); its mean over 0–45° is 1.0548.
pub fn staircase_rate(angle: f64) -> f64 {
    let t = angle.to_radians().tan();
    (1.0 + (std::f64::consts::SQRT_2 - 1.0) * t) / (1.0 + t * t).sqrt()
}

/// V-REGRESS, disc (seed 003 §2.6, fig. 16): a disc of radius 0.5 mm and
/// `n` nodes per diameter, every exterior node fluid, regressed to half its
/// radius at 1 mm/s with the normal estimated over `radius` spacings,
/// 0.05 h per step.
pub fn regress_disc(n: usize, radius: f64) -> Result<RegressResult, MsdmError> {
    regress_disc_with(n, radius, 0.05)
}

/// [`regress_disc`] with `step_fraction` h of regression per step.
pub fn regress_disc_with(
    n: usize,
    radius: f64,
    step_fraction: f64,
) -> Result<RegressResult, MsdmError> {
    let r0 = 0.5e-3;
    let h = 2.0 * r0 / n as f64;
    let nb = n + 3;
    let origin = [
        -(nb as f64 - 1.0) * 0.5 * h,
        -(nb as f64 - 1.0) * 0.5 * h,
        0.0,
    ];
    let geom = Geometry::new(Dim::Two, [nb, nb, 1], h, false, |ix, iy, _| {
        let p = [origin[0] + ix as f64 * h, origin[1] + iy as f64 * h];
        (p[0] * p[0] + p[1] * p[1] <= r0 * r0 * (1.0 + 1e-12)).then_some(0)
    })
    .with_origin(origin);
    let mut lat = regress_lattice(geom, radius, step_fraction, |_| false)?;
    let nodes = (0..lat.len()).filter(|&i| lat.geom.is_solid(i)).count();
    let depth = lat.geom.out_of_plane();
    let radii = |l: &MsdmLattice| -> Vec<f64> {
        exposed_nodes(l)
            .into_iter()
            .map(|i| l.x[0][i].hypot(l.x[1][i]))
            .collect()
    };
    let probe = move |l: &MsdmLattice| {
        [
            (total_volume(l) / (std::f64::consts::PI * depth)).sqrt(),
            mean_rms_spread(&radii(l)).0,
        ]
    };
    let start = exposed_positions(&lat);
    let t_end = 0.5 * r0 / REGRESS_SPEED;
    let (steps, [(t1, p1), (t2, p2)]) = run_regression(&mut lat, 0.1 * t_end, t_end, probe)?;
    let (mean, rms, spread) = mean_rms_spread(&radii(&lat));
    Ok(RegressResult {
        nodes,
        spacing: h,
        steps,
        rate_ratio: (p1[1] - p2[1]) / (t2 - t1) / REGRESS_SPEED,
        rate_ratio_volume: (p1[0] - p2[0]) / (t2 - t1) / REGRESS_SPEED,
        rms,
        spread,
        mean,
        mean_from_volume: p2[0],
        surfaces: [start, exposed_positions(&lat)],
    })
}

/// Arrhenius parameters of seed 003 §3.1: AP (A, Eₐ).
pub const AP_ARRHENIUS: (f64, f64) = (5.0e6, 92_109.6);
/// Arrhenius parameters of seed 003 §3.1: HTPB (A, Eₐ).
pub const HTPB_ARRHENIUS: (f64, f64) = (3.0e4, 62_800.0);
/// Densities of AP and HTPB, kg/m³.
pub const AP_HTPB_DENSITY: (f64, f64) = (1950.0, 920.0);

/// Density of the 80 wt % AP/HTPB propellant by ideal mixing,
/// 1/(0.8/ρ_AP + 0.2/ρ_HTPB) = 1593.3 kg/m³: the ρ₀ of the regression
/// r = A exp(−Eₐ/RT) Δt/ρ₀ (seed 003 §2.4) under the reading that ρ₀ is
/// the propellant's density (see `docs/physics/lattice/validation.md`,
/// E-APHTPB: Table 1 exceeds the pure-AP speed at ρ_AP = 1950 kg/m³, which
/// no pack with the components' own densities can).
pub fn propellant_density() -> f64 {
    let (rho_ap, rho_htpb) = AP_HTPB_DENSITY;
    1.0 / (0.8 / rho_ap + 0.2 / rho_htpb)
}

/// What an E-APHTPB burn measured.
#[derive(Debug, Clone, PartialEq)]
pub struct BurnResult {
    /// Burn rate from the mean height of the remaining propellant
    /// (remaining volume over width × depth) at `times`, m/s.
    pub rate: f64,
    /// Burn rate from the mean height of the topmost solid node of each
    /// column at `times`, m/s.
    pub rate_surface: f64,
    /// AP mass fraction of the nodes.
    pub ap_mass_fraction: f64,
    /// The two times, s.
    pub times: [f64; 2],
    /// Steps taken.
    pub steps: usize,
    /// Nodes along x and y.
    pub n: [usize; 2],
    /// Material of each node of the solid block at the end (0 AP, 1 HTPB,
    /// −1 burnt), row-major from the bottom row.
    pub materials: Vec<i8>,
}

/// E-APHTPB (seed 003 ch. 3): a `side` × `side` slice of `n` × `n` nodes,
/// 200 µm AP discs at 80 wt % in HTPB (random pack `seed`), burning from the
/// top face at the surface temperature `temperature` with the catalytic
/// factor `omega` on AP, no mechanics. The mean heights are taken when the
/// AP rate would have burnt 0.2 mm and 1.2 mm (scaled to the slice).
pub fn aphtpb_burn(
    side: f64,
    n: usize,
    temperature: f64,
    omega: f64,
    seed: u64,
) -> Result<BurnResult, MsdmError> {
    aphtpb_burn_with(side, n, temperature, omega, seed, AP_HTPB_DENSITY)
}

/// [`aphtpb_burn`] with the densities (AP, HTPB) of the Arrhenius
/// regression r = A exp(−Eₐ/RT) Δt/ρ₀ given; the pack's mass fraction
/// still uses [`AP_HTPB_DENSITY`].
pub fn aphtpb_burn_with(
    side: f64,
    n: usize,
    temperature: f64,
    omega: f64,
    seed: u64,
    densities: (f64, f64),
) -> Result<BurnResult, MsdmError> {
    use super::pack::{area_fraction, node_mass_fraction, random_disc_pack};
    use super::regress::{Arrhenius, SurfaceRegression};
    let h = side / (n - 1) as f64;
    let (rho_ap, rho_htpb) = AP_HTPB_DENSITY;
    let phi = area_fraction(0.8, rho_ap, rho_htpb);
    let pack =
        random_disc_pack(side + h, side + h, 2.0e-4, phi, seed).map_err(MsdmError::Invalid)?;
    let inside = pack.rasterise(n, n, h);
    let geom = Geometry::new(Dim::Two, [n, n, 1], h, false, |ix, iy, _| {
        Some(if inside[ix + n * iy] { 0 } else { 1 })
    });
    let mats = vec![
        LatticeMaterial::elastic("ap", 20e9, inert_eos(densities.0, 2500.0)),
        LatticeMaterial::elastic("htpb", 1e9, inert_eos(densities.1, 1600.0)),
    ];
    let opts = MsdmOptions {
        thermal: false,
        initial_temperature: temperature,
        ..MsdmOptions::default()
    };
    let mut lat = MsdmLattice::new(geom, mats, opts)?;
    lat.mechanics = false;
    let ap = Arrhenius {
        pre_exponential: AP_ARRHENIUS.0,
        activation_energy: AP_ARRHENIUS.1,
        catalytic_factor: omega,
    };
    let htpb = Arrhenius {
        pre_exponential: HTPB_ARRHENIUS.0,
        activation_energy: HTPB_ARRHENIUS.1,
        catalytic_factor: 1.0,
    };
    let mut reg = SurfaceRegression::new(&lat, vec![Some(ap), Some(htpb)], 1.0, 0.05)?;
    let top = lat.geom.n[1] - 1;
    let g = lat.geom.clone();
    reg.set_walls(&lat, |i| g.coords(i)[1] != top);
    lat.set_regression(reg)?;
    // The pack's AP mass fraction at the components' own densities,
    // whatever density the regression uses.
    let ap_mass_fraction = if densities == AP_HTPB_DENSITY {
        node_mass_fraction(&lat, 0)
    } else {
        let (mut ap, mut all) = (0.0, 0.0);
        for i in 0..lat.len() {
            match lat.material_of(i) {
                Some(0) => {
                    ap += rho_ap * lat.volume[i];
                    all += rho_ap * lat.volume[i];
                }
                Some(_) => all += rho_htpb * lat.volume[i],
                None => {}
            }
        }
        ap / all
    };
    let width_depth = side * lat.geom.out_of_plane();
    let heights = |l: &MsdmLattice| -> [f64; 2] {
        let v: f64 = l
            .regression
            .as_ref()
            .map_or(0.0, |r| r.remaining.iter().sum());
        let mut tops = 0.0;
        for ix in 0..n {
            let mut y = 0.0f64;
            for iy in (0..n).rev() {
                let i = l.geom.solid_index(ix, iy, 0);
                if l.geom.is_solid(i) {
                    y = l.x[1][i];
                    break;
                }
            }
            tops += y;
        }
        [v / width_depth, tops / n as f64]
    };
    let speed = ap.speed(rho_ap, temperature);
    let t1 = 0.2 * side / 2.4 / speed;
    let t2 = 1.2 * side / 2.4 / speed;
    let (steps, [(ta, ha), (tb, hb)]) = run_regression(&mut lat, t1, t2, heights)?;
    let materials = (0..n * n)
        .map(|k| {
            let i = lat.geom.solid_index(k % n, k / n, 0);
            lat.material_of(i).map_or(-1, |m| m as i8)
        })
        .collect();
    Ok(BurnResult {
        rate: (ha[0] - hb[0]) / (tb - ta),
        rate_surface: (ha[1] - hb[1]) / (tb - ta),
        ap_mass_fraction,
        times: [ta, tb],
        steps,
        n: [n, n],
        materials,
    })
}

/// The lattice of the explicit-step throughput target (issue: ≥ 30e6
/// node-updates/s, criterion bench `lattice_step`): an Estane block
/// (seed 003 Table 2 EOS, E = 6.25 GPa, κ = 0.2 W/(m·K)) of `n` × `n`
/// nodes at h = 10 µm moving at −100 m/s along x, axial springs with the
/// perpendicular corrective force of eq 10b (E⊥ = 1 GPa) and optionally
/// the diagonal springs, explicit Euler with the energy equation.
pub fn estane_step_block(n: usize, diagonals: bool) -> Result<MsdmLattice, MsdmError> {
    let geom = Geometry::new(Dim::Two, [n, n, 1], 1.0e-5, diagonals, |_, _, _| Some(0));
    let mut mat = LatticeMaterial::elastic("estane", 6.25e9, MieGruneisenThermal::estane_seed003());
    mat.conductivity = 0.2;
    mat.perpendicular_modulus = 1.0e9;
    let mut lat = MsdmLattice::new(
        geom,
        vec![mat],
        MsdmOptions {
            integrator: Integrator::ExplicitEuler,
            ..MsdmOptions::default()
        },
    )?;
    for i in 0..lat.len() {
        if lat.geom.is_solid(i) {
            lat.u[0][i] = -100.0;
        }
    }
    Ok(lat)
}

/// V-STIFF soft springs between the held node and the stiff block.
pub const STIFF_SOFT_SPRINGS: usize = 4;
/// V-STIFF nodes in the stiff block.
pub const STIFF_BLOCK_NODES: usize = 16;
/// V-STIFF initial velocity of the block, m/s.
pub const STIFF_V0: f64 = 1.0;

/// V-STIFF: a chain (h = 1 m, ρ = 1 kg/m³, so interior nodes of 1 kg) of
/// [`STIFF_SOFT_SPRINGS`] soft springs (E = 1 Pa, k = 1 N/m, Kelvin–Voigt
/// η = 0.1 Pa·s) from a held node to a block of [`STIFF_BLOCK_NODES`]
/// stiff nodes (E = `ratio` Pa, Kelvin–Voigt η = √ratio Pa·s, which
/// critically damps the block's shortest mode: λ = −2c/m, twice). The
/// slow mode is the block oscillating on the soft springs (ω ≈
/// 1/√(4·16.5) ≈ 0.123 rad/s, period ≈ 51 s); the stiff block's modes
/// bound explicit steps (explicit Euler: Δt ≤ 2m/(2c) = 1/√ratio). The
/// initial velocity is the slow mode's quasi-static shape: a linear ramp
/// 0 → [`STIFF_V0`] along the soft springs and [`STIFF_V0`] on the block.
pub fn stiff_chain(integrator: Integrator, ratio: f64) -> Result<MsdmLattice, MsdmError> {
    let s = STIFF_SOFT_SPRINGS;
    let n = s + 1 + STIFF_BLOCK_NODES;
    let geom = Geometry::new(Dim::One, [n, 1, 1], 1.0, false, |k, _, _| {
        Some(u16::from(k > s))
    });
    let mut soft = LatticeMaterial::elastic("stiff-case soft", 1.0, inert_eos(1.0, 100.0));
    soft.damping = super::law::Damping::KelvinVoigt { viscosity: 0.1 };
    let mut stiff = LatticeMaterial::elastic(
        "stiff-case stiff",
        ratio,
        inert_eos(1.0, 100.0 * ratio.sqrt()),
    );
    stiff.damping = super::law::Damping::KelvinVoigt {
        viscosity: ratio.sqrt(),
    };
    let mut lat = MsdmLattice::new(geom, vec![soft, stiff], mechanical(integrator))?;
    for k in 0..n {
        let i = lat.geom.solid_index(k, 0, 0);
        lat.u[0][i] = STIFF_V0 * (k as f64 / s as f64).min(1.0);
    }
    lat.prescribed[lat.geom.solid_index(0, 0, 0)] = true;
    Ok(lat)
}

/// One V-STIFF run.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StiffRun {
    /// Steps taken.
    pub steps: usize,
    /// Displacement of the block's end node at `t_end`, m (non-finite or
    /// huge when the integrator is unstable).
    pub tip: f64,
    /// Largest |tip displacement| over the run, m.
    pub peak: f64,
    /// Wall time of the stepping loop, s.
    pub wall_seconds: f64,
    /// Accumulated implicit timing (zero for explicit integrators).
    pub timing: super::model::ImplicitTiming,
}

/// Runs V-STIFF ([`stiff_chain`]) with `integrator` at step `dt` to
/// `t_end` (rounded to a whole number of steps). Stops early, with a
/// non-finite `tip`, when the motion exceeds 10⁶ times the initial
/// velocity's reach v₀·t_end (an unstable explicit step).
pub fn stiff_run(
    integrator: Integrator,
    ratio: f64,
    dt: f64,
    t_end: f64,
) -> Result<StiffRun, MsdmError> {
    let mut lat = stiff_chain(integrator, ratio)?;
    let tip_node = lat
        .geom
        .solid_index(STIFF_SOFT_SPRINGS + STIFF_BLOCK_NODES, 0, 0);
    let x0 = lat.x[0][tip_node];
    let steps = (t_end / dt).round() as usize;
    let bound = 1e6 * STIFF_V0 * t_end;
    let mut peak = 0.0f64;
    let start = std::time::Instant::now();
    for _ in 0..steps {
        lat.step(dt)?;
        let d = lat.x[0][tip_node] - x0;
        peak = peak.max(d.abs());
        if !(d.abs() <= bound) {
            return Ok(StiffRun {
                steps,
                tip: f64::INFINITY,
                peak: f64::INFINITY,
                wall_seconds: start.elapsed().as_secs_f64(),
                timing: lat.implicit_timing(),
            });
        }
    }
    Ok(StiffRun {
        steps,
        tip: lat.x[0][tip_node] - x0,
        peak,
        wall_seconds: start.elapsed().as_secs_f64(),
        timing: lat.implicit_timing(),
    })
}
