//! The growth environment: attractors and repellers, gravity, boundaries.
//!
//! CONTRACT: the growth engine calls [`Environment::displacement`] for
//! every vertex each step and adds it to the growth move, then
//! [`Environment::constrain`] on the whole move. Vertices that rewriting
//! places on a forbidden side (a chord's midpoint inside a sphere) go
//! through [`Environment::settle`]; [`Environment::is_outside_soft`] counts
//! for the soft-boundary fitness criterion.
//!
//! - [`charges`]: the attractor / repeller law and gravity;
//! - [`boundary`]: sphere, box, plane and mesh boundaries, their sides and
//!   behaviours;
//! - [`mesh`]: triangle-mesh boundaries with a BVH;
//! - [`guides`]: preview geometry for all of it.

pub mod boundary;
pub mod charges;
pub mod guides;
pub mod mesh;

pub use boundary::{Behaviour, Boundary, Keep, Shape};
pub use charges::{Axis, Charge, ChargeKind, Gravity};
pub use mesh::MeshBoundary;

use glam::DVec3;

/// How far (relative to `1 + |p|`) a vertex that a slide or stop boundary
/// holds back keeps clear of it, so that it stays strictly on the allowed
/// side. Far above the rounding of the intersection tests (about 1e-8
/// relative for a grazing sphere hit), far below anything visible.
pub const SKIN: f64 = 1e-6;

/// The clearance [`SKIN`] at `p`.
pub fn skin(p: DVec3) -> f64 {
    SKIN * (1.0 + p.length())
}

/// Everything around a growing surface. The default is empty: no
/// displacement, no boundary.
#[derive(Clone, Debug)]
pub struct Environment {
    /// Attractors and repellers, summed in this order.
    pub charges: Vec<Charge>,
    /// Uniform gravity, added after the charges.
    pub gravity: Option<Gravity>,
    /// Boundaries; ties between crossings go to the earlier one.
    pub boundaries: Vec<Boundary>,
    /// The smallest distance the charge law uses (it is singular at the
    /// charge): a charge displaces by at most `c / min_distance^e`.
    pub min_distance: f64,
}

impl Default for Environment {
    fn default() -> Self {
        Environment { charges: Vec::new(), gravity: None, boundaries: Vec::new(), min_distance: Self::MIN_DISTANCE }
    }
}

impl Environment {
    /// Default [`Environment::min_distance`].
    pub const MIN_DISTANCE: f64 = 1e-3;

    /// An empty environment.
    pub fn new() -> Self {
        Self::default()
    }

    /// Adds an attractor or repeller.
    pub fn with_charge(mut self, charge: Charge) -> Self {
        self.charges.push(charge);
        self
    }

    /// Sets gravity.
    pub fn with_gravity(mut self, gravity: Gravity) -> Self {
        self.gravity = Some(gravity);
        self
    }

    /// Adds a boundary.
    pub fn with_boundary(mut self, boundary: Boundary) -> Self {
        self.boundaries.push(boundary);
        self
    }

    /// Whether the environment can move, stop or count anything (lets the
    /// engine skip the per-vertex calls). Soft boundaries make it non-empty.
    pub fn is_empty(&self) -> bool {
        self.charges.is_empty() && self.gravity.is_none_or(|g| g.magnitude == 0.0) && self.boundaries.is_empty()
    }

    /// Whether any boundary slides or stops (only then does
    /// [`Environment::constrain`] or [`Environment::settle`] change anything).
    pub fn has_hard_boundaries(&self) -> bool {
        self.boundaries.iter().any(|b| b.behaviour != Behaviour::Soft)
    }

    /// Whether any boundary is soft.
    pub fn has_soft_boundaries(&self) -> bool {
        self.boundaries.iter().any(|b| b.behaviour == Behaviour::Soft)
    }

