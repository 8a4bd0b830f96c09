//! Checkpoints and restart: `brisance run --restart <checkpoint>` continues
//! an interrupted run and ends bit-identical to an uninterrupted one, also
//! on another thread count and patch split; a checkpoint of another problem
//! or a damaged checkpoint file is refused with one clear error line.

use std::fs;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use serde_json::Value;

use crate::common::{assert_same_bytes, assert_success, read_json, run_quiet, BIN};
const SOD: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/configs/sod.ron");

/// The overrides every run of these tests shares.
const SETS: [&str; 4] = [
    "--set",
    "domain.cells=(100,1,1)",
    "--set",
    "outputs.checkpoint_every=10",
];

/// Runs `brisance run configs/sod.ron --out <out> --quiet <SETS> <extra...>`.
fn run_sod(out: &Path, extra: &[&str]) -> Output {
    run_config(Path::new(SOD), out, extra)
}

/// Runs `brisance run <config> --out <out> --quiet <SETS> <extra...>`.
fn run_config(config: &Path, out: &Path, extra: &[&str]) -> Output {
    run_quiet(config, out, &[&SETS[..], extra].concat())
}

fn single_error_line(out: &Output) -> String {
    let err = String::from_utf8_lossy(&out.stderr).into_owned();
    assert_eq!(out.status.code(), Some(1), "expected exit code 1:\n{err}");
    assert!(!err.contains("panicked"), "the binary panicked:\n{err}");
    let line = err.strip_suffix('\n').unwrap_or(&err);
    assert!(
        line.starts_with("error: ") && !line.contains('\n'),
        "expected one `error: ` line, got:\n{err}"
    );
    line.to_string()
}

/// The uninterrupted reference run, and the checkpoint in its middle.
fn reference_run(dir: &Path) -> (PathBuf, PathBuf) {
    let a = dir.join("A");
    assert_success(&run_sod(&a, &[]));
    let middle = middle_checkpoint(&a);
    (a, middle)
}

/// The checkpoint in the middle of those a run wrote under `out`.
pub(crate) fn middle_checkpoint(out: &Path) -> PathBuf {
    let mut checkpoints: Vec<PathBuf> = fs::read_dir(out.join("checkpoints"))
        .expect("the run wrote checkpoints")
        .map(|e| e.unwrap().path())
        .collect();
    checkpoints.sort();
    assert!(
        checkpoints.len() >= 2,
        "need a checkpoint before the end: {checkpoints:?}"
    );
    checkpoints[checkpoints.len() / 2].clone()
}

/// Every file under `dir`, as paths relative to `root`, sorted.
fn files_under(root: &Path, dir: &str) -> Vec<PathBuf> {
    let mut files = Vec::new();
    let mut stack = vec![root.join(dir)];
    while let Some(d) = stack.pop() {
        for e in fs::read_dir(&d).unwrap_or_else(|e| panic!("cannot list {}: {e}", d.display())) {
            let p = e.unwrap().path();
            if p.is_dir() {
                stack.push(p);
            } else {
                files.push(p.strip_prefix(root).unwrap().to_path_buf());
            }
        }
    }
    files.sort();
    files
}

/// The final VTK file and line-out of the sod scenario.
fn final_outputs(root: &Path) -> Vec<PathBuf> {
    let vtk = files_under(root, "vtk");
    let last_vti = vtk.last().expect("a VTK file was written").clone();
    vec![last_vti, PathBuf::from("lineouts/tube_final.csv")]
}

#[test]
fn restart_ends_bit_identical_to_an_uninterrupted_run() {
    let dir = tempfile::tempdir().unwrap();
    let (a, checkpoint) = reference_run(dir.path());
    let b = dir.path().join("B");
    assert_success(&run_sod(&b, &["--restart", checkpoint.to_str().unwrap()]));

    let mut compared = Vec::new();
    for sub in ["vtk", "lineouts", "gauges"] {
        compared.extend(files_under(&b, sub));
    }
    compared.push(PathBuf::from("conservation.csv"));
    compared.push(PathBuf::from("sod.pvd"));
    // The restarted run wrote the later field outputs, including the last.
    assert!(
        compared.contains(&final_outputs(&a)[0]),
        "the restarted run did not write the final VTK file: {compared:?}"
    );
    assert!(compared.contains(&PathBuf::from("lineouts/tube_final.csv")));
    assert!(compared.contains(&PathBuf::from("gauges/x0_75.csv")));
    for rel in &compared {
        assert_same_bytes(&a, &b, rel);
    }

    let sa = read_json(&a.join("summary.json"));
    let sb = read_json(&b.join("summary.json"));
    assert_eq!(sb["completed"], Value::Bool(true), "{sb}");
    for key in [
        "steps",
        "final_time",
        "initial_totals",
        "final_totals",
        "relative_mass_change",
        "relative_energy_change",
    ] {
        assert_eq!(sa[key], sb[key], "summary `{key}` differs");
    }
}

