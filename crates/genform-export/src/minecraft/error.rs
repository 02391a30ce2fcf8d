//! [`MinecraftError`], what every reader and writer here reports, and
//! [`malformed`], the shorthand for its `Malformed` case.

use super::constants::{MAX_TERRAIN_CELLS, MIN_CHUNK_DATA_VERSION};
use glam::UVec3;

/// What went wrong reading or writing Minecraft data.
#[derive(thiserror::Error, Debug, Clone, PartialEq, Eq)]
pub enum MinecraftError {
    /// The region file as a whole cannot be used.
    #[error("region file r.{x}.{z}.mca is corrupt: {reason}")]
    CorruptRegion {
        /// Region x.
        x: i32,
        /// Region z.
        z: i32,
        /// What is wrong.
        reason: String,
    },
    /// One chunk's entry or data cannot be read.
    #[error("chunk ({x}, {z}) cannot be read: {reason}")]
    ChunkUnreadable {
        /// Chunk x (world chunk coordinates, blocks / 16).
        x: i32,
        /// Chunk z.
        z: i32,
        /// What is wrong.
        reason: String,
    },
    /// The chunk predates the 1.18 format.
    #[error(
        "chunk ({x}, {z}) has DataVersion {version}, older than Minecraft 1.18 ({min}); \
         only 1.18+ chunks can be read or written (open and save the world in 1.18 or later first)",
        min = MIN_CHUNK_DATA_VERSION
    )]
    UnsupportedDataVersion {
        /// Chunk x.
        x: i32,
        /// Chunk z.
        z: i32,
        /// Its DataVersion.
        version: i32,
    },
    /// Blocks were to be written into a chunk the region does not hold, or
    /// one whose generation is not finished.
    #[error(
        "cannot write into chunk ({x}, {z}): {reason}; load that area in Minecraft once so the chunk is fully generated"
    )]
    ChunkNotGenerated {
        /// Chunk x.
        x: i32,
        /// Chunk z.
        z: i32,
        /// Missing, or its status.
        reason: String,
    },
    /// Blocks were to be written above or below the chunk's sections.
    #[error("cannot write block y = {y} into chunk ({x}, {z}): its sections hold y {min}..={max}")]
    OutsideWorldHeight {
        /// Chunk x.
        x: i32,
        /// Chunk z.
        z: i32,
        /// The block's y.
        y: i32,
        /// Lowest block y the chunk holds.
        min: i32,
        /// Highest block y the chunk holds.
        max: i32,
    },
    /// A rewritten chunk no longer fits a region entry (255 sectors, 1 MiB).
    #[error("chunk ({x}, {z}) compresses to {bytes} bytes, more than a region entry holds (1044475)")]
    ChunkTooLarge {
        /// Chunk x.
        x: i32,
        /// Chunk z.
        z: i32,
        /// Its compressed size.
        bytes: usize,
    },
    /// The box to read is larger than [`MAX_TERRAIN_CELLS`].
    #[error("a box of {cells} cells is too large to read (at most {max})", max = MAX_TERRAIN_CELLS)]
    BoxTooLarge {
        /// Cells asked for.
        cells: u64,
    },
    /// A file is not the format it should be, or is damaged.
    #[error("the {format} file is malformed: {reason}")]
    Malformed {
        /// `schem`, `litematic`, ….
        format: &'static str,
        /// What is wrong.
        reason: String,
    },
    /// A schematic's version is not one this reader knows.
    #[error("unsupported {format} version {version} (supported: {supported})")]
    UnsupportedVersion {
        /// `schem` or `litematic`.
        format: &'static str,
        /// The version found.
        version: i32,
        /// The versions that are read.
        supported: &'static str,
    },
    /// The grid is too large for the format.
    #[error("a {}×{}×{} grid is too large for {format}: {limit}", size.x, size.y, size.z)]
    TooLarge {
        /// `schem`, `litematic`, `vox`.
        format: &'static str,
        /// The grid size.
        size: UVec3,
        /// The format's limit, in words.
        limit: &'static str,
    },
    /// There are no blocks to write.
    #[error("there are no blocks to write")]
    Empty,
    /// A grid's cell count does not match its size.
    #[error("the grid has {cells} cells, but its size {}×{}×{} needs {}", size.x, size.y, size.z, u64::from(size.x) * u64::from(size.y) * u64::from(size.z))]
    InconsistentGrid {
        /// `cells.len()`.
        cells: usize,
        /// The grid's size.
        size: UVec3,
    },
}

/// A `format` error with `reason`.
pub(super) fn malformed(format: &'static str, reason: impl Into<String>) -> MinecraftError {
    MinecraftError::Malformed { format, reason: reason.into() }
}
