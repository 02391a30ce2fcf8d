//! The interpreter: runs the operation programs of the genes of a genome,
//! from the root, with scope state, and emits primitives.
//!
//! All state lives in explicit stacks (frames, envs, saved scopes, slot
//! counters, loops), so a deep derivation never deepens the Rust stack. The
//! same interpreter serves expression ([`crate::express::ExpressMode`]) and
//! prior sampling ([`crate::sample::SampleMode`]); the mode decides what a
//! link holds.
//!
//! Expression runs tens of thousands of times a second inside optimizers,
//! so the hot path is kept lean: the running gene's frame and scope live
//! outside the stacks (no indexing per operation, and a call saves the
//! caller's scope once), the stacks are reused between runs ([`Stacks`]),
//! trivial operands skip the bytecode evaluator ([`Fast`]), and error
//! values stay small and are built out of line.

mod build;
pub(crate) mod occlusion;
mod pieces;
mod scope_geom;

use crate::builtins::{ENV_COUNT, ENV_DEPTH, ENV_INDEX, ENV_LOT, ENV_SX};
use crate::fast_expr::Fast;
use crate::grammar::ShapeGrammar;
use crate::program::*;
use crate::scope::ScopeState;
use genform_core::genome::GenePos;
use genform_core::{ExpressError, Genome, LimitKind, Limits, Primitive};
use glam::{Affine3A, DVec3};
use scope_geom::Geom;

/// Operations one run may execute per unit of its primitive and gene
/// limits, so grammars that loop without emitting (huge `repeat`s, nested
/// `mirror`s re-running subtrees) still stop.
const OPS_PER_UNIT: u64 = 256;
/// Operations every run may execute regardless of limits.
const OPS_BASE: u64 = 1_000_000;

/// Why a run stopped early.
pub(crate) enum Stop {
    /// A real error (boxed: it is rare, and a small `Stop` keeps every
    /// `Result` of the hot path small).
    Error(Box<ExpressError>),
    /// Sampling reached a limit: keep what was grown.
    Truncate(LimitKind),
}

impl From<ExpressError> for Stop {
    fn from(e: ExpressError) -> Self {
        Stop::Error(Box::new(e))
    }
}

/// What a link holds, and where emitted geometry goes.
pub(crate) trait Mode {
    /// The genome being run.
    fn genome(&self) -> &Genome;
    /// The child in `link` of `gene`, deciding the link first when sampling.
    /// `child_depth` is the depth the child would have.
    fn touch(
        &mut self,
        gene: GenePos,
        link: usize,
        slot: &SlotCode,
        child_depth: usize,
    ) -> Result<Option<GenePos>, Stop>;
    /// Places one primitive (already counted against the limit).
    fn emit(&mut self, g: &ShapeGrammar, transform: Affine3A, prim: Primitive, tag: u32);
    /// Places one planar polygon, in world coordinates (counted already).
    fn emit_polygon(&mut self, g: &ShapeGrammar, points: Vec<glam::Vec3>, tag: u32);
    /// Places one mesh made by the run (a mass or a roof; counted already).
    fn emit_mesh(&mut self, g: &ShapeGrammar, transform: Affine3A, mesh: genform_core::Mesh, tag: u32);
    /// What hitting a limit means in this mode.
    fn limit(&self, kind: LimitKind, limits: &Limits) -> Stop;
    /// Records that the run left something out, and why (expression keeps
    /// it in the scene; sampling drops it, the expression that follows
    /// sees the same).
    fn note(&mut self, _text: String) {}
}

/// One running gene (its scope is kept apart: see [`Stacks::caller_scopes`]).
#[derive(Clone, Copy)]
struct Frame {
    sym: u32,
    gene: GenePos,
    pc: usize,
    depth: usize,
    /// Start of this frame's env in [`Stacks::env`].
    env: usize,
    /// Start of this frame's slot counters.
    counters: usize,
}

