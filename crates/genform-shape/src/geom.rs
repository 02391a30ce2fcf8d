//! Planar polygons, prisms and roofs: the geometry of polygon and mass
//! scopes (`lot`, `extrude`, `comp`, `roof_*`).
//!
//! Everything here is plain `f64` geometry with no grammar concepts, so it
//! is tested on its own. Polygons are lists of points, counter-clockwise
//! (positive signed area) unless a function says otherwise.

use crate::polygon::{area2, bbox};
use genform_core::scene::{Mesh, triangulate_polygon};
use glam::{DVec2, DVec3, Vec3};

/// The area centroid, or the vertex mean when the area is zero.
pub(crate) fn centroid(p: &[DVec2]) -> DVec2 {
    let n = p.len();
    let a = area2(p);
    if a == 0.0 || n < 3 {
        return p.iter().copied().sum::<DVec2>() / n.max(1) as f64;
    }
    let mut c = DVec2::ZERO;
    for i in 0..n {
        let (u, v) = (p[i], p[(i + 1) % n]);
        c += (u + v) * u.perp_dot(v);
    }
    c / (3.0 * a)
}

/// Whether segments `a–b` and `c–d` touch (closed segments).
fn segments_touch(a: DVec2, b: DVec2, c: DVec2, d: DVec2) -> bool {
    let o = |p: DVec2, q: DVec2, r: DVec2| (q - p).perp_dot(r - p);
    let on = |p: DVec2, q: DVec2, r: DVec2| r.cmpge(p.min(q)).all() && r.cmple(p.max(q)).all();
    let (d1, d2, d3, d4) = (o(c, d, a), o(c, d, b), o(a, b, c), o(a, b, d));
    if ((d1 > 0.0 && d2 < 0.0) || (d1 < 0.0 && d2 > 0.0)) && ((d3 > 0.0 && d4 < 0.0) || (d3 < 0.0 && d4 > 0.0)) {
        return true;
    }
    (d1 == 0.0 && on(c, d, a)) || (d2 == 0.0 && on(c, d, b)) || (d3 == 0.0 && on(a, b, c)) || (d4 == 0.0 && on(a, b, d))
}

/// Whether the outline is a simple polygon: at least three corners, no
/// repeated points, no two edges meeting except neighbours at their shared
/// corner.
pub(crate) fn is_simple(p: &[DVec2]) -> bool {
    let n = p.len();
    if n < 3 {
        return false;
    }
    for i in 0..n {
        for j in i + 1..n {
            if p[i] == p[j] {
                return false;
            }
            let adjacent = j == i + 1 || (i == 0 && j == n - 1);
            if !adjacent && segments_touch(p[i], p[(i + 1) % n], p[j], p[(j + 1) % n]) {
                return false;
            }
        }
    }
    true
}

/// Whether a counter-clockwise polygon is convex (collinear corners allowed).
pub(crate) fn is_convex(p: &[DVec2]) -> bool {
    let n = p.len();
    let scale = bbox(p).map_or(0.0, |(lo, hi)| (hi - lo).length_squared());
    (0..n).all(|i| {
        let (a, b, c) = (p[i], p[(i + 1) % n], p[(i + 2) % n]);
        (b - a).perp_dot(c - b) >= -1e-12 * scale
    })
}

/// Sutherland–Hodgman: the part of `p` where `n · x <= c`. Convex pieces
/// stay convex; a concave polygon may come back with zero-width bridges,
/// which keep its area right.
pub(crate) fn clip(p: &[DVec2], n: DVec2, c: f64) -> Vec<DVec2> {
    let mut out = Vec::with_capacity(p.len() + 2);
    let len = p.len();
    for i in 0..len {
        let (a, b) = (p[i], p[(i + 1) % len]);
        let (da, db) = (n.dot(a) - c, n.dot(b) - c);
        if da <= 0.0 {
            out.push(a);
        }
        if (da < 0.0 && db > 0.0) || (da > 0.0 && db < 0.0) {
            let t = da / (da - db);
            out.push(a + (b - a) * t);
        }
    }
    out
}

/// The part of `p` with `lo <= x[axis] <= hi`.
pub(crate) fn clip_slab(p: &[DVec2], axis: usize, lo: f64, hi: f64) -> Vec<DVec2> {
    let mut n = DVec2::ZERO;
    n[axis] = 1.0;
    let upper = clip(p, n, hi);
    clip(&upper, -n, -lo)
}

/// Where along `axis` (between `-half` and `half`) the part of `p` before
/// the cut has area `area` (the area grows with the cut: bisection).
pub(crate) fn cut_at_area(p: &[DVec2], axis: usize, area: f64, half: f64) -> f64 {
    let (mut lo, mut hi) = (-half, half);
    for _ in 0..64 {
        let mid = 0.5 * (lo + hi);
        if crate::polygon::area2(&clip_slab(p, axis, -half - 1.0, mid)).abs() / 2.0 < area {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    0.5 * (lo + hi)
}

/// A counter-clockwise polygon grown outwards by `d` (each edge moved out
/// by `d`, neighbours' lines intersected: mitred corners). Corners on a
/// straight run are dropped first. On a concave polygon a large `d` can
/// make the outline cross itself; callers check.
pub(crate) fn offset_miter(p: &[DVec2], d: f64) -> Vec<DVec2> {
    if d == 0.0 {
        return p.to_vec();
    }
    let n = p.len();
    let q: Vec<DVec2> = (0..n)
        .filter(|&i| {
            let (a, b, c) = (p[(i + n - 1) % n], p[i], p[(i + 1) % n]);
            (b - a).perp_dot(c - b).abs() > 1e-12 * (b - a).length() * (c - b).length()
        })
        .map(|i| p[i])
        .collect();
    let m = q.len();
    if m < 3 {
        return p.to_vec();
    }
    // Edge i from q[i] to q[i+1], moved out along its right normal.
    let line = |i: usize| {
        let (a, b) = (q[i], q[(i + 1) % m]);
        let dir = (b - a).normalize();
        let out = DVec2::new(dir.y, -dir.x);
        (a + out * d, dir)
    };
    (0..m)
        .map(|i| {
            let (p0, d0) = line((i + m - 1) % m);
            let (p1, d1) = line(i);
            let t = (p1 - p0).perp_dot(d1) / d0.perp_dot(d1);
            p0 + d0 * t
        })
        .collect()
}

/// Converts an `f64` mesh to the Scene's `f32` mesh.
fn to_mesh(name: &str, pos: &[DVec3], tris: Vec<[u32; 3]>) -> Mesh {
    Mesh { name: name.to_string(), positions: pos.iter().map(|p| p.as_vec3()).collect(), triangles: tris }
}

/// The closed prism over a footprint in the unit scope: `foot` gives
/// `(x, z)` points counter-clockwise seen from +y (above), bottom at
/// y = −0.5, top at y = +0.5; triangles wind counter-clockwise seen from
/// outside. A concave footprint is ear-clipped.
pub(crate) fn prism_mesh(foot: &[DVec2]) -> Mesh {
    let n = foot.len();
    let mut pos: Vec<DVec3> = Vec::with_capacity(2 * n);
    pos.extend(foot.iter().map(|p| DVec3::new(p.x, -0.5, p.y)));
    pos.extend(foot.iter().map(|p| DVec3::new(p.x, 0.5, p.y)));
    let top: Vec<Vec3> = pos[n..].iter().map(|p| p.as_vec3()).collect();
    let mut tris = Vec::new();
    for t in triangulate_polygon(&top) {
        tris.push([t[0] + n as u32, t[1] + n as u32, t[2] + n as u32]);
        tris.push([t[2], t[1], t[0]]);
    }
    for i in 0..n as u32 {
        let j = (i + 1) % n as u32;
        let n = n as u32;
        tris.push([i, j, j + n]);
        tris.push([i, j + n, i + n]);
    }
    to_mesh("mass", &pos, tris)
}

/// The base of a taper over a counter-clockwise polygon (in the xy plane):
/// its area centroid, its corners at z = 0 and their triangles facing −z;
/// `None` for a degenerate polygon or `h` ≤ 0.
fn taper_base(foot: &[DVec2], h: f64) -> Option<(DVec2, Vec<DVec3>, Vec<[u32; 3]>)> {
    if foot.len() < 3 || area2(foot) <= 0.0 || h <= 0.0 {
        return None;
    }
    let pos: Vec<DVec3> = foot.iter().map(|p| DVec3::new(p.x, p.y, 0.0)).collect();
    let base: Vec<Vec3> = pos.iter().map(|p| p.as_vec3()).collect();
    let cap = triangulate_polygon(&base).into_iter().map(|t| [t[2], t[1], t[0]]).collect();
    Some((centroid(foot), pos, cap))
}

/// The pyramid over a counter-clockwise polygon (in the xy plane) with its
/// apex `h` above the polygon's area centroid: the base facing −z, one
/// triangle per edge. Empty for a degenerate polygon or `h` = 0.
pub(crate) fn pyramid_mesh(foot: &[DVec2], h: f64) -> Mesh {
    let Some((c, mut pos, mut tris)) = taper_base(foot, h) else {
        return Mesh { name: "taper".into(), ..Mesh::default() };
    };
    let n = foot.len() as u32;
    pos.push(DVec3::new(c.x, c.y, h));
    tris.extend((0..n).map(|i| [i, (i + 1) % n, n]));
    to_mesh("taper", &pos, tris)
}

/// The frustum over a counter-clockwise polygon (in the xy plane): its top
/// the polygon scaled by `s` (0 < s ≤ 1) about its area centroid, `h`
/// above; the base facing −z, one quad per edge. Empty for a degenerate
/// polygon or `h` = 0.
pub(crate) fn frustum_mesh(foot: &[DVec2], h: f64, s: f64) -> Mesh {
    let Some((c, mut pos, mut tris)) = taper_base(foot, h) else {
        return Mesh { name: "taper".into(), ..Mesh::default() };
    };
    let n = foot.len() as u32;
    pos.extend(foot.iter().map(|p| {
        let q = c + (*p - c) * s;
        DVec3::new(q.x, q.y, h)
    }));
    // The top: the base's triangles turned up, on the top's corners.
    let top: Vec<[u32; 3]> = tris.iter().map(|t| [t[2] + n, t[1] + n, t[0] + n]).collect();
    tris.extend(top);
    for i in 0..n {
        let j = (i + 1) % n;
        tris.push([i, j, j + n]);
        tris.push([i, j + n, i + n]);
    }
    to_mesh("taper", &pos, tris)
}

/// A height on a roof, never below the eaves, and +0 there: `f64::max`
/// may answer −0 for −0 and 0 (it did in debug builds and not in release
/// ones), which gave the two builds different bytes.
fn eave_height(h: f64) -> f64 {
    if h > 0.0 { h } else { 0.0 }
}

/// Most corners of a roof footprint.
pub(crate) const MAX_ROOF_CORNERS: usize = 256;

/// The four roof kinds.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum RoofKind {
    /// Two slopes meeting at a ridge along the longer side of the bounding
    /// box, vertical gable walls at the ends.
    Gable,
    /// One slope from every edge (the straight skeleton roof).
    Hip,
    /// Planes from every edge to one apex above the centroid.
    Pyramid,
    /// One slope rising towards +y.
    Shed,
    /// CGA's `roofRidge`: two slopes meeting at one ridge along the longer
    /// side of the bounding box, over any footprint: no hips, no gables
    /// at wing ends, vertical walls wherever the outline is off the eaves.
    Ridge,
}

impl RoofKind {
    /// The operation's name.
    pub(crate) fn name(self) -> &'static str {
        match self {
            RoofKind::Gable => "roof_gable",
            RoofKind::Hip => "roof_hip",
            RoofKind::Pyramid => "roof_pyramid",
            RoofKind::Shed => "roof_shed",
            RoofKind::Ridge => "roof_ridge",
        }
    }
}

