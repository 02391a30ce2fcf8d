//! Pictures of an evolve run a user can judge at a glance: the best model
//! with its target behind it (`best.png`) and an animation of the best
//! individual over the run (`evolution.png`, an animated PNG).
//!
//! Volume targets are drawn as tinted glass around the model in a fitted
//! 3/4 view; image targets as the picture behind the model, seen through
//! the target's camera in the scorers' (mirrored) frame so the two line up
//! as they do for the fitness. A scene with both shows the volume.

use anyhow::Result;
use genform_core::camera::Camera;
use genform_core::scene::Tessellation;
use genform_core::{Mesh, Scene};
use genform_export::{Backdrop, RenderOptions};
use genform_score::ImageScorer;
use std::sync::Arc;

use crate::files::write_atomic;

/// Frames an animation aims for, whatever the run's length.
pub const FRAMES: usize = 30;

/// Widest animation frame; larger target pictures are halved until they fit.
const FRAME_WIDTH: u32 = 480;

/// The target of a scene as previews draw it.
pub struct TargetPicture {
    ghosts: Vec<Mesh>,
    image: Option<TargetImage>,
}

/// An image target's camera and picture (RGB, the scorers' frame).
struct TargetImage {
    camera: Camera,
    width: u32,
    height: u32,
    rgb: Vec<u8>,
}

/// Backdrop colours of an image target: pixels to cover, pixels to avoid,
/// don't-care pixels (a paler version of `best-silhouette.png`'s greys).
const IMAGE_COVER: [u8; 3] = [178, 196, 226];
const IMAGE_AVOID: [u8; 3] = [255, 255, 255];
const IMAGE_DONT_CARE: [u8; 3] = [236, 238, 241];

impl TargetPicture {
    /// The target as its scorers show it: `ghosts` (volume targets'
    /// meshes) or else the first image target.
    pub fn new(ghosts: &[Mesh], images: &[Arc<ImageScorer>]) -> Self {
        let image = if ghosts.is_empty() { images.first().map(|i| target_image(i)) } else { None };
        TargetPicture { ghosts: ghosts.to_vec(), image }
    }

    /// The picture size: the image target's, else 800 × 600.
    fn size(&self) -> (u32, u32) {
        self.image.as_ref().map_or((800, 600), |i| (i.width, i.height))
    }

    /// `scene` with the target behind it, seen through `camera` (volume
    /// targets; `None` fits the view to the model and the target) or the
    /// image target's camera, as RGB `(pixels, width, height)`.
    pub fn render(&self, scene: &Scene, camera: Option<Camera>) -> (Vec<u8>, u32, u32) {
        self.render_at(scene, camera, self.size(), self.image.as_ref())
    }

    /// [`TargetPicture::render`] at `size`, with `image` (the image target
    /// scaled to `size`) behind the model.
    fn render_at(
        &self,
        scene: &Scene,
        camera: Option<Camera>,
        (width, height): (u32, u32),
        image: Option<&TargetImage>,
    ) -> (Vec<u8>, u32, u32) {
        let mut opts = RenderOptions { width, height, camera, ..RenderOptions::default() };
        let backdrop = match image {
            Some(img) => {
                opts.camera = Some(img.camera);
                Backdrop { image: Some(&img.rgb), mirrored: true, ..Backdrop::default() }
            }
            None => Backdrop { ghosts: &self.ghosts, ..Backdrop::default() },
        };
        genform_export::render_rgb_over(scene, &opts, &backdrop)
    }

    /// `best.png`: [`TargetPicture::render`] with a fitted view, as PNG.
    pub fn best_png(&self, scene: &Scene) -> Vec<u8> {
        let (rgb, w, h) = self.render(scene, None);
        genform_export::plot::encode_png_rgb(&rgb, w, h)
    }

    /// One view for every frame of an animation: fitted to the target and
    /// all of `scenes` (image targets use their own camera).
    fn shared_camera(&self, scenes: &[&Scene]) -> Option<Camera> {
        if self.image.is_some() {
            return None;
        }
        let (w, h) = self.size();
        let tess = Tessellation::default();
        let boxes = scenes.iter().filter_map(|s| s.bounds(tess)).chain(self.ghosts.iter().filter_map(Mesh::bounds));
        let (lo, hi) = boxes.reduce(|(a, b), (c, d)| (a.min(c), b.max(d)))?;
        Some(Camera::fit_aspect((lo, hi), w as f32 / h as f32))
    }

