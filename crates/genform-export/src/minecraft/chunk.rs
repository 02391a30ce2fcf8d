//! One 1.18+ chunk: its NBT tree, its sections' block states, and edits
//! that keep every tag they do not change.

use super::constants::MIN_CHUNK_DATA_VERSION;
use super::error::MinecraftError;
use super::nbt::{self, Tag};
use super::packing::{aligned_len, pack_aligned, section_bits, unpack_aligned};
use genform_core::blocks::BlockState;

/// Blocks per section.
pub(crate) const SECTION_CELLS: usize = 4096;

/// A decoded chunk.
pub(crate) struct Chunk {
    /// World chunk coordinates.
    pub cx: i32,
    pub cz: i32,
    root_name: Vec<u8>,
    pub root: Tag,
}

/// A section's blocks: its palette and one palette index per block
/// (`y*256 + z*16 + x`).
pub(crate) struct SectionBlocks {
    pub palette: Vec<BlockState>,
    pub indices: SectionIndices,
}

/// Block indices of a section: one palette entry everywhere, or one per
/// block.
pub(crate) enum SectionIndices {
    Uniform,
    PerBlock(Vec<u32>),
}

impl Chunk {
    /// Decodes chunk NBT read from the region entry of chunk (`cx`, `cz`)
    /// and checks that it is a 1.18+ chunk of that position.
    pub fn decode(bytes: &[u8], cx: i32, cz: i32) -> Result<Chunk, MinecraftError> {
        let bad = |reason: String| MinecraftError::ChunkUnreadable { x: cx, z: cz, reason };
        let (root_name, root) = nbt::decode(bytes).map_err(|e| bad(format!("bad NBT: {e}")))?;
        let version = root.get("DataVersion").and_then(Tag::as_i64);
        let version = version.ok_or_else(|| bad("no DataVersion".into()))? as i32;
        if version < MIN_CHUNK_DATA_VERSION || root.get("Level").is_some() {
            return Err(MinecraftError::UnsupportedDataVersion { x: cx, z: cz, version });
        }
        let pos = |k| root.get(k).and_then(Tag::as_i64).map(|v| v as i32);
        if let (Some(x), Some(z)) = (pos("xPos"), pos("zPos"))
            && (x, z) != (cx, cz)
        {
            return Err(bad(format!(
                "it says it is chunk ({x}, {z}); is the region file named after its real coordinates?"
            )));
        }
        if root.get("sections").and_then(Tag::as_list).is_none() {
            return Err(bad("no `sections` list".into()));
        }
        Ok(Chunk { cx, cz, root_name, root })
    }

    /// The chunk's NBT bytes.
    pub fn encode(&self) -> Vec<u8> {
        nbt::encode(&self.root_name, &self.root)
    }

    /// The generation status without namespace (`full`, `features`, …).
    pub fn status(&self) -> String {
        let s = self.root.get("Status").and_then(Tag::as_str).unwrap_or_default();
        s.strip_prefix("minecraft:").map(str::to_string).unwrap_or(s)
    }

    /// Whether generation finished: only such chunks count as terrain.
    pub fn is_full(&self) -> bool {
        self.status() == "full"
    }

    fn sections(&self) -> &[Tag] {
        self.root.get("sections").and_then(Tag::as_list).unwrap_or(&[])
    }

    fn bad(&self, reason: String) -> MinecraftError {
        MinecraftError::ChunkUnreadable { x: self.cx, z: self.cz, reason }
    }

    /// The sections with block states whose y `keep` accepts: (section y,
    /// its blocks).
    pub fn section_blocks(&self, keep: impl Fn(i32) -> bool) -> Result<Vec<(i32, SectionBlocks)>, MinecraftError> {
        let mut out = Vec::new();
        for s in self.sections() {
            let Some(y) = s.get("Y").and_then(Tag::as_i64) else { continue };
            if !keep(y as i32) {
                continue;
            }
            if let Some(states) = s.get("block_states") {
                let blocks = decode_block_states(states).map_err(|r| self.bad(format!("section y = {y}: {r}")))?;
                out.push((y as i32, blocks));
            }
        }
        Ok(out)
    }

    /// Section ys that hold blocks, lowest and highest.
    pub fn section_range(&self) -> Option<(i32, i32)> {
        let ys = self
            .sections()
            .iter()
            .filter(|s| s.get("block_states").is_some())
            .filter_map(|s| s.get("Y").and_then(Tag::as_i64).map(|y| y as i32));
        ys.fold(None, |r, y| Some(r.map_or((y, y), |(lo, hi): (i32, i32)| (lo.min(y), hi.max(y)))))
    }

