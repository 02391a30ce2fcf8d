//! `[silhouettes]`: a target shape matched by its outline from several
//! views — front (from +z), side (from +x), top (from +y) — so that a model
//! with the right footprint but the wrong height, or the right front but
//! the wrong depth, is told apart from the target (a volume target counts
//! voxels and cannot say which way a model is wrong).
//!
//! Each view is an image target of genform-score's contract: the target
//! mesh's silhouette, seen through a narrow-angle camera fitted to it, is
//! the picture to cover (+1) and everything else is to stay out of (−1);
//! the views' counts add up to the others' under the scene's `[fitness]`
//! (whose form defaults to `image`).
//!
//! ```toml
//! [silhouettes]
//! mesh = "targets/setback_envelope.obj"
//! views = ["front", "side", "top"]   # the default
//! size = 128                         # pixels a side of each view
//! fov = 10                           # degrees: narrow, nearly parallel lines of sight
//! ```

use anyhow::{Context, Result, bail};
use genform_core::camera::Camera;
use genform_core::{Instance, Mesh, Primitive, Scene};
use genform_score::{Form, ImageScorer, ImageTarget};
use glam::Vec3;
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};
use std::sync::Arc;

use super::row::{Built, Part, ScorerRow, ScorerSection};
use crate::memory::{Size, human};
use crate::toml_doc::{Doc, Value};

/// The `[silhouettes]` row.
pub(crate) struct Silhouettes;

/// A direction a target is seen from.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Deserialize, Serialize)]
#[serde(rename_all = "lowercase")]
enum View {
    /// From +z.
    Front,
    /// From +x.
    Side,
    /// From +y, looking down.
    Top,
}

impl View {
    /// The orbit camera's azimuth and elevation of this view.
    fn angles(self) -> (f32, f32) {
        use std::f32::consts::FRAC_PI_2;
        match self {
            View::Front => (FRAC_PI_2, 0.0),
            View::Side => (0.0, 0.0),
            View::Top => (FRAC_PI_2, FRAC_PI_2),
        }
    }
}

/// `[silhouettes]` as written.
#[derive(Clone, Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
struct SilhouettesConfig {
    /// The target shape (.obj, .stl, .glb), relative to the scene.
    mesh: PathBuf,
    /// The views (default front, side and top).
    #[serde(default = "all_views")]
    views: Vec<View>,
    /// Pixels a side of each (square) view.
    #[serde(default = "size")]
    size: u32,
    /// Vertical field of view of the cameras, in degrees.
    #[serde(default = "fov")]
    fov: f32,
}

fn all_views() -> Vec<View> {
    vec![View::Front, View::Side, View::Top]
}
fn size() -> u32 {
    128
}
fn fov() -> f32 {
    10.0
}

/// Bytes per pixel of a view: its weight and the rendering.
const PIXEL_BYTES: u128 = 16;

/// A read `[silhouettes]` and where it is, for refusals made when built.
#[derive(Debug)]
struct SilhouettesSection {
    config: SilhouettesConfig,
    place: String,
}

impl ScorerRow for Silhouettes {
    fn section(&self) -> &'static str {
        "silhouettes"
    }

    fn read(&self, doc: &Doc, value: &Value, base: &Path) -> Result<Arc<dyn ScorerSection>> {
        let mut config: SilhouettesConfig = doc.read(value)?;
        let refuse = |key: &str, why: String| doc.refuse(&["silhouettes", key], format!("[silhouettes] {why}"));
        if config.views.is_empty() {
            return Err(refuse("views", "views is empty: give at least one of \"front\", \"side\", \"top\"".into()));
        }
        if let Some((i, v)) = config.views.iter().enumerate().find(|(i, v)| config.views[..*i].contains(v)) {
            return Err(refuse("views", format!("view {} ({v:?}) is given twice", i + 1)));
        }
        if !(16..=2048).contains(&config.size) {
            return Err(refuse("size", format!("size must be 16 to 2048 pixels, not {}", config.size)));
        }
        if !(config.fov.is_finite() && (1.0..=60.0).contains(&config.fov)) {
            return Err(refuse("fov", format!("fov must be 1 to 60 degrees, not {}", config.fov)));
        }
        config.mesh = base.join(&config.mesh);
        Ok(Arc::new(SilhouettesSection { config, place: doc.place(&["silhouettes"]) }))
    }

    fn default_form(&self) -> Form {
        Form::Image
    }
}