/// A height plane `z = a·x + b·y + c`.
#[derive(Clone, Copy, Debug)]
struct Plane {
    g: DVec2,
    c: f64,
}

impl Plane {
    fn at(&self, p: DVec2) -> f64 {
        self.g.dot(p) + self.c
    }
}

/// The roof planes of `kind` over a convex counter-clockwise footprint;
/// `dir` (a unit vector) turns a gable's ridge along it, or a shed's slope
/// up it.
fn roof_planes(p: &[DVec2], kind: RoofKind, t: f64, dir: Option<DVec2>) -> Vec<Plane> {
    let n = p.len();
    let (lo, hi) = bbox(p).unwrap_or_default();
    // Inward unit normal of edge i and its base point.
    let edge = |i: usize| {
        let (a, b) = (p[i], p[(i + 1) % n]);
        let d = (b - a).normalize_or_zero();
        (DVec2::new(-d.y, d.x), a)
    };
    match kind {
        RoofKind::Hip => (0..n)
            .map(|i| {
                let (m, a) = edge(i);
                Plane { g: m * t, c: -t * m.dot(a) }
            })
            .filter(|pl| pl.g != DVec2::ZERO)
            .collect(),
        RoofKind::Pyramid => {
            let c = centroid(p);
            let r = (0..n)
                .map(|i| {
                    let (m, a) = edge(i);
                    m.dot(c - a)
                })
                .fold(f64::INFINITY, f64::min);
            let h = t * r;
            (0..n)
                .filter_map(|i| {
                    let (m, a) = edge(i);
                    let dist = m.dot(c - a);
                    (dist > 0.0 && m != DVec2::ZERO).then(|| {
                        let s = h / dist;
                        Plane { g: m * s, c: -s * m.dot(a) }
                    })
                })
                .collect()
        }
        RoofKind::Gable | RoofKind::Ridge if let Some(r) = dir => {
            let m = DVec2::new(-r.y, r.x);
            let (lo, hi) =
                p.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), q| (a.min(m.dot(*q)), b.max(m.dot(*q))));
            vec![Plane { g: m * t, c: -t * lo }, Plane { g: -m * t, c: t * hi }]
        }
        RoofKind::Shed if let Some(u) = dir => {
            let lo = p.iter().map(|q| u.dot(*q)).fold(f64::INFINITY, f64::min);
            vec![Plane { g: u * t, c: -t * lo }]
        }
        RoofKind::Gable | RoofKind::Ridge => {
            let along_x = hi.x - lo.x >= hi.y - lo.y;
            let k = if along_x { 1 } else { 0 };
            let mut g = DVec2::ZERO;
            g[k] = t;
            vec![Plane { g, c: -t * lo[k] }, Plane { g: -g, c: t * hi[k] }]
        }
        RoofKind::Shed => vec![Plane { g: DVec2::new(0.0, t), c: -t * lo.y }],
    }
}

/// Points welded within a tolerance.
struct Weld {
    pts: Vec<DVec2>,
    eps: f64,
}

impl Weld {
    fn id(&mut self, p: DVec2) -> usize {
        if let Some(i) = self.pts.iter().position(|q| q.distance_squared(p) <= self.eps * self.eps) {
            return i;
        }
        self.pts.push(p);
        self.pts.len() - 1
    }
}

/// The points of `pts` on segment `a`–`b` strictly between its ends (within
/// `eps`), in order from `a`.
fn points_between(pts: &[DVec2], a: usize, b: usize, eps: f64) -> Vec<usize> {
    let (pa, pb) = (pts[a], pts[b]);
    let d = pb - pa;
    let l2 = d.length_squared();
    if l2 == 0.0 {
        return Vec::new();
    }
    let mut on: Vec<(f64, usize)> = (0..pts.len())
        .filter(|&k| k != a && k != b)
        .filter_map(|k| {
            let s = (pts[k] - pa).dot(d) / l2;
            let off = (pts[k] - pa).perp_dot(d).abs() / l2.sqrt();
            (s > 0.0 && s < 1.0 && off <= eps).then_some((s, k))
        })
        .collect();
    on.sort_by(|x, y| x.0.total_cmp(&y.0));
    on.into_iter().map(|(_, k)| k).collect()
}

/// A ring of welded point ids with every welded point that lies on one of
/// its edges inserted, so that neighbouring faces share their corners.
fn full_ring(pts: &[DVec2], ids: &[usize], eps: f64) -> Vec<usize> {
    let mut r = Vec::with_capacity(ids.len());
    for k in 0..ids.len() {
        let (a, b) = (ids[k], ids[(k + 1) % ids.len()]);
        if a == b {
            continue;
        }
        r.push(a);
        r.extend(points_between(pts, a, b, eps));
    }
    r.dedup();
    while r.len() > 1 && r.first() == r.last() {
        r.pop();
    }
    r
}

