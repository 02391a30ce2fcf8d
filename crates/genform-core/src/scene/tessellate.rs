//! The unit meshes of the built-in primitives, and how finely curved ones
//! are tessellated; [`Scene::for_each_triangle`](super::Scene::for_each_triangle)
//! walks a scene's triangles with them.

use super::mesh::Mesh;
use super::primitive::Primitive;
use glam::Vec3;

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
