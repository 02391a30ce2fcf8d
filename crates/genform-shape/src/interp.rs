//! The interpreter: runs the operation programs of the genes of a genome,
//! from the root, with scope state, and emits primitives.
//!
//! All state lives in explicit stacks (frames, envs, saved scopes, slot
//! counters, loops), so a deep derivation never deepens the Rust stack. The
//! same interpreter serves expression ([`ExpressMode`]) and prior sampling
//! ([`crate::sample::SampleMode`]); the mode decides what a link holds.

use crate::ShapeGrammar;
use crate::program::*;
use genform_core::genome::GenePos;
use genform_core::{ExpressError, Genome, Instance, LimitKind, Limits, Primitive, Scene};
use glam::{Affine3A, DAffine3, DMat3, DVec3};

/// Operations one run may execute per unit of its primitive and gene
/// limits, so grammars that loop without emitting (huge `repeat`s, nested
/// `mirror`s re-running subtrees) still stop.
const OPS_PER_UNIT: u64 = 256;
/// Operations every run may execute regardless of limits.
const OPS_BASE: u64 = 1_000_000;

/// Why a run stopped early.
pub(crate) enum Stop {
    /// A real error.
    Error(ExpressError),
    /// Sampling reached a limit: keep what was grown.
    Truncate(LimitKind),
}

impl From<ExpressError> for Stop {
    fn from(e: ExpressError) -> Self {
        Stop::Error(e)
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
    /// What hitting a limit means in this mode.
    fn limit(&self, kind: LimitKind, limits: &Limits) -> Stop;
}

/// The scope: frame (rotation + position of the centre) and size.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct ScopeState {
    pub frame: DAffine3,
    pub size: DVec3,
    pub tag: u32,
}

fn axis_vec(axis: u8) -> DVec3 {
    match axis {
        0 => DVec3::X,
        1 => DVec3::Y,
        _ => DVec3::Z,
    }
}

impl ScopeState {
    /// Moves in the local frame (rotation only; size is not applied).
    pub fn translate(&mut self, v: DVec3) {
        self.frame.translation += self.frame.matrix3 * v;
    }

    /// Rotates about a local axis (post-multiplication).
    pub fn rotate(&mut self, axis: u8, degrees: f64) {
        let r = match axis {
            0 => DMat3::from_rotation_x(degrees.to_radians()),
            1 => DMat3::from_rotation_y(degrees.to_radians()),
            _ => DMat3::from_rotation_z(degrees.to_radians()),
        };
        self.frame.matrix3 *= r;
    }

    /// Reflects across the local plane normal to `axis`.
    pub fn reflect(&mut self, axis: u8) {
        let mut d = DVec3::ONE;
        d[axis as usize] = -1.0;
        self.frame.matrix3 *= DMat3::from_diagonal(d);
    }

    /// Narrows the scope to the piece centred at `centre` (along `axis`,
    /// relative to the scope centre) of length `len`.
    pub fn piece(&mut self, axis: u8, centre: f64, len: f64) {
        self.translate(axis_vec(axis) * centre);
        self.size[axis as usize] = len;
    }

    /// Unit primitive → world: frame × diag(size).
    pub fn transform(&self) -> Affine3A {
        let m = self.frame.matrix3 * DMat3::from_diagonal(self.size);
        Affine3A::from_mat3_translation(m.as_mat3(), self.frame.translation.as_vec3())
    }
}

/// Express mode: links are read from a finished genome; geometry goes to a Scene.
pub(crate) struct ExpressMode<'a> {
    pub genome: &'a Genome,
    pub scene: &'a mut Scene,
    /// Grammar tag → scene tag (`u32::MAX` until first used).
    pub tags: Vec<u32>,
    /// Grammar mesh → scene mesh.
    pub meshes: Vec<u32>,
}

impl Mode for ExpressMode<'_> {
    fn genome(&self) -> &Genome {
        self.genome
    }

    fn touch(&mut self, gene: GenePos, link: usize, _: &SlotCode, _: usize) -> Result<Option<GenePos>, Stop> {
        Ok(match self.genome.gene(gene).link(link) {
            genform_core::genome::Link::Child(c) => Some(c),
            _ => None,
        })
    }

    fn emit(&mut self, g: &ShapeGrammar, transform: Affine3A, prim: Primitive, tag: u32) {
        let t = tag as usize;
        if self.tags[t] == u32::MAX {
            self.tags[t] = self.scene.tag(&g.tags[t]);
        }
        let primitive = match prim {
            Primitive::Mesh(m) => {
                let m = m as usize;
                if self.meshes[m] == u32::MAX {
                    self.meshes[m] = self.scene.mesh(&g.meshes[m]);
                }
                Primitive::Mesh(self.meshes[m])
            }
            p => p,
        };
        self.scene.instances.push(Instance { transform, primitive, tag: self.tags[t] });
    }

    fn limit(&self, kind: LimitKind, limits: &Limits) -> Stop {
        Stop::Error(ExpressError::Limit { kind, limit: kind.value(limits) })
    }
}

