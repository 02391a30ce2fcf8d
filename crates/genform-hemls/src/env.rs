//! The growth environment: attractors and repellers, gravity, boundaries.
//!
//! CONTRACT (filled in by the environment work): the growth engine calls
//! [`Environment::displacement`] for every vertex each step and adds it to
//! the growth move, then [`Environment::constrain`] on the whole move.

use glam::DVec3;

/// Everything around a growing surface. The default is empty: no
/// displacement, no boundary.
#[derive(Clone, Debug, Default)]
pub struct Environment {}

impl Environment {
    /// Whether the environment can move or stop anything (lets the engine
    /// skip the per-vertex calls).
    pub fn is_empty(&self) -> bool {
        true
    }

    /// The environmental displacement `f(p)` of a vertex at `p` in one step:
    /// the sum over charges and gravity.
    pub fn displacement(&self, _p: DVec3) -> DVec3 {
        DVec3::ZERO
    }

    /// Where a vertex moving from `from` to `to` ends, after the boundaries'
    /// slide and stop behaviours.
    pub fn constrain(&self, _from: DVec3, to: DVec3) -> DVec3 {
        to
    }
}
