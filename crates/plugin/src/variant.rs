//! A model enum with an open plugin variant: what the variant holds, and
//! the enum's serde.
//!
//! A family's model enum (`EosModel`, `MaterialModel`, the ICE's
//! `IceReactionModel`) keeps one variant per built-in model, with its
//! `match` dispatch, and one `Plugin` variant for every model a plugin
//! crate registered. In a config the plugin model is written under its
//! registered name, `NobleAbel(...)`, never as `Plugin`: the enum
//! implements [`PluginEnum`] and reads itself with [`deserialize`], which
//! gives a built-in name to the enum's own code and resolves any other
//! name among the installed plugins.

use std::fmt;
use std::marker::PhantomData;
use std::sync::Arc;

use serde::de::{self, Deserializer, EnumAccess, VariantAccess, Visitor};
use serde::{Deserialize, Serializer};

use crate::{Installed, Params, ParamsText, PluginInfo};

/// A plugin model as a model enum holds it: the registration, the
/// parameters as canonical RON text (so that it serializes back and
/// compares by value), and the model.
pub struct PluginInstance<P: PluginInfo> {
    plugin: &'static P,
    params: Params,
    model: Arc<P::Model>,
}

impl<P: PluginInfo> PluginInstance<P> {
    /// Builds the model of `plugin` from the RON text of its parameters
    /// (`(a: 1.0, ...)` or `a: 1.0, ...`); the message of an error names
    /// the field.
    pub fn new(plugin: &'static P, params: &str) -> Result<Self, String> {
        let (model, params) = plugin.parse(params)?;
        Ok(Self::from_parts(plugin, model, params))
    }

    /// The plugin model `model` of `plugin` with its parameters `params`
    /// (a model built in code, `params` being [`Params::of`] its
    /// parameter type).
    pub fn from_parts(plugin: &'static P, model: Arc<P::Model>, params: Params) -> Self {
        Self {
            plugin,
            params,
            model,
        }
    }

    /// The registration this model came from.
    pub fn plugin(&self) -> &'static P {
        self.plugin
    }

    /// The parameters, as canonical RON text.
    pub fn params(&self) -> &Params {
        &self.params
    }

    /// The model.
    pub fn model(&self) -> &Arc<P::Model> {
        &self.model
    }
}

impl<P: PluginInfo> Clone for PluginInstance<P> {
    fn clone(&self) -> Self {
        Self {
            plugin: self.plugin,
            params: self.params.clone(),
            model: Arc::clone(&self.model),
        }
    }
}

impl<P: PluginInfo> fmt::Debug for PluginInstance<P>
where
    P::Model: fmt::Debug,
{
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_tuple(self.plugin.name())
            .field(&&*self.model)
            .finish()
    }
}

/// Two plugin models are equal when they are the same plugin with the same
/// canonical parameters.
impl<P: PluginInfo> PartialEq for PluginInstance<P> {
    fn eq(&self, other: &Self) -> bool {
        self.plugin.name() == other.plugin.name() && self.params == other.params
    }
}

/// A model enum with built-in variants and one open plugin variant.
pub trait PluginEnum: Sized {
    /// The family's registration struct.
    type Plugin: PluginInfo;
    /// The enum's name, as serde is told it (`EosModel`).
    const NAME: &'static str;
    /// The config names of the enum's built-in variants, in order.
    const VARIANTS: &'static [&'static str];
    /// What a config should write here, for serde's "expected ..."
    /// messages ("an equation of state such as `IdealGas(...)`").
    const EXPECTING: &'static str;

    /// The family's installed registry.
    fn installed() -> &'static Installed<Self::Plugin>;

    /// Reads the built-in variant `name` (one of [`Self::VARIANTS`]) from
    /// `variant`.
    fn read_builtin<'de, A: VariantAccess<'de>>(
        name: &'static str,
        variant: A,
    ) -> Result<Self, A::Error>;

    /// The enum holding the plugin model `model`.
    fn from_plugin(model: PluginInstance<Self::Plugin>) -> Self;

    /// The error for a name that is neither built in nor installed. By
    /// default serde's unknown variant, listing every name of the family.
    fn unknown<E: de::Error>(name: &str) -> E {
        E::unknown_variant(name, Self::installed().names())
    }
}

