//! Scan conversion of convex polygons: edges stepped row by row in exact
//! integer arithmetic ([`EdgeWalk`]) and the row spans between a polygon's
//! two chains ([`fill_convex`]), used by the triangle filler and the outline
//! filler alike. The coverage rule is [`super::raster`]'s.

use super::coverage::{Mask, or_span};
use super::project::{Frame, HALF, ONE, Pt, SUB};

/// `(floor(n / d), n mod d)` for `0 < d < 2^31` and `|n| < 2^62`: an `f64`
/// estimate made exact with integer remainders (an `i64` division is
/// several times slower, and edge setups do two).
#[inline]
fn div_floor(n: i64, d: i64) -> (i64, i64) {
    // Off by at most |n / d|·2^-52 + 1 (≤ 2^10 here); rounded towards −∞
    // (not zero) so that negative quotients rarely need the correction.
    let t = n as f64 / d as f64;
    let mut q = t as i64;
    if (q as f64) > t {
        q -= 1;
    }
    let mut r = n - q * d;
    if r < 0 || r >= d {
        // |r| < 2^41: this estimate is off by at most one.
        let q2 = (r as f64 / d as f64) as i64;
        q += q2;
        r -= q2 * d;
        if r < 0 {
            q -= 1;
            r += d;
        } else if r >= d {
            q += 1;
            r -= d;
        }
    }
    (q, r)
}

/// First pixel row whose center `y * ONE + HALF` is at or below `y`.
#[inline]
pub(crate) fn first_row(y: i64) -> i64 {
    (y - HALF + ONE - 1) >> SUB
}

/// One edge of a chain, stepped row by row: `x = u.x + floor(n / d)` with
/// `n` growing by `step` per row, kept as quotient and remainder.
pub(crate) struct EdgeWalk {
    /// Rows `..end` use this edge.
    end: i64,
    /// The edge's offset at the current row (see [`EdgeWalk::new`]).
    pub x: i64,
    r: i64,
    d: i64,
    step_q: i64,
    step_r: i64,
}

impl EdgeWalk {
    /// The edge from `u` (upper) to `l` (lower), at pixel row `row`. A left
    /// edge gives the least center `x = u.x + t` with `E >= 0`, a right edge
    /// the greatest with `E > 0`, where `E = d·t − k` or `k − d·t`,
    /// `d = l.y − u.y`, `k = (l.x − u.x)(y − u.y)`.
    pub fn new(u: Pt, l: Pt, row: i64, left: bool) -> EdgeWalk {
        let d = l[1] - u[1];
        if d <= 0 {
            // A horizontal edge covers no row center: already finished.
            return EdgeWalk { end: i64::MIN, x: 0, r: 0, d: 1, step_q: 0, step_r: 0 };
        }
        let dx = l[0] - u[0];
        let y = row * ONE + HALF;
        let k = dx * (y - u[1]);
        // Left: t >= ceil(k / d) = floor((k + d − 1) / d).
        // Right: t <= floor((k − 1) / d).
        let n = if left { k + d - 1 } else { k - 1 };
        let (q, r) = div_floor(n, d);
        let (step_q, step_r) = div_floor(dx * ONE, d);
        EdgeWalk { end: first_row(l[1]), x: u[0] + q, r, d, step_q, step_r }
    }

    #[inline(always)]
    pub fn step(&mut self) {
        // Branch-free carry: the remainder pattern of a slope is erratic.
        let r = self.r + self.step_r;
        let carry = !((r - self.d) >> 63);
        self.x += self.step_q + (carry & 1);
        self.r = r - (carry & self.d);
    }
}

/// Per-row chain positions of the polygon being filled (one slot per image
/// row), so each chain is walked in its own tight loop.
#[derive(Default)]
pub(crate) struct Rows {
    left: Vec<i64>,
    right: Vec<i64>,
}

/// Walks both chains down from `top`, writing the left and right edge
/// positions of each row of `rows` into `left` and `right`. The two chains
/// step in one loop so their carry chains overlap.
fn walk_chains(poly: &[Pt], top: usize, bottom: usize, (row0, row_end): (i64, i64), rows: &mut Rows) {
    let n = poly.len();
    let next = |i: usize| (i + 1) % n;
    let prev = |i: usize| (i + n - 1) % n;
    let (mut ri, mut li) = (top, top);
    let mut right = EdgeWalk::new(poly[ri], poly[next(ri)], row0, false);
    let mut left = EdgeWalk::new(poly[li], poly[prev(li)], row0, true);
    let mut row = row0;
    while row < row_end {
        // (An edge ending at or above `row` before the bottom would be
        // replaced at once: its set-up, two divisions, is skipped.)
        while right.end <= row && ri != bottom {
            ri = next(ri);
            if ri == bottom || first_row(poly[next(ri)][1]) > row {
                right = EdgeWalk::new(poly[ri], poly[next(ri)], row, false);
            }
        }
        while left.end <= row && li != bottom {
            li = prev(li);
            if li == bottom || first_row(poly[prev(li)][1]) > row {
                left = EdgeWalk::new(poly[li], poly[prev(li)], row, true);
            }
        }
        // Rows up to `end` keep both edges (in a proper polygon every row
        // has one on each chain; `max` only guards against looping forever).
        let end = left.end.min(right.end).min(row_end).max(row + 1);
        let span = (row - row0) as usize..(end - row0) as usize;
        for (l, r) in rows.left[span.clone()].iter_mut().zip(&mut rows.right[span]) {
            *l = left.x;
            *r = right.x;
            left.step();
            right.step();
        }
        row = end;
    }
}

