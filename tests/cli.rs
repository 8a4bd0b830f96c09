//! The `brisance` command line: bad input gives one clear error line
//! (file:line:column where it applies, what was expected), exit code 1, no
//! panic and nothing written; the basic commands (`run`, `check`, `list`)
//! work and a run writes its outputs under the documented names.

use std::fs;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use serde_json::Value;

const BIN: &str = env!("CARGO_BIN_EXE_brisance");
const SOD: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/configs/sod.ron");

/// The text of `configs/sod.ron`, read at test time.
fn sod_text() -> String {
    fs::read_to_string(SOD).expect("configs/sod.ron is readable")
}

/// `text` with `from` replaced by `to`, which must occur exactly once.
fn replaced(text: &str, from: &str, to: &str) -> String {
    assert_eq!(
        text.matches(from).count(),
        1,
        "`{from}` should occur once in the config"
    );
    text.replacen(from, to, 1)
}

/// The 1-based number of the (only) line of `text` containing `marker`.
fn line_of(text: &str, marker: &str) -> usize {
    let lines: Vec<usize> = text
        .lines()
        .enumerate()
        .filter(|(_, l)| l.contains(marker))
        .map(|(i, _)| i + 1)
        .collect();
    assert_eq!(lines.len(), 1, "`{marker}` should be on exactly one line");
    lines[0]
}

/// The `brisance` binary, with logging at its default level.
fn brisance() -> Command {
    let mut cmd = Command::new(BIN);
    cmd.env_remove("BRISANCE_LOG");
    cmd
}

/// Runs `brisance run <config> --out <out> --quiet <extra...>`.
fn run(config: &Path, out: &Path, extra: &[&str]) -> Output {
    brisance()
        .arg("run")
        .arg(config)
        .arg("--out")
        .arg(out)
        .arg("--quiet")
        .args(extra)
        .output()
        .expect("the brisance binary runs")
}

/// A temporary directory holding `c.ron` with `text`; returns the dir, the
/// config path and the (not yet existing) output path `<dir>/out`.
fn scenario(text: &str) -> (tempfile::TempDir, PathBuf, PathBuf) {
    let dir = tempfile::tempdir().unwrap();
    let config = dir.path().join("c.ron");
    fs::write(&config, text).unwrap();
    let out = dir.path().join("out");
    (dir, config, out)
}

fn stderr(out: &Output) -> String {
    String::from_utf8_lossy(&out.stderr).into_owned()
}

fn stdout(out: &Output) -> String {
    String::from_utf8_lossy(&out.stdout).into_owned()
}

/// Checks that the command failed cleanly: exit code 1, no panic, and
/// stderr is exactly one line starting with `error: `. Returns that line
/// without the `error: ` prefix.
fn single_error_line(out: &Output) -> String {
    let err = stderr(out);
    assert_eq!(
        out.status.code(),
        Some(1),
        "expected exit code 1; stderr:\n{err}\nstdout:\n{}",
        stdout(out)
    );
    assert!(!err.contains("panicked"), "the binary panicked:\n{err}");
    let line = err.strip_suffix('\n').unwrap_or(&err);
    assert!(
        !line.is_empty() && !line.contains('\n'),
        "expected exactly one error line, got:\n{err}"
    );
    line.strip_prefix("error: ")
        .unwrap_or_else(|| panic!("error line should start with `error: `: {line}"))
        .to_string()
}

/// Checks a located configuration error: one clean error line of the form
/// `error: <file>:<line>:<col>: <message>` with the expected line. Returns
/// the message.
fn located_error(out: &Output, file: &Path, line: usize) -> String {
    let msg = single_error_line(out);
    let prefix = format!("{}:", file.display());
    let rest = msg
        .strip_prefix(&prefix)
        .unwrap_or_else(|| panic!("error should start with `{prefix}`: {msg}"));
    let mut parts = rest.splitn(3, ':');
    let got_line: usize = parts
        .next()
        .and_then(|s| s.parse().ok())
        .unwrap_or_else(|| panic!("no line number in: {msg}"));
    let got_col: usize = parts
        .next()
        .and_then(|s| s.parse().ok())
        .unwrap_or_else(|| panic!("no column number in: {msg}"));
    let message = parts
        .next()
        .unwrap_or_else(|| panic!("no message in: {msg}"));
    assert_eq!(got_line, line, "wrong line in: {msg}");
    assert!(got_col >= 1, "column should be 1-based in: {msg}");
    message.trim().to_string()
}

/// Nothing was written: the output directory does not exist or is empty.
fn assert_nothing_written(out: &Path) {
    if out.exists() {
        let entries: Vec<_> = fs::read_dir(out).unwrap().collect();
        assert!(
            entries.is_empty(),
            "{} should be empty, holds {entries:?}",
            out.display()
        );
    }
}

fn read_json(path: &Path) -> Value {
    let text =
        fs::read_to_string(path).unwrap_or_else(|e| panic!("cannot read {}: {e}", path.display()));
    serde_json::from_str(&text).unwrap_or_else(|e| panic!("{} is not JSON: {e}", path.display()))
}

