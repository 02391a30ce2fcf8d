//! Boundaries: spheres, boxes, planes and triangle meshes that a growing
//! surface may not cross (slide, stop) or is penalised for crossing (soft).
//!
//! Every shape has a *front* side: the outside of a closed shape, the side
//! a plane's normal points to, the side an open mesh's triangle normals
//! point to. `keep = outside` (the default) allows the front side (an
//! obstacle, or a wall facing its normal); `keep = inside` allows the back
//! side (an enclosure). The boundary surface itself counts as allowed.

use super::mesh::MeshBoundary;
use glam::DVec3;
use std::sync::Arc;

/// What a boundary does to a vertex that would cross it.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Behaviour {
    /// Growth is cut at the boundary and the rest of the move slides along
    /// it (Genr8's default wall).
    #[default]
    Slide,
    /// The vertex stops dead at the boundary.
    Stop,
    /// Nothing is stopped; vertices on the wrong side are counted by the
    /// soft-boundary fitness criterion.
    Soft,
}

impl Behaviour {
    /// `slide`, `stop` or `soft` (the env-file spelling).
    pub fn name(self) -> &'static str {
        match self {
            Behaviour::Slide => "slide",
            Behaviour::Stop => "stop",
            Behaviour::Soft => "soft",
        }
    }
}

/// Which side of a boundary is allowed.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Keep {
    /// The front side: outside a closed shape (an obstacle), the normal's
    /// side of a plane or open mesh.
    #[default]
    Outside,
    /// The back side: inside a closed shape (an enclosure), behind a plane
    /// or open mesh.
    Inside,
}

impl Keep {
    /// `outside` or `inside` (the env-file spelling).
    pub fn name(self) -> &'static str {
        match self {
            Keep::Outside => "outside",
            Keep::Inside => "inside",
        }
    }
}

/// The geometry of a boundary.
#[derive(Clone, Debug)]
pub enum Shape {
    /// A sphere.
    Sphere {
        /// Centre.
        center: DVec3,
        /// Radius (positive).
        radius: f64,
    },
    /// An axis-aligned box.
    Box {
        /// Lowest corner.
        min: DVec3,
        /// Highest corner.
        max: DVec3,
    },
    /// An infinite plane; its front side is the one `normal` points to.
    Plane {
        /// A point on the plane.
        point: DVec3,
        /// Unit normal.
        normal: DVec3,
    },
    /// A triangle mesh (closed or open), prepared once.
    Mesh(Arc<MeshBoundary>),
}

/// A boundary: a shape, what it does, and which side is allowed.
#[derive(Clone, Debug)]
pub struct Boundary {
    /// The geometry.
    pub shape: Shape,
    /// Slide (default), stop or soft.
    pub behaviour: Behaviour,
    /// Which side is allowed (default: outside).
    pub keep: Keep,
}

/// A crossing found on a segment: parameter in `[0, 1]` and the unit normal
/// of the boundary there (either orientation).
#[derive(Clone, Copy, Debug)]
pub(crate) struct Crossing {
    pub t: f64,
    pub normal: DVec3,
}

impl Boundary {
    /// A sliding obstacle sphere (radius made non-negative).
    pub fn sphere(center: DVec3, radius: f64) -> Self {
        Self::of(Shape::Sphere { center, radius: radius.abs() })
    }

    /// A sliding obstacle box between two corners (in any order).
    pub fn cuboid(a: DVec3, b: DVec3) -> Self {
        Self::of(Shape::Box { min: a.min(b), max: a.max(b) })
    }

    /// A sliding plane through `point` whose `normal` side is allowed;
    /// `None` for a zero or non-finite normal.
    pub fn plane(point: DVec3, normal: DVec3) -> Option<Self> {
        let normal = normal.try_normalize()?;
        Some(Self::of(Shape::Plane { point, normal }))
    }

