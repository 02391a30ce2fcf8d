//! Block worlds: block states, their kinds, and dense boxes of blocks with a
//! palette — the terrain a block grammar observes and the blocks it builds.

use glam::{IVec3, UVec3};
use std::fmt;

/// A block state: a namespaced id and its properties, sorted by key
/// (`minecraft:oak_stairs[facing=east,half=bottom]`).
#[derive(Clone, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct BlockState {
    /// Namespaced id, e.g. `minecraft:stone`.
    pub name: String,
    /// Properties, sorted by key.
    pub properties: Vec<(String, String)>,
}

/// How a block behaves, for observer constraints.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum BlockKind {
    /// Air (`air`, `cave_air`, `void_air`).
    Air,
    /// A fluid (`water`, `lava`, `bubble_column`).
    Liquid,
    /// A full or partial block an entity collides with.
    Solid,
    /// Anything passable: plants, torches, rails, snow layers, signs, ….
    Passable,
}

/// Block ids (without namespace) that are passable although not air or
/// fluid; matched exactly or, for entries ending in `_`, as suffixes
/// (`*_sapling`, …).
const PASSABLE: &[&str] = &[
    "short_grass",
    "grass",
    "tall_grass",
    "fern",
    "large_fern",
    "dead_bush",
    "seagrass",
    "tall_seagrass",
    "kelp",
    "kelp_plant",
    "dandelion",
    "poppy",
    "blue_orchid",
    "allium",
    "azure_bluet",
    "red_tulip",
    "orange_tulip",
    "white_tulip",
    "pink_tulip",
    "oxeye_daisy",
    "cornflower",
    "lily_of_the_valley",
    "sunflower",
    "lilac",
    "rose_bush",
    "peony",
    "sugar_cane",
    "vine",
    "glow_lichen",
    "torch",
    "wall_torch",
    "redstone_wire",
    "rail",
    "snow",
    "brown_mushroom",
    "red_mushroom",
    "sweet_berry_bush",
    "cobweb",
    "lily_pad",
    "pink_petals",
    "hanging_roots",
    "spore_blossom",
    "small_dripleaf",
    "big_dripleaf_stem",
    "cave_vines",
    "cave_vines_plant",
    "twisting_vines",
    "weeping_vines",
    "light",
    "structure_void",
];

/// Suffixes of passable block ids.
const PASSABLE_SUFFIXES: &[&str] =
    &["_sapling", "_sign", "_button", "_pressure_plate", "_carpet", "_banner", "_coral_fan"];

impl BlockState {
    /// A block without properties; `name` gets the `minecraft:` namespace
    /// when it has none.
    pub fn new(name: &str) -> BlockState {
        BlockState { name: namespaced(name), properties: Vec::new() }
    }

    /// Air.
    pub fn air() -> BlockState {
        BlockState::new("minecraft:air")
    }

    /// Parses `id` or `id[key=value,…]` (namespace optional, properties
    /// sorted on the way in). The message says what is wrong.
    pub fn parse(text: &str) -> Result<BlockState, String> {
        let text = text.trim();
        let (name, props) = match text.split_once('[') {
            Some((n, rest)) => {
                let inner =
                    rest.strip_suffix(']').ok_or_else(|| format!("`{text}`: the properties need a closing `]`"))?;
                (n, Some(inner))
            }
            None => (text, None),
        };
        let valid_id = |s: &str| {
            !s.is_empty() && s.chars().all(|c| c.is_ascii_lowercase() || c.is_ascii_digit() || "_-./:".contains(c))
        };
        if !valid_id(name) || name.matches(':').count() > 1 {
            return Err(format!("`{name}` is not a block id (lowercase letters, digits, `_ - . /`, one `namespace:`)"));
        }
        let mut properties = Vec::new();
        if let Some(inner) = props.filter(|p| !p.trim().is_empty()) {
            for pair in inner.split(',') {
                let (k, v) = pair.split_once('=').ok_or_else(|| format!("`{pair}` in `{text}` is not `key=value`"))?;
                let (k, v) = (k.trim(), v.trim());
                if k.is_empty() || v.is_empty() {
                    return Err(format!("`{pair}` in `{text}` is not `key=value`"));
                }
                properties.push((k.to_string(), v.to_string()));
            }
        }
        properties.sort();
        properties.dedup_by(|a, b| a.0 == b.0);
        Ok(BlockState { name: namespaced(name), properties })
    }

    /// The id without its namespace.
    pub fn id(&self) -> &str {
        self.name.split_once(':').map_or(&self.name, |(_, id)| id)
    }

    /// What kind of block this is (by id; waterlogged blocks are solid).
    pub fn kind(&self) -> BlockKind {
        let id = self.id();
        match id {
            "air" | "cave_air" | "void_air" => BlockKind::Air,
            "water" | "lava" | "bubble_column" => BlockKind::Liquid,
            _ if PASSABLE.contains(&id) || PASSABLE_SUFFIXES.iter().any(|s| id.ends_with(s)) => BlockKind::Passable,
            _ => BlockKind::Solid,
        }
    }
}

fn namespaced(name: &str) -> String {
    if name.contains(':') { name.to_string() } else { format!("minecraft:{name}") }
}

impl fmt::Display for BlockState {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.name)?;
        if !self.properties.is_empty() {
            f.write_str("[")?;
            for (i, (k, v)) in self.properties.iter().enumerate() {
                if i > 0 {
                    f.write_str(",")?;
                }
                write!(f, "{k}={v}")?;
            }
            f.write_str("]")?;
        }
        Ok(())
    }
}