/// An open `mirror`, `split` or `repeat`.
#[derive(Clone, Copy)]
enum Loop {
    Mirror {
        axis: u8,
        second: bool,
        saved: usize,
    },
    Split {
        axis: u8,
        pieces: usize,
        index: f64,
        count: f64,
    },
    Repeat {
        axis: u8,
        i: u32,
        n: u32,
        len: f64,
        size: f64,
        index: f64,
        count: f64,
    },
    /// `comp(f)`: `n` faces from `faces` in [`Stacks::faces`]; the running
    /// one is `pos`, the `k`-th of its arm.
    Comp {
        faces: usize,
        n: u32,
        pos: u32,
        k: u32,
        index: f64,
        count: f64,
    },
}

/// The interpreter's stacks. A run starts from empty stacks but keeps their
/// capacity, so once warmed up (see [`crate::scratch`]) a run allocates
/// nothing.
#[derive(Default)]
pub(crate) struct Stacks {
    /// The callers of the running gene.
    frames: Vec<Frame>,
    /// Their scopes at the calls (apart from `frames`: two small copies
    /// are cheaper than one large one).
    caller_scopes: Vec<ScopeState>,
    env: Vec<f64>,
    scopes: Vec<ScopeState>,
    counters: Vec<u32>,
    saved_counters: Vec<u32>,
    loops: Vec<Loop>,
    pieces: Vec<(f64, f64)>,
    args: Vec<f64>,
    /// Polygons and masses of polygon scopes (see `build`).
    geoms: Vec<Geom>,
    /// Their points.
    pts: Vec<glam::DVec2>,
    /// Faces of open `comp`s: arm and scope.
    faces: Vec<(u32, ScopeState)>,
    /// The solid a roof or taper built for the face split that follows it.
    /// (The roof apart from its flush walls, and those walls.)
    solid: Option<(genform_core::scene::Mesh, genform_core::scene::Mesh)>,
    /// What the run has placed, for occlusion queries (only kept when the
    /// grammar asks them).
    placed: Vec<occlusion::Placed>,
    /// The running gene and its callers (a query's lineage).
    lineage: Vec<GenePos>,
}

impl Stacks {
    fn clear(&mut self) {
        self.frames.clear();
        self.caller_scopes.clear();
        self.env.clear();
        self.scopes.clear();
        self.counters.clear();
        self.saved_counters.clear();
        self.loops.clear();
        self.pieces.clear();
        self.args.clear();
        self.geoms.clear();
        self.pts.clear();
        self.faces.clear();
        self.solid = None;
        self.placed.clear();
    }

    /// Bytes held by the stacks' buffers.
    pub(crate) fn capacity_bytes(&self) -> usize {
        use std::mem::size_of;
        self.frames.capacity() * size_of::<Frame>()
            + self.caller_scopes.capacity() * size_of::<ScopeState>()
            + (self.env.capacity() + self.args.capacity()) * size_of::<f64>()
            + self.scopes.capacity() * size_of::<ScopeState>()
            + (self.counters.capacity() + self.saved_counters.capacity()) * size_of::<u32>()
            + self.loops.capacity() * size_of::<Loop>()
            + self.pieces.capacity() * size_of::<(f64, f64)>()
            + self.geoms.capacity() * size_of::<Geom>()
            + self.pts.capacity() * size_of::<glam::DVec2>()
            + self.faces.capacity() * size_of::<(u32, ScopeState)>()
    }
}

/// Runs the derivation of `mode`'s genome (which must have a root) from
/// the unit scope, on `stacks`, and hands back the mode.
pub(crate) fn run<M: Mode>(g: &ShapeGrammar, limits: &Limits, mode: M, stacks: &mut Stacks) -> (Result<(), Stop>, M) {
    let mut it = Interp::new(g, limits, mode, std::mem::take(stacks));
    // A grammar set on a footprint starts on it, as if its axiom began
    // with `lot` of the footprint's corners.
    let res = match &g.start_lot {
        Some(lot) => it.start_on(lot.to_vec(), g.start_props.street_edge).and_then(|()| it.run()),
        None => it.run(),
    };
    *stacks = it.st;
    (res, it.mode)
}

