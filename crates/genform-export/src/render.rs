//! A small software rasterizer for PNG previews.

use crate::minecraft::{BlockMesh, block_color, shaped_block_meshes};
use crate::palette::{GuideRole, edge_color, guide_color, lighten, linear_to_srgb, srgb_to_linear, tag_color};
use crate::shapes::Shapes;
use genform_core::scene::{Mesh, Primitive, Scene, Tessellation, triangulate_polygon};
use genform_core::surface::{GuideKind, SurfaceEdge};
use glam::{Vec2, Vec3};
use std::sync::OnceLock;

pub use genform_core::camera::Camera;

/// The preview's right-handed view frame `(right, up, forward)`, with the
/// world's `+y` as up. It matches [`Camera::axes`] mirrored left-right
/// (`right` is negated) for |θ| < 90°: previews show models as a physical
/// camera would, while scorers use the reference renderer's mirrored frame.
fn preview_basis(cam: &Camera) -> (Vec3, Vec3, Vec3) {
    let (st, ct) = cam.theta.sin_cos();
    let (sp, cp) = cam.phi.sin_cos();
    let fwd = -Vec3::new(ct * cp, st, ct * sp).normalize_or(Vec3::NEG_Z);
    let world_up = if fwd.y.abs() > 0.999 { Vec3::new(-cp, 0.0, -sp) * fwd.y.signum() } else { Vec3::Y };
    let right = fwd.cross(world_up).normalize_or(Vec3::X);
    let up = right.cross(fwd);
    (right, up, fwd)
}

/// Tightens an auto-fitted view to the actual points: re-centers the image
/// on their projected extent and moves as close as they allow.
fn refine(cam: &mut Camera, aspect: f32, pts: &[Vec3]) {
    if pts.is_empty() {
        return;
    }
    let floor = cam.radius * 1e-3;
    for _ in 0..2 {
        let (right, up, fwd) = preview_basis(cam);
        let eye = cam.eye();
        let (mut lo, mut hi) = (Vec2::splat(f32::INFINITY), Vec2::splat(f32::NEG_INFINITY));
        for &p in pts {
            let q = p - eye;
            let z = q.dot(fwd).max(floor);
            let s = Vec2::new(q.dot(right) / z, q.dot(up) / z);
            (lo, hi) = (lo.min(s), hi.max(s));
        }
        let mid = (lo + hi) * 0.5;
        if mid.is_finite() {
            cam.look_at += cam.radius * (mid.x * right + mid.y * up);
        }
        let d = cam.fit_distance(aspect, pts.iter().copied());
        if d.is_finite() && d > floor {
            cam.radius = d;
        }
    }
}

/// The largest image side [`export`](crate::export) accepts for
/// [`Format::Png`](crate::Format::Png).
pub const MAX_IMAGE_SIDE: u32 = 8192;

/// Settings for [`render_png`] and [`render_rgb`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RenderOptions {
    /// Image width in pixels.
    pub width: u32,
    /// Image height in pixels.
    pub height: u32,
    /// The view; `None` fits a [`Camera::fit_aspect`] view to the scene bounds.
    pub camera: Option<Camera>,
    /// Background color, 8-bit sRGB.
    pub background: [u8; 3],
}

impl Default for RenderOptions {
    /// 800×600, auto-fitted camera, light grey background.
    fn default() -> Self {
        RenderOptions { width: 800, height: 600, camera: None, background: [236, 238, 241] }
    }
}

/// Renders `scene` to an RGB image and returns `(pixels, width, height)`,
/// pixels row by row from the top, 3 bytes each.
///
/// Perspective view, z-buffer, flat Lambert shading (a key light from the
/// upper left of the view, a weaker fill light and ambient), each tag in its
/// [`crate::tag_color`], 2×2 supersampling (for images up to 4 megapixels).
/// Built-in primitives are closed, so their back faces are culled; mesh
/// assets and polygons are two-sided, lit from whichever side faces the
/// camera. Polylines are drawn as lines of their stroke width (at least one
/// pixel). Block grids are drawn as their greedy meshes, each block in its
/// [`crate::minecraft::block_color`].
///
/// Surfaces are two-sided (split by
/// [`genform_core::scene::triangulate_polygon`]), their edges drawn over the faces (depth tested
/// with a small bias) in the colours of [`crate::edge_color`], typed edges
/// 1.5 pixels wide, untyped ones thinner. With several surfaces (a
/// derivation's steps overlaid) earlier ones are paler and later ones win
/// where they coincide. Guides are drawn faintly over the model: boundary
/// meshes as translucent lit faces, points as discs of their radius (at
/// least 6 pixels across), blue for attractors and red for repellers (tag
/// names containing `attract` / `repel`; a `#rrggbb` tag suffix wins).
///
/// With no camera given, the view is a [`Camera::fit_aspect`] 3/4
/// view tightened to the actual geometry; guides do not count for it (they
/// may lie partly outside the image).
///
/// A flat drawing (no instances, every point at z = 0, such as a 2D
/// turtle's) with no camera given is drawn instead as [`crate::write_svg`]
/// draws it, rendered by resvg: seen from +z, fitted to the image with its
/// aspect ratio kept and centred, anti-aliased, strokes at least 1.5 pixels
/// wide. Instances are
/// tessellated with [`Tessellation::default`]. An empty scene gives a plain
/// background. The size is clamped to `1..=`[`crate::MAX_IMAGE_SIDE`].
///
/// # Panics
///
/// If an instance refers to a missing mesh asset (see [`crate::export`],
/// which checks). Surfaces naming missing vertices are left out.
pub fn render_rgb(scene: &Scene, opts: &RenderOptions) -> (Vec<u8>, u32, u32) {
    render_rgb_with(scene, opts, Tessellation::default())
}

/// [`render_rgb`], encoded as PNG (8-bit RGB).
///
/// # Panics
///
/// If an instance refers to a missing mesh asset (see [`crate::export`],
/// which checks).
pub fn render_png(scene: &Scene, opts: &RenderOptions) -> Vec<u8> {
    render_png_with(scene, opts, Tessellation::default())
}

pub(crate) fn render_png_with(scene: &Scene, opts: &RenderOptions, tess: Tessellation) -> Vec<u8> {
    let (rgb, w, h) = render_rgb_with(scene, opts, tess);
    crate::plot::encode_png_rgb(&rgb, w, h)
}

pub(crate) fn render_rgb_with(scene: &Scene, opts: &RenderOptions, tess: Tessellation) -> (Vec<u8>, u32, u32) {
    render_backdrop_with(scene, opts, &Backdrop::default(), tess)
}

/// What a preview shows beside a scene that is not part of it: the target
/// a model was evolved toward, so a picture shows how well it fits.
#[derive(Clone, Copy, Debug, Default)]
pub struct Backdrop<'a> {
    /// Meshes in world coordinates drawn as tinted glass: translucent, lit,
    /// two-sided faces over the model where they are in front of it and
    /// hidden where they are behind it. A fitted camera frames them too.
    pub ghosts: &'a [Mesh],
    /// A picture behind everything: `width × height` RGB pixels of the
    /// options, rows from the top, in the picture's frame (see `mirrored`).
    /// Ignored unless its size matches.
    pub image: Option<&'a [u8]>,
    /// Mirror the preview left-right: the frame of the image scorers
    /// ([`Camera::axes`]), so a model seen through a target's camera lines
    /// up with the target picture.
    pub mirrored: bool,
}

