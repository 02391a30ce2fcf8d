//! `.gg.yaml` text → [`GraphGrammar`], reporting every error found.

mod daughter;
mod production;
mod scope;
mod syntax;

use crate::grammar::{Daughter, GraphGrammar, Group};
use crate::graph::{Graph, NewAttrs, NewCommon, Value};
use crate::names::Interner;
use crate::yaml;
use genform_core::diag::{Diagnostic, Diagnostics, SourceFile, Span};
use genform_core::expr::vec2::{Compiled, compile_any};
use genform_core::expr::{Program, did_you_mean, parse};
use scope::{GlobalInfo, GlobalScope};
use std::collections::BTreeMap;
use std::sync::Arc;
use syntax::{Element, FileSyn, Formula, GraphSyn, Reader, Written};

/// Compiles a `.gg.yaml` file. Returns the grammar and its warnings, or
/// every error found (bad YAML stops at the first YAML error; everything
/// else is collected).
pub fn compile(file: &SourceFile) -> Result<(GraphGrammar, Diagnostics), Diagnostics> {
    let mut diags = Diagnostics::new(file.clone());
    let root = match yaml::parse(&file.text) {
        Ok(n) => n,
        Err(d) => {
            diags.push(d);
            return Err(diags);
        }
    };
    let mut reader = Reader { text: &file.text, errors: Vec::new() };
    let syn = reader.file(&root);
    let mut cx =
        Cx { errors: reader.errors, warnings: Vec::new(), labels: Interner::default(), attrs: Interner::default() };
    cx.collect_names(&syn);
    let globals = cx.globals(&syn.globals);
    let host = cx.host(&syn.host, &globals.0);
    let mut productions = Vec::new();
    let mut seen: Vec<(&str, Span)> = Vec::new();
    for p in &syn.productions {
        if let Some((_, first)) = seen.iter().find(|(n, _)| *n == p.name.s) {
            cx.errors.push(
                Diagnostic::error(p.name.span, format!("production `{}` is defined twice", p.name.s))
                    .with_label(*first, "first defined here"),
            );
        }
        seen.push((&p.name.s, p.name.span));
        if let Some(prod) = cx.production(p, &globals.0) {
            productions.push((p.priority, prod));
        }
    }
    let groups = cx.groups(&syn, &productions);
    for w in cx.warnings {
        diags.push(w);
    }
    if !cx.errors.is_empty() {
        // In file order, as people read them.
        cx.errors.sort_by_key(|d| d.span.map(|s| s.start));
        for e in cx.errors {
            diags.push(e);
        }
        return Err(diags);
    }
    let track = productions.iter().any(|(_, p)| p.oldest);
    let new_elements = productions.iter_mut().flat_map(|(_, p)| &mut p.options).flat_map(|o| {
        o.new_vertices.iter_mut().map(|v| &mut v.list_key).chain(o.new_edges.iter_mut().map(|e| &mut e.list_key))
    });
    for (k, key) in new_elements.enumerate() {
        *key = k as u32;
    }
    let most =
        |count: fn(&Daughter) -> usize| productions.iter().flat_map(|(_, p)| &p.options).map(count).max().unwrap_or(0);
    let new_per_step = [most(|o| o.new_vertices.len()), most(|o| o.new_edges.len())];
    let host = build_host(host, cx.labels, cx.attrs, track);
    let name = match &syn.name {
        Some(n) => n.s.clone(),
        None => {
            let base = file.name.rsplit(['/', '\\']).next().unwrap_or("");
            base.trim_end_matches(".yaml").trim_end_matches(".yml").trim_end_matches(".gg").to_string()
        }
    };
    let grammar = GraphGrammar {
        name,
        host,
        steps: syn.steps.map(|(n, _)| n),
        time_limit: syn.time_limit.map_or(crate::derive::DEFAULT_TIME_LIMIT, std::time::Duration::from_secs_f64),
        groups,
        new_per_step,
        productions: productions.into_iter().map(|(_, p)| p).collect(),
        globals: globals.1,
        source: file.clone(),
    };
    Ok((grammar, diags))
}

type Attrs = Vec<(u32, Value)>;