/// The interpreter state.
struct Interp<'g, M> {
    g: &'g ShapeGrammar,
    limits: Limits,
    mode: M,
    st: Stacks,
    /// The running gene; its callers are on `st.frames`.
    top: Frame,
    /// The running gene's scope.
    cur: ScopeState,
    /// The running gene's program.
    rule: &'g RuleCode,
    ops: u64,
    budget: u64,
    emitted: usize,
}

impl<'g, M: Mode> Interp<'g, M> {
    /// Prepares a run from the genome's root in the unit scope, on
    /// `stacks` (cleared first).
    fn new(g: &'g ShapeGrammar, limits: &Limits, mode: M, mut stacks: Stacks) -> Self {
        stacks.clear();
        // What stands around (`context "…";`) is placed before anything.
        if g.occlusion {
            stacks.placed.extend_from_slice(&g.context);
        }
        let (top, rule) = enter(g, mode.genome(), &mut stacks, GenePos(0), 0, 0);
        let cur = ScopeState { tagged: rule.tag, ..ScopeState::UNIT };
        let units = (limits.max_primitives as u64).saturating_add(limits.max_genes as u64);
        Interp {
            g,
            limits: *limits,
            mode,
            st: stacks,
            top,
            cur,
            rule,
            ops: 0,
            budget: units.saturating_mul(OPS_PER_UNIT).saturating_add(OPS_BASE),
            emitted: 0,
        }
    }

    /// Runs the derivation.
    fn run(&mut self) -> Result<(), Stop> {
        loop {
            let rule = self.rule;
            let pc = self.top.pc;
            let Some(&op) = rule.code.get(pc) else {
                // The gene's program is done: return to its caller.
                self.st.env.truncate(self.top.env);
                self.st.counters.truncate(self.top.counters);
                let (Some(caller), Some(cur)) = (self.st.frames.pop(), self.st.caller_scopes.pop()) else {
                    return Ok(());
                };
                self.top = caller;
                self.cur = cur;
                self.rule = &self.g.rules[caller.sym as usize];
                continue;
            };
            self.ops += 1;
            if self.ops > self.budget {
                return Err(self.mode.limit(LimitKind::Primitives, &self.limits));
            }
            self.top.pc = pc + 1;
            self.step(rule, op)?;
        }
    }

    /// Evaluates expression `e` of the running rule.
    #[inline(always)]
    fn eval(&mut self, rule: &'g RuleCode, e: u32) -> Result<f64, Stop> {
        let fast = &rule.fast[e as usize];
        if matches!(fast, Fast::Run) {
            return self.run_expr(rule, e);
        }
        // The running gene's env is the last one: the rest of the stack.
        debug_assert_eq!(self.st.env.len(), self.top.env + rule.env_init.len());
        Ok(fast.eval(&self.cur.size, &self.st.env, self.top.env))
    }

    /// Evaluates expression `e` with the bytecode evaluator.
    fn run_expr(&mut self, rule: &'g RuleCode, e: u32) -> Result<f64, Stop> {
        let ex = &rule.exprs[e as usize];
        let base = self.top.env;
        if ex.needs_size {
            self.st.env[base + ENV_SX..base + ENV_SX + 3].copy_from_slice(&self.cur.size.to_array());
        }
        for &(idx, slot) in &ex.has {
            let v = self.has(rule, slot)?;
            self.st.env[base + idx as usize] = v;
        }
        if !ex.queries.is_empty() {
            let st = &mut self.st;
            st.lineage.clear();
            st.lineage.extend(st.frames.iter().map(|f| f.gene).chain([self.top.gene]));
            let scope = occlusion::Placed::of(&self.cur, self.top.gene);
            for &(idx, q) in &ex.queries {
                let v = occlusion::holds(q, &scope, &st.placed, &st.lineage, &self.g.base_tags);
                st.env[base + idx as usize] = if v { 1.0 } else { 0.0 };
            }
        }
        Ok(ex.prog.eval(&self.st.env[base..base + rule.env_init.len()]))
    }

    /// Evaluates a value used as geometry: it must be finite.
    #[inline(always)]
    fn num(&mut self, rule: &'g RuleCode, e: u32, what: &str) -> Result<f64, Stop> {
        let v = self.eval(rule, e)?;
        if v.is_finite() { Ok(v) } else { Err(self.not_finite(rule, e, what, v)) }
    }

