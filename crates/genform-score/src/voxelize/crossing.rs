//! Where a lattice row line crosses a triangle, with a tie rule that makes
//! lines through shared edges and vertices count once.
//!
//! Coordinates are in "ray order": component 0 runs along the line, the
//! line sits at `(u, v)` = components 1 and 2. The triangle is projected on
//! the `(u, v)` plane and made counter-clockwise there. A line hits it when
//! every edge function is positive, or zero on an edge whose inside lies
//! towards `+u` (or, for edges with constant `u`, towards `+v`). That is
//! the symbolic perturbation `q + (ε, ε²)`: a line through an edge or vertex
//! shared by triangles covering its neighbourhood once is counted once, and
//! a cube spanning `[a, b]` covers exactly the line positions in `[a, b)`.
//!
//! Edge functions are evaluated in `f64` from the `f32` inputs, always with
//! the edge's endpoints in one canonical order, so the two triangles sharing
//! an edge see exactly opposite values even when rounding occurs; on
//! vertices they are exactly zero. Signs can only be wrong for lines within
//! about 1e-16 (relative) of an edge that do not pass through it exactly.

use glam::Vec3;

type P2 = (f64, f64);

/// `(b − a) × (q − a)`: positive when `q` is left of `a → b`.
#[inline]
fn orient(a: P2, b: P2, q: P2) -> f64 {
    (b.0 - a.0) * (q.1 - a.1) - (b.1 - a.1) * (q.0 - a.0)
}

/// [`orient`] with the endpoints in canonical (lexicographic) order, so
/// `edge(a, b, q) == -edge(b, a, q)` bit for bit.
#[inline]
fn edge(a: P2, b: P2, q: P2) -> f64 {
    if (a.0, a.1) < (b.0, b.1) { orient(a, b, q) } else { -orient(b, a, q) }
}

/// Whether points exactly on a counter-clockwise edge with direction `d`
/// belong to the triangle: its inside normal `(−d.v, d.u)` points to `+u`,
/// or along `+v` when it has no `u` part.
#[inline]
fn owns_edge(d: P2) -> bool {
    d.1 < 0.0 || (d.1 == 0.0 && d.0 > 0.0)
}

/// Where the line `(·, qu, qv)` crosses triangle `t`: the coordinate along
/// the line, and `+1` if the triangle faces along the line (its normal has a
/// positive component 0), `−1` if against. `None` when the line misses it
/// or the triangle is edge-on. Vertices must be finite.
#[inline]
pub(crate) fn crossing(t: &[Vec3; 3], qu: f32, qv: f32) -> Option<(f64, i8)> {
    let p = t.map(|v| (f64::from(v.y), f64::from(v.z)));
    let q = (f64::from(qu), f64::from(qv));
    let area = orient(p[0], p[1], p[2]);
    if area == 0.0 || area.is_nan() {
        return None;
    }
    // Counter-clockwise order of the projection.
    let o = if area > 0.0 { [0, 1, 2] } else { [0, 2, 1] };
    let mut w = [0.0f64; 3];
    for e in 0..3 {
        let (s, f) = (p[o[e]], p[o[(e + 1) % 3]]);
        let ev = edge(s, f, q);
        if ev < 0.0 || (ev == 0.0 && !owns_edge((f.0 - s.0, f.1 - s.1))) {
            return None;
        }
        // The edge opposite vertex o[e + 2] weighs that vertex.
        w[o[(e + 2) % 3]] = ev;
    }
    let sum = w[0] + w[1] + w[2];
    let xs = t.map(|v| f64::from(v.x));
    let x = if sum > 0.0 { (w[0] * xs[0] + w[1] * xs[1] + w[2] * xs[2]) / sum } else { xs[0] };
    let x = x.clamp(xs[0].min(xs[1]).min(xs[2]), xs[0].max(xs[1]).max(xs[2]));
    Some((x, if area > 0.0 { 1 } else { -1 }))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn v(x: f32, y: f32, z: f32) -> Vec3 {
        Vec3::new(x, y, z)
    }

    #[test]
    fn interpolates_the_crossing() {
        // The plane x = 1 + y, triangle facing −x... and +x when reversed.
        let t = [v(1.0, 0.0, 0.0), v(3.0, 2.0, 0.0), v(1.0, 0.0, 2.0)];
        let (x, s) = crossing(&t, 0.5, 0.5).unwrap();
        assert!((x - 1.5).abs() < 1e-12);
        let r = [t[0], t[2], t[1]];
        assert_eq!(crossing(&r, 0.5, 0.5).unwrap().1, -s);
        assert!(crossing(&t, 1.5, 1.0).is_none());
        // Edge-on triangles are never crossed.
        assert!(crossing(&[v(0., 0., 0.), v(1., 0., 0.), v(0., 0., 1.)], 0.0, 0.5).is_none());
    }

    /// A unit square `[0, 1]²` in (u, v) split into two triangles either way
    /// is hit exactly on `[0, 1)²`, once.
    #[test]
    fn square_covers_half_open_once() {
        let c = [v(0., 0., 0.), v(0., 1., 0.), v(0., 1., 1.), v(0., 0., 1.)];
        for split in [[[0, 1, 2], [0, 2, 3]], [[0, 1, 3], [1, 2, 3]]] {
            for flip in [false, true] {
                for qu in [-0.5f32, 0.0, 0.25, 0.5, 1.0, 1.5] {
                    for qv in [-0.5f32, 0.0, 0.5, 0.75, 1.0] {
                        let hits = split
                            .iter()
                            .filter(|t| {
                                let mut tri = t.map(|i| c[i]);
                                if flip {
                                    tri.swap(1, 2);
                                }
                                crossing(&tri, qu, qv).is_some()
                            })
                            .count();
                        let want = usize::from((0.0..1.0).contains(&qu) && (0.0..1.0).contains(&qv));
                        assert_eq!(hits, want, "split {split:?} flip {flip} at ({qu}, {qv})");
                    }
                }
            }
        }
    }

    /// A fan around a vertex is hit once at the vertex.
    #[test]
    fn fan_vertex_counts_once() {
        let centre = v(0., 0.3, 0.7);
        let n = 7;
        let ring: Vec<Vec3> = (0..n)
            .map(|i| {
                let a = std::f32::consts::TAU * i as f32 / n as f32;
                v(0.0, 0.3 + a.cos(), 0.7 + a.sin())
            })
            .collect();
        let hits = (0..n).filter(|&i| crossing(&[centre, ring[i], ring[(i + 1) % n]], 0.3, 0.7).is_some()).count();
        assert_eq!(hits, 1);
    }
}
