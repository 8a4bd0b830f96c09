//! The end-of-run summary (`summary.json`).

use std::path::Path;

use brisance_core::ConservationTotals;
use serde::{Deserialize, Serialize};

use crate::atomic::write_atomic;
use crate::IoError;

/// What a finished (or stopped) run reports about itself.
///
/// Non-finite numbers (e.g. a relative change from a zero initial total)
/// are written by JSON as `null`, which [`read_summary`] rejects.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct RunSummary {
    /// Name of the scenario that was run.
    pub scenario: String,
    /// Name of the solver pipeline that ran it.
    pub pipeline: String,
    /// Number of time steps taken.
    pub steps: u64,
    /// Simulation time reached, s.
    pub final_time: f64,
    /// Wall-clock time of the run, s.
    pub wall_seconds: f64,
    /// Work per wall-clock second, in `throughput_unit`.
    pub throughput: f64,
    /// Unit of `throughput`, e.g. `cell-updates/s`.
    pub throughput_unit: String,
    /// Conserved totals at the start of the run.
    pub initial_totals: ConservationTotals,
    /// Conserved totals at the end of the run.
    pub final_totals: ConservationTotals,
    /// [`relative_change`] of the total mass.
    pub relative_mass_change: f64,
    /// [`relative_change`] of the total energy.
    pub relative_energy_change: f64,
    /// Number of worker threads used.
    pub threads: usize,
    /// Whether the run reached its end time.
    pub completed: bool,
    /// Why the run stopped early, when it did.
    pub stop_reason: Option<String>,
    /// What left through the open boundaries over the run (a part of
    /// `final_totals`), where the solver books it.
    #[serde(default)]
    pub outflow: Option<ConservationTotals>,
    /// Wall seconds in each named part of a method made of several (e.g.
    /// `fdm` and `mpm` of the bridge), and on several MPI ranks the time
    /// in MPI calls of the rank that spent most there; empty for a method
    /// with one part on one rank.
    #[serde(default)]
    pub wall_split: Vec<WallPart>,
    /// How often each safeguard of the method acted (e.g. the FDM's
    /// positivity limiter); empty for a method without one.
    #[serde(default)]
    pub safeguards: Vec<Safeguard>,
    /// The steps the run took and what set the last one; absent in a
    /// run that took no step.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub time_step: Option<TimeStepSummary>,
    /// What the run warned of (a one-way open face that held back an
    /// inflow, for instance), in the order it happened; left out of the
    /// file when there is none.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub warnings: Vec<String>,
}

/// How often one safeguard of a method acted over a run.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Safeguard {
    /// What acted, e.g. `positivity limiter`.
    pub name: String,
    /// What it counts, e.g. `faces`.
    pub unit: String,
    /// How many it changed.
    pub acted: u64,
    /// How many it checked.
    pub checked: u64,
}

/// The time steps of a run: where a step collapsed, and what set it.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct TimeStepSummary {
    /// The first step, s.
    pub first: f64,
    /// The smallest step, s (output times cut a step short too).
    pub smallest: f64,
    /// The time at the start of the smallest step, s.
    pub smallest_at: f64,
    /// The last step, s.
    pub last: f64,
    /// What sets the stable step at the end of the run, in the method's
    /// words (`Solver::time_step_limit`), where it says.
    pub limit: Option<String>,
}

/// Wall-clock seconds one named part of a coupled method took.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct WallPart {
    /// The part's name, e.g. `fdm`.
    pub part: String,
    /// Wall-clock seconds spent in it, s.
    pub seconds: f64,
}

/// `(final_ - initial) / |initial|`; 0 when both are 0 (and ±infinity when
/// only `initial` is 0).
pub fn relative_change(initial: f64, final_: f64) -> f64 {
    if initial == 0.0 && final_ == 0.0 {
        0.0
    } else {
        (final_ - initial) / initial.abs()
    }
}

/// Writes `summary` to `path` as pretty-printed JSON (atomically).
pub fn write_summary(path: &Path, summary: &RunSummary) -> Result<(), IoError> {
    let mut text =
        serde_json::to_string_pretty(summary).map_err(|e| IoError::encode(path, e.to_string()))?;
    text.push('\n');
    write_atomic(path, text.as_bytes())
}