/// Ear clipping that keeps every corner, including corners on a straight
/// run (a T-junction with a neighbouring face must stay a vertex for the
/// mesh to stay closed): a corner is an ear when it turns left and no other
/// corner lies in or on its triangle. Triangles index `p` and wind
/// counter-clockwise. A ring with no ear left is finished as a fan.
fn ear_clip_all(p: &[DVec2], eps: f64) -> Vec<[usize; 3]> {
    let mut ring: Vec<usize> = (0..p.len()).collect();
    let mut tris = Vec::with_capacity(p.len().saturating_sub(2));
    let inside = |x: DVec2, a: DVec2, b: DVec2, c: DVec2| {
        let tol = -eps * (b - a).length().max((c - b).length());
        (b - a).perp_dot(x - a) >= tol && (c - b).perp_dot(x - b) >= tol && (a - c).perp_dot(x - c) >= tol
    };
    while ring.len() > 3 {
        let m = ring.len();
        let ear = (0..m).find(|&i| {
            let (a, b, c) = (ring[(i + m - 1) % m], ring[i], ring[(i + 1) % m]);
            let (pa, pb, pc) = (p[a], p[b], p[c]);
            (pb - pa).perp_dot(pc - pb) > eps * (pb - pa).length().max((pc - pb).length())
                && !ring.iter().any(|&k| k != a && k != b && k != c && inside(p[k], pa, pb, pc))
        });
        let Some(i) = ear else { break };
        tris.push([ring[(i + m - 1) % m], ring[i], ring[(i + 1) % m]]);
        ring.remove(i);
    }
    for k in 1..ring.len().saturating_sub(1) {
        tris.push([ring[0], ring[k], ring[k + 1]]);
    }
    tris
}

/// Whether `m` lies on the outline of `foot` (within `tol`).
fn on_outline(foot: &[DVec2], m: DVec2, tol: f64) -> bool {
    (0..foot.len()).any(|i| {
        let (a, b) = (foot[i], foot[(i + 1) % foot.len()]);
        let d = b - a;
        let s = ((m - a).dot(d) / d.length_squared().max(f64::MIN_POSITIVE)).clamp(0.0, 1.0);
        (a + d * s).distance(m) <= tol
    })
}

/// The shed roof over any simple counter-clockwise footprint `f` (the
/// footprint `foot` grown by the overhangs): one plane of slope `t` rising
/// along the unit vector `up` from the lowest corner, the footprint lifted
/// onto it as the top, vertical walls down each edge. With `apart` the
/// walls in `foot`'s edges (no overhang there) are the second mesh.
fn shed_roof(f: &[DVec2], foot: &[DVec2], t: f64, up: DVec2, apart: bool) -> (Mesh, Mesh) {
    let n = f.len();
    let (lo, hi) = bbox(f).unwrap_or_default();
    let scale = (hi - lo).length().max(f64::MIN_POSITIVE);
    let eps = 1e-9 * scale;
    let low = f.iter().map(|q| up.dot(*q)).fold(f64::INFINITY, f64::min);
    let mut pos: Vec<DVec3> = f.iter().map(|p| DVec3::new(p.x, p.y, 0.0)).collect();
    let top: Vec<usize> = (0..n)
        .map(|k| {
            let z = eave_height(t * (up.dot(f[k]) - low));
            if z > eps {
                pos.push(DVec3::new(f[k].x, f[k].y, z));
                pos.len() - 1
            } else {
                k
            }
        })
        .collect();
    let cap = ear_clip_all(f, eps);
    lifted_solid(&pos, f, &top, &cap, &cap, (foot, apart, scale))
}

/// The closed solid between a ring at the eaves (corners `0..n` of `pos`,
/// `ring`'s points, ear-clipped into `cap`) and a top over it (`top_tris`,
/// whose corners `top` maps into `pos`): the ring's cap facing down, the
/// top, and a vertical wall down each edge of the ring where the top stands
/// above it. `(foot, apart, scale)`: with `apart`, the walls in `foot`'s
/// edges (within 10⁻⁷ `scale`) are the second mesh.
fn lifted_solid(
    pos: &[DVec3],
    ring: &[DVec2],
    top: &[usize],
    cap: &[[usize; 3]],
    top_tris: &[[usize; 3]],
    (foot, apart, scale): (&[DVec2], bool, f64),
) -> (Mesh, Mesh) {
    let n = ring.len();
    let mut tris: Vec<[u32; 3]> = cap.iter().map(|c| [c[2], c[1], c[0]].map(|i| i as u32)).collect();
    tris.extend(top_tris.iter().map(|c| c.map(|i| top[i] as u32)));
    let mut walls: Vec<[u32; 3]> = Vec::new();
    for a in 0..n {
        let b = (a + 1) % n;
        let (ta, tb) = (top[a], top[b]);
        let out =
            if apart && on_outline(foot, (ring[a] + ring[b]) * 0.5, 1e-7 * scale) { &mut walls } else { &mut tris };
        if tb != b {
            out.push([a as u32, b as u32, tb as u32]);
        }
        if ta != a {
            out.push([a as u32, tb as u32, ta as u32]);
        }
    }
    if walls.is_empty() {
        return (compact_mesh("roof", pos, &tris), Mesh { name: "gable".into(), ..Mesh::default() });
    }
    (compact_mesh("roof", pos, &tris), compact_mesh("gable", pos, &walls))
}

/// The ridge roof over any simple counter-clockwise footprint `f` (the
/// footprint `foot` grown by the overhangs): two planes of slope `t` rising
/// across the unit ridge direction `r` from the outline's extremes, the
/// top the lower of them, vertical walls down each edge (with `apart`,
/// those in `foot`'s edges are the second mesh). The footprint is
/// triangulated, every triangle the ridge line crosses cut along it, and
/// the corners lifted.
fn ridge_roof(f: &[DVec2], foot: &[DVec2], t: f64, r: DVec2, apart: bool) -> (Mesh, Mesh) {
    let m = r.perp();
    let (lo, hi) = f.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), q| (a.min(m.dot(*q)), b.max(m.dot(*q))));
    let mid = 0.5 * (lo + hi);
    let (blo, bhi) = bbox(f).unwrap_or_default();
    let scale = (bhi - blo).length().max(f64::MIN_POSITIVE);
    let eps = 1e-9 * scale;
    let height = |p: DVec2| eave_height(t * (m.dot(p) - lo).min(hi - m.dot(p)));
    // The outline with a corner wherever it crosses the ridge line.
    let mut ring: Vec<DVec2> = Vec::with_capacity(f.len() + 4);
    for i in 0..f.len() {
        let (a, b) = (f[i], f[(i + 1) % f.len()]);
        ring.push(a);
        let (sa, sb) = (m.dot(a) - mid, m.dot(b) - mid);
        if (sa > eps && sb < -eps) || (sa < -eps && sb > eps) {
            ring.push(a + (b - a) * (sa / (sa - sb)));
        }
    }
    let n = ring.len();
    let mut flat = ring.clone();
    let cap = ear_clip_all(&ring, eps);
    // Triangles cut along the ridge line; a cut point on an inner edge is
    // shared by the two triangles on that edge.
    let mut cuts: std::collections::HashMap<(usize, usize), usize> = std::collections::HashMap::new();
    let mut top_tris: Vec<[usize; 3]> = Vec::new();
    let opposite = |p: f64, q: f64| (p > eps && q < -eps) || (p < -eps && q > eps);
    for c in &cap {
        let side = c.map(|i| m.dot(flat[i]) - mid);
        // Corner `k` of the triangle, the next two, and their sides.
        let at = |k: usize| {
            let (b, c2) = ((k + 1) % 3, (k + 2) % 3);
            ([c[k], c[b], c[c2]], [side[k], side[b], side[c2]])
        };
        if let Some(k) = (0..3).find(|&k| opposite(side[k], side[(k + 1) % 3]) && opposite(side[k], side[(k + 2) % 3]))
        {
            // A corner alone on its side: both its edges are cut.
            let ([a, b, c2], [sa, sb, sc]) = at(k);
            let xb = cut_point(&mut flat, &mut cuts, a, b, sa, sb);
            let xc = cut_point(&mut flat, &mut cuts, c2, a, sc, sa);
            top_tris.extend([[a, xb, xc], [xb, b, c2], [xb, c2, xc]]);
        } else if let Some(k) = (0..3).find(|&k| side[k].abs() <= eps && opposite(side[(k + 1) % 3], side[(k + 2) % 3]))
        {
            // Crossed through a corner: the opposite edge is cut.
            let ([a, b, c2], [_, sb, sc]) = at(k);
            let x = cut_point(&mut flat, &mut cuts, b, c2, sb, sc);
            top_tris.extend([[a, b, x], [a, x, c2]]);
        } else {
            top_tris.push(*c);
        }
    }
    // Corners: the outline at the eaves (0..n), then the lifted ones.
    let mut pos: Vec<DVec3> = ring.iter().map(|p| DVec3::new(p.x, p.y, 0.0)).collect();
    let mut top: Vec<usize> = Vec::with_capacity(flat.len());
    for (k, p) in flat.iter().enumerate() {
        let z = height(*p);
        if k < n && z <= eps {
            top.push(k);
        } else {
            pos.push(DVec3::new(p.x, p.y, z));
            top.push(pos.len() - 1);
        }
    }
    lifted_solid(&pos, &ring, &top, &cap, &top_tris, (foot, apart, scale))
}

