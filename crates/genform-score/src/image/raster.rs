//! The fast silhouette rasterizer.
//!
//! A closed surface (the built-in primitives' unit meshes, closed mesh
//! assets) whose vertices need no clipping is filled from its outline edges
//! (see [`super::outline`]). Open meshes and anything crossing the near, far
//! or guard planes are filled triangle by triangle after clipping. Spans go
//! into a bit mask one word (64 pixels) at a time. (The convex hull of a
//! convex primitive's snapped vertices is not used: snapping can make the
//! projected outline non-convex, so the hull may cover a pixel that no
//! triangle does.)
//!
//! Coverage rule: a pixel is covered when its center lies inside, and a
//! center exactly on an edge counts as the point nudged by `(ε, ε²)` (right,
//! then down). That is the usual top-left rule; it makes adjacent triangles
//! share no pixel and leave no gap, so a convex polygon and the union of the
//! triangles it is made of cover the same pixels. All tests after snapping
//! (see [`super::project`]) are exact integer arithmetic.

use super::coverage::Mask;
use super::outline::{EdgeTable, OutlineBuffers, fill_outline};
use super::project::{Frame, HALF, ONE, Projector, Pt, SUB, Shapes};
use crate::span_cache::{CachePool, CacheSlot, Lookup, MeshKeys, Span};
use genform_core::scene::triangulate_polygon;
use genform_core::scene::{Instance, Mesh, Primitive, Scene, Tessellation};
use std::sync::Arc;

/// Per-thread buffers of an image scorer: the mask, the tessellated unit
/// primitives and projection buffers. Made by
/// [`super::ImageScorer::scratch`]; after the first evaluations nothing is
/// allocated.
pub struct ImageScratch {
    pub(crate) mask: Mask,
    shapes: Shapes,
    projector: Projector,
    rows: Rows,
    closed: ClosedMeshes,
    outline: OutlineBuffers,
    /// Mesh instances' spans kept across evaluations (scorers' scratches),
    /// the spans of the instance being recorded, and per mesh of the Scene
    /// its cache key once looked up.
    cache: CacheSlot<Frame>,
    spans: Vec<Span>,
    mesh_keys: MeshKeys,
}

impl ImageScratch {
    pub(crate) fn new(width: usize, height: usize, tess: Tessellation) -> ImageScratch {
        ImageScratch {
            mask: Mask::new(width, height),
            shapes: Shapes::new(tess),
            projector: Projector::default(),
            rows: Rows::default(),
            closed: ClosedMeshes::default(),
            outline: OutlineBuffers::default(),
            cache: CacheSlot::default(),
            spans: Vec::new(),
            mesh_keys: Vec::new(),
        }
    }

    /// A scratch whose mesh instances are cached in a cache of `pool`.
    pub(crate) fn with_cache(width: usize, height: usize, tess: Tessellation, pool: &CachePool<Frame>) -> ImageScratch {
        ImageScratch { cache: pool.take(), ..ImageScratch::new(width, height, tess) }
    }

    /// Mesh instances replayed from this scratch's cache so far.
    #[cfg(test)]
    pub(crate) fn cache_hits(&self) -> u64 {
        self.cache.cache.as_ref().map_or(0, |c| c.hits)
    }

    /// Makes the buffers fit a scorer (a scratch made for another one is
    /// rebuilt rather than misused).
    pub(crate) fn fit(&mut self, width: usize, height: usize, tess: Tessellation) {
        if self.mask.size() != (width, height) || self.shapes.tessellation() != tess {
            *self = ImageScratch::new(width, height, tess);
        }
    }
}

/// The edge tables of the mesh assets that are closed surfaces (see
/// [`is_closed`]; `None` for the others), for the last few assets seen.
/// Holding the `Arc` keeps its address from being reused by another mesh
/// while cached.
#[derive(Default)]
struct ClosedMeshes {
    seen: Vec<(Arc<Mesh>, Option<EdgeTable>)>,
}

impl ClosedMeshes {
    /// Assets remembered (scenes use a handful).
    const CAPACITY: usize = 16;