/// Opacity of ghost faces out of 256: each layer tints a little, so the
/// front and back of a target volume together still let the model show.
const GHOST_ALPHA: u32 = 60;

/// Colour of ghost faces (8-bit sRGB): a blue that no tag colour of the
/// model is likely to be mistaken for once translucent.
const GHOST_COLOR: [u8; 3] = [0x3d, 0x7b, 0xe0];

/// [`render_rgb`] with a [`Backdrop`]: target meshes as glass and/or a
/// target picture behind the model. With an empty backdrop it is
/// [`render_rgb`] except that flat drawings and block tiles are drawn in
/// perspective too (one code path for every frame of an animation).
pub fn render_rgb_over(scene: &Scene, opts: &RenderOptions, backdrop: &Backdrop) -> (Vec<u8>, u32, u32) {
    render_backdrop_with(scene, opts, backdrop, Tessellation::default())
}

fn render_backdrop_with(
    scene: &Scene,
    opts: &RenderOptions,
    backdrop: &Backdrop,
    tess: Tessellation,
) -> (Vec<u8>, u32, u32) {
    let w = opts.width.clamp(1, MAX_IMAGE_SIDE);
    let h = opts.height.clamp(1, MAX_IMAGE_SIDE);
    let plain = backdrop.ghosts.is_empty() && backdrop.image.is_none() && !backdrop.mirrored;
    if !plain {
        return render_over(scene, opts, backdrop, tess, w, h);
    }
    if opts.camera.is_none()
        && crate::flat::is_flat(scene)
        && let Some(rgb) = crate::flat::render_rgb(scene, w, h, opts.background, tess)
    {
        return (rgb, w, h);
    }
    if opts.camera.is_none()
        && let Some(grid) = crate::minecraft::flat_grid(scene)
    {
        return (crate::minecraft::render_tiles(grid, w, h, opts.background), w, h);
    }
    let ss = supersampling(w, h);
    let mut r = Raster::new(w as usize * ss, h as usize * ss, pack(opts.background));
    if !scene.is_empty() || !scene.blocks.is_empty() {
        draw_scene(&mut r, scene, opts.camera, &[], tess, ss);
    }
    (r.downsample(ss, w as usize, h as usize), w, h)
}

/// Samples per pixel side: 2 for images up to 4 megapixels.
fn supersampling(w: u32, h: u32) -> usize {
    if u64::from(w) * u64::from(h) <= 4 << 20 { 2 } else { 1 }
}

/// The perspective path of [`render_rgb_over`]. Mirroring is done on the
/// finished picture (and the backdrop picture is mirrored in first), so
/// the rasterizer keeps its one frame.
fn render_over(
    scene: &Scene,
    opts: &RenderOptions,
    b: &Backdrop,
    tess: Tessellation,
    w: u32,
    h: u32,
) -> (Vec<u8>, u32, u32) {
    let ss = supersampling(w, h);
    let (wu, hu) = (w as usize, h as usize);
    let mut r = Raster::new(wu * ss, hu * ss, pack(opts.background));
    if let Some(img) = b.image.filter(|i| i.len() == wu * hu * 3) {
        for y in 0..hu * ss {
            for x in 0..wu * ss {
                let (px, py) = (x / ss, y / ss);
                let px = if b.mirrored { wu - 1 - px } else { px };
                let i = 3 * (py * wu + px);
                r.samples[y * r.w + x] = u64::from(pack([img[i], img[i + 1], img[i + 2]]));
            }
        }
    }
    draw_scene(&mut r, scene, opts.camera, b.ghosts, tess, ss);
    let mut rgb = r.downsample(ss, wu, hu);
    if b.mirrored {
        for row in rgb.chunks_exact_mut(wu * 3) {
            for x in 0..wu / 2 {
                for c in 0..3 {
                    row.swap(3 * x + c, 3 * (wu - 1 - x) + c);
                }
            }
        }
    }
    (rgb, w, h)
}

/// The fitted 3/4 view of everything drawn (the scene, its block meshes
/// and `ghosts`) for an image of `aspect = width / height`.
fn auto_camera(scene: &Scene, shapes: &Shapes, blocks: &[BlockMesh], ghosts: &[Mesh], aspect: f32) -> Camera {
    let mut pts = Vec::new();
    finite_points(scene, shapes, |p| pts.push(p));
    pts.extend(blocks.iter().flat_map(|m| m.mesh.positions.iter().copied()));
    pts.extend(ghosts.iter().flat_map(|m| m.positions.iter().copied()).filter(|p| p.is_finite()));
    let bounds = |pts: &[Vec3]| {
        pts.iter().fold(None, |b: Option<(Vec3, Vec3)>, &p| Some(b.map_or((p, p), |(lo, hi)| (lo.min(p), hi.max(p)))))
    };
    let mut b = bounds(&pts);
    // Guides near the model (an environment's box, its charges) are framed
    // with it, so the picture shows them whole; guides far away (a boundary
    // many times the model's size) would shrink the model to a speck, so
    // the frame is the model's alone then.
    if let Some((lo, hi)) = b {
        let limit = GUIDE_FRAME_GROWTH * (hi - lo).length().max(f32::EPSILON);
        for guide in &scene.guides {
            let near = guide_points(guide);
            if let Some((glo, ghi)) = bounds(&near)
                && (hi.max(ghi) - lo.min(glo)).length() <= limit
            {
                pts.extend(near);
            }
        }
        b = bounds(&pts);
    }
    let mut cam = Camera::fit_aspect(b.unwrap_or((Vec3::splat(-0.5), Vec3::splat(0.5))), aspect);
    refine(&mut cam, aspect, &pts);
    cam
}

/// How much larger than the model's own bounds (diagonal) the bounds with
/// a guide may be for that guide to be framed too.
const GUIDE_FRAME_GROWTH: f32 = 3.0;

/// The finite points of a guide as drawn: a mesh's corners, a point
/// marker's centre ± its radius along each axis.
fn guide_points(g: &genform_core::surface::Guide) -> Vec<Vec3> {
    match &g.kind {
        GuideKind::Mesh(mesh) => mesh.positions.iter().copied().filter(|p| p.is_finite()).collect(),
        GuideKind::Point { at, radius } if at.is_finite() && radius.is_finite() => {
            let r = radius.abs();
            [Vec3::X, Vec3::Y, Vec3::Z].iter().flat_map(|&d| [*at + d * r, *at - d * r]).collect()
        }
        GuideKind::Point { .. } => Vec::new(),
    }
}

/// The camera [`render_rgb`] fits to `scene` when
/// [`RenderOptions::camera`] is `None`, for an image of `width × height`.
/// Rendering several scenes through the camera fitted to all of them
/// together shows them at one scale, e.g. the steps of a growth, each
/// drawn alone but in the frame of the last.
pub fn fitted_camera(scene: &Scene, width: u32, height: u32) -> Camera {
    let shapes = Shapes::new(scene, Tessellation::default());
    let blocks = shaped_block_meshes(scene);
    auto_camera(scene, &shapes, &blocks, &[], width.max(1) as f32 / height.max(1) as f32)
}

