//! Text templates: `"M {A} Q {C + v/2} {B}"`, literal text with formula
//! holes, each formatted deterministically.
//!
//! A hole holds a number or a vector formula, optionally followed by
//! `:.N` for N decimals (`{r:.2}`); numbers are otherwise written with up
//! to 4 decimals, trailing zeros trimmed, and vectors as `x,y`. `{{` and
//! `}}` are literal braces. A template that is exactly one number hole
//! yields a number, not text.

use crate::graph::Value;
use crate::yaml::Positions;
use genform_core::diag::{Diagnostic, Span};
use genform_core::expr::vec2::{Compiled, VecScope, compile_any};
use genform_core::expr::{Program, parse_prefix};
use genform_core::rng::Draws;
use std::fmt::Write;
use std::sync::Arc;

/// Decimals of a number hole without `:.N`.
const DEFAULT_DECIMALS: usize = 4;

#[derive(Clone, Debug)]
enum Part {
    Text(String),
    Num(Program, Option<usize>),
    Vec([Program; 2], Option<usize>),
}

/// A compiled template.
#[derive(Clone, Debug)]
pub(crate) struct Template {
    parts: Vec<Part>,
}

impl Template {
    /// Compiles `text`; `pos` says where its bytes were written in the
    /// file, for error spans. Every error is reported.
    pub(crate) fn compile(text: &str, pos: &Positions, scope: &dyn VecScope) -> Result<Template, Vec<Diagnostic>> {
        let mut parts = Vec::new();
        let mut errors = Vec::new();
        let mut lit = String::new();
        let b = text.as_bytes();
        let mut i = 0;
        while i < text.len() {
            let c = b[i];
            if c == b'{' && b.get(i + 1) == Some(&b'{') || c == b'}' && b.get(i + 1) == Some(&b'}') {
                lit.push(c as char);
                i += 2;
                continue;
            }
            if c == b'}' {
                errors.push(
                    Diagnostic::error(pos.span(Span::new(i, i + 1)), "unmatched `}` in a template")
                        .with_hint("write `}}` for a literal brace"),
                );
                i += 1;
                continue;
            }
            if c != b'{' {
                let ch = text[i..].chars().next().unwrap_or(' ');
                lit.push(ch);
                i += ch.len_utf8();
                continue;
            }
            // A hole: a formula, then `}` or `:.N}`.
            let start = i + 1;
            let inner = &text[start..];
            let (ast, used) = match parse_prefix(inner) {
                Ok(x) => x,
                Err(d) => {
                    errors.push(pos.place(d.shifted(start)));
                    match inner.find('}') {
                        Some(j) => {
                            i = start + j + 1;
                            continue;
                        }
                        None => break,
                    }
                }
            };
            let mut j = start + used;
            while j < text.len() && b[j].is_ascii_whitespace() {
                j += 1;
            }
            let mut decimals = None;
            if text[j..].starts_with(":.") {
                let digits: String = text[j + 2..].chars().take_while(char::is_ascii_digit).collect();
                match digits.parse::<usize>() {
                    Ok(n) if n <= 12 => decimals = Some(n),
                    _ => errors.push(
                        Diagnostic::error(
                            pos.span(Span::new(j, j + 2 + digits.len())),
                            "bad precision in a template hole",
                        )
                        .with_hint("write `{r:.2}` for two decimals (at most 12)"),
                    ),
                }
                j += 2 + digits.len();
            }
            if b.get(j) != Some(&b'}') {
                errors.push(
                    Diagnostic::error(pos.span(Span::new(j, j + 1)), "expected `}` to close the template hole")
                        .with_hint("a hole is `{formula}` or `{formula:.N}`"),
                );
                match text[j..].find('}') {
                    Some(k) => {
                        i = j + k + 1;
                        continue;
                    }
                    None => break,
                }
            }
            i = j + 1;
            match compile_any(&ast, scope) {
                Ok(c) => {
                    if !lit.is_empty() {
                        parts.push(Part::Text(std::mem::take(&mut lit)));
                    }
                    parts.push(match c {
                        Compiled::Scalar(p) => Part::Num(p, decimals),
                        Compiled::Vector(p) => Part::Vec(p, decimals),
                    });
                }
                Err(ds) => errors.extend(ds.into_iter().map(|d| pos.place(d.shifted(start)))),
            }
        }
        if !lit.is_empty() {
            parts.push(Part::Text(lit));
        }
        if errors.is_empty() { Ok(Template { parts }) } else { Err(errors) }
    }

    /// Whether the template has no holes.
    pub(crate) fn is_literal(&self) -> bool {
        self.parts.iter().all(|p| matches!(p, Part::Text(_)))
    }

    /// Evaluates on `env`; random draws come from `draws`; `buf` is
    /// scratch space.
    pub(crate) fn eval(&self, env: &[f64], draws: &mut impl Draws, buf: &mut String) -> Value {
        if let [Part::Num(p, _)] = self.parts.as_slice() {
            return Value::Num(p.eval_draws(env, draws));
        }
        self.write(env, draws, buf);
        Value::Text(Arc::from(buf.as_str()))
    }

