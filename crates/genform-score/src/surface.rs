//! Genr8's six surface fitness criteria (paper §5.3, reference §8): what a
//! HEMLS surface measures, and how targets and weights turn the measures
//! into one fitness.
//!
//! [`SurfaceMeasures`] reads every [`Surface`](genform_core::Surface) of a
//! Scene together: the vertices are the paper's "nodes", the edges its
//! neighbour relation.
//!
//! | criterion | measure |
//! |---|---|
//! | size | x-extent + y-extent |
//! | smoothness | Σ over edges \|Δz\| (= ½ Σ_i Σ_{j∈N(i)} \|z_i − z_j\|) |
//! | soft boundary | vertices on the wrong side of soft boundaries (Σ `outside_soft`) |
//! | subdivisions | vertices / edges (1 for a bare polygon) |
//! | symmetry | (sym(x) + sym(y)) / 2, sym = min/max of the node counts either side of the bounding-box centre line |
//! | undulation | z-extent |
//!
//! The choices the reference leaves open (\[D\] in §8), made here:
//!
//! - soft boundary: the *count* of such vertices (the paper's "penalty for
//!   each node"); [`SurfaceMeasures::soft_boundary_fraction`] gives the
//!   fraction too;
//! - subdivisions of a scene without edges (empty, or isolated points): 1,
//!   "no internal structure";
//! - symmetry: the bounding-box centre; min/max so that 1 is symmetric;
//!   nodes on the line are left out, and a scene with no node off the line
//!   scores 1. The reference suggests a tolerance of 1e-9 × extent for "on
//!   the line", but positions are `f32` (resolution ≈ 6e-8 of the
//!   coordinate), so a node the grower put on the axis is typically a few
//!   ulps off it; the tolerance here is [`SYMMETRY_TOLERANCE`] × (extent +
//!   |centre|), about a hundred ulps, so such nodes still count as on it.
//!
//! [`SurfaceScorer`] combines the criteria, in the bounded form (the
//! default) or the paper's (see [`scorer`] for both and why).

mod criterion;
mod measures;
pub mod scorer;

#[cfg(test)]
mod tests;

pub use criterion::SurfaceCriterion;
pub use measures::{SYMMETRY_TOLERANCE, SurfaceMeasures};
pub use scorer::{
    SurfaceComponent, SurfaceError, SurfaceForm, SurfaceGoal, SurfaceObjective, SurfaceScore, SurfaceScorer,
};
