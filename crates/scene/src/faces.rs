//! The scenario's boundary faces and thermodynamic states: the `boundaries`
//! section and the `state` of initial regions and `Fixed` faces, which
//! every grid pipeline reads, with the checks the pipelines share.

use brisance_core::Eos;
use serde::{Deserialize, Serialize};

use crate::FieldError;

/// Boundary conditions on the six faces.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, Default)]
#[serde(deny_unknown_fields, default)]
pub struct Boundaries {
    /// x = x_min
    pub x_low: BoundaryConfig,
    /// x = x_max
    pub x_high: BoundaryConfig,
    /// y = y_min
    pub y_low: BoundaryConfig,
    /// y = y_max
    pub y_high: BoundaryConfig,
    /// z = z_min
    pub z_low: BoundaryConfig,
    /// z = z_max
    pub z_high: BoundaryConfig,
}

/// Six open faces (`Outflow`), what a scenario without a `boundaries`
/// section has.
pub static OPEN_FACES: Boundaries = Boundaries {
    x_low: BoundaryConfig::Outflow,
    x_high: BoundaryConfig::Outflow,
    y_low: BoundaryConfig::Outflow,
    y_high: BoundaryConfig::Outflow,
    z_low: BoundaryConfig::Outflow,
    z_high: BoundaryConfig::Outflow,
};

impl Boundaries {
    /// The faces in storage order with their config names.
    pub fn faces(&self) -> [(&'static str, &BoundaryConfig); 6] {
        [
            ("x_low", &self.x_low),
            ("x_high", &self.x_high),
            ("y_low", &self.y_low),
            ("y_high", &self.y_high),
            ("z_low", &self.z_low),
            ("z_high", &self.z_high),
        ]
    }

    /// Every face must be one of `accepted` (config names) for the
    /// pipeline `pipeline`; otherwise the error names the face
    /// (`boundaries.x_low`), says what the pipeline takes and adds
    /// `hint(condition)` (empty, or a sentence that starts with "; ").
    pub fn check_faces(
        &self,
        pipeline: &str,
        accepted: &[&str],
        hint: impl Fn(&BoundaryConfig) -> &'static str,
    ) -> Result<(), FieldError> {
        for (face, bc) in self.faces() {
            if !accepted.contains(&bc.name()) {
                return Err(FieldError::new(
                    format!("boundaries.{face}"),
                    format!(
                        "the {pipeline} pipeline takes {} faces, not `{}`{}",
                        either(accepted),
                        bc.name(),
                        hint(bc)
                    ),
                ));
            }
        }
        Ok(())
    }

    /// The faces as `x_low=outflow y_high=reflective …`, for the
    /// pipelines' descriptions.
    pub fn summary(&self) -> String {
        self.faces()
            .iter()
            .map(|(f, b)| format!("{f}={}", b.lower_name()))
            .collect::<Vec<_>>()
            .join(" ")
    }
}

/// `a`, `b` or `c`, each in backticks.
fn either(names: &[&str]) -> String {
    let quoted: Vec<String> = names.iter().map(|n| format!("`{n}`")).collect();
    match quoted.split_last() {
        Some((last, rest)) if !rest.is_empty() => format!("{} or {last}", rest.join(", ")),
        _ => quoted.join(""),
    }
}

/// The material of the state of `Fixed` face `face`: the one it names, or
/// the only one of `materials` (the pipeline's materials of that kind);
/// `kind` says what they are in the messages ("gas", "particle material").
pub fn fixed_face_material<'a>(
    face: &str,
    state: &'a StateConfig,
    materials: &'a [String],
    kind: &str,
) -> Result<&'a str, FieldError> {
    let listed = || {
        materials
            .iter()
            .map(|m| format!("`{m}`"))
            .collect::<Vec<_>>()
            .join(", ")
    };
    match (&state.material, materials) {
        // No material of that kind at all: say so rather than list none.
        (m, []) => Err(FieldError::new(
            if m.is_some() {
                format!("boundaries.{face}.material")
            } else {
                format!("boundaries.{face}")
            },
            format!(
                "the pipeline has no {kind}{} to fill this face's state",
                if kind == "particle material" {
                    " (a material with a constitutive `model`, e.g. `(model: Null(eos: ...))` for a gas)"
                } else {
                    ""
                }
            ),
        )),
        (Some(m), _) if materials.contains(m) => Ok(m),
        (Some(m), _) => Err(FieldError::new(
            format!("boundaries.{face}.material"),
            format!("`{m}` is not a {kind} of this pipeline; it has {}", listed()),
        )),
        (None, [only]) => Ok(only),
        (None, _) => Err(FieldError::new(
            format!("boundaries.{face}"),
            format!(
                "the pipeline carries several {kind}s ({}): say which fills this face's state, e.g. `Fixed(material: \"{}\", density: ..., pressure: ...)`",
                listed(),
                materials.first().map_or("", |m| m.as_str())
            ),
        )),
    }
}

