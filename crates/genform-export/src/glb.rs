//! Binary glTF 2.0 (GLB).

use crate::granularity::Granularity;
use crate::minecraft::{block_color, block_meshes};
use crate::palette::{edge_color, edge_type_name, explicit_color, srgb_to_linear, tag_color};
use crate::shapes::{Shapes, tag_name};
use crate::stl::face_normal;
use crate::uv::{face_axes, texture_coords};
use genform_core::blocks::BlockState;
use genform_core::scene::{Instance, Polygon, Scene, TagId, Tessellation, TextureId, triangulate_polygon};
use glam::{Affine3A, DMat4, Mat4, Vec3};
use serde_json::{Map, Value, json};
use std::collections::{BTreeMap, HashMap};

const ARRAY_BUFFER: u32 = 34962;
const ELEMENT_ARRAY_BUFFER: u32 = 34963;
const FLOAT: u32 = 5126;
const UNSIGNED_SHORT: u32 = 5123;
const UNSIGNED_INT: u32 = 5125;
/// A node rotation (x, y, z, w) of −90° about x: it takes a surface's
/// +z (up as grown) to glTF's +y and its +y to −z.
pub const Z_UP_TO_Y_UP: [f32; 4] = [-std::f32::consts::FRAC_1_SQRT_2, 0.0, 0.0, std::f32::consts::FRAC_1_SQRT_2];

const MODE_LINES: u32 = 1;
/// Sampler values: `REPEAT` wrapping, `LINEAR` magnification,
/// `LINEAR_MIPMAP_LINEAR` minification.
const REPEAT: u32 = 10497;
const LINEAR: u32 = 9729;
const LINEAR_MIPMAP_LINEAR: u32 = 9987;

/// Writes `scene` as binary glTF 2.0 (a `.glb` file), split into nodes
/// by [`Granularity::Auto`]; see [`write_glb_with`].
///
/// # Panics
///
/// If an instance refers to a missing mesh asset or a surface to a missing
/// vertex (see [`crate::export`], which checks).
pub fn write_glb(scene: &Scene, tess: Tessellation) -> Vec<u8> {
    write_glb_with(scene, tess, Granularity::Auto)
}

/// Writes `scene` as binary glTF 2.0 (a `.glb` file), its instances and
/// polygons split into nodes as `granularity` says
/// ([`Granularity::resolve`] decides `Auto` from the count of instances and polygons).
///
/// [`Granularity::Instanced`]:
/// - One set of vertex data per distinct primitive (box, each frustum or
///   tapered-box parameter, sphere, each mesh asset), flat shaded: `POSITION`
///   (with exact `min`/`max`), `NORMAL` and `u16`/`u32` indices, in the unit
///   frame. Degenerate triangles are dropped.
/// - One glTF mesh per (primitive, tag) pair in use, sharing that data, with
///   the tag's material.
/// - One node per instance, named `<tag>_<index>`, with the instance
///   transform as its `matrix` (omitted when identity; reflections are
///   allowed). glTF requires node matrices that decompose into
///   translation–rotation–scale, so instances whose transform is singular
///   (a zero scale) or sheared are instead baked into the world-space mesh
///   `baked`; instances with non-finite transforms are skipped.
/// - Polygons go into the world-space mesh `polygons` (double-sided
///   materials).
///
/// [`Granularity::Merged`]: every instance (transformed to world space,
/// faces kept outward for reflections) and every polygon in one mesh and
/// node `model`, one flat-shaded primitive per (tag, double-sided) in tag
/// order, polygons taking the double-sided material.
/// [`Granularity::PerTag`]: the same triangles, one mesh and node per tag,
/// named by the tag, in tag order.
///
/// Textured tags ([`Scene::texture_of`]) have their texture coordinates
/// projected from world positions onto each face's plane (`u` along its
/// horizontal, `v` up its slope, in world units from the world's origin
/// divided by the image's size; horizontal faces take world x and z), so
/// their instances are always in world space: in
/// [`Granularity::Instanced`] they go into `baked`.
///
/// In every mode:
/// - Polylines go into the mesh `polylines` as `LINES` primitives
///   (stroke widths are not kept).
/// - One material per tag: base color from [`crate::tag_color`] (converted to
///   linear), metallic 0, roughness 0.8. A textured tag's material has the
///   image as its `baseColorTexture` (the PNG embedded in the binary chunk,
///   one `image` per texture, one sampler repeating both ways) and a base
///   colour of white, or of the tag's `#rrggbb` (which tints the image);
///   its primitives have `TEXCOORD_0`.
/// - Block grids ([`Scene::blocks`]) as greedy meshes
///   ([`crate::minecraft::mesh_blocks`]) in world space: one mesh and node
///   per block state, named by the state (`minecraft:oak_stairs[facing=east]`);
///   one material per block id, named by the id, coloured by
///   [`crate::minecraft::block_color`].
/// - Surfaces ([`Scene::surfaces`]) last, one world-space mesh and node
///   each, named `<tag>_surface<k>`: a triangle primitive of the faces
///   (split by [`triangulate_polygon`], zero-area triangles dropped) with
///   smooth area-weighted vertex normals and the tag's double-sided
///   material, then one `LINES` primitive per edge type in ascending order
///   (untyped last), sharing the surface's `POSITION` accessor, with the
///   material `edge<N>` (`edge_untyped`) coloured by [`crate::edge_color`].
///   Surfaces grow with +z as the seed's normal (HEMLS) while glTF's up is
///   +y, so their nodes carry a −90° turn about x (the vertices stay as grown).
///   Guides are not written.
///
/// # Panics
///
/// If an instance refers to a missing mesh asset or a surface to a missing
/// vertex (see [`crate::export`], which checks).
pub fn write_glb_with(scene: &Scene, tess: Tessellation, granularity: Granularity) -> Vec<u8> {
    let shapes = Shapes::new(scene, tess);
    let mut doc = Doc::default();
    match granularity.resolve(scene.instances.len() + scene.polygons.len()) {
        Granularity::Merged => doc.grouped(scene, &shapes, false),
        Granularity::PerTag => doc.grouped(scene, &shapes, true),
        Granularity::Instanced | Granularity::Auto => doc.instanced(scene, &shapes),
    }
    doc.polylines(scene);
    doc.blocks(scene);
    doc.surfaces(scene);
    doc.finish(scene.origin.as_deref())
}

