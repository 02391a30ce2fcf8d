//! Catmull–Clark subdivision of polygon [`Surface`]s with boundaries,
//! keeping edge types.

use crate::surface::{Surface, SurfaceEdge};
use glam::DVec3;
use std::collections::HashMap;

/// `steps` rounds of Catmull–Clark subdivision of `surface` (0 gives a
/// copy).
///
/// Each round replaces a face of `k` corners by `k` quads, so the result is
/// all quads after one round; every round gives `V' = V + E + F` vertices,
/// `E' = 2E + Σ face sizes` edges and `F' = Σ face sizes` faces, and keeps
/// `V − E + F`. Vertex order: the old vertices (moved), then one point per
/// edge in edge order, then one per face in face order. Faces stay
/// counter-clockwise seen from the front.
///
/// The rules are the standard ones with boundaries:
/// - face point: the average of the face's corners;
/// - edge point of an edge between two faces: the average of its ends and
///   the two face points; of any other edge (a boundary edge, with one
///   face or bounding only the outer face, or an edge of three or more
///   faces): its midpoint;
/// - a vertex on exactly two boundary edges moves to `(a + 6P + b) / 8`,
///   `a` and `b` being their other ends; a vertex on one or more than two
///   boundary edges (the end of a dangling edge, a pinch) stays put, as
///   does a vertex on no edge;
/// - any other vertex of valence `n` moves to `(F + 2R + (n − 3)P) / n`,
///   `F` averaging the face points of its faces and `R` the midpoints of
///   its edges.
///
/// Both halves of an edge keep its type; the edges added inside faces
/// (edge point to face point) are [`SurfaceEdge::UNTYPED`], as is a face
/// side missing from [`Surface::edges`] (it is added). The first of
/// several edges joining the same two vertices is kept, and malformed
/// pieces are dropped: edges and faces naming a missing vertex, edges from
/// a vertex to itself, faces of fewer than three corners or with a corner
/// repeated next to itself. Coordinates are computed in `f64`. The tag and
/// [`Surface::outside_soft`] are kept.
///
/// The face count grows about fourfold per round: callers bound `steps`.
pub fn catmull_clark(surface: &Surface, steps: u32) -> Surface {
    let mut s = surface.clone();
    for _ in 0..steps {
        s = subdivide_once(&s);
    }
    s
}

impl Surface {
    /// [`catmull_clark`]: `steps` rounds of Catmull–Clark subdivision.
    pub fn catmull_clark(&self, steps: u32) -> Surface {
        catmull_clark(self, steps)
    }
}

/// Per edge: its faces and the sum of their face points.
#[derive(Clone, Copy, Default)]
struct EdgeFaces {
    count: u32,
    sum: DVec3,
}

/// Per vertex: what the vertex rules average.
#[derive(Clone, Copy, Default)]
struct VertexSums {
    faces: u32,
    face_sum: DVec3,
    edges: u32,
    midpoint_sum: DVec3,
    boundary: u32,
    boundary_sum: DVec3,
}