/// The host graph's elements, before the name tables are complete:
/// vertices (position, label, attributes) and edges (ends as vertex
/// indices, directed, label, attributes).
struct HostParts {
    vertices: Vec<([f64; 2], u32, Attrs)>,
    edges: Vec<(usize, usize, bool, u32, Attrs)>,
}

fn build_host(parts: HostParts, labels: Interner, attrs: Interner, track: bool) -> Graph {
    let mut g = Graph::empty(labels, Arc::new(attrs), track);
    let ids: Vec<u32> = parts
        .vertices
        .into_iter()
        .map(|(pos, label, mut attrs)| {
            g.add_vertex(pos, NewCommon { label, generation: 0, attrs: NewAttrs::List(&mut attrs) })
        })
        .collect();
    for (a, b, directed, label, mut attrs) in parts.edges {
        g.add_edge(ids[a], ids[b], directed, NewCommon { label, generation: 0, attrs: NewAttrs::List(&mut attrs) });
    }
    g
}

/// Keys an element may carry, per place.
#[derive(Clone, Copy, PartialEq, Eq)]
pub(crate) enum Place {
    HostVertex,
    HostEdge,
    MotherVertex,
    MotherEdge,
    DaughterVertex,
    DaughterEdge,
}

impl Place {
    fn describe(self) -> &'static str {
        match self {
            Place::HostVertex => "a host vertex",
            Place::HostEdge => "a host edge",
            Place::MotherVertex => "a mother vertex",
            Place::MotherEdge => "a mother edge",
            Place::DaughterVertex => "a daughter vertex",
            Place::DaughterEdge => "a daughter edge",
        }
    }
}

pub(crate) struct Cx {
    pub(crate) errors: Vec<Diagnostic>,
    pub(crate) warnings: Vec<Diagnostic>,
    pub(crate) labels: Interner,
    pub(crate) attrs: Interner,
}

impl Cx {
    pub(crate) fn error(&mut self, span: Span, msg: impl Into<String>) -> &mut Diagnostic {
        self.errors.push(Diagnostic::error(span, msg));
        self.errors.last_mut().expect("just pushed")
    }

    /// Interns every attribute name and literal label in file order, so
    /// formulas can check `A.attr` names and ids are stable.
    fn collect_names(&mut self, syn: &FileSyn) {
        let mut graphs: Vec<&GraphSyn> = vec![&syn.host];
        for p in &syn.productions {
            graphs.push(&p.mother);
            graphs.extend(p.options.iter().map(|o| &o.graph));
        }
        for g in graphs {
            for e in g.vertices.iter().chain(&g.edges) {
                for (name, _) in &e.attrs {
                    self.attrs.intern(&name.s);
                }
                if let Some(l) = &e.label
                    && !l.s.contains(['{', '}'])
                {
                    self.labels.intern(&l.s);
                }
            }
        }
    }

    /// Reports keys `e` has that do not belong in `place`.
    pub(crate) fn check_keys(&mut self, e: &Element, place: Place) {
        use Place::*;
        let vertex = matches!(place, HostVertex | MotherVertex | DaughterVertex);
        let present: [(&str, Option<Span>); 11] = [
            ("label", e.label.as_ref().map(|f| f.span)),
            ("when", e.when.as_ref().map(|f| f.span)),
            ("wildcard", e.wildcard.map(|w| w.1)),
            ("at", e.at.map(|a| a.1)),
            ("keep", e.keep.as_ref().map(|k| k.span)),
            ("pos", e.pos.as_ref().map(|f| f.span)),
            ("x", e.x.as_ref().map(Written::span)),
            ("y", e.y.as_ref().map(Written::span)),
            ("from", e.from.as_ref().map(|t| t.span)),
            ("to", e.to.as_ref().map(|t| t.span)),
            ("directed", e.directed.map(|d| d.1)),
        ];
        for (key, span) in present {
            let Some(span) = span else { continue };
            let ok = match key {
                "label" => true,
                "when" => matches!(place, MotherVertex | MotherEdge),
                "wildcard" => place == MotherVertex,
                "at" => matches!(place, MotherVertex | DaughterVertex),
                "keep" => matches!(place, DaughterVertex | DaughterEdge),
                "pos" => place == DaughterVertex,
                "x" | "y" => matches!(place, HostVertex | DaughterVertex),
                _ => !vertex,
            };
            if ok {
                continue;
            }
            let hint = match (key, place) {
                ("x" | "y", MotherVertex) => {
                    "positions take no part in matching: test them in a condition \
                     (`when: \"A.x > 0\"`), or give the vertex's place in the production's drawing with `at: [x, y]`"
                }
                ("x" | "y" | "pos" | "at", _) if !vertex => "edges have no position; their ends do",
                ("at", HostVertex) => "host vertices have `x` and `y`; `at` is a position in a production's drawing",
                ("pos", HostVertex) => "write `x:` and `y:`",
                ("pos", MotherVertex) => "positions take no part in matching: test them in a condition",
                ("when", _) => "conditions belong to the mother graph, which is what is matched",
                ("wildcard", _) => "wildcards are mother vertices that match any vertex",
                ("keep", _) => "`keep` maps a daughter element to a mother element",
                ("from" | "to" | "directed", _) => "edges are listed under `edges:`",
                _ => "",
            };
            let d = self.error(span, format!("`{key}` does not belong to {}", place.describe()));
            if !hint.is_empty() {
                d.hints.push(hint.to_string());
            }
        }
    }

