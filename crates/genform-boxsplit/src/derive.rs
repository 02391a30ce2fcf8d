//! Derivation with backtracking (Baron & Eger 2023), on an explicit stack.
//!
//! Pending scopes wait on a work stack, taken depth first. Applying a rule
//! filters its alternatives by their constraints once, draws one by weight
//! and removes it; when alternatives remain, the application is recorded
//! with its scope, the remaining set, and how long the fill log and work
//! stack were. When a rule fails (no alternative applies, or a split is
//! impossible), the derivation returns to the nearest enclosing recorded
//! application with an alternative left — the failed scope lies in its
//! subtree, and everything done since it was applied is that subtree, so
//! truncating the stacks to the recorded lengths forgets exactly what was
//! derived below it — and applies its next alternative from the stored set
//! without re-evaluating constraints. Siblings finished earlier are not
//! revisited: observers read only the pre-existing world, so no choice
//! outside a scope's ancestors can change whether it derives (this is the
//! paper's "a rule explores all its alternatives before reporting failure
//! to its parent"). Failure with nothing left up to the axiom fails the
//! derivation.
//!
//! Nothing is written while deriving: fills are logged, and the result grid
//! is painted from the log once the derivation has succeeded.

use crate::formula::FIXED;
use crate::grammar::{BoxGrammar, DeriveLimits, Guard, Op, OpId, Paint, RuleId};
use crate::observe::World;
use crate::split::{Piece, Scratch, SplitError, split_with};
use crate::trace::{Trace, TraceEvent, TraceScope};
use genform_core::BlockGrid;
use genform_core::rng::Draws;
use glam::IVec3;
use serde::{Deserialize, Serialize};

/// How to derive.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct DeriveOptions {
    /// Limits; `None` uses the grammar's `limits` declaration (or the defaults).
    pub limits: Option<DeriveLimits>,
    /// Record a [`Trace`] of every choice (off by default: it costs time).
    pub trace: bool,
}

/// Counts of one derivation.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct DeriveStats {
    /// Rule applications, counting re-applications after backtracking.
    pub applications: u64,
    /// Backtracks.
    pub backtracks: u64,
    /// Cells written by `fill` and `void`.
    pub filled: u64,
    /// Deepest nesting of rule applications.
    pub max_depth: u32,
    /// Cells the grammar's `support` declarations changed after the
    /// derivation (blocks with nothing to hang from, stand on or lean
    /// against, taken away).
    #[serde(default)]
    pub unsupported: u64,
}

/// What a `site` did on a world (see the `site` declaration).
#[derive(Clone, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct SiteReport {
    /// The floor's world y.
    pub floor: i32,
    /// Cells of foundation laid, under the floor and paving the yard.
    pub foundation: u64,
    /// Cells cleared above the floor (terrain the building cut back).
    pub cleared: u64,
    /// Foundation cells at the box's bottom with no ground under them: the
    /// box did not reach down to the ground there.
    pub foundation_hanging: u64,
    /// Log blocks just outside the box joined to a tree the building cut:
    /// the part of the tree outside the box stays, without its trunk.
    pub cut_wood: Vec<[i32; 3]>,
}

/// A successful derivation.
#[derive(Clone, Debug)]
pub struct Derivation {
    /// The derivation box: cells painted by `fill` and `void`, the rest
    /// (`skip`) [`BlockGrid::UNSET`].
    pub blocks: BlockGrid,
    /// The trace, when asked for.
    pub trace: Option<Trace>,
    /// Counts.
    pub stats: DeriveStats,
    /// With a `site` on a world: where the floor went and what was laid.
    pub site: Option<SiteReport>,
}

/// Why a derivation ended without a result.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum FailureKind {
    /// Every alternative up to the axiom was tried.
    Exhausted,
    /// The application limit was reached.
    Applications,
    /// The backtrack limit was reached.
    Backtracks,
    /// The nesting limit was reached.
    Depth,
    /// The derivation box is empty or too large.
    InvalidBox,
    /// A formula divided by zero (`/`, `//` or `%`).
    DivisionByZero,
}

/// A rule failure: the rule, where, and why.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct FailurePoint {
    /// The rule.
    pub rule: String,
    /// Its scope.
    pub scope: TraceScope,
    /// Why it failed.
    pub reason: String,
}

