//! The Scene: resolved output with no grammar concepts left.
//!
//! Generators write a [`Scene`]; exporters and scorers read only a Scene.
//! Geometry is `f32` (what GPUs, glTF and voxelizers use); generators do
//! their own scope arithmetic in `f64` and convert when they emit.
//!
//! Today a Scene holds instanced primitives and meshes (shape grammars),
//! polylines and polygons (turtles). Later formalisms add their own kinds
//! (half-edge surfaces, block sets, 2D graphs) as new fields here.

use glam::{Affine3A, Vec3};
use std::sync::Arc;

/// Index into [`Scene::tags`].
pub type TagId = u32;
/// Index into [`Scene::meshes`].
pub type MeshId = u32;

/// A unit-sized shape, placed by an instance transform.
///
/// Every built-in primitive fits the cube `[-0.5, 0.5]³`; axial ones run
/// along local +y, with the base at y = −0.5.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Primitive {
    /// The cube `[-0.5, 0.5]³`.
    Box,
    /// A frustum along y: bottom radius 0.5, top radius `0.5 * top`.
    /// `top = 1` is a cylinder, `top = 0` a cone.
    Frustum {
        /// Top radius relative to the bottom radius.
        top: f32,
    },
    /// The sphere of radius 0.5.
    Sphere,
    /// A box whose top face (y = +0.5) is scaled by `top` in x and z
    /// (a square frustum; `top = 0` is a pyramid).
    TaperedBox {
        /// Top face size relative to the bottom face.
        top: f32,
    },
    /// A mesh asset from [`Scene::meshes`], used as is (not normalized).
    Mesh(MeshId),
}

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

/// A triangle mesh (an asset or a tessellated primitive).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Mesh {
    /// Display name (file stem for assets).
    pub name: String,
    /// Vertex positions.
    pub positions: Vec<Vec3>,
    /// Counter-clockwise triangles seen from outside.
    pub triangles: Vec<[u32; 3]>,
}

impl Mesh {
    /// Reads the geometry of a Wavefront OBJ text: `v` positions and `f`
    /// faces (`i`, `i/t`, `i//n`, `i/t/n`; negative indices count back;
    /// polygons are fan-triangulated). Other statements are ignored. Errors
    /// name the line.
    pub fn from_obj(name: &str, text: &str) -> Result<Mesh, String> {
        let mut positions = Vec::new();
        let mut triangles = Vec::new();
        let mut face = Vec::new();
        for (ln, line) in text.lines().enumerate() {
            let mut it = line.split_whitespace();
            match it.next() {
                Some("v") => {
                    let mut c = [0f32; 3];
                    for v in &mut c {
                        *v = it
                            .next()
                            .and_then(|t| t.parse::<f32>().ok())
                            .filter(|v| v.is_finite())
                            .ok_or_else(|| format!("line {}: a vertex needs three finite numbers", ln + 1))?;
                    }
                    positions.push(Vec3::from_array(c));
                }
                Some("f") => {
                    face.clear();
                    for t in it {
                        let idx = t.split('/').next().unwrap_or("");
                        let i: i64 = idx.parse().map_err(|_| format!("line {}: bad face index `{t}`", ln + 1))?;
                        let n = positions.len() as i64;
                        let abs = if i < 0 { n + i } else { i - 1 };
                        if abs < 0 || abs >= n {
                            return Err(format!("line {}: face index {i} refers to a missing vertex", ln + 1));
                        }
                        face.push(abs as u32);
                    }
                    if face.len() < 3 {
                        return Err(format!("line {}: a face needs at least 3 vertices", ln + 1));
                    }
                    for i in 1..face.len() - 1 {
                        triangles.push([face[0], face[i], face[i + 1]]);
                    }
                }
                _ => {}
            }
        }
        if triangles.is_empty() {
            return Err("the OBJ file has no faces".into());
        }
        Ok(Mesh { name: name.to_string(), positions, triangles })
    }

    /// Axis-aligned bounds, `None` when empty.
    pub fn bounds(&self) -> Option<(Vec3, Vec3)> {
        bounds_of(self.positions.iter().copied())
    }
}

