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
//! - `support rooted T;` — connected bodies of `T` (trees: logs and leaves,
//!   joined through faces, edges and corners) that the derivation cut are
//!   kept only while they still stand: a body whose members no longer rest
//!   on a solid block that is not a member is removed whole when it lies
//!   inside the box, and spared when it reaches beyond it (the box's
//!   promise is that nothing outside changes, so the part outside could not
//!   go): the derivation's changes to the tree and to the ground under it
//!   are given back, and the passage goes around the trunk (`Settle::rooted`
//!   has the details).
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
    // Trees first: removing one can leave snow or a lantern without hold,
    // which the other sides then take away.
    if let Some(ty) = union(Side::Rooted) {
        changed += s.rooted(&ty);
    }
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

    /// `support rooted`: bodies of members (26-connected: acacia branches
    /// join diagonally) in the view — the box and one cell around it, the
    /// same cells whatever the output — are found before and after the
    /// derivation. A body *stands* when one of its members rests on a solid
    /// block that is not a member, or lies in the view's bottom layer (the
    /// view ends there; a trunk going down is taken to stand). A body after
    /// the derivation *floats* when it does not stand but holds a block of a
    /// world body that did: the derivation cut it from its ground. Bodies
    /// made only of placed blocks, and world bodies that did not stand in
    /// the view (a canopy whose trunk is outside), are left alone.
    ///
    /// A floating body that lies inside the box, with nothing outside the
    /// box resting on or hanging from it (snow, vines), is removed. One that
    /// reaches beyond the box cannot be, so every world body it holds is
    /// spared: its cells and the ground under its roots, where the
    /// derivation changed them, are given back (left unset), and the
    /// bodies are found again; each body is spared at most once, so this
    /// ends. Returns the cells changed.
    fn rooted(&mut self, ty: &BlockType) -> u64 {
        let view = View::new(self.out.origin - IVec3::ONE, self.out.size.as_ivec3() + IVec3::splat(2));
        let world: Vec<bool> = (0..view.len).map(|i| ty.matches(self.world(view.pos(i)))).collect();
        let (wbody, wcount) = view.bodies(&world);
        let mut wstands = vec![false; wcount];
        for i in 0..view.len {
            if world[i] && view.stands(i, |q| self.world(q), ty) {
                wstands[wbody[i] as usize] = true;
            }
        }
        let mut spared = vec![false; wcount];
        let mut changed = 0;
        loop {
            let after: Vec<bool> = (0..view.len).map(|i| ty.matches(self.after(view.pos(i)))).collect();
            let (abody, acount) = view.bodies(&after);
            let mut stands = vec![false; acount];
            let mut cut = vec![false; acount];
            let mut removable = vec![true; acount];
            for i in 0..view.len {
                if !after[i] {
                    continue;
                }
                let b = abody[i] as usize;
                let p = view.pos(i);
                stands[b] |= view.stands(i, |q| self.after(q), ty);
                cut[b] |= world[i] && wstands[wbody[i] as usize];
                removable[b] &= self.out.index(p).is_some()
                    && SIX.iter().all(|&d| {
                        let q = p + d;
                        self.out.index(q).is_some() || self.after(q).kind() != BlockKind::Passable
                    });
            }
            let floats = |b: usize| cut[b] && !stands[b];
            // Spare first: a body given back may join a floating one.
            let mut spare = false;
            for i in 0..view.len {
                let b = abody[i] as usize;
                if after[i]
                    && floats(b)
                    && !removable[b]
                    && world[i]
                    && wstands[wbody[i] as usize]
                    && !spared[wbody[i] as usize]
                {
                    spared[wbody[i] as usize] = true;
                    spare = true;
                }
            }
            if spare {
                for i in 0..view.len {
                    // Bodies spared in an earlier round are whole already.
                    if !world[i] || !spared[wbody[i] as usize] {
                        continue;
                    }
                    let p = view.pos(i);
                    let ground = p - IVec3::Y;
                    for q in [p, ground] {
                        if (q == p || !ty.matches(self.world(q))) && self.changed(q) {
                            self.unset(q);
                            changed += 1;
                        }
                    }
                }
                continue;
            }
            for i in 0..view.len {
                // A floating body that reaches out and holds no body that
                // stood cannot be helped: it stays.
                if !(after[i] && floats(abody[i] as usize) && removable[abody[i] as usize]) {
                    continue;
                }
                let p = view.pos(i);
                let w = self.world(p);
                if ty.matches(w) || w.kind() == BlockKind::Solid {
                    let air = self.air.clone();
                    self.out.set(p, &air);
                } else {
                    self.unset(p);
                }
                changed += 1;
            }
            return changed;
        }
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

/// The six face neighbours.
const SIX: [IVec3; 6] = [IVec3::X, IVec3::NEG_X, IVec3::Y, IVec3::NEG_Y, IVec3::Z, IVec3::NEG_Z];

/// A box of cells indexed x fastest, then z, then y.
struct View {
    min: IVec3,
    n: IVec3,
    len: usize,
}

impl View {
    fn new(min: IVec3, n: IVec3) -> View {
        View { min, n, len: (n.x * n.y * n.z) as usize }
    }

    fn pos(&self, i: usize) -> IVec3 {
        let i = i as i32;
        self.min + IVec3::new(i % self.n.x, i / (self.n.x * self.n.z), (i / self.n.x) % self.n.z)
    }

    fn index(&self, p: IVec3) -> Option<usize> {
        let l = p - self.min;
        (l.cmpge(IVec3::ZERO).all() && l.cmplt(self.n).all())
            .then(|| (l.x + self.n.x * (l.z + self.n.z * l.y)) as usize)
    }

    /// Whether the member at `i` rests on a solid non-member (read through
    /// `at`) or lies in the bottom layer.
    fn stands<'b>(&self, i: usize, at: impl Fn(IVec3) -> &'b BlockState, ty: &BlockType) -> bool {
        let p = self.pos(i);
        if p.y == self.min.y {
            return true;
        }
        let q = at(p - IVec3::Y);
        q.kind() == BlockKind::Solid && !ty.matches(q)
    }

    /// The 26-connected bodies of `member` cells, numbered in index order
    /// (`u32::MAX` off the members), and how many there are.
    fn bodies(&self, member: &[bool]) -> (Vec<u32>, usize) {
        let mut body = vec![u32::MAX; self.len];
        let mut count = 0u32;
        let mut stack = Vec::new();
        for start in 0..self.len {
            if !member[start] || body[start] != u32::MAX {
                continue;
            }
            body[start] = count;
            stack.push(start);
            while let Some(i) = stack.pop() {
                let p = self.pos(i);
                for dy in -1..=1 {
                    for dz in -1..=1 {
                        for dx in -1..=1 {
                            if let Some(j) = self.index(p + IVec3::new(dx, dy, dz))
                                && member[j]
                                && body[j] == u32::MAX
                            {
                                body[j] = count;
                                stack.push(j);
                            }
                        }
                    }
                }
            }
            count += 1;
        }
        (body, count as usize)
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

    /// `ground()` (stone below y 2) with an oak: a trunk at x = z = 3 from
    /// y 2 to 6, leaves around it at y 5 and 6, snow on the top leaf; the
    /// world covers -1..9 on every axis.
    fn oak() -> BlockGrid {
        let mut w = BlockGrid::new(IVec3::splat(-1), UVec3::splat(10));
        for i in 0..w.volume() {
            let p = IVec3::new((i % 10) as i32, (i / 100) as i32, ((i / 10) % 10) as i32) - 1;
            let b = match p {
                p if p.y < 2 => "stone",
                p if p.x == 3 && p.z == 3 && p.y <= 6 => "oak_log",
                p if (2..=4).contains(&p.x) && (2..=4).contains(&p.z) && (5..=6).contains(&p.y) => "oak_leaves",
                p if p.x == 3 && p.z == 3 && p.y == 7 => "snow",
                _ => "air",
            };
            w.set(p, &BlockState::new(b));
        }
        w
    }

    const TREE: &str = "group TREE = oak_log, oak_leaves;\nsupport rooted TREE;\nsupport below snow;\n";

    /// Digs the row z = 3 in the layers `y0..y0 + h` of the box.
    fn dig(y0: u32, h: u32) -> String {
        format!("{TREE}A {{ split y [{y0}, {h}, -1] {{ skip, split z [3, 1, -1] {{ skip, void, skip }}, skip }} }}\n")
    }

    #[test]
    fn a_tree_cut_from_its_ground_goes_whole() {
        let out = derive(&dig(2, 2), &oak(), IVec3::ZERO, IVec3::new(7, 9, 7));
        for p in
            [IVec3::new(3, 4, 3), IVec3::new(3, 6, 3), IVec3::new(2, 5, 2), IVec3::new(4, 6, 4), IVec3::new(3, 7, 3)]
        {
            assert_eq!(out.get(p).map(|b| b.id()), Some("air"), "{p} is taken away with the tree");
        }
        assert_eq!(out.get(IVec3::new(3, 2, 3)).unwrap().id(), "air", "the dug trunk stays dug");
        // Cut higher up: the stump stands and stays as it was.
        let out = derive(&dig(4, 1), &oak(), IVec3::ZERO, IVec3::new(7, 9, 7));
        assert_eq!(out.get(IVec3::new(3, 3, 3)), None, "the stump stays");
        assert_eq!(out.get(IVec3::new(2, 5, 2)).unwrap().id(), "air", "the crown goes");
        // Not cut at all: the leaves trimmed off one row leave a tree that stands.
        let out = derive(
            &format!("{TREE}A {{ split x [4, -1] {{ skip, void }} }}\n"),
            &oak(),
            IVec3::new(0, 2, 0),
            IVec3::new(7, 9, 7),
        );
        assert_eq!(out.get(IVec3::new(2, 5, 2)), None, "the crown of a standing tree stays");
        assert_eq!(out.get(IVec3::new(4, 5, 2)).unwrap().id(), "air", "the trimmed leaves stay dug");
    }

    #[test]
    fn a_tree_reaching_out_of_the_box_is_spared() {
        // The box ends at y 5: the crown is partly outside and cannot go, so
        // the trunk is given back and the passage goes around it.
        let out = derive(&dig(2, 2), &oak(), IVec3::ZERO, IVec3::new(7, 6, 7));
        assert_eq!(out.get(IVec3::new(3, 2, 3)), None, "the trunk is given back");
        assert_eq!(out.get(IVec3::new(3, 3, 3)), None);
        assert_eq!(out.get(IVec3::new(2, 2, 3)).unwrap().id(), "air", "the rest of the passage is dug");
        assert_eq!(out.get(IVec3::new(2, 5, 2)), None, "the crown stays");
    }
}