fn first_line(path: &Path) -> String {
    let text =
        fs::read_to_string(path).unwrap_or_else(|e| panic!("cannot read {}: {e}", path.display()));
    text.lines().next().unwrap_or_default().to_string()
}

/// The names of the files directly in `dir`, sorted.
fn file_names(dir: &Path) -> Vec<String> {
    let mut names: Vec<String> = fs::read_dir(dir)
        .unwrap_or_else(|e| panic!("cannot list {}: {e}", dir.display()))
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    names
}

// ---------------------------------------------------------------------------
// Bad input: one clear error line, exit code 1, nothing written.

#[test]
fn malformed_ron_is_one_located_error_saying_what_was_expected() {
    let text = replaced(&sod_text(), "end: 0.2, cfl", "end: 0.2 cfl");
    let (_dir, config, out) = scenario(&text);
    let output = run(&config, &out, &[]);
    let message = located_error(&output, &config, line_of(&text, "end: 0.2 cfl"));
    assert!(
        message.to_lowercase().contains("expected comma"),
        "{message}"
    );
    assert_nothing_written(&out);
}

#[test]
fn wrong_type_is_one_located_error_naming_the_expected_type() {
    let text = replaced(&sod_text(), "end: 0.2,", "end: \"soon\",");
    let (_dir, config, out) = scenario(&text);
    let output = run(&config, &out, &[]);
    let message = located_error(&output, &config, line_of(&text, "\"soon\""));
    assert!(message.to_lowercase().contains("float"), "{message}");
    assert_nothing_written(&out);
}

#[test]
fn check_warns_of_an_unused_material_at_its_line_and_succeeds() {
    let text = replaced(
        &sod_text(),
        "materials: {",
        "materials: {\n        \"spare\": (library: \"air\"),",
    );
    let (_dir, config, _out) = scenario(&text);
    let output = brisance().arg("check").arg(&config).output().unwrap();
    assert!(output.status.success(), "{}", stderr(&output));
    let err = stderr(&output);
    let expected = format!(
        "warning: {}:{}:",
        config.display(),
        line_of(&text, "\"spare\"")
    );
    assert!(err.starts_with(&expected), "{err}");
    assert!(
        err.contains("`materials.spare`: material `spare` is defined but nothing uses it"),
        "{err}"
    );
}

#[test]
fn a_bridge_region_with_a_renamed_material_is_one_located_error() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("configs/plate_case2.ron");
    let text = replaced(
        &fs::read_to_string(path).unwrap(),
        "\"rha\": (library",
        "\"armour\": (library",
    );
    let (_dir, config, _out) = scenario(&text);
    let output = brisance().arg("check").arg(&config).output().unwrap();
    let message = located_error(
        &output,
        &config,
        line_of(&text, "0.22)), material: \"rha\""),
    );
    assert!(message.contains("`initial.1.material`"), "{message}");
    assert!(message.contains("unknown material `rha`"), "{message}");
}

#[test]
fn unknown_eos_name_lists_the_known_ones() {
    let text = replaced(&sod_text(), "eos: IdealGas(", "eos: PerfectGas(");
    let (_dir, config, out) = scenario(&text);
    let output = run(&config, &out, &[]);
    let message = located_error(&output, &config, line_of(&text, "PerfectGas"));
    assert!(message.contains("PerfectGas"), "{message}");
    assert!(message.contains("IdealGas"), "{message}");
    assert_nothing_written(&out);
}

#[test]
fn negative_density_is_located_and_says_it_must_be_positive() {
    let text = replaced(
        &sod_text(),
        "(density: 0.125, pressure: 0.1)",
        "(density: -0.125, pressure: 0.1)",
    );
    let (_dir, config, out) = scenario(&text);
    let output = run(&config, &out, &[]);
    let message = located_error(&output, &config, line_of(&text, "density: -0.125"));
    assert!(message.contains("density"), "{message}");
    assert!(message.contains("positive"), "{message}");
    assert!(message.contains("-0.125"), "{message}");
    assert_nothing_written(&out);
}

#[test]
fn empty_domain_is_located_and_says_zero_cells() {
    let text = replaced(&sod_text(), "cells: (400, 1, 1)", "cells: (0, 1, 1)");
    let (_dir, config, out) = scenario(&text);
    let output = run(&config, &out, &[]);
    let message = located_error(&output, &config, line_of(&text, "cells: (0, 1, 1)"));
    assert!(message.contains("domain.cells"), "{message}");
    assert!(message.contains("0 cells"), "{message}");
    assert_nothing_written(&out);
}

#[test]
fn cfl_above_the_scheme_limit_is_located_and_names_the_limit() {
    let text = replaced(&sod_text(), "cfl: 0.8", "cfl: 1.5");
    let (_dir, config, out) = scenario(&text);
    let output = run(&config, &out, &[]);
    let message = located_error(&output, &config, line_of(&text, "cfl: 1.5"));
    assert!(message.contains("cfl"), "{message}");
    assert!(message.contains("1.5"), "{message}");
    assert!(message.contains("(0, 1]"), "limit 1 not named: {message}");
    assert!(message.contains("stability limit"), "{message}");
    assert_nothing_written(&out);
}