/// An open or closed line through points (turtle strokes).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Polyline {
    /// The points, in order.
    pub points: Vec<Vec3>,
    /// Stroke width in scene units.
    pub width: f32,
    /// Semantic tag.
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
    /// `stroke-width`, …), written as given, in order.
    pub attributes: Vec<(String, String)>,
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
    pub polylines: Vec<Polyline>,
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
}

/// How finely curved primitives are tessellated.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Tessellation {
    /// Segments around a frustum.
    pub radial: u32,
    /// Rings of a sphere (pole to pole).
    pub rings: u32,
}

impl Default for Tessellation {
    fn default() -> Self {
        Tessellation { radial: 24, rings: 12 }
    }
}

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
        for l in &self.polylines {
            pts.extend_from_slice(&l.points);
        }
        bounds_of(pts.into_iter())
    }
}

fn bounds_of(mut it: impl Iterator<Item = Vec3>) -> Option<(Vec3, Vec3)> {
    let first = it.next()?;
    Some(it.fold((first, first), |(lo, hi), p| (lo.min(p), hi.max(p))))
}

/// Splits a planar polygon into triangles by ear clipping in its plane;
/// returns index triples into `points`.
///
/// The plane's normal is the polygon's Newell normal, so clockwise and
/// counter-clockwise input both work: every triangle winds
/// counter-clockwise seen from that normal's side, i.e. the way the input
/// itself turns. Repeated points and points on a straight run (or at the tip
/// of a zero-width spike) are skipped. Fewer than three distinct corners or
/// zero area give no triangles. A convex outline gives the fan from its
/// first kept corner. On a self-intersecting outline where no ear is left
/// to clip, the rest is finished as a fan. Non-finite points give the plain
/// fan, so callers that check coordinates still see them.
pub fn triangulate_polygon(points: &[Vec3]) -> Vec<[u32; 3]> {
    let n = points.len();
    if n < 3 {
        return Vec::new();
    }
    if !points.iter().all(|p| p.is_finite()) {
        return (1..n as u32 - 1).map(|i| [0, i, i + 1]).collect();
    }
    ear_clip::triangulate(points)
}

mod ear_clip {
    //! Ear clipping in `f64` on the polygon projected to its plane.

    use glam::{DVec2, DVec3, Vec3};

    /// Relative tolerances: points closer than `SAME * size` are one point;
    /// a corner whose turn has |sin| below `STRAIGHT` is no corner. Both are
    /// far above `f32` rounding, far below anything drawn on purpose.
    const SAME: f64 = 1e-6;
    const STRAIGHT: f64 = 1e-6;

    /// [`super::triangulate_polygon`] for at least 3 finite points.
    pub(super) fn triangulate(points: &[Vec3]) -> Vec<[u32; 3]> {
        let Some(q) = project(points) else { return Vec::new() };
        let size = bounds_size(&q);
        let mut ring = distinct(&q, SAME * size);
        drop_straight(&q, &mut ring);
        if ring.len() < 3 {
            return Vec::new();
        }
        let mut out = Vec::with_capacity(ring.len() - 2);
        let m = ring.len();
        if (0..m).all(|i| turn(&q, ring[(i + m - 1) % m], ring[i], ring[(i + 1) % m]) > 0.0) {
            out.extend((1..m - 1).map(|k| [ring[0], ring[k], ring[k + 1]]));
        } else {
            clip_ears(&q, ring, SAME * size, &mut out);
        }
        out.into_iter().map(|t| t.map(|i| i as u32)).collect()
    }

    /// The points in 2D coordinates of their plane, seen from the side of the
    /// Newell normal (so the outline turns counter-clockwise); `None` when
    /// the outline encloses no area.
    fn project(points: &[Vec3]) -> Option<Vec<DVec2>> {
        let p: Vec<DVec3> = points.iter().map(|v| v.as_dvec3()).collect();
        let o = p[0];
        let normal: DVec3 = (0..p.len()).map(|i| (p[i] - o).cross(p[(i + 1) % p.len()] - o)).sum();
        let (lo, hi) = p.iter().fold((o, o), |(lo, hi), &v| (lo.min(v), hi.max(v)));
        let size = (hi - lo).length();
        // |normal| is twice the area.
        if normal.length() <= 1e-10 * size * size {
            return None;
        }
        let w = normal.normalize();
        let u = w.any_orthonormal_vector();
        let v = w.cross(u);
        Some(p.iter().map(|&x| DVec2::new((x - o).dot(u), (x - o).dot(v))).collect())
    }

