//! Deterministic per-tag colors, shared by the GLB materials and the preview;
//! the fixed edge-type palette and the guide colours.

use genform_core::SurfaceEdge;

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

/// The colours of edge types 0, 1, 2, …, repeating: saturated and dark
/// enough to show over the light tag colours of the faces.
const EDGE_PALETTE: [[u8; 3]; 9] = [
    [0x1f, 0x77, 0xb4],
    [0xd6, 0x27, 0x28],
    [0x2c, 0xa0, 0x2c],
    [0xff, 0x7f, 0x0e],
    [0x94, 0x67, 0xbd],
    [0x17, 0xbe, 0xcf],
    [0xe3, 0x77, 0xc2],
    [0x8c, 0x56, 0x4b],
    [0xbc, 0xbd, 0x22],
];

/// The colour of untyped edges ([`SurfaceEdge::UNTYPED`]): a neutral grey.
const UNTYPED_EDGE: [u8; 3] = [0x70, 0x70, 0x70];

/// The display colour of surface edges of type `kind`, as 8-bit sRGB: a fixed
/// palette of nine colours repeating with the type, grey for
/// [`SurfaceEdge::UNTYPED`]. The GLB materials, the SVG strokes and the PNG
/// preview all use it.
pub fn edge_color(kind: u32) -> [u8; 3] {
    if kind == SurfaceEdge::UNTYPED { UNTYPED_EDGE } else { EDGE_PALETTE[kind as usize % EDGE_PALETTE.len()] }
}

/// The name of edge type `kind` in files: `edge<N>`, or `edge_untyped`.
pub(crate) fn edge_type_name(kind: u32) -> String {
    if kind == SurfaceEdge::UNTYPED { "edge_untyped".to_string() } else { format!("edge{kind}") }
}

/// What a guide is drawn as, from its tag name.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum GuideRole {
    /// A point pulling the growth (tag containing `attract`).
    Attractor,
    /// A point pushing it away (tag containing `repel`).
    Repeller,
    /// Anything else (a boundary).
    Other,
}

impl GuideRole {
    /// The role a guide tag names (case-insensitive).
    pub(crate) fn of(tag: &str) -> GuideRole {
        let t = tag.to_ascii_lowercase();
        if t.contains("repel") {
            GuideRole::Repeller
        } else if t.contains("attract") {
            GuideRole::Attractor
        } else {
            GuideRole::Other
        }
    }
}

/// The colour of a guide: a `#rrggbb` suffix of its tag if any, else blue
/// for attractors, red for repellers, blue-grey for anything else.
pub(crate) fn guide_color(tag: &str) -> [u8; 3] {
    explicit_color(tag).unwrap_or(match GuideRole::of(tag) {
        GuideRole::Attractor => [0x2b, 0x6c, 0xd9],
        GuideRole::Repeller => [0xe0, 0x3c, 0x31],
        GuideRole::Other => [0x9a, 0xa8, 0xbd],
    })
}

/// `c` mixed with white: `amount` 0 keeps it, 1 gives white.
pub(crate) fn lighten(c: [u8; 3], amount: f32) -> [u8; 3] {
    c.map(|x| (f32::from(x) + (255.0 - f32::from(x)) * amount.clamp(0.0, 1.0)).round() as u8)
}

/// The `#rrggbb` a name ends with, if any.
pub(crate) fn explicit_color(name: &str) -> Option<[u8; 3]> {
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
    fn edge_palette_repeats_and_untyped_is_grey() {
        assert_eq!(edge_color(0), edge_color(9));
        let first: std::collections::BTreeSet<[u8; 3]> = (0..9).map(edge_color).collect();
        assert_eq!(first.len(), 9);
        assert_eq!(edge_color(SurfaceEdge::UNTYPED), UNTYPED_EDGE);
        assert!(!first.contains(&UNTYPED_EDGE));
        assert_eq!((edge_type_name(3), edge_type_name(SurfaceEdge::UNTYPED)), ("edge3".into(), "edge_untyped".into()));
        assert_ne!(guide_color("attractor"), guide_color("Repeller"));
        assert_eq!(guide_color("repellor#102030"), [0x10, 0x20, 0x30]);
        assert_eq!(lighten([0, 100, 255], 0.5), [128, 178, 255]);
    }

    #[test]
    fn srgb_round_trips() {
        for c in 0..=255u8 {
            assert_eq!(linear_to_srgb(srgb_to_linear(c)), c);
        }
    }
}
