//! `Graph` → YAML in the host format, so a result can be read back as the
//! host of another grammar.

use crate::graph::{Graph, Value};
use crate::table::grown;
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
        // Ryū finds the shortest text that reads back as `v`, several
        // times faster than the standard formatter; where two such texts
        // lie equally close to `v` the two break the tie differently. A
        // tie puts `v` halfway between two texts of d decimals, so `v`
        // has exactly d + 1 decimals, that is d + 1 binary fraction digits
        // (2^−k has k decimals): only then, and where Ryū writes an
        // exponent (far from 1), is the standard text written. Ryū also
        // writes `1.0` for `1`.
        let mut buf = ryu::Buffer::new();
        let text = buf.format_finite(v);
        // One pass over the (at most 24) bytes for the point and an exponent.
        let (mut point, mut exponent) = (None, false);
        for (i, &b) in text.as_bytes().iter().enumerate() {
            match b {
                b'.' => point = Some(i),
                b'e' => exponent = true,
                _ => {}
            }
        }
        let decimals = match point {
            Some(i) if &text[i..] != ".0" => (text.len() - i - 1) as u32,
            _ => 0,
        };
        if exponent || fraction_bits(v) == decimals + 1 {
            let _ = write!(out, "{v}");
        } else {
            out.push_str(text.strip_suffix(".0").unwrap_or(text));
        }
    }
}

/// How many binary digits `v` (finite) has after the point.
fn fraction_bits(v: f64) -> u32 {
    let bits = v.to_bits();
    let (exp, mantissa) = ((bits >> 52) & 0x7ff, bits & ((1 << 52) - 1));
    let (m, e) = if exp == 0 { (mantissa, -1074) } else { (mantissa | 1 << 52, exp as i32 - 1075) };
    if m == 0 {
        return 0;
    }
    // v = m · 2^e with m made odd.
    (-(e + m.trailing_zeros() as i32)).max(0) as u32
}

/// Appends `n` in decimal.
fn push_u32(out: &mut String, n: u32) {
    push_decimal(out, u64::from(n));
}

/// Appends `n` in decimal, without the formatter.
pub(crate) fn push_decimal(out: &mut String, mut n: u64) {
    let mut digits = [0u8; 20];
    let mut at = digits.len();
    loop {
        at -= 1;
        digits[at] = b'0' + (n % 10) as u8;
        n /= 10;
        if n == 0 {
            break;
        }
    }
    // Pushed one by one: checking a few bytes for UTF-8 costs more.
    digits[at..].iter().for_each(|&d| out.push(char::from(d)));
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

/// Each label's and each attribute list's text, written once: the elements
/// of a graph share a few.
struct Texts<'g> {
    g: &'g Graph,
    labels: Vec<Option<String>>,
    lists: Vec<Option<String>>,
}

impl Texts<'_> {
    /// `, label: "…"`, or nothing for no label.
    fn label(&mut self, id: u32) -> &str {
        let g = self.g;
        grown(&mut self.labels, id as usize).get_or_insert_with(|| {
            let mut out = String::new();
            let name = g.labels.name(id);
            if !name.is_empty() {
                out.push_str(", label: ");
                push_quoted(&mut out, name);
            }
            out
        })
    }

    /// `, name: value` for each attribute of list `id`.
    fn list(&mut self, id: u32) -> &str {
        let g = self.g;
        grown(&mut self.lists, id as usize).get_or_insert_with(|| {
            let mut out = String::new();
            for (a, v) in g.attr_sets.get(id) {
                let _ = write!(out, ", {}: ", key(g.attr_names.name(*a)));
                push_value(&mut out, v);
            }
            out
        })
    }
}

