//! Compiles one symbol (a rule, or one instance of a template rule): its
//! parameters and slots for the generator graph, and its body into flat
//! operations.
//!
//! This module holds the shared state, expressions and statements;
//! [`decl`] the declarations (parameters, slots, implicit slots, `alt`
//! parameters) and [`ops`] the operations and invocations.

mod decl;
mod ops;

use crate::ast::*;
use crate::builtins::BUILTINS;
use crate::program::*;
use genform_core::expr::{Ast, Node, Program, Scope, did_you_mean};
use genform_core::{Diagnostic, Distribution, ParamSpec, SlotSpec, Span, SymbolSpec};
use std::cell::RefCell;
use std::sync::Arc;

/// Operations (statement names with a built-in meaning).
pub(crate) const OPS: &[&str] = &[
    "translate",
    "rotate",
    "size",
    "scale",
    "tag",
    "color",
    "texture",
    "box",
    "cylinder",
    "cone",
    "sphere",
    "frustum",
    "taper_box",
    "mesh",
    "insert",
    "lot",
    "extrude",
    "taper",
    "shape",
    "roof_gable",
    "roof_hip",
    "roof_pyramid",
    "roof_shed",
    "roof_ridge",
];
/// Statement keywords.
pub(crate) const KEYWORDS: &[&str] =
    &["param", "slot", "let", "if", "else", "alt", "mirror", "split", "repeat", "comp"];
/// Names that the expression language already gives a value.
const EXPR_CONSTANTS: &[&str] = &["pi", "PI", "tau", "e", "true", "false"];
/// Distributions a `param` may use.
const DISTRIBUTIONS: &[&str] = &["uniform", "normal", "int", "choice"];
/// Most links one slot may declare.
const MAX_SLOT_COUNT: f64 = 65_535.0;

impl Globals {
    /// The index of asset `i` fitted to the unit cube (CGA's `i()`): its
    /// bounding box centred and stretched to [−0.5, 0.5] on every axis it
    /// extends along (a flat asset stays flat, centred), so the scope's
    /// size is the inserted asset's size. Made once per asset, kept beside
    /// the declared ones under a name no declaration can take.
    pub fn fitted_mesh(&mut self, i: usize) -> usize {
        let key = format!("{} (fitted)", self.meshes[i].0);
        if let Some(j) = self.meshes.iter().position(|(n, _)| *n == key) {
            return j;
        }
        let mut fit = (*self.meshes[i].1).clone();
        if let Some((lo, hi)) = fit.bounds() {
            let (c, e) = ((lo + hi) * 0.5, hi - lo);
            let scale = glam::Vec3::select(e.cmpgt(glam::Vec3::ZERO), e.recip(), glam::Vec3::ONE);
            for p in &mut fit.positions {
                *p = (*p - c) * scale;
            }
        }
        self.meshes.push((key, Arc::new(fit)));
        self.meshes.len() - 1
    }
}

/// One texture of `texture("file", w, h)`: the file as written, where,
/// and the size of one copy of the image in world units.
pub(crate) struct TextureUse {
    pub path: String,
    pub span: Span,
    pub size: [f64; 2],
}

/// A source rule as the compiler sees it.
pub(crate) struct RuleInfo {
    pub name: String,
    /// `[lo, hi)` of a template rule.
    pub range: Option<(i64, i64)>,
    /// Symbol id of the first instance.
    pub first: u32,
    pub n_args: usize,
    pub arg_names: Vec<String>,
}

/// What every symbol compilation shares.
pub(crate) struct Globals {
    pub consts: Vec<(String, f64)>,
    pub rules: Vec<RuleInfo>,
    pub meshes: Vec<(String, Arc<genform_core::Mesh>)>,
    pub tags: Vec<String>,
    /// Which of `tags` a rule or a `tag(…)` gives (the others are only
    /// named by occlusion queries, see [`Globals::check_query_tags`]).
    pub tags_given: Vec<bool>,
    /// Tags named by occlusion queries: name, the call, its position.
    pub query_tags: Vec<(String, String, Span)>,
    /// The colours of `color(…)`, `#rrggbb` in lower case.
    pub colors: Vec<String>,
    /// The textures of `texture(…)`, each (file, size) once, in order of
    /// first use.
    pub textures: Vec<TextureUse>,
    /// Tags of textured shapes (`wall@brick`): the name, the tag without
    /// the texture (`wall`) and the texture; see [`Globals::textured_tags`].
    pub textured: Vec<(String, String, u32)>,
    /// `0` compiled once, standing in for expressions that failed.
    pub zero: Program,
}