    #[cold]
    fn not_finite(&self, rule: &RuleCode, e: u32, what: &str, v: f64) -> Stop {
        let sym = &self.g.graph.symbols[self.top.sym as usize].name;
        let loc = self.g.file.location(rule.exprs[e as usize].span.start);
        ExpressError::Eval(format!("{loc}: rule `{sym}`: {what} is not a finite number (it is {v})")).into()
    }

    #[inline(always)]
    fn vec3(&mut self, rule: &'g RuleCode, e: u32, what: &str) -> Result<DVec3, Stop> {
        Ok(DVec3::new(self.num(rule, e, what)?, self.num(rule, e + 1, what)?, self.num(rule, e + 2, what)?))
    }

    /// `has(slot)`: whether link 0 of the slot holds a child.
    fn has(&mut self, rule: &'g RuleCode, slot: u32) -> Result<f64, Stop> {
        let s = &rule.slots[slot as usize];
        let (gene, depth) = (self.top.gene, self.top.depth);
        Ok(if self.mode.touch(gene, s.link as usize, s, depth + 1)?.is_some() { 1.0 } else { 0.0 })
    }

    #[inline(always)]
    fn step(&mut self, rule: &'g RuleCode, op: Op) -> Result<(), Stop> {
        match op {
            Op::Push => self.st.scopes.push(self.cur),
            Op::Pop => {
                if let Some(s) = self.st.scopes.pop() {
                    self.cur = s;
                }
            }
            Op::Translate(e) => {
                let v = self.vec3(rule, e, "a translation")?;
                self.cur.translate(v);
            }
            Op::Rotate(axis, e) => {
                let a = self.num(rule, e, "a rotation angle")?;
                self.cur.rotate(axis, a);
            }
            Op::Size(e) => {
                let v = self.vec3(rule, e, "a size")?;
                self.cur.size = v;
            }
            Op::Scale(e) => {
                let v = self.vec3(rule, e, "a scale factor")?;
                let s = self.cur.size * v;
                if !s.is_finite() {
                    return Err(self.overflow(rule, e, "the scaled size"));
                }
                self.cur.size = s;
            }
            Op::Tag(t) => self.cur.set_tag(t),
            Op::Color(k) => self.cur.set_tag(self.g.color_tags[k as usize][self.cur.tag() as usize]),
            Op::Texture(k) => self.cur.set_tag(self.g.texture_tags[k as usize][self.cur.tag() as usize]),
            Op::Let(idx, e) => {
                let v = self.eval(rule, e)?;
                self.st.env[self.top.env + idx as usize] = v;
            }
            Op::Emit(p) => self.emit(rule, p)?,
            Op::Invoke { slot, args, nargs, site } => self.invoke(rule, slot, args, nargs, site)?,
            Op::JumpUnless(e, t) => {
                let v = self.eval(rule, e)?;
                if v == 0.0 || v.is_nan() {
                    self.top.pc = t as usize;
                }
            }
            Op::Jump(t) => self.top.pc = t as usize,
            Op::Alt { env, table } => {
                let v = self.st.env[self.top.env + env as usize];
                let targets = &rule.tables[table as usize];
                let k = if v.is_finite() && v >= 0.0 && (v as usize) < targets.len() { v as usize } else { 0 };
                if let Some(t) = targets.get(k) {
                    self.top.pc = *t as usize;
                }
            }
            Op::MirrorBegin(axis) => {
                let saved = self.st.saved_counters.len();
                let c = self.top.counters;
                self.st.saved_counters.extend_from_slice(&self.st.counters[c..c + rule.slots.len()]);
                self.st.scopes.push(self.cur);
                self.st.loops.push(Loop::Mirror { axis, second: false, saved });
            }
            Op::MirrorEnd(start) => self.mirror_end(rule, start),
            Op::SplitBegin { axis, first, n, span } => self.split_begin(rule, axis, first, n, span)?,
            Op::Piece(k) => {
                if let Some(&Loop::Split { axis, pieces: first, .. }) = self.st.loops.last() {
                    let (centre, len) = self.st.pieces[first + k as usize];
                    self.st.scopes.push(self.cur);
                    let parent = self.cur.size[axis as usize];
                    self.cur.piece(axis, centre, len);
                    if self.cur.geom != crate::scope::NO_GEOM {
                        self.cut_geom(axis, centre, len, parent)?;
                    }
                    self.st.env[self.top.env + ENV_INDEX] = k as f64;
                }
            }
            Op::Lot { args, n, span } => self.lot(rule, args, n, span)?,
            Op::Extrude(e) => self.extrude(rule, e)?,
            Op::Taper { height, span, faces } => self.taper(rule, height, span, faces)?,
            Op::Shape(_) => self.shape(rule)?,
            op @ Op::Roof { .. } => self.roof(rule, op)?,
            Op::CompBegin { kind, args, first, n, span } => self.comp_begin(rule, kind, args, first, n, span)?,
            Op::CompArm { arm, end } => self.comp_arm(arm, end),
            Op::CompNext { arm, body } => self.comp_next(arm, body),
            Op::CompEnd => self.comp_end(),
            Op::SplitEnd => {
                if let Some(Loop::Split { pieces: first, index, count, .. }) = self.st.loops.pop() {
                    self.st.pieces.truncate(first);
                    self.restore_index(index, count);
                }
            }
            Op::RepeatBegin { axis, tile } => {
                let t = self.num(rule, tile, "a repeat tile size")?;
                let size = self.cur.size[axis as usize];
                let base = self.top.env;
                let (index, count) = (self.st.env[base + ENV_INDEX], self.st.env[base + ENV_COUNT]);
                let ratio = size.abs() / t;
                let n = if t > 0.0 && ratio.is_finite() { ratio.round().clamp(1.0, u32::MAX as f64) as u32 } else { 1 };
                let len = size / n as f64;
                self.st.loops.push(Loop::Repeat { axis, i: 0, n, len, size, index, count });
                self.enter_tile(axis, 0, n, len, size)?;
            }
            Op::RepeatNext(body) => self.repeat_next(body)?,
        }
        Ok(())
    }

