//! The Scene: resolved output with no grammar concepts left.
//!
//! Generators write a [`Scene`]; exporters and scorers read only a Scene.
//! Geometry is `f32` (what GPUs, glTF and voxelizers use); generators do
//! their own scope arithmetic in `f64` and convert when they emit.
//!
//! Today a Scene holds instanced primitives and meshes (shape grammars),
//! polylines and polygons (turtles). Later formalisms add their own kinds
//! (half-edge surfaces, block sets, 2D graphs) as new fields here.
//!
//! The parts live in submodules, all re-exported here:
//! - `mesh`: [`Mesh`] and the [`TagId`]/[`MeshId`] ids;
//! - `obj`: [`Mesh::from_obj`], reading Wavefront OBJ text;
//! - `polylines`: [`Polylines`], every stroke's points in one array;
//! - `triangulate`: [`triangulate_polygon`], ear clipping of planar polygons;
//! - `primitive`: [`Primitive`], the built-in unit shapes;
//! - `texture`: [`Texture`], a PNG image with its size in the world;
//! - `tessellate`: [`Tessellation`] and [`unit_mesh`], which
//!   [`Scene::for_each_triangle`] (here) walks the triangles with.

pub(crate) mod mesh;
mod obj;
mod polylines;
mod primitive;
mod tessellate;
#[cfg(test)]
mod tests;
mod texture;
mod triangulate;

pub use mesh::{Mesh, MeshId, TagId};
pub use polylines::{Polyline, Polylines};
pub use primitive::Primitive;
pub use tessellate::{Tessellation, unit_mesh};
pub use texture::{Texture, TextureId};
pub use triangulate::triangulate_polygon;

use glam::Affine3A;
use glam::Vec3;
use mesh::bounds_of;
use std::sync::Arc;

/// One placed primitive.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Instance {
    /// Unit primitive → world. May include a reflection (negative determinant).
    pub transform: Affine3A,
    /// What is placed.
    pub primitive: Primitive,
    /// Semantic tag (by default the symbol that emitted it).
    pub tag: TagId,
}

/// A planar polygon (turtle `{ … }` regions).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Polygon {
    /// Boundary points, in order.
    pub points: Vec<Vec3>,
    /// Semantic tag.
    pub tag: TagId,
}

/// A 2D vector-drawing element on the xy plane (y up), in scene units: what
/// a graph grammar's `svg_*` attributes describe.
#[derive(Clone, Debug, PartialEq)]
pub struct Shape2d {
    /// The geometry.
    pub kind: Shape2dKind,
    /// Extra SVG presentation attributes (`stroke`, `fill`,
    /// `stroke-width`, …), written as given, in order; shared, since many
    /// shapes of a drawing carry the same list.
    pub attributes: std::sync::Arc<[(String, String)]>,
    /// Semantic tag.
    pub tag: TagId,
}

/// The geometry of a [`Shape2d`].
#[derive(Clone, Debug, PartialEq)]
pub enum Shape2dKind {
    /// A straight line.
    Line {
        /// Start point.
        from: glam::Vec2,
        /// End point.
        to: glam::Vec2,
    },
    /// A circle.
    Circle {
        /// Centre.
        center: glam::Vec2,
        /// Radius.
        radius: f32,
    },
    /// An axis-aligned rectangle.
    Rect {
        /// Lower-left corner (y up).
        min: glam::Vec2,
        /// Width and height.
        size: glam::Vec2,
    },
    /// SVG path data in scene coordinates (y up).
    Path {
        /// The `d` attribute.
        d: String,
    },
    /// An external image.
    Image {
        /// The `href`.
        href: String,
        /// Lower-left corner (y up).
        min: glam::Vec2,
        /// Width and height.
        size: glam::Vec2,
    },
}

/// Resolved geometry.
#[derive(Clone, Debug, Default)]
pub struct Scene {
    /// Instanced primitives, in emission order.
    pub instances: Vec<Instance>,
    /// Mesh assets referenced by [`Primitive::Mesh`].
    pub meshes: Vec<Arc<Mesh>>,
    /// Interned tag names.
    pub tags: Vec<String>,
    /// Turtle strokes.
    pub polylines: Polylines,
    /// Turtle polygons.
    pub polygons: Vec<Polygon>,
    /// Block structures (box-split grammars): unit cubes on the integer
    /// grid, cell (x, y, z) covering [x, x+1]×[y, y+1]×[z, z+1]. Exporters
    /// mesh them themselves; [`Scene::for_each_triangle`] leaves them out.
    pub blocks: Vec<crate::blocks::BlockGrid>,
    /// 2D vector-drawing elements (graph grammars), drawn by the SVG and
    /// PNG exporters in order.
    pub shapes2d: Vec<Shape2d>,
    /// Polygon surfaces with typed edges (HEMLS growth). Their faces are
    /// part of [`Scene::for_each_triangle`].
    pub surfaces: Vec<crate::surface::Surface>,
    /// Context geometry previews draw faintly; not part of the model (no
    /// exporter writes it into a model file, no scorer sees it).
    pub guides: Vec<crate::surface::Guide>,
    /// Where the model's origin lies in the data it was built on, in words
    /// (e.g. geographic footprints' tangent point "50.1°N 14.4°E (WGS 84;
    /// …)"), for formats with a place for it: GLB `asset.extras.origin`,
    /// an OBJ and a PLY comment. `None`: the data's own origin.
    pub origin: Option<String>,
    /// Images shown by textured tags ([`Scene::tag_textures`]), each once.
    pub textures: Vec<Arc<Texture>>,
    /// Which tags show which texture: (tag, index into
    /// [`Scene::textures`]), a tag at most once, in the order they were
    /// set. Other tags show their flat colour.
    pub tag_textures: Vec<(TagId, TextureId)>,
    /// What the generator left out and why (an inset that left nothing, a
    /// roof on a polygon without area), each with how often it happened,
    /// at most [`MAX_NOTES`] distinct ones: the door shows them as
    /// warnings after a sample. Exporters ignore them.
    pub notes: Vec<(String, u32)>,
}

