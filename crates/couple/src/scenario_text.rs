//! Sections and models read from RON text as a scenario reads them, for
//! the unit tests of the pipeline sections.

/// `text` read with a scenario's extensions
/// ([`brisance_plugin::ron_options`]: implicit `Some`, unwrapped newtype
/// variants); panics naming the text where it does not parse.
pub(crate) fn parse<T: serde::de::DeserializeOwned>(text: &str) -> T {
    brisance_plugin::ron_options()
        .from_str(text)
        .unwrap_or_else(|e| panic!("{text}: {e}"))
}
