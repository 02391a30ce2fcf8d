//! The half-edge map a HEMLS surface grows on: vertices, typed edges and
//! regions (faces), always a connected disc.
//!
//! Layout (Vec-backed, indices are `u32`):
//!
//! - edge `e` owns the half-edges `2e` and `2e + 1`; the twin of `h` is
//!   `h ^ 1`. Half-edge `2e` always runs from the edge's *start* to its
//!   *end* (the direction rules read; `~` swaps which geometric direction
//!   that is).
//! - every half-edge has an origin vertex, a next and a previous half-edge
//!   around its face, and a face. A face lies on the **right** of its
//!   half-edges seen from the surface normal (the seed is traversed clockwise
//!   seen from +z and its normal is +z), so internal face loops are clockwise
//!   seen from the front; [`Map::face_loop`] and [`Map::to_surface`] reverse
//!   them into the counter-clockwise convention of [`Surface`].
//! - face 0 is the unbounded outer face; bounded faces are `1..`.
//!
//! Vertices and faces are never deleted. Rewriting an edge appends its
//! pieces and retires the old edge (its slot is removed when the step ends,
//! keeping the order of the rest), joining appends one edge and one face. So
//! edges are stored in creation order, every step keeps `V − E + F = 1`
//! (F = bounded faces) by construction, and [`Map::validate`] checks it
//! together with the links.

use crate::grammar::AxiomSide;
use crate::settings::GrowthLimits;
use genform_core::{Surface, SurfaceEdge, TagId};
use glam::DVec3;

/// "No index" marker.
pub(crate) const NONE: u32 = u32::MAX;
/// The unbounded face.
pub(crate) const OUTER: u32 = 0;

/// One piece of a rewritten edge: its type, whether `~` reversed it, its age.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct Piece {
    pub kind: u32,
    pub reversed: bool,
    pub age: u32,
}

/// One half-edge: where it starts, its neighbours around its face, its face.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct HalfEdge {
    pub origin: u32,
    pub next: u32,
    pub prev: u32,
    pub face: u32,
}

impl HalfEdge {
    const UNSET: HalfEdge = HalfEdge { origin: NONE, next: NONE, prev: NONE, face: NONE };
}

/// How [`Map::split_face`] labelled the two loops it made.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Split {
    /// The id of the new face.
    pub new_face: u32,
    /// Whether the new face is loop 1 (the one holding the chord `u → v`).
    pub new_is_loop1: bool,
}

/// A HEMLS surface under growth: a half-edge map in `f64` coordinates.
#[derive(Clone, Debug, Default)]
pub struct Map {
    pub(crate) pos: Vec<DVec3>,
    /// One outgoing half-edge per vertex.
    pub(crate) vert_out: Vec<u32>,
    /// Half-edges (one array of structs: loop walks touch one cache line).
    pub(crate) he: Vec<HalfEdge>,
    pub(crate) edge_kind: Vec<u32>,
    pub(crate) edge_age: Vec<u32>,
    /// One half-edge per face; index 0 is the outer face.
    pub(crate) face_he: Vec<u32>,
    /// Vector area of every face loop as stored (relative to `area_ref`),
    /// kept exact under rewrites and splits; the face normal is its negation.
    pub(crate) face_area: Vec<DVec3>,
    /// Reference point for vector areas (the start position), so that
    /// surfaces far from the origin keep precise normals.
    pub(crate) area_ref: DVec3,
    /// Dead edge slots (rewritten edges) until the next [`Map::compact`].
    pub(crate) dead: usize,
}

