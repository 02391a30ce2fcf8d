//! The derivation loop: priority groups, random production order, one
//! match and one daughter option per step, limits.

use crate::choices::{InOrder, Pick, Random};
use crate::grammar::{GraphGrammar, Production};
use crate::graph::Graph;
use crate::rewrite::{Scratch, apply};
use crate::search::{Exhausted, Search};
use genform_core::rng::Draws;

/// The default most elements (vertices + edges) a derivation may make.
pub const DEFAULT_MAX_ELEMENTS: usize = 1_000_000;

/// Steps a derivation with no step limit (neither `steps:` nor
/// `max_steps`) may take before it is ended as non-terminating.
pub const UNLIMITED_STEPS: usize = 10_000_000;

/// Steps between two readings of the clock by the step loop.
const CLOCK_STEPS: usize = 64;

/// Candidate tests one search may make before it is given up (a mother
/// pattern that is very expensive to match in this host).
pub const SEARCH_LIMIT: u64 = 50_000_000;

/// Wall-clock time one derivation may take unless the grammar sets
/// `time_limit:`: ten seconds, far above what a grammar that terminates
/// needs, short enough that a pattern which never matches cannot stall a
/// command or an evolution step for long.
pub const DEFAULT_TIME_LIMIT: std::time::Duration = std::time::Duration::from_secs(10);

/// The largest `time_limit:` a grammar may set, in seconds (a day).
pub const MAX_TIME_LIMIT_SECS: f64 = 86_400.0;

/// Why a derivation stopped.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Stop {
    /// The step limit was reached.
    StepLimit,
    /// No production matched: the graph is terminal.
    NoMatch,
}

/// Counters of one derivation.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Stats {
    /// Applications per production, in file order.
    pub applications: Vec<usize>,
    /// Candidate tests made by all searches.
    pub search_work: u64,
    /// Why it stopped.
    pub stop: Stop,
}

/// The result of [`GraphGrammar::derive`].
#[derive(Clone, Debug)]
pub struct Derivation {
    /// The final graph.
    pub graph: Graph,
    /// Steps (production applications) made.
    pub steps: usize,
    /// Counters.
    pub stats: Stats,
}

/// A derivation that ran into a limit.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum DeriveError {
    /// The graph would grow past the element limit.
    #[error(
        "the graph would grow past {limit} elements at step {step}; lower the step limit or raise the element limit"
    )]
    TooManyElements {
        /// The limit.
        limit: usize,
        /// The step that would have passed it.
        step: usize,
    },
    /// Matching one production took too many candidate tests.
    #[error(
        "matching production `{production}` took more than {limit} candidate tests at step {step}; \
         give its mother graph labels or conditions that narrow the search"
    )]
    SearchLimit {
        /// The production.
        production: String,
        /// The limit ([`SEARCH_LIMIT`]).
        limit: u64,
        /// The step.
        step: usize,
    },
    /// The derivation ran past the grammar's time limit (wall clock): its
    /// searches were too slow for its step limit.
    #[error(
        "its time limit of {seconds} s passed at step {step}{while_matching}; \
         raise `time_limit:` (seconds) in the grammar, lower the step limit, or give mother graphs \
         labels or conditions that narrow the search"
    )]
    TimeLimit {
        /// The limit, in seconds, as text.
        seconds: String,
        /// The step (0-based).
        step: usize,
        /// " while matching production `name`", or empty between searches.
        while_matching: String,
    },
    /// A daughter vertex position evaluated to NaN or an infinity.
    #[error(
        "production `{production}` placed a vertex at a coordinate that is {value} at step {step} ({at}); \
         check its `pos:` formulas for a division by zero or an overflow"
    )]
    NonFinitePosition {
        /// The production.
        production: String,
        /// `file:line:col` of the position formula that gave it.
        at: String,
        /// The coordinate, as text (`NaN`, `inf`, `-inf`).
        value: String,
        /// The step (0-based, as in the other errors).
        step: usize,
    },
    /// No step limit was set and productions still matched.
    #[error("no step limit is set and the derivation was still going after {steps} steps; add `steps:` to the grammar")]
    NoTermination {
        /// Steps made.
        steps: usize,
    },
}