/// Where the segment `u`–`v` of `flat` crosses a line (`su`, `sv`: the
/// ends' signed distances from it): a new point the first time, the same
/// one for the triangle on the segment's other side.
fn cut_point(
    flat: &mut Vec<DVec2>,
    cuts: &mut std::collections::HashMap<(usize, usize), usize>,
    u: usize,
    v: usize,
    su: f64,
    sv: f64,
) -> usize {
    *cuts.entry((u.min(v), u.max(v))).or_insert_with(|| {
        flat.push(flat[u] + (flat[v] - flat[u]) * (su / (su - sv)));
        flat.len() - 1
    })
}

/// The pyramid roof over a concave counter-clockwise footprint that its
/// area centroid sees whole (a star-shaped one): one triangle from each
/// edge to the apex above the centroid, as high as slope `t` from the
/// nearest edge, as on a convex footprint.
fn star_pyramid(f: &[DVec2], t: f64) -> Result<Mesh, String> {
    let c = centroid(f);
    let n = f.len();
    let reach = (0..n)
        .map(|i| {
            let (a, b) = (f[i], f[(i + 1) % n]);
            let d = (b - a).normalize_or_zero();
            DVec2::new(-d.y, d.x).dot(c - a)
        })
        .fold(f64::INFINITY, f64::min);
    if reach.is_nan() || reach <= 0.0 {
        return Err("`roof_pyramid`: the centre of this concave footprint does not see every edge, so the \
             slopes would cross; use `roof_hip`, or split the footprint into parts"
            .to_string());
    }
    // The base by the ear clipping that keeps every corner, so that each
    // base edge meets its slope's (the general one may leave a T-junction).
    let mut pos: Vec<DVec3> = f.iter().map(|p| DVec3::new(p.x, p.y, 0.0)).collect();
    pos.push(DVec3::new(c.x, c.y, t * reach));
    let (lo, hi) = bbox(f).unwrap_or_default();
    let mut tris: Vec<[u32; 3]> =
        ear_clip_all(f, 1e-9 * (hi - lo).length()).iter().map(|c| [c[2], c[1], c[0]].map(|i| i as u32)).collect();
    tris.extend((0..n as u32).map(|i| [i, (i + 1) % n as u32, n as u32]));
    Ok(to_mesh("roof", &pos, tris))
}

/// The hip roof over a simple (possibly concave) counter-clockwise
/// footprint from its straight skeleton: each edge's face rises at slope
/// `t`, the footprint closes the solid from below.
fn skeleton_roof(f: &[DVec2], t: f64) -> Result<Mesh, String> {
    skeleton_roofs(f, t, None, false).map(|(roof, _)| roof)
}

/// The wing ends among the edges of the straight skeleton of the
/// counter-clockwise polygon `c` (`faces` of welded `pts`): an edge between
/// convex corners whose face is a triangle ending one ridge that runs into
/// the edge (and, with `ridge`, lies across that direction). Per edge:
/// the apex `m`, the ridge's other node `r`, and how far along `r → m`
/// the ridge meets the edge.
fn wing_ends(
    c: &[DVec2],
    faces: &[Vec<usize>],
    pts: &[DVec2],
    ridge: Option<DVec2>,
    eps: f64,
) -> Vec<Option<(usize, usize, f64)>> {
    let k = c.len();
    let convex = |i: usize| (c[i] - c[(i + k - 1) % k]).perp_dot(c[(i + 1) % k] - c[i]) > 0.0;
    let on = |id: usize| faces.iter().filter(|fc| fc.contains(&id)).count();
    (0..k)
        .map(|e| {
            let (prev, next) = ((e + k - 1) % k, (e + 1) % k);
            if k < 4 || !(convex(e) && convex(next)) || faces[e].len() != 3 {
                return None;
            }
            let m = faces[e][2];
            // The ridge: the other node the faces on both sides share.
            let &r = faces[prev].iter().find(|&&id| id != m && faces[next].contains(&id))?;
            if on(m) != 3 || pts[r].distance(pts[m]) <= 8.0 * eps {
                return None;
            }
            let (a, b) = (pts[faces[e][0]], pts[faces[e][1]]);
            let dr = pts[m] - pts[r];
            let along_edge = |v: DVec2| v.normalize_or_zero().dot((b - a).normalize_or_zero()).abs();
            if along_edge(dr) > 0.5 || ridge.is_some_and(|rd| along_edge(rd) > std::f64::consts::FRAC_1_SQRT_2) {
                return None;
            }
            let den = dr.perp_dot(b - a);
            if den.abs() <= 1e-12 * dr.length() * (b - a).length() {
                return None;
            }
            let s = (a - pts[r]).perp_dot(b - a) / den;
            let along = (pts[r] + dr * s - a).dot(b - a) / (b - a).length_squared();
            (s >= 1.0 && along > 1e-6 && along < 1.0 - 1e-6).then_some((m, r, s))
        })
        .collect()
}

/// Which edges of the counter-clockwise polygon `foot` a gable roof over
/// it ends in (its skeleton's [`wing_ends`]): where `ends =` applies.
fn gable_end_edges(foot: &[DVec2], ridge: Option<DVec2>) -> Result<Vec<bool>, String> {
    let sk = crate::skeleton::skeleton(foot, None)?;
    let (lo, hi) = bbox(foot).unwrap_or_default();
    let eps = 1e-9 * (hi - lo).length().max(f64::MIN_POSITIVE);
    let mut weld = Weld { pts: Vec::new(), eps: 8.0 * eps };
    let faces: Vec<Vec<usize>> = sk.faces.iter().map(|fc| fc.iter().map(|q| weld.id(*q)).collect()).collect();
    let ends = wing_ends(&sk.corners, &faces, &weld.pts, ridge, eps);
    let k = sk.corners.len();
    // The skeleton dropped corners on straight runs: a footprint edge is
    // an end when its midpoint lies on an end edge.
    Ok((0..foot.len())
        .map(|i| {
            let mid = (foot[i] + foot[(i + 1) % foot.len()]) * 0.5;
            (0..k).any(|e| {
                let (a, b) = (sk.corners[e], sk.corners[(e + 1) % k]);
                let s = (mid - a).dot(b - a) / (b - a).length_squared();
                ends[e].is_some()
                    && (0.0..=1.0).contains(&s)
                    && (mid - a).perp_dot((b - a).normalize()).abs() <= 8.0 * eps
            })
        })
        .collect())
}

