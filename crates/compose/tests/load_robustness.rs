//! Bad scenario input never panics: every shipped config with a material
//! renamed, out-of-range values, and a generated stream of mutated RON
//! text and `--set` overrides all end in a located error (a field or a
//! file position) or a loaded scenario. docs/testing.md reports the runs.

use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::PathBuf;

use brisance_compose::{load_str, ConfigError};
use proptest::prelude::*;
use proptest::test_runner::{Config, TestRunner};

fn configs_dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../configs")
}

/// (file name, text) of every shipped scenario, those of the validation
/// cases (`configs/validation/`) included, sorted by name.
fn shipped() -> Vec<(String, String)> {
    let mut v: Vec<(String, String)> = ["", "validation"]
        .into_iter()
        .flat_map(|sub| {
            std::fs::read_dir(configs_dir().join(sub))
                .unwrap()
                .filter_map(|e| e.ok())
                .map(|e| e.path())
                .filter(|p| p.extension().is_some_and(|x| x == "ron"))
                .map(move |p| {
                    let name = p.file_name().unwrap().to_string_lossy().into_owned();
                    let name = if sub.is_empty() {
                        name
                    } else {
                        format!("{sub}/{name}")
                    };
                    (name, std::fs::read_to_string(&p).unwrap())
                })
        })
        .collect();
    v.sort();
    v
}

/// Loads without letting a panic escape; the panic's message otherwise.
/// A scenario that loads is also described (`brisance check`), which must
/// not panic either.
fn load_caught(file: &str, text: &str, sets: &[String]) -> Result<Result<(), ConfigError>, String> {
    catch_unwind(AssertUnwindSafe(|| {
        load_str(file, text, sets).map(|loaded| {
            brisance_compose::build::describe(&loaded.scenario);
        })
    }))
    .map_err(|p| {
        p.downcast_ref::<String>()
            .cloned()
            .or_else(|| p.downcast_ref::<&str>().map(|s| s.to_string()))
            .unwrap_or_else(|| "a panic".into())
    })
}

/// The check every generated case passes: no panic, and an error says
/// where (a position in the file or a field path).
fn no_panic_and_located(file: &str, text: &str, sets: &[String]) -> Result<(), TestCaseError> {
    match load_caught(file, text, sets) {
        Err(panic) => Err(TestCaseError::fail(format!(
            "panicked: {panic}\n--set {sets:?}\n--- text ---\n{text}"
        ))),
        Ok(Err(e)) if e.position.is_none() && e.field.is_none() => Err(TestCaseError::fail(
            format!("error names neither a position nor a field: {e}\n--- text ---\n{text}"),
        )),
        Ok(_) => Ok(()),
    }
}

#[test]
fn every_shipped_config_loads() {
    for (name, text) in shipped() {
        if let Err(e) = load_str(&name, &text, &[]) {
            panic!("{name}: {e}");
        }
    }
}

#[test]
fn a_renamed_material_in_the_bridge_config_is_a_located_error() {
    let text = std::fs::read_to_string(configs_dir().join("plate_case2.ron")).unwrap();
    let renamed = text.replace("\"rha\": (", "\"armour\": (");
    assert_ne!(renamed, text);
    let err = load_caught("plate_case2.ron", &renamed, &[])
        .expect("no panic")
        .unwrap_err();
    assert_eq!(err.field.as_deref(), Some("initial.1.material"), "{err}");
    let line = renamed
        .lines()
        .position(|l| l.contains("material: \"rha\""))
        .unwrap()
        + 1;
    assert_eq!(err.position.map(|p| p.0), Some(line), "{err}");
    let shown = err.to_string();
    assert!(
        shown.starts_with(&format!("plate_case2.ron:{line}:")),
        "{shown}"
    );
    assert!(shown.contains("unknown material `rha`"), "{shown}");
}

