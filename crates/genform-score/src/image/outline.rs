//! Silhouettes of closed surfaces filled from their outline edges.
//!
//! Filling a closed mesh triangle by triangle writes every row of every
//! front face, although neighbouring front faces only tile the same
//! region. Here the faces are summed instead: per pixel row, a positively
//! wound triangle covers the centres `L ≤ x < R + 1`, where `L` and `R + 1`
//! are both "the first column whose centre is at or right of the edge" (the
//! coverage rule puts a centre on an edge in the triangle to its right; see
//! [`super::raster`]). So the number of front faces covering a centre is a
//! sum of `+1` at each left edge's column and `−1` at each right edge's,
//! and the union is where that sum is positive. An edge shared by two front
//! faces is a right edge of one and a left edge of the other at the same
//! columns (the same upper and lower vertex, the same integer arithmetic):
//! its two terms cancel, so only the edges between a front face and a back
//! or degenerate one (the outline) are walked. This is exact for any set of
//! triangles; it equals the union of *all* triangles for closed surfaces
//! (see `Projector::triangles_culled`).
//!
//! That count is also the winding number of the outline (interior edges
//! cancel as chains too), so when the outline is a single strictly convex
//! polygon run once, the union is that polygon, filled with one span per
//! row like a triangle (most trunk and leaf instances, every box seen whole).
//! Otherwise each outline edge's columns become `±` events per row, summed
//! left to right.

use super::coverage::Mask;
use super::coverage::or_span;
use super::edge_table::EdgeTable;
use super::project::{Frame, HALF, ONE, Pt, SUB, cross};
use super::scan::{EdgeWalk, Rows, fill_convex, first_row};
use genform_core::scene::Mesh;

/// Working memory of [`fill_outline`].
#[derive(Default)]
pub(crate) struct OutlineBuffers {
    /// Per triangle: 1 when positively wound on screen.
    front: Vec<i32>,
    /// Outline edges `(a, b, w)`: `w > 0` more front faces run `a → b`
    /// than `b → a`.
    outline: Vec<(u32, u32, i32)>,
    /// Per vertex: the outline edge leaving it (convex check).
    succ: Vec<u32>,
    /// The outline as a polygon, when it is one and convex.
    poly: Vec<Pt>,
    /// Chain positions for [`fill_convex`].
    rows: Rows,
    /// Outline edges: upper and lower vertex, weight, first and end row.
    edges: Vec<(Pt, Pt, i32, i64, i64)>,
    /// Events per row, then where each row's events start.
    starts: Vec<u32>,
    /// `(column, weight)` per event, grouped by row.
    events: Vec<(i32, i32)>,
}

