//! Litematica schematics (`.litematic`, gzipped NBT).
//!
//! One or more regions, each a palette (air first) and its indices packed
//! back to back into longs, entries straddling long boundaries, with
//! `max(2, ⌈log₂ n⌉)` bits and the index `(y·sizeZ + z)·sizeX + x`.

use super::constants::LITEMATIC_V7_DATA_VERSION;
use super::error::{MinecraftError, malformed};
use super::grid::{check_grid, dense_palette, merge_grids};
use super::nbt_file::{self, Compound};
use super::packing::{litematic_bits, pack_tight, tight_len, unpack_tight};
use fastnbt::{LongArray, Value};
use genform_core::blocks::{BlockGrid, BlockState};
use glam::{IVec3, UVec3};
use serde::Serialize;
use std::collections::BTreeMap;

const FORMAT: &str = "litematic";

/// The creation and modification time written (ms since 1970): fixed, so
/// the same grid always gives the same bytes.
const FIXED_TIME_MS: i64 = 1_700_000_000_000;

#[derive(Serialize)]
#[serde(rename_all = "PascalCase")]
struct File<'a> {
    minecraft_data_version: i32,
    version: i32,
    sub_version: i32,
    metadata: Metadata<'a>,
    regions: BTreeMap<&'a str, Region>,
}

#[derive(Serialize)]
#[serde(rename_all = "PascalCase")]
struct Metadata<'a> {
    name: &'a str,
    author: &'a str,
    description: &'a str,
    region_count: i32,
    total_volume: i32,
    total_blocks: i32,
    time_created: i64,
    time_modified: i64,
    enclosing_size: Xyz,
}

#[derive(Serialize)]
struct Xyz {
    x: i32,
    y: i32,
    z: i32,
}

#[derive(Serialize)]
#[serde(rename_all = "PascalCase")]
struct Region {
    position: Xyz,
    size: Xyz,
    block_state_palette: Vec<PaletteEntry>,
    block_states: LongArray,
    tile_entities: Vec<Value>,
    entities: Vec<Value>,
    pending_block_ticks: Vec<Value>,
    pending_fluid_ticks: Vec<Value>,
}

#[derive(Serialize)]
#[serde(rename_all = "PascalCase")]
struct PaletteEntry {
    name: String,
    #[serde(skip_serializing_if = "BTreeMap::is_empty")]
    properties: BTreeMap<String, String>,
}

/// Writes `grid` as a Litematica schematic with one region called `name`.
///
/// Format version 6 for `data_version` below 3837 (1.20.5), else 7. The
/// region sits at position (0, 0, 0): a litematic is placed by the player,
/// so the grid origin is not kept. Unset cells are air. Metadata: author
/// `genform`, empty description, `TotalBlocks` = non-air blocks, fixed
/// times.
///
/// Errors with [`MinecraftError::TooLarge`] when the volume exceeds
/// `i32::MAX` cells.
pub fn write_litematic(grid: &BlockGrid, data_version: i32, name: &str) -> Result<Vec<u8>, MinecraftError> {
    check_grid(grid)?;
    let s = grid.size;
    let volume = grid.cells.len();
    if volume > i32::MAX as usize || s.max_element() > i32::MAX as u32 {
        return Err(MinecraftError::TooLarge { format: FORMAT, size: s, limit: "at most 2³¹ − 1 blocks" });
    }
    let (palette, cells) = dense_palette(grid, true);
    let bits = litematic_bits(palette.len());
    let total_blocks = cells.iter().filter(|&&c| c != 0).count() as i32;
    let size = Xyz { x: s.x as i32, y: s.y as i32, z: s.z as i32 };
    let region = Region {
        position: Xyz { x: 0, y: 0, z: 0 },
        size: Xyz { ..size },
        block_state_palette: palette
            .iter()
            .map(|b| PaletteEntry { name: b.name.clone(), properties: b.properties.iter().cloned().collect() })
            .collect(),
        block_states: LongArray::new(pack_tight(&cells, bits)),
        tile_entities: Vec::new(),
        entities: Vec::new(),
        pending_block_ticks: Vec::new(),
        pending_fluid_ticks: Vec::new(),
    };
    let file = File {
        minecraft_data_version: data_version,
        version: if data_version < LITEMATIC_V7_DATA_VERSION { 6 } else { 7 },
        sub_version: 1,
        metadata: Metadata {
            name,
            author: "genform",
            description: "",
            region_count: 1,
            total_volume: volume as i32,
            total_blocks,
            time_created: FIXED_TIME_MS,
            time_modified: FIXED_TIME_MS,
            enclosing_size: Xyz { ..size },
        },
        regions: BTreeMap::from([(name, region)]),
    };
    Ok(nbt_file::write_gzipped(&file, ""))
}

