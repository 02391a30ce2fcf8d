//! Growing a HEMLS surface: the seed, then derivation steps of three phases
//! (grow, rewrite, join).
//!
//! Phase 1 moves every vertex to `c + S·(v − c) + f(v)` and lets the
//! environment constrain the move; c is the vertex mean (or the start
//! position with `fixed_center`); with `fixed_perimeter` the outer boundary
//! does not move.
//!
//! Phases 2 and 3: in **async** mode (the default) the rules run one at a
//! time in file order, each followed by a join pass; rule r rewrites every
//! edge of its type that exists when its pass begins and was not produced by
//! a rewrite in this step (edges made by joins are eligible: this is what
//! makes the four-sided tiles subdivide into squares), provided the rule
//! chosen for that edge is r or an earlier rule. In **sync** mode every edge
//! that existed at the start of the step is rewritten in one pass, then one
//! join pass runs. Each edge is rewritten at most once per step. Rule choice
//! per edge: context rules before context-free ones, then file order; the
//! rule's condition and context must hold, evaluated on the map as it is when
//! the pass begins; no rule means the identity. Edge frames, too, read the
//! face normals (and, where a normal runs along the edge, the faces' vertex
//! means) as they are when the pass begins, so that rewriting one edge never
//! changes the frame of another in the same pass: a mirror-symmetric
//! surface with palindromic successors stays symmetric. Edges are visited in
//! creation order, which is the map's edge order: a rewrite appends its
//! pieces in successor order and retires the old edge, a join appends its
//! edge (so the order is that of a string rewrite, and the pieces of one
//! edge stay together in memory). Growth is thus deterministic; a stochastic
//! rule draws one number per application, in that order. Branches still
//! unjoined at the end of a step are removed.

use crate::env::Environment;
pub use crate::error::GrowError;
use crate::grammar::{Age, Condition, Hemls};
use crate::join::{JoinParams, Joiner};
use crate::map::{Map, NONE, OUTER, Piece};
use crate::settings::Settings;
use crate::turtle::{self, Template};
use genform_core::Draws;
use glam::DVec3;

/// Element counts after one step (step 0 is the seed).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct StepStats {
    /// Step number, 0 for the seed.
    pub step: u32,
    /// Vertices.
    pub vertices: usize,
    /// Edges.
    pub edges: usize,
    /// Bounded faces.
    pub faces: usize,
}

/// A grown surface and how it got there.
#[derive(Clone, Debug)]
pub struct Growth {
    /// The final map.
    pub map: Map,
    /// Counts after every step, the seed first.
    pub steps: Vec<StepStats>,
    /// Vertices of the final surface on the wrong side of a soft boundary.
    pub outside_soft: u32,
    /// Branches drawn over the whole growth (each is joined or removed).
    pub branches: u64,
    /// Joins made (each consumes two branches).
    pub joins: u64,
}

impl Growth {
    /// The final surface as a Scene surface, with its soft-boundary count.
    pub fn surface(&self, tag: genform_core::TagId) -> genform_core::Surface {
        let mut s = self.map.to_surface(tag);
        s.outside_soft = self.outside_soft;
        s
    }
}

/// Grows `h` for `s.steps` derivation steps in `env`. `draws` feeds the
/// stochastic rules (one draw per application); deterministic grammars
/// draw nothing.
pub fn grow(h: &Hemls, s: &Settings, env: &Environment, draws: &mut dyn Draws) -> Result<Growth, GrowError> {
    grow_with(h, s, env, draws, &mut |_, _| {})
}

