//! The built-in unit shapes (and mesh assets) an [`Instance`](super::Instance)
//! places.

use super::mesh::MeshId;

/// A unit-sized shape, placed by an instance transform.
///
/// Every built-in primitive fits the cube `[-0.5, 0.5]³`; axial ones run
/// along local +y, with the base at y = −0.5.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Primitive {
    /// The cube `[-0.5, 0.5]³`.
    Box,
    /// A frustum along y: bottom radius 0.5, top radius `0.5 * top`.
    /// `top = 1` is a cylinder, `top = 0` a cone.
    Frustum {
        /// Top radius relative to the bottom radius.
        top: f32,
    },
    /// The sphere of radius 0.5.
    Sphere,
    /// A box whose top face (y = +0.5) is scaled by `top` in x and z
    /// (a square frustum; `top = 0` is a pyramid).
    TaperedBox {
        /// Top face size relative to the bottom face.
        top: f32,
    },
    /// A mesh asset from [`Scene::meshes`](super::Scene::meshes), used as is (not normalized).
    Mesh(MeshId),
}