    /// A sliding boundary from a triangle mesh (see [`MeshBoundary::new`]
    /// for the errors).
    pub fn mesh(mesh: &genform_core::Mesh) -> Result<Self, String> {
        Ok(Self::of(Shape::Mesh(Arc::new(MeshBoundary::new(mesh)?))))
    }

    fn of(shape: Shape) -> Self {
        Boundary { shape, behaviour: Behaviour::Slide, keep: Keep::Outside }
    }

    /// The same boundary with another behaviour.
    pub fn with_behaviour(mut self, behaviour: Behaviour) -> Self {
        self.behaviour = behaviour;
        self
    }

    /// The same boundary allowing the other side.
    pub fn with_keep(mut self, keep: Keep) -> Self {
        self.keep = keep;
        self
    }

    /// Whether `p` lies strictly on the side this boundary does not allow.
    /// For an open mesh, a point whose nearest mesh point lies on the mesh's
    /// rim is beside the sheet, not behind it: allowed.
    pub fn is_wrong_side(&self, p: DVec3) -> bool {
        let obstacle = self.keep == Keep::Outside;
        match &self.shape {
            Shape::Sphere { center, radius } => {
                let d2 = (p - *center).length_squared();
                if obstacle { d2 < radius * radius } else { d2 > radius * radius }
            }
            Shape::Box { min, max } => {
                let inside_open = p.cmpgt(*min).all() && p.cmplt(*max).all();
                let inside_closed = p.cmpge(*min).all() && p.cmple(*max).all();
                if obstacle { inside_open } else { !inside_closed }
            }
            Shape::Plane { point, normal } => {
                let s = (p - *point).dot(*normal);
                if obstacle { s < 0.0 } else { s > 0.0 }
            }
            Shape::Mesh(m) if m.is_closed() => m.contains(p) == obstacle,
            Shape::Mesh(m) => {
                let near = m.nearest(p);
                if near.on_border {
                    return false;
                }
                let s = (p - near.point).dot(near.normal);
                if obstacle { s < 0.0 } else { s > 0.0 }
            }
        }
    }

    /// The first point of the segment `from + t·d`, `t ∈ [0, 1]`, where it
    /// crosses from the allowed into the forbidden side. Segments that start
    /// on the forbidden side are only stopped where they would cross in
    /// again.
    pub(crate) fn crossing(&self, from: DVec3, d: DVec3) -> Option<Crossing> {
        let obstacle = self.keep == Keep::Outside;
        match &self.shape {
            Shape::Sphere { center, radius } => sphere_crossing(from - *center, d, *radius, obstacle),
            Shape::Box { min, max } => box_crossing(from, d, *min, *max, obstacle),
            Shape::Plane { point, normal } => {
                let n = if obstacle { *normal } else { -*normal };
                let s0 = (from - *point).dot(n);
                let ds = d.dot(n);
                // Allowed at the start (s ≥ 0) and moving to the back.
                if s0 < 0.0 || ds >= 0.0 || s0 + ds >= 0.0 {
                    return None;
                }
                let t = (s0 / -ds).clamp(0.0, 1.0);
                Some(Crossing { t, normal: n })
            }
            Shape::Mesh(m) => {
                let sign = if obstacle { -1.0 } else { 1.0 };
                m.first_crossing(from, d, sign).map(|h| Crossing { t: h.t, normal: h.normal })
            }
        }
    }

