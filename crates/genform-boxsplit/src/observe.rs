//! Block types and observation of the pre-existing world.
//!
//! A block type is a set of block states: one of the four kinds (SOLID,
//! LIQUID, AIR, PASSABLE), a user `group`, or a single block id. Observers
//! count the cells of a type in a box; [`World`] answers that in O(1) from a
//! 3D summed-area table per type, built once per derivation on first use.

use crate::syntax::Ident;
use genform_core::diag::{Diagnostic, Span};
use genform_core::expr::did_you_mean;
use genform_core::{BlockGrid, BlockKind, BlockState};
use glam::IVec3;
use std::collections::HashMap;

/// A set of block states.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct BlockType {
    pub name: String,
    /// Member kinds, indexed by [`kind_index`].
    pub kinds: [bool; 4],
    /// Member ids (any properties), namespaced.
    pub ids: Vec<String>,
    /// Member states (exact properties).
    pub states: Vec<BlockState>,
}

/// The built-in kind types, in type-id order.
pub(crate) const KIND_NAMES: [&str; 4] = ["AIR", "LIQUID", "SOLID", "PASSABLE"];

pub(crate) fn kind_index(k: BlockKind) -> usize {
    match k {
        BlockKind::Air => 0,
        BlockKind::Liquid => 1,
        BlockKind::Solid => 2,
        BlockKind::Passable => 3,
    }
}

impl BlockType {
    pub(crate) fn empty(name: &str) -> BlockType {
        BlockType { name: name.to_string(), kinds: [false; 4], ids: Vec::new(), states: Vec::new() }
    }

    /// Whether `b` belongs to the type.
    pub(crate) fn matches(&self, b: &BlockState) -> bool {
        self.kinds[kind_index(b.kind())] || self.ids.contains(&b.name) || self.states.contains(b)
    }

    pub(crate) fn absorb(&mut self, other: &BlockType) {
        for (a, b) in self.kinds.iter_mut().zip(other.kinds) {
            *a |= b;
        }
        self.ids.extend(other.ids.iter().cloned());
        self.states.extend(other.states.iter().cloned());
    }
}

/// Every block type of a grammar, by name.
#[derive(Clone, Debug)]
pub(crate) struct TypeTable {
    pub types: Vec<BlockType>,
    by_name: HashMap<String, u32>,
    /// Block ids named by groups and observers (first use of each
    /// spelling), for the compiler's check against Minecraft's lists.
    pub named_ids: Vec<(BlockState, Span)>,
}

impl TypeTable {
    /// The four kinds.
    pub(crate) fn new() -> TypeTable {
        let mut t = TypeTable { types: Vec::new(), by_name: HashMap::new(), named_ids: Vec::new() };
        for (i, n) in KIND_NAMES.iter().enumerate() {
            let mut ty = BlockType::empty(n);
            ty.kinds[i] = true;
            t.add(ty);
        }
        t
    }

    fn add(&mut self, ty: BlockType) -> u32 {
        let id = self.types.len() as u32;
        self.by_name.insert(ty.name.clone(), id);
        self.types.push(ty);
        id
    }

    /// Declares `group name = members`; members are kinds, earlier groups
    /// or block ids.
    pub(crate) fn define_group(&mut self, name: &Ident, members: &[Ident], errors: &mut Vec<Diagnostic>) {
        if let Some(&id) = self.by_name.get(&name.name) {
            let what = if (id as usize) < KIND_NAMES.len() { "a built-in block type" } else { "defined twice" };
            errors.push(Diagnostic::error(name.span, format!("group `{}` is {what}", name.name)));
            return;
        }
        let mut ty = BlockType::empty(&name.name);
        for m in members {
            match self.resolve(m) {
                Ok(id) => {
                    let other = self.types[id as usize].clone();
                    ty.absorb(&other);
                }
                Err(d) => errors.push(d),
            }
        }
        self.add(ty);
    }

