//! Locating values in RON text by dotted path (`domain.cells`,
//! `initial.1.state.density`, `materials.air.eos.gamma`), for `--set`
//! overrides and for error messages that point at a line and column.
//!
//! A small structural reader, not a validator: it tokenises the text
//! (strings, comments, brackets), builds a tree of value spans and walks
//! it. Serde/ron still parse the result; this only finds where things are.

use std::ops::Range;

/// A located value.
#[derive(Debug, Clone, PartialEq)]
struct Node {
    span: Range<usize>,
    kind: Kind,
}

#[derive(Debug, Clone, PartialEq)]
enum Kind {
    /// `Name(field: v, ...)` or `(field: v, ...)`; `close` is the position of
    /// the closing parenthesis.
    Struct {
        fields: Vec<(String, Node)>,
        close: usize,
    },
    /// `(a, b)`, `[a, b]`, or `Variant(a, ...)` (enum content).
    Seq(Vec<Node>),
    /// `{ "k": v }`.
    Map(Vec<(String, Node)>),
    /// Anything else (numbers, strings, unit variants).
    Atom,
}

struct Reader<'a> {
    s: &'a [u8],
    pos: usize,
}

impl<'a> Reader<'a> {
    fn skip_ws(&mut self) {
        loop {
            while self.pos < self.s.len() && self.s[self.pos].is_ascii_whitespace() {
                self.pos += 1;
            }
            if self.s[self.pos..].starts_with(b"//") {
                while self.pos < self.s.len() && self.s[self.pos] != b'\n' {
                    self.pos += 1;
                }
            } else if self.s[self.pos..].starts_with(b"/*") {
                let mut depth = 0usize;
                while self.pos < self.s.len() {
                    if self.s[self.pos..].starts_with(b"/*") {
                        depth += 1;
                        self.pos += 2;
                    } else if self.s[self.pos..].starts_with(b"*/") {
                        depth -= 1;
                        self.pos += 2;
                        if depth == 0 {
                            break;
                        }
                    } else {
                        self.pos += 1;
                    }
                }
            } else {
                return;
            }
        }
    }

    fn peek(&mut self) -> Option<u8> {
        self.skip_ws();
        self.s.get(self.pos).copied()
    }

    fn ident(&mut self) -> Option<String> {
        self.skip_ws();
        let start = self.pos;
        while self.pos < self.s.len()
            && (self.s[self.pos].is_ascii_alphanumeric() || self.s[self.pos] == b'_')
        {
            self.pos += 1;
        }
        (self.pos > start && !self.s[start].is_ascii_digit())
            .then(|| String::from_utf8_lossy(&self.s[start..self.pos]).into_owned())
            .or_else(|| {
                self.pos = start;
                None
            })
    }

    fn string(&mut self) -> Option<String> {
        // At a '"': read to the closing quote, honouring escapes.
        let start = self.pos + 1;
        self.pos += 1;
        while self.pos < self.s.len() {
            match self.s[self.pos] {
                b'\\' => self.pos += 2,
                b'"' => {
                    self.pos += 1;
                    return Some(
                        String::from_utf8_lossy(&self.s[start..self.pos - 1]).into_owned(),
                    );
                }
                _ => self.pos += 1,
            }
        }
        None
    }

    /// Whether the next tokens are `ident :` (a named field).
    fn at_field(&mut self) -> bool {
        let save = self.pos;
        let named = self.ident().is_some() && self.peek() == Some(b':');
        self.pos = save;
        named
    }

