//! Tests of the Scene, its meshes, triangulation and tessellation.

use super::*;

/// Signed volume via the divergence theorem; positive iff outward winding.
fn volume(m: &Mesh) -> f32 {
    m.triangles
        .iter()
        .map(|t| {
            let [a, b, c] = t.map(|i| m.positions[i as usize]);
            a.dot(b.cross(c)) / 6.0
        })
        .sum()
}

#[test]
fn unit_primitives_are_closed_and_outward() {
    let tess = Tessellation::default();
    let cases = [
        (Primitive::Box, 1.0),
        (Primitive::TaperedBox { top: 0.0 }, 1.0 / 3.0),
        (Primitive::Frustum { top: 1.0 }, std::f32::consts::PI * 0.25),
        (Primitive::Frustum { top: 0.0 }, std::f32::consts::PI * 0.25 / 3.0),
        (Primitive::Sphere, std::f32::consts::PI / 6.0),
    ];
    for (p, exact) in cases {
        let v = volume(&unit_mesh(p, tess));
        assert!(v > 0.0, "{p:?} winding");
        assert!((v - exact).abs() / exact < 0.06, "{p:?}: {v} vs {exact}");
    }
}

#[test]
fn reflected_instances_keep_outward_winding() {
    let mut s = Scene::new();
    let tag = s.tag("x");
    s.instances.push(Instance {
        transform: Affine3A::from_scale(Vec3::new(-2.0, 1.0, 1.0)),
        primitive: Primitive::Box,
        tag,
    });
    let mut v = 0.0;
    s.for_each_triangle(Tessellation::default(), |[a, b, c], _| v += a.dot(b.cross(c)) / 6.0);
    assert!((v - 2.0).abs() < 1e-5, "{v}");
    assert_eq!(s.bounds(Tessellation::default()).unwrap().0, Vec3::new(-1.0, -0.5, -0.5));
}

#[test]
fn obj_reader_handles_polygons_and_reports_bad_lines() {
    let m = Mesh::from_obj("q", "# quad\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nf 1/1 2/1 3/1 -1/1\n").unwrap();
    assert_eq!(m.triangles, vec![[0, 1, 2], [0, 2, 3]]);
    assert!(Mesh::from_obj("q", "v 0 0\n").unwrap_err().contains("line 1"));
    assert!(Mesh::from_obj("q", "v 0 0 0\nf 1 2 3\n").unwrap_err().contains("missing vertex"));
    assert!(Mesh::from_obj("q", "").unwrap_err().contains("no faces"));
}

/// 2D outline → 3D points on a tilted plane (so the Newell projection
/// is exercised), reversed for clockwise input.
fn tilted(outline: &[(f32, f32)], clockwise: bool) -> Vec<Vec3> {
    let r = glam::Quat::from_euler(glam::EulerRot::XYZ, 0.7, -0.4, 0.2);
    let mut pts: Vec<Vec3> = outline.iter().map(|&(x, y)| r * Vec3::new(x, y, 0.0) + Vec3::splat(3.0)).collect();
    if clockwise {
        pts.reverse();
    }
    pts
}

fn newell(pts: &[Vec3]) -> Vec3 {
    (0..pts.len()).map(|i| (pts[i] - pts[0]).cross(pts[(i + 1) % pts.len()] - pts[0])).sum()
}

/// Even-odd point in polygon on the 2D outline.
fn inside(outline: &[(f32, f32)], (x, y): (f32, f32)) -> bool {
    let mut odd = false;
    for i in 0..outline.len() {
        let ((x0, y0), (x1, y1)) = (outline[i], outline[(i + 1) % outline.len()]);
        if (y0 > y) != (y1 > y) && x < x0 + (y - y0) / (y1 - y0) * (x1 - x0) {
            odd = !odd;
        }
    }
    odd
}

/// Checks a triangulation of a simple outline: `expected` triangles,
/// each counter-clockwise about the Newell normal and inside the
/// outline, their areas adding up to the polygon's.
fn check_triangulation(outline: &[(f32, f32)], expected: usize) {
    for clockwise in [false, true] {
        let pts = tilted(outline, clockwise);
        let flat: Vec<(f32, f32)> = if clockwise { outline.iter().rev().copied().collect() } else { outline.to_vec() };
        let tris = triangulate_polygon(&pts);
        assert_eq!(tris.len(), expected, "{outline:?} cw={clockwise}: {tris:?}");
        let n = newell(&pts);
        let mut area = 0.0;
        for t in &tris {
            let [a, b, c] = t.map(|i| pts[i as usize]);
            let tn = (b - a).cross(c - a);
            assert!(tn.dot(n) > 0.0, "{t:?} winds the wrong way");
            area += tn.length() / 2.0;
            let [p, q, r] = t.map(|i| flat[i as usize]);
            let centroid = ((p.0 + q.0 + r.0) / 3.0, (p.1 + q.1 + r.1) / 3.0);
            assert!(inside(outline, centroid), "{t:?} lies outside {outline:?}");
        }
        assert!((area - n.length() / 2.0).abs() < 1e-4 * area, "{area} vs {}", n.length() / 2.0);
    }
}

