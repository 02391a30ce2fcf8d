//! The module string: symbols and their parameters in two flat arrays.

use crate::alphabet::{Alphabet, Sym};
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
        for (s, p) in self.modules(alphabet) {
            out.push_str(&names[s as usize].name);
            if with_params && !p.is_empty() {
                out.push('(');
                for (i, v) in p.iter().enumerate() {
                    if i > 0 {
                        out.push(',');
                    }
                    let _ = write!(out, "{v}");
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
