//! `Graph` → YAML in the host format, so a result can be read back as the
//! host of another grammar.

use crate::graph::{Graph, Value};
use std::fmt::Write;

/// The shortest text that reads back as exactly `v` (YAML's `.nan`,
/// `.inf`, `-.inf` for the non-finite).
pub(crate) fn number(v: f64) -> String {
    if v.is_nan() {
        ".nan".into()
    } else if v.is_infinite() {
        if v > 0.0 { ".inf".into() } else { "-.inf".into() }
    } else if v == 0.0 {
        "0".into()
    } else {
        format!("{v}")
    }
}

/// A double-quoted YAML string.
fn quoted(s: &str) -> String {
    let mut out = String::with_capacity(s.len() + 2);
    out.push('"');
    for c in s.chars() {
        match c {
            '"' => out.push_str("\\\""),
            '\\' => out.push_str("\\\\"),
            '\n' => out.push_str("\\n"),
            '\t' => out.push_str("\\t"),
            '\r' => out.push_str("\\r"),
            c if (c as u32) < 0x20 => {
                let _ = write!(out, "\\x{:02x}", c as u32);
            }
            c => out.push(c),
        }
    }
    out.push('"');
    out
}

fn value(v: &Value) -> String {
    match v {
        Value::Num(x) => number(*x),
        Value::Text(t) => quoted(t),
    }
}

/// Attribute names are identifiers, but a few read as other YAML scalars.
fn key(name: &str) -> String {
    if matches!(name, "true" | "false" | "null" | "True" | "False" | "Null" | "TRUE" | "FALSE" | "NULL") {
        quoted(name)
    } else {
        name.to_string()
    }
}

impl Graph {
    /// The graph as a `.gg.yaml` document with only a host: vertices named
    /// `v0, v1, …` and edges `e0, e1, …` in creation order, with positions,
    /// labels, directions and every attribute. Numbers are written so they
    /// read back exactly; generations are not kept (a graph read back starts
    /// at generation 0).
    pub fn to_yaml(&self) -> String {
        let mut out = String::new();
        let _ = writeln!(out, "# {} vertices, {} edges", self.vertex_count(), self.edge_count());
        out.push_str("host:\n  vertices:");
        let mut names = vec![u32::MAX; self.vertices.len()];
        let mut any = false;
        for (i, v) in self.vertices().enumerate() {
            any = true;
            names[v.id() as usize] = i as u32;
            let [x, y] = v.pos();
            let _ = write!(out, "\n    v{i}: {{x: {}, y: {}", number(x), number(y));
            if !v.label().is_empty() {
                let _ = write!(out, ", label: {}", quoted(v.label()));
            }
            for (name, val) in v.attrs() {
                let _ = write!(out, ", {}: {}", key(name), value(val));
            }
            out.push('}');
        }
        if !any {
            out.push_str(" {}");
        }
        out.push_str("\n  edges:");
        let mut any = false;
        for (i, e) in self.edges().enumerate() {
            any = true;
            let _ = write!(
                out,
                "\n    - {{name: e{i}, from: v{}, to: v{}",
                names[e.from() as usize],
                names[e.to() as usize]
            );
            if e.directed() {
                out.push_str(", directed: true");
            }
            if !e.label().is_empty() {
                let _ = write!(out, ", label: {}", quoted(e.label()));
            }
            for (name, val) in e.attrs() {
                let _ = write!(out, ", {}: {}", key(name), value(val));
            }
            out.push('}');
        }
        if !any {
            out.push_str(" []");
        }
        out.push('\n');
        out
    }
}
