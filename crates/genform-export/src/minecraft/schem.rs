//! Sponge schematics (`.schem`, gzipped NBT), versions 2 and 3 (1 is read
//! like 2).
//!
//! Blocks are a palette (`"minecraft:x[k=v]"` → index) and one varint per
//! block, x fastest, then z, then y (`x + z·W + y·W·L`). Version 2 keeps
//! the fields in the root compound (named `Schematic`); version 3 nests them
//! in a `Schematic` compound and the blocks in `Blocks{Palette, Data}`.

use super::error::{MinecraftError, malformed};
use super::grid::{check_grid, dense_palette};
use super::nbt_file::{self, Compound};
use super::packing::{put_varint, read_varints};
use fastnbt::{ByteArray, IntArray, Value};
use genform_core::blocks::{BlockGrid, BlockState};
use glam::{IVec3, UVec3};
use serde::Serialize;
use serde::ser::SerializeMap;

const FORMAT: &str = "schem";
const LIMIT: &str = "at most 65535 blocks per side (sizes are shorts) and 2³¹ bytes of block data";

/// Which Sponge schematic version to write.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum SchemVersion {
    /// Version 2 (WorldEdit 7.0–7.2 and most tools).
    #[default]
    V2,
    /// Version 3 (WorldEdit 7.3+).
    V3,
}

/// The palette as an NBT compound in palette order.
struct Palette<'a>(&'a [BlockState]);

impl Serialize for Palette<'_> {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        let mut m = s.serialize_map(Some(self.0.len()))?;
        for (i, state) in self.0.iter().enumerate() {
            m.serialize_entry(&state.to_string(), &(i as i32))?;
        }
        m.end()
    }
}

#[derive(Serialize)]
#[serde(rename_all = "PascalCase")]
struct V2<'a> {
    version: i32,
    data_version: i32,
    width: i16,
    height: i16,
    length: i16,
    offset: IntArray,
    palette_max: i32,
    palette: Palette<'a>,
    block_data: ByteArray,
    block_entities: Vec<Value>,
}

#[derive(Serialize)]
struct V3Root<'a> {
    #[serde(rename = "Schematic")]
    schematic: V3<'a>,
}

#[derive(Serialize)]
#[serde(rename_all = "PascalCase")]
struct V3<'a> {
    version: i32,
    data_version: i32,
    width: i16,
    height: i16,
    length: i16,
    offset: IntArray,
    blocks: V3Blocks<'a>,
}

#[derive(Serialize)]
#[serde(rename_all = "PascalCase")]
struct V3Blocks<'a> {
    palette: Palette<'a>,
    data: ByteArray,
    block_entities: Vec<Value>,
}

/// Writes `grid` as a gzipped Sponge schematic of `version`.
///
/// `Offset` is the grid origin; the palette lists the states in use in
/// first-use order. Sponge has no "leave as is" block, so unset cells are
/// written as `minecraft:air` (pasting with WorldEdit's `-a` skips air).
/// No block entities or entities are written.
///
/// Errors with [`MinecraftError::TooLarge`] when a side exceeds 65535 (the
/// sizes are unsigned shorts).
pub fn write_schem(grid: &BlockGrid, version: SchemVersion, data_version: i32) -> Result<Vec<u8>, MinecraftError> {
    check_grid(grid)?;
    let s = grid.size;
    if s.max_element() > u32::from(u16::MAX) {
        return Err(MinecraftError::TooLarge { format: FORMAT, size: s, limit: LIMIT });
    }
    let (palette, cells) = dense_palette(grid, false);
    // Cells are already in Sponge order: x, then z, then y.
    let mut data = Vec::with_capacity(cells.len());
    for c in cells {
        put_varint(&mut data, c);
    }
    if data.len() > i32::MAX as usize {
        return Err(MinecraftError::TooLarge { format: FORMAT, size: s, limit: LIMIT });
    }
    let data = ByteArray::new(data.into_iter().map(|b| b as i8).collect());
    let offset = IntArray::new(grid.origin.to_array().to_vec());
    let (w, h, l) = (s.x as u16 as i16, s.y as u16 as i16, s.z as u16 as i16);
    Ok(match version {
        SchemVersion::V2 => nbt_file::write_gzipped(
            &V2 {
                version: 2,
                data_version,
                width: w,
                height: h,
                length: l,
                offset,
                palette_max: palette.len() as i32,
                palette: Palette(&palette),
                block_data: data,
                block_entities: Vec::new(),
            },
            "Schematic",
        ),
        SchemVersion::V3 => nbt_file::write_gzipped(
            &V3Root {
                schematic: V3 {
                    version: 3,
                    data_version,
                    width: w,
                    height: h,
                    length: l,
                    offset,
                    blocks: V3Blocks { palette: Palette(&palette), data, block_entities: Vec::new() },
                },
            },
            "",
        ),
    })
}