    /// After the first pass: restores the scope and the slot counters,
    /// reflects and runs the body again; after the second: leaves.
    fn mirror_end(&mut self, rule: &RuleCode, start: u32) {
        let Some(Loop::Mirror { axis, second, saved }) = self.st.loops.last_mut() else {
            return;
        };
        let (axis, saved) = (*axis, *saved);
        if !*second {
            *second = true;
            let mut s = self.st.scopes.last().copied().unwrap_or(self.cur);
            s.reflect(axis);
            self.cur = s;
            self.top.pc = start as usize;
            let n = rule.slots.len();
            let c = self.top.counters;
            self.st.counters[c..c + n].copy_from_slice(&self.st.saved_counters[saved..saved + n]);
        } else {
            if let Some(s) = self.st.scopes.pop() {
                self.cur = s;
            }
            self.st.saved_counters.truncate(saved);
            self.st.loops.pop();
        }
    }

    /// Computes the `n` pieces of a split: absolute sizes first, the rest
    /// shared by the relative ones.
    fn split_begin(&mut self, rule: &'g RuleCode, axis: u8, first: u32, n: u32, span: u32) -> Result<(), Stop> {
        let (area, axis) = (axis & SPLIT_AREA != 0, axis & !SPLIT_AREA);
        // `splitArea`: sizes in the polygon's area, cut where the area
        // before the cut is the pieces' so far.
        let polygon = if area { Some(self.area_polygon(rule, axis, span)?) } else { None };
        let total = match &polygon {
            Some(p) => crate::polygon::area2(p) / 2.0,
            None => self.cur.size[axis as usize],
        };
        let base = self.top.env;
        let (index, count) = (self.st.env[base + ENV_INDEX], self.st.env[base + ENV_COUNT]);
        let at = self.st.pieces.len();
        let sizes = &rule.pieces[first as usize..(first + n) as usize];
        // Floating sizes stretch to fill the scope unless relative pieces
        // take the rest; then they are absolute.
        let any_rel = sizes.iter().any(|p| p.1 == SizeKind::Relative);
        let mut absolute = 0.0;
        let mut weights = 0.0;
        let mut floating = 0.0;
        for k in 0..n {
            let (e, kind) = rule.pieces[(first + k) as usize];
            let v = self.num(rule, e, "a split size")?.max(0.0);
            let tag = match kind {
                SizeKind::Relative => {
                    weights += v;
                    1.0
                }
                SizeKind::Floating if !any_rel => {
                    floating += v;
                    2.0
                }
                _ => {
                    absolute += v;
                    0.0
                }
            };
            self.st.pieces.push((v, tag));
        }
        let rest = (total - absolute).max(0.0);
        let stretch = if floating > 0.0 { rest / floating } else { 0.0 };
        let mut pos = -0.5 * total;
        for p in &mut self.st.pieces[at..] {
            let len = if p.1 == 1.0 {
                if weights > 0.0 { rest * p.0 / weights } else { 0.0 }
            } else if p.1 == 2.0 {
                p.0 * stretch
            } else {
                p.0
            };
            *p = (pos + 0.5 * len, len);
            pos += len;
        }
        if let Some(poly) = polygon {
            let half = 0.5 * self.cur.size[axis as usize];
            let (mut before, mut cut) = (0.0, -half);
            for p in &mut self.st.pieces[at..] {
                before += p.1;
                let next =
                    if before >= total { half } else { crate::geom::cut_at_area(&poly, axis as usize, before, half) };
                *p = (0.5 * (cut + next), (next - cut).max(0.0));
                cut = next;
            }
        }
        self.st.loops.push(Loop::Split { axis, pieces: at, index, count });
        self.st.env[base + ENV_COUNT] = n as f64;
        Ok(())
    }