    /// Rewrites section `sy`: `cell(i)` is the new state of section cell
    /// `i` as an index into `states`, or `None` to keep the block. The
    /// section is created (air, biomes copied from the nearest section)
    /// when missing. Unused palette entries are dropped; kept entries keep
    /// their NBT as read. Returns the cells whose state changed.
    pub fn edit_section(
        &mut self,
        sy: i32,
        states: &[BlockState],
        cell: impl Fn(usize) -> Option<u32>,
    ) -> Result<Vec<usize>, MinecraftError> {
        let index = self.section_index_or_create(sy);
        let (cx, cz) = (self.cx, self.cz);
        let sections = self.root.get_mut("sections").and_then(Tag::as_list_mut).expect("checked at decode");
        let section = &mut sections[index];
        if section.get("block_states").is_none() {
            section.insert("block_states", air_states());
        }
        let block_states = section.get_mut("block_states").expect("just ensured");
        let bad = |reason: String| MinecraftError::ChunkUnreadable { x: cx, z: cz, reason };
        let blocks = decode_block_states(block_states).map_err(|r| bad(format!("section y = {sy}: {r}")))?;
        let mut entries: Vec<Tag> =
            block_states.get("palette").and_then(Tag::as_list).map(<[Tag]>::to_vec).unwrap_or_default();
        let mut palette = blocks.palette;
        let mut idx = match blocks.indices {
            SectionIndices::Uniform => vec![0u32; SECTION_CELLS],
            SectionIndices::PerBlock(v) => v,
        };
        // Section palette index of each grid state, found on first use.
        let mut local: Vec<Option<u32>> = vec![None; states.len()];
        let mut changed = Vec::new();
        for (i, slot) in idx.iter_mut().enumerate() {
            let Some(new) = cell(i) else { continue };
            let Some(state) = states.get(new as usize) else { continue };
            let k = *local[new as usize].get_or_insert_with(|| match palette.iter().position(|p| p == state) {
                Some(k) => k as u32,
                None => {
                    entries.push(palette_entry(state));
                    palette.push(state.clone());
                    (palette.len() - 1) as u32
                }
            });
            if *slot != k {
                *slot = k;
                changed.push(i);
            }
        }
        if changed.is_empty() {
            return Ok(changed);
        }
        // Drop unused entries, keeping the order of the rest.
        let mut count = vec![0usize; palette.len()];
        idx.iter().for_each(|&i| count[i as usize] += 1);
        let mut remap = vec![0u32; palette.len()];
        let mut kept = Vec::new();
        for (i, e) in entries.into_iter().enumerate() {
            if count[i] > 0 {
                remap[i] = kept.len() as u32;
                kept.push(e);
            }
        }
        idx.iter_mut().for_each(|i| *i = remap[*i as usize]);
        let n = kept.len();
        block_states.insert("palette", nbt::list(kept));
        if n == 1 {
            block_states.remove("data");
        } else {
            block_states.insert("data", Tag::LongArray(pack_aligned(&idx, section_bits(n))));
        }
        Ok(changed)
    }

    /// The position of section `sy` in `sections`, creating it (in y
    /// order) when missing.
    fn section_index_or_create(&mut self, sy: i32) -> usize {
        let sections = self.sections();
        let y_of = |s: &Tag| s.get("Y").and_then(Tag::as_i64).map(|y| y as i32);
        if let Some(i) = sections.iter().position(|s| y_of(s) == Some(sy)) {
            return i;
        }
        // Biomes from the nearest section that has them, else plains.
        let biomes = sections
            .iter()
            .filter(|s| s.get("biomes").is_some())
            .min_by_key(|s| y_of(s).map_or(i32::MAX, |y| (y - sy).abs()))
            .and_then(|s| s.get("biomes").cloned())
            .unwrap_or_else(|| {
                Tag::Compound(vec![(b"palette".to_vec(), nbt::list(vec![Tag::string("minecraft:plains")]))])
            });
        let at = sections.iter().position(|s| y_of(s).is_some_and(|y| y > sy)).unwrap_or(sections.len());
        let section = Tag::Compound(vec![
            (b"Y".to_vec(), Tag::Byte(sy as i8)),
            (b"block_states".to_vec(), air_states()),
            (b"biomes".to_vec(), biomes),
        ]);
        let list = self.root.get_mut("sections").and_then(Tag::as_list_mut).expect("checked at decode");
        list.insert(at, section);
        at
    }

