//! Binary little-endian PLY.

use genform_core::scene::{Scene, Tessellation};
use glam::Vec3;

/// Writes every triangle of `scene` (instances, polygons and block-grid
/// meshes, in world space)
/// as a binary little-endian PLY 1.0 file.
///
/// The header declares `element vertex N` with `float x y z` and
/// `element face M` with `list uchar int vertex_indices`. Vertices are not
/// welded: each triangle has its own three, so `N = 3 M`. Polylines are
/// left out.
///
/// # Panics
///
/// If an instance refers to a missing mesh asset (see [`crate::export`],
/// which checks).
pub fn write_ply(scene: &Scene, tess: Tessellation) -> Vec<u8> {
    let mut verts: Vec<u8> = Vec::new();
    let mut faces = 0usize;
    let mut add = |t: [Vec3; 3]| {
        for p in t {
            for c in p.to_array() {
                verts.extend_from_slice(&c.to_le_bytes());
            }
        }
        faces += 1;
    };
    scene.for_each_triangle(tess, |t, _| add(t));
    crate::minecraft::for_each_block_triangle(scene, |t, _| add(t));
    let header = format!(
        "ply\nformat binary_little_endian 1.0\ncomment genform\nelement vertex {}\n\
         property float x\nproperty float y\nproperty float z\nelement face {faces}\n\
         property list uchar int vertex_indices\nend_header\n",
        3 * faces
    );
    let mut out = Vec::with_capacity(header.len() + verts.len() + faces * 13);
    out.extend_from_slice(header.as_bytes());
    out.extend_from_slice(&verts);
    for f in 0..faces {
        out.push(3);
        for v in 0..3 {
            out.extend_from_slice(&((3 * f + v) as i32).to_le_bytes());
        }
    }
    out
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
        assert_eq!(bytes.len() - end, 72 * 12 + 24 * 13);
        // The first vertex is a corner of the first box.
        let x = f32::from_le_bytes(bytes[end..end + 4].try_into().unwrap());
        assert_eq!(x.abs(), 0.5);
        // The last face points at the last three vertices.
        let tail = &bytes[bytes.len() - 13..];
        assert_eq!(tail[0], 3);
        assert_eq!(i32::from_le_bytes(tail[9..13].try_into().unwrap()), 71);
    }
}
