//! Image targets: one weight per pixel (positive = cover, negative = avoid,
//! zero = don't care; thesis §4.2), prepared so that counting a covered
//! mask costs a popcount per word (one weight per sign) or two prefix-sum
//! lookups per covered run (any weights).

use super::coverage::{MAX_SIDE, Mask, words_per_row};
use super::decode::{LUMA_ONE, decode_png, parse_pfm};
use super::error::ImageError;

/// How a PNG's pixels become weights.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum PngMode {
    /// Dark = target, as the reference's black-on-white targets: a pixel with
    /// luminance below 0.5 and alpha at least 0.5 weighs +1, every other
    /// pixel −1 (covering it is "bad").
    #[default]
    Dark,
    /// Signed weights from grey levels: luminance 128 is 0 (don't care), 255
    /// is +1 and 0 is −1, linear in between (`(l − 128) / 127` above 128,
    /// `(l − 128) / 128` below). Pixels with alpha below 0.5 weigh 0.
    Signed,
}

impl PngMode {
    /// Every mode with its configuration name.
    pub const NAMES: [(&'static str, PngMode); 2] = [("dark", PngMode::Dark), ("signed", PngMode::Signed)];

    /// The mode named `name` (see [`PngMode::NAMES`]).
    pub fn from_name(name: &str) -> Option<PngMode> {
        PngMode::NAMES.iter().find(|(n, _)| *n == name).map(|&(_, m)| m)
    }
}

/// How covered weight is summed.
#[derive(Clone, Debug)]
enum Sums {
    /// Every positive pixel weighs `pos`, every negative one `−neg`: a
    /// popcount per mask word.
    Uniform { pos: f64, neg: f64 },
    /// Per row, `width + 1` running sums of the positive weights and of the
    /// magnitudes of the negative ones: a covered run costs two lookups.
    Prefix { pos: Vec<f64>, neg: Vec<f64> },
}

/// A weight image to compare silhouettes with.
#[derive(Clone, Debug)]
pub struct ImageTarget {
    width: u32,
    height: u32,
    weights: Vec<f32>,
    /// Bit per pixel, rows of [`words_per_row`] words: weight > 0.
    positive: Vec<u64>,
    /// Bit per pixel: weight < 0.
    negative: Vec<u64>,
    sums: Sums,
    total_positive: f64,
    total_negative: f64,
}

impl ImageTarget {
    /// A target from PNG bytes, read as `mode` says.
    pub fn from_png(bytes: &[u8], mode: PngMode) -> Result<ImageTarget, ImageError> {
        let img = decode_png(bytes, MAX_SIDE)?;
        let weights: Vec<f32> = img
            .luma
            .iter()
            .zip(&img.alpha)
            .map(|(&l, &a)| match mode {
                PngMode::Dark => {
                    if 2 * l < LUMA_ONE && a >= 128 {
                        1.0
                    } else {
                        -1.0
                    }
                }
                PngMode::Signed if a < 128 => 0.0,
                PngMode::Signed => {
                    let l = f64::from(l) / 10_000.0 - 128.0;
                    (if l >= 0.0 { l / 127.0 } else { l / 128.0 }) as f32
                }
            })
            .collect();
        ImageTarget::from_weights(img.width, img.height, &weights)
    }

    /// A target from a PFM float map (`Pf` grey or `PF` RGB, whose first
    /// channel is used): the values are the weights. PFM rows run bottom to
    /// top; this flips them.
    pub fn from_pfm(bytes: &[u8]) -> Result<ImageTarget, ImageError> {
        let (w, h, values) = parse_pfm(bytes, MAX_SIDE)?;
        ImageTarget::from_weights(w, h, &values)
    }

    /// A target from one weight per pixel, row by row from the top.
    pub fn from_weights(width: u32, height: u32, weights: &[f32]) -> Result<ImageTarget, ImageError> {
        if width == 0 || height == 0 || width > MAX_SIDE || height > MAX_SIDE {
            return Err(ImageError::BadSize { width, height, max: MAX_SIDE });
        }
        let (w, h) = (width as usize, height as usize);
        if weights.len() != w * h {
            return Err(ImageError::WeightCount { got: weights.len(), width, height });
        }
        if let Some(i) = weights.iter().position(|v| !v.is_finite()) {
            return Err(ImageError::NonFiniteWeight { x: (i % w) as u32, y: (i / w) as u32 });
        }
        let wpr = words_per_row(width);
        let mut positive = vec![0u64; wpr * h];
        let mut negative = vec![0u64; wpr * h];
        let (mut total_positive, mut total_negative) = (0.0, 0.0);
        let (mut pos_level, mut neg_level) = (None, None);
        let (mut uniform_pos, mut uniform_neg) = (true, true);
        for (i, &v) in weights.iter().enumerate() {
            let (x, y) = (i % w, i / w);
            let bit = 1u64 << (x % 64);
            if v > 0.0 {
                positive[y * wpr + x / 64] |= bit;
                total_positive += f64::from(v);
                uniform_pos &= *pos_level.get_or_insert(v) == v;
            } else if v < 0.0 {
                negative[y * wpr + x / 64] |= bit;
                total_negative -= f64::from(v);
                uniform_neg &= *neg_level.get_or_insert(v) == v;
            }
        }
        let sums = if uniform_pos && uniform_neg {
            Sums::Uniform { pos: pos_level.map_or(0.0, f64::from), neg: neg_level.map_or(0.0, |v: f32| -f64::from(v)) }
        } else {
            let mut pos = Vec::with_capacity((w + 1) * h);
            let mut neg = Vec::with_capacity((w + 1) * h);
            for row in weights.chunks_exact(w) {
                let (mut p, mut n) = (0.0, 0.0);
                pos.push(0.0);
                neg.push(0.0);
                for &v in row {
                    p += f64::from(v.max(0.0));
                    n -= f64::from(v.min(0.0));
                    pos.push(p);
                    neg.push(n);
                }
            }
            Sums::Prefix { pos, neg }
        };
        Ok(ImageTarget {
            width,
            height,
            weights: weights.to_vec(),
            positive,
            negative,
            sums,
            total_positive,
            total_negative,
        })
    }

    /// Width in pixels.
    pub fn width(&self) -> u32 {
        self.width
    }

    /// Height in pixels.
    pub fn height(&self) -> u32 {
        self.height
    }

    /// The weight of pixel `(x, y)` (`y` from the top); 0 outside.
    pub fn weight(&self, x: u32, y: u32) -> f32 {
        if x < self.width && y < self.height { self.weights[(y * self.width + x) as usize] } else { 0.0 }
    }

    /// Σ of the positive weights: the most a silhouette can cover (`T`).
    pub fn total_positive(&self) -> f64 {
        self.total_positive
    }

    /// Σ of the magnitudes of the negative weights.
    pub fn total_negative(&self) -> f64 {
        self.total_negative
    }

    /// Number of pixels with a positive weight.
    pub fn positive_pixels(&self) -> u64 {
        self.positive.iter().map(|w| u64::from(w.count_ones())).sum()
    }

    /// Covered positive and (magnitude of) negative weight of the mask, which
    /// is cleared.
    pub(crate) fn drain_covered(&self, mask: &mut Mask) -> (f64, f64) {
        let wpr = words_per_row(self.width);
        match &self.sums {
            Sums::Uniform { pos, neg } => {
                let (mut p, mut n) = (0u64, 0u64);
                mask.drain(|y, w, bits| {
                    let i = y * wpr + w;
                    p += u64::from((bits & self.positive[i]).count_ones());
                    n += u64::from((bits & self.negative[i]).count_ones());
                });
                (p as f64 * pos, n as f64 * neg)
            }
            Sums::Prefix { .. } => {
                let (mut p, mut n) = (0.0, 0.0);
                mask.drain(|y, w, bits| {
                    let (a, b) = self.word_sums(y, w, bits);
                    p += a;
                    n += b;
                });
                (p, n)
            }
        }
    }

    /// Covered positive and (magnitude of) negative weight of the mask word
    /// `word` of row `y`, whose set bits are covered pixels.
    #[inline]
    pub(crate) fn word_sums(&self, y: usize, word: usize, bits: u64) -> (f64, f64) {
        let i = y * words_per_row(self.width) + word;
        match &self.sums {
            Sums::Uniform { pos, neg } => (
                f64::from((bits & self.positive[i]).count_ones()) * pos,
                f64::from((bits & self.negative[i]).count_ones()) * neg,
            ),
            Sums::Prefix { pos, neg } => {
                let base = y * (self.width as usize + 1) + word * 64;
                let (mut p, mut n) = (0.0, 0.0);
                // Bits past the right edge have no prefix entries.
                let valid = (self.width as usize).saturating_sub(word * 64);
                let mut rest = if valid >= 64 { bits } else { bits & ((1u64 << valid) - 1) };
                while rest != 0 {
                    let start = rest.trailing_zeros() as usize;
                    let run = (!(rest >> start)).trailing_zeros() as usize;
                    let (a, b) = (base + start, base + start + run);
                    p += pos[b] - pos[a];
                    n += neg[b] - neg[a];
                    // `run` may be 64 (start 0, all bits set).
                    rest &= if start + run >= 64 { 0 } else { !0u64 << (start + run) };
                }
                (p, n)
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn encode_grey(w: u32, h: u32, data: &[u8]) -> Vec<u8> {
        let mut out = Vec::new();
        let mut enc = png::Encoder::new(&mut out, w, h);
        enc.set_color(png::ColorType::Grayscale);
        enc.set_depth(png::BitDepth::Eight);
        let mut wr = enc.write_header().unwrap();
        wr.write_image_data(data).unwrap();
        wr.finish().unwrap();
        out
    }

    #[test]
    fn dark_png_pixels_are_the_target() {
        let bytes = encode_grey(3, 2, &[0, 127, 128, 255, 10, 200]);
        let t = ImageTarget::from_png(&bytes, PngMode::Dark).unwrap();
        assert_eq!((t.width(), t.height()), (3, 2));
        let w: Vec<f32> = (0..2).flat_map(|y| (0..3).map(move |x| (x, y))).map(|(x, y)| t.weight(x, y)).collect();
        assert_eq!(w, [1.0, 1.0, -1.0, -1.0, 1.0, -1.0]);
        assert_eq!((t.total_positive(), t.total_negative(), t.positive_pixels()), (3.0, 3.0, 3));
        assert!(matches!(t.sums, Sums::Uniform { pos: 1.0, neg: 1.0 }));
    }

    #[test]
    fn signed_png_maps_grey_to_weights() {
        let bytes = encode_grey(4, 1, &[0, 128, 255, 191]);
        let t = ImageTarget::from_png(&bytes, PngMode::Signed).unwrap();
        assert_eq!([t.weight(0, 0), t.weight(1, 0), t.weight(2, 0)], [-1.0, 0.0, 1.0]);
        assert!((t.weight(3, 0) - 63.0 / 127.0).abs() < 1e-6);
        assert!(matches!(t.sums, Sums::Prefix { .. }));
        assert_eq!(PngMode::from_name("signed"), Some(PngMode::Signed));
        assert_eq!(PngMode::from_name("bright"), None);
    }

    #[test]
    fn word_sums_agree_with_per_pixel_sums() {
        let (w, h) = (130u32, 3u32);
        let weights: Vec<f32> = (0..w * h).map(|i| ((i * 37 % 11) as f32 - 5.0) * 0.25).collect();
        let t = ImageTarget::from_weights(w, h, &weights).unwrap();
        for bits in [u64::MAX, 0, 0b1011_0110, 1 << 63 | 1, 0xF0F0_0000_0000_0F0F] {
            for y in 0..h as usize {
                for word in 0..words_per_row(w) {
                    let (p, n) = t.word_sums(y, word, bits);
                    let (mut ep, mut en) = (0.0, 0.0);
                    for k in 0..64 {
                        let x = word * 64 + k;
                        if bits >> k & 1 == 1 && x < w as usize {
                            let v = f64::from(weights[y * w as usize + x]);
                            if v > 0.0 { ep += v } else { en -= v }
                        }
                    }
                    assert!((p - ep).abs() < 1e-9 && (n - en).abs() < 1e-9, "row {y} word {word} bits {bits:x}");
                }
            }
        }
    }

    #[test]
    fn bad_weight_lists_are_errors() {
        assert_eq!(
            ImageTarget::from_weights(2, 2, &[0.0; 3]).unwrap_err(),
            ImageError::WeightCount { got: 3, width: 2, height: 2 }
        );
        assert_eq!(
            ImageTarget::from_weights(2, 1, &[0.0, f32::INFINITY]).unwrap_err(),
            ImageError::NonFiniteWeight { x: 1, y: 0 }
        );
        assert!(matches!(ImageTarget::from_weights(0, 1, &[]), Err(ImageError::BadSize { .. })));
    }
}
