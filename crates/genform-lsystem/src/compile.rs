//! From the syntax tree to rule tables: symbols interned, formulas compiled
//! against their production's parameters and the file's constants.

use crate::alphabet::{self, Alphabet, Command, Sym};
use crate::arg::Arg;
use crate::body::{Body, Op};
use crate::ranged::{self, RangedConstant, Recipe};
use crate::rules::{Entry, Rule, Table};
use crate::settings::{Heading, Settings, View};
use crate::string::ModuleString;
use crate::surface::{self, SurfaceAssets};
use crate::syntax::{self, Call, Expr, Pattern, Section, Setting, Stmt};
use genform_core::Mesh;
use genform_core::diag::{Diagnostic, Span};
use genform_core::expr::{self, Program, Scope};
use std::collections::HashMap;
use std::sync::Arc;

/// A compiled L-system.
#[derive(Clone, Debug)]
pub struct LSystem {
    /// Settings from the file's header.
    pub settings: Settings,
    /// Every module symbol the system uses.
    pub alphabet: Alphabet,
    /// The axiom.
    pub axiom: ModuleString,
    pub(crate) productions: Table,
    pub(crate) decomposition: Table,
    pub(crate) interpretation: Table,
    /// Per symbol: skipped when matching contexts.
    pub(crate) ignored: Vec<bool>,
    /// Per symbol: is `[`, is `]`.
    pub(crate) brackets: [Vec<bool>; 2],
    /// The file it was compiled from, to locate rules in run-time errors.
    pub(crate) source: Option<genform_core::SourceFile>,
    /// The global state before the derivation: `iteration` (0), then the
    /// `global` variables' declared values.
    pub(crate) initial_state: Vec<f64>,
    /// Names of the global state's slots (`iteration` first).
    pub(crate) state_names: Vec<String>,
    /// Statements of the Start, StartEach, EndEach and End hooks.
    pub(crate) hooks: [Vec<Op>; 4],
    /// Per symbol: the surface a `~name` module draws, by index into
    /// `surfaces`.
    pub(crate) surface_of: Vec<Option<u32>>,
    /// The meshes of the built-in and declared surfaces.
    pub(crate) surfaces: Vec<Arc<Mesh>>,
    /// The ranged constants (genes of a generator), in file order.
    pub(crate) ranged: Vec<RangedConstant>,
    /// How to recompile with other values of the ranged constants (only
    /// kept when there are some).
    pub(crate) recipe: Option<Arc<Recipe>>,
}

/// Where a compilation takes its surface meshes from.
pub(crate) enum Meshes<'a> {
    /// Loads declared surfaces through a resolver.
    Load(&'a dyn SurfaceAssets),
    /// Reuses the surfaces an earlier compilation of the same file loaded.
    Reuse(&'a [(String, Arc<Mesh>)]),
}

/// The name of the global-state slot holding the derivation step (L-Py's
/// `getIterationNb()`).
pub(crate) const ITERATION: &str = "iteration";

/// Names visible in a production or hook: its formal parameters, the
/// global state (`iteration` and the `global` variables) and a body's
/// local variables, in that order in the environment, and the file's
/// `define`s (constants).
struct RuleScope<'a> {
    formals: &'a [String],
    state: &'a [String],
    locals: &'a [String],
    defines: &'a HashMap<String, f64>,
}

impl Scope for RuleScope<'_> {
    fn variable(&self, name: &str) -> Option<u32> {
        let (f, g) = (self.formals.len(), self.state.len());
        self.formals
            .iter()
            .rposition(|n| n == name)
            .or_else(|| self.state.iter().position(|n| n == name).map(|i| f + i))
            .or_else(|| self.locals.iter().position(|n| n == name).map(|i| f + g + i))
            .map(|i| i as u32)
    }
    fn constant(&self, name: &str) -> Option<f64> {
        self.defines.get(name).copied()
    }
    fn names(&self) -> Vec<String> {
        let vars = self.formals.iter().chain(self.state).chain(self.locals).cloned();
        vars.chain(self.defines.keys().cloned()).collect()
    }
}

struct Compiler {
    alphabet: Alphabet,
    defines: HashMap<String, f64>,
    /// `iteration`, then the `global` variables.
    state: Vec<String>,
    /// The surfaces `~name` can draw: built-in and declared.
    surfaces: Vec<(String, Arc<Mesh>)>,
    /// Surface names used but not known (each reported once).
    unknown_surfaces: Vec<String>,
    errors: Vec<Diagnostic>,
    warnings: Vec<Diagnostic>,
    /// First use of each turtle-looking module genform does not draw.
    unsupported: HashMap<String, Span>,
}

/// Compiles a parsed file, loading its surfaces through `assets`. Returns
/// the system and warnings, or every error.
pub fn compile(file: &syntax::File, assets: &dyn SurfaceAssets) -> Result<(LSystem, Vec<Diagnostic>), Vec<Diagnostic>> {
    compile_with(file, Meshes::Load(assets), None)
}