/// [`grow`], calling `on_step(k, map)` with the seed (k = 0) and after every
/// completed step k.
pub fn grow_with(
    h: &Hemls,
    s: &Settings,
    env: &Environment,
    draws: &mut dyn Draws,
    on_step: &mut dyn FnMut(u32, &Map),
) -> Result<Growth, GrowError> {
    check_settings(h, s)?;
    let rules = compile_rules(h)?;
    let mut eng = Engine::new(h, s, env, rules);
    let stats = |step: u32, m: &Map| StepStats {
        step,
        vertices: m.vertex_count(),
        edges: m.edge_count(),
        faces: m.face_count(),
    };
    let mut steps = vec![stats(0, &eng.map)];
    on_step(0, &eng.map);
    for step in 1..=s.steps {
        eng.step(step, draws)?;
        steps.push(stats(step, &eng.map));
        on_step(step, &eng.map);
    }
    let outside_soft = if env.has_soft_boundaries() {
        eng.map.positions().iter().filter(|&&p| env.is_outside_soft(p)).count() as u32
    } else {
        0
    };
    Ok(Growth { map: eng.map, steps, outside_soft, branches: eng.joiner.added, joins: eng.joiner.joined })
}

fn invalid(message: String) -> GrowError {
    GrowError::Invalid { message }
}

fn check_settings(h: &Hemls, s: &Settings) -> Result<(), GrowError> {
    if h.axiom.len() < 3 {
        return Err(invalid(format!("the axiom needs at least 3 sides to make a polygon; it has {}", h.axiom.len())));
    }
    if !h.angle.is_finite() {
        return Err(invalid(format!("Angle must be a finite number of degrees, not {}", h.angle)));
    }
    if let Some(b) = h.branch_angle.filter(|b| !b.is_finite()) {
        return Err(invalid(format!("BranchAngle must be a finite number of degrees, not {b}")));
    }
    if !(s.start_length.is_finite() && s.start_length > 0.0) {
        return Err(invalid(format!("the start length must be a positive number, not {}", s.start_length)));
    }
    if !s.scale.is_finite() {
        return Err(invalid(format!("the scale must be finite, not {}", s.scale)));
    }
    if !s.start_position.is_finite() {
        return Err(invalid(format!("the start position must be finite, not {}", s.start_position)));
    }
    if !s.branch_angle.is_finite() || s.branch_length.is_nan() {
        return Err(invalid("the branch angle and branch length must be numbers".into()));
    }
    Ok(())
}

/// A rule ready to apply.
#[derive(Debug)]
struct CompiledRule {
    kind: u32,
    left: Option<u32>,
    right: Option<u32>,
    condition: Option<Condition>,
    templates: Vec<Template>,
    /// Cumulative normalised weights (stochastic rules).
    cumulative: Vec<f64>,
    /// Most new vertices (= new edges) one application adds.
    max_new: usize,
    /// Most branches one application adds.
    max_branches: usize,
}

fn compile_rules(h: &Hemls) -> Result<Vec<CompiledRule>, GrowError> {
    let mut out = Vec::with_capacity(h.rules.len());
    for (i, r) in h.rules.iter().enumerate() {
        let err = |message: String| GrowError::Rule { rule: i, kind: r.pred.kind, span: r.span, message };
        if r.successors.is_empty() {
            return Err(err("it has no successor".into()));
        }
        let several = r.successors.len() > 1;
        let mut templates = Vec::with_capacity(r.successors.len());
        for (j, succ) in r.successors.iter().enumerate() {
            let t = turtle::compile(&succ.items, h.angle).map_err(|m| {
                err(if several { format!("successor {}: {m}", j + 1) } else { format!("the successor: {m}") })
            })?;
            templates.push(t);
        }
        let total: f64 = r.successors.iter().map(|s| s.weight).sum();
        let bad_weight = |w: f64| !w.is_finite() || w < 0.0;
        if r.successors.iter().any(|s| bad_weight(s.weight)) || total.is_nan() || total <= 0.0 {
            return Err(err("successor weights must be finite, not negative, and not all zero".into()));
        }
        let mut acc = 0.0;
        let mut cumulative: Vec<f64> = r
            .successors
            .iter()
            .map(|s| {
                acc += s.weight;
                acc / total
            })
            .collect();
        // Rounding must not leave a gap below 1 that a zero-weight successor
        // at the end could catch.
        let last = r.successors.iter().rposition(|s| s.weight > 0.0).unwrap_or(0);
        cumulative[last..].fill(1.0);
        out.push(CompiledRule {
            kind: r.pred.kind,
            left: r.pred.left,
            right: r.pred.right,
            condition: r.condition,
            max_new: templates.iter().map(|t| t.pieces.len() - 1).max().unwrap_or(0),
            max_branches: templates.iter().map(|t| t.branches.len()).max().unwrap_or(0),
            templates,
            cumulative,
        });
    }
    Ok(out)
}