impl Globals {
    pub fn rule(&self, name: &str) -> Option<usize> {
        self.rules.iter().position(|r| r.name == name)
    }

    /// The id of tag `name`, which a rule or a `tag(…)` gives.
    pub fn intern_tag(&mut self, name: &str) -> u32 {
        let i = self.tag_id(name);
        self.tags_given[i as usize] = true;
        i
    }

    fn tag_id(&mut self, name: &str) -> u32 {
        if let Some(i) = self.tags.iter().position(|t| t == name) {
            return i as u32;
        }
        self.tags.push(name.to_string());
        self.tags_given.push(false);
        (self.tags.len() - 1) as u32
    }

    /// The id of tag `name` named by occlusion query `call` at `at`; it is
    /// checked once every rule is compiled (a `tag(…)` may come later in
    /// the file).
    fn query_tag(&mut self, name: &str, call: String, at: Span) -> u32 {
        self.query_tags.push((name.to_string(), call, at));
        self.tag_id(name)
    }

    /// Makes the tags of textured shapes, before [`Globals::color_tags`]
    /// (so that every textured tag gets its coloured variants): for every
    /// tag `name` or `name#rrggbb` and every texture, `name@<texture>` (or
    /// `name@<texture>#rrggbb`), `names` being the textures' short names.
    /// Nothing when no rule says `texture(…)`, so grammars without
    /// textures keep exactly their tags.
    pub fn textured_tags(&mut self, names: &[String]) {
        if names.is_empty() {
            return;
        }
        let tags = self.tags.clone();
        for t in &tags {
            let plain = base_tag(t);
            let colour = &t[plain.len()..];
            for (k, n) in names.iter().enumerate() {
                let textured = format!("{plain}@{n}");
                if !self.textured.iter().any(|(x, _, _)| *x == textured) {
                    self.textured.push((textured.clone(), plain.to_string(), k as u32));
                }
                self.intern_tag(&format!("{textured}{colour}"));
            }
        }
    }

    /// Once every tag is made: for each texture, the tag each tag becomes
    /// under `texture(…)` (the same name, colour kept, that texture instead
    /// of any other), and each tag's texture. Adds no tag: a name that is
    /// missing (a tag only occlusion queries name) maps to itself.
    pub fn texture_tables(&self, textures: usize) -> (Vec<Vec<u32>>, Vec<Option<u32>>) {
        if textures == 0 {
            return (Vec::new(), Vec::new());
        }
        let parts = |t: &str| -> (String, Option<u32>, String) {
            let b = base_tag(t);
            let colour = t[b.len()..].to_string();
            match self.textured.iter().find(|(x, _, _)| x == b) {
                Some((_, plain, k)) => (plain.clone(), Some(*k), colour),
                None => (b.to_string(), None, colour),
            }
        };
        let split: Vec<_> = self.tags.iter().map(|t| parts(t)).collect();
        let of = split.iter().map(|(_, k, _)| *k).collect();
        let table = (0..textures)
            .map(|k| {
                let k = k as u32;
                split
                    .iter()
                    .enumerate()
                    .map(|(i, (plain, _, colour))| {
                        let want = match self.textured.iter().find(|(_, p, x)| p == plain && *x == k) {
                            Some((name, _, _)) => format!("{name}{colour}"),
                            None => return i as u32,
                        };
                        self.tags.iter().position(|t| *t == want).map_or(i as u32, |j| j as u32)
                    })
                    .collect()
            })
            .collect();
        (table, of)
    }

