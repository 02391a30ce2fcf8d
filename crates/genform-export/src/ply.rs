//! Binary little-endian PLY.

use genform_core::SurfaceEdge;
use genform_core::scene::{Scene, Tessellation};
use glam::Vec3;

use crate::minecraft::block_color;
use crate::palette::tag_color;

/// Writes `scene` as a binary little-endian PLY 1.0 file: every triangle
/// (instances, polygons and block-grid meshes, in world space), and the
/// surfaces as polygons with their typed edges.
///
/// The header declares `element vertex N` with `float x y z` and
/// `uchar red green blue` (the tag's colour, as the GLB's material has it;
/// a block's colour from the block palette), and
/// `element face M` with `list uchar int vertex_indices` (`list int int`
/// when a surface face has more than 255 corners). Triangles come first;
/// their vertices are not welded: each has its own three. Then each
/// surface's vertices (shared by its faces) and its faces, whole and
/// counter-clockwise from the front. When the scene has surfaces an
/// `element surface_edge` follows with `int vertex1`, `int vertex2` and
/// `int type` per surface edge (`type` −1 for [`SurfaceEdge::UNTYPED`]),
/// in surface and edge order. Not `element edge`: readers take an `edge`
/// element for a wireframe of exactly two indices (trimesh refuses a third
/// property and turns edges into a path, dropping the faces), and skip
/// elements they do not know, so the typed edges travel beside the mesh
/// without stopping any reader from opening it. Polylines and guides are
/// left out.
///
/// # Panics
///
/// If an instance refers to a missing mesh asset or a surface to a missing
/// vertex (see [`crate::export`], which checks).
pub fn write_ply(scene: &Scene, tess: Tessellation) -> Vec<u8> {
    let mut verts: Vec<u8> = Vec::new();
    let mut triangles = 0usize;
    let mut add = |t: [Vec3; 3], rgb: [u8; 3]| {
        for p in t {
            push_point(&mut verts, p);
            verts.extend_from_slice(&rgb);
        }
        triangles += 1;
    };
    // Vertex colours: a tag's colour as in the GLB's materials, a block's
    // as in its block palette.
    let mut by_tag: Vec<Option<[u8; 3]>> = vec![None; scene.tags.len() + 1];
    let mut color_of = |tag: u32| -> [u8; 3] {
        let i = (tag as usize).min(scene.tags.len());
        *by_tag[i].get_or_insert_with(|| tag_color(&name_of(scene, tag)))
    };
    crate::surfaces::without_surfaces(scene).for_each_triangle(tess, |t, tag| add(t, color_of(tag)));
    crate::minecraft::for_each_block_triangle(scene, |t, state| add(t, block_color(state)));
    let mut vertex_count = 3 * triangles;
    for s in &scene.surfaces {
        let rgb = color_of(s.tag);
        s.positions.iter().for_each(|&p| {
            push_point(&mut verts, p);
            verts.extend_from_slice(&rgb);
        });
        vertex_count += s.positions.len();
    }
    let faces = triangles + scene.surfaces.iter().map(|s| s.face_count()).sum::<usize>();
    let wide = scene.surfaces.iter().flat_map(|s| s.faces()).any(|f| f.len() > usize::from(u8::MAX));
    let mut header = format!(
        "ply\nformat binary_little_endian 1.0\ncomment genform\nelement vertex {vertex_count}\n\
         property float x\nproperty float y\nproperty float z\n\
         property uchar red\nproperty uchar green\nproperty uchar blue\nelement face {faces}\n\
         property list {} int vertex_indices\n",
        if wide { "int" } else { "uchar" }
    );
    if let Some(origin) = &scene.origin {
        // A comment line after `comment genform`, where readers skip it.
        header = header.replacen(
            "comment genform\n",
            &format!("comment genform\ncomment origin: {}\n", origin.replace('\n', " ")),
            1,
        );
    }
    if !scene.surfaces.is_empty() {
        let edges: usize = scene.surfaces.iter().map(|s| s.edges.len()).sum();
        header.push_str(&format!(
            "element surface_edge {edges}\nproperty int vertex1\nproperty int vertex2\nproperty int type\n"
        ));
    }
    header.push_str("end_header\n");
    let mut out = Vec::with_capacity(header.len() + verts.len() + faces * 13);
    out.extend_from_slice(header.as_bytes());
    out.extend_from_slice(&verts);
    let count = |out: &mut Vec<u8>, n: usize| {
        if wide {
            out.extend_from_slice(&(n as i32).to_le_bytes());
        } else {
            out.push(n as u8);
        }
    };
    for f in 0..triangles {
        count(&mut out, 3);
        for v in 0..3 {
            out.extend_from_slice(&((3 * f + v) as i32).to_le_bytes());
        }
    }
    let mut base = 3 * triangles;
    let mut bases = Vec::with_capacity(scene.surfaces.len());
    for s in &scene.surfaces {
        bases.push(base);
        for face in s.faces() {
            count(&mut out, face.len());
            for &v in face {
                out.extend_from_slice(&((base + v as usize) as i32).to_le_bytes());
            }
        }
        base += s.positions.len();
    }
    for (s, base) in scene.surfaces.iter().zip(bases) {
        for e in &s.edges {
            let kind = if e.kind == SurfaceEdge::UNTYPED { -1 } else { e.kind as i32 };
            for x in [(base + e.a as usize) as i32, (base + e.b as usize) as i32, kind] {
                out.extend_from_slice(&x.to_le_bytes());
            }
        }
    }
    out
}

/// A tag's name as the GLB names its material (`tag{k}` when unnamed).
fn name_of(scene: &Scene, tag: u32) -> String {
    scene.tags.get(tag as usize).cloned().unwrap_or_else(|| format!("tag{tag}"))
}

fn push_point(out: &mut Vec<u8>, p: Vec3) {
    for c in p.to_array() {
        out.extend_from_slice(&c.to_le_bytes());
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::test_scenes;

    #[test]
    fn header_and_body_agree() {
        let s = test_scenes::boxes(2);
        let bytes = write_ply(&s, Tessellation::default());
        let end = bytes.windows(11).position(|w| w == b"end_header\n").unwrap() + 11;
        let header = std::str::from_utf8(&bytes[..end]).unwrap();
        assert!(header.starts_with("ply\nformat binary_little_endian 1.0\n"));
        assert!(header.contains("element vertex 72\n"));
        assert!(header.contains("property float x\nproperty float y\nproperty float z\n"));
        assert!(header.contains("element face 24\nproperty list uchar int vertex_indices\n"));
        assert!(header.contains("property uchar red\nproperty uchar green\nproperty uchar blue\n"));
        assert_eq!(bytes.len() - end, 72 * 15 + 24 * 13);
        // The first vertex is a corner of the first box, in its tag's colour.
        let x = f32::from_le_bytes(bytes[end..end + 4].try_into().unwrap());
        assert_eq!(x.abs(), 0.5);
        let rgb = &bytes[end + 12..end + 15];
        assert_eq!(rgb, tag_color(&name_of(&s, s.instances[0].tag)));
        // The last face points at the last three vertices.
        let tail = &bytes[bytes.len() - 13..];
        assert_eq!(tail[0], 3);
        assert_eq!(i32::from_le_bytes(tail[9..13].try_into().unwrap()), 71);
    }
}
