//! The module string: symbols and their parameters in two flat arrays.

use crate::alphabet::{Alphabet, PyKinds, Sym};
use std::fmt::Write;

/// The size of the pieces [`ModuleString::display_pieces`] hands over.
const PIECE: usize = 1 << 16;

/// A string of modules. Symbol `syms[i]` owns the next
/// `alphabet.arity(syms[i])` values of `params`, in order, so the string is
/// two contiguous arrays (no per-module allocation) and a parameter-free
/// string is a plain `Vec<u16>`.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ModuleString {
    /// The symbols.
    pub syms: Vec<Sym>,
    /// All parameters, module after module.
    pub params: Vec<f64>,
    /// The L-system's global state after the derivation that made the
    /// string: the steps done (`iteration`), then the `global` variables
    /// in declaration order (empty when not derived; interpretation rules
    /// then read the declared values).
    pub state: Vec<f64>,
}

impl ModuleString {
    /// Number of modules.
    pub fn len(&self) -> usize {
        self.syms.len()
    }

    /// No modules.
    pub fn is_empty(&self) -> bool {
        self.syms.is_empty()
    }

    /// How many modules have symbol name `name` (any arity).
    pub fn count(&self, alphabet: &Alphabet, name: &str) -> usize {
        let mut hit = vec![false; alphabet.symbols.len()];
        for s in alphabet.named(name) {
            hit[s as usize] = true;
        }
        self.syms.iter().filter(|&&s| hit[s as usize]).count()
    }

    /// Each module with its parameters, in order.
    pub fn modules<'a>(&'a self, alphabet: &'a Alphabet) -> impl Iterator<Item = (Sym, &'a [f64])> + 'a {
        let mut off = 0;
        self.syms.iter().map(move |&s| {
            let n = alphabet.arity(s);
            let p = &self.params[off..off + n];
            off += n;
            (s, p)
        })
    }

    /// The string as text: names, and parameters in parentheses when
    /// `with_params` (shortest round-trip formatting).
    pub fn display(&self, alphabet: &Alphabet, with_params: bool) -> String {
        let mut out = String::new();
        let _ = self.display_pieces(alphabet, with_params, |piece| {
            out.push_str(piece);
            Ok::<(), std::convert::Infallible>(())
        });
        out
    }

    /// [`ModuleString::display`] handed to `take` in pieces of about 64 KB,
    /// in order: `--string-out` of a plant is megabytes, never held whole.
    /// Stops at `take`'s first error.
    pub fn display_pieces<E>(
        &self,
        alphabet: &Alphabet,
        with_params: bool,
        mut take: impl FnMut(&str) -> Result<(), E>,
    ) -> Result<(), E> {
        let names = &alphabet.symbols;
        if (!with_params || self.params.is_empty()) && names.iter().all(|n| n.name.len() == 1) {
            // One-letter names: one table lookup per module.
            let bytes: Vec<u8> = names.iter().map(|n| n.name.as_bytes()[0]).collect();
            let mut buf = Vec::with_capacity(PIECE.min(self.syms.len()));
            for chunk in self.syms.chunks(PIECE) {
                buf.clear();
                buf.extend(chunk.iter().map(|&s| bytes[s as usize]));
                take(std::str::from_utf8(&buf).expect("one-byte names are ASCII"))?;
            }
            return Ok(());
        }
        let mut out = String::new();
        // `iteration` after a derivation (none: the axiom).
        let steps = self.state.first().map_or(0, |&steps| steps as usize);
        for (s, p) in self.modules(alphabet) {
            out.push_str(&names[s as usize].name);
            if with_params && !p.is_empty() {
                out.push('(');
                let python = names[s as usize].python.as_ref().map(|p| p.at(steps));
                for (i, &v) in p.iter().enumerate() {
                    if i > 0 {
                        out.push(',');
                    }
                    match python {
                        None => {
                            let _ = write!(out, "{v}");
                        }
                        Some(py) => python_number(&mut out, v, py, i),
                    }
                }
                out.push(')');
            }
            if out.len() >= PIECE {
                take(&out)?;
                out.clear();
            }
        }
        if out.is_empty() { Ok(()) } else { take(&out) }
    }
}