#[test]
fn unwritable_output_dir_is_one_error_naming_the_path() {
    let (dir, config, _) = scenario(&sod_text());
    let blocker = dir.path().join("afile");
    fs::write(&blocker, b"a regular file").unwrap();
    let out = blocker.join("out");
    let output = run(&config, &out, &["--set", "domain.cells=(50,1,1)"]);
    let message = single_error_line(&output);
    assert!(
        message.contains(&out.display().to_string()),
        "error should name {}: {message}",
        out.display()
    );
    assert!(blocker.is_file());
    assert_eq!(fs::read(&blocker).unwrap(), b"a regular file");
    assert_eq!(file_names(dir.path()), ["afile", "c.ron"]);
}

#[test]
fn unknown_pipeline_material_lists_the_known_materials() {
    let text = replaced(
        &sod_text(),
        "Fdm(material: \"gas\"",
        "Fdm(material: \"air\"",
    );
    let (_dir, config, out) = scenario(&text);
    let output = run(&config, &out, &[]);
    let message = located_error(&output, &config, line_of(&text, "\"air\""));
    assert!(message.contains("unknown material `air`"), "{message}");
    assert!(message.contains("known materials: `gas`"), "{message}");
    assert_nothing_written(&out);
}

#[test]
fn set_with_a_path_that_does_not_exist_names_the_path() {
    let (_dir, config, out) = scenario(&sod_text());
    // A path below a field that does not exist.
    let output = run(&config, &out, &["--set", "time.nothere.x=3"]);
    let message = single_error_line(&output);
    assert!(message.contains("time.nothere.x"), "{message}");
    assert_nothing_written(&out);
    // A misspelt field of an existing struct.
    let output = run(&config, &out, &["--set", "time.cfll=0.5"]);
    let message = single_error_line(&output);
    assert!(message.contains("cfll"), "{message}");
    assert!(message.contains("cfl"), "{message}");
    assert_nothing_written(&out);
}

// ---------------------------------------------------------------------------
// The basic commands.

#[test]
fn set_overrides_the_grid_and_the_run_completes() {
    let (_dir, config, out) = scenario(&sod_text());
    let output = run(&config, &out, &["--set", "domain.cells=(60,1,1)"]);
    assert_eq!(output.status.code(), Some(0), "{}", stderr(&output));
    assert!(!stderr(&output).contains("panicked"));
    let summary = read_json(&out.join("summary.json"));
    assert_eq!(summary["completed"], Value::Bool(true), "{summary}");
    assert!(summary["steps"].as_u64().unwrap() > 0, "{summary}");
    assert_eq!(summary["final_time"].as_f64(), Some(0.2), "{summary}");
    // The steps and what set the last one: a cell of the 60.
    let steps = &summary["time_step"];
    let (first, smallest, last) = (
        steps["first"].as_f64().unwrap(),
        steps["smallest"].as_f64().unwrap(),
        steps["last"].as_f64().unwrap(),
    );
    assert!(smallest > 0.0 && smallest <= first.min(last), "{summary}");
    let limit = steps["limit"].as_str().unwrap();
    assert!(limit.starts_with("FDM cell ["), "{limit}");
    let text = stdout(&output);
    assert!(text.contains("  time step: first "), "{text}");
    assert!(
        text.contains(&format!("  last step set by: {limit}")),
        "{text}"
    );
    // The field files hold 60 cells along x.
    let vti = fs::read_to_string(out.join("vtk").join("sod_00000.vti")).unwrap();
    assert!(
        vti.contains("WholeExtent=\"0 60 0 1 0 1\""),
        "not a 60-cell grid: {}",
        &vti[..vti.len().min(300)]
    );
}

#[test]
fn check_prints_the_resolved_pipeline() {
    let output = brisance().arg("check").arg(SOD).output().unwrap();
    assert_eq!(output.status.code(), Some(0), "{}", stderr(&output));
    let text = stdout(&output);
    assert!(text.contains("ok"), "{text}");
    assert!(text.contains("Fdm"), "{text}");
    assert!(text.contains("400 x 1 x 1"), "{text}");
    assert!(text.contains("IdealGas"), "{text}");
}

#[test]
fn check_of_a_bad_file_fails_with_a_located_error() {
    let text = replaced(&sod_text(), "cfl: 0.8", "cfl: 2.0");
    let (_dir, config, _) = scenario(&text);
    let output = brisance().arg("check").arg(&config).output().unwrap();
    let message = located_error(&output, &config, line_of(&text, "cfl: 2.0"));
    assert!(message.contains("cfl"), "{message}");
    assert!(stdout(&output).is_empty(), "{}", stdout(&output));
}