#[test]
fn renaming_any_material_key_of_any_config_never_panics() {
    for (name, text) in shipped() {
        let loaded = load_str(&name, &text, &[]).unwrap();
        for key in loaded.scenario.materials.keys() {
            let renamed = text.replacen(&format!("{key:?}:"), "\"renamed_key\":", 1);
            match load_caught(&name, &renamed, &[]) {
                Err(panic) => panic!("{name}, `{key}` renamed: panicked: {panic}"),
                Ok(Err(e)) => assert!(
                    e.field.is_some() && e.position.is_some(),
                    "{name}, `{key}` renamed: {e}"
                ),
                Ok(Ok(())) => {}
            }
        }
    }
}

const SOD: &str = include_str!("../../../configs/sod.ron");

fn sod_with(sets: &[&str]) -> ConfigError {
    let sets: Vec<String> = sets.iter().map(|s| s.to_string()).collect();
    load_str("sod.ron", SOD, &sets).unwrap_err()
}

#[test]
fn non_physical_numbers_are_refused_at_load_with_their_field_and_line() {
    for (set, field) in [
        ("initial.0.state.density=-1.0", "initial.0.state.density"),
        ("initial.0.state.density=0.0", "initial.0.state.density"),
        ("initial.0.state.density=NaN", "initial.0.state.density"),
        ("initial.0.state.density=inf", "initial.0.state.density"),
        ("initial.0.state.pressure=-1.0", "initial.0.state.pressure"),
        ("initial.0.state.pressure=NaN", "initial.0.state.pressure"),
        ("time.end=0.0", "time.end"),
        ("time.end=-1.0", "time.end"),
        ("time.end=inf", "time.end"),
        ("time.cfl=0.0", "time.cfl"),
        ("time.cfl=1.5", "time.cfl"),
        ("time.cfl=NaN", "time.cfl"),
        ("domain.upper=(0.0, 1.0, 1.0)", "domain.upper.0"),
        ("domain.upper=(inf, 1.0, 1.0)", "domain.upper.0"),
    ] {
        let err = sod_with(&[set]);
        assert_eq!(err.field.as_deref(), Some(field), "{set}: {err}");
        assert!(err.position.is_some(), "{set}: {err}");
    }
}

#[test]
fn a_region_entirely_outside_the_domain_is_refused() {
    for region in [
        "Box(min: (2.0, -1.0, -1.0), max: (3.0, 1.0, 1.0))",
        "Sphere(centre: (-5.0, 0.0, 0.0), radius: 1.0)",
        "Cylinder(base: (0.5, 5.0, 0.0), axis: (0.0, 1.0, 0.0), radius: 0.1, length: 1.0)",
        "Shell(base: (0.5, 0.0, 9.0), axis: (0.0, 0.0, 2.0), inner_radius: 0.1, outer_radius: 0.2, length: 1.0)",
        "HalfSpace(point: (2.0, 0.0, 0.0), normal: (1.0, 0.0, 0.0))",
    ] {
        let err = sod_with(&[&format!("initial.1.region={region}")]);
        assert_eq!(err.field.as_deref(), Some("initial.1.region"), "{region}: {err}");
        assert!(err.message.contains("outside the domain"), "{err}");
        assert!(err.position.is_some(), "{err}");
    }
    // Touching or crossing the domain is fine.
    for region in [
        "Box(min: (0.9, -1.0, -1.0), max: (3.0, 1.0, 1.0))",
        "HalfSpace(point: (0.5, 0.0, 0.0), normal: (-1.0, 0.0, 0.0))",
        "Sphere(centre: (1.5, 0.0, 0.0), radius: 1.0)",
    ] {
        let sets = [format!("initial.1.region={region}")];
        load_str("sod.ron", SOD, &sets).unwrap_or_else(|e| panic!("{region}: {e}"));
    }
}

#[test]
fn a_gauge_outside_the_domain_is_an_error() {
    let err = sod_with(&[
        "outputs.gauges=[(name: \"g\", point: (1.5, 0.0, 0.0), fields: [\"pressure\"])]",
    ]);
    assert_eq!(
        err.field.as_deref(),
        Some("outputs.gauges.0.point"),
        "{err}"
    );
    assert!(err.message.contains("outside the domain"), "{err}");
}

