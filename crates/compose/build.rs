//! Embeds the material library (`configs/materials/*.ron`) in the binary, so
//! a config can name `library: "tnt"` on any machine. Adding a material is
//! adding a file.

use std::fmt::Write as _;
use std::path::Path;

fn main() {
    // The manifest directory of this run, not of the build that compiled
    // the script: cargo shares one compiled build script between copies of
    // the workspace at different paths (the hash is relative to the
    // workspace root), so `env!` would read the copy it was compiled in.
    let manifest = std::env::var("CARGO_MANIFEST_DIR")
        .expect("cargo sets CARGO_MANIFEST_DIR for build scripts");
    let dir = Path::new(&manifest).join("../../configs/materials");
    println!("cargo:rerun-if-changed={}", dir.display());
    let read = std::fs::read_dir(&dir)
        .unwrap_or_else(|e| panic!("the material library {}: {e}", dir.display()));
    let mut entries: Vec<(String, String)> = read
        .filter_map(|e| e.ok())
        .map(|e| e.path())
        .filter(|p| p.extension().is_some_and(|x| x == "ron"))
        .filter_map(|p| {
            let stem = p.file_stem()?.to_str()?.to_string();
            let abs = p.canonicalize().ok()?.to_str()?.to_string();
            Some((stem, abs))
        })
        .collect();
    assert!(
        !entries.is_empty(),
        "the material library {} holds no .ron file",
        dir.display()
    );
    entries.sort();
    let mut out = String::from("/// (name, RON text) of every library material, sorted by name.\npub const LIBRARY: &[(&str, &str)] = &[\n");
    for (name, path) in &entries {
        println!("cargo:rerun-if-changed={path}");
        let _ = writeln!(out, "    ({name:?}, include_str!({path:?})),");
    }
    out.push_str("];\n");
    let dest =
        Path::new(&std::env::var("OUT_DIR").expect("cargo sets OUT_DIR")).join("materials.rs");
    std::fs::write(dest, out).expect("OUT_DIR is writable");
}