    /// `evolution.png`: an animated PNG of `frames` (generation, best model
    /// so far), all through one camera, each captioned with its generation
    /// and fitness; `None` without frames. Frames are drawn at the size they
    /// are shown (the picture size halved until at most [`FRAME_WIDTH`]
    /// wide), side by side on the current pool.
    pub fn evolution_apng(&self, frames: &[(usize, f64, Scene)]) -> Option<Vec<u8>> {
        use rayon::prelude::*;
        let scenes: Vec<&Scene> = frames.iter().map(|(_, _, s)| s).collect();
        let camera = self.shared_camera(&scenes);
        let (mut size, mut scaled) = (self.size(), None);
        while size.0 > FRAME_WIDTH && size.1 >= 2 {
            scaled = scaled.as_ref().or(self.image.as_ref()).map(TargetImage::halved);
            size = (size.0 / 2, size.1 / 2);
        }
        let image = scaled.as_ref().or(self.image.as_ref());
        let pictures: Vec<Vec<u8>> = frames
            .par_iter()
            .map(|(generation, fitness, scene)| {
                let (mut rgb, w, _) = self.render_at(scene, camera, size, image);
                let caption = format!("gen {generation}  {fitness:.4}");
                genform_export::plot::caption_rgb(&mut rgb, w, 6, 6, &caption);
                rgb
            })
            .collect();
        genform_export::plot::encode_apng_rgb(&pictures, size.0, size.1, 250, 2000)
    }
}

impl TargetImage {
    /// The picture at half its size, seen through the same camera.
    fn halved(&self) -> TargetImage {
        let (rgb, width, height) = halve(&self.rgb, self.width, self.height);
        TargetImage { camera: self.camera, width, height, rgb }
    }
}

/// The image target as a backdrop picture.
fn target_image(img: &ImageScorer) -> TargetImage {
    let (width, height) = (img.width(), img.height());
    let t = img.target();
    let rgb = (0..height)
        .flat_map(|y| (0..width).map(move |x| (x, y)))
        .flat_map(|(x, y)| {
            let w = t.weight(x, y);
            if w > 0.0 {
                IMAGE_COVER
            } else if w < 0.0 {
                IMAGE_AVOID
            } else {
                IMAGE_DONT_CARE
            }
        })
        .collect();
    TargetImage { camera: *img.camera(), width, height, rgb }
}

/// Halves an RGB picture (2 × 2 box filter; an odd last row or column is dropped).
fn halve(rgb: &[u8], w: u32, h: u32) -> (Vec<u8>, u32, u32) {
    let (nw, nh) = (w / 2, h / 2);
    let at = |x: u32, y: u32, c: usize| u32::from(rgb[3 * (y * w + x) as usize + c]);
    let out = (0..nh)
        .flat_map(|y| (0..nw).map(move |x| (x, y)))
        .flat_map(|(x, y)| {
            [0, 1, 2].map(|c| {
                let sum = at(2 * x, 2 * y, c)
                    + at(2 * x + 1, 2 * y, c)
                    + at(2 * x, 2 * y + 1, c)
                    + at(2 * x + 1, 2 * y + 1, c);
                ((sum + 2) / 4) as u8
            })
        })
        .collect();
    (out, nw, nh)
}

/// The best individual of a run as it improved: `(generation, fitness,
/// genome)` each time the best so far got better. Cheap to keep during a
/// run (a clone per improvement); pictures are made from it at the end.
#[derive(Clone, Debug)]
pub struct BestHistory<G> {
    steps: Vec<(usize, f64, G)>,
    last_generation: usize,
    /// Fewest generations between kept improvements; doubles whenever
    /// [`MAX_STEPS`] are kept, so a long run's history stays small and
    /// spread evenly over the run.
    spacing: usize,
}

impl<G> Default for BestHistory<G> {
    fn default() -> Self {
        BestHistory { steps: Vec::new(), last_generation: 0, spacing: 1 }
    }
}

/// Most improvements kept.
const MAX_STEPS: usize = 4 * FRAMES;