/// Growth state, reused across steps.
struct Engine<'a> {
    h: &'a Hemls,
    s: &'a Settings,
    env: &'a Environment,
    rules: Vec<CompiledRule>,
    /// Sorted (kind, group) pairs: the group of rules for each type.
    kinds: Vec<(u32, u32)>,
    /// Per group: rule indices in selection order (context rules first).
    groups: Vec<Vec<u32>>,
    /// Group of every rule.
    group_of: Vec<u32>,
    map: Map,
    joiner: Joiner,
    /// Step in which each edge was produced by a rewrite (0: not this step).
    stamp: Vec<u32>,
    todo: Vec<(u32, u32)>,
    interior: Vec<DVec3>,
    pieces: Vec<Piece>,
    fixed: Vec<bool>,
    scratch: Vec<u32>,
    /// Face normals as they were when the current rewrite pass began.
    pass_normals: Vec<Option<DVec3>>,
    /// The vertex count when the current rewrite pass began.
    pass_first_vertex: usize,
    prm: JoinParams,
}

impl<'a> Engine<'a> {
    fn new(h: &'a Hemls, s: &'a Settings, env: &'a Environment, rules: Vec<CompiledRule>) -> Self {
        let mut kinds: Vec<(u32, u32)> = Vec::new();
        let mut groups: Vec<Vec<u32>> = Vec::new();
        let mut group_of = Vec::with_capacity(rules.len());
        for (i, r) in rules.iter().enumerate() {
            let g = match kinds.iter().find(|(k, _)| *k == r.kind) {
                Some(&(_, g)) => g,
                None => {
                    kinds.push((r.kind, groups.len() as u32));
                    groups.push(Vec::new());
                    groups.len() as u32 - 1
                }
            };
            groups[g as usize].push(i as u32);
            group_of.push(g);
        }
        kinds.sort_unstable();
        for g in &mut groups {
            // Stable: context rules first, file order within each class.
            g.sort_by_key(|&r| {
                let r = &rules[r as usize];
                r.left.is_none() && r.right.is_none()
            });
        }
        Engine {
            h,
            s,
            env,
            rules,
            kinds,
            groups,
            group_of,
            map: Map::seed(&h.axiom, s.start_length, s.start_position),
            joiner: Joiner::default(),
            stamp: Vec::new(),
            todo: Vec::new(),
            interior: Vec::new(),
            pieces: Vec::new(),
            fixed: Vec::new(),
            scratch: Vec::new(),
            pass_normals: Vec::new(),
            pass_first_vertex: 0,
            prm: JoinParams::new(0.0, f64::INFINITY, s.join),
        }
    }

