//! Splitting planar polygons (turtle regions, surface faces) into
//! triangles.

use glam::Vec3;

/// Splits a planar polygon into triangles by ear clipping in its plane;
/// returns index triples into `points`.
///
/// The plane's normal is the polygon's Newell normal, so clockwise and
/// counter-clockwise input both work: every triangle winds
/// counter-clockwise seen from that normal's side, i.e. the way the input
/// itself turns. Repeated points and points on a straight run (or at the tip
/// of a zero-width spike) are skipped. Fewer than three distinct corners or
/// zero area give no triangles. A convex outline gives the fan from its
/// first kept corner. On a self-intersecting outline where no ear is left
/// to clip, the rest is finished as a fan. Non-finite points give the plain
/// fan, so callers that check coordinates still see them.
pub fn triangulate_polygon(points: &[Vec3]) -> Vec<[u32; 3]> {
    let n = points.len();
    if n < 3 {
        return Vec::new();
    }
    if !points.iter().all(|p| p.is_finite()) {
        return (1..n as u32 - 1).map(|i| [0, i, i + 1]).collect();
    }
    ear_clip::triangulate(points)
}

mod ear_clip {
    //! Ear clipping in `f64` on the polygon projected to its plane.

    use glam::{DVec2, DVec3, Vec3};

    /// Relative tolerances: points closer than `SAME * size` are one point;
    /// a corner whose turn has |sin| below `STRAIGHT` is no corner. Both are
    /// far above `f32` rounding, far below anything drawn on purpose.
    const SAME: f64 = 1e-6;
    const STRAIGHT: f64 = 1e-6;

    /// [`super::triangulate_polygon`] for at least 3 finite points.
    pub(super) fn triangulate(points: &[Vec3]) -> Vec<[u32; 3]> {
        let Some(q) = project(points) else { return Vec::new() };
        let size = bounds_size(&q);
        let mut ring = distinct(&q, SAME * size);
        drop_straight(&q, &mut ring);
        if ring.len() < 3 {
            return Vec::new();
        }
        let mut out = Vec::with_capacity(ring.len() - 2);
        let m = ring.len();
        if (0..m).all(|i| turn(&q, ring[(i + m - 1) % m], ring[i], ring[(i + 1) % m]) > 0.0) {
            out.extend((1..m - 1).map(|k| [ring[0], ring[k], ring[k + 1]]));
        } else {
            clip_ears(&q, ring, SAME * size, &mut out);
        }
        out.into_iter().map(|t| t.map(|i| i as u32)).collect()
    }

    /// The points in 2D coordinates of their plane, seen from the side of the
    /// Newell normal (so the outline turns counter-clockwise); `None` when
    /// the outline encloses no area.
    fn project(points: &[Vec3]) -> Option<Vec<DVec2>> {
        let p: Vec<DVec3> = points.iter().map(|v| v.as_dvec3()).collect();
        let o = p[0];
        let normal: DVec3 = (0..p.len()).map(|i| (p[i] - o).cross(p[(i + 1) % p.len()] - o)).sum();
        let (lo, hi) = p.iter().fold((o, o), |(lo, hi), &v| (lo.min(v), hi.max(v)));
        let size = (hi - lo).length();
        // |normal| is twice the area.
        if normal.length() <= 1e-10 * size * size {
            return None;
        }
        let w = normal.normalize();
        let u = w.any_orthonormal_vector();
        let v = w.cross(u);
        Some(p.iter().map(|&x| DVec2::new((x - o).dot(u), (x - o).dot(v))).collect())
    }

    fn bounds_size(q: &[DVec2]) -> f64 {
        let (lo, hi) = q.iter().fold((q[0], q[0]), |(lo, hi), &v| (lo.min(v), hi.max(v)));
        (hi - lo).length()
    }

