//! Built-in primitives in their unit frame: the point-inside predicate both
//! voxelizers use, and the row-interval guesses of the fast one.
//!
//! Predicates are half-open along each unit axis (`−0.5 ≤ u < 0.5`, and
//! `−r ≤ u < r` across tapered shapes), the same convention as the mesh
//! crossing rule, so that two boxes sharing a face never both claim a voxel
//! centre lying exactly on it.

use glam::{DVec3, Vec3A};

/// The largest `top` factor used for frustums and tapered boxes; larger
/// (or infinite) values are clamped to it, NaN and negatives read as 0 (as
/// the tessellation does).
pub(crate) const MAX_TOP: f32 = 1.0e4;

/// A solid primitive, with the slope `k` of its radius `r(y) = 0.5 + k·(y + 0.5)`
/// for the tapered ones (`k = (top − 1)/2`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum Shape {
    Box,
    Tapered { k: f32 },
    Frustum { k: f32 },
    Sphere,
}

/// Reads a `top` factor the way the tessellation does, bounded.
pub(crate) fn slope_of_top(top: f32) -> f32 {
    let top = if top.is_nan() { 0.0 } else { top.clamp(0.0, MAX_TOP) };
    0.5 * (top - 1.0)
}

impl Shape {
    /// Whether the unit-frame point `u` is inside.
    #[inline]
    pub fn contains(self, u: Vec3A) -> bool {
        let y_ok = u.y >= -0.5 && u.y < 0.5;
        match self {
            Shape::Box => (u.cmpge(Vec3A::splat(-0.5)) & u.cmplt(Vec3A::splat(0.5))).all(),
            Shape::Tapered { k } => {
                let r = 0.5 + k * (u.y + 0.5);
                y_ok && u.x >= -r && u.x < r && u.z >= -r && u.z < r
            }
            Shape::Frustum { k } => {
                let r = 0.5 + k * (u.y + 0.5);
                y_ok && u.x * u.x + u.z * u.z < r * r
            }
            Shape::Sphere => u.x * u.x + u.y * u.y + u.z * u.z < 0.25,
        }
    }

    /// The radius slope (0 for boxes and spheres).
    pub fn slope(self) -> f32 {
        match self {
            Shape::Tapered { k } | Shape::Frustum { k } => k,
            _ => 0.0,
        }
    }

    /// Half the extent of the unit bounding box across x and z (y is ±0.5).
    pub fn half_width(self) -> f64 {
        0.5f64.max(0.5 + f64::from(self.slope()))
    }

    /// Volume in the unit frame.
    pub fn volume(self) -> f64 {
        let top = |k: f32| 2.0 * f64::from(k) + 1.0;
        let taper = |t: f64| (1.0 + t + t * t) / 3.0;
        match self {
            Shape::Box => 1.0,
            Shape::Tapered { k } => taper(top(k)),
            Shape::Frustum { k } => std::f64::consts::FRAC_PI_4 * taper(top(k)),
            Shape::Sphere => std::f64::consts::PI / 6.0,
        }
    }

    /// A superset of the parameters `t` where the line `a + b·t` lies in the
    /// shape grown by `delta` (so that rounding in [`Shape::contains`]
    /// cannot put a point outside it), or `None` when the line misses it.
    /// The result may be unbounded.
    pub fn guess(self, a: DVec3, b: DVec3, delta: f64) -> Option<(f64, f64)> {
        let h = 0.5 + delta;
        let mut iv = slab(a.y, b.y, -h, h)?;
        match self {
            Shape::Box => {
                iv = meet(iv, slab(a.x, b.x, -h, h)?)?;
                meet(iv, slab(a.z, b.z, -h, h)?)
            }
            Shape::Tapered { k } => {
                // ±u − k·u_y − (0.5 + 0.5k) − δ' ≤ 0 for u = u_x, u_z.
                let k = f64::from(k);
                let d = delta * (1.0 + k.abs());
                let c = 0.5 + 0.5 * k + d;
                for (s, (au, bu)) in [(1.0, (a.x, b.x)), (-1.0, (a.x, b.x)), (1.0, (a.z, b.z)), (-1.0, (a.z, b.z))] {
                    iv = meet(iv, half_line(s * au - k * a.y - c, s * bu - k * b.y)?)?;
                }
                Some(iv)
            }
            Shape::Frustum { k } => {
                let k = f64::from(k);
                // r(t) + δ' = r0 + r1·t
                let r0 = 0.5 + k * (a.y + 0.5) + delta * (1.0 + k.abs());
                let r1 = k * b.y;
                let qa = b.x * b.x + b.z * b.z - r1 * r1;
                let qb = 2.0 * (a.x * b.x + a.z * b.z - r0 * r1);
                let qc = a.x * a.x + a.z * a.z - r0 * r0;
                quadratic_hull(qa, qb, qc, iv)
            }
            Shape::Sphere => {
                let qa = b.length_squared();
                let qb = 2.0 * a.dot(b);
                let qc = a.length_squared() - h * h;
                quadratic_hull(qa, qb, qc, iv)
            }
        }
    }
}

/// `{t : lo ≤ a + b·t ≤ hi}`.
pub(crate) fn slab(a: f64, b: f64, lo: f64, hi: f64) -> Option<(f64, f64)> {
    if b == 0.0 {
        return (a >= lo && a <= hi).then_some((f64::NEG_INFINITY, f64::INFINITY));
    }
    let (t0, t1) = ((lo - a) / b, (hi - a) / b);
    Some(if t0 <= t1 { (t0, t1) } else { (t1, t0) })
}

