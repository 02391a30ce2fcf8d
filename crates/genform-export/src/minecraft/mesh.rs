//! Greedy meshing of block grids: per block state, the visible faces, with
//! coplanar neighbouring faces of the same state merged into rectangles.

use genform_core::blocks::{BlockGrid, BlockKind, BlockState};
use genform_core::scene::{Mesh, Scene};
use glam::Vec3;

/// The surface of all blocks of one state.
#[derive(Clone, Debug, PartialEq)]
pub struct BlockMesh {
    /// The block state.
    pub state: BlockState,
    /// World-space quads (4 vertices, 2 counter-clockwise triangles each);
    /// named after the state.
    pub mesh: Mesh,
    /// The face normal of each vertex.
    pub normals: Vec<Vec3>,
}

/// Meshes the grid: one [`BlockMesh`] per palette entry with a visible face,
/// in palette order.
///
/// A block face is drawn unless the neighbouring cell holds a solid block
/// ([`BlockKind::Solid`]) or the same state (no faces between water and
/// water). Air is never drawn; unset cells and cells outside the grid hide
/// nothing. Coplanar faces of one state that touch are merged greedily into
/// rectangles (a 2×1×1 bar is 6 quads).
pub fn mesh_blocks(grid: &BlockGrid) -> Vec<BlockMesh> {
    let n = grid.palette.len();
    // Per palette entry, and last for unset (or out-of-range) cells:
    // bit 0 = drawn, bit 1 = hides its neighbours' faces.
    let mut flags: Vec<u8> = grid
        .palette
        .iter()
        .map(|s| u8::from(s.kind() != BlockKind::Air) | (u8::from(s.kind() == BlockKind::Solid) << 1))
        .collect();
    flags.push(0);
    let flag = |c: u32| flags[(c as usize).min(n)];
    // Whether cell value `a`'s face toward cell value `b` shows (a drawn
    // `a` is in range, so `a == b` means the same state).
    let visible = |a: u32, b: u32| flag(a) & 1 != 0 && flag(b) & 2 == 0 && a != b;
    let dims = [grid.size.x as usize, grid.size.y as usize, grid.size.z as usize];
    let stride = [1, dims[0] * dims[2], dims[0]];
    let mut quads: Vec<Vec<Quad>> = vec![Vec::new(); n];
    if grid.cells.len() != dims.iter().product::<usize>() {
        return Vec::new();
    }
    for d in 0..3 {
        // Walk the plane with the smaller-stride axis innermost (cache
        // friendly); when that reverses the cyclic order d → u → v, the
        // corner order flips to stay counter-clockwise.
        let (mut u, mut v) = ((d + 1) % 3, (d + 2) % 3);
        let swapped = stride[u] > stride[v];
        if swapped {
            std::mem::swap(&mut u, &mut v);
        }
        let (nu, nv) = (dims[u], dims[v]);
        let mut pos = vec![0u32; nu * nv];
        let mut neg = vec![0u32; nu * nv];
        for k in 0..=dims[d] {
            for j in 0..nv {
                for i in 0..nu {
                    let base = i * stride[u] + j * stride[v];
                    let a = if k > 0 { grid.cells[base + (k - 1) * stride[d]] } else { BlockGrid::UNSET };
                    let b = if k < dims[d] { grid.cells[base + k * stride[d]] } else { BlockGrid::UNSET };
                    pos[j * nu + i] = if visible(a, b) { a + 1 } else { 0 };
                    neg[j * nu + i] = if visible(b, a) { b + 1 } else { 0 };
                }
            }
            for (mask, positive) in [(&mut pos, true), (&mut neg, false)] {
                merge(mask, nu, nv, |label, i0, i1, j0, j1| {
                    let axes = [d as u8, u as u8, v as u8];
                    let ccw = positive != swapped;
                    quads[label as usize - 1].push(Quad { axes, positive, ccw, k: k as u32, i0, i1, j0, j1 });
                });
            }
        }
    }
    let origin = grid.origin.as_vec3();
    quads
        .into_iter()
        .enumerate()
        .filter(|(_, q)| !q.is_empty())
        .map(|(i, q)| {
            let state = grid.palette[i].clone();
            let mut mesh = Mesh { name: state.to_string(), ..Mesh::default() };
            let mut normals = Vec::with_capacity(4 * q.len());
            for quad in q {
                quad.emit(origin, &mut mesh, &mut normals);
            }
            BlockMesh { state, mesh, normals }
        })
        .collect()
}