    fn get(&mut self, mesh: &Arc<Mesh>) -> Option<&EdgeTable> {
        let i = match self.seen.iter().position(|(m, _)| Arc::ptr_eq(m, mesh)) {
            Some(i) => i,
            None => {
                let table = is_closed(mesh).then(|| EdgeTable::new(mesh));
                if self.seen.len() == Self::CAPACITY {
                    self.seen.remove(0);
                }
                self.seen.push((mesh.clone(), table));
                self.seen.len() - 1
            }
        };
        self.seen[i].1.as_ref()
    }
}

/// Whether `mesh`'s triangles form a closed surface: every vertex index in
/// range, no triangle repeating an index, and each edge `a → b` used as
/// often as `b → a`.
pub(crate) fn is_closed(mesh: &Mesh) -> bool {
    let n = mesh.positions.len();
    let mut edges = Vec::with_capacity(3 * mesh.triangles.len());
    for t in &mesh.triangles {
        if t.iter().any(|&i| i as usize >= n) || t[0] == t[1] || t[1] == t[2] || t[0] == t[2] {
            return false;
        }
        for e in 0..3 {
            let (a, b) = (t[e], t[(e + 1) % 3]);
            edges.push(if a < b { (a, b, 1i64) } else { (b, a, -1) });
        }
    }
    edges.sort_unstable();
    edges.chunk_by(|x, y| (x.0, x.1) == (y.0, y.1)).all(|g| g.iter().map(|e| e.2).sum::<i64>() == 0)
}

/// Rasterizes every instance and polygon of `scene` into `s.mask`.
pub(crate) fn rasterize(frame: &Frame, scene: &Scene, s: &mut ImageScratch) {
    let mut cache = s.cache.cache.take();
    if let Some(c) = cache.as_mut() {
        c.drawn_on(frame);
    }
    let mut keys = std::mem::take(&mut s.mesh_keys);
    keys.clear();
    for inst in &scene.instances {
        // Mesh instances met before are filled from their recorded spans.
        let key = match (inst.primitive, cache.as_mut()) {
            (Primitive::Mesh(id), Some(c)) => c.scene_mesh_key(scene, id, &mut keys),
            _ => None,
        };
        let Some((k, c)) = key.zip(cache.as_mut()) else {
            draw(frame, scene, inst, s);
            continue;
        };
        match c.lookup(k, inst) {
            Lookup::Hit { spans, bounds, .. } => s.mask.replay(spans, bounds),
            Lookup::Draw => draw(frame, scene, inst, s),
            Lookup::Record => {
                let mut spans = std::mem::take(&mut s.spans);
                spans.clear();
                s.mask.record = Some(spans);
                draw(frame, scene, inst, s);
                let spans = s.mask.record.take().unwrap_or_default();
                c.insert(k, inst, &spans, 0);
                s.spans = spans;
            }
        }
    }
    s.cache.cache = cache;
    s.mesh_keys = keys;
    let view = frame.world_view();
    for poly in &scene.polygons {
        let tris = triangulate_polygon(&poly.points).into_iter();
        s.projector.triangles(frame, &view, &poly.points, tris, |t| fill_triangle(frame, t, &mut s.mask, &mut s.rows));
    }
}

/// Rasterizes one instance into `s.mask`.
fn draw(frame: &Frame, scene: &Scene, inst: &Instance, s: &mut ImageScratch) {
    let Some(to_view) = frame.instance_view(&inst.transform) else { return };
    let (mesh, table) = match inst.primitive {
        Primitive::Mesh(id) => {
            let Some(mesh) = scene.meshes.get(id as usize) else { return };
            (&**mesh, s.closed.get(mesh))
        }
        p => s.shapes.get_with_edges(p),
    };
    let kept = s.projector.project(frame, &to_view, &mesh.positions);
    match table {
        // A closed surface, all on screen: its outline.
        Some(table) if kept => {
            fill_outline(frame, mesh, table, s.projector.snapped(), &mut s.mask, &mut s.outline);
        }
        _ => s.projector.projected_triangles(frame, mesh.triangles.iter().copied(), false, |t| {
            fill_triangle(frame, t, &mut s.mask, &mut s.rows)
        }),
    }
}

/// `(b − a) × (c − a)`: positive when `a, b, c` turn the way every filled
/// polygon here is wound (clockwise on screen, as `y` runs down).
#[inline]
pub(crate) fn cross(a: Pt, b: Pt, c: Pt) -> i64 {
    (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])
}