/// `outputs.checkpoint_layout: Patches`: a checkpoint file and a folder
/// of one file per patch beside it; the restart ends bit-identical to the
/// uninterrupted run, needs the same patches, and refuses a damaged
/// patch file naming it.
#[test]
fn a_checkpoint_written_per_patch_restarts_bit_identical() {
    let dir = tempfile::tempdir().unwrap();
    let patches = [
        "--set",
        "domain.patches=(4,1,1)",
        "--set",
        "outputs.checkpoint_layout=Patches",
    ];
    let a = dir.path().join("A");
    assert_success(&run_sod(&a, &patches));
    let mut checkpoints: Vec<PathBuf> = fs::read_dir(a.join("checkpoints"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "bin"))
        .collect();
    checkpoints.sort();
    assert!(checkpoints.len() >= 2, "{checkpoints:?}");
    let middle = checkpoints[checkpoints.len() / 2].clone();
    let folder = middle.with_extension("");
    let names: Vec<String> = {
        let mut v: Vec<String> = fs::read_dir(&folder)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        v.sort();
        v
    };
    assert_eq!(
        names,
        [
            "patch_00000.bin",
            "patch_00001.bin",
            "patch_00002.bin",
            "patch_00003.bin"
        ]
    );

    let b = dir.path().join("B");
    let restart = ["--restart", middle.to_str().unwrap()];
    assert_success(&run_sod(&b, &[&patches[..], &restart].concat()));
    let mut compared = Vec::new();
    for sub in ["vtk", "lineouts", "gauges"] {
        compared.extend(files_under(&b, sub));
    }
    compared.push(PathBuf::from("conservation.csv"));
    assert!(compared.contains(&final_outputs(&a)[0]), "{compared:?}");
    for rel in &compared {
        assert_same_bytes(&a, &b, rel);
    }

    // Other patches cannot read the pieces.
    let c = dir.path().join("C");
    let other = [
        "--set",
        "domain.patches=(2,1,1)",
        "--set",
        "outputs.checkpoint_layout=Patches",
    ];
    let line = single_error_line(&run_sod(&c, &[&other[..], &restart].concat()));
    assert!(line.contains("restarts with the same patches"), "{line}");

    // A damaged patch file is refused, naming it.
    let piece = folder.join("patch_00002.bin");
    let mut bytes = fs::read(&piece).unwrap();
    let at = bytes.len() / 2;
    bytes[at] ^= 1;
    fs::write(&piece, &bytes).unwrap();
    let d = dir.path().join("D");
    let line = single_error_line(&run_sod(&d, &[&patches[..], &restart].concat()));
    assert!(line.contains("patch_00002.bin"), "{line}");
    assert!(line.contains("checksum"), "{line}");
}

#[test]
fn restart_on_other_threads_and_patches_ends_bit_identical() {
    let dir = tempfile::tempdir().unwrap();
    let (a, checkpoint) = reference_run(dir.path());
    let c = dir.path().join("C");
    assert_success(&run_sod(
        &c,
        &[
            "--threads",
            "1",
            "--set",
            "domain.patches=(4,1,1)",
            "--restart",
            checkpoint.to_str().unwrap(),
        ],
    ));
    for rel in final_outputs(&a) {
        assert_same_bytes(&a, &c, &rel);
    }
    let sa = read_json(&a.join("summary.json"));
    let sc = read_json(&c.join("summary.json"));
    assert_eq!(sa["steps"], sc["steps"]);
    assert_eq!(sa["final_totals"], sc["final_totals"]);
}

#[test]
fn restart_with_another_domain_is_refused_as_another_problem() {
    let dir = tempfile::tempdir().unwrap();
    let (_a, checkpoint) = reference_run(dir.path());
    let d = dir.path().join("D");
    let output = run_sod(
        &d,
        &[
            "--set",
            "domain.cells=(120,1,1)",
            "--restart",
            checkpoint.to_str().unwrap(),
        ],
    );
    let line = single_error_line(&output);
    assert!(
        line.contains(&checkpoint.display().to_string()),
        "should name the checkpoint: {line}"
    );
    assert!(line.contains("written for another problem"), "{line}");
    assert!(line.contains("domain"), "{line}");
    assert!(!d.exists(), "nothing should be written");
}