#[test]
fn a_plot_must_draw_columns_its_gauges_write() {
    let plot = |series: &str| {
        format!("outputs.plots=[(name: \"p\", y_label: \"p [Pa]\", series: [{series}])]")
    };
    let ok = plot("(from: Gauge(\"x0_75\"), column: \"pressure\")");
    let loaded = load_str("sod.ron", SOD, &[ok]).unwrap();
    assert_eq!(loaded.scenario.outputs.plots[0].series[0].scale, 1.0);
    for (series, field, words) in [
        (
            "(from: Gauge(\"nowhere\"), column: \"pressure\")",
            "outputs.plots.0.series.0.from",
            "no point gauge `nowhere`",
        ),
        (
            "(from: Gauge(\"x0_75\"), column: \"temperature\")",
            "outputs.plots.0.series.0.column",
            "its columns: density, pressure, velocity_x",
        ),
        (
            "(from: ParticleGauge(\"x0_75\"), column: \"pressure\")",
            "outputs.plots.0.series.0.from",
            "no particle gauge `x0_75`",
        ),
        (
            "(from: Gauge(\"x0_75\"), column: \"pressure\", scale: 0.0)",
            "outputs.plots.0.series.0.scale",
            "non-zero",
        ),
    ] {
        let err = sod_with(&[&plot(series)]);
        assert_eq!(err.field.as_deref(), Some(field), "{err}");
        assert!(err.message.contains(words), "{err}");
    }
    let err = sod_with(&["outputs.plots=[(name: \"a/b\", y_label: \"y\", series: [])]"]);
    assert_eq!(err.field.as_deref(), Some("outputs.plots.0.name"), "{err}");
    let err = sod_with(&["outputs.plots=[(name: \"p\", y_label: \"y\", series: [])]"]);
    assert_eq!(
        err.field.as_deref(),
        Some("outputs.plots.0.series"),
        "{err}"
    );
}

#[test]
fn an_unused_material_is_a_located_warning_not_an_error() {
    let text = SOD.replacen(
        "materials: {",
        "materials: {\n        \"spare\": (library: \"air\"),",
        1,
    );
    assert_ne!(text, SOD);
    let loaded = load_str("sod.ron", &text, &[]).unwrap();
    assert_eq!(loaded.warnings.len(), 1, "{:?}", loaded.warnings);
    let w = &loaded.warnings[0];
    assert_eq!(w.field.as_deref(), Some("materials.spare"));
    let line = text.lines().position(|l| l.contains("\"spare\"")).unwrap() + 1;
    assert_eq!(w.position.map(|p| p.0), Some(line), "{w}");
    assert!(w.message.contains("nothing uses it"), "{w}");
    // No shipped scenario defines a material it does not use.
    for (name, text) in shipped() {
        let loaded = load_str(&name, &text, &[]).unwrap();
        assert!(loaded.warnings.is_empty(), "{name}: {:?}", loaded.warnings);
    }
}

// ---- generated input ----

/// Values a mutation writes in place of a number.
const NASTY_NUMBERS: &[&str] = &[
    "NaN",
    "inf",
    "-inf",
    "-1",
    "-1.0",
    "0",
    "0.0",
    "1e308",
    "-1e308",
    "1e-320",
    "18446744073709551615",
    "18446744073709551616",
    "99999999999999999999999",
    "-0.0",
];

/// Byte ranges of the numbers in `text` (digits, with sign, point and
/// exponent), skipping comments only roughly; enough to aim mutations.
fn number_spans(text: &str) -> Vec<(usize, usize)> {
    let b = text.as_bytes();
    let mut spans = Vec::new();
    let mut i = 0;
    while i < b.len() {
        let starts = b[i].is_ascii_digit()
            && (i == 0 || !(b[i - 1].is_ascii_alphanumeric() || b[i - 1] == b'_'));
        if starts {
            let s = if i > 0 && b[i - 1] == b'-' { i - 1 } else { i };
            let mut e = i;
            while e < b.len()
                && (b[e].is_ascii_digit()
                    || b[e] == b'.'
                    || b[e] == b'e'
                    || b[e] == b'E'
                    || ((b[e] == b'-' || b[e] == b'+') && matches!(b[e - 1], b'e' | b'E')))
            {
                e += 1;
            }
            spans.push((s, e));
            i = e;
        } else {
            i += 1;
        }
    }
    spans
}

