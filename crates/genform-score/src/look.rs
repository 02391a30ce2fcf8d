//! What a model looks like to a scorer, as text ([`crate::Scorer::look`]):
//! galleries show one individual per look, so a converged population does
//! not fill a gallery with copies of one model.

use genform_core::scene::Scene;
use std::fmt::Write as _;

/// A number to 4 significant digits.
fn sig4(v: f64) -> String {
    if v == 0.0 || !v.is_finite() { format!("{v}") } else { format!("{v:.3e}") }
}

/// What a model looks like in a gallery, as text: per surface its face
/// count, the scene's instance and polyline counts, its bounds and the
/// scorer's `measures` (a target's covered cells), numbers to 4
/// significant digits. Two individuals with the same look draw the same
/// picture, give or take an edge's colour or a vertex splitting a straight
/// edge: GE phenotypes often differ only in rules that never fire or in an
/// edge type, so a gallery of distinct phenotype texts can show one model
/// 16 times.
pub fn look(scene: &Scene, measures: &[f64]) -> String {
    let mut out = String::new();
    for s in &scene.surfaces {
        let _ = write!(out, "surface {} faces; ", s.face_count());
    }
    let _ = write!(out, "{} instances {} polylines; ", scene.instances.len(), scene.polylines.len());
    if let Some((lo, hi)) = scene.bounds(Default::default()) {
        let corners: Vec<String> = lo.to_array().into_iter().chain(hi.to_array()).map(|v| sig4(v.into())).collect();
        let _ = write!(out, "bounds {}; ", corners.join(" "));
    }
    let values: Vec<String> = measures.iter().map(|&m| sig4(m)).collect();
    let _ = write!(out, "measures {}", values.join(" "));
    out
}

/// What a surface looks like in a gallery, as text: per surface its face
/// count, then the surface criteria's raw values (`criteria`), numbers to 4
/// significant digits. Unlike [`look`] it leaves out the bounds: a surface
/// and its mirror image or a shifted copy (GE finds many: a rule set that
/// turns left where another turns right) score alike and look alike, but
/// their bounds differ, so galleries of Genr8 runs showed one surface
/// twice with the same score (canopy, seed 3: two cells at 3.8118). Two
/// surfaces with one face count and one set of criteria values show once.
pub fn surface_look(scene: &Scene, criteria: &[f64]) -> String {
    let mut out = String::new();
    for s in &scene.surfaces {
        let _ = write!(out, "surface {} faces; ", s.face_count());
    }
    let values: Vec<String> = criteria.iter().map(|&m| sig4(m)).collect();
    let _ = write!(out, "criteria {}", values.join(" "));
    out
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use genform_core::surface::Surface;

    /// A square of `faces` strips in the xy plane, its edges of `edge_type`.
    pub(crate) fn strips(faces: u32, edge_type: u32) -> Scene {
        let mut s = Surface::new(0);
        for k in 0..=faces {
            let x = k as f32 / faces as f32;
            s.positions.extend([glam::Vec3::new(x, 0.0, 0.0), glam::Vec3::new(x, 1.0, 0.0)]);
        }
        for k in 0..faces {
            s.push_face(&[2 * k, 2 * k + 2, 2 * k + 3, 2 * k + 1]);
            s.edges.push(genform_core::surface::SurfaceEdge { a: 2 * k, b: 2 * k + 2, kind: edge_type });
        }
        let mut scene = Scene::new();
        scene.surfaces.push(s);
        scene
    }

    #[test]
    fn looks_tell_models_apart_by_counts_bounds_and_measures() {
        assert_eq!(look(&strips(4, 1), &[10.0, 0.5]), look(&strips(4, 2), &[10.0, 0.5]), "edge types do not show");
        assert_ne!(look(&strips(4, 1), &[10.0, 0.5]), look(&strips(5, 1), &[10.0, 0.5]));
        assert_ne!(look(&strips(4, 1), &[10.0, 0.5]), look(&strips(4, 1), &[10.0, 0.5001]));
        assert!(look(&strips(4, 1), &[]).starts_with("surface 4 faces; 0 instances 0 polylines; bounds"));
    }

    #[test]
    fn surface_looks_ignore_where_a_surface_lies_and_which_way_it_faces() {
        let mut mirrored = strips(4, 1);
        for p in &mut mirrored.surfaces[0].positions {
            *p = glam::Vec3::new(-p.x + 3.0, p.y, p.z);
        }
        assert_ne!(look(&strips(4, 1), &[10.0, 0.5]), look(&mirrored, &[10.0, 0.5]), "bounds differ");
        assert_eq!(surface_look(&strips(4, 1), &[10.0, 0.5]), surface_look(&mirrored, &[10.0, 0.5]));
        assert_ne!(surface_look(&strips(4, 1), &[10.0, 0.5]), surface_look(&strips(5, 1), &[10.0, 0.5]));
        assert_ne!(surface_look(&strips(4, 1), &[10.0, 0.5]), surface_look(&strips(4, 1), &[10.0, 0.5001]));
        assert_eq!(surface_look(&strips(4, 2), &[10.0, 0.5]), "surface 4 faces; criteria 1.000e1 5.000e-1");
    }
}
