//! The registry of one model family and the slot it is installed in.

use std::fmt;
use std::sync::{Arc, OnceLock};

use crate::Params;

/// What a family's registration struct tells the generic machinery: the
/// family (for messages and the built-in names no plugin may take), the
/// plugin's name and descriptions, and how it builds its model.
pub trait PluginInfo: Sized + 'static {
    /// The family in messages: `equation of state`, `reaction model`,
    /// `constitutive model`.
    const FAMILY: &'static str;
    /// The names of the family's built-in models, which no plugin may
    /// take; the first names a config may write, before the plugins'.
    const BUILT_IN: &'static [&'static str];
    /// The model a plugin builds, behind the family's trait
    /// (`dyn brisance_eos::PluginModel`, ...).
    type Model: ?Sized;

    /// The name a config writes (`NobleAbel`), in the style of the
    /// built-in variants.
    fn name(&self) -> &'static str;
    /// One line on what it is, with its source, for `brisance list`.
    fn summary(&self) -> &'static str;
    /// The model's docs page, relative to the repository root.
    fn docs(&self) -> &'static str;
    /// A RON example of the config value.
    fn example(&self) -> &'static str;
    /// Builds the model from the RON text of its parameters; see
    /// [`crate::ParseFn`].
    fn parse(&self, params: &str) -> Result<(Arc<Self::Model>, Params), String>;
}

/// The plugins of one family in one program, in registration order.
pub struct Registry<P> {
    plugins: Vec<P>,
}

impl<P> Default for Registry<P> {
    fn default() -> Self {
        Self::new()
    }
}

impl<P: fmt::Debug> fmt::Debug for Registry<P> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("Registry")
            .field("plugins", &self.plugins)
            .finish()
    }
}

impl<P> Registry<P> {
    /// An empty registry.
    pub const fn new() -> Self {
        Self {
            plugins: Vec::new(),
        }
    }

    /// Every registered plugin, in registration order.
    pub fn plugins(&self) -> &[P] {
        &self.plugins
    }
}

impl<P: PluginInfo> Registry<P> {
    /// Adds `plugin`. Panics if its name is a built-in model's or already
    /// registered: two crates claiming one config name is a programming
    /// error that the first test run must show.
    pub fn register(&mut self, plugin: P) {
        let name = plugin.name();
        assert!(
            !P::BUILT_IN.contains(&name),
            "{} `{name}` is a built-in model",
            P::FAMILY
        );
        assert!(
            self.get(name).is_none(),
            "{} `{name}` registered twice",
            P::FAMILY
        );
        self.plugins.push(plugin);
    }

    /// The plugin registered under `name`.
    pub fn get(&self, name: &str) -> Option<&P> {
        self.plugins.iter().find(|p| p.name() == name)
    }
}

/// The installed registry of a family and the names a config may write.
struct Slot<P> {
    registry: Registry<P>,
    names: Vec<&'static str>,
}

/// The process-wide registry of one family, kept in a `static`
/// (`static INSTALLED: Installed<EosPlugin> = Installed::new();`): serde
/// gives a deserializer no other way to reach it. It is installed once;
/// until then it holds no plugins and its names are the built-in ones.
pub struct Installed<P> {
    slot: OnceLock<Slot<P>>,
}

impl<P> Default for Installed<P> {
    fn default() -> Self {
        Self::new()
    }
}

impl<P> Installed<P> {
    /// An empty slot.
    pub const fn new() -> Self {
        Self {
            slot: OnceLock::new(),
        }
    }
}

impl<P: PluginInfo> Installed<P> {
    /// Makes `registry` the installed one. The first call wins; a later
    /// one gives its registry back.
    pub fn install(&self, registry: Registry<P>) -> Result<(), Registry<P>> {
        let mut given = Some(registry);
        self.slot.get_or_init(|| {
            let registry = given.take().expect("taken once");
            let names = P::BUILT_IN
                .iter()
                .copied()
                .chain(registry.plugins.iter().map(P::name))
                .collect();
            Slot { registry, names }
        });
        match given {
            None => Ok(()),
            Some(r) => Err(r),
        }
    }

    /// The installed registry, if any.
    pub fn registry(&self) -> Option<&Registry<P>> {
        self.slot.get().map(|s| &s.registry)
    }

    /// Every name a config may write: the built-in models, then the
    /// installed plugins in registration order.
    pub fn names(&self) -> &[&'static str] {
        self.slot.get().map_or(P::BUILT_IN, |s| s.names.as_slice())
    }

    /// The names of the installed plugins, in registration order.
    pub fn plugin_names(&self) -> &[&'static str] {
        &self.names()[P::BUILT_IN.len()..]
    }

    /// The installed plugin registered under `name`.
    pub fn find(&self, name: &str) -> Option<&P> {
        self.registry().and_then(|r| r.get(name))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[derive(Debug, PartialEq)]
    struct Toy(&'static str);

    impl PluginInfo for Toy {
        const FAMILY: &'static str = "toy model";
        const BUILT_IN: &'static [&'static str] = &["Ball", "Kite"];
        type Model = str;
        fn name(&self) -> &'static str {
            self.0
        }
        fn summary(&self) -> &'static str {
            "a toy"
        }
        fn docs(&self) -> &'static str {
            "docs/toys.md"
        }
        fn example(&self) -> &'static str {
            "Top()"
        }
        fn parse(&self, params: &str) -> Result<(Arc<str>, Params), String> {
            Ok((params.into(), Params::of(&params)?))
        }
    }

    #[test]
    #[should_panic(expected = "toy model `Top` registered twice")]
    fn a_name_is_registered_once() {
        let mut r = Registry::new();
        r.register(Toy("Top"));
        r.register(Toy("Top"));
    }

    #[test]
    #[should_panic(expected = "toy model `Kite` is a built-in model")]
    fn a_plugin_cannot_take_a_built_in_name() {
        Registry::new().register(Toy("Kite"));
    }

    #[test]
    fn names_are_the_built_in_ones_then_the_plugins_in_registration_order() {
        static SLOT: Installed<Toy> = Installed::new();
        assert_eq!(SLOT.names(), ["Ball", "Kite"]);
        assert!(SLOT.registry().is_none() && SLOT.plugin_names().is_empty());
        let mut r = Registry::new();
        r.register(Toy("Yoyo"));
        r.register(Toy("Top"));
        assert_eq!(r.get("Top"), Some(&Toy("Top")));
        assert_eq!(r.get("Ball"), None);
        SLOT.install(r).unwrap();
        assert_eq!(SLOT.names(), ["Ball", "Kite", "Yoyo", "Top"]);
        assert_eq!(SLOT.plugin_names(), ["Yoyo", "Top"]);
        assert_eq!(SLOT.find("Yoyo"), Some(&Toy("Yoyo")));
        assert_eq!(SLOT.find("Ball"), None);
        assert_eq!(SLOT.registry().unwrap().plugins().len(), 2);
    }

    #[test]
    fn a_second_install_gives_its_registry_back() {
        static SLOT: Installed<Toy> = Installed::new();
        let mut first = Registry::new();
        first.register(Toy("Top"));
        assert!(SLOT.install(first).is_ok());
        let mut second = Registry::new();
        second.register(Toy("Yoyo"));
        let back = SLOT.install(second).unwrap_err();
        assert_eq!(back.plugins(), [Toy("Yoyo")]);
        assert_eq!(SLOT.plugin_names(), ["Top"]);
    }
}