/// One mother-pattern match: host ids per mother vertex and per mother
/// edge, in the production's order.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Match {
    /// Host vertex ids.
    pub vertices: Vec<u32>,
    /// Host edge ids.
    pub edges: Vec<u32>,
}

fn truthy(v: f64) -> bool {
    v != 0.0 && !v.is_nan()
}

/// Per-production envs with the per-run values in place.
fn run_envs(g: &GraphGrammar, choices: &mut impl Draws) -> Vec<Vec<f64>> {
    let mut globals: Vec<f64> = Vec::with_capacity(g.globals.len());
    for prog in &g.globals {
        let v = prog.eval_draws(&globals, choices);
        globals.push(v);
    }
    g.productions
        .iter()
        .map(|p| {
            let mut env = vec![f64::NAN; p.env_len];
            for &(slot, gi) in &p.global_slots {
                env[slot as usize] = globals[gi];
            }
            for (slot, prog) in &p.run_vars {
                let v = prog.eval_draws(&env, choices);
                env[*slot as usize] = v;
            }
            env
        })
        .collect()
}

/// The mother element with the fewest candidates (on ties: edges, which
/// bind three elements at once, then labelled elements); `None` when a
/// labelled element has none, so nothing can match.
fn anchor(g: &Graph, p: &Production) -> Option<usize> {
    let count = |index: &crate::index::Index, label: Option<u32>| match label {
        None => index.all.len(),
        Some(l) => index.by_label.get(l as usize).map_or(0, Vec::len),
    };
    let vertices = p.mv.iter().map(|v| {
        let label = if v.wildcard { None } else { v.label };
        (count(&g.vindex, label), 1u8, u8::from(label.is_none()))
    });
    let edges = p.me.iter().map(|e| (count(&g.eindex, e.label), 0u8, u8::from(e.label.is_none())));
    let mut best: Option<((usize, u8, u8), usize)> = None;
    for (i, key) in vertices.chain(edges).enumerate() {
        if key.0 == 0 {
            return None;
        }
        if best.is_none_or(|(b, _)| key < b) {
            best = Some((key, i));
        }
    }
    Some(best.map_or(0, |(_, i)| i))
}

/// Searches one match of `p`; on success `mv`/`me` hold it and `env` its
/// values.
#[allow(clippy::too_many_arguments)]
fn find(
    g: &Graph,
    p: &Production,
    env: &mut [f64],
    mv: &mut [u32],
    me: &mut [u32],
    pick: &mut impl Pick,
    work: &mut u64,
    deadline: Option<std::time::Instant>,
    visit: &mut dyn FnMut(&[u32], &[u32]) -> bool,
) -> Result<bool, Exhausted> {
    if !p.pre_checks.iter().all(|c| truthy(c.eval(env))) {
        return Ok(false);
    }
    let Some(a) = anchor(g, p) else { return Ok(false) };
    let plan = &p.plans[a];
    let mut s = Search { g, p, env, mv, me, max_gen: None, work: 0, limit: SEARCH_LIMIT, deadline };
    // An empty pattern has one match, whatever the generations.
    let found = if p.oldest && !(p.mv.is_empty() && p.me.is_empty()) {
        // The oldest match: the lowest generation level at which one
        // exists, a match's level being its newest element's generation.
        let mut found = Ok(false);
        for level in g.live_generations() {
            s.max_gen = Some(level);
            found = s.run(plan, pick, visit);
            if found != Ok(false) {
                break;
            }
        }
        found
    } else {
        s.run(plan, pick, visit)
    };
    *work += s.work;
    found
}

