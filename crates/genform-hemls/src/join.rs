//! Phase 3 of a derivation step: joining pending branches into edges.
//!
//! Two branches p and q join when they are in the same region (face), have
//! the same type, are nearly anti-parallel (`d_p·d_q ≤ −cos β`), each base
//! lies in the other's cone of half-angle β (`(q − p)·d_p ≥ cos β·|q − p|`
//! and the same from q), their bases are within the join distance, and no
//! edge joins the two bases yet (a join never doubles an edge). β is the
//! grammar's `BranchAngle`, else the settings' `branch_angle`.
//!
//! Matching is greedy, nearest pair first, ties by creation order (the pair
//! key is `(distance², earlier branch, later branch)`), within each face;
//! different faces never interact, because a join only splits its own face.
//! A join adds the edge p.base → q.base (p the earlier branch; `~` on p
//! reverses it) with age 0, splits the face, and moves every pending branch
//! of the face to the side its base and direction lie on.
//!
//! Complexity, per join pass: pending branches are grouped by face in O(B).
//! A face group of m branches is matched by brute force when m ≤
//! [`Joiner::brute_force_max`] (O(m²) pair tests, at most 32² here). A
//! larger group gets a bounding-volume tree over (base, direction, type),
//! built in O(m log m); each "nearest valid partner" query is a best-first
//! search pruned by distance, type, anti-parallel direction bounds and the
//! cone, typically O(log m); the greedy pops a lazy heap and re-queries a
//! branch only when its partner was taken or moved to another face. The
//! worst case (many branches passing every bound but failing the exact
//! tests) is O(m²) for that face alone: never a scan over the branch pairs
//! of the whole surface. A split costs O(shorter loop) (the map walks both
//! loops in lockstep and relabels the shorter one, moving only the branches
//! based on it), so repeated splits of one big face stay O(n log n).

use crate::error::GrowError;
use crate::map::{Map, NONE};
use crate::settings::GrowthLimits;
use glam::DVec3;
use std::cmp::Reverse;
use std::collections::BinaryHeap;

/// Slack on the angle tests, so exact constructions (the tiles) join despite
/// rounding.
const EPS: f64 = 1e-9;
/// Items per tree leaf.
const LEAF: usize = 4;

/// A branch waiting to be joined.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Pending {
    pub base: u32,
    pub kind: u32,
    /// The face it points into (a bounded face).
    pub face: u32,
    /// Next pending branch based at the same vertex.
    pub next_at: u32,
    /// Unit direction.
    pub dir: DVec3,
    pub reversed: bool,
    pub alive: bool,
}

/// A candidate pair in the greedy heap: (distance² bits, earlier branch,
/// later branch, the querying branch, its partner).
type Candidate = (u64, u32, u32, u32, u32);

/// The join criteria of one pass.
#[derive(Clone, Copy, Debug)]
pub(crate) struct JoinParams {
    /// Largest scalar product of the two directions: −cos β for the
    /// anti-parallel readings, cos β for the literal one.
    pub max_dot: f64,
    /// Largest squared base distance (infinite when unlimited).
    pub max_d2: f64,
    /// cos of the half-angle of the cone each base must lie in around the
    /// other branch: cos β for the cone test, 0 for the facing test, −∞ for
    /// none.
    pub cone_cos: f64,
}

impl JoinParams {
    /// The criteria for BranchAngle `cos` with no distance limit and `test`.
    pub fn new(cos: f64, max_d2: f64, test: crate::settings::JoinTest) -> Self {
        use crate::settings::JoinTest;
        let cone_cos = match test {
            JoinTest::Cone => cos,
            // A hair above 0: a partner exactly beside the branch (a
            // chord at 90° to it) is not in front of it.
            JoinTest::Facing | JoinTest::Scalar => 1e-6,
            JoinTest::Paper => f64::NEG_INFINITY,
        };
        let max_dot = if test == JoinTest::Scalar { cos } else { -cos };
        JoinParams { max_dot, max_d2, cone_cos }
    }
}

