//! The straight skeleton of a simple polygon without holes: every edge
//! moves inwards at unit speed, parallel to itself, and the corners trace
//! the skeleton. It gives the hip roof of a concave footprint (each edge's
//! *face* rises at the roof's slope) and the inset of a polygon by any
//! distance with its changes of topology (`offset(-d)`).
//!
//! The wavefront is simulated event by event (Felkel & Obdržálek's edge and
//! split events): the next event over all wavefront edges and reflex
//! vertices is found by brute force, which is cubic in the corner count but
//! simple and robust for the ≤ 256 corners a roof footprint may have.
//! Simultaneous events (squares, symmetric L and U shapes) are handled by
//! merging every wavefront edge that has shrunk to nothing and collapsing
//! every wavefront polygon that has lost its area, within a tolerance
//! relative to the polygon's size.

use crate::polygon::{area2, bbox};
use glam::DVec2;

/// A wavefront vertex: where the offset lines of edges `ein` (arriving) and
/// `eout` (leaving) meet, at `birth` at time `t0`, moving with `vel`.
#[derive(Clone, Copy, Debug)]
struct Vert {
    ein: usize,
    eout: usize,
    birth: DVec2,
    t0: f64,
    vel: DVec2,
}

impl Vert {
    fn at(&self, t: f64) -> DVec2 {
        self.birth + self.vel * (t - self.t0)
    }
}

/// The next event: its time, and for a split the wavefront polygon, the
/// index of the reflex vertex and of the edge it hits (`None` for edges
/// that shrink to nothing).
type Event = Option<(f64, Option<(usize, usize, usize)>)>;

/// The skeleton of a polygon, or its wavefront at a given time.
pub(crate) struct Skeleton {
    /// The polygon after repeated and collinear corners were dropped
    /// (counter-clockwise); edge `k` runs from corner `k` to `k + 1`.
    pub corners: Vec<DVec2>,
    /// Per edge, its face: a counter-clockwise polygon beginning with the
    /// edge's two corners. Empty when the wavefront was stopped early.
    pub faces: Vec<Vec<DVec2>>,
    /// The wavefront polygons at the stop time (empty when run to the end).
    pub fronts: Vec<Vec<DVec2>>,
}

/// Why a skeleton could not be built (numerically hopeless input).
const GAVE_UP: &str = "the straight skeleton of this footprint could not be built (nearly touching edges?)";

struct Run {
    n: Vec<DVec2>,
    d: Vec<DVec2>,
    off: Vec<f64>,
    verts: Vec<Vert>,
    lavs: Vec<Vec<usize>>,
    /// Undirected boundary segments of each edge's face.
    segs: Vec<Vec<(DVec2, DVec2)>>,
    /// Lengths below this are nothing.
    eps: f64,
}

impl Run {
    fn new_vert(&mut self, ein: usize, eout: usize, at: DVec2, t: f64) -> usize {
        let (a, b) = (self.n[ein], self.n[eout]);
        let det = a.perp_dot(b);
        // The vertex starts where the event happened (so the skeleton's
        // paths meet exactly) and moves along the bisector of its lines.
        let vel = if det.abs() > 1e-12 {
            DVec2::new(b.y - a.y, a.x - b.x) / det
        } else if a.dot(b) > 0.0 {
            a
        } else {
            // Antiparallel lines that coincide now: a wavefront of no width,
            // collapsed by the next normalisation.
            DVec2::ZERO
        };
        self.verts.push(Vert { ein, eout, birth: at, t0: t, vel: if vel.is_finite() { vel } else { DVec2::ZERO } });
        self.verts.len() - 1
    }

    /// Ends vertex `v` at time `t`: its path bounds the faces on both sides.
    fn end(&mut self, v: usize, t: f64) {
        let w = self.verts[v];
        let p = w.at(t);
        if w.birth.distance(p) > self.eps {
            self.segs[w.ein].push((w.birth, p));
            self.segs[w.eout].push((w.birth, p));
        }
    }