impl ScorerSection for SilhouettesSection {
    fn to_json(&self) -> serde_json::Value {
        serde_json::to_value(&self.config).unwrap_or_default()
    }

    fn memory(&self) -> Vec<Size<'static>> {
        let c = &self.config;
        let n = u128::from(c.size) * u128::from(c.size) * c.views.len() as u128;
        vec![Size {
            section: "silhouettes",
            key: "size",
            value: u128::from(c.size),
            bytes: n.saturating_mul(PIXEL_BYTES),
            what: format!(
                "{} views of {} × {} pixels, {} a pixel",
                c.views.len(),
                c.size,
                c.size,
                human(PIXEL_BYTES as f64)
            ),
        }]
    }

    fn build(&self) -> Result<Built> {
        let c = &self.config;
        let at = || format!("{}: [silhouettes]", self.place);
        let mesh = crate::gate::read_mesh(&c.mesh).with_context(at)?;
        let views = c
            .views
            .iter()
            .map(|v| view(&mesh, *v, c.size, c.fov).with_context(|| format!("{}, view {v:?}", at())).map(Arc::new))
            .collect::<Result<Vec<Arc<ImageScorer>>>>()?;
        let counters = views.iter().map(|s| s.clone() as Arc<dyn genform_score::Counter>).collect();
        Ok(Built { part: Part::Counters(counters), ghosts: vec![mesh], images: views })
    }

    fn target_meshes(&self) -> Result<Vec<Mesh>> {
        Ok(vec![crate::gate::read_mesh(&self.config.mesh)?])
    }

    fn has_target_meshes(&self) -> bool {
        true
    }
}

/// The scene of `mesh` alone, at its place.
fn scene_of(mesh: &Mesh) -> Scene {
    let mut scene = Scene::new();
    let tag = scene.tag("target");
    let id = scene.mesh(&Arc::new(mesh.clone()));
    scene.instances.push(Instance { transform: glam::Affine3A::IDENTITY, primitive: Primitive::Mesh(id), tag });
    scene
}

/// The image target of `mesh` seen from `view`: a camera fitted to the
/// mesh's bounding box, its silhouette to cover and the rest to avoid.
fn view(mesh: &Mesh, view: View, size: u32, fov: f32) -> Result<ImageScorer> {
    let Some((lo, hi)) = mesh.bounds() else { bail!("the target mesh has no vertices") };
    let (phi, theta) = view.angles();
    let mut camera = Camera { fov_deg: fov, phi, theta, radius: 1.0, look_at: (lo + hi) * 0.5 };
    let corners = (0..8).map(|k| {
        Vec3::new(
            if k & 1 == 0 { lo.x } else { hi.x },
            if k & 2 == 0 { lo.y } else { hi.y },
            if k & 4 == 0 { lo.z } else { hi.z },
        )
    });
    let reach = (hi - lo).length().max(1e-3);
    camera.radius = camera.fit_distance(1.0, corners).max(reach);
    // Everything within the box's reach of the look-at point is in range.
    let (znear, zfar) = ((camera.radius - reach).max(camera.radius * 1e-3), camera.radius + reach);
    let n = (size * size) as usize;
    let blank = ImageTarget::from_weights(size, size, &vec![0.0; n])?;
    let probe = ImageScorer::new(camera, size, size, blank)?.with_depth_range(znear, zfar)?;
    let covered = probe.coverage(&scene_of(mesh), &mut probe.scratch());
    let weights: Vec<f32> =
        (0..n).map(|i| if covered.get((i as u32) % size, (i as u32) / size) { 1.0 } else { -1.0 }).collect();
    if !weights.contains(&1.0) {
        bail!("the target covers no pixel (is the mesh closed and not flat along this view?)");
    }
    let target = ImageTarget::from_weights(size, size, &weights)?;
    Ok(ImageScorer::new(camera, size, size, target)?.with_depth_range(znear, zfar)?)
}

