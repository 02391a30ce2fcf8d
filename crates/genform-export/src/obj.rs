//! Wavefront OBJ text.

use crate::granularity::Granularity;
use crate::palette::{explicit_color, tag_color};
use crate::shapes::{Shapes, tag_name};
use crate::stl::face_normal;
use crate::uv::{face_axes, polygon_normal, texture_coords};
use genform_core::scene::{Scene, TagId, Tessellation, Texture};
use glam::Vec3;
use std::collections::BTreeMap;
use std::fmt::Write;

/// Writes `scene` as Wavefront OBJ text, split into objects by
/// [`Granularity::Auto`]; see [`write_obj_with`].
///
/// # Panics
///
/// If an instance refers to a missing mesh asset (see [`crate::export`],
/// which checks).
pub fn write_obj(scene: &Scene, tess: Tessellation) -> String {
    write_obj_with(scene, tess, Granularity::Auto)
}

/// Writes `scene` as Wavefront OBJ text, its instances and polygons split
/// into objects as `granularity` says ([`Granularity::resolve`] decides
/// `Auto` from the count of instances and polygons).
///
/// An instance is its unit mesh transformed to world space (`v` lines),
/// then its triangles (`f`, counter-clockwise from outside, also for
/// reflected instances): a box gives 8 vertices and 12 faces. A polygon is
/// one n-gon face.
///
/// - [`Granularity::Instanced`]: OBJ has no instancing, so one object per
///   instance (`o <tag>_<index>`, `index` being its position in
///   [`Scene::instances`]), each with its own vertices, then one object per
///   polygon (`o <tag>_polygon<k>`).
/// - [`Granularity::PerTag`]: one object per tag (`o <tag>`, tag order)
///   holding its instances (in order) and then its polygons.
/// - [`Granularity::Merged`]: one object `o model` with one group per tag
///   (`g <tag>`), each as in `PerTag`. OBJ without a material library has
///   no materials, so the tag groups stand in for them.
///
/// In every mode, vertices are not shared between instances, then come one
/// object per polyline (`o <tag>_polyline<k>`, one `l` statement), one
/// object per block state of the block grids (`o <state>`, the greedy mesh
/// of [`crate::minecraft::mesh_blocks`], quads as two triangles), and one
/// object per surface (`o <tag>_surface<k>`): its vertices, its faces as
/// polygons (`f`, counter-clockwise from the front, not triangulated),
/// then its edges as two-point `l` lines, one group per edge type in
/// ascending order, `g <tag>_surface<k>_edges_type<N>`, untyped edges last
/// in `g <tag>_surface<k>_edges_untyped`. Guides are left out. No normals
/// and no materials ([`write_obj_materials`] adds them); texture
/// coordinates only on the faces of textured tags (as
/// [`write_obj_materials`] says). Numbers are printed with at most 6
/// decimals, trailing zeros trimmed, so the text is identical from run to
/// run.
///
/// # Panics
///
/// If an instance refers to a missing mesh asset (see [`crate::export`],
/// which checks).
pub fn write_obj_with(scene: &Scene, tess: Tessellation, granularity: Granularity) -> String {
    write(scene, tess, granularity, None).0
}