    fn step(&mut self, step: u32, draws: &mut dyn Draws) -> Result<(), GrowError> {
        self.grow_phase(step)?;
        self.map.refresh_face_areas();
        let s = self.s;
        let beta = self.h.branch_angle.unwrap_or(s.branch_angle);
        let smax = s.scale.abs().max_element();
        let max_d2 = if s.branch_length >= 0.0 {
            let d = s.branch_length * s.start_length * smax.powi(step.min(i32::MAX as u32) as i32);
            d * d
        } else {
            f64::INFINITY
        };
        self.prm = JoinParams::new(beta.to_radians().cos(), max_d2, s.join);
        self.stamp.clear();
        let first_new = self.map.pos.len();
        let result = self.rewrite_and_join(step, draws);
        self.joiner.clear();
        result?;
        // A vertex that rewriting placed on the wrong side of a hard boundary
        // (a chord's midpoint inside a sphere) is moved to the nearest
        // allowed point; grown vertices are already on the allowed side.
        if self.env.has_hard_boundaries() {
            for p in &mut self.map.pos[first_new..] {
                *p = self.env.settle(*p);
            }
        }
        self.map.compact(&mut self.scratch);
        if !self.map.pos.iter().all(|p| p.is_finite()) {
            return Err(GrowError::NonFinite { step });
        }
        Ok(())
    }

    fn rewrite_and_join(&mut self, step: u32, draws: &mut dyn Draws) -> Result<(), GrowError> {
        let limits = self.s.limits;
        if self.h.sync {
            if self.rewrite_pass(None, step, draws)? {
                self.joiner.pass(&mut self.map, self.prm, &limits, step)?;
            }
        } else {
            for r in 0..self.rules.len() {
                if self.rewrite_pass(Some(r), step, draws)? {
                    self.joiner.pass(&mut self.map, self.prm, &limits, step)?;
                }
            }
        }
        Ok(())
    }

    /// Phase 1.
    fn grow_phase(&mut self, step: u32) -> Result<(), GrowError> {
        let s = self.s;
        let n = self.map.pos.len();
        let c = if s.fixed_center { s.start_position } else { self.map.pos.iter().copied().sum::<DVec3>() / n as f64 };
        self.fixed.clear();
        self.fixed.resize(n, false);
        if s.fixed_perimeter {
            self.scratch.clear();
            self.map.loop_vertices(OUTER, &mut self.scratch);
            for &v in &self.scratch {
                self.fixed[v as usize] = true;
            }
        }
        let env_active = !self.env.is_empty();
        for (p, &fixed) in self.map.pos.iter_mut().zip(&self.fixed) {
            if fixed {
                continue;
            }
            let from = *p;
            let mut to = c + s.scale * (from - c);
            if env_active {
                to += self.env.displacement(from);
                to = self.env.constrain(from, to);
            }
            *p = to;
        }
        if !self.map.pos.iter().all(|p| p.is_finite()) {
            return Err(GrowError::NonFinite { step });
        }
        Ok(())
    }

    fn group_of_kind(&self, kind: u32) -> Option<u32> {
        self.kinds.binary_search_by_key(&kind, |&(k, _)| k).ok().map(|i| self.kinds[i].1)
    }

    /// The rule for edge `e` within `group`, if any.
    fn select(&self, e: u32, group: u32) -> Option<u32> {
        let m = &self.map;
        let age = m.edge_age[e as usize];
        let (a, b) = (m.he[2 * e as usize].origin, m.he[2 * e as usize + 1].origin);
        self.groups[group as usize].iter().copied().find(|&r| {
            let r = &self.rules[r as usize];
            r.condition.is_none_or(|c| c.holds(age))
                && r.left.is_none_or(|k| m.has_other_edge_of_kind(a, e, k))
                && r.right.is_none_or(|k| m.has_other_edge_of_kind(b, e, k))
        })
    }

