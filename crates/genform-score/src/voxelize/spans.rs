//! Spans of solid primitives: per-row interval guesses settled by the
//! predicate, and separable boxes that share one span across their rows.

use super::out::{Out, emit};
use super::prepare::{Prepared, Solid};
use super::shape::{self, Shape};
use crate::grid::Lattice;
use glam::{DVec3, Vec3};

/// The exact held index range of a row inside `[i0, i1]`, starting from a
/// guess: settle each end with the predicate, walking inwards while the
/// guess holds outside centres and outwards while the neighbour is held.
#[inline]
fn settle(guess: (f64, f64), (i0, i1): (i64, i64), inside: impl Fn(i64) -> bool) -> Option<(i64, i64)> {
    // The guess is a superset up to its own f64 rounding; a hair of slack.
    let (mut lo, mut hi) = (ceil_within(guess.0 - 1e-6, i0, i1), floor_within(guess.1 + 1e-6, i0, i1));
    while lo <= hi && !inside(lo) {
        lo += 1;
    }
    if lo > hi {
        return None;
    }
    while !inside(hi) {
        hi -= 1;
    }
    while lo > i0 && inside(lo - 1) {
        lo -= 1;
    }
    while hi < i1 && inside(hi + 1) {
        hi += 1;
    }
    Some((lo, hi))
}

/// `⌈x⌉` clamped to `[lo, hi + 1]` (NaN gives `hi + 1`), without a libm call.
#[inline]
fn ceil_within(x: f64, lo: i64, hi: i64) -> i64 {
    if x.is_nan() || x > hi as f64 {
        return hi + 1;
    }
    if x <= lo as f64 {
        return lo;
    }
    let t = x as i64;
    if (t as f64) < x { t + 1 } else { t }
}

/// `⌊x⌋` clamped to `[lo − 1, hi]` (NaN gives `lo − 1`).
#[inline]
fn floor_within(x: f64, lo: i64, hi: i64) -> i64 {
    if x.is_nan() || x < lo as f64 {
        return lo - 1;
    }
    if x >= hi as f64 {
        return hi;
    }
    let t = x as i64;
    if (t as f64) > x { t - 1 } else { t }
}

/// The unit-frame line of lattice row `(py, pz)`, as `a + b·i` for index `i`.
#[inline]
fn row_line(lat: &Lattice, solid: &Solid, py: f32, pz: f32) -> (DVec3, DVec3) {
    let base = solid.m64[1] * f64::from(py) + solid.m64[2] * f64::from(pz) + solid.t64;
    let x0 = f64::from(lat.centre(0, 0));
    (base + solid.m64[0] * x0, solid.m64[0] * lat.size(0))
}

pub(super) fn solid_rows(lat: &Lattice, p: &Prepared, solid: &Solid, out: &mut Out) {
    let (Some([(j0, j1), (k0, k1)]), Some(irange)) = (p.row_ranges(lat), p.x_range(lat)) else { return };
    for k in k0..=k1 {
        let pz = lat.centre(2, k);
        for j in j0..=j1 {
            if let Some((lo, hi)) = row_span(lat, solid, irange, lat.centre(1, j), pz) {
                emit(lat, out, j, k, lo, hi);
            }
        }
    }
}

/// The held index range of row `(py, pz)` within `irange`, if any.
#[inline]
fn row_span(lat: &Lattice, solid: &Solid, irange: (i64, i64), py: f32, pz: f32) -> Option<(i64, i64)> {
    let (a, b) = row_line(lat, solid, py, pz);
    let guess = match solid.shape {
        Shape::Box => box_guess(a, solid.inv_step, 0.5 + solid.delta),
        shape => shape.guess(a, b, solid.delta),
    }?;
    let base = solid.row_base(py, pz);
    settle(guess, irange, |i: i64| solid.shape.contains(solid.unit(lat.centre(0, i), base)))
}

/// A box whose unit axis `c` is driven by cross-row lattice axis `l` alone
/// (see [`Solid::split`]): the held range along `l` is found once, then one
/// span per line of rows across it, computed at the range's first index
/// (where the `c` test holds, so the full predicate is the other two) and
/// held for the whole range.
pub(super) fn split_box(lat: &Lattice, p: &Prepared, solid: &Solid, (l, c): (usize, usize), out: &mut Out) {
    let (Some([jr, kr]), Some(ir)) = (p.row_ranges(lat), p.x_range(lat)) else { return };
    let at = Vec3::new(lat.centre(0, ir.0), lat.centre(1, jr.0), lat.centre(2, kr.0));
    if l == 1 {
        let Some((ja, jb)) = box_axis_range(lat, solid, c, 1, jr, at) else { return };
        let py = lat.centre(1, ja);
        for k in kr.0..=kr.1 {
            if let Some(span) = row_span(lat, solid, ir, py, lat.centre(2, k)) {
                lattice_box(lat, span, (ja, jb), (k, k), out);
            }
        }
    } else {
        let Some((ka, kb)) = box_axis_range(lat, solid, c, 2, kr, at) else { return };
        let pz = lat.centre(2, ka);
        for j in jr.0..=jr.1 {
            if let Some(span) = row_span(lat, solid, ir, lat.centre(1, j), pz) {
                lattice_box(lat, span, (j, j), (ka, kb), out);
            }
        }
    }
}