impl Map {
    /// The seed: a regular polygon with one edge per axiom side, side
    /// `start_length`, the first side along +x, traversed clockwise seen from
    /// +z (normal +z), centred (vertex mean) at `start_position`. `~` on a
    /// side makes that edge run against the traversal. Needs at least one
    /// side (growth checks for three).
    pub(crate) fn seed(sides: &[AxiomSide], start_length: f64, start_position: DVec3) -> Map {
        let k = sides.len();
        let mut m = Map { area_ref: start_position, ..Map::default() };
        let turn = std::f64::consts::TAU / k as f64;
        let mut p = DVec3::ZERO;
        for i in 0..k {
            m.pos.push(p);
            // Right turns: the heading angle decreases by the exterior angle.
            let a = -(i as f64) * turn;
            p += start_length * DVec3::new(a.cos(), a.sin(), 0.0);
        }
        let mean = m.pos.iter().copied().sum::<DVec3>() / k as f64;
        for q in &mut m.pos {
            *q = *q - mean + start_position;
        }
        // Inner half-edge of side i runs P_i → P_{i+1} (face 1 on its right),
        // the outer one P_{i+1} → P_i.
        let inner = |i: usize| (2 * i + sides[i].reversed as usize) as u32;
        let outer = |i: usize| inner(i) ^ 1;
        let n = 2 * k;
        m.he = vec![HalfEdge::UNSET; n];
        for (i, side) in sides.iter().enumerate() {
            let j = (i + 1) % k;
            let prev = (i + k - 1) % k;
            let (hi, ho) = (inner(i) as usize, outer(i) as usize);
            m.he[hi].origin = i as u32;
            m.he[ho].origin = j as u32;
            m.he[hi].face = 1;
            m.he[ho].face = OUTER;
            m.he[hi].next = inner(j);
            m.he[hi].prev = inner(prev);
            m.he[ho].next = outer(prev);
            m.he[ho].prev = outer(j);
            m.edge_kind.push(side.kind);
            m.edge_age.push(0);
            m.vert_out.push(inner(i));
        }
        m.face_he = vec![outer(0), inner(0)];
        m.face_area = vec![DVec3::ZERO; 2];
        m.refresh_face_areas();
        m
    }

    /// Number of vertices.
    pub fn vertex_count(&self) -> usize {
        self.pos.len()
    }

    /// Number of edges.
    pub fn edge_count(&self) -> usize {
        self.edge_kind.len() - self.dead
    }

    /// Number of bounded faces (the outer face is not counted).
    pub fn face_count(&self) -> usize {
        self.face_he.len() - 1
    }

    /// `V − E + F` with F the bounded faces: 1 for the disc a HEMLS grows.
    pub fn euler_characteristic(&self) -> i64 {
        self.vertex_count() as i64 - self.edge_count() as i64 + self.face_count() as i64
    }

    /// Vertex positions.
    pub fn positions(&self) -> &[DVec3] {
        &self.pos
    }

    /// The type (`N` of `EdgeN`) of every edge.
    pub fn edge_kinds(&self) -> &[u32] {
        &self.edge_kind
    }

    /// The age of every edge (timed HEMLS).
    pub fn edge_ages(&self) -> &[u32] {
        &self.edge_age
    }

    /// Start and end vertex of edge `e` (its direction for rewriting).
    pub fn edge_ends(&self, e: usize) -> (u32, u32) {
        (self.he[2 * e].origin, self.he[2 * e + 1].origin)
    }

    /// The vertex loop of bounded face `f` (`0..face_count()`),
    /// counter-clockwise seen from the front (the surface normal), like
    /// [`Surface`] faces.
    pub fn face_loop(&self, f: usize) -> Vec<u32> {
        let mut out = Vec::new();
        self.loop_vertices(f as u32 + 1, &mut out);
        out.reverse();
        out
    }

    /// The outer boundary's vertices in the seed's traversal direction
    /// (clockwise seen from the front).
    pub fn boundary(&self) -> Vec<u32> {
        let mut out = Vec::new();
        self.loop_vertices(OUTER, &mut out);
        out.reverse();
        out
    }

    /// The unit normal of bounded face `f` (`0..face_count()`), or `None`
    /// for a degenerate face.
    pub fn face_normal(&self, f: usize) -> Option<DVec3> {
        self.normal_of(f as u32 + 1)
    }

    /// The polygon surface: positions (as `f32`), the bounded faces
    /// counter-clockwise seen from the front, every edge from start to end
    /// with its type. `outside_soft` is left 0 (the environment counts it).
    pub fn to_surface(&self, tag: TagId) -> Surface {
        let mut s = Surface::new(tag);
        s.positions = self.pos.iter().map(|p| p.as_vec3()).collect();
        s.face_offsets.reserve(self.face_count());
        s.face_vertices.reserve(self.he.len() / 2 + self.face_count());
        let mut loop_ = Vec::new();
        for f in 1..self.face_he.len() as u32 {
            loop_.clear();
            self.loop_vertices(f, &mut loop_);
            loop_.reverse();
            s.push_face(&loop_);
        }
        s.edges = (0..self.edge_count())
            .map(|e| {
                let (a, b) = self.edge_ends(e);
                SurfaceEdge { a, b, kind: self.edge_kind[e] }
            })
            .collect();
        s
    }