impl Doc {
    /// [`Granularity::Instanced`]: a node per instance over shared meshes,
    /// then the meshes `baked` and `polygons`.
    fn instanced(&mut self, scene: &Scene, shapes: &Shapes) {
        let doc = self;
        // Per shape: not built yet / built but empty / (position, normal, index) accessors.
        let mut shape_data: Vec<Option<Option<[usize; 3]>>> = vec![None; shapes.meshes.len()];
        let mut mesh_of: HashMap<(u32, TagId), usize> = HashMap::new();
        let mut baked: BTreeMap<TagId, Vec<Flat>> = BTreeMap::new();

        for (i, inst) in scene.instances.iter().enumerate() {
            match placement(&inst.transform) {
                Placement::Skip => continue,
                Placement::Bake => world_triangles(shapes, i, inst, baked.entry(inst.tag).or_default()),
                // World-anchored texture coordinates are not shared.
                Placement::Node(_) if scene.texture_of(inst.tag).is_some() => {
                    world_triangles(shapes, i, inst, baked.entry(inst.tag).or_default())
                }
                Placement::Node(matrix) => {
                    let s = shapes.of_instance[i];
                    let data = *shape_data[s as usize].get_or_insert_with(|| {
                        let m = &shapes.meshes[s as usize];
                        let tris = m.triangles.iter().map(|t| t.map(|v| m.positions[v as usize]));
                        doc.flat_geometry(tris.map(|t| (t, face_normal(t))))
                    });
                    let Some([pos, nrm, idx]) = data else { continue };
                    let mesh = match mesh_of.get(&(s, inst.tag)) {
                        Some(&m) => m,
                        None => {
                            let material = doc.material(scene, inst.tag, false);
                            let name = format!("{}.{}", shapes.meshes[s as usize].name, tag_name(scene, inst.tag));
                            let prim = json!({
                                "attributes": {"POSITION": pos, "NORMAL": nrm},
                                "indices": idx,
                                "material": material,
                            });
                            doc.meshes.push(json!({"name": name, "primitives": [prim]}));
                            mesh_of.insert((s, inst.tag), doc.meshes.len() - 1);
                            doc.meshes.len() - 1
                        }
                    };
                    let mut node = Map::new();
                    node.insert("name".into(), format!("{}_{i}", tag_name(scene, inst.tag)).into());
                    node.insert("mesh".into(), mesh.into());
                    if matrix != Mat4::IDENTITY {
                        node.insert("matrix".into(), floats(&matrix.to_cols_array()));
                    }
                    doc.nodes.push(Value::Object(node));
                }
            }
        }

        doc.world_mesh(scene, "baked", &baked, false);
        let mut polygons: BTreeMap<TagId, Vec<Flat>> = BTreeMap::new();
        for poly in &scene.polygons {
            polygon_triangles(poly, polygons.entry(poly.tag).or_default());
        }
        doc.world_mesh(scene, "polygons", &polygons, true);
    }

    /// [`Granularity::Merged`] (one node `model`) or, when `per_tag`,
    /// [`Granularity::PerTag`] (one node per tag): instances and polygons in
    /// world space, one primitive per (tag, double-sided).
    fn grouped(&mut self, scene: &Scene, shapes: &Shapes, per_tag: bool) {
        let mut tris: BTreeMap<(TagId, bool), Vec<Flat>> = BTreeMap::new();
        for (i, inst) in scene.instances.iter().enumerate() {
            if Mat4::from(inst.transform).is_finite() {
                world_triangles(shapes, i, inst, tris.entry((inst.tag, false)).or_default());
            }
        }
        for poly in &scene.polygons {
            polygon_triangles(poly, tris.entry((poly.tag, true)).or_default());
        }
        let mut prims: Vec<(TagId, Value)> = Vec::new();
        for (&(tag, double_sided), t) in &tris {
            if let Some(prim) = self.tag_primitive(scene, tag, double_sided, t) {
                prims.push((tag, prim));
            }
        }
        if !per_tag {
            self.named_mesh_node("model", prims.into_iter().map(|(_, p)| p).collect());
            return;
        }
        let mut prims = prims.into_iter().peekable();
        while let Some((tag, first)) = prims.next() {
            let mut group = vec![first];
            while let Some((_, p)) = prims.next_if(|(t, _)| *t == tag) {
                group.push(p);
            }
            self.named_mesh_node(&tag_name(scene, tag), group);
        }
    }
}

/// A triangle and its flat normal.
type Flat = ([Vec3; 3], Vec3);

/// Appends instance `i`'s non-degenerate triangles in world space, wound
/// counter-clockwise from outside also when its transform is a reflection.
///
/// The normal is the unit-frame face normal carried through the inverse
/// transpose rather than recomputed from the world positions, so the two
/// halves of a flat quad keep bit-identical normals and share vertices as
/// they do in the unit frame; where that disagrees with the world face
/// normal (a singular transform, float noise on a sliver), the latter wins.
fn world_triangles(shapes: &Shapes, i: usize, inst: &Instance, out: &mut Vec<Flat>) {
    let mesh = shapes.of(i);
    let flip = inst.transform.matrix3.determinant() < 0.0;
    let normal_matrix = inst.transform.matrix3.inverse().transpose();
    for t in &mesh.triangles {
        let unit = t.map(|v| mesh.positions[v as usize]);
        let [a, b, c] = unit.map(|p| inst.transform.transform_point3(p));
        let world = if flip { [a, c, b] } else { [a, b, c] };
        let seen = face_normal(world);
        if seen == Vec3::ZERO {
            continue;
        }
        let carried = (normal_matrix * face_normal(unit)).normalize_or_zero();
        out.push((world, if carried.is_finite() && carried.dot(seen) > 0.9999 { carried } else { seen }));
    }
}

/// Appends a polygon's triangles (split by [`triangulate_polygon`]) with
/// their face normals; polygons with non-finite points add nothing.
fn polygon_triangles(poly: &Polygon, out: &mut Vec<Flat>) {
    if poly.points.iter().all(|p| p.is_finite()) {
        let tris = triangulate_polygon(&poly.points).into_iter().map(|t| t.map(|k| poly.points[k as usize]));
        out.extend(tris.map(|t| (t, face_normal(t))));
    }
}

/// What to do with an instance transform.
enum Placement {
    /// A node with this matrix.
    Node(Mat4),
    /// Not expressible as a glTF node matrix: bake into world space.
    Bake,
    /// Not finite: leave out.
    Skip,
}

/// Decides how an instance goes into glTF: a node if its matrix is finite,
/// clearly invertible and decomposes into translation, rotation and
/// (possibly negative) scale, i.e. its columns are orthogonal up to a
/// relative 1e-4.
///
/// The validator compares a matrix with its own TRS recomposition to an
/// absolute tolerance, so even float noise fails for large scales: the
/// matrix written is the exact recomposition (columns re-orthogonalized in
/// `f64`), which moves no vertex by more than 1e-4 of the instance size.
fn placement(t: &Affine3A) -> Placement {
    if !Mat4::from(*t).is_finite() {
        return Placement::Skip;
    }
    let c = [t.matrix3.x_axis, t.matrix3.y_axis, t.matrix3.z_axis].map(|c| c.as_dvec3());
    let s = c.map(|c| c.length());
    if s[0] * s[1] * s[2] < 1e-24 || s.iter().any(|&l| l < 1e-12 * s[0].max(s[1]).max(s[2])) {
        return Placement::Bake;
    }
    for (i, j) in [(0, 1), (0, 2), (1, 2)] {
        if c[i].dot(c[j]).abs() > 1e-4 * s[i] * s[j] {
            return Placement::Bake;
        }
    }
    let u0 = c[0] / s[0];
    let u1 = (c[1] - c[1].dot(u0) * u0).normalize();
    let u2 = u0.cross(u1);
    let u2 = if u2.dot(c[2]) < 0.0 { -u2 } else { u2 };
    let m = DMat4::from_cols(
        (u0 * s[0]).extend(0.0),
        (u1 * s[1]).extend(0.0),
        (u2 * s[2]).extend(0.0),
        t.translation.as_dvec3().extend(1.0),
    );
    Placement::Node(m.as_mat4())
}

