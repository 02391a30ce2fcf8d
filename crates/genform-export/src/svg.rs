//! SVG line drawings: the scene seen orthographically along −z.

use crate::palette::{edge_color, lighten, tag_color};
use crate::shapes::Shapes;
use genform_core::scene::{Primitive, Scene, Shape2d, Shape2dKind, TagId, Tessellation};
use genform_core::surface::{Surface, SurfaceEdge};
use glam::Vec2;
use std::collections::BTreeMap;
use std::fmt::Write;

/// Settings for [`write_svg`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SvgOptions {
    /// Nominal rendered width in pixels (the `width` attribute); the height
    /// follows the drawing's aspect ratio.
    pub width_px: u32,
    /// The thinnest stroke, in pixels at the nominal width: thinner strokes
    /// (a turtle's width 0 included) are drawn this wide so they stay
    /// visible.
    pub min_stroke_px: f32,
    /// The colour behind the drawing (8-bit sRGB), or `None` for a
    /// transparent background.
    pub background: Option<[u8; 3]>,
}

impl Default for SvgOptions {
    /// 1000 px wide, strokes at least 1 px, white background.
    fn default() -> Self {
        SvgOptions { width_px: 1000, min_stroke_px: 1.0, background: Some([255; 3]) }
    }
}

/// Writes `scene` as an SVG drawing, viewed orthographically onto the xy
/// plane (z is dropped, +y points up).
///
/// The view box fits everything drawn but guides, plus a margin of 3% of
/// the larger extent. Draw order: boundary guides (meshes, each one faint
/// `<path>` of its triangles), instances (their triangles, filled, one `<path>` per
/// tag, faces turned away from the viewer of closed primitives left out),
/// then polygons (one filled `<polygon>` each), then surfaces (per
/// surface a `<path>` of its faces filled in a light shade of the tag
/// colour, earlier surfaces of several paler, then its edges as one
/// `<line>` each, stroked in [`crate::edge_color`] of their type: untyped
/// edges first at the thinnest width, typed ones in ascending type at twice
/// that), then polylines (stroked
/// `<path>`s with round caps and joins, consecutive polylines with the same
/// tag and stroke width sharing one element), each in scene order, so strokes
/// stay on top, and last the 2D shapes ([`Scene::shapes2d`]) in order, one
/// element each (`<line>`, `<circle>`, `<rect>`, `<path>`, `<image>`) with
/// their own attributes (a shape with neither `fill` nor `stroke` gets its
/// tag's colour), and last the point guides as faint `<circle>`s of their
/// radius (at least 3 px), blue for attractors and red for repellers. A stroke is its polyline's width in scene units, never
/// thinner than [`SvgOptions::min_stroke_px`]. Colours are [`tag_color`]s.
/// There is no depth sorting: it is a line-drawing view, not a renderer.
///
/// A scene of 2D shapes only is sized in centimetres, 1 unit = 1 cm
/// (`width="12.5cm"`); any other drawing is [`SvgOptions::width_px`] wide.
///
/// Numbers have a fixed number of decimals, chosen so that about 10⁴–10⁵
/// steps span the drawing; the same scene gives the same bytes. Non-finite
/// points, polylines of fewer than two points and polygons of fewer than
/// three are left out. An empty drawing is a 1×1 view box.
///
/// # Panics
///
/// If an instance refers to a missing mesh asset (see [`crate::export`],
/// which checks). Surfaces naming missing vertices are left out.
pub fn write_svg(scene: &Scene, opts: &SvgOptions) -> String {
    Drawing::new(scene, Tessellation::default()).write(scene, opts)
}

/// Instance triangles projected and the frame around everything drawn:
/// what [`write_svg`] needs before it writes, and what the PNG path needs to
/// choose the nominal width.
pub(crate) struct Drawing {
    /// Per tag, the projected instance triangles (counter-clockwise in xy).
    fills: BTreeMap<TagId, Vec<[Vec2; 3]>>,
    /// The view box in SVG coordinates (y down): top left corner and size.
    origin: Vec2,
    size: Vec2,
    /// Decimals of every coordinate written.
    decimals: usize,
    /// Whether the drawing is only 2D shapes, written at 1 unit = 1 cm.
    physical: bool,
}

impl Drawing {
    /// Projects the instances and measures the drawing.
    pub(crate) fn new(scene: &Scene, tess: Tessellation) -> Drawing {
        let fills = project_instances(scene, tess);
        let mut bounds = Bounds::default();
        fills.values().flatten().flatten().for_each(|&p| bounds.add(p, 0.0));
        for poly in scene.polygons.iter().filter(|p| drawable(&p.points, 3)) {
            poly.points.iter().for_each(|p| bounds.add(p.truncate(), 0.0));
        }
        for line in scene.polylines.iter().filter(|l| drawable(l.points, 2)) {
            let half = if line.width.is_finite() { 0.5 * line.width.max(0.0) } else { 0.0 };
            line.points.iter().for_each(|p| bounds.add(p.truncate(), half));
        }
        // Shapes sharing an attribute list share its stroke width.
        let mut last: Option<(&Shape2d, f32)> = None;
        for shape in &scene.shapes2d {
            let half = match last {
                Some((before, half)) if std::sync::Arc::ptr_eq(&before.attributes, &shape.attributes) => half,
                _ => shapes2d::half_stroke(shape),
            };
            last = Some((shape, half));
            shapes2d::bounds(shape, half, &mut |p, r| bounds.add(p, r));
        }
        for surface in &scene.surfaces {
            surface.positions.iter().filter(|p| p.is_finite()).for_each(|p| bounds.add(p.truncate(), 0.0));
        }
        let (lo, hi) = match (bounds.lo, bounds.hi) {
            (Some(lo), Some(hi)) => (lo, hi),
            _ => (Vec2::ZERO, Vec2::ZERO),
        };
        let extent = (hi - lo).max_element();
        // A lone point or nothing: a unit view around it.
        let margin = if extent > 0.0 && extent.is_finite() { 0.03 * extent } else { 0.5 };
        // SVG's y runs down: the top edge is at −max y.
        let origin = Vec2::new(lo.x - margin, -hi.y - margin);
        let size = (hi - lo) + Vec2::splat(2.0 * margin);
        let decimals = (4 - size.max_element().log10().floor() as i32).clamp(0, 12) as usize;
        let physical = !scene.shapes2d.is_empty()
            && scene.instances.is_empty()
            && scene.polylines.is_empty()
            && scene.polygons.is_empty()
            && scene.surfaces.is_empty();
        Drawing { fills, origin, size, decimals, physical }
    }

