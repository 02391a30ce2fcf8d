//! The genotype → phenotype mapper.
//!
//! Standard GE exactly as the golden traces define it (leftmost expansion,
//! one codon per non-terminal, `codon mod count`, wrapping, depth limit),
//! plus Genr8's extensions when [`MapOptions::genr8`] is set. After the
//! first few genomes the hot loop allocates nothing: the stack, the
//! phenotype buffer and the bookkeeping vectors are reused.

use crate::bnf::Bnf;
use crate::options::{CodonLayout, MapError, MapOptions};
use crate::outcome::{Failure, Mapping, Outcome, Step, StepKind};
use crate::program::{Program, Sym, TermKind};
use std::fmt::Write as _;

const NONE: u32 = u32::MAX;

/// Settings resolved to plain numbers for the hot loop.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Cfg {
    max_wraps: u32,
    /// `u32::MAX` when unlimited.
    pub(crate) max_tree_depth: u32,
    spaced: bool,
    repeat_constant: u32,
    /// `u32::MAX` when off.
    pub(crate) limit_depth: u32,
    initial_max_id: u32,
    repair: Option<RepairCfg>,
}

#[derive(Clone, Copy, Debug)]
struct RepairCfg {
    rule: u32,
    predecessor: u32,
    /// The `<` terminal, if the grammar has one.
    lt: u32,
    max_rules: u32,
}

#[derive(Clone, Copy, Debug)]
struct Frame {
    sym: Sym,
    /// Depth of the symbol (for groups: of their items).
    depth: u32,
    /// Repetition counter of a `{ }` frame.
    count: u32,
    /// Binding slot of the production instance, or `NONE`.
    inst: u32,
}

/// Repair bookkeeping of one genome.
#[derive(Debug, Default)]
struct RepairState {
    /// Edge types that occur.
    seen: Vec<bool>,
    /// Edge types that are the strict edge of some predecessor.
    has_rule: Vec<bool>,
    /// Inside a predecessor expansion.
    in_pred: bool,
    pred_first: u32,
    pred_strict: u32,
    pred_after_lt: bool,
    /// A rule expansion just ended; the next terminal is its line end.
    await_end: bool,
    /// Byte offset after that line end, and the terminal.
    insert_at: Option<(usize, u32)>,
    /// Depth of the first rule expansion.
    rule_depth: u32,
    /// Replace the next predecessor expansion by this edge type.
    fixed: u32,
}

fn mark(v: &mut Vec<bool>, id: u32) {
    let i = id as usize;
    if v.len() <= i {
        v.resize(i + 1, false);
    }
    v[i] = true;
}

/// Mapping state reused across genomes.
#[derive(Debug, Default)]
pub(crate) struct State {
    stack: Vec<Frame>,
    out: String,
    /// Line end already written (no space before the next terminal).
    line_start: bool,
    bindings: Vec<[u32; 3]>,
    pub(crate) pos: usize,
    wraps: u32,
    used: usize,
    max_id: u32,
    steps: Vec<Step>,
    repair: RepairState,
    /// Repaired rules, written here and then spliced into `out`.
    extra: String,
    /// Per kind of decision, the reads so far ([`CodonLayout::PerChoice`]).
    stream_reads: Vec<u32>,
}

/// Maps genomes over one grammar with fixed options.
///
/// ```
/// use genform_ge::{MapOptions, Mapper};
/// let bnf = genform_ge::parse_str("doc.bnf", "<e> ::= <e> \"+\" <e> | \"x\" | \"y\"").unwrap();
/// let mut m = Mapper::new(&bnf, MapOptions::default()).unwrap();
/// let out = m.map(&[0, 1, 2]);
/// assert!(out.valid());
/// assert_eq!(m.phenotype(), Some("x+y"));
/// ```
#[derive(Debug)]
pub struct Mapper {
    pub(crate) prog: Program,
    pub(crate) cfg: Cfg,
    options: MapOptions,
    s: State,
    valid: bool,
}

