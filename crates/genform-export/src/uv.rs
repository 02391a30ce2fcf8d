//! Texture coordinates of textured tags ([`Scene::texture_of`]), projected
//! from world positions onto each face's own plane.
//!
//! The projection is anchored in the world, not in the face: `u` runs
//! along the face's horizontal in-plane direction, `v` up its slope (a
//! wall's up, a roof's fall line), both in world units from the world's
//! origin, divided by the size of one copy of the image. Two pieces of a
//! split wall, or the tiles of a facade, lie in one plane with one basis,
//! so their patterns continue across the cut without the grammar saying
//! anything. Horizontal faces (floors, flat roofs) take world x and z.
//!
//! [`Scene::texture_of`]: genform_core::Scene::texture_of

use glam::{DVec3, Vec3};

/// Below this length of a unit normal's horizontal part (about 0.06°
/// from vertical) a face counts as horizontal: its in-plane horizontal
/// direction is too ill-defined to follow.
const HORIZONTAL: f64 = 1e-3;

/// The directions `u` and `v` of the plane of a face with unit normal `n`
/// (outward), as a viewer facing the face sees them: `u` to the right
/// along the horizontal, `v` up the slope. A face looking up takes world
/// +x and −z (north up on a map seen from above), one looking down +x and
/// +z.
pub(crate) fn face_axes(n: Vec3) -> (DVec3, DVec3) {
    let n = n.as_dvec3();
    let across = DVec3::Y.cross(n);
    if across.length() < HORIZONTAL {
        return if n.y >= 0.0 { (DVec3::X, DVec3::NEG_Z) } else { (DVec3::X, DVec3::Z) };
    }
    let u = across.normalize();
    (u, n.cross(u).normalize())
}

/// The texture coordinates of `p` on a face with axes `axes`
/// ([`face_axes`]): in copies of an image covering `size` (width, height)
/// world units, `v` counted upwards (OBJ's convention; glTF's `v` runs
/// down the image, so the GLB writer negates it).
pub(crate) fn texture_coords(p: Vec3, axes: (DVec3, DVec3), size: [f32; 2]) -> [f32; 2] {
    let p = p.as_dvec3();
    [(p.dot(axes.0) / f64::from(size[0])) as f32, (p.dot(axes.1) / f64::from(size[1])) as f32]
}

/// The unit normal of the planar polygon `points` by Newell's method
/// (counter-clockwise seen from its front), zero when it has no area.
pub(crate) fn polygon_normal(points: &[Vec3]) -> Vec3 {
    let mut n = DVec3::ZERO;
    for (i, a) in points.iter().enumerate() {
        let (a, b) = (a.as_dvec3(), points[(i + 1) % points.len()].as_dvec3());
        n += DVec3::new((a.y - b.y) * (a.z + b.z), (a.z - b.z) * (a.x + b.x), (a.x - b.x) * (a.y + b.y));
    }
    n.normalize_or_zero().as_vec3()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: [f32; 2], b: [f32; 2]) -> bool {
        (a[0] - b[0]).abs() < 1e-5 && (a[1] - b[1]).abs() < 1e-5
    }

    #[test]
    fn a_wall_facing_the_viewer_runs_right_and_up_in_metres() {
        // A wall facing +z: u along +x, v along +y, 2 × 1 m per copy.
        let axes = face_axes(Vec3::Z);
        assert!(close(texture_coords(Vec3::new(4.0, 3.0, 7.0), axes, [2.0, 1.0]), [2.0, 3.0]));
        // Facing +x, a viewer on +x sees −z to the right.
        let (u, v) = face_axes(Vec3::X);
        assert!((u - DVec3::NEG_Z).length() < 1e-12 && (v - DVec3::Y).length() < 1e-12);
    }

    #[test]
    fn a_wall_split_into_tiles_keeps_one_continuous_pattern() {
        // A 6 m wall in the plane z = 2, facing −z, split at x = 2.5 into two
        // tiles (four triangles): the corners the tiles share get the same
        // coordinates from either tile, and every corner the coordinates of
        // the unsplit wall.
        let n = Vec3::NEG_Z;
        let corner = |x: f32, y: f32| Vec3::new(x, y, 2.0);
        let tiles = [
            [corner(0.0, 0.0), corner(0.0, 3.0), corner(2.5, 3.0), corner(2.5, 0.0)],
            [corner(2.5, 0.0), corner(2.5, 3.0), corner(6.0, 3.0), corner(6.0, 0.0)],
        ];
        let whole = [corner(0.0, 0.0), corner(0.0, 3.0), corner(6.0, 3.0), corner(6.0, 0.0)];
        let size = [1.5, 0.75];
        let uv = |p: Vec3| texture_coords(p, face_axes(n), size);
        assert!(close(uv(tiles[0][2]), uv(tiles[1][1])));
        assert!(close(uv(tiles[0][3]), uv(tiles[1][0])));
        assert!(close(uv(whole[0]), uv(tiles[0][0])) && close(uv(whole[2]), uv(tiles[1][2])));
        // Along the wall the pattern advances by length / width per copy.
        let [u0, v0] = uv(whole[0]);
        let [u1, v1] = uv(whole[2]);
        assert!(((u1 - u0).abs() - 6.0 / 1.5).abs() < 1e-5);
        assert!(((v1 - v0) - 3.0 / 0.75).abs() < 1e-5, "v runs up the wall");
        // The normal of each tile by Newell's method is the wall's.
        for t in &tiles {
            let mut ccw = *t;
            ccw.reverse();
            assert!((polygon_normal(t) + polygon_normal(&ccw)).length() < 1e-6);
            assert!(polygon_normal(t).dot(n).abs() > 0.999_999);
        }
    }

    #[test]
    fn a_roof_face_is_measured_in_metres_along_its_slope() {
        // A 30° roof plane rising towards −z (its normal leans to +z):
        // 4 m of run is 4 / cos 30° m of slope.
        let slope = 30f32.to_radians();
        let n = Vec3::new(0.0, slope.cos(), slope.sin());
        let axes = face_axes(n);
        assert!((axes.0 - DVec3::X).length() < 1e-6, "u along the eaves");
        let eave = Vec3::new(0.0, 5.0, 4.0);
        let ridge = Vec3::new(0.0, 5.0 + 4.0 * slope.tan(), 0.0);
        let [_, v0] = texture_coords(eave, axes, [1.0, 0.5]);
        let [_, v1] = texture_coords(ridge, axes, [1.0, 0.5]);
        let along = 4.0 / slope.cos();
        assert!(((v1 - v0) - along / 0.5).abs() < 1e-4, "{} vs {}", v1 - v0, along / 0.5);
        // Along the eaves, plain metres.
        let [u0, _] = texture_coords(eave, axes, [1.0, 0.5]);
        let [u1, _] = texture_coords(eave + Vec3::new(3.0, 0.0, 0.0), axes, [1.0, 0.5]);
        assert!(((u1 - u0) - 3.0).abs() < 1e-5);
    }

    #[test]
    fn horizontal_faces_take_world_x_and_z() {
        let up = face_axes(Vec3::Y);
        assert_eq!(up, (DVec3::X, DVec3::NEG_Z));
        assert!(close(texture_coords(Vec3::new(3.0, 9.0, -2.0), up, [1.0, 2.0]), [3.0, 1.0]));
        // Float noise in a floor's normal does not turn its pattern.
        assert_eq!(face_axes(Vec3::new(1e-6, 1.0, -1e-6).normalize()), up);
        assert_eq!(face_axes(Vec3::NEG_Y), (DVec3::X, DVec3::Z));
    }
}
