//! The orbit camera shared by the preview renderer and the image scorers.
//!
//! A [`Camera`] sits on a sphere around the point it looks at. Its image
//! frame and perspective are those of the ShapeGenetics reference renderer,
//! so the reference targets (800×600 silhouettes, each with its camera) line
//! up with what the image scorers see; [`Projection`] maps world points to
//! pixels of a `width × height` image with that frame.

use glam::{DAffine3, DMat3, DVec2, DVec3, Mat4, Vec2, Vec3, Vec4};

/// An orbit camera looking at a point.
///
/// The eye sits at
/// `look_at + radius * (cos θ cos φ, sin θ, cos θ sin φ)`, with `+y` up.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Camera {
    /// Vertical field of view, in degrees.
    pub fov_deg: f32,
    /// Azimuth φ around the y axis, in radians (0 = on the +x side).
    pub phi: f32,
    /// Elevation θ above the xz plane, in radians.
    pub theta: f32,
    /// Distance from `look_at` to the eye.
    pub radius: f32,
    /// The point the camera looks at (the image center).
    pub look_at: Vec3,
}

impl Default for Camera {
    /// A 3/4 view of the unit cube around the origin.
    fn default() -> Self {
        Camera::fit((Vec3::splat(-0.5), Vec3::splat(0.5)))
    }
}

impl Camera {
    /// Default vertical field of view of [`Camera::fit`], in degrees.
    pub const FIT_FOV_DEG: f32 = 35.0;
    /// Near clipping distance of the reference renderer.
    pub const ZNEAR: f32 = 0.1;
    /// Far clipping distance of the reference renderer.
    pub const ZFAR: f32 = 100.0;

    /// A pleasant 3/4 view (from the front right, a little above) of the
    /// box `bounds = (min, max)`, close enough that the box fills most of a
    /// square image.
    pub fn fit(bounds: (Vec3, Vec3)) -> Camera {
        Camera::fit_aspect(bounds, 1.0)
    }

    /// Like [`Camera::fit`] for an image `aspect = width / height`: the whole
    /// box stays in view horizontally too.
    pub fn fit_aspect(bounds: (Vec3, Vec3), aspect: f32) -> Camera {
        let (mut lo, mut hi) = bounds;
        if !(lo.is_finite() && hi.is_finite()) || lo.cmpgt(hi).any() {
            (lo, hi) = (Vec3::splat(-0.5), Vec3::splat(0.5));
        }
        let center = (lo + hi) * 0.5;
        let mut half = (hi - lo) * 0.5;
        let size = half.max_element();
        // Flat boxes get a little thickness, empty ones a unit size.
        half = half.max(Vec3::splat(if size > 0.0 { size * 1e-3 } else { 0.5 }));
        let mut cam = Camera {
            fov_deg: Self::FIT_FOV_DEG,
            phi: 50f32.to_radians(),
            theta: 25f32.to_radians(),
            radius: 1.0,
            look_at: center,
        };
        let corners = (0..8).map(|k| {
            center
                + Vec3::new(
                    if k & 1 == 0 { -half.x } else { half.x },
                    if k & 2 == 0 { -half.y } else { half.y },
                    if k & 4 == 0 { -half.z } else { half.z },
                )
        });
        cam.radius = cam.fit_distance(aspect, corners).max(half.length() * 1.05);
        cam
    }

    /// The least distance from `look_at` (along the current view direction)
    /// at which every point projects inside an image of `aspect`, with a
    /// small margin.
    pub fn fit_distance(&self, aspect: f32, points: impl IntoIterator<Item = Vec3>) -> f32 {
        let (right, up, fwd) = self.axes();
        let tan_y = (self.fov_deg.clamp(1.0, 170.0).to_radians() * 0.5).tan() / 1.08;
        let tan_x = tan_y * aspect.clamp(0.05, 20.0);
        let mut d: f32 = 0.0;
        for p in points {
            let q = p - self.look_at;
            let (x, y, z) = (q.dot(right), q.dot(up), q.dot(fwd));
            d = d.max(x.abs() / tan_x - z).max(y.abs() / tan_y - z);
        }
        d
    }