/// The glTF document being built and its binary chunk.
#[derive(Default)]
struct Doc {
    bin: Vec<u8>,
    views: Vec<Value>,
    accessors: Vec<Value>,
    meshes: Vec<Value>,
    nodes: Vec<Value>,
    materials: Vec<Value>,
    material_of: HashMap<(TagId, bool), usize>,
    block_material_of: HashMap<String, usize>,
    edge_material_of: HashMap<u32, usize>,
    textured_material_of: HashMap<(TagId, bool), usize>,
    /// Scene texture → glTF texture.
    texture_of: HashMap<TextureId, usize>,
    images: Vec<Value>,
    samplers: Vec<Value>,
    textures: Vec<Value>,
}

impl Doc {
    /// Appends `bytes` as a new bufferView (4-byte aligned) and returns its index.
    fn view(&mut self, bytes: &[u8], target: u32) -> usize {
        self.bin.resize(self.bin.len().next_multiple_of(4), 0);
        self.views.push(json!({
            "buffer": 0,
            "byteOffset": self.bin.len(),
            "byteLength": bytes.len(),
            "target": target,
        }));
        self.bin.extend_from_slice(bytes);
        self.views.len() - 1
    }

    /// A `VEC3` float accessor over `data` (non-empty); with `min`/`max` when
    /// `bounds`.
    fn vec3(&mut self, data: &[Vec3], bounds: bool) -> usize {
        let mut bytes = Vec::with_capacity(data.len() * 12);
        for v in data {
            for c in v.to_array() {
                bytes.extend_from_slice(&c.to_le_bytes());
            }
        }
        let view = self.view(&bytes, ARRAY_BUFFER);
        let mut acc = json!({"bufferView": view, "componentType": FLOAT, "count": data.len(), "type": "VEC3"});
        if bounds {
            let (lo, hi) = data.iter().fold((data[0], data[0]), |(lo, hi), &p| (lo.min(p), hi.max(p)));
            acc["min"] = floats(&lo.to_array());
            acc["max"] = floats(&hi.to_array());
        }
        self.accessors.push(acc);
        self.accessors.len() - 1
    }

    /// A `SCALAR` index accessor, `u16` when every index fits below the
    /// `u16` primitive-restart value, else `u32`.
    fn indices(&mut self, idx: &[u32], vertex_count: usize) -> usize {
        let (bytes, ty) = if vertex_count < usize::from(u16::MAX) {
            (idx.iter().flat_map(|&i| (i as u16).to_le_bytes()).collect::<Vec<u8>>(), UNSIGNED_SHORT)
        } else {
            (idx.iter().flat_map(|&i| i.to_le_bytes()).collect(), UNSIGNED_INT)
        };
        let view = self.view(&bytes, ELEMENT_ARRAY_BUFFER);
        self.accessors.push(json!({"bufferView": view, "componentType": ty, "count": idx.len(), "type": "SCALAR"}));
        self.accessors.len() - 1
    }

    /// Flat-shaded vertex data for triangles, each with its normal:
    /// vertices shared only between triangles with the same position and
    /// normal; triangles with a zero normal (degenerate) dropped. `None`
    /// when nothing is left.
    fn flat_geometry(&mut self, tris: impl Iterator<Item = Flat>) -> Option<[usize; 3]> {
        let (pos, nrm, _, idx) = self.welded(tris, None)?;
        Some([pos, nrm, idx])
    }

    /// [`Doc::flat_geometry`]'s accessors (positions, normals, indices),
    /// with texture coordinates when `size` is given: each vertex's world
    /// position projected onto its face's plane ([`crate::uv`]) in copies
    /// of an image covering `size` world units; `v` negated, since glTF's
    /// runs down the image. The coordinates follow from position and
    /// normal, so welding on both shares exactly the vertices whose
    /// coordinates agree.
    fn welded(
        &mut self,
        tris: impl Iterator<Item = Flat>,
        size: Option<[f32; 2]>,
    ) -> Option<(usize, usize, Option<usize>, usize)> {
        let (mut pos, mut nrm, mut uvs, mut idx) = (Vec::new(), Vec::new(), Vec::new(), Vec::new());
        // FxHash: SipHash was a fifth of writing a million-segment drawing.
        let mut weld: rustc_hash::FxHashMap<([u32; 3], [u32; 3]), u32> = Default::default();
        for (t, n) in tris {
            if n == Vec3::ZERO || !t.iter().all(|p| p.is_finite()) {
                continue;
            }
            let axes = size.map(|size| (face_axes(n), size));
            for p in t {
                let key = (p.to_array().map(f32::to_bits), n.to_array().map(f32::to_bits));
                let v = *weld.entry(key).or_insert_with(|| {
                    pos.push(p);
                    nrm.push(n);
                    if let Some((axes, size)) = axes {
                        let [u, v] = texture_coords(p, axes, size);
                        // `+ 0.0` folds −0 so equal coordinates have equal bits.
                        uvs.push([u + 0.0, -v + 0.0]);
                    }
                    (pos.len() - 1) as u32
                });
                idx.push(v);
            }
        }
        if idx.is_empty() {
            return None;
        }
        let p = self.vec3(&pos, true);
        let n = self.vec3(&nrm, false);
        let uv = size.map(|_| {
            let mut bytes = Vec::with_capacity(uvs.len() * 8);
            for c in uvs.iter().flatten() {
                bytes.extend_from_slice(&c.to_le_bytes());
            }
            let view = self.view(&bytes, ARRAY_BUFFER);
            self.accessors
                .push(json!({"bufferView": view, "componentType": FLOAT, "count": uvs.len(), "type": "VEC2"}));
            self.accessors.len() - 1
        });
        Some((p, n, uv, self.indices(&idx, pos.len())))
    }

    /// The material index of `tag` (double-sided or not), added on first use.
    fn material(&mut self, scene: &Scene, tag: TagId, double_sided: bool) -> usize {
        if let Some(&m) = self.material_of.get(&(tag, double_sided)) {
            return m;
        }
        let name = scene.tags.get(tag as usize).cloned().unwrap_or_else(|| format!("tag{tag}"));
        let rgb = tag_color(&name).map(|c| f64::from((srgb_to_linear(c) * 10_000.0).round()) / 10_000.0);
        let m = self.push_material(&name, rgb, None, double_sided);
        self.material_of.insert((tag, double_sided), m);
        m
    }

    /// Adds the material `name` of base colour `rgb` (linear), with the
    /// texture `texture` as its base colour texture if any; returns its
    /// index.
    fn push_material(&mut self, name: &str, rgb: [f64; 3], texture: Option<usize>, double_sided: bool) -> usize {
        let mut pbr = json!({"baseColorFactor": [rgb[0], rgb[1], rgb[2], 1.0]});
        if let Some(index) = texture {
            pbr["baseColorTexture"] = json!({"index": index});
        }
        pbr["metallicFactor"] = 0.0.into();
        pbr["roughnessFactor"] = 0.8.into();
        let mut mat = json!({"name": name, "pbrMetallicRoughness": pbr});
        if double_sided {
            mat["doubleSided"] = true.into();
            mat["name"] = format!("{name} (double-sided)").into();
        }
        self.materials.push(mat);
        self.materials.len() - 1
    }

    /// A node and mesh of world-space triangles, one primitive per tag.
    fn world_mesh(&mut self, scene: &Scene, name: &str, tris: &BTreeMap<TagId, Vec<Flat>>, double_sided: bool) {
        let mut prims = Vec::new();
        for (&tag, t) in tris {
            prims.extend(self.tag_primitive(scene, tag, double_sided, t));
        }
        self.named_mesh_node(name, prims);
    }