/// One face's boundary condition. What each does in each pipeline, and
/// which pipeline takes which, is the boundary table of
/// `docs/user-guide.md`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, Default)]
pub enum BoundaryConfig {
    /// The default open face, each pipeline's own: `ZeroGradient` for Fdm
    /// (and the bridge's FDM region), `OutflowOnly` for Ice and IceMpm, and
    /// for Mpm a free face through which particles leave and are booked
    /// and none enter.
    #[default]
    Outflow,
    /// Transmissive both ways: what leaves goes freely, and where the flow
    /// at the face points inwards the boundary cell's state (for Mpm, that
    /// of the particles in it) enters.
    ZeroGradient,
    /// Zero gradient for what leaves; where the flow at the face points
    /// inwards the face holds it back, as a wall would.
    OutflowOnly,
    /// Slip wall / symmetry plane.
    Reflective,
    /// Periodic (set on both faces of the axis).
    Periodic,
    /// A fixed state beyond the face, which enters where its velocity
    /// points inwards (an inflow reservoir): Fdm, Ice, Mpm.
    Fixed(StateConfig),
    /// A rigid no-slip wall: every grid velocity component is zero (Mpm).
    Wall,
}

impl BoundaryConfig {
    /// The name a scenario writes.
    pub fn name(&self) -> &'static str {
        match self {
            Self::Outflow => "Outflow",
            Self::ZeroGradient => "ZeroGradient",
            Self::OutflowOnly => "OutflowOnly",
            Self::Reflective => "Reflective",
            Self::Periodic => "Periodic",
            Self::Fixed(_) => "Fixed",
            Self::Wall => "Wall",
        }
    }

    /// The name in the descriptions of `brisance check`
    /// (`zero_gradient`).
    pub fn lower_name(&self) -> &'static str {
        match self {
            Self::Outflow => "outflow",
            Self::ZeroGradient => "zero_gradient",
            Self::OutflowOnly => "outflow_only",
            Self::Reflective => "reflective",
            Self::Periodic => "periodic",
            Self::Fixed(_) => "fixed",
            Self::Wall => "wall",
        }
    }
}

/// A thermodynamic state: density, velocity and exactly one of pressure,
/// specific internal energy or temperature.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct StateConfig {
    /// Density, kg/m³.
    pub density: f64,
    /// Velocity, m/s.
    #[serde(default)]
    pub velocity: [f64; 3],
    /// Pressure, Pa.
    #[serde(default)]
    pub pressure: Option<f64>,
    /// Specific internal energy, J/kg.
    #[serde(default)]
    pub specific_internal_energy: Option<f64>,
    /// Temperature, K.
    #[serde(default)]
    pub temperature: Option<f64>,
    /// The material of a `Fixed` face's state (a key of `materials`),
    /// needed where the pipeline carries several; initial regions name
    /// theirs beside the state instead.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub material: Option<String>,
}

impl StateConfig {
    /// A positive, finite density, a finite velocity and exactly one of
    /// pressure, specific internal energy or temperature, positive and
    /// finite; the error names the field under `path` (`initial.0.state`,
    /// `boundaries.x_low`).
    pub fn check(&self, path: &str) -> Result<(), FieldError> {
        if !(self.density > 0.0 && self.density.is_finite()) {
            return Err(FieldError::new(
                format!("{path}.density"),
                format!("density must be positive and finite, got {}", self.density),
            ));
        }
        if !self.velocity.iter().all(|v| v.is_finite()) {
            return Err(FieldError::new(
                format!("{path}.velocity"),
                "velocity must be finite",
            ));
        }
        let given = [
            ("pressure", self.pressure),
            ("specific_internal_energy", self.specific_internal_energy),
            ("temperature", self.temperature),
        ];
        let mut given = given.iter().filter_map(|&(n, v)| v.map(|v| (n, v)));
        match (given.next(), given.next()) {
            (Some((name, v)), None) if !(v > 0.0 && v.is_finite()) => Err(FieldError::new(
                format!("{path}.{name}"),
                format!("{name} must be positive and finite, got {v}"),
            )),
            (Some(_), None) => Ok(()),
            (None, _) => Err(FieldError::new(
                path,
                "give one of `pressure`, `specific_internal_energy` or `temperature`",
            )),
            (Some(_), Some(_)) => Err(FieldError::new(
                path,
                "give only one of `pressure`, `specific_internal_energy` or `temperature`",
            )),
        }
    }

    /// The pressure of this state in a material of equation of state
    /// `eos`: the given one, or the EOS's at the given density and energy
    /// or temperature.
    pub fn pressure_in<E: Eos + ?Sized>(&self, eos: &E) -> Result<f64, String> {
        match (
            self.pressure,
            self.specific_internal_energy,
            self.temperature,
        ) {
            (Some(p), _, _) => Ok(p),
            (None, Some(e), _) => Ok(eos.pressure(self.density, e)),
            (None, None, Some(t)) => Ok(eos.pressure(
                self.density,
                eos.specific_internal_energy_from_temperature(self.density, t),
            )),
            _ => Err("no pressure, energy or temperature".into()),
        }
    }
}

