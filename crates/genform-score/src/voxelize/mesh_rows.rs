//! Spans of mesh instances: row crossings, bucketed by row, filled by parity.
//!
//! Each triangle is set up once ([`Setup`]: its counter-clockwise order,
//! canonical edges and which edges own their points) and then scanned
//! line by line across the rows its projection covers: per line of rows
//! the real-arithmetic interval of the projection (widened by a voxel)
//! bounds the rows tried, and each tried row evaluates exactly the edge
//! functions and interpolation of [`super::crossing`], with the same
//! operations in the same order, so the crossings, and with them the held
//! voxels, are the oracle's bit for bit.

use super::mesh_buffers::{MeshBuffers, NONE, P2, Point};
use super::out::{Out, emit};
use super::prepare::Prepared;
use crate::grid::Lattice;
use genform_core::scene::Mesh;
use glam::Vec3;

/// The longest range of centres along the rows kept in a table.
const TABLE_MAX: i64 = 1 << 16;

/// One edge of a triangle's projection: `E(q) = ±((b − a) × (q − a))` with
/// `a, b` in canonical order (as `crossing::edge` computes it).
#[derive(Clone, Copy, Debug)]
struct Edge {
    a: P2,
    d: P2,
    /// Whether `E` is the negated orientation (`a, b` swapped).
    neg: bool,
    /// `−1` when `neg`, else `1`: multiplying by it negates exactly (zeros
    /// included), without a branch.
    sign: f64,
    /// Points with `E == 0` belong to the triangle.
    owned: bool,
}

impl Edge {
    /// `E` at a row, from its first product `t = d.0 · (q.1 − a.1)`.
    #[inline]
    fn eval(&self, t: f64, qu: f64) -> f64 {
        (t - self.d.1 * (qu - self.a.0)) * self.sign
    }

    /// Whether `e` is inside (NaN passes), without short-circuits:
    /// compare-and-set rather than branches.
    #[inline]
    fn passes(&self, e: f64) -> bool {
        !((e < 0.0) | ((e == 0.0) & !self.owned))
    }
}

/// A triangle ready to scan: its edges, its vertices' row coordinates and
/// their bounds.
struct Setup {
    edges: [Edge; 3],
    /// What each edge says about the rows of a line: inside from
    /// (`lower`) or up to (`upper`) its zero, with `d.0 / d.1`; NaN where
    /// it says neither (so its zero is NaN and does not bound).
    lower: [f64; 3],
    upper: [f64; 3],
    xs: [f64; 3],
    x_lo: f64,
    x_hi: f64,
    /// Whether an edge runs along the rows (`d.1 = 0`, rare): only then
    /// can [`Setup::line`] exclude a whole line.
    flat: bool,
}

impl Setup {
    /// `None` for triangles edge-on to the rows (never crossed).
    fn new(t: [&Point; 3]) -> Option<Setup> {
        let p = [t[0].p, t[1].p, t[2].p];
        let orient = |a: P2, b: P2, q: P2| (b.0 - a.0) * (q.1 - a.1) - (b.1 - a.1) * (q.0 - a.0);
        let area = orient(p[0], p[1], p[2]);
        if area == 0.0 || area.is_nan() {
            return None;
        }
        // Edge `w` is the weight of vertex `w`: the edge from the next
        // vertex to the one after, counter-clockwise.
        let edge = |s: P2, f: P2| {
            let owned = {
                let d = (f.0 - s.0, f.1 - s.1);
                d.1 < 0.0 || (d.1 == 0.0 && d.0 > 0.0)
            };
            let (a, b, neg) = if (s.0, s.1) < (f.0, f.1) { (s, f, false) } else { (f, s, true) };
            Edge { a, d: (b.0 - a.0, b.1 - a.1), neg, sign: if neg { -1.0 } else { 1.0 }, owned }
        };
        let edges = if area > 0.0 {
            [edge(p[1], p[2]), edge(p[2], p[0]), edge(p[0], p[1])]
        } else {
            [edge(p[2], p[1]), edge(p[0], p[2]), edge(p[1], p[0])]
        };
        // E = ±(d.0·(qv − a.1) − d.1·(qu − a.0)) grows with qu when ∓d.1 > 0.
        let (mut lower, mut upper) = ([f64::NAN; 3], [f64::NAN; 3]);
        let mut flat = false;
        for (e, (lo, hi)) in edges.iter().zip(lower.iter_mut().zip(&mut upper)) {
            match e.d.1 {
                0.0 => flat = true,
                d1 if (d1 < 0.0) != e.neg => *lo = e.d.0 / d1,
                d1 => *hi = e.d.0 / d1,
            }
        }
        let xs = [t[0].x, t[1].x, t[2].x];
        let (x_lo, x_hi) = (xs[0].min(xs[1]).min(xs[2]), xs[0].max(xs[1]).max(xs[2]));
        Some(Setup { edges, lower, upper, xs, x_lo, x_hi, flat })
    }