    fn is_reflex(&self, v: usize) -> bool {
        let w = self.verts[v];
        self.d[w.ein].perp_dot(self.d[w.eout]) < -1e-12
    }

    /// The signed length of the wavefront edge from `u` to `w` at `t`.
    fn length(&self, u: usize, w: usize, t: f64) -> f64 {
        let e = self.verts[u].eout;
        self.d[e].dot(self.verts[w].at(t) - self.verts[u].at(t))
    }

    /// The earliest event at or after `t`: (time, Some((lav, v index,
    /// edge index)) for a split, None for an edge event).
    fn next_event(&self, t: f64) -> Event {
        let mut best: Event = None;
        fn take(best: &mut Event, te: f64, what: Option<(usize, usize, usize)>) {
            if te.is_finite() && best.is_none_or(|(b, _)| te < b) {
                *best = Some((te, what));
            }
        }
        for (li, lav) in self.lavs.iter().enumerate() {
            let m = lav.len();
            for i in 0..m {
                let (u, w) = (lav[i], lav[(i + 1) % m]);
                let e = self.verts[u].eout;
                let rate = self.d[e].dot(self.verts[w].vel - self.verts[u].vel);
                if rate < -1e-12 {
                    let l0 = self.length(u, w, t);
                    take(&mut best, (t - l0 / rate).max(t), None);
                }
            }
            for i in 0..m {
                let v = lav[i];
                if !self.is_reflex(v) {
                    continue;
                }
                let vv = self.verts[v];
                let pv = vv.at(t);
                for j in 0..m {
                    let (a, b) = (lav[j], lav[(j + 1) % m]);
                    if a == v || b == v {
                        continue;
                    }
                    let e = self.verts[a].eout;
                    if e == vv.ein || e == vv.eout {
                        continue;
                    }
                    let g0 = self.n[e].dot(pv) - (self.off[e] + t);
                    let closing = 1.0 - self.n[e].dot(vv.vel);
                    if g0 < -self.eps || closing <= 1e-12 {
                        continue;
                    }
                    let th = t + (g0 / closing).max(0.0);
                    if best.is_some_and(|(b, _)| th >= b) {
                        continue;
                    }
                    let x = vv.at(th);
                    let (pa, pb) = (self.verts[a].at(th), self.verts[b].at(th));
                    let (sa, sb, sx) = (self.d[e].dot(pa), self.d[e].dot(pb), self.d[e].dot(x));
                    if sb - sa >= -self.eps && sx >= sa - self.eps && sx <= sb + self.eps {
                        take(&mut best, th, Some((li, i, j)));
                    }
                }
            }
        }
        best
    }

    /// Splits lav `li` where its vertex at `i` hits the edge beginning at `j`.
    fn split(&mut self, li: usize, i: usize, j: usize, t: f64) {
        let mut lav = std::mem::take(&mut self.lavs[li]);
        lav.rotate_left(i);
        let m = lav.len();
        let j = (j + m - i) % m;
        let v = lav[0];
        let e = self.verts[lav[j]].eout;
        let x = self.verts[v].at(t);
        self.end(v, t);
        let (ein, eout) = (self.verts[v].ein, self.verts[v].eout);
        let v1 = self.new_vert(ein, e, x, t);
        let v2 = self.new_vert(e, eout, x, t);
        let mut first = vec![v1];
        first.extend_from_slice(&lav[j + 1..]);
        let mut second = vec![v2];
        second.extend_from_slice(&lav[1..=j]);
        self.lavs[li] = first;
        self.lavs.push(second);
    }