#[cfg(test)]
mod tests {
    use brisance_eos::IdealGas;

    use super::*;

    fn state(p: Option<f64>, e: Option<f64>, t: Option<f64>) -> StateConfig {
        StateConfig {
            density: 2.0,
            velocity: [0.0; 3],
            pressure: p,
            specific_internal_energy: e,
            temperature: t,
            material: None,
        }
    }

    /// The pressure is the given one, else (γ − 1) ρ e of the given energy,
    /// else of the temperature's energy e = c_v T.
    #[test]
    fn a_state_has_its_pressure_from_whichever_it_gives() {
        let gas = IdealGas::new(1.4, 1000.0, 1.0);
        assert_eq!(state(Some(3.0), None, None).pressure_in(&gas), Ok(3.0));
        let p = state(None, Some(5.0e5), None).pressure_in(&gas).unwrap();
        assert!((p - 0.4 * 2.0 * 5.0e5).abs() <= 1e-9 * p);
        let p = state(None, None, Some(300.0)).pressure_in(&gas).unwrap();
        assert!((p - 0.4 * 2.0 * 1000.0 * 300.0).abs() <= 1e-9 * p);
        assert!(state(None, None, None).pressure_in(&gas).is_err());
    }

    /// A state needs a positive density and exactly one positive
    /// thermodynamic variable; the error names the field.
    #[test]
    fn a_bad_state_names_its_field() {
        let field = |s: StateConfig| s.check("initial.1.state").err().map(|e| e.field);
        assert_eq!(field(state(Some(1.0), None, None)), None);
        assert_eq!(field(state(None, None, Some(300.0))), None);
        let mut s = state(Some(1.0), None, None);
        s.density = 0.0;
        assert_eq!(field(s).as_deref(), Some("initial.1.state.density"));
        let mut s = state(Some(1.0), None, None);
        s.velocity[2] = f64::NAN;
        assert_eq!(field(s).as_deref(), Some("initial.1.state.velocity"));
        assert_eq!(
            field(state(None, Some(-1.0), None)).as_deref(),
            Some("initial.1.state.specific_internal_energy")
        );
        let e = state(None, None, None).check("x").unwrap_err();
        assert_eq!(e.field, "x");
        assert!(e.message.starts_with("give one of"), "{e}");
        let e = state(Some(1.0), None, Some(2.0)).check("x").unwrap_err();
        assert!(e.message.starts_with("give only one of"), "{e}");
    }

    /// A face a pipeline does not take is named, with the list of those it
    /// takes and the hint.
    #[test]
    fn a_face_outside_the_list_is_named() {
        let mut b = OPEN_FACES.clone();
        assert!(b.check_faces("P", &["Outflow"], |_| "").is_ok());
        b.y_high = BoundaryConfig::Wall;
        let e = b
            .check_faces("P", &["Outflow", "Reflective", "Fixed"], |_| "; hint")
            .unwrap_err();
        assert_eq!(e.field, "boundaries.y_high");
        assert_eq!(
            e.message,
            "the P pipeline takes `Outflow`, `Reflective` or `Fixed` faces, not `Wall`; hint"
        );
        assert_eq!(
            b.summary(),
            "x_low=outflow x_high=outflow y_low=outflow y_high=wall z_low=outflow z_high=outflow"
        );
    }

    /// A fixed face's material is the one it names when the pipeline has
    /// it, the only one when it names none.
    #[test]
    fn a_fixed_face_takes_the_named_or_the_only_material() {
        let mut s = state(Some(1.0), None, None);
        let one = ["air".to_string()];
        let two = ["air".to_string(), "products".to_string()];
        assert_eq!(fixed_face_material("x_low", &s, &one, "gas"), Ok("air"));
        let e = fixed_face_material("x_low", &s, &two, "gas").unwrap_err();
        assert_eq!(e.field, "boundaries.x_low");
        s.material = Some("products".into());
        assert_eq!(
            fixed_face_material("x_low", &s, &two, "gas"),
            Ok("products")
        );
        let e = fixed_face_material("x_low", &s, &one, "gas").unwrap_err();
        assert_eq!(e.field, "boundaries.x_low.material");
        // None of the kind: named as such, not as an empty list.
        let e = fixed_face_material("x_low", &s, &[], "particle material").unwrap_err();
        assert_eq!(e.field, "boundaries.x_low.material");
        assert!(
            e.message.starts_with(
                "the pipeline has no particle material (a material with a constitutive `model`"
            ),
            "{}",
            e.message
        );
        s.material = None;
        let e = fixed_face_material("x_low", &s, &[], "gas").unwrap_err();
        assert_eq!(e.field, "boundaries.x_low");
        assert_eq!(
            e.message,
            "the pipeline has no gas to fill this face's state"
        );
    }
}