#[test]
fn ear_clipping_handles_concave_outlines_both_ways_round() {
    let l_shape = [(0.0, 0.0), (2.0, 0.0), (2.0, 1.0), (1.0, 1.0), (1.0, 2.0), (0.0, 2.0)];
    check_triangulation(&l_shape, 4);
    let star: Vec<(f32, f32)> = (0..10)
        .map(|i| {
            let a = std::f32::consts::TAU * i as f32 / 10.0;
            let r = if i % 2 == 0 { 1.0 } else { 0.38 };
            (r * a.cos(), r * a.sin())
        })
        .collect();
    check_triangulation(&star, 8);
    // A comb: the fan from vertex 0 would cross the outside.
    let comb = [(0.0, 0.0), (5.0, 0.0), (5.0, 3.0), (4.0, 3.0), (4.0, 1.0), (3.0, 1.0), (3.0, 3.0), (0.0, 3.0)];
    check_triangulation(&comb, 6);
}

#[test]
fn ear_clipping_drops_repeats_straight_runs_and_degenerates() {
    // A unit square with repeated corners, midpoints and a zero-width spike.
    let square = [
        (0.0, 0.0),
        (0.0, 0.0),
        (0.5, 0.0),
        (1.0, 0.0),
        (1.0, 0.5),
        (1.5, 0.5),
        (1.0, 0.5),
        (1.0, 1.0),
        (0.0, 1.0),
        (0.0, 0.0),
    ];
    let pts = tilted(&square, false);
    let tris = triangulate_polygon(&pts);
    assert_eq!(tris.len(), 2, "{tris:?}");
    let area: f32 = tris
        .iter()
        .map(|t| {
            let [a, b, c] = t.map(|i| pts[i as usize]);
            (b - a).cross(c - a).length() / 2.0
        })
        .sum();
    assert!((area - 1.0).abs() < 1e-5, "{area}");
    // A convex outline keeps the fan from its first corner.
    let quad = [Vec3::ZERO, Vec3::X, Vec3::new(1.0, 1.0, 0.0), Vec3::Y];
    assert_eq!(triangulate_polygon(&quad), vec![[0, 1, 2], [0, 2, 3]]);
    // Nothing from too few points, one point, a line, or zero area.
    assert!(triangulate_polygon(&quad[..2]).is_empty());
    assert!(triangulate_polygon(&[Vec3::ONE; 5]).is_empty());
    assert!(triangulate_polygon(&[Vec3::ZERO, Vec3::X, Vec3::X * 2.0, Vec3::X * 0.5]).is_empty());
    // Non-finite input still shows up (as the plain fan).
    assert_eq!(triangulate_polygon(&[Vec3::ZERO, Vec3::X, Vec3::NAN, Vec3::Y]).len(), 2);
}

#[test]
fn self_intersecting_outlines_do_not_get_stuck() {
    // A bow tie and a pentagram: some triangles, all finite, no panic.
    let bow = [Vec3::ZERO, Vec3::new(2.0, 1.0, 0.0), Vec3::new(2.0, 0.0, 0.0), Vec3::new(0.0, 1.2, 0.0)];
    let pentagram: Vec<Vec3> = (0..5)
        .map(|i| {
            let a = std::f32::consts::TAU * (2 * i) as f32 / 5.0;
            Vec3::new(a.cos(), a.sin(), 0.0)
        })
        .collect();
    for pts in [&bow[..], &pentagram] {
        let tris = triangulate_polygon(pts);
        assert!(!tris.is_empty() && tris.len() <= pts.len() - 2, "{tris:?}");
        assert!(tris.iter().flatten().all(|&i| (i as usize) < pts.len()));
    }
}

#[test]
fn scene_polygons_are_ear_clipped() {
    let mut s = Scene::new();
    let tag = s.tag("leaf");
    let l_shape = [(0.0, 0.0), (2.0, 0.0), (2.0, 1.0), (1.0, 1.0), (1.0, 2.0), (0.0, 2.0)];
    s.polygons.push(Polygon { points: l_shape.iter().map(|&(x, y)| Vec3::new(x, y, 0.0)).collect(), tag });
    let mut area = 0.0;
    s.for_each_triangle(Tessellation::default(), |[a, b, c], t| {
        assert_eq!(t, tag);
        let n = (b - a).cross(c - a);
        assert!(n.z > 0.0);
        area += n.z / 2.0;
    });
    assert_eq!(s.triangle_count(Tessellation::default()), 4);
    assert!((area - 3.0).abs() < 1e-5, "{area}");
}

proptest::proptest! {
    /// Random star-shaped outlines (simple by construction) split into
    /// n − 2 inside triangles covering the area exactly.
    #[test]
    fn random_star_shaped_outlines(radii in proptest::collection::vec(0.2f32..1.0, 3..24)) {
        let n = radii.len();
        let outline: Vec<(f32, f32)> = radii
            .iter()
            .enumerate()
            .map(|(i, r)| {
                let a = std::f32::consts::TAU * i as f32 / n as f32;
                (r * a.cos(), r * a.sin())
            })
            .collect();
        // Nearly straight corners may be dropped, so up to n − 2.
        let pts = tilted(&outline, false);
        let tris = triangulate_polygon(&pts);
        let kept: std::collections::BTreeSet<u32> = tris.iter().flatten().copied().collect();
        proptest::prop_assert_eq!(tris.len(), kept.len() - 2);
        check_triangulation(&outline, tris.len());
    }
}

#[test]
fn tags_and_meshes_are_interned() {
    let mut s = Scene::new();
    assert_eq!(s.tag("a"), 0);
    assert_eq!(s.tag("b"), 1);
    assert_eq!(s.tag("a"), 0);
    let m = Arc::new(Mesh::default());
    assert_eq!(s.mesh(&m), 0);
    assert_eq!(s.mesh(&m), 0);
    assert_eq!(s.mesh(&Arc::new(Mesh::default())), 1);
}