    /// For each colour of `color(…)`, the tag each tag becomes: its name
    /// without a `#rrggbb` suffix, then the colour (exporters colour a tag
    /// named `name#rrggbb` exactly so). Interns what it needs.
    pub fn color_tags(&mut self) -> Vec<Vec<u32>> {
        if self.colors.is_empty() {
            return Vec::new();
        }
        let bases: Vec<String> = self.tags.iter().map(|t| base_tag(t).to_string()).collect();
        let colors = self.colors.clone();
        for b in &bases {
            for c in &colors {
                self.intern_tag(&format!("{b}{c}"));
            }
        }
        // Interning added tags whose bases are among `bases`: every
        // combination already exists, so this lookup adds nothing.
        let all: Vec<String> = self.tags.iter().map(|t| base_tag(t).to_string()).collect();
        colors.iter().map(|c| all.iter().map(|b| self.tag_id(&format!("{b}{c}"))).collect()).collect()
    }

    /// Each tag's tag without a colour suffix or texture (itself when it
    /// has neither), which occlusion queries name.
    pub fn base_tags(&mut self) -> Vec<u32> {
        let plain = |b: &str| match self.textured.iter().find(|(x, _, _)| x == b) {
            Some((_, p, _)) => p.clone(),
            None => b.to_string(),
        };
        let bases: Vec<String> = self.tags.iter().map(|t| plain(base_tag(t))).collect();
        bases.iter().map(|b| self.tag_id(b)).collect()
    }

    /// Errors for query tags that no rule and no `tag(…)` gives.
    pub fn check_query_tags(&self, errors: &mut Vec<Diagnostic>) {
        for (name, call, at) in &self.query_tags {
            let given = self.tags.iter().zip(&self.tags_given).any(|(t, g)| *g && t == name);
            if given || self.rule(name).is_some() {
                continue;
            }
            let fname = call.split('(').next().unwrap_or_default();
            let known = self
                .rules
                .iter()
                .map(|r| r.name.as_str())
                .chain(self.tags.iter().zip(&self.tags_given).filter(|(_, g)| **g).map(|(t, _)| t.as_str()));
            let d = Diagnostic::error(*at, format!("`{call}`: no rule or tag is called `{name}`"));
            errors.push(match did_you_mean(name, known) {
                Some(s) => d.with_hint(format!("did you mean `{fname}({s})`?")),
                None => d.with_hint(format!(
                    "`{fname}` takes a rule name or a tag given with `tag(\"…\")`, or nothing for any occluder"
                )),
            });
        }
    }
}

/// A tag name without its `#rrggbb` colour suffix.
pub(crate) fn base_tag(t: &str) -> &str {
    match t.rsplit_once('#') {
        Some((b, c)) if c.len() == 6 && c.bytes().all(|x| x.is_ascii_hexdigit()) => b,
        _ => t,
    }
}

/// Name of a template instance.
pub(crate) fn instance_name(rule: &str, index: i64) -> String {
    format!("{rule}<{index}>")
}

/// Names known at compile time: constants and the template index.
pub(crate) struct ConstScope<'a> {
    pub consts: &'a [(String, f64)],
    pub template: Option<(&'a str, f64)>,
}

impl Scope for ConstScope<'_> {
    fn variable(&self, name: &str) -> Option<u32> {
        if let Some((t, _)) = self.template
            && t == name
        {
            return Some(self.consts.len() as u32);
        }
        self.consts.iter().rposition(|(n, _)| n == name).map(|i| i as u32)
    }
    fn names(&self) -> Vec<String> {
        let mut v: Vec<String> = self.consts.iter().map(|(n, _)| n.clone()).collect();
        v.extend(self.template.map(|(t, _)| t.to_string()));
        v
    }
}

