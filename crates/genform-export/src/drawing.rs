//! Flat drawings as geometry: a 2D turtle's strokes and a graph grammar's
//! shapes turned into flat polygons in the z = 0 plane, so that the mesh
//! formats (OBJ, GLB, PLY, STL) and `Model.mesh()` have faces to hold
//! where the SVG has only strokes and fills.
//!
//! Strokes become ribbons: one quad per straight run, as wide as the
//! stroke, with a round wedge on the outer side of every bend (the SVG's
//! round joins) and a half disc at the ends of round-capped strokes; a
//! stroke of one point becomes a disc. A polyline that continues the one
//! before it (same tag and width, starting at its end) joins its ribbon. Filled
//! shapes become one polygon per closed sub-path (holes are filled: the
//! fill rule is not kept). Graph-grammar shapes go through the SVG writer
//! and usvg, so circles, rectangles and path data (Bézier curves and arcs
//! flattened) come out exactly where the SVG draws them, in their SVG
//! colours.

use crate::flat::is_flat;
use crate::palette::tag_color;
use crate::svg::shape_document;
use genform_core::scene::{Polygon, Scene, Shape2d, Shape2dKind, TagId};
use glam::{Vec2, Vec3};
use resvg::usvg;
use std::borrow::Cow;
use usvg::tiny_skia_path::PathSegment;

/// The width of a stroke that has none (a turtle's hairline, width 0) and
/// the diameter of a lone point, as a share of the drawing's largest
/// extent: 0.5 %, a thin but visible line at any scale.
pub const HAIRLINE_SHARE: f32 = 0.005;

/// Corners of a whole disc (lone points); joins and caps use as many per
/// turn.
const DISC_SIDES: usize = 8;

/// How far each colour layer sits above the one drawn before it, as a
/// share of the drawing's extent: overlapping shapes of different colours
/// (a window on a wall) would otherwise flicker in a viewer's depth test.
const LAYER_SHARE: f32 = 2e-4;

/// Straight pieces per Bézier curve.
const CURVE_STEPS: usize = 16;

/// `scene` with its flat drawing turned into polygons, as the mesh
/// formats and `Model.mesh()` write it; the scene itself when it is not a
/// flat drawing (anything solid in it, or a stroke off the z = 0 plane:
/// 3D turtle strokes stay lines) or has no strokes or 2D shapes.
///
/// Polylines become ribbons of their width ([`HAIRLINE_SHARE`] of the
/// drawing's extent when it is 0), round-capped and round-joined as the
/// SVG draws them, with their own tags. 2D shapes become polygons tagged
/// `<tag>#rrggbb` with their SVG fill or stroke colour (the palette reads
/// the suffix, so every format shows the drawing's colours); shapes
/// painted with a gradient or pattern keep their tag, and images are left
/// out. Each change of tag lifts what follows by [`LAYER_SHARE`] of the
/// extent, drawing order kept; a drawing in one colour stays at z = 0.
pub fn drawing_geometry(scene: &Scene) -> Cow<'_, Scene> {
    let finite = scene.polylines.points().iter().all(|p| p.is_finite());
    if !is_flat(scene) || !finite || (scene.polylines.is_empty() && scene.shapes2d.is_empty()) {
        return Cow::Borrowed(scene);
    }
    let mut out = scene.clone();
    out.polylines.clear();
    out.shapes2d.clear();
    let mut parts: Vec<(TagId, Part)> = Vec::new();
    for l in &scene.polylines {
        let width = (l.width.is_finite() && l.width > 0.0).then_some(l.width);
        // A polyline that starts where the one before it ended, in the same
        // tag and width, continues it: a turtle often starts a new polyline
        // where the last one ended (around brackets, for one), and two round
        // caps on one point are the round join the continued stroke draws
        // there. One ribbon instead of many keeps the caps to the real ends.
        if let Some((tag, Part::Stroke { points, width: w, .. })) = parts.last_mut()
            && *tag == l.tag
            && *w == width
            && l.points.first().map(|p| p.truncate()) == points.last().copied()
        {
            points.extend(l.points.iter().skip(1).map(|p| p.truncate()));
            continue;
        }
        let points = l.points.iter().map(|p| p.truncate()).collect();
        parts.push((l.tag, Part::Stroke { points, closed: false, width, cap: Cap::Round }));
    }
    for shape in &scene.shapes2d {
        let name = scene.tags.get(shape.tag as usize).map_or("shape", |t| t.as_str());
        for (color, part) in shape_parts(shape, tag_color(name)) {
            let tag = match color {
                Some([r, g, b]) => out.tag(&format!("{}#{r:02x}{g:02x}{b:02x}", strip_color(name))),
                None => shape.tag,
            };
            parts.push((tag, part));
        }
    }
    let mut bounds: Option<(Vec2, Vec2)> = None;
    let points = parts.iter().flat_map(|(_, p)| p.points()).copied();
    for p in points.chain(scene.polygons.iter().flat_map(|p| &p.points).map(|p| p.truncate())) {
        bounds = Some(bounds.map_or((p, p), |(lo, hi)| (lo.min(p), hi.max(p))));
    }
    let extent = bounds.map_or(0.0, |(lo, hi)| (hi - lo).max_element());
    let extent = if extent > 0.0 && extent.is_finite() { extent } else { 1.0 };
    let mut b = Builder {
        polygons: &mut out.polygons,
        hairline: HAIRLINE_SHARE * extent,
        lift: LAYER_SHARE * extent,
        // Above the turtle's own filled regions, which were drawn first.
        layer: usize::from(!scene.polygons.is_empty()),
        last: None,
    };
    for (tag, part) in &parts {
        b.part(*tag, part);
    }
    Cow::Owned(out)
}