    /// Evaluates to text.
    pub(crate) fn text(&self, env: &[f64], draws: &mut impl Draws) -> String {
        let mut out = String::new();
        self.write(env, draws, &mut out);
        out
    }

    /// Evaluates into `out` (cleared first).
    pub(crate) fn write(&self, env: &[f64], draws: &mut impl Draws, out: &mut String) {
        out.clear();
        for part in &self.parts {
            match part {
                Part::Text(t) => out.push_str(t),
                Part::Num(p, d) => push_number(out, p.eval_draws(env, draws), *d),
                Part::Vec([x, y], d) => {
                    push_number(out, x.eval(env), *d);
                    out.push(',');
                    push_number(out, y.eval(env), *d);
                }
            }
        }
    }
}

/// `v` with `decimals` decimals (fixed), or up to 4 with trailing zeros
/// trimmed; never `-0`.
pub(crate) fn format_number(v: f64, decimals: Option<usize>) -> String {
    let mut s = String::new();
    push_number(&mut s, v, decimals);
    s
}

/// Appends [`format_number`]'s text. Rounds `v · 10^d` half away from zero
/// and prints the integer: the same digits for the same value everywhere,
/// and much cheaper than exact decimal expansion.
fn push_number(out: &mut String, v: f64, decimals: Option<usize>) {
    let d = decimals.unwrap_or(DEFAULT_DECIMALS);
    let scale = 10u64.pow(d as u32);
    let n = (v * scale as f64).round();
    if n.is_nan() || n.abs() >= 9e15 {
        // Huge or not finite: the standard formatting.
        let _ = write!(out, "{v:.d$}");
        return;
    }
    let n = n as i64;
    if n < 0 {
        out.push('-');
    }
    let n = n.unsigned_abs();
    crate::write::push_decimal(out, n / scale);
    let mut frac = n % scale;
    let mut digits = [b'0'; 12];
    for i in (0..d).rev() {
        digits[i] = b'0' + (frac % 10) as u8;
        frac /= 10;
    }
    let mut len = d;
    if decimals.is_none() {
        while len > 0 && digits[len - 1] == b'0' {
            len -= 1;
        }
    }
    if len > 0 {
        out.push('.');
        out.extend(digits[..len].iter().map(|&b| b as char));
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use genform_core::Rng;
    use genform_core::expr::Scope;

    struct S;
    impl Scope for S {
        fn variable(&self, name: &str) -> Option<u32> {
            ["A.x", "A.y", "r"].iter().position(|n| *n == name).map(|i| i as u32)
        }
    }
    impl VecScope for S {
        fn vector(&self, name: &str) -> Option<[String; 2]> {
            (name == "A").then(|| ["A.x".into(), "A.y".into()])
        }
    }

    fn run(t: &str) -> Value {
        let tpl = Template::compile(t, &Positions::verbatim(0, t.len()), &S).unwrap_or_else(|e| panic!("{t}: {e:?}"));
        tpl.eval(&[1.5, -2.0, 1.0 / 3.0], &mut Rng::from_seed(1), &mut String::new())
    }

    #[test]
    fn holes_are_formatted_deterministically() {
        assert_eq!(run("M {A} L {A + vec(1, 0)}"), Value::Text("M 1.5,-2 L 2.5,-2".into()));
        assert_eq!(run("{r}"), Value::Num(1.0 / 3.0));
        assert_eq!(run("w={r}"), Value::Text("w=0.3333".into()));
        assert_eq!(run("{r:.2} {{x}}"), Value::Text("0.33 {x}".into()));
        assert_eq!(run("{-0.00001}"), Value::Num(-0.00001));
        assert_eq!(run("[{-0.00001}]"), Value::Text("[0]".into()));
        assert_eq!(run("#ff0000"), Value::Text("#ff0000".into()));
        assert_eq!(format_number(-0.0, Some(2)), "0.00");
        assert_eq!(format_number(12.5, None), "12.5");
        assert_eq!(format_number(-3.00004, None), "-3");
        assert_eq!(format_number(-3.00006, None), "-3.0001");
        assert_eq!(format_number(0.5, Some(0)), "1");
        assert_eq!(format_number(1e20, Some(1)), "100000000000000000000.0");
        assert_eq!(format_number(f64::NAN, None), "NaN");
    }

    #[test]
    fn errors_point_into_the_text() {
        let e = Template::compile("ab {A.z} {r +} }", &Positions::verbatim(10, 16), &S).unwrap_err();
        let spans: Vec<u32> = e.iter().map(|d| d.span.unwrap().start).collect();
        assert_eq!(e.len(), 3, "{e:?}");
        assert_eq!(spans, [14, 23, 25]);
        assert!(e[0].message.contains("unknown name `A.z`"));
        let e = Template::compile("{r", &Positions::verbatim(0, 2), &S).unwrap_err();
        assert!(e[0].message.contains("expected `}`"), "{e:?}");
    }
}