    /// Checks every structural invariant: links are mutual inverses, faces
    /// are consistent around their loops, every half-edge is on exactly one
    /// loop, every vertex has degree ≥ 2, the map is connected, and
    /// `V − E + F = 1`. Returns what is broken.
    pub fn validate(&self) -> Result<(), String> {
        let nh = self.he.len();
        if nh != 2 * self.edge_count() || self.edge_age.len() != self.edge_count() {
            return Err("half-edge arrays disagree in length".into());
        }
        if self.face_area.len() != self.face_he.len() || self.vert_out.len() != self.pos.len() {
            return Err("face or vertex arrays disagree in length".into());
        }
        for h in 0..nh {
            let (n, p) = (self.he[h].next as usize, self.he[h].prev as usize);
            if n >= nh || p >= nh || self.he[n].prev as usize != h || self.he[p].next as usize != h {
                return Err(format!("half-edge {h}: next/prev are not inverse"));
            }
            if self.he[n].origin != self.he[h ^ 1].origin {
                return Err(format!("half-edge {h}: next does not start where it ends"));
            }
            if self.he[n].face != self.he[h].face {
                return Err(format!("half-edge {h}: next is on another face"));
            }
            if self.he[h].origin == self.he[h ^ 1].origin {
                return Err(format!("edge {}: a loop on one vertex", h / 2));
            }
        }
        let mut seen = vec![false; nh];
        for (f, &start) in self.face_he.iter().enumerate() {
            if self.he[start as usize].face != f as u32 {
                return Err(format!("face {f}: its half-edge belongs to another face"));
            }
            let mut h = start as usize;
            loop {
                if seen[h] {
                    return Err(format!("face {f}: half-edge {h} is on two loops"));
                }
                seen[h] = true;
                h = self.he[h].next as usize;
                if h == start as usize {
                    break;
                }
            }
        }
        if let Some(h) = seen.iter().position(|s| !s) {
            return Err(format!("half-edge {h} is on no face loop"));
        }
        // Degree and connectivity around vertices.
        let mut visited = vec![false; self.pos.len()];
        let mut stack = vec![0u32];
        if !self.pos.is_empty() {
            visited[0] = true;
        }
        let mut degree_total = 0usize;
        while let Some(v) = stack.pop() {
            let start = self.vert_out[v as usize];
            if self.he[start as usize].origin != v {
                return Err(format!("vertex {v}: its half-edge starts elsewhere"));
            }
            let (mut h, mut deg) = (start, 0usize);
            loop {
                deg += 1;
                if deg > nh {
                    return Err(format!("vertex {v}: the fan does not close"));
                }
                let w = self.he[(h ^ 1) as usize].origin;
                if !visited[w as usize] {
                    visited[w as usize] = true;
                    stack.push(w);
                }
                h = self.he[(h ^ 1) as usize].next;
                if h == start {
                    break;
                }
            }
            if deg < 2 {
                return Err(format!("vertex {v} is dangling (degree {deg})"));
            }
            degree_total += deg;
        }
        if visited.iter().any(|v| !v) {
            return Err("the map is not connected".into());
        }
        if degree_total != nh {
            return Err("vertex fans do not cover every half-edge once".into());
        }
        if self.euler_characteristic() != 1 {
            return Err(format!(
                "V − E + F = {} − {} + {} ≠ 1",
                self.vertex_count(),
                self.edge_count(),
                self.face_count()
            ));
        }
        Ok(())
    }

    // ---- internals used by growth and joining ----

    /// The vertex a half-edge ends at.
    #[inline]
    pub(crate) fn dest(&self, h: u32) -> u32 {
        self.he[(h ^ 1) as usize].origin
    }