impl<G: Clone> BestHistory<G> {
    /// Notes generation `generation`, whose best so far is `best` (genome, fitness).
    pub fn record(&mut self, generation: usize, best: Option<(&G, f64)>) {
        self.last_generation = generation;
        let Some((genome, fitness)) = best else { return };
        if self.steps.last().is_some_and(|(_, f, _)| *f >= fitness) {
            return;
        }
        let step = (generation, fitness, genome.clone());
        let n = self.steps.len();
        // Within `spacing` of the previous kept one: the newer best replaces the last.
        if n >= 2 && generation - self.steps[n - 2].0 < self.spacing {
            self.steps[n - 1] = step;
        } else {
            self.steps.push(step);
        }
        if self.steps.len() > MAX_STEPS {
            self.spacing *= 2;
            let last = self.steps.pop();
            let mut kept: Vec<(usize, f64, G)> = Vec::with_capacity(MAX_STEPS);
            for s in self.steps.drain(..) {
                if kept.last().is_none_or(|k| s.0 - k.0 >= self.spacing) {
                    kept.push(s);
                }
            }
            kept.extend(last);
            self.steps = kept;
        }
    }

    /// About `n` frames spread evenly over the generations recorded, each
    /// `(generation, fitness, genome)` of the best so far at it; frames
    /// that would repeat the previous one are left out, and the last frame
    /// is always the final best.
    pub fn frames(&self, n: usize) -> Vec<(usize, f64, &G)> {
        let Some(first) = self.steps.first() else { return Vec::new() };
        let (from, to) = (first.0, self.last_generation.max(first.0));
        let n = n.max(2);
        let mut out: Vec<(usize, f64, &G)> = Vec::new();
        let mut last_step = usize::MAX;
        for k in 0..n {
            let generation = from + ((to - from) as f64 * k as f64 / (n - 1) as f64).round() as usize;
            let step = self.steps.iter().rposition(|(g, _, _)| *g <= generation).unwrap_or(0);
            if step != last_step {
                let (_, f, genome) = &self.steps[step];
                out.push((generation, *f, genome));
                last_step = step;
            }
        }
        out
    }
}

/// Writes `best-silhouette.png` (then `-2`, `-3`, …): `scene` over each
/// image target, as the scorer sees it.
pub fn write_silhouettes(out: &std::path::Path, images: &[Arc<ImageScorer>], scene: &Scene) -> Result<()> {
    for (i, img) in images.iter().enumerate() {
        let (rgba, w, h) = img.silhouette(scene);
        let rgb: Vec<u8> = rgba.chunks_exact(4).flat_map(|p| [p[0], p[1], p[2]]).collect();
        let name = if i == 0 { "best-silhouette.png".to_string() } else { format!("best-silhouette-{}.png", i + 1) };
        write_atomic(&out.join(name), &genform_export::plot::encode_png_rgb(&rgb, w, h))?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn history_keeps_improvements_and_spreads_frames() {
        let mut h = BestHistory::default();
        h.record(0, None);
        for g in 0..=100usize {
            let fitness = (g / 10) as f64;
            h.record(g, Some((&g, fitness)));
        }
        assert_eq!(h.steps.len(), 11, "one entry per improvement");
        let frames = h.frames(21);
        assert_eq!(frames.first().map(|f| (f.0, *f.2)), Some((0, 0)));
        assert_eq!(frames.last().map(|f| (f.0, f.1, *f.2)), Some((100, 10.0, 100)));
        assert_eq!(frames.len(), 11, "frames repeating the previous best are left out");
        assert!(frames.windows(2).all(|w| w[0].0 < w[1].0 && w[0].1 < w[1].1));
        assert!(BestHistory::<u8>::default().frames(30).is_empty());
    }

    #[test]
    fn history_stays_small_in_long_runs() {
        let mut h = BestHistory::default();
        for g in 0..10_000usize {
            h.record(g, Some((&g, g as f64)));
        }
        assert!(h.steps.len() <= MAX_STEPS);
        assert_eq!(h.steps.first().map(|s| s.0), Some(0));
        assert_eq!(h.steps.last().map(|s| s.0), Some(9_999));
        let frames = h.frames(FRAMES);
        assert!(frames.len() > FRAMES / 2, "{}", frames.len());
    }

    #[test]
    fn halving_averages_blocks() {
        let rgb = [0u8, 0, 0, 100, 100, 100, 200, 200, 200, 100, 100, 100];
        assert_eq!(halve(&rgb, 2, 2), (vec![100, 100, 100], 1, 1));
    }
}