    /// One rewrite pass: only rule `only` (async) or all rules (sync).
    /// Returns whether anything was rewritten.
    fn rewrite_pass(&mut self, only: Option<usize>, step: u32, draws: &mut dyn Draws) -> Result<bool, GrowError> {
        // Edge slots, dead ones (rewritten this step) included.
        let ne = self.map.edge_kind.len();
        self.stamp.resize(ne, 0);
        let mut todo = std::mem::take(&mut self.todo);
        todo.clear();
        match only {
            Some(r) => {
                let kind = self.rules[r].kind;
                let g = self.group_of[r];
                for e in 0..ne as u32 {
                    if self.map.edge_kind[e as usize] == kind
                        && self.stamp[e as usize] != step
                        && self.map.he[2 * e as usize].origin != NONE
                        && let Some(sel) = self.select(e, g)
                        && sel as usize <= r
                    {
                        todo.push((e, sel));
                    }
                }
            }
            None => {
                for e in 0..ne as u32 {
                    if let Some(g) = self.group_of_kind(self.map.edge_kind[e as usize])
                        && let Some(sel) = self.select(e, g)
                    {
                        todo.push((e, sel));
                    }
                }
            }
        }
        if todo.is_empty() {
            self.todo = todo;
            return Ok(false);
        }
        // Predict the worst case before allocating anything.
        let limits = &self.s.limits;
        let (mut dv, mut nb) = (0usize, 0usize);
        for &(_, r) in &todo {
            dv = dv.saturating_add(self.rules[r as usize].max_new);
            nb = nb.saturating_add(self.rules[r as usize].max_branches);
        }
        if self.map.vertex_count().saturating_add(dv) > limits.max_vertices {
            return Err(GrowError::Limit { what: "vertices", limit: limits.max_vertices, step });
        }
        // Pending branches count against the edges: each joined pair is one.
        if self.map.edge_count().saturating_add(dv) > limits.max_edges
            || self.joiner.branches.len().saturating_add(nb) / 2 > limits.max_edges
        {
            return Err(GrowError::Limit { what: "edges", limit: limits.max_edges, step });
        }
        self.map.reserve(dv, dv + todo.len(), 0, limits);
        self.stamp.reserve(dv + todo.len());
        self.joiner.reserve(nb);
        // Edge frames read the face normals as they are when the pass begins,
        // so an edge's frame does not depend on which edges of its faces were
        // rewritten before it in this pass.
        self.pass_normals.clear();
        self.pass_normals.extend((0..self.map.face_he.len() as u32).map(|f| self.map.normal_of(f)));
        self.pass_first_vertex = self.map.vertex_count();
        for &(e, r) in &todo {
            self.apply(e, r as usize, step, draws);
        }
        self.todo = todo;
        Ok(true)
    }

    /// Rewrites edge `e` with rule `r`.
    fn apply(&mut self, e: u32, r: usize, step: u32, draws: &mut dyn Draws) {
        let rule = &self.rules[r];
        let t = if rule.templates.len() == 1 {
            0
        } else {
            let u = draws.next_f64();
            rule.cumulative.iter().position(|&c| u < c).unwrap_or(rule.cumulative.len() - 1)
        };
        let tpl = &rule.templates[t];
        let m = &mut self.map;
        let h = 2 * e as usize;
        let (a, b) = (m.he[h].origin, m.he[h + 1].origin);
        let (fr, fl) = (m.he[h].face, m.he[h + 1].face);
        let (pa, pb) = (m.pos[a as usize], m.pos[b as usize]);
        let ab = pb - pa;
        // Scaled, so that huge (but finite) edges do not overflow to ∞.
        let big = ab.abs().max_element();
        let len = if big > 0.0 { big * (ab / big).length() } else { 0.0 };
        let hd = if len > 0.0 && len.is_finite() { ab / len } else { DVec3::X };
        let mut un = DVec3::ZERO;
        for f in [fr, fl] {
            if f != OUTER
                && let Some(n) = self.pass_normals[f as usize]
            {
                un += n;
            }
        }
        let up = match perpendicular(un, hd) {
            Some(up) => up,
            // The faces' normal runs along the edge (an edge standing
            // straight up out of its face): take "left" from where the faces
            // lie instead, which mirrors with the surface (reflecting a
            // surface and reversing an edge maps this frame onto the
            // mirrored edge's), where a fixed fallback axis would not.
            None => match perpendicular(
                towards_left(m, &mut self.scratch, self.pass_first_vertex, [fr, fl], pa + 0.5 * ab),
                hd,
            ) {
                Some(left) => hd.cross(left),
                None => orthonormal_up(un, hd),
            },
        };
        let left = up.cross(hd);

        let age = m.edge_age[e as usize];
        self.interior.clear();
        self.interior.extend(tpl.points.iter().map(|t| pa + t.x * ab + len * (t.y * left + t.z * up)));
        self.pieces.clear();
        self.pieces.extend(tpl.pieces.iter().map(|p| Piece {
            kind: p.sym.kind,
            reversed: p.sym.reversed,
            age: match p.sym.age {
                Age::Zero => 0,
                Age::Same => age,
                Age::Plus1 => age.saturating_add(1),
                Age::Minus1 => age.saturating_sub(1),
            },
        }));
        let nv = m.vertex_count() as u32;
        let k = tpl.pieces.len() as u32;
        m.rewrite_edge(e, &self.interior, &self.pieces);
        self.stamp.resize(m.edge_kind.len(), step);
        for bt in &tpl.branches {
            let face = match bt.side {
                1 => fl,
                -1 => fr,
                _ => continue,
            };
            if face == OUTER {
                continue;
            }
            let base = match bt.at {
                0 => a,
                i if i == k => b,
                i => nv + i - 1,
            };
            let dir = bt.dir.x * hd + bt.dir.y * left + bt.dir.z * up;
            self.joiner.add(m, base, dir, bt.sym.kind, face, bt.sym.reversed);
        }
    }
}

