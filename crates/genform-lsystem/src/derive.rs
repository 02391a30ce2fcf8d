//! Parallel rewriting: each step replaces every module by the successor of
//! the first rule that matches it (identity when none does) — a rule whose
//! predecessor has several modules replaces them all, matches taken left to
//! right without overlap — then applies decomposition rules and cuts.

use crate::alphabet::{Command, Sym};
use crate::arg::is_true;
use crate::body::Faults;
use crate::compile::LSystem;
use crate::context::{Context, bracket_partners};
use crate::rules::{Entry, Rule, Table};
use crate::string::ModuleString;
use genform_core::{Draws, Rng};

/// Why a derivation stopped.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum DeriveError {
    /// The string outgrew the module limit.
    #[error(
        "step {step} of {steps}: the string grew past {limit} modules (it had {previous} after step {prev_step}); \
         raise the limit with --max-modules (or `max_modules:`) or derive fewer steps",
        prev_step = step - 1
    )]
    TooLong {
        /// The step that overflowed (1-based).
        step: u32,
        /// Steps asked for.
        steps: u32,
        /// The limit.
        limit: usize,
        /// Length after the previous step.
        previous: usize,
    },
    /// The derivation as a whole wrote too many modules (long strings over
    /// many steps), which would take minutes.
    #[error(
        "step {step} of {steps}: the derivation has written more than {limit} modules in all ({WORK_FACTOR} × the module limit); \
         derive fewer steps or raise --max-modules"
    )]
    TooMuchWork {
        /// The step that passed the budget.
        step: u32,
        /// Steps asked for.
        steps: u32,
        /// Modules the whole derivation may write.
        limit: u64,
    },
    /// A production computed a parameter that is not a finite number
    /// (a division by zero, an overflow): drawing it would silently drop
    /// or misplace geometry.
    #[error(
        "step {step} of {steps}: the production at {at} (`{rule}`) gave a module parameter that is {value}; \
         guard the formula with a condition (e.g. `A(x) : x != 0 -> …`) or change it"
    )]
    NonFinite {
        /// The step where it happened (1-based).
        step: u32,
        /// Steps asked for.
        steps: u32,
        /// `file:line:col` of the production.
        at: String,
        /// The production's text.
        rule: String,
        /// The value, as text (`inf`, `-inf`, `NaN`).
        value: String,
    },
    /// A hook assigned a global a value that is not a finite number.
    #[error(
        "step {step} of {steps}: the {hook} hook set global `{name}` to {value} at {at}; \
         guard the formula (e.g. with `if`) or change it"
    )]
    NonFiniteGlobal {
        /// The step (0 for Start, the number of steps for End).
        step: u32,
        /// Steps asked for.
        steps: u32,
        /// `Start`, `StartEach`, `EndEach` or `End`.
        hook: &'static str,
        /// `file:line:col` of the assignment.
        at: String,
        /// The global's name.
        name: String,
        /// The value, as text.
        value: String,
    },
}

/// Why one rewriting pass stopped early.
pub(crate) enum Stop {
    /// The string outgrew the module limit.
    Full,
    /// Rule `.0` of the table gave the non-finite parameter `.1`.
    NonFinite(u32, f64),
}

/// Modules a derivation may write over all its steps, per module of the
/// limit on one string: bounds the time of many steps over a long string
/// (about 20 s at the default limit on the slowest path).
pub const WORK_FACTOR: u64 = 200;

/// Reusable buffers of one derivation.
#[derive(Default)]
pub(crate) struct Scratch {
    partners: Vec<u32>,
    offsets: Vec<u32>,
    /// The bound parameters of the rule last chosen.
    pub(crate) env: Vec<f64>,
    found: Vec<usize>,
    candidates: Vec<(u32, f64)>,
    /// The first rule (and value) that emitted a non-finite parameter
    /// during an [`LSystem::expand`].
    pub(crate) non_finite: Option<(u32, f64)>,
    /// The global state rules read: `iteration`, then the globals.
    pub(crate) state: Vec<f64>,
    /// What the body of the rule last chosen produced, and its first
    /// non-finite parameter.
    body_out: ModuleString,
    body_bad: Option<f64>,
}

impl Scratch {
    /// Buffers for rules that read the global `state`.
    pub(crate) fn with_state(state: &[f64]) -> Scratch {
        Scratch { state: state.to_vec(), ..Scratch::default() }
    }
}

/// The hooks, by index into `LSystem::hooks`.
const HOOK_NAMES: [&str; 4] = ["Start", "StartEach", "EndEach", "End"];