    /// Parses and compiles a formula (number or vector) against `scope`;
    /// errors are placed in the file and reported.
    pub(crate) fn formula(&mut self, f: &Formula, scope: &dyn genform_core::expr::vec2::VecScope) -> Option<Compiled> {
        let ast = match parse(&f.s) {
            Ok(a) => a,
            Err(d) => {
                self.errors.push(f.pos.place(d));
                return None;
            }
        };
        match compile_any(&ast, scope) {
            Ok(c) => Some(c),
            Err(ds) => {
                self.errors.extend(ds.into_iter().map(|d| f.pos.place(d)));
                None
            }
        }
    }

    /// A number formula.
    pub(crate) fn scalar(
        &mut self,
        f: &Formula,
        scope: &dyn genform_core::expr::vec2::VecScope,
        what: &str,
    ) -> Option<Program> {
        match self.formula(f, scope)? {
            Compiled::Scalar(p) => Some(p),
            Compiled::Vector(_) => {
                self.error(f.content_span(), format!("{what} must be a number, found a vector"))
                    .hints
                    .push("use `norm(v)` for a length, or `v.x` / `v.y` for a component".into());
                None
            }
        }
    }

    /// Globals in file order: constants are folded, the rest evaluated once
    /// per run.
    fn globals(&mut self, gs: &[(syntax::Text, Written)]) -> (Vec<(String, GlobalInfo)>, Vec<Program>) {
        let mut list: Vec<(String, GlobalInfo)> = Vec::new();
        let mut programs = Vec::new();
        for (name, w) in gs {
            if list.iter().any(|(n, _)| *n == name.s) {
                self.error(name.span, format!("global `{}` is defined twice", name.s));
                continue;
            }
            let info = match w {
                Written::Num(v, _) => GlobalInfo::Const(*v),
                Written::Str(f) => {
                    let scope = GlobalScope { before: &list };
                    match self.scalar(f, &scope, "a global") {
                        Some(p) => match p.constant() {
                            Some(v) if !p.uses_rng() => GlobalInfo::Const(v),
                            _ => {
                                programs.push(p);
                                GlobalInfo::Formula(programs.len() - 1)
                            }
                        },
                        // Keep later formulas from reporting it as unknown.
                        None => GlobalInfo::Const(f64::NAN),
                    }
                }
            };
            list.push((name.s.clone(), info));
        }
        (list, programs)
    }

    /// A host coordinate: a number or a formula of constants.
    fn host_number(&mut self, w: &Written, globals: &[(String, GlobalInfo)]) -> f64 {
        // A NaN or infinite coordinate would silently vanish from drawings.
        let finite = |cx: &mut Self, v: f64, span: Span| {
            if v.is_finite() {
                return v;
            }
            cx.error(span, format!("a host coordinate must be a finite number, not {v}"));
            0.0
        };
        match w {
            Written::Num(v, span) => finite(self, *v, *span),
            Written::Str(f) => {
                let scope = GlobalScope { before: globals };
                match self.scalar(f, &scope, "a host coordinate") {
                    Some(p) if p.loads().next().is_none() && !p.uses_rng() => {
                        let v = p.eval(&[]);
                        finite(self, v, f.content_span())
                    }
                    Some(_) => {
                        self.error(f.content_span(), "a host coordinate must be a constant")
                            .hints
                            .push("it may use numbers, constant globals and functions, not random draws".into());
                        0.0
                    }
                    None => 0.0,
                }
            }
        }
    }