impl Mapper {
    /// A mapper for `bnf` with `options`; fails when the options name
    /// rules the grammar lacks or are inconsistent.
    pub fn new(bnf: &Bnf, options: MapOptions) -> Result<Mapper, MapError> {
        let g = options.genr8.clone().unwrap_or_default();
        if g.repeat_constant == 0 {
            return Err(MapError::ZeroRepeatConstant);
        }
        let genr8 = options.genr8.is_some();
        let edge_ids = genr8 && g.edge_ids;
        let prog = Program::new(bnf, edge_ids);
        let repair = match options.genr8.as_ref().and_then(|g| g.repair.as_ref()) {
            Some(r) => {
                if !edge_ids {
                    return Err(MapError::RepairNeedsEdgeIds);
                }
                let find =
                    |name: &str| bnf.rule_id(name).map(|r| r.0).ok_or_else(|| MapError::UnknownRule(name.into()));
                let lt = prog.terms.iter().position(|t| t == "<").map_or(NONE, |i| i as u32);
                Some(RepairCfg { rule: find(&r.rule)?, predecessor: find(&r.predecessor)?, lt, max_rules: r.max_rules })
            }
            _ => None,
        };
        let cfg = Cfg {
            max_wraps: options.max_wraps,
            max_tree_depth: options.max_tree_depth.unwrap_or(u32::MAX),
            spaced: options.spaced,
            repeat_constant: g.repeat_constant,
            limit_depth: if genr8 { g.max_depth.unwrap_or(u32::MAX) } else { u32::MAX },
            initial_max_id: g.initial_max_id,
            repair,
        };
        Ok(Mapper { prog, cfg, options, s: State::default(), valid: false })
    }

    /// The options it was made with.
    pub fn options(&self) -> &MapOptions {
        &self.options
    }

    /// Maps `genome`; the phenotype is then [`Mapper::phenotype`]. Records
    /// no steps (the fast path).
    pub fn map(&mut self, genome: &[u32]) -> Outcome {
        self.run::<false>(genome)
    }

    /// The phenotype of the last [`Mapper::map`] or [`Mapper::trace`], or
    /// `None` if that individual was invalid.
    pub fn phenotype(&self) -> Option<&str> {
        self.valid.then_some(self.s.out.as_str())
    }

    /// Maps `genome` and records every codon read.
    pub fn trace(&mut self, genome: &[u32]) -> Mapping {
        let out = self.run::<true>(genome);
        let steps = std::mem::take(&mut self.s.steps);
        Mapping {
            valid: out.valid(),
            fail: out.fail,
            phenotype: self.phenotype().map(str::to_string),
            used_codons: out.used_codons,
            wraps: out.wraps,
            choices: steps.iter().map(|s| s.choice).collect(),
            steps,
        }
    }

    fn run<const TRACE: bool>(&mut self, genome: &[u32]) -> Outcome {
        match self.options.layout {
            CodonLayout::Sequential => self.run_with::<TRACE, _>(&mut Fixed(genome)),
            CodonLayout::PerChoice => {
                let (rules, groups) = (self.prog.rules.len() as u32, self.prog.groups.len() as u32);
                self.s.stream_reads.clear();
                self.s.stream_reads.resize((rules + groups + 1) as usize, 0);
                self.run_with::<TRACE, _>(&mut PerChoice { genome, rules, groups, furthest: 0 })
            }
        }
    }

    /// Maps with codons from `genes` (a genome, or a generator writing one).
    pub(crate) fn run_with<const TRACE: bool, G: Genes>(&mut self, genes: &mut G) -> Outcome {
        let s = &mut self.s;
        s.stack.clear();
        s.out.clear();
        s.line_start = true;
        s.bindings.clear();
        s.pos = 0;
        s.wraps = 0;
        s.used = 0;
        s.max_id = self.cfg.initial_max_id;
        s.steps.clear();
        if self.cfg.repair.is_some() {
            let r = &mut s.repair;
            r.seen.clear();
            r.has_rule.clear();
            r.in_pred = false;
            r.await_end = false;
            r.insert_at = None;
            r.rule_depth = NONE;
            r.fixed = NONE;
        }
        s.stack.push(Frame { sym: Sym::Nt(0), depth: 1, count: 0, inst: NONE });
        let mut result = run::<TRACE, G>(&self.prog, &self.cfg, s, genes);
        if result.is_ok() && self.cfg.repair.is_some() {
            result = repair::<TRACE, G>(&self.prog, &self.cfg, s, genes);
        }
        self.valid = result.is_ok();
        Outcome { fail: result.err(), used_codons: s.used, wraps: s.wraps, extent: genes.extent(s) }
    }
}

