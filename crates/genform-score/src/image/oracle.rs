//! The per-pixel reference rasterizer: the test oracle of the fast path and
//! the baseline of its benchmark.
//!
//! Every triangle of every instance and polygon is clipped and snapped
//! exactly as the fast path does it (shared code, `image::project`); then
//! every pixel center in the triangle's bounding box is tested against its
//! three edges. No hulls, no spans, no incremental stepping: only the
//! coverage rule written out as a predicate.

use super::ImageScorer;
use super::coverage::Coverage;
use super::project::{HALF, ONE, Projector, Pt, SUB, Shapes};
use crate::fitness::Counts;
use genform_core::scene::triangulate_polygon;
use genform_core::scene::{Primitive, Scene};

/// The pixels `scene` covers through `scorer`'s camera, by brute force.
pub fn coverage(scorer: &ImageScorer, scene: &Scene) -> Coverage {
    let frame = &scorer.frame;
    let mut out = Coverage::new(frame.width as u32, frame.height as u32);
    let mut shapes = Shapes::new(scorer.tessellation());
    let mut projector = Projector::default();
    let mut cover = |t: [Pt; 3]| cover_triangle(t, &mut out);
    for inst in &scene.instances {
        let Some(to_view) = frame.instance_view(&inst.transform) else { continue };
        let mesh = match inst.primitive {
            Primitive::Mesh(id) => match scene.meshes.get(id as usize) {
                Some(m) => &**m,
                None => continue,
            },
            p => shapes.get(p),
        };
        projector.triangles(frame, &to_view, &mesh.positions, mesh.triangles.iter().copied(), &mut cover);
    }
    for poly in &scene.polygons {
        projector.triangles(
            frame,
            &frame.world_view(),
            &poly.points,
            triangulate_polygon(&poly.points).into_iter(),
            &mut cover,
        );
    }
    out
}

/// [`ImageScorer::counts`] computed pixel by pixel from [`coverage`].
pub fn counts(scorer: &ImageScorer, scene: &Scene) -> Counts {
    let cov = coverage(scorer, scene);
    let target = scorer.target();
    let mut c = Counts { target: target.total_positive(), ..Counts::default() };
    for y in 0..cov.height() {
        for x in 0..cov.width() {
            if cov.get(x, y) {
                let w = f64::from(target.weight(x, y));
                if w > 0.0 {
                    c.good += w;
                } else {
                    c.bad -= w;
                }
            }
        }
    }
    c
}

/// Whether the center `p` is covered by the triangle `t` (wound so that its
/// edge functions are positive inside): inside every edge, where a center
/// exactly on an edge counts as nudged by `(ε, ε²)`.
fn covers(t: &[Pt; 3], p: Pt) -> bool {
    (0..3).all(|i| {
        let (a, b) = (t[i], t[(i + 1) % 3]);
        let e = (b[0] - a[0]) * (p[1] - a[1]) - (b[1] - a[1]) * (p[0] - a[0]);
        let (de_dx, de_dy) = (a[1] - b[1], b[0] - a[0]);
        e > 0 || (e == 0 && (de_dx > 0 || (de_dx == 0 && de_dy > 0)))
    })
}

/// Sets the pixels whose centers the triangle covers (either winding).
pub(crate) fn cover_triangle([a, b, c]: [Pt; 3], out: &mut Coverage) {
    let area = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
    let t = match area {
        0 => return,
        1.. => [a, b, c],
        _ => [a, c, b],
    };
    let lo = |k: usize| (t.iter().map(|p| p[k]).min().unwrap_or(0) - HALF) >> SUB;
    let hi = |k: usize| ((t.iter().map(|p| p[k]).max().unwrap_or(0) - HALF) >> SUB) + 1;
    let (w, h) = (i64::from(out.width()), i64::from(out.height()));
    for y in lo(1).max(0)..hi(1).min(h) {
        for x in lo(0).max(0)..hi(0).min(w) {
            if covers(&t, [x * ONE + HALF, y * ONE + HALF]) {
                out.set(x as u32, y as u32);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn edge_rule_splits_shared_edges() {
        // Two triangles sharing a diagonal through pixel centers: each
        // center on it belongs to exactly one of them.
        let p = |x: i64, y: i64| [x * ONE + HALF, y * ONE + HALF];
        let (a, b, c, d) = (p(0, 0), p(4, 0), p(4, 4), p(0, 4));
        let t1 = [a, b, c];
        let t2 = [a, c, d];
        for y in 0..=4 {
            for x in 0..=4 {
                let n = covers(&t1, p(x, y)) as u32 + covers(&t2, p(x, y)) as u32;
                let inside = x < 4 && y < 4;
                assert_eq!(n, inside as u32, "({x}, {y})");
            }
        }
    }
}