/// Evaluates an expression that must be known when the grammar is compiled.
pub(crate) fn eval_const(e: &ExprSrc, scope: &ConstScope<'_>, what: &str, errors: &mut Vec<Diagnostic>) -> Option<f64> {
    let prog = match genform_core::expr::compile(&e.ast, scope) {
        Ok(p) => p,
        Err(ds) => {
            for d in ds {
                let unknown = d.message.starts_with("unknown name");
                let mut d = d.shifted(e.offset);
                if unknown {
                    d = d.with_hint(format!(
                        "{what} must be known when the grammar is compiled: use numbers, `const`s and the template index"
                    ));
                }
                errors.push(d);
            }
            return None;
        }
    };
    if prog.uses_rng() {
        errors.push(random_error(e.span()));
        return None;
    }
    let mut env: Vec<f64> = scope.consts.iter().map(|(_, v)| *v).collect();
    env.push(scope.template.map_or(0.0, |(_, v)| v));
    let v = prog.eval(&env);
    if !v.is_finite() {
        errors.push(Diagnostic::error(e.span(), format!("{what} is not a finite number (it is {v})")));
        return None;
    }
    Some(v)
}

fn random_error(span: Span) -> Diagnostic {
    Diagnostic::error(span, "random functions are not allowed in shape grammars")
        .with_hint("randomness comes from `param`s, which are the genes optimizers choose")
}

/// Why a name cannot be declared by the user, if it cannot.
pub(crate) fn reserved(name: &str) -> Option<&'static str> {
    if BUILTINS.contains(&name) || name == "lot" {
        Some("a built-in variable")
    } else if EXPR_CONSTANTS.contains(&name) {
        Some("a built-in constant")
    } else {
        None
    }
}

/// A slot of the symbol being compiled, including dropped ones.
struct LocalSlot {
    name: String,
    /// Index in the graph's slot list; `None` when dropped.
    graph: Option<u32>,
    has_env: u32,
    /// Source rule of the target (for argument checks).
    rule: usize,
    /// Implicit slots count their invocation sites; each site owns one link.
    implicit: bool,
}

/// How a call statement resolved.
#[derive(Clone, Copy)]
enum CallKind {
    Op,
    /// A local slot and the invocation's site: its own link of an
    /// implicit slot, or [`COUNTED`] for a declared one.
    Slot(usize, u32),
    /// Already reported.
    Bad,
}

struct BodyScope<'s> {
    names: &'s [(String, u32)],
    lets: &'s [(String, u32)],
    slots: &'s [LocalSlot],
    bad_has: RefCell<Vec<String>>,
    /// Occlusion queries by their call text (`inside(Wing)`, `touches()`).
    queries: &'s [(String, u32, Query)],
}

impl Scope for BodyScope<'_> {
    fn variable(&self, name: &str) -> Option<u32> {
        if let Some((_, i, _)) = self.queries.iter().find(|(k, _, _)| k == name) {
            return Some(*i);
        }
        if let Some((_, i)) = self.lets.iter().rev().find(|(n, _)| n == name) {
            return Some(*i);
        }
        if let Some((_, i)) = self.names.iter().rev().find(|(n, _)| n == name) {
            return Some(*i);
        }
        if let Some(inner) = name.strip_prefix("has(").and_then(|s| s.strip_suffix(')')) {
            if let Some(s) = self.slots.iter().find(|s| s.name == inner) {
                return Some(s.has_env);
            }
            // Reported by the caller with a better message than "unknown function".
            self.bad_has.borrow_mut().push(inner.to_string());
            return Some(0);
        }
        None
    }
    fn names(&self) -> Vec<String> {
        let mut v: Vec<String> = self.lets.iter().chain(self.names).map(|(n, _)| n.clone()).collect();
        v.extend(self.slots.iter().map(|s| format!("has({})", s.name)));
        v
    }
}

