//! One daughter option of a production: which mother elements it keeps,
//! deletes and adds, and the formulas of the new values.

use super::Cx;
use super::Place;
use super::production::constant_program;
use super::scope::ProdScope;
use super::syntax::{Element, Formula, OptionSyn, Text, Written};
use crate::grammar::{AttrSpec, Coord, DEdge, DVertex, Daughter, End, LabelSpec};
use crate::graph::Value;
use crate::mother::{MEdge, MVertex};
use crate::template::Template;
use genform_core::Rng;
use genform_core::diag::{Diagnostic, Span};
use genform_core::expr::vec2::Compiled;
use genform_core::expr::{Program, did_you_mean};
use std::sync::Arc;

impl Cx {
    /// A daughter formula: number or vector as `want_vector` says.
    fn daughter_formula(
        &mut self,
        f: &Formula,
        scope: &ProdScope,
        new_names: &[String],
        vector: bool,
    ) -> Option<Compiled> {
        let before = self.errors.len();
        let c = self.formula(f, scope);
        self.explain_new_names(before, new_names);
        let c = c?;
        match (c, vector) {
            (Compiled::Vector(v), true) => Some(Compiled::Vector(v)),
            (Compiled::Scalar(s), false) => Some(Compiled::Scalar(s)),
            (_, true) => {
                self.error(f.content_span(), "`pos` must be a vector, found a number")
                    .hints
                    .push("write a point such as `A + v / 2`, or `vec(x, y)`".into());
                None
            }
            (_, false) => {
                self.error(f.content_span(), "expected a number, found a vector")
                    .hints
                    .push("use `norm(v)` for a length, or `v.x` / `v.y` for a component".into());
                None
            }
        }
    }

    /// Rewords "unknown name" errors about elements the daughter adds.
    fn explain_new_names(&mut self, from: usize, new_names: &[String]) {
        for d in &mut self.errors[from..] {
            let Some(rest) = d.message.strip_prefix("unknown name `") else { continue };
            let name = rest.trim_end_matches('`');
            let base = name.split('.').next().unwrap_or(name);
            if new_names.iter().any(|n| n == base) {
                d.message = format!("`{base}` is added by this daughter; formulas read only the matched elements");
                d.hints = vec!["compute from the mother's elements, vectors and variables".into()];
            }
        }
    }

    fn template(&mut self, f: &Formula, scope: &ProdScope, new_names: &[String]) -> Option<Template> {
        let before = self.errors.len();
        let t = Template::compile(&f.s, &f.pos, scope);
        match t {
            Ok(t) => Some(t),
            Err(ds) => {
                self.errors.extend(ds);
                self.explain_new_names(before, new_names);
                None
            }
        }
    }

    fn label_spec(&mut self, f: &Formula, scope: &ProdScope, new_names: &[String]) -> Option<LabelSpec> {
        let t = self.template(f, scope, new_names)?;
        Some(if t.is_literal() {
            LabelSpec::Fixed(self.labels.intern(&t.text(&[], &mut Rng::from_seed(0))))
        } else {
            LabelSpec::Template(t)
        })
    }

    fn attr_specs(&mut self, e: &Element, scope: &ProdScope, new_names: &[String]) -> Vec<(u32, AttrSpec)> {
        let mut out: Vec<(u32, AttrSpec)> = Vec::new();
        for (name, w) in &e.attrs {
            let id = scope.attrs.get(&name.s).unwrap_or(0);
            if out.iter().any(|(a, _)| *a == id) {
                self.error(name.span, format!("attribute `{}` is given twice", name.s));
                continue;
            }
            let spec = match w {
                Written::Num(v, _) => AttrSpec::Value(Value::Num(*v)),
                Written::Str(f) => match self.template(f, scope, new_names) {
                    Some(t) if t.is_literal() => {
                        AttrSpec::Value(Value::Text(Arc::from(t.text(&[], &mut Rng::from_seed(0)))))
                    }
                    Some(t) => AttrSpec::Template(t),
                    None => continue,
                },
            };
            out.push((id, spec));
        }
        out
    }

    fn coord(&mut self, w: &Written, scope: &ProdScope, new_names: &[String]) -> Option<Coord> {
        match w {
            Written::Num(v, _) => Some(Coord::Formula(constant_program(*v))),
            Written::Str(f) => match self.daughter_formula(f, scope, new_names, false)? {
                Compiled::Scalar(p) => Some(Coord::Formula(p)),
                Compiled::Vector(_) => None,
            },
        }
    }