/// What the mapper is about to decide with the next codon: the codon is
/// taken modulo `n`, and the [`Genes`] source may use the rest (a
/// generator picks the choice it wants and writes a codon that gives it).
#[derive(Clone, Copy, Debug)]
pub(crate) enum Ask {
    /// A non-terminal at `depth`; `limited`: only its terminal-only
    /// productions are open (Genr8's depth rule).
    Rule { rule: u32, depth: u32, limited: bool },
    /// A `{ }` group whose items lie at `depth`, `count` times emitted so
    /// far: a choice above `count` emits it once more.
    Repeat { group: u32, depth: u32, count: u32 },
    /// A `[ ]` group whose items lie at `depth`: choice 1 emits it.
    Option { group: u32, depth: u32 },
    /// An edge ID.
    Edge,
}

/// Where the mapper's codons come from: a fixed genome (mapping) or a
/// generator that writes the codons as they are asked for.
pub(crate) trait Genes {
    /// The next codon and its genome position, for a choice among `n`.
    fn next(&mut self, s: &mut State, max_wraps: u32, n: u32, ask: Ask) -> Result<(usize, u32), Failure>;

    /// One past the furthest codon position read so far (the whole genome
    /// once reading wrapped): [`Outcome::extent`].
    fn extent(&self, s: &State) -> usize;
}

/// A genome read left to right, with wrapping.
struct Fixed<'a>(&'a [u32]);

impl Genes for Fixed<'_> {
    #[inline(always)]
    fn next(&mut self, s: &mut State, max_wraps: u32, _: u32, _: Ask) -> Result<(usize, u32), Failure> {
        s.read(self.0, max_wraps)
    }

    fn extent(&self, s: &State) -> usize {
        if s.wraps > 0 { self.0.len() } else { s.pos }
    }
}

/// A genome read as one interleaved stream per kind of decision
/// ([`CodonLayout::PerChoice`]): kinds are the rules, then the groups, then
/// edge IDs.
struct PerChoice<'a> {
    genome: &'a [u32],
    rules: u32,
    groups: u32,
    /// One past the furthest position read without wrapping.
    furthest: usize,
}

impl Genes for PerChoice<'_> {
    fn next(&mut self, s: &mut State, max_wraps: u32, _: u32, ask: Ask) -> Result<(usize, u32), Failure> {
        let len = self.genome.len() as u64;
        if len == 0 {
            return Err(Failure::EmptyGenome);
        }
        let kind = match ask {
            Ask::Rule { rule, .. } => rule,
            Ask::Repeat { group, .. } | Ask::Option { group, .. } => self.rules + group,
            Ask::Edge => self.rules + self.groups,
        };
        let kinds = u64::from(self.rules + self.groups + 1);
        let reads = &mut s.stream_reads[kind as usize];
        let p = u64::from(*reads) * kinds + u64::from(kind);
        let wraps = p / len;
        if wraps > u64::from(max_wraps) {
            return Err(Failure::WrapLimit);
        }
        *reads = reads.saturating_add(1);
        let pos = (p % len) as usize;
        s.wraps = s.wraps.max(wraps as u32);
        s.used += 1;
        self.furthest = self.furthest.max(pos + 1);
        Ok((pos, self.genome[pos]))
    }

    fn extent(&self, s: &State) -> usize {
        if s.wraps > 0 { self.genome.len() } else { self.furthest }
    }
}

impl State {
    /// Counts a codon that a generator writes at the end of its genome
    /// (never wrapping); returns its position.
    pub(crate) fn append(&mut self) -> usize {
        let pos = self.pos;
        self.pos += 1;
        self.used += 1;
        pos
    }

    /// Reads the next codon, wrapping as allowed; returns its position too.
    #[inline(always)]
    pub(crate) fn read(&mut self, genome: &[u32], max_wraps: u32) -> Result<(usize, u32), Failure> {
        if self.pos >= genome.len() {
            if genome.is_empty() {
                return Err(Failure::EmptyGenome);
            }
            if self.wraps >= max_wraps {
                return Err(Failure::WrapLimit);
            }
            self.wraps += 1;
            self.pos = 0;
        }
        let pos = self.pos;
        self.pos += 1;
        self.used += 1;
        Ok((pos, genome[pos]))
    }

    #[inline(always)]
    fn emit(&mut self, spaced: bool, text: &str) {
        if !spaced {
            self.out.push_str(text);
            return;
        }
        if text.is_empty() {
            return;
        }
        if !self.line_start && !text.starts_with('\n') {
            self.out.push(' ');
        }
        self.out.push_str(text);
        self.line_start = text.ends_with('\n');
    }

