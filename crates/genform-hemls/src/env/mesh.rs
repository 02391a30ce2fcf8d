//! Triangle-mesh boundaries: a cleaned copy of the mesh (welded, degenerate
//! triangles dropped, closed meshes wound outward), pseudo-normals for
//! side tests, and a bounding-volume hierarchy so that segment, ray and
//! nearest-point queries cost O(log triangles), not O(triangles).

use genform_core::Mesh;
use glam::{DVec3, Vec3};
use std::collections::HashMap;
use std::sync::Arc;

/// Triangles per BVH leaf.
const LEAF_SIZE: usize = 4;
/// How far (in barycentric units) a segment may pass outside a triangle and
/// still hit it, so that a segment through a shared edge cannot slip
/// between the two triangles through rounding.
const INFLATE: f64 = 1e-7;
/// A triangle whose doubled area is below this times its longest edge²
/// (a sliver or a point) has no usable normal and is dropped.
const SLIVER: f64 = 1e-12;

/// A triangle mesh prepared for boundary queries. Built once; cheap to
/// share behind an [`Arc`].
pub struct MeshBoundary {
    name: String,
    positions: Vec<DVec3>,
    triangles: Vec<[u32; 3]>,
    normals: Vec<DVec3>,
    vertex_normals: Vec<DVec3>,
    vertex_on_border: Vec<bool>,
    edges: HashMap<(u32, u32), EdgeInfo>,
    closed: bool,
    nodes: Vec<Node>,
    order: Vec<u32>,
    lo: DVec3,
    hi: DVec3,
    preview: Arc<Mesh>,
}

impl std::fmt::Debug for MeshBoundary {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("MeshBoundary")
            .field("name", &self.name)
            .field("vertices", &self.positions.len())
            .field("triangles", &self.triangles.len())
            .field("closed", &self.closed)
            .finish()
    }
}

#[derive(Clone, Copy, Debug)]
struct EdgeInfo {
    /// Sum of the unit normals of the triangles on the edge.
    normal: DVec3,
    /// Used by one triangle only (the rim of an open mesh).
    border: bool,
}

/// A BVH node: a leaf holds `order[first..first + count]`; an inner node
/// (count 0) has children `first` and `first + 1`.
#[derive(Clone, Copy, Debug)]
struct Node {
    lo: DVec3,
    hi: DVec3,
    first: u32,
    count: u32,
}

/// Where on a triangle the nearest point lies.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Feature {
    Face,
    Edge(u32, u32),
    Vertex(u32),
}

/// The nearest point of the mesh to a query point.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Nearest {
    /// The point on the mesh.
    pub point: DVec3,
    /// The pseudo-normal there (front side; unit length or zero).
    pub normal: DVec3,
    /// Whether it lies on the rim of an open mesh.
    pub on_border: bool,
}

/// A segment hit: parameter along the segment and the triangle's unit normal.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Hit {
    pub t: f64,
    pub normal: DVec3,
}