#[test]
fn list_names_the_equations_of_state_and_pipelines() {
    let output = brisance().arg("list").output().unwrap();
    assert_eq!(output.status.code(), Some(0), "{}", stderr(&output));
    let text = stdout(&output);
    assert!(text.contains("IdealGas"), "{text}");
    assert!(text.contains("Fdm"), "{text}");
    // A plugin crate's model, with the docs page it registered.
    assert!(text.contains("NobleAbel"), "{text}");
    assert!(
        text.contains("docs: docs/physics/eos/noble_abel.md"),
        "{text}"
    );
    // And a plugin crate's constitutive model, under the constitutive
    // models.
    let materials = text
        .split("constitutive models (material):")
        .nth(1)
        .and_then(|rest| rest.split("reaction models").next())
        .unwrap_or_else(|| panic!("no constitutive models section:\n{text}"));
    assert!(materials.contains("SteinbergGuinan"), "{text}");
    assert!(
        materials.contains("docs: docs/physics/constitutive/steinberg_guinan.md"),
        "{text}"
    );
}

#[test]
fn the_noble_abel_shock_tube_checks_and_runs() {
    let config = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/configs/noble_abel_shock_tube.ron"
    );
    let output = brisance().arg("check").arg(config).output().unwrap();
    assert_eq!(output.status.code(), Some(0), "{}", stderr(&output));
    assert!(
        stdout(&output).contains("(NobleAbel)"),
        "{}",
        stdout(&output)
    );
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    let output = run(std::path::Path::new(config), &out, &[]);
    assert_eq!(output.status.code(), Some(0), "{}", stderr(&output));
    assert!(out.join("summary.json").is_file());
}

#[test]
fn run_without_a_config_runs_the_built_in_default_scenario() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    let output = brisance()
        .current_dir(dir.path())
        .arg("run")
        .arg("--out")
        .arg(&out)
        .arg("--quiet")
        .args(["--set", "time.end=2e-6"])
        .output()
        .unwrap();
    assert_eq!(output.status.code(), Some(0), "{}", stderr(&output));
    let summary = read_json(&out.join("summary.json"));
    assert_eq!(summary["completed"], Value::Bool(true), "{summary}");
    assert_eq!(summary["final_time"].as_f64(), Some(2e-6), "{summary}");
    assert_eq!(summary["pipeline"], "ice_mpm", "{summary}");
    // The headline figures, whole PNGs.
    assert_eq!(
        file_names(&out.join("plots")),
        ["axis_pressure.png", "wall_velocity.png"]
    );
    let png = std::fs::read(out.join("plots").join("wall_velocity.png")).unwrap();
    assert_eq!(&png[..8], b"\x89PNG\r\n\x1a\n");
    assert!(out.join("conservation.csv").is_file());
    let names = file_names(&out);
    assert!(names.iter().any(|n| n.ends_with(".pvd")), "{names:?}");
    let vtk = file_names(&out.join("vtk"));
    // Cells (ImageData) and copper particles (UnstructuredGrid) at t = 0
    // and at the end.
    assert_eq!(
        vtk,
        [
            "cylinder_default_00000.vti",
            "cylinder_default_00001.vti",
            "cylinder_default_particles_00000.vtu",
            "cylinder_default_particles_00001.vtu"
        ],
    );
    // Nothing is written next to the working directory besides `out`.
    assert_eq!(file_names(dir.path()), ["out"]);
}

#[test]
fn run_writes_its_outputs_under_the_documented_names() {
    let (_dir, config, out) = scenario(&sod_text());
    let output = run(&config, &out, &["--set", "domain.cells=(50,1,1)"]);
    assert_eq!(output.status.code(), Some(0), "{}", stderr(&output));

    assert_eq!(
        first_line(&out.join("gauges").join("x0_75.csv")),
        "time,density,pressure,velocity_x"
    );
    // Output times 0, 0.05, 0.1, 0.15, 0.2: five numbered line-outs + final.
    let lineouts = file_names(&out.join("lineouts"));
    assert_eq!(
        lineouts,
        [
            "tube_0.csv",
            "tube_1.csv",
            "tube_2.csv",
            "tube_3.csv",
            "tube_4.csv",
            "tube_final.csv"
        ]
    );
    for name in &lineouts {
        let header = first_line(&out.join("lineouts").join(name));
        assert!(header.starts_with("x,y,z,"), "{name}: {header}");
        assert_eq!(
            header, "x,y,z,density,velocity_x,pressure,specific_internal_energy",
            "{name}"
        );
    }
    assert_eq!(
        first_line(&out.join("conservation.csv")),
        "time,mass,momentum_x,momentum_y,momentum_z,energy"
    );
    let vtk = file_names(&out.join("vtk"));
    assert_eq!(
        vtk,
        [
            "sod_00000.vti",
            "sod_00001.vti",
            "sod_00002.vti",
            "sod_00003.vti",
            "sod_00004.vti"
        ]
    );
    let pvd = fs::read_to_string(out.join("sod.pvd")).unwrap();
    for name in &vtk {
        assert!(pvd.contains(&format!("file=\"vtk/{name}\"")), "{pvd}");
    }

    let s = read_json(&out.join("summary.json"));
    assert!(s["steps"].as_u64().unwrap() > 0, "{s}");
    assert_eq!(s["final_time"].as_f64(), Some(0.2), "{s}");
    assert!(s["wall_seconds"].as_f64().unwrap() >= 0.0, "{s}");
    assert!(s["throughput"].as_f64().unwrap() > 0.0, "{s}");
    assert_eq!(s["throughput_unit"], "cell-updates/s", "{s}");
    let dm = s["relative_mass_change"]
        .as_f64()
        .expect("relative_mass_change");
    let de = s["relative_energy_change"]
        .as_f64()
        .expect("relative_energy_change");
    assert!(dm.abs() < 1e-6, "{s}");
    assert!(de.abs() < 1e-6, "{s}");
    assert_eq!(s["completed"], Value::Bool(true), "{s}");
    assert_eq!(s["stop_reason"], Value::Null, "{s}");
}