fn subdivide_once(s: &Surface) -> Surface {
    let nv = s.positions.len();
    let p: Vec<DVec3> = s.positions.iter().map(|v| v.as_dvec3()).collect();
    let in_range = |i: u32| (i as usize) < nv;
    let key = |a: u32, b: u32| (a.min(b), a.max(b));

    let mut edges: Vec<SurfaceEdge> = Vec::with_capacity(s.edges.len());
    let mut edge_of: HashMap<(u32, u32), u32> = HashMap::with_capacity(s.edges.len());
    for e in &s.edges {
        if in_range(e.a) && in_range(e.b) && e.a != e.b {
            edge_of.entry(key(e.a, e.b)).or_insert_with(|| {
                edges.push(*e);
                (edges.len() - 1) as u32
            });
        }
    }

    // Well-formed faces, their face points and, per side (corner i to
    // i + 1), its edge.
    let mut faces: Vec<&[u32]> = Vec::with_capacity(s.face_count());
    let mut face_points: Vec<DVec3> = Vec::with_capacity(s.face_count());
    let mut side_edges: Vec<u32> = Vec::with_capacity(s.face_vertices.len());
    for f in s.faces() {
        let k = f.len();
        if k < 3 || !f.iter().all(|&v| in_range(v)) || (0..k).any(|i| f[i] == f[(i + 1) % k]) {
            continue;
        }
        faces.push(f);
        face_points.push(f.iter().map(|&v| p[v as usize]).sum::<DVec3>() / k as f64);
        for i in 0..k {
            let (a, b) = (f[i], f[(i + 1) % k]);
            let e = *edge_of.entry(key(a, b)).or_insert_with(|| {
                edges.push(SurfaceEdge { a, b, kind: SurfaceEdge::UNTYPED });
                (edges.len() - 1) as u32
            });
            side_edges.push(e);
        }
    }
    let (ne, nf) = (edges.len(), faces.len());

    let mut edge_faces = vec![EdgeFaces::default(); ne];
    let mut sums = vec![VertexSums::default(); nv];
    let mut side = 0;
    for (f, &fp) in faces.iter().zip(&face_points) {
        for &v in *f {
            let e = &mut edge_faces[side_edges[side] as usize];
            e.count += 1;
            e.sum += fp;
            side += 1;
            let vs = &mut sums[v as usize];
            vs.faces += 1;
            vs.face_sum += fp;
        }
    }

    let mut positions = Vec::with_capacity(nv + ne + nf);
    let mut edge_points = Vec::with_capacity(ne);
    for (e, ef) in edges.iter().zip(&edge_faces) {
        let (pa, pb) = (p[e.a as usize], p[e.b as usize]);
        let mid = 0.5 * (pa + pb);
        let boundary = ef.count != 2;
        for (v, other) in [(e.a, pb), (e.b, pa)] {
            let vs = &mut sums[v as usize];
            vs.edges += 1;
            vs.midpoint_sum += mid;
            if boundary {
                vs.boundary += 1;
                vs.boundary_sum += other;
            }
        }
        edge_points.push(if boundary { mid } else { 0.25 * (pa + pb + ef.sum) });
    }
    for (&pv, vs) in p.iter().zip(&sums) {
        let moved = if vs.boundary == 2 {
            (vs.boundary_sum + 6.0 * pv) / 8.0
        } else if vs.boundary > 0 || vs.edges == 0 || vs.faces == 0 {
            pv
        } else {
            let n = f64::from(vs.edges);
            let f = vs.face_sum / f64::from(vs.faces);
            let r = vs.midpoint_sum / n;
            (f + 2.0 * r + (n - 3.0) * pv) / n
        };
        positions.push(moved.as_vec3());
    }
    positions.extend(edge_points.iter().map(|q| q.as_vec3()));
    positions.extend(face_points.iter().map(|q| q.as_vec3()));

    let (ev, fv) = (nv as u32, (nv + ne) as u32);
    let corners = side_edges.len();
    let mut out = Surface {
        positions,
        face_offsets: Vec::with_capacity(corners + 1),
        face_vertices: Vec::with_capacity(4 * corners),
        edges: Vec::with_capacity(2 * ne + corners),
        tag: s.tag,
        outside_soft: s.outside_soft,
    };
    out.face_offsets.push(0);
    for e in &edges {
        let m = ev + out.edges.len() as u32 / 2;
        out.edges.push(SurfaceEdge { a: e.a, b: m, kind: e.kind });
        out.edges.push(SurfaceEdge { a: m, b: e.b, kind: e.kind });
    }
    let mut first_side = 0;
    for (fi, f) in faces.iter().enumerate() {
        let k = f.len();
        let center = fv + fi as u32;
        let sides = &side_edges[first_side..first_side + k];
        for i in 0..k {
            // Corner i, the point of the side leaving it, the centre, the
            // point of the side entering it: the face's own turning sense.
            let (leaving, entering) = (ev + sides[i], ev + sides[(i + k - 1) % k]);
            out.push_face(&[f[i], leaving, center, entering]);
            out.edges.push(SurfaceEdge { a: leaving, b: center, kind: SurfaceEdge::UNTYPED });
        }
        first_side += k;
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3;

    /// An `n × m` grid of unit quads in the xy plane, heights from `z`;
    /// boundary edges of type 1, interior ones of type 2.
    fn grid(n: u32, m: u32, z: impl Fn(u32, u32) -> f32) -> Surface {
        let mut s = Surface::new(0);
        let id = |i: u32, j: u32| j * (n + 1) + i;
        for j in 0..=m {
            for i in 0..=n {
                s.positions.push(Vec3::new(i as f32, j as f32, z(i, j)));
            }
        }
        for j in 0..m {
            for i in 0..n {
                s.push_face(&[id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)]);
            }
        }
        for j in 0..=m {
            for i in 0..=n {
                if i < n {
                    let kind = if j == 0 || j == m { 1 } else { 2 };
                    s.edges.push(SurfaceEdge { a: id(i, j), b: id(i + 1, j), kind });
                }
                if j < m {
                    let kind = if i == 0 || i == n { 1 } else { 2 };
                    s.edges.push(SurfaceEdge { a: id(i, j), b: id(i, j + 1), kind });
                }
            }
        }
        s
    }

    fn face_normal(s: &Surface, f: &[u32]) -> DVec3 {
        let q: Vec<DVec3> = f.iter().map(|&v| s.positions[v as usize].as_dvec3()).collect();
        (0..q.len()).map(|i| (q[i] - q[0]).cross(q[(i + 1) % q.len()] - q[0])).sum()
    }

    fn sum_of_face_sizes(s: &Surface) -> usize {
        s.faces().map(<[u32]>::len).sum()
    }

    #[test]
    fn a_tilted_flat_grid_stays_in_its_plane_and_the_counts_follow() {
        let plane = |x: f32, y: f32| 0.3 * x - 0.2 * y + 1.0;
        let s = grid(3, 2, |i, j| plane(i as f32, j as f32));
        let (v, e, f) = (s.positions.len(), s.edges.len(), s.face_count());
        assert_eq!((v, e, f), (12, 17, 6));
        let t = catmull_clark(&s, 1);
        assert_eq!(t.positions.len(), v + e + f);
        assert_eq!(t.face_count(), sum_of_face_sizes(&s));
        assert_eq!(t.edges.len(), 2 * e + sum_of_face_sizes(&s));
        assert!(t.faces().all(|q| q.len() == 4));
        let t2 = t.catmull_clark(2);
        assert_eq!(t2.face_count(), 6 * 4 * 4 * 4);
        for u in [&t, &t2] {
            for q in &u.positions {
                assert!((q.z - plane(q.x, q.y)).abs() < 1e-5, "{q} left the plane");
            }
            // Every face still faces +z (counter-clockwise from above).
            assert!(u.faces().all(|q| face_normal(u, q).z > 0.0));
        }
        // The corners move inward by the boundary rule, the outline stays
        // within the original rectangle.
        let (lo, hi) = t2.bounds().unwrap();
        assert!(lo.x >= 0.0 && lo.y >= 0.0 && hi.x <= 3.0 && hi.y <= 2.0);
    }

    #[test]
    fn euler_characteristic_is_kept() {
        let disc = grid(4, 3, |i, j| ((i * 7 + j * 3) % 5) as f32 * 0.1);
        assert_eq!(disc.euler_characteristic(), 1);
        for steps in 0..4 {
            assert_eq!(disc.catmull_clark(steps).euler_characteristic(), 1, "{steps} steps");
        }
        // A mixed disc: a triangle, a quad and a pentagon around one vertex.
        let mut s = Surface::new(0);
        s.positions = vec![
            Vec3::ZERO,
            Vec3::new(2.0, 0.0, 0.0),
            Vec3::new(1.5, 1.5, 0.0),
            Vec3::new(-0.5, 2.0, 0.0),
            Vec3::new(-2.0, 0.5, 0.0),
            Vec3::new(-1.5, -1.5, 0.0),
            Vec3::new(0.5, -2.0, 0.0),
            Vec3::new(1.8, -1.2, 0.0),
        ];
        s.push_face(&[0, 1, 2]);
        s.push_face(&[0, 2, 3, 4]);
        s.push_face(&[0, 4, 5, 6, 7, 1]);
        // Only some sides listed: the rest are added untyped.
        s.edges = vec![SurfaceEdge { a: 0, b: 1, kind: 3 }, SurfaceEdge { a: 2, b: 3, kind: 5 }];
        let t = s.catmull_clark(1);
        let edges_in = 10;
        assert_eq!(t.positions.len(), 8 + edges_in + 3);
        assert_eq!(t.face_count(), 3 + 4 + 6);
        assert_eq!(t.edges.len(), 2 * edges_in + 13);
        assert_eq!(t.euler_characteristic(), 1);
        assert!(t.faces().all(|q| q.len() == 4 && face_normal(&t, q).z > 0.0));
        // Edge types: halves of listed edges keep theirs.
        assert_eq!(t.edges[0], SurfaceEdge { a: 0, b: 8, kind: 3 });
        assert_eq!(t.edges[1], SurfaceEdge { a: 8, b: 1, kind: 3 });
        assert_eq!((t.edges[2].kind, t.edges[3].kind), (5, 5));
        assert!(t.edges[4..].iter().all(|e| e.kind == SurfaceEdge::UNTYPED));
    }

    #[test]
    fn one_square_gives_four_quads_by_the_boundary_rules() {
        let s = grid(1, 1, |_, _| 0.0);
        let t = s.catmull_clark(1);
        assert_eq!((t.positions.len(), t.edges.len(), t.face_count()), (4 + 4 + 1, 12, 4));
        let v = |x: f32, y: f32| Vec3::new(x, y, 0.0);
        // Corners: (a + 6P + b) / 8 with both neighbours on the boundary.
        assert_eq!(&t.positions[..4], &[v(0.125, 0.125), v(0.875, 0.125), v(0.125, 0.875), v(0.875, 0.875)]);
        // Edge points are the midpoints, in edge order; the centre last.
        let mids: Vec<Vec3> =
            s.edges.iter().map(|e| 0.5 * (s.positions[e.a as usize] + s.positions[e.b as usize])).collect();
        assert_eq!(&t.positions[4..8], &mids[..]);
        assert_eq!(t.positions[8], v(0.5, 0.5));
        // Each quad: corner, leaving edge point, centre, entering edge point.
        assert!(t.faces().all(|q| q[2] == 8 && q[0] < 4 && (4..8).contains(&q[1]) && (4..8).contains(&q[3])));
        assert!(t.faces().all(|q| face_normal(&t, q).z > 0.0));
        // Boundary halves keep type 1, the four new inner edges are untyped.
        assert_eq!(t.edges.iter().filter(|e| e.kind == 1).count(), 8);
        assert_eq!(t.edges.iter().filter(|e| e.kind == SurfaceEdge::UNTYPED).count(), 4);
    }

    #[test]
    fn a_closed_cube_follows_the_interior_rule() {
        // The unit cube centred at the origin, faces counter-clockwise from
        // outside.
        let mut s = Surface::new(0);
        for i in 0..8u32 {
            let c = |b: u32| if i & b != 0 { 0.5 } else { -0.5 };
            s.positions.push(Vec3::new(c(1), c(2), c(4)));
        }
        for f in [[0, 2, 3, 1], [4, 5, 7, 6], [0, 1, 5, 4], [2, 6, 7, 3], [0, 4, 6, 2], [1, 3, 7, 5]] {
            s.push_face(&f);
        }
        let mut pairs = std::collections::BTreeSet::new();
        for f in s.faces() {
            for i in 0..4 {
                pairs.insert((f[i].min(f[(i + 1) % 4]), f[i].max(f[(i + 1) % 4])));
            }
        }
        s.edges = pairs.into_iter().map(|(a, b)| SurfaceEdge { a, b, kind: 0 }).collect();
        assert_eq!(s.euler_characteristic(), 2);
        let t = s.catmull_clark(1);
        assert_eq!((t.positions.len(), t.face_count()), (26, 24));
        assert_eq!(t.euler_characteristic(), 2);
        // Corner: F = (1/6, 1/6, 1/6), R = (1/3, 1/3, 1/3), n = 3:
        // (F + 2R) / 3 = 5/18 per coordinate.
        assert!((t.positions[7] - Vec3::splat(5.0 / 18.0)).length() < 1e-6, "{}", t.positions[7]);
        // An edge point: (two ends + two face points) / 4.
        let e = s.edges.iter().position(|e| (e.a, e.b) == (6, 7)).unwrap();
        assert!((t.positions[8 + e] - Vec3::new(0.0, 0.375, 0.375)).length() < 1e-6);
        // Every face still faces outward.
        assert!(t.faces().all(|q| {
            let c: Vec3 = q.iter().map(|&v| t.positions[v as usize]).sum::<Vec3>() / 4.0;
            face_normal(&t, q).dot(c.as_dvec3()) > 0.0
        }));
    }

    #[test]
    fn smoothing_a_bumpy_grid_flattens_it() {
        let bumpy = grid(6, 6, |i, j| if (i + j) % 2 == 0 { 1.0 } else { -1.0 });
        let max_step = |s: &Surface| {
            s.edges
                .iter()
                .map(|e| (s.positions[e.a as usize].z - s.positions[e.b as usize].z).abs())
                .fold(0.0, f32::max)
        };
        let before = max_step(&bumpy);
        let once = bumpy.catmull_clark(1);
        let twice = bumpy.catmull_clark(2);
        assert!(max_step(&once) < 0.5 * before, "{} vs {before}", max_step(&once));
        assert!(max_step(&twice) < max_step(&once));
    }

    #[test]
    fn dangling_edges_and_malformed_pieces() {
        // A triangle with a dangling edge from corner 2 to vertex 3, a
        // duplicate edge, a self-loop and an out-of-range edge and face.
        let mut s = Surface::new(7);
        s.positions = vec![Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::new(0.0, 2.0, 0.0)];
        s.push_face(&[0, 1, 2]);
        s.push_face(&[0, 9, 2]);
        s.push_face(&[0, 0, 1]);
        s.edges = vec![
            SurfaceEdge { a: 0, b: 1, kind: 1 },
            SurfaceEdge { a: 1, b: 2, kind: 1 },
            SurfaceEdge { a: 2, b: 0, kind: 1 },
            SurfaceEdge { a: 2, b: 3, kind: 4 },
            SurfaceEdge { a: 1, b: 0, kind: 9 },
            SurfaceEdge { a: 3, b: 3, kind: 9 },
            SurfaceEdge { a: 3, b: 12, kind: 9 },
        ];
        s.outside_soft = 2;
        let t = s.catmull_clark(1);
        assert_eq!((t.positions.len(), t.edges.len(), t.face_count()), (4 + 4 + 1, 8 + 3, 3));
        assert_eq!((t.tag, t.outside_soft), (7, 2));
        // The dangling edge's far end stays; its midpoint splits it in
        // two halves of type 4. Corner 2 lies on three boundary edges: fixed.
        assert_eq!(t.positions[3], Vec3::new(0.0, 2.0, 0.0));
        assert_eq!(t.positions[2], Vec3::Y);
        assert_eq!(t.positions[7], Vec3::new(0.0, 1.5, 0.0));
        assert_eq!(t.edges.iter().filter(|e| e.kind == 4).count(), 2);
        assert!(t.edges.iter().all(|e| e.kind != 9));
        assert_eq!(catmull_clark(&s, 0), s);
    }

    proptest::proptest! {
        /// Random grids of random heights: counts and V − E + F follow.
        #[test]
        fn counts_follow_for_random_grids(n in 1u32..6, m in 1u32..6, seed in 0u32..1000) {
            let s = grid(n, m, |i, j| ((i * 31 + j * 17 + seed) % 13) as f32 * 0.1);
            let t = s.catmull_clark(1);
            proptest::prop_assert_eq!(t.positions.len(), s.positions.len() + s.edges.len() + s.face_count());
            proptest::prop_assert_eq!(t.face_count(), 4 * s.face_count());
            proptest::prop_assert_eq!(t.euler_characteristic(), 1);
            proptest::prop_assert!(t.positions.iter().all(|p| p.is_finite()));
        }
    }
}
