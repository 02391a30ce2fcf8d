//! Split arithmetic: how a box of `length` cells along one axis is cut into
//! pieces for a size list, so that every cell belongs to exactly one piece.
//!
//! Sizes: a positive value is an absolute length in blocks (rounded down);
//! a negative value is a relative weight of what the absolute pieces leave.
//!
//! * Without `repeat`, absolute pieces take their length; the remainder `R`
//!   is shared by the relative pieces in proportion to their weights, each
//!   getting the whole-block part of its share. The `k` cells those
//!   rounded-down shares leave over go, one each, to relative pieces chosen
//!   by the rounding mode: `start` the first `k`, `end` the last `k`,
//!   `middle` the `k` nearest the middle of the list, `truncate` (default)
//!   all of them to the last relative piece. With no relative piece the
//!   absolute sizes must add up to the length exactly.
//! * With `repeat` and only absolute sizes, the pattern is tiled `n = L / P`
//!   times (`P` its length) and the `r = L mod P` cells left form a partial
//!   copy, clipped: `truncate` and `end` put the pattern's first pieces at
//!   the end (the last one cut short), `start` puts its last pieces at the
//!   start (the first one cut short), `middle` centres the tiling with
//!   `r / 2` cells of partial copy at the start and the rest at the end.
//! * With `repeat` and relative sizes, a weight also counts as its piece's
//!   nominal length in blocks: `n = max(1, ⌊L / P⌋)` copies fit, and the
//!   relative pieces of all copies share what the absolute ones leave as
//!   above, so the copies stretch to fill the box exactly.
//!
//! An absolute part longer than the box, a piece of zero cells, or a size
//! that is zero or not finite fails the split (a rule failure, never a
//! piece outside the box).

use serde::{Deserialize, Serialize};

/// Where the cells that do not divide evenly go.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Round {
    /// Computed from the start; the end takes what is left (the last
    /// relative piece grows, a partial repeat copy is clipped at the end).
    #[default]
    Truncate,
    /// Leftover cells go to the first relative pieces; a partial copy
    /// goes at the start.
    Start,
    /// Leftover cells go to the last relative pieces; a partial copy goes
    /// at the end.
    End,
    /// Leftover cells go to the relative pieces nearest the middle; partial
    /// copies go to both ends.
    Middle,
}

/// One piece of a split: the index of its size (and child) in the pattern
/// and its length in cells.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Piece {
    /// Position in the size list (and so which child it becomes).
    pub child: usize,
    /// Cells along the split axis.
    pub length: u32,
}

/// Why a split cannot be made.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum SplitError {
    /// A size is zero, NaN or infinite.
    #[error("size {value} of child {child} is not a length (zero, NaN or infinite)")]
    BadSize {
        /// Position in the size list.
        child: usize,
        /// The size.
        value: f64,
    },
    /// The absolute pieces do not fit.
    #[error("the absolute sizes need {needed} blocks but the box is only {length} long")]
    Oversized {
        /// Blocks the absolute pieces need.
        needed: u64,
        /// Length of the box.
        length: u32,
    },
    /// Absolute sizes only, and they do not add up to the length.
    #[error("the sizes add up to {sum} but the box is {length} long (add a relative size such as -1, or `repeat`)")]
    Mismatch {
        /// Sum of the sizes.
        sum: u64,
        /// Length of the box.
        length: u32,
    },
    /// A piece would get no cells.
    #[error("child {child} would have zero size")]
    ZeroSize {
        /// Position in the size list.
        child: usize,
    },
    /// No sizes at all.
    #[error("a split needs at least one size")]
    NoSizes,
}

#[derive(Clone, Copy)]
enum Size {
    Abs(u64),
    Rel,
}

/// Reusable buffers, so a derivation splits without allocating.
#[derive(Default)]
pub(crate) struct Scratch {
    pattern: Vec<Size>,
    weights: Vec<f64>,
    shares: Vec<u64>,
    order: Vec<usize>,
    lens: Vec<u64>,
}

/// Cuts `length` cells by `sizes`; the pieces, in order, go to `out`
/// (cleared first). Their lengths add up to `length` on success.
pub fn split_lengths(
    length: u32,
    sizes: &[f64],
    repeat: bool,
    round: Round,
    out: &mut Vec<Piece>,
) -> Result<(), SplitError> {
    split_with(&mut Scratch::default(), length, sizes, repeat, round, out)
}