/// Reads a Litematica schematic: every region into one grid covering them
/// all, placed relative to the schematic origin (regions with negative
/// sizes extend from their position towards −∞). Air is read as air (set
/// cells); where regions overlap, later ones (by name) win.
pub fn read_litematic(bytes: &[u8]) -> Result<BlockGrid, MinecraftError> {
    let root = nbt_file::read_root(bytes, FORMAT)?;
    let version = nbt_file::int(&root, "Version", FORMAT)? as i32;
    if !(1..=7).contains(&version) {
        return Err(MinecraftError::UnsupportedVersion { format: FORMAT, version, supported: "1 to 7" });
    }
    let regions = nbt_file::compound(&root, "Regions", FORMAT)?;
    let mut names: Vec<&String> = regions.keys().collect();
    names.sort();
    let mut grids = Vec::with_capacity(names.len());
    for name in names {
        let Value::Compound(r) = &regions[name] else {
            return Err(malformed(FORMAT, format!("region `{name}` is not a compound")));
        };
        grids.push(read_region(r).map_err(|e| match e {
            MinecraftError::Malformed { format, reason } => {
                MinecraftError::Malformed { format, reason: format!("region `{name}`: {reason}") }
            }
            e => e,
        })?);
    }
    merge_grids(&grids).ok_or_else(|| malformed(FORMAT, "it has no regions"))
}

fn read_region(r: &Compound) -> Result<BlockGrid, MinecraftError> {
    let pos = nbt_file::xyz(r, "Position", FORMAT)?;
    let size = nbt_file::xyz(r, "Size", FORMAT)?;
    let abs = size.map(i64::unsigned_abs);
    if abs.iter().any(|&a| a > 1 << 20) {
        return Err(malformed(FORMAT, format!("a size of {size:?} is not plausible")));
    }
    let volume = (abs[0] * abs[1] * abs[2]) as usize;
    // A negative size extends from the position towards −∞.
    let min: [i64; 3] = std::array::from_fn(|i| if size[i] < 0 { pos[i] + size[i] + 1 } else { pos[i] });
    let Some(Value::List(entries)) = r.get("BlockStatePalette") else {
        return Err(malformed(FORMAT, "`BlockStatePalette` is missing or not a list"));
    };
    let palette = entries.iter().map(palette_entry).collect::<Result<Vec<_>, _>>()?;
    if palette.is_empty() {
        return Err(malformed(FORMAT, "the palette is empty"));
    }
    let Some(Value::LongArray(data)) = r.get("BlockStates") else {
        return Err(malformed(FORMAT, "`BlockStates` is missing or not a long array"));
    };
    let bits = litematic_bits(palette.len());
    if data.len() < tight_len(volume, bits) {
        return Err(malformed(
            FORMAT,
            format!(
                "{} longs of block states; {volume} blocks at {bits} bits need {}",
                data.len(),
                tight_len(volume, bits)
            ),
        ));
    }
    let cells = unpack_tight(data, bits, volume).ok_or_else(|| malformed(FORMAT, "the block states are too short"))?;
    if let Some(bad) = cells.iter().find(|&&c| c as usize >= palette.len()) {
        return Err(malformed(FORMAT, format!("a block refers to palette entry {bad} of {}", palette.len())));
    }
    let origin = IVec3::new(min[0] as i32, min[1] as i32, min[2] as i32);
    let size = UVec3::new(abs[0] as u32, abs[1] as u32, abs[2] as u32);
    Ok(BlockGrid { origin, size, palette, cells })
}