    /// The eye position.
    pub fn eye(&self) -> Vec3 {
        let (st, ct) = self.theta.sin_cos();
        let (sp, cp) = self.phi.sin_cos();
        self.look_at + self.radius * Vec3::new(ct * cp, st, ct * sp)
    }

    /// The image frame `(right, up, forward)` of the reference renderer:
    /// `forward = −(cos θ cos φ, sin θ, cos θ sin φ)` points from the eye to
    /// `look_at`, `up = (−sin θ cos φ, cos θ, −sin θ sin φ)` is the direction
    /// the eye moves in as θ grows (so past the pole, |θ| > 90°, the picture
    /// turns upside down rather than flipping), and
    /// `right = up × forward = (−sin φ, 0, cos φ)`.
    ///
    /// This frame is left-handed: the picture is the mirror image of what a
    /// right-handed camera at the same spot would show. The reference targets
    /// were drawn for it (the tree sketch's trunk stands at the origin only
    /// in this frame), so scorers use it.
    pub fn axes(&self) -> (Vec3, Vec3, Vec3) {
        let (r, u, f) = self.axes_f64();
        (r.as_vec3(), u.as_vec3(), f.as_vec3())
    }

    fn axes_f64(&self) -> (DVec3, DVec3, DVec3) {
        let (st, ct) = f64::from(self.theta).sin_cos();
        let (sp, cp) = f64::from(self.phi).sin_cos();
        let fwd = -DVec3::new(ct * cp, st, ct * sp);
        let up = DVec3::new(-st * cp, ct, -st * sp);
        (DVec3::new(-sp, 0.0, cp), up, fwd)
    }

    /// World → view space as a matrix: view x runs to the image's right, y
    /// up, z is the depth in front of the eye (see [`Camera::axes`]).
    pub fn view_matrix(&self) -> Mat4 {
        let (r, u, f) = self.axes();
        let e = self.eye();
        Mat4::from_cols(
            Vec4::new(r.x, u.x, f.x, 0.0),
            Vec4::new(r.y, u.y, f.y, 0.0),
            Vec4::new(r.z, u.z, f.z, 0.0),
            Vec4::new(-r.dot(e), -u.dot(e), -f.dot(e), 1.0),
        )
    }

    /// The reference renderer's perspective for an image of `aspect =
    /// width / height`: view space (depth `z > 0`) → OpenGL clip space, with
    /// `w = z`, normalized x to the right, y up, and z from −1 at `znear` to
    /// +1 at `zfar`.
    pub fn projection_matrix(&self, aspect: f32, znear: f32, zfar: f32) -> Mat4 {
        let s2 = 1.0 / (0.5 * self.fov_deg.to_radians()).tan();
        let s1 = s2 / aspect;
        let z1 = (zfar + znear) / (zfar - znear);
        let z2 = -2.0 * znear * zfar / (zfar - znear);
        Mat4::from_cols(
            Vec4::new(s1, 0.0, 0.0, 0.0),
            Vec4::new(0.0, s2, 0.0, 0.0),
            Vec4::new(0.0, 0.0, z1, 1.0),
            Vec4::new(0.0, 0.0, z2, 0.0),
        )
    }

    /// The mapping from world points to pixels of a `width × height` image,
    /// with the reference clipping distances [`Camera::ZNEAR`] and
    /// [`Camera::ZFAR`].
    pub fn projection(&self, width: u32, height: u32) -> Projection {
        Projection::new(self, width, height)
    }
}

/// World → pixel mapping of one camera and image size, in `f64`.
///
/// Pixel coordinates run right and down from the image's top-left corner;
/// pixel `(i, j)` covers `[i, i+1) × [j, j+1)` and its center is
/// `(i + 0.5, j + 0.5)`. Pixels are square (the field of view is vertical).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Projection {
    /// World → view (x right, y up, z depth).
    view: DAffine3,
    /// Pixels per unit of `x / z` (and `y / z`).
    focal: f64,
    center: DVec2,
    znear: f64,
    zfar: f64,
    width: u32,
    height: u32,
}