/// Draws instances, polygons and polylines into `r` (`ss` samples per pixel
/// side).
fn draw_scene(r: &mut Raster, scene: &Scene, camera: Option<Camera>, ghosts: &[Mesh], tess: Tessellation, ss: usize) {
    let shapes = Shapes::new(scene, tess);
    let blocks = shaped_block_meshes(scene);
    let camera = camera.unwrap_or_else(|| auto_camera(scene, &shapes, &blocks, ghosts, r.w as f32 / r.h as f32));
    let view = View::new(&camera, r.w, r.h);
    let colors: Vec<[f32; 3]> = scene.tags.iter().map(|t| tag_color(t).map(srgb_to_linear)).collect();
    let color_of = |tag: u32| colors.get(tag as usize).copied().unwrap_or([0.5; 3]);

    // Per instance: vertices to world and camera space once, then its
    // triangles. Built-in primitives are closed, so their back faces are
    // culled; mesh assets and polygons may be open and are two-sided.
    let mut verts: Vec<Vertex> = Vec::new();
    for (i, inst) in scene.instances.iter().enumerate() {
        let mesh = shapes.of(i);
        verts.clear();
        verts.extend(mesh.positions.iter().map(|&p| view.vertex(inst.transform.transform_point3(p))));
        if verts.iter().all(|v| v.cam.z < view.near) {
            continue;
        }
        let flip = inst.transform.matrix3.determinant() < 0.0;
        let closed = !matches!(inst.primitive, Primitive::Mesh(_));
        let color = color_of(inst.tag);
        for t in &mesh.triangles {
            let [a, b, c] = t.map(|v| &verts[v as usize]);
            let (b, c) = if flip { (c, b) } else { (b, c) };
            view.draw(r, [a, b, c], color, closed);
        }
    }
    // Block meshes are closed where seen from outside: cull back faces.
    // Slabs, stairs, doors, panes, fences and the like are drawn in their
    // shapes (`shaped_block_meshes`), other blocks as whole cubes.
    for m in &blocks {
        let color = block_color(&m.state).map(srgb_to_linear);
        verts.clear();
        verts.extend(m.mesh.positions.iter().map(|&p| view.vertex(p)));
        for t in &m.mesh.triangles {
            view.draw(r, t.map(|v| &verts[v as usize]), color, true);
        }
    }
    for poly in &scene.polygons {
        let color = color_of(poly.tag);
        verts.clear();
        verts.extend(poly.points.iter().map(|&p| view.vertex(p)));
        for t in triangulate_polygon(&poly.points) {
            view.draw(r, t.map(|k| &verts[k as usize]), color, false);
        }
    }
    let min_half_width = 0.5 * ss as f32;
    for line in &scene.polylines {
        let c = shade(color_of(line.tag), 0.8);
        for seg in line.points.windows(2) {
            if seg.iter().all(|p| p.is_finite()) {
                r.segment(&view, [seg[0], seg[1]], line.width.max(0.0), min_half_width, c);
            }
        }
    }
    draw_surfaces(r, scene, &view, ss, &colors);
    draw_guides(r, scene, &view, ss);
    let ghost = GHOST_COLOR.map(srgb_to_linear);
    for mesh in ghosts {
        verts.clear();
        verts.extend(mesh.positions.iter().map(|&p| view.vertex(p)));
        for t in &mesh.triangles {
            if t.iter().all(|&v| (v as usize) < verts.len()) {
                view.draw_with(r, t.map(|v| &verts[v as usize]), ghost, false, Paint::Blend(GHOST_ALPHA));
            }
        }
    }
}

/// The surfaces' faces (two-sided) and their edges on top.
fn draw_surfaces(r: &mut Raster, scene: &Scene, view: &View, ss: usize, colors: &[[f32; 3]]) {
    let n = scene.surfaces.len();
    let mut verts: Vec<Vertex> = Vec::new();
    for (k, s) in scene.surfaces.iter().enumerate() {
        if !crate::surfaces::well_formed(s) {
            continue;
        }
        // Earlier steps of a stack paler; later ones win depth ties. Faces
        // a little lighter than the tag colour so the edges stand out.
        let pale = if n > 1 { 0.6 * (n - 1 - k) as f32 / (n - 1) as f32 } else { 0.0 };
        let tag_rgb = colors.get(s.tag as usize).copied().unwrap_or([0.5; 3]);
        let color = tag_rgb.map(|c| c + (1.0 - c) * (0.25 + 0.75 * pale));
        let bias = 1.0 + 2e-5 * k as f32;
        verts.clear();
        verts.extend(s.positions.iter().map(|&p| view.vertex(p)));
        for t in crate::surfaces::triangles(s) {
            view.draw_with(r, t.map(|v| &verts[v as usize]), color, false, Paint::Opaque(bias));
        }
        for e in &s.edges {
            let (a, b) = (s.positions[e.a as usize], s.positions[e.b as usize]);
            if e.a == e.b || !a.is_finite() || !b.is_finite() {
                continue;
            }
            let half = if e.kind == SurfaceEdge::UNTYPED { 0.4 } else { 0.75 };
            r.segment(view, [a, b], 0.0, half * ss as f32, pack(lighten(edge_color(e.kind), pale)));
        }
    }
}

/// Guides, faintly: point markers as discs, then meshes translucent.
fn draw_guides(r: &mut Raster, scene: &Scene, view: &View, ss: usize) {
    let name = |tag: u32| scene.tags.get(tag as usize).map_or("", String::as_str);
    for g in &scene.guides {
        if let GuideKind::Point { at, radius } = g.kind {
            let c = view.to_camera(at);
            if !(c.z >= view.near && c.is_finite()) {
                continue;
            }
            let center = view.project(c);
            let px = (radius.abs() * view.focal * center.z).max(3.0 * ss as f32);
            let role = GuideRole::of(name(g.tag));
            let alpha = if role == GuideRole::Other { 120 } else { 200 };
            r.disc(center, px, pack(guide_color(name(g.tag))), alpha);
        }
    }
    let mut verts: Vec<Vertex> = Vec::new();
    for g in &scene.guides {
        if let GuideKind::Mesh(mesh) = &g.kind {
            let color = guide_color(name(g.tag)).map(srgb_to_linear);
            verts.clear();
            verts.extend(mesh.positions.iter().map(|&p| view.vertex(p)));
            for t in &mesh.triangles {
                if t.iter().all(|&v| (v as usize) < verts.len()) {
                    view.draw_with(r, t.map(|v| &verts[v as usize]), color, false, Paint::Blend(56));
                }
            }
        }
    }
}

/// How [`View::draw_with`] paints.
#[derive(Clone, Copy)]
enum Paint {
    /// Depth-tested and written; the inverse depth scaled by the bias
    /// (above 1 pulls toward the eye).
    Opaque(f32),
    /// Depth-tested, not written: the colour mixed over what is there with
    /// this opacity out of 256.
    Blend(u32),
}

/// Calls `f` with every finite instance vertex (of meshes with triangles),
/// polygon point, polyline point and surface vertex (guides left out).
fn finite_points(scene: &Scene, shapes: &Shapes, mut f: impl FnMut(Vec3)) {
    let mut add = |p: Vec3| {
        if p.is_finite() {
            f(p);
        }
    };
    for (i, inst) in scene.instances.iter().enumerate() {
        let mesh = shapes.of(i);
        if !mesh.triangles.is_empty() {
            mesh.positions.iter().for_each(|&p| add(inst.transform.transform_point3(p)));
        }
    }
    scene.polygons.iter().filter(|p| p.points.len() >= 3).flat_map(|p| p.points.iter().copied()).for_each(&mut add);
    scene.polylines.points().iter().copied().for_each(&mut add);
    scene.surfaces.iter().flat_map(|s| s.positions.iter().copied()).for_each(add);
}

