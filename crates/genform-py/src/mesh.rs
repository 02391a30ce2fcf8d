//! A Scene as indexed triangle arrays for NumPy: the points and faces the
//! OBJ writer of `genform_export` writes (n-gons split by
//! `triangulate_polygon`, a flat drawing's strokes and shapes as the
//! polygons of `drawing_geometry`, 3D lines as points without faces), in the Scene's
//! order (instances, polygons, polylines, block meshes merged per block
//! state, surfaces), with exact `f32` coordinates.

use genform_core::Mesh;
use genform_core::scene::{Primitive, Scene, Tessellation, triangulate_polygon, unit_mesh};
use glam::Vec3;

/// Flat vertex coordinates (x, y, z per vertex) and triangle indices.
#[derive(Default)]
pub struct Arrays {
    /// 3 floats per vertex.
    pub vertices: Vec<f32>,
    /// 3 indices per triangle.
    pub faces: Vec<u32>,
    /// Per triangle, its group in [`Arrays::tag_names`].
    pub tags: Vec<u32>,
    /// The groups: the scene's tags, then one per block state.
    pub tag_names: Vec<String>,
    /// Per group, its display colour (8-bit sRGB): a tag's
    /// `genform_export::tag_color`, a block state's
    /// `genform_export::minecraft::block_color` — the GLB materials' colours.
    pub tag_colors: Vec<[u8; 3]>,
}

impl Arrays {
    fn base(&self) -> u32 {
        (self.vertices.len() / 3) as u32
    }

    fn push_points(&mut self, points: impl IntoIterator<Item = Vec3>) {
        for p in points {
            self.vertices.extend_from_slice(&p.to_array());
        }
    }

    /// A polygon over vertices `base..base + points.len()`, as triangles of group `tag`.
    fn push_polygon(&mut self, base: u32, points: &[Vec3], tag: u32, corners: impl Fn(u32) -> u32) {
        for t in triangulate_polygon(points) {
            self.faces.extend(t.map(|i| base + corners(i)));
            self.tags.push(tag);
        }
    }

    /// Gives the triangles added since `from` (a face count) group `tag`.
    fn tag_since(&mut self, from: usize, tag: u32) {
        self.tags.resize(self.tags.len() + (self.faces.len() / 3 - from), tag);
    }
}

/// `scene` as arrays: instances, polygons, polylines (vertices only),
/// block meshes (merged per block state), surfaces.
pub fn arrays(scene: &Scene, tess: Tessellation) -> Arrays {
    // A flat drawing as polygons and surfaces turned to +y up, as the OBJ,
    // PLY and STL writers give them.
    let drawn = genform_export::drawing_geometry(scene);
    let scene = &*genform_export::surfaces_y_up(&drawn);
    let tag_colors = scene.tags.iter().map(|t| genform_export::tag_color(t)).collect();
    let mut out = Arrays { tag_names: scene.tags.clone(), tag_colors, ..Arrays::default() };
    let mut cache: Vec<(Primitive, Mesh)> = Vec::new();
    for inst in &scene.instances {
        let mesh: &Mesh = match inst.primitive {
            Primitive::Mesh(id) => &scene.meshes[id as usize],
            p => {
                let i = cache.iter().position(|(q, _)| *q == p).unwrap_or_else(|| {
                    cache.push((p, unit_mesh(p, tess)));
                    cache.len() - 1
                });
                &cache[i].1
            }
        };
        let base = out.base();
        out.push_points(mesh.positions.iter().map(|&p| inst.transform.transform_point3(p)));
        let flip = inst.transform.matrix3.determinant() < 0.0;
        for t in &mesh.triangles {
            let [a, b, c] = t.map(|v| base + v);
            out.faces.extend(if flip { [a, c, b] } else { [a, b, c] });
            out.tags.push(inst.tag);
        }
    }
    for poly in scene.polygons.iter().filter(|p| p.points.len() >= 3) {
        let base = out.base();
        out.push_points(poly.points.iter().copied());
        out.push_polygon(base, &poly.points, poly.tag, |i| i);
    }
    for line in scene.polylines.iter().filter(|l| l.points.len() >= 2) {
        out.push_points(line.points.iter().copied());
    }
    for (state, mesh) in block_meshes(scene) {
        let base = out.base();
        let (from, tag) = (out.faces.len() / 3, out.tag_names.len() as u32);
        out.tag_names.push(state.to_string());
        out.tag_colors.push(genform_export::minecraft::block_color(&state));
        out.push_points(mesh.positions.iter().copied());
        out.faces.extend(mesh.triangles.iter().flat_map(|t| t.map(|v| base + v)));
        out.tag_since(from, tag);
    }
    for surface in &scene.surfaces {
        let base = out.base();
        out.push_points(surface.positions.iter().copied());
        for face in surface.faces() {
            let points: Vec<Vec3> = face.iter().map(|&v| surface.positions[v as usize]).collect();
            out.push_polygon(base, &points, surface.tag, |i| face[i as usize]);
        }
    }
    out
}

/// The block grids' greedy meshes, one per block state across all grids,
/// in first-seen order (as the OBJ writer merges them).
fn block_meshes(scene: &Scene) -> Vec<(genform_core::BlockState, Mesh)> {
    let mut out: Vec<(genform_core::BlockState, Mesh)> = Vec::new();
    for grid in &scene.blocks {
        for m in genform_export::minecraft::mesh_blocks(grid) {
            match out.iter_mut().find(|(s, _)| *s == m.state) {
                Some((_, o)) => {
                    let b = o.positions.len() as u32;
                    o.positions.extend_from_slice(&m.mesh.positions);
                    o.triangles.extend(m.mesh.triangles.iter().map(|t| t.map(|v| v + b)));
                }
                None => out.push((m.state, m.mesh)),
            }
        }
    }
    out
}