/// A module being rewritten and what its contexts can see.
pub(crate) struct Site<'a> {
    pub sym: Sym,
    pub params: &'a [f64],
    /// Position, the string's context view, parameter offsets and all
    /// parameters (only for tables with contexts).
    pub ctx: Option<(usize, &'a Context<'a>, &'a [u32], &'a [f64])>,
}

impl LSystem {
    /// Derives `steps` steps from the axiom with the file's module limit;
    /// stochastic choices and random formulas draw from `rng`.
    pub fn derive(&self, steps: u32, rng: &mut Rng) -> Result<ModuleString, DeriveError> {
        self.derive_limited(steps, rng, self.settings.max_modules, |_, _| {})
    }

    /// [`LSystem::derive`] with an explicit module limit, calling
    /// `after_step(step, string)` after each step.
    pub fn derive_limited(
        &self,
        steps: u32,
        rng: &mut Rng,
        max_modules: usize,
        mut after_step: impl FnMut(u32, &ModuleString),
    ) -> Result<ModuleString, DeriveError> {
        let mut cur = self.axiom.clone();
        let mut next = ModuleString::default();
        let mut scratch = Scratch::default();
        let mut state = self.initial_state.clone();
        self.hook(0, &mut state, rng, 0, steps)?;
        let queries = self.queries();
        if let Some(kinds) = &queries {
            self.fill_queries(&mut cur, kinds, &state, 0);
        }
        let fast = self.fast_table();
        let has_cut = self.alphabet.symbols.iter().any(|s| s.command == Command::Cut);
        let budget = (max_modules as u64).saturating_mul(WORK_FACTOR);
        let mut written = 0u64;
        for step in 1..=steps {
            if has_cut && self.settings.lpy {
                self.cut(&mut cur);
            }
            // L-Py's getIterationNb(): steps done before this one.
            state[0] = f64::from(step - 1);
            self.hook(1, &mut state, rng, step, steps)?;
            scratch.state.clone_from(&state);
            let rewritten = match &fast {
                Some(table) => {
                    if rewrite_fast(table, &cur.syms, &mut next.syms, max_modules) {
                        Ok(())
                    } else {
                        Err(Stop::Full)
                    }
                }
                None => self.rewrite(&self.productions, &cur, &mut next, rng, max_modules, &mut scratch),
            };
            let done = rewritten.map_err(|stop| (stop, &self.productions)).and_then(|()| {
                if self.decomposition.is_empty() {
                    Ok(())
                } else {
                    self.decompose(&mut next, rng, max_modules, &state).map_err(|stop| (stop, &self.decomposition))
                }
            });
            match done {
                Ok(()) => {}
                Err((Stop::Full, _)) => {
                    return Err(DeriveError::TooLong { step, steps, limit: max_modules, previous: cur.len() });
                }
                Err((Stop::NonFinite(r, v), table)) => {
                    return Err(self.non_finite(&table.rules[r as usize], v, step, steps));
                }
            }
            if has_cut && !self.settings.lpy {
                self.cut(&mut next);
            }
            std::mem::swap(&mut cur, &mut next);
            written += cur.len() as u64;
            if written > budget {
                return Err(DeriveError::TooMuchWork { step, steps, limit: budget });
            }
            if let Some(kinds) = &queries {
                self.fill_queries(&mut cur, kinds, &state, u64::from(step));
            }
            self.hook(2, &mut state, rng, step, steps)?;
            after_step(step, &cur);
        }
        state[0] = f64::from(steps);
        self.hook(3, &mut state, rng, steps, steps)?;
        cur.state = state;
        Ok(cur)
    }

    /// The symbol → successor map when every production is a
    /// parameter-free, unconditional, context-free, deterministic rule and
    /// no module has parameters: rewriting is then a copy per module.
    fn fast_table(&self) -> Option<FastTable> {
        if self.alphabet.symbols.iter().any(|s| s.arity > 0) {
            return None;
        }
        let mut table = FastTable { ranges: Vec::new(), succ: Vec::new(), wide: None };
        for s in 0..self.alphabet.symbols.len() {
            let start = table.succ.len() as u32;
            match self.productions.unconditional(s as Sym)? {
                Some(rule) => table.succ.extend_from_slice(&rule.succ_syms),
                None => table.succ.push(s as Sym),
            }
            table.ranges.push((start, table.succ.len() as u32));
        }
        if table.ranges.iter().all(|&(a, b)| (b - a) as usize <= WIDE) {
            let wide = table.ranges.iter().map(|&(a, b)| {
                let mut w = [0; WIDE];
                w[..(b - a) as usize].copy_from_slice(&table.succ[a as usize..b as usize]);
                w
            });
            table.wide = Some(wide.collect());
        }
        Some(table)
    }