/// `{t : a + b·t ≤ 0}`.
fn half_line(a: f64, b: f64) -> Option<(f64, f64)> {
    if b == 0.0 {
        (a <= 0.0).then_some((f64::NEG_INFINITY, f64::INFINITY))
    } else if b > 0.0 {
        Some((f64::NEG_INFINITY, -a / b))
    } else {
        Some((-a / b, f64::INFINITY))
    }
}

fn meet(x: (f64, f64), y: (f64, f64)) -> Option<(f64, f64)> {
    let r = (x.0.max(y.0), x.1.min(y.1));
    (r.0 <= r.1).then_some(r)
}

/// The hull of `{t ∈ within : qa·t² + qb·t + qc ≤ 0}`.
fn quadratic_hull(qa: f64, qb: f64, qc: f64, within: (f64, f64)) -> Option<(f64, f64)> {
    if qa == 0.0 {
        return meet(within, half_line(qc, qb)?);
    }
    let disc = qb * qb - 4.0 * qa * qc;
    if disc < 0.0 {
        // No roots: the quadratic keeps the sign of qa everywhere.
        return (qa < 0.0).then_some(within);
    }
    // Stable roots (no cancellation between qb and √disc).
    let q = -0.5 * (qb + disc.sqrt().copysign(qb));
    let (r1, r2) = if q == 0.0 { (0.0, 0.0) } else { (q / qa, qc / q) };
    let (r1, r2) = if r1 <= r2 { (r1, r2) } else { (r2, r1) };
    if qa > 0.0 {
        meet(within, (r1, r2))
    } else {
        let left = meet(within, (f64::NEG_INFINITY, r1));
        let right = meet(within, (r2, f64::INFINITY));
        match (left, right) {
            (Some(l), Some(r)) => Some((l.0, r.1)),
            (l, r) => l.or(r),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn predicates_are_half_open() {
        let p = |x, y, z| Vec3A::new(x, y, z);
        assert!(Shape::Box.contains(p(-0.5, -0.5, -0.5)));
        assert!(!Shape::Box.contains(p(0.5, 0.0, 0.0)));
        assert!(Shape::Box.contains(p(0.49, 0.49, 0.49)));
        let pyramid = Shape::Tapered { k: slope_of_top(0.0) };
        assert!(pyramid.contains(p(0.2, 0.0, -0.2)));
        assert!(!pyramid.contains(p(0.3, 0.0, 0.0)));
        assert!(!pyramid.contains(p(0.0, 0.5, 0.0)));
        let cyl = Shape::Frustum { k: slope_of_top(1.0) };
        assert!(cyl.contains(p(0.35, 0.4, 0.35)));
        assert!(!cyl.contains(p(0.36, 0.4, 0.36)));
        assert!(Shape::Sphere.contains(p(0.0, 0.0, -0.49)) && !Shape::Sphere.contains(p(0.3, 0.3, 0.3)));
    }

    #[test]
    fn volumes_and_tops() {
        assert_eq!(slope_of_top(f32::NAN), -0.5);
        assert_eq!(slope_of_top(f32::INFINITY), 0.5 * (MAX_TOP - 1.0));
        assert!((Shape::Tapered { k: slope_of_top(0.0) }.volume() - 1.0 / 3.0).abs() < 1e-12);
        assert!((Shape::Frustum { k: 0.0 }.volume() - std::f64::consts::FRAC_PI_4).abs() < 1e-12);
        assert_eq!(Shape::Frustum { k: slope_of_top(3.0) }.half_width(), 1.5);
    }

    #[test]
    fn guesses_cover_the_true_intervals() {
        let a = DVec3::new(-2.0, 0.1, 0.2);
        let b = DVec3::new(0.5, 0.0, 0.0);
        // Box: u_x ∈ [−0.5, 0.5] ⇔ t ∈ [3, 5].
        assert_eq!(Shape::Box.guess(a, b, 0.0), Some((3.0, 5.0)));
        // Sphere: u_x² ≤ 0.25 − 0.05 ⇔ |u_x| ≤ 0.447…
        let (t0, t1) = Shape::Sphere.guess(a, b, 0.0).unwrap();
        assert!((t0 - (4.0 - 0.2f64.sqrt() * 2.0)).abs() < 1e-12 && (t1 - (4.0 + 0.2f64.sqrt() * 2.0)).abs() < 1e-12);
        assert_eq!(Shape::Box.guess(a, DVec3::ZERO, 0.0), None);
        // A line along the axis of a cone: inside for u_y ∈ [−0.5, 0.5].
        let cone = Shape::Frustum { k: slope_of_top(0.0) };
        let (t0, t1) = cone.guess(DVec3::ZERO, DVec3::Y, 0.0).unwrap();
        assert!((t0 + 0.5).abs() < 1e-12 && (t1 - 0.5).abs() < 1e-12);
        // A line crossing a cone's side twice, inside between.
        let (t0, t1) = cone.guess(DVec3::new(0.0, 0.0, 0.0), DVec3::X, 0.0).unwrap();
        assert!((t0 + 0.25).abs() < 1e-12 && (t1 - 0.25).abs() < 1e-12);
    }
}
