//! `gallery.png`: the best individuals of a population side by side, each
//! framed on its own model and captioned; and which individuals to show
//! when a converged population holds many copies of one model.

use genform_core::Scene;
use genform_export::RenderOptions;
use genform_export::plot::{Tile, encode_png_rgb, gallery_rgb};

/// `gallery.png`: the given scenes in a 4-column grid of 256×256 previews,
/// each captioned with its rank and fitness under it.
pub fn gallery_png(scenes: &[(Scene, f64)]) -> Vec<u8> {
    let tiles: Vec<(&Scene, String)> =
        scenes.iter().enumerate().map(|(i, (scene, fitness))| (scene, format!("#{} {:.4}", i + 1, fitness))).collect();
    gallery_png_captioned(&tiles)
}

/// [`gallery_png`] with the captions given (lines split at `\n`).
///
/// Every cell is framed on its own model (the renderer's fitted 3/4 view),
/// so each model fills its cell. One camera fitted to all of them would
/// keep sizes comparable, but the models rarely share a place: ships grow
/// from the origin in different directions and lengths, so each one ended
/// up small in a corner of a frame made for their union. Sizes are in the
/// captions' descriptors and in `best.png`, which shows the target.
pub fn gallery_png_captioned(scenes: &[(&Scene, String)]) -> Vec<u8> {
    let tiles: Vec<Tile> = scenes
        .iter()
        .map(|(scene, caption)| {
            let opts = RenderOptions { width: 256, height: 256, camera: None, ..RenderOptions::default() };
            let (rgb, width, height) = genform_export::render_rgb(scene, &opts);
            Tile { rgb, width, height, caption: caption.clone() }
        })
        .collect();
    let (rgb, w, h) = gallery_rgb(&tiles, 4);
    encode_png_rgb(&rgb, w, h)
}

/// Up to `n` of `items` (`(look, item)`, best individual first) whose
/// looks differ ([`genform_score::Scorer::look`]): the first of each look,
/// in order. Fewer than `n` when fewer distinct looks exist, so a converged
/// run shows a short gallery rather than copies. Reads `items` only until
/// it has `n`.
pub fn distinct_looks<T>(items: impl IntoIterator<Item = (String, T)>, n: usize) -> Vec<T> {
    let mut seen = std::collections::HashSet::new();
    items.into_iter().filter(|(l, _)| seen.insert(l.clone())).map(|(_, t)| t).take(n).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn galleries_keep_one_individual_per_look() {
        let looks = ["a", "b", "a", "c", "a", "d", "b"];
        let ranked = || looks.iter().map(|l| l.to_string()).enumerate().map(|(i, l)| (l, i));
        assert_eq!(distinct_looks(ranked(), 16), [0, 1, 3, 5], "fewer cells when fewer looks exist");
        let mut read = 0;
        let counted = ranked().inspect(|_| read += 1);
        assert_eq!(distinct_looks(counted, 2), [0, 1]);
        assert_eq!(read, 2, "stops reading once it has enough");
    }
}