    /// One step of `table` over `cur` into `out`; false when `out` would
    /// exceed `cap` modules.
    pub(crate) fn rewrite(
        &self,
        table: &Table,
        cur: &ModuleString,
        out: &mut ModuleString,
        rng: &mut Rng,
        cap: usize,
        sc: &mut Scratch,
    ) -> Result<(), Stop> {
        // Tables without predecessors of several modules keep a loop with
        // no passing over.
        if table.several {
            self.rewrite_with::<true>(table, cur, out, rng, cap, sc)
        } else {
            self.rewrite_with::<false>(table, cur, out, rng, cap, sc)
        }
    }

    /// [`LSystem::rewrite`]; `SEVERAL`: some rule's predecessor has several
    /// modules.
    fn rewrite_with<const SEVERAL: bool>(
        &self,
        table: &Table,
        cur: &ModuleString,
        out: &mut ModuleString,
        rng: &mut Rng,
        cap: usize,
        sc: &mut Scratch,
    ) -> Result<(), Stop> {
        out.syms.clear();
        out.params.clear();
        let mut partners = std::mem::take(&mut sc.partners);
        let mut offsets = std::mem::take(&mut sc.offsets);
        if table.context {
            self.view_parts(&cur.syms, &mut partners, &mut offsets);
        }
        let view = self.view(&cur.syms, &partners);
        let mut off = 0usize;
        let mut done = Ok(());
        // Modules still to pass over: the rest of a predecessor of several
        // modules that was just replaced (matches do not overlap).
        let mut skip = 0usize;
        for (i, &sym) in cur.syms.iter().enumerate() {
            let n = self.alphabet.arity(sym);
            let params = &cur.params[off..off + n];
            off += n;
            if SEVERAL && skip > 0 {
                skip -= 1;
                continue;
            }
            let site = Site { sym, params, ctx: table.context.then_some((i, &view, &offsets[..], &cur.params[..])) };
            match self.choose(table, &site, rng, sc) {
                Some(r) => {
                    let rule = &table.rules[r as usize];
                    if SEVERAL {
                        skip = rule.rest.len();
                    }
                    if let Err(v) = emit(rule, &self.alphabet, sc, out, rng) {
                        done = Err(Stop::NonFinite(r, v));
                        break;
                    }
                }
                None => {
                    out.syms.push(sym);
                    out.params.extend_from_slice(params);
                }
            }
            if !within(out, cap) {
                done = Err(Stop::Full);
                break;
            }
        }
        sc.partners = partners;
        sc.offsets = offsets;
        done
    }

    /// Fills the bracket partners and parameter offsets of `syms`, which
    /// rules with a context or several predecessor modules read.
    pub(crate) fn view_parts(&self, syms: &[Sym], partners: &mut Vec<u32>, offsets: &mut Vec<u32>) {
        bracket_partners(syms, &self.alphabet, partners);
        offsets.clear();
        let mut off = 0u32;
        for &s in syms {
            offsets.push(off);
            off += self.alphabet.arity(s) as u32;
        }
    }