#[test]
fn non_physical_state_stops_with_the_cell_and_time_and_keeps_earlier_outputs() {
    // The halves fly apart at Mach ~ 50: the gap between them empties. The
    // scheme as printed (no face limiter) stops there.
    let text = replaced(
        &sod_text(),
        "(density: 1.0, pressure: 1.0)",
        "(density: 1.0, velocity: (-20, 0, 0), pressure: 0.01)",
    );
    let text = replaced(
        &text,
        "(density: 0.125, pressure: 0.1)",
        "(density: 0.125, velocity: (20, 0, 0), pressure: 0.01)",
    );
    let (_dir, config, out) = scenario(&text);
    let output = run(
        &config,
        &out,
        &[
            "--set",
            "domain.cells=(50,1,1)",
            "--set",
            "pipeline.limiter=Off",
        ],
    );
    let message = single_error_line(&output);
    assert!(
        message.contains("non-physical state at t = "),
        "should name the time: {message}"
    );
    assert!(
        message.contains(" in cell ("),
        "should name the cell: {message}"
    );

    let summary = read_json(&out.join("summary.json"));
    assert_eq!(summary["completed"], Value::Bool(false), "{summary}");
    let reason = summary["stop_reason"]
        .as_str()
        .unwrap_or_else(|| panic!("no stop_reason: {summary}"));
    assert!(reason.contains("non-physical state"), "{reason}");
    // The outputs written before the failure are kept.
    assert!(out.join("vtk").join("sod_00000.vti").is_file());
    assert!(out.join("lineouts").join("tube_0.csv").is_file());
    assert!(out.join("sod.pvd").is_file());
    assert!(out.join("conservation.csv").is_file());
    // The last good state (here the initial one: the first step fails) is
    // written as the next output, not the half-updated state of the
    // failed step.
    let last = out.join("vtk").join("sod_00001.vti");
    assert!(last.is_file(), "the last good state is written");
    assert_eq!(
        std::fs::read(&last).unwrap(),
        std::fs::read(out.join("vtk").join("sod_00000.vti")).unwrap(),
        "the last good state is the state before the failed step"
    );
    assert!(out.join("lineouts").join("tube_1.csv").is_file());
    let pvd = std::fs::read_to_string(out.join("sod.pvd")).unwrap();
    assert!(pvd.contains("sod_00001.vti"), "{pvd}");

    // With the face limiter (the default) the same flow runs to its end,
    // and the summary says how often the limiter kept positivity.
    let out2 = out.with_file_name("out_limited");
    let output = run(&config, &out2, &["--set", "domain.cells=(50,1,1)"]);
    assert!(output.status.success(), "{}", stderr(&output));
    let s = read_json(&out2.join("summary.json"));
    assert_eq!(s["completed"], Value::Bool(true), "{s}");
    let guards = s["safeguards"].as_array().expect("safeguards");
    let positivity = guards
        .iter()
        .find(|g| g["name"].as_str().is_some_and(|n| n.contains("positivity")))
        .unwrap_or_else(|| panic!("no positivity entry: {s}"));
    assert!(positivity["acted"].as_u64().unwrap() > 0, "{s}");
    assert_eq!(positivity["unit"], "faces", "{s}");
}

#[test]
fn a_run_stopping_steps_in_writes_the_state_before_the_failed_step() {
    // Streams colliding in the middle under the bare scheme (no limiter,
    // no viscosity): the pressure goes negative some forty steps in.
    let text = replaced(
        &sod_text(),
        "(density: 1.0, pressure: 1.0)",
        "(density: 1.0, velocity: (1.35, 0, 0), pressure: 0.6)",
    );
    let text = replaced(
        &text,
        "(density: 0.125, pressure: 0.1)",
        "(density: 0.125, velocity: (-1.35, 0, 0), pressure: 0.6)",
    );
    let (_dir, config, out) = scenario(&text);
    let sets = [
        "--set",
        "domain.cells=(200,1,1)",
        "--set",
        "pipeline.limiter=Off",
        "--set",
        "pipeline.viscosity=Off",
    ];
    let message = single_error_line(&run(&config, &out, &sets));
    let steps: u64 = message
        .strip_prefix("run stopped at step ")
        .and_then(|m| m.split(':').next())
        .and_then(|n| n.parse().ok())
        .unwrap_or_else(|| panic!("no step count: {message}"));
    assert!(steps > 1, "should fail some steps in: {message}");
    // Found at the start of a step, the bad state is the one the previous
    // step left: the state before it is the last good one.
    let steps = if message.contains("(at the start of a step)") {
        steps - 1
    } else {
        steps
    };
    // The same run told to stop after those steps writes the state they
    // reach as its last output: the failed run's last output is the same
    // file, bit for bit.
    let good = out.with_file_name("out_good");
    let max = format!("time.max_steps={steps}");
    let output = run(&config, &good, &[&sets[..], &["--set", &max]].concat());
    assert!(output.status.success(), "{}", stderr(&output));
    let last = |dir: &Path| file_names(&dir.join("vtk")).pop().expect("a VTK file");
    assert_eq!(last(&out), last(&good));
    let name = last(&out);
    assert!(
        std::fs::read(out.join("vtk").join(&name)).unwrap()
            == std::fs::read(good.join("vtk").join(&name)).unwrap(),
        "{name}: the last good state differs from the state after {steps} steps"
    );
}