/// One running gene.
struct Frame {
    sym: u32,
    gene: GenePos,
    pc: usize,
    depth: usize,
    /// Start of this frame's env in [`Interp::env`].
    env: usize,
    /// Start of this frame's slot counters.
    counters: usize,
    cur: ScopeState,
}

/// An open `mirror`, `split` or `repeat`.
enum Loop {
    Mirror { axis: u8, second: bool, saved: usize },
    Split { axis: u8, pieces: usize, index: f64, count: f64 },
    Repeat { axis: u8, i: u32, n: u32, len: f64, size: f64, index: f64, count: f64 },
}

/// The interpreter state.
pub(crate) struct Interp<'g, M> {
    g: &'g ShapeGrammar,
    limits: Limits,
    pub mode: M,
    frames: Vec<Frame>,
    env: Vec<f64>,
    scopes: Vec<ScopeState>,
    counters: Vec<u32>,
    saved_counters: Vec<u32>,
    loops: Vec<Loop>,
    pieces: Vec<(f64, f64)>,
    args: Vec<f64>,
    ops: u64,
    budget: u64,
    emitted: usize,
}

impl<'g, M: Mode> Interp<'g, M> {
    pub(crate) fn new(g: &'g ShapeGrammar, limits: &Limits, mode: M) -> Self {
        let units = (limits.max_primitives as u64).saturating_add(limits.max_genes as u64);
        Interp {
            g,
            limits: *limits,
            mode,
            frames: Vec::new(),
            env: Vec::new(),
            scopes: Vec::new(),
            counters: Vec::new(),
            saved_counters: Vec::new(),
            loops: Vec::new(),
            pieces: Vec::new(),
            args: Vec::new(),
            ops: 0,
            budget: units.saturating_mul(OPS_PER_UNIT).saturating_add(OPS_BASE),
            emitted: 0,
        }
    }

    /// Starts gene `gene` at `depth` in scope `cur` with `args`.
    fn push_frame(&mut self, gene: GenePos, depth: usize, mut cur: ScopeState, args_from: usize) {
        let sym = self.mode.genome().gene(gene).symbol();
        let rule = &self.g.rules[sym as usize];
        let env = self.env.len();
        self.env.extend_from_slice(&rule.env_init);
        let a = env + rule.arg_base as usize;
        let n = rule.n_args as usize;
        for i in 0..n {
            self.env[a + i] = self.args.get(args_from + i).copied().unwrap_or(0.0);
        }
        self.args.truncate(args_from);
        let p = env + rule.param_base as usize;
        for (i, v) in self.mode.genome().gene(gene).params().enumerate() {
            if let Some(slot) = self.env.get_mut(p + i) {
                *slot = v;
            }
        }
        self.env[env + ENV_DEPTH] = depth as f64;
        self.env[env + ENV_INDEX] = 0.0;
        self.env[env + ENV_COUNT] = 1.0;
        let counters = self.counters.len();
        self.counters.extend(std::iter::repeat_n(0, rule.slots.len()));
        cur.tag = rule.tag;
        self.frames.push(Frame { sym, gene, pc: 0, depth, env, counters, cur });
    }

    /// Runs the derivation from the genome's root.
    pub(crate) fn run(&mut self) -> Result<(), Stop> {
        let identity = ScopeState { frame: DAffine3::IDENTITY, size: DVec3::ONE, tag: 0 };
        self.push_frame(GenePos(0), 0, identity, 0);
        while let Some(fi) = self.frames.len().checked_sub(1) {
            let f = &self.frames[fi];
            let g: &'g ShapeGrammar = self.g;
            let rule: &'g RuleCode = &g.rules[f.sym as usize];
            if f.pc >= rule.code.len() {
                let f = self.frames.pop().unwrap_or_else(|| unreachable!());
                self.env.truncate(f.env);
                self.counters.truncate(f.counters);
                continue;
            }
            self.ops += 1;
            if self.ops > self.budget {
                return Err(self.mode.limit(LimitKind::Primitives, &self.limits));
            }
            let op = rule.code[f.pc];
            self.frames[fi].pc += 1;
            self.step(fi, rule, op)?;
        }
        Ok(())
    }

