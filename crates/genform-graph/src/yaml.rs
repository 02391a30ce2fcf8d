//! YAML text → a tree of values with byte spans (via serde-saphyr).
//!
//! The grammar is read from this tree rather than deserialized into
//! structs directly, so that every schema problem (a wrong type, an unknown
//! key, a bad name) is reported with its position, all at once.

use genform_core::diag::{Diagnostic, Span};
use serde::de::{Deserialize, Deserializer, MapAccess, SeqAccess, Visitor};
use serde_saphyr::{Location, Spanned};
use std::fmt;

/// Most YAML nodes a file may have (serde-saphyr's default is 250,000,
/// too few for a large result graph read back as a host).
const MAX_NODES: usize = 20_000_000;

/// A YAML value with where it is.
#[derive(Clone, Debug)]
pub(crate) struct Node {
    pub(crate) value: Val,
    pub(crate) span: Span,
}

/// A map key with where it is.
#[derive(Clone, Debug)]
pub(crate) struct Key {
    pub(crate) name: String,
    pub(crate) span: Span,
}

#[derive(Clone, Debug)]
pub(crate) enum Val {
    Null,
    Bool(bool),
    Num(f64),
    Str(String),
    Seq(Vec<Node>),
    Map(Vec<(Key, Node)>),
}

impl Val {
    /// "a number", "a list", … for messages.
    pub(crate) fn kind(&self) -> &'static str {
        match self {
            Val::Null => "nothing",
            Val::Bool(_) => "a boolean",
            Val::Num(_) => "a number",
            Val::Str(_) => "text",
            Val::Seq(_) => "a list",
            Val::Map(_) => "a map",
        }
    }
}

/// The raw value as serde-saphyr hands it over, spans still as locations.
enum Raw {
    Null,
    Bool(bool),
    Num(f64),
    Str(String),
    Seq(Vec<Spanned<Raw>>),
    Map(Vec<(Spanned<String>, Spanned<Raw>)>),
}

impl<'de> Deserialize<'de> for Raw {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct V;
        impl<'de> Visitor<'de> for V {
            type Value = Raw;
            fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
                f.write_str("a YAML value")
            }
            fn visit_unit<E>(self) -> Result<Raw, E> {
                Ok(Raw::Null)
            }
            fn visit_none<E>(self) -> Result<Raw, E> {
                Ok(Raw::Null)
            }
            fn visit_bool<E>(self, v: bool) -> Result<Raw, E> {
                Ok(Raw::Bool(v))
            }
            fn visit_i64<E>(self, v: i64) -> Result<Raw, E> {
                Ok(Raw::Num(v as f64))
            }
            fn visit_u64<E>(self, v: u64) -> Result<Raw, E> {
                Ok(Raw::Num(v as f64))
            }
            fn visit_i128<E>(self, v: i128) -> Result<Raw, E> {
                Ok(Raw::Num(v as f64))
            }
            fn visit_u128<E>(self, v: u128) -> Result<Raw, E> {
                Ok(Raw::Num(v as f64))
            }
            fn visit_f64<E>(self, v: f64) -> Result<Raw, E> {
                Ok(Raw::Num(v))
            }
            fn visit_str<E>(self, v: &str) -> Result<Raw, E> {
                Ok(Raw::Str(v.to_string()))
            }
            fn visit_string<E>(self, v: String) -> Result<Raw, E> {
                Ok(Raw::Str(v))
            }
            fn visit_seq<A: SeqAccess<'de>>(self, mut s: A) -> Result<Raw, A::Error> {
                let mut v = Vec::new();
                while let Some(x) = s.next_element()? {
                    v.push(x);
                }
                Ok(Raw::Seq(v))
            }
            fn visit_map<A: MapAccess<'de>>(self, mut m: A) -> Result<Raw, A::Error> {
                let mut v = Vec::new();
                while let Some(k) = m.next_key::<Spanned<String>>()? {
                    v.push((k, m.next_value()?));
                }
                Ok(Raw::Map(v))
            }
        }
        d.deserialize_any(V)
    }
}

/// Byte offsets of line starts, to turn (line, column) into offsets.
struct Lines<'a> {
    text: &'a str,
    starts: Vec<usize>,
}

impl<'a> Lines<'a> {
    fn new(text: &'a str) -> Self {
        let mut starts = vec![0];
        starts.extend(text.match_indices('\n').map(|(i, _)| i + 1));
        Lines { text, starts }
    }

    /// Byte offset of 1-based (line, character column).
    fn offset(&self, line: u64, col: u64) -> usize {
        let Some(&start) = self.starts.get((line.max(1) - 1) as usize) else {
            return self.text.len();
        };
        let rest = &self.text[start..];
        rest.char_indices().nth((col.max(1) - 1) as usize).map_or(self.text.len(), |(i, _)| start + i)
    }

    fn span(&self, loc: &Location) -> Span {
        let s = loc.span();
        match (s.byte_offset(), s.byte_len()) {
            (Some(o), Some(l)) => Span::new(o as usize, (o + l) as usize),
            (Some(o), None) => Span::new(o as usize, o as usize),
            _ => {
                let o = self.offset(loc.line(), loc.column());
                Span::new(o, o)
            }
        }
    }
}

fn convert(raw: Spanned<Raw>, lines: &Lines) -> Node {
    let span = lines.span(&raw.referenced);
    let value = match raw.value {
        Raw::Null => Val::Null,
        Raw::Bool(b) => Val::Bool(b),
        Raw::Num(v) => Val::Num(v),
        Raw::Str(s) => Val::Str(s),
        Raw::Seq(v) => Val::Seq(v.into_iter().map(|x| convert(x, lines)).collect()),
        Raw::Map(v) => Val::Map(
            v.into_iter()
                .map(|(k, x)| (Key { span: lines.span(&k.referenced), name: k.value }, convert(x, lines)))
                .collect(),
        ),
    };
    Node { value, span }
}