/// The roof of [`skeleton_roof`]; with `gables` a gable roof instead: the
/// hip's triangle over each wing's end (an edge between convex corners
/// whose face is a triangle ending one ridge, the ridge running into the
/// edge; with `Some(direction)`, only edges across it) is stood upright in
/// the edge's plane, its apex moved out along the ridge to the edge — as
/// the weighted skeleton with that edge standing still would put it. Unless `apart`, the gable
/// walls are part of the roof and the second mesh is empty.
fn skeleton_roofs(f: &[DVec2], t: f64, gables: Option<Option<DVec2>>, apart: bool) -> Result<(Mesh, Mesh), String> {
    let sk = crate::skeleton::skeleton(f, None)?;
    let (lo, hi) = bbox(f).unwrap_or_default();
    let eps = 1e-9 * (hi - lo).length().max(f64::MIN_POSITIVE);
    let mut weld = Weld { pts: Vec::new(), eps: 8.0 * eps };
    let corners: Vec<usize> = sk.corners.iter().map(|q| weld.id(*q)).collect();
    let mut faces: Vec<Vec<usize>> = sk.faces.iter().map(|fc| fc.iter().map(|q| weld.id(*q)).collect()).collect();
    let mut pts = weld.pts.clone();
    // Height: the distance from a face's edge line, the same on every face
    // a point is on.
    let k = sk.corners.len();
    let mut h = vec![0.0f64; pts.len()];
    for (e, fc) in faces.iter().enumerate() {
        let (a, b) = (sk.corners[e], sk.corners[(e + 1) % k]);
        let dir = (b - a).normalize();
        for &id in fc {
            h[id] = eave_height(dir.perp_dot(pts[id] - a) * t);
        }
    }
    let mut upright = vec![false; k];
    if let Some(ridge) = gables {
        // Every apex first, from the hip as it is; then the moves.
        let ends = wing_ends(&sk.corners, &faces, &pts, ridge, eps);
        let mut moved = Vec::new();
        for (e, end) in ends.into_iter().enumerate() {
            if let Some((m, r, s)) = end {
                let id = pts.len() + moved.len();
                moved.push((pts[r] + (pts[m] - pts[r]) * s, h[r] + (h[m] - h[r]) * s));
                for fc in [(e + k - 1) % k, e, (e + 1) % k] {
                    for x in faces[fc].iter_mut().filter(|x| **x == m) {
                        *x = id;
                    }
                }
                // The old apex is nobody's now: keep it off every ring.
                upright[e] = true;
                pts[m] = DVec2::NAN;
            }
        }
        for (p, z) in moved {
            pts.push(p);
            h.push(z);
        }
    }
    let pos: Vec<DVec3> = pts.iter().zip(&h).map(|(p, z)| DVec3::new(p.x, p.y, *z)).collect();
    let mut tris: Vec<[u32; 3]> = Vec::new();
    let mut walls: Vec<[u32; 3]> = Vec::new();
    for (e, fc) in faces.iter().enumerate() {
        if upright[e] {
            let wall = [fc[0] as u32, fc[1] as u32, fc[2] as u32];
            if apart {
                walls.push(wall)
            } else {
                tris.push(wall)
            }
            continue;
        }
        let ring = full_ring(&pts, fc, 8.0 * eps);
        let flat: Vec<DVec2> = ring.iter().map(|&i| pts[i]).collect();
        tris.extend(ear_clip_all(&flat, eps).into_iter().map(|t| t.map(|i| ring[i] as u32)));
    }
    // The eaves: only points at height 0 can lie on the footprint's edges
    // (a gable's apex stands above one).
    let eaves: Vec<DVec2> = pts.iter().zip(&h).map(|(p, z)| if *z > 0.0 { DVec2::NAN } else { *p }).collect();
    let ring = full_ring(&eaves, &corners, 8.0 * eps);
    let flat: Vec<DVec2> = ring.iter().map(|&i| pts[i]).collect();
    tris.extend(ear_clip_all(&flat, eps).into_iter().map(|t| [t[2], t[1], t[0]].map(|i| ring[i] as u32)));
    if gables.is_none() {
        return Ok((to_mesh("roof", &pos, tris), Mesh { name: "gable".into(), ..Mesh::default() }));
    }
    Ok((compact_mesh("roof", &pos, &tris), compact_mesh("gable", &pos, &walls)))
}

/// The closed roof solid over a convex counter-clockwise footprint in the
/// xy plane (heights along +z from the eaves at z = 0): the points under
/// the lower envelope of the roof planes, after growing the footprint by
/// `overhang`. `angle` is the slope in degrees. Triangles wind
/// counter-clockwise seen from outside and share their corners exactly, so
/// the mesh is closed (every edge used once each way).
pub(crate) fn roof_mesh(foot: &[DVec2], kind: RoofKind, angle: f64, overhang: f64) -> Result<Mesh, String> {
    let opts = RoofOpts { overhang: vec![overhang; foot.len()], ridge: None, ends: None, gables: false };
    roof_meshes(foot, kind, angle, &opts).map(|(m, _)| m)
}

/// How a roof is laid on its footprint (edge `i` runs from corner `i` to
/// `i + 1`).
#[derive(Clone, Debug, Default)]
pub(crate) struct RoofOpts {
    /// The overhang of each edge (≥ 0).
    pub overhang: Vec<f64>,
    /// The edge a gable's ridge runs along, or a shed's slope rises from
    /// (its eaves); `None`: along the longer side, or up +y.
    pub ridge: Option<usize>,
    /// The overhang of the gable ends (gable and shed: the edges more across
    /// the ridge than along it), in place of `overhang` there.
    pub ends: Option<f64>,
    /// Whether the gable walls that lie in the footprint's edges (where
    /// those have no overhang) form a mesh of their own.
    pub gables: bool,
}

/// A footprint grown by `d[i]` outwards along each edge `i` (mitred
/// corners; a step between parallel neighbours of different overhangs).
fn offset_edges(p: &[DVec2], d: &[f64]) -> Vec<DVec2> {
    let n = p.len();
    let line = |i: usize| {
        let (a, b) = (p[i], p[(i + 1) % n]);
        let dir = (b - a).normalize_or_zero();
        (a + DVec2::new(dir.y, -dir.x) * d[i], dir)
    };
    let mut q: Vec<DVec2> = Vec::with_capacity(n + 2);
    for (i, &corner) in p.iter().enumerate() {
        let (p0, d0) = line((i + n - 1) % n);
        let (p1, d1) = line(i);
        let cr = d0.perp_dot(d1);
        if cr.abs() <= 1e-12 {
            q.push(p0 + d0 * (corner - p0).dot(d0));
            q.push(p1);
        } else {
            q.push(p0 + d0 * ((p1 - p0).perp_dot(d1) / cr));
        }
    }
    let (lo, hi) = bbox(&q).unwrap_or_default();
    let eps = 1e-12 * (hi - lo).length();
    q.dedup_by(|a, b| a.distance(*b) <= eps);
    while q.len() > 1 && q[0].distance(q[q.len() - 1]) <= eps {
        q.pop();
    }
    q
}

/// The mesh of the triangles `tris` of `pos`, without the unused points.
fn compact_mesh(name: &str, pos: &[DVec3], tris: &[[u32; 3]]) -> Mesh {
    let mut map = vec![u32::MAX; pos.len()];
    let mut used = Vec::new();
    let tris = tris
        .iter()
        .map(|t| {
            t.map(|i| {
                if map[i as usize] == u32::MAX {
                    map[i as usize] = used.len() as u32;
                    used.push(pos[i as usize]);
                }
                map[i as usize]
            })
        })
        .collect();
    to_mesh(name, &used, tris)
}