    fn cur(&mut self, fi: usize) -> &mut ScopeState {
        &mut self.frames[fi].cur
    }

    /// Evaluates expression `e` of the running rule.
    fn eval(&mut self, fi: usize, rule: &'g RuleCode, e: u32) -> Result<f64, Stop> {
        let ex = &rule.exprs[e as usize];
        let f = &self.frames[fi];
        let base = f.env;
        let size = f.cur.size;
        self.env[base + ENV_SX..base + ENV_SX + 3].copy_from_slice(&size.to_array());
        for &(idx, slot) in &ex.has {
            let v = self.has(fi, rule, slot)?;
            self.env[base + idx as usize] = v;
        }
        Ok(ex.prog.eval(&self.env[base..base + rule.env_init.len()]))
    }

    /// Evaluates a value used as geometry: it must be finite.
    fn num(&mut self, fi: usize, rule: &'g RuleCode, e: u32, what: &str) -> Result<f64, Stop> {
        let v = self.eval(fi, rule, e)?;
        if v.is_finite() {
            return Ok(v);
        }
        let sym = &self.g.graph.symbols[self.frames[fi].sym as usize].name;
        let loc = self.g.file.location(rule.exprs[e as usize].span.start);
        Err(Stop::Error(ExpressError::Eval(format!("{loc}: rule `{sym}`: {what} is not a finite number (it is {v})"))))
    }

    fn vec3(&mut self, fi: usize, rule: &'g RuleCode, e: u32, what: &str) -> Result<DVec3, Stop> {
        Ok(DVec3::new(self.num(fi, rule, e, what)?, self.num(fi, rule, e + 1, what)?, self.num(fi, rule, e + 2, what)?))
    }

    /// `has(slot)`: whether link 0 of the slot holds a child.
    fn has(&mut self, fi: usize, rule: &'g RuleCode, slot: u32) -> Result<f64, Stop> {
        let s = &rule.slots[slot as usize];
        let f = &self.frames[fi];
        let (gene, depth) = (f.gene, f.depth);
        Ok(if self.mode.touch(gene, s.link as usize, s, depth + 1)?.is_some() { 1.0 } else { 0.0 })
    }

