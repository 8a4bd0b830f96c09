//! What the 3D and (r, z) bridge cases with a bare spherical TNT charge
//! share (E-PLATE, [`crate::plate`]; E-SLAB in the validation tool): the
//! charge's radius and remap time, the 1D spherical detonation remapped
//! onto the FDM region (what `brisance remap` does,
//! docs/physics/couple/remap.md), and the step loop that samples a case
//! built from its config through the composer as it goes, with its wall
//! time and memory.

use std::path::Path;
use std::time::Instant;

use brisance_compose::build::build_solver;
use brisance_compose::load_file;
use brisance_core::Solver;

/// TNT density, kg/m³ (configs/materials/tnt.ron).
const TNT_DENSITY: f64 = 1630.0;
/// TNT detonation velocity, m/s (configs/materials/tnt.ron).
const TNT_DETONATION_VELOCITY: f64 = 6930.0;

/// Radius of a bare spherical charge of `mass` kg TNT, m.
pub fn charge_radius(mass: f64) -> f64 {
    (3.0 * mass / (4.0 * std::f64::consts::PI * TNT_DENSITY)).cbrt()
}

/// Time of the remap after initiation: the burn of a centre-initiated
/// sphere is complete at r_c / D; `margin` after that, s.
pub fn remap_time(mass: f64, margin: f64) -> f64 {
    charge_radius(mass) / TNT_DETONATION_VELOCITY + margin
}

/// A 1D spherical TNT detonation with program burn (`DetonationSetup::tnt_in_air`)
/// run to `time` and remapped onto a uniform grid within `radius` of the
/// origin.
pub struct SphericalRemap {
    pub charge_radius: f64,
    pub time: f64,
    /// Outer radius of the 1D run, m, and its cells.
    pub radius_1d: f64,
    pub cells_1d: usize,
    /// The FDM region and its cells.
    pub lower: [f64; 3],
    pub upper: [f64; 3],
    pub cells: [usize; 3],
    pub radius: f64,
    /// Cartesian, or an (r, z) grid of rings with the charge on its axis.
    pub coordinates: brisance_core::Geometry,
}

impl SphericalRemap {
    /// Runs the detonation, remaps it and writes `remap.bin` into `out`;
    /// returns the line "relative change: mass …, energy …, products …"
    /// of the charge's totals over the remap.
    pub fn write(&self, out: &Path) -> Result<String, String> {
        use brisance_couple::remap::{remap, RadialProfile, RemapTarget};
        use brisance_fdm::detonation::{DetonationSetup, RadialDetonation, Symmetry};
        let setup = DetonationSetup::tnt_in_air(
            Symmetry::Spherical,
            self.charge_radius,
            self.radius_1d,
            self.cells_1d,
        );
        let mut run = RadialDetonation::new(setup).map_err(|e| e.to_string())?;
        run.run_until(self.time).map_err(|e| e.to_string())?;
        let profile = RadialProfile::from_detonation(&run).map_err(|e| e.to_string())?;
        let (lower, upper, cells) = (self.lower, self.upper, self.cells);
        let target = RemapTarget {
            geometry: brisance_core::UniformGridGeometry {
                origin: lower,
                spacing: std::array::from_fn(|d| (upper[d] - lower[d]) / cells[d] as f64),
                cells,
            },
            centre: [0.0; 3],
            radius: Some(self.radius),
            subsamples: None,
            coordinates: self.coordinates,
        };
        let mapped = remap(&profile, &target).map_err(|e| e.to_string())?;
        std::fs::create_dir_all(out)
            .map_err(|e| format!("cannot create {}: {e}", out.display()))?;
        mapped
            .save(&out.join("remap.bin"))
            .map_err(|e| e.to_string())?;
        let r = mapped.report;
        let rel = |grid: f64, amb: f64, charge: f64| (grid - amb - charge) / charge;
        Ok(format!(
            "relative change: mass {:.3e}, energy {:.3e}, products {:.3e}",
            rel(r.grid_mass, r.ambient.mass, r.charge.mass),
            rel(r.grid_energy, r.ambient.energy, r.charge.energy),
            rel(r.grid_products, r.ambient.products, r.charge.products),
        ))
    }
}

/// A case's solver built from its config, stepped by [`CaseRun::step`].
pub struct CaseRun {
    pub solver: Box<dyn Solver>,
    end: f64,
    max_steps: u64,
    pub steps: u64,
    /// Why the run stopped early (a solver error), if it did.
    pub stop: Option<String>,
    start: Instant,
    rss0: Option<f64>,
    peak: CasePeak,
}

/// What [`CaseRun::finish`] measured.
pub struct Finished {
    pub final_time: f64,
    /// Wall time of the build and the steps, s.
    pub wall: f64,
    pub split: Vec<(&'static str, f64)>,
    pub resident_growth: Option<f64>,
    pub peak_resident: Option<f64>,
}

impl CaseRun {
    /// Loads `config` (relative to `root`) with the `sets` overrides,
    /// creates `out` and builds the solver; the wall clock and the
    /// resident-memory baseline and peak start here.
    pub fn build(root: &Path, config: &str, sets: &[String], out: &Path) -> Result<Self, String> {
        let loaded = load_file(&root.join(config), sets)
            .map_err(|e| format!("{config} does not load: {e}"))?;
        std::fs::create_dir_all(out)
            .map_err(|e| format!("cannot create {}: {e}", out.display()))?;
        // The case's own peak, not the process's so far.
        let peak = CasePeak::start();
        let rss0 = resident_bytes();
        let start = Instant::now();
        let solver = build_solver(&loaded.scenario).map_err(|e| loaded.locate(e).to_string())?;
        Ok(Self {
            solver,
            end: loaded.scenario.time.end,
            max_steps: loaded.scenario.time.max_steps.unwrap_or(u64::MAX),
            steps: 0,
            stop: None,
            start,
            rss0,
            peak,
        })
    }