/// One merged rectangle on the plane `axis d = k`, spanning `[i0, i1)` along
/// axis u and `[j0, j1)` along axis v (`axes` = [d, u, v]), facing +d or
/// −d; `ccw` when the corner order (i0,j0) (i1,j0) (i1,j1) (i0,j1) is
/// counter-clockwise seen from the side it faces.
#[derive(Clone, Copy)]
struct Quad {
    axes: [u8; 3],
    positive: bool,
    ccw: bool,
    k: u32,
    i0: u32,
    i1: u32,
    j0: u32,
    j1: u32,
}

impl Quad {
    fn emit(&self, origin: Vec3, mesh: &mut Mesh, normals: &mut Vec<Vec3>) {
        let [d, u, v] = self.axes.map(usize::from);
        let at = |i: u32, j: u32| {
            let mut p = [0.0f32; 3];
            p[d] = self.k as f32;
            p[u] = i as f32;
            p[v] = j as f32;
            origin + Vec3::from_array(p)
        };
        let (i0, i1, j0, j1) = (self.i0, self.i1, self.j0, self.j1);
        let corners = if self.ccw {
            [at(i0, j0), at(i1, j0), at(i1, j1), at(i0, j1)]
        } else {
            [at(i0, j0), at(i0, j1), at(i1, j1), at(i1, j0)]
        };
        let mut n = [0.0f32; 3];
        n[d] = if self.positive { 1.0 } else { -1.0 };
        let b = mesh.positions.len() as u32;
        mesh.positions.extend_from_slice(&corners);
        normals.extend_from_slice(&[Vec3::from_array(n); 4]);
        mesh.triangles.push([b, b + 1, b + 2]);
        mesh.triangles.push([b, b + 2, b + 3]);
    }
}

/// Greedy rectangles of equal non-zero labels in an `nu × nv` mask (row j
/// at `j * nu`); calls `emit(label, i0, i1, j0, j1)` and clears the mask.
fn merge(mask: &mut [u32], nu: usize, nv: usize, mut emit: impl FnMut(u32, u32, u32, u32, u32)) {
    for j in 0..nv {
        let mut i = 0;
        while i < nu {
            let l = mask[j * nu + i];
            if l == 0 {
                i += 1;
                continue;
            }
            let mut w = 1;
            while i + w < nu && mask[j * nu + i + w] == l {
                w += 1;
            }
            let mut h = 1;
            while j + h < nv && mask[(j + h) * nu + i..(j + h) * nu + i + w].iter().all(|&m| m == l) {
                h += 1;
            }
            for r in j..j + h {
                mask[r * nu + i..r * nu + i + w].fill(0);
            }
            emit(l, i as u32, (i + w) as u32, j as u32, (j + h) as u32);
            i += w;
        }
    }
}

/// Adds `m` to `out`: joined to the mesh of its state, or as a new one.
fn join_mesh(out: &mut Vec<BlockMesh>, m: BlockMesh) {
    match out.iter_mut().find(|o| o.state == m.state) {
        Some(o) => {
            let b = o.mesh.positions.len() as u32;
            o.mesh.positions.extend_from_slice(&m.mesh.positions);
            o.mesh.triangles.extend(m.mesh.triangles.iter().map(|t| t.map(|v| v + b)));
            o.normals.extend_from_slice(&m.normals);
        }
        None => out.push(m),
    }
}

/// The block meshes of every grid of `scene`, one per distinct state
/// (grids' meshes of the same state joined), in first-seen order.
pub(crate) fn block_meshes(scene: &Scene) -> Vec<BlockMesh> {
    let mut out: Vec<BlockMesh> = Vec::new();
    for grid in &scene.blocks {
        for m in mesh_blocks(grid) {
            join_mesh(&mut out, m);
        }
    }
    out
}

