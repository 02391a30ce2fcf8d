//! Can a building be entered? Blocks seen as walls, doors, ladders and
//! stairs over a window of the world, with an air flood (sealed pockets)
//! and a two-block walker (rooms nobody reaches on foot). Shared by
//! `enterable.rs` (derivations in an empty box) and genform-cli's
//! `structures.rs` (the same buildings written into real regions), which
//! includes this file by path: it reads blocks, never the grammar.

use genform_core::{BlockKind, BlockState};
use glam::IVec3;
use std::collections::VecDeque;

/// What a cell is to someone walking about.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub enum Cell {
    /// Air, an unset cell, plants and the like.
    Open,
    /// Either half of a door, or a trapdoor.
    Door,
    Ladder,
    Stairs,
    /// Everything else, glass panes and slabs included.
    Solid,
}

impl Cell {
    /// The cell a block is (`None`: air).
    pub fn of(b: Option<&BlockState>) -> Cell {
        let Some(b) = b else { return Cell::Open };
        match b.id() {
            "ladder" => Cell::Ladder,
            id if id.ends_with("_door") || id.ends_with("_trapdoor") => Cell::Door,
            id if id.ends_with("_stairs") => Cell::Stairs,
            _ if matches!(b.kind(), BlockKind::Air | BlockKind::Passable) => Cell::Open,
            _ => Cell::Solid,
        }
    }
}

/// Cells over the window `min .. min + size` (world coordinates). Below the
/// window is solid ground, above it open air; beside it each column goes on
/// as the window's nearest border column does, so the ground outside is as
/// high as at the border.
pub struct Walls {
    min: IVec3,
    size: IVec3,
    cells: Vec<Cell>,
}

const SIDES: [IVec3; 4] = [IVec3::X, IVec3::NEG_X, IVec3::Z, IVec3::NEG_Z];

impl Walls {
    /// The window's cells from `cell`.
    pub fn new(min: IVec3, size: IVec3, cell: impl Fn(IVec3) -> Cell) -> Walls {
        let mut cells = Vec::with_capacity((size.x * size.y * size.z) as usize);
        for y in 0..size.y {
            for z in 0..size.z {
                for x in 0..size.x {
                    cells.push(cell(min + IVec3::new(x, y, z)));
                }
            }
        }
        Walls { min, size, cells }
    }

    /// Whether `p` lies in the window.
    pub fn inside(&self, p: IVec3) -> bool {
        let q = p - self.min;
        q.cmpge(IVec3::ZERO).all() && q.cmplt(self.size).all()
    }

    fn index(&self, p: IVec3) -> usize {
        let q = p - self.min;
        ((q.y * self.size.z + q.z) * self.size.x + q.x) as usize
    }

    fn point(&self, i: usize) -> IVec3 {
        let (sx, sz) = (self.size.x as usize, self.size.z as usize);
        self.min + IVec3::new((i % sx) as i32, (i / (sx * sz)) as i32, ((i / sx) % sz) as i32)
    }

    /// The cell at `p`, in the window or around it.
    pub fn at(&self, p: IVec3) -> Cell {
        let max = self.min + self.size - IVec3::ONE;
        if p.y < self.min.y {
            Cell::Solid
        } else if p.y > max.y {
            Cell::Open
        } else {
            let q = IVec3::new(p.x.clamp(self.min.x, max.x), p.y, p.z.clamp(self.min.z, max.z));
            self.cells[self.index(q)]
        }
    }

    /// Air flood from the window's faces through air, doors, ladders and
    /// stairs: the sizes of the components it does not reach that hold a
    /// cell `counts` says is the building's, largest first.
    pub fn sealed_pockets(&self, counts: impl Fn(IVec3) -> bool) -> Vec<usize> {
        let through = |c: Cell| c != Cell::Solid;
        let mut seen = vec![false; self.cells.len()];
        let mut queue = VecDeque::new();
        let mut flood = |start: IVec3, seen: &mut Vec<bool>| -> (usize, bool) {
            let (mut n, mut counted) = (0, false);
            seen[self.index(start)] = true;
            queue.push_back(start);
            while let Some(p) = queue.pop_front() {
                n += 1;
                counted |= counts(p);
                for d in [IVec3::X, IVec3::NEG_X, IVec3::Y, IVec3::NEG_Y, IVec3::Z, IVec3::NEG_Z] {
                    let q = p + d;
                    if self.inside(q) && !seen[self.index(q)] && through(self.at(q)) {
                        seen[self.index(q)] = true;
                        queue.push_back(q);
                    }
                }
            }
            (n, counted)
        };
        let s = self.size;
        for i in 0..self.cells.len() {
            let q = self.point(i) - self.min;
            let face = q.x == 0 || q.y == 0 || q.z == 0 || q.x == s.x - 1 || q.y == s.y - 1 || q.z == s.z - 1;
            if face && through(self.cells[i]) && !seen[i] {
                flood(self.point(i), &mut seen);
            }
        }
        let mut pockets = Vec::new();
        for i in 0..self.cells.len() {
            if !seen[i] && through(self.cells[i]) {
                let (n, counted) = flood(self.point(i), &mut seen);
                if counted {
                    pockets.push(n);
                }
            }
        }
        pockets.sort_unstable_by(|a, b| b.cmp(a));
        pockets
    }