/// [`compile`] with the surfaces from `meshes` and, when `overrides` is
/// given, the ranged constants set to its values (one per ranged `define`,
/// in file order, already checked against their ranges).
pub(crate) fn compile_with(
    file: &syntax::File,
    meshes: Meshes,
    overrides: Option<&[f64]>,
) -> Result<(LSystem, Vec<Diagnostic>), Vec<Diagnostic>> {
    let mut c = Compiler {
        alphabet: Alphabet::default(),
        defines: HashMap::new(),
        state: vec![ITERATION.to_string()],
        surfaces: Vec::new(),
        unknown_surfaces: Vec::new(),
        errors: Vec::new(),
        warnings: Vec::new(),
        unsupported: HashMap::new(),
    };
    let mut ranged = Vec::new();
    let mut k = 0;
    for d in &file.defines {
        let (name, span) = (&d.name, d.span);
        let mut value = c.constant(&d.expr, &format!("`define {name}`"));
        if let Some(r) = &d.range {
            value = match overrides {
                Some(values) => values.get(k).copied(),
                None => {
                    let what = format!("the range of `{name}`");
                    let bounds = (c.constant(&r.min, &what), c.constant(&r.max, &what));
                    if let Some(rc) = ranged::check(d, r, value, bounds, &mut c.errors) {
                        ranged.push(rc);
                    }
                    // A bad range is reported once: readers of the
                    // constant still see its written value.
                    value
                }
            };
            k += 1;
        }
        if let Some(v) = value {
            if c.defines.insert(name.clone(), v).is_some() {
                c.warnings.push(Diagnostic::warning(span, format!("`{name}` is defined again; the later value wins")));
            }
        } else {
            // Keep later formulas from reporting it as unknown.
            c.defines.insert(name.clone(), f64::NAN);
        }
    }
    match meshes {
        Meshes::Load(assets) => c.surfaces(file, assets),
        Meshes::Reuse(loaded) => c.surfaces = loaded.to_vec(),
    }
    let initial_state = c.globals(file);
    let hooks = std::array::from_fn(|k| c.statements(&file.hooks[k], &[], &mut Vec::new(), false));
    let settings = c.settings(file);
    let axiom = match &file.axiom {
        Some((calls, span)) => {
            if calls.is_empty() {
                c.errors
                    .push(Diagnostic::error(*span, "the axiom is empty").with_hint("write `axiom: F`, for example"));
            }
            c.axiom(calls)
        }
        None => {
            c.errors.push(
                Diagnostic::error(Span::new(0, 0), "the L-system has no axiom")
                    .with_hint("add a line `axiom: F`, for example"),
            );
            ModuleString::default()
        }
    };
    let mut rules: [Vec<(Rule, bool)>; 3] = Default::default();
    for (section, p) in &file.productions {
        for rule in c.rules_of(p, *section) {
            let weighted = p.weight.is_some();
            rules[*section as usize].push((rule, weighted));
        }
    }
    let ignored = c.ignored(file);
    let n = c.alphabet.symbols.len();
    let [prod, dec, interp] = rules;
    let depth = |i: usize, default: u32| file.max_depth[i].map_or(default, |(d, _)| d);
    let productions = Table::new(prod, n, 1);
    let decomposition = Table::new(dec, n, depth(0, 1));
    let interpretation = Table::new(interp, n, depth(1, 1));
    c.unused_predecessors(&productions, &axiom, [&decomposition, &interpretation]);
    c.undrawn_commands(&interpretation);
    let surface_of = c
        .alphabet
        .symbols
        .iter()
        .map(|s| {
            let name = s.name.strip_prefix('~')?;
            c.surfaces.iter().position(|(n, _)| n == name).map(|k| k as u32)
        })
        .collect();
    if c.errors.is_empty() {
        // Recompiling with a genome's constants starts from the parsed file
        // and the loaded meshes (only kept when some constant is a gene).
        let recipe = (overrides.is_none() && !ranged.is_empty())
            .then(|| Arc::new(Recipe { file: file.clone(), surfaces: c.surfaces.clone() }));
        let is = |cmd: Command| c.alphabet.symbols.iter().map(|s| s.command == cmd).collect::<Vec<bool>>();
        let brackets = [is(Command::Push), is(Command::Pop)];
        let system = LSystem {
            settings,
            alphabet: c.alphabet,
            axiom,
            productions,
            decomposition,
            interpretation,
            ignored,
            brackets,
            source: None,
            initial_state,
            state_names: c.state,
            hooks,
            surface_of,
            surfaces: c.surfaces.into_iter().map(|(_, m)| m).collect(),
            ranged,
            recipe,
        };
        Ok((system, c.warnings))
    } else {
        Err(c.errors)
    }
}

impl Compiler {
    /// A formula without names other than constants and without random
    /// draws.
    fn constant(&mut self, e: &Expr, what: &str) -> Option<f64> {
        let scope = RuleScope { formals: &[], state: &[], locals: &[], defines: &self.defines };
        match expr::compile(&e.ast, &scope) {
            Ok(p) if p.uses_rng() => {
                self.errors.push(
                    Diagnostic::error(e.ast.span.shift(e.at), format!("{what} must be a constant, not a random draw"))
                        .with_hint("random draws belong in productions, where each application draws anew"),
                );
                None
            }
            Ok(p) => Some(p.eval(&[])),
            Err(ds) => {
                self.errors.extend(ds.into_iter().map(|d| d.shifted(e.at)));
                None
            }
        }
    }

