//! One production: the mother pattern, its variables, conditions, spatial
//! order and search plans; its daughters are compiled in `daughter.rs`.

use super::scope::{GlobalInfo, Owner, ProdScope, Slots, VecDef};
use super::syntax::{Formula, ProductionSyn, Variable, Written};
use super::{Cx, Place};
use crate::grammar::{Daughter, Production};
use crate::mother::{MEdge, MVertex, PairVector, SpatialPair};
use crate::plan::make_plan;
use genform_core::diag::{Diagnostic, Span};
use genform_core::expr::{Program, did_you_mean, parse};
use std::cell::RefCell;

/// A constant as a program (variables and coordinates written as plain
/// numbers).
pub(super) fn constant_program(v: f64) -> Program {
    let text = if v.is_nan() {
        "0/0".to_string()
    } else if v.is_infinite() {
        if v > 0.0 { "1/0" } else { "-1/0" }.to_string()
    } else {
        format!("{v}")
    };
    // A number's text always parses and compiles to itself.
    let ast = parse(&text).expect("a number parses");
    genform_core::expr::compile(&ast, &genform_core::expr::Names(&[])).expect("a number compiles")
}

/// Hands each env slot to what fills it now that every formula is in: the
/// loads of mother vertices and edges, the pair vectors (two consecutive
/// slots each) and the globals (slot, global index).
fn wire_slots(
    slots: &Slots,
    mv: &mut [MVertex],
    me: &mut [MEdge],
    pairs: &[(usize, usize)],
) -> (Vec<PairVector>, Vec<(u32, usize)>) {
    let mut pair_vectors: Vec<PairVector> = Vec::new();
    let mut global_slots = Vec::new();
    for (slot, owner) in slots.owners.iter().enumerate() {
        let slot = slot as u32;
        match *owner {
            Owner::Vertex(v, load) => mv[v].loads.push((slot, load)),
            Owner::Edge(e, load) => me[e].loads.push((slot, load)),
            Owner::Pair(i) => {
                // Two consecutive slots per pair vector: keep the first.
                if !pair_vectors.iter().any(|pv| pv.slot + 1 == slot) {
                    pair_vectors.push(PairVector { from: pairs[i].0, to: pairs[i].1, slot });
                }
            }
            Owner::Global(i) => global_slots.push((slot, i)),
            Owner::RunVar | Owner::AppVar => {}
        }
    }
    (pair_vectors, global_slots)
}

/// What a program reads: mother elements (vertices, then edges) and
/// whether it reads a per-application variable.
fn deps(p: &Program, slots: &Slots, nv: usize, pairs: &[(usize, usize)]) -> (Vec<usize>, bool) {
    let mut out = Vec::new();
    let mut app = false;
    for s in p.loads() {
        match slots.owners.get(s as usize) {
            Some(Owner::Vertex(v, _)) => out.push(*v),
            Some(Owner::Edge(e, _)) => out.push(nv + e),
            Some(Owner::Pair(i)) => out.extend([pairs[*i].0, pairs[*i].1]),
            Some(Owner::AppVar) => app = true,
            _ => {}
        }
    }
    out.sort_unstable();
    out.dedup();
    (out, app)
}

/// A production's conditions, split by what they read.
#[derive(Default)]
struct Conditions {
    /// Conditions that read no matched element, checked before searching.
    pre_checks: Vec<Program>,
    /// The others, with the mother elements each reads.
    conditions: Vec<Program>,
    deps: Vec<Vec<usize>>,
}

