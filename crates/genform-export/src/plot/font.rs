//! A 3×5 bitmap font for captions in PNG reports.
//!
//! The previews are rasterized by our own renderer and resvg is built
//! without its `text` feature (which would pull in font discovery, system
//! fonts and a shaper — and make pictures depend on the fonts installed,
//! breaking byte-identical outputs across machines). Captions only need
//! numbers and short labels, so a tiny embedded font keeps them
//! dependency-free and identical everywhere.

/// Pixels per font pixel.
const SCALE: usize = 2;
/// Glyph cell width in font pixels (3 of glyph, 1 of space).
const ADVANCE: usize = 4;
/// Line height in font pixels (5 of glyph, 2 of space).
const LINE: usize = 7;

/// The 3×5 glyph of `c` (case-insensitive), one row per entry from the
/// top, bit 2 = left column; `?` for characters the font lacks.
fn glyph(c: char) -> [u8; 5] {
    match c.to_ascii_uppercase() {
        '0' => [7, 5, 5, 5, 7],
        '1' => [2, 6, 2, 2, 7],
        '2' => [7, 1, 7, 4, 7],
        '3' => [7, 1, 3, 1, 7],
        '4' => [5, 5, 7, 1, 1],
        '5' => [7, 4, 7, 1, 7],
        '6' => [7, 4, 7, 5, 7],
        '7' => [7, 1, 1, 2, 2],
        '8' => [7, 5, 7, 5, 7],
        '9' => [7, 5, 7, 1, 7],
        'A' => [2, 5, 7, 5, 5],
        'B' => [6, 5, 6, 5, 6],
        'C' => [3, 4, 4, 4, 3],
        'D' => [6, 5, 5, 5, 6],
        'E' => [7, 4, 6, 4, 7],
        'F' => [7, 4, 6, 4, 4],
        'G' => [3, 4, 5, 5, 3],
        'H' => [5, 5, 7, 5, 5],
        'I' => [7, 2, 2, 2, 7],
        'J' => [1, 1, 1, 5, 2],
        'K' => [5, 5, 6, 5, 5],
        'L' => [4, 4, 4, 4, 7],
        'M' => [5, 7, 7, 5, 5],
        'N' => [6, 5, 5, 5, 5],
        'O' => [2, 5, 5, 5, 2],
        'P' => [6, 5, 6, 4, 4],
        'Q' => [2, 5, 5, 6, 3],
        'R' => [6, 5, 6, 5, 5],
        'S' => [3, 4, 2, 1, 6],
        'T' => [7, 2, 2, 2, 2],
        'U' => [5, 5, 5, 5, 7],
        'V' => [5, 5, 5, 5, 2],
        'W' => [5, 5, 7, 7, 5],
        'X' => [5, 5, 2, 5, 5],
        'Y' => [5, 5, 2, 2, 2],
        'Z' => [7, 1, 2, 4, 7],
        '.' => [0, 0, 0, 0, 2],
        ',' => [0, 0, 0, 2, 4],
        ':' => [0, 2, 0, 2, 0],
        '=' => [0, 7, 0, 7, 0],
        '-' => [0, 0, 7, 0, 0],
        '+' => [0, 2, 7, 2, 0],
        '(' => [1, 2, 2, 2, 1],
        ')' => [4, 2, 2, 2, 4],
        '/' => [1, 1, 2, 4, 4],
        '%' => [5, 1, 2, 4, 5],
        '_' => [0, 0, 0, 0, 7],
        '#' => [5, 7, 5, 7, 5],
        ' ' => [0; 5],
        _ => [7, 1, 2, 0, 2],
    }
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
        let top = y + l * LINE * SCALE;
        for dy in 0..LINE * SCALE {
            for dx in 0..(chars * ADVANCE + 1) * SCALE {
                put(x + dx, top + dy, 255);
            }
        }
        for (i, c) in line.chars().enumerate() {
            for (row, bits) in glyph(c).iter().enumerate() {
                for col in 0..3 {
                    if bits & (4 >> col) == 0 {
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
        let set = "0123456789abcdefghijklmnopqrstuvwxyz.,:=-+()/%_# ";
        let unknown = glyph('\u{1}');
        let glyphs: Vec<[u8; 5]> = set.chars().map(glyph).collect();
        for (i, (c, g)) in set.chars().zip(&glyphs).enumerate() {
            assert_ne!(*g, unknown, "{c:?} falls back to `?`");
            assert!(glyphs[..i].iter().all(|o| o != g), "{c:?} looks like an earlier character");
        }
        assert_eq!(glyph('A'), glyph('a'));
    }

    #[test]
    fn lines_stack_and_stay_inside_the_picture() {
        let (w, h) = (40, 40);
        let mut img = vec![128u8; w * h * 3];
        draw_text(&mut img, w, 2, 2, "1\n1");
        let dark_rows: Vec<usize> = (0..h).filter(|y| (0..w).any(|x| img[(y * w + x) * 3] == 40)).collect();
        // Two glyphs of 5 rows at scale 2, 14 pixels apart.
        assert_eq!(dark_rows.len(), 20);
        assert_eq!(dark_rows[10] - dark_rows[0], 14);
        // Text running off the right edge is cut, not wrapped into the next row.
        draw_text(&mut img, w, 30, 30, "888888");
        assert_eq!(img.len(), w * h * 3);
    }
}