    fn number(&mut self, s: &Setting) -> Option<f64> {
        match expr::parse(&s.value) {
            Ok(ast) => {
                let v = self.constant(&Expr { ast, at: s.at }, &format!("`{}`", s.key))?;
                if v.is_finite() {
                    Some(v)
                } else {
                    self.errors.push(Diagnostic::error(value_span(s), format!("`{}` is not a finite number", s.key)));
                    None
                }
            }
            Err(d) => {
                self.errors.push(d.shifted(s.at));
                None
            }
        }
    }

    fn settings(&mut self, file: &syntax::File) -> Settings {
        let mut st = Settings::default();
        for s in &file.settings {
            match s.key.as_str() {
                "name" => st.name = s.value.trim_matches('"').to_string(),
                "derivation" => {
                    if let Some(v) = self.number(s) {
                        if v >= 0.0 && v.fract() == 0.0 && v <= 1e6 {
                            st.derivation = v as u32;
                        } else {
                            self.errors.push(
                                Diagnostic::error(value_span(s), "the derivation length is a whole number of steps")
                                    .with_hint("for example `derivation: 5`"),
                            );
                        }
                    }
                }
                "angle" => st.angle = self.number(s).unwrap_or(st.angle),
                "step" => st.step = self.number(s).unwrap_or(st.step),
                "width" => st.width = self.non_negative(s).unwrap_or(st.width),
                "width_factor" => st.width_factor = self.number(s).unwrap_or(st.width_factor),
                "width_unit" => match self.number(s) {
                    Some(u) if u > 0.0 => st.width_unit = u,
                    Some(_) => self.errors.push(
                        Diagnostic::error(value_span(s), "`width_unit` must be positive")
                            .with_hint("every width is multiplied by it, e.g. `width_unit: 0.01` for pixel widths"),
                    ),
                    None => {}
                },
                "elasticity" => st.elasticity = self.number(s).unwrap_or(st.elasticity),
                "growth" => match self.number(s) {
                    Some(g) if (0.0..=1.0).contains(&g) => st.growth = g,
                    Some(_) => self.errors.push(
                        Diagnostic::error(value_span(s), "`growth` is a probability")
                            .with_hint("a number from 0 to 1, e.g. `growth: 0.9`"),
                    ),
                    None => {}
                },
                "max_modules" => {
                    if let Some(v) = self.non_negative(s) {
                        st.max_modules = v.min(usize::MAX as f64) as usize;
                        st.max_modules_at = Some(value_span(s));
                    }
                }
                "view" => match s.value.as_str() {
                    "2d" | "2D" => st.view = View::Flat,
                    "3d" | "3D" => st.view = View::Solid,
                    _ => self.errors.push(
                        Diagnostic::error(value_span(s), format!("unknown view `{}`", s.value))
                            .with_hint("`view: 2d` draws lines (SVG), `view: 3d` draws widths as frusta (GLB)"),
                    ),
                },
                "heading" => match Heading::parse(&s.value) {
                    Some(h) => st.heading = h,
                    None => self.errors.push(
                        Diagnostic::error(value_span(s), format!("unknown heading `{}`", s.value)).with_hint(
                            "one of +x, -x, +y, -y, +z, -z (curves usually start along +x, plants along +y)",
                        ),
                    ),
                },
                "tropism" => {
                    let parts: Vec<&str> = s.value.split(',').collect();
                    let mut v = [0.0; 3];
                    let mut ok = parts.len() == 3;
                    if ok {
                        let mut at = s.at;
                        for (k, part) in parts.iter().enumerate() {
                            let sub =
                                Setting { key: "tropism".into(), key_span: s.key_span, value: part.to_string(), at };
                            match self.number(&sub) {
                                Some(x) => v[k] = x,
                                None => ok = false,
                            }
                            at += part.len() + 1;
                        }
                    } else {
                        self.errors.push(
                            Diagnostic::error(value_span(s), "the tropism vector has three components")
                                .with_hint("for example `tropism: 0, -1, 0` (gravity) with `elasticity: 0.2`"),
                        );
                    }
                    if ok {
                        st.tropism = Some(v);
                    }
                }
                "colors" => {
                    st.colors.clear();
                    for w in s.value.split_whitespace() {
                        match parse_hex(w) {
                            Some(c) => st.colors.push(c),
                            None => self.errors.push(
                                Diagnostic::error(value_span(s), format!("`{w}` is not a colour"))
                                    .with_hint("colours are written #rrggbb, e.g. `colors: #6b4423 #3a7d23`"),
                            ),
                        }
                    }
                }
                _ => self.errors.push(Diagnostic::error(s.key_span, format!("`{}` is not valid here", s.key))),
            }
        }
        if st.angle.abs() > 1e6 {
            self.errors.push(Diagnostic::error(Span::new(0, 0), "the angle is out of range"));
        }
        st
    }

    fn non_negative(&mut self, s: &Setting) -> Option<f64> {
        let v = self.number(s)?;
        if v < 0.0 {
            self.errors.push(Diagnostic::error(value_span(s), format!("`{}` cannot be negative", s.key)));
            return None;
        }
        Some(v)
    }

