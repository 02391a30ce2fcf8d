//! Scorers for genform Scenes: voxel volume targets, image silhouette
//! targets and Genr8's surface criteria, behind one contract
//! ([`contract`]: a [`Scorer`] gives a fitness, named components with
//! weights and reachable maxima, and steerable knobs). Scorers read only a
//! [`genform_core::Scene`]; counting targets reduce it to [`Counts`],
//! which a [`Fitness`] turns into the number optimizers maximize.

pub mod component;
pub mod contract;
pub mod descriptor;
pub mod fitness;
pub mod image;
pub mod look;

mod bits;
pub mod error;
pub mod grid;
mod span_cache;
pub mod surface;
pub mod target;
pub mod volume;
pub mod voxel_set;
pub mod voxelize;

pub use component::{Component, Score};
pub use contract::{Counter, FITNESS_WEIGHTS, Knob, Scorer, Scratch, Sum, Targets};
pub use descriptor::Descriptor;
pub use fitness::{Counts, Fitness, Form, smootherstep};

pub use error::ScoreError;
pub use grid::{Grid, MAX_VOXELS};
pub use image::{Coverage, ImageError, ImageScorer, ImageScratch, ImageTarget, PngMode};
pub use surface::{
    SurfaceComponent, SurfaceCriterion, SurfaceError, SurfaceForm, SurfaceGoal, SurfaceMeasures, SurfaceObjective,
    SurfaceScore, SurfaceScorer,
};
pub use target::TargetReport;
pub use volume::{VolumeScorer, VolumeTarget};
pub use voxel_set::VoxelSet;
pub use voxelize::{VolumeScratch, Voxelized};
