//! From Scene geometry to snapped pixel-space triangles, shared by the fast
//! rasterizer and the per-pixel oracle so that the two differ only in how
//! they decide coverage.
//!
//! View-space positions are computed in `f64`, clipped against the near and
//! far planes and a guard band far outside the image, projected, and snapped
//! to fixed point with [`SUB`] fractional bits. From there on every test is
//! exact integer arithmetic, so the fast path can be checked against the
//! oracle pixel for pixel.

use super::edge_table::{EdgeTable, is_closed};
use genform_core::camera::Projection;
use genform_core::scene::{Mesh, Primitive, Tessellation, unit_mesh};
use glam::{Affine3A, DAffine3, DVec3, Vec3};

/// Fractional bits of snapped pixel coordinates.
pub(crate) const SUB: u32 = 14;
/// One pixel in snapped units.
pub(crate) const ONE: i64 = 1 << SUB;
/// Half a pixel: pixel `i`'s center is at `i * ONE + HALF`.
pub(crate) const HALF: i64 = ONE / 2;
/// Bound on snapped coordinates: differences stay below 2^30 and edge
/// functions (products of two differences) below 2^61, so `i64` is exact.
const LIMIT: i64 = 1 << 29;
/// Geometry is kept up to this many pixels from the image center (with
/// images of at most 4096 pixels a side, snapped values stay below
/// [`LIMIT`]).
const GUARD_PX: f64 = 16384.0;
/// Most vertices a triangle clipped by 6 planes can have.
pub(crate) const MAX_CLIPPED: usize = 9;

/// A snapped point: pixel coordinates times [`ONE`], `y` down.
pub(crate) type Pt = [i64; 2];

/// `(b − a) × (c − a)`: positive when `a, b, c` turn the way every filled
/// polygon here is wound (clockwise on screen, as `y` runs down).
#[inline]
pub(crate) fn cross(a: Pt, b: Pt, c: Pt) -> i64 {
    (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])
}

/// A camera and image size prepared for rasterizing.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Frame {
    view: DAffine3,
    focal: f64,
    cx: f64,
    cy: f64,
    znear: f64,
    zfar: f64,
    /// The guard band as a slope: kept points have `|x|, |y| <= guard * z`.
    guard: f64,
    pub width: usize,
    pub height: usize,
}

impl Frame {
    pub fn new(p: &Projection) -> Frame {
        Frame {
            view: p.view(),
            focal: p.focal(),
            cx: p.center().x,
            cy: p.center().y,
            znear: p.znear(),
            zfar: p.zfar(),
            guard: GUARD_PX / p.focal(),
            width: p.width() as usize,
            height: p.height() as usize,
        }
    }

    /// World → view.
    pub fn world_view(&self) -> DAffine3 {
        self.view
    }

    /// Unit primitive → view for an instance; `None` when the transform is
    /// not finite (such an instance covers nothing).
    pub fn instance_view(&self, t: &Affine3A) -> Option<DAffine3> {
        let m = self.view * t.as_daffine3();
        m.is_finite().then_some(m)
    }

    /// Signed distance-like values of `v` to the six clipping planes (near,
    /// far, guard band right, left, top, bottom); kept where all are ≥ 0.
    #[inline]
    fn planes(&self, v: DVec3) -> [f64; 6] {
        let g = self.guard * v.z;
        [v.z - self.znear, self.zfar - v.z, g - v.x, g + v.x, g - v.y, g + v.y]
    }

    /// `planes(v)[k]`, computing only that one (the same arithmetic).
    #[inline]
    fn plane(&self, v: DVec3, k: usize) -> f64 {
        let g = self.guard * v.z;
        match k {
            0 => v.z - self.znear,
            1 => self.zfar - v.z,
            2 => g - v.x,
            3 => g + v.x,
            4 => g - v.y,
            _ => g + v.y,
        }
    }

    /// Whether `v` needs no clipping.
    #[inline]
    pub fn inside(&self, v: DVec3) -> bool {
        self.planes(v).iter().all(|&d| d >= 0.0)
    }

    /// Projects and snaps a view-space point with `z >= znear`.
    #[inline]
    pub fn snap(&self, v: DVec3) -> Pt {
        let iz = self.focal / v.z;
        let x = (self.cx + v.x * iz) * ONE as f64;
        let y = (self.cy - v.y * iz) * ONE as f64;
        // `as` saturates; the clamp only guards rounding at the band's edge.
        [(x as i64).clamp(-LIMIT, LIMIT), (y as i64).clamp(-LIMIT, LIMIT)]
    }

