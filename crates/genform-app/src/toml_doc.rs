//! A TOML file read once with the span of every key and value, so each
//! part of a scene is read by its owner and every refusal — a wrong type,
//! an unknown key, a value out of range, two settings that do not go
//! together — names `file:line:col` of the value it refuses.
//!
//! A scene with a settings patch (`--set`, Python keywords) is read from
//! the edited text, whose positions would mislead: its refusals name the
//! patch instead ([`Doc::patched`]).

use anyhow::{Result, anyhow};
use serde::de::DeserializeOwned;
use std::ops::Range;
use std::path::Path;
use toml::Spanned;
use toml::de::{DeTable, DeValue, ValueDeserializer};

/// A value with its span.
pub(crate) type Value<'t> = Spanned<DeValue<'t>>;

/// A parsed TOML file.
pub(crate) struct Doc<'t> {
    path: &'t Path,
    text: &'t str,
    root: DeTable<'t>,
    /// The settings patch this text was edited with (`--set a=1 --set b=2`)
    /// and the keys it sets: refusals name it rather than positions in the
    /// edited text.
    patch: Option<(String, Vec<Vec<String>>)>,
}

impl<'t> Doc<'t> {
    /// Parses `text`, read from `path`; a syntax error names its position.
    pub(crate) fn parse(path: &'t Path, text: &'t str) -> Result<Doc<'t>> {
        let root = DeTable::parse(text).map_err(|e| {
            let at = e.span().map(|s| position_suffix(text, s.start)).unwrap_or_default();
            anyhow!("{}{at}: {}", path.display(), e.message().trim())
        })?;
        Ok(Doc { path, text, root: root.into_inner(), patch: None })
    }

    /// This document as the edited text of `patch` (e.g. `--set a=1`),
    /// which sets `keys`.
    pub(crate) fn patched(mut self, patch: String, keys: Vec<Vec<String>>) -> Doc<'t> {
        self.patch = Some((patch, keys));
        self
    }

    /// The file the text came from.
    pub(crate) fn path(&self) -> &Path {
        self.path
    }

    /// The top-level keys with their values, in the order of the file.
    pub(crate) fn entries(&self) -> Vec<(&str, &Value<'t>, Range<usize>)> {
        let mut all: Vec<_> = self.root.iter().map(|(k, v)| (k.get_ref().as_ref(), v, k.span())).collect();
        all.sort_by_key(|(_, _, span)| span.start);
        all
    }

    /// The top-level value of `key`.
    pub(crate) fn get(&self, key: &str) -> Option<&Value<'t>> {
        self.root.get(key)
    }

    /// The entries of the table `value` (none for other values), in the
    /// order of the file.
    pub(crate) fn table_entries<'v>(value: &'v Value<'t>) -> Vec<(&'v str, &'v Value<'t>, Range<usize>)> {
        let DeValue::Table(t) = value.get_ref() else { return Vec::new() };
        let mut all: Vec<_> = t.iter().map(|(k, v)| (k.get_ref().as_ref(), v, k.span())).collect();
        all.sort_by_key(|(_, _, span)| span.start);
        all
    }

    /// `value` read as a `T`; a mistake names its position (unknown keys
    /// with the known ones, wrong types, numbers out of range).
    pub(crate) fn read<T: DeserializeOwned>(&self, value: &Value<'t>) -> Result<T> {
        T::deserialize(ValueDeserializer::from(value.clone())).map_err(|e| {
            let message = e.message().trim().to_string();
            match (&self.patch, e.span()) {
                (Some((patch, keys)), _) => anyhow!("{patch}: {}", explain(&message, keys)),
                (None, Some(span)) => anyhow!("{}: {message}", self.at(span.start)),
                (None, None) => anyhow!("{}: {message}", self.path.display()),
            }
        })
    }

    /// The whole file read as a `T` (whose fields are top-level keys;
    /// keys it does not know are left to their owners).
    pub(crate) fn read_root<T: DeserializeOwned>(&self) -> Result<T> {
        self.read(&Spanned::new(0..self.text.len(), DeValue::Table(self.root.clone())))
    }

    /// Refuses an integer outside TOML's range (64-bit signed: the toml
    /// reader takes larger ones into unsigned settings, so a count of
    /// 2⁶⁴−1 would otherwise run until killed), at its position.
    pub(crate) fn check_integers(&self) -> Result<()> {
        fn find<'a, 'v>(value: &'a Value<'v>) -> Option<&'a Value<'v>> {
            match value.get_ref() {
                DeValue::Integer(i) => i64::from_str_radix(i.as_str(), i.radix()).is_err().then_some(value),
                DeValue::Array(a) => a.iter().find_map(find),
                DeValue::Table(t) => t.values().find_map(find),
                _ => None,
            }
        }
        let Some(bad) = self.root.values().find_map(find) else { return Ok(()) };
        let written = &self.text[bad.span()];
        let message = format!(
            "{written} is beyond TOML's integers ({} to {}); no setting needs so large a number",
            i64::MIN,
            i64::MAX
        );
        Err(match &self.patch {
            Some((patch, _)) => anyhow!("{patch}: {message}"),
            None => anyhow!("{}: {message}", self.at(bad.span().start)),
        })
    }

    /// `file:line:col` of byte `offset`.
    pub(crate) fn at(&self, offset: usize) -> String {
        format!("{}{}", self.path.display(), position_suffix(self.text, offset))
    }

    /// The span of the value at `path` (keys, and indices into arrays), or
    /// of the deepest part of it the file has (a missing key's table); for
    /// a top-level key the file lacks, `None`.
    pub(crate) fn span_of(&self, path: &[&str]) -> Option<Range<usize>> {
        let (first, rest) = path.split_first()?;
        let mut at = self.root.get(*first)?;
        for key in rest {
            let next = match at.get_ref() {
                DeValue::Table(t) => t.get(*key),
                DeValue::Array(a) => key.parse::<usize>().ok().and_then(|i| a.get(i)),
                _ => None,
            };
            match next {
                Some(v) => at = v,
                None => break,
            }
        }
        Some(at.span())
    }

    /// Where the value at `path` is (see [`Doc::span_of`]): `file:line:col`,
    /// the file alone when it lacks the key, or, for a patched text, the
    /// patch (`--set …`).
    pub(crate) fn place(&self, path: &[&str]) -> String {
        match (&self.patch, self.span_of(path)) {
            (Some((patch, _)), _) => patch.clone(),
            (None, Some(span)) => self.at(span.start),
            (None, None) => self.path.display().to_string(),
        }
    }

    /// A refusal of the value at `path`: `PLACE: message` ([`Doc::place`]).
    pub(crate) fn refuse(&self, path: &[&str], message: impl std::fmt::Display) -> anyhow::Error {
        anyhow!("{}: {message}", self.place(path))
    }
}