/// Fills one triangle of either winding; degenerate ones cover nothing.
fn fill_triangle(frame: &Frame, [a, b, c]: [Pt; 3], mask: &mut Mask, rows: &mut Rows) {
    let area = cross(a, b, c);
    if area > 0 {
        fill_convex(frame, &[a, b, c], mask, rows);
    } else if area < 0 {
        fill_convex(frame, &[a, c, b], mask, rows);
    }
}

/// The convex hull of `pts` (reordered, deduplicated) into `hull`, wound so
/// that [`cross`] is positive, with no collinear vertices (Andrew's monotone
/// chain, exact). Fewer than 3 vertices when the points are collinear.
/// (Tests build convex polygons with it.)
#[cfg(test)]
pub(crate) fn convex_hull(pts: &mut Vec<Pt>, hull: &mut Vec<Pt>) {
    // Below ~64 points sorting them all is cheaper than the prefilter.
    if pts.len() > 64 {
        discard_interior(pts, hull);
    }
    pts.sort_unstable();
    pts.dedup();
    hull.clear();
    if pts.len() < 3 {
        return;
    }
    for &p in pts.iter() {
        while hull.len() >= 2 && cross(hull[hull.len() - 2], hull[hull.len() - 1], p) <= 0 {
            hull.pop();
        }
        hull.push(p);
    }
    let lower = hull.len() + 1;
    for &p in pts.iter().rev().skip(1) {
        while hull.len() >= lower && cross(hull[hull.len() - 2], hull[hull.len() - 1], p) <= 0 {
            hull.pop();
        }
        hull.push(p);
    }
    hull.pop();
}

/// Akl–Toussaint: drops the points strictly inside the polygon of the
/// extreme points in 8 directions (they cannot be hull vertices), so the
/// sort sees only the outline of a many-vertex sphere or frustum.
#[cfg(test)]
fn discard_interior(pts: &mut Vec<Pt>, buf: &mut Vec<Pt>) {
    // Extremes of x, y, x + y and x − y, low then high.
    let mut ex = [pts[0]; 8];
    let key = |p: Pt| [p[0], p[1], p[0] + p[1], p[0] - p[1]];
    let mut lo = key(pts[0]);
    let mut hi = lo;
    for &p in pts.iter() {
        let k = key(p);
        for j in 0..4 {
            if k[j] < lo[j] {
                lo[j] = k[j];
                ex[2 * j] = p;
            }
            if k[j] > hi[j] {
                hi[j] = k[j];
                ex[2 * j + 1] = p;
            }
        }
    }
    let mut ex = ex.to_vec();
    convex_hull(&mut ex, buf);
    if buf.len() < 3 {
        return;
    }
    // The octagon's edges as (start, end) pairs: no modulo in the hot loop.
    let mut edges = [([0i64; 2], [0i64; 2]); 8];
    let m = buf.len();
    for (i, e) in edges.iter_mut().enumerate().take(m) {
        *e = (buf[i], buf[(i + 1) % m]);
    }
    let edges = &edges[..m];
    pts.retain(|&p| edges.iter().any(|&(a, b)| cross(a, b, p) <= 0));
}

/// `(floor(n / d), n mod d)` for `0 < d < 2^31` and `|n| < 2^62`: an `f64`
/// estimate made exact with integer remainders (an `i64` division is
/// several times slower, and edge setups do two).
#[inline]
fn div_floor(n: i64, d: i64) -> (i64, i64) {
    // Off by at most |n / d|·2^-52 + 1 (≤ 2^10 here); rounded towards −∞
    // (not zero) so that negative quotients rarely need the correction.
    let t = n as f64 / d as f64;
    let mut q = t as i64;
    if (q as f64) > t {
        q -= 1;
    }
    let mut r = n - q * d;
    if r < 0 || r >= d {
        // |r| < 2^41: this estimate is off by at most one.
        let q2 = (r as f64 / d as f64) as i64;
        q += q2;
        r -= q2 * d;
        if r < 0 {
            q -= 1;
            r += d;
        } else if r >= d {
            q += 1;
            r -= d;
        }
    }
    (q, r)
}

