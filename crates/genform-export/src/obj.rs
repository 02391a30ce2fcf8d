//! Wavefront OBJ text.

use crate::shapes::{Shapes, tag_name};
use genform_core::scene::{Scene, Tessellation};
use glam::Vec3;
use std::fmt::Write;

/// Writes `scene` as Wavefront OBJ text.
///
/// One object (`o <tag>_<index>`) per instance, `index` being its position
/// in [`Scene::instances`]: the instance's unit mesh transformed to world
/// space (`v` lines), then its triangles (`f`, counter-clockwise from
/// outside, also for reflected instances). A box gives 8 vertices and 12
/// faces. Then one object per polygon (`o <tag>_polygon<k>`, one n-gon
/// face) and per polyline (`o <tag>_polyline<k>`, one `l` statement), and
/// last one object per block state of the block grids (`o <state>`, the
/// greedy mesh of [`crate::minecraft::mesh_blocks`], quads as two
/// triangles).
///
/// Then one object per surface (`o <tag>_surface<k>`): its vertices, its
/// faces as polygons (`f`, counter-clockwise from the front, not
/// triangulated), then its edges as two-point `l` lines, one group per edge
/// type in ascending order, `g <tag>_surface<k>_edges_type<N>`, untyped
/// edges last in `g <tag>_surface<k>_edges_untyped`. Guides are left out.
/// No normals, texture coordinates or materials. Numbers are printed with
/// at most 6 decimals, trailing zeros trimmed, so the text is identical
/// from run to run.
///
/// # Panics
///
/// If an instance refers to a missing mesh asset (see [`crate::export`],
/// which checks).
pub fn write_obj(scene: &Scene, tess: Tessellation) -> String {
    let shapes = Shapes::new(scene, tess);
    let mut out = String::with_capacity(64 + scene.instances.len() * 400);
    out.push_str("# genform\n");
    // OBJ indices are 1-based and global.
    let mut next = 1usize;
    for (i, inst) in scene.instances.iter().enumerate() {
        let mesh = shapes.of(i);
        let _ = writeln!(out, "o {}_{i}", tag_name(scene, inst.tag));
        for &p in &mesh.positions {
            vertex(&mut out, inst.transform.transform_point3(p));
        }
        let flip = inst.transform.matrix3.determinant() < 0.0;
        for t in &mesh.triangles {
            let [a, b, c] = t.map(|v| next + v as usize);
            let (b, c) = if flip { (c, b) } else { (b, c) };
            let _ = writeln!(out, "f {a} {b} {c}");
        }
        next += mesh.positions.len();
    }
    // Polygons become one n-sided face (`f`), polylines one line element (`l`).
    let runs = scene
        .polygons
        .iter()
        .enumerate()
        .filter(|(_, p)| p.points.len() >= 3)
        .map(|(k, p)| ('f', "polygon", k, p.tag, &p.points));
    let lines = scene
        .polylines
        .iter()
        .enumerate()
        .filter(|(_, l)| l.points.len() >= 2)
        .map(|(k, l)| ('l', "polyline", k, l.tag, &l.points));
    for (element, kind, k, tag, points) in runs.chain(lines) {
        let _ = writeln!(out, "o {}_{kind}{k}", tag_name(scene, tag));
        for &p in points {
            vertex(&mut out, p);
        }
        out.push(element);
        for v in next..next + points.len() {
            let _ = write!(out, " {v}");
        }
        out.push('\n');
        next += points.len();
    }
    for m in crate::minecraft::block_meshes(scene) {
        let _ = writeln!(out, "o {}", m.mesh.name);
        for &p in &m.mesh.positions {
            vertex(&mut out, p);
        }
        for t in &m.mesh.triangles {
            let [a, b, c] = t.map(|v| next + v as usize);
            let _ = writeln!(out, "f {a} {b} {c}");
        }
        next += m.mesh.positions.len();
    }
    for (k, surface) in scene.surfaces.iter().enumerate() {
        let name = crate::surfaces::surface_name(scene, k);
        let _ = writeln!(out, "o {name}");
        for &p in &surface.positions {
            vertex(&mut out, p);
        }
        for face in surface.faces() {
            out.push('f');
            for &v in face {
                let _ = write!(out, " {}", next + v as usize);
            }
            out.push('\n');
        }
        for (kind, pairs) in crate::surfaces::edges_by_type(surface) {
            if kind == genform_core::SurfaceEdge::UNTYPED {
                let _ = writeln!(out, "g {name}_edges_untyped");
            } else {
                let _ = writeln!(out, "g {name}_edges_type{kind}");
            }
            for [a, b] in pairs {
                let _ = writeln!(out, "l {} {}", next + a as usize, next + b as usize);
            }
        }
        next += surface.positions.len();
    }
    out
}