/// `name` without a `#rrggbb` colour suffix.
fn strip_color(name: &str) -> &str {
    match name.rsplit_once('#') {
        Some((base, hex)) if hex.len() == 6 && hex.bytes().all(|c| c.is_ascii_hexdigit()) => base,
        _ => name,
    }
}

/// How an open stroke ends.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Cap {
    /// At the end point.
    Butt,
    /// A half disc past the end point.
    Round,
    /// Half the width past the end point.
    Square,
}

/// One thing to turn into polygons, in the drawing's coordinates (y up).
#[derive(Clone, Debug, PartialEq)]
enum Part {
    /// A filled outline.
    Fill(Vec<Vec2>),
    /// A stroked line; `width` `None` for a hairline.
    Stroke { points: Vec<Vec2>, closed: bool, width: Option<f32>, cap: Cap },
}

impl Part {
    fn points(&self) -> &[Vec2] {
        match self {
            Part::Fill(p) | Part::Stroke { points: p, .. } => p,
        }
    }
}

/// The fills and strokes of one 2D shape as the SVG draws it, each with its
/// colour (`None` for a gradient or pattern): the shape's SVG element
/// parsed by usvg, curves flattened, transforms applied, y turned up again.
fn shape_parts(shape: &Shape2d, color: [u8; 3]) -> Vec<(Option<[u8; 3]>, Part)> {
    // An image's href would have usvg read a file: images are not drawn.
    if matches!(shape.kind, Shape2dKind::Image { .. }) {
        return Vec::new();
    }
    let Ok(tree) = usvg::Tree::from_str(&shape_document(shape, color), &usvg::Options::default()) else {
        return Vec::new();
    };
    let mut out = Vec::new();
    collect(tree.root(), &mut out);
    out
}

fn collect(group: &usvg::Group, out: &mut Vec<(Option<[u8; 3]>, Part)>) {
    for node in group.children() {
        match node {
            usvg::Node::Group(g) => collect(g, out),
            usvg::Node::Path(p) if p.is_visible() => {
                let ts = p.abs_transform();
                let subpaths = flatten(p.data(), ts);
                if let Some(fill) = p.fill() {
                    for (points, _) in subpaths.iter().filter(|(p, _)| p.len() >= 3) {
                        out.push((paint_color(fill.paint()), Part::Fill(points.clone())));
                    }
                }
                if let Some(stroke) = p.stroke() {
                    // A transform's area scale, square-rooted, scales widths.
                    let scale = (ts.sx * ts.sy - ts.kx * ts.ky).abs().sqrt();
                    let width = stroke.width().get() * scale;
                    let cap = match stroke.linecap() {
                        usvg::LineCap::Butt => Cap::Butt,
                        usvg::LineCap::Round => Cap::Round,
                        usvg::LineCap::Square => Cap::Square,
                    };
                    for (points, closed) in subpaths {
                        let part = Part::Stroke { points, closed, width: Some(width), cap };
                        out.push((paint_color(stroke.paint()), part));
                    }
                }
            }
            _ => {}
        }
    }
}