/// A vector from an edge's midpoint `mid` towards its left face and away
/// from its right face (`[right, left]`), each through the mean of the
/// face's vertices older than `first_new` (the pass's first new vertex: the
/// older ones have not moved in this pass, so this is the face as the pass
/// began); the outer face counts for nothing.
fn towards_left(m: &Map, scratch: &mut Vec<u32>, first_new: usize, [fr, fl]: [u32; 2], mid: DVec3) -> DVec3 {
    let mut v = DVec3::ZERO;
    for (f, sign) in [(fl, 1.0), (fr, -1.0)] {
        if f == OUTER {
            continue;
        }
        scratch.clear();
        m.loop_vertices(f, scratch);
        let old = scratch.iter().filter(|&&q| (q as usize) < first_new);
        let (sum, n) = old.fold((DVec3::ZERO, 0usize), |(s, n), &q| (s + m.pos[q as usize], n + 1));
        if n > 0 {
            v += sign * (sum / n as f64 - mid);
        }
    }
    v
}

/// `n` made perpendicular to the unit `heading` and unit, unless that
/// leaves (almost) nothing of it.
fn perpendicular(n: DVec3, heading: DVec3) -> Option<DVec3> {
    let u = n - n.dot(heading) * heading;
    let l = u.length();
    (l > 1e-12 * n.length().max(1e-300) && l.is_finite()).then(|| u / l)
}

