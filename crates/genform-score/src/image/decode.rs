//! Picture decoding for image targets: PNG (any colour type and bit depth the
//! `png` crate reads) to luminance and alpha, and PFM (portable float map) to
//! weights. Both take bytes; neither reads files.

use super::error::ImageError;
use std::io::Cursor;

/// A decoded PNG: per pixel, row by row from the top, the Rec. 709
/// luminance of its 8-bit values (`2126 R + 7152 G + 722 B`, so 0 to
/// 2 550 000) and its 8-bit alpha.
pub(crate) struct LumaAlpha {
    pub width: u32,
    pub height: u32,
    pub luma: Vec<u32>,
    pub alpha: Vec<u8>,
}

/// Scale of [`LumaAlpha::luma`]: luminance 1.0 (white).
pub(crate) const LUMA_ONE: u32 = 2_550_000;

/// Decodes a PNG, normalized to 8 bits per channel (palettes and
/// transparency chunks expanded, 16-bit values stripped). Pictures with a
/// side above `max_side` are refused before their pixels are decoded.
pub(crate) fn decode_png(bytes: &[u8], max_side: u32) -> Result<LumaAlpha, ImageError> {
    let err = |e: png::DecodingError| ImageError::Png(e.to_string());
    let mut decoder = png::Decoder::new(Cursor::new(bytes));
    decoder.set_transformations(png::Transformations::normalize_to_color8());
    let mut reader = decoder.read_info().map_err(err)?;
    let (width, height) = (reader.info().width, reader.info().height);
    if width == 0 || height == 0 || width > max_side || height > max_side {
        return Err(ImageError::BadSize { width, height, max: max_side });
    }
    let size = reader.output_buffer_size().ok_or_else(|| ImageError::Png("the picture is too large".into()))?;
    let mut buf = vec![0; size];
    let info = reader.next_frame(&mut buf).map_err(err)?;
    let (color, depth) = reader.output_color_type();
    if depth != png::BitDepth::Eight {
        return Err(ImageError::Png(format!("unexpected bit depth {depth:?} after normalizing to 8 bits")));
    }
    let channels = match color {
        png::ColorType::Grayscale => 1,
        png::ColorType::GrayscaleAlpha => 2,
        png::ColorType::Rgb => 3,
        png::ColorType::Rgba => 4,
        png::ColorType::Indexed => return Err(ImageError::Png("palette left unexpanded".into())),
    };
    let n = width as usize * height as usize;
    let mut luma = Vec::with_capacity(n);
    let mut alpha = Vec::with_capacity(n);
    for row in buf[..info.buffer_size()].chunks_exact(info.line_size) {
        for px in row[..width as usize * channels].chunks_exact(channels) {
            let (l, a) = match *px {
                [g] => (u32::from(g) * 10_000, 255),
                [g, a] => (u32::from(g) * 10_000, a),
                [r, g, b] => (rec709(r, g, b), 255),
                [r, g, b, a] => (rec709(r, g, b), a),
                _ => unreachable!("chunks of 1 to 4 channels"),
            };
            luma.push(l);
            alpha.push(a);
        }
    }
    if luma.len() != n {
        return Err(ImageError::Png(format!("decoded {} pixels, expected {n}", luma.len())));
    }
    Ok(LumaAlpha { width, height, luma, alpha })
}

fn rec709(r: u8, g: u8, b: u8) -> u32 {
    2126 * u32::from(r) + 7152 * u32::from(g) + 722 * u32::from(b)
}

