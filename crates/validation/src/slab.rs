//! E-SLAB (seed 001 §5.3; Luccioni & Luege 2006): a 25 MPa
//! concrete slab, 150 mm thick, under bare spherical TNT charges 0.5 m
//! above its top face, through the 3D FDM–MPM bridge
//! (`configs/slab_{4,10}kg.ron`, docs/physics/couple/slab.md).
//!
//! For each charge the driver makes the 1D spherical detonation and its
//! remap onto the FDM region, builds the bridge from the config (the
//! 2 and 20 kg runs are the 4 kg config with their own remap), advances it
//! to the config's end time and measures on the particles:
//!
//! - the crushing diameter: the concrete particles that started in the top
//!   face layer (within [`FACE_LAYER`] particle spacings of the top face;
//!   followed by identity, so the layer does not empty as the face is
//!   pushed down) binned by their initial distance from the charge's axis,
//!   one particle spacing per ring; the crushed zone is the rings, counted
//!   from the axis, in which at least half the particles are crushed (HJC
//!   damage D reached 1 under compression, [`DamageOnset`]); its
//!   diameter is twice the outer radius of the last such ring
//!   ([`crushing_diameter`]). The diameter of a disc with the area of all
//!   crushed top-face particles is reported beside it;
//! - the back-face tensile damage map: particles of the initial bottom
//!   layer with D_t ≥ 1 and below, drawn with the top face's in
//!   `docs/img/e_slab_faces.png`.
//!
//! Both are compared with the test (250 and 300 mm for 4 and 10 kg) and
//! with seed 001 eq 67, ln(3.63 D/h) = 0.1838 W^{1/3}/h, within 20 %.
//!
//! `cargo xtask validate --only slab` runs the charges and writes their
//! report; the tests run the configs at reduced size.

use std::fmt::Write as _;
use std::path::Path;

use brisance_core::Solver;

use crate::bridge_blast::{self, CaseRun, Finished, SphericalRemap};

/// Time after the burn completes at which the 1D detonation is remapped, s.
pub const REMAP_MARGIN: f64 = 0.16e-6;
/// 1D cell size of the detonation run, m (as E-PLATE's: 0.1 mm).
pub const CELL_1D: f64 = 1.0e-4;
/// Material index of the concrete in the bridge's MPM: air 0, products 1,
/// then the structures in name order (`concrete` only).
pub const CONCRETE: f64 = 2.0;
/// Height of the charge's centre above the slab's top face, m.
pub const HEIGHT: f64 = 0.5;
/// The slab's top face (z, m) in the configs: the charge centre is the
/// origin.
pub const TOP: f64 = 0.5;
/// The slab's back face, m (150 mm thick).
pub const BACK: f64 = 0.65;
/// Cell size of the configs, m.
pub const CELL: f64 = 0.01;
/// Particles per cell per direction of the configs.
pub const PPC: f64 = 2.0;
/// Particle spacing, m.
pub const SPACING: f64 = CELL / PPC;
/// Depth of a face layer, in particle spacings: the top two (bottom two)
/// layers of particles.
pub const FACE_LAYER: f64 = 2.0;
/// Radius about the axis within which failed face particles count toward
/// the area diameter, m: beyond eq 67's largest crushing radius (187 mm at
/// 20 kg), short of the cut edges of the modelled slab (400 mm).
pub const AREA_RADIUS: f64 = 0.2;
/// Steps between two samples of the crushing diameter.
pub const SAMPLE_EVERY: u64 = 5;
/// Relative tolerance on the crushing diameter, stated before the runs.
pub const TOLERANCE: f64 = 0.20;
/// FDM region of the configs and its cells (the remap's grid).
pub const FDM_LOWER: [f64; 3] = [0.0, 0.0, -0.18];
pub const FDM_UPPER: [f64; 3] = [0.4, 0.4, 0.46];
pub const FDM_CELLS: [usize; 3] = [40, 40, 64];