    /// The rows' first products `d.0 · (qv − a.1)` of line `qv`, or `None`
    /// when an edge parallel to the rows excludes the whole line.
    #[inline]
    fn line(&self, qv: f64) -> Option<[f64; 3]> {
        // (Spelled out: `array::map` is not inlined here.)
        let [e0, e1, e2] = &self.edges;
        let t = [e0.d.0 * (qv - e0.a.1), e1.d.0 * (qv - e1.a.1), e2.d.0 * (qv - e2.a.1)];
        if self.flat {
            for (e, &t) in self.edges.iter().zip(&t) {
                // `d.1 = 0`: E is the same for every row of the line.
                if e.d.1 == 0.0 && !e.passes(e.eval(t, 0.0)) {
                    return None;
                }
            }
        }
        Some(t)
    }

    /// The `qu` where line `qv` is inside, in real arithmetic: `(lo, hi)`
    /// (possibly infinite), from each edge's zero `a.0 + (qv − a.1)·r`.
    #[inline]
    fn line_bounds(&self, qv: f64) -> (f64, f64) {
        let (mut lo, mut hi) = (f64::NEG_INFINITY, f64::INFINITY);
        for (e, (l, u)) in self.edges.iter().zip(self.lower.iter().zip(&self.upper)) {
            // A NaN zero (no such bound, or 0 · ∞) does not bound.
            let s = qv - e.a.1;
            lo = greater(e.a.0 + s * l, lo);
            hi = lesser(e.a.0 + s * u, hi);
        }
        (lo, hi)
    }

    /// Where row `qu` of a line with products `t` crosses the triangle
    /// (the value `crossing` gives), if it does.
    #[inline]
    fn cross(&self, t: &[f64; 3], qu: f64) -> Option<f64> {
        let [e0, e1, e2] = &self.edges;
        let w = [e0.eval(t[0], qu), e1.eval(t[1], qu), e2.eval(t[2], qu)];
        if !(e0.passes(w[0]) & e1.passes(w[1]) & e2.passes(w[2])) {
            return None;
        }
        let sum = w[0] + w[1] + w[2];
        let xs = self.xs;
        let x = if sum > 0.0 { (w[0] * xs[0] + w[1] * xs[1] + w[2] * xs[2]) / sum } else { xs[0] };
        // (A reciprocal of `sum` per line would not give the same bits.)
        // `clamp` without its check of the bounds (ordered: finite `x`s).
        let x = if x < self.x_lo { self.x_lo } else { x };
        Some(if x > self.x_hi { self.x_hi } else { x })
    }
}

