//! Reading a scenario: RON text → `--set` overrides → serde → validation,
//! with every error located at file:line:column.

use std::path::Path;

use ron::extensions::Extensions;

use crate::build::pipeline_limits;
use crate::config::Scenario;
use crate::error::ConfigError;
use crate::ron_path;
use crate::validate::validate;

/// The built-in default scenario (`brisance run` with no config): a 2D
/// cylindrical blast wave in air reflecting from walls.
pub const DEFAULT_SCENARIO: &str = include_str!("../../../configs/default.ron");

/// Name shown for the built-in scenario in messages.
pub const DEFAULT_SCENARIO_NAME: &str = "<built-in default scenario>";

/// A parsed, overridden and validated scenario with the text it came from.
#[derive(Debug, Clone)]
pub struct LoadedScenario {
    /// The file it came from (or [`DEFAULT_SCENARIO_NAME`]).
    pub file: String,
    /// The RON text after `--set` overrides.
    pub text: String,
    /// The scenario.
    pub scenario: Scenario,
}

/// RON options shared by every reader: `Some(x)` may be written `x`, and
/// `Variant((fields))` may be written `Variant(fields)`.
pub fn ron_options() -> ron::Options {
    ron::Options::default()
        .with_default_extension(Extensions::IMPLICIT_SOME | Extensions::UNWRAP_VARIANT_NEWTYPES)
}

/// Reads and validates a scenario file, applying `PATH=VALUE` overrides.
pub fn load_file(path: &Path, sets: &[String]) -> Result<LoadedScenario, ConfigError> {
    let file = path.display().to_string();
    let text = std::fs::read_to_string(path).map_err(|e| ConfigError {
        file: file.clone(),
        position: None,
        field: None,
        message: format!("cannot read the file: {e}"),
    })?;
    load_str(&file, &text, sets)
}

/// Parses and validates scenario text, applying `PATH=VALUE` overrides.
pub fn load_str(file: &str, text: &str, sets: &[String]) -> Result<LoadedScenario, ConfigError> {
    let mut text = text.to_string();
    for set in sets {
        let Some((path, value)) = set.split_once('=') else {
            return Err(ConfigError {
                file: "--set".into(),
                position: None,
                field: None,
                message: format!(
                    "`{set}` is not of the form PATH=VALUE (e.g. domain.cells=(800,1,1))"
                ),
            });
        };
        text = ron_path::set(&text, path.trim(), value.trim()).map_err(|message| ConfigError {
            file: "--set".into(),
            position: None,
            field: Some(path.trim().to_string()),
            message: format!("{message} (in {file})"),
        })?;
    }
    let suffix = if sets.is_empty() {
        ""
    } else {
        " (after --set overrides)"
    };
    let scenario: Scenario = ron_options().from_str(&text).map_err(|e| ConfigError {
        file: file.to_string(),
        position: Some((e.span.start.line, e.span.start.col)),
        field: None,
        message: format!("{}{suffix}", e.code),
    })?;
    let (fields, max_cfl) = pipeline_limits(&scenario.pipeline);
    validate(&scenario, fields, max_cfl).map_err(|(path, message)| ConfigError {
        file: file.to_string(),
        position: ron_path::find_nearest(&text, &path).map(|r| ron_path::line_col(&text, r.start)),
        field: Some(path),
        message: format!("{message}{suffix}"),
    })?;
    Ok(LoadedScenario {
        file: file.to_string(),
        text,
        scenario,
    })
}