    /// Merges every wavefront edge shorter than the tolerance at `t` and
    /// removes the wavefront polygons that have collapsed.
    fn normalise(&mut self, t: f64) {
        let mut li = 0;
        while li < self.lavs.len() {
            let mut merged = true;
            while merged && self.lavs[li].len() >= 2 {
                merged = false;
                let m = self.lavs[li].len();
                for i in 0..m {
                    let (u, w) = (self.lavs[li][i], self.lavs[li][(i + 1) % m]);
                    if self.length(u, w, t) <= self.eps || self.verts[u].at(t).distance(self.verts[w].at(t)) <= self.eps
                    {
                        let x = (self.verts[u].at(t) + self.verts[w].at(t)) * 0.5;
                        self.end(u, t);
                        self.end(w, t);
                        let (ein, eout) = (self.verts[u].ein, self.verts[w].eout);
                        let nv = self.new_vert(ein, eout, x, t);
                        let lav = &mut self.lavs[li];
                        if i + 1 == m {
                            lav.pop();
                            lav[0] = nv;
                        } else {
                            lav[i] = nv;
                            lav.remove(i + 1);
                        }
                        merged = true;
                        break;
                    }
                }
            }
            let pts: Vec<DVec2> = self.lavs[li].iter().map(|&v| self.verts[v].at(t)).collect();
            // No area left: narrower than the tolerance everywhere (its
            // area at most its perimeter times the tolerance), or inverted.
            let perimeter: f64 = (0..pts.len()).map(|k| pts[k].distance(pts[(k + 1) % pts.len()])).sum();
            if pts.len() < 3 || area2(&pts) <= 2.0 * self.eps * perimeter {
                let lav = self.lavs.swap_remove(li);
                let m = lav.len();
                for k in 0..m {
                    let (u, w) = (lav[k], lav[(k + 1) % m]);
                    self.end(u, t);
                    let (pu, pw) = (self.verts[u].at(t), self.verts[w].at(t));
                    if m >= 2 && pu.distance(pw) > self.eps {
                        self.segs[self.verts[u].eout].push((pu, pw));
                    }
                }
            } else {
                li += 1;
            }
        }
    }
}

/// Drops repeated corners and corners on a straight run; orients the
/// polygon counter-clockwise.
pub(crate) fn clean(p: &[DVec2], eps: f64) -> Vec<DVec2> {
    let mut q: Vec<DVec2> = Vec::with_capacity(p.len());
    for &x in p {
        if q.last().is_none_or(|l: &DVec2| l.distance(x) > eps) {
            q.push(x);
        }
    }
    while q.len() > 1 && q[0].distance(q[q.len() - 1]) <= eps {
        q.pop();
    }
    loop {
        let m = q.len();
        if m < 3 {
            break;
        }
        let straight = (0..m).find(|&i| {
            let (a, b, c) = (q[(i + m - 1) % m], q[i], q[(i + 1) % m]);
            (b - a).perp_dot(c - b).abs() <= 1e-12 * (b - a).length() * (c - b).length() && (b - a).dot(c - b) > 0.0
        });
        match straight {
            Some(i) => {
                q.remove(i);
            }
            None => break,
        }
    }
    if area2(&q) < 0.0 {
        q.reverse();
    }
    q
}