    fn value(&mut self) -> Option<Node> {
        let c = self.peek()?;
        let start = self.pos;
        match c {
            b'(' => self.paren(start),
            b'[' => {
                self.pos += 1;
                let items = self.items(b']')?;
                Some(Node {
                    span: start..self.pos,
                    kind: Kind::Seq(items),
                })
            }
            b'{' => {
                self.pos += 1;
                let mut entries = Vec::new();
                loop {
                    match self.peek()? {
                        b'}' => {
                            self.pos += 1;
                            break;
                        }
                        b',' => self.pos += 1,
                        _ => {
                            let key_node = self.value()?;
                            let key = String::from_utf8_lossy(&self.s[key_node.span.clone()])
                                .trim_matches('"')
                                .to_string();
                            if self.peek()? != b':' {
                                return None;
                            }
                            self.pos += 1;
                            entries.push((key, self.value()?));
                        }
                    }
                }
                Some(Node {
                    span: start..self.pos,
                    kind: Kind::Map(entries),
                })
            }
            b'"' => {
                self.string()?;
                Some(Node {
                    span: start..self.pos,
                    kind: Kind::Atom,
                })
            }
            _ => {
                if self.ident().is_some() {
                    let after = self.pos;
                    if self.peek() == Some(b'(') {
                        let p = self.pos;
                        return self.paren(p).map(|n| Node {
                            span: start..n.span.end,
                            kind: n.kind,
                        });
                    }
                    self.pos = after;
                    return Some(Node {
                        span: start..after,
                        kind: Kind::Atom,
                    });
                }
                // Numbers, chars and other atoms: up to a delimiter.
                while self.pos < self.s.len()
                    && !b",)]}:".contains(&self.s[self.pos])
                    && !self.s[self.pos].is_ascii_whitespace()
                {
                    self.pos += 1;
                }
                (self.pos > start).then_some(Node {
                    span: start..self.pos,
                    kind: Kind::Atom,
                })
            }
        }
    }

    /// At '(': a struct body (named fields) or a tuple/enum content.
    fn paren(&mut self, start: usize) -> Option<Node> {
        self.pos += 1;
        if self.at_field() {
            let mut fields = Vec::new();
            loop {
                match self.peek()? {
                    b')' => {
                        let close = self.pos;
                        self.pos += 1;
                        return Some(Node {
                            span: start..self.pos,
                            kind: Kind::Struct { fields, close },
                        });
                    }
                    b',' => self.pos += 1,
                    _ => {
                        let name = self.ident()?;
                        if self.peek()? != b':' {
                            return None;
                        }
                        self.pos += 1;
                        fields.push((name, self.value()?));
                    }
                }
            }
        }
        let items = self.items(b')')?;
        Some(Node {
            span: start..self.pos,
            kind: Kind::Seq(items),
        })
    }

    fn items(&mut self, close: u8) -> Option<Vec<Node>> {
        let mut items = Vec::new();
        loop {
            match self.peek()? {
                c if c == close => {
                    self.pos += 1;
                    return Some(items);
                }
                b',' => self.pos += 1,
                _ => items.push(self.value()?),
            }
        }
    }
}

fn parse(text: &str) -> Option<Node> {
    Reader {
        s: text.as_bytes(),
        pos: 0,
    }
    .value()
}

/// Where a path leads: a value, or a struct that lacks the last field.
enum Found<'a> {
    Value(&'a Node),
    MissingField { close: usize },
}

fn walk<'a>(node: &'a Node, path: &[&str]) -> Option<Found<'a>> {
    let Some((seg, rest)) = path.split_first() else {
        return Some(Found::Value(node));
    };
    match &node.kind {
        Kind::Struct { fields, close } => match fields.iter().find(|(n, _)| n == seg) {
            Some((_, child)) => walk(child, rest),
            None if rest.is_empty() => Some(Found::MissingField { close: *close }),
            None => None,
        },
        Kind::Seq(items) => match seg.parse::<usize>() {
            Ok(i) => walk(items.get(i)?, rest),
            // An enum variant wrapping one struct: look through it.
            Err(_) if items.len() == 1 => walk(&items[0], path),
            Err(_) => None,
        },
        Kind::Map(entries) => walk(&entries.iter().find(|(k, _)| k == seg)?.1, rest),
        Kind::Atom => None,
    }
}

/// The byte range of the value at `path` (dot-separated), if present.
pub fn find(text: &str, path: &str) -> Option<Range<usize>> {
    let root = parse(text)?;
    let segs: Vec<&str> = path.split('.').filter(|s| !s.is_empty()).collect();
    match walk(&root, &segs)? {
        Found::Value(n) => Some(n.span.clone()),
        Found::MissingField { .. } => None,
    }
}