/// Parses a PFM: `PF` (RGB, the first channel is used) or `Pf` (grey), the
/// width and height, the scale (its sign gives the byte order: negative is
/// little-endian; its size is ignored), one whitespace byte, then 32-bit
/// floats with rows from the **bottom** up. Returns the width, height and
/// values row by row from the top.
pub(crate) fn parse_pfm(bytes: &[u8], max_side: u32) -> Result<(u32, u32, Vec<f32>), ImageError> {
    let bad = |m: String| ImageError::Pfm(m);
    let mut pos = 0;
    let mut token = |what: &str| -> Result<&str, ImageError> {
        while pos < bytes.len() && bytes[pos].is_ascii_whitespace() {
            pos += 1;
        }
        let start = pos;
        while pos < bytes.len() && !bytes[pos].is_ascii_whitespace() && pos - start < 32 {
            pos += 1;
        }
        if start == pos {
            return Err(bad(format!("the header ends before the {what}")));
        }
        std::str::from_utf8(&bytes[start..pos]).map_err(|_| bad(format!("the {what} is not text")))
    };
    let channels = match token("magic number")? {
        "PF" => 3,
        "Pf" => 1,
        other => return Err(bad(format!("starts with `{}`, not `PF` or `Pf`", other.escape_debug()))),
    };
    let side = |t: &str, what: &str| -> Result<u32, ImageError> {
        t.parse::<u32>().map_err(|_| bad(format!("the {what} `{}` is not a whole number", t.escape_debug())))
    };
    let width = side(token("width")?, "width")?;
    let height = side(token("height")?, "height")?;
    if width == 0 || height == 0 || width > max_side || height > max_side {
        return Err(ImageError::BadSize { width, height, max: max_side });
    }
    let scale_text = token("scale")?;
    let scale: f32 = scale_text
        .parse()
        .ok()
        .filter(|s: &f32| s.is_finite() && *s != 0.0)
        .ok_or_else(|| bad(format!("the scale `{}` is not a finite non-zero number", scale_text.escape_debug())))?;
    // Exactly one whitespace byte separates the header from the data.
    if pos >= bytes.len() || !bytes[pos].is_ascii_whitespace() {
        return Err(bad("no whitespace after the scale".into()));
    }
    let data = &bytes[pos + 1..];
    let row_len = width as usize * channels;
    let expected = row_len * height as usize * 4;
    if data.len() != expected {
        return Err(bad(format!(
            "{width}×{height}×{channels} floats need {expected} data bytes, the file has {}",
            data.len()
        )));
    }
    let little = scale < 0.0;
    let mut out = vec![0f32; width as usize * height as usize];
    for (file_row, row) in data.chunks_exact(row_len * 4).enumerate() {
        let y = height as usize - 1 - file_row;
        for x in 0..width as usize {
            let b: [u8; 4] = row[x * channels * 4..][..4].try_into().expect("4 bytes");
            let v = if little { f32::from_le_bytes(b) } else { f32::from_be_bytes(b) };
            if !v.is_finite() {
                return Err(ImageError::NonFiniteWeight { x: x as u32, y: y as u32 });
            }
            out[y * width as usize + x] = v;
        }
    }
    Ok((width, height, out))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn pfm(magic: &str, w: u32, h: u32, scale: &str, rows_bottom_up: &[f32]) -> Vec<u8> {
        let mut v = format!("{magic}\n{w} {h}\n{scale}\n").into_bytes();
        let little = scale.starts_with('-');
        for f in rows_bottom_up {
            v.extend_from_slice(&if little { f.to_le_bytes() } else { f.to_be_bytes() });
        }
        v
    }

    #[test]
    fn pfm_rows_run_bottom_to_top() {
        // File rows: bottom row first.
        let bytes = pfm("Pf", 2, 2, "-1.0", &[1.0, 2.0, 3.0, 4.0]);
        assert_eq!(parse_pfm(&bytes, 64).unwrap(), (2, 2, vec![3.0, 4.0, 1.0, 2.0]));
        // Big-endian and RGB: the first channel counts.
        let bytes = pfm("PF", 1, 2, "1.0", &[0.5, 9.0, 9.0, -0.25, 9.0, 9.0]);
        assert_eq!(parse_pfm(&bytes, 64).unwrap(), (1, 2, vec![-0.25, 0.5]));
    }

    #[test]
    fn malformed_pfm_is_an_error() {
        let good = pfm("Pf", 2, 2, "-1.0", &[1.0, 2.0, 3.0, 4.0]);
        let err = |b: &[u8]| parse_pfm(b, 64).unwrap_err().to_string();
        assert!(err(&good[..good.len() - 3]).contains("need 16 data bytes, the file has 13"), "{}", err(&good[..20]));
        assert!(err(b"P6\n2 2\n-1\n").contains("not `PF` or `Pf`"));
        assert!(err(b"Pf\n2 x\n-1\n").contains("height `x`"));
        assert!(err(b"Pf\n2 2\n").contains("before the scale"));
        assert!(err(b"Pf\n2 2\n0\n").contains("scale `0`"));
        assert!(err(b"Pf\n2 2\n-1").contains("no whitespace"));
        assert!(err(b"").contains("before the magic"));
        assert!(matches!(parse_pfm(b"Pf\n100 2\n-1\n", 64), Err(ImageError::BadSize { width: 100, .. })));
        let nan = pfm("Pf", 2, 1, "-1.0", &[1.0, f32::NAN]);
        assert_eq!(parse_pfm(&nan, 64), Err(ImageError::NonFiniteWeight { x: 1, y: 0 }));
    }

    #[test]
    fn png_of_any_layout_decodes_to_luma_and_alpha() {
        let encode = |w: u32, h: u32, color: png::ColorType, depth: png::BitDepth, data: &[u8]| {
            let mut out = Vec::new();
            let mut enc = png::Encoder::new(&mut out, w, h);
            enc.set_color(color);
            enc.set_depth(depth);
            let mut wr = enc.write_header().unwrap();
            wr.write_image_data(data).unwrap();
            wr.finish().unwrap();
            out
        };
        let rgba = encode(2, 1, png::ColorType::Rgba, png::BitDepth::Eight, &[255, 255, 255, 255, 0, 0, 0, 10]);
        let d = decode_png(&rgba, 64).unwrap();
        assert_eq!((d.width, d.height, d.luma, d.alpha), (2, 1, vec![LUMA_ONE, 0], vec![255, 10]));
        // 16-bit grey: stripped to its high byte.
        let g16 = encode(1, 2, png::ColorType::Grayscale, png::BitDepth::Sixteen, &[0x80, 0x01, 0xFF, 0xFF]);
        let d = decode_png(&g16, 64).unwrap();
        assert_eq!(d.luma, vec![128 * 10_000, LUMA_ONE]);
        // 1-bit grey: expanded to 0 / 255.
        let g1 = encode(3, 1, png::ColorType::Grayscale, png::BitDepth::One, &[0b1010_0000]);
        assert_eq!(decode_png(&g1, 64).unwrap().luma, vec![LUMA_ONE, 0, LUMA_ONE]);
        assert!(matches!(decode_png(&rgba, 1), Err(ImageError::BadSize { .. })));
        assert!(matches!(decode_png(&rgba[..20], 64), Err(ImageError::Png(_))));
        assert!(matches!(decode_png(b"not a png", 64), Err(ImageError::Png(_))));
    }
}