    fn step(&mut self, fi: usize, rule: &'g RuleCode, op: Op) -> Result<(), Stop> {
        match op {
            Op::Push => {
                let c = self.frames[fi].cur;
                self.scopes.push(c);
            }
            Op::Pop => {
                if let Some(s) = self.scopes.pop() {
                    self.frames[fi].cur = s;
                }
            }
            Op::Translate(e) => {
                let v = self.vec3(fi, rule, e, "a translation")?;
                self.cur(fi).translate(v);
            }
            Op::Rotate(axis, e) => {
                let a = self.num(fi, rule, e, "a rotation angle")?;
                self.cur(fi).rotate(axis, a);
            }
            Op::Size(e) => {
                let v = self.vec3(fi, rule, e, "a size")?;
                self.cur(fi).size = v;
            }
            Op::Scale(e) => {
                let v = self.vec3(fi, rule, e, "a scale factor")?;
                let c = self.cur(fi);
                let s = c.size * v;
                if !s.is_finite() {
                    return Err(self.overflow(fi, rule, e, "the scaled size"));
                }
                c.size = s;
            }
            Op::Tag(t) => self.cur(fi).tag = t,
            Op::Let(idx, e) => {
                let v = self.eval(fi, rule, e)?;
                let base = self.frames[fi].env;
                self.env[base + idx as usize] = v;
            }
            Op::Emit(p) => self.emit(fi, rule, p)?,
            Op::Invoke { slot, args, nargs } => self.invoke(fi, rule, slot, args, nargs)?,
            Op::JumpUnless(e, t) => {
                let v = self.eval(fi, rule, e)?;
                if v == 0.0 || v.is_nan() {
                    self.frames[fi].pc = t as usize;
                }
            }
            Op::Jump(t) => self.frames[fi].pc = t as usize,
            Op::Alt { env, table } => {
                let v = self.env[self.frames[fi].env + env as usize];
                let targets = &rule.tables[table as usize];
                let k = if v.is_finite() && v >= 0.0 && (v as usize) < targets.len() { v as usize } else { 0 };
                if let Some(t) = targets.get(k) {
                    self.frames[fi].pc = *t as usize;
                }
            }
            Op::MirrorBegin(axis) => {
                let f = &self.frames[fi];
                let saved = self.saved_counters.len();
                let n = rule.slots.len();
                self.saved_counters.extend_from_slice(&self.counters[f.counters..f.counters + n]);
                self.scopes.push(f.cur);
                self.loops.push(Loop::Mirror { axis, second: false, saved });
            }
            Op::MirrorEnd(start) => {
                if let Some(Loop::Mirror { axis, second, saved }) = self.loops.last_mut() {
                    let (axis, saved) = (*axis, *saved);
                    if !*second {
                        *second = true;
                        let mut s = self.scopes.last().copied().unwrap_or(self.frames[fi].cur);
                        s.reflect(axis);
                        let f = &mut self.frames[fi];
                        f.cur = s;
                        f.pc = start as usize;
                        let n = rule.slots.len();
                        let c = f.counters;
                        self.counters[c..c + n].copy_from_slice(&self.saved_counters[saved..saved + n]);
                    } else {
                        if let Some(s) = self.scopes.pop() {
                            self.frames[fi].cur = s;
                        }
                        self.saved_counters.truncate(saved);
                        self.loops.pop();
                    }
                }
            }
            Op::SplitBegin { axis, first, n } => {
                let f = &self.frames[fi];
                let total = f.cur.size[axis as usize];
                let (index, count) = (self.env[f.env + ENV_INDEX], self.env[f.env + ENV_COUNT]);
                let at = self.pieces.len();
                let mut absolute = 0.0;
                let mut weights = 0.0;
                for k in 0..n {
                    let (e, rel) = rule.pieces[(first + k) as usize];
                    let v = self.num(fi, rule, e, "a split size")?.max(0.0);
                    if rel {
                        weights += v;
                    } else {
                        absolute += v;
                    }
                    self.pieces.push((v, if rel { 1.0 } else { 0.0 }));
                }
                let rest = (total - absolute).max(0.0);
                let mut pos = -0.5 * total;
                for p in &mut self.pieces[at..] {
                    let len = if p.1 == 1.0 { if weights > 0.0 { rest * p.0 / weights } else { 0.0 } } else { p.0 };
                    *p = (pos + 0.5 * len, len);
                    pos += len;
                }
                self.loops.push(Loop::Split { axis, pieces: at, index, count });
                let base = self.frames[fi].env;
                self.env[base + ENV_COUNT] = n as f64;
            }
            Op::Piece(k) => {
                if let Some(Loop::Split { axis, pieces, .. }) = self.loops.last() {
                    let (centre, len) = self.pieces[pieces + k as usize];
                    let axis = *axis;
                    let c = self.frames[fi].cur;
                    self.scopes.push(c);
                    self.cur(fi).piece(axis, centre, len);
                    let base = self.frames[fi].env;
                    self.env[base + ENV_INDEX] = k as f64;
                }
            }
            Op::SplitEnd => {
                if let Some(Loop::Split { pieces, index, count, .. }) = self.loops.pop() {
                    self.pieces.truncate(pieces);
                    self.restore_index(fi, index, count);
                }
            }
            Op::RepeatBegin { axis, tile } => {
                let t = self.num(fi, rule, tile, "a repeat tile size")?;
                let f = &self.frames[fi];
                let size = f.cur.size[axis as usize];
                let (index, count) = (self.env[f.env + ENV_INDEX], self.env[f.env + ENV_COUNT]);
                let ratio = size.abs() / t;
                let n = if t > 0.0 && ratio.is_finite() { ratio.round().clamp(1.0, u32::MAX as f64) as u32 } else { 1 };
                let len = size / n as f64;
                self.loops.push(Loop::Repeat { axis, i: 0, n, len, size, index, count });
                self.enter_tile(fi, axis, 0, n, len, size);
            }
            Op::RepeatNext(body) => {
                if let Some(s) = self.scopes.pop() {
                    self.frames[fi].cur = s;
                }
                if let Some(Loop::Repeat { axis, i, n, len, size, index, count }) = self.loops.last_mut() {
                    *i += 1;
                    let (axis, i, n, len, size, index, count) = (*axis, *i, *n, *len, *size, *index, *count);
                    if i < n {
                        self.enter_tile(fi, axis, i, n, len, size);
                        self.frames[fi].pc = body as usize;
                    } else {
                        self.loops.pop();
                        self.restore_index(fi, index, count);
                    }
                }
            }
        }
        Ok(())
    }