    /// Leaves the tile; enters the next one (jumping to `body`) or ends.
    fn repeat_next(&mut self, body: u32) -> Result<(), Stop> {
        if let Some(s) = self.st.scopes.pop() {
            self.cur = s;
        }
        if let Some(Loop::Repeat { axis, i, n, len, size, index, count }) = self.st.loops.last_mut() {
            *i += 1;
            let (axis, i, n, len, size, index, count) = (*axis, *i, *n, *len, *size, *index, *count);
            if i < n {
                self.enter_tile(axis, i, n, len, size)?;
                self.top.pc = body as usize;
            } else {
                self.st.loops.pop();
                self.restore_index(index, count);
            }
        }
        Ok(())
    }

    #[cold]
    fn overflow(&self, rule: &RuleCode, e: u32, what: &str) -> Stop {
        let sym = &self.g.graph.symbols[self.top.sym as usize].name;
        let loc = self.g.file.location(rule.exprs[e as usize].span.start);
        ExpressError::Eval(format!("{loc}: rule `{sym}`: {what} is not a finite number")).into()
    }

    fn enter_tile(&mut self, axis: u8, i: u32, n: u32, len: f64, size: f64) -> Result<(), Stop> {
        self.st.scopes.push(self.cur);
        let centre = -0.5 * size + (i as f64 + 0.5) * len;
        self.cur.piece(axis, centre, len);
        if self.cur.geom != crate::scope::NO_GEOM {
            self.cut_geom(axis, centre, len, size)?;
        }
        let base = self.top.env;
        self.st.env[base + ENV_INDEX] = i as f64;
        self.st.env[base + ENV_COUNT] = n as f64;
        Ok(())
    }

    fn restore_index(&mut self, index: f64, count: f64) {
        let base = self.top.env;
        self.st.env[base + ENV_INDEX] = index;
        self.st.env[base + ENV_COUNT] = count;
    }

    fn emit(&mut self, rule: &'g RuleCode, p: Prim) -> Result<(), Stop> {
        let prim = match p {
            Prim::Box => Primitive::Box,
            Prim::Cylinder => Primitive::Frustum { top: 1.0 },
            Prim::Cone => Primitive::Frustum { top: 0.0 },
            Prim::Sphere => Primitive::Sphere,
            Prim::Frustum(e) => Primitive::Frustum { top: self.num(rule, e, "a frustum's top ratio")?.max(0.0) as f32 },
            Prim::Taper(e) => Primitive::TaperedBox { top: self.num(rule, e, "a taper ratio")?.max(0.0) as f32 },
            Prim::Mesh(m) => Primitive::Mesh(m),
        };
        let t = self.count_emission()?;
        self.mode.emit(self.g, t, prim, self.cur.tag());
        Ok(())
    }