impl Cx {
    /// Compiles production `p` in passes: the mother pattern
    /// ([`Cx::mother_pattern`]), its named vectors, the variables, the
    /// conditions, the spatial order, the daughter options, and — once every
    /// formula is in and nothing was reported — the slot wiring and search
    /// plans. `None` when it reported an error.
    pub(crate) fn production(&mut self, p: &ProductionSyn, globals: &[(String, GlobalInfo)]) -> Option<Production> {
        let errors_before = self.errors.len();
        let (mut mv, mut me, names) = self.mother_pattern(p);
        let nv = mv.len();
        let vnames: Vec<String> = mv.iter().map(|v| v.name.clone()).collect();
        let (vectors, pairs) = self.named_vectors(p, &names, &vnames);
        // The scope borrows its own copy of the attribute table, so errors
        // can be reported while it is alive.
        let attrs = self.attrs.clone();
        let mut scope = ProdScope {
            globals,
            attrs: &attrs,
            vertices: vnames,
            edges: me.iter().map(|e| e.name.clone()).collect(),
            vectors,
            pairs: pairs.clone(),
            vars: Vec::new(),
            slots: RefCell::new(Slots::default()),
        };
        let element_names: Vec<String> = names.iter().map(|(n, _)| n.clone()).collect();

        let mut run_vars = Vec::new();
        let mut app_vars = Vec::new();
        self.variables(&p.vars, &mut scope, &element_names, &mut run_vars, &mut app_vars, nv);
        let conditions = self.conditions(p, &scope, nv, &pairs);
        let spatial = self.spatial_order(p, &mv);
        let (options, weights) = self.daughter_options(p, (&mv, &me), &mut scope, &element_names, &mut run_vars);

        if self.errors.len() > errors_before {
            return None;
        }

        let slots = scope.slots.into_inner();
        let (pair_vectors, global_slots) = wire_slots(&slots, &mut mv, &mut me, &pairs);
        let plans = (0..nv + me.len())
            .map(|anchor| make_plan(anchor, &mv, &me, &pair_vectors, &spatial, &conditions.deps))
            .collect();
        let plans = if nv + me.len() == 0 { vec![make_plan(0, &mv, &me, &[], &[], &[])] } else { plans };
        Some(Production {
            name: p.name.s.clone(),
            oldest: p.oldest,
            mv,
            me,
            env_len: slots.owners.len(),
            global_slots,
            run_vars,
            app_vars,
            pre_checks: conditions.pre_checks,
            conditions: conditions.conditions,
            vectors: pair_vectors,
            spatial,
            plans,
            options,
            weights,
        })
    }

    /// The mother pattern's vertices and edges, and every element name
    /// with where it is written (each reported once when listed twice).
    #[allow(clippy::type_complexity)]
    fn mother_pattern(&mut self, p: &ProductionSyn) -> (Vec<MVertex>, Vec<MEdge>, Vec<(String, Span)>) {
        let pname = &p.name.s;
        let mut names: Vec<(String, Span)> = Vec::new();
        let mut claim = |cx: &mut Cx, name: String, span: Span, what: &str| {
            if let Some((_, first)) = names.iter().find(|(n, _)| *n == name) {
                cx.errors.push(
                    Diagnostic::error(span, format!("{what} `{name}` is listed twice in the mother of `{pname}`"))
                        .with_label(*first, "first here")
                        .with_hint("every mother element needs its own name; name parallel edges with `name:`"),
                );
            }
            names.push((name, span));
        };
        let mut mv = Vec::new();
        for v in &p.mother.vertices {
            self.check_keys(v, Place::MotherVertex);
            let name = v.name();
            claim(self, name.clone(), v.name_span(), "vertex");
            let wildcard = v.wildcard.is_some_and(|w| w.0);
            if wildcard && (v.label.is_some() || !v.attrs.is_empty() || v.when.is_some()) {
                self.error(v.name_span(), format!("wildcard `{name}` cannot have a label, attributes or a condition"))
                    .hints
                    .push("a wildcard matches any vertex; drop `wildcard: true` to constrain it".into());
            }
            let label = v.label.as_ref().map(|l| self.labels.intern(&l.s));
            let attrs = self.literal_attrs(v);
            mv.push(MVertex { name, label, attrs, wildcard, at: v.at.map(|a| a.0), loads: Vec::new() });
        }
        let vnames: Vec<String> = mv.iter().map(|v| v.name.clone()).collect();
        let mut me = Vec::new();
        for e in &p.mother.edges {
            self.check_keys(e, Place::MotherEdge);
            let name = e.name();
            if e.from.is_none() || e.to.is_none() {
                self.error(e.span, "an edge needs `from` and `to`");
                continue;
            }
            claim(self, name.clone(), e.name_span(), "edge");
            let from = self.mother_vertex(e.from.as_ref(), &vnames, pname);
            let to = self.mother_vertex(e.to.as_ref(), &vnames, pname);
            let label = e.label.as_ref().map(|l| self.labels.intern(&l.s));
            let attrs = self.literal_attrs(e);
            if let (Some(from), Some(to)) = (from, to) {
                me.push(MEdge {
                    name,
                    from,
                    to,
                    directed: e.directed.is_some_and(|d| d.0),
                    label,
                    attrs,
                    loads: Vec::new(),
                });
            }
        }
        (mv, me, names)
    }