#[test]
fn truncated_or_garbage_checkpoint_is_refused_naming_the_file() {
    let dir = tempfile::tempdir().unwrap();
    let (_a, checkpoint) = reference_run(dir.path());
    let bytes = fs::read(&checkpoint).unwrap();

    let mut garbage_after_header = bytes[..12].to_vec();
    garbage_after_header.extend((0..200u32).map(|i| (i * 37 % 251) as u8));
    let cases: [(&str, Vec<u8>, Option<&str>); 4] = [
        (
            "truncated.bin",
            bytes[..bytes.len() / 2].to_vec(),
            Some("truncated"),
        ),
        ("empty.bin", Vec::new(), Some("truncated")),
        (
            "garbage.bin",
            b"this is not a checkpoint at all\n".to_vec(),
            Some("magic"),
        ),
        ("garbage_after_header.bin", garbage_after_header, None),
    ];
    for (name, content, says) in cases {
        let file = dir.path().join(name);
        fs::write(&file, &content).unwrap();
        let out = dir.path().join(format!("out_{name}"));
        let output = run_sod(&out, &["--restart", file.to_str().unwrap()]);
        let line = single_error_line(&output);
        assert!(
            line.contains(&file.display().to_string()),
            "{name}: should name the file: {line}"
        );
        assert!(
            line.contains("not a valid Brisance checkpoint"),
            "{name}: {line}"
        );
        if let Some(word) = says {
            assert!(line.contains(word), "{name}: should say `{word}`: {line}");
        }
        assert!(!out.exists(), "{name}: nothing should be written");
    }
    // A checkpoint that does not exist.
    let missing = dir.path().join("missing.bin");
    let out = dir.path().join("out_missing");
    let output = run_sod(&out, &["--restart", missing.to_str().unwrap()]);
    let line = single_error_line(&output);
    assert!(line.contains(&missing.display().to_string()), "{line}");
    assert!(!out.exists());
}

/// A checkpoint whose run state has another layout, as one written by an
/// older build before the run loop kept its time steps (the state ends
/// without them), is refused with one line that names the file and says
/// to rerun; nothing is written.
#[test]
fn a_checkpoint_of_another_run_state_layout_is_refused_naming_the_file() {
    let dir = tempfile::tempdir().unwrap();
    let (_a, checkpoint) = reference_run(dir.path());
    let mut ck = brisance_io::read_checkpoint(&checkpoint).unwrap();
    // `time_steps: Some(..)` is the state's last field: a tag byte and
    // four f64.
    let old_len = ck.run_state.len() - 33;
    ck.run_state.truncate(old_len);
    let file = dir.path().join("older.bin");
    brisance_io::write_checkpoint(&file, &ck).unwrap();
    let out = dir.path().join("out_older");
    let output = run_sod(&out, &["--restart", file.to_str().unwrap()]);
    let line = single_error_line(&output);
    assert!(line.contains(&file.display().to_string()), "{line}");
    assert!(line.contains("run state does not decode"), "{line}");
    assert!(line.contains("rerun from the start"), "{line}");
    assert!(!out.exists(), "nothing should be written");
}