    /// The type named by an observer argument or group member: a kind, a
    /// group, or a block id (which becomes a one-block type).
    pub(crate) fn resolve(&mut self, arg: &Ident) -> Result<u32, Diagnostic> {
        if let Some(&id) = self.by_name.get(&arg.name) {
            return Ok(id);
        }
        let lower_start = arg.name.starts_with(|c: char| c.is_ascii_lowercase() || c.is_ascii_digit());
        if !lower_start {
            let mut d = Diagnostic::error(arg.span, format!("unknown block type `{}`", arg.name));
            d = match did_you_mean(&arg.name, self.by_name.keys().map(String::as_str)) {
                Some(s) => d.with_hint(format!("did you mean `{s}`?")),
                None => d.with_hint("block types are SOLID, LIQUID, AIR, PASSABLE, a `group` declared above, or a block id like `water`"),
            };
            return Err(d);
        }
        let state = BlockState::parse(&arg.name).map_err(|m| Diagnostic::error(arg.span, m))?;
        self.named_ids.push((state.clone(), arg.span));
        let key = state.to_string();
        if let Some(&id) = self.by_name.get(&key) {
            self.by_name.insert(arg.name.clone(), id);
            return Ok(id);
        }
        let mut ty = BlockType::empty(&key);
        if state.properties.is_empty() {
            ty.ids.push(state.name);
        } else {
            ty.states.push(state);
        }
        let id = self.add(ty);
        self.by_name.insert(arg.name.clone(), id);
        Ok(id)
    }
}

/// A 3D summed-area table over the derivation box: `table[(y·(sz+1) + z)·(sx+1) + x]`
/// counts matching cells with local coordinates below (x, y, z).
#[derive(Clone, Debug)]
struct Sat {
    table: Vec<u32>,
}

/// The pre-existing world as seen from one derivation box.
pub(crate) struct World<'w> {
    grid: Option<&'w BlockGrid>,
    min: IVec3,
    size: IVec3,
    tables: Vec<Option<Sat>>,
}