/// First pixel row whose center `y * ONE + HALF` is at or below `y`.
#[inline]
pub(crate) fn first_row(y: i64) -> i64 {
    (y - HALF + ONE - 1) >> SUB
}

/// One edge of a chain, stepped row by row: `x = u.x + floor(n / d)` with
/// `n` growing by `step` per row, kept as quotient and remainder.
pub(crate) struct EdgeWalk {
    /// Rows `..end` use this edge.
    end: i64,
    /// The edge's offset at the current row (see [`EdgeWalk::new`]).
    pub x: i64,
    r: i64,
    d: i64,
    step_q: i64,
    step_r: i64,
}

impl EdgeWalk {
    /// The edge from `u` (upper) to `l` (lower), at pixel row `row`. A left
    /// edge gives the least center `x = u.x + t` with `E >= 0`, a right edge
    /// the greatest with `E > 0`, where `E = d·t − k` or `k − d·t`,
    /// `d = l.y − u.y`, `k = (l.x − u.x)(y − u.y)`.
    pub fn new(u: Pt, l: Pt, row: i64, left: bool) -> EdgeWalk {
        let d = l[1] - u[1];
        if d <= 0 {
            // A horizontal edge covers no row center: already finished.
            return EdgeWalk { end: i64::MIN, x: 0, r: 0, d: 1, step_q: 0, step_r: 0 };
        }
        let dx = l[0] - u[0];
        let y = row * ONE + HALF;
        let k = dx * (y - u[1]);
        // Left: t >= ceil(k / d) = floor((k + d − 1) / d).
        // Right: t <= floor((k − 1) / d).
        let n = if left { k + d - 1 } else { k - 1 };
        let (q, r) = div_floor(n, d);
        let (step_q, step_r) = div_floor(dx * ONE, d);
        EdgeWalk { end: first_row(l[1]), x: u[0] + q, r, d, step_q, step_r }
    }

    #[inline(always)]
    pub fn step(&mut self) {
        // Branch-free carry: the remainder pattern of a slope is erratic.
        let r = self.r + self.step_r;
        let carry = !((r - self.d) >> 63);
        self.x += self.step_q + (carry & 1);
        self.r = r - (carry & self.d);
    }
}

/// Per-row chain positions of the polygon being filled (one slot per image
/// row), so each chain is walked in its own tight loop.
#[derive(Default)]
pub(crate) struct Rows {
    left: Vec<i64>,
    right: Vec<i64>,
}

/// Walks both chains down from `top`, writing the left and right edge
/// positions of each row of `rows` into `left` and `right`. The two chains
/// step in one loop so their carry chains overlap.
fn walk_chains(poly: &[Pt], top: usize, bottom: usize, (row0, row_end): (i64, i64), rows: &mut Rows) {
    let n = poly.len();
    let next = |i: usize| (i + 1) % n;
    let prev = |i: usize| (i + n - 1) % n;
    let (mut ri, mut li) = (top, top);
    let mut right = EdgeWalk::new(poly[ri], poly[next(ri)], row0, false);
    let mut left = EdgeWalk::new(poly[li], poly[prev(li)], row0, true);
    let mut row = row0;
    while row < row_end {
        // (An edge ending at or above `row` before the bottom would be
        // replaced at once: its set-up, two divisions, is skipped.)
        while right.end <= row && ri != bottom {
            ri = next(ri);
            if ri == bottom || first_row(poly[next(ri)][1]) > row {
                right = EdgeWalk::new(poly[ri], poly[next(ri)], row, false);
            }
        }
        while left.end <= row && li != bottom {
            li = prev(li);
            if li == bottom || first_row(poly[prev(li)][1]) > row {
                left = EdgeWalk::new(poly[li], poly[prev(li)], row, true);
            }
        }
        // Rows up to `end` keep both edges (in a proper polygon every row
        // has one on each chain; `max` only guards against looping forever).
        let end = left.end.min(right.end).min(row_end).max(row + 1);
        let span = (row - row0) as usize..(end - row0) as usize;
        for (l, r) in rows.left[span.clone()].iter_mut().zip(&mut rows.right[span]) {
            *l = left.x;
            *r = right.x;
            left.step();
            right.step();
        }
        row = end;
    }
}

