//! Predefined surfaces (cpfg/L-Py `~`): `~l(size)` places a mesh at the
//! turtle, oriented by its frame and scaled by `size`. `l` is a leaf built
//! into genform, a bicubic Bézier patch (the kind of surface cpfg reads
//! from `.s` files); `surface name = "file.obj"` declares others, loaded
//! through a [`SurfaceAssets`] resolver.
//!
//! A surface's local frame: +y runs along the turtle's heading H (the
//! leaf's base at the origin, its tip at y = 1), +z along the up vector U,
//! +x to the turtle's right (−L), so the mapping is a rotation.

use genform_core::Mesh;
use glam::{DVec3, Vec3};

/// Loads the mesh files that `surface name = "path"` declarations name.
pub trait SurfaceAssets {
    /// Loads the mesh at `path`, exactly as written in the `.ls` file (the
    /// caller resolves it, e.g. relative to the file). The error message is
    /// shown to the user next to the path.
    fn load_mesh(&self, path: &str) -> Result<Mesh, String>;
}

/// A resolver without files: every `surface` declaration is an error (the
/// built-in surfaces still work).
#[derive(Clone, Copy, Debug, Default)]
pub struct NoSurfaceAssets;

impl SurfaceAssets for NoSurfaceAssets {
    fn load_mesh(&self, path: &str) -> Result<Mesh, String> {
        Err(format!("no mesh files can be loaded here (asked for \"{path}\")"))
    }
}

/// The built-in surfaces' names.
pub const BUILT_IN: &[&str] = &["l"];

/// Control points of the leaf patch, row by row from the base (y = 0) to
/// the tip (y = 1), each row from right (x < 0) to left: the base and tip
/// rows collapse to a point, and the edges rise a little (z) so the blade
/// is cupped.
pub const LEAF_CONTROL: [[[f64; 3]; 4]; 4] = [
    [[0.0, 0.0, 0.0]; 4],
    [[-0.5, 1.0 / 3.0, 0.1], [-0.2, 1.0 / 3.0, 0.0], [0.2, 1.0 / 3.0, 0.0], [0.5, 1.0 / 3.0, 0.1]],
    [[-0.4, 2.0 / 3.0, 0.15], [-0.15, 2.0 / 3.0, 0.0], [0.15, 2.0 / 3.0, 0.0], [0.4, 2.0 / 3.0, 0.15]],
    [[0.0, 1.0, 0.0]; 4],
];

/// Quads per side of the leaf's tessellation.
pub const LEAF_GRID: usize = 8;

/// The cubic Bernstein weights at `t`.
fn bernstein(t: f64) -> [f64; 4] {
    let s = 1.0 - t;
    [s * s * s, 3.0 * s * s * t, 3.0 * s * t * t, t * t * t]
}

/// The Bézier patch with control points `c` (rows along v) at (u, v).
pub fn bezier_patch(c: &[[[f64; 3]; 4]; 4], u: f64, v: f64) -> DVec3 {
    let (bu, bv) = (bernstein(u), bernstein(v));
    let mut p = DVec3::ZERO;
    for (i, row) in c.iter().enumerate() {
        for (j, q) in row.iter().enumerate() {
            p += DVec3::from_array(*q) * (bv[i] * bu[j]);
        }
    }
    p
}

/// The built-in surface `name` as a mesh.
pub(crate) fn built_in(name: &str) -> Option<Mesh> {
    (name == "l").then(leaf)
}

/// The leaf patch tessellated on a (LEAF_GRID + 1)² vertex grid (row-major
/// from the base, u across); triangles that collapse at the base and tip
/// are left out.
fn leaf() -> Mesh {
    let n = LEAF_GRID;
    let mut positions = Vec::with_capacity((n + 1) * (n + 1));
    for i in 0..=n {
        for j in 0..=n {
            let p = bezier_patch(&LEAF_CONTROL, j as f64 / n as f64, i as f64 / n as f64);
            positions.push(p.as_vec3());
        }
    }
    let mut triangles = Vec::new();
    let id = |i: usize, j: usize| (i * (n + 1) + j) as u32;
    let area = |t: [u32; 3], p: &[Vec3]| {
        let [a, b, c] = t.map(|k| p[k as usize]);
        (b - a).cross(c - a).length()
    };
    for i in 0..n {
        for j in 0..n {
            // Counter-clockwise seen from +z (the upper side).
            for t in [[id(i, j), id(i, j + 1), id(i + 1, j + 1)], [id(i, j), id(i + 1, j + 1), id(i + 1, j)]] {
                if area(t, &positions) > 1e-9 {
                    triangles.push(t);
                }
            }
        }
    }
    Mesh { name: "leaf".into(), positions, triangles }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_patch_interpolates_its_corners_and_matches_bernstein_by_hand() {
        // Corners of a Bézier patch are its corner control points.
        assert_eq!(bezier_patch(&LEAF_CONTROL, 0.0, 0.0), DVec3::ZERO);
        assert_eq!(bezier_patch(&LEAF_CONTROL, 1.0, 1.0), DVec3::new(0.0, 1.0, 0.0));
        // At (½, ½) the weights are (1, 3, 3, 1)/8 each way: y = (0 + 3·⅓ +
        // 3·⅔ + 1)/8 = ½; z = ⅜·(0.1 + 0.1)/8 + ⅜·(0.15 + 0.15)/8.
        let mid = bezier_patch(&LEAF_CONTROL, 0.5, 0.5);
        assert!((mid - DVec3::new(0.0, 0.5, 0.0234375)).length() < 1e-15, "{mid}");
        // The right edge at mid-length: x = (3·(−0.5) + 3·(−0.4))/8.
        assert!((bezier_patch(&LEAF_CONTROL, 0.0, 0.5).x + 0.3375).abs() < 1e-15);
    }

    #[test]
    fn the_leaf_mesh_is_the_patch_without_collapsed_triangles() {
        let m = leaf();
        assert_eq!(m.positions.len(), 81);
        // 8 × 8 quads, less one triangle per quad along the base and the tip rows.
        assert_eq!(m.triangles.len(), 2 * 64 - 2 * 8);
        assert!((m.positions[4 * 9 + 4].as_dvec3() - DVec3::new(0.0, 0.5, 0.0234375)).length() < 1e-7);
        for t in &m.triangles {
            let [a, b, c] = t.map(|k| m.positions[k as usize]);
            assert!((b - a).cross(c - a).z > 0.0, "faces up");
        }
    }
}

