//! The signed area and bounding box of a planar polygon: the measures the
//! straight skeleton shares with the rest of the geometry, kept apart so
//! that the skeleton does not depend on the roofs built from it.

use glam::DVec2;

/// Twice the signed area (positive when counter-clockwise).
pub(crate) fn area2(p: &[DVec2]) -> f64 {
    let n = p.len();
    (0..n).map(|i| p[i].perp_dot(p[(i + 1) % n])).sum()
}

/// Lower and upper corners of the bounding box (`None` when empty).
pub(crate) fn bbox(p: &[DVec2]) -> Option<(DVec2, DVec2)> {
    let first = *p.first()?;
    Some(p.iter().fold((first, first), |(lo, hi), q| (lo.min(*q), hi.max(*q))))
}