// ---------------------------------------------------------------------------
// `brisance remap` and the blast scenario it feeds.

/// Runs `brisance remap` of a TNT charge of `symmetry`: the 1D run
/// `[charge radius, 1D radius, 1D cells, time]`, the target grid
/// `[lower, upper, cells, centre]` (comma-separated triples), into `out`,
/// with `extra` arguments.
fn remap(symmetry: &str, one_d: [&str; 4], grid: [&str; 4], out: &Path, extra: &[&str]) -> Output {
    let [charge, radius, cells_1d, time] = one_d;
    let [lower, upper, cells, centre] = grid;
    brisance()
        .arg("remap")
        .args(["--symmetry", symmetry, "--charge-radius", charge])
        .args([
            "--radius-1d",
            radius,
            "--cells-1d",
            cells_1d,
            "--time",
            time,
        ])
        .arg(format!("--lower={lower}"))
        .arg(format!("--upper={upper}"))
        .args(["--cells", cells])
        .arg(format!("--centre={centre}"))
        .arg("--out")
        .arg(out)
        .args(extra)
        .output()
        .expect("the brisance binary runs")
}

/// The relative changes `brisance remap` prints for the charge's mass,
/// energy and products mass.
fn remap_changes(text: &str) -> [f64; 3] {
    let line = text
        .lines()
        .find(|l| l.starts_with("relative change:"))
        .unwrap_or_else(|| panic!("no relative-change line in {text}"));
    let values: Vec<f64> = line
        .split(',')
        .map(|part| part.split_whitespace().last().unwrap().parse().unwrap())
        .collect();
    [values[0], values[1], values[2]]
}

#[test]
fn remap_writes_the_initial_state_and_keeps_the_charge() {
    // A 10 mm cylindrical TNT charge detonated on 60 cells of 0.5 mm and
    // remapped onto a 2D quarter grid of 1 mm cells.
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("remap");
    let output = remap(
        "cylindrical",
        ["0.01", "0.03", "60", "3e-6"],
        ["0,0,0", "0.04,0.04,0.001", "40,40,1", "0,0,0"],
        &out,
        &[],
    );
    assert_eq!(output.status.code(), Some(0), "{}", stderr(&output));
    let text = stdout(&output);
    assert!(text.contains("1D cylindrical detonation"), "{text}");
    // The charge's mass, energy and products mass over the remap.
    for (name, change) in ["mass", "energy", "products"]
        .iter()
        .zip(remap_changes(&text))
    {
        assert!(change.abs() < 1e-12, "{name}: {change:e}\n{text}");
    }
    assert_eq!(
        file_names(&out),
        ["profile.csv", "remap.bin", "remap.vti"],
        "{text}"
    );
    assert_eq!(
        first_line(&out.join("profile.csv")),
        "radius,density,velocity,pressure,products_mass_fraction"
    );
    // 60 radial cells, one line each.
    let rows = fs::read_to_string(out.join("profile.csv"))
        .unwrap()
        .lines()
        .count();
    assert_eq!(rows, 61);
    let vti = fs::read_to_string(out.join("remap.vti")).unwrap();
    assert!(
        vti.contains("WholeExtent=\"0 40 0 40 0 1\""),
        "{}",
        &vti[..vti.len().min(300)]
    );
}

#[test]
fn remap_with_a_malformed_grid_fails_before_running_and_writes_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("remap");
    let output = remap(
        "spherical",
        ["0.01", "0.03", "60", "3e-6"],
        ["0,0", "0.04,0.04,0.04", "8,8,8", "0,0,0"],
        &out,
        &[],
    );
    assert_eq!(output.status.code(), Some(1));
    let err = stderr(&output);
    assert!(
        err.contains("--lower takes three comma-separated values, got 2"),
        "{err}"
    );
    assert!(!err.contains("panicked"), "{err}");
    assert!(!out.exists());
}

