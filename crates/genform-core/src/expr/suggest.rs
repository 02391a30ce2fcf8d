//! "Did you mean" hints: [`did_you_mean`] picks the known name closest to
//! a misspelt one by optimal-string-alignment distance.

/// The closest of `candidates` to `name` by edit distance, if close enough
/// to be a plausible typo (at most a third of the longer name's characters,
/// at least one); ties go to the first candidate.
pub fn did_you_mean<'a>(name: &str, candidates: impl IntoIterator<Item = &'a str>) -> Option<&'a str> {
    let name: Vec<char> = name.chars().collect();
    let mut rows = Rows::default();
    let mut best: Option<(usize, &str)> = None;
    for c in candidates {
        let len = c.chars().count();
        let limit = (name.len().max(len) / 3).max(1);
        // Only a strictly closer candidate replaces the best so far; the
        // length difference alone bounds the distance from below, so most
        // of a long list (every block id) is never aligned at all.
        let bound = best.map_or(limit, |(d, _)| limit.min(d.saturating_sub(1)));
        if best.is_some_and(|(d, _)| d == 0) || len.abs_diff(name.len()) > bound {
            continue;
        }
        if let Some(d) = distance_within(&name, c, bound, &mut rows) {
            best = Some((d, c));
        }
    }
    best.map(|(_, c)| c)
}

/// Edit distance counting a swap of two neighbouring characters as one
/// edit (optimal string alignment): `stpes` is one typo from `steps`.
#[cfg(test)]
pub(super) fn edit_distance(a: &str, b: &str) -> usize {
    let a: Vec<char> = a.chars().collect();
    distance_within(&a, b, usize::MAX, &mut Rows::default()).expect("no bound")
}

/// The three rows of the alignment table an optimal-string-alignment
/// distance needs, reused across candidates.
#[derive(Default)]
struct Rows {
    b: Vec<char>,
    before: Vec<usize>,
    last: Vec<usize>,
    this: Vec<usize>,
}

/// The optimal-string-alignment distance of `a` and `b` if it is at most
/// `max`, else `None` (given up as soon as a whole row exceeds `max`).
fn distance_within(a: &[char], b: &str, max: usize, rows: &mut Rows) -> Option<usize> {
    let Rows { b: bc, before, last, this } = rows;
    bc.clear();
    bc.extend(b.chars());
    let n = bc.len();
    for row in [&mut *before, &mut *last, &mut *this] {
        row.clear();
        row.resize(n + 1, 0);
    }
    last.iter_mut().enumerate().for_each(|(j, cell)| *cell = j);
    for i in 1..=a.len() {
        this[0] = i;
        let mut row_min = i;
        for j in 1..=n {
            let cost = usize::from(a[i - 1] != bc[j - 1]);
            let mut d = (last[j - 1] + cost).min(last[j] + 1).min(this[j - 1] + 1);
            if i > 1 && j > 1 && a[i - 1] == bc[j - 2] && a[i - 2] == bc[j - 1] {
                d = d.min(before[j - 2] + 1);
            }
            this[j] = d;
            row_min = row_min.min(d);
        }
        if row_min > max {
            return None;
        }
        std::mem::swap(before, last);
        std::mem::swap(last, this);
    }
    Some(last[n]).filter(|&d| d <= max)
}
