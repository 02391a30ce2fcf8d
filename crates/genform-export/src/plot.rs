//! Run reports: line charts as SVG text and picture galleries as PNG.

mod font;

use font::draw_text;
use std::fmt::Write as _;

/// One line of a chart.
#[derive(Clone, Debug, PartialEq)]
pub struct Series {
    /// Legend text.
    pub name: String,
    /// CSS colour, e.g. `#1f77b4`.
    pub color: String,
    /// (x, y) points in drawing order; non-finite points are skipped.
    pub points: Vec<(f64, f64)>,
    /// A shaded band `(x, low, high)` drawn under the line (e.g. mean ±
    /// standard deviation); empty for none.
    pub band: Vec<(f64, f64, f64)>,
}

/// One panel: axes with labels and any number of series.
#[derive(Clone, Debug, PartialEq)]
pub struct Chart {
    /// Title above the panel.
    pub title: String,
    /// Label of the horizontal axis.
    pub x_label: String,
    /// Label of the vertical axis.
    pub y_label: String,
    /// The lines.
    pub series: Vec<Series>,
}

const PANEL_W: f64 = 480.0;
const PANEL_H: f64 = 320.0;
const MARGIN_L: f64 = 62.0;
const MARGIN_R: f64 = 16.0;
const MARGIN_T: f64 = 30.0;
const MARGIN_B: f64 = 44.0;

/// Draws `charts` side by side into one standalone SVG document.
pub fn charts_svg(charts: &[Chart]) -> String {
    let width = PANEL_W * charts.len().max(1) as f64;
    let mut s = String::new();
    let _ = writeln!(
        s,
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="{width}" height="{PANEL_H}" viewBox="0 0 {width} {PANEL_H}" font-family="sans-serif" font-size="11">"#
    );
    let _ = writeln!(s, r#"<rect width="{width}" height="{PANEL_H}" fill="white"/>"#);
    for (i, c) in charts.iter().enumerate() {
        panel(&mut s, c, PANEL_W * i as f64);
    }
    s.push_str("</svg>\n");
    s
}

fn escape(t: &str) -> String {
    t.replace('&', "&amp;").replace('<', "&lt;").replace('>', "&gt;").replace('"', "&quot;")
}

/// Axis range covering `values`, padded when flat.
fn range(values: impl Iterator<Item = f64>) -> (f64, f64) {
    let (lo, hi) =
        values.filter(|v| v.is_finite()).fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| (a.min(v), b.max(v)));
    if !lo.is_finite() {
        return (0.0, 1.0);
    }
    if hi - lo < 1e-12 {
        let pad = if lo.abs() > 1e-12 { lo.abs() * 0.1 } else { 1.0 };
        return (lo - pad, hi + pad);
    }
    (lo, hi)
}

/// About five round tick values in `[lo, hi]`.
fn ticks(lo: f64, hi: f64) -> Vec<f64> {
    let raw = (hi - lo) / 5.0;
    let mag = 10f64.powf(raw.log10().floor());
    let step = [1.0, 2.0, 5.0, 10.0].iter().map(|m| m * mag).find(|s| *s >= raw).unwrap_or(10.0 * mag);
    let first = (lo / step).ceil() as i64;
    let last = (hi / step).floor() as i64;
    (first..=last).take(50).map(|k| k as f64 * step).collect()
}

fn label(v: f64) -> String {
    let t = format!("{v:.6}");
    let t = t.trim_end_matches('0').trim_end_matches('.');
    if t == "-0" { "0".into() } else { t.to_string() }
}

