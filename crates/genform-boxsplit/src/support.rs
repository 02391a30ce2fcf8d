//! `support` declarations: after a derivation has succeeded, blocks that
//! need something to hang from, stand on or lean against are kept only where
//! they have it, in the world as it will be (the pre-existing terrain with
//! the derived blocks written over it).
//!
//! - `support beside T;` — a block of `T` placed where the world held no
//!   solid block is kept only when one of its four horizontal neighbours is
//!   solid and not itself of `T` (terrain that stays, or another placed
//!   block such as a roof): no free-standing lining. Removed ones are
//!   `skip`ped: the world keeps what it had there.
//! - `support above T;` — a block of `T` is kept only under a solid block
//!   or another block of `T` (a lantern under a chain). Checked top down.
//! - `support below T;` — a block of `T` is kept only on a solid block or
//!   another block of `T`. Checked bottom up.
//!
//! `above` and `below` look at placed blocks, and at pre-existing blocks of
//! `T` whose neighbour the derivation changed (snow left on a dug cell). A
//! removed block becomes air where the world was solid (the grammar dug
//! there) and the world's own block otherwise — or air, when that block
//! would float in its turn. Cells outside the box and outside the world
//! grid read as air, so a caller passes a world that reaches one cell
//! beyond the box. Nothing here draws a random number: the result depends
//! only on the derived blocks and the world.

use crate::grammar::{Side, Support};
use crate::observe::BlockType;
use genform_core::{BlockGrid, BlockKind, BlockState};
use glam::IVec3;

/// Applies `supports` to the derived blocks `out` (the derivation box) over
/// `world`; returns how many cells were changed.
pub(crate) fn settle(supports: &[Support], world: Option<&BlockGrid>, out: &mut BlockGrid) -> u64 {
    let union = |side: Side| {
        let mut ty = BlockType::empty("");
        let mut any = false;
        for s in supports.iter().filter(|s| s.side == side) {
            ty.absorb(&s.ty);
            any = true;
        }
        any.then_some(ty)
    };
    let mut s = Settle::new(world, out);
    let mut changed = 0;
    if let Some(ty) = union(Side::Beside) {
        changed += s.beside(&ty);
    }
    if let Some(ty) = union(Side::Above) {
        changed += s.vertical(&ty, 1);
    }
    if let Some(ty) = union(Side::Below) {
        changed += s.vertical(&ty, -1);
    }
    changed
}

struct Settle<'a> {
    world: Option<&'a BlockGrid>,
    out: &'a mut BlockGrid,
    air: BlockState,
}

impl<'a> Settle<'a> {
    fn new(world: Option<&'a BlockGrid>, out: &'a mut BlockGrid) -> Settle<'a> {
        Settle { world, out, air: BlockState::air() }
    }

    /// The pre-existing block at `p` (air where unknown).
    fn world(&self, p: IVec3) -> &BlockState {
        self.world.and_then(|w| w.get(p)).unwrap_or(&self.air)
    }

    /// The block the derivation placed at `p`, if any.
    fn placed(&self, p: IVec3) -> Option<&BlockState> {
        self.out.get(p)
    }

    /// The block at `p` once the derived blocks are written.
    fn after(&self, p: IVec3) -> &BlockState {
        match self.placed(p) {
            Some(b) => b,
            None => self.world(p),
        }
    }

    fn changed(&self, p: IVec3) -> bool {
        self.placed(p).is_some_and(|b| b != self.world(p))
    }

    fn unset(&mut self, p: IVec3) {
        if let Some(i) = self.out.index(p) {
            self.out.cells[i] = BlockGrid::UNSET;
        }
    }

    /// Cells of the box, layer by layer: top down when `down`.
    fn cells(&self, down: bool) -> Vec<IVec3> {
        let (o, n) = (self.out.origin, self.out.size.as_ivec3());
        let mut v = Vec::with_capacity(self.out.volume());
        for k in 0..n.y {
            let y = if down { n.y - 1 - k } else { k };
            for z in 0..n.z {
                for x in 0..n.x {
                    v.push(o + IVec3::new(x, y, z));
                }
            }
        }
        v
    }

    fn beside(&mut self, ty: &BlockType) -> u64 {
        const SIDES: [IVec3; 4] = [IVec3::X, IVec3::NEG_X, IVec3::Z, IVec3::NEG_Z];
        let mut free = Vec::new();
        for p in self.cells(false) {
            let Some(b) = self.placed(p) else { continue };
            if !ty.matches(b) || self.world(p).kind() == BlockKind::Solid {
                continue;
            }
            let leans = SIDES.iter().any(|&d| {
                let q = self.after(p + d);
                q.kind() == BlockKind::Solid && !ty.matches(q)
            });
            if !leans {
                free.push(p);
            }
        }
        // Removing a member never takes an anchor away: members are none.
        for &p in &free {
            self.unset(p);
        }
        free.len() as u64
    }

    /// `up = 1`: members need support above (checked top down); `up = -1`:
    /// below (bottom up).
    fn vertical(&mut self, ty: &BlockType, up: i32) -> u64 {
        let d = IVec3::new(0, up, 0);
        let mut changed = 0;
        for p in self.cells(up > 0) {
            let b = self.after(p);
            if !ty.matches(b) || !(self.placed(p).is_some() || self.changed(p + d)) {
                continue;
            }
            let held = |s: &Settle, p: IVec3| {
                let q = s.after(p + d);
                q.kind() == BlockKind::Solid || ty.matches(q)
            };
            if held(self, p) {
                continue;
            }
            changed += 1;
            let w = self.world(p);
            if w.kind() != BlockKind::Solid && !ty.matches(w) {
                // The world's own block stays (water, air, a plant the
                // grammar had covered).
                self.unset(p);
            } else {
                let air = self.air.clone();
                self.out.set(p, &air);
            }
        }
        changed
    }
}

