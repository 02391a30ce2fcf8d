//! A 5×7 bitmap font for captions in PNG reports.
//!
//! The previews are rasterized by our own renderer and resvg is built
//! without its `text` feature (which would pull in font discovery, system
//! fonts and a shaper — and make pictures depend on the fonts installed,
//! breaking byte-identical outputs across machines). Captions only need
//! numbers and short labels, so a small embedded font keeps them
//! dependency-free and identical everywhere. 5×7 (the classic character-LCD
//! size) rather than 3×5: at 3×5, `#` and `H`, `M` and `N`, `0` and `O`
//! could not be told apart.

/// Pixels per font pixel.
pub(crate) const SCALE: usize = 2;
/// Glyph width in font pixels.
const GLYPH_W: usize = 5;
/// Glyph height in font pixels.
const GLYPH_H: usize = 7;
/// Glyph cell width in font pixels (5 of glyph, 1 of space).
const ADVANCE: usize = GLYPH_W + 1;
/// Line height in font pixels (1 of space above, 7 of glyph, 1 below).
const LINE: usize = GLYPH_H + 2;

/// Pixel height of one line of text, its white box included.
pub(crate) const LINE_PX: usize = LINE * SCALE;

/// The 5×7 glyph of `c` (case-insensitive), one row per entry from the
/// top, bit 4 = left column; `?` for characters the font lacks.
fn glyph(c: char) -> [u8; 7] {
    match c.to_ascii_uppercase() {
        '0' => [0x0E, 0x11, 0x13, 0x15, 0x19, 0x11, 0x0E],
        '1' => [0x04, 0x0C, 0x04, 0x04, 0x04, 0x04, 0x0E],
        '2' => [0x0E, 0x11, 0x01, 0x02, 0x04, 0x08, 0x1F],
        '3' => [0x1F, 0x02, 0x04, 0x02, 0x01, 0x11, 0x0E],
        '4' => [0x02, 0x06, 0x0A, 0x12, 0x1F, 0x02, 0x02],
        '5' => [0x1F, 0x10, 0x1E, 0x01, 0x01, 0x11, 0x0E],
        '6' => [0x06, 0x08, 0x10, 0x1E, 0x11, 0x11, 0x0E],
        '7' => [0x1F, 0x01, 0x02, 0x04, 0x08, 0x08, 0x08],
        '8' => [0x0E, 0x11, 0x11, 0x0E, 0x11, 0x11, 0x0E],
        '9' => [0x0E, 0x11, 0x11, 0x0F, 0x01, 0x02, 0x0C],
        'A' => [0x0E, 0x11, 0x11, 0x11, 0x1F, 0x11, 0x11],
        'B' => [0x1E, 0x11, 0x11, 0x1E, 0x11, 0x11, 0x1E],
        'C' => [0x0E, 0x11, 0x10, 0x10, 0x10, 0x11, 0x0E],
        'D' => [0x1C, 0x12, 0x11, 0x11, 0x11, 0x12, 0x1C],
        'E' => [0x1F, 0x10, 0x10, 0x1E, 0x10, 0x10, 0x1F],
        'F' => [0x1F, 0x10, 0x10, 0x1E, 0x10, 0x10, 0x10],
        'G' => [0x0E, 0x11, 0x10, 0x17, 0x11, 0x11, 0x0F],
        'H' => [0x11, 0x11, 0x11, 0x1F, 0x11, 0x11, 0x11],
        'I' => [0x0E, 0x04, 0x04, 0x04, 0x04, 0x04, 0x0E],
        'J' => [0x07, 0x02, 0x02, 0x02, 0x02, 0x12, 0x0C],
        'K' => [0x11, 0x12, 0x14, 0x18, 0x14, 0x12, 0x11],
        'L' => [0x10, 0x10, 0x10, 0x10, 0x10, 0x10, 0x1F],
        'M' => [0x11, 0x1B, 0x15, 0x15, 0x11, 0x11, 0x11],
        'N' => [0x11, 0x11, 0x19, 0x15, 0x13, 0x11, 0x11],
        'O' => [0x0E, 0x11, 0x11, 0x11, 0x11, 0x11, 0x0E],
        'P' => [0x1E, 0x11, 0x11, 0x1E, 0x10, 0x10, 0x10],
        'Q' => [0x0E, 0x11, 0x11, 0x11, 0x15, 0x12, 0x0D],
        'R' => [0x1E, 0x11, 0x11, 0x1E, 0x14, 0x12, 0x11],
        'S' => [0x0F, 0x10, 0x10, 0x0E, 0x01, 0x01, 0x1E],
        'T' => [0x1F, 0x04, 0x04, 0x04, 0x04, 0x04, 0x04],
        'U' => [0x11, 0x11, 0x11, 0x11, 0x11, 0x11, 0x0E],
        'V' => [0x11, 0x11, 0x11, 0x11, 0x11, 0x0A, 0x04],
        'W' => [0x11, 0x11, 0x11, 0x15, 0x15, 0x15, 0x0A],
        'X' => [0x11, 0x11, 0x0A, 0x04, 0x0A, 0x11, 0x11],
        'Y' => [0x11, 0x11, 0x11, 0x0A, 0x04, 0x04, 0x04],
        'Z' => [0x1F, 0x01, 0x02, 0x04, 0x08, 0x10, 0x1F],
        '.' => [0x00, 0x00, 0x00, 0x00, 0x00, 0x0C, 0x0C],
        ',' => [0x00, 0x00, 0x00, 0x00, 0x0C, 0x04, 0x08],
        ':' => [0x00, 0x0C, 0x0C, 0x00, 0x0C, 0x0C, 0x00],
        '=' => [0x00, 0x00, 0x1F, 0x00, 0x1F, 0x00, 0x00],
        '-' => [0x00, 0x00, 0x00, 0x1F, 0x00, 0x00, 0x00],
        '+' => [0x00, 0x04, 0x04, 0x1F, 0x04, 0x04, 0x00],
        '(' => [0x02, 0x04, 0x08, 0x08, 0x08, 0x04, 0x02],
        ')' => [0x08, 0x04, 0x02, 0x02, 0x02, 0x04, 0x08],
        '<' => [0x02, 0x04, 0x08, 0x10, 0x08, 0x04, 0x02],
        '>' => [0x08, 0x04, 0x02, 0x01, 0x02, 0x04, 0x08],
        '/' => [0x00, 0x01, 0x02, 0x04, 0x08, 0x10, 0x00],
        '%' => [0x18, 0x19, 0x02, 0x04, 0x08, 0x13, 0x03],
        '_' => [0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x1F],
        '#' => [0x0A, 0x0A, 0x1F, 0x0A, 0x1F, 0x0A, 0x0A],
        '*' => [0x00, 0x04, 0x15, 0x0E, 0x15, 0x04, 0x00],
        ' ' => [0; 7],
        _ => [0x0E, 0x11, 0x01, 0x02, 0x04, 0x00, 0x04],
    }
}