/// A weighted index from one uniform draw.
fn weighted(choices: &mut impl Draws, weights: &[f64]) -> usize {
    let total: f64 = weights.iter().sum();
    let mut u = choices.next_f64() * total;
    let mut last = 0;
    for (i, &w) in weights.iter().enumerate() {
        if w > 0.0 {
            if u < w {
                return i;
            }
            u -= w;
            last = i;
        }
    }
    last
}

impl GraphGrammar {
    /// Runs the grammar on a copy of its host graph. Each step tries the
    /// priority groups lowest first (skipping those at their
    /// `priority_limits` cap), the productions of a group in random order;
    /// the first production with a match is applied at a random match
    /// (`match: oldest`: among the oldest), with one daughter option drawn
    /// by weight. It stops at the step limit (`max_steps`, else the
    /// grammar's `steps:`) or when nothing matches.
    ///
    /// Every random decision comes from `choices`, so the same choices give
    /// the same graph.
    ///
    /// # Errors
    ///
    /// When the graph would pass `max_elements`, a search runs past
    /// [`SEARCH_LIMIT`], the derivation runs past the grammar's
    /// [`time_limit`](GraphGrammar::time_limit) (wall clock: a derivation
    /// stopped by it is the one result that may differ between machines), or no step limit is set and the derivation passes
    /// [`UNLIMITED_STEPS`].
    pub fn derive(
        &self,
        choices: &mut impl Draws,
        max_steps: Option<usize>,
        max_elements: usize,
    ) -> Result<Derivation, DeriveError> {
        self.derive_reusing(choices, max_steps, max_elements, None)
    }