/// Seed 001 eq 67 (Luccioni & Luege 2006): the crushing diameter D, m, of
/// a charge of W kg TNT at height h, m: ln(3.63 D/h) = 0.1838 W^{1/3}/h.
pub fn eq67_diameter(charge: f64, height: f64) -> f64 {
    height / 3.63 * (0.1838 * charge.cbrt() / height).exp()
}

/// One charge of E-SLAB.
#[derive(Debug, Clone, Copy)]
pub struct SlabCase {
    /// Charge mass, kg TNT.
    pub charge: f64,
    /// Measured crushing diameter, m (the 4 and 10 kg tests).
    pub experiment: Option<f64>,
    /// The config the run starts from.
    pub config: &'static str,
}

impl SlabCase {
    /// Radius of the bare spherical charge, m.
    pub fn charge_radius(&self) -> f64 {
        bridge_blast::charge_radius(self.charge)
    }

    /// Time of the remap after initiation: the burn of a centre-initiated
    /// sphere is complete at r_c / D, s.
    pub fn remap_time(&self) -> f64 {
        bridge_blast::remap_time(self.charge, REMAP_MARGIN)
    }

    /// Outer radius of the 1D run, m: 1.5 r_c.
    pub fn radius_1d(&self) -> f64 {
        1.5 * self.charge_radius()
    }

    /// Radius within which the 1D state is remapped, m: 1.1 r_c + 2 mm,
    /// beyond the air shock at the remap time (it has moved about 1.5 mm
    /// past r_c in the 0.16 µs; E-PLATE: 55.5 mm for r_c = 54.3 mm).
    pub fn remap_radius(&self) -> f64 {
        1.1 * self.charge_radius() + 0.002
    }

    pub fn label(&self) -> String {
        format!("{} kg", self.charge)
    }

    pub fn slug(&self) -> String {
        format!("{}kg", self.charge)
    }
}

/// The charges of seed 001 §5.3 (Fig. 15): the two tests and the two
/// extra runs of the seed.
pub const SLAB_CASES: [SlabCase; 4] = [
    SlabCase {
        charge: 2.0,
        experiment: None,
        config: "configs/slab_4kg.ron",
    },
    SlabCase {
        charge: 4.0,
        experiment: Some(0.25),
        config: "configs/slab_4kg.ron",
    },
    SlabCase {
        charge: 10.0,
        experiment: Some(0.30),
        config: "configs/slab_10kg.ron",
    },
    SlabCase {
        charge: 20.0,
        experiment: None,
        config: "configs/slab_4kg.ron",
    },
];

/// Makes a charge's remap (the 1D spherical detonation with program burn,
/// remapped onto the FDM region within [`SlabCase::remap_radius`]) and
/// writes `remap.bin` into `out`; returns the relative changes of the
/// charge's mass, energy and products over the remap.
pub fn make_remap(case: &SlabCase, out: &Path) -> Result<String, String> {
    let r1 = case.radius_1d();
    let cells_1d = (r1 / CELL_1D).ceil() as usize;
    let changes = SphericalRemap {
        charge_radius: case.charge_radius(),
        time: case.remap_time(),
        radius_1d: r1,
        cells_1d,
        lower: FDM_LOWER,
        upper: FDM_UPPER,
        cells: FDM_CELLS,
        radius: case.remap_radius(),
        coordinates: brisance_core::Geometry::Cartesian,
    }
    .write(out)?;
    Ok(format!(
        "1D: r_c {:.1} mm, {} cells to {:.0} mm, remapped at {:.2} µs within {:.1} mm; {changes}",
        case.charge_radius() * 1e3,
        cells_1d,
        r1 * 1e3,
        case.remap_time() * 1e6,
        case.remap_radius() * 1e3,
    ))
}

