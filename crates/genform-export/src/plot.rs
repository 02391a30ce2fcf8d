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
    /// Whether the y-axis range covers this series. `false` for a line
    /// that would squash the others flat (a population's worst individual
    /// far below its best and mean): it is drawn clipped to the range the
    /// others set, and its legend entry says `(clipped)` when part of it
    /// falls outside.
    pub scales_axis: bool,
}

impl Series {
    /// A plain line: no band, covered by the y-axis.
    pub fn line(name: impl Into<String>, color: impl Into<String>, points: Vec<(f64, f64)>) -> Series {
        Series { name: name.into(), color: color.into(), points, band: Vec::new(), scales_axis: true }
    }
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
const MARGIN_L: f64 = 62.0;
const MARGIN_R: f64 = 16.0;
const MARGIN_T: f64 = 30.0;
/// Height of the data area.
const PLOT_H: f64 = 246.0;
/// From the data area's bottom to the legend: tick labels and the axis label.
const AXIS_H: f64 = 44.0;
/// Height of one legend row.
const LEGEND_ROW: f64 = 16.0;
/// Padding inside the legend frame.
const LEGEND_PAD: f64 = 6.0;
/// Width of a legend entry's colour swatch and the gap after it.
const SWATCH: f64 = 24.0;
/// Space between legend columns.
const LEGEND_GAP: f64 = 14.0;
/// Estimated width of one character of 11-pixel sans-serif text: a little
/// more than the widest common glyphs (digits in DejaVu Sans are 7.0 px,
/// lowercase letters 6–7 px), so text measured with it stays inside the
/// boxes laid out for it whatever font the viewer picks.
const CHAR_W: f64 = 7.0;
/// Share of the y-range added above and below the data, so lines at the
/// extremes stay off the frame.
const Y_PAD: f64 = 0.04;

/// Estimated width in pixels of `text` at the charts' 11-pixel font.
pub fn text_width_px(text: &str) -> f64 {
    text.chars().count() as f64 * CHAR_W
}

/// A legend: its entries' texts and colours laid out in columns.
struct Legend {
    /// (text, colour) per entry, in series order.
    entries: Vec<(String, String)>,
    /// Columns, each `column` wide.
    columns: usize,
    column: f64,
}

impl Legend {
    /// Lays `entries` out in equal columns no wider than `width` in all;
    /// texts too long for one column of the whole width are cut with `…`.
    fn new(entries: Vec<(String, String)>, width: f64) -> Legend {
        let inner = (width - 2.0 * LEGEND_PAD).max(SWATCH + CHAR_W);
        let max_chars = ((inner - SWATCH) / CHAR_W).floor().max(1.0) as usize;
        let entries: Vec<(String, String)> = entries
            .into_iter()
            .map(|(text, color)| {
                if text.chars().count() <= max_chars {
                    (text, color)
                } else {
                    let cut: String = text.chars().take(max_chars.saturating_sub(1)).collect();
                    (format!("{cut}…"), color)
                }
            })
            .collect();
        let widest = entries.iter().map(|(t, _)| SWATCH + text_width_px(t)).fold(0.0, f64::max);
        let column = widest + LEGEND_GAP;
        let columns = (((inner + LEGEND_GAP) / column).floor() as usize).clamp(1, entries.len().max(1));
        Legend { entries, columns, column }
    }

    fn rows(&self) -> usize {
        self.entries.len().div_ceil(self.columns)
    }

    /// Height of the framed legend; 0 without entries.
    fn height(&self) -> f64 {
        if self.entries.is_empty() { 0.0 } else { self.rows() as f64 * LEGEND_ROW + 2.0 * LEGEND_PAD }
    }

    /// Width of the framed legend.
    fn width(&self) -> f64 {
        self.columns as f64 * self.column - LEGEND_GAP + 2.0 * LEGEND_PAD
    }