/// Reads a Sponge schematic (version 1, 2 or 3; gzipped or not) into a
/// grid at its `Offset` (origin 0 when absent). Air is read as air (set
/// cells). Block entities, entities and biomes are ignored.
pub fn read_schem(bytes: &[u8]) -> Result<BlockGrid, MinecraftError> {
    let root = nbt_file::read_root(bytes, FORMAT)?;
    let (m, nested) = match root.get("Schematic") {
        Some(Value::Compound(inner)) => (inner, true),
        _ => (&root, false),
    };
    let version = nbt_file::int(m, "Version", FORMAT)? as i32;
    let supported = "1, 2, 3";
    match (version, nested) {
        (1 | 2, _) | (3, true) => {}
        (3, false) => return Err(malformed(FORMAT, "version 3 data must sit in a `Schematic` compound")),
        _ => return Err(MinecraftError::UnsupportedVersion { format: FORMAT, version, supported }),
    }
    let side = |k: &str| nbt_file::int(m, k, FORMAT).map(|v| u32::from(v as u16));
    let size = UVec3::new(side("Width")?, side("Height")?, side("Length")?);
    let origin = match m.get("Offset") {
        Some(Value::IntArray(a)) if a.len() == 3 => IVec3::new(a[0], a[1], a[2]),
        Some(_) => return Err(malformed(FORMAT, "`Offset` is not three ints")),
        None => IVec3::ZERO,
    };
    let (palette, data) = if version == 3 {
        let blocks = nbt_file::compound(m, "Blocks", FORMAT)?;
        (nbt_file::compound(blocks, "Palette", FORMAT)?, blocks.get("Data"))
    } else {
        (nbt_file::compound(m, "Palette", FORMAT)?, m.get("BlockData"))
    };
    let Some(Value::ByteArray(data)) = data else {
        return Err(malformed(FORMAT, "the block data is missing or not a byte array"));
    };
    let states = palette_states(palette)?;
    let volume = size.x as usize * size.y as usize * size.z as usize;
    // Each block takes at least one byte: check before allocating.
    if data.len() < volume {
        return Err(malformed(FORMAT, format!("{} bytes of block data for {volume} blocks", data.len())));
    }
    let bytes: Vec<u8> = data.iter().map(|&b| b as u8).collect();
    let cells = read_varints(&bytes, volume).ok_or_else(|| malformed(FORMAT, "the block data ends early"))?;
    let mut grid = BlockGrid::new(origin, size);
    let mut map: Vec<Option<u32>> = vec![None; states.len()];
    for (dst, c) in grid.cells.iter_mut().zip(cells) {
        let Some(Some(state)) = states.get(c as usize) else {
            return Err(malformed(FORMAT, format!("a block refers to palette index {c}, which is not in the palette")));
        };
        *dst = *map[c as usize].get_or_insert_with(|| {
            grid.palette.push(state.clone());
            (grid.palette.len() - 1) as u32
        });
    }
    Ok(grid)
}