    /// The primitive of `tag`'s world-space triangles `tris` with its
    /// material: flat-shaded, with texture coordinates when the tag is
    /// textured. `None` when no triangle is left.
    fn tag_primitive(&mut self, scene: &Scene, tag: TagId, double_sided: bool, tris: &[Flat]) -> Option<Value> {
        let textured = scene.tag_textures.iter().find(|(t, _)| *t == tag).map(|&(_, x)| x);
        if let Some(texture) = textured.filter(|&x| (x as usize) < scene.textures.len()) {
            let size = scene.textures[texture as usize].size;
            let (pos, nrm, uv, idx) = self.welded(tris.iter().copied(), Some(size))?;
            let material = self.textured_material(scene, tag, texture, double_sided);
            return Some(json!({
                "attributes": {"POSITION": pos, "NORMAL": nrm, "TEXCOORD_0": uv},
                "indices": idx,
                "material": material,
            }));
        }
        let [pos, nrm, idx] = self.flat_geometry(tris.iter().copied())?;
        let material = self.material(scene, tag, double_sided);
        Some(json!({"attributes": {"POSITION": pos, "NORMAL": nrm}, "indices": idx, "material": material}))
    }

    /// The material of textured `tag` (double-sided or not), added on first
    /// use: [`Doc::material`]'s, with the image as base colour texture and
    /// a white base colour unless the tag names a `#rrggbb`.
    fn textured_material(&mut self, scene: &Scene, tag: TagId, texture: TextureId, double_sided: bool) -> usize {
        if let Some(&m) = self.textured_material_of.get(&(tag, double_sided)) {
            return m;
        }
        let index = self.texture(scene, texture);
        let name = scene.tags.get(tag as usize).cloned().unwrap_or_else(|| format!("tag{tag}"));
        let rgb = explicit_color(&name)
            .map(|c| c.map(|c| f64::from((srgb_to_linear(c) * 10_000.0).round()) / 10_000.0))
            .unwrap_or([1.0; 3]);
        let m = self.push_material(&name, rgb, Some(index), double_sided);
        self.textured_material_of.insert((tag, double_sided), m);
        m
    }

    /// The glTF texture of scene texture `texture`, added on first use: its
    /// PNG as an image in the binary chunk, the one repeating sampler.
    fn texture(&mut self, scene: &Scene, texture: TextureId) -> usize {
        if let Some(&t) = self.texture_of.get(&texture) {
            return t;
        }
        let tex = &scene.textures[texture as usize];
        // An image's bufferView has no target (it is not vertex data).
        self.bin.resize(self.bin.len().next_multiple_of(4), 0);
        self.views.push(json!({"buffer": 0, "byteOffset": self.bin.len(), "byteLength": tex.png.len()}));
        self.bin.extend_from_slice(&tex.png);
        self.images.push(json!({"name": tex.name, "bufferView": self.views.len() - 1, "mimeType": "image/png"}));
        if self.samplers.is_empty() {
            self.samplers.push(json!({
                "magFilter": LINEAR,
                "minFilter": LINEAR_MIPMAP_LINEAR,
                "wrapS": REPEAT,
                "wrapT": REPEAT,
            }));
        }
        self.textures.push(json!({"name": tex.name, "sampler": 0, "source": self.images.len() - 1}));
        self.texture_of.insert(texture, self.textures.len() - 1);
        self.textures.len() - 1
    }

    /// The polylines as one mesh of `LINES` primitives, one per tag.
    fn polylines(&mut self, scene: &Scene) {
        let mut segs: BTreeMap<TagId, Vec<Vec3>> = BTreeMap::new();
        for l in &scene.polylines {
            if l.points.len() >= 2 && l.points.iter().all(|p| p.is_finite()) {
                segs.entry(l.tag).or_default().extend(l.points.windows(2).flatten());
            }
        }
        let mut prims = Vec::new();
        for (tag, pts) in segs {
            let pos = self.vec3(&pts, true);
            let material = self.material(scene, tag, false);
            prims.push(json!({"attributes": {"POSITION": pos}, "mode": MODE_LINES, "material": material}));
        }
        self.named_mesh_node("polylines", prims);
    }

    /// The block grids: one mesh and node per block state.
    fn blocks(&mut self, scene: &Scene) {
        for m in block_meshes(scene) {
            if m.mesh.triangles.is_empty() {
                continue;
            }
            let pos = self.vec3(&m.mesh.positions, true);
            let nrm = self.vec3(&m.normals, false);
            let flat: Vec<u32> = m.mesh.triangles.iter().flatten().copied().collect();
            let idx = self.indices(&flat, m.mesh.positions.len());
            let material = self.block_material(&m.state);
            let prim = json!({"attributes": {"POSITION": pos, "NORMAL": nrm}, "indices": idx, "material": material});
            self.named_mesh_node(&m.mesh.name, vec![prim]);
        }
    }

    /// The material of a block id (properties ignored), added on first use.
    fn block_material(&mut self, state: &BlockState) -> usize {
        if let Some(&m) = self.block_material_of.get(&state.name) {
            return m;
        }
        let rgb = block_color(state).map(|c| f64::from((srgb_to_linear(c) * 10_000.0).round()) / 10_000.0);
        self.materials.push(json!({
            "name": state.name,
            "pbrMetallicRoughness": {
                "baseColorFactor": [rgb[0], rgb[1], rgb[2], 1.0],
                "metallicFactor": 0.0,
                "roughnessFactor": 0.8,
            },
        }));
        self.block_material_of.insert(state.name.clone(), self.materials.len() - 1);
        self.materials.len() - 1
    }

    /// The surfaces: per surface one mesh and node of its faces and its
    /// edges, one `LINES` primitive per type.
    fn surfaces(&mut self, scene: &Scene) {
        for (k, s) in scene.surfaces.iter().enumerate() {
            if s.positions.is_empty() || !s.positions.iter().all(|p| p.is_finite()) {
                continue;
            }
            let mut tris = crate::surfaces::triangles(s);
            tris.retain(|t| face_normal(t.map(|v| s.positions[v as usize])) != Vec3::ZERO);
            let groups = crate::surfaces::edges_by_type(s);
            if tris.is_empty() && groups.is_empty() {
                continue;
            }
            let pos = self.vec3(&s.positions, true);
            let mut prims = Vec::new();
            if !tris.is_empty() {
                let normals = crate::surfaces::vertex_normals(s, &tris);
                let nrm = self.vec3(&normals, false);
                let flat: Vec<u32> = tris.iter().flatten().copied().collect();
                let idx = self.indices(&flat, s.positions.len());
                let material = self.material(scene, s.tag, true);
                prims.push(
                    json!({"attributes": {"POSITION": pos, "NORMAL": nrm}, "indices": idx, "material": material}),
                );
            }
            for (kind, pairs) in groups {
                let flat: Vec<u32> = pairs.iter().flatten().copied().collect();
                let idx = self.indices(&flat, s.positions.len());
                let material = self.edge_material(kind);
                prims.push(
                    json!({"attributes": {"POSITION": pos}, "indices": idx, "mode": MODE_LINES, "material": material}),
                );
            }
            self.named_mesh_node(&crate::surfaces::surface_name(scene, k), prims);
            if let Some(node) = self.nodes.last_mut() {
                node["rotation"] = json!(Z_UP_TO_Y_UP);
            }
        }
    }

