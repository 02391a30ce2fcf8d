//! What runs report: `stats.csv` and `fitness.svg` ([`stats`], one writer
//! each for every scene kind), galleries, the best model's pictures,
//! MAP-Elites' archive, and the tables and plots of `compare` and `sweep`.

pub mod archive;
pub mod comparison;
pub mod gallery;
pub mod pictures;
pub mod stats;
pub mod sweep;
