//! Bit-packed voxel rows.
//!
//! A [`BitRows`] holds one bit per voxel: rows of `u64` words along the
//! lattice row axis, one row per `(j, k)`. Voxel `i` of a row is bit
//! `i % 64` of word `i / 64`; bits past the row's end stay zero.

use crate::error::ScoreError;

/// Rows of bits, `words` `u64`s each.
#[derive(Clone, Debug, PartialEq, Eq)]
pub(crate) struct BitRows {
    words: usize,
    data: Vec<u64>,
}

/// The mask of bits `a..=b` (both `< 64`, `a <= b`) of one word.
#[inline]
pub(crate) fn bit_range(a: u32, b: u32) -> u64 {
    debug_assert!(a <= b && b < 64);
    (u64::MAX >> (63 - b)) & (u64::MAX << a)
}

/// Calls `f(word, mask)` for each word that bits `a..=b` of a row cover.
#[inline]
pub(crate) fn for_each_word(a: usize, b: usize, mut f: impl FnMut(usize, u64)) {
    let (wa, wb) = (a / 64, b / 64);
    if wa == wb {
        f(wa, bit_range((a % 64) as u32, (b % 64) as u32));
        return;
    }
    f(wa, u64::MAX << (a % 64));
    for w in wa + 1..wb {
        f(w, u64::MAX);
    }
    f(wb, u64::MAX >> (63 - b % 64));
}

impl BitRows {
    /// `rows` empty rows of `words` words.
    pub fn new(words: usize, rows: usize) -> BitRows {
        BitRows { words, data: vec![0; words * rows] }
    }

    /// `rows` empty rows of `words` words, allocated fallibly: a grid of
    /// `voxels` past the machine's memory is [`ScoreError::Allocation`].
    pub fn try_new(words: usize, rows: usize, voxels: u64) -> Result<BitRows, ScoreError> {
        let failed = || ScoreError::Allocation { voxels, bytes: words as u128 * rows as u128 * 8 };
        let n = words.checked_mul(rows).ok_or_else(failed)?;
        let mut data = Vec::new();
        data.try_reserve_exact(n).map_err(|_| failed())?;
        data.resize(n, 0);
        Ok(BitRows { words, data })
    }

    /// All words, row after row.
    pub fn data(&self) -> &[u64] {
        &self.data
    }

    /// All words, mutably.
    pub fn data_mut(&mut self) -> &mut [u64] {
        &mut self.data
    }

    /// The words of row `r`.
    pub fn row(&self, r: usize) -> &[u64] {
        &self.data[r * self.words..(r + 1) * self.words]
    }

    /// Whether bit `i` of row `r` is set.
    pub fn get(&self, r: usize, i: usize) -> bool {
        self.data[r * self.words + i / 64] >> (i % 64) & 1 == 1
    }

    /// Sets bits `a..=b` of row `r`.
    pub fn set_range(&mut self, r: usize, a: usize, b: usize) {
        let row = &mut self.data[r * self.words..(r + 1) * self.words];
        for_each_word(a, b, |w, m| row[w] |= m);
    }

    /// Set bits in all rows.
    pub fn count(&self) -> u64 {
        popcount(&self.data)
    }

    /// `|self ∧ other|` over the rows `rows` yields.
    pub fn count_and(&self, other: &BitRows, rows: impl IntoIterator<Item = usize>) -> u64 {
        rows.into_iter()
            .map(|r| self.row(r).iter().zip(other.row(r)).map(|(a, b)| (a & b).count_ones() as u64).sum::<u64>())
            .sum()
    }

    /// `|self ∧ ¬other|` over the rows `rows` yields.
    pub fn count_andnot(&self, other: &BitRows, rows: impl IntoIterator<Item = usize>) -> u64 {
        rows.into_iter()
            .map(|r| self.row(r).iter().zip(other.row(r)).map(|(a, b)| (a & !b).count_ones() as u64).sum::<u64>())
            .sum()
    }

    /// Calls `f(r, a, b)` for each maximal run `a..=b` of set bits, row by row.
    pub fn for_each_run(&self, mut f: impl FnMut(usize, usize, usize)) {
        let rows = self.data.len().checked_div(self.words).unwrap_or(0);
        for r in 0..rows {
            let row = self.row(r);
            let mut start: Option<usize> = None;
            for (w, &word) in row.iter().enumerate() {
                let mut pos = 0u32;
                while pos < 64 {
                    // Inside a run look for the next zero, else for the next one.
                    let rest = if start.is_some() { !word >> pos } else { word >> pos };
                    if rest == 0 {
                        break;
                    }
                    pos += rest.trailing_zeros();
                    let at = w * 64 + pos as usize;
                    match start.take() {
                        Some(s) => f(r, s, at - 1),
                        None => start = Some(at),
                    }
                }
            }
            if let Some(s) = start {
                f(r, s, row.len() * 64 - 1);
            }
        }
    }
}

/// Set bits in a slice of words.
#[inline]
pub(crate) fn popcount(words: &[u64]) -> u64 {
    words.iter().map(|w| u64::from(w.count_ones())).sum()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rows_past_the_machine_are_an_error_not_an_abort() {
        let e = BitRows::try_new(usize::MAX / 4, 3, 7).unwrap_err();
        assert_eq!(e, ScoreError::Allocation { voxels: 7, bytes: (usize::MAX / 4) as u128 * 3 * 8 });
        assert!(e.to_string().starts_with("cannot allocate ") && e.to_string().ends_with("lower `voxels`"));
        let e = BitRows::try_new(usize::MAX / 16, 1, 9).unwrap_err();
        assert!(matches!(e, ScoreError::Allocation { voxels: 9, .. }), "{e}");
        assert_eq!(BitRows::try_new(2, 3, 100).unwrap(), BitRows::new(2, 3));
    }

    #[test]
    fn ranges_and_words() {
        assert_eq!(bit_range(0, 63), u64::MAX);
        assert_eq!(bit_range(3, 5), 0b111000);
        let mut seen = Vec::new();
        for_each_word(60, 130, |w, m| seen.push((w, m)));
        assert_eq!(seen, vec![(0, 0xF << 60), (1, u64::MAX), (2, 0b111)]);
        seen.clear();
        for_each_word(64, 64, |w, m| seen.push((w, m)));
        assert_eq!(seen, vec![(1, 1)]);
    }

    #[test]
    fn counting_over_rows() {
        let mut a = BitRows::new(2, 3);
        let mut b = BitRows::new(2, 3);
        a.set_range(0, 10, 70); // 61 bits
        a.set_range(2, 0, 0);
        b.set_range(0, 60, 127);
        b.set_range(1, 0, 127);
        assert_eq!(a.count(), 62);
        assert!(a.get(0, 70) && !a.get(0, 71) && a.get(2, 0));
        assert_eq!(a.count_and(&b, 0..3), 11);
        assert_eq!(a.count_andnot(&b, 0..3), 51);
        assert_eq!(a.count_and(&b, [2]), 0);
        assert_eq!(a.count_andnot(&b, [2]), 1);
    }

    #[test]
    fn runs_cover_exactly_the_set_bits() {
        let mut a = BitRows::new(2, 2);
        a.set_range(0, 0, 3);
        a.set_range(0, 5, 5);
        a.set_range(0, 63, 64);
        a.set_range(0, 100, 127);
        a.set_range(1, 64, 64);
        let mut runs = Vec::new();
        a.for_each_run(|r, s, e| runs.push((r, s, e)));
        assert_eq!(runs, vec![(0, 0, 3), (0, 5, 5), (0, 63, 64), (0, 100, 127), (1, 64, 64)]);
    }
}