fn palette_entry(v: &Value) -> Result<BlockState, MinecraftError> {
    let Value::Compound(m) = v else { return Err(malformed(FORMAT, "a palette entry is not a compound")) };
    let Some(Value::String(name)) = m.get("Name") else {
        return Err(malformed(FORMAT, "a palette entry has no Name"));
    };
    let mut properties = Vec::new();
    if let Some(Value::Compound(p)) = m.get("Properties") {
        for (k, v) in p {
            if let Value::String(v) = v {
                properties.push((k.clone(), v.clone()));
            }
        }
    }
    properties.sort();
    let name = if name.contains(':') { name.clone() } else { format!("minecraft:{name}") };
    Ok(BlockState { name, properties })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::minecraft::test_grids::{as_strings, random};

    fn root_of(bytes: &[u8]) -> Compound {
        nbt_file::read_root(bytes, FORMAT).unwrap()
    }

    #[test]
    fn round_trips_with_properties_and_unset() {
        for (states, seed) in [(1, 1), (3, 2), (5, 3), (10, 4), (40, 5)] {
            let mut g = random(UVec3::new(9, 4, 7), seed, states);
            let bytes = write_litematic(&g, 3955, "house").unwrap();
            let back = read_litematic(&bytes).unwrap();
            assert_eq!(back.size, g.size);
            assert_eq!(back.origin, IVec3::ZERO);
            g.origin = IVec3::ZERO;
            assert_eq!(as_strings(&back), as_strings(&g), "{states} states");
            assert_eq!(write_litematic(&g, 3955, "house").unwrap(), bytes, "deterministic");
        }
    }

    #[test]
    fn header_metadata_and_packing_by_hand() {
        // 5 states + air = 6 entries → 3 bits; 23 cells → 69 bits → 2
        // longs, cell 21 straddling the first boundary.
        let mut g = BlockGrid::new(IVec3::new(4, 5, 6), UVec3::new(23, 1, 1));
        let names = ["stone", "dirt", "glass", "sand", "gravel"];
        for (i, n) in names.iter().enumerate() {
            g.set(IVec3::new(4 + i as i32, 5, 6), &BlockState::new(n));
        }
        g.set(IVec3::new(4 + 21, 5, 6), &BlockState::new("sand"));
        g.set(IVec3::new(4 + 22, 5, 6), &BlockState::new("gravel"));
        let root = root_of(&write_litematic(&g, 3700, "r").unwrap());
        assert_eq!(root["Version"], Value::Int(6));
        assert_eq!(root["MinecraftDataVersion"], Value::Int(3700));
        let meta = nbt_file::compound(&root, "Metadata", FORMAT).unwrap();
        assert_eq!(meta["TotalBlocks"], Value::Int(7));
        assert_eq!(meta["TotalVolume"], Value::Int(23));
        assert_eq!(meta["RegionCount"], Value::Int(1));
        assert_eq!(meta["TimeCreated"], Value::Long(FIXED_TIME_MS));
        assert_eq!(nbt_file::xyz(meta, "EnclosingSize", FORMAT).unwrap(), [23, 1, 1]);
        let region = nbt_file::compound(nbt_file::compound(&root, "Regions", FORMAT).unwrap(), "r", FORMAT).unwrap();
        let Value::List(p) = &region["BlockStatePalette"] else { panic!() };
        let Value::Compound(first) = &p[0] else { panic!() };
        assert_eq!(first["Name"], Value::String("minecraft:air".into()));
        let Value::LongArray(d) = &region["BlockStates"] else { panic!() };
        // Cells 0..5 hold 1..=5 (3 bits each); cell 21 (sand = 4 = 0b100)
        // starts at bit 63: its low bit 0 in long 0, its high bits 0b10 in
        // long 1; cell 22 (gravel = 5 = 0b101) at bits 2..5 of long 1.
        let low: u64 = (1..=5u64).enumerate().map(|(i, v)| v << (3 * i)).sum();
        assert_eq!(d[0] as u64, low);
        assert_eq!(d[1] as u64, 0b10 | 0b101 << 2);
        assert_eq!(d.len(), 2);
        let root = root_of(&write_litematic(&g, 3837, "r").unwrap());
        assert_eq!(root["Version"], Value::Int(7));
    }

    #[test]
    fn negative_sizes_and_several_regions() {
        let g = random(UVec3::new(3, 2, 2), 8, 4);
        let bytes = write_litematic(&g, 3955, "a").unwrap();
        let mut root = root_of(&bytes);
        let Some(Value::Compound(regions)) = root.get_mut("Regions") else { panic!() };
        let mut a = regions["a"].clone();
        // The same blocks, now described from the opposite corner.
        if let Value::Compound(r) = &mut a {
            r.insert("Position".into(), fastnbt::nbt!({"x": 12, "y": 1, "z": 1}));
            r.insert("Size".into(), fastnbt::nbt!({"x": -3, "y": -2, "z": -2}));
        }
        regions.insert("b".into(), a);
        let raw = fastnbt::to_bytes(&Value::Compound(root)).unwrap();
        let back = read_litematic(&raw).unwrap();
        assert_eq!(back.origin, IVec3::new(0, 0, 0));
        assert_eq!(back.size, UVec3::new(13, 2, 2));
        let at = |p: IVec3| back.get(p).map(|s| s.to_string());
        assert_eq!(at(IVec3::new(10, 1, 0)), at(IVec3::new(0, 1, 0)));
        assert_eq!(at(IVec3::new(12, 0, 1)), at(IVec3::new(2, 0, 1)));
        assert_eq!(at(IVec3::new(5, 0, 0)), None);
    }

    #[test]
    fn bad_inputs_are_errors() {
        let bytes = write_litematic(&random(UVec3::new(5, 5, 5), 2, 7), 3955, "x").unwrap();
        for cut in [0, 1, 5, bytes.len() / 2, bytes.len() - 1] {
            assert!(read_litematic(&bytes[..cut]).is_err(), "cut at {cut}");
        }
        let mut raw = Vec::new();
        std::io::Read::read_to_end(&mut flate2::read::GzDecoder::new(&bytes[..]), &mut raw).unwrap();
        let mut rng = 5u64;
        for _ in 0..3000 {
            let mut b = raw.clone();
            rng = rng.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            let i = (rng >> 33) as usize % b.len();
            b[i] = (rng >> 7) as u8;
            let _ = read_litematic(&b);
        }
    }
}