    fn emit_edge(&mut self, cfg: &Cfg, id: u32) {
        if cfg.spaced && !self.line_start {
            self.out.push(' ');
        }
        self.line_start = false;
        let _ = write!(self.out, "Edge{id}");
        if cfg.repair.is_some() {
            let r = &mut self.repair;
            mark(&mut r.seen, id);
            if r.in_pred {
                if r.pred_first == NONE {
                    r.pred_first = id;
                }
                if r.pred_after_lt && r.pred_strict == NONE {
                    r.pred_strict = id;
                }
            }
        }
    }

    /// Reads an edge ID under Genr8's rule.
    fn fresh_id<const TRACE: bool, G: Genes>(
        &mut self,
        genes: &mut G,
        cfg: &Cfg,
        name: &str,
        depth: u32,
    ) -> Result<u32, Failure> {
        let n = self.max_id.saturating_add(1);
        let (pos, codon) = genes.next(self, cfg.max_wraps, n, Ask::Edge)?;
        let id = codon % n;
        if id == self.max_id {
            self.max_id = self.max_id.saturating_add(1);
        }
        if TRACE {
            self.steps.push(Step { nt: name.to_string(), pos, codon, n, choice: id, depth, kind: StepKind::Edge });
        }
        Ok(id)
    }

    #[inline(always)]
    fn push_range(&mut self, syms: &[Sym], depth: u32, inst: u32) {
        self.stack.extend(syms.iter().rev().map(|&sym| Frame { sym, depth, count: 0, inst }));
    }
}

/// Expands until the stack is empty.
fn run<const TRACE: bool, G: Genes>(p: &Program, cfg: &Cfg, s: &mut State, genes: &mut G) -> Result<(), Failure> {
    while let Some(f) = s.stack.pop() {
        match f.sym {
            Sym::Term(t) => {
                if f.depth > cfg.max_tree_depth {
                    return Err(Failure::DepthLimit);
                }
                match p.kinds[t as usize] {
                    TermKind::Plain => {
                        let text = &p.terms[t as usize];
                        s.emit(cfg.spaced, text);
                        if let Some(r) = &cfg.repair {
                            let st = &mut s.repair;
                            if st.in_pred && t == r.lt {
                                st.pred_after_lt = true;
                            }
                            if st.await_end {
                                st.await_end = false;
                                st.insert_at = Some((s.out.len(), t));
                            }
                        }
                    }
                    TermKind::Edge => {
                        let id = s.fresh_id::<TRACE, G>(genes, cfg, &p.terms[t as usize], f.depth)?;
                        s.emit_edge(cfg, id);
                    }
                    TermKind::Bound(k) => {
                        let slot = f.inst as usize;
                        let bound = s.bindings.get(slot).map_or(NONE, |b| b[k as usize]);
                        let id = if bound == NONE {
                            let id = s.fresh_id::<TRACE, G>(genes, cfg, &p.terms[t as usize], f.depth)?;
                            if let Some(b) = s.bindings.get_mut(slot) {
                                b[k as usize] = id;
                            }
                            id
                        } else {
                            bound
                        };
                        s.emit_edge(cfg, id);
                    }
                }
            }
            Sym::Nt(r) => {
                if f.depth >= cfg.max_tree_depth {
                    return Err(Failure::DepthLimit);
                }
                let mut end_mark = None;
                if let Some(rc) = &cfg.repair {
                    if r == rc.predecessor {
                        let st = &mut s.repair;
                        if st.fixed != NONE {
                            let id = st.fixed;
                            st.fixed = NONE;
                            mark(&mut st.has_rule, id);
                            s.emit_edge(cfg, id);
                            continue;
                        }
                        st.in_pred = true;
                        st.pred_first = NONE;
                        st.pred_strict = NONE;
                        st.pred_after_lt = false;
                        end_mark = Some(Sym::PredEnd);
                    } else if r == rc.rule {
                        if s.repair.rule_depth == NONE {
                            s.repair.rule_depth = f.depth;
                        }
                        end_mark = Some(Sym::RuleEnd);
                    }
                }
                let rule = &p.rules[r as usize];
                let limited = f.depth >= cfg.limit_depth && rule.limited_n > 0;
                let n = if limited { rule.limited_n } else { rule.n };
                let (pos, codon) = genes.next(s, cfg.max_wraps, n, Ask::Rule { rule: r, depth: f.depth, limited })?;
                let (local, n, kind) = if limited {
                    let k = codon % rule.limited_n;
                    (p.limited[(rule.limited_first + k) as usize], rule.limited_n, StepKind::Limited)
                } else {
                    (codon % rule.n, rule.n, StepKind::Expand)
                };
                if TRACE {
                    s.steps.push(Step {
                        nt: p.names[r as usize].clone(),
                        pos,
                        codon,
                        n,
                        choice: local,
                        depth: f.depth,
                        kind,
                    });
                }
                let prod = p.prods[(rule.first + local) as usize];
                let inst = if prod.binds {
                    s.bindings.push([NONE; 3]);
                    s.bindings.len() as u32 - 1
                } else {
                    NONE
                };
                if let Some(m) = end_mark {
                    s.stack.push(Frame { sym: m, depth: f.depth, count: 0, inst: NONE });
                }
                s.push_range(&p.syms[prod.start as usize..prod.end as usize], f.depth + 1, inst);
            }
            Sym::Repeat(g) => {
                let n = f.count.saturating_add(cfg.repeat_constant);
                let ask = Ask::Repeat { group: g, depth: f.depth, count: f.count };
                let (pos, codon) = genes.next(s, cfg.max_wraps, n, ask)?;
                let choice = codon % n;
                if TRACE {
                    let nt = p.names[p.group_owner[g as usize] as usize].clone();
                    s.steps.push(Step { nt, pos, codon, n, choice, depth: f.depth, kind: StepKind::Repeat });
                }
                if choice > f.count {
                    s.stack.push(Frame { count: f.count + 1, ..f });
                    let range = p.groups[g as usize];
                    s.push_range(&p.syms[range.start as usize..range.end as usize], f.depth, f.inst);
                }
            }
            Sym::Option(g) => {
                let (pos, codon) = genes.next(s, cfg.max_wraps, 2, Ask::Option { group: g, depth: f.depth })?;
                let choice = codon % 2;
                if TRACE {
                    let nt = p.names[p.group_owner[g as usize] as usize].clone();
                    s.steps.push(Step { nt, pos, codon, n: 2, choice, depth: f.depth, kind: StepKind::Option });
                }
                if choice == 1 {
                    let range = p.groups[g as usize];
                    s.push_range(&p.syms[range.start as usize..range.end as usize], f.depth, f.inst);
                }
            }
            Sym::PredEnd => {
                let st = &mut s.repair;
                st.in_pred = false;
                let strict = if st.pred_strict != NONE { st.pred_strict } else { st.pred_first };
                if strict != NONE {
                    mark(&mut st.has_rule, strict);
                }
            }
            Sym::RuleEnd => s.repair.await_end = true,
        }
    }
    Ok(())
}