/// A `v x y z` line.
fn vertex(out: &mut String, p: Vec3) {
    out.push('v');
    for c in p.to_array() {
        out.push(' ');
        number(out, c);
    }
    out.push('\n');
}

/// `x` with 6 decimals, trailing zeros (and a bare point) trimmed, `-0` as `0`.
pub(crate) fn number(out: &mut String, x: f32) {
    let start = out.len();
    let _ = write!(out, "{x:.6}");
    if out[start..].contains('.') {
        let keep = out.trim_end_matches('0').trim_end_matches('.').len();
        out.truncate(keep);
    }
    if &out[start..] == "-0" {
        out.truncate(start);
        out.push('0');
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::test_scenes;

    fn count(text: &str, prefix: &str) -> usize {
        text.lines().filter(|l| l.starts_with(prefix)).count()
    }

    #[test]
    fn numbers_are_short_and_stable() {
        let cases = [
            (0.0, "0"),
            (-0.0, "0"),
            (-1e-9, "0"),
            (1.5, "1.5"),
            (-2.0, "-2"),
            (0.1, "0.1"),
            (0.49999997, "0.5"),
            (1234.5677, "1234.567749"),
            (10.0, "10"),
        ];
        for (x, want) in cases {
            let mut s = String::from("v ");
            number(&mut s, x);
            assert_eq!(&s[2..], want, "{x}");
        }
    }

    #[test]
    fn one_object_per_box_instance() {
        let s = test_scenes::boxes(3);
        let text = write_obj(&s, Tessellation::default());
        assert_eq!(count(&text, "o "), 3);
        assert_eq!(count(&text, "v "), 24);
        assert_eq!(count(&text, "f "), 36);
        assert!(text.contains("\no hull_0\n") && text.contains("\no hull_2\n"));
        // The second box starts at x = 2 - 0.5.
        assert!(text.contains("\nv 1.5 -0.5 -0.5\n"), "{text}");
        // Face indices of the third object point at its own vertices.
        let last = text.lines().rev().find(|l| l.starts_with("f ")).unwrap();
        assert!(last.split_whitespace().skip(1).all(|v| (17..=24).contains(&v.parse::<usize>().unwrap())));
    }

    #[test]
    fn faces_stay_outward_for_reflected_instances() {
        let s = test_scenes::mixed();
        let text = write_obj(&s, Tessellation::default());
        // Re-read and sum the signed volume object by object.
        let mut verts: Vec<Vec3> = Vec::new();
        let mut vol = Vec::new();
        for line in text.lines() {
            let mut it = line.split_whitespace();
            match it.next() {
                Some("o") => vol.push((it.next().unwrap().to_string(), 0.0f64)),
                Some("v") => {
                    let c: Vec<f32> = it.map(|t| t.parse().unwrap()).collect();
                    verts.push(Vec3::new(c[0], c[1], c[2]));
                }
                Some("f") => {
                    let idx: Vec<usize> = it.map(|t| t.parse::<usize>().unwrap() - 1).collect();
                    let [a, b, c] = [verts[idx[0]], verts[idx[1]], verts[idx[2]]];
                    vol.last_mut().unwrap().1 += f64::from(a.dot(b.cross(c))) / 6.0;
                }
                _ => {}
            }
        }
        // All instances but the flattened one have positive volume.
        assert_eq!(vol.len(), 16 + 1 + 1);
        for (i, (name, v)) in vol.iter().enumerate().take(16) {
            if i == 14 {
                assert!(v.abs() < 1e-4, "{name}: {v}");
            } else {
                assert!(*v > 1e-3, "{name}: {v}");
            }
        }
        assert!(text.contains("\no roof_tile_1") || text.contains("\no roof_tile_14"));
        assert!(text.contains("\no roof_tile_polygon0\n") && text.contains("\no trunk_polyline0\n"));
        assert!(text.contains("\nl ") && text.lines().any(|l| l.starts_with("f ") && l.split(' ').count() == 5));
    }

    #[test]
    fn block_grids_are_objects_per_state() {
        use genform_core::blocks::{BlockGrid, BlockState};
        use glam::{IVec3, UVec3};
        let mut s = test_scenes::boxes(1);
        let mut g = BlockGrid::new(IVec3::new(0, 5, 0), UVec3::new(2, 1, 1));
        g.set(IVec3::new(0, 5, 0), &BlockState::new("stone"));
        g.set(IVec3::new(1, 5, 0), &BlockState::new("stone"));
        s.blocks.push(g);
        let text = write_obj(&s, Tessellation::default());
        assert!(text.contains("\no minecraft:stone\n"), "{text}");
        // The box (8 vertices, 12 faces), then the bar: 6 quads.
        assert_eq!(count(&text, "v "), 8 + 24);
        assert_eq!(count(&text, "f "), 12 + 12);
        assert!(text.contains("\nv 2 6 1\n"));
        let last = text.lines().rev().find(|l| l.starts_with("f ")).unwrap();
        assert!(last.split_whitespace().skip(1).all(|v| (9..=32).contains(&v.parse::<usize>().unwrap())));
    }

    #[test]
    fn surfaces_keep_polygons_and_typed_edges() {
        let s = test_scenes::surfaces();
        let text = write_obj(&s, Tessellation::default());
        // The box first, then the two surfaces.
        assert_eq!(count(&text, "o "), 3);
        assert_eq!(count(&text, "v "), 8 + 9 + 25);
        assert_eq!(count(&text, "f "), 12 + 4 + 16);
        assert_eq!(count(&text, "l "), 12 + 40);
        let lines: Vec<&str> = text.lines().collect();
        let at = |l: &str| lines.iter().position(|x| *x == l).unwrap_or_else(|| panic!("no `{l}`"));
        let (o0, o1) = (at("o shell_surface0"), at("o shell_surface1"));
        let (g1, g2) = (at("g shell_surface0_edges_type1"), at("g shell_surface0_edges_type2"));
        let untyped = at("g shell_surface1_edges_untyped");
        assert!(o0 < g1 && g1 < g2 && g2 < o1 && o1 < untyped);
        // 8 boundary edges of type 1, then 4 inner ones of type 2.
        assert!(lines[g1 + 1..g2].iter().all(|l| l.starts_with("l ")) && g2 - g1 - 1 == 8);
        assert!(lines[g2 + 1..o1].iter().all(|l| l.starts_with("l ")) && o1 - g2 - 1 == 4);
        // Quads are kept whole and point at the surface's own vertices
        // (9..=17 after the box's 8).
        let faces: Vec<&str> = lines[o0..g1].iter().copied().filter(|l| l.starts_with("f ")).collect();
        assert_eq!(faces[0], "f 9 10 13 12");
        assert!(lines[g1 + 1].split_whitespace().skip(1).all(|v| (9..=17).contains(&v.parse::<usize>().unwrap())));
        assert!(text.contains("\nv 1 1 0.5\n"));
        // Guides are not written.
        assert!(!text.contains("boundary") && !text.contains("attractor"));
    }

    #[test]
    fn text_is_deterministic() {
        let s = test_scenes::mixed();
        assert_eq!(write_obj(&s, Tessellation::default()), write_obj(&s.clone(), Tessellation::default()));
    }
}
