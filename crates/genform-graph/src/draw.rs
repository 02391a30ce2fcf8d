//! `Graph` → `Scene`: one 2D shape per element, styled by `svg_*`
//! attributes.

use crate::graph::{Common, Graph, Value};
use crate::template::format_number;
use genform_core::scene::{Scene, Shape2d, Shape2dKind};
use glam::Vec2;

/// Radius of a vertex drawn with the default style.
pub const DEFAULT_VERTEX_RADIUS: f64 = 0.1;
/// Stroke width of an edge drawn with the default style.
pub const DEFAULT_STROKE_WIDTH: f64 = 0.1;

/// Attributes with a meaning of their own (not passed through).
const GEOMETRY: &[&str] = &["svg_tag", "svg_d", "svg_r", "svg_width", "svg_height", "svg_href", "svg_z"];

enum Tag {
    Default,
    Hidden,
    Circle,
    Rect,
    Path,
    Image,
    Line,
}

/// A shape, its SVG attributes and its tag name.
type Drawn = (Shape2dKind, Vec<(String, String)>, String);

struct Styled<'g> {
    g: &'g Graph,
    c: &'g Common,
}

impl Styled<'_> {
    fn value(&self, name: &str) -> Option<&Value> {
        self.g.attr_names.get(name).and_then(|id| self.c.attr(id))
    }

    fn text(&self, name: &str) -> Option<String> {
        match self.value(name)? {
            Value::Text(t) => Some(t.to_string()),
            Value::Num(v) => Some(format_number(*v, Some(6)).trim_end_matches('0').trim_end_matches('.').to_string()),
        }
    }

    fn num(&self, name: &str) -> Option<f64> {
        match self.value(name)? {
            Value::Num(v) => Some(*v),
            Value::Text(t) => t.trim().trim_end_matches("cm").trim().parse().ok(),
        }
    }

    fn tag(&self) -> Tag {
        match self.text("svg_tag").as_deref() {
            Some("hidden") | Some("none") => Tag::Hidden,
            Some("circle") => Tag::Circle,
            Some("rect") => Tag::Rect,
            Some("path") => Tag::Path,
            Some("image") => Tag::Image,
            Some("line") => Tag::Line,
            _ => Tag::Default,
        }
    }

    /// Presentation attributes: every other `svg_xxx_yyy` as `xxx-yyy`,
    /// in the grammar's attribute order, plus defaults.
    fn attributes(&self, stroked: bool) -> Vec<(String, String)> {
        let mut out = Vec::new();
        for (id, v) in &self.c.attrs {
            let name = self.g.attr_names.name(*id);
            let Some(rest) = name.strip_prefix("svg_") else { continue };
            if GEOMETRY.contains(&name) {
                continue;
            }
            let text = match v {
                Value::Text(t) => t.to_string(),
                Value::Num(x) => crate::write::number(*x),
            };
            out.push((rest.replace('_', "-"), text));
        }
        let has = |k: &str, out: &[(String, String)]| out.iter().any(|(n, _)| n == k);
        if stroked {
            if !has("stroke", &out) {
                out.push(("stroke".into(), "#000000".into()));
            }
            if !has("stroke-width", &out) {
                out.push(("stroke-width".into(), crate::write::number(DEFAULT_STROKE_WIDTH)));
            }
            if !has("fill", &out) {
                out.push(("fill".into(), "none".into()));
            }
        } else if !has("fill", &out) && !has("stroke", &out) {
            out.push(("fill".into(), "#000000".into()));
        }
        out
    }
}

fn v2(p: [f64; 2]) -> Vec2 {
    Vec2::new(p[0] as f32, p[1] as f32)
}