fn panel(s: &mut String, c: &Chart, x0: f64) {
    let (xl, xh) = range(c.series.iter().flat_map(|se| se.points.iter().map(|p| p.0)));
    let (yl, yh) = range(
        c.series.iter().flat_map(|se| se.points.iter().map(|p| p.1).chain(se.band.iter().flat_map(|b| [b.1, b.2]))),
    );
    let (pw, ph) = (PANEL_W - MARGIN_L - MARGIN_R, PANEL_H - MARGIN_T - MARGIN_B);
    let px = |x: f64| x0 + MARGIN_L + (x - xl) / (xh - xl) * pw;
    let py = |y: f64| MARGIN_T + (1.0 - (y - yl) / (yh - yl)) * ph;
    let _ = writeln!(
        s,
        r#"<text x="{}" y="18" font-size="13" font-weight="bold">{}</text>"#,
        x0 + MARGIN_L,
        escape(&c.title)
    );
    let _ = writeln!(
        s,
        r##"<rect x="{}" y="{MARGIN_T}" width="{pw}" height="{ph}" fill="none" stroke="#888"/>"##,
        x0 + MARGIN_L
    );
    for t in ticks(xl, xh) {
        let x = px(t);
        let _ = writeln!(
            s,
            r##"<line x1="{x:.1}" y1="{MARGIN_T}" x2="{x:.1}" y2="{:.1}" stroke="#eee"/><text x="{x:.1}" y="{:.1}" text-anchor="middle">{}</text>"##,
            MARGIN_T + ph,
            MARGIN_T + ph + 14.0,
            label(t)
        );
    }
    for t in ticks(yl, yh) {
        let y = py(t);
        let _ = writeln!(
            s,
            r##"<line x1="{:.1}" y1="{y:.1}" x2="{:.1}" y2="{y:.1}" stroke="#eee"/><text x="{:.1}" y="{:.1}" text-anchor="end">{}</text>"##,
            x0 + MARGIN_L,
            x0 + MARGIN_L + pw,
            x0 + MARGIN_L - 4.0,
            y + 4.0,
            label(t)
        );
    }
    let _ = writeln!(
        s,
        r#"<text x="{:.1}" y="{:.1}" text-anchor="middle">{}</text>"#,
        x0 + MARGIN_L + pw / 2.0,
        PANEL_H - 8.0,
        escape(&c.x_label)
    );
    let _ = writeln!(
        s,
        r#"<text transform="translate({:.1} {:.1}) rotate(-90)" text-anchor="middle">{}</text>"#,
        x0 + 14.0,
        MARGIN_T + ph / 2.0,
        escape(&c.y_label)
    );
    for se in &c.series {
        let band: Vec<(f64, f64, f64)> =
            se.band.iter().copied().filter(|(x, l, h)| x.is_finite() && l.is_finite() && h.is_finite()).collect();
        if band.len() > 1 {
            let upper = band.iter().map(|&(x, _, h)| format!("{:.1},{:.1}", px(x), py(h)));
            let lower = band.iter().rev().map(|&(x, l, _)| format!("{:.1},{:.1}", px(x), py(l)));
            let pts: Vec<String> = upper.chain(lower).collect();
            let _ = writeln!(
                s,
                r#"<polygon fill="{}" fill-opacity="0.18" stroke="none" points="{}"/>"#,
                escape(&se.color),
                pts.join(" ")
            );
        }
    }
    for (i, se) in c.series.iter().enumerate() {
        let pts: Vec<String> = se
            .points
            .iter()
            .filter(|(x, y)| x.is_finite() && y.is_finite())
            .map(|&(x, y)| format!("{:.1},{:.1}", px(x), py(y)))
            .collect();
        if !pts.is_empty() {
            let _ = writeln!(
                s,
                r#"<polyline fill="none" stroke="{}" stroke-width="1.5" points="{}"/>"#,
                escape(&se.color),
                pts.join(" ")
            );
        }
        let ly = MARGIN_T + 12.0 + 14.0 * i as f64;
        let lx = x0 + MARGIN_L + pw - 90.0;
        let _ = writeln!(
            s,
            r#"<line x1="{lx:.1}" y1="{:.1}" x2="{:.1}" y2="{:.1}" stroke="{}" stroke-width="2"/><text x="{:.1}" y="{ly:.1}">{}</text>"#,
            ly - 4.0,
            lx + 16.0,
            ly - 4.0,
            escape(&se.color),
            lx + 20.0,
            escape(&se.name)
        );
    }
}