/// Rows of a mesh instance: crossings per row, grouped by row, filled by
/// parity.
pub(super) fn mesh_rows(lat: &Lattice, p: &Prepared, mesh: &Mesh, verts: &[Vec3], out: &mut Out) {
    let (Some([(j0, j1), (k0, k1)]), Some((i0, i1))) = (p.row_ranges(lat), p.x_range(lat)) else { return };
    let nj = j1 - j0 + 1;
    let mut buf = out.s.take_mesh_buffers();
    let [ci, cj, ck] = &mut buf.centres;
    ci.clear();
    // A table for rows of reasonable length (an instance may stretch far
    // outside the grid along its rows).
    let table = i1 - i0 < TABLE_MAX;
    if table {
        ci.extend((i0..=i1).map(|i| f64::from(lat.centre(0, i))));
    }
    cj.clear();
    cj.extend((j0..=j1).map(|j| f64::from(lat.centre(1, j))));
    ck.clear();
    ck.extend((k0..=k1).map(|k| f64::from(lat.centre(2, k))));
    let cross = &mut buf.crossings;
    cross.clear();
    // Lattice coordinates (centres at integers) by a multiply: bounds only.
    let (inv1, inv2) = (1.0 / lat.size(1), 1.0 / lat.size(2));
    let (c1, c2) = (lat.coord(1, 0.0), lat.coord(2, 0.0));
    let points = &mut buf.points;
    points.clear();
    let (mut my, mut mz) = (0.0f64, 0.0f64);
    points.extend(verts.iter().map(|v| {
        let (y, z) = (f64::from(v.y), f64::from(v.z));
        // NaN coordinates do not count (as `max` drops them).
        (my, mz) = (my.max(y.abs()), mz.max(z.abs()));
        Point { p: (y, z), x: f64::from(v.x), u: y * inv1 + c1, v: z * inv2 + c2, rows: [0; 4] }
    }));
    let mag = my * inv1 + mz * inv2;
    // Slack for the real-arithmetic bounds, in rows: far more than their
    // rounding and the `f32` centres' (2⁻²⁴ relative), which grow with the
    // coordinates' magnitude (the instance's largest: more slack only tries
    // more rows, each decided exactly).
    let slack = 1e-3 + 1e-6 * (mag + c1.abs() + c2.abs());
    for p in points.iter_mut() {
        let (ja, jb) = row_bounds(p.u, slack, (j0, j1));
        let (ka, kb) = row_bounds(p.v, slack, (k0, k1));
        p.rows = [ja, jb, ka, kb];
    }
    for t in &mesh.triangles {
        let (Some(p0), Some(p1), Some(p2)) =
            (points.get(t[0] as usize), points.get(t[1] as usize), points.get(t[2] as usize))
        else {
            continue;
        };
        let tri = [p0, p1, p2];
        // Rows whose centres lie in the triangle's bounding box (the lattice
        // map is monotonic, so this is the box of the mapped vertices; and
        // rounding `ceil`/`floor` are monotonic, so the box's rows are the
        // least and greatest of its vertices').
        // (A NaN vertex tries every row; the triangle's NaN area skips it.)
        let [a, b, c] = [tri[0].rows, tri[1].rows, tri[2].rows];
        let (ja, jb) = (a[0].min(b[0]).min(c[0]), a[1].max(b[1]).max(c[1]));
        if ja > jb {
            continue;
        }
        let (ka, kb) = (a[2].min(b[2]).min(c[2]), a[3].max(b[3]).max(c[3]));
        if ka > kb {
            continue;
        }
        let Some(setup) = Setup::new(tri) else { continue };
        // (Half-open ranges: cheaper to step than `..=`.)
        for (k, &qv) in (ka..).zip(&ck[(ka - k0) as usize..(kb - k0 + 1) as usize]) {
            let Some(tk) = setup.line(qv) else { continue };
            let (ulo, uhi) = setup.line_bounds(qv);
            let (ra, rb) = index_span(ulo * inv1 + c1, uhi * inv1 + c1, slack, (ja, jb));
            // Offsets in the box (`ja ≤ ra`, and `rb = ra − 1` when empty).
            let (ra, rb) = ((ra - j0) as usize, (rb - j0 + 1) as usize);
            let row0 = ((k - k0) * nj) as usize;
            for (r, &qu) in (ra..).zip(&cj[ra..rb]) {
                if let Some(x) = setup.cross(&tk, qu) {
                    cross.push(((row0 + r) as u32, x));
                }
            }
        }
    }
    link_rows(&mut buf, (nj * (k1 - k0 + 1)) as usize);
    let MeshBuffers { crossings, head, next, xs, centres: [ci, ..], .. } = &mut buf;
    // The table index of `x` is about `x · inv0 + g0 − ½` (a start guess
    // only; rounded to the nearest, `+ ½` makes it the ceiling).
    let (inv0, g0) = (1.0 / lat.size(0), lat.coord(0, 0.0) - i0 as f64 + 0.5);
    let ci: &[f64] = ci;
    // `first_at_or_after(0, x)` clamped to `[i0, i1 + 1]`, from the table.
    // (Small and capturing copies, so that it is inlined.)
    let first = move |x: f64| match table {
        true => i0 + first_at_or_after(ci, x, x * inv0 + g0),
        false => first_far(lat, x, (i0, i1)),
    };
    // Rows in order (the scratch's rows are then visited in memory order),
    // a line at a time (empty rows cost a compare each).
    // (`nj ≥ 1`: `row_ranges` gives non-empty ranges.)
    for (k, line) in (k0..).zip(head.chunks_exact(nj as usize)) {
        for (j, &h) in (j0..).zip(line) {
            if h == NONE {
                continue;
            }
            // Two crossings (the rule for closed meshes): no list to build.
            let g = next[h as usize];
            if g != NONE && next[g as usize] == NONE {
                let (x0, x1) = (crossings[g as usize].1, crossings[h as usize].1);
                let (x0, x1) = if x1.total_cmp(&x0).is_lt() { (x1, x0) } else { (x0, x1) };
                let (a, b) = (first(x0), first(x1) - 1);
                if a <= b {
                    emit(lat, out, j, k, a, b);
                }
                continue;
            }
            xs.clear();
            let mut c = h;
            while c != NONE {
                xs.push(crossings[c as usize].1);
                c = next[c as usize];
            }
            // (One order for any order of arrival: `total_cmp` is total.)
            if let [a, b] = xs.as_mut_slice() {
                if b.total_cmp(a).is_lt() {
                    std::mem::swap(a, b);
                }
            } else {
                xs.sort_unstable_by(f64::total_cmp);
            }
            let n = xs.len();
            // Held iff an odd number of crossings lie beyond the centre: the
            // centres in [xs[m−1], xs[m]) have n − m of them.
            let mut m = 1 - n % 2;
            while m <= n {
                let a = if m == 0 { i0 } else { first(xs[m - 1]) };
                let b = if m == n { i1 } else { first(xs[m]) - 1 };
                if a <= b {
                    emit(lat, out, j, k, a, b);
                }
                m += 2;
            }
        }
    }
    out.s.put_mesh_buffers(buf);
}