    /// Compiles one daughter option of production `pname` over the mother
    /// vertices `mv` and edges `me`, in two passes: the daughter's vertices
    /// ([`Cx::daughter_vertices`]: kept, moved or new, with their
    /// positions), then its edges ([`Cx::daughter_edges`]), which join the
    /// ends the first pass named. `None` when it reported an error.
    pub(super) fn daughter(
        &mut self,
        o: &OptionSyn,
        mv: &[MVertex],
        me: &[MEdge],
        scope: &ProdScope,
        vars: Vec<(u32, Program)>,
        pname: &str,
    ) -> Option<Daughter> {
        let errors_before = self.errors.len();
        let m = Mother { vertices: mv, edges: me, scope, production: pname, new_names: new_names(o, mv, me) };
        let mut d = Daughter {
            vars,
            delete_vertices: Vec::new(),
            delete_edges: Vec::new(),
            kept_vertices: Vec::new(),
            kept_edges: Vec::new(),
            new_vertices: Vec::new(),
            new_edges: Vec::new(),
            placement: false,
        };
        let ends = self.daughter_vertices(o, &m, &mut d);
        self.daughter_edges(o, &m, &ends, &mut d);
        if self.errors.len() > errors_before { None } else { Some(d) }
    }

    /// The vertex pass: each daughter vertex kept (`keep:` or its mother's
    /// name) or new, with its position, label and attributes; then which
    /// mother vertices are deleted and whether automatic placement runs.
    /// Returns every daughter vertex name's edge end; wildcards are ends
    /// without being listed.
    fn daughter_vertices(&mut self, o: &OptionSyn, m: &Mother, d: &mut Daughter) -> Vec<(String, End)> {
        let mv = m.vertices;
        let mut ends: Vec<(String, End)> =
            mv.iter().enumerate().filter(|(_, v)| v.wildcard).map(|(i, v)| (v.name.clone(), End::Mother(i))).collect();
        let mut kept_v: Vec<Option<Span>> = vec![None; mv.len()];
        let mut first_auto: Option<Span> = None;
        for v in &o.graph.vertices {
            self.check_keys(v, Place::DaughterVertex);
            let name = v.name();
            let span = v.name_span();
            if ends.iter().any(|(n, _)| *n == name) {
                let msg = if mv.iter().any(|m| m.wildcard && m.name == name) {
                    format!("wildcard `{name}` cannot appear in a daughter")
                } else {
                    format!("vertex `{name}` is listed twice in this daughter")
                };
                self.error(span, msg)
                    .hints
                    .push("a wildcard is kept unchanged; daughter edges may still connect to it".into());
                continue;
            }
            let Some(target) = self.vertex_target(v, &name, m) else { continue };
            if let Some(i) = target {
                if mv[i].wildcard {
                    self.error(span, format!("wildcard `{}` cannot appear in a daughter", mv[i].name))
                        .hints
                        .push("a wildcard is kept unchanged; daughter edges may still connect to it".into());
                    continue;
                }
                if let Some(first) = kept_v[i] {
                    self.errors.push(
                        Diagnostic::error(span, format!("mother vertex `{}` is kept twice", mv[i].name))
                            .with_label(first, "first kept here"),
                    );
                    continue;
                }
                kept_v[i] = Some(span);
            }
            let (pos, pos_spans, auto) = self.vertex_position(v, &name, target, m);
            if auto {
                first_auto.get_or_insert(span);
            }
            let at = v.at.map(|a| a.0);
            let label = v.label.as_ref().and_then(|l| self.label_spec(l, m.scope, &m.new_names));
            let attrs = self.attr_specs(v, m.scope, &m.new_names);
            let dv = DVertex { mother: target, label, pos, pos_spans, at, attrs, list_key: 0 };
            match target {
                Some(i) => {
                    ends.push((name, End::Mother(i)));
                    d.kept_vertices.push(dv);
                }
                None => {
                    ends.push((name, End::New(d.new_vertices.len())));
                    d.new_vertices.push(dv);
                }
            }
        }
        if let Some(span) = first_auto {
            d.placement = true;
            if let Some(m) = mv.iter().find(|m| m.at.is_none()) {
                self.error(
                    span,
                    format!("automatic placement needs `at: [x, y]` on every mother vertex; `{}` has none", m.name),
                )
                .hints
                .push("or give this vertex `pos`, or `x` and `y`".into());
            }
        }
        d.delete_vertices = (0..mv.len()).filter(|&i| kept_v[i].is_none() && !mv[i].wildcard).collect();
        ends
    }

