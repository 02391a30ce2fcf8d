//! YAML text → a tree of values with byte spans (via serde-saphyr).
//!
//! The grammar is read from this tree rather than deserialized into
//! structs directly, so that every schema problem (a wrong type, an unknown
//! key, a bad name) is reported with its position, all at once.

use genform_core::diag::{Diagnostic, Span};
use serde::de::{Deserialize, Deserializer, MapAccess, SeqAccess, Visitor};
use serde_saphyr::{Location, Spanned};
use std::fmt;
use std::sync::Arc;

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

/// Where each byte of a decoded string value was written in the file.
/// Quotes, escapes, folded line breaks and the indentation of block
/// scalars make the two differ, so every position inside a formula or
/// template goes through this map; each lies inside the file.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Positions(Arc<[u32]>);

impl Positions {
    /// A value written as is from byte `at` (a number shown as text).
    pub(crate) fn verbatim(at: usize, len: usize) -> Positions {
        Positions((at..=at + len).map(|k| k as u32).collect())
    }

    /// The positions of `value`, whose node starts at `node` in `text`: the
    /// value is walked against the text from where its content starts, in
    /// the scalar's style — byte for byte where it was written as is, one
    /// escape (double quotes), doubled quote (single quotes) or folded line
    /// break at a time where not, skipping indentation and escaped line
    /// breaks, which decode to nothing. Positions only move forwards and
    /// never past the end of the text.
    pub(crate) fn of(text: &str, node: usize, value: &str) -> Positions {
        let raw = text.as_bytes();
        let (style, mut r) = content_start(text, node);
        let mut out = Vec::with_capacity(value.len() + 1);
        for ch in value.chars() {
            r = skip_silent(text, r, ch, style);
            let here = r;
            r = if style == Style::Double && raw.get(r) == Some(&b'\\') {
                r + escape_len(&raw[r..])
            } else if style == Style::Single && ch == '\'' && text[r..].starts_with("''") {
                r + 2
            } else if text[r..].starts_with(ch) {
                r + ch.len_utf8()
            } else if matches!(raw.get(r), Some(b'\n' | b'\r')) {
                skip_fold(raw, r)
            } else {
                r
            }
            .min(text.len());
            while !text.is_char_boundary(r) {
                r += 1;
            }
            for b in 0..ch.len_utf8() {
                out.push((here + b).min(r.max(here)) as u32);
            }
        }
        out.push(r as u32);
        Positions(out.into())
    }

    /// The file offset of byte `k` of the value (its end for `k` past it).
    pub(crate) fn at(&self, k: usize) -> usize {
        self.0[k.min(self.0.len() - 1)] as usize
    }

    /// A span of the value as a span of the file.
    pub(crate) fn span(&self, s: Span) -> Span {
        let start = self.at(s.start as usize);
        Span::new(start, self.at(s.end as usize).max(start))
    }

    /// A diagnostic about the value (spans within it) placed in the file.
    pub(crate) fn place(&self, mut d: Diagnostic) -> Diagnostic {
        d.span = d.span.map(|s| self.span(s));
        for (s, _) in &mut d.labels {
            *s = self.span(*s);
        }
        d
    }
}

/// How a string scalar is written.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Style {
    Plain,
    Single,
    Double,
    Block,
}

/// The style of the scalar at `node` and where its content starts: after
/// the opening quote, or at `node` itself (a block scalar's node starts at
/// its first content line, after a header line ending in `|` or `>` with
/// any chomping and indentation indicators).
fn content_start(text: &str, node: usize) -> (Style, usize) {
    let node = node.min(text.len());
    let before = text.get(..node).unwrap_or("");
    let line = before.rfind('\n').map_or(0, |i| i + 1);
    if line > 0 && before[line..].bytes().all(|b| b == b' ' || b == b'\t') {
        let header = before[..line - 1].lines().next_back().unwrap_or("");
        let header = header.split(" #").next().unwrap_or("").trim_end();
        let indicators = header.trim_end_matches(|c: char| c == '-' || c == '+' || c.is_ascii_digit());
        if indicators.ends_with('|') || indicators.ends_with('>') {
            return (Style::Block, node);
        }
    }
    match text.as_bytes().get(node) {
        Some(b'"') => (Style::Double, node + 1),
        Some(b'\'') => (Style::Single, node + 1),
        _ => (Style::Plain, node),
    }
}

