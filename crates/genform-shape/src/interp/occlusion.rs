//! Occlusion queries: `inside()`, `overlaps()` and `touches()` (CGA's
//! names) test the running scope's box against the boxes of what the
//! derivation has placed before it, so a rule can leave out the windows of
//! a wall that another wing covers.
//!
//! An occluder is the scope box a primitive, polygon or mass was placed in
//! (a mass's box bounds its footprint; a roof's box is its polygon's). A
//! face (a scope of no depth, its +z outwards) is inside an occluder when
//! it lies within it facing into it, so a wall in the plane of another
//! wing's wall counts as open.
//! Placements by the running gene and its ancestors are not occluders: a
//! façade always lies on its own mass. The derivation is depth first, so a
//! query sees the branches derived before it — a grammar places its masses
//! before it decorates them.

use crate::program::{Query, QueryKind};
use crate::scope::ScopeState;
use genform_core::Mesh;
use genform_core::genome::GenePos;
use glam::DVec3;

/// A placed box: centre, unit axis directions and half extents along them.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Placed {
    centre: DVec3,
    dirs: [DVec3; 3],
    half: [f64; 3],
    /// The tag it was placed with.
    pub tag: u32,
    /// The gene that placed it.
    pub gene: GenePos,
}

impl Placed {
    /// The box of `scope`, placed by `gene`.
    pub(crate) fn of(scope: &ScopeState, gene: GenePos) -> Placed {
        let m = scope.frame.matrix3;
        let cols = [m.x_axis, m.y_axis, m.z_axis];
        // Frames are rotations and reflections; sizes may be negative
        // (mirrored scopes): the box is the same.
        let dirs = cols.map(|c| c.normalize_or_zero());
        let half = [0, 1, 2].map(|i| (scope.size[i] * cols[i].length()).abs() * 0.5);
        Placed { centre: scope.frame.translation, dirs, half, tag: scope.tag(), gene }
    }

    /// The world-axis boxes of a context mesh (`context "…";`): one per
    /// connected part (triangles sharing corners: each building of a city
    /// model), tagged `tag` and placed by no gene, so every query sees them.
    pub(crate) fn context(m: &Mesh, tag: u32) -> Vec<Placed> {
        let n = m.positions.len();
        let mut parent: Vec<usize> = (0..n).collect();
        fn root(p: &mut [usize], mut i: usize) -> usize {
            while p[i] != i {
                p[i] = p[p[i]];
                i = p[i];
            }
            i
        }
        for t in &m.triangles {
            let a = root(&mut parent, t[0] as usize);
            for &k in &t[1..] {
                let b = root(&mut parent, k as usize);
                parent[b] = a;
            }
        }
        let mut bounds: Vec<Option<(DVec3, DVec3)>> = vec![None; n];
        for t in &m.triangles {
            for &k in t {
                let r = root(&mut parent, k as usize);
                let p = m.positions[k as usize].as_dvec3();
                let b = bounds[r].get_or_insert((p, p));
                *b = (b.0.min(p), b.1.max(p));
            }
        }
        bounds
            .into_iter()
            .flatten()
            .map(|(lo, hi)| Placed {
                centre: (lo + hi) * 0.5,
                dirs: [DVec3::X, DVec3::Y, DVec3::Z],
                half: ((hi - lo) * 0.5).to_array(),
                tag,
                gene: GenePos(u32::MAX),
            })
            .collect()
    }

    /// The box's radius when projected on `axis`.
    fn radius(&self, axis: DVec3) -> f64 {
        (0..3).map(|i| (self.dirs[i].dot(axis) * self.half[i]).abs()).sum()
    }

    fn scale(&self) -> f64 {
        self.centre.abs().max_element().max(self.half[0]).max(self.half[1]).max(self.half[2])
    }
}

/// `a` lies in `b` (every corner, to within `eps`).
fn inside(a: &Placed, b: &Placed, eps: f64) -> bool {
    let d = a.centre - b.centre;
    (0..3).all(|j| d.dot(b.dirs[j]).abs() + a.radius(b.dirs[j]) <= b.half[j] + eps)
}

/// The boxes' gap along the axis that separates them most: negative when
/// they overlap (by that much on the axis where they overlap least).
fn separation(a: &Placed, b: &Placed) -> f64 {
    let d = b.centre - a.centre;
    let mut axes: Vec<DVec3> = a.dirs.iter().chain(&b.dirs).copied().collect();
    for i in 0..3 {
        for j in 0..3 {
            let c = a.dirs[i].cross(b.dirs[j]);
            // Parallel edges: their cross product is no separating axis.
            if c.length_squared() > 1e-12 {
                axes.push(c.normalize());
            }
        }
    }
    axes.into_iter()
        .filter(|l| l.length_squared() > 0.5)
        .map(|l| d.dot(l).abs() - a.radius(l) - b.radius(l))
        .fold(f64::NEG_INFINITY, f64::max)
}

