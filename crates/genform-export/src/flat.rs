//! Flat drawings (a 2D turtle's lines and regions) as images: the SVG
//! drawing rendered by resvg, which anti-aliases thin strokes far better
//! than the 3D preview rasterizer.

use crate::svg::{Drawing, SvgOptions};
use genform_core::scene::{Scene, Tessellation};
use resvg::{tiny_skia, usvg};

/// The thinnest stroke in an image, in pixels.
const MIN_STROKE_PX: f32 = 1.5;

/// Whether the scene is a non-empty drawing in the z = 0 plane with nothing
/// solid in it: no instances, blocks or surfaces, every polyline and polygon point at z = 0
/// (2D shapes are always flat).
pub(crate) fn is_flat(scene: &Scene) -> bool {
    (!scene.is_empty() || !scene.shapes2d.is_empty())
        && scene.instances.is_empty()
        && scene.blocks.is_empty()
        && scene.surfaces.is_empty()
        && scene.polylines.points().iter().all(|p| p.z == 0.0)
        && scene.polygons.iter().flat_map(|p| &p.points).all(|p| p.z == 0.0)
}

/// Renders the drawing into a `width × height` RGB image (rows from the
/// top) on `background`, fitted with its aspect ratio kept and centred;
/// `None` when resvg cannot (an image too large for it), so the caller can
/// fall back to the rasterizer.
pub(crate) fn render_rgb(
    scene: &Scene,
    width: u32,
    height: u32,
    background: [u8; 3],
    tess: Tessellation,
) -> Option<Vec<u8>> {
    let drawing = Drawing::new(scene, tess);
    // The drawing's width in the image, so the stroke floor is in pixels.
    let fitted = (width as f32).min(height as f32 * drawing.aspect());
    let opts = SvgOptions { width_px: fitted.round().max(1.0) as u32, min_stroke_px: MIN_STROKE_PX, background: None };
    if scene.shapes2d.is_empty() && scene.guides.is_empty() {
        return render_lines(scene, &drawing, &opts, width, height, background);
    }
    // Sized in pixels even for a drawing that is otherwise in centimetres.
    let svg = drawing.write_sized(scene, &opts, false);
    let tree = usvg::Tree::from_str(&svg, &usvg::Options::default()).ok()?;
    let size = tree.size();
    let k = (width as f32 / size.width()).min(height as f32 / size.height());
    let dx = 0.5 * (width as f32 - k * size.width());
    let dy = 0.5 * (height as f32 - k * size.height());
    let mut pixmap = tiny_skia::Pixmap::new(width, height)?;
    let [r, g, b] = background;
    pixmap.fill(tiny_skia::Color::from_rgba8(r, g, b, 255));
    resvg::render(&tree, tiny_skia::Transform::from_row(k, 0.0, 0.0, k, dx, dy), &mut pixmap.as_mut());
    // Opaque background: premultiplied RGBA is plain RGB with alpha 255.
    Some(pixmap.data().chunks_exact(4).flat_map(|p| [p[0], p[1], p[2]]).collect())
}