/// Edges read ahead per chunk by [`Graph::write_yaml`].
const GATHER: usize = 256;

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
        let mut text = String::new();
        let mut append = |piece: &str| {
            text.push_str(piece);
            Ok(())
        };
        self.write_pieces(&mut append).expect("writing to memory cannot fail");
        text
    }

    /// Writes [`Graph::to_yaml`]'s text to `w` piece by piece, never
    /// holding the whole text (a large graph's YAML is larger than the
    /// graph).
    ///
    /// # Errors
    ///
    /// The writer's.
    pub fn write_yaml(&self, w: &mut impl std::io::Write) -> std::io::Result<()> {
        self.write_pieces(&mut |piece| w.write_all(piece.as_bytes()))
    }

    /// The YAML text, handed to `sink` in pieces of about [`CHUNK`] bytes.
    fn write_pieces(&self, sink: &mut dyn FnMut(&str) -> std::io::Result<()>) -> std::io::Result<()> {
        let mut out = String::with_capacity(CHUNK + 1024);
        let flush = |out: &mut String, sink: &mut dyn FnMut(&str) -> std::io::Result<()>, force: bool| {
            if force || out.len() >= CHUNK {
                sink(out)?;
                out.clear();
            }
            std::io::Result::Ok(())
        };
        let _ = writeln!(out, "# {} vertices, {} edges", self.vertex_count(), self.edge_count());
        out.push_str("host:\n  vertices:");
        let mut texts = Texts { g: self, labels: Vec::new(), lists: Vec::new() };
        let mut names = vec![u32::MAX; self.vertices.len()];
        for (i, v) in self.vertices().enumerate() {
            names[v.id() as usize] = i as u32;
            let [x, y] = v.pos();
            out.push_str("\n    v");
            push_u32(&mut out, i as u32);
            out.push_str(": {x: ");
            push_number(&mut out, x);
            out.push_str(", y: ");
            push_number(&mut out, y);
            let c = &self.vertices[v.id() as usize].c;
            out.push_str(texts.label(c.label));
            out.push_str(texts.list(c.attrs));
            out.push('}');
            flush(&mut out, sink, false)?;
        }
        if self.vertex_count() == 0 {
            out.push_str(" {}");
        }
        out.push_str("\n  edges:");
        let edges = self.edge_ids();
        // A chunk's edge records and their ends' names first, in loops of
        // their own: edges in creation order are scattered over their slots,
        // and small loops keep many of those reads in flight.
        let mut read = Vec::with_capacity(GATHER);
        for (c, chunk) in edges.chunks(GATHER).enumerate() {
            read.clear();
            read.extend(chunk.iter().map(|&id| {
                let e = &self.edges[id as usize];
                (e.from, e.to, e.directed, e.c.label, e.c.attrs)
            }));
            for r in &mut read {
                (r.0, r.1) = (names[r.0 as usize], names[r.1 as usize]);
            }
            for (k, &(from, to, directed, label, attrs)) in read.iter().enumerate() {
                out.push_str("\n    - {name: e");
                push_u32(&mut out, (c * GATHER + k) as u32);
                out.push_str(", from: v");
                push_u32(&mut out, from);
                out.push_str(", to: v");
                push_u32(&mut out, to);
                if directed {
                    out.push_str(", directed: true");
                }
                out.push_str(texts.label(label));
                out.push_str(texts.list(attrs));
                out.push('}');
                flush(&mut out, sink, false)?;
            }
        }
        if edges.is_empty() {
            out.push_str(" []");
        }
        out.push('\n');
        flush(&mut out, sink, true)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    #[test]
    fn integers_and_special_numbers() {
        for n in [0, 7, 10, 99, 1000, 4_294_967_295u32] {
            let mut s = String::new();
            push_u32(&mut s, n);
            assert_eq!(s, n.to_string());
        }
        for (v, want) in [(f64::NAN, ".nan"), (f64::INFINITY, ".inf"), (-f64::INFINITY, "-.inf"), (-0.0, "0")] {
            assert_eq!(number(v), want);
        }
        for v in [1.0, -2.0, 0.1, 1e15, 1e16, 1e17, 1e-5, 1e-7, 123456789.125, f64::MAX, f64::MIN_POSITIVE, 5e-324] {
            assert_eq!(number(v), format!("{v}"), "{v:e}");
        }
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(20_000))]

        #[test]
        fn any_number_is_written_as_the_standard_formatter_writes_it(bits in any::<u64>()) {
            let v = f64::from_bits(bits);
            prop_assume!(v.is_finite() && v != 0.0);
            prop_assert_eq!(number(v), format!("{v}"));
        }

        #[test]
        fn numbers_near_the_last_digits_are_written_as_the_standard_formatter_writes_them(
            v in 1e12f64..1e17, k in 0u32..5
        ) {
            // Where 15 to 17 significant digits meet, and two shortest
            // texts can tie (a quarter at 2^51, say).
            let v = (v * 4f64.powi(k as i32)).round() / 4f64.powi(k as i32);
            prop_assert_eq!(number(v), format!("{v}"));
        }

        #[test]
        fn coordinates_are_written_as_the_standard_formatter_writes_them(v in -1e6f64..1e6, k in 0u32..9) {
            // Values with few decimals, as a grammar's constants make them,
            // and (k = 8) with every bit used, as placement formulas do.
            let v = if k == 8 { v } else { (v * 10f64.powi(k as i32)).round() / 10f64.powi(k as i32) };
            prop_assume!(v != 0.0);
            prop_assert_eq!(number(v), format!("{v}"));
        }
    }
}