    /// The environmental displacement `f(p)` of a vertex at `p` in one step:
    /// the sum over charges (in order), then gravity.
    pub fn displacement(&self, p: DVec3) -> DVec3 {
        let mut f = DVec3::ZERO;
        for c in &self.charges {
            f += c.displacement(p, self.min_distance);
        }
        if let Some(g) = self.gravity {
            f += g.vector();
        }
        f
    }

    /// Where a vertex moving from `from` to `to` ends, after the boundaries'
    /// slide and stop behaviours (soft boundaries change nothing).
    ///
    /// The segment is tested against every slide/stop boundary; at the
    /// earliest crossing into a forbidden side:
    /// - stop: the vertex stays at the hit point, backed off along the move
    ///   until it is [`skin`] clear of the boundary (at most back to `from`);
    /// - slide: from that point, the rest of the move projected onto the
    ///   boundary's tangent plane at the hit is tested once more, and if it
    ///   crosses again the vertex stops there.
    ///
    /// A vertex already on a forbidden side is only stopped where it would
    /// cross into one again; [`Environment::settle`] moves it out.
    pub fn constrain(&self, from: DVec3, to: DVec3) -> DVec3 {
        let d = to - from;
        if d == DVec3::ZERO || !d.is_finite() || !from.is_finite() {
            return to;
        }
        let Some((hit, behaviour)) = self.first_crossing(from, d) else { return to };
        let held = back_off(from, d, hit);
        if behaviour == Behaviour::Stop {
            return held;
        }
        let at = from + d * hit.t;
        let rest = to - at;
        let d2 = rest - hit.normal * rest.dot(hit.normal);
        if d2 == DVec3::ZERO || !d2.is_finite() {
            return held;
        }
        match self.first_crossing(held, d2) {
            None => held + d2,
            Some((hit2, _)) => back_off(held, d2, hit2),
        }
    }

    /// The earliest crossing of `from + t·d` into the forbidden side of a
    /// slide or stop boundary.
    fn first_crossing(&self, from: DVec3, d: DVec3) -> Option<(boundary::Crossing, Behaviour)> {
        let mut best: Option<(boundary::Crossing, Behaviour)> = None;
        for b in &self.boundaries {
            if b.behaviour == Behaviour::Soft {
                continue;
            }
            if let Some(c) = b.crossing(from, d)
                && best.is_none_or(|(old, _)| c.t < old.t)
            {
                best = Some((c, b.behaviour));
            }
        }
        best
    }

    /// Moves a point that lies on the forbidden side of a slide or stop
    /// boundary to the nearest allowed point ([`skin`] clear of it); other
    /// points are returned unchanged. Boundaries are visited once, in order
    /// (a point pushed out of one into another is pushed out of that one if
    /// it comes later).
    pub fn settle(&self, p: DVec3) -> DVec3 {
        if !p.is_finite() {
            return p;
        }
        let mut q = p;
        for b in &self.boundaries {
            // The side test first: it is cheap, and almost every point
            // passes it, so the clearance (a square root) is rarely needed.
            if b.behaviour != Behaviour::Soft && b.is_wrong_side(q) {
                q = b.settle(q, skin(q));
            }
        }
        q
    }

    /// Whether `p` lies on the forbidden side of any soft boundary.
    pub fn is_outside_soft(&self, p: DVec3) -> bool {
        self.boundaries.iter().any(|b| b.behaviour == Behaviour::Soft && b.is_wrong_side(p))
    }
}

/// The point of `from + t·d` at the crossing, backed off along the move far
/// enough to be [`skin`] clear of the boundary's tangent plane, but never
/// behind `from`.
fn back_off(from: DVec3, d: DVec3, hit: boundary::Crossing) -> DVec3 {
    let len = d.length();
    let travelled = hit.t * len;
    let along = d / len;
    let cos = along.dot(hit.normal).abs();
    let s = skin(from + d * hit.t);
    let back = if cos > 0.0 { (s / cos).min(travelled) } else { travelled };
    let kept = (travelled - back).max(0.0);
    if kept == 0.0 { from } else { from + along * kept }
}