/// How many distinct [`Scene::notes`] a scene keeps (repeats of a kept
/// note are still counted).
pub const MAX_NOTES: usize = 32;

impl Scene {
    /// An empty scene.
    pub fn new() -> Self {
        Scene::default()
    }

    /// Empties the scene, keeping allocations for reuse.
    pub fn clear(&mut self) {
        self.instances.clear();
        self.meshes.clear();
        self.tags.clear();
        self.polylines.clear();
        self.polygons.clear();
        self.blocks.clear();
        self.shapes2d.clear();
        self.surfaces.clear();
        self.guides.clear();
        self.textures.clear();
        self.tag_textures.clear();
        self.notes.clear();
    }

    /// Records that the generator left something out: `text` says what
    /// and why (with its place in the grammar). A repeated note is
    /// counted, not repeated.
    pub fn note(&mut self, text: String) {
        if let Some((_, n)) = self.notes.iter_mut().find(|(t, _)| *t == text) {
            *n += 1;
        } else if self.notes.len() < MAX_NOTES {
            self.notes.push((text, 1));
        }
    }

    /// The id of tag `name`, interning it on first use.
    pub fn tag(&mut self, name: &str) -> TagId {
        if let Some(i) = self.tags.iter().position(|t| t == name) {
            return i as TagId;
        }
        self.tags.push(name.to_string());
        (self.tags.len() - 1) as TagId
    }

    /// The id of a mesh asset, adding it on first use (by pointer identity).
    pub fn mesh(&mut self, mesh: &Arc<Mesh>) -> MeshId {
        if let Some(i) = self.meshes.iter().position(|m| Arc::ptr_eq(m, mesh)) {
            return i as MeshId;
        }
        self.meshes.push(mesh.clone());
        (self.meshes.len() - 1) as MeshId
    }

    /// Gives `tag` the texture `texture` (replacing one it had), adding
    /// the texture on first use (by pointer identity).
    pub fn set_texture(&mut self, tag: TagId, texture: &Arc<Texture>) {
        let id = match self.textures.iter().position(|t| Arc::ptr_eq(t, texture)) {
            Some(i) => i as TextureId,
            None => {
                self.textures.push(texture.clone());
                (self.textures.len() - 1) as TextureId
            }
        };
        match self.tag_textures.iter_mut().find(|(t, _)| *t == tag) {
            Some(p) => p.1 = id,
            None => self.tag_textures.push((tag, id)),
        }
    }

    /// The texture `tag` shows, if it has one.
    pub fn texture_of(&self, tag: TagId) -> Option<&Texture> {
        let (_, id) = self.tag_textures.iter().find(|(t, _)| *t == tag)?;
        self.textures.get(*id as usize).map(|t| &**t)
    }

    /// Whether nothing was emitted.
    pub fn is_empty(&self) -> bool {
        self.instances.is_empty()
            && self.polylines.is_empty()
            && self.polygons.is_empty()
            && self.blocks.iter().all(|g| g.set_count() == 0)
            && self.shapes2d.is_empty()
            && self.surfaces.iter().all(|s| s.positions.is_empty())
    }

    /// Calls `f(triangle, tag)` for every triangle of every instance,
    /// polygon and surface face, in world space and counter-clockwise seen from outside
    /// (triangles of reflected instances are re-ordered to stay so).
    /// Polygons are split by [`triangulate_polygon`]: counter-clockwise seen
    /// from the side their points wind counter-clockwise around.
    pub fn for_each_triangle(&self, tess: Tessellation, mut f: impl FnMut([Vec3; 3], TagId)) {
        let mut cache: Vec<(Primitive, Mesh)> = Vec::new();
        for inst in &self.instances {
            let mesh: &Mesh = match inst.primitive {
                Primitive::Mesh(id) => &self.meshes[id as usize],
                p => {
                    let i = match cache.iter().position(|(q, _)| *q == p) {
                        Some(i) => i,
                        None => {
                            cache.push((p, unit_mesh(p, tess)));
                            cache.len() - 1
                        }
                    };
                    &cache[i].1
                }
            };
            let flip = inst.transform.matrix3.determinant() < 0.0;
            for t in &mesh.triangles {
                let [a, b, c] = t.map(|i| inst.transform.transform_point3(mesh.positions[i as usize]));
                f(if flip { [a, c, b] } else { [a, b, c] }, inst.tag);
            }
        }
        for poly in &self.polygons {
            for t in triangulate_polygon(&poly.points) {
                f(t.map(|i| poly.points[i as usize]), poly.tag);
            }
        }
        for surface in &self.surfaces {
            surface.for_each_face_points(|pts| {
                for t in triangulate_polygon(pts) {
                    f(t.map(|i| pts[i as usize]), surface.tag);
                }
            });
        }
    }

    /// Number of triangles [`Scene::for_each_triangle`] yields.
    pub fn triangle_count(&self, tess: Tessellation) -> usize {
        let mut n = 0;
        self.for_each_triangle(tess, |_, _| n += 1);
        n
    }

    /// Axis-aligned bounds of all geometry, `None` when empty.
    pub fn bounds(&self, tess: Tessellation) -> Option<(Vec3, Vec3)> {
        let mut pts = Vec::new();
        self.for_each_triangle(tess, |t, _| pts.extend_from_slice(&t));
        pts.extend_from_slice(self.polylines.points());
        bounds_of(pts.into_iter())
    }
}
