//! Bit-packed pixel masks: [`Mask`], the rasterizer's reusable buffer that
//! remembers which rows and words it touched (so only those are counted and
//! cleared), and [`Coverage`], an owned copy for callers and tests.

use crate::span_cache::{Bounds, Span};

/// The largest image side accepted, in pixels.
pub const MAX_SIDE: u32 = 4096;

/// Mask words per row of a `width`-pixel image.
pub(crate) fn words_per_row(width: u32) -> usize {
    (width as usize).div_ceil(64)
}

/// Covers pixels `x0..=x1` (`0 <= x0 <= x1`, within the row) of one row's
/// mask words.
#[inline]
pub(crate) fn or_span(line: &mut [u64], x0: i64, x1: i64) {
    let (w0, w1) = (x0 as usize / 64, x1 as usize / 64);
    let first = !0u64 << (x0 % 64);
    let last = !0u64 >> (63 - x1 % 64);
    // Branch-free for one or two words (whether a span crosses a word
    // boundary is a coin toss): with one word both writes set the same
    // bits.
    let one = w0 == w1;
    line[w0] |= first & if one { last } else { !0 };
    line[w1] |= last & if one { first } else { !0 };
    // Short runs are the rule; a loop beats a call to memset.
    for w in line.iter_mut().take(w1).skip(w0 + 1) {
        *w = !0;
    }
}

/// Which pixels a silhouette covers: one bit per pixel, rows from the top,
/// each row [`Coverage::words_per_row`] `u64` words with pixel `x` at bit
/// `x % 64` of word `x / 64`.
#[derive(Clone, PartialEq, Eq)]
pub struct Coverage {
    width: u32,
    height: u32,
    words: Vec<u64>,
}

impl std::fmt::Debug for Coverage {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "Coverage({}×{}, {} pixels covered)", self.width, self.height, self.count())
    }
}

impl Coverage {
    /// An empty mask.
    pub fn new(width: u32, height: u32) -> Coverage {
        Coverage { width, height, words: vec![0; words_per_row(width) * height as usize] }
    }

    /// Width in pixels.
    pub fn width(&self) -> u32 {
        self.width
    }

    /// Height in pixels.
    pub fn height(&self) -> u32 {
        self.height
    }

    /// Words per row (`ceil(width / 64)`).
    pub fn words_per_row(&self) -> usize {
        words_per_row(self.width)
    }

    /// The mask words, row by row.
    pub fn words(&self) -> &[u64] {
        &self.words
    }

    /// Whether pixel `(x, y)` is covered (`false` outside the image).
    pub fn get(&self, x: u32, y: u32) -> bool {
        x < self.width && y < self.height && {
            let w = self.words[y as usize * self.words_per_row() + x as usize / 64];
            w >> (x % 64) & 1 == 1
        }
    }

    /// Marks pixel `(x, y)` covered (ignored outside the image).
    pub fn set(&mut self, x: u32, y: u32) {
        if x < self.width && y < self.height {
            let i = y as usize * self.words_per_row() + x as usize / 64;
            self.words[i] |= 1 << (x % 64);
        }
    }

    /// Number of covered pixels.
    pub fn count(&self) -> u64 {
        self.words.iter().map(|w| u64::from(w.count_ones())).sum()
    }

    /// The pixels covered in one mask and not the other, row-major.
    pub fn differences(&self, other: &Coverage) -> Vec<(u32, u32)> {
        let mut out = Vec::new();
        for y in 0..self.height.max(other.height) {
            for x in 0..self.width.max(other.width) {
                if self.get(x, y) != other.get(x, y) {
                    out.push((x, y));
                }
            }
        }
        out
    }
}

/// The rasterizer's mask. Spans set bits and record their row and word
/// range; [`Mask::drain`] visits exactly the touched words and clears them,
/// so an evaluation costs what the silhouette covers, not the image size.
pub(crate) struct Mask {
    width: usize,
    height: usize,
    wpr: usize,
    words: Vec<u64>,
    /// Per row, the first and last touched word (`lo > hi`: untouched).
    lo: Vec<u32>,
    hi: Vec<u32>,
    /// One bit per row: touched since the last drain.
    rows: Vec<u64>,
    /// Where the spans being filled are recorded too, if they are (a mesh
    /// instance's for the span cache).
    pub record: Option<Vec<Span>>,
}

impl Mask {
    pub fn new(width: usize, height: usize) -> Mask {
        let wpr = width.div_ceil(64);
        Mask {
            width,
            height,
            wpr,
            words: vec![0; wpr * height],
            lo: vec![u32::MAX; height],
            hi: vec![0; height],
            rows: vec![0; height.div_ceil(64)],
            record: None,
        }
    }