fn paint_color(paint: &usvg::Paint) -> Option<[u8; 3]> {
    match paint {
        usvg::Paint::Color(c) => Some([c.red, c.green, c.blue]),
        _ => None,
    }
}

/// The sub-paths of `path` as point lists (y up, `ts` applied), each with
/// whether it was closed.
fn flatten(path: &usvg::tiny_skia_path::Path, ts: usvg::Transform) -> Vec<(Vec<Vec2>, bool)> {
    let map = |p: usvg::tiny_skia_path::Point| {
        let mut q = p;
        ts.map_point(&mut q);
        Vec2::new(q.x, -q.y)
    };
    let mut out = Vec::new();
    let mut cur: Vec<Vec2> = Vec::new();
    let (mut last, mut start) = (Vec2::ZERO, Vec2::ZERO);
    let finish = |cur: &mut Vec<Vec2>, closed: bool, out: &mut Vec<(Vec<Vec2>, bool)>| {
        if !cur.is_empty() {
            out.push((std::mem::take(cur), closed));
        }
    };
    for seg in path.segments() {
        match seg {
            PathSegment::MoveTo(p) => {
                finish(&mut cur, false, &mut out);
                last = map(p);
                start = last;
                cur.push(last);
            }
            PathSegment::LineTo(p) => {
                last = map(p);
                cur.push(last);
            }
            PathSegment::QuadTo(c, p) => {
                let (a, c, p) = (last, map(c), map(p));
                for k in 1..=CURVE_STEPS {
                    let t = k as f32 / CURVE_STEPS as f32;
                    cur.push(a * (1.0 - t) * (1.0 - t) + c * 2.0 * t * (1.0 - t) + p * t * t);
                }
                last = p;
            }
            PathSegment::CubicTo(c1, c2, p) => {
                let (a, c1, c2, p) = (last, map(c1), map(c2), map(p));
                for k in 1..=CURVE_STEPS {
                    let t = k as f32 / CURVE_STEPS as f32;
                    let s = 1.0 - t;
                    cur.push(a * s * s * s + c1 * 3.0 * s * s * t + c2 * 3.0 * s * t * t + p * t * t * t);
                }
                last = p;
            }
            PathSegment::Close => {
                finish(&mut cur, true, &mut out);
                // After a close the pen is back at the sub-path's start.
                last = start;
            }
        }
    }
    finish(&mut cur, false, &mut out);
    out
}

/// Writes parts as polygons, lifting each new colour layer.
struct Builder<'a> {
    polygons: &'a mut Vec<Polygon>,
    hairline: f32,
    lift: f32,
    layer: usize,
    last: Option<TagId>,
}

