//! The README and the user guide name every pipeline, every registered
//! model and every subcommand the program has: the lists are read from the
//! program itself (the model enums' own "expected one of", the registry
//! with its plugin models and pipelines, `brisance --help`), so a new
//! variant or plugin crate that the docs miss fails here.

use brisance_compose::registry::entries;
use brisance_constitutive::MaterialModel;
use brisance_eos::EosModel;
use serde::de::DeserializeOwned;
use std::process::Command;

/// The variant names of enum `T` as its deserializer lists them when
/// given a name it does not know.
fn variants<T: DeserializeOwned + std::fmt::Debug>() -> Vec<String> {
    let err = ron::from_str::<T>("NoSuchVariantAtAll")
        .unwrap_err()
        .to_string();
    let list = err
        .split("expected one of")
        .nth(1)
        .or_else(|| err.split("expected").nth(1))
        .unwrap_or_else(|| panic!("no variant list in `{err}`"));
    let names: Vec<String> = list
        .split('`')
        .skip(1)
        .step_by(2)
        .map(str::to_string)
        .collect();
    assert!(!names.is_empty(), "no variant list in `{err}`");
    names
}

fn docs() -> String {
    let root = env!("CARGO_MANIFEST_DIR");
    let read = |p: &str| std::fs::read_to_string(format!("{root}/{p}")).unwrap();
    read("README.md") + &read("docs/user-guide.md")
}

fn missing<'a>(names: impl IntoIterator<Item = &'a str>, docs: &str) -> Vec<&'a str> {
    names
        .into_iter()
        .filter(|n| !docs.contains(&format!("`{n}`")) && !docs.contains(&format!("{n}(")))
        .collect()
}

#[test]
fn every_pipeline_and_model_is_named_in_the_readme_or_the_user_guide() {
    let docs = docs();
    let mut names = Vec::new();
    // The pipelines are every registration's, in `entries` below.
    names.extend(variants::<EosModel>());
    names.extend(variants::<MaterialModel>());
    names.extend(entries().iter().map(|e| e.name.to_string()));
    names.sort();
    names.dedup();
    let gaps = missing(names.iter().map(String::as_str), &docs);
    assert!(
        gaps.is_empty(),
        "not named in README.md or docs/user-guide.md: {gaps:?}"
    );
}

#[test]
fn every_subcommand_is_named_in_the_readme_or_the_user_guide() {
    let out = Command::new(env!("CARGO_BIN_EXE_brisance"))
        .arg("--help")
        .output()
        .unwrap();
    let help = String::from_utf8(out.stdout).unwrap();
    let commands: Vec<&str> = help
        .split("Commands:")
        .nth(1)
        .expect("a Commands section")
        .split("\n\n")
        .next()
        .unwrap()
        .lines()
        .filter_map(|l| l.split_whitespace().next())
        .filter(|c| *c != "help")
        .collect();
    assert!(commands.contains(&"run"), "{help}");
    let docs = docs();
    let gaps: Vec<&&str> = commands
        .iter()
        .filter(|c| !docs.contains(&format!("brisance {c}")))
        .collect();
    assert!(
        gaps.is_empty(),
        "subcommands not shown in README.md or docs/user-guide.md: {gaps:?}"
    );
}