#[cfg(test)]
mod tests {
    use crate::DeriveOptions;
    use genform_core::{BlockGrid, BlockState, Rng, SourceFile};
    use glam::{IVec3, UVec3};

    fn derive(src: &str, world: &BlockGrid, min: IVec3, max: IVec3) -> BlockGrid {
        let (g, _) = crate::compile(&SourceFile::new("t.bsg", src)).unwrap();
        g.derive(Some(world), min, max, &mut Rng::from_seed(1), &DeriveOptions::default()).unwrap().blocks
    }

    /// A world of stone below y = 2, air above, one cell beyond a 3×4×3 box.
    fn ground() -> BlockGrid {
        let mut w = BlockGrid::new(IVec3::splat(-1), UVec3::new(5, 6, 5));
        for p in (0..w.volume()).map(|i| IVec3::new((i % 5) as i32, (i / 25) as i32, ((i / 5) % 5) as i32) - 1) {
            let b = if p.y < 2 { "stone" } else { "air" };
            w.set(p, &BlockState::new(b));
        }
        w
    }

    #[test]
    fn hanging_blocks_stay_only_under_solid_ones() {
        // A lantern in the dug layer under stone stays; one in open air goes.
        let src = "support above lantern[hanging=true];\n\
                   A { split y [-1, 1, 1] { skip, void, fill lantern[hanging=true] } }\n";
        let out = derive(src, &ground(), IVec3::ZERO, IVec3::new(3, 4, 3));
        // y 3: a lantern under air (and the box top): taken away, the world's air stays.
        assert_eq!(out.get(IVec3::new(1, 3, 1)), None);
        let src = "support above lantern[hanging=true];\n\
                   A { split y [1, 1, -1] { void, fill lantern[hanging=true], skip } }\n";
        let out = derive(src, &ground(), IVec3::ZERO, IVec3::new(3, 4, 3));
        // y 1 hangs under y 2 (air): taken away; the world was stone there, so it is dug (air).
        assert_eq!(out.get(IVec3::new(1, 1, 1)).unwrap().id(), "air");
        let src = "support above lantern[hanging=true];\n\
                   A { split y [1, 1, -1] { fill lantern[hanging=true], skip, skip } }\n";
        let out = derive(src, &ground(), IVec3::ZERO, IVec3::new(3, 4, 3));
        // y 0 under the stone of y 1: stays.
        assert_eq!(out.get(IVec3::new(1, 0, 1)).unwrap().id(), "lantern");
    }

    #[test]
    fn standing_blocks_and_loose_terrain_need_ground() {
        let mut w = ground();
        for x in -1..4 {
            for z in -1..4 {
                w.set(IVec3::new(x, 2, z), &BlockState::new("snow"));
            }
        }
        // Dig the stone of y 1 under the middle column; the snow on it goes.
        let src = "support below snow, torch;\n\
                   A { split y [1, 1, -1] { skip, split x [1, 1, 1] { skip, void, skip }, split x [1, 1, 1] { skip, split y [1, -1] { skip, fill torch }, skip } } }\n";
        let out = derive(src, &w, IVec3::ZERO, IVec3::new(3, 4, 3));
        assert_eq!(out.get(IVec3::new(1, 2, 1)).unwrap().id(), "air", "floating snow taken away");
        assert_eq!(out.get(IVec3::new(0, 2, 1)), None, "snow on stone stays as it was");
        assert_eq!(out.get(IVec3::new(1, 3, 1)), None, "the torch on that snow goes with it");
    }

    #[test]
    fn lining_leans_on_terrain_or_other_blocks() {
        // Bricks over the whole box: those in the stone stay, those above it
        // with only bricks around go; in the air layer one leans on a placed log.
        let src = "material lining = 1 stone_bricks;\nsupport beside lining;\n\
                   A { split x [1, -1] { fill oak_log, fill lining } }\n";
        let out = derive(src, &ground(), IVec3::ZERO, IVec3::new(3, 4, 3));
        assert_eq!(out.get(IVec3::new(2, 0, 1)).unwrap().id(), "stone_bricks", "replaces the hill");
        assert_eq!(out.get(IVec3::new(1, 3, 1)).unwrap().id(), "stone_bricks", "leans on the log");
        assert_eq!(out.get(IVec3::new(2, 3, 1)), None, "stands free");
    }
}
