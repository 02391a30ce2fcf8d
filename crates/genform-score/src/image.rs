//! Image targets: how well a Scene's silhouette, seen through an orbit
//! camera, matches a weight image (thesis §4.2, reference §1.5).
//!
//! [`ImageScorer::counts`] rasterizes the silhouette (every instance and
//! polygon, flat, no depth test, both faces; polylines have no area and are
//! left out) into a bit mask and sums the target weights it covers:
//! `good` = covered positive weight, `bad` = covered negative weight's
//! magnitude, `target` = all positive weight. With a PNG read as
//! [`PngMode::Dark`] these are the reference's pixel counts, except that the
//! reference takes only pure black as target (this takes every dark pixel)
//! and culls back faces (the same silhouette for closed shapes seen from
//! outside).
//!
//! The camera is [`Camera`]'s reference frame and perspective (see
//! [`Camera::axes`]) with `znear` 0.1 and `zfar` 100 unless set.
//!
//! Modules: [`target`] (weights and their loaders), `raster` (the fast
//! path), `outline` (closed meshes filled from their outline edges),
//! `oracle` (the per-pixel reference; tests and benches only, feature `test-support`), `coverage` (bit masks),
//! `project` (clipping and snapping shared by both rasterizers), `decode`
//! (PNG and PFM), `preview` (the overlay picture).

mod coverage;
mod decode;
mod edge_table;
mod error;
#[cfg(any(test, feature = "test-support"))]
pub mod oracle;
mod outline;
mod preview;
mod project;
mod raster;
mod scan;
pub mod target;

pub use coverage::{Coverage, MAX_SIDE};
pub use error::ImageError;
pub use raster::ImageScratch;
pub use target::{ImageTarget, PngMode};

use crate::fitness::Counts;
use crate::span_cache::CachePool;
use genform_core::camera::{Camera, Projection};
use genform_core::scene::{Scene, Tessellation};
use project::Frame;

/// Scores Scenes against one image target through one camera.
#[derive(Clone, Debug)]
pub struct ImageScorer {
    camera: Camera,
    projection: Projection,
    frame: Frame,
    target: ImageTarget,
    tess: Tessellation,
    /// The scratches' caches of mesh instances (see `span_cache`); clones
    /// share it.
    caches: CachePool<Frame>,
}

impl ImageScorer {
    /// A scorer rendering `width × height` pixels through `camera`, compared
    /// with `target` (which must have that size). Curved primitives are
    /// tessellated with [`Tessellation::default`], as the exporters and the
    /// volume scorer do.
    pub fn new(camera: Camera, width: u32, height: u32, target: ImageTarget) -> Result<ImageScorer, ImageError> {
        if width == 0 || height == 0 || width > MAX_SIDE || height > MAX_SIDE {
            return Err(ImageError::BadSize { width, height, max: MAX_SIDE });
        }
        if (target.width(), target.height()) != (width, height) {
            return Err(ImageError::SizeMismatch {
                target_width: target.width(),
                target_height: target.height(),
                width,
                height,
            });
        }
        let finite = [camera.fov_deg, camera.phi, camera.theta, camera.radius].iter().all(|v| v.is_finite())
            && camera.look_at.is_finite();
        if !finite {
            return Err(ImageError::BadCamera(format!("every value must be finite: {camera:?}")));
        }
        if !(camera.fov_deg > 0.0 && camera.fov_deg < 180.0) {
            return Err(ImageError::BadCamera(format!(
                "the field of view must be between 0 and 180 degrees, not {}",
                camera.fov_deg
            )));
        }
        let projection = camera.projection(width, height);
        Ok(ImageScorer {
            camera,
            projection,
            frame: Frame::new(&projection),
            target,
            tess: Tessellation::default(),
            caches: CachePool::default(),
        })
    }

    /// The same scorer clipping at other distances (the reference uses
    /// `zfar` 200 in one scene). Requires `0 < znear < zfar`, both finite.
    pub fn with_depth_range(mut self, znear: f32, zfar: f32) -> Result<ImageScorer, ImageError> {
        if !(znear.is_finite() && zfar.is_finite() && znear > 0.0 && znear < zfar) {
            return Err(ImageError::BadCamera(format!("need 0 < znear < zfar, got znear {znear}, zfar {zfar}")));
        }
        self.projection = self.projection.with_depth_range(znear, zfar);
        self.frame = Frame::new(&self.projection);
        Ok(self)
    }

    /// The same scorer tessellating curved primitives as `tess` says.
    pub fn with_tessellation(mut self, tess: Tessellation) -> ImageScorer {
        self.tess = tess;
        self
    }

    /// The camera.
    pub fn camera(&self) -> &Camera {
        &self.camera
    }

    /// The world → pixel mapping used.
    pub fn projection(&self) -> &Projection {
        &self.projection
    }

    /// The target.
    pub fn target(&self) -> &ImageTarget {
        &self.target
    }

    /// How curved primitives are tessellated.
    pub fn tessellation(&self) -> Tessellation {
        self.tess
    }

    /// Rendering width in pixels.
    pub fn width(&self) -> u32 {
        self.target.width()
    }

    /// Rendering height in pixels.
    pub fn height(&self) -> u32 {
        self.target.height()
    }

    /// Buffers for [`ImageScorer::counts`]; keep one per thread. It comes
    /// with a cache of mesh instances' spans that outlives it (given back
    /// when it is dropped).
    pub fn scratch(&self) -> ImageScratch {
        ImageScratch::with_cache(self.frame.width, self.frame.height, self.tess, &self.caches)
    }

    /// Empties the caches of mesh instances' spans (for measurements that
    /// must not profit from earlier evaluations; results never depend on
    /// them).
    pub fn clear_caches(&self) {
        self.caches.clear();
    }

    /// What the silhouette of `scene` covers: `good` = Σ covered positive
    /// weight, `bad` = Σ |covered negative weight|, `target` = Σ positive
    /// weight; `overlap` and `outside` are 0. Allocation-free once `scratch`
    /// has seen a scene of this kind.
    pub fn counts(&self, scene: &Scene, scratch: &mut ImageScratch) -> Counts {
        scratch.fit(self.frame.width, self.frame.height, self.tess);
        raster::rasterize(&self.frame, scene, scratch);
        let (good, bad) = self.target.drain_covered(&mut scratch.mask);
        Counts { good, bad, target: self.target.total_positive(), ..Counts::default() }
    }

    /// The pixels the silhouette of `scene` covers.
    pub fn coverage(&self, scene: &Scene, scratch: &mut ImageScratch) -> Coverage {
        scratch.fit(self.frame.width, self.frame.height, self.tess);
        raster::rasterize(&self.frame, scene, scratch);
        scratch.mask.take()
    }

    /// A picture of the silhouette over the target, for previews and
    /// debugging: `(rgba, width, height)`, 4 bytes per pixel, rows from the
    /// top. Covered target pixels are green, covered pixels to avoid red,
    /// covered don't-care pixels dark grey; uncovered target pixels are light
    /// grey and the rest white (don't-care: pale blue).
    pub fn silhouette(&self, scene: &Scene) -> (Vec<u8>, u32, u32) {
        let cov = self.coverage(scene, &mut self.scratch());
        (preview::overlay(&self.target, &cov), self.width(), self.height())
    }
}

#[cfg(test)]
mod tests;
