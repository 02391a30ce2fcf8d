//! `setback` on a concave polygon: each selected edge's strip is the
//! polygon within its convex band (see [`cut`]), strips taken in order so
//! they do not overlap, the remainder what no strip took. Polygon booleans
//! come from `i_overlay` (the engine `geo` uses): cutting a concave
//! polygon with half-planes alone let a strip take in a far arm of the
//! polygon and left the remainder convex.

use glam::DVec2;
use i_overlay::core::fill_rule::FillRule;
use i_overlay::core::overlay_rule::OverlayRule;
use i_overlay::float::single::SingleFloatOverlay;

/// The outer outlines of `shapes`, counter-clockwise (holes dropped: a
/// piece of a setback is a polygon scope, which has none), leaving out
/// slivers under `least` in area: where two strips meet along a line the
/// overlay's rounding leaves needles of 10⁻⁸ m² that, kept, multiplied
/// with every later strip (21,492 pieces on one real plot).
fn outlines(shapes: Vec<Vec<Vec<[f64; 2]>>>, least: f64) -> Vec<Vec<DVec2>> {
    shapes
        .into_iter()
        .filter_map(|s| s.into_iter().next())
        .filter_map(|c| {
            let mut p: Vec<DVec2> = c.into_iter().map(DVec2::from).collect();
            let a = crate::polygon::area2(&p) / 2.0;
            if a < 0.0 {
                p.reverse();
            }
            (p.len() >= 3 && a.abs() >= least).then_some(p)
        })
        .collect()
}

/// The strips of `poly` (counter-clockwise) in the convex `bands` (one per
/// selected edge, in order: each strip is what its band holds of the
/// polygon and no earlier strip, nor `exclude`, took), and the remainder:
/// the polygon less every strip (and `exclude`). Each may come out in
/// several pieces. (`offset(d > 0)` cuts its border from the grown outline
/// with the original polygon excluded.)
pub(crate) fn cut(
    poly: &[DVec2],
    bands: &[Vec<DVec2>],
    exclude: Option<&[DVec2]>,
) -> (Vec<Vec<Vec<DVec2>>>, Vec<Vec<DVec2>>) {
    let subject: Vec<[f64; 2]> = poly.iter().map(|p| p.to_array()).collect();
    let least = crate::polygon::bbox(poly).map_or(0.0, |(lo, hi)| 1e-7 * (hi - lo).length_squared());
    let mut taken: Vec<Vec<[f64; 2]>> = exclude.map(|e| e.iter().map(|p| p.to_array()).collect()).into_iter().collect();
    let mut strips = Vec::with_capacity(bands.len());
    for band in bands {
        let band: Vec<[f64; 2]> = band.iter().map(|p| p.to_array()).collect();
        if band.len() < 3 {
            strips.push(Vec::new());
            continue;
        }
        let mut s = subject.overlay(&band, OverlayRule::Intersect, FillRule::NonZero);
        if !taken.is_empty() && !s.is_empty() {
            s = s.overlay(&taken, OverlayRule::Difference, FillRule::NonZero);
        }
        let pieces = outlines(s, least);
        taken.extend(pieces.iter().map(|p| p.iter().map(|q| q.to_array()).collect()));
        strips.push(pieces);
    }
    let rest = if taken.is_empty() {
        vec![poly.to_vec()]
    } else {
        outlines(subject.overlay(&taken, OverlayRule::Difference, FillRule::NonZero), least)
    };
    (strips, rest)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::polygon::area2;

    #[test]
    fn an_l_set_back_along_one_edge_keeps_its_far_arm() {
        // An L: the strip along the bottom edge (y = 0) 1 deep is 4 × 1;
        // the band is clipped to the edge's reach, so the upper arm stays
        // in the remainder, whole.
        let l: Vec<DVec2> = [(0.0, 0.0), (4.0, 0.0), (4.0, 1.5), (1.0, 1.5), (1.0, 4.0), (0.0, 4.0)]
            .iter()
            .map(|&(x, y)| DVec2::new(x, y))
            .collect();
        let band = vec![DVec2::new(-10.0, 0.0), DVec2::new(10.0, 0.0), DVec2::new(10.0, 1.0), DVec2::new(-10.0, 1.0)];
        let (strips, rest) = cut(&l, &[band], None);
        let a = |p: &Vec<DVec2>| area2(p) / 2.0;
        assert_eq!(strips[0].len(), 1);
        assert!((a(&strips[0][0]) - 4.0).abs() < 1e-6);
        assert_eq!(rest.len(), 1);
        assert!((a(&rest[0]) - (4.0 * 1.5 + 2.5 - 4.0)).abs() < 1e-6, "{}", a(&rest[0]));
    }
}