/// Pixel width of the widest line of `text` as [`draw_text`] draws it,
/// its white box included.
pub(crate) fn text_width(text: &str) -> usize {
    text.lines().map(|l| l.chars().count()).max().map_or(0, |n| if n == 0 { 0 } else { (n * ADVANCE + 1) * SCALE })
}

/// Pixel height of `text` as [`draw_text`] draws it: one [`LINE_PX`] per line.
pub(crate) fn text_height(text: &str) -> usize {
    text.lines().count() * LINE_PX
}

/// Draws `text` (lines split at `\n`) at 2× scale in dark grey (40), each
/// line on a white box, with its top-left corner at `(x, y)` of the RGB
/// picture `img` that is `width` pixels wide; pixels outside are skipped.
pub(crate) fn draw_text(img: &mut [u8], width: usize, x: usize, y: usize, text: &str) {
    let height = img.len() / 3 / width.max(1);
    let mut put = |px: usize, py: usize, v: u8| {
        if px < width && py < height {
            img[(py * width + px) * 3..][..3].fill(v);
        }
    };
    for (l, line) in text.lines().enumerate() {
        let chars = line.chars().count();
        if chars == 0 {
            continue;
        }
        let top = y + l * LINE_PX;
        for dy in 0..LINE_PX {
            for dx in 0..(chars * ADVANCE + 1) * SCALE {
                put(x + dx, top + dy, 255);
            }
        }
        for (i, c) in line.chars().enumerate() {
            for (row, bits) in glyph(c).iter().enumerate() {
                for col in 0..GLYPH_W {
                    if bits & (0x10 >> col) == 0 {
                        continue;
                    }
                    for sy in 0..SCALE {
                        for sx in 0..SCALE {
                            put(x + (1 + i * ADVANCE + col) * SCALE + sx, top + (1 + row) * SCALE + sy, 40);
                        }
                    }
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_caption_character_has_its_own_glyph() {
        let set = "0123456789abcdefghijklmnopqrstuvwxyz.,:=-+()<>/%_#* ";
        let unknown = glyph('\u{1}');
        let glyphs: Vec<[u8; 7]> = set.chars().map(glyph).collect();
        for (i, (c, g)) in set.chars().zip(&glyphs).enumerate() {
            assert_ne!(*g, unknown, "{c:?} falls back to `?`");
            assert!(glyphs[..i].iter().all(|o| o != g), "{c:?} looks like an earlier character");
            assert!(g.iter().all(|row| *row < 0x20), "{c:?} is wider than 5 columns");
        }
        assert_eq!(glyph('A'), glyph('a'));
    }

    /// Pixels where two glyphs differ: a pair that differs in only a pixel
    /// or two is hard to read apart at a glance.
    fn difference(a: char, b: char) -> u32 {
        glyph(a).iter().zip(glyph(b)).map(|(x, y)| (x ^ y).count_ones()).sum()
    }

    #[test]
    fn look_alike_pairs_differ_clearly() {
        for (a, b) in [('#', 'H'), ('0', 'O'), ('M', 'N'), ('8', 'B'), ('5', 'S'), ('1', 'I'), ('2', 'Z')] {
            assert!(difference(a, b) >= 3, "{a:?} and {b:?} differ in {} pixels", difference(a, b));
        }
    }

    #[test]
    fn lines_stack_and_stay_inside_the_picture() {
        let (w, h) = (40, 40);
        let mut img = vec![128u8; w * h * 3];
        draw_text(&mut img, w, 2, 2, "1\n1");
        let dark_rows: Vec<usize> = (0..h).filter(|y| (0..w).any(|x| img[(y * w + x) * 3] == 40)).collect();
        // Two glyphs of 7 rows at scale 2, one line (18 pixels) apart.
        assert_eq!(dark_rows.len(), 28);
        assert_eq!(dark_rows[14] - dark_rows[0], LINE_PX);
        assert_eq!(text_width("1\n123"), (3 * ADVANCE + 1) * SCALE);
        assert_eq!(text_height("1\n123"), 2 * LINE_PX);
        // Text running off the right edge is cut, not wrapped into the next row.
        draw_text(&mut img, w, 30, 30, "888888");
        assert_eq!(img.len(), w * h * 3);
    }
}
