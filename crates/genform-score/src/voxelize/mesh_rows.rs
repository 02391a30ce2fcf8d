//! Spans of mesh instances: row crossings, sorted, filled by parity.

use super::prepare::Prepared;
use super::{Out, crossing, emit};
use crate::grid::Lattice;
use genform_core::scene::Mesh;
use glam::Vec3;

/// Rows of a mesh instance: crossings per row, sorted, filled by parity.
pub(super) fn mesh_rows(lat: &Lattice, p: &Prepared, mesh: &Mesh, verts: &[Vec3], out: &mut Out) {
    let (Some([(j0, j1), (k0, k1)]), Some((i0, i1))) = (p.row_ranges(lat), p.x_range(lat)) else { return };
    let nj = j1 - j0 + 1;
    let mut cross = out.s.take_crossings();
    let n = verts.len();
    for t in &mesh.triangles {
        if !t.iter().all(|&i| (i as usize) < n) {
            continue;
        }
        let tri = t.map(|i| verts[i as usize]);
        let (lo, hi) = (tri[0].min(tri[1]).min(tri[2]), tri[0].max(tri[1]).max(tri[2]));
        let (ja, jb) = lat.index_range(1, f64::from(lo.y), f64::from(hi.y));
        let (ka, kb) = lat.index_range(2, f64::from(lo.z), f64::from(hi.z));
        for k in ka.max(k0)..=kb.min(k1) {
            let qv = lat.centre(2, k);
            for j in ja.max(j0)..=jb.min(j1) {
                if let Some((x, _)) = crossing(&tri, lat.centre(1, j), qv) {
                    cross.push((((k - k0) * nj + (j - j0)) as u32, x));
                }
            }
        }
    }
    cross.sort_unstable_by(|a, b| a.0.cmp(&b.0).then(a.1.total_cmp(&b.1)));
    let mut g = 0;
    while g < cross.len() {
        let row = cross[g].0;
        let end = g + cross[g..].iter().take_while(|c| c.0 == row).count();
        let xs = &cross[g..end];
        let (j, k) = (j0 + i64::from(row) % nj, k0 + i64::from(row) / nj);
        let n = xs.len();
        // Held iff an odd number of crossings lie beyond the centre: the
        // centres in [xs[m−1], xs[m]) have n − m of them.
        for m in (0..=n).filter(|m| (n - m) % 2 == 1) {
            let a = if m == 0 { i0 } else { lat.first_at_or_after(0, xs[m - 1].1).max(i0) };
            let b = if m == n { i1 } else { (lat.first_at_or_after(0, xs[m].1) - 1).min(i1) };
            if a <= b {
                emit(lat, out, j, k, a, b);
            }
        }
        g = end;
    }
    out.s.put_crossings(cross);
}