    /// Clips a view-space triangle to the kept volume and snaps the
    /// resulting convex polygon into `out`; returns its vertex count (0 when
    /// nothing is left).
    pub fn clip_snap(&self, tri: [DVec3; 3], out: &mut [Pt; MAX_CLIPPED]) -> usize {
        let mut a = [DVec3::ZERO; MAX_CLIPPED];
        let mut b = [DVec3::ZERO; MAX_CLIPPED];
        a[..3].copy_from_slice(&tri);
        let mut n = 3;
        for plane in 0..6 {
            let mut m = 0;
            for i in 0..n {
                let (p, q) = (a[i], a[(i + 1) % n]);
                let (dp, dq) = (self.plane(p, plane), self.plane(q, plane));
                if dp >= 0.0 {
                    b[m] = p;
                    m += 1;
                }
                if (dp >= 0.0) != (dq >= 0.0) {
                    // Cut from the kept end, so two triangles sharing this
                    // edge cut it at the very same point.
                    let (i_, o, di, d_o) = if dp >= 0.0 { (p, q, dp, dq) } else { (q, p, dq, dp) };
                    b[m] = i_ + (o - i_) * (di / (di - d_o));
                    m += 1;
                }
            }
            std::mem::swap(&mut a, &mut b);
            n = m;
            if n < 3 {
                return 0;
            }
        }
        for (o, v) in out.iter_mut().zip(&a[..n]) {
            *o = self.snap(*v);
        }
        n
    }
}

/// Per-vertex state in [`Projector`].
#[derive(Clone, Copy, PartialEq, Eq)]
enum Vertex {
    /// NaN or infinite: its triangles are skipped.
    Bad,
    /// Outside the kept volume: its triangles are clipped.
    Clip,
    /// Inside: its snapped position is ready.
    Kept,
}

/// Reusable buffers for [`Projector::triangles`].
#[derive(Default)]
pub(crate) struct Projector {
    view: Vec<DVec3>,
    state: Vec<Vertex>,
    snapped: Vec<Pt>,
}

impl Projector {
    /// Calls `f` with every snapped triangle of the mesh `positions` /
    /// `triangles` placed by `to_view`: triangles inside the kept volume as
    /// they are, others clipped and fanned. Triangles with a non-finite
    /// vertex or an index out of range are skipped.
    pub fn triangles(
        &mut self,
        frame: &Frame,
        to_view: &DAffine3,
        positions: &[Vec3],
        triangles: impl Iterator<Item = [u32; 3]>,
        f: impl FnMut([Pt; 3]),
    ) {
        self.triangles_culled(frame, to_view, positions, triangles, false, f);
    }

    /// [`Projector::triangles`], except that with `closed` (the triangles
    /// form a closed surface: every edge `a → b` as often as `b → a`) and
    /// no vertex needing clipping, only the triangles wound positively on
    /// screen ([`super::raster::cross`] `> 0`) are passed on. They cover
    /// exactly the pixels all of them cover: the projection of a closed
    /// surface covers every point off its edges as many times positively as
    /// negatively, and the coverage rule decides each pixel center as such a
    /// point (nudged off every edge); degenerate triangles cover nothing.
    pub fn triangles_culled(
        &mut self,
        frame: &Frame,
        to_view: &DAffine3,
        positions: &[Vec3],
        triangles: impl Iterator<Item = [u32; 3]>,
        closed: bool,
        f: impl FnMut([Pt; 3]),
    ) {
        let kept = self.project(frame, to_view, positions);
        self.projected_triangles(frame, triangles, closed && kept, f);
    }

    /// Places and snaps `positions` (kept for [`Projector::snapped`] and
    /// [`Projector::projected_triangles`]); whether none needs clipping (and
    /// none is bad).
    pub fn project(&mut self, frame: &Frame, to_view: &DAffine3, positions: &[Vec3]) -> bool {
        let n = positions.len();
        self.view.resize(n, DVec3::ZERO);
        self.state.resize(n, Vertex::Bad);
        self.snapped.resize(n, [0; 2]);
        let mut kept = true;
        let out = self.view.iter_mut().zip(&mut self.state).zip(&mut self.snapped);
        for (((view, state), snapped), &p) in out.zip(positions) {
            let v = to_view.transform_point3(p.as_dvec3());
            // Inside implies finite (every plane test fails on NaN or ±∞).
            (*state, *snapped) = if frame.inside(v) {
                (Vertex::Kept, frame.snap(v))
            } else {
                kept = false;
                (if v.is_finite() { Vertex::Clip } else { Vertex::Bad }, [0; 2])
            };
            *view = v;
        }
        kept
    }

    /// The snapped positions of the last [`Projector::project`] (meaningful
    /// where it returned `true`).
    pub fn snapped(&self) -> &[Pt] {
        &self.snapped
    }

