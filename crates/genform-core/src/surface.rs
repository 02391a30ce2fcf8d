//! Polygon surfaces with typed edges (what HEMLS growth produces), and the
//! faint context geometry (guides) previews draw around a model.

use crate::scene::mesh::{Mesh, TagId};
use glam::Vec3;
use std::sync::Arc;

/// One edge of a [`Surface`]: two vertex indices and the edge's type (the
/// `N` of a HEMLS `EdgeN`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct SurfaceEdge {
    /// Start vertex.
    pub a: u32,
    /// End vertex.
    pub b: u32,
    /// Edge type ([`SurfaceEdge::UNTYPED`] for edges that smoothing adds
    /// inside faces).
    pub kind: u32,
}

impl SurfaceEdge {
    /// The type of edges that belong to no rewrite rule (e.g. the ones
    /// Catmull–Clark subdivision adds inside faces).
    pub const UNTYPED: u32 = u32::MAX;
}

/// A polygon surface: vertices, bounded faces as vertex loops, and typed
/// edges (every face side is an edge; edges may also bound the outer face
/// only).
///
/// Faces are stored compressed: face `f` is
/// `face_vertices[face_offsets[f] as usize..face_offsets[f + 1] as usize]`,
/// counter-clockwise seen from the surface's front side (its normal).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Surface {
    /// Vertex positions.
    pub positions: Vec<Vec3>,
    /// `faces + 1` offsets into [`Surface::face_vertices`], starting at 0.
    pub face_offsets: Vec<u32>,
    /// Concatenated face loops.
    pub face_vertices: Vec<u32>,
    /// Typed edges.
    pub edges: Vec<SurfaceEdge>,
    /// Semantic tag of the faces; edges are tagged by type when exported.
    pub tag: TagId,
    /// How many vertices ended on the wrong side of a soft boundary of the
    /// environment the surface grew in (the soft-boundary fitness criterion
    /// reads it; 0 without soft boundaries).
    pub outside_soft: u32,
}

impl Surface {
    /// An empty surface with `tag`.
    pub fn new(tag: TagId) -> Self {
        Surface { face_offsets: vec![0], tag, ..Default::default() }
    }

    /// Number of bounded faces.
    pub fn face_count(&self) -> usize {
        self.face_offsets.len().saturating_sub(1)
    }

    /// The vertex loop of face `f`.
    pub fn face(&self, f: usize) -> &[u32] {
        &self.face_vertices[self.face_offsets[f] as usize..self.face_offsets[f + 1] as usize]
    }

    /// Iterates over the face loops.
    pub fn faces(&self) -> impl Iterator<Item = &[u32]> + '_ {
        (0..self.face_count()).map(|f| self.face(f))
    }

    /// Appends a face loop.
    pub fn push_face(&mut self, loop_: &[u32]) {
        if self.face_offsets.is_empty() {
            self.face_offsets.push(0);
        }
        self.face_vertices.extend_from_slice(loop_);
        self.face_offsets.push(self.face_vertices.len() as u32);
    }

    /// V − E + F with F the bounded faces: 1 for a disc.
    pub fn euler_characteristic(&self) -> i64 {
        self.positions.len() as i64 - self.edges.len() as i64 + self.face_count() as i64
    }

    /// Axis-aligned bounds of the vertices, `None` when empty.
    pub fn bounds(&self) -> Option<(Vec3, Vec3)> {
        let mut it = self.positions.iter().copied();
        let first = it.next()?;
        Some(it.fold((first, first), |(lo, hi), p| (lo.min(p), hi.max(p))))
    }

    /// Calls `f` with every face's corner positions (scratch buffer reused).
    pub fn for_each_face_points(&self, mut f: impl FnMut(&[Vec3])) {
        let mut pts = Vec::new();
        for face in self.faces() {
            pts.clear();
            pts.extend(face.iter().map(|&i| self.positions[i as usize]));
            f(&pts);
        }
    }
}

/// Context geometry shown faintly by previews for orientation (a growth
/// environment's boundaries and charges). Model exporters and scorers leave
/// guides out: they are not part of the model.
#[derive(Clone, Debug, PartialEq)]
pub struct Guide {
    /// The geometry.
    pub kind: GuideKind,
    /// Semantic tag (e.g. `boundary`, `attractor`, `repeller`).
    pub tag: TagId,
}

/// The geometry of a [`Guide`].
#[derive(Clone, Debug, PartialEq)]
pub enum GuideKind {
    /// A triangle mesh in world coordinates.
    Mesh(Arc<Mesh>),
    /// A point marker of a given radius in scene units.
    Point {
        /// Where.
        at: Vec3,
        /// Marker radius.
        radius: f32,
    },
}