    /// Removes block entities at `positions` (world block coordinates):
    /// the blocks there changed, and an entity left behind would belong to
    /// a block that is gone.
    pub fn remove_block_entities(&mut self, positions: &std::collections::HashSet<[i32; 3]>) {
        let Some(list) = self.root.get_mut("block_entities").and_then(Tag::as_list_mut) else { return };
        list.retain(|e| {
            let c = |k| e.get(k).and_then(Tag::as_i64).map(|v| v as i32);
            match (c("x"), c("y"), c("z")) {
                (Some(x), Some(y), Some(z)) => !positions.contains(&[x, y, z]),
                _ => true,
            }
        });
    }

    /// Marks the chunk's stored light as stale so Minecraft relights it on
    /// load (`isLightOn = 0`).
    pub fn invalidate_light(&mut self) {
        self.root.insert("isLightOn", Tag::Byte(0));
    }
}

/// `block_states` of an all-air section.
fn air_states() -> Tag {
    Tag::Compound(vec![(b"palette".to_vec(), nbt::list(vec![palette_entry(&BlockState::air())]))])
}

/// A palette compound: `{Name, Properties{k: v}}` (no Properties when
/// there are none, as Minecraft writes it).
pub(crate) fn palette_entry(s: &BlockState) -> Tag {
    let mut items = vec![(b"Name".to_vec(), Tag::string(&s.name))];
    if !s.properties.is_empty() {
        let props = s.properties.iter().map(|(k, v)| (nbt::to_mutf8(k), Tag::string(v))).collect();
        items.push((b"Properties".to_vec(), Tag::Compound(props)));
    }
    Tag::Compound(items)
}

/// A palette compound as a block state (properties sorted).
pub(crate) fn parse_palette_entry(t: &Tag) -> Result<BlockState, String> {
    let name = t.get("Name").and_then(Tag::as_str).ok_or("a palette entry has no Name")?;
    let mut properties: Vec<(String, String)> = match t.get("Properties").and_then(Tag::as_compound) {
        Some(p) => p.iter().filter_map(|(k, v)| Some((nbt::from_mutf8(k), v.as_str()?))).collect(),
        None => Vec::new(),
    };
    properties.sort();
    Ok(BlockState { name, properties })
}