/// Palette compound → state per index (`None` for unused indices).
fn palette_states(palette: &Compound) -> Result<Vec<Option<BlockState>>, MinecraftError> {
    let mut entries = Vec::with_capacity(palette.len());
    for (name, v) in palette {
        let i = match v {
            Value::Int(i) => *i,
            _ => return Err(malformed(FORMAT, format!("palette entry `{name}` is not an int"))),
        };
        if i < 0 || i as usize > 4 * palette.len() + 1024 {
            return Err(malformed(FORMAT, format!("palette entry `{name}` has index {i}")));
        }
        let state = BlockState::parse(name).map_err(|e| malformed(FORMAT, format!("palette entry: {e}")))?;
        entries.push((i as usize, state));
    }
    let mut states = vec![None; entries.iter().map(|(i, _)| i + 1).max().unwrap_or(0)];
    for (i, s) in entries {
        states[i] = Some(s);
    }
    Ok(states)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::minecraft::test_grids::{as_strings, random};

    fn smallhouse() -> Vec<u8> {
        std::fs::read(concat!(env!("CARGO_MANIFEST_DIR"), "/../../examples/terrain/smallhouse1.schem")).unwrap()
    }

    #[test]
    fn v2_and_v3_round_trip_with_properties_and_unset() {
        let g = random(UVec3::new(7, 5, 6), 3, 10);
        for v in [SchemVersion::V2, SchemVersion::V3] {
            let bytes = write_schem(&g, v, 3955).unwrap();
            assert_eq!(&bytes[..2], &[0x1F, 0x8B]);
            let back = read_schem(&bytes).unwrap();
            assert_eq!((back.origin, back.size), (g.origin, g.size));
            assert_eq!(as_strings(&back), as_strings(&g), "{v:?}");
            // Unset cells come back as air, which is set.
            assert_eq!(back.set_count(), back.volume());
            assert_eq!(write_schem(&g, v, 3955).unwrap(), bytes, "deterministic");
        }
    }

    #[test]
    fn layout_matches_the_spec_for_an_independent_decoder() {
        let mut g = BlockGrid::new(IVec3::new(5, -2, 9), UVec3::new(3, 2, 2));
        g.set(IVec3::new(6, -2, 9), &BlockState::new("stone"));
        g.set(IVec3::new(5, -1, 10), &BlockState::parse("oak_stairs[facing=north]").unwrap());
        let v2 = write_schem(&g, SchemVersion::V2, 3337).unwrap();
        let mut nbt = Vec::new();
        std::io::Read::read_to_end(&mut flate2::read::GzDecoder::new(&v2[..]), &mut nbt).unwrap();
        // Root name `Schematic`.
        assert_eq!(&nbt[..12], b"\x0a\x00\x09Schematic");
        let root: Value = fastnbt::from_bytes(&nbt).unwrap();
        let Value::Compound(m) = root else { panic!() };
        assert_eq!(m["Version"], Value::Int(2));
        assert_eq!(m["DataVersion"], Value::Int(3337));
        assert_eq!((&m["Width"], &m["Height"], &m["Length"]), (&Value::Short(3), &Value::Short(2), &Value::Short(2)));
        assert_eq!(m["Offset"], Value::IntArray(IntArray::new(vec![5, -2, 9])));
        let Value::Compound(p) = &m["Palette"] else { panic!() };
        assert_eq!(p["minecraft:air"], Value::Int(2));
        assert_eq!(p["minecraft:stone"], Value::Int(0));
        assert_eq!(p["minecraft:oak_stairs[facing=north]"], Value::Int(1));
        assert_eq!(m["PaletteMax"], Value::Int(3));
        // x + z W + y W L: stone at (1,0,0) → 1; stairs at (0,1,1) → 9.
        let Value::ByteArray(d) = &m["BlockData"] else { panic!() };
        assert_eq!(&d[..], &[2, 0, 2, 2, 2, 2, 2, 2, 2, 1, 2, 2]);
    }

    #[test]
    fn reads_the_real_smallhouse() {
        let g = read_schem(&smallhouse()).unwrap();
        assert_eq!(g.size, UVec3::new(21, 28, 20));
        assert_eq!(g.palette.len(), 173);
        assert_eq!(g.set_count(), 21 * 28 * 20);
        let non_air = g.cells.iter().filter(|&&c| g.palette[c as usize].id() != "air").count();
        assert!(non_air > 1000, "{non_air} blocks");
        // Written again and re-read, it is the same house.
        let again = read_schem(&write_schem(&g, SchemVersion::V3, 2586).unwrap()).unwrap();
        assert_eq!(as_strings(&again), as_strings(&g));
    }

    #[test]
    fn bad_inputs_are_errors() {
        let big = BlockGrid::new(IVec3::ZERO, UVec3::new(70_000, 1, 1));
        assert!(matches!(write_schem(&big, SchemVersion::V2, 3955), Err(MinecraftError::TooLarge { .. })));
        let good = smallhouse();
        for cut in [0, 1, 2, 10, 100, good.len() / 2, good.len() - 1] {
            assert!(read_schem(&good[..cut]).is_err(), "cut at {cut}");
        }
        let g = random(UVec3::new(4, 3, 5), 9, 6);
        let raw = {
            let mut v = Vec::new();
            let bytes = write_schem(&g, SchemVersion::V2, 3955).unwrap();
            std::io::Read::read_to_end(&mut flate2::read::GzDecoder::new(&bytes[..]), &mut v).unwrap();
            v
        };
        let mut rng = 77u64;
        for _ in 0..3000 {
            let mut b = raw.clone();
            rng = rng.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            let i = (rng >> 33) as usize % b.len();
            b[i] = (rng >> 7) as u8;
            let _ = read_schem(&b);
        }
        let e = read_schem(&raw[..raw.len() - 3]).unwrap_err();
        assert!(e.to_string().contains("schem file is malformed"), "{e}");
    }
}