    fn bounds_size(q: &[DVec2]) -> f64 {
        let (lo, hi) = q.iter().fold((q[0], q[0]), |(lo, hi), &v| (lo.min(v), hi.max(v)));
        (hi - lo).length()
    }

    /// Indices of `q` without runs of (nearly) equal points, also across the
    /// wrap-around.
    fn distinct(q: &[DVec2], eps: f64) -> Vec<usize> {
        let mut ring: Vec<usize> = Vec::with_capacity(q.len());
        for i in 0..q.len() {
            if ring.last().is_none_or(|&j| q[j].distance(q[i]) > eps) {
                ring.push(i);
            }
        }
        while ring.len() > 1 && q[ring[0]].distance(q[ring[ring.len() - 1]]) <= eps {
            ring.pop();
        }
        ring
    }

    /// The turn at `b` on the way `a → b → c`: positive when left
    /// (counter-clockwise), 0 for a straight run or a spike.
    fn turn(q: &[DVec2], a: usize, b: usize, c: usize) -> f64 {
        let (d0, d1) = (q[b] - q[a], q[c] - q[b]);
        let cross = d0.perp_dot(d1);
        if cross.abs() <= STRAIGHT * d0.length() * d1.length() { 0.0 } else { cross }
    }

    /// Removes corners that do not turn, until every remaining one does.
    fn drop_straight(q: &[DVec2], ring: &mut Vec<usize>) {
        let mut i = 0;
        let mut unchanged = 0;
        while ring.len() >= 3 && unchanged < ring.len() {
            let m = ring.len();
            if turn(q, ring[(i + m - 1) % m], ring[i], ring[(i + 1) % m]) == 0.0 {
                ring.remove(i);
                unchanged = 0;
                // Step back: the previous corner has a new neighbour.
                i = (i + ring.len() - 1) % ring.len().max(1);
            } else {
                i = (i + 1) % m;
                unchanged += 1;
            }
        }
    }

    /// Whether `p` lies inside the counter-clockwise triangle `t` or within
    /// `eps` of its edges. A corner on the cut (a, c) must stop the ear, or
    /// the ring left behind has a straight corner and one triangle too few.
    fn in_triangle(p: DVec2, [a, b, c]: [DVec2; 3], eps: f64) -> bool {
        let left = |s: DVec2, e: DVec2| (e - s).perp_dot(p - s) >= -eps * (e - s).length();
        left(a, b) && left(b, c) && left(c, a)
    }

    /// Clips ears off a counter-clockwise ring of turning corners.
    fn clip_ears(q: &[DVec2], mut ring: Vec<usize>, eps: f64, out: &mut Vec<[usize; 3]>) {
        let mut i = 0;
        let mut tried = 0;
        while ring.len() > 3 {
            let m = ring.len();
            let (a, b, c) = (ring[(i + m - 1) % m], ring[i], ring[(i + 1) % m]);
            let t = turn(q, a, b, c);
            // A corner that became straight is dropped without a triangle.
            let clip = t == 0.0 || (t > 0.0 && is_ear(q, &ring, [a, b, c], eps));
            if clip {
                if t != 0.0 {
                    out.push([a, b, c]);
                }
                ring.remove(i);
                i %= ring.len();
                tried = 0;
            } else {
                i = (i + 1) % m;
                tried += 1;
                if tried >= m {
                    // Stuck (the outline crosses itself): fan the rest.
                    out.extend((1..m - 1).map(|k| [ring[0], ring[k], ring[k + 1]]));
                    return;
                }
            }
        }
        if let [a, b, c] = ring[..]
            && turn(q, a, b, c) != 0.0
        {
            out.push([a, b, c]);
        }
    }

