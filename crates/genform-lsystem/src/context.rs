//! Bracket-aware context matching (ABOP §1.8, L-Py): the left context skips
//! whole sibling branches and steps out to the parent at `[`; the right
//! context skips lateral branches and fails at `]`, and its bracketed
//! sub-patterns match branches; ignored modules are passed over; nothing
//! matches past the string's ends.

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
    /// positions (in pattern order) to `found`. The pattern is an axial
    /// tree (ABOP §1.8): a bracketed sub-pattern `[…]` must match one of the
    /// branches that grow from the current node (the first that fits, in
    /// string order; the rest of that branch is not looked at), and the
    /// pattern goes on along the axis after it. Brackets in `pattern` are
    /// balanced (the compiler checks).
    pub(crate) fn right(&self, i: usize, pattern: &[Sym], found: &mut Vec<usize>) -> bool {
        let mut pos = i;
        let mut k = 0;
        while k < pattern.len() {
            let want = pattern[k];
            if self.push[want as usize] {
                let close = k + pattern_close(&pattern[k..], self.push, self.pop);
                return self.branch(pos, &pattern[k + 1..close], &pattern[(close + 1).min(pattern.len())..], found);
            }
            if self.pop[want as usize] {
                return false;
            }
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
            k += 1;
        }
        true
    }

    /// Tries `inner` against each branch growing from the node after `pos`
    /// (only ignored modules may stand between), then `rest` after the first
    /// branch that fits. No backtracking is needed: `rest` finds the same
    /// axis modules after any of the branches and has the most branches
    /// left after the earliest, so if the first fit fails, every later fit
    /// does too (and matching stays linear in the string).
    fn branch(&self, pos: usize, inner: &[Sym], rest: &[Sym], found: &mut Vec<usize>) -> bool {
        let mark = found.len();
        let mut at = pos + 1;
        while at < self.syms.len() {
            let s = self.syms[at] as usize;
            if self.ignored[s] {
                at += 1;
                continue;
            }
            if !self.push[s] {
                return false;
            }
            let close = self.partners[at] as usize;
            if close >= self.syms.len() {
                return false;
            }
            if self.right(at, inner, found) {
                return self.right(close, rest, found);
            }
            found.truncate(mark);
            at = close + 1;
        }
        false
    }
}

/// Index in `pattern` (which starts with `[`) of the `]` closing it, or
/// the pattern's length if none does.
fn pattern_close(pattern: &[Sym], push: &[bool], pop: &[bool]) -> usize {
    let mut depth = 0usize;
    for (k, &s) in pattern.iter().enumerate() {
        if push[s as usize] {
            depth += 1;
        } else if pop[s as usize] {
            depth -= 1;
            if depth == 0 {
                return k;
            }
        }
    }
    pattern.len()
}
