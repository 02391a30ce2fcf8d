//! Finding a match of a mother pattern in the host graph.
//!
//! Matching is injective and non-induced over vertices and edges: distinct
//! mother elements go to distinct host elements, and host edges the
//! pattern does not mention are ignored. A directed mother edge matches a
//! directed host edge in its direction; an undirected one matches any host
//! edge in either orientation (both are separate matches). The search
//! follows a [`Plan`]: the anchor's candidates come from the label index
//! (or, at a generation level, from the generation buckets), the rest from
//! adjacency lists; each level visits its candidates in a random order (a
//! uniform first pick, then a random stride), so the first match found is
//! a random one without enumerating all of them.

use crate::choices::{Order, Pick};
use crate::element::Common;
use crate::grammar::Production;
use crate::graph::{Graph, Value};
use crate::mother::Load;
use crate::plan::{Op, Plan, Step};

/// Marker of an unbound mother element.
pub(crate) const UNBOUND: u32 = u32::MAX;

/// The search ran past its work limit or its derivation's deadline.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Exhausted {
    /// More candidate tests than the search may make.
    Work,
    /// The derivation's time limit passed.
    Time,
}

/// Candidate tests between two looks at the clock.
const CLOCK_EVERY: u64 = 1 << 12;

/// Candidates of one scan: a slice, or generation buckets.
enum Cands<'g> {
    One(&'g [u32]),
    Many(Vec<&'g [u32]>, usize),
}

impl Cands<'_> {
    fn len(&self) -> usize {
        match self {
            Cands::One(s) => s.len(),
            Cands::Many(_, n) => *n,
        }
    }

    fn get(&self, mut i: usize) -> u32 {
        match self {
            Cands::One(s) => s[i],
            Cands::Many(parts, _) => {
                for p in parts {
                    if i < p.len() {
                        return p[i];
                    }
                    i -= p.len();
                }
                unreachable!("index within the candidate count")
            }
        }
    }
}

/// The state of one search.
pub(crate) struct Search<'a> {
    pub(crate) g: &'a Graph,
    pub(crate) p: &'a Production,
    pub(crate) env: &'a mut [f64],
    pub(crate) mv: &'a mut [u32],
    pub(crate) me: &'a mut [u32],
    /// Only elements of at most this generation take part.
    pub(crate) max_gen: Option<u32>,
    /// Candidate tests so far, and the most allowed.
    pub(crate) work: u64,
    pub(crate) limit: u64,
    /// When the derivation must have ended (its time limit), if any.
    pub(crate) deadline: Option<std::time::Instant>,
}

fn truthy(v: f64) -> bool {
    v != 0.0 && !v.is_nan()
}

impl<'a> Search<'a> {
    /// Runs the search with `plan`; `visit` sees every complete match and
    /// returns whether to stop. Returns whether it stopped.
    pub(crate) fn run(
        &mut self,
        plan: &Plan,
        pick: &mut impl Pick,
        visit: &mut dyn FnMut(&[u32], &[u32]) -> bool,
    ) -> Result<bool, Exhausted> {
        self.mv.fill(UNBOUND);
        self.me.fill(UNBOUND);
        self.level(plan, 0, pick, visit)
    }

    fn tick(&mut self) -> Result<(), Exhausted> {
        self.work += 1;
        if self.work > self.limit {
            return Err(Exhausted::Work);
        }
        if self.work.is_multiple_of(CLOCK_EVERY) && self.deadline.is_some_and(|d| std::time::Instant::now() >= d) {
            return Err(Exhausted::Time);
        }
        Ok(())
    }