    /// No other corner of the ring lies in the triangle (corners at the same
    /// place as one of its own, where an outline touches itself, aside).
    fn is_ear(q: &[DVec2], ring: &[usize], t: [usize; 3], eps: f64) -> bool {
        let tri = t.map(|i| q[i]);
        let m = ring.len();
        (0..m).all(|k| {
            let j = ring[k];
            let p = q[j];
            // Only reflex corners can be inside an ear.
            t.contains(&j)
                || tri.contains(&p)
                || turn(q, ring[(k + m - 1) % m], j, ring[(k + 1) % m]) > 0.0
                || !in_triangle(p, tri, eps)
        })
    }
}

/// The triangle mesh of a built-in primitive in its unit frame.
/// [`Primitive::Mesh`] gives an empty mesh (assets live in the Scene).
pub fn unit_mesh(p: Primitive, tess: Tessellation) -> Mesh {
    match p {
        Primitive::Box => tapered_box(1.0, "box"),
        Primitive::TaperedBox { top } => tapered_box(top, "tapered_box"),
        Primitive::Frustum { top } => frustum(top, tess.radial.max(3)),
        Primitive::Sphere => sphere(tess.rings.max(2), tess.radial.max(3)),
        Primitive::Mesh(_) => Mesh::default(),
    }
}

fn tapered_box(top: f32, name: &str) -> Mesh {
    let t = 0.5 * top.max(0.0);
    let positions = vec![
        Vec3::new(-0.5, -0.5, -0.5),
        Vec3::new(0.5, -0.5, -0.5),
        Vec3::new(0.5, -0.5, 0.5),
        Vec3::new(-0.5, -0.5, 0.5),
        Vec3::new(-t, 0.5, -t),
        Vec3::new(t, 0.5, -t),
        Vec3::new(t, 0.5, t),
        Vec3::new(-t, 0.5, t),
    ];
    // Quads as (a, b, c, d) counter-clockwise seen from outside.
    let quads = [
        [0, 1, 2, 3], // bottom (−y)
        [4, 7, 6, 5], // top (+y)
        [0, 4, 5, 1], // −z
        [1, 5, 6, 2], // +x
        [2, 6, 7, 3], // +z
        [3, 7, 4, 0], // −x
    ];
    let mut triangles = Vec::with_capacity(12);
    for [a, b, c, d] in quads {
        triangles.push([a, b, c]);
        triangles.push([a, c, d]);
    }
    if top <= 0.0 {
        // Degenerate top face: drop its zero-area triangles.
        triangles.retain(|t| !t.iter().all(|&i| i >= 4));
    }
    Mesh { name: name.to_string(), positions, triangles }
}

fn frustum(top: f32, n: u32) -> Mesh {
    let rt = 0.5 * top.max(0.0);
    let mut positions = Vec::with_capacity(2 * n as usize + 2);
    for i in 0..n {
        let a = std::f32::consts::TAU * i as f32 / n as f32;
        let (s, c) = a.sin_cos();
        positions.push(Vec3::new(0.5 * c, -0.5, 0.5 * s));
        positions.push(Vec3::new(rt * c, 0.5, rt * s));
    }
    let bottom_c = positions.len() as u32;
    positions.push(Vec3::new(0.0, -0.5, 0.0));
    let top_c = positions.len() as u32;
    positions.push(Vec3::new(0.0, 0.5, 0.0));
    let mut triangles = Vec::new();
    for i in 0..n {
        let j = (i + 1) % n;
        let (b0, t0, b1, t1) = (2 * i, 2 * i + 1, 2 * j, 2 * j + 1);
        triangles.push([b0, t0, t1]);
        if rt > 0.0 {
            triangles.push([b0, t1, b1]);
            triangles.push([top_c, t1, t0]);
        } else {
            triangles.pop();
            triangles.push([b0, t0, b1]);
        }
        triangles.push([bottom_c, b0, b1]);
    }
    Mesh { name: "frustum".into(), positions, triangles }
}

