//! `Graph` → `Scene`: one 2D shape per element, styled by `svg_*`
//! attributes.

use crate::graph::{Graph, Value};
use crate::template::format_number;
use genform_core::scene::{Scene, Shape2d, Shape2dKind, TagId};
use glam::Vec2;
use std::sync::Arc;

/// Radius of a vertex drawn with the default style.
pub const DEFAULT_VERTEX_RADIUS: f64 = 0.1;
/// Stroke width of an edge drawn with the default style.
pub const DEFAULT_STROKE_WIDTH: f64 = 0.1;

/// Attributes with a meaning of their own (not passed through).
const GEOMETRY: &[&str] = &["svg_tag", "svg_d", "svg_r", "svg_width", "svg_height", "svg_href", "svg_z"];

#[derive(Clone, Copy)]
enum Tag {
    Default,
    Hidden,
    Circle,
    Rect,
    Path,
    Image,
    Line,
}

/// SVG presentation attributes, shared by the shapes that carry them.
type Attributes = Arc<[(String, String)]>;

/// What drawing reads of an element's slot.
#[derive(Clone, Copy)]
struct Element {
    attrs: u32,
    label: u32,
    /// An edge's vertices; a vertex itself, twice.
    ends: [u32; 2],
    is_vertex: bool,
}

/// Elements drawn per chunk by [`Graph::to_scene`].
const DRAW_CHUNK: usize = 256;

/// An element's attribute list read for drawing.
struct Styled<'g> {
    g: &'g Graph,
    attrs: &'g [(u32, Value)],
}

/// What one attribute list means for drawing, worked out once per list
/// (per shared list id): elements of a grammar share a few lists.
struct Style {
    z: f64,
    tag: Tag,
    /// The presentation attributes, for stroked and for filled shapes.
    attributes: [Option<Attributes>; 2],
}

/// Per shared attribute list id, its [`Style`] once asked for.
struct Styles(Vec<Option<Style>>);

impl Styles {
    fn get(&mut self, g: &Graph, set: u32) -> &mut Style {
        self.0[set as usize].get_or_insert_with(|| {
            let s = Styled { g, attrs: g.attr_sets.get(set) };
            Style { z: s.num("svg_z").unwrap_or(0.0), tag: s.tag(), attributes: [None, None] }
        })
    }

    fn attributes(&mut self, g: &Graph, set: u32, stroked: bool) -> Attributes {
        let style = self.get(g, set);
        style.attributes[usize::from(stroked)]
            .get_or_insert_with(|| Styled { g, attrs: g.attr_sets.get(set) }.attributes(stroked).into())
            .clone()
    }
}