fn pack([r, g, b]: [u8; 3]) -> u32 {
    u32::from(r) << 16 | u32::from(g) << 8 | u32::from(b)
}

/// A linear color times a light intensity, packed as sRGB.
fn shade(c: [f32; 3], light: f32) -> u32 {
    // Linear → sRGB through a table (12-bit linear input).
    static LUT: OnceLock<Vec<u8>> = OnceLock::new();
    let lut = LUT.get_or_init(|| (0..=4096).map(|i| linear_to_srgb(i as f32 / 4096.0)).collect());
    pack(c.map(|x| lut[(x * light * 4096.0).round().clamp(0.0, 4096.0) as usize]))
}

/// The camera frame and projection at sample resolution.
struct View {
    eye: Vec3,
    right: Vec3,
    up: Vec3,
    fwd: Vec3,
    /// Focal length in samples.
    focal: f32,
    center: Vec2,
    near: f32,
    /// Unit vector toward the key light.
    key: Vec3,
    /// Unit vector toward the fill light.
    fill: Vec3,
}

impl View {
    fn new(cam: &Camera, w: usize, h: usize) -> View {
        let (right, up, fwd) = preview_basis(cam);
        let fov = cam.fov_deg.clamp(1.0, 170.0).to_radians();
        View {
            eye: cam.eye(),
            right,
            up,
            fwd,
            focal: 0.5 * h as f32 / (0.5 * fov).tan(),
            center: Vec2::new(0.5 * w as f32, 0.5 * h as f32),
            near: (cam.radius.abs() * 1e-4).max(1e-6),
            key: (-0.45 * right + 0.75 * up - 0.5 * fwd).normalize(),
            fill: (0.6 * right - 0.2 * up - 0.75 * fwd).normalize(),
        }
    }

    /// World → camera space (`z` = depth in front of the eye).
    fn to_camera(&self, p: Vec3) -> Vec3 {
        let d = p - self.eye;
        Vec3::new(d.dot(self.right), d.dot(self.up), d.dot(self.fwd))
    }

    /// A world-space point with its camera-space and screen positions.
    fn vertex(&self, world: Vec3) -> Vertex {
        let cam = self.to_camera(world);
        let screen = if cam.z >= self.near { self.project(cam) } else { Vec3::ZERO };
        Vertex { world, cam, screen }
    }

    /// Shades and rasterizes one counter-clockwise triangle: flat Lambert
    /// from the key and fill lights plus ambient. A `closed` surface's back
    /// faces are culled; otherwise the side facing the eye is lit.
    fn draw(&self, r: &mut Raster, tri: [&Vertex; 3], color: [f32; 3], closed: bool) {
        self.draw_with(r, tri, color, closed, Paint::Opaque(1.0));
    }

    /// [`View::draw`] with a choice of paint.
    fn draw_with(&self, r: &mut Raster, [a, b, c]: [&Vertex; 3], color: [f32; 3], closed: bool, paint: Paint) {
        let n = (b.world - a.world).cross(c.world - a.world);
        let facing = n.dot(self.eye - a.world);
        // Also rejects NaN.
        if !(facing > 0.0 || (!closed && facing < 0.0)) {
            return;
        }
        let n = n.normalize_or_zero() * facing.signum();
        let light = 0.28 + 0.72 * n.dot(self.key).max(0.0) + 0.18 * n.dot(self.fill).max(0.0);
        let c32 = shade(color, light);
        let mut fill = |v: [Vec3; 3]| match paint {
            Paint::Opaque(bias) => r.triangle(v, c32, bias),
            Paint::Blend(alpha) => r.blend_triangle(v, c32, alpha),
        };
        if a.cam.z >= self.near && b.cam.z >= self.near && c.cam.z >= self.near {
            fill([a.screen, b.screen, c.screen]);
        } else {
            let (pts, k) = clip_near([a.cam, b.cam, c.cam], self.near);
            for i in 1..k.saturating_sub(1) {
                fill([pts[0], pts[i], pts[i + 1]].map(|p| self.project(p)));
            }
        }
    }

    /// Camera space (in front of the near plane) → sample coordinates and
    /// inverse depth.
    fn project(&self, c: Vec3) -> Vec3 {
        let iz = 1.0 / c.z;
        Vec3::new(self.center.x + c.x * iz * self.focal, self.center.y - c.y * iz * self.focal, iz)
    }
}

/// `x.floor()` as an integer, without a libm call (saturating; NaN is 0).
fn floor_i64(x: f32) -> i64 {
    let i = x as i64;
    if (i as f32) > x { i - 1 } else { i }
}

/// `x.ceil()` as an integer, without a libm call (saturating; NaN is 0).
fn ceil_i64(x: f32) -> i64 {
    let i = x as i64;
    if (i as f32) < x { i + 1 } else { i }
}

/// A vertex in world, camera and (when in front of the near plane) screen
/// space: sample x, sample y, inverse depth.
struct Vertex {
    world: Vec3,
    cam: Vec3,
    screen: Vec3,
}

/// Clips a camera-space triangle to `z >= near`: up to 4 points.
fn clip_near(t: [Vec3; 3], near: f32) -> ([Vec3; 4], usize) {
    let mut out = [Vec3::ZERO; 4];
    let mut k = 0;
    for i in 0..3 {
        let (a, b) = (t[i], t[(i + 1) % 3]);
        let (ina, inb) = (a.z >= near, b.z >= near);
        if ina {
            out[k] = a;
            k += 1;
        }
        if ina != inb {
            let s = (near - a.z) / (b.z - a.z);
            out[k] = a.lerp(b, s);
            out[k].z = near;
            k += 1;
        }
    }
    (out, k)
}

/// A sample with `color` mixed into its colour at opacity `alpha` out of
/// 256 (in sRGB, as previews do), its depth kept.
fn blend(sample: u64, color: u32, alpha: u32) -> u64 {
    let (dst, a) = (sample as u32, alpha.min(256));
    // Red and blue side by side in one word, green apart: no overlap.
    let rb = (((dst & 0xFF00FF) * (256 - a) + (color & 0xFF00FF) * a) >> 8) & 0xFF00FF;
    let g = (((dst & 0xFF00) * (256 - a) + (color & 0xFF00) * a) >> 8) & 0xFF00;
    (sample & !0xFFFF_FFFF) | u64::from(rb | g)
}

/// One buffer of samples: the inverse depth's bits in the high half, the
/// packed color in the low half. Inverse depths are non-negative, so their
/// bits order like the values and a depth test is an integer `max`.
struct Raster {
    w: usize,
    h: usize,
    samples: Vec<u64>,
}

impl Raster {
    fn new(w: usize, h: usize, background: u32) -> Raster {
        Raster { w, h, samples: vec![u64::from(background); w * h] }
    }

    /// Fills a triangle given as (sample x, sample y, inverse depth) per
    /// vertex, either winding. Samples sit at pixel centers; an edge passing
    /// exactly through one covers it. `bias` scales the inverse depth
    /// (above 1 pulls toward the eye).
    fn triangle(&mut self, v: [Vec3; 3], color: u32, bias: f32) {
        let color = u64::from(color);
        // Branch-free depth test (visibility flips are unpredictable).
        self.scan(v, bias, |s, iz| s.max(u64::from(iz.to_bits()) << 32 | color));
    }