fn sphere(rings: u32, n: u32) -> Mesh {
    let mut positions = vec![Vec3::new(0.0, -0.5, 0.0)];
    for r in 1..rings {
        let phi = std::f32::consts::PI * r as f32 / rings as f32;
        let (y, rad) = (-0.5 * phi.cos(), 0.5 * phi.sin());
        for i in 0..n {
            let a = std::f32::consts::TAU * i as f32 / n as f32;
            positions.push(Vec3::new(rad * a.cos(), y, rad * a.sin()));
        }
    }
    let north = positions.len() as u32;
    positions.push(Vec3::new(0.0, 0.5, 0.0));
    let ring = |r: u32, i: u32| 1 + (r - 1) * n + (i % n);
    let mut triangles = Vec::new();
    for i in 0..n {
        triangles.push([0, ring(1, i), ring(1, i + 1)]);
        triangles.push([north, ring(rings - 1, i + 1), ring(rings - 1, i)]);
    }
    for r in 1..rings - 1 {
        for i in 0..n {
            let (a, b, c, d) = (ring(r, i), ring(r, i + 1), ring(r + 1, i + 1), ring(r + 1, i));
            triangles.push([a, d, c]);
            triangles.push([a, c, b]);
        }
    }
    Mesh { name: "sphere".into(), positions, triangles }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Signed volume via the divergence theorem; positive iff outward winding.
    fn volume(m: &Mesh) -> f32 {
        m.triangles
            .iter()
            .map(|t| {
                let [a, b, c] = t.map(|i| m.positions[i as usize]);
                a.dot(b.cross(c)) / 6.0
            })
            .sum()
    }

    #[test]
    fn unit_primitives_are_closed_and_outward() {
        let tess = Tessellation::default();
        let cases = [
            (Primitive::Box, 1.0),
            (Primitive::TaperedBox { top: 0.0 }, 1.0 / 3.0),
            (Primitive::Frustum { top: 1.0 }, std::f32::consts::PI * 0.25),
            (Primitive::Frustum { top: 0.0 }, std::f32::consts::PI * 0.25 / 3.0),
            (Primitive::Sphere, std::f32::consts::PI / 6.0),
        ];
        for (p, exact) in cases {
            let v = volume(&unit_mesh(p, tess));
            assert!(v > 0.0, "{p:?} winding");
            assert!((v - exact).abs() / exact < 0.06, "{p:?}: {v} vs {exact}");
        }
    }

    #[test]
    fn reflected_instances_keep_outward_winding() {
        let mut s = Scene::new();
        let tag = s.tag("x");
        s.instances.push(Instance {
            transform: Affine3A::from_scale(Vec3::new(-2.0, 1.0, 1.0)),
            primitive: Primitive::Box,
            tag,
        });
        let mut v = 0.0;
        s.for_each_triangle(Tessellation::default(), |[a, b, c], _| v += a.dot(b.cross(c)) / 6.0);
        assert!((v - 2.0).abs() < 1e-5, "{v}");
        assert_eq!(s.bounds(Tessellation::default()).unwrap().0, Vec3::new(-1.0, -0.5, -0.5));
    }

    #[test]
    fn obj_reader_handles_polygons_and_reports_bad_lines() {
        let m =
            Mesh::from_obj("q", "# quad\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nf 1/1 2/1 3/1 -1/1\n").unwrap();
        assert_eq!(m.triangles, vec![[0, 1, 2], [0, 2, 3]]);
        assert!(Mesh::from_obj("q", "v 0 0\n").unwrap_err().contains("line 1"));
        assert!(Mesh::from_obj("q", "v 0 0 0\nf 1 2 3\n").unwrap_err().contains("missing vertex"));
        assert!(Mesh::from_obj("q", "").unwrap_err().contains("no faces"));
    }

    /// 2D outline → 3D points on a tilted plane (so the Newell projection
    /// is exercised), reversed for clockwise input.
    fn tilted(outline: &[(f32, f32)], clockwise: bool) -> Vec<Vec3> {
        let r = glam::Quat::from_euler(glam::EulerRot::XYZ, 0.7, -0.4, 0.2);
        let mut pts: Vec<Vec3> = outline.iter().map(|&(x, y)| r * Vec3::new(x, y, 0.0) + Vec3::splat(3.0)).collect();
        if clockwise {
            pts.reverse();
        }
        pts
    }

    fn newell(pts: &[Vec3]) -> Vec3 {
        (0..pts.len()).map(|i| (pts[i] - pts[0]).cross(pts[(i + 1) % pts.len()] - pts[0])).sum()
    }

    /// Even-odd point in polygon on the 2D outline.
    fn inside(outline: &[(f32, f32)], (x, y): (f32, f32)) -> bool {
        let mut odd = false;
        for i in 0..outline.len() {
            let ((x0, y0), (x1, y1)) = (outline[i], outline[(i + 1) % outline.len()]);
            if (y0 > y) != (y1 > y) && x < x0 + (y - y0) / (y1 - y0) * (x1 - x0) {
                odd = !odd;
            }
        }
        odd
    }

    /// Checks a triangulation of a simple outline: `expected` triangles,
    /// each counter-clockwise about the Newell normal and inside the
    /// outline, their areas adding up to the polygon's.
    fn check_triangulation(outline: &[(f32, f32)], expected: usize) {
        for clockwise in [false, true] {
            let pts = tilted(outline, clockwise);
            let flat: Vec<(f32, f32)> =
                if clockwise { outline.iter().rev().copied().collect() } else { outline.to_vec() };
            let tris = triangulate_polygon(&pts);
            assert_eq!(tris.len(), expected, "{outline:?} cw={clockwise}: {tris:?}");
            let n = newell(&pts);
            let mut area = 0.0;
            for t in &tris {
                let [a, b, c] = t.map(|i| pts[i as usize]);
                let tn = (b - a).cross(c - a);
                assert!(tn.dot(n) > 0.0, "{t:?} winds the wrong way");
                area += tn.length() / 2.0;
                let [p, q, r] = t.map(|i| flat[i as usize]);
                let centroid = ((p.0 + q.0 + r.0) / 3.0, (p.1 + q.1 + r.1) / 3.0);
                assert!(inside(outline, centroid), "{t:?} lies outside {outline:?}");
            }
            assert!((area - n.length() / 2.0).abs() < 1e-4 * area, "{area} vs {}", n.length() / 2.0);
        }
    }

    #[test]
    fn ear_clipping_handles_concave_outlines_both_ways_round() {
        let l_shape = [(0.0, 0.0), (2.0, 0.0), (2.0, 1.0), (1.0, 1.0), (1.0, 2.0), (0.0, 2.0)];
        check_triangulation(&l_shape, 4);
        let star: Vec<(f32, f32)> = (0..10)
            .map(|i| {
                let a = std::f32::consts::TAU * i as f32 / 10.0;
                let r = if i % 2 == 0 { 1.0 } else { 0.38 };
                (r * a.cos(), r * a.sin())
            })
            .collect();
        check_triangulation(&star, 8);
        // A comb: the fan from vertex 0 would cross the outside.
        let comb = [(0.0, 0.0), (5.0, 0.0), (5.0, 3.0), (4.0, 3.0), (4.0, 1.0), (3.0, 1.0), (3.0, 3.0), (0.0, 3.0)];
        check_triangulation(&comb, 6);
    }

    #[test]
    fn ear_clipping_drops_repeats_straight_runs_and_degenerates() {
        // A unit square with repeated corners, midpoints and a zero-width spike.
        let square = [
            (0.0, 0.0),
            (0.0, 0.0),
            (0.5, 0.0),
            (1.0, 0.0),
            (1.0, 0.5),
            (1.5, 0.5),
            (1.0, 0.5),
            (1.0, 1.0),
            (0.0, 1.0),
            (0.0, 0.0),
        ];
        let pts = tilted(&square, false);
        let tris = triangulate_polygon(&pts);
        assert_eq!(tris.len(), 2, "{tris:?}");
        let area: f32 = tris
            .iter()
            .map(|t| {
                let [a, b, c] = t.map(|i| pts[i as usize]);
                (b - a).cross(c - a).length() / 2.0
            })
            .sum();
        assert!((area - 1.0).abs() < 1e-5, "{area}");
        // A convex outline keeps the fan from its first corner.
        let quad = [Vec3::ZERO, Vec3::X, Vec3::new(1.0, 1.0, 0.0), Vec3::Y];
        assert_eq!(triangulate_polygon(&quad), vec![[0, 1, 2], [0, 2, 3]]);
        // Nothing from too few points, one point, a line, or zero area.
        assert!(triangulate_polygon(&quad[..2]).is_empty());
        assert!(triangulate_polygon(&[Vec3::ONE; 5]).is_empty());
        assert!(triangulate_polygon(&[Vec3::ZERO, Vec3::X, Vec3::X * 2.0, Vec3::X * 0.5]).is_empty());
        // Non-finite input still shows up (as the plain fan).
        assert_eq!(triangulate_polygon(&[Vec3::ZERO, Vec3::X, Vec3::NAN, Vec3::Y]).len(), 2);
    }

    #[test]
    fn self_intersecting_outlines_do_not_get_stuck() {
        // A bow tie and a pentagram: some triangles, all finite, no panic.
        let bow = [Vec3::ZERO, Vec3::new(2.0, 1.0, 0.0), Vec3::new(2.0, 0.0, 0.0), Vec3::new(0.0, 1.2, 0.0)];
        let pentagram: Vec<Vec3> = (0..5)
            .map(|i| {
                let a = std::f32::consts::TAU * (2 * i) as f32 / 5.0;
                Vec3::new(a.cos(), a.sin(), 0.0)
            })
            .collect();
        for pts in [&bow[..], &pentagram] {
            let tris = triangulate_polygon(pts);
            assert!(!tris.is_empty() && tris.len() <= pts.len() - 2, "{tris:?}");
            assert!(tris.iter().flatten().all(|&i| (i as usize) < pts.len()));
        }
    }

    #[test]
    fn scene_polygons_are_ear_clipped() {
        let mut s = Scene::new();
        let tag = s.tag("leaf");
        let l_shape = [(0.0, 0.0), (2.0, 0.0), (2.0, 1.0), (1.0, 1.0), (1.0, 2.0), (0.0, 2.0)];
        s.polygons.push(Polygon { points: l_shape.iter().map(|&(x, y)| Vec3::new(x, y, 0.0)).collect(), tag });
        let mut area = 0.0;
        s.for_each_triangle(Tessellation::default(), |[a, b, c], t| {
            assert_eq!(t, tag);
            let n = (b - a).cross(c - a);
            assert!(n.z > 0.0);
            area += n.z / 2.0;
        });
        assert_eq!(s.triangle_count(Tessellation::default()), 4);
        assert!((area - 3.0).abs() < 1e-5, "{area}");
    }

    proptest::proptest! {
        /// Random star-shaped outlines (simple by construction) split into
        /// n − 2 inside triangles covering the area exactly.
        #[test]
        fn random_star_shaped_outlines(radii in proptest::collection::vec(0.2f32..1.0, 3..24)) {
            let n = radii.len();
            let outline: Vec<(f32, f32)> = radii
                .iter()
                .enumerate()
                .map(|(i, r)| {
                    let a = std::f32::consts::TAU * i as f32 / n as f32;
                    (r * a.cos(), r * a.sin())
                })
                .collect();
            // Nearly straight corners may be dropped, so up to n − 2.
            let pts = tilted(&outline, false);
            let tris = triangulate_polygon(&pts);
            let kept: std::collections::BTreeSet<u32> = tris.iter().flatten().copied().collect();
            proptest::prop_assert_eq!(tris.len(), kept.len() - 2);
            check_triangulation(&outline, tris.len());
        }
    }

    #[test]
    fn tags_and_meshes_are_interned() {
        let mut s = Scene::new();
        assert_eq!(s.tag("a"), 0);
        assert_eq!(s.tag("b"), 1);
        assert_eq!(s.tag("a"), 0);
        let m = Arc::new(Mesh::default());
        assert_eq!(s.mesh(&m), 0);
        assert_eq!(s.mesh(&m), 0);
        assert_eq!(s.mesh(&Arc::new(Mesh::default())), 1);
    }
}