    fn sym(&mut self, name: &str, arity: usize, span: Span) -> Sym {
        if let Some(surface) = name.strip_prefix('~').filter(|s| !s.is_empty())
            && !self.surfaces.iter().any(|(n, _)| n == surface)
            && !self.unknown_surfaces.iter().any(|n| n == surface)
        {
            self.unknown_surfaces.push(surface.to_string());
            let mut d = Diagnostic::error(span, format!("unknown surface `{surface}` in `{name}`"));
            d = match expr::did_you_mean(surface, self.surfaces.iter().map(|(n, _)| n.as_str())) {
                Some(s) => d.with_hint(format!("did you mean `~{s}`?")),
                None => d.with_hint(format!(
                    "surfaces here: {}; declare others with `surface {surface} = \"{surface}.obj\"`",
                    self.surfaces.iter().map(|(n, _)| format!("~{n}")).collect::<Vec<_>>().join(", ")
                )),
            };
            self.errors.push(d);
        }
        if alphabet::unsupported(name).is_some() {
            let first = self.unsupported.entry(name.to_string()).or_insert(span);
            if span.start < first.start {
                *first = span;
            }
        }
        match self.alphabet.intern(name, arity) {
            Some(s) => s,
            None => {
                self.errors
                    .push(Diagnostic::error(span, "too many distinct modules or parameters (at most 65535 and 255)"));
                0
            }
        }
    }

    fn axiom(&mut self, calls: &[Call]) -> ModuleString {
        let mut out = ModuleString::default();
        for call in calls {
            let s = self.sym(&call.name, call.args.len(), call.span);
            out.syms.push(s);
            for a in &call.args {
                match self.constant(a, "an axiom parameter") {
                    Some(v) if v.is_finite() => out.params.push(v),
                    Some(_) => {
                        self.errors.push(Diagnostic::error(
                            a.ast.span.shift(a.at),
                            "this axiom parameter is not a finite number",
                        ));
                        out.params.push(f64::NAN);
                    }
                    None => out.params.push(f64::NAN),
                }
            }
        }
        self.balanced(calls, &out.syms, "the axiom");
        out
    }

    /// Reports brackets of `calls` (interned as `syms`) that do not pair
    /// up: a `]` that closes nothing, or `[`s left open. Branches must
    /// close where they open, or the turtle pops states that were never
    /// pushed and contexts see a different tree than the one drawn.
    fn balanced(&mut self, calls: &[Call], syms: &[Sym], what: &str) {
        let mut open: Vec<Span> = Vec::new();
        for (call, &s) in calls.iter().zip(syms) {
            match self.alphabet.command(s) {
                Command::Push => open.push(call.span),
                Command::Pop if open.pop().is_none() => {
                    self.errors.push(
                        Diagnostic::error(call.span, format!("this `]` in {what} closes no branch"))
                            .with_hint("every `]` needs a `[` before it in the same axiom or successor"),
                    );
                    return;
                }
                _ => {}
            }
        }
        if let Some(&first) = open.first() {
            let n = open.len();
            self.errors.push(
                Diagnostic::error(
                    first,
                    format!("{what} opens {n} branch{} with `[` that it never closes", if n == 1 { "" } else { "es" }),
                )
                .with_hint("add the missing `]`: a branch must close in the axiom or successor that opens it"),
            );
        }
    }

    fn is_bracket(&self, s: Sym) -> bool {
        matches!(self.alphabet.command(s), Command::Push | Command::Pop)
    }

    /// Reports the first bracket of a right context that does not pair up:
    /// a bracketed sub-pattern matches one whole branch, so it must close.
    fn balanced_context(&mut self, patterns: &[Pattern], syms: &[Sym]) {
        let mut open: Vec<Span> = Vec::new();
        for (m, &s) in patterns.iter().zip(syms) {
            match self.alphabet.command(s) {
                Command::Push => open.push(m.span),
                Command::Pop if open.pop().is_none() => {
                    self.errors.push(
                        Diagnostic::error(m.span, "this `]` in the right context closes no branch")
                            .with_hint("a branch in a context is written whole: `A > [B]C`"),
                    );
                    return;
                }
                _ => {}
            }
        }
        if let Some(&first) = open.first() {
            self.errors.push(
                Diagnostic::error(first, "this `[` in the right context is never closed")
                    .with_hint("a branch in a context is written whole: `A > [B]C`"),
            );
        }
    }

    fn pattern(&mut self, p: &Pattern, formals: &mut Vec<String>) -> Sym {
        for (f, span) in &p.formals {
            if formals.contains(f) {
                self.errors.push(
                    Diagnostic::error(*span, format!("parameter `{f}` is named twice in this production"))
                        .with_hint("give every parameter of the predecessor and its contexts its own name"),
                );
            }
            formals.push(f.clone());
        }
        self.sym(&p.name, p.formals.len(), p.span)
    }

    /// Checks a strict predecessor of several modules (`first` then
    /// `rest`): decomposition rules have none, and it holds no brackets.
    fn several(&mut self, p: &syntax::Production, section: Section, first: Sym, rest: &[Sym]) {
        let whole = Span::new(p.strict[0].span.start as usize, p.strict[p.strict.len() - 1].span.end as usize);
        if section == Section::Decomposition {
            self.errors.push(
                Diagnostic::error(
                    whole,
                    format!("a decomposition rule rewrites one module, this predecessor has {}", p.strict.len()),
                )
                .with_hint("rewrite the sequence in a production (`A B -> C`), or write one rule per module"),
            );
        }
        let syms = std::iter::once(&first).chain(rest);
        if let Some(m) = syms.zip(&p.strict).find(|(s, _)| self.is_bracket(**s)).map(|(_, m)| m) {
            self.errors.push(
                Diagnostic::error(m.span, "a predecessor of several modules cannot hold a bracket")
                    .with_hint("match a branch with a right context instead: `A > [B] -> …`"),
            );
        }
    }