    fn overflow(&self, fi: usize, rule: &RuleCode, e: u32, what: &str) -> Stop {
        let sym = &self.g.graph.symbols[self.frames[fi].sym as usize].name;
        let loc = self.g.file.location(rule.exprs[e as usize].span.start);
        Stop::Error(ExpressError::Eval(format!("{loc}: rule `{sym}`: {what} is not a finite number")))
    }

    fn enter_tile(&mut self, fi: usize, axis: u8, i: u32, n: u32, len: f64, size: f64) {
        let c = self.frames[fi].cur;
        self.scopes.push(c);
        let centre = -0.5 * size + (i as f64 + 0.5) * len;
        self.cur(fi).piece(axis, centre, len);
        let base = self.frames[fi].env;
        self.env[base + ENV_INDEX] = i as f64;
        self.env[base + ENV_COUNT] = n as f64;
    }

    fn restore_index(&mut self, fi: usize, index: f64, count: f64) {
        let base = self.frames[fi].env;
        self.env[base + ENV_INDEX] = index;
        self.env[base + ENV_COUNT] = count;
    }

    fn emit(&mut self, fi: usize, rule: &'g RuleCode, p: Prim) -> Result<(), Stop> {
        let prim = match p {
            Prim::Box => Primitive::Box,
            Prim::Cylinder => Primitive::Frustum { top: 1.0 },
            Prim::Cone => Primitive::Frustum { top: 0.0 },
            Prim::Sphere => Primitive::Sphere,
            Prim::Frustum(e) => {
                Primitive::Frustum { top: self.num(fi, rule, e, "a frustum's top ratio")?.max(0.0) as f32 }
            }
            Prim::Taper(e) => Primitive::TaperedBox { top: self.num(fi, rule, e, "a taper ratio")?.max(0.0) as f32 },
            Prim::Mesh(m) => Primitive::Mesh(m),
        };
        if self.emitted >= self.limits.max_primitives {
            return Err(self.mode.limit(LimitKind::Primitives, &self.limits));
        }
        self.emitted += 1;
        let cur = self.frames[fi].cur;
        let t = cur.transform();
        if !t.is_finite() {
            let sym = &self.g.graph.symbols[self.frames[fi].sym as usize].name;
            return Err(Stop::Error(ExpressError::Eval(format!(
                "rule `{sym}`: a primitive's placement overflows (size {:?})",
                cur.size
            ))));
        }
        self.mode.emit(self.g, t, prim, cur.tag);
        Ok(())
    }

    fn invoke(&mut self, fi: usize, rule: &'g RuleCode, slot: u32, args: u32, nargs: u32) -> Result<(), Stop> {
        let args_from = self.args.len();
        for a in 0..nargs {
            let v = self.eval(fi, rule, args + a)?;
            self.args.push(v);
        }
        let s = &rule.slots[slot as usize];
        let f = &self.frames[fi];
        let counter = f.counters + slot as usize;
        let k = self.counters[counter];
        self.counters[counter] = k.saturating_add(1);
        if k >= s.max {
            self.args.truncate(args_from);
            return Ok(());
        }
        let (gene, depth, cur) = (f.gene, f.depth, f.cur);
        let child = self.mode.touch(gene, (s.link + k) as usize, s, depth + 1)?;
        let Some(child) = child else {
            self.args.truncate(args_from);
            return Ok(());
        };
        if depth + 1 > self.limits.max_depth {
            return Err(self.mode.limit(LimitKind::Depth, &self.limits));
        }
        self.push_frame(child, depth + 1, cur, args_from);
        Ok(())
    }
}

/// Expresses `genome` into `scene`.
pub(crate) fn express(
    g: &ShapeGrammar,
    genome: &Genome,
    limits: &Limits,
    scene: &mut Scene,
) -> Result<(), ExpressError> {
    genome.validate(&g.graph)?;
    if genome.len() > limits.max_genes {
        return Err(ExpressError::Limit { kind: LimitKind::Genes, limit: limits.max_genes });
    }
    let mode =
        ExpressMode { genome, scene, tags: vec![u32::MAX; g.tags.len()], meshes: vec![u32::MAX; g.meshes.len()] };
    let mut it = Interp::new(g, limits, mode);
    match it.run() {
        Ok(()) => Ok(()),
        Err(Stop::Error(e)) => Err(e),
        Err(Stop::Truncate(kind)) => Err(ExpressError::Limit { kind, limit: kind.value(limits) }),
    }
}