impl<'w> World<'w> {
    /// `grid` seen from the box at `min` of `size` cells (cells outside the
    /// grid or unset in it are air).
    pub(crate) fn new(grid: Option<&'w BlockGrid>, min: IVec3, size: IVec3, types: usize) -> World<'w> {
        World { grid, min, size, tables: vec![None; types] }
    }

    /// Cells of type `ty` in the box at world position `min` of `size`,
    /// which lies inside the derivation box.
    pub(crate) fn count(&mut self, types: &[BlockType], ty: u32, min: IVec3, size: IVec3) -> u64 {
        let t = ty as usize;
        if self.grid.is_none() {
            // No world: every cell is air.
            let air = types[t].matches(&BlockState::air());
            return if air { size.x as u64 * size.y as u64 * size.z as u64 } else { 0 };
        }
        if self.tables[t].is_none() {
            self.tables[t] = Some(self.build(&types[t]));
        }
        let Some(sat) = &self.tables[t] else { return 0 };
        let (sx, sz) = (self.size.x as usize + 1, self.size.z as usize + 1);
        let l = min - self.min;
        let h = l + size;
        let at = |x: i32, y: i32, z: i32| sat.table[(y as usize * sz + z as usize) * sx + x as usize];
        // Inclusion–exclusion in wrapping u32: exact because the true count fits.
        let v = at(h.x, h.y, h.z)
            .wrapping_sub(at(l.x, h.y, h.z))
            .wrapping_sub(at(h.x, l.y, h.z))
            .wrapping_sub(at(h.x, h.y, l.z))
            .wrapping_add(at(l.x, l.y, h.z))
            .wrapping_add(at(l.x, h.y, l.z))
            .wrapping_add(at(h.x, l.y, l.z))
            .wrapping_sub(at(l.x, l.y, l.z));
        v as u64
    }

    fn build(&self, ty: &BlockType) -> Sat {
        let (nx, ny, nz) = (self.size.x as usize, self.size.y as usize, self.size.z as usize);
        let (sx, sz) = (nx + 1, nz + 1);
        let mut table = vec![0u32; sx * (ny + 1) * sz];
        let Some(grid) = self.grid else { return Sat { table } };
        let palette: Vec<u32> = grid.palette.iter().map(|b| u32::from(ty.matches(b))).collect();
        let air = u32::from(ty.matches(&BlockState::air()));
        // Cell values first (at +1 offsets), then prefix sums along x, z, y.
        // In i64: the grid and the box may lie far apart.
        let gsize = grid.size.as_i64vec3();
        let base = self.min.as_i64vec3() - grid.origin.as_i64vec3();
        for y in 0..ny {
            for z in 0..nz {
                let row = ((y + 1) * sz + z + 1) * sx + 1;
                let (wy, wz) = (base.y + y as i64, base.z + z as i64);
                let inside_yz = wy >= 0 && wy < gsize.y && wz >= 0 && wz < gsize.z;
                for x in 0..nx {
                    let wx = base.x + x as i64;
                    table[row + x] = if inside_yz && wx >= 0 && wx < gsize.x {
                        let c = grid.cells[((wy * gsize.z + wz) * gsize.x + wx) as usize];
                        palette.get(c as usize).copied().unwrap_or(air)
                    } else {
                        air
                    };
                }
            }
        }
        for row in table.chunks_exact_mut(sx) {
            for x in 1..sx {
                row[x] += row[x - 1];
            }
        }
        for layer in table.chunks_exact_mut(sx * sz) {
            for z in 1..sz {
                let (prev, cur) = layer.split_at_mut(z * sx);
                for (c, p) in cur[..sx].iter_mut().zip(&prev[(z - 1) * sx..]) {
                    *c += *p;
                }
            }
        }
        let layer = sx * sz;
        for y in 1..=ny {
            let (prev, cur) = table.split_at_mut(y * layer);
            for (c, p) in cur[..layer].iter_mut().zip(&prev[(y - 1) * layer..]) {
                *c += *p;
            }
        }
        Sat { table }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use genform_core::diag::Span;
    use glam::UVec3;

    fn ident(s: &str) -> Ident {
        Ident { name: s.to_string(), span: Span::new(0, s.len()) }
    }

    #[test]
    fn groups_union_kinds_ids_and_states() {
        let mut t = TypeTable::new();
        let mut errors = Vec::new();
        t.define_group(
            &ident("GROUND"),
            &[ident("minecraft:grass_block"), ident("dirt"), ident("LIQUID")],
            &mut errors,
        );
        t.define_group(&ident("STAIRS"), &[ident("oak_stairs[facing=east]")], &mut errors);
        assert!(errors.is_empty(), "{errors:?}");
        let gi = t.resolve(&ident("GROUND")).unwrap() as usize;
        let g = &t.types[gi];
        assert!(g.matches(&BlockState::new("grass_block")));
        assert!(g.matches(&BlockState::parse("dirt[snowy=true]").unwrap()));
        assert!(g.matches(&BlockState::new("lava")));
        assert!(!g.matches(&BlockState::new("stone")));
        let si = t.resolve(&ident("STAIRS")).unwrap() as usize;
        let s = &t.types[si];
        assert!(s.matches(&BlockState::parse("oak_stairs[facing=east]").unwrap()));
        assert!(!s.matches(&BlockState::parse("oak_stairs[facing=west]").unwrap()));
        assert!(t.resolve(&ident("ROCK")).is_err());
        t.define_group(&ident("SOLID"), &[ident("stone")], &mut errors);
        assert_eq!(errors.len(), 1);
    }

    /// Counts by brute force and by table agree on every sub-box.
    #[test]
    fn summed_area_counts_match_brute_force() {
        let mut grid = BlockGrid::new(IVec3::new(-2, 5, 1), UVec3::new(5, 4, 3));
        let mut seed = 7u32;
        for i in 0..grid.volume() {
            seed = seed.wrapping_mul(1_103_515_245).wrapping_add(12345);
            grid.cells[i] = match (seed >> 16) % 4 {
                0 => BlockGrid::UNSET,
                1 => grid.intern(&BlockState::new("stone")),
                2 => grid.intern(&BlockState::new("water")),
                _ => grid.intern(&BlockState::new("air")),
            };
        }
        let types = TypeTable::new().types;
        // The derivation box sticks out of the grid on two sides.
        let (min, size) = (IVec3::new(-3, 5, 0), IVec3::new(6, 5, 4));
        let mut w = World::new(Some(&grid), min, size, types.len());
        let kind_of = |p: IVec3| grid.get(p).map_or(BlockKind::Air, |b| b.kind());
        for ty in 0..4u32 {
            for (lo, hi) in
                [(IVec3::ZERO, size), (IVec3::new(1, 1, 1), IVec3::new(4, 3, 2)), (IVec3::new(5, 4, 3), size)]
            {
                let mut brute = 0;
                for x in lo.x..hi.x {
                    for y in lo.y..hi.y {
                        for z in lo.z..hi.z {
                            brute +=
                                u64::from(types[ty as usize].kinds[kind_index(kind_of(min + IVec3::new(x, y, z)))]);
                        }
                    }
                }
                assert_eq!(w.count(&types, ty, min + lo, hi - lo), brute, "type {ty} box {lo}..{hi}");
            }
        }
    }
}