    /// The rules of production `p`: one, or one per combination of the
    /// alternatives of its `or(…)` patterns (in order: the first that
    /// matches applies), each binding the parameters of the others to NaN
    /// (L-Py's None).
    fn rules_of(&mut self, p: &syntax::Production, section: Section) -> Vec<Rule> {
        let has_or = |ps: &[Pattern]| ps.iter().any(|m| !m.alts.is_empty());
        if !(has_or(&p.left) || has_or(&p.strict) || has_or(&p.right)) {
            return self.rule(p, section, &[]).into_iter().collect();
        }
        if p.weight.is_some() {
            self.errors.push(
                Diagnostic::error(p.span, "a stochastic production cannot hold an `or(…)` pattern")
                    .with_hint("write one weighted production per alternative"),
            );
            return Vec::new();
        }
        let (left, strict, right) = (alternatives(&p.left), alternatives(&p.strict), alternatives(&p.right));
        let n = left.len() * strict.len() * right.len();
        if n > MAX_ALTERNATIVES {
            self.errors.push(
                Diagnostic::error(p.span, format!("the `or(…)` patterns of this rule combine into {n} predecessors"))
                    .with_hint(format!("at most {MAX_ALTERNATIVES}: split the rule into several")),
            );
            return Vec::new();
        }
        let mut names = Vec::new();
        for m in p.left.iter().chain(&p.strict).chain(&p.right) {
            formal_names(m, &mut names);
        }
        let mut out = Vec::new();
        let seen = self.errors.len();
        for l in &left {
            for st in &strict {
                for r in &right {
                    let q = syntax::Production { left: l.clone(), strict: st.clone(), right: r.clone(), ..p.clone() };
                    let mark = self.errors.len();
                    let rule = self.rule(&q, section, &names);
                    // Each combination repeats the errors of the parts they share.
                    let new: Vec<Diagnostic> = self.errors.drain(mark..).collect();
                    for d in new {
                        if !self.errors[seen..].iter().any(|e| e.span == d.span && e.message == d.message) {
                            self.errors.push(d);
                        }
                    }
                    out.extend(rule);
                }
            }
        }
        out
    }

    /// Compiles one production; `extra` names parameters bound to NaN
    /// after the predecessor's and contexts' own (those of the other
    /// alternatives of an `or(…)`).
    fn rule(&mut self, p: &syntax::Production, section: Section, extra: &[String]) -> Option<Rule> {
        if section == Section::Decomposition && !(p.left.is_empty() && p.right.is_empty()) {
            self.errors.push(
                Diagnostic::error(p.span, "decomposition rules are context-free")
                    .with_hint("move the context to a production or an interpretation rule, or drop it"),
            );
        }
        let mut formals = Vec::new();
        let left: Vec<Sym> = p.left.iter().map(|m| self.pattern(m, &mut formals)).collect();
        let strict = self.pattern(&p.strict[0], &mut formals);
        let rest: Vec<Sym> = p.strict[1..].iter().map(|m| self.pattern(m, &mut formals)).collect();
        if !rest.is_empty() {
            self.several(p, section, strict, &rest);
        }
        let right: Vec<Sym> = p.right.iter().map(|m| self.pattern(m, &mut formals)).collect();
        let bound = formals.len();
        for name in extra {
            if !formals.contains(name) {
                formals.push(name.clone());
            }
        }
        let pad = (formals.len() - bound) as u32;
        // ABOP §1.8 (and cpfg): the left context is a path towards the root,
        // so it has no branches; the right context is an axial tree.
        if let Some(m) = left.iter().zip(&p.left).find(|(s, _)| self.is_bracket(**s)).map(|(_, m)| m) {
            self.errors.push(
                Diagnostic::error(m.span, "brackets cannot be part of a left context")
                    .with_hint("it is the path to the root (ABOP §1.8) and skips branches by itself"),
            );
        }
        self.balanced_context(&p.right, &right);
        let scope = RuleScope { formals: &formals, state: &self.state, locals: &[], defines: &self.defines };
        let cond = p.cond.as_ref().and_then(|e| program(e, &scope, &mut self.errors));
        let weight = p.weight.as_ref().and_then(|e| program(e, &scope, &mut self.errors));
        // A weight known now must be a usable one; weights that read
        // parameters are checked where they are drawn (below zero counts as 0).
        if let (Some(w), Some(e)) = (&weight, &p.weight)
            && w.loads().next().is_none()
            && !w.uses_rng()
        {
            let v = w.eval(&[]);
            if !(v.is_finite() && v >= 0.0) {
                self.errors.push(
                    Diagnostic::error(e.ast.span.shift(e.at), format!("a production weight must be ≥ 0, not {v}"))
                        .with_hint("weights are relative chances: write 0 to switch a production off"),
                );
            }
        }
        let mut progs = Vec::new();
        let mut failed = false;
        for call in &p.successor {
            for a in &call.args {
                match program(a, &scope, &mut self.errors) {
                    Some(prog) => progs.push(prog),
                    None => failed = true,
                }
            }
        }
        let mut succ_syms = Vec::with_capacity(p.successor.len());
        for call in &p.successor {
            succ_syms.push(self.sym(&call.name, call.args.len(), call.span));
        }
        self.balanced(&p.successor, &succ_syms, "the successor");
        let body = p.body.as_ref().map(|stmts| {
            let mut locals = Vec::new();
            let ops = self.statements(stmts, &formals, &mut locals, true);
            Body { ops, locals: locals.len() }
        });
        if let Some(b) = &body {
            if p.weight.is_some() {
                self.errors.push(
                    Diagnostic::error(p.span, "a production with a body cannot have a weight")
                        .with_hint("choose inside the body with `if uniform(0, 1) < 0.3: produce …`"),
                );
            }
            crate::body::produced_syms(&b.ops, &mut succ_syms);
        }
        if failed || (p.cond.is_some() && cond.is_none()) || (p.weight.is_some() && weight.is_none()) {
            return None;
        }
        // Whether the rule reads the global state (appended to its
        // environment after the formal parameters).
        let n = formals.len() as u32;
        let reads = |prog: &Program| prog.loads().any(|i| i >= n);
        let state = body.is_some() || cond.iter().chain(&weight).chain(&progs).any(reads);
        let mut draws = cond.as_ref().map_or(0, Program::max_draws) + weight.as_ref().map_or(0, Program::max_draws);
        draws += progs.iter().map(Program::max_draws).sum::<usize>();
        let succ_args = progs.into_iter().map(Arg::of).collect();
        let mut rule = Rule {
            strict,
            rest,
            pad,
            view: false,
            tail: pad > 0 || state,
            left,
            right,
            env: formals.len(),
            cond,
            weight,
            succ_syms,
            succ_args,
            draws,
            span: p.span,
            body,
            state,
        };
        rule.view = rule.needs_view();
        Some(rule)
    }

