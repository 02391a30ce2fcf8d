//! Triangle meshes (assets and tessellated primitives) and the ids the
//! parts of a [`Scene`](super::Scene) refer to tags and meshes by.

use glam::Vec3;

/// Index into [`Scene::tags`](super::Scene::tags).
pub type TagId = u32;
/// Index into [`Scene::meshes`](super::Scene::meshes).
pub type MeshId = u32;

/// A triangle mesh (an asset or a tessellated primitive).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Mesh {
    /// Display name (file stem for assets).
    pub name: String,
    /// Vertex positions.
    pub positions: Vec<Vec3>,
    /// Counter-clockwise triangles seen from outside.
    pub triangles: Vec<[u32; 3]>,
}

impl Mesh {
    /// Axis-aligned bounds, `None` when empty.
    pub fn bounds(&self) -> Option<(Vec3, Vec3)> {
        bounds_of(self.positions.iter().copied())
    }
}

/// The axis-aligned bounds of `it`'s points, `None` when there are none.
pub(super) fn bounds_of(mut it: impl Iterator<Item = Vec3>) -> Option<(Vec3, Vec3)> {
    let first = it.next()?;
    Some(it.fold((first, first), |(lo, hi), p| (lo.min(p), hi.max(p))))
}