    /// Appends face `f`'s loop vertices in storage order (clockwise seen
    /// from the front).
    pub(crate) fn loop_vertices(&self, f: u32, out: &mut Vec<u32>) {
        let start = self.face_he[f as usize];
        let mut h = start;
        loop {
            out.push(self.he[h as usize].origin);
            h = self.he[h as usize].next;
            if h == start {
                break;
            }
        }
    }

    /// Unit normal of face `f` (any id, 0 = outer gives its mirror), `None`
    /// when degenerate.
    #[inline]
    pub(crate) fn normal_of(&self, f: u32) -> Option<DVec3> {
        let a = -self.face_area[f as usize];
        let l = a.length();
        (l > 1e-300 && l.is_finite()).then(|| a / l)
    }

    /// Recomputes every face's vector area from the current positions.
    pub(crate) fn refresh_face_areas(&mut self) {
        self.face_area.clear();
        self.face_area.resize(self.face_he.len(), DVec3::ZERO);
        let r = self.area_ref;
        for h in 0..self.he.len() {
            if self.he[h].origin == NONE {
                continue; // a retired edge
            }
            let a = self.pos[self.he[h].origin as usize] - r;
            let b = self.pos[self.he[h ^ 1].origin as usize] - r;
            self.face_area[self.he[h].face as usize] += 0.5 * a.cross(b);
        }
    }

    /// Reserves room for `vertices` more vertices, `edges` more edge slots
    /// and `faces` more faces. A growing buffer gets room for up to four
    /// times its length at once (HEMLS growth is geometric; unused capacity
    /// costs no memory until touched, while every reallocation copies and
    /// touches fresh pages), but never more headroom than `limits` allow.
    pub(crate) fn reserve(&mut self, vertices: usize, edges: usize, faces: usize, limits: &GrowthLimits) {
        fn room<T>(v: &mut Vec<T>, additional: usize, cap: usize) {
            if v.capacity() - v.len() < additional {
                v.reserve(additional.max((3 * v.len()).min(cap.saturating_sub(v.len()))));
            }
        }
        let (mv, me, mf) = (limits.max_vertices, limits.max_edges.saturating_mul(2), limits.max_faces);
        room(&mut self.pos, vertices, mv);
        room(&mut self.vert_out, vertices, mv);
        room(&mut self.he, 2 * edges, me.saturating_mul(2));
        room(&mut self.edge_kind, edges, me);
        room(&mut self.edge_age, edges, me);
        room(&mut self.face_he, faces, mf);
        room(&mut self.face_area, faces, mf);
    }

    /// Whether an edge joins `u` and `v`.
    pub(crate) fn adjacent(&self, u: u32, v: u32) -> bool {
        let start = self.vert_out[u as usize];
        let mut h = start;
        loop {
            if self.dest(h) == v {
                return true;
            }
            h = self.he[(h ^ 1) as usize].next;
            if h == start {
                return false;
            }
        }
    }

    /// The half-edge of face `f` arriving at `u` (`None` when `u` is not on
    /// `f`'s loop).
    pub(crate) fn arriving_in_face(&self, u: u32, f: u32) -> Option<u32> {
        let start = self.vert_out[u as usize];
        let mut h = start;
        loop {
            if self.he[h as usize].face == f {
                return Some(self.he[h as usize].prev);
            }
            h = self.he[(h ^ 1) as usize].next;
            if h == start {
                return None;
            }
        }
    }

    /// Whether some edge at `v` other than `e` has type `kind` (context
    /// rules; edge directions are ignored).
    pub(crate) fn has_other_edge_of_kind(&self, v: u32, e: u32, kind: u32) -> bool {
        let start = self.vert_out[v as usize];
        let mut h = start;
        loop {
            let g = h >> 1;
            if g != e && self.edge_kind[g as usize] == kind {
                return true;
            }
            h = self.he[(h ^ 1) as usize].next;
            if h == start {
                return false;
            }
        }
    }

