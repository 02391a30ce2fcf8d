//! The planar faces of a solid (a roof, a taper) for `roof_hip(30) { top:
//! A | side: B }`: the triangles the solid was built from, joined where
//! they share an edge and a plane, each face's outline read off the edges
//! that only one of its triangles has.
//!
//! Working from the finished mesh rather than from each roof kind's own
//! construction keeps one definition of "a face" for every solid (convex
//! envelopes, straight-skeleton roofs, gables stood up at wing ends,
//! tapers), and what a face holds is exactly what would have been drawn.

use genform_core::scene::Mesh;
use glam::{DVec2, DVec3};
use std::collections::HashMap;

/// One planar face: its unit outward normal and its outline,
/// counter-clockwise seen from outside, without collinear corners.
#[derive(Clone, Debug)]
pub(crate) struct PlanarFace {
    pub normal: DVec3,
    pub outline: Vec<DVec3>,
}

/// The frame a face is laid in: x along its horizontal direction (the
/// eaves of a slope, the base of a wall; world x for a level face), y up
/// the face (y = normal × x), z its outward normal.
pub(crate) fn face_axes(n: DVec3) -> (DVec3, DVec3) {
    let h = DVec3::new(-n.y, n.x, 0.0);
    let x = if h.length_squared() <= 1e-18 { DVec3::X } else { h.normalize() };
    (x, n.cross(x))
}

fn find(parent: &mut [usize], mut i: usize) -> usize {
    while parent[i] != i {
        parent[i] = parent[parent[i]];
        i = parent[i];
    }
    i
}

/// The planar faces of a closed mesh, in the order their first triangle
/// comes; degenerate triangles are left out.
pub(crate) fn planar_faces(mesh: &Mesh) -> Vec<PlanarFace> {
    // Corners at the same place are one corner (a roof may repeat them per
    // face).
    let mut ids: HashMap<[u32; 3], usize> = HashMap::new();
    let mut pos: Vec<DVec3> = Vec::new();
    let vid: Vec<usize> = mesh
        .positions
        .iter()
        .map(|p| {
            let key = [p.x.to_bits(), p.y.to_bits(), p.z.to_bits()];
            *ids.entry(key).or_insert_with(|| {
                pos.push(p.as_dvec3());
                pos.len() - 1
            })
        })
        .collect();
    let size = pos.iter().fold(0.0f64, |m, p| m.max(p.abs().max_element())).max(1e-12);
    let tris: Vec<([usize; 3], DVec3, f64)> = mesh
        .triangles
        .iter()
        .filter_map(|t| {
            let v = t.map(|i| vid[i as usize]);
            let c = (pos[v[1]] - pos[v[0]]).cross(pos[v[2]] - pos[v[0]]);
            let l = c.length();
            (l > 1e-12 * size * size).then(|| {
                let n = c / l;
                (v, n, n.dot(pos[v[0]]))
            })
        })
        .collect();
    // Triangles that share an edge and a plane are one face.
    let mut parent: Vec<usize> = (0..tris.len()).collect();
    let mut by_edge: HashMap<(usize, usize), usize> = HashMap::new();
    for (k, (v, _, _)) in tris.iter().enumerate() {
        for e in 0..3 {
            let (a, b) = (v[e], v[(e + 1) % 3]);
            if let Some(&j) = by_edge.get(&(b, a)) {
                let same = tris[j].1.dot(tris[k].1) > 1.0 - 1e-6 && (tris[j].2 - tris[k].2).abs() <= 1e-6 * size;
                if same {
                    let (ra, rb) = (find(&mut parent, j), find(&mut parent, k));
                    parent[ra.max(rb)] = ra.min(rb);
                }
            }
            by_edge.insert((a, b), k);
        }
    }
    let mut groups: Vec<(usize, Vec<usize>)> = Vec::new();
    let mut slot: HashMap<usize, usize> = HashMap::new();
    for k in 0..tris.len() {
        let r = find(&mut parent, k);
        let g = *slot.entry(r).or_insert_with(|| {
            groups.push((r, Vec::new()));
            groups.len() - 1
        });
        groups[g].1.push(k);
    }
    let mut faces = Vec::new();
    for (_, members) in groups {
        // The face's normal weighted by area (the triangles agree within
        // the tolerance above).
        let n = members
            .iter()
            .map(|&k| {
                let v = tris[k].0;
                (pos[v[1]] - pos[v[0]]).cross(pos[v[2]] - pos[v[0]])
            })
            .sum::<DVec3>()
            .normalize_or_zero();
        if n == DVec3::ZERO {
            continue;
        }
        let inner: std::collections::HashSet<(usize, usize)> = members
            .iter()
            .flat_map(|&k| {
                let v = tris[k].0;
                (0..3).map(move |e| (v[e], v[(e + 1) % 3]))
            })
            .collect();
        let mut next: HashMap<usize, usize> = HashMap::new();
        let mut starts: Vec<usize> = Vec::new();
        for &k in &members {
            let v = tris[k].0;
            for e in 0..3 {
                let (a, b) = (v[e], v[(e + 1) % 3]);
                if !inner.contains(&(b, a)) {
                    next.insert(a, b);
                    starts.push(a);
                }
            }
        }
        let (x, y) = face_axes(n);
        // No outline is longer than the face's boundary.
        let most = next.len();
        for s in starts {
            let Some(mut b) = next.remove(&s) else { continue };
            let mut ring = vec![s];
            while b != s && ring.len() <= most {
                ring.push(b);
                match next.remove(&b) {
                    Some(c) => b = c,
                    None => break,
                }
            }
            let flat: Vec<DVec2> = ring.iter().map(|&i| DVec2::new(pos[i].dot(x), pos[i].dot(y))).collect();
            let keep = corners(&flat, 1e-9 * size);
            if keep.len() < 3 || crate::polygon::area2(&keep.iter().map(|&i| flat[i]).collect::<Vec<_>>()) <= 0.0 {
                // A hole or a sliver: not a face of its own.
                continue;
            }
            faces.push(PlanarFace { normal: n, outline: keep.iter().map(|&i| pos[ring[i]]).collect() });
        }
    }
    faces
}