impl MeshBoundary {
    /// Prepares `mesh`: welds identical positions, drops degenerate
    /// triangles, decides whether it is closed (every edge shared by
    /// exactly two triangles) and, if so, winds it outward. Errors: no
    /// triangle with an area, non-finite or missing vertices, or
    /// inconsistent winding (an edge used twice in the same direction).
    pub fn new(mesh: &Mesh) -> Result<Self, String> {
        let mut weld: HashMap<[u32; 3], u32> = HashMap::new();
        let mut positions = Vec::new();
        let mut remap = Vec::with_capacity(mesh.positions.len());
        for (i, p) in mesh.positions.iter().enumerate() {
            if !p.is_finite() {
                return Err(format!("vertex {} is not finite", i + 1));
            }
            // Adding 0.0 turns −0.0 into 0.0, so both weld together.
            let key = (*p + Vec3::ZERO).to_array().map(f32::to_bits);
            let next = positions.len() as u32;
            let id = *weld.entry(key).or_insert(next);
            if id == next {
                positions.push(p.as_dvec3());
            }
            remap.push(id);
        }
        let mut tris = Vec::with_capacity(mesh.triangles.len());
        for (i, t) in mesh.triangles.iter().enumerate() {
            let Some(&[a, b, c]) =
                t.iter().map(|&v| remap.get(v as usize).copied()).collect::<Option<Vec<_>>>().as_deref()
            else {
                return Err(format!("triangle {} refers to a missing vertex", i + 1));
            };
            if a != b && b != c && a != c {
                tris.push([a, b, c]);
            }
        }

        // Edge use: directed counts tell closedness and winding consistency.
        let mut uses: HashMap<(u32, u32), (u32, u32)> = HashMap::new();
        for &[a, b, c] in &tris {
            for (u, v) in [(a, b), (b, c), (c, a)] {
                let e = uses.entry((u.min(v), u.max(v))).or_default();
                if u < v { e.0 += 1 } else { e.1 += 1 }
            }
        }
        for (&(u, v), &(fwd, back)) in &uses {
            if fwd + back == 2 && (fwd == 2 || back == 2) {
                return Err(format!(
                    "the triangles are not consistently wound: the edge between vertices {} and {} runs the same way in both of its triangles",
                    u + 1,
                    v + 1
                ));
            }
        }
        let closed = !uses.is_empty() && uses.values().all(|&(f, b)| f == 1 && b == 1);

        let area_ok = |t: &[u32; 3]| {
            let [a, b, c] = t.map(|i| positions[i as usize]);
            let longest = (b - a).length_squared().max((c - b).length_squared()).max((a - c).length_squared());
            (b - a).cross(c - a).length() > SLIVER * longest
        };
        if closed {
            let volume: f64 = tris
                .iter()
                .map(|t| {
                    let [a, b, c] = t.map(|i| positions[i as usize]);
                    a.dot(b.cross(c))
                })
                .sum();
            if volume < 0.0 {
                for t in &mut tris {
                    t.swap(1, 2);
                }
            }
        }
        tris.retain(area_ok);
        if tris.is_empty() {
            return Err("the mesh has no triangle with an area".into());
        }
        let normals: Vec<DVec3> = tris
            .iter()
            .map(|t| {
                let [a, b, c] = t.map(|i| positions[i as usize]);
                (b - a).cross(c - a).normalize_or_zero()
            })
            .collect();

        // Pseudo-normals (Bærentzen & Aanæs): angle-weighted at vertices,
        // summed at edges; their sign decides the side of a nearest point.
        let mut vertex_normals = vec![DVec3::ZERO; positions.len()];
        let mut edges: HashMap<(u32, u32), EdgeInfo> = HashMap::new();
        for (t, n) in tris.iter().zip(&normals) {
            for k in 0..3 {
                let (i, j, l) = (t[k], t[(k + 1) % 3], t[(k + 2) % 3]);
                let (p, q, r) = (positions[i as usize], positions[j as usize], positions[l as usize]);
                let angle = (q - p).angle_between(r - p);
                if angle.is_finite() {
                    vertex_normals[i as usize] += *n * angle;
                }
                let key = (i.min(j), i.max(j));
                let e = edges.entry(key).or_insert(EdgeInfo { normal: DVec3::ZERO, border: false });
                e.normal += *n;
            }
        }
        let mut vertex_on_border = vec![false; positions.len()];
        for (key, e) in &mut edges {
            let (f, b) = uses.get(key).copied().unwrap_or((1, 0));
            e.border = f + b == 1;
            if e.border {
                vertex_on_border[key.0 as usize] = true;
                vertex_on_border[key.1 as usize] = true;
            }
        }

        let (lo, hi) =
            positions.iter().fold((DVec3::INFINITY, DVec3::NEG_INFINITY), |(lo, hi), &p| (lo.min(p), hi.max(p)));
        let preview = Arc::new(Mesh {
            name: mesh.name.clone(),
            positions: positions.iter().map(|p| p.as_vec3()).collect(),
            triangles: tris.clone(),
        });
        let mut out = MeshBoundary {
            name: mesh.name.clone(),
            positions,
            triangles: tris,
            normals,
            vertex_normals: vertex_normals.into_iter().map(|n| n.normalize_or_zero()).collect(),
            vertex_on_border,
            edges,
            closed,
            nodes: Vec::new(),
            order: Vec::new(),
            lo,
            hi,
            preview,
        };
        out.build_bvh();
        Ok(out)
    }

    /// The mesh's display name.
    pub fn name(&self) -> &str {
        &self.name
    }

    /// Whether every edge is shared by exactly two triangles (then the mesh
    /// has an inside, and its triangles were wound to face outward).
    pub fn is_closed(&self) -> bool {
        self.closed
    }

    /// Number of triangles kept (degenerate ones dropped).
    pub fn triangle_count(&self) -> usize {
        self.triangles.len()
    }

    /// Axis-aligned bounds of the vertices.
    pub fn bounds(&self) -> (DVec3, DVec3) {
        (self.lo, self.hi)
    }

    /// The cleaned mesh (for previews).
    pub fn preview(&self) -> &Arc<Mesh> {
        &self.preview
    }