/// The block meshes of every grid of `scene` as [`block_meshes`], with the
/// blocks that are not full cubes drawn in their shapes (see
/// [`block_boxes`]): slabs half high, stairs as a slab and a step, doors,
/// trapdoors and ladders as thin panels, panes, bars, fences and walls as
/// posts with arms to their connections, lanterns, torches, chains,
/// carpets and snow layers small. For previews: the other formats keep
/// whole cubes.
pub(crate) fn shaped_block_meshes(scene: &Scene) -> Vec<BlockMesh> {
    let mut out: Vec<BlockMesh> = Vec::new();
    for grid in &scene.blocks {
        let boxes: Vec<Option<Vec<[Vec3; 2]>>> = grid.palette.iter().map(block_boxes).collect();
        let mut meshes = if boxes.iter().any(Option::is_some) {
            // The full cubes without the shaped cells: those hide nothing
            // and are drawn box by box below.
            let mut cubes = grid.clone();
            for c in &mut cubes.cells {
                if boxes.get(*c as usize).is_some_and(Option::is_some) {
                    *c = BlockGrid::UNSET;
                }
            }
            let mut meshes = mesh_blocks(&cubes);
            let n = grid.size.as_ivec3();
            for (i, &c) in grid.cells.iter().enumerate() {
                let Some(Some(parts)) = boxes.get(c as usize) else { continue };
                let i = i as i32;
                let corner = (grid.origin + glam::IVec3::new(i % n.x, i / (n.x * n.z), (i / n.x) % n.z)).as_vec3();
                let state = &grid.palette[c as usize];
                let at = match meshes.iter().position(|m| &m.state == state) {
                    Some(at) => at,
                    None => {
                        let mesh = Mesh { name: state.to_string(), ..Mesh::default() };
                        meshes.push(BlockMesh { state: state.clone(), mesh, normals: Vec::new() });
                        meshes.len() - 1
                    }
                };
                let m = &mut meshes[at];
                for &[lo, hi] in parts {
                    push_box(&mut m.mesh, &mut m.normals, corner + lo, corner + hi);
                }
            }
            meshes
        } else {
            mesh_blocks(grid)
        };
        for m in meshes.drain(..) {
            join_mesh(&mut out, m);
        }
    }
    out
}

/// A closed box from `lo` to `hi`: 6 quads, counter-clockwise from outside.
fn push_box(mesh: &mut Mesh, normals: &mut Vec<Vec3>, lo: Vec3, hi: Vec3) {
    for d in 0..3 {
        let (u, v) = ((d + 1) % 3, (d + 2) % 3);
        for positive in [true, false] {
            let at = |i: bool, j: bool| {
                let mut p = [0.0f32; 3];
                p[d] = if positive { hi[d] } else { lo[d] };
                p[u] = if i { hi[u] } else { lo[u] };
                p[v] = if j { hi[v] } else { lo[v] };
                Vec3::from_array(p)
            };
            let corners = if positive {
                [at(false, false), at(true, false), at(true, true), at(false, true)]
            } else {
                [at(false, false), at(false, true), at(true, true), at(true, false)]
            };
            let mut n = [0.0f32; 3];
            n[d] = if positive { 1.0 } else { -1.0 };
            let b = mesh.positions.len() as u32;
            mesh.positions.extend_from_slice(&corners);
            normals.extend_from_slice(&[Vec3::from_array(n); 4]);
            mesh.triangles.push([b, b + 1, b + 2]);
            mesh.triangles.push([b, b + 2, b + 3]);
        }
    }
}

/// A horizontal direction's unit step (x, z), from a `facing` value.
fn facing(state: &BlockState) -> Option<(f32, f32)> {
    match prop(state, "facing")? {
        "north" => Some((0.0, -1.0)),
        "south" => Some((0.0, 1.0)),
        "east" => Some((1.0, 0.0)),
        "west" => Some((-1.0, 0.0)),
        _ => None,
    }
}

fn prop<'a>(state: &'a BlockState, key: &str) -> Option<&'a str> {
    state.properties.iter().find(|(k, _)| k == key).map(|(_, v)| v.as_str())
}