/// Pending branches of the current step and the scratch space of matching
/// (kept across steps so that growth reuses its allocations).
#[derive(Debug)]
pub(crate) struct Joiner {
    pub branches: Vec<Pending>,
    alive: Vec<u32>,
    vert_head: Vec<u32>,
    face_head: Vec<u32>,
    group_next: Vec<u32>,
    touched: Vec<u32>,
    group: Vec<u32>,
    pairs: Vec<(u64, u32, u32)>,
    small: Vec<u32>,
    bvh: Bvh,
    heap: BinaryHeap<Reverse<Candidate>>,
    /// Largest face group matched by brute force.
    pub brute_force_max: usize,
    /// Branches added since creation (statistics, never reset by `clear`).
    pub added: u64,
    /// Joins made since creation.
    pub joined: u64,
}

impl Default for Joiner {
    fn default() -> Self {
        Joiner {
            branches: Vec::new(),
            alive: Vec::new(),
            vert_head: Vec::new(),
            face_head: Vec::new(),
            group_next: Vec::new(),
            touched: Vec::new(),
            group: Vec::new(),
            pairs: Vec::new(),
            small: Vec::new(),
            bvh: Bvh::default(),
            heap: BinaryHeap::new(),
            brute_force_max: 32,
            added: 0,
            joined: 0,
        }
    }
}

/// Whether p and q pass the static join tests; their squared distance.
#[inline]
fn compatible(pos: &[DVec3], a: &Pending, b: &Pending, prm: JoinParams) -> Option<f64> {
    if a.kind != b.kind || a.base == b.base || a.dir.dot(b.dir) > prm.max_dot + EPS {
        return None;
    }
    let v = pos[b.base as usize] - pos[a.base as usize];
    let d2 = v.length_squared();
    if !(d2 > 0.0 && d2 <= prm.max_d2) {
        return None;
    }
    let lim = (prm.cone_cos - EPS) * d2.sqrt();
    (v.dot(a.dir) >= lim && -v.dot(b.dir) >= lim).then_some(d2)
}

/// Counter-clockwise angle from `a` to `b` seen from `n`, in [0, 2π).
#[inline]
fn ccw(a: DVec3, b: DVec3, n: DVec3) -> f64 {
    let t = a.cross(b).dot(n).atan2(a.dot(b));
    if t < 0.0 { t + std::f64::consts::TAU } else { t }
}

impl Joiner {
    /// Adds a pending branch (creation order = insertion order).
    pub fn add(&mut self, map: &Map, base: u32, dir: DVec3, kind: u32, face: u32, reversed: bool) {
        let i = self.branches.len() as u32;
        if self.vert_head.len() < map.vertex_count() {
            self.vert_head.resize(map.vertex_count(), NONE);
        }
        let next_at = self.vert_head[base as usize];
        self.vert_head[base as usize] = i;
        self.branches.push(Pending { base, kind, face, next_at, dir, reversed, alive: true });
        self.alive.push(i);
        self.added += 1;
    }

    /// Reserves room for `n` more branches.
    pub fn reserve(&mut self, n: usize) {
        self.branches.reserve(n);
        self.alive.reserve(n);
    }

    /// Removes every pending branch (the end of a step).
    pub fn clear(&mut self) {
        for b in &self.branches {
            self.vert_head[b.base as usize] = NONE;
        }
        self.branches.clear();
        self.alive.clear();
    }