/// The corners of a closed outline that are not on the line through their
/// neighbours (within `eps`), by index.
fn corners(p: &[DVec2], eps: f64) -> Vec<usize> {
    let m = p.len();
    (0..m)
        .filter(|&i| {
            let (a, b, c) = (p[(i + m - 1) % m], p[i], p[(i + 1) % m]);
            let (u, v) = (b - a, c - b);
            let l = u.length() * v.length();
            l > 0.0 && (u.perp_dot(v).abs() > eps * (u.length() + v.length()) || u.dot(v) < 0.0)
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geom::{RoofKind, roof_mesh};

    fn rect(w: f64, d: f64) -> Vec<DVec2> {
        vec![DVec2::new(0.0, 0.0), DVec2::new(w, 0.0), DVec2::new(w, d), DVec2::new(0.0, d)]
    }

    fn count(faces: &[PlanarFace], pred: impl Fn(DVec3) -> bool) -> usize {
        faces.iter().filter(|f| pred(f.normal)).count()
    }

    #[test]
    fn a_gable_roof_has_two_slopes_two_gable_walls_and_a_bottom() {
        let mesh = roof_mesh(&rect(10.0, 6.0), RoofKind::Gable, 40.0, 0.0).unwrap();
        let faces = planar_faces(&mesh);
        assert_eq!(faces.len(), 5, "{faces:?}");
        assert_eq!(count(&faces, |n| n.z > 1e-6), 2);
        assert_eq!(count(&faces, |n| n.z.abs() <= 1e-6), 2);
        assert_eq!(count(&faces, |n| n.z < -0.999), 1);
        // The slopes and the bottom are rectangles, the gables triangles.
        for f in &faces {
            let want = if f.normal.z.abs() > 1e-6 { 4 } else { 3 };
            assert_eq!(f.outline.len(), want, "{f:?}");
        }
    }

    #[test]
    fn a_hip_roof_on_an_l_has_one_face_per_edge_and_a_bottom() {
        let l = vec![
            DVec2::new(0.0, 0.0),
            DVec2::new(12.0, 0.0),
            DVec2::new(12.0, 5.0),
            DVec2::new(5.0, 5.0),
            DVec2::new(5.0, 10.0),
            DVec2::new(0.0, 10.0),
        ];
        let mesh = roof_mesh(&l, RoofKind::Hip, 35.0, 0.0).unwrap();
        let faces = planar_faces(&mesh);
        assert_eq!(count(&faces, |n| n.z > 1e-6), 6, "{faces:?}");
        assert_eq!(count(&faces, |n| n.z < -0.999), 1);
        let bottom = faces.iter().find(|f| f.normal.z < -0.999).unwrap();
        assert_eq!(bottom.outline.len(), 6, "the L's six corners: {bottom:?}");
        // Each outline lies in its plane and turns counter-clockwise seen
        // from outside.
        for f in &faces {
            let d = f.normal.dot(f.outline[0]);
            assert!(f.outline.iter().all(|p| (f.normal.dot(*p) - d).abs() < 1e-4), "{f:?}");
            let (x, y) = face_axes(f.normal);
            let flat: Vec<DVec2> = f.outline.iter().map(|p| DVec2::new(p.dot(x), p.dot(y))).collect();
            assert!(crate::polygon::area2(&flat) > 0.0);
        }
        // The slopes and the bottom cover the same plan area.
        let plan = |f: &PlanarFace| {
            crate::polygon::area2(&f.outline.iter().map(|p| DVec2::new(p.x, p.y)).collect::<Vec<_>>()).abs() / 2.0
        };
        let top: f64 = faces.iter().filter(|f| f.normal.z > 1e-6).map(plan).sum();
        assert!((top - 85.0).abs() < 1e-3, "{top}");
    }

    #[test]
    fn face_axes_run_along_the_eaves_and_up_the_slope() {
        let n = DVec3::new(0.0, -1.0, 1.0).normalize();
        let (x, y) = face_axes(n);
        assert!((x - DVec3::X).length() < 1e-12);
        assert!(y.z > 0.0 && y.dot(n).abs() < 1e-12);
        let (x, y) = face_axes(DVec3::NEG_Z);
        assert_eq!(x, DVec3::X);
        assert!((y - DVec3::NEG_Y).length() < 1e-12);
    }
}