/// The part of the unit cell within `t` (in 16ths) of side `(dx, dz)`, over
/// heights `y0..y1` (16ths).
fn side_panel((dx, dz): (f32, f32), t: f32, y0: f32, y1: f32) -> [Vec3; 2] {
    let (t, y0, y1) = (t / 16.0, y0 / 16.0, y1 / 16.0);
    // Along one axis: the `t` next to the side the direction points to, or
    // the whole cell.
    let span = |d: f32| {
        if d > 0.0 {
            (1.0 - t, 1.0)
        } else if d < 0.0 {
            (0.0, t)
        } else {
            (0.0, 1.0)
        }
    };
    let ((x0, x1), (z0, z1)) = (span(dx), span(dz));
    [Vec3::new(x0, y0, z0), Vec3::new(x1, y1, z1)]
}

/// A box in 16ths of a block.
fn px(x0: f32, y0: f32, z0: f32, x1: f32, y1: f32, z1: f32) -> [Vec3; 2] {
    [Vec3::new(x0, y0, z0) / 16.0, Vec3::new(x1, y1, z1) / 16.0]
}

/// A centred post of width `w` (16ths) from `y0` to `y1`, with arms of
/// width `aw` at heights `arms` towards each side whose property is
/// connected (`true`, `low`, `tall`; a wall's `tall` arm runs to `tall_top`).
fn post_and_arms(
    state: &BlockState,
    w: f32,
    y0: f32,
    y1: f32,
    aw: f32,
    arms: &[(f32, f32)],
    tall_top: f32,
) -> Vec<[Vec3; 2]> {
    let (p0, p1) = (8.0 - w / 2.0, 8.0 + w / 2.0);
    let (a0, a1) = (8.0 - aw / 2.0, 8.0 + aw / 2.0);
    let mut v = Vec::new();
    if y1 > y0 {
        v.push(px(p0, y0, p0, p1, y1, p1));
    }
    for (side, (dx, dz)) in [("north", (0, -1)), ("south", (0, 1)), ("east", (1, 0)), ("west", (-1, 0))] {
        let value = prop(state, side).unwrap_or("false");
        if matches!(value, "false" | "none") {
            continue;
        }
        for &(b, t) in arms {
            let t = if value == "tall" { tall_top } else { t };
            let (x0, x1) = match dx {
                1 => (p1.min(a1), 16.0),
                -1 => (0.0, p0.max(a0)),
                _ => (a0, a1),
            };
            let (z0, z1) = match dz {
                1 => (p1.min(a1), 16.0),
                -1 => (0.0, p0.max(a0)),
                _ => (a0, a1),
            };
            v.push(px(x0, b, z0, x1, t, z1));
        }
    }
    v
}

