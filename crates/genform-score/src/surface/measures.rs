//! The six raw measures of a Scene's surfaces.

use super::criterion::SurfaceCriterion;
use genform_core::Surface;
use genform_core::scene::Scene;

/// Nodes closer to a symmetry line than this fraction of (extent + |centre|)
/// along the axis count as on the line (see the module docs for why not
/// the reference's 1e-9).
pub const SYMMETRY_TOLERANCE: f64 = 1e-5;

/// The raw criteria of all surfaces of a Scene together (see the module
/// docs for definitions). Computed in `f64` from the `f32` positions.
///
/// Non-finite coordinates make the measures that read them non-finite
/// (size, smoothness, symmetry, undulation); [`SurfaceMeasures::is_finite`]
/// tells, and the scorer gives such criteria the worst score.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SurfaceMeasures {
    /// x-extent + y-extent of the vertices (0 when there are none).
    pub size: f64,
    /// Σ over edges |z_a − z_b|.
    pub smoothness: f64,
    /// Vertices on the wrong side of a soft boundary (Σ `outside_soft`).
    pub soft_boundary: f64,
    /// Vertices / edges; 1 when there are no edges.
    pub subdivisions: f64,
    /// (sym(x) + sym(y)) / 2, in [0, 1].
    pub symmetry: f64,
    /// z-extent of the vertices (0 when there are none).
    pub undulation: f64,
    /// Vertices counted.
    pub vertices: usize,
    /// Edges counted.
    pub edges: usize,
}

/// Running min/max along one axis.
#[derive(Clone, Copy)]
struct Span {
    lo: f64,
    hi: f64,
}

impl Span {
    const EMPTY: Span = Span { lo: f64::INFINITY, hi: f64::NEG_INFINITY };

    fn add(&mut self, v: f64) {
        self.lo = self.lo.min(v);
        self.hi = self.hi.max(v);
    }

    fn extent(self) -> f64 {
        if self.lo <= self.hi { self.hi - self.lo } else { 0.0 }
    }

    fn centre(self) -> f64 {
        0.5 * (self.lo + self.hi)
    }
}

/// Node counts either side of one symmetry line.
#[derive(Clone, Copy, Default)]
struct Sides {
    below: u64,
    above: u64,
}

impl Sides {
    fn add(&mut self, d: f64, tol: f64) {
        if d > tol {
            self.above += 1;
        } else if d < -tol {
            self.below += 1;
        }
    }

    /// min/max, 1 when no node is off the line.
    fn ratio(self) -> f64 {
        let (lo, hi) = (self.below.min(self.above), self.below.max(self.above));
        if hi == 0 { 1.0 } else { lo as f64 / hi as f64 }
    }
}

impl SurfaceMeasures {
    /// The measures of `scene`'s surfaces (its other geometry is ignored).
    pub fn of(scene: &Scene) -> SurfaceMeasures {
        SurfaceMeasures::of_surfaces(&scene.surfaces)
    }

    /// The measures of `surfaces` taken together. Reads the vertices
    /// twice (symmetry needs the bounding box first) and the edges once;
    /// allocates nothing. Edges whose indices are out of range count as
    /// edges but add no |Δz|.
    pub fn of_surfaces(surfaces: &[Surface]) -> SurfaceMeasures {
        let (mut x, mut y, mut z) = (Span::EMPTY, Span::EMPTY, Span::EMPTY);
        let (mut vertices, mut edges, mut outside) = (0usize, 0usize, 0u64);
        let mut smoothness = 0.0;
        // f64::min/max skip NaN, so non-finite input is tracked apart.
        let mut finite = true;
        for s in surfaces {
            for p in &s.positions {
                finite &= p.is_finite();
                x.add(f64::from(p.x));
                y.add(f64::from(p.y));
                z.add(f64::from(p.z));
            }
            for e in &s.edges {
                if let (Some(a), Some(b)) = (s.positions.get(e.a as usize), s.positions.get(e.b as usize)) {
                    smoothness += (f64::from(a.z) - f64::from(b.z)).abs();
                }
            }
            vertices += s.positions.len();
            edges += s.edges.len();
            outside += u64::from(s.outside_soft);
        }
        let tol = |s: Span| SYMMETRY_TOLERANCE * (s.extent() + s.centre().abs());
        let (cx, cy, tx, ty) = (x.centre(), y.centre(), tol(x), tol(y));
        let (mut about_x, mut about_y) = (Sides::default(), Sides::default());
        if finite {
            for p in surfaces.iter().flat_map(|s| &s.positions) {
                // sym(x): the line parallel to the x-axis splits by y.
                about_x.add(f64::from(p.y) - cy, ty);
                about_y.add(f64::from(p.x) - cx, tx);
            }
        }
        let nan_unless = |v: f64| if finite { v } else { f64::NAN };
        SurfaceMeasures {
            size: nan_unless(x.extent() + y.extent()),
            smoothness,
            soft_boundary: outside as f64,
            subdivisions: if edges == 0 { 1.0 } else { vertices as f64 / edges as f64 },
            symmetry: nan_unless(0.5 * (about_x.ratio() + about_y.ratio())),
            undulation: nan_unless(z.extent()),
            vertices,
            edges,
        }
    }

    /// The measure of `criterion`.
    pub fn get(&self, criterion: SurfaceCriterion) -> f64 {
        match criterion {
            SurfaceCriterion::Size => self.size,
            SurfaceCriterion::Smoothness => self.smoothness,
            SurfaceCriterion::SoftBoundary => self.soft_boundary,
            SurfaceCriterion::Subdivisions => self.subdivisions,
            SurfaceCriterion::Symmetry => self.symmetry,
            SurfaceCriterion::Undulation => self.undulation,
        }
    }

    /// The soft-boundary count as a fraction of the vertices (0 without
    /// vertices).
    pub fn soft_boundary_fraction(&self) -> f64 {
        if self.vertices == 0 { 0.0 } else { self.soft_boundary / self.vertices as f64 }
    }

    /// Whether every measure is finite (false when a vertex coordinate is
    /// NaN or infinite, e.g. after a growth blow-up).
    pub fn is_finite(&self) -> bool {
        SurfaceCriterion::ALL.iter().all(|&c| self.get(c).is_finite())
    }
}