    /// Draws the legend with its top-left corner at `(x, y)`, framed by a
    /// `<rect class="legend">` (what tests check the layout with).
    fn draw(&self, s: &mut String, x: f64, y: f64) {
        if self.entries.is_empty() {
            return;
        }
        let _ = writeln!(
            s,
            r##"<g class="legend"><rect class="legend" x="{x:.1}" y="{y:.1}" width="{:.1}" height="{:.1}" fill="white" stroke="#ccc"/>"##,
            self.width(),
            self.height()
        );
        for (i, (text, color)) in self.entries.iter().enumerate() {
            let (col, row) = (i % self.columns, i / self.columns);
            let ex = x + LEGEND_PAD + col as f64 * self.column;
            let ey = y + LEGEND_PAD + row as f64 * LEGEND_ROW + LEGEND_ROW / 2.0;
            let _ = writeln!(
                s,
                r#"<line x1="{ex:.1}" y1="{ey:.1}" x2="{:.1}" y2="{ey:.1}" stroke="{}" stroke-width="2"/><text x="{:.1}" y="{:.1}">{}</text>"#,
                ex + SWATCH - 6.0,
                escape(color),
                ex + SWATCH,
                ey + 4.0,
                escape(text)
            );
        }
        s.push_str("</g>\n");
    }
}

/// Draws `charts` side by side into one standalone SVG document.
///
/// Each panel's y-axis spans the series that scale it
/// ([`Series::scales_axis`]) with a little room above and below; the
/// others are clipped to it. Legends sit below the axes, never on the
/// data: one shared legend across the figure when every panel has the
/// same entries, else one under each panel. The data area of panel `i` is
/// `<rect class="plot">` with its axis ranges in `data-x-range` and
/// `data-y-range` (`"low high"`), so tests and scripts can read them back.
pub fn charts_svg(charts: &[Chart]) -> String {
    let width = PANEL_W * charts.len().max(1) as f64;
    let entries = |c: &Chart| -> Vec<(String, String)> {
        let (_, (yl, yh)) = ranges(c);
        c.series.iter().map(|se| (legend_text(se, yl, yh), se.color.clone())).collect()
    };
    let all: Vec<Vec<(String, String)>> = charts.iter().map(entries).collect();
    let shared = charts.len() > 1 && all.windows(2).all(|w| w[0] == w[1]);
    let legends: Vec<Legend> = if shared {
        vec![Legend::new(all[0].clone(), width - MARGIN_L - MARGIN_R)]
    } else {
        all.into_iter().map(|e| Legend::new(e, PANEL_W - MARGIN_L - MARGIN_R)).collect()
    };
    let legend_h = legends.iter().map(Legend::height).fold(0.0, f64::max);
    let legend_top = MARGIN_T + PLOT_H + AXIS_H;
    let height = legend_top + legend_h + if legend_h > 0.0 { 8.0 } else { 0.0 };
    let mut s = String::new();
    let _ = writeln!(
        s,
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="{width}" height="{height}" viewBox="0 0 {width} {height}" font-family="sans-serif" font-size="11">"#
    );
    let _ = writeln!(s, r#"<rect width="{width}" height="{height}" fill="white"/>"#);
    for (i, c) in charts.iter().enumerate() {
        panel(&mut s, c, i, PANEL_W * i as f64);
    }
    for (i, legend) in legends.iter().enumerate() {
        let x0 = if shared { 0.0 } else { PANEL_W * i as f64 };
        legend.draw(&mut s, x0 + MARGIN_L, legend_top);
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

/// The y values of `se`: its points and its band.
fn y_values(se: &Series) -> impl Iterator<Item = f64> + '_ {
    se.points.iter().map(|p| p.1).chain(se.band.iter().flat_map(|b| [b.1, b.2]))
}

/// The x and y axis ranges of `c`: x over every series; y over the series
/// that scale the axis (every series when none of those has a finite
/// value), with [`Y_PAD`] of room on each side.
fn ranges(c: &Chart) -> ((f64, f64), (f64, f64)) {
    let x = range(c.series.iter().flat_map(|se| se.points.iter().map(|p| p.0)));
    let scaling = || c.series.iter().filter(|se| se.scales_axis).flat_map(y_values);
    let (lo, hi) =
        if scaling().any(f64::is_finite) { range(scaling()) } else { range(c.series.iter().flat_map(y_values)) };
    let pad = (hi - lo) * Y_PAD;
    (x, (lo - pad, hi + pad))
}

/// The legend text of `se` on a y-axis `yl..yh`: its name, with
/// `(clipped)` when it does not scale the axis and part of it is outside.
fn legend_text(se: &Series, yl: f64, yh: f64) -> String {
    let outside = !se.scales_axis && y_values(se).any(|y| y.is_finite() && !(yl..=yh).contains(&y));
    if outside { format!("{} (clipped)", se.name) } else { se.name.clone() }
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

/// Draws panel `index` of a figure with its left edge at `x0`: title,
/// frame, grid, axis labels, bands and lines (clipped to the data area).
fn panel(s: &mut String, c: &Chart, index: usize, x0: f64) {
    let ((xl, xh), (yl, yh)) = ranges(c);
    let (pw, ph) = (PANEL_W - MARGIN_L - MARGIN_R, PLOT_H);
    let px = |x: f64| x0 + MARGIN_L + (x - xl) / (xh - xl) * pw;
    let py = |y: f64| MARGIN_T + (1.0 - (y - yl) / (yh - yl)) * ph;
    let left = x0 + MARGIN_L;
    let _ = writeln!(s, r#"<text x="{left}" y="18" font-size="13" font-weight="bold">{}</text>"#, escape(&c.title));
    let _ = writeln!(
        s,
        r#"<clipPath id="plot{index}"><rect x="{left}" y="{MARGIN_T}" width="{pw}" height="{ph}"/></clipPath>"#
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
            r##"<line x1="{left:.1}" y1="{y:.1}" x2="{:.1}" y2="{y:.1}" stroke="#eee"/><text x="{:.1}" y="{:.1}" text-anchor="end">{}</text>"##,
            left + pw,
            left - 4.0,
            y + 4.0,
            label(t)
        );
    }
    let _ = writeln!(
        s,
        r#"<text x="{:.1}" y="{:.1}" text-anchor="middle">{}</text>"#,
        left + pw / 2.0,
        MARGIN_T + ph + 34.0,
        escape(&c.x_label)
    );
    let _ = writeln!(
        s,
        r#"<text transform="translate({:.1} {:.1}) rotate(-90)" text-anchor="middle">{}</text>"#,
        x0 + 14.0,
        MARGIN_T + ph / 2.0,
        escape(&c.y_label)
    );
    let clip = format!(r#"clip-path="url(#plot{index})""#);
    for se in &c.series {
        let band: Vec<(f64, f64, f64)> =
            se.band.iter().copied().filter(|(x, l, h)| x.is_finite() && l.is_finite() && h.is_finite()).collect();
        if band.len() > 1 {
            let upper = band.iter().map(|&(x, _, h)| format!("{:.1},{:.1}", px(x), py(h)));
            let lower = band.iter().rev().map(|&(x, l, _)| format!("{:.1},{:.1}", px(x), py(l)));
            let pts: Vec<String> = upper.chain(lower).collect();
            let _ = writeln!(
                s,
                r#"<polygon {clip} fill="{}" fill-opacity="0.18" stroke="none" points="{}"/>"#,
                escape(&se.color),
                pts.join(" ")
            );
        }
    }
    // Lines that scale the axis last, so a clipped one never hides them.
    let order = c.series.iter().filter(|se| !se.scales_axis).chain(c.series.iter().filter(|se| se.scales_axis));
    for se in order {
        let pts: Vec<String> = se
            .points
            .iter()
            .filter(|(x, y)| x.is_finite() && y.is_finite())
            .map(|&(x, y)| format!("{:.1},{:.1}", px(x), py(y)))
            .collect();
        if !pts.is_empty() {
            let _ = writeln!(
                s,
                r#"<polyline {clip} fill="none" stroke="{}" stroke-width="1.5" points="{}"/>"#,
                escape(&se.color),
                pts.join(" ")
            );
        }
    }
    let _ = writeln!(
        s,
        r##"<rect class="plot" x="{left}" y="{MARGIN_T}" width="{pw}" height="{ph}" fill="none" stroke="#888" data-x-range="{xl} {xh}" data-y-range="{yl} {yh}"/>"##
    );
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
    enc.set_compression(png::Compression::Fast);
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
    /// A caption drawn under the picture: digits, letters and
    /// `.,:=-+()<>/%_#*`, lines split at `\n`.
    pub caption: String,
}

/// White space between gallery cells and around the grid, in pixels.
pub const GUTTER: usize = 4;

/// Lays `tiles` out in a grid of `columns` with a [`GUTTER`]-pixel white
/// gutter and returns the RGB picture `(pixels, width, height)`. Each cell
/// is a picture with its caption on a strip below it, so captions never
/// cover a model; cells are as big as the largest picture (wider if a
/// caption needs it, pictures centred) over the tallest caption.
pub fn gallery_rgb(tiles: &[Tile], columns: usize) -> (Vec<u8>, u32, u32) {
    let cols = columns.clamp(1, tiles.len().max(1));
    let rows = tiles.len().div_ceil(cols).max(1);
    let caption_h = tiles.iter().map(|t| font::text_height(&t.caption)).max().unwrap_or(0);
    let caption_w = tiles.iter().map(|t| font::text_width(&t.caption)).max().unwrap_or(0);
    let picture_h = tiles.iter().map(|t| t.height as usize).max().unwrap_or(1);
    let cw = tiles.iter().map(|t| t.width as usize).max().unwrap_or(1).max(caption_w);
    let ch = picture_h + caption_h;
    let (w, h) = (cols * cw + (cols + 1) * GUTTER, rows * ch + (rows + 1) * GUTTER);
    let mut img = vec![255u8; w * h * 3];
    for (i, t) in tiles.iter().enumerate() {
        let (ox, oy) = (GUTTER + (i % cols) * (cw + GUTTER), GUTTER + (i / cols) * (ch + GUTTER));
        let px = ox + (cw - t.width as usize) / 2;
        for y in 0..t.height as usize {
            let src = &t.rgb[y * t.width as usize * 3..(y + 1) * t.width as usize * 3];
            let at = ((oy + y) * w + px) * 3;
            img[at..at + src.len()].copy_from_slice(src);
        }
        draw_text(&mut img, w, ox, oy + picture_h, &t.caption);
    }
    (img, w as u32, h as u32)
}

/// Pixel size `(width, height)` of `text` as [`caption_rgb`] draws it.
pub fn caption_size(text: &str) -> (u32, u32) {
    (font::text_width(text) as u32, font::text_height(text) as u32)
}

/// Draws `text` (digits, letters and `.,:=-+()<>/%_#*`, lines split at
/// `\n`; a 5×7 font at 2× scale, dark grey on a white box per line) into
/// the RGB picture `img` of `width` pixels per row, its top-left corner at
/// `(x, y)`; what falls outside is clipped.
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
                    band: vec![(0.0, -4.0, -3.0), (1.0, 0.2, 0.6)],
                    ..Series::line("max", "#d62728", vec![(0.0, -3.5), (1.0, 0.4)])
                },
                Series::line("min", "#1f77b4", vec![(0.0, f64::NEG_INFINITY)]),
            ],
        };
        let svg = charts_svg(&[c.clone(), c]);
        assert_eq!(svg.matches("<polyline").count(), 2, "the all-non-finite series draws nothing");
        assert_eq!(svg.matches("<polygon").count(), 2, "one band per panel");
        assert!(svg.contains("fitness &lt;gen&gt;"));
        assert!(svg.starts_with("<svg") && svg.trim_end().ends_with("</svg>"));
        assert_eq!(svg.matches(r#"<rect class="legend""#).count(), 1, "panels with the same entries share a legend");
    }

    /// A parsed chart: the image size, each data area with its axis
    /// ranges `(x, y, w, h, [xl, xh], [yl, yh])` and each legend frame `(x, y, w, h)`.
    #[allow(clippy::type_complexity)]
    fn layout(svg: &str) -> ((f64, f64), Vec<([f64; 4], [f64; 2], [f64; 2])>, Vec<[f64; 4]>) {
        let doc = roxmltree::Document::parse(svg).expect("the chart is well-formed XML");
        let root = doc.root_element();
        let num = |n: roxmltree::Node, a: &str| n.attribute(a).unwrap().parse::<f64>().unwrap();
        let pair = |t: &str| {
            let v: Vec<f64> = t.split(' ').map(|x| x.parse().unwrap()).collect();
            [v[0], v[1]]
        };
        let rect = |n: roxmltree::Node| [num(n, "x"), num(n, "y"), num(n, "width"), num(n, "height")];
        let class = |c: &'static str| {
            doc.descendants().filter(move |n| n.has_tag_name("rect") && n.attribute("class") == Some(c))
        };
        let plots = class("plot")
            .map(|n| (rect(n), pair(n.attribute("data-x-range").unwrap()), pair(n.attribute("data-y-range").unwrap())))
            .collect();
        let legends = class("legend").map(rect).collect();
        ((num(root, "width"), num(root, "height")), plots, legends)
    }

    fn overlap(a: [f64; 4], b: [f64; 4]) -> bool {
        a[0] < b[0] + b[2] && b[0] < a[0] + a[2] && a[1] < b[1] + b[3] && b[1] < a[1] + a[3]
    }

    #[test]
    fn the_y_axis_follows_best_and_mean_and_clips_the_worst() {
        let gens: Vec<f64> = (0..20).map(f64::from).collect();
        let best: Vec<(f64, f64)> = gens.iter().map(|&g| (g, 1.0 + 0.01 * g)).collect();
        let mean: Vec<(f64, f64)> = gens.iter().map(|&g| (g, 0.8 + 0.01 * g)).collect();
        let worst: Vec<(f64, f64)> = gens.iter().map(|&g| (g, if g < 3.0 { -50.0 } else { 0.9 })).collect();
        let chart = Chart {
            title: "t".into(),
            x_label: "generation".into(),
            y_label: "fitness".into(),
            series: vec![
                Series::line("max", "#d62728", best),
                Series::line("avg", "#2ca02c", mean),
                Series { scales_axis: false, ..Series::line("min", "#1f77b4", worst) },
            ],
        };
        let svg = charts_svg(&[chart]);
        let (_, plots, _) = layout(&svg);
        let [yl, yh] = plots[0].2;
        // The data spans 0.8..1.19: the axis adds its 4 % pad, no more.
        assert!((yl - (0.8 - 0.0156)).abs() < 1e-9 && (yh - (1.19 + 0.0156)).abs() < 1e-9, "{yl} {yh}");
        assert!(svg.contains(">min (clipped)<"), "the legend says the worst line leaves the axis");
        assert!(svg.matches(r#"clip-path="url(#plot0)""#).count() == 3, "every line is clipped to the data area");
        // Without a scaling series the axis covers everything.
        let alone = Chart {
            series: vec![Series { scales_axis: false, ..Series::line("min", "#000", vec![(0.0, -5.0), (1.0, 5.0)]) }],
            ..Chart { title: String::new(), x_label: String::new(), y_label: String::new(), series: vec![] }
        };
        let (_, plots, _) = layout(&charts_svg(&[alone]));
        assert!(plots[0].2[0] < -5.0 && plots[0].2[1] > 5.0);
    }

    #[test]
    fn legends_sit_below_the_data_and_inside_the_image() {
        let long = |i: usize| format!("ga.population={} ga.selection.first={{tournament={i}}}", 10 * i);
        let series = |n: usize| -> Vec<Series> {
            (0..n).map(|i| Series::line(long(i), "#1f77b4", vec![(0.0, i as f64), (1.0, 2.0 * i as f64)])).collect()
        };
        let chart = |n: usize| Chart { title: "t".into(), x_label: "x".into(), y_label: "y".into(), series: series(n) };
        let very_long = Chart { series: vec![Series::line("x".repeat(300), "#000", vec![(0.0, 1.0)])], ..chart(0) };
        for charts in [vec![chart(5), chart(5)], vec![chart(3), chart(7)], vec![chart(12)], vec![very_long]] {
            let svg = charts_svg(&charts);
            let ((w, h), plots, legends) = layout(&svg);
            assert_eq!(plots.len(), charts.len());
            assert!(!legends.is_empty());
            for l in &legends {
                assert!(l[0] >= 0.0 && l[1] >= 0.0 && l[0] + l[2] <= w && l[1] + l[3] <= h, "legend {l:?} in {w}×{h}");
                for (p, _, _) in &plots {
                    assert!(!overlap(*l, *p), "legend {l:?} covers data area {p:?}");
                }
            }
            // Every legend text fits its frame at the estimated glyph width.
            let doc = roxmltree::Document::parse(&svg).unwrap();
            for g in doc.descendants().filter(|n| n.attribute("class") == Some("legend") && n.has_tag_name("g")) {
                let frame = g.children().find(|n| n.has_tag_name("rect")).unwrap();
                let right = frame.attribute("x").unwrap().parse::<f64>().unwrap()
                    + frame.attribute("width").unwrap().parse::<f64>().unwrap();
                for t in g.children().filter(|n| n.has_tag_name("text")) {
                    let x: f64 = t.attribute("x").unwrap().parse().unwrap();
                    assert!(x + text_width_px(t.text().unwrap()) <= right + 1e-6, "{:?} runs out", t.text());
                }
            }
        }
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
    fn captions_go_below_the_pictures() {
        let t = Tile { rgb: vec![128; 40 * 20 * 3], width: 40, height: 20, caption: "#1 0.5".into() };
        let (img, w, h) = gallery_rgb(&[t], 1);
        let (cw, ch) = caption_size("#1 0.5");
        assert_eq!((w, h), (cw.max(40) + 8, 20 + ch + 8));
        let w = w as usize;
        let grey = (4..24).all(|y| (0..40).all(|x| img[(y * w + (w - 40) / 2 + x) * 3] == 128));
        assert!(grey, "the caption leaves the picture whole");
        assert!(img[(24 * w) * 3..].chunks(3).any(|p| p[0] == 40), "the caption is drawn under it");
    }
}