/// From `r`, past what decodes to nothing before character `ch`:
/// indentation and line breaks that a block scalar or a fold consumed, and
/// escaped line breaks in double quotes. Where the text does not explain
/// `ch` at all (a fuzzer's input), the next place it is written, within a
/// short window, else `r`.
fn skip_silent(text: &str, mut r: usize, ch: char, style: Style) -> usize {
    let raw = text.as_bytes();
    loop {
        if style == Style::Double && raw.get(r) == Some(&b'\\') && matches!(raw.get(r + 1), Some(b'\n' | b'\r')) {
            r = skip_fold(raw, r + 1);
            continue;
        }
        if matches!(raw.get(r), Some(b' ' | b'\t')) && !text[r..].starts_with(ch) {
            // Indentation (or spaces a fold swallowed).
            let mut k = r;
            while matches!(raw.get(k), Some(b' ' | b'\t')) {
                k += 1;
            }
            let line_start = r == 0 || matches!(raw.get(r - 1), Some(b'\n' | b'\r' | b' ' | b'\t'));
            if line_start {
                r = k;
                continue;
            }
        }
        break;
    }
    let explained = |k: usize| {
        text[k..].starts_with(ch)
            || style == Style::Double && raw.get(k) == Some(&b'\\')
            || matches!(raw.get(k), Some(b'\n' | b'\r')) && matches!(ch, ' ' | '\n')
    };
    if r >= text.len() || explained(r) {
        return r.min(text.len());
    }
    let end = text.len().min(r + 256);
    (r + 1..end).find(|&k| text.is_char_boundary(k) && explained(k)).unwrap_or(r)
}

/// Bytes of the escape at the start of `raw` (a backslash first).
fn escape_len(raw: &[u8]) -> usize {
    match raw.get(1) {
        Some(b'x') => 4,
        Some(b'u') => 6,
        Some(b'U') => 10,
        Some(_) => 2,
        None => 1,
    }
}

/// Past a line break at `r` and the indentation after it.
fn skip_fold(raw: &[u8], mut r: usize) -> usize {
    if raw.get(r) == Some(&b'\r') {
        r += 1;
    }
    if raw.get(r) == Some(&b'\n') {
        r += 1;
    }
    while matches!(raw.get(r), Some(b' ' | b'\t')) {
        r += 1;
    }
    r
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
        assert_eq!(&src[Positions::of(src, when.span.start as usize, s).at(0)..][..7], "A.x > 2");
        let Val::Seq(items) = &v[1].1.value else { panic!() };
        assert!(matches!(items[3].value, Val::Null));
        assert_eq!(items[1].span.start, 49);
    }

    /// The scalar of `k: …` and its positions.
    fn positions(src: &str) -> (String, Positions) {
        let root = parse(src).unwrap_or_else(|e| panic!("{src:?}: {e:?}"));
        let n = &map(&root)[0].1;
        let Val::Str(s) = &n.value else { panic!("{src:?}: {:?}", n.value) };
        (s.clone(), Positions::of(src, n.span.start as usize, s))
    }

    /// Every brace of the value is found where it was written, in every
    /// style; no position leaves the file.
    fn braces_are_where_written(src: &str) {
        let (value, pos) = positions(src);
        let mut last = 0;
        for k in 0..=value.len() {
            let at = pos.at(k);
            assert!(at >= last && at <= src.len(), "{src:?}: byte {k} of {value:?} at {at}");
            last = at;
        }
        for (k, c) in value.char_indices().filter(|(_, c)| matches!(c, '{' | '}')) {
            assert_eq!(src[pos.at(k)..].chars().next(), Some(c), "{src:?}: {value:?} byte {k}");
        }
    }

    #[test]
    fn escapes_folds_and_indentation_keep_positions() {
        for src in [
            "k: \"a\\tb {x} \\\" }\"\n",
            "k: 'it''s {x} }'\n",
            "k: |-\n  line {a}\n    more }\n  end {b\n",
            "k: >-\n  one {a}\n  two }\n",
            "k: \"é\\u00e9 {x}\\\n   folded }\"\n",
            "k: plain {a}\n  continued }\n",
        ] {
            braces_are_where_written(src);
        }
        // The escape `\t` is one character of the value, two of the file.
        let (v, pos) = positions("k: \"\\t{\"\n");
        assert_eq!((v.as_str(), pos.at(0), pos.at(1)), ("\t{", 4, 6));
    }

    proptest::proptest! {
        /// Random text of quotes, escapes, braces and line breaks, written
        /// as a double-quoted, single-quoted and literal block scalar.
        #[test]
        fn positions_follow_every_style(chars in proptest::collection::vec(
            proptest::sample::select(vec!["a", " ", "{", "}", "\"", "'", "\\", "\t", "é", "\n", "x {", "} y"]), 0..24)) {
            let value: String = chars.concat();
            let double: String = value.chars().map(|c| match c {
                '"' => "\\\"".to_string(),
                '\\' => "\\\\".to_string(),
                '\t' => "\\t".to_string(),
                '\n' => "\\n".to_string(),
                c => c.to_string(),
            }).collect();
            braces_are_where_written(&format!("k: \"{double}\"\n"));
            let one_line: String = value.replace(['\n', '\t'], " ");
            if !one_line.trim().is_empty() {
                braces_are_where_written(&format!("k: '{}'\n", one_line.replace('\'', "''")));
            }
            let lines: Vec<&str> = value.split('\n').map(str::trim).filter(|l| !l.is_empty()).collect();
            if !lines.is_empty() && !lines.iter().any(|l| l.starts_with('#')) {
                braces_are_where_written(&format!("k: |-\n  {}\n", lines.join("\n  ")));
            }
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