    #[cold]
    fn placement_overflow(&self) -> Stop {
        let sym = &self.g.graph.symbols[self.top.sym as usize].name;
        let size = self.cur.size;
        ExpressError::Eval(format!("rule `{sym}`: a primitive's placement overflows (size {size:?})")).into()
    }

    /// Runs the child of `slot` that the invocation at `site` expresses
    /// (see [`Op::Invoke`]): an invocation that runs again (in every face,
    /// tile or piece of a component split, repeat or split) re-expresses
    /// its implicit slot's one gene, or takes a declared slot's next link,
    /// back to its first once all are used; nothing is left out.
    fn invoke(&mut self, rule: &'g RuleCode, slot: u32, args: u32, nargs: u32, site: u32) -> Result<(), Stop> {
        let args_from = self.st.args.len();
        for a in 0..nargs {
            let v = self.eval(rule, args + a)?;
            self.st.args.push(v);
        }
        let s = &rule.slots[slot as usize];
        if s.max == 0 {
            self.st.args.truncate(args_from);
            return Ok(());
        }
        let k = if site == COUNTED {
            let counter = self.top.counters + slot as usize;
            let k = self.st.counters[counter];
            self.st.counters[counter] = k.saturating_add(1);
            if k < s.max { k } else { k % s.max }
        } else {
            site.min(s.max - 1)
        };
        let (gene, depth) = (self.top.gene, self.top.depth);
        let Some(child) = self.mode.touch(gene, (s.link + k) as usize, s, depth + 1)? else {
            self.st.args.truncate(args_from);
            return Ok(());
        };
        if depth + 1 > self.limits.max_depth {
            return Err(self.mode.limit(LimitKind::Depth, &self.limits));
        }
        let (callee, rule) = enter(self.g, self.mode.genome(), &mut self.st, child, depth + 1, args_from);
        // The callee starts in the caller's scope; only the tag changes.
        self.st.frames.push(std::mem::replace(&mut self.top, callee));
        self.st.caller_scopes.push(self.cur);
        self.cur.set_tag(rule.tag);
        self.rule = rule;
        Ok(())
    }
}

/// Sets up gene `gene` at `depth`: its env (built-ins,
/// arguments from `st.args[args_from..]`, which are consumed, and parameter
/// values) and its slot counters.
#[inline(always)]
fn enter<'g>(
    g: &'g ShapeGrammar,
    genome: &Genome,
    st: &mut Stacks,
    gene: GenePos,
    depth: usize,
    args_from: usize,
) -> (Frame, &'g RuleCode) {
    let gene_ref = genome.gene(gene);
    let sym = gene_ref.symbol();
    let rule = &g.rules[sym as usize];
    let env = st.env.len();
    st.env.extend_from_slice(&rule.env_init);
    let a = env + rule.arg_base as usize;
    for i in 0..rule.n_args as usize {
        st.env[a + i] = st.args.get(args_from + i).copied().unwrap_or(0.0);
    }
    st.args.truncate(args_from);
    // Values beyond the env are dropped (a validated genome has none).
    if let Some(slots) = st.env.get_mut(env + rule.param_base as usize..) {
        for (i, slot) in slots.iter_mut().take(gene_ref.param_len()).enumerate() {
            *slot = gene_ref.param(i);
        }
    }
    st.env[env + ENV_DEPTH] = depth as f64;
    st.env[env + ENV_INDEX] = 0.0;
    st.env[env + ENV_COUNT] = 1.0;
    let lot = g.start_props.to_array();
    st.env[env + ENV_LOT..env + ENV_LOT + lot.len()].copy_from_slice(&lot);
    let counters = st.counters.len();
    st.counters.extend(std::iter::repeat_n(0, rule.slots.len()));
    (Frame { sym, gene, pc: 0, depth, env, counters }, rule)
}