/// A dense box of blocks: `cells[(y * size.z + z) * size.x + x]` indexes
/// `palette`, or is [`BlockGrid::UNSET`] where the grid says nothing (a
/// grammar's `skip`, or terrain that was not loaded).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct BlockGrid {
    /// World position of the cell (0, 0, 0).
    pub origin: IVec3,
    /// Cells per axis.
    pub size: UVec3,
    /// Distinct block states.
    pub palette: Vec<BlockState>,
    /// Palette index per cell, x fastest, then z, then y.
    pub cells: Vec<u32>,
}

impl BlockGrid {
    /// A cell that holds no block.
    pub const UNSET: u32 = u32::MAX;

    /// A grid of `size` cells at `origin`, every cell unset.
    pub fn new(origin: IVec3, size: UVec3) -> BlockGrid {
        let n = size.x as usize * size.y as usize * size.z as usize;
        BlockGrid { origin, size, palette: Vec::new(), cells: vec![Self::UNSET; n] }
    }

    /// Number of cells.
    pub fn volume(&self) -> usize {
        self.cells.len()
    }

    /// The cell index of world position `p`, if inside.
    #[inline]
    pub fn index(&self, p: IVec3) -> Option<usize> {
        let l = p - self.origin;
        if l.cmplt(IVec3::ZERO).any() || l.as_uvec3().cmpge(self.size).any() {
            return None;
        }
        let l = l.as_uvec3();
        Some(((l.y as usize * self.size.z as usize) + l.z as usize) * self.size.x as usize + l.x as usize)
    }

    /// The palette index of `state`, added on first use.
    pub fn intern(&mut self, state: &BlockState) -> u32 {
        match self.palette.iter().position(|s| s == state) {
            Some(i) => i as u32,
            None => {
                self.palette.push(state.clone());
                (self.palette.len() - 1) as u32
            }
        }
    }

    /// The block at world position `p` (`None` outside or unset).
    pub fn get(&self, p: IVec3) -> Option<&BlockState> {
        let c = self.cells[self.index(p)?];
        self.palette.get(c as usize)
    }

    /// Sets the block at world position `p`; false when outside.
    pub fn set(&mut self, p: IVec3, state: &BlockState) -> bool {
        let Some(i) = self.index(p) else { return false };
        let c = self.intern(state);
        self.cells[i] = c;
        true
    }

    /// Number of cells that hold a block.
    pub fn set_count(&self) -> usize {
        self.cells.iter().filter(|&&c| c != Self::UNSET).count()
    }

    /// Every set cell as (world position, palette index), y then z then x.
    pub fn iter_set(&self) -> impl Iterator<Item = (IVec3, u32)> + '_ {
        let (sx, sz) = (self.size.x as usize, self.size.z as usize);
        self.cells.iter().enumerate().filter(|(_, c)| **c != Self::UNSET).map(move |(i, &c)| {
            let x = (i % sx) as i32;
            let z = ((i / sx) % sz) as i32;
            let y = (i / (sx * sz)) as i32;
            (self.origin + IVec3::new(x, y, z), c)
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn block_states_parse_sort_and_print() {
        let b = BlockState::parse("oak_stairs[half=bottom,facing=east]").unwrap();
        assert_eq!(b.to_string(), "minecraft:oak_stairs[facing=east,half=bottom]");
        assert_eq!(BlockState::parse("minecraft:stone").unwrap(), BlockState::new("stone"));
        assert!(BlockState::parse("Stone").is_err());
        assert!(BlockState::parse("oak_stairs[facing]").is_err());
        assert!(BlockState::parse("oak_stairs[facing=east").is_err());
    }

    #[test]
    fn kinds() {
        let k = |s: &str| BlockState::new(s).kind();
        assert_eq!(k("air"), BlockKind::Air);
        assert_eq!(k("cave_air"), BlockKind::Air);
        assert_eq!(k("water"), BlockKind::Liquid);
        assert_eq!(k("stone"), BlockKind::Solid);
        assert_eq!(k("grass_block"), BlockKind::Solid);
        assert_eq!(k("oak_leaves"), BlockKind::Solid);
        assert_eq!(k("short_grass"), BlockKind::Passable);
        assert_eq!(k("oak_sapling"), BlockKind::Passable);
        assert_eq!(k("oak_wall_sign"), BlockKind::Passable);
    }

    #[test]
    fn grid_indexing_and_iteration() {
        let mut g = BlockGrid::new(IVec3::new(10, -4, 3), UVec3::new(3, 2, 4));
        assert_eq!(g.volume(), 24);
        assert!(g.set(IVec3::new(12, -3, 6), &BlockState::new("stone")));
        assert!(!g.set(IVec3::new(13, -3, 6), &BlockState::new("stone")));
        assert_eq!(g.index(IVec3::new(12, -3, 6)), Some((4 + 3) * 3 + 2));
        assert_eq!(g.get(IVec3::new(12, -3, 6)).unwrap().id(), "stone");
        assert_eq!(g.get(IVec3::new(10, -4, 3)), None);
        let set: Vec<_> = g.iter_set().collect();
        assert_eq!(set, vec![(IVec3::new(12, -3, 6), 0)]);
        assert_eq!(g.set_count(), 1);
    }
}
