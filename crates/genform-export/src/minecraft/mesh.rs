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

/// The block meshes of every grid of `scene`, one per distinct state
/// (grids' meshes of the same state joined), in first-seen order.
pub(crate) fn block_meshes(scene: &Scene) -> Vec<BlockMesh> {
    let mut out: Vec<BlockMesh> = Vec::new();
    for grid in &scene.blocks {
        for m in mesh_blocks(grid) {
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
    }
    out
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
}
