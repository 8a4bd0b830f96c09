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
/// field, and where in `text` it is ([`at_parameter`]), which the config
/// reader turns into the file's line and column.
pub fn parse_params<T>(text: &str) -> Result<(T, Params), String>
where
    T: DeserializeOwned + Serialize,
{
    let wrapped;
    let (source, shifted) = if text.trim_start().starts_with('(') {
        (text, false)
    } else {
        wrapped = format!("({text}\n)");
        (wrapped.as_str(), true)
    };
    let model: T = ron_options().from_str(source).map_err(|e| {
        let (line, col) = (e.span.start.line, e.span.start.col);
        // The opening parenthesis added in front of the first line.
        let col = if shifted && line == 1 { col - 1 } else { col };
        at_parameter(&e.code.to_string(), line, col)
    })?;
    let params = Params::of(&model)?;
    Ok((model, params))
}

/// The text [`parse_params`] appends to an error: its position in the
/// parameters' text (line and column from 1, columns in characters).
const AT: (&str, &str) = (" (at ", " of the parameters)");

/// `message` with its position in a plugin's parameters,
/// `… (at 3:14 of the parameters)`.
pub fn at_parameter(message: &str, line: usize, col: usize) -> String {
    format!("{message}{}{line}:{col}{}", AT.0, AT.1)
}

/// Splits a message of [`at_parameter`] (possibly nested: a plugin inside
/// another's parameters) into the message without any position and the
/// outermost position (the last one appended), if there is one.
pub fn parameter_position(message: &str) -> (String, Option<(usize, usize)>) {
    let mut rest = String::with_capacity(message.len());
    let mut outer = None;
    let mut from = 0;
    while let Some(i) = message[from..].find(AT.0).map(|i| from + i) {
        let after = &message[i + AT.0.len()..];
        let parsed = after.find(AT.1).and_then(|n| {
            let (l, c) = after[..n].split_once(':')?;
            let digits = |t: &str| !t.is_empty() && t.bytes().all(|b| b.is_ascii_digit());
            if !(digits(l) && digits(c)) {
                return None;
            }
            Some(((l.parse().ok()?, c.parse().ok()?), n))
        });
        match parsed {
            Some((position, n)) => {
                rest.push_str(&message[from..i]);
                from = i + AT.0.len() + n + AT.1.len();
                if from == message.len() {
                    outer = Some(position);
                }
            }
            None => {
                rest.push_str(&message[from..i + AT.0.len()]);
                from = i + AT.0.len();
            }
        }
    }
    rest.push_str(&message[from..]);
    (rest, outer)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// An error in a plugin's parameters says where in them it is, on
    /// the parameters as written (the added parenthesis of a text of fields
    /// alone does not count), and the position comes back off the message,
    /// also through a nested plugin's.
    #[test]
    fn a_parameter_error_is_located_in_the_parameters() {
        let e = parse_params::<Solid>("shear_modulus: 1.0,\n  rate: Sideways").unwrap_err();
        let (message, at) = parameter_position(&e);
        assert!(message.contains("`Sideways`"), "{message}");
        assert!(!message.contains("of the parameters"), "{message}");
        assert_eq!(at, Some((2, 9)), "{e}");
        let e = parse_params::<Solid>("shaer_modulus: 1.0").unwrap_err();
        assert_eq!(parameter_position(&e).1, Some((1, 1)), "{e}");
        let e = parse_params::<Solid>("(shaer_modulus: 1.0)").unwrap_err();
        assert_eq!(parameter_position(&e).1, Some((1, 2)), "{e}");
        let nested = at_parameter(&format!("Inner: {}", at_parameter("bad", 1, 3)), 4, 7);
        assert_eq!(
            parameter_position(&nested),
            ("Inner: bad".to_string(), Some((4, 7)))
        );
        let plain = "at least one (at most two)";
        assert_eq!(parameter_position(plain), (plain.to_string(), None));
    }

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