/// `(line, column)` of byte `offset` of `text`, both from 1; the column
/// counts characters.
pub(crate) fn line_col(text: &str, offset: usize) -> (usize, usize) {
    let offset = offset.min(text.len());
    let before = &text[..offset];
    let line = before.matches('\n').count() + 1;
    let col = before[before.rfind('\n').map_or(0, |i| i + 1)..].chars().count() + 1;
    (line, col)
}

/// `:line:col` of byte `offset` of `text`.
fn position_suffix(text: &str, offset: usize) -> String {
    let (line, col) = line_col(text, offset);
    format!(":{line}:{col}")
}

/// "`x` is not a KIND; did you mean `y`? The KINDs are a, b, c" — the
/// message for an unknown name among `names`.
pub(crate) fn unknown_name(name: &str, kind: &str, names: &[&str]) -> String {
    let hint = genform_core::expr::did_you_mean(name, names.iter().copied())
        .map(|n| format!("did you mean `{n}`? "))
        .unwrap_or_default();
    format!("`{name}` is not a {kind}; {hint}the names are {}", names.join(", "))
}

/// A deserialization message in terms of the keys set: unknown keys and
/// variants get the closest known name and the section they are in.
pub(crate) fn explain(message: &str, paths: &[Vec<String>]) -> String {
    for kind in ["field", "variant"] {
        let Some(rest) = message.strip_prefix(&format!("unknown {kind} `")) else { continue };
        let Some((name, expected)) = rest.split_once('`') else { continue };
        let known: Vec<&str> = expected.split('`').skip(1).step_by(2).collect();
        let suggestion = genform_core::expr::did_you_mean(name, known.iter().copied())
            .map(|s| format!("; did you mean `{s}`?"))
            .unwrap_or_default();
        let list = if known.is_empty() { String::new() } else { format!(" (known: {})", known.join(", ")) };
        if kind == "variant" {
            return format!("unknown value `{name}`{suggestion}{list}");
        }
        let section = paths
            .iter()
            .find_map(|p| p.iter().position(|s| s == name).map(|i| p[..i].join(".")))
            .map(|s| if s.is_empty() { "at the top level".to_string() } else { format!("in [{s}]") })
            .unwrap_or_default();
        return format!("unknown key `{name}` {section}{suggestion}{list}");
    }
    message.trim().to_string()
}