    /// The view box in SVG coordinates (y down): top left corner and size.
    pub(crate) fn view(&self) -> (Vec2, Vec2) {
        (self.origin, self.size)
    }

    /// The view box's width over its height.
    pub(crate) fn aspect(&self) -> f32 {
        self.size.x / self.size.y
    }

    /// The SVG text: sized in centimetres (1 unit = 1 cm) when the scene
    /// holds only 2D shapes, else in pixels.
    pub(crate) fn write(&self, scene: &Scene, opts: &SvgOptions) -> String {
        self.write_sized(scene, opts, self.physical)
    }

    /// The SVG text, sized in centimetres when `physical`, else
    /// `opts.width_px` wide.
    pub(crate) fn write_sized(&self, scene: &Scene, opts: &SvgOptions, physical: bool) -> String {
        self.write_pieces(scene, opts, physical, &mut |_| {})
    }

    /// The SVG text ([`Drawing::write`]) written to `sink` piece by piece,
    /// so a drawing of millions of shapes is never held as one text.
    pub(crate) fn write_to(
        &self,
        scene: &Scene,
        opts: &SvgOptions,
        sink: &mut dyn std::io::Write,
    ) -> std::io::Result<()> {
        let mut failed = None;
        let rest = self.write_pieces(scene, opts, self.physical, &mut |out| {
            if out.len() >= PIECE {
                if failed.is_none() {
                    failed = sink.write_all(out.as_bytes()).err();
                }
                out.clear();
            }
        });
        match failed {
            Some(e) => Err(e),
            None => sink.write_all(rest.as_bytes()),
        }
    }

    /// Writes the text; `spill` is offered the text so far after every 2D
    /// shape (the one part that grows with the model) and may take it;
    /// returns what is left.
    fn write_pieces(
        &self,
        scene: &Scene,
        opts: &SvgOptions,
        physical: bool,
        spill: &mut dyn FnMut(&mut String),
    ) -> String {
        let mut w = Writer { out: String::new(), decimals: self.decimals };
        let width_px = opts.width_px.max(1);
        let height_px = ((width_px as f32 / self.aspect()).round() as u32).max(1);
        w.out.push_str("<svg xmlns=\"http://www.w3.org/2000/svg\"");
        if physical {
            w.out.push_str(" width=\"");
            w.num(self.size.x);
            w.out.push_str("cm\" height=\"");
            w.num(self.size.y);
            w.out.push_str("cm\" viewBox=\"");
        } else {
            let _ = write!(w.out, " width=\"{width_px}\" height=\"{height_px}\" viewBox=\"");
        }
        w.point(self.origin);
        w.out.push(' ');
        w.point(self.size);
        w.out.push_str("\">\n");
        if let Some(bg) = opts.background {
            w.out.push_str("<rect x=\"");
            w.num(self.origin.x);
            w.out.push_str("\" y=\"");
            w.num(self.origin.y);
            w.out.push_str("\" width=\"");
            w.num(self.size.x);
            w.out.push_str("\" height=\"");
            w.num(self.size.y);
            let _ = writeln!(w.out, "\" fill=\"{}\"/>", hex(bg));
        }
        let color = |tag: TagId| scene.tags.get(tag as usize).map_or([128; 3], |t| tag_color(t));
        // The thinnest stroke, in scene units.
        let floor = opts.min_stroke_px.max(0.0) * self.size.x / width_px as f32;
        guides::write_meshes(&mut w, scene);

        for (&tag, tris) in &self.fills {
            let _ = write!(w.out, "<path fill=\"{}\" d=\"", hex(color(tag)));
            for t in tris {
                // Flipped y reverses the winding, the same for all: nonzero
                // filling then gives their union.
                let [a, b, c] = t.map(flip);
                w.out.push('M');
                w.point(a);
                w.out.push('L');
                w.point(b);
                w.out.push(' ');
                w.point(c);
                w.out.push('Z');
            }
            w.out.push_str("\"/>\n");
        }

        for poly in scene.polygons.iter().filter(|p| drawable(&p.points, 3)) {
            let _ = write!(w.out, "<polygon fill=\"{}\" points=\"", hex(color(poly.tag)));
            for (i, p) in poly.points.iter().enumerate() {
                if i > 0 {
                    w.out.push(' ');
                }
                w.point(flip(p.truncate()));
            }
            w.out.push_str("\"/>\n");
        }

        let n = scene.surfaces.len();
        for (k, surface) in scene.surfaces.iter().enumerate() {
            let pale = if n > 1 { 0.4 * (n - 1 - k) as f32 / (n - 1) as f32 } else { 0.0 };
            write_surface(&mut w, surface, lighten(color(surface.tag), 0.45 + pale), floor);
        }

        // Strokes: consecutive polylines with the same tag and written width
        // share one path.
        let mut open: Option<(TagId, String)> = None;
        for line in scene.polylines.iter().filter(|l| drawable(l.points, 2)) {
            let width = if line.width.is_finite() { line.width.max(floor) } else { floor };
            let width = w.format(width, self.decimals + 2);
            if open.as_ref().is_none_or(|(tag, wd)| *tag != line.tag || *wd != width) {
                if open.is_some() {
                    w.out.push_str("\"/>\n");
                }
                let _ = write!(
                    w.out,
                    "<path fill=\"none\" stroke=\"{}\" stroke-width=\"{width}\" stroke-linecap=\"round\" \
                     stroke-linejoin=\"round\" d=\"",
                    hex(color(line.tag))
                );
                open = Some((line.tag, width));
            }
            w.run(line.points.iter().map(|p| flip(p.truncate())));
        }
        if open.is_some() {
            w.out.push_str("\"/>\n");
        }
        // Each tag's colour text once, not once per shape.
        let defaults: Vec<String> = scene.tags.iter().map(|t| hex(tag_color(t))).collect();
        let unknown = hex([0; 3]);
        let mut tail = shapes2d::Tail::default();
        for shape in &scene.shapes2d {
            let default = defaults.get(shape.tag as usize).unwrap_or(&unknown);
            shapes2d::write(&mut w, &mut tail, shape, default);
            spill(&mut w.out);
        }
        guides::write_points(&mut w, scene, 3.0 * floor.max(self.size.x / width_px as f32));
        w.out.push_str("</svg>\n");
        w.out
    }
}