/// Fills the union of the positively wound triangles of `mesh` with the
/// snapped vertices `pts` (every index in range) into `mask`; whether it
/// was filled as one convex polygon.
pub(crate) fn fill_outline(
    frame: &Frame,
    mesh: &Mesh,
    table: &EdgeTable,
    pts: &[Pt],
    mask: &mut Mask,
    buf: &mut OutlineBuffers,
) -> bool {
    let (mut lo, mut hi) = ([i64::MAX; 2], [i64::MIN; 2]);
    for p in pts {
        lo = [lo[0].min(p[0]), lo[1].min(p[1])];
        hi = [hi[0].max(p[0]), hi[1].max(p[1])];
    }
    let row0 = first_row(lo[1]).max(0);
    let row_end = first_row(hi[1]).min(frame.height as i64);
    let x_max = frame.width as i64 - 1;
    let (col0, col1) = (((lo[0] - HALF + ONE - 1) >> SUB).max(0), ((hi[0] - HALF) >> SUB).min(x_max));
    if row0 >= row_end || col0 > col1 {
        return false;
    }
    let OutlineBuffers { front, outline, succ, poly, rows: chains, edges, starts, events } = buf;
    front.resize(mesh.triangles.len(), 0);
    for (f, t) in front.iter_mut().zip(&mesh.triangles) {
        let (a, b, c) = (pts[t[0] as usize], pts[t[1] as usize], pts[t[2] as usize]);
        *f = i32::from(cross(a, b, c) > 0);
    }
    // Weights: front faces running a → b minus those running b → a.
    outline.clear();
    let mut add = |a: u32, b: u32, w: i32| match w {
        0 => {}
        w if w > 0 => outline.push((a, b, w)),
        w => outline.push((b, a, -w)),
    };
    for &[a, b, f, k] in &table.pairs {
        add(a, b, front[f as usize] - front[k as usize]);
    }
    for ([a, b], uses) in &table.others {
        add(*a, *b, table.uses[uses.clone()].iter().map(|&(t, s)| front[t as usize] * s).sum());
    }
    // The count of front faces over a point is the winding number of the
    // outline around it: where the outline is one convex polygon run once,
    // the union is that polygon (same coverage rule), filled span by span.
    if convex_polygon(pts, outline, succ, poly) {
        fill_convex(frame, poly, mask, chains);
        return true;
    }
    // Events per row counted as differences: +1 where an edge's rows start,
    // −1 where they end.
    let rows = (row_end - row0) as usize;
    starts.clear();
    starts.resize(rows + 1, 0);
    edges.clear();
    for &(a, b, w) in outline.iter() {
        let (pa, pb) = (pts[a as usize], pts[b as usize]);
        // Running down (a above b), a → b is a right edge of its front
        // faces (−1); running up, a left edge (+1). Level edges cover no
        // row centre.
        let (u, l, w) = if pa[1] < pb[1] { (pa, pb, -w) } else { (pb, pa, w) };
        let (r0, r1) = (first_row(u[1]).max(row0), first_row(l[1]).min(row_end));
        if r0 < r1 {
            // (Wrapping: a row's difference may be negative.)
            let (i0, i1) = ((r0 - row0) as usize, (r1 - row0) as usize);
            starts[i0] = starts[i0].wrapping_add(1);
            starts[i1] = starts[i1].wrapping_sub(1);
            edges.push((u, l, w, r0, r1));
        }
    }
    if edges.is_empty() {
        return false;
    }
    // Running sums of the differences are the events per row; their
    // exclusive sums each row's start, which doubles as its cursor while
    // placing.
    let (mut active, mut total) = (0u32, 0u32);
    for s in starts.iter_mut() {
        active = active.wrapping_add(*s);
        *s = total;
        total += active;
    }
    events.clear();
    events.resize(total as usize, (0, 0));
    let width = frame.width as i64;
    for &(u, l, w, r0, r1) in edges.iter() {
        let mut walk = EdgeWalk::new(u, l, r0, true);
        let cursors = &mut starts[(r0 - row0) as usize..(r1 - row0) as usize];
        for c in cursors {
            // The first column whose centre is at or right of the edge.
            let x = ((walk.x - HALF + ONE - 1) >> SUB).clamp(0, width);
            events[*c as usize] = (x as i32, w);
            *c += 1;
            walk.step();
        }
    }
    // Cursors now hold each row's end: its start is the previous end.
    mask.mark(row0 as usize..row_end as usize, col0 as usize / 64, col1 as usize / 64);
    let mut record = mask.record.take();
    let (words, wpr) = mask.words_mut();
    let mut begin = 0usize;
    for (r, &end) in starts[..rows].iter().enumerate() {
        let row = &mut events[begin..end as usize];
        begin = end as usize;
        if row.is_empty() {
            continue;
        }
        sort_small(row);
        let line = &mut words[(row0 as usize + r) * wpr..][..wpr];
        let (mut sum, mut from) = (0i32, 0i64);
        for &(x, w) in row.iter() {
            let was = sum > 0;
            sum += w;
            let x = i64::from(x);
            if !was && sum > 0 {
                from = x;
            } else if was && sum <= 0 && from < x {
                let to = (x - 1).min(x_max);
                or_span(line, from, to);
                if let Some(rec) = &mut record {
                    rec.push(((row0 as usize + r) as u32, from as u32, to as u32));
                }
            }
        }
    }
    mask.record = record;
    false
}

/// Whether the outline edges (`w > 0` from `a` to `b`) are one polygon,
/// each edge once, strictly convex and wound once, positively (as
/// [`cross`] counts): then `poly` holds its vertices in order.
fn convex_polygon(pts: &[Pt], outline: &[(u32, u32, i32)], succ: &mut Vec<u32>, poly: &mut Vec<Pt>) -> bool {
    let n = outline.len();
    if n < 3 || outline.iter().any(|e| e.2 != 1) {
        return false;
    }
    succ.clear();
    succ.resize(pts.len(), NONE);
    for &(a, b, _) in outline {
        let s = &mut succ[a as usize];
        if *s != NONE {
            return false;
        }
        *s = b;
    }
    poly.clear();
    let start = outline[0].0;
    let mut v = start;
    loop {
        poly.push(pts[v as usize]);
        v = succ[v as usize];
        if v == start {
            break;
        }
        if v == NONE || poly.len() == n {
            return false;
        }
    }
    if poly.len() != n {
        return false;
    }
    // Every turn strictly positive, and the direction of travel turning
    // once around: `y` changes from falling to rising (or back) twice.
    let (mut turns, mut last, mut first) = (0, 0, 0);
    for i in 0..n {
        let (a, b, c) = (poly[i], poly[(i + 1) % n], poly[(i + 2) % n]);
        if cross(a, b, c) <= 0 {
            return false;
        }
        let dy = (b[1] - a[1]).signum();
        if dy != 0 {
            if last != 0 && dy != last {
                turns += 1;
            }
            if first == 0 {
                first = dy;
            }
            last = dy;
        }
    }
    if last != first {
        turns += 1;
    }
    turns == 2
}

/// No outline edge leaves this vertex.
const NONE: u32 = u32::MAX;

