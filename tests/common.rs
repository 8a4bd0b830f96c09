//! What several integration modules need to drive the `brisance` binary
//! and read what it wrote.

use std::fs;
use std::path::Path;
use std::process::{Command, Output};

use serde_json::Value;

/// The binary under test.
pub const BIN: &str = env!("CARGO_BIN_EXE_brisance");

/// Runs `brisance run <config> --out <out> --quiet <args...>`.
pub fn run_quiet(config: &Path, out: &Path, args: &[&str]) -> Output {
    Command::new(BIN)
        .env_remove("BRISANCE_LOG")
        .arg("run")
        .arg(config)
        .arg("--out")
        .arg(out)
        .arg("--quiet")
        .args(args)
        .output()
        .expect("the brisance binary runs")
}

/// The run exited 0; else its standard error is the message.
pub fn assert_success(out: &Output) {
    assert_eq!(
        out.status.code(),
        Some(0),
        "run failed:\n{}",
        String::from_utf8_lossy(&out.stderr)
    );
}

/// The file `rel` has the same bytes under `a` and `b`.
pub fn assert_same_bytes(a: &Path, b: &Path, rel: &Path) {
    let left = fs::read(a.join(rel)).unwrap_or_else(|e| panic!("{}: {e}", rel.display()));
    let right = fs::read(b.join(rel)).unwrap_or_else(|e| panic!("{}: {e}", rel.display()));
    assert!(
        left == right,
        "{} differs between {} and {}",
        rel.display(),
        a.display(),
        b.display()
    );
}

/// A JSON file, parsed.
pub fn read_json(path: &Path) -> Value {
    let text =
        fs::read_to_string(path).unwrap_or_else(|e| panic!("cannot read {}: {e}", path.display()));
    serde_json::from_str(&text).unwrap_or_else(|e| panic!("{} is not JSON: {e}", path.display()))
}