    /// The context view of `syms` with its bracket `partners`.
    pub(crate) fn view<'a>(&'a self, syms: &'a [Sym], partners: &'a [u32]) -> Context<'a> {
        Context { syms, partners, ignored: &self.ignored, push: &self.brackets[0], pop: &self.brackets[1] }
    }

    /// The error for rule `rule` having emitted the non-finite `value` at
    /// `step`, located in the source file when the system has one.
    pub(crate) fn non_finite(&self, rule: &Rule, value: f64, step: u32, steps: u32) -> DeriveError {
        let (at, text) = match &self.source {
            Some(f) => {
                let text = f.text.get(rule.span.start as usize..rule.span.end as usize).unwrap_or("");
                (f.location(rule.span.start), text.lines().next().unwrap_or("").trim().to_string())
            }
            None => (format!("byte {}", rule.span.start), String::new()),
        };
        DeriveError::NonFinite { step, steps, at, rule: text, value: value.to_string() }
    }

    /// The rule applied at `site`, its parameters bound in `sc.env`: the
    /// first entry that matches; a stochastic group draws among its
    /// matching members by weight.
    pub(crate) fn choose(&self, table: &Table, site: &Site, draws: &mut impl Draws, sc: &mut Scratch) -> Option<u32> {
        self.choose_with(table, site, draws, None, sc)
    }

    /// [`LSystem::choose`] where a stochastic group's roulette position is
    /// `roulette` (in `[0, 1)`) when given, else a draw.
    pub(crate) fn choose_with(
        &self,
        table: &Table,
        site: &Site,
        draws: &mut impl Draws,
        roulette: Option<f64>,
        sc: &mut Scratch,
    ) -> Option<u32> {
        let entries = table.by_sym.get(site.sym as usize)?;
        for entry in entries {
            match entry {
                Entry::One(r) => {
                    if self.applies(&table.rules[*r as usize], site, draws, sc) {
                        return Some(*r);
                    }
                }
                Entry::Group(members) => {
                    let mut cands = std::mem::take(&mut sc.candidates);
                    cands.clear();
                    let mut total = 0.0;
                    for &r in members {
                        let rule = &table.rules[r as usize];
                        if self.applies(rule, site, draws, sc) {
                            let w = rule.weight.as_ref().map_or(1.0, |p| p.eval_draws(&sc.env, draws));
                            let w = if w > 0.0 && w.is_finite() { w } else { 0.0 };
                            total += w;
                            cands.push((r, w));
                        }
                    }
                    let picked = pick(&cands, total, roulette, draws);
                    sc.candidates = cands;
                    if let Some(r) = picked {
                        // Re-bind the chosen rule's parameters.
                        let bound = self.bind(&table.rules[r as usize], site, sc);
                        debug_assert!(bound);
                        return Some(r);
                    }
                }
            }
        }
        None
    }

    /// Contexts match, the condition holds and a body (if any) produces;
    /// binds the parameters.
    fn applies(&self, rule: &Rule, site: &Site, draws: &mut impl Draws, sc: &mut Scratch) -> bool {
        if !(self.bind(rule, site, sc) && rule.cond.as_ref().is_none_or(|c| is_true(c.eval_draws(&sc.env, draws)))) {
            return false;
        }
        let Some(body) = &rule.body else { return true };
        // Local variables start undefined (NaN) after the formals and state.
        sc.env.resize(sc.env.len() + body.locals, f64::NAN);
        sc.body_out.syms.clear();
        sc.body_out.params.clear();
        let mut faults = Faults::default();
        let out = crate::body::run(&body.ops, &mut sc.env, &self.alphabet, &mut sc.body_out, draws, &mut faults);
        // A local that is not finite is harmless until a module carries it.
        sc.body_bad = faults.param;
        out.produced
    }

    /// Runs hook `k` over the global `state`; a global set to a value that
    /// is not finite is an error.
    fn hook(&self, k: usize, state: &mut [f64], rng: &mut Rng, step: u32, steps: u32) -> Result<(), DeriveError> {
        let ops = &self.hooks[k];
        if ops.is_empty() {
            return Ok(());
        }
        let mut faults = Faults::default();
        crate::body::run(ops, state, &self.alphabet, &mut ModuleString::default(), rng, &mut faults);
        match faults.assign {
            None => Ok(()),
            Some((slot, span, v)) => {
                let at = match &self.source {
                    Some(f) => f.location(span.start),
                    None => format!("byte {}", span.start),
                };
                let name = self.state_names.get(slot as usize).cloned().unwrap_or_default();
                Err(DeriveError::NonFiniteGlobal { step, steps, hook: HOOK_NAMES[k], at, name, value: v.to_string() })
            }
        }
    }

    /// Matches the rest of the predecessor and the contexts, and fills
    /// `sc.env` with the formal parameters.
    fn bind(&self, rule: &Rule, site: &Site, sc: &mut Scratch) -> bool {
        sc.env.clear();
        if rule.view {
            let Some((i, view, offsets, all)) = site.ctx else { return false };
            // L-Py matches the strict predecessor module after module, with
            // no module (ignored or bracket) in between.
            let mut last = i;
            if !rule.rest.is_empty() {
                last += rule.rest.len();
                if view.syms.get(i + 1..=last) != Some(&rule.rest[..]) {
                    return false;
                }
            }
            let ctx_params = |pos: usize, env: &mut Vec<f64>| {
                let o = offsets[pos] as usize;
                env.extend_from_slice(&all[o..o + self.alphabet.arity(view.syms[pos])]);
            };
            sc.found.clear();
            if !view.left(i, &rule.left, &mut sc.found) {
                return false;
            }
            for &pos in &sc.found {
                ctx_params(pos, &mut sc.env);
            }
            sc.env.extend_from_slice(site.params);
            for pos in i + 1..=last {
                ctx_params(pos, &mut sc.env);
            }
            sc.found.clear();
            if !view.right(last, &rule.right, &mut sc.found) {
                return false;
            }
            for &pos in &sc.found {
                ctx_params(pos, &mut sc.env);
            }
        } else {
            sc.env.extend_from_slice(site.params);
        }
        if rule.tail {
            sc.env.resize(sc.env.len() + rule.pad as usize, f64::NAN);
            if rule.state {
                sc.env.extend_from_slice(&sc.state);
            }
        }
        true
    }

    /// Applies the decomposition rules to every module of `s`, recursively
    /// up to their depth; stops when the result exceeds `cap` or a rule
    /// computes a non-finite parameter.
    fn decompose(&self, s: &mut ModuleString, rng: &mut Rng, cap: usize, state: &[f64]) -> Result<(), Stop> {
        let mut out = ModuleString::default();
        let mut sc = Scratch::with_state(state);
        let ok = s.modules(&self.alphabet).all(|(sym, params)| {
            self.expand(&self.decomposition, (sym, params), 0, rng, &mut sc, &mut |sym, p| {
                out.syms.push(sym);
                out.params.extend_from_slice(p);
                within(&out, cap)
            }) && sc.non_finite.is_none()
        });
        *s = out;
        match sc.non_finite {
            Some((r, v)) => Err(Stop::NonFinite(r, v)),
            None if !ok => Err(Stop::Full),
            None => Ok(()),
        }
    }

    /// Rewrites one module with a context-free `table` again and again (up
    /// to the table's depth), passing the final modules to `sink`; stops
    /// (returning false) as soon as `sink` returns false.
    pub(crate) fn expand(
        &self,
        table: &Table,
        (sym, params): (Sym, &[f64]),
        depth: u32,
        draws: &mut impl Draws,
        sc: &mut Scratch,
        sink: &mut impl FnMut(Sym, &[f64]) -> bool,
    ) -> bool {
        self.expand_at(table, &Site { sym, params, ctx: None }, depth, draws, sc, sink).1
    }

    /// [`LSystem::expand`] for a module of a string seen through `site`
    /// (its context view), so that rules with a context or a predecessor of
    /// several modules apply; they match only the string itself, not what
    /// the rules produce from it. Returns how many modules after the site
    /// the chosen rule's predecessor took as well (to pass over), and
    /// whether `sink` asked to go on.
    pub(crate) fn expand_site(
        &self,
        table: &Table,
        site: &Site,
        draws: &mut impl Draws,
        sc: &mut Scratch,
        sink: &mut impl FnMut(Sym, &[f64]) -> bool,
    ) -> (usize, bool) {
        self.expand_at(table, site, 0, draws, sc, sink)
    }

    /// [`LSystem::expand_site`] at `depth` rewritings deep.
    fn expand_at(
        &self,
        table: &Table,
        site: &Site,
        depth: u32,
        draws: &mut impl Draws,
        sc: &mut Scratch,
        sink: &mut impl FnMut(Sym, &[f64]) -> bool,
    ) -> (usize, bool) {
        let rule = if depth < table.max_depth { self.choose(table, site, draws, sc) } else { None };
        match rule {
            None => (0, sink(site.sym, site.params)),
            Some(r) => (table.rules[r as usize].rest.len(), self.expand_rule(table, r, depth, draws, sc, sink)),
        }
    }

    /// Emits rule `r` (just chosen at `depth`) and expands what it produced
    /// one level deeper.
    fn expand_rule(
        &self,
        table: &Table,
        r: u32,
        depth: u32,
        draws: &mut impl Draws,
        sc: &mut Scratch,
        sink: &mut impl FnMut(Sym, &[f64]) -> bool,
    ) -> bool {
        let mut produced = ModuleString::default();
        if let Err(v) = emit(&table.rules[r as usize], &self.alphabet, sc, &mut produced, draws) {
            sc.non_finite.get_or_insert((r, v));
        }
        produced.modules(&self.alphabet).all(|(s, p)| self.expand(table, (s, p), depth + 1, draws, sc, sink))
    }

    /// Removes every `%` with the rest of its branch (up to, not including,
    /// the `]` that closes it).
    pub(crate) fn cut(&self, s: &mut ModuleString) {
        let mut out = ModuleString {
            syms: Vec::with_capacity(s.len()),
            params: Vec::with_capacity(s.params.len()),
            state: Vec::new(),
        };
        let mut skip_depth: Option<usize> = None;
        let mut depth = 0usize;
        for (sym, params) in s.modules(&self.alphabet) {
            let cmd = self.alphabet.command(sym);
            match cmd {
                Command::Push => depth += 1,
                Command::Pop => {
                    if skip_depth == Some(depth) {
                        skip_depth = None;
                    }
                    depth = depth.saturating_sub(1);
                }
                _ => {}
            }
            if skip_depth.is_none() && cmd == Command::Cut {
                skip_depth = Some(depth);
            }
            if skip_depth.is_none() {
                out.syms.push(sym);
                out.params.extend_from_slice(params);
            }
        }
        *s = out;
    }
}