    /// A player (two cells high) can be here: feet and head in open cells.
    pub fn passable(&self, p: IVec3) -> bool {
        matches!(self.at(p), Cell::Open | Cell::Door | Cell::Ladder)
    }

    /// Feet at `p` fit.
    pub fn stands(&self, p: IVec3) -> bool {
        self.passable(p) && self.passable(p + IVec3::Y)
    }

    /// Feet at `p` do not fall.
    pub fn supported(&self, p: IVec3) -> bool {
        self.at(p) == Cell::Ladder || !self.passable(p - IVec3::Y)
    }

    fn fall(&self, mut p: IVec3) -> IVec3 {
        while !self.supported(p) {
            p -= IVec3::Y;
        }
        p
    }

    /// Where a player can walk from the ground just outside the window:
    /// walking, falling, stepping or jumping up one block (stairs, a
    /// floor's edge) with room overhead, climbing ladders. Indexed like the
    /// window's cells (feet positions).
    fn walk(&self) -> Vec<bool> {
        let (min, s) = (self.min, self.size);
        let (fx, fz) = (s.x + 2, s.z + 2);
        // Feet positions in a frame one column wider than the window.
        let key = |p: IVec3| {
            let q = p - min;
            (((q.y * fz) + q.z + 1) * fx + q.x + 1) as usize
        };
        let in_frame = |p: IVec3| {
            let q = p - min;
            q.x >= -1 && q.x <= s.x && q.z >= -1 && q.z <= s.z && q.y >= 0 && q.y < s.y
        };
        let mut seen = vec![false; (fx * s.y * fz) as usize];
        let mut queue = VecDeque::new();
        let visit = |p: IVec3, seen: &mut Vec<bool>, queue: &mut VecDeque<IVec3>| {
            if in_frame(p) && !seen[key(p)] {
                seen[key(p)] = true;
                queue.push_back(p);
            }
        };
        let top = min.y + s.y - 1;
        for x in -1..=s.x {
            for z in -1..=s.z {
                if x == -1 || z == -1 || x == s.x || z == s.z {
                    let start = self.fall(min + IVec3::new(x, top - min.y, z));
                    if self.stands(start) {
                        visit(start, &mut seen, &mut queue);
                    }
                }
            }
        }
        while let Some(p) = queue.pop_front() {
            for d in SIDES {
                let q = p + d;
                if self.stands(q) {
                    visit(self.fall(q), &mut seen, &mut queue);
                } else if !self.passable(q) && self.stands(q + IVec3::Y) && self.passable(p + 2 * IVec3::Y) {
                    visit(q + IVec3::Y, &mut seen, &mut queue);
                }
            }
            if self.at(p) == Cell::Ladder && self.passable(p + 2 * IVec3::Y) {
                visit(p + IVec3::Y, &mut seen, &mut queue);
            }
            if self.passable(p - IVec3::Y) {
                visit(self.fall(p - IVec3::Y), &mut seen, &mut queue);
            }
        }
        (0..self.cells.len()).map(|i| seen[key(self.point(i))]).collect()
    }

    /// Places to stand indoors (on a floor, two cells high, under a block
    /// `built` says is the building's) that nobody can walk to from the
    /// ground outside.
    pub fn unreachable_rooms(&self, built: impl Fn(IVec3) -> bool) -> Vec<IVec3> {
        let reach = self.walk();
        let mut out = Vec::new();
        let (min, s) = (self.min, self.size);
        for z in 0..s.z {
            for x in 0..s.x {
                let mut roofed = false;
                for y in (0..s.y).rev() {
                    let p = min + IVec3::new(x, y, z);
                    if !self.passable(p) {
                        roofed |= built(p);
                    } else if roofed
                        && self.stands(p)
                        && !self.passable(p - IVec3::Y)
                        && self.at(p) != Cell::Ladder
                        && !reach[self.index(p)]
                    {
                        out.push(p);
                    }
                }
            }
        }
        out
    }
}
