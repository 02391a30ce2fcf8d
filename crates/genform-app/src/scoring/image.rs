//! `[[image]]`: a silhouette target seen through a camera (a PNG or a PFM
//! weight image), scored by [`genform_score::ImageScorer`].

use anyhow::{Context, Result};
use genform_core::camera::Camera;
use genform_score::{Form, ImageScorer, ImageTarget, PngMode};
use glam::Vec3;
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};
use std::sync::Arc;

use super::row::{Built, Part, ScorerRow, ScorerSection};
use crate::memory::{Size, human};
use crate::toml_doc::{Doc, Value};

/// The `[[image]]` row.
pub(crate) struct Images;

/// `[[image]]`: a silhouette target seen through a camera.
#[derive(Clone, Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct ImageConfig {
    /// Target picture: a PNG (dark = target) or a PFM float weight image.
    pub target: PathBuf,
    /// How a PNG is read: "dark" (dark = target, rest = avoid) or "signed"
    /// (grey 128 = don't care, white = +1, black = −1).
    #[serde(default = "dark")]
    pub mode: String,
    /// Rendering width in pixels (must match the target).
    #[serde(default = "width")]
    pub width: u32,
    /// Rendering height in pixels (must match the target).
    #[serde(default = "height")]
    pub height: u32,
    /// The orbit camera.
    pub camera: CameraConfig,
}

/// An orbit camera: eye = look_at + radius·(cosθ cosφ, sinθ, cosθ sinφ).
#[derive(Clone, Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct CameraConfig {
    /// Vertical field of view in degrees.
    #[serde(default = "fov")]
    pub fov: f32,
    /// Azimuth in radians.
    pub phi: f32,
    /// Elevation in radians.
    pub theta: f32,
    /// Distance from the look-at point.
    pub radius: f32,
    /// The point at the image centre.
    pub look_at: [f32; 3],
}

fn fov() -> f32 {
    60.0
}
fn width() -> u32 {
    800
}
fn height() -> u32 {
    600
}
fn dark() -> String {
    "dark".into()
}

/// Bytes per pixel of an image target: its weight and the rendering.
const PIXEL_BYTES: u128 = 16;

/// The `[[image]]` targets of a scene.
#[derive(Debug)]
struct ImageSection {
    images: Vec<ImageConfig>,
    /// `file:line:col` of each `[[image]]`.
    places: Vec<String>,
}

impl ScorerRow for Images {
    fn section(&self) -> &'static str {
        "image"
    }

    fn read(&self, doc: &Doc, value: &Value, base: &Path) -> Result<Arc<dyn ScorerSection>> {
        let mut images: Vec<ImageConfig> = doc.read(value)?;
        let mut places = Vec::new();
        for (i, img) in images.iter_mut().enumerate() {
            let index = i.to_string();
            if PngMode::from_name(&img.mode).is_none() {
                return Err(doc.refuse(
                    &["image", &index, "mode"],
                    format!("[[image]] #{}: mode `{}` is unknown; use \"dark\" or \"signed\"", i + 1, img.mode),
                ));
            }
            places.push(doc.place(&["image", &index]));
            img.target = base.join(&img.target);
        }
        Ok(Arc::new(ImageSection { images, places }))
    }

    fn default_form(&self) -> Form {
        Form::Image
    }
}

/// The camera an image config describes.
pub(crate) fn camera(c: &CameraConfig) -> Camera {
    Camera { fov_deg: c.fov, phi: c.phi, theta: c.theta, radius: c.radius, look_at: Vec3::from(c.look_at) }
}

impl ScorerSection for ImageSection {
    fn to_json(&self) -> serde_json::Value {
        serde_json::to_value(&self.images).unwrap_or_default()
    }

    fn memory(&self) -> Vec<Size<'static>> {
        self.images
            .iter()
            .map(|img| {
                let n = u128::from(img.width) * u128::from(img.height);
                Size {
                    section: "image",
                    key: "width",
                    value: n,
                    bytes: n.saturating_mul(PIXEL_BYTES),
                    what: format!("a {} × {} picture, {} a pixel", img.width, img.height, human(PIXEL_BYTES as f64)),
                }
            })
            .collect()
    }

    /// Each image is a counting target of its own (its counts add to the
    /// others'); the first is the one pictures show.
    fn build(&self) -> Result<Built> {
        let scorers = self
            .images
            .iter()
            .enumerate()
            .map(|(i, c)| image(c).with_context(|| format!("{}: [[image]] #{}", self.places[i], i + 1)).map(Arc::new))
            .collect::<Result<Vec<Arc<ImageScorer>>>>()?;
        let counters = scorers.iter().map(|s| s.clone() as Arc<dyn genform_score::Counter>).collect();
        Ok(Built { part: Part::Counters(counters), ghosts: Vec::new(), images: scorers })
    }

    fn target_pictures(&self) -> Vec<PathBuf> {
        self.images.iter().map(|i| i.target.clone()).collect()
    }
}

/// The scorer of one image target: its picture read, its camera set.
fn image(c: &ImageConfig) -> Result<ImageScorer> {
    let bytes = crate::gate::read_bytes(&c.target, "target image")?;
    let is_pfm = c.target.extension().is_some_and(|e| e.eq_ignore_ascii_case("pfm"));
    let target = if is_pfm {
        ImageTarget::from_pfm(&bytes)
    } else {
        ImageTarget::from_png(&bytes, PngMode::from_name(&c.mode).unwrap_or_default())
    }
    .with_context(|| format!("cannot read target image {}", c.target.display()))?;
    Ok(ImageScorer::new(camera(&c.camera), c.width, c.height, target)?)
}