/// Whether `s` keeps within the module limit `cap` (and, so that
/// parameters cannot exhaust memory either, at most four parameters per
/// module of the limit).
#[inline]
pub(crate) fn within(s: &ModuleString, cap: usize) -> bool {
    s.syms.len() <= cap && s.params.len() <= cap.saturating_mul(4)
}

/// Appends the successor of `rule` (just chosen with `sc`): its
/// parameters evaluated on the bound environment, or what its body
/// produced; the first non-finite parameter as the error (the successor is
/// still appended whole).
pub(crate) fn emit(
    rule: &Rule,
    alphabet: &crate::alphabet::Alphabet,
    sc: &Scratch,
    out: &mut ModuleString,
    draws: &mut impl Draws,
) -> Result<(), f64> {
    if rule.body.is_some() {
        out.syms.extend_from_slice(&sc.body_out.syms);
        out.params.extend_from_slice(&sc.body_out.params);
        return sc.body_bad.map_or(Ok(()), Err);
    }
    let env = &sc.env[..];
    if rule.succ_args.is_empty() {
        out.syms.extend_from_slice(&rule.succ_syms);
        return Ok(());
    }
    let mut a = 0;
    let mut bad = None;
    for &s in &rule.succ_syms {
        out.syms.push(s);
        for _ in 0..alphabet.arity(s) {
            let v = rule.succ_args[a].eval(env, draws);
            if !v.is_finite() {
                bad.get_or_insert(v);
            }
            out.params.push(v);
            a += 1;
        }
    }
    bad.map_or(Ok(()), Err)
}