    /// [`GraphGrammar::derive`], starting from the allocations of
    /// `previous` (a graph an earlier derivation returned, of any grammar):
    /// for loops that derive again and again, where a fresh graph would
    /// be allocated and its pages faulted in every time. The result is the
    /// same as `derive`'s.
    ///
    /// # Errors
    ///
    /// As [`GraphGrammar::derive`].
    pub fn derive_reusing(
        &self,
        choices: &mut impl Draws,
        max_steps: Option<usize>,
        max_elements: usize,
        previous: Option<Graph>,
    ) -> Result<Derivation, DeriveError> {
        let mut g = match previous {
            Some(mut g) => {
                g.reset_from(&self.host);
                g
            }
            None => self.host.clone(),
        };
        if let Some(steps) = max_steps.or(self.steps) {
            // Address space only: pages are touched as elements come, and
            // the arrays never grow by copying (1.1–1.2× on Koch).
            let [v, e] = self.new_per_step.map(|n| n.saturating_mul(steps).min(max_elements));
            g.reserve(v, e);
        }
        let mut envs = run_envs(self, choices);
        let nv = self.productions.iter().map(|p| p.mv.len()).max().unwrap_or(0);
        let ne = self.productions.iter().map(|p| p.me.len()).max().unwrap_or(0);
        let (mut mv, mut me) = (vec![0u32; nv], vec![0u32; ne]);
        let mut scratch = Scratch::default();
        let mut order: Vec<usize> = Vec::new();
        let mut group_counts = vec![0usize; self.groups.len()];
        let mut applications = vec![0usize; self.productions.len()];
        let mut work = 0u64;
        let limit = max_steps.or(self.steps);
        let mut steps = 0usize;
        let started = std::time::Instant::now();
        let deadline = started.checked_add(self.time_limit);
        let out_of_time = |step: usize, production: Option<&str>| DeriveError::TimeLimit {
            seconds: format!("{}", self.time_limit.as_secs_f64()),
            step,
            while_matching: production.map(|p| format!(" while matching production `{p}`")).unwrap_or_default(),
        };
        let stop = loop {
            // The clock between steps every few steps (a step's own search
            // reads it while it runs): reading it was 2 % of a Koch step.
            if steps.is_multiple_of(CLOCK_STEPS) && deadline.is_some_and(|d| std::time::Instant::now() >= d) {
                return Err(out_of_time(steps, None));
            }
            match limit {
                Some(l) if steps >= l => break Stop::StepLimit,
                None if steps >= UNLIMITED_STEPS => return Err(DeriveError::NoTermination { steps }),
                _ => {}
            }
            let mut applied = None;
            'groups: for (gi, group) in self.groups.iter().enumerate() {
                if group.cap.is_some_and(|c| group_counts[gi] >= c) {
                    continue;
                }
                order.clear();
                order.extend(&group.members);
                while !order.is_empty() {
                    let k = if order.len() == 1 { 0 } else { choices.below(order.len()) };
                    let pi = order.swap_remove(k);
                    let p = &self.productions[pi];
                    let (pv, pe) = (&mut mv[..p.mv.len()], &mut me[..p.me.len()]);
                    let found =
                        find(&g, p, &mut envs[pi], pv, pe, &mut Random(choices), &mut work, deadline, &mut |_, _| true);
                    match found {
                        Ok(true) => {
                            applied = Some((gi, pi));
                            break 'groups;
                        }
                        Ok(false) => {}
                        Err(Exhausted::Time) => return Err(out_of_time(steps, Some(&p.name))),
                        Err(Exhausted::Work) => {
                            return Err(DeriveError::SearchLimit {
                                production: p.name.clone(),
                                limit: SEARCH_LIMIT,
                                step: steps,
                            });
                        }
                    }
                }
            }
            let Some((gi, pi)) = applied else { break Stop::NoMatch };
            let p = &self.productions[pi];
            let oi = if p.options.len() == 1 { 0 } else { weighted(choices, &p.weights) };
            let opt = &p.options[oi];
            if g.element_count() + opt.new_vertices.len() + opt.new_edges.len() > max_elements {
                return Err(DeriveError::TooManyElements { limit: max_elements, step: steps });
            }
            apply(&mut g, p, opt, &mut envs[pi], &mv[..p.mv.len()], &me[..p.me.len()], choices, &mut scratch).map_err(
                |(v, span)| DeriveError::NonFinitePosition {
                    production: p.name.clone(),
                    at: self.source.location(span.unwrap_or_default().start),
                    value: v.to_string(),
                    step: steps,
                },
            )?;
            group_counts[gi] += 1;
            applications[pi] += 1;
            steps += 1;
        };
        scratch.release(&mut g);
        Ok(Derivation { graph: g, steps, stats: Stats { applications, search_work: work, stop } })
    }

    /// Every match of production `name` in `graph`, enumerated in a fixed
    /// order (conditions that read per-run values see those of seed 0);
    /// `None` for an unknown production.
    ///
    /// # Errors
    ///
    /// Never for an unknown production; `Err` when the enumeration runs
    /// past [`SEARCH_LIMIT`] candidate tests.
    pub fn matches(&self, graph: &Graph, name: &str) -> Result<Option<Vec<Match>>, DeriveError> {
        let Some(pi) = self.productions.iter().position(|p| p.name == name) else { return Ok(None) };
        let p = &self.productions[pi];
        let mut envs = run_envs(self, &mut genform_core::Rng::from_seed(0));
        let (mut mv, mut me) = (vec![0u32; p.mv.len()], vec![0u32; p.me.len()]);
        let mut out = Vec::new();
        let mut work = 0;
        let mut visit = |v: &[u32], e: &[u32]| {
            out.push(Match { vertices: v.to_vec(), edges: e.to_vec() });
            false
        };
        // Enumeration ignores "oldest": it lists every match.
        let mut all = p.clone();
        all.oldest = false;
        let r = find(graph, &all, &mut envs[pi], &mut mv, &mut me, &mut InOrder, &mut work, None, &mut visit);
        match r {
            Ok(_) => Ok(Some(out)),
            Err(_) => Err(DeriveError::SearchLimit { production: p.name.clone(), limit: SEARCH_LIMIT, step: 0 }),
        }
    }
}