#[cfg(test)]
mod tests {
    use super::*;

    const TEXT: &str = "grammar = \"g.sg\"\n[ga]\nelitism = 3\npopulation   = 99\n[[volume.target]]\nmesh = \"a\"\n[[volume.target]]\nfill = 2.0\n";

    #[test]
    fn values_keep_their_positions() {
        let path = Path::new("s.toml");
        let doc = Doc::parse(path, TEXT).unwrap();
        let keys: Vec<&str> = doc.entries().iter().map(|(k, _, _)| *k).collect();
        assert_eq!(keys, ["grammar", "ga", "volume"], "in the file's order");
        let at = |p: &[&str]| doc.span_of(p).map(|s| line_col(TEXT, s.start));
        assert_eq!(at(&["ga", "population"]), Some((4, 16)));
        assert_eq!(at(&["volume", "target", "1", "fill"]), Some((8, 8)));
        assert_eq!(at(&["ga", "chains"]), Some((2, 1)), "a missing key: its table");
        assert_eq!(at(&["mh", "chains"]), None);
        assert_eq!(
            doc.refuse(&["ga", "population"], "[ga] population is too big").to_string(),
            "s.toml:4:16: [ga] population is too big"
        );
        assert_eq!(doc.refuse(&["mh"], "no").to_string(), "s.toml: no");
        let patched = Doc::parse(path, TEXT).unwrap().patched("--set ga.population=99".into(), Vec::new());
        assert_eq!(patched.refuse(&["ga", "population"], "bad").to_string(), "--set ga.population=99: bad");
    }

    #[test]
    fn reading_a_section_names_the_mistake_at_its_position() {
        #[derive(serde::Deserialize, Debug)]
        #[serde(deny_unknown_fields)]
        #[allow(dead_code)]
        struct Ga {
            population: u8,
            elitism: usize,
        }
        let path = Path::new("s.toml");
        let doc = Doc::parse(path, "[ga]\nelitism = 3\npopulation = 999\n").unwrap();
        let e = doc.read::<Ga>(doc.get("ga").unwrap()).unwrap_err().to_string();
        assert!(e.starts_with("s.toml:3:14: "), "{e}");
        let doc = Doc::parse(path, "[ga]\nelitism = 3\npopulaton = 9\n").unwrap();
        let e = doc.read::<Ga>(doc.get("ga").unwrap()).unwrap_err().to_string();
        assert!(e.starts_with("s.toml:3:1: unknown field `populaton`"), "{e}");
        let e = Doc::parse(path, "[ga\n").err().unwrap().to_string();
        assert!(e.starts_with("s.toml:1:"), "{e}");
    }

    #[test]
    fn unknown_names_get_a_suggestion() {
        assert_eq!(
            unknown_name("sise", "criterion", &["size", "symmetry"]),
            "`sise` is not a criterion; did you mean `size`? the names are size, symmetry"
        );
    }

    #[test]
    fn unknown_keys_and_values_get_suggestions() {
        let m = "unknown field `populaton`, expected one of `population`, `elitism`";
        assert_eq!(
            explain(m, &[vec!["ga".to_string(), "populaton".to_string()]]),
            "unknown key `populaton` in [ga]; did you mean `population`? (known: population, elitism)"
        );
        let top = explain("unknown field `gaa`, expected `ga` or `mh`", &[vec!["gaa".into(), "population".into()]]);
        assert!(top.starts_with("unknown key `gaa` at the top level; did you mean `ga`?"), "{top}");
        let v = explain("unknown variant `roulete`, expected `roulette` or `random`", &[vec!["ga".into(), "x".into()]]);
        assert!(v.starts_with("unknown value `roulete`; did you mean `roulette`?"), "{v}");
        assert_eq!(
            explain("invalid type: string \"x\", expected usize\n", &[]),
            "invalid type: string \"x\", expected usize"
        );
    }
}