#[cfg(test)]
mod placement_tests {
    use super::*;
    use genform_core::scene::Primitive;
    use genform_core::{Rng, Scene, SourceFile};

    /// Loads every path as a unit triangle named after it.
    struct Triangles;

    impl SurfaceAssets for Triangles {
        fn load_mesh(&self, path: &str) -> Result<Mesh, String> {
            if path == "missing.obj" {
                return Err("no such file".into());
            }
            let positions = vec![Vec3::ZERO, Vec3::X, Vec3::Y];
            Ok(Mesh { name: path.into(), positions, triangles: vec![[0, 1, 2]] })
        }
    }

    /// The world positions of every surface instance's vertices.
    fn placed(text: &str) -> Vec<Vec<DVec3>> {
        let file = SourceFile::new("s.ls", text);
        let (s, w) = crate::compile_with_assets(&file, &Triangles).unwrap();
        assert!(w.items.is_empty(), "{}", w.short());
        let mut scene = Scene::new();
        s.interpret(&s.axiom, &mut Rng::from_seed(0), 1000, &mut scene).unwrap();
        scene
            .instances
            .iter()
            .filter_map(|i| match i.primitive {
                Primitive::Mesh(id) => Some(
                    scene.meshes[id as usize]
                        .positions
                        .iter()
                        .map(|p| i.transform.transform_point3(*p).as_dvec3())
                        .collect(),
                ),
                _ => None,
            })
            .collect()
    }

    #[test]
    fn a_leaf_follows_the_turtle_frame_and_size() {
        // Heading +y after F: the leaf's base at (0, 1, 0), its tip 2 further
        // along H, its mid-vertex at base + 2·(0, ½, z½) with U = +z.
        let leaves = placed("view: 3d\naxiom: F ~l(2)\n");
        assert_eq!(leaves.len(), 1);
        let v = &leaves[0];
        assert!((v[0] - DVec3::new(0.0, 1.0, 0.0)).length() < 1e-6);
        assert!((v[80] - DVec3::new(0.0, 3.0, 0.0)).length() < 1e-6);
        assert!((v[40] - DVec3::new(0.0, 2.0, 2.0 * 0.0234375)).length() < 1e-6, "{}", v[40]);
        // Turned by `+(90)`: H = −x, L = −y, U = +z.
        let leaves = placed("view: 3d\naxiom: +(90) ~l\n");
        let v = &leaves[0];
        assert!((v[80] - DVec3::new(-1.0, 0.0, 0.0)).length() < 1e-6, "tip along H = −x");
        // u = 0 at half the length is local (−0.3375, ½, (3·0.1 + 3·0.15)/8):
        // x runs along −L = +y, so it lands at y = −0.3375, lifted along U.
        assert!((v[36] - DVec3::new(-0.5, -0.3375, 0.09375)).length() < 1e-6, "{}", v[36]);
    }

    #[test]
    fn declared_surfaces_load_through_the_resolver_and_scale() {
        let leaves = placed("view: 3d\nsurface petal = \"petal.obj\"\naxiom: ~petal(3) @Di(2) ~petal\n");
        assert_eq!(leaves.len(), 2);
        // Local x is the right (−L = +x at heading +y), local y the heading.
        assert!((leaves[0][1] - DVec3::new(3.0, 0.0, 0.0)).length() < 1e-6);
        assert!((leaves[0][2] - DVec3::new(0.0, 3.0, 0.0)).length() < 1e-6);
        assert!((leaves[1][2] - DVec3::new(0.0, 2.0, 0.0)).length() < 1e-6, "scale 2 × default size 1");
    }

    #[test]
    fn surface_errors_have_positions_and_hints() {
        let file = SourceFile::new("s.ls", "surface a = \"missing.obj\"\naxiom: ~lf ~l ~b ~b\n");
        let e = crate::compile_with_assets(&file, &Triangles).unwrap_err();
        let msgs: Vec<String> = e.items.iter().map(|d| format!("{} {:?}", d.message, d.hints)).collect();
        assert_eq!(msgs.len(), 3, "{msgs:?}");
        assert!(msgs[0].contains("cannot load surface `a`: no such file"));
        assert!(msgs[1].contains("unknown surface `lf`") && msgs[1].contains("did you mean `~l`?"), "{msgs:?}");
        assert!(msgs[2].contains("unknown surface `b`"), "reported once: {msgs:?}");
        // Without a resolver a declaration cannot load.
        let file = SourceFile::new("s.ls", "surface a = \"a.obj\"\naxiom: ~a\n");
        let e = crate::compile(&file).unwrap_err();
        assert!(e.items[0].message.contains("no mesh files can be loaded here"), "{}", e.short());
    }
}
