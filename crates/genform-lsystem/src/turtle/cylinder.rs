//! Generalized cylinders (`@Gc` … `@Ge`): the rings of one branch swept
//! into a single mesh with smooth joints.

use genform_core::scene::{Mesh, TagId};
use glam::{DVec3, Vec3};

/// Segments around each ring.
pub(super) const RING_SEGMENTS: u32 = 12;

/// One cross-section: a circle of radius `radius` around `center`, in the
/// plane whose normal is `normal`.
#[derive(Clone, Copy, Debug)]
struct Ring {
    center: DVec3,
    normal: DVec3,
    radius: f64,
}

/// A cylinder being traced.
#[derive(Clone, Debug)]
pub(super) struct Cylinder {
    rings: Vec<Ring>,
    /// The turtle's up vector at `@Gc`: where the first ring's vertex 0
    /// lies (later rings follow by parallel transport, so the mesh does not
    /// twist).
    up: DVec3,
    /// The colour at `@Gc`.
    pub(super) tag: TagId,
}

impl Cylinder {
    /// A cylinder starting with a ring at `center` (heading `h`, up `u`).
    pub(super) fn start(center: DVec3, h: DVec3, u: DVec3, radius: f64, tag: TagId) -> Cylinder {
        Cylinder { rings: vec![Ring { center, normal: h, radius }], up: u, tag }
    }

    /// Adds the ring at the end of a segment drawn along `h`. The ring
    /// before it gets the bisecting plane of the headings in and out (the
    /// first ring the plane of the first segment), so the joint is smooth.
    pub(super) fn add(&mut self, center: DVec3, h: DVec3, radius: f64) {
        let first = self.rings.len() == 1;
        if let Some(last) = self.rings.last_mut() {
            let bisector = (last.normal + h).normalize_or_zero();
            last.normal = if first || bisector == DVec3::ZERO { h } else { bisector };
        }
        self.rings.push(Ring { center, normal: h, radius });
    }

    /// The swept mesh: `RING_SEGMENTS` vertices per ring, quads between
    /// consecutive rings split in two, and both ends capped (fans over the
    /// ring vertices, so the vertex count stays rings × segments). `None`
    /// for fewer than two rings.
    pub(super) fn mesh(&self) -> Option<Mesh> {
        if self.rings.len() < 2 {
            return None;
        }
        let n = RING_SEGMENTS;
        let mut positions = Vec::with_capacity(self.rings.len() * n as usize);
        let mut reference = self.up;
        for ring in &self.rings {
            let nrm = ring.normal;
            // Parallel transport: the previous reference projected into
            // this ring's plane; any perpendicular when that degenerates.
            let mut e1 = (reference - nrm * reference.dot(nrm)).normalize_or_zero();
            if e1 == DVec3::ZERO {
                e1 = nrm.any_orthonormal_vector();
            }
            reference = e1;
            // (e1, normal, e2) right-handed, like (U, H, L) for the frusta:
            // triangles below then wind counter-clockwise seen from outside.
            let e2 = e1.cross(nrm);
            for i in 0..n {
                let (s, c) = (std::f64::consts::TAU * f64::from(i) / f64::from(n)).sin_cos();
                let p = ring.center + (e1 * c + e2 * s) * ring.radius;
                positions.push(Vec3::new(p.x as f32, p.y as f32, p.z as f32));
            }
        }
        let mut triangles = Vec::new();
        for k in 0..self.rings.len() as u32 - 1 {
            let (b, t) = (k * n, (k + 1) * n);
            for i in 0..n {
                let j = (i + 1) % n;
                triangles.push([b + i, t + i, t + j]);
                triangles.push([b + i, t + j, b + j]);
            }
        }
        let top = (self.rings.len() as u32 - 1) * n;
        for i in 1..n - 1 {
            triangles.push([0, i, i + 1]);
            triangles.push([top, top + i + 1, top + i]);
        }
        Some(Mesh { name: "generalized cylinder".into(), positions, triangles })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Signed volume (positive when every triangle winds counter-clockwise
    /// seen from outside).
    fn volume(m: &Mesh) -> f64 {
        m.triangles
            .iter()
            .map(|t| {
                let [a, b, c] = t.map(|i| m.positions[i as usize].as_dvec3());
                a.dot(b.cross(c)) / 6.0
            })
            .sum()
    }

    #[test]
    fn a_straight_cylinder_is_closed_and_faces_outwards() {
        let mut c = Cylinder::start(DVec3::ZERO, DVec3::Y, DVec3::X, 0.5, 0);
        c.add(DVec3::Y * 2.0, DVec3::Y, 0.5);
        let m = c.mesh().unwrap();
        // A 12-gon prism of circumradius 0.5 and height 2.
        let n = f64::from(RING_SEGMENTS);
        let area = 0.5 * n * 0.25 * (std::f64::consts::TAU / n).sin();
        assert!((volume(&m) - 2.0 * area).abs() < 1e-5, "{}", volume(&m));
        assert_eq!(m.triangles.len() as u32, 2 * RING_SEGMENTS + 2 * (RING_SEGMENTS - 2));
    }

    #[test]
    fn one_ring_is_no_mesh() {
        assert!(Cylinder::start(DVec3::ZERO, DVec3::Y, DVec3::X, 0.5, 0).mesh().is_none());
    }
}