/// [`split_lengths`] with reusable buffers.
pub(crate) fn split_with(
    s: &mut Scratch,
    length: u32,
    sizes: &[f64],
    repeat: bool,
    round: Round,
    out: &mut Vec<Piece>,
) -> Result<(), SplitError> {
    out.clear();
    if sizes.is_empty() {
        return Err(SplitError::NoSizes);
    }
    s.pattern.clear();
    s.weights.clear();
    let (mut abs, mut weight) = (0u64, 0.0f64);
    for (child, &v) in sizes.iter().enumerate() {
        if !v.is_finite() || v == 0.0 {
            return Err(SplitError::BadSize { child, value: v });
        }
        if v > 0.0 {
            let a = v.floor().min(u32::MAX as f64) as u64;
            if a == 0 {
                return Err(SplitError::ZeroSize { child });
            }
            abs += a;
            s.pattern.push(Size::Abs(a));
        } else {
            weight += -v;
            s.weights.push(-v);
            s.pattern.push(Size::Rel);
        }
    }
    let rels = s.weights.len();
    let l = length as u64;
    if !repeat {
        if abs > l {
            return Err(SplitError::Oversized { needed: abs, length });
        }
        if rels == 0 && abs != l {
            return Err(SplitError::Mismatch { sum: abs, length });
        }
        distribute(s, l - abs, round);
        return emit(&s.pattern, 1, &s.shares, out);
    }
    if rels == 0 {
        let (n, r) = (l / abs, l % abs);
        s.lens.clear();
        s.lens.extend(s.pattern.iter().map(|p| if let Size::Abs(a) = p { *a } else { 0 }));
        let (front, back) = match round {
            Round::Truncate | Round::End => (0, r),
            Round::Start => (r, 0),
            Round::Middle => (r / 2, r - r / 2),
        };
        tail(&s.lens, front, out);
        for _ in 0..n {
            out.extend(s.lens.iter().enumerate().map(|(child, &a)| Piece { child, length: a as u32 }));
        }
        head(&s.lens, back, out);
        return Ok(());
    }
    let nominal = abs as f64 + weight;
    let n = ((l as f64 / nominal).floor() as u64).max(1);
    if n.saturating_mul(abs) > l {
        return Err(SplitError::Oversized { needed: n.saturating_mul(abs), length });
    }
    if n.saturating_mul(s.pattern.len() as u64) > l {
        let child = s.pattern.iter().position(|p| matches!(p, Size::Rel)).unwrap_or(0);
        return Err(SplitError::ZeroSize { child });
    }
    for _ in 1..n {
        s.weights.extend_from_within(..rels);
    }
    distribute(s, l - n * abs, round);
    emit(&s.pattern, n, &s.shares, out)
}

/// `n` copies of the pattern with the relative pieces' lengths from `shares`.
fn emit(pattern: &[Size], n: u64, shares: &[u64], out: &mut Vec<Piece>) -> Result<(), SplitError> {
    let mut next = shares.iter();
    for _ in 0..n {
        for (child, p) in pattern.iter().enumerate() {
            let len = match p {
                Size::Abs(a) => *a,
                Size::Rel => next.next().copied().unwrap_or(0),
            };
            if len == 0 {
                return Err(SplitError::ZeroSize { child });
            }
            out.push(Piece { child, length: len as u32 });
        }
    }
    Ok(())
}

/// The pattern's first pieces, the last one clipped, covering `k` cells.
fn head(lens: &[u64], mut k: u64, out: &mut Vec<Piece>) {
    for (child, &a) in lens.iter().enumerate() {
        if k == 0 {
            return;
        }
        let take = a.min(k);
        out.push(Piece { child, length: take as u32 });
        k -= take;
    }
}

/// The pattern's last pieces, the first one clipped, covering `k` cells.
fn tail(lens: &[u64], mut k: u64, out: &mut Vec<Piece>) {
    let at = out.len();
    for (child, &a) in lens.iter().enumerate().rev() {
        if k == 0 {
            break;
        }
        let take = a.min(k);
        out.push(Piece { child, length: take as u32 });
        k -= take;
    }
    out[at..].reverse();
}