/// A drawing of only lines and polygons (an L-system's, a turtle's)
/// stroked and filled straight into the pixmap: the picture the SVG path
/// gives (same view, widths, caps, joins and colours) without writing the
/// SVG text and parsing it into a tree, which for a million segments took
/// seconds and most of a gigabyte. Each line is stroked on its own, so the
/// memory is the image's and the longest line's.
fn render_lines(
    scene: &Scene,
    drawing: &Drawing,
    opts: &SvgOptions,
    width: u32,
    height: u32,
    background: [u8; 3],
) -> Option<Vec<u8>> {
    use crate::palette::tag_color;
    let (origin, size) = drawing.view();
    // The SVG's own size, its view box fitted into it (xMidYMid meet), and
    // that fitted into the image, as `render_rgb` places the SVG.
    let (svg_w, svg_h) =
        (opts.width_px.max(1) as f32, ((opts.width_px.max(1) as f32 / drawing.aspect()).round()).max(1.0));
    let s = (svg_w / size.x).min(svg_h / size.y);
    let off = glam::Vec2::new(0.5 * (svg_w - s * size.x), 0.5 * (svg_h - s * size.y));
    let k = (width as f32 / svg_w).min(height as f32 / svg_h);
    let (dx, dy) = (0.5 * (width as f32 - k * svg_w), 0.5 * (height as f32 - k * svg_h));
    // Scene (x, y) → pixels, y flipped as in the SVG.
    let transform = tiny_skia::Transform::from_row(
        k * s,
        0.0,
        0.0,
        -k * s,
        k * (off.x - s * origin.x) + dx,
        k * (off.y - s * origin.y) + dy,
    );
    if !(transform.is_finite() && k * s > 0.0) {
        return None;
    }
    let mut pixmap = tiny_skia::Pixmap::new(width, height)?;
    let [r, g, b] = background;
    pixmap.fill(tiny_skia::Color::from_rgba8(r, g, b, 255));
    let paint = |tag: u32| {
        let [r, g, b] = scene.tags.get(tag as usize).map_or([128; 3], |t| tag_color(t));
        let mut p = tiny_skia::Paint::default();
        p.set_color_rgba8(r, g, b, 255);
        p.anti_alias = true;
        p
    };
    for poly in scene.polygons.iter().filter(|p| p.points.len() >= 3 && p.points.iter().all(|q| q.is_finite())) {
        let mut pb = tiny_skia::PathBuilder::with_capacity(poly.points.len() + 1, poly.points.len());
        pb.move_to(poly.points[0].x, poly.points[0].y);
        poly.points[1..].iter().for_each(|q| pb.line_to(q.x, q.y));
        pb.close();
        if let Some(path) = pb.finish() {
            pixmap.fill_path(&path, &paint(poly.tag), tiny_skia::FillRule::Winding, transform, None);
        }
    }
    // The thinnest stroke, in scene units, as the SVG writes it.
    let floor = opts.min_stroke_px.max(0.0) * size.x / svg_w;
    for line in scene.polylines.iter().filter(|l| l.points.len() >= 2 && l.points.iter().all(|q| q.is_finite())) {
        let mut pb = tiny_skia::PathBuilder::with_capacity(line.points.len(), line.points.len());
        pb.move_to(line.points[0].x, line.points[0].y);
        line.points[1..].iter().for_each(|q| pb.line_to(q.x, q.y));
        let width = if line.width.is_finite() { line.width.max(floor) } else { floor };
        let Some(path) = pb.finish() else {
            // A line that stays on one point is a dot (its round caps).
            let p = line.points[0];
            if let Some(dot) = tiny_skia::PathBuilder::from_circle(p.x, p.y, 0.5 * width) {
                pixmap.fill_path(&dot, &paint(line.tag), tiny_skia::FillRule::Winding, transform, None);
            }
            continue;
        };
        let stroke = tiny_skia::Stroke {
            width,
            line_cap: tiny_skia::LineCap::Round,
            line_join: tiny_skia::LineJoin::Round,
            ..tiny_skia::Stroke::default()
        };
        pixmap.stroke_path(&path, &paint(line.tag), &stroke, transform, None);
    }
    Some(pixmap.data().chunks_exact(4).flat_map(|p| [p[0], p[1], p[2]]).collect())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{ExportOptions, Format, RenderOptions, export};
    use genform_core::scene::{Instance, Polyline, Primitive};
    use glam::Vec3;

    fn decode(png_bytes: &[u8]) -> (Vec<u8>, u32, u32) {
        let mut reader = png::Decoder::new(std::io::Cursor::new(png_bytes)).read_info().unwrap();
        let mut buf = vec![0; reader.output_buffer_size().unwrap()];
        let info = reader.next_frame(&mut buf).unwrap();
        assert_eq!(info.color_type, png::ColorType::Rgb);
        buf.truncate(info.buffer_size());
        (buf, info.width, info.height)
    }

    /// A hairline "L": a long horizontal stroke and a short vertical one.
    fn hairline_l() -> Scene {
        let mut s = Scene::new();
        let tag = s.tag("ink#204080");
        let pts = [(0.0, 1.0), (0.0, 0.0), (4.0, 0.0)];
        s.polylines.push(Polyline {
            points: &pts.iter().map(|&(x, y)| Vec3::new(x, y, 0.0)).collect::<Vec<_>>(),
            width: 0.0,
            tag,
        });
        s
    }

    #[test]
    fn flat_drawings_render_through_the_svg_writer() {
        let s = hairline_l();
        let render = RenderOptions { width: 200, height: 200, background: [255; 3], camera: None };
        let opts = ExportOptions { render, ..Default::default() };
        let bytes = export(&s, Format::Png, &opts).unwrap();
        assert_eq!(bytes, export(&s, Format::Png, &opts).unwrap());
        let (rgb, w, h) = decode(&bytes);
        assert_eq!((w, h), (200, 200));
        let px = |x: u32, y: u32| {
            let i = 3 * (y * w + x) as usize;
            [rgb[i], rgb[i + 1], rgb[i + 2]]
        };
        // View box 4.24 × 1.24 fitted to the width (47.2 px per unit) and
        // centred: y = 0 at row 100 + 0.5·1.24·47.2 − 0.03·4·47.2 ≈ 123.6,
        // x = 0 at column 5.7.
        let ink = |p: [u8; 3]| p[2] > p[0] + 40 && p[0] < 200;
        for x in [20, 100, 180] {
            assert!(ink(px(x, 123)) || ink(px(x, 124)), "no ink at column {x}: {:?}", px(x, 123));
            assert_eq!(px(x, 110), [255; 3]);
            assert_eq!(px(x, 140), [255; 3]);
        }
        assert!(ink(px(5, 100)) || ink(px(6, 100)), "no vertical stroke");
        for (x, y) in [(0, 0), (199, 0), (0, 199), (199, 199), (100, 60), (100, 160), (196, 124)] {
            assert_eq!(px(x, y), [255; 3], "({x}, {y})");
        }
    }

    #[test]
    fn shape_drawings_render_through_resvg() {
        use genform_core::scene::{Shape2d, Shape2dKind};
        use glam::Vec2;
        let mut s = Scene::new();
        let tag = s.tag("wall");
        let rect = |min: Vec2, fill: &str| Shape2d {
            kind: Shape2dKind::Rect { min, size: Vec2::splat(1.0) },
            attributes: vec![("fill".into(), fill.into())].into(),
            tag,
        };
        // Red lower left, blue upper right (y up).
        s.shapes2d.push(rect(Vec2::ZERO, "#ff0000"));
        s.shapes2d.push(rect(Vec2::ONE, "#0000ff"));
        assert!(is_flat(&s));
        let render = RenderOptions { width: 100, height: 100, background: [255; 3], camera: None };
        let bytes = export(&s, Format::Png, &ExportOptions { render, ..Default::default() }).unwrap();
        let (rgb, w, _) = decode(&bytes);
        let px = |x: u32, y: u32| {
            let i = 3 * (y * w + x) as usize;
            [rgb[i], rgb[i + 1], rgb[i + 2]]
        };
        assert_eq!(px(25, 75), [255, 0, 0]);
        assert_eq!(px(75, 25), [0, 0, 255]);
        assert_eq!(px(75, 75), [255, 255, 255]);
    }

    #[test]
    fn only_camera_less_flat_drawings_take_the_svg_path() {
        let s = hairline_l();
        assert!(is_flat(&s));
        assert!(!is_flat(&Scene::new()));
        let mut raised = s.clone();
        raised.polylines.points_mut(0)[1].z = 0.5;
        assert!(!is_flat(&raised));
        let mut surface = s.clone();
        surface.surfaces.push(genform_core::Surface::new(0));
        surface.surfaces[0].positions.push(Vec3::ZERO);
        assert!(!is_flat(&surface), "surfaces go to the rasterizer");
        let mut solid = s.clone();
        solid.instances.push(Instance { transform: Default::default(), primitive: Primitive::Box, tag: 0 });
        assert!(!is_flat(&solid));
        // The SVG path keeps the background colour; an explicit camera asks
        // for the 3D view.
        let opts = RenderOptions { width: 64, height: 48, background: [10, 20, 30], camera: None };
        let (flat, _, _) = crate::render_rgb(&s, &opts);
        assert_eq!(flat[..3], [10, 20, 30]);
        assert_eq!(Some(flat.clone()), render_rgb(&s, 64, 48, [10, 20, 30], Tessellation::default()));
        let cam = crate::Camera::fit((Vec3::new(0.0, 0.0, -1.0), Vec3::new(4.0, 1.0, 1.0)));
        let (view, _, _) = crate::render_rgb(&s, &RenderOptions { camera: Some(cam), ..opts });
        assert_ne!(flat, view);
    }
}