/// [`write_obj_with`] with materials: the OBJ names the material library
/// `mtl_file` (`mtllib`, a file name relative to the OBJ, as readers look
/// for it beside the OBJ) and says `usemtl <name>` before each part's
/// faces and lines; returns the OBJ text and the `.mtl` text.
///
/// One material per tag (named like the tag's objects with `#` as `_`, its colour from
/// [`tag_color`], so the OBJ shows the GLB's colours), per block id
/// (`minecraft:stone`, [`crate::minecraft::block_color`]) and per surface
/// edge type (`edge<N>`, [`crate::edge_color`]), in first-use order: `Kd`
/// the colour as displayed (sRGB, 0–1, 4 decimals; MTL names no colour
/// space and most viewers show `Kd` as given), `Ka` 0, `Ks` 0, `d` 1,
/// `illum 1` (diffuse only).
///
/// A textured tag ([`Scene::texture_of`]) gets texture coordinates (`vt`,
/// one per face corner, projected from world positions onto the face's
/// plane as for GLB ([`crate::write_glb_with`]), `v` up) on its faces (`f v/vt …`) and
/// `map_Kd` naming the image's file beside the OBJ
/// ([`obj_texture_file`]), with `Kd` white or the tag's `#rrggbb` (which
/// tints it). Writing the image files is the caller's
/// ([`crate::obj_texture_files`]).
pub fn write_obj_materials(
    scene: &Scene,
    tess: Tessellation,
    granularity: Granularity,
    mtl_file: &str,
) -> (String, String) {
    write(scene, tess, granularity, Some(mtl_file))
}

/// The name of the file beside an OBJ that its material library
/// `mtl_file` names for `texture` (`map_Kd`): the library's stem, the
/// texture's name, `.png` (`house.mtl` → `house.brick.png`), so models
/// written side by side keep their images apart and none replaces the
/// grammar's own image.
pub fn obj_texture_file(mtl_file: &str, texture: &Texture) -> String {
    let stem = mtl_file.strip_suffix(".mtl").unwrap_or(mtl_file);
    format!("{stem}.{}.png", texture.name)
}

/// Materials in first-use order, written as `usemtl` lines when on.
struct Materials<'a> {
    /// The library's file name, when materials are on.
    mtl: Option<&'a str>,
    /// Name, colour, image file (`map_Kd`).
    list: Vec<(String, [u8; 3], Option<String>)>,
}

impl Materials<'_> {
    /// `usemtl name`, adding the material on first use.
    fn use_(&mut self, out: &mut String, name: &str, rgb: [u8; 3]) {
        self.use_with(out, name, rgb, None);
    }

    fn use_with(&mut self, out: &mut String, name: &str, rgb: [u8; 3], map: Option<String>) {
        if self.mtl.is_none() {
            return;
        }
        if !self.list.iter().any(|(n, _, _)| n == name) {
            self.list.push((name.to_string(), rgb, map));
        }
        let _ = writeln!(out, "usemtl {name}");
    }

    fn tag(&mut self, out: &mut String, scene: &Scene, tag: TagId) {
        // `#` starts a comment in many MTL readers: `leaf#3a7d23` → `leaf_3a7d23`.
        let name = tag_name(scene, tag).replace('#', "_");
        let full = scene.tags.get(tag as usize).map_or("", String::as_str);
        match (scene.texture_of(tag), self.mtl) {
            (Some(t), Some(mtl)) => {
                let rgb = explicit_color(full).unwrap_or([255; 3]);
                self.use_with(out, &name, rgb, Some(obj_texture_file(mtl, t)));
            }
            _ => self.use_(out, &name, tag_color(full)),
        }
    }

    /// The `.mtl` text.
    fn library(&self) -> String {
        let mut out = String::from("# genform\n");
        for (name, rgb, map) in &self.list {
            let _ = writeln!(out, "newmtl {name}");
            out.push_str("Kd");
            for c in rgb {
                let _ = write!(out, " {}", trimmed(f32::from(*c) / 255.0, 4));
            }
            out.push_str("\nKa 0 0 0\nKs 0 0 0\nd 1\nillum 1\n");
            if let Some(file) = map {
                let _ = writeln!(out, "map_Kd {file}");
            }
        }
        out
    }
}

/// `x` with `decimals` decimals, trailing zeros trimmed.
fn trimmed(x: f32, decimals: usize) -> String {
    let s = format!("{x:.decimals$}");
    if s.contains('.') { s.trim_end_matches('0').trim_end_matches('.').to_string() } else { s }
}

