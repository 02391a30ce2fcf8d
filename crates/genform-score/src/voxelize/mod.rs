//! Voxelizing a Scene: which lattice voxel centres each instance holds.
//!
//! Semantics (shared by the fast voxelizer here and the per-voxel
//! `oracle` — tests and benches only, feature `test-support` — which agree bit for bit):
//!
//! - A solid primitive holds a voxel when the voxel centre, mapped to the
//!   unit frame by the inverse instance transform, passes the primitive's
//!   half-open point test. Singular or non-finite transforms hold nothing.
//! - A mesh instance holds a voxel of its lattice bounding box when a ray
//!   from the centre along the row axis crosses its world-space triangles
//!   an odd number of times (crossings exactly at the centre do not count;
//!   lines through edges and vertices follow the tie rule of `crossing`).
//! - A voxel held by two or more instances is an *overlap* voxel; one
//!   instance never overlaps itself.
//! - A block structure ([`Scene::blocks`](genform_core::Scene::blocks))
//!   holds the voxel centres inside its non-air cells, each cell the
//!   half-open box `[x, x+1) × [y, y+1) × [z, z+1)`, decided exactly (see
//!   `blocks`); each block grid counts as one instance.
//! - `outside` counts, per instance, the held centres of the infinite
//!   lattice that lie outside the grid. It is exact unless an instance's
//!   bounding box spans more than 2²⁰ lattice rows; then only rows inside
//!   the grid are voxelized and `outside` is estimated as
//!   `max(0, round(|det|·volume / voxel volume) − voxels held in the grid)`.
//!
//! The fast voxelizer works by spans: for each lattice row the instance's
//! bounding box covers, it computes the interval of the row line inside the
//! primitive analytically in `f64` (slabs for boxes and tapered boxes, a
//! quadratic for spheres and frustums), for a shape grown by a bound on the
//! predicate's rounding, then settles both ends by evaluating the oracle's
//! own `f32` predicate on the boundary centres, walking inwards and then
//! outwards. Each unit coordinate is a monotone function of the index along
//! a row (one rounded multiply-add of a monotone centre), so for boxes the
//! held centres of a row are an interval and the settled ends are exact by
//! construction; for the curved and tapered primitives the same holds
//! except on rows that graze a face to within rounding (never seen in
//! 300,000 random cases per property against the oracle). Boxes whose
//! transform maps lattice axes to unit axes one to one (axis-aligned,
//! possibly mirrored) are separable: one span serves all their rows.
//! Boxes with one cross-row lattice axis driving one unit axis alone (a
//! box rotated about that axis) share each span along that axis. Meshes
//! scan each triangle across the rows it covers, group the crossings by
//! row and fill between them by parity.
//!
//! Spans go into a [`VolumeScratch`] with two bit planes, occupied and
//! overlap (`overlap |= occupied & span; occupied |= span`), which counts
//! new held, overlap and target voxels as it marks them and remembers the
//! rows it touched, so that clearing visits only those. A scorer's scratch
//! also brings a span cache (`span_cache`): a mesh instance met before is
//! marked from its recorded spans instead of being scanned again.

mod blocks;
mod crossing;
mod mesh_buffers;
mod mesh_rows;
#[cfg(any(test, feature = "test-support"))]
pub mod oracle;
mod out;
mod prepare;
mod scratch;
mod shape;
mod spans;

pub(crate) use crossing::crossing;
use mesh_rows::mesh_rows;
use out::{Out, Tally};
use prepare::{Body, prepare};
pub(crate) use scratch::Plane;
pub use scratch::VolumeScratch;
use spans::{separable_box, solid_rows, split_box};

use crate::grid::{Grid, Lattice};
use crate::span_cache::Lookup;
use crate::voxel_set::VoxelSet;
use genform_core::scene::{Primitive, Scene};

/// A voxelized Scene: the voxels it holds, those held more than once, and
/// how many held lattice voxels lie outside the grid.
#[derive(Clone, Debug, PartialEq)]
pub struct Voxelized {
    /// Voxels held by at least one instance.
    pub occupancy: VoxelSet,
    /// Voxels held by at least two instances.
    pub overlap: VoxelSet,
    /// Held lattice voxels outside the grid, summed over instances.
    pub outside: u64,
}

/// Voxelizes `scene` on `grid` with the fast voxelizer (allocates its own
/// scratch; scorers reuse a [`VolumeScratch`] instead).
pub fn voxelize(grid: &Grid, scene: &Scene) -> Voxelized {
    let lat = Lattice::new(grid);
    let mut s = VolumeScratch::new(&lat);
    rasterize(&lat, scene, &mut s, &[]);
    let out = Voxelized {
        occupancy: VoxelSet::from_bits(lat.clone(), s.plane(Plane::Occupied)),
        overlap: VoxelSet::from_bits(lat.clone(), s.plane(Plane::Overlap)),
        outside: s.outside,
    };
    s.clear();
    out
}

/// Voxelizes every instance and block grid of `scene` into `s` (which must be clear),
/// counting held voxels that are set in `target` (a [`crate::bits::BitRows`]
/// layout of the lattice, or empty).
pub(crate) fn rasterize(lat: &Lattice, scene: &Scene, s: &mut VolumeScratch, target: &[u64]) {
    let mut verts = s.take_verts();
    let (mut cache, mut spans, mut keys) = s.take_cache();
    if let Some(c) = cache.as_mut() {
        c.drawn_on(lat);
    }
    // Per mesh of the scene: its cache key, once looked up.
    keys.clear();
    for inst in &scene.instances {
        let key = match (inst.primitive, cache.as_mut()) {
            (Primitive::Mesh(id), Some(c)) => c.scene_mesh_key(scene, id, &mut keys),
            _ => None,
        };
        let mut record = false;
        if let (Some(k), Some(c)) = (key, cache.as_mut()) {
            match c.lookup(k, inst) {
                Lookup::Hit { spans, outside, .. } => {
                    for &(r, a, b) in spans {
                        s.write(r as usize, a as usize, b as usize, target);
                    }
                    s.outside = s.outside.saturating_add(outside);
                    continue;
                }
                Lookup::Record => record = true,
                Lookup::Draw => {}
            }
        }
        spans.clear();
        let mut outside = 0;
        if let Some(p) = prepare(lat, scene, inst, &mut verts) {
            let mut tally = Tally::default();
            match &p.body {
                Body::Solid(solid) => {
                    let out = &mut Out { s, tally: &mut tally, target, record: None };
                    match (solid.separable, solid.split) {
                        (Some(perm), _) => separable_box(lat, &p, solid, perm, out),
                        (None, Some(split)) => split_box(lat, &p, solid, split, out),
                        (None, None) => solid_rows(lat, &p, solid, out),
                    }
                }
                Body::Mesh(mesh) => {
                    let record = record.then_some(&mut spans);
                    mesh_rows(lat, &p, mesh, &verts, &mut Out { s, tally: &mut tally, target, record });
                }
            }
            outside = p.outside(tally.in_grid, tally.outside);
            s.outside = s.outside.saturating_add(outside);
        }
        if let (true, Some(k), Some(c)) = (record, key, cache.as_mut()) {
            c.insert(k, inst, &spans, outside);
        }
    }
    s.put_cache(cache, spans, keys);
    s.put_verts(verts);
    blocks::rasterize_blocks(lat, scene, s, target);
}

#[cfg(test)]
pub(crate) mod tests;