    /// One join pass over all pending branches.
    pub fn pass(&mut self, map: &mut Map, prm: JoinParams, limits: &GrowthLimits, step: u32) -> Result<(), GrowError> {
        let br = &self.branches;
        self.alive.retain(|&i| br[i as usize].alive);
        if self.alive.len() < 2 {
            return Ok(());
        }
        // Vertices added since the last branch have no branches yet.
        self.vert_head.resize(map.vertex_count(), NONE);
        let joins = self.alive.len() / 2;
        map.reserve(0, joins, joins, limits);
        let nf = map.face_he.len();
        if self.face_head.len() < nf {
            self.face_head.resize(nf, NONE);
        }
        self.group_next.resize(self.branches.len(), NONE);
        self.touched.clear();
        // Prepend in reverse so every face list is in creation order.
        for &i in self.alive.iter().rev() {
            let f = self.branches[i as usize].face as usize;
            if self.face_head[f] == NONE {
                self.touched.push(f as u32);
            }
            self.group_next[i as usize] = self.face_head[f];
            self.face_head[f] = i;
        }
        let touched = std::mem::take(&mut self.touched);
        let mut result = Ok(());
        for &f in touched.iter().rev() {
            self.group.clear();
            let mut i = std::mem::replace(&mut self.face_head[f as usize], NONE);
            while i != NONE {
                self.group.push(i);
                i = self.group_next[i as usize];
            }
            if result.is_err() || self.group.len() < 2 {
                continue;
            }
            result = if self.group.len() <= self.brute_force_max {
                self.match_small(map, prm, limits, step)
            } else {
                self.match_large(map, prm, limits, step)
            };
        }
        self.touched = touched;
        result
    }

    fn match_small(
        &mut self,
        map: &mut Map,
        prm: JoinParams,
        limits: &GrowthLimits,
        step: u32,
    ) -> Result<(), GrowError> {
        if let &[p, q] = self.group.as_slice() {
            let (a, b) = (&self.branches[p as usize], &self.branches[q as usize]);
            if compatible(&map.pos, a, b, prm).is_some() && !map.adjacent(a.base, b.base) {
                return self.join(map, p, q, limits, step);
            }
            return Ok(());
        }
        let mut pairs = std::mem::take(&mut self.pairs);
        pairs.clear();
        for (x, &i) in self.group.iter().enumerate() {
            let a = &self.branches[i as usize];
            for &j in &self.group[x + 1..] {
                if let Some(d2) = compatible(&map.pos, a, &self.branches[j as usize], prm) {
                    pairs.push((d2.to_bits(), i, j));
                }
            }
        }
        pairs.sort_unstable();
        let mut result = Ok(());
        for &(_, p, q) in &pairs {
            let (a, b) = (&self.branches[p as usize], &self.branches[q as usize]);
            if a.alive && b.alive && a.face == b.face && !map.adjacent(a.base, b.base) {
                result = self.join(map, p, q, limits, step);
                if result.is_err() {
                    break;
                }
            }
        }
        self.pairs = pairs;
        result
    }

    fn match_large(
        &mut self,
        map: &mut Map,
        prm: JoinParams,
        limits: &GrowthLimits,
        step: u32,
    ) -> Result<(), GrowError> {
        self.bvh.build(&self.group, &self.branches, &map.pos);
        // The cone's half-angle (π: no cone, nothing pruned by it).
        let beta = (prm.cone_cos - EPS).clamp(-1.0, 1.0).acos();
        self.heap.clear();
        for &p in &self.group {
            if let Some((d, lo, hi, q)) = self.bvh.query(p, &self.branches, map, prm, beta) {
                self.heap.push(Reverse((d, lo, hi, p, q)));
            }
        }
        // Lazy greedy: a stored entry's key never exceeds its branch's current
        // best (validity only shrinks within a pass), so the first valid entry
        // popped is the global nearest pair.
        while let Some(Reverse((_, _, _, p, q))) = self.heap.pop() {
            let (a, b) = (&self.branches[p as usize], &self.branches[q as usize]);
            if !a.alive {
                continue;
            }
            if b.alive && a.face == b.face && !map.adjacent(a.base, b.base) {
                self.join(map, p.min(q), p.max(q), limits, step)?;
                self.bvh.kill(p);
                self.bvh.kill(q);
            } else if let Some((d, lo, hi, q)) = self.bvh.query(p, &self.branches, map, prm, beta) {
                self.heap.push(Reverse((d, lo, hi, p, q)));
            }
        }
        Ok(())
    }