    /// The built-in surfaces, then the declared ones (a declaration may
    /// replace a built-in one).
    fn surfaces(&mut self, file: &syntax::File, assets: &dyn SurfaceAssets) {
        for name in surface::BUILT_IN {
            if let Some(m) = surface::built_in(name) {
                self.surfaces.push((name.to_string(), Arc::new(m)));
            }
        }
        let mut declared: Vec<&str> = Vec::new();
        for (name, span, path, path_span) in &file.surfaces {
            if declared.contains(&name.as_str()) {
                self.errors.push(Diagnostic::error(*span, format!("surface `{name}` is declared twice")));
                continue;
            }
            declared.push(name);
            match assets.load_mesh(path) {
                Ok(mut m) => {
                    if m.positions.iter().any(|p| !p.is_finite()) || m.triangles.is_empty() {
                        self.errors.push(Diagnostic::error(
                            *path_span,
                            format!("\"{path}\" has no usable triangles or non-finite vertices"),
                        ));
                        continue;
                    }
                    m.name = name.clone();
                    let mesh = Arc::new(m);
                    match self.surfaces.iter_mut().find(|(n, _)| n == name) {
                        Some(slot) => slot.1 = mesh,
                        None => self.surfaces.push((name.clone(), mesh)),
                    }
                }
                Err(e) => self.errors.push(
                    Diagnostic::error(*path_span, format!("cannot load surface `{name}`: {e}"))
                        .with_hint("the path is relative to the .ls file; OBJ, STL and GLB meshes load"),
                ),
            }
        }
    }

    /// The `global` variables: their names join the state after
    /// `iteration`; returns the initial state.
    fn globals(&mut self, file: &syntax::File) -> Vec<f64> {
        let mut values = vec![0.0];
        for (name, span, e) in &file.globals {
            let clash = if name == ITERATION {
                Some("`iteration` is the derivation step, kept by genform; choose another name".to_string())
            } else if self.state.contains(name) {
                Some(format!("global `{name}` is declared twice"))
            } else if self.defines.contains_key(name) {
                Some(format!("`{name}` is already a constant (`define`)"))
            } else {
                None
            };
            if let Some(msg) = clash {
                self.errors.push(Diagnostic::error(*span, msg));
                continue;
            }
            let v = self.constant(e, &format!("`global {name}`")).unwrap_or(f64::NAN);
            self.state.push(name.clone());
            values.push(v);
        }
        values
    }

    /// Compiles statements: a production body's (`in_body`, after the
    /// production's `formals`, declaring `locals`) or a hook's.
    fn statements(&mut self, stmts: &[Stmt], formals: &[String], locals: &mut Vec<String>, in_body: bool) -> Vec<Op> {
        stmts.iter().filter_map(|st| self.statement(st, formals, locals, in_body)).collect()
    }