/// The roof of [`roof_mesh`] laid as `opts` says, and the gable walls
/// apart when `opts.gables` (else an empty mesh).
pub(crate) fn roof_meshes(foot: &[DVec2], kind: RoofKind, angle: f64, opts: &RoofOpts) -> Result<(Mesh, Mesh), String> {
    let name = kind.name();
    let no_walls = || Mesh { name: "gable".into(), ..Mesh::default() };
    if opts.overhang.len() != foot.len() {
        return Err(format!("`{name}`: {} overhangs for {} edges", opts.overhang.len(), foot.len()));
    }
    if let Some(&o) = opts.overhang.iter().chain(&opts.ends).find(|o| !(**o >= 0.0 && o.is_finite())) {
        return Err(format!("`{name}`: the overhang must be a finite number ≥ 0, found {o}"));
    }
    // The ridge's direction and the gable ends.
    let n = foot.len();
    let dir_of = |i: usize| (foot[(i + 1) % n] - foot[i]).normalize_or_zero();
    let dir = opts.ridge.filter(|&i| i < n).map(|i| match kind {
        RoofKind::Shed => dir_of(i).perp(),
        _ => dir_of(i),
    });
    let mut overhangs = opts.overhang.clone();
    if let Some(e) = opts.ends.filter(|_| matches!(kind, RoofKind::Gable | RoofKind::Shed | RoofKind::Ridge)) {
        let r = match (kind, dir) {
            (RoofKind::Shed, Some(u)) => u.perp(),
            (_, Some(r)) => r,
            (RoofKind::Shed, None) => DVec2::X,
            _ => {
                let (lo, hi) = bbox(foot).unwrap_or_default();
                if hi.x - lo.x >= hi.y - lo.y { DVec2::X } else { DVec2::Y }
            }
        };
        // On a concave footprint the ends are its wings' ends.
        let wings = if kind == RoofKind::Gable && foot.len() >= 4 && !is_convex(foot) && area2(foot) > 0.0 {
            Some(gable_end_edges(foot, dir)?)
        } else {
            None
        };
        for (i, o) in overhangs.iter_mut().enumerate() {
            let d = dir_of(i);
            let end = match &wings {
                Some(w) => w[i],
                None => d.dot(r).abs() < d.perp_dot(r).abs(),
            };
            if end {
                *o = e;
            }
        }
    }
    let uniform = overhangs.iter().all(|o| *o == overhangs[0]);
    let overhang = if uniform { overhangs.first().copied().unwrap_or(0.0) } else { 0.0 };
    if !(angle > 0.0 && angle < 90.0) {
        return Err(format!("`{name}`: the slope angle must lie strictly between 0 and 90 degrees, found {angle}"));
    }
    if foot.len() < 3 || area2(foot) <= 0.0 {
        return Ok((Mesh { name: "roof".into(), ..Mesh::default() }, no_walls()));
    }
    // Mitred corners, or where those would cross (an overhang wider than
    // a notch), the outside wavefront that closes the notch.
    let grow = |p: &[DVec2]| -> Result<Vec<DVec2>, String> {
        let f = if uniform { offset_miter(p, overhang) } else { offset_edges(p, &overhangs) };
        if f.len() >= 3 && is_simple(&f) && area2(&f) > 0.0 {
            return Ok(f);
        }
        crate::skeleton::grow(p, &overhangs)?.filter(|f| f.len() >= 3 && is_simple(f)).ok_or_else(|| {
            format!("`{name}`: the overhangs of this footprint could not be laid out (nearly touching edges?)")
        })
    };
    if foot.len() > MAX_ROOF_CORNERS {
        return Err(format!(
            "`{name}`: a roof footprint has at most {MAX_ROOF_CORNERS} corners, found {} (building the roof is cubic in them)",
            foot.len()
        ));
    }
    if !is_convex(foot) {
        let f = grow(foot)?;
        let t = angle.to_radians().tan();
        return match kind {
            RoofKind::Hip => Ok((skeleton_roof(&f, t)?, no_walls())),
            RoofKind::Gable => skeleton_roofs(&f, t, Some(dir), opts.gables),
            RoofKind::Shed => Ok(shed_roof(&f, foot, t, dir.unwrap_or(DVec2::Y), opts.gables)),
            RoofKind::Pyramid => star_pyramid(&f, t).map(|m| (m, no_walls())),
            RoofKind::Ridge => {
                let r = dir.unwrap_or_else(|| {
                    let (lo, hi) = bbox(&f).unwrap_or_default();
                    if hi.x - lo.x >= hi.y - lo.y { DVec2::X } else { DVec2::Y }
                });
                Ok(ridge_roof(&f, foot, t, r, opts.gables))
            }
        };
    }
    let f = grow(foot)?;
    let planes = roof_planes(&f, kind, angle.to_radians().tan(), dir);
    let (lo, hi) = bbox(&f).unwrap_or_default();
    let scale = (hi - lo).length().max(f64::MIN_POSITIVE);
    let eps = 1e-9 * scale;
    let env = |p: DVec2| eave_height(planes.iter().map(|pl| pl.at(p)).fold(f64::INFINITY, f64::min));
    let mut weld = Weld { pts: Vec::new(), eps };
    for q in &f {
        weld.id(*q);
    }
    if opts.gables {
        // The footprint's corners on the outline split its edges where the
        // overhang changes, so that the gable walls end at the façade.
        for q in foot {
            weld.id(*q);
        }
    }
    // Top regions: where each plane is the lowest.
    let mut regions: Vec<(usize, Vec<usize>)> = Vec::new();
    for (i, pi) in planes.iter().enumerate() {
        let mut r = f.clone();
        for (j, pj) in planes.iter().enumerate() {
            if i == j || r.is_empty() {
                continue;
            }
            let g = pi.g - pj.g;
            if g.length() <= 1e-12 * (pi.g.length() + pj.g.length()) {
                // Parallel planes: the lower one wins, ties to the first.
                if pi.c > pj.c || (pi.c == pj.c && j < i) {
                    r.clear();
                }
                continue;
            }
            r = clip(&r, g, pj.c - pi.c);
        }
        if r.len() >= 3 && area2(&r) > eps * scale {
            let ids = r.iter().map(|q| weld.id(*q)).collect();
            regions.push((i, ids));
        }
    }
    let pts = weld.pts.clone();
    // Vertices: bottom (z = 0) per welded point, top where the roof is
    // above the eaves (else the bottom one).
    let mut pos: Vec<DVec3> = pts.iter().map(|p| DVec3::new(p.x, p.y, 0.0)).collect();
    let mut top: Vec<usize> = (0..pts.len()).collect();
    for (k, p) in pts.iter().enumerate() {
        let h = env(*p);
        if h > eps {
            top[k] = pos.len();
            pos.push(DVec3::new(p.x, p.y, h));
        }
    }
    let mut tris: Vec<[u32; 3]> = Vec::new();
    let fan = |pos: &mut Vec<DVec3>, ring: &[usize], centre: DVec3, flip: bool, tris: &mut Vec<[u32; 3]>| {
        let c = pos.len() as u32;
        pos.push(centre);
        for k in 0..ring.len() {
            let (a, b) = (ring[k] as u32, ring[(k + 1) % ring.len()] as u32);
            tris.push(if flip { [c, b, a] } else { [c, a, b] });
        }
    };
    // The bottom ring: footprint corners with every point on its edges.
    let corners: Vec<usize> = f.iter().map(|q| weld.id(*q)).collect();
    let ring = full_ring(&pts, &corners, eps);
    let cf = centroid(&f);
    fan(&mut pos, &ring, DVec3::new(cf.x, cf.y, 0.0), true, &mut tris);
    // Walls: between the bottom ring and the roof along each edge; with
    // `gables` those in the footprint's edges go to `walls`.
    let in_foot = |m: DVec2| on_outline(foot, m, 1e-7 * scale);
    let mut walls: Vec<[u32; 3]> = Vec::new();
    for k in 0..ring.len() {
        let (a, b) = (ring[k], ring[(k + 1) % ring.len()]);
        let (ta, tb) = (top[a], top[b]);
        let out = if opts.gables && in_foot((pts[a] + pts[b]) * 0.5) { &mut walls } else { &mut tris };
        if tb != b {
            out.push([a as u32, b as u32, tb as u32]);
        }
        if ta != a {
            out.push([a as u32, tb as u32, ta as u32]);
        }
    }
    // Roof faces, each with every point on its edges.
    for (i, ids) in &regions {
        let r = full_ring(&pts, ids, eps);
        if r.len() < 3 {
            continue;
        }
        let c2 = centroid(&r.iter().map(|&k| pts[k]).collect::<Vec<_>>());
        let ring: Vec<usize> = r.iter().map(|&k| top[k]).collect();
        fan(&mut pos, &ring, DVec3::new(c2.x, c2.y, eave_height(planes[*i].at(c2))), false, &mut tris);
    }
    if walls.is_empty() {
        return Ok((to_mesh("roof", &pos, tris), no_walls()));
    }
    Ok((compact_mesh("roof", &pos, &tris), compact_mesh("gable", &pos, &walls)))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A closed roof mesh of ridge height `height` and volume `vol`.
    fn assert_roof(m: &Mesh, height: f32, vol: f64) {
        assert!(is_closed(m));
        assert!((max_z(m) - height).abs() < 1e-5, "height {}", max_z(m));
        assert!((volume(m) - vol).abs() < 1e-3, "volume {}", volume(m));
    }
    /// An L of three unit squares (area 3, concave at (1, 1)).
    fn l_shape() -> Vec<DVec2> {
        vec![
            DVec2::new(0.0, 0.0),
            DVec2::new(2.0, 0.0),
            DVec2::new(2.0, 1.0),
            DVec2::new(1.0, 1.0),
            DVec2::new(1.0, 2.0),
            DVec2::new(0.0, 2.0),
        ]
    }

    fn rect(w: f64, d: f64) -> Vec<DVec2> {
        vec![
            DVec2::new(-w / 2.0, -d / 2.0),
            DVec2::new(w / 2.0, -d / 2.0),
            DVec2::new(w / 2.0, d / 2.0),
            DVec2::new(-w / 2.0, d / 2.0),
        ]
    }

    /// Every directed edge is used once and its reverse once: closed and
    /// consistently oriented.
    pub(crate) fn is_closed(m: &Mesh) -> bool {
        let mut edges = std::collections::HashMap::<(u32, u32), i32>::new();
        for t in &m.triangles {
            for k in 0..3 {
                *edges.entry((t[k], t[(k + 1) % 3])).or_default() += 1;
            }
        }
        edges.iter().all(|(&(a, b), &n)| n == 1 && edges.get(&(b, a)) == Some(&1))
    }

    /// Signed volume by the divergence theorem (positive when outward).
    pub(crate) fn volume(m: &Mesh) -> f64 {
        m.triangles
            .iter()
            .map(|t| {
                let [a, b, c] = t.map(|i| m.positions[i as usize].as_dvec3());
                a.dot(b.cross(c)) / 6.0
            })
            .sum()
    }

    fn max_z(m: &Mesh) -> f32 {
        m.positions.iter().map(|p| p.z).fold(0.0, f32::max)
    }

    #[test]
    fn pyramids_are_closed_with_a_third_of_the_prism() {
        for (foot, area) in [(rect(4.0, 2.0), 8.0), (l_shape(), 3.0)] {
            let m = pyramid_mesh(&foot, 3.0);
            assert!(is_closed(&m), "{foot:?}");
            assert!((volume(&m) - area * 3.0 / 3.0).abs() < 1e-9, "{}", volume(&m));
            assert_eq!(max_z(&m), 3.0);
            assert_eq!(m.triangles.len(), (foot.len() - 2) + foot.len());
        }
        assert!(pyramid_mesh(&rect(4.0, 2.0), 0.0).triangles.is_empty());
    }

    #[test]
    fn polygon_measures() {
        let r = rect(4.0, 2.0);
        assert_eq!(area2(&r), 16.0);
        assert_eq!(centroid(&r), DVec2::ZERO);
        assert!(is_simple(&r) && is_convex(&r));
        let bow = vec![DVec2::new(0.0, 0.0), DVec2::new(1.0, 1.0), DVec2::new(1.0, 0.0), DVec2::new(0.0, 1.0)];
        assert!(!is_simple(&bow));
        let l = l_shape();
        assert!(is_simple(&l) && !is_convex(&l));
        assert_eq!(area2(&l), 6.0);
    }

    #[test]
    fn slab_clips_keep_area() {
        let l = l_shape();
        let parts: f64 =
            [(0.0, 0.5), (0.5, 1.5), (1.5, 2.0)].iter().map(|&(a, b)| area2(&clip_slab(&l, 0, a, b))).sum();
        assert!((parts - 6.0).abs() < 1e-12, "{parts}");
        assert!(clip_slab(&l, 1, 3.0, 4.0).is_empty());
    }

    #[test]
    fn offset_grows_rectangles_exactly() {
        let o = offset_miter(&rect(4.0, 2.0), 0.5);
        assert!((area2(&o) / 2.0 - 5.0 * 3.0).abs() < 1e-12);
    }

    #[test]
    fn prism_is_closed_with_unit_volume_share() {
        let m =
            prism_mesh(&[DVec2::new(-0.5, 0.5), DVec2::new(0.5, 0.5), DVec2::new(0.5, -0.5), DVec2::new(-0.5, -0.5)]);
        assert!(is_closed(&m));
        assert!((volume(&m) - 1.0).abs() < 1e-6, "{}", volume(&m));
        assert_eq!(m.triangles.len(), 12);
    }

    #[test]
    fn gable_on_a_rectangle() {
        // 10 × 6, 45°: ridge along x at height 3, volume = 10 · 6 · 3 / 2.
        let m = roof_mesh(&rect(10.0, 6.0), RoofKind::Gable, 45.0, 0.0).unwrap();
        assert_roof(&m, 3.0, 90.0);
        // With an overhang of 1 the footprint is 12 × 8: ridge 4.
        let m = roof_mesh(&rect(10.0, 6.0), RoofKind::Gable, 45.0, 1.0).unwrap();
        assert_roof(&m, 4.0, 12.0 * 8.0 * 4.0 / 2.0);
    }

    #[test]
    fn hip_on_a_rectangle() {
        // 10 × 6, 45°: height 3; volume = prism of the ridge part minus the
        // two hip pyramids' complements: W²/4·tan·(L − W/3) = 9·(10 − 2) = 72.
        let m = roof_mesh(&rect(10.0, 6.0), RoofKind::Hip, 45.0, 0.0).unwrap();
        assert_roof(&m, 3.0, 72.0);
    }

    #[test]
    fn pyramid_and_shed_on_a_square() {
        let m = roof_mesh(&rect(6.0, 6.0), RoofKind::Pyramid, 45.0, 0.0).unwrap();
        assert_roof(&m, 3.0, 36.0 * 3.0 / 3.0);
        let m = roof_mesh(&rect(6.0, 4.0), RoofKind::Shed, 45.0, 0.0).unwrap();
        assert_roof(&m, 4.0, 6.0 * 4.0 * 4.0 / 2.0);
    }

    #[test]
    fn hip_on_a_convex_pentagon_is_closed() {
        let p: Vec<DVec2> =
            (0..5).map(|k| DVec2::from_angle(k as f64 * std::f64::consts::TAU / 5.0 + 0.3) * 4.0).collect();
        for kind in [RoofKind::Hip, RoofKind::Pyramid, RoofKind::Gable, RoofKind::Shed] {
            let m = roof_mesh(&p, kind, 30.0, 0.25).unwrap();
            assert!(is_closed(&m), "{kind:?}");
            assert!(volume(&m) > 0.0, "{kind:?}");
        }
        // A regular polygon's hip roof is its pyramid.
        let hip = roof_mesh(&p, RoofKind::Hip, 30.0, 0.0).unwrap();
        let pyr = roof_mesh(&p, RoofKind::Pyramid, 30.0, 0.0).unwrap();
        assert!((volume(&hip) - volume(&pyr)).abs() < 1e-6);
    }

    #[test]
    fn skeleton_hip_roofs_on_concave_footprints() {
        // Through the skeleton, a rectangle gives the textbook hip volume
        // t·d²(3w − d)/12 and ridge height t·d/2.
        let r = skeleton_roof(&rect(10.0, 4.0), 1.0).unwrap();
        assert_roof(&r, 2.0, 16.0 * 26.0 / 12.0);
        use crate::skeleton::fixtures;
        let shapes = [
            (l_shape(), 0.5),
            (fixtures::l_arms_4(), 2.0),
            (fixtures::u_legs_3(), 2.0),
            (fixtures::notched(), f64::NAN),
        ];
        for (foot, ridge) in shapes {
            let t = 30f64.to_radians().tan();
            let m = roof_mesh(&foot, RoofKind::Hip, 30.0, 0.0).unwrap();
            assert!(is_closed(&m), "{foot:?}");
            // The volume is each face's area times its height at the
            // face's centroid (the faces are planar).
            let sk = crate::skeleton::skeleton(&foot, None).unwrap();
            let k = sk.corners.len();
            let expect: f64 = sk
                .faces
                .iter()
                .enumerate()
                .map(|(e, f)| {
                    let (a, b) = (sk.corners[e], sk.corners[(e + 1) % k]);
                    area2(f) / 2.0 * t * (b - a).normalize().perp_dot(centroid(f) - a)
                })
                .sum();
            assert!((volume(&m) - expect).abs() < 1e-6 * expect, "{} vs {expect}", volume(&m));
            if ridge.is_finite() {
                assert!((max_z(&m) as f64 - ridge * t).abs() < 1e-5);
            }
            // With an overhang the roof covers more and rises higher.
            let o = roof_mesh(&foot, RoofKind::Hip, 30.0, 0.2).unwrap();
            assert!(is_closed(&o) && volume(&o) > volume(&m));
        }
    }

    #[test]
    fn shed_roofs_on_concave_footprints_are_one_plane_over_the_footprint() {
        // The L of three unit squares, rising along +y at 45°: the volume
        // is the footprint's integral of y (squares at y 0.5, 0.5, 1.5).
        let m = roof_mesh(&l_shape(), RoofKind::Shed, 45.0, 0.0).unwrap();
        assert_roof(&m, 2.0, 2.5);
        // Along the edge `ridge` names, with the walls in the footprint's
        // edges apart: every triangle lies in one of the two meshes.
        let opts = RoofOpts { overhang: vec![0.0; 6], ridge: Some(1), ends: None, gables: true };
        let (roof, walls) = roof_meshes(&l_shape(), RoofKind::Shed, 45.0, &opts).unwrap();
        assert!(!walls.triangles.is_empty());
        let mut both = roof.clone();
        let base = both.positions.len() as u32;
        both.positions.extend(&walls.positions);
        both.triangles.extend(walls.triangles.iter().map(|t| t.map(|i| i + base)));
        // Rising away from edge 1 (x = 2, facing +x), towards −x: height
        // 2 − x, integrated over the squares centred at x 0.5, 1.5, 0.5.
        assert!((volume(&both) - 3.5).abs() < 1e-9, "{}", volume(&both));
        assert!((max_z(&both) - 2.0).abs() < 1e-6);
    }

    #[test]
    fn pyramid_roofs_stand_on_concave_footprints_their_centre_sees() {
        // A plus sign (centre sees every edge): twelve slopes to one apex,
        // as high as 45° from the nearest edge (0.5 away).
        let plus: Vec<DVec2> = [
            (1.0, 0.0),
            (2.0, 0.0),
            (2.0, 1.0),
            (3.0, 1.0),
            (3.0, 2.0),
            (2.0, 2.0),
            (2.0, 3.0),
            (1.0, 3.0),
            (1.0, 2.0),
            (0.0, 2.0),
            (0.0, 1.0),
            (1.0, 1.0),
        ]
        .iter()
        .map(|&(x, y)| DVec2::new(x, y))
        .collect();
        let m = roof_mesh(&plus, RoofKind::Pyramid, 45.0, 0.0).unwrap();
        assert!(is_closed(&m), "{m:?}");
        assert!((max_z(&m) - 0.5).abs() < 1e-6, "{}", max_z(&m));
        // A cone over the plus: area 5 · height / 3.
        assert!((volume(&m) - 5.0 * 0.5 / 3.0).abs() < 1e-6, "{}", volume(&m));
        // The L of three squares: its centroid sees every edge. A longer
        // L's does not: a clear error.
        assert!(is_closed(&roof_mesh(&l_shape(), RoofKind::Pyramid, 45.0, 0.0).unwrap()));
        let long: Vec<DVec2> = [(0.0, 0.0), (4.0, 0.0), (4.0, 1.0), (1.0, 1.0), (1.0, 4.0), (0.0, 4.0)]
            .iter()
            .map(|&(x, y)| DVec2::new(x, y))
            .collect();
        let e = roof_mesh(&long, RoofKind::Pyramid, 45.0, 0.0).unwrap_err();
        assert!(e.contains("does not see every edge"), "{e}");
    }

    #[test]
    fn gable_roofs_on_concave_footprints_stand_their_wing_ends_upright() {
        // Over each wing end of width w, a gable adds to the hip the
        // prism's half-end (w²t/4 · w/2) less the hip's pyramid (w³t/12):
        // w³t/24. The L's two ends are 4 wide, the U's two 3 wide.
        use crate::skeleton::fixtures;
        let t = 30f64.to_radians().tan();
        for (foot, w, ridge) in [(fixtures::l_arms_4(), 4.0f64, 2.0), (fixtures::u_legs_3(), 3.0, 2.0)] {
            let hip = roof_mesh(&foot, RoofKind::Hip, 30.0, 0.0).unwrap();
            let gable = roof_mesh(&foot, RoofKind::Gable, 30.0, 0.0).unwrap();
            assert!(is_closed(&gable), "{foot:?}");
            let more = volume(&gable) - volume(&hip);
            assert!((more - 2.0 * w.powi(3) * t / 24.0).abs() < 1e-5, "{more}");
            assert!((max_z(&gable) as f64 - ridge * t).abs() < 1e-5);
            // Apart, the two gables are upright triangles in the wing
            // ends' planes, up to the ridge.
            let opts = RoofOpts { overhang: vec![0.0; foot.len()], gables: true, ..RoofOpts::default() };
            let (roof, walls) = roof_meshes(&foot, RoofKind::Gable, 30.0, &opts).unwrap();
            assert_eq!(walls.triangles.len(), 2);
            for tri in &walls.triangles {
                let [a, b, c] = tri.map(|i| walls.positions[i as usize].as_dvec3());
                assert!((b - a).cross(c - a).normalize().z.abs() < 1e-6, "upright");
                assert!((c.z - w / 2.0 * t).abs() < 1e-5, "apex at the ridge: {c}");
            }
            assert_eq!(roof.triangles.len() + 2, gable.triangles.len());
        }
        // With eaves overhanging 0.5 and `ends = 0`, the L's gables stand
        // flush in its wing ends (x = 10, y = 10), not out at the eaves.
        let foot = fixtures::l_arms_4();
        let opts = RoofOpts { overhang: vec![0.5; 6], ends: Some(0.0), gables: true, ..RoofOpts::default() };
        let (_, walls) = roof_meshes(&foot, RoofKind::Gable, 30.0, &opts).unwrap();
        assert_eq!(walls.triangles.len(), 2);
        for tri in &walls.triangles {
            let ps = tri.map(|i| walls.positions[i as usize]);
            assert!(
                ps.iter().all(|p| (p.x - 10.0).abs() < 1e-4) || ps.iter().all(|p| (p.y - 10.0).abs() < 1e-4),
                "{ps:?}"
            );
        }
    }

    proptest::proptest! {
        /// Hip roofs on random star-shaped (mostly concave) footprints are
        /// closed solids no higher than the footprint's inradius allows.
        #[test]
        fn star_hip_roofs_are_closed(radii in proptest::collection::vec(1.0f64..10.0, 3..20)) {
            let k = radii.len();
            let foot: Vec<DVec2> = radii
                .iter()
                .enumerate()
                .map(|(i, r)| DVec2::from_angle(std::f64::consts::TAU * i as f64 / k as f64) * *r)
                .collect();
            let m = roof_mesh(&foot, RoofKind::Hip, 45.0, 0.0).unwrap();
            proptest::prop_assert!(is_closed(&m));
            proptest::prop_assert!(volume(&m) > 0.0);
            proptest::prop_assert!(max_z(&m) <= 10.0);
            // Shed and ridge roofs stand on any footprint: closed, and
            // no higher than their planes (the outline's extent).
            for kind in [RoofKind::Shed, RoofKind::Ridge] {
                let m = roof_mesh(&foot, kind, 45.0, 0.0).unwrap();
                proptest::prop_assert!(is_closed(&m), "{:?}", kind);
                proptest::prop_assert!(volume(&m) > 0.0);
                proptest::prop_assert!(max_z(&m) <= 20.0);
            }
        }
    }

    #[test]
    fn ridge_roofs_lay_one_ridge_over_any_footprint() {
        // The L of three unit squares, ridge along x at y = 1, 45°: height
        // min(y, 2 − y), integrated: 0.5 + 0.5 over the bottom squares,
        // 0.5 over the top one.
        let m = roof_mesh(&l_shape(), RoofKind::Ridge, 45.0, 0.0).unwrap();
        assert_roof(&m, 1.0, 1.5);
        // On a rectangle it is the gable roof.
        let (r, g) = (rect(4.0, 2.0), RoofKind::Gable);
        let (a, b) = (roof_mesh(&r, RoofKind::Ridge, 30.0, 0.0).unwrap(), roof_mesh(&r, g, 30.0, 0.0).unwrap());
        assert!((volume(&a) - volume(&b)).abs() < 1e-9 && (max_z(&a) - max_z(&b)).abs() < 1e-6);
        // Across the L (ridge = edge 1, along y at x = 1): the same by symmetry.
        let opts = RoofOpts { overhang: vec![0.0; 6], ridge: Some(1), ends: None, gables: false };
        let (m, _) = roof_meshes(&l_shape(), RoofKind::Ridge, 45.0, &opts).unwrap();
        assert_roof(&m, 1.0, 1.5);
    }

    #[test]
    fn hostile_roofs_are_errors_or_empty() {
        // An overhang that folds the notch of an L over itself.
        let notch = vec![
            DVec2::new(0.0, 0.0),
            DVec2::new(5.0, 0.0),
            DVec2::new(5.0, 4.0),
            DVec2::new(3.0, 4.0),
            DVec2::new(3.0, 0.5),
            DVec2::new(2.0, 0.5),
            DVec2::new(2.0, 4.0),
            DVec2::new(0.0, 4.0),
        ];
        assert!(roof_mesh(&notch, RoofKind::Hip, 30.0, 0.0).is_ok());
        // An overhang wider than the notch closes it: the mitred outline
        // would cross itself, the outside wavefront fills the notch, and
        // the roof is the hip over the grown 7 × 6 rectangle.
        let closed = roof_mesh(&notch, RoofKind::Hip, 30.0, 1.0).unwrap();
        assert!(is_closed(&closed));
        let (lo, hi) = closed.bounds().unwrap();
        assert_eq!((lo.x, lo.y, hi.x, hi.y), (-1.0, -1.0, 6.0, 5.0));
        assert!(
            (volume(&closed) - volume(&roof_mesh(&rect(7.0, 6.0), RoofKind::Hip, 30.0, 0.0).unwrap())).abs() < 1e-4
        );
        assert!(roof_mesh(&rect(1.0, 1.0), RoofKind::Hip, 90.0, 0.0).is_err());
        assert!(roof_mesh(&rect(1.0, 1.0), RoofKind::Hip, f64::NAN, 0.0).is_err());
        assert!(roof_mesh(&rect(1.0, 1.0), RoofKind::Hip, 30.0, -1.0).is_err());
        assert!(roof_mesh(&[], RoofKind::Hip, 30.0, 0.0).unwrap().triangles.is_empty());
        let many: Vec<DVec2> = (0..300).map(|k| DVec2::from_angle(k as f64 * std::f64::consts::TAU / 300.0)).collect();
        assert!(roof_mesh(&many, RoofKind::Hip, 30.0, 0.0).unwrap_err().contains("at most 256 corners"));
    }
}