    /// Indices of `q` without runs of (nearly) equal points, also across the
    /// wrap-around.
    fn distinct(q: &[DVec2], eps: f64) -> Vec<usize> {
        let mut ring: Vec<usize> = Vec::with_capacity(q.len());
        for i in 0..q.len() {
            if ring.last().is_none_or(|&j| q[j].distance(q[i]) > eps) {
                ring.push(i);
            }
        }
        while ring.len() > 1 && q[ring[0]].distance(q[ring[ring.len() - 1]]) <= eps {
            ring.pop();
        }
        ring
    }

    /// The turn at `b` on the way `a → b → c`: positive when left
    /// (counter-clockwise), 0 for a straight run or a spike.
    fn turn(q: &[DVec2], a: usize, b: usize, c: usize) -> f64 {
        let (d0, d1) = (q[b] - q[a], q[c] - q[b]);
        let cross = d0.perp_dot(d1);
        if cross.abs() <= STRAIGHT * d0.length() * d1.length() { 0.0 } else { cross }
    }

    /// Removes corners that do not turn, until every remaining one does.
    fn drop_straight(q: &[DVec2], ring: &mut Vec<usize>) {
        let mut i = 0;
        let mut unchanged = 0;
        while ring.len() >= 3 && unchanged < ring.len() {
            let m = ring.len();
            if turn(q, ring[(i + m - 1) % m], ring[i], ring[(i + 1) % m]) == 0.0 {
                ring.remove(i);
                unchanged = 0;
                // Step back: the previous corner has a new neighbour.
                i = (i + ring.len() - 1) % ring.len().max(1);
            } else {
                i = (i + 1) % m;
                unchanged += 1;
            }
        }
    }

    /// Whether `p` lies inside the counter-clockwise triangle `t` or within
    /// `eps` of its edges. A corner on the cut (a, c) must stop the ear, or
    /// the ring left behind has a straight corner and one triangle too few.
    fn in_triangle(p: DVec2, [a, b, c]: [DVec2; 3], eps: f64) -> bool {
        let left = |s: DVec2, e: DVec2| (e - s).perp_dot(p - s) >= -eps * (e - s).length();
        left(a, b) && left(b, c) && left(c, a)
    }

    /// Clips ears off a counter-clockwise ring of turning corners.
    fn clip_ears(q: &[DVec2], mut ring: Vec<usize>, eps: f64, out: &mut Vec<[usize; 3]>) {
        let mut i = 0;
        let mut tried = 0;
        while ring.len() > 3 {
            let m = ring.len();
            let (a, b, c) = (ring[(i + m - 1) % m], ring[i], ring[(i + 1) % m]);
            let t = turn(q, a, b, c);
            // A corner that became straight is dropped without a triangle.
            let clip = t == 0.0 || (t > 0.0 && is_ear(q, &ring, [a, b, c], eps));
            if clip {
                if t != 0.0 {
                    out.push([a, b, c]);
                }
                ring.remove(i);
                i %= ring.len();
                tried = 0;
            } else {
                i = (i + 1) % m;
                tried += 1;
                if tried >= m {
                    // Stuck (the outline crosses itself): fan the rest.
                    out.extend((1..m - 1).map(|k| [ring[0], ring[k], ring[k + 1]]));
                    return;
                }
            }
        }
        if let [a, b, c] = ring[..]
            && turn(q, a, b, c) != 0.0
        {
            out.push([a, b, c]);
        }
    }

    /// No other corner of the ring lies in the triangle (corners at the same
    /// place as one of its own, where an outline touches itself, aside).
    fn is_ear(q: &[DVec2], ring: &[usize], t: [usize; 3], eps: f64) -> bool {
        let tri = t.map(|i| q[i]);
        let m = ring.len();
        (0..m).all(|k| {
            let j = ring[k];
            let p = q[j];
            // Only reflex corners can be inside an ear.
            t.contains(&j)
                || tri.contains(&p)
                || turn(q, ring[(k + m - 1) % m], j, ring[(k + 1) % m]) > 0.0
                || !in_triangle(p, tri, eps)
        })
    }
}