    fn statement(&mut self, st: &Stmt, formals: &[String], locals: &mut Vec<String>, in_body: bool) -> Option<Op> {
        let (f, g) = (formals.len(), self.state.len());
        match st {
            Stmt::Assign { name, span, value } => {
                let scope = RuleScope { formals, state: &self.state, locals, defines: &self.defines };
                let prog = program(value, &scope, &mut self.errors);
                let slot = if name == ITERATION {
                    self.errors.push(
                        Diagnostic::error(*span, "`iteration` is the derivation step and cannot be assigned")
                            .with_hint("count in a global variable of your own: `global n = 0`"),
                    );
                    None
                } else if in_body {
                    if let Some(i) = formals.iter().rposition(|n| n == name) {
                        Some(i)
                    } else if self.state.contains(name) {
                        self.errors.push(
                            Diagnostic::error(*span, format!("global `{name}` cannot change in a production"))
                                .with_hint("productions rewrite in parallel; change globals in Start, StartEach, EndEach or End"),
                        );
                        None
                    } else {
                        let i = locals.iter().position(|n| n == name).unwrap_or_else(|| {
                            locals.push(name.clone());
                            locals.len() - 1
                        });
                        Some(f + g + i)
                    }
                } else if let Some(i) = self.state.iter().position(|n| n == name) {
                    Some(i)
                } else {
                    let mut d = Diagnostic::error(*span, format!("unknown global `{name}`"));
                    d = match expr::did_you_mean(name, self.state[1..].iter().map(String::as_str)) {
                        Some(s) => d.with_hint(format!("did you mean `{s}`?")),
                        None => d.with_hint(format!("declare it at the top of the file: `global {name} = 0`")),
                    };
                    self.errors.push(d);
                    None
                };
                Some(Op::Assign(slot? as u32, prog?, *span))
            }
            Stmt::If { cond, then, els } => {
                let scope = RuleScope { formals, state: &self.state, locals, defines: &self.defines };
                let c = program(cond, &scope, &mut self.errors);
                let then = self.statement(then, formals, locals, in_body).into_iter().collect();
                let els = match els {
                    Some(e) => self.statement(e, formals, locals, in_body).into_iter().collect(),
                    None => Vec::new(),
                };
                Some(Op::If(c?, then, els))
            }
            Stmt::Produce { calls, end, .. } => {
                let syms: Vec<Sym> = calls.iter().map(|c| self.sym(&c.name, c.args.len(), c.span)).collect();
                self.balanced(calls, &syms, if *end { "this `produce`" } else { "this `nproduce`" });
                let scope = RuleScope { formals, state: &self.state, locals, defines: &self.defines };
                let mut args = Vec::new();
                let mut ok = true;
                for a in calls.iter().flat_map(|c| &c.args) {
                    match program(a, &scope, &mut self.errors) {
                        Some(p) => args.push(Arg::of(p)),
                        None => ok = false,
                    }
                }
                ok.then_some(Op::Produce { syms, args, end: *end })
            }
        }
    }

    /// Per symbol: whether contexts skip it (`ignore:` lists the skipped,
    /// `consider:` the matched; brackets always count).
    fn ignored(&mut self, file: &syntax::File) -> Vec<bool> {
        let n = self.alphabet.symbols.len();
        let mut out = vec![false; n];
        let sets = &file.context_sets;
        if sets.len() > 1 {
            self.errors.push(
                Diagnostic::error(sets[1].2, "give either one `ignore:` or one `consider:` list")
                    .with_hint("`consider:` matches only the listed modules; `ignore:` skips the listed ones"),
            );
        }
        let Some((consider, names, _)) = sets.first() else { return out };
        for (i, sym) in self.alphabet.symbols.iter().enumerate() {
            let listed = names.contains(&sym.name);
            let bracket = matches!(sym.command, Command::Push | Command::Pop);
            out[i] = !bracket && (listed != *consider);
        }
        out
    }

    /// Warns once per turtle-looking module that genform does not draw
    /// (`~`, `@M`, `?P`, …), at its first use, unless an interpretation
    /// rule gives it a drawing: silence would hide a missing surface or
    /// cylinder.
    fn undrawn_commands(&mut self, interpretation: &Table) {
        let mut found: Vec<(String, Span)> = self.unsupported.drain().collect();
        found.sort_by_key(|(_, s)| s.start);
        for (name, span) in found {
            let interpreted =
                interpretation.rules.iter().any(|r| self.alphabet.symbols[r.strict as usize].name == name);
            let Some(what) = alphabet::unsupported(&name) else { continue };
            if !interpreted {
                self.warnings.push(
                    Diagnostic::warning(
                        span,
                        format!("`{name}` ({what}) is not drawn by genform; it is kept as a plain module"),
                    )
                    .with_hint(format!("give it a drawing with an interpretation rule (`{name} -> …`) or remove it")),
                );
            }
        }
    }

    fn unused_predecessors(&mut self, productions: &Table, axiom: &ModuleString, others: [&Table; 2]) {
        // Symbols that can ever appear: the axiom's and every successor's.
        let mut reachable = vec![false; self.alphabet.symbols.len()];
        for &s in &axiom.syms {
            reachable[s as usize] = true;
        }
        for t in std::iter::once(productions).chain(others) {
            for r in &t.rules {
                for &s in &r.succ_syms {
                    reachable[s as usize] = true;
                }
            }
        }
        let missing = |r: &Rule| std::iter::once(&r.strict).chain(&r.rest).find(|&&s| !reachable[s as usize]).copied();
        for t in std::iter::once(productions).chain(others) {
            for (k, r) in t.rules.iter().enumerate() {
                // The rules of one production's `or(…)` share its span: warn
                // once, when none of them can apply.
                let same = |o: &Rule| o.span == r.span;
                if t.rules[..k].iter().any(same)
                    || t.rules[k..].iter().filter(|o| same(o)).any(|o| missing(o).is_none())
                {
                    continue;
                }
                if let Some(s) = missing(r) {
                    let info = &self.alphabet.symbols[s as usize];
                    let others: Vec<String> = self
                        .alphabet
                        .named(&info.name)
                        .filter(|&s| reachable[s as usize])
                        .map(|s| self.alphabet.arity(s).to_string())
                        .collect();
                    let mut d = Diagnostic::warning(
                        r.span,
                        format!(
                            "no module `{}` with {} parameter{} ever appears, so this rule never applies",
                            info.name,
                            info.arity,
                            if info.arity == 1 { "" } else { "s" }
                        ),
                    );
                    if !others.is_empty() {
                        d = d.with_hint(format!("`{}` appears with {} parameter(s)", info.name, others.join(" or ")));
                    }
                    self.warnings.push(d);
                }
            }
        }
    }
}

