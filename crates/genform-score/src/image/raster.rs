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
use super::edge_table::{EdgeTable, is_closed};
use super::outline::{OutlineBuffers, fill_outline};
use super::project::{Frame, Projector, Pt, Shapes, cross};
use super::scan::{Rows, fill_convex};
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::image::coverage::Coverage;
    use crate::image::oracle::cover_triangle;
    use crate::image::scan::tests::point;
    use genform_core::camera::Camera;
    use proptest::prelude::*;

    fn frame(w: u32, h: u32) -> Frame {
        Frame::new(&Camera::default().projection(w, h))
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(400))]

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
