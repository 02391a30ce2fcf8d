//! `--set KEY=V1,V2,…`: a scene key and the values a sweep gives it, and
//! applying them to the scene's TOML text.
//!
//! The scene is edited as a `toml_edit` document (the file's layout,
//! comments and every other key kept) and loaded again by the normal
//! loader, so each variant gets exactly the validation of a scene written
//! by hand. Problems the edit causes are reported against the `--set`
//! that caused them, not against positions in the edited text.

use anyhow::{Result, anyhow, bail};
use std::path::Path;
use toml_edit::{DocumentMut, Item, Table, TableLike, Value};

/// One `--set`: a dotted scene key and its values, in the order given.
#[derive(Clone, Debug)]
pub struct Axis {
    /// The dotted key, e.g. `ga.population` or `volume.target.0.fill`.
    pub key: String,
    /// The values as written (trimmed), e.g. `10`, `"roulette"`, `[10, 10]`.
    pub values: Vec<String>,
    parsed: Vec<Value>,
}

impl Axis {
    /// The key's segments.
    fn path(&self) -> Vec<&str> {
        self.key.split('.').collect()
    }

    /// `KEY=V1,V2,…` as given, for messages.
    pub fn shown(&self) -> String {
        format!("--set {}={}", self.key, self.values.join(","))
    }
}

/// Parses one `--set` argument: `KEY=V1,V2,…`.
///
/// Values are TOML values. They are separated by commas or semicolons
/// outside brackets, braces and quotes, so arrays and inline tables need
/// no escaping: `ga.initial_length=[10,10],[50,50]`,
/// `ga.selection.first={tournament=10},"roulette"`. A bare word that is
/// not a TOML value (`roulette`, `thesis`) is taken as a string, since
/// shells strip the quotes of `"roulette"`.
pub fn parse_set(arg: &str) -> Result<Axis> {
    let Some((key, values)) = arg.split_once('=') else {
        bail!("--set {arg}: expected KEY=V1,V2,… (e.g. --set ga.population=50,100,200)");
    };
    let key = key.trim();
    let bad_segment = |s: &str| s.is_empty() || !s.chars().all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '-');
    if key.split('.').any(bad_segment) {
        bail!("--set {arg}: `{key}` is not a dotted scene key such as ga.population or fitness.good");
    }
    let pieces = split_values(values).map_err(|e| anyhow!("--set {arg}: {e}"))?;
    let mut axis = Axis { key: key.to_string(), values: Vec::new(), parsed: Vec::new() };
    for piece in pieces {
        let value = parse_value(&piece).map_err(|e| anyhow!("--set {arg}: {e}"))?;
        if axis.values.contains(&piece) {
            bail!("--set {arg}: the value {piece} is given twice");
        }
        axis.values.push(piece);
        axis.parsed.push(value);
    }
    Ok(axis)
}

/// Splits `text` at commas and semicolons outside brackets, braces and
/// quotes; pieces are trimmed and may not be empty.
fn split_values(text: &str) -> Result<Vec<String>, String> {
    let mut pieces = Vec::new();
    let (mut depth, mut quote, mut escaped) = (0i32, None::<char>, false);
    let mut current = String::new();
    for c in text.chars() {
        match quote {
            Some(q) => {
                if escaped {
                    escaped = false;
                } else if c == '\\' && q == '"' {
                    escaped = true;
                } else if c == q {
                    quote = None;
                }
            }
            None => match c {
                '"' | '\'' => quote = Some(c),
                '[' | '{' => depth += 1,
                ']' | '}' => depth -= 1,
                ',' | ';' if depth == 0 => {
                    pieces.push(std::mem::take(&mut current));
                    continue;
                }
                _ => {}
            },
        }
        current.push(c);
    }
    if quote.is_some() || depth != 0 {
        return Err("unbalanced quotes or brackets in the values".into());
    }
    pieces.push(current);
    let pieces: Vec<String> = pieces.into_iter().map(|p| p.trim().to_string()).collect();
    if pieces.iter().any(String::is_empty) {
        return Err("an empty value (values are separated by `,` or `;`)".into());
    }
    Ok(pieces)
}

/// A TOML value, or a bare word taken as a string.
fn parse_value(text: &str) -> Result<Value, String> {
    match text.parse::<Value>() {
        Ok(v) => Ok(v),
        Err(e) => {
            let word = text.chars().all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '-');
            if word && text.starts_with(|c: char| c.is_ascii_alphabetic()) {
                Ok(Value::from(text))
            } else {
                let why = e.to_string().lines().last().unwrap_or_default().trim().to_string();
                Err(format!(
                    "`{text}` is not a TOML value (a number, \"string\", [array] or {{inline = table}}): {why}"
                ))
            }
        }
    }
}

