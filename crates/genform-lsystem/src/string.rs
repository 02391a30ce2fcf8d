//! The module string: symbols and their parameters in two flat arrays.

use crate::alphabet::{Alphabet, Sym};
use std::fmt::Write;

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
        let names = &alphabet.symbols;
        if !with_params || self.params.is_empty() {
            // Names only: one table lookup per module (`--string-out` of a
            // plant is millions of one-letter names).
            if names.iter().all(|n| n.name.len() == 1) {
                let bytes: Vec<u8> = names.iter().map(|n| n.name.as_bytes()[0]).collect();
                let out: Vec<u8> = self.syms.iter().map(|&s| bytes[s as usize]).collect();
                return String::from_utf8(out).expect("one-byte names are ASCII");
            }
            let len = self.syms.iter().map(|&s| names[s as usize].name.len()).sum();
            let mut out = String::with_capacity(len);
            for &s in &self.syms {
                out.push_str(&names[s as usize].name);
            }
            return out;
        }
        let mut out = String::new();
        for (s, p) in self.modules(alphabet) {
            out.push_str(&alphabet.symbols[s as usize].name);
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
        }
        out
    }
}