/// Byte ranges of the whitespace-separated tokens of `text`.
fn token_spans(text: &str) -> Vec<(usize, usize)> {
    let mut spans = Vec::new();
    let mut start = None;
    for (i, c) in text.char_indices() {
        match (c.is_whitespace(), start) {
            (true, Some(s)) => {
                spans.push((s, i));
                start = None;
            }
            (false, None) => start = Some(i),
            _ => {}
        }
    }
    if let Some(s) = start {
        spans.push((s, text.len()));
    }
    spans
}

/// One mutation of a config's text; indices are taken modulo the sizes.
#[derive(Debug, Clone)]
enum Mutation {
    /// XOR one byte (the text is read back lossily as UTF-8).
    FlipByte(usize, u8),
    /// Keep only the first bytes.
    Truncate(usize),
    /// Exchange two whitespace-separated tokens.
    SwapTokens(usize, usize),
    /// Replace a number by one of [`NASTY_NUMBERS`].
    Number(usize, usize),
    /// Delete a token.
    DeleteToken(usize),
}

fn mutation() -> impl Strategy<Value = Mutation> {
    prop_oneof![
        (any::<usize>(), 1u8..=255).prop_map(|(i, x)| Mutation::FlipByte(i, x)),
        any::<usize>().prop_map(Mutation::Truncate),
        (any::<usize>(), any::<usize>()).prop_map(|(a, b)| Mutation::SwapTokens(a, b)),
        (any::<usize>(), any::<usize>()).prop_map(|(a, b)| Mutation::Number(a, b)),
        any::<usize>().prop_map(Mutation::DeleteToken),
    ]
}

fn apply(text: &str, m: &Mutation) -> String {
    let replace =
        |(s, e): (usize, usize), with: &str| format!("{}{with}{}", &text[..s], &text[e..]);
    match *m {
        Mutation::FlipByte(i, x) => {
            let mut b = text.as_bytes().to_vec();
            let i = i % b.len();
            b[i] ^= x;
            String::from_utf8_lossy(&b).into_owned()
        }
        Mutation::Truncate(n) => {
            let mut n = n % text.len();
            while !text.is_char_boundary(n) {
                n -= 1;
            }
            text[..n].to_string()
        }
        Mutation::SwapTokens(a, b) => {
            let t = token_spans(text);
            if t.is_empty() {
                return text.to_string();
            }
            let (mut x, mut y) = (t[a % t.len()], t[b % t.len()]);
            if x.0 > y.0 {
                std::mem::swap(&mut x, &mut y);
            }
            if x == y {
                return text.to_string();
            }
            format!(
                "{}{}{}{}{}",
                &text[..x.0],
                &text[y.0..y.1],
                &text[x.1..y.0],
                &text[x.0..x.1],
                &text[y.1..]
            )
        }
        Mutation::Number(i, k) => {
            let n = number_spans(text);
            if n.is_empty() {
                return text.to_string();
            }
            replace(n[i % n.len()], NASTY_NUMBERS[k % NASTY_NUMBERS.len()])
        }
        Mutation::DeleteToken(i) => {
            let t = token_spans(text);
            if t.is_empty() {
                return text.to_string();
            }
            replace(t[i % t.len()], "")
        }
    }
}

/// Path pieces `--set` overrides are built from: real fields, indices in
/// and out of range, and malformed pieces.
const PATH_PIECES: &[&str] = &[
    "domain",
    "cells",
    "lower",
    "upper",
    "patches",
    "0",
    "1",
    "2",
    "7",
    "99",
    "time",
    "end",
    "cfl",
    "max_steps",
    "materials",
    "gas",
    "air",
    "eos",
    "gamma",
    "pipeline",
    "material",
    "initial",
    "region",
    "state",
    "density",
    "pressure",
    "outputs",
    "gauges",
    "interval",
    "fields",
    "point",
    "boundaries",
    "x_low",
    "",
    " ",
    "-1",
    "18446744073709551616",
    "é",
    "\"",
    "(",
    ")",
    "[",
    "]",
];

