//! The six criteria by name, apart from the measures and the scorer that
//! both read them.

/// One of the six criteria.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum SurfaceCriterion {
    /// x-extent + y-extent.
    Size,
    /// Σ over edges |Δz|.
    Smoothness,
    /// Vertices on the wrong side of soft boundaries.
    SoftBoundary,
    /// Vertices / edges.
    Subdivisions,
    /// (sym(x) + sym(y)) / 2.
    Symmetry,
    /// z-extent.
    Undulation,
}

impl SurfaceCriterion {
    /// All six, in the paper's order.
    pub const ALL: [SurfaceCriterion; 6] = [
        SurfaceCriterion::Size,
        SurfaceCriterion::Smoothness,
        SurfaceCriterion::SoftBoundary,
        SurfaceCriterion::Subdivisions,
        SurfaceCriterion::Symmetry,
        SurfaceCriterion::Undulation,
    ];

    /// The configuration and log name (`soft_boundary` etc.).
    pub fn name(self) -> &'static str {
        match self {
            SurfaceCriterion::Size => "size",
            SurfaceCriterion::Smoothness => "smoothness",
            SurfaceCriterion::SoftBoundary => "soft_boundary",
            SurfaceCriterion::Subdivisions => "subdivisions",
            SurfaceCriterion::Symmetry => "symmetry",
            SurfaceCriterion::Undulation => "undulation",
        }
    }

    /// The criterion named `name` (see [`SurfaceCriterion::name`]).
    pub fn from_name(name: &str) -> Option<SurfaceCriterion> {
        SurfaceCriterion::ALL.into_iter().find(|c| c.name() == name)
    }

    /// The default error floor ε of [`SurfaceGoal::floor`](super::SurfaceGoal::floor): 1 for the lengths
    /// (scene units) and the node count, 0.1 for the ratios, which lie in
    /// [0, 1] (subdivisions can exceed 1 only for edge-poor graphs).
    pub fn default_floor(self) -> f64 {
        match self {
            SurfaceCriterion::Subdivisions | SurfaceCriterion::Symmetry => 0.1,
            SurfaceCriterion::Size
            | SurfaceCriterion::Smoothness
            | SurfaceCriterion::SoftBoundary
            | SurfaceCriterion::Undulation => 1.0,
        }
    }
}