/// The crushed zone of a face layer.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Crushing {
    /// Twice the outer radius of the last ring, counted from the axis, in
    /// which at least half the layer's particles have failed, m (0 when the
    /// innermost ring has not).
    pub diameter: f64,
    /// Diameter of the full disc whose quarter has the area of the failed
    /// particles of the layer within [`AREA_RADIUS`] of the axis (each
    /// `spacing`² of face), m.
    pub area_diameter: f64,
    /// Failed particles in the layer.
    pub failed: usize,
    /// Particles in the layer.
    pub particles: usize,
}

/// The crushed zone of the layer of concrete particles (material
/// [`CONCRETE`]) with `z_lo ≤ z < z_hi`, in a quarter model about the z
/// axis: rings of width `spacing` in r = √(x² + y²); the zone runs from
/// the axis to the first ring in which fewer than half the particles have
/// failed (`failed` = 1).
pub fn crushing_diameter(
    positions: &[[f64; 3]],
    material: &[f64],
    failed: &[f64],
    z_lo: f64,
    z_hi: f64,
    spacing: f64,
) -> Crushing {
    let mut rings: Vec<(usize, usize)> = Vec::new();
    let (mut n, mut nf, mut inner) = (0usize, 0usize, 0usize);
    for ((x, m), f) in positions.iter().zip(material).zip(failed) {
        if *m != CONCRETE || !(x[2] >= z_lo && x[2] < z_hi) {
            continue;
        }
        let r = x[0].hypot(x[1]);
        let k = (r / spacing) as usize;
        if rings.len() <= k {
            rings.resize(k + 1, (0, 0));
        }
        rings[k].0 += 1;
        n += 1;
        if *f != 0.0 {
            rings[k].1 += 1;
            nf += 1;
            if r < AREA_RADIUS {
                inner += 1;
            }
        }
    }
    let crushed = rings
        .iter()
        .take_while(|(count, fails)| *count > 0 && 2 * fails >= *count)
        .count();
    Crushing {
        diameter: 2.0 * crushed as f64 * spacing,
        area_diameter: 2.0 * (4.0 * inner as f64 * spacing * spacing / std::f64::consts::PI).sqrt(),
        failed: nf,
        particles: n,
    }
}

/// One face layer for the map: (x, y, failed) of its concrete particles.
type FaceMap = Vec<(f64, f64, bool)>;

fn face_map(
    positions: &[[f64; 3]],
    material: &[f64],
    failed: &[f64],
    z_lo: f64,
    z_hi: f64,
) -> FaceMap {
    positions
        .iter()
        .zip(material)
        .zip(failed)
        .filter(|((x, m), _)| **m == CONCRETE && x[2] >= z_lo && x[2] < z_hi)
        .map(|((x, _), f)| (x[0], x[1], *f != 0.0))
        .collect()
}

/// What one charge's run measured.
pub struct SlabRun {
    pub case: SlabCase,
    /// (time, crushing diameter, failed concrete particles, mean pressure
    /// of the top layer at the axis).
    pub history: Vec<(f64, f64, usize, f64)>,
    /// Largest sampled axis pressure of the top layer, Pa, and its time.
    pub peak_pressure: (f64, f64),
    pub front: Crushing,
    pub back: Crushing,
    pub front_map: FaceMap,
    pub back_map: FaceMap,
    pub failed_total: usize,
    pub concrete_total: usize,
    pub stop: Option<String>,
    pub steps: u64,
    pub finished: Finished,
    pub remap_line: String,
}

/// The particle fields the measurement needs. Layers are selected and
/// rings drawn on each particle's *initial* position (found through its
/// identity), so a face pushed down keeps its layer; `crushed` marks the
/// particles whose HJC damage D reached 1 under compression (see
/// [`DamageOnset`]), `tensile` those whose tensile damage D_t reached 1
/// (1 or 0), `failed` the model's failed flag (any of them).
struct Sample {
    initial: Vec<[f64; 3]>,
    material: Vec<f64>,
    failed: Vec<f64>,
    crushed: Vec<f64>,
    tensile: Vec<f64>,
    pressure: Vec<f64>,
}

