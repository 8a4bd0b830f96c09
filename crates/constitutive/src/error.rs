//! Errors of the constitutive models.

/// Why a constitutive model's parameters were rejected, or why a stress
/// update could not use the kinematics it was given.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ConstitutiveError {
    /// A parameter is outside its allowed range; names the model and field.
    #[error("{model}: field `{field}` = {value}, expected {expected}")]
    InvalidParameter {
        /// Registry name of the model.
        model: &'static str,
        /// The offending field, as a config writes it.
        field: &'static str,
        /// The value found.
        value: f64,
        /// What was expected, in words with units.
        expected: &'static str,
    },
    /// The equation of state of the model failed its own validation.
    #[error("{model}: field `pressure`: {detail}")]
    Eos {
        /// Registry name of the model.
        model: &'static str,
        /// The EOS's message (names its own field).
        detail: String,
    },
    /// A plugin model's parameters failed its own check
    /// ([`crate::plugin::PluginMaterial::validate`]).
    #[error("{detail}")]
    Plugin {
        /// The name the plugin registered (`SteinbergGuinan`).
        model: &'static str,
        /// The plugin's message (names its own field).
        detail: String,
    },
    /// `I − ½ L Δt` is singular: the step is far too large for the
    /// velocity gradient (an eigenvalue of L Δt equals 2).
    #[error(
        "incremental deformation gradient is singular (step too large for the velocity gradient)"
    )]
    SingularIncrement,
    /// The deformation gradient has det F ≤ 0 (an inverted point) or is not
    /// finite, so it has no polar decomposition with a proper rotation.
    #[error("deformation gradient has det F = {det} (must be finite and > 0)")]
    InvertedDeformation {
        /// The determinant found.
        det: f64,
    },
}

/// Checks that `value` of `field` of `model` is finite and > 0; the
/// error names the field (for plugin models as for the built-in ones).
pub fn positive(
    model: &'static str,
    field: &'static str,
    value: f64,
) -> Result<(), ConstitutiveError> {
    if value.is_finite() && value > 0.0 {
        Ok(())
    } else {
        Err(ConstitutiveError::InvalidParameter {
            model,
            field,
            value,
            expected: "a finite value > 0",
        })
    }
}

/// Checks that `value` of `field` of `model` is finite and ≥ 0; the
/// error names the field.
pub fn non_negative(
    model: &'static str,
    field: &'static str,
    value: f64,
) -> Result<(), ConstitutiveError> {
    if value.is_finite() && value >= 0.0 {
        Ok(())
    } else {
        Err(ConstitutiveError::InvalidParameter {
            model,
            field,
            value,
            expected: "a finite value ≥ 0",
        })
    }
}