    /// The production's named vectors (a mother vertex's position, or the
    /// difference of two), and the ends of the pair vectors.
    #[allow(clippy::type_complexity)]
    fn named_vectors(
        &mut self,
        p: &ProductionSyn,
        names: &[(String, Span)],
        vnames: &[String],
    ) -> (Vec<(String, VecDef)>, Vec<(usize, usize)>) {
        let pname = &p.name.s;
        let mut vectors = Vec::new();
        let mut pairs = Vec::new();
        for (name, def) in &p.vectors {
            if names.iter().any(|(n, _)| *n == name.s) {
                self.error(name.span, format!("vector `{}` has the name of a mother element", name.s));
                continue;
            }
            match def {
                super::syntax::VectorSyn::Point(a) => {
                    if let Some(v) = self.mother_vertex(Some(a), vnames, pname) {
                        vectors.push((name.s.clone(), VecDef::Point(v)));
                    }
                }
                super::syntax::VectorSyn::Pair(a, b) => {
                    let (a, b) =
                        (self.mother_vertex(Some(a), vnames, pname), self.mother_vertex(Some(b), vnames, pname));
                    if let (Some(a), Some(b)) = (a, b) {
                        vectors.push((name.s.clone(), VecDef::Pair(pairs.len())));
                        pairs.push((a, b));
                    }
                }
            }
        }
        (vectors, pairs)
    }

    /// The conditions, in file order: element conditions, then the
    /// production's. None may draw random numbers or read a
    /// per-application variable.
    fn conditions(&mut self, p: &ProductionSyn, scope: &ProdScope, nv: usize, pairs: &[(usize, usize)]) -> Conditions {
        let whens: Vec<&Formula> = p
            .mother
            .vertices
            .iter()
            .chain(&p.mother.edges)
            .filter_map(|e| e.when.as_ref())
            .chain(p.when.iter())
            .collect();
        let mut out = Conditions::default();
        for f in whens {
            let Some(prog) = self.scalar(f, scope, "a condition") else { continue };
            if prog.uses_rng() {
                self.error(f.content_span(), "a condition cannot draw random numbers")
                    .hints
                    .push("choose randomly with weighted daughters, or draw a per-run variable".into());
                continue;
            }
            let (d, app) = deps(&prog, &scope.slots.borrow(), nv, pairs);
            if app {
                self.error(
                    f.content_span(),
                    "a condition cannot read a per-application variable (it is drawn after matching)",
                )
                .hints
                .push("make the variable `per: run`".into());
                continue;
            }
            if d.is_empty() {
                out.pre_checks.push(prog);
            } else {
                out.conditions.push(prog);
                out.deps.push(d);
            }
        }
        out
    }

    /// Spatial matching: the order in x and y of every pair of mother
    /// vertices (their `at:` positions) that a match must keep.
    fn spatial_order(&mut self, p: &ProductionSyn, mv: &[MVertex]) -> Vec<SpatialPair> {
        let mut spatial = Vec::new();
        if !p.spatial {
            return spatial;
        }
        let nv = mv.len();
        for (i, v) in mv.iter().enumerate() {
            if v.at.is_none() {
                self.error(
                    p.mother.vertices[i].name_span(),
                    format!("spatial matching needs `at: [x, y]` on `{}`", v.name),
                )
                .hints
                .push("the mother's layout positions give the order its match must keep".into());
            }
        }
        for a in 0..nv {
            for b in a + 1..nv {
                if let (Some(pa), Some(pb)) = (mv[a].at, mv[b].at) {
                    let sign = |d: f64| {
                        if d.abs() <= 1e-9 {
                            0
                        } else if d > 0.0 {
                            1
                        } else {
                            -1
                        }
                    };
                    spatial.push(SpatialPair { a, b, order: [sign(pb[0] - pa[0]), sign(pb[1] - pa[1])] });
                }
            }
        }
        spatial
    }