/// `configs/blast2d.ron` on the strip 150 ≤ y ≤ 350 mm through the
/// charge's centre (100 rows instead of 250) and the charge's remap made by
/// `brisance remap` into `dir/remap` (440 cells, within 100 mm of the
/// centre, inside the strip): the remap file and the strip's overrides.
fn blast2d_strip(dir: &Path) -> (PathBuf, Vec<String>) {
    let remapped = dir.join("remap");
    let output = remap(
        "cylindrical",
        ["0.05", "0.11", "440", "1.2e-5"],
        ["-0.18,0.15,0", "0.12,0.35,0.002", "150,100,1", "0,0.25,0"],
        &remapped,
        &["--radius", "0.1"],
    );
    assert_eq!(output.status.code(), Some(0), "{}", stderr(&output));
    let strip = [
        "domain.lower=(-0.18, 0.15, 0.0)",
        "domain.upper=(0.16, 0.35, 0.002)",
        "domain.cells=(170, 100, 1)",
        "pipeline.fdm_region=(lower: (-0.18, 0.15, 0.0), upper: (0.12, 0.35, 0.002))",
        "pipeline.mpm_region=(lower: (0.11, 0.15, 0.0), upper: (0.16, 0.35, 0.002))",
    ];
    (
        remapped.join("remap.bin"),
        strip.iter().map(|s| s.to_string()).collect(),
    )
}

/// `--set` arguments of `sets`.
fn set_args(sets: &[String]) -> Vec<String> {
    sets.iter()
        .flat_map(|s| ["--set".to_string(), s.clone()])
        .collect()
}

/// Runs `config` quietly into `out` with the `--set` overrides `sets`,
/// remaps cached in `cache`; asserts that it succeeds.
fn run_cached(config: &Path, out: &Path, cache: &Path, sets: &[String]) {
    let mut cmd = brisance();
    cmd.env("BRISANCE_CACHE_DIR", cache)
        .arg("run")
        .arg(config)
        .arg("--out")
        .arg(out)
        .arg("--quiet")
        .args(set_args(sets));
    let output = cmd.output().expect("the brisance binary runs");
    assert_eq!(output.status.code(), Some(0), "{}", stderr(&output));
}

/// Asserts that two runs' `conservation.csv` hold the same mass and
/// energy (columns 1 and 5) at every row, to `tolerance` relative.
fn assert_same_mass_and_energy(a: &Path, b: &Path, tolerance: f64) {
    let table = |out: &Path| -> Vec<Vec<f64>> {
        fs::read_to_string(out.join("conservation.csv"))
            .unwrap()
            .lines()
            .skip(1)
            .map(|l| l.split(',').map(|x| x.parse().unwrap()).collect())
            .collect()
    };
    let (a, b) = (table(a), table(b));
    assert!(!a.is_empty() && a.len() == b.len(), "{a:?} {b:?}");
    for (x, y) in a.iter().zip(&b) {
        for k in [1, 5] {
            assert!(
                (x[k] - y[k]).abs() <= tolerance * x[k].abs(),
                "{x:?} vs {y:?}"
            );
        }
    }
}

/// The strip of `blast2d_runs_through_the_bridge_on_a_strip_of_its_domain`
/// to 1 µs, its FDM region from the charge stated in the config (the run
/// remaps it) or from `brisance remap`'s file: the same totals. The first
/// charge run stores the remap in the cache, the second reads it back and
/// gives the same bytes.
#[test]
fn a_charge_in_the_config_is_remapped_by_the_run_and_cached() {
    let dir = tempfile::tempdir().unwrap();
    let cache = dir.path().join("cache");
    let (remap_file, mut strip) = blast2d_strip(dir.path());
    strip.extend(["time.end=1e-6".to_string(), "outputs.interval=1.0".into()]);
    let config = Path::new(env!("CARGO_MANIFEST_DIR")).join("configs/blast2d.ron");
    let go = |out: &Path, source: &[String]| {
        run_cached(&config, out, &cache, &[&strip[..], source].concat());
    };
    let from_file = dir.path().join("from_file");
    go(
        &from_file,
        &[
            format!("pipeline.remap=Some(\"{}\")", remap_file.display()),
            "pipeline.charge=None".into(),
        ],
    );
    let charge = "pipeline.charge=Some(explosive: \"tnt\", symmetry: Cylindrical, centre: (0.0, 0.25, 0.0), radius: 0.05, radius_1d: 0.11, cells_1d: 440, time: 1.2e-5, remap_radius: Some(0.1))".to_string();
    let first = dir.path().join("first");
    go(&first, std::slice::from_ref(&charge));
    let cached = file_names(&cache.join("remap"));
    assert_eq!(cached.len(), 1, "{cached:?}");
    let stamp = |f: &Path| fs::metadata(f).unwrap().modified().unwrap();
    let entry = cache.join("remap").join(&cached[0]);
    let written = stamp(&entry);
    let second = dir.path().join("second");
    go(&second, &[charge]);
    // Read, not made again (which would replace the file).
    assert_eq!(stamp(&entry), written);
    for rel in ["conservation.csv", "gauges/gauge1.csv"] {
        crate::common::assert_same_bytes(&first, &second, Path::new(rel));
    }
    assert_eq!(file_names(&cache.join("remap")), cached);
    // Against the file: the same state but for the grid spacing's last
    // bits (the command line divides the FDM box by its cells, the run
    // the domain): mass and energy agree to round-off.
    assert_same_mass_and_energy(&from_file, &first, 1e-12);
}