    /// Seconds since [`CaseRun::build`] started.
    pub fn elapsed(&self) -> f64 {
        self.start.elapsed().as_secs_f64()
    }

    /// Steps at the solver's stable Δt up to the config's end time or step
    /// limit, calling `each(solver, steps, seconds since the build)` after
    /// every `every` steps; it returns whether to stop. A solver error ends the loop and is kept
    /// in [`CaseRun::stop`]; an error of `each` is returned.
    pub fn step<E>(
        &mut self,
        every: u64,
        mut each: impl FnMut(&dyn Solver, u64, f64) -> Result<bool, E>,
    ) -> Result<(), E> {
        while self.solver.time() < self.end && self.steps < self.max_steps {
            let dt = match self.solver.stable_dt() {
                Ok(dt) => dt.min(self.end - self.solver.time()),
                Err(e) => {
                    self.stop = Some(e.to_string());
                    break;
                }
            };
            if let Err(e) = self.solver.advance(dt) {
                self.stop = Some(e.to_string());
                break;
            }
            self.steps += 1;
            if self.steps.is_multiple_of(every)
                && each(self.solver.as_ref(), self.steps, self.elapsed())?
            {
                break;
            }
        }
        Ok(())
    }

    /// Measures the run (`wall`: the build and the steps, as the caller
    /// took it with [`CaseRun::elapsed`] before its own end-of-run
    /// sampling) and writes the solver's end-of-run outputs into `out`.
    pub fn finish(&mut self, out: &Path, wall: f64) -> Result<Finished, String> {
        let resident_growth = match (self.rss0, resident_bytes()) {
            (Some(a), Some(b)) => Some(b - a),
            _ => None,
        };
        self.solver.finish(out).map_err(|e| e.to_string())?;
        Ok(Finished {
            final_time: self.solver.time(),
            wall,
            split: self.solver.wall_split(),
            resident_growth,
            peak_resident: self.peak.bytes(),
        })
    }
}

/// The overrides the reduced tests of a case's config use: no remap, one
/// particle per cell, the MPM started at once (activation below ambient),
/// and at most `max_steps` steps if given.
#[cfg(test)]
pub(crate) fn reduced_sets(max_steps: Option<u64>) -> Vec<String> {
    let mut sets: Vec<String> = vec![
        "pipeline.remap=None".into(),
        "pipeline.charge=None".into(),
        "pipeline.ppc=1".into(),
        "pipeline.activation_pressure=1.0e5".into(),
    ];
    if let Some(n) = max_steps {
        sets.push(format!("time.max_steps=Some({n})"));
    }
    sets
}

/// The workspace's root, where the configs are (for the tests).
#[cfg(test)]
pub(crate) fn workspace_root() -> std::path::PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// The peak resident memory of one case run in this process.
pub struct CasePeak {
    reset: bool,
}

impl CasePeak {
    /// Resets this process's peak resident memory (`VmHWM`) to its current
    /// resident set (Linux: `5` into `/proc/self/clear_refs`), so that the
    /// peak that follows is the case's.
    pub fn start() -> Self {
        Self {
            reset: std::fs::write("/proc/self/clear_refs", "5").is_ok(),
        }
    }

    /// The case's peak, bytes; `None` where the kernel refused the reset
    /// (the process's peak so far would include the cases before it) or
    /// gives no `VmHWM`.
    pub fn bytes(&self) -> Option<f64> {
        if self.reset {
            peak_resident_bytes()
        } else {
            None
        }
    }
}

/// Peak resident memory of this process since the start or the last
/// reset ([`CasePeak::start`]), bytes (Linux `VmHWM`).
pub fn peak_resident_bytes() -> Option<f64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with("VmHWM:"))?;
    let kb: f64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kb * 1024.0)
}

/// Resident memory of this process now, bytes (Linux `VmRSS`).
pub fn resident_bytes() -> Option<f64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with("VmRSS:"))?;
    let kb: f64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kb * 1024.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn charge_radius_and_remap_time_follow_the_tnt_density() {
        // (3 · 1.094 / (4π · 1630))^(1/3) = 0.0543142 m; / 6930 m/s = 7.8376 µs.
        assert!((charge_radius(1.094) - 0.054_314_2).abs() < 1e-7);
        assert!((remap_time(1.094, 0.16e-6) - (7.837_55e-6 + 0.16e-6)).abs() < 1e-10);
        // 4 kg: (3 · 4 / (4π · 1630))^(1/3) = 0.0836748 m.
        assert!((charge_radius(4.0) - 0.083_674_8).abs() < 1e-7);
    }
}