    fn host(&mut self, g: &GraphSyn, globals: &[(String, GlobalInfo)]) -> HostParts {
        let mut parts = HostParts { vertices: Vec::new(), edges: Vec::new() };
        let mut names: Vec<&str> = Vec::new();
        for v in &g.vertices {
            self.check_keys(v, Place::HostVertex);
            let name = v.name.as_ref().map_or("", |n| n.s.as_str());
            if names.contains(&name) {
                self.error(v.span, format!("host vertex `{name}` is listed twice"));
            }
            names.push(name);
            let x = v.x.as_ref().map_or(0.0, |w| self.host_number(w, globals));
            let y = v.y.as_ref().map_or(0.0, |w| self.host_number(w, globals));
            let label = v.label.as_ref().map_or(0, |l| self.labels.intern(&l.s));
            let attrs = self.literal_attrs(v);
            parts.vertices.push(([x, y], label, attrs));
        }
        let mut edge_names: Vec<&str> = Vec::new();
        for e in &g.edges {
            self.check_keys(e, Place::HostEdge);
            if let Some(n) = &e.name {
                if edge_names.contains(&n.s.as_str()) {
                    self.error(n.span, format!("host edge `{}` is named twice", n.s));
                }
                edge_names.push(&n.s);
            }
            let ends = [&e.from, &e.to].map(|end| match end {
                Some(t) => match names.iter().position(|n| *n == t.s) {
                    Some(i) => Some(i),
                    None => {
                        let d = self.error(t.span, format!("unknown host vertex `{}`", t.s));
                        if let Some(s) = did_you_mean(&t.s, names.iter().copied()) {
                            d.hints.push(format!("did you mean `{s}`?"));
                        }
                        None
                    }
                },
                None => None,
            });
            if e.from.is_none() || e.to.is_none() {
                self.error(e.span, "an edge needs `from` and `to`");
            }
            let label = e.label.as_ref().map_or(0, |l| self.labels.intern(&l.s));
            let attrs = self.literal_attrs(e);
            if let [Some(a), Some(b)] = ends {
                parts.edges.push((a, b, e.directed.is_some_and(|d| d.0), label, attrs));
            }
        }
        parts
    }

    /// Attributes as literal values (host data, mother constraints).
    pub(crate) fn literal_attrs(&mut self, e: &Element) -> Vec<(u32, Value)> {
        let mut out: Vec<(u32, Value)> = Vec::new();
        for (name, w) in &e.attrs {
            let id = self.attrs.intern(&name.s);
            if out.iter().any(|(a, _)| *a == id) {
                self.error(name.span, format!("attribute `{}` is given twice", name.s));
                continue;
            }
            let v = match w {
                Written::Num(v, _) => Value::Num(*v),
                Written::Str(f) => Value::Text(Arc::from(f.s.as_str())),
            };
            out.push((id, v));
        }
        out.sort_by_key(|(a, _)| *a);
        out
    }

    fn groups(&mut self, syn: &FileSyn, productions: &[(i64, crate::grammar::Production)]) -> Vec<Group> {
        let mut by: BTreeMap<i64, Vec<usize>> = BTreeMap::new();
        for (i, (prio, _)) in productions.iter().enumerate() {
            by.entry(*prio).or_default().push(i);
        }
        for (prio, span, _) in &syn.limits {
            if !by.contains_key(prio) {
                self.warnings.push(Diagnostic::warning(*span, format!("no production has priority {prio}")));
            }
        }
        by.into_iter()
            .map(|(priority, members)| Group {
                cap: syn.limits.iter().rev().find(|(p, _, _)| *p == priority).map(|(_, _, n)| *n),
                members,
            })
            .collect()
    }
}