/// The state of compiling one symbol: a rule, or one instance (`index`) of a template rule.
pub(crate) struct SymbolCx<'a> {
    g: &'a mut Globals,
    rule: &'a Rule,
    sym_name: String,
    index: Option<i64>,
    errors: &'a mut Vec<Diagnostic>,
    names: Vec<(String, u32)>,
    lets: Vec<(String, u32)>,
    env_init: Vec<f64>,
    params: Vec<ParamSpec>,
    /// Env index of each `alt`'s hidden parameter, in source order.
    alt_envs: Vec<u32>,
    alt_next: usize,
    slots: Vec<LocalSlot>,
    graph_slots: Vec<SlotSpec>,
    calls: Vec<(u32, CallKind)>,
    code: Vec<Op>,
    exprs: Vec<Expr>,
    tables: Vec<Vec<u32>>,
    pieces: Vec<(u32, SizeKind)>,
    comps: Vec<(u8, u64)>,
    spans: Vec<Span>,
    emits: bool,
    /// Compiling the roof or taper of a [`CompKind::Solid`] split.
    solid_faces: bool,
    /// Occlusion queries met so far: call text, env index, query.
    queries: Vec<(String, u32, Query)>,
}

impl<'a> SymbolCx<'a> {
    pub(crate) fn new(g: &'a mut Globals, rule: &'a Rule, index: Option<i64>, errors: &'a mut Vec<Diagnostic>) -> Self {
        let sym_name = match index {
            Some(i) => instance_name(&rule.name, i),
            None => rule.name.clone(),
        };
        SymbolCx {
            g,
            rule,
            sym_name,
            index,
            errors,
            names: Vec::new(),
            lets: Vec::new(),
            env_init: Vec::new(),
            params: Vec::new(),
            alt_envs: Vec::new(),
            alt_next: 0,
            slots: Vec::new(),
            graph_slots: Vec::new(),
            calls: Vec::new(),
            code: Vec::new(),
            exprs: Vec::new(),
            tables: Vec::new(),
            pieces: Vec::new(),
            comps: Vec::new(),
            spans: Vec::new(),
            emits: false,
            solid_faces: false,
            queries: Vec::new(),
        }
    }

    fn err(&mut self, span: Span, msg: impl Into<String>) {
        self.errors.push(Diagnostic::error(span, msg));
    }

    fn new_env(&mut self, name: Option<&str>, init: f64) -> u32 {
        let i = self.env_init.len() as u32;
        self.env_init.push(init);
        if let Some(n) = name {
            self.names.push((n.to_string(), i));
        }
        i
    }

    fn eval_const(&mut self, e: &ExprSrc, what: &str) -> Option<f64> {
        let template = match (&self.rule.template, self.index) {
            (Some(t), Some(i)) => Some((t.var.as_str(), i as f64)),
            _ => None,
        };
        let scope = ConstScope { consts: &self.g.consts, template };
        eval_const(e, &scope, what, self.errors)
    }

    /// Checks that a user name can be declared here.
    fn declare_ok(&mut self, name: &str, span: Span, what: &str) -> bool {
        if let Some(why) = reserved(name) {
            self.err(span, format!("`{name}` is {why} and cannot name a {what}"));
            return false;
        }
        if self.names.iter().any(|(n, _)| n == name || n.strip_prefix(name).is_some_and(|r| r.starts_with('.'))) {
            let d = Diagnostic::error(span, format!("`{name}` is defined twice in rule `{}`", self.rule.name))
                .with_hint("parameters, arguments, constants and the template index share one namespace");
            self.errors.push(d);
            return false;
        }
        true
    }