/// Genr8's repair post-pass (see [`crate::RepairOptions`]).
fn repair<const TRACE: bool, G: Genes>(p: &Program, cfg: &Cfg, s: &mut State, genes: &mut G) -> Result<(), Failure> {
    let Some(rc) = cfg.repair else { return Ok(()) };
    // Write the added rules into `extra`, then splice them in.
    std::mem::swap(&mut s.out, &mut s.extra);
    s.out.clear();
    // Rule ends inside `extra` must not move the insertion point.
    let insert_at = s.repair.insert_at;
    let result = (|| {
        let mut added = 0;
        let (_, end) = insert_at.unwrap_or((0, NONE));
        let depth = if s.repair.rule_depth == NONE { 2 } else { s.repair.rule_depth };
        loop {
            let st = &s.repair;
            let missing = (0..st.seen.len()).find(|&i| st.seen[i] && !st.has_rule.get(i).copied().unwrap_or(false));
            let Some(id) = missing else { return Ok(()) };
            if added >= rc.max_rules {
                return Err(Failure::RepairLimit);
            }
            added += 1;
            s.line_start = true;
            s.repair.fixed = id as u32;
            s.repair.await_end = false;
            if end != NONE {
                s.stack.push(Frame { sym: Sym::Term(end), depth, count: 0, inst: NONE });
            }
            s.stack.push(Frame { sym: Sym::Nt(rc.rule), depth, count: 0, inst: NONE });
            run::<TRACE, G>(p, cfg, s, genes)?;
            // A rule whose expansion never reached the predecessor still
            // counts as repaired, so the loop always advances.
            mark(&mut s.repair.has_rule, id as u32);
        }
    })();
    std::mem::swap(&mut s.out, &mut s.extra);
    s.repair.insert_at = insert_at;
    if result.is_ok() && !s.extra.is_empty() {
        let at = match s.repair.insert_at {
            Some((at, _)) => at,
            None => {
                if !s.out.is_empty() && !s.out.ends_with('\n') && cfg.spaced {
                    s.out.push('\n');
                }
                s.out.len()
            }
        };
        s.out.insert_str(at, &s.extra);
    }
    result
}