/// One 2D shape as a standalone SVG document in scene units with y
/// flipped (SVG y runs down), exactly as [`write_svg`] writes the element;
/// the drawing-to-geometry conversion parses it with usvg. `color` stands
/// in when the shape has neither fill nor stroke.
pub(crate) fn shape_document(shape: &Shape2d, color: [u8; 3]) -> String {
    let mut w = Writer { out: String::new(), decimals: 6 };
    // No view box: usvg then applies no transform of its own, and keeps
    // elements outside the 1×1 viewport (only rendering clips).
    w.out.push_str("<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"1\" height=\"1\">\n");
    shapes2d::write(&mut w, &mut shapes2d::Tail::default(), shape, &hex(color));
    w.out.push_str("</svg>\n");
    w.out
}

/// A surface seen from +z: its faces as one filled path (each face turned
/// counter-clockwise, so the fill is their union), then its edges as lines,
/// untyped first and thinnest.
fn write_surface(w: &mut Writer, s: &Surface, fill: [u8; 3], floor: f32) {
    if !s.positions.iter().all(|p| p.is_finite()) || !crate::surfaces::well_formed(s) {
        return;
    }
    let mut d = Writer { out: String::new(), decimals: w.decimals };
    let mut pts: Vec<Vec2> = Vec::new();
    for face in s.faces() {
        pts.clear();
        pts.extend(face.iter().map(|&v| s.positions[v as usize].truncate()));
        let area: f32 = (0..pts.len()).map(|i| pts[i].perp_dot(pts[(i + 1) % pts.len()])).sum();
        if area == 0.0 || !area.is_finite() {
            continue;
        }
        if area < 0.0 {
            pts.reverse();
        }
        d.run(pts.iter().map(|&p| flip(p)));
        d.out.push('Z');
    }
    if !d.out.is_empty() {
        let _ = writeln!(w.out, "<path fill=\"{}\" d=\"{}\"/>", hex(fill), d.out);
    }
    let groups = crate::surfaces::edges_by_type(s);
    let untyped = groups.get(&SurfaceEdge::UNTYPED).into_iter().map(|e| (SurfaceEdge::UNTYPED, e));
    let typed = groups.iter().filter(|(k, _)| **k != SurfaceEdge::UNTYPED).map(|(&k, e)| (k, e));
    for (kind, pairs) in untyped.chain(typed) {
        let width = w.format(if kind == SurfaceEdge::UNTYPED { floor } else { 2.0 * floor }, w.decimals + 2);
        let stroke = hex(edge_color(kind));
        for &[a, b] in pairs {
            let (a, b) = (flip(s.positions[a as usize].truncate()), flip(s.positions[b as usize].truncate()));
            w.line_open(a, b);
            let _ = writeln!(w.out, "\" stroke=\"{stroke}\" stroke-width=\"{width}\" stroke-linecap=\"round\"/>");
        }
    }
}

/// Guides, faint: boundary meshes under everything, points over it.
mod guides {
    use crate::palette::guide_color;
    use crate::svg::{Writer, flip, hex};
    use genform_core::scene::Scene;
    use genform_core::surface::GuideKind;
    use glam::Vec2;
    use std::fmt::Write;

    fn tag(scene: &Scene, tag: u32) -> &str {
        scene.tags.get(tag as usize).map_or("", String::as_str)
    }

    /// Each mesh guide as one path of its projected triangles (turned
    /// counter-clockwise, so the fill is their union), fill opacity 0.2.
    pub(super) fn write_meshes(w: &mut Writer, scene: &Scene) {
        for g in &scene.guides {
            let GuideKind::Mesh(mesh) = &g.kind else { continue };
            let mut d = Writer { out: String::new(), decimals: w.decimals };
            for t in &mesh.triangles {
                let Some(pts) = t
                    .iter()
                    .map(|&v| mesh.positions.get(v as usize).map(|p| p.truncate()))
                    .collect::<Option<Vec<Vec2>>>()
                else {
                    continue;
                };
                let area = (pts[1] - pts[0]).perp_dot(pts[2] - pts[0]);
                if area == 0.0 || !area.is_finite() {
                    continue;
                }
                let order = if area > 0.0 { [0, 1, 2] } else { [0, 2, 1] };
                d.run(order.iter().map(|&i| flip(pts[i])));
                d.out.push('Z');
            }
            if !d.out.is_empty() {
                let color = hex(guide_color(tag(scene, g.tag)));
                let _ = writeln!(w.out, "<path fill=\"{color}\" fill-opacity=\"0.2\" d=\"{}\"/>", d.out);
            }
        }
    }

    /// Each point guide as a circle of its radius (at least `min_radius`),
    /// half-transparent fill, outlined.
    pub(super) fn write_points(w: &mut Writer, scene: &Scene, min_radius: f32) {
        for g in &scene.guides {
            let GuideKind::Point { at, radius } = g.kind else { continue };
            if !(at.is_finite() && radius.is_finite()) {
                continue;
            }
            let c = flip(at.truncate());
            let color = hex(guide_color(tag(scene, g.tag)));
            w.out.push_str("<circle cx=\"");
            w.num(c.x);
            w.out.push_str("\" cy=\"");
            w.num(c.y);
            w.out.push_str("\" r=\"");
            w.num(radius.abs().max(min_radius));
            let stroke = w.format(min_radius / 3.0, w.decimals + 2);
            let _ = writeln!(
                w.out,
                "\" fill=\"{color}\" fill-opacity=\"0.45\" stroke=\"{color}\" stroke-opacity=\"0.8\" stroke-width=\"{stroke}\"/>"
            );
        }
    }
}

/// At least `min` points, all finite.
fn drawable(points: &[glam::Vec3], min: usize) -> bool {
    points.len() >= min && points.iter().all(|p| p.is_finite())
}

/// Scene xy → SVG user coordinates (y down).
fn flip(p: Vec2) -> Vec2 {
    Vec2::new(p.x, -p.y)
}

fn hex([r, g, b]: [u8; 3]) -> String {
    format!("#{r:02x}{g:02x}{b:02x}")
}

