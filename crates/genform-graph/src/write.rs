//! `Graph` → YAML in the host format, so a result can be read back as the
//! host of another grammar.

use crate::graph::{Graph, Value};
use std::fmt::Write;

/// The shortest text that reads back as exactly `v` (YAML's `.nan`,
/// `.inf`, `-.inf` for the non-finite).
pub(crate) fn number(v: f64) -> String {
    let mut out = String::new();
    push_number(&mut out, v);
    out
}

/// Appends [`number`]'s text.
fn push_number(out: &mut String, v: f64) {
    if v.is_nan() {
        out.push_str(".nan");
    } else if v.is_infinite() {
        out.push_str(if v > 0.0 { ".inf" } else { "-.inf" });
    } else if v == 0.0 {
        out.push('0');
    } else {
        let _ = write!(out, "{v}");
    }
}

/// A double-quoted YAML string.
fn quoted(s: &str) -> String {
    let mut out = String::with_capacity(s.len() + 2);
    push_quoted(&mut out, s);
    out
}

/// Appends [`quoted`]'s text.
fn push_quoted(out: &mut String, s: &str) {
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
}

fn push_value(out: &mut String, v: &Value) {
    match v {
        Value::Num(x) => push_number(out, *x),
        Value::Text(t) => push_quoted(out, t),
    }
}

/// Text buffered before it goes to the writer.
const CHUNK: usize = 1 << 16;

/// Attribute names are identifiers, but a few read as other YAML scalars.
fn key(name: &str) -> std::borrow::Cow<'_, str> {
    if matches!(name, "true" | "false" | "null" | "True" | "False" | "Null" | "TRUE" | "FALSE" | "NULL") {
        quoted(name).into()
    } else {
        name.into()
    }
}

impl Graph {
    /// The graph as a `.gg.yaml` document with only a host: vertices named
    /// `v0, v1, …` and edges `e0, e1, …` in creation order, with positions,
    /// labels, directions and every attribute. Numbers are written so they
    /// read back exactly; generations are not kept (a graph read back starts
    /// at generation 0).
    pub fn to_yaml(&self) -> String {
        let mut out = Vec::new();
        self.write_yaml(&mut out).expect("writing to memory cannot fail");
        String::from_utf8(out).expect("the YAML text is UTF-8")
    }

    /// Writes [`Graph::to_yaml`]'s text to `w` piece by piece, never
    /// holding the whole text (a large graph's YAML is larger than the
    /// graph).
    ///
    /// # Errors
    ///
    /// The writer's.
    pub fn write_yaml(&self, w: &mut impl std::io::Write) -> std::io::Result<()> {
        let mut out = String::with_capacity(CHUNK + 1024);
        let flush = |out: &mut String, w: &mut dyn std::io::Write, force: bool| {
            if force || out.len() >= CHUNK {
                w.write_all(out.as_bytes())?;
                out.clear();
            }
            std::io::Result::Ok(())
        };
        let _ = writeln!(out, "# {} vertices, {} edges", self.vertex_count(), self.edge_count());
        out.push_str("host:\n  vertices:");
        let mut names = vec![u32::MAX; self.vertices.len()];
        let mut any = false;
        for (i, v) in self.vertices().enumerate() {
            any = true;
            names[v.id() as usize] = i as u32;
            let [x, y] = v.pos();
            let _ = write!(out, "\n    v{i}: {{x: ");
            push_number(&mut out, x);
            out.push_str(", y: ");
            push_number(&mut out, y);
            if !v.label().is_empty() {
                out.push_str(", label: ");
                push_quoted(&mut out, v.label());
            }
            for (name, val) in v.attrs() {
                let _ = write!(out, ", {}: ", key(name));
                push_value(&mut out, val);
            }
            out.push('}');
            flush(&mut out, w, false)?;
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
                out.push_str(", label: ");
                push_quoted(&mut out, e.label());
            }
            for (name, val) in e.attrs() {
                let _ = write!(out, ", {}: ", key(name));
                push_value(&mut out, val);
            }
            out.push('}');
            flush(&mut out, w, false)?;
        }
        if !any {
            out.push_str(" []");
        }
        out.push('\n');
        flush(&mut out, w, true)
    }
}