    /// Compiles the symbol. Returns its graph node and code.
    pub(crate) fn compile(mut self) -> (SymbolSpec, RuleCode) {
        // Built-ins, constants, the template index and the arguments.
        for b in BUILTINS {
            self.new_env(Some(b), 0.0);
        }
        let consts = self.g.consts.clone();
        for (n, v) in &consts {
            self.new_env(Some(n), *v);
        }
        if let (Some(t), Some(i)) = (&self.rule.template, self.index)
            && self.declare_ok(&t.var, t.var_span, "template index")
        {
            self.new_env(Some(&t.var), i as f64);
        }
        let arg_base = self.env_init.len() as u32;
        for (a, span) in &self.rule.args {
            if self.declare_ok(a, *span, "argument") {
                self.new_env(Some(a), 0.0);
            } else {
                self.new_env(None, 0.0);
            }
        }
        let n_args = self.rule.args.len() as u32;

        // Declarations: parameters and slots at the top level, then the
        // hidden `alt` parameters and implicit slots found anywhere.
        let param_base = self.env_init.len() as u32;
        let body = &self.rule.body;
        for s in body {
            if let Stmt::Param(p) = s {
                self.param(p);
            }
        }
        for s in body {
            if let Stmt::Slot(sd) = s {
                self.slot(sd);
            }
        }
        self.prepass(body, true);
        for i in 0..self.slots.len() {
            self.slots[i].has_env = self.new_env(None, 0.0);
        }

        // The body.
        self.stmts(body);

        let slots_code: Vec<SlotCode> = {
            let mut link = 0u32;
            self.graph_slots
                .iter()
                .map(|s| {
                    let c = SlotCode { link, max: s.max_count, target: s.target, prob: s.prob };
                    link = link.saturating_add(s.max_count);
                    c
                })
                .collect()
        };
        let tag = self.g.intern_tag(&self.rule.name);
        let spec = SymbolSpec {
            name: self.sym_name.clone(),
            params: std::mem::take(&mut self.params),
            slots: std::mem::take(&mut self.graph_slots),
            emits_geometry: self.emits,
        };
        let code = RuleCode {
            code: self.code,
            fast: self.exprs.iter().map(|e| e.fast).collect(),
            exprs: self.exprs,
            tables: self.tables,
            pieces: self.pieces,
            comps: self.comps,
            spans: self.spans,
            env_init: self.env_init,
            arg_base,
            n_args,
            param_base,
            slots: slots_code,
            tag,
        };
        (spec, code)
    }

    // ---- expressions --------------------------------------------------

    fn expr(&mut self, e: &ExprSrc) -> u32 {
        self.find_queries(&e.ast, e.offset);
        let scope = BodyScope {
            names: &self.names,
            lets: &self.lets,
            slots: &self.slots,
            bad_has: RefCell::new(vec![]),
            queries: &self.queries,
        };
        let res = genform_core::expr::compile(&e.ast, &scope);
        let bad = scope.bad_has.into_inner();
        let mut prog = self.g.zero.clone();
        for b in bad {
            let mut d = Diagnostic::error(e.span(), format!("`has({b})`: rule `{}` has no slot `{b}`", self.rule.name));
            d = match did_you_mean(&b, self.slots.iter().map(|s| s.name.as_str())) {
                Some(s) => d.with_hint(format!("did you mean `has({s})`?")),
                None => d.with_hint("`has` takes a slot of this rule: a declared `slot` or an invoked rule"),
            };
            self.errors.push(d);
        }
        match res {
            Ok(p) if p.uses_rng() => self.errors.push(random_error(e.span())),
            Ok(p) => prog = p,
            Err(ds) => self.errors.extend(ds.into_iter().map(|d| d.shifted(e.offset))),
        }
        let mut has: Vec<(u32, u32)> = Vec::new();
        for i in prog.loads() {
            if let Some(s) = self.slots.iter().find(|s| s.has_env == i && s.graph.is_some()) {
                let pair = (i, s.graph.unwrap_or_default());
                if !has.contains(&pair) {
                    has.push(pair);
                }
            }
        }
        let loads: Vec<u32> = prog.loads().collect();
        let queries = self.queries.iter().filter(|(_, i, _)| loads.contains(i)).map(|&(_, i, q)| (i, q)).collect();
        self.exprs.push(Expr::with_queries(prog, has, queries, e.span()));
        (self.exprs.len() - 1) as u32
    }