    /// Size of the mesh, for relative tolerances.
    fn size(&self) -> f64 {
        (self.hi - self.lo).length()
    }

    fn build_bvh(&mut self) {
        let centroids: Vec<DVec3> =
            self.triangles.iter().map(|t| t.iter().map(|&i| self.positions[i as usize]).sum::<DVec3>() / 3.0).collect();
        self.order = (0..self.triangles.len() as u32).collect();
        self.nodes = vec![Node { lo: DVec3::ZERO, hi: DVec3::ZERO, first: 0, count: 0 }];
        let mut stack = vec![(0usize, 0usize, self.triangles.len())];
        while let Some((node, start, end)) = stack.pop() {
            let (lo, hi) = self.order[start..end].iter().fold((DVec3::INFINITY, DVec3::NEG_INFINITY), |acc, &t| {
                self.triangles[t as usize]
                    .iter()
                    .fold(acc, |(lo, hi), &i| (lo.min(self.positions[i as usize]), hi.max(self.positions[i as usize])))
            });
            self.nodes[node].lo = lo;
            self.nodes[node].hi = hi;
            if end - start <= LEAF_SIZE {
                self.nodes[node].first = start as u32;
                self.nodes[node].count = (end - start) as u32;
                continue;
            }
            let (clo, chi) =
                self.order[start..end].iter().fold((DVec3::INFINITY, DVec3::NEG_INFINITY), |(lo, hi), &t| {
                    (lo.min(centroids[t as usize]), hi.max(centroids[t as usize]))
                });
            let ext = chi - clo;
            let axis = if ext.x >= ext.y && ext.x >= ext.z {
                0
            } else if ext.y >= ext.z {
                1
            } else {
                2
            };
            let mid = start + (end - start) / 2;
            self.order[start..end].select_nth_unstable_by(mid - start, |&a, &b| {
                centroids[a as usize][axis].total_cmp(&centroids[b as usize][axis])
            });
            let left = self.nodes.len();
            self.nodes.push(Node { lo: DVec3::ZERO, hi: DVec3::ZERO, first: 0, count: 0 });
            self.nodes.push(Node { lo: DVec3::ZERO, hi: DVec3::ZERO, first: 0, count: 0 });
            self.nodes[node].first = left as u32;
            self.nodes[node].count = 0;
            stack.push((left, start, mid));
            stack.push((left + 1, mid, end));
        }
    }

    /// Calls `f` for every triangle whose node box the segment
    /// `from + t·d`, `t ∈ [0, t_max]` may touch.
    fn for_each_candidate(&self, from: DVec3, d: DVec3, t_max: f64, mut f: impl FnMut(usize)) {
        let mut stack = vec![0usize];
        while let Some(n) = stack.pop() {
            let node = self.nodes[n];
            if !segment_meets_box(from, d, t_max, node.lo, node.hi) {
                continue;
            }
            if node.count > 0 {
                for &t in &self.order[node.first as usize..(node.first + node.count) as usize] {
                    f(t as usize);
                }
            } else {
                stack.push(node.first as usize);
                stack.push(node.first as usize + 1);
            }
        }
    }

    /// The first point of `from + t·d`, `t ∈ [0, 1]`, where the segment
    /// crosses a triangle with `d·n` of sign `sign` (−1: from the front
    /// side to the back, +1: back to front).
    pub(crate) fn first_crossing(&self, from: DVec3, d: DVec3, sign: f64) -> Option<Hit> {
        let mut best: Option<Hit> = None;
        self.for_each_candidate(from, d, 1.0, |t| {
            let n = self.normals[t];
            if d.dot(n) * sign <= 0.0 {
                return;
            }
            if let Some(s) = self.intersect(t, from, d, INFLATE)
                && (0.0..=1.0).contains(&s)
                && best.is_none_or(|b| s < b.t)
            {
                best = Some(Hit { t: s, normal: n });
            }
        });
        best
    }

    /// Whether `p` is inside the closed mesh: the parity of the crossings of
    /// three rays in fixed, skew directions, by majority (a ray grazing an
    /// edge or vertex can miscount; two rarely both do).
    pub(crate) fn contains(&self, p: DVec3) -> bool {
        if !(p.cmpge(self.lo).all() && p.cmple(self.hi).all()) {
            return false;
        }
        // Skew directions, unlikely to run along the edges of modelled meshes.
        let dirs = [DVec3::new(0.57, 0.61, 0.55), DVec3::new(-0.27, 0.8, -0.53), DVec3::new(0.69, -0.13, -0.71)];
        let reach = self.size() + (p - (self.lo + self.hi) * 0.5).length() + 1.0;
        let votes = dirs
            .iter()
            .filter(|&&dir| {
                let d = dir.normalize() * reach;
                let mut crossings = 0u32;
                self.for_each_candidate(p, d, 1.0, |t| {
                    if self.intersect(t, p, d, 0.0).is_some_and(|s| s > 0.0 && s <= 1.0) {
                        crossings += 1;
                    }
                });
                crossings % 2 == 1
            })
            .count();
        votes >= 2
    }

