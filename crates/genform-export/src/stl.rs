//! Binary STL.

use genform_core::scene::{Scene, Tessellation};
use glam::Vec3;

/// Writes every triangle of `scene` (instances, polygons, surface faces
/// split into triangles, and block-grid meshes, in world space) as binary
/// STL.
///
/// An 80-byte header starting with `genform` (zero padded), the triangle
/// count, then per triangle its unit normal (computed from the vertices;
/// zero for a degenerate triangle), the three vertices and a zero attribute
/// word. Polylines, surface edges and guides are left out.
///
/// # Panics
///
/// If an instance refers to a missing mesh asset or a surface to a missing
/// vertex (see [`crate::export`], which checks).
pub fn write_stl(scene: &Scene, tess: Tessellation) -> Vec<u8> {
    let mut out = vec![0u8; 84];
    out[..7].copy_from_slice(b"genform");
    let mut count = 0u32;
    let mut add = |t: [Vec3; 3]| {
        let n = face_normal(t);
        for v in [n, t[0], t[1], t[2]] {
            for c in v.to_array() {
                out.extend_from_slice(&c.to_le_bytes());
            }
        }
        out.extend_from_slice(&[0, 0]);
        count += 1;
    };
    scene.for_each_triangle(tess, |t, _| add(t));
    crate::minecraft::for_each_block_triangle(scene, |t, _| add(t));
    out[80..84].copy_from_slice(&count.to_le_bytes());
    out
}

/// The unit normal of a counter-clockwise triangle (computed in `f64`);
/// zero when degenerate or not finite.
pub(crate) fn face_normal([a, b, c]: [Vec3; 3]) -> Vec3 {
    let (a, b, c) = (a.as_dvec3(), b.as_dvec3(), c.as_dvec3());
    let n = (b - a).cross(c - a);
    let len = n.length();
    // `+ 0.0` folds `-0.0` so equal normals have equal bits.
    if len > 0.0 && len.is_finite() { (n / len).as_vec3() + Vec3::ZERO } else { Vec3::ZERO }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::test_scenes;

    #[test]
    fn triangle_count_and_normals() {
        let s = test_scenes::boxes(3);
        let bytes = write_stl(&s, Tessellation::default());
        assert_eq!(&bytes[..8], b"genform\0");
        let n = u32::from_le_bytes(bytes[80..84].try_into().unwrap());
        assert_eq!(n, 36);
        assert_eq!(bytes.len(), 84 + 36 * 50);
        for tri in bytes[84..].chunks(50) {
            let f = |i: usize| f32::from_le_bytes(tri[4 * i..4 * i + 4].try_into().unwrap());
            let normal = Vec3::new(f(0), f(1), f(2));
            assert!((normal.length() - 1.0).abs() < 1e-6);
            // Axis-aligned boxes have axis-aligned normals.
            assert_eq!(normal.abs().max_element(), 1.0);
            let [a, b, c] = [1, 2, 3].map(|k| Vec3::new(f(3 * k), f(3 * k + 1), f(3 * k + 2)));
            assert!((b - a).cross(c - a).dot(normal) > 0.0);
            assert_eq!(&tri[48..], &[0, 0]);
        }
        assert_eq!(face_normal([Vec3::ZERO; 3]), Vec3::ZERO);
    }
}