/// Fills a convex polygon wound so that [`cross`] is positive, with no
/// repeated vertices, using the coverage rule of the module docs: rows whose
/// center `y` has `top <= y < bottom`; in each, the centers right of (or on)
/// the left chain and strictly left of the right chain.
pub(crate) fn fill_convex(frame: &Frame, poly: &[Pt], mask: &mut Mask, rows: &mut Rows) {
    let (mut top, mut bottom) = (0, 0);
    let (mut x_lo, mut x_hi) = (i64::MAX, i64::MIN);
    for (i, p) in poly.iter().enumerate() {
        if p[1] < poly[top][1] {
            top = i;
        }
        if p[1] > poly[bottom][1] {
            bottom = i;
        }
        x_lo = x_lo.min(p[0]);
        x_hi = x_hi.max(p[0]);
    }
    let row0 = first_row(poly[top][1]).max(0);
    let row_end = first_row(poly[bottom][1]).min(frame.height as i64);
    let x_max = frame.width as i64 - 1;
    // Pixel columns of the bounding box.
    let (col0, col1) = (((x_lo - HALF + ONE - 1) >> SUB).max(0), ((x_hi - HALF) >> SUB).min(x_max));
    if row0 >= row_end || col0 > col1 {
        return;
    }
    let len = (row_end - row0) as usize;
    if rows.left.len() < len {
        rows.left.resize(frame.height, 0);
        rows.right.resize(frame.height, 0);
    }
    // Forward from the top runs down the right chain; backward, the left.
    walk_chains(poly, top, bottom, (row0, row_end), rows);
    // Bookkeeping once per polygon, not per span.
    mask.mark(row0 as usize..row_end as usize, col0 as usize / 64, col1 as usize / 64);
    let mut record = mask.record.take();
    let (words, wpr) = mask.words_mut();
    let lines = words.chunks_exact_mut(wpr).skip(row0 as usize);
    for (y, ((line, &xl), &xr)) in (row0..).zip(lines.zip(&rows.left[..len]).zip(&rows.right[..len])) {
        // Center i·ONE + HALF >= xl  ⇔  i >= ceil((xl − HALF) / ONE).
        let x0 = ((xl - HALF + ONE - 1) >> SUB).max(col0);
        let x1 = ((xr - HALF) >> SUB).min(col1);
        if x0 > x1 {
            continue;
        }
        or_span(line, x0, x1);
        if let Some(r) = &mut record {
            r.push((y as u32, x0 as u32, x1 as u32));
        }
    }
    mask.record = record;
}