/// The index of the variant named `name` in formats that write indices:
/// the built-in variants in order, then the installed plugins in
/// registration order.
pub fn variant_index<M: PluginEnum>(name: &str) -> u32 {
    let plugins = M::installed().plugin_names();
    let index = match M::VARIANTS.iter().position(|v| *v == name) {
        Some(i) => i,
        None => {
            M::VARIANTS.len()
                + plugins
                    .iter()
                    .position(|v| *v == name)
                    .unwrap_or(plugins.len())
        }
    };
    index as u32
}

/// Writes the plugin model `model` of the enum `M` as `Name(params)`, the
/// parameters in their canonical text.
pub fn serialize_plugin<M: PluginEnum, S: Serializer>(
    model: &PluginInstance<M::Plugin>,
    s: S,
) -> Result<S::Ok, S::Error> {
    let name = model.plugin().name();
    s.serialize_newtype_variant(M::NAME, variant_index::<M>(name), name, model.params())
}

/// A variant name as a deserializer gives it: a built-in one (by name or,
/// for formats that write indices, by index), an installed plugin, or
/// neither.
enum Tag<M: PluginEnum> {
    Builtin(&'static str),
    Plugin(&'static M::Plugin),
    Unknown(String),
}

impl<'de, M: PluginEnum> Deserialize<'de> for Tag<M> {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct TagVisitor<M>(PhantomData<M>);
        impl<M: PluginEnum> Visitor<'_> for TagVisitor<M> {
            type Value = Tag<M>;
            fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
                write!(f, "the name of a {}", M::Plugin::FAMILY)
            }
            fn visit_str<E: de::Error>(self, name: &str) -> Result<Tag<M>, E> {
                if let Some(v) = M::VARIANTS.iter().find(|v| **v == name) {
                    Ok(Tag::Builtin(v))
                } else if let Some(p) = M::installed().find(name) {
                    Ok(Tag::Plugin(p))
                } else {
                    Ok(Tag::Unknown(name.to_string()))
                }
            }
            fn visit_u64<E: de::Error>(self, index: u64) -> Result<Tag<M>, E> {
                let plugins = M::installed().plugin_names();
                let name = usize::try_from(index).ok().and_then(|i| {
                    M::VARIANTS
                        .get(i)
                        .or_else(|| plugins.get(i - M::VARIANTS.len()))
                });
                match name {
                    Some(name) => self.visit_str(name),
                    None => Err(E::invalid_value(
                        de::Unexpected::Unsigned(index),
                        &"a variant index",
                    )),
                }
            }
        }
        d.deserialize_identifier(TagVisitor(PhantomData))
    }
}

/// Reads the model enum `M`: a built-in name through
/// [`PluginEnum::read_builtin`], an installed plugin's name through the
/// plugin, from the RON text of its parameters. A plugin's error is
/// prefixed with its name (`NobleAbel: unknown field ...`); a name that is
/// neither is [`PluginEnum::unknown`].
pub fn deserialize<'de, M: PluginEnum, D: Deserializer<'de>>(d: D) -> Result<M, D::Error> {
    struct ModelVisitor<M>(PhantomData<M>);
    impl<'de, M: PluginEnum> Visitor<'de> for ModelVisitor<M> {
        type Value = M;
        fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
            f.write_str(M::EXPECTING)
        }
        fn visit_enum<A: EnumAccess<'de>>(self, data: A) -> Result<M, A::Error> {
            let (tag, variant) = data.variant::<Tag<M>>()?;
            match tag {
                Tag::Builtin(name) => M::read_builtin(name, variant),
                Tag::Plugin(p) => {
                    let ParamsText(params) = variant.newtype_variant()?;
                    PluginInstance::new(p, &params)
                        .map(M::from_plugin)
                        .map_err(|m| de::Error::custom(format!("{}: {m}", p.name())))
                }
                Tag::Unknown(name) => Err(M::unknown(&name)),
            }
        }
    }
    d.deserialize_enum(M::NAME, M::VARIANTS, ModelVisitor(PhantomData))
}