impl Builder<'_> {
    fn part(&mut self, tag: TagId, part: &Part) {
        if self.last.is_some_and(|t| t != tag) {
            self.layer += 1;
        }
        self.last = Some(tag);
        let z = self.layer as f32 * self.lift;
        match part {
            Part::Fill(points) => self.fill(points, z, tag),
            Part::Stroke { points, closed, width, cap } => {
                let w = width.unwrap_or(self.hairline);
                if w > 0.0 && w.is_finite() {
                    self.stroke(points, *closed, 0.5 * w, *cap, z, tag);
                }
            }
        }
    }

    /// A polygon of `points`, turned counter-clockwise (its front facing
    /// +z, towards a viewer of the SVG).
    fn push(&mut self, points: impl Iterator<Item = Vec2>, z: f32, tag: TagId) {
        let mut points: Vec<Vec3> = points.map(|p| p.extend(z)).collect();
        let twice_area: f32 = (0..points.len())
            .map(|i| {
                let (a, b) = (points[i], points[(i + 1) % points.len()]);
                a.x * b.y - b.x * a.y
            })
            .sum();
        if twice_area == 0.0 || !twice_area.is_finite() {
            return;
        }
        if twice_area < 0.0 {
            points.reverse();
        }
        self.polygons.push(Polygon { points, tag });
    }

    fn fill(&mut self, points: &[Vec2], z: f32, tag: TagId) {
        let mut pts = dedup(points);
        if pts.len() > 1 && pts.first() == pts.last() {
            pts.pop();
        }
        if pts.len() >= 3 {
            self.push(pts.into_iter(), z, tag);
        }
    }

    fn disc(&mut self, c: Vec2, r: f32, z: f32, tag: TagId) {
        let corner = |k: usize| {
            let a = std::f32::consts::TAU * k as f32 / DISC_SIDES as f32;
            c + r * Vec2::new(a.cos(), a.sin())
        };
        self.push((0..DISC_SIDES).map(corner), z, tag);
    }

    /// A ribbon `2·h` wide along `points`: a quad per straight run, round
    /// joins at the bends and (round caps) half discs at the ends.
    fn stroke(&mut self, points: &[Vec2], closed: bool, h: f32, cap: Cap, z: f32, tag: TagId) {
        let mut pts = dedup(points);
        if closed && pts.len() > 1 && pts.first() == pts.last() {
            pts.pop();
        }
        straighten(&mut pts);
        let n = pts.len();
        if n == 0 {
            return;
        }
        if n == 1 {
            // A dot: what SVG draws for a zero-length round or square cap.
            if cap != Cap::Butt {
                self.disc(pts[0], h, z, tag);
            }
            return;
        }
        let closed = closed && n > 2;
        let segments = if closed { n } else { n - 1 };
        for i in 0..segments {
            let (mut a, mut b) = (pts[i], pts[(i + 1) % n]);
            let d = (b - a).normalize();
            if !closed && cap == Cap::Square {
                if i == 0 {
                    a -= d * h;
                }
                if i == segments - 1 {
                    b += d * h;
                }
            }
            let side = d.perp() * h;
            self.push([a - side, b - side, b + side, a + side].into_iter(), z, tag);
        }
        // Bends: where the direction turns, a round join closes the wedge
        // the two quads leave open on the outer side.
        let bends = if closed { 0..n } else { 1..n - 1 };
        for i in bends {
            let (prev, next) = (pts[(i + n - 1) % n], pts[(i + 1) % n]);
            let (u, v) = ((pts[i] - prev).normalize(), (next - pts[i]).normalize());
            if turns(u, v) {
                // The signed turn; an exact reversal turns left by π.
                let turn = u.perp_dot(v).atan2(u.dot(v));
                let outer = if turn >= 0.0 { -u.perp() } else { u.perp() };
                self.arc(pts[i], outer, turn, h, true, z, tag);
            }
        }
        if !closed && cap == Cap::Round {
            // Half discs: the other half lies inside the end quads.
            let (first, last) = ((pts[1] - pts[0]).normalize(), (pts[n - 1] - pts[n - 2]).normalize());
            self.arc(pts[0], first.perp(), std::f32::consts::PI, h, false, z, tag);
            self.arc(pts[n - 1], -last.perp(), std::f32::consts::PI, h, false, z, tag);
        }
    }

    /// A round piece of radius `r` about `c`: the arc from the unit vector
    /// `from` turned by `sweep` radians, in steps of at most a disc side
    /// ([`DISC_SIDES`]), closed through `c` (`fan`) or by its chord.
    #[allow(clippy::too_many_arguments)]
    fn arc(&mut self, c: Vec2, from: Vec2, sweep: f32, r: f32, fan: bool, z: f32, tag: TagId) {
        let steps = (sweep.abs() / (std::f32::consts::TAU / DISC_SIDES as f32)).ceil().max(1.0) as usize;
        let corner = |k: usize| c + r * Vec2::from_angle(sweep * k as f32 / steps as f32).rotate(from);
        self.push(fan.then_some(c).into_iter().chain((0..=steps).map(corner)), z, tag);
    }
}

/// Whether the path turns at a point it reaches along `u` and leaves along
/// `v` (unit vectors): where a round join needs its disc.
fn turns(u: Vec2, v: Vec2) -> bool {
    u.perp_dot(v).abs() > 1e-4 || u.dot(v) < 0.0
}

/// Drops the interior points where the path goes straight on (no bend), so
/// a straight run is one quad however many segments drew it: a turtle's
/// `F → FF` draws each branch as 2ⁿ segments in a line. The first and last
/// point stay (a closed path's seam too).
fn straighten(pts: &mut Vec<Vec2>) {
    if pts.len() < 3 {
        return;
    }
    let mut kept = 1;
    for i in 1..pts.len() - 1 {
        let (prev, here, next) = (pts[kept - 1], pts[i], pts[i + 1]);
        if turns((here - prev).normalize(), (next - here).normalize()) {
            pts[kept] = here;
            kept += 1;
        }
    }
    let last = pts[pts.len() - 1];
    pts[kept] = last;
    pts.truncate(kept + 1);
}

