//! Applying a production at a match, in place (single-pushout).
//!
//! Every new value (variables, positions, attributes, labels) is computed
//! first, from the match as it is; then unmatched mother elements are
//! deleted (a deleted vertex takes its remaining edges with it), kept
//! elements updated and daughter-only elements added. New elements get the
//! match's largest generation + 1.

use crate::grammar::{AttrSpec, Coord, DEdge, DVertex, Daughter, End, LabelSpec, Production};
use crate::graph::{Graph, NewAttrs, NewCommon, Value};
use crate::placement::Similarity;
use crate::table::grown;
use genform_core::rng::Draws;

/// Per new daughter element (by its `list_key`): `None` until its list is
/// looked at, then the set of the list when it is all constants.
type ConstantSets = Vec<Option<Option<u32>>>;

/// Reused buffers of one derivation.
#[derive(Default)]
pub(crate) struct Scratch {
    m_points: Vec<[f64; 2]>,
    h_points: Vec<[f64; 2]>,
    hints: Vec<(usize, usize)>,
    kept_v: Vec<Pending>,
    kept_e: Vec<Pending>,
    new_v: Vec<Pending>,
    new_e: Vec<Pending>,
    new_ids: Vec<u32>,
    text: String,
    attrs: Vec<(u32, Value)>,
    /// The graph's set of each daughter element's attribute list that is
    /// all constants, by the element's `list_key`, so each list is looked at
    /// once; the entry holds one user of the set, so its id stays valid.
    /// Koch's new edges all carry one such list: looking it up once saves
    /// cloning, sorting and hashing it at every step, and a dense key a
    /// hash-map probe.
    constant: ConstantSets,
}

impl Scratch {
    /// Gives back the users the cache of constant lists holds.
    pub(crate) fn release(&mut self, g: &mut Graph) {
        for id in self.constant.drain(..).flatten().flatten() {
            g.attr_sets.release(id);
        }
    }
}

#[derive(Default)]
struct Pending {
    label: Option<u32>,
    pos: [f64; 2],
    attrs: Vec<(u32, Value)>,
    /// Set instead of `attrs` when the list is all constants.
    interned: Option<u32>,
}

/// The graph's set for `specs` (the list of the new daughter element
/// `key`) when it is a non-empty list of constants (interned on first use
/// and cached), else `None`.
fn constant_set(g: &mut Graph, specs: &[(u32, AttrSpec)], key: u32, cache: &mut ConstantSets) -> Option<u32> {
    if specs.is_empty() {
        return None;
    }
    *grown(cache, key as usize).get_or_insert_with(|| {
        let constants: Option<Vec<(u32, Value)>> = specs
            .iter()
            .map(|(a, s)| match s {
                AttrSpec::Value(v) => Some((*a, v.clone())),
                AttrSpec::Template(_) => None,
            })
            .collect();
        constants.map(|mut list| {
            list.sort_by_key(|(a, _)| *a);
            g.attr_sets.intern(&list)
        })
    })
}