#[test]
fn restart_of_a_scenario_with_library_materials_continues() {
    // The same tube with the gas taken from the material library: the
    // checkpoint's scenario must be compared after the library is resolved.
    let dir = tempfile::tempdir().unwrap();
    let text = fs::read_to_string(SOD).unwrap().replace(
        r#""gas": (eos: IdealGas(gamma: 1.4, cv: 1.0, rho0: 1.0)),"#,
        r#""gas": (library: "air"),"#,
    );
    assert!(text.contains(r#"(library: "air")"#), "sod.ron changed");
    let config = dir.path().join("sod_air.ron");
    fs::write(&config, text).unwrap();
    let a = dir.path().join("A");
    assert_success(&run_config(&config, &a, &[]));
    let middle = middle_checkpoint(&a);
    let b = dir.path().join("B");
    assert_success(&run_config(
        &config,
        &b,
        &["--restart", middle.to_str().unwrap()],
    ));
    assert_same_bytes(&a, &b, Path::new("conservation.csv"));
}

#[test]
fn a_checkpoint_with_bytes_changed_anywhere_is_refused_naming_the_file() {
    let dir = tempfile::tempdir().unwrap();
    let (_a, checkpoint) = reference_run(dir.path());
    let bytes = fs::read(&checkpoint).unwrap();
    let n = bytes.len();
    // Past the header, in the middle (the fields) and at the end.
    for offset in [16, n / 2, n - 9, n - 1] {
        let mut changed = bytes.clone();
        changed[offset] ^= 0x04;
        let file = dir.path().join(format!("changed_{offset}.bin"));
        fs::write(&file, &changed).unwrap();
        let out = dir.path().join(format!("out_changed_{offset}"));
        let output = run_sod(&out, &["--restart", file.to_str().unwrap()]);
        let line = single_error_line(&output);
        assert!(line.contains(&file.display().to_string()), "{line}");
        assert!(line.contains("checksum does not match"), "{line}");
        assert!(!out.exists(), "byte {offset}: nothing should be written");
    }
}

/// A sod tube long enough (about 3000 steps of 40000 cells) to be stopped
/// in its middle; no checkpoints but the one the stop writes.
#[cfg(unix)]
const LONG: [&str; 8] = [
    "--set",
    "domain.cells=(40000,1,1)",
    "--set",
    "outputs.checkpoint_every=100000000",
    "--set",
    "time.end=0.05",
    "--set",
    "outputs.interval=0.01",
];

#[cfg(unix)]
#[test]
fn sigterm_checkpoints_and_restart_latest_ends_bit_identical() {
    let dir = tempfile::tempdir().unwrap();
    let a = dir.path().join("A");
    assert_success(&run_sod(&a, &LONG));

    let b = dir.path().join("B");
    let child = Command::new(BIN)
        .env_remove("BRISANCE_LOG")
        .arg("run")
        .arg(SOD)
        .arg("--out")
        .arg(&b)
        .arg("--quiet")
        .args(SETS)
        .args(LONG)
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .expect("the brisance binary runs");
    // Stop it once its first output is on disk.
    let first = b.join("vtk").join("sod_00000.vti");
    let waited = std::time::Instant::now();
    while !first.is_file() {
        assert!(waited.elapsed().as_secs() < 120, "no first output");
        std::thread::sleep(std::time::Duration::from_millis(5));
    }
    let killed = Command::new("kill")
        .args(["-TERM", &child.id().to_string()])
        .status()
        .unwrap();
    assert!(killed.success());
    let output = child.wait_with_output().unwrap();
    assert_eq!(
        output.status.code(),
        Some(130),
        "{}",
        String::from_utf8_lossy(&output.stderr)
    );
    let err = String::from_utf8_lossy(&output.stderr).into_owned();
    let line = err.strip_suffix('\n').unwrap_or(&err);
    assert!(!line.contains('\n'), "one line: {err}");
    assert!(line.starts_with("error: interrupted at step "), "{line}");
    assert!(line.contains("; continue with: "), "{line}");
    assert!(line.ends_with(" --restart latest"), "{line}");
    assert!(line.contains(&format!("--out {}", b.display())), "{line}");
    let checkpoints = files_under(&b, "checkpoints");
    assert_eq!(checkpoints.len(), 1, "{checkpoints:?}");
    assert!(
        line.contains(&b.join(&checkpoints[0]).display().to_string()),
        "names the checkpoint: {line}"
    );
    let s = read_json(&b.join("summary.json"));
    assert_eq!(s["completed"], Value::Bool(false), "{s}");
    assert!(s["stop_reason"].as_str().unwrap().contains("interrupted"));

    // `--restart latest` finds it and ends where the uninterrupted run did.
    assert_success(&run_sod(
        &b,
        &[&LONG[..], &["--restart", "latest"]].concat(),
    ));
    for rel in final_outputs(&a) {
        assert_same_bytes(&a, &b, &rel);
    }
    assert_same_bytes(&a, &b, Path::new("conservation.csv"));
    assert_same_bytes(&a, &b, Path::new("gauges/x0_75.csv"));
    let (sa, sb) = (
        read_json(&a.join("summary.json")),
        read_json(&b.join("summary.json")),
    );
    assert_eq!(sa["steps"], sb["steps"]);
    assert_eq!(sb["completed"], Value::Bool(true), "{sb}");
}

#[test]
fn restart_latest_skips_a_damaged_newest_checkpoint_and_says_when_there_is_none() {
    let dir = tempfile::tempdir().unwrap();
    let (a, _) = reference_run(dir.path());
    // No checkpoints folder at all.
    let empty = dir.path().join("empty");
    let line = single_error_line(&run_sod(&empty, &["--restart", "latest"]));
    assert!(line.contains("no valid checkpoint in"), "{line}");
    // Damage the newest: the one before it is used, and the run ends as
    // the reference did.
    let b = dir.path().join("B");
    fs::create_dir_all(b.join("checkpoints")).unwrap();
    let all = files_under(&a, "checkpoints");
    let (newest, before) = (&all[all.len() - 1], &all[all.len() - 2]);
    let mut bytes = fs::read(a.join(newest)).unwrap();
    let k = bytes.len() / 2;
    bytes[k] ^= 1;
    fs::write(b.join(newest), bytes).unwrap();
    fs::copy(a.join(before), b.join(before)).unwrap();
    assert_success(&run_sod(&b, &["--restart", "latest"]));
    for rel in final_outputs(&a) {
        assert_same_bytes(&a, &b, &rel);
    }
}
