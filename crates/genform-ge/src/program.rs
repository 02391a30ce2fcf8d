//! The grammar flattened for the mapper's hot loop: every alternative and
//! group is a range of one symbol array, terminals are ids with a
//! precomputed kind, and each rule knows its terminal-only alternatives.

use crate::bnf::{Bnf, Item};

/// A symbol of a flattened alternative or group, or a bookkeeping mark the
/// mapper pushes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Sym {
    /// Terminal id.
    Term(u32),
    /// Rule id.
    Nt(u32),
    /// `{ }` group id.
    Repeat(u32),
    /// `[ ]` group id (evolved options only; `[? ]` is dropped).
    Option(u32),
    /// End of a repair-rule expansion (repair bookkeeping).
    RuleEnd,
    /// End of a predecessor expansion (repair bookkeeping).
    PredEnd,
}

/// How the mapper treats a terminal.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum TermKind {
    /// Written as is.
    Plain,
    /// `Edge`: reads a fresh ID.
    Edge,
    /// `EdgeX` (0), `EdgeY` (1), `EdgeZ` (2): bound per production instance.
    Bound(u8),
}

#[derive(Clone, Copy, Debug)]
pub(crate) struct RuleP {
    /// First alternative in `Program::prods`.
    pub first: u32,
    /// Number of alternatives.
    pub n: u32,
    /// First entry in `Program::limited`.
    pub limited_first: u32,
    /// Number of alternatives with no non-terminal.
    pub limited_n: u32,
}

#[derive(Clone, Copy, Debug)]
pub(crate) struct Range {
    pub start: u32,
    pub end: u32,
    /// Whether a bound edge (`EdgeX`…) occurs in it, groups included.
    pub binds: bool,
}

#[derive(Clone, Debug)]
pub(crate) struct Program {
    pub names: Vec<String>,
    pub terms: Vec<String>,
    pub kinds: Vec<TermKind>,
    pub rules: Vec<RuleP>,
    pub prods: Vec<Range>,
    /// Per rule, the local indices of its terminal-only alternatives.
    pub limited: Vec<u32>,
    pub groups: Vec<Range>,
    /// The rule each group belongs to (for traces).
    pub group_owner: Vec<u32>,
    pub syms: Vec<Sym>,
}

impl Program {
    /// Flattens `bnf`; with `edge_ids`, the `Edge…` terminals get their kinds.
    pub fn new(bnf: &Bnf, edge_ids: bool) -> Program {
        let kinds = bnf
            .terminals
            .iter()
            .map(|t| match (edge_ids, t.as_str()) {
                (true, "Edge") => TermKind::Edge,
                (true, "EdgeX") => TermKind::Bound(0),
                (true, "EdgeY") => TermKind::Bound(1),
                (true, "EdgeZ") => TermKind::Bound(2),
                _ => TermKind::Plain,
            })
            .collect();
        let mut p = Program {
            names: bnf.rules.iter().map(|r| r.name.clone()).collect(),
            terms: bnf.terminals.clone(),
            kinds,
            rules: Vec::new(),
            prods: Vec::new(),
            limited: Vec::new(),
            groups: Vec::new(),
            group_owner: Vec::new(),
            syms: Vec::new(),
        };
        for (ri, rule) in bnf.rules.iter().enumerate() {
            let first = p.prods.len() as u32;
            let limited_first = p.limited.len() as u32;
            for (ai, alt) in rule.alternatives.iter().enumerate() {
                let range = p.flatten(&alt.items, ri as u32);
                p.prods.push(range);
                if !alt.has_nonterminal() {
                    p.limited.push(ai as u32);
                }
            }
            p.rules.push(RuleP {
                first,
                n: rule.alternatives.len() as u32,
                limited_first,
                limited_n: p.limited.len() as u32 - limited_first,
            });
        }
        p
    }

    /// Appends `items` as one contiguous range (groups get ranges of their
    /// own, placed after it).
    fn flatten(&mut self, items: &[Item], owner: u32) -> Range {
        let mut seq = Vec::with_capacity(items.len());
        let mut binds = false;
        for item in items {
            match item {
                Item::Terminal(t) => {
                    binds |= matches!(self.kinds[t.0 as usize], TermKind::Bound(_));
                    seq.push(Sym::Term(t.0));
                }
                Item::NonTerminal(r) => seq.push(Sym::Nt(r.0)),
                Item::Repeat(g) => {
                    let id = self.group(g, owner, &mut binds);
                    seq.push(Sym::Repeat(id));
                }
                Item::Optional { items: g, evolved: true } => {
                    let id = self.group(g, owner, &mut binds);
                    seq.push(Sym::Option(id));
                }
                // Not evolved: never emitted and reads no gene.
                Item::Optional { evolved: false, .. } => {}
            }
        }
        let start = self.syms.len() as u32;
        self.syms.extend(seq);
        Range { start, end: self.syms.len() as u32, binds }
    }

    fn group(&mut self, items: &[Item], owner: u32, binds: &mut bool) -> u32 {
        let id = self.groups.len() as u32;
        // Reserve the id first so nested groups number after their parent.
        self.groups.push(Range { start: 0, end: 0, binds: false });
        self.group_owner.push(owner);
        let r = self.flatten(items, owner);
        *binds |= r.binds;
        self.groups[id as usize] = r;
        id
    }
}