impl Sample {
    /// The concrete particles with the model's failed flag set.
    fn failed_concrete(&self) -> usize {
        self.material
            .iter()
            .zip(&self.failed)
            .filter(|(m, f)| **m == CONCRETE && **f != 0.0)
            .count()
    }
}

/// Per particle identity, whether its HJC damage D was first seen at 1
/// under compression (p > 0) — crushing — or not. HJC's D also grows on
/// the tension continuation of its pressure curve (ε_f = EF_min there,
/// docs/physics/constitutive/hjc.md), so D ≥ 1 alone does not tell a
/// crushed particle from one torn in tension; the pressure at the sample
/// where D is first seen at 1 (every [`SAMPLE_EVERY`] steps) does. A failed
/// particle keeps only its compressive pressure, so one that failed in
/// tension reads p = 0 there.
pub type DamageOnset = std::collections::HashMap<u32, bool>;

/// 1 for each particle whose damage D is at 1 and was first seen there
/// under compression, else 0; records the onset of each newly damaged
/// particle in `onset`.
fn crushed_flags(
    ids: &[f64],
    damage: &[f64],
    pressure: &[f64],
    onset: &mut DamageOnset,
) -> Vec<f64> {
    ids.iter()
        .zip(damage)
        .zip(pressure)
        .map(|((&i, &d), &p)| {
            let compressed = d >= 1.0 && *onset.entry(i as u32).or_insert(p > 0.0);
            f64::from(u8::from(compressed))
        })
        .collect()
}

/// Initial positions by particle identity.
type Initial = std::collections::HashMap<u32, [f64; 3]>;

/// The initial positions of the particles, by identity.
fn initial_positions(solver: &dyn Solver) -> Result<Initial, String> {
    let data = solver
        .particle_data()
        .ok_or("the bridge gives no particle data")?;
    let id = data.field("id").ok_or("particle field id missing")?;
    Ok(id
        .iter()
        .map(|&i| i as u32)
        .zip(data.positions.iter().copied())
        .collect())
}

fn sample(
    solver: &dyn Solver,
    initial: &Initial,
    onset: &mut DamageOnset,
) -> Result<Sample, String> {
    let mut data = solver
        .particle_data()
        .ok_or("the bridge gives no particle data")?;
    let mut field = |name: &str| {
        data.fields
            .iter()
            .position(|(n, _)| n == name)
            .map(|i| std::mem::take(&mut data.fields[i].1))
            .ok_or(format!("particle field {name} missing"))
    };
    let material = field("material")?;
    let failed = field("failed")?;
    let pressure = field("pressure")?;
    let at_least_one = |v: Vec<f64>| {
        v.into_iter()
            .map(|d| f64::from(u8::from(d >= 1.0)))
            .collect()
    };
    let damage = field("damage")?;
    let tensile = at_least_one(field("tensile_damage")?);
    let ids = field("id")?;
    let crushed = crushed_flags(&ids, &damage, &pressure, onset);
    // Particles made after the start (inflow air) have no initial place.
    let initial = ids
        .iter()
        .map(|&i| initial.get(&(i as u32)).copied().unwrap_or([f64::NAN; 3]))
        .collect();
    Ok(Sample {
        initial,
        material,
        failed,
        crushed,
        tensile,
        pressure,
    })
}

/// Mean pressure of the top-layer concrete particles within one cell of
/// the axis (r < [`CELL`]), Pa: the load the blast puts on the slab's
/// centre.
pub fn axis_pressure(
    positions: &[[f64; 3]],
    material: &[f64],
    pressure: &[f64],
    z_hi: f64,
    radius: f64,
) -> Option<f64> {
    let (mut sum, mut n) = (0.0, 0usize);
    for ((x, m), p) in positions.iter().zip(material).zip(pressure) {
        if *m == CONCRETE && x[2] < z_hi && x[0].hypot(x[1]) < radius {
            sum += p;
            n += 1;
        }
    }
    (n > 0).then(|| sum / n as f64)
}