/// [`Shape::guess`] for boxes, with the reciprocal slopes `inv` of the row
/// line precomputed (infinite where the line does not move).
#[inline]
fn box_guess(a: DVec3, inv: DVec3, h: f64) -> Option<(f64, f64)> {
    let (mut lo, mut hi) = (f64::NEG_INFINITY, f64::INFINITY);
    for c in 0..3 {
        let (ac, ic) = (a[c], inv[c]);
        if ic.is_infinite() {
            if ac.is_nan() || ac.abs() > h {
                return None;
            }
            continue;
        }
        let (t1, t2) = ((-h - ac) * ic, (h - ac) * ic);
        let (t1, t2) = if ic > 0.0 { (t1, t2) } else { (t2, t1) };
        if t1 > lo {
            lo = t1;
        }
        if t2 < hi {
            hi = t2;
        }
    }
    (lo <= hi).then_some((lo, hi))
}

/// The held index range along lattice axis `l` of a box whose unit axis `c`
/// only that lattice axis drives.
fn box_axis_range(lat: &Lattice, solid: &Solid, c: usize, l: usize, range: (i64, i64), at: Vec3) -> Option<(i64, i64)> {
    // u_c depends on lattice coordinate l alone; evaluate the full map at
    // points that differ only along l (the other terms are exact zeros).
    let a = solid.m64[l][c] * f64::from(lat.centre(l, 0)) + solid.t64[c];
    let b = solid.m64[l][c] * lat.size(l);
    let h = 0.5 + solid.delta;
    let guess = shape::slab(a, b, -h, h)?;
    settle(guess, range, |i| {
        // Built in registers: a store into `at[l]` read back as a vector
        // missed store forwarding, a stall per probe.
        let x = lat.centre(l, i);
        let q = match l {
            0 => Vec3::new(x, at.y, at.z),
            1 => Vec3::new(at.x, x, at.z),
            _ => Vec3::new(at.x, at.y, x),
        };
        let u = solid.unit_point(q)[c];
        (-0.5..0.5).contains(&u)
    })
}

pub(super) fn separable_box(lat: &Lattice, p: &Prepared, solid: &Solid, perm: [usize; 3], out: &mut Out) {
    let (Some([jr, kr]), Some(ir)) = (p.row_ranges(lat), p.x_range(lat)) else { return };
    let at = Vec3::new(lat.centre(0, ir.0), lat.centre(1, jr.0), lat.centre(2, kr.0));
    let (Some((i0, i1)), Some((j0, j1)), Some((k0, k1))) = (
        box_axis_range(lat, solid, perm[0], 0, ir, at),
        box_axis_range(lat, solid, perm[1], 1, jr, at),
        box_axis_range(lat, solid, perm[2], 2, kr, at),
    ) else {
        return;
    };
    lattice_box(lat, (i0, i1), (j0, j1), (k0, k1), out);
}

/// Holds every lattice voxel of the index box `[i0, i1] × [j0, j1] × [k0, k1]`
/// (lattice order; empty ranges hold nothing): the spans of its rows in the
/// grid, and the rest counted as outside in bulk.
pub(super) fn lattice_box(
    lat: &Lattice,
    (i0, i1): (i64, i64),
    (j0, j1): (i64, i64),
    (k0, k1): (i64, i64),
    out: &mut Out,
) {
    if i0 > i1 || j0 > j1 || k0 > k1 {
        return;
    }
    // In u128: block structures may span ±2³¹ lattice voxels along each axis.
    let span = |a: i64, b: i64| (b - a + 1) as u128;
    let sat = |n: u128| u64::try_from(n).unwrap_or(u64::MAX);
    let (gj0, gj1) = (j0.max(0), j1.min(lat.dims[1] - 1));
    let (gk0, gk1) = (k0.max(0), k1.min(lat.dims[2] - 1));
    let len = span(i0, i1);
    let rows = span(j0, j1) * span(k0, k1);
    let grid_rows = if gj0 <= gj1 && gk0 <= gk1 { span(gj0, gj1) * span(gk0, gk1) } else { 0 };
    let (a, b) = (i0.max(0), i1.min(lat.dims[0] - 1));
    let held = if grid_rows == 0 || a > b { 0 } else { span(a, b) };
    // Rows outside the grid, and the parts of grid rows outside it, only add
    // to `outside`.
    out.tally.outside = out.tally.outside.saturating_add(sat((rows - grid_rows) * len + grid_rows * (len - held)));
    if held == 0 {
        return;
    }
    out.tally.in_grid += sat(grid_rows * held);
    for k in gk0..=gk1 {
        let first = (k * lat.dims[1] + gj0) as usize;
        out.s.write_rows(first, (gj1 - gj0 + 1) as usize, a as usize, b as usize, out.target);
    }
}