    /// The mother vertex daughter vertex `v` (named `name`) keeps:
    /// `Some(None)` for a new vertex, `None` after reporting a `keep:` or
    /// name that is no mother vertex.
    fn vertex_target(&mut self, v: &Element, name: &str, m: &Mother) -> Option<Option<usize>> {
        let (mv, me) = (m.vertices, m.edges);
        match &v.keep {
            Some(k) => {
                let vertices: Vec<&str> = mv.iter().map(|x| x.name.as_str()).collect();
                let edges: Vec<&str> = me.iter().map(|x| x.name.as_str()).collect();
                self.kept(k, &vertices, &edges, ("vertex", "edge"), m.production).map(Some)
            }
            None => {
                if me.iter().any(|m| m.name == name) {
                    self.error(
                        v.name_span(),
                        format!("`{name}` names a mother edge; a daughter vertex cannot keep an edge"),
                    );
                    return None;
                }
                Some(mv.iter().position(|m| m.name == name))
            }
        }
    }

    /// The position of daughter vertex `v`: `pos`, or `x` and `y`, each
    /// coordinate not given kept, or placed automatically when the vertex
    /// moves (`at:` differs from its mother's). Returns the coordinates,
    /// their spans and whether automatic placement is asked for.
    fn vertex_position(
        &mut self,
        v: &Element,
        name: &str,
        target: Option<usize>,
        m: &Mother,
    ) -> ([Coord; 2], [Option<Span>; 2], bool) {
        let mut pos = [Coord::Keep, Coord::Keep];
        let mut pos_spans = [None; 2];
        let mut given = [false; 2];
        if let Some(f) = &v.pos {
            pos_spans = [Some(f.content_span()); 2];
            if v.x.is_some() || v.y.is_some() {
                self.error(f.content_span(), "give either `pos` or `x`/`y`, not both");
            }
            if let Some(Compiled::Vector([x, y])) = self.daughter_formula(f, m.scope, &m.new_names, true) {
                pos = [Coord::Formula(x), Coord::Formula(y)];
            }
            given = [true; 2];
        }
        for (k, w) in [&v.x, &v.y].into_iter().enumerate() {
            if let Some(w) = w {
                given[k] = true;
                pos_spans[k] = Some(w.span());
                if let Some(c) = self.coord(w, m.scope, &m.new_names) {
                    pos[k] = c;
                }
            }
        }
        let moved = match (target, v.at.map(|a| a.0)) {
            (None, Some(_)) => true,
            (Some(i), Some(a)) => m.vertices[i].at != Some(a),
            (_, None) => false,
        };
        let mut auto = false;
        if !(given[0] && given[1]) {
            if moved {
                for k in 0..2 {
                    if !given[k] {
                        pos[k] = Coord::Auto;
                    }
                }
                auto = true;
            } else if target.is_none() {
                self.error(v.name_span(), format!("new vertex `{name}` needs a position"))
                    .hints
                    .push("give `pos`, or `x` and `y`, or `at: [x, y]` to place it automatically".into());
            }
        }
        (pos, pos_spans, auto)
    }

    /// The edge pass: each daughter edge kept (`keep:` or its mother's
    /// name, joining the same vertices) or new, between the `ends` the
    /// vertex pass named; then which mother edges are deleted.
    fn daughter_edges(&mut self, o: &OptionSyn, m: &Mother, ends: &[(String, End)], d: &mut Daughter) {
        let me = m.edges;
        let mut kept_e: Vec<Option<Span>> = vec![None; me.len()];
        let mut edge_names: Vec<String> = Vec::new();
        for e in &o.graph.edges {
            self.check_keys(e, Place::DaughterEdge);
            let (Some(from), Some(to)) = (&e.from, &e.to) else {
                self.error(e.span, "an edge needs `from` and `to`");
                continue;
            };
            let name = e.name();
            if edge_names.contains(&name) {
                self.error(e.name_span(), format!("edge `{name}` is listed twice in this daughter"))
                    .hints
                    .push("name parallel edges with `name:`".into());
                continue;
            }
            edge_names.push(name.clone());
            let (a, b) = (self.edge_end(from, ends, m), self.edge_end(to, ends, m));
            let Some(target) = self.edge_target(e, &name, m) else { continue };
            let (Some(a), Some(b)) = (a, b) else { continue };
            if let Some(i) = target
                && !self.keeps_edge(e, i, (a, b), &mut kept_e, m)
            {
                continue;
            }
            let label = e.label.as_ref().and_then(|l| self.label_spec(l, m.scope, &m.new_names));
            let attrs = self.attr_specs(e, m.scope, &m.new_names);
            let directed = e.directed.map(|d| d.0);
            let de = DEdge {
                mother: target,
                from: a,
                to: b,
                directed: if target.is_some() { directed } else { Some(directed.unwrap_or(false)) },
                label,
                attrs,
                list_key: 0,
            };
            if target.is_some() {
                d.kept_edges.push(de);
            } else {
                d.new_edges.push(de);
            }
        }
        d.delete_edges = (0..me.len()).filter(|&i| kept_e[i].is_none()).collect();
    }