impl Projection {
    /// The projection of `camera` onto a `width × height` image, clipping at
    /// [`Camera::ZNEAR`] and [`Camera::ZFAR`]. The field of view is clamped
    /// to [1°, 179°].
    pub fn new(camera: &Camera, width: u32, height: u32) -> Projection {
        let (r, u, f) = camera.axes_f64();
        let c = camera;
        let (st, ct) = f64::from(c.theta).sin_cos();
        let (sp, cp) = f64::from(c.phi).sin_cos();
        let eye = c.look_at.as_dvec3() + f64::from(c.radius) * DVec3::new(ct * cp, st, ct * sp);
        let rot = DMat3::from_cols(r, u, f).transpose();
        let fov = f64::from(c.fov_deg).clamp(1.0, 179.0).to_radians();
        Projection {
            view: DAffine3 { matrix3: rot, translation: -(rot * eye) },
            focal: 0.5 * f64::from(height) / (0.5 * fov).tan(),
            center: DVec2::new(0.5 * f64::from(width), 0.5 * f64::from(height)),
            znear: f64::from(Camera::ZNEAR),
            zfar: f64::from(Camera::ZFAR),
            width,
            height,
        }
    }

    /// The same projection clipping at other distances (the reference uses
    /// 200 as `zfar` in one scene).
    pub fn with_depth_range(self, znear: f32, zfar: f32) -> Projection {
        Projection { znear: f64::from(znear), zfar: f64::from(zfar), ..self }
    }

    /// Image width in pixels.
    pub fn width(&self) -> u32 {
        self.width
    }

    /// Image height in pixels.
    pub fn height(&self) -> u32 {
        self.height
    }

    /// Near clipping distance.
    pub fn znear(&self) -> f64 {
        self.znear
    }

    /// Far clipping distance.
    pub fn zfar(&self) -> f64 {
        self.zfar
    }

    /// Pixels per unit of `x / z`: half the height over `tan(fov / 2)`.
    pub fn focal(&self) -> f64 {
        self.focal
    }

    /// The image center in pixels, where `look_at` lands.
    pub fn center(&self) -> DVec2 {
        self.center
    }

    /// World → view space (x right, y up, z depth in front of the eye).
    pub fn view(&self) -> DAffine3 {
        self.view
    }

    /// A view-space point → pixel coordinates, whatever its depth (points
    /// behind the eye land mirrored; check the depth first).
    pub fn view_to_pixel(&self, v: DVec3) -> DVec2 {
        let iz = self.focal / v.z;
        DVec2::new(self.center.x + v.x * iz, self.center.y - v.y * iz)
    }

