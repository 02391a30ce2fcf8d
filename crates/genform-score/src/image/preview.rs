//! The overlay picture of a silhouette on its target.

use super::coverage::Coverage;
use super::target::ImageTarget;

/// RGBA, rows from the top: see [`super::ImageScorer::silhouette`].
pub(crate) fn overlay(target: &ImageTarget, cov: &Coverage) -> Vec<u8> {
    let mut out = Vec::with_capacity(cov.width() as usize * cov.height() as usize * 4);
    for y in 0..cov.height() {
        for x in 0..cov.width() {
            let w = target.weight(x, y);
            let rgb = match (cov.get(x, y), w > 0.0, w < 0.0) {
                (true, true, _) => [0, 150, 60],
                (true, _, true) => [215, 40, 40],
                (true, _, _) => [90, 90, 90],
                (false, true, _) => [190, 190, 190],
                (false, _, true) => [255, 255, 255],
                (false, _, _) => [225, 235, 250],
            };
            out.extend_from_slice(&[rgb[0], rgb[1], rgb[2], 255]);
        }
    }
    out
}
