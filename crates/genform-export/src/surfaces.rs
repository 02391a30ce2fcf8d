//! What the writers share about polygon surfaces: names, edges grouped by
//! type, triangles by vertex index, vertex normals, and the scene without
//! its surfaces (for writers that treat surface faces apart from the
//! triangle soup).

use crate::shapes::tag_name;
use genform_core::scene::{Scene, triangulate_polygon};
use genform_core::surface::Surface;
use glam::{DVec3, Vec3};
use std::borrow::Cow;
use std::collections::BTreeMap;

/// A surface's point as grown (+z up, the seed's normal) in genform's
/// up-axis convention, +y up: (x, y, z) → (x, z, −y), the turn the GLB
/// writer gives a surface's node (`Z_UP_TO_Y_UP`).
pub fn grown_to_y_up(p: Vec3) -> Vec3 {
    Vec3::new(p.x, p.z, -p.y)
}

/// `scene` with its surfaces turned from their grown +z up to genform's +y
/// up ([`grown_to_y_up`]), as OBJ, PLY, STL and `Model.mesh()` give them
/// (the GLB turns the surface's node instead); the scene itself when it
/// has no surfaces.
pub fn surfaces_y_up(scene: &Scene) -> Cow<'_, Scene> {
    if scene.surfaces.is_empty() {
        return Cow::Borrowed(scene);
    }
    let mut turned = scene.clone();
    for s in &mut turned.surfaces {
        s.positions.iter_mut().for_each(|p| *p = grown_to_y_up(*p));
    }
    Cow::Owned(turned)
}

/// `scene` as previews show grown surfaces: its surfaces and guides turned
/// from their grown +z up to +y up ([`grown_to_y_up`]), so a picture shows
/// the surface from above the way it grew.
pub fn preview_y_up(scene: &Scene) -> Scene {
    let mut s = scene.clone();
    for surface in &mut s.surfaces {
        surface.positions.iter_mut().for_each(|p| *p = grown_to_y_up(*p));
    }
    for g in &mut s.guides {
        match &mut g.kind {
            genform_core::GuideKind::Point { at, .. } => *at = grown_to_y_up(*at),
            genform_core::GuideKind::Mesh(m) => {
                let mut mesh = (**m).clone();
                mesh.positions.iter_mut().for_each(|p| *p = grown_to_y_up(*p));
                *m = std::sync::Arc::new(mesh);
            }
        }
    }
    s
}

/// Whether every face corner and edge end of `s` names one of its vertices
/// (what the previews check before drawing a surface, so a malformed one is
/// left out instead of panicking).
pub(crate) fn well_formed(s: &Surface) -> bool {
    let n = s.positions.len();
    let offsets = s.face_offsets.windows(2).all(|w| w[0] <= w[1])
        && s.face_offsets.first().is_none_or(|&o| o == 0)
        && s.face_offsets.last().is_none_or(|&o| o as usize == s.face_vertices.len());
    offsets && s.face_vertices.iter().all(|&v| (v as usize) < n) && s.edges.iter().all(|e| (e.a.max(e.b) as usize) < n)
}

/// The display name of surface `k`: `<tag>_surface<k>`, no whitespace.
pub(crate) fn surface_name(scene: &Scene, k: usize) -> String {
    format!("{}_surface{k}", tag_name(scene, scene.surfaces[k].tag))
}

/// The surface's edges as vertex pairs, grouped by type in ascending order
/// (so [`genform_core::SurfaceEdge::UNTYPED`] comes last), each group in edge
/// order. Edges from a vertex to itself are left out.
pub(crate) fn edges_by_type(s: &Surface) -> BTreeMap<u32, Vec<[u32; 2]>> {
    let mut groups: BTreeMap<u32, Vec<[u32; 2]>> = BTreeMap::new();
    for e in s.edges.iter().filter(|e| e.a != e.b) {
        groups.entry(e.kind).or_default().push([e.a, e.b]);
    }
    groups
}

/// The faces split into triangles ([`triangulate_polygon`]), as vertex
/// indices of the surface, counter-clockwise like the faces.
pub(crate) fn triangles(s: &Surface) -> Vec<[u32; 3]> {
    let mut out = Vec::with_capacity(s.face_vertices.len());
    let mut pts = Vec::new();
    for f in s.faces() {
        pts.clear();
        pts.extend(f.iter().map(|&v| s.positions[v as usize]));
        out.extend(triangulate_polygon(&pts).into_iter().map(|t| t.map(|k| f[k as usize])));
    }
    out
}

/// Unit vertex normals: the area-weighted sum of the normals of the
/// triangles around each vertex (in `f64`). A vertex on no triangle of
/// area, or whose sum cancels, gets the surface's overall normal (the sum
/// over all triangles), or +z when that cancels too.
pub(crate) fn vertex_normals(s: &Surface, tris: &[[u32; 3]]) -> Vec<Vec3> {
    let mut sums = vec![DVec3::ZERO; s.positions.len()];
    let mut total = DVec3::ZERO;
    for t in tris {
        let [a, b, c] = t.map(|v| s.positions[v as usize].as_dvec3());
        // Twice the area times the unit normal.
        let n = (b - a).cross(c - a);
        if !n.is_finite() {
            continue;
        }
        total += n;
        for &v in t {
            sums[v as usize] += n;
        }
    }
    let unit = |n: DVec3| {
        let len = n.length();
        // Relative to the largest component so tiny surfaces keep normals.
        (len > 0.0 && len.is_finite() && len > 1e-12 * n.abs().max_element()).then(|| (n / len).as_vec3())
    };
    let fallback = unit(total).unwrap_or(Vec3::Z);
    // `+ 0.0` folds `-0.0` so equal normals have equal bits.
    sums.into_iter().map(|n| unit(n).unwrap_or(fallback) + Vec3::ZERO).collect()
}

/// What [`Scene::for_each_triangle`] needs of the scene apart from its
/// surfaces: the same instances, mesh assets, tags and polygons, and
/// nothing else (borrowed when there are no surfaces).
pub(crate) fn without_surfaces(scene: &Scene) -> Cow<'_, Scene> {
    if scene.surfaces.is_empty() {
        return Cow::Borrowed(scene);
    }
    Cow::Owned(Scene {
        instances: scene.instances.clone(),
        meshes: scene.meshes.clone(),
        tags: scene.tags.clone(),
        polygons: scene.polygons.clone(),
        ..Scene::default()
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::test_scenes;
    use genform_core::scene::Tessellation;

    #[test]
    fn grid_surface_helpers() {
        let s = test_scenes::surfaces();
        let grid = &s.surfaces[0];
        assert_eq!(surface_name(&s, 0), "shell_surface0");
        assert_eq!(edges_by_type(grid).keys().copied().collect::<Vec<_>>(), [1, 2]);
        let smooth = &s.surfaces[1];
        let groups = edges_by_type(smooth);
        assert_eq!(groups.keys().copied().collect::<Vec<_>>(), [1, 2, genform_core::SurfaceEdge::UNTYPED]);
        assert_eq!(groups.values().map(Vec::len).sum::<usize>(), smooth.edges.len());
        let tris = triangles(grid);
        assert_eq!(tris.len(), 2 * grid.face_count());
        let normals = vertex_normals(grid, &tris);
        assert!(normals.iter().all(|n| (n.length() - 1.0).abs() < 1e-6 && n.z > 0.5));
        let plain = without_surfaces(&s);
        assert!(plain.surfaces.is_empty());
        assert_eq!(plain.triangle_count(Tessellation::default()), 12);
    }
}