/// The boxes (in the unit cell) that draw a block that is not a full cube,
/// or `None` for a full cube. The shapes follow the game's outlines
/// closely enough for a preview.
pub(crate) fn block_boxes(state: &BlockState) -> Option<Vec<[Vec3; 2]>> {
    let id = state.id();
    let top = prop(state, "half") == Some("top") || prop(state, "type") == Some("top");
    if id.ends_with("_slab") {
        return match prop(state, "type") {
            Some("double") => None,
            _ if top => Some(vec![px(0.0, 8.0, 0.0, 16.0, 16.0, 16.0)]),
            _ => Some(vec![px(0.0, 0.0, 0.0, 16.0, 8.0, 16.0)]),
        };
    }
    if id.ends_with("_stairs") {
        let (base, step) = if top { ((8.0, 16.0), (0.0, 8.0)) } else { ((0.0, 8.0), (8.0, 16.0)) };
        let mut v = vec![px(0.0, base.0, 0.0, 16.0, base.1, 16.0)];
        let f = facing(state).unwrap_or((0.0, -1.0));
        // Counter-clockwise (left) and clockwise (right) of the facing.
        let left = (f.1, -f.0);
        let right = (-f.1, f.0);
        // Quarters of the step: (side a, side b) both half-cell panels.
        let quarter = |a: (f32, f32), b: (f32, f32)| {
            let [lo_a, hi_a] = side_panel(a, 8.0, step.0, step.1);
            let [lo_b, hi_b] = side_panel(b, 8.0, step.0, step.1);
            [lo_a.max(lo_b), hi_a.min(hi_b)]
        };
        let back = (-f.0, -f.1);
        match prop(state, "shape").unwrap_or("straight") {
            "outer_left" => v.push(quarter(f, left)),
            "outer_right" => v.push(quarter(f, right)),
            "inner_left" => v.extend([side_panel(f, 8.0, step.0, step.1), quarter(back, left)]),
            "inner_right" => v.extend([side_panel(f, 8.0, step.0, step.1), quarter(back, right)]),
            _ => v.push(side_panel(f, 8.0, step.0, step.1)),
        }
        return Some(v);
    }
    let open = prop(state, "open") == Some("true");
    if id.ends_with("_door") {
        let f = facing(state).unwrap_or((0.0, -1.0));
        let side = if !open {
            (-f.0, -f.1)
        } else if prop(state, "hinge") == Some("right") {
            (f.1, -f.0)
        } else {
            (-f.1, f.0)
        };
        return Some(vec![side_panel(side, 3.0, 0.0, 16.0)]);
    }
    if id.ends_with("_trapdoor") {
        if open {
            let f = facing(state).unwrap_or((0.0, -1.0));
            return Some(vec![side_panel((-f.0, -f.1), 3.0, 0.0, 16.0)]);
        }
        return Some(vec![if top { px(0.0, 13.0, 0.0, 16.0, 16.0, 16.0) } else { px(0.0, 0.0, 0.0, 16.0, 3.0, 16.0) }]);
    }
    if id == "ladder" {
        let f = facing(state).unwrap_or((0.0, -1.0));
        return Some(vec![side_panel((-f.0, -f.1), 2.0, 0.0, 16.0)]);
    }
    if id.ends_with("glass_pane") || id == "iron_bars" {
        return Some(post_and_arms(state, 2.0, 0.0, 16.0, 2.0, &[(0.0, 16.0)], 16.0));
    }
    if id.ends_with("_fence_gate") {
        let f = facing(state).unwrap_or((0.0, -1.0));
        return Some(vec![if f.0 == 0.0 {
            px(0.0, 5.0, 7.0, 16.0, 16.0, 9.0)
        } else {
            px(7.0, 5.0, 0.0, 9.0, 16.0, 16.0)
        }]);
    }
    if id.ends_with("_fence") {
        return Some(post_and_arms(state, 4.0, 0.0, 16.0, 2.0, &[(6.0, 9.0), (12.0, 15.0)], 15.0));
    }
    if id.ends_with("_wall") && !id.contains("_wall_") && id != "wall_torch" {
        let post = if prop(state, "up") == Some("false") { 0.0 } else { 16.0 };
        return Some(post_and_arms(state, 8.0, 0.0, post, 6.0, &[(0.0, 14.0)], 16.0));
    }
    if id.ends_with("lantern") && !id.ends_with("jack_o_lantern") && id != "sea_lantern" {
        let hanging = prop(state, "hanging") == Some("true");
        let (y0, y1) = if hanging { (1.0, 8.0) } else { (0.0, 7.0) };
        let mut v = vec![px(5.0, y0, 5.0, 11.0, y1, 11.0), px(6.0, y1, 6.0, 10.0, y1 + 2.0, 10.0)];
        if hanging {
            v.push(px(7.0, y1 + 2.0, 7.0, 9.0, 16.0, 9.0));
        }
        return Some(v);
    }
    if id == "chain" {
        return Some(vec![match prop(state, "axis") {
            Some("x") => px(0.0, 7.0, 7.0, 16.0, 9.0, 9.0),
            Some("z") => px(7.0, 7.0, 0.0, 9.0, 9.0, 16.0),
            _ => px(7.0, 0.0, 7.0, 9.0, 16.0, 9.0),
        }]);
    }
    if matches!(id, "torch" | "soul_torch" | "redstone_torch") {
        return Some(vec![px(7.0, 0.0, 7.0, 9.0, 10.0, 9.0)]);
    }
    if id.ends_with("_carpet") || id.ends_with("_pressure_plate") {
        return Some(vec![px(0.0, 0.0, 0.0, 16.0, 1.0, 16.0)]);
    }
    if id == "snow" {
        let layers: f32 = prop(state, "layers").and_then(|l| l.parse().ok()).unwrap_or(1.0);
        return Some(vec![px(0.0, 0.0, 0.0, 16.0, 2.0 * layers.clamp(1.0, 8.0), 16.0)]);
    }
    None
}

