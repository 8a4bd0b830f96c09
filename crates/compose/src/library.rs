//! The material library: named materials (`configs/materials/*.ron`,
//! embedded at build time) that a scenario references with
//! `(library: "tnt")` instead of repeating parameters.
//!
//! An entry carries an equation of state (for the Eulerian solvers and for
//! temperatures), a constitutive model (for particle pipelines), or both.
//! A scenario material that names an entry takes both; it may give its own
//! `model` instead of the entry's (the entry's EOS stays), but not its own
//! `eos` (then it should not name the entry).

use brisance_constitutive::MaterialModel;
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
    /// Its equation of state, if it has one on its own (the concrete of
    /// the HJC model carries its EOS inside its constitutive model).
    #[serde(default)]
    pub eos: Option<EosModel>,
    /// Its constitutive model for particle pipelines, if the library
    /// gives one.
    #[serde(default)]
    pub model: Option<MaterialModel>,
}

impl LibraryMaterial {
    /// Checks the entry: an EOS or a model (or both), each valid, and a
    /// positive density.
    pub fn validate(&self) -> Result<(), String> {
        if self.eos.is_none() && self.model.is_none() {
            return Err(format!(
                "library material `{}` gives neither `eos` nor `model`",
                self.name
            ));
        }
        if !(self.density > 0.0 && self.density.is_finite()) {
            return Err(format!(
                "library material `{}`: `density` must be positive, got {}",
                self.name, self.density
            ));
        }
        if let Some(eos) = &self.eos {
            eos.validate()
                .map_err(|e| format!("library material `{}`: eos: {e}", self.name))?;
        }
        if let Some(model) = &self.model {
            model
                .validate()
                .map_err(|e| format!("library material `{}`: model: {e}", self.name))?;
        }
        Ok(())
    }
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
            m.validate().unwrap_or_else(|e| panic!("{e}"));
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
            "steel_4340_cookoff",
            "rha_steel",
            "concrete_25mpa",
            "concrete_48mpa",
            "soil",
        ] {
            assert!(names().contains(&name), "missing {name}");
        }
        assert!(get("unobtainium").unwrap_err().contains("known: air"));
    }

    #[test]
    fn the_cookoff_steel_entry_is_the_seed000_section_5_3_model() {
        let entry = get("steel_4340_cookoff").unwrap();
        assert_eq!(
            entry.model,
            Some(MaterialModel::ElasticPlastic(
                brisance_constitutive::ElasticPlastic::steel_4340_cookoff_seed000()
            ))
        );
        assert_eq!(entry.eos, get("steel_4340").unwrap().eos);
    }

    #[test]
    fn an_entry_without_eos_or_model_or_with_a_bad_density_is_refused() {
        let mut m = get("soil").unwrap();
        m.model = None;
        assert!(m
            .validate()
            .unwrap_err()
            .contains("neither `eos` nor `model`"));
        let mut m = get("air").unwrap();
        m.density = -1.0;
        assert!(m.validate().unwrap_err().contains("`density`"));
    }
}
