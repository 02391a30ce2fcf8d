//! Cleaning a user mesh before voxelizing it: weld equal positions, drop
//! degenerate and duplicated faces, and orient each connected piece
//! consistently.

use genform_core::scene::Mesh;
use glam::Vec3;
use std::collections::{HashMap, HashSet, VecDeque};

/// What the clean-up changed.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Repairs {
    /// Vertices merged into an earlier vertex at the same position.
    pub welded_vertices: usize,
    /// Faces dropped because two of their corners coincide.
    pub degenerate_faces: usize,
    /// Faces dropped because another face has the same three corners
    /// (in either orientation).
    pub duplicate_faces: usize,
    /// Faces turned round to agree with their neighbours.
    pub flipped_faces: usize,
}

/// The cleaned triangles (indices into the returned positions) and what changed.
pub(crate) fn repair(mesh: &Mesh) -> (Vec<Vec3>, Vec<[u32; 3]>, Repairs) {
    let mut rep = Repairs::default();
    // Weld by exact position (−0 and +0 are one position).
    let mut index: HashMap<[u32; 3], u32> = HashMap::new();
    let mut positions = Vec::new();
    let remap: Vec<u32> = mesh
        .positions
        .iter()
        .map(|&p| {
            let key = (p + Vec3::ZERO).to_array().map(f32::to_bits);
            *index.entry(key).or_insert_with(|| {
                positions.push(p);
                (positions.len() - 1) as u32
            })
        })
        .collect();
    rep.welded_vertices = mesh.positions.len() - positions.len();

    let mut seen: HashSet<[u32; 3]> = HashSet::new();
    let mut tris: Vec<[u32; 3]> = Vec::with_capacity(mesh.triangles.len());
    for t in &mesh.triangles {
        let t = t.map(|i| remap[i as usize]);
        if t[0] == t[1] || t[1] == t[2] || t[0] == t[2] {
            rep.degenerate_faces += 1;
            continue;
        }
        let mut key = t;
        key.sort_unstable();
        if !seen.insert(key) {
            rep.duplicate_faces += 1;
            continue;
        }
        tris.push(t);
    }
    rep.flipped_faces = orient(&mut tris);
    (positions, tris, rep)
}

/// Makes faces that share a manifold edge (an edge of exactly two faces)
/// traverse it in opposite directions, keeping in each connected piece the
/// orientation most of its faces already had. Returns how many faces turned.
fn orient(tris: &mut [[u32; 3]]) -> usize {
    // (edge key, face, whether the face runs the edge from low to high).
    let mut edges: Vec<(u32, u32, u32, bool)> = Vec::with_capacity(tris.len() * 3);
    for (f, t) in tris.iter().enumerate() {
        for e in 0..3 {
            let (a, b) = (t[e], t[(e + 1) % 3]);
            edges.push((a.min(b), a.max(b), f as u32, a < b));
        }
    }
    edges.sort_unstable();
    // Neighbours across manifold edges: (face, must differ in flip state).
    let mut adj: Vec<Vec<(u32, bool)>> = vec![Vec::new(); tris.len()];
    let mut g = 0;
    while g < edges.len() {
        let key = (edges[g].0, edges[g].1);
        let end = g + edges[g..].iter().take_while(|e| (e.0, e.1) == key).count();
        if end - g == 2 {
            let (x, y) = (edges[g], edges[g + 1]);
            // Consistent faces run a shared edge in opposite directions.
            let same = x.3 == y.3;
            adj[x.2 as usize].push((y.2, same));
            adj[y.2 as usize].push((x.2, same));
        }
        g = end;
    }
    let mut flip: Vec<Option<bool>> = vec![None; tris.len()];
    let mut flipped = 0;
    let mut queue = VecDeque::new();
    let mut piece = Vec::new();
    for seed in 0..tris.len() {
        if flip[seed].is_some() {
            continue;
        }
        flip[seed] = Some(false);
        piece.clear();
        queue.push_back(seed);
        while let Some(f) = queue.pop_front() {
            piece.push(f);
            let ff = flip[f].unwrap_or(false);
            for &(n, differ) in &adj[f] {
                if flip[n as usize].is_none() {
                    flip[n as usize] = Some(ff ^ differ);
                    queue.push_back(n as usize);
                }
            }
        }
        let turned = piece.iter().filter(|&&f| flip[f] == Some(true)).count();
        // Keep the majority's orientation.
        let invert = 2 * turned > piece.len();
        for &f in &piece {
            if (flip[f] == Some(true)) != invert {
                tris[f].swap(1, 2);
                flipped += 1;
            }
        }
    }
    flipped
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tetra() -> Mesh {
        Mesh::from_obj("t", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n").unwrap()
    }

    #[test]
    fn closed_consistent_meshes_are_left_alone() {
        let m = tetra();
        let (p, t, r) = repair(&m);
        assert_eq!(r, Repairs::default());
        assert_eq!(p, m.positions);
        assert_eq!(t, m.triangles);
    }

    #[test]
    fn welds_dedupes_and_orients() {
        let mut m = tetra();
        // A copy of vertex 0, a face using it twice, a duplicate face (reversed),
        // and one face turned round.
        m.positions.push(Vec3::ZERO);
        m.triangles.push([4, 0, 1]);
        m.triangles.push([0, 1, 2]);
        m.triangles[3] = [1, 3, 2];
        let (p, t, r) = repair(&m);
        assert_eq!(p.len(), 4);
        assert_eq!(r, Repairs { welded_vertices: 1, degenerate_faces: 1, duplicate_faces: 1, flipped_faces: 1 });
        assert_eq!(t.len(), 4);
        assert_eq!(t[3], [1, 2, 3]);
    }
}