/// Encodes 8-bit RGB pixels (rows from the top) as PNG.
///
/// # Panics
///
/// If `rgb` does not hold `width × height × 3` bytes or a side is 0.
pub fn encode_png_rgb(rgb: &[u8], width: u32, height: u32) -> Vec<u8> {
    let mut out = Vec::new();
    let mut enc = png::Encoder::new(&mut out, width, height);
    enc.set_color(png::ColorType::Rgb);
    enc.set_depth(png::BitDepth::Eight);
    enc.set_compression(png::Compression::Fast);
    let mut writer = enc.write_header().expect("valid PNG header for a non-empty image");
    writer.write_image_data(rgb).expect("writing to memory cannot fail");
    writer.finish().expect("writing to memory cannot fail");
    out
}

/// An animated PNG (APNG) of RGB `frames`, each `width × height` pixels
/// rows from the top, shown `frame_ms` apart, the last one held for
/// `last_ms`, looping forever. The still image that viewers without APNG
/// support show (a separate default image) is the last frame: the end
/// result. `None` when there are no frames or one has the wrong size.
pub fn encode_apng_rgb(frames: &[Vec<u8>], width: u32, height: u32, frame_ms: u16, last_ms: u16) -> Option<Vec<u8>> {
    let size = width as usize * height as usize * 3;
    let last = frames.last()?;
    if width == 0 || height == 0 || frames.iter().any(|f| f.len() != size) {
        return None;
    }
    let mut out = Vec::new();
    let mut enc = png::Encoder::new(&mut out, width, height);
    enc.set_color(png::ColorType::Rgb);
    enc.set_depth(png::BitDepth::Eight);
    enc.set_compression(png::Compression::Balanced);
    enc.set_animated(frames.len() as u32, 0).ok()?;
    enc.set_sep_def_img(true).ok()?;
    let mut writer = enc.write_header().ok()?;
    writer.write_image_data(last).ok()?;
    for (i, f) in frames.iter().enumerate() {
        let ms = if i + 1 == frames.len() { last_ms } else { frame_ms };
        writer.set_frame_delay(ms, 1000).ok()?;
        writer.write_image_data(f).ok()?;
    }
    writer.finish().ok()?;
    Some(out)
}

/// An RGB picture: pixels row by row from the top.
#[derive(Clone, Debug, PartialEq)]
pub struct Tile {
    /// 3 bytes per pixel.
    pub rgb: Vec<u8>,
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// A caption drawn in the top-left corner: digits, letters and
    /// `.,:=-+()/%_#`, lines split at `\n`.
    pub caption: String,
}

/// Lays `tiles` out in a grid of `columns` with a 4-pixel white gutter and
/// returns the RGB picture `(pixels, width, height)`. Tiles of different
/// sizes are placed in cells of the largest size.
pub fn gallery_rgb(tiles: &[Tile], columns: usize) -> (Vec<u8>, u32, u32) {
    const GUTTER: usize = 4;
    let cols = columns.clamp(1, tiles.len().max(1));
    let rows = tiles.len().div_ceil(cols).max(1);
    let cw = tiles.iter().map(|t| t.width as usize).max().unwrap_or(1);
    let ch = tiles.iter().map(|t| t.height as usize).max().unwrap_or(1);
    let (w, h) = (cols * cw + (cols + 1) * GUTTER, rows * ch + (rows + 1) * GUTTER);
    let mut img = vec![255u8; w * h * 3];
    for (i, t) in tiles.iter().enumerate() {
        let (ox, oy) = (GUTTER + (i % cols) * (cw + GUTTER), GUTTER + (i / cols) * (ch + GUTTER));
        for y in 0..t.height as usize {
            let src = &t.rgb[y * t.width as usize * 3..(y + 1) * t.width as usize * 3];
            let at = ((oy + y) * w + ox) * 3;
            img[at..at + src.len()].copy_from_slice(src);
        }
        draw_text(&mut img, w, ox + 4, oy + 4, &t.caption);
    }
    (img, w as u32, h as u32)
}