/// `points` without consecutive repeats.
fn dedup(points: &[Vec2]) -> Vec<Vec2> {
    let mut out: Vec<Vec2> = Vec::with_capacity(points.len());
    for &p in points {
        if out.last() != Some(&p) {
            out.push(p);
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use genform_core::scene::{Instance, Polyline, Primitive, Tessellation};

    fn line(s: &mut Scene, points: &[(f32, f32)], width: f32, tag: TagId) {
        let points: Vec<Vec3> = points.iter().map(|&(x, y)| Vec3::new(x, y, 0.0)).collect();
        s.polylines.push(Polyline { points: &points, width, tag });
    }

    fn area(scene: &Scene) -> f32 {
        let mut a = 0.0;
        scene.for_each_triangle(Tessellation::default(), |t, _| a += 0.5 * (t[1] - t[0]).cross(t[2] - t[0]).length());
        a
    }

    #[test]
    fn a_stroke_becomes_a_ribbon_of_its_width_facing_plus_z() {
        let mut s = Scene::new();
        let tag = s.tag("ink");
        line(&mut s, &[(0.0, 0.0), (10.0, 0.0)], 0.5, tag);
        let g = drawing_geometry(&s);
        assert!(g.polylines.is_empty());
        // One quad 10 × 0.5 and two round caps of radius 0.25: half
        // octagons outside the quad, so nothing is covered twice.
        assert_eq!(g.polygons.len(), 3);
        let quad = &g.polygons[0];
        assert_eq!(quad.points.len(), 4);
        let (lo, hi) = quad.points.iter().fold((Vec3::MAX, Vec3::MIN), |(l, h), &p| (l.min(p), h.max(p)));
        assert_eq!((lo, hi), (Vec3::new(0.0, -0.25, 0.0), Vec3::new(10.0, 0.25, 0.0)));
        let octagon = 2.0 * 2.0f32.sqrt() * 0.25 * 0.25;
        assert!((area(&g) - (5.0 + octagon)).abs() < 1e-4, "{}", area(&g));
        assert!(g.polygons[1..].iter().all(|p| p.points.len() == 5), "half octagons");
        // Every triangle faces +z.
        g.for_each_triangle(Tessellation::default(), |t, _| assert!((t[1] - t[0]).cross(t[2] - t[0]).z > 0.0));
    }

    #[test]
    fn hairlines_get_a_share_of_the_extent_and_bends_a_disc() {
        let mut s = Scene::new();
        let tag = s.tag("ink");
        line(&mut s, &[(0.0, 0.0), (100.0, 0.0), (100.0, 50.0)], 0.0, tag);
        line(&mut s, &[(20.0, 20.0)], 0.0, tag);
        let g = drawing_geometry(&s);
        // 2 quads, 1 bend, 2 caps, 1 dot.
        assert_eq!(g.polygons.len(), 6);
        // The bend turns left by 90°: a fan of two steps on its outer
        // (right) side, a quarter of the disc.
        let wedge = &g.polygons[2].points;
        assert_eq!(wedge.len(), 4, "{wedge:?}");
        let half = 0.5 * HAIRLINE_SHARE * 100.0;
        let ys: Vec<f32> = g.polygons[0].points.iter().map(|p| p.y).collect();
        assert!(ys.iter().all(|y| (y.abs() - half).abs() < 1e-6), "{ys:?}");
        assert!(g.polygons.iter().all(|p| p.points.iter().all(|q| q.z == 0.0)), "one colour: no lift");
    }

    #[test]
    fn straight_runs_and_continued_polylines_make_one_ribbon() {
        let mut s = Scene::new();
        let (ink, red) = (s.tag("ink"), s.tag("red"));
        // A turtle's `FFF` then a new polyline from its end: one quad for
        // the straight run, one for the turn, a wedge at the bend and caps
        // only at the two real ends.
        line(&mut s, &[(0.0, 0.0), (1.0, 0.0), (2.0, 0.0), (3.0, 0.0)], 0.1, ink);
        line(&mut s, &[(3.0, 0.0), (3.0, 1.0)], 0.1, ink);
        assert_eq!(drawing_geometry(&s).polygons.len(), 2 + 1 + 2);
        // Another width, another tag or a gap starts a ribbon of its own.
        for (width, tag) in [(0.2, ink), (0.1, red)] {
            let mut t = s.clone();
            line(&mut t, &[(3.0, 1.0), (4.0, 1.0)], width, tag);
            assert_eq!(drawing_geometry(&t).polygons.len(), 5 + 3);
        }
        line(&mut s, &[(3.0, 1.5), (4.0, 1.5)], 0.1, ink);
        assert_eq!(drawing_geometry(&s).polygons.len(), 5 + 3);
    }

    #[test]
    fn only_flat_drawings_are_turned() {
        let mut s = Scene::new();
        let tag = s.tag("ink");
        line(&mut s, &[(0.0, 0.0), (1.0, 0.0)], 0.1, tag);
        let mut raised = s.clone();
        raised.polylines.points_mut(0)[1].z = 1.0;
        assert!(matches!(drawing_geometry(&raised), Cow::Borrowed(_)));
        let mut solid = s.clone();
        solid.instances.push(Instance { transform: Default::default(), primitive: Primitive::Box, tag });
        assert!(matches!(drawing_geometry(&solid), Cow::Borrowed(_)));
        assert!(matches!(drawing_geometry(&Scene::new()), Cow::Borrowed(_)));
        assert!(matches!(drawing_geometry(&s), Cow::Owned(_)));
    }

    fn shape(kind: Shape2dKind, attrs: &[(&str, &str)], tag: TagId) -> Shape2d {
        Shape2d { kind, attributes: attrs.iter().map(|(a, b)| (a.to_string(), b.to_string())).collect(), tag }
    }

    #[test]
    fn shapes_keep_their_place_size_and_svg_colours() {
        let mut s = Scene::new();
        let wall = s.tag("wall");
        let rect = Shape2dKind::Rect { min: Vec2::new(2.0, 3.0), size: Vec2::new(4.0, 1.0) };
        s.shapes2d.push(shape(rect, &[("fill", "#8f8f8f"), ("stroke", "red"), ("stroke-width", "0.2")], wall));
        let circle = Shape2dKind::Circle { center: Vec2::new(10.0, 10.0), radius: 1.0 };
        s.shapes2d.push(shape(circle, &[("fill", "#1b4965")], wall));
        // Path data in scene coordinates, y up: a triangle above y = 20.
        let d = "M 0 20 L 4 20 L 2 24 Z".to_string();
        s.shapes2d.push(shape(Shape2dKind::Path { d }, &[("fill", "#00ff00")], wall));
        let g = drawing_geometry(&s);
        let names: Vec<&str> = g.tags.iter().map(|t| t.as_str()).collect();
        assert_eq!(names, ["wall", "wall#8f8f8f", "wall#ff0000", "wall#1b4965", "wall#00ff00"]);
        let of = |tag: &str| {
            let t = g.tags.iter().position(|n| n == tag).unwrap() as TagId;
            let pts: Vec<Vec3> = g.polygons.iter().filter(|p| p.tag == t).flat_map(|p| p.points.clone()).collect();
            pts.iter().fold((Vec3::MAX, Vec3::MIN), |(l, h), &p| (l.min(p), h.max(p)))
        };
        let (lo, hi) = of("wall#8f8f8f");
        assert!(
            (lo.truncate() - Vec2::new(2.0, 3.0)).length() < 1e-4
                && (hi.truncate() - Vec2::new(6.0, 4.0)).length() < 1e-4
        );
        let (lo, hi) = of("wall#ff0000");
        assert!((lo.truncate() - Vec2::new(1.9, 2.9)).length() < 1e-3, "{lo}");
        assert!((hi.truncate() - Vec2::new(6.1, 4.1)).length() < 1e-3, "{hi}");
        assert!(lo.z > 0.0, "the stroke lies above the fill");
        let (lo, hi) = of("wall#1b4965");
        assert!(
            (lo.truncate() - Vec2::splat(9.0)).length() < 1e-3 && (hi.truncate() - Vec2::splat(11.0)).length() < 1e-3
        );
        let (lo, hi) = of("wall#00ff00");
        assert!((lo.truncate() - Vec2::new(0.0, 20.0)).length() < 1e-4, "{lo}");
        assert!((hi.truncate() - Vec2::new(4.0, 24.0)).length() < 1e-4, "{hi}");
        assert_eq!(tag_color("wall#1b4965"), [0x1b, 0x49, 0x65]);
        // Images are not drawn; a drawing of only an image has no geometry.
        let mut img = Scene::new();
        let t = img.tag("pic");
        let kind = Shape2dKind::Image { href: "/etc/passwd".into(), min: Vec2::ZERO, size: Vec2::ONE };
        img.shapes2d.push(shape(kind, &[], t));
        assert!(drawing_geometry(&img).polygons.is_empty());
    }
}
