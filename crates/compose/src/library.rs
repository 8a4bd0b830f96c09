//! The material library: named materials (`configs/materials/*.ron`,
//! embedded at build time) that a scenario references with
//! `(library: "tnt")` instead of repeating parameters.

use brisance_eos::EosModel;
use serde::Deserialize;

use crate::load::ron_options;

include!(concat!(env!("OUT_DIR"), "/materials.rs"));

/// One library material.
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LibraryMaterial {
    /// Name (the file stem).
    pub name: String,
    /// One line on what it is.
    pub description: String,
    /// Where the parameters come from.
    pub source: String,
    /// Nominal initial density, kg/m³.
    pub density: f64,
    /// Its equation of state.
    pub eos: EosModel,
}

/// Names of every library material.
pub fn names() -> Vec<&'static str> {
    LIBRARY.iter().map(|(n, _)| *n).collect()
}

/// The library material `name`, or an error listing the known names.
pub fn get(name: &str) -> Result<LibraryMaterial, String> {
    let (_, text) = LIBRARY.iter().find(|(n, _)| *n == name).ok_or_else(|| {
        format!(
            "no library material `{name}`; known: {}",
            names().join(", ")
        )
    })?;
    ron_options()
        .from_str(text)
        .map_err(|e| format!("library material `{name}` does not parse: {e}"))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_library_file_parses_validates_and_is_named_after_its_file() {
        assert!(!LIBRARY.is_empty());
        for name in names() {
            let m = get(name).unwrap();
            assert_eq!(m.name, name, "file {name}.ron names itself `{}`", m.name);
            m.eos.validate().unwrap_or_else(|e| panic!("{name}: {e}"));
            assert!(m.density > 0.0);
        }
    }

    #[test]
    fn the_library_holds_the_seed_materials() {
        for name in [
            "air",
            "tnt",
            "anfo_k1_reactant",
            "anfo_k1_products",
            "qm100_products",
            "ofhc_copper",
            "steel_4340",
        ] {
            assert!(names().contains(&name), "missing {name}");
        }
        assert!(get("unobtainium").unwrap_err().contains("known: air"));
    }
}
