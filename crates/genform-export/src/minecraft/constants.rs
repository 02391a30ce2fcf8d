//! The DataVersions and the size limit that the readers, the writers and
//! [`MinecraftError`](super::MinecraftError)'s messages share.

/// The first DataVersion with the 1.18 chunk layout (`sections` at the
/// root, paletted `block_states`): Minecraft 1.18.
pub const MIN_CHUNK_DATA_VERSION: i32 = 2860;

/// DataVersion of Minecraft 1.21.1, the default for written schematics.
pub const DATA_VERSION_1_21_1: i32 = 3955;

/// The first DataVersion (1.20.5) whose Litematica files are format 7.
pub const LITEMATIC_V7_DATA_VERSION: i32 = 3837;

/// The largest box [`read_terrain`](super::read_terrain) fills, in cells (2²⁷: 512 MiB of `u32`
/// cells).
pub const MAX_TERRAIN_CELLS: u64 = 1 << 27;