/// Roulette choice among weighted candidates; the first candidate when
/// every weight is zero.
fn pick(cands: &[(u32, f64)], total: f64, roulette: Option<f64>, draws: &mut impl Draws) -> Option<u32> {
    let first = cands.first()?.0;
    if total <= 0.0 {
        return Some(first);
    }
    let mut u = roulette.unwrap_or_else(|| draws.next_f64()) * total;
    for &(r, w) in cands {
        if u < w {
            return Some(r);
        }
        u -= w;
    }
    Some(cands.iter().rev().find(|c| c.1 > 0.0).map_or(first, |c| c.0))
}

/// Successor of each symbol as a range of `succ` (identity included).
struct FastTable {
    ranges: Vec<(u32, u32)>,
    succ: Vec<Sym>,
    /// Each successor padded to [`WIDE`] symbols, when none is longer:
    /// copying a fixed-size block and advancing by the true length beats a
    /// variable-length copy per module (most successors are a few symbols).
    wide: Option<Vec<[Sym; WIDE]>>,
}

/// Successors up to this many symbols are copied as fixed-size blocks.
const WIDE: usize = 16;

/// One deterministic, parameter-free step: a copy per module.
fn rewrite_fast(table: &FastTable, cur: &[Sym], out: &mut Vec<Sym>, cap: usize) -> bool {
    out.clear();
    // The exact length first, so the output is allocated once and the
    // limit is checked before any work.
    let len: usize = cur
        .iter()
        .map(|&s| {
            let (a, b) = table.ranges[s as usize];
            (b - a) as usize
        })
        .sum();
    if len > cap {
        return false;
    }
    if let Some(wide) = &table.wide {
        // Room for the last block's padding; cut off after.
        out.resize(len + WIDE, 0);
        let mut at = 0;
        for &s in cur {
            out[at..at + WIDE].copy_from_slice(&wide[s as usize]);
            let (a, b) = table.ranges[s as usize];
            at += (b - a) as usize;
        }
        out.truncate(len);
        return true;
    }
    out.reserve(len);
    for &s in cur {
        let (a, b) = table.ranges[s as usize];
        out.extend_from_slice(&table.succ[a as usize..b as usize]);
    }
    true
}