/// Decodes a section's `block_states` compound.
fn decode_block_states(states: &Tag) -> Result<SectionBlocks, String> {
    let entries = states.get("palette").and_then(Tag::as_list).ok_or("block_states has no palette")?;
    if entries.is_empty() {
        return Err("block_states has an empty palette".into());
    }
    let palette = entries.iter().map(parse_palette_entry).collect::<Result<Vec<_>, _>>()?;
    let data = match states.get("data") {
        Some(Tag::LongArray(d)) => d,
        Some(_) => return Err("block_states data is not a long array".into()),
        None if palette.len() == 1 => return Ok(SectionBlocks { palette, indices: SectionIndices::Uniform }),
        None => return Err(format!("block_states has {} palette entries but no data", palette.len())),
    };
    if palette.len() == 1 {
        return Ok(SectionBlocks { palette, indices: SectionIndices::Uniform });
    }
    let bits = section_bits(palette.len());
    if data.len() != aligned_len(SECTION_CELLS, bits) {
        return Err(format!(
            "block_states data has {} longs; {} palette entries at {bits} bits need {}",
            data.len(),
            palette.len(),
            aligned_len(SECTION_CELLS, bits)
        ));
    }
    let idx = unpack_aligned(data, bits, SECTION_CELLS).ok_or("block_states data is too short")?;
    if let Some(&bad) = idx.iter().find(|&&i| i as usize >= palette.len()) {
        return Err(format!("a block refers to palette entry {bad} of {}", palette.len()));
    }
    Ok(SectionBlocks { palette, indices: SectionIndices::PerBlock(idx) })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::minecraft::region::tests::fixture;
    use flate2::read::ZlibDecoder;
    use std::io::Read;

    /// The NBT of local chunk (`x`, `z`) of a fixture.
    fn chunk_nbt(dir: &str, x: usize, z: usize) -> Vec<u8> {
        let r = fixture(dir);
        let i = 4 * (x + 32 * z);
        let sector =
            (usize::from(r.bytes[i]) << 16 | usize::from(r.bytes[i + 1]) << 8 | usize::from(r.bytes[i + 2])) * 4096;
        let len = u32::from_be_bytes(r.bytes[sector..sector + 4].try_into().unwrap()) as usize;
        assert_eq!(r.bytes[sector + 4], 2, "zlib");
        let mut out = Vec::new();
        ZlibDecoder::new(&r.bytes[sector + 5..sector + 4 + len]).read_to_end(&mut out).unwrap();
        out
    }

    #[test]
    fn real_chunks_re_encode_byte_for_byte() {
        for (dir, x, z) in [("fastanvil-1.19.4", 3, 4), ("prismarine-1.21.1", 1, 2), ("fastanvil-1.19.4", 20, 20)] {
            let nbt = chunk_nbt(dir, x, z);
            let c = Chunk::decode(&nbt, x as i32, z as i32).unwrap();
            assert_eq!(c.encode(), nbt, "{dir} ({x}, {z})");
        }
    }

    #[test]
    fn a_missing_section_is_created_in_order_with_neighbour_biomes() {
        let nbt = chunk_nbt("prismarine-1.21.1", 1, 1);
        let mut c = Chunk::decode(&nbt, 1, 1).unwrap();
        let y_of = |s: &Tag| s.get("Y").and_then(Tag::as_i64).unwrap();
        let list = c.root.get_mut("sections").and_then(Tag::as_list_mut).unwrap();
        let at = list.iter().position(|s| y_of(s) == 5).unwrap();
        list.remove(at);
        let biomes_4 = list.iter().find(|s| y_of(s) == 4).unwrap().get("biomes").cloned().unwrap();
        let stone = [BlockState::new("stone")];
        // Cell 0 and the top corner cell 4095 become stone.
        let changed = c.edit_section(5, &stone, |i| (i == 0 || i == 4095).then_some(0)).unwrap();
        assert_eq!(changed, [0, 4095]);
        let list = c.root.get("sections").and_then(Tag::as_list).unwrap();
        let ys: Vec<i64> = list.iter().map(y_of).collect();
        assert!(ys.windows(2).all(|w| w[0] < w[1]), "{ys:?}");
        let s5 = &list[at];
        assert_eq!(y_of(s5), 5);
        assert_eq!(s5.get("biomes"), Some(&biomes_4));
        let blocks = decode_block_states(s5.get("block_states").unwrap()).unwrap();
        assert_eq!(blocks.palette, [BlockState::air(), BlockState::new("stone")]);
        let SectionIndices::PerBlock(idx) = blocks.indices else { panic!("two entries need data") };
        assert_eq!((idx[0], idx[1], idx[4095]), (1, 0, 1));
        // The first long holds cell 0 in its low nibble.
        let Some(Tag::LongArray(d)) = s5.get("block_states").and_then(|b| b.get("data")) else { panic!() };
        assert_eq!(d[0], 1);
        assert_eq!(d[255] as u64, 1 << 60);
    }

    #[test]
    fn bad_block_states_are_described() {
        let entry = |n: &str| palette_entry(&BlockState::new(n));
        let states = |palette: Vec<Tag>, data: Option<Vec<i64>>| {
            let mut items = vec![(b"palette".to_vec(), nbt::list(palette))];
            if let Some(d) = data {
                items.push((b"data".to_vec(), Tag::LongArray(d)));
            }
            Tag::Compound(items)
        };
        let err = |t: Tag| decode_block_states(&t).err().unwrap();
        assert!(err(states(vec![], None)).contains("empty palette"));
        assert!(err(states(vec![entry("a"), entry("b")], None)).contains("no data"));
        assert!(err(states(vec![entry("a"), entry("b")], Some(vec![0; 10]))).contains("need 256"));
        // Index 3 with two entries.
        assert!(err(states(vec![entry("a"), entry("b")], Some(vec![3; 256]))).contains("palette entry 3 of 2"));
        let ok = decode_block_states(&states(vec![entry("a")], Some(vec![7; 3]))).unwrap();
        assert!(matches!(ok.indices, SectionIndices::Uniform));
        let props = palette_entry(&BlockState::parse("oak_log[axis=y]").unwrap());
        assert_eq!(parse_palette_entry(&props).unwrap().to_string(), "minecraft:oak_log[axis=y]");
    }
}