/// The first index of the ascending `centres` at or after `x` (their
/// length if none), starting the search at about `guess`: the clamped
/// `first_at_or_after` of the lattice, exact like it (same `f32` centres).
#[inline]
fn first_at_or_after(centres: &[f64], x: f64, guess: f64) -> i64 {
    if x.is_nan() {
        return centres.len() as i64;
    }
    // Any start gives the exact answer; a good one saves the walk. The
    // guess rounded to the nearest integer by adding `1.5 · 2⁵²` (as in
    // [`ceil_floor`]; for `|guess| > 2⁵¹` or infinite the start is off but
    // clamped, and the walk still ends at the answer).
    const M: f64 = 6_755_399_441_055_744.0;
    // (Wrapping: far negative sums have bits that would overflow.)
    let n = ((guess + M).to_bits() as i64).wrapping_sub(M.to_bits() as i64);
    let mut g = n.clamp(0, centres.len() as i64) as usize;
    while g > 0 && centres[g - 1] >= x {
        g -= 1;
    }
    while g < centres.len() && centres[g] < x {
        g += 1;
    }
    g as i64
}

/// `first_at_or_after(0, x)` of the lattice clamped to `[i0, i1 + 1]`
/// (rows too long for a table; kept out of line).
#[inline(never)]
fn first_far(lat: &Lattice, x: f64, (i0, i1): (i64, i64)) -> i64 {
    lat.first_at_or_after(0, x).clamp(i0, i1 + 1)
}

/// `(least, greatest)` index `i` with `x − slack ≤ i ≤ x + slack`, the
/// first clamped to `[a, b + 1]` and the second to `[a − 1, b]` (so that
/// the least and greatest over a triangle's vertices are [`index_span`]
/// of its box; a NaN `x` gives `(a, b)`).
#[inline]
fn row_bounds(x: f64, slack: f64, (a, b): (i64, i64)) -> (i64, i64) {
    let lo = lesser(greater(x - slack, a as f64), (b + 1) as f64);
    let hi = greater(lesser(x + slack, b as f64), (a - 1) as f64);
    // Both lie within a lattice's ±2³¹ + 1 rows.
    ceil_floor(lo, hi)
}

/// The indices `i` in `within` with `lo − slack ≤ i ≤ hi + slack`
/// (NaN bounds do not bound; empty: `lo > hi`).
#[inline]
fn index_span(lo: f64, hi: f64, slack: f64, (a, b): (i64, i64)) -> (i64, i64) {
    // A NaN operand yields the bound, so neither is NaN; both fit an i64.
    let (lo, hi) = (greater(lo - slack, a as f64), lesser(hi + slack, b as f64));
    if lo > hi {
        return (a, a - 1);
    }
    ceil_floor(lo, hi)
}

