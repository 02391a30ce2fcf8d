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

use super::prepare::Prepared;
use super::{Out, emit};
use crate::grid::Lattice;
use genform_core::scene::Mesh;
use glam::Vec3;

/// Working memory of [`mesh_rows`], kept in the scratch.
#[derive(Clone, Debug, Default)]
pub(crate) struct MeshBuffers {
    /// `(row, x)` per crossing, in triangle order.
    crossings: Vec<(u32, f64)>,
    /// Crossings per row, then where each row's crossings start in `xs`.
    starts: Vec<u32>,
    /// Crossing coordinates grouped by row.
    xs: Vec<f64>,
    /// Voxel centres along the rows and along lattice axis 1 over the
    /// instance's bounding box (`f32` centres, widened).
    centres: [Vec<f64>; 2],
    /// Per vertex: its projection `(y, z)` and row coordinate `x` widened to
    /// `f64`, and its lattice coordinates along axes 1 and 2 (bounds only).
    points: Vec<Point>,
}

/// A vertex converted once per instance rather than once per triangle.
#[derive(Clone, Copy, Debug, Default)]
struct Point {
    p: P2,
    x: f64,
    u: f64,
    v: f64,
}

type P2 = (f64, f64);

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

    #[inline]
    fn passes(&self, e: f64) -> bool {
        !(e < 0.0 || (e == 0.0 && !self.owned))
    }
}

/// What an edge says about the rows of a line: inside from (`Lower`) or
/// up to (`Upper`) its zero, with `d.0 / d.1`; `None` for edges parallel
/// to the rows.
#[derive(Clone, Copy, Debug)]
enum Bound {
    Lower(f64),
    Upper(f64),
    None,
}

/// A triangle ready to scan: its edges, its vertices' row coordinates and
/// their bounds.
struct Setup {
    edges: [Edge; 3],
    bounds: [Bound; 3],
    xs: [f64; 3],
    x_lo: f64,
    x_hi: f64,
}

impl Setup {
    /// `None` for triangles edge-on to the rows (never crossed).
    fn new(t: [&Point; 3]) -> Option<Setup> {
        let p = t.map(|v| v.p);
        let orient = |a: P2, b: P2, q: P2| (b.0 - a.0) * (q.1 - a.1) - (b.1 - a.1) * (q.0 - a.0);
        let area = orient(p[0], p[1], p[2]);
        if area == 0.0 || area.is_nan() {
            return None;
        }
        let o = if area > 0.0 { [0, 1, 2] } else { [0, 2, 1] };
        // Edge `e` (counter-clockwise from `o[e]`) is the weight of vertex
        // `o[e + 2]`; stored by that vertex: edge `w` is the weight of `w`.
        let at = if area > 0.0 { [1, 2, 0] } else { [1, 0, 2] };
        let edges = std::array::from_fn(|w| {
            let e = at[w];
            debug_assert_eq!(o[(e + 2) % 3], w);
            let (s, f) = (p[o[e]], p[o[(e + 1) % 3]]);
            let owned = {
                let d = (f.0 - s.0, f.1 - s.1);
                d.1 < 0.0 || (d.1 == 0.0 && d.0 > 0.0)
            };
            let (a, b, neg) = if (s.0, s.1) < (f.0, f.1) { (s, f, false) } else { (f, s, true) };
            Edge { a, d: (b.0 - a.0, b.1 - a.1), neg, sign: if neg { -1.0 } else { 1.0 }, owned }
        });
        // E = ±(d.0·(qv − a.1) − d.1·(qu − a.0)) grows with qu when ∓d.1 > 0.
        let bounds = edges.map(|e: Edge| match e.d.1 {
            0.0 => Bound::None,
            d1 if (d1 < 0.0) != e.neg => Bound::Lower(e.d.0 / d1),
            d1 => Bound::Upper(e.d.0 / d1),
        });
        let xs = t.map(|v| v.x);
        Some(Setup { edges, bounds, xs, x_lo: xs[0].min(xs[1]).min(xs[2]), x_hi: xs[0].max(xs[1]).max(xs[2]) })
    }

    /// The rows' first products `d.0 · (qv − a.1)` of line `qv`, or `None`
    /// when an edge parallel to the rows excludes the whole line.
    #[inline]
    fn line(&self, qv: f64) -> Option<[f64; 3]> {
        let t = self.edges.map(|e| e.d.0 * (qv - e.a.1));
        for (e, &t) in self.edges.iter().zip(&t) {
            // `d.1 = 0`: E is the same for every row of the line.
            if e.d.1 == 0.0 && !e.passes(e.eval(t, 0.0)) {
                return None;
            }
        }
        Some(t)
    }

