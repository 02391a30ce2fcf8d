//! Bracket-aware context matching (ABOP §1.8, L-Py): the left context skips
//! whole sibling branches and steps out to the parent at `[`; the right
//! context skips lateral branches and fails at `]`; ignored modules are
//! passed over; nothing matches past the string's ends.

use crate::alphabet::{Alphabet, Command, Sym};

/// Per position: the partner of each bracket, computed once per step.
/// An unmatched `]` is its own partner (the left search steps out there); an
/// unmatched `[` points past the end (the right search fails there).
pub(crate) fn bracket_partners(syms: &[Sym], alphabet: &Alphabet, out: &mut Vec<u32>) {
    out.clear();
    out.resize(syms.len(), 0);
    let mut stack = Vec::new();
    for (i, &s) in syms.iter().enumerate() {
        match alphabet.command(s) {
            Command::Push => stack.push(i),
            Command::Pop => match stack.pop() {
                Some(open) => {
                    out[open] = i as u32;
                    out[i] = open as u32;
                }
                None => out[i] = i as u32,
            },
            _ => {}
        }
    }
    for open in stack {
        out[open] = syms.len() as u32;
    }
}

/// What context matching reads.
pub(crate) struct Context<'a> {
    pub syms: &'a [Sym],
    pub partners: &'a [u32],
    pub ignored: &'a [bool],
    pub push: &'a [bool],
    pub pop: &'a [bool],
}

impl Context<'_> {
    /// Matches `pattern` to the left of position `i`; pushes the matched
    /// positions (in string order) to `found`.
    pub(crate) fn left(&self, i: usize, pattern: &[Sym], found: &mut Vec<usize>) -> bool {
        let start = found.len();
        let mut pos = i;
        let mut j = pattern.len();
        while j > 0 {
            if pos == 0 {
                return false;
            }
            pos -= 1;
            let s = self.syms[pos] as usize;
            if self.pop[s] {
                pos = self.partners[pos] as usize;
                continue;
            }
            if self.push[s] || self.ignored[s] {
                continue;
            }
            if self.syms[pos] != pattern[j - 1] {
                return false;
            }
            found.push(pos);
            j -= 1;
        }
        found[start..].reverse();
        true
    }

    /// Matches `pattern` to the right of position `i`; pushes the matched
    /// positions to `found`.
    pub(crate) fn right(&self, i: usize, pattern: &[Sym], found: &mut Vec<usize>) -> bool {
        let mut pos = i;
        for &want in pattern {
            loop {
                pos += 1;
                if pos >= self.syms.len() {
                    return false;
                }
                let s = self.syms[pos] as usize;
                if self.push[s] {
                    pos = self.partners[pos] as usize;
                    continue;
                }
                if self.pop[s] {
                    return false;
                }
                if !self.ignored[s] {
                    break;
                }
            }
            if self.syms[pos] != want {
                return false;
            }
            found.push(pos);
        }
        true
    }
}