/// Every instance's triangles projected onto xy, per tag, turned
/// counter-clockwise; zero-area ones dropped. Closed primitives keep only
/// the faces toward +z: the others lie under them.
fn project_instances(scene: &Scene, tess: Tessellation) -> BTreeMap<TagId, Vec<[Vec2; 3]>> {
    let mut fills: BTreeMap<TagId, Vec<[Vec2; 3]>> = BTreeMap::new();
    if scene.instances.is_empty() {
        return fills;
    }
    let shapes = Shapes::new(scene, tess);
    let mut verts = Vec::new();
    for (i, inst) in scene.instances.iter().enumerate() {
        let mesh = shapes.of(i);
        verts.clear();
        verts.extend(mesh.positions.iter().map(|&p| inst.transform.transform_point3(p)));
        let closed = !matches!(inst.primitive, Primitive::Mesh(_));
        let flip = inst.transform.matrix3.determinant() < 0.0;
        let out = fills.entry(inst.tag).or_default();
        for t in &mesh.triangles {
            let [a, b, c] = t.map(|v| verts[v as usize]);
            if !(a.is_finite() && b.is_finite() && c.is_finite()) {
                continue;
            }
            let [a, b, c] = [a, b, c].map(|p| p.truncate());
            // Outward winding first, as in `Scene::for_each_triangle`.
            let (b, c) = if flip { (c, b) } else { (b, c) };
            let area = (b - a).perp_dot(c - a);
            if area > 0.0 {
                out.push([a, b, c]);
            } else if area < 0.0 && !closed {
                out.push([a, c, b]);
            }
        }
    }
    fills.retain(|_, t| !t.is_empty());
    fills
}

/// Bounds of points, each widened by a radius.
#[derive(Default)]
struct Bounds {
    lo: Option<Vec2>,
    hi: Option<Vec2>,
}

impl Bounds {
    fn add(&mut self, p: Vec2, r: f32) {
        self.lo = Some(self.lo.map_or(p - r, |lo| lo.min(p - r)));
        self.hi = Some(self.hi.map_or(p + r, |hi| hi.max(p + r)));
    }
}

/// The SVG text with its number format.
/// Text gathered before [`Drawing::write_to`] hands it on.
const PIECE: usize = 1 << 16;

struct Writer {
    out: String,
    decimals: usize,
}

impl Writer {
    /// `v` with `decimals` decimals, trailing zeros trimmed, never `-0`.
    fn format(&self, v: f32, decimals: usize) -> String {
        crate::fixed::fixed(v, decimals)
    }

    fn num(&mut self, v: f32) {
        crate::fixed::push_fixed(&mut self.out, v, self.decimals);
    }

    /// `<line x1="…" y1="…" x2="…" y2="…` (attributes still open).
    fn line_open(&mut self, a: Vec2, b: Vec2) {
        self.out.push_str("<line x1=\"");
        self.num(a.x);
        self.out.push_str("\" y1=\"");
        self.num(a.y);
        self.out.push_str("\" x2=\"");
        self.num(b.x);
        self.out.push_str("\" y2=\"");
        self.num(b.y);
    }

    fn point(&mut self, p: Vec2) {
        self.num(p.x);
        self.out.push(' ');
        self.num(p.y);
    }

    /// One `M…L…` run; points that print the same as the one before are
    /// skipped, but a run keeps at least one segment (a dot, with round
    /// caps).
    fn run(&mut self, points: impl Iterator<Item = Vec2>) {
        let (mut last, mut s) = (String::new(), String::new());
        let mut n = 0;
        for p in points {
            s.clear();
            crate::fixed::push_fixed(&mut s, p.x, self.decimals);
            s.push(' ');
            crate::fixed::push_fixed(&mut s, p.y, self.decimals);
            if s == last {
                continue;
            }
            self.out.push(match n {
                0 => 'M',
                1 => 'L',
                _ => ' ',
            });
            self.out.push_str(&s);
            std::mem::swap(&mut last, &mut s);
            n += 1;
        }
        if n == 1 {
            self.out.push('L');
            self.out.push_str(&last);
        }
    }
}

/// 2D shapes: their extent and their SVG elements.
mod shapes2d {
    use crate::svg::{Shape2d, Shape2dKind, Vec2, Writer, flip};
    use std::fmt::Write;
    use std::sync::Arc;