    /// The end an edge's `from`/`to` names among the daughter's `ends`, or
    /// `None` after reporting a deleted or unknown vertex.
    fn edge_end(&mut self, t: &Text, ends: &[(String, End)], m: &Mother) -> Option<End> {
        if let Some((_, end)) = ends.iter().find(|(n, _)| *n == t.s) {
            return Some(*end);
        }
        if m.vertices.iter().any(|v| v.name == t.s) {
            self.error(t.span, format!("`{}` is deleted by this daughter, so no edge can reach it", t.s))
                .hints
                .push(format!("list `{}: {{}}` under the daughter's vertices to keep it", t.s));
        } else {
            let d = self.error(t.span, format!("unknown vertex `{}` in a daughter of `{}`", t.s, m.production));
            if let Some(s) = did_you_mean(&t.s, ends.iter().map(|(n, _)| n.as_str())) {
                d.hints.push(format!("did you mean `{s}`?"));
            }
        }
        None
    }

    /// The mother edge daughter edge `e` (named `name`) keeps: `Some(None)`
    /// for a new edge, `None` after reporting a `keep:` that names no mother
    /// edge.
    fn edge_target(&mut self, e: &Element, name: &str, m: &Mother) -> Option<Option<usize>> {
        let (mv, me) = (m.vertices, m.edges);
        match &e.keep {
            Some(k) => {
                let vertices: Vec<&str> = mv.iter().map(|x| x.name.as_str()).collect();
                let edges: Vec<&str> = me.iter().map(|x| x.name.as_str()).collect();
                self.kept(k, &edges, &vertices, ("edge", "vertex"), m.production).map(Some)
            }
            None => Some(me.iter().position(|m| m.name == name)),
        }
    }

    /// The mother element `keep: NAME` names among `own` (the names of the
    /// mother's elements of the daughter element's kind), or `None` after
    /// reporting that it names one of the `other` kind, or none at all
    /// (with a did-you-mean). `kinds`: (own, other), e.g. ("vertex", "edge").
    fn kept(
        &mut self,
        keep: &Text,
        own: &[&str],
        other: &[&str],
        kinds: (&str, &str),
        production: &str,
    ) -> Option<usize> {
        if let Some(i) = own.iter().position(|n| *n == keep.s) {
            return Some(i);
        }
        let (kind, other_kind) = kinds;
        if other.contains(&keep.s.as_str()) {
            self.error(
                keep.span,
                format!("`keep: {}` names a mother {other_kind}; a {kind} can keep only a {kind}", keep.s),
            );
        } else {
            let d =
                self.error(keep.span, format!("`keep: {}` names no {kind} of the mother of `{production}`", keep.s));
            if let Some(s) = did_you_mean(&keep.s, own.iter().copied()) {
                d.hints.push(format!("did you mean `{s}`?"));
            }
        }
        None
    }

    /// Whether daughter edge `e`, joining `ends`, may keep mother edge `i`:
    /// it must join the same vertices and keep it only once (`kept` records
    /// where each mother edge was first kept). Reports why not.
    fn keeps_edge(&mut self, e: &Element, i: usize, ends: (End, End), kept: &mut [Option<Span>], m: &Mother) -> bool {
        let me = &m.edges[i];
        let same = matches!(ends, (End::Mother(x), End::Mother(y))
            if (x, y) == (me.from, me.to) || (x, y) == (me.to, me.from));
        if !same {
            self.error(
                e.name_span(),
                format!(
                    "kept edge `{}` must join the vertices its mother edge joins (`{}` and `{}`)",
                    me.name, m.vertices[me.from].name, m.vertices[me.to].name
                ),
            )
            .hints
            .push("give the daughter edge another name to delete the old edge and add a new one".into());
            return false;
        }
        if let Some(first) = kept[i] {
            self.errors.push(
                Diagnostic::error(e.name_span(), format!("mother edge `{}` is kept twice", me.name))
                    .with_label(first, "first kept here"),
            );
            return false;
        }
        kept[i] = Some(e.name_span());
        true
    }
}

/// The mother a daughter rewrites, and what its passes share.
struct Mother<'a> {
    vertices: &'a [MVertex],
    edges: &'a [MEdge],
    /// The names daughter formulas read.
    scope: &'a ProdScope<'a>,
    /// The production's name, for messages.
    production: &'a str,
    /// Names of the elements the daughter adds (formulas cannot read them).
    new_names: Vec<String>,
}

/// The names of the vertices and edges daughter `o` adds: those that are
/// no mother element's.
fn new_names(o: &OptionSyn, mv: &[MVertex], me: &[MEdge]) -> Vec<String> {
    o.graph
        .vertices
        .iter()
        .chain(&o.graph.edges)
        .map(Element::name)
        .filter(|n| !mv.iter().any(|m| m.name == *n) && !me.iter().any(|m| m.name == *n))
        .collect()
}