/// Fills a convex polygon wound so that [`cross`](super::project::cross) is positive, with no
/// repeated vertices, using the coverage rule of the module docs: rows whose
/// center `y` has `top <= y < bottom`; in each, the centers right of (or on)
/// the left chain and strictly left of the right chain.
pub(crate) fn fill_convex(frame: &Frame, poly: &[Pt], mask: &mut Mask, rows: &mut Rows) {
    let (mut top, mut bottom) = (0, 0);
    let (mut x_lo, mut x_hi) = (i64::MAX, i64::MIN);
    for (i, p) in poly.iter().enumerate() {
        if p[1] < poly[top][1] {
            top = i;
        }
        if p[1] > poly[bottom][1] {
            bottom = i;
        }
        x_lo = x_lo.min(p[0]);
        x_hi = x_hi.max(p[0]);
    }
    let row0 = first_row(poly[top][1]).max(0);
    let row_end = first_row(poly[bottom][1]).min(frame.height as i64);
    let x_max = frame.width as i64 - 1;
    // Pixel columns of the bounding box.
    let (col0, col1) = (((x_lo - HALF + ONE - 1) >> SUB).max(0), ((x_hi - HALF) >> SUB).min(x_max));
    if row0 >= row_end || col0 > col1 {
        return;
    }
    let len = (row_end - row0) as usize;
    if rows.left.len() < len {
        rows.left.resize(frame.height, 0);
        rows.right.resize(frame.height, 0);
    }
    // Forward from the top runs down the right chain; backward, the left.
    walk_chains(poly, top, bottom, (row0, row_end), rows);
    // Bookkeeping once per polygon, not per span.
    mask.mark(row0 as usize..row_end as usize, col0 as usize / 64, col1 as usize / 64);
    let mut record = mask.record.take();
    let (words, wpr) = mask.words_mut();
    let lines = words.chunks_exact_mut(wpr).skip(row0 as usize);
    for (y, ((line, &xl), &xr)) in (row0..).zip(lines.zip(&rows.left[..len]).zip(&rows.right[..len])) {
        // Center i·ONE + HALF >= xl  ⇔  i >= ceil((xl − HALF) / ONE).
        let x0 = ((xl - HALF + ONE - 1) >> SUB).max(col0);
        let x1 = ((xr - HALF) >> SUB).min(col1);
        if x0 > x1 {
            continue;
        }
        or_span(line, x0, x1);
        if let Some(r) = &mut record {
            r.push((y as u32, x0 as u32, x1 as u32));
        }
    }
    mask.record = record;
}

#[cfg(test)]
pub(super) mod tests {
    use super::*;
    use proptest::prelude::*;

    /// Snapped points on a grid of half pixels (so many edges and vertices
    /// pass exactly through pixel centers) or anywhere, reaching past the
    /// borders of a 16×12 image.
    pub(in crate::image) fn point() -> impl Strategy<Value = Pt> {
        prop_oneof![
            (-6i64..40, -6i64..30).prop_map(|(x, y)| [x * HALF, y * HALF]),
            (-6 * HALF..40 * HALF, -6 * HALF..30 * HALF).prop_map(|(x, y)| [x, y]),
        ]
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(400))]

        /// Stepping an edge row by row gives the same offsets as dividing
        /// afresh at every row.
        #[test]
        fn edge_walks_step_exactly(u in point(), l in point(), left in any::<bool>()) {
            let (u, l) = if u[1] <= l[1] { (u, l) } else { (l, u) };
            prop_assume!(u[1] < l[1]);
            let start = first_row(u[1]);
            let mut walk = EdgeWalk::new(u, l, start, left);
            for row in start..walk.end {
                let fresh = EdgeWalk::new(u, l, row, left);
                prop_assert_eq!((walk.x, walk.r), (fresh.x, fresh.r), "row {}", row);
                walk.step();
            }
        }

        /// The float-estimated division is exact over the whole range edge
        /// setups use, near the extremes too.
        #[test]
        fn div_floor_is_exact(
            n in prop_oneof![any::<i64>().prop_map(|n| n >> 2), -1_000_000i64..1_000_000],
            d in prop_oneof![1i64..100, 1i64..(1 << 31)],
        ) {
            prop_assert_eq!(div_floor(n, d), (n.div_euclid(d), n.rem_euclid(d)));
        }

        /// One step keeps `q·d + r` = the numerator and `0 <= r < d`,
        /// carrying exactly when the remainder reaches the denominator.
        #[test]
        fn edge_steps_carry_exactly(d in 1i64..50, r in 0i64..50, q in -99i64..99, step in -500i64..500) {
            let r = r % d;
            let step_q = step.div_euclid(d);
            let mut w = EdgeWalk { end: 0, x: q, r, d, step_q, step_r: step - step_q * d };
            w.step();
            let n = q * d + r + step;
            prop_assert_eq!((w.x, w.r), (n.div_euclid(d), n.rem_euclid(d)));
        }
    }
}