    /// Replaces edge `e` (start a, end b) by the chain
    /// `a = v0, v1, …, v(k−1), b = vk` with `interior` = the k − 1 new
    /// positions and one [`Piece`] per chain segment (k ≥ 1). The pieces
    /// are appended in order, as are the new vertices; `e` becomes a dead
    /// slot until [`Map::compact`]. Face areas on both sides are updated.
    pub(crate) fn rewrite_edge(&mut self, e: u32, interior: &[DVec3], pieces: &[Piece]) {
        let k = pieces.len();
        debug_assert!(k >= 1 && interior.len() + 1 == k);
        let h = 2 * e;
        let t = h + 1;
        let (a, b) = (self.he[h as usize].origin, self.he[t as usize].origin);
        let (fh, ft) = (self.he[h as usize].face, self.he[t as usize].face);
        let (ph, nh) = (self.he[h as usize].prev, self.he[h as usize].next);
        let (pt, nt) = (self.he[t as usize].prev, self.he[t as usize].next);

        // Area change of the face on h's side: the chain replaces a → b.
        let r = self.area_ref;
        let pa = self.pos[a as usize] - r;
        let pb = self.pos[b as usize] - r;
        let mut chain_area = DVec3::ZERO;
        let mut prev = pa;
        for &q in interior {
            let q = q - r;
            chain_area += prev.cross(q);
            prev = q;
        }
        chain_area += prev.cross(pb);
        let delta = 0.5 * (chain_area - pa.cross(pb));
        self.face_area[fh as usize] += delta;
        self.face_area[ft as usize] -= delta;

        let nv = self.pos.len() as u32;
        let ne = self.edge_kind.len() as u32;
        self.pos.extend_from_slice(interior);
        self.vert_out.resize(self.pos.len(), NONE);
        self.he.resize(self.he.len() + 2 * k, HalfEdge::UNSET);
        self.edge_kind.extend(pieces.iter().map(|p| p.kind));
        self.edge_age.extend(pieces.iter().map(|p| p.age));

        let vertex = |i: usize| -> u32 {
            if i == 0 {
                a
            } else if i == k {
                b
            } else {
                nv + i as u32 - 1
            }
        };
        let chain_he = |i: usize| -> u32 { 2 * (ne + i as u32) + pieces[i].reversed as u32 };
        // Along h's side: ph → c0 → … → c(k−1) → nh.
        let mut before = ph;
        for i in 0..k {
            let c = chain_he(i);
            let (cu, du) = (c as usize, (c ^ 1) as usize);
            self.he[cu].origin = vertex(i);
            self.he[du].origin = vertex(i + 1);
            self.he[cu].face = fh;
            self.he[du].face = ft;
            self.he[before as usize].next = c;
            self.he[cu].prev = before;
            before = c;
            if i > 0 {
                self.vert_out[vertex(i) as usize] = c;
            }
        }
        self.he[before as usize].next = nh;
        self.he[nh as usize].prev = before;
        // Along t's side: pt → d(k−1) → … → d0 → nt.
        let mut before = pt;
        for i in (0..k).rev() {
            let d = chain_he(i) ^ 1;
            self.he[before as usize].next = d;
            self.he[d as usize].prev = before;
            before = d;
        }
        self.he[before as usize].next = nt;
        self.he[nt as usize].prev = before;

        let c0 = chain_he(0);
        self.vert_out[a as usize] = c0;
        self.vert_out[b as usize] = chain_he(k - 1) ^ 1;
        self.face_he[fh as usize] = c0;
        self.face_he[ft as usize] = c0 ^ 1;
        self.he[h as usize] = HalfEdge::UNSET;
        self.he[t as usize] = HalfEdge::UNSET;
        self.dead += 1;
    }

    /// Removes the dead edge slots that rewriting left, keeping the order of
    /// the live edges (so edge order is creation order: the pieces of one
    /// rewrite stay together, which also keeps neighbours close in memory).
    pub(crate) fn compact(&mut self, new_index: &mut Vec<u32>) {
        if self.dead == 0 {
            return;
        }
        let ne = self.edge_kind.len();
        new_index.clear();
        new_index.reserve(ne);
        let mut n = 0u32;
        for e in 0..ne {
            if self.he[2 * e].origin == NONE {
                new_index.push(NONE);
            } else {
                new_index.push(n);
                n += 1;
            }
        }
        let map_he = |h: u32| 2 * new_index[(h >> 1) as usize] + (h & 1);
        for (e, &to) in new_index.iter().enumerate() {
            if to == NONE {
                continue;
            }
            let to = to as usize;
            self.edge_kind[to] = self.edge_kind[e];
            self.edge_age[to] = self.edge_age[e];
            for side in 0..2 {
                let x = self.he[2 * e + side];
                self.he[2 * to + side] = HalfEdge { next: map_he(x.next), prev: map_he(x.prev), ..x };
            }
        }
        let n = n as usize;
        self.edge_kind.truncate(n);
        self.edge_age.truncate(n);
        self.he.truncate(2 * n);
        for h in self.vert_out.iter_mut().chain(self.face_he.iter_mut()) {
            *h = map_he(*h);
        }
        self.dead = 0;
    }

