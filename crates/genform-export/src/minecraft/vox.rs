//! MagicaVoxel `.vox` (version 150).
//!
//! `VOX ` header, then a `MAIN` chunk whose children are, per model, a
//! `SIZE` and an `XYZI` chunk (at most 256 voxels per axis), then — when
//! there are several models — a scene graph placing them (`nTRN` / `nGRP`
//! / `nSHP`), and last the `RGBA` palette. MagicaVoxel is z-up: our
//! (x, y, z) with y up is written as (x, size_z − 1 − z, y), a rotation
//! (no mirror).

use super::colors::block_color;
use super::error::MinecraftError;
use super::grid::check_grid;
use genform_core::blocks::{BlockGrid, BlockKind};

/// Colours a `.vox` palette holds (index 0 is reserved for "empty").
pub const MAX_VOX_COLORS: usize = 255;

/// Largest model side MagicaVoxel accepts.
const MODEL_SIDE: u32 = 256;

/// Largest grid side written (pieces of 256 placed by the scene graph).
const MAX_SIDE: u32 = 2048;

/// Writes the set, non-air cells of `grid` as a MagicaVoxel file.
///
/// Each block gets its [`super::block_color`]; blocks of the same colour
/// share a palette slot. With more than 255 colours the extra ones take
/// the nearest of the first 255. A grid up to 256 per axis is one model;
/// a larger one (up to 2048 per axis) is cut into 256³ pieces, one model
/// each, placed by a scene graph (translation = piece centre, the pivot
/// MagicaVoxel uses being ⌊size / 2⌋ per axis). Empty pieces are left out.
///
/// Errors: [`MinecraftError::Empty`] when no block is drawn,
/// [`MinecraftError::TooLarge`] above 2048 per axis.
pub fn write_vox(grid: &BlockGrid) -> Result<Vec<u8>, MinecraftError> {
    check_grid(grid)?;
    let s = grid.size;
    if s.max_element() > MAX_SIDE {
        return Err(MinecraftError::TooLarge { format: "vox", size: s, limit: "at most 2048 blocks per side" });
    }
    // Palette slot per grid palette entry (0 = not drawn).
    let mut colors: Vec<[u8; 3]> = Vec::new();
    let slot: Vec<u8> = grid
        .palette
        .iter()
        .map(|b| {
            if b.kind() == BlockKind::Air {
                return 0;
            }
            let c = block_color(b);
            if let Some(i) = colors.iter().position(|&k| k == c) {
                return (i + 1) as u8;
            }
            if colors.len() < MAX_VOX_COLORS {
                colors.push(c);
                return colors.len() as u8;
            }
            let dist = |k: &[u8; 3]| k.iter().zip(c).map(|(&a, b)| (i32::from(a) - i32::from(b)).pow(2)).sum::<i32>();
            let nearest = colors.iter().enumerate().min_by_key(|(_, k)| dist(k)).map_or(0, |(i, _)| i);
            (nearest + 1) as u8
        })
        .collect();

    let dims = [s.x, s.z, s.y];
    let mut models: Vec<Model> = Vec::new();
    let pieces = dims.map(|d| d.div_ceil(MODEL_SIDE).max(1));
    for pz in 0..pieces[2] {
        for py in 0..pieces[1] {
            for px in 0..pieces[0] {
                let lo = [px, py, pz].map(|p| p * MODEL_SIDE);
                let size: [u32; 3] = std::array::from_fn(|i| (dims[i] - lo[i]).min(MODEL_SIDE));
                let mut voxels = Vec::new();
                for vz in lo[2]..lo[2] + size[2] {
                    for vy in lo[1]..lo[1] + size[1] {
                        let (y, z) = (vz as usize, (s.z - 1 - vy) as usize);
                        let row = (y * s.z as usize + z) * s.x as usize;
                        for vx in lo[0]..lo[0] + size[0] {
                            let c = grid.cells[row + vx as usize];
                            let k = slot.get(c as usize).copied().unwrap_or(0);
                            if k != 0 {
                                voxels.push([(vx - lo[0]) as u8, (vy - lo[1]) as u8, (vz - lo[2]) as u8, k]);
                            }
                        }
                    }
                }
                if !voxels.is_empty() {
                    models.push((lo, size, voxels));
                }
            }
        }
    }
    if models.is_empty() {
        return Err(MinecraftError::Empty);
    }

    let mut children = Vec::new();
    for (_, size, voxels) in &models {
        chunk(&mut children, b"SIZE", &size.iter().flat_map(|v| v.to_le_bytes()).collect::<Vec<_>>());
        let mut xyzi = Vec::with_capacity(4 + 4 * voxels.len());
        xyzi.extend_from_slice(&(voxels.len() as u32).to_le_bytes());
        voxels.iter().for_each(|v| xyzi.extend_from_slice(v));
        chunk(&mut children, b"XYZI", &xyzi);
    }
    if models.len() > 1 {
        scene_graph(&mut children, &models.iter().map(|(lo, size, _)| (*lo, *size)).collect::<Vec<_>>());
    }
    let mut rgba = Vec::with_capacity(1024);
    for i in 0..256 {
        let c = colors.get(i).copied().unwrap_or([0, 0, 0]);
        rgba.extend_from_slice(&[c[0], c[1], c[2], 255]);
    }
    chunk(&mut children, b"RGBA", &rgba);

    let mut out = Vec::with_capacity(20 + children.len());
    out.extend_from_slice(b"VOX ");
    out.extend_from_slice(&150u32.to_le_bytes());
    out.extend_from_slice(b"MAIN");
    out.extend_from_slice(&0u32.to_le_bytes());
    out.extend_from_slice(&(children.len() as u32).to_le_bytes());
    out.extend_from_slice(&children);
    Ok(out)
}

