//! Preview geometry for an environment: boundaries as meshes, charges as
//! point markers.

use super::{Boundary, Environment, Shape};
use genform_core::scene::{Primitive, Tessellation, unit_mesh};
use genform_core::{Guide, GuideKind, Mesh, Scene};
use glam::Vec3;
use std::sync::Arc;

/// Side of the square that stands for an (infinite) plane in previews.
pub const PLANE_GUIDE_SIZE: f64 = 10.0;
/// Radius of the marker of an attractor or repeller.
pub const CHARGE_GUIDE_RADIUS: f32 = 0.1;

impl Environment {
    /// Pushes preview guides into `scene`: every boundary as a mesh tagged
    /// `boundary` (planes as squares of side [`PLANE_GUIDE_SIZE`]), every
    /// charge as a point tagged `attractor` or `repeller`.
    pub fn guides(&self, scene: &mut Scene) {
        self.guides_sized(scene, PLANE_GUIDE_SIZE);
    }

    /// [`Environment::guides`] with planes drawn as squares of side
    /// `plane_size` around their point.
    pub fn guides_sized(&self, scene: &mut Scene, plane_size: f64) {
        if !self.boundaries.is_empty() {
            let tag = scene.tag("boundary");
            for b in &self.boundaries {
                scene.guides.push(Guide { kind: GuideKind::Mesh(boundary_mesh(b, plane_size)), tag });
            }
        }
        for c in &self.charges {
            let tag = scene.tag(c.kind.name());
            scene
                .guides
                .push(Guide { kind: GuideKind::Point { at: c.position.as_vec3(), radius: CHARGE_GUIDE_RADIUS }, tag });
        }
    }
}

/// A boundary as a triangle mesh in world coordinates.
pub fn boundary_mesh(b: &Boundary, plane_size: f64) -> Arc<Mesh> {
    match &b.shape {
        Shape::Sphere { center, radius } => {
            let unit = unit_mesh(Primitive::Sphere, Tessellation { radial: 32, rings: 16 });
            let scale = (2.0 * radius) as f32;
            Arc::new(placed(unit, "sphere", |p| p * scale + center.as_vec3()))
        }
        Shape::Box { min, max } => {
            let unit = unit_mesh(Primitive::Box, Tessellation::default());
            let (size, mid) = ((*max - *min).as_vec3(), ((*min + *max) * 0.5).as_vec3());
            Arc::new(placed(unit, "box", |p| p * size + mid))
        }
        Shape::Plane { point, normal } => {
            let (u, v) = normal.any_orthonormal_pair();
            let h = 0.5 * plane_size;
            let corner = |a: f64, b: f64| (*point + u * a + v * b).as_vec3();
            // u × v = normal, so (−,−), (+,−), (+,+), (−,+) winds counter-clockwise
            // seen from the normal's side.
            let positions = vec![corner(-h, -h), corner(h, -h), corner(h, h), corner(-h, h)];
            Arc::new(Mesh { name: "plane".into(), positions, triangles: vec![[0, 1, 2], [0, 2, 3]] })
        }
        Shape::Mesh(m) => m.preview().clone(),
    }
}

fn placed(mut mesh: Mesh, name: &str, f: impl Fn(Vec3) -> Vec3) -> Mesh {
    for p in &mut mesh.positions {
        *p = f(*p);
    }
    mesh.name = name.into();
    mesh
}