/// A derivation that ended without a result.
#[derive(Clone, Debug, thiserror::Error)]
#[error("{message}")]
pub struct DeriveFailure {
    /// What ended it.
    pub kind: FailureKind,
    /// A sentence naming the rule and scope that failed.
    pub message: String,
    /// The last rule failure before the end.
    pub failed: Option<Box<FailurePoint>>,
    /// The full trace when tracing was on; otherwise the last failure and
    /// the end.
    pub trace: Trace,
    /// Counts up to the end.
    pub stats: DeriveStats,
}

/// Largest derivation box, in cells: 2²⁷ (for example 512×256×1024), so
/// the result grid (4 bytes a cell) and each observer table (4 bytes a cell)
/// stay within half a gibibyte each.
pub const MAX_VOLUME: u64 = 1 << 27;

const NONE: u32 = u32::MAX;

#[derive(Clone, Copy, Debug)]
struct Scope {
    min: IVec3,
    size: IVec3,
    /// World axis of each local axis.
    axes: [u8; 3],
}

impl Scope {
    fn local(&self, i: usize) -> i32 {
        self.size[self.axes[i] as usize]
    }

    fn trace(&self) -> TraceScope {
        TraceScope {
            min: self.min.to_array(),
            size: self.size.to_array(),
            axes: self.axes.iter().map(|&a| ["x", "y", "z"][a as usize]).collect(),
        }
    }
}

#[derive(Clone, Copy)]
struct Task {
    scope: Scope,
    op: OpId,
    /// Rule whose alternative holds `op`.
    owner: RuleId,
    /// Nearest enclosing recorded application.
    parent: u32,
    depth: u32,
}

/// A rule application with alternatives left.
struct App {
    scope: Scope,
    rule: RuleId,
    remaining: Vec<u16>,
    parent: u32,
    fills: usize,
    work: usize,
    depth: u32,
}

struct FillRec {
    min: IVec3,
    size: IVec3,
    paint: Paint,
}

enum Stop {
    /// A rule failure, to backtrack from.
    Fail { parent: u32, rule: RuleId, scope: Scope, reason: Reason },
    /// The end.
    Abort(FailureKind),
    /// A formula of `rule` at `scope` divided by zero: the end.
    DivisionByZero { rule: RuleId, scope: Scope, at: String, text: String },
}

enum Reason {
    NoAlternative,
    Split(SplitError),
}

impl Reason {
    fn text(&self) -> String {
        match self {
            Reason::NoAlternative => "no alternative applies".to_string(),
            Reason::Split(e) => format!("split failed: {e}"),
        }
    }
}

struct Engine<'g, 'w, 'c, C: Draws + ?Sized> {
    g: &'g BoxGrammar,
    world: World<'w>,
    choices: &'c mut C,
    limits: DeriveLimits,
    box_min: IVec3,
    box_size: IVec3,
    env: Vec<f64>,
    apps: Vec<App>,
    work: Vec<Task>,
    fills: Vec<FillRec>,
    cands: Vec<u16>,
    weights: Vec<f64>,
    sizes: Vec<f64>,
    pieces: Vec<Piece>,
    scratch: Scratch,
    stats: DeriveStats,
    trace: Option<Vec<TraceEvent>>,
    last_failure: Option<FailurePoint>,
}

impl DeriveFailure {
    /// A box no derivation can run in, and why.
    fn invalid_box(message: String) -> DeriveFailure {
        DeriveFailure {
            kind: FailureKind::InvalidBox,
            message,
            failed: None,
            trace: Trace::default(),
            stats: DeriveStats::default(),
        }
    }
}