    /// Möller–Trumbore: the parameter `s` where `from + s·d` meets the plane
    /// of triangle `t` inside it (barycentrics may undershoot by
    /// `inflate`); `None` when parallel or outside.
    fn intersect(&self, t: usize, from: DVec3, d: DVec3, inflate: f64) -> Option<f64> {
        let [a, b, c] = self.triangles[t].map(|i| self.positions[i as usize]);
        let (e1, e2) = (b - a, c - a);
        let pv = d.cross(e2);
        let det = e1.dot(pv);
        // Parallel (or a zero move): no crossing.
        if det.abs() <= 1e-300 || !det.is_finite() {
            return None;
        }
        let inv = 1.0 / det;
        let tv = from - a;
        let u = tv.dot(pv) * inv;
        if u < -inflate || u > 1.0 + inflate {
            return None;
        }
        let qv = tv.cross(e1);
        let v = d.dot(qv) * inv;
        if v < -inflate || u + v > 1.0 + inflate {
            return None;
        }
        let s = e2.dot(qv) * inv;
        s.is_finite().then_some(s)
    }

    /// The nearest point of the mesh to `p`, with the pseudo-normal there.
    pub(crate) fn nearest(&self, p: DVec3) -> Nearest {
        let mut best = (f64::INFINITY, DVec3::ZERO, 0usize, Feature::Face);
        let mut stack = vec![0usize];
        while let Some(n) = stack.pop() {
            let node = self.nodes[n];
            if box_distance_squared(p, node.lo, node.hi) >= best.0 {
                continue;
            }
            if node.count > 0 {
                for &t in &self.order[node.first as usize..(node.first + node.count) as usize] {
                    let (q, feature) = self.closest_on_triangle(t as usize, p);
                    let d2 = (p - q).length_squared();
                    if d2 < best.0 {
                        best = (d2, q, t as usize, feature);
                    }
                }
            } else {
                // Nearer child first, so the bound tightens early.
                let (l, r) = (node.first as usize, node.first as usize + 1);
                let dl = box_distance_squared(p, self.nodes[l].lo, self.nodes[l].hi);
                let dr = box_distance_squared(p, self.nodes[r].lo, self.nodes[r].hi);
                if dl < dr {
                    stack.push(r);
                    stack.push(l);
                } else {
                    stack.push(l);
                    stack.push(r);
                }
            }
        }
        let (_, point, tri, feature) = best;
        let (normal, on_border) = match feature {
            Feature::Face => (self.normals[tri], false),
            Feature::Edge(i, j) => {
                let e = self.edges[&(i.min(j), i.max(j))];
                (e.normal.normalize_or_zero(), e.border)
            }
            Feature::Vertex(i) => (self.vertex_normals[i as usize], self.vertex_on_border[i as usize]),
        };
        Nearest { point, normal, on_border }
    }

    /// Ericson's closest point on a triangle, with the feature it lies on.
    fn closest_on_triangle(&self, t: usize, p: DVec3) -> (DVec3, Feature) {
        let [ia, ib, ic] = self.triangles[t];
        let [a, b, c] = self.triangles[t].map(|i| self.positions[i as usize]);
        let (ab, ac, ap) = (b - a, c - a, p - a);
        let (d1, d2) = (ab.dot(ap), ac.dot(ap));
        if d1 <= 0.0 && d2 <= 0.0 {
            return (a, Feature::Vertex(ia));
        }
        let bp = p - b;
        let (d3, d4) = (ab.dot(bp), ac.dot(bp));
        if d3 >= 0.0 && d4 <= d3 {
            return (b, Feature::Vertex(ib));
        }
        let vc = d1 * d4 - d3 * d2;
        if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
            let v = d1 / (d1 - d3);
            return (a + ab * v, Feature::Edge(ia, ib));
        }
        let cp = p - c;
        let (d5, d6) = (ab.dot(cp), ac.dot(cp));
        if d6 >= 0.0 && d5 <= d6 {
            return (c, Feature::Vertex(ic));
        }
        let vb = d5 * d2 - d1 * d6;
        if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
            let w = d2 / (d2 - d6);
            return (a + ac * w, Feature::Edge(ia, ic));
        }
        let va = d3 * d6 - d5 * d4;
        if va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0 {
            let w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
            return (b + (c - b) * w, Feature::Edge(ib, ic));
        }
        let denom = 1.0 / (va + vb + vc);
        let (v, w) = (vb * denom, vc * denom);
        (a + ab * v + ac * w, Feature::Face)
    }
}

