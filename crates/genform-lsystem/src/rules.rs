//! Compiled rules: predecessor with contexts, condition, weight, and a
//! successor whose parameters are compiled formulas.

use crate::alphabet::Sym;
use crate::arg::Arg;
use crate::body::Body;
use genform_core::Draws;
use genform_core::diag::Span;
use genform_core::expr::Program;

/// One production (or decomposition / interpretation rule).
#[derive(Clone, Debug)]
pub(crate) struct Rule {
    /// The (first) module of the strict predecessor: the rule is tried for
    /// it.
    pub strict: Sym,
    /// The predecessor's further modules (L-Py's `A B --> …`): they must
    /// follow `strict` directly in the string, and the whole sequence is
    /// replaced.
    pub rest: Vec<Sym>,
    /// Parameters bound to NaN after the matched ones: those of the other
    /// alternatives of an `or(…)` pattern.
    pub pad: u32,
    /// [`Rule::needs_view`], kept for the rewriting loop.
    pub view: bool,
    /// `pad > 0 || state`: the environment goes on after the matched
    /// parameters.
    pub tail: bool,
    pub left: Vec<Sym>,
    pub right: Vec<Sym>,
    /// Formal parameters: left context's, the predecessor's (module after
    /// module), the right context's, in string order.
    pub env: usize,
    pub cond: Option<Program>,
    pub weight: Option<Program>,
    pub succ_syms: Vec<Sym>,
    /// The successor's parameters, module after module.
    pub succ_args: Vec<Arg>,
    /// The most random draws one application takes (not counting a
    /// body's).
    pub draws: usize,
    pub span: Span,
    /// Statements that compute the successor (`-> { … }`); `succ_syms`
    /// then lists every module they can produce.
    pub body: Option<Body>,
    /// Whether the environment holds the global state after the formal
    /// parameters (the rule reads `iteration` or a global, or has a body).
    pub state: bool,
}

impl Rule {
    /// Whether matching looks at other modules than the rewritten one: a
    /// context, or a predecessor of several modules.
    pub(crate) fn needs_view(&self) -> bool {
        !self.left.is_empty() || !self.right.is_empty() || !self.rest.is_empty()
    }
}

/// What is tried for a module, in order: a single rule, or a stochastic
/// group (every member whose match and condition hold is a candidate; one
/// is drawn by weight).
#[derive(Clone, Debug, PartialEq)]
pub(crate) enum Entry {
    One(u32),
    Group(Vec<u32>),
}

/// The rules of one section, indexed by predecessor symbol.
#[derive(Clone, Debug, Default)]
pub(crate) struct Table {
    pub rules: Vec<Rule>,
    pub by_sym: Vec<Vec<Entry>>,
    /// How often the rules re-apply to their own output (decomposition and
    /// interpretation).
    pub max_depth: u32,
    /// Some rule has a context or a predecessor of several modules: the
    /// rules see the string around the module.
    pub context: bool,
    /// Some rule's predecessor has several modules.
    pub several: bool,
}

impl Table {
    pub(crate) fn from_parts(rules: Vec<Rule>, by_sym: Vec<Vec<Entry>>, max_depth: u32) -> Table {
        let context = rules.iter().any(Rule::needs_view);
        let several = rules.iter().any(|r| !r.rest.is_empty());
        Table { rules, by_sym, max_depth, context, several }
    }

    pub(crate) fn is_empty(&self) -> bool {
        self.rules.is_empty()
    }

    /// The rule of symbol `s`'s first entry when that rule always applies
    /// and produces parameter-free modules with no draws: the whole table is
    /// then a symbol → successor map.
    pub(crate) fn unconditional(&self, s: Sym) -> Option<Option<&Rule>> {
        match self.by_sym.get(s as usize).and_then(|l| l.first()) {
            None => Some(None),
            Some(Entry::One(r)) => {
                let r = &self.rules[*r as usize];
                (r.cond.is_none() && !r.needs_view() && r.succ_args.is_empty() && r.env == 0 && r.body.is_none())
                    .then_some(Some(r))
            }
            Some(Entry::Group(_)) => None,
        }
    }
}

/// Replays stored uniforms as draws (a genome's), then 0.5 if exhausted.
pub(crate) struct Stored<'a> {
    pub values: &'a [f64],
    pub next: usize,
}

impl Draws for Stored<'_> {
    fn next_f64(&mut self) -> f64 {
        let v = self.values.get(self.next).copied().unwrap_or(0.5);
        self.next += 1;
        v
    }
}