fn write(scene: &Scene, tess: Tessellation, granularity: Granularity, mtl: Option<&str>) -> (String, String) {
    let shapes = Shapes::new(scene, tess);
    let mut out = String::with_capacity(64 + scene.instances.len() * 400);
    out.push_str("# genform\n");
    if let Some(origin) = &scene.origin {
        let _ = writeln!(out, "# origin: {}", origin.replace('\n', " "));
    }
    let mut mats = Materials { mtl, list: Vec::new() };
    if let Some(file) = mtl {
        let _ = writeln!(out, "mtllib {file}");
    }
    // OBJ indices are 1-based and global (`vt` have their own).
    let mut next = 1usize;
    let mut next_vt = 1usize;
    let polygons = || scene.polygons.iter().enumerate().filter(|(_, p)| p.points.len() >= 3);
    let mode = granularity.resolve(scene.instances.len() + scene.polygons.len());
    if mode == Granularity::Instanced {
        for (i, inst) in scene.instances.iter().enumerate() {
            let _ = writeln!(out, "o {}_{i}", tag_name(scene, inst.tag));
            mats.tag(&mut out, scene, inst.tag);
            match scene.texture_of(inst.tag) {
                Some(t) => textured_instance(&mut out, [&mut next, &mut next_vt], &shapes, scene, i, t.size),
                None => instance(&mut out, &mut next, &shapes, scene, i),
            }
        }
        for (k, p) in polygons() {
            let _ = writeln!(out, "o {}_polygon{k}", tag_name(scene, p.tag));
            mats.tag(&mut out, scene, p.tag);
            match scene.texture_of(p.tag) {
                Some(t) => textured_polygon(&mut out, [&mut next, &mut next_vt], &p.points, t.size),
                None => run(&mut out, &mut next, 'f', &p.points),
            }
        }
    } else {
        // Per tag: its instances and polygons, each in scene order.
        let mut by_tag: BTreeMap<TagId, (Vec<usize>, Vec<usize>)> = BTreeMap::new();
        for (i, inst) in scene.instances.iter().enumerate() {
            by_tag.entry(inst.tag).or_default().0.push(i);
        }
        for (k, p) in polygons() {
            by_tag.entry(p.tag).or_default().1.push(k);
        }
        let merged = mode == Granularity::Merged;
        if merged && !by_tag.is_empty() {
            out.push_str("o model\n");
        }
        for (tag, (instances, polys)) in by_tag {
            let _ = writeln!(out, "{} {}", if merged { 'g' } else { 'o' }, tag_name(scene, tag));
            mats.tag(&mut out, scene, tag);
            let texture = scene.texture_of(tag).map(|t| t.size);
            for i in instances {
                match texture {
                    Some(size) => textured_instance(&mut out, [&mut next, &mut next_vt], &shapes, scene, i, size),
                    None => instance(&mut out, &mut next, &shapes, scene, i),
                }
            }
            for k in polys {
                let points = &scene.polygons[k].points;
                match texture {
                    Some(size) => textured_polygon(&mut out, [&mut next, &mut next_vt], points, size),
                    None => run(&mut out, &mut next, 'f', points),
                }
            }
        }
    }
    // Polylines become one line element (`l`) each.
    for (k, l) in scene.polylines.iter().enumerate().filter(|(_, l)| l.points.len() >= 2) {
        let _ = writeln!(out, "o {}_polyline{k}", tag_name(scene, l.tag));
        mats.tag(&mut out, scene, l.tag);
        run(&mut out, &mut next, 'l', l.points);
    }
    for m in crate::minecraft::block_meshes(scene) {
        let _ = writeln!(out, "o {}", m.mesh.name);
        mats.use_(&mut out, &m.state.name, crate::minecraft::block_color(&m.state));
        for &p in &m.mesh.positions {
            vertex(&mut out, p);
        }
        for t in &m.mesh.triangles {
            let [a, b, c] = t.map(|v| next + v as usize);
            let _ = writeln!(out, "f {a} {b} {c}");
        }
        next += m.mesh.positions.len();
    }
    for (k, surface) in scene.surfaces.iter().enumerate() {
        let name = crate::surfaces::surface_name(scene, k);
        let _ = writeln!(out, "o {name}");
        mats.tag(&mut out, scene, surface.tag);
        for &p in &surface.positions {
            vertex(&mut out, p);
        }
        for face in surface.faces() {
            out.push('f');
            for &v in face {
                let _ = write!(out, " {}", next + v as usize);
            }
            out.push('\n');
        }
        for (kind, pairs) in crate::surfaces::edges_by_type(surface) {
            if kind == genform_core::SurfaceEdge::UNTYPED {
                let _ = writeln!(out, "g {name}_edges_untyped");
            } else {
                let _ = writeln!(out, "g {name}_edges_type{kind}");
            }
            mats.use_(&mut out, &crate::palette::edge_type_name(kind), crate::palette::edge_color(kind));
            for [a, b] in pairs {
                let _ = writeln!(out, "l {} {}", next + a as usize, next + b as usize);
            }
        }
        next += surface.positions.len();
    }
    let library = mats.library();
    (out, library)
}