/// Writes parameter `i` of a module whose parameters print as Python's
/// (see [`crate::PyParams`]): a boolean as `True`/`False`, a float always with
/// its point or exponent (`6.0`, `1e-05`), any other whole number as an
/// int, anything else as the float it must be.
fn python_number(out: &mut String, v: f64, py: PyKinds, i: usize) {
    let bit = if i < 64 { 1u64 << i } else { 0 };
    if py.bools & bit != 0 && (v == 0.0 || v == 1.0) {
        out.push_str(if v == 1.0 { "True" } else { "False" });
    } else if py.floats & bit == 0 && v.fract() == 0.0 {
        // `-0.0` is the int 0.
        let _ = write!(out, "{}", v + 0.0);
    } else {
        python_float(out, v);
    }
}

/// Python's `repr` of a float: the shortest digits that read back, in
/// positional notation with a point when 1e-4 ≤ |v| < 1e16 (exactly where
/// those digits' exponent is −4 to 15: the shortest digits of a double
/// read back to it, so they lie on its side of a bound that is a double
/// itself), else as `d.ddde±XX`.
pub(crate) fn python_float(out: &mut String, v: f64) {
    if v.is_nan() {
        out.push_str("nan");
    } else if v.is_infinite() {
        out.push_str(if v > 0.0 { "inf" } else { "-inf" });
    } else if v == 0.0 || (1e-4..1e16).contains(&v.abs()) {
        let start = out.len();
        positional(out, start, v);
        even_tie(out, start, v);
    } else {
        let start = out.len();
        let _ = write!(out, "{v:e}");
        even_tie(out, start, v);
        let e = start + out[start..].find('e').expect("`{:e}` writes an exponent");
        let exp: i32 = out[e + 1..].parse().expect("`{:e}` writes a whole exponent");
        out.truncate(e + 1);
        let _ = write!(out, "{}{:02}", if exp < 0 { '-' } else { '+' }, exp.unsigned_abs());
    }
}

/// Where two shortest digit strings read back to `v` and `v` lies exactly
/// halfway between them (`631496354690342.25` between `…342.2` and
/// `…342.3`), Python's `repr` takes the even last digit; Rust's shortest
/// formatting takes the upper one. Rewrites `out[start..]` (positional, or
/// Rust's `{:e}`) to Python's.
fn even_tie(out: &mut String, start: usize, v: f64) {
    let text = &out[start..];
    let (mantissa, exp) = match text.find('e') {
        Some(e) => (&text[..e], text[e + 1..].parse::<i32>().unwrap_or(0)),
        None => (text, 0),
    };
    let Some(&last) = mantissa.as_bytes().last().filter(|b| b.is_ascii_digit()) else { return };
    if (last - b'0').is_multiple_of(2) {
        return;
    }
    // The last digit stands for 10^place. Both neighbours read back only
    // when one step of the last digit fits in v's rounding interval (one
    // ulp wide), and a midpoint (a 5 at 10^(place-1)) is a double only when
    // v·2^(1-place) is whole: most values stop here.
    let fraction = mantissa.rfind('.').map_or(0, |d| mantissa.len() - d - 1) as i32;
    let place = exp - fraction;
    // 2^(1-place), exactly, from its bits (a normal double up to 2^1023).
    let dyadic = |k: i32| (0..=1023).contains(&k).then(|| f64::from_bits(((1023 + k) as u64) << 52));
    if place <= 0 && dyadic(1 - place).is_some_and(|p| (v * p).fract() != 0.0) {
        return;
    }
    let ulp = f64::from_bits(v.abs().to_bits() + 1) - v.abs();
    if ulp < 0.5 * 10f64.powi(place) {
        return;
    }
    let lower_mantissa = format!("{}{}", &mantissa[..mantissa.len() - 1], last - b'0' - 1);
    let mid_mantissa = format!("{lower_mantissa}5");
    let tail = &text[mantissa.len()..];
    let (lower, mid) = (format!("{lower_mantissa}{tail}"), format!("{mid_mantissa}{tail}"));
    if lower.parse::<f64>() != Ok(v) || mid.parse::<f64>() != Ok(v) {
        return;
    }
    // `v` exactly, digit for digit (every double has a finite expansion),
    // against the midpoint's digits.
    let digits = |s: &str| -> String {
        let d: String = s.chars().take_while(|&c| c != 'e').filter(char::is_ascii_digit).collect();
        d.trim_start_matches('0').trim_end_matches('0').to_string()
    };
    if digits(&format!("{:.800e}", v.abs())) == digits(&mid_mantissa) {
        out.truncate(start);
        out.push_str(&lower);
    }
}

/// `v` in positional notation from `start` of `out`, with a point.
fn positional(out: &mut String, start: usize, v: f64) {
    let _ = write!(out, "{v}");
    if !out[start..].contains('.') {
        out.push_str(".0");
    }
}