/// Shares of `total` cells for `s.weights` into `s.shares`, summing to
/// `total` exactly.
fn distribute(s: &mut Scratch, total: u64, round: Round) {
    let weights = &s.weights;
    let shares = &mut s.shares;
    shares.clear();
    let m = weights.len();
    if m <= 1 {
        shares.extend(weights.iter().map(|_| total));
        return;
    }
    let sum: f64 = weights.iter().sum();
    let integral = weights.iter().all(|w| w.fract() == 0.0 && *w < 1e15) && sum < 1e15;
    if integral {
        let t = sum as u128;
        shares.extend(weights.iter().map(|&w| (total as u128 * w as u128 / t) as u64));
    } else {
        shares.extend(weights.iter().map(|&w| ((total as f64) * (w / sum)).floor().max(0.0) as u64));
    }
    // Floating rounding may overshoot by a cell; take it back from the end.
    let mut given: u64 = shares.iter().sum();
    for v in shares.iter_mut().rev() {
        while given > total && *v > 0 {
            *v -= 1;
            given -= 1;
        }
    }
    let mut left = total - given;
    if left == 0 {
        return;
    }
    if round == Round::Truncate {
        shares[m - 1] += left;
        return;
    }
    let order = &mut s.order;
    order.clear();
    match round {
        Round::Start | Round::Truncate => order.extend(0..m),
        Round::End => order.extend((0..m).rev()),
        Round::Middle => {
            order.extend(0..m);
            order.sort_by_key(|&i| ((2 * i as i64 - (m as i64 - 1)).abs(), i));
        }
    }
    while left > 0 {
        for &i in order.iter() {
            if left == 0 {
                break;
            }
            shares[i] += 1;
            left -= 1;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    fn lens(length: u32, sizes: &[f64], repeat: bool, round: Round) -> Result<Vec<(usize, u32)>, SplitError> {
        let mut out = Vec::new();
        split_lengths(length, sizes, repeat, round, &mut out)?;
        Ok(out.iter().map(|p| (p.child, p.length)).collect())
    }

    fn only(length: u32, sizes: &[f64], repeat: bool, round: Round) -> Vec<u32> {
        lens(length, sizes, repeat, round).unwrap().into_iter().map(|(_, l)| l).collect()
    }

    #[test]
    fn absolute_and_relative_pieces() {
        assert_eq!(only(10, &[4.0, -1.0, 4.0], false, Round::Truncate), vec![4, 2, 4]);
        assert_eq!(only(10, &[1.0, -1.0, -2.0], false, Round::Truncate), vec![1, 3, 6]);
        assert_eq!(only(4, &[1.0, 2.0, 1.0], false, Round::Truncate), vec![1, 2, 1]);
        // 2.7 blocks round down to 2.
        assert_eq!(only(5, &[2.7, -1.0], false, Round::Truncate), vec![2, 3]);
    }

    #[test]
    fn every_rounding_mode_places_the_leftover_cells() {
        // 11 cells in 4 equal shares: 2 each, 3 left over.
        let w = [-1.0; 4];
        assert_eq!(only(11, &w, false, Round::Truncate), vec![2, 2, 2, 5]);
        assert_eq!(only(11, &w, false, Round::Start), vec![3, 3, 3, 2]);
        assert_eq!(only(11, &w, false, Round::End), vec![2, 3, 3, 3]);
        assert_eq!(only(10, &w, false, Round::Middle), vec![2, 3, 3, 2]);
        assert_eq!(only(9, &w, false, Round::Middle), vec![2, 3, 2, 2]);
        assert_eq!(only(12, &[-1.0; 5], false, Round::Middle), vec![2, 3, 3, 2, 2]);
        assert_eq!(only(11, &[-1.0; 5], false, Round::Middle), vec![2, 2, 3, 2, 2]);
    }

    #[test]
    fn repeat_clips_the_partial_copy_where_the_mode_says() {
        // Pattern 1 + 2 = 3 long, 8 cells: 2 copies and 2 left.
        let p = [1.0, 2.0];
        assert_eq!(lens(8, &p, true, Round::Truncate).unwrap(), vec![(0, 1), (1, 2), (0, 1), (1, 2), (0, 1), (1, 1)]);
        assert_eq!(lens(8, &p, true, Round::End).unwrap(), lens(8, &p, true, Round::Truncate).unwrap());
        assert_eq!(lens(8, &p, true, Round::Start).unwrap(), vec![(1, 2), (0, 1), (1, 2), (0, 1), (1, 2)]);
        assert_eq!(lens(8, &p, true, Round::Middle).unwrap(), vec![(1, 1), (0, 1), (1, 2), (0, 1), (1, 2), (0, 1)]);
        // The pattern longer than the box: one clipped copy.
        assert_eq!(lens(2, &[3.0, 1.0], true, Round::Truncate).unwrap(), vec![(0, 2)]);
        assert_eq!(lens(2, &[3.0, 1.0], true, Round::Start).unwrap(), vec![(0, 1), (1, 1)]);
    }

    #[test]
    fn repeat_with_relative_pieces_stretches_the_copies() {
        // Nominal 1 + 2 = 3; 10 cells fit 3 copies, relative pieces share 10.
        assert_eq!(
            lens(10, &[-1.0, -2.0], true, Round::Middle).unwrap(),
            vec![(0, 1), (1, 2), (0, 2), (1, 2), (0, 1), (1, 2)]
        );
        // Absolute pieces keep their size: 3 copies of 1 + stretch.
        assert_eq!(only(11, &[1.0, -2.0], true, Round::Start), vec![1, 3, 1, 3, 1, 2]);
    }

    #[test]
    fn failures_instead_of_writes_outside_the_parent() {
        assert_eq!(lens(5, &[4.0, 4.0], false, Round::Truncate), Err(SplitError::Oversized { needed: 8, length: 5 }));
        assert_eq!(
            lens(5, &[4.0, -1.0, 2.0], false, Round::Truncate),
            Err(SplitError::Oversized { needed: 6, length: 5 })
        );
        assert_eq!(lens(8, &[4.0, 2.0], false, Round::Truncate), Err(SplitError::Mismatch { sum: 6, length: 8 }));
        assert_eq!(lens(4, &[4.0, -1.0], false, Round::Truncate), Err(SplitError::ZeroSize { child: 1 }));
        assert_eq!(lens(1, &[-1.0, 1.0], false, Round::Truncate), Err(SplitError::ZeroSize { child: 0 }));
        assert_eq!(lens(3, &[-1.0, -1.0, -1.0, -1.0], false, Round::End), Err(SplitError::ZeroSize { child: 0 }));
        assert!(matches!(lens(3, &[0.0, -1.0], false, Round::End), Err(SplitError::BadSize { child: 0, .. })));
        assert!(matches!(lens(3, &[f64::NAN], false, Round::End), Err(SplitError::BadSize { .. })));
        assert_eq!(lens(3, &[0.5, -1.0], false, Round::End), Err(SplitError::ZeroSize { child: 0 }));
        assert_eq!(lens(3, &[4.0, -1.0], true, Round::End), Err(SplitError::Oversized { needed: 4, length: 3 }));
        // A tiny weight asks for more copies than there are cells.
        assert_eq!(lens(5, &[-0.01], true, Round::End), Err(SplitError::ZeroSize { child: 0 }));
    }

    proptest! {
        /// Whatever the sizes, a successful split covers every cell exactly
        /// once, in order, with positive lengths and valid child indices.
        #[test]
        fn splits_partition_the_length(
            length in 1u32..300,
            sizes in prop::collection::vec(prop_oneof![(1u32..20).prop_map(f64::from), (1u32..5).prop_map(|w| -f64::from(w)), (0.1f64..4.0).prop_map(|w| -w)], 1..6),
            repeat in any::<bool>(),
            round in prop_oneof![Just(Round::Truncate), Just(Round::Start), Just(Round::End), Just(Round::Middle)],
        ) {
            let mut out = Vec::new();
            if split_lengths(length, &sizes, repeat, round, &mut out).is_ok() {
                prop_assert_eq!(out.iter().map(|p| p.length as u64).sum::<u64>(), length as u64);
                prop_assert!(out.iter().all(|p| p.length > 0 && p.child < sizes.len()));
                // Absolute pieces are never longer than asked.
                for p in &out {
                    if sizes[p.child] > 0.0 {
                        prop_assert!(p.length as f64 <= sizes[p.child].floor());
                    }
                }
                if !repeat {
                    prop_assert_eq!(out.len(), sizes.len());
                }
            }
            if repeat && sizes.iter().all(|s| *s > 0.0) {
                prop_assert!(split_lengths(length, &sizes, repeat, round, &mut out).is_ok(), "pure repeats always fit");
            }
        }
    }
}