    /// Gives each occlusion query in `ast` (`inside()`, `overlaps(Wing)`, …)
    /// an env slot the interpreter fills before evaluating. A name, when
    /// given, must be a rule or a tag: occluders are filtered by the tag
    /// they were placed with.
    fn find_queries(&mut self, ast: &Ast, offset: usize) {
        let mut stack = vec![ast];
        while let Some(a) = stack.pop() {
            match &a.kind {
                Node::Call(name, name_span, args) => {
                    let arg = match args.as_slice() {
                        [] => Some(None),
                        [Ast { kind: Node::Var(t), .. }] => Some(Some(t.as_str())),
                        _ => None,
                    };
                    match (QueryKind::from_name(name), arg) {
                        (Some(kind), Some(tag)) => self.query(name, kind, tag, name_span.shift(offset)),
                        _ => stack.extend(args),
                    }
                }
                Node::Unary(_, x) => stack.push(x),
                Node::Binary(_, x, y) => stack.extend([&**x, &**y]),
                Node::Cond(c, x, y) => stack.extend([&**c, &**x, &**y]),
                Node::Num(_) | Node::Var(_) => {}
            }
        }
    }

    fn query(&mut self, name: &str, kind: QueryKind, tag: Option<&str>, at: Span) {
        let key = format!("{name}({})", tag.unwrap_or(""));
        if self.queries.iter().any(|(k, _, _)| *k == key) {
            return;
        }
        let tag = tag.map(|t| self.g.query_tag(base_tag(t), key.clone(), at));
        let env = self.new_env(None, 0.0);
        self.queries.push((key, env, Query { kind, tag }));
    }

    /// An expression for a parameter component (`size.x`), or 0.
    fn component_expr(&mut self, name: &str, span: Span) -> u32 {
        let prog = genform_core::expr::parse(name)
            .ok()
            .and_then(|ast| {
                let idx = self.names.iter().rev().find(|(n, _)| n == name).map(|(_, i)| *i)?;
                genform_core::expr::compile(&ast, &IndexScope { name, idx }).ok()
            })
            .unwrap_or_else(|| self.g.zero.clone());
        self.exprs.push(Expr::new(prog, Vec::new(), span));
        (self.exprs.len() - 1) as u32
    }

    // ---- statements ---------------------------------------------------

    fn stmts(&mut self, body: &[Stmt]) {
        let saved = self.lets.len();
        for s in body {
            self.stmt(s);
        }
        self.lets.truncate(saved);
    }

    /// Records where a fallible operation is written.
    fn span_index(&mut self, span: Span) -> u32 {
        self.spans.push(span);
        (self.spans.len() - 1) as u32
    }

    fn here(&self) -> u32 {
        self.code.len() as u32
    }