    /// Fills recorded spans `(y, x0, x1)` again; `[y0, y1, x0, x1]` bound
    /// them (marked once, as a polygon's box is).
    pub fn replay(&mut self, spans: &[Span], [y0, y1, x0, x1]: Bounds) {
        if spans.is_empty() {
            return;
        }
        self.mark(y0 as usize..y1 as usize + 1, x0 as usize / 64, x1 as usize / 64);
        for &(y, a, b) in spans {
            let y = y as usize;
            or_span(&mut self.words[y * self.wpr..(y + 1) * self.wpr], i64::from(a), i64::from(b));
        }
    }

    pub fn size(&self) -> (usize, usize) {
        (self.width, self.height)
    }

    /// Covers pixels `x0..=x1` of row `y` (`x0 <= x1 < width`, `y < height`).
    #[cfg(test)]
    pub fn span(&mut self, y: usize, x0: usize, x1: usize) {
        debug_assert!(x0 <= x1 && x1 < self.width && y < self.height);
        self.mark(y..y + 1, x0 / 64, x1 / 64);
        for x in x0..=x1 {
            self.words[y * self.wpr + x / 64] |= 1 << (x % 64);
        }
    }

    /// Records that `rows` may get bits in words `w_lo..=w_hi`; call before
    /// writing through [`Mask::words_mut`].
    pub fn mark(&mut self, rows: std::ops::Range<usize>, w_lo: usize, w_hi: usize) {
        for (lo, hi) in self.lo[rows.clone()].iter_mut().zip(&mut self.hi[rows.clone()]) {
            *lo = (*lo).min(w_lo as u32);
            *hi = (*hi).max(w_hi as u32);
        }
        // Whole words of the row bitset at a time.
        let mut y = rows.start;
        while y < rows.end {
            let stop = rows.end.min((y / 64 + 1) * 64);
            let bits = (!0u64 >> (64 - (stop - y))) << (y % 64);
            self.rows[y / 64] |= bits;
            y = stop;
        }
    }

    /// The words, row by row, and the words per row.
    pub fn words_mut(&mut self) -> (&mut [u64], usize) {
        (&mut self.words, self.wpr)
    }

    /// Calls `f(y, word, bits)` for every touched word, rows from the top
    /// and words from the left, and clears the mask.
    #[inline]
    pub fn drain(&mut self, mut f: impl FnMut(usize, usize, u64)) {
        for (k, rows) in self.rows.iter_mut().enumerate() {
            let mut bits = std::mem::take(rows);
            while bits != 0 {
                let y = k * 64 + bits.trailing_zeros() as usize;
                bits &= bits - 1;
                let (lo, hi) = (self.lo[y] as usize, self.hi[y] as usize);
                for (w, word) in self.words[y * self.wpr..][lo..=hi].iter_mut().enumerate() {
                    // Marked ranges are bounding boxes: skip their empty words.
                    if *word != 0 {
                        f(y, lo + w, std::mem::take(word));
                    }
                }
                self.lo[y] = u32::MAX;
                self.hi[y] = 0;
            }
        }
    }

    /// Moves the covered pixels into a [`Coverage`], clearing the mask.
    pub fn take(&mut self) -> Coverage {
        let mut c = Coverage::new(self.width as u32, self.height as u32);
        let wpr = self.wpr;
        self.drain(|y, w, bits| c.words[y * wpr + w] = bits);
        c
    }

    /// Whether no bit is set (for tests: a drain must leave it so).
    #[cfg(test)]
    pub fn is_clear(&self) -> bool {
        self.words.iter().all(|&w| w == 0) && self.rows.iter().all(|&w| w == 0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn spans_set_exactly_their_pixels_and_drain_clears() {
        let mut m = Mask::new(200, 5);
        m.span(1, 3, 3);
        m.span(1, 60, 130);
        m.span(4, 0, 199);
        let c = m.take();
        assert!(m.is_clear());
        let expect = |x: u32, y: u32| (y == 1 && (x == 3 || (60..=130).contains(&x))) || y == 4;
        for y in 0..5 {
            for x in 0..200 {
                assert_eq!(c.get(x, y), expect(x, y), "({x}, {y})");
            }
        }
        assert_eq!(c.count(), 1 + 71 + 200);
        // Drains visit only touched rows, in order.
        m.span(3, 64, 64);
        m.span(0, 10, 20);
        let mut seen = Vec::new();
        m.drain(|y, w, bits| seen.push((y, w, bits)));
        assert_eq!(seen, vec![(0, 0, ((1u64 << 11) - 1) << 10), (3, 1, 1)]);
    }
}