/// `(⌈lo⌉, ⌊hi⌋)` for `|lo|, |hi| ≤ 2⁵¹` (not NaN), exact: adding
/// `1.5 · 2⁵²` rounds to an integer (ties to even) that the sum's bits hold
/// in their low part, and one compare fixes the rounding direction. Fewer
/// instructions than a saturating `as i64` and its fix-up.
#[inline]
fn ceil_floor(lo: f64, hi: f64) -> (i64, i64) {
    const M: f64 = 6_755_399_441_055_744.0;
    let (tl, th) = (lo + M, hi + M);
    let base = M.to_bits() as i64;
    let (nl, nh) = (tl.to_bits() as i64 - base, th.to_bits() as i64 - base);
    (nl + i64::from(tl - M < lo), nh - i64::from(th - M > hi))
}

/// `a` if it is less than `b`, else `b` (so `b` when either is NaN): one
/// `minsd`, where `f64::min` must also handle NaN either side.
#[inline]
fn lesser(a: f64, b: f64) -> f64 {
    if a < b { a } else { b }
}

/// `a` if it is greater than `b`, else `b` (so `b` when either is NaN).
#[inline]
fn greater(a: f64, b: f64) -> f64 {
    if a > b { a } else { b }
}

/// Links the crossings by row: `head[r]` is the last crossing of row `r`
/// (of `rows`), `next[c]` the one before crossing `c` in its row.
fn link_rows(buf: &mut MeshBuffers, rows: usize) {
    let MeshBuffers { crossings, head, next, .. } = buf;
    head.clear();
    head.resize(rows, NONE);
    next.clear();
    next.resize(crossings.len(), NONE);
    for ((c, &(r, _)), n) in crossings.iter().enumerate().zip(next.iter_mut()) {
        let h = &mut head[r as usize];
        *n = *h;
        *h = c as u32;
    }
}

#[cfg(test)]
mod tests {
    use super::{ceil_floor, first_at_or_after};
    use crate::grid::{Grid, Lattice};
    use glam::Vec3;

    /// The table look-up with `mesh_rows`' start guess equals the lattice's
    /// exact `first_at_or_after` clamped to the table, on centres, a
    /// rounding step either side, between centres, outside the table, far
    /// outside (where the guess is garbage), infinite and NaN.
    #[test]
    fn table_look_ups_equal_the_lattice() {
        let grid = Grid::new(Vec3::new(-3.3, 0.0, 0.0), Vec3::new(7.1, 1.0, 1.0), [37, 1, 1]).unwrap();
        let lat = Lattice::new(&grid);
        for (i0, i1) in [(0, 36), (-5, 3), (30, 50), (7, 7)] {
            let ci: Vec<f64> = (i0..=i1).map(|i| f64::from(lat.centre(0, i))).collect();
            let (inv0, g0) = (1.0 / lat.size(0), lat.coord(0, 0.0) - i0 as f64 + 0.5);
            let mut xs = vec![f64::INFINITY, f64::NEG_INFINITY, f64::NAN, 1e300, -1e300];
            // Guesses near `−1.5 · 2⁵²` (negative sums with small bits).
            xs.extend([0.5, 1.0, 1.5, 1.99].map(|f| -f * 6_755_399_441_055_744.0 * lat.size(0)));
            for i in i0 - 3..=i1 + 3 {
                let c = f64::from(lat.centre(0, i));
                xs.extend([c, c.next_up(), c.next_down(), c + 0.3 * lat.size(0), c - 0.5 * lat.size(0)]);
            }
            for x in xs {
                let want = lat.first_at_or_after(0, x).clamp(i0, i1 + 1);
                assert_eq!(i0 + first_at_or_after(&ci, x, x * inv0 + g0), want, "{x} in {i0}..={i1}");
            }
        }
    }

    /// The rounding trick equals `ceil`/`floor` on integers, ties, both
    /// zeros and values a rounding step off them, up to the lattice limit
    /// and beyond (2⁵¹).
    #[test]
    fn ceil_floor_equals_libm() {
        let mut xs = vec![0.0, -0.0, 2f64.powi(51), -(2f64.powi(51)), 2f64.powi(31) + 1.0, -(2f64.powi(31)) - 1.0];
        for i in -300..300 {
            for f in [0.0, 0.25, 0.5, 0.75, 1e-9, -1e-9, 1.5] {
                let x = f64::from(i) + f;
                xs.extend([x, x.next_up(), x.next_down(), x * 1e5, x * 1.7e9]);
            }
        }
        for x in xs {
            let (c, f) = ceil_floor(x, x);
            assert_eq!((c, f), (x.ceil() as i64, x.floor() as i64), "{x}");
        }
    }
}