/// The scene text with `key` set to `value`: missing tables are created,
/// numeric segments index arrays (`volume.target.0.fill`).
fn edit(doc: &mut DocumentMut, path: &[&str], value: &Value) -> Result<(), String> {
    set_in(doc.as_table_mut(), path, value)
}

fn set_in(table: &mut dyn TableLike, path: &[&str], value: &Value) -> Result<(), String> {
    let Some((first, rest)) = path.split_first() else { return Ok(()) };
    if rest.is_empty() {
        table.insert(first, Item::Value(value.clone()));
        return Ok(());
    }
    if table.get(first).is_none() {
        let mut t = Table::new();
        t.set_implicit(true);
        table.insert(first, Item::Table(t));
    }
    let child = table.get_mut(first).ok_or_else(|| format!("cannot reach `{first}`"))?;
    if let Ok(index) = rest[0].parse::<usize>() {
        let element: Option<&mut dyn TableLike> = match child {
            Item::ArrayOfTables(a) => a.get_mut(index).map(|t| t as &mut dyn TableLike),
            Item::Value(Value::Array(a)) => {
                a.get_mut(index).and_then(Value::as_inline_table_mut).map(|t| t as &mut dyn TableLike)
            }
            _ => return Err(format!("`{first}` is not a list, so `{}` cannot index it", rest[0])),
        };
        let element = element.ok_or_else(|| format!("`{first}` has no table number {index} (counting from 0)"))?;
        if rest.len() == 1 {
            return Err(format!("set a key inside `{first}.{index}`, not the whole entry"));
        }
        return set_in(element, &rest[1..], value);
    }
    match child.as_table_like_mut() {
        Some(t) => set_in(t, rest, value),
        None => Err(format!("`{first}` is a value, not a table, so it has no key `{}`", rest[0])),
    }
}

/// One combination of values: the text of each axis' value, in axis order.
pub type Combination = Vec<String>;

/// A scene text edited by a settings patch: the text, and how refusals
/// name the patch.
pub(crate) struct Patched {
    /// The edited text.
    pub text: String,
    /// `--set a=1 --set b=2`, what refusals name instead of positions.
    pub shown: String,
    /// The dotted keys set, for messages about unknown keys.
    pub keys: Vec<Vec<String>>,
}

/// `text` (the scene at `path`) with each axis set to its value at the
/// index given.
pub(crate) fn apply(path: &Path, text: &str, settings: &[(&Axis, usize)]) -> Result<Patched> {
    let mut doc: DocumentMut = text.parse().map_err(|e| anyhow!("{}: {e}", path.display()))?;
    let shown: Vec<String> = settings.iter().map(|(a, i)| format!("{}={}", a.key, a.values[*i])).collect();
    let shown = format!("--set {}", shown.join(" --set "));
    for (axis, i) in settings {
        edit(&mut doc, &axis.path(), &axis.parsed[*i]).map_err(|e| anyhow!("{shown}: {e}"))?;
    }
    let keys = settings.iter().map(|(a, _)| a.path().iter().map(|s| s.to_string()).collect()).collect();
    Ok(Patched { text: doc.to_string(), shown, keys })
}

/// Every combination of the axes' values (the first axis varies slowest),
/// as indices into each axis' values.
pub(crate) fn combinations(axes: &[Axis]) -> Vec<Vec<usize>> {
    let mut combos: Vec<Vec<usize>> = vec![Vec::new()];
    for axis in axes {
        combos = combos
            .into_iter()
            .flat_map(|c| (0..axis.values.len()).map(move |i| [c.clone(), vec![i]].concat()))
            .collect();
    }
    combos
}

/// A settings patch: `KEY=VALUE` arguments (`--set` of evolve, score and
/// compare; Python keyword arguments; one value each), parsed as sweep
/// axes are.
pub fn parse_patch(args: &[String]) -> Result<Vec<Axis>> {
    args.iter()
        .map(|arg| {
            let axis = parse_set(arg)?;
            if axis.values.len() != 1 {
                bail!("--set {arg}: give one value here (several values are for `genform sweep`)");
            }
            Ok(axis)
        })
        .collect()
}

/// Whether `name` is a table of a scene file (tree or codon) that keyword
/// settings may name with a dict of its keys: an optimizer's, a scorer's,
/// `[fitness]`, `[mapper]`, `[run]` or `[limits]`.
fn is_section(name: &str) -> bool {
    crate::optimizers::SECTIONS.iter().any(|s| s.name == name)
        || crate::scoring::SCORERS.iter().any(|s| s.section() == name)
        || ["fitness", "mapper", "run", "limits"].contains(&name)
}