/// Covers pixels `x0..=x1` (`0 <= x0 <= x1`, within the row) of one row's
/// mask words.
#[inline]
pub(crate) fn or_span(line: &mut [u64], x0: i64, x1: i64) {
    let (w0, w1) = (x0 as usize / 64, x1 as usize / 64);
    let first = !0u64 << (x0 % 64);
    let last = !0u64 >> (63 - x1 % 64);
    // Branch-free for one or two words (whether a span crosses a word
    // boundary is a coin toss): with one word both writes set the same
    // bits.
    let one = w0 == w1;
    line[w0] |= first & if one { last } else { !0 };
    line[w1] |= last & if one { first } else { !0 };
    // Short runs are the rule; a loop beats a call to memset.
    for w in line.iter_mut().take(w1).skip(w0 + 1) {
        *w = !0;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::image::coverage::Coverage;
    use crate::image::oracle::cover_triangle;
    use genform_core::camera::Camera;
    use proptest::prelude::*;

    fn frame(w: u32, h: u32) -> Frame {
        Frame::new(&Camera::default().projection(w, h))
    }

    /// Snapped points on a grid of half pixels (so many edges and vertices
    /// pass exactly through pixel centers) or anywhere, reaching past the
    /// borders of a 16×12 image.
    fn point() -> impl Strategy<Value = Pt> {
        prop_oneof![
            (-6i64..40, -6i64..30).prop_map(|(x, y)| [x * HALF, y * HALF]),
            (-6 * HALF..40 * HALF, -6 * HALF..30 * HALF).prop_map(|(x, y)| [x, y]),
        ]
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(400))]

        /// Stepping an edge row by row gives the same offsets as dividing
        /// afresh at every row.
        #[test]
        fn edge_walks_step_exactly(u in point(), l in point(), left in any::<bool>()) {
            let (u, l) = if u[1] <= l[1] { (u, l) } else { (l, u) };
            prop_assume!(u[1] < l[1]);
            let start = first_row(u[1]);
            let mut walk = EdgeWalk::new(u, l, start, left);
            for row in start..walk.end {
                let fresh = EdgeWalk::new(u, l, row, left);
                prop_assert_eq!((walk.x, walk.r), (fresh.x, fresh.r), "row {}", row);
                walk.step();
            }
        }

        /// The float-estimated division is exact over the whole range edge
        /// setups use, near the extremes too.
        #[test]
        fn div_floor_is_exact(
            n in prop_oneof![any::<i64>().prop_map(|n| n >> 2), -1_000_000i64..1_000_000],
            d in prop_oneof![1i64..100, 1i64..(1 << 31)],
        ) {
            prop_assert_eq!(div_floor(n, d), (n.div_euclid(d), n.rem_euclid(d)));
        }

        /// One step keeps `q·d + r` = the numerator and `0 <= r < d`,
        /// carrying exactly when the remainder reaches the denominator.
        #[test]
        fn edge_steps_carry_exactly(d in 1i64..50, r in 0i64..50, q in -99i64..99, step in -500i64..500) {
            let r = r % d;
            let step_q = step.div_euclid(d);
            let mut w = EdgeWalk { end: 0, x: q, r, d, step_q, step_r: step - step_q * d };
            w.step();
            let n = q * d + r + step;
            prop_assert_eq!((w.x, w.r), (n.div_euclid(d), n.rem_euclid(d)));
        }

        /// Exact ties included: triangle spans and hull spans cover what the
        /// per-pixel edge tests cover.
        #[test]
        fn spans_follow_the_coverage_rule(pts in prop::collection::vec(point(), 3..12)) {
            let f = frame(16, 12);
            let mut mask = Mask::new(16, 12);
            let mut rows = Rows::default();
            fill_triangle(&f, [pts[0], pts[1], pts[2]], &mut mask, &mut rows);
            let mut expect = Coverage::new(16, 12);
            cover_triangle([pts[0], pts[1], pts[2]], &mut expect);
            let got = mask.take();
            prop_assert_eq!(got.differences(&expect), vec![]);
            // The hull against the fan of triangles it splits into.
            let (mut pts, mut hull) = (pts, Vec::new());
            convex_hull(&mut pts, &mut hull);
            let mut expect = Coverage::new(16, 12);
            if hull.len() >= 3 {
                fill_convex(&f, &hull, &mut mask, &mut rows);
                for i in 1..hull.len() - 1 {
                    cover_triangle([hull[0], hull[i], hull[i + 1]], &mut expect);
                }
            }
            prop_assert_eq!(mask.take().differences(&expect), vec![]);
        }
    }

    #[test]
    fn hull_drops_interior_and_collinear_points() {
        let mut pts = vec![[0, 0], [10, 0], [5, 0], [10, 10], [0, 10], [5, 5], [0, 10], [3, 7]];
        let mut hull = Vec::new();
        convex_hull(&mut pts, &mut hull);
        assert_eq!(hull.len(), 4);
        for i in 0..4 {
            assert!(cross(hull[i], hull[(i + 1) % 4], hull[(i + 2) % 4]) > 0);
        }
        // Many points on a circle plus interior ones: the prefilter keeps
        // the outline intact.
        let mut pts: Vec<Pt> = (0..200)
            .map(|i| {
                let a = i as f64 * 0.0314159 * 2.0;
                let r = if i % 3 == 0 { 1e6 } else { 5e5 };
                [(r * a.cos()) as i64, (r * a.sin()) as i64]
            })
            .collect();
        let outline: Vec<Pt> = pts.iter().step_by(3).copied().collect();
        convex_hull(&mut pts, &mut hull);
        let mut brute = outline.clone();
        let mut expect = Vec::new();
        convex_hull(&mut brute, &mut expect);
        assert_eq!(hull, expect);
        assert!(hull.len() > 50);
        // Collinear input: no polygon.
        let mut line = vec![[0, 0], [1, 1], [2, 2]];
        convex_hull(&mut line, &mut hull);
        assert!(hull.len() < 3);
    }
}
