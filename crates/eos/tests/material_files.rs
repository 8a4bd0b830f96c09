//! The material files in configs/materials parse into the EOS parameter
//! structs, validate, and the JWL products sets reproduce their published
//! CJ detonation velocity and pressure within 3 %.

use brisance_core::Eos;
use brisance_eos::tools::{chapman_jouguet, cj_on_jwl_cterm_isentrope, UnreactedState};
use brisance_eos::{IdealGas, Jwl, JwlCTerm, Murnaghan};
use ron::extensions::Extensions;
use serde::Deserialize;
use std::path::{Path, PathBuf};

/// Mirrors the registry enum the configuration layer builds.
#[derive(Debug, Deserialize)]
#[allow(dead_code)]
enum EosModel {
    IdealGas(IdealGas),
    Jwl(Jwl),
    JwlCTerm(JwlCTerm),
    Murnaghan(Murnaghan),
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
#[allow(dead_code)]
struct MaterialFile {
    name: String,
    description: String,
    source: String,
    density: f64,
    eos: EosModel,
    /// The constitutive model of a solid entry (read by the composer).
    #[serde(default)]
    model: Option<serde::de::IgnoredAny>,
}

fn materials_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../configs/materials")
}

fn load(name: &str) -> MaterialFile {
    let path = materials_dir().join(format!("{name}.ron"));
    let text = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{path:?}: {e}"));
    ron::Options::default()
        .with_default_extension(Extensions::IMPLICIT_SOME | Extensions::UNWRAP_VARIANT_NEWTYPES)
        .from_str(&text)
        .unwrap_or_else(|e| panic!("{path:?}: {e}"))
}

/// The detonation material files this crate's models read (other files in
/// the directory belong to other models).
const DETONATION_MATERIALS: [&str; 7] = [
    "tnt",
    "pbx_9501",
    "petn",
    "anfo_k1_reactant",
    "anfo_k1_products",
    "qm100_reactant",
    "qm100_products",
];

#[test]
fn detonation_material_files_parse_validate_and_are_named_for_their_file() {
    for stem in DETONATION_MATERIALS {
        let m = load(stem);
        assert_eq!(m.name, stem);
        let (check, rho0) = match &m.eos {
            EosModel::IdealGas(g) => (Ok(()), g.rho0),
            EosModel::Jwl(j) => (j.validate(), j.rho0),
            EosModel::JwlCTerm(j) => (j.validate(), j.rho0),
            EosModel::Murnaghan(j) => (j.validate(), j.rho0),
        };
        check.unwrap_or_else(|e| panic!("{stem}: {e}"));
        assert_eq!(m.density, rho0, "{stem}: density and eos rho0 differ");
    }
}

#[test]
fn shipped_files_equal_the_constructors() {
    match load("tnt").eos {
        EosModel::Jwl(j) => assert_eq!(j, Jwl::tnt()),
        other => panic!("tnt: {other:?}"),
    }
    match load("anfo_k1_products").eos {
        EosModel::JwlCTerm(j) => assert_eq!(j, JwlCTerm::anfo_k1()),
        other => panic!("{other:?}"),
    }
    match load("qm100_products").eos {
        EosModel::JwlCTerm(j) => assert_eq!(j, JwlCTerm::qm100()),
        other => panic!("{other:?}"),
    }
    match load("anfo_k1_reactant").eos {
        EosModel::Murnaghan(m) => assert_eq!(m, Murnaghan::anfo_k1()),
        other => panic!("{other:?}"),
    }
    match load("qm100_reactant").eos {
        EosModel::Murnaghan(m) => assert_eq!(m, Murnaghan::qm100()),
        other => panic!("{other:?}"),
    }
}

/// Published D (m/s) and P_CJ (Pa) of the LLNL Explosives Handbook JWL sets
/// (Dobratz & Crawford 1985) shipped in configs/materials.
const PUBLISHED_CJ: [(&str, f64, f64); 3] = [
    ("tnt", 6930.0, 21.0e9),
    ("pbx_9501", 8800.0, 37.0e9),
    ("petn", 8300.0, 33.5e9),
];

#[test]
fn jwl_material_files_reproduce_their_published_cj_state_within_three_percent() {
    for (name, d_pub, p_pub) in PUBLISHED_CJ {
        let EosModel::Jwl(j) = load(name).eos else {
            panic!("{name} is not a JWL file");
        };
        let u = UnreactedState {
            density: j.rho0,
            specific_internal_energy: j.specific_detonation_energy(),
            pressure: 0.0,
        };
        let cj = chapman_jouguet(&j, &u).unwrap();
        let d_err = (cj.detonation_velocity - d_pub).abs() / d_pub;
        let p_err = (cj.pressure - p_pub).abs() / p_pub;
        println!(
            "{name}: D = {:.1} m/s ({:+.2} %), P_CJ = {:.3} GPa ({:+.2} %)",
            cj.detonation_velocity,
            100.0 * (cj.detonation_velocity / d_pub - 1.0),
            cj.pressure / 1e9,
            100.0 * (cj.pressure / p_pub - 1.0)
        );
        assert!(d_err < 0.03 && p_err < 0.03, "{name}: {cj:?}");
    }
}

#[test]
fn jwl_cterm_products_files_have_a_cj_state() {
    for name in ["anfo_k1_products", "qm100_products"] {
        let EosModel::JwlCTerm(m) = load(name).eos else {
            panic!("{name} is not a C-term file");
        };
        let cj = cj_on_jwl_cterm_isentrope(&m).unwrap();
        assert!(m.pressure(cj.density, cj.specific_internal_energy) > 0.0);
        println!("{name}: {cj:?}");
    }
}