fn front_of(s: &Sample) -> Crushing {
    crushing_diameter(
        &s.initial,
        &s.material,
        &s.crushed,
        f64::NEG_INFINITY,
        TOP + FACE_LAYER * SPACING,
        SPACING,
    )
}

/// Runs one charge from its config with `sets` overrides to the config's
/// end time (or a stop), sampling the crushing diameter.
pub fn run_case(
    root: &Path,
    case: &SlabCase,
    sets: &[String],
    out: &Path,
    remap_line: String,
    progress: &mut dyn FnMut(&str),
) -> Result<SlabRun, String> {
    let mut run = CaseRun::build(root, case.config, sets, out)?;
    let initial = initial_positions(run.solver.as_ref())?;
    let mut onset = DamageOnset::new();
    let mut history = vec![(0.0, 0.0, 0usize, 0.0)];
    let mut peak_pressure = (0.0f64, 0.0);
    run.step(SAMPLE_EVERY, |solver, steps, elapsed| {
        let s = sample(solver, &initial, &mut onset)?;
        let front = front_of(&s);
        let failed = s.failed_concrete();
        let p = axis_pressure(
            &s.initial,
            &s.material,
            &s.pressure,
            TOP + FACE_LAYER * SPACING,
            CELL,
        )
        .unwrap_or(f64::NAN);
        if p > peak_pressure.0 {
            peak_pressure = (p, solver.time());
        }
        history.push((solver.time(), front.diameter, failed, p));
        if steps.is_multiple_of(20 * SAMPLE_EVERY) {
            progress(&format!(
                "{}: step {steps}, t = {:.1} µs, crushing D = {:.0} mm, {failed} failed, axis p {:.1} MPa, {:.0} s",
                case.label(),
                solver.time() * 1e6,
                front.diameter * 1e3,
                p / 1e6,
                elapsed
            ));
        }
        Ok::<_, String>(false)
    })?;
    let wall = run.elapsed();
    let solver = &run.solver;
    let s = sample(solver.as_ref(), &initial, &mut onset)?;
    let front = front_of(&s);
    let back_lo = BACK - FACE_LAYER * SPACING;
    let back = crushing_diameter(
        &s.initial,
        &s.material,
        &s.tensile,
        back_lo,
        f64::INFINITY,
        SPACING,
    );
    let front_map = face_map(
        &s.initial,
        &s.material,
        &s.crushed,
        f64::NEG_INFINITY,
        TOP + FACE_LAYER * SPACING,
    );
    let back_map = face_map(&s.initial, &s.material, &s.tensile, back_lo, f64::INFINITY);
    let concrete_total = s.material.iter().filter(|m| **m == CONCRETE).count();
    let failed_total = s.failed_concrete();
    let stop = run.stop.clone();
    let finished = run
        .finish(out, wall)
        .map_err(|e| format!("{}: {e}", case.label()))?;
    let mut csv = String::from("time,crushing_diameter,failed_concrete_particles,axis_pressure\n");
    for (t, d, n, p) in &history {
        let _ = writeln!(csv, "{t:e},{d:e},{n},{p:e}");
    }
    std::fs::write(out.join("crushing.csv"), csv)
        .map_err(|e| format!("cannot write {}: {e}", out.display()))?;
    Ok(SlabRun {
        case: *case,
        history,
        peak_pressure,
        front,
        back,
        front_map,
        back_map,
        failed_total,
        concrete_total,
        stop,
        steps: run.steps,
        finished,
        remap_line,
    })
}

/// Time integral of the sampled axis pressure (trapezoids), Pa·s.
pub fn axis_impulse(history: &[(f64, f64, usize, f64)]) -> f64 {
    history
        .windows(2)
        .map(|w| 0.5 * (w[0].3 + w[1].3) * (w[1].0 - w[0].0))
        .filter(|v| v.is_finite())
        .sum()
}

#[cfg(test)]
mod tests;