/// Instance `i`'s world-space vertices and triangles (faces kept outward
/// for reflections).
fn instance(out: &mut String, next: &mut usize, shapes: &Shapes, scene: &Scene, i: usize) {
    let inst = &scene.instances[i];
    let mesh = shapes.of(i);
    for &p in &mesh.positions {
        vertex(out, inst.transform.transform_point3(p));
    }
    let flip = inst.transform.matrix3.determinant() < 0.0;
    for t in &mesh.triangles {
        let [a, b, c] = t.map(|v| *next + v as usize);
        let (b, c) = if flip { (c, b) } else { (b, c) };
        let _ = writeln!(out, "f {a} {b} {c}");
    }
    *next += mesh.positions.len();
}

/// [`instance`] with texture coordinates: one `vt` per triangle corner,
/// projected onto the triangle's plane ([`crate::uv`]), in copies of an
/// image covering `size` world units.
fn textured_instance(
    out: &mut String,
    [next, next_vt]: [&mut usize; 2],
    shapes: &Shapes,
    scene: &Scene,
    i: usize,
    size: [f32; 2],
) {
    let inst = &scene.instances[i];
    let mesh = shapes.of(i);
    let world: Vec<Vec3> = mesh.positions.iter().map(|&p| inst.transform.transform_point3(p)).collect();
    for &p in &world {
        vertex(out, p);
    }
    let flip = inst.transform.matrix3.determinant() < 0.0;
    for t in &mesh.triangles {
        let t = if flip { [t[0], t[2], t[1]] } else { *t };
        let corners = t.map(|v| world[v as usize]);
        let axes = face_axes(face_normal(corners));
        for p in corners {
            texture_vertex(out, texture_coords(p, axes, size));
        }
        let [a, b, c] = t.map(|v| *next + v as usize);
        let vt = *next_vt;
        let _ = writeln!(out, "f {a}/{vt} {b}/{} {c}/{}", vt + 1, vt + 2);
        *next_vt += 3;
    }
    *next += mesh.positions.len();
}

/// A polygon as one face `f v/vt …` with texture coordinates projected
/// onto its plane.
fn textured_polygon(out: &mut String, [next, next_vt]: [&mut usize; 2], points: &[Vec3], size: [f32; 2]) {
    let axes = face_axes(polygon_normal(points));
    for &p in points {
        vertex(out, p);
    }
    for &p in points {
        texture_vertex(out, texture_coords(p, axes, size));
    }
    out.push('f');
    for k in 0..points.len() {
        let _ = write!(out, " {}/{}", *next + k, *next_vt + k);
    }
    out.push('\n');
    *next += points.len();
    *next_vt += points.len();
}