/// `configs/blast2d_mpm.ron` on a strip of its domain for two steps, its
/// particles from the charge stated in the config (the run remaps it onto
/// the whole strip) or from `brisance remap`'s file onto the same cells:
/// the same mass and energy to round-off (the command line divides the box
/// by its cells, the run the domain).
#[test]
fn a_charge_of_the_pure_mpm_remap_is_remapped_by_the_run() {
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("remap");
    let output = remap(
        "cylindrical",
        ["0.05", "0.11", "440", "1.2e-5"],
        ["-0.18,0.15,0", "0.16,0.35,0.002", "170,100,1", "0,0.25,0"],
        &file,
        &["--radius", "0.1"],
    );
    assert_eq!(output.status.code(), Some(0), "{}", stderr(&output));
    let config = Path::new(env!("CARGO_MANIFEST_DIR")).join("configs/blast2d_mpm.ron");
    let strip: Vec<String> = [
        "domain.lower=(-0.18, 0.15, 0.0)",
        "domain.upper=(0.16, 0.35, 0.002)",
        "domain.cells=(170, 100, 1)",
        "time.max_steps=Some(2)",
        "outputs.interval=1.0",
    ]
    .map(String::from)
    .to_vec();
    let cache = dir.path().join("cache");
    let go = |out: &Path, source: &[String]| {
        run_cached(&config, out, &cache, &[&strip[..], source].concat());
    };
    let from_file = dir.path().join("from_file");
    go(
        &from_file,
        &[
            format!(
                "pipeline.remap.file=Some(\"{}\")",
                file.join("remap.bin").display()
            ),
            "pipeline.remap.charge=None".into(),
        ],
    );
    let from_charge = dir.path().join("from_charge");
    go(
        &from_charge,
        &["pipeline.remap.charge=Some(explosive: \"tnt\", symmetry: Cylindrical, centre: (0.0, 0.25, 0.0), radius: 0.05, radius_1d: 0.11, cells_1d: 440, time: 1.2e-5, remap_radius: Some(0.1))".to_string()],
    );
    assert_same_mass_and_energy(&from_file, &from_charge, 1e-12);
    // The charge is in: the energy is the detonation's (7.0e9 J/m³ over the
    // 50 mm disc 2 mm thick, 1.1e5 J), far above the strip's air (34 J).
    let energy: f64 = fs::read_to_string(from_charge.join("conservation.csv"))
        .unwrap()
        .lines()
        .nth(1)
        .and_then(|l| l.split(',').nth(5))
        .and_then(|x| x.parse().ok())
        .unwrap();
    assert!(energy > 5e4, "{energy}");
}

#[test]
fn blast2d_runs_through_the_bridge_on_a_strip_of_its_domain() {
    // The strip from its own remap, to 10 us: the blast reaches the MPM
    // region, which starts, and gauge 2 in it sees the shock.
    let dir = tempfile::tempdir().unwrap();
    let (remap_file, mut sets) = blast2d_strip(dir.path());
    sets.extend([
        format!("pipeline.remap=Some(\"{}\")", remap_file.display()),
        "pipeline.charge=None".into(),
        "time.end=1e-5".into(),
        "outputs.interval=1.0".into(),
    ]);
    let config = Path::new(env!("CARGO_MANIFEST_DIR")).join("configs/blast2d.ron");
    let out = dir.path().join("out");
    let args = set_args(&sets);
    let args: Vec<&str> = args.iter().map(String::as_str).collect();
    let output = run(&config, &out, &args);
    assert_eq!(output.status.code(), Some(0), "{}", stderr(&output));
    let s = read_json(&out.join("summary.json"));
    assert_eq!(s["completed"], Value::Bool(true), "{s}");
    let split = read_json(&out.join("time_split.json"));
    let activated = split["activated_at"]
        .as_f64()
        .expect("the MPM region started");
    assert!(activated > 0.0 && activated < 1e-5, "{split}");
    assert!(split["mpm_seconds"].as_f64().unwrap() > 0.0, "{split}");
    assert!(
        split["created"].as_u64().unwrap() + split["deposited"].as_u64().unwrap() > 0,
        "{split}"
    );
    // Gauge 2, in the MPM region, 125 mm from the charge's centre: ambient
    // first, then the blast (tens of bar at this distance).
    let gauge = fs::read_to_string(out.join("gauges").join("gauge2.csv")).unwrap();
    let p: Vec<f64> = gauge
        .lines()
        .skip(1)
        .map(|l| l.split(',').nth(1).unwrap().parse().unwrap())
        .collect();
    // The config's air: p = (γ − 1) ρ e = 0.4 × 1.225 × 2.0685e5 Pa.
    let ambient = 0.4 * 1.225 * 2.0685e5;
    assert!(
        (p[0] - ambient).abs() < 1e-6 * ambient,
        "{} {ambient}",
        p[0]
    );
    let peak = p.iter().copied().fold(0.0, f64::max);
    eprintln!(
        "gauge 2: {} samples, peak {peak:.4e} Pa; activated at {activated:e} s",
        p.len()
    );
    assert!(peak > 1.0e6, "gauge 2 peak {peak} Pa");
}