/// Draws `text` (digits, letters and `.,:=-+()/%_#`, lines split at `\n`;
/// 2× scale, dark grey on a white box per line) into the RGB picture `img` of
/// `width` pixels per row, its top-left corner at `(x, y)`; what falls
/// outside is clipped.
pub fn caption_rgb(img: &mut [u8], width: u32, x: u32, y: u32, text: &str) {
    draw_text(img, width as usize, x as usize, y as usize, text);
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn apng_has_every_frame_and_the_last_as_still_image() {
        let frames: Vec<Vec<u8>> = (0..3u8).map(|k| vec![k * 100; 4 * 2 * 3]).collect();
        let bytes = encode_apng_rgb(&frames, 4, 2, 100, 1000).unwrap();
        let mut reader = png::Decoder::new(std::io::Cursor::new(&bytes)).read_info().unwrap();
        assert_eq!(reader.info().animation_control.map(|a| a.num_frames), Some(3));
        let mut buf = vec![0; reader.output_buffer_size().unwrap()];
        reader.next_frame(&mut buf).unwrap();
        assert_eq!(buf[0], 200, "the still image is the last frame");
        let mut seen = Vec::new();
        while let Ok(info) = reader.next_frame(&mut buf) {
            assert_eq!((info.width, info.height), (4, 2));
            seen.push(buf[0]);
        }
        assert_eq!(seen, [0, 100, 200]);
        assert!(encode_apng_rgb(&[], 4, 2, 100, 100).is_none());
        assert!(encode_apng_rgb(&[vec![0; 5]], 4, 2, 100, 100).is_none());
    }

    #[test]
    fn ticks_are_round_and_inside() {
        assert_eq!(ticks(0.0, 10.0), vec![0.0, 2.0, 4.0, 6.0, 8.0, 10.0]);
        let t = ticks(-3.52, 0.41);
        assert!(t.iter().all(|v| (-3.52..=0.41).contains(v)));
        assert_eq!(t, vec![-3.0, -2.0, -1.0, 0.0]);
    }

    #[test]
    fn chart_has_a_polyline_per_series_and_escapes_text() {
        let c = Chart {
            title: "fitness <gen>".into(),
            x_label: "generation".into(),
            y_label: "fitness".into(),
            series: vec![
                Series {
                    name: "max".into(),
                    color: "#d62728".into(),
                    points: vec![(0.0, -3.5), (1.0, 0.4)],
                    band: vec![(0.0, -4.0, -3.0), (1.0, 0.2, 0.6)],
                },
                Series {
                    name: "min".into(),
                    color: "#1f77b4".into(),
                    points: vec![(0.0, f64::NEG_INFINITY)],
                    band: vec![],
                },
            ],
        };
        let svg = charts_svg(&[c.clone(), c]);
        assert_eq!(svg.matches("<polyline").count(), 2, "the all-non-finite series draws nothing");
        assert_eq!(svg.matches("<polygon").count(), 2, "one band per panel");
        assert!(svg.contains("fitness &lt;gen&gt;"));
        assert!(svg.starts_with("<svg") && svg.trim_end().ends_with("</svg>"));
    }

    #[test]
    fn gallery_places_tiles_in_a_grid() {
        let tile = |v: u8| Tile { rgb: vec![v; 10 * 6 * 3], width: 10, height: 6, caption: String::new() };
        let (img, w, h) = gallery_rgb(&[tile(0), tile(100), tile(200)], 2);
        assert_eq!((w, h), (2 * 10 + 3 * 4, 2 * 6 + 3 * 4));
        let px = |x: usize, y: usize| img[(y * w as usize + x) * 3];
        assert_eq!(px(4, 4), 0);
        assert_eq!(px(4 + 10 + 4, 4), 100);
        assert_eq!(px(4, 4 + 6 + 4), 200);
        assert_eq!(px(4 + 10 + 4, 4 + 6 + 4), 255, "the empty cell stays white");
        assert_eq!(px(0, 0), 255);
    }

    #[test]
    fn captions_draw_dark_pixels() {
        let t = Tile { rgb: vec![128; 40 * 20 * 3], width: 40, height: 20, caption: "#1 0.5".into() };
        let (img, _, _) = gallery_rgb(&[t], 1);
        assert!(img.chunks(3).any(|p| p[0] == 40));
    }
}
