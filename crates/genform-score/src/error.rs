//! Why a scorer could not be built.

/// An invalid grid, target or mesh given to a volume scorer. Each variant
/// says what was wrong and what to change.
#[derive(thiserror::Error, Debug, Clone, PartialEq)]
pub enum ScoreError {
    /// A grid corner has a NaN or infinite coordinate.
    #[error("the voxel grid bounds must be finite (min {min:?}, max {max:?})")]
    NonFiniteGrid {
        /// The lower corner given.
        min: [f32; 3],
        /// The upper corner given.
        max: [f32; 3],
    },
    /// A grid axis has `min >= max`; give the lower bound first.
    #[error("the voxel grid is empty along {axis}: min {min} must be below max {max}")]
    EmptyGridAxis {
        /// `'x'`, `'y'` or `'z'`.
        axis: char,
        /// The lower bound given.
        min: f32,
        /// The upper bound given.
        max: f32,
    },
    /// A grid axis has no voxels; every axis needs at least one.
    #[error("the voxel grid has 0 voxels along {axis}; every axis needs at least 1")]
    ZeroVoxels {
        /// `'x'`, `'y'` or `'z'`.
        axis: char,
    },
    /// The grid has more voxels than [`crate::grid::MAX_VOXELS`]; use fewer
    /// voxels per axis.
    #[error("the voxel grid has {count} voxels, more than the limit of {max}; use fewer voxels per axis")]
    TooManyVoxels {
        /// Voxels asked for.
        count: u64,
        /// The limit.
        max: u64,
    },
    /// A target was voxelized on another grid than the scorer's; voxelize
    /// every target on the scorer's grid.
    #[error("volume target {index} was voxelized on a different grid than the scorer's")]
    GridMismatch {
        /// Index of the target.
        index: usize,
    },
    /// A target weight is NaN or infinite.
    #[error("volume target {index} has a non-finite weight (fill {fill}, avoid {avoid})")]
    BadWeight {
        /// Index of the target.
        index: usize,
        /// Its fill weight `w_i`.
        fill: f64,
        /// Its avoid weight `w̃_i`.
        avoid: f64,
    },
    /// A target mesh cannot be voxelized: a vertex index is out of range or
    /// a vertex is not finite.
    #[error("target mesh `{name}`: {problem}")]
    BadMesh {
        /// The mesh's name.
        name: String,
        /// What is wrong, naming the triangle or vertex.
        problem: String,
    },
    /// The memory for a voxel grid could not be had (the machine is short
    /// of what the grid's size asks for); use fewer voxels per axis.
    #[error("cannot allocate {bytes} bytes for the voxel grid of {voxels} voxels; lower `voxels`")]
    Allocation {
        /// Voxels in the grid.
        voxels: u64,
        /// Bytes asked for.
        bytes: u128,
    },
}