impl Graph {
    /// The graph as a drawing: one [`Shape2d`] per element in
    /// `(svg_z, creation)` order, y up, 1 unit = 1 cm.
    ///
    /// `svg_tag` picks the shape: `circle` (a vertex's default; radius
    /// `svg_r`, default 0.1), `line` (an edge's default), `rect` and `image`
    /// (`svg_width` × `svg_height` from the vertex as lower-left corner; for
    /// an edge, the box its ends span unless a size is given), `path`
    /// (`svg_d`, in graph coordinates), `hidden`. Every other `svg_xxx_yyy`
    /// attribute becomes the SVG attribute `xxx-yyy` (`svg_stroke_width` →
    /// `stroke-width`). Lines and paths default to a black stroke 0.1 wide
    /// and no fill, circles and rectangles to a black fill. Each shape's tag
    /// is the element's label (`vertex`/`edge` when it has none).
    pub fn to_scene(&self) -> Scene {
        let mut scene = Scene::new();
        let mut order: Vec<(f64, u64, bool, u32)> = Vec::new();
        for &id in &self.vindex.all {
            let c = &self.vertices[id as usize].c;
            order.push((Styled { g: self, c }.num("svg_z").unwrap_or(0.0), c.birth, true, id));
        }
        for &id in &self.eindex.all {
            let c = &self.edges[id as usize].c;
            order.push((Styled { g: self, c }.num("svg_z").unwrap_or(0.0), c.birth, false, id));
        }
        order.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
        for (_, _, is_vertex, id) in order {
            let shape = if is_vertex { self.vertex_shape(id) } else { self.edge_shape(id) };
            if let Some((kind, attributes, label)) = shape {
                let tag = scene.tag(&label);
                scene.shapes2d.push(Shape2d { kind, attributes, tag });
            }
        }
        scene
    }

    fn vertex_shape(&self, id: u32) -> Option<Drawn> {
        let v = &self.vertices[id as usize];
        let s = Styled { g: self, c: &v.c };
        let p = v2(v.pos);
        let size = || Vec2::new(s.num("svg_width").unwrap_or(1.0) as f32, s.num("svg_height").unwrap_or(1.0) as f32);
        let (kind, stroked) = match s.tag() {
            Tag::Hidden => return None,
            Tag::Default | Tag::Circle | Tag::Line => (
                Shape2dKind::Circle { center: p, radius: s.num("svg_r").unwrap_or(DEFAULT_VERTEX_RADIUS) as f32 },
                false,
            ),
            Tag::Rect => (Shape2dKind::Rect { min: p, size: size() }, false),
            Tag::Image => {
                (Shape2dKind::Image { href: s.text("svg_href").unwrap_or_default(), min: p, size: size() }, false)
            }
            Tag::Path => (Shape2dKind::Path { d: s.text("svg_d").unwrap_or_default() }, true),
        };
        let label = self.labels.name(v.c.label);
        Some((kind, s.attributes(stroked), if label.is_empty() { "vertex".into() } else { label.into() }))
    }

    fn edge_shape(&self, id: u32) -> Option<Drawn> {
        let e = &self.edges[id as usize];
        let s = Styled { g: self, c: &e.c };
        let (a, b) = (v2(self.vertices[e.from as usize].pos), v2(self.vertices[e.to as usize].pos));
        let bbox = || match (s.num("svg_width"), s.num("svg_height")) {
            (Some(w), Some(h)) => (a, Vec2::new(w as f32, h as f32)),
            _ => (a.min(b), (b - a).abs()),
        };
        let (kind, stroked) = match s.tag() {
            Tag::Hidden => return None,
            Tag::Default | Tag::Line => (Shape2dKind::Line { from: a, to: b }, true),
            Tag::Circle => {
                let r = s.num("svg_r").map_or(0.5 * a.distance(b), |r| r as f32);
                (Shape2dKind::Circle { center: 0.5 * (a + b), radius: r }, false)
            }
            Tag::Rect => {
                let (min, size) = bbox();
                (Shape2dKind::Rect { min, size }, false)
            }
            Tag::Image => {
                let (min, size) = bbox();
                (Shape2dKind::Image { href: s.text("svg_href").unwrap_or_default(), min, size }, false)
            }
            Tag::Path => (Shape2dKind::Path { d: s.text("svg_d").unwrap_or_default() }, true),
        };
        let label = self.labels.name(e.c.label);
        Some((kind, s.attributes(stroked), if label.is_empty() { "edge".into() } else { label.into() }))
    }
}