/// Keyword settings (Python's `population=20`, `ga={...}`) as a settings
/// patch: a key naming a table of the scene ([`is_section`]) takes an
/// object of that table's keys; any other key belongs to `own` (the
/// algorithm's table).
pub fn patch_from_json(own: &str, updates: &serde_json::Map<String, serde_json::Value>) -> Result<Vec<String>> {
    let mut patch = Vec::new();
    for (key, value) in updates {
        match (is_section(key), value) {
            (true, serde_json::Value::Object(keys)) => {
                for (k, v) in keys {
                    patch.push(format!("{key}.{k}={}", toml_literal(v)?));
                }
            }
            (true, _) => bail!("settings: `{key}` takes a dict of the scene's [{key}] keys"),
            (false, v) => patch.push(format!("{own}.{key}={}", toml_literal(v)?)),
        }
    }
    Ok(patch)
}

/// `value` written as a TOML value (inline tables for objects).
fn toml_literal(value: &serde_json::Value) -> Result<String> {
    let v = toml::Value::try_from(value).map_err(|e| anyhow!("settings: {value} is not a TOML value ({e})"))?;
    Ok(v.to_string())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn values_split_outside_brackets_and_quotes() {
        let a = parse_set("ga.initial_length=[10,10];[50, 50]").unwrap();
        assert_eq!(
            (a.key.as_str(), a.values.clone()),
            ("ga.initial_length", vec!["[10,10]".into(), "[50, 50]".into()])
        );
        let b = parse_set(r#"ga.selection.first={tournament=10},"a,b",roulette"#).unwrap();
        assert_eq!(b.values, ["{tournament=10}", "\"a,b\"", "roulette"]);
        assert_eq!(b.parsed[2].as_str(), Some("roulette"), "a bare word is a string");
        assert_eq!(parse_set("ga.population= 10 , 50").unwrap().values, ["10", "50"]);
        for bad in ["ga.population", "=5", "ga..x=1", "ga.population=1,,2", "x=[1,2", "x=1,1", "x=1.5.5"] {
            assert!(parse_set(bad).is_err(), "{bad}");
        }
        let msg = parse_set("x=@").unwrap_err().to_string();
        assert!(msg.starts_with("--set x=@: `@` is not a TOML value"), "{msg}");
    }

    #[test]
    fn edits_reach_nested_inline_and_listed_tables() {
        let text = "a = 1 # keep\n[ga]\npopulation = 5\nselection = { first = \"random\" }\n[[t]]\nfill = 1\n[[t]]\nfill = 2\n";
        let mut doc: DocumentMut = text.parse().unwrap();
        let v = |s: &str| parse_value(s).unwrap();
        edit(&mut doc, &["ga", "population"], &v("50")).unwrap();
        edit(&mut doc, &["ga", "selection", "first"], &v("{ tournament = 3 }")).unwrap();
        edit(&mut doc, &["t", "1", "fill"], &v("-1.5")).unwrap();
        edit(&mut doc, &["run", "generations"], &v("7")).unwrap();
        let back: toml::Table = toml::from_str(&doc.to_string()).unwrap();
        assert_eq!(back["ga"]["population"].as_integer(), Some(50));
        assert_eq!(back["ga"]["selection"]["first"]["tournament"].as_integer(), Some(3));
        assert_eq!(back["t"][1]["fill"].as_float(), Some(-1.5));
        assert_eq!(back["t"][0]["fill"].as_integer(), Some(1));
        assert_eq!(back["run"]["generations"].as_integer(), Some(7));
        assert!(doc.to_string().contains("# keep"), "the rest of the file is kept");
        assert!(edit(&mut doc, &["a", "b"], &v("1")).unwrap_err().contains("is a value"));
        assert!(edit(&mut doc, &["t", "5", "fill"], &v("1")).unwrap_err().contains("no table number 5"));
    }

    #[test]
    fn keyword_settings_become_a_patch() {
        let updates: serde_json::Map<String, serde_json::Value> = serde_json::from_str(
            r#"{"population": 20, "selection": {"first": {"tournament": 3}}, "mh": {"chains": 4}, "name": "x"}"#,
        )
        .unwrap();
        let patch = patch_from_json("ga", &updates).unwrap();
        assert_eq!(
            patch,
            ["mh.chains=4", "ga.name=\"x\"", "ga.population=20", "ga.selection={ first = { tournament = 3 } }",]
        );
        for p in &patch {
            assert_eq!(parse_set(p).unwrap().values.len(), 1, "{p}");
        }
        let bad: serde_json::Map<String, serde_json::Value> = serde_json::from_str(r#"{"ga": 3}"#).unwrap();
        assert!(patch_from_json("ga", &bad).unwrap_err().to_string().contains("takes a dict"));
    }
}