    /// Mixes `color` into the samples of a triangle (as [`Raster::triangle`]
    /// places it) that it is not behind, with opacity `alpha` out of 256,
    /// leaving their depth.
    fn blend_triangle(&mut self, v: [Vec3; 3], color: u32, alpha: u32) {
        self.scan(v, 1.0, |s, iz| if iz.to_bits() >= (s >> 32) as u32 { blend(s, color, alpha) } else { s });
    }

    /// Mixes `color` into the samples within `radius` of `center` (sample
    /// x, sample y, inverse depth) with opacity `alpha` out of 256, a third
    /// of that where the disc is behind what is drawn: a flat disc facing
    /// the eye.
    fn disc(&mut self, center: Vec3, radius: f32, color: u32, alpha: u32) {
        let iz = center.z.max(0.0).to_bits();
        let (x0, x1) = ((center.x - radius - 0.5).ceil().max(0.0), (center.x + radius - 0.5).floor());
        let (y0, y1) = ((center.y - radius - 0.5).ceil().max(0.0), (center.y + radius - 0.5).floor());
        let (x1, y1) = (x1.min(self.w as f32 - 1.0), y1.min(self.h as f32 - 1.0));
        if !(x0 <= x1 && y0 <= y1) {
            return;
        }
        for y in y0 as usize..=y1 as usize {
            for x in x0 as usize..=x1 as usize {
                let d = Vec2::new(x as f32 + 0.5, y as f32 + 0.5) - center.truncate();
                let s = &mut self.samples[y * self.w + x];
                if d.length_squared() <= radius * radius {
                    // Behind something: still there, fainter.
                    let a = if iz >= (*s >> 32) as u32 { alpha } else { alpha / 3 };
                    *s = blend(*s, color, a);
                }
            }
        }
    }

    /// Calls `op(sample, inverse depth)` on every sample a triangle covers
    /// and stores what it returns. The triangle is given as (sample x,
    /// sample y, inverse depth) per vertex, either winding. Samples sit at
    /// pixel centers; an edge passing exactly through one covers it. `bias`
    /// scales the inverse depth.
    #[inline(always)]
    fn scan(&mut self, v: [Vec3; 3], bias: f32, op: impl Fn(u64, f32) -> u64) {
        let [a, mut b, mut c] = v;
        let edge = |p: Vec3, q: Vec3, x: f32, y: f32| (q.x - p.x) * (y - p.y) - (q.y - p.y) * (x - p.x);
        let mut area = edge(a, b, c.x, c.y);
        if !area.is_finite() || area == 0.0 {
            return;
        }
        if area < 0.0 {
            std::mem::swap(&mut b, &mut c);
            area = -area;
        }
        let min = a.min(b).min(c);
        let max = a.max(b).max(c);
        let x0 = (min.x - 0.5).ceil().max(0.0);
        let y0 = (min.y - 0.5).ceil().max(0.0);
        let x1 = (max.x - 0.5).floor().min(self.w as f32 - 1.0);
        let y1 = (max.y - 0.5).floor().min(self.h as f32 - 1.0);
        if x0 > x1 || y0 > y1 {
            return;
        }
        let (x0, y0, x1, y1) = (x0 as usize, y0 as usize, x1 as usize, y1 as usize);
        // Edge functions at the first sample of the row and their steps;
        // e[0] weighs a. Inverse depth is affine in the edge functions.
        let (px, py) = (x0 as f32 + 0.5, y0 as f32 + 0.5);
        let mut row = [edge(b, c, px, py), edge(c, a, px, py), edge(a, b, px, py)];
        let dx = [b.y - c.y, c.y - a.y, a.y - b.y];
        let dy = [c.x - b.x, a.x - c.x, b.x - a.x];
        let z = [a.z, b.z, c.z].map(|z| z * bias / area);
        let z_dx = dx[0] * z[0] + dx[1] * z[1] + dx[2] * z[2];
        let inv_dx = dx.map(|d| if d == 0.0 { 0.0 } else { 1.0 / d });
        let span = (x1 - x0) as i64;
        for y in y0..=y1 {
            // The run of samples inside all three edges, as offsets from x0.
            let (mut lo, mut hi) = (0i64, span);
            for k in 0..3 {
                if dx[k] > 0.0 {
                    lo = lo.max(ceil_i64(-row[k] * inv_dx[k]));
                } else if dx[k] < 0.0 {
                    hi = hi.min(floor_i64(-row[k] * inv_dx[k]));
                } else if row[k] < 0.0 {
                    hi = -1;
                }
            }
            if lo <= hi {
                let (lo, hi) = (x0 + lo as usize, x0 + hi as usize);
                let line = y * self.w;
                let iz0 = row[0] * z[0] + row[1] * z[1] + row[2] * z[2] + (lo - x0) as f32 * z_dx;
                for (i, s) in self.samples[line + lo..=line + hi].iter_mut().enumerate() {
                    let iz = (iz0 + i as f32 * z_dx).max(0.0);
                    *s = op(*s, iz);
                }
            }
            for k in 0..3 {
                row[k] += dy[k];
            }
        }
    }

    /// Draws a world-space line segment as a screen-space quad of the
    /// projected stroke width (at least `2 * min_half` samples), with square
    /// caps and a little depth bias so lines on surfaces show.
    fn segment(&mut self, view: &View, [p, q]: [Vec3; 2], width: f32, min_half: f32, color: u32) {
        let (mut a, mut b) = (view.to_camera(p), view.to_camera(q));
        if a.z < view.near && b.z < view.near {
            return;
        }
        if a.z < view.near {
            a = b.lerp(a, (b.z - view.near) / (b.z - a.z));
            a.z = view.near;
        } else if b.z < view.near {
            b = a.lerp(b, (a.z - view.near) / (a.z - b.z));
            b.z = view.near;
        }
        let (sa, sb) = (view.project(a), view.project(b));
        let dir = (sb - sa).truncate();
        let len = dir.length();
        if !len.is_finite() {
            return;
        }
        let dir = if len > 1e-6 { dir / len } else { Vec2::X };
        let normal = dir.perp();
        let half = |s: Vec3| (0.5 * width * view.focal * s.z).max(min_half);
        let (ha, hb) = (half(sa), half(sb));
        let corner = |s: Vec3, h: f32, side: f32, cap: f32| {
            let xy = s.truncate() + normal * (side * h) + dir * (cap * h);
            Vec3::new(xy.x, xy.y, s.z)
        };
        let quad = [
            corner(sa, ha, -1.0, -1.0),
            corner(sb, hb, -1.0, 1.0),
            corner(sb, hb, 1.0, 1.0),
            corner(sa, ha, 1.0, -1.0),
        ];
        self.triangle([quad[0], quad[1], quad[2]], color, 1.002);
        self.triangle([quad[0], quad[2], quad[3]], color, 1.002);
    }