/// Parses YAML text into a spanned tree.
pub(crate) fn parse(text: &str) -> Result<Node, Diagnostic> {
    let budget = serde_saphyr::budget! { max_nodes: MAX_NODES };
    // YAML 1.2 booleans only: `y`, `n`, `on`, `off` stay names.
    let options = serde_saphyr::options! {
        budget: budget,
        strict_booleans: true,
        non_finite_float_policy: serde_saphyr::NonFiniteFloatPolicy::PassThrough,
    };
    let lines = Lines::new(text);
    match serde_saphyr::from_str_with_options::<Spanned<Raw>>(text, options) {
        Ok(raw) => Ok(convert(raw, &lines)),
        Err(e) => {
            let span = e.location().map_or(Span::new(0, 0), |l| lines.span(&l));
            let mut message = e.without_snippet().to_string();
            // The location is ours to show.
            if let Some(i) = message.rfind(" at line ") {
                message.truncate(i);
            }
            Err(Diagnostic::error(span, format!("invalid YAML: {message}"))
                .with_hint("check indentation, `:` after keys and matching brackets and quotes"))
        }
    }
}

/// Where the text of string `value` starts, given its node starts at
/// `node`: after an opening quote, or on the first content line of a block
/// scalar. Formula positions are offsets from here.
pub(crate) fn content_offset(text: &str, node: usize, value: &str) -> usize {
    let rest = text.get(node..).unwrap_or("");
    if rest.starts_with(value) {
        return node;
    }
    if (rest.starts_with('"') || rest.starts_with('\'')) && rest[1..].starts_with(value) {
        return node + 1;
    }
    // Quoted with escapes, or a block scalar: find the first line of the
    // value nearby.
    let first = value.lines().next().unwrap_or("").trim();
    if !first.is_empty() {
        let mut end = rest.len().min(value.len() * 2 + 256);
        while !rest.is_char_boundary(end) {
            end -= 1;
        }
        let window = &rest[..end];
        if let Some(i) = window.find(first) {
            let lead = value.len() - value.trim_start().len();
            return (node + i).saturating_sub(lead);
        }
    }
    node + usize::from(rest.starts_with('"') || rest.starts_with('\''))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn map(n: &Node) -> &[(Key, Node)] {
        match &n.value {
            Val::Map(m) => m,
            v => panic!("not a map: {v:?}"),
        }
    }

    #[test]
    fn the_search_window_never_cuts_a_character() {
        // A fuzzer's find: the window after a node ended inside a two-byte
        // character (every odd offset here is a boundary, 258 is not).
        let text = format!("a{}", "é".repeat(200));
        assert_eq!(content_offset(&text, 0, "x"), 0);
        assert_eq!(content_offset(&text, 0, "éé"), 1);
    }

    #[test]
    fn values_keep_their_byte_spans() {
        let src = "name: k\nv:\n  a: {x: 1, when: \"A.x > 2\"}\n  b: [1, 'q', true, ~]\n";
        let root = parse(src).unwrap();
        let top = map(&root);
        assert_eq!(top[0].0.name, "name");
        let v = map(&top[1].1);
        assert_eq!((v[0].0.name.as_str(), v[0].0.span.start), ("a", 13));
        let a = map(&v[0].1);
        let when = &a[1].1;
        let Val::Str(s) = &when.value else { panic!() };
        assert_eq!(&src[content_offset(src, when.span.start as usize, s)..][..7], "A.x > 2");
        let Val::Seq(items) = &v[1].1.value else { panic!() };
        assert!(matches!(items[3].value, Val::Null));
        assert_eq!(items[1].span.start, 49);
    }

    #[test]
    fn block_scalars_and_escapes_find_their_text() {
        let src = "a: |\n  B.y + 1\nb: \"x\\ty + q\"\n";
        let root = parse(src).unwrap();
        let top = map(&root);
        // An escape moves later columns; the text start is still right.
        for (i, want) in [(0, "B.y + 1"), (1, "x\\ty")] {
            let n = &top[i].1;
            let Val::Str(s) = &n.value else { panic!() };
            let at = content_offset(src, n.span.start as usize, s);
            assert!(src[at..].starts_with(want), "{i}: {:?}", &src[at..]);
        }
    }

    #[test]
    fn yaml_1_2_scalars() {
        let root = parse("a: [Y, n, on, true, .nan, -.inf, 0x10]").unwrap();
        let Val::Seq(items) = &map(&root)[0].1.value else { panic!() };
        let kinds: Vec<String> = items
            .iter()
            .map(|n| match &n.value {
                Val::Str(s) => s.clone(),
                Val::Bool(b) => b.to_string(),
                Val::Num(v) => format!("{v}"),
                v => v.kind().into(),
            })
            .collect();
        assert_eq!(kinds, ["Y", "n", "on", "true", "NaN", "-inf", "16"]);
    }

    #[test]
    fn bad_yaml_is_one_error_with_a_position() {
        let e = parse("a: 1\nb: [1, 2\n").unwrap_err();
        assert!(e.message.starts_with("invalid YAML: "), "{}", e.message);
        assert!(!e.message.contains("line"), "{}", e.message);
        let e = parse("a: 1\na: 2\n").unwrap_err();
        assert!(e.message.contains("duplicate"), "{}", e.message);
        assert_eq!(e.span.map(|s| s.start), Some(5));
    }
}