    /// The nearest allowed point to `p`, `skin` clear of the boundary when
    /// `p` is on the wrong side; `p` itself otherwise.
    pub(crate) fn settle(&self, p: DVec3, skin: f64) -> DVec3 {
        if !self.is_wrong_side(p) {
            return p;
        }
        let obstacle = self.keep == Keep::Outside;
        match &self.shape {
            Shape::Sphere { center, radius } => {
                // A point exactly at the centre has no nearest direction:
                // it leaves upwards (+z).
                let dir = (p - *center).try_normalize().unwrap_or(DVec3::Z);
                if obstacle { *center + dir * (radius + skin) } else { *center + dir * (radius - skin).max(0.0) }
            }
            Shape::Box { min, max } => {
                if obstacle {
                    // Out through the nearest face (ties: −x, +x, −y, +y, −z, +z).
                    let mut best = (f64::INFINITY, 0usize, 0.0);
                    for k in 0..3 {
                        for (dist, to) in [(p[k] - min[k], min[k] - skin), (max[k] - p[k], max[k] + skin)] {
                            if dist < best.0 {
                                best = (dist, k, to);
                            }
                        }
                    }
                    let mut q = p;
                    q[best.1] = best.2;
                    q
                } else {
                    let mut q = p;
                    for k in 0..3 {
                        let (lo, hi) = (min[k] + skin, max[k] - skin);
                        q[k] = if lo <= hi { p[k].clamp(lo, hi) } else { 0.5 * (min[k] + max[k]) };
                    }
                    q
                }
            }
            Shape::Plane { point, normal } => {
                let n = if obstacle { *normal } else { -*normal };
                p + n * (skin - (p - *point).dot(n))
            }
            Shape::Mesh(m) => {
                let near = m.nearest(p);
                let n = if obstacle { near.normal } else { -near.normal };
                near.point + n * skin
            }
        }
    }
}

/// First crossing of `m + t·d` (relative to the centre) with the sphere
/// into the forbidden side: inwards for an obstacle, outwards for an
/// enclosure. Tangent lines never cross.
fn sphere_crossing(m: DVec3, d: DVec3, r: f64, obstacle: bool) -> Option<Crossing> {
    let a = d.length_squared();
    if a == 0.0 {
        return None;
    }
    let h = m.dot(d);
    let c = m.length_squared() - r * r;
    let disc = h * h - a * c;
    if disc <= 0.0 || !disc.is_finite() {
        return None;
    }
    // The cancellation-free pair of roots.
    let q = -(h + h.signum() * disc.sqrt());
    let (mut t0, mut t1) = (q / a, if q != 0.0 { c / q } else { -q / a });
    if t0 > t1 {
        std::mem::swap(&mut t0, &mut t1);
    }
    let t = if obstacle {
        // Entering; a start inside (t0 < 0 < t1) is not a crossing.
        t0
    } else {
        t1
    };
    if !(0.0..=1.0).contains(&t) {
        return None;
    }
    // An obstacle segment starting inside (c < 0) never enters.
    if obstacle && c < 0.0 {
        return None;
    }
    let normal = (m + d * t).normalize_or(DVec3::Z);
    Some(Crossing { t, normal })
}

/// First crossing of `from + t·d` with the box into the forbidden side:
/// entering the open interior for an obstacle, leaving it for an enclosure.
fn box_crossing(from: DVec3, d: DVec3, min: DVec3, max: DVec3, obstacle: bool) -> Option<Crossing> {
    let (mut t_in, mut t_out) = (f64::NEG_INFINITY, f64::INFINITY);
    let (mut axis_in, mut axis_out) = (0usize, 0usize);
    for k in 0..3 {
        if d[k] == 0.0 {
            // Parallel to this slab: inside it throughout or never.
            if from[k] <= min[k] || from[k] >= max[k] {
                return None;
            }
            continue;
        }
        let (mut a, mut b) = ((min[k] - from[k]) / d[k], (max[k] - from[k]) / d[k]);
        if a > b {
            std::mem::swap(&mut a, &mut b);
        }
        if a > t_in {
            t_in = a;
            axis_in = k;
        }
        if b < t_out {
            t_out = b;
            axis_out = k;
        }
    }
    if t_in >= t_out {
        return None;
    }
    let (t, axis) = if obstacle { (t_in, axis_in) } else { (t_out, axis_out) };
    if !(0.0..=1.0).contains(&t) || !t.is_finite() {
        return None;
    }
    let mut normal = DVec3::ZERO;
    normal[axis] = 1.0;
    Some(Crossing { t, normal })
}