    /// Joins p (the earlier) and q: adds the edge, splits the face and
    /// reassigns the face's pending branches.
    fn join(&mut self, map: &mut Map, p: u32, q: u32, limits: &GrowthLimits, step: u32) -> Result<(), GrowError> {
        if map.edge_count() >= limits.max_edges {
            return Err(GrowError::Limit { what: "edges", limit: limits.max_edges, step });
        }
        if map.face_count() >= limits.max_faces {
            return Err(GrowError::Limit { what: "faces", limit: limits.max_faces, step });
        }
        self.joined += 1;
        let (bp, bq) = (self.branches[p as usize], self.branches[q as usize]);
        let (u, v, f) = (bp.base, bq.base, bp.face);
        self.branches[p as usize].alive = false;
        self.branches[q as usize].alive = false;
        let (Some(hu), Some(hv)) = (map.arriving_in_face(u, f), map.arriving_in_face(v, f)) else {
            // A branch's base is always on its face; keep going if not.
            debug_assert!(false, "branch base not on its face");
            return Ok(());
        };
        let n = map.normal_of(f).unwrap_or(DVec3::Z);
        let (pu, pv) = (map.pos[u as usize], map.pos[v as usize]);
        let in_u = map.pos[map.he[hu as usize].origin as usize] - pu;
        let in_v = map.pos[map.he[hv as usize].origin as usize] - pv;
        self.small.clear();
        let split = map.split_face(hu, hv, bp.kind, 0, bp.reversed, &mut self.small);
        let new = split.new_face;
        let (id1, id2) = if split.new_is_loop1 { (new, f) } else { (f, new) };
        for &x in &self.small {
            if x == u || x == v {
                continue;
            }
            let mut i = self.vert_head[x as usize];
            while i != NONE {
                let b = &mut self.branches[i as usize];
                if b.alive && b.face == f {
                    b.face = new;
                }
                i = b.next_at;
            }
        }
        // At the chord's ends, the side follows the direction's sector: loop
        // 1 has the corner from the incoming edge to the chord at u, loop 2
        // the one from the incoming edge to the chord at v.
        for (x, inc, chord, first, second) in [(u, in_u, pv - pu, id1, id2), (v, in_v, pu - pv, id2, id1)] {
            let mut cut = None;
            let mut i = self.vert_head[x as usize];
            while i != NONE {
                let b = &mut self.branches[i as usize];
                if b.alive && b.face == f {
                    let cut = *cut.get_or_insert_with(|| ccw(inc, chord, n));
                    b.face = if ccw(inc, b.dir, n) < cut { first } else { second };
                }
                i = b.next_at;
            }
        }
        Ok(())
    }
}

/// A bounding-volume tree over one face group's branches: base position box,
/// direction box, type mask and live count per node.
#[derive(Debug, Default)]
struct Bvh {
    nodes: Vec<Node>,
    items: Vec<u32>,
    /// Leaf node of every branch in the tree (indexed by branch).
    leaf_of: Vec<u32>,
    queue: BinaryHeap<Reverse<(u64, u32)>>,
}

#[derive(Clone, Copy, Debug)]
struct Node {
    lo: DVec3,
    hi: DVec3,
    dlo: DVec3,
    dhi: DVec3,
    mask: u64,
    alive: u32,
    parent: u32,
    /// Leaf: items a..b; internal: children a and b.
    a: u32,
    b: u32,
    leaf: bool,
}

#[inline]
fn box_d2(x: DVec3, lo: DVec3, hi: DVec3) -> f64 {
    let d = (lo - x).max(x - hi).max(DVec3::ZERO);
    d.length_squared()
}

impl Bvh {
    fn build(&mut self, group: &[u32], br: &[Pending], pos: &[DVec3]) {
        self.items.clear();
        self.items.extend_from_slice(group);
        self.nodes.clear();
        if self.leaf_of.len() < br.len() {
            self.leaf_of.resize(br.len(), NONE);
        }
        self.build_node(0, group.len(), NONE, br, pos);
    }

