//! Scorers for genform Scenes: voxel volume targets and image silhouette
//! targets. Scorers read only a [`genform_core::Scene`]; they reduce it to
//! [`Counts`], which a [`Fitness`] turns into the number optimizers maximize.

#![warn(missing_docs)]

pub mod fitness;

pub use fitness::{Counts, Fitness, Form, smootherstep};