/// Sorts a row's events by column (insertion sort: rows hold a few).
#[inline]
fn sort_small(row: &mut [(i32, i32)]) {
    if let [a, b] = row {
        if b.0 < a.0 {
            std::mem::swap(a, b);
        }
        return;
    }
    for i in 1..row.len() {
        let v = row[i];
        let mut j = i;
        while j > 0 && row[j - 1].0 > v.0 {
            row[j] = row[j - 1];
            j -= 1;
        }
        row[j] = v;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::image::coverage::Coverage;
    use crate::image::oracle::cover_triangle;
    use genform_core::Rng;
    use genform_core::camera::Camera;
    use genform_core::scene::{Primitive, Tessellation, unit_mesh};

    /// Closed topologies: the tree assets, the cube, a sphere and a frustum.
    fn closed() -> Vec<Mesh> {
        let obj = |name, text| Mesh::from_obj(name, text).unwrap();
        let tess = Tessellation { radial: 7, rings: 4 };
        vec![
            obj("trunk", include_str!("../../tests/data/trunk.obj")),
            obj("leaf", include_str!("../../tests/data/leaf_low_poly.obj")),
            obj("cube", include_str!("../../tests/data/cube.obj")),
            unit_mesh(Primitive::Sphere, tess),
            unit_mesh(Primitive::Frustum { top: 0.4 }, tess),
        ]
    }

    /// The outline fill against the per-pixel coverage rule: the union of
    /// the positively wound triangles, and (the topology being closed) of
    /// all triangles. Vertices are placed anywhere, also on a grid of half
    /// pixels where edges and vertices fall on pixel centres (the tie
    /// rule), reaching past the image borders; self-intersecting and folded
    /// placements included.
    #[test]
    fn outline_fill_equals_the_union_of_triangles() {
        let meshes = closed();
        let mut rng = Rng::stream(18, &[3]);
        let mut buf = OutlineBuffers::default();
        let mut convex = 0;
        for case in 0..6000 {
            let (w, h) = if case % 3 == 0 { (16, 12) } else { (70, 33) };
            let frame = Frame::new(&Camera::default().projection(w, h));
            let mesh = &meshes[case % meshes.len()];
            assert!(crate::image::edge_table::is_closed(mesh));
            let table = EdgeTable::new(mesh);
            // Placements: a random affine image of the unit shape, snapped
            // to a grid of 1/2, 1/4 pixel or anywhere, sometimes flattened.
            let grid = [HALF, HALF / 2, 1][rng.below(3) as usize];
            let mut m = [0.0; 6];
            for v in &mut m {
                *v = (rng.next_f64() - 0.5) * 2.5 * w as f64;
            }
            if rng.below(4) == 0 {
                m[rng.below(3) as usize] = 0.0;
            }
            let (cx, cy) = (rng.next_f64() * w as f64, rng.next_f64() * h as f64);
            let pts: Vec<Pt> = mesh
                .positions
                .iter()
                .map(|p| {
                    let (p, q, r) = (f64::from(p.x), f64::from(p.y), f64::from(p.z));
                    let x = (cx + m[0] * p + m[1] * q + m[2] * r) * ONE as f64;
                    let y = (cy + m[3] * p + m[4] * q + m[5] * r) * ONE as f64;
                    [(x as i64).div_euclid(grid) * grid, (y as i64).div_euclid(grid) * grid]
                })
                .collect();
            let mut mask = Mask::new(w as usize, h as usize);
            convex += usize::from(fill_outline(&frame, mesh, &table, &pts, &mut mask, &mut buf));
            let got = mask.take();
            let (mut front, mut all) = (Coverage::new(w, h), Coverage::new(w, h));
            for t in &mesh.triangles {
                let [a, b, c] = t.map(|i| pts[i as usize]);
                if cross(a, b, c) > 0 {
                    cover_triangle([a, b, c], &mut front);
                }
                cover_triangle([a, b, c], &mut all);
            }
            assert_eq!(got.differences(&front), vec![], "case {case}: front faces");
            assert_eq!(got.differences(&all), vec![], "case {case}: all faces");
            assert!(mask.is_clear());
        }
        // Both ways of filling are exercised.
        assert!((500..5800).contains(&convex), "{convex} of 6000 filled as convex polygons");
    }

    #[test]
    fn edge_tables_pair_each_edge_of_a_closed_mesh() {
        for mesh in closed() {
            let table = EdgeTable::new(&mesh);
            // Every edge of these 2-manifolds is one pair of opposite uses.
            assert_eq!((2 * table.pairs.len(), table.others.len()), (3 * mesh.triangles.len(), 0), "{}", mesh.name);
            for &[a, b, f, k] in &table.pairs {
                assert!(a < b);
                let runs = |t: u32, x: u32, y: u32| {
                    let t = mesh.triangles[t as usize];
                    (0..3).any(|e| (t[e], t[(e + 1) % 3]) == (x, y))
                };
                assert!(runs(f, a, b) && runs(k, b, a), "{}: edge {a}–{b}", mesh.name);
            }
        }
    }
}