#[cfg(test)]
mod tests {
    use super::*;
    use genform_score::{Counter, Scorer};

    /// A closed box mesh from `lo` to `hi`.
    fn cuboid(lo: Vec3, hi: Vec3) -> Mesh {
        let positions: Vec<Vec3> = (0..8)
            .map(|k| {
                Vec3::new(
                    if k & 1 == 0 { lo.x } else { hi.x },
                    if k & 2 == 0 { lo.y } else { hi.y },
                    if k & 4 == 0 { lo.z } else { hi.z },
                )
            })
            .collect();
        let quads = [[0, 2, 3, 1], [4, 5, 7, 6], [0, 1, 5, 4], [2, 6, 7, 3], [0, 4, 6, 2], [1, 3, 7, 5]];
        let triangles = quads.iter().flat_map(|q| [[q[0], q[1], q[2]], [q[0], q[2], q[3]]]).collect();
        Mesh { name: "box".into(), positions, triangles }
    }

    #[test]
    fn every_view_scores_the_target_itself_best_and_tells_a_wrong_depth() {
        let target = cuboid(Vec3::new(-2.0, 0.0, -1.0), Vec3::new(2.0, 6.0, 1.0));
        let views: Vec<ImageScorer> =
            [View::Front, View::Side, View::Top].iter().map(|v| view(&target, *v, 64, 10.0).unwrap()).collect();
        let counts = |mesh: &Mesh| -> Vec<genform_score::Counts> {
            views.iter().map(|v| Counter::counts(v, &scene_of(mesh), &mut Counter::scratch(v))).collect()
        };
        for (v, c) in counts(&target).iter().enumerate() {
            assert!(c.target > 20.0 && c.good == c.target && c.bad == 0.0, "view {v}: {c:?}");
        }
        // Twice as deep along z: the front view cannot tell, the side and top views can.
        let deep = counts(&cuboid(Vec3::new(-2.0, 0.0, -2.0), Vec3::new(2.0, 6.0, 2.0)));
        assert!(deep[0].bad == 0.0 && deep[1].bad > 0.0 && deep[2].bad > 0.0, "{deep:?}");
        // All three views under the image form: the target scores the most.
        let fitness = genform_score::Fitness { form: Form::Image, length: 0.0, ..Default::default() };
        let scorer =
            genform_score::Targets::new(views.into_iter().map(|v| Arc::new(v) as Arc<dyn Counter>).collect(), fitness);
        let score = |mesh: &Mesh| scorer.fitness(&scene_of(mesh), 1, &mut Scorer::scratch(&scorer));
        let deeper = cuboid(Vec3::new(-2.0, 0.0, -2.0), Vec3::new(2.0, 6.0, 2.0));
        assert_eq!(score(&target), fitness.max_reachable(1));
        assert!(score(&deeper) < score(&target));
    }

    #[test]
    fn settings_are_refused_at_their_position() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("s.toml");
        let grammar = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/shape/setback_tower.sg");
        let scene = |extra: &str| {
            format!("grammar = {:?}\n[silhouettes]\nmesh = \"t.obj\"\n{extra}", grammar.display().to_string())
        };
        let refusal = |extra: &str| {
            std::fs::write(&path, scene(extra)).unwrap();
            format!("{:#}", crate::scene::Scene::load(&path, &[]).unwrap_err())
        };
        assert!(
            refusal("views = [\"front\", \"front\"]")
                .ends_with("s.toml:4:9: [silhouettes] view 2 (Front) is given twice")
        );
        assert!(refusal("size = 4").ends_with("s.toml:4:8: [silhouettes] size must be 16 to 2048 pixels, not 4"));
        assert!(refusal("views = [\"back\"]").contains("s.toml:4:10: unknown variant `back`"));
        std::fs::write(&path, scene("")).unwrap();
        let loaded = crate::scene::Scene::load(&path, &[]).unwrap();
        assert_eq!(loaded.scoring.fitness([1.0, 2.0]).form, Form::Image, "the image form by default");
    }
}