    fn stmt(&mut self, s: &Stmt) {
        match s {
            Stmt::Param(_) | Stmt::Slot(_) => {}
            Stmt::Let { name, span, value } => {
                let e = self.expr(value);
                if let Some(why) = reserved(name) {
                    self.err(*span, format!("`{name}` is {why} and cannot be redefined with `let`"));
                }
                let idx = self.new_env(None, 0.0);
                self.lets.push((name.clone(), idx));
                self.code.push(Op::Let(idx, e));
            }
            Stmt::If { cond, then, els } => {
                let c = self.expr(cond);
                let j = self.code.len();
                self.code.push(Op::JumpUnless(c, 0));
                self.stmts(then);
                if els.is_empty() {
                    self.code[j] = Op::JumpUnless(c, self.here());
                } else {
                    let j2 = self.code.len();
                    self.code.push(Op::Jump(0));
                    self.code[j] = Op::JumpUnless(c, self.here());
                    self.stmts(els);
                    self.code[j2] = Op::Jump(self.here());
                }
            }
            Stmt::Alt { arms, .. } => {
                let env = self.alt_envs.get(self.alt_next).copied().unwrap_or(0);
                self.alt_next += 1;
                let t = self.tables.len();
                self.tables.push(Vec::new());
                self.code.push(Op::Alt { env, table: t as u32 });
                let mut ends = Vec::new();
                for (_, arm) in arms {
                    let start = self.here();
                    self.tables[t].push(start);
                    self.stmts(arm);
                    ends.push(self.code.len());
                    self.code.push(Op::Jump(0));
                }
                let end = self.here();
                for j in ends {
                    self.code[j] = Op::Jump(end);
                }
            }
            Stmt::Mirror { axis, body } => {
                self.code.push(Op::MirrorBegin(axis.index() as u8));
                let start = self.here();
                self.stmts(body);
                self.code.push(Op::MirrorEnd(start));
            }
            Stmt::Split { axis, pieces, area, span } => {
                let first = self.pieces.len() as u32;
                for p in pieces {
                    let e = self.expr(&p.size);
                    let kind = match (p.relative, p.floating) {
                        (true, _) => SizeKind::Relative,
                        (_, true) => SizeKind::Floating,
                        _ => SizeKind::Absolute,
                    };
                    self.pieces.push((e, kind));
                }
                let axis = axis.index() as u8 | if *area { SPLIT_AREA } else { 0 };
                let span = self.span_index(*span);
                self.code.push(Op::SplitBegin { axis, first, n: pieces.len() as u32, span });
                for (k, p) in pieces.iter().enumerate() {
                    self.code.push(Op::Piece(k as u32));
                    self.stmts(&p.body);
                    self.code.push(Op::Pop);
                }
                self.code.push(Op::SplitEnd);
            }
            Stmt::Repeat { axis, tile, body } => {
                let t = self.expr(tile);
                self.code.push(Op::RepeatBegin { axis: axis.index() as u8, tile: t });
                let start = self.here();
                self.stmts(body);
                self.code.push(Op::RepeatNext(start));
            }
            Stmt::Comp { span, kind, args, arms, solid } => {
                if let Some(solid) = solid {
                    // The roof's op keeps its solid for the split's faces.
                    self.solid_faces = true;
                    self.op(&solid.0, Some(&solid.1));
                    self.solid_faces = false;
                }
                let (name, want) = kind.name();
                // A setback's per-edge distances follow its fixed arguments.
                let fits = if *kind == CompKind::Setback { args.len() >= want } else { args.len() == want };
                if !fits {
                    let form = match kind {
                        CompKind::Offset => "offset(distance)",
                        CompKind::Setback => "setback(distance)",
                        CompKind::ShapeL => "shapeL(front, left)",
                        CompKind::ShapeU => "shapeU(front, left, right)",
                        CompKind::ShapeO => "shapeO(front, right, back, left)",
                        CompKind::Faces | CompKind::Edges | CompKind::Vertices | CompKind::Solid => name,
                    };
                    self.arity(name, *span, form, args.len());
                }
                // The arguments are consecutive expressions.
                let exprs: Vec<u32> = args.iter().map(|a| self.expr(a)).collect();
                let args = exprs.first().copied().unwrap_or(0);
                let first = self.comps.len() as u32;
                self.comps.extend(arms.iter().map(|a| (a.mask, a.indices)));
                let at = self.span_index(*span);
                self.code.push(Op::CompBegin { kind: *kind as u8, args, first, n: arms.len() as u32, span: at });
                for (k, arm) in arms.iter().enumerate() {
                    let j = self.code.len();
                    self.code.push(Op::CompArm { arm: k as u32, end: 0 });
                    let body = self.here();
                    self.stmts(&arm.body);
                    self.code.push(Op::CompNext { arm: k as u32, body });
                    self.code[j] = Op::CompArm { arm: k as u32, end: self.here() };
                }
                self.code.push(Op::CompEnd);
            }
            Stmt::Scoped(body) => {
                self.code.push(Op::Push);
                self.stmts(body);
                self.code.push(Op::Pop);
            }
            Stmt::Call { target, args, .. } => {
                let kind = self.calls.iter().find(|(s, _)| *s == target.span.start).map(|(_, k)| *k);
                match kind {
                    Some(CallKind::Op) => self.op(target, args.as_deref()),
                    Some(CallKind::Slot(i, site)) => self.invoke(i, site, target, args.as_deref()),
                    Some(CallKind::Bad) | None => {}
                }
            }
        }
    }
}

/// A scope with exactly one name.
struct IndexScope<'a> {
    name: &'a str,
    idx: u32,
}

impl Scope for IndexScope<'_> {
    fn variable(&self, name: &str) -> Option<u32> {
        (name == self.name).then_some(self.idx)
    }
}
