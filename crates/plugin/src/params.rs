//! A plugin's parameters as RON text.
//!
//! [`ron::Value`] keeps numbers, strings, sequences and maps but drops the
//! names of enum variants (`rate: Jaumann` reads as `()`,
//! `pressure: Eos(MieGruneisenLinear(...))` as a bare sequence), and a
//! plugin's parameters may hold enums. A plugin therefore receives the RON
//! text of its parameters, taken from the config through the ron
//! deserializer's raw-value protocol (the one [`ron::value::RawValue`]
//! uses), and parses it into its own type with the config reader's RON
//! extensions ([`ron_options`]). What a model keeps for comparison and for
//! writing itself back is that type serialized again ([`Params`]): one
//! canonical text per parameter set, whatever the spacing and comments of
//! the config.

use std::fmt;
use std::sync::Arc;

use ron::extensions::Extensions;
use serde::de::{self, DeserializeOwned, Deserializer, Visitor};
use serde::{Deserialize, Serialize, Serializer};

/// The newtype name through which the ron deserializer hands a value's
/// text to [`ron::value::RawValue`] (and its serializer writes one back
/// verbatim). The tests of this crate read parameters through it, so a
/// change of the name in ron fails them.
const RAW_VALUE_TOKEN: &str = "$ron::private::RawValue";

/// The RON options a plugin reads its parameters with: those of the
/// config reader (`Some(x)` may be written `x`, and `Variant((fields))`
/// may be written `Variant(fields)`).
pub fn ron_options() -> ron::Options {
    ron::Options::default()
        .with_default_extension(Extensions::IMPLICIT_SOME | Extensions::UNWRAP_VARIANT_NEWTYPES)
}

/// A plugin model's parameters as canonical RON text: its parameter type
/// serialized with [`ron_options`], which reads it back. Two parameter
/// sets compare equal when their values are equal, however the configs
/// spaced and commented them.
///
/// It serializes as the text itself: verbatim into RON (the way
/// [`ron::value::RawValue`] writes), as a string into other formats.
#[derive(Clone, PartialEq, Eq, Hash)]
pub struct Params(Arc<str>);

impl Params {
    /// The parameters `value`, as canonical text.
    pub fn of<T: Serialize + ?Sized>(value: &T) -> Result<Self, String> {
        ron_options()
            .to_string(value)
            .map(|text| Self(text.into()))
            .map_err(|e| e.to_string())
    }

    /// The canonical text.
    pub fn as_str(&self) -> &str {
        &self.0
    }
}

impl fmt::Debug for Params {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.0)
    }
}

impl fmt::Display for Params {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.0)
    }
}

impl PartialEq<str> for Params {
    fn eq(&self, other: &str) -> bool {
        *self.0 == *other
    }
}

impl PartialEq<&str> for Params {
    fn eq(&self, other: &&str) -> bool {
        *self.0 == **other
    }
}

impl Serialize for Params {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.serialize_newtype_struct(RAW_VALUE_TOKEN, &*self.0)
    }
}

/// The RON text of a value, as the ron deserializer hands it over: a
/// plugin's parameters, `(a: 1.0, rate: Jaumann)` or, inside an unwrapped
/// variant, `a: 1.0, rate: Jaumann`. From a format without the raw-value
/// protocol it reads the string [`Params`] writes there.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ParamsText(pub String);

impl<'de> Deserialize<'de> for ParamsText {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct TextVisitor;
        impl<'de> Visitor<'de> for TextVisitor {
            type Value = ParamsText;
            fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
                write!(f, "the parameters of a plugin model, in RON")
            }
            fn visit_str<E: de::Error>(self, v: &str) -> Result<ParamsText, E> {
                Ok(ParamsText(v.to_string()))
            }
            fn visit_string<E: de::Error>(self, v: String) -> Result<ParamsText, E> {
                Ok(ParamsText(v))
            }
            fn visit_newtype_struct<D: Deserializer<'de>>(
                self,
                d: D,
            ) -> Result<ParamsText, D::Error> {
                String::deserialize(d).map(ParamsText)
            }
        }
        d.deserialize_newtype_struct(RAW_VALUE_TOKEN, TextVisitor)
    }
}