/// Runs the wavefront of the simple polygon `p` until it has collapsed
/// (faces) or until time `stop` (fronts).
pub(crate) fn skeleton(p: &[DVec2], stop: Option<f64>) -> Result<Skeleton, String> {
    let scale = bbox(p).map_or(0.0, |(lo, hi)| (hi - lo).length());
    let eps = 1e-9 * scale.max(f64::MIN_POSITIVE);
    let corners = clean(p, eps);
    let k = corners.len();
    if k < 3 {
        return Ok(Skeleton { corners, faces: Vec::new(), fronts: Vec::new() });
    }
    let d: Vec<DVec2> = (0..k).map(|i| (corners[(i + 1) % k] - corners[i]).normalize()).collect();
    let n: Vec<DVec2> = d.iter().map(|d| DVec2::new(-d.y, d.x)).collect();
    let off: Vec<f64> = (0..k).map(|i| n[i].dot(corners[i])).collect();
    let mut run = Run { n, d, off, verts: Vec::new(), lavs: Vec::new(), segs: vec![Vec::new(); k], eps };
    let lav: Vec<usize> = (0..k).map(|i| run.new_vert((i + k - 1) % k, i, corners[i], 0.0)).collect();
    run.lavs.push(lav);
    let mut t = 0.0;
    let mut guard = 8 * k * k + 64;
    while !run.lavs.is_empty() {
        guard = guard.checked_sub(1).ok_or_else(|| GAVE_UP.to_string())?;
        let Some((te, what)) = run.next_event(t) else {
            // Nothing left to happen: whatever remains has no area.
            if stop.is_some() {
                break;
            }
            run.normalise(t);
            let rest = std::mem::take(&mut run.lavs);
            for lav in rest {
                for v in lav {
                    run.end(v, t);
                }
            }
            break;
        };
        if stop.is_some_and(|s| te > s) {
            break;
        }
        t = te;
        if let Some((li, i, j)) = what {
            run.split(li, i, j, t);
        }
        run.normalise(t);
    }
    if let Some(s) = stop {
        let fronts = run
            .lavs
            .iter()
            .map(|lav| lav.iter().map(|&v| run.verts[v].at(s)).collect::<Vec<_>>())
            .filter(|f| area2(f) > eps * scale)
            .collect();
        return Ok(Skeleton { corners, faces: Vec::new(), fronts });
    }
    let mut faces = Vec::with_capacity(k);
    for (e, segs) in run.segs.iter().enumerate() {
        faces.push(chain(corners[e], corners[(e + 1) % k], segs, eps).ok_or_else(|| GAVE_UP.to_string())?);
    }
    Ok(Skeleton { corners, faces, fronts: Vec::new() })
}

/// The face of edge `a → b`: `a`, `b`, then the skeleton path from `b`
/// back to `a` through the face's segments.
fn chain(a: DVec2, b: DVec2, segs: &[(DVec2, DVec2)], eps: f64) -> Option<Vec<DVec2>> {
    let mut used = vec![false; segs.len()];
    let mut face = vec![a, b];
    let mut cur = b;
    let tol = 8.0 * eps;
    for _ in 0..=segs.len() {
        if cur.distance(a) <= tol && face.len() > 2 {
            face.pop();
            return Some(face);
        }
        let here = *face.get(face.len().wrapping_sub(2)).unwrap_or(&a);
        let dir_in = (cur - here).normalize_or_zero();
        let mut pick: Option<(f64, usize, DVec2)> = None;
        for (s, &(p, q)) in segs.iter().enumerate() {
            if used[s] {
                continue;
            }
            let other = if p.distance(cur) <= tol {
                q
            } else if q.distance(cur) <= tol {
                p
            } else {
                continue;
            };
            let out = (other - cur).normalize_or_zero();
            // Angle turned left from straight on: walking with the face on
            // the left, the sharpest left turn stays on its boundary.
            let turn = dir_in.perp_dot(out).atan2(dir_in.dot(out));
            if pick.is_none_or(|(bt, _, _)| turn > bt) {
                pick = Some((turn, s, other));
            }
        }
        let (_, s, other) = pick?;
        used[s] = true;
        face.push(other);
        cur = other;
    }
    None
}

/// Concave footprints the skeleton's and the roofs' tests share.
#[cfg(test)]
pub(crate) mod fixtures {
    use glam::DVec2;

    fn poly(c: &[(f64, f64)]) -> Vec<DVec2> {
        c.iter().map(|&(x, y)| DVec2::new(x, y)).collect()
    }

    /// An L of arms 4 wide, 10 long: its hip roof's ridge is 2 high.
    pub(crate) fn l_arms_4() -> Vec<DVec2> {
        poly(&[(0.0, 0.0), (10.0, 0.0), (10.0, 4.0), (4.0, 4.0), (4.0, 10.0), (0.0, 10.0)])
    }