const SET_VALUES: &[&str] = &[
    "1",
    "0",
    "-1",
    "NaN",
    "inf",
    "1e308",
    "(1, 1, 1)",
    "(0, 0, 0)",
    "[]",
    "()",
    "\"x\"",
    "Reflective",
    "Box(min: (0, 0, 0), max: (1, 1, 1))",
    "",
    "(",
    ")",
    "[1,",
    "\"",
    "Some(0)",
    "None",
    "{}",
    "18446744073709551616",
];

fn set_arg() -> impl Strategy<Value = String> {
    (
        proptest::collection::vec(0..PATH_PIECES.len(), 1..5),
        0..SET_VALUES.len(),
    )
        .prop_map(|(path, v)| {
            let path: Vec<&str> = path.iter().map(|&i| PATH_PIECES[i]).collect();
            format!("{}={}", path.join("."), SET_VALUES[v])
        })
}

/// Runs the generated cases: `cases` mutated texts (1 to 3 mutations of a
/// shipped config) and `cases` sets of `--set` overrides; returns the
/// number of loads.
fn fuzz(cases: u32) -> u64 {
    let configs = shipped();
    let n = configs.len();
    let loads = std::cell::Cell::new(0u64);
    let runner = || {
        TestRunner::new(Config {
            cases,
            failure_persistence: None,
            ..Config::default()
        })
    };
    runner()
        .run(
            &(0..n, proptest::collection::vec(mutation(), 1..4)),
            |(k, mutations)| {
                let (name, text) = &configs[k];
                let mut text = text.clone();
                for m in &mutations {
                    if text.is_empty() {
                        break;
                    }
                    text = apply(&text, m);
                }
                loads.set(loads.get() + 1);
                no_panic_and_located(name, &text, &[])
            },
        )
        .unwrap();
    runner()
        .run(
            &(0..n, proptest::collection::vec(set_arg(), 1..3)),
            |(k, sets)| {
                let (name, text) = &configs[k];
                loads.set(loads.get() + 1);
                no_panic_and_located(name, text, &sets)
            },
        )
        .unwrap();
    loads.get()
}

#[test]
fn generated_bad_input_never_panics_and_every_error_is_located() {
    let loads = fuzz(256);
    assert!(loads >= 512, "{loads}");
}

/// The long run: `cargo test -p brisance-compose --test load_robustness
/// -- --ignored --nocapture`; `BRISANCE_FUZZ_CASES` sets the cases per
/// generator (default 20000).
#[test]
#[ignore]
fn generated_bad_input_long_run() {
    let cases = std::env::var("BRISANCE_FUZZ_CASES")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(20_000);
    let start = std::time::Instant::now();
    let loads = fuzz(cases);
    println!(
        "{loads} loads of generated input in {:.1} s, no panic, every error located",
        start.elapsed().as_secs_f64()
    );
}

/// What the generated runs found, kept as fixed cases (docs/testing.md).
#[test]
fn inputs_the_generated_runs_found_are_located_errors() {
    for (config, sets, field) in [
        // A spacing tiny beside the domain overflowed the node count.
        (
            "lattice_impact.ron",
            &["pipeline.spacing=1e-300"][..],
            "pipeline.spacing",
        ),
        (
            "lattice_burn.ron",
            &["pipeline.spacing=5e-324"][..],
            "pipeline.spacing",
        ),
        // A cell count whose product overflows loaded, then panicked in
        // `brisance check`'s description (and could not run).
        (
            "fdm_products_tube.ron",
            &["domain.cells=(200, 18446744073709551615, 1)"][..],
            "domain.cells",
        ),
        (
            "sod.ron",
            &["domain.cells=(100000, 100000, 100000)"][..],
            "domain.cells",
        ),
    ] {
        let text = std::fs::read_to_string(configs_dir().join(config)).unwrap();
        let sets: Vec<String> = sets.iter().map(|s| s.to_string()).collect();
        let err = load_caught(config, &text, &sets)
            .unwrap_or_else(|p| panic!("{config} {sets:?}: panicked: {p}"))
            .unwrap_err();
        assert_eq!(err.field.as_deref(), Some(field), "{err}");
        assert!(err.position.is_some(), "{err}");
    }
}