    fn candidates(&self, label: Option<u32>, vertices: bool) -> Cands<'a> {
        let g = self.g;
        let index = if vertices { &g.vindex } else { &g.eindex };
        match (self.max_gen, label) {
            (None, None) => Cands::One(&index.all),
            (None, Some(l)) => Cands::One(index.by_label.get(l as usize).map_or(&[], |s| s.as_slice())),
            (Some(max), label) => {
                let buckets = match label {
                    None => Some(&index.gen_all),
                    Some(l) => index.gen_label.get(l as usize),
                };
                let Some(buckets) = buckets else { return Cands::One(&[]) };
                let mut sets = buckets.up_to(max);
                // Most searches (oldest first) see one generation: no list.
                match (sets.next(), sets.next()) {
                    (None, _) => Cands::One(&[]),
                    (Some(one), None) => Cands::One(one),
                    (Some(a), Some(b)) => {
                        let parts: Vec<&[u32]> = [a, b].into_iter().chain(sets).collect();
                        let n = parts.iter().map(|p| p.len()).sum();
                        Cands::Many(parts, n)
                    }
                }
            }
        }
    }

    fn level(
        &mut self,
        plan: &Plan,
        k: usize,
        pick: &mut impl Pick,
        visit: &mut dyn FnMut(&[u32], &[u32]) -> bool,
    ) -> Result<bool, Exhausted> {
        let Some(step) = plan.steps.get(k) else {
            return Ok(visit(self.mv, self.me));
        };
        let g = self.g;
        let p = self.p;
        match step.op {
            Op::ScanVertex(v) => {
                let m = &p.mv[v];
                let cands = self.candidates(if m.wildcard { None } else { m.label }, true);
                let mut order = Order::new(cands.len(), pick);
                while let Some(i) = order.next(pick) {
                    self.tick()?;
                    if self.bind_vertex(v, cands.get(i)) {
                        if self.checks(step) && self.level(plan, k + 1, pick, visit)? {
                            return Ok(true);
                        }
                        self.mv[v] = UNBOUND;
                    }
                }
            }
            Op::ScanEdge(e) => {
                let m = &p.me[e];
                let cands = self.candidates(m.label, false);
                let mut order = Order::new(cands.len(), pick);
                while let Some(i) = order.next(pick) {
                    self.tick()?;
                    let h = cands.get(i);
                    if !self.edge_ok(e, h) {
                        continue;
                    }
                    let he = &g.edges[h as usize];
                    let (a, b) = (he.from, he.to);
                    let ways: &[(u32, u32)] = if m.directed || a == b {
                        &[(a, b)]
                    } else if pick.coin() {
                        &[(b, a), (a, b)]
                    } else {
                        &[(a, b), (b, a)]
                    };
                    for &(x, y) in ways {
                        if m.from == m.to && x != y {
                            continue;
                        }
                        self.bind_edge(e, h);
                        if self.bind_vertex(m.from, x) {
                            if (m.from == m.to || self.bind_vertex(m.to, y))
                                && self.checks(step)
                                && self.level(plan, k + 1, pick, visit)?
                            {
                                return Ok(true);
                            }
                            self.mv[m.to] = UNBOUND;
                            self.mv[m.from] = UNBOUND;
                        }
                        self.me[e] = UNBOUND;
                    }
                }
            }
            Op::Extend { edge, from, to, to_bound } => {
                let m = &p.me[edge];
                let hv = self.mv[from];
                let adj = g.adj.list(&g.vertices[hv as usize].adj);
                let mut order = Order::new(adj.len(), pick);
                while let Some(i) = order.next(pick) {
                    self.tick()?;
                    let h = adj[i];
                    let he = &g.edges[h as usize];
                    // A self-loop is listed twice: take it once.
                    if he.from == he.to && he.adj_pos[0] as usize != i {
                        continue;
                    }
                    if !self.edge_ok(edge, h) {
                        continue;
                    }
                    let other = if m.directed {
                        if from == m.from {
                            if he.from != hv {
                                continue;
                            }
                            he.to
                        } else {
                            if he.to != hv {
                                continue;
                            }
                            he.from
                        }
                    } else if he.from == hv {
                        he.to
                    } else {
                        he.from
                    };
                    if to_bound && other != self.mv[to] {
                        continue;
                    }
                    self.bind_edge(edge, h);
                    if to_bound || self.bind_vertex(to, other) {
                        if self.checks(step) && self.level(plan, k + 1, pick, visit)? {
                            return Ok(true);
                        }
                        if !to_bound {
                            self.mv[to] = UNBOUND;
                        }
                    }
                    self.me[edge] = UNBOUND;
                }
            }
        }
        Ok(false)
    }

    fn gen_ok(&self, c: &Common) -> bool {
        self.max_gen.is_none_or(|m| c.generation <= m)
    }

    /// Binds mother vertex `v` to host vertex `h` when it fits.
    fn bind_vertex(&mut self, v: usize, h: u32) -> bool {
        if self.mv.contains(&h) {
            return false;
        }
        let m = &self.p.mv[v];
        let hv = &self.g.vertices[h as usize];
        if !self.gen_ok(&hv.c) {
            return false;
        }
        if !m.wildcard && (m.label.is_some_and(|l| l != hv.c.label) || !attrs_match(self.g, &m.attrs, &hv.c)) {
            return false;
        }
        self.mv[v] = h;
        for &(slot, load) in &m.loads {
            self.env[slot as usize] = match load {
                Load::X => hv.pos[0],
                Load::Y => hv.pos[1],
                Load::Degree => f64::from(hv.adj.len),
                Load::Generation => f64::from(hv.c.generation),
                Load::Attr(a) => num_attr(self.g, &hv.c, a),
            };
        }
        true
    }

    /// Whether host edge `h` fits mother edge `e` (ends aside).
    fn edge_ok(&self, e: usize, h: u32) -> bool {
        let m = &self.p.me[e];
        let he = &self.g.edges[h as usize];
        !self.me.contains(&h)
            && (!m.directed || he.directed)
            && m.label.is_none_or(|l| l == he.c.label)
            && self.gen_ok(&he.c)
            && attrs_match(self.g, &m.attrs, &he.c)
    }

    fn bind_edge(&mut self, e: usize, h: u32) {
        self.me[e] = h;
        let he = &self.g.edges[h as usize];
        for &(slot, load) in &self.p.me[e].loads {
            self.env[slot as usize] = match load {
                Load::Generation => f64::from(he.c.generation),
                Load::Attr(a) => num_attr(self.g, &he.c, a),
                Load::X | Load::Y | Load::Degree => f64::NAN,
            };
        }
    }

    /// The checks that become possible after `step`.
    fn checks(&mut self, step: &Step) -> bool {
        let g = self.g;
        let p = self.p;
        for &i in &step.vectors {
            let v = p.vectors[i];
            let (a, b) = (g.vertices[self.mv[v.from] as usize].pos, g.vertices[self.mv[v.to] as usize].pos);
            self.env[v.slot as usize] = b[0] - a[0];
            self.env[v.slot as usize + 1] = b[1] - a[1];
        }
        for &i in &step.spatial {
            let s = p.spatial[i];
            let (a, b) = (g.vertices[self.mv[s.a] as usize].pos, g.vertices[self.mv[s.b] as usize].pos);
            if !(0..2).all(|k| same_order(s.order[k], b[k] - a[k])) {
                return false;
            }
        }
        step.conditions.iter().all(|&i| truthy(p.conditions[i].eval(self.env)))
    }
}

/// Positions closer than this count as equal in spatial matching.
pub(crate) const SPATIAL_EPS: f64 = 1e-6;

fn same_order(want: i8, d: f64) -> bool {
    match want {
        0 => d.abs() <= SPATIAL_EPS,
        1 => d > SPATIAL_EPS,
        _ => d < -SPATIAL_EPS,
    }
}

fn num_attr(g: &Graph, c: &Common, a: u32) -> f64 {
    match g.attr(c, a) {
        Some(Value::Num(v)) => *v,
        _ => f64::NAN,
    }
}

fn attrs_match(g: &Graph, want: &[(u32, Value)], c: &Common) -> bool {
    want.is_empty() || {
        let have = g.attr_sets.get(c.attrs);
        want.iter().all(|(a, v)| have.iter().find(|(b, _)| b == a).map(|(_, w)| w) == Some(v))
    }
}