    /// Where the world point `p` lands, in pixel coordinates; `None` when it
    /// is nearer than `znear` or farther than `zfar` (or not finite). The
    /// result may lie outside the image.
    pub fn to_pixel(&self, p: Vec3) -> Option<Vec2> {
        let v = self.view.transform_point3(p.as_dvec3());
        (v.z >= self.znear && v.z <= self.zfar).then(|| self.view_to_pixel(v).as_vec2())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[allow(clippy::approx_constant)] // the reference's φ, not quite −π/2
    const SKETCH: Camera =
        Camera { fov_deg: 60.0, phi: -1.5708, theta: 0.0, radius: 9.4716, look_at: Vec3::new(-0.680994, 3.2558, 0.0) };

    #[test]
    fn eye_and_axes_follow_the_reference_formulas() {
        let c = Camera { fov_deg: 60.0, phi: 0.7, theta: 0.3, radius: 4.0, look_at: Vec3::new(1.0, 2.0, 3.0) };
        let expect =
            c.look_at + 4.0 * Vec3::new(0.3f32.cos() * 0.7f32.cos(), 0.3f32.sin(), 0.3f32.cos() * 0.7f32.sin());
        assert!((c.eye() - expect).length() < 1e-5);
        let (r, u, f) = c.axes();
        assert!((f + (c.eye() - c.look_at).normalize()).length() < 1e-5);
        assert!((r - Vec3::new(-0.7f32.sin(), 0.0, 0.7f32.cos())).length() < 1e-6);
        assert!((r - u.cross(f)).length() < 1e-6, "right = up × forward");
        assert!(u.y > 0.0 && r.dot(u).abs() < 1e-6 && u.dot(f).abs() < 1e-6);
        // Past the pole the picture turns upside down.
        let over = Camera { theta: 1.668, ..c };
        assert!(over.axes().1.y < 0.0);
    }

    #[test]
    fn look_at_lands_at_the_center_and_up_is_up() {
        let p = SKETCH.projection(800, 600);
        assert_eq!(p.to_pixel(SKETCH.look_at).unwrap().round(), Vec2::new(400.0, 300.0));
        let above = p.to_pixel(SKETCH.look_at + Vec3::Y).unwrap();
        assert!(above.y < 300.0 && (above.x - 400.0).abs() < 1e-3);
        // Behind the eye or beyond zfar: no pixel.
        assert!(p.to_pixel(SKETCH.eye() - 0.05 * SKETCH.axes().2).is_none());
        assert!(p.to_pixel(SKETCH.look_at + 200.0 * SKETCH.axes().2).is_none());
        assert!(p.with_depth_range(0.1, 300.0).to_pixel(SKETCH.look_at + 200.0 * SKETCH.axes().2).is_some());
    }

    #[test]
    fn tree_sketch_trunk_lands_bottom_center() {
        // The sketch's trunk (tree_target_sketch1.png) spans columns ≈ 407–461
        // and rows ≈ 390–540; a trunk at the origin must land there.
        let p = SKETCH.projection(800, 600);
        let base = p.to_pixel(Vec3::new(0.0, -0.8, 0.0)).unwrap();
        let top = p.to_pixel(Vec3::new(0.0, 1.0, 0.0)).unwrap();
        assert!((430.0..445.0).contains(&base.x), "{base}");
        assert!((510.0..535.0).contains(&base.y), "{base}");
        assert!((415.0..435.0).contains(&top.y), "{top}");
    }

    #[test]
    fn matrices_agree_with_the_projection() {
        let c = Camera { fov_deg: 50.0, phi: 2.1, theta: -0.4, radius: 7.0, look_at: Vec3::new(0.5, -1.0, 2.0) };
        let (w, h) = (320, 200);
        let clip = c.projection_matrix(w as f32 / h as f32, 0.1, 100.0) * c.view_matrix();
        let p = c.projection(w, h);
        for q in [Vec3::new(0.3, 0.2, 1.0), Vec3::new(-1.0, 1.5, 2.5), c.look_at] {
            let v = clip * q.extend(1.0);
            let ndc = v.truncate() / v.w;
            let px = Vec2::new((ndc.x + 1.0) * 0.5 * w as f32, (1.0 - ndc.y) * 0.5 * h as f32);
            assert!((px - p.to_pixel(q).unwrap()).length() < 1e-3, "{px} vs {:?}", p.to_pixel(q));
            assert!(ndc.z > -1.0 && ndc.z < 1.0);
        }
    }

    #[test]
    fn fit_frames_the_bounds() {
        let cam = Camera::fit((Vec3::new(-2.0, 0.0, -1.0), Vec3::new(2.0, 3.0, 1.0)));
        assert_eq!(cam.look_at, Vec3::new(0.0, 1.5, 0.0));
        let p = cam.projection(100, 100);
        for k in 0..8 {
            let corner = Vec3::new(
                if k & 1 == 0 { -2.0 } else { 2.0 },
                if k & 2 == 0 { 0.0 } else { 3.0 },
                if k & 4 == 0 { -1.0 } else { 1.0 },
            );
            let px = p.to_pixel(corner).unwrap();
            assert!(px.cmpge(Vec2::ZERO).all() && px.cmple(Vec2::splat(100.0)).all(), "{corner} → {px}");
        }
    }
}