impl Styled<'_> {
    fn value(&self, name: &str) -> Option<&Value> {
        let id = self.g.attr_names.get(name)?;
        self.attrs.iter().find(|(a, _)| *a == id).map(|(_, v)| v)
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
        for (id, v) in self.attrs {
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
        let mut styles = Styles((0..self.attr_sets.len()).map(|_| None).collect());
        // Element ids (the top bit set for vertices) in drawing order: by
        // `svg_z` when elements differ in it, then by birth. Hidden
        // elements are left out here, as they are from the drawing.
        const VERTEX: u32 = 1 << 31;
        let mut zs = Vec::new();
        let vertices = self.vertices.iter().map(|v| &v.c).enumerate().map(|(id, c)| (id, c, VERTEX));
        let edges = self.edges.iter().map(|e| &e.c).enumerate().map(|(id, c)| (id, c, 0));
        let drawn = vertices.chain(edges).filter(|(_, c, _)| c.alive()).filter_map(|(id, c, kind)| {
            let id = u32::try_from(id).ok().filter(|&id| id < VERTEX).expect("fewer than 2^31 slots");
            let style = styles.get(self, c.attrs);
            if matches!(style.tag, Tag::Hidden) {
                return None;
            }
            let z = style.z;
            if zs.len() < 2 && !zs.iter().any(|&x: &f64| x.total_cmp(&z).is_eq()) {
                zs.push(z);
            }
            Some((c.birth, id | kind))
        });
        let mut order = crate::graph::by_birth(self.next_birth(), self.element_count(), drawn);
        if zs.len() >= 2 {
            // Every list met above has its style already; the sort is
            // stable, so births stay in order within a z.
            let styles = &styles;
            let z = |tagged: u32| {
                let id = (tagged & !VERTEX) as usize;
                let set = if tagged & VERTEX != 0 { self.vertices[id].c.attrs } else { self.edges[id].c.attrs };
                styles.0[set as usize].as_ref().map_or(0.0, |s| s.z)
            };
            order.sort_by(|&a, &b| z(a).total_cmp(&z(b)));
        }
        scene.shapes2d.reserve(order.len());
        // Shapes are built a chunk at a time: first, in loops of their own
        // (small enough to keep many reads in flight), the chunk's slots
        // and their vertices, which are read at random; then the shapes
        // from what was read. Done element by element, the reads' cache
        // misses queued one behind the other: taking a shape's reference
        // count is a locked instruction, which waits for every read before
        // it.
        // Per label, its scene tag for vertices and for edges.
        let mut tags: Vec<[Option<TagId>; 2]> = Vec::new();
        let room = DRAW_CHUNK.min(order.len());
        let (mut elements, mut ends) = (Vec::with_capacity(room), Vec::with_capacity(room));
        for chunk in order.chunks(DRAW_CHUNK) {
            elements.clear();
            elements.extend(chunk.iter().map(|&tagged| match tagged & !VERTEX {
                v if tagged & VERTEX != 0 => {
                    let c = &self.vertices[v as usize].c;
                    Element { attrs: c.attrs, label: c.label, ends: [v, v], is_vertex: true }
                }
                e => {
                    let e = &self.edges[e as usize];
                    Element { attrs: e.c.attrs, label: e.c.label, ends: [e.from, e.to], is_vertex: false }
                }
            }));
            ends.clear();
            ends.extend(elements.iter().map(|e| e.ends.map(|v| v2(self.vertices[v as usize].pos))));
            for (&e, &[a, b]) in elements.iter().zip(&ends) {
                let Some((kind, stroked)) = self.shape(e, a, b, &mut styles) else { continue };
                let tag = &mut crate::table::grown(&mut tags, e.label as usize)[usize::from(e.is_vertex)];
                let tag = *tag.get_or_insert_with(|| {
                    let name = self.labels.name(e.label);
                    scene.tag(if !name.is_empty() {
                        name
                    } else if e.is_vertex {
                        "vertex"
                    } else {
                        "edge"
                    })
                });
                let attributes = styles.attributes(self, e.attrs, stroked);
                scene.shapes2d.push(Shape2d { kind, attributes, tag });
            }
        }
        scene
    }

    /// Element `e`'s shape and whether it is stroked; `a`, `b`: the
    /// positions of its ends (a vertex's own twice).
    fn shape(&self, e: Element, a: Vec2, b: Vec2, styles: &mut Styles) -> Option<(Shape2dKind, bool)> {
        let s = Styled { g: self, attrs: self.attr_sets.get(e.attrs) };
        let tag = styles.get(self, e.attrs).tag;
        let (kind, stroked) = match (tag, e.is_vertex) {
            (Tag::Hidden, _) => return None,
            (Tag::Path, _) => (Shape2dKind::Path { d: s.text("svg_d").unwrap_or_default() }, true),
            (Tag::Rect | Tag::Image, _) => {
                let (min, size) = match (s.num("svg_width"), s.num("svg_height")) {
                    // A vertex's size defaults to 1 × 1, an edge's to the
                    // box its ends span.
                    (w, h) if e.is_vertex => (a, Vec2::new(w.unwrap_or(1.0) as f32, h.unwrap_or(1.0) as f32)),
                    (Some(w), Some(h)) => (a, Vec2::new(w as f32, h as f32)),
                    _ => (a.min(b), (b - a).abs()),
                };
                match tag {
                    Tag::Image => {
                        (Shape2dKind::Image { href: s.text("svg_href").unwrap_or_default(), min, size }, false)
                    }
                    _ => (Shape2dKind::Rect { min, size }, false),
                }
            }
            (Tag::Default | Tag::Circle | Tag::Line, true) => {
                let radius = s.num("svg_r").unwrap_or(DEFAULT_VERTEX_RADIUS) as f32;
                (Shape2dKind::Circle { center: a, radius }, false)
            }
            (Tag::Circle, false) => {
                let r = s.num("svg_r").map_or(0.5 * a.distance(b), |r| r as f32);
                (Shape2dKind::Circle { center: 0.5 * (a + b), radius: r }, false)
            }
            (Tag::Default | Tag::Line, false) => (Shape2dKind::Line { from: a, to: b }, true),
        };
        Some((kind, stroked))
    }
}