    /// The value of presentation attribute `name`.
    fn attr<'a>(shape: &'a Shape2d, name: &str) -> Option<&'a str> {
        shape.attributes.iter().find(|(n, _)| n == name).map(|(_, v)| v.as_str())
    }

    /// Half the stroke width, when the shape is stroked.
    pub(super) fn half_stroke(shape: &Shape2d) -> f32 {
        if attr(shape, "stroke").is_none_or(|s| s == "none") {
            return 0.0;
        }
        let w = attr(shape, "stroke-width").and_then(|w| w.trim().parse::<f32>().ok()).unwrap_or(1.0);
        if w.is_finite() { 0.5 * w.max(0.0) } else { 0.0 }
    }

    fn finite(shape: &Shape2d) -> bool {
        match &shape.kind {
            Shape2dKind::Line { from, to } => from.is_finite() && to.is_finite(),
            Shape2dKind::Circle { center, radius } => center.is_finite() && radius.is_finite(),
            Shape2dKind::Rect { min, size } | Shape2dKind::Image { min, size, .. } => {
                min.is_finite() && size.is_finite()
            }
            Shape2dKind::Path { d } => path_points(d).iter().all(|p| p.is_finite()),
        }
    }

    /// Calls `add(point, radius)` for points whose discs cover the shape;
    /// `h`: its [`half_stroke`].
    pub(super) fn bounds(shape: &Shape2d, h: f32, add: &mut dyn FnMut(Vec2, f32)) {
        if !finite(shape) {
            return;
        }
        match &shape.kind {
            Shape2dKind::Line { from, to } => {
                add(*from, h);
                add(*to, h);
            }
            Shape2dKind::Circle { center, radius } => add(*center, radius.abs() + h),
            Shape2dKind::Rect { min, size } | Shape2dKind::Image { min, size, .. } => {
                add(*min, h);
                add(*min + *size, h);
            }
            Shape2dKind::Path { d } => path_points(d).into_iter().for_each(|p| add(p, h)),
        }
    }

    /// Appends `s` with `&`, `<`, `>` and `"` escaped (no allocation: a
    /// drawing of a graph grammar writes millions of attribute values).
    fn push_escaped(out: &mut String, s: &str) {
        for c in s.chars() {
            match c {
                '&' => out.push_str("&amp;"),
                '<' => out.push_str("&lt;"),
                '>' => out.push_str("&gt;"),
                '"' => out.push_str("&quot;"),
                c => out.push(c),
            }
        }
    }

    fn valid_name(n: &str) -> bool {
        !n.is_empty() && n.chars().all(|c| c.is_ascii_alphanumeric() || matches!(c, '-' | '_' | ':' | '.'))
    }

    /// Writes one shape; `color` stands in when it has neither fill nor
    /// stroke.
    pub(super) fn write(w: &mut Writer, tail: &mut Tail, shape: &Shape2d, color: &str) {
        if !finite(shape) {
            return;
        }
        let open_line = matches!(shape.kind, Shape2dKind::Line { .. } | Shape2dKind::Path { .. });
        match &shape.kind {
            Shape2dKind::Line { from, to } => {
                let (a, b) = (flip(*from), flip(*to));
                w.line_open(a, b);
                w.out.push('"');
            }
            Shape2dKind::Circle { center, radius } => {
                let c = flip(*center);
                w.out.push_str("<circle cx=\"");
                w.num(c.x);
                w.out.push_str("\" cy=\"");
                w.num(c.y);
                w.out.push_str("\" r=\"");
                w.num(radius.abs());
                w.out.push('"');
            }
            Shape2dKind::Rect { min, size } | Shape2dKind::Image { min, size, .. } => {
                let image = matches!(shape.kind, Shape2dKind::Image { .. });
                w.out.push_str(if image { "<image" } else { "<rect" });
                if let Shape2dKind::Image { href, .. } = &shape.kind {
                    w.out.push_str(" href=\"");
                    push_escaped(&mut w.out, href);
                    w.out.push_str("\" preserveAspectRatio=\"none\"");
                }
                // The top edge in SVG's y-down frame.
                w.out.push_str(" x=\"");
                w.num(min.x);
                w.out.push_str("\" y=\"");
                w.num(-(min.y + size.y));
                w.out.push_str("\" width=\"");
                w.num(size.x.abs());
                w.out.push_str("\" height=\"");
                w.num(size.y.abs());
                w.out.push('"');
            }
            Shape2dKind::Path { d } => {
                // Path data stays in scene coordinates; the transform flips y.
                w.out.push_str("<path transform=\"scale(1 -1)\" d=\"");
                push_escaped(&mut w.out, d);
                w.out.push('"');
            }
        }
        let cached = tail.list.as_ref().is_some_and(|list| Arc::ptr_eq(list, &shape.attributes))
            && tail.open_line == open_line
            && tail.color == color;
        if !cached {
            tail.text.clear();
            write_tail(&mut tail.text, shape, open_line, color);
            tail.list = Some(shape.attributes.clone());
            (tail.open_line, tail.color) = (open_line, color.to_string());
        }
        w.out.push_str(&tail.text);
    }

    /// The text after a shape's geometry, written once per attribute list:
    /// most shapes of a drawing share a few lists.
    #[derive(Default)]
    pub(super) struct Tail {
        /// The attribute list, whether the shape is an open line and the
        /// stand-in colour that `text` was written for.
        list: Option<Arc<[(String, String)]>>,
        open_line: bool,
        color: String,
        text: String,
    }

    /// The default paint, the presentation attributes and the end of the
    /// element.
    fn write_tail(out: &mut String, shape: &Shape2d, open_line: bool, color: &str) {
        let has = |n: &str| attr(shape, n).is_some();
        if !has("fill") && !has("stroke") {
            if open_line {
                let _ = write!(out, " fill=\"none\" stroke=\"{color}\"");
            } else {
                let _ = write!(out, " fill=\"{color}\"");
            }
        }
        for (n, v) in shape.attributes.iter() {
            if valid_name(n) {
                let _ = write!(out, " {n}=\"");
                push_escaped(out, v);
                out.push('"');
            }
        }
        out.push_str("/>\n");
    }

    /// The points an SVG path visits, control points included (arcs add
    /// their end points widened by their radii): a box around them covers
    /// the path. Relative commands are resolved; malformed data ends the
    /// list where it breaks.
    pub(super) fn path_points(d: &str) -> Vec<Vec2> {
        let mut t = Tokens { s: d.as_bytes(), i: 0 };
        let mut out = Vec::new();
        let (mut cur, mut start) = (Vec2::ZERO, Vec2::ZERO);
        // Path data must start with a command.
        let mut cmd = b'?';
        loop {
            t.skip();
            let Some(&c) = t.s.get(t.i) else { break };
            if c.is_ascii_alphabetic() {
                cmd = c;
                t.i += 1;
                if matches!(cmd, b'Z' | b'z') {
                    cur = start;
                    continue;
                }
            } else if matches!(cmd, b'Z' | b'z') {
                break;
            }
            let rel = cmd.is_ascii_lowercase();
            let base = if rel { cur } else { Vec2::ZERO };
            let pt = |t: &mut Tokens| -> Option<Vec2> { Some(base + Vec2::new(t.num()?, t.num()?)) };
            let ok = match cmd.to_ascii_uppercase() {
                b'M' | b'L' | b'T' => pt(&mut t).map(|p| {
                    out.push(p);
                    if cmd.eq_ignore_ascii_case(&b'M') {
                        start = p;
                        // Later pairs of a moveto are linetos.
                        cmd = if rel { b'l' } else { b'L' };
                    }
                    cur = p;
                }),
                b'H' => t.num().map(|x| {
                    cur.x = if rel { cur.x + x } else { x };
                    out.push(cur);
                }),
                b'V' => t.num().map(|y| {
                    cur.y = if rel { cur.y + y } else { y };
                    out.push(cur);
                }),
                b'C' => (|| {
                    let (a, b, c) = (pt(&mut t)?, pt(&mut t)?, pt(&mut t)?);
                    out.extend([a, b, c]);
                    cur = c;
                    Some(())
                })(),
                b'S' | b'Q' => (|| {
                    let (a, b) = (pt(&mut t)?, pt(&mut t)?);
                    out.extend([a, b]);
                    cur = b;
                    Some(())
                })(),
                b'A' => (|| {
                    let (rx, ry) = (t.num()?.abs(), t.num()?.abs());
                    let _rotation = t.num()?;
                    let (_large, _sweep) = (t.flag()?, t.flag()?);
                    let end = base + Vec2::new(t.num()?, t.num()?);
                    let r = Vec2::new(rx, ry).max_element();
                    for p in [cur, end] {
                        out.extend([p - Vec2::splat(r), p + Vec2::splat(r)]);
                    }
                    out.push(end);
                    cur = end;
                    Some(())
                })(),
                _ => None,
            };
            if ok.is_none() {
                break;
            }
        }
        out
    }

    struct Tokens<'a> {
        s: &'a [u8],
        i: usize,
    }

    impl Tokens<'_> {
        fn skip(&mut self) {
            while self.s.get(self.i).is_some_and(|c| c.is_ascii_whitespace() || *c == b',') {
                self.i += 1;
            }
        }

        fn num(&mut self) -> Option<f32> {
            self.skip();
            let start = self.i;
            let s = self.s;
            let mut j = self.i;
            if j < s.len() && matches!(s[j], b'+' | b'-') {
                j += 1;
            }
            let mut dot = false;
            while j < s.len() && (s[j].is_ascii_digit() || (s[j] == b'.' && !dot)) {
                dot |= s[j] == b'.';
                j += 1;
            }
            if j < s.len() && matches!(s[j], b'e' | b'E') {
                let mut k = j + 1;
                if k < s.len() && matches!(s[k], b'+' | b'-') {
                    k += 1;
                }
                if k < s.len() && s[k].is_ascii_digit() {
                    while k < s.len() && s[k].is_ascii_digit() {
                        k += 1;
                    }
                    j = k;
                }
            }
            let v = std::str::from_utf8(&s[start..j]).ok()?.parse().ok()?;
            self.i = j;
            Some(v)
        }

        fn flag(&mut self) -> Option<bool> {
            self.skip();
            let c = *self.s.get(self.i)?;
            self.i += 1;
            match c {
                b'0' => Some(false),
                b'1' => Some(true),
                _ => None,
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{ExportError, ExportOptions, Format, export, test_scenes};
    use genform_core::scene::{Instance, Polygon, Polyline, Shape2d, Shape2dKind};
    use glam::{Affine3A, Vec3};

    fn line(s: &mut Scene, points: &[(f32, f32)], width: f32, tag: TagId) {
        let points: Vec<Vec3> = points.iter().map(|&(x, y)| Vec3::new(x, y, 0.0)).collect();
        s.polylines.push(Polyline { points: &points, width, tag });
    }

    /// The value of the first `name="…"` attribute at or after `from`.
    fn attr<'a>(svg: &'a str, name: &str) -> &'a str {
        let key = format!(" {name}=\"");
        let start = svg.find(&key).unwrap_or_else(|| panic!("no {name} in {svg}")) + key.len();
        &svg[start..start + svg[start..].find('"').unwrap()]
    }

    fn numbers(s: &str) -> Vec<f32> {
        s.split(|c: char| !(c.is_ascii_digit() || c == '.' || c == '-'))
            .filter(|t| !t.is_empty())
            .map(|t| t.parse().unwrap())
            .collect()
    }

    #[test]
    fn output_is_deterministic_and_parses() {
        let s = test_scenes::mixed();
        let svg = write_svg(&s, &SvgOptions::default());
        assert_eq!(svg, write_svg(&s.clone(), &SvgOptions::default()));
        assert!(svg.starts_with("<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"1000\""), "{svg}");
        assert!(svg.ends_with("</svg>\n"));
        let tree = resvg::usvg::Tree::from_str(&svg, &resvg::usvg::Options::default()).unwrap();
        assert_eq!(tree.size().width(), 1000.0);
        // Every number is compact: no negative zero, no trailing zeros.
        for token in svg.split(|c: char| !(c.is_ascii_digit() || c == '.' || c == '-')) {
            assert!(token != "-0" && !(token.contains('.') && token.ends_with('0')), "`{token}`");
        }
    }

    #[test]
    fn view_box_fits_with_a_margin_and_y_points_up() {
        let mut s = Scene::new();
        let tag = s.tag("stem");
        line(&mut s, &[(0.0, 0.0), (2.0, 1.0)], 0.0, tag);
        let svg = write_svg(&s, &SvgOptions::default());
        // Extent 2, margin 0.06; the top edge is at −(1 + 0.06).
        assert_eq!(attr(&svg, "viewBox"), "-0.06 -1.06 2.12 1.12");
        assert_eq!(attr(&svg, "height"), "528");
        // y = +1 is drawn above y = 0 (smaller SVG y).
        let d = numbers(attr(&svg, "d"));
        assert_eq!(d, [0.0, 0.0, 2.0, -1.0]);
        // The background covers the view box.
        assert!(svg.contains("<rect x=\"-0.06\" y=\"-1.06\" width=\"2.12\" height=\"1.12\" fill=\"#ffffff\"/>"));
        let no_bg = write_svg(&s, &SvgOptions { background: None, ..Default::default() });
        assert!(!no_bg.contains("<rect"));
    }

    #[test]
    fn a_lone_point_gets_a_unit_view_and_a_dot() {
        let mut s = Scene::new();
        let tag = s.tag("dot");
        line(&mut s, &[(3.0, -2.0), (3.0, -2.0)], 0.0, tag);
        let svg = write_svg(&s, &SvgOptions::default());
        assert_eq!(attr(&svg, "viewBox"), "2.5 1.5 1 1");
        assert_eq!(attr(&svg, "d"), "M3 2L3 2");
    }

    #[test]
    fn strokes_keep_their_width_with_a_floor_and_group_by_tag_and_width() {
        let mut s = Scene::new();
        let (a, b) = (s.tag("a"), s.tag("b"));
        line(&mut s, &[(0.0, 0.0), (10.0, 0.0)], 0.0, a);
        line(&mut s, &[(0.0, 1.0), (10.0, 1.0)], 0.0, a);
        line(&mut s, &[(0.0, 2.0), (10.0, 2.0)], 0.5, a);
        line(&mut s, &[(0.0, 3.0), (10.0, 3.0)], 0.5, b);
        line(&mut s, &[(0.0, 4.0), (10.0, 4.0)], 0.5, b);
        let svg = write_svg(&s, &SvgOptions { width_px: 500, ..Default::default() });
        let paths: Vec<&str> = svg.lines().filter(|l| l.starts_with("<path")).collect();
        assert_eq!(paths.len(), 3, "{svg}");
        // Extent 10 + 2·0.25 (round caps of the thick lines), view box
        // 1.06 times that: 1 px of 500 is 0.02226 units.
        assert_eq!(attr(paths[0], "stroke-width"), "0.02226");
        assert_eq!(attr(paths[0], "d").matches('M').count(), 2);
        assert_eq!(attr(paths[1], "stroke-width"), "0.5");
        assert_eq!(attr(paths[2], "d").matches('M').count(), 2);
        assert_eq!(attr(paths[0], "stroke"), attr(paths[1], "stroke"));
        assert_ne!(attr(paths[1], "stroke"), attr(paths[2], "stroke"));
        assert!(paths.iter().all(|p| p.contains("stroke-linecap=\"round\" stroke-linejoin=\"round\"")));
    }

    #[test]
    fn instances_fill_one_path_per_tag_under_polygons_and_strokes() {
        let s = test_scenes::mixed();
        let svg = write_svg(&s, &SvgOptions::default());
        let lines: Vec<&str> = svg.lines().collect();
        let fills: Vec<usize> = (0..lines.len()).filter(|&i| lines[i].starts_with("<path fill=\"#")).collect();
        assert_eq!(fills.len(), 3, "one per instance tag");
        let polygon = lines.iter().position(|l| l.starts_with("<polygon")).unwrap();
        let stroke = lines.iter().position(|l| l.contains("stroke=")).unwrap();
        assert!(fills.iter().all(|&i| i < polygon) && polygon < stroke);
        let trunk = format!("\"{}\"", hex(tag_color("trunk")));
        assert!(lines[stroke].contains(&format!("stroke={trunk}")));
        assert!(lines[polygon].contains(&format!("fill=\"{}\"", hex(tag_color("roof tile")))));

        // A box seen from +z: its front face only (two triangles).
        let mut s = Scene::new();
        let tag = s.tag("box#102030");
        s.instances.push(Instance { transform: Affine3A::IDENTITY, primitive: Primitive::Box, tag });
        let svg = write_svg(&s, &SvgOptions::default());
        assert_eq!(attr(&svg, "d"), "M0.5 0.5L0.5 -0.5 -0.5 -0.5ZM0.5 0.5L-0.5 -0.5 -0.5 0.5Z");
        assert!(svg.contains("fill=\"#102030\""));
    }

    #[test]
    fn polygons_are_filled_outlines() {
        let mut s = Scene::new();
        let tag = s.tag("leaf#3a7d23");
        let pts = [(0.0, 0.0), (2.0, 0.0), (2.0, 1.0), (1.0, 1.0), (1.0, 2.0), (0.0, 2.0)];
        s.polygons.push(Polygon { points: pts.iter().map(|&(x, y)| Vec3::new(x, y, 5.0)).collect(), tag });
        let svg = write_svg(&s, &SvgOptions::default());
        assert!(svg.contains("<polygon fill=\"#3a7d23\" points=\"0 0 2 0 2 -1 1 -1 1 -2 0 -2\"/>"), "{svg}");
    }

    fn shape(kind: Shape2dKind, attributes: &[(&str, &str)], tag: TagId) -> Shape2d {
        Shape2d { kind, attributes: attributes.iter().map(|(k, v)| (k.to_string(), v.to_string())).collect(), tag }
    }

    #[test]
    fn shapes_sharing_attribute_lists_are_written_as_each_alone() {
        use glam::Vec2;
        use std::sync::Arc;
        type List = Arc<[(String, String)]>;
        let list =
            |pairs: &[(&str, &str)]| -> List { pairs.iter().map(|(k, v)| (k.to_string(), v.to_string())).collect() };
        let mut s = Scene::new();
        let (ink, leaf) = (s.tag("ink"), s.tag("leaf#3a7d23"));
        let lists = [list(&[("stroke", "#123"), ("stroke-width", "2")]), list(&[("fill", "a<b")]), list(&[])];
        // Lists shared and alternating, one list under two tags (two
        // stand-in colours), one list on open and on closed shapes.
        for i in 0..24 {
            let from = Vec2::new(i as f32, 0.0);
            let kind = match i % 3 {
                0 => Shape2dKind::Circle { center: from, radius: 1.0 },
                _ => Shape2dKind::Line { from, to: from + Vec2::ONE },
            };
            let attributes = lists[[0, 1, 2, 2, 2][i % 5]].clone();
            s.shapes2d.push(Shape2d { kind, attributes, tag: if i / 2 % 2 == 0 { ink } else { leaf } });
        }
        let svg = write_svg(&s, &SvgOptions::default());
        let drawn: Vec<&str> = svg.lines().filter(|l| l.starts_with("<line") || l.starts_with("<circle")).collect();
        assert_eq!(drawn.len(), s.shapes2d.len());
        for (shape, written) in s.shapes2d.iter().zip(drawn) {
            let alone = shape_document(shape, tag_color(&s.tags[shape.tag as usize]));
            assert_eq!(alone.lines().nth(1), Some(written));
        }
        assert!(
            svg.contains(" fill=\"none\" stroke=\"#3a7d23\"/>")
                && svg.contains("<circle cx=\"0\" cy=\"0\" r=\"1\" stroke=\"#123\"")
        );
    }

    #[test]
    fn a_drawing_written_in_pieces_has_the_same_bytes() {
        use glam::Vec2;
        let mut s = Scene::new();
        let ink = s.tag("ink");
        for i in 0..5000 {
            let from = Vec2::new(i as f32 * 0.01, (i % 7) as f32);
            s.shapes2d.push(shape(Shape2dKind::Line { from, to: from + Vec2::ONE }, &[("stroke", "#000")], ink));
        }
        let opts = crate::ExportOptions::default();
        let whole = crate::export(&s, crate::Format::Svg, &opts).unwrap();
        assert!(whole.len() > 3 * PIECE, "several pieces: {}", whole.len());
        let mut pieces = Vec::new();
        crate::export_to(&s, crate::Format::Svg, &opts, &mut pieces).unwrap();
        assert_eq!(pieces, whole);
        // A refused scene writes nothing.
        let mut none = Vec::new();
        let err = crate::export_to(&Scene::new(), crate::Format::Svg, &opts, &mut none).unwrap_err();
        assert!(matches!(err, crate::ExportError::EmptyScene(_)) && none.is_empty(), "{err}");
        // A failing sink is an error, not a panic.
        struct Full;
        impl std::io::Write for Full {
            fn write(&mut self, _: &[u8]) -> std::io::Result<usize> {
                Err(std::io::Error::other("disk full"))
            }
            fn flush(&mut self) -> std::io::Result<()> {
                Ok(())
            }
        }
        let err = crate::export_to(&s, crate::Format::Svg, &opts, &mut Full).unwrap_err();
        assert_eq!(err.to_string(), "disk full");
    }

    #[test]
    fn shapes2d_are_drawn_in_centimetres_with_y_up() {
        use glam::Vec2;
        let mut s = Scene::new();
        let (ink, leaf) = (s.tag("ink"), s.tag("leaf#3a7d23"));
        s.shapes2d.push(shape(
            Shape2dKind::Line { from: Vec2::ZERO, to: Vec2::new(10.0, 0.0) },
            &[("stroke", "#000"), ("stroke-width", "1")],
            ink,
        ));
        s.shapes2d.push(shape(Shape2dKind::Circle { center: Vec2::new(2.0, 3.0), radius: 1.0 }, &[], leaf));
        s.shapes2d.push(shape(
            Shape2dKind::Rect { min: Vec2::new(4.0, 1.0), size: Vec2::new(2.0, 3.0) },
            &[("fill", "red"), ("bad name", "x"), ("title", "a<b&\"c\"")],
            ink,
        ));
        s.shapes2d.push(shape(Shape2dKind::Path { d: "M 0 0 Q 5 10 10 0".into() }, &[], ink));
        s.shapes2d.push(shape(
            Shape2dKind::Image { href: "brush.png".into(), min: Vec2::new(8.0, 2.0), size: Vec2::new(1.0, 1.0) },
            &[],
            ink,
        ));
        let svg = write_svg(&s, &SvgOptions::default());
        // x ∈ [−0.5, 10.5] (the line's ends widened by half its stroke), y ∈
        // [−0.5, 10] (stroke, path control point): extent 11, margin 0.33.
        assert_eq!((attr(&svg, "width"), attr(&svg, "height")), ("11.66cm", "11.16cm"));
        assert_eq!(attr(&svg, "viewBox"), "-0.83 -10.33 11.66 11.16");
        let lines: Vec<&str> = svg.lines().collect();
        assert_eq!(lines[2], "<line x1=\"0\" y1=\"0\" x2=\"10\" y2=\"0\" stroke=\"#000\" stroke-width=\"1\"/>");
        assert_eq!(
            lines[3],
            format!("<circle cx=\"2\" cy=\"-3\" r=\"1\" fill=\"{}\"/>", hex(tag_color("leaf#3a7d23")))
        );
        assert_eq!(
            lines[4],
            "<rect x=\"4\" y=\"-4\" width=\"2\" height=\"3\" fill=\"red\" title=\"a&lt;b&amp;&quot;c&quot;\"/>"
        );
        assert!(
            lines[5].starts_with("<path transform=\"scale(1 -1)\" d=\"M 0 0 Q 5 10 10 0\" fill=\"none\" stroke="),
            "{}",
            lines[5]
        );
        assert!(
            lines[6].starts_with("<image href=\"brush.png\" preserveAspectRatio=\"none\" x=\"8\" y=\"-3\""),
            "{}",
            lines[6]
        );
        resvg::usvg::Tree::from_str(&svg, &resvg::usvg::Options::default()).unwrap();
        // With anything else in the scene the drawing keeps pixel sizes.
        line(&mut s, &[(0.0, 0.0), (1.0, 1.0)], 0.0, ink);
        assert_eq!(attr(&write_svg(&s, &SvgOptions::default()), "width"), "1000");
        // Non-finite shapes are left out.
        let mut bad = Scene::new();
        bad.shapes2d.push(shape(Shape2dKind::Circle { center: Vec2::NAN, radius: 1.0 }, &[], ink));
        assert!(!write_svg(&bad, &SvgOptions::default()).contains("<circle"));
    }

    #[test]
    fn path_points_cover_every_command() {
        use glam::Vec2;
        let pts = shapes2d::path_points(
            "M1,2 L3 4 h2 v-1 l1 1 Q 0 0 1 1 t 1 1 C 1 2 3 4 5 6 s 1 1 2 2 A 1 1 0 0 1 9 9 m1-1 z L 0 0",
        );
        let v = |x: f32, y: f32| Vec2::new(x, y);
        assert_eq!(&pts[..6], &[v(1.0, 2.0), v(3.0, 4.0), v(5.0, 4.0), v(5.0, 3.0), v(6.0, 4.0), v(0.0, 0.0)]);
        // The arc's end widened by its radius; relative moveto after it.
        assert!(pts.contains(&v(10.0, 10.0)) && pts.contains(&v(10.0, 8.0)), "{pts:?}");
        assert_eq!(pts.last(), Some(&v(0.0, 0.0)));
        // Broken data stops the list where it breaks.
        assert_eq!(shapes2d::path_points("M 1 2 L 3 x 4"), [v(1.0, 2.0)]);
        assert_eq!(shapes2d::path_points("1 2 L 3 4"), Vec::<Vec2>::new(), "data starts with a command");
        assert!(!shapes2d::path_points("M 1e400 2")[0].is_finite());
    }

    #[test]
    fn export_checks_the_drawing() {
        let opts = ExportOptions::default();
        assert_eq!(export(&Scene::new(), Format::Svg, &opts), Err(ExportError::EmptyScene(Format::Svg)));
        let mut s = Scene::new();
        let tag = s.tag("a");
        line(&mut s, &[(0.0, 0.0)], 1.0, tag);
        assert_eq!(export(&s, Format::Svg, &opts), Err(ExportError::EmptyScene(Format::Svg)));
        line(&mut s, &[(0.0, 0.0), (f32::NAN, 1.0)], 1.0, tag);
        assert!(matches!(export(&s, Format::Svg, &opts), Err(ExportError::NonFinite(_))));
        s.polylines.points_mut(1)[1].x = 1.0;
        let bytes = export(&s, Format::Svg, &opts).unwrap();
        assert_eq!(String::from_utf8(bytes).unwrap(), write_svg(&s, &SvgOptions::default()));
        s.polygons.push(Polygon { points: vec![Vec3::ZERO, Vec3::X, Vec3::INFINITY], tag });
        assert!(matches!(export(&s, Format::Svg, &opts), Err(ExportError::NonFinite(_))));
        assert_eq!(Format::from_path(std::path::Path::new("plant.SVG")), Some(Format::Svg));
        assert_eq!(Format::Svg.to_string(), "SVG");
    }
}