/// Reads the parameters of a plugin whose parameter type is the serde
/// struct `T`: the model and its canonical text. The text may be the
/// struct `(a: 1.0, ...)` or its fields alone (how a config writes them
/// inside `Name(...)`); an error carries serde's message, which names the
/// field, without the position inside the parameters.
pub fn parse_params<T>(text: &str) -> Result<(T, Params), String>
where
    T: DeserializeOwned + Serialize,
{
    let wrapped;
    let text = if text.trim_start().starts_with('(') {
        text
    } else {
        wrapped = format!("({text}\n)");
        &wrapped
    };
    let model: T = ron_options()
        .from_str(text)
        .map_err(|e| e.code.to_string())?;
    let params = Params::of(&model)?;
    Ok((model, params))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
    enum Rate {
        Jaumann,
        GreenNaghdi,
    }

    #[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
    enum Pressure {
        Linear { bulk_modulus: f64 },
        Table(Vec<f64>),
    }

    #[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
    #[serde(deny_unknown_fields)]
    struct Solid {
        shear_modulus: f64,
        pressure: Pressure,
        rate: Rate,
        #[serde(default)]
        note: Option<String>,
    }

    /// A config value holding the parameters as [`ParamsText`] and
    /// writing them back as [`Params`].
    #[derive(Debug, PartialEq, Deserialize)]
    struct Holder {
        model: ParamsText,
        after: u32,
    }

    #[derive(Serialize)]
    struct Written {
        model: Params,
        after: u32,
    }

    #[test]
    fn differently_spaced_parameters_have_one_canonical_text() {
        let a = "shear_modulus: 43.8e9, // G\n  pressure: Linear(bulk_modulus: 117.0e9),\n rate: GreenNaghdi";
        let b = "(rate: GreenNaghdi,pressure:Linear(bulk_modulus:1.17e11),shear_modulus: 4.38e10)";
        let (ma, pa) = parse_params::<Solid>(a).unwrap();
        let (mb, pb) = parse_params::<Solid>(b).unwrap();
        assert_eq!(ma, mb);
        assert_eq!(ma.rate, Rate::GreenNaghdi);
        assert_eq!(pa, pb);
        assert_eq!(pa, Params::of(&ma).unwrap());
        // The canonical text reads back to the same value and text.
        let (back, again) = parse_params::<Solid>(pa.as_str()).unwrap();
        assert_eq!((back, again), (ma, pa.clone()));
        // Another enum value is another parameter set.
        let (_, pj) = parse_params::<Solid>(&a.replace("GreenNaghdi", "Jaumann")).unwrap();
        assert_ne!(pa, pj);
    }

    #[test]
    fn errors_name_the_field() {
        let unknown = parse_params::<Solid>("shear_modulus: 1.0, bulk: 2.0").unwrap_err();
        assert!(unknown.contains("bulk"), "{unknown}");
        let missing = parse_params::<Solid>("(rate: Jaumann)").unwrap_err();
        assert!(missing.contains("shear_modulus"), "{missing}");
        let variant = parse_params::<Solid>(
            "shear_modulus: 1.0, pressure: Linear(bulk_modulus: 1.0), rate: Truesdell",
        )
        .unwrap_err();
        assert!(variant.contains("Truesdell"), "{variant}");
    }

    /// The ron deserializer hands over the text through the raw-value
    /// token, and the serializer writes it back verbatim: this fails if
    /// ron renames the token.
    #[test]
    fn the_text_is_captured_from_ron_and_written_back_verbatim() {
        let text =
            "(model: (rate: Jaumann, pressure: Table([1.0, 2.0]), shear_modulus: 1.0), after: 3)";
        let h: Holder = ron_options().from_str(text).unwrap();
        assert_eq!(
            h.model.0,
            "(rate: Jaumann, pressure: Table([1.0, 2.0]), shear_modulus: 1.0)"
        );
        assert_eq!(h.after, 3);
        let (solid, params) = parse_params::<Solid>(&h.model.0).unwrap();
        assert_eq!(solid.pressure, Pressure::Table(vec![1.0, 2.0]));
        let written = Written {
            model: params.clone(),
            after: h.after,
        };
        let out = ron_options().to_string(&written).unwrap();
        assert!(out.contains(params.as_str()), "{out}");
        let back: Holder = ron_options().from_str(&out).unwrap();
        assert_eq!(back.model.0, params.as_str());
    }

    #[test]
    fn other_formats_carry_the_text_as_a_string() {
        let params = Params::of(&Rate::GreenNaghdi).unwrap();
        let written = Written {
            model: params.clone(),
            after: 1,
        };
        let json = serde_json::to_string(&written).unwrap();
        assert_eq!(json, r#"{"model":"GreenNaghdi","after":1}"#);
        let back: Holder = serde_json::from_str(&json).unwrap();
        assert_eq!(back.model.0, params.as_str());
    }
}