    /// The triangles of the last [`Projector::project`] (see
    /// [`Projector::triangles_culled`]; `cull` only when the mesh is closed
    /// and nothing needed clipping).
    pub fn projected_triangles(
        &mut self,
        frame: &Frame,
        triangles: impl Iterator<Item = [u32; 3]>,
        cull: bool,
        mut f: impl FnMut([Pt; 3]),
    ) {
        let mut poly = [[0i64; 2]; MAX_CLIPPED];
        for t in triangles {
            let [a, b, c] = t.map(|i| i as usize);
            let n = self.state.len();
            if a >= n || b >= n || c >= n {
                continue;
            }
            let s = [self.state[a], self.state[b], self.state[c]];
            if s.contains(&Vertex::Bad) {
                continue;
            }
            if s == [Vertex::Kept; 3] {
                let t = [self.snapped[a], self.snapped[b], self.snapped[c]];
                if !cull || cross(t[0], t[1], t[2]) > 0 {
                    f(t);
                }
                continue;
            }
            let k = frame.clip_snap([self.view[a], self.view[b], self.view[c]], &mut poly);
            for i in 1..k.saturating_sub(1) {
                f([poly[0], poly[i], poly[i + 1]]);
            }
        }
    }
}

/// Unit meshes of built-in primitives, tessellated once per kind and kept
/// (at most [`Shapes::CAP`] kinds; the oldest is replaced beyond that).
pub(crate) struct Shapes {
    tess: Tessellation,
    /// Each kind's unit mesh and, when it is a closed surface, its edges.
    meshes: Vec<(Primitive, Mesh, Option<EdgeTable>)>,
    next: usize,
}

impl Shapes {
    const CAP: usize = 64;

    pub fn new(tess: Tessellation) -> Shapes {
        Shapes { tess, meshes: Vec::new(), next: 0 }
    }

    pub fn tessellation(&self) -> Tessellation {
        self.tess
    }

    /// The unit mesh of a built-in primitive (empty for [`Primitive::Mesh`]).
    #[cfg(any(test, feature = "test-support"))]
    pub fn get(&mut self, p: Primitive) -> &Mesh {
        self.get_with_edges(p).0
    }

    /// The unit mesh of a built-in primitive and, when it is a closed
    /// surface (see [`super::raster::is_closed`]), its edge table.
    pub fn get_with_edges(&mut self, p: Primitive) -> (&Mesh, Option<&EdgeTable>) {
        let make = |p| {
            let mesh = unit_mesh(p, self.tess);
            let table = is_closed(&mesh).then(|| EdgeTable::new(&mesh));
            (p, mesh, table)
        };
        let i = match self.meshes.iter().position(|(q, ..)| *q == p) {
            Some(i) => i,
            None if self.meshes.len() < Self::CAP => {
                self.meshes.push(make(p));
                self.meshes.len() - 1
            }
            None => {
                let i = self.next;
                self.next = (self.next + 1) % Self::CAP;
                self.meshes[i] = make(p);
                i
            }
        };
        let (_, mesh, table) = &self.meshes[i];
        (mesh, table.as_ref())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use genform_core::camera::Camera;

    fn frame() -> Frame {
        let cam = Camera { fov_deg: 60.0, phi: 0.0, theta: 0.0, radius: 5.0, look_at: Vec3::ZERO };
        Frame::new(&cam.projection(64, 48))
    }

    #[test]
    fn clipping_keeps_what_is_in_front() {
        let f = frame();
        let mut out = [[0; 2]; MAX_CLIPPED];
        // Straddling the near plane: a quad remains, every point projectable.
        let n =
            f.clip_snap([DVec3::new(0.0, 0.0, -1.0), DVec3::new(1.0, 0.0, 2.0), DVec3::new(0.0, 1.0, 2.0)], &mut out);
        assert_eq!(n, 4);
        // Entirely behind the eye: nothing.
        let n =
            f.clip_snap([DVec3::new(0.0, 0.0, -1.0), DVec3::new(1.0, 0.0, -2.0), DVec3::new(0.0, 1.0, -2.0)], &mut out);
        assert_eq!(n, 0);
        // Inside: the snapped vertices themselves.
        let tri = [DVec3::new(0.0, 0.0, 3.0), DVec3::new(1.0, 0.0, 3.0), DVec3::new(0.0, 1.0, 3.0)];
        assert_eq!(f.clip_snap(tri, &mut out), 3);
        assert_eq!(&out[..3], &tri.map(|v| f.snap(v)));
        // The view center lands at the image center.
        assert_eq!(f.snap(DVec3::new(0.0, 0.0, 3.0)), [32 * ONE, 24 * ONE]);
    }

    #[test]
    fn shapes_cache_is_bounded() {
        let mut s = Shapes::new(Tessellation::default());
        for i in 0..200 {
            let m = s.get(Primitive::Frustum { top: i as f32 / 200.0 });
            assert!(!m.triangles.is_empty());
        }
        assert_eq!(s.meshes.len(), Shapes::CAP);
    }
}