/// Reads a summary written by [`write_summary`].
pub fn read_summary(path: &Path) -> Result<RunSummary, IoError> {
    let bytes = std::fs::read(path).map_err(|e| IoError::read(path, e))?;
    serde_json::from_slice(&bytes)
        .map_err(|e| IoError::malformed(path, "Brisance run summary", e.to_string()))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sample() -> RunSummary {
        let initial = ConservationTotals {
            mass: 2.0,
            momentum: [0.0; 3],
            energy: 1.0e6,
        };
        let final_ = ConservationTotals {
            mass: 2.0 + 1e-12,
            momentum: [0.1 + 0.2, 0.0, -1e-300],
            energy: 0.999e6,
        };
        RunSummary {
            scenario: "sphere_in_air".to_string(),
            pipeline: "fdm-euler".to_string(),
            steps: 1234,
            final_time: 1e-3,
            wall_seconds: 12.5,
            throughput: 3.2e7,
            throughput_unit: "cell-updates/s".to_string(),
            initial_totals: initial,
            final_totals: final_,
            relative_mass_change: relative_change(initial.mass, final_.mass),
            relative_energy_change: relative_change(initial.energy, final_.energy),
            threads: 2,
            completed: false,
            stop_reason: Some("wall-clock limit".to_string()),
            outflow: Some(ConservationTotals {
                mass: 0.25,
                momentum: [1.0, 0.0, 0.0],
                energy: 3.0e4,
            }),
            safeguards: vec![Safeguard {
                name: "positivity limiter".to_string(),
                unit: "faces".to_string(),
                acted: 12,
                checked: 123_456,
            }],
            wall_split: vec![
                WallPart {
                    part: "fdm".to_string(),
                    seconds: 4.25,
                },
                WallPart {
                    part: "mpm".to_string(),
                    seconds: 8.0,
                },
            ],
            time_step: Some(TimeStepSummary {
                first: 2.5e-7,
                smallest: 1.0e-9,
                smallest_at: 7.5e-4,
                last: 3.0e-8,
                limit: Some("MPM particle 7 (material 0, ideal gas)".to_string()),
            }),
            warnings: vec!["x_low held back an inflow".to_string()],
        }
    }

    #[test]
    fn relative_change_is_signed_and_scaled_by_initial_magnitude() {
        assert_eq!(relative_change(2.0, 3.0), 0.5);
        assert_eq!(relative_change(-2.0, -3.0), -0.5);
        assert_eq!(relative_change(4.0, 3.0), -0.25);
        assert_eq!(relative_change(0.0, 0.0), 0.0);
        assert_eq!(relative_change(0.0, 1.0), f64::INFINITY);
    }

    #[test]
    fn summary_round_trips_through_pretty_json() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("summary.json");
        let summary = sample();
        write_summary(&path, &summary).unwrap();
        let text = std::fs::read_to_string(&path).unwrap();
        assert!(
            text.starts_with("{\n  \"scenario\": \"sphere_in_air\",\n"),
            "{text}"
        );
        assert!(
            text.contains("\"stop_reason\": \"wall-clock limit\""),
            "{text}"
        );
        assert!(text.contains("\"momentum\": [\n"), "{text}");
        assert_eq!(read_summary(&path).unwrap(), summary);
        assert_eq!(summary.relative_energy_change, -0.001);
    }

    #[test]
    fn a_run_without_warnings_writes_no_warnings_key() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("summary.json");
        let mut summary = sample();
        summary.warnings.clear();
        write_summary(&path, &summary).unwrap();
        let text = std::fs::read_to_string(&path).unwrap();
        assert!(!text.contains("warnings"), "{text}");
        assert_eq!(read_summary(&path).unwrap(), summary);
    }

    #[test]
    fn reading_garbage_names_the_file() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("summary.json");
        std::fs::write(&path, "{\"scenario\": 3}").unwrap();
        let err = read_summary(&path).unwrap_err();
        assert!(
            err.to_string().starts_with(&format!(
                "{} is not a valid Brisance run summary",
                path.display()
            )),
            "{err}"
        );
    }
}