/// Whether the segment `from + t·d`, `t ∈ [0, t_max]`, meets the closed box.
fn segment_meets_box(from: DVec3, d: DVec3, t_max: f64, lo: DVec3, hi: DVec3) -> bool {
    // Boxes are grown a little so that hits on a face lying in a box side
    // are not lost to rounding.
    let pad = (hi - lo).max_element() * 1e-9 + 1e-12;
    let (lo, hi) = (lo - DVec3::splat(pad), hi + DVec3::splat(pad));
    let (mut t0, mut t1) = (0.0f64, t_max);
    for k in 0..3 {
        if d[k] == 0.0 {
            if from[k] < lo[k] || from[k] > hi[k] {
                return false;
            }
            continue;
        }
        let inv = 1.0 / d[k];
        let (mut a, mut b) = ((lo[k] - from[k]) * inv, (hi[k] - from[k]) * inv);
        if a > b {
            std::mem::swap(&mut a, &mut b);
        }
        t0 = t0.max(a);
        t1 = t1.min(b);
        if t0 > t1 {
            return false;
        }
    }
    true
}

fn box_distance_squared(p: DVec3, lo: DVec3, hi: DVec3) -> f64 {
    (lo - p).max(p - hi).max(DVec3::ZERO).length_squared()
}

#[cfg(test)]
mod tests {
    use super::*;
    use genform_core::scene::{Primitive, Tessellation, unit_mesh};

    /// A UV sphere of radius 1 around the origin.
    fn sphere_mesh() -> MeshBoundary {
        let mut m = unit_mesh(Primitive::Sphere, Tessellation { radial: 24, rings: 12 });
        for p in &mut m.positions {
            *p *= 2.0;
        }
        MeshBoundary::new(&m).unwrap()
    }

    /// Deterministic points in [-1.5, 1.5]³ (a simple LCG; no RNG needed).
    fn points(n: usize) -> Vec<DVec3> {
        let mut s = 0x2545_f491_4f6c_dd1du64;
        let mut next = || {
            s = s.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            (s >> 11) as f64 / (1u64 << 53) as f64 * 3.0 - 1.5
        };
        (0..n).map(|_| DVec3::new(next(), next(), next())).collect()
    }

    #[test]
    fn bvh_nearest_matches_brute_force() {
        let m = sphere_mesh();
        assert!(m.is_closed());
        for p in points(300) {
            let fast = m.nearest(p).point;
            let brute = (0..m.triangles.len())
                .map(|t| m.closest_on_triangle(t, p).0)
                .min_by(|a, b| (*a - p).length_squared().total_cmp(&(*b - p).length_squared()))
                .unwrap();
            assert!(((fast - p).length() - (brute - p).length()).abs() < 1e-12, "{p}: {fast} vs {brute}");
        }
    }

    #[test]
    fn parity_and_pseudo_normals_agree_on_a_closed_mesh() {
        let m = sphere_mesh();
        for p in points(300) {
            let near = m.nearest(p);
            let by_normal = (p - near.point).dot(near.normal) < 0.0;
            // Far from the surface both tests are unambiguous.
            if (p - near.point).length() > 1e-6 {
                assert_eq!(m.contains(p), by_normal, "{p}");
            }
            assert!(!near.on_border);
        }
        assert!(m.contains(DVec3::ZERO));
        assert!(!m.contains(DVec3::new(0.0, 0.0, 1.5)));
    }

    #[test]
    fn segment_crossings_respect_the_direction() {
        let m = sphere_mesh();
        let (from, d) = (DVec3::new(0.0, 0.0, 3.0), DVec3::new(0.0, 0.0, -6.0));
        let enter = m.first_crossing(from, d, -1.0).unwrap();
        assert!((from.z + d.z * enter.t - 1.0).abs() < 1e-6 && enter.normal.z > 0.9);
        let leave = m.first_crossing(from, d, 1.0).unwrap();
        assert!((from.z + d.z * leave.t + 1.0).abs() < 1e-6 && leave.normal.z < -0.9);
        assert!(m.first_crossing(from, DVec3::ZERO, -1.0).is_none());
        assert!(m.first_crossing(from, DVec3::new(0.0, 0.0, 0.5), -1.0).is_none());
    }
}