    /// A U of legs 3 wide on a base 4 deep: ridge 2 high.
    pub(crate) fn u_legs_3() -> Vec<DVec2> {
        poly(&[(0.0, 0.0), (12.0, 0.0), (12.0, 10.0), (9.0, 10.0), (9.0, 4.0), (3.0, 4.0), (3.0, 10.0), (0.0, 10.0)])
    }

    /// An irregular hexagon with a sharp notch.
    pub(crate) fn notched() -> Vec<DVec2> {
        poly(&[(0.0, 0.0), (9.0, 1.0), (8.0, 7.0), (5.0, 3.0), (2.5, 8.0), (-1.0, 5.0)])
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn poly(c: &[(f64, f64)]) -> Vec<DVec2> {
        c.iter().map(|&(x, y)| DVec2::new(x, y)).collect()
    }

    /// The distance from `x` to the line of edge `e` of `s`.
    fn height(s: &Skeleton, e: usize, x: DVec2) -> f64 {
        let k = s.corners.len();
        let (a, b) = (s.corners[e], s.corners[(e + 1) % k]);
        (b - a).normalize().perp_dot(x - a)
    }

    /// The faces tile the polygon and every face point is where its edge's
    /// wavefront arrives first: its height is the least over all edges
    /// whose face it is in. Returns the highest point's height.
    fn check(p: &[DVec2]) -> f64 {
        let s = skeleton(p, None).unwrap();
        let total: f64 = s.faces.iter().map(|f| area2(f)).sum();
        assert!((total - area2(&s.corners)).abs() < 1e-7 * area2(&s.corners), "faces {total} vs {}", area2(p));
        // A point on several faces is as far from each face's edge line:
        // the roof planes meet there.
        for (e, f) in s.faces.iter().enumerate() {
            for x in f {
                for (e2, f2) in s.faces.iter().enumerate() {
                    if e2 != e && f2.iter().any(|y| y.distance(*x) < 1e-7) {
                        let (h1, h2) = (height(&s, e, *x), height(&s, e2, *x));
                        assert!((h1 - h2).abs() < 1e-7, "point {x} on faces {e} ({h1}) and {e2} ({h2})");
                    }
                }
            }
        }
        let mut top = 0.0f64;
        for (e, f) in s.faces.iter().enumerate() {
            assert!(area2(f) > 0.0, "face {e} {f:?}");
            for x in f {
                let h = height(&s, e, *x);
                assert!(h >= -1e-9, "face {e} point {x} below the eaves: {h}");
                top = top.max(h);
            }
        }
        top
    }

    #[test]
    fn a_rectangle_has_four_faces_and_a_ridge_at_half_its_depth() {
        let r = poly(&[(0.0, 0.0), (10.0, 0.0), (10.0, 4.0), (0.0, 4.0)]);
        assert!((check(&r) - 2.0).abs() < 1e-12);
        let s = skeleton(&r, None).unwrap();
        // Trapezoids along the long sides, triangles at the ends.
        let sizes: Vec<usize> = s.faces.iter().map(|f| f.len()).collect();
        assert_eq!(sizes, [4, 3, 4, 3]);
        assert!((area2(&s.faces[0]) / 2.0 - (10.0 + 6.0) / 2.0 * 2.0).abs() < 1e-9);
    }

    #[test]
    fn a_square_meets_in_its_centre() {
        let r = poly(&[(0.0, 0.0), (2.0, 0.0), (2.0, 2.0), (0.0, 2.0)]);
        assert!((check(&r) - 1.0).abs() < 1e-12);
        assert!(skeleton(&r, None).unwrap().faces.iter().all(|f| f.len() == 3));
    }

    #[test]
    fn concave_footprints_l_u_and_irregular() {
        // L of arms 4 wide: ridge height 2 everywhere.
        let l = fixtures::l_arms_4();
        assert!((check(&l) - 2.0).abs() < 1e-9);
        // L with arms of different widths (6 and 4).
        let l2 = poly(&[(0.0, 0.0), (12.0, 0.0), (12.0, 6.0), (4.0, 6.0), (4.0, 10.0), (0.0, 10.0)]);
        assert!((check(&l2) - 3.0).abs() < 1e-9);
        // U: legs 3 wide, base 4 deep.
        let u = fixtures::u_legs_3();
        assert!((check(&u) - 2.0).abs() < 1e-9);
        // An irregular concave polygon with a sharp notch.
        let q = fixtures::notched();
        check(&q);
        // A plus sign: four reflex corners meeting in vertex events.
        let plus = poly(&[
            (2.0, 0.0),
            (4.0, 0.0),
            (4.0, 2.0),
            (6.0, 2.0),
            (6.0, 4.0),
            (4.0, 4.0),
            (4.0, 6.0),
            (2.0, 6.0),
            (2.0, 4.0),
            (0.0, 4.0),
            (0.0, 2.0),
            (2.0, 2.0),
        ]);
        assert!((check(&plus) - 1.0).abs() < 1e-9);
    }

    #[test]
    fn convex_skeleton_heights_match_the_lower_envelope() {
        // On a convex polygon the roof is the lower envelope of the edge
        // planes: every face point's height is its least edge distance.
        let p = poly(&[(0.0, 0.0), (7.0, -1.0), (9.0, 3.0), (5.0, 7.0), (1.0, 5.0)]);
        let s = skeleton(&p, None).unwrap();
        for (e, f) in s.faces.iter().enumerate() {
            for x in f {
                let least = (0..s.corners.len()).map(|k| height(&s, k, *x)).fold(f64::INFINITY, f64::min);
                assert!((height(&s, e, *x) - least).abs() < 1e-9);
            }
        }
    }

    proptest::proptest! {
        /// Star-shaped polygons (random radii at sorted angles) are simple
        /// and often concave: their skeletons tile them with consistent
        /// heights, and insets never grow.
        #[test]
        fn star_polygons(radii in proptest::collection::vec(1.0f64..10.0, 3..24), turn in 0.0f64..1.0, d in 0.1f64..3.0) {
            let k = radii.len();
            let p: Vec<DVec2> = radii
                .iter()
                .enumerate()
                .map(|(i, r)| DVec2::from_angle(std::f64::consts::TAU * (i as f64 + turn * 0.5) / k as f64) * *r)
                .collect();
            check(&p);
            let inset: f64 = skeleton(&p, Some(d)).unwrap().fronts.iter().map(|f| area2(f)).sum();
            proptest::prop_assert!(inset <= area2(&p) + 1e-9);
        }
    }

    #[test]
    fn insets_change_topology() {
        // A dumbbell: two 6 × 6 squares joined by a corridor 2 wide; an
        // inset by 1.5 leaves two 3 × 3 squares.
        let db = poly(&[
            (0.0, 0.0),
            (6.0, 0.0),
            (6.0, 2.0),
            (10.0, 2.0),
            (10.0, 0.0),
            (16.0, 0.0),
            (16.0, 6.0),
            (10.0, 6.0),
            (10.0, 4.0),
            (6.0, 4.0),
            (6.0, 6.0),
            (0.0, 6.0),
        ]);
        let s = skeleton(&db, Some(1.5)).unwrap();
        assert_eq!(s.fronts.len(), 2);
        for f in &s.fronts {
            assert!((area2(f) / 2.0 - 9.0).abs() < 1e-9, "{f:?}");
        }
        // By 0.5 it is one polygon: the corridor 1 wide survives.
        let s = skeleton(&db, Some(0.5)).unwrap();
        assert_eq!(s.fronts.len(), 1);
        assert!((area2(&s.fronts[0]) / 2.0 - (2.0 * 25.0 + 5.0)).abs() < 1e-9);
        // Past the inradius nothing is left.
        assert!(skeleton(&db, Some(3.5)).unwrap().fronts.is_empty());
    }
}