    /// Splits the face holding `hu_in` and `hv_in` (both on one bounded
    /// face loop, arriving at distinct vertices u and v) by a new edge
    /// u → v (or v → u when `reversed`) of `kind`/`age`. Loop 1 is the one
    /// through `hu_in` and the chord u → v, loop 2 the one through `hv_in`
    /// and v → u. The shorter loop (by edge count; found by walking both
    /// loops in lockstep, so a split costs O(shorter loop)) becomes the new
    /// face; its vertices are appended to `small`.
    pub(crate) fn split_face(
        &mut self,
        hu_in: u32,
        hv_in: u32,
        kind: u32,
        age: u32,
        reversed: bool,
        small: &mut Vec<u32>,
    ) -> Split {
        let f = self.he[hu_in as usize].face;
        debug_assert_eq!(f, self.he[hv_in as usize].face);
        let u = self.dest(hu_in);
        let v = self.dest(hv_in);
        let hu_out = self.he[hu_in as usize].next;
        let hv_out = self.he[hv_in as usize].next;
        let e = self.edge_kind.len() as u32;
        self.edge_kind.push(kind);
        self.edge_age.push(age);
        self.he.resize(self.he.len() + 2, HalfEdge { face: f, ..HalfEdge::UNSET });
        let c = 2 * e + reversed as u32; // u → v
        let c2 = c ^ 1; // v → u
        self.he[c as usize].origin = u;
        self.he[c2 as usize].origin = v;
        self.he[hu_in as usize].next = c;
        self.he[c as usize].prev = hu_in;
        self.he[c as usize].next = hv_out;
        self.he[hv_out as usize].prev = c;
        self.he[hv_in as usize].next = c2;
        self.he[c2 as usize].prev = hv_in;
        self.he[c2 as usize].next = hu_out;
        self.he[hu_out as usize].prev = c2;

        // Walk both loops in lockstep until one closes.
        let (mut x1, mut x2) = (self.he[c as usize].next, self.he[c2 as usize].next);
        let loop1_smaller = loop {
            if x1 == c {
                break true;
            }
            if x2 == c2 {
                break false;
            }
            x1 = self.he[x1 as usize].next;
            x2 = self.he[x2 as usize].next;
        };
        let (small_start, big_start) = if loop1_smaller { (c, c2) } else { (c2, c) };
        let new_face = self.face_he.len() as u32;
        let r = self.area_ref;
        let mut area = DVec3::ZERO;
        let mut h = small_start;
        loop {
            self.he[h as usize].face = new_face;
            let o = self.he[h as usize].origin;
            small.push(o);
            area += (self.pos[o as usize] - r).cross(self.pos[self.dest(h) as usize] - r);
            h = self.he[h as usize].next;
            if h == small_start {
                break;
            }
        }
        area *= 0.5;
        self.he[big_start as usize].face = f;
        self.face_he[f as usize] = big_start;
        self.face_he.push(small_start);
        self.face_area[f as usize] -= area;
        self.face_area.push(area);
        Split { new_face, new_is_loop1: loop1_smaller }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn square(rev: [bool; 4]) -> Map {
        let sides: Vec<AxiomSide> = (0..4).map(|i| AxiomSide { kind: i as u32 % 2, reversed: rev[i] }).collect();
        Map::seed(&sides, 1.0, DVec3::ZERO)
    }

    #[test]
    fn seed_is_a_clockwise_square_centred_on_the_start_position() {
        let m = Map::seed(&[AxiomSide { kind: 0, reversed: false }; 4], 2.0, DVec3::new(1.0, 2.0, 3.0));
        m.validate().unwrap();
        assert_eq!((m.vertex_count(), m.edge_count(), m.face_count()), (4, 4, 1));
        let p = m.positions();
        // First side along +x, polygon on its −y side.
        assert!((p[1] - p[0] - DVec3::new(2.0, 0.0, 0.0)).length() < 1e-12);
        assert!((p[2] - p[1] - DVec3::new(0.0, -2.0, 0.0)).length() < 1e-12);
        let mean = p.iter().copied().sum::<DVec3>() / 4.0;
        assert!((mean - DVec3::new(1.0, 2.0, 3.0)).length() < 1e-12);
        assert!((m.face_normal(0).unwrap() - DVec3::Z).length() < 1e-12);
        // CCW seen from +z on output.
        assert_eq!(m.face_loop(0), vec![3, 2, 1, 0]);
    }

    #[test]
    fn reversed_axiom_sides_swap_start_and_end() {
        let m = square([false, true, false, true]);
        m.validate().unwrap();
        assert_eq!(m.edge_ends(0), (0, 1));
        assert_eq!(m.edge_ends(1), (2, 1));
        assert_eq!(m.edge_ends(3), (0, 3));
        let s = m.to_surface(TagId::default());
        assert_eq!(s.edges[1], SurfaceEdge { a: 2, b: 1, kind: 1 });
        assert_eq!(s.euler_characteristic(), 1);
    }

    #[test]
    fn rewriting_and_splitting_keep_the_disc_and_exact_areas() {
        let mut m = square([false, true, false, false]);
        // Split edge 0 into three (middle piece reversed) with a bump.
        let pieces = [
            Piece { kind: 5, reversed: false, age: 1 },
            Piece { kind: 6, reversed: true, age: 2 },
            Piece { kind: 7, reversed: false, age: 3 },
        ];
        let interior = [DVec3::new(-0.2, 0.7, 0.0), DVec3::new(0.2, 0.7, 0.0)];
        m.rewrite_edge(0, &interior, &pieces);
        assert_eq!(m.edge_count(), 6);
        let mut scratch = Vec::new();
        m.compact(&mut scratch);
        m.validate().unwrap();
        // The old edge is gone, the pieces follow the other edges in order.
        assert_eq!(m.edge_kinds(), &[1, 0, 1, 5, 6, 7]);
        assert_eq!(m.edge_ends(3), (0, 4));
        assert_eq!(m.edge_ends(4), (5, 4));
        assert_eq!(m.edge_ends(5), (5, 1));
        let before = m.face_area.clone();
        m.refresh_face_areas();
        for (a, b) in before.iter().zip(&m.face_area) {
            assert!((*a - *b).length() < 1e-12);
        }
        // Also rewrite the reversed side 1 (start 2 → end 1) in two.
        assert_eq!(m.edge_ends(0), (2, 1));
        m.rewrite_edge(0, &[DVec3::new(0.5, 0.0, 0.0)], &[Piece { kind: 1, reversed: false, age: 0 }; 2]);
        m.compact(&mut scratch);
        m.validate().unwrap();
        assert_eq!(m.edge_ends(5), (2, 6));
        // Split the square from vertex 6 (middle of the right side) to 3.
        let f = 1;
        let hu = m.arriving_in_face(6, f).unwrap();
        let hv = m.arriving_in_face(3, f).unwrap();
        let mut small = Vec::new();
        let sp = m.split_face(hu, hv, 9, 0, false, &mut small);
        m.validate().unwrap();
        assert_eq!(m.face_count(), 2);
        assert_eq!(sp.new_face, 2);
        let before = m.face_area.clone();
        m.refresh_face_areas();
        for (a, b) in before.iter().zip(&m.face_area) {
            assert!((*a - *b).length() < 1e-12);
        }
        assert!(m.adjacent(6, 3) && m.adjacent(3, 6) && !m.adjacent(0, 2));
        // Both pieces are clockwise seen from +z: their normals are +z.
        for f in 0..2 {
            assert!((m.face_normal(f).unwrap() - DVec3::Z).length() < 1e-12);
        }
    }
}