    /// The `qu` where line `qv` is inside, in real arithmetic: `(lo, hi)`
    /// (possibly infinite), from each edge's zero `a.0 + (qv − a.1)·r`.
    #[inline]
    fn line_bounds(&self, qv: f64) -> (f64, f64) {
        let (mut lo, mut hi) = (f64::NEG_INFINITY, f64::INFINITY);
        for (e, b) in self.edges.iter().zip(&self.bounds) {
            match b {
                // A NaN zero (0 · ∞) does not bound.
                Bound::Lower(r) => lo = greater(e.a.0 + (qv - e.a.1) * r, lo),
                Bound::Upper(r) => hi = lesser(e.a.0 + (qv - e.a.1) * r, hi),
                Bound::None => {}
            }
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
    let [ci, cj] = &mut buf.centres;
    ci.clear();
    // A table for rows of reasonable length (an instance may stretch far
    // outside the grid along its rows).
    let table = i1 - i0 < TABLE_MAX;
    if table {
        ci.extend((i0..=i1).map(|i| f64::from(lat.centre(0, i))));
    }
    cj.clear();
    cj.extend((j0..=j1).map(|j| f64::from(lat.centre(1, j))));
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
        Point { p: (y, z), x: f64::from(v.x), u: y * inv1 + c1, v: z * inv2 + c2 }
    }));
    let mag = my * inv1 + mz * inv2;
    // Slack for the real-arithmetic bounds, in rows: far more than their
    // rounding and the `f32` centres' (2⁻²⁴ relative), which grow with the
    // coordinates' magnitude (the instance's largest: more slack only tries
    // more rows, each decided exactly).
    let slack = 1e-3 + 1e-6 * (mag + c1.abs() + c2.abs());
    let n = points.len();
    for t in &mesh.triangles {
        if !t.iter().all(|&i| (i as usize) < n) {
            continue;
        }
        let tri = t.map(|i| &points[i as usize]);
        // Rows whose centres lie in the triangle's bounding box (the lattice
        // map is monotonic, so this is the box of the mapped vertices).
        // (A NaN bound tries every row; the triangle's NaN area then skips it.)
        let (ulo, uhi) = (lesser(lesser(tri[0].u, tri[1].u), tri[2].u), greater(greater(tri[0].u, tri[1].u), tri[2].u));
        let (ja, jb) = index_span(ulo, uhi, slack, (j0, j1));
        if ja > jb {
            continue;
        }
        let (vlo, vhi) = (lesser(lesser(tri[0].v, tri[1].v), tri[2].v), greater(greater(tri[0].v, tri[1].v), tri[2].v));
        let (ka, kb) = index_span(vlo, vhi, slack, (k0, k1));
        if ka > kb {
            continue;
        }
        let Some(setup) = Setup::new(tri) else { continue };
        for k in ka..=kb {
            let qv = f64::from(lat.centre(2, k));
            let Some(tk) = setup.line(qv) else { continue };
            let (ulo, uhi) = setup.line_bounds(qv);
            let (ra, rb) = index_span(ulo * inv1 + c1, uhi * inv1 + c1, slack, (ja, jb));
            let row0 = (k - k0) * nj;
            for (r, &qu) in (ra - j0..=rb - j0).zip(&cj[(ra - j0) as usize..]) {
                if let Some(x) = setup.cross(&tk, qu) {
                    cross.push(((row0 + r) as u32, x));
                }
            }
        }
    }
    group_by_row(&mut buf, (nj * (k1 - k0 + 1)) as usize);
    let MeshBuffers { starts, xs, centres: [ci, _], .. } = &buf;
    let (inv0, c0) = (1.0 / lat.size(0), lat.coord(0, 0.0));
    // `first_at_or_after(0, x)` clamped to `[i0, i1 + 1]`, from the table.
    let first = |x: f64| match table {
        true => i0 + first_at_or_after(ci, x, x * inv0 + c0 - i0 as f64),
        false => lat.first_at_or_after(0, x).clamp(i0, i1 + 1),
    };
    // Rows in order, with their (j, k) counted along (no division).
    let (mut j, mut k) = (j0 - 1, k0);
    for w in starts.windows(2) {
        j += 1;
        if j > j1 {
            (j, k) = (j0, k + 1);
        }
        let xs = &xs[w[0] as usize..w[1] as usize];
        if xs.is_empty() {
            continue;
        }
        let n = xs.len();
        // Held iff an odd number of crossings lie beyond the centre: the
        // centres in [xs[m−1], xs[m]) have n − m of them.
        for m in (0..=n).filter(|m| (n - m) % 2 == 1) {
            let a = if m == 0 { i0 } else { first(xs[m - 1]) };
            let b = if m == n { i1 } else { first(xs[m]) - 1 };
            if a <= b {
                emit(lat, out, j, k, a, b);
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
    // Any start gives the exact answer; a good one saves the walk.
    // (`as` saturates, NaN to 0; to `i32`, the cheapest conversion: the
    // table has at most `TABLE_MAX` entries.)
    let mut g = (guess as i32).clamp(0, centres.len() as i32) as usize;
    while g > 0 && centres[g - 1] >= x {
        g -= 1;
    }
    while g < centres.len() && centres[g] < x {
        g += 1;
    }
    g as i64
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
    let (l, h) = (lo as i64, hi as i64);
    // Truncation is towards zero: fix up to ceil / floor.
    (if (l as f64) < lo { l + 1 } else { l }, if (h as f64) > hi { h - 1 } else { h })
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

/// Groups the crossings by row into `xs`, each row's sorted, with row `r`
/// at `xs[starts[r]..starts[r + 1]]` (a counting sort: rows are few and
/// mostly hold two crossings).
fn group_by_row(buf: &mut MeshBuffers, rows: usize) {
    let MeshBuffers { crossings, starts, xs, .. } = buf;
    starts.clear();
    starts.resize(rows + 1, 0);
    for &(r, _) in crossings.iter() {
        starts[r as usize + 1] += 1;
    }
    for r in 0..rows {
        starts[r + 1] += starts[r];
    }
    xs.clear();
    xs.resize(crossings.len(), 0.0);
    // Scatter, using `starts[r]` as row r's cursor, then shift back.
    for &(r, x) in crossings.iter() {
        let c = &mut starts[r as usize];
        xs[*c as usize] = x;
        *c += 1;
    }
    for r in (1..=rows).rev() {
        starts[r] = starts[r - 1];
    }
    starts[0] = 0;
    for w in starts.windows(2) {
        let row = &mut xs[w[0] as usize..w[1] as usize];
        if row.len() == 2 {
            if row[1].total_cmp(&row[0]).is_lt() {
                row.swap(0, 1);
            }
        } else if row.len() > 2 {
            row.sort_unstable_by(f64::total_cmp);
        }
    }
}