    /// Box-filters `ss × ss` samples into each of `w × h` RGB pixels.
    fn downsample(&self, ss: usize, w: usize, h: usize) -> Vec<u8> {
        let mut out = Vec::with_capacity(w * h * 3);
        if ss == 1 {
            out.extend(self.samples.iter().flat_map(|&c| [(c >> 16) as u8, (c >> 8) as u8, c as u8]));
            return out;
        }
        debug_assert_eq!(ss, 2);
        let rows = || self.samples.chunks_exact(self.w);
        for (top, bottom) in rows().step_by(2).zip(rows().skip(1).step_by(2)) {
            for (t, b) in top.chunks_exact(2).zip(bottom.chunks_exact(2)) {
                let (t, b) = ([t[0] as u32, t[1] as u32], [b[0] as u32, b[1] as u32]);
                // Red and blue summed side by side in one word (no overlap:
                // each sum is at most 1020), green on its own.
                let rb = (t[0] & 0xFF00FF) + (t[1] & 0xFF00FF) + (b[0] & 0xFF00FF) + (b[1] & 0xFF00FF);
                let g = (t[0] & 0xFF00) + (t[1] & 0xFF00) + (b[0] & 0xFF00) + (b[1] & 0xFF00);
                out.extend([((rb >> 16) + 2) >> 2, ((g >> 8) + 2) >> 2, ((rb & 0xFFFF) + 2) >> 2].map(|v| v as u8));
            }
        }
        debug_assert_eq!(out.len(), w * h * 3);
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::test_scenes;

    fn pixel(rgb: &[u8], w: u32, x: u32, y: u32) -> [u8; 3] {
        let i = 3 * (y * w + x) as usize;
        [rgb[i], rgb[i + 1], rgb[i + 2]]
    }

    #[test]
    fn a_box_fills_the_middle() {
        let s = test_scenes::boxes(1);
        let opts = RenderOptions { width: 200, height: 150, ..Default::default() };
        let png_bytes = render_png(&s, &opts);
        let decoder = png::Decoder::new(std::io::Cursor::new(&png_bytes));
        let mut reader = decoder.read_info().unwrap();
        let mut buf = vec![0; reader.output_buffer_size().unwrap()];
        let info = reader.next_frame(&mut buf).unwrap();
        assert_eq!((info.width, info.height, info.color_type), (200, 150, png::ColorType::Rgb));
        let rgb = &buf[..info.buffer_size()];
        let bg = opts.background;
        assert_ne!(pixel(rgb, 200, 100, 75), bg);
        for (x, y) in [(0, 0), (199, 0), (0, 149), (199, 149)] {
            assert_eq!(pixel(rgb, 200, x, y), bg);
        }
        // Three faces are visible, each lit differently.
        let (raw, _, _) = render_rgb(&s, &opts);
        assert_eq!(raw, rgb);
        let mut shades: Vec<[u8; 3]> = raw.chunks(3).map(|c| [c[0], c[1], c[2]]).filter(|&c| c != bg).collect();
        shades.sort();
        shades.dedup();
        assert!(shades.len() >= 3);
    }

    /// A cube mesh of side 2 around `center`, as a target volume would be.
    fn cube(center: Vec3) -> Mesh {
        let mut s = Scene::new();
        let tag = s.tag("t");
        s.instances.push(genform_core::scene::Instance {
            transform: glam::Affine3A::from_scale_rotation_translation(Vec3::splat(2.0), Default::default(), center),
            primitive: Primitive::Box,
            tag,
        });
        let mut m = Mesh::default();
        s.for_each_triangle(Tessellation::default(), |t, _| {
            let i = m.positions.len() as u32;
            m.positions.extend(t);
            m.triangles.push([i, i + 1, i + 2]);
        });
        m
    }

    #[test]
    fn ghosts_tint_only_where_they_are_and_fitted_views_frame_them() {
        let s = test_scenes::boxes(1);
        let cam = Camera::fit((Vec3::splat(-3.0), Vec3::splat(3.0)));
        let opts = RenderOptions { width: 120, height: 90, camera: Some(cam), ..Default::default() };
        let (plain, _, _) = render_rgb(&s, &opts);
        assert_eq!(render_rgb_over(&s, &opts, &Backdrop::default()).0, plain, "an empty backdrop changes nothing");
        let ghost = [cube(Vec3::ZERO)];
        let (glass, _, _) = render_rgb_over(&s, &opts, &Backdrop { ghosts: &ghost, ..Default::default() });
        let bg = opts.background;
        let differ = |x: u32, y: u32| pixel(&glass, 120, x, y) != pixel(&plain, 120, x, y);
        assert!(differ(60, 45), "the ghost is in front of the box's middle: tinted");
        assert!(!differ(0, 0) && pixel(&glass, 120, 0, 0) == bg, "no ghost in the corner");
        let (tinted, under) = (pixel(&glass, 120, 60, 45), pixel(&plain, 120, 60, 45));
        let blueness = |c: [u8; 3]| i32::from(c[2]) - i32::from(c[0]);
        assert!(blueness(tinted) > blueness(under), "the tint is blue: {tinted:?} over {under:?}");
        // Without a camera, a ghost far from the model still ends up in the picture.
        let far = [cube(Vec3::new(0.0, 0.0, 12.0))];
        let fit = RenderOptions { width: 120, height: 90, ..Default::default() };
        let (both, _, _) = render_rgb_over(&s, &fit, &Backdrop { ghosts: &far, ..Default::default() });
        let (alone, _, _) = render_rgb(&s, &fit);
        let covered = |rgb: &[u8]| rgb.chunks(3).filter(|c| *c != bg).count();
        assert!(covered(&both) < covered(&alone), "the view moved back to frame the far ghost too");
    }

    #[test]
    fn a_backdrop_picture_shows_behind_and_mirrors_with_the_model() {
        let s = test_scenes::boxes(1);
        let cam = Camera::fit((Vec3::splat(-3.0), Vec3::splat(3.0)));
        let opts = RenderOptions { width: 40, height: 30, camera: Some(cam), ..Default::default() };
        // Left half red, right half green.
        let img: Vec<u8> = (0..40 * 30).flat_map(|i| if i % 40 < 20 { [200, 0, 0] } else { [0, 200, 0] }).collect();
        let (rgb, _, _) = render_rgb_over(&s, &opts, &Backdrop { image: Some(&img), ..Default::default() });
        assert_eq!((pixel(&rgb, 40, 0, 0), pixel(&rgb, 40, 39, 29)), ([200, 0, 0], [0, 200, 0]));
        assert_ne!(pixel(&rgb, 40, 20, 15), [200, 0, 0], "the box covers the middle");
        let (plain, _, _) = render_rgb(&s, &opts);
        let mirrored = Backdrop { image: Some(&img), mirrored: true, ..Default::default() };
        let (m, _, _) = render_rgb_over(&s, &opts, &mirrored);
        assert_eq!(
            (pixel(&m, 40, 0, 0), pixel(&m, 40, 39, 29)),
            ([200, 0, 0], [0, 200, 0]),
            "the picture keeps its frame"
        );
        for (x, y) in [(20, 15), (14, 10), (25, 20)] {
            if pixel(&plain, 40, x, y) != opts.background {
                assert_eq!(pixel(&m, 40, 39 - x, y), pixel(&plain, 40, x, y), "the model is mirrored");
            }
        }
    }

    #[test]
    fn empty_scene_is_background() {
        let opts = RenderOptions { width: 8, height: 4, background: [1, 2, 3], camera: None };
        let (rgb, w, h) = render_rgb(&Scene::new(), &opts);
        assert_eq!((w, h), (8, 4));
        assert!(rgb.chunks(3).all(|c| c == [1, 2, 3]));
    }

    #[test]
    fn explicit_camera_and_clipping() {
        let s = test_scenes::boxes(1);
        // Looking away from the box: nothing drawn.
        let away = Camera {
            fov_deg: 40.0,
            phi: std::f32::consts::PI,
            theta: 0.0,
            radius: 3.0,
            look_at: Vec3::new(6.0, 0.0, 0.0),
        };
        let opts = RenderOptions { width: 64, height: 48, camera: Some(away), ..Default::default() };
        let (rgb, _, _) = render_rgb(&s, &opts);
        assert!(rgb.chunks(3).all(|c| c == opts.background));
        // The eye inside a (closed) box sees only back faces: culled.
        let inside = Camera { fov_deg: 60.0, phi: 0.3, theta: 0.2, radius: 0.1, look_at: Vec3::ZERO };
        let (rgb, _, _) = render_rgb(&s, &RenderOptions { camera: Some(inside), ..opts });
        assert!(rgb.chunks(3).all(|c| c == opts.background));
        // A ground polygon reaching behind the eye is clipped at the near
        // plane: it fills the lower half of the view, the sky stays empty.
        let mut s = Scene::new();
        let tag = s.tag("ground");
        let big = 1000.0;
        s.polygons.push(genform_core::scene::Polygon {
            points: vec![
                Vec3::new(-big, 0.0, -big),
                Vec3::new(big, 0.0, -big),
                Vec3::new(big, 0.0, big),
                Vec3::new(-big, 0.0, big),
            ],
            tag,
        });
        let low = Camera { fov_deg: 50.0, phi: 0.0, theta: 0.0, radius: 5.0, look_at: Vec3::new(0.0, 1.0, 0.0) };
        let (rgb, w, h) = render_rgb(&s, &RenderOptions { camera: Some(low), ..opts });
        assert_eq!(pixel(&rgb, w, w / 2, h / 4), opts.background);
        assert_eq!(pixel(&rgb, w, 0, h - 1), pixel(&rgb, w, w - 1, h - 1));
        assert_ne!(pixel(&rgb, w, 0, h - 1), opts.background);
    }

    #[test]
    fn polylines_are_drawn() {
        let mut s = Scene::new();
        let tag = s.tag("stroke");
        s.polylines.push(genform_core::scene::Polyline {
            points: &[Vec3::new(-1.0, 0.0, 0.0), Vec3::new(1.0, 0.0, 0.0)],
            width: 0.0,
            tag,
        });
        let opts = RenderOptions { width: 100, height: 100, ..Default::default() };
        let (rgb, _, _) = render_rgb(&s, &opts);
        assert_ne!(pixel(&rgb, 100, 50, 50), opts.background);
        assert_eq!(pixel(&rgb, 100, 50, 10), opts.background);
    }

    #[test]
    fn polylines_in_3d_are_depth_tested() {
        // Seen from +z: a unit box, and a stroke passing behind or in front.
        let cam =
            Camera { fov_deg: 40.0, phi: std::f32::consts::FRAC_PI_2, theta: 0.0, radius: 8.0, look_at: Vec3::ZERO };
        let opts = RenderOptions { width: 80, height: 80, camera: Some(cam), ..Default::default() };
        let with_stroke = |z: f32| {
            let mut s = test_scenes::boxes(1);
            let tag = s.tag("wire#ff0000");
            s.polylines.push(genform_core::scene::Polyline {
                points: &[Vec3::new(-3.0, 0.0, z), Vec3::new(0.0, 0.0, z + 0.1), Vec3::new(3.0, 0.0, z)],
                width: 0.0,
                tag,
            });
            render_rgb(&s, &opts).0
        };
        let (plain, _, _) = render_rgb(&test_scenes::boxes(1), &opts);
        let (behind, front) = (with_stroke(-2.0), with_stroke(1.0));
        assert_eq!(pixel(&behind, 80, 40, 40), pixel(&plain, 80, 40, 40), "hidden behind the box");
        // The stroke is a pixel wide and may straddle rows 39 and 40.
        let red = |rgb: &[u8], x: u32| {
            [39, 40].iter().any(|&y| {
                let p = pixel(rgb, 80, x, y);
                p[0] > p[1].saturating_add(50) && p[0] > p[2].saturating_add(50)
            })
        };
        assert!(red(&front, 40));
        // Beside the box both are visible.
        assert!(red(&behind, 15) && red(&front, 15));
        assert_eq!(pixel(&front, 80, 40, 20), pixel(&plain, 80, 40, 20));
    }

    #[test]
    fn fit_frames_the_bounds() {
        let cam = Camera::fit((Vec3::new(-2.0, 0.0, -1.0), Vec3::new(2.0, 3.0, 1.0)));
        assert_eq!(cam.look_at, Vec3::new(0.0, 1.5, 0.0));
        assert!(cam.radius > 2.5 && cam.radius < 20.0, "{cam:?}");
        let eye = cam.eye();
        assert!(eye.x > 0.0 && eye.y > 1.5 && eye.z > 0.0);
        assert!(((eye - cam.look_at).length() - cam.radius).abs() < 1e-4);
        // Degenerate bounds still give a usable camera.
        let p = Camera::fit((Vec3::ONE, Vec3::ONE));
        assert!(p.radius > 0.0 && p.radius.is_finite());
    }

    #[test]
    fn block_grids_are_drawn() {
        use genform_core::blocks::{BlockGrid, BlockState};
        use glam::{IVec3, UVec3};
        let mut s = Scene::new();
        let mut g = BlockGrid::new(IVec3::new(100, 60, -40), UVec3::new(8, 4, 8));
        for (p, _) in (0..256).map(|i| (IVec3::new(100 + i % 8, 60 + i / 64, -40 + (i / 8) % 8), ())) {
            g.set(p, &BlockState::new(if p.y == 63 { "grass_block" } else { "dirt" }));
        }
        s.blocks.push(g);
        let opts = RenderOptions { width: 120, height: 90, ..Default::default() };
        let (rgb, w, h) = render_rgb(&s, &opts);
        // Auto-fitted: the block in the middle, background in the corners.
        let mid = pixel(&rgb, w, w / 2, h / 2);
        assert_ne!(mid, opts.background);
        assert_eq!(pixel(&rgb, w, 0, 0), opts.background);
        // Seen from above the grass top is green-dominant.
        let greenish =
            rgb.chunks(3).filter(|c| c[1] as u32 > c[0] as u32 + 20 && c[1] as u32 > c[2] as u32 + 20).count();
        assert!(greenish > 200, "{greenish} green pixels");
    }

    /// A flat 2×2 grid surface on y = 0 seen straight from above (+y), its
    /// outline of type 0 and its inner cross of type 1.
    fn grid_from_above(tag_name: &str) -> (Scene, RenderOptions) {
        use genform_core::surface::{Surface, SurfaceEdge};
        let mut s = Scene::new();
        let tag = s.tag(tag_name);
        let mut g = Surface::new(tag);
        let id = |i: u32, j: u32| 3 * j + i;
        for j in 0..3 {
            for i in 0..3 {
                g.positions.push(Vec3::new(i as f32 - 1.0, 0.0, j as f32 - 1.0));
            }
        }
        for j in 0..2 {
            for i in 0..2 {
                // Counter-clockwise seen from +y.
                g.push_face(&[id(i, j), id(i, j + 1), id(i + 1, j + 1), id(i + 1, j)]);
            }
        }
        for j in 0..3 {
            for i in 0..2 {
                g.edges.push(SurfaceEdge { a: id(i, j), b: id(i + 1, j), kind: u32::from(j == 1) });
                g.edges.push(SurfaceEdge { a: id(j, i), b: id(j, i + 1), kind: u32::from(j == 1) });
            }
        }
        s.surfaces.push(g);
        let top =
            Camera { fov_deg: 40.0, phi: std::f32::consts::FRAC_PI_2, theta: 1.5, radius: 8.0, look_at: Vec3::ZERO };
        (s, RenderOptions { width: 100, height: 100, camera: Some(top), ..Default::default() })
    }

    #[test]
    fn surface_edges_show_over_the_faces_in_their_type_colours() {
        let (s, opts) = grid_from_above("shell#c0c0c0");
        let (rgb, w, _) = render_rgb(&s, &opts);
        let close = |p: [u8; 3], c: [u8; 3]| (0..3).all(|i| (i32::from(p[i]) - i32::from(c[i])).abs() < 30);
        // The inner cross through the centre is type 1, the outline type 0.
        let centre_row: Vec<[u8; 3]> = (0..w).map(|x| pixel(&rgb, w, x, 50)).collect();
        assert!(centre_row.iter().filter(|&&p| close(p, edge_color(1))).count() > 30, "{centre_row:?}");
        let outline = (0..w).flat_map(|x| [pixel(&rgb, w, x, 50)]).chain((0..100).map(|y| pixel(&rgb, w, 50, y)));
        assert!(outline.filter(|&p| close(p, edge_color(0))).count() >= 2);
        // Between the edges: the face, grey, not an edge colour.
        let face = pixel(&rgb, w, 35, 35);
        assert!(face != opts.background && face[0].abs_diff(face[2]) < 12, "{face:?}");
        // The same picture with the edges gone has no edge colour left.
        let mut bare = s.clone();
        bare.surfaces[0].edges.clear();
        let (rgb, _, _) = render_rgb(&bare, &opts);
        assert!(rgb.chunks(3).all(|p| !close([p[0], p[1], p[2]], edge_color(1))));
    }

    #[test]
    fn later_surfaces_win_where_they_coincide_and_earlier_ones_are_paler() {
        let (mut s, opts) = grid_from_above("one#3060c0");
        let mut second = s.surfaces[0].clone();
        second.tag = s.tag("two#c06030");
        second.edges.clear();
        s.surfaces[0].edges.clear();
        s.surfaces.push(second);
        let (rgb, w, _) = render_rgb(&s, &opts);
        let p = pixel(&rgb, w, 35, 35);
        assert!(p[0] > p[2] + 40, "the second (reddish) surface shows: {p:?}");
        s.surfaces.swap(0, 1);
        let (rgb, w, _) = render_rgb(&s, &opts);
        let q = pixel(&rgb, w, 35, 35);
        assert!(q[2] > q[0] + 40, "now the bluish one: {q:?}");
    }

    #[test]
    fn guides_are_faint_and_far_ones_left_out_of_the_framing() {
        use genform_core::surface::{Guide, GuideKind};
        let (mut s, mut opts) = grid_from_above("shell#c0c0c0");
        // No edges, whose palette has a red and a blue too.
        s.surfaces[0].edges.clear();
        let plain_scene = s.clone();
        let a = s.tag("attractor");
        let r = s.tag("repeller");
        // A repeller under the middle of the surface, an attractor above a
        // corner, both seen from above.
        s.guides.push(Guide { kind: GuideKind::Point { at: Vec3::new(0.5, -0.5, 0.5), radius: 0.2 }, tag: r });
        s.guides.push(Guide { kind: GuideKind::Point { at: Vec3::new(-1.5, 0.5, -1.5), radius: 0.2 }, tag: a });
        let (rgb, _, _) = render_rgb(&s, &opts);
        let (plain, _, _) = render_rgb(&plain_scene, &opts);
        // Hidden under the surface: a faint red tint, nowhere full red.
        let redness = |rgb: &[u8], lo: i32, hi: i32| {
            rgb.chunks(3).filter(|p| (lo..hi).contains(&(i32::from(p[0]) - i32::from(p[2])))).count()
        };
        assert_eq!(redness(&plain, 1, 255), 0);
        assert!(redness(&rgb, 15, 80) > 20, "{}", redness(&rgb, 15, 80));
        assert_eq!(redness(&rgb, 100, 255), 0);
        let blue = rgb.chunks(3).filter(|p| i32::from(p[2]) > i32::from(p[0]) + 80).count();
        assert!(blue > 20, "{blue}");
        // Auto-framing leaves far guides out: a boundary 100 units away
        // changes nothing about where the surface is drawn.
        opts.camera = None;
        let far = genform_core::Mesh {
            name: "far".into(),
            positions: vec![Vec3::new(100.0, 0.0, 0.0), Vec3::new(101.0, 0.0, 0.0), Vec3::new(100.0, 0.0, 1.0)],
            triangles: vec![[0, 1, 2]],
        };
        let b = s.tag("boundary");
        let (framed, _, _) = render_rgb(&s, &opts);
        s.guides.push(Guide { kind: GuideKind::Mesh(std::sync::Arc::new(far)), tag: b });
        let (again, _, _) = render_rgb(&s, &opts);
        assert_eq!(framed, again);
    }

    #[test]
    fn a_guide_box_near_the_model_is_framed_whole() {
        use genform_core::surface::{Guide, GuideKind};
        let (mut s, mut opts) = grid_from_above("shell#c0c0c0");
        opts.camera = None;
        // A box twice the surface's size around it (an environment's
        // boundary): every corner projects inside the picture.
        let (lo, hi) = (Vec3::new(-2.0, -2.0, -2.0), Vec3::new(2.0, 2.0, 2.0));
        let corners: Vec<Vec3> =
            (0..8).map(|i| Vec3::new([lo.x, hi.x][i & 1], [lo.y, hi.y][(i >> 1) & 1], [lo.z, hi.z][i >> 2])).collect();
        let faces = [[0, 1, 3], [0, 3, 2], [4, 6, 7], [4, 7, 5], [0, 4, 5], [0, 5, 1], [2, 3, 7], [2, 7, 6]];
        let boxy = genform_core::Mesh { name: "box".into(), positions: corners.clone(), triangles: faces.to_vec() };
        let b = s.tag("boundary");
        s.guides.push(Guide { kind: GuideKind::Mesh(std::sync::Arc::new(boxy)), tag: b });
        let camera = fitted_camera(&s, opts.width, opts.height);
        let view = View::new(&camera, opts.width as usize, opts.height as usize);
        for c in corners {
            let p = view.project(view.to_camera(c));
            assert!(
                (0.0..=opts.width as f32).contains(&p.x) && (0.0..=opts.height as f32).contains(&p.y),
                "corner {c} at {p} of {}×{}",
                opts.width,
                opts.height
            );
        }
    }

    #[test]
    fn rendering_is_deterministic_and_fast_enough() {
        let s = test_scenes::mixed();
        let opts = RenderOptions::default();
        assert_eq!(render_png(&s, &opts), render_png(&s, &opts));
    }
}