/// One model: its piece's origin in vox coordinates, its size, its voxels
/// (x, y, z, palette slot).
type Model = ([u32; 3], [u32; 3], Vec<[u8; 4]>);

/// Appends a leaf chunk: id, content size, no children, content.
fn chunk(out: &mut Vec<u8>, id: &[u8; 4], content: &[u8]) {
    out.extend_from_slice(id);
    out.extend_from_slice(&(content.len() as u32).to_le_bytes());
    out.extend_from_slice(&0u32.to_le_bytes());
    out.extend_from_slice(content);
}

/// A vox STRING / DICT writer.
struct Content(Vec<u8>);

impl Content {
    fn int(&mut self, v: i32) -> &mut Self {
        self.0.extend_from_slice(&v.to_le_bytes());
        self
    }
    fn dict(&mut self, items: &[(&str, &str)]) -> &mut Self {
        self.int(items.len() as i32);
        for (k, v) in items {
            for s in [k, v] {
                self.int(s.len() as i32);
                self.0.extend_from_slice(s.as_bytes());
            }
        }
        self
    }
}

/// Root transform 0 → group 1 → per model: transform 2 + 2k (at the
/// piece's centre) → shape 3 + 2k → model k.
fn scene_graph(out: &mut Vec<u8>, models: &[([u32; 3], [u32; 3])]) {
    let mut c = Content(Vec::new());
    c.int(0).dict(&[]).int(1).int(-1).int(-1).int(1).dict(&[]);
    chunk(out, b"nTRN", &c.0);
    let mut c = Content(Vec::new());
    c.int(1).dict(&[]).int(models.len() as i32);
    for k in 0..models.len() {
        c.int(2 + 2 * k as i32);
    }
    chunk(out, b"nGRP", &c.0);
    for (k, (lo, size)) in models.iter().enumerate() {
        let t: [u32; 3] = std::array::from_fn(|i| lo[i] + size[i] / 2);
        let t = format!("{} {} {}", t[0], t[1], t[2]);
        let mut c = Content(Vec::new());
        c.int(2 + 2 * k as i32).dict(&[]).int(3 + 2 * k as i32).int(-1).int(0).int(1).dict(&[("_t", &t)]);
        chunk(out, b"nTRN", &c.0);
        let mut c = Content(Vec::new());
        c.int(3 + 2 * k as i32).dict(&[]).int(1).int(k as i32).dict(&[]);
        chunk(out, b"nSHP", &c.0);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use genform_core::blocks::BlockState;
    use glam::{IVec3, UVec3};

    /// (id, content, children) of each chunk in `b`.
    fn chunks(b: &[u8]) -> Vec<([u8; 4], &[u8], &[u8])> {
        let mut out = Vec::new();
        let mut i = 0;
        while i < b.len() {
            let id: [u8; 4] = b[i..i + 4].try_into().unwrap();
            let n = u32::from_le_bytes(b[i + 4..i + 8].try_into().unwrap()) as usize;
            let m = u32::from_le_bytes(b[i + 8..i + 12].try_into().unwrap()) as usize;
            out.push((id, &b[i + 12..i + 12 + n], &b[i + 12 + n..i + 12 + n + m]));
            i += 12 + n + m;
        }
        out
    }

    fn u32_at(b: &[u8], i: usize) -> u32 {
        u32::from_le_bytes(b[4 * i..4 * i + 4].try_into().unwrap())
    }

    #[test]
    fn one_model_structure_and_axes() {
        let mut g = BlockGrid::new(IVec3::new(10, 20, 30), UVec3::new(3, 4, 2));
        g.set(IVec3::new(10, 20, 30), &BlockState::new("stone"));
        g.set(IVec3::new(12, 23, 30), &BlockState::new("dirt"));
        g.set(IVec3::new(11, 20, 31), &BlockState::new("air"));
        g.set(IVec3::new(11, 21, 31), &BlockState::parse("oak_log[axis=x]").unwrap());
        let b = write_vox(&g).unwrap();
        assert_eq!(&b[..8], b"VOX \x96\x00\x00\x00");
        let main = chunks(&b[8..]);
        assert_eq!(main.len(), 1);
        assert_eq!(&main[0].0, b"MAIN");
        assert!(main[0].1.is_empty());
        let kids = chunks(main[0].2);
        let ids: Vec<_> = kids.iter().map(|k| k.0).collect();
        assert_eq!(ids, [*b"SIZE", *b"XYZI", *b"RGBA"]);
        // z-up: size (x, z, y).
        assert_eq!([0, 1, 2].map(|i| u32_at(kids[0].1, i)), [3, 2, 4]);
        let xyzi = kids[1].1;
        assert_eq!(u32_at(xyzi, 0), 3, "air is not drawn");
        let vox: Vec<[u8; 4]> = xyzi[4..].chunks(4).map(|c| c.try_into().unwrap()).collect();
        // stone at local (0,0,0) → (0, 1, 0); dirt (2,3,0) → (2, 1, 3);
        // log (1,1,1) → (1, 0, 1).
        let at = |p: [u8; 3]| vox.iter().find(|v| v[..3] == p).map(|v| v[3]);
        let (stone, dirt, log) = (at([0, 1, 0]).unwrap(), at([2, 1, 3]).unwrap(), at([1, 0, 1]).unwrap());
        assert!(stone != dirt && dirt != log && stone != log);
        let rgba = kids[2].1;
        assert_eq!(rgba.len(), 1024);
        let color = |slot: u8| &rgba[4 * (slot as usize - 1)..4 * (slot as usize - 1) + 3];
        assert_eq!(color(stone), block_color(&BlockState::new("stone")));
        assert_eq!(color(dirt), block_color(&BlockState::new("dirt")));
    }

    #[test]
    fn large_grids_become_placed_models() {
        let mut g = BlockGrid::new(IVec3::ZERO, UVec3::new(300, 2, 1));
        g.set(IVec3::new(0, 0, 0), &BlockState::new("stone"));
        g.set(IVec3::new(299, 1, 0), &BlockState::new("stone"));
        let b = write_vox(&g).unwrap();
        let kids = chunks(chunks(&b[8..])[0].2);
        let ids: Vec<String> = kids.iter().map(|k| String::from_utf8_lossy(&k.0).into_owned()).collect();
        assert_eq!(ids, ["SIZE", "XYZI", "SIZE", "XYZI", "nTRN", "nGRP", "nTRN", "nSHP", "nTRN", "nSHP", "RGBA"]);
        assert_eq!([0, 1, 2].map(|i| u32_at(kids[2].1, i)), [44, 1, 2]);
        // The second piece's transform names its centre: 256 + 22, 0, 1.
        let t = String::from_utf8_lossy(kids[8].1);
        assert!(t.contains("_t") && t.contains("278 0 1"), "{t}");
        assert!(matches!(write_vox(&BlockGrid::new(IVec3::ZERO, UVec3::new(3, 3, 3))), Err(MinecraftError::Empty)));
        let huge = BlockGrid::new(IVec3::ZERO, UVec3::new(4000, 1, 1));
        assert!(matches!(write_vox(&huge), Err(MinecraftError::TooLarge { .. })));
    }
}