    /// The material `edge<N>` of edge type `kind`, added on first use.
    fn edge_material(&mut self, kind: u32) -> usize {
        if let Some(&m) = self.edge_material_of.get(&kind) {
            return m;
        }
        let rgb = edge_color(kind).map(|c| f64::from((srgb_to_linear(c) * 10_000.0).round()) / 10_000.0);
        self.materials.push(json!({
            "name": edge_type_name(kind),
            "pbrMetallicRoughness": {
                "baseColorFactor": [rgb[0], rgb[1], rgb[2], 1.0],
                "metallicFactor": 0.0,
                "roughnessFactor": 0.8,
            },
        }));
        self.edge_material_of.insert(kind, self.materials.len() - 1);
        self.materials.len() - 1
    }

    fn named_mesh_node(&mut self, name: &str, prims: Vec<Value>) {
        if prims.is_empty() {
            return;
        }
        self.meshes.push(json!({"name": name, "primitives": prims}));
        self.nodes.push(json!({"name": name, "mesh": self.meshes.len() - 1}));
    }

    /// The GLB container: header, JSON chunk (space padded), BIN chunk
    /// (zero padded, left out when empty).
    fn finish(mut self, origin: Option<&str>) -> Vec<u8> {
        self.bin.resize(self.bin.len().next_multiple_of(4), 0);
        let mut root = Map::new();
        let mut asset = json!({"version": "2.0", "generator": "genform"});
        if let Some(o) = origin {
            // Where the model's (0, 0, 0) lies in the data it was built on.
            asset["extras"] = json!({ "origin": o });
        }
        root.insert("asset".into(), asset);
        let mut put = |key: &str, items: Vec<Value>| {
            if !items.is_empty() {
                root.insert(key.into(), Value::Array(items));
            }
        };
        let node_ids: Vec<Value> = (0..self.nodes.len()).map(Value::from).collect();
        let scene = if node_ids.is_empty() { json!({}) } else { json!({"nodes": node_ids}) };
        put("scenes", vec![scene]);
        put("nodes", self.nodes);
        put("meshes", self.meshes);
        put("materials", self.materials);
        put("textures", self.textures);
        put("images", self.images);
        put("samplers", self.samplers);
        put("accessors", self.accessors);
        put("bufferViews", self.views);
        if !self.bin.is_empty() {
            put("buffers", vec![json!({"byteLength": self.bin.len()})]);
        }
        root.insert("scene".into(), 0.into());
        let mut json = serde_json::to_vec(&Value::Object(root)).expect("JSON values always serialize");
        json.resize(json.len().next_multiple_of(4), b' ');

        let bin_chunk = if self.bin.is_empty() { 0 } else { 8 + self.bin.len() };
        let total = 12 + 8 + json.len() + bin_chunk;
        let mut out = Vec::with_capacity(total);
        out.extend_from_slice(b"glTF");
        out.extend_from_slice(&2u32.to_le_bytes());
        out.extend_from_slice(&(total as u32).to_le_bytes());
        out.extend_from_slice(&(json.len() as u32).to_le_bytes());
        out.extend_from_slice(b"JSON");
        out.extend_from_slice(&json);
        if !self.bin.is_empty() {
            out.extend_from_slice(&(self.bin.len() as u32).to_le_bytes());
            out.extend_from_slice(b"BIN\0");
            out.extend_from_slice(&self.bin);
        }
        out
    }
}