impl BoxGrammar {
    /// Derives the axiom in the box `min..max_exclusive`, observing `world`
    /// (cells it does not cover, or leaves unset, count as air; `None`: all
    /// air). Every random choice comes from `choices`; the same choices give
    /// the same result. The grammar's `support` declarations, and the
    /// connection states of placed fences, panes, walls and stairs (as the
    /// game computes them), then look at the world one cell beyond the box
    /// too: pass a world that covers it.
    pub fn derive<C: Draws + ?Sized>(
        &self,
        world: Option<&BlockGrid>,
        min: IVec3,
        max_exclusive: IVec3,
        choices: &mut C,
        options: &DeriveOptions,
    ) -> Result<Derivation, DeriveFailure> {
        // In i64: the corners may be anywhere in i32.
        let wide = max_exclusive.as_i64vec3() - min.as_i64vec3();
        let fits = wide.cmpgt(glam::I64Vec3::ZERO).all() && wide.cmple(glam::I64Vec3::splat(i32::MAX as i64)).all();
        let volume = if fits { wide.x as u64 * wide.y as u64 * wide.z as u64 } else { 0 };
        let size = if fits { wide.as_ivec3() } else { IVec3::ZERO };
        if !fits || volume > MAX_VOLUME {
            let message = if volume > MAX_VOLUME {
                format!("the derivation box of {volume} cells is larger than the {MAX_VOLUME} cells supported")
            } else {
                format!("the derivation box {min}..{max_exclusive} is empty")
            };
            return Err(DeriveFailure::invalid_box(message));
        }
        // A site derives the axiom in its plot, found from the world.
        let plot = match (&self.site, world) {
            (Some(site), Some(w)) => Some(crate::site::plot(site, w, min, size).map_err(DeriveFailure::invalid_box)?),
            _ => None,
        };
        let (dmin, dsize) = plot.map_or((min, size), |p| (p.min, p.size));
        let mut e = Engine {
            g: self,
            world: World::new(world, dmin, dsize, self.types.len()),
            choices,
            limits: options.limits.unwrap_or(self.limits),
            box_min: dmin,
            box_size: dsize,
            env: vec![0.0; FIXED + self.slots.len()],
            apps: Vec::new(),
            work: Vec::new(),
            fills: Vec::new(),
            cands: Vec::new(),
            weights: Vec::new(),
            sizes: Vec::new(),
            pieces: Vec::new(),
            scratch: Scratch::default(),
            stats: DeriveStats::default(),
            trace: options.trace.then(Vec::new),
            last_failure: None,
        };
        let root = Scope { min: dmin, size: dsize, axes: [0, 1, 2] };
        e.work.push(Task { scope: root, op: self.start, owner: self.axiom, parent: NONE, depth: 0 });
        e.run()?;
        let mut blocks = e.paint();
        let mut report = None;
        if let (Some(plot), Some(site), Some(w)) = (plot, &self.site, world) {
            let choices = &mut *e.choices;
            let mut draw = || match site.foundation {
                Paint::Block(b) => self.blocks[b as usize].clone(),
                Paint::Material(m) => {
                    let mat = &self.materials[m as usize];
                    self.blocks[mat.blocks[mat.pick(choices)] as usize].clone()
                }
            };
            let (whole, laid) = crate::site::lay(&plot, w, min, size, &blocks, &mut draw);
            blocks = whole;
            report = Some(SiteReport {
                floor: plot.floor,
                foundation: laid.foundation,
                cleared: laid.cleared,
                foundation_hanging: laid.hanging,
                cut_wood: laid.cut_wood.iter().map(|p| p.to_array()).collect(),
            });
        }
        if !self.supports.is_empty() {
            e.stats.unsupported = crate::support::settle(&self.supports, world, &mut blocks);
        }
        // Fences, panes, walls and stairs take the states the game would
        // give them, in the world as it now will be.
        crate::connect::connect(world, &mut blocks);
        let stats = e.stats;
        let trace = e.trace.take().map(|mut events| {
            events.push(TraceEvent::Done { applications: stats.applications, backtracks: stats.backtracks });
            Trace { events }
        });
        Ok(Derivation { blocks, trace, stats, site: report })
    }
}