/// Applies option `opt` of production `p` at the match (`mv`, `me`: host
/// ids per mother vertex and edge); `env` holds the match's loaded values.
/// A daughter position that is not a finite number is the error (its
/// value and where its formula is written), and the graph is then left
/// unchanged.
#[allow(clippy::too_many_arguments)]
pub(crate) fn apply(
    g: &mut Graph,
    p: &Production,
    opt: &Daughter,
    env: &mut [f64],
    mv: &[u32],
    me: &[u32],
    choices: &mut impl Draws,
    s: &mut Scratch,
) -> Result<(), (f64, Option<genform_core::diag::Span>)> {
    for (slot, prog) in p.app_vars.iter().chain(&opt.vars) {
        env[*slot as usize] = prog.eval_draws(env, choices);
    }
    let generation = 1 + mv
        .iter()
        .map(|&v| g.vertices[v as usize].c.generation)
        .chain(me.iter().map(|&e| g.edges[e as usize].c.generation))
        .max()
        .unwrap_or(0);
    let place = opt.placement.then(|| {
        s.m_points.clear();
        s.h_points.clear();
        s.hints.clear();
        for (i, m) in p.mv.iter().enumerate() {
            s.m_points.push(m.at.unwrap_or_default());
            s.h_points.push(g.vertices[mv[i] as usize].pos);
        }
        s.hints.extend(p.me.iter().filter(|e| e.directed && e.from != e.to).map(|e| (e.from, e.to)));
        let n = p.mv.len();
        for i in 0..n {
            for j in (i + 1..n).rev() {
                s.hints.push((i, j));
            }
        }
        Similarity::fit(&s.m_points, &s.h_points, &s.hints)
    });

    // Everything new is computed before the graph changes.
    let eval_vertex =
        |g: &mut Graph, d: &DVertex, old: Option<[f64; 2]>, out: &mut Pending, ch: &mut _, buf: &mut String| {
            out.label = label(g, d.label.as_ref(), env, ch, buf);
            let auto = place.map(|t| t.apply(d.at.unwrap_or_default()));
            for k in 0..2 {
                out.pos[k] = match &d.pos[k] {
                    Coord::Keep => old.map_or(0.0, |o| o[k]),
                    Coord::Auto => auto.map_or(0.0, |a| a[k]),
                    Coord::Formula(prog) => prog.eval_draws(env, ch),
                };
            }
            if out.interned.is_none() {
                attrs(&d.attrs, env, ch, &mut out.attrs, buf);
            }
        };
    resize(&mut s.kept_v, opt.kept_vertices.len());
    for (d, out) in opt.kept_vertices.iter().zip(&mut s.kept_v) {
        let host = mv[d.mother.expect("a kept vertex has a mother")];
        let old = g.vertices[host as usize].pos;
        eval_vertex(g, d, Some(old), out, choices, &mut s.text);
    }
    resize(&mut s.kept_e, opt.kept_edges.len());
    for (d, out) in opt.kept_edges.iter().zip(&mut s.kept_e) {
        edge_values(g, d, env, choices, out, &mut s.text);
    }
    resize(&mut s.new_v, opt.new_vertices.len());
    for (d, out) in opt.new_vertices.iter().zip(&mut s.new_v) {
        out.interned = constant_set(g, &d.attrs, d.list_key, &mut s.constant);
        eval_vertex(g, d, None, out, choices, &mut s.text);
    }
    resize(&mut s.new_e, opt.new_edges.len());
    for (d, out) in opt.new_edges.iter().zip(&mut s.new_e) {
        out.interned = constant_set(g, &d.attrs, d.list_key, &mut s.constant);
        edge_values(g, d, env, choices, out, &mut s.text);
    }
    // A NaN or infinite position would silently vanish from the drawing.
    let placed = s.kept_v[..opt.kept_vertices.len()].iter().chain(&s.new_v[..opt.new_vertices.len()]);
    let specs = opt.kept_vertices.iter().chain(&opt.new_vertices);
    for (v, d) in placed.zip(specs) {
        if let Some(k) = (0..2).find(|&k| !v.pos[k].is_finite()) {
            return Err((v.pos[k], d.pos_spans[k]));
        }
    }

    // Delete edges first: a deleted vertex would take them along anyway.
    for &i in &opt.delete_edges {
        g.remove_edge(me[i]);
    }
    for &i in &opt.delete_vertices {
        g.remove_vertex(mv[i]);
    }
    for (d, new) in opt.kept_vertices.iter().zip(&mut s.kept_v) {
        let id = mv[d.mother.expect("a kept vertex has a mother")];
        if let Some(l) = new.label {
            g.relabel_vertex(id, l);
        }
        g.vertices[id as usize].pos = new.pos;
        new.attrs.sort_by_key(|(a, _)| *a);
        g.set_attrs(true, id, &mut new.attrs, &mut s.attrs);
    }
    for (d, new) in opt.kept_edges.iter().zip(&mut s.kept_e) {
        let id = me[d.mother.expect("a kept edge has a mother")];
        if let Some(l) = new.label {
            g.relabel_edge(id, l);
        }
        let (End::Mother(a), End::Mother(b)) = (d.from, d.to) else {
            unreachable!("kept edges join mother vertices (checked when compiling)")
        };
        let directed = d.directed.unwrap_or(g.edges[id as usize].directed);
        g.orient_edge(id, mv[a], mv[b], directed);
        new.attrs.sort_by_key(|(a, _)| *a);
        g.set_attrs(false, id, &mut new.attrs, &mut s.attrs);
    }
    s.new_ids.clear();
    for new in &mut s.new_v[..opt.new_vertices.len()] {
        let (pos, label) = (new.pos, new.label.unwrap_or(0));
        let id = g.add_vertex(pos, NewCommon { label, generation, attrs: new_attrs(new) });
        s.new_ids.push(id);
    }
    for (d, new) in opt.new_edges.iter().zip(&mut s.new_e) {
        let end = |e: End| match e {
            End::Mother(i) => mv[i],
            End::New(i) => s.new_ids[i],
        };
        let label = new.label.unwrap_or(0);
        let common = NewCommon { label, generation, attrs: new_attrs(new) };
        g.add_edge(end(d.from), end(d.to), d.directed.unwrap_or(false), common);
    }
    Ok(())
}

/// A new element's attributes: its cached constant set or its sorted list.
fn new_attrs(new: &mut Pending) -> NewAttrs<'_> {
    match new.interned {
        Some(id) => NewAttrs::Interned(id),
        None => {
            new.attrs.sort_by_key(|(a, _)| *a);
            NewAttrs::List(&mut new.attrs)
        }
    }
}

fn resize(v: &mut Vec<Pending>, n: usize) {
    if v.len() < n {
        v.resize_with(n, Pending::default);
    }
}

fn label(g: &mut Graph, spec: Option<&LabelSpec>, env: &[f64], ch: &mut impl Draws, buf: &mut String) -> Option<u32> {
    Some(match spec? {
        LabelSpec::Fixed(l) => *l,
        LabelSpec::Template(t) => {
            t.write(env, ch, buf);
            g.intern_label(buf)
        }
    })
}

fn attrs(specs: &[(u32, AttrSpec)], env: &[f64], ch: &mut impl Draws, out: &mut Vec<(u32, Value)>, buf: &mut String) {
    out.clear();
    for (a, spec) in specs {
        let v = match spec {
            AttrSpec::Value(v) => v.clone(),
            AttrSpec::Template(t) => t.eval(env, ch, buf),
        };
        out.push((*a, v));
    }
}

fn edge_values(g: &mut Graph, d: &DEdge, env: &[f64], ch: &mut impl Draws, out: &mut Pending, buf: &mut String) {
    out.label = label(g, d.label.as_ref(), env, ch, buf);
    if out.interned.is_none() {
        attrs(&d.attrs, env, ch, &mut out.attrs, buf);
    }
}
