//! A mesh asset's edges: whether they close a surface ([`is_closed`]) and
//! which triangles use each ([`EdgeTable`]), read by the projection and the
//! outline filler alike.

use genform_core::scene::Mesh;

/// Whether `mesh`'s triangles form a closed surface: every vertex index in
/// range, no triangle repeating an index, and each edge `a → b` used as
/// often as `b → a`.
pub(crate) fn is_closed(mesh: &Mesh) -> bool {
    let n = mesh.positions.len();
    let mut edges = Vec::with_capacity(3 * mesh.triangles.len());
    for t in &mesh.triangles {
        if t.iter().any(|&i| i as usize >= n) || t[0] == t[1] || t[1] == t[2] || t[0] == t[2] {
            return false;
        }
        for e in 0..3 {
            let (a, b) = (t[e], t[(e + 1) % 3]);
            edges.push(if a < b { (a, b, 1i64) } else { (b, a, -1) });
        }
    }
    edges.sort_unstable();
    edges.chunk_by(|x, y| (x.0, x.1) == (y.0, y.1)).all(|g| g.iter().map(|e| e.2).sum::<i64>() == 0)
}

/// A mesh asset's undirected edges, each with the triangles that use it.
#[derive(Debug, Default)]
pub(crate) struct EdgeTable {
    /// Edges used once each way (all edges of a closed 2-manifold): the
    /// vertices `a < b`, the triangle running `a → b`, the one running
    /// `b → a`.
    pub(super) pairs: Vec<[u32; 4]>,
    /// Other edges: the vertices `a < b` and the range of their uses.
    pub(super) others: Vec<([u32; 2], std::ops::Range<usize>)>,
    /// `(triangle, +1 if it runs a → b else −1)` of the other edges.
    pub(super) uses: Vec<(u32, i32)>,
}

impl EdgeTable {
    /// The edges of `mesh` (whose indices must all be in range).
    pub fn new(mesh: &Mesh) -> EdgeTable {
        let mut all: Vec<(u32, u32, u32, i32)> = Vec::with_capacity(3 * mesh.triangles.len());
        for (t, tri) in mesh.triangles.iter().enumerate() {
            for e in 0..3 {
                let (a, b) = (tri[e], tri[(e + 1) % 3]);
                all.push(if a < b { (a, b, t as u32, 1) } else { (b, a, t as u32, -1) });
            }
        }
        all.sort_unstable();
        let mut table = EdgeTable::default();
        for group in all.chunk_by(|x, y| (x.0, x.1) == (y.0, y.1)) {
            let (a, b) = (group[0].0, group[0].1);
            if let [(.., t, s), (.., u, r)] = group
                && s + r == 0
            {
                let (fwd, back) = if *s > 0 { (*t, *u) } else { (*u, *t) };
                table.pairs.push([a, b, fwd, back]);
            } else {
                let start = table.uses.len();
                table.uses.extend(group.iter().map(|&(_, _, t, s)| (t, s)));
                table.others.push(([a, b], start..table.uses.len()));
            }
        }
        table
    }
}