impl<C: Draws + ?Sized> Engine<'_, '_, '_, C> {
    fn run(&mut self) -> Result<(), DeriveFailure> {
        let mut pending: Option<Task> = None;
        loop {
            let task = match pending.take() {
                Some(t) => t,
                None => match self.work.pop() {
                    Some(t) => t,
                    None => return Ok(()),
                },
            };
            match self.task(task) {
                Ok(()) => {}
                Err(Stop::Abort(kind)) => return Err(self.failure(kind)),
                Err(Stop::DivisionByZero { rule, scope, at, text }) => {
                    let rule = &self.g.rules[rule as usize].name;
                    let message = format!(
                        "rule `{rule}` at {}: the formula at {at} divides by zero (`{text}`); \
                         guard it with a condition on the scope, e.g. `when X > 4 {{ … }}`",
                        scope.trace()
                    );
                    let mut f = self.failure(FailureKind::DivisionByZero);
                    f.message = message;
                    return Err(f);
                }
                Err(Stop::Fail { parent, rule, scope, reason }) => {
                    pending = Some(self.backtrack(parent, rule, scope, reason)?);
                }
            }
        }
    }

    /// Runs one task: rule applications and reorientations in place, then
    /// a terminal or a split that queues its children.
    fn task(&mut self, t: Task) -> Result<(), Stop> {
        let g = self.g;
        let Task { mut scope, mut op, mut owner, mut parent, mut depth } = t;
        loop {
            match &g.ops[op as usize] {
                Op::Rule(r) => {
                    let r = *r;
                    depth += 1;
                    if depth > self.limits.depth {
                        return Err(Stop::Abort(FailureKind::Depth));
                    }
                    self.count_application()?;
                    self.stats.max_depth = self.stats.max_depth.max(depth);
                    self.candidates(r, &scope)?;
                    if self.cands.is_empty() {
                        return Err(Stop::Fail { parent, rule: r, scope, reason: Reason::NoAlternative });
                    }
                    let total = self.cands.len();
                    let mut cands = std::mem::take(&mut self.cands);
                    let pick = self.draw(r, &mut cands);
                    if !cands.is_empty() {
                        self.apps.push(App {
                            scope,
                            rule: r,
                            remaining: cands.clone(),
                            parent,
                            fills: self.fills.len(),
                            work: self.work.len(),
                            depth,
                        });
                        parent = (self.apps.len() - 1) as u32;
                    }
                    self.trace_apply(r, &scope, pick, total, cands.len(), depth);
                    self.cands = cands;
                    owner = r;
                    op = g.rules[r as usize].alternatives[pick as usize].op;
                }
                Op::Reorient(perm, then) => {
                    let a = scope.axes;
                    scope.axes = [a[perm[0] as usize], a[perm[1] as usize], a[perm[2] as usize]];
                    op = *then;
                }
                Op::Fill(paint) => {
                    self.fills.push(FillRec { min: scope.min, size: scope.size, paint: *paint });
                    return Ok(());
                }
                Op::Skip => return Ok(()),
                Op::Split { axis, sizes, constant, repeat, round, children } => {
                    self.sizes.clear();
                    match constant {
                        Some(c) => self.sizes.extend_from_slice(c),
                        None => {
                            self.set_env(&scope);
                            for f in sizes {
                                self.observe(&f.observers, &scope);
                                if let Some(d) = f.zero_divisor(&self.env) {
                                    let (at, text) = (d.at.clone(), d.text.clone());
                                    return Err(Stop::DivisionByZero { rule: owner, scope, at, text });
                                }
                                self.sizes.push(f.program.eval(&self.env));
                            }
                        }
                    }
                    let w = scope.axes[*axis as usize] as usize;
                    let length = scope.size[w] as u32;
                    if let Err(e) =
                        split_with(&mut self.scratch, length, &self.sizes, *repeat, *round, &mut self.pieces)
                    {
                        return Err(Stop::Fail { parent, rule: owner, scope, reason: Reason::Split(e) });
                    }
                    // Children go on the stack last first, so the first is derived first.
                    let mut end = length as i32;
                    for p in self.pieces.iter().rev() {
                        let start = end - p.length as i32;
                        let mut child = scope;
                        child.min[w] += start;
                        child.size[w] = p.length as i32;
                        self.work.push(Task { scope: child, op: children[p.child], owner, parent, depth });
                        end = start;
                    }
                    return Ok(());
                }
            }
        }
    }

    fn count_application(&mut self) -> Result<(), Stop> {
        self.stats.applications += 1;
        if self.stats.applications > self.limits.applications {
            return Err(Stop::Abort(FailureKind::Applications));
        }
        Ok(())
    }

    /// The applicable alternatives of `rule` at `scope` into `self.cands`.
    fn candidates(&mut self, rule: RuleId, scope: &Scope) -> Result<(), Stop> {
        let alts = &self.g.rules[rule as usize].alternatives;
        self.cands.clear();
        let mut env_ready = false;
        let mut has_else = None;
        for (i, a) in alts.iter().enumerate() {
            let ok = match &a.guard {
                Guard::Always => true,
                Guard::Else => {
                    has_else = Some(i);
                    false
                }
                Guard::When(f) => {
                    if !env_ready {
                        self.set_env(scope);
                        env_ready = true;
                    }
                    self.observe(&f.observers, scope);
                    if let Some(d) = f.zero_divisor(&self.env) {
                        let (at, text) = (d.at.clone(), d.text.clone());
                        return Err(Stop::DivisionByZero { rule, scope: *scope, at, text });
                    }
                    let v = f.program.eval(&self.env);
                    v != 0.0 && !v.is_nan()
                }
            };
            if ok {
                self.cands.push(i as u16);
            }
        }
        if self.cands.is_empty()
            && let Some(i) = has_else
        {
            self.cands.push(i as u16);
        }
        Ok(())
    }

    /// Draws one of `cands` by weight and removes it. Zero weights are
    /// drawn only when every remaining weight is zero.
    fn draw(&mut self, rule: RuleId, cands: &mut Vec<u16>) -> u16 {
        if cands.len() == 1 {
            return cands.pop().unwrap_or(0);
        }
        let alts = &self.g.rules[rule as usize].alternatives;
        self.weights.clear();
        self.weights.extend(cands.iter().map(|&i| alts[i as usize].weight));
        if self.weights.iter().all(|&w| w <= 0.0) {
            self.weights.iter_mut().for_each(|w| *w = 1.0);
        }
        let i = self.choices.choose(&self.weights).min(cands.len() - 1);
        cands.remove(i)
    }

    fn set_env(&mut self, s: &Scope) {
        let (x, y, z) = (s.local(0) as f64, s.local(1) as f64, s.local(2) as f64);
        let off = s.min - self.box_min;
        let e = &mut self.env;
        e[0] = x;
        e[1] = y;
        e[2] = z;
        e[3] = self.box_size.x as f64;
        e[4] = self.box_size.y as f64;
        e[5] = self.box_size.z as f64;
        e[6] = x.min(y).min(z);
        e[7] = x.max(y).max(z);
        e[8] = s.min.x as f64;
        e[9] = s.min.y as f64;
        e[10] = s.min.z as f64;
        e[11] = off.x as f64;
        e[12] = off.y as f64;
        e[13] = off.z as f64;
    }

    fn observe(&mut self, slots: &[u32], s: &Scope) {
        let volume = s.size.x as u64 * s.size.y as u64 * s.size.z as u64;
        for &slot in slots {
            let (obs, ty) = self.g.slots[slot as usize];
            let count = self.world.count(&self.g.types, ty, s.min, s.size);
            self.env[FIXED + slot as usize] = obs.value(count, volume);
        }
    }

    /// Returns to the nearest enclosing application with an alternative
    /// left and gives the task that applies its next alternative.
    fn backtrack(&mut self, parent: u32, rule: RuleId, scope: Scope, reason: Reason) -> Result<Task, DeriveFailure> {
        let point = FailurePoint {
            rule: self.g.rules[rule as usize].name.clone(),
            scope: scope.trace(),
            reason: reason.text(),
        };
        if let Some(t) = &mut self.trace {
            t.push(TraceEvent::Fail {
                rule: point.rule.clone(),
                scope: point.scope.clone(),
                reason: point.reason.clone(),
            });
        }
        self.last_failure = Some(point);
        let mut p = parent;
        while p != NONE && self.apps[p as usize].remaining.is_empty() {
            p = self.apps[p as usize].parent;
        }
        if p == NONE {
            return Err(self.failure(FailureKind::Exhausted));
        }
        self.stats.backtracks += 1;
        if self.stats.backtracks > self.limits.backtracks {
            return Err(self.failure(FailureKind::Backtracks));
        }
        let idx = p as usize;
        let discarded = self.apps.len() - idx - 1;
        let discarded_fills = self.fills.len() - self.apps[idx].fills;
        self.apps.truncate(idx + 1);
        self.fills.truncate(self.apps[idx].fills);
        self.work.truncate(self.apps[idx].work);
        if self.count_application().is_err() {
            return Err(self.failure(FailureKind::Applications));
        }
        let mut remaining = std::mem::take(&mut self.apps[idx].remaining);
        let (r, scope, depth, up) = {
            let a = &self.apps[idx];
            (a.rule, a.scope, a.depth, a.parent)
        };
        let pick = self.draw(r, &mut remaining);
        let left = remaining.len();
        if let Some(t) = &mut self.trace {
            t.push(TraceEvent::Backtrack {
                rule: self.g.rules[r as usize].name.clone(),
                scope: scope.trace(),
                discarded,
                discarded_fills,
            });
        }
        let parent = if remaining.is_empty() {
            // Nothing left to come back to: the record can go.
            self.apps.pop();
            up
        } else {
            self.apps[idx].remaining = remaining;
            p
        };
        self.trace_apply(r, &scope, pick, left + 1, left, depth);
        let op = self.g.rules[r as usize].alternatives[pick as usize].op;
        Ok(Task { scope, op, owner: r, parent, depth })
    }

    fn trace_apply(&mut self, rule: RuleId, scope: &Scope, pick: u16, candidates: usize, left: usize, depth: u32) {
        if let Some(t) = &mut self.trace {
            let r = &self.g.rules[rule as usize];
            t.push(TraceEvent::Apply {
                rule: r.name.clone(),
                scope: scope.trace(),
                alternative: pick as usize,
                line: r.alternatives[pick as usize].line,
                candidates,
                left,
                depth,
            });
        }
    }

    fn failure(&mut self, kind: FailureKind) -> DeriveFailure {
        let axiom = self.g.axiom().to_string();
        let last = self.last_failure.clone();
        let last_text = last.as_ref().map(|f| format!("rule `{}` at {}: {}", f.rule, f.scope, f.reason));
        let message = match kind {
            FailureKind::Exhausted => format!(
                "no derivation: every alternative up to the axiom `{axiom}` was tried ({} backtracks); the last failure was {}",
                self.stats.backtracks,
                last_text.unwrap_or_else(|| "unknown".into())
            ),
            FailureKind::Applications => format!(
                "stopped after {} rule applications (limit `applications = {}`); the grammar may recurse without end{}",
                self.limits.applications,
                self.limits.applications,
                last_text.map(|t| format!("; the last failure was {t}")).unwrap_or_default()
            ),
            FailureKind::Backtracks => format!(
                "stopped after {} backtracks (limit `backtracks = {}`); the last failure was {}",
                self.limits.backtracks,
                self.limits.backtracks,
                last_text.unwrap_or_else(|| "unknown".into())
            ),
            FailureKind::Depth => format!(
                "stopped at {} nested rule applications (limit `depth = {}`); the grammar may recurse without shrinking its scope",
                self.limits.depth, self.limits.depth
            ),
            FailureKind::InvalidBox => "invalid derivation box".to_string(),
            FailureKind::DivisionByZero => "a formula divided by zero".to_string(),
        };
        let mut trace = Trace { events: self.trace.take().unwrap_or_default() };
        if trace.events.is_empty()
            && let Some(f) = &last
        {
            trace.events.push(TraceEvent::Fail {
                rule: f.rule.clone(),
                scope: f.scope.clone(),
                reason: f.reason.clone(),
            });
        }
        if kind == FailureKind::Exhausted {
            trace.events.push(TraceEvent::Exhausted { rule: axiom });
        }
        DeriveFailure { kind, message, failed: last.map(Box::new), trace, stats: self.stats }
    }

    /// Paints the logged fills into the result grid.
    fn paint(&mut self) -> BlockGrid {
        let g = self.g;
        let mut grid = BlockGrid::new(self.box_min, self.box_size.as_uvec3());
        let mut palette = vec![BlockGrid::UNSET; g.blocks.len()];
        let mut index = |grid: &mut BlockGrid, b: u32| {
            let slot = &mut palette[b as usize];
            if *slot == BlockGrid::UNSET {
                grid.palette.push(g.blocks[b as usize].clone());
                *slot = (grid.palette.len() - 1) as u32;
            }
            *slot
        };
        let (sx, sz) = (self.box_size.x as usize, self.box_size.z as usize);
        let mut mix: Vec<u32> = Vec::new();
        for f in &self.fills {
            let l = (f.min - self.box_min).as_uvec3();
            let (nx, ny, nz) = (f.size.x as usize, f.size.y as usize, f.size.z as usize);
            self.stats.filled += (nx * ny * nz) as u64;
            match f.paint {
                Paint::Block(b) => {
                    let c = index(&mut grid, b);
                    for y in 0..ny {
                        for z in 0..nz {
                            let row = ((l.y as usize + y) * sz + l.z as usize + z) * sx + l.x as usize;
                            grid.cells[row..row + nx].fill(c);
                        }
                    }
                }
                Paint::Material(m) => {
                    let mat = &g.materials[m as usize];
                    mix.clear();
                    for &b in &mat.blocks {
                        let c = index(&mut grid, b);
                        mix.push(c);
                    }
                    for y in 0..ny {
                        for z in 0..nz {
                            let row = ((l.y as usize + y) * sz + l.z as usize + z) * sx + l.x as usize;
                            for cell in &mut grid.cells[row..row + nx] {
                                *cell = mix[mat.pick(self.choices)];
                            }
                        }
                    }
                }
            }
        }
        grid
    }
}