/// A `vt u v` line.
fn texture_vertex(out: &mut String, [u, v]: [f32; 2]) {
    out.push_str("vt ");
    number(out, u);
    out.push(' ');
    number(out, v);
    out.push('\n');
}

/// `points` as vertices and one element over them all: `f` (an n-gon) or
/// `l` (a line).
fn run(out: &mut String, next: &mut usize, element: char, points: &[Vec3]) {
    for &p in points {
        vertex(out, p);
    }
    out.push(element);
    for v in *next..*next + points.len() {
        let _ = write!(out, " {v}");
    }
    out.push('\n');
    *next += points.len();
}

/// A `v x y z` line.
fn vertex(out: &mut String, p: Vec3) {
    out.push('v');
    for c in p.to_array() {
        out.push(' ');
        number(out, c);
    }
    out.push('\n');
}

/// `x` with 6 decimals, trailing zeros (and a bare point) trimmed, `-0` as `0`.
pub(crate) fn number(out: &mut String, x: f32) {
    let start = out.len();
    let _ = write!(out, "{x:.6}");
    if out[start..].contains('.') {
        let keep = out.trim_end_matches('0').trim_end_matches('.').len();
        out.truncate(keep);
    }
    if &out[start..] == "-0" {
        out.truncate(start);
        out.push('0');
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::test_scenes;

    fn count(text: &str, prefix: &str) -> usize {
        text.lines().filter(|l| l.starts_with(prefix)).count()
    }

    #[test]
    fn numbers_are_short_and_stable() {
        let cases = [
            (0.0, "0"),
            (-0.0, "0"),
            (-1e-9, "0"),
            (1.5, "1.5"),
            (-2.0, "-2"),
            (0.1, "0.1"),
            (0.49999997, "0.5"),
            (1234.5677, "1234.567749"),
            (10.0, "10"),
        ];
        for (x, want) in cases {
            let mut s = String::from("v ");
            number(&mut s, x);
            assert_eq!(&s[2..], want, "{x}");
        }
    }

    #[test]
    fn one_object_per_box_instance() {
        let s = test_scenes::boxes(3);
        let text = write_obj(&s, Tessellation::default());
        assert_eq!(count(&text, "o "), 3);
        assert_eq!(count(&text, "v "), 24);
        assert_eq!(count(&text, "f "), 36);
        assert!(text.contains("\no hull_0\n") && text.contains("\no hull_2\n"));
        // The second box starts at x = 2 - 0.5.
        assert!(text.contains("\nv 1.5 -0.5 -0.5\n"), "{text}");
        // Face indices of the third object point at its own vertices.
        let last = text.lines().rev().find(|l| l.starts_with("f ")).unwrap();
        assert!(last.split_whitespace().skip(1).all(|v| (17..=24).contains(&v.parse::<usize>().unwrap())));
    }

    #[test]
    fn faces_stay_outward_for_reflected_instances() {
        let s = test_scenes::mixed();
        let text = write_obj(&s, Tessellation::default());
        // Re-read and sum the signed volume object by object.
        let mut verts: Vec<Vec3> = Vec::new();
        let mut vol = Vec::new();
        for line in text.lines() {
            let mut it = line.split_whitespace();
            match it.next() {
                Some("o") => vol.push((it.next().unwrap().to_string(), 0.0f64)),
                Some("v") => {
                    let c: Vec<f32> = it.map(|t| t.parse().unwrap()).collect();
                    verts.push(Vec3::new(c[0], c[1], c[2]));
                }
                Some("f") => {
                    let idx: Vec<usize> = it.map(|t| t.parse::<usize>().unwrap() - 1).collect();
                    let [a, b, c] = [verts[idx[0]], verts[idx[1]], verts[idx[2]]];
                    vol.last_mut().unwrap().1 += f64::from(a.dot(b.cross(c))) / 6.0;
                }
                _ => {}
            }
        }
        // All instances but the flattened one have positive volume.
        assert_eq!(vol.len(), 16 + 1 + 1);
        for (i, (name, v)) in vol.iter().enumerate().take(16) {
            if i == 14 {
                assert!(v.abs() < 1e-4, "{name}: {v}");
            } else {
                assert!(*v > 1e-3, "{name}: {v}");
            }
        }
        assert!(text.contains("\no roof_tile_1") || text.contains("\no roof_tile_14"));
        assert!(text.contains("\no roof_tile_polygon0\n") && text.contains("\no trunk_polyline0\n"));
        assert!(text.contains("\nl ") && text.lines().any(|l| l.starts_with("f ") && l.split(' ').count() == 5));
    }

    #[test]
    fn block_grids_are_objects_per_state() {
        use genform_core::blocks::{BlockGrid, BlockState};
        use glam::{IVec3, UVec3};
        let mut s = test_scenes::boxes(1);
        let mut g = BlockGrid::new(IVec3::new(0, 5, 0), UVec3::new(2, 1, 1));
        g.set(IVec3::new(0, 5, 0), &BlockState::new("stone"));
        g.set(IVec3::new(1, 5, 0), &BlockState::new("stone"));
        s.blocks.push(g);
        let text = write_obj(&s, Tessellation::default());
        assert!(text.contains("\no minecraft:stone\n"), "{text}");
        // The box (8 vertices, 12 faces), then the bar: 6 quads.
        assert_eq!(count(&text, "v "), 8 + 24);
        assert_eq!(count(&text, "f "), 12 + 12);
        assert!(text.contains("\nv 2 6 1\n"));
        let last = text.lines().rev().find(|l| l.starts_with("f ")).unwrap();
        assert!(last.split_whitespace().skip(1).all(|v| (9..=32).contains(&v.parse::<usize>().unwrap())));
    }

    #[test]
    fn surfaces_keep_polygons_and_typed_edges() {
        let s = test_scenes::surfaces();
        let text = write_obj(&s, Tessellation::default());
        // The box first, then the two surfaces.
        assert_eq!(count(&text, "o "), 3);
        assert_eq!(count(&text, "v "), 8 + 9 + 25);
        assert_eq!(count(&text, "f "), 12 + 4 + 16);
        assert_eq!(count(&text, "l "), 12 + 40);
        let lines: Vec<&str> = text.lines().collect();
        let at = |l: &str| lines.iter().position(|x| *x == l).unwrap_or_else(|| panic!("no `{l}`"));
        let (o0, o1) = (at("o shell_surface0"), at("o shell_surface1"));
        let (g1, g2) = (at("g shell_surface0_edges_type1"), at("g shell_surface0_edges_type2"));
        let untyped = at("g shell_surface1_edges_untyped");
        assert!(o0 < g1 && g1 < g2 && g2 < o1 && o1 < untyped);
        // 8 boundary edges of type 1, then 4 inner ones of type 2.
        assert!(lines[g1 + 1..g2].iter().all(|l| l.starts_with("l ")) && g2 - g1 - 1 == 8);
        assert!(lines[g2 + 1..o1].iter().all(|l| l.starts_with("l ")) && o1 - g2 - 1 == 4);
        // Quads are kept whole and point at the surface's own vertices
        // (9..=17 after the box's 8).
        let faces: Vec<&str> = lines[o0..g1].iter().copied().filter(|l| l.starts_with("f ")).collect();
        assert_eq!(faces[0], "f 9 10 13 12");
        assert!(lines[g1 + 1].split_whitespace().skip(1).all(|v| (9..=17).contains(&v.parse::<usize>().unwrap())));
        assert!(text.contains("\nv 1 1 0.5\n"));
        // Guides are not written.
        assert!(!text.contains("boundary") && !text.contains("attractor"));
    }

    #[test]
    fn granularity_sets_objects_and_groups() {
        let s = test_scenes::mixed();
        let tess = Tessellation::default();
        let obj = |g| write_obj_with(&s, tess, g);
        let heads = |text: &str| -> Vec<String> {
            text.lines().filter(|l| l.starts_with("o ") || l.starts_with("g ")).map(String::from).collect()
        };
        let instanced = obj(Granularity::Instanced);
        assert_eq!(write_obj(&s, tess), instanced, "16 instances: one object each by default");
        assert_eq!(count(&instanced, "o "), 16 + 1 + 1);
        let merged = obj(Granularity::Merged);
        assert_eq!(heads(&merged), ["o model", "g wall", "g roof_tile", "g trunk", "o trunk_polyline0"]);
        let per_tag = obj(Granularity::PerTag);
        assert_eq!(heads(&per_tag), ["o wall", "o roof_tile", "o trunk", "o trunk_polyline0"]);
        // The same vertices and elements, only regrouped (OBJ never shares
        // vertices between instances).
        for text in [&merged, &per_tag] {
            for prefix in ["v ", "f ", "l "] {
                assert_eq!(count(text, prefix), count(&instanced, prefix), "{prefix}");
            }
        }
        // The roof tile's object holds its instances, then the polygon (a quad).
        let lines: Vec<&str> = per_tag.lines().collect();
        let at = |l: &str| lines.iter().position(|x| *x == l).unwrap();
        let roof = &lines[at("o roof_tile")..at("o trunk")];
        assert_eq!(roof.iter().rfind(|l| l.starts_with("f ")).unwrap().split(' ').count(), 5);
        // … as many faces as the instanced text's `roof_tile_*` objects.
        let mut faces_of_roof_objects = 0;
        let mut in_roof = false;
        for l in instanced.lines() {
            if let Some(name) = l.strip_prefix("o ") {
                in_roof = name.starts_with("roof_tile_");
            }
            faces_of_roof_objects += usize::from(in_roof && l.starts_with("f "));
        }
        assert!(faces_of_roof_objects > 12);
        assert_eq!(roof.iter().filter(|l| l.starts_with("f ")).count(), faces_of_roof_objects);
    }

    #[test]
    fn large_models_merge_by_default() {
        let tess = Tessellation::default();
        let text = write_obj(&test_scenes::boxes(crate::AUTO_MERGE_ABOVE + 1), tess);
        assert_eq!(text.lines().filter(|l| l.starts_with("o ") || l.starts_with("g ")).count(), 2);
        assert!(text.starts_with("# genform\no model\ng hull\n"));
        assert_eq!(count(&text, "f "), 12 * (crate::AUTO_MERGE_ABOVE + 1));
        let small = write_obj(&test_scenes::boxes(crate::AUTO_MERGE_ABOVE), tess);
        assert_eq!(count(&small, "o "), crate::AUTO_MERGE_ABOVE);
    }

    #[test]
    fn text_is_deterministic() {
        let s = test_scenes::mixed();
        assert_eq!(write_obj(&s, Tessellation::default()), write_obj(&s.clone(), Tessellation::default()));
    }

    #[test]
    fn materials_name_every_part_and_read_back() {
        let mut s = test_scenes::surfaces();
        let leaf = s.tag("leaf#3a7d23");
        s.polygons.push(genform_core::scene::Polygon { points: vec![Vec3::ZERO, Vec3::X, Vec3::Y], tag: leaf });
        let (obj, mtl) = write_obj_materials(&s, Tessellation::default(), Granularity::Auto, "m.mtl");
        assert!(obj.starts_with("# genform\nmtllib m.mtl\n"));
        // Without materials the text is the plain OBJ.
        let plain: String = obj
            .lines()
            .filter(|l| !l.starts_with("mtllib") && !l.starts_with("usemtl"))
            .map(|l| format!("{l}\n"))
            .collect();
        assert_eq!(plain, write_obj_with(&s, Tessellation::default(), Granularity::Auto));
        let load = tobj::LoadOptions { triangulate: false, ignore_lines: false, ..Default::default() };
        let (models, mats) = tobj::load_obj_buf(&mut std::io::Cursor::new(obj.as_bytes()), &load, |p| {
            assert_eq!(p, std::path::Path::new("m.mtl"));
            tobj::load_mtl_buf(&mut std::io::Cursor::new(mtl.as_bytes()))
        })
        .unwrap();
        let mats = mats.unwrap();
        let names: Vec<&str> = mats.iter().map(|m| m.name.as_str()).collect();
        assert_eq!(names, ["hull", "leaf_3a7d23", "shell", "edge1", "edge2", "edge_untyped"]);
        let kd = |n: &str| mats.iter().find(|m| m.name == n).unwrap().diffuse.unwrap();
        assert_eq!(kd("leaf_3a7d23"), [0.2275, 0.4902, 0.1373]);
        let hull = tag_color("hull");
        assert_eq!(kd("hull"), hull.map(|c| (f32::from(c) / 255.0 * 1e4).round() / 1e4));
        assert_eq!(kd("edge1"), crate::edge_color(1).map(|c| (f32::from(c) / 255.0 * 1e4).round() / 1e4));
        assert!(models.iter().all(|m| m.mesh.material_id.is_some()), "every part has a material");
    }

    #[test]
    fn textured_tags_get_texture_coordinates_and_map_kd() {
        let s = test_scenes::textured_wall();
        for granularity in [Granularity::Instanced, Granularity::PerTag, Granularity::Merged] {
            let (obj, mtl) = write_obj_materials(&s, Tessellation::default(), granularity, "house.mtl");
            assert!(mtl.contains("newmtl wall\nKd 1 1 1\n") && mtl.contains("map_Kd house.brick.png\n"), "{mtl}");
            assert_eq!(mtl.matches("map_Kd").count(), 1, "the plain box has none");
            // Two textured boxes: 12 triangles each, one `vt` per corner.
            assert_eq!(count(&obj, "vt "), 2 * 12 * 3, "{granularity}");
            let vs: Vec<Vec3> = obj
                .lines()
                .filter_map(|l| l.strip_prefix("v "))
                .map(|l| {
                    let c: Vec<f32> = l.split(' ').map(|x| x.parse().unwrap()).collect();
                    Vec3::new(c[0], c[1], c[2])
                })
                .collect();
            let vts: Vec<[f32; 2]> = obj
                .lines()
                .filter_map(|l| l.strip_prefix("vt "))
                .map(|l| {
                    let c: Vec<f32> = l.split(' ').map(|x| x.parse().unwrap()).collect();
                    [c[0], c[1]]
                })
                .collect();
            // Every corner on the front (z = 0) has u = x / 2, v = y / 1.
            let mut front = 0;
            for l in obj.lines().filter(|l| l.starts_with("f ") && l.contains('/')) {
                let corners: Vec<(usize, usize)> = l[2..]
                    .split(' ')
                    .map(|c| c.split_once('/').map(|(v, t)| (v.parse().unwrap(), t.parse().unwrap())).unwrap())
                    .collect();
                if corners.iter().all(|&(v, _)| vs[v - 1].z.abs() < 1e-6) {
                    for (v, t) in corners {
                        let (p, uv) = (vs[v - 1], vts[t - 1]);
                        assert!((uv[0] - p.x / 2.0).abs() < 1e-5 && (uv[1] - p.y).abs() < 1e-5, "{p} → {uv:?}");
                        front += 1;
                    }
                }
            }
            assert_eq!(front, 2 * 2 * 3, "{granularity}: two front quads of two triangles");
        }
        assert_eq!(
            crate::obj_texture_files(&s, "house.mtl"),
            vec![("house.brick.png".to_string(), &s.textures[0].png[..])]
        );
    }
}