    fn build_node(&mut self, start: usize, end: usize, parent: u32, br: &[Pending], pos: &[DVec3]) -> u32 {
        let (mut lo, mut hi) = (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY));
        let (mut dlo, mut dhi) = (lo, hi);
        let mut mask = 0u64;
        for &i in &self.items[start..end] {
            let b = &br[i as usize];
            let p = pos[b.base as usize];
            lo = lo.min(p);
            hi = hi.max(p);
            dlo = dlo.min(b.dir);
            dhi = dhi.max(b.dir);
            mask |= 1u64 << (b.kind & 63);
        }
        let me = self.nodes.len() as u32;
        let leaf = end - start <= LEAF;
        self.nodes.push(Node {
            lo,
            hi,
            dlo,
            dhi,
            mask,
            alive: (end - start) as u32,
            parent,
            a: start as u32,
            b: end as u32,
            leaf,
        });
        if leaf {
            for &i in &self.items[start..end] {
                self.leaf_of[i as usize] = me;
            }
            return me;
        }
        let ext = hi - lo;
        let axis = if ext.x >= ext.y && ext.x >= ext.z {
            0
        } else if ext.y >= ext.z {
            1
        } else {
            2
        };
        let mid = (start + end) / 2;
        self.items[start..end].select_nth_unstable_by(mid - start, |&x, &y| {
            pos[br[x as usize].base as usize][axis].total_cmp(&pos[br[y as usize].base as usize][axis])
        });
        let l = self.build_node(start, mid, me, br, pos);
        let r = self.build_node(mid, end, me, br, pos);
        let n = &mut self.nodes[me as usize];
        n.a = l;
        n.b = r;
        me
    }

    fn kill(&mut self, branch: u32) {
        let mut n = self.leaf_of[branch as usize];
        while n != NONE {
            let node = &mut self.nodes[n as usize];
            node.alive -= 1;
            n = node.parent;
        }
    }

    /// Whether no branch of `node` can be a partner of a branch at `x` with
    /// direction `d` (conservative bounds only).
    #[inline]
    fn prune(node: &Node, x: DVec3, d: DVec3, prm: JoinParams, beta: f64, best: u64) -> Option<f64> {
        let lb = box_d2(x, node.lo, node.hi);
        if lb > prm.max_d2 || lb.to_bits() > best {
            return None;
        }
        // Smallest d·e over the direction box must reach −cos β.
        let m = (d * node.dlo).min(d * node.dhi);
        if m.x + m.y + m.z > prm.max_dot + EPS {
            return None;
        }
        // The box's bounding sphere must meet the cone around d.
        let c = 0.5 * (node.lo + node.hi);
        let r = 0.5 * (node.hi - node.lo).length();
        let w = c - x;
        let dist = w.length();
        if dist > r {
            let theta = (w.dot(d) / dist).clamp(-1.0, 1.0).acos();
            if theta - (r / dist).asin() > beta + EPS {
                return None;
            }
        }
        Some(lb)
    }

    /// The best valid partner of `p`: (distance² bits, earlier, later, q).
    fn query(&mut self, p: u32, br: &[Pending], map: &Map, prm: JoinParams, beta: f64) -> Option<(u64, u32, u32, u32)> {
        let a = &br[p as usize];
        let x = map.pos[a.base as usize];
        let bit = 1u64 << (a.kind & 63);
        let mut best: Option<(u64, u32, u32, u32)> = None;
        self.queue.clear();
        let root = &self.nodes[0];
        if root.alive == 0 || root.mask & bit == 0 {
            return None;
        }
        self.queue.push(Reverse((0, 0)));
        while let Some(Reverse((lb, ni))) = self.queue.pop() {
            if best.is_some_and(|b| lb > b.0) {
                break;
            }
            let node = self.nodes[ni as usize];
            if node.leaf {
                for &q in &self.items[node.a as usize..node.b as usize] {
                    let b = &br[q as usize];
                    if q == p || !b.alive || b.face != a.face {
                        continue;
                    }
                    if let Some(d2) = compatible(&map.pos, a, b, prm) {
                        let key = (d2.to_bits(), p.min(q), p.max(q), q);
                        if best.is_none_or(|b| key < b) && !map.adjacent(a.base, b.base) {
                            best = Some(key);
                        }
                    }
                }
                continue;
            }
            let bound = best.map_or(u64::MAX, |b| b.0);
            for child in [node.a, node.b] {
                let c = &self.nodes[child as usize];
                if c.alive == 0 || c.mask & bit == 0 {
                    continue;
                }
                if let Some(lb) = Self::prune(c, x, a.dir, prm, beta, bound) {
                    self.queue.push(Reverse((lb.to_bits(), child)));
                }
            }
        }
        best
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::grammar::AxiomSide;
    use crate::settings::JoinTest;

    /// A regular n-gon (one face) with `per_vertex` inward branches at every
    /// vertex, their directions fanned by a deterministic jitter.
    fn fan(n: usize, per_vertex: usize, brute_force_max: usize, cos: f64) -> Map {
        let sides = vec![AxiomSide { kind: 0, reversed: false }; n];
        let mut map = Map::seed(&sides, 1.0, DVec3::ZERO);
        let mut j = Joiner { brute_force_max, ..Joiner::default() };
        let c = map.pos.iter().copied().sum::<DVec3>() / n as f64;
        let mut s = 12345u64;
        for v in 0..n as u32 {
            for _ in 0..per_vertex {
                s = s.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
                let jitter = ((s >> 33) as f64 / (1u64 << 31) as f64 - 0.5) * 1.2;
                let to_c = (c - map.pos[v as usize]).normalize();
                let dir = glam::DQuat::from_rotation_z(jitter) * to_c;
                j.add(&map, v, dir, (s >> 20) as u32 % 2, 1, false);
            }
        }
        let prm = JoinParams::new(cos, f64::INFINITY, JoinTest::Cone);
        j.pass(&mut map, prm, &GrowthLimits::default(), 1).unwrap();
        map.validate().unwrap();
        map
    }

    #[test]
    fn tree_matching_equals_brute_force() {
        for (n, per, cos) in [(40, 1, 0.9), (64, 2, 0.8), (97, 3, 0.95), (30, 4, 0.5)] {
            let a = fan(n, per, usize::MAX, cos);
            let b = fan(n, per, 2, cos);
            assert!(a.face_count() > 1, "some joins happen for n = {n}");
            let ends = |m: &Map| (0..m.edge_count()).map(|e| m.edge_ends(e)).collect::<Vec<_>>();
            assert_eq!(ends(&a), ends(&b), "n = {n}");
            assert_eq!(a.face_count(), b.face_count());
        }
    }

    #[test]
    fn branches_at_a_chord_end_go_to_the_side_they_point_into() {
        // Square 0(−½,½) 1(½,½) 2(½,−½) 3(−½,−½): join 0 → 2 along the
        // diagonal; a third branch at 0 pointing down goes to the lower-left
        // triangle (0, 2, 3), one pointing right to the upper-right (0, 1, 2).
        let sides = vec![AxiomSide { kind: 0, reversed: false }; 4];
        let mut map = Map::seed(&sides, 1.0, DVec3::ZERO);
        let mut j = Joiner::default();
        let diag = (map.pos[2] - map.pos[0]).normalize();
        j.add(&map, 0, diag, 7, 1, false);
        j.add(&map, 2, -diag, 7, 1, false);
        j.add(&map, 0, DVec3::new(0.1, -1.0, 0.0).normalize(), 8, 1, false);
        j.add(&map, 0, DVec3::new(1.0, -0.1, 0.0).normalize(), 9, 1, false);
        j.pass(
            &mut map,
            JoinParams::new(30f64.to_radians().cos(), f64::INFINITY, JoinTest::Cone),
            &GrowthLimits::default(),
            1,
        )
        .unwrap();
        map.validate().unwrap();
        assert_eq!(map.face_count(), 2);
        assert_eq!(map.edge_ends(4), (0, 2));
        let face_of = |i: usize| j.branches[i].face;
        let has3 = |f: u32| {
            let mut l = Vec::new();
            map.loop_vertices(f, &mut l);
            l.contains(&3)
        };
        assert!(has3(face_of(2)));
        assert!(!has3(face_of(3)));
    }

    #[test]
    fn the_four_readings_of_the_orientation_criterion() {
        // Square corners 0 and 2; branches of one type at both.
        let sides = vec![AxiomSide { kind: 0, reversed: false }; 4];
        let base = Map::seed(&sides, 1.0, DVec3::ZERO);
        let joins = |d0: DVec3, d2: DVec3, test: JoinTest| {
            let mut map = base.clone();
            let mut j = Joiner::default();
            j.add(&map, 0, d0.normalize(), 0, 1, false);
            j.add(&map, 2, d2.normalize(), 0, 1, false);
            let prm = JoinParams::new(30f64.to_radians().cos(), f64::INFINITY, test);
            j.pass(&mut map, prm, &GrowthLimits::default(), 1).unwrap();
            assert_eq!(j.joined as usize, map.face_count() - 1);
            map.face_count() == 2
        };
        let diag = DVec3::new(1.0, -1.0, 0.0);
        let rot = |deg: f64, v: DVec3| glam::DQuat::from_rotation_z(deg.to_radians()) * v;
        // Exactly opposite along the chord: every reading joins.
        assert!(JoinTest::ALL.iter().all(|&t| joins(diag, -diag, t)));
        // Anti-parallel, both 40° off the chord: not in the cone.
        let (a, b) = (rot(40.0, diag), rot(40.0, -diag));
        assert!(!joins(a, b, JoinTest::Cone));
        assert!(joins(a, b, JoinTest::Facing) && joins(a, b, JoinTest::Paper) && joins(a, b, JoinTest::Scalar));
        // 90° apart, each pointing 45° off the chord towards the other:
        // only the literal scalar product (0 < cos 30°) joins.
        let (a, b) = (rot(45.0, diag), rot(-45.0, -diag));
        assert!(joins(a, b, JoinTest::Scalar));
        assert!(!joins(a, b, JoinTest::Cone) && !joins(a, b, JoinTest::Facing) && !joins(a, b, JoinTest::Paper));
        // Anti-parallel but back to back: only the paper's bare criteria.
        assert!(joins(-diag, diag, JoinTest::Paper));
        assert!(!joins(-diag, diag, JoinTest::Facing) && !joins(-diag, diag, JoinTest::Scalar));
        // Nearly parallel (20° apart) never joins.
        assert!(JoinTest::ALL.iter().all(|&t| !joins(rot(10.0, diag), rot(-10.0, diag), t)));
    }

    #[test]
    fn distance_limit_and_cone_block_joins() {
        let sides = vec![AxiomSide { kind: 0, reversed: false }; 4];
        let base = Map::seed(&sides, 1.0, DVec3::ZERO);
        let run = |d0: DVec3, d2: DVec3, max_d2: f64| {
            let mut map = base.clone();
            let mut j = Joiner::default();
            j.add(&map, 0, d0.normalize(), 0, 1, false);
            j.add(&map, 2, d2.normalize(), 0, 1, false);
            j.pass(
                &mut map,
                JoinParams::new(30f64.to_radians().cos(), max_d2, JoinTest::Cone),
                &GrowthLimits::default(),
                1,
            )
            .unwrap();
            map.face_count()
        };
        let diag = DVec3::new(1.0, -1.0, 0.0);
        assert_eq!(run(diag, -diag, f64::INFINITY), 2);
        assert_eq!(run(diag, -diag, 1.9), 1); // |diag| = √2, d² = 2
        // Anti-parallel but both rotated 40° off the line: outside the cone.
        let r = glam::DQuat::from_rotation_z(40f64.to_radians());
        assert_eq!(run(r * diag, r * -diag, f64::INFINITY), 1);
        // Same type is required.
        let mut map = base.clone();
        let mut j = Joiner::default();
        j.add(&map, 0, diag.normalize(), 0, 1, false);
        j.add(&map, 2, -diag.normalize(), 1, 1, false);
        j.pass(&mut map, JoinParams::new(0.5, f64::INFINITY, JoinTest::Cone), &GrowthLimits::default(), 1).unwrap();
        assert_eq!(map.face_count(), 1);
    }
}