/// Whether some grid of `scene` has a block that is drawn (set, not air):
/// then its meshes are not empty (the drawn block farthest along +x shows
/// its +x face).
pub(crate) fn has_drawn_blocks(scene: &Scene) -> bool {
    scene.blocks.iter().any(|g| {
        let drawn: Vec<bool> = g.palette.iter().map(|s| s.kind() != BlockKind::Air).collect();
        g.cells.iter().any(|&c| drawn.get(c as usize).copied().unwrap_or(false))
    })
}

/// Calls `f` with every block-mesh triangle of `scene` (world space,
/// counter-clockwise from outside) and its state.
pub(crate) fn for_each_block_triangle(scene: &Scene, mut f: impl FnMut([Vec3; 3], &BlockState)) {
    for m in block_meshes(scene) {
        for t in &m.mesh.triangles {
            f(t.map(|v| m.mesh.positions[v as usize]), &m.state);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::{IVec3, UVec3};

    fn quads(meshes: &[BlockMesh]) -> usize {
        meshes.iter().map(|m| m.mesh.triangles.len() / 2).sum()
    }

    /// Signed volume enclosed by the triangles (positive when outward).
    fn volume(meshes: &[BlockMesh]) -> f32 {
        meshes
            .iter()
            .flat_map(|m| m.mesh.triangles.iter().map(|t| t.map(|v| m.mesh.positions[v as usize])))
            .map(|[a, b, c]| a.dot(b.cross(c)) / 6.0)
            .sum()
    }

    #[test]
    fn a_bar_is_six_quads() {
        let mut g = BlockGrid::new(IVec3::new(5, 0, -2), UVec3::new(2, 1, 1));
        g.set(IVec3::new(5, 0, -2), &BlockState::new("stone"));
        g.set(IVec3::new(6, 0, -2), &BlockState::new("stone"));
        let m = mesh_blocks(&g);
        assert_eq!(m.len(), 1);
        assert_eq!(quads(&m), 6);
        assert!((volume(&m) - 2.0).abs() < 1e-4, "{}", volume(&m));
        let (lo, hi) = m[0].mesh.bounds().unwrap();
        assert_eq!((lo, hi), (Vec3::new(5.0, 0.0, -2.0), Vec3::new(7.0, 1.0, -1.0)));
        // Normals point the way the triangles face.
        for (t, i) in m[0].mesh.triangles.iter().zip(0..) {
            let [a, b, c] = t.map(|v| m[0].mesh.positions[v as usize]);
            assert_eq!((b - a).cross(c - a).normalize(), m[0].normals[t[0] as usize], "triangle {i}");
        }
        // Two different states side by side: 5 + 5 quads, the shared face hidden.
        g.set(IVec3::new(6, 0, -2), &BlockState::new("dirt"));
        let m = mesh_blocks(&g);
        assert_eq!((m.len(), quads(&m)), (2, 10));
    }

    #[test]
    fn a_hollow_box_hides_its_inner_faces_only_where_solid() {
        // A 3×3×3 shell of stone around one air cell: the air is not drawn
        // and no face looks into it... except that stone faces next to air
        // do show: 6 outer 3×3 faces (merged, 6 quads) + 6 inner faces.
        let mut g = BlockGrid::new(IVec3::ZERO, UVec3::splat(3));
        for p in (0..27).map(|i| IVec3::new(i % 3, i / 9, (i / 3) % 3)) {
            let s = if p == IVec3::ONE { "air" } else { "stone" };
            g.set(p, &BlockState::new(s));
        }
        let m = mesh_blocks(&g);
        assert_eq!(m.len(), 1);
        assert_eq!(quads(&m), 12);
        // Volume: 27 outside minus the 1 cavity.
        assert!((volume(&m) - 26.0).abs() < 1e-3);
        // Filled with glass (solid): the cavity faces disappear as well.
        g.set(IVec3::ONE, &BlockState::new("glass"));
        let m = mesh_blocks(&g);
        assert_eq!(quads(&m), 6);
        // Water next to water shows no faces between them; unset hides nothing.
        let mut w = BlockGrid::new(IVec3::ZERO, UVec3::new(4, 1, 1));
        for x in 0..3 {
            w.set(IVec3::new(x, 0, 0), &BlockState::new("water"));
        }
        assert_eq!(quads(&mesh_blocks(&w)), 6);
    }

    #[test]
    fn greedy_merging_keeps_rectangles() {
        // An L of 3 + 2 blocks on one layer: the top has one 3×1 and one
        // 1×1 (or 2×1/1×2) rectangle, never 5 single quads.
        let mut g = BlockGrid::new(IVec3::ZERO, UVec3::new(3, 1, 2));
        for p in [IVec3::new(0, 0, 0), IVec3::new(1, 0, 0), IVec3::new(2, 0, 0), IVec3::new(0, 0, 1)] {
            g.set(p, &BlockState::new("stone"));
        }
        let m = mesh_blocks(&g);
        let up = m[0].normals.iter().filter(|n| **n == Vec3::Y).count() / 4;
        assert_eq!(up, 2);
        assert!((volume(&m) - 4.0).abs() < 1e-4);
    }

    #[test]
    fn a_big_grid_meshes_quickly() {
        // 96×24×96 terrain-like grid: a stone floor with noise pillars.
        let mut g = BlockGrid::new(IVec3::ZERO, UVec3::new(96, 24, 96));
        let (stone, grass) = (g.intern(&BlockState::new("stone")), g.intern(&BlockState::new("grass_block")));
        for z in 0..96 {
            for x in 0..96 {
                let h = 4 + ((x * 7 + z * 13) % 11) as usize;
                for y in 0..h {
                    let i = g.index(IVec3::new(x, y as i32, z)).unwrap();
                    g.cells[i] = if y + 1 == h { grass } else { stone };
                }
            }
        }
        let t = std::time::Instant::now();
        let m = mesh_blocks(&g);
        assert!(t.elapsed().as_secs_f32() < 2.0, "{:?}", t.elapsed());
        assert_eq!(m.len(), 2);
        let v = volume(&m);
        let blocks = g.set_count() as f32;
        assert!((v - blocks).abs() < 1e-2 * blocks, "{v} vs {blocks}");
    }

    fn shaped(states: &[&str]) -> Vec<BlockMesh> {
        let mut g = BlockGrid::new(IVec3::ZERO, UVec3::new(states.len() as u32, 1, 1));
        for (x, s) in (0..).zip(states) {
            g.set(IVec3::new(x, 0, 0), &BlockState::parse(s).unwrap());
        }
        let mut scene = Scene::default();
        scene.blocks.push(g);
        shaped_block_meshes(&scene)
    }

    #[test]
    fn previews_draw_blocks_in_their_shapes() {
        let v = |s: &str| volume(&shaped(&[s]));
        assert!((v("stone_slab[type=bottom]") - 0.5).abs() < 1e-4);
        assert!((v("stone_slab[type=double]") - 1.0).abs() < 1e-4);
        assert!((v("oak_stairs[facing=east,half=bottom,shape=straight]") - 0.75).abs() < 1e-4);
        assert!((v("oak_stairs[facing=east,half=top,shape=outer_left]") - 0.625).abs() < 1e-4);
        assert!((v("oak_stairs[facing=east,half=top,shape=inner_right]") - 0.875).abs() < 1e-4);
        assert!((v("oak_door[facing=north,half=lower,hinge=left,open=false]") - 3.0 / 16.0).abs() < 1e-4);
        assert!(v("oak_fence[east=true,north=false,south=false,west=false]") < 0.2);
        assert!(v("glass_pane[east=false,north=false,south=false,west=false]") < 0.02);
        // A straight stairs facing east has its step on the east half, on top.
        let m = shaped(&["oak_stairs[facing=east,half=bottom,shape=straight]"]);
        let top = m[0].mesh.positions.iter().filter(|p| p.y == 1.0).map(|p| p.x).fold(f32::INFINITY, f32::min);
        assert_eq!(top, 0.5);
        // A closed door facing north stands at the south edge of its cell.
        let m = shaped(&["oak_door[facing=north,half=lower,hinge=left,open=false]"]);
        let (lo, hi) = m[0].mesh.bounds().unwrap();
        assert_eq!((lo.z, hi.z), (13.0 / 16.0, 1.0));
        // Full blocks next to a slab still show the face towards it.
        let m = shaped(&["stone", "stone_slab[type=bottom]"]);
        assert!((volume(&m) - 1.5).abs() < 1e-4);
    }
}