/// The deepest existing prefix of `path` and its byte range (for pointing
/// at the closest thing when the exact value does not exist).
pub fn find_nearest(text: &str, path: &str) -> Option<Range<usize>> {
    let segs: Vec<&str> = path.split('.').filter(|s| !s.is_empty()).collect();
    (0..=segs.len())
        .rev()
        .find_map(|n| find(text, &segs[..n].join(".")))
}

/// Replaces the value at `path` with `value` (inserting the field if the
/// enclosing struct lacks it).
pub fn set(text: &str, path: &str, value: &str) -> Result<String, String> {
    let root = parse(text).ok_or("the file is not structurally valid RON")?;
    let segs: Vec<&str> = path.split('.').filter(|s| !s.is_empty()).collect();
    if segs.is_empty() {
        return Err("empty path".into());
    }
    match walk(&root, &segs) {
        Some(Found::Value(n)) => Ok(format!(
            "{}{}{}",
            &text[..n.span.start],
            value,
            &text[n.span.end..]
        )),
        Some(Found::MissingField { close }) => {
            let field = segs[segs.len() - 1];
            let before = text[..close].trim_end();
            let sep = if before.ends_with(',') || before.ends_with('(') {
                ""
            } else {
                ","
            };
            Ok(format!("{before}{sep} {field}: {value}{}", &text[close..]))
        }
        None => Err(format!("no `{path}` in the configuration")),
    }
}

/// 1-based line and column of byte offset `pos`.
pub fn line_col(text: &str, pos: usize) -> (usize, usize) {
    let before = &text[..pos.min(text.len())];
    let line = before.matches('\n').count() + 1;
    let col = before.rsplit('\n').next().map_or(0, |l| l.chars().count()) + 1;
    (line, col)
}

#[cfg(test)]
mod tests {
    use super::*;

    const TEXT: &str = r#"// a comment (with parens)
Scenario(
    name: "x(1)",
    domain: (lower: (0.0, 0.0, 0.0), upper: (1.0, 1.0, 1.0), cells: (100, 1, 1)),
    materials: { "air": (eos: IdealGas(gamma: 1.4, cv: 717.5)) },
    pipeline: Fdm(material: "air"),
    initial: [
        (region: Everywhere, material: "air", state: (density: 1.0, pressure: 1.0)),
        (region: Box(min: (0,0,0), max: (0.5,1,1)), material: "air", state: (density: 2.0, pressure: 1.0)),
    ],
)"#;

    fn at(path: &str) -> &'static str {
        &TEXT[find(TEXT, path).unwrap()]
    }

    #[test]
    fn finds_nested_struct_tuple_map_and_list_values() {
        assert_eq!(at("domain.cells"), "(100, 1, 1)");
        assert_eq!(at("domain.cells.0"), "100");
        assert_eq!(at("name"), "\"x(1)\"");
        assert_eq!(at("materials.air.eos.gamma"), "1.4");
        assert_eq!(at("pipeline.material"), "\"air\"");
        assert_eq!(at("initial.1.state.density"), "2.0");
        assert_eq!(at("initial.1.region.max"), "(0.5,1,1)");
        assert_eq!(find(TEXT, "domain.nope"), None);
    }

    #[test]
    fn set_replaces_or_inserts_and_reports_missing_parents() {
        let t = set(TEXT, "domain.cells", "(800,1,1)").unwrap();
        assert!(t.contains("cells: (800,1,1)"));
        let t = set(TEXT, "domain.patches", "(2,1,1)").unwrap();
        assert_eq!(&t[find(&t, "domain.patches").unwrap()], "(2,1,1)");
        let t = set(TEXT, "pipeline.viscosity", "Off").unwrap();
        assert_eq!(&t[find(&t, "pipeline.viscosity").unwrap()], "Off");
        assert!(set(TEXT, "nothing.here", "1")
            .unwrap_err()
            .contains("nothing.here"));
    }

    #[test]
    fn line_and_column_are_one_based() {
        let pos = find(TEXT, "domain.cells").unwrap().start;
        let (line, col) = line_col(TEXT, pos);
        assert_eq!(line, 4);
        assert_eq!(&TEXT.lines().nth(3).unwrap()[col - 1..col + 3], "(100");
        assert_eq!(find_nearest(TEXT, "domain.nope.x"), find(TEXT, "domain"));
    }
}
