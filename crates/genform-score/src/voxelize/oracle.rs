//! The per-voxel voxelizer: the test oracle and benchmark baseline.
//!
//! For every lattice voxel centre in each instance's bounding box it maps
//! the centre to the unit frame and asks the primitive's predicate, or, for
//! meshes, counts the triangles the row ray crosses beyond the centre; for
//! block structures it tests every centre near each solid cell. It
//! shares only the per-instance set-up, the predicates and the crossing
//! rule with the fast voxelizer, none of the span logic. Its cost is the
//! bounding-box volume (times the triangle count for meshes): use it on
//! small grids.

use super::blocks::oracle_cells;
use super::prepare::{Body, prepare};
use super::{Voxelized, crossing};
use crate::bits::BitRows;
use crate::grid::{Grid, Lattice};
use crate::voxel_set::VoxelSet;
use genform_core::scene::Scene;
use glam::Vec3;

/// Voxelizes `scene` on `grid` one voxel centre at a time. Same result as
/// [`super::voxelize`], bit for bit.
pub fn voxelize(grid: &Grid, scene: &Scene) -> Voxelized {
    let lat = Lattice::new(grid);
    // Hits per grid voxel, saturating at 2.
    let mut hits = vec![0u8; lat.words * 64 * lat.rows];
    let mut outside = 0u64;
    let mut verts = Vec::new();
    for inst in &scene.instances {
        let Some(p) = prepare(&lat, scene, inst, &mut verts) else { continue };
        let (Some([(j0, j1), (k0, k1)]), Some((i0, i1))) = (p.row_ranges(&lat), p.x_range(&lat)) else { continue };
        let (mut in_grid, mut out) = (0u64, 0u64);
        for k in k0..=k1 {
            for j in j0..=j1 {
                let (py, pz) = (lat.centre(1, j), lat.centre(2, k));
                for i in i0..=i1 {
                    let px = lat.centre(0, i);
                    let held = match &p.body {
                        Body::Solid(s) => s.contains(Vec3::new(px, py, pz)),
                        Body::Mesh(mesh) => {
                            let n = verts.len();
                            let beyond = mesh
                                .triangles
                                .iter()
                                .filter(|t| t.iter().all(|&v| (v as usize) < n))
                                .filter_map(|t| crossing(&t.map(|v| verts[v as usize]), py, pz))
                                .filter(|&(x, _)| x > f64::from(px))
                                .count();
                            beyond % 2 == 1
                        }
                    };
                    if !held {
                        continue;
                    }
                    match lat.row(j, k) {
                        Some(r) if (0..lat.dims[0]).contains(&i) => {
                            let h = &mut hits[r * lat.words * 64 + i as usize];
                            *h = (*h + 1).min(2);
                            in_grid += 1;
                        }
                        _ => out += 1,
                    }
                }
            }
        }
        outside = outside.saturating_add(p.outside(in_grid, out));
    }
    for g in &scene.blocks {
        let mut out = 0u64;
        oracle_cells(&lat, g, |i, j, k| match lat.row(j, k) {
            Some(r) if (0..lat.dims[0]).contains(&i) => {
                let h = &mut hits[r * lat.words * 64 + i as usize];
                *h = (*h + 1).min(2);
            }
            _ => out += 1,
        });
        outside = outside.saturating_add(out);
    }
    let plane = |min: u8| {
        let mut b = BitRows::new(lat.words, lat.rows);
        for (v, &h) in hits.iter().enumerate() {
            if h >= min {
                let (r, i) = (v / (lat.words * 64), v % (lat.words * 64));
                b.set_range(r, i, i);
            }
        }
        VoxelSet::from_bits(lat.clone(), b)
    };
    Voxelized { occupancy: plane(1), overlap: plane(2), outside }
}