/// Whether the query holds for `scope` against `placed`, leaving out what
/// `lineage` (the running gene and its ancestors) placed; a query's tag is
/// matched against each occluder's tag without its colour (`base`).
pub(crate) fn holds(q: Query, scope: &Placed, placed: &[Placed], lineage: &[GenePos], base: &[u32]) -> bool {
    let tagged = |p: &Placed| q.tag.is_none_or(|t| base.get(p.tag as usize).copied().unwrap_or(p.tag) == t);
    placed.iter().filter(|p| tagged(p) && !lineage.contains(&p.gene)).any(|p| {
        // Positions are `f64` from `f32`-free arithmetic, but long chains of
        // splits leave rounding of a few ulps of the model's size.
        let eps = 1e-9 * (1.0 + scope.scale().max(p.scale()));
        match q.kind {
            // A face (no depth; +z outwards) on an occluder's boundary is
            // covered only when it faces into it: a wall continuing another
            // wing's wall in its plane stays open.
            QueryKind::Inside if scope.half[2] <= eps => {
                let lifted = Placed { centre: scope.centre + scope.dirs[2] * (16.0 * eps), ..*scope };
                inside(&lifted, p, eps)
            }
            QueryKind::Inside => inside(scope, p, eps),
            QueryKind::Overlaps => separation(scope, p) < -eps,
            QueryKind::Touches => separation(scope, p) <= eps,
        }
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::{DAffine3, DMat3};

    fn boxed(centre: [f64; 3], size: [f64; 3], turn_deg: f64) -> Placed {
        let scope = ScopeState {
            frame: DAffine3::from_mat3_translation(
                DMat3::from_rotation_y(turn_deg.to_radians()),
                DVec3::from_array(centre),
            ),
            size: DVec3::from_array(size),
            ..ScopeState::UNIT
        };
        Placed::of(&scope, GenePos(1))
    }

    fn ask(kind: QueryKind, a: &Placed, b: &Placed) -> bool {
        holds(Query { kind, tag: None }, a, std::slice::from_ref(b), &[], &[])
    }

    #[test]
    fn boxes_inside_overlapping_touching_and_apart() {
        let wing = boxed([0.0, 0.0, 0.0], [10.0, 6.0, 4.0], 0.0);
        // A wall piece within the wing, one on its face, one beside it.
        let within = boxed([2.0, 1.0, 0.0], [2.0, 2.0, 0.0], 0.0);
        // A face whose +z (outwards) is world +x, on the wing's +x face.
        let on_face = boxed([5.0, 0.0, 0.0], [2.0, 2.0, 0.0], 90.0);
        let beside = boxed([6.0, 0.0, 0.0], [1.0, 1.0, 1.0], 0.0);
        assert!(ask(QueryKind::Inside, &within, &wing) && ask(QueryKind::Overlaps, &within, &wing));
        // A face on the wing's surface touches it but does not overlap its
        // interior; facing out of it, it is not inside; facing in, it is.
        assert!(ask(QueryKind::Touches, &on_face, &wing) && !ask(QueryKind::Overlaps, &on_face, &wing));
        assert!(!ask(QueryKind::Inside, &on_face, &wing));
        let facing_in = boxed([5.0, 0.0, 0.0], [2.0, 2.0, 0.0], -90.0);
        assert!(ask(QueryKind::Inside, &facing_in, &wing));
        assert!(!ask(QueryKind::Inside, &beside, &wing) && !ask(QueryKind::Touches, &beside, &wing));
        let half_in = boxed([5.0, 0.0, 0.0], [1.0, 1.0, 1.0], 0.0);
        assert!(ask(QueryKind::Overlaps, &half_in, &wing) && !ask(QueryKind::Inside, &half_in, &wing));
    }

    #[test]
    fn rotated_boxes_use_their_own_axes() {
        // A 10×1×1 bar turned 45° about y, and a unit cube near its end:
        // apart along the bar's diagonal, though their world-axis bounding
        // boxes overlap.
        let bar = boxed([0.0, 0.0, 0.0], [10.0, 1.0, 1.0], 45.0);
        let cube = boxed([3.2, 0.0, -0.3], [1.0, 1.0, 1.0], 0.0);
        assert!(!ask(QueryKind::Overlaps, &cube, &bar) && !ask(QueryKind::Touches, &cube, &bar));
        let on_bar = boxed([2.0, 0.0, -2.0], [0.5, 0.5, 0.5], 45.0);
        assert!(ask(QueryKind::Inside, &on_bar, &bar));
    }

    #[test]
    fn tags_and_the_lineage_filter_occluders() {
        let wing = Placed { tag: 3, gene: GenePos(7), ..boxed([0.0; 3], [4.0; 3], 0.0) };
        let piece = boxed([0.0; 3], [1.0; 3], 0.0);
        let q = |tag| Query { kind: QueryKind::Inside, tag };
        assert!(holds(q(Some(3)), &piece, &[wing], &[GenePos(0)], &[]));
        assert!(!holds(q(Some(4)), &piece, &[wing], &[GenePos(0)], &[]));
        assert!(!holds(q(None), &piece, &[wing], &[GenePos(0), GenePos(7)], &[]), "its own branch's mass");
        // Tag 3 recoloured is tag 5, whose base is 3.
        let red = Placed { tag: 5, ..wing };
        assert!(holds(q(Some(3)), &piece, &[red], &[GenePos(0)], &[0, 1, 2, 3, 4, 3]));
    }
}