#[test]
fn a_stated_charge_is_checked_at_load_with_its_field_and_line() {
    let text = include_str!("../../../configs/blast2d.ron");
    let line = text.lines().position(|l| l.contains("charge:")).unwrap() + 1;
    let charge = |explosive: &str, time: &str| {
        format!(
            "pipeline.charge=Some(explosive: \"{explosive}\", symmetry: Cylindrical, centre: (0.0, 0.25, 0.0), radius: 0.05, radius_1d: 0.11, cells_1d: 880, time: {time})"
        )
    };
    for (sets, words) in [
        (vec![charge("rdx", "1.2e-5")], "knows TNT"),
        (vec![charge("tnt", "-1.0")], "time = -1"),
        (
            vec!["pipeline.remap=Some(\"x.bin\")".to_string()],
            "not both",
        ),
    ] {
        let err = load_str("blast2d.ron", text, &sets).unwrap_err();
        assert_eq!(err.field.as_deref(), Some("pipeline.charge"), "{err}");
        assert_eq!(err.position.map(|p| p.0), Some(line), "{err}");
        assert!(err.message.contains(words), "{err}");
    }
    load_str("blast2d.ron", text, &[]).unwrap();
}

/// The pure-MPM remap states its charge as the bridge does: checked at
/// load under `pipeline.remap.charge` with its line, one of `file` and
/// `charge` required, not both.
#[test]
fn a_charge_of_the_mpm_remap_is_checked_at_load_with_its_field_and_line() {
    let text = include_str!("../../../configs/blast2d_mpm.ron");
    let line = text.lines().position(|l| l.contains("charge:")).unwrap() + 1;
    let charge = |explosive: &str, time: &str| {
        format!(
            "pipeline.remap.charge=Some(explosive: \"{explosive}\", symmetry: Cylindrical, centre: (0.0, 0.25, 0.0), radius: 0.05, radius_1d: 0.11, cells_1d: 880, time: {time})"
        )
    };
    for (sets, words) in [
        (vec![charge("rdx", "1.2e-5")], "knows TNT"),
        (vec![charge("tnt", "-1.0")], "time = -1"),
        (
            vec!["pipeline.remap.file=Some(\"x.bin\")".to_string()],
            "not both",
        ),
    ] {
        let err = load_str("blast2d_mpm.ron", text, &sets).unwrap_err();
        assert_eq!(err.field.as_deref(), Some("pipeline.remap.charge"), "{err}");
        assert_eq!(err.position.map(|p| p.0), Some(line), "{err}");
        assert!(err.message.contains(words), "{err}");
    }
    let err = load_str(
        "blast2d_mpm.ron",
        text,
        &["pipeline.remap.charge=None".to_string()],
    )
    .unwrap_err();
    assert_eq!(err.field.as_deref(), Some("pipeline.remap"), "{err}");
    assert!(err.message.contains("`file` or the `charge`"), "{err}");
    load_str("blast2d_mpm.ron", text, &[]).unwrap();
}

/// Every shipped scenario runs from a fresh checkout: none names a remap
/// file (which a separate command would have to make first); the ones
/// that start from a detonation state their charge.
#[test]
fn no_shipped_config_needs_a_file_made_by_another_command() {
    let mut charged = 0;
    for (name, text) in shipped() {
        let loaded = load_str(&name, &text, &[]).unwrap_or_else(|e| panic!("{e}"));
        let pipeline = &loaded.scenario.pipeline;
        if let Some(b) = pipeline.section::<brisance_couple::BridgeConfig>() {
            assert!(b.remap.is_none(), "{name} names a remap file");
            charged += usize::from(b.charge.is_some());
        }
        if let Some(m) = pipeline.section::<brisance_couple::MpmConfig>() {
            if let Some(r) = &m.remap {
                assert!(r.file.is_none(), "{name} names a remap file");
                charged += usize::from(r.charge.is_some());
            }
        }
    }
    // blast2d, blast2d_mpm, the six plate cases in 3D and in (r, z), and
    // the two slabs.
    assert_eq!(charged, 16);
}
