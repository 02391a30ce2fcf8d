//! Deterministic per-tag colors, shared by the GLB materials and the preview.

/// The display color of a tag, as 8-bit sRGB.
///
/// A name ending in `#rrggbb` (six hex digits, either case), such as
/// `leaf#3a7d23` or just `#3a7d23`, gets exactly that color. Any other name
/// gets one derived from a hash of the name alone, so a tag keeps its color
/// across scenes, runs and formats: any hue, moderate saturation, fairly
/// bright.
pub fn tag_color(name: &str) -> [u8; 3] {
    if let Some(rgb) = explicit_color(name) {
        return rgb;
    }
    // FNV-1a, then a splitmix64 finalizer to spread the bits.
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for b in name.bytes() {
        h ^= u64::from(b);
        h = h.wrapping_mul(0x0000_0100_0000_01b3);
    }
    h ^= h >> 30;
    h = h.wrapping_mul(0xbf58_476d_1ce4_e5b9);
    h ^= h >> 27;
    h = h.wrapping_mul(0x94d0_49bb_1331_11eb);
    h ^= h >> 31;
    let unit = |bits: u64| (bits & 0xFFFF) as f32 / 65535.0;
    let hue = unit(h);
    let sat = 0.40 + 0.25 * unit(h >> 16);
    let val = 0.72 + 0.20 * unit(h >> 32);
    hsv_to_rgb(hue, sat, val).map(|c| (c * 255.0).round().clamp(0.0, 255.0) as u8)
}

/// The `#rrggbb` a name ends with, if any.
fn explicit_color(name: &str) -> Option<[u8; 3]> {
    let hex = name.len().checked_sub(7).and_then(|i| name.get(i..))?.strip_prefix('#')?;
    if !hex.bytes().all(|b| b.is_ascii_hexdigit()) {
        return None;
    }
    let channel = |i: usize| u8::from_str_radix(&hex[i..i + 2], 16).ok();
    Some([channel(0)?, channel(2)?, channel(4)?])
}

/// HSV (all in `[0, 1]`) to RGB in `[0, 1]`.
fn hsv_to_rgb(h: f32, s: f32, v: f32) -> [f32; 3] {
    let h6 = (h.fract() * 6.0).min(5.999_999);
    let sector = h6 as u32;
    let f = h6 - sector as f32;
    let (p, q, t) = (v * (1.0 - s), v * (1.0 - s * f), v * (1.0 - s * (1.0 - f)));
    match sector {
        0 => [v, t, p],
        1 => [q, v, p],
        2 => [p, v, t],
        3 => [p, q, v],
        4 => [t, p, v],
        _ => [v, p, q],
    }
}

/// An 8-bit sRGB channel to linear light.
pub(crate) fn srgb_to_linear(c: u8) -> f32 {
    let c = f32::from(c) / 255.0;
    if c <= 0.04045 { c / 12.92 } else { ((c + 0.055) / 1.055).powf(2.4) }
}

/// Linear light to an 8-bit sRGB channel.
pub(crate) fn linear_to_srgb(c: f32) -> u8 {
    let c = c.clamp(0.0, 1.0);
    let s = if c <= 0.003_130_8 { c * 12.92 } else { 1.055 * c.powf(1.0 / 2.4) - 0.055 };
    (s * 255.0).round() as u8
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn colors_are_stable_and_distinct() {
        assert_eq!(tag_color("wall"), tag_color("wall"));
        assert_ne!(tag_color("wall"), tag_color("roof"));
        for name in ["", "a", "wall", "roof", "trunk", "leaf"] {
            let c = tag_color(name);
            let (lo, hi) = (*c.iter().min().unwrap(), *c.iter().max().unwrap());
            assert!(hi >= 180 && lo >= 60, "{name}: {c:?} too dark or too saturated");
        }
    }

    #[test]
    fn a_hex_suffix_names_the_color() {
        assert_eq!(tag_color("leaf#3a7d23"), [0x3a, 0x7d, 0x23]);
        assert_eq!(tag_color("#3A7D23"), [0x3a, 0x7d, 0x23]);
        assert_eq!(tag_color("stem #000000"), [0, 0, 0]);
        // Not a suffix of exactly six hex digits: the hashed color.
        for name in ["leaf#3a7d2", "leaf#3a7d2g", "leaf3a7d23", "#3a7d23 ", "leaf#3a7d23ff", "é#12345", "x#é"] {
            assert_eq!(explicit_color(name), None, "{name}");
        }
        assert_ne!(tag_color("leaf#3a7d2"), [0x3a, 0x7d, 0x2]);
    }

    #[test]
    fn srgb_round_trips() {
        for c in 0..=255u8 {
            assert_eq!(linear_to_srgb(srgb_to_linear(c)), c);
        }
    }
}