/// `f32`s as JSON numbers holding their exact values (so `min`/`max` match
/// the binary data bit for bit).
fn floats(v: &[f32]) -> Value {
    Value::Array(v.iter().map(|&x| Value::from(f64::from(x))).collect())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::AUTO_MERGE_ABOVE;
    use crate::test_scenes;

    /// A parsed GLB: its JSON and its binary chunk.
    fn parse(glb: &[u8]) -> (Value, Vec<u8>) {
        let u32_at = |o: usize| u32::from_le_bytes(glb[o..o + 4].try_into().unwrap()) as usize;
        assert_eq!(&glb[..4], b"glTF");
        assert_eq!(u32_at(4), 2);
        assert_eq!(u32_at(8), glb.len());
        let json_len = u32_at(12);
        assert_eq!(&glb[16..20], b"JSON");
        assert_eq!(json_len % 4, 0);
        let json: Value = serde_json::from_slice(&glb[20..20 + json_len]).unwrap();
        let rest = &glb[20 + json_len..];
        if rest.is_empty() {
            assert!(json.get("buffers").is_none());
            return (json, Vec::new());
        }
        let bin_len = u32::from_le_bytes(rest[..4].try_into().unwrap()) as usize;
        assert_eq!(&rest[4..8], b"BIN\0");
        assert_eq!(bin_len % 4, 0);
        assert_eq!(rest.len(), 8 + bin_len);
        assert_eq!(json["buffers"][0]["byteLength"], bin_len);
        (json, rest[8..].to_vec())
    }

    /// The `f32` vectors an accessor holds.
    fn read_vec3(json: &Value, bin: &[u8], acc: usize) -> Vec<Vec3> {
        let a = &json["accessors"][acc];
        let view = &json["bufferViews"][a["bufferView"].as_u64().unwrap() as usize];
        assert_eq!(a["componentType"], FLOAT);
        assert_eq!(view["target"], ARRAY_BUFFER);
        let off = view["byteOffset"].as_u64().unwrap() as usize;
        let count = a["count"].as_u64().unwrap() as usize;
        assert_eq!(view["byteLength"].as_u64().unwrap() as usize, count * 12);
        (0..count)
            .map(|i| {
                let f = |k: usize| f32::from_le_bytes(bin[off + 12 * i + 4 * k..][..4].try_into().unwrap());
                Vec3::new(f(0), f(1), f(2))
            })
            .collect()
    }

    fn as_vec3(v: &Value) -> Vec3 {
        let f = |i: usize| v[i].as_f64().unwrap() as f32;
        Vec3::new(f(0), f(1), f(2))
    }

    /// Checks every accessor against its data; returns the number of
    /// triangles drawn per mesh.
    fn check_accessors(json: &Value, bin: &[u8]) {
        for mesh in json["meshes"].as_array().unwrap() {
            for prim in mesh["primitives"].as_array().unwrap() {
                let pa = prim["attributes"]["POSITION"].as_u64().unwrap() as usize;
                let pos = read_vec3(json, bin, pa);
                let (lo, hi) = pos.iter().fold((pos[0], pos[0]), |(lo, hi), &p| (lo.min(p), hi.max(p)));
                assert_eq!(as_vec3(&json["accessors"][pa]["min"]), lo);
                assert_eq!(as_vec3(&json["accessors"][pa]["max"]), hi);
                if let Some(na) = prim["attributes"].get("NORMAL") {
                    let nrm = read_vec3(json, bin, na.as_u64().unwrap() as usize);
                    assert_eq!(nrm.len(), pos.len());
                    assert!(nrm.iter().all(|n| (n.length() - 1.0).abs() < 1e-5));
                }
                if let Some(ia) = prim.get("indices") {
                    let a = &json["accessors"][ia.as_u64().unwrap() as usize];
                    let view = &json["bufferViews"][a["bufferView"].as_u64().unwrap() as usize];
                    assert_eq!(view["target"], ELEMENT_ARRAY_BUFFER);
                    let off = view["byteOffset"].as_u64().unwrap() as usize;
                    assert_eq!(off % 4, 0);
                    let count = a["count"].as_u64().unwrap() as usize;
                    assert_eq!(count % if prim["mode"] == MODE_LINES { 2 } else { 3 }, 0);
                    let wide = a["componentType"] == UNSIGNED_INT;
                    for k in 0..count {
                        let i = if wide {
                            u32::from_le_bytes(bin[off + 4 * k..][..4].try_into().unwrap()) as usize
                        } else {
                            u16::from_le_bytes(bin[off + 2 * k..][..2].try_into().unwrap()) as usize
                        };
                        assert!(i < pos.len());
                    }
                }
            }
        }
    }

    #[test]
    fn boxes_make_one_mesh_and_a_node_each() {
        let s = test_scenes::boxes(5);
        let glb = write_glb(&s, Tessellation::default());
        let (json, bin) = parse(&glb);
        assert_eq!(json["asset"]["version"], "2.0");
        assert_eq!(json["asset"]["generator"], "genform");
        assert_eq!(json["nodes"].as_array().unwrap().len(), 5);
        assert_eq!(json["scenes"][0]["nodes"].as_array().unwrap().len(), 5);
        assert_eq!(json["meshes"].as_array().unwrap().len(), 1);
        assert_eq!(json["materials"].as_array().unwrap().len(), 1);
        assert_eq!(json["materials"][0]["pbrMetallicRoughness"]["roughnessFactor"], 0.8);
        check_accessors(&json, &bin);
        // Flat shading: 6 faces × 4 corners, 12 triangles.
        let pos = json["meshes"][0]["primitives"][0]["attributes"]["POSITION"].as_u64().unwrap() as usize;
        assert_eq!(json["accessors"][pos]["count"], 24);
        assert_eq!(as_vec3(&json["accessors"][pos]["min"]), Vec3::splat(-0.5));
        let idx = json["meshes"][0]["primitives"][0]["indices"].as_u64().unwrap() as usize;
        assert_eq!(json["accessors"][idx]["count"], 36);
        assert_eq!(json["accessors"][idx]["componentType"], UNSIGNED_SHORT);
        // The first box sits at the origin, so its node has no matrix.
        assert!(json["nodes"][0].get("matrix").is_none());
        assert_eq!(json["nodes"][2]["matrix"][12], 4.0);
        assert_eq!(json["nodes"][2]["name"], "hull_2");
    }

    #[test]
    fn mixed_scene_structure() {
        let s = test_scenes::mixed();
        let glb = write_glb(&s, Tessellation::default());
        let (json, bin) = parse(&glb);
        check_accessors(&json, &bin);
        let names: Vec<&str> = json["nodes"].as_array().unwrap().iter().map(|n| n["name"].as_str().unwrap()).collect();
        // 14 instance nodes (flattened and sheared boxes are baked), then the
        // world-space meshes.
        assert_eq!(names.len(), 14 + 3, "{names:?}");
        assert_eq!(&names[14..], ["baked", "polygons", "polylines"]);
        assert!(names[..14].iter().all(|n| n.contains('_')));
        // One vertex set per distinct primitive: 7 shapes × 3 accessors, plus
        // baked (2 tags), polygons (1 tag) and polylines (1 tag).
        assert_eq!(json["accessors"].as_array().unwrap().len(), 7 * 3 + 2 * 3 + 3 + 1);
        let lines = json["meshes"].as_array().unwrap().last().unwrap();
        assert_eq!(lines["primitives"][0]["mode"], MODE_LINES);
        let mats = json["materials"].as_array().unwrap();
        assert!(mats.iter().any(|m| m["doubleSided"] == true));
        // Reflected instances keep their negative-determinant matrix.
        let m = &json["nodes"][1]["matrix"];
        let m = Mat4::from_cols_array(&std::array::from_fn(|i| m[i].as_f64().unwrap() as f32));
        assert!(m.determinant() < 0.0);
    }

    #[test]
    fn block_grids_become_one_mesh_per_state() {
        use genform_core::blocks::BlockGrid;
        use glam::{IVec3, UVec3};
        let mut s = test_scenes::boxes(1);
        let mut g = BlockGrid::new(IVec3::new(10, 0, 0), UVec3::new(3, 2, 1));
        for x in 10..13 {
            g.set(IVec3::new(x, 0, 0), &BlockState::new("stone"));
        }
        g.set(IVec3::new(10, 1, 0), &BlockState::parse("oak_stairs[facing=east]").unwrap());
        g.set(IVec3::new(11, 1, 0), &BlockState::parse("oak_stairs[facing=west]").unwrap());
        g.set(IVec3::new(12, 1, 0), &BlockState::air());
        s.blocks.push(g);
        let (json, bin) = parse(&write_glb(&s, Tessellation::default()));
        check_accessors(&json, &bin);
        let names: Vec<&str> = json["nodes"].as_array().unwrap().iter().map(|n| n["name"].as_str().unwrap()).collect();
        assert_eq!(
            names,
            ["hull_0", "minecraft:stone", "minecraft:oak_stairs[facing=east]", "minecraft:oak_stairs[facing=west]"]
        );
        let mats: Vec<&str> =
            json["materials"].as_array().unwrap().iter().map(|m| m["name"].as_str().unwrap()).collect();
        assert_eq!(mats, ["hull", "minecraft:stone", "minecraft:oak_stairs"]);
        // The stone bar's top is covered by (solid) stairs except under the
        // air at x = 12. Positions lie on the grid.
        let stone = &json["meshes"][1]["primitives"][0];
        let pos = read_vec3(&json, &bin, stone["attributes"]["POSITION"].as_u64().unwrap() as usize);
        assert!(pos.iter().all(|p| *p == p.round()));
        let (lo, hi) = pos.iter().fold((pos[0], pos[0]), |(lo, hi), &p| (lo.min(p), hi.max(p)));
        assert_eq!((lo, hi), (Vec3::new(10.0, 0.0, 0.0), Vec3::new(13.0, 1.0, 1.0)));
        let idx = json["accessors"][stone["indices"].as_u64().unwrap() as usize]["count"].as_u64().unwrap();
        assert_eq!(idx, 6 * 6, "6 quads: bottom, top (only x = 12 shows), 4 sides");
    }

    #[test]
    fn empty_scene_is_a_valid_empty_document() {
        let (json, bin) = parse(&write_glb(&Scene::new(), Tessellation::default()));
        assert!(bin.is_empty());
        assert!(json.get("nodes").is_none() && json.get("meshes").is_none());
        assert_eq!(json["scene"], 0);
    }

    #[test]
    fn large_meshes_use_u32_indices() {
        let tess = Tessellation { radial: 400, rings: 200 };
        let mut s = Scene::new();
        s.instances.push(genform_core::Instance {
            transform: Affine3A::IDENTITY,
            primitive: genform_core::Primitive::Sphere,
            tag: 0,
        });
        let (json, bin) = parse(&write_glb(&s, tess));
        check_accessors(&json, &bin);
        assert_eq!(json["accessors"][2]["componentType"], UNSIGNED_INT);
    }

    #[test]
    fn surfaces_are_meshes_of_faces_and_typed_lines() {
        let s = test_scenes::surfaces();
        let (json, bin) = parse(&write_glb(&s, Tessellation::default()));
        check_accessors(&json, &bin);
        let names: Vec<&str> = json["nodes"].as_array().unwrap().iter().map(|n| n["name"].as_str().unwrap()).collect();
        assert_eq!(names, ["hull_0", "shell_surface0", "shell_surface1"]);
        // Surfaces are turned +z → +y (glTF's up); other nodes are not.
        let rotation = |n: usize| json["nodes"][n].get("rotation").cloned();
        assert_eq!(rotation(0), None);
        for n in [1, 2] {
            let q: Vec<f32> =
                rotation(n).unwrap().as_array().unwrap().iter().map(|v| v.as_f64().unwrap() as f32).collect();
            let turned = glam::Quat::from_xyzw(q[0], q[1], q[2], q[3]) * Vec3::Z;
            assert!(turned.abs_diff_eq(Vec3::Y, 1e-6), "{turned}");
        }
        let grid = &json["meshes"][1]["primitives"];
        assert_eq!(grid.as_array().unwrap().len(), 3, "faces, type 1, type 2");
        // The lines share the faces' positions: the grid's 9 vertices.
        let pos = &grid[0]["attributes"]["POSITION"];
        assert!((1..3).all(|i| grid[i]["attributes"]["POSITION"] == *pos && grid[i]["mode"] == MODE_LINES));
        assert_eq!(json["accessors"][pos.as_u64().unwrap() as usize]["count"], 9);
        let count = |p: &Value| json["accessors"][p["indices"].as_u64().unwrap() as usize]["count"].as_u64().unwrap();
        assert_eq!([count(&grid[0]), count(&grid[1]), count(&grid[2])], [4 * 6, 8 * 2, 4 * 2]);
        // Materials: the box, the double-sided shell, one per edge type,
        // each edge material shared between the surfaces.
        let mats: Vec<&str> =
            json["materials"].as_array().unwrap().iter().map(|m| m["name"].as_str().unwrap()).collect();
        assert_eq!(mats, ["hull", "shell (double-sided)", "edge1", "edge2", "edge_untyped"]);
        let smooth = &json["meshes"][2]["primitives"];
        assert_eq!(smooth[1]["material"], grid[1]["material"]);
        assert_eq!(smooth[3]["material"], 4);
        let rgb = crate::edge_color(2).map(|c| f64::from(srgb_to_linear(c)));
        let factor = &json["materials"][3]["pbrMetallicRoughness"]["baseColorFactor"];
        assert!((0..3).all(|i| (factor[i].as_f64().unwrap() - rgb[i]).abs() < 1e-4));
        // Smooth normals: the raised middle vertex of the grid points up.
        let normals = read_vec3(&json, &bin, grid[0]["attributes"]["NORMAL"].as_u64().unwrap() as usize);
        assert_eq!(normals[4], Vec3::Z);
    }

    /// The triangles of a mesh primitive, read through its indices.
    fn read_triangles(json: &Value, bin: &[u8], prim: &Value) -> Vec<[Vec3; 3]> {
        let pos = read_vec3(json, bin, prim["attributes"]["POSITION"].as_u64().unwrap() as usize);
        let a = &json["accessors"][prim["indices"].as_u64().unwrap() as usize];
        let off = json["bufferViews"][a["bufferView"].as_u64().unwrap() as usize]["byteOffset"].as_u64().unwrap();
        let wide = a["componentType"] == UNSIGNED_INT;
        let index = |k: usize| {
            let o = off as usize + k * if wide { 4 } else { 2 };
            if wide {
                u32::from_le_bytes(bin[o..o + 4].try_into().unwrap()) as usize
            } else {
                u16::from_le_bytes(bin[o..o + 2].try_into().unwrap()) as usize
            }
        };
        let count = a["count"].as_u64().unwrap() as usize;
        (0..count / 3).map(|t| [0, 1, 2].map(|c| pos[index(3 * t + c)])).collect()
    }

    /// Every triangle drawn, in world space (node matrices applied), by
    /// material name.
    fn world_triangles_by_material(glb: &[u8]) -> BTreeMap<String, Vec<[Vec3; 3]>> {
        let (json, bin) = parse(glb);
        check_accessors(&json, &bin);
        let mut out: BTreeMap<String, Vec<[Vec3; 3]>> = BTreeMap::new();
        for node in json["nodes"].as_array().unwrap() {
            let m = node.get("matrix").map_or(Mat4::IDENTITY, |m| {
                Mat4::from_cols_array(&std::array::from_fn(|i| m[i].as_f64().unwrap() as f32))
            });
            let mesh = &json["meshes"][node["mesh"].as_u64().unwrap() as usize];
            for prim in mesh["primitives"].as_array().unwrap() {
                if prim["mode"] == MODE_LINES {
                    continue;
                }
                let name = json["materials"][prim["material"].as_u64().unwrap() as usize]["name"].as_str().unwrap();
                let tris = read_triangles(&json, &bin, prim).into_iter().map(|t| t.map(|p| m.transform_point3(p)));
                out.entry(name.to_string()).or_default().extend(tris);
            }
        }
        out
    }

    fn node_names(json: &Value) -> Vec<&str> {
        json["nodes"].as_array().unwrap().iter().map(|n| n["name"].as_str().unwrap()).collect()
    }

    #[test]
    fn granularity_sets_nodes_and_meshes() {
        let s = test_scenes::mixed();
        let tess = Tessellation::default();
        let glb = |g| write_glb_with(&s, tess, g);
        // Small scenes default to one node per instance.
        assert_eq!(write_glb(&s, tess), glb(Granularity::Instanced));
        let (json, bin) = parse(&glb(Granularity::Merged));
        check_accessors(&json, &bin);
        assert_eq!(node_names(&json), ["model", "polylines"]);
        assert_eq!(json["meshes"].as_array().unwrap().len(), 2);
        // wall, roof tile, roof tile (double-sided, the polygon), trunk.
        let mats = |mesh: &Value| -> Vec<String> {
            let prims = mesh["primitives"].as_array().unwrap();
            prims
                .iter()
                .map(|p| json["materials"][p["material"].as_u64().unwrap() as usize]["name"].to_string())
                .collect()
        };
        assert_eq!(
            mats(&json["meshes"][0]),
            [r#""wall""#, r#""roof tile""#, r#""roof tile (double-sided)""#, r#""trunk""#]
        );
        assert!(json["nodes"][0].get("matrix").is_none());

        let (json, bin) = parse(&glb(Granularity::PerTag));
        check_accessors(&json, &bin);
        assert_eq!(node_names(&json), ["wall", "roof_tile", "trunk", "polylines"]);
        assert_eq!(json["meshes"].as_array().unwrap().len(), 4);
        assert_eq!(mats(&json["meshes"][1]), [r#""roof tile""#, r#""roof tile (double-sided)""#]);

        // 33 boxes: past the threshold, the default merges them.
        let many = test_scenes::boxes(AUTO_MERGE_ABOVE + 1);
        let (json, _) = parse(&write_glb(&many, tess));
        assert_eq!(node_names(&json), ["model"]);
        let idx = json["meshes"][0]["primitives"][0]["indices"].as_u64().unwrap() as usize;
        assert_eq!(json["accessors"][idx]["count"], 36 * (AUTO_MERGE_ABOVE + 1));
        // Turned and stretched boxes still weld each face's two triangles:
        // 24 vertices a box, as in the shared unit mesh.
        let mut turned = many.clone();
        for (i, inst) in turned.instances.iter_mut().enumerate() {
            let rot = glam::Quat::from_euler(glam::EulerRot::YXZ, 0.37 * i as f32, 1.1, -0.2 * i as f32);
            inst.transform =
                Affine3A::from_scale_rotation_translation(Vec3::new(0.01, 3.0, 1.7), rot, Vec3::splat(99.5))
                    * inst.transform;
        }
        let (json, _) = parse(&write_glb(&turned, tess));
        let pos = json["meshes"][0]["primitives"][0]["attributes"]["POSITION"].as_u64().unwrap() as usize;
        assert_eq!(json["accessors"][pos]["count"], 24 * (AUTO_MERGE_ABOVE + 1));
        let (json, _) = parse(&write_glb(&test_scenes::boxes(AUTO_MERGE_ABOVE), tess));
        assert_eq!(json["nodes"].as_array().unwrap().len(), AUTO_MERGE_ABOVE);
        assert_eq!(json["meshes"].as_array().unwrap().len(), 1, "instances share one mesh");
    }

    #[test]
    fn every_granularity_draws_the_same_triangles() {
        let s = test_scenes::mixed();
        let tess = Tessellation::default();
        // The merged mesh holds exactly the scene's non-degenerate
        // triangles, bit for bit, under their materials.
        let mut want: BTreeMap<String, Vec<[Vec3; 3]>> = BTreeMap::new();
        let double_sided: Vec<[Vec3; 3]> = s
            .polygons
            .iter()
            .flat_map(|p| triangulate_polygon(&p.points).into_iter().map(|t| t.map(|k| p.points[k as usize])))
            .collect();
        s.for_each_triangle(tess, |t, tag| {
            if face_normal(t) != Vec3::ZERO {
                let mut name = s.tags[tag as usize].clone();
                if double_sided.contains(&t) {
                    name.push_str(" (double-sided)");
                }
                want.entry(name).or_default().push(t);
            }
        });
        let bits = |tris: &[[Vec3; 3]]| {
            let mut b: Vec<[u32; 9]> =
                tris.iter().map(|t| std::array::from_fn(|k| t[k / 3].to_array()[k % 3].to_bits())).collect();
            b.sort_unstable();
            b
        };
        let merged = world_triangles_by_material(&write_glb_with(&s, tess, Granularity::Merged));
        assert_eq!(merged.keys().collect::<Vec<_>>(), want.keys().collect::<Vec<_>>());
        for (name, tris) in &want {
            assert_eq!(bits(&merged[name]), bits(tris), "{name}");
        }
        assert_eq!(world_triangles_by_material(&write_glb_with(&s, tess, Granularity::PerTag)), merged);
        // Instance nodes carry re-orthogonalized matrices: the same
        // triangles up to float noise (count, area, bounds).
        let instanced = world_triangles_by_material(&write_glb_with(&s, tess, Granularity::Instanced));
        assert_eq!(instanced.keys().collect::<Vec<_>>(), want.keys().collect::<Vec<_>>());
        let area =
            |t: &[[Vec3; 3]]| t.iter().map(|[a, b, c]| f64::from((*b - *a).cross(*c - *a).length())).sum::<f64>();
        let bounds = |t: &[[Vec3; 3]]| {
            t.iter().flatten().fold((Vec3::INFINITY, Vec3::NEG_INFINITY), |(lo, hi), &p| (lo.min(p), hi.max(p)))
        };
        for (name, tris) in &merged {
            let other = &instanced[name];
            assert_eq!(other.len(), tris.len(), "{name}");
            assert!((area(other) - area(tris)).abs() < 1e-4 * area(tris), "{name}");
            let ((a, b), (c, d)) = (bounds(other), bounds(tris));
            assert!(a.abs_diff_eq(c, 1e-4) && b.abs_diff_eq(d, 1e-4), "{name}");
        }
    }

    #[test]
    fn textured_tags_embed_their_image_and_carry_world_texture_coordinates() {
        let s = test_scenes::textured_wall();
        for granularity in [Granularity::Instanced, Granularity::Merged, Granularity::PerTag] {
            let glb = write_glb_with(&s, Tessellation::default(), granularity);
            // An independent reader sees the image, the sampler and the coordinates.
            let (doc, buffers, _) = gltf::import_slice(&glb).expect("a valid GLB");
            let image = doc.images().next().expect("one image");
            assert_eq!(doc.images().count(), 1);
            let gltf::image::Source::View { view, mime_type } = image.source() else { panic!("embedded") };
            assert_eq!(mime_type, "image/png");
            assert_eq!(&buffers[0][view.offset()..view.offset() + view.length()], &s.textures[0].png[..]);
            let sampler = doc.textures().next().unwrap().sampler();
            assert_eq!(sampler.wrap_s(), gltf::texture::WrappingMode::Repeat);
            assert_eq!(sampler.wrap_t(), gltf::texture::WrappingMode::Repeat);
            let mut front = Vec::new();
            let mut plain = 0;
            for mesh in doc.meshes() {
                for prim in mesh.primitives() {
                    let material = prim.material();
                    let reader = prim.reader(|b| Some(&buffers[b.index()]));
                    let textured = material.pbr_metallic_roughness().base_color_texture().is_some();
                    assert_eq!(textured, material.name().unwrap().starts_with("wall"), "{granularity}");
                    let Some(uv) = reader.read_tex_coords(0) else {
                        assert!(!textured);
                        plain += 1;
                        continue;
                    };
                    assert_eq!(
                        material.pbr_metallic_roughness().base_color_factor(),
                        [1.0; 4],
                        "white: the image as it is"
                    );
                    let uv: Vec<[f32; 2]> = uv.into_f32().collect();
                    let pos: Vec<[f32; 3]> = reader.read_positions().unwrap().collect();
                    let nrm: Vec<[f32; 3]> = reader.read_normals().unwrap().collect();
                    for ((p, n), t) in pos.iter().zip(&nrm).zip(&uv) {
                        if n[2] > 0.99 && p[2].abs() < 1e-6 {
                            front.push((*p, *t));
                        }
                    }
                }
            }
            assert_eq!(plain, 1, "{granularity}: the untextured box keeps its plain primitive");
            // The front of both pieces: u = x / 2 m, v = −y / 1 m (glTF's v runs
            // down the image), the shared edge at x = 1.5 with one value.
            assert!(front.len() >= 6, "{granularity}: {front:?}");
            for (p, t) in &front {
                assert!((t[0] - p[0] / 2.0).abs() < 1e-5 && (t[1] + p[1]).abs() < 1e-5, "{p:?} → {t:?}");
            }
            assert!(front.iter().any(|(p, _)| (p[0] - 1.5).abs() < 1e-6));
        }
    }

    #[test]
    fn scenes_without_textures_write_no_texture_coordinates() {
        let glb = write_glb(&test_scenes::mixed(), Tessellation::default());
        let (json, _) = parse(&glb);
        for key in ["images", "textures", "samplers"] {
            assert!(json.get(key).is_none(), "{key}");
        }
        assert!(!String::from_utf8_lossy(&glb).contains("TEXCOORD_0"));
    }

    #[test]
    fn output_is_deterministic() {
        let s = test_scenes::mixed();
        assert_eq!(write_glb(&s, Tessellation::default()), write_glb(&s.clone(), Tessellation::default()));
    }
}