    /// The daughter options and their weights; each option's own variables
    /// are visible only to it (its per-run ones join `run_vars`).
    fn daughter_options(
        &mut self,
        p: &ProductionSyn,
        (mv, me): (&[MVertex], &[MEdge]),
        scope: &mut ProdScope,
        element_names: &[String],
        run_vars: &mut Vec<(u32, Program)>,
    ) -> (Vec<Daughter>, Vec<f64>) {
        let pname = &p.name.s;
        let nv = mv.len();
        let mut options = Vec::new();
        let mut weights = Vec::new();
        for o in &p.options {
            let w = match o.weight {
                Some((w, span)) if !(w.is_finite() && w >= 0.0) => {
                    self.error(span, "a weight must be a number ≥ 0");
                    0.0
                }
                Some((w, _)) => w,
                None => 1.0,
            };
            weights.push(w);
            let mark = scope.vars.len();
            let mut vars = Vec::new();
            let mut run_in_option = Vec::new();
            self.variables(&o.vars, scope, element_names, &mut run_in_option, &mut vars, nv);
            run_vars.extend(run_in_option);
            if let Some(d) = self.daughter(o, mv, me, scope, vars, pname) {
                options.push(d);
            }
            scope.vars.truncate(mark);
        }
        if !weights.is_empty() && weights.iter().all(|w| *w == 0.0) {
            self.error(p.name.span, format!("every daughter of `{pname}` has weight 0"));
        }
        (options, weights)
    }

    fn mother_vertex(&mut self, t: Option<&super::syntax::Text>, names: &[String], pname: &str) -> Option<usize> {
        let t = t?;
        match names.iter().position(|n| *n == t.s) {
            Some(i) => Some(i),
            None => {
                let d = self.error(t.span, format!("unknown vertex `{}` in the mother of `{pname}`", t.s));
                if let Some(s) = did_you_mean(&t.s, names.iter().map(String::as_str)) {
                    d.hints.push(format!("did you mean `{s}`?"));
                } else {
                    d.hints.push("list it under the mother's `vertices:` first".into());
                }
                None
            }
        }
    }

    /// Compiles variables in order (each sees the ones before it) and
    /// declares them in `scope`.
    fn variables(
        &mut self,
        vars: &[Variable],
        scope: &mut ProdScope,
        element_names: &[String],
        run: &mut Vec<(u32, Program)>,
        app: &mut Vec<(u32, Program)>,
        nv: usize,
    ) {
        for v in vars {
            let clash = element_names.contains(&v.name.s)
                || scope.vectors.iter().any(|(n, _)| *n == v.name.s)
                || scope.vars.iter().any(|(n, _)| *n == v.name.s)
                || scope.globals.iter().any(|(n, _)| *n == v.name.s);
            if clash {
                self.error(
                    v.name.span,
                    format!("variable `{}` has the name of another variable, global, vector or element", v.name.s),
                );
                continue;
            }
            let prog = match &v.value {
                Written::Num(x, _) => Some(constant_program(*x)),
                Written::Str(f) => self.scalar(f, &*scope, "a variable"),
            };
            let Some(prog) = prog else {
                // Declare anyway so later formulas do not report it unknown.
                scope.declare(&v.name.s, v.per_run);
                continue;
            };
            if v.per_run {
                let pairs = scope.pairs.clone();
                let (d, a) = deps(&prog, &scope.slots.borrow(), nv, &pairs);
                if !d.is_empty() || a {
                    self.error(v.value.span(), format!("per-run variable `{}` cannot read matched elements", v.name.s))
                        .hints
                        .push("it is drawn once, before any match; make it per application".into());
                }
            }
            let slot = scope.declare(&v.name.s, v.per_run);
            if v.per_run { run.push((slot, prog)) } else { app.push((slot, prog)) }
        }
    }
}