/// Most predecessors the `or(…)` patterns of one rule may combine into.
const MAX_ALTERNATIVES: usize = 64;

/// The plain module sequences `patterns` can match, one per combination
/// of the alternatives of its `or(…)`s, in order of preference.
fn alternatives(patterns: &[Pattern]) -> Vec<Vec<Pattern>> {
    let mut out = vec![Vec::new()];
    for p in patterns {
        if p.alts.is_empty() {
            for o in &mut out {
                o.push(p.clone());
            }
            continue;
        }
        let mut next = Vec::new();
        for o in &out {
            for alt in &p.alts {
                for tail in alternatives(alt) {
                    let mut v = o.clone();
                    v.extend(tail);
                    next.push(v);
                }
            }
        }
        out = next;
        if out.len() > MAX_ALTERNATIVES {
            break;
        }
    }
    out
}

/// Appends the parameter names of `p` (and its alternatives) not yet in
/// `names`, in text order.
fn formal_names(p: &Pattern, names: &mut Vec<String>) {
    for (f, _) in &p.formals {
        if !names.contains(f) {
            names.push(f.clone());
        }
    }
    for m in p.alts.iter().flatten() {
        formal_names(m, names);
    }
}

/// Compiles a formula against `scope`, its errors shifted to the file.
fn program(e: &Expr, scope: &RuleScope, errors: &mut Vec<Diagnostic>) -> Option<Program> {
    match expr::compile(&e.ast, scope) {
        Ok(p) => Some(p),
        Err(ds) => {
            errors.extend(ds.into_iter().map(|d| d.shifted(e.at)));
            None
        }
    }
}

fn value_span(s: &Setting) -> Span {
    Span::new(s.at, s.at + s.value.len().max(1))
}

fn parse_hex(w: &str) -> Option<[u8; 3]> {
    let h = w.strip_prefix('#')?;
    if h.len() != 6 || !h.bytes().all(|b| b.is_ascii_hexdigit()) {
        return None;
    }
    let v = u32::from_str_radix(h, 16).ok()?;
    Some([(v >> 16) as u8, (v >> 8) as u8, v as u8])
}

impl Table {
    /// Groups rules per predecessor symbol, in file order: consecutive
    /// weighted rules of one symbol form one stochastic group.
    fn new(rules: Vec<(Rule, bool)>, symbols: usize, max_depth: u32) -> Table {
        let mut by_sym: Vec<Vec<Entry>> = vec![Vec::new(); symbols];
        let mut flat = Vec::with_capacity(rules.len());
        for (i, (rule, weighted)) in rules.into_iter().enumerate() {
            let list = &mut by_sym[rule.strict as usize];
            match (weighted, list.last_mut()) {
                (true, Some(Entry::Group(g))) => g.push(i as u32),
                (true, _) => list.push(Entry::Group(vec![i as u32])),
                (false, _) => list.push(Entry::One(i as u32)),
            }
            flat.push(rule);
        }
        Table::from_parts(flat, by_sym, max_depth)
    }
}

#[cfg(test)]
pub(crate) fn compile_text(text: &str) -> Result<(LSystem, Vec<Diagnostic>), Vec<Diagnostic>> {
    let (file, errors) = syntax::parse(text);
    if !errors.is_empty() {
        return Err(errors);
    }
    compile(&file, &crate::surface::NoSurfaceAssets)
}

impl LSystem {
    /// `file:line:col` of a position in the file it was compiled from.
    pub fn location(&self, span: genform_core::Span) -> Option<String> {
        self.source.as_ref().map(|f| f.location(span.start))
    }

    /// Number of productions, decomposition rules and interpretation rules.
    pub fn rule_counts(&self) -> [usize; 3] {
        [self.productions.rules.len(), self.decomposition.rules.len(), self.interpretation.rules.len()]
    }

    /// The `global` variables with their declared values, in file order.
    pub fn globals(&self) -> impl Iterator<Item = (&str, f64)> + '_ {
        self.state_names.iter().zip(&self.initial_state).skip(1).map(|(n, v)| (n.as_str(), *v))
    }

    /// Whether some Start, StartEach, EndEach or End hook has statements.
    pub fn has_hooks(&self) -> bool {
        self.hooks.iter().any(|h| !h.is_empty())
    }

    /// Whether some production has a left or right context or a
    /// predecessor of several modules.
    pub fn is_context_sensitive(&self) -> bool {
        self.productions.context
    }
}