/// The unit "up" of an edge frame: the mean face normal made perpendicular
/// to the heading, else +z, else any perpendicular.
fn orthonormal_up(n: DVec3, heading: DVec3) -> DVec3 {
    for c in [n, DVec3::Z] {
        let u = c - c.dot(heading) * heading;
        let l = u.length();
        if l > 1e-12 * c.length().max(1e-300) && l.is_finite() {
            return u / l;
        }
    }
    heading.any_orthonormal_vector()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testkit::{hemls, settings};
    use genform_core::Rng;

    fn run(h: &Hemls, s: &Settings) -> Growth {
        grow(h, s, &Environment::default(), &mut Rng::from_seed(1)).unwrap()
    }

    #[test]
    fn koch_counts_and_rule_order() {
        let h = hemls("Edge0 + Edge0 + Edge0", &["Edge0 -> Edge0 - Edge0 + + Edge0 - Edge0"], 60.0, false);
        let g = run(&h, &settings(3, 1.0));
        let counts: Vec<_> = g.steps.iter().map(|s| (s.vertices, s.edges, s.faces)).collect();
        assert_eq!(counts, vec![(3, 3, 1), (12, 12, 1), (48, 48, 1), (192, 192, 1)]);
    }

    #[test]
    fn sync_rewrites_only_edges_of_the_step_start() {
        // Async tiles give 4 squares; the same grammar in sync mode leaves the
        // new middle edges unrewritten, so the two families cross and make
        // fewer faces than 4.
        let rules = ["Edge0 -> Edge0 [ + Edge1 ] [ - Edge1 ] Edge0", "Edge1 -> Edge1 [ + Edge0 ] [ - Edge0 ] Edge1"];
        let h = hemls("Edge0 + ~ Edge1 + Edge0 + ~ Edge1", &rules, 90.0, false);
        assert_eq!(run(&h, &settings(1, 1.0)).map.face_count(), 4);
        let h = hemls("Edge0 + ~ Edge1 + Edge0 + ~ Edge1", &rules, 90.0, true);
        let g = run(&h, &settings(1, 1.0));
        g.map.validate().unwrap();
        assert!(g.map.face_count() < 4);
    }

    #[test]
    fn unbalanced_main_lines_are_stretched_onto_the_edge() {
        let h = hemls("Edge0 + Edge0 + Edge0 + Edge0", &["Edge0 -> + Edge0 Edge0"], 30.0, false);
        let g = run(&h, &settings(2, 1.0));
        g.map.validate().unwrap();
        assert_eq!(g.map.vertex_count(), 16);
        // The vertices stay on the square's edges (straight chains).
        for p in g.map.positions() {
            assert!((p.x.abs() - 0.5).abs() < 1e-12 || (p.y.abs() - 0.5).abs() < 1e-12);
        }
    }

    /// Whether the vertex set is its own mirror image in x → −x (within
    /// 1e-9 of its size).
    fn mirrored_in_x(m: &Map) -> bool {
        let size = m.positions().iter().map(|p| p.length()).fold(0.0, f64::max);
        m.positions().iter().all(|p| {
            let q = DVec3::new(-p.x, p.y, p.z);
            m.positions().iter().any(|r| (*r - q).length() <= 1e-9 * size)
        })
    }

    #[test]
    fn palindromes_that_leave_the_plane_keep_the_seeds_mirror() {
        // Palindromic successors on a square (mirror x → −x): the pitched one
        // tilts its face's normal as each edge is rewritten, and its 45°
        // pitches pile up into edges standing straight up out of their face
        // (frames that need the fallback). Frames read as the pass began,
        // with the fallback taken from where the faces lie, keep the mirror.
        let rules = [
            "Edge0 -> Edge1 - Edge1 + & Edge2 ^ + Edge3 - - Edge3 + ^ Edge2 & + Edge1 - Edge1",
            "Edge1 -> Edge0",
            "Edge2 -> Edge0 - Edge3 + + Edge3 - Edge0",
            "Edge3 -> Edge1",
        ];
        for sync in [false, true] {
            let h = hemls("Edge0 + Edge0 + Edge0 + Edge0", &rules, 45.0, sync);
            for steps in 1..=4 {
                let g = run(&h, &settings(steps, 1.5));
                assert!(mirrored_in_x(&g.map), "sync {sync}, {steps} steps");
            }
            let g = run(&h, &settings(4, 1.5));
            assert!(g.map.positions().iter().any(|p| p.z.abs() > 0.1), "the surface leaves the plane");
        }
    }

    #[test]
    fn orthonormal_up_falls_back() {
        assert_eq!(orthonormal_up(DVec3::ZERO, DVec3::X), DVec3::Z);
        let u = orthonormal_up(DVec3::ZERO, DVec3::Z);
        assert!(u.dot(DVec3::Z).abs() < 1e-12 && (u.length() - 1.0).abs() < 1e-12);
        let u = orthonormal_up(DVec3::new(0.0, 1.0, 1.0), DVec3::Y);
        assert!((u - DVec3::Z).length() < 1e-12);
    }
}
